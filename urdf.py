"""URDF in and out for DH robots.

* :func:`to_urdf` (robot → URDF text; see :mod:`_urdf_out` for the links, joints,
  limits, inertials and cylinders it writes);
* :func:`load_urdf` (URDF file → :class:`~robot_defs.RobotParams` by the common-normal
  construction; see :mod:`_urdf_in`), also reached through ``robot_defs.load_robot`` for
  paths ending in ``.urdf``.
"""
from __future__ import annotations

from _urdf_in import load_urdf
from _urdf_out import to_urdf

__all__ = ["load_urdf", "to_urdf"]
