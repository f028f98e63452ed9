"""The IK target of a viewer session (no Qt, no GL): a world pose the user shows, moves
by keys or drags, and whose analytic branches (keys B, Shift+B) the ghost shows.

:class:`TargetControl` is a part of :class:`robot_sim.viewer.session.ViewerSession` (it
holds the session's target methods; the session holds the state).  What a moved target
does depends on the session's driver (``Driver.reach_target``): kinematically and under a
joint-space controller IK is solved from the desired joints and the ghost goes there;
a task-space controller takes the pose itself.  Positions in metres, angles in radians,
world frame.
"""
from __future__ import annotations

from typing import Callable

import numpy as np

from robot_sim.graphics.camera import Camera
from robot_sim.kinematics import IKResult, Kinematics, ik_position_only_required, solve_ik
from robot_sim.model.params import RobotParams
from robot_sim.model.state import RobotState
from robot_sim.transforms import HomogeneousTransform
from robot_sim.viewer.branches import Branches, solve_branches
from robot_sim.viewer.drivers import Driver


class TargetControl:
    """The IK target's methods of a session: show, move, solve, branches."""

    robot: RobotParams
    state: RobotState
    kin: Kinematics
    camera: Camera
    driver: Driver
    target_tf: HomogeneousTransform | None
    ik_result: IKResult | None
    branches: Branches | None
    _posed: bool
    update_kinematics: Callable[[], None]

    @property
    def target_reachable(self) -> bool:
        """False when the last IK solve for the target failed."""
        return self.ik_result is None or self.ik_result.success

    def toggle_target(self) -> bool:
        """Show or hide the IK target and the ghost (the desired state); a new target starts
        at the endeffector.  Returns whether it is shown."""
        shown = self.target_tf is None
        self.target_tf = HomogeneousTransform(self.kin.endeff_tf.mat.copy()) if shown else None
        self.ik_result, self.branches = None, None
        self.driver.target_toggled(self)
        return shown

    def move_target(self, translation: np.ndarray | None = None, rpy: np.ndarray | None = None) -> bool:
        """Translate the target by ``translation`` (3,) m and rotate it about world axes
        through its origin by ``rpy`` (3,) rad; then reach it as the driver does (IK, or
        a task-space controller's desired pose).  Shows a hidden target and ends the
        circle demo.

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
        self.driver.target_moved(self)
        return self.driver.reach_target(self)

    def solve_target(self) -> bool:
        """Solve IK for the target from the desired joints; the ghost (the desired joints)
        goes there when it is reachable.  Returns whether it is."""
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

    # ---- analytic branches ----
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
