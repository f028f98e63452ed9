"""The collision kernels' cache rule: stale machine code is dropped, nobody else's is."""
from __future__ import annotations

from pathlib import Path

import numba
import pytest

from robot_sim.collision import _jit


@pytest.fixture
def cache_dir(tmp_path, monkeypatch):
    monkeypatch.setattr(numba.config, "CACHE_DIR", str(tmp_path / "numba"))
    return tmp_path / "numba"


def _own_folder(cache_dir: Path) -> Path:
    (folder,) = [d for d in _jit._cache_dirs() if d.is_relative_to(cache_dir)]
    return folder


def test_a_new_cache_dir_is_stamped_before_numba_first_saves(cache_dir):
    # Without a stamp the next process took every kernel for stale and compiled
    # all of them again (about 100 s of CPU): the folder did not exist yet.
    _jit.drop_stale_cache()
    stamp = _own_folder(cache_dir) / "collision-kernels.sha256"
    assert stamp.is_file()
    kept = _own_folder(cache_dir) / "batch.distance_batch-1.py311.nbi"
    kept.write_bytes(b"x")
    _jit.drop_stale_cache()
    assert kept.exists()


def test_changed_sources_drop_only_this_checkout_s_kernels(cache_dir):
    _jit.drop_stale_cache()
    own = _own_folder(cache_dir)
    other = cache_dir / "collision_0123456789abcdef"  # another checkout's folder
    other.mkdir()
    (other / "collision-kernels.sha256").write_text("another digest")
    for folder in (own, other):
        (folder / "gjk.gjk-1.py311.nbi").write_bytes(b"x")
    (own / "collision-kernels.sha256").write_text("sources before an edit")
    _jit.drop_stale_cache()
    assert not (own / "gjk.gjk-1.py311.nbi").exists()
    assert (other / "gjk.gjk-1.py311.nbi").exists()
