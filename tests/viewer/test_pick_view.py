"""Pick demo drawing and command line: table, object and gripper where Camera.project puts
them (OSMesa), the final scene past the end, the recorded PNG sequence, one-line errors."""
from __future__ import annotations

import imageio_ffmpeg
import numpy as np
import pytest

from robot_sim.graphics import defs as gd
from robot_sim import graphics as go
from robot_sim.viewer import recording
from robot_sim.graphics.task_scene import gripper_placements
from kin_helpers import robot
from robot_sim.planning.pick_task import default_plan
from cli_helpers import assert_one_line_error, read_png, run
from robot_sim.viewer.session import ViewerSession

W, H = 640, 480


def colour_fraction(image: np.ndarray, xy: np.ndarray, rgba: tuple[float, ...], radius: int = 3) -> float:
    """Fraction of the pixels within ``radius`` of ``xy`` whose colour direction (shading
    removed) is that of ``rgba``."""
    x, y = (int(round(v)) for v in xy)
    patch = image[max(y - radius, 0): y + radius + 1, max(x - radius, 0): x + radius + 1, :3].reshape(-1, 3).astype(float)
    want = np.array(rgba[:3]) / np.linalg.norm(rgba[:3])
    norms = np.linalg.norm(patch, axis=1)
    cos = (patch @ want) / np.where(norms > 0, norms, 1.0)
    return float(np.mean((cos > 0.995) & (norms > 40)))


@pytest.fixture(scope="module")
def renderer():
    go.require_osmesa_platform()
    with go.OffscreenRenderer(W, H) as r:
        yield r


def pick_session(name: str, t: float) -> ViewerSession:
    session = ViewerSession(robot(name), aspect=W / H)
    session.start_pick(default_plan(robot(name)), t)
    return session


def test_table_object_and_gripper_at_their_projections(renderer):
    session = pick_session("ur5", 0.0)
    plan, cam = session.pick.plan, session.camera
    image = renderer.render(cam, session.scene(), session.options)
    spec = plan.spec
    obj_xy = cam.project(spec.object_pose[None, :3, 3], W, H)[0]
    assert colour_fraction(image, obj_xy, gd.OBJECT_COLOR) > 0.5
    # the empty table where the object will be placed
    place_top = spec.place[:3, 3] - [0.0, 0.0, spec.object_size[2] / 2]
    assert colour_fraction(image, cam.project(place_top[None], W, H)[0], gd.TABLE_COLOR) > 0.5
    # nothing of the task where the object is, in a frame without the task
    bare = renderer.render(cam, session.scene().__class__(session.kin), session.options)
    assert colour_fraction(bare, obj_xy, gd.OBJECT_COLOR) == 0.0
    # gripper fingers, close to the object while the gripper closes
    session.show_pick_at(plan.phase_times()["close"] + spec.dwell / 2)
    image = renderer.render(cam, session.scene(), session.options)
    palm = gripper_placements(session.scene().task)[0]
    assert colour_fraction(image, cam.project(palm[None, :3, 3], W, H)[0], gd.GRIPPER_COLOR, radius=2) > 0.3


def test_the_wall_between_pick_and_place_is_drawn(renderer):
    session = pick_session("ur5", 0.0)
    cam, spec = session.camera, session.pick.plan.spec
    wall = dict(spec.obstacles)["wall"]
    image = renderer.render(cam, session.scene(), session.options)
    face = wall.pose[:3, 3] + [0.0, 0.0, wall.size[2] / 4]  # its upper half, above the table
    xy = cam.project(face[None], W, H)[0]
    assert colour_fraction(image, xy, gd.TASK_OBSTACLE_COLOR) > 0.5
    bare = renderer.render(cam, session.scene().__class__(session.kin), session.options)
    assert colour_fraction(bare, xy, gd.TASK_OBSTACLE_COLOR) == 0.0


def test_object_drawn_at_its_place_after_the_end(renderer):
    session = pick_session("puma560", 1e6)
    plan, cam = session.pick.plan, session.camera
    assert session.pick.time == plan.duration
    image = renderer.render(cam, session.scene(), session.options)
    placed_xy = cam.project(plan.placed_pose[None, :3, 3], W, H)[0]
    start_xy = cam.project(plan.spec.object_pose[None, :3, 3], W, H)[0]
    assert colour_fraction(image, placed_xy, gd.OBJECT_COLOR) > 0.5
    assert colour_fraction(image, start_xy, gd.OBJECT_COLOR) == 0.0


def test_cli_pick_screenshot_past_the_end_shows_the_final_scene(tmp_path):
    out = tmp_path / "pick.png"
    result = run("--robot", "ur5", "--demo", "pick", "--time", "1000", "--size", f"{W}x{H}", "--screenshot", str(out))
    assert result.returncode == 0, result.stderr
    image = read_png(out)
    session = pick_session("ur5", 1000.0)
    placed_xy = session.camera.project(session.pick.plan.placed_pose[None, :3, 3], W, H)[0]
    assert colour_fraction(image, placed_xy, gd.OBJECT_COLOR) > 0.5


def test_cli_record_writes_the_expected_frames(tmp_path):
    out = tmp_path / "frames"
    result = run("--robot", "ur5", "--demo", "pick", "--record", str(out), "--duration", "0.5", "--fps", "4",
                 "--size", "320x240")
    assert result.returncode == 0, result.stderr
    names = sorted(p.name for p in out.iterdir())
    assert names == ["frame_00000.png", "frame_00001.png", "frame_00002.png", "recording.mp4"]
    assert result.stdout.strip() == f"wrote 3 frames to {out} and {out / 'recording.mp4'}"
    frames = [read_png(out / n) for n in names[:3]]
    # the video (the `video` extra is in the test extra) holds the same three pictures
    reader = imageio_ffmpeg.read_frames(str(out / "recording.mp4"))
    meta = next(reader)
    assert meta["size"] == (320, 240) and meta["fps"] == 4
    video = [np.frombuffer(f, np.uint8).reshape(240, 320, 3) for f in reader]
    assert len(video) == 3
    for picture, decoded in zip(frames, video):  # lossy: close on average, not bit-exact
        assert np.mean(np.abs(decoded.astype(float) - picture[..., :3])) < 4.0
    assert all(f.shape[:2] == (240, 320) for f in frames)
    # the arm moves toward the pre-grasp pose: every frame differs from the one before
    assert all(np.count_nonzero(np.any(a != b, axis=2)) > 20 for a, b in zip(frames, frames[1:]))
    # frame k shows t = k / fps, seen by the camera framed at the start
    session = ViewerSession(robot("ur5"), aspect=320 / 240)
    session.start_pick(default_plan(robot("ur5")), 0.0)
    session.show_pick_at(0.5)
    go.require_osmesa_platform()
    with go.OffscreenRenderer(320, 240) as r:
        np.testing.assert_array_equal(r.render(session.camera, session.scene(), session.options)[..., :3], frames[2][..., :3])


@pytest.mark.parametrize(
    "args, fragments",
    [
        (["--time", "2"], ["--time: needs --demo pick"]),
        (["--demo", "pick", "--time", "nan"], ["--time: expected a finite time in seconds >= 0, got 'nan'"]),
        (["--demo", "pick", "--record", "/nonexistent/dir/x", "--duration", "1"], ["--record: cannot write frames to"]),
        (["--demo", "pick", "--record", "{tmp}/r", "--fps", "0"], ["--fps: expected a positive number of frames per second"]),
    ],
)
def test_cli_pick_bad_input_is_one_line(tmp_path, args, fragments):
    assert_one_line_error(run("--robot", "ur5", *[a.format(tmp=tmp_path) for a in args]), *fragments)


def test_cli_unreachable_task_is_one_line_before_anything_moves(tmp_path):
    task = tmp_path / "far.toml"
    task.write_text('[table]\nxyz = [3, 0, 0.2]\nsize = [0.4, 0.4, 0.2]\n[object]\nshape = "box"\n'
                    'size = [0.04, 0.04, 0.08]\nxyz = [3.0, 0.0, 0.24]\n[place]\nxyz = [3.0, 0.2, 0.24]\n')
    out = tmp_path / "never.png"
    result = run("--robot", "ur5", "--demo", "pick", "--task", str(task), "--screenshot", str(out))
    assert_one_line_error(result, f"task {task}: UR5: pre-grasp: tool at xyz [3.000, 0.000, 0.400] m", "is out of reach")
    assert not out.exists()


def _pick_session() -> ViewerSession:
    session = ViewerSession(robot("ur5"), aspect=160 / 120)
    session.start_pick(default_plan(robot("ur5")), 0.0)
    return session


def test_record_without_the_video_extra_writes_frames_only(tmp_path, monkeypatch):
    monkeypatch.setattr(recording, "imageio_ffmpeg", None)
    frames, video = recording.record(_pick_session(), tmp_path, 0.25, 4.0, (160, 120))
    assert video is None
    assert sorted(p.name for p in tmp_path.iterdir()) == ["frame_00000.png", "frame_00001.png"]
    assert frames == [tmp_path / "frame_00000.png", tmp_path / "frame_00001.png"]


def test_a_failed_recording_leaves_no_video(tmp_path, monkeypatch):
    """A frame that cannot be written stops the recording: the partial MP4 and the frames
    already written are removed with the folder they were staged in (issue 31)."""
    written = []

    def save_png(path, image, text=None):
        if written:
            raise OSError(28, "No space left on device")
        written.append(path)
        path.write_bytes(b"png")

    monkeypatch.setattr(go, "save_png", save_png)
    with pytest.raises(OSError):
        recording.record(_pick_session(), tmp_path, 0.5, 4.0, (160, 120))
    assert list(tmp_path.iterdir()) == [] and len(written) == 1


def test_recording_again_into_a_directory_leaves_only_its_own_frames(tmp_path, monkeypatch):
    """A shorter recording into the directory of a longer one: the old higher-numbered
    frames go (the PNG sequence is this recording), other files stay untouched."""
    monkeypatch.setattr(recording, "imageio_ffmpeg", None)
    for name in ("frame_00005.png", "frame_00002.png", "notes.txt", "frame_00007.png.bak"):
        (tmp_path / name).write_bytes(b"old")
    frames, _ = recording.record(_pick_session(), tmp_path, 0.25, 4.0, (160, 120))
    assert sorted(p.name for p in tmp_path.iterdir()) == [
        "frame_00000.png", "frame_00001.png", "frame_00007.png.bak", "notes.txt"]
    assert (tmp_path / "notes.txt").read_bytes() == b"old"
    assert all(p.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" for p in frames)


def test_a_ghost_during_the_pick_task_keeps_every_part_but_the_sphere(renderer):
    """While the task's gripper replaces the arm's endeffector sphere, a ghost in another
    pose draws all its parts except its own sphere (it used to be compared with the arm's
    shorter part list, out of step, and lose parts)."""
    from robot_sim.graphics.items.ghost import GhostItem
    from robot_sim.graphics.solid import posed_parts
    from robot_sim.kinematics import Kinematics
    from robot_sim.model.state import RobotState

    session = _pick_session()
    desired = RobotState(session.robot)
    desired.set_q(session.state.q() + 0.3)
    ghost_kin = Kinematics(session.robot)
    ghost_kin.update(desired.joint_state)
    scene = session.scene()
    assert scene.task is not None
    renderer.render(session.camera, go.Scene(session.kin, ghost=ghost_kin, task=scene.task), session.options)
    ghost = renderer.view.item(GhostItem)
    expected = [(p.mesh, p.color) for p in posed_parts(ghost_kin, "dh", False) if p.color != gd.ENDEFF_COLOR]
    assert [(p.mesh, p.color) for p in ghost.parts] == expected


def test_hidden_by_box_agrees_with_sampling_the_sight_line() -> None:
    from robot_sim.viewer.pick_view import hidden_by_box

    rng = np.random.default_rng(3)
    lo, hi = np.array([-0.2, -0.3, 0.0]), np.array([0.2, 0.3, 0.5])
    eye = np.array([2.0, 1.0, 1.2])
    points = rng.uniform([-1.0, -1.0, -0.2], [1.0, 1.0, 1.0], size=(300, 3))
    points[:40] = rng.uniform(lo, hi, size=(40, 3))  # inside the box: behind its near face
    t = np.linspace(0.0, 0.999, 4000)[None, :, None]
    line = eye + t * (points[:, None, :] - eye)
    want = np.all((line >= lo) & (line <= hi), axis=-1).any(axis=1)
    got = hidden_by_box(eye, points, lo, hi)
    assert want.sum() > 50
    np.testing.assert_array_equal(got, want)
