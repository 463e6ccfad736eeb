"""Errors: scene errors as exceptions carrying the command line's `file:line: message`, dictionary
errors naming the key path, and bad input from Python (wrong types, bad numbers, unknown
plugins, missing files) as Python exceptions with the reason, never a crash."""

import subprocess

import numpy as np
import pytest

from conftest import BINARY, SCENES, candela

BROKEN = {
    # name: (text, line of the error, words of the reason)
    "bad_number": ('<scene version="3.0.0">\n  <integrator type="path"/>\n  <shape type="sphere">\n'
                   '    <float name="radius" value="abc"/>\n  </shape>\n</scene>\n', 4, "not a number"),
    "bad_xml": ('<scene version="3.0.0">\n  <shape type="sphere">\n    <bsdf type="diffuse">\n  </shape>\n</scene>\n',
                4, "malformed XML"),
    "unknown_plugin": ('<scene version="3.0.0">\n\n  <shape type="nosuchshape"/>\n</scene>\n', 3, "unknown shape type"),
}


@pytest.mark.parametrize("name", sorted(BROKEN))
def test_scene_error_carries_file_and_line(tmp_path, name):
    text, line, reason = BROKEN[name]
    path = tmp_path / f"{name}.xml"
    path.write_text(text)
    with pytest.raises(candela.SceneError) as info:
        candela.load_file(path)
    e = info.value
    assert str(e).startswith(f"{path}:{line}: ")
    assert reason in str(e)
    assert (e.file, e.line) == (str(path), line)
    assert reason in e.message
    assert isinstance(e, ValueError)
    # The command line prints the same line and exits with 2.
    cli = subprocess.run([str(BINARY), "render", str(path), "-o", str(tmp_path / "x.exr"), "-q"], capture_output=True, text=True)
    assert cli.returncode == 2
    assert str(e) in cli.stderr


def test_load_string_error_line():
    with pytest.raises(candela.SceneError) as info:
        candela.load_string('<scene version="3.0.0">\n<shape type="sphere"><float name="radius" value="-"/></shape></scene>')
    assert info.value.line == 2
    assert ":2: " in str(info.value)


def test_missing_file_names_the_path_and_the_reason(tmp_path):
    missing = tmp_path / "nowhere.xml"
    with pytest.raises(candela.SceneError, match="no such file") as info:
        candela.load_file(missing)
    assert str(missing) in str(info.value)
    with pytest.raises(candela.InputError, match="nowhere.exr"):
        candela.read_image(tmp_path / "nowhere.exr")
    with pytest.raises(candela.SceneError, match=r"ball\.bsdf\.reflectance\.filename: file not found"):
        candela.load_dict({"type": "scene", "ball": {"type": "sphere", "bsdf": {"type": "diffuse", "reflectance": {
            "type": "bitmap", "filename": str(tmp_path / "none.png")}}}})


def test_dict_errors_name_the_key_path():
    with pytest.raises(candela.SceneError) as info:
        candela.load_dict({"type": "scene", "sphere": {"type": "sphere", "bsdf": {"type": "diffuse", "foo": 1.0}}})
    assert str(info.value).startswith("sphere.bsdf.foo: ")
    assert "foo" in info.value.message
    with pytest.raises(candela.SceneError, match=r"^sphere\.radius: .*expected float"):
        candela.load_dict({"type": "scene", "sphere": {"type": "sphere", "radius": "big"}})
    with pytest.raises(candela.SceneError, match=r"^ball\.bsdf: reference to unknown id"):
        candela.load_dict({"type": "scene", "ball": {"type": "sphere", "bsdf": {"type": "ref", "id": "nothing"}}})


def test_dict_unknown_plugin_and_bad_values():
    with pytest.raises(candela.DictError, match=r"sphere: unknown plugin type 'spherex'"):
        candela.load_dict({"type": "scene", "sphere": {"type": "spherex"}})
    with pytest.raises(candela.DictError, match=r"s\.bsdf: unknown plugin type 'difuse'"):
        candela.load_dict({"type": "scene", "s": {"type": "sphere", "bsdf": {"type": "difuse"}}})
    with pytest.raises(candela.DictError, match=r"a\.bsdf\.reflectance\.value: an rgb takes one or three numbers"):
        candela.load_dict({"type": "scene", "a": {"type": "sphere", "bsdf": {"type": "diffuse", "reflectance": {
            "type": "rgb", "value": [1, 2]}}}})
    with pytest.raises(candela.DictError, match=r"a\.radius: .* is not finite"):
        candela.load_dict({"type": "scene", "a": {"type": "sphere", "radius": float("nan")}})
    with pytest.raises(candela.DictError, match=r"a\.center: cannot make a scene property"):
        candela.load_dict({"type": "scene", "a": {"type": "sphere", "center": [1, 2]}})
    with pytest.raises(candela.DictError, match="a plugin needs a 'type'"):
        candela.load_dict({"type": "scene", "a": {"type": 3}})
    with pytest.raises(candela.DictError, match="expects a dictionary"):
        candela.load_dict([("type", "scene")])
    with pytest.raises(candela.DictError, match="unknown plugin type"):
        candela.load_dict({"type": "nosuch"})
    # DictError is a ValueError, as SceneError is.
    assert issubclass(candela.DictError, ValueError)


@pytest.fixture(scope="module")
def small_scene():
    return candela.load_file(SCENES / "cbox.xml", res=8, spp=1)


@pytest.mark.parametrize("kwargs, error, words", [
    (dict(spp=-1), ValueError, "spp"),
    (dict(spp=0), ValueError, "spp"),
    (dict(spp=2.5), ValueError, "spp"),
    (dict(spp="4"), ValueError, "spp"),
    (dict(spp=True), ValueError, "spp"),
    (dict(spp=1 << 31), ValueError, "spp"),
    (dict(seed=-1), ValueError, "seed"),
    (dict(seed=1 << 64), ValueError, "seed"),
    (dict(seed=1.5), ValueError, "seed"),
    (dict(threads=-2), ValueError, "threads"),
    (dict(sensor=1), ValueError, "sensor"),
    (dict(progress=5), TypeError, "callable"),
    (dict(integrator=42), TypeError, "integrator"),
    (dict(integrator="nosuch"), candela.DictError, "nosuch"),
    (dict(integrator={"type": "path", "max_depth": "deep"}), candela.SceneError, "max_depth"),
    (dict(aovs=["bogus"]), candela.InputError, "bogus"),
])
def test_bad_render_arguments(small_scene, kwargs, error, words):
    with pytest.raises(error, match=words):
        candela.render(small_scene, **kwargs)


def test_bad_types():
    with pytest.raises(TypeError, match="candela.Scene"):
        candela.render("scenes/cbox.xml")
    with pytest.raises(TypeError):
        candela.load_file(123)
    with pytest.raises(TypeError):
        candela.load_string(b'<scene version="3.0.0"/>')
    with pytest.raises(TypeError, match="candela.Scene"):
        candela.traverse("scene")


def test_progress_callback_exception_propagates(small_scene):
    def fail(fraction):
        raise RuntimeError("from the callback")

    with pytest.raises(RuntimeError, match="from the callback"):
        candela.render(small_scene, spp=4096, progress=fail)
    # The scene renders again afterwards.
    assert np.isfinite(np.asarray(candela.render(small_scene))).all()


def test_bad_parameter_edits(small_scene):
    params = candela.traverse(small_scene)
    with pytest.raises(KeyError, match=r"no parameter 'reflectance.value'; did you mean '\w+\.reflectance\.value'"):
        params["reflectance.value"] = 1.0
    with pytest.raises(ValueError, match="color"):
        params["red.reflectance.value"] = [1.0, 2.0]
    with pytest.raises(ValueError, match="finite"):
        params["red.reflectance.value"] = [1.0, float("inf"), 0.0]
    with pytest.raises(ValueError):
        params["PerspectiveCamera.to_world"] = np.zeros(12)
    with pytest.raises((ValueError, TypeError)):
        params["PerspectiveCamera.x_fov"] = "wide"
    assert params.update() == []


def test_bad_images(tmp_path):
    with pytest.raises(ValueError, match="height x width x channels"):
        candela.Image(np.zeros((2, 2, 2, 2)))
    with pytest.raises(ValueError, match=r"\.exr or \.png"):
        candela.write_image(tmp_path / "x.tiff", np.zeros((2, 2, 3)))
    with pytest.raises(candela.InputError):
        candela.write_image(tmp_path / "no" / "such" / "dir.exr", np.zeros((2, 2, 3)))
    not_an_image = tmp_path / "text.exr"
    not_an_image.write_text("hello")
    with pytest.raises(candela.InputError):
        candela.read_image(not_an_image)
