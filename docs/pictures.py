"""Render every picture of docs/ again with the command written next to it in the docs.

Each ``.venv/bin/robot-sim ... --screenshot docs/NAME.png`` (or ``--report docs/NAME.png``) command of README.md or a
docs/*.md page (found by tests/doc_blocks.py, the parser the doc tests use) is run from
the checkout's root, so the PNGs record relative paths only (tests/docs/test_docs_pictures.py
checks that).  The window picture is made by docs/window_picture.py (it needs a display).
Run by ``make pictures``.
"""
from __future__ import annotations

import os
import shlex
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))

from doc_blocks import all_commands  # noqa: E402


#: Options that name the picture a command writes (``robot-sim calibrate`` draws a report).
PICTURE_OPTIONS = ("--screenshot", "--report")


def picture_target(args: list[str]) -> str | None:
    """The picture a ``robot-sim`` argument list writes, if any."""
    option = next((o for o in PICTURE_OPTIONS if o in args), None)
    return None if option is None else (args[args.index(option) + 1:] or [None])[0]


def documented_commands() -> list[list[str]]:
    """The argument lists of every documented command writing a picture into docs/
    (``--screenshot docs/...``, ``--report docs/...``), once each, in page order."""
    found: list[list[str]] = []
    for command in all_commands():
        args = command.robot_sim_args() or []
        target = picture_target(args)
        if target and target.startswith("docs/") and args not in found:
            found.append(args)
    return found


def main() -> int:
    env = dict(os.environ, PYOPENGL_PLATFORM="osmesa")
    for args in documented_commands():
        print("robot-sim", shlex.join(args), flush=True)
        result = subprocess.run([sys.executable, "simulator.py", *args], cwd=ROOT, env=env)
        if result.returncode != 0:
            return result.returncode
    return 0


if __name__ == "__main__":
    sys.exit(main())
