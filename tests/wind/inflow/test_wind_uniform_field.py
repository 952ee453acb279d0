"""Steady and uniform-file wind over space (UniformFieldWind, uniform_velocity_expr) against InflowWind.

References: hand-computed values of InflowWind's uniform-field formula (one column at a time), OpenFAST
v5.0.0 runs with 9 output points (``ifw_reference.py``: a uniform file with every column non-zero and
changing, with PropagationDir and VFlowAng; steady wind with a power law and PropagationDir), the shared
yawed steady case's Wind1VelX/Y, finite differences for the SX derivatives.
"""

from __future__ import annotations

import math

import casadi as ca
import numpy as np
import pytest

from mbsym.exceptions import WindFieldDomainError, WindInputError
from mbsym.wind.inflow import (POWER_LAW_MIN_HEIGHT, UniformFieldWind, UniformWind, read_uniform_wind,
                               uniform_velocity_expr)

from .conftest import need
from .ifw_reference import CASES, UNIFORM_ROWS, read_reference

DEG = math.pi / 180.0


def _one_row(**columns):
    return UniformFieldWind(UniformWind([0.0], **{"speed": [10.0], **{k: [v] for k, v in columns.items()}}), 90.0, 126.0)


@pytest.mark.parametrize("columns, point, expected", [
    ({}, (5.0, 7.0, 90.0), (10.0, 0.0, 0.0)),
    ({"power_law_exponent": 0.2}, (0.0, 0.0, 45.0), (10.0 * 0.5 ** 0.2, 0.0, 0.0)),
    ({"horizontal_shear": 0.3}, (0.0, 21.0, 90.0), (10.0 * (1 + 0.3 * 21.0 / 126.0), 0.0, 0.0)),
    ({"linear_vertical_shear": 0.4}, (0.0, 0.0, 120.0), (10.0 * (1 + 0.4 * 30.0 / 126.0), 0.0, 0.0)),
    ({"gust_speed": 2.0}, (0.0, 0.0, 60.0), (12.0, 0.0, 0.0)),
    ({"vertical_speed": 1.5}, (0.0, 0.0, 90.0), (10.0, 0.0, 1.5)),
    ({"direction": 30 * DEG}, (0.0, 0.0, 90.0), (10.0 * math.cos(30 * DEG), -10.0 * math.sin(30 * DEG), 0.0)),
    ({"upflow": 5 * DEG}, (0.0, 0.0, 90.0), (10.0 * math.cos(5 * DEG), 0.0, 10.0 * math.sin(5 * DEG))),
    # horizontal shear acts across the wind: y cos(δ) + x sin(δ)
    ({"horizontal_shear": 0.3, "direction": 90 * DEG}, (12.6, 0.0, 90.0), (0.0, -10.0 * 1.03, 0.0)),
])
def test_hand_computed_values(columns, point, expected):
    v = _one_row(**columns).velocity(0.0, point)
    assert np.allclose(v, expected, atol=1e-12)


@pytest.mark.parametrize("case", ["uniform", "steady_shear"])
def test_points_against_openfast(case, tmp_path):
    """9 points per case written by OpenFAST v5 (9 significant digits)."""
    spec = CASES[case]
    angles = dict(propagation_direction=spec["PropagationDir"] * DEG, upflow_angle=spec["VFlowAng"] * DEG)
    if case == "uniform":
        (tmp_path / "u.hh").write_text(UNIFORM_ROWS)
        field = UniformFieldWind(read_uniform_wind(tmp_path / "u.hh"), 90.0, spec["RefLength"], **angles)
    else:
        field = UniformFieldWind.steady(spec["HWindSpeed"], reference_height=90.0, power_law_exponent=spec["PLexp"],
                                        **angles)
    t, ref = read_reference(case)
    v = field.velocity(t, np.array(spec["points"]))
    assert np.abs(v - ref).max() <= 2e-6 * max(1.0, np.abs(ref).max() / 10)


def test_yawed_steady_case_of_the_shared_runs(aero):
    """ss14_yaw10_flex: PropagationDir 10 deg, Wind1VelX/Y at the hub (CSV, 7 digits)."""
    data = np.genfromtxt(need(aero / "ss14_yaw10_flex.csv"), delimiter=",", names=True, max_rows=3, usecols=(0, 1, 2, 3))
    field = UniformFieldWind.steady(14.0, reference_height=90.0, power_law_exponent=0.2,
                                    propagation_direction=10 * DEG)
    v = field.velocity(data["Time_s"], [0.0, 0.0, 90.0])
    assert np.allclose(v[:, 0], data["Wind1VelX_ms"], atol=1e-5) and np.allclose(v[:, 1], data["Wind1VelY_ms"],
                                                                                 atol=1e-5)


def test_casadi_expression_equals_numpy_with_the_instantaneous_columns(tmp_path):
    (tmp_path / "u.hh").write_text(UNIFORM_ROWS)
    field = UniformFieldWind(read_uniform_wind(tmp_path / "u.hh"), 90.0, 125.0, propagation_direction=7 * DEG,
                             upflow_angle=2 * DEG)
    pts = np.array(CASES["uniform"]["points"])
    symbols = {k: ca.SX.sym(k) for k in field.columns_at(0.0)}
    p = ca.SX.sym("p", 3, pts.shape[0])
    expr = uniform_velocity_expr(symbols, p, ref_height=90.0, ref_length=125.0, propagation_direction=7 * DEG,
                                 upflow_angle=2 * DEG)
    f = ca.Function("uniform_test", [*symbols.values(), p], [expr])
    for t in (-1.0, 0.4, 1.5, 2.75, 9.0):               # includes both held ends
        cols = field.columns_at(t)
        assert np.abs(np.array(f(*cols.values(), pts.T)).T - field.velocity(t, pts)).max() < 1e-12


def test_derivatives_match_finite_differences():
    """∂uvw/∂(speed, shears) of the SX expression against central differences (step 1e-6, tol 1e-7)."""
    keys = ("speed", "horizontal_shear", "linear_vertical_shear", "power_law_exponent", "direction")
    x = ca.SX.sym("x", len(keys))
    pts = ca.DM([[3.0, -20.0], [15.0, 33.0], [70.0, 130.0]])
    expr = uniform_velocity_expr(dict(zip(keys, ca.vertsplit(x))), pts, ref_height=90.0, ref_length=126.0)
    f = ca.Function("f", [x], [ca.vec(expr)])
    jac = ca.Function("j", [x], [ca.jacobian(ca.vec(expr), x)])
    x0 = np.array([11.0, 0.1, 0.2, 0.14, 0.05])
    fd = np.column_stack([(np.array(f(x0 + h)) - np.array(f(x0 - h))).ravel() / 2e-6 for h in np.eye(5) * 1e-6])
    assert np.abs(np.array(jac(x0)) - fd).max() < 1e-7


def test_power_law_guard_and_ground():
    field = UniformFieldWind.steady(10.0, reference_height=90.0, power_law_exponent=0.2)
    with pytest.raises(WindFieldDomainError, match="at or below the ground"):
        field.velocity(0.0, [[0.0, 0.0, 50.0], [0.0, 0.0, -1.0]])
    assert np.array_equal(field.velocity(0.0, [0.0, 0.0, 0.0], below_ground="zero"), np.zeros(3))  # InflowWind
    e = uniform_velocity_expr({"speed": 10.0, "power_law_exponent": 0.2}, ca.DM([[0.0], [0.0], [-5.0]]),
                              ref_height=90.0, ref_length=1.0)
    held = 10.0 * (POWER_LAW_MIN_HEIGHT / 90.0) ** 0.2               # documented guard: height held at 1 mm
    assert float(ca.evalf(e)[0]) == pytest.approx(held, rel=1e-12)


def test_columns_at_holds_the_ends_and_unwraps_the_direction():
    table = UniformWind([0.0, 10.0], [10.0, 12.0], direction=[170 * DEG, -170 * DEG])
    field = UniformFieldWind(table, 90.0, 100.0)
    assert field.columns_at(-5.0)["speed"] == 10.0 and field.columns_at(50.0)["speed"] == 12.0
    # InflowWind brings -170 deg within 180 deg of 170 deg (190 deg): halfway is 180 deg, not 0
    assert field.columns_at(5.0)["direction"] == pytest.approx(math.pi)


def test_bad_arguments():
    with pytest.raises(WindInputError, match="unknown column"):
        uniform_velocity_expr({"sped": 1.0}, ca.DM([0, 0, 90.0]), ref_height=90.0, ref_length=1.0)
    with pytest.raises(WindInputError, match="reference_length must be positive"):
        UniformFieldWind(UniformWind([0.0], [1.0]), 90.0, 0.0)
    with pytest.raises(WindInputError, match="below_ground"):
        UniformFieldWind.steady(1.0, reference_height=90.0).velocity(0.0, [0, 0, 90.0], below_ground="nan")
