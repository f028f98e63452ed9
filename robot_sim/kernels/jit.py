"""The numba settings and the one cache rule of every compiled kernel of the package.

Kernels are compiled once per machine and cached (``cache=True``) next to their modules in
``__pycache__``.  When the package directory is not writable (an installed package, a
read-only or another user's checkout), the cache goes to a per-user directory under the
temporary directory instead, so later processes still load machine code rather than
compiling again.

numba checks a cached function against its own file only, not against the files of the
functions it calls (which it compiled in): a kernel edited in ``kernels/algebra.py`` would
stay stale inside the cached machine code of ``dynamics.compiled`` or of the collision
loops.  So the rule is one for the whole package: every module that takes its settings
from here is a kernel source, and the cached machine code of all of them is dropped
whenever any of their sources changes (a digest of them is kept next to each cache).
A shared ``NUMBA_CACHE_DIR`` holds one folder per source directory; only this checkout's
folders are stamped and dropped, so two checkouts never wipe each other's machine code.

A kernel called from another kernel is compiled for its arguments' plain types, never for
the literal value a call site passes (``fd_one(..., False, ...)`` and ``fd_one(..., held,
...)`` are one machine code, not two): numba would otherwise compile a callee once more per
constant it is called with, which had the contact torque compiled three times (about a
minute of CPU on a fresh clone) and a GJK helper six times.  This holds for the package's
kernels only (:func:`plain_argument_types`).

Importing this module applies these choices before any kernel is defined.  Imports
nothing of the project.
"""
from __future__ import annotations

import hashlib
import os
import tempfile
from pathlib import Path

import numba
from numba import njit
from numba.core import types
from numba.core.caching import UserProvidedCacheLocator
from numba.core.dispatcher import Dispatcher

PACKAGE = Path(__file__).resolve().parent.parent
#: The text by which a module of the package declares itself a kernel source.
KERNEL_MARK = b"from robot_sim.kernels.jit import"
#: The stamp file holding the digest of the kernel sources, in each cache folder.
STAMP = "robot_sim-kernels.sha256"

if not os.access(PACKAGE, os.W_OK) and not os.environ.get("NUMBA_CACHE_DIR"):
    numba.config.CACHE_DIR = str(Path(tempfile.gettempdir()) / f"robot_sim-numba-{os.getuid()}")

#: Options of every compiled kernel: cached, releasing the GIL, NumPy's float semantics.
JIT = dict(cache=True, nogil=True, error_model="numpy")
#: Options of small helpers, inlined into the kernels that call them.
INLINE = dict(JIT, inline="always")
#: Options of kernels called at every step whose arithmetic is smaller than numba's
#: bookkeeping (the contact kernels; the IK families' solvers, called once per block of
#: poses): :data:`JIT`'s without numba's reference counting of
#: arrays (its ``_nrt`` flag off).  Such a kernel allocates nothing and returns no array;
#: counted, each array it is passed and each view it takes would cost two calls of the
#: runtime at every call (more than the arithmetic of the contact points of a UR5 at rest).
UNCOUNTED = dict(JIT, _nrt=False)


def kernel_sources() -> list[Path]:
    """The package's modules holding compiled kernels (those importing this module), and
    this module itself, sorted."""
    found = [Path(__file__).resolve()]
    for path in sorted(PACKAGE.rglob("*.py")):
        try:
            if path.name != "jit.py" and KERNEL_MARK in path.read_bytes():
                found.append(path)
        except OSError:  # vanished while listed
            continue
    return found


def sources_digest(sources: list[Path]) -> str:
    """SHA-256 over the kernel sources' package paths and contents."""
    digest = hashlib.sha256()
    for path in sources:
        digest.update(str(path.relative_to(PACKAGE)).encode() + b"\0")
        try:
            digest.update(path.read_bytes())
        except OSError:
            continue
    return digest.hexdigest()


def cache_dirs(folder: Path) -> list[Path]:
    """Where numba may keep the kernels of the source ``folder``: beside them, and that
    folder's subfolder of ``numba.config.CACHE_DIR`` when one is set."""
    dirs = [folder / "__pycache__"]
    if numba.config.CACHE_DIR:
        sub = UserProvidedCacheLocator.get_suitable_cache_subpath(str(folder / "__init__.py"))
        dirs.append(Path(numba.config.CACHE_DIR) / sub)
    return dirs


def drop_stale_cache() -> None:
    """Remove the cached machine code of every kernel module if any kernel source changed."""
    sources = kernel_sources()
    stamp_text = sources_digest(sources)
    by_folder: dict[Path, list[str]] = {}
    for path in sources:
        by_folder.setdefault(path.parent, []).append(path.stem)
    for folder, names in by_folder.items():
        for cache in cache_dirs(folder):
            stamp = cache / STAMP
            try:
                cache.mkdir(parents=True, exist_ok=True)  # stamped before numba's first save
                if stamp.exists() and stamp.read_text() == stamp_text:
                    continue
                for name in names:
                    for old in cache.glob(f"{name}.*.nb[ic]"):
                        old.unlink(missing_ok=True)
                stamp.write_text(stamp_text)
            except OSError:  # a read-only or vanishing cache: numba recompiles as needed
                continue


drop_stale_cache()


def plain_argument_types() -> None:
    """Make a call from compiled code to one of the package's kernels compile (or reuse)
    the kernel for the plain types of its arguments (``bool`` for ``Literal[bool](True)``,
    ``int64`` for ``Literal[int](3)``).  Other projects' numba functions are left as numba
    types them.  Idempotent."""
    plain = Dispatcher.get_call_template
    if getattr(plain, "_plain_argument_types", False):
        return

    def get_call_template(self, args, kws):  # noqa: ANN001, ANN202 - numba's signature
        if self.py_func.__module__.startswith("robot_sim."):
            _, args = self._compiler.fold_argument_types(args, kws)
            args, kws = tuple(types.unliteral(a) for a in args), {}
        return plain(self, args, kws)

    get_call_template._plain_argument_types = True
    Dispatcher.get_call_template = get_call_template


plain_argument_types()

__all__ = ["INLINE", "JIT", "njit"]
