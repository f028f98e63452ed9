"""Running the command line in a child process and reading what it wrote (shared by the CLI tests)."""
from __future__ import annotations

import struct
import subprocess
import sys
import zlib
from pathlib import Path

import numpy as np


ROOT = Path(__file__).resolve().parents[1]
SIMULATOR = ROOT / "simulator.py"


def run(*args: str, env: dict[str, str] | None = None) -> subprocess.CompletedProcess[str]:
    """Run ``python simulator.py ARGS`` and capture its output."""
    return subprocess.run(
        [sys.executable, str(SIMULATOR), *args], capture_output=True, text=True, timeout=120, env=env, cwd=ROOT
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
