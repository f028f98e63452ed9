"""A viewer session's scene in the browser: what the window draws, as viser scene nodes.

:class:`WebScene` reads ``session.scene()`` and ``session.options`` and sends what
changed: the arm in its look (DH segments, solid, its meshes, or both) as copies of the
project's unit meshes (robot_sim.graphics.robot_parts and solid, the same parts the
OpenGL view draws), its own meshes once per robot, the frames shown as RGB axes with
their labels, the floor, the world's obstacles, the collision display, the trail, the IK
target and the ghost, the annotation of one joint's DH parameters, and the pick task.
A mesh goes to the browser once; later updates carry poses only, and nothing at all
for what did not move.  World frame (z up), metres.
"""
from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from robot_sim.graphics import defs as gd
from robot_sim.graphics.annotation_geometry import dh_annotation
from robot_sim.graphics.collision_scene import closest_marks, collision_parts
from robot_sim.graphics.floor_grid import FloorGrid
from robot_sim.graphics.frame_axes import axes_placements, frame_labels, frames_and_names
from robot_sim.graphics.looks import look_for
from robot_sim.graphics.placements import spheres
from robot_sim.graphics.robot_parts import branch_label_point, differing_masks, robot_look, robot_reach
from robot_sim.graphics.solid import posed_parts
from robot_sim.graphics.task_scene import obstacle_placements, task_parts
from robot_sim.graphics.themes import theme
from robot_sim.graphics.visuals import visual_pieces
from robot_sim.model.params import RobotParams
from robot_sim.web.parts import PartsLayer, instance_poses, rgb255

#: Intensity of the ambient light added to viser's default lights.
AMBIENT_LIGHT = 0.8


def merged_labels(labels: list[tuple[NDArray[np.float64], str]],
                  tol: float = gd.GHOST_TOLERANCE) -> list[tuple[NDArray[np.float64], str]]:
    """Labels (anchor (3,) world [m], text) with those at one anchor (within ``tol``)
    written as one, a line each, in their order: the browser places a label at its
    anchor without moving it apart from others (two IK branches that differ only past
    their middle joint, a wrist flip, are labelled at the same point)."""
    merged: list[tuple[NDArray[np.float64], str]] = []
    for anchor, text in labels:
        for k, (at, written) in enumerate(merged):
            if np.abs(at - anchor).max() <= tol:
                merged[k] = (at, f"{written}\n{text}")
                break
        else:
            merged.append((anchor, text))
    return merged


class WebScene:
    """The scene nodes of one viser server (``scene`` is its ``server.scene``) showing one
    session at a time; :meth:`sync` sends the session's current state."""

    def __init__(self, scene: Any) -> None:
        self.scene = scene
        # Lit by the default lights plus a soft ambient one, without shadows or viser's
        # environment map: on software WebGL (SwiftShader) those two take the page from
        # about 45 frames a second to 8 and 1.
        scene.configure_environment_map(None)
        scene.configure_default_lights(True, cast_shadow=False)
        scene.add_light_ambient("/lights/ambient", intensity=AMBIENT_LIGHT)
        self.robot_layer = PartsLayer(scene, "/robot/parts")
        self.visual_units = PartsLayer(scene, "/robot/visual_units")
        self.ghost_layer = PartsLayer(scene, "/ghost")
        self.frame_layer = PartsLayer(scene, "/frames/axes")
        self.world_layer = PartsLayer(scene, "/world")
        self.collision_layer = PartsLayer(scene, "/collision")
        self.task_layer = PartsLayer(scene, "/task")
        self.target_layer = PartsLayer(scene, "/target")
        self._robot: RobotParams | None = None
        self._theme: str | None = None
        self._meshes: list[tuple[Any, int, NDArray[np.float64]]] = []  # handle, frame, local
        self._labels: dict[str, list[Any]] = {}
        self._lines: dict[str, bytes] = {}

    # ---- the whole scene ----
    def sync(self, session: Any) -> None:
        """Send what changed in ``session`` (its robot, pose, options, target, task, ...)."""
        options, scene = session.options, session.scene()
        robot = session.robot
        if robot is not self._robot or options.theme != self._theme:
            self._new_robot(robot, session, options.theme)
        look = look_for(robot, options.look)
        kin = scene.kinematics
        arm = posed_parts(kin, look, options.show_com) if look != "mesh" else []
        if scene.task is not None:
            arm = [p for p in arm if p.color != gd.ENDEFF_COLOR]  # the gripper is the endeffector
        self.robot_layer.update([(p.mesh, p.color, p.placements) for p in arm], opacity=float(options.alpha),
                                wireframe=options.wireframe, visible=look != "mesh")
        self._sync_visuals(kin.frames, look, options)
        self._sync_ghost(scene, look, options)
        self._sync_frames(kin, options)
        self._sync_target(scene, options)
        self._sync_collision(scene)
        self._sync_task(scene)
        self._sync_line("/trail", scene.trail, gd.TRAIL_COLOR, gd.TRAIL_WIDTH_PX)
        self._sync_annotation(kin, options)

    def _new_robot(self, robot: RobotParams, session: Any, theme_name: str) -> None:
        """A new robot (or theme): its meshes, the floor under its base, the world."""
        colours = theme(theme_name)
        for handle, _, _ in self._meshes:
            handle.remove()
        self._meshes = []
        self.visual_units.clear()
        for i, piece in enumerate(visual_pieces(robot)):
            if piece.vertices is None:
                continue
            handle = self.scene.add_mesh_simple(f"/robot/meshes/{i}", piece.vertices.astype(np.float32),
                                                piece.faces.astype(np.uint32), color=tuple(rgb255(piece.color)),
                                                visible=False)
            self._meshes.append((handle, piece.frame, piece.local))
        self._units = [p for p in visual_pieces(robot) if p.vertices is None]
        grid = FloorGrid.for_reach(robot_reach(robot), session.kin.frames[0, :2, 3])
        size = 2.0 * grid.half_extent
        lines = tuple(rgb255(np.asarray(colours.grid[:3]) * colours.grid[3] + np.asarray(colours.background[:3]) * (1.0 - colours.grid[3])))
        self.scene.add_grid("/floor", width=size, height=size, plane="xy", cell_size=grid.step,
                            section_size=size, cell_color=lines, section_color=lines,
                            position=(float(grid.centre_xy[0]), float(grid.centre_xy[1]), 0.0))
        background = np.broadcast_to(rgb255(colours.background), (2, 2, 3)).copy()
        self.scene.set_background_image(background, format="png")
        world = session.world.obstacles if session.world is not None else ()
        self.world_layer.update(obstacle_placements(world))
        self._robot, self._theme = robot, theme_name

    # ---- parts of the scene ----
    def _sync_visuals(self, frames: NDArray[np.float64], look: str, options: Any) -> None:
        shown = look in ("mesh", "both")
        alpha = gd.MESH_OVER_DH_ALPHA if look == "both" else float(options.alpha)
        for handle, frame, local in self._meshes:
            if handle.visible != shown:
                handle.visible = shown
            if shown:  # viser sends a property only when its value changes
                wxyz, pos, scale = instance_poses(frames[frame] @ local)
                handle.wxyz, handle.position = wxyz[0], pos[0]
                handle.scale = tuple(float(s) for s in scale[0])
                handle.opacity = None if alpha >= 1.0 else alpha
                handle.wireframe = options.wireframe
        units: dict[str, tuple[list, list]] = {}
        for piece in self._units:
            mats, colours = units.setdefault(piece.unit or "box", ([], []))
            mats.append(frames[piece.frame] @ piece.local)
            colours.append(piece.color)
        self.visual_units.update([(unit, np.array(c), np.array(m)) for unit, (m, c) in units.items()],
                                 opacity=alpha, wireframe=options.wireframe, visible=shown)

    def _sync_ghost(self, scene: Any, look: str, options: Any) -> None:
        """The ghost and the IK branches drawn at once (Shift+B), each labelled."""
        ghosts = ([] if scene.ghost is None else [scene.ghost]) + [kin for kin, _ in scene.branches]
        if not ghosts or not options.show_ghost:
            self.ghost_layer.update([])
            self._sync_labels("/ghost/labels", [])
            return
        shape = "solid" if look == "solid" else "dh"
        reference = posed_parts(scene.kinematics, shape, options.show_com)
        parts, opacities = [], []
        for kin in ghosts:
            ghost = posed_parts(kin, shape, options.show_com)
            masks = differing_masks(ghost, reference)
            if scene.task is not None:
                masks = [m & (p.color != gd.ENDEFF_COLOR) for m, p in zip(masks, ghost)]
            parts += [(p.mesh, gd.GHOST_COLOR, p.placements) for p in ghost]
            opacities += [np.where(m, gd.GHOST_COLOR[3], 0.0) for m in masks]
        self.ghost_layer.update(parts, opacities=opacities, wireframe=options.wireframe)
        self._sync_labels("/ghost/labels", merged_labels([(branch_label_point(kin), name)
                                                          for kin, name in scene.branches]))

    def _sync_frames(self, kin: Any, options: Any) -> None:
        frames, names = frames_and_names(kin, options.show_frames, options.show_endeff_frame)
        length = robot_look(kin.robot).frame_length
        shafts, cones, colours, lengths = axes_placements(frames, length)
        self.frame_layer.update([("cylinder", colours, shafts), ("cone", colours, cones)])
        labels = frame_labels(frames, names, lengths) if options.show_labels else []
        self._sync_labels("/frames/labels", [(anchor, text) for anchor, text in labels])

    def _sync_target(self, scene: Any, options: Any) -> None:
        target = scene.target_tf
        if target is None or not options.show_target:
            self.target_layer.update([])
            return
        reach = robot_reach(scene.kinematics.robot)
        pose = target.mat
        shafts, cones, colours, _ = axes_placements(pose[None], reach * gd.TARGET_FRAME_LENGTH_FRAC)
        colour = gd.TARGET_COLOR if scene.target_reachable else gd.TARGET_UNREACHABLE_COLOR
        self.target_layer.update([("cylinder", colours, shafts), ("cone", colours, cones),
                                  ("sphere", colour, spheres(pose[:3, 3], reach * gd.TARGET_MARKER_RADIUS_FRAC))])

    def _sync_collision(self, scene: Any) -> None:
        shown = scene.collision
        if shown is None:
            self.collision_layer.update([])
            self._sync_line("/collision/closest", None, gd.CLOSEST_COLOR, gd.CLOSEST_WIDTH_PX)
            self._sync_labels("/collision/labels", [])
            return
        parts = collision_parts(shown)
        opacities: list = [colours[:, 3] for _, colours, _ in parts]
        marks = closest_marks(shown)
        points = None if marks is None else marks[0]
        if marks is not None:
            parts.append(("sphere", gd.CLOSEST_COLOR, marks[1]))
            opacities.append(None)
        self.collision_layer.update(parts, opacities=opacities)
        self._sync_line("/collision/closest", points, gd.CLOSEST_COLOR, gd.CLOSEST_WIDTH_PX)
        self._sync_labels("/collision/labels", [] if points is None else [(points.mean(axis=0), shown.distance_text())])

    def _sync_task(self, scene: Any) -> None:
        task = scene.task
        self.task_layer.update([] if task is None else task_parts(task))
        self._sync_line("/task/path", None if task is None else task.path, gd.PATH_COLOR, gd.PATH_LINE_WIDTH_PX)

    def _sync_annotation(self, kin: Any, options: Any) -> None:
        joint = options.annotate_joint
        if joint is None or not 1 <= joint <= kin.robot.n_dofs:
            self._sync_segments("/annotation/lines", np.zeros((0, 2, 3)), np.zeros((0, 2, 3), np.uint8))
            self._sync_labels("/annotation/labels", [])
            return
        annotation = dh_annotation(kin.frames, joint, kin.robot.is_modified, robot_look(kin.robot).frame_length)
        segments, colours = [], []
        for points, rgba, _dashed in annotation.lines:
            pairs = np.stack([points[:-1], points[1:]], axis=1)
            segments.append(pairs)
            colours.append(np.broadcast_to(rgb255(rgba), pairs.shape))
        self._sync_segments("/annotation/lines", np.concatenate(segments), np.concatenate(colours),
                            gd.ANNOTATION_LINE_WIDTH)
        self._sync_labels("/annotation/labels", [(anchor, text) for anchor, text, _ in annotation.labels])

    # ---- helpers ----
    def _sync_line(self, name: str, points: NDArray[np.float64] | None, rgba: tuple, width: float) -> None:
        """A polyline through ``points`` (k, 3), or nothing when None or fewer than two."""
        pts = np.zeros((0, 3)) if points is None else np.asarray(points, dtype=float).reshape(-1, 3)
        pairs = np.stack([pts[:-1], pts[1:]], axis=1) if len(pts) >= 2 else np.zeros((0, 2, 3))
        self._sync_segments(name, pairs, np.broadcast_to(rgb255(rgba), pairs.shape), width)

    def _sync_segments(self, name: str, pairs: NDArray, colours: NDArray, width: float = 1.0) -> None:
        key = pairs.astype(np.float32).tobytes() + np.asarray(colours, np.uint8).tobytes()
        if self._lines.get(name) == key:
            return
        self._lines[name] = key
        if len(pairs) == 0:
            self.scene.add_line_segments(name, np.zeros((1, 2, 3), np.float32), (0, 0, 0), visible=False)
            return
        self.scene.add_line_segments(name, pairs.astype(np.float32), np.ascontiguousarray(colours, dtype=np.uint8),
                                     thickness=width, thickness_units="screen")

    def _sync_labels(self, prefix: str, labels: list[tuple[NDArray[np.float64], str]]) -> None:
        """Labels (anchor (3,), text) under ``prefix``: handles reused, text and position
        sent only when they change."""
        handles = self._labels.setdefault(prefix, [])
        for i, (anchor, text) in enumerate(labels):
            position = tuple(float(v) for v in anchor)
            if i < len(handles):
                handle = handles[i]
                if handle.text != text:
                    handle.text = text
                if tuple(handle.position) != position:
                    handle.position = position
                handle.visible = True
            else:
                handles.append(self.scene.add_label(f"{prefix}/{i}", text, position=position, font_screen_scale=0.8))
        for handle in handles[len(labels):]:
            handle.visible = False
