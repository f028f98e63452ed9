"""OpenGL plumbing of the viewer: the lazily imported PyOpenGL module, the platform
choice and the current context (placements of the unit meshes: ``placements``).

Nothing here knows about robots.  ``OpenGL.GL`` is imported on first use only, so a host
can still choose PyOpenGL's platform (:func:`require_osmesa_platform`) after importing
the viewer's modules.
"""
from __future__ import annotations

import ctypes
import importlib
import os
import sys
from types import ModuleType
from typing import Any


class _LazyModule:
    """Stands for a module that is imported on first attribute access.

    PyOpenGL fixes its platform (GLX, EGL, OSMesa) when ``OpenGL.GL`` is first imported;
    deferring that import lets a host pick the platform after importing this module.
    Looked-up attributes are cached on the instance, so later lookups cost a dict access.
    When this is the first import of PyOpenGL, its per-call error checking (a
    glGetError after every call, a third of a frame's Python time) is switched off;
    hosts and tests check ``glGetError`` once per frame instead.
    """

    def __init__(self, name: str) -> None:
        self._name = name

    def __getattr__(self, attr: str) -> Any:
        if "OpenGL.GL" not in sys.modules:
            import OpenGL

            OpenGL.ERROR_CHECKING = False
        module: ModuleType = importlib.import_module(self._name)
        value = getattr(module, attr)
        setattr(self, attr, value)
        return value


GL: Any = _LazyModule("OpenGL.GL")


def require_osmesa_platform() -> None:
    """Make PyOpenGL use OSMesa (offscreen, no display) in this process.

    Sets ``PYOPENGL_PLATFORM=osmesa`` when PyOpenGL has not chosen a platform yet.
    Raises RuntimeError when it already has and the choice is not OSMesa: PyOpenGL
    cannot switch platforms, so offscreen rendering must run in its own process.
    """
    platform_module = sys.modules.get("OpenGL.platform")
    if platform_module is None:
        os.environ["PYOPENGL_PLATFORM"] = "osmesa"
        return
    chosen = type(platform_module.PLATFORM).__name__
    if chosen != "OSMesaPlatform":
        raise RuntimeError(
            f"PyOpenGL was already imported with the {chosen} platform; offscreen rendering "
            "needs OSMesa. Set PYOPENGL_PLATFORM=osmesa before anything imports OpenGL, "
            "or render offscreen in a separate process."
        )


def context_key() -> int:
    """Address of the current GL context (0 when none is current or the platform cannot tell)."""
    from OpenGL import contextdata, error

    try:
        context = contextdata.getContext()
    except error.Error:
        return 0
    if isinstance(context, int):
        return context
    return int(ctypes.cast(context, ctypes.c_void_p).value or 0)
