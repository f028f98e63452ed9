"""What an item needs to paint one frame: the camera's matrices, the lights and the
shadow map, the theme, the shared GL resources of the context (programs, unit meshes, a
stream buffer), and helpers that draw instanced meshes, meshes, lines and points with
the right program.  World frame, z up, metres; pixels x right, y down.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robot_sim.graphics import defs as gd
from robot_sim.graphics.buffers import StaticMesh, StreamBuffer, set_constant_color, set_constant_model
from robot_sim.graphics.gl import GL
from robot_sim.graphics.meshes import unit_meshes
from robot_sim.graphics.shaders import COLOR, SOURCES, Program
from robot_sim.graphics.themes import Theme

if TYPE_CHECKING:
    from robot_sim.graphics.camera import Camera
    from robot_sim.graphics.scene import GraphicsOptions

SHADOW_UNIT = 1   # texture unit of the shadow map (unit 0 is the glyph atlas)
RGBA = tuple[float, float, float, float]


class Resources:
    """GL objects of one context shared by all items: the programs of
    :data:`~robot_sim.graphics.shaders.SOURCES`, the unit meshes, a stream buffer and
    the vertex array object that holds the attribute state while the view draws."""

    def __init__(self) -> None:
        self.vao = int(GL.glGenVertexArrays(1))
        self.programs = {name: Program(name) for name in SOURCES}
        self.meshes = {name: StaticMesh.from_triangles(v, n) for name, (v, n) in unit_meshes().items()}
        self.stream = StreamBuffer()

    def valid(self) -> bool:
        """True while the current context holds these objects."""
        return bool(GL.glIsProgram(self.programs["lit"].handle))

    def release(self, current: bool) -> None:
        """Delete (``current``) or forget every object."""
        for mesh in self.meshes.values():
            (mesh.delete if current else mesh.forget)()
        (self.stream.delete if current else self.stream.forget)()
        if current:
            for program in self.programs.values():
                program.delete()
            GL.glDeleteVertexArrays(1, [self.vao])


@dataclass
class Light:
    """The key light (unit vector towards it, shadowed), the fill light, and the shadow
    map's world -> light clip ``matrix`` and texel size (``shadows`` False: none); the
    shadow map sees the sphere of ``radius`` metres about world ``centre`` (3,), which
    holds every caster and its shadow on the floor; ``footprint`` (4, 3): the floor's
    corners of the only region the casters can shade
    (:func:`~robot_sim.graphics.lighting.shadow_footprint`)."""

    key: NDArray[np.float64]
    fill: NDArray[np.float64]
    matrix: NDArray[np.float64]
    texel: float
    shadows: bool
    centre: NDArray[np.float64] = field(default_factory=lambda: np.zeros(3))
    radius: float = 0.0
    footprint: NDArray[np.float64] = field(default_factory=lambda: np.zeros((0, 3)))


def _keep_winding(placements: NDArray[np.float64]) -> bool:
    """True when every placement (N, 4, 4) keeps a mesh's winding (positive determinant):
    back faces may then be culled (a mirroring placement would turn them to the front)."""
    return bool(np.all(np.linalg.det(placements[:, :3, :3]) > 0.0))


class Drawing:
    """Draws meshes with the program in use: the base of :class:`Frame`, and what the
    shadow pass gives :meth:`Item.paint_depth` (only positions and placements count).

    ``culling``: closed meshes are drawn without their back faces (the shadow pass, and
    the opaque layer unless an item draws a wireframe; see :class:`StaticMesh`).
    ``cell``: the size (metres) below which detail does not show; meshes are drawn as
    their :meth:`StaticMesh.coarse` stand-ins for it (the shadow pass: a few texels; a
    :class:`Frame` sizes it per mesh, see :meth:`Frame.detail`).
    """

    resources: Resources
    culling: bool = False
    cell: float = 0.0

    def __init__(self, resources: Resources, culling: bool = False, cell: float = 0.0) -> None:
        self.resources = resources
        self.culling, self.cell = culling, cell

    def instances(self, mesh: str, placements: ArrayLike, colors: ArrayLike) -> None:
        """Draw unit mesh ``mesh`` (``meshes.unit_meshes``) once per world placement
        (N, 4, 4) (rotation x scale) in ``colors`` ((N, 4) or one RGBA)."""
        mats = np.asarray(placements, dtype=float).reshape(-1, 4, 4)
        if len(mats) == 0:
            return
        stream = self.resources.stream
        n = stream.instances(mats, colors)
        self.resources.meshes[mesh].draw(n, cull=self.culling and _keep_winding(mats))
        stream.end_instances()

    def mesh(self, mesh: StaticMesh, placement: ArrayLike, color: ArrayLike) -> None:
        """Draw ``mesh`` (or its coarse stand-in for ``cell``) once at world ``placement``
        (4, 4, rigid) in ``color``."""
        mat = np.asarray(placement, dtype=float).reshape(4, 4)
        set_constant_model(mat)
        set_constant_color(color)
        mesh.coarse(self.detail(mesh, mat)).draw(cull=self.culling and _keep_winding(mat[None]))

    def detail(self, mesh: StaticMesh, placement: NDArray[np.float64]) -> float:
        """The size (metres) below which ``mesh`` at world ``placement`` (4, 4) shows no
        detail: ``cell``."""
        return self.cell


@dataclass
class Frame(Drawing):
    """One frame being drawn; items read it and draw through its helpers."""

    camera: Camera
    options: GraphicsOptions
    width: int
    height: int
    theme: Theme
    light: Light
    resources: Resources
    view_proj: NDArray[np.float64] = field(init=False)
    labels: list[tuple[NDArray[np.float64], str, RGBA]] = field(default_factory=list)
    #: World polylines ((k, 3) each) the labels keep clear of: axes, arrows, dimensions.
    obstacles: list[NDArray[np.float64]] = field(default_factory=list)
    #: Texts written at fixed pixel boxes (box (left, top, right, bottom), text, rgba):
    #: drawn as they are, and kept clear of by the labels.
    texts: list[tuple[NDArray[np.float64], str, RGBA]] = field(default_factory=list)

    def __post_init__(self) -> None:
        view = self.camera.view_matrix()
        self.view_proj = self.camera.projection_matrix(self.width / self.height) @ view
        self._depth_row = -view[2]  # world point (homogeneous) -> depth in front of the eye

    def detail(self, mesh: StaticMesh, placement: NDArray[np.float64]) -> float:
        """``MESH_DETAIL_PX`` pixels at the depth of the nearest point of ``mesh``'s
        bounding sphere at world ``placement`` (4, 4, rigid), in metres: meshes finer
        than a pixel are drawn through a coarse stand-in (llvmpipe pays for every
        triangle at every multisample, however small)."""
        depth = float(self._depth_row @ placement[:, 3]) - mesh.radius
        return gd.MESH_DETAIL_PX * self.camera.pixel_size(depth, self.height)

    def add_label(self, point: ArrayLike, text: str, rgba: RGBA | None = None) -> None:
        """Write ``text`` next to world ``point`` in the text layer (theme colour by default)."""
        self.labels.append((np.asarray(point, dtype=float).reshape(3), text, rgba or self.theme.label))

    def add_obstacle(self, points: ArrayLike) -> None:
        """Keep labels clear of the world polyline through ``points`` (k, 3)."""
        self.obstacles.append(np.asarray(points, dtype=float).reshape(-1, 3))

    def add_text(self, box: ArrayLike, text: str, rgba: RGBA | None = None) -> None:
        """Write ``text`` in the pixel ``box`` (left, top, right, bottom) in the text layer."""
        self.texts.append((np.asarray(box, dtype=float).reshape(4), text, rgba or self.theme.label))

    def scissor_box(self, points: NDArray[np.float64], margin: int) -> tuple[int, int, int, int] | None:
        """The GL scissor box (x, y from the bottom left, width, height) of the pixels the
        hull of world ``points`` (N, 3) covers, grown by ``margin`` pixels; the whole
        picture when a point lies behind the eye; None when nothing is covered."""
        if len(points) == 0:
            return None
        pixels = self.camera.project(points, self.width, self.height)
        if np.isnan(pixels).any():
            return 0, 0, self.width, self.height
        x0, top = np.floor(pixels.min(axis=0) - margin).astype(int)
        x1, bottom = np.ceil(pixels.max(axis=0) + margin).astype(int)
        x0, x1 = max(x0, 0), min(x1, self.width - 1)
        y0, y1 = max(self.height - 1 - bottom, 0), min(self.height - 1 - top, self.height - 1)  # GL rows, from the bottom
        if x1 < x0 or y1 < y0:
            return None
        return int(x0), int(y0), int(x1 - x0 + 1), int(y1 - y0 + 1)

    def pixel_matrix(self) -> NDArray[np.float64]:
        """Clip coordinates of pixels (x right, y down from the top row, z 0)."""
        m = np.eye(4)
        m[0, 0], m[0, 3] = 2.0 / self.width, -1.0
        m[1, 1], m[1, 3] = -2.0 / self.height, 1.0
        return m

    def pixel_shapes(self, points: ArrayLike, colors: ArrayLike, mode: int, width: float = 1.0) -> None:
        """Unlit ``mode`` primitives (GL_LINES, GL_TRIANGLES, ...) through pixel ``points``
        (N, 2) in per-vertex ``colors`` (N, 4), ``width`` pixels for lines."""
        pts = np.asarray(points, dtype=float).reshape(-1, 2)
        if len(pts) == 0:
            return
        self.resources.programs["unlit"].use().set("u_view_proj", self.pixel_matrix())
        set_constant_model(np.eye(4))
        GL.glLineWidth(float(width))
        n = self.resources.stream.vertices(np.c_[pts, np.zeros(len(pts))], colors)
        GL.glDrawArrays(mode, 0, n)
        GL.glDisableVertexAttribArray(COLOR)
        GL.glLineWidth(1.0)

    # ------------------------------------------------------------------ programs

    def lit(self, alpha: float = 1.0, markers: bool = False) -> Program:
        """The lit program in use with this frame's camera, lights and shadow map, every
        fragment's alpha multiplied by ``alpha``; ``markers`` (the overlay layer's axes,
        target and arrows): the marker program instead, lit from the eye with no shadow
        and no highlight, so that they read in their colours from every side."""
        light, theme = self.light, self.theme
        if markers:
            program = self.resources.programs["marker"].use()
            program.set("u_view_proj", self.view_proj).set("u_eye", self.camera.eye())
            return program.set("u_alpha", float(alpha)).set("u_below_floor", theme.below_floor)
        program = self.resources.programs["lit"].use()
        program.set("u_view_proj", self.view_proj).set("u_light_matrix", light.matrix)
        program.set("u_key_dir", light.key).set("u_key_color", gd.KEY_LIGHT_COLOR)
        program.set("u_fill_dir", light.fill).set("u_fill_color", gd.FILL_LIGHT_COLOR)
        program.set("u_sky_color", gd.SKY_AMBIENT).set("u_ground_color", gd.GROUND_AMBIENT)
        program.set("u_eye", self.camera.eye()).set("u_specular", gd.SPECULAR_STRENGTH)
        program.set("u_shininess", gd.SHININESS).set("u_alpha", float(alpha))
        program.set("u_below_floor", theme.below_floor)
        self.bind_shadow(program)
        return program

    def bind_shadow(self, program: Program) -> None:
        """Set ``program``'s shadow uniforms (the map is bound to ``SHADOW_UNIT``)."""
        light = self.light
        program.set("u_shadow_map", SHADOW_UNIT).set("u_shadows", int(light.shadows))
        program.set("u_shadow_texel", light.texel).set("u_shadow_bias", gd.SHADOW_BIAS)

    def unlit(self) -> Program:
        """The unlit program in use (positions in the world, per-vertex or constant colour)."""
        return self.resources.programs["unlit"].use().set("u_view_proj", self.view_proj)

    # ------------------------------------------------------------------ drawing

    def lines(self, points: ArrayLike, color: ArrayLike, mode: int | None = None, width: float = 1.0,
              colors: ArrayLike | None = None) -> None:
        """Unlit lines through world ``points`` (N, 3) (``mode``: GL_LINES by default,
        GL_LINE_STRIP, GL_POINTS), ``width`` pixels, in ``color`` or per-vertex ``colors``."""
        pts = np.asarray(points, dtype=float).reshape(-1, 3)
        if len(pts) == 0:
            return
        self.unlit()
        set_constant_model(np.eye(4))
        if colors is None:
            set_constant_color(color)
        GL.glLineWidth(float(width))
        n = self.resources.stream.vertices(pts, colors)
        GL.glDrawArrays(GL.GL_LINES if mode is None else mode, 0, n)
        GL.glDisableVertexAttribArray(COLOR)
        GL.glLineWidth(1.0)
