"""The documentation says what the program does: the README's first screen, links that
resolve, the command line's --help and the window's keys shown as they are, and none of
the statements issue 16 found wrong."""
from __future__ import annotations

import re
import subprocess
from pathlib import Path

import pytest

from cli_helpers import run
from doc_blocks import PAGES, ROOT, blocks

README = ROOT / "README.md"
FIRST_SCREEN = 50  # lines


def test_the_readme_fits_and_its_first_screen_says_what_to_do() -> None:
    lines = README.read_text(encoding="utf-8").splitlines()
    assert len(lines) <= 250, f"README.md has {len(lines)} lines; at most 250"
    first = "\n".join(lines[:FIRST_SCREEN])
    assert "![" in first and "make run" in first and "make test" in first
    shell = [b for b in blocks("sh") if b.page == README and b.line < FIRST_SCREEN]
    python = [b for b in blocks("python") if b.page == README and b.line < FIRST_SCREEN]
    commands = [c for b in shell for c in b.commands()]
    assert python and 6 <= len(commands) + len(python[0].commands()) <= 20, "a try-this block of about ten lines"
    for shown in ("--screenshot", "Space", "Ctrl+left-drag", "press H"):
        assert shown in first, f"the first screen shows {shown}"
    assert any(b.info.split()[1:2] == ["runnable"] for b in shell), "the headless commands are run by the tests"


def test_no_statement_issue_16_found_wrong_is_back() -> None:
    everything = "\n".join(page.read_text(encoding="utf-8") for page in PAGES)
    for wrong in ("all 18", "zero steady-state error", "return quickly once set up", "python simulator.py --list"):
        assert wrong not in everything, wrong


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.name)
def test_links_resolve(page: Path) -> None:
    text = page.read_text(encoding="utf-8")
    for target in re.findall(r"\]\(([^)#\s]+)(?:#[^)]*)?\)", text):
        if re.match(r"[a-z]+://", target):
            continue
        assert (page.parent / target).exists(), f"{page.name}: link to {target}, which does not exist"


def test_the_command_line_page_shows_the_help_as_it_is() -> None:
    """docs/command-line.md holds `robot-sim --help` as printed at 100 columns (compared
    with runs of spaces folded, so Python versions that wrap differently agree)."""
    help_text = run("--help", env={"COLUMNS": "100", "PATH": "/usr/bin:/bin"}).stdout
    page = (ROOT / "docs" / "command-line.md").read_text(encoding="utf-8")
    shown = re.search(r"```text\n(.*?)```", page, re.S).group(1)

    def folded(text: str) -> str:
        return " ".join(text.split())

    assert folded(shown) == folded(help_text), (
        "docs/command-line.md's ```text block is not `robot-sim --help`: paste the output of "
        "`COLUMNS=100 .venv/bin/robot-sim --help` there")
    for option in ("--demo {circle,pick}", "--task", "--time", "--record", "--fps"):
        assert option in shown


def test_the_window_page_lists_every_key_binding() -> None:
    from robot_sim.qt.overlays import help_rows

    page = (ROOT / "docs" / "window.md").read_text(encoding="utf-8")
    rows = re.findall(r"^\| `([^`]+)` \| (.+) \|$", page, re.M)
    assert rows == help_rows(), (
        "docs/window.md's key table is not the window's help (robot_sim.qt.overlays.help_rows): "
        f"missing {[r for r in help_rows() if r not in rows]}, extra {[r for r in rows if r not in help_rows()]}")


def test_make_run_passes_its_arguments() -> None:
    result = subprocess.run(["make", "-n", "run", "ARGS=--robot ur5 --demo pick"], cwd=ROOT,
                            capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    assert "simulator.py --robot ur5 --demo pick" in result.stdout
