"""Offscreen rendering in tests: the renderer fixture, posed robots, cameras and pixel masks
(shared by the rendering tests)."""
from __future__ import annotations

import math
import weakref
from typing import Any, Iterator, Sequence

import numpy as np
import pytest

from robot_sim import graphics as go

go.require_osmesa_platform()

from robot_sim.graphics import defs as gd  # noqa: E402
from robot_sim.kinematics import Kinematics  # noqa: E402
from robot_sim.model.params import JTYPE_PRISMATIC, JTYPE_REVOLUTE, RobotParams
from robot_sim.io.robot_file import load_robot  # noqa: E402
from robot_sim.model.state import RobotState  # noqa: E402
from robot_sim.transforms import HomogeneousTransform  # noqa: E402

W, H = 320, 240
DEG = math.pi / 180.0
R_, P_ = JTYPE_REVOLUTE, JTYPE_PRISMATIC
BACKGROUND_PX = np.round(255.0 * np.asarray(go.THEMES["dark"].background[:3])).astype(int)
MAGENTA = (1.0, 0.0, 1.0, 1.0)


# ------------------------------------------------------------------- renderer


class Frames:
    """The module's OSMesa renderer; every frame is followed by a glGetError check."""

    def __init__(self) -> None:
        go.require_osmesa_platform()
        from OpenGL import GL

        self.gl = GL
        self.renderer = go.OffscreenRenderer(W, H)

    def __call__(self, camera: go.Camera, scene: go.Scene, options: go.GraphicsOptions) -> np.ndarray:
        image = self.renderer.render(camera, scene, options)
        error = self.gl.glGetError()
        assert error == self.gl.GL_NO_ERROR, f"glGetError() = {error:#06x} after a frame"
        return image

    def pair(self, camera: go.Camera, kin: Kinematics, options: go.GraphicsOptions) -> tuple[np.ndarray, np.ndarray]:
        """The robot alone, and the same view without the robot."""
        return self(camera, go.Scene(kin), options), self(camera, go.Scene(sunk(kin)), options)


@pytest.fixture(scope="module")
def render() -> Iterator[Frames]:
    frames = Frames()
    yield frames
    frames.renderer.close()


# -------------------------------------------------------------------- robots


def posed(robot: RobotParams | str, q: Sequence[float] | None = None, base: HomogeneousTransform | None = None) -> Kinematics:
    """Kinematics of ``robot`` at joint vector ``q`` (home when None)."""
    rob = load_robot(robot) if isinstance(robot, str) else robot
    state = RobotState(rob)
    if q is not None:
        state.set_q(q)
    kin = Kinematics(rob)
    kin.update(state.joint_state, base)
    _POSES[kin] = state.q()
    return kin


_POSES: weakref.WeakKeyDictionary[Kinematics, np.ndarray] = weakref.WeakKeyDictionary()  # q of posed()


def sunk(kin: Kinematics) -> Kinematics:
    """The same robot and pose, 1 km below the ground: beyond the far plane, ground unchanged."""
    return posed(kin.robot, _POSES[kin], HomogeneousTransform.from_rt(t=[0.0, 0.0, -1000.0]))


def key_points(kin: Kinematics) -> np.ndarray:
    """Frame origins and the endeffector (N, 3), world."""
    return np.vstack([[tf.t() for tf in kin.h_tf], kin.endeff_tf.t()])


def framed(points: np.ndarray, **camera_args: float) -> go.Camera:
    """A camera framing ``points`` (frame origins, mostly) with room for the parts drawn
    around them: ``fit`` fills 70 % of the picture with the points alone."""
    camera = go.Camera(**camera_args)
    camera.fit(points)
    camera.zoom(1.3)
    return camera


def options_for(kin: Kinematics, base_frame: bool = False) -> go.GraphicsOptions:
    options = go.GraphicsOptions(kin.robot.n_dofs + 1)
    if not base_frame:
        assert options.toggle_frame(0)
    return options


# -------------------------------------------------------------------- pixels


def project(camera: go.Camera, points: Any) -> np.ndarray:
    return camera.project(np.asarray(points, dtype=float).reshape(-1, 3), W, H)


def color_mask(image: np.ndarray, rgba: Sequence[float], margin: int = 30, ratio: float = 1.6,
               min_high: int = 60) -> np.ndarray:
    """Pixels (H, W) whose dominant channels are those of ``rgba``: each channel at least
    60 % of the colour's peak is >= ``min_high`` and exceeds ``ratio`` times each channel
    at most 35 % of the peak by ``margin`` (red (0.9, 0.08, 0.08): R high, G and B low).
    Lighting scales the channels, so a shaded red (80, 9, 9) still counts."""
    ref = np.asarray(rgba[:3], dtype=float)
    high, low = np.flatnonzero(ref >= 0.6 * ref.max()), np.flatnonzero(ref <= 0.35 * ref.max())
    assert len(high) and len(low), f"{rgba} has no dominant hue"
    px = image[..., :3].astype(float)
    mask = np.ones(image.shape[:2], dtype=bool)
    for h in high:
        mask &= px[..., h] >= min_high
        for lo in low:
            mask &= px[..., h] >= ratio * px[..., lo] + margin
    return mask


def robot_mask(image: np.ndarray, empty: np.ndarray, tol: int = 12) -> np.ndarray:
    """Pixels (H, W) that differ from the robot-less render ``empty``."""
    return np.abs(image[..., :3].astype(int) - empty[..., :3].astype(int)).max(axis=-1) > tol


def window(mask: np.ndarray, xy: Sequence[float], radius: int = 2) -> np.ndarray:
    """The part of ``mask`` within ``radius`` pixels (square) of pixel ``xy``."""
    assert np.all(np.isfinite(xy)), f"point projects to {xy}"
    x, y = int(round(xy[0])), int(round(xy[1]))
    assert 0 <= x < W and 0 <= y < H, f"pixel {x, y} is outside the {W}x{H} image"
    return mask[max(y - radius, 0): y + radius + 1, max(x - radius, 0): x + radius + 1]


def pixel(image: np.ndarray, xy: Sequence[float]) -> np.ndarray:
    return image[int(round(xy[1])), int(round(xy[0])), :3].astype(int)


def along(a: np.ndarray, b: np.ndarray, fractions: Sequence[float]) -> np.ndarray:
    """World points (k, 3) at ``fractions`` of the way from ``a`` to ``b``."""
    f = np.asarray(fractions, dtype=float)[:, None]
    return (1.0 - f) * np.asarray(a, dtype=float) + f * np.asarray(b, dtype=float)


def assert_drawn_along(image: np.ndarray, before: np.ndarray, rgba: Sequence[float], camera: go.Camera,
                       a: np.ndarray, b: np.ndarray, what: str, fractions: Sequence[float] = (0.5, 0.6, 0.7, 0.8)) -> None:
    """Pixels of ``rgba``'s hue near the projections of points from ``a`` to ``b``, that
    were not of that hue in ``before``."""
    new = color_mask(image, rgba) & ~color_mask(before, rgba)
    for f, xy in zip(fractions, project(camera, along(a, b, fractions))):
        assert window(new, xy).any(), f"{what}: no new {rgba} pixel near {xy.round(1)} ({f:.0%} of the way)"


def assert_sane(image: np.ndarray, empty: np.ndarray | None = None, min_robot_px: int = 100) -> None:
    """Not a blank or background-only frame; with ``empty``, the robot drew something."""
    background = np.all(np.abs(image[..., :3].astype(int) - BACKGROUND_PX) <= 2, axis=-1)
    assert background.mean() < 0.97, f"{background.mean():.1%} of the frame is background"
    assert image[..., :3].std() > 5.0, "the frame is flat"
    if empty is not None:
        count = int(robot_mask(image, empty).sum())
        assert count >= min_robot_px, f"only {count} robot pixels"


# ---------------------------------------------------- 1. endeffector position

POSES = [
    ("planar3", None),
    ("planar3", [0.0, 0.0, 0.0]),
    ("planar3", [90 * DEG, -90 * DEG, 45 * DEG]),
    ("planar3", [-120 * DEG, 60 * DEG, -30 * DEG]),
    ("spherical", None),
    ("spherical", [0.0, math.pi, 0.5]),  # the prismatic link points straight down
    ("spherical", [90 * DEG, -60 * DEG, 0.9]),
    ("spherical", [-45 * DEG, 120 * DEG, 0.2]),
    ("anthropomorphic", None),
    ("anthropomorphic", [0.0, 0.0, 0.0]),
    ("anthropomorphic", [90 * DEG, 90 * DEG, 0.0]),  # straight up
    ("anthropomorphic", [-135 * DEG, 30 * DEG, 120 * DEG]),
]
