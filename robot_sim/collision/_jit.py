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

import hashlib
from pathlib import Path

import numba
from numba import njit
from numba.core.caching import UserProvidedCacheLocator

from robot_sim.jit import JIT

HERE = Path(__file__).resolve().parent
#: The modules holding compiled kernels (they call each other).
KERNEL_MODULES = ("closest", "gjk", "narrow", "batch", "contact_kernels", "certify")


def _cache_dirs() -> list[Path]:
    """Where numba may keep this package's kernels: beside them, and its folder in CACHE_DIR."""
    dirs = [HERE / "__pycache__"]
    if numba.config.CACHE_DIR:
        folder = UserProvidedCacheLocator.get_suitable_cache_subpath(str(HERE / "batch.py"))
        dirs.append(Path(numba.config.CACHE_DIR) / folder)
    return dirs


def drop_stale_cache() -> None:
    """Remove the cached machine code of the kernel modules if their sources changed."""
    digest = hashlib.sha256()
    for name in KERNEL_MODULES:
        path = HERE / f"{name}.py"
        if path.exists():
            digest.update(path.read_bytes())
    stamp_text = digest.hexdigest()
    for cache in _cache_dirs():
        stamp = cache / "collision-kernels.sha256"
        try:
            cache.mkdir(parents=True, exist_ok=True)  # stamped before numba's first save
            if stamp.exists() and stamp.read_text() == stamp_text:
                continue
            for name in KERNEL_MODULES:
                for old in cache.glob(f"{name}.*.nb[ic]"):
                    old.unlink(missing_ok=True)
            stamp.write_text(stamp_text)
        except OSError:  # a read-only or vanishing cache: numba recompiles as needed
            continue


drop_stale_cache()

__all__ = ["JIT", "njit"]
