"""The compiled atan2 of robot_sim.kernels.atan2 against the C library's ``math.atan2``
(IBM's correctly rounded one in glibc): within 1 ulp on 10⁶ pairs spread over quadrants,
octants, magnitudes, ratios near the table's grid and near the axes; equal, signed zeros
included, on the special values; a row at once equal to it; and the fused multiply-add it
is built on rounds once."""
from __future__ import annotations

import math

import numba
import numpy as np

from robot_sim.kernels.atan2 import STEPS, atan2, atan2_row, fma


@numba.njit(cache=False, error_model="numpy")  # as the package compiles (JIT)
def _atan2_all(y: np.ndarray, x: np.ndarray) -> np.ndarray:
    out = np.empty(y.shape[0])
    for i in range(y.shape[0]):
        out[i] = atan2(y[i], x[i])
    return out


@numba.njit(cache=False, error_model="numpy")  # as the package compiles (JIT)
def _rows(Y: np.ndarray, X: np.ndarray, m: int) -> np.ndarray:
    out = np.full(Y.shape, -7.0)
    for r in range(Y.shape[0]):
        atan2_row(Y, r, X, r, out, r, m)
    return out


@numba.njit(cache=False, error_model="numpy")  # as the package compiles (JIT)
def _fma(a: float, b: float, c: float) -> float:
    return fma(a, b, c)


def _ordered(a: np.ndarray) -> np.ndarray:
    """Doubles as integers in the order of the doubles (adjacent doubles differ by 1)."""
    bits = a.view(np.int64)
    return np.where(bits < 0, -(bits & 0x7FFFFFFFFFFFFFFF), bits)


def _pairs(rng: np.random.Generator, n: int) -> tuple[np.ndarray, np.ndarray]:
    sign = rng.choice([-1.0, 1.0], size=(2, 6, n))
    x = sign[1] * rng.uniform(0.1, 10.0, (6, n))
    ys, xs = [rng.normal(size=n)], [rng.normal(size=n)]
    e = rng.uniform(-1074, 1023, size=(2, n))  # every magnitude, the C library's range included
    ys.append(sign[0, 0] * 2.0 ** e[0] * rng.uniform(1, 2, n))
    xs.append(sign[1, 0] * 2.0 ** e[1] * rng.uniform(1, 2, n))
    e = rng.uniform(-30, 30, size=(2, n))
    ys.append(sign[0, 1] * 2.0 ** e[0])
    xs.append(sign[1, 1] * 2.0 ** e[1])
    small = rng.uniform(0.0, 3.0 / STEPS, n) * np.abs(x[2])  # near the x axis, then the y axis
    ys += [sign[0, 2] * small, x[2]]
    xs += [x[2], sign[0, 2] * small]
    grid = np.abs(rng.integers(0, STEPS + 1, n) / STEPS + rng.uniform(-1e-3, 1e-3, n) / STEPS)  # table edges
    ys.append(sign[0, 3] * grid * np.abs(x[3]))
    xs.append(x[3])
    return np.concatenate(ys), np.concatenate(xs)


def test_within_one_ulp_of_the_c_library_on_a_million_pairs() -> None:
    y, x = _pairs(np.random.default_rng(29), 166_667)  # six sets
    assert y.size >= 1_000_000
    got = _atan2_all(y, x)
    want = np.array([math.atan2(a, b) for a, b in zip(y.tolist(), x.tolist())])
    ulps = np.abs(_ordered(got) - _ordered(want))
    assert ulps.max() == 1  # (a few in a hundred differ, by one ulp)
    assert 0.001 < np.mean(ulps > 0) < 0.05
    assert (np.signbit(got) == np.signbit(want)).all()


def test_special_values_are_the_c_librarys() -> None:
    v = [0.0, -0.0, 1.0, -1.0, 5e-324, -5e-324, 1e-310, 2.0 ** -960, 2.0 ** -961, 2.0 ** 960, 2.0 ** 961, 1e308,
         -1e308, math.inf, -math.inf, math.nan, 3.0, -0.5]
    Y, X = np.meshgrid(v, v)
    y, x = Y.ravel(), X.ravel()
    got = _atan2_all(y, x)
    want = np.array([math.atan2(a, b) for a, b in zip(y.tolist(), x.tolist())])
    assert (np.isnan(got) == np.isnan(want)).all()
    finite = ~np.isnan(want)
    assert (got[finite].view(np.int64) == want[finite].view(np.int64)).all()  # bit for bit, signed zeros too
    assert _atan2_all(np.array([-0.0, 0.0, 1.0]), np.array([-1.0, -1.0, 1.0])).tolist() == [-math.pi, math.pi,
                                                                                            math.pi / 4]


def test_a_row_at_once_is_the_scalar_atan2_bit_for_bit() -> None:
    rng = np.random.default_rng(3)
    Y, X = rng.normal(size=(3, 40)), rng.normal(size=(3, 40))
    Y[1, [0, 5, 9]], X[1, [0, 5, 9]] = [0.0, np.nan, np.inf], [0.0, 1.0, -2.0]  # row 1: the C library's pairs
    got = _rows(Y, X, 37)
    want = _atan2_all(Y.ravel(), X.ravel()).reshape(Y.shape)
    assert (np.isnan(got) == np.isnan(want))[:, :37].all() and np.isnan(got[1, 5])
    finite = ~np.isnan(want[:, :37])
    assert (got[:, :37][finite].view(np.int64) == want[:, :37][finite].view(np.int64)).all()
    assert (got[:, 37:] == -7.0).all()  # nothing past m


def test_fma_rounds_once() -> None:
    a = 1.0 + 2.0 ** -30
    # a·a = 1 + 2⁻²⁹ + 2⁻⁶⁰: the product rounded first loses the 2⁻⁶⁰ that fma keeps
    assert _fma(a, a, -(1.0 + 2.0 ** -29)) == 2.0 ** -60
    assert a * a - (1.0 + 2.0 ** -29) == 0.0
