"""Mitsuba 3's Python API, the part its getting-started scripts use, on Candela:

    import candela.mitsuba as mi          # instead of: import mitsuba as mi
    mi.set_variant("scalar_rgb")
    scene = mi.load_file("scenes/cbox.xml", res=128)
    image = mi.render(scene, spp=64)
    params = mi.traverse(scene)
    params["red.reflectance.value"] = mi.Color3f(0.2, 0.6, 0.2)
    params.update()
    mi.util.write_bitmap("cbox.png", mi.render(scene, spp=64, seed=1))

What is here behaves as Mitsuba's does, rendered by Candela: RGB and spectral variants (the LLVM
and CUDA ones run on Candela's CPU renderer, with a notice), scenes from files, strings and
dictionaries, rendering, traverse/update, what a scene holds (its sensors with their films and
samplers, shapes, emitters and bounds, read-only), the transform and 3-vector types, Bitmap and
mi.util's image writers, the Cornell box dictionary. What is not here (autodiff and Dr.Jit arrays,
Python plugins, ray queries from Python, polarised and monochrome rendering, ...) raises
NotImplementedError naming the feature instead of answering differently from Mitsuba.
docs/python.md has the table.
"""

from __future__ import annotations

import contextlib
import copy
import enum
import os
import re
import struct
import sys
import threading
import types
import weakref
from xml.parsers import expat as _expat
import zlib

import numpy as np

import candela as _candela
from . import _candela as _native
from ._dict import Plugin as _Plugin, scene_xml as _scene_xml
from .image import Image as _Image, srgb8 as _srgb8
from .parameters import SceneParameters as _CandelaSceneParameters
from .transform import Transform

__all__ = [
    "set_variant", "variant", "variants", "variant_context", "is_rgb", "is_spectral", "is_polarized", "is_monochromatic",
    "load_file", "load_string", "load_dict", "render", "traverse", "SceneParameters", "Scene", "cornell_box",
    "ScalarTransform4f", "Transform4f", "ScalarAffineTransform4f", "AffineTransform4f",
    "ScalarPoint3f", "Point3f", "ScalarVector3f", "Vector3f", "ScalarNormal3f", "Normal3f", "ScalarColor3f", "Color3f",
    "ScalarVector2u", "Vector2u", "ScalarBoundingBox3f", "BoundingBox3f",
    "Sensor", "Film", "Sampler", "Shape", "Mesh", "Emitter", "BSDF", "Integrator",
    "Bitmap", "Struct", "FilterBoundaryCondition", "util", "luminance", "LogLevel", "set_log_level", "log_level", "Log",
]

# --------------------------------------------------------------------------------------------------
# Variants
# --------------------------------------------------------------------------------------------------

# Mitsuba's variant names: backend, optional autodiff, colour representation, optional
# polarisation and precision. Candela renders RGB, spectral and spectral polarized in single
# precision on the CPU: each name renders as candela's scalar variant of its colour representation.
_VARIANT = re.compile(r"^(scalar|llvm|cuda)(_ad)?_(rgb|mono|spectral)(_polarized)?(_double|_half)?$")
_LISTED_VARIANTS = ["scalar_rgb", "scalar_spectral", "llvm_rgb", "llvm_ad_rgb", "llvm_spectral", "llvm_ad_spectral", "cuda_rgb",
                    "cuda_ad_rgb", "cuda_spectral", "cuda_ad_spectral", "scalar_spectral_polarized", "llvm_spectral_polarized",
                    "llvm_ad_spectral_polarized", "cuda_spectral_polarized", "cuda_ad_spectral_polarized"]
_state = {"variant": None}
_noticed: set[str] = set()
_lock = threading.Lock()


def _variant_problem(name) -> Exception | None:
    """None if Candela renders `name`; otherwise the exception set_variant raises for it."""
    if not isinstance(name, str):
        return TypeError(f"a variant is a name (a string), got {name!r}")
    m = _VARIANT.match(name)
    if m is None:
        return ImportError(f"Requested an unsupported variant {name!r}. The variants candela.mitsuba renders: "
                           f"{', '.join(_LISTED_VARIANTS)} (and their _double forms)")
    colour, polarized = m.group(3), m.group(4)
    if colour == "mono":
        return NotImplementedError(f"variant {name!r}: monochrome rendering is not available in Candela "
                                   "(it renders RGB and spectral; use an *_rgb or *_spectral variant)")
    if polarized and colour != "spectral":
        return NotImplementedError(f"variant {name!r}: Candela renders polarisation in the spectral variant only "
                                   "(use an *_spectral_polarized variant)")
    return None


def _candela_variant(name: str) -> str:
    """The candela variant a Mitsuba variant name renders as: scalar_rgb, scalar_spectral or
    scalar_spectral_polarized."""
    m = _VARIANT.match(name)
    return "scalar_" + m.group(3) + (m.group(4) or "")


def _set_state(name: str | None) -> None:
    """Makes `name` (None: none yet) the variant, with Mitsuba's is_* flags that go with it."""
    global is_rgb, is_spectral, is_polarized
    _state["variant"] = name
    candela_variant = _candela_variant(name) if name is not None else "scalar_rgb"
    spectral = candela_variant != "scalar_rgb"
    is_rgb, is_spectral, is_polarized = not spectral, spectral, candela_variant == "scalar_spectral_polarized"


def set_variant(*names: str) -> None:
    """Sets the variant: the first of `names` that Candela renders (Mitsuba picks the first one
    available). RGB, spectral and spectral polarized variants all render on Candela's CPU renderer
    in single precision, as scalar_rgb, scalar_spectral and scalar_spectral_polarized; any but
    those three prints a one-line notice on stderr the first time it is set. RGB polarized and
    monochrome variants raise NotImplementedError."""
    if not names:
        raise TypeError("set_variant() needs at least one variant name")
    first_problem = None
    for name in names:
        problem = _variant_problem(name)
        if problem is None:
            renders_as = _candela_variant(name)
            with _lock:
                _set_state(name)
                notice = name != renders_as and name not in _noticed
                _noticed.add(name)
            if notice:
                m = _VARIANT.match(name)
                parts = []
                if m.group(1) in ("llvm", "cuda"):
                    parts.append(f"not {m.group(1).upper()}")
                if m.group(2):
                    parts.append("without automatic differentiation")
                if m.group(5):
                    parts.append("in single precision")
                print(f"candela.mitsuba: variant {name!r} renders as {renders_as} on Candela's CPU renderer "
                      f"({', '.join(parts)})", file=sys.stderr)
            return
        if first_problem is None:
            first_problem = problem
    raise first_problem


def variant() -> str | None:
    """The variant set by set_variant, or None before it."""
    return _state["variant"]


def variants() -> list[str]:
    """The variants Candela renders (all on its CPU renderer, as scalar_rgb or scalar_spectral)."""
    return list(_LISTED_VARIANTS)


@contextlib.contextmanager
def variant_context(*names: str):
    """Sets the variant for the duration of a ``with`` block, then restores the previous one."""
    previous = variant()
    set_variant(*names)
    try:
        yield
    finally:
        with _lock:
            _set_state(previous)


scoped_set_variant = variant_context

# Mitsuba's flags of the current variant (module attributes, as in Mitsuba; set_variant updates
# is_rgb, is_spectral and is_polarized). Candela renders no monochrome variant.
is_rgb = True
is_spectral = False
is_polarized = False
is_monochromatic = False


def _ensure_variant() -> str:
    """The candela variant to load in. Mitsuba refuses to load without a variant; scripts always
    set one, so a missing one is taken as scalar_rgb instead of failing."""
    if _state["variant"] is None:
        _set_state("scalar_rgb")
    return _candela_variant(_state["variant"])


# --------------------------------------------------------------------------------------------------
# Scenes
# --------------------------------------------------------------------------------------------------

Scene = _candela.Scene


# How each scene from this module's loaders was made, so that render(sensor=<a sensor object>)
# can load it again with that sensor in place of its own, and render(sensor=<index>) with another
# of its sensors.
_recipes: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


def _load_scene(load, params: dict):
    """`load(parameters, variant)` in the current variant. Keyword arguments are the scene's
    parameters, all of them (one named `variant` included), as in Mitsuba, whose loaders take the
    variant from set_variant."""
    return load(_candela._parameters(params), _ensure_variant())


def load_file(path, update_scene: bool = False, parallel: bool = True, optimize: bool = True, **params):
    """Loads a Mitsuba 3 XML scene; keyword arguments set its ``$name`` parameters. ``update_scene``,
    ``parallel`` and ``optimize`` are accepted and have no effect (Candela loads in parallel and
    never rewrites the file)."""
    scene = _load_scene(lambda p, v: _native.load_file(os.fspath(path), p, v), params)
    _recipes[scene] = ("file", os.path.abspath(os.fspath(path)), dict(params))
    return scene


def load_string(string: str, parallel: bool = True, optimize: bool = True, **params):
    """Loads a scene from XML text (files it names are found relative to the working directory)."""
    if not isinstance(string, str):
        raise TypeError(f"load_string expects XML text (a str), got {type(string).__name__}")
    virtual = os.path.join(os.getcwd(), "<string>.xml")
    scene = _load_scene(lambda p, v: _native.load_string(string, virtual, p, v), params)
    _recipes[scene] = ("string", string, dict(params), virtual)
    return scene


def load_dict(d: dict, parallel: bool = True, optimize: bool = True):
    """Loads a scene dictionary (``'type': 'scene'``) as a Scene; any other plugin's dictionary
    is checked and returned as a candela.Plugin, which render(integrator=...) and other
    dictionaries take."""
    variant_name = _ensure_variant()
    if not isinstance(d, dict):
        raise TypeError(f"load_dict expects a dictionary, got {type(d).__name__}")
    result = _candela.load_dict(d, variant=variant_name)
    if isinstance(result, _candela.Scene):
        try:
            _recipes[result] = ("dict", copy.deepcopy(d))
        except Exception:  # noqa: BLE001 - a value deepcopy cannot copy: no recipe, no sensor objects
            pass
    return result


def _is_sensor(value) -> bool:
    if isinstance(value, _Plugin):
        return value.kind == "sensor"
    return isinstance(value, dict) and isinstance(value.get("type"), str) and _native.plugin_tag(value["type"]) == "sensor"


def _without_sensors_xml(text: str) -> tuple[str, int]:
    """The scene XML without its top-level <sensor> elements, and where the first one was."""
    data = text.encode("utf-8")
    spans, depth, start = [], 0, None
    parser = _expat.ParserCreate()

    def begin(name, attributes):
        nonlocal depth, start
        depth += 1
        if depth == 2 and name == "sensor":
            start = parser.CurrentByteIndex

    def end(name):
        nonlocal depth, start
        if depth == 2 and name == "sensor" and start is not None:
            index = parser.CurrentByteIndex
            stop = data.index(b">", index) + 1
            spans.append((start, stop))
            start = None
        depth -= 1

    parser.StartElementHandler, parser.EndElementHandler = begin, end
    parser.Parse(data, True)
    if not spans:
        at = data.rindex(b"</scene>")
        return text, len(data[:at].decode("utf-8"))
    out, last = [], 0
    for a, b in spans:
        out.append(data[last:a])
        last = b
    out.append(data[last:])
    first = len(data[:spans[0][0]].decode("utf-8"))
    return b"".join(out).decode("utf-8"), first


def _sensor_xml(sensor: dict) -> str:
    xml_text, _ = _scene_xml({"type": "scene", "_candela_sensor": sensor})
    return "\n".join(xml_text.splitlines()[1:-1])


def _load_recipe(recipe, variant: str, sensor: dict | None = None, sensor_index: int = 0):
    """The scene loaded again: with `sensor` (a dictionary) in place of its own sensors, or
    rendering its sensor `sensor_index`."""
    kind = recipe[0]
    if kind == "dict":
        d = recipe[1]
        if sensor is not None:
            d = {k: v for k, v in d.items() if not _is_sensor(v)}
            d["_candela_sensor"] = sensor
        return _candela.load_dict(d, variant=variant, sensor=sensor_index)
    if kind == "file":
        with open(recipe[1], encoding="utf-8") as f:
            text = f.read()
        virtual, params = recipe[1], recipe[2]
    else:
        text, params, virtual = recipe[1], recipe[2], recipe[3]
    if sensor is not None:
        text, at = _without_sensors_xml(text)
        text = text[:at] + _sensor_xml(sensor) + text[at:]
    return _native.load_string(text, virtual, _candela._parameters(params), variant, sensor_index)


# The scene last loaded for render(scene, sensor=<another index>), per scene: (the index, that
# scene, what its sensor changes: _load_with_sensor). Rendering from that sensor again carries the
# edits over instead of loading twice; one entry per scene, so a scene keeps at most one more
# copy of itself in memory.
_other_sensor_scenes: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


def _load_with_sensor(scene, recipe, **sensor):
    """The scene loaded again from its recipe with another sensor (`sensor_index=` or `sensor=`
    as _load_recipe takes them), and the parameters that sensor changes: {name: (its value with
    the scene's own sensor, its value with this one)}, from one load with each."""
    moved = _load_recipe(recipe, scene.variant, **sensor)
    fresh = _load_recipe(recipe, scene.variant)
    changed = {}
    for name, _ in _native.parameter_list(moved):
        value = _native.get_parameter(moved, name)
        try:
            own = _native.get_parameter(fresh, name)
        except Exception:  # noqa: BLE001 - only in the scene with this sensor
            own = None
        if own is None or not np.array_equal(value, own):
            changed[name] = (own, value)
    return moved, changed


def _carry_edits(scene, moved, changed) -> None:
    """Gives `moved` the scene's parameter values as they are now (edited through traverse or
    not), but the camera's own (to_world, x_fov); where moved's sensor changed a value
    (`changed`), only an edit made to the scene carries over."""
    updates = {}
    wanted = dict(_native.parameter_list(moved))
    for name, _ in _native.parameter_list(scene):
        if name.endswith((".to_world", ".x_fov")) or name not in wanted:
            continue
        value = _native.get_parameter(scene, name)
        if name in changed:
            own, with_sensor = changed[name]
            if own is not None and np.array_equal(value, own):
                value = with_sensor  # not edited: moved keeps what its sensor gives it
        if not np.array_equal(value, _native.get_parameter(moved, name)):
            updates[name] = np.asarray(value, dtype=np.float32)
    if updates:
        _native.set_parameters(moved, updates)


def _render_with_sensor(scene, sensor, spp, seed, integrator):
    """Renders `scene` from `sensor` (a sensor from load_dict, or the index of another of the
    scene's sensors): the scene is loaded again with that sensor (for an index, once while the
    scene keeps rendering from it), and the parameters changed since it was loaded (through
    traverse) are carried over, the camera's own (to_world, x_fov) excepted."""
    recipe = _recipes.get(scene)
    if recipe is None:
        raise NotImplementedError("mi.render(..., sensor=...) with a sensor other than the scene's first, for a scene not "
                                  "loaded by candela.mitsuba's load_file, load_string or load_dict, is not available")
    # Loaded again in the scene's own variant, whatever the current one is.
    if isinstance(sensor, _Plugin):
        moved, changed = _load_with_sensor(scene, recipe, sensor=sensor.dictionary)
    else:
        cached = _other_sensor_scenes.get(scene)
        if cached is not None and cached[0] == sensor:
            moved, changed = cached[1], cached[2]
        else:
            _other_sensor_scenes.pop(scene, None)  # its memory before the next load
            moved, changed = _load_with_sensor(scene, recipe, sensor_index=sensor)
            _other_sensor_scenes[scene] = (sensor, moved, changed)
    _carry_edits(scene, moved, changed)
    return _candela.render(moved, spp=int(spp) or None, seed=seed, integrator=integrator)


def render(scene, params=None, sensor=0, integrator=None, seed: int = 0, seed_grad: int = 0, spp: int = 0,
           spp_grad: int = 0):
    """Renders the scene and returns the image (a candela.Image: H x W x 3 float32, a NumPy array).
    ``spp=0`` keeps the scene's (or the given sensor's) sample count. ``sensor``: the index of one
    of the scene's sensors, in file order (0, the first, by default), or a sensor from load_dict
    (the scene is rendered from it, with its film and sampler).
    ``integrator``: an integrator from load_dict (or its dictionary, or its name). ``params``,
    ``seed_grad`` and ``spp_grad`` concern gradients: they do not change the image and are
    accepted as Mitsuba accepts them. The pixels equal ``candela render SCENE --spp SPP --seed
    SEED``'s."""
    _ensure_variant()
    if not isinstance(scene, _candela.Scene):
        raise TypeError(f"render expects a scene (from load_file, load_string or load_dict), got {type(scene).__name__}")
    if params is not None and not isinstance(params, _CandelaSceneParameters):
        raise TypeError("params should be an instance of mi.SceneParameters (from mi.traverse), or None")
    if isinstance(spp, bool) or not isinstance(spp, (int, np.integer)):
        raise TypeError(f"spp must be a whole number (0: the scene's sample count), got {spp!r}")
    if spp < 0:
        raise ValueError(f"spp must be >= 0 (0: the scene's sample count), got {spp}")
    if isinstance(sensor, _Plugin):
        if sensor.kind != "sensor":
            raise TypeError(f"sensor must be a sensor (from load_dict) or an index, got a {sensor.kind}")
        return _render_with_sensor(scene, sensor, spp, seed, integrator)
    if isinstance(integrator, Integrator):
        if integrator._scene is not scene:
            raise ValueError("integrator is another scene's (scene.integrator()): give this scene's, or one from "
                             "load_dict")
        integrator = None
    if isinstance(sensor, Sensor):
        if sensor._scene is not scene:
            raise ValueError("sensor is one of another scene's sensors: give a sensor of this scene (scene.sensors()), "
                             "its index, or a sensor from load_dict")
        sensor = sensor._index
    if isinstance(sensor, bool) or not isinstance(sensor, (int, np.integer)):
        raise TypeError(f"sensor must be a sensor's index (an int) or a sensor from load_dict, got {sensor!r}")
    if not 0 <= sensor < scene.sensor_count:
        raise IndexError(f"sensor index {sensor} is out of range: the scene has {scene.sensor_count} sensor"
                         f"{'s' if scene.sensor_count != 1 else ''}")
    if sensor != scene.sensor_index:
        image = _render_with_sensor(scene, int(sensor), spp, seed, integrator)
    else:
        image = _candela.render(scene, spp=int(spp) or None, seed=seed, integrator=integrator)
    _developed.setdefault(scene, {})[int(sensor)] = image
    return image


class SceneParameters(_CandelaSceneParameters):
    """Mitsuba's SceneParameters on a Candela scene: ``params[name]`` reads a value (a Color3f, a
    float, a ScalarTransform4f, or a flat float32 array for vertex positions), ``params[name] = v``
    assigns one, ``update()`` applies the assignments. As in Mitsuba, a value read and then changed
    in place (``params['x.vertex_positions'][1] += 0.1``) is applied by the next update(), and
    iterating gives (name, value) pairs, as items() does."""

    def __init__(self, scene):
        super().__init__(scene)
        self._handed: dict[str, tuple[object, np.ndarray]] = {}

    def __iter__(self):
        return iter(self.items())

    def values(self):
        return [value for _, value in self.items()]

    def __getitem__(self, name: str):
        value = super().__getitem__(name)
        kind = self._types[name]
        if kind == "color":
            value = Color3f(value)
        if kind != "float":
            self._handed[name] = (value, np.array(np.asarray(value), copy=True))
        return value

    def __setitem__(self, name: str, value):
        super().__setitem__(name, value)
        self._handed.pop(name, None)

    def set_dirty(self, name: str):
        """Marks a parameter as changed, so that update() applies its current value."""
        self._check(name)
        if name in self._handed and name not in self._pending:
            super().__setitem__(name, self._handed[name][0])

    def update(self, values: dict = None) -> list[str]:
        """Assigns `values` (names this view does not have are ignored, as in Mitsuba), then
        applies the assignments (and the in-place changes of values read) since the last update;
        returns the names it changed."""
        for name, (value, snapshot) in list(self._handed.items()):
            if name in self and name not in self._pending and not np.array_equal(np.asarray(value), snapshot):
                super().__setitem__(name, value)
        self._handed = {}
        return super().update(values)

    def keep(self, keys) -> None:
        """Keeps the parameters whose names a regular expression of `keys` (one, or a list)
        matches at their start, as Mitsuba's keep: ``keep('red')`` keeps 'red.reflectance.value'."""
        if keys is None:
            raise NotImplementedError("SceneParameters.keep(None): keeping the differentiable parameters needs "
                                      "parameter flags, and Candela has no automatic differentiation")
        patterns = [re.compile(k) for k in ([keys] if isinstance(keys, str) else keys)]
        self._types = {k: t for k, t in self._types.items() if any(p.match(k) for p in patterns)}

    def flags(self, name: str):
        raise NotImplementedError("SceneParameters.flags: parameter flags describe differentiability, and Candela "
                                  "has no automatic differentiation")

    def torch(self):
        raise NotImplementedError("SceneParameters.torch: PyTorch interoperation (automatic differentiation) is not "
                                  "available in Candela")


def traverse(obj) -> SceneParameters:
    """The scene's editable parameters by Mitsuba's names ('red.reflectance.value',
    'PerspectiveCamera.x_fov', 'PerspectiveCamera.to_world', 'mesh.vertex_positions', ...)."""
    if isinstance(obj, _candela.Scene):
        return SceneParameters(obj)
    if isinstance(obj, _Plugin):
        raise NotImplementedError("mi.traverse of an object outside a scene (a BSDF, emitter, ... from load_dict) is "
                                  "not available in Candela: traverse the scene that holds it")
    raise TypeError(f"traverse expects a scene, got {type(obj).__name__}")


# --------------------------------------------------------------------------------------------------
# Transforms and 3-vectors
# --------------------------------------------------------------------------------------------------

ScalarTransform4f = Transform
Transform4f = Transform
ScalarAffineTransform4f = Transform
AffineTransform4f = Transform


class _Array3(np.ndarray):
    """Three numbers (float64) as Dr.Jit's 3-vectors: built from three numbers, one number (all
    three alike) or a sequence of three; x, y, z; arithmetic as NumPy's."""

    _candela_kind = "point"

    def __new__(cls, *args):
        if len(args) == 1:
            a = np.asarray(args[0], dtype=np.float64).reshape(-1) if not np.isscalar(args[0]) else \
                np.full(3, float(args[0]))
        elif len(args) == 3:
            if not all(np.ndim(v) == 0 for v in args):
                raise NotImplementedError(f"{cls.__name__} of arrays (Dr.Jit's vectorized arrays) is not available in "
                                          "candela.mitsuba: use NumPy arrays of shape N x 3")
            a = np.array([float(v) for v in args])
        elif len(args) == 0:
            a = np.zeros(3)
        else:
            raise TypeError(f"{cls.__name__} takes three numbers, one number or a sequence of three, got {len(args)} arguments")
        if a.size == 1:
            a = np.repeat(a, 3)
        if a.size != 3:
            raise NotImplementedError(f"{cls.__name__} of {a.size} numbers (Dr.Jit's vectorized arrays) is not available "
                                      "in candela.mitsuba: it holds three numbers")
        return np.array(a, dtype=np.float64).view(cls)

    x = property(lambda self: float(self[0]), lambda self, v: self.__setitem__(0, v))
    y = property(lambda self: float(self[1]), lambda self, v: self.__setitem__(1, v))
    z = property(lambda self: float(self[2]), lambda self, v: self.__setitem__(2, v))

    def __repr__(self):
        return "[" + ", ".join(f"{float(v):g}" for v in np.asarray(self).reshape(-1)) + "]"

    __str__ = __repr__

    def __reduce__(self):
        return (type(self), (np.asarray(self).tolist(),))


class ScalarPoint3f(_Array3):
    """A point: three numbers (written to a scene as <point>)."""


class ScalarVector3f(_Array3):
    """A direction: three numbers (written to a scene as <vector>; transforms leave out the
    translation)."""

    _candela_kind = "vector"
    _candela_vector = True


class ScalarNormal3f(_Array3):
    """A normal: three numbers (transforms apply the inverse transpose)."""

    _candela_kind = "normal"
    _candela_vector = True


class ScalarColor3f(_Array3):
    """An RGB colour: three numbers (written to a scene as <rgb>)."""

    _candela_kind = "color"
    _candela_colour = True

    r = property(lambda self: float(self[0]), lambda self, v: self.__setitem__(0, v))
    g = property(lambda self: float(self[1]), lambda self, v: self.__setitem__(1, v))
    b = property(lambda self: float(self[2]), lambda self, v: self.__setitem__(2, v))


Point3f = ScalarPoint3f
Vector3f = ScalarVector3f
Normal3f = ScalarNormal3f
Color3f = ScalarColor3f


def luminance(color) -> float:
    """The luminance (Y) of a linear sRGB colour, with Mitsuba's weights."""
    c = np.asarray(color, dtype=np.float64)
    return c[..., 0] * 0.212671 + c[..., 1] * 0.715160 + c[..., 2] * 0.072169


# --------------------------------------------------------------------------------------------------
# The Cornell box (mi.cornell_box)
# --------------------------------------------------------------------------------------------------

def cornell_box() -> dict:
    """The dictionary of Mitsuba's Cornell box (mi.cornell_box()): 256 x 256, 64 samples per
    pixel, path tracing to depth 8, a Gaussian pixel filter; its walls, boxes, light and camera as
    Mitsuba defines them."""
    T = Transform

    def diffuse(rgb):
        return {"type": "diffuse", "reflectance": {"type": "rgb", "value": list(rgb)}}

    white_ref = {"type": "ref", "id": "white"}
    return {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": 8},
        "sensor": {
            "type": "perspective",
            "fov_axis": "smaller",
            "near_clip": 0.001,
            "far_clip": 100.0,
            "focus_distance": 1000,
            "fov": 39.3077,
            "to_world": T.look_at(origin=[0, 0, 3.90], target=[0, 0, 0], up=[0, 1, 0]),
            "sampler": {"type": "independent", "sample_count": 64},
            "film": {"type": "hdrfilm", "width": 256, "height": 256, "rfilter": {"type": "gaussian"},
                     "pixel_format": "rgb", "component_format": "float32"},
        },
        "white": diffuse([0.885809, 0.698859, 0.666422]),
        "green": diffuse([0.105421, 0.37798, 0.076425]),
        "red": diffuse([0.570068, 0.0430135, 0.0443706]),
        "light": {
            "type": "rectangle",
            "to_world": T.translate([0.0, 0.99, 0.01]) @ T.rotate([1, 0, 0], 90) @ T.scale([0.23, 0.19, 0.19]),
            "bsdf": dict(white_ref),
            "emitter": {"type": "area", "radiance": {"type": "rgb", "value": [18.387, 13.9873, 6.75357]}},
        },
        "floor": {"type": "rectangle", "to_world": T.translate([0, -1, 0]) @ T.rotate([1, 0, 0], -90),
                  "bsdf": dict(white_ref)},
        "ceiling": {"type": "rectangle", "to_world": T.translate([0, 1, 0]) @ T.rotate([1, 0, 0], 90),
                    "bsdf": dict(white_ref)},
        "back": {"type": "rectangle", "to_world": T.translate([0, 0, -1]), "bsdf": dict(white_ref)},
        "green-wall": {"type": "rectangle", "to_world": T.translate([1, 0, 0]) @ T.rotate([0, 1, 0], -90),
                       "bsdf": {"type": "ref", "id": "green"}},
        "red-wall": {"type": "rectangle", "to_world": T.translate([-1, 0, 0]) @ T.rotate([0, 1, 0], 90),
                     "bsdf": {"type": "ref", "id": "red"}},
        "small-box": {"type": "cube",
                      "to_world": T.translate([0.335, -0.7, 0.38]) @ T.rotate([0, 1, 0], -17) @ T.scale(0.3),
                      "bsdf": dict(white_ref)},
        "large-box": {"type": "cube",
                      "to_world": T.translate([-0.33, -0.4, -0.28]) @ T.rotate([0, 1, 0], 18.25) @ T.scale([0.3, 0.61, 0.3]),
                      "bsdf": dict(white_ref)},
    }


# --------------------------------------------------------------------------------------------------
# What a scene holds, read-only: its sensors (films, samplers), shapes, emitters and bounds
# --------------------------------------------------------------------------------------------------

class ScalarVector2u(np.ndarray):
    """Two whole numbers (uint32), as a film's size(): x, y; indexing and arithmetic as NumPy's."""

    def __new__(cls, x=0, y=None):
        values = [x, x if y is None else y] if np.ndim(x) == 0 else list(np.asarray(x).reshape(-1))
        if len(values) != 2 or any(int(v) != v or v < 0 for v in values):
            raise TypeError(f"{cls.__name__} holds two whole numbers >= 0, got {values!r}")
        return np.array([int(v) for v in values], dtype=np.uint32).view(cls)

    x = property(lambda self: int(self[0]))
    y = property(lambda self: int(self[1]))

    def __repr__(self):
        return f"[{int(self[0])}, {int(self[1])}]"

    __str__ = __repr__


Vector2u = ScalarVector2u


class ScalarBoundingBox3f:
    """An axis-aligned box, as Mitsuba's: min and max (ScalarPoint3f); without arguments an empty
    box (min +inf, max -inf), which expand() grows. scene.bbox() gives the scene's."""

    def __init__(self, min=None, max=None):  # noqa: A002 - Mitsuba's argument names
        if min is None:
            self.reset()
        else:
            self.min = ScalarPoint3f(min)
            self.max = ScalarPoint3f(min if max is None else max)

    def valid(self) -> bool:
        return bool(np.all(self.min <= self.max))

    def center(self) -> ScalarPoint3f:
        return ScalarPoint3f((np.asarray(self.min) + np.asarray(self.max)) * 0.5)

    def extents(self) -> ScalarVector3f:
        return ScalarVector3f(np.asarray(self.max) - np.asarray(self.min))

    def volume(self) -> float:
        return float(np.prod(self.extents())) if self.valid() else 0.0

    def surface_area(self) -> float:
        if not self.valid():
            return 0.0
        e = np.asarray(self.extents())
        return float(2.0 * (e[0] * e[1] + e[1] * e[2] + e[2] * e[0]))

    def major_axis(self) -> int:
        return int(np.argmax(np.asarray(self.extents())))

    def minor_axis(self) -> int:
        return int(np.argmin(np.asarray(self.extents())))

    def contains(self, p) -> bool:
        if isinstance(p, ScalarBoundingBox3f):
            return bool(np.all(self.min <= p.min) and np.all(p.max <= self.max))
        p = np.asarray(p, dtype=np.float64)
        return bool(np.all(self.min <= p) and np.all(p <= self.max))

    def expand(self, p) -> None:
        """Grows the box to hold the point or box `p`."""
        low, high = (p.min, p.max) if isinstance(p, ScalarBoundingBox3f) else (p, p)
        self.min = ScalarPoint3f(np.minimum(np.asarray(self.min), np.asarray(low, dtype=np.float64)))
        self.max = ScalarPoint3f(np.maximum(np.asarray(self.max), np.asarray(high, dtype=np.float64)))

    def reset(self) -> None:
        self.min, self.max = ScalarPoint3f(np.inf), ScalarPoint3f(-np.inf)

    def __eq__(self, other):
        return isinstance(other, ScalarBoundingBox3f) and np.array_equal(self.min, other.min) and \
            np.array_equal(self.max, other.max)

    def __repr__(self):
        return f"BoundingBox3f[\n  min = {self.min!r},\n  max = {self.max!r}\n]"


BoundingBox3f = ScalarBoundingBox3f


def _scene_bbox(self) -> ScalarBoundingBox3f:
    """The scene's bounds: the box around its shapes (empty, not valid(), for a scene without)."""
    low, high = _native.scene_bbox(self)
    return ScalarBoundingBox3f(low, high)


class _SceneObjectView:
    """What one of a scene's objects (a sensor, its film or sampler, a shape, an emitter, a BSDF)
    shows of itself in Python: a read-only view of the scene as it is now. Mitsuba's other
    methods on it say they are not available."""

    _kind = "object"
    _read = staticmethod(_native.sensor_info)  # (scene, index) -> the object's facts

    def __init__(self, scene, index: int):
        self._scene, self._index = scene, index

    def _info(self) -> dict:
        return self._read(self._scene, self._index)

    def __eq__(self, other):
        return type(other) is type(self) and other._scene is self._scene and other._index == self._index

    def __hash__(self):
        return hash((type(self), id(self._scene), self._index))

    def __getattr__(self, name):
        if name.startswith("_"):
            raise AttributeError(name)
        if name in _PLUGIN_METHODS or name in _VIEW_METHODS:
            raise NotImplementedError(f"{self._kind}.{name}: {_OBJECTS} is not available in candela.mitsuba (a scene's "
                                      f"{self._kind} shows what it is; edit it with mi.traverse, render it with "
                                      "mi.render)")
        raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")


class _NamedView(_SceneObjectView):
    """A view of an object with its own plugin type and id (a sensor, shape or emitter)."""

    def id(self) -> str:
        return self._info()["id"]

    def __repr__(self):
        info = self._info()
        return f"{type(self).__name__}[type={info['type']}, id={info['id']!r}, index={self._index}]"


class Sampler(_SceneObjectView):
    """A scene sensor's sampler: its type and sample_count()."""

    _kind = "sampler"

    def sample_count(self) -> int:
        return int(self._info()["spp"])

    def __repr__(self):
        info = self._info()
        return f"Sampler[type={info['sampler_type']}, sample_count={info['spp']}]"


class Film(_SceneObjectView):
    """A scene sensor's film: size() (the full film), crop_size(), crop_offset(), and after
    mi.render from this sensor, the image: develop() as render returned it, bitmap() as a Bitmap."""

    _kind = "film"

    def size(self) -> ScalarVector2u:
        return ScalarVector2u(self._info()["film_size"])

    def crop_size(self) -> ScalarVector2u:
        return ScalarVector2u(self._info()["crop_size"])

    def crop_offset(self) -> ScalarVector2u:
        return ScalarVector2u(self._info()["crop_offset"])

    def _image(self):
        image = _developed.get(self._scene, {}).get(self._index)
        if image is None:
            raise RuntimeError(f"{self._kind}.develop(): sensor {self._index}'s film holds no image yet; render it "
                               "first (mi.render(scene, sensor=...))")
        return image

    def develop(self, raw: bool = False):
        """The image of the last mi.render from this film's sensor (a candela.Image, H x W x C)."""
        return self._image()

    def bitmap(self, raw: bool = False):
        """The same image as a Bitmap."""
        return Bitmap(self._image())

    def write(self, path) -> None:
        """Writes that image to `path` (its format from the extension, as Bitmap.write)."""
        self.bitmap().write(path)

    def __repr__(self):
        info = self._info()
        return (f"Film[type={info['film_type']}, size={list(info['film_size'])}, crop_size={list(info['crop_size'])}, "
                f"crop_offset={list(info['crop_offset'])}]")


class Sensor(_NamedView):
    """One of a scene's sensors (scene.sensors()[i]): its film(), sampler(), pose
    (world_transform()), shutter and id(); mi.render(scene, sensor=it) renders from it."""

    _kind = "sensor"

    def film(self) -> Film:
        return Film(self._scene, self._index)

    def sampler(self) -> Sampler:
        return Sampler(self._scene, self._index)

    def world_transform(self) -> Transform:
        return Transform(np.asarray(self._info()["to_world"], dtype=np.float64))

    def shutter_open(self) -> float:
        return float(self._info()["shutter_open"])

    def shutter_open_time(self) -> float:
        return float(self._info()["shutter_open_time"])


class BSDF(_SceneObjectView):
    """The BSDF of one of a scene's shapes (shape.bsdf()): its id()."""

    _kind = "bsdf"
    _read = staticmethod(_native.shape_info)

    def id(self) -> str:
        return self._info()["bsdf_id"]

    def __repr__(self):
        info = self._info()
        return f"BSDF[type={info['bsdf_type']}, id={info['bsdf_id']!r}]"


class Emitter(_NamedView):
    """One of a scene's emitters (scene.emitters()[i]): id(), is_environment(), and for an area
    light the shape it lies on (shape())."""

    _kind = "emitter"
    _read = staticmethod(_native.emitter_info)

    def is_environment(self) -> bool:
        return bool(self._info()["is_environment"])

    def shape(self):
        index = self._info()["shape_index"]
        return _shape_view(self._scene, index) if index >= 0 else None


class Shape(_NamedView):
    """One of a scene's shapes (scene.shapes()[i]): id(), bbox(), surface_area(), its bsdf(),
    emitter() and sensor() (None when it has none), is_emitter(), is_sensor(), is_mesh()."""

    _kind = "shape"
    _read = staticmethod(_native.shape_info)

    def bbox(self) -> "ScalarBoundingBox3f":
        low, high = self._info()["bbox"]
        return ScalarBoundingBox3f(low, high)

    def surface_area(self) -> float:
        return float(self._info()["surface_area"])

    def is_mesh(self) -> bool:
        return bool(self._info()["is_mesh"])

    def is_emitter(self) -> bool:
        return self._info()["emitter_index"] >= 0

    def is_sensor(self) -> bool:
        return self._info()["sensor_index"] >= 0

    def emitter(self):
        index = self._info()["emitter_index"]
        return Emitter(self._scene, index) if index >= 0 else None

    def sensor(self):
        index = self._info()["sensor_index"]
        return Sensor(self._scene, index) if index >= 0 else None

    def bsdf(self):
        return BSDF(self._scene, self._index) if self._info()["bsdf_type"] else None


class Mesh(Shape):
    """A scene's shape that is a triangle mesh: also vertex_count() and face_count()."""

    _kind = "mesh"

    def vertex_count(self) -> int:
        return int(self._info()["vertex_count"])

    def face_count(self) -> int:
        return int(self._info()["face_count"])


def _shape_view(scene, index: int) -> Shape:
    return (Mesh if _native.shape_info(scene, index)["is_mesh"] else Shape)(scene, index)


def _scene_shapes(self) -> list:
    """The scene's shapes (meshes as mi.Mesh)."""
    return [_shape_view(self, i) for i in range(self.shape_count)]


def _scene_emitters(self) -> list:
    """The scene's emitters: the area lights of its shapes, then the others in file order."""
    return [Emitter(self, i) for i in range(self.emitter_count)]


class Integrator(_SceneObjectView):
    """A scene's integrator (scene.integrator()): render(scene, sensor) renders the scene with it,
    as mi.render does, and leaves the image in the sensor's film (film().bitmap())."""

    _kind = "integrator"

    def __init__(self, scene):
        super().__init__(scene, 0)

    def render(self, scene, sensor=0, seed: int = 0, spp: int = 0, develop: bool = True, evaluate: bool = True):
        """The image of `scene` from `sensor` (an index or one of scene.sensors()), as
        mi.render(scene, sensor=sensor, seed=seed, spp=spp). `develop` and `evaluate` are accepted:
        the image is always developed, and also kept in the sensor's film."""
        if scene is not self._scene:
            raise ValueError("Integrator.render: this is another scene's integrator (scene.integrator() of the scene "
                             "you render)")
        return render(scene, sensor=sensor, seed=seed, spp=spp)

    def __repr__(self):
        return f"Integrator[type={str(self._scene.integrator)}]"


class _IntegratorName(str):
    """candela.Scene.integrator under candela.mitsuba: still the integrator's name (a str), and,
    called as Mitsuba's scene.integrator(), the scene's Integrator."""

    def __new__(cls, name: str, scene):
        value = super().__new__(cls, name)
        value._scene = scene
        return value

    def __call__(self) -> Integrator:
        return Integrator(self._scene)


# The image each of a scene's sensors last rendered through mi.render (its film's develop()).
_developed: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()
# Mitsuba's methods of sensors, films and samplers that are not in _PLUGIN_METHODS.
_VIEW_METHODS = ("prepare", "clear", "put_block", "create_block", "schedule_storage", "rfilter", "set_size",
                 "set_crop_window", "sample_border", "base_channels_count", "prepare_sample", "seed", "fork",
                 "advance", "next_1d", "next_2d", "set_sample_count", "wavefront_size", "set_shape",
                 "needs_aperture_sample", "shape", "x_fov", "near_clip", "far_clip", "set_film")


def _scene_sensors(self) -> list:
    """The scene's sensors in file order (mi.render(scene, sensor=i) renders the i-th)."""
    return [Sensor(self, i) for i in range(self.sensor_count)]


# --------------------------------------------------------------------------------------------------
# Bitmap and Struct
# --------------------------------------------------------------------------------------------------

class Struct:
    """Mitsuba's Struct, for its component types (mi.Struct.Type.UInt8, .Float32, ...)."""

    class Type(enum.Enum):
        Int8 = "int8"
        UInt8 = "uint8"
        Int16 = "int16"
        UInt16 = "uint16"
        Int32 = "int32"
        UInt32 = "uint32"
        Int64 = "int64"
        UInt64 = "uint64"
        Float16 = "float16"
        Float32 = "float32"
        Float64 = "float64"
        Invalid = "invalid"

        def __repr__(self):
            return f"Struct.Type.{self.name}"


_DTYPES = {Struct.Type.Int8: np.int8, Struct.Type.UInt8: np.uint8, Struct.Type.Int16: np.int16,
           Struct.Type.UInt16: np.uint16, Struct.Type.Int32: np.int32, Struct.Type.UInt32: np.uint32,
           Struct.Type.Int64: np.int64, Struct.Type.UInt64: np.uint64, Struct.Type.Float16: np.float16,
           Struct.Type.Float32: np.float32, Struct.Type.Float64: np.float64}


def _component_type(dtype) -> Struct.Type:
    dtype = np.dtype(dtype)
    for t, d in _DTYPES.items():
        if np.dtype(d) == dtype:
            return t
    raise TypeError(f"Bitmap: unsupported component type {dtype} (integers, float16, float32 or float64)")


class _PixelFormat(enum.Enum):
    Y = "y"
    YA = "ya"
    RGB = "rgb"
    RGBA = "rgba"
    RGBW = "rgbw"
    RGBAW = "rgbaw"
    XYZ = "xyz"
    XYZA = "xyza"
    MultiChannel = "multichannel"

    def __repr__(self):
        return f"Bitmap.PixelFormat.{self.name}"


class _FileFormat(enum.Enum):
    PNG = "png"
    OpenEXR = "exr"
    RGBE = "rgbe"
    PFM = "pfm"
    PPM = "ppm"
    JPEG = "jpeg"
    TGA = "tga"
    BMP = "bmp"
    Unknown = "unknown"
    Auto = "auto"


class _AlphaTransform(enum.Enum):
    Empty = "empty"
    Premultiply = "premultiply"
    Unpremultiply = "unpremultiply"


_CHANNELS = {_PixelFormat.Y: ["Y"], _PixelFormat.YA: ["Y", "A"], _PixelFormat.RGB: ["R", "G", "B"],
             _PixelFormat.RGBA: ["R", "G", "B", "A"], _PixelFormat.XYZ: ["X", "Y", "Z"],
             _PixelFormat.XYZA: ["X", "Y", "Z", "A"], _PixelFormat.RGBW: ["R", "G", "B", "W"],
             _PixelFormat.RGBAW: ["R", "G", "B", "A", "W"]}
_BY_COUNT = {1: _PixelFormat.Y, 2: _PixelFormat.YA, 3: _PixelFormat.RGB, 4: _PixelFormat.RGBA}
_LUMINANCE = np.array([0.212671, 0.715160, 0.072169])


def _to_linear(x: np.ndarray) -> np.ndarray:
    return np.where(x <= 0.04045, x / 12.92, np.power((np.maximum(x, 0.04045) + 0.055) / 1.055, 2.4))


def _to_srgb(x: np.ndarray) -> np.ndarray:
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(np.maximum(x, 0.0031308), 1.0 / 2.4) - 0.055)


class Bitmap:
    """An image as Mitsuba's Bitmap: ``Bitmap(array)`` (H x W x C, or H x W; the pixel format from
    the channel count, the component format from the dtype), ``Bitmap(path)`` (reads OpenEXR, PNG,
    JPEG, ...), ``.convert(pixel_format, component_format, srgb_gamma)``, ``.write(path)`` (.exr
    keeps the components, float; .png and .jpg are 8-bit, sRGB-encoded from float data) and
    ``np.array(bitmap)``."""

    PixelFormat = _PixelFormat
    FileFormat = _FileFormat
    AlphaTransform = _AlphaTransform

    def __init__(self, data, pixel_format=None, channel_names=None, *args):
        if isinstance(data, _PixelFormat):
            # Bitmap(pixel_format, component_format, size, channel_count=0, channel_names=[])
            self._init_empty(data, pixel_format, channel_names, *args)
            return
        metadata = {}
        srgb = None
        names = None
        if isinstance(data, Bitmap):
            array, names, srgb, metadata = data._data.copy(), list(data._names), data._srgb, dict(data._metadata)
            pixel_format = pixel_format or data._format
        elif isinstance(data, (str, os.PathLike)):
            array, names, srgb, metadata = self._read(os.fspath(data))
        else:
            if type(data).__module__.startswith("torch"):
                data = data.detach().cpu().numpy()
            if isinstance(data, _Image):
                names = list(data.channels)
                metadata = dict(data.metadata)
            array = np.array(data, copy=True)
            if array.dtype == np.bool_ or array.dtype.kind not in "uif":
                raise TypeError(f"Bitmap: expected an array of numbers, got dtype {array.dtype}")
        if array.ndim == 2:
            array = array[:, :, None]
        if array.ndim != 3:
            raise ValueError(f"Bitmap: expected an H x W x C (or H x W) array, got shape {array.shape}")
        self._data = np.ascontiguousarray(array)
        self._component = _component_type(self._data.dtype)
        count = self._data.shape[2]
        if channel_names:
            names = list(channel_names)
        if pixel_format is None:
            if names and len(names) == count:
                known = {tuple(v): k for k, v in _CHANNELS.items()}
                pixel_format = known.get(tuple(names), _PixelFormat.MultiChannel)
            else:
                pixel_format = _BY_COUNT.get(count, _PixelFormat.MultiChannel)
        if not isinstance(pixel_format, _PixelFormat):
            raise TypeError(f"Bitmap: pixel_format must be a Bitmap.PixelFormat, got {pixel_format!r}")
        expected = _CHANNELS.get(pixel_format)
        if expected is not None and len(expected) != count:
            raise ValueError(f"Bitmap: pixel format {pixel_format.name} has {len(expected)} channels, the data {count}")
        self._format = pixel_format
        if expected is not None:
            self._names = list(expected)
        elif names and len(names) == count:
            self._names = list(names)
        else:
            self._names = [f"C{i}" for i in range(count)]
        # As Mitsuba: 8-bit data is taken as sRGB-encoded, everything else as linear.
        self._srgb = bool(srgb) if srgb is not None else self._component == Struct.Type.UInt8
        self._metadata = metadata

    def _init_empty(self, pixel_format, component_format, size, channel_count=0, channel_names=None):
        if not isinstance(component_format, Struct.Type) or component_format not in _DTYPES:
            raise TypeError(f"Bitmap: component_format must be a Struct.Type, got {component_format!r}")
        width, height = (int(v) for v in size)
        names = _CHANNELS.get(pixel_format)
        count = len(names) if names else int(channel_count)
        if count < 1:
            raise ValueError("Bitmap: a MultiChannel bitmap needs channel_count")
        self._data = np.zeros((height, width, count), dtype=_DTYPES[component_format])
        self._component = component_format
        self._format = pixel_format
        self._names = list(names or channel_names or [f"C{i}" for i in range(count)])
        self._srgb = component_format == Struct.Type.UInt8
        self._metadata = {}

    @staticmethod
    def _read(path: str):
        image = _candela.read_image(path, raw=True)
        metadata = dict(image.metadata)
        array = np.asarray(image)
        bits = 0
        with open(path, "rb") as f:
            head = f.read(32)
        if head.startswith(b"\x89PNG"):
            bits = head[24]
        elif head.startswith(b"\xff\xd8"):
            bits = 8
        if bits in (8, 16):
            # 8- and 16-bit files come back as in the file: integers, sRGB-encoded where the file says so.
            scale = 255 if bits == 8 else 65535
            array = np.round(array.astype(np.float64) * scale).astype(np.uint8 if bits == 8 else np.uint16)
            srgb = metadata.get("oiio:ColorSpace", "sRGB").lower() == "srgb"
        else:
            srgb = False
        return array, list(image.channels), srgb, metadata

    # --- properties as Mitsuba's methods ------------------------------------------------------
    def width(self) -> int:
        return self._data.shape[1]

    def height(self) -> int:
        return self._data.shape[0]

    def size(self) -> tuple[int, int]:
        return (self.width(), self.height())

    def pixel_count(self) -> int:
        return self.width() * self.height()

    def channel_count(self) -> int:
        return self._data.shape[2]

    def pixel_format(self):
        return self._format

    def component_format(self):
        return self._component

    def srgb_gamma(self) -> bool:
        return self._srgb

    def set_srgb_gamma(self, value: bool):
        self._srgb = bool(value)

    def has_alpha(self) -> bool:
        return self._format in (_PixelFormat.YA, _PixelFormat.RGBA, _PixelFormat.XYZA, _PixelFormat.RGBAW)

    def metadata(self) -> dict:
        return self._metadata

    def channel_names(self) -> list[str]:
        return list(self._names)

    def bytes_per_pixel(self) -> int:
        return self._data.dtype.itemsize * self.channel_count()

    def buffer_size(self) -> int:
        return self._data.nbytes

    def __array__(self, dtype=None, copy=None):
        return self._data if dtype is None else self._data.astype(dtype)

    @property
    def shape(self):
        return self._data.shape

    def __eq__(self, other):
        return (isinstance(other, Bitmap) and self._format == other._format and self._component == other._component
                and self._srgb == other._srgb and np.array_equal(self._data, other._data))

    __hash__ = None

    def __repr__(self):
        return (f"Bitmap[\n  pixel_format = {self._format.value},\n  component_format = {self._component.value},\n"
                f"  size = [{self.width()}, {self.height()}],\n  srgb_gamma = {int(self._srgb)},\n"
                f"  channels = {self._names}\n]")

    def _repr_png_(self):
        # None (Jupyter then shows the text) for what has no RGB picture, a MultiChannel bitmap
        # of bands, rather than a traceback under the cell.
        try:
            rgb = self.convert(_PixelFormat.RGB, Struct.Type.UInt8, True)
        except NotImplementedError:
            return None
        return _native.encode_png(np.ascontiguousarray(rgb._data))

    # --- conversion ----------------------------------------------------------------------------
    def _linear(self) -> np.ndarray:
        """The pixels as float64, linear (integers scaled to [0, 1], sRGB decoded except alpha)."""
        x = self._data.astype(np.float64)
        if self._component in _DTYPES and np.issubdtype(self._data.dtype, np.integer):
            x /= float(np.iinfo(self._data.dtype).max)
        if self._srgb:
            colour = [i for i, n in enumerate(self._names) if n != "A"]
            x[:, :, colour] = _to_linear(x[:, :, colour])
        return x

    def convert(self, pixel_format=None, component_format=None, srgb_gamma=None, alpha_transform=None):
        """A new Bitmap in another pixel format (Y, YA, RGB, RGBA), component format (integers
        scaled to their range and clamped, or floats) and encoding (srgb_gamma: sRGB-encoded or
        linear). ``convert(PixelFormat.RGB, Struct.Type.UInt8, True)`` gives the 8-bit sRGB
        picture that PNG files hold, equal to ``candela render --png``'s."""
        if alpha_transform not in (None, _AlphaTransform.Empty):
            raise NotImplementedError(f"Bitmap.convert(alpha_transform={alpha_transform!r}): premultiplying alpha is "
                                      "not available in candela.mitsuba")
        if isinstance(pixel_format, Struct.Type) and component_format is None:
            # convert(component_format) as a single argument, as Mitsuba allows.
            pixel_format, component_format = None, pixel_format
        target_format = pixel_format if pixel_format is not None else self._format
        target_component = component_format if component_format is not None else self._component
        target_srgb = bool(srgb_gamma) if srgb_gamma is not None else self._srgb
        if not isinstance(target_format, _PixelFormat):
            raise TypeError(f"convert: pixel_format must be a Bitmap.PixelFormat, got {pixel_format!r}")
        if not isinstance(target_component, Struct.Type) or target_component not in _DTYPES:
            raise TypeError(f"convert: component_format must be a Struct.Type, got {component_format!r}")

        x = self._linear()
        x, names = self._reformat(x, target_format)
        colour = [i for i, n in enumerate(names) if n != "A"]
        alpha = [i for i, n in enumerate(names) if n == "A"]
        dtype = _DTYPES[target_component]
        if np.issubdtype(np.dtype(dtype), np.integer):
            top = float(np.iinfo(dtype).max)
            out = np.empty(x.shape, dtype=dtype)
            if target_srgb and top == 255:
                # The same encoding as candela.write_image's PNG and `candela render --png`.
                out[:, :, colour] = _srgb8(x[:, :, colour])
            else:
                c = np.clip(np.nan_to_num(x[:, :, colour], nan=0.0, posinf=1.0, neginf=0.0), 0.0, 1.0)
                if target_srgb:
                    c = _to_srgb(c)
                out[:, :, colour] = np.round(c * top).astype(dtype)
            if alpha:
                a = np.clip(np.nan_to_num(x[:, :, alpha], nan=0.0), 0.0, 1.0)
                out[:, :, alpha] = np.round(a * top).astype(dtype)
        else:
            out = x.copy()
            if target_srgb:
                out[:, :, colour] = _to_srgb(out[:, :, colour])
            out = out.astype(dtype)
        result = Bitmap.__new__(Bitmap)
        result._data = np.ascontiguousarray(out)
        result._component = target_component
        result._format = target_format
        result._names = names
        result._srgb = target_srgb
        result._metadata = dict(self._metadata)
        return result

    def _reformat(self, x: np.ndarray, target):
        source = self._format
        if target == source:
            return x, list(self._names)
        if source == _PixelFormat.MultiChannel and all(c in self._names for c in ("R", "G", "B")):
            # A render with extra layers (R, G, B first, then AOVs): its colour, and alpha if any.
            keep = [self._names.index(c) for c in ("R", "G", "B")]
            source = _PixelFormat.RGB
            if "A" in self._names:
                keep.append(self._names.index("A"))
                source = _PixelFormat.RGBA
            x = x[:, :, keep]
            if target == source:
                return x, list(_CHANNELS[source])
        if source == _PixelFormat.MultiChannel or target == _PixelFormat.MultiChannel or \
                target not in (_PixelFormat.Y, _PixelFormat.YA, _PixelFormat.RGB, _PixelFormat.RGBA) or \
                source not in (_PixelFormat.Y, _PixelFormat.YA, _PixelFormat.RGB, _PixelFormat.RGBA):
            raise NotImplementedError(f"Bitmap.convert from {source.name} to {target.name} is not available in "
                                      "candela.mitsuba (it converts among Y, YA, RGB and RGBA)")
        h, w, _ = x.shape
        has_alpha = source in (_PixelFormat.YA, _PixelFormat.RGBA)
        alpha = x[:, :, -1:] if has_alpha else np.ones((h, w, 1))
        if source in (_PixelFormat.Y, _PixelFormat.YA):
            y = x[:, :, :1]
            rgb = np.repeat(y, 3, axis=2)
        else:
            rgb = x[:, :, :3]
            y = (rgb @ _LUMINANCE)[:, :, None]
        parts = {_PixelFormat.Y: [y], _PixelFormat.YA: [y, alpha], _PixelFormat.RGB: [rgb],
                 _PixelFormat.RGBA: [rgb, alpha]}[target]
        return np.concatenate(parts, axis=2), list(_CHANNELS[target])

    # --- files -----------------------------------------------------------------------------------
    def write(self, path, format=_FileFormat.Auto, quality: int = -1):
        """Writes the bitmap at `path`, in `format` (Auto: the one its extension names). OpenEXR
        (.exr): the channels as float32 (float16 for a Float16 bitmap), linear. PNG (.png) and JPEG
        (.jpg, .jpeg): 8-bit; float data is converted to 8-bit sRGB first (as write_bitmap does),
        8-bit data is written as it is. ``quality`` is JPEG's (1-100; -1: 100)."""
        path = os.fspath(path)
        if not isinstance(format, _FileFormat):
            raise TypeError(f"write: format must be a Bitmap.FileFormat, got {format!r}")
        if format in (_FileFormat.Auto, _FileFormat.Unknown):
            extension = os.path.splitext(path)[1].lower()
            format = {".exr": _FileFormat.OpenEXR, ".png": _FileFormat.PNG, ".jpg": _FileFormat.JPEG,
                      ".jpeg": _FileFormat.JPEG, ".hdr": _FileFormat.RGBE, ".rgbe": _FileFormat.RGBE,
                      ".pfm": _FileFormat.PFM, ".ppm": _FileFormat.PPM, ".tga": _FileFormat.TGA,
                      ".bmp": _FileFormat.BMP}.get(extension)
            if format is None:
                raise ValueError(f"{path}: unknown file format (extension {extension!r}); Bitmap writes .exr, .png and .jpg")
        if format == _FileFormat.OpenEXR:
            b = self if self._component in (Struct.Type.Float16, Struct.Type.Float32) and not self._srgb else \
                self.convert(component_format=Struct.Type.Float32, srgb_gamma=False)
            # Written at `path` whatever its extension (whole or not at all, as every writer here).
            buffer = _native.ImageBuffer(np.ascontiguousarray(b._data, dtype=np.float32), list(b._names), self._string_metadata())
            _native.write_exr(buffer, path, b._component != Struct.Type.Float16)
        elif format == _FileFormat.PNG:
            self._eight_bit()._write_png(path)
        elif format == _FileFormat.JPEG:
            from ._jpeg import encode_jpeg

            b = self._eight_bit()
            if b._format in (_PixelFormat.RGBA, _PixelFormat.YA):
                b = b.convert(_PixelFormat.RGB if b._format == _PixelFormat.RGBA else _PixelFormat.Y)
            data = encode_jpeg(b._data, 100 if quality is None or quality < 0 else int(quality))
            _write_whole(path, data)
        else:
            raise NotImplementedError(f"Bitmap.write: writing {format.name} files is not available in candela.mitsuba "
                                      "(it writes OpenEXR, PNG and JPEG)")

    def write_async(self, path, format=_FileFormat.Auto, quality: int = -1):
        """As write (the file is complete when this returns)."""
        self.write(path, format, quality)

    def _string_metadata(self) -> dict:
        return {str(k): str(v) for k, v in self._metadata.items() if not str(k).startswith("oiio:")}

    def _eight_bit(self) -> "Bitmap":
        if self._component == Struct.Type.UInt8:
            b = self
        elif self._component == Struct.Type.UInt16:
            return self
        else:
            b = self.convert(component_format=Struct.Type.UInt8, srgb_gamma=True)
        if b._format not in (_PixelFormat.Y, _PixelFormat.YA, _PixelFormat.RGB, _PixelFormat.RGBA):
            raise NotImplementedError(f"writing a {b._format.name} bitmap as PNG or JPEG is not available in "
                                      "candela.mitsuba: convert it to Y, YA, RGB or RGBA first")
        return b

    def _write_png(self, path: str):
        if self._component == Struct.Type.UInt8 and self._format == _PixelFormat.RGB:
            _native.write_png(np.ascontiguousarray(self._data), path)
            return
        colour_type = {_PixelFormat.Y: 0, _PixelFormat.YA: 4, _PixelFormat.RGB: 2, _PixelFormat.RGBA: 6}.get(self._format)
        if colour_type is None:
            raise NotImplementedError(f"writing a {self._format.name} bitmap as PNG is not available in candela.mitsuba")
        _write_whole(path, _encode_png(self._data, colour_type, self._srgb))

    # --- editing and resampling ---------------------------------------------------------------
    def clear(self) -> None:
        """Sets every component to zero."""
        self._data[...] = 0

    def vflip(self) -> None:
        """Flips the image upside down, in place."""
        self._data[...] = self._data[::-1].copy()

    def accumulate(self, bitmap, source_offset=None, target_offset=None, size=None) -> None:
        """Adds `bitmap`'s pixels to this one's: the `size` pixels from `source_offset` in it onto
        `target_offset` here (defaults: the origins, the whole source), cut to both images as
        Mitsuba does. Both must have the same pixel format, component format and channels.
        ``accumulate(bitmap, target_offset)`` adds the whole bitmap there."""
        if not isinstance(bitmap, Bitmap):
            raise TypeError(f"Bitmap.accumulate expects a Bitmap, got {type(bitmap).__name__}")
        self._check_same_layout(bitmap, "Bitmap.accumulate: the source and target bitmaps are incompatible")
        if target_offset is None and size is None and source_offset is not None:
            source_offset, target_offset = None, source_offset  # accumulate(bitmap, target_offset)
        sx, sy = (int(v) for v in (source_offset if source_offset is not None else (0, 0)))
        tx, ty = (int(v) for v in (target_offset if target_offset is not None else (0, 0)))
        w, h = (int(v) for v in (size if size is not None else (bitmap.width(), bitmap.height())))
        sx, tx, w = _clip_span(sx, tx, w, bitmap.width(), self.width())
        sy, ty, h = _clip_span(sy, ty, h, bitmap.height(), self.height())
        if w <= 0 or h <= 0:
            return
        region = self._data[ty:ty + h, tx:tx + w]
        region += bitmap._data[sy:sy + h, sx:sx + w].astype(region.dtype, copy=False)

    def _check_same_layout(self, other: "Bitmap", message: str) -> None:
        """Raises ValueError(message ...) unless `other` has this bitmap's pixel format,
        component format and channel count."""
        if (other._format, other._component, other.channel_count()) != (self._format, self._component,
                                                                         self.channel_count()):
            raise ValueError(f"{message} (pixel format, component format and channel count must agree)")

    def split(self) -> list:
        """The layers of a multichannel image (an EXR with AOVs): (name, Bitmap) pairs sorted by
        name, channels grouped by the prefix before their last '.' ('albedo.R' -> layer 'albedo';
        channels without one form '<root>'). A layer of R, G, B (and A) becomes an RGB (RGBA)
        bitmap, of X, Y, Z an XYZ one, of Y a Y one, others MultiChannel. A bitmap that is not
        MultiChannel is its own only layer, '<root>'."""
        if self._format != _PixelFormat.MultiChannel:
            return [("<root>", self)]
        layers: dict[str, list[tuple[str, int]]] = {}
        for i, name in enumerate(self._names):
            prefix, dot, suffix = name.rpartition(".")
            layers.setdefault(prefix if dot else "<root>", []).append((suffix, i))
        result = []
        for prefix, members in layers.items():
            suffixes = [suffix for suffix, _ in members]
            extras = [x for x in ("A", "W") if x in suffixes]
            if "W" in extras and (prefix != "<root>" or "A" not in extras):
                raise ValueError(f"Bitmap.split: layer {prefix!r} has a weight channel (W), which only the root layer "
                                 "may have, with an alpha channel")
            colours = sorted(x for x in suffixes if x not in extras)
            pixel_format = None
            for candidate in (_PixelFormat.RGB, _PixelFormat.XYZ, _PixelFormat.Y):
                if colours == sorted(_CHANNELS[candidate]) and len(suffixes) == len(colours) + len(extras):
                    pixel_format = _PixelFormat[candidate.name + "".join(extras)] if extras else candidate
            if pixel_format is None or pixel_format not in _CHANNELS:
                pixel_format, order = _PixelFormat.MultiChannel, suffixes
            else:
                order = _CHANNELS[pixel_format]
            index = dict(members)
            layer = Bitmap(self._data[:, :, [index[x] for x in order]], pixel_format,
                           order if pixel_format == _PixelFormat.MultiChannel else None)
            layer._srgb = self._srgb
            result.append((prefix, layer))
        return sorted(result, key=lambda item: item[0])

    def resample(self, res, rfilter=None, bc=None, clamp=None, temp=None):
        """Up- or downsamples to `res` (width, height) with Mitsuba's separable resampler: each
        output pixel is a normalised sum of source pixels weighted by the reconstruction filter
        `rfilter` (a filter from load_dict; default a 2-lobe Lanczos), the filter widened by the
        scale factor when downsampling. `bc`: what lies outside the image along x and y
        (FilterBoundaryCondition, default Clamp for both); `clamp`: (low, high) limits of the
        results. Float16, float32 and float64 bitmaps only, as in Mitsuba. ``resample(target,
        ...)`` with a Bitmap fills that one (same formats) instead of returning a new one."""
        if self._component not in (Struct.Type.Float16, Struct.Type.Float32, Struct.Type.Float64):
            raise ValueError(f"Bitmap.resample: the component format must be Float16, Float32 or Float64, not "
                             f"{self._component.name} (convert the bitmap first), as in Mitsuba")
        target = res if isinstance(res, Bitmap) else None
        if target is not None:
            self._check_same_layout(target, "Bitmap.resample: the target bitmap is incompatible")
            res = target.size()
        width, height = (int(v) for v in res)
        if width < 1 or height < 1:
            raise ValueError(f"Bitmap.resample: the resolution must be at least 1 x 1, got {width} x {height}")
        if bc is None:
            bc = (FilterBoundaryCondition.Clamp, FilterBoundaryCondition.Clamp)
        elif isinstance(bc, FilterBoundaryCondition):
            bc = (bc, bc)
        low, high = (-np.inf, np.inf) if clamp is None else (float(clamp[0]), float(clamp[1]))
        radius, weights_at = _filter_weights(rfilter)
        # In the bitmap's own precision, as Mitsuba (float32 for float16 data).
        data = self._data.astype(np.float64 if self._component == Struct.Type.Float64 else np.float32)
        if width != self.width():
            data = _resample_axis(data, 1, width, radius, weights_at, bc[0], low, high)
        if height != self.height():
            data = _resample_axis(data, 0, height, radius, weights_at, bc[1], low, high)
        data = data.astype(self._data.dtype)
        if target is None:
            target = Bitmap(self)
            target._data = np.ascontiguousarray(data)
        else:
            target._data[...] = data
        return target

    # --- what Mitsuba's Bitmap has besides ---------------------------------------------------
    def __getattr__(self, name):
        if name in ("rebuild_channels", "struct_", "detect_file_format"):
            raise NotImplementedError(f"Bitmap.{name} is not available in candela.mitsuba: use NumPy on np.array(bitmap)")
        raise AttributeError(f"'Bitmap' object has no attribute {name!r}")


class FilterBoundaryCondition(enum.Enum):
    """What Bitmap.resample reads outside the image: the nearest edge pixel (Clamp), the image
    repeated (Repeat) or mirrored (Mirror), or zeros (Zero) or ones (One)."""
    Clamp = 0
    Repeat = 1
    Mirror = 2
    Zero = 3
    One = 4


# The reconstruction filters Bitmap.resample used, by their dictionary: a filter is evaluated by
# Candela's own plugin (loaded in a film), so the weights are those a film would use.
_filters: dict[str, object] = {}


def _filter_weights(rfilter):
    """(radius, weights at offsets) of a reconstruction filter from load_dict (or its dictionary);
    None is Mitsuba's default for resampling, a 2-lobe Lanczos."""
    if rfilter is None:
        rfilter = {"type": "lanczos", "lobes": 2}
    if isinstance(rfilter, _Plugin):
        if rfilter.kind != "rfilter":
            raise TypeError(f"Bitmap.resample: rfilter must be a reconstruction filter, got a {rfilter.kind}")
        rfilter = rfilter.dictionary
    if not isinstance(rfilter, dict):
        raise TypeError(f"Bitmap.resample: rfilter must be a reconstruction filter from load_dict, got {rfilter!r}")
    key = repr(sorted(rfilter.items()))
    holder = _filters.get(key)
    if holder is None:
        holder = _candela.load_dict({"type": "scene", "sensor": {
            "type": "perspective", "film": {"type": "hdrfilm", "width": 1, "height": 1, "rfilter": rfilter}}})
        _filters[key] = holder
    radius = _native.film_filter(holder, np.zeros(0))[0]
    return radius, lambda offsets: _native.film_filter(holder, offsets)[1]


def _resample_axis(data: np.ndarray, axis: int, size: int, radius: float, weights_at, bc, low: float, high: float):
    """Resamples `data` (H x W x C, float32 or float64) along `axis` to `size` pixels (Mitsuba's Resampler:
    output pixel i's centre lies at (i + 0.5) source / size; its weights are the filter's at the
    source pixel centres around it, normalised to sum to one; downsampling widens the filter by
    the scale factor, so that it averages every source pixel it covers)."""
    source = data.shape[axis]
    scale = 1.0
    if size < source:
        scale = source / size
        radius = radius * scale
    taps = int(np.ceil(2.0 * radius))
    if size == source and taps % 2 != 1:
        taps -= 1  # the same size: taps centred on the source pixel, which a filter keeps whole
    centres = (np.arange(size) + 0.5) * (source / size)
    starts = np.floor(centres - radius + 0.5).astype(np.int64)
    index = starts[:, None] + np.arange(taps)[None, :]
    weights = weights_at(((index + 0.5 - centres[:, None]) / scale).reshape(-1)).reshape(size, taps)
    total = weights.sum(axis=1, keepdims=True)
    weights = np.divide(weights, total, out=np.zeros_like(weights), where=total != 0)
    outside = (index < 0) | (index >= source)
    constant = 0.0
    if bc == FilterBoundaryCondition.Clamp:
        index = np.clip(index, 0, source - 1)
    elif bc == FilterBoundaryCondition.Repeat:
        index = np.mod(index, source)
    elif bc == FilterBoundaryCondition.Mirror:
        index = np.mod(index, 2 * source)
        index = np.where(index >= source, 2 * source - index - 1, index)
    elif bc in (FilterBoundaryCondition.Zero, FilterBoundaryCondition.One):
        constant = 1.0 if bc == FilterBoundaryCondition.One else 0.0
        constant = (weights * outside).sum(axis=1) * constant  # what the pixels outside add
        weights = np.where(outside, 0.0, weights)
        index = np.clip(index, 0, source - 1)
    else:
        raise TypeError(f"Bitmap.resample: bc must be FilterBoundaryCondition values, got {bc!r}")
    moved = np.moveaxis(data, axis, 0)  # the resampled axis first
    weights = weights.astype(data.dtype)
    out = np.zeros((size,) + moved.shape[1:], dtype=data.dtype)
    for k in range(taps):
        out += weights[:, k].reshape((size,) + (1,) * (moved.ndim - 1)) * moved[index[:, k]]
    out += np.reshape(constant, (-1,) + (1,) * (moved.ndim - 1)).astype(data.dtype)
    return np.moveaxis(np.clip(out, low, high), 0, axis)


def _clip_span(source: int, target: int, length: int, source_size: int, target_size: int) -> tuple[int, int, int]:
    """A span of `length` pixels from `source` in one image onto `target` in another, along one
    axis, cut to both: negative starts move it, the images' ends stop it. Its new start in each
    and its length (0 or less: nothing left)."""
    shift = max(0, -source, -target)
    source, target = source + shift, target + shift
    return source, target, min(length - shift, source_size - source, target_size - target)


def _write_whole(path: str, data: bytes):
    """Writes a file whole or not at all (a temporary beside it, renamed)."""
    directory = os.path.dirname(os.path.abspath(path))
    temporary = os.path.join(directory, f".{os.path.basename(path)}.{os.getpid()}.{threading.get_ident()}.tmp")
    try:
        with open(temporary, "wb") as f:
            f.write(data)
        os.replace(temporary, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.remove(temporary)
        raise


def _encode_png(data: np.ndarray, colour_type: int, srgb: bool) -> bytes:
    """A PNG of 8- or 16-bit pixels (H x W x C; colour type 0 grey, 2 RGB, 4 grey+alpha, 6 RGBA)."""
    height, width, channels = data.shape
    depth = 8 if data.dtype == np.uint8 else 16
    rows = data.astype(">u2") if depth == 16 else data
    raw = b"".join(b"\x00" + rows[y].tobytes() for y in range(height))

    def chunk(kind: bytes, payload: bytes) -> bytes:
        return struct.pack(">I", len(payload)) + kind + payload + struct.pack(">I", zlib.crc32(kind + payload) & 0xFFFFFFFF)

    out = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, depth, colour_type, 0, 0, 0))
    if srgb:
        out += chunk(b"sRGB", b"\x00")
    return out + chunk(b"IDAT", zlib.compress(raw, 6)) + chunk(b"IEND", b"")


# --------------------------------------------------------------------------------------------------
# mi.util
# --------------------------------------------------------------------------------------------------

def _convert_to_bitmap(data, uint8_srgb: bool = True) -> Bitmap:
    """The image `data` (an array, an image from render, a Bitmap) as a Bitmap; with uint8_srgb
    (the default, as Mitsuba) converted to 8-bit sRGB RGB."""
    bitmap = data if isinstance(data, Bitmap) else Bitmap(data)
    if uint8_srgb:
        bitmap = bitmap.convert(_PixelFormat.RGB, Struct.Type.UInt8, True)
    return bitmap


def _write_bitmap(filename, data, write_async: bool = True, quality: int = -1) -> None:
    """Writes the image `data` to a file: .png, .jpg and .jpeg as 8-bit sRGB RGB, .exr (and others)
    as the data's float values."""
    name = os.fspath(filename)
    uint8_srgb = name.lower().endswith((".png", ".jpg", ".jpeg"))
    _convert_to_bitmap(data, uint8_srgb).write(name, quality=quality)


def _core_count() -> int:
    return os.cpu_count() or 1


class _UtilModule(types.ModuleType):
    def __getattr__(self, name):
        if name.startswith("__"):
            raise AttributeError(name)
        raise NotImplementedError(f"mitsuba.util.{name} is not available in candela.mitsuba (it offers write_bitmap, "
                                  "convert_to_bitmap, traverse, render and core_count)")


util = _UtilModule(__name__ + ".util", "Mitsuba's mi.util: write_bitmap, convert_to_bitmap and a few helpers.")
util.write_bitmap = _write_bitmap
util.convert_to_bitmap = _convert_to_bitmap
util.core_count = _core_count
util.traverse = traverse
util.render = render
util.SceneParameters = SceneParameters
sys.modules[util.__name__] = util


# --------------------------------------------------------------------------------------------------
# Dr.Jit: scripts import it beside Mitsuba (`import drjit as dr`). Where it is not installed, a
# stand-in module answers every `dr.<name>` with NotImplementedError, so that a script fails at
# the first Dr.Jit call it makes, naming it. Registered only when no real drjit can be imported.
# --------------------------------------------------------------------------------------------------

class _DrJitStandIn(types.ModuleType):
    def __getattr__(self, name):
        if name.startswith("__"):
            raise AttributeError(name)
        raise NotImplementedError(f"drjit.{name}: Dr.Jit (its arrays, automatic differentiation and loops) is not "
                                  "available with candela.mitsuba: images and parameters are NumPy arrays, use NumPy")


def _install_drjit_stand_in():
    import importlib.util

    if "drjit" in sys.modules:
        return
    try:
        if importlib.util.find_spec("drjit") is not None:
            return
    except (ImportError, ValueError):
        pass
    stand_in = _DrJitStandIn("drjit", "A stand-in for Dr.Jit registered by candela.mitsuba: every attribute raises "
                                      "NotImplementedError.")
    stand_in.__candela_stand_in__ = True
    sys.modules["drjit"] = stand_in


_install_drjit_stand_in()


# --------------------------------------------------------------------------------------------------
# Logging (accepted; Candela's loader and renderer report errors as exceptions)
# --------------------------------------------------------------------------------------------------

class LogLevel(enum.IntEnum):
    Trace = 0
    Debug = 100
    Info = 200
    Warn = 300
    Error = 400


_log = {"level": LogLevel.Warn}


def set_log_level(level) -> None:
    """Sets the level of messages Log prints (Candela itself reports problems as exceptions)."""
    _log["level"] = LogLevel(int(level))


def log_level():
    return _log["level"]


def Log(level, message: str) -> None:  # noqa: N802 - Mitsuba's name
    """Prints `message` on stderr if `level` is at least the log level; Error raises RuntimeError."""
    level = LogLevel(int(level))
    if level >= LogLevel.Error:
        raise RuntimeError(str(message))
    if level >= _log["level"]:
        print(f"{level.name.upper()}: {message}", file=sys.stderr)


# --------------------------------------------------------------------------------------------------
# Everything else Mitsuba has: a clear NotImplementedError
# --------------------------------------------------------------------------------------------------

_AUTODIFF = "Dr.Jit arrays and automatic differentiation (Candela's images and parameters are NumPy arrays)"
_PLUGINS = "custom plugins written in Python (Candela's plugins are native; see docs/plugins)"
_OBJECTS = "Mitsuba's plugin objects and their methods from Python (Candela loads, renders and edits scenes whole)"
_QUERIES = "ray tracing and sampling queries from Python (scene.ray_intersect, mi.Ray3f, interactions, ...)"

_UNSUPPORTED: dict[str, str] = {}
for _name in ("Float", "Float16", "Float32", "Float64", "Int", "Int8", "Int32", "Int64", "UInt", "UInt8", "UInt32",
              "UInt64", "Bool", "Mask", "TensorXf", "TensorXf16", "TensorXf64", "TensorXi", "TensorXu", "TensorXb",
              "TensorXi64", "TensorXu64", "ArrayXf", "ArrayXi", "ArrayXu", "ArrayXb", "ArrayXf64", "Array2f", "Array3f",
              "Array4f", "Point2f", "Point2i", "Point2u", "Point4f", "Vector2f", "Vector2i", "Vector4f",
              "Vector3i", "Vector3u", "Point3i", "Point3u", "Vector0f", "Vector1f", "Color0f", "Color1f", "Spectrum",
              "UnpolarizedSpectrum", "Matrix2f", "Matrix3f", "Matrix4f", "Matrix44f", "Quaternion4f", "Complex2f",
              "ScalarFloat", "ScalarInt32", "ScalarUInt32", "ScalarPoint2f", "ScalarPoint2i", "ScalarPoint2u",
              "ScalarPoint3i", "ScalarPoint3u", "ScalarVector2f", "ScalarVector2i", "ScalarVector3i",
              "ScalarVector3u", "ScalarVector4f", "ScalarColor0f", "ScalarColor1f", "ScalarMatrix2f", "ScalarMatrix3f",
              "ScalarMatrix4f", "ScalarBoundingBox2f", "ScalarBoundingSphere3f", "BoundingBox2f",
              "BoundingSphere3f", "Transform3f", "ScalarTransform3f", "AffineTransform3f",
              "ScalarAffineTransform3f", "Frame3f", "ScalarFrame3f", "Loop", "Texture2f", "Texture3f", "Spectrum3f",
              "UnpolarizedSpectrum3f", "Stokes4f", "MuellerMatrix"):
    _UNSUPPORTED[_name] = _AUTODIFF
for _name in ("ad", "grad", "enable_grad", "disable_grad", "backward", "forward", "Optimizer", "SGD", "Adam",
              "detach", "CustomOp"):
    _UNSUPPORTED[_name] = "automatic differentiation (mi.ad, optimizers, gradients)"
for _name in ("register_bsdf", "register_emitter", "register_integrator", "register_sensor", "register_texture",
              "register_medium", "register_phasefunction", "register_volume", "register_film", "register_rfilter",
              "register_sampler", "register_shape", "SamplingIntegrator", "ADIntegrator",
              "AdjointIntegrator", "python"):
    _UNSUPPORTED[_name] = _PLUGINS
for _name in ("Texture", "ImageBlock", "Medium",
              "PhaseFunction", "Volume", "VolumeGrid", "ReconstructionFilter", "Endpoint", "ShapeGroup", "Object",
              "Properties", "PluginManager", "TraversalCallback", "ParamFlags", "BSDFFlags", "EmitterFlags", "RayFlags",
              "Resampler", "ProjectiveCamera", "Class", "load_plugin"):
    _UNSUPPORTED[_name] = _OBJECTS
for _name in ("Ray3f", "RayDifferential3f", "ScalarRay3f", "SurfaceInteraction3f", "Interaction3f",
              "MediumInteraction3f", "PreliminaryIntersection3f", "BSDFContext", "BSDFSample3f", "DirectionSample3f",
              "PositionSample3f", "SilhouetteSample3f", "PhaseFunctionContext", "TransportMode", "has_flag",
              "coordinate_system", "reflect", "refract", "fresnel", "fresnel_conductor", "fresnel_polarized",
              "MicrofacetDistribution", "MicrofacetType", "sample_tea_32", "sample_tea_64", "sample_tea_float",
              "sample_tea_float32", "sample_tea_float64", "PCG32", "sample_rgb_spectrum", "pdf_rgb_spectrum",
              "cie1931_xyz", "cie1931_y", "srgb_model_fetch", "srgb_model_eval", "srgb_model_mean", "xyz_to_srgb",
              "srgb_to_xyz", "spectrum_to_srgb", "spectrum_from_file", "spectrum_to_file", "warp", "math", "spline",
              "quad", "chi2", "DiscreteDistribution", "ContinuousDistribution", "IrregularContinuousDistribution",
              "Hierarchical2D0", "MarginalContinuous2D0", "MarginalDiscrete2D0", "eval_reflectance",
              "lookup_ior", "polarization", "mueller", "depolarizer", "unpolarized_spectrum"):
    _UNSUPPORTED[_name] = _QUERIES
_UNSUPPORTED.update({
    "xml": "mi.xml (dict_to_xml, the XML writer)",
    "dict_to_xml": "mi.xml.dict_to_xml (writing a dictionary back to XML)",
    "Thread": "mi.Thread (its file resolver and logger); give paths relative to the working directory or absolute",
    "FileResolver": "mi.FileResolver (search paths); give paths relative to the working directory or absolute",
    "Logger": "mi.Logger and Appender (use mi.set_log_level)",
    "Appender": "mi.Logger and Appender (use mi.set_log_level)",
    "Timer": "mi.Timer (use time.perf_counter)",
    "MemoryMappedFile": "Mitsuba's stream classes",
    "Stream": "Mitsuba's stream classes",
    "FileStream": "Mitsuba's stream classes",
    "MemoryStream": "Mitsuba's stream classes",
    "ZStream": "Mitsuba's stream classes",
    "DummyStream": "Mitsuba's stream classes",
    "StructConverter": "Mitsuba's StructConverter",
    "set_thread_count": "mi.set_thread_count (Candela renders on all cores; candela.render takes threads=)",
    "TensorFile": "mi.TensorFile (tensor_io)",
    "tensor_io": "mi.tensor_io",
    "plugins": "mi.plugins (Python texture plugins)",
    "testing": "mi.testing",
    "sys_info": "mi.sys_info",
    "MI_VERSION": "Mitsuba's version constants (this is Candela: candela.__version__)",
    "MI_VERSION_MAJOR": "Mitsuba's version constants (this is Candela: candela.__version__)",
    "MI_VERSION_MINOR": "Mitsuba's version constants (this is Candela: candela.__version__)",
    "MI_VERSION_PATCH": "Mitsuba's version constants (this is Candela: candela.__version__)",
    "MI_ENABLE_CUDA": "Mitsuba's build constants",
    "MI_ENABLE_EMBREE": "Mitsuba's build constants",
    "DEBUG": "Mitsuba's build constants",
})
del _name


# Mitsuba's scene and plugin objects have methods that Candela's do not: asking a candela.Scene or
# a candela.Plugin for one of them says so, instead of a bare AttributeError.
_SCENE_METHODS = ("shapes_dr", "emitters_dr", "sensors_dr", "ray_intersect",
                  "ray_intersect_preliminary", "ray_test", "sample_emitter", "sample_emitter_direction",
                  "sample_emitter_ray", "eval_emitter_direction", "pdf_emitter", "pdf_emitter_direction",
                  "environment", "sample_silhouette", "invert_silhouette_sample", "parameters_changed", "id",
                  "shapegroups", "integrator_", "set_integrator")
_PLUGIN_METHODS = ("eval", "sample", "pdf", "eval_pdf", "eval_pdf_sample", "albedo", "flags", "component_count",
                   "needs_differentials", "sample_ray", "sample_ray_differential", "sample_direction",
                   "pdf_direction", "eval_direction", "sample_position", "pdf_position", "sample_wavelengths",
                   "film", "sampler", "world_transform", "shutter_open", "bbox", "surface_area", "ray_intersect",
                   "vertex_positions_buffer", "faces_buffer", "vertex_count", "face_count", "write_ply",
                   "render", "eval_1", "eval_3", "mean", "id", "parameters_changed", "crop_size", "size", "develop")


def _scene_getattr(self, name):
    if name in _SCENE_METHODS:
        raise NotImplementedError(f"Scene.{name}: {_OBJECTS} is not available in candela.mitsuba (a Candela scene has "
                                  "film_size, spp, integrator and path; edit it with mi.traverse)")
    raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")


def _plugin_getattr(self, name):
    if name in _PLUGIN_METHODS:
        raise NotImplementedError(f"{self.kind}.{name}: {_OBJECTS} is not available in candela.mitsuba (a plugin from "
                                  "load_dict is a checked description, used inside a scene or as render's integrator "
                                  "or sensor)")
    raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")


if "__getattr__" not in _candela.Scene.__dict__:
    _candela.Scene.__getattr__ = _scene_getattr
    _candela.Scene.sensors = _scene_sensors
    _candela.Scene.shapes = _scene_shapes
    _candela.Scene.emitters = _scene_emitters
    _candela.Scene.bbox = _scene_bbox
    _integrator_name = _candela.Scene.integrator
    _candela.Scene.integrator = property(lambda self: _IntegratorName(_integrator_name.fget(self), self),
                                         doc=_integrator_name.__doc__)
if "__getattr__" not in _Plugin.__dict__:
    _Plugin.__getattr__ = _plugin_getattr


def __getattr__(name: str):
    if name in _UNSUPPORTED:
        raise NotImplementedError(f"mitsuba.{name}: {_UNSUPPORTED[name]} is not available in candela.mitsuba "
                                  "(see docs/python.md for what it offers)")
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    return sorted(globals())
