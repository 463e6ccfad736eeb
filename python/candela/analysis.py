"""What the command line's verification commands do, as functions that return dictionaries and
arrays: compare (candela compare), converge, validate, estimate, compare-modes."""

from __future__ import annotations

import os

import numpy as np

from . import _candela
from .image import Image


def _buffer(image, name):
    if isinstance(image, (str, os.PathLike)):
        return _candela.read_image(os.fspath(image))
    if not isinstance(image, Image):
        image = Image(image)
    return _candela.ImageBuffer(np.ascontiguousarray(image, dtype=np.float32), list(image.channels), dict(image.metadata))


def compare(test, reference, block_size: int = 16, heatmap_range: float = 0.1) -> dict:
    """Compares a render with a reference (arrays, Images or EXR paths): rmse, relmse, mare,
    block_mare (16 x 16 blocks), the per-channel means and their relative difference, whether
    they agree by the validation criteria (``agree``, ``reason``) and the relative-difference
    ``heatmap`` (an Image)."""
    if block_size < 1:
        raise ValueError("block_size must be at least 1")
    result = _candela.compare(_buffer(test, "test"), _buffer(reference, "reference"), int(block_size), float(heatmap_range))
    result["heatmap"] = Image(result["heatmap"])
    for key in ("mean_test", "mean_reference", "mean_relative_difference"):
        result[key] = np.asarray(result[key], dtype=np.float64)
    return result


def converge(scene, spp=(4, 16, 64, 256), expected: float | None = None, reference=None, seed: int = 0, threads: int = 0) -> dict:
    """Renders the scene at each sample count (count i with seed + i) and measures its error
    against `expected` (every pixel's exact value; by default the scene's own "expected" parameter,
    as analytic scenes state it) or a `reference` image: per count its RMSE with a standard error,
    relMSE and bias; the fitted log-log slope (-1/2 for an unbiased estimator), ``converges`` and
    the ``failures`` as ``candela converge`` judges them, and the ``plot``."""
    if expected is None and reference is None and "expected" in scene.parameters:
        expected = _candela.evaluate_expression(scene.parameters["expected"])
    if (expected is None) == (reference is None):
        raise ValueError("converge needs exactly one of expected (a number; or a scene with an \"expected\" parameter) and reference")
    counts = [int(n) for n in spp]
    if not counts or min(counts) < 1:
        raise ValueError("spp: sample counts of at least 1")
    ref = _buffer(reference, "reference") if reference is not None else None
    result = _candela.converge(scene, counts, None if expected is None else float(expected), ref, int(seed), int(threads))
    if "plot" in result:
        result["plot"] = Image(result["plot"])
    return result


def validate(scene_path, reference_path, spp: int = 0, reference_spp: int = 2048, threads: int = 0,
             variant: str = "scalar_rgb") -> dict:
    """Renders a scene file and compares it with its reference EXR as ``candela validate`` does:
    the metrics, ``passed`` and the ``reason``, and the per-pixel z-test's counts. ``variant``:
    the variant the scene is loaded in (``--variant``; see candela.variants())."""
    if not isinstance(variant, str):
        raise TypeError(f"variant must be a variant's name (a str), got {variant!r}")
    return _candela.validate(os.fspath(scene_path), os.fspath(reference_path), int(spp), int(reference_spp), int(threads),
                             variant)


def estimate_irradiance(scene, points, normals, samples: int = 65536, seed: int = 0, threads: int = 0, max_depth: int = -1) -> dict:
    """The irradiance (W m^-2) at N points facing `normals` (N x 3 arrays), each from `samples`
    independent paths: ``mean`` and ``std_error`` (N x 3), and ``ci95_low`` / ``ci95_high`` (the
    mean -/+ 1.96 standard errors)."""
    p = np.atleast_2d(np.asarray(points, dtype=np.float32))
    n = np.atleast_2d(np.asarray(normals, dtype=np.float32))
    result = _candela.estimate_irradiance(scene, p, n, int(samples), int(seed), int(threads), int(max_depth))
    result["ci95_low"] = result["mean"] - 1.96 * result["std_error"]
    result["ci95_high"] = result["mean"] + 1.96 * result["std_error"]
    return result


def estimate_radiance(scene, origin, direction, samples: int = 65536, seed: int = 0, threads: int = 0, max_depth: int = -1) -> dict:
    """The radiance arriving at `origin` from `direction`: ``mean`` and ``std_error`` (RGB) and
    the 95% interval."""
    result = _candela.estimate_radiance(scene, [float(x) for x in origin], [float(x) for x in direction], int(samples), int(seed),
                                        int(threads), int(max_depth))
    mean, error = np.asarray(result["mean"]), np.asarray(result["std_error"])
    result.update(mean=mean, std_error=error, ci95_low=mean - 1.96 * error, ci95_high=mean + 1.96 * error)
    return result


def compare_modes(scene, methods=None, spp: int = 0, reference=None, reference_spp: int = 1024,
                  threads: int = 0, heatmap_range: float = 0.5) -> dict:
    """Renders the scene by several methods (``candela compare-modes``: integrator names with
    ``:key=value`` parameters, ``raster-gi``, ``baked``) and compares each with a converged
    path-traced reference (or `reference`, an image): per method its ``image``, time, relMSE,
    MARE, block MARE, mean luminance difference and ``heatmap``; the Markdown ``table``, the
    contact ``sheet`` and the ``reference``. ``methods=None`` compares the command's default list
    (raster, baked, radiosity, path)."""
    if methods is None:
        methods = _candela.default_compared_methods
    if isinstance(methods, (list, tuple)):
        methods = ",".join(methods)
    ref = _buffer(reference, "reference") if reference is not None else None
    result = _candela.compare_modes(scene, str(methods), int(spp), ref, int(reference_spp), int(threads), float(heatmap_range))
    for m in result["methods"]:
        m["image"], m["heatmap"] = Image(m["image"]), Image(m["heatmap"])
    result["sheet"], result["reference"] = Image(result["sheet"]), Image(result["reference"])
    return result
