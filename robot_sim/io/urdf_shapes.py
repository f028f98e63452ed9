"""URDF ``<visual>`` and ``<collision>`` elements in and out (for :mod:`urdf_in`, :mod:`urdf_out`).

In: each element's ``<origin>`` (link frame → shape frame), its one ``<geometry>`` child
(``box size``, ``sphere radius``, ``cylinder radius length``, ``capsule radius length``,
``mesh filename scale``) and, for a visual, its ``<material>`` colour: an inline
``<color rgba>``, or the colour of the material of that name defined at the top of the
file or inline in an earlier visual (textures are not read).  Primitives become shapes
at once; meshes stay references (:class:`MeshRef`) until :func:`placed` knows which
links the chain keeps, so a missing mesh of a link off the chain is no error.  Elements
named :data:`DH_DRAWING_NAME` are skipped: they are the cylinders :func:`write_shapes`'s
caller writes for a robot without geometry, so that robot comes back without any.

Out: :func:`write_shapes` writes shapes as those elements; mesh filenames relative to
the folder the URDF is written to (absolute when it is not known).
"""
from __future__ import annotations

import os
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path
from typing import Protocol

import numpy as np

from robot_sim.io.meshes import MeshError, MeshReader, resolve_mesh_uri
from robot_sim.model.shapes import Box, Capsule, Color, Cylinder, Mesh, Sphere
from robot_sim.transforms import HomogeneousTransform, rpy_from_rot

#: Name of the visual and collision elements that only draw a robot's DH segments.
DH_DRAWING_NAME = "dh_drawing"
#: Geometry elements read, with the attributes each needs.
GEOMETRY_TAGS = {"box": ("size",), "sphere": ("radius",), "cylinder": ("radius", "length"),
                 "capsule": ("radius", "length"), "mesh": ("filename",)}

Shape = Box | Sphere | Cylinder | Capsule | Mesh


class _Reader(Protocol):
    def fail(self, where: str, message: str) -> Exception: ...

    def floats(self, element: ET.Element | None, attr: str, count: int, default: list[float], where: str) -> np.ndarray: ...


@dataclass(frozen=True)
class MeshRef:
    """A ``<mesh>`` not read yet: its URI, origin (4, 4) in its link frame, scale (3,),
    colour and the element's name for messages (``link 'x' visual 2``)."""

    uri: str
    origin: np.ndarray
    scale: np.ndarray
    color: Color | None
    where: str


@dataclass(frozen=True)
class LinkGeometry:
    """The visuals and collisions of one URDF link in its frame (shapes or mesh refs)."""

    visuals: tuple[Shape | MeshRef, ...] = ()
    collisions: tuple[Shape | MeshRef, ...] = ()


def materials(reader: _Reader, root: ET.Element) -> dict[str, Color]:
    """Colours of the named materials: the top-level ``<material>`` elements, then those
    defined inline in visuals (the first definition of a name wins)."""
    found: dict[str, Color] = {}
    for element in [*root.findall("material"), *root.findall("link/visual/material")]:
        name, color = element.get("name"), _rgba(reader, element, f"material '{element.get('name')}'")
        if name and color is not None:
            found.setdefault(name, color)
    return found


def _rgba(reader: _Reader, material: ET.Element, where: str) -> Color | None:
    tag = material.find("color")
    if tag is None or tag.get("rgba") is None:
        return None
    rgba = reader.floats(tag, "rgba", 4, [], f"{where} color")
    if not ((rgba >= 0.0) & (rgba <= 1.0)).all():
        raise reader.fail(f"{where} color", f"expected rgba in 0..1, got {tag.get('rgba')!r}")
    return tuple(float(v) for v in rgba)  # type: ignore[return-value]


def link_geometry(reader: _Reader, link: ET.Element, named: dict[str, Color]) -> LinkGeometry:
    """The checked visuals and collisions of ``link``; ``named`` are the file's material
    colours (:func:`materials`)."""
    name = link.get("name", "")
    out: dict[str, list[Shape | MeshRef]] = {"visual": [], "collision": []}
    for kind, items in out.items():
        for k, element in enumerate(link.findall(kind)):
            if element.get("name") == DH_DRAWING_NAME:
                continue
            where = f"link '{name}' {kind} {k + 1}"
            color = None
            material = element.find("material") if kind == "visual" else None
            if material is not None:
                color = _rgba(reader, material, f"{where} material")
                color = named.get(material.get("name", "")) if color is None else color
            items.append(_geometry(reader, element, where, color))
    return LinkGeometry(tuple(out["visual"]), tuple(out["collision"]))


def _geometry(reader: _Reader, element: ET.Element, where: str, color: Color | None) -> Shape | MeshRef:
    origin_tag = element.find("origin")
    xyz = reader.floats(origin_tag, "xyz", 3, [0.0, 0.0, 0.0], f"{where} origin")
    rpy = reader.floats(origin_tag, "rpy", 3, [0.0, 0.0, 0.0], f"{where} origin")
    origin = HomogeneousTransform.from_xyz_rpy(xyz, rpy).mat
    geometry = element.find("geometry")
    shapes = [] if geometry is None else [child for child in geometry if child.tag in GEOMETRY_TAGS]
    if len(shapes) != 1:
        raise reader.fail(where, f"expected one <geometry> holding one of {', '.join(GEOMETRY_TAGS)}")
    tag = shapes[0]
    where = f"{where} {tag.tag}"
    for attr in GEOMETRY_TAGS[tag.tag]:
        if tag.get(attr) is None:
            raise reader.fail(where, f"missing attribute {attr}")
    if tag.tag == "mesh":
        text = tag.get("scale", "1 1 1")
        scale = reader.floats(tag, "scale", 3 if len(text.split()) != 1 else 1, [1.0, 1.0, 1.0], where)
        if not (scale > 0.0).all():
            raise reader.fail(f"{where} scale", f"expected scale factors > 0, got {text!r}")
        return MeshRef(tag.get("filename", ""), origin, np.broadcast_to(scale, 3).copy(), color,
                       f"{where} '{tag.get('filename')}'")
    sizes = {attr: reader.floats(tag, attr, 3 if attr == "size" else 1, [], where) for attr in GEOMETRY_TAGS[tag.tag]}
    if not all((v > 0.0).all() or (tag.tag == "capsule" and a == "length" and v[0] == 0.0) for a, v in sizes.items()):
        raise reader.fail(where, f"expected lengths > 0 m, got {', '.join(f'{a}={tag.get(a)!r}' for a in sizes)}")
    if tag.tag == "box":
        return Box(sizes["size"], pose=origin, color=color)
    if tag.tag == "sphere":
        return Sphere(float(sizes["radius"][0]), center=origin[:3, 3], color=color)
    kind = Cylinder if tag.tag == "cylinder" else Capsule
    return kind(float(sizes["radius"][0]), float(sizes["length"][0]), pose=origin, color=color)


def placed(items: list[tuple[np.ndarray, Shape | MeshRef]], urdf_dir: Path, meshes: MeshReader) -> tuple[Shape, ...]:
    """The shapes of ``items`` (transform into the target frame, shape or mesh ref), each
    moved by its transform; meshes resolved from ``urdf_dir`` and read by ``meshes``
    (skipped ones left out)."""
    out: list[Shape] = []
    for tf, item in items:
        if not isinstance(item, MeshRef):
            out.append(item.moved(tf))
            continue
        try:
            path: Path | MeshError = resolve_mesh_uri(item.uri, urdf_dir)
        except MeshError as exc:
            path = exc
        mesh = meshes.mesh(path, item.where, tf @ item.origin, item.scale, item.color)
        if mesh is not None:
            out.append(mesh)
    return tuple(out)


def num_text(values: float | np.ndarray) -> str:
    """Space-separated shortest exact decimal forms (``repr``) of float values."""
    return " ".join(repr(float(v) + 0.0) for v in np.atleast_1d(values))


def write_origin(parent: ET.Element, mat: np.ndarray) -> None:
    """``<origin xyz rpy>`` of the rigid transform ``mat`` (4, 4) under ``parent``."""
    ET.SubElement(parent, "origin", xyz=num_text(mat[:3, 3]), rpy=num_text(np.array(rpy_from_rot(mat[:3, :3]))))


def mesh_filename(path: str, directory: Path | None) -> str:
    """``path`` as a URDF or robot-file mesh reference: relative to ``directory`` (posix
    separators) when given, else absolute."""
    absolute = os.path.abspath(path)
    if directory is None:
        return Path(absolute).as_posix()
    return Path(os.path.relpath(absolute, os.path.abspath(directory))).as_posix()


def write_shapes(link: ET.Element, kind: str, shapes: tuple[Shape, ...], directory: Path | None) -> None:
    """``shapes`` (posed in ``link``'s frame) as ``<visual>`` or ``<collision>`` (``kind``)
    elements of ``link``.  ValueError for a mesh that has no file (given as arrays)."""
    for k, shape in enumerate(shapes):
        element = ET.SubElement(link, kind)
        write_origin(element, shape.pose)
        geometry = ET.SubElement(element, "geometry")
        if isinstance(shape, Box):
            ET.SubElement(geometry, "box", size=num_text(shape.size))
        elif isinstance(shape, Sphere):
            ET.SubElement(geometry, "sphere", radius=num_text(shape.radius))
        elif isinstance(shape, (Cylinder, Capsule)):
            tag = "cylinder" if isinstance(shape, Cylinder) else "capsule"
            ET.SubElement(geometry, tag, radius=num_text(shape.radius), length=num_text(shape.length))
        else:
            if shape.path is None:
                raise ValueError(f"link '{link.get('name')}' {kind} {k + 1}: a mesh given as arrays has no file to name in a URDF")
            attrs = {"filename": mesh_filename(shape.path, directory)}
            if not np.array_equal(shape.scale, np.ones(3)):
                attrs["scale"] = num_text(shape.scale)
            ET.SubElement(geometry, "mesh", attrs)
        if kind == "visual" and shape.color is not None:
            material = ET.SubElement(element, "material", name=f"{link.get('name')}_{k + 1}")
            ET.SubElement(material, "color", rgba=num_text(np.array(shape.color)))

