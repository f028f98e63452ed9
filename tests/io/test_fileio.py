"""fileio.write_atomic: complete file or none, non-regular targets refused, clear errors."""
from __future__ import annotations

import errno
import os
import stat
import subprocess
from pathlib import Path

import pytest

from robot_sim.io import files as fileio
from robot_sim.io.files import FileWriteError, write_atomic


def listing(directory: Path) -> list[str]:
    return sorted(p.name for p in directory.iterdir())


def test_writes_bytes_and_text(tmp_path: Path) -> None:
    write_atomic(tmp_path / "a.bin", b"\x00\x01\xff")
    write_atomic(tmp_path / "b.txt", "gr\u00fc\u00dfe\n")
    assert (tmp_path / "a.bin").read_bytes() == b"\x00\x01\xff"
    assert (tmp_path / "b.txt").read_bytes() == "gr\u00fc\u00dfe\n".encode("utf-8")
    assert listing(tmp_path) == ["a.bin", "b.txt"]  # no temporary file left


def test_new_file_gets_umask_permissions_existing_keeps_its_own(tmp_path: Path) -> None:
    old = os.umask(0o027)
    try:
        write_atomic(tmp_path / "new", b"x")
    finally:
        os.umask(old)
    assert stat.S_IMODE((tmp_path / "new").stat().st_mode) == 0o640
    existing = tmp_path / "existing"
    existing.write_bytes(b"old")
    existing.chmod(0o604)
    write_atomic(existing, b"new")
    assert existing.read_bytes() == b"new"
    assert stat.S_IMODE(existing.stat().st_mode) == 0o604


def test_symlink_keeps_pointing_at_the_new_file(tmp_path: Path) -> None:
    real = tmp_path / "real.png"
    real.write_bytes(b"old")
    link = tmp_path / "link.png"
    link.symlink_to(real)
    write_atomic(link, b"new")
    assert link.is_symlink() and real.read_bytes() == b"new"


@pytest.mark.parametrize(
    "make, kind",
    [
        (lambda p: p.mkdir(), "a directory"),
        (lambda p: os.mkfifo(p), "a FIFO (named pipe)"),
    ],
)
def test_refuses_targets_that_are_not_regular_files(tmp_path: Path, make, kind: str) -> None:
    target = tmp_path / "target"
    make(target)
    with pytest.raises(FileWriteError) as info:
        write_atomic(target, b"data")  # a FIFO must not block: it is never opened
    assert str(info.value) == f"cannot write '{target}': it is {kind}, not a regular file"
    assert listing(tmp_path) == ["target"]


def test_refuses_a_device() -> None:
    with pytest.raises(FileWriteError, match=r"^cannot write '/dev/null': it is a character device, not a regular file$"):
        write_atomic("/dev/null", b"data")
    assert stat.S_ISCHR(os.stat("/dev/null").st_mode)


def test_missing_directory_and_too_long_name(tmp_path: Path) -> None:
    with pytest.raises(FileWriteError, match=r"directory '.*/nowhere' does not exist$"):
        write_atomic(tmp_path / "nowhere" / "x.png", b"data")
    long_name = tmp_path / ("x" * 300 + ".png")
    with pytest.raises(FileWriteError) as info:
        write_atomic(long_name, b"data")
    assert info.value.errno == errno.ENAMETOOLONG
    assert str(info.value).endswith("File name too long")
    assert listing(tmp_path) == []


def test_symlink_loop_is_an_error(tmp_path: Path) -> None:
    loop = tmp_path / "loop"
    loop.symlink_to(loop)
    with pytest.raises(FileWriteError, match="Too many levels of symbolic links"):
        write_atomic(loop, b"data")


def test_failure_while_writing_leaves_old_file_and_no_temporary(tmp_path: Path, monkeypatch) -> None:
    target = tmp_path / "shot.png"
    target.write_bytes(b"previous picture")

    def full_disk(fd: int) -> None:
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(fileio.os, "fsync", full_disk)
    with pytest.raises(FileWriteError) as info:
        write_atomic(target, b"x" * 100_000)
    assert str(info.value) == f"cannot write '{target}': No space left on device"
    assert info.value.errno == errno.ENOSPC
    assert target.read_bytes() == b"previous picture"
    assert listing(tmp_path) == ["shot.png"]


def _small_tmpfs(mount_point: Path) -> str | None:
    """Mount a 64 KiB tmpfs; None when mounted, else the reason it cannot be."""
    if os.geteuid() != 0:
        return "a full disk needs a small tmpfs, which only root can mount"
    mount_point.mkdir()
    run = subprocess.run(
        ["mount", "-t", "tmpfs", "-o", "size=64k", "tmpfs", str(mount_point)], capture_output=True, text=True
    )
    return None if run.returncode == 0 else f"mount -t tmpfs failed: {run.stderr.strip()}"


def test_really_full_disk_leaves_no_file(tmp_path: Path) -> None:
    disk = tmp_path / "disk"
    reason = _small_tmpfs(disk)
    if reason:
        print(f"SKIPPED full-disk test: {reason}")
        pytest.skip(reason)
    try:
        (disk / "old.png").write_bytes(b"old")
        with pytest.raises(FileWriteError, match="No space left on device"):
            write_atomic(disk / "big.png", os.urandom(256 * 1024))
        with pytest.raises(FileWriteError, match="No space left on device"):
            write_atomic(disk / "old.png", os.urandom(256 * 1024))
        assert listing(disk) == ["old.png"]
        assert (disk / "old.png").read_bytes() == b"old"
    finally:
        subprocess.run(["umount", str(disk)], check=True)
