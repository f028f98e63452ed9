"""``rs.Visualizer``: a robot shown from a script or a notebook, as Pinocchio's visualizers
(``display``, ``play``, ``captureImage``) and MuJoCo's passive viewer (the user's loop owns
time) do it::

    import robot_sim as rs
    robot = rs.load_robot("ur5")
    with rs.Visualizer(robot, size=(320, 240)) as viz:   # offscreen: no display needed
        viz.display(robot.q_home)
        image = viz.capture()                            # (240, 320, 3) uint8

The backend shows :attr:`Visualizer.session`
(:class:`~robot_sim.viewer.session.ViewerSession`: joints, options, trail, camera,
world) and is loaded on request (robot_sim.viewer.backend.BACKENDS): ``"offscreen"``
(OSMesa), ``"window"`` (the Qt window; each :meth:`~Visualizer.display` serves its events,
as matplotlib's interactive mode does) and ``"web"`` (a browser view).  Joint values are SI
(rad, m), times seconds, sizes pixels (width, height).
"""
from __future__ import annotations

import importlib
import math
import time
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robot_sim.kinematics import forward_kinematics
from robot_sim.model.params import RobotParams
from robot_sim.model.world import World
from robot_sim.planning.trajectory import Trajectory, check_times
from robot_sim.viewer.backend import BACKENDS, Backend
from robot_sim.viewer.builder import SessionSpec, build_session
from robot_sim.viewer.session import ViewerSession

#: Largest picture side accepted [px] (as the command line's --size).
MAX_SIZE = 8192


def load_backend(name: str) -> type[Backend]:
    """The backend class named ``name`` (a key of BACKENDS), imported now.  ValueError for
    another name."""
    where = BACKENDS.get(name) if isinstance(name, str) else None
    if where is None:
        raise ValueError(f"backend: expected one of {', '.join(BACKENDS)}, got {str(name)[:80]!r}")
    module, cls = where.split(":")
    return getattr(importlib.import_module(module), cls)


def _check_size(size: tuple[int, int]) -> tuple[int, int]:
    try:
        width, height = (int(v) for v in size)
        ok = all(1 <= v <= MAX_SIZE and v == s for v, s in zip((width, height), size))
    except (TypeError, ValueError):
        ok = False
    if not ok:
        raise ValueError(f"size: expected (width, height) in pixels, each 1..{MAX_SIZE}, got {str(size)[:80]}")
    return width, height


class Visualizer:
    """Shows ``robot`` through a backend ("offscreen", "window" or "web"); ``size`` is the
    picture's (width, height) in pixels; ``theme`` (graphics.THEMES) and ``look`` (the
    robot's looks) as the command line's --theme and --look; ``world`` the obstacles
    drawn (None: the floor only); ``backend_options`` go to the backend (e.g. the web
    server's port).  Attributes the backend adds (e.g. ``url``) are read through the
    visualizer.  ValueError for a bad name, size, theme or look, before anything opens."""

    def __init__(self, robot: RobotParams, backend: str = "offscreen", size: tuple[int, int] = (800, 600),
                 theme: str | None = None, look: str | None = None, world: World | None = None,
                 **backend_options: Any) -> None:
        if not isinstance(robot, RobotParams):
            raise TypeError(f"robot: expected a RobotParams (rs.load_robot), got {type(robot).__name__}")
        size = _check_size(size)
        cls = load_backend(backend)
        self._session = build_session(SessionSpec(robot, size=size, theme=theme, look=look, world=world))
        self.backend: Backend = cls(self._session, size=size, **backend_options)

    @property
    def session(self) -> ViewerSession:
        """The session shown: its frames, options, trail, annotation, camera and world.
        Change it, then call :meth:`refresh` (``display`` and ``play`` do)."""
        return getattr(self.backend, "session", self._session)

    @property
    def robot(self) -> RobotParams:
        """The robot shown."""
        return self.session.robot

    def display(self, q: ArrayLike | None = None) -> None:
        """Pose the arm at ``q`` (n,) [rad, m] (None: as it is) and show it now; the window
        backend serves its events meanwhile.  ValueError for a wrong length or a
        non-finite value (nothing changes)."""
        if q is not None:
            self.session.set_q(np.asarray(q, dtype=float))
        self.backend.refresh()

    def refresh(self) -> None:
        """Show the session as it is now (after changing its options, trail or camera)."""
        self.backend.refresh()

    def play(self, trajectory: Trajectory | tuple[ArrayLike, ArrayLike], speed: float = 1.0) -> None:
        """Show ``trajectory`` (a Trajectory, or ``(t, q)`` arrays (N,) s and (N, n)).
        Offscreen every sample is rendered once, at once, without sleeping.  A real-time
        backend (window, web) shows at each moment the latest sample due, sample k being due
        ``(t[k] - t[0]) / speed`` seconds of wall time after the start, and serves its
        events meanwhile: samples due faster than frames can be drawn are skipped, the last
        one is always shown, and a trail shown gets the tool positions of the skipped ones.
        ValueError for bad arrays or speed (nothing is shown)."""
        if not (isinstance(speed, (int, float)) and math.isfinite(speed) and speed > 0):
            raise ValueError(f"speed: expected a positive finite number, got {str(speed)[:80]}")
        t, q = self._samples(trajectory)
        if not self.backend.realtime:
            for qk in q:
                self.display(qk)
            return
        due = (t - t[0]) / speed
        start, k, shown = time.monotonic(), 0, -1
        while True:
            k = max(k, int(np.searchsorted(due, time.monotonic() - start, side="right")) - 1)
            trail = self.session.trail
            if trail is not None and k > shown + 1:  # the samples skipped still mark the path
                for point in forward_kinematics(self.robot, q[shown + 1:k])[:, :3, 3]:
                    trail.add(point)
            self.display(q[k])
            shown = k
            if k == len(t) - 1:
                return
            self.backend.wait(max(0.0, due[k + 1] - (time.monotonic() - start)))

    def _samples(self, trajectory: Trajectory | tuple[ArrayLike, ArrayLike]) -> tuple[NDArray, NDArray]:
        if isinstance(trajectory, Trajectory):
            t, q = trajectory.t, trajectory.q
        else:
            try:
                t_in, q_in = trajectory
            except (TypeError, ValueError):
                raise ValueError("trajectory: expected a Trajectory or a (t, q) pair of arrays") from None
            t = check_times(t_in, "t")
            q = np.asarray(q_in, dtype=float)
        n = self.robot.n_dofs
        if q.shape != (t.shape[0], n):
            raise ValueError(f"trajectory: q must have shape ({t.shape[0]}, {n}) for {t.shape[0]} times and "
                             f"robot '{self.robot.name}', got {q.shape}")
        if not np.isfinite(q).all():
            raise ValueError("trajectory: q contains NaN or infinite values")
        return t, q

    def capture(self) -> NDArray[np.uint8]:
        """The picture shown, (H, W, 3) uint8 RGB, top row first."""
        return self.backend.capture()

    def close(self) -> None:
        """Close the backend (window, server, GL context); harmless twice."""
        self.backend.close()

    def _repr_html_(self) -> str | None:
        """Jupyter shows the backend inline when it can (the web backend: its live page;
        ``viz.embed()`` gives a static copy that stays in a saved notebook)."""
        inline = getattr(self.backend, "_repr_html_", None)
        return None if inline is None else inline()

    def __enter__(self) -> Visualizer:
        return self

    def __exit__(self, *exc_info: object) -> None:
        self.close()

    def __getattr__(self, name: str) -> Any:
        # the backend's own attributes (e.g. the web backend's url); only called when
        # normal lookup fails, and never for private names
        if name.startswith("_") or "backend" not in self.__dict__:
            raise AttributeError(name)
        return getattr(self.__dict__["backend"], name)


def show(robot: RobotParams, q: ArrayLike | None = None, backend: str = "window", **options: Any) -> NDArray[np.uint8] | None:
    """The one-line form: show ``robot`` at ``q`` (None: home).  A real-time backend is
    served until it closes (the window: until the user closes it) and None is returned;
    offscreen the picture (H, W, 3) uint8 is returned.  ``options``: Visualizer's."""
    with Visualizer(robot, backend=backend, **options) as viz:
        viz.display(q)
        if not viz.backend.realtime:
            return viz.capture()
        viz.backend.wait(math.inf)
    return None
