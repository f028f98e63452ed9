"""The workspace cloud as one cancellable background job with a visible state (Qt-free).

A :class:`WorkspaceJob` computes at most one cloud at a time in a worker thread.  Its
``state`` is always one of

* ``idle``: nothing computed for this robot;
* ``computing``: a worker is sampling (``message`` says how many points);
* ``shown`` / ``hidden``: a cloud is ready and drawn or not;
* ``failed``: the computation raised (``message`` holds the reason, e.g. a prismatic
  joint without limits);
* ``cancelled``: the user stopped it (pressed E again, or switched robot).

Starting a job cancels the previous one, which stops at its next chunk of samples, so
switching robots never piles up threads or memory.  The worker never touches the
caller's objects: it calls ``notify()`` (from its own thread) when it ends, and the GUI
thread then calls :meth:`collect` to take the result; results of a job that has been
cancelled or replaced are dropped.  This module imports neither Qt nor OpenGL.
"""
from __future__ import annotations

import threading
from typing import Callable

from robot_sim.graphics.workspace import WorkspaceCloud
from robot_sim.kinematics import WorkspaceCancelled, workspace_points
from robot_sim.model.messages import clip
from robot_sim.model.params import RobotParams
from robot_sim.viewer import settings as vs

IDLE, COMPUTING, SHOWN, HIDDEN, FAILED, CANCELLED = "idle", "computing", "shown", "hidden", "failed", "cancelled"

#: What computes a cloud: (robot, number of points, cancelled) -> the cloud.
Compute = Callable[[RobotParams, int, Callable[[], bool]], WorkspaceCloud]


def compute_workspace(robot: RobotParams, n_points: int,
                      cancelled: Callable[[], bool] | None = None) -> WorkspaceCloud:
    """Workspace cloud of ``n_points`` endeffector positions (m, world) coloured by
    manipulability; ``cancelled`` as in kinematics.workspace_points."""
    points, manipulability = workspace_points(robot, n_points, seed=vs.WORKSPACE_SEED, cancelled=cancelled)
    return WorkspaceCloud(points, manipulability)


class WorkspaceJob:
    """One workspace computation at a time, cancellable, with a state the window shows.

    ``compute(robot, n_points, cancelled)`` builds the cloud; it must call ``cancelled()``
    now and then and stop (raise WorkspaceCancelled) when it returns True.  ``notify()``
    is called from the worker thread when a computation ends (however it ends).
    """

    def __init__(self, compute: Compute, notify: Callable[[], None]) -> None:
        self._compute = compute
        self._notify = notify
        self._lock = threading.Lock()
        self._generation = 0
        self._stop = threading.Event()
        self._outcome: tuple[int, str, WorkspaceCloud | str] | None = None  # (generation, state, cloud or message)
        self._thread: threading.Thread | None = None
        self.state = IDLE
        self.message = ""
        self.cloud: WorkspaceCloud | None = None

    # ---- GUI thread ----
    def start(self, robot: RobotParams, n_points: int) -> None:
        """Cancel whatever runs and start computing ``n_points`` for ``robot``."""
        self.cancel(quiet=True)
        with self._lock:
            self._generation += 1
            generation, stop = self._generation, threading.Event()
            self._stop = stop
            self._outcome = None
        self.state, self.cloud = COMPUTING, None
        self.message = f"computing workspace ({n_points} points) ..."
        self._thread = threading.Thread(
            target=self._work, args=(generation, stop, robot, n_points), name="workspace", daemon=True
        )
        self._thread.start()

    def cancel(self, quiet: bool = False) -> None:
        """Stop a running computation (its result will be dropped).  Unless ``quiet``,
        the state becomes ``cancelled``; a finished cloud is kept."""
        with self._lock:
            self._stop.set()
            self._generation += 1
            self._outcome = None
        if self.state == COMPUTING:
            self.state = IDLE if quiet else CANCELLED
            self.message = "" if quiet else "workspace computation cancelled"

    def reset(self) -> None:
        """Forget everything (a new robot): cancel, drop the cloud, back to idle."""
        self.cancel(quiet=True)
        self.state, self.message, self.cloud = IDLE, "", None

    def toggle(self, robot: RobotParams, n_points: int) -> str:
        """What key E does: start when there is no cloud, cancel while computing, show or
        hide a finished cloud.  Returns the new state."""
        if self.state == COMPUTING:
            self.cancel()
        elif self.state == SHOWN:
            self.state, self.message = HIDDEN, "workspace hidden"
        elif self.state == HIDDEN:
            self.state, self.message = SHOWN, f"workspace: {len(self.cloud.points)} points"
        else:
            self.start(robot, n_points)
        return self.state

    def collect(self) -> bool:
        """Take the outcome of the current job if it has ended; True if the state changed."""
        with self._lock:
            outcome, self._outcome = self._outcome, None
            current = self._generation
        if outcome is None or outcome[0] != current or self.state != COMPUTING:
            return False
        _, state, value = outcome
        if state == SHOWN:
            self.state, self.cloud = SHOWN, value
            self.message = f"workspace: {len(value.points)} points"
        else:
            self.state, self.message = state, value
        return True

    def wait(self, timeout: float | None = None) -> bool:
        """Wait for the worker thread to end (tests); True if it has."""
        thread = self._thread
        if thread is not None:
            thread.join(timeout)
            return not thread.is_alive()
        return True

    # ---- worker thread ----
    def _work(self, generation: int, stop: threading.Event, robot: RobotParams, n_points: int) -> None:
        try:
            outcome = (generation, SHOWN, self._compute(robot, n_points, stop.is_set))
        except WorkspaceCancelled:
            outcome = (generation, CANCELLED, "workspace computation cancelled")
        except Exception as exc:  # noqa: BLE001 - reported in the status bar, never lost
            outcome = (generation, FAILED, f"workspace failed: {clip(str(exc), 200)}")
        with self._lock:
            if generation == self._generation:
                self._outcome = outcome
        self._notify()
