"""``--record DIR --duration T --fps F``: render a session offscreen (OSMesa) to a numbered
PNG sequence, one frame every 1/F s of simulated time, and to an H.264 MP4 beside it when
the optional ``video`` extra (imageio-ffmpeg, which carries its own ffmpeg) is installed.
No Qt."""
from __future__ import annotations

import math
import os
import re
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from robot_sim.io.staged_folder import staged_folder
from robot_sim.viewer import settings as vs
from robot_sim import graphics as go

#: A frame's file name (``RECORD_FRAME_FORMAT``) with its index as group 1.
_FRAME_NAME = re.compile(re.escape(vs.RECORD_FRAME_FORMAT.split("{")[0]) + r"(\d+)" + re.escape(vs.RECORD_FRAME_FORMAT.split("}")[1]))

try:
    import imageio_ffmpeg
except ImportError:  # the optional extra: pip install 'robot-sim[video]'
    imageio_ffmpeg = None


class _Mp4:
    """An MP4 written frame by frame to a temporary name in its directory and renamed
    when complete, so a failed recording leaves no partial video."""

    def __init__(self, path: Path, size: tuple[int, int], fps: float) -> None:
        self.path = path
        self.tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp.mp4")
        # macro_block_size 2: H.264's yuv420p needs even sizes (odd ones are rounded up)
        self.writer: Any = imageio_ffmpeg.write_frames(
            str(self.tmp), size, fps=fps, quality=vs.RECORD_VIDEO_QUALITY, macro_block_size=2,
        )
        self.writer.send(None)

    def add(self, image: NDArray[np.uint8]) -> None:
        self.writer.send(np.ascontiguousarray(image[..., :3]))

    def finish(self) -> Path:
        self.writer.close()
        os.replace(self.tmp, self.path)
        return self.path

    def abort(self) -> None:
        self.writer.close()
        self.tmp.unlink(missing_ok=True)


def frame_times(duration: float, fps: float) -> list[float]:
    """Times [s] of the frames: k / fps for k = 0 .. round(duration * fps) (at least one).
    ValueError for a negative or non-finite duration, a non-positive fps or more than
    RECORD_MAX_FRAMES frames (checked before any is listed)."""
    if not (math.isfinite(duration) and duration >= 0.0):
        raise ValueError(f"duration must be a finite number of seconds >= 0, got {duration!r}")
    if not (math.isfinite(fps) and fps > 0.0):
        raise ValueError(f"fps must be a positive number, got {fps!r}")
    if not duration * fps < vs.RECORD_MAX_FRAMES:
        raise ValueError(f"duration × fps = {duration * fps:.3g} frames; at most {vs.RECORD_MAX_FRAMES} are accepted")
    return [k / fps for k in range(round(duration * fps) + 1)]


def record(
    session, out_dir: Path, duration: float, fps: float, size: tuple[int, int],
    text: dict[str, str] | None = None,
) -> tuple[list[Path], Path | None]:
    """Render ``session`` (a robot_sim.viewer.session.ViewerSession) at each of :func:`frame_times` into
    ``out_dir`` as ``RECORD_FRAME_FORMAT`` PNGs (each written atomically) and, when
    imageio-ffmpeg is installed, into ``RECORD_VIDEO_NAME`` at ``fps``; returns the frames'
    paths and the video's (None without the extra).  ``text``: each frame's PNG text
    chunks (what rendered it).  Everything is written into a folder beside ``out_dir`` and
    moved into it when complete (:func:`robot_sim.io.staged_folder.staged_folder`): a
    failure leaves an earlier recording there as it was, and the frames an earlier, longer
    recording left are removed only once this one is complete.

    A pick demo is shown at its start time plus each frame time (scrubbed, exact); anything
    else (the circle demo, an animation) is advanced by 1/fps between frames.
    """
    times = frame_times(duration, fps)
    start = session.pick.time if session.pick is not None else 0.0
    go.require_osmesa_platform()
    count = 0
    with staged_folder(out_dir, _is_output) as stage:  # an earlier recording stays until this one is complete
        video = _Mp4(stage / vs.RECORD_VIDEO_NAME, size, fps) if imageio_ffmpeg is not None else None
        try:
            with go.OffscreenRenderer(*size) as renderer:
                for index, t in enumerate(times):
                    if session.pick is not None:
                        session.show_pick_at(start + t)
                    elif index:
                        session.step(1.0 / fps)
                    image = renderer.render(session.camera, session.scene(), session.options)
                    go.save_png(stage / vs.RECORD_FRAME_FORMAT.format(index=index), image, text)
                    count += 1
                    if video is not None:
                        video.add(image)
        except BaseException:
            if video is not None:
                video.abort()
            raise
        if video is not None:
            video.finish()
    paths = [out_dir / vs.RECORD_FRAME_FORMAT.format(index=index) for index in range(count)]
    return paths, (out_dir / vs.RECORD_VIDEO_NAME if video is not None else None)


def _is_output(name: str) -> bool:
    """Whether ``name`` is a file a recording writes (a frame named exactly like
    ``RECORD_FRAME_FORMAT``, or the video): an earlier recording's such files that this
    one does not write are removed, so the folder's sequence is this recording."""
    return bool(_FRAME_NAME.fullmatch(name)) or name == vs.RECORD_VIDEO_NAME
