"""Safe file access: every file the program writes goes through :func:`write_atomic`, every
file it reads through :func:`read_regular_file`.

A file is either written completely or not at all: the data goes to a temporary file in
the target's directory, is flushed to the disk (``fsync``), and only then renamed over the
target (``os.replace``, atomic on POSIX).  A failure on the way (full disk, quota, I/O
error) removes the temporary file and leaves any previous target untouched.  Targets that
are not regular files (a directory, a FIFO, a device, a socket) are refused before
anything is written, so writing never blocks on a FIFO and never replaces ``/dev/null``.
Reading likewise refuses what is not a regular file (without blocking on a FIFO) and
files larger than the caller's bound.
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


class FileError(OSError):
    """A file could not be read or written.  ``reason`` says why in a few words (the
    system's message, or "it is a directory, not a regular file"), ``filename`` is the
    path as given and ``errno`` the underlying error number when there is one."""

    VERB = "access"

    def __init__(self, path: str, reason: str, code: int | None = None) -> None:
        super().__init__(f"cannot {self.VERB} '{path}': {reason}")
        self.errno = code
        self.strerror = reason  # so code that reports ``exc.strerror`` of an OSError shows the reason
        self.filename = path
        self.reason = reason

    def __str__(self) -> str:
        return str(self.args[0])


class FileWriteError(FileError):
    """A file could not be written (the target and its directory are unchanged)."""

    VERB = "write"


class FileReadError(FileError):
    """A file could not be read."""

    VERB = "read"


def _non_regular(mode: int) -> str | None:
    """What a file of this ``st_mode`` is when it is not a regular file, else None."""
    for is_kind, kind in _KINDS:
        if is_kind(mode):
            return f"it is {kind}, not a regular file"
    return None


def read_regular_file(path: str | os.PathLike[str], max_bytes: int) -> bytes:
    """The bytes of the regular file at ``path``, which must hold at most ``max_bytes``.

    Raises :class:`FileReadError` naming the path and the reason: not found, permission
    denied, name too long, a symbolic-link loop, not a regular file (a directory, a FIFO,
    a device: refused without reading or waiting), or larger than ``max_bytes``.
    """
    shown = os.fspath(path)
    try:
        # O_NONBLOCK: a FIFO opens at once instead of waiting for a writer, and is refused.
        fd = os.open(shown, os.O_RDONLY | os.O_NONBLOCK | os.O_NOCTTY)
    except OSError as exc:
        raise FileReadError(shown, exc.strerror or str(exc), exc.errno) from None
    except ValueError:  # a NUL character in the name
        raise FileReadError(shown, "the file name contains a NUL character", errno.EINVAL) from None
    try:
        st = os.fstat(fd)
        reason = _non_regular(st.st_mode)
        if reason is None and st.st_size > max_bytes:
            reason = f"it is larger than {max_bytes} bytes"
        if reason is not None:
            raise FileReadError(shown, reason, errno.EINVAL)
        chunks, total = [], 0
        while total <= max_bytes:
            chunk = os.read(fd, max_bytes + 1 - total)
            if not chunk:
                break
            chunks.append(chunk)
            total += len(chunk)
        if total > max_bytes:  # it grew while we read it
            raise FileReadError(shown, f"it is larger than {max_bytes} bytes", errno.EFBIG)
        return b"".join(chunks)
    except FileReadError:
        raise
    except OSError as exc:
        raise FileReadError(shown, exc.strerror or str(exc), exc.errno) from None
    finally:
        os.close(fd)


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
    reason = _non_regular(st.st_mode)
    if reason is not None:
        raise FileWriteError(shown, reason, errno.EINVAL)
    return Path(os.path.realpath(target)), stat.S_IMODE(st.st_mode)


def check_writable(path: str | os.PathLike[str]) -> None:
    """Check, before any work is done, that :func:`write_atomic` could write ``path``:
    FileWriteError for a target that is not a regular file, a missing directory, a name
    longer than the file system accepts, or a directory that cannot be entered or written
    (as judged for the real user).  Writing may still fail later (a full disk)."""
    shown = os.fspath(path)
    target, _ = _target(path)
    try:
        name_max = os.pathconf(target.parent, "PC_NAME_MAX")
    except (OSError, ValueError):
        name_max = None
    if name_max is not None and len(os.fsencode(target.name)) > name_max:
        raise FileWriteError(shown, os.strerror(errno.ENAMETOOLONG), errno.ENAMETOOLONG)
    if not os.access(target.parent, os.W_OK | os.X_OK):
        raise FileWriteError(shown, os.strerror(errno.EACCES), errno.EACCES)


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
