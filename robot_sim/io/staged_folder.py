"""A folder of output files written beside its target and moved into place when complete.

:func:`staged_folder` gives a fresh temporary folder next to ``target`` (same file
system, so the files move by rename).  When the ``with`` block ends normally, every file
of the temporary folder replaces its namesake in ``target`` (``target`` is created if
missing: the temporary folder itself is renamed to it), and the files of an earlier
output that this one does not have (those ``owned`` says belong to the output) are
removed.  When the block raises (a full disk, an interrupt), the temporary folder is
removed and ``target`` is exactly as it was: an earlier recording survives a failed one.
"""
from __future__ import annotations

import contextlib
import os
import shutil
import tempfile
from collections.abc import Callable, Iterator
from pathlib import Path

#: Longest prefix of the target's name kept in the temporary folder's name.
_PREFIX_CHARS = 64


def check_output_folder(target: Path) -> str | None:
    """Why files cannot be written to the folder ``target`` (existing or to be created
    beside its siblings), or None: checked before any work starts, nothing created."""
    if target.exists():
        if not target.is_dir():
            return "it exists and is not a directory"
        if not os.access(target, os.W_OK | os.X_OK):
            return "the directory is not writable"
    parent = target.parent
    if not parent.is_dir():
        return f"its parent folder {parent} does not exist"
    if not os.access(parent, os.W_OK | os.X_OK):
        return f"its parent folder {parent} is not writable"
    return None


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


@contextlib.contextmanager
def staged_folder(target: Path, owned: Callable[[str], bool]) -> Iterator[Path]:
    """Yield a temporary folder beside ``target`` to write the output into; see the
    module docstring for what happens when the block ends or raises."""
    tmp = Path(tempfile.mkdtemp(prefix=f".{target.name[:_PREFIX_CHARS]}.", suffix=".tmp", dir=target.parent))
    try:
        yield tmp
        if not target.exists():
            os.chmod(tmp, 0o777 & ~_umask())  # mkdtemp made it private
            os.rename(tmp, target)
            return
        names = set(os.listdir(tmp))
        for name in sorted(names):
            os.replace(tmp / name, target / name)
        for path in target.iterdir():
            if path.name not in names and owned(path.name) and path.is_file():
                path.unlink()
        tmp.rmdir()
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
