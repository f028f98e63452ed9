"""--theme and --look: the command line sets the session's theme and look, which the
render path draws (a robot with a box visual shows it in the mesh look, translucent in
``both``, not at all in ``dh``; the light theme's background is light), and the
offscreen --screenshot writes exactly that picture."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from robot_sim.app.prepare import prepare, session_from_config

from cli_helpers import read_png, run
from geometry_helpers import boxed_arm
from render_helpers import H, W, render  # noqa: F401 - fixture


def _session(*args: str):
    config = prepare([*args, "--size", f"{W}x{H}"])
    return session_from_config(config)


def _picture(render, *args: str) -> np.ndarray:  # noqa: F811 - the fixture
    session = _session(*args)
    return render(session.camera, session.scene(), session.options)[..., :3].astype(int)


def _red(image: np.ndarray) -> int:
    return int(np.count_nonzero((image[..., 0] > 120) & (image[..., 0] > 2 * image[..., 1] + 30)))


def test_options_reach_the_session() -> None:
    assert (_session().options.theme, _session().options.look) == ("dark", None)
    options = _session("--theme", "light", "--look", "solid").options
    assert (options.theme, options.look) == ("light", "solid")


def test_screenshot_draws_the_theme_and_look_asked_for(render, tmp_path: Path) -> None:  # noqa: F811
    out = tmp_path / "light_solid.png"
    result = run("--theme", "light", "--look", "solid", "--size", f"{W}x{H}", "--screenshot", str(out))
    assert result.returncode == 0, result.stderr
    written = read_png(out)[..., :3].astype(int)
    assert np.abs(written - _picture(render, "--theme", "light", "--look", "solid")).max() <= 2
    plain, dh_light = _picture(render), _picture(render, "--theme", "light")
    assert plain[0, 0].sum() < 3 * 80 and written[0, 0].sum() > 3 * 230  # the corner shows the background
    assert np.count_nonzero(np.any(np.abs(written - dh_light) > 8, axis=2)) > 100  # solid is not the DH look


def test_looks_of_a_robot_with_visuals(render, tmp_path: Path) -> None:  # noqa: F811
    boxed = str(boxed_arm(tmp_path))
    red = {look: _red(_picture(render, "--robot", boxed, "--look", look)) for look in ("mesh", "both", "dh")}
    assert _red(_picture(render, "--robot", boxed)) == red["mesh"]  # meshes by default
    assert red["mesh"] > 300 and red["mesh"] > red["both"] > red["dh"]  # translucent over the DH segments
