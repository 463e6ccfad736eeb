"""The spectral variant from Python: candela's loaders take `variant=`, a scene knows its variant,
render's integrator override is loaded in it, and candela.mitsuba's spectral variants render in it.
The command line's `--variant scalar_spectral` is the reference (bit for bit), scalar_rgb renders
are the ones of a load without a variant."""

import subprocess
import sys

import numpy as np
import pytest

import candela.mitsuba as mi
from conftest import BINARY, Z, candela, cli_render, subprocess_env
from test_images import decode_png

# A grey floor and a grey ball lit by a rectangle whose emission is a measured spectrum: green,
# 500 to 570 nm. In the spectral variant the light is used per wavelength; in scalar_rgb it is
# the spectrum's colour.
SCENE = """<scene version="3.0.0">
    <default name="spp" value="16"/>
    <integrator type="path"><integer name="max_depth" value="3"/></integrator>
    <shape type="rectangle">
        <transform name="to_world"><scale value="3"/><rotate x="1" angle="-90"/><translate y="-1"/></transform>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.5, 0.5, 0.5"/></bsdf>
    </shape>
    <shape type="sphere">
        <float name="radius" value="0.6"/>
        <point name="center" value="0, -0.4, 0"/>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.7, 0.7, 0.7"/></bsdf>
    </shape>
    <shape type="rectangle">
        <transform name="to_world"><rotate x="1" angle="90"/><translate y="1.5"/></transform>
        <emitter type="area">
            <spectrum name="radiance" value="450:0, 490:0, 500:4, 570:4, 580:0, 700:0"/>
        </emitter>
    </shape>
    <sensor type="perspective">
        <float name="fov" value="50"/>
        <transform name="to_world"><lookat origin="0, 1, 4" target="0, 0, 0" up="0, 1, 0"/></transform>
        <sampler type="independent"><integer name="sample_count" value="$spp"/></sampler>
        <film type="hdrfilm">
            <integer name="width" value="32"/><integer name="height" value="24"/>
            <string name="component_format" value="float32"/>
        </film>
    </sensor>
</scene>
"""

RASTER = SCENE.replace('<integrator type="path"><integer name="max_depth" value="3"/></integrator>',
                       '<integrator type="raster"/>')


@pytest.fixture(autouse=True)
def scalar_rgb():
    mi.set_variant("scalar_rgb")
    yield
    mi.set_variant("scalar_rgb")


@pytest.fixture
def scene_file(tmp_path):
    path = tmp_path / "green_light.xml"
    path.write_text(SCENE)
    return path


def test_variants_and_the_scene_variant(scene_file):
    assert candela.variants() == ["scalar_rgb", "scalar_spectral"]
    assert candela.load_file(scene_file).variant == "scalar_rgb"
    assert candela.load_file(scene_file, variant="scalar_rgb").variant == "scalar_rgb"
    assert candela.load_file(scene_file, variant="scalar_spectral").variant == "scalar_spectral"
    assert candela.load_string(SCENE, variant="scalar_spectral").variant == "scalar_spectral"


def test_spectral_render_matches_the_command_line_and_is_green(scene_file, tmp_path):
    scene = candela.load_file(scene_file, variant="scalar_spectral", spp=8)
    image = candela.render(scene, seed=3)
    assert image.shape == (24, 32, 3) and image.dtype == np.float32
    assert np.all(np.isfinite(image))
    reference = cli_render(scene_file, tmp_path / "cli.exr", 8, 3, {"spp": 8}, extra=("--variant", "scalar_spectral"))
    assert np.array_equal(np.asarray(image), np.asarray(reference))
    # The light is green: so is what it lights, on average.
    r, g, b = np.asarray(image, dtype=np.float64).reshape(-1, 3).mean(axis=0)
    assert g > 0.05 and g > 2 * r and g > 2 * b


def test_spectral_render_estimates_the_rgb_render(scene_file):
    # Grey surfaces reflect every wavelength alike, so the spectral render estimates the image the
    # RGB render does (the light's colour is its spectrum's): the pixels' mean green agrees within
    # Z standard errors of the two renders' independent noise.
    spectral = np.asarray(candela.render(candela.load_file(scene_file, variant="scalar_spectral", spp=64), seed=1), np.float64)
    rgb = np.asarray(candela.render(candela.load_file(scene_file, spp=64), seed=2), np.float64)
    g_spectral, g_rgb = spectral[:, :, 1].reshape(-1), rgb[:, :, 1].reshape(-1)
    se = np.sqrt(g_spectral.var(ddof=1) / g_spectral.size + g_rgb.var(ddof=1) / g_rgb.size)
    assert abs(g_spectral.mean() - g_rgb.mean()) <= Z * se, (g_spectral.mean(), g_rgb.mean(), se)


def test_scalar_rgb_is_the_default_bit_for_bit(scene_file, tmp_path):
    default = candela.render(candela.load_file(scene_file, spp=4), seed=5)
    explicit = candela.render(candela.load_file(scene_file, spp=4, variant="scalar_rgb"), seed=5)
    from_dict_default = candela.render(candela.load_string(SCENE, spp=4), seed=5)
    assert np.array_equal(np.asarray(default), np.asarray(explicit))
    assert np.array_equal(np.asarray(default), np.asarray(from_dict_default))
    assert np.array_equal(np.asarray(default), np.asarray(cli_render(scene_file, tmp_path / "cli.exr", 4, 5, {"spp": 4})))
    spectral = candela.render(candela.load_file(scene_file, spp=4, variant="scalar_spectral"), seed=5)
    assert not np.array_equal(np.asarray(default), np.asarray(spectral))


def test_plugins_not_spectral_ready_name_scalar_rgb(tmp_path):
    with pytest.raises(candela.SceneError, match="scalar_rgb") as e:
        candela.load_string(RASTER, variant="scalar_spectral")
    assert "raster" in e.value.message and e.value.line > 0
    assert candela.load_string(RASTER).variant == "scalar_rgb"
    # A dictionary: at its key path.
    d = {"type": "scene", "ball": {"type": "sphere"}, "integrator": {"type": "raster"}}
    with pytest.raises(candela.SceneError, match=r"^integrator: .*scalar_rgb"):
        candela.load_dict(d, variant="scalar_spectral")
    candela.load_dict(d)
    with pytest.raises(candela.SceneError, match="scalar_rgb"):
        candela.load_dict({"type": "raster"}, variant="scalar_spectral")
    assert candela.load_dict({"type": "raster"}).kind == "integrator"


def test_an_integrator_override_is_loaded_in_the_scene_variant():
    spectral = candela.load_string(SCENE, variant="scalar_spectral", spp=1)
    for integrator in ("raster", {"type": "raster"}, candela.load_dict({"type": "raster"})):
        with pytest.raises(candela.SceneError, match=r"^integrator: .*scalar_rgb"):
            candela.render(spectral, integrator=integrator)
    # Those that render in the variant do, as in the scene file.
    direct = candela.render(spectral, integrator="direct", seed=2)
    in_file = candela.render(candela.load_string(SCENE.replace('<integrator type="path"><integer name="max_depth" value="3"/></integrator>',
                                                   '<integrator type="direct"/>'), variant="scalar_spectral", spp=1),
                             seed=2)
    assert np.array_equal(np.asarray(direct), np.asarray(in_file))
    # The RGB scene takes them all.
    candela.render(candela.load_string(SCENE, spp=1), integrator={"type": "ptracer", "max_depth": 2})


def test_bad_variant_names(scene_file):
    with pytest.raises(candela.InputError, match="is not a variant"):
        candela.load_file(scene_file, variant="scalar_rgb_polarized")
    with pytest.raises(candela.InputError, match=r"\"llvm_ad_rgb\" is not a variant \(known: scalar_rgb, scalar_spectral"):
        candela.load_file(scene_file, variant="llvm_ad_rgb")
    with pytest.raises(candela.InputError, match="is not a variant"):
        candela.load_dict({"type": "path"}, variant="spectral")
    with pytest.raises(TypeError, match="variant"):
        candela.load_string(SCENE, variant=1)
    with pytest.raises(candela.InputError, match="is not a variant"):
        candela.validate(scene_file, scene_file, variant="rgb")


def test_colour_edits_apply_in_the_spectral_variant():
    scene = candela.load_string(SCENE, variant="scalar_spectral", spp=2)
    before = candela.render(scene, seed=1)
    params = candela.traverse(scene)
    name = next(k for k in params.keys() if k.endswith("reflectance.value") and np.allclose(params[k], 0.7))
    params[name] = [0.0, 0.0, 0.0]
    params.update()
    after = candela.render(scene, seed=1)
    assert np.asarray(after).mean() < np.asarray(before).mean()


def test_editing_a_measured_emission_applies_in_the_spectral_variant():
    scene = candela.load_string(SCENE, variant="scalar_spectral", spp=2)
    params = candela.traverse(scene)
    name = next(k for k in params.keys() if k.endswith("emitter.radiance.value"))
    params[name] = [0.0, 0.0, 0.0]
    params.update()
    assert np.asarray(candela.render(scene, seed=1)).max() == 0.0


def test_variant_is_never_a_scene_parameter(tmp_path):
    # A scene with a parameter named `variant`: loaded without variant= it keeps its default;
    # with variant= the keyword would be ambiguous, and is refused instead of read one way.
    path = tmp_path / "named.xml"
    path.write_text(SCENE.replace('<default name="spp" value="16"/>', '<default name="spp" value="16"/>\n'
                                  '    <default name="variant" value="2"/>'))
    scene = candela.load_file(path)
    assert scene.variant == "scalar_rgb" and scene.parameters["variant"] == "2"
    with pytest.raises(candela.InputError, match="parameter named 'variant'"):
        candela.load_file(path, variant="scalar_spectral")
    # Mitsuba's loaders take the variant from set_variant: there, every keyword is a parameter.
    mi.set_variant("scalar_spectral")
    scene = mi.load_file(path, variant="3")
    assert scene.variant == "scalar_spectral" and scene.parameters["variant"] == "3"


# --- candela.mitsuba ------------------------------------------------------------------------------

def test_mitsuba_spectral_variants():
    for name in ("scalar_spectral", "llvm_spectral", "llvm_ad_spectral", "cuda_spectral", "cuda_ad_spectral"):
        assert name in mi.variants()
    mi.set_variant("scalar_spectral")
    assert mi.variant() == "scalar_spectral" and mi.is_spectral is True and mi.is_rgb is False
    assert mi.is_polarized is False and mi.is_monochromatic is False
    with mi.variant_context("scalar_rgb"):
        assert mi.is_rgb is True and mi.is_spectral is False
        assert mi.load_string(SCENE, spp=1).variant == "scalar_rgb"
    assert mi.variant() == "scalar_spectral" and mi.is_spectral is True
    assert mi.load_string(SCENE, spp=1).variant == "scalar_spectral"
    mi.set_variant("scalar_mono", "llvm_ad_spectral")
    assert mi.variant() == "llvm_ad_spectral" and mi.is_spectral is True and mi.is_polarized is False


def test_mitsuba_polarized_variant_renders_stokes_channels():
    # Two polarisers at 60 degrees in front of a light: Malus' law in S0 (a quarter of the aligned
    # pair's light), through Mitsuba's dict API and the stokes integrator.
    mi.set_variant("scalar_spectral_polarized")
    assert mi.is_polarized is True and mi.is_spectral is True and mi.is_rgb is False

    def scene(theta):
        return mi.load_dict({
            "type": "scene",
            "integrator": {"type": "stokes", "inner": {"type": "path"}},
            "sensor": {"type": "perspective", "fov": 2,
                       "to_world": mi.ScalarTransform4f.look_at(origin=[0, 0, 5], target=[0, 0, 0], up=[0, 1, 0]),
                       "sampler": {"type": "independent", "sample_count": 4},
                       "film": {"type": "hdrfilm", "width": 4, "height": 4, "rfilter": {"type": "box"}}},
            "light": {"type": "rectangle", "to_world": mi.ScalarTransform4f.translate([0, 0, -1]).scale(50),
                      "emitter": {"type": "area", "radiance": {"type": "rgb", "value": 1.0}}},
            "first": {"type": "rectangle", "to_world": mi.ScalarTransform4f.scale(50), "bsdf": {"type": "polarizer"}},
            "second": {"type": "rectangle", "to_world": mi.ScalarTransform4f.translate([0, 0, 1]).scale(50),
                       "bsdf": {"type": "polarizer", "theta": theta}},
        })

    aligned, turned = (np.asarray(mi.render(scene(t), seed=1)) for t in (0.0, 60.0))
    assert aligned.shape[-1] == 3 + 12
    np.testing.assert_allclose(turned[..., :3], 0.25 * aligned[..., :3], rtol=1e-5, atol=1e-7)
    s0, s1 = turned[..., 3 + 1], turned[..., 6 + 1]  # S0.G and S1.G
    np.testing.assert_allclose(s1 / s0, np.cos(np.radians(120.0)), atol=1e-3)


def test_mitsuba_loads_and_renders_in_the_current_variant(scene_file, tmp_path):
    mi.set_variant("scalar_spectral")
    image = mi.render(mi.load_file(scene_file, spp=8), seed=3)
    reference = cli_render(scene_file, tmp_path / "cli.exr", 8, 3, {"spp": 8}, extra=("--variant", "scalar_spectral"))
    assert np.array_equal(np.asarray(image), np.asarray(reference))
    with pytest.raises(candela.SceneError, match="scalar_rgb"):
        mi.load_string(RASTER)
    with pytest.raises(candela.SceneError, match="scalar_rgb"):
        mi.load_dict({"type": "raster"})
    # Rendered from a sensor object, the scene is loaded again in its own variant, whatever the
    # current one is.
    T = mi.ScalarTransform4f
    scene = mi.load_dict({"type": "scene", "light": {"type": "constant"}, "ball": {"type": "sphere"}})
    camera = mi.load_dict({"type": "perspective", "fov": 40, "to_world": T.look_at(origin=[0, 0, 4], target=[0, 0, 0], up=[0, 1, 0]),
                           "film": {"type": "hdrfilm", "width": 8, "height": 8}})
    mi.set_variant("scalar_rgb")
    assert mi.render(scene, sensor=camera, spp=2).shape == (8, 8, 3)
    with pytest.raises(candela.SceneError, match="scalar_rgb"):
        mi.render(scene, integrator="raster", sensor=camera, spp=1)


def test_mitsuba_cornell_box_in_the_spectral_variant():
    mi.set_variant("cuda_ad_spectral")
    box = mi.cornell_box()
    box["sensor"]["film"]["width"] = box["sensor"]["film"]["height"] = 16
    image = mi.render(mi.load_dict(box), spp=16)
    assert image.shape == (16, 16, 3) and np.all(np.isfinite(image))
    # The red wall is red, the green wall green, in the spectral variant too.
    left, right = np.asarray(image[4:12, 1:3]).reshape(-1, 3).mean(axis=0), np.asarray(image[4:12, 13:15]).reshape(-1, 3).mean(axis=0)
    assert left[0] > left[1] and right[1] > right[0]


def test_spectral_variants_give_a_notice_once():
    code = ("import candela.mitsuba as mi\n"
            "mi.set_variant('scalar_spectral'); mi.set_variant('llvm_ad_spectral'); mi.set_variant('llvm_ad_spectral')\n"
            "mi.set_variant('scalar_rgb'); mi.set_variant('cuda_spectral')\n")
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=subprocess_env())
    assert result.returncode == 0, result.stderr
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 2
    assert "'llvm_ad_spectral' renders as scalar_spectral" in lines[0] and "'cuda_spectral' renders as scalar_spectral" in lines[1]


def test_specfilm_from_a_mitsuba_dictionary():
    # Mitsuba's specfilm as its scripts write it: bands as 'spectrum' pairs and as a 'regular'
    # spectrum, named by their keys. Under a flat sky of radiance 1 each band is its response's
    # integral: 100 for both (a box over 400-500 nm, a ramp 0-2 over 550-650 nm). Channels in
    # alphabetical order; the RGB variant refuses the film.
    scene_dict = {
        "type": "scene",
        "integrator": {"type": "path"},
        "sensor": {
            "type": "perspective",
            "sampler": {"type": "independent", "sample_count": 64},
            "film": {
                "type": "specfilm", "width": 8, "height": 8, "component_format": "float32",
                "ramp": {"type": "regular", "wavelength_min": 550, "wavelength_max": 650, "values": "0, 1, 2"},
                "box": {"type": "spectrum", "value": [(400, 1.0), (500, 1.0)]},
            },
        },
        "sky": {"type": "constant", "radiance": {"type": "spectrum", "value": 1.0}},
    }
    with mi.variant_context("scalar_spectral"):
        image = mi.render(mi.load_dict(scene_dict))
        assert mi.Bitmap(image).channel_names() == ["box", "ramp"]
        pixels = np.asarray(image).reshape(-1, 2)
        # 64 independent pixels: the mean's error from their spread; Sidak at 1% over 2 bands.
        error = pixels.std(axis=0, ddof=1) / np.sqrt(len(pixels))
        assert np.all(np.abs(pixels.mean(axis=0) - 100.0) < 2.8 * error)
    with mi.variant_context("scalar_rgb"):
        with pytest.raises(Exception, match="spectral variants only"):
            mi.load_dict(scene_dict)


def test_the_viewer_refuses_a_specfilm(tmp_path):
    # The viewer's displays and its raster side are colour images: a specfilm scene stops with an
    # InputError from Python and exit code 2 from `candela view`, before anything is served.
    xml = """<scene version="3.0.0"><sensor type="perspective"><film type="specfilm">
        <integer name="width" value="8"/><integer name="height" value="8"/>
        <spectrum name="band" value="400:1, 500:1"/></film></sensor></scene>"""
    with pytest.raises(candela.InputError, match="specfilm"):
        candela.view(candela.load_string(xml, variant="scalar_spectral"))
    path = tmp_path / "specfilm.xml"
    path.write_text(xml)
    done = subprocess.run([str(BINARY), "view", str(path), "--variant", "scalar_spectral"], capture_output=True, text=True,
                          timeout=60, env=subprocess_env())
    assert done.returncode == 2
    assert "specfilm" in done.stderr


def test_a_specfilm_image_shows_its_bands_side_by_side():
    # Jupyter's picture of a specfilm render: each band in grey, left to right in the channels'
    # order, under one scale (the largest value white), not the first bands taken for R, G and B;
    # mitsuba.Bitmap has no RGB picture of bands and offers none (None: Jupyter shows the text).
    xml = """<scene version="3.0.0"><integrator type="path"/><sensor type="perspective">
        <sampler type="independent"><integer name="sample_count" value="4"/></sampler>
        <film type="specfilm"><integer name="width" value="6"/><integer name="height" value="4"/>
        <spectrum name="narrow" value="500:1, 550:1"/><spectrum name="wide" value="400:1, 600:1"/></film></sensor>
        <emitter type="constant"><spectrum name="radiance" value="1"/></emitter></scene>"""
    image = candela.render(candela.load_string(xml, variant="scalar_spectral"))
    assert image.channels == ["narrow", "wide"]
    shown = decode_png(image._repr_png_())
    assert shown.shape == (4, 12, 3)
    bands = np.asarray(image, dtype=np.float64)
    expected = candela.image.srgb8(np.repeat((np.concatenate([bands[:, :, 0], bands[:, :, 1]], axis=1) / bands.max())[:, :, None], 3, axis=2))
    assert np.array_equal(shown, expected)
    # The wide band (200 nm of a flat sky, about 200) on the right, brighter than the narrow one
    # (50 nm, about 50). Each sample's wide value is at least its narrow one (the wide response
    # covers the narrow one), so every pixel is at least as bright, and the tile brighter.
    assert np.all(shown[:, 6:] >= shown[:, :6]) and shown[:, 6:].mean() > shown[:, :6].mean()
    assert mi.Bitmap(image)._repr_png_() is None
