# Written like a Mitsuba 3 script that renders in a spectral variant: a scene built with
# load_dict, with a measured reflectance spectrum and a measured sky; the only change for Candela
# is the import line.
import candela.mitsuba as mi

mi.set_variant("scalar_spectral")
assert mi.is_spectral and not mi.is_rgb

T = mi.ScalarTransform4f

scene = mi.load_dict({
    "type": "scene",
    "integrator": {"type": "path", "max_depth": 4},
    "sky": {
        "type": "constant",
        "radiance": {"type": "spectrum", "value": [(400, 0.6), (500, 0.45), (600, 0.3), (700, 0.2)]},
    },
    "sun": {
        "type": "directional",
        "direction": mi.ScalarVector3f(-1.0, -2.0, -1.0),
        "irradiance": {"type": "rgb", "value": [3.0, 2.8, 2.5]},
    },
    "floor": {
        "type": "rectangle",
        "to_world": T.translate([0, -1, 0]) @ T.rotate([1, 0, 0], -90) @ T.scale(4),
        "bsdf": {"type": "diffuse", "reflectance": {"type": "rgb", "value": [0.45, 0.45, 0.4]}},
    },
    "ball": {
        "type": "sphere",
        "to_world": T.translate([0, -0.3, 0]) @ T.scale(0.7),
        "bsdf": {
            "type": "diffuse",
            # A green pigment, measured every 50 nm.
            "reflectance": {"type": "spectrum", "value": [(400, 0.05), (450, 0.08), (500, 0.35), (550, 0.7),
                                                          (600, 0.3), (650, 0.08), (700, 0.05)]},
        },
    },
    "sensor": {
        "type": "perspective",
        "fov": 40,
        "to_world": T.look_at(origin=[0, 1.5, 6], target=[0, -0.3, 0], up=[0, 1, 0]),
        "sampler": {"type": "independent", "sample_count": 16},
        "film": {"type": "hdrfilm", "width": 40, "height": 30, "rfilter": {"type": "box"},
                 "component_format": "float32"},
    },
})

image = mi.render(scene, spp=16)

mi.util.write_bitmap("spectral_scene.exr", image)
mi.util.write_bitmap("spectral_scene.png", image)
print("rendered", image.shape, "in", mi.variant())
