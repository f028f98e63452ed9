"""``make test`` runs the real-window tests by collecting tests/qt only (collecting the
whole suite in the window process costs seconds of CPU for nothing): so every test marked
``window`` must live there, or make test would never run it."""
from __future__ import annotations

import re

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
