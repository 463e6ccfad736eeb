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
    with pytest.raises(ValueError, match="sensor"):
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
    with pytest.raises(NotImplementedError, match="resample"):
        b.resample([8, 8])


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
    ("BSDF", "plugin objects"),
    ("Ray3f", "ray tracing"),
    ("warp", "sampling queries"),
])
def test_what_is_not_offered_raises_not_implemented(name, words):
    with pytest.raises(NotImplementedError, match=words) as info:
        getattr(mi, name)
    assert f"mitsuba.{name}" in str(info.value)


def test_scene_and_plugin_methods_of_mitsuba():
    scene = mi.load_file(CBOX, res=8)
    with pytest.raises(NotImplementedError, match=r"Scene\.sensors"):
        scene.sensors()
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
