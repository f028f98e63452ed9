"""Xacro robot descriptions (``arm.urdf.xacro``): expanded to URDF text with the ``xacro``
package from PyPI, an optional extra (``pip install 'robot-sim[xacro]'`` or ``pip install
xacro``).

``$(find PKG)`` is answered without ROS: a folder named ``PKG`` found the way
``package://PKG`` mesh references are (``ROS_PACKAGE_PATH``, then the file's parent
folders; :func:`robot_sim.io.meshes.package_folder`).  ``$(arg NAME)`` takes the values
given as ``NAME:=VALUE`` (the command line's ``--xacro-arg``).  Errors name the file and
the kind of fault, never the text of the file.
"""
from __future__ import annotations

import contextlib
import io
import os
from collections.abc import Sequence
from pathlib import Path

from robot_sim.io.meshes import PACKAGE_PATH_VARIABLE, package_folder
from robot_sim.model.messages import clip, clip_repr
from robot_sim.model.params import RobotDefinitionError

#: Suffixes of xacro files (lower case).
XACRO_SUFFIXES = (".xacro",)
#: Largest URDF text a xacro file may expand to (bytes), as for a URDF file.
MAX_EXPANDED_BYTES = 16 << 20
#: Most ``--xacro-arg`` values, and the longest name and value accepted.
MAX_XACRO_ARGS = 100
MAX_XACRO_ARG_CHARS = 1000


def parse_xacro_args(items: Sequence[str]) -> dict[str, str]:
    """``["name:=value", ...]`` as a mapping; ValueError naming the first bad item."""
    if len(items) > MAX_XACRO_ARGS:
        raise ValueError(f"{len(items)} xacro arguments; at most {MAX_XACRO_ARGS} are accepted")
    out: dict[str, str] = {}
    for item in items:
        name, sep, value = str(item).partition(":=")
        if not sep or not name.strip() or len(item) > MAX_XACRO_ARG_CHARS or not name.isidentifier():
            raise ValueError(f"xacro argument {clip_repr(item)}: expected NAME:=VALUE "
                             f"(a name, ':=' and a value, at most {MAX_XACRO_ARG_CHARS} characters)")
        out[name] = value
    return out


def expand_xacro(path: Path, args: dict[str, str] | None = None) -> bytes:
    """The URDF text (UTF-8) that the xacro file at ``path`` expands to with arguments
    ``args``.  RobotDefinitionError naming the file when ``xacro`` is not installed, the
    file cannot be expanded, or the result is larger than MAX_EXPANDED_BYTES."""
    try:
        import xacro
        from xacro import substitution_args
    except ImportError:
        raise RobotDefinitionError(
            f"{path}: reading .xacro files needs the xacro package (pip install xacro)") from None
    if not path.is_file():
        raise RobotDefinitionError(f"{path}: xacro file not found")
    here = Path(os.path.abspath(path)).parent
    package_path = os.environ.get(PACKAGE_PATH_VARIABLE, "")

    def find(package: str) -> str:
        folder = package_folder(package, here, package_path)
        if folder is None:
            raise LookupError(f"package '{clip(package)}' not found")
        return str(folder)

    saved = substitution_args._eval_find
    substitution_args._eval_find = find  # $(find PKG) without ROS (no ament_index_python)
    try:
        with contextlib.redirect_stderr(io.StringIO()):  # xacro's own warnings
            text = xacro.process_file(str(path), mappings=dict(args or {})).toxml()
    except Exception as exc:  # xacro raises many kinds; its messages quote the file
        raise RobotDefinitionError(
            f"{path}: xacro could not expand the file ({type(exc).__name__}); run 'xacro {clip(str(path))}' to see why"
        ) from None
    finally:
        substitution_args._eval_find = saved
    raw = text.encode("utf-8")
    if len(raw) > MAX_EXPANDED_BYTES:
        raise RobotDefinitionError(f"{path}: expands to {len(raw)} bytes of URDF; at most {MAX_EXPANDED_BYTES} are accepted")
    return raw
