"""Where the lights are and what the shadow map sees (pure NumPy, no GL).

The key light is fixed in the world, high and to the left of the default view, so a
shadow changes only when what casts it moves (the shadow map is kept while the camera
orbits); the fill light follows the camera from its right, lower and unshadowed, so the
faces turned to the viewer are never black.  World frame, z up, metres.
"""
from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

KEY_AZIMUTH_DEG = 100.0         # key light about world z from +x (the default camera is at 45)
KEY_ELEVATION_DEG = 60.0        # key light above the floor
FILL_AZIMUTH_OFFSET_DEG = -20.0  # fill light's azimuth = the camera's + this (to its right)
FILL_ELEVATION_DEG = 20.0


def direction(azimuth_deg: float, elevation_deg: float) -> NDArray[np.float64]:
    """Unit world vector (3,) pointing towards a light at ``azimuth_deg`` about z from +x
    and ``elevation_deg`` above the xy plane."""
    az, el = math.radians(azimuth_deg), math.radians(elevation_deg)
    return np.array([math.cos(el) * math.cos(az), math.cos(el) * math.sin(az), math.sin(el)])


def key_light() -> NDArray[np.float64]:
    """Unit world vector (3,) towards the key light."""
    return direction(KEY_AZIMUTH_DEG, KEY_ELEVATION_DEG)


def fill_light(camera_azimuth_deg: float) -> NDArray[np.float64]:
    """Unit vector (3,) towards the fill light for a camera at ``camera_azimuth_deg``."""
    return direction(camera_azimuth_deg + FILL_AZIMUTH_OFFSET_DEG, FILL_ELEVATION_DEG)


def shadow_sphere(casters: ArrayLike, towards_light: ArrayLike) -> tuple[NDArray[np.float64], float]:
    """Centre (3,) and radius of a sphere enclosing world points ``casters`` (N, 3) and
    their shadows on the floor z = 0 (each point moved along ``-towards_light`` down to
    the floor): what the shadow map must see."""
    pts = np.asarray(casters, dtype=float).reshape(-1, 3)
    back = np.asarray(towards_light, dtype=float)
    above = np.maximum(pts[:, 2], 0.0) / max(back[2], 1e-3)
    pts = np.vstack([pts, pts - above[:, None] * back])
    centre = 0.5 * (pts.min(axis=0) + pts.max(axis=0))
    return centre, float(np.max(np.linalg.norm(pts - centre, axis=1)))


def light_matrix(towards_light: ArrayLike, centre: ArrayLike, radius: float) -> NDArray[np.float64]:
    """World -> light clip transform (4, 4) of a directional light shining along
    ``-towards_light`` onto the sphere of ``radius`` metres about world ``centre``: an
    orthographic box just enclosing that sphere, depth 0..1 over its diameter (clip z
    from -1 at the side facing the light to 1 at the far side)."""
    back = np.asarray(towards_light, dtype=float)
    back = back / np.linalg.norm(back)
    helper = np.array([0.0, 0.0, 1.0]) if abs(back[2]) < 0.99 else np.array([1.0, 0.0, 0.0])
    right = np.cross(helper, back)
    right /= np.linalg.norm(right)
    up = np.cross(back, right)
    r = max(float(radius), 1e-6)
    view = np.eye(4)
    view[0, :3], view[1, :3], view[2, :3] = right, up, back
    eye = np.asarray(centre, dtype=float) + 2.0 * r * back
    view[:3, 3] = -view[:3, :3] @ eye
    proj = np.diag([1.0 / r, 1.0 / r, -1.0 / r, 1.0])  # distance from the eye r..3r -> clip z -1..1
    proj[2, 3] = -2.0
    return proj @ view


def shadow_footprint(matrix: ArrayLike, towards_light: ArrayLike, casters: ArrayLike,
                     margin: float) -> NDArray[np.float64]:
    """Corners (4, 3) on the floor z = 0 of the only region where ``casters`` (N, 3
    world points whose hull holds every caster) can cast a shadow from the directional
    light of world -> light clip ``matrix`` (:func:`light_matrix`) towards
    ``towards_light``: the box of the casters in the light's x and y, grown by
    ``margin`` (light clip units) on each side, carried down to the floor along the
    light.  A floor point outside it sees no caster in the shadow map (its lookups fall
    where the map is clear), whatever the casters' heights."""
    m = np.asarray(matrix, dtype=float)
    pts = np.asarray(casters, dtype=float).reshape(-1, 3)
    xy = (np.c_[pts, np.ones(len(pts))] @ m.T)[:, :2]
    (x0, y0), (x1, y1) = xy.min(axis=0) - margin, xy.max(axis=0) + margin
    corners = np.array([[x0, y0, 0.0, 1.0], [x1, y0, 0.0, 1.0], [x1, y1, 0.0, 1.0], [x0, y1, 0.0, 1.0]])
    world = (corners @ np.linalg.inv(m).T)[:, :3]
    back = np.asarray(towards_light, dtype=float)
    return world - (world[:, 2] / back[2])[:, None] * back
