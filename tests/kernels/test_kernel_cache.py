"""The one cache rule of the compiled kernels: machine code that may be stale is dropped
(a cached caller whose callee changed in another file included), nobody else's is."""
from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import numba
import pytest

from paths import PACKAGE
from robot_sim.kernels import jit



@pytest.fixture
def cache_dir(tmp_path, monkeypatch):
    monkeypatch.setattr(numba.config, "CACHE_DIR", str(tmp_path / "numba"))
    return tmp_path / "numba"


def _own_folder(cache_dir: Path, folder: Path) -> Path:
    (found,) = [d for d in jit.cache_dirs(folder) if d.is_relative_to(cache_dir)]
    return found


def test_every_module_with_compiled_kernels_is_a_kernel_source():
    sources = {p.relative_to(PACKAGE).as_posix() for p in jit.kernel_sources()}
    with_njit = {p.relative_to(PACKAGE).as_posix() for p in PACKAGE.rglob("*.py") if "@njit" in p.read_text()}
    assert with_njit <= sources
    assert {"kernels/algebra.py", "kernels/chain.py", "dynamics/compiled.py", "collision/batch.py",
            "control/task_space_compiled.py"} <= sources


def test_a_new_cache_dir_is_stamped_before_numba_first_saves(cache_dir):
    # Without a stamp the next process took every kernel for stale and compiled
    # all of them again (about 100 s of CPU): the folder did not exist yet.
    jit.drop_stale_cache()
    own = _own_folder(cache_dir, PACKAGE / "collision")
    assert (own / jit.STAMP).is_file()
    kept = own / "batch.distance_batch-1.py311.nbi"
    kept.write_bytes(b"x")
    jit.drop_stale_cache()
    assert kept.exists()


def test_changed_sources_drop_only_this_checkout_s_kernels(cache_dir):
    jit.drop_stale_cache()
    own = _own_folder(cache_dir, PACKAGE / "collision")
    other = cache_dir / "collision_0123456789abcdef"  # another checkout's folder
    other.mkdir()
    (other / jit.STAMP).write_text("another digest")
    for folder in (own, other):
        (folder / "gjk.gjk-1.py311.nbi").write_bytes(b"x")
    (own / jit.STAMP).write_text("sources before an edit")
    jit.drop_stale_cache()
    assert not (own / "gjk.gjk-1.py311.nbi").exists()
    assert (other / "gjk.gjk-1.py311.nbi").exists()


CALLER = """
import numpy as np
from robot_sim.kernels import chain
from robot_sim.kernels.model import compiled_model
from robot_sim.io.robot_file import load_robot
robot = load_robot({robot!r})
model = compiled_model(robot)
F = np.empty((robot.n_dofs + 1, 3, 4))
chain.frames(model.table, model.modified, model.base, robot.q_home + 0.3, F)
print(repr(float(F[-1, 0, 3])), sum(chain.frames.stats.cache_hits.values()))
"""


def _run_caller(root: Path) -> tuple[str, int]:
    env = {k: v for k, v in os.environ.items() if k not in ("NUMBA_CACHE_DIR", "NUMBA_DISABLE_JIT")}
    env["PYTHONPATH"] = str(root)
    script = CALLER.format(robot=str(PACKAGE.parent / "robots" / "ur5.toml"))
    out = subprocess.run([sys.executable, "-c", script], cwd=root, env=env, capture_output=True, text=True,
                         timeout=600, check=True).stdout.split()
    return out[0], int(out[1])


def test_a_cached_caller_is_recompiled_when_a_callee_in_another_file_changes(tmp_path):
    # numba checks a cached function against its own file only: chain.frames (kernels/chain.py)
    # has cos_sin (kernels/algebra.py) compiled in, so without the package-wide rule an edit of
    # algebra.py would leave the old machine code of frames running.
    root = tmp_path / "copy"
    shutil.copytree(PACKAGE, root / "robot_sim", ignore=shutil.ignore_patterns("__pycache__"))
    first, _ = _run_caller(root)
    again, hits = _run_caller(root)
    assert again == first
    assert list((root / "robot_sim" / "kernels" / "__pycache__").glob("chain.frames-*.nbi"))
    assert hits > 0  # the second run loaded frames' machine code from the cache
    algebra = root / "robot_sim" / "kernels" / "algebra.py"
    source = algebra.read_text()
    edited = source.replace("        return cos_r, sin_r\n", "        return -cos_r, -sin_r\n", 1)
    assert edited != source
    algebra.write_text(edited)
    changed, _ = _run_caller(root)
    assert changed != first
