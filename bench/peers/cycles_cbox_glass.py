"""bench/peers/scenes/cbox_glass.xml (the validation Cornell box with a smooth glass sphere:
a caustic on the floor) rebuilt in Blender Cycles (CPU), headless. Everything but the sphere is
cycles_cbox.py unchanged (same walls, boxes, light, camera, render settings).

Usage:
  blender -b --factory-startup --python cycles_cbox_glass.py -- \
      --spp 64 --threads 2 --out /path/out.exr

The sphere (cbox_glass.xml: center (-0.4, -0.55, 0.5), radius 0.3, smooth `dielectric`,
int_ior 1.5, ext_ior 1):
  * Cycles 3.4 has no analytic sphere shape for a surface (its point clouds render as spheres,
    but were not tried here for a refracting solid), so the sphere is an icosphere of --subdiv
    levels (default 7: 81,920 triangles, vertices on the sphere; a flat facet lies at most
    4.4e-5 x radius inside it) with exact radial custom normals at the vertices (smooth shading interpolates them;
    Mitsuba and Candela intersect the analytic sphere).
  * Material: Glass BSDF, distribution Sharp, IOR 1.5, colour white. Cycles 3.4's sharp glass
    (svm_closure.h, CLOSURE_BSDF_SHARP_GLASS_ID) splits into a reflection closure of weight F and
    a refraction closure of weight 1 - F with F = fresnel_dielectric_cos (exact unpolarised
    dielectric Fresnel, eta = 1/1.5 on back faces): the same as Mitsuba's `dielectric`. Mitsuba
    scales transmitted radiance by 1/eta^2 and Cycles does not, but every path that enters the
    sphere leaves it (camera and light are outside), so the factors cancel (eta^2 / eta^2).
  * Caustics: reflective and refractive caustics on, filter glossy (blur_glossy) 0, no clamping.

Scene (all from cbox.xml, Mitsuba world coordinates, y up):
  * `rectangle` = [-1,1]^2 in the z=0 plane, normal +z; `cube` = [-1,1]^3, outward normals.
  * every to_world is composed in document order (each element left-multiplies:
    M = translate * rotate * scale), rotations right-handed about the given axis
    (Mitsuba's Transform4f::rotate = Rodrigues), written out explicitly below.
  * walls: floor Rx(-90),T(y=-1); ceiling Rx(90),T(y=1); back T(z=-1);
    left (red) Ry(90),T(x=-1); right (green) Ry(-90),T(x=1).  The box is open at z=+1.
  * tall box:  S(0.3,0.6,0.3), Ry(15),  T(-0.33,-0.4,-0.28)
    short box: S(0.3),         Ry(-18), T(0.33,-0.7,0.3)
  * light: S(0.25), Rx(90), T(y=0.99): 0.5 x 0.5 quad facing -y, one-sided emitter of
    radiance (17,12,4), black diffuse BSDF (= no reflection).  In Cycles: emission on the
    front face, black on the back face, no BSDF.  A Cycles mesh emitter with Emission
    strength 1 has radiance equal to its colour.
  * diffuse BSDFs white (0.725,0.71,0.68), red (0.63,0.065,0.05), green (0.14,0.45,0.091):
    Cycles Diffuse BSDF with roughness 0 (Lambert).  Mitsuba's diffuse is one-sided;
    Cycles' is two-sided, but no path in this scene reaches the back of a wall
    (the box interior only opens to the black environment at z=+1).
  * camera: lookat origin (0,0,3.9) -> (0,0,0), up +y, fov 39.3077 deg along x,
    square 256x256, box filter (1 px).  Mitsuba's camera frame is (left, up, dir) with
    left = cross(up, dir) = -x, and camera +x maps to image LEFT, i.e. image right = +x.
    A Blender camera looks down its local -z with local +x = image right, so its
    world matrix has columns (-left, up, -dir) = identity here: image right = world +x,
    image up = world +y, as in Mitsuba (no mirroring).
  * integrator: Mitsuba path, max_depth=-1 (unbounded, Russian roulette from depth 5)
    -> Cycles bounce limits all set to --bounces (default 64).

Coordinates: by default the whole scene (geometry AND camera) is rotated by
Rx(+90deg), Mitsuba (x,y,z) -> Blender (x,-z,y), so that Blender's z is up (as in
cbox.py).  This is a rigid motion of everything and does not change the image;
--yup keeps Mitsuba's coordinates unchanged (a self-check).

Render settings are those of cbox.py: no adaptive sampling, no denoising, BOX filter
width 1, Standard view transform, float32 RGBA EXR (linear radiance), clamping off,
light threshold 0, fixed thread count.
"""
import os
import sys
import time

T_SCRIPT_START = time.perf_counter()

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))  # Blender runs this file by path
import numpy as np  # noqa: E402
import cycles_common as cc  # noqa: E402


def glass_arguments(ap):
    ap.add_argument("--subdiv", type=int, default=7, help="icosphere subdivisions of the glass sphere (7: 81920 triangles)")
    ap.add_argument("--ior", type=float, default=1.5, help="glass sphere IOR (cbox_glass.xml: 1.5)")


args = cc.parse_args("cycles_cbox_glass.py", "cbox_glass.exr", cc.CBOX_FOV, "cbox.xml", glass_arguments)
C = cc.blender_frame(args.yup)
scene = cc.fresh_scene()
cc.add_cornell_box(scene, C)
# The glass sphere (cbox_glass.xml).
SPHERE_CENTER, SPHERE_RADIUS = np.array([-0.4, -0.55, 0.5]), 0.3
sphere_ob = cc.add_sphere(scene, C, "glass_sphere", SPHERE_CENTER, SPHERE_RADIUS, args.subdiv, cc.glass_material("glass", args.ior))
cc.add_camera(scene, C, *cc.CBOX_CAMERA, args.fov)
cc.configure_render(scene, args)
cc.render("[cbox_glass]", "bench/peers/scenes/cbox_glass.xml", scene, args, T_SCRIPT_START,
          summary_extra={"sphere_triangles": len(sphere_ob.data.polygons)})
