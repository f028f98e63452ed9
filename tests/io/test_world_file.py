"""World files (robot_sim.io.world_file.load_world): obstacles read as shapes, the floor
unless floor = false, and every bad field named with what is accepted."""
from __future__ import annotations

import math

import numpy as np
import pytest

from robot_sim.io.world_file import WorldDefinitionError, load_world
from robot_sim.model.shapes import Box, Capsule, Cylinder, HalfSpace, Mesh, Sphere

GOOD = '''units = "deg"
[[obstacles]]
name = "table"
shape = "box"
size = [0.8, 0.6, 0.04]
xyz = [0.5, 0.0, 0.38]
rpy = [0, 0, 90]
[[obstacles]]
name = "ball"
shape = "sphere"
radius = 0.05
xyz = [0.3, 0.4, 0.25]
[[obstacles]]
name = "post"
shape = "cylinder"
radius = 0.03
length = 0.5
xyz = [0.3, -0.4, 0.25]
[[obstacles]]
name = "bar"
shape = "capsule"
radius = 0.02
length = 0.4
color = [1, 0, 0, 1]
'''


def write(tmp_path, text: str):
    path = tmp_path / "world.toml"
    path.write_text(text)
    return path


def test_good_world(tmp_path):
    world = load_world(write(tmp_path, GOOD))
    assert world.names == ("floor", "table", "ball", "post", "bar")
    assert isinstance(world["floor"], HalfSpace) and world.floor
    table = world["table"]
    assert isinstance(table, Box) and np.allclose(table.size, [0.8, 0.6, 0.04])
    assert np.allclose(table.pose[:3, 3], [0.5, 0.0, 0.38]) and np.allclose(table.pose[:3, 0], [0, 1, 0])
    assert isinstance(world["ball"], Sphere) and np.allclose(world["ball"].center, [0.3, 0.4, 0.25])
    assert isinstance(world["post"], Cylinder) and world["post"].length == 0.5
    assert isinstance(world["bar"], Capsule) and world["bar"].color == (1.0, 0.0, 0.0, 1.0)


def test_radians_by_default_and_no_floor(tmp_path):
    world = load_world(write(tmp_path, 'floor = false\n[[obstacles]]\nname = "b"\nshape = "box"\n'
                                       f'size = [1, 1, 1]\nrpy = [0, 0, {math.pi / 2}]\n'))
    assert world.names == ("b",) and np.allclose(world["b"].pose[:3, 0], [0, 1, 0])


def test_mesh_obstacle_relative_to_the_file(tmp_path):
    trimesh = pytest.importorskip("trimesh")
    (tmp_path / "meshes").mkdir()
    trimesh.creation.box((1, 1, 1)).export(tmp_path / "meshes" / "cube.stl")
    world = load_world(write(tmp_path, '[[obstacles]]\nname = "m"\nshape = "mesh"\nmesh = "meshes/cube.stl"\n'
                                       'scale = [2, 2, 2]\n'))
    assert isinstance(world["m"], Mesh) and np.allclose(np.abs(world["m"].vertices), 1.0)


@pytest.mark.parametrize("text, fragment", [
    ('floor = "yes"\n', "floor: expected true or false"),
    ('units = "grad"\n', "units: unknown units 'grad'; accepted: 'deg' or 'rad'"),
    ('walls = 1\n', "walls: unknown key 'walls'; accepted keys: floor, obstacles, units"),
    ('[[obstacles]]\nname = "a"\nshape = "cone"\n', "obstacles[0].shape: unknown shape 'cone'; accepted: box, sphere"),
    ('[[obstacles]]\nname = "a"\nshape = "box"\n', "obstacles[0].size: missing: a box needs size"),
    ('[[obstacles]]\nname = "a"\nshape = "box"\nsize = [1, 0, 1]\n', "obstacles[0].size[1]: expected a length > 0 m"),
    ('[[obstacles]]\nname = "a"\nshape = "box"\nsize = [1, 1]\n', "obstacles[0].size: expected a list of 3 numbers"),
    ('[[obstacles]]\nname = "a"\nshape = "sphere"\nradius = 0.1\nsize = [1, 1, 1]\n',
     "obstacles[0].size: unknown key 'size'; accepted keys: color, name, radius, rpy, shape, xyz"),
    ('[[obstacles]]\nname = "a"\nshape = "cylinder"\nradius = 0.1\n', "obstacles[0].length: missing: a cylinder needs length and radius"),
    ('[[obstacles]]\nname = "floor"\nshape = "sphere"\nradius = 0.1\n', "obstacles[0].name: obstacle name 'floor' is used twice"),
    ('[[obstacles]]\nname = "a"\nshape = "sphere"\nradius = 0.1\n[[obstacles]]\nname = "a"\nshape = "sphere"\nradius = 0.2\n',
     "obstacles[1].name: obstacle name 'a' is used twice"),
    ('[[obstacles]]\nname = ""\nshape = "sphere"\nradius = 0.1\n', "obstacles[0].name: expected a non-empty name"),
    ('[[obstacles]]\nname = "a"\nshape = "sphere"\nradius = 0.1\nxyz = [0, "x", 0]\n', "obstacles[0].xyz[1]: expected a number"),
    ('[[obstacles]]\nname = "a"\nshape = "sphere"\nradius = 0.1\ncolor = [2, 0, 0, 1]\n', "obstacles[0].color: expected RGBA"),
    ('[[obstacles]]\nname = "a"\nshape = "mesh"\nmesh = "nope.stl"\n', "nope.stl: mesh file not found"),
    ('obstacles = 3\n', "obstacles: expected [[obstacles]] tables"),
    ('[[obstacles\n', "invalid TOML"),
])
def test_bad_world_files_name_file_and_field(tmp_path, text, fragment):
    path = write(tmp_path, text)
    with pytest.raises(WorldDefinitionError) as info:
        load_world(path)
    assert str(info.value).startswith(f"{path}: ") and fragment in str(info.value), str(info.value)


def test_missing_world_file(tmp_path):
    with pytest.raises(WorldDefinitionError, match="world file not found"):
        load_world(tmp_path / "none.toml")
