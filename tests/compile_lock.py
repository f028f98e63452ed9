"""One compile per kernel for the whole suite, however many processes run it.

``make test`` runs the suite in several processes at once (the headless tests in two
pytest-xdist workers, the window tests beside them).  On a fresh clone numba's on-disk
cache is empty, and numba has no lock between processes: every process that reaches a
kernel before another has saved it compiles it again (tens of seconds of CPU for the
dynamics and collision kernels).  :func:`install` makes each process take an exclusive
file lock per cached kernel while it compiles or loads one; a process that finds the lock
taken waits, then loads the machine code the other one saved (numba's ``compile`` looks
in the cache first).  The lock also keeps two processes from rewriting a kernel's cache
index at the same time, which could lose the other's entry.

Locks are per kernel (its cache index file), re-entrant within a process (a kernel's
compile compiles the kernels it calls: their locks nest along the call graph, which has
no cycle, so two processes cannot wait for each other), and live in a folder of the
temporary directory, never in the checkout.
"""
from __future__ import annotations

import fcntl
import hashlib
import os
import tempfile
from pathlib import Path

LOCKS = Path(tempfile.gettempdir()) / f"robot_sim-numba-locks-{os.getuid()}"

_held: dict[str, tuple[int, int]] = {}  # lock path -> (file descriptor, depth), this process


def _lock_path(index_path: str) -> str:
    return str(LOCKS / (hashlib.sha256(index_path.encode()).hexdigest()[:32] + ".lock"))


def _acquire(path: str) -> None:
    fd_depth = _held.get(path)
    if fd_depth is not None:
        _held[path] = (fd_depth[0], fd_depth[1] + 1)
        return
    LOCKS.mkdir(parents=True, exist_ok=True)
    fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o600)
    fcntl.flock(fd, fcntl.LOCK_EX)
    _held[path] = (fd, 1)


def _release(path: str) -> None:
    fd, depth = _held[path]
    if depth > 1:
        _held[path] = (fd, depth - 1)
        return
    del _held[path]
    fcntl.flock(fd, fcntl.LOCK_UN)
    os.close(fd)


def install() -> None:
    """Wrap numba's ``Dispatcher.compile`` (which loads from the cache, else compiles and
    saves) in the kernel's lock, for kernels compiled with ``cache=True``.  Idempotent."""
    from numba.core import sigutils
    from numba.core.compiler_lock import global_compiler_lock
    from numba.core.dispatcher import Dispatcher

    if getattr(Dispatcher.compile, "_one_compile_per_kernel", False):
        return
    plain = Dispatcher.compile

    def compile(self, sig):  # noqa: ANN001, ANN202 - numba's signature
        cache_file = getattr(self._cache, "_cache_file", None)
        if cache_file is None or tuple(sigutils.normalize_signature(sig)[0]) in self.overloads:
            return plain(self, sig)
        path = _lock_path(cache_file._index_path)
        with global_compiler_lock:  # numba's own (threads of this process), taken first as numba does
            _acquire(path)
            try:
                return plain(self, sig)
            finally:
                _release(path)

    compile._one_compile_per_kernel = True
    Dispatcher.compile = compile
