"""The robot's surroundings: named obstacle shapes posed in the world frame (metres).

``World(obstacles)`` holds them in order; the floor, the half-space z <= 0 named
``"floor"``, comes first unless ``floor=False``.  Immutable; world files are read by
:func:`robot_sim.io.world_file.load_world`.
"""
from __future__ import annotations

from collections.abc import Iterable, Iterator, Mapping
from typing import Union

from robot_sim.model.shapes import SHAPE_TYPES, HalfSpace, Shape

FLOOR_NAME = "floor"

Obstacles = Union[Mapping[str, Shape], Iterable[tuple[str, Shape]]]


class World:
    """Named obstacles in the world frame: a mapping of names to shapes, or (name, shape)
    pairs.  ``floor`` adds the half-space z <= 0 as ``"floor"`` (first).  ValueError for a
    name that is empty, not a string or given twice, or a value that is not a shape."""

    __slots__ = ("_items", "_floor")

    def __init__(self, obstacles: Obstacles = (), *, floor: bool = True) -> None:
        if not isinstance(floor, bool):
            raise ValueError(f"World: floor must be True or False, got {floor!r}")
        pairs = list(obstacles.items()) if isinstance(obstacles, Mapping) else list(obstacles)
        items: list[tuple[str, Shape]] = [(FLOOR_NAME, HalfSpace())] if floor else []
        seen = {name for name, _ in items}
        for k, entry in enumerate(pairs):
            if not (isinstance(entry, tuple) and len(entry) == 2):
                raise ValueError(f"World: obstacle {k} must be a (name, shape) pair, got {entry!r}")
            name, shape = entry
            if not isinstance(name, str) or not name.strip():
                raise ValueError(f"World: obstacle {k}: name must be a non-empty string, got {name!r}")
            if name in seen:
                hint = " (the floor is added unless floor=False)" if name == FLOOR_NAME else ""
                raise ValueError(f"World: obstacle name {name!r} given twice{hint}")
            if not isinstance(shape, SHAPE_TYPES):
                raise ValueError(f"World: obstacle {name!r} must be a Box, Sphere, Cylinder, Capsule, Mesh or "
                                 f"HalfSpace, got {type(shape).__name__}")
            seen.add(name)
            items.append((name, shape))
        self._items = tuple(items)
        self._floor = floor

    @property
    def obstacles(self) -> tuple[tuple[str, Shape], ...]:
        """(name, shape) pairs in order, the floor first when there is one."""
        return self._items

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(name for name, _ in self._items)

    @property
    def shapes(self) -> tuple[Shape, ...]:
        return tuple(shape for _, shape in self._items)

    @property
    def floor(self) -> bool:
        """Whether the floor half-space is one of the obstacles."""
        return self._floor

    def __len__(self) -> int:
        return len(self._items)

    def __iter__(self) -> Iterator[tuple[str, Shape]]:
        return iter(self._items)

    def __getitem__(self, name: str) -> Shape:
        for key, shape in self._items:
            if key == name:
                return shape
        raise KeyError(f"no obstacle named {name!r}; obstacles: {', '.join(self.names) or 'none'}")

    def with_obstacles(self, obstacles: Obstacles) -> "World":
        """A new world with ``obstacles`` added after these (same floor setting)."""
        pairs = list(obstacles.items()) if isinstance(obstacles, Mapping) else list(obstacles)
        own = [item for item in self._items if not (self._floor and item[0] == FLOOR_NAME)]
        return World(own + pairs, floor=self._floor)

    def __repr__(self) -> str:
        return f"World({', '.join(self.names) or 'empty'})"
