"""``--record DIR --duration T --fps F``: render a session offscreen (OSMesa) to a numbered
PNG sequence, one frame every 1/F s of simulated time.  No Qt."""
from __future__ import annotations

import math
from pathlib import Path

import graphics_defs as gd
import graphics_objects as go


def frame_times(duration: float, fps: float) -> list[float]:
    """Times [s] of the frames: k / fps for k = 0 .. round(duration * fps) (at least one).
    ValueError for a negative or non-finite duration or a non-positive fps."""
    if not (math.isfinite(duration) and duration >= 0.0):
        raise ValueError(f"duration must be a finite number of seconds >= 0, got {duration!r}")
    if not (math.isfinite(fps) and fps > 0.0):
        raise ValueError(f"fps must be a positive number, got {fps!r}")
    return [k / fps for k in range(round(duration * fps) + 1)]


def record(session, out_dir: Path, duration: float, fps: float, size: tuple[int, int]) -> list[Path]:
    """Render ``session`` (a viewer_state.ViewerSession) at each of :func:`frame_times` into
    ``out_dir`` as ``RECORD_FRAME_FORMAT`` PNGs (each written atomically); returns the paths.

    A pick demo is shown at its start time plus each frame time (scrubbed, exact); anything
    else (the circle demo, an animation) is advanced by 1/fps between frames.
    """
    times = frame_times(duration, fps)
    start = session.pick.time if session.pick is not None else 0.0
    paths = []
    go.require_osmesa_platform()
    with go.OffscreenRenderer(*size) as renderer:
        for index, t in enumerate(times):
            if session.pick is not None:
                session.show_pick_at(start + t)
            elif index:
                session.step(1.0 / fps)
            image = renderer.render(session.camera, session.scene(), session.options)
            path = out_dir / gd.RECORD_FRAME_FORMAT.format(index=index)
            go.save_png(path, image)
            paths.append(path)
    return paths
