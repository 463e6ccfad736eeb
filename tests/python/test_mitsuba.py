"""candela.mitsuba: Mitsuba 3's Python API as its getting-started scripts use it, and a clear
NotImplementedError for the rest."""

import subprocess
import sys

import numpy as np
import pytest

import candela.mitsuba as mi
from conftest import SCENES, assert_same_expectation, candela, cli_render, subprocess_env
from test_images import decode_png

CBOX = SCENES / "cbox.xml"


@pytest.fixture(autouse=True)
def scalar_rgb():
    mi.set_variant("scalar_rgb")
    yield


# --- variants -------------------------------------------------------------------------------------

def test_variants():
    assert "scalar_rgb" in mi.variants() and "llvm_ad_rgb" in mi.variants() and "cuda_ad_rgb" in mi.variants()
    assert "scalar_spectral" in mi.variants() and "llvm_ad_spectral" in mi.variants()
    assert all(v.endswith(("_rgb", "_spectral", "_spectral_polarized")) for v in mi.variants())
    assert mi.variant() == "scalar_rgb"
    mi.set_variant("llvm_ad_rgb")
    assert mi.variant() == "llvm_ad_rgb"
    # The first variant Candela renders wins, as Mitsuba takes the first one available.
    mi.set_variant("scalar_mono", "cuda_ad_rgb", "scalar_rgb")
    assert mi.variant() == "cuda_ad_rgb"
    with mi.variant_context("scalar_rgb_double"):
        assert mi.variant() == "scalar_rgb_double"
    assert mi.variant() == "cuda_ad_rgb"
    assert mi.is_rgb is True and mi.is_spectral is False and mi.is_polarized is False and mi.is_monochromatic is False


@pytest.mark.parametrize("name, words", [
    ("scalar_rgb_polarized", "polarisation in the spectral variant only"),
    ("cuda_ad_rgb_polarized", "polarisation in the spectral variant only"),
    ("scalar_mono", "monochrome rendering"),
    ("llvm_ad_mono_polarized_double", "monochrome"),
])
def test_variants_candela_does_not_render(name, words):
    with pytest.raises(NotImplementedError, match=words):
        mi.set_variant(name)
    assert mi.variant() == "scalar_rgb"


def test_unknown_variant():
    with pytest.raises(ImportError, match="unsupported variant 'gpu_rgb'"):
        mi.set_variant("gpu_rgb")
    with pytest.raises(TypeError):
        mi.set_variant()


def test_accelerated_variants_give_a_notice_once():
    code = ("import candela.mitsuba as mi\n"
            "mi.set_variant('llvm_ad_rgb'); mi.set_variant('llvm_ad_rgb'); mi.set_variant('cuda_rgb')\n"
            "mi.set_variant('scalar_rgb'); mi.set_variant('cuda_rgb')\n")
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=subprocess_env())
    assert result.returncode == 0, result.stderr
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 2
    assert "'llvm_ad_rgb'" in lines[0] and "'cuda_rgb'" in lines[1]
    assert all("CPU" in line for line in lines)


# --- loading and rendering ----------------------------------------------------------------------

def test_quickstart_in_process_matches_the_command_line(tmp_path):
    scene = mi.load_file(str(CBOX), res=24)
    image = mi.render(scene, spp=8, seed=3)
    assert isinstance(image, candela.Image) and image.shape == (24, 24, 3)
    reference = cli_render(CBOX, tmp_path / "cli.exr", 8, 3, {"res": 24})
    assert np.array_equal(np.asarray(image), np.asarray(reference))
    # spp=0 keeps the scene's sample count, as in Mitsuba.
    scene = mi.load_file(CBOX, res=8, spp=3, update_scene=False, parallel=False, optimize=True)
    assert np.array_equal(np.asarray(mi.render(scene)), np.asarray(candela.render(scene, spp=3)))


def test_load_string_and_load_dict():
    xml = CBOX.read_text()
    scene = mi.load_string(xml, res=8, parallel=True)
    assert isinstance(scene, mi.Scene) and scene.film_size == (8, 8)
    plugin = mi.load_dict({"type": "direct"})
    assert isinstance(plugin, candela.Plugin) and plugin.kind == "integrator"
    with pytest.raises(TypeError):
        mi.load_dict("not a dict")
    with pytest.raises(TypeError):
        mi.load_string(None)


def test_render_arguments():
    scene = mi.load_file(CBOX, res=8, spp=2)
    direct = mi.render(scene, integrator=mi.load_dict({"type": "direct"}), seed=1)
    assert np.array_equal(np.asarray(direct), np.asarray(candela.render(scene, integrator="direct", seed=1)))
    params = mi.traverse(scene)
    # params (for gradients), seed_grad and spp_grad leave the image as it is.
    assert np.array_equal(np.asarray(mi.render(scene, params, 0, None, 5, 7, 2, 9)),
                          np.asarray(candela.render(scene, spp=2, seed=5)))
    with pytest.raises(ValueError, match="spp"):
        mi.render(scene, spp=-4)
    with pytest.raises(TypeError, match="spp"):
        mi.render(scene, spp=2.0)
    with pytest.raises(TypeError, match="scene"):
        mi.render({"type": "scene"})
    with pytest.raises(TypeError, match="SceneParameters"):
        mi.render(scene, params={"a": 1})
    with pytest.raises(IndexError, match="sensor index 1 is out of range: the scene has 1 sensor$"):
        mi.render(scene, sensor=1)
    with pytest.raises(TypeError, match="sensor"):
        mi.render(scene, sensor=mi.load_dict({"type": "diffuse"}))
    with pytest.raises(NotImplementedError, match="not loaded by candela.mitsuba"):
        mi.render(candela.load_file(CBOX, res=8), sensor=mi.load_dict({"type": "perspective", "fov": 30}))


def sensor(origin, width=24, height=16, spp=8, to_world=None):
    return mi.load_dict({
        "type": "perspective", "fov": 40,
        "to_world": to_world if to_world is not None else mi.ScalarTransform4f.look_at(origin=origin, target=[0, 0, 0], up=[0, 1, 0]),
        "sampler": {"type": "independent", "sample_count": spp},
        "film": {"type": "hdrfilm", "width": width, "height": height, "rfilter": {"type": "box"}, "component_format": "float32"},
    })


def test_render_from_sensor_objects():
    # As Mitsuba's multi-view tutorial: a scene without a camera, rendered from several sensors.
    T = mi.ScalarTransform4f
    base = {"type": "scene", "integrator": {"type": "path"}, "light": {"type": "constant"},
            "ball": {"type": "sphere", "to_world": T.scale(0.8), "bsdf": {"type": "diffuse", "reflectance": {"type": "rgb", "value": [0.7, 0.3, 0.2]}}},
            "floor": {"type": "rectangle", "to_world": T.translate([0, -0.8, 0]).rotate([1, 0, 0], -90).scale(3)}}
    scene = mi.load_dict(base)
    for x in (-2.0, 2.0):
        view = sensor([x, 1, 4])
        image = mi.render(scene, sensor=view, seed=1)
        assert image.shape == (16, 24, 3)
        with_camera = mi.load_dict({**base, "sensor": view})
        assert np.array_equal(np.asarray(image), np.asarray(mi.render(with_camera, seed=1)))
    left, right = (np.asarray(mi.render(scene, sensor=sensor([x, 1, 4]))) for x in (-2.0, 2.0))
    assert not np.array_equal(left, right)
    # The scene keeps its own camera for other renders.
    assert mi.render(scene, spp=1).shape == candela.render(candela.load_dict(base), spp=1).shape


def test_render_a_scene_sensor_by_index(tmp_path):
    # Mitsuba 3 loads every sensor of a scene; render(scene, sensor=i) renders the i-th, in the
    # order of the file (here of the dictionary).
    T = mi.ScalarTransform4f
    base = {"type": "scene", "light": {"type": "constant"},
            "ball": {"type": "sphere", "to_world": T.scale(0.8), "bsdf": {"type": "diffuse"}}}
    two = {**base, "camera_a": sensor([-2, 1, 4], 24, 16), "camera_b": sensor([2, 1, 4], 12, 10)}
    scene = mi.load_dict(two)
    assert (scene.sensor_count, scene.sensor_index) == (2, 0)
    first, second = mi.render(scene, seed=4), mi.render(scene, sensor=1, seed=4)
    assert first.shape == (16, 24, 3) and second.shape == (10, 12, 3)
    assert np.array_equal(np.asarray(first), np.asarray(mi.render(scene, sensor=0, seed=4)))
    # The same as a scene holding only the second camera, and as candela's own loader told which.
    only_b = mi.load_dict({**base, "camera_b": sensor([2, 1, 4], 12, 10)})
    assert np.array_equal(np.asarray(second), np.asarray(mi.render(only_b, seed=4)))
    assert np.array_equal(np.asarray(second), np.asarray(candela.render(candela.load_dict(two, sensor=1), seed=4)))
    with pytest.raises(IndexError, match="sensor index 2 is out of range: the scene has 2 sensors"):
        mi.render(scene, sensor=2)
    # A file's sensors likewise, and parameter edits carry over to the other sensor's render.
    xml = tmp_path / "two.xml"
    text = CBOX.read_text()
    start, end = text.index("<sensor"), text.index("</sensor>") + len("</sensor>")
    camera = text[start:end]
    xml.write_text(text[:end] + camera.replace('<lookat origin="0, 0, 3.9"', '<lookat origin="0.3, 0, 3.9"') + text[end:])
    from_file = mi.load_file(xml, res=16, spp=4)
    params = mi.traverse(from_file)
    params["red.reflectance.value"] = mi.Color3f(0.1, 0.2, 0.9)
    params.update()
    edited = xml.read_text().replace('value="0.63, 0.065, 0.05"', 'value="0.1, 0.2, 0.9"')
    (tmp_path / "edited.xml").write_text(edited)
    expected = candela.render(candela.load_file(tmp_path / "edited.xml", sensor=1, res=16, spp=4), seed=5)
    assert np.array_equal(np.asarray(mi.render(from_file, sensor=1, seed=5)), np.asarray(expected))
    with pytest.raises(ValueError, match="loaded to render sensor 0"):
        candela.render(candela.load_file(xml, res=16, spp=4), sensor=1)
    with pytest.raises(candela.SceneError, match="sensor index 5 is out of range: the scene has 2 sensors"):
        candela.load_file(xml, sensor=5)


def test_render_another_sensor_again_loads_once(monkeypatch):
    # render(scene, sensor=i) loads the scene again with sensor i active; rendering from it again
    # reuses that load and carries traverse's edits over (made, changed, undone), the same pixels
    # as a scene loaded with each edit in place.
    base = {"type": "scene", "light": {"type": "constant"},
            "ball": {"type": "sphere", "bsdf": {"type": "diffuse", "id": "paint",
                                                "reflectance": {"type": "rgb", "value": [0.5, 0.5, 0.5]}}},
            "camera_a": sensor([-2, 1, 4], 12, 8, 4), "camera_b": sensor([2, 1, 4], 10, 6, 4),
            "camera_c": sensor([0, 3, 4], 8, 8, 4)}
    scene = mi.load_dict(base)
    loads = []
    real_load = mi._load_recipe
    monkeypatch.setattr(mi, "_load_recipe", lambda *args, **kwargs: loads.append(kwargs) or real_load(*args, **kwargs))

    def expected(value):
        edited = {**base, "ball": {**base["ball"], "bsdf": {**base["ball"]["bsdf"],
                                                            "reflectance": {"type": "rgb", "value": value}}}}
        return np.asarray(candela.render(candela.load_dict(edited, sensor=1), seed=2))

    unedited = np.asarray(mi.render(scene, sensor=1, seed=2))
    assert len(loads) == 2  # the scene with sensor 1, and once with its own to tell what the sensor changes
    assert np.array_equal(unedited, expected([0.5, 0.5, 0.5]))
    params = mi.traverse(scene)
    for value in ([0.9, 0.1, 0.1], [0.1, 0.9, 0.1], [0.5, 0.5, 0.5]):
        params["paint.reflectance.value"] = mi.Color3f(*value)
        params.update()
        assert np.array_equal(np.asarray(mi.render(scene, sensor=1, seed=2)), expected(value))
    assert len(loads) == 2
    # The scene's own sensor takes no load, nor another sample count.
    mi.render(scene, sensor=0, seed=2)
    mi.render(scene, sensor=1, seed=2, spp=1)
    assert len(loads) == 2
    assert np.array_equal(np.asarray(mi.render(scene, sensor=1, seed=2)), unedited)
    # Another index replaces the kept load (one per scene): going back loads sensor 1 again.
    mi.render(scene, sensor=2, seed=2)
    assert len(loads) == 4
    assert np.array_equal(np.asarray(mi.render(scene, sensor=1, seed=2)), unedited)
    assert len(loads) == 6


def test_scene_sensors_films_and_bounds():
    # Mitsuba's scene.sensors()[i].film().size() and friends, read from the scene as it is now.
    T = mi.ScalarTransform4f
    base = {"type": "scene", "light": {"type": "constant"},
            "ball": {"type": "sphere", "center": [0.5, 0, 0], "radius": 0.8, "bsdf": {"type": "diffuse"}}}
    scene = mi.load_dict({**base, "camera_a": sensor([-2, 1, 4], 24, 16, 8),
                          "camera_b": {"type": "perspective", "fov": 40, "shutter_open": 0.25, "shutter_close": 0.75,
                                       "to_world": T.translate([1, 2, 3]),
                                       "sampler": {"type": "stratified", "sample_count": 9},
                                       "film": {"type": "hdrfilm", "width": 40, "height": 30, "crop_offset_x": 4,
                                                "crop_offset_y": 2, "crop_width": 12, "crop_height": 10}}})
    a, b = scene.sensors()
    assert isinstance(a, mi.Sensor) and (a.id(), b.id()) == ("camera_a", "camera_b")
    assert list(a.film().size()) == [24, 16] and a.film().crop_size().x == 24 and a.sampler().sample_count() == 8
    assert list(b.film().size()) == [40, 30] and list(b.film().crop_size()) == [12, 10]
    assert list(b.film().crop_offset()) == [4, 2] and b.sampler().sample_count() == 9
    assert (b.shutter_open(), b.shutter_open_time()) == (0.25, 0.5) and a.shutter_open_time() == 0.0
    assert np.allclose(b.world_transform().matrix, T.translate([1, 2, 3]).matrix)
    # The pose follows traverse's edits.
    params = mi.traverse(scene)
    params["camera_a.to_world"] = T.translate([0, 0, 5])
    params.update()
    assert np.allclose(a.world_transform().matrix, T.translate([0, 0, 5]).matrix)
    # A film holds the image of the last render from its sensor (Mitsuba's develop() and bitmap()).
    with pytest.raises(RuntimeError, match="holds no image yet"):
        b.film().develop()
    image = mi.render(scene, sensor=b, seed=3)
    assert image.shape == (10, 12, 3)
    assert np.array_equal(np.asarray(image), np.asarray(mi.render(scene, sensor=1, seed=3)))
    assert np.array_equal(np.asarray(b.film().develop()), np.asarray(image))
    assert np.array_equal(np.asarray(b.film().bitmap()), np.asarray(image))
    with pytest.raises(RuntimeError, match="holds no image yet"):
        a.film().develop()
    with pytest.raises(ValueError, match="another scene's sensors"):
        mi.render(mi.load_dict(base), sensor=a)
    with pytest.raises(NotImplementedError, match=r"film\.rfilter"):
        a.film().rfilter()
    # The bounds: the box around the shapes (the sphere, centre (0.5, 0, 0), radius 0.8).
    box = scene.bbox()
    assert isinstance(box, mi.BoundingBox3f) and box.valid()
    assert np.allclose(box.min, [-0.3, -0.8, -0.8], atol=1e-5) and np.allclose(box.max, [1.3, 0.8, 0.8], atol=1e-5)
    assert np.allclose(box.center(), [0.5, 0, 0], atol=1e-5) and box.major_axis() in (0, 1, 2)
    assert box.contains([0.5, 0.5, 0.5]) and not box.contains([2, 0, 0])
    assert not mi.BoundingBox3f().valid() and not mi.load_dict({"type": "scene"}).bbox().valid()


def test_scene_integrator_renders_into_the_sensor_film(tmp_path):
    # Mitsuba 3 scripts: scene.integrator().render(scene, sensor), then sensor.film().bitmap().
    scene = mi.load_file(CBOX, res=16, spp=4)
    assert scene.integrator == "path" and isinstance(scene.integrator, str)  # candela's name, still
    integrator = scene.integrator()
    assert isinstance(integrator, mi.Integrator)
    sensor = scene.sensors()[0]
    image = integrator.render(scene, sensor, seed=3)
    assert np.array_equal(np.asarray(image), np.asarray(mi.render(scene, seed=3)))
    assert np.array_equal(np.array(sensor.film().bitmap()), np.asarray(image))
    assert np.array_equal(np.asarray(mi.render(scene, integrator=integrator, seed=3)), np.asarray(image))
    sensor.film().write(tmp_path / "film.exr")
    assert np.array_equal(np.asarray(candela.read_image(tmp_path / "film.exr")), np.asarray(image))
    other = mi.load_file(CBOX, res=8, spp=4)
    with pytest.raises(ValueError, match="another scene's integrator"):
        integrator.render(other, 0)
    with pytest.raises(ValueError, match="another scene's"):
        mi.render(other, integrator=integrator)


def test_scene_shapes_and_emitters():
    scene = mi.load_file(CBOX, res=8)
    shapes = {shape.id(): shape for shape in scene.shapes()}
    assert len(scene.shapes()) == 8 and all(isinstance(s, mi.Shape) for s in shapes.values())
    light, box = shapes["light"], shapes["tall_box"]
    assert light.is_emitter() and not box.is_emitter() and box.emitter() is None and not light.is_sensor()
    assert isinstance(box, mi.Mesh) and box.face_count() == 12 and light.face_count() == 2
    assert box.bsdf().id() == "white" and shapes["left"].bsdf().id() == "red"
    assert np.isclose(light.surface_area(), 0.25) and np.allclose(light.bbox().center(), [0, 0.99, 0], atol=1e-6)
    emitters = scene.emitters()
    assert len(emitters) == 1 and emitters[0] == light.emitter() and emitters[0].shape() == light
    assert not emitters[0].is_environment()
    # Moving a shape through traverse moves its bounds (and the scene's).
    params = mi.traverse(scene)
    positions = np.asarray(params["tall_box.vertex_positions"]).reshape(-1, 3) + [0, 0, 5]
    params["tall_box.vertex_positions"] = positions.reshape(-1)
    params.update()
    assert np.isclose(box.bbox().center()[2], -0.28 + 5, atol=1e-4) and scene.bbox().max[2] > 5
    # An environment emitter, a sphere that is no mesh.
    sky = mi.load_dict({"type": "scene", "sky": {"type": "constant"}, "ball": {"type": "sphere", "radius": 2}})
    (ball,), (env,) = sky.shapes(), sky.emitters()
    assert not isinstance(ball, mi.Mesh) and not ball.is_mesh() and np.isclose(ball.surface_area(), 16 * np.pi, rtol=1e-5)
    assert env.is_environment() and env.id() == "sky" and env.shape() is None
    with pytest.raises(NotImplementedError, match=r"bsdf\.eval"):
        box.bsdf().eval


def test_render_from_a_sensor_object_keeps_parameter_edits(tmp_path):
    scene = mi.load_file(CBOX, res=16, spp=4)
    params = mi.traverse(scene)
    params["red.reflectance.value"] = mi.Color3f(0.1, 0.2, 0.9)
    params.update()
    # The scene's own camera given as a sensor object (its matrix as the scene holds it, its film
    # and sample count): the image of the edited scene.
    same_view = sensor(None, 16, 16, 4, to_world=mi.ScalarTransform4f(params["PerspectiveCamera.to_world"].matrix))
    same_view.dictionary["fov"] = params["PerspectiveCamera.x_fov"]
    # (The camera inverts a <matrix> numerically, a <lookat> exactly: equal up to float rounding.)
    assert_same_expectation(mi.render(scene, sensor=same_view, seed=2), mi.render(scene, seed=2), "the scene's own view")
    assert not np.array_equal(np.asarray(mi.render(scene, sensor=same_view, seed=2)),
                              np.asarray(mi.render(mi.load_file(CBOX, res=16, spp=4), seed=2)))  # the edit is there
    # Another view of the edited scene equals the file with both changes.
    other = sensor([0.5, 0.25, 3.5], 16, 16, 4, to_world=mi.ScalarTransform4f.translate([0.5, 0.25, 3.5]) @ mi.ScalarTransform4f.scale([-1, 1, -1]))
    text = CBOX.read_text().replace('value="0.63, 0.065, 0.05"', 'value="0.1, 0.2, 0.9"')
    start, end = text.index("<sensor"), text.index("</sensor>") + len("</sensor>")
    text = text[:start] + """<sensor type="perspective"><float name="fov" value="40"/>
        <transform name="to_world"><scale x="-1" y="1" z="-1"/><translate x="0.5" y="0.25" z="3.5"/></transform>
        <sampler type="independent"><integer name="sample_count" value="4"/></sampler>
        <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/><rfilter type="box"/>
        <string name="component_format" value="float32"/></film></sensor>""" + text[end:]
    (tmp_path / "moved.xml").write_text(text)
    expected = candela.render(candela.load_file(tmp_path / "moved.xml"), seed=3)
    assert np.array_equal(np.asarray(mi.render(scene, sensor=other, seed=3)), np.asarray(expected))


def test_cornell_box():
    d = mi.cornell_box()
    assert d["type"] == "scene" and d["sensor"]["film"]["width"] == 256 and d["integrator"]["max_depth"] == 8
    # Mitsuba's Cornell box, as its dictionary gives the transforms.
    np.testing.assert_allclose(np.asarray(d["light"]["to_world"]), [[0.23, 0, 0, 0], [0, 0, -0.19, 0.99], [0, 0.19, 0, 0.01], [0, 0, 0, 1]], atol=1e-7)
    np.testing.assert_allclose(np.asarray(d["small-box"]["to_world"]),
                               [[0.286891, 0, -0.0877115, 0.335], [0, 0.3, 0, -0.7], [0.0877115, 0, 0.286891, 0.38], [0, 0, 0, 1]], atol=1e-6)
    np.testing.assert_allclose(np.asarray(d["large-box"]["to_world"]),
                               [[0.28491, 0, 0.0939491, -0.33], [0, 0.61, 0, -0.4], [-0.0939491, 0, 0.28491, -0.28], [0, 0, 0, 1]], atol=1e-6)
    np.testing.assert_allclose(np.asarray(d["sensor"]["to_world"]), [[-1, 0, 0, 0], [0, 1, 0, 0], [0, 0, -1, 3.9], [0, 0, 0, 1]])
    d["sensor"]["film"]["width"] = d["sensor"]["film"]["height"] = 16
    scene = mi.load_dict(d)
    image = mi.render(scene, spp=4)
    assert image.shape == (16, 16, 3) and np.isfinite(np.asarray(image)).all() and image.mean() > 0
    assert "red.reflectance.value" in mi.traverse(scene).keys()
    # A fresh dictionary every call.
    assert mi.cornell_box()["sensor"]["film"]["width"] == 256


AOV_XML = """<scene version="3.0.0">
    <integrator type="aov"><string name="aovs" value="dd.y:depth"/><integrator type="path" name="my_image"/></integrator>
    <sensor type="perspective"><film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/>
        <string name="component_format" value="float32"/></film></sensor>
    <shape type="sphere"/><emitter type="constant"/></scene>"""


def test_aov_channels_of_a_nested_integrator_are_named_by_its_key(tmp_path):
    # As the XML's name attribute: Mitsuba's aov names a nested integrator's channels by its key.
    aov = {"type": "aov", "aovs": "dd.y:depth", "my_image": {"type": "path"}}
    base = {"type": "scene", "sensor": {"type": "perspective", "film": {"type": "hdrfilm", "width": 8, "height": 8,
                                                                        "component_format": "float32"}},
            "s": {"type": "sphere"}, "l": {"type": "constant"}}
    expected = ["R", "G", "B", "my_image.R", "my_image.G", "my_image.B", "my_image.A", "dd.y.T"]
    from_xml = mi.render(mi.load_string(AOV_XML), spp=2, seed=1)
    assert from_xml.channels == expected
    from_dict = mi.render(mi.load_dict({**base, "integrator": aov}), spp=2, seed=1)
    assert from_dict.channels == expected and np.array_equal(np.asarray(from_dict), np.asarray(from_xml))
    plain = mi.load_dict(base)
    for integrator in (aov, mi.load_dict(aov)):
        image = mi.render(plain, integrator=integrator, spp=2, seed=1)
        assert image.channels == expected and np.array_equal(np.asarray(image), np.asarray(from_xml))
    mi.util.write_bitmap(tmp_path / "aov.exr", from_dict)
    written = candela.read_image(tmp_path / "aov.exr")
    assert sorted(written.channels) == sorted(expected)  # OpenEXR keeps channels sorted by name
    assert np.array_equal(np.asarray(written.layer("my_image")), np.asarray(from_dict.layer("my_image")))


SPECTRUM_CAMERA = """<sensor type="perspective"><film type="hdrfilm"><integer name="width" value="8"/>
    <integer name="height" value="8"/><string name="component_format" value="float32"/></film></sensor>"""


@pytest.mark.parametrize("variant", ["scalar_rgb", "scalar_spectral"])
@pytest.mark.parametrize("role, xml, d", [
    ("reflectance", '<rgb name="color" value="0.8, 0.1, 0.1"/>', {"type": "srgb", "color": [0.8, 0.1, 0.1]}),
    ("reflectance", '<float name="value" value="0.5"/>', {"type": "uniform", "value": 0.5}),
    ("reflectance", '<float name="wavelength_min" value="400"/><float name="wavelength_max" value="700"/>'
                    '<string name="values" value="0.1, 0.5, 0.9"/>',
     {"type": "regular", "wavelength_min": 400, "wavelength_max": 700, "values": "0.1, 0.5, 0.9"}),
    ("reflectance", '<string name="wavelengths" value="400, 550, 700"/><string name="values" value="0.9, 0.2, 0.6"/>',
     {"type": "irregular", "wavelengths": "400, 550, 700", "values": "0.9, 0.2, 0.6"}),
    ("radiance", '<float name="scale" value="0.5"/>', {"type": "d65", "scale": 0.5}),
    ("radiance", '<float name="temperature" value="4000"/>', {"type": "blackbody", "temperature": 4000}),
], ids=["srgb", "uniform", "regular", "irregular", "d65", "blackbody"])
def test_spectrum_plugins_in_dictionaries_load_as_in_xml(variant, role, xml, d):
    mi.set_variant(variant)
    spectrum = f'<spectrum type="{d["type"]}" name="{role}">{xml}</spectrum>'
    if role == "reflectance":
        text = (f'<emitter type="constant"/><shape type="sphere"><point name="center" x="0" y="0" z="3"/>'
                f'<bsdf type="diffuse">{spectrum}</bsdf></shape>')
        objects = {"l": {"type": "constant"},
                   "s": {"type": "sphere", "center": [0, 0, 3], "bsdf": {"type": "diffuse", "reflectance": d}}}
    else:
        text = f'<emitter type="constant">{spectrum}</emitter>'
        objects = {"l": {"type": "constant", "radiance": d}}
    from_xml = mi.render(mi.load_string(f'<scene version="3.0.0">{SPECTRUM_CAMERA}{text}</scene>'), spp=4, seed=1)
    camera = {"type": "perspective", "film": {"type": "hdrfilm", "width": 8, "height": 8, "component_format": "float32"}}
    from_dict = mi.render(mi.load_dict({"type": "scene", "sensor": camera, **objects}), spp=4, seed=1)
    assert np.asarray(from_xml).mean() > 0
    assert np.array_equal(np.asarray(from_dict), np.asarray(from_xml))


def test_a_spectrum_plugin_alone_is_a_texture():
    d65 = mi.load_dict({"type": "d65", "scale": 0.5})
    assert isinstance(d65, candela.Plugin) and d65.kind == "texture"
    camera = {"type": "perspective", "film": {"type": "hdrfilm", "width": 4, "height": 4}}
    with_plugin = mi.load_dict({"type": "scene", "sensor": camera, "l": {"type": "constant", "radiance": d65}})
    with_dict = mi.load_dict({"type": "scene", "sensor": camera,
                              "l": {"type": "constant", "radiance": {"type": "d65", "scale": 0.5}}})
    assert np.array_equal(np.asarray(mi.render(with_plugin, spp=1)), np.asarray(mi.render(with_dict, spp=1)))
    with pytest.raises(candela.SceneError, match="outside"):
        mi.load_dict({"type": "srgb", "color": [2, 0, 0]})


def test_image_numpy():
    image = mi.render(mi.load_file(CBOX, res=8), spp=1)
    array = image.numpy()
    # As TensorXf.numpy(): a plain NumPy array, H x W x C, of the pixels (here a copy).
    assert type(array) is np.ndarray and array.shape == (8, 8, 3) and array.dtype == np.float32
    assert np.array_equal(array, np.asarray(image)) and not np.shares_memory(array, np.asarray(image))


# --- traverse -------------------------------------------------------------------------------------

def test_traverse_and_update():
    scene = mi.load_file(CBOX, res=12, spp=2)
    original = np.asarray(mi.render(scene))
    params = mi.traverse(scene)
    assert isinstance(params, mi.SceneParameters) and isinstance(params, candela.SceneParameters)
    red = params["red.reflectance.value"]
    assert isinstance(red, mi.Color3f) and np.allclose(red, [0.63, 0.065, 0.05])
    params["red.reflectance.value"] = mi.Color3f(0.1, 0.2, 0.9)
    assert params.update() == ["red.reflectance.value"]
    edited = np.asarray(mi.render(scene))
    assert not np.array_equal(edited, original)
    # A value changed in place counts, as in Mitsuba.
    colour = params["red.reflectance.value"]
    colour[0] = 0.63
    colour[1:] = [0.065, 0.05]
    assert params.update() == ["red.reflectance.value"]
    assert np.array_equal(np.asarray(mi.render(scene)), original)
    to_world = params["PerspectiveCamera.to_world"]
    assert isinstance(to_world, mi.ScalarTransform4f)
    params["PerspectiveCamera.to_world"] = mi.ScalarTransform4f.rotate([0, 1, 0], 10) @ to_world
    params["PerspectiveCamera.x_fov"] = 45
    assert sorted(params.update()) == ["PerspectiveCamera.to_world", "PerspectiveCamera.x_fov"]
    # Read and not changed: nothing to update.
    params["white.reflectance.value"]
    params["tall_box.vertex_positions"]
    assert params.update() == []


def test_in_place_vertex_edit_equals_assignment():
    a, b = mi.load_file(CBOX, res=12, spp=2), mi.load_file(CBOX, res=12, spp=2)
    pa, pb = mi.traverse(a), mi.traverse(b)
    v = pa["short_box.vertex_positions"]
    v[1::3] += 0.1
    assert pa.update() == ["short_box.vertex_positions"]
    w = pb["short_box.vertex_positions"]
    pb["short_box.vertex_positions"] = w + np.tile(np.float32([0, 0.1, 0]), w.size // 3)
    pb.update()
    assert np.array_equal(mi.traverse(a)["short_box.vertex_positions"], mi.traverse(b)["short_box.vertex_positions"])
    assert np.array_equal(np.asarray(mi.render(a)), np.asarray(mi.render(b)))


def test_traverse_extras():
    scene = mi.load_file(CBOX, res=8)
    params = mi.traverse(scene)
    params.keep(["red.reflectance.value", "PerspectiveCamera.x_fov"])
    assert sorted(params.keys()) == ["PerspectiveCamera.x_fov", "red.reflectance.value"]
    params = mi.traverse(scene)
    params.keep(r".*\.reflectance\.value")
    assert set(params.keys()) == {"white.reflectance.value", "red.reflectance.value", "green.reflectance.value",
                                  "light.bsdf.reflectance.value"}
    colour = params["green.reflectance.value"]
    colour *= 0.5
    params.set_dirty("green.reflectance.value")
    assert params.update() == ["green.reflectance.value"]
    with pytest.raises(NotImplementedError, match="differentiab"):
        params.flags("green.reflectance.value")
    with pytest.raises(NotImplementedError, match="outside a scene"):
        mi.traverse(mi.load_dict({"type": "diffuse"}))
    with pytest.raises(TypeError):
        mi.traverse(42)
    assert mi.util.traverse is mi.traverse


def test_scene_parameters_mapping_as_mitsuba():
    import collections.abc

    scene = mi.load_file(CBOX, res=8, spp=2)
    original = np.asarray(mi.render(scene))
    params = mi.traverse(scene)
    assert isinstance(params, collections.abc.Mapping)
    names = list(params.keys())
    assert "red.reflectance.value" in names and len(names) == len(params)
    # Mitsuba's quirk: iterating gives (name, value) pairs, as items() does.
    pairs = list(params)
    assert [name for name, _ in pairs] == names == [name for name, _ in params.items()]
    assert np.array_equal(dict(pairs)["red.reflectance.value"], params["red.reflectance.value"])
    assert len(params.values()) == len(names)
    assert isinstance(params.get("red.reflectance.value"), mi.Color3f)
    assert params.get("no.such.value") is None and params.get("no.such.value", 7) == 7
    # copy() and del: another view of the same scene; deleting a name leaves the scene alone.
    view = params.copy()
    assert isinstance(view, mi.SceneParameters) and list(view.keys()) == names
    del view["red.reflectance.value"]
    assert "red.reflectance.value" not in view and "red.reflectance.value" in params and len(view) == len(params) - 1
    with pytest.raises(KeyError):
        del view["red.reflectance.value"]
    # update(values): the names it holds are assigned first, others ignored, then applied.
    assert params.update({"red.reflectance.value": mi.Color3f(0.1, 0.2, 0.9), "no.such.value": 1.0}) == ["red.reflectance.value"]
    assert np.allclose(mi.traverse(scene)["red.reflectance.value"], [0.1, 0.2, 0.9])
    edited = np.asarray(mi.render(scene))
    assert not np.array_equal(edited, original)
    assert view.update({"red.reflectance.value": [0.63, 0.065, 0.05]}) == []  # not in this view: ignored
    assert np.array_equal(np.asarray(mi.render(scene)), edited)
    params.update({"red.reflectance.value": [0.63, 0.065, 0.05]})
    assert np.array_equal(np.asarray(mi.render(scene)), original)


def test_keep_matches_regular_expressions_at_the_start():
    scene = mi.load_file(CBOX, res=8)

    def kept(keys):
        params = mi.traverse(scene)
        params.keep(keys)
        return sorted(params.keys())

    # As Mitsuba's keep: re.match, a match at the start of the name, not of all of it.
    assert kept("red") == ["red.reflectance.value"]
    assert kept(["red", "green"]) == ["green.reflectance.value", "red.reflectance.value"]
    assert kept(r".*\.x_fov") == ["PerspectiveCamera.x_fov"]
    assert kept("reflectance") == []
    assert kept(["red.reflectance.value", "PerspectiveCamera.x_fov"]) == ["PerspectiveCamera.x_fov", "red.reflectance.value"]
    params = mi.traverse(scene)
    with pytest.raises(NotImplementedError, match="differentiable"):
        params.keep(None)


# --- transforms and 3-vectors ---------------------------------------------------------------------

def test_transform_styles_agree():
    T = mi.ScalarTransform4f
    assert T is mi.Transform4f is candela.Transform
    a = T.translate([1, 2, 3]) @ T.rotate([0, 1, 0], 30) @ T.scale(0.5)
    b = T().translate([1, 2, 3]).rotate([0, 1, 0], 30).scale(0.5)
    c = T.translate(v=[1, 2, 3]) * T.rotate(axis=[0, 1, 0], angle=30) * T.scale([0.5, 0.5, 0.5])
    assert np.allclose(a.matrix, b.matrix) and np.allclose(a.matrix, c.matrix)
    look = T.look_at(origin=[1, 2, 5], target=[0, 0, 0], up=[0, 1, 0])
    assert look == T().look_at([1, 2, 5], [0, 0, 0], [0, 1, 0])
    # The camera looks along its +z, from its origin.
    assert np.allclose(look @ mi.ScalarPoint3f(0, 0, 0), [1, 2, 5])
    direction = look @ mi.ScalarVector3f(0, 0, 1)
    assert isinstance(direction, mi.ScalarVector3f)
    assert np.allclose(direction, -np.array([1, 2, 5]) / np.linalg.norm([1, 2, 5]))
    assert np.allclose(a.inverse().matrix @ a.matrix, np.identity(4))
    assert np.allclose(T(a.matrix.tolist()).matrix, a.matrix)


def test_transform_translation_scale_inverse_transpose_and_orthographic():
    T = mi.ScalarTransform4f
    m = T.translate([1, 2, 3]) @ T.rotate([0.3, 1, 0.2], 35) @ T.scale([2, 0.5, 1])
    # translation(): the matrix's last column (Mitsuba's Transform::translation).
    assert np.array_equal(m.translation(), m.matrix[:3, 3]) and np.allclose(T.translate([1, 2, 3]).translation(), [1, 2, 3])
    # has_scale(): M M^T is not the identity (within 1e-3); rotations and reflections have none.
    assert m.has_scale() is True and T.scale(1.01).has_scale() is True
    assert T.rotate([0, 1, 0], 30).has_scale() is False and T.translate([4, 0, 0]).has_scale() is False
    assert T.scale([-1, 1, 1]).has_scale() is False and T.scale(1.0001).has_scale() is False
    # inverse_transpose (a field in Mitsuba, not a method): what maps normals.
    assert np.allclose(m.inverse_transpose, np.linalg.inv(m.matrix).T)
    n = m @ mi.Normal3f(0, 0, 1)
    assert np.allclose(n, (m.inverse_transpose @ [0, 0, 1, 0])[:3])
    # orthographic(near, far) = scale([1, 1, 1 / (far - near)]) @ translate([0, 0, -near]): z from [near, far] to [0, 1].
    ortho = T.orthographic(0.5, 4.5)
    assert np.allclose(ortho.matrix, (T.scale([1, 1, 0.25]) @ T.translate([0, 0, -0.5])).matrix)
    assert np.allclose(ortho @ mi.Point3f(1, 2, 0.5), [1, 2, 0]) and np.allclose(ortho @ mi.Point3f(1, 2, 4.5), [1, 2, 1])
    assert np.allclose(T().translate([1, 0, 0]).orthographic(0.5, 4.5).matrix, (T.translate([1, 0, 0]) @ ortho).matrix)
    # from_frame and to_frame take a mi.Frame3f, which candela.mitsuba does not have.
    with pytest.raises(NotImplementedError):
        mi.Frame3f


def test_points_vectors_and_normals_transform_differently():
    T = mi.ScalarTransform4f
    m = T.translate([10, 0, 0]) @ T.scale([2, 1, 1])
    p = m @ mi.Point3f(1, 1, 1)
    v = m @ mi.Vector3f(1, 1, 1)
    n = m @ mi.Normal3f(1, 1, 1)
    assert isinstance(p, mi.Point3f) and np.allclose(p, [12, 1, 1])
    assert isinstance(v, mi.Vector3f) and np.allclose(v, [2, 1, 1])
    assert isinstance(n, mi.Normal3f) and np.allclose(n, [0.5, 1, 1])
    assert np.allclose(m @ [1, 1, 1], [12, 1, 1])  # plain numbers are a point


def test_transforms_match_the_scene_format():
    # A rectangle ([-1, 1]^2 at z = 0) placed by <rotate>, <scale> and <translate> in a file, and
    # by the same ScalarTransform4f builders: the same vertices.
    xml = """<scene version="3.0.0"><shape type="rectangle" id="r"><transform name="to_world">
        <scale x="2" y="0.5" z="1"/><rotate x="0.3" y="1" z="0.2" angle="35"/><translate x="1" y="-2" z="0.5"/>
        </transform></shape></scene>"""
    loaded = candela.traverse(candela.load_string(xml))["r.vertex_positions"].reshape(-1, 3)
    T = mi.ScalarTransform4f
    m = T.translate([1, -2, 0.5]) @ T.rotate([0.3, 1, 0.2], 35) @ T.scale([2, 0.5, 1])
    corners = [m @ mi.Point3f(x, y, 0) for x, y in [(-1, -1), (1, -1), (1, 1), (-1, 1)]]
    for corner in corners:
        assert np.min(np.linalg.norm(loaded - corner, axis=1)) < 1e-5


def test_three_vectors():
    p = mi.ScalarPoint3f(1, 2, 3)
    assert (p.x, p.y, p.z) == (1, 2, 3)
    assert np.array_equal(mi.ScalarPoint3f([4, 5, 6]), [4, 5, 6])
    assert np.array_equal(mi.ScalarPoint3f(7), [7, 7, 7])
    assert np.array_equal(mi.Point3f(), [0, 0, 0])
    c = mi.Color3f(0.1, 0.2, 0.3)
    assert (c.r, c.g, c.b) == (0.1, 0.2, 0.3)
    assert isinstance(c * 2, mi.Color3f)
    assert mi.ScalarColor3f is mi.Color3f and mi.ScalarVector3f is mi.Vector3f
    assert repr(mi.Vector3f(1, 0.5, 0)) == "[1, 0.5, 0]"
    assert mi.luminance(mi.Color3f(1, 1, 1)) == pytest.approx(1.0)
    with pytest.raises(NotImplementedError, match="vectorized"):
        mi.Point3f(np.zeros(4), np.zeros(4), np.zeros(4))
    with pytest.raises(NotImplementedError, match="vectorized"):
        mi.Point3f([1, 2, 3, 4])
    with pytest.raises(TypeError):
        mi.Point3f(1, 2)


def test_three_vectors_as_dictionary_values():
    def scene(direction, colour, centre):
        return {"type": "scene",
                "sun": {"type": "directional", "direction": direction, "irradiance": {"type": "rgb", "value": 2.0}},
                "ball": {"type": "sphere", "center": centre, "radius": 0.5, "bsdf": {"type": "diffuse", "reflectance": colour}},
                "sensor": {"type": "perspective", "fov": 40,
                           "to_world": mi.ScalarTransform4f.look_at(origin=[0, 0, 4], target=[0, 0, 0], up=[0, 1, 0]),
                           "film": {"type": "hdrfilm", "width": 12, "height": 12, "component_format": "float32"}}}

    with_types = mi.load_dict(scene(mi.ScalarVector3f(-1, -1, -2), mi.ScalarColor3f(0.2, 0.5, 0.8), mi.ScalarPoint3f(0.1, 0, 0)))
    plain = mi.load_dict(scene([-1, -1, -2], {"type": "rgb", "value": [0.2, 0.5, 0.8]}, [0.1, 0, 0]))
    assert np.allclose(mi.traverse(with_types)["ball.bsdf.reflectance.value"], [0.2, 0.5, 0.8])
    a, b = np.asarray(mi.render(with_types, spp=4)), np.asarray(mi.render(plain, spp=4))
    assert a.mean() > 0 and np.array_equal(a, b)


# --- Bitmap and mi.util -----------------------------------------------------------------------------

@pytest.fixture(scope="module")
def image():
    return candela.render(candela.load_file(CBOX, res=16), spp=4, seed=2)


def test_bitmap_from_an_image(image):
    b = mi.Bitmap(image)
    assert b.pixel_format() == mi.Bitmap.PixelFormat.RGB
    assert b.component_format() == mi.Struct.Type.Float32
    assert b.srgb_gamma() is False and not b.has_alpha()
    assert (b.width(), b.height(), b.size(), b.channel_count()) == (16, 16, (16, 16), 3)
    assert np.array_equal(np.array(b), np.asarray(image))
    assert "rgb" in repr(b) and "float32" in repr(b)
    assert mi.Bitmap(np.zeros((2, 3))).pixel_format() == mi.Bitmap.PixelFormat.Y
    assert mi.Bitmap(np.zeros((2, 3, 4), np.float16)).pixel_format() == mi.Bitmap.PixelFormat.RGBA
    assert mi.Bitmap(np.zeros((2, 3, 3), np.uint8)).srgb_gamma() is True
    empty = mi.Bitmap(mi.Bitmap.PixelFormat.RGBA, mi.Struct.Type.UInt8, [5, 4])
    assert np.array(empty).shape == (4, 5, 4) and np.array(empty).dtype == np.uint8


def test_bitmap_convert(image):
    b = mi.Bitmap(image)
    srgb = b.convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.UInt8, srgb_gamma=True)
    assert isinstance(srgb, mi.Bitmap) and srgb.srgb_gamma()
    assert np.array(srgb).dtype == np.uint8
    assert np.array_equal(np.array(srgb), image.to_srgb8())
    # Back to linear float: the 8-bit values decoded.
    linear = srgb.convert(component_format=mi.Struct.Type.Float32, srgb_gamma=False)
    assert np.allclose(np.array(linear), np.clip(np.asarray(image), 0, 1), atol=0.02)
    grey = b.convert(mi.Bitmap.PixelFormat.Y)
    expected_y = np.asarray(image, dtype=np.float64) @ [0.212671, 0.715160, 0.072169]
    assert np.allclose(np.array(grey)[:, :, 0], expected_y, rtol=1e-6)
    rgba = b.convert(mi.Bitmap.PixelFormat.RGBA, mi.Struct.Type.Float16, False)
    assert np.array(rgba).dtype == np.float16 and np.all(np.array(rgba)[:, :, 3] == 1)
    assert np.array(b.convert(mi.Struct.Type.Float64)).dtype == np.float64
    with pytest.raises(NotImplementedError, match="XYZ"):
        b.convert(mi.Bitmap.PixelFormat.XYZ)
    with pytest.raises(NotImplementedError, match="alpha"):
        b.convert(alpha_transform=mi.Bitmap.AlphaTransform.Premultiply)


def test_bitmap_of_a_render_with_layers(tmp_path):
    layered = candela.render(candela.load_file(CBOX, res=8), spp=2, aovs=["albedo"])
    b = mi.Bitmap(layered)
    assert b.pixel_format() == mi.Bitmap.PixelFormat.MultiChannel and b.channel_names()[3] == "albedo.R"
    assert np.array_equal(np.array(b.convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.UInt8, True)), layered.to_srgb8())
    mi.util.write_bitmap(tmp_path / "layered.png", layered)
    assert np.array_equal(decode_png((tmp_path / "layered.png").read_bytes()), layered.to_srgb8())
    b.write(tmp_path / "layered.exr")  # every layer
    assert candela.read_image(tmp_path / "layered.exr").channels == layered.channels
    with pytest.raises(NotImplementedError, match="MultiChannel"):
        mi.Bitmap(np.zeros((2, 2, 5), np.float32)).convert(mi.Bitmap.PixelFormat.RGB)


def test_bitmap_split_of_a_render_with_layers():
    # Mitsuba's split(): one bitmap per layer, sorted by name, '<root>' for the unprefixed channels.
    layered = candela.render(candela.load_file(CBOX, res=8), spp=2, aovs=["albedo", "depth"])
    layers = dict(mi.Bitmap(layered).split())
    assert sorted(layers) == ["<root>", "albedo", "depth"]
    assert layers["<root>"].pixel_format() == mi.Bitmap.PixelFormat.RGB
    assert layers["albedo"].pixel_format() == mi.Bitmap.PixelFormat.RGB
    assert np.array_equal(np.array(layers["<root>"]), np.asarray(layered)[:, :, :3])
    names = list(layered.channels)
    for layer, channels in (("albedo", "RGB"), ("depth", "Z")):  # --aov depth is the EXR's depth.Z
        columns = [names.index(f"{layer}.{c}") for c in channels]
        assert np.array_equal(np.array(layers[layer]), np.asarray(layered)[:, :, columns])
    assert layers["depth"].pixel_format() == mi.Bitmap.PixelFormat.MultiChannel
    assert layers["depth"].channel_names() == ["Z"]
    # Channels in another order come back in R, G, B order; a bitmap with one layer is its own.
    mixed = mi.Bitmap(np.arange(24, dtype=np.float32).reshape(2, 3, 4), channel_names=["n.B", "n.G", "n.R", "n.A"])
    (name, layer), = mixed.split()
    assert name == "n" and layer.pixel_format() == mi.Bitmap.PixelFormat.RGBA
    assert np.array_equal(np.array(layer), np.array(mixed)[:, :, [2, 1, 0, 3]])
    rgb = mi.Bitmap(np.zeros((2, 2, 3), np.float32))
    assert rgb.split() == [("<root>", rgb)]


def test_bitmap_resample():
    ramp = np.tile(np.arange(8, dtype=np.float64), (2, 1))[:, :, None]  # 2 x 8, value = x
    b = mi.Bitmap(ramp)
    # The same size with the default 2-lobe Lanczos: the filter is zero at the other pixel centres.
    assert np.array_equal(np.array(b.resample([8, 2])), ramp)
    # Upsampled 2x with a tent (radius 1): linear interpolation between pixel centres, the edges
    # clamped. Output pixel i lies at x = (i + 0.5) / 2 - 0.5 in source pixel coordinates.
    up = np.array(b.resample([16, 2], rfilter=mi.load_dict({"type": "tent"})))[0, :, 0]
    assert np.allclose(up, np.clip((np.arange(16) + 0.5) / 2 - 0.5, 0, 7))
    # Downsampled 2x with a box: the mean of each pair of pixels (the filter widened to 2 pixels).
    rng = np.random.default_rng(5)
    data = rng.random((6, 10, 3)).astype(np.float32)
    box = np.array(mi.Bitmap(data).resample([5, 3], rfilter=mi.load_dict({"type": "box"})))
    assert box.dtype == np.float32 and np.allclose(box, data.reshape(3, 2, 5, 2, 3).mean(axis=(1, 3)), atol=1e-6)
    # Boundary conditions, on a constant image: Clamp, Repeat and Mirror keep it, Zero darkens
    # the edges by the weight outside, One keeps it; clamp limits the results.
    ones = mi.Bitmap(np.ones((4, 4, 1), np.float32))
    B = mi.FilterBoundaryCondition
    for bc in (B.Clamp, B.Repeat, B.Mirror, B.One):
        assert np.allclose(np.array(ones.resample([7, 3], bc=(bc, bc))), 1.0), bc
    zero = np.array(ones.resample([7, 3], bc=(B.Zero, B.Zero)))[..., 0]
    assert zero[1, 3] > zero[0, 0] and not np.allclose(zero, 1.0)
    limited = np.array(ones.resample([7, 3], bc=(B.Zero, B.Zero), clamp=(0.95, 0.97)))
    assert limited.min() == np.float32(0.95) and limited.max() == np.float32(0.97)
    # Repeat wraps, Mirror reflects: a 1-pixel-wide upsample reads across the edges.
    step = mi.Bitmap(np.array([[[0.0], [1.0]]]))  # 1 x 2
    wrapped = np.array(step.resample([4, 1], rfilter=mi.load_dict({"type": "tent"}), bc=(B.Repeat, B.Repeat)))
    mirrored = np.array(step.resample([4, 1], rfilter=mi.load_dict({"type": "tent"}), bc=(B.Mirror, B.Mirror)))
    assert np.allclose(wrapped[0, :, 0], [0.25, 0.25, 0.75, 0.75]) and np.allclose(mirrored[0, :, 0], [0, 0.25, 0.75, 1])
    # Into a given bitmap; 8-bit bitmaps are refused, as by Mitsuba.
    target = mi.Bitmap(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float32, [5, 3])
    assert mi.Bitmap(data).resample(target, rfilter=mi.load_dict({"type": "box"})) is target
    assert np.allclose(np.array(target), box)
    with pytest.raises(ValueError, match="Float16, Float32 or Float64"):
        mi.Bitmap(np.zeros((2, 2, 3), np.uint8)).resample([1, 1])


def test_bitmap_clear_vflip_accumulate():
    data = np.arange(24, dtype=np.float32).reshape(2, 4, 3)
    b = mi.Bitmap(data)
    b.vflip()
    assert np.array_equal(np.array(b), data[::-1])
    total = mi.Bitmap(np.zeros((3, 5, 3), np.float32))
    total.accumulate(mi.Bitmap(data))
    total.accumulate(mi.Bitmap(data), [2, 2])  # at x 2, y 2: cut to the target
    expected = np.zeros((3, 5, 3), np.float32)
    expected[:2, :4] += data
    expected[2:, 2:] += data[:1, :3]
    assert np.array_equal(np.array(total), expected)
    total.accumulate(mi.Bitmap(data), [1, 0], [0, 0], [2, 1])  # a 2 x 1 region from x 1
    expected[0, 0:2] += data[0, 1:3]
    assert np.array_equal(np.array(total), expected)
    total.clear()
    assert not np.array(total).any()
    with pytest.raises(ValueError, match="incompatible"):
        total.accumulate(mi.Bitmap(np.zeros((2, 2, 4), np.float32)))


def test_bitmap_write_and_read(tmp_path, image):
    b = mi.Bitmap(image)
    b.write(tmp_path / "b.exr")
    assert np.array_equal(np.asarray(candela.read_image(tmp_path / "b.exr")), np.asarray(image))
    b.write(str(tmp_path / "b.png"))
    assert np.array_equal(decode_png((tmp_path / "b.png").read_bytes()), image.to_srgb8())
    # 8-bit data is written as it is; grey and RGBA PNGs too.
    b.convert(mi.Bitmap.PixelFormat.Y, mi.Struct.Type.UInt8, True).write(tmp_path / "y.png")
    y = decode_png((tmp_path / "y.png").read_bytes())
    assert y.shape == (16, 16, 1)
    b.convert(mi.Bitmap.PixelFormat.RGBA, mi.Struct.Type.UInt8, True).write(tmp_path / "rgba.png")
    rgba = decode_png((tmp_path / "rgba.png").read_bytes())
    assert np.array_equal(rgba[:, :, :3], image.to_srgb8()) and np.all(rgba[:, :, 3] == 255)
    # Reading a PNG gives its 8-bit sRGB values, as Mitsuba's Bitmap(path).
    back = mi.Bitmap(tmp_path / "b.png")
    assert back.component_format() == mi.Struct.Type.UInt8 and back.srgb_gamma()
    assert np.array_equal(np.array(back), image.to_srgb8())
    assert mi.Bitmap(str(tmp_path / "b.exr")).component_format() == mi.Struct.Type.Float32
    # Half-precision EXR.
    b.convert(component_format=mi.Struct.Type.Float16).write(tmp_path / "h.exr")
    assert np.array_equal(np.asarray(candela.read_image(tmp_path / "h.exr")), np.asarray(image).astype(np.float16).astype(np.float32))
    with pytest.raises(NotImplementedError, match="RGBE"):
        b.write(tmp_path / "b.hdr")
    with pytest.raises(ValueError, match="unknown file format"):
        b.write(tmp_path / "b.xyz")
    with pytest.raises(NotImplementedError, match="struct_"):
        b.struct_()


def test_bitmap_write_in_a_given_format_at_the_exact_path(tmp_path, image):
    b = mi.Bitmap(image)
    # The format given decides; the file is written at the path as it is, whatever its extension.
    b.write(tmp_path / "render", mi.Bitmap.FileFormat.OpenEXR)
    assert (tmp_path / "render").read_bytes()[:4] == b"v/1\x01"
    assert np.array_equal(np.asarray(candela.read_image(tmp_path / "render")), np.asarray(image))
    b.write(tmp_path / "really.png", mi.Bitmap.FileFormat.OpenEXR)
    assert (tmp_path / "really.png").read_bytes()[:4] == b"v/1\x01"
    b.write(str(tmp_path / "picture.exr"), mi.Bitmap.FileFormat.PNG)
    assert np.array_equal(decode_png((tmp_path / "picture.exr").read_bytes()), image.to_srgb8())
    b.write(tmp_path / "photo", mi.Bitmap.FileFormat.JPEG)
    assert (tmp_path / "photo").read_bytes()[:2] == b"\xff\xd8"
    b.write(tmp_path / "auto.exr", mi.Bitmap.FileFormat.Auto)
    assert (tmp_path / "auto.exr").read_bytes()[:4] == b"v/1\x01"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["auto.exr", "photo", "picture.exr", "really.png", "render"]
    # A file that cannot be written leaves nothing behind.
    (tmp_path / "folder").mkdir()
    with pytest.raises(candela.InputError, match="directory"):
        b.write(tmp_path / "folder", mi.Bitmap.FileFormat.OpenEXR)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["auto.exr", "folder", "photo", "picture.exr", "really.png", "render"]
    assert list((tmp_path / "folder").iterdir()) == []


def test_jpeg(tmp_path, image):
    mi.Bitmap(image).write(tmp_path / "b.jpg")
    data = (tmp_path / "b.jpg").read_bytes()
    assert data[:2] == b"\xff\xd8" and data[-2:] == b"\xff\xd9"
    decoded = np.asarray(candela.read_image(tmp_path / "b.jpg", raw=True))
    error = np.abs(np.round(decoded * 255) - image.to_srgb8().astype(np.float64))
    # Lossy, but at quality 100 within a few levels of the 8-bit picture.
    assert decoded.shape == (16, 16, 3) and error.mean() < 2.0
    grey = mi.Bitmap(image).convert(mi.Bitmap.PixelFormat.Y, mi.Struct.Type.UInt8, True)
    grey.write(tmp_path / "g.jpeg", quality=90)
    assert candela.read_image(tmp_path / "g.jpeg").shape == (16, 16, 1)


def test_util_write_bitmap_and_convert_to_bitmap(tmp_path, image):
    mi.util.write_bitmap(tmp_path / "u.png", image)
    mi.util.write_bitmap(str(tmp_path / "u.exr"), image, write_async=False)
    mi.util.write_bitmap(str(tmp_path / "u.jpg"), image)
    assert np.array_equal(decode_png((tmp_path / "u.png").read_bytes()), image.to_srgb8())
    assert np.array_equal(np.asarray(candela.read_image(tmp_path / "u.exr")), np.asarray(image))
    assert (tmp_path / "u.jpg").stat().st_size > 0
    converted = mi.util.convert_to_bitmap(image)
    assert converted.component_format() == mi.Struct.Type.UInt8 and np.array_equal(np.array(converted), image.to_srgb8())
    assert mi.util.convert_to_bitmap(image, uint8_srgb=False).component_format() == mi.Struct.Type.Float32
    import candela.mitsuba.util as util_module
    from candela.mitsuba import util

    assert util is util_module is mi.util
    assert mi.util.core_count() >= 1
    with pytest.raises(NotImplementedError, match="mitsuba.util.time_string"):
        mi.util.time_string(3.0)


# --- everything else ----------------------------------------------------------------------------

@pytest.mark.parametrize("name, words", [
    ("Float", "automatic differentiation"),
    ("TensorXf", "automatic differentiation"),
    ("UInt32", "automatic differentiation"),
    ("ScalarPoint2f", "Dr.Jit"),
    ("Loop", "Dr.Jit"),
    ("ad", "automatic differentiation"),
    ("register_bsdf", "custom plugins written in Python"),
    ("register_integrator", "custom plugins"),
    ("SamplingIntegrator", "custom plugins"),
    ("xml", "dict_to_xml"),
    ("Thread", "file resolver"),
    ("Texture", "plugin objects"),
    ("Ray3f", "ray tracing"),
    ("warp", "sampling queries"),
])
def test_what_is_not_offered_raises_not_implemented(name, words):
    with pytest.raises(NotImplementedError, match=words) as info:
        getattr(mi, name)
    assert f"mitsuba.{name}" in str(info.value)


def test_scene_and_plugin_methods_of_mitsuba():
    scene = mi.load_file(CBOX, res=8)
    with pytest.raises(NotImplementedError, match=r"Scene\.shapes_dr"):
        scene.shapes_dr()
    with pytest.raises(NotImplementedError, match=r"Scene\.ray_intersect"):
        scene.ray_intersect
    bsdf = mi.load_dict({"type": "diffuse"})
    with pytest.raises(NotImplementedError, match=r"bsdf\.eval"):
        bsdf.eval
    # Other names stay AttributeErrors; what the objects have works as before.
    assert not hasattr(scene, "no_such_method") and not hasattr(bsdf, "no_such_method")
    assert scene.film_size == (8, 8) and bsdf.type == "diffuse"


def test_drjit_calls_raise_not_implemented():
    # Scripts import Dr.Jit beside Mitsuba; without it installed, candela.mitsuba stands in for it.
    code = ("import candela.mitsuba as mi\nimport drjit as dr\n"
            "try:\n    dr.unravel(mi.Point3f, [1.0, 2.0, 3.0])\nexcept NotImplementedError as e:\n    print(e)\n")
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=subprocess_env())
    assert result.returncode == 0, result.stderr
    if "Dr.Jit" in result.stdout:
        assert result.stdout.startswith("drjit.unravel: Dr.Jit")
    else:  # a real Dr.Jit is installed: it is left alone
        import importlib.util

        assert importlib.util.find_spec("drjit") is not None


def test_unknown_names_are_attribute_errors():
    with pytest.raises(AttributeError):
        mi.no_such_thing
    assert not hasattr(mi, "no_such_thing")
    assert "load_dict" in dir(mi) and "is_rgb" in dir(mi)


def test_logging():
    mi.set_log_level(mi.LogLevel.Error)
    assert mi.log_level() == mi.LogLevel.Error
    mi.Log(mi.LogLevel.Warn, "not printed")
    with pytest.raises(RuntimeError, match="fatal"):
        mi.Log(mi.LogLevel.Error, "fatal")
    mi.set_log_level(mi.LogLevel.Warn)
