"""The offscreen host: an OSMesa context rendering images without a display, and PNG
writing (zlib only)."""
from __future__ import annotations

import os
import struct
import zlib
from typing import Mapping

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robot_sim.graphics import defs as gd
from robot_sim.io.files import write_atomic
from robot_sim.graphics.camera import Camera
from robot_sim.graphics.gl import GL, require_osmesa_platform
from robot_sim.graphics.render import View
from robot_sim.graphics.scene import GraphicsOptions, Scene


class OffscreenRenderer:
    """An OSMesa context rendering ``width`` x ``height`` RGBA images without a display.

    Use as a context manager or call :meth:`close`.  Needs PyOpenGL on its OSMesa
    platform (see :func:`require_osmesa_platform`, called here) and libOSMesa.  Its
    :class:`~robot_sim.graphics.render.View` (``self.view``) keeps the scene's items and
    their GL objects from frame to frame.
    """

    def __init__(self, width: int, height: int) -> None:
        if int(width) < 1 or int(height) < 1:
            raise ValueError(f"OffscreenRenderer: size must be positive, got {width}x{height}")
        require_osmesa_platform()
        self.width, self.height = int(width), int(height)
        missing = (
            f"OSMesa is not available; install the Debian package {gd.OSMESA_PACKAGE} "
            f"(apt-get install {gd.OSMESA_PACKAGE})"
        )
        try:
            from OpenGL import osmesa

            self._osmesa = osmesa
            self._context = osmesa.OSMesaCreateContextExt(
                osmesa.OSMESA_RGBA, gd.DEPTH_BUFFER_BITS, gd.OSMESA_STENCIL_BITS, 0, None
            )
        except Exception as exc:  # ImportError, NullFunctionError, ctypes errors
            raise RuntimeError(f"{missing}: {exc}") from exc
        if not self._context:
            raise RuntimeError(f"{missing}: OSMesaCreateContextExt failed")
        self._buffer = np.zeros((self.height, self.width, 4), dtype=np.uint8)
        self._make_current()
        self.view = View()

    def _make_current(self) -> None:
        if self._context is None:
            raise RuntimeError("OffscreenRenderer: render() after close()")
        ok = self._osmesa.OSMesaMakeCurrent(self._context, self._buffer, GL.GL_UNSIGNED_BYTE, self.width, self.height)
        if not ok:
            raise RuntimeError(f"OSMesaMakeCurrent failed for a {self.width}x{self.height} buffer")
        self._osmesa.OSMesaPixelStore(self._osmesa.OSMESA_Y_UP, 0)  # row 0 = top of the image

    def render(self, camera: Camera, scene: Scene, options: GraphicsOptions) -> NDArray[np.uint8]:
        """Render ``scene`` and return a copy of the image (H, W, 4) uint8 RGBA, row 0 at the top."""
        self._make_current()
        self.view.render(camera, scene, options, self.width, self.height)
        GL.glFinish()
        return self._buffer.copy()

    def close(self) -> None:
        """Free the context and its GL objects; further render() calls raise."""
        if self._context is not None:
            self._make_current()
            self.view.release()
            self._osmesa.OSMesaDestroyContext(self._context)
            self._context = None

    def __enter__(self) -> OffscreenRenderer:
        return self

    def __exit__(self, *exc_info: object) -> None:
        self.close()


# ------------------------------------------------------------------------------- PNG


def save_png(path: str | os.PathLike[str], image: ArrayLike, text: Mapping[str, str] | None = None) -> None:
    """Write ``image`` (H, W, 3) RGB or (H, W, 4) RGBA uint8, row 0 at the top, as a PNG,
    with ``text`` (keyword -> UTF-8 text, e.g. the command that rendered it) as iTXt chunks.

    The file is written atomically (robot_sim.io.files.write_atomic): complete or not at all.  Raises
    ValueError for another shape or dtype and robot_sim.io.files.FileWriteError (an OSError) naming
    the path and the reason when it cannot be written."""
    img = np.asarray(image)
    if img.dtype != np.uint8 or img.ndim != 3 or img.shape[2] not in (3, 4) or 0 in img.shape:
        raise ValueError(f"save_png: need an (H, W, 3|4) uint8 image, got {img.shape} {img.dtype}")
    height, width, channels = img.shape
    rows = np.zeros((height, 1 + width * channels), dtype=np.uint8)  # filter byte 0 per row
    rows[:, 1:] = img.reshape(height, -1)

    def chunk(kind: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    color_type = 6 if channels == 4 else 2
    header = struct.pack(">IIBBBBB", width, height, 8, color_type, 0, 0, 0)
    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header)
    for keyword, value in (text or {}).items():  # keyword, no compression, no language, no translation
        png += chunk(b"iTXt", keyword.encode("latin-1")[:79] + b"\0\0\0\0\0" + value.encode("utf-8"))
    png += chunk(b"IDAT", zlib.compress(rows.tobytes(), 6))
    png += chunk(b"IEND", b"")
    write_atomic(path, png)
