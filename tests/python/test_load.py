"""Loading scenes: load_file with $parameters, load_string, load_dict (Mitsuba 3's dictionary
format) checked against the XML it stands for by rendering both."""

import numpy as np
import pytest

from conftest import SCENES, candela


def render_pixels(scene, spp=4, seed=3):
    return np.asarray(candela.render(scene, spp=spp, seed=seed))


def test_load_file_keyword_parameters():
    scene = candela.load_file(SCENES / "cbox.xml", res=16, spp=3)
    assert isinstance(scene, candela.Scene)
    assert scene.film_size == (16, 16)
    assert scene.spp == 3
    assert scene.integrator == "path"
    # Without keywords the scene's defaults hold (res 256, spp 64).
    default = candela.load_file(str(SCENES / "cbox.xml"))
    assert default.film_size == (256, 256) and default.spp == 64


def test_load_file_parameter_kinds(tmp_path):
    # Booleans, numbers and sequences become the text the scene file would hold.
    (tmp_path / "s.xml").write_text("""<scene version="3.0.0">
        <default name="flip" value="false"/><default name="colour" value="1, 1, 1"/><default name="r" value="1"/>
        <integrator type="path"/>
        <sensor type="perspective"><float name="fov" value="90"/>
            <transform name="to_world"><lookat origin="0, 0, 0" target="0, 0, 1" up="0, 1, 0"/></transform>
            <film type="hdrfilm"><integer name="width" value="4"/><integer name="height" value="4"/>
                <rfilter type="box"/><string name="component_format" value="float32"/></film></sensor>
        <shape type="sphere"><float name="radius" value="$r"/><boolean name="flip_normals" value="$flip"/>
            <bsdf type="diffuse"><rgb name="reflectance" value="0"/></bsdf>
            <emitter type="area"><rgb name="radiance" value="$colour"/></emitter></shape>
    </scene>""")
    # The camera is inside the sphere: it sees the emitting inside only with flipped normals.
    inside_dark = render_pixels(candela.load_file(tmp_path / "s.xml", colour=[0.5, 0.25, 2.0], r=2))
    inside_lit = render_pixels(candela.load_file(tmp_path / "s.xml", flip=True, colour=np.array([0.5, 0.25, 2.0]), r=2.0))
    assert np.all(inside_dark == 0)
    assert np.allclose(inside_lit, [0.5, 0.25, 2.0])


def test_load_string_resolves_files_from_the_working_directory(tmp_path, monkeypatch):
    xml = (SCENES / "validation" / "textured.xml").read_text()
    monkeypatch.chdir(SCENES / "validation")
    scene = candela.load_string(xml, res=8, spp=2)
    assert scene.film_size == (8, 8)
    from_file = candela.load_file(SCENES / "validation" / "textured.xml", res=8, spp=2)
    assert np.array_equal(render_pixels(scene), render_pixels(from_file))


# A scene as a dictionary, and the same scene as XML: the dictionary exercises nested plugins,
# ids and references, transforms as 4x4 arrays and as candela.Transform, rgb and spectrum values,
# booleans, integers, floats, strings and points.
MATRIX = [[2.0, 0.0, 0.0, 0.25], [0.0, 2.0, 0.0, -1.0], [0.0, 0.0, 2.0, -1.0], [0.0, 0.0, 0.0, 1.0]]
# A lamp above the spheres, facing down.
LAMP = [[0.5, 0.0, 0.0, 0.0], [0.0, 0.0, -0.5, 2.5], [0.0, 0.5, 0.0, 1.0], [0.0, 0.0, 0.0, 1.0]]


def dict_scene():
    T = candela.Transform
    return {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": 5, "hide_emitters": False},
        "sensor": {
            "type": "perspective",
            "fov": 45.0,
            "to_world": T.translate([0.0, 0.5, 6.0]) @ T.scale([-1.0, 1.0, -1.0]),
            "sampler": {"type": "independent", "sample_count": 4},
            "film": {"type": "hdrfilm", "width": 24, "height": 16, "rfilter": {"type": "box"},
                     "component_format": "float32"},
        },
        "grey": {"type": "diffuse", "reflectance": {"type": "spectrum", "value": 0.5}},
        "floor": {"type": "rectangle", "to_world": MATRIX, "bsdf": {"type": "ref", "id": "grey"}},
        "ball": {"type": "sphere", "center": [0.5, 0.0, 0.0], "radius": 0.75,
                 "bsdf": {"type": "diffuse", "id": "red", "reflectance": {"type": "rgb", "value": [0.7, 0.2, 0.1]}}},
        "ball2": {"type": "sphere", "center": [-1.0, 0.25, 0.0], "radius": 0.5, "bsdf": {"type": "ref", "id": "red"}},
        "lamp": {"type": "rectangle", "to_world": np.array(LAMP),
                 "emitter": {"type": "area", "radiance": {"type": "rgb", "value": 4.0}}},
        "sky": {"type": "constant", "radiance": {"type": "spectrum", "value": [(400, 0.2), (700, 0.2)]}},
    }


def matrix_text(m):
    return ", ".join(repr(float(v)) for v in np.asarray(m, dtype=float).reshape(16))


def xml_scene():
    lamp = LAMP
    return f"""<scene version="3.0.0">
    <integrator type="path"><integer name="max_depth" value="5"/><boolean name="hide_emitters" value="false"/></integrator>
    <sensor type="perspective">
        <float name="fov" value="45"/>
        <transform name="to_world"><scale x="-1" y="1" z="-1"/><translate x="0" y="0.5" z="6"/></transform>
        <sampler type="independent"><integer name="sample_count" value="4"/></sampler>
        <film type="hdrfilm"><integer name="width" value="24"/><integer name="height" value="16"/><rfilter type="box"/>
            <string name="component_format" value="float32"/></film>
    </sensor>
    <bsdf type="diffuse" id="grey"><spectrum name="reflectance" value="0.5"/></bsdf>
    <shape type="rectangle" id="floor"><transform name="to_world"><matrix value="{matrix_text(MATRIX)}"/></transform>
        <ref id="grey"/></shape>
    <shape type="sphere" id="ball"><point name="center" value="0.5, 0, 0"/><float name="radius" value="0.75"/>
        <bsdf type="diffuse" id="red"><rgb name="reflectance" value="0.7, 0.2, 0.1"/></bsdf></shape>
    <shape type="sphere" id="ball2"><point name="center" value="-1, 0.25, 0"/><float name="radius" value="0.5"/><ref id="red"/></shape>
    <shape type="rectangle" id="lamp"><transform name="to_world"><matrix value="{matrix_text(lamp)}"/></transform>
        <emitter type="area"><rgb name="radiance" value="4"/></emitter></shape>
    <emitter type="constant" id="sky"><spectrum name="radiance" value="400:0.2, 700:0.2"/></emitter>
</scene>"""


def test_load_dict_equals_the_xml_it_stands_for():
    from_dict = candela.load_dict(dict_scene())
    from_xml = candela.load_string(xml_scene())
    assert from_dict.film_size == (24, 16) and from_dict.spp == 4
    a, b = render_pixels(from_dict, spp=8, seed=11), render_pixels(from_xml, spp=8, seed=11)
    assert a.shape == (16, 24, 3)
    assert a.mean() > 0
    assert np.array_equal(a, b)
    # Ids: top-level keys and explicit 'id's name the objects; traverse sees them.
    names = candela.traverse(from_dict).keys()
    assert "grey.reflectance.value" in names and "red.reflectance.value" in names
    assert "lamp.emitter.radiance.value" in names and "sensor.to_world" in names


def test_load_dict_transform_object_and_array_agree():
    d = dict_scene()
    d["sensor"]["to_world"] = (candela.Transform.translate([0.0, 0.5, 6.0]) @ candela.Transform.scale([-1.0, 1.0, -1.0])).matrix
    d["floor"]["to_world"] = candela.Transform(MATRIX)
    assert np.array_equal(render_pixels(candela.load_dict(d)), render_pixels(candela.load_dict(dict_scene())))


def test_load_dict_of_a_single_plugin_is_a_checked_plugin():
    integrator = candela.load_dict({"type": "path", "max_depth": 2})
    assert isinstance(integrator, candela.Plugin)
    assert integrator.kind == "integrator" and integrator.type == "path"
    bsdf = candela.load_dict({"type": "diffuse", "reflectance": {"type": "rgb", "value": [0.1, 0.2, 0.3]}})
    assert bsdf.kind == "bsdf"
    # A checked plugin goes into another dictionary as a value.
    d = dict_scene()
    d["ball3"] = {"type": "sphere", "center": [0.0, 1.5, 0.0], "radius": 0.25, "bsdf": bsdf}
    assert isinstance(candela.load_dict(d), candela.Scene)
    with pytest.raises(candela.SceneError, match="max_depth"):
        candela.load_dict({"type": "path", "max_depth": "deep"})


def test_a_merge_dictionary_adds_its_shapes_to_the_scene():
    # Mitsuba 3.8's merge shape, as scripts write it: its shapes are the scene's own, and the
    # image is the one of the same shapes written at the top level, bit for bit.
    shapes = {"a": {"type": "sphere"}, "b": {"type": "cube", "to_world": candela.mitsuba.ScalarTransform4f().translate([2, 0, 0])}}
    base = {"type": "scene", "sky": {"type": "constant"},
            "camera": {"type": "perspective", "to_world": candela.mitsuba.ScalarTransform4f().look_at(origin=[0, 0, 6], target=[1, 0, 0], up=[0, 1, 0]),
                       "film": {"type": "hdrfilm", "width": 16, "height": 12}}}
    flat = candela.load_dict({**base, **shapes})
    merged = candela.load_dict({**base, "merged": {"type": "merge", **shapes}})
    np.testing.assert_array_equal(render_pixels(flat), render_pixels(merged))
