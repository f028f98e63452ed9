"""Issue 31, outputs: a recording is staged beside its folder and moved into place when
complete (a full disk leaves the earlier one as it was, with one error line); outputs
and counts are checked before any work starts."""
from __future__ import annotations

import errno

import pytest

from robot_sim import graphics as go
from robot_sim.app.main import main
from robot_sim.viewer import settings as vs

RECORD = ["--robot", "planar3", "--size", "48x36", "--fps", "10"]


def _one_error_line(capsys, *fragments):
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err, err
    for fragment in fragments:
        assert fragment in err, err


def test_a_full_disk_during_a_recording_leaves_the_earlier_one_intact(tmp_path, capsys, monkeypatch):
    out = tmp_path / "rec"
    assert main([*RECORD, "--record", str(out), "--duration", "0.2"]) == 0
    capsys.readouterr()
    before = {p.name: p.read_bytes() for p in out.iterdir()}
    assert sorted(before)[:3] == ["frame_00000.png", "frame_00001.png", "frame_00002.png"]
    save = go.save_png
    written = []

    def full_disk(path, image, text=None):
        if written:
            raise OSError(errno.ENOSPC, "No space left on device")
        written.append(path)
        save(path, image, text)

    monkeypatch.setattr(go, "save_png", full_disk)
    assert main([*RECORD, "--record", str(out), "--duration", "0.5", "--q", "0.3,0.2,0.1"]) == 2
    _one_error_line(capsys, f"--record: cannot write frames to '{out}': No space left on device")
    assert {p.name: p.read_bytes() for p in out.iterdir()} == before  # not one byte changed
    assert sorted(p.name for p in tmp_path.iterdir()) == ["rec"]  # no staging folder left behind


def test_record_frame_count_is_bounded_before_anything(tmp_path, capsys):
    out = tmp_path / "d"
    assert main([*RECORD, "--record", str(out), "--duration", "1e9", "--fps", "1000"]) == 2
    _one_error_line(capsys, "--duration × --fps: 1e+09 s at 1000 frames per second is 1e+12 frames; "
                            f"at most {vs.RECORD_MAX_FRAMES} are accepted")
    assert not out.exists()


def test_a_refused_size_creates_no_record_folder(tmp_path, capsys):
    out = tmp_path / "newdir"
    assert main(["--robot", "planar3", "--record", str(out), "--size", "0x0"]) == 2
    _one_error_line(capsys, "--size")
    assert not out.exists()


def test_a_recording_into_a_missing_parent_is_refused_before_rendering(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr(go, "save_png", lambda *a, **k: pytest.fail("rendered a recording it cannot keep"))
    out = tmp_path / "missing" / "rec"
    assert main([*RECORD, "--record", str(out)]) == 2
    _one_error_line(capsys, f"--record: cannot write frames to '{out}': its parent folder {out.parent} does not exist")
