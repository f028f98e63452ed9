"""The command line parses, then prepares, then outputs: what each step imports (a still
screenshot loads neither numba nor Qt; a bad --robot answers before any GL, Qt or numba
import), that parsing creates nothing, and --trail drawn into --screenshot and --record
pictures where the tool went."""
from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from cli_helpers import ROOT, assert_one_line_error, read_png, run
from robot_sim.app import prepare
from robot_sim.graphics import defs as gd
from robot_sim.viewer import settings as vs

TRAIL_RGB = np.round(255 * np.asarray(gd.TRAIL_COLOR[:3])).astype(int)
W, H = 320, 240


def modules_after(*args: str) -> tuple[int, list[str], str]:
    """Exit status of ``main(args)`` in a fresh interpreter, which of numba, PyQt5 and
    OpenGL it imported, and its stderr."""
    code = ("import json, sys\nfrom robot_sim.app.main import main\n"
            f"status = main({list(args)!r})\n"
            "print(json.dumps([status, [m for m in ('numba', 'PyQt5', 'OpenGL') if m in sys.modules]]))")
    env = dict(os.environ, PYTHONPATH=str(ROOT), PYOPENGL_PLATFORM="osmesa")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=180, cwd=ROOT, env=env)
    status, modules = json.loads(done.stdout.strip().splitlines()[-1])
    return status, modules, done.stderr


def test_a_still_screenshot_imports_neither_numba_nor_qt(tmp_path: Path) -> None:
    out = tmp_path / "still.png"
    status, modules, _ = modules_after("--robot", "ur5", "--q", "10,-60,90,-30,45,0", "--frames", "all",
                                       "--screenshot", str(out), "--size", "64x48")
    assert status == 0 and out.exists()
    assert modules == ["OpenGL"]  # drawn through OSMesa, without the planner or the window
    # the check can fail: the pick demo plans, which compiles with numba
    status, modules, _ = modules_after("--robot", "ur5", "--demo", "pick", "--screenshot",
                                       str(tmp_path / "pick.png"), "--size", "64x48")
    assert status == 0 and "numba" in modules and "PyQt5" not in modules


def test_a_bad_robot_answers_before_any_gl_qt_or_numba_import() -> None:
    status, modules, stderr = modules_after("--robot", "nonexistent", "--demo", "pick", "--motion", "ct")
    assert status == 2 and modules == []
    assert stderr.startswith("robot-sim: error: unknown robot 'nonexistent'; available robots: ")
    assert len(stderr.splitlines()) == 1


def test_parsing_creates_nothing_and_checks_the_record_folder_first(tmp_path: Path) -> None:
    folder = tmp_path / "frames"
    assert_one_line_error(run("--robot", "nonexistent", "--record", str(folder)), "unknown robot 'nonexistent'")
    assert not folder.exists()  # the output step creates it, and only then
    missing = tmp_path / "no" / "frames"
    status, modules, stderr = modules_after("--demo", "pick", "--record", str(missing))
    assert status == 2 and "numba" not in modules  # refused before the task is planned
    assert stderr == (f"robot-sim: error: --record: cannot write frames to '{missing}': "
                      "its parent is not a writable directory\n")


def _trail_hits(image: np.ndarray, pixels: np.ndarray) -> list[bool]:
    """Per projected trail point inside the picture: a trail-coloured pixel within 2 px."""
    height, width = image.shape[:2]
    hits = []
    for x, y in np.round(pixels).astype(int):
        if 2 <= x < width - 2 and 2 <= y < height - 2:
            window = image[y - 2:y + 3, x - 2:x + 3, :3].astype(int)
            hits.append(bool(np.any(np.all(np.abs(window - TRAIL_RGB) <= 3, axis=-1))))
    return hits


def test_trail_in_a_screenshot_of_a_simulated_fall(tmp_path: Path) -> None:
    args = ["--robot", "ur5", "--motion", "passive", "--duration", "0.6", "--size", f"{W}x{H}", "--frames", "none"]
    with_trail, without = tmp_path / "trail.png", tmp_path / "plain.png"
    assert run(*args, "--trail", "--screenshot", str(with_trail)).returncode == 0
    assert run(*args, "--screenshot", str(without)).returncode == 0
    session = prepare.session_from_config(prepare.prepare([*args, "--trail"]))  # the same fall, in process
    points = session.trail.points()
    assert len(points) > 20
    assert points[-1][2] < points[0][2] - 0.1  # the tool fell to the floor
    assert np.linalg.norm(points[-1] - session.kin.endeff_tf.t()) < vs.TRAIL_MIN_STEP_M  # closer: not stored
    pixels = session.camera.project(points, W, H)
    hits = _trail_hits(read_png(with_trail), pixels)
    assert sum(hits) >= 8  # the wrist hides the lower part of the path
    assert not any(_trail_hits(read_png(without), pixels))


def test_trail_in_a_recording_of_the_circle_demo(tmp_path: Path) -> None:
    args = ["--robot", "ur5", "--demo", "circle", "--size", f"{W}x{H}", "--frames", "none", "--trail",
            "--fps", "10", "--duration", "4"]
    folder = tmp_path / "frames"
    assert run(*args, "--record", str(folder)).returncode == 0
    session = prepare.session_from_config(prepare.prepare([*args, "--record", str(folder)]))
    for _ in range(40):  # what --record did between its 41 frames
        session.step(0.1)
    points = session.trail.points()
    centre = session.demo.center
    radii = np.linalg.norm((points - centre)[:, :2], axis=1)
    assert np.all(np.abs(radii[10:] - 0.1) < 0.01)  # on the demo's 10 cm circle once on it
    hits = _trail_hits(read_png(folder / "frame_00040.png"), session.camera.project(points, W, H))
    assert len(hits) > 20 and np.mean(hits) > 0.6
    assert not any(_trail_hits(read_png(folder / "frame_00000.png"), session.camera.project(points[5:], W, H)))


@pytest.mark.parametrize("args", [["--trail", "--print-dh"]])
def test_trail_is_an_option_of_the_parser(args: list[str]) -> None:
    assert run(*args).returncode == 0
