"""Trajectories (joint and Cartesian), retiming to limits, the pick task and its task files.
Never imports graphics, viewer, qt or app.
"""
