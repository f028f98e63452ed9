"""Analytic IK on random DH tables of each family, in both conventions (issue 29): the
family is found from the axes, and the solutions are complete, exact and distinct."""
from __future__ import annotations

import numpy as np
import pytest

from ik_helpers import check_complete
from kin_helpers import CONVENTIONS
from robot_sim.ik.family import ik_family
from robot_sim.kinematics import random_configurations
from robot_sim.model.convert import to_convention
from robot_sim.model.params import RobotParams
from robot_sim.transforms import HomogeneousTransform, rot_from_rpy

TABLES = 6  # random tables per family
POSES = 30  # random configurations per table


def _twist(rng: np.random.Generator) -> float:
    """A twist angle neither 0 nor 180° (so consecutive axes are not parallel)."""
    return float(rng.choice([-1.0, 1.0]) * rng.uniform(0.3, 2.8))


def _placed(rng: np.random.Generator) -> dict:
    """A random base and tool (both folded into the chain by the solver)."""
    def tf() -> HomogeneousTransform:
        return HomogeneousTransform.from_rt(rot_from_rpy(rng.uniform(-np.pi, np.pi, 3)), rng.uniform(-0.3, 0.3, 3))
    return {"base_tf": tf(), "tool_tf": tf()}


def spherical_wrist(rng: np.random.Generator, arm: str) -> RobotParams:
    """Standard DH: a4 = a5 = d5 = 0 makes axes 4, 5, 6 meet; α2 = 0 makes axes 2 and 3
    parallel ("parallel"), a1 = d2 = 0 makes axes 1 and 2 meet ("meet")."""
    a = rng.uniform(0.05, 0.5, 6)
    d = rng.uniform(-0.3, 0.3, 6)
    alpha = np.array([_twist(rng) for _ in range(6)])
    a[3] = a[4] = d[4] = 0.0
    if arm == "parallel":
        alpha[1] = 0.0
    else:
        a[0] = d[1] = 0.0
    return RobotParams.from_arrays(f"random wrist {arm}", a, alpha, d, rng.uniform(-np.pi, np.pi, 6), np.zeros(6),
                                   q_min=np.full(6, -np.pi), q_max=np.full(6, np.pi), **_placed(rng))


def three_parallel(rng: np.random.Generator) -> RobotParams:
    """α2 = α3 = 0: axes 2, 3, 4 parallel; a5 = 0: axes 5 and 6 meet."""
    a = rng.uniform(0.05, 0.5, 6)
    d = rng.uniform(-0.3, 0.3, 6)
    alpha = np.array([_twist(rng) for _ in range(6)])
    alpha[1] = alpha[2] = 0.0
    a[4] = 0.0
    return RobotParams.from_arrays("random UR", a, alpha, d, rng.uniform(-np.pi, np.pi, 6), np.zeros(6),
                                   q_min=np.full(6, -np.pi), q_max=np.full(6, np.pi), **_placed(rng))


def stanford_like(rng: np.random.Generator) -> RobotParams:
    """RRP arm (axes 1 and 2 meet, joint 3 slides) with a spherical wrist."""
    a = np.zeros(6)
    d = rng.uniform(0.05, 0.4, 6)
    alpha = np.array([_twist(rng) for _ in range(6)])
    d[1] = d[2] = d[4] = 0.0
    jtype = np.array([0, 0, 1, 0, 0, 0])
    return RobotParams.from_arrays("random RRP", a, alpha, d, rng.uniform(-np.pi, np.pi, 6), jtype,
                                   q_min=np.r_[np.full(2, -np.pi), 0.2, np.full(3, -np.pi)],
                                   q_max=np.r_[np.full(2, np.pi), 0.9, np.full(3, np.pi)],
                                   q_home=[0.0, 0.0, 0.5, 0.0, 0.0, 0.0], **_placed(rng))


def position_arm(rng: np.random.Generator) -> RobotParams:
    """Three revolute joints, axes 1 and 2 meeting."""
    a = rng.uniform(0.1, 0.5, 3)
    a[0] = 0.0
    d = rng.uniform(-0.3, 0.3, 3)
    d[1] = 0.0
    alpha = np.array([_twist(rng) for _ in range(3)])
    return RobotParams.from_arrays("random position arm", a, alpha, d, rng.uniform(-np.pi, np.pi, 3), np.zeros(3),
                                   q_min=np.full(3, -np.pi), q_max=np.full(3, np.pi), **_placed(rng))


def planar(rng: np.random.Generator) -> RobotParams:
    """Three parallel revolute axes (random lengths, offsets along the axes)."""
    return RobotParams.from_arrays("random planar", rng.uniform(0.1, 0.5, 3), np.zeros(3), rng.uniform(-0.2, 0.2, 3),
                                   rng.uniform(-np.pi, np.pi, 3), np.zeros(3),
                                   q_min=np.full(3, -np.pi), q_max=np.full(3, np.pi), **_placed(rng))


def srs(rng: np.random.Generator) -> RobotParams:
    """A 7-joint arm with a spherical shoulder and wrist (iiwa-like), random lengths."""
    d = np.array([rng.uniform(0.1, 0.4), 0.0, rng.uniform(0.2, 0.5), 0.0, rng.uniform(0.2, 0.5), 0.0,
                  rng.uniform(0.05, 0.2)])
    alpha = np.array([-1, 1, 1, -1, -1, 1, 0]) * np.pi / 2
    return RobotParams.from_arrays("random SRS", np.zeros(7), alpha, d, np.zeros(7), np.zeros(7),
                                   q_min=np.full(7, -np.pi), q_max=np.full(7, np.pi), **_placed(rng))


BUILDERS = {
    ("spherical wrist", "parallel"): lambda rng: spherical_wrist(rng, "parallel"),
    ("spherical wrist", "meet"): lambda rng: spherical_wrist(rng, "meet"),
    ("three parallel axes", ""): three_parallel,
    ("spherical wrist", "slide"): stanford_like,
    ("position arm", ""): position_arm,
    ("parallel axes", ""): planar,
    ("spherical wrist", "7"): srs,
}


@pytest.mark.parametrize(("family", "variant"), sorted(BUILDERS))
@pytest.mark.parametrize("convention", CONVENTIONS)
def test_random_tables_of_each_family(family: str, variant: str, convention: str) -> None:
    rng = np.random.default_rng(hash((family, variant)) % 2**32)
    for _ in range(TABLES):
        arm = to_convention(BUILDERS[(family, variant)](rng), convention)
        assert ik_family(arm).name == family, (arm, ik_family(arm))
        check_complete(arm, random_configurations(arm, POSES, rng))


def test_a_general_6r_table_has_no_closed_form() -> None:
    rng = np.random.default_rng(6)
    arm = RobotParams.from_arrays("general", rng.uniform(0.1, 0.5, 6), [_twist(rng) for _ in range(6)],
                                  rng.uniform(0.1, 0.3, 6), np.zeros(6), np.zeros(6))
    family = ik_family(arm)
    assert family.name == "general 6R" and not family.closed_form
    assert repr(family) == "<IKFamily general 6R (6 joints): no closed form>"
