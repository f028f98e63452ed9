"""Running the command line and reading what it wrote (shared by the CLI tests).

:func:`run` calls ``robot_sim.app.main.main(argv)`` in the test process, as a child process
would run it: in the checkout, with stdout, stderr and warnings captured, ``os.environ``
and the working directory restored afterwards, and no display (so a command that would
open the window answers with the "no display" error instead).  :func:`run_process` starts
``python simulator.py`` for the few tests that need a real process: exit codes seen by a
shell, a clean interpreter (``sys.modules`` checks), file descriptors.
"""
from __future__ import annotations

import contextlib
import io
import os
import signal
import struct
import subprocess
import sys
import warnings
import zlib
from pathlib import Path
from typing import Iterator

import numpy as np

from paths import ROOT, SIMULATOR

#: Variables that would let the program open a window.
DISPLAY_VARIABLES = ("DISPLAY", "WAYLAND_DISPLAY", "QT_QPA_PLATFORM")


@contextlib.contextmanager
def program_context(env: dict[str, str] | None, cwd: Path) -> Iterator[tuple[io.StringIO, io.StringIO]]:
    """Inside: ``env`` (default: this process's, less the display) as ``os.environ``, ``cwd``
    as the working directory, stdout and stderr (and warnings, shown as Python shows them)
    going to the two StringIO yielded.  Everything is put back on the way out."""
    saved_env, saved_cwd = dict(os.environ), os.getcwd()
    out, err = io.StringIO(), io.StringIO()
    try:
        new_env = dict(os.environ if env is None else env)
        if env is None:
            for key in DISPLAY_VARIABLES:
                new_env.pop(key, None)
        os.environ.clear()
        os.environ.update(new_env)
        os.chdir(cwd)
        with warnings.catch_warnings(), contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            warnings.resetwarnings()
            warnings.simplefilter("default")
            warnings.showwarning = _warning_to_stderr
            yield out, err
    finally:
        os.chdir(saved_cwd)
        os.environ.clear()
        os.environ.update(saved_env)


def _warning_to_stderr(message, category, filename, lineno, file=None, line=None) -> None:  # noqa: ANN001
    sys.stderr.write(warnings.formatwarning(message, category, filename, lineno, line))


@contextlib.contextmanager
def time_limit(seconds: float, what: str) -> Iterator[None]:
    """Raise TimeoutError in the body after ``seconds`` (SIGALRM: the main thread only), so
    that a hang (a blocking open of a FIFO, say) fails the test instead of stalling the suite."""
    def expire(signum, frame) -> None:  # noqa: ANN001
        raise TimeoutError(f"{what} did not finish within {seconds} s")

    previous = signal.signal(signal.SIGALRM, expire)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)


def run(*args: str, env: dict[str, str] | None = None, cwd: Path = ROOT,
        timeout: float = 300) -> subprocess.CompletedProcess[str]:
    """``robot-sim ARGS`` in this process (see the module's docstring); the exit status is
    main's return value or SystemExit's code.  Any other exception propagates, failing the
    test with its traceback (a child process would have printed it and exited 1)."""
    with program_context(env, cwd) as (out, err), time_limit(timeout, f"robot-sim {' '.join(args)}"):
        from robot_sim.app.main import main  # inside: its import sets OPENBLAS_NUM_THREADS

        try:
            code = main(list(args))
        except SystemExit as exc:  # as the interpreter turns it into an exit status
            code = 0 if exc.code is None else exc.code
            if not isinstance(code, int):
                print(code, file=sys.stderr)
                code = 1
    return subprocess.CompletedProcess(["robot-sim", *args], code, out.getvalue(), err.getvalue())


def run_process(*args: str, env: dict[str, str] | None = None, cwd: Path = ROOT,
                timeout: float = 120) -> subprocess.CompletedProcess[str]:
    """Run ``python simulator.py ARGS`` in a child process and capture its output."""
    return subprocess.run(
        [sys.executable, str(SIMULATOR), *args], capture_output=True, text=True, timeout=timeout, env=env, cwd=cwd
    )


def read_png(path: Path) -> np.ndarray:
    """Decode an 8-bit RGB/RGBA PNG whose rows all use filter 0 (as save_png writes)."""
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    pos, chunks = 8, {}
    while pos < len(data):
        (length,) = struct.unpack(">I", data[pos:pos + 4])
        kind, body = data[pos + 4:pos + 8], data[pos + 8:pos + 8 + length]
        assert struct.unpack(">I", data[pos + 8 + length:pos + 12 + length])[0] == zlib.crc32(kind + body)
        chunks[kind] = chunks.get(kind, b"") + body
        pos += 12 + length
    width, height, depth, color_type = struct.unpack(">IIBB", chunks[b"IHDR"][:10])
    assert depth == 8 and color_type in (2, 6)
    channels = 4 if color_type == 6 else 3
    rows = np.frombuffer(zlib.decompress(chunks[b"IDAT"]), np.uint8).reshape(height, 1 + width * channels)
    assert np.all(rows[:, 0] == 0)
    return rows[:, 1:].reshape(height, width, channels)


def assert_one_line_error(result: subprocess.CompletedProcess[str], *fragments: str) -> None:
    assert result.returncode == 2, result.stderr
    assert "Traceback" not in result.stderr
    lines = result.stderr.splitlines()
    assert len(lines) == 1, result.stderr
    assert lines[0].startswith("robot-sim: error: ")
    for fragment in fragments:
        assert fragment in lines[0]
