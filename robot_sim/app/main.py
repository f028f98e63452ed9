"""``robot-sim``'s entry point (thin, as MuJoCo's viewer): parse the command line
(:mod:`robot_sim.app.cli`), prepare the robot and the session (:mod:`robot_sim.app.prepare`),
then output: the robot actions, the offscreen pictures, or the window
(:mod:`robot_sim.app.output`).

Bad input is reported as one ``robot-sim: error: ...`` line with exit status 2;
``--screenshot`` renders offscreen through OSMesa without importing Qt at all.
"""
from __future__ import annotations

import os
import shlex
import sys
from typing import Sequence

# The renderer (llvmpipe) needs both cores; OpenBLAS worker threads spinning after the
# small matrix products of each frame only compete with it.  Set before NumPy loads.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

from robot_sim.app.cli import PROG, CliError, build_parser, parse_args  # noqa: E402
from robot_sim.app import web_cmd  # noqa: E402
from robot_sim.app.prepare import Config, config_from_args, session_from_config  # noqa: E402

__all__ = ["Config", "build_parser", "config_from_args", "launch", "main"]


def launch(config: Config) -> int:
    """Open the viewer window for a prepared ``config`` (robot_sim.app.output.launch)."""
    from robot_sim.app import output

    return output.launch(config)


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of ``robot-sim``; returns the exit status (2 for bad input)."""
    argv = list(sys.argv[1:] if argv is None else argv)
    if argv[:1] == ["sweep"]:  # robot-sim sweep ...: its own parser (robot_sim.app.sweep_cmd)
        from robot_sim.app import sweep_cmd

        return sweep_cmd.main(argv[1:])
    if argv[:1] in (["calibrate"], ["calibration-poses"]):  # robot_sim.app.calibrate_cmd
        from robot_sim.app import calibrate_cmd

        return calibrate_cmd.main(argv)
    try:
        args = parse_args(argv)
        if args.list_robots:
            from robot_sim.app.robot_cmds import robots_table

            print(robots_table())
            return 0
        config = config_from_args(args)
        config.command = shlex.join([PROG, *argv])
        from robot_sim.app import output

        if output.robot_actions(args, config.robot) and config.screenshot is None:
            return 0
        if config.pick_report is not None:
            print(config.pick_report)
        if config.record is not None:
            frames, video = output.write_recording(config)
            print(f"wrote {len(frames)} frames to {config.record}" + (f" and {video}" if video else ""))
            return 0
        if web_cmd.wanted(args):  # --web, --export-html: the browser view (robot_sim.app.web_cmd)
            return web_cmd.run(args, config, session_from_config, CliError)
        if config.screenshot is not None:
            output.write_screenshot(config)
            print(f"wrote {config.screenshot}")
            return 0
        output.check_display()
    except CliError as exc:
        message = " ".join(str(exc).split())
        print(f"{PROG}: error: {message}", file=sys.stderr)
        return 2
    except BrokenPipeError:
        # The reader of a table went away (`--print-dh | head`): stop quietly, and point
        # stdout at /dev/null so the interpreter's final flush cannot raise again.
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 1
    return output.launch(config)
