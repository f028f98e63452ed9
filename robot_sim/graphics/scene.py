"""What a frame shows (:class:`Scene`) and how (:class:`GraphicsOptions`): plain data
that hosts fill and the render path reads (no GL).  Poses in the world frame, metres."""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robot_sim.graphics import defs as gd
from robot_sim.graphics.themes import DEFAULT_THEME
from robot_sim.kinematics import Kinematics
from robot_sim.transforms import HomogeneousTransform

if TYPE_CHECKING:
    from robot_sim.graphics.collision_scene import CollisionScene
    from robot_sim.graphics.workspace import WorkspaceCloud
    from robot_sim.graphics.task_scene import TaskScene

RGBA = tuple[float, float, float, float]
Vector = tuple[ArrayLike, ArrayLike, RGBA]  # (origin (3,), vector (3,), rgba) in the world


class GraphicsOptions:
    """What the viewer shows; hosts flip these from keys, the renderer only reads them.

    ``show_frames[i]`` shows frame i (``h_tf[i]``) for i in 0..n_frames-1, with
    ``n_frames = n_dofs + 1``; the base frame (index 0) starts shown, the others hidden.
    The endeffector (tool) frame ``endeff_tf`` has its own flag ``show_endeff_frame``
    so frame indices stay equal to DH frame numbers.  ``show_labels`` writes each drawn
    frame's number (0, 1, ..., E) next to it; ``show_com`` draws each link's centre of
    mass.  ``annotate_joint`` = i (1..n_dofs, DH table row i) draws joint i's DH
    parameters between frames i−1 and i (standard: d_i along z_{i−1}, θ_i about z_{i−1},
    a_i along x_i, α_i about x_i; modified: a_{i−1}, α_{i−1}, θ_i, d_i), each labelled
    with its value; None draws none.

    ``theme`` names the colours of the world (``themes.THEMES``: "dark", "light");
    ``look`` how the robot is drawn (``looks.LOOKS``; None: its meshes if it has any,
    else its DH segments); ``samples`` the multisample anti-aliasing (0 or 1: none);
    ``shadows`` whether the key light casts shadows; ``show_collision`` the collision
    display (key C).
    """

    def __init__(self, n_frames: int) -> None:
        if int(n_frames) < 1:
            raise ValueError(f"GraphicsOptions: n_frames must be >= 1 (frames 0..n_dofs), got {n_frames}")
        self.wireframe: bool = False
        self.alpha: float = 1.0
        self.show_frames: list[bool] = [True] + [False] * (int(n_frames) - 1)
        self.show_endeff_frame: bool = False
        self.show_vectors: bool = True
        self.show_workspace: bool = False
        self.show_ghost: bool = True
        self.show_target: bool = True
        self.show_com: bool = False
        self.show_labels: bool = True
        # joint number i (1..n_dofs, the DH table's row i) whose DH parameters are drawn
        # as dimensions and arcs between frames i-1 and i, or None
        self.annotate_joint: int | None = None
        self.theme: str = DEFAULT_THEME
        self.look: str | None = None
        self.samples: int = gd.MSAA_SAMPLES
        self.shadows: bool = True
        self.show_collision: bool = False

    @property
    def n_frames(self) -> int:
        """Number of DH frames that can be toggled (frames 0..n_frames-1)."""
        return len(self.show_frames)

    def toggle_frame(self, i: int) -> bool:
        """Flip frame ``i``'s visibility.  Returns True when ``i`` is a frame index
        (0..n_frames-1) and was flipped; False, changing nothing, otherwise."""
        if not isinstance(i, (int, np.integer)) or not 0 <= i < len(self.show_frames):
            return False
        self.show_frames[i] = not self.show_frames[i]
        return True

    def show_only_frames(self, frames: list[int]) -> None:
        """Show exactly the frames listed: DH frame indices 0..n_frames-1, and
        ``n_frames`` for the endeffector frame; every other frame is hidden."""
        chosen = set(frames)
        self.show_frames = [i in chosen for i in range(len(self.show_frames))]
        self.show_endeff_frame = len(self.show_frames) in chosen

    def toggle_endeff_frame(self) -> bool:
        """Flip the endeffector frame's visibility; returns the new state."""
        self.show_endeff_frame = not self.show_endeff_frame
        return self.show_endeff_frame

    def toggle_all_frames(self) -> None:
        """Show every frame (DH frames and endeffector) unless all are shown already,
        in which case hide all but the base frame."""
        show = not (all(self.show_frames) and self.show_endeff_frame)
        self.show_frames = [True] + [show] * (len(self.show_frames) - 1)
        self.show_endeff_frame = show

    def toggle_wireframe(self) -> bool:
        """Flip wireframe drawing of the robot; returns the new state."""
        self.wireframe = not self.wireframe
        return self.wireframe

    def cycle_look(self, looks: tuple[str, ...], current: str) -> str:
        """Switch to the look after ``current`` among ``looks`` (``looks.looks_of`` the
        robot shown, ``current`` as ``looks.look_for`` resolved it); returns it."""
        self.look = looks[(looks.index(current) + 1) % len(looks)] if current in looks else looks[0]
        return self.look

    def toggle_alpha(self) -> float:
        """Switch the robot between opaque (1.0) and ``TRANSLUCENT_ALPHA``; returns the alpha."""
        self.alpha = gd.TRANSLUCENT_ALPHA if self.alpha >= 1.0 else 1.0
        return self.alpha


@dataclass
class Scene:
    """What one frame shows; all poses in the world frame.

    ``kinematics``: the robot's current state (updated).  ``ghost``: the desired state,
    drawn translucent in ``GHOST_COLOR``, or None.  ``target_tf``: the IK target, drawn as
    a small frame and marker sphere, yellow, or magenta when ``target_reachable`` is
    False.  ``vectors``: arrows (origin (3,), vector (3,), rgba), 1 m per unit.
    ``workspace``: a point cloud or None.  ``task``: the pick task's table, object,
    gripper and planned path (the endeffector sphere is then left out: the gripper is
    the endeffector), or None.  ``trail``: the endeffector's recent path (N, 3), drawn
    as a line in ``TRAIL_COLOR``, or None.  ``collision``: the collision display (key
    C: collision shapes, contacts, the closest pair), or None.  ``branches``: the IK
    target's analytic branches drawn at once (key Shift+B), each as a ghost labelled with
    its posture name.
    """

    kinematics: Kinematics
    ghost: Kinematics | None = None
    target_tf: HomogeneousTransform | None = None
    target_reachable: bool = True
    vectors: list[Vector] = field(default_factory=list)
    workspace: WorkspaceCloud | None = None
    task: TaskScene | None = None
    trail: NDArray[np.float64] | None = None
    collision: CollisionScene | None = None
    branches: list[tuple[Kinematics, str]] = field(default_factory=list)

