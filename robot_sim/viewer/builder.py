"""The one builder of viewer sessions: the command line, the window and ``rs.Visualizer``
describe what to show as a :class:`SessionSpec` and get a framed
:class:`~robot_sim.viewer.session.ViewerSession` from :func:`build_session` (no Qt, no GL).

Joint values are SI (rad, m); sizes in pixels; times in seconds.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from robot_sim import graphics as go
from robot_sim.model.params import RobotParams
from robot_sim.model.world import World
from robot_sim.viewer.session import ViewerSession

if TYPE_CHECKING:
    from robot_sim.planning.pick_task import TaskPlan

#: The demos a session can start with.
DEMOS = ("circle", "pick")


@dataclass(frozen=True)
class PickShow:
    """A planned pick task to show from ``time`` [s]; ``effort`` (N, n) and ``mode`` when
    the plan holds a run simulated in that motion mode (control.MOTION_MODES)."""

    plan: TaskPlan
    time: float = 0.0
    effort: np.ndarray | None = None
    mode: str = "kinematic"


@dataclass(frozen=True)
class SessionSpec:
    """What a session shows and how it starts.

    ``size`` (width, height) px gives the framing's aspect; ``q`` (n,) the start joints
    (None: home); ``theme`` one of graphics.THEMES (None: the default), ``look`` one of the
    robot's looks (None: its default); ``world`` the obstacles (None: the floor);
    ``gains`` control.control_gains keywords; ``motion`` a physical mode simulated for
    ``simulate`` seconds first (None: kinematic); ``frames`` exactly the frames shown
    (n_dofs + 1 = endeffector; None: the base frame); ``annotate`` the joint (1..n) whose
    DH parameters are drawn; ``trail`` the endeffector trail; ``demo`` "circle" to start
    the circle demo; ``pick`` a pick task to play; ``workspace`` a cloud to show;
    ``ik_branches`` every analytic IK branch of the start pose drawn (key Shift+B).
    """

    robot: RobotParams
    size: tuple[int, int] = (1024, 768)
    q: np.ndarray | None = None
    theme: str | None = None
    look: str | None = None
    world: World | None = None
    gains: dict[str, Any] = field(default_factory=dict)
    motion: str | None = None
    simulate: float = 0.0
    frames: list[int] | None = None
    wireframe: bool = False
    collision: bool = False
    annotate: int | None = None
    trail: bool = False
    demo: str | None = None
    pick: PickShow | None = None
    workspace: go.WorkspaceCloud | None = None
    ik_branches: bool = False


def check_style(robot: RobotParams, theme: str | None, look: str | None) -> None:
    """ValueError unless ``theme`` is None or one of graphics.THEMES and ``look`` None or
    one of the looks ``robot`` can be drawn in (graphics.looks_of)."""
    if theme is not None and theme not in go.THEMES:
        raise ValueError(f"theme: expected one of {', '.join(go.THEMES)}, got {str(theme)[:80]!r}")
    if look is not None and look not in go.looks_of(robot):
        raise ValueError(f"look: robot '{robot.name}' can be drawn as {', '.join(go.looks_of(robot))}; "
                         f"got {str(look)[:80]!r}")


def build_session(spec: SessionSpec) -> ViewerSession:
    """A session showing ``spec``, framed for all of it.  ValueError (nothing built) for a
    bad theme, look or demo; ValueError with the reason when ``ik_branches`` finds none; ValueError from the motion mode when the dynamics refuse the
    robot or the first ``simulate`` seconds stop at a joint's stop."""
    check_style(spec.robot, spec.theme, spec.look)
    if spec.demo not in (None, *DEMOS):
        raise ValueError(f"demo: expected one of {', '.join(DEMOS)}, got {str(spec.demo)[:80]!r}")
    width, height = spec.size
    session = ViewerSession(spec.robot, aspect=width / height, gain_overrides=dict(spec.gains), world=spec.world)
    options = session.options
    options.show_collision = spec.collision
    if spec.q is not None:
        session.set_q(spec.q)
    if spec.trail and spec.pick is None:  # from the start pose on (a pick task: from its start)
        session.toggle_trail()
    if spec.motion is not None and spec.pick is None:  # a simulated pick run is replayed
        session.set_motion(spec.motion)
        session.simulate(spec.simulate)
        if session.motion.sim.stopped:
            raise ValueError(str(session.motion.sim.stopped))
    if spec.frames is not None:
        options.show_only_frames(spec.frames)
    options.wireframe = spec.wireframe
    if spec.theme is not None:
        options.theme = spec.theme
    options.look = spec.look
    if spec.pick is not None:
        session.start_pick(spec.pick.plan, spec.pick.time, spec.pick.effort, spec.pick.mode)
        if spec.trail:
            session.toggle_trail()
    options.annotate_joint = spec.annotate
    if spec.ik_branches:
        shown = session.toggle_all_branches()
        if isinstance(shown, str):
            raise ValueError(shown)
    if spec.workspace is not None:
        session.workspace = spec.workspace
        options.show_workspace = True
    session.fit_camera(on_annotation=spec.annotate is not None)
    if spec.demo == "circle":
        session.toggle_demo()
    return session
