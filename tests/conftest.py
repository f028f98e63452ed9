"""Shared by every test file: the folder of this file on ``sys.path``, so that test files in
subfolders (tests/model, tests/io, ...) import the helper modules here (``paths``,
``cli_helpers``, ``doc_blocks``, ...) by name.

Also, for every process of the suite (``make test`` runs several side by side): one
compile per kernel across them (:mod:`compile_lock`), no time limit on a Hypothesis
example (timing belongs in benchmarks; a deadline only fails a test on a loaded machine),
and Python's cycle collector run less often (:data:`GC_THRESHOLDS`).  The longest test
files are collected first, so that ``make test``'s workers (which take whole files in
collection order: ``--no-loadscope-reorder``) end together instead of one running them
alone at the end."""
from __future__ import annotations

import gc
import sys
from pathlib import Path

from hypothesis import settings

_TESTS = str(Path(__file__).resolve().parent)
if _TESTS not in sys.path:
    sys.path.insert(0, _TESTS)

import compile_lock  # noqa: E402 - from the folder just put on the path

compile_lock.install()

#: The cycle collector's thresholds in the suite's processes (Python's default: 700, 10, 10).
#: numba's compiler allocates millions of objects, and at the default each worker of a
#: cold ``make test`` spent 10-15 s of CPU in the collector, 12 % of its time: 39 s of the
#: three workers' 334 s; with these, 10 s of 300 s (gc.callbacks timing, one cold run
#: each).  Memory stays bounded: a young collection still runs every 50 000 objects.
GC_THRESHOLDS = (50_000, 20, 100)
gc.set_threshold(*GC_THRESHOLDS)

#: The test files that take longest (the first compiles, a browser driven), longest first
#: (a cold ``make test``'s time line: each file's tests summed).
LONGEST_FIRST = ("tests/sim/test_simulation.py", "tests/docs/test_docs_commands.py", "tests/web/test_web.py",
                 "tests/planning/test_task.py", "tests/control/test_task_space.py", "tests/model/test_dh_conventions.py",
                 "tests/collision/test_collision_checker.py", "tests/ik/test_ik_analytic.py", "tests/sim/test_contact.py",
                 "tests/graphics/test_render_speedups.py", "tests/ik/test_ik_general6r.py", "tests/web/test_web_browser.py")


def pytest_collection_modifyitems(items: list) -> None:
    """The files of :data:`LONGEST_FIRST` first, in its order; the rest as collected."""
    def rank(item) -> int:  # noqa: ANN001 - a pytest item
        path = item.nodeid.split("::")[0]
        return LONGEST_FIRST.index(path) if path in LONGEST_FIRST else len(LONGEST_FIRST)

    items.sort(key=rank)
settings.register_profile("suite", deadline=None)
settings.load_profile("suite")
