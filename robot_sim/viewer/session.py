"""What a viewer shows, without Qt: :class:`ViewerSession` holds one robot's current and
desired joint state, their kinematics, the camera, the graphics options, the IK target,
the circle demo and the workspace cloud, and turns them into a ``robot_sim.graphics.Scene``.

The Qt window (robot_sim/qt/window.py) and the offscreen screenshot (robot_sim.app.cli.py) both show a session;
``--screenshot`` renders one through OSMesa without importing Qt at all.

Units: joint values are radians (revolute) and metres (prismatic) inside; the command
line ``--q`` and the sliders use degrees for revolute joints and metres for prismatic
ones (:func:`display_scale`).  Positions are in metres in the world frame.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Callable

import numpy as np

from robot_sim.graphics import defs as gd
from robot_sim.viewer import settings as vs
from robot_sim import graphics as go
from robot_sim.kinematics import (
    IKResult,
    Kinematics,
    diff_ik_velocity,
    ik_position_only_required,
    solve_ik,
    workspace_points,
)
from robot_sim.control.reference import fixed_pose
from robot_sim.viewer.collision_display import CollisionDisplay
from robot_sim.viewer.motion import Motion
from robot_sim.viewer.pick_demo import PickDemo
from robot_sim.viewer.pick_view import clear_view_azimuth
from robot_sim.planning.pick_task import TaskPlan
from robot_sim.model.params import JTYPE_PRISMATIC, RobotParams
from robot_sim.model.state import RobotState
from robot_sim.model.world import World
from robot_sim.transforms import HomogeneousTransform, rotation_log


# --------------------------------------------------------------------------------------
# units shared by the command line and the sliders
# --------------------------------------------------------------------------------------
def display_scale(robot: RobotParams) -> np.ndarray:
    """Per-joint factor (n,) from SI joint values (rad, m) to display units (deg, m)."""
    return np.where(robot.jtype == JTYPE_PRISMATIC, 1.0, 180.0 / math.pi)


def display_range(robot: RobotParams) -> tuple[np.ndarray, np.ndarray]:
    """Slider range (lo, hi), each (n,), in display units (deg, m).

    Joint limits where finite; otherwise ±UNLIMITED_REVOLUTE_RANGE_DEG for revolute and
    ±UNLIMITED_PRISMATIC_RANGE_M for prismatic joints.
    """
    prismatic = robot.jtype == JTYPE_PRISMATIC
    default = np.where(prismatic, vs.UNLIMITED_PRISMATIC_RANGE_M, vs.UNLIMITED_REVOLUTE_RANGE_DEG)
    scale = display_scale(robot)
    lo = np.where(np.isfinite(robot.q_min), robot.q_min * scale, -default)
    hi = np.where(np.isfinite(robot.q_max), robot.q_max * scale, default)
    return lo, hi


def wrap_display(robot: RobotParams, q: np.ndarray) -> np.ndarray:
    """Joint values (n,) in display units; unlimited revolute joints wrapped to [-180, 180)."""
    values = np.asarray(q, dtype=float) * display_scale(robot)
    wrap = (robot.jtype != JTYPE_PRISMATIC) & ~np.isfinite(robot.q_min) & ~np.isfinite(robot.q_max)
    return np.where(wrap, (values + 180.0) % 360.0 - 180.0, values)


# --------------------------------------------------------------------------------------
# the Qt-free session shown by the window and by --screenshot
# --------------------------------------------------------------------------------------
@dataclass
class DemoCircle:
    """Endeffector circle in the horizontal world plane through its start position (m, s)."""

    center: np.ndarray
    radius: float = vs.DEMO_CIRCLE_RADIUS_M
    period: float = vs.DEMO_CIRCLE_PERIOD_S
    time: float = 0.0

    def point_and_velocity(self) -> tuple[np.ndarray, np.ndarray]:
        """Desired world position (3,) in m and linear velocity (3,) in m/s at ``time``."""
        return self._motion_at(self.time)[:2]

    def _motion_at(self, time: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Position [m], velocity [m/s] and acceleration [m/s²] (3,) each at ``time`` [s]."""
        omega = 2.0 * math.pi / self.period
        c, s = math.cos(omega * time), math.sin(omega * time)
        point = self.center + self.radius * np.array([c, s, 0.0])
        velocity = self.radius * omega * np.array([-s, c, 0.0])
        return point, velocity, -self.radius * omega**2 * np.array([c, s, 0.0])

    def task_reference(self, rotation: np.ndarray, start: float) -> Callable[[float], tuple]:
        """The circle as a task reference of simulated time [s] (at its start at ``start``),
        the tool held at the world orientation ``rotation`` (3, 3)."""
        zero, begun = np.zeros(3), self.time

        def at(time: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
            point, velocity, accel = self._motion_at(begun + time - start)
            pose = np.eye(4)
            pose[:3, :3], pose[:3, 3] = rotation, point
            return pose, np.concatenate([velocity, zero]), np.concatenate([accel, zero])

        return at


@dataclass
class ViewerSession:
    """What a viewer shows, without Qt: one robot's state, kinematics, camera and options.

    ``state.joint_state`` is drawn as the robot, ``state.joint_state_des`` as the ghost.
    The IK target ``target_tf`` is a world pose; moving it solves IK from the desired q and
    the current q then follows with :meth:`step_animation`.
    """

    robot: RobotParams
    aspect: float = 1.0  # viewport width / height, for framing the robot
    state: RobotState = field(init=False)
    kin: Kinematics = field(init=False)
    ghost: Kinematics = field(init=False)
    camera: Any = field(init=False)
    options: Any = field(init=False)
    target_tf: HomogeneousTransform | None = None
    ik_result: IKResult | None = None
    workspace: Any = None
    demo: DemoCircle | None = None
    pick: PickDemo | None = None
    #: Gain overrides of the physical motion modes (control.control_gains keywords).
    gain_overrides: dict[str, Any] = field(default_factory=dict)
    #: Joint-limit arrivals of the simulation since the window last took them.
    limit_events: list[Any] = field(default_factory=list)
    #: The obstacles the arm collides with and, simulated, rests on (None: the floor).
    world: World | None = None
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

    @property
    def target_reachable(self) -> bool:
        """False when the last IK solve for the target failed."""
        return self.ik_result is None or self.ik_result.success

    def update_kinematics(self) -> None:
        """Recompute the world frames of the current (robot) and desired (ghost) state."""
        self.kin.update(self.state.joint_state)
        self.ghost.update(self.state.joint_state_des)

    def fit_camera(self, on_annotation: bool = False) -> None:
        """Reset the camera and frame everything drawn (``robot_sim.graphics.visible_points``):
        the arm at its current pose, the floor under its base, the drawn frames, the IK
        target and the workspace cloud when shown (world, m).  With ``on_annotation`` and
        a joint annotated, frame that joint's DH annotation and its two frames only, so
        its dimensions, arcs and labels are large enough to read.  During the pick task
        the camera turns about the vertical, if it must, until the table hides none of the
        arm (pick_view.clear_view_azimuth)."""
        self.camera.reset()
        focus = go.annotation_points(self.scene(), self.options) if on_annotation else None
        points = focus if focus is not None else go.visible_points(self.scene(), self.options)
        if self.pick is not None and focus is None:
            azimuth = clear_view_azimuth(self.camera, self.pick.plan, points, self.aspect)
            self.camera.set_view(azimuth, self.camera.elevation_deg)
        self.camera.fit(points, self.aspect)

    # ---- motion mode (kinematic or simulated, see motion.py) ----
    @property
    def motion(self) -> Motion:
        """The robot's motion modes and simulation, built on first use (dynamics are
        imported and the gains computed only when a physical mode is wanted)."""
        if self._motion is None:
            self._motion = Motion(self.robot, self.state, self.gain_overrides, self.world)
        return self._motion

    @property
    def physical(self) -> bool:
        """True while the arm is simulated (any motion mode but kinematic)."""
        return self._motion is not None and self._motion.physical

    @property
    def task_space(self) -> bool:
        """True in a task-space motion mode (operational space, impedance): the IK target,
        dragged, is the tool's desired pose itself (no IK), and the circle demo a Cartesian
        reference."""
        return self.physical and self.motion.task_space

    def set_motion(self, mode: str) -> None:
        """Switch the motion mode (control.MOTION_MODES); the demo keeps running.  In a
        task-space mode a shown IK target becomes the tool's desired pose."""
        self.motion.set_mode(mode)
        if self.task_space:
            if self.demo is not None:
                self._follow_demo()
            elif self.target_tf is not None:
                self.motion.follow(fixed_pose(self.target_tf))
        self.update_kinematics()

    def tracking_error(self) -> tuple[float, float] | None:
        """In a physical mode, how far the tool is from its desired pose: position [m] and
        rotation angle [rad] (the desired pose of a task-space controller, else the tool
        pose of the desired joints); None in kinematic mode."""
        if not self.physical:
            return None
        desired = self.motion.sim.desired_pose if self.task_space else None
        if desired is None:
            desired = self.ghost.endeff_tf.mat
        actual = self.kin.endeff_tf.mat
        rotation = rotation_log(desired[:3, :3] @ actual[:3, :3].T)
        return float(np.linalg.norm(desired[:3, 3] - actual[:3, 3])), float(np.linalg.norm(rotation))

    # ---- collision (key C) ----
    @property
    def collision(self) -> CollisionDisplay:
        """Collision queries of the robot in its world (the checker is built on first use)."""
        if self._collision is None:
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

    # ---- joints ----
    def set_q(self, q: np.ndarray) -> None:
        """Set current and desired q (SI) at rest, e.g. from sliders; stops any motion.
        In a physical mode only the desired q is set: the controller moves the arm.

        A shown IK target snaps to the new endeffector pose.
        """
        self.demo = None
        self._posed = True
        if self.pick is not None:
            self.pick.playing = False
        if self.physical:
            self.motion.follow(None)  # the sliders' joints are the set point again
            self.state.set_q_des(q)
            self.state.set_qd_des(np.zeros(self.robot.n_dofs))
            self.update_kinematics()
            if self.target_tf is not None:
                self.target_tf = HomogeneousTransform(self.ghost.endeff_tf.mat.copy())
                self.ik_result = None
            return
        self.state.set_q(q)
        self.state.set_q_des(q)
        self.state.set_qd(np.zeros(self.robot.n_dofs))
        self.update_kinematics()
        if self.target_tf is not None:
            self.target_tf = HomogeneousTransform(self.kin.endeff_tf.mat.copy())
            self.ik_result = None

    def set_joint(self, index: int, value: float) -> None:
        """Set joint ``index`` to ``value`` (rad or m) like :meth:`set_q`."""
        q = self.state.q()
        q[index] = value
        self.set_q(q)

    def moving(self) -> bool:
        """True while the current q has not reached the desired q, a demo runs, or the
        arm is simulated (until the simulation stops)."""
        if self.pick is not None and self.pick.playing:
            return True
        if self.physical:
            return self.motion.sim.stopped is None
        if self.demo is not None:
            return True
        return bool(np.any(np.abs(self.state.q_des() - self.state.q()) > vs.ANIM_ARRIVED_TOL))

    def step_animation(self, dt: float) -> None:
        """Move the current q toward the desired q at bounded joint speed for ``dt`` s."""
        q, q_des = self.state.q(), self.state.q_des()
        speed = np.where(self.robot.jtype == JTYPE_PRISMATIC, vs.ANIM_SPEED_PRISMATIC, vs.ANIM_SPEED_REVOLUTE)
        step = np.clip(q_des - q, -speed * dt, speed * dt)
        arrived = np.all(np.abs(q_des - q) <= np.maximum(speed * dt, vs.ANIM_ARRIVED_TOL))
        self.state.set_q(q_des if arrived else q + step)
        self.state.set_qd(np.zeros_like(q) if arrived else step / dt)
        self.update_kinematics()

    # ---- IK target ----
    def toggle_target(self) -> bool:
        """Show or hide the IK target and the ghost (the desired state); a new target starts
        at the endeffector.  Returns whether it is shown."""
        shown = self.target_tf is None
        self.target_tf = HomogeneousTransform(self.kin.endeff_tf.mat.copy()) if shown else None
        self.ik_result = None
        if self.task_space:
            if shown:
                self.motion.follow(fixed_pose(self.target_tf))
            else:
                self._hold_here()
        return shown

    def move_target(self, translation: np.ndarray | None = None, rpy: np.ndarray | None = None) -> bool:
        """Translate the target by ``translation`` (3,) m and rotate it about world axes
        through its origin by ``rpy`` (3,) rad; then re-solve IK.  Shows a hidden target.

        Returns whether the target is reachable; if not, the ghost stays where it was.
        """
        if self.target_tf is None:
            self.toggle_target()
        mat = self.target_tf.mat.copy()
        if translation is not None:
            mat[:3, 3] += translation
        if rpy is not None:
            mat[:3, :3] = HomogeneousTransform.from_xyz_rpy(np.zeros(3), rpy).R() @ mat[:3, :3]
        self.target_tf = HomogeneousTransform(mat)
        self.demo = None
        if self.task_space:  # the controller takes the pose itself: no IK
            self.ik_result = None
            self.motion.follow(fixed_pose(mat))
            return True
        self.ik_result = solve_ik(
            self.robot,
            self.target_tf,
            q0=self.state.q_des(),
            position_only=ik_position_only_required(self.robot),
        )
        if self.ik_result.success:
            self.state.set_q_des(self.ik_result.q)
            self._posed = True
            self.update_kinematics()
        return self.ik_result.success

    def move_target_in_view(self, dx_px: float, dy_px: float, height_px: int) -> bool:
        """Move the target by a mouse drag of (dx, dy) pixels (x right, y down) in the view plane."""
        right, up = self.camera.view_plane_axes()
        scale = self.camera.world_per_pixel(height_px)
        return self.move_target(translation=(dx_px * np.asarray(right) - dy_px * np.asarray(up)) * scale)

    # ---- circle demo (differential IK) ----
    def toggle_demo(self) -> bool:
        """Start the circle demo at the current endeffector position, or stop it."""
        if self.demo is not None:
            self.demo = None
            if self.task_space:
                self._hold_here()
            elif self.physical:
                self.state.set_qd_des(np.zeros(self.robot.n_dofs))
            else:
                self.state.set_qd(np.zeros(self.robot.n_dofs))
            self.update_kinematics()
            return False
        start = (self.ghost if self.physical and not self.task_space else self.kin).endeff_tf.t()
        self.demo = DemoCircle(center=start - np.array([vs.DEMO_CIRCLE_RADIUS_M, 0.0, 0.0]))
        if self.task_space:
            self._follow_demo()
        return True

    def _follow_demo(self) -> None:
        """The running circle demo as the task-space controller's reference, the tool held
        at its current orientation."""
        self.motion.follow(self.demo.task_reference(self.kin.endeff_tf.R().copy(), self.motion.sim.time))

    def _hold_here(self) -> None:
        """Task space: back to the state's desired joints, set where the arm is, at rest."""
        self.motion.follow(None)
        self.state.set_q_des(self.state.q())
        self.state.set_qd_des(np.zeros(self.robot.n_dofs))

    def step_demo(self, dt: float) -> None:
        """Advance the circle demo by ``dt`` s: qd from diff_ik_velocity with position
        feedback.  Kinematic mode moves the arm; a joint-space physical mode moves the
        desired state (q_des, qd_des), which the controller tracks; in a task-space mode
        the simulation follows the circle itself and nothing is solved here."""
        self.demo.time += dt
        if self.task_space:  # the simulation follows the circle itself (_follow_demo)
            return
        point, velocity = self.demo.point_and_velocity()
        physical = self.physical
        ee = (self.ghost if physical else self.kin).endeff_tf.t()
        command = velocity + vs.DEMO_FEEDBACK_GAIN * (point - ee)
        q = self.state.q_des() if physical else self.state.q()
        qd = diff_ik_velocity(self.robot, q, command)
        q_new = np.clip(q + qd * dt, self.robot.q_min, self.robot.q_max)
        self.state.set_q_des(q_new)
        if physical:
            self.state.set_qd_des((q_new - q) / dt)
        else:
            self.state.set_q(q_new)
            self.state.set_qd((q_new - q) / dt)
        self.update_kinematics()

    def step(self, dt: float) -> None:
        """Advance whatever moves (pick demo, circle demo, simulation, animation toward the
        ghost) by ``dt`` s of wall-clock time.  The pick demo plays its planned joint
        motion kinematically in every motion mode."""
        if self.pick is not None:
            self.pick.step(dt)
            self.show_pick_at(self.pick.time)
            return
        if self.demo is not None:
            self.step_demo(dt)
        if self.physical:
            self.limit_events.extend(self.motion.advance(dt))
            self.update_kinematics()
        elif self.demo is None:
            self.step_animation(dt)

    # ---- pick demo (planned task, scrubbed or played) ----
    def start_pick(self, plan: TaskPlan, time: float = 0.0, effort: np.ndarray | None = None,
                   mode: str = "kinematic") -> None:
        """Show the pick task ``plan`` at ``time`` s (past the end: the final scene),
        playing unless at the end; stops the circle demo and hides the IK target.
        ``effort`` (N, n): the joint efforts when ``plan`` holds a run simulated in motion
        ``mode`` (control.MOTION_MODES)."""
        self.demo, self.target_tf, self.ik_result = None, None, None
        self.pick = PickDemo(plan, effort, mode=mode)
        self.show_pick_at(time)
        self.pick.playing = self.pick.time < self.pick.duration
        self.fit_camera()

    def show_pick_at(self, t: float) -> None:
        """Put the arm (current and desired state) where the pick plan has it at ``t`` s."""
        self.pick.seek(t)
        q, qd, _ = self.pick.plan.trajectory.evaluate(self.pick.plan.trajectory.t[0] + self.pick.time)
        self.state.set_q(q)
        self.state.set_q_des(q)
        self.state.set_qd(qd)
        self.update_kinematics()

    # ---- drawing ----
    def velocity_vectors(self) -> list[tuple[np.ndarray, np.ndarray, tuple[float, ...]]]:
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

    def ghost_apart(self) -> bool:
        """In a physical mode: True while the arm is visibly away from its desired state
        (then the ghost shows the set point)."""
        if not self.physical:
            return False
        return bool(np.any(np.abs(self.state.q_des() - self.state.q()) > gd.GHOST_APART_TOL))

    def pull_vectors(self) -> list[tuple[np.ndarray, np.ndarray, tuple[float, ...]]]:
        """The mouse pull's spring as an arrow from the endeffector to its anchor (world m)."""
        if not self.physical or self.motion.pull_point is None:
            return []
        origin = self.kin.endeff_tf.t()
        return [(origin, self.motion.pull_point - origin, gd.PULL_COLOR)]

    def start_pull(self) -> None:
        """Begin pulling the endeffector (physical modes only; ValueError otherwise)."""
        if not self.physical:
            raise ValueError("pulling needs a physical motion mode (press Shift+M)")
        self.motion.start_pull()

    def move_pull_in_view(self, dx_px: float, dy_px: float, height_px: int) -> None:
        """Move the pull's anchor by a mouse drag of (dx, dy) pixels in the plane through it
        facing the camera, so that it stays under the cursor (perspective included)."""
        if not self.physical or self.motion.pull_point is None:
            return
        point = self.motion.pull_point
        right, up = self.camera.view_plane_axes()
        eye = np.asarray(self.camera.eye())
        forward = np.asarray(self.camera.target) - eye
        distance = float(np.linalg.norm(forward))
        depth = float((point - eye) @ forward) / distance
        scale = self.camera.world_per_pixel(height_px) * depth / distance
        self.motion.move_pull(point + (dx_px * np.asarray(right) - dy_px * np.asarray(up)) * scale)

    def scene(self) -> Any:
        """The robot_sim.graphics.Scene of the current state."""
        following = self.task_space and self.motion.sim.reference is not None
        target = self.target_tf
        if following and target is None and self.motion.sim.desired_pose is not None:
            target = HomogeneousTransform(self.motion.sim.desired_pose.copy())  # the demo's moving pose
        return go.Scene(
            self.kin,
            # a task-space controller following a pose has no desired joints: the target shows it
            ghost=None if following else (self.ghost if self.target_tf is not None or self.ghost_apart() else None),
            target_tf=target,
            target_reachable=self.target_reachable,
            vectors=(self.velocity_vectors() if self.options.show_vectors else []) + self.pull_vectors(),
            workspace=self.workspace,
            task=None if self.pick is None else self.pick.task_scene(),
            collision=self.collision.scene(self.state.q()) if self.options.show_collision else None,
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


def compute_workspace(robot: RobotParams, n_points: int, cancelled: Callable[[], bool] | None = None) -> Any:
    """Workspace cloud of ``n_points`` endeffector positions (m, world) coloured by
    manipulability; ``cancelled`` as in kinematics.workspace_points."""
    points, manipulability = workspace_points(robot, n_points, seed=vs.WORKSPACE_SEED, cancelled=cancelled)
    return go.WorkspaceCloud(points, manipulability)

