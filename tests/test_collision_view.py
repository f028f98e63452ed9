"""The collision display without a window: what the session shows at a configuration in
and out of collision (touching links, the closest pair, the readout's distance, the
status flag), its pixels (red links in contact), the command line's --world and
--collision, and a passive arm in the viewer resting on its world instead of falling
through it."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from cli_helpers import assert_one_line_error, run
from render_helpers import render  # noqa: F401 (fixture)
from robot_sim import dynamics
from robot_sim.app import prepare
from robot_sim.collision import CollisionChecker
from robot_sim.graphics.collision_scene import collision_parts
from robot_sim.graphics import defs as gd
from robot_sim.io.world_file import load_world
from robot_sim.viewer.session import ViewerSession
from robot_sim.io.robot_file import load_robot

TABLE = """[[obstacles]]
name = "table"
shape = "box"
size = [0.6, 0.6, 0.1]
xyz = [-0.55, -0.1, 0.05]
"""
INTO_TABLE = np.radians([0.0, -30.0, 60.0, -120.0, 0.0, 0.0])  # the UR5's forearm inside the table


@pytest.fixture
def world(tmp_path: Path):
    path = tmp_path / "world.toml"
    path.write_text(TABLE)
    return path


def session_at(world_path: Path, q: np.ndarray) -> ViewerSession:
    session = ViewerSession(load_robot("ur5"), world=load_world(world_path))
    session.set_q(q)
    return session


def test_the_display_shows_who_touches_and_the_closest_pair(world):
    session = session_at(world, INTO_TABLE)
    assert session.scene().collision is None and session.collision_readout() is None
    assert session.toggle_collision()
    shown = session.scene().collision
    checker = CollisionChecker(session.robot, load_world(world))
    expected = checker.distance(INTO_TABLE)
    assert shown.closest.pair == expected.pair == ("link3", "table") and expected.distance < -0.01
    assert shown.closest.distance == pytest.approx(expected.distance, abs=1e-12)
    touching = {name for c in checker.contacts(INTO_TABLE) for name in c.pair}
    assert shown.touching == touching and "link3" in touching and "table" in touching
    assert [name for name, _ in shown.shapes] == [name for name, _ in checker.shapes(INTO_TABLE)]
    assert session.collision_readout() == f"min distance {expected.distance * 1000:+.1f} mm (link3 - table)"
    assert "IN COLLISION: link3 - table" in session.status_text("60 fps")
    # red exactly for the shapes of touching links
    reds = sum(1 for _, colours, _ in collision_parts(shown) for rgba in colours
               if tuple(rgba) == gd.COLLISION_CONTACT_COLOR)
    expected_reds = sum({"capsule": 3, "sphere": 1, "box": 1, "cylinder": 1}[type(s).__name__.lower()]
                        for name, s in shown.shapes if name in touching)
    assert reds == expected_reds


def test_a_free_pose_is_not_flagged(world):
    session = session_at(world, load_robot("ur5").q_home + np.radians([0, -40, 0, 0, 0, 0]))
    session.toggle_collision()
    shown = session.scene().collision
    assert shown.touching == frozenset() and shown.closest.distance > 0
    assert "COLLISION" not in session.status_text("60 fps")


def _red(image: np.ndarray) -> int:
    r, g, b = (image[..., k].astype(int) for k in range(3))
    return int(np.count_nonzero((r > 150) & (g < 80) & (b < 80)))


def test_links_in_contact_are_drawn_red(world, render):  # noqa: F811
    session = session_at(world, INTO_TABLE)
    session.options.show_only_frames([])
    session.fit_camera()
    plain = render(session.camera, session.scene(), session.options)
    session.toggle_collision()
    shown = render(session.camera, session.scene(), session.options)
    free = session_at(world, load_robot("ur5").q_home + np.radians([0, -40, 0, 0, 0, 0]))
    free.options.show_only_frames([])
    free.toggle_collision()
    free_image = render(session.camera, free.scene(), free.options)
    assert _red(shown) > _red(plain) + 200
    assert _red(free_image) < _red(plain) + 20


def test_passive_arm_in_the_viewer_rests_on_the_table(world):
    session = session_at(world, load_robot("ur5").q_home)
    session.set_motion("passive")
    session.motion.simulate(1.5)
    checker = CollisionChecker(session.robot, load_world(world))
    result = checker.distance(session.state.q())
    assert result.pair[1] in ("table", "floor") and -0.005 < result.distance < 0.0
    kinetic, _ = dynamics.energy(session.motion.robot, session.state.q(), session.state.qd())
    assert kinetic < 1e-3  # at rest but for the last joint's free spin (no joint friction in the file)


def test_command_line_world_and_collision(world, tmp_path):
    config = prepare.prepare(
        ["--robot", "ur5", "--world", str(world), "--collision", "--q", "0,-30,60,-120,0,0"])
    session = prepare.session_from_config(config)
    assert session.options.show_collision and session.world.names == ("floor", "table")
    bad = tmp_path / "bad.toml"
    bad.write_text('[[obstacles]]\nname = "x"\nshape = "cone"\n')
    assert_one_line_error(run("--world", str(bad), "--print-dh"), "--world:", "cone")


def test_a_pose_set_into_collision_is_flagged_without_the_display(world):
    untouched = ViewerSession(load_robot("ur5"), world=load_world(world))
    untouched.status_text("60 fps")
    assert untouched._collision is None  # nothing posed: the checker is not even built
    session = session_at(world, INTO_TABLE)  # as the sliders do
    assert not session.options.show_collision
    assert "IN COLLISION: link3 - table" in session.status_text("60 fps")
