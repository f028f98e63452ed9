"""Atomic file writing: every file the program writes goes through :func:`write_atomic`.

A file is either written completely or not at all: the data goes to a temporary file in
the target's directory, is flushed to the disk (``fsync``), and only then renamed over the
target (``os.replace``, atomic on POSIX).  A failure on the way (full disk, quota, I/O
error) removes the temporary file and leaves any previous target untouched.  Targets that
are not regular files (a directory, a FIFO, a device, a socket) are refused before
anything is written, so writing never blocks on a FIFO and never replaces ``/dev/null``.
"""
from __future__ import annotations

import errno
import os
import stat
import tempfile
from pathlib import Path

#: Longest prefix of the target's name kept in the temporary file's name, so that the
#: temporary name stays within NAME_MAX (255 bytes) for any valid target name.
_TMP_PREFIX_CHARS = 64

_KINDS = (
    (stat.S_ISDIR, "a directory"),
    (stat.S_ISFIFO, "a FIFO (named pipe)"),
    (stat.S_ISCHR, "a character device"),
    (stat.S_ISBLK, "a block device"),
    (stat.S_ISSOCK, "a socket"),
)


class FileWriteError(OSError):
    """A file could not be written; the message names the path and the reason, and
    ``errno`` holds the underlying error number when there is one."""

    def __init__(self, path: str, reason: str, code: int | None = None) -> None:
        super().__init__(f"cannot write '{path}': {reason}")
        self.errno = code
        self.filename = path

    def __str__(self) -> str:
        return str(self.args[0])


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def _target(path: str | os.PathLike[str]) -> tuple[Path, int | None]:
    """The file to replace (symbolic links followed, so a link keeps pointing at the new
    file) and its permission bits if it exists.  FileWriteError for a target that is not
    a regular file or a directory that does not exist."""
    shown = os.fspath(path)
    if not shown:
        raise FileWriteError(shown, "empty file name", errno.ENOENT)
    target = Path(shown)
    try:
        st = os.stat(target)
    except FileNotFoundError:
        if os.path.islink(target):  # a dangling link: write where it points
            target = Path(os.path.realpath(target))
        parent = target.parent
        if not parent.is_dir():
            raise FileWriteError(shown, f"directory '{parent}' does not exist", errno.ENOENT) from None
        return target, None
    except OSError as exc:
        raise FileWriteError(shown, exc.strerror or str(exc), exc.errno) from None
    for is_kind, kind in _KINDS:
        if is_kind(st.st_mode):
            raise FileWriteError(shown, f"it is {kind}, not a regular file", errno.EINVAL)
    return Path(os.path.realpath(target)), stat.S_IMODE(st.st_mode)


def write_atomic(path: str | os.PathLike[str], data: bytes | str) -> None:
    """Write ``data`` (bytes, or str encoded as UTF-8) to ``path`` atomically.

    The file appears complete or not at all, with the permissions of the file it replaces
    (or ``0o666`` minus the umask for a new file).  Raises :class:`FileWriteError` (an
    ``OSError``) naming the path and the reason: not a regular file, missing directory,
    permission denied, name too long, no space left, and so on; the target and its
    directory are then as they were.
    """
    payload = data.encode("utf-8") if isinstance(data, str) else bytes(data)
    shown = os.fspath(path)
    target, mode = _target(path)
    try:
        fd, tmp = tempfile.mkstemp(
            dir=target.parent, prefix=f".{target.name[:_TMP_PREFIX_CHARS]}.", suffix=".tmp"
        )
    except OSError as exc:
        raise FileWriteError(shown, exc.strerror or str(exc), exc.errno) from None
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(payload)
            fh.flush()
            os.fchmod(fh.fileno(), mode if mode is not None else 0o666 & ~_umask())
            os.fsync(fh.fileno())
        os.replace(tmp, target)
    except OSError as exc:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise FileWriteError(shown, exc.strerror or str(exc), exc.errno) from None
    _sync_directory(target.parent)


def _sync_directory(directory: Path) -> None:
    """Flush the rename to the disk (best effort: some file systems refuse fsync on a
    directory, and the data itself is already safe)."""
    try:
        fd = os.open(directory, os.O_RDONLY | os.O_DIRECTORY)
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:
        pass
    finally:
        os.close(fd)
