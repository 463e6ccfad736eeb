"""Mitsuba 3's dictionary scene format (``mi.load_dict``) turned into Candela's scene XML.

A scene dictionary has ``'type': 'scene'``; every other key names a child: a nested dictionary
with a ``'type'`` is a plugin (its key is its id at the top level, unless it gives an ``'id'``, and
its name, as XML's ``name=``, when nested), ``{'type': 'rgb', 'value': ...}`` and
``{'type': 'spectrum', ...}`` are colours, the spectrum plugins (``srgb``, ``uniform``, ``d65``,
``regular``, ``irregular``, ``blackbody``) are written as ``<spectrum type="...">``,
``{'type': 'ref', 'id': ...}`` refers to an object declared elsewhere, and plain values are
properties: ``bool``, ``int``, ``float``, ``str``, three numbers (a point), a 4x4 matrix or a
transform (``candela.Transform``, ``mitsuba.ScalarTransform4f``). The XML is written one element
per line, and each line remembers the key path it came from, so that an error the loader reports
at ``<dict>:LINE`` is reported at ``sphere.bsdf.reflectance`` instead.
"""

from __future__ import annotations

import math
import numbers
from xml.sax.saxutils import quoteattr

from . import _candela

COLOUR_TYPES = ("rgb", "spectrum")
# Mitsuba's spectrum plugins, written as <spectrum type="..."> (docs/scene-format.md).
SPECTRUM_TYPES = ("uniform", "srgb", "d65", "regular", "irregular", "blackbody")


class DictError(ValueError):
    """A dictionary that is not a scene description: raised with the key path of the problem."""


def _matrix_of(value):
    """The 16 numbers (row by row) of a transform or a 4x4 array-like, or None."""
    m = getattr(value, "matrix", None)
    if m is not None and not callable(m):
        value = m
    try:
        import numpy as np

        a = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        return None
    if a.shape != (4, 4):
        return None
    return [float(x) for x in a.reshape(16)]


def _numbers(value, path):
    try:
        values = [float(x) for x in value]
    except (TypeError, ValueError):
        raise DictError(f"{path}: expected numbers, got {value!r}") from None
    if not all(math.isfinite(v) for v in values):
        raise DictError(f"{path}: {value!r} is not finite")
    return values


def _format(values):
    return ", ".join(repr(float(v)) for v in values)


class _Writer:
    def __init__(self):
        self.lines: list[str] = []
        self.paths: list[str] = []  # per line (1-based line i is paths[i - 1])

    def emit(self, text: str, path: str):
        self.lines.append(text)
        self.paths.append(path)

    def xml(self) -> str:
        return "\n".join(self.lines) + "\n"

    # A plugin dictionary as an element; `name` is its property name (None at the top level).
    def plugin(self, d: dict, path: str, key: str | None, top_level: bool):
        plugin_type = d.get("type")
        if not isinstance(plugin_type, str):
            raise DictError(f"{path}: a plugin needs a 'type' (a string), got {plugin_type!r}")
        if plugin_type == "ref":
            ref = d.get("id")
            if not isinstance(ref, str):
                raise DictError(f"{path}: a reference needs an 'id' (a string)")
            name = f" name={quoteattr(key)}" if key and not top_level else ""
            self.emit(f"<ref{name} id={quoteattr(ref)}/>", path)
            return
        tag = "spectrum" if plugin_type in SPECTRUM_TYPES else _candela.plugin_tag(plugin_type)
        if tag is None:
            raise DictError(f"{path}: unknown plugin type {plugin_type!r}")
        attributes = f"type={quoteattr(plugin_type)}"
        object_id = d.get("id", key if top_level else None)
        if object_id is not None:
            if not isinstance(object_id, str):
                raise DictError(f"{path}.id: an id is a string, got {object_id!r}")
            attributes += f" id={quoteattr(object_id)}"
        # A nested plugin is named by its key, as the XML's name attribute names it (Mitsuba: the
        # aov integrator's channels, a shape's interior and exterior media).
        if key and not top_level:
            attributes += f" name={quoteattr(key)}"
        self.emit(f"<{tag} {attributes}>", path)
        for child_key, value in d.items():
            if child_key in ("type", "id"):
                continue
            if not isinstance(child_key, str):
                raise DictError(f"{path}: keys are strings, got {child_key!r}")
            if tag == "spectrum" and child_key == "color" and not isinstance(value, (dict, Plugin)):
                value = {"type": "rgb", "value": value}  # an srgb's or d65's colour: an <rgb>
            self.value(child_key, value, f"{path}.{child_key}" if path else child_key)
        self.emit(f"</{tag}>", path)

    def value(self, key: str, value, path: str):
        name = quoteattr(key)
        if isinstance(value, Plugin):
            value = value.dictionary
        if isinstance(value, dict):
            kind = value.get("type")
            if kind in COLOUR_TYPES:
                self.colour(key, value, path)
            else:
                self.plugin(value, path, key, top_level=False)
        elif isinstance(value, bool):
            self.emit(f"<boolean name={name} value=\"{'true' if value else 'false'}\"/>", path)
        elif isinstance(value, numbers.Integral):
            self.emit(f"<integer name={name} value=\"{int(value)}\"/>", path)
        elif isinstance(value, numbers.Real):
            if not math.isfinite(float(value)):
                raise DictError(f"{path}: {value!r} is not finite")
            self.emit(f"<float name={name} value={quoteattr(repr(float(value)))}/>", path)
        elif isinstance(value, str):
            self.emit(f"<string name={name} value={quoteattr(value)}/>", path)
        elif getattr(value, "_candela_colour", False):
            self.emit(f"<rgb name={name} value=\"{_format(_numbers(value, path))}\"/>", path)
        elif getattr(value, "_candela_vector", False):
            values = _numbers(value, path)
            if len(values) != 3:
                raise DictError(f"{path}: a vector has three numbers, got {value!r}")
            self.emit(f"<vector name={name} value=\"{_format(values)}\"/>", path)
        elif _matrix_of(value) is not None:
            m = _matrix_of(value)
            if not all(math.isfinite(v) for v in m):
                raise DictError(f"{path}: the transform is not finite")
            self.emit(f"<transform name={name}><matrix value=\"{_format(m)}\"/></transform>", path)
        else:
            values = _numbers(value, path) if not isinstance(value, (bytes, bytearray)) else None
            if values is None or len(values) != 3:
                raise DictError(f"{path}: cannot make a scene property of {value!r} (a number, text, three numbers, "
                                f"a 4x4 transform, or a plugin dictionary)")
            self.emit(f"<point name={name} value=\"{_format(values)}\"/>", path)

    def colour(self, key: str, d: dict, path: str):
        name = quoteattr(key)
        for k in d:
            if k not in ("type", "value", "filename"):
                raise DictError(f"{path}.{k}: a {d['type']} takes 'value' (or, for a spectrum, 'filename'), not {k!r}")
        if d["type"] == "rgb":
            v = d.get("value")
            values = [float(v)] if isinstance(v, numbers.Real) else _numbers(v if v is not None else [], path + ".value")
            if len(values) not in (1, 3):
                raise DictError(f"{path}.value: an rgb takes one or three numbers, got {v!r}")
            self.emit(f"<rgb name={name} value=\"{_format(values)}\"/>", path)
            return
        if "filename" in d:
            self.emit(f"<spectrum name={name} filename={quoteattr(str(d['filename']))}/>", path)
            return
        v = d.get("value")
        if isinstance(v, numbers.Real):
            self.emit(f"<spectrum name={name} value=\"{float(v)!r}\"/>", path)
            return
        try:
            pairs = [(float(w), float(x)) for w, x in v]
        except (TypeError, ValueError):
            raise DictError(f"{path}.value: a spectrum takes one number or (wavelength, value) pairs, got {v!r}") from None
        text = ", ".join(f"{w!r}:{x!r}" for w, x in pairs)
        self.emit(f"<spectrum name={name} value={quoteattr(text)}/>", path)


class Plugin:
    """A plugin described by a dictionary outside a scene (``load_dict({'type': 'path'})``): used
    as the ``integrator`` of ``render`` or as a value in another dictionary."""

    def __init__(self, dictionary: dict, kind: str):
        self.dictionary = dictionary
        self.kind = kind

    @property
    def type(self) -> str:
        return self.dictionary["type"]

    def __repr__(self):
        return f"candela.Plugin({self.kind} {self.type!r})"


def scene_xml(d: dict) -> tuple[str, list[str]]:
    """The XML of a scene dictionary and, per line, the key path it came from."""
    if not isinstance(d, dict):
        raise DictError(f"load_dict expects a dictionary, got {type(d).__name__}")
    if d.get("type") != "scene":
        raise DictError("a scene dictionary has 'type': 'scene'")
    w = _Writer()
    w.emit('<scene version="3.0.0">', "")
    for key, value in d.items():
        if key == "type":
            continue
        if not isinstance(key, str):
            raise DictError(f"keys are strings, got {key!r}")
        if isinstance(value, Plugin):
            value = value.dictionary
        if not isinstance(value, dict) or "type" not in value:
            raise DictError(f"{key}: a scene's children are plugin dictionaries with a 'type', got {value!r}")
        w.plugin(value, key, key, top_level=True)
    w.emit("</scene>", "")
    return w.xml(), w.paths


def plugin_scene(d: dict) -> tuple[str, dict]:
    """A single plugin's dictionary (not a scene): its kind ("integrator", "bsdf", ...) and a scene
    dictionary that holds it, so that loading that scene checks it."""
    plugin_type = d.get("type") if isinstance(d, dict) else None
    if not isinstance(plugin_type, str):
        raise DictError("a plugin dictionary needs a 'type' (a string)")
    tag = "spectrum" if plugin_type in SPECTRUM_TYPES else _candela.plugin_tag(plugin_type)
    if tag is None:
        raise DictError(f"unknown plugin type {plugin_type!r}")
    if tag == "spectrum":
        # A spectrum plugin is a texture (as in Mitsuba), checked as an emitter's radiance, where
        # every spectrum fits.
        tag, holder = "texture", {"type": "scene", "object": {"type": "constant", "radiance": d}}
    elif tag in ("integrator", "emitter", "shape", "sensor"):
        holder = {"type": "scene", "object": d}
    elif tag == "bsdf":
        holder = {"type": "scene", "object": {"type": "sphere", "bsdf": d}}
    elif tag == "texture":
        holder = {"type": "scene", "object": {"type": "sphere", "bsdf": {"type": "diffuse", "reflectance": d}}}
    else:
        holder = None
    return tag, holder
