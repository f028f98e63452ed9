"""Where the suite finds things, wherever a test file sits under tests/."""
from __future__ import annotations

from pathlib import Path

#: The checkout.
ROOT = Path(__file__).resolve().parents[1]
#: The import package.
PACKAGE = ROOT / "robot_sim"
#: Hand-written URDFs and other test inputs.
DATA = ROOT / "tests" / "data"
#: The program, as run from a checkout.
SIMULATOR = ROOT / "simulator.py"
