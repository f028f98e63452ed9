"""workspace_job.WorkspaceJob (Qt-free): one cancellable computation with a visible state."""
from __future__ import annotations

import threading
import time

import numpy as np
import pytest

from kin_helpers import robot as shipped
from robot_sim.kinematics import WorkspaceCancelled, workspace_points
from robot_sim.model.params import JTYPE_PRISMATIC, RobotParams
from robot_sim.viewer.workspace_job import compute_workspace
from robot_sim.viewer.workspace_job import CANCELLED, COMPUTING, FAILED, HIDDEN, IDLE, SHOWN, WorkspaceJob


class Notifications:
    """Counts notify() calls (made from the worker thread)."""

    def __init__(self) -> None:
        self.count = 0
        self.threads: list[str] = []

    def __call__(self) -> None:
        self.count += 1
        self.threads.append(threading.current_thread().name)


def finished(job: WorkspaceJob) -> WorkspaceJob:
    assert job.wait(60)
    job.collect()
    return job


def test_computes_then_shows_and_hides() -> None:
    notes = Notifications()
    job = WorkspaceJob(compute_workspace, notes)
    assert job.state == IDLE
    job.toggle(shipped("puma560"), 5000)
    assert job.state == COMPUTING and job.message == "computing workspace (5000 points) ..."
    finished(job)
    assert job.state == SHOWN and len(job.cloud.points) == 5000
    assert job.message == "workspace: 5000 points"
    assert notes.count == 1 and notes.threads == ["workspace"]
    assert job.toggle(None, 0) == HIDDEN
    assert job.toggle(None, 0) == SHOWN and job.cloud is not None


def test_second_press_while_computing_cancels_and_the_worker_stops() -> None:
    started, release = threading.Event(), threading.Event()
    seen_cancel = []

    def slow(robot, n, cancelled):
        started.set()
        while not cancelled():
            release.wait(0.01)
        seen_cancel.append(True)
        raise WorkspaceCancelled("stopped")

    job = WorkspaceJob(slow, Notifications())
    job.toggle("robot", 10)
    assert started.wait(10)
    assert job.toggle("robot", 10) == CANCELLED
    assert job.message == "workspace computation cancelled"
    assert job.wait(10) and seen_cancel == [True]
    assert not job.collect() and job.state == CANCELLED and job.cloud is None
    assert job.toggle("robot", 10) == COMPUTING  # E again: start afresh
    job.cancel()


def test_failure_is_a_state_with_the_reason() -> None:
    slider = RobotParams.from_arrays("slider", [0.0], [0.0], [0.0], [0.0], [JTYPE_PRISMATIC])
    job = WorkspaceJob(compute_workspace, Notifications())
    job.toggle(slider, 100)
    finished(job)
    assert job.state == FAILED
    assert job.message == "workspace failed: slider: prismatic joint 1 has no limits; cannot sample its range"
    assert job.toggle(slider, 100) == COMPUTING  # E retries after a failure
    finished(job)
    assert job.state == FAILED


def test_a_new_start_drops_the_old_result_and_stops_its_worker() -> None:
    gates = {"a": threading.Event(), "b": threading.Event()}
    stopped = []

    def compute(robot, n, cancelled):
        while not cancelled() and not gates[robot].is_set():
            time.sleep(0.005)
        if cancelled():
            stopped.append(robot)
            raise WorkspaceCancelled(robot)
        return type("Cloud", (), {"points": np.zeros((n, 3))})()

    job = WorkspaceJob(compute, Notifications())
    job.start("a", 3)
    first = job._thread
    job.start("b", 4)  # switching robot: the first computation is cancelled
    first.join(10)
    assert not first.is_alive() and stopped == ["a"]
    gates["b"].set()
    finished(job)
    assert job.state == SHOWN and len(job.cloud.points) == 4


def test_reset_forgets_the_cloud() -> None:
    job = WorkspaceJob(compute_workspace, Notifications())
    job.start(shipped("planar3"), 100)
    finished(job)
    job.reset()
    assert (job.state, job.message, job.cloud) == (IDLE, "", None)


def test_workspace_points_stops_when_cancelled() -> None:
    calls = []

    def cancelled() -> bool:
        calls.append(1)
        return len(calls) > 1

    with pytest.raises(WorkspaceCancelled, match=r"^workspace of PUMA 560 cancelled after 65536 of 200000 samples$"):
        workspace_points(shipped("puma560"), 200_000, seed=0, cancelled=cancelled)
