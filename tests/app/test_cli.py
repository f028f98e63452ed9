"""Command line of robot-sim: bad input gives one stderr line and exit status 2;
--screenshot renders offscreen (OSMesa, no display, no Qt); --list-robots.

``run`` calls the program's ``main`` in this process; the tests that need a real process
(an exit status seen from outside, a clean interpreter, a closed pipe) start one."""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from robot_sim.model.params import RobotDefinitionError
from robot_sim.io.robot_file import available_robots, load_robot

from cli_helpers import (  # noqa: F401 - fixtures and helpers
    ROOT,
    SIMULATOR,
    run,
    run_process,
    read_png,
    assert_one_line_error,
)


@pytest.mark.parametrize(
    ("args", "fragments"),
    [
        (["--robot", "nosuch"], ["unknown robot 'nosuch'", "available robots:", "anthropomorphic", "puma560"]),
        (["--q", "10,20"], ["--q:", "has 3 joints, got 2 values"]),
        (["--q", "10,abc,30"], ["--q: value 2 'abc' is not a number"]),
        (["--q", "10,nan,30"], ["--q: value 2 'nan' is not a finite number"]),
        (["--q", "0,0,500"], ["--q: joint 3 value 500 deg is outside its limits"]),
        (["--size", "big"], ["--size: expected WxH", "got 'big'"]),
        (["--size", "0x100"], ["--size: expected WxH", "got '0x100'"]),
        (["--frames", "1,9"], ["--frames: expected 'all', 'none' or frame numbers 0..3 and E", "got '9'"]),
        (["--screenshot", "x.jpg"], ["--screenshot: 'x.jpg' must end in .png (screenshots are PNG files)"]),
        (["--workspace", "-5"], ["--workspace", "expected a positive integer, got '-5'"]),
        (["--demo", "square"], ["--demo", "invalid choice: 'square'"]),
        (["--bogus"], ["unrecognized arguments: --bogus"]),
        (["--screenshot", "/nonexistent-dir/shot.png"], ["cannot write", "directory '/nonexistent-dir' does not exist"]),
    ],
)
def test_bad_input_gives_one_line_and_status_2(args: list[str], fragments: list[str], tmp_path: Path) -> None:
    out = tmp_path / "never.png"
    if "--screenshot" not in args:  # so that a validation bug cannot open a window
        args = [*args, "--screenshot", str(out)]
    assert_one_line_error(run(*args), *fragments)
    assert not out.exists()


def test_screenshot_path_that_is_a_directory(tmp_path: Path) -> None:
    assert_one_line_error(run("--screenshot", str(tmp_path)), f"cannot write '{tmp_path}': it is a directory")


def test_broken_robot_file_reports_its_load_error(tmp_path: Path) -> None:
    bad = tmp_path / "broken.toml"
    bad.write_text('name = "broken"\nunits = "deg"\n[[joints]]\ntype = "revolute"\na = "wide"\n')
    with pytest.raises(RobotDefinitionError) as expected:
        load_robot(bad)
    result = run("--robot", str(bad), "--screenshot", str(tmp_path / "x.png"))
    assert_one_line_error(result, " ".join(str(expected.value).split()))
    assert not (tmp_path / "x.png").exists()


def test_missing_robot_file(tmp_path: Path) -> None:
    assert_one_line_error(run("--robot", str(tmp_path / "none.toml")), "none.toml", "not found")


def test_no_display_without_screenshot_says_so() -> None:
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY", "QT_QPA_PLATFORM")}
    assert_one_line_error(run(env=env), "no display", "use --screenshot FILE.png")


def test_missing_osmesa_names_the_package(tmp_path: Path) -> None:
    # a sitecustomize that makes `from OpenGL import osmesa` fail, as without libOSMesa
    (tmp_path / "sitecustomize.py").write_text("import sys\nsys.modules['OpenGL.osmesa'] = None\n")
    env = dict(os.environ, PYTHONPATH=str(tmp_path))
    result = run_process("--screenshot", str(tmp_path / "x.png"), env=env)  # a fresh interpreter
    assert_one_line_error(result, "offscreen rendering failed", "libosmesa6")


def test_bad_input_from_a_real_process(tmp_path: Path) -> None:
    """What a shell sees: exit status 2 and one line on stderr, no traceback, nothing written."""
    out = tmp_path / "never.png"
    assert_one_line_error(run_process("--robot", "nosuch", "--screenshot", str(out)), "unknown robot 'nosuch'")
    assert not out.exists()


def test_list_robots() -> None:
    """A table: heading, then per shipped robot its name, DOF, joint letters, convention
    and description."""
    result = run("--list-robots")
    assert result.returncode == 0, result.stderr
    lines = result.stdout.splitlines()
    assert lines[0].split() == ["name", "DOF", "joints", "convention", "description"]
    assert [line.split()[0] for line in lines[1:]] == available_robots()
    for line, name in zip(lines[1:], available_robots()):
        rob = load_robot(name)
        letters = ["R" if t == 0 else "P" for t in rob.jtype]
        assert line.split()[1 : 3 + rob.n_dofs] == [str(rob.n_dofs), *letters, rob.convention]
        assert line.rstrip().endswith(rob.description or rob.name)


def test_screenshot_writes_png_of_requested_size(tmp_path: Path) -> None:
    out = tmp_path / "shot.png"
    result = run("--screenshot", str(out), "--size", "320x200")
    assert result.returncode == 0, result.stderr
    image = read_png(out)
    assert image.shape[:2] == (200, 320)
    red = (image[..., 0] > 150) & (image[..., 1] < 80) & (image[..., 2] < 80)
    assert red.sum() > 20  # the endeffector sphere (and the x axis of the base frame)


def test_screenshot_options_change_the_picture(tmp_path: Path) -> None:
    def shot(name: str, *args: str) -> np.ndarray:
        out = tmp_path / f"{name}.png"
        result = run("--screenshot", str(out), "--size", "240x180", *args)
        assert result.returncode == 0, result.stderr
        return read_png(out)

    plain = shot("plain")
    for name, args in {
        "q": ["--q", "90,30,-60"],
        "frames": ["--frames", "all"],
        "wireframe": ["--wireframe"],
        "workspace": ["--workspace", "3000"],
        "robot": ["--robot", "puma560"],
    }.items():
        assert np.count_nonzero(np.any(shot(name, *args) != plain, axis=2)) > 100, name


def test_negative_first_joint_value(tmp_path: Path) -> None:
    out = tmp_path / "neg.png"
    result = run("--q", "-30,45,-60", "--screenshot", str(out), "--size", "64x48")
    assert result.returncode == 0, result.stderr
    assert out.exists()


def test_robot_file_path_is_accepted(tmp_path: Path) -> None:
    robot_file = tmp_path / "arm.toml"
    robot_file.write_text((ROOT / "robots" / "planar3.toml").read_text())
    out = tmp_path / "arm.png"
    result = run("--robot", str(robot_file), "--q", "10,20,30", "--screenshot", str(out), "--size", "64x48")
    assert result.returncode == 0, result.stderr
    assert read_png(out).shape[:2] == (48, 64)


def test_screenshot_path_does_not_import_qt(tmp_path: Path) -> None:
    out = tmp_path / "noqt.png"
    code = (
        "import sys, simulator\n"
        f"status = simulator.main(['--screenshot', {str(out)!r}, '--size', '64x48'])\n"
        "assert not [m for m in sys.modules if m.startswith('PyQt5')], 'Qt was imported'\n"
        "sys.exit(status)\n"
    )
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120, cwd=ROOT)
    assert result.returncode == 0, result.stderr
    assert out.exists()


def test_screenshot_with_another_extension_is_refused_and_nothing_written(tmp_path: Path) -> None:
    out = tmp_path / "x.jpg"
    result = run("--screenshot", str(out))
    assert_one_line_error(result)
    assert result.stderr == "robot-sim: error: --screenshot: 'x.jpg' must end in .png (screenshots are PNG files)\n"
    assert not out.exists()


@pytest.mark.parametrize(
    ("text", "expected"),
    [(None, None), ("none", []), ("0", [0]), ("2, 0", [2, 0]), ("0,E", [0, 4]), ("e", [4]), ("all", [0, 1, 2, 3, 4])],
)
def test_frames_option_lists_exactly_the_frames_to_show(text: str | None, expected: list[int] | None) -> None:
    from robot_sim.app.prepare import parse_frames, prepare, session_from_config

    assert parse_frames(text, 4) == expected
    args = ["--screenshot", "unused.png"] + ([] if text is None else ["--frames", text])
    options = session_from_config(prepare(args)).options
    if expected is None:  # the default: the base frame only
        assert options.show_frames == [True, False, False, False] and not options.show_endeff_frame
    else:
        assert [i for i, shown in enumerate(options.show_frames) if shown] == sorted(i for i in expected if i < 4)
        assert options.show_endeff_frame == (4 in expected)


def test_frames_0_draws_the_base_frame(tmp_path: Path) -> None:
    """``--frames 0`` shows the base frame (it used to toggle it off): red and green pixels
    where Camera.project puts its x and y axes, absent with ``--frames none``."""
    from robot_sim import graphics as go
    from robot_sim.app.prepare import prepare, session_from_config

    pictures, sessions = {}, {}
    for frames in ("0", "none"):
        out = tmp_path / f"frames-{frames}.png"
        args = ["--robot", "puma560", "--frames", frames, "--size", "320x240", "--screenshot", str(out)]
        assert run(*args).returncode == 0
        pictures[frames] = read_png(out)[..., :3].astype(int)
        sessions[frames] = session_from_config(prepare(args))
    kin = sessions["0"].kin
    length = go.robot_look(kin.robot).frame_length
    base = kin.h_tf[0]
    for column, name in ((0, "x"), (1, "y")):
        for frames, expect_axis in (("0", True), ("none", False)):
            camera = sessions[frames].camera
            point = base.t() + 0.75 * length * base.R()[:, column]
            x, y = np.round(camera.project(point[None], 320, 240)[0]).astype(int)
            r, g, b = pictures[frames][y, x]
            channel = (r, g)[column]
            others = [v for i, v in enumerate((r, g, b)) if i != column]
            is_axis = channel > max(others) + 40
            assert is_axis == expect_axis, f"--frames {frames}: {name} axis pixel {(r, g, b)} at {(x, y)}"


def test_annotate_draws_the_joint_s_dh_parameters(tmp_path: Path) -> None:
    """``--annotate 2`` changes the picture near frames 1 and 2 (dimensions, arcs, values);
    a joint number outside 1..n is one error line, exit 2."""
    pictures = {}
    for extra in ([], ["--annotate", "2"]):
        out = tmp_path / f"annotate{len(extra)}.png"
        args = ["--robot", "puma560", "--q", "0,45,-135,0,45,0", "--size", "320x240", "--screenshot", str(out), *extra]
        assert run(*args).returncode == 0
        pictures[len(extra)] = read_png(out)[..., :3].astype(int)
    assert (np.abs(pictures[2] - pictures[0]).max(axis=-1) > 40).sum() > 200
    for bad in ("0", "7", "x"):
        result = run("--robot", "puma560", "--annotate", bad, "--screenshot", str(tmp_path / "bad.png"))
        assert result.returncode == 2
        assert result.stderr == f"robot-sim: error: --annotate: expected a joint number 1..6, got '{bad}'\n"


def test_table_into_a_closed_pipe_exits_without_a_traceback() -> None:
    """`robot-sim --list-robots | head -1`: the reader closes the pipe after one line; the
    program stops quietly (no BrokenPipeError traceback on stderr)."""
    proc = subprocess.Popen(
        [sys.executable, str(SIMULATOR), "--list-robots"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, cwd=ROOT,
    )
    proc.stdout.close()  # nobody reads: the first write meets a closed pipe
    _, err = proc.communicate(timeout=120)
    assert err == b""
    assert proc.returncode == 1


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--theme", "blue"], "robot-sim: error: --theme: expected one of dark, light, got 'blue'"),
        (["--look", "fancy"], "robot-sim: error: --look: expected one of dh, solid, mesh, both, got 'fancy'"),
        (["--look", "mesh"], "robot-sim: error: --look: robot 'Anthropomorphic arm' has no visual shapes, "
                             "so its looks are dh, solid; got 'mesh'"),
    ],
)
def test_bad_theme_or_look_is_one_exact_line(args: list[str], message: str, tmp_path: Path) -> None:
    out = tmp_path / "never.png"
    result = run(*args, "--screenshot", str(out))
    assert result.returncode == 2
    assert result.stderr == message + "\n"
    assert not out.exists()



def test_in_process_runs_leave_the_test_process_as_it_was(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """cli_helpers.run: inside, no display (a command that would open the window says so)
    and the given working folder; afterwards the environment, folder and streams are back."""
    monkeypatch.setenv("DISPLAY", ":99")
    before = (dict(os.environ), os.getcwd(), sys.stdout, sys.stderr)
    assert_one_line_error(run("--robot", "planar3"), "no display", "use --screenshot FILE.png")
    result = run("--robot", "planar3", "--size", "32x24", "--screenshot", "here.png", cwd=tmp_path)
    assert result.returncode == 0 and result.stdout == f"wrote {tmp_path / 'here.png'}\n" and result.stderr == ""
    assert read_png(tmp_path / "here.png").shape[:2] == (24, 32)
    assert run("--robot", "planar3", "--print-dh").stdout.startswith("Three-link planar arm: 3 joints (R R R)")
    assert (dict(os.environ), os.getcwd(), sys.stdout, sys.stderr) == before


def test_ik_branches_draws_the_branches_of_the_q_pose(tmp_path: Path) -> None:
    def shot(name: str, *args: str) -> np.ndarray:
        out = tmp_path / f"{name}.png"
        result = run("--robot", "puma560", "--q", "30,50,-100,20,30,-20", "--size", "320x240",
                     "--screenshot", str(out), *args)
        assert result.returncode == 0, result.stderr
        return read_png(out)

    plain, branches = shot("plain"), shot("branches", "--ik-branches")
    # the translucent ghost colour (GHOST_COLOR, cyan) over the dark background: bluish pixels appear
    added = np.any(branches != plain, axis=2) & (branches[..., 2].astype(int) > branches[..., 0].astype(int) + 40)
    assert added.sum() > 200


def test_ik_branches_of_an_arm_without_a_closed_form_is_one_line(tmp_path: Path) -> None:
    from robot_sim.io.robot_writer import to_toml
    from robot_sim.model.params import RobotParams

    arm = RobotParams.from_arrays("skewed", [0.3, 0.2, 0.4, 0.15, 0.25], [0.4, 1.1, -0.7, 0.9, -1.2],
                                  [0.2, 0.15, 0.1, 0.25, 0.12], np.zeros(5), np.zeros(5))
    path = tmp_path / "skewed.toml"
    path.write_text(to_toml(arm))
    out = tmp_path / "never.png"
    assert_one_line_error(run("--robot", str(path), "--ik-branches", "--screenshot", str(out)),
                          "--ik-branches: skewed has no closed-form IK (general)")
    assert not out.exists()
