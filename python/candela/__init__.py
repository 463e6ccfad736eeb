"""Candela from Python: load Mitsuba 3 scenes (files, strings, dictionaries), render them to NumPy
images, edit their parameters and render again, and check renders against references.

    import candela
    scene = candela.load_file("scenes/cbox.xml", spp=64)
    image = candela.render(scene)          # H x W x 3 float32, a NumPy array
    params = candela.traverse(scene)
    params["red.reflectance.value"] = [0.2, 0.6, 0.2]
    params.update()
    image2 = candela.render(scene, seed=1)

Scripts written for Mitsuba 3 run with ``import candela.mitsuba as mi`` (see candela/mitsuba.py
and docs/python.md for what that covers).
"""

from __future__ import annotations

import os
import threading

import numpy as np

from .errors import InputError, InternalError, SceneError
from . import _candela
from ._candela import Scene
from ._dict import DictError, Plugin, plugin_scene, scene_xml
from .analysis import compare, compare_modes, converge, estimate_irradiance, estimate_radiance, validate
from .image import Image, read_image, write_image
from .parameters import SceneParameters, traverse
from .transform import Transform

__all__ = [
    "Scene", "Image", "Transform", "Plugin", "SceneParameters", "SceneError", "InputError", "InternalError", "DictError",
    "load_file", "load_string", "load_dict", "render", "traverse", "read_image", "write_image", "compare", "converge", "validate",
    "estimate_irradiance", "estimate_radiance", "compare_modes", "variants", "__version__",
]

__version__ = _candela.version()


def _parameters(params: dict) -> dict:
    """Mitsuba's $name parameters, as the text the scene file would hold."""
    out = {}
    for name, value in params.items():
        if isinstance(value, bool):
            out[name] = "true" if value else "false"
        elif isinstance(value, (list, tuple, np.ndarray)):
            out[name] = ", ".join(repr(float(v)) for v in np.asarray(value).reshape(-1))
        else:
            out[name] = str(value)
    return out


def load_file(path, **params) -> Scene:
    """Loads a Mitsuba 3 XML scene; keyword arguments set its ``$name`` parameters
    (``load_file("cbox.xml", spp=64, res=256)``). Errors raise SceneError with ``file:line``."""
    return _candela.load_file(os.fspath(path), _parameters(params))


def load_string(xml: str, **params) -> Scene:
    """Loads a scene from XML text; files it names are found relative to the working directory."""
    if not isinstance(xml, str):
        raise TypeError(f"load_string expects XML text (a str), got {type(xml).__name__}")
    return _candela.load_string(xml, os.path.join(os.getcwd(), "<string>.xml"), _parameters(params))


def load_dict(d: dict, **params):
    """Loads a scene from Mitsuba 3's dictionary format (``{'type': 'scene', ...}``). A dictionary
    of another plugin (``{'type': 'path', 'max_depth': 8}``) is checked and returned as a Plugin,
    for ``render(..., integrator=...)`` or as a value in another dictionary. Errors raise
    SceneError naming the key path (``sphere.bsdf.reflectance: ...``)."""
    if isinstance(d, dict) and d.get("type") != "scene":
        kind, holder = plugin_scene(d)
        if holder is not None:
            _load_dict_scene(holder, {}, prefix_strip="object")
        return Plugin(d, kind)
    return _load_dict_scene(d, params)


def _load_dict_scene(d: dict, params: dict, prefix_strip: str | None = None) -> Scene:
    xml, paths = scene_xml(d)
    virtual = os.path.join(os.getcwd(), "<dict>.xml")
    try:
        return _candela.load_string(xml, virtual, _parameters(params))
    except SceneError as e:
        line = getattr(e, "line", 0)
        path = paths[line - 1] if 0 < line <= len(paths) else ""
        if prefix_strip and (path == prefix_strip or path.startswith(prefix_strip + ".")):
            path = path[len(prefix_strip) + 1:]
        where = path if path else "<dict>"
        raise SceneError(f"{where}: {e.message}", where, 0, e.message) from None


def render(scene: Scene, spp: int | None = None, seed: int = 0, sensor: int = 0, threads: int | None = None, integrator=None,
           progress=None, aovs=None) -> Image:
    """Renders the scene with its integrator (or `integrator`: a plugin name, a dictionary or a
    Plugin) and returns the image. ``spp`` overrides the sampler's count (rounded as the sampler
    rounds it), ``seed`` is the render's seed. The pixels are bit-identical to ``candela render``
    with the same scene, spp and seed. The GIL is released while rendering; Ctrl-C raises
    KeyboardInterrupt within a second. ``progress(fraction)`` is called from the calling thread
    about ten times a second. ``aovs``: extra layers, as ``--aov`` (albedo, normal, depth,
    variance, samples)."""
    if not isinstance(scene, Scene):
        raise TypeError(f"render expects a candela.Scene, got {type(scene).__name__}")
    if spp is not None and (isinstance(spp, bool) or not isinstance(spp, (int, np.integer)) or not 1 <= spp <= 1 << 30):
        raise ValueError(f"spp must be a whole number of samples, 1 to 2^30 (got {spp!r})")
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or not 0 <= seed < 1 << 64:
        raise ValueError(f"seed must be a whole number, 0 to 2^64 - 1 (got {seed!r})")
    if sensor != 0:
        raise ValueError(f"the scene has one sensor (index 0); sensor={sensor!r}")
    if threads is not None and (not isinstance(threads, (int, np.integer)) or threads < 0):
        raise ValueError(f"threads must be a whole number >= 0 (got {threads!r})")
    if progress is not None and not callable(progress):
        raise TypeError("progress must be callable (it receives the fraction done)")
    integrator_xml = ""
    if integrator is not None:
        if isinstance(integrator, str):
            integrator = {"type": integrator}
        if isinstance(integrator, dict):
            integrator = load_dict(integrator)
        if not isinstance(integrator, Plugin) or integrator.kind != "integrator":
            raise TypeError(f"integrator must be an integrator's name, dictionary or Plugin, got {integrator!r}")
        xml, _ = scene_xml({"type": "scene", "integrator": integrator.dictionary})
        integrator_xml = xml
    buffer = _candela.render(scene, int(spp or 0), int(seed), int(threads or 0), integrator_xml, progress, list(aovs or []))
    return Image(buffer)


def variants() -> list[str]:
    """Candela renders in RGB on the CPU (Mitsuba's scalar_rgb)."""
    return ["scalar_rgb"]


class Viewer:
    """The live viewer of a scene (``candela.view``): a local web server showing the path tracer
    and the raster mode side by side (docs/viewer.md). In Jupyter the object shows the page in
    the output cell; ``url`` opens it in any browser; ``stop()`` ends it."""

    def __init__(self, handle):
        self._handle = handle

    @property
    def url(self) -> str:
        return self._handle.url

    @property
    def port(self) -> int:
        return self._handle.port

    def stop(self):
        self._handle.stop()

    def _repr_html_(self):
        return f'<iframe src="{self.url}" width="100%" height="640" style="border:0"></iframe><p><a href="{self.url}">{self.url}</a></p>'

    def __repr__(self):
        return f"candela.Viewer({self.url})"


def view(scene: Scene, port: int = 0, bind: str = "127.0.0.1") -> Viewer:
    """Serves the scene live to a browser, as ``candela view`` does (port 0: a free one); returns
    the Viewer, whose ``url`` carries the access token. Binds to this machine only by default."""
    if not isinstance(scene, Scene):
        raise TypeError(f"view expects a candela.Scene, got {type(scene).__name__}")
    if not isinstance(port, int) or not 0 <= port <= 65535:
        raise ValueError(f"port must lie between 0 and 65535 (got {port!r})")
    return Viewer(_candela.start_viewer(scene, port, bind))
