"""The code blocks of README.md and docs/*.md, for the tests that run and check them.

The convention (docs/documentation.md): a fenced block whose info string is ``sh runnable``
holds shell commands that run as written right after ``make``, headless, one a line (``#``
starts a comment); ``sh runnable slow`` the same, run by the slow suite only.  Any other
``sh`` block is shown, not run (commands that open the window, or need a server), but the
options of its ``robot-sim`` commands are parsed.  ``python`` blocks are whole programs
(``python slow``: slow suite only).
"""
from __future__ import annotations

import re
import shlex
from dataclasses import dataclass
from pathlib import Path

from paths import ROOT

PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
_FENCE = re.compile(r"^```([^\n`]*)\n(.*?)^```", re.M | re.S)
_INLINE = re.compile(r"`(\.venv/bin/robot-sim [^`\n]+)`")
#: Options after which robot-sim writes output and exits instead of opening the window.
HEADLESS_OPTIONS = {"--screenshot", "--record", "--print-dh", "--list-robots", "--export-urdf",
                    "--export-toml", "--help", "-h"}


@dataclass(frozen=True)
class Command:
    """One command line of the documentation: page, line number and text (comment dropped)."""

    page: Path
    line: int
    text: str

    @property
    def where(self) -> str:
        return f"{self.page.relative_to(ROOT)}:{self.line}"

    @property
    def words(self) -> list[str]:
        return shlex.split(self.text, comments=True)

    def robot_sim_args(self) -> list[str] | None:
        """The arguments of a ``.venv/bin/robot-sim`` (or ``make run ARGS=...``) command, else None."""
        words = self.words
        if words[:1] == [".venv/bin/robot-sim"]:
            return words[1:]
        if words[:2] == ["make", "run"]:
            found = [w[len("ARGS="):] for w in words[2:] if w.startswith("ARGS=")]
            return shlex.split(found[0]) if found else []
        return None

    def opens_window(self) -> bool:
        """Whether this is a robot-sim command that opens the window (rather than writing output)."""
        args = self.robot_sim_args()
        if args is None or args[:1] in (["sweep"], ["calibrate"], ["calibration-poses"]):
            return False
        return not any(word.split("=")[0] in HEADLESS_OPTIONS for word in args)


@dataclass(frozen=True)
class Block:
    """One fenced block: its page, the line of its opening fence, info string and text."""

    page: Path
    line: int
    info: str
    text: str

    @property
    def name(self) -> str:
        return f"{self.page.relative_to(ROOT)}:{self.line}"

    @property
    def slow(self) -> bool:
        return "slow" in self.info.split()[1:]

    def commands(self) -> list[Command]:
        """The block's command lines with their line numbers in the page (blank lines and
        comment lines skipped)."""
        return [Command(self.page, self.line + 1 + k, line.strip())
                for k, line in enumerate(self.text.splitlines())
                if line.strip() and not line.lstrip().startswith("#")]


def all_blocks() -> list[Block]:
    """Every fenced block of the pages, in page order."""
    found = []
    for page in PAGES:
        text = page.read_text(encoding="utf-8")
        for match in _FENCE.finditer(text):
            found.append(Block(page, text.count("\n", 0, match.start()) + 1, match.group(1).strip(), match.group(2)))
    return found


def blocks(kind: str, runnable: bool | None = None) -> list[Block]:
    """The blocks whose info string starts with ``kind`` (``sh``, ``python``); with
    ``runnable`` only those marked (or not marked) ``runnable``."""
    chosen = [b for b in all_blocks() if b.info.split()[:1] == [kind]]
    if runnable is not None:
        chosen = [b for b in chosen if ("runnable" in b.info.split()) == runnable]
    return chosen


def inline_commands() -> list[Command]:
    """The ``.venv/bin/robot-sim ...`` commands written as inline code (tables, prose)."""
    found = []
    for page in PAGES:
        for number, line in enumerate(page.read_text(encoding="utf-8").splitlines(), start=1):
            if line.startswith("```"):
                continue
            found += [Command(page, number, match.group(1)) for match in _INLINE.finditer(line)]
    return found


def all_commands() -> list[Command]:
    """Every documented command: in shell blocks and inline."""
    return [c for b in blocks("sh") for c in b.commands()] + inline_commands()
