"""The numba settings of every compiled kernel of the package (dynamics and collision).

Kernels are compiled once per machine and cached (``cache=True``) next to their modules in
``__pycache__``.  When the package directory is not writable (an installed package, a
read-only or another user's checkout), the cache goes to a per-user directory under the
temporary directory instead, so later processes still load machine code rather than
compiling again.  Importing this module applies that choice before any kernel is defined.
Imports nothing of the project.
"""
from __future__ import annotations

import os
import tempfile
from pathlib import Path

import numba

if not os.access(Path(__file__).resolve().parent, os.W_OK) and not os.environ.get("NUMBA_CACHE_DIR"):
    numba.config.CACHE_DIR = str(Path(tempfile.gettempdir()) / f"robot_sim-numba-{os.getuid()}")

#: Options of every compiled kernel: cached, releasing the GIL, NumPy's float semantics.
JIT = dict(cache=True, nogil=True, error_model="numpy")
