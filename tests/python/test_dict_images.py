"""Images in memory in a scene dictionary, as Mitsuba 3 takes them: a Bitmap as a bitmap texture's
or an envmap's 'bitmap', a tensor (a NumPy array) as a bitmap texture's 'data'. Each renders as
the same scene with the image written to a file and named by 'filename' does, and the temporary
files the loader read are gone afterwards."""

import os
import tempfile

import numpy as np
import pytest

import candela.mitsuba as mi
from conftest import candela

T = mi.ScalarTransform4f


@pytest.fixture(autouse=True)
def scalar_rgb():
    mi.set_variant("scalar_rgb")
    yield


@pytest.fixture
def temporary_directories(monkeypatch):
    """The directories tempfile.mkdtemp makes while a test runs."""
    made = []
    make = tempfile.mkdtemp

    def recording(*args, **kwargs):
        made.append(make(*args, **kwargs))
        return made[-1]

    monkeypatch.setattr(tempfile, "mkdtemp", recording)
    return made


def pixels(rng, shape, dtype=np.float32):
    if dtype == np.uint8:
        return rng.integers(0, 256, shape).astype(np.uint8)
    return rng.uniform(0.05, 0.95, shape).astype(dtype)


def textured(texture, seed=5):
    """A square filling the view, textured by `texture`, under a uniform sky, rendered."""
    d = {"type": "scene", "integrator": {"type": "direct"}, "light": {"type": "constant"},
         "sensor": {"type": "perspective", "fov": 40, "to_world": T.look_at(origin=[0, 0, 3], target=[0, 0, 0], up=[0, 1, 0]),
                    "sampler": {"type": "independent", "sample_count": 4},
                    "film": {"type": "hdrfilm", "width": 16, "height": 16, "rfilter": {"type": "box"}}},
         "square": {"type": "rectangle", "bsdf": {"type": "diffuse", "reflectance": texture}}}
    return np.asarray(mi.render(mi.load_dict(d), seed=seed))


def lit_by(envmap, seed=5):
    """A grey ball seen against `envmap`, lit by it, rendered."""
    d = {"type": "scene", "integrator": {"type": "path"}, "sky": envmap,
         "sensor": {"type": "perspective", "fov": 60, "to_world": T.look_at(origin=[0, 0, 3], target=[0, 0, 0], up=[0, 1, 0]),
                    "sampler": {"type": "independent", "sample_count": 4},
                    "film": {"type": "hdrfilm", "width": 16, "height": 16, "rfilter": {"type": "box"}}},
         "ball": {"type": "sphere", "bsdf": {"type": "diffuse"}}}
    return np.asarray(mi.render(mi.load_dict(d), seed=seed))


@pytest.mark.parametrize("dtype, channels, extension", [
    (np.float32, 3, ".exr"), (np.float32, 1, ".exr"), (np.float32, 4, ".exr"), (np.float32, 2, ".exr"), (np.float16, 3, ".exr"),
    (np.uint8, 3, ".png"), (np.uint8, 1, ".png"), (np.uint8, 4, ".png"), (np.uint8, 2, ".png"), (np.uint16, 3, ".png")])
def test_bitmap_texture_renders_as_its_file(tmp_path, temporary_directories, dtype, channels, extension):
    data = pixels(np.random.default_rng(1), (8, 8, channels), dtype)
    # Alpha is ignored (Mitsuba converts a texture's bitmap to Y or RGB): the file holds the colour.
    mi.Bitmap(data[:, :, :3 if channels >= 3 else 1]).write(tmp_path / f"texture{extension}")
    from_memory = textured({"type": "bitmap", "bitmap": mi.Bitmap(data), "filter_type": "nearest"})
    # A 16-bit Bitmap from an array is linear, as in Mitsuba (an 8-bit one sRGB-encoded).
    from_file = textured({"type": "bitmap", "filename": str(tmp_path / f"texture{extension}"), "filter_type": "nearest",
                          "raw": dtype == np.uint16})
    assert from_memory.mean() > 0 and np.array_equal(from_memory, from_file)
    assert temporary_directories and not any(os.path.exists(d) for d in temporary_directories)


def test_eight_bit_bitmap_is_srgb_unless_raw(tmp_path):
    # A UInt8 Bitmap is sRGB-encoded: decoded to linear as an 8-bit file is, unless 'raw' (Mitsuba
    # then leaves the values as stored) or the bitmap says it is linear (srgb_gamma false).
    data = pixels(np.random.default_rng(2), (8, 8, 3), np.uint8)
    bitmap = mi.Bitmap(data)
    assert bitmap.srgb_gamma()
    bitmap.write(tmp_path / "texture.png")
    decoded = textured({"type": "bitmap", "bitmap": bitmap})
    assert np.array_equal(decoded, textured({"type": "bitmap", "filename": str(tmp_path / "texture.png")}))
    stored = textured({"type": "bitmap", "filename": str(tmp_path / "texture.png"), "raw": True})
    assert not np.array_equal(decoded, stored)
    assert np.array_equal(textured({"type": "bitmap", "bitmap": bitmap, "raw": True}), stored)
    linear = mi.Bitmap(data)
    linear.set_srgb_gamma(False)
    assert np.array_equal(textured({"type": "bitmap", "bitmap": linear}), stored)
    # As linear float values, the same (to float precision) as the raw 8-bit file.
    as_floats = mi.Bitmap(data.astype(np.float32) / 255)
    assert np.allclose(textured({"type": "bitmap", "bitmap": as_floats}), stored, rtol=1e-5, atol=1e-6)


def test_bitmap_texture_in_the_spectral_variant(tmp_path):
    bitmap = mi.Bitmap(pixels(np.random.default_rng(7), (8, 8, 3), np.uint8))
    bitmap.write(tmp_path / "texture.png")
    with mi.variant_context("scalar_spectral"):
        from_memory = textured({"type": "bitmap", "bitmap": bitmap})
        assert np.array_equal(from_memory, textured({"type": "bitmap", "filename": str(tmp_path / "texture.png")}))
    assert not np.array_equal(from_memory, textured({"type": "bitmap", "bitmap": bitmap}))


@pytest.mark.parametrize("channels", [3, 1])
def test_data_tensor_renders_as_its_file(tmp_path, temporary_directories, channels):
    data = pixels(np.random.default_rng(3), (8, 6, channels))
    candela.write_image(tmp_path / "data.exr", data)
    from_memory = textured({"type": "bitmap", "data": data, "raw": True})
    assert from_memory.mean() > 0
    assert np.array_equal(from_memory, textured({"type": "bitmap", "filename": str(tmp_path / "data.exr"), "raw": True}))
    # A tensor is taken as linear values, 'raw' or not.
    assert np.array_equal(from_memory, textured({"type": "bitmap", "data": data}))
    assert temporary_directories and not any(os.path.exists(d) for d in temporary_directories)


def test_data_must_be_height_by_width_by_one_or_three():
    for data, words in ((np.zeros((4, 4, 4), np.float32), "1 or 3 channels"), (np.zeros((4, 4), np.float32), "H x W x C"),
                        (np.array([["a"]]), "H x W x C"), ("texture.png", "H x W x C"), (np.zeros((0, 4, 3)), "empty")):
        with pytest.raises(candela.DictError, match=rf"square\.bsdf\.reflectance\.data: .*{words}"):
            textured({"type": "bitmap", "data": data})


@pytest.mark.parametrize("dtype", [np.float32, np.uint8])
def test_envmap_bitmap_renders_as_its_file(tmp_path, temporary_directories, dtype):
    bitmap = mi.Bitmap(pixels(np.random.default_rng(4), (6, 12, 3), dtype) * dtype(2 if dtype == np.float32 else 1))
    # Mitsuba's envmap converts the bitmap to linear float RGB (an 8-bit one decoded from sRGB).
    bitmap.convert(component_format=mi.Struct.Type.Float32, srgb_gamma=False).write(tmp_path / "sky.exr")
    from_memory = lit_by({"type": "envmap", "bitmap": bitmap, "scale": 1.5})
    assert from_memory.mean() > 0
    assert np.array_equal(from_memory, lit_by({"type": "envmap", "filename": str(tmp_path / "sky.exr"), "scale": 1.5}))
    assert temporary_directories and not any(os.path.exists(d) for d in temporary_directories)


def test_envmap_takes_no_data():
    # Mitsuba's envmap exposes 'data' to traverse, but is made from 'filename' or 'bitmap' only.
    with pytest.raises(candela.DictError, match=r"sky\.data: .*'filename' or 'bitmap'"):
        lit_by({"type": "envmap", "data": np.ones((4, 8, 3), np.float32)})


def test_candela_load_dict_takes_images_and_arrays(tmp_path):
    rng = np.random.default_rng(5)
    linear = pixels(rng, (8, 8, 3))
    candela.write_image(tmp_path / "linear.exr", linear)
    encoded = pixels(rng, (8, 8, 3), np.uint8)
    mi.Bitmap(encoded).write(tmp_path / "encoded.png")

    def render(texture):
        d = {"type": "scene", "light": {"type": "constant"},
             "sensor": {"type": "perspective", "to_world": candela.Transform.look_at([0, 0, 3], [0, 0, 0], [0, 1, 0]),
                        "film": {"type": "hdrfilm", "width": 8, "height": 8}},
             "square": {"type": "rectangle", "bsdf": {"type": "diffuse", "reflectance": texture}}}
        return np.asarray(candela.render(candela.load_dict(d), spp=2, seed=1))

    from_file = render({"type": "bitmap", "filename": str(tmp_path / "linear.exr")})
    assert np.array_equal(render({"type": "bitmap", "data": linear}), from_file)
    assert np.array_equal(render({"type": "bitmap", "data": candela.Image(linear)}), from_file)
    assert np.array_equal(render({"type": "bitmap", "bitmap": candela.Image(linear)}), from_file)
    assert np.array_equal(render({"type": "bitmap", "bitmap": linear}), from_file)
    # An 8-bit array as 'bitmap' is taken as mi.Bitmap takes it: sRGB-encoded.
    encoded_file = render({"type": "bitmap", "filename": str(tmp_path / "encoded.png")})
    assert np.array_equal(render({"type": "bitmap", "bitmap": encoded}), encoded_file)
    # A checked plugin keeps its image for the scene it goes into.
    texture = candela.load_dict({"type": "bitmap", "bitmap": mi.Bitmap(linear)})
    assert np.array_equal(render(texture), from_file)


def test_no_temporary_files_remain_when_loading_fails(temporary_directories):
    bitmap = mi.Bitmap(np.full((4, 4, 3), 0.5, np.float32))
    with pytest.raises(candela.SceneError, match=r"square\.bsdf\.reflectance"):
        textured({"type": "bitmap", "bitmap": bitmap, "wrap_mode": "sideways"})
    # A dictionary refused after its first image was written.
    with pytest.raises(candela.DictError, match=r"square\.bsdf\.reflectance\.to_uv"):
        textured({"type": "bitmap", "data": np.zeros((2, 2, 3), np.float32), "to_uv": bitmap})
    with pytest.raises(candela.DictError, match="'filename' and 'bitmap'"):
        textured({"type": "bitmap", "bitmap": bitmap, "filename": "texture.png"})
    with pytest.raises(candela.DictError, match=r"reflectance\.bitmap: expected a Bitmap"):
        textured({"type": "bitmap", "bitmap": "texture.png"})
    with pytest.raises(candela.DictError, match=r"reflectance\.bitmap: a MultiChannel bitmap"):
        textured({"type": "bitmap", "bitmap": mi.Bitmap(np.zeros((4, 4, 5), np.float32))})
    assert temporary_directories and not any(os.path.exists(d) for d in temporary_directories)


def test_render_from_another_sensor_loads_the_images_again(temporary_directories):
    # mi.render(sensor=...) loads the scene again from its dictionary, Bitmap included.
    bitmap = mi.Bitmap(pixels(np.random.default_rng(6), (8, 8, 3), np.uint8))
    base = {"type": "scene", "integrator": {"type": "direct"}, "light": {"type": "constant"},
            "square": {"type": "rectangle", "bsdf": {"type": "diffuse", "reflectance": {"type": "bitmap", "bitmap": bitmap}}}}
    view = mi.load_dict({"type": "perspective", "fov": 40, "to_world": T.look_at(origin=[0.5, 0, 3], target=[0, 0, 0], up=[0, 1, 0]),
                         "sampler": {"type": "independent", "sample_count": 4},
                         "film": {"type": "hdrfilm", "width": 16, "height": 12}})
    scene = mi.load_dict(base)
    image = np.asarray(mi.render(scene, sensor=view, seed=2))
    assert image.mean() > 0
    assert np.array_equal(image, np.asarray(mi.render(mi.load_dict({**base, "sensor": view}), seed=2)))
    assert len(temporary_directories) >= 3 and not any(os.path.exists(d) for d in temporary_directories)
