"""Wind signals: exact step and ramp, the IEC 61400-1 extreme operating gust, tables, CasADi, simulate.

References: closed forms written out here (step, ramp, the EOG formula of IEC 61400-1 ed. 3 Eq. 17-18
with its Table 1 constants, computed by hand below) and exact integrals of piecewise-linear signals.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import mbsym as mb
from mbsym.exceptions import WindInputError
from mbsym.wind.inflow import (ExtremeOperatingGust, RampWind, SteadyWind, StepWind, TabulatedWind,
                               iec_gust_speed)


def test_step_is_exact_on_both_sides_and_tabulates_with_a_tiny_rise():
    w = StepWind(10.0, 14.0, 30.0)
    t = np.array([0.0, 29.999999, 30.0, 30.5, 90.0])
    assert np.array_equal(w(t), [10.0, 10.0, 14.0, 14.0, 14.0])        # exact: U1 from T on
    grid, values = w.table(60.0)
    assert grid.tolist() == [0.0, 30.0, 30.0 + 1e-6, 60.0]
    assert values.tolist() == [10.0, 10.0, 14.0, 14.0]
    assert w(31.0) == 14.0 and isinstance(w(31.0), float)


def test_ramp_is_linear_between_its_ends_and_constant_outside():
    w = RampWind(10.0, 14.0, 30.0, 30.1)
    t = np.array([0.0, 30.0, 30.025, 30.05, 30.1, 50.0])
    expected = np.array([10.0, 10.0, 11.0, 12.0, 14.0, 14.0])             # 4 m/s over 0.1 s
    assert np.allclose(w(t), expected, rtol=0, atol=1e-12)
    # its table is exact: the trapezoid integral equals the closed form 30*10 + 0.1*12 + 29.9*14
    grid, values = w.table(60.0)
    assert np.trapezoid(values, grid) == pytest.approx(300.0 + 1.2 + 418.6, rel=1e-14)


def test_eog_matches_the_iec_formula_written_out_by_hand():
    # IEC 61400-1 ed.3: class I (V_ref = 50 m/s), category A (I_ref = 0.16), D = 126 m, z_hub = 90 m, V_hub = 25 m/s
    sigma1 = 0.16 * (0.75 * 25.0 + 5.6)                   # 3.896 m/s
    v_e1 = 0.8 * 1.4 * 50.0                                # 56 m/s
    v_gust = min(1.35 * (v_e1 - 25.0), 3.3 * sigma1 / (1.0 + 0.1 * 126.0 / 42.0))   # Lambda_1 = 42 m
    assert v_gust == pytest.approx(9.889846153846, rel=1e-12)
    assert iec_gust_speed(25.0, rotor_diameter=126.0, hub_height=90.0, turbine_class="I",
                          turbulence_category="A") == pytest.approx(v_gust, rel=1e-14)
    gust = ExtremeOperatingGust(25.0, start=5.0, rotor_diameter=126.0, hub_height=90.0, turbine_class="I",
                                turbulence_category="A")
    t = np.linspace(0.0, 20.0, 4001)
    tau = (t - 5.0) / 10.5
    reference = np.where((tau >= 0) & (tau <= 1),
                         25.0 - 0.37 * v_gust * np.sin(3 * np.pi * tau) * (1 - np.cos(2 * np.pi * tau)), 25.0)
    assert np.max(np.abs(gust(t) - reference)) < 1e-12
    # shape properties: continuous at both ends, mean over the gust = V_hub + 0.37 V_gust 8/(15 pi)
    assert gust(5.0) == pytest.approx(25.0, abs=1e-12) and gust(15.5) == pytest.approx(25.0, abs=1e-12)
    grid, values = gust.table(20.0, dt=0.001)
    inside = (grid >= 5.0) & (grid <= 15.5)
    mean = np.trapezoid(values[inside], grid[inside]) / 10.5
    assert mean == pytest.approx(25.0 + 0.37 * v_gust * 8.0 / (15.0 * math.pi), abs=1e-6)


def test_hub_height_below_60m_uses_lambda_0p7_z():
    sigma1 = 0.14 * (0.75 * 10.0 + 5.6)
    expected = min(1.35 * (0.8 * 1.4 * 42.5 - 10.0), 3.3 * sigma1 / (1.0 + 0.1 * 40.0 / (0.7 * 50.0)))
    assert iec_gust_speed(10.0, rotor_diameter=40.0, hub_height=50.0, turbine_class="II",
                          turbulence_category="B") == pytest.approx(expected, rel=1e-14)


@pytest.mark.parametrize("wind", [SteadyWind(8.0), StepWind(10.0, 14.0, 3.0), StepWind(10, 14, 3, rise=0.5),
                                  RampWind(5.0, 9.0, 1.0, 4.0), ExtremeOperatingGust(12.0, start=1.0, gust_speed=6.0),
                                  TabulatedWind([0.0, 2.0, 5.0], [7.0, 9.0, 8.0])])
def test_casadi_function_equals_numpy(wind):
    f = wind.to_casadi()
    t = np.linspace(-1.0, 15.0, 321)
    assert np.max(np.abs(np.asarray(f(t.reshape(1, -1))).ravel() - wind(t))) < 1e-12


def test_tabulated_wind_holds_its_ends_like_inflowwind():
    w = TabulatedWind([10.0, 20.0], [5.0, 7.0])
    assert w(np.array([0.0, 15.0, 99.0])).tolist() == [5.0, 6.0, 7.0]


def test_signals_drive_mbsym_simulate_as_callables_and_as_tables():
    # a unit mass pushed by a force equal to the wind: qd(60) = integral of U = 30*10 + 30*14 = 720
    system = mb.System(gravity=[0.0, 0.0, 0.0])
    q = system.coordinates("q")
    force = system.inputs("U")
    body = mb.RigidBody("b", mass=1.0, com=[0.0, 0.0, 0.0], inertia=np.eye(3))
    system.add_joint(mb.Prismatic(system.ground, body, axis=[1, 0, 0], coordinate=q))
    system.add_generalized_force(q, force)
    eom = system.equations()
    wind = StepWind(10.0, 14.0, 30.0)
    table = mb.simulate(eom, 60.0, x0=[0.0, 0.0], inputs={"U": wind.table(60.0)}, method="cvodes",
                        rtol=1e-10, atol=1e-10)
    assert table.x[-1, 1] == pytest.approx(720.0, abs=1e-4)            # knots stop the integrator
    callable_ = mb.simulate(eom, 60.0, x0=[0.0, 0.0], inputs={"U": wind}, method="rk4", dt=0.01)
    assert callable_.x[-1, 1] == pytest.approx(720.0, abs=4.0 * 0.01 + 1e-9)   # the jump falls inside one step


@pytest.mark.parametrize("make, match", [
    (lambda: SteadyWind(-1.0), "at least 0"),
    (lambda: SteadyWind(float("nan")), "finite"),
    (lambda: SteadyWind("12"), "must be a number"),
    (lambda: RampWind(10, 12, 5.0, 5.0), "must end after it starts"),
    (lambda: StepWind(10, 12, 3.0, rise=-1.0), "at least 0"),
    (lambda: ExtremeOperatingGust(12.0), "gust_speed or both"),
    (lambda: iec_gust_speed(12.0, rotor_diameter=126, hub_height=90, turbine_class="IV"), "turbine_class"),
    (lambda: TabulatedWind([0.0, 1.0, 1.0], [5, 6, 7]), "strictly increase"),
    (lambda: TabulatedWind([0.0, 1.0], [5.0]), "same length"),
    (lambda: SteadyWind(8.0).table(-1.0), "greater than 0"),
])
def test_bad_parameters_raise_wind_input_errors(make, match):
    with pytest.raises(WindInputError, match=match):
        make()
