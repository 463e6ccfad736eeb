"""4x4 affine transforms as the scene format composes them (``<translate>``, ``<rotate>``,
``<scale>``, ``<lookat>``, ``<matrix>``), for ``load_dict`` and ``traverse``.

``Transform`` follows Mitsuba 3's ``ScalarTransform4f``: its builders work both on the class, as
in Mitsuba before 3.6 (``T.translate([0, 0, 1])`` is a translation), and on a transform, as in
3.6 and later (``T().translate(...).scale(...)`` is the transform followed by ... : each builder
multiplies on the right, so the last one written applies first to points). Products ``a @ b`` and
``a * b`` compose; ``t @ point`` maps a point. Angles are in degrees.
"""

from __future__ import annotations

import math

import numpy as np


class _Builder:
    """A method usable on the class (a new transform) and on an instance (instance @ new)."""

    def __init__(self, make):
        self.make = make
        self.__doc__ = make.__doc__

    def __get__(self, instance, owner):
        def build(*args, **kwargs):
            m = owner(self.make(*args, **kwargs))
            return m if instance is None else owner(instance.matrix @ m.matrix)

        build.__doc__ = self.make.__doc__
        return build


def _vector(v, default=None):
    if v is None:
        return default
    if np.isscalar(v):
        return np.array([float(v)] * 3)
    a = np.asarray(v, dtype=float).reshape(-1)
    if a.size != 3:
        raise ValueError(f"expected three numbers, got {v!r}")
    return a


class Transform:
    """An affine transform of 3D points, stored as a 4x4 matrix (float64, row-major)."""

    def __init__(self, matrix=None):
        if matrix is None:
            self.matrix = np.identity(4)
        else:
            m = getattr(matrix, "matrix", matrix)
            self.matrix = np.array(m, dtype=float).reshape(4, 4)

    # --- builders -------------------------------------------------------------------------------
    def _translate(v):
        """A translation by v (three numbers)."""
        m = np.identity(4)
        m[:3, 3] = _vector(v)
        return m

    def _scale(v):
        """A scale by v (one number, or three)."""
        return np.diag(list(_vector(v)) + [1.0])

    def _rotate(axis, angle):
        """A rotation by `angle` degrees about `axis` (right-handed, as <rotate>)."""
        a = _vector(axis)
        a = a / np.linalg.norm(a)
        t = math.radians(float(angle))
        c, s = math.cos(t), math.sin(t)
        # Exact values at multiples of 90 degrees keep axis-aligned scenes axis-aligned (as <rotate>).
        s = 0.0 if abs(s) < 1e-7 else s
        c = 0.0 if abs(c) < 1e-7 else c
        x, y, z = a
        r = np.array([[c + x * x * (1 - c), x * y * (1 - c) - z * s, x * z * (1 - c) + y * s],
                      [y * x * (1 - c) + z * s, c + y * y * (1 - c), y * z * (1 - c) - x * s],
                      [z * x * (1 - c) - y * s, z * y * (1 - c) + x * s, c + z * z * (1 - c)]])
        m = np.identity(4)
        m[:3, :3] = r
        return m

    def _look_at(origin, target, up):
        """The camera-to-world transform of a camera at `origin` looking at `target` (as <lookat>:
        the camera looks along +z, x points left, y up)."""
        o, t, u = _vector(origin), _vector(target), _vector(up)
        d = t - o
        d = d / np.linalg.norm(d)
        left = np.cross(u, d)
        if np.linalg.norm(left) == 0:
            raise ValueError("look_at: up is parallel to the view direction")
        left = left / np.linalg.norm(left)
        new_up = np.cross(d, left)
        m = np.identity(4)
        m[:3, 0], m[:3, 1], m[:3, 2], m[:3, 3] = left, new_up, d, o
        return m

    def _perspective(fov, near, far):
        """Mitsuba's perspective projection (fov in degrees)."""
        recip = 1.0 / (far - near)
        cot = 1.0 / math.tan(math.radians(float(fov)) / 2.0)
        m = np.diag([cot, cot, far * recip, 0.0])
        m[2, 3] = -near * far * recip
        m[3, 2] = 1.0
        return m

    def _orthographic(near, far):
        """Mitsuba's orthographic projection: z from [near, far] to [0, 1], x and y unchanged."""
        m = np.diag([1.0, 1.0, 1.0 / (far - near), 1.0])
        m[2, 3] = -near / (far - near)
        return m

    translate = _Builder(_translate)
    scale = _Builder(_scale)
    rotate = _Builder(_rotate)
    look_at = _Builder(_look_at)
    perspective = _Builder(_perspective)
    orthographic = _Builder(_orthographic)

    # --- algebra --------------------------------------------------------------------------------
    def __matmul__(self, other):
        if isinstance(other, Transform):
            return type(self)(self.matrix @ other.matrix)
        p = np.asarray(other, dtype=float)
        if p.shape == (3,):
            # Three numbers are a point, unless they say they are a vector or a normal
            # (candela.mitsuba's Vector3f, Normal3f): a vector takes no translation, a normal the
            # inverse transpose, as in Mitsuba.
            kind = getattr(other, "_candela_kind", "point")
            if kind == "vector":
                q = self.matrix[:3, :3] @ p
            elif kind == "normal":
                q = np.linalg.inv(self.matrix[:3, :3]).T @ p
            else:
                h = self.matrix @ np.append(p, 1.0)
                q = h[:3] / h[3]
            if isinstance(other, np.ndarray) and type(other) is not np.ndarray:
                return q.view(type(other))
            return q
        return type(self)(self.matrix @ np.asarray(other, dtype=float).reshape(4, 4))

    def __mul__(self, other):
        return self.__matmul__(other)

    def inverse(self) -> "Transform":
        return Transform(np.linalg.inv(self.matrix))

    @property
    def inverse_transpose(self) -> np.ndarray:
        """The inverse transpose of the matrix (4x4), which maps normals."""
        return np.linalg.inv(self.matrix).T

    def translation(self) -> np.ndarray:
        """The translation: the last column's first three numbers."""
        return self.matrix[:3, 3].copy()

    def has_scale(self) -> bool:
        """Whether the upper-left 3x3 part scales or shears: M M^T differs from the identity by
        more than 1e-3 somewhere (Mitsuba's test; rotations and reflections have none)."""
        m = self.matrix[:3, :3]
        return bool(np.any(np.abs(m @ m.T - np.identity(3)) > 1e-3))

    def transform_affine(self, point):
        return self @ point

    def __eq__(self, other):
        return isinstance(other, Transform) and np.array_equal(self.matrix, other.matrix)

    def __array__(self, dtype=None):
        return self.matrix if dtype is None else self.matrix.astype(dtype)

    def __repr__(self):
        rows = "\n ".join(np.array2string(r, precision=6, suppress_small=True) for r in self.matrix)
        return f"[{rows}]"
