"""Scalar algebra of the reference recursion: operands are Python floats (constants;
0.0 means "structurally zero", and terms with such a factor are skipped) or arrays of
configurations; vectors are triples of them, symmetric matrices sextuples (xx, yy, zz,
xy, yz, xz)."""
from __future__ import annotations

from typing import Union

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]
Scalar = Union[float, FloatArray]  # a Python float (constant, possibly exactly 0) or an array
Vec = tuple  # three Scalars


def _zero(x: Scalar) -> bool:
    return isinstance(x, float) and x == 0.0


def _add(a: Scalar, b: Scalar) -> Scalar:
    if _zero(a):
        return b
    if _zero(b):
        return a
    return a + b


def _sub(a: Scalar, b: Scalar) -> Scalar:
    if _zero(b):
        return a
    if _zero(a):
        return -b
    return a - b


def _mul(a: Scalar, b: Scalar) -> Scalar:
    if _zero(a) or _zero(b):
        return 0.0
    if isinstance(a, float) and a in (1.0, -1.0):
        return b if a == 1.0 else -b
    if isinstance(b, float) and b in (1.0, -1.0):
        return a if b == 1.0 else -a
    return a * b


def _sum(*terms: Scalar) -> Scalar:
    out: Scalar = 0.0
    for t in terms:
        out = _add(out, t)
    return out


def _vadd(a: Vec, b: Vec) -> Vec:
    return (_add(a[0], b[0]), _add(a[1], b[1]), _add(a[2], b[2]))


def _vsub(a: Vec, b: Vec) -> Vec:
    return (_sub(a[0], b[0]), _sub(a[1], b[1]), _sub(a[2], b[2]))


def _scale(s: Scalar, v: Vec) -> Vec:
    return (_mul(s, v[0]), _mul(s, v[1]), _mul(s, v[2]))


def _dot(a: Vec, b: Vec) -> Scalar:
    return _sum(_mul(a[0], b[0]), _mul(a[1], b[1]), _mul(a[2], b[2]))


def _cross(a: Vec, b: Vec) -> Vec:
    return (
        _sub(_mul(a[1], b[2]), _mul(a[2], b[1])),
        _sub(_mul(a[2], b[0]), _mul(a[0], b[2])),
        _sub(_mul(a[0], b[1]), _mul(a[1], b[0])),
    )


def _matvec(m: tuple, v: Vec) -> Vec:
    return tuple(_sum(_mul(m[r][0], v[0]), _mul(m[r][1], v[1]), _mul(m[r][2], v[2])) for r in range(3))


def _sym_matvec(s: tuple, v: Vec) -> Vec:
    """Symmetric matrix (xx, yy, zz, xy, yz, xz) times v."""
    xx, yy, zz, xy, yz, xz = s
    return (
        _sum(_mul(xx, v[0]), _mul(xy, v[1]), _mul(xz, v[2])),
        _sum(_mul(xy, v[0]), _mul(yy, v[1]), _mul(yz, v[2])),
        _sum(_mul(xz, v[0]), _mul(yz, v[1]), _mul(zz, v[2])),
    )


def _rot_z(v: Vec, c: Scalar, s: Scalar) -> Vec:
    """Rz(θ) v."""
    return (_sub(_mul(c, v[0]), _mul(s, v[1])), _add(_mul(s, v[0]), _mul(c, v[1])), v[2])


def _rot_z_t(v: Vec, c: Scalar, s: Scalar) -> Vec:
    """Rz(θ)ᵀ v."""
    return (_add(_mul(c, v[0]), _mul(s, v[1])), _sub(_mul(c, v[1]), _mul(s, v[0])), v[2])


def _rot_x(v: Vec, c: float, s: float) -> Vec:
    """Rx(α) v."""
    return (v[0], _sub(_mul(c, v[1]), _mul(s, v[2])), _add(_mul(s, v[1]), _mul(c, v[2])))


def _rot_x_t(v: Vec, c: float, s: float) -> Vec:
    """Rx(α)ᵀ v."""
    return (v[0], _add(_mul(c, v[1]), _mul(s, v[2])), _sub(_mul(c, v[2]), _mul(s, v[1])))


def _rot_sym_z(m: tuple, c: Scalar, s: Scalar) -> tuple:
    """Rz(θ) S Rz(θ)ᵀ of a symmetric S = (xx, yy, zz, xy, yz, xz)."""
    xx, yy, zz, xy, yz, xz = m
    c2, s2 = _sub(_mul(c, c), _mul(s, s)), _mul(2.0, _mul(c, s))
    mean, half = _mul(0.5, _add(xx, yy)), _mul(0.5, _sub(xx, yy))
    t = _sub(_mul(half, c2), _mul(xy, s2))
    return (
        _add(mean, t),
        _sub(mean, t),
        zz,
        _add(_mul(half, s2), _mul(xy, c2)),
        _add(_mul(s, xz), _mul(c, yz)),
        _sub(_mul(c, xz), _mul(s, yz)),
    )


def _rot_sym_x(m: tuple, c: float, s: float) -> tuple:
    """Rx(α) S Rx(α)ᵀ of a symmetric S = (xx, yy, zz, xy, yz, xz)."""
    xx, yy, zz, xy, yz, xz = m
    c2, s2 = c * c - s * s, 2.0 * c * s
    mean, half = _mul(0.5, _add(yy, zz)), _mul(0.5, _sub(yy, zz))
    t = _sub(_mul(half, c2), _mul(yz, s2))
    return (
        xx,
        _add(mean, t),
        _sub(mean, t),
        _sub(_mul(c, xy), _mul(s, xz)),
        _add(_mul(half, s2), _mul(yz, c2)),
        _add(_mul(s, xy), _mul(c, xz)),
    )
