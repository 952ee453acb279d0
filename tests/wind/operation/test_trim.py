"""Trim of the operating turbine: residual zero, the controller's steady laws, region logic in closed form.

References (independent of the trim's own residual Function):
- residual: the composed model's right-hand side evaluated through :meth:`mbsym.Dynamics.rhs_value` at the
  trimmed state (every row but the rotor azimuth's within 1e-8 in its unit, m/s, m/s², rad/s², N m/s, ...;
  Newton stops at a relative step of 1e-10);
- the controller's laws checked by hand: TSR tracking on the wind estimate, the estimate balancing the
  generator torque on the controller's own Cp table (scipy's bilinear RegularGridInterpolator on the
  DISCON.IN table, not CasADi), rated speed and power in region 3, the peak-shaving minimum pitch
  (numpy.interp on PS_WindSpeeds/PS_BldPitchMin);
- a toy rotor whose torque coefficient is a quadratic ``cq = c0 − a (λ − λ0)² − b β²``: regions 2, 2.5
  and 3 in closed form (rotor speed, pitch holding rated power), the optimal λ of ``cp = λ cq`` from
  its cubic (k·ω² control settles exactly there), the estimator's bias with a table 5 % low (a scalar
  equation solved by brentq). The rotor's spline reproduces the quadratic to 6e-6 (measured), hence
  the 1e-4 tolerances.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from mbsym.exceptions import ParameterError
from mbsym.wind.operation import SteadyControl, Trimmer

RPM = 30.0 / math.pi


@pytest.fixture(scope="module")
def nrel_trimmer(operating):
    return Trimmer(operating, SteadyControl.nrel5mw())


@pytest.fixture(scope="module")
def nrel_points(nrel_trimmer):
    return {p.wind_speed: p for p in nrel_trimmer.sweep([6.0, 10.0, 11.4, 18.0])}


# ---------------------------------------------------------------------------------------------- residual
def test_trim_residual_is_zero(nrel_trimmer, nrel_points):
    dyn = nrel_trimmer.dyn
    for U, point in nrel_points.items():
        assert point.success, point.message
        rhs = dyn.rhs_value(point.state, point.inputs, dict(point.parameters))
        for name, value in zip(dyn.states, rhs):
            if name == "GeAz":       # the azimuth turns at the rotor speed
                assert value == pytest.approx(point["RotSpeed"] / RPM, rel=1e-12)
            else:
                assert abs(value) <= 1e-8, (U, name, value)
        assert np.allclose(point.rhs, rhs, rtol=0, atol=1e-12)


def test_nrel5mw_controller_laws_hold(nrel_trimmer, nrel_points):
    from scipy.interpolate import RegularGridInterpolator

    c = nrel_trimmer.control
    cp = RegularGridInterpolator((np.array(c.cp_tsr), np.array(c.cp_pitch)), np.array(c.cp))
    for U, p in nrel_points.items():
        omega = p["RotSpeed"] / RPM
        beta_c = p.u()["BlPitchCom"]
        torque = p.u()["GenTqCom"]
        est = p.wind_estimate
        # the estimator's torque balance on its own table (ROSCO's EKF at rest)
        lam = omega * c.rotor_radius / est
        q_est = 0.5 * c.air_density * math.pi * c.rotor_radius**2 * est**3 / omega * float(cp([lam, beta_c])[0])
        assert q_est == pytest.approx(c.gearbox_ratio * torque, rel=1e-9)
        min_pitch = max(float(np.interp(est, c.min_pitch_wind_speeds, c.min_pitch_schedule)), c.fine_pitch)
        assert p.min_pitch == pytest.approx(min_pitch, abs=1e-12)
        if p.region == "3":
            assert p["GenSpeed"] / RPM == pytest.approx(c.pitch_reference_speed, rel=1e-9)
            assert p["GenPwr"] == pytest.approx(c.rated_power / 1e3, rel=1e-9)
            assert beta_c > min_pitch
        else:                      # torque holds the TSR reference, pitch at its minimum
            ref = min(c.optimal_tsr * est / c.rotor_radius * c.gearbox_ratio, c.rated_generator_speed)
            assert p["GenSpeed"] / RPM == pytest.approx(ref, rel=1e-9)
            assert beta_c == pytest.approx(min_pitch, abs=1e-12)
    assert nrel_points[6.0].region == "2" and not nrel_points[6.0].peak_shaving
    assert nrel_points[11.4].region == "2.5" and nrel_points[11.4].peak_shaving
    assert nrel_points[18.0].region == "3"
    # ROSCO's table is below the rotor's Cp: its estimate is high, so region 2 runs above VS_TSRopt
    assert nrel_points[6.0].wind_estimate > 6.0 * 1.005


def test_trim_rejects_bad_input(operating):
    with pytest.raises(TypeError, match="OperatingTurbine"):
        Trimmer(object())
    with pytest.raises(TypeError, match="SteadyControl"):
        Trimmer(operating, control="DISCON.IN")
    with pytest.raises(ParameterError, match="n_azimuth"):
        Trimmer(operating, n_azimuth=0)
    with pytest.raises(ParameterError, match="tol"):
        Trimmer(operating, tol=1.0)
    trimmer = Trimmer(operating)
    for bad in (0.0, -3.0, float("nan"), "8"):
        with pytest.raises(ParameterError, match="wind_speed"):
            trimmer.solve(bad)


# ---------------------------------------------------------------------------------------------- toy rotor
C0, A, L0, B = 0.07, 0.0015, 7.0, 0.3          # cq = C0 − A (λ − L0)² − B β²
RADIUS, TILT, RHO = 63.0, math.radians(-5.0), 1.225


def cq(lam, beta=0.0):
    return C0 - A * (lam - L0) ** 2 - B * beta**2


def optimal_tsr() -> float:
    """Maximum of cp = λ cq(λ, 0): root of −3Aλ² + 4A L0 λ + C0 − A L0² = 0."""
    a, b, c = -3 * A, 4 * A * L0, C0 - A * L0**2
    return (-b - math.sqrt(b * b - 4 * a * c)) / (2 * a)


@pytest.fixture(scope="module")
def toy_model():
    from mbsym.wind import nrel5mw
    from mbsym.wind.aero.rotor import RotorAero
    from mbsym.wind.deck.performance import PerformanceTable
    from mbsym.wind.operation import ActuatorSettings, OperatingTurbine

    lam = np.arange(2.0, 14.01, 0.5)
    beta = np.radians(np.arange(-5.0, 30.01, 1.0))
    L, Bt = np.meshgrid(lam, beta, indexing="ij")
    table = PerformanceTable(tsr=lam, pitch=beta, cp=L * cq(L, Bt), ct=0.9 - 0.01 * (L - L0) ** 2 - 0.5 * Bt,
                             cq=cq(L, Bt), source="toy quadratic")
    rotor = RotorAero(table, RADIUS, air_density=RHO, shaft_tilt=TILT)
    actuators = ActuatorSettings.nrel5mw().replace(pitch_min=-0.2)     # fine pitch 0 inside the actuator's range
    model = OperatingTurbine(nrel5mw(), rotor, dofs=["GenDOF"], dynamic_inflow=False, actuators=actuators)
    model.dynamics()
    return model, table


def toy_control(model, **changes) -> SteadyControl:
    eta = model.dynamics().defaults["generator_efficiency"]        # the controller's VS_GenEff = the plant's
    values = dict(torque_mode=2, constant_power=True, rated_power=3.0e6, generator_efficiency=eta,
                  gearbox_ratio=model.gearbox_ratio, rated_generator_speed=110.0, pitch_reference_speed=110.0,
                  min_generator_speed=10.0, optimal_tsr=optimal_tsr(), rotor_radius=RADIUS, torque_max=1e6,
                  torque_min=0.0, fine_pitch=0.0, pitch_max=1.5, wind_estimator=0)
    values.update(changes)
    return SteadyControl(**values)


def _power(U, omega, beta, eta):
    us = U * math.cos(TILT)
    torque = 0.5 * RHO * math.pi * RADIUS**3 * us**2 * cq(omega * RADIUS / us, beta)
    return eta * torque * omega


def test_regions_2_25_3_in_closed_form(toy_model):
    model, _ = toy_model
    c = toy_control(model)
    n, lam = model.gearbox_ratio, optimal_tsr()
    w_rated = c.rated_generator_speed / n
    u_25 = w_rated * RADIUS / lam                         # end of region 2: TSR tracking reaches rated speed
    points = Trimmer(model, c).sweep([0.8 * u_25, 1.03 * u_25, 15.0])
    p2, p25, p3 = points
    assert [p.region for p in points] == ["2", "2.5", "3"], [p.message for p in points]
    # region 2: Ω = λ* U / R, pitch at fine pitch, power from the quadratic
    U = p2.wind_speed
    omega = lam * U / RADIUS
    assert p2["RotSpeed"] / RPM == pytest.approx(omega, rel=1e-9)
    assert p2["BldPitch1"] == pytest.approx(0.0, abs=1e-9)
    assert p2["GenPwr"] * 1e3 == pytest.approx(_power(U, omega, 0.0, c.generator_efficiency), rel=1e-4)
    # region 2.5: rated speed, fine pitch, power below rated
    assert p25["RotSpeed"] / RPM == pytest.approx(w_rated, rel=1e-9)
    assert p25["GenPwr"] * 1e3 == pytest.approx(_power(p25.wind_speed, w_rated, 0.0, c.generator_efficiency), rel=1e-4)
    assert p25["GenPwr"] * 1e3 < c.rated_power
    # region 3: rated speed and power, pitch from cq(λ, β) = the torque that gives rated power
    us = 15.0 * math.cos(TILT)
    q_needed = c.rated_power / c.generator_efficiency / w_rated
    cq_needed = q_needed / (0.5 * RHO * math.pi * RADIUS**3 * us**2)
    beta = math.sqrt((cq(w_rated * RADIUS / us) - cq_needed) / B)
    assert p3["RotSpeed"] / RPM == pytest.approx(w_rated, rel=1e-9)
    assert p3["GenPwr"] * 1e3 == pytest.approx(c.rated_power, rel=1e-9)
    assert math.radians(p3["BldPitch1"]) == pytest.approx(beta, rel=1e-4)


def test_k_omega_squared_settles_at_the_optimal_tsr(toy_model):
    model, _ = toy_model
    lam = optimal_tsr()
    n = model.gearbox_ratio
    cp_max = lam * cq(lam)
    k = 0.5 * RHO * math.pi * RADIUS**5 * cp_max / (lam**3 * n**3)      # ROSCO's VS_Rgn2K (no losses)
    c = toy_control(model, torque_mode=1, region2_gain=k, region25_torque_max=2e4, min_generator_speed=10.0)
    point = Trimmer(model, c).solve(6.0)
    assert point.success and point.region == "2", point.message
    us = 6.0 * math.cos(TILT)
    assert point["RotSpeed"] / RPM * RADIUS / us == pytest.approx(lam, rel=1e-4)
    assert point["GenTq"] * 1e3 == pytest.approx(k * (point["GenSpeed"] / RPM) ** 2, rel=1e-9)
    # the optimum is a maximum of cp: neighbours are lower
    assert lam * cq(lam) > max((lam - 0.1) * cq(lam - 0.1), (lam + 0.1) * cq(lam + 0.1))


def test_peak_shaving_minimum_pitch_on_the_estimate(toy_model):
    model, _ = toy_model
    c = toy_control(model, peak_shaving=True, min_pitch_wind_speeds=(3.0, 30.0), min_pitch_schedule=(0.0, 0.27))
    point = Trimmer(model, c).solve(6.0)
    assert point.success and point.peak_shaving, point.message
    beta = 0.01 * (6.0 - 3.0)
    omega = c.optimal_tsr * 6.0 / RADIUS
    assert math.radians(point["BldPitch1"]) == pytest.approx(beta, abs=1e-9)
    assert point["GenPwr"] * 1e3 == pytest.approx(_power(6.0, omega, beta, c.generator_efficiency), rel=1e-4)


def test_estimator_bias_from_a_low_cp_table(toy_model):
    from scipy.optimize import brentq

    model, table = toy_model
    scale = 0.95
    c = toy_control(model, optimal_tsr=7.0, wind_estimator=2, air_density=RHO, cp_tsr=table.tsr,
                    cp_pitch=table.pitch, cp=scale * table.cp)
    point = Trimmer(model, c).solve(6.0)
    assert point.success and point.region == "2", point.message
    # at rest: ½ρπR²Û³ cp_table(7)/Ω = Q_rotor with Ω = 7 Û/R, i.e. 0.95 r² cq(7) = cq(7 r), r = Û / U_shaft
    us = 6.0 * math.cos(TILT)
    r = brentq(lambda r: scale * r * r * cq(7.0) - cq(7.0 * r), 1.0, 1.5)
    assert point.wind_estimate == pytest.approx(r * us, rel=1e-4)
    assert point["RotSpeed"] / RPM == pytest.approx(7.0 * r * us / RADIUS, rel=1e-4)


def test_free_yaw_without_spring_is_reported_not_solved():
    """A yaw bearing without spring has no equilibrium under the rotor's reaction torque: held, and reported."""
    import warnings

    from mbsym.wind.operation import OperatingTurbine

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)         # "YawDOF gets no aerodynamic load"
        model = OperatingTurbine.nrel5mw(dofs=["GenDOF", "YawDOF"], dynamic_inflow=False)
    trimmer = Trimmer(model)
    assert [model.structure.eom.coordinates[k] for k in trimmer.held] == ["Yaw"]
    point = trimmer.solve(8.0)
    assert not point.success and "Yaw has no stiffness" in point.message
    assert point.x()["Yaw"] == model.dynamics().x0[model.dynamics().states.index("Yaw")]
