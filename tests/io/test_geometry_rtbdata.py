"""Real URDFs with real meshes (the Robotics Toolbox's ``rtb-data`` package, in the test
extra; skipped only where it is not installed): every visual and collision of the chain
loads, meshes through package:// URIs whose packages sit in the URDF's parent folders
(PUMA) or were renamed (ABB, KUKA: found as the parent folder holding the path), and
sampled vertices moved by our forward kinematics are where the URDF's joint chain puts
them."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from geometry_helpers import shape_world, urdf_visual_world
from robot_sim.io.robot_file import load_robot
from robot_sim.kinematics import forward_kinematics, random_configurations
from robot_sim.model.shapes import Mesh
from urdf_helpers import chain, parse

rtbdata = pytest.importorskip("rtbdata")
XACRO = Path(rtbdata.__file__).parent / "xacro"

URDFS = {  # file, tip link
    "puma560": ("unimation_puma560_description/urdf/puma560_robot.urdf", "link7"),
    "irb140": ("abb_irb140_description/urdf/irb140.urdf", "tool0"),
    "iiwa14": ("kuka_description/kuka_lbr_iiwa/urdf/lbr_iiwa_14_r820.urdf", "tool0"),
    "al5d": ("lynxmotion_al5d_description/urdf/al5d_robot.urdf", "link4"),
}


@pytest.mark.parametrize("conv", ["standard", "modified"])
@pytest.mark.parametrize("name", sorted(URDFS))
def test_real_urdf_meshes_sit_on_the_urdf_chain(monkeypatch, name, conv):
    monkeypatch.delenv("ROS_PACKAGE_PATH", raising=False)
    file, tip = URDFS[name]
    path = XACRO / file
    robot = load_robot(path, tip=tip, convention=conv)
    model = parse(path.read_text())
    joints = chain(model, tip)
    links = [model.get_root(), *(j.child for j in joints)]
    # every visual of the chain's links is read, in chain order, the base's before link 1's
    ours = [s for shapes in (robot.base_visuals, *robot.visuals) for s in shapes]
    theirs = [(link, v) for link in links for v in model.link_map[link].visuals]
    assert len(ours) == len(theirs) and len(ours) >= robot.n_dofs
    n_collisions = sum(len(model.link_map[link].collisions) for link in links)
    assert sum(map(len, (robot.base_collisions, *robot.collisions))) == n_collisions
    body = np.repeat(np.arange(robot.n_dofs + 1), [len(robot.base_visuals), *map(len, robot.visuals)])
    rng = np.random.default_rng(5)
    for q in random_configurations(robot, 3, rng):
        frames = forward_kinematics(robot, q, all_frames=True)
        for shape, (link, visual), i in zip(ours, theirs, body):
            assert isinstance(shape, Mesh) and Path(shape.path).is_file()
            pick = rng.choice(len(shape.vertices), size=min(50, len(shape.vertices)), replace=False)
            raw = shape.vertices[pick] / shape.scale  # the file's vertices, read by trimesh
            expected = urdf_visual_world(model, link, visual, q, raw)
            got = shape_world(frames[i], shape)[pick]
            np.testing.assert_allclose(got, expected, atol=1e-9, rtol=0)
