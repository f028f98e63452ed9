"""Optional: one simulation step against MuJoCo's ``mj_step`` on the same arm, same run.

MuJoCo is not a dependency of this project (``pip install mujoco`` to run this).  Each
arm is exported through our URDF writer and loaded by MuJoCo's URDF importer with
contacts off, RK4 at 1 kHz (as ``Simulation`` runs it).  Before timing, both simulate
1 s passively from the same state and must agree (MuJoCo's URDF import keeps no drive
terms, so the arms are compared without drives).  Then, alternated and the median of :data:`ROUNDS`:

* MuJoCo ``mj_step`` (passive);
* ``Simulation.step`` passive RK4, per step of ``step(500)`` (target ≤ 3× mj_step), and
  one ``step()`` call on its own (which also writes the state to the RobotState);
* ``Simulation.step`` RK4 + computed torque (target ≤ 1.2× our passive step);
* ``BatchSimulation`` RK4 + computed torque at n_envs = 1000, per arm-step (target ≤ 1× mj_step).

    python benchmarks/compare_mujoco.py [--robots ur5 panda humanoid7]
"""
from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path
from typing import Callable

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import mujoco  # noqa: E402

from oracle_arms import without_drives  # noqa: E402
from robot_sim.sim.batch import BatchSimulation  # noqa: E402
from robot_sim.control.controllers import ComputedTorque, control_gains  # noqa: E402
from robot_sim.sim.simulation import Simulation  # noqa: E402
from robot_sim.io.robot_file import load_robot  # noqa: E402
from robot_sim.io.urdf_out import to_urdf  # noqa: E402
from robot_sim.model.params import RobotParams  # noqa: E402

STEPS = 500
DT = 1e-3
N_ENVS = 1000
BATCH_STEPS = 5
ROUNDS = 5  # alternated rounds; the median is reported


def mujoco_model(robot: RobotParams) -> tuple[mujoco.MjModel, mujoco.MjData]:
    """The arm in MuJoCo: our URDF, contacts off, RK4 at :data:`DT`."""
    model = mujoco.MjModel.from_xml_string(to_urdf(robot))
    model.opt.timestep = DT
    model.opt.integrator = mujoco.mjtIntegrator.mjINT_RK4
    model.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_CONTACT
    return model, mujoco.MjData(model)


def agreement(robot: RobotParams, q0: np.ndarray) -> float:
    """Largest joint-angle difference [rad] after 1 s of passive motion from q0."""
    model, data = mujoco_model(robot)
    data.qpos[:] = q0
    sim = Simulation(robot, dt=DT)
    sim.q, sim.qd = q0.copy(), np.zeros(robot.n_dofs)
    for _ in range(int(1.0 / DT)):
        mujoco.mj_step(model, data)
    sim.step(int(1.0 / DT))
    return float(np.abs(sim.q - data.qpos).max())


def per_call(fn: Callable[[], object], calls: int) -> float:
    """Seconds per call of ``fn`` over ``calls`` calls."""
    start = time.perf_counter()
    for _ in range(calls):
        fn()
    return (time.perf_counter() - start) / calls


def compare(name: str) -> None:
    robot = without_drives(load_robot(name), limits=False)
    q0 = robot.q_home + 0.2
    print(f"{name}: |q_ours - q_mujoco| after 1 s passive = {agreement(robot, q0):.1e} rad")
    model, data = mujoco_model(robot)
    passive = Simulation(robot, dt=DT, integrator="rk4")
    ct = Simulation(robot, controller=ComputedTorque(robot, control_gains(robot)), dt=DT, integrator="rk4")
    ct.state.set_q_des(robot.q_home + 0.3)
    batch = BatchSimulation(robot, N_ENVS, controller="ct", integrator="rk4", dt=DT)
    batch.set_reference(q=robot.q_home + 0.3)
    rows: dict[str, list[float]] = {"mj_step": [], "passive": [], "ct": [], "step()": [], "batch": []}
    for _ in range(ROUNDS):  # alternated, median
        rows["mj_step"].append(per_call(lambda: mujoco.mj_step(model, data), STEPS))
        rows["passive"].append(per_call(lambda: passive.step(STEPS), 1) / STEPS)
        rows["ct"].append(per_call(lambda: ct.step(STEPS), 1) / STEPS)
        rows["step()"].append(per_call(lambda: passive.step(), STEPS))
        rows["batch"].append(per_call(lambda: batch.step(), BATCH_STEPS) / N_ENVS)
        for sim in (passive, ct):
            sim.load_state()
    med = {k: statistics.median(v) for k, v in rows.items()}
    mj = med["mj_step"]
    print(f"  mj_step                          {mj * 1e6:7.1f} µs")
    print(f"  Simulation.step passive RK4      {med['passive'] * 1e6:7.1f} µs  {med['passive'] / mj:4.2f}× mj_step (≤ 3)")
    print(f"  Simulation.step RK4 + CT         {med['ct'] * 1e6:7.1f} µs  {med['ct'] / med['passive']:4.2f}× passive (≤ 1.2)")
    print(f"  one Simulation.step() call       {med['step()'] * 1e6:7.1f} µs  (passive; writes the RobotState each call)")
    print(f"  BatchSimulation CT, {N_ENVS} envs  {med['batch'] * 1e6:7.2f} µs/arm-step  {med['batch'] / mj:4.2f}× mj_step (≤ 1)")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--robots", nargs="+", default=["ur5", "panda", "humanoid7"])
    for name in parser.parse_args().robots:
        compare(name)


if __name__ == "__main__":
    main()
