"""Property tests over robot files (hypothesis): shipped files with a field replaced by a
value of any TOML type (nested arrays and tables, huge integers, NaN, dates), with extra
tables, or with raw bytes inserted.  Every outcome is a robot whose forward kinematics is
finite everywhere inside its limits, or a RobotDefinitionError that starts with the path."""
from __future__ import annotations

import datetime
import json
import re
import tempfile
from pathlib import Path

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from robot_sim.kinematics import forward_kinematics
from robot_sim.model.params import JTYPE_REVOLUTE, RobotDefinitionError, RobotParams
from robot_sim.io.robot_file import MAX_LENGTH, ROBOTS_DIR, load_robot

SHIPPED = sorted(ROBOTS_DIR.glob("*.toml"))
FUZZ = settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])

# ------------------------------------------------------------------ TOML values as text

_bare_keys = st.from_regex(r"[A-Za-z_][A-Za-z0-9_-]{0,8}", fullmatch=True)
_scalars = st.one_of(
    st.integers(min_value=-(10**30), max_value=10**30).map(str),
    st.sampled_from(["1" + "0" * 400, "-" + "9" * 330, "0", "-0", "1_000"]),
    st.floats(allow_nan=True, allow_infinity=True).map(
        lambda f: "nan" if f != f else ("inf" if f == float("inf") else ("-inf" if f == float("-inf") else repr(f)))
    ),
    st.sampled_from(["1e308", "-1e308", "1e-320", "5e-324", "1e400"]),
    st.booleans().map(lambda b: "true" if b else "false"),
    st.text(max_size=20).map(json.dumps),
    st.sampled_from(['"revolute"', '"prismatic"', '"deg"', '"rad"', '"standard"', '"modified"', '""']),
    st.datetimes(min_value=datetime.datetime(1900, 1, 1)).map(lambda d: d.isoformat()),
    st.dates().map(lambda d: d.isoformat()),
)
toml_values = st.recursive(
    _scalars,
    lambda inner: st.one_of(
        st.lists(inner, max_size=4).map(lambda xs: "[" + ", ".join(xs) + "]"),
        st.dictionaries(_bare_keys, inner, max_size=3).map(
            lambda d: "{ " + ", ".join(f"{k} = {v}" for k, v in d.items()) + " }"
        ),
    ),
    max_leaves=8,
)

_ASSIGNMENT = re.compile(r"^(\s*[A-Za-z_][A-Za-z0-9_]*\s*=\s*)(.*)$", re.M)


def check_outcome(path: Path) -> None:
    """The property: a valid robot with finite kinematics over its limits, or one
    RobotDefinitionError starting with the path."""
    try:
        robot = load_robot(path)
    except RobotDefinitionError as exc:
        assert str(exc).startswith(f"{path}: "), str(exc)
        return
    assert_finite_over_limits(robot)


def assert_finite_over_limits(robot: RobotParams) -> None:
    """Forward kinematics (every frame) finite at home, at the corners of the limits and
    at random in-limit configurations (unlimited joints: ±π, or ±MAX_LENGTH if prismatic)."""
    revolute = robot.jtype == JTYPE_REVOLUTE
    reach = np.where(revolute, np.pi, MAX_LENGTH)
    lo = np.where(np.isfinite(robot.q_min), robot.q_min, -reach)
    hi = np.where(np.isfinite(robot.q_max), robot.q_max, reach)
    rng = np.random.default_rng(0)
    Q = np.vstack([robot.q_home, lo, hi, lo + (hi - lo) * rng.random((16, robot.n_dofs))])
    frames = forward_kinematics(robot, Q, all_frames=True)
    assert np.isfinite(frames).all(), robot.name


def fuzz_file(content: bytes) -> None:
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "fuzzed.toml"
        path.write_bytes(content)
        check_outcome(path)


# ------------------------------------------------------------------ properties


@FUZZ
@given(source=st.sampled_from(SHIPPED), data=st.data(), value=toml_values)
def test_a_field_replaced_by_any_toml_value(source: Path, data: st.DataObject, value: str) -> None:
    text = source.read_text(encoding="utf-8")
    fields = list(_ASSIGNMENT.finditer(text))
    field = data.draw(st.sampled_from(fields))
    mutated = text[: field.start(2)] + value + text[field.end(2) :]
    fuzz_file(mutated.encode("utf-8"))


@FUZZ
@given(
    source=st.sampled_from(SHIPPED),
    data=st.data(),
    header=st.sampled_from(["[joints.extra]", "[base.sub]", "[tool]", "[control]", "[[joints]]", "[x.y.z]",
                            "[joints.inertial]", "[joints.drive]", "[[base]]"]),
    body=st.dictionaries(_bare_keys, toml_values, max_size=3),
)
def test_an_extra_table_anywhere(source: Path, data: st.DataObject, header: str, body: dict[str, str]) -> None:
    lines = source.read_text(encoding="utf-8").splitlines(keepends=True)
    at = data.draw(st.integers(0, len(lines)))
    table = header + "\n" + "".join(f"{k} = {v}\n" for k, v in body.items())
    fuzz_file(("".join(lines[:at]) + "\n" + table + "".join(lines[at:])).encode("utf-8"))


@FUZZ
@given(source=st.sampled_from(SHIPPED), data=st.data(), inserted=st.binary(min_size=1, max_size=8))
def test_raw_bytes_inserted(source: Path, data: st.DataObject, inserted: bytes) -> None:
    raw = source.read_bytes()
    at = data.draw(st.integers(0, len(raw)))
    fuzz_file(raw[:at] + inserted + raw[at:])


@FUZZ
@given(source=st.sampled_from(SHIPPED), data=st.data(), scale=st.sampled_from([1e3, 1e6, 1e9, 1e300, -1e300]))
def test_lengths_scaled_beyond_the_bounds(source: Path, data: st.DataObject, scale: float) -> None:
    """Every number of one field multiplied: sizes beyond the bounds are refused, never
    loaded with infinite kinematics."""
    text = source.read_text(encoding="utf-8")
    numbers = list(re.finditer(r"(?<![\w.])-?\d+\.\d+(?:[eE][-+]?\d+)?", text))
    number = data.draw(st.sampled_from(numbers))
    mutated = text[: number.start()] + repr(float(number.group()) * scale) + text[number.end() :]
    fuzz_file(mutated.encode("utf-8"))


def test_every_shipped_robot_is_finite_over_its_limits() -> None:
    for source in SHIPPED:
        assert_finite_over_limits(load_robot(source))
