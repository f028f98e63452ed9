"""The pictures of docs/ say how they were made and carry no path from outside the checkout.

A picture's visible text (the window's title, the DH dock's file name) comes from its
command, so every PNG in docs/ must record its command (text chunk ``Source``, written by
``--screenshot``, ``--record``, ``P`` and docs/window_picture.py), that command must be one
the docs show (so ``make pictures`` can make it again) and no text chunk may name the
folder the checkout lives in.  tests/docs/test_docs_commands.py checks that no documented
command uses an absolute path."""
from __future__ import annotations

import shlex
import shutil
import struct
import sys
import zlib
from pathlib import Path

import pytest

from cli_helpers import run
from doc_blocks import ROOT

sys.path.insert(0, str(ROOT / "docs"))
from pictures import documented_commands, picture_target  # noqa: E402

PICTURES = sorted((ROOT / "docs").glob("*.png"))
WINDOW_PICTURE = "window.png"  # made by docs/window_picture.py, which needs a display


def png_chunks(path: Path) -> list[tuple[bytes, bytes]]:
    """The chunks of a PNG, (type, data), checked against their CRCs."""
    data, pos, chunks = path.read_bytes(), 8, []
    assert data[:8] == b"\x89PNG\r\n\x1a\n", f"{path.name}: not a PNG"
    while pos < len(data):
        (length,) = struct.unpack(">I", data[pos:pos + 4])
        kind, body = data[pos + 4:pos + 8], data[pos + 8:pos + 8 + length]
        (crc,) = struct.unpack(">I", data[pos + 8 + length:pos + 12 + length])
        assert zlib.crc32(kind + body) & 0xFFFFFFFF == crc, f"{path.name}: bad CRC in {kind!r}"
        chunks.append((kind, body))
        pos += 12 + length
    return chunks


def png_texts(path: Path) -> dict[str, str]:
    """The tEXt, zTXt and iTXt chunks of a PNG, keyword -> text."""
    texts = {}
    for kind, body in png_chunks(path):
        key, _, rest = body.partition(b"\0")
        if kind == b"tEXt":
            texts[key.decode("latin-1")] = rest.decode("latin-1")
        elif kind == b"zTXt":
            texts[key.decode("latin-1")] = zlib.decompress(rest[1:]).decode("latin-1")
        elif kind == b"iTXt":
            compressed, rest = rest[0], rest[2:]
            _language, _, rest = rest.partition(b"\0")
            _translated, _, value = rest.partition(b"\0")
            texts[key.decode("latin-1")] = (zlib.decompress(value) if compressed else value).decode("utf-8")
    return texts


def png_size(path: Path) -> tuple[int, int]:
    kind, header = png_chunks(path)[0]
    assert kind == b"IHDR"
    return struct.unpack(">II", header[:8])


def documented_picture_commands() -> dict[str, list[str]]:
    """``docs/NAME.png`` -> the arguments of the documented command that renders it."""
    return {picture_target(args): args for args in documented_commands()}


def test_every_docs_picture_records_a_documented_command_and_no_outside_path() -> None:
    outside = str(ROOT.parent)
    documented = {shlex.join(["robot-sim", *args]) for args in documented_picture_commands().values()}
    assert len(PICTURES) > 20
    for picture in PICTURES:
        texts = png_texts(picture)
        for key, value in texts.items():
            assert outside not in value, f"docs/{picture.name}: its {key} text names {outside}: {value}"
        source = texts.get("Source", "")
        assert source, f"docs/{picture.name}: records no command (no Source text): render it with `make pictures`"
        if picture.name == WINDOW_PICTURE:
            assert source.startswith("docs/window_picture.py"), source
        else:
            assert source in documented, f"docs/{picture.name}: made by `{source}`, which no docs page shows"
            assert f"--screenshot docs/{picture.name}" in source or f"--report docs/{picture.name}" in source, source


def test_every_documented_picture_exists() -> None:
    for target in documented_picture_commands():
        assert (ROOT / target).is_file(), f"{target}: documented but not in docs/ (run `make pictures`)"


def test_a_screenshot_records_its_command_as_given(tmp_path: Path) -> None:
    args = ["--robot", "planar3", "--q", "30,30,30", "--size", "64x48", "--screenshot", "small.png"]
    result = run(*args, cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    texts = png_texts(tmp_path / "small.png")
    assert texts == {"Software": "robot-sim", "Source": shlex.join(["robot-sim", *args])}
    assert png_size(tmp_path / "small.png") == (64, 48)


@pytest.mark.slow
def test_make_pictures_renders_every_docs_picture_again(tmp_path: Path) -> None:
    """Each documented picture command, run in a fresh folder, makes a picture of the size
    of the one in docs/ (the pixels differ with the GL driver; the command is what is kept).
    The folder holds the world files of docs/, as the checkout does."""
    (tmp_path / "docs").mkdir()
    for data in (ROOT / "docs").glob("*.toml"):  # the world files the commands read
        (tmp_path / "docs" / data.name).write_bytes(data.read_bytes())
    for target, args in documented_picture_commands().items():
        if "--data" in args:  # robot-sim calibrate reads the measurements kept beside the picture
            data = args[args.index("--data") + 1]
            shutil.copy(ROOT / data, tmp_path / data)
        result = run(*args, cwd=tmp_path)
        assert result.returncode == 0, f"{target}: {shlex.join(args)}\n{result.stderr}"
        assert png_size(tmp_path / target) == png_size(ROOT / target), target
