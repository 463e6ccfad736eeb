# Written like Mitsuba 3's tutorials that build a scene in Python with load_dict; the only change
# for Candela is the import line.
import candela.mitsuba as mi

mi.set_variant("llvm_ad_rgb")

T = mi.ScalarTransform4f

scene = mi.load_dict({
    "type": "scene",
    "integrator": {"type": "path", "max_depth": 6},
    "sky": {"type": "constant", "radiance": {"type": "rgb", "value": 0.3}},
    "sun": {
        "type": "directional",
        "direction": mi.ScalarVector3f(-1.0, -2.0, -1.0),
        "irradiance": {"type": "rgb", "value": [3.0, 2.8, 2.5]},
    },
    "floor": {
        "type": "rectangle",
        "to_world": T().translate([0, -1, 0]).rotate(axis=[1, 0, 0], angle=-90).scale(4),
        "bsdf": {"type": "diffuse", "reflectance": {"type": "rgb", "value": [0.45, 0.45, 0.4]}},
    },
    "ball": {
        "type": "sphere",
        "to_world": T().translate([-0.6, -0.3, 0]).scale(0.7),
        "bsdf": {
            "type": "plastic",
            "diffuse_reflectance": {"type": "rgb", "value": mi.ScalarColor3f(0.1, 0.25, 0.7)},
        },
    },
    "box": {
        "type": "cube",
        "to_world": T.translate([0.9, -0.6, -0.3]) @ T.rotate([0, 1, 0], 30) @ T.scale(0.4),
        "bsdf": {"type": "diffuse", "reflectance": {"type": "rgb", "value": mi.Color3f(0.7, 0.3, 0.1)}},
    },
    "sensor": {
        "type": "perspective",
        "fov": 40,
        "to_world": T().look_at(origin=[0, 1.5, 6], target=[0, -0.3, 0], up=[0, 1, 0]),
        "sampler": {"type": "independent", "sample_count": 16},
        "film": {"type": "hdrfilm", "width": 48, "height": 32, "rfilter": {"type": "box"}},
    },
})

image = mi.render(scene, seed=2)

mi.Bitmap(image).write("dict_scene.exr")
mi.util.write_bitmap("dict_scene.png", image)
print("wrote dict_scene.exr and dict_scene.png")
