"""Constants of the viewer session (robot_sim.viewer): default window size, animation speeds, the
circle demo and its gains, readout and status formats, trail, recording."""

# Window size (the window and --screenshot default)
WINDOW_DEFAULT_SIZE = (1024, 768)    # px, --size default: --screenshot and --record pictures
UNLIMITED_REVOLUTE_RANGE_DEG = 180.0 # slider range of a revolute joint without limits
UNLIMITED_PRISMATIC_RANGE_M = 1.0    # slider range of a prismatic joint without limits

# Status bar
STATUS_FORMAT = "{robot} | {fps}"  # permanent, right; one-off messages on its left
STATUS_TARGET_UNREACHABLE = " | IK target UNREACHABLE (pos err {pos_err:.3f} m, rot err {rot_err_deg:.1f} deg)"
STATUS_POSITION_UNREACHABLE = " | IK target UNREACHABLE (pos err {pos_err:.3f} m)"  # arms that only place the tool
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
WORKSPACE_SEED = 0
READOUT_FORMAT = ("xyz [m]   {x:+.4f} {y:+.4f} {z:+.4f}\n"
                  "rpy [deg] {roll:+.2f} {pitch:+.2f} {yaw:+.2f}\n"
                  "quat wxyz {qw:+.4f} {qx:+.4f} {qy:+.4f} {qz:+.4f}\n"
                  "manipulability {m:.4g}")
#: Added below the pose in a physical mode: the tool's distance from its desired pose.
READOUT_TRACKING_FORMAT = "\ntracking error {mm:.2f} mm {deg:.2f}°"

# Endeffector trail (toggle key in KEY_BINDINGS)
TRAIL_MAX_POINTS = 4000              # oldest points dropped beyond this
TRAIL_MIN_STEP_M = 0.002             # a point closer than this to the last is not stored
TRAIL_SAMPLE_S = 0.01                # simulated at once (--duration), the trail takes a point this often
PATH_SAMPLE_STEP = 10                      # draw every 10th sample of the 1 kHz plan

# --record: offscreen frames written to DIR
RECORD_FRAME_FORMAT = "frame_{index:05d}.png"
RECORD_VIDEO_NAME = "recording.mp4"     # beside the frames, when the optional `video` extra is installed
RECORD_VIDEO_QUALITY = 8                # imageio-ffmpeg quality, 0 (worst) .. 10 (best)

# Key commands (robot_sim.viewer.commands): camera and IK target steps per press
KEY_ORBIT_STEP_DEG = 5.0
KEY_ZOOM_FACTOR = 1.15               # per W / S press
TARGET_STEP_M = 0.02                 # per I/K/J/L/U/O press
TARGET_STEP_DEG = 5.0                # per Shift+I/K/J/L/U/O press
# View presets (Ctrl+1..4): camera (azimuth, elevation) in degrees, target and distance kept.
# front: eye on +x looking back at the base; side: eye on -y (x to the right);
# top: looking down (x right, y up); iso: eye along (1, 1, 1).
VIEW_PRESETS = {
    "front": (0.0, 0.0),
    "side": (-90.0, 0.0),
    "top": (-90.0, 90.0),
    "iso": (45.0, 35.26438968),
}

