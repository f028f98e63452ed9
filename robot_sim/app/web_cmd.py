"""The command line's browser options: ``--web`` (serve the interactive viewer until
Ctrl+C), ``--host``/``--port`` (where), ``--export-html FILE.html`` (a self-contained page
of the pose, the pick task or a simulated motion).  Validated before anything starts;
errors are one line (CliError)."""
from __future__ import annotations

import argparse
import dataclasses
import sys
from pathlib import Path
from typing import Any

import numpy as np

from robot_sim.io.files import FileWriteError

HOST_HELP = "with --web: the address to listen on (default 127.0.0.1: this machine only; any other prints a warning)"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Add --web, --host, --port and --export-html to ``parser``."""
    parser.add_argument("--web", action="store_true",
                        help="serve the viewer in a browser (http://127.0.0.1:8080/ by default) until Ctrl+C")
    parser.add_argument("--host", metavar="ADDRESS", help=HOST_HELP)
    parser.add_argument("--port", metavar="N", help="with --web: the port to listen on (default 8080)")
    parser.add_argument("--export-html", metavar="FILE.html",
                        help="write a self-contained page (opens offline) of the pose, or of the whole motion with "
                             "--demo pick or --motion MODE --duration T, and exit")


def wanted(args: argparse.Namespace) -> bool:
    """True when the command line asks for the browser (serve or export)."""
    return bool(args.web) or args.export_html is not None


def parse_port(text: str | None, error: type[Exception]) -> int:
    """The --port value (default 8080); ``error`` for anything but a whole number 1..65535."""
    from robot_sim.web.server import DEFAULT_PORT, PORT_RANGE

    if text is None:
        return DEFAULT_PORT
    try:
        port = int(text)
    except ValueError:
        port = -1
    if not PORT_RANGE[0] <= port <= PORT_RANGE[1]:
        raise error(f"--port: expected a whole number {PORT_RANGE[0]}..{PORT_RANGE[1]}, got '{text[:80]}'")
    return port


def motion_trajectory(session: Any, duration: float, fps: float) -> Any:
    """The simulated motion of ``session`` (in a physical mode) over ``duration`` s, sampled
    at ``fps`` from its start, as a Trajectory (velocities from the simulation)."""
    from robot_sim.planning.trajectory import Trajectory
    from robot_sim.web.export import sample_times

    times = sample_times(duration, fps)
    sim = session.motion.sim
    q, qd = [session.state.q()], [session.state.qd()]
    for gap in np.diff(times):
        sim.step(max(1, round(gap / sim.dt)))
        q.append(session.state.q())
        qd.append(session.state.qd())
    sim.take_events()
    return Trajectory(times, np.array(q), np.array(qd), np.zeros((len(times), session.robot.n_dofs)))


def run(args: argparse.Namespace, config: Any, session_from_config: Any, error: type[Exception]) -> int:
    """Serve (--web) or export (--export-html) for the validated ``config``; ``error`` is the
    command line's one-line error class.  Returns the exit status."""
    from robot_sim.web.server import DEFAULT_HOST, WebServerError

    host = DEFAULT_HOST if args.host is None else args.host
    port = parse_port(args.port, error)
    if args.export_html is not None:
        return _export(args, config, session_from_config, error)
    if not args.web:
        raise error("--host/--port: apply to --web")
    session = session_from_config(config)
    from robot_sim.web.serve import serve

    try:
        return serve(session, config.robot_arg, host, port)
    except WebServerError as exc:
        raise error(f"--web: {exc}") from None


def _export(args: argparse.Namespace, config: Any, session_from_config: Any, error: type[Exception]) -> int:
    from robot_sim.web.export import EXPORT_FPS, export_html

    path, fps = Path(args.export_html), EXPORT_FPS
    simulated = config.motion is not None and config.pick_plan is None and config.simulate > 0.0
    session = session_from_config(dataclasses.replace(config, simulate=0.0) if simulated else config)
    try:
        trajectory = motion_trajectory(session, config.simulate, fps) if simulated else None
        written = export_html(session, path, trajectory=trajectory, fps=fps)
    except (ValueError, FileWriteError) as exc:
        raise error(f"--export-html: {str(exc).removeprefix('export_html: ')}") from None
    print(f"wrote {written}", file=sys.stdout)
    return 0
