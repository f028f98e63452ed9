"""No exception escapes a Qt handler: a failure inside a key, wheel, paint, slider or
timer handler shows in the status bar and the window keeps running (real window under
xvfb-run; each case in its own process, since an escaping exception aborts PyQt5)."""
from __future__ import annotations

import json
import os
import subprocess
import sys

import pytest

from paths import ROOT

PROBE = ROOT / "tests" / "window_fault_probe.py"


@pytest.mark.window
@pytest.mark.parametrize("case", ["key", "wheel", "paint", "slider", "timer"])
def test_handler_exception_is_shown_and_the_window_lives(case: str) -> None:
    if not os.environ.get("DISPLAY"):
        pytest.fail("window tests need an X display: run them with xvfb-run (make test)")
    env = {k: v for k, v in os.environ.items() if k != "PYOPENGL_PLATFORM"}
    run = subprocess.run([sys.executable, str(PROBE), case], capture_output=True, text=True, timeout=120, env=env)
    assert run.returncode == 0, f"exit {run.returncode}: {run.stderr[-2000:]}"
    outcome = json.loads(run.stdout.strip().splitlines()[-1])
    assert outcome["alive"]
    assert outcome["message"].startswith("error in ") and "Boom: injected failure" in outcome["message"], outcome
    assert "Traceback" in run.stderr  # the developer still gets the traceback on stderr
