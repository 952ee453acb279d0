"""Rotor loads from the surfaces: definitions, power balance, damping sign, OpenFAST.

References: the definitions T = ½ρπR²U²ct, Q = ½ρπR³U²cq evaluated with an independent
interpolant (scipy); the power identity P = Ω Q; the steady OpenFAST v5 + AeroDyn 15 runs
of the NREL 5 MW (``shared/openfast/aero/steady_states.csv``: RtAeroFxh, RtAeroMxh,
RtAeroPwr at RtVAvgxh, RotSpeed, BldPitch1).
"""

from __future__ import annotations

import csv
import math

import casadi as ca
import numpy as np
import pytest
from scipy.interpolate import RectBivariateSpline

from mbsym.exceptions import ParameterError
from mbsym.wind.aero import RotorAero, nrel5mw_rotor

from .conftest import AERO, ROSCO_TABLE, need


@pytest.fixture(scope="module")
def rotor() -> RotorAero:
    return nrel5mw_rotor()


def symbols():
    return tuple(ca.SX.sym(n) for n in ("u", "omega", "pitch", "rho"))


def test_loads_follow_the_definitions(rotor):
    u_rel, omega, pitch, rho = 9.3, 1.02, 0.031, 1.18
    out = rotor.steady(u_rel, omega, pitch, rho)
    # the documented smooth floor of U (u_min = 0.01 m/s; 1e-6 relative at 9.3 m/s)
    u = 0.5 * (u_rel + math.sqrt(u_rel**2 + 4 * rotor.u_min**2))
    assert abs(u / u_rel - 1) < 2e-6
    tsr = omega * rotor.radius / u
    table = rotor.table
    ct = RectBivariateSpline(table.tsr, table.pitch, table.ct, s=0).ev(tsr, pitch)
    cq = RectBivariateSpline(table.tsr, table.pitch, table.cq, s=0).ev(tsr, pitch)
    q_area = 0.5 * rho * math.pi * rotor.radius**2 * u**2
    assert out["thrust"] == pytest.approx(q_area * ct, rel=1e-12)
    assert out["torque"] == pytest.approx(q_area * rotor.radius * cq, rel=1e-12)
    assert out["tsr"] == pytest.approx(tsr, rel=1e-14)
    assert out["power"] == pytest.approx(omega * out["torque"], rel=1e-14)  # P = Omega Q
    assert out["cp"] == pytest.approx(tsr * cq, rel=1e-12)


def test_scale_factors_scale_torque_power_and_thrust(rotor):
    u, omega, pitch, rho = symbols()
    s_cp, s_ct = ca.SX.sym("s_cp"), ca.SX.sym("s_ct")
    out = rotor.loads(u, omega, pitch, rho, cp_scale=s_cp, ct_scale=s_ct)
    f = ca.Function("f", [u, omega, pitch, rho, s_cp, s_ct],
                    [out["torque"], out["power"], out["thrust"]])
    base = [float(v) for v in f(11.0, 1.2, 0.05, 1.225, 1.0, 1.0)]
    scaled = [float(v) for v in f(11.0, 1.2, 0.05, 1.225, 0.97, 1.04)]
    assert scaled[0] == pytest.approx(0.97 * base[0], rel=1e-14)
    assert scaled[1] == pytest.approx(0.97 * base[1], rel=1e-14)
    assert scaled[2] == pytest.approx(1.04 * base[2], rel=1e-14)


@pytest.fixture(scope="module")
def openfast_states() -> list[dict[str, float]]:
    with open(need(AERO / "steady_states.csv"), newline="") as f:
        return [{k: float(v) for k, v in row.items()} for row in csv.DictReader(f)]


def test_builtin_rotor_reproduces_openfast_aero_loads(rotor, openfast_states):
    # The packaged surfaces (nominal 5 deg skew) through the spline, at OpenFAST's own wind
    # along the shaft (RtVAvgxh), rotor speed and pitch: thrust, torque and power within 1 %
    # of AeroDyn's RtAeroFxh, RtAeroMxh, RtAeroPwr at all 17 steady states.
    for s in openfast_states:
        out = rotor.steady(s["RtVAvgxh_[m/s]"], s["RotSpeed_[rpm]"] * math.pi / 30,
                           math.radians(s["BldPitch1_[deg]"]))
        label = s["WindSpeed_[m/s]"]
        assert abs(out["thrust"] / s["RtAeroFxh_[N]"] - 1) < 0.01, label
        assert abs(out["torque"] / s["RtAeroMxh_[N-m]"] - 1) < 0.01, label
        assert abs(out["power"] / s["RtAeroPwr_[W]"] - 1) < 0.01, label


def test_aerodynamic_damping_sign(rotor, openfast_states):
    # Tower moving downwind lowers U_rel, hence thrust: dT/dU_rel > 0 at every operating point
    # (positive aerodynamic damping of tower fore-aft motion); and torque rises with wind.
    u, omega, pitch, rho = symbols()
    out = rotor.loads(u, omega, pitch, rho)
    f = ca.Function("f", [u, omega, pitch, rho], [ca.jacobian(out["thrust"], u),
                                                  ca.jacobian(out["torque"], u)])
    for s in openfast_states:
        d_thrust, d_torque = f(s["RtVAvgxh_[m/s]"], s["RotSpeed_[rpm]"] * math.pi / 30,
                               math.radians(s["BldPitch1_[deg]"]), 1.225)
        assert float(d_thrust) > 0 and float(d_torque) > 0, s["WindSpeed_[m/s]"]


def test_no_wind_and_reverse_flow_stay_finite(rotor):
    u, omega, pitch, rho = symbols()
    out = rotor.loads(u, omega, pitch, rho)
    f = ca.Function("f", [u, omega, pitch, rho],
                    [out["thrust"], out["torque"], ca.gradient(out["torque"], ca.vertcat(u, omega))])
    for u0 in (0.0, -2.0, 1e-6):
        values = [np.array(v) for v in f(u0, 1.0, 0.0, 1.225)]
        assert all(np.all(np.isfinite(v)) for v in values)
    thrust_idle = float(f(0.0, 0.0, 0.0, 1.225)[0])
    assert abs(thrust_idle) < 1.0  # no wind, no rotation: (almost) no load [N]


def test_inflow_lag_rhs(rotor):
    u, omega, pitch, rho = symbols()
    state = ca.SX.sym("x", 2)
    rhs, out = rotor.inflow_lag_rhs(state, u, omega, pitch, rho)
    f = ca.Function("f", [state, u, omega, pitch, rho],
                    [rhs, out["thrust"], out["torque"], out["time_constant"]])
    rhs0, thrust, torque, tau = f([0.0, 0.0], 10.0, 1.2, 0.0, 1.225)
    assert float(tau) == pytest.approx(1.1 * rotor.radius / 10.0, rel=1e-6)
    np.testing.assert_allclose(np.array(rhs0).ravel(),
                               [float(thrust) / float(tau), float(torque) / float(tau)], rtol=1e-12)
    at_rest = f([float(thrust), float(torque)], 10.0, 1.2, 0.0, 1.225)[0]
    np.testing.assert_allclose(np.array(at_rest).ravel(), 0.0, atol=1e-9)


def test_rosco_table_radius_convention():
    # A rotor built from ROSCO's table (normalized with the 63 m blade length) gives the
    # table's Cp at the table's own TSR definition.
    from mbsym.wind.deck.performance import read_performance_table

    table = read_performance_table(need(ROSCO_TABLE))
    rotor = RotorAero(table, radius=63.0)
    i, j = 11, 5  # TSR 7.5, pitch 0
    omega = table.tsr[i] * 10.0 / 63.0
    out = rotor.steady(10.0, omega, table.pitch[j])
    assert abs(out["cp"] - table.cp[i, j]) < 1e-3  # cq in ROSCO's file is cp/tsr to 1e-3


def test_bad_arguments(rotor):
    with pytest.raises(ParameterError, match="radius must be a positive"):
        RotorAero(rotor.table, radius=-1.0)
    with pytest.raises(ParameterError, match="air_density"):
        RotorAero(rotor.table, radius=63.0, air_density=0.0)
    with pytest.raises(ParameterError, match="shaft_tilt"):
        RotorAero(rotor.table, radius=63.0, shaft_tilt=3.0)
    with pytest.raises(TypeError, match="PerformanceTable"):
        RotorAero("table", radius=63.0)  # type: ignore[arg-type]
    with pytest.raises(TypeError):
        rotor.loads(1.0, 1.0, 0.0, density=1.2)  # type: ignore[call-arg]


def test_tower_oscillation_decays_faster_with_wind(rotor):
    # A 1-DOF tower-top oscillator (NREL 5 MW order of magnitude: 4.4e5 kg modal mass,
    # 0.32 Hz, 1 % structural damping) carrying the rotor thrust T(U - x') at 12 m/s
    # (12.1 rpm, pitch 3.9 deg), compared with the structure alone:
    #     m x'' + c_s x' + k x = T(U - x') - T(U).
    # Reference: linearization, zeta = zeta_s + (dT/dU) / (2 m w_n); the measured logarithmic
    # decrement must match it within 3 % and exceed the no-wind decay.
    m, f_n, zeta_s = 4.4e5, 0.32, 0.01
    w_n = 2 * math.pi * f_n
    k, c_s = m * w_n**2, 2 * zeta_s * m * w_n
    omega, pitch = 12.1 * math.pi / 30, math.radians(3.9)
    x, v = ca.SX.sym("x"), ca.SX.sym("v")
    wind, aero = ca.SX.sym("U"), ca.SX.sym("aero")  # aero = 0: the structure alone
    thrust = rotor.loads(wind - v, omega, pitch)["thrust"]
    thrust0 = rotor.loads(wind, omega, pitch)["thrust"]
    ode = {"x": ca.vertcat(x, v), "p": ca.vertcat(wind, aero),
           "ode": ca.vertcat(v, (aero * (thrust - thrust0) - c_s * v - k * x) / m)}
    times = np.linspace(0, 30, 3001)
    sim = ca.integrator("tower", "cvodes", ode, 0.0, times, {"abstol": 1e-10, "reltol": 1e-10})
    dT_dU = float(ca.Function("d", [wind], [ca.jacobian(thrust0, wind)])(11.95))
    decay = {}
    for aero_on in (0.0, 1.0):
        xs = np.array(sim(x0=[0.05, 0.0], p=[11.95, aero_on])["xf"])[0]
        peaks = xs[1:-1][(xs[1:-1] > xs[:-2]) & (xs[1:-1] > xs[2:])]
        delta = np.log(peaks[0] / peaks[-1]) / (len(peaks) - 1)
        decay[aero_on] = delta / math.sqrt(4 * math.pi**2 + delta**2)  # zeta from the decrement
    predicted = zeta_s + dT_dU / (2 * m * w_n)
    assert decay[1.0] > decay[0.0] + 0.02  # aerodynamic damping: several per cent
    assert abs(decay[1.0] / predicted - 1) < 0.03
    assert abs(decay[0.0] / zeta_s - 1) < 0.03


def test_rotor_from_openfast_deck_matches_the_builtin_rotor(rotor):
    # Same BEM, same AeroDyn data, same ElastoDyn geometry: identical surface values at
    # common grid nodes, whatever the grid. The smooth wind floor moves the TSR 1e-6 off the
    # node, where the two splines (different grids) differ slightly: tolerance 1e-6.
    fst = need(AERO / "openfast_inputs" / "steady_12" / "steady_12.fst")
    small = RotorAero.from_openfast(fst, tsr=np.arange(5.0, 9.01, 0.5),
                                    pitch=np.radians(np.arange(-2.0, 6.01, 1.0)))
    assert small.radius == pytest.approx(rotor.radius, rel=1e-12)
    assert small.air_density == 1.225 and small.shaft_tilt == rotor.shaft_tilt
    for tsr, pitch_deg in ((7.5, 0.0), (6.0, 3.0), (8.5, -2.0)):
        omega = tsr * 10.0 / rotor.radius
        a = small.steady(10.0, omega, math.radians(pitch_deg))
        b = rotor.steady(10.0, omega, math.radians(pitch_deg))
        assert a["thrust"] == pytest.approx(b["thrust"], rel=1e-6)
        assert a["torque"] == pytest.approx(b["torque"], rel=1e-6)
