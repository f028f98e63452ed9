"""The :class:`Trajectory` value: sampled joint motion, evaluable at any time, CSV in/out.

Private helper of :mod:`trajectory` (import from there).  No Qt, no OpenGL.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robot_sim.model.arrays import frozen
from robot_sim.io.files import write_atomic

FloatArray = NDArray[np.float64]

#: Default sampling rate of every planner [Hz] (``times=None``).
DEFAULT_RATE = 1000.0
#: Most samples of one planned motion (16.7 min at DEFAULT_RATE), checked before allocating.
MAX_SAMPLES = 1_000_000
#: Column groups of the CSV file, in order; a pose adds its top three rows (T11 .. T34).
_POSE_COLUMNS = [f"T{r}{c}" for r in range(1, 4) for c in range(1, 5)]


def check_times(times: ArrayLike, what: str = "times") -> FloatArray:
    """``times`` as a float array (N,), N >= 1, finite and strictly increasing [s].

    Raises ValueError naming ``what``, the first bad index and its value.
    """
    t = np.asarray(times, dtype=float)
    if t.ndim != 1 or t.size == 0:
        raise ValueError(f"{what} must be a non-empty 1-D array of seconds, got shape {t.shape}")
    bad = np.flatnonzero(~np.isfinite(t))
    if bad.size:
        raise ValueError(f"{what}[{bad[0]}] is {float(t[bad[0]])!r}; times must be finite")
    steps = np.flatnonzero(np.diff(t) <= 0.0)
    if steps.size:
        i = int(steps[0])
        raise ValueError(
            f"{what} must be strictly increasing: {what}[{i}] = {float(t[i])!r} >= {what}[{i + 1}] = {float(t[i + 1])!r}"
        )
    return t


def sample_times(duration: float, rate: float = DEFAULT_RATE) -> FloatArray:
    """Uniform sample times from 0 to ``duration`` inclusive, spaced at most 1/``rate`` s.

    ValueError, before anything is allocated, when that takes more than MAX_SAMPLES."""
    wanted = np.ceil(float(duration) * float(rate) - 1e-9)
    if not wanted < MAX_SAMPLES:  # also NaN and inf
        raise ValueError(f"a motion of {float(duration):.6g} s sampled every {1.0 / float(rate):.3g} s needs "
                         f"{wanted:.3g} samples; at most {MAX_SAMPLES} are accepted")
    steps = max(1, int(wanted))
    return np.linspace(0.0, duration, steps + 1)


@dataclass(frozen=True, eq=False)
class Trajectory:
    """Joint motion sampled at times ``t``: a value (read-only arrays), SI units.

    ``t`` (N,) seconds, strictly increasing; ``q``, ``qd``, ``qdd`` (N, n) joint positions
    (rad or m), velocities and accelerations; ``poses`` (N, 4, 4) the tool pose in the world
    at each sample, or None (joint-space plans).  ``marks`` names instants of the motion,
    e.g. ``((1.2, "via 1"), ...)`` for the times a via-point path passes its via points or
    the start of each phase of a task.
    """

    t: FloatArray
    q: FloatArray
    qd: FloatArray
    qdd: FloatArray
    poses: FloatArray | None = None
    marks: tuple[tuple[float, str], ...] = field(default=())

    def __post_init__(self) -> None:
        t = check_times(self.t, "t")
        object.__setattr__(self, "t", frozen(t))
        n_samples = t.shape[0]
        for name in ("q", "qd", "qdd"):
            arr = np.asarray(getattr(self, name), dtype=float)
            if arr.ndim != 2 or arr.shape[0] != n_samples:
                raise ValueError(f"{name} must have shape ({n_samples}, n), got {arr.shape}")
            if not np.isfinite(arr).all():
                raise ValueError(f"{name} contains NaN or infinite values")
            object.__setattr__(self, name, frozen(arr))
        if not (self.q.shape == self.qd.shape == self.qdd.shape):
            raise ValueError(f"q, qd, qdd shapes differ: {self.q.shape}, {self.qd.shape}, {self.qdd.shape}")
        if self.poses is not None:
            poses = np.asarray(self.poses, dtype=float)
            if poses.shape != (n_samples, 4, 4) or not np.isfinite(poses).all():
                raise ValueError(f"poses must be finite with shape ({n_samples}, 4, 4), got {poses.shape}")
            object.__setattr__(self, "poses", frozen(poses))
        object.__setattr__(self, "marks", tuple((float(tm), str(name)) for tm, name in self.marks))

    @property
    def n_samples(self) -> int:
        """Number of samples N."""
        return int(self.t.shape[0])

    @property
    def n_dofs(self) -> int:
        """Number of joints n."""
        return int(self.q.shape[1])

    @property
    def duration(self) -> float:
        """``t[-1] - t[0]`` in seconds."""
        return float(self.t[-1] - self.t[0])

    def evaluate(self, times: ArrayLike) -> tuple[FloatArray, FloatArray, FloatArray]:
        """``(q, qd, qdd)`` at ``times`` [s]: (n,) each for a scalar time, (M, n) for (M,).

        Between samples q is the cubic Hermite interpolant of the sampled q and qd and qd its
        derivative (both exact at the samples), qdd is linear.  Times before the first or
        after the last sample hold that sample's values.  Raises ValueError for NaN times.
        """
        tq = np.asarray(times, dtype=float)
        if not np.isfinite(tq).all():
            raise ValueError(f"times must be finite, got {tq!r}")
        scalar = tq.ndim == 0
        tq = np.clip(tq.reshape(-1), self.t[0], self.t[-1])
        if self.n_samples == 1:
            q, qd, qdd = (np.repeat(a, tq.shape[0], axis=0) for a in (self.q, self.qd, self.qdd))
        else:
            i = np.clip(np.searchsorted(self.t, tq, side="right") - 1, 0, self.n_samples - 2)
            h = (self.t[i + 1] - self.t[i])[:, None]
            s = ((tq - self.t[i])[:, None]) / h
            q0, q1, v0, v1 = self.q[i], self.q[i + 1], self.qd[i] * h, self.qd[i + 1] * h
            s2, s3 = s * s, s * s * s
            q = (2 * s3 - 3 * s2 + 1) * q0 + (s3 - 2 * s2 + s) * v0 + (-2 * s3 + 3 * s2) * q1 + (s3 - s2) * v1
            qd = ((6 * s2 - 6 * s) * (q0 - q1) + (3 * s2 - 4 * s + 1) * v0 + (3 * s2 - 2 * s) * v1) / h
            qdd = (1 - s) * self.qdd[i] + s * self.qdd[i + 1]
        if scalar:
            return q[0], qd[0], qdd[0]
        return q, qd, qdd

    def shifted(self, dt: float) -> "Trajectory":
        """The same motion ``dt`` seconds later (marks shifted too)."""
        return Trajectory(
            self.t + dt, self.q, self.qd, self.qdd, self.poses, tuple((tm + dt, m) for tm, m in self.marks)
        )

    def then(self, other: "Trajectory", tol: float = 1e-6) -> "Trajectory":
        """This motion followed by ``other`` (re-timed to start where this one ends).

        ``other`` must start where this one ends (joint positions within ``tol``); its first
        sample is dropped in favour of this one's last.  Poses are kept only if both have
        them.  Raises ValueError for a jump or a different number of joints.
        """
        if other.n_dofs != self.n_dofs:
            raise ValueError(f"cannot join trajectories of {self.n_dofs} and {other.n_dofs} joints")
        jump = float(np.max(np.abs(other.q[0] - self.q[-1])))
        if jump > tol:
            raise ValueError(f"cannot join trajectories: q jumps by {jump:.3g} at t = {self.t[-1]:.6g} s")
        nxt = other.shifted(self.t[-1] - other.t[0])
        poses = None
        if self.poses is not None and nxt.poses is not None:
            poses = np.concatenate([self.poses, nxt.poses[1:]])
        return Trajectory(
            np.concatenate([self.t, nxt.t[1:]]),
            np.concatenate([self.q, nxt.q[1:]]),
            np.concatenate([self.qd, nxt.qd[1:]]),
            np.concatenate([self.qdd, nxt.qdd[1:]]),
            poses,
            self.marks + nxt.marks,
        )

    def columns(self) -> list[str]:
        """CSV column names: t, q1..qn, qd1..qdn, qdd1..qddn, then T11..T34 with poses."""
        names = ["t"] + [f"{g}{j + 1}" for g in ("q", "qd", "qdd") for j in range(self.n_dofs)]
        return names + (_POSE_COLUMNS if self.poses is not None else [])

    def to_csv(self, path: str | Path) -> None:
        """Write the samples as CSV (one header line, ``# mark,<t>,<name>`` comment lines for
        marks, 17 significant digits so :meth:`from_csv` gives the same numbers back),
        atomically."""
        blocks = [self.t[:, None], self.q, self.qd, self.qdd]
        if self.poses is not None:
            blocks.append(self.poses[:, :3, :].reshape(-1, 12))
        data = np.hstack(blocks)
        lines = [",".join(self.columns())]
        lines += [f"# mark,{tm!r},{name}" for tm, name in self.marks]
        lines += [",".join(repr(float(v)) for v in row) for row in data]
        write_atomic(path, "\n".join(lines) + "\n")

    @classmethod
    def from_csv(cls, path: str | Path) -> "Trajectory":
        """Read a file written by :meth:`to_csv`.  Raises ValueError naming the file, the line
        and what is wrong (a bad header, a wrong number of values, a non-number)."""
        path = Path(path)
        try:
            lines = path.read_text(encoding="utf-8").splitlines()
        except OSError as exc:
            raise ValueError(f"{path}: cannot read trajectory file: {exc.strerror}") from None
        if not lines:
            raise ValueError(f"{path}: empty file; expected a header line 't,q1,...'")
        header = lines[0].split(",")
        n_vals = len(header) - 1
        n = n_vals // 3 if header[-1] != "T34" else (n_vals - 12) // 3
        expected = ["t"] + [f"{g}{j + 1}" for g in ("q", "qd", "qdd") for j in range(n)]
        if header[-1] == "T34":
            expected += _POSE_COLUMNS
        if n < 1 or header != expected:
            raise ValueError(f"{path}: line 1: header {lines[0]!r} is not 't,q1..qn,qd1..qdn,qdd1..qddn[,T11..T34]'")
        rows, marks = [], []
        for lineno, line in enumerate(lines[1:], start=2):
            if line.startswith("# mark,"):
                _, tm, name = line.split(",", 2)
                marks.append((float(tm), name))
                continue
            parts = line.split(",")
            if len(parts) != len(header):
                raise ValueError(f"{path}: line {lineno}: {len(parts)} values, expected {len(header)}")
            try:
                rows.append([float(p) for p in parts])
            except ValueError:
                raise ValueError(f"{path}: line {lineno}: not a number in {line!r}") from None
        if not rows:
            raise ValueError(f"{path}: no samples after the header")
        data = np.array(rows)
        poses = None
        if header[-1] == "T34":
            poses = np.zeros((data.shape[0], 4, 4))
            poses[:, :3, :] = data[:, 1 + 3 * n :].reshape(-1, 3, 4)
            poses[:, 3, 3] = 1.0
        try:
            return cls(data[:, 0], data[:, 1 : 1 + n], data[:, 1 + n : 1 + 2 * n], data[:, 1 + 2 * n : 1 + 3 * n], poses, tuple(marks))
        except ValueError as exc:
            raise ValueError(f"{path}: {exc}") from None
