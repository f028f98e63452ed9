"""Analytic inverse kinematics of DH arms: the closed-form family read from the joint
axes (:func:`ik_family`) and every solution of a pose or a batch of poses
(:func:`ik_solutions`).  Imports only ``model``, ``transforms`` and ``kernels`` (whose one cache rule covers the
compiled modules here: each imports ``robot_sim.kernels.jit``)."""
