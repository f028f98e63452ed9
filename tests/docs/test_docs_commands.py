"""The documentation's commands run as written (the convention is in docs/documentation.md).

Every ``sh runnable`` block of README.md and docs/*.md runs in a fresh temporary directory
laid out as a checkout after ``make`` (``.venv`` is this test's environment, ``docs/`` an
empty folder, the checkout's modules first on the path), headless; every ``python`` block
runs as a program there.  Commands that open the window are never marked runnable; theirs
and every other documented ``robot-sim`` command's options are parsed by the program's own
parser, and a shipped robot they name must exist.  Failures name the page, the line and the
command.

To keep the suite fast, a plain ``.venv/bin/robot-sim ARGS`` line runs as the program's
``main(ARGS)`` in this process (``cli_helpers.run``: in that directory, with that
environment, output captured) and a Python block is executed in a fresh namespace there;
a line that needs the shell (pipes, redirections, variables) goes to ``bash``, and a block
that needs its own interpreter (see ``needs_own_interpreter``) to ``python``.
"""
from __future__ import annotations

import os
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

from cli_helpers import program_context, run, time_limit
from doc_blocks import ROOT, Block, Command, all_commands, blocks

RUNNABLE = blocks("sh", runnable=True)
PYTHON = blocks("python")
TIMEOUT = 600  # s: a hung command fails instead of stalling the suite


def params(found: list[Block]) -> list:
    """Blocks as pytest parameters, the ``slow`` ones marked so."""
    return [pytest.param(b, id=b.name, marks=[pytest.mark.slow] if b.slow else []) for b in found]


def environment() -> dict[str, str]:
    """This checkout's modules first, headless rendering, no display."""
    env = dict(os.environ, PYTHONPATH=str(ROOT), PYOPENGL_PLATFORM="osmesa", OPENBLAS_NUM_THREADS="1")
    for key in ("DISPLAY", "WAYLAND_DISPLAY"):
        env.pop(key, None)
    return env


def workdir(tmp: Path) -> Path:
    """A temporary directory that looks to the commands like a checkout after ``make``."""
    (tmp / ".venv").symlink_to(sys.prefix, target_is_directory=True)
    (tmp / "docs").mkdir()
    return tmp


#: Words of a Python block after which it runs in its own interpreter: it starts processes,
#: changes the environment of the process, or loads Qt, a browser server or a GL platform of
#: its own (a Visualizer's offscreen backend draws through the OSMesa this process uses).
OWN_INTERPRETER = ("os.environ", "putenv", "subprocess", "multiprocessing", "workers=", "client=",
                   "PyQt5", "OpenGL", 'backend="window"', "backend='window'", 'backend="web"',
                   "backend='web'", "faulthandler", "signal")


def needs_own_interpreter(block: Block) -> bool:
    """Whether a Python block must run as a separate program rather than in the test process."""
    return any(word in block.text for word in OWN_INTERPRETER)


def in_process_args(command: Command) -> list[str] | None:
    """The arguments of a plain ``.venv/bin/robot-sim ARGS`` line (no pipe, redirection,
    variable or second command), which the test runs in its own process; else None."""
    lexer = shlex.shlex(command.text, posix=True, punctuation_chars=True)
    lexer.commenters = "#"
    words = list(lexer)
    if words[:1] != [".venv/bin/robot-sim"] or any(c in command.text for c in "$`*?~"):
        return None
    if any(word and all(c in lexer.punctuation_chars for c in word) for word in words):
        return None
    return command.words[1:]


def run_command(command: Command, cwd: Path, env: dict[str, str]) -> subprocess.CompletedProcess[str]:
    """One line of a runnable block, in ``cwd`` with ``env``: in this process where it can."""
    args = in_process_args(command)
    if args is not None:
        return run(*args, env=env, cwd=cwd, timeout=TIMEOUT)
    return subprocess.run(["bash", "-c", command.text], cwd=cwd, env=env, capture_output=True,
                          text=True, timeout=TIMEOUT)


def failure(command: Command, result: subprocess.CompletedProcess[str]) -> str:
    return (f"{command.where}: `{command.text}` exited {result.returncode}\n"
            f"stdout: {result.stdout[-1500:]}\nstderr: {result.stderr[-2500:]}")


def check_outputs(command: Command, cwd: Path) -> None:
    """What a command says it writes is there, complete."""
    words = command.words
    for option in ("--screenshot", "--export-urdf", "--export-toml", "--out"):
        if option in words:
            target = cwd / words[words.index(option) + 1]
            assert target.is_file() and target.stat().st_size > 0, f"{command.where}: `{command.text}` wrote no {target.name}"
            if option == "--screenshot":
                assert target.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", f"{command.where}: {target.name} is no PNG"
    if "--record" in words:
        frames = sorted((cwd / words[words.index("--record") + 1]).glob("frame_*.png"))
        assert frames, f"{command.where}: `{command.text}` recorded no frames"


def test_the_pages_hold_runnable_blocks_and_python_blocks() -> None:
    pages = {b.page.name for b in RUNNABLE} | {b.page.name for b in PYTHON}
    assert "README.md" in pages and len(pages) >= 4, pages


def test_no_runnable_command_opens_the_window() -> None:
    for block in RUNNABLE:
        for command in block.commands():
            assert not command.opens_window(), (
                f"{command.where}: `{command.text}` opens the window: show it in a plain ```sh block instead")


@pytest.mark.parametrize("block", params(RUNNABLE))
def test_runnable_commands_run_as_written(block: Block, tmp_path: Path) -> None:
    cwd, env = workdir(tmp_path), environment()
    commands = block.commands()
    assert commands, f"{block.name}: an empty runnable block"
    for command in commands:
        result = run_command(command, cwd, env)
        assert result.returncode == 0, failure(command, result)
        assert "Traceback" not in result.stderr and "error:" not in result.stderr, failure(command, result)
        check_outputs(command, cwd)


@pytest.mark.parametrize("block", params(PYTHON))
def test_python_blocks_run(block: Block, tmp_path: Path) -> None:
    program = workdir(tmp_path) / "example.py"
    if needs_own_interpreter(block):
        program.write_text(block.text, encoding="utf-8")
        result = subprocess.run([sys.executable, str(program)], cwd=tmp_path, env=environment(),
                                capture_output=True, text=True, timeout=TIMEOUT)
        assert result.returncode == 0, f"{block.name}: the python block failed\n{result.stderr[-3000:]}"
        return
    code = compile(block.text, f"{block.name} (python block)", "exec")
    with program_context(environment(), tmp_path), time_limit(TIMEOUT, block.name):
        exec(code, {"__name__": "__main__", "__file__": str(program)})  # a traceback names page and line


def test_in_process_runs_only_plain_robot_sim_lines() -> None:
    def args(text: str) -> list[str] | None:
        return in_process_args(Command(ROOT / "README.md", 1, text))

    assert args(".venv/bin/robot-sim --robot ur5 --print-dh   # a comment") == ["--robot", "ur5", "--print-dh"]
    assert args(".venv/bin/robot-sim --q=-30,45 --screenshot 'a b.png'") == ["--q=-30,45", "--screenshot", "a b.png"]
    for shell in (".venv/bin/robot-sim --list-robots | head -3", ".venv/bin/robot-sim --print-dh > dh.txt",
                  ".venv/bin/robot-sim --help && ls", "COLUMNS=100 .venv/bin/robot-sim --help",
                  ".venv/bin/robot-sim --robot $HOME/arm.toml", "make run ARGS='--robot ur5'"):
        assert args(shell) is None, shell


def parse_robot_sim(args: list[str]) -> None:
    """Parse ``robot-sim`` arguments as the program does, without running anything; a shipped
    robot name must exist.  Raises the program's own error for anything it would refuse."""
    from robot_sim.io.robot_file import available_robots

    if args[:1] == ["sweep"]:
        from robot_sim.app import sweep_cmd

        parsed = sweep_cmd.build_parser().parse_args(args[1:])
    elif args[:1] in (["calibrate"], ["calibration-poses"]):
        from robot_sim.app import calibrate_cmd

        parsed = calibrate_cmd.build_parser(args[0]).parse_args(args[1:])
    else:
        from robot_sim.app import cli

        parsed = cli.build_parser().parse_args(cli.attach_negative_values(args))
    robot = parsed.robot or ""
    if robot and "/" not in robot and "." not in robot:
        assert robot in available_robots(), f"no shipped robot {robot!r}"


def test_every_documented_robot_sim_command_parses() -> None:
    commands = [c for c in all_commands() if c.robot_sim_args() is not None]
    assert len(commands) > 30, "the parser found the documented commands"
    problems = []
    for command in commands:
        try:
            parse_robot_sim(command.robot_sim_args())
        except (Exception, SystemExit) as exc:  # the parsers' errors, or an unknown robot
            problems.append(f"{command.where}: `{command.text}`: {type(exc).__name__}: {exc}")
    assert not problems, "\n".join(problems)


def test_no_documented_command_uses_an_absolute_path() -> None:
    """Pictures record their command, and a docs page is read on other machines."""
    for command in all_commands():
        args = command.robot_sim_args()
        if args is None:
            continue
        for word in args:
            value = word.split("=", 1)[-1]
            assert not value.startswith(("/", "~")) and str(ROOT.parent) not in value, (
                f"{command.where}: `{command.text}` uses the absolute path {value}")
