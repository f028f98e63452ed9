"""Mesh files and URDFs with geometry for the geometry tests, generated with trimesh
into a test's tmp_path, and the expected world vertices of a URDF visual computed from
the URDF alone (urdf_parser_py's model and urdf_helpers' joint chain, never this
package's importer)."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import trimesh

from paths import ROOT
from urdf_helpers import origin_matrix, urdf_fk


def write_mesh(path: Path, mesh: trimesh.Trimesh) -> Path:
    """``mesh`` written to ``path`` in the format of its suffix (STL, OBJ, PLY, DAE)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    if path.suffix == ".dae":
        path.write_bytes(trimesh.exchange.dae.export_collada(mesh))
    else:
        mesh.export(path)
    return path


def odd_mesh(seed: int, size: float = 0.1) -> trimesh.Trimesh:
    """A small mesh without symmetry (a box with a moved corner), so a wrong pose shows."""
    rng = np.random.default_rng(seed)
    mesh = trimesh.creation.box((size, 0.6 * size, 0.3 * size))
    vertices = np.array(mesh.vertices)
    vertices[0] += rng.uniform(-0.2, 0.2, 3) * size
    vertices += rng.uniform(-0.5, 0.5, 3) * size
    return trimesh.Trimesh(vertices, mesh.faces, process=False)


def file_vertices(path: Path, unit: float = 1.0) -> np.ndarray:
    """The vertices of a mesh file as trimesh reads it (times the file's ``unit``)."""
    return np.asarray(trimesh.load(path, force="mesh").vertices, dtype=float) * unit


def urdf_visual_world(model, link: str, visual, q: np.ndarray, vertices: np.ndarray) -> np.ndarray:
    """World points (V, 3) of ``vertices`` of ``visual`` of ``link`` at joint values q:
    the link's pose through the URDF's joint chain, the visual's origin, its scale."""
    scale = np.ones(3)
    if visual.geometry.scale is not None:
        scale = np.broadcast_to(np.asarray(visual.geometry.scale, dtype=float), 3)
    T = urdf_fk(model, link, q) @ origin_matrix(visual.origin)
    return (T[:3, :3] @ (vertices * scale).T).T + T[:3, 3]


def shape_world(frame: np.ndarray, shape) -> np.ndarray:
    """World points (V, 3) of a mesh shape's vertices in link frame ``frame`` (4, 4)."""
    T = frame @ shape.pose
    return (T[:3, :3] @ shape.vertices.T).T + T[:3, 3]


def boxed_arm(folder: Path) -> Path:
    """The shipped planar3 robot file with a red box visual on link 2, written to
    ``folder`` (a robot that has a mesh look, without any mesh file)."""
    text = (ROOT / "robots" / "planar3.toml").read_text()
    third = text.index("[[joints]]", text.index("[[joints]]", text.index("[[joints]]") + 1) + 1)
    box = '\n[[joints.visual]]\nbox = [0.4, 0.12, 0.12]\nxyz = [-0.2, 0.0, 0.0]\ncolor = [0.9, 0.1, 0.1, 1.0]\n\n'
    path = folder / "boxed.toml"
    path.write_text(text[:third] + box + text[third:])
    return path
