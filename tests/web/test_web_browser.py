"""The browser view in a real browser (Debian's chromium, headless, every host but
127.0.0.1 blocked; tests/browser_helpers.py): the page loads with no request leaving the
machine, the arm is drawn where the camera projects it, a slider, the gizmo and the pick
timeline move it, a bad DH edit is refused with the window's message, and the exported
page plays from file://.  Screenshots go to /work/wt/web-shots/ for the closing note."""
from __future__ import annotations

import io
import time
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from browser_helpers import (
    SHOTS,
    Served,
    Traffic,
    browser,  # noqa: F401 - the fixture
    playwright_driver,  # noqa: F401 - the fixture
    canvas_box,
    click_at_fraction,
    connected,
    control,
    open_page,
    settled_capture,
    wait_until,
)
from robot_sim.graphics.robot_parts import dh_segments
from robot_sim.io.robot_file import load_robot
from robot_sim.viewer.dh_table import edit_cell
from robot_sim.viewer.pick_demo import plan_for
from robot_sim.viewer.session import ViewerSession

ARM_DIFF_TOL = 24  # RGB levels: a pixel the arm covers in one picture and not in the other


def _session(robot: str = "puma560", theme: str = "dark", annotate: int | None = 2) -> ViewerSession:
    session = ViewerSession(load_robot(robot), aspect=1.5)
    session.options.look, session.options.theme, session.options.annotate_joint = "dh", theme, annotate
    session.fit_camera()
    return session


def _shot(page, name: str) -> None:
    SHOTS.mkdir(parents=True, exist_ok=True)
    page.screenshot(path=str(SHOTS / name))


def _canvas_pixels(page) -> np.ndarray:
    """The page's first canvas as an (H, W, 3) uint8 array (a screenshot of the page clipped
    to the canvas: a third of the time of the element's own screenshot, which waits for
    the element to hold still)."""
    shot = page.screenshot(clip=page.locator("canvas").first.bounding_box())
    return np.asarray(Image.open(io.BytesIO(shot)).convert("RGB"))


def _arm_points(session: ViewerSession, per_segment: int = 12) -> np.ndarray:
    """World points (k, 3) along the arm's DH segments past joint 1's column (inside its
    drawn links) and at joints 2..n: what turning joint 1 moves."""
    seg = dh_segments(session.kin.frames, session.robot.is_modified)
    t = np.linspace(0.1, 0.9, per_segment)[:, None, None]
    pieces = []
    for start, end in ((seg.axis_start[1:], seg.axis_end[1:]), (seg.offset_start, seg.offset_end)):
        long_enough = np.linalg.norm(end - start, axis=1) > 0.05
        pieces.append((start + t * (end - start))[:, long_enough].reshape(-1, 3))
    return np.concatenate([*pieces, seg.joint[1:]])


def test_the_page_loads_with_nothing_leaving_the_machine(browser) -> None:
    served = Served(_session(), "puma560")
    traffic = Traffic()
    try:
        page = open_page(browser, served.viewer.url, traffic)
        connected(page, served.viewer.backend)
        image = settled_capture(served.viewer.backend)
        assert image.std() > 10, "the page draws the scene"
        time.sleep(2.0)  # anything fetched late (fonts, decoders, environment maps) would show now
        _shot(page, "puma_dh_annotation_dark.png")
        page.close()
    finally:
        served.close()
    assert traffic.requests, "the page was requested through the recorder"
    assert traffic.blocked == [], f"requests that would leave the machine: {traffic.blocked}"


def test_light_theme_screenshot(browser) -> None:
    served = Served(_session(theme="light"), "puma560")
    try:
        page = open_page(browser, served.viewer.url, Traffic())
        connected(page, served.viewer.backend)
        image = settled_capture(served.viewer.backend)
        assert image[5:40, 5:40].mean() > 200, "the light theme's background is light"
        _shot(page, "puma_dh_annotation_light.png")
        page.close()
    finally:
        served.close()


def test_the_arm_is_drawn_where_the_camera_projects_it(browser) -> None:
    session = _session(annotate=None)
    session.options.show_frames = [False] * session.n_frames  # nothing but the arm near it
    served = Served(session, "puma560")
    backend = served.viewer.backend
    try:
        page = open_page(browser, backend.url, Traffic())
        connected(page, backend)
        q = session.state.q()
        shown = settled_capture(backend)
        points = _arm_points(session)
        with backend.lock:
            session.set_q(q + np.r_[np.pi, np.zeros(len(q) - 1)])  # turned away: what was arm is floor now
        away = settled_capture(backend)
        page.close()
    finally:
        served.close()
    width, height = backend.size
    arm = np.abs(shown.astype(int) - away.astype(int)).max(axis=-1) > ARM_DIFF_TOL
    pixels = session.camera.project(points, width, height)
    inside = (pixels[:, 0] >= 0) & (pixels[:, 0] < width) & (pixels[:, 1] >= 0) & (pixels[:, 1] < height)
    assert inside.all(), "the fitted camera sees the whole arm"
    hits = arm[np.rint(pixels[:, 1]).astype(int), np.rint(pixels[:, 0]).astype(int)]
    assert hits.mean() > 0.9, f"{hits.mean():.0%} of the arm's points land on drawn arm pixels"
    shifted = np.rint(pixels + [0.0, 0.15 * height]).astype(int)  # the same points a little lower: mostly off the arm
    keep = (shifted[:, 1] < height)
    assert arm[shifted[keep, 1], shifted[keep, 0]].mean() < 0.6


def test_a_slider_moves_the_arm(browser) -> None:
    served = Served(_session(annotate=None), "puma560")
    backend = served.viewer.backend
    try:
        page = open_page(browser, backend.url, Traffic())
        connected(page, backend)
        before_q, before = served.session.state.q(), settled_capture(backend)
        click_at_fraction(page, "q1 [°]", 0.85)  # -160..160 degrees: about +112
        wait_until(lambda: abs(served.session.state.q()[0] - before_q[0]) > 1.0, what="joint 1 to follow the slider")
        wait_until(lambda: not served.session.moving(), what="the arm to arrive")
        after = settled_capture(backend)
        page.close()
    finally:
        served.close()
    expected = np.radians(-160 + 0.85 * 320)
    assert served.session.state.q()[0] == pytest.approx(expected, abs=np.radians(4))
    assert np.allclose(served.session.state.q()[1:], before_q[1:])
    moved = np.abs(after.astype(int) - before.astype(int)).max(axis=-1) > ARM_DIFF_TOL
    assert moved.mean() > 0.01, "the picture changed where the arm moved"


def test_dragging_the_gizmo_makes_the_tool_follow(browser) -> None:
    session = _session(annotate=None)
    served = Served(session, "puma560")
    backend = served.viewer.backend
    try:
        page = open_page(browser, backend.url, Traffic())
        connected(page, backend)
        control(page, "IK target").check()
        wait_until(lambda: served.session.target_tf is not None, what="the IK target")
        wait_until(lambda: served.viewer.panel._gizmo is not None, what="the gizmo")
        time.sleep(1.0)
        start_target = served.session.target_tf.t().copy()
        start_tool = served.session.kin.endeff_tf.t().copy()
        box = canvas_box(page)
        camera = served.session.camera
        from robot_sim.web.panel import GIZMO_SCALE_FRAC
        from robot_sim.graphics.robot_parts import robot_reach

        scale = GIZMO_SCALE_FRAC * robot_reach(served.session.robot)
        # grab the gizmo's x arrow (the target's own x axis) 60 % along it and pull it outwards
        axis = served.session.target_tf.R()[:, 0].copy()
        ends = camera.project(np.array([start_target + 0.6 * scale * axis, start_target + 0.8 * scale * axis]),
                              int(box["width"]), int(box["height"]))
        grab = ends[0] + [box["x"], box["y"]]
        out = (ends[1] - ends[0]) / np.linalg.norm(ends[1] - ends[0])
        page.mouse.move(*grab)
        page.mouse.down()
        for k in range(1, 11):
            page.mouse.move(*(grab + out * 5 * k))
            time.sleep(0.05)
        page.mouse.up()
        wait_until(lambda: (served.session.target_tf.t() - start_target) @ axis > 0.01, what="the target to move")
        wait_until(lambda: not served.session.moving(), what="the arm to follow")
        _shot(page, "puma_gizmo_dragged.png")
        page.close()
    finally:
        served.close()
    target, tool = served.session.target_tf.t(), served.session.kin.endeff_tf.t()
    moved = target - start_target
    assert moved @ axis > 0.01 and np.linalg.norm(moved - (moved @ axis) * axis) < 0.1 * (moved @ axis), \
        "the target moved along the dragged arrow"
    assert served.session.target_reachable
    assert np.linalg.norm(tool - target) < 1e-3, "the tool sits on the dragged target"
    assert (tool - start_tool) @ axis > 0.01


def test_the_timeline_scrubs_the_pick_task(browser) -> None:
    robot = load_robot("ur5")
    session = ViewerSession(robot, aspect=1.5)
    session.start_pick(plan_for(robot, None))
    session.pick.playing = False
    served = Served(session, "ur5")
    backend = served.viewer.backend
    try:
        page = open_page(browser, backend.url, Traffic())
        connected(page, backend)
        start = settled_capture(backend)
        duration = served.session.pick.duration
        click_at_fraction(page, "time [s]", 0.55)
        wait_until(lambda: served.session.pick.time > 0.3 * duration, what="the pick task to be scrubbed")
        t = served.session.pick.time
        phase = served.session.pick.plan.phase_at(t)
        wait_until(lambda: page.get_by_text(f"at {t:.2f} s of {duration:.2f} s").count() > 0, what="the phase line")
        assert page.get_by_text(phase, exact=True).count() > 0
        middle = settled_capture(backend)
        _shot(page, "ur5_pick_mid_transport.png")
        page.close()
    finally:
        served.close()
    assert t == pytest.approx(0.55 * duration, abs=0.05 * duration)
    expected_q = served.session.pick.plan.trajectory.evaluate(served.session.pick.plan.trajectory.t[0] + t)[0]
    assert np.allclose(served.session.state.q(), expected_q)
    assert (np.abs(middle.astype(int) - start.astype(int)).max(axis=-1) > ARM_DIFF_TOL).mean() > 0.01


def test_a_bad_dh_edit_is_refused_with_the_windows_message(browser) -> None:
    served = Served(_session(annotate=None), "puma560")
    backend = served.viewer.backend
    robot = served.session.robot
    try:
        page = open_page(browser, backend.url, Traffic())
        connected(page, backend)
        page.get_by_text("DH table", exact=True).click()
        box = control(page, "2 a [m]")
        box.fill("0.4x")
        with pytest.raises(ValueError) as window_says:
            edit_cell(robot, 1, "a", "0.4x")
        message = f"refused: {window_says.value}"
        wait_until(lambda: page.get_by_text(message, exact=True).count() > 0, what="the refusal on the page")
        assert served.session.robot is robot, "nothing changed"
        box.fill("0.5")
        wait_until(lambda: served.session.robot.dh_a[1] == 0.5, what="the accepted edit")
        time.sleep(1.0)
        _shot(page, "puma_dh_table_edited.png")
        page.close()
    finally:
        served.close()


def test_the_exported_page_plays_from_a_file(browser, tmp_path: Path) -> None:
    from robot_sim.web.export import export_html

    robot = load_robot("ur5")
    session = ViewerSession(robot, aspect=1.5)
    session.start_pick(plan_for(robot, None))
    path = export_html(session, tmp_path / "pick.html")
    traffic = Traffic()
    page = open_page(browser, path.as_uri(), traffic)
    try:
        wait_until(lambda: page.locator("canvas").count() > 0, what="the page's canvas")
        shots: list[np.ndarray] = []
        wait_until(lambda: shots.append(_canvas_pixels(page)) or shots[-1].std() > 10, what="the scene drawn")
        drawn = shots[-1]
        wait_until(lambda: not np.array_equal(_canvas_pixels(page), drawn), timeout=30.0, what="the motion to play")
        pause = page.locator("button").filter(has=page.locator("svg")).first
        assert pause.count() == 1
        _shot(page, "ur5_pick_export_file.png")
    finally:
        page.close()
    assert traffic.blocked == [] and all(u.split(":")[0] in ("file", "blob", "data") for u in traffic.requests)


def test_every_tab_sees_the_same_session(browser) -> None:
    served = Served(_session(annotate=None), "puma560")
    backend = served.viewer.backend
    try:
        first, second = (open_page(browser, backend.url, Traffic()) for _ in range(2))
        connected(first, backend)
        connected(second, backend)
        wait_until(lambda: len(backend.server.get_clients()) == 2, what="both tabs")
        first.bring_to_front()  # the tab opened last is in front; chromium throttles the other
        click_at_fraction(first, "q2 [°]", 0.8)
        wait_until(lambda: not served.session.moving() and abs(served.session.state.q()[1] - np.radians(45)) > 0.1,
                   what="joint 2 to follow the first tab's slider")
        shown = np.degrees(served.session.state.q()[1])
        thumb = control(second, "q2 [°]").get_by_role("slider")
        wait_until(lambda: abs(float(thumb.get_attribute("aria-valuenow")) - shown) < 0.2,
                   what="the second tab's slider to show the new value")
        first.close()
        second.close()
    finally:
        served.close()


def test_a_robot_switch_asks_about_unsaved_edits(browser) -> None:
    served = Served(_session(annotate=None), "puma560")
    backend = served.viewer.backend
    try:
        page = open_page(browser, backend.url, Traffic())
        connected(page, backend)
        page.get_by_text("DH table", exact=True).click()
        control(page, "2 a [m]").fill("0.5")
        wait_until(lambda: served.session.robot.dh_a[1] == 0.5, what="the edit")
        edited = served.session.robot

        def choose_ur5() -> None:
            control(page, "robot").click()
            page.get_by_role("option", name="ur5", exact=True).click()

        question = f"{edited.name} has unsaved edits. Save them before switching to ur5?"
        choose_ur5()
        page.get_by_text(question, exact=True).wait_for()
        page.get_by_role("button", name="Cancel", exact=True).click()
        wait_until(lambda: page.get_by_text(question, exact=True).count() == 0, what="the question to close")
        time.sleep(1.0)
        assert served.session.robot is edited, "Cancel keeps the robot and its edits"
        choose_ur5()
        page.get_by_text(question, exact=True).wait_for()
        page.get_by_role("button", name="Discard", exact=True).click()
        wait_until(lambda: served.session.robot.name == "UR5", what="the switch after Discard")
        page.close()
    finally:
        served.close()
