"""The scene item model (after pyqtgraph's ``GLGraphicsItem``): the render path holds a
persistent list of items; each reads what it shows from the frame's Scene and options,
owns its GL objects and paints itself in one layer of the frame.

Layers, in drawing order: ``opaque`` (lit, depth written; also drawn into the shadow map
when ``casts_shadow``), ``translucent`` (blended, depth tested, not written), ``overlay``
(over a cleared depth buffer: frames, target, arrows, annotation lines) and ``text``
(labels in pixels).  Within a layer items are drawn by ``order``.

An opaque item that is ``cached`` (the workspace cloud: costly to draw, and the same
while the camera stands still) is drawn into the view's background picture, with the
clear colour and its depth, only when that picture changes; each frame then starts from
a copy of it (:class:`~robot_sim.graphics.render.View`).
"""
from __future__ import annotations

from typing import TYPE_CHECKING, ClassVar

import numpy as np
from numpy.typing import NDArray

from robot_sim.graphics.meshes import CUBE_CORNERS

if TYPE_CHECKING:
    from robot_sim.graphics.frame import Drawing, Frame
    from robot_sim.graphics.scene import GraphicsOptions, Scene

LAYERS = ("opaque", "translucent", "overlay", "text")



def around(centres: NDArray[np.float64], half: NDArray[np.float64] | float) -> NDArray[np.float64]:
    """Corners (8N, 3) of the cubes of half side ``half`` (scalar or (N,), metres) about
    world ``centres`` (N, 3): their hull encloses a ball of radius ``half`` about each."""
    centres = np.asarray(centres, dtype=float).reshape(-1, 1, 3)
    halves = np.broadcast_to(np.asarray(half, dtype=float).reshape(-1), (len(centres),))
    return (centres + halves[:, None, None] * CUBE_CORNERS).reshape(-1, 3)


class Item:
    """One drawable of the scene.  Subclasses set ``layer`` and ``order``, implement
    :meth:`paint` and, as needed, :meth:`update`, :meth:`paint_depth`,
    :meth:`shadow_key`, :meth:`bounds` and :meth:`release`."""

    layer: ClassVar[str] = "opaque"
    order: ClassVar[float] = 0.0
    casts_shadow: ClassVar[bool] = False
    cached: ClassVar[bool] = False

    def __init__(self) -> None:
        self.visible = True

    def update(self, scene: Scene, options: GraphicsOptions) -> None:
        """Take what this frame shows from ``scene`` and ``options`` (no GL); set
        ``visible`` False to be skipped."""

    def paint(self, frame: Frame) -> None:
        """Issue this item's GL calls in its layer (the layer's GL state is set)."""
        raise NotImplementedError(f"{type(self).__name__} must implement paint()")

    def paint_depth(self, drawing: Drawing) -> None:
        """Draw this item's geometry into the shadow map (items that ``casts_shadow``):
        the same instances and meshes as :meth:`paint`, through ``drawing``."""

    def shadow_key(self) -> object:
        """A value that changes whenever this item's shadow does (the shadow map is
        redrawn only then)."""
        return None

    def cache_key(self) -> object:
        """A value that changes whenever what a ``cached`` item draws does, the camera
        aside (its background picture is redrawn only then, or when the view moves)."""
        return None

    def bounds(self) -> NDArray[np.float64]:
        """World points (N, 3) whose convex hull encloses what this item draws: the shadow
        map is fitted to its casters' bounds, and the overlay layer clears depth only over
        the picture of its items' bounds, so an overlay item that tests depth must enclose
        every fragment it draws (:func:`around` helps)."""
        return np.zeros((0, 3))

    def release(self, current: bool) -> None:
        """Let go of this item's GL objects: delete them when ``current`` (their context
        is current), else only forget them (their context is gone)."""
