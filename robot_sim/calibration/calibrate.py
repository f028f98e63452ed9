"""Kinematic calibration: identify a robot's DH table, joint offsets, base and tool from
measured tool positions or poses (:func:`calibrate`).

The model is :mod:`robot_sim.calibration.chain`'s sequence of motions, with Hayati's beta
where consecutive axes are (nearly) parallel; the fit is Levenberg–Marquardt
(:mod:`~robot_sim.calibration.solver`) on the analytic parameter Jacobian; the parameters
the data cannot separate are found first (:mod:`~robot_sim.calibration.identifiability`)
and held at their nominal values; the result goes back to an exact DH table of the
robot's convention (:mod:`~robot_sim.calibration.exact_dh`).  A seeded fifth of the poses is
held out: the same fit on the other four fifths predicts it (``holdout``); the returned
robot is fitted on all poses.  Units: metres and radians.
"""
from __future__ import annotations

import dataclasses
import datetime
from dataclasses import dataclass
from typing import Callable, Sequence

import numpy as np
from numpy.typing import NDArray

from robot_sim.calibration.chain import GROUPS, Chain, build_chain, walk
from robot_sim.model.calibration_data import CalibrationData, CalibrationDataError
from robot_sim.calibration.exact_dh import to_robot
from robot_sim.calibration.identifiability import Unidentifiable, condition_number, dependencies, observability
from robot_sim.calibration.measure import pose_errors, stacked
from robot_sim.calibration.solver import ROBUST_ROUNDS, huber_weights, least_squares
from robot_sim.kinematics import forward_kinematics
from robot_sim.model.messages import clip_repr
from robot_sim.model.params import RobotParams
from robot_sim.transforms import HomogeneousTransform, rpy_from_rot

FloatArray = NDArray[np.float64]

#: Seed of the held-out fifth's choice.
HOLDOUT_SEED = 0
HOLDOUT_FRACTION = 5  # one pose in five
#: Largest change of a parameter in one fit step: angles [rad], lengths [robot sizes].
MAX_STEP_ANGLE, MAX_STEP_LENGTH = 0.05, 0.05
#: Size of the random step [m or rad] to a generic point (see :func:`generic`).
GENERIC_STEP = 1e-3


@dataclass(frozen=True)
class ParameterRow:
    """One parameter: ``name`` (``a3``, ``alpha2``, ``theta_offset4``, ``beta2``, ``base.x``,
    ``tool.rz``), ``nominal`` and ``identified`` values [m or rad] and the standard error
    ``std`` of the identified value (NaN where the data cannot identify it, which then
    keeps its nominal value)."""

    name: str
    nominal: float
    identified: float
    std: float


@dataclass(frozen=True)
class Residuals:
    """Measured minus modelled at the poses ``poses`` (indices into the data): position
    error sizes (k,) [m] and, with measured poses, rotation error angles (k,) [rad]."""

    poses: NDArray[np.int64]
    position: FloatArray
    rotation: FloatArray | None

    @property
    def rms(self) -> float:
        """Root mean square of the position errors [m]."""
        return float(np.sqrt(np.mean(self.position**2)))

    @property
    def max(self) -> float:
        """Largest position error [m]."""
        return float(self.position.max())

    @property
    def rotation_rms(self) -> float | None:
        """Root mean square of the rotation errors [rad] (None without measured poses)."""
        return None if self.rotation is None else float(np.sqrt(np.mean(self.rotation**2)))

    @property
    def rotation_max(self) -> float | None:
        """Largest rotation error [rad] (None without measured poses)."""
        return None if self.rotation is None else float(self.rotation.max())


@dataclass(frozen=True)
class CalibrationResult:
    """What :func:`calibrate` found.

    ``robot``: the calibrated robot (same convention, limits, inertials and geometry);
    ``parameters``: a :class:`ParameterRow` per parameter asked for, in the well-conditioned
    model the fit used (Hayati's beta where axes are parallel; ``robot`` holds the
    equivalent DH table); ``unidentifiable``: what the data cannot separate, with the
    reason; ``before`` and ``after``: residuals at every pose of the nominal and the
    calibrated robot; ``holdout``: residuals at the held-out fifth of a fit without them;
    ``condition_number`` of the column-scaled Jacobian and Borm and Menq's
    ``observability`` index O1 (angle columns times the robot's size), both of the
    identifiable parameters at the generic point next to the nominal one (see
    :func:`generic`), so they describe the poses, not the fit; ``table_error``: the largest
    distance [m] between the tool positions of ``robot``'s DH table and of the identified
    model at the measured poses; ``rms_before``/``rms_after`` and ``max_before``/``max_after``:
    the position errors [m] of ``before`` and ``after``, ``rms_rotation_*`` and
    ``max_rotation_*`` their rotation errors [rad] (None with positions only).
    """

    robot: RobotParams
    parameters: tuple[ParameterRow, ...]
    unidentifiable: tuple[Unidentifiable, ...]
    before: Residuals
    after: Residuals
    holdout: Residuals
    condition_number: float
    observability: float
    table_error: float
    rms_before: float
    rms_after: float
    max_before: float
    max_after: float
    rms_rotation_before: float | None
    rms_rotation_after: float | None
    max_rotation_before: float | None
    max_rotation_after: float | None

    @property
    def n_poses(self) -> int:
        """Number of measured poses."""
        return len(self.before.poses)


def free_columns(chain: Chain, identify: Sequence[str]) -> NDArray[np.int64]:
    """Motions in the groups ``identify`` that a fit may change (Hayati rows' d held)."""
    return np.array([k for k in range(chain.size) if chain.group[k] in identify and not chain.held[k]],
                    dtype=np.int64)


def minimum_poses(n_parameters: int, rows_per_pose: int) -> int:
    """Fewest poses (at least five, so one is held out) whose four fifths give more measured
    values than ``n_parameters``."""
    n = HOLDOUT_FRACTION
    while (n - n // HOLDOUT_FRACTION) * rows_per_pose <= n_parameters:
        n += 1
    return n


def angle_scaled(J: FloatArray, chain: Chain, columns: NDArray[np.int64]) -> FloatArray:
    """J with its angle columns multiplied by the robot's size [m], so all are m per m."""
    return J * np.where(chain.is_angle[columns], chain.robot.size, 1.0)


def generic(chain: Chain, columns: NDArray[np.int64]) -> Chain:
    """The chain with its ``columns`` moved by a seeded :data:`GENERIC_STEP` (metres or
    radians): what the data can identify is judged there, away from the special values
    (zero lengths, right angles) at which a DH table's columns may coincide."""
    values = chain.value.copy()
    values[columns] += GENERIC_STEP * np.random.default_rng(HOLDOUT_SEED).standard_normal(len(columns))
    return chain.with_values(values)


def _check_identify(identify: Sequence[str]) -> tuple[str, ...]:
    if isinstance(identify, str) or not isinstance(identify, (tuple, list)) or not identify or any(
            g not in GROUPS for g in identify):
        raise ValueError(f"identify: expected a non-empty tuple of {', '.join(map(repr, GROUPS))}, "
                         f"got {clip_repr(identify)}")
    return tuple(identify)


def _residuals(chain: Chain, data: CalibrationData, poses: NDArray[np.int64]) -> Residuals:
    position, rotation = pose_errors(chain, data)
    return Residuals(poses, np.linalg.norm(position, axis=1),
                     None if rotation is None else np.linalg.norm(rotation, axis=1))


def registered(chain: Chain, data: CalibrationData, columns: NDArray[np.int64]) -> Chain:
    """The chain with the base moved by the rigid motion that best maps its tool points onto
    the measured ones (Kabsch's least-squares rotation; Arun, Huang & Blostein, IEEE PAMI
    9(5), 1987), where the base's xyz and rpy are among ``columns``: the instrument's
    frame may be anywhere, and the fit then starts next to it."""
    base = [chain.name.index(f"base.{key}") for key in ("x", "y", "z", "rx", "ry", "rz")]
    if not np.isin(base, columns).any():
        return chain
    _, points, _, _ = walk(chain, data.q, np.zeros(chain.size, dtype=bool))
    model_mean, measured_mean = points.mean(axis=0), data.positions.mean(axis=0)
    U, _, Vt = np.linalg.svd((points - model_mean).T @ (data.positions - measured_mean))
    flip = np.diag([1.0, 1.0, np.sign(np.linalg.det(Vt.T @ U.T))])
    R = Vt.T @ flip @ U.T
    move = HomogeneousTransform.from_rt(R, measured_mean - R @ model_mean)
    frame = move @ HomogeneousTransform.from_xyz_rpy(chain.value[base[:3]], chain.value[base[3:]])
    values = chain.value.copy()
    new = np.concatenate([frame.t(), rpy_from_rot(frame.R())])
    keep = np.isin(base, columns)
    values[np.array(base)[keep]] = new[keep]
    return chain.with_values(values)


def _fit(chain: Chain, data: CalibrationData, columns: NDArray[np.int64], robust: bool,
         progress: Callable[[str], None] | None) -> tuple[Chain, FloatArray, FloatArray]:
    """Fitted chain, weighted residuals r and Jacobian J at the solution (Huber-reweighted
    poses when ``robust``).  The fit starts from the :func:`generic` point (at the nominal
    values a wrist centred on the tool point, say, turns it about axes through it, and
    those columns vanish) of the :func:`registered` chain."""
    def problem_for(fit_data: CalibrationData) -> Callable[[FloatArray], tuple[FloatArray, FloatArray]]:
        def problem(x: FloatArray) -> tuple[FloatArray, FloatArray]:
            values = chain.value.copy()
            values[columns] = x
            return stacked(chain.with_values(values), fit_data, columns)
        return problem

    def report(iteration: int, cost: float) -> None:
        if progress is not None:
            progress(f"iteration {iteration}: weighted RMS {np.sqrt(cost / len(data)) * 1e3:.4g} mm")

    x = generic(registered(chain, data, columns), columns).value[columns]
    max_step = np.where(chain.is_angle[columns], MAX_STEP_ANGLE, MAX_STEP_LENGTH * chain.robot.size)
    fit_data = data
    for _ in range(ROBUST_ROUNDS if robust else 1):
        x, r, J = least_squares(problem_for(fit_data), x, max_step, report)
        if robust:
            fitted = chain.value.copy()
            fitted[columns] = x
            position, rotation = pose_errors(chain.with_values(fitted), data)
            norms = np.linalg.norm(position if rotation is None else np.hstack([position, rotation]), axis=1)
            fit_data = CalibrationData(data.q, None if data.has_rotation else data.positions, data.poses,
                                       data.weights * huber_weights(norms))
    values = chain.value.copy()
    values[columns] = x
    return chain.with_values(values), r, J


def calibrate(robot: RobotParams, data: CalibrationData, *, identify: Sequence[str] = GROUPS,
              robust: bool = False, progress: Callable[[str], None] | None = None) -> CalibrationResult:
    """Identify ``robot``'s parameters in the groups ``identify`` from ``data``.

    Groups: ``"dh"`` (a, α, d of revolute and θ of prismatic joints, and Hayati's beta where
    consecutive axes lie within 10° of parallel, whose d is then held), ``"joint_offsets"``
    (θ of revolute, d of prismatic joints), ``"base"`` (frame 0 in the instrument's frame,
    xyz and roll-pitch-yaw) and ``"tool"`` (the tool frame in frame n).  ``robust`` gives
    poses with large residuals less weight (Huber, re-fitted five times).  ``progress``
    receives a line per iteration.  Raises ValueError (CalibrationDataError for the data)
    before any work for unknown groups, data that do not suit the robot (joint count,
    units, a joint outside its limits) and too few poses for the parameters asked.
    """
    groups = _check_identify(identify)
    data.check_robot(robot)
    chain = build_chain(robot)
    asked = free_columns(chain, groups)
    rows = 6 if data.has_rotation else 3
    needed = minimum_poses(len(asked), rows)
    if len(data) < needed:
        kind = "poses" if data.has_rotation else "positions"
        raise CalibrationDataError(
            f"too few poses: identifying {len(asked)} parameters from measured {kind} ({rows} values per pose, "
            f"a fifth held out) needs at least {needed} poses, got {len(data)}")
    _, J0 = stacked(generic(chain, asked), data, asked)
    kept, lost = dependencies(angle_scaled(J0, chain, asked), tuple(chain.name[k] for k in asked), data.has_rotation)
    columns = asked[kept]
    lost += [Unidentifiable(chain.name[k], (f"d{chain.row[k] + 2}",),
                            f"held: the axes of joints {chain.row[k] + 1} and {chain.row[k] + 2} are (nearly) parallel, "
                            f"so it slides along both as d{chain.row[k] + 2} does; Hayati's beta is identified instead")
             for k in range(chain.size) if chain.held[k] and chain.group[k] in groups]
    everything = np.arange(len(data))
    held_out = np.sort(np.random.default_rng(HOLDOUT_SEED).permutation(len(data))[: len(data) // HOLDOUT_FRACTION])
    train = np.setdiff1d(everything, held_out)
    trained, _, _ = _fit(chain, data.subset(train), columns, robust, None)
    fitted, r, J = _fit(chain, data, columns, robust, progress)
    cov = _covariance(J, r)
    std = dict(zip(columns.tolist(), np.sqrt(np.diag(cov))))
    parameters = tuple(ParameterRow(chain.name[k], float(chain.nominal[k]), float(fitted.value[k]),
                                    float(std.get(k, np.nan)))
                       for k in range(chain.size) if chain.group[k] in groups)
    before, after = _residuals(chain, data, everything), _residuals(fitted, data, everything)
    holdout = _residuals(trained, data.subset(held_out), held_out)
    note = (f"Calibrated by robot-sim on {datetime.date.today().isoformat()} from {len(data)} measured "
            f"{'poses' if data.has_rotation else 'positions'}: RMS {before.rms * 1e3:.4g} mm before, "
            f"{after.rms * 1e3:.4g} mm after ({holdout.rms * 1e3:.4g} mm on the held-out fifth)")
    calibrated = dataclasses.replace(to_robot(fitted), notes=robot.notes + (note,))
    _, model_points, _, _ = walk(fitted, data.q, np.zeros(chain.size, dtype=bool))
    table_points = forward_kinematics(calibrated, data.q)[:, :3, 3]
    return CalibrationResult(
        robot=calibrated, parameters=parameters, unidentifiable=tuple(lost),
        before=before, after=after, holdout=holdout,
        rms_before=before.rms, rms_after=after.rms, max_before=before.max, max_after=after.max,
        rms_rotation_before=before.rotation_rms, rms_rotation_after=after.rotation_rms,
        max_rotation_before=before.rotation_max, max_rotation_after=after.rotation_max,
        condition_number=condition_number(J0[:, kept]), observability=observability(angle_scaled(J0[:, kept], chain, columns)),
        table_error=float(np.linalg.norm(table_points - model_points, axis=1).max()),
    )


def _covariance(J: FloatArray, r: FloatArray) -> FloatArray:
    """Covariance of the parameters: s² (JᵀJ)⁻¹ with s² = |r|²/(m − p), by the SVD of the
    column-scaled J."""
    m, p = J.shape
    norms = np.linalg.norm(J, axis=0)
    scale = np.where(norms > 0, norms, 1.0)
    _, s, Vt = np.linalg.svd(J / scale, full_matrices=False)
    inv = (Vt.T / s**2) @ Vt
    return float(r @ r) / max(m - p, 1) * inv / np.outer(scale, scale)
