"""Controllers (joint space) and the physics loop (:class:`~robot_sim.control.simulation.Simulation`).
Never imports graphics, viewer, qt or app.
"""
