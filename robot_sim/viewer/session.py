"""What a viewer shows, without Qt: :class:`ViewerSession` holds one robot's current and
desired joint state, their kinematics, the camera, the graphics options, the IK target,
the workspace cloud, the endeffector trail and the one driver that moves the arm
(robot_sim.viewer.drivers), and turns them into a ``robot_sim.graphics.Scene``.

Whatever depends on what moves the arm (a still pose, a simulation, the circle demo, a
pick task played) the session asks its driver; switching the motion mode or starting a
demo replaces the driver, and the options, camera, trail and target stay.

The Qt window (robot_sim.qt), the command line's ``--screenshot`` and ``--record``
(robot_sim.app) and :class:`robot_sim.viewer.visualizer.Visualizer` all show a session;
offscreen ones render it through OSMesa without importing Qt at all.

Units: joint values are radians (revolute) and metres (prismatic); positions are in
metres in the world frame (display units: robot_sim.viewer.units).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from robot_sim import graphics as go
from robot_sim.graphics import defs as gd
from robot_sim.kinematics import IKResult, Kinematics, ik_position_only_required
from robot_sim.model.params import RobotParams
from robot_sim.model.state import RobotState
from robot_sim.model.world import World
from robot_sim.transforms import HomogeneousTransform, rotation_log
from robot_sim.viewer import settings as vs
from robot_sim.viewer.branches import Branches
from robot_sim.viewer.dh_table import carry_joint_values
from robot_sim.viewer.drivers import Driver, StillDriver, motion_driver
from robot_sim.viewer.drivers.circle import CircleDriver
from robot_sim.viewer.drivers.circle_path import DemoCircle
from robot_sim.viewer.target import TargetControl
from robot_sim.viewer.trail import Trail

if TYPE_CHECKING:  # these pull the planner, the checker and the simulation (numba): loaded on use
    from robot_sim.sim.stops import LimitEvent
    from robot_sim.planning.pick_task import TaskPlan
    from robot_sim.viewer.collision_display import CollisionDisplay
    from robot_sim.viewer.motion import Motion
    from robot_sim.viewer.pick_demo import PickDemo

#: A drawn arrow: start (3,) and vector (3,) in the world [m], and its RGBA colour.
Arrow = tuple[np.ndarray, np.ndarray, tuple[float, ...]]


@dataclass
class ViewerSession(TargetControl):
    """What a viewer shows, without Qt: one robot's state, kinematics, camera and options,
    what moves it (:attr:`driver`, one at a time), the endeffector trail and whether the
    camera follows the endeffector.

    ``state.joint_state`` is drawn as the robot, ``state.joint_state_des`` as the ghost.
    The IK target ``target_tf`` is a world pose (robot_sim.viewer.target); moving it
    solves IK from the desired q and the current q then follows with :meth:`step`.
    """

    robot: RobotParams
    aspect: float = 1.0  # viewport width / height, for framing the robot
    state: RobotState = field(init=False)
    kin: Kinematics = field(init=False)
    ghost: Kinematics = field(init=False)
    camera: go.Camera = field(init=False)
    options: go.GraphicsOptions = field(init=False)
    target_tf: HomogeneousTransform | None = None
    ik_result: IKResult | None = None
    workspace: go.WorkspaceCloud | None = None
    #: What moves the arm (drivers/): still, simulated, circle demo or pick playback.
    driver: Driver = field(default_factory=StillDriver)
    #: Gain overrides of the physical motion modes (control.control_gains keywords).
    gain_overrides: dict[str, Any] = field(default_factory=dict)
    #: Joint-limit arrivals of the simulation since the window last took them.
    limit_events: list[LimitEvent] = field(default_factory=list)
    #: The obstacles the arm collides with and, simulated, rests on (None: the floor).
    world: World | None = None
    #: The endeffector's recent path, drawn as a line (None: no trail).
    trail: Trail | None = None
    #: Whether the camera's target follows the endeffector.
    follow: bool = False
    #: The IK target's analytic branches (keys B, Shift+B), None until asked and after the target moves.
    branches: Branches | None = None
    _motion: Motion | None = field(default=None, init=False, repr=False)
    _collision: CollisionDisplay | None = field(default=None, init=False, repr=False)
    #: Whether the joints were set (sliders, boxes, IK, --q): from then on the status bar
    #: flags a pose in collision (the checker is loaded only when there is a pose to flag).
    _posed: bool = field(default=False, init=False, repr=False)

    def __post_init__(self) -> None:
        self.state = RobotState(self.robot)
        self.kin = Kinematics(self.robot)
        self.ghost = Kinematics(self.robot)
        self.options = go.GraphicsOptions(self.n_frames)
        self.camera = go.Camera()
        self.update_kinematics()
        self.fit_camera()

    @property
    def n_frames(self) -> int:
        """Number of joint frames that can be shown: frame 0 (base) to frame n."""
        return self.robot.n_dofs + 1

    def update_kinematics(self) -> None:
        """Recompute the world frames of the current (robot) and desired (ghost) state;
        extend the trail and move a following camera's target to the endeffector."""
        self.kin.update(self.state.joint_state)
        self.ghost.update(self.state.joint_state_des)
        if self.trail is not None:
            self.trail.add(self.kin.endeff_tf.t())
        if self.follow:
            self.camera.target = self.kin.endeff_tf.t().copy()

    def fit_camera(self, on_annotation: bool = False) -> None:
        """Reset the camera and frame everything drawn (``robot_sim.graphics.visible_points``):
        the arm at its current pose, the floor under its base, the drawn frames, the IK
        target and the workspace cloud when shown (world, m).  With ``on_annotation`` and
        a joint annotated, frame that joint's DH annotation and its two frames only, so
        its dimensions, arcs and labels are large enough to read.  The driver may turn
        the camera first (during the pick task, until the table hides none of the arm)."""
        self.camera.reset()
        focus = go.annotation_points(self.scene(), self.options) if on_annotation else None
        if focus is None:
            focus = go.visible_points(self.scene(), self.options)
            self.driver.aim(self.camera, focus, self.aspect)
        self.camera.fit(focus, self.aspect)
        if self.follow:
            self.camera.target = self.kin.endeff_tf.t().copy()

    def with_robot(self, robot: RobotParams, keep_q: bool = True) -> ViewerSession:
        """A session showing ``robot`` with this one's options, world, gains (those that do
        not count joints), trail (emptied), follow camera and projection.  With ``keep_q``
        the joint values (carried over joint by joint, robot_sim.viewer.dh_table), the
        camera and, for the same number of joints, the frame choice and the annotated joint
        stay; otherwise the new robot is at home and framed anew."""
        gains = {k: v for k, v in self.gain_overrides.items() if k in ("bandwidth", "damping")}
        new = ViewerSession(robot, aspect=self.aspect, gain_overrides=gains, world=self.world, follow=self.follow)
        for flag in ("wireframe", "alpha", "show_vectors", "show_labels", "show_com", "theme", "look",
                     "show_collision", "samples", "shadows"):
            setattr(new.options, flag, getattr(self.options, flag))
        new.camera.orthographic = self.camera.orthographic
        if self.trail is not None:
            new.trail = Trail()
        if keep_q:
            new.set_q(carry_joint_values(self.robot, self.state.q(), robot))
            new.camera = self.camera
            if robot.n_dofs == self.robot.n_dofs:
                new.options.show_frames = list(self.options.show_frames)
                new.options.show_endeff_frame = self.options.show_endeff_frame
                new.options.annotate_joint = self.options.annotate_joint
        return new

    # ---- trail and follow camera ----
    def toggle_trail(self) -> bool:
        """Start drawing the endeffector's path from here, or stop and forget it; returns
        whether the trail is on."""
        self.trail = Trail() if self.trail is None else None
        if self.trail is not None:
            self.trail.add(self.kin.endeff_tf.t())
        return self.trail is not None

    def toggle_follow(self) -> bool:
        """Keep the camera aimed at the endeffector (its target follows it) or stop;
        returns whether it follows."""
        self.follow = not self.follow
        if self.follow:
            self.camera.target = self.kin.endeff_tf.t().copy()
        return self.follow

    # ---- the driver: motion mode and demos ----
    @property
    def motion(self) -> Motion:
        """The robot's motion modes and simulation, built on first use (dynamics are
        imported and the gains computed only when a physical mode is wanted)."""
        if self._motion is None:
            from robot_sim.viewer.motion import Motion  # dynamics, collision: numba

            self._motion = Motion(self.robot, self.state, self.gain_overrides, self.world)
        return self._motion

    @property
    def physical(self) -> bool:
        """True while the arm is simulated (any motion mode but kinematic)."""
        return self.driver.physical

    @property
    def task_space(self) -> bool:
        """True in a task-space motion mode (operational space, impedance): the IK target,
        dragged, is the tool's desired pose itself (no IK), and the circle demo a Cartesian
        reference."""
        return self.driver.task_space

    @property
    def demo(self) -> DemoCircle | None:
        """The running circle demo, or None."""
        return self.driver.circle

    @property
    def pick(self) -> PickDemo | None:
        """The pick task being shown (played or paused), or None."""
        return self.driver.pick

    def set_motion(self, mode: str) -> None:
        """Switch the motion mode (control.MOTION_MODES): its driver replaces the motion
        driver, under a demo if one runs (the demo keeps running over it).  In a
        task-space mode a shown IK target becomes the tool's desired pose."""
        self.motion.set_mode(mode)
        self.driver = self.driver.over(motion_driver(self.motion))
        self.driver.engage(self)
        self.update_kinematics()

    def simulate(self, duration: float) -> None:
        """Simulate ``duration`` seconds at once in the physical mode set (``--duration``);
        ValueError in kinematic mode."""
        self.driver.base.simulate(self, duration)

    def toggle_demo(self) -> bool:
        """Start the circle demo at the current endeffector position, or stop it (the arm
        then rests where it is: a task-space controller holds it there)."""
        if isinstance(self.driver, CircleDriver):
            self.driver = self.driver.stop(self)
            return False
        self.driver = CircleDriver.start(self)
        return True

    def start_pick(self, plan: TaskPlan, time: float = 0.0, effort: np.ndarray | None = None,
                   mode: str = "kinematic") -> None:
        """Show the pick task ``plan`` at ``time`` s (past the end: the final scene),
        playing unless at the end; stops the circle demo and hides the IK target.
        ``effort`` (N, n): the joint efforts when ``plan`` holds a run simulated in motion
        ``mode`` (control.MOTION_MODES)."""
        from robot_sim.viewer.drivers.pick import PickDriver  # the planner: numba

        self.target_tf, self.ik_result, self.branches = None, None, None
        self.driver = PickDriver.start(self, plan, time, effort, mode)
        self.fit_camera()

    def show_pick_at(self, t: float) -> None:
        """Put the arm (current and desired state) where the pick plan has it at ``t`` s;
        ValueError without a pick task."""
        self.driver.show_at(self, t)

    # ---- joints ----
    def set_q(self, q: np.ndarray) -> None:
        """Set the joints (SI) by hand, e.g. from sliders: ends the circle demo, pauses the
        pick task; kinematically current and desired q are set at rest, in a physical mode
        only the desired q (the controller moves the arm).  A shown IK target snaps to the
        new endeffector pose."""
        self._posed = True
        self.driver.set_q(self, q)

    def q_set_point(self) -> np.ndarray:
        """The joint values (n,) the sliders show and set: the arm's own kinematically,
        the controller's desired ones in a physical mode."""
        return self.driver.set_point(self)

    def set_joint(self, index: int, value: float) -> None:
        """Set joint ``index`` of :meth:`q_set_point` to ``value`` (rad or m) like :meth:`set_q`."""
        q = self.q_set_point()
        q[index] = value
        self.set_q(q)

    def moving(self) -> bool:
        """True while the driver moves the arm: the current q has not reached the desired
        q, a demo runs, or the simulation has not stopped."""
        return self.driver.moving(self)

    def step(self, dt: float) -> None:
        """Advance whatever moves (the driver) by ``dt`` s of wall-clock time."""
        self.driver.advance(self, dt)

    def tracking_error(self) -> tuple[float, float] | None:
        """In a physical mode, how far the tool is from its desired pose: position [m] and
        rotation angle [rad] (the desired pose of a task-space controller, else the tool
        pose of the desired joints); None in kinematic mode."""
        desired = self.driver.desired_tool_pose(self)
        if desired is None:
            return None
        actual = self.kin.endeff_tf.mat
        rotation = rotation_log(desired[:3, :3] @ actual[:3, :3].T)
        return float(np.linalg.norm(desired[:3, 3] - actual[:3, 3])), float(np.linalg.norm(rotation))

    # ---- collision (key C) ----
    @property
    def collision(self) -> CollisionDisplay:
        """Collision queries of the robot in its world (the checker is built on first use)."""
        if self._collision is None:
            from robot_sim.viewer.collision_display import CollisionDisplay  # the checker: numba

            self._collision = CollisionDisplay(self.robot, self.world)
        return self._collision

    def toggle_collision(self) -> bool:
        """Show or hide the collision display (shapes, contacts in red, the closest pair with
        its distance, the readout's minimum distance); returns whether it is shown."""
        self.options.show_collision = not self.options.show_collision
        return self.options.show_collision

    def collision_readout(self) -> str | None:
        """The readout's minimum-distance line while the collision display is shown."""
        return self.collision.readout(self.state.q()) if self.options.show_collision else None

    # ---- pulling the endeffector with the mouse (physical modes) ----
    @property
    def pulling(self) -> bool:
        """True while the mouse pulls the endeffector."""
        return self.driver.pull_point is not None

    def start_pull(self) -> None:
        """Begin pulling the endeffector (physical modes only; ValueError otherwise)."""
        self.driver.start_pull(self)

    def move_pull_in_view(self, dx_px: float, dy_px: float, height_px: int) -> None:
        """Move the pull's anchor by a mouse drag of (dx, dy) pixels in the plane through it
        facing the camera, so that it stays under the cursor (perspective included)."""
        point = self.driver.pull_point
        if point is None:
            return
        right, up = self.camera.view_plane_axes()
        eye = np.asarray(self.camera.eye())
        forward = np.asarray(self.camera.target) - eye
        distance = float(np.linalg.norm(forward))
        depth = float((point - eye) @ forward) / distance
        scale = self.camera.world_per_pixel(height_px) * depth / distance
        self.driver.move_pull(point + (dx_px * np.asarray(right) - dy_px * np.asarray(up)) * scale)

    def end_pull(self) -> None:
        """Let go of the endeffector."""
        self.driver.end_pull()

    # ---- drawing ----
    def velocity_vectors(self) -> list[Arrow]:
        """Endeffector linear (m/s) and angular (rad/s) velocity arrows (world): each
        starts on the endeffector sphere's surface in its own direction, ``VECTOR_SCALE_*``
        metres long per unit, so the whole arrow shows outside the sphere."""
        centre = self.kin.endeff_tf.t()
        radius = go.robot_look(self.robot).endeff_radius
        twist = np.asarray(self.kin.endeff_twist)
        arrows = []
        for vec, color in ((twist[:3] * vs.VECTOR_SCALE_LINEAR, gd.LINEAR_VELOCITY_COLOR),
                           (twist[3:] * vs.VECTOR_SCALE_ANGULAR, gd.ANGULAR_VELOCITY_COLOR)):
            norm = float(np.linalg.norm(vec))
            arrows.append((centre + (vec / norm * radius if norm > 0.0 else 0.0), vec, color))
        return arrows

    def pull_vectors(self) -> list[Arrow]:
        """The mouse pull's spring as an arrow from the endeffector to its anchor (world m)."""
        point = self.driver.pull_point
        if point is None:
            return []
        origin = self.kin.endeff_tf.t()
        return [(origin, point - origin, gd.PULL_COLOR)]

    def scene(self) -> go.Scene:
        """The robot_sim.graphics.Scene of the current state, the trail included; the
        ghost, the target drawn and the task are the driver's."""
        return go.Scene(
            self.kin,
            ghost=self.driver.shown_ghost(self),
            target_tf=self.driver.shown_target(self),
            target_reachable=self.target_reachable,
            vectors=(self.velocity_vectors() if self.options.show_vectors else []) + self.pull_vectors(),
            workspace=self.workspace,
            task=self.driver.task_scene(),
            collision=self.collision.scene(self.state.q()) if self.options.show_collision else None,
            trail=None if self.trail is None else self.trail.points(),
            branches=self.branches.ghosts(self.robot) if self.branches is not None and self.branches.show_all else [],
        )

    def status_text(self, fps_text: str) -> str:
        """Status bar text: robot name and frame rate, and a failed IK target's errors
        (the position error only for an arm whose IK places the tool without orienting it:
        its rotation error is no failure), and a pose in collision once the joints were set
        (sliders, IK), while the collision display is shown or while the arm is simulated;
        the endeffector pose has its own readout in the window."""
        text = vs.STATUS_FORMAT.format(robot=self.robot.name, fps=fps_text)
        if self.target_tf is not None and not self.target_reachable:
            if ik_position_only_required(self.robot):
                text += vs.STATUS_POSITION_UNREACHABLE.format(pos_err=self.ik_result.pos_err)
            else:
                text += vs.STATUS_TARGET_UNREACHABLE.format(
                    pos_err=self.ik_result.pos_err, rot_err_deg=math.degrees(self.ik_result.rot_err))
        if self._posed or self.options.show_collision or self.physical:  # reached by sliders, IK or physics
            text += self.collision.flag(self.state.q())
        if self._motion is not None:
            text += " | " + self._motion.status_text()
        return text
