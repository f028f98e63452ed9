"""The control panel of ``robot-sim --web``: what the window's docks offer, in the page.

Robot chooser (asking about unsaved DH edits first, as the window does), motion mode,
view toggles (frames, labels, wireframe, look, collision display, trail, IK target,
annotated joint), the IK target's analytic branches (the window's keys B and Shift+B as
buttons), the IK target as a draggable gizmo, joint sliders, the DH table (each
cell a text box validated by robot_sim.viewer.dh_table, refused edits answered with the
window's message), the pick task's timeline and the readout.  Every page sees the same
session; a handler runs under the backend's lock and never lets an exception out
(robot_sim.web.guard).  Handlers only change the session; :meth:`WebPanel.tick` (the
server's loop) shows the result.
"""
from __future__ import annotations

import math
from typing import Any, Callable

import numpy as np

from robot_sim.control.controllers import MOTION_MODES
from robot_sim.graphics.looks import look_for, looks_of
from robot_sim.graphics.robot_parts import robot_reach
from robot_sim.io.robot_file import available_robots, load_robot
from robot_sim.io.robot_writer import to_toml
from robot_sim.model.params import RobotDefinitionError, RobotParams
from robot_sim.transforms import quaternion_from_rot, rot_from_quaternion, rpy_from_rot
from robot_sim.viewer.commands import COMMANDS
from robot_sim.viewer.dh_table import COLUMNS, HEADERS, cell_text, edit_cell, is_editable
from robot_sim.viewer.readout import session_readout
from robot_sim.viewer.session import ViewerSession
from robot_sim.viewer.units import display_range, display_scale, wrap_display
from robot_sim.web.guard import guarded

#: The annotate chooser's entry for no joint.
NO_JOINT = "none"
#: Slider steps in display units (degrees, metres).
SLIDER_STEP = 0.1
#: The pick timeline's line: phase, time and length [s].
PICK_FORMAT = "phase: **{phase}** at {t:.2f} s of {duration:.2f} s"
#: A widget :meth:`WebPanel.tick` has not written yet.
_UNSHOWN = object()
#: Size of the IK gizmo as a fraction of the robot's reach.
GIZMO_SCALE_FRAC = 0.15


class WebPanel:
    """The panel of ``backend`` (a robot_sim.web.backend.WebBackend) for ``robot_arg`` (the
    shipped robot's name or the file it came from)."""

    def __init__(self, backend: Any, robot_arg: str) -> None:
        self.backend = backend
        self.gui = backend.server.gui
        self.lock = backend.lock
        self.robot_choice = robot_arg
        self.edited = False  # the DH table holds edits not saved to a file
        self.message = ""
        self.on_new_session: Callable[[ViewerSession], None] = lambda session: None
        self._gizmo: Any = None
        self._dragging = False
        #: Per widget (by id): the value :meth:`tick` last put there or a handler last took
        #: from the page (:meth:`_show`, :meth:`_taken`).
        self._shown: dict[int, Any] = {}
        self._build()

    @property
    def session(self) -> ViewerSession:
        return self.backend.session

    # ---- building ----
    def _build(self) -> None:
        gui = self.gui
        self.status = gui.add_markdown("")
        self.readout = gui.add_markdown("")
        with gui.add_folder("Robot"):
            names = available_robots()
            options = names if self.robot_choice in names else [self.robot_choice, *names]
            self.robot_box = gui.add_dropdown("robot", tuple(options), initial_value=self.robot_choice)
            self.robot_box.on_update(self._robot_chosen)
            self.motion_box = gui.add_dropdown("motion", MOTION_MODES, initial_value=self._mode())
            self.motion_box.on_update(self._motion_chosen)
            self.circle_button = gui.add_button("circle demo")
            self.circle_button.on_click(self._circle_clicked)
            self.download_button = gui.add_button("download robot file (TOML)")
            self.download_button.on_click(self._download_clicked)
        with gui.add_folder("View"):
            self.look_box = gui.add_dropdown("look", ("dh",), initial_value="dh")
            self.look_box.on_update(self._look_chosen)
            self.frames_box = gui.add_checkbox("all frames", False)
            self.frames_box.on_update(self._frames_toggled)
            self.labels_box = gui.add_checkbox("frame labels", True)
            self.labels_box.on_update(self._labels_toggled)
            self.wire_box = gui.add_checkbox("wireframe", False)
            self.wire_box.on_update(self._wire_toggled)
            self.collision_box = gui.add_checkbox("collision display", False)
            self.collision_box.on_update(self._collision_toggled)
            self.trail_box = gui.add_checkbox("trail", False)
            self.trail_box.on_update(self._trail_toggled)
            self.target_box = gui.add_checkbox("IK target", False)
            self.target_box.on_update(self._target_toggled)
            self.branch_button = gui.add_button("next IK branch (B)")
            self.branch_button.on_click(self._branch_clicked)
            self.branches_button = gui.add_button("all IK branches (Shift+B)")
            self.branches_button.on_click(self._branches_clicked)
            self.annotate_box = gui.add_dropdown("annotate joint", (NO_JOINT,), initial_value=NO_JOINT)
            self.annotate_box.on_update(self._annotate_chosen)
        with gui.add_folder("Pick task") as self.pick_folder:
            self.pick_phase = gui.add_markdown("")
            self.pick_play = gui.add_button("play / pause")
            self.pick_play.on_click(self._pick_play_clicked)
            self.pick_time = gui.add_slider("time [s]", 0.0, 1.0, 0.01, 0.0)
            self.pick_time.on_update(self._pick_scrubbed)
        self.pick_folder.visible = self.session.pick is not None  # shown from the start: no layout jump later
        self.joint_folder = gui.add_folder("Joints")
        self.dh_folder = gui.add_folder("DH table", expand_by_default=False)
        self.sliders: list[Any] = []
        self.cells: dict[tuple[int, str], Any] = {}
        self._robot_widgets_for: RobotParams | None = None
        self.rebuild()

    def rebuild(self) -> None:
        """Widgets that depend on the robot shown: sliders, DH cells, looks, joints."""
        session = self.session
        robot = session.robot
        for handle in [*self.sliders, *self.cells.values()]:
            self._shown.pop(id(handle), None)
            handle.remove()
        self.sliders, self.cells = [], {}
        lo, hi = display_range(robot)
        values = wrap_display(robot, session.state.q())
        units = ["m" if s == 1.0 else "°" for s in display_scale(robot)]
        with self.joint_folder:
            for i in range(robot.n_dofs):
                slider = self.gui.add_slider(f"q{i + 1} [{units[i]}]", float(lo[i]), float(hi[i]), SLIDER_STEP,
                                             float(np.clip(values[i], lo[i], hi[i])))
                slider.on_update(lambda event, i=i: self._slider_moved(event, i))
                self.sliders.append(slider)
        with self.dh_folder:
            for row in range(robot.n_dofs):
                for column, header in zip(COLUMNS, HEADERS):
                    box = self.gui.add_text(f"{row + 1} {header}", cell_text(robot, session.state.q(), row, column),
                                            disabled=not is_editable(robot, row, column))
                    box.on_update(lambda event, row=row, column=column: self._cell_edited(event, row, column))
                    self.cells[(row, column)] = box
        looks = looks_of(robot)
        self.look_box.options = looks
        self.look_box.value = look_for(robot, session.options.look)
        self.annotate_box.options = (NO_JOINT, *(str(i + 1) for i in range(robot.n_dofs)))
        joint = session.options.annotate_joint
        self.annotate_box.value = NO_JOINT if joint is None else str(joint)
        self._robot_widgets_for = robot

    # ---- status ----
    def say(self, text: str) -> None:
        """Show ``text`` in the status line of every page."""
        self.message = text
        self.status.content = f"**{text}**" if text else ""

    # ---- what a page sends is checked (a page can send anything, not only what it shows) ----
    def _offered(self, dropdown: Any, value: Any) -> bool:
        """True when ``value`` is one of ``dropdown``'s options; otherwise says so."""
        if value in dropdown.options:
            return True
        self.say(f"{dropdown.label}: expected one of {', '.join(dropdown.options)}, got {str(value)[:80]!r}")
        return False

    def _number(self, value: Any, lo: float, hi: float) -> float | None:
        """``value`` as a finite number within [lo, hi], or None (said on the page)."""
        try:
            number = float(value)
        except (TypeError, ValueError):
            number = math.nan
        if not lo <= number <= hi:
            self.say(f"expected a number in {lo:g}..{hi:g}, got {str(value)[:80]!r}")
            return None
        return number

    # ---- handlers (guarded: under the lock, never raising) ----
    @guarded
    def _slider_moved(self, event: Any, index: int) -> None:
        if event.client is None:
            return
        value = self._number(self._taken(event), event.target.min, event.target.max)
        if value is not None:
            self.session.set_joint(index, value / float(display_scale(self.session.robot)[index]))

    @guarded
    def _cell_edited(self, event: Any, row: int, column: str) -> None:
        if event.client is None:
            return
        try:
            robot = edit_cell(self.session.robot, row, column, event.target.value)
        except ValueError as exc:
            self.say(f"refused: {exc}")
            return
        self.edited = True
        self._show_robot(robot)
        self.say(f"{robot.name}: joint {row + 1} {column} set (unsaved: download the robot file to keep it)")

    @guarded
    def _robot_chosen(self, event: Any) -> None:
        if event.client is None:
            return
        name = event.target.value
        if name == self.robot_choice:
            return
        if not self._offered(self.robot_box, name):  # a page can send any text: never a path of its own
            return
        if self.edited:
            self._ask_unsaved(name, event.client)
            return
        self._switch_to(name)

    def _ask_unsaved(self, name: str, client: Any) -> None:
        """The window's question before dropping unsaved edits: save (download the file),
        discard, or cancel (the chooser goes back)."""
        self.robot_box.value = self.robot_choice
        with client.gui.add_modal("robot-sim") as modal:
            client.gui.add_markdown(f"{self.session.robot.name} has unsaved edits. Save them before switching to {name}?")
            save, discard, cancel = (client.gui.add_button(label) for label in ("Save", "Discard", "Cancel"))

            def answer(choice: str) -> None:
                modal.close()
                self._answered(choice, name, client)

            save.on_click(lambda _: answer("save"))
            discard.on_click(lambda _: answer("discard"))
            cancel.on_click(lambda _: answer("cancel"))

    @guarded
    def _answered(self, choice: str, name: str, client: Any) -> None:
        if choice == "cancel":
            self.say(f"kept {self.session.robot.name} and its edits")
            return
        if choice == "save":
            self._download(client)
        self._switch_to(name)

    def _switch_to(self, name: str) -> None:
        try:
            robot = load_robot(name)
        except RobotDefinitionError as exc:
            self.say(str(exc))
            self.robot_box.value = self.robot_choice
            return
        self.robot_choice, self.edited = name, False
        self._show_robot(robot)
        self.robot_box.value = name
        self.say(f"showing {robot.name}")

    def _show_robot(self, robot: RobotParams) -> None:
        session = self.session.with_robot(robot)
        self.backend.set_session(session)
        self.on_new_session(session)
        self.rebuild()
        self.backend.reset_cameras()

    @guarded
    def _download_clicked(self, event: Any) -> None:
        if event.client is not None:
            self._download(event.client)

    def _download(self, client: Any) -> None:
        """The shown robot as a robot file, downloaded by the page (nothing is written here)."""
        robot = self.session.robot
        client.send_file_download(f"{robot.name}.toml", to_toml(robot).encode(), save_immediately=True)
        self.edited = False
        self.say(f"downloaded {robot.name}.toml")

    @guarded
    def _motion_chosen(self, event: Any) -> None:
        if event.client is None:
            return
        mode = self._taken(event)
        try:
            self.session.set_motion(mode)
        except ValueError as exc:  # e.g. dynamics refusing the robot's data; the tick shows the mode kept
            self.say(f"motion {mode}: {exc}")
            return
        self.say(f"motion: {mode}")

    def _mode(self) -> str:
        return self.session.driver.mode

    @guarded
    def _circle_clicked(self, event: Any) -> None:
        running = self.session.toggle_demo()
        self.say("circle demo running" if running else "circle demo stopped")

    @guarded
    def _look_chosen(self, event: Any) -> None:
        if event.client is not None and self._offered(self.look_box, event.target.value):
            self.session.options.look = event.target.value

    @guarded
    def _frames_toggled(self, event: Any) -> None:
        if event.client is None:
            return
        options = self.session.options
        options.show_only_frames(list(range(options.n_frames + 1)) if event.target.value else [0])

    @guarded
    def _labels_toggled(self, event: Any) -> None:
        if event.client is not None:
            self.session.options.show_labels = bool(event.target.value)

    @guarded
    def _wire_toggled(self, event: Any) -> None:
        if event.client is not None:
            self.session.options.wireframe = bool(event.target.value)

    @guarded
    def _collision_toggled(self, event: Any) -> None:
        if event.client is not None and bool(self._taken(event)) != self.session.options.show_collision:
            self.session.toggle_collision()

    @guarded
    def _trail_toggled(self, event: Any) -> None:
        if event.client is not None and bool(event.target.value) != (self.session.trail is not None):
            self.session.toggle_trail()

    @guarded
    def _target_toggled(self, event: Any) -> None:
        if event.client is not None and bool(self._taken(event)) != (self.session.target_tf is not None):
            self.session.toggle_target()

    @guarded
    def _branch_clicked(self, event: Any) -> None:
        self.say(COMMANDS["cycle_branch"](self.session, None))

    @guarded
    def _branches_clicked(self, event: Any) -> None:
        self.say(COMMANDS["toggle_all_branches"](self.session, None))

    @guarded
    def _annotate_chosen(self, event: Any) -> None:
        if event.client is not None:
            value = event.target.value
            if self._offered(self.annotate_box, value):
                self.session.options.annotate_joint = None if value == NO_JOINT else int(value)

    @guarded
    def _pick_play_clicked(self, event: Any) -> None:
        pick = self.session.pick
        if pick is None:
            return
        if pick.time >= pick.duration:
            self.session.show_pick_at(0.0)
        pick.playing = not pick.playing

    @guarded
    def _pick_scrubbed(self, event: Any) -> None:
        if event.client is None or self.session.pick is None:
            return
        t = self._number(self._taken(event), 0.0, self.session.pick.duration)
        if t is not None:
            self.session.pick.playing = False
            self.session.show_pick_at(t)

    @guarded
    def _gizmo_moved(self, event: Any) -> None:
        """A drag of the gizmo (phases start, update, end): the IK target follows it."""
        self._dragging = event.phase != "end"
        session, handle = self.session, event.target
        if session.target_tf is None:
            return
        old = session.target_tf.mat
        if not (np.isfinite(handle.position).all() and np.isfinite(handle.wxyz).all()):
            self.say("IK target: the page sent a pose that is not finite")
            return
        rotation = rot_from_quaternion(handle.wxyz) @ old[:3, :3].T  # about world axes through the target
        translation = np.asarray(handle.position, dtype=float) - old[:3, 3]
        reached = session.move_target(translation=translation, rpy=np.array(rpy_from_rot(rotation)))
        if not reached:
            self.say("IK target out of reach")

    # ---- the loop's part ----
    @guarded
    def tick(self) -> None:
        """Show the session's state in the widgets (sliders, gizmo, pick timeline, readout);
        called by the server's loop a few times a second."""
        session = self.session
        robot = session.robot
        if robot is not self._robot_widgets_for:
            self.rebuild()
        values = wrap_display(robot, session.state.q())
        for slider, value in zip(self.sliders, values):
            self._show(slider, float(np.clip(round(float(value), 6), slider.min, slider.max)))
        self._sync_gizmo()
        self._show(self.target_box, session.target_tf is not None)
        self._show(self.collision_box, session.options.show_collision)
        self._show(self.motion_box, self._mode())
        pick = session.pick
        self.pick_folder.visible = pick is not None
        if pick is not None:
            self.pick_time.max = float(pick.duration)
            self._show(self.pick_time, float(min(pick.time, pick.duration)))
            self.pick_phase.content = PICK_FORMAT.format(phase=pick.plan.phase_at(pick.time), t=pick.time, duration=pick.duration)
        self.readout.content = "```\n" + session_readout(session) + "\n" + session.status_text("web") + "\n```"

    def _show(self, widget: Any, value: Any) -> None:
        """Put the session's ``value`` in ``widget``, unless the widget holds a value the page
        sent that no handler has taken yet (:meth:`_taken`).  viser stores the page's value
        in the widget, then runs the handler on another thread: writing the session's
        older value over it first would make the handler see no change, and the page's
        click would be lost."""
        shown = self._shown.get(id(widget), _UNSHOWN)
        if shown is not _UNSHOWN and widget.value != shown:
            return  # the page's value, waiting for its handler
        if shown is _UNSHOWN or value != shown:
            widget.value = value
            self._shown[id(widget)] = value

    def _taken(self, event: Any) -> Any:
        """The value the page sent in ``event``'s widget, marked as taken: from now on
        :meth:`tick` shows the session's value there again (the page's, if it was applied;
        the one before it, if it was refused)."""
        value = event.target.value
        self._shown[id(event.target)] = value
        return value

    def _sync_gizmo(self) -> None:
        target = self.session.target_tf
        if target is None:
            if self._gizmo is not None:
                self._gizmo.remove()
                self._gizmo = None
            return
        wxyz, position = tuple(float(v) for v in quaternion_from_rot(target.mat[:3, :3])), target.mat[:3, 3]
        if self._gizmo is None:
            self._gizmo = self.backend.server.scene.add_transform_controls(
                "/target_gizmo", scale=GIZMO_SCALE_FRAC * robot_reach(self.session.robot), depth_test=False,
                wxyz=wxyz, position=tuple(position))
            self._gizmo.on_update(self._gizmo_moved)
        elif not self._dragging:
            self._gizmo.wxyz, self._gizmo.position = wxyz, tuple(position)
