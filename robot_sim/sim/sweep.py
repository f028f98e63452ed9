"""Parameter sweeps: many simulations of one robot (gains, initial states, payloads), run in
batches, summarised as a table of metrics.

:func:`sweep` turns a grid (``{"kp": [100, 200], "damping": [0.7, 1.0]}``: every
combination) or a list of samples (``[{"kp": 100, "q0": q}, ...]``) into runs, cuts them
into chunks and runs each chunk as one :class:`~robot_sim.sim.batch.BatchSimulation`:
on the local cores by default (one process per core), or as tasks of a
``dask.distributed`` ``Client`` when one is given.  A run's result depends on nothing but
its own parameters (the batch equals single simulations bit for bit), so the table is the
same however the runs are chunked and wherever the chunks run.

The motion is a set-point step: each arm starts at rest at ``q0`` (default the robot's
home) and is commanded to ``q_des`` (default :func:`default_target`) for ``duration``
seconds.  Parameters of a run:

* ``kp``, ``kd``: PD gains for ``pd``/``pdg`` (N·m/rad, N·m·s/rad; a number for every
  joint or one per joint); for ``ct`` ``kp`` is the error dynamics' stiffness ω² [1/s²]
  (``kd`` = 2ζω from ``damping`` unless given, one number);
* ``bandwidth`` [Hz], ``damping`` (ζ): as ``control.control_gains``;
* ``q0``, ``q_des`` (n,): initial and desired joint values [rad, m];
* ``payload`` [kg]: a point mass at the tool frame's origin (the controller's model is
  the robot without it, as a real controller would be).

Metrics (columns of the table, :data:`METRICS`): ``tracking_rms`` (RMS over time and
joints of q_des − q [rad or m]), ``peak_effort`` (largest |τ| applied [N·m or N]),
``settling_time`` [s] (the last time a joint was farther than :data:`SETTLE_FRACTION` of its
step, at least :data:`SETTLE_FLOOR`, from its target; inf if still at the end), ``limit_hits`` (joint-limit
arrivals), ``diverged`` (1 if the run stopped on a non-finite state).
"""
from __future__ import annotations

import itertools
import math
import os
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import dataclass, replace
from multiprocessing import get_all_start_methods, get_context
from pathlib import Path
from typing import Any, Callable, Mapping, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robot_sim.sim.batch import BatchSimulation, batched_controller
from robot_sim.control.controllers import JOINT_MODES, Gains, control_gains
from robot_sim.sim.simulation import DEFAULT_DT, INTEGRATORS
from robot_sim.io.files import write_atomic
from robot_sim.model.inertials import LinkInertials, _combine
from robot_sim.model.params import JTYPE_REVOLUTE, RobotParams

FloatArray = NDArray[np.float64]

METRICS = ("tracking_rms", "peak_effort", "settling_time", "limit_hits", "diverged")
PARAMETERS = ("kp", "kd", "bandwidth", "damping", "q0", "q_des", "payload")
MODES = tuple(m for m in JOINT_MODES if m != "passive")  # the controlled modes BatchSimulation steps
#: A joint has settled when within this fraction of its step (and at least the floor).
SETTLE_FRACTION = 0.02
SETTLE_FLOOR = 1e-3  # rad or m
#: Default step of :func:`default_target`: revolute [rad], prismatic [m].
TARGET_STEP = (0.3, 0.05)
#: Runs per chunk unless told (one BatchSimulation; large enough to amortise its steps).
DEFAULT_CHUNK = 1000
#: Local worker processes start by fork where there is one (the compiled kernels come
#: along, and a caller's script needs no ``if __name__ == "__main__"`` guard).
_START_METHOD = "fork" if "fork" in get_all_start_methods() else "spawn"


def default_target(robot: RobotParams) -> FloatArray:
    """The default set point: home plus :data:`TARGET_STEP` per joint, kept inside the limits."""
    step = np.where(robot.jtype == JTYPE_REVOLUTE, TARGET_STEP[0], TARGET_STEP[1])
    return np.clip(robot.q_home + step, robot.q_min, robot.q_max)


@dataclass(frozen=True)
class SweepTable:
    """One row per run: the run's parameters (vectors spread over columns ``name_1`` …
    ``name_n``) and its metrics, as columns of equal length."""

    columns: dict[str, np.ndarray]

    def __len__(self) -> int:
        return len(next(iter(self.columns.values()))) if self.columns else 0

    def __getitem__(self, name: str) -> np.ndarray:
        return self.columns[name]

    def to_csv(self) -> str:
        """The table as CSV text (header line, then one line per run; repr-exact floats)."""
        names = list(self.columns)
        lines = [",".join(names)]
        for i in range(len(self)):
            lines.append(",".join(repr(float(self.columns[k][i])) if self.columns[k].dtype.kind == "f"
                                  else str(self.columns[k][i]) for k in names))
        return "\n".join(lines) + "\n"

    def write_csv(self, path: str | Path) -> Path:
        """Write :meth:`to_csv` to ``path`` (through a temporary file, renamed)."""
        write_atomic(path, self.to_csv())
        return Path(path)

    def equals(self, other: "SweepTable") -> bool:
        """Same columns with the same values, bit for bit (NaN equal to NaN)."""
        return list(self.columns) == list(other.columns) and all(
            np.array_equal(a, other.columns[k], equal_nan=a.dtype.kind == "f") for k, a in self.columns.items()
        )


# ------------------------------------------------------------------ runs


def _runs(robot: RobotParams, grid_or_samples: Mapping[str, Sequence[Any]] | Sequence[Mapping[str, Any]]) -> list[dict]:
    """The list of runs (parameter dicts) of a grid (every combination) or of samples."""
    if isinstance(grid_or_samples, Mapping):
        names = list(grid_or_samples)
        values = []
        for name in names:
            v = grid_or_samples[name]
            vals = list(v) if not isinstance(v, np.ndarray) or v.ndim > 0 else [v.item()]
            if not vals:
                raise ValueError(f"grid entry {name!r} has no values")
            values.append(vals)
        runs = [dict(zip(names, combo)) for combo in itertools.product(*values)]
    else:
        runs = [dict(sample) for sample in grid_or_samples]
    if not runs:
        raise ValueError("grid_or_samples gives no runs")
    n = robot.n_dofs
    for k, run in enumerate(runs):
        unknown = sorted(set(run) - set(PARAMETERS))
        if unknown:
            raise ValueError(f"run {k}: unknown parameter {unknown[0]!r}; accepted: {', '.join(PARAMETERS)}")
        for name, value in run.items():
            arr = np.asarray(value, dtype=float)
            vector = name in ("q0", "q_des")
            if (arr.shape != (n,)) if vector else arr.shape not in ((), (n,)):
                want = f"({n},)" if vector else f"a number or ({n},)"
                raise ValueError(f"run {k}: {name} must be {want}, got shape {arr.shape}")
            if not np.isfinite(arr).all() or (name in ("kp", "kd", "bandwidth", "damping", "payload") and (arr < 0).any()):
                raise ValueError(f"run {k}: {name} must be finite" + ("" if vector else " and >= 0") + f", got {value!r}")
            run[name] = arr
    return runs


def with_payload(robot: RobotParams, mass: float) -> RobotParams:
    """``robot`` carrying a point mass ``mass`` [kg] at the tool frame's origin (added to
    the last link's inertial: mass, centre of mass and inertia about it)."""
    if mass == 0.0:
        return robot
    li = robot.inertials
    tool = robot.tool_tf.t()  # the tool origin in frame n
    m, c, inertia = _combine([(float(li.mass[-1]), li.com[-1], li.inertia[-1]), (float(mass), tool, np.zeros((3, 3)))])
    masses, coms, inertias = np.array(li.mass, dtype=float), np.array(li.com, dtype=float), np.array(li.inertia, dtype=float)
    masses[-1], coms[-1], inertias[-1] = m, c, inertia
    return replace(robot, inertials=LinkInertials.from_arrays(masses, coms, inertias, li.estimated))


def _gains(robot: RobotParams, mode: str, run: Mapping[str, FloatArray]) -> Gains:
    keys = {k: (float(run[k]) if run[k].ndim == 0 else run[k]) for k in ("bandwidth", "damping") if k in run}
    if mode == "ct" and "kp" in run:
        if run["kp"].ndim != 0:
            raise ValueError("for computed torque kp is one number (the error dynamics' ω²), got one per joint")
        if not float(run["kp"]) > 0.0:  # checked here: it would be reported as a bandwidth of 0
            raise ValueError(f"kp must be > 0 for computed torque (the error dynamics' ω² [1/s²]), got {float(run['kp']):g}")
        keys["bandwidth"] = math.sqrt(float(run["kp"])) / (2.0 * math.pi)
    gains = control_gains(robot, **keys, **{
        k: np.broadcast_to(run[k], (robot.n_dofs,)) for k in ("kp", "kd") if k in run and mode != "ct"
    })
    if mode == "ct" and "kd" in run:  # Kd given: ζ = Kd / 2ω
        gains = replace(gains, zeta=float(run["kd"]) / (2.0 * gains.omega))
    return gains


@dataclass(frozen=True)
class _Chunk:
    """What one task needs: the robot (with the chunk's payload), the runs' parameters."""

    robot: RobotParams
    model: RobotParams  # the controller's model (the robot without payload)
    mode: str
    runs: tuple
    duration: float
    dt: float
    integrator: str
    metrics: tuple


def run_chunk(chunk: _Chunk) -> dict[str, np.ndarray]:
    """Simulate one chunk as a BatchSimulation and return its metric columns."""
    robot, n_runs = chunk.robot, len(chunk.runs)
    gains = [_gains(chunk.model, chunk.mode, run) for run in chunk.runs]
    controller = batched_controller(chunk.model, chunk.mode, gains, n_runs)
    sim = BatchSimulation(robot, n_runs, controller=controller, integrator=chunk.integrator, dt=chunk.dt)
    q0 = np.array([run.get("q0", robot.q_home) for run in chunk.runs], dtype=float)
    q_des = np.array([run.get("q_des", default_target(robot)) for run in chunk.runs], dtype=float)
    sim.set_state(q0)
    sim.set_reference(q=q_des)
    tolerance = np.maximum(SETTLE_FRACTION * np.abs(q_des - sim.q), SETTLE_FLOOR)
    n_steps = int(round(chunk.duration / chunk.dt))
    sq_error = np.zeros(n_runs)
    peak = np.zeros(n_runs)
    last_out = np.full(n_runs, -1)
    hits = np.zeros(n_runs, dtype=np.int64)
    for k in range(n_steps):
        sim.step()
        error = q_des - sim.q
        sq_error += np.einsum("ij,ij->i", error, error)
        peak = np.maximum(peak, np.abs(sim.effort).max(axis=1))
        last_out = np.where((np.abs(error) > tolerance).any(axis=1), k, last_out)
        for env, _ in sim.take_events():
            hits[env] += 1
    steps = np.maximum(sim.steps, 1)
    diverged = np.array([s is not None for s in sim.stopped])
    settling = np.where(last_out < n_steps - 1, (last_out + 1) * chunk.dt, np.inf)
    values = {
        "tracking_rms": np.sqrt(sq_error / (steps * robot.n_dofs)),
        "peak_effort": peak,
        "settling_time": np.where(diverged, np.inf, settling),
        "limit_hits": hits,
        "diverged": diverged.astype(np.int64),
    }
    return {name: values[name] for name in chunk.metrics}


def _chunks(robot: RobotParams, mode: str, runs: list[dict], duration: float, dt: float, integrator: str,
            metrics: tuple, chunk_size: int) -> list[tuple[list[int], _Chunk]]:
    """(run indices, chunk) pairs: runs grouped by payload (one robot per batch), in order."""
    groups: dict[float, list[int]] = {}
    for i, run in enumerate(runs):
        groups.setdefault(float(run.get("payload", 0.0)), []).append(i)
    out = []
    for payload, idx in groups.items():
        loaded = with_payload(robot, payload)
        for s in range(0, len(idx), chunk_size):
            part = idx[s : s + chunk_size]
            out.append((part, _Chunk(loaded, robot, mode, tuple(runs[i] for i in part), duration, dt, integrator, metrics)))
    return out


def sweep(
    robot: RobotParams,
    grid_or_samples: Mapping[str, Sequence[Any]] | Sequence[Mapping[str, Any]],
    controller: str = "ct",
    duration: float = 1.0,
    metrics: Sequence[str] = METRICS,
    *,
    dt: float = DEFAULT_DT,
    integrator: str = "rk4",
    chunk_size: int = DEFAULT_CHUNK,
    client: Any = None,
    workers: int | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> SweepTable:
    """Simulate every run of ``grid_or_samples`` (see the module docstring) under the
    controller mode ``controller`` (``pd``, ``pdg`` or ``ct``) for ``duration`` [s] and
    return a :class:`SweepTable` of the runs' parameters and ``metrics``.

    Chunks of ``chunk_size`` runs go to ``workers`` local processes (default: one per
    core; 1 runs them in this process), or, given a ``dask.distributed.Client`` as
    ``client``, to its workers as tasks; the table is the same either way.
    ``progress(done, total)`` is called as chunks finish (runs done, runs in all).
    """
    if controller not in MODES:
        raise ValueError(f"controller must be one of {', '.join(MODES)}, got {controller!r}")
    if not (isinstance(dt, (int, float)) and math.isfinite(dt) and dt > 0):
        raise ValueError(f"dt must be a positive finite number of seconds, got {dt!r}")
    if not (isinstance(duration, (int, float)) and math.isfinite(duration) and duration >= dt):
        raise ValueError(f"duration must be a finite number of seconds >= dt ({dt}), got {duration!r}")
    metrics = tuple(metrics)
    bad = [m for m in metrics if m not in METRICS]
    if bad or not metrics:
        raise ValueError(f"metrics must be some of {', '.join(METRICS)}, got {bad[0] if bad else 'none'!r}")
    if isinstance(chunk_size, bool) or not isinstance(chunk_size, int) or chunk_size < 1:
        raise ValueError(f"chunk_size must be a positive integer, got {chunk_size!r}")
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int) or workers < 1):
        raise ValueError(f"workers must be a positive integer (or None: one per core), got {workers!r}")
    if integrator not in INTEGRATORS:
        raise ValueError(f"integrator must be one of {', '.join(INTEGRATORS)}, got {integrator!r}")
    runs = _runs(robot, grid_or_samples)
    for run in runs[:1]:
        _gains(robot, controller, run)  # bad gains fail here, before any work
    chunks = _chunks(robot, controller, runs, float(duration), float(dt), integrator, metrics, chunk_size)
    results: list[dict | None] = [None] * len(chunks)
    done = 0

    def finished(k: int, value: dict) -> None:
        nonlocal done
        results[k] = value
        done += len(chunks[k][0])
        if progress is not None:
            progress(done, len(runs))

    if client is not None:
        from distributed import as_completed as dask_completed

        futures = client.map(run_chunk, [c for _, c in chunks], pure=False)
        index = {f.key: k for k, f in enumerate(futures)}
        for future in dask_completed(futures):
            finished(index[future.key], future.result())
    else:
        n_workers = min(workers or os.cpu_count() or 1, len(chunks))
        if n_workers <= 1:
            for k, (_, chunk) in enumerate(chunks):
                finished(k, run_chunk(chunk))
        else:
            with ProcessPoolExecutor(n_workers, mp_context=get_context(_START_METHOD)) as pool:
                pending = {pool.submit(run_chunk, c): k for k, (_, c) in enumerate(chunks)}
                for future in as_completed(pending):
                    finished(pending[future], future.result())
    return _table(robot, runs, chunks, results, metrics)


def _table(robot: RobotParams, runs: list[dict], chunks: list, results: list, metrics: tuple) -> SweepTable:
    """Parameter and metric columns in run order."""
    columns: dict[str, np.ndarray] = {}
    n = robot.n_dofs
    for name in PARAMETERS:
        if not any(name in run for run in runs):
            continue
        per_joint = any(np.ndim(run.get(name, 0.0)) == 1 for run in runs)
        shape = (n,) if per_joint else ()
        values = np.array([np.broadcast_to(run.get(name, np.nan), shape) for run in runs], dtype=float)
        if values.ndim == 1:
            columns[name] = values
        else:
            for j in range(n):
                columns[f"{name}_{j + 1}"] = values[:, j]
    for metric in metrics:
        sample = results[0][metric]
        column = np.empty(len(runs), dtype=sample.dtype)
        for (idx, _), result in zip(chunks, results):
            column[idx] = result[metric]
        columns[metric] = column
    return SweepTable(columns)
