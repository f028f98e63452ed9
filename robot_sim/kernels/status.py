"""The status of one arm's integration step, as the compiled stepper
(``robot_sim.dynamics.compiled``, whose kernels return these numbers), the physics loop
and the controllers that integrate their own law (``Controller.integrate``) report it.
No numba here: a controller module can name a status without compiling anything.

* ``OK``: stepped;
* ``BAD_STATE`` / ``BAD_ACCEL``: a stage state / an acceleration was not finite (or M not
  positive definite): the step did not happen;
* ``CROSSED``: stepped from a start on no stop, beyond a limit at the end (the caller
  resolves the stops from this trial step);
* ``AT_STOP``: not stepped: the start on a stop needs what the kernel does not do (an
  impact, a one-point range, a release, an arrival while held);
* ``BAD_EFFORT``: the controller's command was not finite (not stepped);
* ``ON_LIMIT``: stepped as OK, some joint exactly on a limit at the end.
"""
OK, BAD_STATE, BAD_ACCEL, CROSSED, AT_STOP, BAD_EFFORT, ON_LIMIT = 0, 1, 2, 3, 4, 5, 6
