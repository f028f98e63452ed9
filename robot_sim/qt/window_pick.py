"""The window's pick demo: the playback dock (play, pause, scrub, speed) and the plots of
the planned motion, following the session's pick playback (a mixin of
``robot_sim.qt.window.MainWindow``)."""
from __future__ import annotations

from PyQt5.QtCore import Qt

from robot_sim.qt import settings as qs
from robot_sim.qt.guard import guarded
from robot_sim.qt.pick_panel import PickPanel, PlotDock
from robot_sim.viewer.pick_demo import plan_for


class PickControls:
    """Pick playback docks of the main window."""

    def show_pick(self) -> None:
        """The pick demo's docks (made on first use) showing the session's plan."""
        if self.pick_panel is None:
            self.pick_panel = PickPanel(self, self.act_toggle_pick, self.seek_pick, self.set_pick_speed)
            self.plot_dock = PlotDock(self)
            # the timeline right under the view, the plots in a tab beside the DH table: each
            # gets the view's whole width (side by side at 1024x768 the plots were cut off)
            self.addDockWidget(Qt.BottomDockWidgetArea, self.pick_panel)
            self.splitDockWidget(self.pick_panel, self.dh_dock, Qt.Vertical)
            self.tabifyDockWidget(self.dh_dock, self.plot_dock)
            self.plot_dock.raise_()
            self.resizeDocks([self.plot_dock], [round(self.height() * qs.PLOT_DOCK_HEIGHT_FRACTION)], Qt.Vertical)
        self.plot_dock.show_trajectory(self.session.pick.plan.trajectory, self.session.pick.effort)
        self.show_motion_mode()
        self.sync_pick()
        self.start_motion()

    def sync_pick(self) -> None:
        """Timeline, label and plot cursors at the demo's time."""
        demo = self.session.pick
        if self.pick_panel is None or demo is None:
            return
        self.pick_panel.sync(demo.time, demo.duration, demo.playing, demo.state().phase)
        self.plot_dock.set_time(demo.time)

    def start_pick(self) -> None:
        """Plan the robot's default pick task and show it (a one-line message if it cannot)."""
        try:
            plan = plan_for(self.session.robot)
        except ValueError as exc:  # TaskError, TaskDefinitionError
            self.message(str(exc))
            return
        self.session.start_pick(plan)
        self.show_pick()

    def act_toggle_pick(self, _: None = None) -> None:
        """Start the pick demo, or play / pause it (also the Play button's handler)."""
        try:
            if self.session.pick is None:
                self.start_pick()
            else:
                self.session.pick.toggle()
                self.start_motion()
        except Exception as exc:  # noqa: BLE001 - an exception escaping a Qt handler aborts PyQt
            self.message(f"pick demo: {exc}")
        self.sync_widgets()

    def seek_pick(self, t: float) -> None:
        """Timeline slider: pause and show the task at ``t`` s."""
        try:
            self.session.pick.playing = False
            self.session.show_pick_at(t)
        except Exception as exc:  # noqa: BLE001 - an exception escaping a Qt handler aborts PyQt
            self.message(f"seek failed: {exc}")
        self.sync_widgets()

    @guarded
    def set_pick_speed(self, speed: float) -> None:
        """Speed box of the timeline: playback at ``speed`` × real time."""
        if self.session.pick is not None:
            self.session.pick.speed = speed
