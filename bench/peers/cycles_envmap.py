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
import math
import os
import sys
import time

T_SCRIPT_START = time.perf_counter()

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))  # Blender runs this file by path
import bpy  # noqa: E402
import numpy as np  # noqa: E402
from mathutils import Matrix  # noqa: E402
import cycles_common as cc  # noqa: E402


def envmap_arguments(ap):
    ap.add_argument("--envmap", default=os.path.join(cc.HERE, "..", "..", "scenes", "validation", "textures", "sky.exr"))
    ap.add_argument("--subdiv", type=int, default=7, help="icosphere subdivisions of each sphere (7: 81920 triangles)")
    ap.add_argument("--world-sampling", default="AUTOMATIC", choices=["AUTOMATIC", "MANUAL", "NONE"])
    ap.add_argument("--world-map-res", type=int, default=1024, help="MIS map resolution with --world-sampling MANUAL")


args = cc.parse_args("cycles_envmap.py", "envmap_object.exr", 45.0, "envmap_object.xml", envmap_arguments)
C = cc.blender_frame(args.yup)

# ---------------------------------------------------------------- scene description (envmap_object.xml)
GROUND = cc.to_world(cc.m_scale(2.5), cc.m_rotate(cc.X, -90))
GROUND_ALBEDO = (0.5, 0.5, 0.5)
SPHERES = [  # name, centre, radius, material
    ("diffuse_sphere", (0.75, 0.5, -0.3), 0.5, "diffuse"),
    ("mirror_sphere", (-0.75, 0.5, -0.3), 0.5, "mirror"),
    ("glass_sphere", (0.0, 0.35, 0.8), 0.35, "glass"),
]
CAM_ORIGIN, CAM_TARGET, CAM_UP = np.array([0.0, 1.4, 4.2]), np.array([0.0, 0.4, 0.0]), np.array([0.0, 1.0, 0.0])
ENV_TO_WORLD = np.eye(4)  # the envmap's to_world (identity in envmap_object.xml)
ENV_SCALE = 1.0

scene = cc.fresh_scene()
MATS = {
    "ground": cc.diffuse_material("ground", GROUND_ALBEDO),
    "diffuse": cc.diffuse_material("diffuse", (0.7, 0.35, 0.2)),
    "mirror": cc.mirror_material("mirror", (0.9, 0.9, 0.9)),
    "glass": cc.glass_material("glass", 1.5),
}
cc.add_shape(scene, C, "ground", "rectangle", GROUND, MATS["ground"])
spheres = [cc.add_sphere(scene, C, n, c_, r_, args.subdiv, MATS[m_]) for n, c_, r_, m_ in SPHERES]


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
RZ90 = cc.m_rotate((0, 0, 1), 90.0)[:3, :3]
E = RZ90 @ cc.RX90[:3, :3] @ np.linalg.inv(ENV_TO_WORLD[:3, :3]) @ np.linalg.inv(C[:3, :3])
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

cc.add_camera(scene, C, CAM_ORIGIN, CAM_TARGET, CAM_UP, args.fov)
cc.configure_render(scene, args)
cc.render("[envmap_object]", "bench/peers/scenes/envmap_object.xml", scene, args, T_SCRIPT_START,
          settings_note=f" world_sampling={world.cycles.sampling_method} envmap mapping euler(deg)="
                        f"{[round(math.degrees(a), 6) for a in eul]}",
          summary_extra={"sphere_triangles": sum(len(s.data.polygons) for s in spheres),
                         "world_sampling": world.cycles.sampling_method})
