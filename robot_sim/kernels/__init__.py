"""The layer below kinematics: the compiled model of a robot (one table per robot, built
once, weakly cached), numba's settings and cache rule, and the compiled building blocks
every algorithm shares (sin/cos, cross product, Cholesky solve, RK4 combine, the chain's
frames and Jacobian).  Imports nothing of ours but ``model`` and ``transforms``."""
