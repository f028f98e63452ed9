"""Pixels of the new look: the light theme, the key light's shadow, multisampling.

Every expected position comes from forward kinematics, ``Camera.project`` and the key
light's direction (``lighting.key_light``)."""
from __future__ import annotations

import numpy as np

from robot_sim import graphics as go

go.require_osmesa_platform()

from render_helpers import DEG, framed, key_points, options_for, posed, project, render  # noqa: E402,F401
from robot_sim.graphics.lighting import key_light  # noqa: E402
from robot_sim.transforms import HomogeneousTransform  # noqa: E402


def test_light_theme_background_is_light(render) -> None:
    kin = posed("ur5")
    options = options_for(kin)
    options.theme = "light"
    image = render(framed(key_points(kin)), go.Scene(kin), options)
    corner = image[:5, :5, :3].astype(float).mean(axis=(0, 1))
    assert corner.min() > 0.85 * 255, f"light theme background {corner}"
    options.theme = "dark"
    dark = render(framed(key_points(kin)), go.Scene(kin), options)
    assert dark[:5, :5, :3].astype(float).mean() < 0.3 * 255


def test_the_shadow_falls_on_the_floor_away_from_the_light(render) -> None:
    """The endeffector's shadow lies where the ray from it away from the key light meets
    the floor: that pixel darkens when shadows are on; the point as far towards the
    light does not."""
    kin = posed("planar3", [0.0, 0.0, 0.0], HomogeneousTransform.from_rt(t=[0.0, 0.0, 0.3]))  # 0.3 m up
    tip = kin.endeff_tf.t()
    key = key_light()
    shadow = tip - key * (tip[2] / key[2])
    towards = tip + key * (tip[2] / key[2]) * np.array([1.0, 1.0, -1.0])  # mirrored towards the light, on the floor
    camera = go.Camera(elevation_deg=70.0)
    camera.fit(np.vstack([key_points(kin), shadow, towards, shadow * (1, 1, 0)]))
    options = options_for(kin)
    lit = render(camera, go.Scene(kin), options)
    options.shadows = False
    unlit = render(camera, go.Scene(kin), options)
    at, away = project(camera, [shadow, towards])
    darker = unlit[..., :3].astype(int).sum(axis=-1) - lit[..., :3].astype(int).sum(axis=-1)
    y, x = int(round(at[1])), int(round(at[0]))
    assert darker[y - 2:y + 3, x - 2:x + 3].max() > 30, f"no shadow at {at.round(1)}"
    y, x = int(round(away[1])), int(round(away[0]))
    assert darker[y - 2:y + 3, x - 2:x + 3].max() <= 3, f"a shadow towards the light at {away.round(1)}"


def test_msaa_gives_intermediate_colours_on_an_edge(render) -> None:
    """The red endeffector sphere against the floor: without multisampling its rim pixels
    are red or floor; with it some are mixtures between the two."""
    kin = posed("planar3", [30 * DEG, 30 * DEG, 30 * DEG])
    camera = framed(key_points(kin))
    options = options_for(kin)
    options.shadows = False

    def mixed(image: np.ndarray) -> int:
        xy = project(camera, kin.endeff_tf.t())[0]
        y, x = int(round(xy[1])), int(round(xy[0]))
        patch = image[max(y - 40, 0):y + 40, max(x - 40, 0):x + 40, :3].astype(int)
        red = patch[..., 0] - np.maximum(patch[..., 1], patch[..., 2])
        return int(np.count_nonzero((red > 25) & (red < 90)))  # partly red: neither sphere nor floor

    options.samples = 0
    hard = mixed(render(camera, go.Scene(kin), options))
    options.samples = 4
    smooth = mixed(render(camera, go.Scene(kin), options))
    assert smooth > hard + 10, f"partly red rim pixels: {smooth} with MSAA, {hard} without"
