"""Constants of the viewer: sizes, colours, tessellation, camera and lighting.

Data only, no logic.  Colours are RGBA tuples of floats in [0, 1].  Robot part
sizes follow each link's own dimensions within fractions of the robot's *reach*
(the sum of its DH link lengths and offsets, see ``graphics_objects.robot_reach``),
so a 3 cm arm and a 3 m arm look alike on screen; other lengths are in metres.
"""

# --- window background --------------------------------------------------------
BACKGROUND_COLOR = (0.16, 0.18, 0.22, 1.0)

# --- tessellation of the unit meshes (built once per GL context) --------------
CYLINDER_SLICES = 16          # segments around a cylinder, disk or cone
SPHERE_SLICES = 16            # segments around a sphere (longitude)
SPHERE_STACKS = 10            # segments pole to pole (latitude)

# --- robot scale used to size the parts (metres) ------------------------------
REACH_MIN = 0.01              # a robot smaller than this (a degenerate one) is drawn at this scale
REACH_MAX = 20.0              # a robot larger than this is drawn at this scale

# --- robot part sizes -------------------------------------------------------------
# Each joint's size follows the link it moves (or a part of the link it sits on, its
# "local length"), clamped to fractions of the robot's reach; then, with the arm at
# home, every joint is shrunk until it clears its neighbours and the endeffector.
JOINT_INCOMING_WEIGHT = 0.35     # local length = max(link moved, this * link carrying the joint)
JOINT_RADIUS_LOCAL_FRAC = 0.14   # joint cylinder radius, fraction of its local length ...
JOINT_RADIUS_MIN_FRAC = 0.012    # ... at least this fraction of the reach ...
JOINT_RADIUS_MAX_FRAC = 0.035    # ... at most this one
JOINT_HALF_LENGTH_RATIO = 1.4    # revolute cylinder half length along its axis / its radius
JOINT_CLEARANCE = 0.5            # a joint's radius <= this * the distance to the nearest other joint
JOINT_CROSSING_FRAC = 0.015      # joints closer than this fraction of the reach share a housing:
                                 # drawn crossing (as at a wrist centre), not shrunk apart
PART_MIN_FRAC = 0.003            # no part radius below this fraction of the reach
LINK_RADIUS_RATIO = 0.5          # link cylinder radius / the smaller joint radius at its ends
ENDEFF_RADIUS_RATIO = 1.2        # endeffector sphere radius / the last joint's radius
ENDEFF_MIN_FRAC = 0.02           # endeffector sphere radius at least this fraction of the reach
ENDEFF_COINCIDENT_RATIO = 0.5    # an endeffector closer than this * its radius to a joint sits in it ...
ENDEFF_NEAR_RATIO = 1.2          # ... and is drawn this * the joint radius
COM_RADIUS_RATIO = 1.3           # centre-of-mass sphere radius / its link's radius
PRISMATIC_SLEEVE_RATIO = 0.8     # prismatic sleeve half width / the joint radius
PRISMATIC_ROD_RATIO = 0.55       # sliding rod radius / the joint radius
UNLIMITED_STROKE_FRAC = 0.25     # drawn stroke of an unlimited prismatic joint, fraction of the reach
BASE_PLATE_RATIO = 1.8           # base plate radius / the first joint's radius
BASE_PLATE_THICKNESS_RATIO = 0.3  # base plate thickness / its radius
MIN_LINK_LENGTH = 1e-6        # metres; shorter links and tool segments are not drawn

# --- robot colours ---------------------------------------------------------------
LINK_COLOR = (0.80, 0.80, 0.82, 1.0)      # light grey
JOINT_COLOR = (0.30, 0.30, 0.33, 1.0)     # dark grey
BASE_COLOR = (0.45, 0.45, 0.48, 1.0)      # mid grey: base plate and the line down to the floor
ENDEFF_COLOR = (0.90, 0.08, 0.08, 1.0)    # red
COM_COLOR = (0.10, 0.25, 0.95, 1.0)       # blue
TRANSLUCENT_ALPHA = 0.35                  # robot alpha when transparency is on
GHOST_COLOR = (0.30, 0.85, 1.00, 0.40)    # desired state, drawn translucent where it differs
GHOST_TOLERANCE = 1e-6                    # metres: ghost parts closer than this to the arm's are not drawn
GHOST_POLYGON_OFFSET = (1.0, 4.0)         # pushes the ghost behind an arm surface it touches

# --- coordinate frames (RGB axes with cone tips) ---------------------------------
FRAME_LENGTH_FRAC = 0.16      # axis length, fraction of the reach
FRAME_SHAFT_RADIUS_FRAC = 0.035  # shaft radius, fraction of the axis length
FRAME_HEAD_RADIUS_FRAC = 0.09    # cone radius, fraction of the axis length
FRAME_HEAD_LENGTH_FRAC = 0.25    # cone length, fraction of the axis length
FRAME_STACK_LENGTH_STEP = 0.15   # a frame sharing its origin with k earlier ones: 1 + k * this longer ...
FRAME_STACK_THINNING = 0.2       # ... and 1 - k * this thinner, so its tips show beyond the others
FRAME_STACK_RADIUS_STEPS = (1.0, 0.94, 0.88)  # shaft radius factors cycled over frames: no shared surfaces
FRAME_LABEL_FRAC = 0.3           # label anchor: this fraction of the axis length between x and y

# --- labels (bitmap text, the same in the window and offscreen) ----------------
LABEL_PIXEL_SCALE = 2         # 5 x 7 glyphs drawn this many pixels per font pixel
LABEL_OFFSET_PX = (4, 4)      # text starts this far right of and above its anchor's pixel
LABEL_COLOR = (1.0, 1.0, 1.0, 1.0)
LABEL_SHADOW_COLOR = (0.0, 0.0, 0.0, 1.0)

# --- DH parameter annotation of one joint (GraphicsOptions.annotate_joint) ---------
ANNOTATION_OFFSET_FRAC = 0.35  # dimension lines this fraction of the frame axis length beside the segment
ANNOTATION_TICK_FRAC = 0.12    # arrowhead size, fraction of the frame axis length
ANNOTATION_ARC_FRAC = 0.6      # angle arc radius, fraction of the frame axis length
ANNOTATION_SPOKE_RATIO = 1.25  # the dashed directions an angle lies between: this * the arc radius
ANNOTATION_ARC_SEGMENTS = 64   # line segments of a full circle
ANNOTATION_LINE_WIDTH = 2.0    # pixels
ANNOTATION_DASH = (2, 0x3333)  # glLineStipple(factor, pattern) of extension lines and spokes
ANNOTATION_COLORS = {
    "d": (0.25, 0.70, 1.00, 1.0),      # along z: light blue
    "a": (1.00, 0.35, 0.25, 1.0),      # along x: light red
    "theta": (1.00, 0.90, 0.20, 1.0),  # about z: yellow
    "alpha": (0.85, 0.25, 1.00, 1.0),  # about x: violet
}
AXIS_X_COLOR = (0.95, 0.10, 0.10, 1.0)
AXIS_Y_COLOR = (0.10, 0.85, 0.10, 1.0)
AXIS_Z_COLOR = (0.15, 0.25, 1.00, 1.0)

# --- vectors (arrows drawn from a point along a world vector) -----------------
VECTOR_SHAFT_RADIUS_FRAC = 0.008  # shaft radius, fraction of the reach
VECTOR_HEAD_RADIUS_FRAC = 0.022   # cone radius, fraction of the reach
VECTOR_HEAD_LENGTH_FRAC = 0.06    # cone length, fraction of the reach (at most half the arrow)
LINEAR_VELOCITY_COLOR = (1.00, 0.55, 0.00, 1.0)   # orange
GHOST_APART_TOL = 0.01             # rad or m: physical modes draw the ghost beyond this error
PULL_COLOR = (0.10, 0.95, 0.60, 1.0)              # mouse pull spring: endeffector -> anchor
ANGULAR_VELOCITY_COLOR = (0.75, 0.20, 0.95, 1.0)  # purple

# --- IK target: a small frame and a marker sphere ------------------------------
TARGET_FRAME_LENGTH_FRAC = 0.10     # fraction of the reach
TARGET_MARKER_RADIUS_FRAC = 0.022   # fraction of the reach
TARGET_COLOR = (1.00, 0.85, 0.00, 1.0)              # yellow: reachable
TARGET_UNREACHABLE_COLOR = (1.00, 0.00, 0.85, 1.0)  # magenta: warning

# --- floor and grid (z = 0 in the world): translucent, the arm passes through it ----
GROUND_COLOR = (0.42, 0.44, 0.47, 0.35)  # the floor's alpha: parts below it show through
GRID_COLOR = (0.62, 0.64, 0.68, 0.8)
GROUND_EXTENT_FRAC = 1.5      # half side of the floor square, fraction of the reach
GRID_LINES_PER_HALF = 10      # about this many grid cells from the centre to an edge
GRID_STEPS = (0.001, 0.002, 0.005, 0.01, 0.02, 0.05, 0.1, 0.2, 0.25, 0.5, 1.0, 2.0, 5.0)  # metres, first >= target used
BASE_LINE_STIPPLE = (2, 0x0F0F)  # glLineStipple(factor, pattern) of the line from a raised base to the floor

# --- workspace point cloud ---------------------------------------------------------
WORKSPACE_POINT_SIZE = 2.0    # pixels
# Colormap stops (value in [0, 1], r, g, b), interpolated linearly (viridis-like).
WORKSPACE_COLORMAP = (
    (0.00, 0.267, 0.005, 0.329),
    (0.25, 0.229, 0.322, 0.546),
    (0.50, 0.128, 0.567, 0.551),
    (0.75, 0.369, 0.789, 0.383),
    (1.00, 0.993, 0.906, 0.144),
)

# --- camera -----------------------------------------------------------------------
CAMERA_DISTANCE = 3.0         # metres from the target
CAMERA_AZIMUTH_DEG = 45.0     # eye direction about world z, from +x
CAMERA_ELEVATION_DEG = 25.0   # eye direction above the xy plane
CAMERA_FOV_DEG = 45.0         # vertical field of view
CAMERA_MAX_ELEVATION_DEG = 89.0   # |elevation| is clamped to this
CAMERA_MIN_DISTANCE = 0.005   # metres
CAMERA_MAX_DISTANCE = 200.0   # metres
CAMERA_NEAR_FRAC = 0.01       # near plane at this fraction of the distance
CAMERA_FAR_FRAC = 20.0        # far plane at this multiple of the distance ...
CAMERA_FAR_MARGIN = 10.0      # ... plus this many metres
CAMERA_FIT_MARGIN = 1.15      # fit() leaves this much room around the points
CAMERA_FIT_MIN_RADIUS = 0.002  # metres; fit() frames at least a sphere this big

# --- lighting (fixed-function) ------------------------------------------------------
# Light 0 is a headlight (eye space, shines along the view); light 1 is fixed in
# the world, from above.  Positions are homogeneous with w = 0 (directional).
HEADLIGHT_DIRECTION = (0.3, 0.4, 1.0, 0.0)
HEADLIGHT_DIFFUSE = (0.65, 0.65, 0.65, 1.0)
SKYLIGHT_DIRECTION = (0.2, -0.3, 1.0, 0.0)
SKYLIGHT_DIFFUSE = (0.30, 0.30, 0.30, 1.0)
AMBIENT_LIGHT = (0.30, 0.30, 0.30, 1.0)
SPECULAR_COLOR = (0.25, 0.25, 0.25, 1.0)
SHININESS = 32.0

# --- offscreen rendering --------------------------------------------------------------
DEPTH_BUFFER_BITS = 24  # bits of depth buffer both hosts (OSMesa and the Qt widget) ask for
OSMESA_STENCIL_BITS = 0
OSMESA_PACKAGE = "libosmesa6"  # Debian package that provides libOSMesa


# ---------------------------------------------------------------------------
# Window (window.py) constants — owned by the simulator/window engineer.
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
    ("C", "", "toggle_demo", None, "circle demo (differential IK) on / off"),
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
    ("B", "", "toggle_trail", None, "endeffector trail on / off"),
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

# Window geometry and command line limits
WINDOW_DEFAULT_SIZE = (1024, 768)    # px, --size default (window and screenshot)
WINDOW_SIZE_LIMITS = (16, 8192)      # px, accepted range of each --size value
DOCK_MIN_WIDTH = 260                 # px

# Joint sliders: integer slider ticks per unit shown in the label
SLIDER_TICKS_PER_DEG = 10            # revolute resolution 0.1 deg
SLIDER_TICKS_PER_M = 1000            # prismatic resolution 1 mm
UNLIMITED_REVOLUTE_RANGE_DEG = 180.0 # slider range of a revolute joint without limits
UNLIMITED_PRISMATIC_RANGE_M = 1.0    # slider range of a prismatic joint without limits

# Dynamics in the dock: per-joint effort bars (fraction of the effort limit) and the
# flash of a joint that hits a limit
EFFORT_BAR_STEPS = 1000              # QProgressBar range 0..STEPS: |effort| / limit
EFFORT_BAR_HEIGHT_PX = 16
EFFORT_BAR_FORMAT = "{percent:+.0f} %"  # the bar's text: signed effort, percent of the limit
EFFORT_BAR_COLOR = "#3a8ee6"         # blue: within the limit
EFFORT_BAR_SATURATED_COLOR = "#e03030"  # red: saturated at the effort limit
LIMIT_FLASH_COLOR = "#ff5050"        # joint label colour after a limit hit
LIMIT_FLASH_MS = 600

# Status bar
STATUS_FORMAT = "{robot} | {fps}"  # permanent, right; one-off messages on its left
STATUS_FPS_FORMAT = "{fps:.0f} fps"
STATUS_FPS_IDLE = "idle"
STATUS_TARGET_UNREACHABLE = " | IK target UNREACHABLE (pos err {pos_err:.3f} m, rot err {rot_err_deg:.1f} deg)"
STATUS_MESSAGE_MS = 5000             # how long transient status messages stay
FPS_WINDOW_S = 1.0                   # frame rate = paints within the last second

# Camera steps
KEY_ORBIT_STEP_DEG = 5.0
KEY_ZOOM_FACTOR = 1.15               # per W / S press
MOUSE_ORBIT_DEG_PER_PX = 0.4
WHEEL_ZOOM_FACTOR = 1.1              # per wheel notch (120 eighths of a degree)

# IK target and animation
TARGET_STEP_M = 0.02                 # per I/K/J/L/U/O press
TARGET_STEP_DEG = 5.0                # per Shift+I/K/J/L/U/O press
ANIM_INTERVAL_MS = 16                # animation / demo timer period
ANIM_SPEED_REVOLUTE = 1.5            # rad/s, current joints moving toward the ghost
ANIM_SPEED_PRISMATIC = 0.3           # m/s
ANIM_ARRIVED_TOL = 1e-6              # rad or m

# Circle demo (differential IK)
DEMO_CIRCLE_RADIUS_M = 0.1
DEMO_CIRCLE_PERIOD_S = 4.0
DEMO_FEEDBACK_GAIN = 5.0             # 1/s, pulls the endeffector back onto the circle

# Motion vectors: arrow length per unit velocity
# (arrows start on the endeffector sphere's surface, so all of an arrow shows; the
# circle demo's 0.16 m/s makes a 0.24 m arrow)
VECTOR_SCALE_LINEAR = 1.5            # m of arrow per m/s
VECTOR_SCALE_ANGULAR = 0.3           # m of arrow per rad/s (colours: *_VELOCITY_COLOR above)

# Workspace cloud
WORKSPACE_DEFAULT_POINTS = 200_000
WORKSPACE_SEED = 0

# Help overlay (QPainter over the GL picture)
HELP_FONT_FAMILY = "monospace"
HELP_FONT_PT = 9
HELP_MARGIN_PX = 12
HELP_BACKGROUND_RGBA = (0, 0, 0, 225)
HELP_TEXT_RGB = (235, 235, 235)

# Screenshots saved with P: into this folder of the working directory (created)
SCREENSHOT_DIR = "screenshots"
SCREENSHOT_NAME_FORMAT = "robot-sim-{robot}-{stamp}.png"

# View presets (Ctrl+1..4): camera (azimuth, elevation) in degrees, target and distance kept.
# front: eye on +x looking back at the base; side: eye on -y (x to the right);
# top: looking down (x right, y up); iso: eye along (1, 1, 1).
VIEW_PRESETS = {
    "front": (0.0, 0.0),
    "side": (-90.0, 0.0),
    "top": (-90.0, 90.0),
    "iso": (45.0, 35.26438968),
}

# Endeffector readout (window dock): world pose and manipulability
READOUT_FONT_PT = 8
READOUT_FORMAT = ("xyz [m]   {x:+.4f} {y:+.4f} {z:+.4f}\n"
                  "rpy [deg] {roll:+.2f} {pitch:+.2f} {yaw:+.2f}\n"
                  "quat wxyz {qw:+.4f} {qx:+.4f} {qy:+.4f} {qz:+.4f}\n"
                  "manipulability {m:.4g}")

# Endeffector trail (toggle key in KEY_BINDINGS)
TRAIL_MAX_POINTS = 4000              # oldest points dropped beyond this
TRAIL_MIN_STEP_M = 0.002             # a point closer than this to the last is not stored
TRAIL_COLOR = (1.0, 0.40, 0.70, 1.0)  # pink: distinct from axes, robot, ghost, target, pick path and object
TRAIL_WIDTH_PX = 2.0

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

# Pick task (--demo pick): table, object, two-finger gripper, planned endeffector path
TABLE_COLOR = (0.50, 0.35, 0.20, 1.0)     # wood brown
OBJECT_COLOR = (0.60, 0.20, 0.75, 1.0)    # purple block (orange is the velocity arrow)
GRIPPER_COLOR = (0.20, 0.22, 0.28, 1.0)   # dark steel
PATH_COLOR = (0.95, 0.85, 0.10, 1.0)      # yellow line
PATH_LINE_WIDTH_PX = 2.0
PATH_SAMPLE_STEP = 10                      # draw every 10th sample of the 1 kHz plan
GRIPPER_FINGER_THICKNESS_M = 0.008         # across the grip (tool y)
GRIPPER_FINGER_WIDTH_M = 0.02              # along tool x
GRIPPER_FINGER_TIP_PAST_M = 0.01           # fingertips this far past the tool point
GRIPPER_PALM_THICKNESS_M = 0.012
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

# --record: offscreen frames written to DIR
RECORD_FRAME_FORMAT = "frame_{index:05d}.png"
RECORD_VIDEO_NAME = "recording.mp4"     # beside the frames, when the optional `video` extra is installed
RECORD_VIDEO_QUALITY = 8                # imageio-ffmpeg quality, 0 (worst) .. 10 (best)
RECORD_DEFAULT_FPS = 25.0
RECORD_DEFAULT_DURATION_S = 5.0           # without the pick demo (whose length is the default)
RECORD_MAX_FPS = 1000.0

# Workspace job state appended to the status bar while it is not idle (workspace_job.py)
STATUS_WORKSPACE_FORMAT = "   workspace: {state}"
# How long an error caught at the Qt boundary stays in the status bar (ms)
STATUS_ERROR_MS = 15000


# Help overlay layout: column pairs (keys, description) side by side when they fit
HELP_MAX_COLUMNS = 2
HELP_COLUMN_GAP_PX = 14

# View information in the GL view's corners: grid spacing, projection, follow mode,
# and the colour legend of the workspace cloud (coloured by manipulability)
VIEW_INFO_GRID_FORMAT = "grid {step:g} m"
VIEW_INFO_MARGIN_PX = 8
VIEW_INFO_TEXT_RGB = (225, 225, 225)
LEGEND_BAR_SIZE_PX = (160, 12)       # width, height
LEGEND_TEXT_PX = 12
LEGEND_TITLE = "manipulability √det(J Jᵀ)"
