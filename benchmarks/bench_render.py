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
  for the PUMA URDF (mesh loading included).

The robot moves every frame (a new configuration), so the shadow map is redrawn each
time, as while the arm is driven.  Run alone: ``python benchmarks/bench_render.py``.
"""
from __future__ import annotations

import dataclasses
import math
import os
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Callable

os.environ.setdefault("PYOPENGL_PLATFORM", "osmesa")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # as simulator.py sets it for the renderer

import numpy as np  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

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


def bench_frames(table: Table) -> None:
    """Per-frame rows (see the module docstring)."""
    humanoid, default = load_robot("humanoid7"), load_robot("anthropomorphic")
    rows: list[tuple[str, Callable[[], tuple[float, float]], str]] = [
        ("empty frame (clear, 4x MSAA resolve, read back)", lambda: frame_time(humanoid, empty=True), "—"),
        ("empty frame without MSAA", lambda: frame_time(humanoid, empty=True, samples=0), "—"),
        ("humanoid7, DH look, all frames", lambda: frame_time(humanoid, frames=True), "≤ 8 ms"),
        ("humanoid7, DH look, all frames, no MSAA", lambda: frame_time(humanoid, frames=True, samples=0), "—"),
        ("anthropomorphic (the default arm), base frame", lambda: frame_time(default), "—"),
    ]
    puma = puma_urdf()
    if puma is not None:
        robot = load_robot(puma, tip=PUMA_URDF[1])
        count = sum(len(shape.faces) for link in robot.visuals for shape in link if isinstance(shape, Mesh))
        rows.append((f"PUMA 560 URDF of rtb-data, its meshes ({count:,} triangles)", lambda: frame_time(robot), "—"))
    heavy = heavy_mesh_arm(humanoid, MESH_TRIANGLES)
    count = sum(len(shape.faces) for link in heavy.visuals for shape in link)
    rows += [
        (f"humanoid7 (base frame) carrying {count:,} mesh triangles", lambda: frame_time(heavy), "≤ 16 ms"),
        (f"humanoid7 (base frame) + {CLOUD_POINTS:,}-point workspace cloud, camera still", lambda: frame_time(humanoid, cloud=True), "—"),
        (f"humanoid7 (base frame) + {CLOUD_POINTS:,}-point workspace cloud, camera orbiting",
         lambda: frame_time(humanoid, cloud=True, orbit=True), "—"),
    ]
    w, h = FRAME_SIZE
    for what, run, target in rows:
        med, iqr = run()
        table.add(f"offscreen frame {w}×{h}: {what}", ms(med), ms(iqr), target=target)


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


def main() -> None:
    table = Table()
    bench_frames(table)
    bench_screenshot(table)
    print(f"\nload average {os.getloadavg()[0]:.2f} (1 min), {os.cpu_count()} cores\n")
    table.print()


if __name__ == "__main__":
    main()
