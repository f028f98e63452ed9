"""A kernel called from compiled code with constants is compiled once, for the plain
types of its arguments (robot_sim.kernels.jit.plain_argument_types): numba's default
compiles it again for each literal value, as a function outside the package shows."""
from __future__ import annotations

import numba

import robot_sim.kernels.jit  # noqa: F401 - applies the rule


def _callers(module: str):
    def callee(flag, k):
        return k + 1 if flag else k - 1

    callee.__module__ = module
    inner = numba.njit(callee)

    @numba.njit
    def with_constants(k):
        return inner(True, 3) + inner(False, 4) + inner(k > 0, k)

    return inner, with_constants


def test_a_package_kernel_called_with_constants_compiles_once_for_plain_types() -> None:
    inner, caller = _callers("robot_sim.kernels.probe")
    assert caller(2) == 4 + 3 + 3
    assert [str(t) for t in inner.signatures[0]] == ["bool", "int64"]
    assert len(inner.signatures) == 1


def test_outside_the_package_numba_types_the_constants_as_literals() -> None:
    inner, caller = _callers("someone_elses.module")
    assert caller(2) == 10
    assert len(inner.signatures) == 3  # Literal True and 3, Literal False and 4, then bool and int64
