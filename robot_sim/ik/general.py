"""Every real solution of a general 6R arm (no closed form): what
:mod:`robot_sim.ik.general_kernel` needs of a robot, built once per robot, and
:func:`general_solutions`, the call :func:`robot_sim.ik.solutions.ik_solutions` makes for
such an arm.

World frame (the robot standing at the origin, base and tool folded into the joint
screws of :mod:`robot_sim.ik.geometry`, so either DH convention), poses 4×4, joint values
in rad.  Lengths inside the elimination are divided by the robot's size (1 m at least).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from robot_sim.ik.family import Solver
from robot_sim.ik.finish import EVERY_TURN, RAW
from robot_sim.ik.geometry import Screws, motion
from robot_sim.ik.general_kernel import SAMPLES, eliminate, sigma, solve_general
from robot_sim.ik.polish import pose_error
from robot_sim.kernels.chain import frames, tool_pose
from robot_sim.kernels.model import compiled_model
from robot_sim.model.params import RobotParams
from robot_sim.transforms import rot_from_rpy

FloatArray = NDArray[np.float64]

#: The grid of sample angles of the exact fits: three angles fix a + b sin q + c cos q.
GRID = np.array([0.0, 2.0 * np.pi / 3.0, 4.0 * np.pi / 3.0])
#: Inverse of the fit's matrix: rows (s, c, 1) of each grid angle.
VI = np.linalg.inv(np.stack([np.sin(GRID), np.cos(GRID), np.ones(3)], axis=1))
#: The smallest singular value of Σ(q3) at a random pose and angle, relative to the
#: largest, below which the elimination has failed (Σ is singular for every q3).
RANK_TOL = 1e-10
#: Branch names: "solution k", k by the order of q3, and '' (index -1) for padding.
NAMES = np.array([f"solution {k + 1}" for k in range(32)] + [""])


def _poly_map() -> FloatArray:
    """(17, SAMPLES): from the determinant's samples at ψ_k = 2πk/SAMPLES (a trigonometric
    polynomial of degree 8) to the coefficients (ascending) of (1 + x²)⁸ times it, a
    polynomial of degree 16 in x = tan(ψ/2): e^{ikψ}(1 + x²)⁸ = (1 + ix)^{8+k} (1 − ix)^{8−k}."""
    psi = 2.0 * np.pi * np.arange(SAMPLES) / SAMPLES
    basis = [np.ones(SAMPLES)]
    expansions = [np.polynomial.polynomial.polypow([1.0, 0.0, 1.0], 8)]
    for k in range(1, 9):
        z = np.polynomial.polynomial.polymul(np.polynomial.polynomial.polypow([1.0, 1.0j], 8 + k),
                                             np.polynomial.polynomial.polypow([1.0, -1.0j], 8 - k))
        basis += [np.cos(k * psi), np.sin(k * psi)]
        expansions += [z.real, z.imag]
    fit = np.linalg.pinv(np.stack(basis, axis=1))  # (17, SAMPLES): samples -> trig coefficients
    return np.stack([np.pad(e, (0, 17 - len(e))) for e in expansions], axis=1) @ fit


W = _poly_map()


def _foot(S: Screws, i: int, j: int) -> FloatArray:
    """The point of axis i nearest axis j (axis i's point when they are parallel)."""
    hi, hj, d = S.H[i], S.H[j], S.P[j] - S.P[i]
    c = hi @ hj
    det = 1.0 - c * c
    if det < 1e-12:
        return S.P[i].copy()
    return S.P[i] + (d @ hi - c * (d @ hj)) / det * hi


def _perpendicular(h: FloatArray) -> FloatArray:
    x = np.cross(h, np.eye(3)[int(np.argmin(np.abs(h)))])
    return x / np.linalg.norm(x)


def _elimination(S: Screws, size: float) -> tuple:
    """The per-robot arguments of the elimination for the chain S (lengths over ``size``):
    C (14, 27), axis 6 in the tool frame (2, 3), the inverse motions of joints 1 and 2 at
    the grid angles (3, 3, 4) each, O on axis 3, the axes H, M's rotation transposed and a
    unit vector ⊥ axis 6 (see :mod:`robot_sim.ik.general_kernel`)."""
    P = S.P / size
    O = _foot(S, 2, 3) / size
    p6 = _foot(S, 5, 4) / size
    Minv_R = np.ascontiguousarray(S.M[:3, :3].T)
    axis6 = np.stack([Minv_R @ (p6 - S.M[:3, 3] / size), Minv_R @ S.H[5]])

    def chain(q3: float, q4: float, q5: float) -> FloatArray:
        E = motion(S.H[2], P[2], True, q3) @ motion(S.H[3], P[3], True, q4) @ motion(S.H[4], P[4], True, q5)
        p, l = E[:3, :3] @ p6 + E[:3, 3] - O, E[:3, :3] @ S.H[5]
        pp, pl = p @ p, p @ l
        return np.concatenate([p, l, [pp, pl], np.cross(p, l), pp * l - 2.0 * pl * p])

    F = np.array([[[chain(a, b, c) for c in GRID] for b in GRID] for a in GRID])
    C = np.ascontiguousarray(np.einsum("ia,jb,kc,abcr->rijk", VI, VI, VI, F).reshape(14, 27))
    E1 = np.stack([motion(S.H[0], P[0], True, -g)[:3] for g in GRID])
    E2 = np.stack([motion(S.H[1], P[1], True, -g)[:3] for g in GRID])
    return C, axis6, E1, E2, O, S.H.copy(), Minv_R, _perpendicular(S.H[5])


def _eliminates(args: tuple, size: float) -> bool:
    """Whether the elimination gives a 12 × 12 matrix Σ(q3) of full rank away from the
    solutions (it does not when axes 1 and 2 meet or run parallel: its determinant
    vanishes for every q3); checked on three random poses and angles."""
    rng = np.random.default_rng(0)
    Q, A, V, beta, G, S = (np.empty((14, 9)), np.empty((14, 8)), np.empty((14, 8)), np.empty(8),
                           np.empty((6, 3, 9)), np.empty((12, 12)))
    for _ in range(3):
        T = np.eye(4)
        T[:3, :3] = rot_from_rpy(rng.uniform(-np.pi, np.pi, 3))
        T[:3, 3] = rng.uniform(-size, size, 3)
        eliminate(T, 1.0 / size, *args[:5], VI, Q, A, V, beta, G)
        sigma(G, rng.uniform(-np.pi, np.pi), S)
        sv = np.linalg.svd(S, compute_uv=False)
        if not sv[-1] > RANK_TOL * sv[0]:
            return False
    return True


@dataclass(frozen=True)
class GeneralData:
    """The per-robot arguments of :func:`robot_sim.ik.general_kernel.solve_general`, in
    its order after the poses, and whether the chain is solved read from the tool back
    (when the elimination fails in the chain's order: axes 1 and 2 meet or run parallel)."""

    args: tuple
    reversed: bool

    @staticmethod
    def build(robot: RobotParams, S: Screws) -> "GeneralData | None":
        """None when the elimination fails in both directions (axes 1, 2 and axes 5, 6
        both meet or run parallel)."""
        size = max(robot.size, 1.0)
        reverse = False
        args = _elimination(S, size)
        if not _eliminates(args, size):
            reverse = True
            args = _elimination(S.reversed(), size)
            if not _eliminates(args, size):
                return None
        C, axis6, E1, E2, O, H, Minv_R, u6 = args
        model = compiled_model(robot)
        return GeneralData((1.0 / size, C, axis6, E1, E2, O, VI.copy(), W.copy(), H, Minv_R, u6, reverse,
                            model.table, model.modified, model.base, model.tool,
                            S.H.copy(), S.P.copy(), S.revolute.astype(np.int64), S.M.copy()), reverse)


def general_data(robot: RobotParams, sv: Solver) -> GeneralData | None:
    """The robot's :class:`GeneralData`, kept with its solver (None: no elimination)."""
    if "general" not in sv.prepared:
        sv.prepared["general"] = GeneralData.build(robot, sv.screws)
    return sv.prepared["general"]


def general_solutions(data: GeneralData, robot: RobotParams, Ts: FloatArray, q0: FloatArray, within: bool,
                      tol: float, max_values: int) -> tuple:
    """(q, code, exact, count, needed) of every pose of Ts (N, 4, 4), as
    :func:`robot_sim.ik.pipeline.run` returns them (see
    :func:`robot_sim.ik.general_kernel.solve_general`)."""
    lo, hi = np.array(robot.q_min, dtype=float), np.array(robot.q_max, dtype=float)
    Te = Ts
    if data.reversed:  # the chain read from the tool back reaches T⁻¹
        Te = np.zeros_like(Ts)
        Te[:, :3, :3] = np.swapaxes(Ts[:, :3, :3], 1, 2)
        Te[:, :3, 3] = -np.einsum("nij,nj->ni", Te[:, :3, :3], Ts[:, :3, 3])
        Te[:, 3, 3] = 1.0
    return solve_general(Ts, Te, *data.args, q0, lo, hi, EVERY_TURN if within else RAW, tol, max_values)


def reach(robot: RobotParams, q: FloatArray, T: FloatArray) -> tuple[float, float]:
    """How far the tool at q (n,) is from the world pose T (4, 4): position [m] and
    rotation angle [rad]."""
    model = compiled_model(robot)
    F, X, e = np.empty((robot.n_dofs + 1, 3, 4)), np.empty((4, 4)), np.empty(6)
    frames(model.table, model.modified, model.base, np.array(q, dtype=float), F)
    tool_pose(F, model.tool, X)
    pose_error(X, np.array(T, dtype=float), 1.0, e)
    return float(np.linalg.norm(e[:3])), float(np.linalg.norm(e[3:]))
