"""The numba settings of every compiled kernel of the package (dynamics and collision).

Kernels are compiled once per machine and cached (``cache=True``) next to their modules in
``__pycache__``.  When the package directory is not writable (an installed package, a
read-only or another user's checkout), the cache goes to a per-user directory under the
temporary directory instead, so later processes still load machine code rather than
compiling again.  Importing this module applies that choice before any kernel is defined.
Imports nothing of the project.
"""
from __future__ import annotations

import hashlib
import os
import tempfile
from pathlib import Path

import numba
from numba.core.caching import UserProvidedCacheLocator

if not os.access(Path(__file__).resolve().parent, os.W_OK) and not os.environ.get("NUMBA_CACHE_DIR"):
    numba.config.CACHE_DIR = str(Path(tempfile.gettempdir()) / f"robot_sim-numba-{os.getuid()}")

#: Options of every compiled kernel: cached, releasing the GIL, NumPy's float semantics.
JIT = dict(cache=True, nogil=True, error_model="numpy")


def cache_dirs(folder: Path, anchor: str) -> list[Path]:
    """Where numba may keep the kernels of the modules in ``folder``: beside them, and
    their folder in CACHE_DIR (named after the module file ``anchor``)."""
    dirs = [folder / "__pycache__"]
    if numba.config.CACHE_DIR:
        dirs.append(Path(numba.config.CACHE_DIR) / UserProvidedCacheLocator.get_suitable_cache_subpath(
            str(folder / anchor)))
    return dirs


def drop_stale_cache(folder: Path, modules: tuple[str, ...], stamp_name: str, anchor: str) -> None:
    """Remove the cached machine code of ``modules`` (files in ``folder``) if any of their
    sources changed.

    numba checks a cached function against its own file only, not against the files of the
    functions it calls (which it compiled in): a kernel edited in one module would stay
    stale inside another's cache.  So the cache of all the modules that call each other is
    dropped whenever any of their sources changes (a digest of them, ``stamp_name``, is
    kept next to the cache).  A shared ``NUMBA_CACHE_DIR`` holds one folder per source
    directory; only this checkout's folder is stamped and dropped, so two checkouts never
    wipe each other's machine code."""
    digest = hashlib.sha256()
    for name in modules:
        path = folder / f"{name}.py"
        if path.exists():
            digest.update(path.read_bytes())
    stamp_text = digest.hexdigest()
    for cache in cache_dirs(folder, anchor):
        stamp = cache / stamp_name
        try:
            cache.mkdir(parents=True, exist_ok=True)  # stamped before numba's first save
            if stamp.exists() and stamp.read_text() == stamp_text:
                continue
            for name in modules:
                for old in cache.glob(f"{name}.*.nb[ic]"):
                    old.unlink(missing_ok=True)
            stamp.write_text(stamp_text)
        except OSError:  # a read-only or vanishing cache: numba recompiles as needed
            continue
