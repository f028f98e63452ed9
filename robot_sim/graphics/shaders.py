"""GLSL programs of the render path and their compilation (GLSL 3.30 in a compatibility
context: Mesa's llvmpipe, through GLX or OSMesa, gives OpenGL 4.5 compatibility).

Vertex attribute locations are fixed for every program (``POSITION`` .. ``MODEL``), so
one buffer layout serves all of them.  An attribute whose array is disabled takes the
constant set with glVertexAttrib4f: a mesh drawn once passes its colour and model matrix
that way, instanced parts pass them per instance.

World frame, z up, metres.  Lighting is Blinn-Phong with a hemisphere ambient term, a
key light that casts shadows (a depth map seen from the light, sampled with
percentage-closer filtering) and an unshadowed fill light.
"""
from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from robot_sim.graphics.gl import GL

POSITION, NORMAL, COLOR, MODEL = 0, 1, 2, 3  # MODEL takes locations 3..6 (a mat4)

_LIT_VERTEX = """
#version 330
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec4 a_color;
layout(location = 3) in mat4 a_model;
uniform mat4 u_view_proj;
uniform mat4 u_light_matrix;
out vec3 v_world;
out vec3 v_normal;
out vec4 v_color;
out vec4 v_light;
void main() {
    vec4 world = a_model * vec4(a_position, 1.0);
    v_world = world.xyz;
    // placements are rotation x scale (orthogonal columns): the inverse transpose of
    // mat3(a_model) is mat3(a_model) with each column divided by its squared length
    mat3 m = mat3(a_model);
    vec3 s2 = vec3(dot(m[0], m[0]), dot(m[1], m[1]), dot(m[2], m[2]));
    v_normal = m * (a_normal / s2);
    v_color = a_color;
    v_light = u_light_matrix * world;
    gl_Position = u_view_proj * world;
}
"""

# Shadow lookup shared by the lit and the floor fragment shaders: four taps of a
# linearly filtered comparison sampler (2x2 PCF each), so the edge is soft.
_SHADOW_GLSL = """
uniform sampler2DShadow u_shadow_map;
uniform int u_shadows;
uniform float u_shadow_texel;
uniform float u_shadow_bias;
float lit_fraction(vec4 light_clip) {
    if (u_shadows == 0) return 1.0;
    vec3 p = light_clip.xyz / light_clip.w * 0.5 + 0.5;
    if (p.x < 0.0 || p.x > 1.0 || p.y < 0.0 || p.y > 1.0 || p.z > 1.0) return 1.0;
    float z = p.z - u_shadow_bias;
    float d = 0.75 * u_shadow_texel;
    float s = texture(u_shadow_map, vec3(p.xy + vec2(-d, -d), z))
            + texture(u_shadow_map, vec3(p.xy + vec2( d, -d), z))
            + texture(u_shadow_map, vec3(p.xy + vec2(-d,  d), z))
            + texture(u_shadow_map, vec3(p.xy + vec2( d,  d), z));
    return 0.25 * s;
}
"""

# Shared by the lit and the marker fragment shaders: the normal turned to the viewer
# (two-sided: inner faces of open meshes), and the tint of what lies under the floor.
_SURFACE_GLSL = """
uniform vec3 u_eye;
uniform vec4 u_below_floor;
vec3 facing(vec3 n, vec3 v) { return dot(n, v) < 0.0 ? -n : n; }
vec3 under_floor(vec3 color, vec3 world) {
    return world.z < 0.0 ? mix(color, u_below_floor.rgb, u_below_floor.a) : color;
}
"""

_LIGHT_GLSL = """
uniform vec3 u_key_dir;
uniform vec3 u_key_color;
uniform vec3 u_fill_dir;
uniform vec3 u_fill_color;
uniform vec3 u_sky_color;
uniform vec3 u_ground_color;
uniform float u_specular;
uniform float u_shininess;
vec3 shade(vec3 base, vec3 n, vec3 world, float lit) {
    vec3 v = normalize(u_eye - world);
    n = facing(n, v);
    vec3 ambient = mix(u_ground_color, u_sky_color, 0.5 + 0.5 * n.z);
    float key = max(dot(n, u_key_dir), 0.0) * lit;
    float fill = max(dot(n, u_fill_dir), 0.0);
    vec3 h = normalize(u_key_dir + v);
    float spec = key > 0.0 ? u_specular * pow(max(dot(n, h), 0.0), u_shininess) * lit : 0.0;
    return base * (ambient + key * u_key_color + fill * u_fill_color) + spec * u_key_color;
}
"""

_LIT_FRAGMENT = """
#version 330
in vec3 v_world;
in vec3 v_normal;
in vec4 v_color;
in vec4 v_light;
uniform float u_alpha;
out vec4 frag;
""" + _SHADOW_GLSL + _SURFACE_GLSL + _LIGHT_GLSL + """
void main() {
    vec3 color = shade(v_color.rgb, normalize(v_normal), v_world, lit_fraction(v_light));
    frag = vec4(under_floor(color, v_world), v_color.a * u_alpha);
}
"""

# Markers (the overlay's axes, target and arrows): lit from the eye, no shadow, no
# specular, so that they read in their colours from every side.  A program of their own:
# llvmpipe runs both sides of a branch, so a switch in the lit shader would still pay
# for its shadow taps and specular term on every marker fragment.
_MARKER_FRAGMENT = """
#version 330
in vec3 v_world;
in vec3 v_normal;
in vec4 v_color;
uniform float u_alpha;
out vec4 frag;
""" + _SURFACE_GLSL + """
void main() {
    vec3 v = normalize(u_eye - v_world);
    vec3 n = facing(normalize(v_normal), v);
    frag = vec4(under_floor(v_color.rgb * (0.45 + 0.55 * dot(n, v)), v_world), v_color.a * u_alpha);
}
"""

_DEPTH_VERTEX = """
#version 330
layout(location = 0) in vec3 a_position;
layout(location = 3) in mat4 a_model;
uniform mat4 u_view_proj;
void main() { gl_Position = u_view_proj * (a_model * vec4(a_position, 1.0)); }
"""

_DEPTH_FRAGMENT = """
#version 330
void main() {}
"""

_UNLIT_VERTEX = """
#version 330
layout(location = 0) in vec3 a_position;
layout(location = 2) in vec4 a_color;
uniform mat4 u_view_proj;
out vec4 v_color;
void main() { v_color = a_color; gl_Position = u_view_proj * vec4(a_position, 1.0); }
"""

_UNLIT_FRAGMENT = """
#version 330
in vec4 v_color;
out vec4 frag;
void main() { frag = v_color; }
"""

# The shadows on the floor z = 0: a patch over where shadows can fall, black with the
# alpha of how much of the key light is blocked (the floor and its grid are plain
# coloured triangles and lines under it: every fragment of the picture costs, four times
# over with multisampling on llvmpipe, so the floor's own fragments do no lookups).
_SHADOW_PATCH_VERTEX = """
#version 330
layout(location = 0) in vec3 a_position;
uniform mat4 u_view_proj;
uniform mat4 u_light_matrix;
out vec4 v_light;
void main() {
    v_light = u_light_matrix * vec4(a_position, 1.0);
    gl_Position = u_view_proj * vec4(a_position, 1.0);
}
"""

_SHADOW_PATCH_FRAGMENT = """
#version 330
in vec4 v_light;
uniform float u_shadow_strength;
out vec4 frag;
""" + _SHADOW_GLSL + """
void main() {
    float dark = u_shadow_strength * (1.0 - lit_fraction(v_light));
    if (dark < 0.004) discard;
    frag = vec4(0.0, 0.0, 0.0, dark);
}
"""

# Text: quads in pixels (origin top left) textured from the glyph atlas, whose red
# channel holds the glyphs' coverage and green the coverage grown by the halo.
_TEXT_VERTEX = """
#version 330
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec4 a_color;
uniform vec2 u_viewport;
out vec2 v_uv;
out vec4 v_color;
void main() {
    v_uv = a_normal.xy;
    v_color = a_color;
    gl_Position = vec4(2.0 * a_position.x / u_viewport.x - 1.0, 1.0 - 2.0 * a_position.y / u_viewport.y, 0.0, 1.0);
}
"""

_TEXT_FRAGMENT = """
#version 330
in vec2 v_uv;
in vec4 v_color;
uniform sampler2D u_atlas;
uniform vec4 u_halo_color;
out vec4 frag;
void main() {
    vec2 ink = texture(u_atlas, v_uv).rg;
    float alpha = max(ink.r, ink.g * u_halo_color.a);
    vec3 color = mix(u_halo_color.rgb, v_color.rgb, ink.r / max(alpha, 1e-6));
    frag = vec4(color, alpha * v_color.a);
}
"""

SOURCES: dict[str, tuple[str, str]] = {
    "lit": (_LIT_VERTEX, _LIT_FRAGMENT),
    "marker": (_LIT_VERTEX, _MARKER_FRAGMENT),
    "depth": (_DEPTH_VERTEX, _DEPTH_FRAGMENT),
    "unlit": (_UNLIT_VERTEX, _UNLIT_FRAGMENT),
    "shadow_patch": (_SHADOW_PATCH_VERTEX, _SHADOW_PATCH_FRAGMENT),
    "text": (_TEXT_VERTEX, _TEXT_FRAGMENT),
}


class ShaderError(RuntimeError):
    """A program failed to compile or link; the message holds the driver's log."""


def _compile(kind: int, source: str, name: str) -> int:
    shader = int(GL.glCreateShader(kind))
    GL.glShaderSource(shader, source)
    GL.glCompileShader(shader)
    if not GL.glGetShaderiv(shader, GL.GL_COMPILE_STATUS):
        log = GL.glGetShaderInfoLog(shader)
        GL.glDeleteShader(shader)
        stage = "vertex" if kind == GL.GL_VERTEX_SHADER else "fragment"
        raise ShaderError(f"shader program '{name}': {stage} shader does not compile: {_text(log)}")
    return shader


def _text(log: Any) -> str:
    return (log.decode(errors="replace") if isinstance(log, bytes) else str(log)).strip()


class Program:
    """A linked GLSL program of :data:`SOURCES` with its uniform locations cached.

    Built in the current context; ``set(name, value)`` sets a uniform of the program in
    use (floats, ints, vectors of 2..4 floats, (4, 4) matrices given row-major)."""

    def __init__(self, name: str) -> None:
        vertex, fragment = SOURCES[name]
        self.name = name
        shaders = [_compile(GL.GL_VERTEX_SHADER, vertex, name), _compile(GL.GL_FRAGMENT_SHADER, fragment, name)]
        self.handle = int(GL.glCreateProgram())
        for shader in shaders:
            GL.glAttachShader(self.handle, shader)
        GL.glLinkProgram(self.handle)
        for shader in shaders:
            GL.glDetachShader(self.handle, shader)
            GL.glDeleteShader(shader)
        if not GL.glGetProgramiv(self.handle, GL.GL_LINK_STATUS):
            log = GL.glGetProgramInfoLog(self.handle)
            GL.glDeleteProgram(self.handle)
            raise ShaderError(f"shader program '{name}' does not link: {_text(log)}")
        # every active uniform's location, read once now that the program is linked
        # (a uniform the compiler removed as unused is absent: setting it is a no-op)
        self._locations: dict[str, int] = {}
        for index in range(int(GL.glGetProgramiv(self.handle, GL.GL_ACTIVE_UNIFORMS))):
            uniform = _text(GL.glGetActiveUniform(self.handle, index)[0]).split("[")[0]
            self._locations[uniform] = int(GL.glGetUniformLocation(self.handle, uniform.encode("ascii")))
        if len(set(self._locations.values())) != len(self._locations):
            raise ShaderError(f"shader program '{name}': uniform locations are not distinct: {self._locations}")

    def use(self) -> Program:
        """Make this the program in use; returns it for chaining ``set`` calls."""
        GL.glUseProgram(self.handle)
        return self

    def location(self, uniform: str) -> int:
        """Location of ``uniform`` (-1 when the compiler removed it as unused)."""
        return self._locations.get(uniform, -1)

    def set(self, uniform: str, value: ArrayLike) -> Program:
        """Set ``uniform`` of this program (which must be in use) to ``value``."""
        loc = self.location(uniform)
        if loc < 0:
            return self
        if isinstance(value, (bool, int, np.integer)):
            GL.glUniform1i(loc, int(value))
            return self
        arr = np.asarray(value, dtype=np.float32)
        if arr.shape == (4, 4):
            GL.glUniformMatrix4fv(loc, 1, GL.GL_TRUE, np.ascontiguousarray(arr))
        elif arr.ndim == 0:
            GL.glUniform1f(loc, float(arr))
        else:
            (GL.glUniform2f, GL.glUniform3f, GL.glUniform4f)[len(arr) - 2](loc, *map(float, arr))
        return self

    def delete(self) -> None:
        """Delete the program (its context must be current)."""
        GL.glDeleteProgram(self.handle)
