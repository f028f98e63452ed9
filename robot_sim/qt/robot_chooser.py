"""The Robot dock's chooser: the shipped robots and the robot given on the command line,
whose long file path is elided in the middle so the dock keeps its width.

A QComboBox sizes itself to its longest item; a robot named by a 300-character path made
the dock, and the window, wider than the screen (joint boxes, upper limits, the Zero
button and the status bar went past its edge).  The chooser is ROBOT_CHOOSER_CHARS
characters wide; an item shows a path's file name, cut in the middle where it is longer,
and keeps the whole name as its data and tooltip.
"""
from __future__ import annotations

from pathlib import Path

from PyQt5 import QtCore, QtWidgets
from PyQt5.QtCore import Qt

from robot_sim.qt import settings as qs


class RobotChooser(QtWidgets.QComboBox):
    """A combo box of robot names or paths; ``chosen(name)`` carries the whole name."""

    chosen = QtCore.pyqtSignal(str)

    def __init__(self, names: list[str], current: str) -> None:
        super().__init__()
        self.setSizeAdjustPolicy(QtWidgets.QComboBox.AdjustToMinimumContentsLengthWithIcon)
        self.setMinimumContentsLength(qs.ROBOT_CHOOSER_CHARS)
        for name in names:
            self.addItem(self._shown(name), name)
        self.show_choice(current)
        self.currentIndexChanged.connect(lambda index: self.chosen.emit(self.itemData(index) or ""))

    def _shown(self, name: str) -> str:
        """A path's file name (a shipped robot's name as it is), elided in the middle to the
        chooser's width."""
        width = self.fontMetrics().horizontalAdvance("x") * qs.ROBOT_CHOOSER_CHARS
        return self.fontMetrics().elidedText(Path(name).name or name, Qt.ElideMiddle, width)

    def show_choice(self, name: str) -> None:
        """Show ``name`` (added first when it is not an item yet) without emitting ``chosen``."""
        index = self.findData(name)
        self.blockSignals(True)
        if index < 0:
            self.insertItem(0, self._shown(name), name)
            self.setItemData(0, name, Qt.ToolTipRole)
            index = 0
        self.setCurrentIndex(index)
        self.setToolTip(name)
        self.blockSignals(False)
