"""dh_table: the DH dock's cells, typed edits in display units, refusals with the reason."""
from __future__ import annotations

import math

import numpy as np
import pytest

from robot_sim.viewer.dh_table import COLUMNS, carry_joint_values, cell_text, edit_cell, is_editable
from kin_helpers import robot
from robot_sim.model.params import JTYPE_PRISMATIC
from robot_sim.io.robot_writer import with_dh_value

DEG = math.pi / 180.0


def test_puma_rows_show_current_theta_and_constants():
    puma = robot("puma560")
    q = np.array([10.0, 20.0, -30.0, 0.0, 0.0, 0.0]) * DEG
    assert [cell_text(puma, q, 0, c) for c in COLUMNS] == [
        "revolute", "10.00 (q1)", "0.67183", "0", "90", "0°", "-160 .. 160°", "0°",
    ]
    assert cell_text(puma, q, 1, "home") == "45°"


def test_stanford_prismatic_row_shows_current_d_and_its_offset_in_metres():
    stanford = robot("stanford")
    assert stanford.jtype[2] == JTYPE_PRISMATIC
    q = np.array(stanford.q_home)
    q[2] = 0.25
    d = stanford.dh_d[2] + 0.25
    assert cell_text(stanford, q, 2, "d") == f"{d:.4f} (q3)"
    assert cell_text(stanford, q, 2, "offset") == f"{stanford.dh_d[2]:.10g} m"
    assert not is_editable(stanford, 2, "d") and is_editable(stanford, 2, "theta")
    assert not is_editable(stanford, 0, "theta") and is_editable(stanford, 0, "d")


@pytest.mark.parametrize(
    "row, column, text, field, value",
    [
        (1, "a", "0.5", "a", 0.5),
        (0, "d", " 0.7 m", "d", 0.7),
        (2, "alpha", "-45°", "alpha", -45 * DEG),
        (1, "offset", "15", "theta", 15 * DEG),
        (1, "home", "30 deg", "home", 30 * DEG),
        (1, "limits", "-50 .. 230", "limits", (-50 * DEG, 230 * DEG)),
        (0, "limits", "unlimited", "limits", None),
        (3, "type", "P", "type", "prismatic"),
    ],
)
def test_typed_cells_equal_the_same_edit_through_with_dh_value(row, column, text, field, value):
    puma = robot("puma560")
    by_cell = edit_cell(puma, row, column, text)
    direct = with_dh_value(puma, row, field, value)
    for name in ("dh_a", "dh_alpha", "dh_d", "dh_th", "jtype", "q_home", "q_min", "q_max"):
        assert np.array_equal(getattr(by_cell, name), getattr(direct, name)), name


def test_prismatic_offset_edits_d_in_metres():
    stanford = robot("stanford")
    edited = edit_cell(stanford, 2, "offset", "0.2")
    assert edited.dh_d[2] == 0.2 and np.array_equal(edited.dh_th, stanford.dh_th)


@pytest.mark.parametrize(
    "row, column, text, message",
    [
        (0, "a", "abc", "joint 1 a: 'abc' is not a number"),
        (0, "a", "inf", "joint 1 a: 'inf' is not a finite number"),
        (0, "theta", "10", "joint 1 θ: it is the joint variable: move it with the slider or type it in the joint box"),
        (1, "limits", "100 .. 50", "joint 2 limits: min 100.0 > max 50.0"),
        (1, "limits", "1 2 3", "joint 2 limits: expected 'min .. max' or 'unlimited', got '1 2 3'"),
        (1, "limits", "50 .. 60", "joint 2 limits: home 45.0 is outside the limits [50.0, 60.0]"),
        (1, "home", "300", "joint 2 home: home 300.0 is outside the limits [-45.0, 225.0]"),
        (2, "alpha", "", "joint 3 α: '' is not a number"),
        (0, "type", "ball", "joint 1 type: expected 'revolute' (R) or 'prismatic' (P), got 'ball'"),
    ],
)
def test_invalid_cells_are_refused_with_the_reason(row, column, text, message):
    with pytest.raises(ValueError) as info:
        edit_cell(robot("puma560"), row, column, text)
    assert str(info.value) == message


def test_joint_values_are_kept_clipped_or_reset():
    puma = robot("puma560")
    q = np.array([150.0, 20.0, -30.0, 0.0, 0.0, 0.0]) * DEG
    narrower = with_dh_value(puma, 0, "limits", (-90 * DEG, 90 * DEG))
    np.testing.assert_array_equal(carry_joint_values(puma, q, narrower), np.r_[90 * DEG, q[1:]])
    retyped = with_dh_value(puma, 1, "type", "prismatic")
    kept = carry_joint_values(puma, q, retyped)
    assert kept[1] == 0.0 and np.array_equal(np.delete(kept, 1), np.delete(q, 1))
    three = robot("anthropomorphic")
    np.testing.assert_array_equal(carry_joint_values(puma, q, three), three.q_home)
