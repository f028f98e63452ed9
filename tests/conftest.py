"""Shared by every test file: the folder of this file on ``sys.path``, so that test files in
subfolders (tests/model, tests/io, ...) import the helper modules here (``paths``,
``cli_helpers``, ``doc_blocks``, ...) by name.

Also, for every process of the suite (``make test`` runs several side by side): one
compile per kernel across them (:mod:`compile_lock`), and no time limit on a Hypothesis
example (timing belongs in benchmarks; a deadline only fails a test on a loaded machine)."""
from __future__ import annotations

import sys
from pathlib import Path

from hypothesis import settings

_TESTS = str(Path(__file__).resolve().parent)
if _TESTS not in sys.path:
    sys.path.insert(0, _TESTS)

import compile_lock  # noqa: E402 - from the folder just put on the path

compile_lock.install()
settings.register_profile("suite", deadline=None)
settings.load_profile("suite")
