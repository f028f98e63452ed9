"""Kinematic calibration: measurements, identification, identifiability and pose choice.

Imports model, io, transforms, kinematics and collision only (never graphics, viewer, Qt,
web or app).
"""
