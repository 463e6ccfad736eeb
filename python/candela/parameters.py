"""A scene's editable parameters by Mitsuba 3's names (``candela.traverse(scene)``), changed
without reloading the scene: assign values, then ``update()``.

    params = candela.traverse(scene)
    params["red.reflectance.value"] = [0.2, 0.6, 0.2]      # a colour: three numbers
    params["PerspectiveCamera.x_fov"] = 30.0                # a float
    params["sensor.to_world"] = candela.Transform.look_at([0, 0, 4], [0, 0, 0], [0, 1, 0])
    v = params["teapot.vertex_positions"]                    # N * 3 numbers, world space
    params["teapot.vertex_positions"] = v + 0.1              # the BVH is rebuilt on update()
    params.update()

Values read back as floats (a Float), NumPy arrays of 3 (a Color) or of N (Floats), and
``candela.Transform`` (a Transform). Assignments are checked (names, sizes, finiteness) and
applied together by ``update()``, which brings every changed object up to date once.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from . import _candela
from .transform import Transform


class SceneParameters(Mapping):
    """A mapping from parameter names to values, with pending changes applied by update()."""

    def __init__(self, scene):
        self._scene = scene
        self._types = dict(_candela.parameter_list(scene))
        self._pending: dict[str, np.ndarray] = {}

    def keys(self):
        return self._types.keys()

    def __iter__(self):
        return iter(self._types)

    def __len__(self):
        return len(self._types)

    def __contains__(self, name):
        return name in self._types

    def items(self):
        return [(k, self[k]) for k in self._types]

    def __delitem__(self, name: str):
        """Removes a parameter from this view (the scene keeps it; an assignment made before is
        still applied by update())."""
        del self._types[self._check(name)]

    def copy(self):
        """Another view of the same scene with the same names (without pending assignments)."""
        other = type(self)(self._scene)
        other._types = dict(self._types)
        return other

    def type(self, name: str) -> str:
        """float, color, transform or floats."""
        return self._types[self._check(name)]

    def _check(self, name):
        if name not in self._types:
            close = [k for k in self._types if k.split(".")[-1] == str(name).split(".")[-1]]
            hint = f"; did you mean {close[0]!r}?" if close else ""
            raise KeyError(f"the scene has no parameter {name!r}{hint}")
        return name

    def __getitem__(self, name: str):
        kind = self._types[self._check(name)]
        values = self._pending.get(name)
        if values is None:
            values = _candela.get_parameter(self._scene, name)
        if kind == "float":
            return float(values[0])
        if kind == "transform":
            return Transform(np.asarray(values, dtype=float).reshape(4, 4))
        return np.array(values, dtype=np.float32)

    def __setitem__(self, name: str, value):
        kind = self._types[self._check(name)]
        if isinstance(value, Transform) or hasattr(value, "matrix"):
            value = getattr(value, "matrix")
        a = np.asarray(value, dtype=np.float64).reshape(-1)
        if kind == "color" and a.size == 1:
            a = np.repeat(a, 3)
        expected = {"float": 1, "color": 3, "transform": 16}.get(kind)
        if expected is not None and a.size != expected:
            raise ValueError(f"{name} is a {kind} ({expected} numbers), got {a.size}")
        if not np.all(np.isfinite(a)):
            raise ValueError(f"{name}: the value must be finite")
        self._pending[name] = a.astype(np.float32)

    def update(self, values=None) -> list[str]:
        """Assigns `values` (a mapping; names this view does not have are ignored, as in Mitsuba),
        then applies the assignments since the last update; returns the names it changed."""
        if values is not None:
            for name, value in values.items():
                if name in self:
                    self[name] = value
        changed = list(self._pending)
        if changed:
            _candela.set_parameters(self._scene, self._pending)
        self._pending = {}
        return changed

    def __repr__(self):
        rows = "\n".join(f"  {k:<40} {t}" for k, t in self._types.items())
        return f"SceneParameters[\n{rows}\n]"


def traverse(scene) -> SceneParameters:
    """The scene's editable parameters (Mitsuba's traverse)."""
    if not isinstance(scene, _candela.Scene):
        raise TypeError(f"traverse expects a candela.Scene, got {type(scene).__name__}")
    return SceneParameters(scene)
