"""The viewer's orbit camera: view and projection matrices, framing, projecting world
points to pixels (pure NumPy, no GL).  World frame z up, metres."""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robot_sim.graphics import defs as gd

_Z_AXIS = np.array([0.0, 0.0, 1.0])


@dataclass
class Camera:
    """Orbit camera looking at ``target`` from ``distance`` metres, world z up.

    The eye sits at ``target + distance * (cos(el) cos(az), cos(el) sin(az), sin(el))``
    with azimuth ``az`` measured about world z from +x and elevation ``el`` above the
    xy plane.  ``fov_deg`` is the vertical field of view; with ``orthographic`` the
    projection is parallel, at the scale the perspective one has in the plane through
    the target (so toggling keeps the target's surroundings the same size).  :meth:`reset` returns to the
    values the camera was constructed with.
    """

    distance: float = gd.CAMERA_DISTANCE
    azimuth_deg: float = gd.CAMERA_AZIMUTH_DEG
    elevation_deg: float = gd.CAMERA_ELEVATION_DEG
    target: NDArray[np.float64] = field(default_factory=lambda: np.zeros(3))
    fov_deg: float = gd.CAMERA_FOV_DEG
    orthographic: bool = False
    _home: tuple[float, float, float, NDArray[np.float64], float] = field(
        init=False, repr=False, compare=False
    )

    def __post_init__(self) -> None:
        self.target = np.array(self.target, dtype=float).reshape(3)
        self.distance = float(np.clip(self.distance, gd.CAMERA_MIN_DISTANCE, gd.CAMERA_MAX_DISTANCE))
        self.elevation_deg = self._clamp_elevation(self.elevation_deg)
        self._home = (self.distance, self.azimuth_deg, self.elevation_deg, self.target.copy(), self.fov_deg)

    @staticmethod
    def _clamp_elevation(elevation_deg: float) -> float:
        limit = gd.CAMERA_MAX_ELEVATION_DEG
        return float(np.clip(elevation_deg, -limit, limit))

    def reset(self) -> None:
        """Return to the distance, angles, target and field of view given at construction."""
        distance, azimuth, elevation, target, fov = self._home
        self.distance, self.azimuth_deg, self.elevation_deg, self.fov_deg = distance, azimuth, elevation, fov
        self.target = target.copy()

    def orbit(self, d_az_deg: float, d_el_deg: float) -> None:
        """Turn the eye about the target: azimuth wraps to [-180, 180), elevation is
        clamped to ±``CAMERA_MAX_ELEVATION_DEG`` (short of the poles)."""
        self.azimuth_deg = (self.azimuth_deg + d_az_deg + 180.0) % 360.0 - 180.0
        self.elevation_deg = self._clamp_elevation(self.elevation_deg + d_el_deg)

    def set_view(self, azimuth_deg: float, elevation_deg: float) -> None:
        """Look at the target from the given direction (degrees; elevation clamped like
        :meth:`orbit`), keeping target and distance: the view presets."""
        self.azimuth_deg = (float(azimuth_deg) + 180.0) % 360.0 - 180.0
        self.elevation_deg = self._clamp_elevation(elevation_deg)

    def zoom(self, factor: float) -> None:
        """Multiply the distance by ``factor`` (< 1 moves closer, > 1 farther), clamped to
        [``CAMERA_MIN_DISTANCE``, ``CAMERA_MAX_DISTANCE``] metres.  Non-positive or
        non-finite factors are ignored."""
        if factor > 0.0 and math.isfinite(factor):
            self.distance = float(
                np.clip(self.distance * factor, gd.CAMERA_MIN_DISTANCE, gd.CAMERA_MAX_DISTANCE)
            )

    def eye(self) -> NDArray[np.float64]:
        """Eye position (3,) in the world, metres."""
        az, el = np.radians(self.azimuth_deg), np.radians(self.elevation_deg)
        direction = np.array([np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el)])
        return self.target + self.distance * direction

    def view_plane_axes(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """World unit vectors (3,) pointing right and up on the screen."""
        forward = self.target - self.eye()
        forward /= np.linalg.norm(forward)
        right = np.cross(forward, _Z_AXIS)
        right /= np.linalg.norm(right)
        return right, np.cross(right, forward)

    def world_per_pixel(self, height: int) -> float:
        """Metres per pixel in the plane through the target facing the camera, for a
        viewport ``height`` pixels tall."""
        return 2.0 * self.distance * math.tan(math.radians(self.fov_deg) / 2.0) / max(int(height), 1)

    def pan(self, dx_px: float, dy_px: float, viewport_height: int) -> None:
        """Move the target in the view plane so the scene follows a mouse drag of
        (``dx_px`` right, ``dy_px`` down) pixels in a viewport ``viewport_height`` tall."""
        right, up = self.view_plane_axes()
        scale = self.world_per_pixel(viewport_height)
        self.target = self.target + scale * (-dx_px * right + dy_px * up)

    def fit(self, points: ArrayLike, aspect: float = 1.0) -> None:
        """Aim at and step back from ``points`` (N, 3) (world, metres), keeping the view
        direction, so that they fill ``CAMERA_FIT_FILL`` of a viewport ``aspect`` = width /
        height: their projection's wider side (relative to the viewport's) spans that
        fraction of it, centred.  Non-finite rows are ignored; with no finite point
        nothing changes."""
        pts = np.asarray(points, dtype=float).reshape(-1, 3)
        pts = pts[np.all(np.isfinite(pts), axis=1)]
        if len(pts) == 0:
            return
        tan_y = math.tan(math.radians(self.fov_deg) / 2.0)
        limit = gd.CAMERA_FIT_FILL * np.array([tan_y * max(aspect, 1e-3), tan_y])  # |x|, |y| / depth allowed
        right, up = self.view_plane_axes()
        back = np.cross(right, up)
        target = 0.5 * (pts.min(axis=0) + pts.max(axis=0))
        for step in range(gd.CAMERA_FIT_STEPS):  # the distance for the extent, then centre the projection
            rel = pts - target
            across = np.stack([rel @ right, rel @ up], axis=1)  # metres in the view plane
            toward = np.zeros(len(pts)) if self.orthographic else rel @ back  # metres towards the eye
            distance = max(float(np.max(toward[:, None] + np.abs(across) / limit)),
                           gd.CAMERA_FIT_MIN_RADIUS / limit[1])
            if step == gd.CAMERA_FIT_STEPS - 1:
                break
            ndc = across / (distance - toward)[:, None] / limit  # -1..1 spans the wanted fraction
            middle = 0.5 * (ndc.min(axis=0) + ndc.max(axis=0))
            target = target + (middle * limit * distance) @ np.stack([right, up])
        self.target = target
        self.distance = float(np.clip(distance, gd.CAMERA_MIN_DISTANCE, gd.CAMERA_MAX_DISTANCE))

    def pixel_size(self, depth: float, height: int) -> float:
        """Metres a pixel spans at ``depth`` metres in front of the eye (along the view
        axis; at least the near plane's) in a picture ``height`` pixels high; the same at
        every depth when orthographic."""
        span = self.distance if self.orthographic else max(depth, self.distance * gd.CAMERA_NEAR_FRAC)
        return 2.0 * span * math.tan(math.radians(self.fov_deg) / 2.0) / max(int(height), 1)

    def view_matrix(self) -> NDArray[np.float64]:
        """World -> eye transform (4, 4) (OpenGL eye space: x right, y up, looking down -z)."""
        eye = self.eye()
        right, up = self.view_plane_axes()
        back = np.cross(right, up)
        view = np.eye(4)
        view[0, :3], view[1, :3], view[2, :3] = right, up, back
        view[:3, 3] = -view[:3, :3] @ eye
        return view

    def projection_matrix(self, aspect: float) -> NDArray[np.float64]:
        """Projection (4, 4) eye -> clip for ``aspect`` = width / height.

        Perspective: near and far planes follow the distance (``CAMERA_NEAR_FRAC``,
        ``CAMERA_FAR_FRAC``, ``CAMERA_FAR_MARGIN``) so depth precision stays good at any
        zoom.  Orthographic: a box ``distance * tan(fov / 2)`` high either side of the
        view axis, reaching as far behind the eye as in front (nothing is cut off when
        zoomed in; depth is linear)."""
        near = self.distance * gd.CAMERA_NEAR_FRAC
        far = self.distance * gd.CAMERA_FAR_FRAC + gd.CAMERA_FAR_MARGIN
        f = 1.0 / math.tan(math.radians(self.fov_deg) / 2.0)
        proj = np.zeros((4, 4))
        if self.orthographic:
            scale = f / self.distance
            proj[0, 0] = scale / max(aspect, 1e-9)
            proj[1, 1] = scale
            proj[2, 2] = -1.0 / far
            proj[3, 3] = 1.0
            return proj
        proj[0, 0] = f / max(aspect, 1e-9)
        proj[1, 1] = f
        proj[2, 2] = (far + near) / (near - far)
        proj[2, 3] = 2.0 * far * near / (near - far)
        proj[3, 2] = -1.0
        return proj

    def project(self, points: ArrayLike, width: int, height: int) -> NDArray[np.float64]:
        """Pixel coordinates (N, 2) of world ``points`` (N, 3) in a ``width`` x ``height`` image.

        x grows to the right, y downwards from the top row; integer values are pixel
        centres, so ``image[round(y), round(x)]`` is the pixel a point lands on.  Uses the
        same matrices as the render path (``render.View``).  Points behind the eye give NaN.
        """
        pts = np.asarray(points, dtype=float).reshape(-1, 3)
        clip = np.c_[pts, np.ones(len(pts))] @ (self.projection_matrix(width / height) @ self.view_matrix()).T
        w = clip[:, 3]
        with np.errstate(divide="ignore", invalid="ignore"):
            ndc = clip[:, :2] / w[:, None]
        pixels = np.empty((len(pts), 2))
        pixels[:, 0] = (ndc[:, 0] + 1.0) * 0.5 * width - 0.5
        pixels[:, 1] = (1.0 - ndc[:, 1]) * 0.5 * height - 0.5
        pixels[w <= 0.0] = np.nan
        return pixels

