"""Command-line actions on a robot description (behind ``robot_sim.app.cli``/``simulator``), Qt- and
GL-free: ``--list-robots`` (a table), ``--print-dh`` (the DH table in both conventions),
``--export-urdf FILE`` and ``--export-toml FILE`` (written atomically).

Writing errors are OSError (``robot_sim.io.files.FileWriteError``) naming the path and the reason;
``robot_sim.app.cli.robot_actions`` reports them as one line with exit status 2.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from robot_sim.model.convert import to_convention
from robot_sim.io.files import write_atomic
from robot_sim.model.params import CONVENTIONS, JTYPE_REVOLUTE, RobotDefinitionError, RobotParams
from robot_sim.io.robot_file import available_robots, load_robot
from robot_sim.io.robot_writer import to_toml
from robot_sim.model.table_text import frame_text, number, snap
from robot_sim.io.urdf_out import to_urdf

#: Column headings of the DH table per convention: (a, α) of row i name a different link.
_DH_HEADINGS = {
    "standard": ("a_i [m]", "alpha_i [deg]"),
    "modified": ("a_{i-1} [m]", "alpha_{i-1} [deg]"),
}
_DH_FORMULAS = {
    "standard": "A_i = Rz(theta_i) Tz(d_i) Tx(a_i) Rx(alpha_i); joint i turns about z of frame i-1",
    "modified": "A_i = Rx(alpha_{i-1}) Tx(a_{i-1}) Rz(theta_i) Tz(d_i); joint i turns about z of frame i",
}


def joint_letters(robot: RobotParams) -> str:
    """Joint types base to tip as letters: R revolute, P prismatic (e.g. ``R R P R``)."""
    return " ".join("R" if t == JTYPE_REVOLUTE else "P" for t in robot.jtype)


def _table(rows: list[tuple[str, ...]]) -> str:
    """Rows (the first is the heading) as aligned, left-justified text columns."""
    widths = [max(len(row[c]) for row in rows) for c in range(len(rows[0]))]
    return "\n".join("  ".join(cell.ljust(w) for cell, w in zip(row, widths)).rstrip() for row in rows)


def robots_table() -> str:
    """The shipped robots: name, DOF, joint types, convention and description."""
    rows = [("name", "DOF", "joints", "convention", "description")]
    for name in available_robots():
        try:
            robot = load_robot(name)
        except RobotDefinitionError as exc:
            rows.append((name, "?", "?", "?", f"does not load: {exc}"))
            continue
        rows.append((name, str(robot.n_dofs), joint_letters(robot), robot.convention, robot.description or robot.name))
    return _table(rows)


def dh_table_text(robot: RobotParams) -> str:
    """The robot's DH table in both conventions (the file's own first), with joint types,
    q ranges, base and tool: angles in degrees, lengths in metres, each value snapped to
    the round number it is within 1e-15 of (model.table_text.snap)."""
    order = sorted(CONVENTIONS, key=lambda c: c != robot.convention)
    out = [f"{robot.name}: {robot.n_dofs} joints ({joint_letters(robot)}), convention of the source: {robot.convention}"]
    for convention in order:
        table = to_convention(robot, convention)
        a_head, alpha_head = _DH_HEADINGS[convention]
        rows = [("i", "type", a_head, alpha_head, "theta_i [deg]", "d_i [m]", "q range")]
        for i in range(table.n_dofs):
            revolute = table.jtype[i] == JTYPE_REVOLUTE
            scale, unit = (180.0 / math.pi, "deg") if revolute else (1.0, "m")
            lo, hi = snap(table.q_min[i]) * scale, snap(table.q_max[i]) * scale
            q_range = "unlimited" if not (np.isfinite(lo) or np.isfinite(hi)) else f"{number(lo)} .. {number(hi)} {unit}"
            rows.append((
                str(i + 1), "revolute" if revolute else "prismatic", number(table.dh_a[i]),
                number(math.degrees(snap(table.dh_alpha[i]))), number(math.degrees(snap(table.dh_th[i]))),
                number(table.dh_d[i]), q_range,
            ))
        out += ["", f"{convention} DH: {_DH_FORMULAS[convention]}", _table(rows),
                f"base: {frame_text(table.base_tf)}", f"tool: {frame_text(table.tool_tf)}"]
    return "\n".join(out)


def export(robot: RobotParams, path: str, kind: str) -> Path:
    """Write ``robot`` as ``kind`` ("urdf" or "toml") to ``path`` atomically, mesh paths
    relative to its folder; returns the path.  Raises OSError (FileWriteError) naming the
    path and the reason, ValueError for a robot the format cannot hold."""
    target = Path(path).expanduser()
    text = to_urdf(robot, path=target) if kind == "urdf" else to_toml(robot, directory=target.parent)
    write_atomic(target, text)
    return target
