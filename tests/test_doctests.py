"""The examples in the package's docstrings (``>>>`` lines and the output shown after
them) run as doctests, so that they stay true."""
from __future__ import annotations

import doctest
import importlib

import pytest

from paths import PACKAGE



def modules_with_examples() -> list[str]:
    """The dotted names of the package's modules whose source holds a ``>>>`` example
    (found by reading the files, so that modules without examples are never imported)."""
    names = []
    for path in sorted(PACKAGE.rglob("*.py")):
        if ">>>" in path.read_text(encoding="utf-8"):
            parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
            names.append(".".join(parts[:-1] if parts[-1] == "__init__" else parts))
    return names


MODULES = modules_with_examples()


def test_the_package_docstring_has_examples() -> None:
    assert "robot_sim" in MODULES


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples_hold(name: str) -> None:
    module = importlib.import_module(name)
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    report: list[str] = []
    for test in doctest.DocTestFinder().find(module, name):
        runner.run(test, out=report.append)
    assert runner.tries > 0, f"{name}: no example found"
    assert runner.failures == 0, "".join(report)
