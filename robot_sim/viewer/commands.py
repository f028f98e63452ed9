"""Key actions that change only the session (options, camera, IK target, trail, demo), as
Qt-free commands: :data:`COMMANDS` maps an action name of the window's KEY_BINDINGS
(robot_sim.qt.settings) to a function of the session and the binding's argument that
returns the status message to show, or None.  The window dispatches its keys through this
table and adds the few actions that need its widgets (help, files, chooser, screenshot).

Steps are in robot_sim.viewer.settings: KEY_ZOOM_FACTOR, KEY_ORBIT_STEP_DEG (degrees),
TARGET_STEP_M (metres, world axes), TARGET_STEP_DEG, VIEW_PRESETS.
"""
from __future__ import annotations

import math
from typing import Any, Callable

import numpy as np

from robot_sim import graphics as go
from robot_sim.viewer import settings as vs
from robot_sim.viewer.session import ViewerSession

Command = Callable[[ViewerSession, Any], "str | None"]

UNREACHABLE = "IK target unreachable: the ghost stays at the last reachable pose"


def _flip(name: str) -> Command:
    """Flip the boolean option ``name`` silently."""
    def command(session: ViewerSession, _: None) -> None:
        setattr(session.options, name, not getattr(session.options, name))
    return command


def toggle_wireframe(session: ViewerSession, _: None) -> None:
    session.options.toggle_wireframe()


def cycle_look(session: ViewerSession, _: None) -> str:
    """The robot's next look (graphics.looks_of: meshes, DH, both, solid)."""
    robot, options = session.robot, session.options
    return f"look: {options.cycle_look(go.looks_of(robot), go.look_for(robot, options.look))}"


def toggle_alpha(session: ViewerSession, _: None) -> None:
    session.options.toggle_alpha()


def toggle_all_frames(session: ViewerSession, _: None) -> None:
    session.options.toggle_all_frames()


def toggle_frame(session: ViewerSession, index: int) -> str | None:
    """Show or hide DH frame ``index``."""
    if session.options.toggle_frame(index):
        return None
    return f"{session.robot.name} has no frame {index} (frames 0..{session.n_frames - 1})"


def zoom(session: ViewerSession, steps: int) -> None:
    """Camera distance times KEY_ZOOM_FACTOR ** ``steps`` (< 0 zooms in)."""
    session.camera.zoom(vs.KEY_ZOOM_FACTOR ** steps)


def orbit(session: ViewerSession, steps: tuple[int, int]) -> None:
    """Orbit by (azimuth, elevation) steps of KEY_ORBIT_STEP_DEG."""
    session.camera.orbit(steps[0] * vs.KEY_ORBIT_STEP_DEG, steps[1] * vs.KEY_ORBIT_STEP_DEG)


def reset_view(session: ViewerSession, _: None) -> None:
    session.fit_camera()


def view_preset(session: ViewerSession, name: str) -> str:
    """Look from the front, side, top or iso direction (VIEW_PRESETS)."""
    session.camera.set_view(*vs.VIEW_PRESETS[name])
    return f"view: {name}"


def toggle_orthographic(session: ViewerSession, _: None) -> str:
    camera = session.camera
    camera.orthographic = not camera.orthographic
    return "orthographic projection" if camera.orthographic else "perspective projection"


def toggle_follow(session: ViewerSession, _: None) -> str:
    return "camera follows the endeffector" if session.toggle_follow() else "camera stays put"


def toggle_trail(session: ViewerSession, _: None) -> str:
    return "endeffector trail on" if session.toggle_trail() else "endeffector trail off"


def toggle_collision(session: ViewerSession, _: None) -> str:
    shown = session.toggle_collision()
    return "collision display " + ("on: shapes, contacts in red, closest pair" if shown else "off")


def toggle_demo(session: ViewerSession, _: None) -> str:
    return "circle demo " + ("started" if session.toggle_demo() else "stopped")


def toggle_target(session: ViewerSession, _: None) -> None:
    session.toggle_target()


def move_target(session: ViewerSession, axis_sign: tuple[int, int]) -> str | None:
    """Move the IK target by TARGET_STEP_M along world axis ``axis`` (0..2) times ``sign``."""
    axis, sign = axis_sign
    return None if session.move_target(translation=sign * vs.TARGET_STEP_M * np.eye(3)[axis]) else UNREACHABLE


def rotate_target(session: ViewerSession, axis_sign: tuple[int, int]) -> str | None:
    """Rotate the IK target by TARGET_STEP_DEG about world axis ``axis`` times ``sign``."""
    axis, sign = axis_sign
    step = sign * math.radians(vs.TARGET_STEP_DEG) * np.eye(3)[axis]
    return None if session.move_target(rpy=step) else UNREACHABLE


def cycle_branch(session: ViewerSession, _: None) -> str:
    """Show the IK target's next analytic branch as the ghost (ViewerSession.cycle_branch)."""
    shown = session.cycle_branch()
    if isinstance(shown, str):
        return shown
    index, count, name = shown
    return f"IK branch {index + 1} of {count}: {name}"


def toggle_all_branches(session: ViewerSession, _: None) -> str:
    """Draw every analytic branch of the IK target at once, or stop."""
    count = session.toggle_all_branches()
    if isinstance(count, str):
        return count
    return f"all {count} IK branches shown" if count else "IK branches hidden"


def go_home(session: ViewerSession, _: None) -> None:
    session.set_q(np.array(session.robot.q_home))


#: Action name (KEY_BINDINGS column 3) -> command taking the session and the row's argument.
COMMANDS: dict[str, Command] = {
    "toggle_wireframe": toggle_wireframe,
    "cycle_look": cycle_look,
    "toggle_alpha": toggle_alpha,
    "toggle_all_frames": toggle_all_frames,
    "toggle_frame": toggle_frame,
    "zoom": zoom,
    "orbit": orbit,
    "reset_view": reset_view,
    "toggle_vectors": _flip("show_vectors"),
    "toggle_labels": _flip("show_labels"),
    "toggle_com": _flip("show_com"),
    "toggle_collision": toggle_collision,
    "toggle_demo": toggle_demo,
    "toggle_target": toggle_target,
    "move_target": move_target,
    "rotate_target": rotate_target,
    "view_preset": view_preset,
    "toggle_orthographic": toggle_orthographic,
    "toggle_follow": toggle_follow,
    "toggle_trail": toggle_trail,
    "cycle_branch": cycle_branch,
    "toggle_all_branches": toggle_all_branches,
    "go_home": go_home,
}

#: The commands that can set the arm moving (a view then starts stepping the session).
STARTS_MOTION = frozenset({"toggle_demo", "toggle_target", "move_target", "rotate_target", "cycle_branch",
                           "go_home"})
