"""What kind of robot description a file is: a robot file (TOML), a URDF or a xacro file.

The suffix decides where it says (``.toml``, ``.urdf``, ``.xacro`` and ``.urdf.xacro``);
otherwise the first bytes do: XML whose root is ``<robot`` is a URDF (one using the
``xacro`` namespace a xacro file), anything else a robot file.  Users name URDFs
``arm.xml`` and keep them without a suffix, as ROS tools accept.
"""
from __future__ import annotations

import os
import re
from pathlib import Path

#: Kinds of robot description, by suffix (lower case).
SUFFIX_KINDS = {".toml": "toml", ".urdf": "urdf", ".xacro": "xacro"}
#: Bytes read to decide a file's kind by its content.
SNIFF_BYTES = 4096
#: What the program accepts for --robot / load_robot, for messages.
ACCEPTED = ("a shipped robot's name, a robot file (.toml), a URDF (.urdf, or XML with a <robot> root "
            "under any name) or a xacro file (.urdf.xacro, .xacro; needs pip install xacro)")
_XML_ROBOT = re.compile(rb"^\s*(<\?xml[^>]*\?>\s*)?(<!--.*?-->\s*)*<robot[\s>]", re.DOTALL)


def robot_kind(path: Path) -> str:
    """"toml", "urdf" or "xacro" for the description at ``path`` (by suffix, else by
    content; a file that cannot be opened is "toml", whose reader says why)."""
    kind = SUFFIX_KINDS.get(path.suffix.lower())
    if kind is not None:
        return kind
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | os.O_NOCTTY)
    except (OSError, ValueError):
        return "toml"
    try:
        head = os.read(fd, SNIFF_BYTES) if os.path.isfile(path) else b""
    except OSError:
        head = b""
    finally:
        os.close(fd)
    head = head.removeprefix(b"\xef\xbb\xbf")
    if not _XML_ROBOT.match(head):
        return "toml"
    return "xacro" if b"xmlns:xacro" in head else "urdf"
