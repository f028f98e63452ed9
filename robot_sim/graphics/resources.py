"""GL objects per context: the shared unit-mesh display lists, and the registry through
which drawables own their own GL objects (display lists, buffers) in every context they
are drawn in.

A drawable keeps its objects in a ``WeakKeyDictionary`` keyed by the context's
:class:`ContextResources`; when the context goes away (an offscreen renderer closes, a
new context appears at a reused address) those entries vanish with it, and when the
drawable is collected its objects are queued and deleted at the next frame drawn in
their context (GL objects can only be deleted while their context is current).
"""
from __future__ import annotations

import weakref
from typing import Any, Callable

import numpy as np

from robot_sim.graphics.gl import GL, compile_list, context_key, draw_arrays, gl_state
from robot_sim.graphics.meshes import unit_meshes


class ContextResources:
    """GL objects of one context: unit-mesh display lists and objects queued for deletion."""

    def __init__(self) -> None:
        self.lists = {
            name: compile_list(lambda v=v, n=n: draw_arrays(GL.GL_TRIANGLES, v, n))
            for name, (v, n) in unit_meshes().items()
        }
        self._dead_lists: list[int] = []
        self._dead_buffers: list[int] = []

    def valid(self) -> bool:
        """True while the current context still holds these objects (a context created
        at a reused address has none of them)."""
        return bool(GL.glIsList(self.lists["sphere"]))

    def own(self, owner: object, kind: str, handle: int) -> None:
        """Delete GL object ``handle`` (``kind`` "list" or "buffer") of this context at the
        next frame after ``owner`` has been collected."""
        weakref.finalize(owner, (self._dead_lists if kind == "list" else self._dead_buffers).append, handle)

    def free_dead(self) -> None:
        """Delete the objects of collected owners (this context must be current)."""
        for handle in self._dead_lists:
            GL.glDeleteLists(handle, 1)
        self._dead_lists.clear()
        if self._dead_buffers:
            GL.glDeleteBuffers(len(self._dead_buffers), np.array(self._dead_buffers, dtype=np.uint32))
            self._dead_buffers.clear()


_RESOURCES: dict[int, ContextResources] = {}


def resources() -> ContextResources:
    """The current context's resources, built on first use or after the context changed."""
    key = context_key()
    found = _RESOURCES.get(key)
    if found is None or not found.valid():
        found = _RESOURCES[key] = ContextResources()
    return found


def forget_context(key: int) -> None:
    """Drop the resources of the context at address ``key`` (it is being destroyed)."""
    _RESOURCES.pop(key, None)


class OwnedObjects:
    """GL objects one drawable owns, one per context, built on first use in a context.

    ``get(build, kind)`` returns this context's object, calling ``build()`` (which
    creates it in the current context and returns its handle) the first time.
    """

    def __init__(self, owner: object) -> None:
        self._owner = weakref.ref(owner)
        self._handles: weakref.WeakKeyDictionary[ContextResources, Any] = weakref.WeakKeyDictionary()

    def get(self, build: Callable[[], int], kind: str = "list") -> int:
        """The current context's object, built by ``build()`` on first use."""
        res = resources()
        handle = self._handles.get(res)
        if handle is None:
            handle = self._handles[res] = build()
            owner = self._owner()
            if owner is not None:
                res.own(owner, kind, handle)
        return handle


class Drawable:
    """Something the render path draws (pyqtgraph's GLGraphicsItem model): it owns its GL
    objects (``self.gl``, built per context on first use) and paints itself inside the GL
    state preset ``gl_preset`` (see ``robot_sim.graphics.gl.GL_PRESETS``), as lines when ``wireframe``.
    Subclasses implement :meth:`paint`; hosts call :meth:`draw`."""

    gl_preset: str = "opaque"
    wireframe: bool = False

    def __init__(self) -> None:
        self.gl = OwnedObjects(self)

    def paint(self) -> None:
        """Issue the GL calls of this drawable (the preset is already set)."""
        raise NotImplementedError(f"{type(self).__name__} must implement paint()")

    def draw(self) -> None:
        """Paint inside this drawable's GL state, restoring the previous state afterwards."""
        with gl_state(self.gl_preset, wireframe=self.wireframe):
            self.paint()
