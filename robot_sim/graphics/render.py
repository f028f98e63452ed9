"""The one render path of every host: a :class:`View` holds the scene's persistent items
(``view.items``, in the manner of pyqtgraph's ``GLViewWidget.items``) and draws them
seen by a camera into the current GL context, whether the Qt widget's or OSMesa's.

A frame: every item reads the Scene and options (:meth:`Item.update`); the shadow
casters are drawn into the shadow map when their shadow changed; then, into a
multisampled target cleared to the theme's background, the opaque layer, the
translucent layer, the overlay layer over a depth buffer cleared where it draws, and the
text layer;
last the samples are resolved into the host's framebuffer.

Cached items (``Item.cached``: the workspace cloud) are drawn over the cleared
background into a second multisampled target, the background picture, only when it
changes (the view, the size, the theme or an item's ``cache_key``); a frame then starts
from a copy of its colour and depth samples instead of a clear, and draws the rest.

The default items are every ``ITEM`` declared by a module of
:mod:`robot_sim.graphics.items`: adding a drawable is adding a file there.  A host may
also append its own items to ``view.items``.
"""
from __future__ import annotations

import importlib
import pkgutil
from typing import Iterable

import numpy as np

from robot_sim.graphics import defs as gd
from robot_sim.graphics import items as items_package
from robot_sim.graphics.camera import Camera
from robot_sim.graphics.frame import SHADOW_UNIT, Drawing, Frame, Light, Resources
from robot_sim.graphics.gl import GL, context_key
from robot_sim.graphics.item import LAYERS, Item
from robot_sim.graphics.lighting import fill_light, key_light, light_matrix, shadow_footprint, shadow_sphere
from robot_sim.graphics.scene import GraphicsOptions, Scene
from robot_sim.graphics.targets import MultisampleTarget, ShadowTarget, max_samples
from robot_sim.graphics.themes import Theme, theme


def item_classes() -> list[type[Item]]:
    """The ``ITEM`` of every module in :mod:`robot_sim.graphics.items`, by module name."""
    found = []
    for info in sorted(pkgutil.iter_modules(items_package.__path__), key=lambda m: m.name):
        module = importlib.import_module(f"{items_package.__name__}.{info.name}")
        item = getattr(module, "ITEM", None)
        if item is not None:
            found.append(item)
    return found


def _clear(palette: Theme) -> None:
    """Clear the bound framebuffer's colour to the theme's background and its depth."""
    GL.glClearColor(*palette.background)
    GL.glDepthMask(GL.GL_TRUE)
    GL.glColorMask(GL.GL_TRUE, GL.GL_TRUE, GL.GL_TRUE, GL.GL_TRUE)
    GL.glClear(GL.GL_COLOR_BUFFER_BIT | GL.GL_DEPTH_BUFFER_BIT)


#: Pixels added on every side of the overlay's depth clear (multisample positions, lines).
OVERLAY_CLEAR_MARGIN_PX = 2


def _clear_overlay_depth(frame: Frame, overlay: list[Item]) -> None:
    """Clear the depth buffer where the ``overlay`` items draw: over the pixel box of their
    bounds grown by ``OVERLAY_CLEAR_MARGIN_PX`` (:meth:`Frame.scissor_box`).  The overlay then
    sees only its own depth, as after a full clear, while llvmpipe clears a small box
    instead of every sample of the picture."""
    bounds = [item.bounds() for item in overlay]
    box = frame.scissor_box(np.concatenate(bounds) if bounds else np.zeros((0, 3)), OVERLAY_CLEAR_MARGIN_PX)
    if box is None:
        return
    GL.glEnable(GL.GL_SCISSOR_TEST)
    GL.glScissor(*box)
    GL.glClear(GL.GL_DEPTH_BUFFER_BIT)
    GL.glDisable(GL.GL_SCISSOR_TEST)


def _layer_state(layer: str) -> None:
    """GL state of a layer (set at its start)."""
    GL.glEnable(GL.GL_DEPTH_TEST)
    GL.glDepthFunc(GL.GL_LEQUAL)
    GL.glDisable(GL.GL_CULL_FACE)
    # the picture's alpha stays the clear's 1 (opaque pictures): no layer writes it, so a
    # colour's alpha (a URDF material's 0.8) never reaches it (and llvmpipe blends a
    # little faster than with an alpha blended to itself)
    GL.glColorMask(GL.GL_TRUE, GL.GL_TRUE, GL.GL_TRUE, GL.GL_FALSE)
    if layer == "opaque":
        GL.glDisable(GL.GL_BLEND)
        GL.glDepthMask(GL.GL_TRUE)
        return
    GL.glEnable(GL.GL_BLEND)  # colours blend
    GL.glBlendFunc(GL.GL_SRC_ALPHA, GL.GL_ONE_MINUS_SRC_ALPHA)
    GL.glDepthMask(GL.GL_TRUE if layer == "overlay" else GL.GL_FALSE)
    if layer == "text":
        GL.glDisable(GL.GL_DEPTH_TEST)


class View:
    """The scene's items and the GL objects of the context they are drawn in.

    ``items`` is the persistent, ordered list of drawables (default: :func:`item_classes`,
    one instance each).  The view's GL objects live in one context at a time: when
    :meth:`render` finds another context current (the Qt widget was re-created, a new
    offscreen context), everything is rebuilt there.  Call :meth:`release` while the
    context is current before destroying it.
    """

    def __init__(self, items: Iterable[Item] | None = None) -> None:
        self.items: list[Item] = list(items) if items is not None else [cls() for cls in item_classes()]
        self._context = 0
        self._resources: Resources | None = None
        self._msaa: MultisampleTarget | None = None
        self._shadow = ShadowTarget(gd.SHADOW_MAP_SIZE)
        self._shadow_state: object = None
        self._background: MultisampleTarget | None = None
        self._background_key: object = None

    def item(self, cls: type[Item]) -> Item:
        """The first item of type ``cls`` (KeyError when there is none)."""
        for item in self.items:
            if isinstance(item, cls):
                return item
        raise KeyError(f"View: no item of type {cls.__name__}")

    def _bind_context(self) -> Resources:
        key = context_key()
        if key == 0:
            raise RuntimeError("View.render: no current OpenGL context (the host failed to create or bind one)")
        # a context created at the address of a destroyed one holds none of our objects
        if key != self._context or self._resources is None or not self._resources.valid():
            self._forget()
            self._context, self._resources = key, Resources()
        return self._resources

    def forget(self) -> None:
        """Drop every GL handle without deleting it: the context they lived in is gone
        (a host calls this when it is given a new context)."""
        self._forget()
        self._context = 0

    def _forget(self) -> None:
        """Drop every GL handle without deleting (the context they lived in is gone)."""
        for item in self.items:
            item.release(current=False)
        if self._resources is not None:
            self._resources.release(current=False)
        self._resources, self._msaa, self._shadow_state = None, None, None
        self._background, self._background_key = None, None
        self._shadow = ShadowTarget(gd.SHADOW_MAP_SIZE)

    def release(self) -> None:
        """Delete every GL object of this view (its context must be current)."""
        for item in self.items:
            item.release(current=True)
        if self._resources is not None:
            self._resources.release(current=True)
        for target in (self._msaa, self._background):
            if target is not None:
                target.delete()
        self._shadow.delete()
        self._resources, self._msaa, self._shadow_state, self._context = None, None, None, 0
        self._background, self._background_key = None, None

    def _light(self, camera: Camera, options: GraphicsOptions, frame_items: list[Item]) -> Light:
        key = key_light()
        casters = [item for item in frame_items if item.casts_shadow]
        bounds = [item.bounds() for item in casters]
        points = np.vstack(bounds) if bounds else np.zeros((0, 3))
        if not options.shadows or len(points) == 0:
            return Light(key, fill_light(camera.azimuth_deg), np.eye(4), 1.0, False)
        centre, radius = shadow_sphere(points, key)
        matrix = light_matrix(key, centre, radius)
        margin = gd.SHADOW_FOOTPRINT_MARGIN_TEXELS * 2.0 / self._shadow.size  # light clip spans 2 a side
        light = Light(key, fill_light(camera.azimuth_deg), matrix, 1.0 / self._shadow.size, True, centre, radius,
                      shadow_footprint(matrix, key, points, margin))
        state = (light.matrix.tobytes(), tuple(item.shadow_key() for item in casters))
        if state != self._shadow_state:
            self._draw_shadow(light, casters)
            self._shadow_state = state
        return light

    def _draw_shadow(self, light: Light, casters: list[Item]) -> None:
        assert self._resources is not None
        previous = self._shadow.begin()
        GL.glEnable(GL.GL_DEPTH_TEST)
        GL.glDepthFunc(GL.GL_LESS)
        GL.glDisable(GL.GL_BLEND)
        GL.glEnable(GL.GL_POLYGON_OFFSET_FILL)
        GL.glPolygonOffset(*gd.SHADOW_POLYGON_OFFSET)
        self._resources.programs["depth"].use().set("u_view_proj", light.matrix)
        texel = 2.0 * light.radius / self._shadow.size  # metres a shadow texel covers
        drawing = Drawing(self._resources, culling=True, cell=gd.SHADOW_CASTER_CELL_TEXELS * texel)
        for item in casters:
            item.paint_depth(drawing)
        GL.glDisable(GL.GL_POLYGON_OFFSET_FILL)
        self._shadow.end(previous)

    def _start_from_background(self, frame: Frame, msaa: MultisampleTarget, cached: list[Item]) -> None:
        """Fill ``msaa`` (bound) with the background picture: the cleared background and
        the ``cached`` items, redrawn first when any of what it shows changed."""
        key = (frame.view_proj.tobytes(), frame.width, frame.height, msaa.samples, frame.theme.background,
               tuple((id(item), item.cache_key()) for item in cached))
        if self._background is None or self._background.samples != msaa.samples:
            if self._background is not None:
                self._background.delete()
            self._background, self._background_key = MultisampleTarget(msaa.samples), None
        if key != self._background_key:
            self._background.bind(frame.width, frame.height)
            _clear(frame.theme)
            _layer_state("opaque")
            for item in sorted(cached, key=lambda i: i.order):
                item.paint(frame)
            self._background_key = key
        msaa.copy_from(self._background)

    def render(self, camera: Camera, scene: Scene, options: GraphicsOptions, width: int, height: int) -> None:
        """Draw ``scene`` seen by ``camera`` with ``options`` into the current context's
        framebuffer (the one bound now), ``width`` x ``height`` pixels.  Raises
        RuntimeError when no GL context is current, ValueError for an unknown theme
        (before anything is drawn).  The host's framebuffer and vertex array stay bound
        afterwards, whatever happens."""
        width, height = max(int(width), 1), max(int(height), 1)
        palette = theme(options.theme)
        resources = self._bind_context()
        host_vao = int(GL.glGetIntegerv(GL.GL_VERTEX_ARRAY_BINDING))
        host_fbo = int(GL.glGetIntegerv(GL.GL_DRAW_FRAMEBUFFER_BINDING))
        GL.glBindVertexArray(resources.vao)  # our attribute state, apart from the host's
        try:
            self._draw(camera, scene, options, width, height, palette, resources)
        finally:
            GL.glUseProgram(0)
            GL.glBindBuffer(GL.GL_ARRAY_BUFFER, 0)
            GL.glDepthMask(GL.GL_TRUE)
            GL.glColorMask(GL.GL_TRUE, GL.GL_TRUE, GL.GL_TRUE, GL.GL_TRUE)
            GL.glDisable(GL.GL_BLEND)
            GL.glBindVertexArray(host_vao)
            GL.glBindFramebuffer(GL.GL_FRAMEBUFFER, host_fbo)

    def _draw(self, camera: Camera, scene: Scene, options: GraphicsOptions, width: int, height: int,
              palette: Theme, resources: Resources) -> None:
        for item in self.items:
            item.visible = True
            item.update(scene, options)
        shown = [item for item in self.items if item.visible]
        light = self._light(camera, options, shown)
        samples = min(int(options.samples), max_samples())
        msaa = None
        if samples > 1:
            if self._msaa is None or self._msaa.samples != samples:
                if self._msaa is not None:
                    self._msaa.delete()
                self._msaa = MultisampleTarget(samples)
            msaa = self._msaa
            msaa.begin(width, height)
        GL.glViewport(0, 0, width, height)
        GL.glActiveTexture(GL.GL_TEXTURE0 + SHADOW_UNIT)
        GL.glBindTexture(GL.GL_TEXTURE_2D, self._shadow.texture if light.shadows else 0)
        GL.glActiveTexture(GL.GL_TEXTURE0)
        frame = Frame(camera, options, width, height, palette, light, resources)
        cached = [item for item in shown if item.cached and item.layer == "opaque"] if msaa is not None else []
        if cached:
            assert msaa is not None
            self._start_from_background(frame, msaa, cached)
        else:
            _clear(palette)
        for layer in LAYERS:
            _layer_state(layer)
            drawn = sorted((i for i in shown if i.layer == layer and i not in cached), key=lambda i: i.order)
            if layer == "overlay":
                _clear_overlay_depth(frame, drawn)
            for item in drawn:
                frame.culling = layer == "opaque"  # translucent pictures show back faces
                item.paint(frame)
        if msaa is not None:
            msaa.end()
