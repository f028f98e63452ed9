"""sweep(): grids and samples become runs whose metrics follow from closed forms (computed
torque's critically damped error), equal BatchSimulation's, and do not depend on how the
runs are chunked or where the chunks run (local processes, a Dask LocalCluster of two
workers); the ``robot-sim sweep`` command writes them as CSV."""
from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from robot_sim.sim.sweep import SETTLE_FRACTION, default_target, sweep, with_payload
from robot_sim import dynamics
from robot_sim.control.controllers import ComputedTorque, control_gains
from robot_sim.sim.simulation import Simulation
from robot_sim.io.robot_file import load_robot

from cli_helpers import run, run_process


def _critical_settling(omega: float) -> float:
    """First t after which (1 + ωt) e^{−ωt} stays below SETTLE_FRACTION (bisection)."""
    lo, hi = 1.0, 50.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if (1 + mid) * math.exp(-mid) > SETTLE_FRACTION else (lo, mid)
    return hi / omega


def test_computed_torque_settles_as_the_closed_form_says():
    robot = dataclasses.replace(load_robot("ur5"), drives=None)  # no effort limits: no saturation
    kp = [100.0, 400.0]
    table = sweep(robot, {"kp": kp, "damping": [1.0]}, "ct", duration=1.0, workers=1)
    assert list(table.columns) == ["kp", "damping", "tracking_rms", "peak_effort", "settling_time", "limit_hits", "diverged"]
    target = default_target(robot)
    e0 = 0.3  # default_target's step on every (revolute) joint of the UR5
    assert np.allclose(target - robot.q_home, e0)
    for i, k in enumerate(kp):
        # the same run as one Simulation, its metrics computed here
        sim = Simulation(robot, controller=ComputedTorque(robot, control_gains(robot, bandwidth=math.sqrt(k) / (2 * math.pi))))
        sim.state.set_q_des(target)
        err = []
        for _ in range(1000):
            sim.step()
            err.append(target - sim.q)
        err = np.array(err)
        outside = np.flatnonzero((np.abs(err) > SETTLE_FRACTION * e0).any(axis=1))
        assert table["settling_time"][i] == (outside[-1] + 1) * 1e-3  # the last time outside the band
        assert table["tracking_rms"][i] == pytest.approx(math.sqrt(np.mean(err**2)), rel=1e-12)
        # e(t) = e0 (1 + ωt) e^{−ωt} of the continuous loop, within 1 % (a 1 kHz sampled controller)
        assert table["settling_time"][i] == pytest.approx(_critical_settling(math.sqrt(k)), rel=0.01)
        t = 1e-3 * np.arange(1, 1001)
        closed = e0 * (1 + math.sqrt(k) * t) * np.exp(-math.sqrt(k) * t)
        assert np.abs(err - closed[:, None]).max() < 0.01 * e0
    assert table["tracking_rms"][1] < table["tracking_rms"][0]  # stiffer tracks closer
    assert (table["limit_hits"] == 0).all() and (table["diverged"] == 0).all()
    # peak effort: computed torque's first step, τ = ID(q0, 0, kp·e0)
    step = default_target(robot) - robot.q_home
    assert np.allclose(step, e0)
    tau0 = dynamics.inverse_dynamics(robot, robot.q_home, np.zeros(6), kp[1] * step)
    assert table["peak_effort"][1] >= np.abs(tau0).max() * (1 - 1e-9)


def test_samples_payloads_and_initial_states():
    robot = load_robot("ur5")
    q0 = robot.q_home + 0.1
    samples = [{"kp": 200.0}, {"kp": 200.0, "payload": 2.0}, {"kp": 200.0, "q0": q0}, {"kp": 200.0, "payload": 0.0}]
    table = sweep(robot, samples, "ct", duration=0.3, workers=1)
    assert table["payload"][0] != table["payload"][0]  # NaN: not given
    assert table["tracking_rms"][3] == table["tracking_rms"][0]  # no payload is payload 0
    assert table["tracking_rms"][1] != table["tracking_rms"][0]  # the model lacks the load: it shows
    assert table["tracking_rms"][2] < table["tracking_rms"][0]  # starting nearer the target
    assert np.allclose(table["q0_1"][2], q0[0])
    loaded = with_payload(robot, 2.0)
    assert loaded.inertials.mass[-1] == pytest.approx(robot.inertials.mass[-1] + 2.0)


def test_the_table_does_not_depend_on_chunks_or_processes(tmp_path):
    robot = load_robot("panda")
    grid = {"kp": np.linspace(50, 500, 5), "damping": [0.8, 1.0]}
    one = sweep(robot, grid, "ct", duration=0.1, workers=1)
    many = sweep(robot, grid, "ct", duration=0.1, chunk_size=3, workers=2)
    assert one.equals(many) and len(one) == 10
    pd = sweep(robot, {"kp": [20.0, 60.0], "kd": [2.0]}, "pdg", duration=0.1, workers=1)
    assert len(pd) == 2 and pd["kd"].tolist() == [2.0, 2.0]
    path = one.write_csv(tmp_path / "t.csv")
    lines = path.read_text().splitlines()
    assert lines[0].startswith("kp,damping,") and len(lines) == 11
    assert float(lines[1].split(",")[2]) == one["tracking_rms"][0]  # repr-exact


def test_dask_cluster_gives_the_local_table():
    distributed = pytest.importorskip("distributed")  # the test extra installs it
    robot = load_robot("ur5")
    grid = {"kp": np.linspace(100, 900, 6)}
    local = sweep(robot, grid, "ct", duration=0.1, chunk_size=2, workers=1)
    seen = []
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        with distributed.Client(cluster) as client:
            remote = sweep(robot, grid, "ct", duration=0.1, chunk_size=2, client=client, progress=lambda d, t: seen.append((d, t)))
    assert local.equals(remote)
    assert seen[-1] == (6, 6) and len(seen) == 3


def test_bad_sweeps_are_refused_naming_the_culprit():
    robot = load_robot("ur5")
    with pytest.raises(ValueError, match="unknown parameter 'kq'"):
        sweep(robot, {"kq": [1.0]})
    with pytest.raises(ValueError, match=r"q0 must be \(6,\)"):
        sweep(robot, [{"q0": [0.0, 1.0]}])
    with pytest.raises(ValueError, match="kp must be finite and >= 0"):
        sweep(robot, {"kp": [-1.0]})
    with pytest.raises(ValueError, match="controller must be one of pd, pdg, ct"):
        sweep(robot, {"kp": [1.0]}, "passive")
    with pytest.raises(ValueError, match="metrics must be some of"):
        sweep(robot, {"kp": [1.0]}, metrics=["rms"])
    with pytest.raises(ValueError, match="computed torque kp is one number"):
        sweep(robot, [{"kp": np.ones(6)}], "ct")


def test_command_line_sweep_writes_csv(tmp_path):
    out = tmp_path / "sweep.csv"
    args = ["sweep", "--robot", "ur5", "--motion", "ct",
            "--kp", "100:1000:4", "--duration", "0.05", "--workers", "1", "--out", str(out)]
    # A process of its own: ProgressBar binds sys.stderr when sweep_cmd is imported, so in
    # this process its bar would go wherever stderr was then (another test's capture).
    done = run_process(*args)
    assert done.returncode == 0, done.stderr
    assert "wrote 4 runs" in done.stdout and "4/4 runs" in done.stderr
    rows = out.read_text().splitlines()
    assert [float(r.split(",")[0]) for r in rows[1:]] == [100.0, 400.0, 700.0, 1000.0]
    bad = run(*args[:6], "100:1000", *args[7:])  # the error line is printed at the call
    assert bad.returncode == 2 and bad.stderr.startswith("robot-sim sweep: error: --kp '100:1000'")
