"""Scene parameters (candela.traverse): edits applied by update() give the same image as loading a
file edited to hold the same values, bit for bit where both build the scene the same way."""

import numpy as np
import pytest

from conftest import SCENES, assert_same_expectation, candela, cli_render

SOURCE = (SCENES / "validation" / "cbox.xml").read_text()
RES, SPP, SEED = 24, 4, 1


def edited(tmp_path, old, new, name="edited.xml"):
    assert SOURCE.count(old) == 1, old
    path = tmp_path / name
    path.write_text(SOURCE.replace(old, new))
    return path


def render(scene):
    return np.asarray(candela.render(scene, spp=SPP, seed=SEED))


@pytest.fixture
def scene():
    return candela.load_file(SCENES / "validation" / "cbox.xml", res=RES)


def test_names_types_and_values(scene):
    params = candela.traverse(scene)
    keys = params.keys()
    for name, kind in [("red.reflectance.value", "color"), ("light.emitter.radiance.value", "color"),
                       ("tall_box.vertex_positions", "floats"), ("PerspectiveCamera.to_world", "transform"),
                       ("PerspectiveCamera.x_fov", "float")]:
        assert name in keys and name in params
        assert params.type(name) == kind
    assert len(params) == len(keys) == len(list(iter(params)))
    assert np.allclose(params["red.reflectance.value"], [0.63, 0.065, 0.05])
    assert params["PerspectiveCamera.x_fov"] == pytest.approx(39.3077, rel=1e-6)
    to_world = params["PerspectiveCamera.to_world"]
    assert isinstance(to_world, candela.Transform)
    assert np.allclose(to_world.matrix, [[-1, 0, 0, 0], [0, 1, 0, 0], [0, 0, -1, 3.9], [0, 0, 0, 1]])
    positions = params["tall_box.vertex_positions"]
    assert positions.dtype == np.float32 and positions.ndim == 1 and positions.size % 3 == 0
    # A value assigned reads back before update(); update() names what it changed, once.
    params["red.reflectance.value"] = 0.5
    assert np.array_equal(params["red.reflectance.value"], [0.5, 0.5, 0.5])
    assert params.update() == ["red.reflectance.value"]
    assert params.update() == []
    assert np.array_equal(candela.traverse(scene)["red.reflectance.value"], [0.5, 0.5, 0.5])
    assert "red.reflectance.value" in repr(params)


def test_reflectance_edit_equals_the_edited_file(tmp_path, scene):
    original = render(scene)
    params = candela.traverse(scene)
    params["red.reflectance.value"] = [0.2, 0.6, 0.25]
    params.update()
    after = render(scene)
    path = edited(tmp_path, '<rgb name="reflectance" value="0.63, 0.065, 0.05"/>', '<rgb name="reflectance" value="0.2, 0.6, 0.25"/>')
    assert np.array_equal(after, render(candela.load_file(path, res=RES)))
    assert np.array_equal(after, np.asarray(cli_render(path, tmp_path / "cli.exr", SPP, SEED, {"res": RES})))
    assert not np.array_equal(after, original)
    # Back to the file's value: the first image again, bit for bit.
    params["red.reflectance.value"] = [0.63, 0.065, 0.05]
    params.update()
    assert np.array_equal(render(scene), original)


def test_emitter_edit_scales_the_image_exactly(scene):
    original = render(scene)
    params = candela.traverse(scene)
    params["light.emitter.radiance.value"] = np.array(params["light.emitter.radiance.value"]) * 2
    params.update()
    # Light transport is linear in the emission, and doubling is exact in floating point.
    assert np.array_equal(render(scene), 2 * original)


def test_field_of_view_edit_equals_the_edited_file(tmp_path, scene):
    params = candela.traverse(scene)
    params["PerspectiveCamera.x_fov"] = 30.0
    params.update()
    path = edited(tmp_path, '<float name="fov" value="39.3077"/>', '<float name="fov" value="30"/>')
    assert np.array_equal(render(scene), render(candela.load_file(path, res=RES)))


def test_camera_transform_edit_equals_the_edited_file(tmp_path, scene):
    lookat = '<lookat origin="0, 0, 3.9" target="0, 0, 0" up="0, 1, 0"/>'
    params = candela.traverse(scene)
    # An axis-aligned view: float (the file) and double (candela.Transform) give the same matrix.
    params["PerspectiveCamera.to_world"] = candela.Transform.look_at([0.5, 0.25, 3.5], [0.5, 0.25, 0], [0, 1, 0])
    params.update()
    path = edited(tmp_path, lookat, '<lookat origin="0.5, 0.25, 3.5" target="0.5, 0.25, 0" up="0, 1, 0"/>')
    assert np.array_equal(render(scene), render(candela.load_file(path, res=RES)))
    # Any view: the same matrix as a <matrix> gives the same pixels; as a <lookat> (composed in
    # float by the loader) the same image up to rounding.
    view = candela.Transform.look_at([0.3, 0.2, 3.5], [0, -0.1, 0], [0, 1, 0])
    params["PerspectiveCamera.to_world"] = view
    params.update()
    image = render(scene)
    values = ", ".join(repr(float(v)) for v in view.matrix.reshape(16))
    as_matrix = edited(tmp_path, lookat, f'<matrix value="{values}"/>', "matrix.xml")
    assert np.array_equal(image, render(candela.load_file(as_matrix, res=RES)))
    as_lookat = edited(tmp_path, lookat, '<lookat origin="0.3, 0.2, 3.5" target="0, -0.1, 0" up="0, 1, 0"/>', "lookat.xml")
    assert_same_expectation(image, render(candela.load_file(as_lookat, res=RES)), "to_world vs <lookat>")


def test_vertex_edit_equals_the_translated_file(tmp_path, scene):
    original = render(scene)
    params = candela.traverse(scene)
    shift = np.array([0.1, 0.0, 0.05], dtype=np.float32)
    params["tall_box.vertex_positions"] = (params["tall_box.vertex_positions"].reshape(-1, 3) + shift).reshape(-1)
    params.update()
    moved = render(scene)
    path = edited(tmp_path, '<translate x="-0.33" y="-0.4" z="-0.28"/>',
                  '<translate x="-0.33" y="-0.4" z="-0.28"/><translate x="0.1" y="0" z="0.05"/>')
    from_file = candela.load_file(path, res=RES)
    # The same positions up to float rounding (the file composes the translation into the matrix)...
    assert np.allclose(candela.traverse(from_file)["tall_box.vertex_positions"], params["tall_box.vertex_positions"], atol=1e-6)
    # ... and the same image up to that rounding (the BVH is rebuilt around the new positions).
    file_image = render(from_file)
    assert_same_expectation(moved, file_image, "moved box vs translated file")
    assert np.count_nonzero(moved != file_image) < np.count_nonzero(moved != original)
    # Putting the vertices back restores the first image exactly.
    params["tall_box.vertex_positions"] = (params["tall_box.vertex_positions"].reshape(-1, 3) - shift).reshape(-1)
    params.update()
    restored = candela.traverse(scene)["tall_box.vertex_positions"]
    assert np.allclose(restored, candela.traverse(candela.load_file(SCENES / "validation" / "cbox.xml"))["tall_box.vertex_positions"], atol=1e-6)
    assert_same_expectation(render(scene), original, "restored box")


def test_several_edits_in_one_update(tmp_path, scene):
    params = candela.traverse(scene)
    params["green.reflectance.value"] = [0.1, 0.1, 0.6]
    params["white.reflectance.value"] = 0.5
    params["PerspectiveCamera.x_fov"] = 45
    assert sorted(params.update()) == ["PerspectiveCamera.x_fov", "green.reflectance.value", "white.reflectance.value"]
    text = SOURCE.replace('value="0.14, 0.45, 0.091"', 'value="0.1, 0.1, 0.6"')
    text = text.replace('value="0.725, 0.71, 0.68"', 'value="0.5"').replace('<float name="fov" value="39.3077"/>', '<float name="fov" value="45"/>')
    path = tmp_path / "several.xml"
    path.write_text(text)
    assert np.array_equal(render(scene), render(candela.load_file(path, res=RES)))


def test_a_mapping_with_copy_delete_and_update_values(scene):
    from collections.abc import Mapping

    params = candela.traverse(scene)
    assert isinstance(params, Mapping)
    assert list(params) == list(params.keys()) and dict(params).keys() == params.keys()
    assert params.get("PerspectiveCamera.x_fov") == pytest.approx(39.3077, rel=1e-6)
    assert params.get("no.such.value", 1.5) == 1.5
    view = params.copy()
    assert type(view) is candela.SceneParameters and list(view.keys()) == list(params.keys())
    del view["PerspectiveCamera.x_fov"]
    assert "PerspectiveCamera.x_fov" not in view and "PerspectiveCamera.x_fov" in params
    # update(values) assigns the names the view holds (others are ignored), then applies.
    assert view.update({"PerspectiveCamera.x_fov": 30.0, "red.reflectance.value": [0.2, 0.6, 0.25]}) == ["red.reflectance.value"]
    assert params["PerspectiveCamera.x_fov"] == pytest.approx(39.3077, rel=1e-6)
    assert np.allclose(params["red.reflectance.value"], [0.2, 0.6, 0.25])
    assert params.update({"PerspectiveCamera.x_fov": 30.0}) == ["PerspectiveCamera.x_fov"]
    assert candela.traverse(scene)["PerspectiveCamera.x_fov"] == 30.0
    # An assignment made before the name is deleted from the view is still applied, as in Mitsuba.
    view["white.reflectance.value"] = 0.5
    del view["white.reflectance.value"]
    assert view.update() == ["white.reflectance.value"]
    assert np.array_equal(params["white.reflectance.value"], [0.5, 0.5, 0.5])
