"""Every notebook of docs/notebooks runs from top to bottom, headless (nbclient on an
IPython kernel, the checkout's robot_sim imported), without an error."""
from __future__ import annotations

import os
from pathlib import Path

import pytest
from paths import ROOT

NOTEBOOKS = sorted((ROOT / "docs" / "notebooks").glob("*.ipynb"))
#: Seconds one cell may take (planning and the first numba compile included).
CELL_TIMEOUT_S = 600


def test_the_tutorial_series_is_there() -> None:
    assert [p.name[:2] for p in NOTEBOOKS] == ["01", "02", "03", "04", "05"]


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_notebook_runs(path: Path, monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    import nbformat
    from jupyter_client.manager import KernelManager
    from nbclient import NotebookClient

    monkeypatch.setenv("PYTHONPATH", os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")]))
    book = nbformat.read(path, as_version=4)
    # The kernel's channels on Unix sockets in tmp_path: TCP ports are picked free and bound
    # later, and another process of the suite (a web view's server) can take one meanwhile.
    kernel = KernelManager(kernel_name="python3", transport="ipc", ip=str(tmp_path / "kernel"))
    NotebookClient(book, km=kernel, timeout=CELL_TIMEOUT_S,
                   resources={"metadata": {"path": str(path.parent)}}).execute()
    outputs = [o for cell in book.cells if cell.cell_type == "code" for o in cell.outputs]
    assert not [o for o in outputs if o.output_type == "error"]
    shown = [o for o in outputs if o.output_type == "execute_result" and "text/html" in o.get("data", {})]
    assert shown, "the notebook shows the robot inline"
    assert all("__VISER_EMBED_DATA__" in o["data"]["text/html"] for o in shown)
