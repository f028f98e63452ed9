"""URDF out and in: exported files parse with an independent parser (urdf_parser_py) and
their forward kinematics, computed from joint origins and axes alone (urdf_helpers),
equals ours; hand-written URDFs in tests/data import to DH robots with the URDF's own
kinematics; bad URDFs are refused with one clear error; robot → URDF → robot round trips."""
from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from paths import DATA
from kin_helpers import CONVENTIONS, ROBOT_NAMES, random_dh_robot, random_q, robot
from robot_sim.dynamics import gravity_torque, mass_matrix
from robot_sim.kinematics import forward_kinematics
from robot_sim.model.params import JTYPE_PRISMATIC, JTYPE_REVOLUTE, RobotDefinitionError
from robot_sim.io.robot_file import load_robot
from robot_sim.io.urdf_out import to_urdf
from urdf_helpers import chain, moving, origin_matrix, parse, urdf_fk, urdf_mass_matrix

seeds = st.integers(0, 2**32 - 1)


def check_export(rob, Q: np.ndarray) -> None:
    """The URDF of ``rob`` parses, has its joints and limits, and its FK is ours."""
    model = parse(to_urdf(rob))
    assert model.name == rob.name
    assert model.get_root() == "world"
    joints = chain(model, "tool0")
    assert [j.name for j in joints] == ["base_joint", *(f"joint{i + 1}" for i in range(rob.n_dofs)), "tool_joint"]
    assert joints[0].type == joints[-1].type == "fixed"
    for i, joint in enumerate(moving(joints)):
        if rob.jtype[i] == JTYPE_PRISMATIC:
            assert joint.type == "prismatic"
        else:
            assert joint.type == ("revolute" if np.isfinite(rob.q_max[i]) else "continuous")
        if np.isfinite(rob.q_max[i]):
            assert (joint.limit.lower, joint.limit.upper) == (rob.q_min[i], rob.q_max[i])
    for q, T in zip(Q, forward_kinematics(rob, Q)):
        np.testing.assert_allclose(urdf_fk(model, "tool0", q), T, atol=1e-12, rtol=0)


@pytest.mark.parametrize("conv", CONVENTIONS)
@pytest.mark.parametrize("name", ROBOT_NAMES)
def test_exported_urdf_of_shipped_robots(name, conv):
    rob = robot(name, conv)
    check_export(rob, random_q(rob, np.random.default_rng(50), 40))


@pytest.mark.parametrize("conv", CONVENTIONS)
@settings(max_examples=25, deadline=None)
@given(seed=seeds, n=st.integers(1, 7))
def test_exported_urdf_of_random_chains(conv, seed, n):
    rng = np.random.default_rng(seed)
    rob = random_dh_robot(rng, n, convention=conv)
    check_export(rob, random_q(rob, rng, 10))


@pytest.mark.parametrize("conv", CONVENTIONS)
@pytest.mark.parametrize("name", ROBOT_NAMES)
def test_exported_inertials_sit_where_ours_do(name, conv):
    """Link i's inertial in the URDF, placed by the URDF's own FK, has our mass, our COM in
    the world and our inertia tensor turned into the world (frame i of either convention)."""
    rob = robot(name, conv)
    model = parse(to_urdf(rob))
    q = random_q(rob, np.random.default_rng(53))
    frames = forward_kinematics(rob, q, all_frames=True)
    for i in range(rob.n_dofs):
        inertial = model.link_map[f"link{i + 1}"].inertial
        assert inertial.mass == rob.inertials.mass[i]
        pose = urdf_fk(model, f"link{i + 1}", q[: i + 1]) @ origin_matrix(inertial.origin)
        R_i = frames[i + 1][:3, :3]
        np.testing.assert_allclose(pose[:3, 3], R_i @ rob.inertials.com[i] + frames[i + 1][:3, 3], atol=1e-12)
        t = inertial.inertia
        I_urdf = np.array([[t.ixx, t.ixy, t.ixz], [t.ixy, t.iyy, t.iyz], [t.ixz, t.iyz, t.izz]])
        np.testing.assert_allclose(pose[:3, :3] @ I_urdf @ pose[:3, :3].T, R_i @ rob.inertials.inertia[i] @ R_i.T,
                                   atol=1e-12 * max(1.0, np.abs(rob.inertials.inertia[i]).max()))


def test_exported_urdf_has_cylinders_and_the_tool_joint():
    rob = robot("stanford")
    model = parse(to_urdf(rob))
    links = {link.name: link for link in model.links}
    for i in range(1, rob.n_dofs + 1):
        assert links[f"link{i}"].visuals and links[f"link{i}"].collisions
        assert links[f"link{i}"].visuals[0].geometry.radius > 0
    tool = [j for j in model.joints if j.name == "tool_joint"][0]
    assert (tool.parent, tool.child) == (f"link{rob.n_dofs}", "tool0")


# ------------------------------------------------------------------ URDF in

HAND_WRITTEN = {
    # file: (tip, moving joint names)
    "rotated_axes.urdf": (None, ["j1", "j2", "j3", "j4", "j5", "j6"]),
    "parallel_axes.urdf": (None, ["waist", "shoulder", "elbow", "wrist", "wrist_same_line"]),
    "prismatic.urdf": (None, ["turn", "slide", "roll", "wrist"]),
    "fixed_mid.urdf": (None, ["j1", "j2", "j3"]),
    "branching.urdf": ("left_finger", ["shoulder", "elbow", "wrist", "left"]),
    "ur5_ros_layout.urdf": (None, ["shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint",
                                   "wrist_1_joint", "wrist_2_joint", "wrist_3_joint"]),
}


def urdf_q(model, tip: str, rng: np.random.Generator, count: int) -> np.ndarray:
    """Random joint values inside the URDF's limits (continuous joints in ±π)."""
    joints = moving(chain(model, tip))
    lo = np.array([j.limit.lower if j.type != "continuous" else -np.pi for j in joints])
    hi = np.array([j.limit.upper if j.type != "continuous" else np.pi for j in joints])
    return lo + (hi - lo) * rng.random((count, len(joints)))


@pytest.mark.parametrize("conv", CONVENTIONS)
@pytest.mark.parametrize("filename", HAND_WRITTEN)
def test_hand_written_urdf_imports_with_its_own_kinematics(filename, conv):
    tip, names = HAND_WRITTEN[filename]
    path = DATA / filename
    rob = load_robot(path, tip=tip, convention=conv)
    model = parse(path.read_text())
    tip_link = tip or model.links[-1].name
    joints = moving(chain(model, tip_link))
    assert [j.name for j in joints] == names
    assert rob.n_dofs == len(names) and rob.convention == conv
    np.testing.assert_array_equal(rob.jtype, [JTYPE_PRISMATIC if j.type == "prismatic" else JTYPE_REVOLUTE for j in joints])
    for i, joint in enumerate(joints):
        if joint.type == "continuous":
            assert rob.q_min[i] == -np.inf and rob.q_max[i] == np.inf
        else:
            assert (rob.q_min[i], rob.q_max[i]) == (joint.limit.lower, joint.limit.upper)
        assert rob.q_min[i] <= rob.q_home[i] <= rob.q_max[i]
    Q = urdf_q(model, tip_link, np.random.default_rng(51), 60)
    for q, T in zip(Q, forward_kinematics(rob, Q)):
        np.testing.assert_allclose(T, urdf_fk(model, tip_link, q), atol=1e-9, rtol=0)


@pytest.mark.parametrize("conv", CONVENTIONS)
def test_inertials_of_fixed_links_are_lumped_into_the_dh_frames(conv):
    """fixed_mid.urdf: the adapter's inertial joins the upper arm's, the tcp's the
    forearm's; the imported mass matrix equals one computed from the URDF alone (COM
    Jacobians by finite differences of the URDF's FK), and the effort and velocity limits
    become drives."""
    path = DATA / "fixed_mid.urdf"
    rob = load_robot(path, convention=conv)
    np.testing.assert_allclose(rob.inertials.mass, [4.0, 3.5, 2.3], atol=1e-15)
    np.testing.assert_array_equal(rob.drives.effort_limit, [1.0, 1.0, 1.0])
    np.testing.assert_array_equal(rob.drives.velocity_limit, [1.0, 1.0, 1.0])
    model = parse(path.read_text())
    for q in random_q(rob, np.random.default_rng(54), 5):
        np.testing.assert_allclose(mass_matrix(rob, q), urdf_mass_matrix(model, "tcp", q), atol=1e-8)


def test_unknown_effort_and_velocity_are_unlimited_drives():
    rob = load_robot(DATA / "rotated_axes.urdf")
    np.testing.assert_array_equal(rob.drives.effort_limit, [100, 100, 50, 20, 20, np.inf])
    np.testing.assert_array_equal(rob.drives.velocity_limit, [2, 2, 3, 4, 4, np.inf])
    model = parse(to_urdf(rob))  # written back: the known limits, 0 for the unknown ones
    limits = [j.limit for j in moving(chain(model, "tool0"))]
    assert [lim.effort for lim in limits[:5]] == [100, 100, 50, 20, 20]
    assert [lim.velocity for lim in limits[:5]] == [2, 2, 3, 4, 4]
    assert limits[5] is None  # continuous, nothing known
    assert load_robot(DATA / "branching.urdf", tip="camera").inertials is None


def test_a_ros_style_ur5_is_the_shipped_ur5_turned_about_z():
    """ur5_ros_layout.urdf (ROS layout, built from UR's DH values) imports to the arm of
    robots/ur5.toml: its tool0 is the DH endeffector turned 180° about the base z axis at
    every q, d1 lands in the base, d6 in the tool, and the lengths come back (a ≥ 0)."""
    rob, ur5 = load_robot(DATA / "ur5_ros_layout.urdf"), load_robot("ur5")
    turn = np.diag([-1.0, -1.0, 1.0, 1.0])
    Q = random_q(ur5, np.random.default_rng(55), 50)
    np.testing.assert_allclose(forward_kinematics(rob, Q), turn @ forward_kinematics(ur5, Q), atol=1e-12)
    np.testing.assert_allclose(rob.dh_a, [0.0, 0.425, 0.39225, 0.0, 0.0, 0.0], atol=1e-15)
    np.testing.assert_allclose(rob.dh_d, [0.0, 0.0, 0.0, 0.10915, 0.09465, 0.0], atol=1e-15)
    np.testing.assert_allclose(rob.base_tf.t(), [0.0, 0.0, 0.089159], atol=1e-15)
    np.testing.assert_allclose(rob.tool_tf.t(), [0.0, 0.0, 0.0823], atol=1e-15)


def test_parallel_and_coincident_axes_give_their_dh_values():
    """Waist vertical, then pitch axes along +y, −y, +y, +y: standard α1 = ±90°, the
    parallel links α = 180° (the axis flips), 180° and 0 (coincident wrist axes), with
    lengths a2 = 0.45 (shoulder to elbow), a3 = 0.35 (elbow to wrist) and a4 = 0."""
    rob = load_robot(DATA / "parallel_axes.urdf", convention="standard")
    np.testing.assert_allclose(np.abs(rob.dh_alpha), [np.pi / 2, np.pi, np.pi, 0.0, 0.0], atol=1e-12)
    np.testing.assert_allclose(rob.dh_a, [0.0, 0.45, 0.35, 0.0, 0.0], atol=1e-12)


def test_intersecting_axes_have_no_common_normal_length():
    """rotated_axes: joints 4, 5 and 6 share a point (a wrist): a4 = a5 = 0 (modified a of
    rows 5 and 6), and so do the standard frames' offsets along the normal."""
    rob = load_robot(DATA / "rotated_axes.urdf", convention="modified")
    np.testing.assert_allclose(rob.dh_a[4:], 0.0, atol=1e-12)
    np.testing.assert_allclose(rob.dh_d[4:], 0.0, atol=1e-12)


def test_branching_tree_needs_a_tip_and_follows_it():
    path = DATA / "branching.urdf"
    with pytest.raises(RobotDefinitionError) as info:
        load_robot(path)
    assert str(info.value) == (
        f"{path}: the tree has several tips (camera, left_finger, right_finger); choose one with tip= (--tip LINK)"
    )
    camera = load_robot(path, tip="camera")
    assert camera.n_dofs == 1
    model = parse(path.read_text())
    for q in (-1.0, 0.3, 2.0):
        np.testing.assert_allclose(forward_kinematics(camera, [q]), urdf_fk(model, "camera", [q]), atol=1e-12)
    right = load_robot(path, tip="right_finger")
    assert right.jtype[-1] == JTYPE_PRISMATIC and right.n_dofs == 4


def test_tip_and_convention_arguments_are_checked():
    with pytest.raises(ValueError, match="tip applies to URDF files only"):
        load_robot("puma560", tip="link6")
    with pytest.raises(ValueError, match="convention must be 'standard' or 'modified', got 'dh'"):
        load_robot(DATA / "prismatic.urdf", convention="dh")
    assert load_robot("puma560", convention="modified").is_modified


# ------------------------------------------------------------------ bad URDFs

LINKS = '<link name="a"/><link name="b"/><link name="c"/>'


def joint(name="j", kind="revolute", parent="a", child="b", extra='<limit lower="-1" upper="1" effort="1" velocity="1"/>'):
    return f'<joint name="{name}" type="{kind}"><parent link="{parent}"/><child link="{child}"/>{extra}</joint>'


BAD_URDFS = {
    "malformed xml": ('<robot name="x"><link name="a"></robot>', "malformed XML: mismatched tag: line 1, column 33"),
    "doctype entity": (
        '<?xml version="1.0"?><!DOCTYPE r [<!ENTITY e "aaaa">]><robot name="x">&e;</robot>',
        "DOCTYPE and ENTITY declarations are not accepted in a URDF",
    ),
    "not a robot": ("<model/>", "the root element is <model>, expected <robot>"),
    "no joints": (f'<robot name="x">{LINKS}</robot>', "no joints: a URDF arm needs <joint> elements"),
    "only fixed joints": (
        f'<robot name="x"><link name="a"/><link name="b"/>{joint(kind="fixed", extra="")}</robot>',
        "no joints: the chain to 'b' has no revolute, continuous or prismatic joint",
    ),
    "unknown parent": (
        f'<robot name="x">{LINKS}{joint(parent="zz")}</robot>',
        "joint 'j': parent link 'zz' is not declared as a <link>",
    ),
    "unknown child": (
        f'<robot name="x">{LINKS}{joint(child="zz")}</robot>',
        "joint 'j': child link 'zz' is not declared as a <link>",
    ),
    "two parents": (
        f'<robot name="x">{LINKS}{joint()}{joint(name="k", parent="c")}</robot>',
        "link 'b' has two parent joints ('j' and 'k'): URDF links must form a tree (a loop is not allowed)",
    ),
    "loop without root": (
        f'<robot name="x"><link name="a"/><link name="b"/>{joint()}{joint(name="k", parent="b", child="a")}</robot>',
        "the joints form a loop: no link is the root",
    ),
    "loop beside the root": (
        f'<robot name="x">{LINKS}<link name="d"/>{joint()}{joint(name="k", parent="c", child="d")}'
        f'{joint(name="m", parent="d", child="c")}</robot>',
        "the joints form a loop through link 'c'",
    ),
    "two trees": (
        f'<robot name="x">{LINKS}{joint()}</robot>',
        "several root links (a, c): the links must form one tree",
    ),
    "several tips": (
        f'<robot name="x">{LINKS}{joint()}{joint(name="k", child="c")}</robot>',
        "the tree has several tips (b, c); choose one with tip= (--tip LINK)",
    ),
    "floating joint": (
        f'<robot name="x">{LINKS}{joint(kind="floating", extra="")}{joint(name="k", parent="b", child="c")}</robot>',
        "joint 'j': floating joints cannot be part of a DH chain",
    ),
    "planar joint": (
        f'<robot name="x">{LINKS}{joint()}{joint(name="k", kind="planar", parent="b", child="c", extra="")}</robot>',
        "joint 'k': planar joints cannot be part of a DH chain",
    ),
    "mimic joint": (
        f'<robot name="x">{LINKS}{joint()}'
        f'{joint(name="k", parent="b", child="c", extra=chr(60) + "mimic joint=" + chr(34) + "j" + chr(34) + "/>" + chr(60) + "limit lower=" + chr(34) + "0" + chr(34) + " upper=" + chr(34) + "1" + chr(34) + "/>")}'
        "</robot>",
        "joint 'k': mimic joints are not supported in the chain",
    ),
    "unknown joint type": (f'<robot name="x">{LINKS}{joint(kind="ball")}</robot>', "joint 'j': unknown joint type 'ball'"),
    "revolute without limit": (
        f'<robot name="x">{LINKS}{joint(extra="")}</robot>',
        "joint 'j': a revolute joint needs <limit lower=... upper=...>",
    ),
    "limits reversed": (
        f'<robot name="x">{LINKS}{joint(extra=chr(60) + "limit lower=" + chr(34) + "1" + chr(34) + " upper=" + chr(34) + "-1" + chr(34) + "/>")}</robot>',
        "joint 'j' limit: lower 1.0 > upper -1.0",
    ),
    "short origin": (
        f'<robot name="x">{LINKS}{joint(extra=chr(60) + "origin xyz=" + chr(34) + "1 2" + chr(34) + "/>")}</robot>',
        "joint 'j' origin xyz: expected 3 finite numbers, got '1 2'",
    ),
    "nan in axis": (
        f'<robot name="x">{LINKS}{joint(kind="continuous", extra=chr(60) + "axis xyz=" + chr(34) + "0 nan 1" + chr(34) + "/>")}</robot>',
        "joint 'j' axis xyz: expected 3 finite numbers, got '0 nan 1'",
    ),
    "zero axis": (
        f'<robot name="x">{LINKS}{joint(kind="continuous", extra=chr(60) + "axis xyz=" + chr(34) + "0 0 0" + chr(34) + "/>")}</robot>',
        "joint 'j' axis: the axis has zero length",
    ),
    "negative mass": (
        '<robot name="x"><link name="a"/><link name="b"><inertial><mass value="-1"/></inertial></link>'
        f'{joint()}</robot>',
        "link 'b' inertial mass: the mass is negative: -1.0",
    ),
    "non-physical inertia": (
        '<robot name="x"><link name="a"/><link name="b"><inertial><mass value="1"/>'
        '<inertia ixx="1" iyy="0" izz="0" ixy="0" ixz="0" iyz="0"/></inertial></link>'
        f'{joint(kind="continuous", extra="")}</robot>',
        "inertia of link 1 principal moments [0, 0, 1] violate the triangle inequality (1 > 0 + 0)",
    ),
    "overflowing origins": (
        f'<robot name="x">{LINKS}{joint(kind="continuous", extra=chr(60) + "origin xyz=" + chr(34) + "1e308 1e308 0" + chr(34) + "/>")}'
        f'{joint(name="k", kind="continuous", parent="b", child="c", extra=chr(60) + "origin xyz=" + chr(34) + "1e308 0 1e308" + chr(34) + "/>")}</robot>',
        "the joint origins add up to positions beyond floating point (inf or NaN)",
    ),
    "duplicate link": ('<robot name="x"><link name="a"/><link name="a"/></robot>', "link 'a': every <link> needs a unique non-empty name"),
}


@pytest.mark.parametrize("text, message", BAD_URDFS.values(), ids=BAD_URDFS.keys())
def test_bad_urdf_raises_one_clear_error(tmp_path, text, message):
    path = tmp_path / "arm.urdf"
    path.write_text(text)
    with pytest.raises(RobotDefinitionError) as info:
        load_robot(path)
    assert str(info.value).startswith(f"{path}: {message}"), str(info.value)


def test_missing_and_unreadable_urdf(tmp_path):
    with pytest.raises(RobotDefinitionError, match=r"nope\.urdf: URDF file not found$"):
        load_robot(tmp_path / "nope.urdf")
    (tmp_path / "dir.urdf").mkdir()
    with pytest.raises(RobotDefinitionError, match=r"dir\.urdf: cannot read URDF file: "):
        load_robot(tmp_path / "dir.urdf")


def test_entities_cannot_hide_behind_another_encoding(tmp_path):
    path = tmp_path / "arm.urdf"
    text = '<?xml version="1.0" encoding="UTF-16"?><!DOCTYPE r [<!ENTITY e "aa">]><robot name="x">&e;</robot>'
    path.write_bytes(text.encode("utf-16"))
    with pytest.raises(RobotDefinitionError) as info:
        load_robot(path)
    assert str(info.value) == f"{path}: not UTF-8 text (byte 0xff at offset 0); save the URDF as UTF-8"
    path.write_bytes(b"\xef\xbb\xbf" + (DATA / "prismatic.urdf").read_bytes())  # a UTF-8 byte-order mark is fine
    assert load_robot(path).n_dofs == 4


def test_unknown_tip_is_named(tmp_path):
    with pytest.raises(RobotDefinitionError, match="tip link 'zz' is not declared; links: base, upper"):
        load_robot(DATA / "branching.urdf", tip="zz")


# ------------------------------------------------------------------ round trips


@pytest.mark.parametrize("conv", CONVENTIONS)
@pytest.mark.parametrize("name", ROBOT_NAMES)
def test_shipped_robot_urdf_round_trip(tmp_path, name, conv):
    rob = robot(name, conv)
    path = tmp_path / f"{name}.urdf"
    path.write_text(to_urdf(rob))
    back = load_robot(path, convention=conv)
    assert back.convention == conv and back.name == rob.name
    np.testing.assert_array_equal(back.jtype, rob.jtype)
    np.testing.assert_array_equal(back.q_min, rob.q_min)
    np.testing.assert_array_equal(back.q_max, rob.q_max)
    Q = random_q(rob, np.random.default_rng(52), 100)
    np.testing.assert_allclose(forward_kinematics(back, Q), forward_kinematics(rob, Q), atol=1e-12, rtol=0)
    # URDF holds no motor inertia, gearing or friction: compare the link dynamics alone
    links_only = dataclasses.replace(rob, drives=None)
    np.testing.assert_allclose(mass_matrix(back, Q[:20]), mass_matrix(links_only, Q[:20]), atol=1e-12, rtol=1e-12)
    np.testing.assert_allclose(gravity_torque(back, Q[:20]), gravity_torque(links_only, Q[:20]), atol=1e-11, rtol=1e-12)


@pytest.mark.parametrize("conv", CONVENTIONS)
@settings(max_examples=25, deadline=None)
@given(seed=seeds, n=st.integers(1, 7))
def test_random_chain_urdf_round_trip(tmp_path_factory, conv, seed, n):
    rng = np.random.default_rng(seed)
    rob = random_dh_robot(rng, n, convention=conv)
    path = tmp_path_factory.mktemp("rt") / "arm.urdf"
    path.write_text(to_urdf(rob))
    back = load_robot(path, convention=conv)
    Q = random_q(rob, rng, 20)
    np.testing.assert_allclose(forward_kinematics(back, Q), forward_kinematics(rob, Q), atol=1e-9, rtol=0)


# ------------------------------------------------------------------ random URDFs

AXES = np.vstack([np.eye(3), -np.eye(3)])


def random_urdf(rng: np.random.Generator, n_links: int) -> str:
    """A chain of random joints: revolute, continuous, prismatic and fixed; axes either
    along ±x, ±y, ±z (parallel, coincident and intersecting successive axes happen) or
    random; origins with zero or random offsets and rpy."""
    links = "".join(f'<link name="l{i}"/>' for i in range(n_links + 1))
    joints = []
    for i in range(n_links):
        kind = rng.choice(["revolute", "continuous", "prismatic", "fixed"], p=[0.4, 0.2, 0.2, 0.2])
        xyz = rng.uniform(-0.5, 0.5, 3) * (rng.random(3) < 0.5)
        rpy = rng.choice([0.0, np.pi / 2, -np.pi / 2, np.pi], 3) if rng.random() < 0.5 else rng.uniform(-np.pi, np.pi, 3)
        axis = AXES[rng.integers(6)] if rng.random() < 0.7 else rng.normal(size=3)
        limit = '<limit lower="-1.5" upper="1.5" effort="0" velocity="0"/>' if kind in ("revolute", "prismatic") else ""
        joints.append(
            f'<joint name="j{i}" type="{kind}"><parent link="l{i}"/><child link="l{i + 1}"/>'
            f'<origin xyz="{" ".join(repr(float(v)) for v in xyz)}" rpy="{" ".join(repr(float(v)) for v in rpy)}"/>'
            f'<axis xyz="{" ".join(repr(float(v)) for v in axis)}"/>{limit}</joint>'
        )
    if not any('type="fixed"' not in j for j in joints):  # at least one moving joint
        joints[0] = joints[0].replace('type="fixed"', 'type="continuous"')
    return f'<robot name="random">{links}{"".join(joints)}</robot>'


@pytest.mark.parametrize("conv", CONVENTIONS)
@settings(max_examples=40, deadline=None)
@given(seed=seeds, n_links=st.integers(1, 9))
def test_random_urdfs_import_with_their_own_kinematics(tmp_path_factory, conv, seed, n_links):
    rng = np.random.default_rng(seed)
    text = random_urdf(rng, n_links)
    path = tmp_path_factory.mktemp("rnd") / "arm.urdf"
    path.write_text(text)
    rob = load_robot(path, convention=conv)
    model = parse(text)
    tip = f"l{n_links}"
    assert rob.n_dofs == len(moving(chain(model, tip)))
    for q in urdf_q(model, tip, rng, 10):
        np.testing.assert_allclose(forward_kinematics(rob, q), urdf_fk(model, tip, q), atol=1e-9, rtol=0)


def test_a_bare_file_name_in_any_case_is_a_path(tmp_path, monkeypatch):
    (tmp_path / "ARM.URDF").write_bytes((DATA / "prismatic.urdf").read_bytes())
    monkeypatch.chdir(tmp_path)
    assert load_robot("ARM.URDF").n_dofs == 4
