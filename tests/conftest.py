"""Shared by every test file: the folder of this file on ``sys.path``, so that test files in
subfolders (tests/model, tests/io, ...) import the helper modules here (``paths``,
``cli_helpers``, ``doc_blocks``, ...) by name."""
from __future__ import annotations

import sys
from pathlib import Path

_TESTS = str(Path(__file__).resolve().parent)
if _TESTS not in sys.path:
    sys.path.insert(0, _TESTS)
