"""Mitsuba 3's measuring sensors and batch sensor from Python, as its scripts use them: a
radiancemeter, irradiancemeter or distant sensor in a scene dictionary, chosen by index or
passed to mi.render as its own object, and a batch of cameras side by side. Under a uniform sky
the meters' readings are exact (every sample carries the same value)."""

import numpy as np
import pytest

import candela.mitsuba as mi

T = mi.ScalarTransform4f
SKY = [0.5, 1.0, 2.0]


@pytest.fixture(autouse=True)
def scalar_rgb():
    mi.set_variant("scalar_rgb")
    yield


def pixel_film():
    return {"type": "hdrfilm", "width": 1, "height": 1, "rfilter": {"type": "box"}, "component_format": "float32"}


def sky_scene(**more):
    scene = {"type": "scene", "integrator": {"type": "path"}, "sky": {"type": "constant", "radiance": {"type": "rgb", "value": SKY}}}
    scene.update(more)
    return mi.load_dict(scene)


def test_meters_in_a_scene_by_index_in_mitsuba_order():
    # Mitsuba numbers the scene's own sensors first, then those nested in shapes.
    scene = sky_scene(
        meter_on_sphere={"type": "sphere", "sensor": {"type": "irradiancemeter", "film": pixel_film()}},
        meter={"type": "radiancemeter", "origin": [0, 0, 5], "direction": [0, 1, 0], "film": pixel_film()},
        far={"type": "distant", "direction": [0, 0, -1], "target": [3, 3, 0], "film": pixel_film()},
    )
    radiance = mi.render(scene, sensor=0, spp=8)
    assert radiance.shape == (1, 1, 3)
    np.testing.assert_allclose(radiance[0, 0], SKY, rtol=1e-6)
    # The distant sensor's target misses the sphere: it sees the sky.
    np.testing.assert_allclose(mi.render(scene, sensor=1, spp=8)[0, 0], SKY, rtol=1e-6)
    np.testing.assert_allclose(mi.render(scene, sensor=2, spp=8)[0, 0], np.pi * np.array(SKY), rtol=1e-5)
    with pytest.raises(IndexError):
        mi.render(scene, sensor=3)


def test_a_radiancemeter_passed_to_render_sees_the_lit_disk():
    scene = sky_scene(disk={"type": "disk"})
    sensor = mi.load_dict({"type": "radiancemeter", "origin": [0.1, 0.2, 1], "direction": [0, 0, -1], "film": pixel_film()})
    reading = mi.render(scene, sensor=sensor, spp=4096, seed=3)[0, 0]
    # The default BSDF (diffuse 0.5) under a uniform sky: 0.5 L, to within a few percent at 4096 spp.
    np.testing.assert_allclose(reading, 0.5 * np.array(SKY), rtol=0.05)


def test_a_batch_renders_its_cameras_side_by_side():
    scene = sky_scene(box={"type": "cube", "to_world": T().scale(0.5)})
    views = [T().look_at(origin=[0, 0, 3], target=[0, 0, 0], up=[0, 1, 0]), T().look_at(origin=[3, 1, 0], target=[0, 0, 0], up=[0, 1, 0])]
    batch = mi.load_dict({
        "type": "batch",
        "left": {"type": "perspective", "fov": 40, "to_world": views[0]},
        "right": {"type": "perspective", "fov": 40, "to_world": views[1]},
        "film": {"type": "hdrfilm", "width": 32, "height": 16, "rfilter": {"type": "box"}},
    })
    image = mi.render(scene, sensor=batch, spp=16, seed=1)
    assert image.shape == (16, 32, 3)
    for k, view in enumerate(views):
        alone = mi.load_dict({
            "type": "perspective", "fov": 40, "to_world": view,
            "film": {"type": "hdrfilm", "width": 16, "height": 16, "rfilter": {"type": "box"}},
        })
        single = mi.render(scene, sensor=alone, spp=16, seed=1)
        part = image[:, 16 * k:16 * (k + 1)]
        # Other pixels draw other numbers: compare where the view is all sky (exact there), away
        # from the box's outline, where a pixel's samples may or may not touch the box.
        sky = np.all(np.isclose(single, SKY, rtol=1e-5), axis=2)
        part_sky = np.all(np.isclose(part, SKY, rtol=1e-5), axis=2)
        inner = eroded(sky)
        assert inner.sum() > 50 and (~sky).sum() > 20
        np.testing.assert_allclose(part[inner], single[inner], rtol=1e-5)
        assert not np.any(part_sky & eroded(~sky))  # the box is where it is alone


def eroded(mask):
    """The pixels whose 3 x 3 neighbourhood (within the image) lies wholly in `mask`."""
    padded = np.pad(mask, 1, constant_values=True)
    out = np.ones_like(mask)
    for dy in range(3):
        for dx in range(3):
            out &= padded[dy:dy + mask.shape[0], dx:dx + mask.shape[1]]
    return out
