"""Constants of the window (robot_sim.qt): key and mouse bindings, status texts, docks, sliders,
overlays and plots.  Key names are Qt key names without the "Key_" prefix; modifiers are "" or
"+"-joined names out of Shift, Ctrl, Alt.  The help overlay is generated from KEY_BINDINGS and
MOUSE_BINDINGS, and key presses are dispatched by looking up (key, modifiers) in KEY_BINDINGS."""

from robot_sim.viewer.settings import (  # noqa: F401 - the key commands' steps, read by the window's tests
    KEY_ORBIT_STEP_DEG, KEY_ZOOM_FACTOR, TARGET_STEP_DEG, TARGET_STEP_M, VIEW_PRESETS,
)

# ---------------------------------------------------------------------------
# Window (robot_sim/qt/window.py) constants — owned by the simulator/window engineer.
# Key names are Qt key names without the "Key_" prefix; modifiers are "" or
# "+"-joined names out of Shift, Ctrl, Alt.  The help overlay is generated from
# KEY_BINDINGS and MOUSE_BINDINGS, and key presses are dispatched by looking
# up (key, modifiers) in KEY_BINDINGS.
# ---------------------------------------------------------------------------

KEY_BINDINGS = (
    # (key, modifiers, action, argument, description).  The window has one handler per
    # action, called with the argument; consecutive rows with the same description
    # share one help line.
    ("H", "", "toggle_help", None, "show / hide this help"),
    ("Escape", "", "quit", None, "close this help, else quit"),
    ("T", "", "toggle_wireframe", None, "wireframe on / off"),
    ("T", "Shift", "cycle_look", None, "next look: meshes, DH, both, solid (without meshes: DH, solid)"),
    ("A", "", "toggle_alpha", None, "transparency on / off"),
    ("0", "", "toggle_all_frames", None, "all joint frames on / off"),
    ("1", "", "toggle_frame", 1, "joint frame 1..9 on / off (all frames: dock list)"),
    ("2", "", "toggle_frame", 2, "joint frame 1..9 on / off (all frames: dock list)"),
    ("3", "", "toggle_frame", 3, "joint frame 1..9 on / off (all frames: dock list)"),
    ("4", "", "toggle_frame", 4, "joint frame 1..9 on / off (all frames: dock list)"),
    ("5", "", "toggle_frame", 5, "joint frame 1..9 on / off (all frames: dock list)"),
    ("6", "", "toggle_frame", 6, "joint frame 1..9 on / off (all frames: dock list)"),
    ("7", "", "toggle_frame", 7, "joint frame 1..9 on / off (all frames: dock list)"),
    ("8", "", "toggle_frame", 8, "joint frame 1..9 on / off (all frames: dock list)"),
    ("9", "", "toggle_frame", 9, "joint frame 1..9 on / off (all frames: dock list)"),
    ("W", "", "zoom", -1, "zoom in / out"),  # distance *= KEY_ZOOM_FACTOR ** argument
    ("S", "", "zoom", 1, "zoom in / out"),
    ("Left", "", "orbit", (-1, 0), "orbit camera left / right"),  # (azimuth, elevation) steps
    ("Right", "", "orbit", (1, 0), "orbit camera left / right"),
    ("Up", "", "orbit", (0, 1), "orbit camera up / down"),
    ("Down", "", "orbit", (0, -1), "orbit camera up / down"),
    ("R", "", "reset_view", None, "reset view"),
    ("P", "", "save_screenshot", None, "save a PNG screenshot (path in status bar)"),
    ("E", "", "toggle_workspace", None, "workspace point cloud on / off"),
    ("V", "", "toggle_vectors", None, "endeffector velocity arrows on / off"),
    ("C", "", "toggle_collision", None, "collision shapes, contacts and closest distance on / off"),
    ("C", "Shift", "toggle_demo", None, "circle demo (differential IK) on / off"),
    ("Space", "", "toggle_pick", None, "pick demo: start, play / pause"),
    ("G", "", "toggle_target", None, "IK target frame and ghost on / off"),
    ("N", "", "toggle_labels", None, "frame labels (numbers) on / off"),
    ("M", "", "toggle_com", None, "link centres of mass on / off"),
    ("M", "Shift", "cycle_motion", None, "next motion mode (kinematic, passive, PD, PD+g, CT)"),
    ("I", "", "move_target", (0, 1), "move IK target +x / -x"),  # (world axis, sign)
    ("K", "", "move_target", (0, -1), "move IK target +x / -x"),
    ("J", "", "move_target", (1, 1), "move IK target +y / -y"),
    ("L", "", "move_target", (1, -1), "move IK target +y / -y"),
    ("U", "", "move_target", (2, 1), "move IK target +z / -z"),
    ("O", "", "move_target", (2, -1), "move IK target +z / -z"),
    ("I", "Shift", "rotate_target", (0, 1), "rotate IK target +/- about world x"),
    ("K", "Shift", "rotate_target", (0, -1), "rotate IK target +/- about world x"),
    ("J", "Shift", "rotate_target", (1, 1), "rotate IK target +/- about world y"),
    ("L", "Shift", "rotate_target", (1, -1), "rotate IK target +/- about world y"),
    ("U", "Shift", "rotate_target", (2, 1), "rotate IK target +/- about world z"),
    ("O", "Shift", "rotate_target", (2, -1), "rotate IK target +/- about world z"),
    ("1", "Ctrl", "view_preset", "front", "view from the front / side / top / iso"),  # VIEW_PRESETS key
    ("2", "Ctrl", "view_preset", "side", "view from the front / side / top / iso"),
    ("3", "Ctrl", "view_preset", "top", "view from the front / side / top / iso"),
    ("4", "Ctrl", "view_preset", "iso", "view from the front / side / top / iso"),
    ("5", "Ctrl", "toggle_orthographic", None, "orthographic / perspective projection"),
    ("F", "", "toggle_follow", None, "camera follows the endeffector on / off"),
    ("F", "Shift", "toggle_trail", None, "endeffector trail on / off"),
    ("B", "", "cycle_branch", None, "ghost at the IK target's next analytic branch"),
    ("B", "Shift", "toggle_all_branches", None, "all analytic branches of the IK target, labelled, on / off"),
    ("D", "", "annotate_next", None, "annotate DH parameters of the next joint (then none)"),
    ("Home", "", "go_home", None, "all joints to their home values"),
    ("O", "Ctrl", "open_robot", None, "open a robot file"),
    ("S", "Ctrl", "save_robot_as", None, "save the robot as a file (comments kept)"),
)

MOUSE_BINDINGS = (
    # (gesture, description) — shown in the help overlay below the keys
    ("left drag", "orbit camera"),
    ("right / middle drag", "pan camera"),
    ("wheel", "zoom"),
    ("Ctrl + left drag", "move IK target in the view plane"),
    ("Shift + left drag", "pull the endeffector (physical motion modes)"),
)
DOCK_MIN_WIDTH = 260                 # px

# Joint sliders: integer slider ticks per unit shown in the label
SLIDER_TICKS_PER_DEG = 10            # revolute resolution 0.1 deg
SLIDER_TICKS_PER_M = 1000            # prismatic resolution 1 mm

# Dynamics in the dock: per-joint effort bars (fraction of the effort limit) and the
# flash of a joint that hits a limit
EFFORT_BAR_STEPS = 1000              # QProgressBar range 0..STEPS: |effort| / limit
EFFORT_BAR_HEIGHT_PX = 16
EFFORT_BAR_FORMAT = "{percent:+.0f} %"  # the bar's text: signed effort, percent of the limit
EFFORT_BAR_COLOR = "#3a8ee6"         # blue: within the limit
EFFORT_BAR_SATURATED_COLOR = "#e03030"  # red: saturated at the effort limit
LIMIT_FLASH_COLOR = "#ff5050"        # joint label colour after a limit hit
LIMIT_FLASH_MS = 600
STATUS_FPS_FORMAT = "{fps:.0f} fps"
STATUS_FPS_IDLE = "idle"
STATUS_MESSAGE_MS = 5000             # how long transient status messages stay
FPS_WINDOW_S = 1.0                   # frame rate = paints within the last second

# Camera steps (the key steps, the target steps and the view presets are the viewer's
# commands': robot_sim.viewer.settings)
MOUSE_ORBIT_DEG_PER_PX = 0.4
WHEEL_ZOOM_FACTOR = 1.1              # per wheel notch (120 eighths of a degree)

# IK target and animation
ANIM_INTERVAL_MS = 16                # animation / demo timer period
REFINE_AFTER_MS = 150                # the still view is repainted with MSAA this long after the camera's last move

# Workspace cloud
WORKSPACE_DEFAULT_POINTS = 200_000

# Help overlay (QPainter over the GL picture)
HELP_FONT_FAMILY = "monospace"
HELP_FONT_PT = 9
HELP_MARGIN_PX = 12
HELP_BACKGROUND_RGBA = (0, 0, 0, 225)
HELP_TEXT_RGB = (235, 235, 235)

# Screenshots saved with P: into this folder of the working directory (created)
SCREENSHOT_DIR = "screenshots"
SCREENSHOT_NAME_FORMAT = "robot-sim-{robot}-{stamp}.png"

# Endeffector readout (window dock): world pose and manipulability
READOUT_FONT_PT = 8

# Joint panel: slider + typed box per joint, limits written at the slider's ends
JOINT_UNIT_REVOLUTE = "°"
JOINT_UNIT_PRISMATIC = " m"
JOINT_UNLIMITED_MARK = " (unlimited)"
JOINT_BOX_DECIMALS_REVOLUTE = 1
JOINT_BOX_DECIMALS_PRISMATIC = 3
JOINT_LIMIT_LABEL_STYLE = "color: gray; font-size: 8pt"

# DH table dock
DH_INVALID_CELL_RGB = (255, 200, 200)   # background of a refused cell (reason in its tooltip)
DH_VARIABLE_CELL_RGB = (230, 230, 230)  # background of the read-only joint-variable cell
DH_RELOAD_DELAY_MS = 200                # wait after a change on disk before reloading
DH_ERROR_STYLE = "color: #b00000"
DH_ROW_PADDING_PX = 6                   # table row height = font height + this
PICK_SPEEDS = (0.25, 0.5, 1.0, 2.0, 4.0)  # playback speed choices (1 = real time)
PICK_SPEED_FORMAT = "{speed:g}x"
PICK_SLIDER_TICKS_PER_S = 1000             # timeline resolution 1 ms
PICK_PLAY_TEXT = "Play"
PICK_PAUSE_TEXT = "Pause"
PICK_LABEL_FORMAT = "t = {t:6.3f} / {duration:.3f} s  {phase}"
PICK_LABEL_MIN_WIDTH = 220
PICK_DOCK_TITLE_PX = 24                    # room for the playback dock's title bar

# Plot dock (pyqtgraph): one row per quantity, one curve per joint
# row labels short enough for a short dock (combining dots do not render in Qt's fonts);
# the units are in the dock's title
PLOT_DOCK_TITLE = "Joint plots: q [rad | m], qd [rad/s | m/s], qdd [rad/s² | m/s²], τ [N·m | N]"
PLOT_ROWS = (("q", "q"), ("qd", "qd"), ("qdd", "qdd"), ("effort", "τ"))
PLOT_JOINT_COLORS = ("#e41a1c", "#377eb8", "#4daf4a", "#984ea3", "#ff7f00", "#a65628", "#f781bf")
PLOT_BACKGROUND = "w"
PLOT_CURSOR_COLOR = "k"
PLOT_GRID_ALPHA = 0.3
PLOT_LABEL_SIZE = "8pt"                    # axis labels and legend
PLOT_LEGEND_COLUMNS = 7                    # joints side by side in the legend row
PLOT_DOCK_MIN_HEIGHT = 240
PLOT_DOCK_HEIGHT_FRACTION = 0.35           # of the window's height when the plots open

# Workspace job state appended to the status bar while it is not idle (workspace_job.py)
STATUS_WORKSPACE_FORMAT = "   workspace: {state}"
# How long an error caught at the Qt boundary stays in the status bar (ms)
STATUS_ERROR_MS = 15000


# Help overlay layout: column pairs (keys, description) side by side when they fit
HELP_MAX_COLUMNS = 2
HELP_COLUMN_GAP_PX = 14

# View information in the GL view's bottom-left corner: grid spacing, projection, follow
# mode (the workspace cloud's colour scale is drawn in the picture: graphics/items/color_scale)
VIEW_INFO_GRID_FORMAT = "grid {step:g} m"
VIEW_INFO_MARGIN_PX = 8
VIEW_INFO_TEXT_RGB = (225, 225, 225)
VIEW_INFO_TEXT_PX = 12

#: Width of the Robot dock's chooser, in characters: longer robot paths are elided in the middle.
ROBOT_CHOOSER_CHARS = 16
