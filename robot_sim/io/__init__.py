"""Files: robot files (TOML read with validation, style-preserving write), URDF in and out,
atomic writes.  Builds on :mod:`robot_sim.model` only.
"""
