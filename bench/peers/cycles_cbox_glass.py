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

Scene, coordinates and render settings: as cycles_cbox.py (its docstring states each one and
where it comes from); only the sphere above is new.
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
