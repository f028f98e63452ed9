"""A robot's collision shapes and a world's obstacles packed for the compiled loops.

The robot collides with its link shapes (``robot.collisions``/``robot.base_collisions``
when its file gives any, else :func:`.capsules.dh_capsules`); links are named ``"base"``
(frame 0) and ``"link1"`` .. ``"linkN"`` (frame i), obstacles by their world names.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from robot_sim.kernels import chain
from robot_sim.kernels.model import compiled_model, kernel_array
from robot_sim.model.params import RobotParams
from robot_sim.model.shapes import Shape
from robot_sim.model.world import World

from robot_sim.collision.capsules import dh_capsules
from robot_sim.collision.pack import pack

FloatArray = NDArray[np.float64]


def link_shapes(robot: RobotParams) -> tuple[tuple[Shape, ...], ...]:
    """Collision shapes of links 0..n, each posed in its link frame (n + 1 tuples): the
    robot's own (``base_collisions``, ``collisions``) when it has any, else DH capsules."""
    links = tuple(tuple(shapes) for shapes in robot.collisions)
    if robot.base_collisions or any(links):
        return (tuple(robot.base_collisions),) + links + ((),) * (robot.n_dofs - len(links))
    return dh_capsules(robot)


@dataclass(frozen=True, eq=False)
class Scene:
    """Packed shapes: robot shapes first (``link`` (S,) says which link holds each), then
    the obstacles; ``owner`` (S + O,) is the name of each row's link or obstacle."""

    robot: RobotParams
    world: World
    shapes: tuple[Shape, ...]  # robot shapes in link frames, then obstacles in the world
    owner: tuple[str, ...]
    link: NDArray[np.int64]
    dh: FloatArray
    world0: FloatArray
    kinds: NDArray[np.int64]
    local: FloatArray
    recs0: FloatArray
    bc: FloatArray
    br: FloatArray
    verts: FloatArray

    @property
    def n_robot(self) -> int:
        return int(self.link.shape[0])

    def args(self) -> tuple:
        """The arguments of :mod:`.batch` after the configurations."""
        return (self.dh, self.robot.is_modified, self.world0, self.link, self.local, self.recs0, self.kinds,
                self.bc, self.br)


def build_scene(robot: RobotParams, world: World) -> Scene:
    names = robot.link_names
    shapes: list[Shape] = []
    owner: list[str] = []
    link: list[int] = []
    for k, group in enumerate(link_shapes(robot)):
        for shape in group:
            shapes.append(shape)
            owner.append(names[k])
            link.append(k)
    for name, shape in world.obstacles:
        shapes.append(shape)
        owner.append(name)
    packed = pack(shapes)
    S = len(link)
    return Scene(
        robot=robot, world=world, shapes=tuple(shapes), owner=tuple(owner),
        link=np.array(link, dtype=np.int64), dh=compiled_model(robot).table,
        world0=np.ascontiguousarray(robot.base_tf.mat, dtype=float), kinds=packed.kinds,
        local=np.ascontiguousarray(packed.recs[:S]), recs0=np.ascontiguousarray(packed.recs),
        bc=np.ascontiguousarray(packed.bound_center), br=packed.bound_radius, verts=packed.verts,
    )


def frames(scene: Scene, q: FloatArray) -> FloatArray:
    """World frames 0..n (n + 1, 4, 4) at q (n,), from the compiled chain."""
    F = np.empty((scene.robot.n_dofs + 1, 3, 4))
    chain.frames(scene.dh, scene.robot.is_modified, scene.world0, kernel_array(q), F)
    out = np.zeros((F.shape[0], 4, 4))
    out[:, :3, :] = F
    out[:, 3, 3] = 1.0
    return out
