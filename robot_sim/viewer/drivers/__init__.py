"""What moves the arm a viewer session shows: one driver at a time (no Qt, no GL).

* :class:`~robot_sim.viewer.drivers.still.StillDriver`: the joints are set by hand (sliders,
  IK, ``display(q)``) and the shown arm follows its desired values at bounded speed;
* :class:`~robot_sim.viewer.drivers.simulated.SimulationDriver`: the arm is simulated and
  a controller tracks the desired values (a physical motion mode);
* :class:`~robot_sim.viewer.drivers.circle.CircleDriver`: the circle demo by differential
  IK, over the still or the simulated driver it interrupts;
* :class:`~robot_sim.viewer.drivers.pick.PickDriver`: playback of a planned pick task.

The circle and pick drivers keep the driver they interrupt (``inner``): the motion mode
survives a demo.  The pick driver's module imports the planner (and numba), so the session
imports it only when a task is shown.
"""
from __future__ import annotations

from robot_sim.viewer.drivers.base import Driver
from robot_sim.viewer.drivers.still import StillDriver

__all__ = ["Driver", "StillDriver"]
