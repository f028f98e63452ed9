"""``robot-sim calibrate`` and ``robot-sim calibration-poses``: kinematic calibration from
the command line.

    robot-sim calibration-poses --robot ur5 -n 50 --out poses.csv
    robot-sim calibrate --robot ur5 --data meas.csv --out calibrated.toml [--report report.png]

``calibration-poses`` writes the joint values to measure (CSV, degrees and millimetres);
``calibrate`` reads the measurements (:mod:`robot_sim.io.calibration_csv`), prints the
parameter table, what the data cannot identify and the residuals before and after (a
progress line per iteration goes to stderr), and writes the calibrated robot file (the
source's comments kept, a note added) and optionally the report picture.  Bad input is
one ``robot-sim <command>: error: ...`` line on stderr with exit status 2.
"""
from __future__ import annotations

import argparse
import shlex
import sys
from typing import Sequence

import numpy as np

from robot_sim.calibration.calibrate import CalibrationResult, calibrate
from robot_sim.calibration.poses import calibration_poses
from robot_sim.io.calibration_csv import load_calibration_data, save_calibration_csv
from robot_sim.io.files import FileError, check_writable
from robot_sim.io.robot_file import load_robot
from robot_sim.io.robot_writer import save_robot
from robot_sim.model.params import RobotDefinitionError

COMMANDS = ("calibrate", "calibration-poses")


class CalibrateCliError(Exception):
    """Bad command-line input (the message says which option and what is accepted)."""


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> None:  # type: ignore[override]
        raise CalibrateCliError(message)


def build_parser(command: str) -> argparse.ArgumentParser:
    parser = _Parser(prog=f"robot-sim {command}")
    parser.add_argument("--robot", required=True, help="robot name or file")
    if command == "calibrate":
        parser.description = "Identify a robot's DH table, joint offsets, base and tool from measurements."
        parser.add_argument("--data", required=True, help="measurements (CSV: q1 [deg], ..., x [mm], y [mm], z [mm])")
        parser.add_argument("--out", required=True, help="calibrated robot file (.toml) to write")
        parser.add_argument("--report", help="PNG picture of the residuals before and after")
        parser.add_argument("--robust", action="store_true", help="give outlying poses less weight (Huber)")
    else:
        parser.description = "Write the joint configurations to measure for calibration."
        parser.add_argument("-n", type=int, required=True, help="number of poses")
        parser.add_argument("--measurement", choices=("position", "pose"), default="position",
                            help="what the instrument measures (default position)")
        parser.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
        parser.add_argument("--out", required=True, help="CSV file to write")
    return parser


def result_text(res: CalibrationResult) -> str:
    """The parameter table, the unidentifiable list and the residuals, as printed."""
    lines = [f"{'parameter':<15}{'nominal':>16}{'identified':>16}{'change':>14}{'std':>12}"]
    for p in res.parameters:
        angle = p.name.startswith(("alpha", "theta", "beta")) or p.name.split(".")[-1].startswith("r")
        unit, scale = ("°", np.degrees(1.0)) if angle else ("mm", 1e3)
        std = "fixed" if not np.isfinite(p.std) else f"{p.std * scale:.3g}"
        lines.append(f"{p.name:<15}{p.nominal * scale:>14.6g}{unit:>2}{p.identified * scale:>14.6g}{unit:>2}"
                     f"{(p.identified - p.nominal) * scale:>12.4g}{unit:>2}{std:>12}")
    lines.append("")
    lines.append("not identifiable from these data (kept at their nominal values):")
    lines += [f"  {u.name}: {u.reason}" for u in res.unidentifiable] or ["  (none)"]
    lines.append("")
    lines.append(f"poses: {res.n_poses}; condition number {res.condition_number:.4g}; observability O1 {res.observability:.4g}")
    lines.append(f"position error RMS {res.rms_before * 1e3:.4g} mm before, {res.rms_after * 1e3:.4g} mm after; "
                 f"max {res.max_before * 1e3:.4g} mm before, {res.max_after * 1e3:.4g} mm after")
    if res.rms_rotation_before is not None:
        lines.append(f"rotation error RMS {np.degrees(res.rms_rotation_before):.4g}° before, "
                     f"{np.degrees(res.rms_rotation_after):.4g}° after")
    lines.append(f"held-out fifth ({len(res.holdout.poses)} poses, fitted without them): RMS {res.holdout.rms * 1e3:.4g} mm, "
                 f"max {res.holdout.max * 1e3:.4g} mm")
    lines.append(f"DH table vs identified model: {res.table_error:.2g} m at most")
    return "\n".join(lines)


def _run(command: str, argv: list[str]) -> int:
    args = build_parser(command).parse_args(argv)
    try:
        robot = load_robot(args.robot)
    except (RobotDefinitionError, FileError) as exc:
        raise CalibrateCliError(f"--robot: {exc}") from None
    check_writable(args.out)
    if command == "calibration-poses":
        try:
            q = calibration_poses(robot, args.n, measurement=args.measurement, seed=args.seed)
        except ValueError as exc:
            raise CalibrateCliError(f"-n: {exc}") from None
        save_calibration_csv(args.out, q, robot.is_revolute)
        print(f"wrote {len(q)} poses of {robot.name} to {args.out}")
        return 0
    if args.report is not None:
        check_writable(args.report)
    data = load_calibration_data(args.data)

    def progress(text: str) -> None:
        print(f"\r{text}", end="", file=sys.stderr, flush=True)

    res = calibrate(robot, data, robust=args.robust, progress=progress)
    print(file=sys.stderr)
    print(result_text(res))
    save_robot(res.robot, args.out)
    print(f"wrote {args.out}")
    if args.report is not None:
        from robot_sim.app.calibration_report import write_report

        write_report(res, args.report, shlex.join(["robot-sim", command, *argv]))
        print(f"wrote {args.report}")
    return 0


def main(argv: Sequence[str]) -> int:
    """``robot-sim calibrate ...`` or ``robot-sim calibration-poses ...`` (argv starts with
    the command); returns the exit status (2 for bad input)."""
    command, rest = argv[0], list(argv[1:])
    try:
        return _run(command, rest)
    except (CalibrateCliError, ValueError, FileError) as exc:
        print(f"robot-sim {command}: error: {' '.join(str(exc).split())}", file=sys.stderr)
        return 2
