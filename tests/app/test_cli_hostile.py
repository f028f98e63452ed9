"""Command line against hostile paths and sizes: one ``robot-sim: error:`` line, exit
status 2, and no file left behind (not even a partial one).  ``run`` calls the program in
this process, with a time limit (a FIFO must not make it hang)."""
from __future__ import annotations

import contextlib
import io
import os
import re
import subprocess
import tempfile
from pathlib import Path

import pytest

from robot_sim.kinematics import max_workspace_samples
from robot_sim.io.robot_file import ROBOTS_DIR, load_robot
from unprivileged import call_unprivileged

from cli_helpers import run


def one_line_error(result: subprocess.CompletedProcess[str] | tuple[int, str]) -> str:
    """The single error line of a failed run (asserting exit status 2 and no traceback)."""
    code, stderr = (result.returncode, result.stderr) if hasattr(result, "returncode") else result
    assert code == 2, stderr
    lines = stderr.splitlines()
    assert len(lines) == 1, stderr
    assert lines[0].startswith("robot-sim: error: ")
    return lines[0]


def main_unprivileged(*args: str) -> tuple[int, str]:
    """``simulator.main(args)`` in a child process running as user nobody (root would
    read and enter everything); returns (exit status, stderr).  The program is imported
    here, before the fork: the checkout and its .venv may sit in a directory nobody cannot
    enter (a private clone run as root), so the child must not need to read them."""
    import simulator

    def body() -> list:
        err = io.StringIO()
        with contextlib.redirect_stderr(err):
            code = simulator.main(list(args))
        return [code, err.getvalue()]

    code, stderr = call_unprivileged(body)
    return code, stderr


@pytest.fixture()
def shared_dir():
    """A temporary directory that user nobody may enter (pytest's tmp_path may not be),
    holding a copy of a shipped robot file nobody may read (robots/ may not be)."""
    with tempfile.TemporaryDirectory() as folder:
        os.chmod(folder, 0o777)
        robot = Path(folder) / "robot.toml"
        robot.write_text((ROBOTS_DIR / "planar3.toml").read_text())
        robot.chmod(0o644)
        yield Path(folder)


# ------------------------------------------------------------------ robot paths


def test_robot_file_name_of_300_characters(tmp_path):
    path = tmp_path / ("r" * 300 + ".toml")
    line = one_line_error(run("--robot", str(path), "--screenshot", str(tmp_path / "x.png")))
    assert line == f"robot-sim: error: {path}: cannot read robot file: File name too long"


def test_robot_path_that_is_a_directory_or_a_fifo(tmp_path):
    folder = tmp_path / "arm.toml"
    folder.mkdir()
    line = one_line_error(run("--robot", str(folder), "--screenshot", str(tmp_path / "x.png")))
    assert line == f"robot-sim: error: {folder}: cannot read robot file: it is a directory, not a regular file"
    fifo = tmp_path / "pipe.toml"
    os.mkfifo(fifo)
    line = one_line_error(run("--robot", str(fifo), "--screenshot", str(tmp_path / "x.png"), timeout=60))
    assert line == f"robot-sim: error: {fifo}: cannot read robot file: it is a FIFO (named pipe), not a regular file"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["arm.toml", "pipe.toml"]


def test_unreadable_robot_file(shared_dir):
    path = shared_dir / "secret.toml"
    path.write_text((ROBOTS_DIR / "planar3.toml").read_text())
    path.chmod(0o000)
    line = one_line_error(main_unprivileged("--robot", str(path), "--screenshot", str(shared_dir / "x.png")))
    assert line == f"robot-sim: error: {path}: cannot read robot file: Permission denied"


# ------------------------------------------------------------------ screenshot paths


def test_screenshot_name_of_300_characters(tmp_path):
    path = tmp_path / ("s" * 300 + ".png")
    line = one_line_error(run("--screenshot", str(path)))
    assert line == f"robot-sim: error: --screenshot: cannot write '{path}': File name too long"
    assert list(tmp_path.iterdir()) == []


def test_screenshot_into_a_directory_that_cannot_be_entered(shared_dir):
    locked = shared_dir / "locked"
    locked.mkdir(mode=0o000)
    locked.chmod(0o000)
    target = locked / "shot.png"
    line = one_line_error(main_unprivileged("--robot", str(shared_dir / "robot.toml"), "--screenshot", str(target)))
    assert line == f"robot-sim: error: --screenshot: cannot write '{target}': Permission denied"


def test_screenshot_into_a_directory_that_cannot_be_written(shared_dir):
    readonly = shared_dir / "readonly"
    readonly.mkdir()
    readonly.chmod(0o555)
    target = readonly / "shot.png"
    line = one_line_error(main_unprivileged("--robot", str(shared_dir / "robot.toml"), "--screenshot", str(target)))
    assert line == f"robot-sim: error: --screenshot: cannot write '{target}': Permission denied"
    assert list(readonly.iterdir()) == []


def test_screenshot_onto_a_fifo_is_refused_without_hanging(tmp_path):
    fifo = tmp_path / "pipe.png"
    os.mkfifo(fifo)
    line = one_line_error(run("--screenshot", str(fifo), timeout=60))
    assert line == f"robot-sim: error: --screenshot: cannot write '{fifo}': it is a FIFO (named pipe), not a regular file"


def test_screenshot_onto_a_device_is_refused(tmp_path):
    link = tmp_path / "null.png"
    link.symlink_to("/dev/null")
    line = one_line_error(run("--screenshot", str(link)))
    assert line == f"robot-sim: error: --screenshot: cannot write '{link}': it is a character device, not a regular file"


def test_screenshot_on_a_full_disk_leaves_no_file(tmp_path):
    disk = tmp_path / "disk"
    if os.geteuid() != 0:
        reason = "a full disk needs a small tmpfs, which only root can mount"
        print(f"SKIPPED full-disk command-line test: {reason}")
        pytest.skip(reason)
    disk.mkdir()
    mounted = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=4k", "tmpfs", str(disk)], capture_output=True, text=True)
    if mounted.returncode != 0:
        reason = f"mount -t tmpfs failed: {mounted.stderr.strip()}"
        print(f"SKIPPED full-disk command-line test: {reason}")
        pytest.skip(reason)
    try:
        target = disk / "shot.png"
        line = one_line_error(run("--screenshot", str(target), "--size", "640x480"))
        assert line == f"robot-sim: error: --screenshot: cannot write '{target}': No space left on device"
        assert list(disk.iterdir()) == []
    finally:
        subprocess.run(["umount", str(disk)], check=True)


# ------------------------------------------------------------------ --workspace


def test_workspace_beyond_memory_is_a_clear_error(tmp_path):
    limit = max_workspace_samples(load_robot("anthropomorphic"))
    for count in (str(limit * 4), "1" + "0" * 100):
        line = one_line_error(run("--workspace", count, "--screenshot", str(tmp_path / "w.png")))
        assert line.startswith(f"robot-sim: error: --workspace: {count[:20]}")
        assert re.search(r" points need more than the \d+ MiB of memory available; at most \d+ points fit$", line), line
    line = one_line_error(run("--workspace", "9" * 5000, "--screenshot", str(tmp_path / "w.png")))
    assert len(line) < 300 and line.startswith("robot-sim: error: argument --workspace: expected a positive integer")
    assert list(tmp_path.iterdir()) == []


def test_workspace_with_an_unlimited_prismatic_joint(tmp_path):
    robot = tmp_path / "slider.toml"
    robot.write_text(
        'name = "slider"\nunits = "deg"\n[[joints]]\ntype = "prismatic"\na = 0.0\nalpha = 0.0\nd = 0.0\ntheta = 0.0\n'
    )
    line = one_line_error(run("--robot", str(robot), "--workspace", "100", "--screenshot", str(tmp_path / "w.png")))
    assert line == "robot-sim: error: --workspace: slider: prismatic joint 1 has no limits; cannot sample its range"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["slider.toml"]
