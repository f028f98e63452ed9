"""The joint panel of the window: per joint a slider with its limits written at its ends,
a box to type the value and, in the physical motion modes, a bar of the joint's effort
beside its name, plus Home and Zero buttons.

Values are shown in degrees (revolute) and metres (prismatic); the signals carry SI
values (radians, metres).  The panel holds no state of its own beyond the robot it was
built for: :meth:`JointPanel.show_q` puts the session's q on the widgets without echoing
signals back.  Effort bars show each joint's applied effort as a fraction of its effort
limit (motion.Motion's ``effort_scale`` for a joint without one), red while the drive
saturates; a joint's name flashes after it hits a joint limit.

Keys and the wheel: a box is being edited while it has the keyboard focus (a click in
its text); Enter commits, Esc restores the shown value, and either, like a click on its
arrows, hands the keyboard back (``edit_finished``) so single-key shortcuts never type
into it.  The wheel over a slider or an unfocused box scrolls the panel instead of
moving a joint.
"""
from __future__ import annotations

import functools
import math
import time
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray
from PyQt5 import QtCore, QtGui, QtWidgets
from PyQt5.QtCore import Qt

from robot_sim.qt import settings as qs
from robot_sim.model.params import JTYPE_PRISMATIC, RobotParams
from robot_sim.viewer.units import display_range, display_scale, wrap_display

if TYPE_CHECKING:
    from robot_sim.viewer.motion import Motion


class JointBox(QtWidgets.QDoubleSpinBox):
    """A joint's typed value: ``finished`` after Enter, Esc (which restores the value
    shown before the edit) or a click on its arrows."""

    finished = QtCore.pyqtSignal()

    def keyPressEvent(self, event: QtGui.QKeyEvent) -> None:
        if event.key() == Qt.Key_Escape:
            self.blockSignals(True)
            self.setValue(self.value())  # the typed text goes: value() is still the one shown before
            self.blockSignals(False)
            self.finished.emit()
            return
        super().keyPressEvent(event)
        if event.key() in (Qt.Key_Return, Qt.Key_Enter):
            self.finished.emit()

    def mouseReleaseEvent(self, event: QtGui.QMouseEvent) -> None:
        super().mouseReleaseEvent(event)
        option = QtWidgets.QStyleOptionSpinBox()
        self.initStyleOption(option)
        hit = self.style().hitTestComplexControl(QtWidgets.QStyle.CC_SpinBox, option, event.pos(), self)
        if hit in (QtWidgets.QStyle.SC_SpinBoxUp, QtWidgets.QStyle.SC_SpinBoxDown):
            self.finished.emit()  # a step, not typing: the keys go back to the shortcuts

    def wheelEvent(self, event: QtGui.QWheelEvent) -> None:
        if self.hasFocus():
            super().wheelEvent(event)
        else:
            event.ignore()  # to the scroll area around the panel


class JointSlider(QtWidgets.QSlider):
    """A joint's slider: dragged or clicked, never turned by the wheel (that scrolls)."""

    def wheelEvent(self, event: QtGui.QWheelEvent) -> None:
        event.ignore()


class JointRow:
    """The widgets of one joint: name, spin box, slider and its two limit labels."""

    def __init__(self, robot: RobotParams, joint: int, layout: QtWidgets.QGridLayout) -> None:
        prismatic = bool(robot.jtype[joint] == JTYPE_PRISMATIC)
        self.ticks = qs.SLIDER_TICKS_PER_M if prismatic else qs.SLIDER_TICKS_PER_DEG
        lo, hi = (float(v[joint]) for v in display_range(robot))
        unit = qs.JOINT_UNIT_PRISMATIC if prismatic else qs.JOINT_UNIT_REVOLUTE
        limited = math.isfinite(robot.q_min[joint]) or math.isfinite(robot.q_max[joint])
        self.name = QtWidgets.QLabel(f"joint {joint + 1}" + ("" if limited else qs.JOINT_UNLIMITED_MARK))
        self.effort = QtWidgets.QProgressBar()
        self.effort.setRange(0, qs.EFFORT_BAR_STEPS)
        self.effort.setFixedHeight(qs.EFFORT_BAR_HEIGHT_PX)
        self.effort.setToolTip(f"joint {joint + 1}'s effort, percent of its effort limit")
        self.effort.hide()
        self.head = QtWidgets.QWidget()  # the name and, in physical modes, the effort bar
        head = QtWidgets.QHBoxLayout(self.head)
        head.setContentsMargins(0, 0, 0, 0)
        head.addWidget(self.name)
        head.addWidget(self.effort, 1)
        self.box = JointBox()
        self.box.setDecimals(qs.JOINT_BOX_DECIMALS_PRISMATIC if prismatic else qs.JOINT_BOX_DECIMALS_REVOLUTE)
        self.box.setRange(lo, hi)
        self.box.setSingleStep(1.0 / self.ticks * 10)
        self.box.setSuffix(unit)
        self.box.setKeyboardTracking(False)  # valueChanged on Enter or focus out, not per digit
        self.box.setToolTip(f"type a value in [{lo:g}, {hi:g}]{unit} and press Enter")
        self.slider = JointSlider(Qt.Horizontal)
        self.slider.setFocusPolicy(Qt.NoFocus)
        self.slider.setRange(math.floor(lo * self.ticks), math.ceil(hi * self.ticks))
        self.low = QtWidgets.QLabel(f"{lo:g}{unit}")
        self.high = QtWidgets.QLabel(f"{hi:g}{unit}")
        for label in (self.low, self.high):
            label.setStyleSheet(qs.JOINT_LIMIT_LABEL_STYLE)
        row = 2 * joint
        layout.addWidget(self.head, row, 0, 1, 2)
        layout.addWidget(self.box, row, 2)
        layout.addWidget(self.low, row + 1, 0)
        layout.addWidget(self.slider, row + 1, 1)
        layout.addWidget(self.high, row + 1, 2, Qt.AlignLeft)

    def widgets(self) -> tuple[QtWidgets.QWidget, ...]:
        return self.head, self.box, self.slider, self.low, self.high

    def show_value(self, value: float) -> None:
        """Put ``value`` (display units) on the box and the slider without signals."""
        for widget, shown in ((self.box, value), (self.slider, round(value * self.ticks))):
            widget.blockSignals(True)
            widget.setValue(shown)
            widget.blockSignals(False)


class JointPanel(QtWidgets.QWidget):
    """Sliders and boxes for every joint, Home and Zero.

    ``joint_moved(joint, value)`` carries one joint's new value (rad or m) from a slider
    or a box; ``q_requested(q)`` a whole joint vector (n,) from Home or Zero;
    ``edit_finished()`` when a box hands the keyboard back.
    """

    joint_moved = QtCore.pyqtSignal(int, float)
    q_requested = QtCore.pyqtSignal(object)
    edit_finished = QtCore.pyqtSignal()

    def __init__(self, parent: QtWidgets.QWidget | None = None) -> None:
        super().__init__(parent)
        self.robot: RobotParams | None = None
        self.rows: list[JointRow] = []
        self.flash_until: dict[int, float] = {}  # joint -> monotonic time its flash ends
        outer = QtWidgets.QVBoxLayout(self)
        outer.setContentsMargins(0, 0, 0, 0)
        self.grid = QtWidgets.QGridLayout()
        self.grid.setVerticalSpacing(1)
        self.grid.setColumnStretch(1, 1)
        outer.addLayout(self.grid)
        buttons = QtWidgets.QHBoxLayout()
        self.home_button = QtWidgets.QPushButton("Home")
        self.home_button.setToolTip("every joint to its home value from the robot file")
        self.zero_button = QtWidgets.QPushButton("Zero")
        self.zero_button.setToolTip("every joint to 0 (the nearest limit where 0 is outside it)")
        for button in (self.home_button, self.zero_button):
            button.setFocusPolicy(Qt.NoFocus)
            buttons.addWidget(button)
        outer.addLayout(buttons)
        outer.addStretch(1)
        self.home_button.clicked.connect(lambda: self.q_requested.emit(np.array(self.robot.q_home)))
        self.zero_button.clicked.connect(
            lambda: self.q_requested.emit(np.clip(np.zeros(self.robot.n_dofs), self.robot.q_min, self.robot.q_max))
        )

    def set_robot(self, robot: RobotParams) -> None:
        """Rebuild the rows for ``robot``."""
        for row in self.rows:
            for widget in row.widgets():
                self.grid.removeWidget(widget)
                widget.deleteLater()
        self.robot = robot
        self.flash_until = {}
        self.rows = [JointRow(robot, i, self.grid) for i in range(robot.n_dofs)]
        for i, row in enumerate(self.rows):
            row.slider.valueChanged.connect(functools.partial(self._slider_moved, i))
            row.box.valueChanged.connect(functools.partial(self._box_changed, i))
            row.box.finished.connect(self.edit_finished.emit)

    def show_q(self, q: NDArray[np.float64]) -> None:
        """Show joint values ``q`` (SI, (n,)) on the rows."""
        for row, value in zip(self.rows, wrap_display(self.robot, q)):
            row.show_value(float(value))

    def _slider_moved(self, joint: int, ticks: int) -> None:
        self._emit(joint, ticks / self.rows[joint].ticks)

    def _box_changed(self, joint: int, value: float) -> None:
        self._emit(joint, value)

    def _emit(self, joint: int, display_value: float) -> None:
        self.joint_moved.emit(joint, display_value / float(display_scale(self.robot)[joint]))

    # ---- effort bars (physical motion modes) ----
    def show_efforts(self, shown: bool) -> None:
        """Show the effort bars (physical modes) or hide them (kinematic)."""
        for row in self.rows:
            row.effort.setVisible(shown)

    def flash(self, joint: int) -> None:
        """Flash joint ``joint``'s name (it hit a limit)."""
        self.flash_until[joint] = time.monotonic() + qs.LIMIT_FLASH_MS / 1000.0

    def sync_efforts(self, motion: Motion | None) -> None:
        """Bars from ``motion`` (a motion.Motion, or None in kinematic mode) and flashes."""
        now = time.monotonic()
        for i, row in enumerate(self.rows):
            flashing = self.flash_until.get(i, 0.0) > now
            _restyle(row.name, f"color: {qs.LIMIT_FLASH_COLOR}; font-weight: bold" if flashing else "")
        if motion is None or not motion.physical:
            return
        fraction = motion.effort_fraction()
        saturated = motion.sim.saturated
        for i, row in enumerate(self.rows):
            row.effort.setValue(round(min(abs(fraction[i]), 1.0) * qs.EFFORT_BAR_STEPS))
            row.effort.setFormat(qs.EFFORT_BAR_FORMAT.format(percent=100.0 * fraction[i]))
            color = qs.EFFORT_BAR_SATURATED_COLOR if saturated[i] else qs.EFFORT_BAR_COLOR
            _restyle(row.effort, f"QProgressBar::chunk {{ background: {color}; }}")

    def effort_fractions(self) -> NDArray[np.float64]:
        """The bars' values (n,) as fractions of the effort limits (for tests and screenshots)."""
        return np.array([row.effort.value() / qs.EFFORT_BAR_STEPS for row in self.rows])


def _restyle(widget: QtWidgets.QWidget, style: str) -> None:
    """Set ``style`` only when it changes: Qt re-polishes a widget on every setStyleSheet,
    about 0.2 ms a tick for seven joints."""
    if widget.styleSheet() != style:
        widget.setStyleSheet(style)
