"""Module constants are bound once: a second binding silently wins over the first."""
from __future__ import annotations

import ast
from collections import Counter

from paths import PACKAGE



def rebound_constants(source: str) -> list[str]:
    """UPPER_CASE names assigned more than once at the top level of a module's source."""
    counts: Counter[str] = Counter()
    for node in ast.parse(source).body:
        if isinstance(node, ast.Assign):
            targets = node.targets
        elif isinstance(node, ast.AnnAssign):
            targets = [node.target]
        else:
            continue
        counts.update(t.id for t in targets if isinstance(t, ast.Name) and t.id.isupper())
    return sorted(name for name, count in counts.items() if count > 1)


def test_the_check_finds_a_rebound_constant() -> None:
    assert rebound_constants("A_COLOR = 1\nB = 2\nA_COLOR = 3\nlower = 1\nlower = 2\n") == ["A_COLOR"]


def test_no_module_binds_a_constant_twice() -> None:
    # Two landings each added OBSTACLE_COLOR to graphics/defs.py: the pick task's walls
    # were drawn in the collision display's see-through steel instead of teal.
    found = {
        str(path.relative_to(PACKAGE.parent)): names
        for path in sorted(PACKAGE.rglob("*.py"))
        if (names := rebound_constants(path.read_text(encoding="utf-8")))
    }
    assert found == {}
