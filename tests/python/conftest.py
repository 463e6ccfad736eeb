"""Shared set-up of the Python package's tests.

CANDELA_PYTHON_DIR: the folder that holds the built package (default: build/python of this
checkout); CANDELA_BINARY: the `candela` command (default: build/candela). Both are set by ctest.
"""

from __future__ import annotations

import math
import os
import re
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[2]
PYTHON_DIR = Path(os.environ.get("CANDELA_PYTHON_DIR", REPO / "build" / "python"))
BINARY = Path(os.environ.get("CANDELA_BINARY", REPO / "build" / "candela"))
SCENES = REPO / "scenes"

if str(PYTHON_DIR) not in sys.path:
    sys.path.insert(0, str(PYTHON_DIR))


def _import_candela():
    # The native module may be in the middle of being rebuilt (the linker replaces the file): try
    # again for a little while before giving up.
    deadline = time.monotonic() + 60
    while True:
        try:
            import candela  # noqa: F401

            return candela
        except ImportError:
            if time.monotonic() > deadline:
                raise
            for name in [m for m in sys.modules if m == "candela" or m.startswith("candela.")]:
                del sys.modules[name]
            time.sleep(2)


candela = _import_candela()

# The z score of the statistical checks: a check of an unbiased estimate against its exact value
# fails by chance with probability 2 * (1 - Phi(4.5)) = 7e-6.
Z = 4.5


def subprocess_env() -> dict:
    """The environment for a child Python that imports the package under test."""
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([str(PYTHON_DIR)] + ([env["PYTHONPATH"]] if env.get("PYTHONPATH") else []))
    env["PYTHONDONTWRITEBYTECODE"] = "1"
    return env


def run_cli(*args, cwd=None, timeout=120) -> subprocess.CompletedProcess:
    """Runs the candela command; fails the test with its output if it fails."""
    result = subprocess.run([str(BINARY), *map(str, args)], cwd=cwd, capture_output=True, text=True, timeout=timeout)
    if result.returncode != 0:
        pytest.fail(f"candela {' '.join(map(str, args))} exited {result.returncode}:\n{result.stdout}\n{result.stderr}")
    return result


def cli_render(scene, output, spp, seed, params=None, extra=()):
    """`candela render SCENE -o OUTPUT --spp N --seed S -D name=value ...`, read back as an Image."""
    defines = []
    for name, value in (params or {}).items():
        defines += ["-D", f"{name}={value}"]
    run_cli("render", scene, "-o", output, "--spp", spp, "--seed", seed, "-q", *defines, *extra)
    return candela.read_image(output)


def scene_expected(path, **params) -> float:
    """The exact pixel value a furnace scene states in its `expected` default, evaluated with its
    defaults overridden by `params` (the expression language of the scene format: $name, + - * /,
    ^, parentheses, pi)."""
    text = Path(path).read_text()
    defaults = dict(re.findall(r'<default\s+name="([^"]+)"\s+value="([^"]*)"\s*/>', text))
    values = {k: str(v) for k, v in defaults.items()}
    values.update({k: str(v) for k, v in params.items()})
    expression = values["expected"]
    for _ in range(8):
        expression = re.sub(r"\$([A-Za-z_][A-Za-z0-9_]*)", lambda m: f"({values[m.group(1)]})", expression)
    if not re.fullmatch(r"[0-9eE.+\-*/^() pi]*", expression):
        raise ValueError(f"{path}: cannot evaluate expected = {expression!r}")
    return float(eval(expression.replace("^", "**"), {"__builtins__": {}}, {"pi": math.pi}))


def assert_mean_agrees(image, expected: float, what: str = "image"):
    """The image's mean over pixels and channels is an unbiased estimate of `expected` (every
    pixel's exact value): it must lie within Z standard errors, the standard error taken from the
    pixels' spread (each pixel is an independent estimate). A float32 rounding allowance of 1e-5
    relative keeps exact renders (zero spread) from failing on the last bits."""
    x = np.asarray(image, dtype=np.float64)[:, :, :3]
    per_pixel = x.mean(axis=2).reshape(-1)
    mean = per_pixel.mean()
    se = per_pixel.std(ddof=1) / math.sqrt(per_pixel.size)
    allowance = Z * se + 1e-5 * abs(expected)
    assert abs(mean - expected) <= allowance, f"{what}: mean {mean} vs exact {expected} (standard error {se})"


@pytest.fixture(scope="session")
def repo() -> Path:
    return REPO


@pytest.fixture(scope="session")
def scenes() -> Path:
    return SCENES


def assert_same_expectation(a, b, what: str = "images"):
    """Two renders of the same scene set up two ways (e.g. edited in Python and loaded from an
    edited file) estimate the same image: the mean of their per-pixel differences is within Z
    standard errors of 0, the standard error from the differences' spread (a paired test: both
    renders use the same random numbers, so the difference is 0 where they agree exactly). A
    float32 rounding allowance of 1e-5 of the image mean covers setups that round differently."""
    x = np.asarray(a, dtype=np.float64)[:, :, :3].mean(axis=2).reshape(-1)
    y = np.asarray(b, dtype=np.float64)[:, :, :3].mean(axis=2).reshape(-1)
    d = x - y
    se = d.std(ddof=1) / math.sqrt(d.size)
    assert abs(d.mean()) <= Z * se + 1e-5 * abs(y.mean()), f"{what}: mean difference {d.mean()} (standard error {se})"
