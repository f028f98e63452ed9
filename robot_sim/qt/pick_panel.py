"""Window parts of the pick demo: the playback dock (play/pause, a timeline slider to
scrub, speed) and the plot dock (pyqtgraph: joint position, velocity and acceleration
against time, with a cursor at the shown time).  Imported by robot_sim/qt/window.py only."""
from __future__ import annotations

from typing import Callable

import numpy as np
import pyqtgraph as pg
from PyQt5 import QtWidgets
from numpy.typing import NDArray
from PyQt5.QtCore import Qt

from robot_sim.qt import settings as qs
from robot_sim.planning.scaling import Trajectory


#: The timeline slider is never narrower than this (it shrank to a lone handle).
TIMELINE_MIN_WIDTH_PX = 200


class PlotDock(QtWidgets.QDockWidget):
    """One plot per row of ``PLOT_ROWS`` (q, qd, qdd, and the joint effort τ of a simulated
    run) under a legend row of the joint colours, one curve per joint, x = time [s], and a
    vertical cursor line at the current time in each.  The effort row is shown only when
    there is an effort to plot."""

    def __init__(self, parent: QtWidgets.QWidget) -> None:
        super().__init__(qs.PLOT_DOCK_TITLE, parent)
        self.setObjectName("plot_dock")
        self.graphics = pg.GraphicsLayoutWidget()
        self.graphics.setBackground(qs.PLOT_BACKGROUND)
        self.plots: dict[str, pg.PlotItem] = {}
        self.cursors: dict[str, pg.InfiniteLine] = {}
        # one legend row (joint colours) above the plots; no plot titles and one time axis
        # (the lowest row's), so the rows keep their height for the curves in a short dock
        self.legend = pg.LegendItem(colCount=qs.PLOT_LEGEND_COLUMNS, labelTextSize=qs.PLOT_LABEL_SIZE)
        self.graphics.addItem(self.legend, row=0, col=0)
        for row, (key, symbol) in enumerate(qs.PLOT_ROWS, start=1):
            plot = self.graphics.addPlot(row=row, col=0)
            plot.setLabel("left", symbol, **{"font-size": qs.PLOT_LABEL_SIZE})
            plot.showGrid(x=True, y=True, alpha=qs.PLOT_GRID_ALPHA)
            if row > 1:
                plot.setXLink(self.plots[qs.PLOT_ROWS[0][0]])
            cursor = pg.InfiniteLine(angle=90, pen=pg.mkPen(qs.PLOT_CURSOR_COLOR))
            plot.addItem(cursor)
            self.plots[key], self.cursors[key] = plot, cursor
        for plot in self.plots.values():
            plot.setLabel("bottom", "time", units="s")
        self.plots["effort"].setVisible(False)
        self.curves: dict[str, list[pg.PlotDataItem]] = {key: [] for key in self.plots}
        self.graphics.setFocusPolicy(Qt.NoFocus)  # keys stay with the GL view
        self.setWidget(self.graphics)
        self.setMinimumHeight(qs.PLOT_DOCK_MIN_HEIGHT)

    def show_trajectory(self, traj: Trajectory, effort: NDArray[np.float64] | None = None) -> None:
        """Plot q, q̇, q̈ of ``traj`` and, if given, ``effort`` (N, n) against its time, one
        colour per joint."""
        series = {"q": traj.q, "qd": traj.qd, "qdd": traj.qdd, "effort": effort}
        self.plots["effort"].setVisible(effort is not None)
        last = "effort" if effort is not None else qs.PLOT_ROWS[-2][0]
        for key, plot in self.plots.items():  # the time axis only under the lowest row shown
            plot.showAxis("bottom", key == last)
        for key, plot in self.plots.items():
            for curve in self.curves[key]:
                plot.removeItem(curve)
            data = series[key]
            if data is None:
                self.curves[key] = []
                continue
            self.curves[key] = [
                plot.plot(traj.t, data[:, j], pen=pg.mkPen(qs.PLOT_JOINT_COLORS[j % len(qs.PLOT_JOINT_COLORS)]))
                for j in range(traj.n_dofs)
            ]
        self.legend.clear()
        for j, curve in enumerate(self.curves["q"]):
            self.legend.addItem(curve, f"joint {j + 1}")

    def set_time(self, t: float) -> None:
        """Move the cursors to time ``t`` [s]."""
        for cursor in self.cursors.values():
            cursor.setValue(t)


class PickPanel(QtWidgets.QDockWidget):
    """Play/pause button, timeline slider (ms ticks), speed chooser and a time/phase label.
    The callbacks get the window's actions: ``toggle()``, ``seek(t)``, ``set_speed(s)``."""

    def __init__(self, parent: QtWidgets.QWidget, toggle: Callable[[], None],
                 seek: Callable[[float], None], set_speed: Callable[[float], None]) -> None:
        super().__init__("Pick demo", parent)
        self.setObjectName("pick_dock")
        panel = QtWidgets.QWidget()
        layout = QtWidgets.QHBoxLayout(panel)
        self.play = QtWidgets.QPushButton(qs.PICK_PLAY_TEXT)
        self.play.clicked.connect(lambda: toggle())
        self.slider = QtWidgets.QSlider(Qt.Horizontal)
        self.slider.setMinimumWidth(TIMELINE_MIN_WIDTH_PX)
        self.slider.valueChanged.connect(lambda ticks: seek(ticks / qs.PICK_SLIDER_TICKS_PER_S))
        self.speed = QtWidgets.QComboBox()
        self.speed.addItems([qs.PICK_SPEED_FORMAT.format(speed=s) for s in qs.PICK_SPEEDS])
        self.speed.setCurrentIndex(qs.PICK_SPEEDS.index(1.0))
        self.speed.currentIndexChanged.connect(lambda i: set_speed(qs.PICK_SPEEDS[i]))
        self.label = QtWidgets.QLabel()
        self.label.setMinimumWidth(qs.PICK_LABEL_MIN_WIDTH)
        for widget in (self.play, self.slider, self.speed):
            widget.setFocusPolicy(Qt.NoFocus)  # keys stay with the GL view
        layout.addWidget(self.play)
        layout.addWidget(self.slider, 1)
        layout.addWidget(self.speed)
        layout.addWidget(self.label)
        self.setWidget(panel)
        self.setMaximumHeight(panel.sizeHint().height() + qs.PICK_DOCK_TITLE_PX)

    def sync(self, time: float, duration: float, playing: bool, phase: str) -> None:
        """Show the demo's time, length, play state and phase without emitting signals."""
        self.slider.blockSignals(True)
        self.slider.setRange(0, round(duration * qs.PICK_SLIDER_TICKS_PER_S))
        self.slider.setValue(round(time * qs.PICK_SLIDER_TICKS_PER_S))
        self.slider.blockSignals(False)
        self.play.setText(qs.PICK_PAUSE_TEXT if playing else qs.PICK_PLAY_TEXT)
        self.label.setText(qs.PICK_LABEL_FORMAT.format(t=time, duration=duration, phase=phase))

