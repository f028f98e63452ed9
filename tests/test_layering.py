"""The package's layering (docs/layout.md): read every import statement under robot_sim/ and
check which layers each one reaches, and that no modules import each other in a cycle."""
from __future__ import annotations

import ast
from pathlib import Path

import pytest

from paths import PACKAGE


#: Layer -> the layers of ours it may import (besides itself).  Layers are the first
#: component under robot_sim (a subpackage, or a top-level module such as kinematics).
ALLOWED = {
    "transforms": set(),
    "model": {"transforms"},
    "io": {"model", "transforms"},
    "kernels": {"model", "transforms"},  # the compiled model and shared kernels, below kinematics
    "ik": {"model", "kernels", "transforms"},  # analytic IK: never kinematics (which calls it) or above
    "kinematics": {"model", "kernels", "ik", "transforms"},
    "dynamics": {"model", "kernels", "ik", "kinematics", "transforms"},
    "collision": {"model", "io", "kernels", "ik", "kinematics", "dynamics", "transforms"},
    "control": {"model", "io", "kernels", "ik", "kinematics", "dynamics", "collision", "planning",
                "transforms"},  # the laws: never sim
    "sim": {"model", "io", "kernels", "ik", "kinematics", "dynamics", "collision", "control",
            "planning", "transforms"},  # the physics loop
    "planning": {"model", "io", "kernels", "ik", "kinematics", "dynamics", "collision", "transforms"},
    "calibration": {"model", "io", "kernels", "ik", "kinematics", "collision", "transforms"},
    "graphics": {"model", "io", "kernels", "ik", "kinematics", "dynamics", "collision", "control", "sim", "planning",
                 "transforms"},
    "viewer": {"model", "io", "kernels", "ik", "kinematics", "dynamics", "collision", "control", "sim", "planning", "graphics",
               "transforms"},
    "qt": {"model", "io", "kernels", "ik", "kinematics", "dynamics", "collision", "control", "sim", "planning", "graphics",
           "viewer", "transforms"},
    # the browser view: graphics only through its GL-free geometry (GRAPHICS_GEOMETRY below)
    "web": {"model", "io", "kernels", "ik", "kinematics", "dynamics", "collision", "control", "sim", "planning", "graphics",
            "viewer", "transforms"},
    "app": {"model", "io", "kernels", "ik", "kinematics", "dynamics", "collision", "control", "sim", "planning",
            "calibration", "graphics", "viewer", "qt", "web", "transforms"},
}
#: Third-party GUI and GL libraries, and the layers that must never import them.
FORBIDDEN_EXTERNAL = {
    "PyQt5": {"transforms", "model", "io", "kernels", "ik", "kinematics", "dynamics", "collision", "control", "sim",
              "planning", "calibration", "graphics", "viewer", "web"},
    "OpenGL": {"transforms", "model", "io", "kernels", "ik", "kinematics", "dynamics", "collision", "control", "sim",
               "planning", "calibration", "web"},
}
#: The graphics modules the browser view may import: geometry in NumPy, no GL.  Each
#: reaches no GL module of graphics, directly or through another (checked below).
GRAPHICS_GEOMETRY = {
    "robot_sim.graphics.annotation_geometry", "robot_sim.graphics.collision_scene", "robot_sim.graphics.defs",
    "robot_sim.graphics.floor_grid", "robot_sim.graphics.frame_axes", "robot_sim.graphics.looks",
    "robot_sim.graphics.meshes", "robot_sim.graphics.placements", "robot_sim.graphics.robot_parts",
    "robot_sim.graphics.solid", "robot_sim.graphics.task_scene", "robot_sim.graphics.themes",
    "robot_sim.graphics.visuals", "robot_sim.graphics.scene", "robot_sim.graphics.camera",
}
#: Graphics modules that hold or load GL code.
GRAPHICS_GL = {"robot_sim.graphics.gl", "robot_sim.graphics.buffers", "robot_sim.graphics.frame",
               "robot_sim.graphics.shaders", "robot_sim.graphics.targets", "robot_sim.graphics.render",
               "robot_sim.graphics.offscreen", "robot_sim.graphics.item", "robot_sim.graphics.font"}


def module_name(path: Path) -> str:
    parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def layer(module: str) -> str | None:
    parts = module.split(".")
    return parts[1] if parts[0] == "robot_sim" and len(parts) > 1 else None


def imports(path: Path) -> list[tuple[int, str]]:
    """(line, imported module) of every import statement, those under ``if TYPE_CHECKING``
    included; ``from robot_sim.x import y`` names robot_sim.x.y when that is a module."""
    found = []
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            found += [(node.lineno, alias.name) for alias in node.names]
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            for alias in node.names:
                sub = f"{node.module}.{alias.name}"
                is_module = (PACKAGE.parent / Path(*sub.split("."))).with_suffix(".py").exists() or (
                    PACKAGE.parent / Path(*sub.split(".")) / "__init__.py").exists()
                found.append((node.lineno, sub if is_module else node.module))
        elif isinstance(node, ast.ImportFrom) and node.level:
            raise AssertionError(f"{path}:{node.lineno}: relative import; use robot_sim.* absolute imports")
    return found


MODULES = {module_name(p): p for p in sorted(PACKAGE.rglob("*.py"))}


def test_every_module_belongs_to_a_known_layer() -> None:
    unknown = sorted({layer(m) for m in MODULES if layer(m) is not None} - set(ALLOWED))
    assert not unknown, f"robot_sim has folders or modules outside the layering table: {unknown}"


@pytest.mark.parametrize("module", sorted(m for m in MODULES if layer(m) is not None))
def test_imports_respect_the_layers(module: str) -> None:
    own = layer(module)
    problems = []
    for line, target in imports(MODULES[module]):
        top = target.split(".")[0]
        if top == "robot_sim":
            other = layer(target)
            if other is not None and other != own and other not in ALLOWED[own]:
                problems.append(f"line {line}: {own} imports {target}")
        elif own in FORBIDDEN_EXTERNAL.get(top, set()):
            problems.append(f"line {line}: {own} imports {top}")
    assert not problems, f"{MODULES[module]}: " + "; ".join(problems)


def test_the_browser_view_uses_graphics_geometry_only() -> None:
    """robot_sim.web imports graphics' GL-free geometry modules only, and those reach no GL
    module (nor any drawable of graphics/items) through their own imports."""
    used = {t for m, p in MODULES.items() if layer(m) == "web" for _, t in imports(p) if layer(t) == "graphics"}
    assert used <= GRAPHICS_GEOMETRY, f"robot_sim.web imports graphics modules with GL: {sorted(used - GRAPHICS_GEOMETRY)}"
    reached, todo = set(), list(GRAPHICS_GEOMETRY)
    while todo:
        module = todo.pop()
        for _, target in imports(MODULES[module]):
            if target in MODULES and target not in reached and layer(target) == "graphics":
                reached.add(target)
                todo.append(target)
    gl = sorted(m for m in reached if m in GRAPHICS_GL or m.startswith("robot_sim.graphics.items"))
    assert not gl, f"graphics' geometry modules reach GL code: {gl}"


def test_the_checker_catches_a_violation(tmp_path: Path) -> None:
    """The reader sees lazy (function-level) and TYPE_CHECKING imports too."""
    probe = tmp_path / "probe.py"
    probe.write_text("from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from robot_sim.qt import window\n"
                     "def f():\n    import PyQt5.QtCore\n")
    assert [t for _, t in imports(probe)] == ["typing", "robot_sim.qt.window", "PyQt5.QtCore"]


def test_no_import_cycles() -> None:
    graph = {m: {t for _, t in imports(p) if t in MODULES and t != m} for m, p in MODULES.items()}
    # a package's __init__ may re-export its own modules; importing the package from one of
    # them is the cycle that matters, so edges into an __init__ from its own package count too
    state: dict[str, int] = {}
    stack: list[str] = []

    def visit(node: str) -> None:
        state[node] = 1
        stack.append(node)
        for nxt in sorted(graph[node]):
            if state.get(nxt) == 1:
                cycle = stack[stack.index(nxt):] + [nxt]
                raise AssertionError("import cycle: " + " -> ".join(cycle))
            if nxt not in state:
                visit(nxt)
        stack.pop()
        state[node] = 2

    for module in sorted(graph):
        if module not in state:
            visit(module)
