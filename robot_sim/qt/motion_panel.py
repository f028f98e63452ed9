"""The dock's motion panel: the motion-mode chooser and one effort bar per joint.

The chooser lists control.MOTION_MODES (the window's ``Shift+M`` steps through it); the bars
show each joint's applied effort as a fraction of its effort limit (motion.Motion's
``effort_scale`` for a joint without one), red while the drive saturates, and a joint's
number flashes after it hits a joint limit.  Qt widgets only: the physics lives in
motion.py and robot_sim/control/simulation.py.
"""
from __future__ import annotations

import time
from typing import Any

import numpy as np
from PyQt5 import QtCore, QtWidgets
from PyQt5.QtCore import Qt

from robot_sim.qt import settings as qs
from robot_sim.control.controllers import MOTION_LABELS, MOTION_MODES


class MotionPanel(QtWidgets.QWidget):
    """Motion chooser (emits ``mode_chosen(mode)``) and per-joint effort bars."""

    mode_chosen = QtCore.pyqtSignal(str)

    def __init__(self) -> None:
        super().__init__()
        layout = QtWidgets.QVBoxLayout(self)
        layout.setContentsMargins(0, 0, 0, 0)
        self.combo = QtWidgets.QComboBox()
        for mode in MOTION_MODES:
            self.combo.addItem(MOTION_LABELS[mode], mode)
        self.combo.setFocusPolicy(Qt.NoFocus)
        self.combo.currentIndexChanged.connect(lambda index: self.mode_chosen.emit(MOTION_MODES[index]))
        layout.addWidget(self.combo)
        self.title = QtWidgets.QLabel("Joint effort (of limit)")
        layout.addWidget(self.title)
        self.effort_box = QtWidgets.QWidget()
        self.grid = QtWidgets.QGridLayout(self.effort_box)
        self.grid.setVerticalSpacing(1)
        layout.addWidget(self.effort_box)
        self.bars: list[QtWidgets.QProgressBar] = []
        self.labels: list[QtWidgets.QLabel] = []
        self.flash_until: dict[int, float] = {}  # joint -> monotonic time its flash ends

    def set_robot(self, n_joints: int) -> None:
        """One bar per joint."""
        while self.grid.count():
            self.grid.takeAt(0).widget().deleteLater()
        self.bars, self.labels, self.flash_until = [], [], {}
        for i in range(n_joints):
            label = QtWidgets.QLabel(f"{i + 1}")
            bar = QtWidgets.QProgressBar()
            bar.setRange(0, qs.EFFORT_BAR_STEPS)
            bar.setFixedHeight(qs.EFFORT_BAR_HEIGHT_PX)
            self.grid.addWidget(label, i, 0)
            self.grid.addWidget(bar, i, 1)
            self.labels.append(label)
            self.bars.append(bar)

    def show_mode(self, mode: str) -> None:
        """Select ``mode`` without emitting; show the bars only in physical modes."""
        self.combo.blockSignals(True)
        self.combo.setCurrentIndex(MOTION_MODES.index(mode))
        self.combo.blockSignals(False)
        physical = mode != "kinematic"
        self.title.setVisible(physical)
        self.effort_box.setVisible(physical)

    def flash(self, joint: int) -> None:
        """Flash joint ``joint``'s number (it hit a limit)."""
        self.flash_until[joint] = time.monotonic() + qs.LIMIT_FLASH_MS / 1000.0

    def sync(self, motion: Any | None) -> None:
        """Bars from ``motion`` (a motion.Motion, or None in kinematic mode) and flashes."""
        now = time.monotonic()
        for i, label in enumerate(self.labels):
            flashing = self.flash_until.get(i, 0.0) > now
            _restyle(label, f"color: {qs.LIMIT_FLASH_COLOR}; font-weight: bold" if flashing else "")
        if motion is None or not motion.physical:
            return
        fraction = motion.effort_fraction()
        saturated = motion.sim.saturated
        for i, bar in enumerate(self.bars):
            bar.setValue(round(min(abs(fraction[i]), 1.0) * qs.EFFORT_BAR_STEPS))
            bar.setFormat(qs.EFFORT_BAR_FORMAT.format(percent=100.0 * fraction[i]))
            color = qs.EFFORT_BAR_SATURATED_COLOR if saturated[i] else qs.EFFORT_BAR_COLOR
            _restyle(bar, f"QProgressBar::chunk {{ background: {color}; }}")

    def fractions(self) -> np.ndarray:
        """The bars' values as fractions (for tests and screenshots)."""
        return np.array([bar.value() / qs.EFFORT_BAR_STEPS for bar in self.bars])


def _restyle(widget: QtWidgets.QWidget, style: str) -> None:
    """Set ``style`` only when it changes: Qt re-polishes a widget on every setStyleSheet,
    about 0.2 ms a tick for seven joints."""
    if widget.styleSheet() != style:
        widget.setStyleSheet(style)
