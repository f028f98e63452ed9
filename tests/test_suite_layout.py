"""``make test`` runs the real-window tests by collecting tests/qt only (collecting the
whole suite in the window process costs seconds of CPU for nothing): so every test marked
``window`` must live there, or make test would never run it.  Its headless workers take
the files of conftest's ``LONGEST_FIRST`` first: a file renamed there would silently lose
its place."""
from __future__ import annotations

import re

from conftest import LONGEST_FIRST
from paths import ROOT

WINDOW_MARK = re.compile(r"pytest\.mark\.window\b")


def test_every_window_test_lives_in_tests_qt() -> None:
    tests = ROOT / "tests"
    outside = sorted(str(path.relative_to(ROOT)) for path in tests.rglob("*.py")
                     if path.parent != tests / "qt" and path != tests / "test_suite_layout.py"
                     and WINDOW_MARK.search(path.read_text(encoding="utf-8")))
    assert outside == []
    inside = [path for path in (tests / "qt").glob("test_*.py") if WINDOW_MARK.search(path.read_text(encoding="utf-8"))]
    assert len(inside) >= 12


def test_the_files_scheduled_first_exist() -> None:
    missing = [name for name in LONGEST_FIRST if not (ROOT / name).is_file()]
    assert missing == []
    assert len(set(LONGEST_FIRST)) == len(LONGEST_FIRST)
