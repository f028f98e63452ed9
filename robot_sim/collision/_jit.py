"""The numba settings of the collision kernels (compiled once per machine, cached).

The kernels are scalar code over one shape pair or one configuration; the batched
entry points loop over configurations inside compiled code.  Where the machine code is
cached is :mod:`robot_sim.jit`'s choice, shared with the dynamics kernels.

numba checks a cached function against its own file only, not against the files of the
functions it calls (which it compiled in): a kernel edited in ``closest.py`` would stay
stale inside ``batch.py``'s cache.  So the cache of all kernel modules is dropped
whenever any of their sources changes (a digest of them is kept next to the cache).
A shared ``NUMBA_CACHE_DIR`` holds one folder per source directory; only this checkout's
folder is stamped and dropped, so two checkouts never wipe each other's machine code.
"""
from __future__ import annotations

from pathlib import Path

from numba import njit

from robot_sim import jit
from robot_sim.jit import JIT

HERE = Path(__file__).resolve().parent
#: The modules holding compiled kernels (they call each other).
KERNEL_MODULES = ("closest", "gjk", "narrow", "batch", "contact_kernels", "certify")


def _cache_dirs() -> list[Path]:
    """Where numba may keep this package's kernels: beside them, and its folder in CACHE_DIR."""
    return jit.cache_dirs(HERE, "batch.py")


def drop_stale_cache() -> None:
    """Remove the cached machine code of the kernel modules if their sources changed."""
    jit.drop_stale_cache(HERE, KERNEL_MODULES, "collision-kernels.sha256", "batch.py")


drop_stale_cache()

__all__ = ["JIT", "njit"]
