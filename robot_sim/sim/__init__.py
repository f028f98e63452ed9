"""The physics loop, in one place: the :class:`~robot_sim.sim.simulation.Simulation` core,
:class:`~robot_sim.sim.batch.BatchSimulation` and sweeps over it, the stepper (RK4 or
semi-implicit Euler, compiled), the one stop resolver (joint limits as stops), and penalty
contact from the collision checker.  Time enters the program here.

May import control (the laws), collision, dynamics, kinematics, planning, model and the
kernels layer; never graphics, viewer, qt or app, and control never imports this package.
"""
