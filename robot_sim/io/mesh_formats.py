"""Mesh file contents: the element counts a file declares checked against its size, then
the triangles parsed (STL, OBJ, PLY through ``trimesh``; DAE through ``trimesh`` with
``pycollada``).

:func:`parse_mesh` takes the bytes of a file already read (and size-capped) by
:mod:`robot_sim.io.meshes`.  Before anything is allocated it checks what a file declares
about its own size: a binary STL's triangle count must match its length exactly, a PLY
header's element counts must fit in the bytes that follow it.  A parser's own message is
never shown (it may quote the file): a fault is reported as :class:`MeshFormatError` with
a few words of our own (``"the parser failed (ValueError)"``).

OBJ files are read with trimesh's OBJ reader alone (``trimesh.exchange.obj.load_obj``), so
texture coordinates and materials are never turned into images: Pillow is not needed.

Vertices are metres in the file's own frame (a DAE's ``<unit meter=...>`` applied).
"""
from __future__ import annotations

import io
import re
import struct

import numpy as np
from numpy.typing import NDArray

#: Mesh file formats read (suffix, lower case) and trimesh's name of each; archives
#: (zip, tar.gz, ...) and every other format trimesh knows are refused.
MESH_FORMATS = {".stl": "stl", ".obj": "obj", ".ply": "ply", ".dae": "dae"}

MeshArrays = tuple[NDArray[np.float64], NDArray[np.int64]]

_STL_HEADER = 84  # 80 bytes of header, a uint32 triangle count
_STL_TRIANGLE = 50  # normal, 3 vertices (12 float32), a uint16 attribute
_PLY_TYPE_BYTES = {
    "char": 1, "uchar": 1, "int8": 1, "uint8": 1, "short": 2, "ushort": 2, "int16": 2, "uint16": 2,
    "int": 4, "uint": 4, "int32": 4, "uint32": 4, "float": 4, "float32": 4, "double": 8, "float64": 8,
}
_PLY_ASCII_BYTES = 2  # the shortest property in an ASCII PLY: one digit and a separator
_PLY_END = re.compile(rb"end_header\r?\n")
_PLY_MAX_HEADER = 64 << 10


class MeshFormatError(ValueError):
    """The contents of a mesh file are not a mesh we read; the message says what kind of
    fault (never quoting the file) and leaves naming the file and format to the caller."""


def check_declared_sizes(raw: bytes, suffix: str) -> None:
    """MeshFormatError when the element counts ``raw`` declares (binary STL, PLY) cannot
    fit in its length, checked before a parser allocates for them."""
    if suffix == ".stl":
        count = struct.unpack_from("<I", raw, 80)[0] if len(raw) >= _STL_HEADER else -1
        binary = _STL_HEADER + _STL_TRIANGLE * count == len(raw)
        if not binary and not raw[:1024].lstrip()[:5].lower() == b"solid":  # neither binary nor ASCII
            raise MeshFormatError(f"the file is not ASCII STL, and as binary STL its {len(raw)} bytes do not "
                                  f"match the header's count of {max(count, 0)} triangles")
    elif suffix == ".ply":
        _check_ply(raw)


def _check_ply(raw: bytes) -> None:
    end = _PLY_END.search(raw, 0, _PLY_MAX_HEADER)
    if not raw.startswith(b"ply") or end is None:
        raise MeshFormatError(f"a PLY file starts with 'ply' and a header ending in 'end_header' "
                              f"within {_PLY_MAX_HEADER} bytes")
    ascii_body = False
    need = 0  # the fewest bytes the declared elements take
    count, per = 0, 0
    for line in raw[:end.start()].decode("latin-1").splitlines():
        words = line.split()
        if not words:
            continue
        if words[0] == "format":
            ascii_body = len(words) > 1 and words[1] == "ascii"
        elif words[0] == "element":
            need += count * per
            try:
                count = int(words[2]) if len(words) == 3 else -1
            except ValueError:
                count = -1
            if count < 0:
                raise MeshFormatError("a PLY element line is not 'element NAME COUNT' with a count >= 0")
            per = 0
        elif words[0] == "property" and len(words) >= 3:
            kind = words[2] if words[1] == "list" else words[1]  # a list: its count's type
            per += _PLY_ASCII_BYTES if ascii_body else _PLY_TYPE_BYTES.get(kind, 1)
    need += count * per
    body = len(raw) - end.end()
    if need > body:
        raise MeshFormatError(f"the PLY header declares elements of at least {need} bytes, "
                              f"which do not fit in the file's {body} bytes of data")


def parse_mesh(raw: bytes, suffix: str) -> MeshArrays:
    """Vertices (V, 3) [m] and triangles (F, 3) of mesh file contents ``raw`` in the
    format of ``suffix`` (a key of MESH_FORMATS), read-only arrays.  Raises
    MeshFormatError for declared sizes the file cannot hold, contents that do not parse,
    no triangle or a vertex that is not finite; ImportError (with ``name``) when the
    format needs a package that is missing."""
    check_declared_sizes(raw, suffix)
    import trimesh  # imported here: only robots with meshes need it

    try:
        if suffix == ".obj":
            vertices, faces = _obj_arrays(raw)
        else:
            mesh = trimesh.load(io.BytesIO(raw), file_type=MESH_FORMATS[suffix], force="mesh")
            vertices = np.array(mesh.vertices, dtype=float).reshape(-1, 3)
            faces = np.array(mesh.faces, dtype=np.int64).reshape(-1, 3)
            if suffix == ".dae" and mesh.units:  # <unit meter="0.001"/> reads "0.001 * meters"
                vertices *= trimesh.units.unit_conversion(mesh.units, "meters")
    except ImportError:
        raise
    except Exception as exc:  # trimesh and its parsers raise anything on a corrupt file
        raise MeshFormatError(f"the parser failed ({type(exc).__name__})") from None
    if faces.shape[0] == 0:
        raise MeshFormatError("it holds no triangles")
    if not np.isfinite(vertices).all():
        raise MeshFormatError("a vertex is not a finite number")
    if faces.min() < 0 or faces.max() >= len(vertices):
        raise MeshFormatError("a face names a vertex that does not exist")
    vertices.setflags(write=False)
    faces.setflags(write=False)
    return vertices, faces


def _obj_arrays(raw: bytes) -> MeshArrays:
    """The triangles of every object in an OBJ file, without building its visuals."""
    from trimesh.exchange.obj import load_obj

    loaded = load_obj(io.BytesIO(raw), skip_materials=True)
    parts = list(loaded.get("geometry", {}).values())
    vertices, faces, offset = [], [], 0
    for part in parts:
        v = np.asarray(part["vertices"], dtype=float).reshape(-1, 3)
        f = np.asarray(part["faces"], dtype=np.int64).reshape(-1, 3)
        vertices.append(v)
        faces.append(f + offset)
        offset += len(v)
    if not parts:
        return np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64)
    return np.concatenate(vertices), np.concatenate(faces)
