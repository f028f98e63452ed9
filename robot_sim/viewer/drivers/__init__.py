"""What moves the arm a viewer session shows: one driver at a time (no Qt, no GL).

* :class:`~robot_sim.viewer.drivers.still.StillDriver`: the joints are set by hand (sliders,
  IK, ``display(q)``) and the shown arm follows its desired values at bounded speed;
* :class:`~robot_sim.viewer.drivers.simulated.SimulationDriver`: the arm is simulated and
  a joint-space controller tracks the desired values;
* :class:`~robot_sim.viewer.drivers.task_space.TaskSpaceDriver`: the arm is simulated and
  a task-space controller follows a tool pose (the IK target, the circle);
* :class:`~robot_sim.viewer.drivers.circle.CircleDriver`: the circle demo, over the
  motion driver it interrupts;
* :class:`~robot_sim.viewer.drivers.pick.PickDriver`: playback of a planned pick task.

The session asks its driver (the interface is :class:`~robot_sim.viewer.drivers.base.Driver`)
for everything that depends on what moves the arm, and switching the motion mode or a
demo replaces the driver.  The circle and pick drivers keep the driver they interrupt
(``inner``): the motion mode survives a demo.  The pick driver's module imports the
planner (and numba), so the session imports it only when a task is shown.
"""
from __future__ import annotations

from typing import TYPE_CHECKING

from robot_sim.viewer.drivers.base import Driver
from robot_sim.viewer.drivers.simulated import SimulationDriver
from robot_sim.viewer.drivers.still import StillDriver
from robot_sim.viewer.drivers.task_space import TaskSpaceDriver

if TYPE_CHECKING:
    from robot_sim.viewer.motion import Motion

__all__ = ["Driver", "StillDriver", "SimulationDriver", "TaskSpaceDriver", "motion_driver"]


def motion_driver(motion: Motion) -> Driver:
    """The driver of ``motion``'s mode: still (kinematic), or its simulation under a
    joint-space or a task-space controller."""
    if not motion.physical:
        return StillDriver()
    return TaskSpaceDriver(motion) if motion.task_space else SimulationDriver(motion)
