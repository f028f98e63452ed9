"""The window's right dock: the robot chooser, the motion chooser, the joint sliders and
boxes, the endeffector readout and the frame list, in one column that scrolls as a whole."""
from __future__ import annotations

from PyQt5 import QtCore, QtGui, QtWidgets
from PyQt5.QtCore import Qt

from robot_sim.graphics import GraphicsOptions
from robot_sim.io.robot_file import available_robots
from robot_sim.qt import settings as qs
from robot_sim.qt.joints import JointPanel
from robot_sim.qt.motion_panel import MotionPanel


class ColumnScroll(QtWidgets.QScrollArea):
    """A vertical scroll area never narrower than its content plus the scroll bar: its
    column scrolls up and down, and nothing is cut off on the right."""

    def setWidget(self, widget: QtWidgets.QWidget) -> None:  # noqa: N802 - Qt's name
        super().setWidget(widget)
        widget.installEventFilter(self)  # its layout changing changes this minimum

    def eventFilter(self, obj: QtCore.QObject, event: QtCore.QEvent) -> bool:  # noqa: N802 - Qt's name
        if obj is self.widget() and event.type() == QtCore.QEvent.LayoutRequest:
            self.updateGeometry()
        return super().eventFilter(obj, event)

    def minimumSizeHint(self) -> QtCore.QSize:  # noqa: N802 - Qt's name
        content = self.widget().minimumSizeHint() if self.widget() is not None else QtCore.QSize(0, 0)
        width = content.width() + self.verticalScrollBar().sizeHint().width() + 2 * self.frameWidth()
        return QtCore.QSize(width, super().minimumSizeHint().height())


class RobotDock(QtWidgets.QDockWidget):
    """The right dock; ``robot_arg`` (a shipped name or a file, as given) is the chooser's
    first entry when it is not a shipped robot."""

    def __init__(self, parent: QtWidgets.QWidget, robot_arg: str) -> None:
        super().__init__("Robot", parent)
        self.setObjectName("robot_dock")
        self.setFeatures(QtWidgets.QDockWidget.NoDockWidgetFeatures)
        panel = QtWidgets.QWidget()
        layout = QtWidgets.QVBoxLayout(panel)
        self.robot_combo = QtWidgets.QComboBox()
        names = available_robots()
        self.robot_combo.addItems(names)
        if robot_arg not in names:
            self.robot_combo.insertItem(0, robot_arg)
        self.robot_combo.setCurrentText(robot_arg)
        layout.addWidget(self.robot_combo)
        self.motion_panel = MotionPanel()
        layout.addWidget(self.motion_panel)
        self.joints = JointPanel()
        self.readout = QtWidgets.QLabel()
        font = QtGui.QFont(qs.HELP_FONT_FAMILY, qs.READOUT_FONT_PT)
        font.setStyleHint(QtGui.QFont.TypeWriter)
        self.readout.setFont(font)
        self.readout.setTextInteractionFlags(Qt.TextSelectableByMouse)
        self.readout.setToolTip("endeffector pose in the world: position, roll-pitch-yaw (URDF), "
                                "quaternion; Yoshikawa's manipulability")
        self.frames_list = QtWidgets.QListWidget()
        self.frames_list.setVerticalScrollBarPolicy(Qt.ScrollBarAlwaysOff)  # as tall as its rows
        # one scroll area for all that grows with the joints: at 1024x768 a 7-joint arm
        # scrolls as a whole instead of squeezing its rows into nested scroll boxes
        body = QtWidgets.QWidget()
        column = QtWidgets.QVBoxLayout(body)
        column.setContentsMargins(0, 0, 0, 0)
        for widget in (self.joints, self.readout, QtWidgets.QLabel("Frames"), self.frames_list):
            column.addWidget(widget)
        column.addStretch(1)
        self.dock_scroll = ColumnScroll()
        self.dock_scroll.setWidgetResizable(True)
        self.dock_scroll.setHorizontalScrollBarPolicy(Qt.ScrollBarAlwaysOff)
        self.dock_scroll.setFrameShape(QtWidgets.QFrame.NoFrame)
        self.dock_scroll.setWidget(body)
        layout.addWidget(self.dock_scroll, 1)
        for widget in (self.robot_combo, self.dock_scroll, self.frames_list):
            widget.setFocusPolicy(Qt.NoFocus)  # keys stay with the GL view
        self.setWidget(panel)
        self.setMinimumWidth(qs.DOCK_MIN_WIDTH)

    def set_frames(self, n_frames: int) -> None:
        """One checkable row per DH frame 0..n_frames-1 and one for the endeffector."""
        frames = self.frames_list
        frames.blockSignals(True)
        frames.clear()
        names = [f"frame {i}" + (" (base)" if i == 0 else "") for i in range(n_frames)]
        for name in names + ["endeffector"]:
            item = QtWidgets.QListWidgetItem(name)
            item.setFlags(Qt.ItemIsUserCheckable | Qt.ItemIsEnabled)
            frames.addItem(item)
        frames.blockSignals(False)
        frames.setFixedHeight(frames.count() * frames.sizeHintForRow(0) + 2 * frames.frameWidth())
        self.dock_scroll.widget().ensurePolished()  # its real fonts and styles, so the dock is
        self.dock_scroll.updateGeometry()  # as wide as it needs before it is first shown

    def show_frames(self, options: GraphicsOptions) -> None:
        """Tick the rows of the frames ``options`` shows."""
        self.frames_list.blockSignals(True)
        for i, shown in enumerate(options.show_frames + [options.show_endeff_frame]):
            self.frames_list.item(i).setCheckState(Qt.Checked if shown else Qt.Unchecked)
        self.frames_list.blockSignals(False)
