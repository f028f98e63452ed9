"""What a viewer shows, without Qt: :class:`ViewerSession` holds one robot's current and
desired joint state, their kinematics, the camera, the graphics options, the IK target,
the workspace cloud, the endeffector trail and the one driver that moves the arm
(robot_sim.viewer.drivers), and turns them into a ``robot_sim.graphics.Scene``.

The Qt window (robot_sim.qt), the command line's ``--screenshot`` and ``--record``
(robot_sim.app) and :class:`robot_sim.viewer.visualizer.Visualizer` all show a session;
offscreen ones render it through OSMesa without importing Qt at all.

Units: joint values are radians (revolute) and metres (prismatic) inside; the command
line ``--q`` and the sliders use degrees for revolute joints and metres for prismatic
ones (:func:`display_scale`).  Positions are in metres in the world frame.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Callable

import numpy as np

from robot_sim import graphics as go
from robot_sim.control.reference import fixed_pose
from robot_sim.graphics import defs as gd
from robot_sim.kinematics import IKResult, Kinematics, ik_position_only_required, solve_ik, workspace_points
from robot_sim.model.params import JTYPE_PRISMATIC, RobotParams
from robot_sim.model.state import RobotState
from robot_sim.model.world import World
from robot_sim.transforms import HomogeneousTransform, rotation_log
from robot_sim.viewer import settings as vs
from robot_sim.viewer.branches import Branches, solve_branches
from robot_sim.viewer.dh_table import carry_joint_values
from robot_sim.viewer.drivers import Driver, StillDriver
from robot_sim.viewer.drivers.base import OverDriver
from robot_sim.viewer.drivers.circle import CircleDriver, DemoCircle
from robot_sim.viewer.trail import Trail

if TYPE_CHECKING:  # these pull the planner, the checker and the simulation (numba): loaded on use
    from robot_sim.sim.stops import LimitEvent
    from robot_sim.planning.pick_task import TaskPlan
    from robot_sim.viewer.collision_display import CollisionDisplay
    from robot_sim.viewer.motion import Motion
    from robot_sim.viewer.pick_demo import PickDemo


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
# the Qt-free session shown by the window, the command line and rs.Visualizer
# --------------------------------------------------------------------------------------
@dataclass
class ViewerSession:
    """What a viewer shows, without Qt: one robot's state, kinematics, camera and options,
    what moves it (:attr:`driver`, one at a time), the endeffector trail and whether the
    camera follows the endeffector.

    ``state.joint_state`` is drawn as the robot, ``state.joint_state_des`` as the ghost.
    The IK target ``target_tf`` is a world pose; moving it solves IK from the desired q and
    the current q then follows with :meth:`step`.
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

    @property
    def target_reachable(self) -> bool:
        """False when the last IK solve for the target failed."""
        return self.ik_result is None or self.ik_result.success

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
        its dimensions, arcs and labels are large enough to read.  During the pick task
        the camera turns about the vertical, if it must, until the table hides none of the
        arm (pick_view.clear_view_azimuth)."""
        self.camera.reset()
        focus = go.annotation_points(self.scene(), self.options) if on_annotation else None
        points = focus if focus is not None else go.visible_points(self.scene(), self.options)
        if self.pick is not None and focus is None:
            from robot_sim.viewer.pick_view import clear_view_azimuth  # the planner: numba

            azimuth = clear_view_azimuth(self.camera, self.pick.plan, points, self.aspect)
            self.camera.set_view(azimuth, self.camera.elevation_deg)
        self.camera.fit(points, self.aspect)
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

    # ---- motion mode (kinematic or simulated, see motion.py) ----
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
        return self.physical and self.motion.task_space

    @property
    def demo(self) -> DemoCircle | None:
        """The running circle demo, or None."""
        return self.driver.circle if isinstance(self.driver, CircleDriver) else None

    @property
    def pick(self) -> PickDemo | None:
        """The pick task being shown (played or paused), or None."""
        return getattr(self.driver, "pick", None)

    def set_motion(self, mode: str) -> None:
        """Switch the motion mode (control.MOTION_MODES); a demo keeps running over the new
        mode.  In a task-space mode a shown IK target becomes the tool's desired pose."""
        self.motion.set_mode(mode)
        base: Driver = StillDriver()
        if self.motion.physical:
            from robot_sim.viewer.drivers.simulated import SimulationDriver

            base = SimulationDriver(self.motion)
        if isinstance(self.driver, OverDriver):
            self.driver.inner = base
        else:
            self.driver = base
        if self.task_space:
            if isinstance(self.driver, CircleDriver):
                self.driver.follow(self)
            elif self.target_tf is not None:
                self.motion.follow(fixed_pose(self.target_tf))
        self.update_kinematics()

    def simulate(self, duration: float) -> None:
        """Simulate ``duration`` seconds at once in the physical mode set (``--duration``);
        ValueError in kinematic mode."""
        if not self.physical:
            raise ValueError("simulating needs a physical motion mode")
        self.driver.base.simulate(self, duration)  # type: ignore[attr-defined]

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

    # ---- joints ----
    def set_q(self, q: np.ndarray) -> None:
        """Set the joints (SI) by hand, e.g. from sliders: ends the circle demo, pauses the
        pick task; kinematically current and desired q are set at rest, in a physical mode
        only the desired q (the controller moves the arm).  A shown IK target snaps to the
        new endeffector pose."""
        self._posed = True
        self.driver.set_q(self, q)

    def set_joint(self, index: int, value: float) -> None:
        """Set joint ``index`` to ``value`` (rad or m) like :meth:`set_q`."""
        q = self.state.q()
        q[index] = value
        self.set_q(q)

    def moving(self) -> bool:
        """True while the driver moves the arm: the current q has not reached the desired
        q, a demo runs, or the simulation has not stopped."""
        return self.driver.moving(self)

    def step(self, dt: float) -> None:
        """Advance whatever moves (the driver) by ``dt`` s of wall-clock time."""
        self.driver.step(self, dt)

    # ---- IK target ----
    def toggle_target(self) -> bool:
        """Show or hide the IK target and the ghost (the desired state); a new target starts
        at the endeffector.  Returns whether it is shown."""
        shown = self.target_tf is None
        self.target_tf = HomogeneousTransform(self.kin.endeff_tf.mat.copy()) if shown else None
        self.ik_result, self.branches = None, None
        if self.task_space:
            if shown:
                self.motion.follow(fixed_pose(self.target_tf))
            else:
                self.driver.base.rest(self)
        return shown

    def move_target(self, translation: np.ndarray | None = None, rpy: np.ndarray | None = None) -> bool:
        """Translate the target by ``translation`` (3,) m and rotate it about world axes
        through its origin by ``rpy`` (3,) rad; then re-solve IK.  Shows a hidden target
        and ends the circle demo.

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
        self.branches = None
        if isinstance(self.driver, CircleDriver):
            self.driver = self.driver.inner
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

    def _branches(self) -> Branches | str:
        """The target's branches (shown at the endeffector if hidden), solved once per target
        nearest to the arm's joints first; or the message saying why there are none."""
        if self.target_tf is None:
            self.toggle_target()
        if self.branches is None:
            found = solve_branches(self.robot, self.target_tf.mat, self.state.q())
            if isinstance(found, str):
                return found
            self.branches = found
        return self.branches

    def cycle_branch(self) -> tuple[int, int, str] | str:
        """Show the target's next analytic branch as the ghost (the desired q; after the last:
        the first).  Returns (index, count, posture name), or the message why there is none."""
        branches = self._branches()
        if isinstance(branches, str):
            return branches
        index = branches.cycle()
        self.state.set_q_des(branches.solutions.q[index])
        self._posed = True
        self.update_kinematics()
        return index, len(branches.solutions), str(branches.solutions.branch[index])

    def toggle_all_branches(self) -> int | str:
        """Draw every analytic branch of the target at once, translucent and labelled, or
        stop.  Returns how many are drawn (0: stopped), or the message why there are none."""
        if self.branches is not None and self.branches.show_all:
            self.branches.show_all = False
            return 0
        branches = self._branches()
        if isinstance(branches, str):
            return branches
        branches.show_all = True
        return len(branches.solutions)

    def move_target_in_view(self, dx_px: float, dy_px: float, height_px: int) -> bool:
        """Move the target by a mouse drag of (dx, dy) pixels (x right, y down) in the view plane."""
        right, up = self.camera.view_plane_axes()
        scale = self.camera.world_per_pixel(height_px)
        return self.move_target(translation=(dx_px * np.asarray(right) - dy_px * np.asarray(up)) * scale)

    # ---- circle demo (differential IK) ----
    def toggle_demo(self) -> bool:
        """Start the circle demo at the current endeffector position, or stop it (the arm
        then rests where it is: a task-space controller holds it there)."""
        if isinstance(self.driver, CircleDriver):
            self.driver = self.driver.inner
            self.driver.rest(self)
            self.update_kinematics()
            return False
        self.driver = CircleDriver.start(self)
        return True

    # ---- pick demo (planned task, scrubbed or played) ----
    def start_pick(self, plan: TaskPlan, time: float = 0.0, effort: np.ndarray | None = None,
                   mode: str = "kinematic") -> None:
        """Show the pick task ``plan`` at ``time`` s (past the end: the final scene),
        playing unless at the end; stops the circle demo and hides the IK target.
        ``effort`` (N, n): the joint efforts when ``plan`` holds a run simulated in motion
        ``mode`` (control.MOTION_MODES)."""
        from robot_sim.viewer.drivers.pick import PickDemo, PickDriver  # the planner: numba

        self.target_tf, self.ik_result, self.branches = None, None, None
        self.driver = PickDriver(PickDemo(plan, effort, mode=mode), self.driver.base)
        self.show_pick_at(time)
        self.pick.playing = self.pick.time < self.pick.duration
        self.fit_camera()

    def show_pick_at(self, t: float) -> None:
        """Put the arm (current and desired state) where the pick plan has it at ``t`` s."""
        self.driver.show_at(self, t)  # type: ignore[attr-defined]

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

    def scene(self) -> go.Scene:
        """The robot_sim.graphics.Scene of the current state, the trail included."""
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


def compute_workspace(robot: RobotParams, n_points: int,
                      cancelled: Callable[[], bool] | None = None) -> go.WorkspaceCloud:
    """Workspace cloud of ``n_points`` endeffector positions (m, world) coloured by
    manipulability; ``cancelled`` as in kinematics.workspace_points."""
    points, manipulability = workspace_points(robot, n_points, seed=vs.WORKSPACE_SEED, cancelled=cancelled)
    return go.WorkspaceCloud(points, manipulability)

