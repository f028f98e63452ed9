"""The browser's camera from a viewer session's orbit camera (robot_sim.graphics.Camera):
eye, target, z up and the vertical field of view.  World frame, metres."""
from __future__ import annotations

import math
from typing import Any


def point_camera(camera: Any, session_camera: Any) -> None:
    """Put a page's viser camera where the session's orbit camera is: eye, target, z up,
    the same vertical field of view."""
    camera.fov = math.radians(session_camera.fov_deg)
    camera.up_direction = (0.0, 0.0, 1.0)
    camera.position = tuple(float(v) for v in session_camera.eye())
    camera.look_at = tuple(float(v) for v in session_camera.target)


def aim_initial_camera(server: Any, session_camera: Any) -> None:
    """The camera a page opens with (and a recording starts from): the session's."""
    initial = server.initial_camera
    initial.up = (0.0, 0.0, 1.0)
    initial.fov = math.radians(session_camera.fov_deg)
    initial.position = tuple(float(v) for v in session_camera.eye())
    initial.look_at = tuple(float(v) for v in session_camera.target)
