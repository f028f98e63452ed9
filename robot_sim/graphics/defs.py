"""Constants of the viewer: sizes, colours, tessellation, camera and lighting.

Data only, no logic.  Colours are RGBA tuples of floats in [0, 1].  Robot part
sizes follow each link's own dimensions within fractions of the robot's *reach*
(the sum of its DH link lengths and offsets, see ``robot_sim.graphics.robot_reach``),
so a 3 cm arm and a 3 m arm look alike on screen; other lengths are in metres.
The colours of the world around the robot (background, floor, labels) are the
themes' (``themes.THEMES``).
"""

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
PEDESTAL_RADIUS_RATIO = 0.8      # column under a raised base / the base plate radius
MIN_LINK_LENGTH = 1e-6        # metres; shorter links and tool segments are not drawn

# --- robot colours ---------------------------------------------------------------
LINK_COLOR = (0.80, 0.80, 0.82, 1.0)      # light grey
JOINT_COLOR = (0.40, 0.41, 0.44, 1.0)     # dark grey (light enough to read on the dark floor)
BASE_COLOR = (0.52, 0.53, 0.56, 1.0)      # mid grey: the base plate
ENDEFF_COLOR = (0.90, 0.08, 0.08, 1.0)    # red
COM_COLOR = (0.10, 0.25, 0.95, 1.0)       # blue
TRANSLUCENT_ALPHA = 0.35                  # robot alpha when transparency is on
GHOST_COLOR = (0.30, 0.85, 1.00, 0.40)    # desired state, drawn translucent where it differs
GHOST_TOLERANCE = 1e-6                    # metres: ghost parts closer than this to the arm's are not drawn
GHOST_POLYGON_OFFSET = (1.0, 4.0)         # pushes the ghost behind an arm surface it touches
PEDESTAL_COLOR = (0.60, 0.62, 0.66, 0.30)  # the column under a raised base: see-through

# --- looks of the robot (visuals.LOOKS) ----------------------------------------------
SOLID_LINK_RATIO = 0.8                 # solid look: capsule radius / the smaller joint radius at its ends
SOLID_HOUSING_RATIO = 1.08             # solid look: housing radius / the joint radius
SOLID_LINK_COLOR = (0.86, 0.86, 0.84, 1.0)     # warm white, as industrial arms are painted
SOLID_HOUSING_COLOR = (0.24, 0.26, 0.29, 1.0)  # dark grey
VISUAL_COLOR = (0.78, 0.79, 0.81, 1.0)  # a visual shape without a colour of its own
MESH_OVER_DH_ALPHA = 0.35               # look "both": the meshes' alpha over the DH segments

# --- coordinate frames (RGB axes with cone tips) ---------------------------------
FRAME_LENGTH_FRAC = 0.16      # axis length, fraction of the reach
FRAME_SHAFT_RADIUS_FRAC = 0.035  # shaft radius, fraction of the axis length
FRAME_HEAD_RADIUS_FRAC = 0.09    # cone radius, fraction of the axis length
FRAME_HEAD_LENGTH_FRAC = 0.25    # cone length, fraction of the axis length
FRAME_STACK_LENGTH_STEP = 0.15   # a frame sharing its origin with k earlier ones: 1 + k * this longer ...
FRAME_STACK_THINNING = 0.2       # ... and 1 - k * this thinner, so its tips show beyond the others
FRAME_STACK_RADIUS_STEPS = (1.0, 0.94, 0.88)  # shaft radius factors cycled over frames: no shared surfaces
FRAME_LABEL_FRAC = 0.3           # label anchor: this fraction of the axis length between x and y

# --- labels (font.py: vector font through FreeType, the same in the window and offscreen)
LABEL_OFFSET_PX = (4, 4)      # text starts this far right of and above its anchor's pixel
LABEL_GAP_PX = 2              # labels moved apart keep this many pixels between their boxes

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

# --- floor and grid (z = 0 in the world, colours from the theme): translucent, the arm passes through it
GROUND_EXTENT_FRAC = 1.5      # half side of the floor square, fraction of the reach
FLOOR_FADE_START = 0.7        # the floor and its grid fade out from this fraction of the half side to the edge
GRID_LINES_PER_HALF = 10      # about this many grid cells from the centre to an edge
GRID_STEPS = (0.001, 0.002, 0.005, 0.01, 0.02, 0.05, 0.1, 0.2, 0.25, 0.5, 1.0, 2.0, 5.0)  # metres, first >= target used

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
CAMERA_FIT_FILL = 0.7         # fit(): the points' projection spans this fraction of the picture
CAMERA_FIT_STEPS = 3          # fit(): rounds of (distance for the extent, centre the projection)
CAMERA_FIT_MIN_RADIUS = 0.002  # metres; fit() frames at least a sphere this big

# --- lighting and shadows (shaders.py, lighting.py) -----------------------------------
KEY_LIGHT_COLOR = (0.58, 0.58, 0.58)   # the key light (casts shadows), fixed in the world
FILL_LIGHT_COLOR = (0.50, 0.50, 0.50)  # the fill light, following the camera
SKY_AMBIENT = (0.37, 0.37, 0.37)       # hemisphere ambient: faces turned up ...
GROUND_AMBIENT = (0.22, 0.22, 0.22)    # ... and faces turned down
SPECULAR_STRENGTH = 0.35               # Blinn-Phong highlight of the key light
SHININESS = 40.0                       # Blinn-Phong exponent
SHADOW_MAP_SIZE = 1024                 # texels a side of the shadow map
MESH_DETAIL_PX = 2.0                   # meshes are drawn with their vertices clustered on a grid up to this many pixels wide
SHADOW_FOOTPRINT_MARGIN_TEXELS = 3.0   # the floor's shadow patch reaches this far past the casters (PCF taps: 1.75)
SHADOW_CASTER_CELL_TEXELS = 4.0        # meshes cast shadows from their vertices clustered on a grid up to this many texels wide
SHADOW_BIAS = 0.002                    # depth bias (light clip units / 2) against shadow acne
SHADOW_POLYGON_OFFSET = (2.0, 4.0)     # glPolygonOffset(factor, units) of the shadow pass
MSAA_SAMPLES = 4                       # multisample anti-aliasing (window and offscreen); 0: off

# --- offscreen rendering --------------------------------------------------------------
DEPTH_BUFFER_BITS = 24  # bits of depth buffer both hosts (OSMesa and the Qt widget) ask for
OSMESA_STENCIL_BITS = 0
OSMESA_PACKAGE = "libosmesa6"  # Debian package that provides libOSMesa

TRAIL_COLOR = (1.0, 0.40, 0.70, 1.0)  # pink: distinct from axes, robot, ghost, target, pick path and object
TRAIL_WIDTH_PX = 2.0

# Pick task (--demo pick): table, object, two-finger gripper, planned endeffector path
TABLE_COLOR = (0.50, 0.35, 0.20, 1.0)     # wood brown
OBJECT_COLOR = (0.60, 0.20, 0.75, 1.0)    # purple block (orange is the velocity arrow)
TASK_OBSTACLE_COLOR = (0.20, 0.55, 0.50, 1.0)  # teal: the task's walls and posts (unlike floor, arm, pull spring)
GRIPPER_COLOR = (0.20, 0.22, 0.28, 1.0)   # dark steel
PATH_COLOR = (0.95, 0.85, 0.10, 1.0)      # yellow line
PATH_LINE_WIDTH_PX = 2.0
GRIPPER_FINGER_THICKNESS_M = 0.008         # across the grip (tool y)
GRIPPER_FINGER_WIDTH_M = 0.02              # along tool x
GRIPPER_FINGER_TIP_PAST_M = 0.01           # fingertips this far past the finger length
GRIPPER_PALM_THICKNESS_M = 0.012

# Collision display (key C): the robot's collision shapes, red where they touch, the
# world's obstacles, and the closest checked pair's line with its distance
COLLISION_SHAPE_COLOR = (0.25, 0.90, 0.45, 0.35)  # translucent green: clear of everything
COLLISION_CONTACT_COLOR = (1.00, 0.10, 0.10, 0.70)  # red: a shape in contact
COLLISION_OBSTACLE_COLOR = (0.55, 0.60, 0.70, 0.55)  # see-through steel: the world's obstacles
CLOSEST_COLOR = (0.10, 0.90, 1.00, 1.0)             # cyan line between the closest pair's points
CLOSEST_WIDTH_PX = 2.0
CLOSEST_POINT_RADIUS_M = 0.006                      # dots at the closest pair's witness points
