"""The closed-form family of an arm: :func:`ik_family` and :class:`IKFamily`.

The family is read from the joint axes at q = 0 (:mod:`robot_sim.ik.classify`), and
kept per robot (weakly, so it goes with the robot) together with what the solver needs.
"""
from __future__ import annotations

import weakref
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from robot_sim.ik.classify import ARM_CASES, Plan, plan
from robot_sim.ik.families import PARALLEL_AXES, POSITION_ONLY, SPHERICAL_WRIST, THREE_PARALLEL
from robot_sim.ik.geometry import Screws, screws
from robot_sim.ik.position import ELBOW_DOWN, ONE_TWO_MEET_SLIDE, SHOULDER_LEFT, WRIST_FLIPPED
from robot_sim.model.params import RobotParams

#: Raw branches per pose of each kernel.
BRANCHES = {SPHERICAL_WRIST: 8, THREE_PARALLEL: 8, PARALLEL_AXES: 2, POSITION_ONLY: 4}
#: The family of a 6R arm without a closed form (solved by :mod:`robot_sim.ik.general`).
GENERAL_6R = "general 6R"
KIND_NAMES = {SPHERICAL_WRIST: "spherical wrist", THREE_PARALLEL: "three parallel axes",
              PARALLEL_AXES: "parallel axes", POSITION_ONLY: "position arm"}


@dataclass(frozen=True)
class IKFamily:
    """An arm's inverse-kinematics family.

    ``name`` is the family ("spherical wrist", "three parallel axes", "parallel axes",
    "position arm", or, when no closed form applies, "general 6R" for six revolute joints,
    solved all the same by :mod:`robot_sim.ik.general`, and "general"); ``arm`` says how the
    first three axes meet where that matters; ``reversed`` that the structure shows when
    the chain is read from the tool back (a spherical shoulder, say); ``free_joint`` the
    0-based index of a 7-joint arm's free joint (None otherwise); ``task`` what the arm
    can place ("pose", "position" of the tool point, or "planar pose": position and the
    turn about the parallel axes); ``branches`` the most branches per pose before turns
    inside the limits; ``postures`` the names its branches carry, when the family names
    them (shoulder, elbow, wrist).
    """

    name: str
    n_joints: int
    closed_form: bool
    arm: str = ""
    reversed: bool = False
    free_joint: int | None = None
    task: str = "pose"
    branches: int = 0
    postures: tuple[str, ...] = ()

    def __repr__(self) -> str:
        parts = [self.arm] if self.arm else []
        if self.reversed:
            parts.append("read from the tool")
        if self.free_joint is not None:
            parts.append(f"joint {self.free_joint + 1} free")
        parts.append(f"{self.task}, up to {self.branches} branches" if self.closed_form else "no closed form")
        return f"<IKFamily {self.name} ({self.n_joints} joints): {'; '.join(parts)}>"


@dataclass(frozen=True)
class Solver:
    """What :func:`robot_sim.ik.solutions.ik_solutions` needs of a robot: its screws, the
    plan (None for a general arm), its family, and its home configuration as a writable
    array (the compiled kernels take writable arrays; the robot's are read only)."""

    screws: Screws
    plan: Plan | None
    family: IKFamily
    size: float
    names: NDArray[np.str_]  # branch number -> name, and '' (index -1) for padding
    home: NDArray[np.float64]
    prepared: dict = field(default_factory=dict)  # "rows": the packed chain, constant rows, joint order


_SOLVERS: "weakref.WeakKeyDictionary[RobotParams, Solver]" = weakref.WeakKeyDictionary()


def _postures(p: Plan) -> tuple[str, ...]:
    """Posture names by branch bits, where the family has textbook names."""
    if p.reversed or p.free is not None:
        return ()
    if p.kind == PARALLEL_AXES:
        pair = ("elbow up", "elbow down") if p.idx[3] < 0 else ("left arm", "right arm")
        return tuple(pair[bool(bits & ELBOW_DOWN)] for bits in range(8))
    shoulder = ("shoulder right", "shoulder left")
    elbow = ("elbow up", "elbow down")
    wrist = ("wrist not flipped", "wrist flipped")
    names = []
    for bits in range(8):
        parts = [shoulder[bool(bits & SHOULDER_LEFT)]]
        if p.case != ONE_TWO_MEET_SLIDE:
            parts.append(elbow[bool(bits & ELBOW_DOWN)])
        if p.kind != POSITION_ONLY:
            parts.append(wrist[bool(bits & WRIST_FLIPPED)])
        names.append(", ".join(parts))
    return tuple(names)


def solver(robot: RobotParams) -> Solver:
    """The robot's solver data, built once per robot."""
    found = _SOLVERS.get(robot)
    if found is not None:
        return found
    S = screws(robot)
    size = robot.size
    p = plan(S, size)
    if p is None:
        name = GENERAL_6R if robot.n_dofs == 6 and S.revolute.all() else "general"
        family = IKFamily(name, robot.n_dofs, False)
    else:
        task = {POSITION_ONLY: "position", PARALLEL_AXES: "planar pose"}.get(p.kind, "pose")
        family = IKFamily(KIND_NAMES[p.kind], robot.n_dofs, True, ARM_CASES[p.case] if p.kind in
                          (SPHERICAL_WRIST, POSITION_ONLY) else "", p.reversed, p.free, task,
                          BRANCHES[p.kind], _postures(p))
    found = Solver(S, p, family, size, np.array((family.postures or tuple(f"branch {b}" for b in range(8))) + ("",)),
                   np.array(robot.q_home, dtype=float))
    _SOLVERS[robot] = found
    return found


def ik_family(robot: RobotParams) -> IKFamily:
    """The closed-form family of ``robot``'s inverse kinematics, found from its joint axes
    (either DH convention, base and tool included) with a tolerance; see
    :class:`IKFamily`."""
    if not isinstance(robot, RobotParams):
        raise ValueError(f"ik_family needs a RobotParams, got {type(robot).__name__}")
    return solver(robot).family
