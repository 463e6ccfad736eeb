"""What the Blender Cycles peer scripts share (cycles_cbox.py, cycles_cbox_glass.py,
cycles_envmap.py): their command line, Mitsuba's transforms, the Mitsuba world -> Blender world
frame, the materials and shapes they rebuild, the camera, the render settings and the report.
Each script holds only its scene; it imports this file from its own folder (Blender runs the
script with --python, so the folder is put on sys.path first).

Conventions (see cycles_cbox.py's docstring for the derivations):
  * every Mitsuba to_world is composed in document order (each element left-multiplies),
    rotations right-handed about their axis (Transform4f::rotate = Rodrigues);
  * by default the whole scene is rotated by C = Rx(+90deg), Mitsuba (x, y, z) -> Blender
    (x, -z, y), so that Blender's z is up; a rigid motion that does not change the image
    (--yup keeps Mitsuba's coordinates, a self-check);
  * the camera is Mitsuba's look_at frame (left, up, dir), left = cross(up, dir), as a Blender
    camera with columns (-left, up, -dir), fov along x (Mitsuba's default fov_axis);
  * render settings: no adaptive sampling, no denoising, BOX filter width 1, Standard view
    transform, float32 RGBA EXR (linear radiance), clamping off, light threshold 0, every bounce
    limit --bounces, a fixed thread count.
"""

import argparse
import json
import math
import os
import sys
import time

import bpy
import numpy as np
from mathutils import Matrix, Vector

HERE = os.path.dirname(os.path.abspath(__file__))


# ---------------------------------------------------------------- arguments
def parse_args(prog, default_out, fov, res_help, add_arguments=None):
    """The options every script takes; `add_arguments(ap)` adds a script's own."""
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    ap = argparse.ArgumentParser(prog=prog)
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--res", type=int, default=256, help=f"image width = height ({res_help}: 256)")
    ap.add_argument("--out", default=os.path.join(HERE, "out", default_out))
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--bounces", type=int, default=64, help="Cycles max bounces (total and every per-type limit)")
    ap.add_argument("--fov", type=float, default=fov, help=f"horizontal field of view in degrees ({res_help})")
    if add_arguments:
        add_arguments(ap)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--pattern", default="PROGRESSIVE_MULTI_JITTER", choices=["PROGRESSIVE_MULTI_JITTER", "SOBOL"])
    ap.add_argument("--yup", action="store_true", help="keep Mitsuba's y-up world coordinates (default: rotate to z-up)")
    ap.add_argument("--save-blend", default="", help="optionally save the built scene to this .blend (debug)")
    ap.add_argument("--no-render", action="store_true", help="build the scene only")
    return ap.parse_args(argv)


# ---------------------------------------------------------------- Mitsuba transforms (float64)
def m_translate(x=0.0, y=0.0, z=0.0):
    m = np.eye(4)
    m[:3, 3] = (x, y, z)
    return m


def m_scale(x, y=None, z=None):
    y = x if y is None else y
    z = x if z is None else z
    return np.diag([x, y, z, 1.0])


def m_rotate(axis, angle_deg):
    """Mitsuba Transform4f::rotate(axis, angle): right-handed rotation (Rodrigues)."""
    a = np.asarray(axis, float)
    x, y, z = a / np.linalg.norm(a)
    s, c = math.sin(math.radians(angle_deg)), math.cos(math.radians(angle_deg))
    cm = 1.0 - c
    return np.array([
        [x * x * cm + c, x * y * cm - z * s, x * z * cm + y * s, 0.0],
        [x * y * cm + z * s, y * y * cm + c, y * z * cm - x * s, 0.0],
        [x * z * cm - y * s, y * z * cm + x * s, z * z * cm + c, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ])


def to_world(*ops):
    """Compose <transform> children in document order: each one left-multiplies."""
    m = np.eye(4)
    for op in ops:
        m = op @ m
    return m


def xform_point(M, p):
    return tuple((M @ np.array([*p, 1.0]))[:3])


X, Y = (1, 0, 0), (0, 1, 0)
RX90 = np.array([[1.0, 0, 0, 0], [0, 0, -1, 0], [0, 1, 0, 0], [0, 0, 0, 1]])  # (x, y, z) -> (x, -z, y)


def blender_frame(yup):
    """Mitsuba world -> Blender world: Rx(+90deg) (Mitsuba's +y up becomes Blender's +z), or the
    identity with --yup."""
    return np.eye(4) if yup else RX90


def fresh_scene():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    return bpy.context.scene


# ---------------------------------------------------------------- materials
def new_material(name):
    """An empty node material: (material, node tree, its output node)."""
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    nt = m.node_tree
    nt.nodes.clear()
    return m, nt, nt.nodes.new("ShaderNodeOutputMaterial")


def diffuse_material(name, rgb):
    """Mitsuba diffuse: Cycles Diffuse BSDF with roughness 0 (Lambert, not Oren-Nayar)."""
    m, nt, out = new_material(name)
    d = nt.nodes.new("ShaderNodeBsdfDiffuse")
    d.inputs["Color"].default_value = (*rgb, 1.0)
    d.inputs["Roughness"].default_value = 0.0
    nt.links.new(d.outputs["BSDF"], out.inputs["Surface"])
    return m


def light_material(name, radiance):
    """One-sided emitter, no reflection (Mitsuba: area emitter + black diffuse)."""
    m, nt, out = new_material(name)
    geo = nt.nodes.new("ShaderNodeNewGeometry")
    em = nt.nodes.new("ShaderNodeEmission")
    em.inputs["Color"].default_value = (*radiance, 1.0)
    em.inputs["Strength"].default_value = 1.0
    black = nt.nodes.new("ShaderNodeEmission")
    black.inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)
    black.inputs["Strength"].default_value = 0.0
    # Fac = Backfacing: 0 (front) -> input 1 (emission), 1 (back) -> input 2 (black)
    mix = nt.nodes.new("ShaderNodeMixShader")
    nt.links.new(geo.outputs["Backfacing"], mix.inputs["Fac"])
    nt.links.new(em.outputs["Emission"], mix.inputs[1])
    nt.links.new(black.outputs["Emission"], mix.inputs[2])
    nt.links.new(mix.outputs["Shader"], out.inputs["Surface"])
    if hasattr(m, "cycles") and hasattr(m.cycles, "sample_as_light"):
        m.cycles.sample_as_light = True  # Cycles 3.4: mesh light with MIS
    return m


def mirror_material(name, rgb):
    """Mitsuba conductor, material none (reflectance 1), times specular_reflectance."""
    m, nt, out = new_material(name)
    g = nt.nodes.new("ShaderNodeBsdfGlossy")
    g.distribution = "SHARP"
    g.inputs["Color"].default_value = (*rgb, 1.0)
    g.inputs["Roughness"].default_value = 0.0
    nt.links.new(g.outputs["BSDF"], out.inputs["Surface"])
    return m


def glass_material(name, ior):
    """Mitsuba smooth dielectric (int_ior/ext_ior = ior/1): Glass BSDF, Sharp."""
    m, nt, out = new_material(name)
    g = nt.nodes.new("ShaderNodeBsdfGlass")
    g.distribution = "SHARP"
    g.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    g.inputs["Roughness"].default_value = 0.0
    g.inputs["IOR"].default_value = ior
    nt.links.new(g.outputs["BSDF"], out.inputs["Surface"])
    return m


# ---------------------------------------------------------------- shapes (in world space)
RECT_VERTS = [(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0)]  # CCW seen from +z -> normal +z
RECT_FACES = [(0, 1, 2, 3)]

CUBE_VERTS = [(sx, sy, sz) for sz in (-1, 1) for sy in (-1, 1) for sx in (-1, 1)]  # index = bit k -> axis k


def _cube_faces():
    faces = []
    for axis in range(3):
        for sign in (-1, 1):
            idx = [i for i, v in enumerate(CUBE_VERTS) if v[axis] == sign]
            # order the 4 corners CCW around the outward normal
            u, w = [(axis + 1) % 3, (axis + 2) % 3]
            idx.sort(key=lambda i: math.atan2(CUBE_VERTS[i][w], CUBE_VERTS[i][u]))
            if sign < 0:
                idx.reverse()
            faces.append(tuple(idx))
    return faces


CUBE_FACES = _cube_faces()


def add_shape(scene, C, name, kind, m_to_world, mat):
    """Mitsuba's `rectangle` ([-1,1]^2 at z=0, normal +z) or `cube` ([-1,1]^3, outward normals),
    flat shaded, its vertices in world space (identity object transform)."""
    verts, faces = (RECT_VERTS, RECT_FACES) if kind == "rectangle" else (CUBE_VERTS, CUBE_FACES)
    M = C @ m_to_world
    assert np.linalg.det(M[:3, :3]) > 0  # winding (and hence normals) preserved
    me = bpy.data.meshes.new(name)
    me.from_pydata([xform_point(M, v) for v in verts], [], faces)
    me.validate()
    me.update()
    me.materials.append(mat)
    for poly in me.polygons:
        poly.use_smooth = False
    ob = bpy.data.objects.new(name, me)
    scene.collection.objects.link(ob)
    # checks: rectangle normal = M * (+z); cube faces point away from the centre
    N = np.linalg.inv(M[:3, :3]).T  # normals transform with the inverse transpose
    if kind == "rectangle":
        want = N @ np.array([0.0, 0.0, 1.0])
        want /= np.linalg.norm(want)
        got = np.array(me.polygons[0].normal)
        assert np.abs(got - want).max() < 1e-5, (name, got, want)
    else:
        ctr = Vector(xform_point(M, (0, 0, 0)))
        for poly in me.polygons:
            assert poly.normal.dot(poly.center - ctr) > 0, (name, poly.index)
    return ob


def add_sphere(scene, C, name, center, radius, subdiv, mat):
    """Icosphere with vertices on the sphere and exact radial (custom split) normals, in world
    space (Cycles 3.4 has no analytic sphere surface; a facet lies at most 4.4e-5 x radius inside
    the sphere at 7 subdivisions)."""
    import bmesh
    bm = bmesh.new()
    bmesh.ops.create_icosphere(bm, subdivisions=subdiv, radius=1.0)
    unit = np.array([tuple(v.co) for v in bm.verts], float)
    unit /= np.linalg.norm(unit, axis=1)[:, None]  # exactly on the unit sphere
    faces = [tuple(v.index for v in f.verts) for f in bm.faces]
    bm.free()
    ctr_b = np.array(xform_point(C, center))
    normals_b = unit @ C[:3, :3].T  # the rigid motion C applied to the normals
    verts_b = ctr_b + radius * normals_b
    me = bpy.data.meshes.new(name)
    me.from_pydata([tuple(v) for v in verts_b], [], faces)
    me.validate()
    me.update()
    for poly in me.polygons:
        poly.use_smooth = True
    me.use_auto_smooth = True  # needed for custom normals in 3.4
    me.auto_smooth_angle = math.pi
    me.normals_split_custom_set_from_vertices([tuple(n) for n in normals_b])
    me.materials.append(mat)
    ob = bpy.data.objects.new(name, me)
    scene.collection.objects.link(ob)
    # outward winding: every face normal points away from the centre
    fc = np.array([tuple(p.center) for p in me.polygons]) - ctr_b
    fn = np.array([tuple(p.normal) for p in me.polygons])
    assert (np.einsum("ij,ij->i", fc, fn) > 0).all(), "sphere faces must point outward"
    return ob


def black_world(scene):
    """No environment light."""
    world = bpy.data.worlds.new("black")
    world.use_nodes = True
    bg = world.node_tree.nodes.get("Background")
    bg.inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)
    bg.inputs["Strength"].default_value = 0.0
    scene.world = world
    return world


# ---------------------------------------------------------------- the validation Cornell box
def add_cornell_box(scene, C):
    """The scene of scenes/validation/cbox.xml (cycles_cbox.py's docstring describes it): walls,
    two boxes and the one-sided area light, in a black world. Returns the objects by name."""
    white, red, green = (0.725, 0.71, 0.68), (0.63, 0.065, 0.05), (0.14, 0.45, 0.091)
    shapes = [
        # name, kind, to_world, material
        ("floor", "rectangle", to_world(m_rotate(X, -90), m_translate(y=-1)), "white"),
        ("ceiling", "rectangle", to_world(m_rotate(X, 90), m_translate(y=1)), "white"),
        ("back", "rectangle", to_world(m_translate(z=-1)), "white"),
        ("left", "rectangle", to_world(m_rotate(Y, 90), m_translate(x=-1)), "red"),
        ("right", "rectangle", to_world(m_rotate(Y, -90), m_translate(x=1)), "green"),
        ("tall_box", "cube", to_world(m_scale(0.3, 0.6, 0.3), m_rotate(Y, 15), m_translate(x=-0.33, y=-0.4, z=-0.28)), "white"),
        ("short_box", "cube", to_world(m_scale(0.3), m_rotate(Y, -18), m_translate(x=0.33, y=-0.7, z=0.3)), "white"),
        ("light", "rectangle", to_world(m_scale(0.25), m_rotate(X, 90), m_translate(y=0.99)), "light"),
    ]
    mats = {
        "white": diffuse_material("white", white),
        "red": diffuse_material("red", red),
        "green": diffuse_material("green", green),
        "light": light_material("light", (17.0, 12.0, 4.0)),
    }
    objs = {name: add_shape(scene, C, name, kind, M, mats[mat]) for name, kind, M, mat in shapes}
    ln = C[:3, :3].T @ np.array(objs["light"].data.polygons[0].normal)  # back in Mitsuba coords
    assert np.abs(ln - np.array([0.0, -1.0, 0.0])).max() < 1e-6, f"light must face -y (down): {ln}"
    black_world(scene)
    return objs


# The Cornell box's camera: look_at (0, 0, 3.9) -> (0, 0, 0), up +y, fov 39.3077 deg along x.
CBOX_CAMERA = (np.array([0.0, 0.0, 3.9]), np.array([0.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0]))
CBOX_FOV = 39.3077


# ---------------------------------------------------------------- camera
def add_camera(scene, C, origin, target, up_hint, fov_deg):
    """Mitsuba's perspective look_at camera: the Blender camera frame's columns (image-right,
    image-up, backwards) are (-left, up, -dir) of Mitsuba's frame (left, up, dir)."""
    d = target - origin
    d /= np.linalg.norm(d)
    left = np.cross(up_hint, d)
    left /= np.linalg.norm(left)
    up = np.cross(d, left)
    frame = np.eye(4)
    frame[:3, 0], frame[:3, 1], frame[:3, 2], frame[:3, 3] = -left, up, -d, origin  # columns
    assert abs(np.linalg.det(frame[:3, :3]) - 1.0) < 1e-12
    cam_data = bpy.data.cameras.new("cam")
    cam_data.type = "PERSP"
    cam_data.sensor_fit = "HORIZONTAL"  # Mitsuba fov_axis = x
    cam_data.lens_unit = "FOV"
    cam_data.angle = math.radians(fov_deg)
    cam_data.clip_start = 1e-2
    cam_data.clip_end = 1e4
    cam_data.dof.use_dof = False
    cam_data.shift_x = cam_data.shift_y = 0.0
    cam = bpy.data.objects.new("cam", cam_data)
    cam.matrix_world = Matrix((C @ frame).tolist())
    scene.collection.objects.link(cam)
    scene.camera = cam
    return cam


# ---------------------------------------------------------------- render settings
def configure_render(scene, args):
    r = scene.render
    r.engine = "CYCLES"
    r.resolution_x = args.res
    r.resolution_y = args.res
    r.resolution_percentage = 100
    r.pixel_aspect_x = r.pixel_aspect_y = 1.0
    r.use_border = False
    r.film_transparent = False
    r.use_motion_blur = False
    r.use_persistent_data = False
    r.threads_mode = "FIXED"
    r.threads = args.threads
    r.use_compositing = False
    r.use_sequencer = False
    r.dither_intensity = 0.0
    r.filepath = args.out
    r.use_file_extension = False
    r.use_overwrite = True
    r.use_stamp = False
    r.use_stamp_render_time = True  # Cycles writes its timing fields into the EXR header

    im = r.image_settings
    im.file_format = "OPEN_EXR"
    im.color_depth = "32"
    im.color_mode = "RGBA"
    im.exr_codec = "ZIP"

    vs = scene.view_settings
    vs.view_transform = "Standard"
    vs.look = "None"
    vs.exposure = 0.0
    vs.gamma = 1.0
    vs.use_curve_mapping = False
    scene.display_settings.display_device = "sRGB"

    c = scene.cycles
    c.device = "CPU"
    c.feature_set = "SUPPORTED"
    c.shading_system = False  # SVM, not OSL
    c.samples = args.spp
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.use_preview_denoising = False
    c.sampling_pattern = args.pattern
    c.seed = args.seed
    c.use_animated_seed = False
    c.scrambling_distance = 1.0
    c.auto_scrambling_distance = False
    c.light_sampling_threshold = 0.0
    c.sample_clamp_direct = 0.0
    c.sample_clamp_indirect = 0.0
    c.blur_glossy = 0.0
    c.caustics_reflective = True
    c.caustics_refractive = True
    c.max_bounces = args.bounces
    c.diffuse_bounces = args.bounces
    c.glossy_bounces = args.bounces
    c.transmission_bounces = args.bounces
    c.volume_bounces = 0
    c.transparent_max_bounces = args.bounces
    c.min_light_bounces = 0
    c.min_transparent_bounces = 0
    c.use_fast_gi = False
    c.pixel_filter_type = "BOX"
    c.filter_width = 1.0
    c.film_exposure = 1.0
    c.use_layer_samples = "IGNORE"
    c.use_auto_tile = False
    c.debug_use_spatial_splits = False

    vl = scene.view_layers[0]
    vl.use_pass_combined = True
    vl.cycles.denoising_store_passes = False
    vl.cycles.use_denoising = False

    if args.save_blend:
        bpy.ops.wm.save_as_mainfile(filepath=os.path.abspath(args.save_blend))
    os.makedirs(os.path.dirname(os.path.abspath(args.out)) or ".", exist_ok=True)


# ---------------------------------------------------------------- render and report
def render(tag, scene_name, scene, args, t_script_start, settings_note="", summary_extra=None):
    """Prints the set-up, then (unless --no-render) renders, prints the timing and writes a JSON
    summary beside the EXR. `settings_note` ends the settings line; `summary_extra` (a dict) goes
    into the summary after the bounce limit."""
    import _cycles

    r, c = scene.render, scene.cycles
    t_setup_done = time.perf_counter()
    print(f"{tag} blender {bpy.app.version_string}, cycles with_embree={_cycles.with_embree}, "
          f"bvh_layout={c.debug_bvh_layout}, device={c.device}, threads={r.threads} ({r.threads_mode}), "
          f"coords={'y-up (Mitsuba)' if args.yup else 'z-up (Rx90 of Mitsuba)'}", flush=True)
    print(f"{tag} spp={c.samples} res={r.resolution_x}x{r.resolution_y} bounces={c.max_bounces} "
          f"filter={c.pixel_filter_type}/{c.filter_width} pattern={c.sampling_pattern} "
          f"adaptive={c.use_adaptive_sampling} denoise={c.use_denoising} "
          f"light_threshold={c.light_sampling_threshold} clamp={c.sample_clamp_direct}/{c.sample_clamp_indirect} "
          f"view={scene.view_settings.view_transform}{settings_note}", flush=True)
    print(f"{tag} camera world matrix = {[list(map(lambda v: round(v, 6), row)) for row in scene.camera.matrix_world]}",
          flush=True)
    print(f"{tag} scene setup (python, in-process) {t_setup_done - t_script_start:.3f} s", flush=True)
    if args.no_render:
        print(f"{tag} --no-render: scene built, not rendering", flush=True)
        return

    bpy.ops.render.render(write_still=True)
    render_s = time.perf_counter() - t_setup_done
    n = args.res * args.res * args.spp
    summary = {
        "scene": scene_name,
        "blender": bpy.app.version_string,
        "embree": bool(_cycles.with_embree),
        "spp": args.spp,
        "res": args.res,
        "threads": args.threads,
        "bounces": args.bounces,
        **(summary_extra or {}),
        "seed": args.seed,
        "yup": args.yup,
        "out": os.path.abspath(args.out),
        "setup_s": round(t_setup_done - t_script_start, 4),
        "render_call_s": round(render_s, 4),
        "samples": n,
        "msamples_per_s_render_call": round(n / render_s / 1e6, 4),
    }
    print(f"{tag} render call (Cycles sync+BVH+path tracing+EXR write) {render_s:.3f} s; "
          f"{n} samples -> {n / render_s / 1e6:.3f} Msamples/s", flush=True)
    print(f"{tag} SUMMARY " + json.dumps(summary), flush=True)
    with open(os.path.splitext(os.path.abspath(args.out))[0] + ".json", "w") as f:
        json.dump(summary, f, indent=1)
