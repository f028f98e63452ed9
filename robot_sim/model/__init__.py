"""Robot model: :class:`RobotParams` (DH table, convention, limits, inertials, drives), joint
state, exact conversion between the DH conventions.  Imports nothing of ours but ``transforms``.
"""
