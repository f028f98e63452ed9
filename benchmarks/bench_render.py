"""Rendering rows of ``make bench``: offscreen frames at 800×600 with 4x MSAA and shadows,
and ``--screenshot`` from start to PNG.

* per frame: humanoid7 with every frame shown (the issue's DH-look row), the default arm
  (anthropomorphic), a mesh arm (the Robotics Toolbox's PUMA 560 URDF from ``rtb-data``,
  when installed), an arm carrying 200 000 mesh triangles, the 200 000-point workspace
  cloud with the camera still and orbiting;
* the floor of this machine: an empty frame (clear, MSAA resolve, read back) and the
  same without multisampling, so the rows above can be read against what llvmpipe
  cannot go below;
* ``python simulator.py --screenshot`` wall time, kinematic, with ``--motion ct`` and
  for the PUMA URDF (mesh loading included);
* the real window at 1280×800 under Xvfb (when ``xvfb-run`` is installed) orbiting
  humanoid7 with every frame shown, driven by a drag step per turn of Qt's event loop:
  paints per second (a row of its own process: the window needs GLX, not OSMesa).

The robot moves every frame (a new configuration), so the shadow map is redrawn each
time, as while the arm is driven.  Run alone: ``python benchmarks/bench_render.py``.

Against another renderer in the same run: ``python benchmarks/bench_render.py --vs
CHECKOUT`` (or ``BENCH_RENDER_VS=CHECKOUT make bench``), where CHECKOUT is another
checkout of the project (e.g. a worktree of main: ``git worktree add ../base main``).
Each frame row then runs in its own processes, this checkout's and CHECKOUT's robot_sim
in turn (A B A B ..., ``VS_ROUNDS`` pairs), and reports the medians of the rounds with
CHECKOUT's in the baseline column and its ratio (the IQR column then holds the range of
this checkout's round medians).
"""
from __future__ import annotations

import argparse
import dataclasses
import math
import os
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Callable

WINDOW_FLAG = "--window-orbit"  # the window row's own process: Qt's GLX context, not OSMesa
if WINDOW_FLAG not in sys.argv:
    os.environ.setdefault("PYOPENGL_PLATFORM", "osmesa")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # as simulator.py sets it for the renderer

import numpy as np  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
# ``--root CHECKOUT`` (a row run for --vs): that checkout's robot_sim, else this one's
_ROOT_ARG = sys.argv.index("--root") + 1 if "--root" in sys.argv else 0
sys.path.insert(0, sys.argv[_ROOT_ARG] if _ROOT_ARG else str(Path(__file__).resolve().parent.parent))

from robot_sim.io.robot_file import load_robot  # noqa: E402
from robot_sim.kinematics import Kinematics, random_configurations, workspace_points  # noqa: E402
from robot_sim.model.params import RobotParams  # noqa: E402
from robot_sim.model.shapes import Mesh  # noqa: E402
from robot_sim.model.state import RobotState  # noqa: E402
from timing import Table, measure, median_iqr, ms  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
FRAME_SIZE = (800, 600)
CLOUD_POINTS = 200_000
MESH_TRIANGLES = 200_000
REPEATS = 30
VS_ROUNDS = 3  # --vs: pairs of processes (this checkout, the other) per row
WINDOW_SIZE = (1280, 800)
WINDOW_SECONDS = 4.0  # of orbiting, after the window is shown
WINDOW_DRAG_PX = 4  # horizontal drag step (pixels) per turn of the event loop
XVFB = ["xvfb-run", "-a", "-s", "-screen 0 1280x1024x24"]
#: The rtb-data URDF of the mesh arm (Collada meshes) and its tip link.
PUMA_URDF = ("unimation_puma560_description/urdf/puma560_robot.urdf", "link7")


def puma_urdf() -> Path | None:
    """The PUMA 560 URDF of ``rtb-data``, or None when the package is not installed."""
    try:
        import rtbdata
    except ImportError:
        return None
    return Path(rtbdata.__file__).parent / "xacro" / PUMA_URDF[0]


def sphere_mesh(triangles: int, radius: float) -> tuple[np.ndarray, np.ndarray]:
    """A latitude-longitude sphere of about ``triangles`` triangles: vertices (V, 3) and
    faces (F, 3)."""
    rings = max(math.ceil(math.sqrt(triangles / 4.0)), 2)
    theta, phi = np.meshgrid(np.linspace(0.0, np.pi, rings + 1), np.linspace(0.0, 2 * np.pi, 2 * rings + 1),
                             indexing="ij")
    vertices = radius * np.stack([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)], -1)
    index = np.arange(vertices.shape[0] * vertices.shape[1]).reshape(vertices.shape[:2])
    a, b, c, d = index[:-1, :-1], index[:-1, 1:], index[1:, 1:], index[1:, :-1]
    faces = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)])
    return vertices.reshape(-1, 3), faces


def heavy_mesh_arm(robot: RobotParams, triangles: int) -> RobotParams:
    """``robot`` with one sphere mesh on every link, ``triangles`` triangles in all."""
    vertices, faces = sphere_mesh(triangles // robot.n_dofs, 0.06)
    color = (0.75, 0.75, 0.78, 1.0)
    visuals = tuple((Mesh((vertices, faces), color=color),) for _ in range(robot.n_dofs))
    return dataclasses.replace(robot, visuals=visuals)


def frame_time(robot: RobotParams, *, frames: bool = False, cloud: bool = False, orbit: bool = False,
               empty: bool = False, samples: int | None = None) -> tuple[float, float]:
    """Median and IQR of one offscreen frame of ``robot`` (a new configuration each
    frame), in seconds."""
    from robot_sim.graphics import Camera, GraphicsOptions, OffscreenRenderer, Scene, WorkspaceCloud, robot_reach

    kin, state = Kinematics(robot), RobotState(robot)
    options = GraphicsOptions(robot.n_dofs + 1)
    if frames:
        options.toggle_all_frames()
    if samples is not None:
        options.samples = samples
    camera = Camera()
    reach = robot_reach(robot)
    camera.fit(np.vstack([kin.frames[:, :3, 3], [[reach] * 3, [-reach] * 3]]))
    scene = Scene(kinematics=kin)
    if cloud:
        points, manip = workspace_points(robot, CLOUD_POINTS, seed=0)
        scene.workspace = WorkspaceCloud(points, manip)
        options.show_workspace = True
    poses = iter(random_configurations(robot, 10 * REPEATS, np.random.default_rng(0)))
    with OffscreenRenderer(*FRAME_SIZE) as renderer:
        if empty:
            renderer.view.items = []

        def one() -> None:
            state.set_q(next(poses))
            kin.update(state.joint_state)
            if orbit:
                camera.orbit(1.0, 0.0)  # a new view every frame: the cloud's background picture is redrawn
            renderer.render(camera, scene, options)

        return median_iqr(measure(one, repeats=REPEATS))


def frame_rows() -> dict[str, tuple[str, Callable[[], tuple[float, float]], str]]:
    """The per-frame rows by key: (what, a function timing it, target)."""
    humanoid, default = load_robot("humanoid7"), load_robot("anthropomorphic")
    rows: dict[str, tuple[str, Callable[[], tuple[float, float]], str]] = {
        "empty": ("empty frame (clear, 4x MSAA resolve, read back)", lambda: frame_time(humanoid, empty=True), "—"),
        "empty_no_msaa": ("empty frame without MSAA", lambda: frame_time(humanoid, empty=True, samples=0), "—"),
        "humanoid7": ("humanoid7, DH look, all frames", lambda: frame_time(humanoid, frames=True), "≤ 8 ms"),
        "humanoid7_no_msaa": ("humanoid7, DH look, all frames, no MSAA",
                              lambda: frame_time(humanoid, frames=True, samples=0), "—"),
        "default": ("anthropomorphic (the default arm), base frame", lambda: frame_time(default), "—"),
    }
    puma = puma_urdf()
    if puma is not None:
        robot = load_robot(puma, tip=PUMA_URDF[1])
        count = sum(len(shape.faces) for link in robot.visuals for shape in link if isinstance(shape, Mesh))
        rows["puma"] = (f"PUMA 560 URDF of rtb-data, its meshes ({count:,} triangles)", lambda: frame_time(robot), "—")
    heavy = heavy_mesh_arm(humanoid, MESH_TRIANGLES)
    count = sum(len(shape.faces) for link in heavy.visuals for shape in link)
    rows["heavy"] = (f"humanoid7 (base frame) carrying {count:,} mesh triangles", lambda: frame_time(heavy), "≤ 16 ms")
    rows["cloud"] = (f"humanoid7 (base frame) + {CLOUD_POINTS:,}-point workspace cloud, camera still",
                     lambda: frame_time(humanoid, cloud=True), "—")
    rows["cloud_orbit"] = (f"humanoid7 (base frame) + {CLOUD_POINTS:,}-point workspace cloud, camera orbiting",
                           lambda: frame_time(humanoid, cloud=True, orbit=True), "—")
    return rows


def _row_in_process(key: str, root: Path) -> float:
    """Median seconds of frame row ``key`` timed in a new process with ``root``'s robot_sim."""
    cmd = [sys.executable, str(Path(__file__).resolve()), "--row", key, "--root", str(root)]
    out = subprocess.run(cmd, check=True, capture_output=True, text=True, cwd=root).stdout
    return float(out.split()[-1])


def bench_frames(table: Table, baseline: Path | None = None) -> None:
    """Per-frame rows (see the module docstring), then the window's row; against
    ``baseline``'s renderer (a checkout), alternated in processes, when given (default:
    ``BENCH_RENDER_VS``)."""
    baseline = baseline or (Path(os.environ["BENCH_RENDER_VS"]) if os.environ.get("BENCH_RENDER_VS") else None)
    w, h = FRAME_SIZE
    for key, (what, run, target) in frame_rows().items():
        if baseline is None:
            med, iqr = run()
            table.add(f"offscreen frame {w}×{h}: {what}", ms(med), ms(iqr), target=target)
            continue
        ours, theirs = [], []
        for _ in range(VS_ROUNDS):
            ours.append(_row_in_process(key, ROOT))
            theirs.append(_row_in_process(key, baseline))
        a, b = float(np.median(ours)), float(np.median(theirs))
        table.add(f"offscreen frame {w}×{h}: {what}", ms(a), ms(float(np.ptp(ours))), baseline=ms(b),
                  ratio=f"{b / a:.2f}x", target=target)
    bench_window(table)


def bench_screenshot(table: Table) -> None:
    """Start to PNG: kinematic, with the physics on (``--motion ct``: numba imported and
    the compiled dynamics kernels loaded from their cache, which the first run fills), and
    the PUMA URDF with its meshes when rtb-data is installed."""
    runs = [([], "kinematic"), (["--motion", "ct"], "--motion ct")]
    puma = puma_urdf()
    if puma is not None:
        runs.append((["--robot", str(puma), "--tip", PUMA_URDF[1]], "rtb-data PUMA 560 URDF with meshes"))
    for extra, what in runs:
        with tempfile.TemporaryDirectory() as tmp:
            png = Path(tmp) / "s.png"
            cmd = [sys.executable, str(ROOT / "simulator.py"), *extra, "--screenshot", str(png)]
            # as a user's Python starts it: with bytecode caches (the warm-up run writes them)
            env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
            env["PYOPENGL_PLATFORM"] = "osmesa"
            med, iqr = median_iqr(measure(lambda: subprocess.run(cmd, check=True, env=env, cwd=ROOT), repeats=7))
        table.add(f"`simulator.py --screenshot` wall time, start to PNG, {what}", ms(med), ms(iqr), target="≤ 1.5 s")


def window_orbit() -> tuple[float, float]:
    """Paints per second of the window orbiting humanoid7 (every frame shown) at
    ``WINDOW_SIZE``, a drag of ``WINDOW_DRAG_PX`` per turn of the event loop for
    ``WINDOW_SECONDS``, and the median seconds of our drawing of one (render and
    glFinish).  Needs a display (run under Xvfb) and PyOpenGL's GLX platform."""
    import time

    from OpenGL import GL
    from PyQt5 import QtCore, QtWidgets
    from PyQt5.QtCore import Qt
    from PyQt5.QtTest import QTest

    from robot_sim.app import output, prepare
    from robot_sim.qt.window import MainWindow

    app = QtWidgets.QApplication.instance() or QtWidgets.QApplication(["robot-sim"])
    config = prepare.prepare(["--robot", "humanoid7"])
    window = MainWindow(prepare.session_from_config(config), output.window_options(config))
    window.resize(*WINDOW_SIZE)
    window.show()
    QTest.qWaitForWindowExposed(window)
    window.session.options.toggle_all_frames()
    QTest.qWait(500)
    draws: list[float] = []
    render = window.view.scene_view.render

    def timed(*args: object) -> None:
        start = time.perf_counter()
        render(*args)
        GL.glFinish()
        draws.append(time.perf_counter() - start)

    window.view.scene_view.render = timed
    drag = QtCore.QTimer()
    drag.setInterval(0)
    drag.timeout.connect(lambda: window.drag(WINDOW_DRAG_PX, 0, Qt.LeftButton, Qt.NoModifier))
    start = time.monotonic()
    drag.start()
    QTest.qWait(round(WINDOW_SECONDS * 1000))
    drag.stop()
    fps = len(draws) / (time.monotonic() - start)
    window.close()
    app.processEvents()
    return fps, float(np.median(draws))


def bench_window(table: Table) -> None:
    """The window row (see the module docstring), skipped without ``xvfb-run``."""
    import shutil

    if shutil.which(XVFB[0]) is None:
        return
    env = {k: v for k, v in os.environ.items() if k != "PYOPENGL_PLATFORM"}
    cmd = [*XVFB, sys.executable, str(Path(__file__).resolve()), WINDOW_FLAG]
    fps, draw = (float(v) for v in subprocess.run(cmd, check=True, capture_output=True, text=True, env=env,
                                                 cwd=ROOT).stdout.split()[-2:])
    w, h = WINDOW_SIZE
    table.add(f"window {w}×{h} (Xvfb) orbiting humanoid7, all frames: paints per second (our drawing {ms(draw)})",
              f"{fps:.0f} fps", "—", target="≥ 30 fps")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--vs", type=Path, help="another checkout: its renderer in the baseline column")
    parser.add_argument("--row", help=argparse.SUPPRESS)  # one frame row, in a process of its own (--vs)
    parser.add_argument("--root", help=argparse.SUPPRESS)  # the checkout whose robot_sim --row times
    parser.add_argument(WINDOW_FLAG, action="store_true", help=argparse.SUPPRESS)  # the window row's process
    args = parser.parse_args()
    if args.window_orbit:
        print(*window_orbit())
        return
    if args.row:
        print(frame_rows()[args.row][1]()[0])
        return
    table = Table()
    bench_frames(table, args.vs.resolve() if args.vs else None)
    bench_screenshot(table)
    print(f"\nload average {os.getloadavg()[0]:.2f} (1 min), {os.cpu_count()} cores\n")
    table.print()


if __name__ == "__main__":
    main()
