"""The browser view without a browser: the server's safety (host, port, no share tunnel,
no file outside viser's client), the geometry sent (unit meshes, instance poses), that
a mesh goes out once and later updates carry poses only, the HTML export, and the
command line's browser options."""
from __future__ import annotations

import io
import socket
import urllib.error
import urllib.request
from pathlib import Path

import numpy as np
import pytest

from cli_helpers import run
from robot_sim.graphics.meshes import unit_meshes
from robot_sim.graphics.robot_parts import robot_parts
from robot_sim.io.robot_file import load_robot
from robot_sim.transforms import quaternion_from_rot, rot_from_quaternion, rot_from_rpy
from robot_sim.viewer.session import ViewerSession
from robot_sim.web.parts import instance_poses, unit_mesh
from robot_sim.web.scene import WebScene
from robot_sim.web.server import WebServerError, exposure_warning, is_loopback, start_server, stop_server
from paths import ROOT


@pytest.fixture()
def server():
    started = start_server("127.0.0.1", None, warn=None)
    yield started
    stop_server(started)


def _busy_port() -> socket.socket:
    sock = socket.socket()
    sock.bind(("127.0.0.1", 0))
    sock.listen()
    return sock


# ---- the server ----
def test_a_busy_port_is_refused_not_moved() -> None:
    """viser alone would take the next port; here the port asked for or an error."""
    with _busy_port() as busy:
        port = busy.getsockname()[1]
        with pytest.raises(WebServerError) as caught:
            start_server("127.0.0.1", port, warn=None)
    assert str(caught.value) == f"port: {port} on 127.0.0.1 is in use; choose another with --port"


@pytest.mark.parametrize("port", [0.5, -1, 65536, "80", True])
def test_a_bad_port_is_refused(port: object) -> None:
    with pytest.raises(WebServerError, match=r"^port: expected a whole number 1\.\.65535, got "):
        start_server("127.0.0.1", port, warn=None)  # type: ignore[arg-type]


def test_loopback_hosts_and_the_warning_for_others() -> None:
    assert all(is_loopback(h) for h in ("127.0.0.1", "localhost", "::1", "127.0.0.2"))
    assert not any(is_loopback(h) for h in ("0.0.0.0", "192.168.1.4", "example.org", "::"))
    assert exposure_warning("127.0.0.1", 8080) is None
    line = exposure_warning("0.0.0.0", 8080)
    assert line is not None and "\n" not in line and line.startswith("warning: serving on 0.0.0.0:8080")


def test_another_host_prints_one_warning_line_and_binds_it() -> None:
    out = io.StringIO()
    started = start_server("0.0.0.0", None, warn=out)
    try:
        assert started.get_host() == "0.0.0.0"
        lines = out.getvalue().splitlines()
        assert lines == [exposure_warning("0.0.0.0", started.get_port())]
    finally:
        stop_server(started)


def test_the_server_binds_loopback_and_hands_out_no_file_but_the_client(server, tmp_path: Path) -> None:
    base = f"http://127.0.0.1:{server.get_port()}"
    assert server.get_host() == "127.0.0.1"
    with urllib.request.urlopen(base + "/") as reply:
        assert b"<div id=\"root\">" in reply.read()
    secret = tmp_path / "secret.txt"
    secret.write_text("not for the browser")
    for path in ["/../../../../../etc/passwd", "/%2e%2e/%2e%2e/%2e%2e/etc/passwd", "/..%5c..%5cetc%5cpasswd",
                 "//etc/passwd", f"/{secret}", f"/..{secret}"]:
        with pytest.raises(urllib.error.HTTPError) as caught:
            urllib.request.urlopen(base + path)
        caught.value.close()  # its connection, which the server's stop would wait for
        assert caught.value.code == 404, path


def test_the_share_tunnel_cannot_be_asked_for(server) -> None:
    """The page's share button would make this machine connect to viser's share service."""
    from viser import _messages

    assert _messages.ShareUrlRequest not in server._websock_server._incoming_handlers


# ---- geometry ----
@pytest.mark.parametrize("name", sorted(unit_meshes()))
def test_unit_meshes_keep_their_triangles_with_shared_corners(name: str) -> None:
    vertices, faces = unit_mesh(name)
    soup = unit_meshes()[name][0]
    assert len(faces) <= len(soup) and len(vertices) < 3 * len(soup)
    # every triangle of the soup that has an area is one of the indexed triangles, same corners, same order
    areas = np.linalg.norm(np.cross(soup[:, 1] - soup[:, 0], soup[:, 2] - soup[:, 0]), axis=1)
    assert np.allclose(np.sort(vertices[faces].reshape(len(faces), -1), axis=0),
                       np.sort(soup[areas > 1e-9].reshape(int((areas > 1e-9).sum()), -1), axis=0), atol=1e-6)
    if name in ("sphere", "joint", "box"):  # closed surfaces: Euler characteristic 2
        edges = {tuple(sorted(e)) for f in faces for e in ((f[0], f[1]), (f[1], f[2]), (f[2], f[0]))}
        assert len(vertices) - len(edges) + len(faces) == 2


def test_instance_poses_rebuild_every_placement_of_a_robot() -> None:
    robot = load_robot("puma560")
    kin = ViewerSession(robot).kin
    mats = np.concatenate([p.placements for p in robot_parts(robot, kin.frames, kin.endeff_tf.mat)])
    wxyz, pos, scale = instance_poses(mats)
    rebuilt = np.array([rot_from_quaternion(q) * s for q, s in zip(wxyz, scale)])
    assert np.allclose(rebuilt, mats[:, :3, :3], atol=1e-5) and np.allclose(pos, mats[:, :3, 3], atol=1e-6)


def test_quaternion_round_trip() -> None:
    for rpy in np.random.default_rng(3).uniform(-3.1, 3.1, (50, 3)):
        rot = rot_from_rpy(rpy)
        assert np.allclose(rot_from_quaternion(quaternion_from_rot(rot)), rot, atol=1e-12)
    with pytest.raises(ValueError, match=r"^quaternion: expected four finite numbers"):
        rot_from_quaternion([0, 0, 0, 0])


# ---- what is sent ----
def _recorded_messages(server, action) -> list[tuple[str, dict]]:
    recording = server.get_scene_serializer()
    before = len(recording._messages)
    action()
    return [(m["type"], m) for _, m in recording._messages[before:]]


def test_meshes_go_once_then_only_poses(server) -> None:
    session = ViewerSession(load_robot("ur5"))  # with meshes: its own and the unit meshes of the DH look
    session.options.look = "both"
    view = WebScene(server.scene)
    first = _recorded_messages(server, lambda: view.sync(session))
    created = [m for kind, m in first if kind in ("BatchedMeshesMessage", "MeshMessage")]
    assert len(created) > 5
    session.set_q(session.state.q() + 0.2)
    later = _recorded_messages(server, lambda: view.sync(session))
    assert later, "a new pose sends something"
    assert {kind for kind, _ in later} <= {"SceneNodeUpdateMessage", "SetPositionMessage", "SetOrientationMessage"}
    sent = {key for kind, m in later if kind == "SceneNodeUpdateMessage" for key in m["updates"]}
    assert sent <= {"batched_wxyzs", "batched_positions", "batched_scales", "scale", "visible",
                    "points", "colors"}, sent
    assert not any("vertices" in str(m) for _, m in later)
    assert _recorded_messages(server, lambda: view.sync(session)) == [], "nothing moved, nothing sent"


# ---- export ----
def test_export_writes_one_self_contained_page(tmp_path: Path) -> None:
    session = ViewerSession(load_robot("puma560"))
    target = tmp_path / "pose.html"
    target.write_text("old page")
    from robot_sim.web.export import export_html

    assert export_html(session, target) == target
    page = target.read_text()
    assert page.startswith("<!doctype html>") and "window.__VISER_EMBED_DATA__=" in page
    assert "<script src=" not in page and "<link rel=\"stylesheet\"" not in page
    assert [p.name for p in tmp_path.iterdir()] == ["pose.html"], "no temporary file left"
    with pytest.raises(ValueError, match=r"^export_html: 'pose\.png' must end in \.html$"):
        export_html(session, tmp_path / "pose.png")


def test_export_refuses_too_many_frames_before_work() -> None:
    from robot_sim.web.export import MAX_EXPORT_FRAMES, sample_times

    assert np.allclose(sample_times(1.0, 4.0), [0.0, 0.25, 0.5, 0.75, 1.0])
    assert np.allclose(sample_times(0.9, 4.0), [0.0, 0.25, 0.5, 0.75, 0.9])
    with pytest.raises(ValueError, match=r"exceed the limit of"):
        sample_times(MAX_EXPORT_FRAMES, 2.0)
    with pytest.raises(ValueError, match=r"^export_html: fps must be in"):
        sample_times(1.0, 0.0)


# ---- command line ----
def test_cli_port_errors_are_one_line() -> None:
    bad = run("--web", "--port", "http")
    assert (bad.returncode, bad.stderr) == (2, "robot-sim: error: --port: expected a whole number 1..65535, got 'http'\n")
    with _busy_port() as busy:
        port = busy.getsockname()[1]
        taken = run("--web", "--port", str(port))
    assert taken.returncode == 2
    assert taken.stderr == f"robot-sim: error: --web: port: {port} on 127.0.0.1 is in use; choose another with --port\n"
    assert "Traceback" not in taken.stderr + taken.stdout


def test_cli_export_html(tmp_path: Path) -> None:
    wrong = run("--export-html", str(tmp_path / "x.png"))
    assert (wrong.returncode, wrong.stderr) == (2, "robot-sim: error: --export-html: 'x.png' must end in .html\n")
    done = run("--robot", "planar3", "--motion", "pd", "--duration", "0.4", "--export-html", str(tmp_path / "m.html"))
    assert done.returncode == 0, done.stderr
    assert done.stdout == f"wrote {tmp_path / 'm.html'}\n"
    assert "__VISER_EMBED_DATA__" in (tmp_path / "m.html").read_text()


# ---- rs.Visualizer(backend="web") ----
def test_the_visualizer_serves_the_session(tmp_path: Path) -> None:
    import robot_sim as rs

    robot = load_robot("puma560")
    with rs.Visualizer(robot, backend="web", size=(320, 240)) as viz:
        port = int(viz.url.rsplit(":", 1)[1].strip("/"))
        assert viz.url == f"http://127.0.0.1:{port}/"
        viz.display(robot.q_home + 0.1)
        assert np.allclose(viz.session.state.q(), robot.q_home + 0.1)
        assert f'src="{viz.url}"' in viz._repr_html_()
        assert 'srcdoc="&lt;!doctype html&gt;' in viz.embed()._repr_html_()
        assert viz.export_html(tmp_path / "pose.html").read_text().startswith("<!doctype html>")
        with pytest.raises(RuntimeError, match=r"^capture: no browser is connected; open http://127\.0\.0\.1:\d+/ first$"):
            viz.capture()
    with socket.socket() as again:  # closed: the port is free again
        again.bind(("127.0.0.1", port))


def test_no_exception_escapes_a_page_handler() -> None:
    from types import SimpleNamespace

    from robot_sim.web.serve import WebViewer

    viewer = WebViewer(ViewerSession(load_robot("puma560")), "puma560", host="127.0.0.1", port=None)
    try:
        event = SimpleNamespace(client=object(), target=SimpleNamespace(value="0.5"))
        viewer.panel._cell_edited(event, 99, "a")  # a row the robot does not have
        assert viewer.panel.message.startswith("internal error in _cell_edited: IndexError")
        event.target.value = "x"
        viewer.panel._cell_edited(event, 0, "a")
        with pytest.raises(ValueError) as window_says:
            from robot_sim.viewer.dh_table import edit_cell

            edit_cell(viewer.backend.session.robot, 0, "a", "x")
        assert viewer.panel.message == f"refused: {window_says.value}"
        with urllib.request.urlopen(viewer.url) as reply:  # still serving
            assert reply.status == 200
    finally:
        viewer.close()


def test_what_a_page_sends_is_checked_before_use(tmp_path: Path) -> None:
    """A page can send any value, not only what its controls offer: never a path to open,
    never a non-finite joint value."""
    from types import SimpleNamespace

    from robot_sim.web.serve import WebViewer

    robot = load_robot("puma560")
    viewer = WebViewer(ViewerSession(robot), "puma560", host="127.0.0.1", port=None)
    panel = viewer.panel
    secret = tmp_path / "robot.toml"
    secret.write_text((ROOT / "robots" / "ur5.toml").read_text())
    try:
        for value in (str(secret), "../robots/ur5", "ur5.toml"):
            panel._robot_chosen(SimpleNamespace(client=object(), target=SimpleNamespace(value=value)))
            assert viewer.backend.session.robot is robot
            assert panel.message.startswith("robot: expected one of ") and panel.message.endswith(f"got {value[:80]!r}")
        q = viewer.backend.session.state.q()
        slider = panel.sliders[0]
        for value in ("nan", float("inf"), slider.max + 1.0, "1e400"):
            panel._slider_moved(SimpleNamespace(client=object(), target=SimpleNamespace(value=value, min=slider.min,
                                                                                         max=slider.max)), 0)
            assert np.array_equal(viewer.backend.session.state.q(), q)
            assert panel.message.startswith("expected a number in -160..160, got ")
        panel._annotate_chosen(SimpleNamespace(client=object(), target=SimpleNamespace(value="7")))
        assert viewer.backend.session.options.annotate_joint is None
        assert panel.message == "annotate joint: expected one of none, 1, 2, 3, 4, 5, 6, got '7'"
    finally:
        viewer.close()


def test_the_panel_buttons_cycle_and_draw_the_ik_branches_as_keys_b_and_shift_b() -> None:
    from types import SimpleNamespace

    from robot_sim.viewer.commands import COMMANDS
    from robot_sim.web.serve import WebViewer

    q = np.radians([30.0, 50.0, -100.0, 20.0, 30.0, -20.0])
    twin = ViewerSession(load_robot("puma560"))  # the same presses through the Qt-free commands
    twin.set_q(q)
    session = ViewerSession(load_robot("puma560"))
    session.set_q(q)
    viewer = WebViewer(session, "puma560", host="127.0.0.1", port=None)
    panel, click = viewer.panel, SimpleNamespace(client=object())
    try:
        for _ in range(3):
            panel._branch_clicked(click)
            assert panel.message == COMMANDS["cycle_branch"](twin, None)
            assert panel.message.startswith("IK branch ")
            np.testing.assert_array_equal(session.state.q_des(), twin.state.q_des())
        panel._branches_clicked(click)
        assert panel.message == COMMANDS["toggle_all_branches"](twin, None)
        viewer.backend.refresh()
        labels = [h for h in viewer.backend.view._labels["/ghost/labels"] if h.visible]
        names = [name for _, name in session.scene().branches]
        assert sorted(line for h in labels for line in h.text.split("\n")) == sorted(names)
        assert len(names) == len(twin.branches.solutions) >= 2
    finally:
        viewer.close()


def test_labels_at_one_anchor_are_written_as_one() -> None:
    """The browser does not move labels apart: a branch and its wrist flip, labelled at
    the same elbow, become one label of two lines; labels elsewhere stay as they are."""
    from robot_sim.web.scene import merged_labels

    elbow, other = np.array([0.3, 0.1, 0.5]), np.array([0.3, 0.1, 0.6])
    labels = [(elbow, "elbow up, wrist not flipped"), (other, "elbow down"), (elbow + 1e-9, "elbow up, wrist flipped")]
    merged = merged_labels(labels)
    assert [text for _, text in merged] == ["elbow up, wrist not flipped\nelbow up, wrist flipped", "elbow down"]
    np.testing.assert_array_equal(merged[0][0], elbow)
    np.testing.assert_array_equal(merged[1][0], other)


def test_a_value_the_page_sent_survives_a_tick_before_its_handler_runs() -> None:
    """viser stores a page's new value in the widget, then runs the handler on another
    thread; the server's tick may run in between.  It must not put the session's old value
    back (the handler would then see no change and the click would be lost, as a loaded
    machine showed in the browser tests), yet it still shows a change of the session."""
    from types import SimpleNamespace

    from robot_sim.web.serve import WebViewer

    viewer = WebViewer(ViewerSession(load_robot("puma560")), "puma560", host="127.0.0.1", port=None)
    panel, session = viewer.panel, viewer.backend.session
    try:
        panel.tick()
        panel.target_box.value = True  # what the page sent, its handler not yet run
        panel.sliders[0].value = 40.0
        panel.tick()
        assert panel.target_box.value is True and panel.sliders[0].value == 40.0
        page = object()
        panel._target_toggled(SimpleNamespace(client=page, target=panel.target_box))
        panel._slider_moved(SimpleNamespace(client=page, target=panel.sliders[0]), 0)
        assert session.target_tf is not None
        assert session.state.q_des()[0] == pytest.approx(np.radians(40.0))
        session.toggle_target()  # the session changes on its own (a key, another page): shown
        panel.tick()
        assert panel.target_box.value is False
        shown = panel.sliders[0].value
        panel.sliders[0].value = 170.0  # beyond the slider's range: refused, then the session's value shown
        panel.tick()
        assert panel.sliders[0].value == 170.0  # not yet handled
        panel._slider_moved(SimpleNamespace(client=page, target=panel.sliders[0]), 0)
        assert panel.message == "expected a number in -160..160, got '170.0'"
        panel.tick()
        assert panel.sliders[0].value == shown
    finally:
        viewer.close()
