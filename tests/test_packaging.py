"""The installed package: the wheel holds one top-level package, robot_sim (with the robot
files as package data), its dist-info and the robot-sim script, so nothing generic
(``control``, ``simulation``, ...) lands in site-packages."""
from __future__ import annotations

import os
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

from paths import ROOT



@pytest.fixture(scope="module")
def wheel(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The wheel built from a copy of the checkout's files (tracked or not ignored), so the
    checkout itself gets no build/ or egg-info."""
    src = tmp_path_factory.mktemp("src")
    tracked = subprocess.run(["git", "ls-files", "-z", "--cached", "--others", "--exclude-standard"], cwd=ROOT, capture_output=True, check=True).stdout
    for name in tracked.decode().split("\0"):
        if name and (ROOT / name).is_file():
            (src / name).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(ROOT / name, src / name)
    out = tmp_path_factory.mktemp("dist")
    subprocess.run([sys.executable, "-m", "pip", "wheel", "-q", "--no-deps", "--no-build-isolation",
                    "--disable-pip-version-check", "-w", str(out), str(src)], check=True, capture_output=True)
    (built,) = out.glob("*.whl")
    return built


def test_wheel_holds_only_robot_sim_and_its_dist_info(wheel: Path) -> None:
    names = zipfile.ZipFile(wheel).namelist()
    top = {name.split("/")[0] for name in names}
    assert top == {"robot_sim", "robot_sim-0.1.0.dist-info"}, top
    packages = {str(p.parent.relative_to(ROOT)) for p in (ROOT / "robot_sim").rglob("__init__.py")}
    assert packages <= {os.path.dirname(n) for n in names}, "a subpackage is missing from pyproject's packages"
    robots = sorted(f"robot_sim/robots/{p.name}" for p in (ROOT / "robots").glob("*.toml"))
    assert robots and robots == sorted(n for n in names if n.startswith("robot_sim/robots/"))
    entry_points = zipfile.ZipFile(wheel).read("robot_sim-0.1.0.dist-info/entry_points.txt").decode()
    assert "robot-sim = robot_sim.app.main:main" in entry_points


def test_installed_next_to_a_package_named_control(wheel: Path, tmp_path: Path) -> None:
    """python-control's import name is ``control``: installed beside it, ours must not
    shadow it, and the robot-sim script must still find its own modules and robot files."""
    site = tmp_path / "site"
    subprocess.run([sys.executable, "-m", "pip", "install", "-q", "--no-deps", "--disable-pip-version-check",
                    "--target", str(site), str(wheel)], check=True, capture_output=True)
    assert sorted(p.name for p in site.iterdir() if not p.name.startswith("__")) == [
        "bin", "robot_sim", "robot_sim-0.1.0.dist-info"]
    other = tmp_path / "other" / "control"
    other.mkdir(parents=True)
    (other / "__init__.py").write_text("WHO = 'python-control'\n")
    env = {**os.environ, "PYTHONPATH": f"{site}{os.pathsep}{other.parent}", "PYOPENGL_PLATFORM": "osmesa"}
    work = tmp_path / "work"
    work.mkdir()
    probe = ("import control, robot_sim, robot_sim.control.controllers as ours; "
             "print(control.WHO, robot_sim.__file__, ours.__name__)")
    out = subprocess.run([sys.executable, "-c", probe], cwd=work, env=env, capture_output=True, text=True, check=True)
    who, location, name = out.stdout.split()
    assert who == "python-control" and location.startswith(str(site)) and name == "robot_sim.control.controllers"
    shot = work / "x.png"
    run = subprocess.run([sys.executable, str(site / "bin" / "robot-sim"), "--robot", "ur5", "--screenshot", str(shot)],
                         cwd=work, env=env, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert shot.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
