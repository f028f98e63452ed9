"""Control laws: joint-space controllers (passive, PD, PD + gravity, computed torque) and
task-space ones (operational space, impedance, resolved rate), their gains and the
desired values they follow.  The physics loop that integrates them is robot_sim/sim/.
Never imports sim, graphics, viewer, qt or app.
"""
