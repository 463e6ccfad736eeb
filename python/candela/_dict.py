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

An image in memory, as Mitsuba takes it (a Bitmap as a ``bitmap`` texture's or an ``envmap``'s
``'bitmap'``, a tensor as a ``bitmap`` texture's ``'data'``), is written to a file in a private
temporary directory (TemporaryFiles) and named as the plugin's ``filename``; the loader reads it
there, and the caller removes the directory once the scene is loaded.
"""

from __future__ import annotations

import math
import numbers
import os
import shutil
import tempfile
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


class TemporaryFiles:
    """The files of the images a dictionary holds in memory, in a private temporary directory
    made at the first one; remove() deletes the directory and everything in it."""

    def __init__(self):
        self.directory = None
        self.count = 0

    def path(self, extension: str) -> str:
        if self.directory is None:
            self.directory = tempfile.mkdtemp(prefix="candela-dict-")
        self.count += 1
        return os.path.join(self.directory, f"image{self.count}{extension}")

    def remove(self):
        if self.directory is not None:
            shutil.rmtree(self.directory, ignore_errors=True)
            self.directory = None


class _Writer:
    def __init__(self, files: TemporaryFiles | None = None):
        self.lines: list[str] = []
        self.paths: list[str] = []  # per line (1-based line i is paths[i - 1])
        self.files = files

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
        skip = ("type", "id")
        images = [k for k in ("bitmap", "data") if k in d] if plugin_type in ("bitmap", "envmap") else []
        if images:
            skip += tuple(images) + (("raw",) if self.image(plugin_type, d, images, path) else ())
        for child_key, value in d.items():
            if child_key in skip:
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

    def image(self, plugin_type: str, d: dict, keys: list[str], path: str) -> bool:
        """A bitmap texture's or envmap's image in memory ('bitmap' or 'data'), written to a
        temporary file and emitted as its filename. True when it emitted 'raw' as well."""
        import numpy as np

        from .image import write_image

        if len(keys) > 1 or "filename" in d:
            given = ["filename"] * ("filename" in d) + keys
            raise DictError(f"{path}: give one of 'filename', 'bitmap' and 'data', not {' and '.join(map(repr, given))}")
        key = keys[0]
        where = f"{path}.{key}"
        value = d[key]
        if self.files is None:
            raise DictError(f"{where}: an image in memory is taken in a scene that load_dict loads, not here")
        if key == "data":
            if plugin_type == "envmap":
                raise DictError(f"{where}: an envmap is made from a 'filename' or 'bitmap' (Mitsuba's envmap has 'data' "
                                "only as a traverse parameter)")
            # Mitsuba's tensor: H x W x 1 or 3 values, used as they are (linear, never decoded).
            try:
                array = np.asarray(value)
            except (TypeError, ValueError):
                array = None
            if array is None or array.ndim != 3 or array.dtype == np.bool_ or array.dtype.kind not in "uif":
                raise DictError(f"{where}: expected an H x W x C array of numbers (a tensor), got {value!r}")
            if array.shape[2] not in (1, 3):
                raise DictError(f"{where}: a bitmap's data has 1 or 3 channels, got {array.shape[2]}")
            if array.size == 0:
                raise DictError(f"{where}: the image is empty ({array.shape[0]} x {array.shape[1]})")
            filename = self.files.path(".exr")
            write_image(filename, np.ascontiguousarray(array, dtype=np.float32))
            self.emit(f"<string name=\"filename\" value={quoteattr(filename)}/>", where)
            return False
        from .mitsuba import Bitmap

        # An Image or an array is taken as mi.Bitmap(array) takes it (8-bit data as sRGB).
        if not isinstance(value, (Bitmap, np.ndarray)):
            raise DictError(f"{where}: expected a Bitmap (or an image as an array), got {value!r}")
        try:
            bitmap = value if isinstance(value, Bitmap) else Bitmap(value)
        except (TypeError, ValueError) as e:
            raise DictError(f"{where}: {e}") from None
        pixel_format = bitmap.pixel_format().name
        if pixel_format not in ("Y", "YA", "RGB", "RGBA"):
            raise DictError(f"{where}: a {pixel_format} bitmap: a texture or envmap takes a Y, YA, RGB or RGBA bitmap")
        if bitmap.width() == 0 or bitmap.height() == 0:
            raise DictError(f"{where}: the image is empty ({bitmap.height()} x {bitmap.width()})")
        if bitmap.has_alpha():
            # Mitsuba converts to Y or RGB, dropping alpha (a file's alpha may be premultiplied when read).
            srgb = bitmap.srgb_gamma()
            bitmap = Bitmap(np.array(bitmap)[:, :, :-1])
            bitmap.set_srgb_gamma(srgb)
        raw = plugin_type == "bitmap" and d.get("raw") is True
        # A texture's 8 and 16 bits as a PNG, which it reads as it reads such a file: decoded from
        # sRGB unless raw (given 'raw' for a bitmap that is not sRGB-encoded, as Mitsuba keeps its
        # values). Floats, and an envmap's bitmap (Mitsuba converts it to linear float RGB), as an
        # OpenEXR file of the linear values.
        integer = plugin_type == "bitmap" and bitmap.component_format().name in ("UInt8", "UInt16")
        if raw and bitmap.srgb_gamma() and not integer:
            bitmap = Bitmap(bitmap)
            bitmap.set_srgb_gamma(False)  # as Mitsuba: raw keeps the values as stored
        filename = self.files.path(".png" if integer else ".exr")
        bitmap.write(filename)
        self.emit(f"<string name=\"filename\" value={quoteattr(filename)}/>", where)
        linear = integer and not bitmap.srgb_gamma() and not raw
        if linear:
            self.emit('<boolean name="raw" value="true"/>', where)
        return linear

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


def scene_xml(d: dict, files: TemporaryFiles | None = None) -> tuple[str, list[str]]:
    """The XML of a scene dictionary and, per line, the key path it came from. Images in memory
    are written to `files` (without, they are a DictError); the caller removes them."""
    if not isinstance(d, dict):
        raise DictError(f"load_dict expects a dictionary, got {type(d).__name__}")
    if d.get("type") != "scene":
        raise DictError("a scene dictionary has 'type': 'scene'")
    w = _Writer(files)
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
