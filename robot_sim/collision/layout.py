"""How a posed shape is packed for the compiled kernels: a kind code and one float record.

A record (``REC`` floats) holds the shape's pose in the world (rotation row-major, then
translation, metres) and its sizes.  Spheres and capsules are stored as a *core* (a point,
a segment along the pose's z) swept by a radius; boxes, cylinders, convex vertex sets and
half-spaces are stored as they are.  Convex shapes keep their vertices (in the shape
frame) in one shared (V, 3) array; the record names their first row and count.
"""
from __future__ import annotations

SPHERE, CAPSULE, BOX, CYLINDER, CONVEX, HALFSPACE = range(6)
KIND_NAMES = ("sphere", "capsule", "box", "cylinder", "convex", "halfspace")

ROT = 0  # 9 entries: R[i, j] at ROT + 3 i + j (shape frame -> world)
POS = 9  # 3 entries: the shape frame's origin (sphere centre, capsule and cylinder middle, box centre)
RADIUS = 12  # swept radius of the core (sphere, capsule); 0 otherwise
HALF_LENGTH = 13  # half the core segment's length (capsule) or half the height (cylinder)
HALF_X, HALF_Y, HALF_Z = 14, 15, 16  # box half extents; HALF_X is also the cylinder radius
CYL_RADIUS = HALF_X
VSTART, VCOUNT = 17, 18  # convex: first row and number of rows in the shared vertex array
REC = 19

# A half-space {n·x <= offset} is stored with n as the pose's z column and offset * n as
# its position.
