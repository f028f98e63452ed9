"""Compiled building blocks shared by every kernel: cos and sin of one angle, 3-vector
arithmetic on tuples (dot and cross products, sums, the part across a unit vector), the Cholesky factorisation and its solve, and the stages and combine of the
classical Runge–Kutta step (and of semi-implicit Euler).

Each exists once in the package; the kernels of kinematics, dynamics, collision,
task-space control and the physics loop call these.  Work arrays are passed in
explicitly: nothing here keeps state.  Imports numpy, numba and the package's numba
settings only.
"""
from __future__ import annotations

import math

from robot_sim.kernels.jit import INLINE, JIT, njit

# ------------------------------------------------------------------ sin and cos
# One range reduction and two polynomials give both (the C library's cos and sin cost
# about 25 ns each here, the largest share of a one-configuration RNEA).  Cody–Waite
# reduction by π/2 in three parts and fdlibm's kernel polynomials: within 1 ulp or so
# of the C library for |x| ≤ 1e5 rad; larger angles go to the C library.
_TWO_OVER_PI = 6.36619772367581382433e-01
_PIO2_1, _PIO2_2, _PIO2_3 = 1.57079632673412561417e00, 6.07710050630396597660e-11, 2.02226624871116645580e-21
_S1, _S2, _S3 = -1.66666666666666324348e-01, 8.33333333332248946124e-03, -1.98412698298579493134e-04
_S4, _S5, _S6 = 2.75573137070700676789e-06, -2.50507602534068634195e-08, 1.58969099521155010221e-10
_C1, _C2, _C3 = 4.16666666666666019037e-02, -1.38888888888741095749e-03, 2.48015872894767294178e-05
_C4, _C5, _C6 = -2.75573143513906633035e-07, 2.08757232129817482790e-09, -1.13596475577881948265e-11
_REDUCE_MAX = 1e5


@njit(**INLINE)
def cos_sin(x):
    """(cos x, sin x) of an angle x [rad]."""
    if not abs(x) <= _REDUCE_MAX:
        return math.cos(x), math.sin(x)
    k = math.floor(x * _TWO_OVER_PI + 0.5)
    r = ((x - k * _PIO2_1) - k * _PIO2_2) - k * _PIO2_3
    z = r * r
    sin_r = r + r * z * (_S1 + z * (_S2 + z * (_S3 + z * (_S4 + z * (_S5 + z * _S6)))))
    hz = 0.5 * z
    w = 1.0 - hz
    cos_r = w + (((1.0 - w) - hz) + z * z * (_C1 + z * (_C2 + z * (_C3 + z * (_C4 + z * (_C5 + z * _C6))))))
    quadrant = int(k) & 3
    if quadrant == 0:
        return cos_r, sin_r
    if quadrant == 1:
        return -sin_r, cos_r
    if quadrant == 2:
        return -cos_r, -sin_r
    return sin_r, -cos_r


# ------------------------------------------------------------------ 3-vectors


@njit(**INLINE)
def cross(a, b):
    """a × b of two 3-vectors (tuples or arrays), as a tuple."""
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


# Plain kernels, not numba-inlined: LLVM inlines them where they are called, and numba's
# inlining of every call site cost the IK's solvers half again their compile time.


@njit(**JIT)
def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


@njit(**JIT)
def add(a, b):
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


@njit(**JIT)
def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


@njit(**JIT)
def madd(a, b, s):
    """a + s b."""
    return (a[0] + s * b[0], a[1] + s * b[1], a[2] + s * b[2])


@njit(**JIT)
def scale(a, s):
    """s a."""
    return (a[0] * s, a[1] * s, a[2] * s)


@njit(**JIT)
def norm(a):
    return math.sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2])


@njit(**JIT)
def perp(k, a):
    """a without its component along the unit vector k."""
    return sub(a, scale(k, dot(k, a)))


# ------------------------------------------------------------------ Cholesky


@njit(**JIT)
def cholesky(A):
    """The lower Cholesky factor L of the symmetric A, in place in A's lower triangle
    (the strict upper triangle is not touched); False, stopping there, if A is not
    positive definite."""
    n = A.shape[0]
    for j in range(n):
        diag = A[j, j]
        for k in range(j):
            diag -= A[j, k] * A[j, k]
        if not diag > 0.0:
            return False
        ljj = math.sqrt(diag)
        A[j, j] = ljj
        for i in range(j + 1, n):
            acc = A[i, j]
            for k in range(j):
                acc -= A[i, k] * A[j, k]
            A[i, j] = acc / ljj
    return True


@njit(**JIT)
def solve_factored(L, b, x):
    """x with L Lᵀ x = b (L in the lower triangle, as :func:`cholesky` leaves it)."""
    n = L.shape[0]
    for i in range(n):
        acc = b[i]
        for k in range(i):
            acc -= L[i, k] * x[k]
        x[i] = acc / L[i, i]
    for i in range(n - 1, -1, -1):
        acc = x[i]
        for k in range(i + 1, n):
            acc -= L[k, i] * x[k]
        x[i] = acc / L[i, i]


@njit(**JIT)
def cholesky_solve(M, b, x):
    """x = M⁻¹ b for the symmetric positive definite M, factorised in place in its lower
    triangle; x all NaN when M is not positive definite."""
    if cholesky(M):
        solve_factored(M, b, x)
    else:
        x[:] = math.nan


# ------------------------------------------------------------------ integration


@njit(**INLINE)
def rk4_stage(step, q, v, a_prev, v_prev, qs, vs):
    """A later stage's state of classical RK4 from (q, v) (n,): vs = v + step·a_prev and
    qs = q + step·v_prev (``v_prev`` the previous stage's velocity; it may be ``vs``)."""
    for j in range(q.shape[0]):
        vs_new = v[j] + step * a_prev[j]
        qs[j] = q[j] + step * v_prev[j]
        vs[j] = vs_new


@njit(**INLINE)
def rk4_combine(h, q, v, a1, a2, a3, a4, q1, qd1):
    """(q, v) after a classical RK4 step of h [s] from the stage accelerations a1..a4 into
    q1, qd1 (stage velocities v2 = v + h/2·a1, v3 = v + h/2·a2, v4 = v + h·a3)."""
    half, sixth = 0.5 * h, h / 6.0
    for j in range(q.shape[0]):
        v2, v3, v4 = v[j] + half * a1[j], v[j] + half * a2[j], v[j] + h * a3[j]
        q1[j] = q[j] + sixth * (v[j] + 2.0 * (v2 + v3) + v4)
        qd1[j] = v[j] + sixth * (a1[j] + 2.0 * (a2[j] + a3[j]) + a4[j])


@njit(**INLINE)
def euler_combine(h, q, v, a1, q1, qd1):
    """(q, v) after a semi-implicit Euler step of h [s]: qd1 = v + h·a1, q1 = q + h·qd1."""
    for j in range(q.shape[0]):
        qd1[j] = v[j] + h * a1[j]
        q1[j] = q[j] + h * qd1[j]
