"""The IK target's analytic branches in a viewer (key B cycles them as the ghost, Shift+B
shows all at once): every closed-form solution of the target pose
(:func:`robot_sim.ik.solutions.ik_solutions`) inside the joint limits, one per posture
(the nearest turn of each: further turns of a joint whose range exceeds 2π look alike),
nearest to the arm's joints when first asked, kept until the target moves or hides."""
from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from robot_sim.kinematics import Kinematics
from robot_sim.model.params import RobotParams
from robot_sim.model.state import RobotState

if TYPE_CHECKING:  # the analytic solver compiles with numba: loaded when first asked
    from robot_sim.ik.solutions import IKSolutions


@dataclass
class Branches:
    """The solutions of one target pose (world 4×4), which of them the ghost shows
    (``index``, None before the first cycle) and whether all are drawn (``show_all``)."""

    solutions: IKSolutions
    index: int | None = None
    show_all: bool = False

    def cycle(self) -> int:
        """The next solution's index (after the last: the first)."""
        self.index = 0 if self.index is None else (self.index + 1) % len(self.solutions)
        return self.index

    def ghosts(self, robot: RobotParams) -> list[tuple[Kinematics, str]]:
        """Every solution's kinematics (world frames updated) and its posture name."""
        shown = []
        for q, name in zip(self.solutions.q, self.solutions.branch):
            state, kin = RobotState(robot), Kinematics(robot)
            state.set_q(q)
            kin.update(state.joint_state)
            shown.append((kin, str(name)))
        return shown


def one_per_posture(solutions: IKSolutions) -> IKSolutions:
    """The first (nearest) solution of each branch code of one pose's ``solutions``, in order."""
    _, first = np.unique(solutions.codes, return_index=True)
    keep = np.sort(first)
    return solutions.take(keep)


def solve_branches(robot: RobotParams, target: np.ndarray, q0: np.ndarray) -> Branches | str:
    """The branches of the world pose ``target`` (4×4) nearest to ``q0`` (n,) first, or the
    status message saying why there are none: no closed form (nor a general 6R's
    elimination), or no solution inside the joint limits."""
    from robot_sim.ik.solutions import ik_solutions, unsolved

    why = unsolved(robot)
    if why is not None:
        return f"IK branches: {robot.name} has {why}"
    solutions = one_per_posture(ik_solutions(robot, target, q0))
    if len(solutions) == 0:
        return "IK branches: no solution of the target inside the joint limits"
    return Branches(solutions)
