"""Robot files (robots/*.toml, load_robot validation) and RobotState."""
from __future__ import annotations

import math

import numpy as np
import pytest

from kin_helpers import ROBOT_NAMES, h_rot_x, h_rot_z, robot
from robot_sim.model.params import JTYPE_PRISMATIC, JTYPE_REVOLUTE, RobotDefinitionError, RobotParams
from robot_sim.io.robot_file import ROBOTS_DIR, available_robots, load_robot
from robot_sim.model.state import RobotState
from robot_sim.transforms import rot_y

DEG = math.pi / 180.0

# name: (n_dofs, index of the prismatic joint or None)
EXPECTED_ROBOTS = {
    "planar3": (3, None),
    "spherical": (3, 2),
    "anthropomorphic": (3, None),
    "anthropomorphic6": (6, None),
    "humanoid7": (7, None),
    "stanford": (6, 2),
    "scara": (4, 2),
    "puma560": (6, None),
    "ur5": (6, None),
}


# ------------------------------------------------------------------ shipped robots


def test_available_robots_lists_the_shipped_files():
    names = available_robots()
    assert set(EXPECTED_ROBOTS) <= set(names)
    assert names == sorted(p.stem for p in ROBOTS_DIR.glob("*.toml"))


@pytest.mark.parametrize("name", ROBOT_NAMES)
def test_every_shipped_robot_loads_consistently(name):
    rob = load_robot(name)
    n = rob.n_dofs
    assert n >= 1 and rob.n_links == n
    for arr in (rob.dh_a, rob.dh_alpha, rob.dh_d, rob.dh_th, rob.jtype, rob.q_home, rob.q_min, rob.q_max, rob.link_com_frac):
        assert arr.shape == (n,)
    assert np.all(np.isfinite([rob.dh_a, rob.dh_alpha, rob.dh_d, rob.dh_th, rob.q_home]))
    assert np.all(rob.q_min <= rob.q_home) and np.all(rob.q_home <= rob.q_max)
    assert np.all((rob.link_com_frac >= 0) & (rob.link_com_frac <= 1))
    assert set(rob.jtype.tolist()) <= {JTYPE_REVOLUTE, JTYPE_PRISMATIC}
    assert rob.name and rob.source == str(ROBOTS_DIR / f"{name}.toml")
    # the file says where its numbers come from
    assert (ROBOTS_DIR / f"{name}.toml").read_text().lstrip().startswith("#")
    with pytest.raises(ValueError):  # parameters are immutable
        rob.dh_a[0] = 1.0


@pytest.mark.parametrize("name, expected", EXPECTED_ROBOTS.items())
def test_shipped_robot_dofs_and_joint_types(name, expected):
    n, prismatic = expected
    rob = load_robot(name)
    assert rob.n_dofs == n
    want = np.full(n, JTYPE_REVOLUTE)
    if prismatic is not None:
        want[prismatic] = JTYPE_PRISMATIC
    np.testing.assert_array_equal(rob.jtype, want)
    np.testing.assert_array_equal(rob.is_revolute, want == JTYPE_REVOLUTE)


def test_shipped_values_are_converted_to_si():
    puma = load_robot("puma560")
    np.testing.assert_allclose(puma.dh_alpha, np.array([90, 0, -90, 90, -90, 0]) * DEG)
    np.testing.assert_allclose(puma.dh_a, [0, 0.4318, 0.0203, 0, 0, 0])
    np.testing.assert_allclose(puma.dh_d, [0.67183, 0, 0.15005, 0.4318, 0, 0])
    np.testing.assert_allclose(puma.q_min[1:3], np.array([-45, -225]) * DEG)
    np.testing.assert_allclose(puma.q_home[1], 45 * DEG)
    np.testing.assert_allclose(puma.base_tf.mat, np.eye(4))
    stanford = load_robot("stanford")
    assert stanford.dh_th[2] == pytest.approx(-math.pi / 2)
    # a prismatic joint's home and limits are metres, not scaled by the degree factor
    assert stanford.q_home[2] == 0.5
    np.testing.assert_allclose([stanford.q_min[2], stanford.q_max[2]], [0.3048, 1.27])
    humanoid = load_robot("humanoid7")
    np.testing.assert_allclose(humanoid.tool_tf.mat, _translation(0, 0, 0.05))
    assert humanoid.has_tool and not puma.has_tool


def _translation(x, y, z):
    m = np.eye(4)
    m[:3, 3] = (x, y, z)
    return m


def test_load_by_name_and_by_path_agree(tmp_path):
    by_name = load_robot("scara")
    path = ROBOTS_DIR / "scara.toml"
    copy = tmp_path / "my_scara.toml"
    copy.write_text(path.read_text())
    for other in (load_robot(path), load_robot(str(path)), load_robot(copy)):
        assert other.name == by_name.name
        for field in ("dh_a", "dh_alpha", "dh_d", "dh_th", "jtype", "q_home", "q_min", "q_max", "link_com_frac"):
            np.testing.assert_array_equal(getattr(other, field), getattr(by_name, field))
        np.testing.assert_array_equal(other.tool_tf.mat, by_name.tool_tf.mat)
    assert load_robot(copy).source == str(copy)


# ------------------------------------------------------------------ writing test files

HEAD = 'name = "test arm"\nunits = "deg"\n'
JOINT = 'type = "revolute"\na = 0.5\nalpha = 90.0\nd = 0.1\ntheta = 0.0\n'


def robot_file(tmp_path, head=HEAD, tables="", joints=(JOINT,), name="robot.toml"):
    """Write a robot file: top-level keys, then extra tables ([base], [tool]), then joints."""
    text = head + tables + "".join(f"\n[[joints]]\n{j}" for j in joints)
    path = tmp_path / name
    path.write_text(text)
    return path


def test_units_deg_and_rad_give_equal_arrays(tmp_path):
    deg_joints = (
        'type = "revolute"\na = 0.3\nalpha = 90.0\nd = 0.2\ntheta = 30.0\nhome = 45.0\nlimits = [-90.0, 120.0]\ncom = 0.25\n',
        'type = "prismatic"\na = 0.1\nalpha = -90.0\nd = 0.05\ntheta = -90.0\nhome = 0.4\nlimits = [0.2, 0.8]\n',
        'type = "revolute"\na = 0.0\nalpha = 180.0\nd = 0.0\ntheta = 0.0\n',
    )
    r = lambda deg: repr(deg * DEG)  # noqa: E731
    rad_joints = (
        f'type = "revolute"\na = 0.3\nalpha = {r(90)}\nd = 0.2\ntheta = {r(30)}\nhome = {r(45)}\nlimits = [{r(-90)}, {r(120)}]\ncom = 0.25\n',
        f'type = "prismatic"\na = 0.1\nalpha = {r(-90)}\nd = 0.05\ntheta = {r(-90)}\nhome = 0.4\nlimits = [0.2, 0.8]\n',
        f'type = "revolute"\na = 0.0\nalpha = {r(180)}\nd = 0.0\ntheta = 0.0\n',
    )
    deg = load_robot(robot_file(tmp_path, tables="[base]\nxyz = [1.0, 2.0, 3.0]\nrpy = [10.0, 20.0, 30.0]\n[tool]\nrpy = [0.0, 0.0, 90.0]\n", joints=deg_joints, name="deg.toml"))
    rad = load_robot(
        robot_file(
            tmp_path,
            head='name = "test arm"\nunits = "rad"\n',
            tables=f"[base]\nxyz = [1.0, 2.0, 3.0]\nrpy = [{r(10)}, {r(20)}, {r(30)}]\n[tool]\nrpy = [0.0, 0.0, {r(90)}]\n",
            joints=rad_joints,
            name="rad.toml",
        )
    )
    for field in ("dh_a", "dh_alpha", "dh_d", "dh_th", "jtype", "q_home", "q_min", "q_max", "link_com_frac"):
        np.testing.assert_allclose(getattr(deg, field), getattr(rad, field), rtol=1e-15, atol=0, err_msg=field)
    np.testing.assert_allclose(deg.base_tf.mat, rad.base_tf.mat, atol=1e-15)
    np.testing.assert_allclose(deg.tool_tf.mat, rad.tool_tf.mat, atol=1e-15)
    # and the values are the SI numbers themselves
    np.testing.assert_allclose(deg.dh_alpha, np.array([90, -90, 180]) * DEG)
    np.testing.assert_allclose(deg.q_home, [45 * DEG, 0.4, 0.0])
    np.testing.assert_allclose(deg.q_min, [-90 * DEG, 0.2, -np.inf])
    np.testing.assert_allclose(deg.q_max, [120 * DEG, 0.8, np.inf])
    np.testing.assert_array_equal(deg.jtype, [JTYPE_REVOLUTE, JTYPE_PRISMATIC, JTYPE_REVOLUTE])


def test_base_and_tool_tables_follow_urdf_rpy(tmp_path):
    tables = "[base]\nxyz = [0.1, -0.2, 0.3]\nrpy = [30.0, -45.0, 60.0]\n[tool]\nxyz = [0.0, 0.0, 0.12]\nrpy = [0.0, 90.0, 0.0]\n"
    rob = load_robot(robot_file(tmp_path, tables=tables))
    base = _translation(0.1, -0.2, 0.3) @ h_rot_z(60 * DEG)
    base[:3, :3] = base[:3, :3] @ rot_y(-45 * DEG) @ h_rot_x(30 * DEG)[:3, :3]
    np.testing.assert_allclose(rob.base_tf.mat, base, atol=1e-15)
    tool = _translation(0, 0, 0.12)
    tool[:3, :3] = [[0, 0, 1], [0, 1, 0], [-1, 0, 0]]
    np.testing.assert_allclose(rob.tool_tf.mat, tool, atol=1e-15)
    assert rob.has_tool
    # xyz or rpy alone: the other defaults to zero
    only_rpy = load_robot(robot_file(tmp_path, tables="[base]\nrpy = [0.0, 0.0, 90.0]\n", name="r.toml"))
    np.testing.assert_allclose(only_rpy.base_tf.mat, h_rot_z(math.pi / 2), atol=1e-15)


def test_defaults(tmp_path):
    rob = load_robot(robot_file(tmp_path, joints=(JOINT, JOINT.replace("revolute", "prismatic"))))
    np.testing.assert_array_equal(rob.q_home, [0.0, 0.0])
    np.testing.assert_array_equal(rob.q_min, [-np.inf, -np.inf])
    np.testing.assert_array_equal(rob.q_max, [np.inf, np.inf])
    np.testing.assert_array_equal(rob.link_com_frac, [0.5, 0.5])
    np.testing.assert_array_equal(rob.base_tf.mat, np.eye(4))
    np.testing.assert_array_equal(rob.tool_tf.mat, np.eye(4))
    assert not rob.has_tool
    assert rob.description == ""
    assert rob.convention == "standard" and not rob.is_modified
    built = RobotParams.from_arrays("p", [1.0], [0.0], [0.0], [0.0], [JTYPE_REVOLUTE])
    assert built.convention == "standard"
    np.testing.assert_array_equal([built.q_home, built.q_min, built.q_max, built.link_com_frac], [[0.0], [-np.inf], [np.inf], [0.5]])


def test_convention_is_read_from_the_file_and_from_arrays(tmp_path):
    rob = load_robot(robot_file(tmp_path, head=HEAD + 'convention = "modified"\n'))
    assert rob.convention == "modified" and rob.is_modified
    assert load_robot(robot_file(tmp_path, head=HEAD + 'convention = "standard"\n', name="s.toml")).convention == "standard"
    built = RobotParams.from_arrays("p", [1.0], [0.0], [0.0], [0.0], [JTYPE_REVOLUTE], convention="modified")
    assert built.is_modified
    with pytest.raises(ValueError, match="convention must be 'standard' or 'modified', got 'Modified'"):
        RobotParams.from_arrays("p", [1.0], [0.0], [0.0], [0.0], [JTYPE_REVOLUTE], convention="Modified")


# ------------------------------------------------------------------ bad files

BAD_FILES = {
    # id: (file pieces, expected message fragments after the path)
    "invalid toml": (dict(head='name = "x"\nunits = \n'), ["invalid TOML"]),
    "no joints": (dict(head=HEAD + "joints = []\n", joints=()), ["joints: no joints"]),
    "joints missing": (dict(joints=()), ["joints: missing required field"]),
    "name missing": (dict(head='units = "deg"\n'), ["name: missing required field"]),
    "units missing": (dict(head='name = "x"\n'), ["units: missing required field"]),
    "empty name": (dict(head='name = " "\nunits = "deg"\n'), ["name: expected a non-empty string"]),
    "unknown units": (dict(head='name = "x"\nunits = "grad"\n'), ["units: unknown units 'grad'; accepted: 'deg' or 'rad'"]),
    "joints not tables": (dict(head=HEAD + "joints = [1, 2]\n", joints=()), ["joints[0]: expected a table, got 1"]),
    "unknown joint type": (
        dict(joints=(JOINT.replace("revolute", "helical"),)),
        ["joints[0].type: unknown joint type 'helical'; accepted: 'revolute' or 'prismatic'"],
    ),
    "missing joint type": (dict(joints=(JOINT.replace('type = "revolute"\n', ""),)), ["joints[0].type: unknown joint type None"]),
    "missing DH d": (dict(joints=(JOINT.replace("d = 0.1\n", ""),)), ["joints[0].d: missing DH value"]),
    "missing DH theta in 2nd joint": (dict(joints=(JOINT, JOINT.replace("theta = 0.0\n", ""))), ["joints[1].theta: missing DH value"]),
    "string DH value": (dict(joints=(JOINT.replace("a = 0.5", 'a = "0.5"'),)), ["joints[0].a: expected a number, got '0.5'"]),
    "bool DH value": (dict(joints=(JOINT.replace("d = 0.1", "d = true"),)), ["joints[0].d: expected a number, got True"]),
    "list DH value": (dict(joints=(JOINT.replace("alpha = 90.0", "alpha = [90.0]"),)), ["joints[0].alpha: expected a number, got [90.0]"]),
    "nan DH value": (dict(joints=(JOINT.replace("alpha = 90.0", "alpha = nan"),)), ["joints[0].alpha: expected a finite number, got nan"]),
    "inf DH value": (dict(joints=(JOINT.replace("d = 0.1", "d = inf"),)), ["joints[0].d: expected a finite number, got inf"]),
    "-inf DH value": (dict(joints=(JOINT, JOINT.replace("theta = 0.0", "theta = -inf"))), ["joints[1].theta: expected a finite number, got -inf"]),
    "short xyz": (dict(tables="[base]\nxyz = [0.0, 0.0]\n"), ["base.xyz: expected a list of 3 numbers, got [0.0, 0.0]"]),
    "long rpy": (dict(tables="[tool]\nrpy = [0.0, 0.0, 0.0, 0.0]\n"), ["tool.rpy: expected a list of 3 numbers"]),
    "scalar xyz": (dict(tables="[tool]\nxyz = 1.0\n"), ["tool.xyz: expected a list of 3 numbers, got 1.0"]),
    "nan in xyz": (dict(tables="[base]\nxyz = [0.0, nan, 0.0]\n"), ["base.xyz[1]: expected a finite number, got nan"]),
    "base not a table": (dict(head=HEAD + "base = 3\n"), ["base: expected a table with keys xyz and rpy, got 3"]),
    "limits min > max": (dict(joints=(JOINT + "limits = [10.0, -10.0]\n",)), ["joints[0].limits: min 10.0 > max -10.0"]),
    "limits wrong length": (dict(joints=(JOINT + "limits = [10.0]\n",)), ["joints[0].limits: expected a list of 2 numbers, got [10.0]"]),
    "limits non-finite": (dict(joints=(JOINT + "limits = [-inf, 10.0]\n",)), ["joints[0].limits[0]: expected a finite number, got -inf"]),
    "home above limits": (
        dict(joints=(JOINT + "home = 20.0\nlimits = [-10.0, 10.0]\n",)),
        ["joints[0].home: home 20.0 is outside the limits [-10.0, 10.0]"],
    ),
    "default home below limits": (
        dict(joints=(JOINT, JOINT.replace("revolute", "prismatic") + "limits = [0.2, 0.5]\n")),
        ["joints[1].home: home 0.0 is outside the limits [0.2, 0.5]"],
    ),
    "home not a number": (dict(joints=(JOINT + 'home = "up"\n',)), ["joints[0].home: expected a number, got 'up'"]),
    "com above 1": (dict(joints=(JOINT + "com = 1.5\n",)), ["joints[0].com: com fraction 1.5 is outside [0, 1]"]),
    "com below 0": (dict(joints=(JOINT + "com = -0.1\n",)), ["joints[0].com: com fraction -0.1 is outside [0, 1]"]),
    "typo in joint": (
        dict(joints=(JOINT.replace("alpha", "alpah"),)),
        ["joints[0].alpah: unknown key 'alpah'; accepted keys: a, alpha, collision, com, d, drive, home, inertial, limits, theta, type, visual"],
    ),
    "typo at top level": (
        dict(head=HEAD + 'descripton = "x"\n'),
        ["descripton: unknown key 'descripton'; accepted keys: balance_inertia, base, collision, control, convention, description, joints, name, tool, units"],
    ),
    "unknown convention": (
        dict(head=HEAD + 'convention = "craig"\n'),
        ["convention: unknown convention 'craig'; accepted: 'standard' or 'modified'"],
    ),
    "convention not a string": (
        dict(head=HEAD + "convention = 1\n"),
        ["convention: unknown convention 1; accepted: 'standard' or 'modified'"],
    ),
    "typo in base": (dict(tables="[base]\nxzy = [0.0, 0.0, 0.0]\n"), ["base.xzy: unknown key 'xzy'; accepted keys: collision, rpy, visual, xyz"]),
    "typo in tool": (dict(tables="[tool]\nrpy = [0.0, 0.0, 0.0]\nroll = 1.0\n"), ["tool.roll: unknown key 'roll'; accepted keys: rpy, xyz"]),
    "description not a string": (dict(head=HEAD + "description = 5\n"), ["description: expected a string, got 5"]),
}


@pytest.mark.parametrize("pieces, fragments", BAD_FILES.values(), ids=BAD_FILES.keys())
def test_bad_robot_file_raises_naming_file_and_field(tmp_path, pieces, fragments):
    path = robot_file(tmp_path, **pieces)
    with pytest.raises(RobotDefinitionError) as info:
        load_robot(path)
    message = str(info.value)
    assert isinstance(info.value, ValueError)
    assert message.startswith(f"{path}: "), message
    for fragment in fragments:
        assert fragment in message, message


def test_missing_file(tmp_path):
    path = tmp_path / "nope.toml"
    with pytest.raises(RobotDefinitionError, match="robot file not found") as info:
        load_robot(path)
    assert str(info.value).startswith(f"{path}: ")
    with pytest.raises(RobotDefinitionError, match="robot file not found"):
        load_robot(str(tmp_path / "sub" / "nope"))  # a path without the suffix


def test_unknown_robot_name_lists_available_robots():
    with pytest.raises(RobotDefinitionError) as info:
        load_robot("pumma560")
    message = str(info.value)
    assert message.startswith("unknown robot 'pumma560': no such file and no shipped robot of that name; accepted: ")
    assert message.endswith(", ".join(available_robots()))


def test_a_good_file_after_bad_ones_still_loads(tmp_path):
    """Validation keeps no state between loads."""
    with pytest.raises(RobotDefinitionError):
        load_robot(robot_file(tmp_path, joints=(JOINT + "com = 2.0\n",), name="bad.toml"))
    rob = load_robot(robot_file(tmp_path, name="good.toml"))
    assert rob.n_dofs == 1 and rob.dh_alpha[0] == pytest.approx(math.pi / 2)


# ------------------------------------------------------------------ RobotState


def _snapshot(state: RobotState):
    return [getattr(js, f).copy() for js in (state.joint_state, state.joint_state_des) for f in ("th", "thd", "d", "dd")]


@pytest.mark.parametrize("name", ROBOT_NAMES)
def test_state_starts_at_home_and_round_trips(name):
    rob = robot(name)
    state = RobotState(rob)
    np.testing.assert_allclose(state.q(), rob.q_home, atol=1e-15)
    np.testing.assert_allclose(state.q_des(), rob.q_home, atol=1e-15)
    np.testing.assert_array_equal(state.qd(), np.zeros(rob.n_dofs))
    rng = np.random.default_rng(5)
    q = rng.uniform(-1.0, 1.0, rob.n_dofs)
    state.set_q(q)
    np.testing.assert_allclose(state.q(), q, atol=1e-15)
    np.testing.assert_allclose(state.q_des(), rob.q_home, atol=1e-15)  # desired untouched
    q_des = rng.uniform(-1.0, 1.0, rob.n_dofs)
    state.set_q_des(q_des)
    np.testing.assert_allclose(state.q_des(), q_des, atol=1e-15)
    np.testing.assert_allclose(state.q(), q, atol=1e-15)
    # θ and d hold the full DH values: offsets plus the joint variable of each joint type
    rev = rob.is_revolute
    for js, qq in ((state.joint_state, q), (state.joint_state_des, q_des)):
        np.testing.assert_allclose(js.th, np.where(rev, rob.dh_th + qq, rob.dh_th), atol=1e-15)
        np.testing.assert_allclose(js.d, np.where(rev, rob.dh_d, rob.dh_d + qq), atol=1e-15)


def test_stanford_prismatic_joint_keeps_its_theta_offset():
    rob = robot("stanford")
    state = RobotState(rob)
    js = state.joint_state
    assert js.th[2] == pytest.approx(-math.pi / 2)
    assert js.d[2] == pytest.approx(0.5)  # dh_d = 0 plus home 0.5
    assert js.d[0] == pytest.approx(0.412) and js.th[0] == pytest.approx(0.0)
    assert js.th[1] == pytest.approx(60 * DEG) and js.d[1] == pytest.approx(0.154)
    state.set_q([0.1, -0.2, 0.9, 0.3, 0.4, -0.5])
    assert js.th[2] == pytest.approx(-math.pi / 2)
    assert js.d[2] == pytest.approx(0.9)
    np.testing.assert_allclose(js.th[[0, 1, 3, 4, 5]], [0.1, -0.2, 0.3, 0.4, -0.5])
    np.testing.assert_allclose(js.d, [0.412, 0.154, 0.9, 0.0, 0.0, 0.263])
    assert state.q()[2] == pytest.approx(0.9)


def test_joint_velocities_go_to_the_right_field():
    rob = robot("scara")  # revolute, revolute, prismatic, revolute
    state = RobotState(rob)
    qd = [0.1, -0.2, 0.3, 0.4]
    state.set_qd(qd)
    np.testing.assert_allclose(state.qd(), qd)
    np.testing.assert_allclose(state.joint_state.thd, [0.1, -0.2, 0.0, 0.4])
    np.testing.assert_allclose(state.joint_state.dd, [0.0, 0.0, 0.3, 0.0])
    np.testing.assert_array_equal(state.joint_state_des.thd, np.zeros(4))


BAD_VECTORS = {
    "too short": [0.0, 0.0],
    "too long": [0.0] * 5,
    "nan": [0.0, np.nan, 0.0, 0.0],
    "inf": [0.0, 0.0, np.inf, 0.0],
    "-inf": [-np.inf, 0.0, 0.0, 0.0],
    "2-D": [[0.0] * 4, [0.0] * 4],
    "scalar": 0.0,
}


@pytest.mark.parametrize("setter", ["set_q", "set_q_des", "set_qd"])
@pytest.mark.parametrize("values", BAD_VECTORS.values(), ids=BAD_VECTORS.keys())
def test_bad_joint_vectors_raise_and_change_nothing(setter, values):
    state = RobotState(robot("scara"))
    state.set_qd([0.5, 0.5, 0.5, 0.5])
    before = _snapshot(state)
    what = setter.removeprefix("set_")
    with pytest.raises(ValueError, match=what):
        getattr(state, setter)(values)
    for old, new in zip(before, _snapshot(state)):
        np.testing.assert_array_equal(old, new)


def test_joint_state_copy_is_independent():
    state = RobotState(robot("planar3"))
    copy = state.joint_state.copy()
    state.set_q([1.0, 2.0, 3.0])
    np.testing.assert_allclose(copy.th, robot("planar3").q_home)
    np.testing.assert_allclose(state.joint_state.th, [1.0, 2.0, 3.0])
