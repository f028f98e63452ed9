"""The floor z = 0: a square around the robot's base with a grid, fading out towards its
edge, and the shadows of the robot and the task on it; translucent, so parts below the
floor still show through it.

The square and the grid are plain coloured triangles and lines (the fade is in their
vertex colours); only a patch over where shadows can fall (the light's footprint of the
casters) looks up the shadow map.
"""
from __future__ import annotations

from robot_sim.graphics.frame import Frame
from robot_sim.graphics.floor_grid import FloorGrid, floor_square
from robot_sim.graphics.gl import GL
from robot_sim.graphics.item import Item
from robot_sim.graphics.robot_parts import robot_reach
from robot_sim.graphics.scene import GraphicsOptions, Scene

RGBA = tuple[float, float, float, float]
#: Pixels added on every side of the shadow patch's scissor box (multisample positions).
SHADOW_PATCH_MARGIN_PX = 2


class FloorItem(Item):
    """The floor under ``scene.kinematics``' base, in the theme's colours."""

    layer = "translucent"
    order = 0.0

    def __init__(self) -> None:
        super().__init__()
        self.grid = FloorGrid.for_reach(1.0)

    def update(self, scene: Scene, options: GraphicsOptions) -> None:
        kin = scene.kinematics
        self.grid = FloorGrid.for_reach(robot_reach(kin.robot), kin.frames[0, :2, 3])

    def paint(self, frame: Frame) -> None:
        grid, theme, light = self.grid, frame.theme, frame.light
        points, colors = grid.triangles(theme.floor)
        frame.lines(points, theme.floor, GL.GL_TRIANGLES, colors=colors)
        points, colors = grid.lines(theme.grid)
        frame.lines(points, theme.grid, GL.GL_LINES, colors=colors)
        if not light.shadows:
            return
        program = frame.resources.programs["shadow_patch"].use()
        program.set("u_view_proj", frame.view_proj).set("u_light_matrix", light.matrix)
        program.set("u_shadow_strength", theme.shadow_strength)
        frame.bind_shadow(program)
        # the patch over all the shadow map sees, its fragments computed only over the
        # casters' footprint: elsewhere every one would find the map clear and be discarded
        box = frame.scissor_box(light.footprint, SHADOW_PATCH_MARGIN_PX)
        if box is None:
            return
        GL.glEnable(GL.GL_SCISSOR_TEST)
        GL.glScissor(*box)
        patch = floor_square(float(light.centre[0]), float(light.centre[1]), light.radius)
        n = frame.resources.stream.vertices(patch)
        GL.glDrawArrays(GL.GL_TRIANGLE_FAN, 0, n)
        GL.glDisable(GL.GL_SCISSOR_TEST)


ITEM = FloorItem
