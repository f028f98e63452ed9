"""Everything fits (xvfb): at 1280x800 and at 1024x768 no widget of the window is cut
off on the right or at the bottom, what is taller than its dock scrolls, the timeline
and the plots keep their width, the θ column never elides a value, and ``--size`` sizes
pictures, not the window."""
from __future__ import annotations

import functools
from typing import Any, Iterator

import numpy as np
import pytest

from test_window import app  # noqa: F401 - the QApplication fixture

from PyQt5.QtCore import QRect  # noqa: E402
from PyQt5.QtTest import QTest  # noqa: E402
from PyQt5.QtWidgets import QAbstractItemView, QAbstractScrollArea, QApplication, QDockWidget, QWidget  # noqa: E402

from robot_sim.app import output, prepare  # noqa: E402
from robot_sim.qt import window as viewer_window  # noqa: E402
from robot_sim.qt.pick_panel import TIMELINE_MIN_WIDTH_PX  # noqa: E402
from robot_sim.viewer.dh_table import COLUMNS, variable_column  # noqa: E402
from robot_sim.viewer.units import display_range, display_scale  # noqa: E402

pytestmark = pytest.mark.window

SIZES = [(1280, 800), (1024, 768)]
CASES = [
    ("--robot", "panda", "--motion", "ct"),
    ("--robot", "humanoid7", "--demo", "pick", "--motion", "ct"),  # the tallest plots: four rows
    ("--robot", "puma560"),
]


@functools.lru_cache(maxsize=None)
def config(*args: str) -> Any:
    """The validated command line (a simulated pick run takes seconds: made once)."""
    return prepare.prepare(list(args))


@pytest.fixture
def opened(app: QApplication) -> Iterator[Any]:  # noqa: F811
    windows: list[Any] = []

    def open_(*args: str, size: tuple[int, int]) -> Any:
        win = viewer_window.MainWindow(prepare.session_from_config(config(*args)), output.window_options(config(*args)))
        win.resize(*size)
        win.show()
        QTest.qWaitForWindowExposed(win)
        if win.session.pick is not None:
            win.timer.stop()
            win.session.pick.playing = False
        app.processEvents()
        windows.append(win)
        return win

    yield open_
    for win in windows:
        win.close()
        win.deleteLater()


def on_window(widget: QWidget, win: Any) -> QRect:
    return QRect(widget.mapTo(win, widget.rect().topLeft()), widget.size())


def scroller(widget: QWidget, win: Any) -> QAbstractScrollArea | None:
    """The scroll area whose viewport holds ``widget``, if any."""
    parent = widget.parentWidget()
    while parent is not None and parent is not win:
        if isinstance(parent, QAbstractScrollArea) and parent.viewport().isAncestorOf(widget):
            return parent
        parent = parent.parentWidget()
    return None


def cut_off(win: Any) -> list[str]:
    """Visible widgets that stick out of a parent: sideways anywhere, downwards unless a
    scroll area holds them and its scroll bar reaches their bottom."""
    bad = []
    docks = [d for d in win.findChildren(QDockWidget) if d.isVisible()]
    tabbed_away = [d for d in docks if not win.rect().intersects(d.geometry())]  # behind another dock's tab
    for widget in win.findChildren(QWidget):
        if not widget.isVisible() or widget.isWindow() or isinstance(widget.parentWidget(), QAbstractItemView):
            continue  # (an item view's own header and corner widgets are laid out by it)
        if any(d is widget or d.isAncestorOf(widget) for d in tabbed_away):
            continue
        rect, parent = on_window(widget, win), widget.parentWidget()
        inner = on_window(parent, win) if parent is not win else win.rect()
        name = f"{type(widget).__name__} {widget.objectName() or getattr(widget, 'text', lambda: '')()}"
        if rect.left() < inner.left() or rect.right() > inner.right():
            area = scroller(widget, win)
            if area is None or area.horizontalScrollBar().maximum() < rect.right() - inner.right():
                bad.append(f"{name}: x {rect.left()}..{rect.right()} outside {inner.left()}..{inner.right()}")
        if rect.top() < inner.top() - 1 or rect.bottom() > inner.bottom():
            area = scroller(widget, win)
            if area is None:
                bad.append(f"{name}: y {rect.top()}..{rect.bottom()} outside {inner.top()}..{inner.bottom()}")
            elif area.verticalScrollBar().maximum() < area.widget().height() - area.viewport().height() \
                    if hasattr(area, "widget") and area.widget() is not None else False:
                bad.append(f"{name}: its scroll area does not reach its bottom")
    return bad


@pytest.mark.parametrize("size", SIZES, ids=lambda s: f"{s[0]}x{s[1]}")
@pytest.mark.parametrize("args", CASES, ids=lambda a: "-".join(a[1::2]))
def test_nothing_is_cut_off(opened: Any, args: tuple[str, ...], size: tuple[int, int]) -> None:
    win = opened(*args, size=size)
    assert (win.width(), win.height()) == size
    assert cut_off(win) == []
    scroll = win.dock_scroll
    assert scroll.viewport().height() >= 0.6 * win.height()  # not a peephole onto 1.5 sliders
    for row in win.joints.rows:  # every joint row, Home and Zero reachable by scrolling
        scroll.ensureWidgetVisible(row.slider)
        assert scroll.viewport().rect().contains(QRect(row.slider.mapTo(scroll.viewport(), row.slider.rect().topLeft()),
                                                       row.slider.size()))
    for button in (win.joints.home_button, win.joints.zero_button):
        scroll.ensureWidgetVisible(button)
        assert not button.visibleRegion().isEmpty() and button.visibleRegion().boundingRect() == button.rect()
    if size == (1280, 800) and win.session.pick is None:
        assert scroll.verticalScrollBar().maximum() == 0  # at 1280x800 the dock needs no scrolling


@pytest.mark.parametrize("size", SIZES, ids=lambda s: f"{s[0]}x{s[1]}")
def test_the_pick_timeline_and_plots_keep_their_width(opened: Any, size: tuple[int, int]) -> None:
    win = opened("--robot", "humanoid7", "--demo", "pick", "--motion", "ct", size=size)
    assert win.pick_panel.slider.width() >= TIMELINE_MIN_WIDTH_PX
    graphics = win.plot_dock.graphics
    assert graphics.viewport().visibleRegion().boundingRect() == graphics.viewport().rect()
    scene = graphics.ci.mapRectToScene(graphics.ci.boundingRect())
    assert scene.width() <= graphics.viewport().width() + 1 and scene.height() <= graphics.viewport().height() + 1
    legend = win.plot_dock.legend.mapRectToScene(win.plot_dock.legend.boundingRect())
    assert legend.right() <= graphics.viewport().width()  # every joint's entry shows
    assert len(win.plot_dock.legend.items) == 7
    for key, plot in win.plot_dock.plots.items():
        if plot.isVisible():
            x_range = plot.viewRange()[0]
            assert x_range[1] >= win.session.pick.duration - 1e-9, key  # the whole task, to its end
    win.dh_dock.raise_()  # the DH table is the other tab, as wide
    app_ = QApplication.instance()
    app_.processEvents()
    assert win.dh_dock.isVisible() and win.dh_dock.width() == win.plot_dock.width()


@pytest.mark.parametrize("robot", ["puma560", "scara", "ur5"])
def test_the_joint_variable_column_never_elides(opened: Any, robot: str) -> None:
    win = opened("--robot", robot, size=(1024, 768))
    table, r = win.dh_dock.table, win.session.robot
    lo, hi = (np.asarray(v) / display_scale(r) for v in display_range(r))
    for q in (lo, hi):
        win.set_q(np.clip(q, r.q_min, r.q_max) if np.all(np.isfinite(r.q_min)) else q)
        for row in range(r.n_dofs):
            col = COLUMNS.index(variable_column(r, row))
            assert table.columnWidth(col) >= table.sizeHintForColumn(col), (row, table.item(row, col).text())


def test_size_sizes_pictures_not_the_window(app: QApplication) -> None:  # noqa: F811
    given = prepare.prepare(["--size", "320x240"])
    assert given.size == (320, 240)
    win = viewer_window.MainWindow(prepare.session_from_config(given), output.window_options(given))
    try:
        assert (win.width(), win.height()) == viewer_window.opening_size() == viewer_window.WINDOW_SIZE
    finally:
        win.close()
        win.deleteLater()


def test_status_texts_end_in_an_ellipsis_at_the_window_edge(opened: Any) -> None:
    win = opened("--robot", "puma560", "--motion", "pd", size=(1024, 768))
    win.timer.stop()
    win.session.toggle_target()
    win.session.move_target(translation=np.array([2.0, 0.0, 0.0]))  # unreachable: a long status line
    long_message = "ct: largest joint tracking error 0.00619 (joint 2), tool 0.125 mm; object placed " * 3
    win.message(long_message)
    win.refresh_status()
    QApplication.instance().processEvents()
    bar = win.statusBar()
    for label in (win.message_label, win.status):
        rect = on_window(label, win)
        assert win.rect().contains(rect) and bar.geometry().contains(rect)
        assert label.fontMetrics().horizontalAdvance(label.shown_text()) <= label.contentsRect().width()
        assert label.toolTip() == label.text()
    assert win.message_label.text() == long_message and win.message_label.shown_text().endswith("…")
    assert "IK target UNREACHABLE" in win.status.text()


def test_no_velocity_disc_on_a_resting_tool(opened: Any) -> None:
    from robot_sim.graphics import defs as gd
    from window_helpers import grab, project

    win = opened("--robot", "puma560", "--motion", "pd", "--duration", "1.5", size=(1024, 768))
    win.timer.stop()  # settling: a few mm/s at the tool
    speed = np.linalg.norm(win.session.kin.endeff_twist[:3])
    assert 0.0 < speed < 0.01
    image = grab(win)
    x, y = np.round(project(win, win.session.kin.endeff_tf.t())).astype(int)
    patch = image[max(y - 40, 0):y + 41, max(x - 40, 0):x + 41, :3].astype(int)
    for color in (gd.LINEAR_VELOCITY_COLOR, gd.ANGULAR_VELOCITY_COLOR):  # no orange or purple disc
        rgb = np.round(255 * np.asarray(color[:3]))
        assert np.count_nonzero(np.all(np.abs(patch - rgb) <= 50, axis=-1)) == 0, color
