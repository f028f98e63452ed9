"""The dock's motion chooser: the motion mode shown and chosen (control.MOTION_MODES; the
window's ``Shift+M`` steps through it).  While the pick demo replays a simulated run it
names that run's mode.  The effort bars live beside the joints (``_win_joints``); the
physics in motion.py and simulation.py."""
from __future__ import annotations

from PyQt5 import QtCore, QtWidgets
from PyQt5.QtCore import Qt

from robot_sim.control.controllers import MOTION_LABELS, MOTION_MODES


class MotionPanel(QtWidgets.QWidget):
    """Motion chooser (emits ``mode_chosen(mode)``)."""

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
        self.replay_note = QtWidgets.QLabel()
        self.replay_note.setWordWrap(True)
        self.replay_note.hide()
        layout.addWidget(self.replay_note)

    def show_mode(self, mode: str, replayed: bool = False) -> None:
        """Select ``mode`` without emitting; ``replayed``: the pick demo replays a run
        simulated in ``mode`` (the arm itself is not simulated now), which a note says."""
        self.combo.blockSignals(True)
        self.combo.setCurrentIndex(MOTION_MODES.index(mode))
        self.combo.blockSignals(False)
        self.replay_note.setText(f"replaying the pick task as {MOTION_LABELS[mode]} ran it")
        self.replay_note.setVisible(replayed)
