"""``robot-sim sweep``: a parameter sweep from the command line, written as a CSV table.

    robot-sim sweep --robot ur5 --motion ct --kp 100:1000:10 --duration 2 --out sweep.csv

A swept value is ``START:STOP:COUNT`` (COUNT values from START to STOP, both included),
a comma-separated list, or one number; several swept options make a grid (every
combination).  Runs go to the local cores, or to a Dask scheduler given by ``--scheduler
ADDRESS`` (needs the ``dask`` extra).  A progress bar goes to stderr.  Bad input is one
``robot-sim sweep: error: ...`` line with exit status 2.
"""
from __future__ import annotations

import argparse
import math
import sys
import time
from typing import Sequence

import numpy as np

from robot_sim.sim.sweep import METRICS, MODES, sweep
from robot_sim.io.files import FileError, check_writable
from robot_sim.io.robot_file import load_robot
from robot_sim.model.messages import clip_repr
from robot_sim.model.params import RobotDefinitionError

PROG = "robot-sim sweep"
#: Options that take swept values, and the sweep parameter each sets.
SWEPT = {"kp": "kp", "kd": "kd", "bandwidth": "bandwidth", "damping": "damping", "payload": "payload"}
MAX_RUNS = 10**7
#: Seconds to wait for a Dask scheduler to answer (--scheduler).
SCHEDULER_TIMEOUT_S = 3.0
BAR_WIDTH = 30


class SweepCliError(Exception):
    """Bad command-line input (the message says which option and what is accepted)."""


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> None:  # type: ignore[override]
        raise SweepCliError(message)


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog=PROG, description="Simulate a grid of runs and write their metrics as CSV.")
    parser.add_argument("--robot", required=True, help="robot name or file")
    parser.add_argument("--motion", choices=MODES, default="ct", help="controller (default ct)")
    for name in SWEPT:
        parser.add_argument(f"--{name}", metavar="VALUES", help=f"{name} values: START:STOP:COUNT, a,b,c or one number")
    parser.add_argument("--duration", type=float, default=1.0, help="simulated seconds per run (default 1)")
    parser.add_argument("--dt", type=float, default=1e-3, help="step [s] (default 0.001)")
    parser.add_argument("--metrics", default=",".join(METRICS), help=f"comma-separated, of {', '.join(METRICS)}")
    parser.add_argument("--workers", type=int, default=None, help="local processes (default: one per core)")
    parser.add_argument("--chunk", type=int, default=1000, help="runs per batch (default 1000)")
    parser.add_argument("--scheduler", metavar="ADDRESS", help="run the chunks on this Dask scheduler")
    parser.add_argument("--out", required=True, help="CSV file to write")
    return parser


def count_values(option: str, text: str) -> int:
    """How many values ``text`` gives (``START:STOP:COUNT``'s COUNT, the items of a list),
    read before any is built; SweepCliError naming ``option`` for a COUNT that is not a
    whole number 1..MAX_RUNS."""
    if ":" not in text:
        return text.count(",") + 1
    count = text.rsplit(":", 1)[1].strip()
    if not count.isdigit() or not 1 <= int(count) <= MAX_RUNS:
        raise SweepCliError(f"--{option} {clip_repr(text)}: expected START:STOP:COUNT (COUNT a whole number "
                            f"1..{MAX_RUNS}), a,b,c or one number")
    return int(count)


def parse_values(option: str, text: str) -> list[float]:
    """``START:STOP:COUNT``, ``a,b,c`` or one number → the values (finite, >= 0)."""
    try:
        if ":" in text:
            start, stop, count = text.split(":")
            n = int(count)
            if n < 1 or n > MAX_RUNS:
                raise ValueError
            values = list(np.linspace(float(start), float(stop), n))
        else:
            values = [float(v) for v in text.split(",")]
    except ValueError:
        raise SweepCliError(
            f"--{option} {clip_repr(text)}: expected START:STOP:COUNT (COUNT a whole number 1..{MAX_RUNS}), a,b,c or one number"
        ) from None
    if not all(math.isfinite(v) and v >= 0 for v in values):
        raise SweepCliError(f"--{option} {clip_repr(text)}: values must be finite and >= 0")
    return values


class ProgressBar:
    """``[#####.....]  k/N runs  t s`` rewritten in place on stderr."""

    def __init__(self, stream=sys.stderr) -> None:  # type: ignore[no-untyped-def]
        self.stream, self.start = stream, time.perf_counter()

    def __call__(self, done: int, total: int) -> None:
        filled = int(BAR_WIDTH * done / total)
        elapsed = time.perf_counter() - self.start
        self.stream.write(f"\r[{'#' * filled}{'.' * (BAR_WIDTH - filled)}] {done}/{total} runs  {elapsed:.1f} s")
        if done == total:
            self.stream.write("\n")
        self.stream.flush()


def _connect(client_type, address: str):  # noqa: ANN001, ANN202  (dask's Client, imported on request)
    """A client of the Dask scheduler at ``address``, or SweepCliError within
    SCHEDULER_TIMEOUT_S when the address is malformed or nothing answers there."""
    try:
        return client_type(address, timeout=SCHEDULER_TIMEOUT_S)
    except ValueError:
        raise SweepCliError(f"--scheduler {clip_repr(address)}: not a scheduler address; expected tcp://HOST:PORT "
                            "(an IPv6 host in brackets)") from None
    except (OSError, TimeoutError):
        raise SweepCliError(f"--scheduler {clip_repr(address)}: no Dask scheduler answered within "
                            f"{SCHEDULER_TIMEOUT_S:g} s") from None


def main(argv: Sequence[str]) -> int:
    """Run ``robot-sim sweep`` with ``argv`` (the arguments after ``sweep``); exit status."""
    try:
        args = build_parser().parse_args(list(argv))
        given = {k: getattr(args, k) for k in SWEPT if getattr(args, k) is not None}
        if not given:
            raise SweepCliError(f"give at least one swept value: {', '.join('--' + k for k in SWEPT)}")
        n_runs = math.prod(count_values(k, text) for k, text in given.items())  # before any value is built
        if n_runs > MAX_RUNS:
            raise SweepCliError(f"{' × '.join('--' + k for k in given)}: the grid has {n_runs} runs; at most {MAX_RUNS}")
        grid = {SWEPT[k]: parse_values(k, text) for k, text in given.items()}
        try:
            check_writable(args.out)  # before the sweep runs, not after
        except FileError as exc:
            raise SweepCliError(f"--out: {exc}") from None
        try:
            robot = load_robot(args.robot)
        except (RobotDefinitionError, FileError, OSError, ValueError) as exc:
            raise SweepCliError(f"--robot {args.robot}: {exc}") from None
        metrics = [m.strip() for m in args.metrics.split(",") if m.strip()]
        client = None
        if args.scheduler is not None:
            try:
                from distributed import Client
            except ImportError:
                raise SweepCliError("--scheduler needs dask.distributed: pip install 'robot-sim[dask]'") from None
            client = _connect(Client, args.scheduler)
        try:
            table = sweep(
                robot, grid, args.motion, args.duration, metrics, dt=args.dt, chunk_size=args.chunk,
                workers=args.workers, client=client, progress=ProgressBar(),
            )
        except ValueError as exc:
            raise SweepCliError(str(exc)) from None
        finally:
            if client is not None:
                client.close()
        try:
            path = table.write_csv(args.out)
        except (FileError, OSError) as exc:
            raise SweepCliError(f"--out {args.out}: {exc}") from None
    except SweepCliError as exc:
        print(f"{PROG}: error: {' '.join(str(exc).split())}", file=sys.stderr)
        return 2
    print(f"wrote {len(table)} runs to {path}")
    return 0
