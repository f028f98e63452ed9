"""The real window in tests: the QApplication fixture, opening a window, input and grabbing pixels
(shared by the window tests; they run under xvfb-run with ``-m window``)."""
from __future__ import annotations


import os
from pathlib import Path
from typing import Any, Iterator

import numpy as np
import pytest

from robot_sim.graphics import defs as gd
from robot_sim.graphics.themes import THEMES
from robot_sim.app import output, prepare
import simulator

if "OpenGL.platform" not in __import__("sys").modules:
    os.environ.pop("PYOPENGL_PLATFORM", None)  # the window needs GLX, not OSMesa

from PyQt5.QtCore import QEvent, QPoint, Qt  # noqa: E402
from PyQt5.QtGui import QImage, QMouseEvent  # noqa: E402
from PyQt5.QtTest import QTest  # noqa: E402
from PyQt5.QtWidgets import QApplication  # noqa: E402

from robot_sim.qt import window as viewer_window  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def app() -> QApplication:
    if not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")):
        pytest.fail("window tests need an X display: run them with xvfb-run (make test)")
    return QApplication.instance() or QApplication(["robot-sim-test"])


def open_window(app: QApplication, *args: str, size: tuple[int, int] = (900, 640)) -> Any:
    """The main window for command-line ``args``, ``size`` pixels, shown and focused."""
    config = prepare.prepare(list(args))
    window = viewer_window.MainWindow(prepare.session_from_config(config), output.window_options(config))
    window.resize(*size)
    window.show()
    window.activateWindow()
    window.view.setFocus()
    assert QTest.qWaitForWindowActive(window)
    return window


@pytest.fixture
def window(app: QApplication) -> Iterator[Any]:
    win = open_window(app)
    yield win
    win.close()
    win.deleteLater()


def grab(win: Any) -> np.ndarray:
    """The GL widget's picture (H, W, 4) RGBA, repainted now."""
    image = win.view.grabFramebuffer().convertToFormat(QImage.Format_RGBA8888)
    bits = image.constBits()
    bits.setsize(image.byteCount())
    return np.frombuffer(bits, np.uint8).reshape(image.height(), image.bytesPerLine() // 4, 4)[:, : image.width()].copy()


def grab_window(win: Any) -> np.ndarray:
    """The whole window with its child widgets (the help overlay), (H, W, 4) RGBA."""
    image = win.grab().toImage().convertToFormat(QImage.Format_RGBA8888)
    bits = image.constBits()
    bits.setsize(image.byteCount())
    return np.frombuffer(bits, np.uint8).reshape(image.height(), image.bytesPerLine() // 4, 4)[:, : image.width()].copy()


def press(app: QApplication, key: int, modifiers: Any = Qt.NoModifier) -> None:
    """A key press delivered to the focus widget, as the keyboard would."""
    focus = app.focusWidget()
    assert focus is not None
    QTest.keyClick(focus, key, modifiers)


def project(win: Any, point: np.ndarray) -> np.ndarray:
    """Pixel (x, y) of a world point in the GL widget."""
    width, height = win.view.pixel_size()
    return win.session.camera.project(np.asarray(point)[None, :], width, height)[0]


def near(image: np.ndarray, xy: np.ndarray, radius: int) -> np.ndarray:
    x, y = int(round(xy[0])), int(round(xy[1]))
    return image[max(y - radius, 0): y + radius + 1, max(x - radius, 0): x + radius + 1, :3].astype(int)


def dominant(pixels: np.ndarray, channel: int) -> int:
    """Number of pixels where ``channel`` is bright and clearly above the other two."""
    others = np.delete(pixels, channel, axis=-1)
    c = pixels[..., channel]
    return int(np.count_nonzero((c > 100) & (c > 2 * others.max(axis=-1))))


def robot_pixels(image: np.ndarray) -> int:
    """Pixels that are neither background (the dark theme's) nor floor: the colours making
    up at least 10 % of the bottom rows (a close-up's link may reach the top rows of a
    wide view; grid lines, shaded like the links, count as non-floor in both pictures)."""
    rgb = image[..., :3].astype(int)
    background = np.round(255 * np.asarray(THEMES["dark"].background[:3])).astype(int)
    colours, counts = np.unique(rgb[-4:].reshape(-1, 3), axis=0, return_counts=True)
    palette = np.concatenate([background[None], colours[counts >= 0.1 * counts.sum()]])
    distance = np.abs(rgb[:, :, None, :] - palette[None, None, :, :]).max(axis=-1).min(axis=-1)
    return int(np.count_nonzero(distance > 24))


def changed_pixels(a: np.ndarray, b: np.ndarray) -> int:
    return int(np.count_nonzero(np.any(a != b, axis=-1)))


def cyan_pixels(pixels: np.ndarray) -> int:
    """Pixels tinted by the translucent cyan ghost (GHOST_COLOR)."""
    r, g, b = pixels[..., 0], pixels[..., 1], pixels[..., 2]
    return int(np.count_nonzero((b > r + 40) & (g > r + 20)))


def is_red(image: np.ndarray, xy: np.ndarray) -> bool:
    return dominant(near(image, xy, 1), 0) >= 5


def drag(app: QApplication, widget: Any, start: QPoint, delta: QPoint, button: Any, modifiers: Any = Qt.NoModifier) -> None:
    """Press ``button`` at ``start``, move by ``delta`` with it held, release."""
    QTest.mousePress(widget, button, modifiers, start)
    app.sendEvent(widget, QMouseEvent(QEvent.MouseMove, start + delta, Qt.NoButton, button, modifiers))
    QTest.mouseRelease(widget, button, modifiers, start + delta)


def wait_until(condition: Any, limit_ms: int = 30000) -> None:
    waited = 0
    while not condition() and waited < limit_ms:
        QTest.qWait(20)
        waited += 20
    assert condition()
