"""A self-contained HTML page of a viewer session: viser's client (bundled in its wheel, no
network fetch) with the scene recorded into the file.  The current pose, or a motion (a
``Trajectory``, or the session's pick task) sampled at ``fps``, which the page plays
with play/pause and a time slider.  It opens from disk with the network off.

The recording is made on a private server bound to 127.0.0.1 on a free port (viser
records what a server sends); the user's session is not changed (a copy is posed).
The file is written atomically.
"""
from __future__ import annotations

import copy
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from robot_sim.io.files import check_writable, write_atomic
from robot_sim.web.camera import aim_initial_camera
from robot_sim.web.scene import WebScene
from robot_sim.web.server import start_server, stop_server

if TYPE_CHECKING:
    from robot_sim.planning.trajectory import Trajectory
    from robot_sim.viewer.session import ViewerSession

#: Frames per second of an exported motion unless told otherwise.
EXPORT_FPS = 25.0
#: At most this many frames (a bound on the file before any work starts).
MAX_EXPORT_FRAMES = 20_000
MAX_EXPORT_FPS = 120.0


def _posed_copy(session: ViewerSession) -> ViewerSession:
    """A copy of ``session`` to pose for the recording (its robot, world, options, target,
    camera and pick task; no simulation)."""
    from robot_sim.viewer.session import ViewerSession  # loaded when a page is made

    twin = ViewerSession(session.robot, aspect=session.aspect, world=session.world)
    twin.options = copy.deepcopy(session.options)
    twin.camera = copy.deepcopy(session.camera)
    twin.state.set_q(session.state.q())
    twin.state.set_q_des(session.state.q_des())
    twin.target_tf, twin.ik_result = session.target_tf, session.ik_result
    twin.update_kinematics()
    return twin


def sample_times(duration: float, fps: float) -> np.ndarray:
    """Sample times (k,) from 0 to ``duration`` s at ``fps``, the end included; ValueError
    when fps is not in (0, MAX_EXPORT_FPS] or the count exceeds MAX_EXPORT_FRAMES."""
    if not np.isfinite(fps) or not 0.0 < fps <= MAX_EXPORT_FPS:
        raise ValueError(f"export_html: fps must be in (0, {MAX_EXPORT_FPS:g}], got {fps!r}")
    if not np.isfinite(duration) or duration < 0.0:
        raise ValueError(f"export_html: the motion's duration must be finite and >= 0 s, got {duration!r}")
    count = int(np.floor(duration * fps + 1e-9)) + 1
    if count > MAX_EXPORT_FRAMES:
        raise ValueError(f"export_html: {count} frames ({duration:g} s at {fps:g} fps) exceed the limit of "
                         f"{MAX_EXPORT_FRAMES}; lower the fps or shorten the motion")
    times = np.arange(count) / fps
    return times if times[-1] >= duration - 1e-9 else np.r_[times, duration]


def export_html(session: ViewerSession, path: str | Path, trajectory: Trajectory | None = None,
                fps: float | None = None) -> Path:
    """Write ``session`` as a self-contained HTML page to ``path`` (atomically) and return
    the path; see :func:`export_page`.  ValueError for a name not ending in .html,
    FileWriteError for a place that cannot be written (both before any work)."""
    target = Path(path)
    if target.suffix.lower() not in (".html", ".htm"):
        raise ValueError(f"export_html: '{str(target.name)[:80]}' must end in .html")
    check_writable(target)
    write_atomic(target, export_page(session, trajectory, fps))
    return target


def export_page(session: ViewerSession, trajectory: Trajectory | None = None, fps: float | None = None) -> str:
    """``session`` as a self-contained HTML page (text).  ``trajectory``
    (robot_sim.planning.Trajectory): the motion played from its first to its last time;
    None: the session's pick task if it shows one, else the current pose alone.  ``fps``:
    samples per second of a motion (default ``EXPORT_FPS``)."""
    rate = EXPORT_FPS if fps is None else float(fps)
    twin = _posed_copy(session)
    pick = session.pick
    if trajectory is not None:
        t0 = float(trajectory.t[0])
        times = sample_times(float(trajectory.t[-1]) - t0, rate)
        poses = trajectory.evaluate(t0 + times)[0]
        shows = [lambda q=q: twin.set_q(q) for q in poses]
    elif pick is not None:
        twin.start_pick(pick.plan, effort=pick.effort, mode=pick.mode)
        twin.camera = copy.deepcopy(session.camera)
        times = sample_times(pick.duration, rate)
        shows = [lambda t=t: twin.show_pick_at(t) for t in times]
    else:
        times, shows = np.zeros(1), [lambda: None]
    server = start_server("127.0.0.1", None, dark=twin.options.theme == "dark", warn=None)
    try:
        view = WebScene(server.scene)
        aim_initial_camera(server, twin.camera)
        shows[0]()
        view.sync(twin)
        recording = server.get_scene_serializer()
        for show, gap in zip(shows[1:], np.diff(times)):
            recording.insert_sleep(float(gap))
            show()
            view.sync(twin)
        if len(times) > 1:
            recording.insert_sleep(1.0 / rate)
        page = recording.as_html(dark_mode=twin.options.theme == "dark")
    finally:
        stop_server(server)
    return page
