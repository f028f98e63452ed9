"""Mesh files of robot descriptions: where a mesh reference points, and reading the file.

* :func:`resolve_mesh_uri` turns a URDF ``<mesh filename=...>`` (``package://PKG/path``,
  ``file:///abs/path``, an absolute path or a path relative to the URDF's folder) into a
  file path.  ``package://PKG`` is looked up, in this order, in the entries of the
  ``ROS_PACKAGE_PATH`` environment variable (an entry that is the folder ``PKG`` itself,
  or holds ``PKG/``), then in the URDF's parent folders (one named ``PKG`` or holding
  ``PKG/``), and last as the nearest parent folder that holds the rest of the path (a
  description copied out of its ROS package under another name, as RViz users often do).
* :func:`read_mesh` is the one reader of mesh files, for URDFs, robot files, world files
  and ``Mesh(path)`` (installed as ``robot_sim.model.shapes.MESH_FILE_READER``).  It
  accepts STL, OBJ, PLY and Collada DAE (no archives, no other format), refuses a file
  over MAX_MESH_BYTES before reading it, and parses it with
  :mod:`robot_sim.io.mesh_formats` (declared element counts checked against the file's
  size first): the triangles of the whole file in metres (a DAE's ``<unit meter=...>`` is
  applied, its ``up_axis`` is not, as in RViz), node transforms applied.  ``trimesh`` is
  imported on the first read, so robots without meshes never load it.  A file unchanged
  since it was read (resolved path, size, modification time) is not read again, nor one
  that failed: a robot edited in the DH table is parsed again at every edit, and a
  thousand obstacles of one file share one copy of its triangles.
* :class:`MeshReader` reads the meshes of one robot description into shapes and turns a
  failure into the caller's one-line error, or, with ``skip_missing``, into one
  :class:`MeshSkippedWarning` per file and no shape.

Vertices are metres in the mesh file's own frame (before any scale or pose).
"""
from __future__ import annotations

import errno
import os
import warnings
from collections.abc import Callable
from pathlib import Path
from urllib.parse import unquote, urlsplit

from numpy.typing import ArrayLike

from robot_sim.io.files import FileReadError, read_regular_file
from robot_sim.io.mesh_formats import MESH_FORMATS, MeshArrays, MeshFormatError, parse_mesh
from robot_sim.model import shapes
from robot_sim.model.messages import clip, clip_middle, clip_repr
from robot_sim.model.shapes import Color, Mesh

#: Largest mesh file read (bytes), checked before reading: CAD exports of arm links are
#: far smaller, and parsing takes several times a file's size in memory.
MAX_MESH_BYTES = 64 << 20
#: Environment variable listing ROS package folders (``os.pathsep`` separated).
PACKAGE_PATH_VARIABLE = "ROS_PACKAGE_PATH"


class MeshError(ValueError):
    """A mesh reference could not be resolved or its file not read; the message says why
    (with the path tried) and leaves naming the robot file to the caller."""


class MeshSkippedWarning(UserWarning):
    """A mesh was left out of a robot loaded with ``skip_missing_meshes`` (one per file)."""


def _package_dirs(package: str, urdf_dir: Path, package_path: str | None) -> list[Path]:
    """Candidate folders of ROS package ``package``, in the order they are searched."""
    candidates: list[Path] = []
    for entry in (package_path or "").split(os.pathsep):
        if entry:
            root = Path(entry).expanduser()
            candidates += [root] if root.name == package else []
            candidates.append(root / package)
    for parent in (urdf_dir, *urdf_dir.parents):
        candidates += [parent] if parent.name == package else []
        candidates.append(parent / package)
    return candidates


def package_folder(package: str, urdf_dir: Path, package_path: str | None) -> Path | None:
    """The first existing folder of ROS package ``package`` for a description in folder
    ``urdf_dir`` (searched as :func:`resolve_mesh_uri` does), or None."""
    return next((d for d in _package_dirs(package, Path(os.path.abspath(urdf_dir)), package_path) if d.is_dir()), None)


def resolve_mesh_uri(uri: str, urdf_dir: Path, package_path: str | None = None) -> Path:
    """The file a URDF mesh ``uri`` names, for a URDF in folder ``urdf_dir``.

    ``package_path`` is the ``ROS_PACKAGE_PATH`` value to search (the environment's when
    None).  Raises :class:`MeshError` for an empty or unsupported URI (``http://``) and for
    a ``package://`` or local file that is nowhere to be found, naming what was tried.
    """
    if not uri.strip():
        raise MeshError("empty mesh filename")
    urdf_dir = Path(os.path.abspath(urdf_dir))  # a URDF named "arm.urdf" still has parent folders
    parts = urlsplit(uri)
    scheme = parts.scheme.lower()
    if scheme == "package":
        package, rest = parts.netloc, unquote(parts.path).lstrip("/")
        if not package or not rest:
            raise MeshError("expected package://PACKAGE/path/to/mesh")
        if package_path is None:
            package_path = os.environ.get(PACKAGE_PATH_VARIABLE, "")
        for folder in _package_dirs(package, urdf_dir, package_path):
            if (folder / rest).is_file():
                return folder / rest
        for parent in (urdf_dir, *urdf_dir.parents):  # a package folder renamed
            if (parent / rest).is_file():
                return parent / rest
        where = f"{PACKAGE_PATH_VARIABLE} ({clip(package_path) or 'unset'})"
        raise MeshError(f"package '{clip(package)}' with {clip_middle(rest)} not found in {where} or the URDF's parent folders")
    if scheme == "file":
        path = Path(unquote(parts.path))
    elif scheme and len(scheme) > 1:  # "c:" is a drive, not a scheme
        raise MeshError(f"unsupported URI scheme '{scheme}://'; accepted: package://, file:// or a file path")
    else:
        path = Path(uri).expanduser()
    return path if path.is_absolute() else urdf_dir / path


def read_mesh(path: Path) -> MeshArrays:
    """Vertices (V, 3) [m] and triangles (F, 3) of the mesh file at ``path`` (read-only).

    The one reader of mesh files (URDF, robot and world files, ``Mesh(path)``).  A file
    read before and unchanged since (same resolved path, size and modification time) is
    not read again, and neither is one that failed.  Raises :class:`MeshError` naming the
    path (a long one cut in the middle) and the kind of fault for a missing, unreadable or
    oversized file (MAX_MESH_BYTES, checked before reading), a format other than STL,
    OBJ, PLY or DAE, declared element counts the file cannot hold, contents that do not
    parse, or a file without a triangle; the file's contents are never quoted.
    """
    shown = clip_middle(str(path))
    suffix = path.suffix.lower()
    if suffix not in MESH_FORMATS:
        raise MeshError(f"{shown}: unsupported mesh format {clip_repr(path.suffix)}; accepted: {', '.join(MESH_FORMATS)}")
    try:
        resolved = os.path.realpath(path)
        info = os.stat(resolved)
        key = (resolved, info.st_size, info.st_mtime_ns)
    except (OSError, ValueError):
        key = None  # read_regular_file says why
    if key in _CACHE:
        return _CACHE[key]
    if key in _FAILED:
        raise MeshError(_FAILED[key])
    try:
        arrays = _read(path, shown, suffix)
    except MeshError as exc:
        if key is not None:
            _FAILED[key] = str(exc)
            while len(_FAILED) > MAX_CACHED_FAILURES:
                _FAILED.pop(next(iter(_FAILED)))
        raise
    if key is not None:
        _remember(key, arrays)
    return arrays


def _read(path: Path, shown: str, suffix: str) -> MeshArrays:
    try:
        raw = read_regular_file(path, MAX_MESH_BYTES)
    except FileReadError as exc:
        raise MeshError(f"{shown}: {'mesh file not found' if exc.errno == errno.ENOENT else exc.reason}") from None
    try:
        return parse_mesh(raw, suffix)
    except MeshFormatError as exc:
        raise MeshError(f"{shown}: not a readable {suffix} mesh: {exc}") from None
    except ImportError as exc:
        package = "trimesh" if exc.name == "trimesh" else (exc.name or "pycollada")
        raise MeshError(f"{shown}: reading {suffix} files needs {package} (pip install {package})") from None


#: Meshes read, by (resolved path, size, modification time).
_CACHE: dict[tuple[str, int, int], MeshArrays] = {}
#: Files that could not be read, by the same key, and the error each gave.
_FAILED: dict[tuple[str, int, int], str] = {}
#: Bytes of vertex and face data the cache keeps at most (the oldest entries go first).
MAX_CACHED_MESH_BYTES = 1 << 30
#: Failures remembered at most (the oldest go first).
MAX_CACHED_FAILURES = 1024


def _remember(key: tuple[str, int, int], arrays: MeshArrays) -> None:
    _CACHE.pop(key, None)
    _CACHE[key] = arrays
    total = sum(v.nbytes + f.nbytes for v, f in _CACHE.values())
    while total > MAX_CACHED_MESH_BYTES and len(_CACHE) > 1:
        oldest = next(iter(_CACHE))
        total -= sum(a.nbytes for a in _CACHE.pop(oldest))


class MeshReader:
    """Reads the meshes of one robot description into :class:`Mesh` shapes.

    ``fail(where, message)`` builds the caller's error (``RobotDefinitionError`` naming
    the robot file); with ``skip_missing`` a mesh that cannot be found or read is left out
    instead, and one :class:`MeshSkippedWarning` per file says so.
    """

    def __init__(self, fail: Callable[[str, str], Exception], skip_missing: bool = False) -> None:
        self.fail = fail
        self.skip_missing = skip_missing
        self._skipped: set[str] = set()

    def mesh(
        self, path: Path | MeshError, where: str, pose: ArrayLike, scale: ArrayLike, color: Color | None = None
    ) -> Mesh | None:
        """The mesh of the file ``path`` (or the MeshError that resolving its reference
        raised) placed by ``pose`` (4, 4) in its link frame and scaled by ``scale`` (3,);
        None when it is skipped.  ``where`` names the element (file, link and URI, or
        field) in the error or warning."""
        try:
            if isinstance(path, MeshError):
                raise path
            path = Path(os.path.abspath(path))
            vertices, faces = read_mesh(path)
        except MeshError as exc:
            if not self.skip_missing:
                raise self.fail(where, str(exc)) from None
            if str(exc) not in self._skipped:
                self._skipped.add(str(exc))
                warnings.warn(f"{self.fail(where, str(exc))}; mesh left out", MeshSkippedWarning, stacklevel=3)
            return None
        try:
            return Mesh.from_file_data(path, vertices, faces, pose=pose, scale=scale, color=color)
        except ValueError as exc:  # a scale or colour the shape refuses
            raise self.fail(where, clip(str(exc))) from None


shapes.MESH_FILE_READER[:] = [read_mesh]
