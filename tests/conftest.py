"""Shared by every test file: the folder of this file on ``sys.path``, so that test files in
subfolders (tests/model, tests/io, ...) import the helper modules here (``paths``,
``cli_helpers``, ``doc_blocks``, ...) by name.

Also, for every process of the suite (``make test`` runs several side by side): one
compile per kernel across them (:mod:`compile_lock`), and no time limit on a Hypothesis
example (timing belongs in benchmarks; a deadline only fails a test on a loaded machine).
The longest test files are collected first, so that ``make test``'s workers (which take
whole files in collection order) end together instead of one running them alone at the end."""
from __future__ import annotations

import sys
from pathlib import Path

from hypothesis import settings

_TESTS = str(Path(__file__).resolve().parent)
if _TESTS not in sys.path:
    sys.path.insert(0, _TESTS)

import compile_lock  # noqa: E402 - from the folder just put on the path

compile_lock.install()

#: The test files that take longest (a browser driven, the first compiles), longest first.
LONGEST_FIRST = ("tests/web/test_web_browser.py", "tests/app/test_cli_motion.py", "tests/docs/test_docs_commands.py",
                 "tests/control/test_task_space.py", "tests/ik/test_ik_general6r.py", "tests/control/test_task_batch.py")


def pytest_collection_modifyitems(items: list) -> None:
    """The files of :data:`LONGEST_FIRST` first, in its order; the rest as collected."""
    def rank(item) -> int:  # noqa: ANN001 - a pytest item
        path = item.nodeid.split("::")[0]
        return LONGEST_FIRST.index(path) if path in LONGEST_FIRST else len(LONGEST_FIRST)

    items.sort(key=rank)
settings.register_profile("suite", deadline=None)
settings.load_profile("suite")
