#!/usr/bin/python3
"""Candela's measuring sensors and batch sensor against Mitsuba 3, on one scene.

bench/peers/scenes/meters.xml is the validation Cornell box seen by a radiancemeter (sensor 0), a
distant sensor (1), a batch of two cameras (2) and an irradiancemeter nested in a floor square
(3). Each meter is rendered by both renderers with SEEDS independent seeds of SPP samples; the
script prints each renderer's mean per channel with its standard error (from the spread over the
seeds) and the difference in units of the combined error. The batch image is compared by relMSE
(mean of (a - b)^2 / (b^2 + 0.01)) between the renderers and between two seeds of each.

  meters.py --candela build/candela --mitsuba /tmp/mitsuba3/mitsuba [--spp 65536 --seeds 32]

Mitsuba runs scalar_rgb; its folder is put on LD_LIBRARY_PATH. Without the peer the script says
so and stops.
"""
import os, subprocess, sys, tempfile
import numpy as np

import candela
from mitsuba_peer import peer_command_line, print_seed_means

SCENE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "scenes", "meters.xml")


def load(path):
    return np.asarray(candela.read_image(path))[..., :3].astype(np.float64)


def relmse(a, b):
    return float(np.mean((a - b) ** 2 / (b ** 2 + 1e-2)))


def main():
    a, env = peer_command_line(spp=65536, seeds=32, add_arguments=lambda ap: ap.add_argument("--batch-spp", type=int, default=1024))
    if env is None:
        return 0
    tmp = tempfile.mkdtemp()

    def render(renderer, sensor, spp, seed):
        out = os.path.join(tmp, f"{renderer}-{sensor}-{spp}-{seed}.exr")
        if renderer == "candela":
            cmd = [a.candela, "render", SCENE, "-s", str(sensor), "-D", f"spp={spp}", "-D", f"seed={seed}", "-o", out, "--quiet"]
        else:
            cmd = [a.mitsuba, "-m", "scalar_rgb", "-t", "2", "-s", str(sensor), f"-Dspp={spp}", f"-Dseed={seed}", "-o", out, SCENE]
        p = subprocess.run(cmd, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        if p.returncode != 0 or not os.path.exists(out):
            sys.exit(f"{renderer} failed on sensor {sensor}: {p.stderr.decode()[-400:]}")
        return load(out)

    print(f"meters: {a.seeds} seeds x {a.spp} spp each; mean +- standard error per channel (R, G, B)")
    for sensor, name in ((0, "radiancemeter"), (1, "distant"), (3, "irradiancemeter")):
        values = {r: np.array([render(r, sensor, a.spp, seed + 1).reshape(3) for seed in range(a.seeds)]) for r in ("candela", "mitsuba")}
        print_seed_means(name, values["candela"], values["mitsuba"])
    images = {(r, s): render(r, 2, a.batch_spp, s) for r in ("candela", "mitsuba") for s in (1, 2)}
    print(f"batch (two cameras, 128 x 64, {a.batch_spp} spp): relMSE candela vs mitsuba "
          f"{relmse(images['candela', 1], images['mitsuba', 1]):.3e} and {relmse(images['candela', 2], images['mitsuba', 2]):.3e}; "
          f"seed to seed: candela {relmse(images['candela', 1], images['candela', 2]):.3e}, "
          f"mitsuba {relmse(images['mitsuba', 1], images['mitsuba', 2]):.3e}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
