"""Candela from Python: load Mitsuba 3 scenes (files, strings, dictionaries), render them to NumPy
images, edit their parameters and render again, and check renders against references.

    import candela
    scene = candela.load_file("scenes/cbox.xml", spp=64)
    image = candela.render(scene)          # H x W x 3 float32, a NumPy array
    params = candela.traverse(scene)
    params["red.reflectance.value"] = [0.2, 0.6, 0.2]
    params.update()
    image2 = candela.render(scene, seed=1)
    spectral = candela.load_file("scenes/cbox.xml", variant="scalar_spectral")

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
from ._dict import DictError, Plugin, TemporaryFiles, plugin_scene, scene_xml
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


# The variants Candela renders, by Mitsuba 3's names (core/variant.h; docs/python.md "Variants").
_VARIANTS = ("scalar_rgb", "scalar_spectral")
_DEFAULT_VARIANT = "scalar_rgb"


def _variant_argument(variant) -> str:
    """The variant name a loader was given (None: the default). The native loader refuses a name
    that is no variant Candela renders with InputError."""
    if variant is None:
        return _DEFAULT_VARIANT
    if not isinstance(variant, str):
        raise TypeError(f"variant must be a variant's name (a str, one of {', '.join(_VARIANTS)}), got {variant!r}")
    return variant


def _sensor_argument(sensor) -> int:
    """The sensor index a loader was given (None: 0, the file's first sensor)."""
    if sensor is None:
        return 0
    if isinstance(sensor, bool) or not isinstance(sensor, (int, np.integer)) or sensor < 0:
        raise ValueError(f"sensor must be a sensor's index, a whole number from 0 (got {sensor!r})")
    return int(sensor)


def _check_no_keyword_parameter(scene: Scene, variant, sensor=None) -> Scene:
    """`variant=` chooses the rendering variant and `sensor=` the sensor, never a scene parameter:
    a scene that declares a `$variant` or `$sensor` parameter of its own, loaded with that keyword
    given, is refused rather than read one way silently."""
    for name, value, means in (("variant", variant, "the rendering variant (candela.variants())"),
                               ("sensor", sensor, "which of the scene's sensors to render")):
        if value is not None and name in scene.parameters:
            raise InputError(f"the scene declares a parameter named '{name}', and {name}={value!r} was given: the "
                             f"keyword chooses {means}, not the scene's parameter, which keeps its <default>; "
                             "rename the parameter to set it from Python")
    return scene


def load_file(path, *, variant: str | None = None, sensor: int | None = None, **params) -> Scene:
    """Loads a Mitsuba 3 XML scene; keyword arguments set its ``$name`` parameters
    (``load_file("cbox.xml", spp=64, res=256)``). Errors raise SceneError with ``file:line``.
    ``variant`` (keyword only; default scalar_rgb) is the variant to load it in: one of
    candela.variants(); a plugin that does not render in it raises SceneError at its line.
    ``sensor`` (keyword only; default 0) is which of the file's sensors the scene renders, counted
    in file order (``candela render -s N``). Neither is ever a scene parameter (see
    _check_no_keyword_parameter)."""
    scene = _candela.load_file(os.fspath(path), _parameters(params), _variant_argument(variant), _sensor_argument(sensor))
    return _check_no_keyword_parameter(scene, variant, sensor)


def load_string(xml: str, *, variant: str | None = None, sensor: int | None = None, **params) -> Scene:
    """Loads a scene from XML text; files it names are found relative to the working directory.
    ``variant`` and ``sensor`` as in load_file."""
    if not isinstance(xml, str):
        raise TypeError(f"load_string expects XML text (a str), got {type(xml).__name__}")
    scene = _candela.load_string(xml, os.path.join(os.getcwd(), "<string>.xml"), _parameters(params), _variant_argument(variant),
                                 _sensor_argument(sensor))
    return _check_no_keyword_parameter(scene, variant, sensor)


def load_dict(d: dict, *, variant: str | None = None, sensor: int | None = None, **params):
    """Loads a scene from Mitsuba 3's dictionary format (``{'type': 'scene', ...}``). A dictionary
    of another plugin (``{'type': 'path', 'max_depth': 8}``) is checked and returned as a Plugin,
    for ``render(..., integrator=...)`` or as a value in another dictionary. Errors raise
    SceneError naming the key path (``sphere.bsdf.reflectance: ...``). ``variant`` as in
    load_file (a plugin is checked in it), and ``sensor`` for a scene."""
    name = _variant_argument(variant)
    if isinstance(d, dict) and d.get("type") != "scene":
        kind, holder = plugin_scene(d)
        if holder is not None:
            _load_dict_scene(holder, {}, name, prefix_strip="object")
        return Plugin(d, kind)
    return _check_no_keyword_parameter(_load_dict_scene(d, params, name, sensor=_sensor_argument(sensor)), variant, sensor)


def _load_dict_scene(d: dict, params: dict, variant: str, prefix_strip: str | None = None, sensor: int = 0) -> Scene:
    # Images held in memory are written to temporary files for the loader, removed once it is done.
    files = TemporaryFiles()
    try:
        xml, paths = scene_xml(d, files)
        virtual = os.path.join(os.getcwd(), "<dict>.xml")
        try:
            return _candela.load_string(xml, virtual, _parameters(params), variant, sensor)
        except SceneError as e:
            line = getattr(e, "line", 0)
            path = paths[line - 1] if 0 < line <= len(paths) else ""
            if prefix_strip and (path == prefix_strip or path.startswith(prefix_strip + ".")):
                path = path[len(prefix_strip) + 1:]
            where = path if path else "<dict>"
            raise SceneError(f"{where}: {e.message}", where, 0, e.message) from None
    finally:
        files.remove()


def render(scene: Scene, spp: int | None = None, seed: int = 0, sensor: int | None = None, threads: int | None = None, integrator=None,
           progress=None, aovs=None) -> Image:
    """Renders the scene with its integrator (or `integrator`: a plugin name, a dictionary or a
    Plugin) and returns the image. ``spp`` overrides the sampler's count (rounded as the sampler
    rounds it), ``seed`` is the render's seed. The pixels are bit-identical to ``candela render``
    with the same scene, spp and seed. The GIL is released while rendering; Ctrl-C raises
    KeyboardInterrupt within a second. ``progress(fraction)`` is called from the calling thread
    about ten times a second. ``aovs``: extra layers, as ``--aov`` (albedo, normal, depth,
    variance, samples). ``sensor``: the scene renders the sensor it was loaded with (load_file's
    ``sensor=``); another index is a ValueError that says so."""
    if not isinstance(scene, Scene):
        raise TypeError(f"render expects a candela.Scene, got {type(scene).__name__}")
    if spp is not None and (isinstance(spp, bool) or not isinstance(spp, (int, np.integer)) or not 1 <= spp <= 1 << 30):
        raise ValueError(f"spp must be a whole number of samples, 1 to 2^30 (got {spp!r})")
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or not 0 <= seed < 1 << 64:
        raise ValueError(f"seed must be a whole number, 0 to 2^64 - 1 (got {seed!r})")
    if sensor is not None and sensor != scene.sensor_index:
        raise ValueError(f"the scene was loaded to render sensor {scene.sensor_index} (of {scene.sensor_count}); sensor={sensor!r} "
                         f"needs the scene loaded with sensor={sensor!r} (load_file, load_string and load_dict take it)")
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
    try:
        buffer = _candela.render(scene, int(spp or 0), int(seed), int(threads or 0), integrator_xml, progress, list(aovs or []))
    except SceneError as e:
        # The integrator is loaded again in the scene's variant, which may refuse it: said at the
        # argument, as load_dict says a key path.
        if integrator_xml and e.file.endswith("<integrator>.xml"):
            raise SceneError(f"integrator: {e.message}", "integrator", 0, e.message) from None
        raise
    return Image(buffer)


def variants() -> list[str]:
    """The variants Candela renders, by Mitsuba 3's names, all on the CPU: scalar_rgb (linear
    Rec. 709 RGB, the default) and scalar_spectral (wavelengths sampled per path, developed to
    RGB). load_file, load_string and load_dict take one as ``variant=``."""
    return list(_VARIANTS)


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
