"""Compiled kernels call no np.linalg (numba's needs SciPy's LAPACK, not a dependency:
a fresh `make test` failed 22 task-space tests with "scipy 0.16+ is required"), and the
compiled OSC's own eigenvalue routine equals LAPACK's."""
from __future__ import annotations

import ast

import numpy as np
import pytest

from paths import PACKAGE
from robot_sim.control.task_space_compiled import _smallest_eigenvalue



def linalg_calls_in_compiled_functions(source: str) -> list[str]:
    """Names of functions decorated with numba's njit/jit whose body uses np.linalg."""
    found = []
    for node in ast.walk(ast.parse(source)):
        if not isinstance(node, ast.FunctionDef):
            continue
        decorators = [d.func if isinstance(d, ast.Call) else d for d in node.decorator_list]
        if not any(getattr(d, "id", getattr(d, "attr", "")) in ("njit", "jit") for d in decorators):
            continue
        if any(isinstance(n, ast.Attribute) and n.attr == "linalg" for n in ast.walk(node)):
            found.append(node.name)
    return found


def test_the_scan_finds_linalg_in_a_compiled_function() -> None:
    source = "@njit(**JIT)\ndef f(a):\n    return np.linalg.eigvalsh(a)\n\ndef g(a):\n    return np.linalg.inv(a)\n"
    assert linalg_calls_in_compiled_functions(source) == ["f"]


def test_no_compiled_function_uses_np_linalg() -> None:
    found = {
        str(path.relative_to(PACKAGE.parent)): names
        for path in sorted(PACKAGE.rglob("*.py"))
        if (names := linalg_calls_in_compiled_functions(path.read_text(encoding="utf-8")))
    }
    assert found == {}


@pytest.mark.parametrize("m", range(1, 7))
def test_jacobi_smallest_eigenvalue_equals_lapack(m: int) -> None:
    rng = np.random.default_rng(m)
    for rank in range(m + 1):  # singular, definite and (shifted) indefinite matrices
        B = rng.normal(size=(m, rank))
        for W in (B @ B.T, B @ B.T - 0.5 * np.eye(m), 1e-9 * (B @ B.T)):
            expected = np.linalg.eigvalsh(W)[0]
            got = _smallest_eigenvalue(W.copy())
            assert got == pytest.approx(expected, abs=1e-14 * max(1.0, np.abs(W).max()) * m)
