"""bench/peers/scenes/envmap_object.xml (three spheres on a diffuse ground square, lit only by an
environment map) rebuilt in Blender Cycles (CPU), headless. Transforms, camera and render
settings follow cycles_cbox.py.

Usage:
  blender -b --factory-startup --python cycles_envmap.py -- \
      --spp 64 --threads 2 --out /path/out.exr

Scene (all from envmap_object.xml, Mitsuba world coordinates, y up):
  * ground: `rectangle` [-1,1]^2 (z=0, normal +z), to_world S(2.5), Rx(-90): the y=0 plane,
    normal +y, Lambertian 0.5.  Mitsuba's diffuse is one-sided and Cycles' two-sided, but no
    path vertex is ever below the ground (the spheres stand on it), so its back is never seen.
  * spheres (Mitsuba: analytic; Cycles: icosphere of --subdiv levels, default 7 = 81,920
    triangles with vertices on the sphere and exact radial custom normals at the vertices,
    smooth shading; a facet lies at most 4.4e-5 x radius inside the sphere):
      diffuse (0.75, 0.5, -0.3) r 0.5, Lambertian (0.7, 0.35, 0.2): Diffuse BSDF, roughness 0;
      mirror  (-0.75, 0.5, -0.3) r 0.5, conductor material "none" (eta 0, k 1: Fresnel
        reflectance exactly 1 at every angle) x specular_reflectance 0.9: Glossy BSDF, Sharp,
        colour 0.9 (Cycles' sharp glossy is a perfect mirror weighted by its colour, no Fresnel);
      glass   (0, 0.35, 0.8) r 0.35, smooth dielectric 1.5/1.0: Glass BSDF, Sharp, IOR 1.5,
        white (exact dielectric Fresnel, see cycles_cbox_glass.py).
  * light: only the envmap, scenes/validation/textures/sky.exr (512 x 256 lat-long, linear
    float), scale 1, to_world identity.  Mitsuba's envmap looks up a world direction d (after
    to_world^-1) at u = atan2(d.x, -d.z) / 2pi, v = acos(d.y) / pi (row 0 = up, +y).  Blender's
    Environment Texture (equirectangular) looks up e at u = 0.5 - atan2(e.y, e.x) / 2pi,
    v = 0.5 + asin(e.z) / pi (top = +z).  With the scene rotated to Blender's z-up by
    C = Rx(+90) ((x, y, z) -> (x, -z, y)), the two agree when e = Rz(+90) C d_mitsuba, i.e. a
    Mapping node (Point) rotating the Blender direction by Rz(+90deg): checked on the three
    directions -z -> u 0, +x -> u 0.25, +z -> u 0.5 in the assertions below, and by comparing
    the images with Mitsuba's (sky and sun reflection in the mirror sphere, shadow directions).
    Interpolation Linear (bilinear, as Mitsuba's envmap), colour space Linear (no transform).
    World importance sampling: Cycles' MIS map, sampling method Automatic (the map resolution
    follows the texture: 512 x 256, the envmap's own pixels, as Mitsuba's warp).
  * camera: lookat (0, 1.4, 4.2) -> (0, 0.4, 0), up +y, fov 45 deg along x (Mitsuba's
    default fov_axis x; Blender sensor fit Horizontal), 256 x 256, box filter 1 px.
  * integrator: Mitsuba path, max_depth -1 -> Cycles bounce limits all --bounces (default 64).

Coordinates: by default the whole scene (geometry, camera AND environment) is rotated by
Rx(+90deg) to Blender's z-up; --yup keeps Mitsuba's coordinates (a self-check: the environment
mapping is then built for that frame, and the image must not change).
"""

import argparse
import json
import math
import os
import sys
import time

T_SCRIPT_START = time.perf_counter()

import bpy  # noqa: E402
import numpy as np  # noqa: E402
from mathutils import Matrix  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))

# ---------------------------------------------------------------- arguments
argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
ap = argparse.ArgumentParser(prog="cycles_envmap.py")
ap.add_argument("--spp", type=int, default=64)
ap.add_argument("--res", type=int, default=256, help="image width = height (envmap_object.xml: 256)")
ap.add_argument("--out", default=os.path.join(HERE, "out", "envmap_object.exr"))
ap.add_argument("--threads", type=int, default=2)
ap.add_argument("--bounces", type=int, default=64, help="Cycles max bounces (total and every per-type limit)")
ap.add_argument("--fov", type=float, default=45.0, help="horizontal field of view in degrees (envmap_object.xml)")
ap.add_argument("--envmap", default=os.path.join(HERE, "..", "..", "scenes", "validation", "textures", "sky.exr"))
ap.add_argument("--subdiv", type=int, default=7, help="icosphere subdivisions of each sphere (7: 81920 triangles)")
ap.add_argument("--seed", type=int, default=0)
ap.add_argument("--pattern", default="PROGRESSIVE_MULTI_JITTER", choices=["PROGRESSIVE_MULTI_JITTER", "SOBOL"])
ap.add_argument("--world-sampling", default="AUTOMATIC", choices=["AUTOMATIC", "MANUAL", "NONE"])
ap.add_argument("--world-map-res", type=int, default=1024, help="MIS map resolution with --world-sampling MANUAL")
ap.add_argument("--yup", action="store_true", help="keep Mitsuba's y-up world coordinates (default: rotate to z-up)")
ap.add_argument("--save-blend", default="", help="optionally save the built scene to this .blend (debug)")
ap.add_argument("--no-render", action="store_true", help="build the scene only")
args = ap.parse_args(argv)


# ---------------------------------------------------------------- Mitsuba transforms (float64)
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


X = (1, 0, 0)
RX90 = np.array([[1.0, 0, 0, 0], [0, 0, -1, 0], [0, 1, 0, 0], [0, 0, 0, 1]])  # (x,y,z) -> (x,-z,y)
# Mitsuba world -> Blender world, a rigid rotation (identity with --yup).
C = np.eye(4) if args.yup else RX90

# ---------------------------------------------------------------- scene description (envmap_object.xml)
GROUND = to_world(m_scale(2.5), m_rotate(X, -90))
GROUND_ALBEDO = (0.5, 0.5, 0.5)
SPHERES = [  # name, centre, radius, material
    ("diffuse_sphere", (0.75, 0.5, -0.3), 0.5, "diffuse"),
    ("mirror_sphere", (-0.75, 0.5, -0.3), 0.5, "mirror"),
    ("glass_sphere", (0.0, 0.35, 0.8), 0.35, "glass"),
]
CAM_ORIGIN, CAM_TARGET, CAM_UP = np.array([0.0, 1.4, 4.2]), np.array([0.0, 0.4, 0.0]), np.array([0.0, 1.0, 0.0])
ENV_TO_WORLD = np.eye(4)  # the envmap's to_world (identity in envmap_object.xml)
ENV_SCALE = 1.0

# ---------------------------------------------------------------- fresh scene
bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene


def new_material(name):
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    nt = m.node_tree
    nt.nodes.clear()
    return m, nt, nt.nodes.new("ShaderNodeOutputMaterial")


def diffuse_material(name, rgb):
    m, nt, out = new_material(name)
    d = nt.nodes.new("ShaderNodeBsdfDiffuse")
    d.inputs["Color"].default_value = (*rgb, 1.0)
    d.inputs["Roughness"].default_value = 0.0  # Lambert (not Oren-Nayar)
    nt.links.new(d.outputs["BSDF"], out.inputs["Surface"])
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


MATS = {
    "ground": diffuse_material("ground", GROUND_ALBEDO),
    "diffuse": diffuse_material("diffuse", (0.7, 0.35, 0.2)),
    "mirror": mirror_material("mirror", (0.9, 0.9, 0.9)),
    "glass": glass_material("glass", 1.5),
}


def add_rectangle(name, m_to_world, mat):
    M = C @ m_to_world
    assert np.linalg.det(M[:3, :3]) > 0
    me = bpy.data.meshes.new(name)
    me.from_pydata([xform_point(M, v) for v in [(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0)]], [], [(0, 1, 2, 3)])
    me.validate()
    me.update()
    me.materials.append(mat)
    me.polygons[0].use_smooth = False
    ob = bpy.data.objects.new(name, me)
    scene.collection.objects.link(ob)
    want = np.linalg.inv(M[:3, :3]).T @ np.array([0.0, 0.0, 1.0])
    want /= np.linalg.norm(want)
    assert np.abs(np.array(me.polygons[0].normal) - want).max() < 1e-5, (name, want)
    return ob


def add_sphere(name, center, radius, subdiv, mat):
    """Icosphere with vertices on the sphere and exact radial (custom split) normals, in world space."""
    import bmesh
    bm = bmesh.new()
    bmesh.ops.create_icosphere(bm, subdivisions=subdiv, radius=1.0)
    unit = np.array([tuple(v.co) for v in bm.verts], float)
    unit /= np.linalg.norm(unit, axis=1)[:, None]  # exactly on the unit sphere
    faces = [tuple(v.index for v in f.verts) for f in bm.faces]
    bm.free()
    ctr_b = np.array(xform_point(C, center))
    normals_b = unit @ C[:3, :3].T
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
    fc = np.array([tuple(p.center) for p in me.polygons]) - ctr_b
    fn = np.array([tuple(p.normal) for p in me.polygons])
    assert (np.einsum("ij,ij->i", fc, fn) > 0).all(), "sphere faces must point outward"
    return ob


add_rectangle("ground", GROUND, MATS["ground"])
spheres = [add_sphere(n, c_, r_, args.subdiv, MATS[m_]) for n, c_, r_, m_ in SPHERES]


# ---------------------------------------------------------------- environment
def mitsuba_uv(d):
    u = math.atan2(d[0], -d[2]) / (2 * math.pi)
    return u - math.floor(u), math.acos(max(-1.0, min(1.0, d[1]))) / math.pi


def blender_uv(e):
    """Cycles direction_to_equirectangular (full sphere), v measured from the top as Mitsuba's."""
    e = np.asarray(e, float) / np.linalg.norm(e)
    u = 0.5 - math.atan2(e[1], e[0]) / (2 * math.pi)
    return u - math.floor(u), 1.0 - (0.5 + math.asin(max(-1.0, min(1.0, e[2]))) / math.pi)


# Blender world direction d -> Mitsuba world C^-1 d -> envmap frame to_world^-1 C^-1 d ->
# the Blender-native direction with the same (u, v): Rz(90) RX90 (see the docstring).
RZ90 = m_rotate((0, 0, 1), 90.0)[:3, :3]
E = RZ90 @ RX90[:3, :3] @ np.linalg.inv(ENV_TO_WORLD[:3, :3]) @ np.linalg.inv(C[:3, :3])
for d_m in [(0, 0, -1), (1, 0, 0), (0, 0, 1), (0, 1, 0), (0.3, -0.5, 0.8), (-0.61, 0.64, -0.46)]:
    d_m = np.asarray(d_m, float) / np.linalg.norm(d_m)
    d_b = C[:3, :3] @ ENV_TO_WORLD[:3, :3] @ d_m
    um, vm = mitsuba_uv(d_m)
    ub, vb = blender_uv(E @ d_b)
    if abs(d_m[1]) < 0.999:  # u is undefined at the poles
        assert min(abs(um - ub), 1 - abs(um - ub)) < 1e-9, (d_m, um, ub)
    assert abs(vm - vb) < 1e-9, (d_m, vm, vb)
assert abs(mitsuba_uv((0, 0, -1))[0]) < 1e-12 and abs(mitsuba_uv((1, 0, 0))[0] - 0.25) < 1e-12

world = bpy.data.worlds.new("env")
world.use_nodes = True
wnt = world.node_tree
bg = wnt.nodes.get("Background")
bg.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
bg.inputs["Strength"].default_value = ENV_SCALE
img = bpy.data.images.load(os.path.abspath(args.envmap), check_existing=False)
img.colorspace_settings.name = "Linear"
assert img.is_float and tuple(img.size) == (512, 256) or "sky.exr" not in args.envmap, (img.is_float, tuple(img.size))
env = wnt.nodes.new("ShaderNodeTexEnvironment")
env.image = img
env.interpolation = "Linear"
env.projection = "EQUIRECTANGULAR"
tc = wnt.nodes.new("ShaderNodeTexCoord")
mp = wnt.nodes.new("ShaderNodeMapping")
mp.vector_type = "POINT"
eul = Matrix(E.tolist()).to_euler("XYZ")
mp.inputs["Rotation"].default_value = eul
mp.inputs["Location"].default_value = (0.0, 0.0, 0.0)
mp.inputs["Scale"].default_value = (1.0, 1.0, 1.0)
# the Euler angles give back E (Mapping: R = Rz Ry Rx, as mathutils' XYZ order)
assert np.abs(np.array(eul.to_matrix()) - E).max() < 1e-6  # mathutils is float32
wnt.links.new(tc.outputs["Generated"], mp.inputs["Vector"])
wnt.links.new(mp.outputs["Vector"], env.inputs["Vector"])
wnt.links.new(env.outputs["Color"], bg.inputs["Color"])
world.cycles.sampling_method = args.world_sampling
world.cycles.sample_map_resolution = args.world_map_res
world.cycles.max_bounces = args.bounces
scene.world = world

# Camera: Mitsuba look_at frame (left, up, dir), left = cross(up, dir); Blender camera frame
# columns (image-right, image-up, backwards) = (-left, up, -dir).
d = CAM_TARGET - CAM_ORIGIN
d /= np.linalg.norm(d)
left = np.cross(CAM_UP, d)
left /= np.linalg.norm(left)
up = np.cross(d, left)
CAM = np.eye(4)
CAM[:3, 0], CAM[:3, 1], CAM[:3, 2], CAM[:3, 3] = -left, up, -d, CAM_ORIGIN  # columns
assert abs(np.linalg.det(CAM[:3, :3]) - 1.0) < 1e-12
cam_data = bpy.data.cameras.new("cam")
cam_data.type = "PERSP"
cam_data.sensor_fit = "HORIZONTAL"  # Mitsuba fov_axis = x
cam_data.lens_unit = "FOV"
cam_data.angle = math.radians(args.fov)
cam_data.clip_start = 1e-2
cam_data.clip_end = 1e4
cam_data.dof.use_dof = False
cam_data.shift_x = cam_data.shift_y = 0.0
cam = bpy.data.objects.new("cam", cam_data)
cam.matrix_world = Matrix((C @ CAM).tolist())
scene.collection.objects.link(cam)
scene.camera = cam

# ---------------------------------------------------------------- render settings (as cycles_cbox.py)
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
r.use_stamp_render_time = True

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

import _cycles  # noqa: E402

T_SETUP_DONE = time.perf_counter()
TAG = "[envmap_object]"
print(f"{TAG} blender {bpy.app.version_string}, cycles with_embree={_cycles.with_embree}, "
      f"bvh_layout={c.debug_bvh_layout}, device={c.device}, threads={r.threads} ({r.threads_mode}), "
      f"coords={'y-up (Mitsuba)' if args.yup else 'z-up (Rx90 of Mitsuba)'}", flush=True)
print(f"{TAG} spp={c.samples} res={r.resolution_x}x{r.resolution_y} bounces={c.max_bounces} "
      f"filter={c.pixel_filter_type}/{c.filter_width} pattern={c.sampling_pattern} "
      f"adaptive={c.use_adaptive_sampling} denoise={c.use_denoising} "
      f"world_sampling={world.cycles.sampling_method} envmap mapping euler(deg)="
      f"{[round(math.degrees(a), 6) for a in eul]} clamp={c.sample_clamp_direct}/{c.sample_clamp_indirect}", flush=True)
print(f"{TAG} scene setup (python, in-process) {T_SETUP_DONE - T_SCRIPT_START:.3f} s", flush=True)


def render_and_report():
    bpy.ops.render.render(write_still=True)
    t_done = time.perf_counter()
    render_s = t_done - T_SETUP_DONE
    n = args.res * args.res * args.spp
    summary = {
        "scene": "bench/peers/scenes/envmap_object.xml",
        "blender": bpy.app.version_string,
        "embree": bool(_cycles.with_embree),
        "spp": args.spp,
        "res": args.res,
        "threads": args.threads,
        "bounces": args.bounces,
        "sphere_triangles": sum(len(s.data.polygons) for s in spheres),
        "world_sampling": world.cycles.sampling_method,
        "seed": args.seed,
        "yup": args.yup,
        "out": os.path.abspath(args.out),
        "setup_s": round(T_SETUP_DONE - T_SCRIPT_START, 4),
        "render_call_s": round(render_s, 4),
        "samples": n,
        "msamples_per_s_render_call": round(n / render_s / 1e6, 4),
    }
    print(f"{TAG} render call (Cycles sync+BVH+path tracing+EXR write) {render_s:.3f} s; "
          f"{n} samples -> {n / render_s / 1e6:.3f} Msamples/s", flush=True)
    print(f"{TAG} SUMMARY " + json.dumps(summary), flush=True)
    with open(os.path.splitext(os.path.abspath(args.out))[0] + ".json", "w") as f:
        json.dump(summary, f, indent=1)


if args.no_render:
    print(f"{TAG} --no-render: scene built, not rendering", flush=True)
else:
    render_and_report()
