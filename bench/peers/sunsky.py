#!/usr/bin/python3
"""Candela's sunsky emitter against Mitsuba 3's, in the RGB variant.

Two checks, each over several emitter configurations (defaults; a sun given by direction with
another turbidity and albedo; a time, place and rotated frame; the limb-darkened complex sun; a
wide sun aperture):

  radiance    radiance meters aimed at fixed directions of the sky and at the sun's disk: the
              model's value along one ray, which both renderers compute exactly, compared as a
              relative difference per channel;
  irradiance  a grey plane lit by sun and sky, seen by a radiance meter: the irradiance each
              renderer gathers by next-event estimation with its own sampling of the emitter
              (Mitsuba: truncated Gaussian mixtures; Candela: a tabulated density), SEEDS seeds x
              SPP samples each, reported as E = pi L / 0.5 with standard errors, and z.

  sunsky.py --candela build/candela --mitsuba /tmp/mitsuba3/mitsuba [--spp 4096 --seeds 16]

Mitsuba runs scalar_rgb; its folder is put on LD_LIBRARY_PATH. Without the peer the script says
so and stops.

timed_sunsky is not compared: the peer build's own is broken (--timed shows it). Its scalar_rgb
returns one meaningless colour, about (3819, 1032, -58), in every direction, and its llvm_ad_rgb
stops with "jit_var_schedule: not permitted". Candela's timed_sunsky is tested against its
sunsky at the same instants instead (tests/lights/test_sunsky.cpp).
"""
import os, subprocess, sys, tempfile
import numpy as np

import candela
from mitsuba_peer import peer_command_line, print_seed_means

# name: (plugin, its parameters, the sensors' shutter)
CONFIGS = {
    "defaults": ("sunsky", "", ""),
    "direction_t6_a06": ("sunsky", '<vector name="sun_direction" x="0.3" y="-0.5" z="0.6"/>'
                                   '<float name="turbidity" value="6.2"/><rgb name="albedo" value="0.6, 0.4, 0.2"/>', ""),
    "time_place_rotated": ("sunsky", '<float name="latitude" value="46.5"/><float name="longitude" value="6.6"/>'
                                     '<float name="timezone" value="1"/><integer name="year" value="2024"/>'
                                     '<integer name="month" value="3"/><integer name="day" value="21"/>'
                                     '<float name="hour" value="9.5"/><float name="turbidity" value="2"/>'
                                     '<transform name="to_world"><rotate x="1" angle="-90"/></transform>', ""),
    "complex_sun": ("sunsky", '<vector name="sun_direction" x="0.3" y="-0.5" z="0.6"/><boolean name="complex_sun" value="true"/>', ""),
    "aperture_3deg": ("sunsky", '<vector name="sun_direction" x="-0.2" y="0.1" z="0.35"/><float name="sun_aperture" value="3"/>'
                                '<float name="sun_scale" value="0.5"/><float name="sky_scale" value="2"/>', ""),
}
# The peer's timed_sunsky with its defaults, over a whole shutter (--timed).
TIMED = ("timed_sunsky", "", '<float name="shutter_open" value="0"/><float name="shutter_close" value="1"/>')
# Directions in the emitter's frame (z up) for the radiance meters; the rotated configuration's
# frame maps them through its to_world.
DIRECTIONS = [(0, 0, 1), (1, 0, 0.05), (0, 1, 0.2), (-1, 0.3, 0.5), (0.4, -0.8, 0.3), (-0.3, -0.2, 0.9),
              (0.7, 0.7, 0.1), (0.1, -0.9, 0.02), (-0.6, 0.6, 0.7), (0.25, -0.45, 0.65)]


def scene(config, sensor):
    plugin, emitter, _ = config
    return f"""<scene version="3.0.0">
  <default name="spp" value="1"/><default name="seed" value="0"/>
  <integrator type="path"><integer name="max_depth" value="-1"/></integrator>
  <emitter type="{plugin}">{emitter}</emitter>
  {sensor}
  <shape type="rectangle"><transform name="to_world"><translate z="-50"/></transform>
    <bsdf type="diffuse"><rgb name="reflectance" value="0"/></bsdf></shape>
</scene>"""


def film():
    return ('<sampler type="independent"><integer name="sample_count" value="$spp"/><integer name="seed" value="$seed"/></sampler>'
            '<film type="hdrfilm"><integer name="width" value="1"/><integer name="height" value="1"/>'
            '<string name="component_format" value="float32"/><rfilter type="box"/></film>')


def meter(direction, rotated, shutter=""):
    d = np.array(direction, float)
    d /= np.linalg.norm(d)
    if rotated:  # rotate x by -90 degrees: (x, y, z) -> (x, z, -y)
        d = np.array([d[0], d[2], -d[1]])
    return (f'<sensor type="radiancemeter"><point name="origin" x="0" y="0" z="0"/>'
            f'<vector name="direction" x="{d[0]:.9f}" y="{d[1]:.9f}" z="{d[2]:.9f}"/>{shutter}{film()}</sensor>')


def lit_plane(rotated, shutter=""):
    # A grey diffuse plane (reflectance 0.5) facing the emitter's zenith, seen straight down by a
    # radiance meter 1 unit above it: L = 0.5 E / pi, with E the irradiance from sun and sky,
    # which each renderer gathers by next-event estimation with its own sampling of the emitter.
    t = '<rotate x="1" angle="-90"/>' if rotated else ""
    origin, direction = ('x="0" y="1" z="0"', 'x="0" y="-1" z="0"') if rotated else ('x="0" y="0" z="1"', 'x="0" y="0" z="-1"')
    return (f'<shape type="rectangle"><transform name="to_world"><scale value="1000"/>{t}</transform>'
            f'<bsdf type="diffuse"><rgb name="reflectance" value="0.5"/></bsdf></shape>'
            f'<sensor type="radiancemeter"><point name="origin" {origin}/><vector name="direction" {direction}/>{shutter}{film()}</sensor>')


def main():
    a, env = peer_command_line(spp=4096, seeds=16, add_arguments=lambda ap: ap.add_argument(
        "--timed", action="store_true", help="only show both renderers' timed_sunsky along a few directions"))
    if env is None:
        return 0
    tmp = tempfile.mkdtemp()

    def render(renderer, xml, spp=1, seed=0):
        path = os.path.join(tmp, "scene.xml")
        with open(path, "w") as f:
            f.write(xml)
        out = os.path.join(tmp, f"{renderer}.exr")
        if os.path.exists(out):
            os.remove(out)
        if renderer == "candela":
            cmd = [a.candela, "render", path, "-D", f"spp={spp}", "-D", f"seed={seed}", "-o", out, "--quiet"]
        else:
            cmd = [a.mitsuba, "-m", "scalar_rgb", "-t", "2", f"-Dspp={spp}", f"-Dseed={seed}", "-o", out, path]
        p = subprocess.run(cmd, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        if p.returncode != 0 or not os.path.exists(out):
            sys.exit(f"{renderer} failed: {p.stderr.decode()[-600:]}")
        return np.asarray(candela.read_image(out))[..., :3].astype(np.float64).reshape(3)

    if a.timed:
        for d in DIRECTIONS[:4]:
            c = render("candela", scene(TIMED, meter(d, False, TIMED[2])), 64)
            m = render("mitsuba", scene(TIMED, meter(d, False, TIMED[2])), 64)
            print(f"timed_sunsky toward {d}, 64 rays over the shutter: candela {c}, mitsuba {m}")
        return 0

    print("radiance along fixed directions (1 ray each): largest relative difference per configuration, |c - m| / max(|m|, 1e-3 max), float32 output")
    for name, config in CONFIGS.items():
        _, emitter, shutter = config
        rotated = "rotate" in emitter
        worst, rows = 0.0, []
        for d in DIRECTIONS:
            c = render("candela", scene(config, meter(d, rotated, shutter)))
            m = render("mitsuba", scene(config, meter(d, rotated, shutter)))
            rel = np.abs(c - m) / np.maximum(np.abs(m), 1e-3 * np.abs(m).max() + 1e-12)
            worst = max(worst, float(rel.max()))
            rows.append((d, c, m))
        print(f"  {name:20s} worst {worst:.2e}   e.g. {rows[1][0]}: candela {np.array2string(rows[1][1], precision=5)} "
              f"mitsuba {np.array2string(rows[1][2], precision=5)}")
        if "sun_direction" in emitter:
            # The sun's centre, and a direction 0.8 of the way to its limb.
            s = emitter.split('name="sun_direction"')[1].split("/>")[0]
            sd = np.array([float(s.split(f'{k}="')[1].split('"')[0]) for k in "xyz"])
            sd /= np.linalg.norm(sd)
            aperture = float(emitter.split('name="sun_aperture" value="')[1].split('"')[0]) if "sun_aperture" in emitter else 0.5358
            perp = np.cross(sd, [0, 0, 1.0])
            perp /= np.linalg.norm(perp)
            ang = np.radians(0.8 * aperture / 2)
            for label, d in (("sun centre", sd), ("sun 0.8 to limb", np.cos(ang) * sd + np.sin(ang) * perp)):
                c = render("candela", scene(config, meter(tuple(d), False)))
                m = render("mitsuba", scene(config, meter(tuple(d), False)))
                print(f"  {'':20s} {label:16s} candela {np.array2string(c, precision=1)} mitsuba {np.array2string(m, precision=1)} "
                      f"rel {np.array2string((c - m) / m, precision=2)}")

    print(f"\nirradiance of an upward plane: {a.seeds} seeds x {a.spp} spp; mean +- standard error (R, G, B), z")
    for name, config in CONFIGS.items():
        rotated = "rotate" in config[1]
        e = {r: np.array([render(r, scene(config, lit_plane(rotated, config[2])), a.spp, s + 1) for s in range(a.seeds)]) * (np.pi / 0.5)
             for r in ("candela", "mitsuba")}
        print_seed_means("  " + name, e["candela"], e["mitsuba"], width=22, number="{:.4g}+-{:.2g}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
