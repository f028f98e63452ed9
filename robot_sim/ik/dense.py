"""Small dense linear algebra for the general 6R solver (compiled, no LAPACK call, so
one pose costs no library overhead): Householder QR and its Qᵀ, the determinant by LU
with partial pivoting, and a null vector by LU with complete pivoting (Golub & Van Loan,
Matrix Computations, §5.2 and §3.4)."""
from __future__ import annotations

import math

import numba
import numpy as np

from robot_sim.kernels.jit import INLINE, JIT


@numba.njit(**INLINE)
def _reflect(V: np.ndarray, beta: np.ndarray, j: int, B: np.ndarray, first: int) -> None:
    """Reflector j of :func:`householder` applied to the columns ``first``… of B."""
    for c in range(first, B.shape[1]):
        dot = 0.0
        for i in range(j, V.shape[0]):
            dot += V[i, j] * B[i, c]
        dot *= beta[j]
        for i in range(j, V.shape[0]):
            B[i, c] -= dot * V[i, j]


@numba.njit(**JIT)
def householder(A: np.ndarray, V: np.ndarray, beta: np.ndarray) -> None:
    """Householder QR of A (m, k) in place: R in A's upper triangle, the reflectors'
    vectors in V's columns (V[:, j] zero above j) and their factors in beta."""
    m, k = A.shape
    for j in range(k):
        norm = 0.0
        for i in range(j, m):
            norm += A[i, j] * A[i, j]
        norm = math.sqrt(norm)
        alpha = -norm if A[j, j] >= 0.0 else norm
        for i in range(m):
            V[i, j] = A[i, j] if i > j else 0.0
        V[j, j] = A[j, j] - alpha
        vv = 0.0
        for i in range(j, m):
            vv += V[i, j] * V[i, j]
        beta[j] = 2.0 / vv if vv > 0.0 else 0.0
        _reflect(V, beta, j, A, j)


@numba.njit(**JIT)
def apply_qt(V: np.ndarray, beta: np.ndarray, B: np.ndarray) -> None:
    """B ← Qᵀ B for the reflectors of :func:`householder` (B (m, c) in place)."""
    for j in range(V.shape[1]):
        _reflect(V, beta, j, B, 0)


@numba.njit(**JIT)
def determinant(S: np.ndarray) -> float:
    """det S by LU with partial pivoting (S is overwritten)."""
    n = S.shape[0]
    det = 1.0
    for k in range(n):
        p = k
        for i in range(k + 1, n):
            if abs(S[i, k]) > abs(S[p, k]):
                p = i
        if S[p, k] == 0.0:
            return 0.0
        if p != k:
            det = -det
            for c in range(k, n):
                S[k, c], S[p, c] = S[p, c], S[k, c]
        det *= S[k, k]
        for i in range(k + 1, n):
            f = S[i, k] / S[k, k]
            for c in range(k + 1, n):
                S[i, c] -= f * S[k, c]
    return det


@numba.njit(**JIT)
def null_vector(S: np.ndarray, z: np.ndarray) -> None:
    """z: a vector with S z ≈ 0 for a (nearly) rank-deficient S, by LU with complete
    pivoting (the last pivot taken as zero); S is overwritten."""
    n = S.shape[0]
    col = np.arange(n)
    for k in range(n - 1):
        pi, pj, best = k, k, -1.0
        for i in range(k, n):
            for j in range(k, n):
                if abs(S[i, j]) > best:
                    best, pi, pj = abs(S[i, j]), i, j
        if best == 0.0:
            break
        for c in range(n):
            S[k, c], S[pi, c] = S[pi, c], S[k, c]
        for r in range(n):
            S[r, k], S[r, pj] = S[r, pj], S[r, k]
        col[k], col[pj] = col[pj], col[k]
        for i in range(k + 1, n):
            f = S[i, k] / S[k, k]
            for c in range(k + 1, n):
                S[i, c] -= f * S[k, c]
    y = np.zeros(n)
    y[n - 1] = 1.0
    for k in range(n - 2, -1, -1):
        acc = 0.0
        for c in range(k + 1, n):
            acc += S[k, c] * y[c]
        y[k] = -acc / S[k, k] if S[k, k] != 0.0 else 0.0
    for k in range(n):
        z[col[k]] = y[k]
