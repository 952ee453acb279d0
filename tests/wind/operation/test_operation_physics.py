"""Physics of the operating turbine: power balance, aerodynamic damping, tower-base moments.

References (independent of the composition under test):
- power balance: the power of the loads computed from the hub's kinematics (thrust × hub velocity
  along the shaft + torque × hub angular velocity about it, minus the generator's N T_gen q̇_GeAz, plus
  the structural damping) equals the equations' own non-conservative power (relative 1e-10), and the
  rate of the structure's kinetic + potential energy (differentiated along the composed right-hand side)
  within 1e-6 (ElastoDyn's slope-rate tower-top kinematics are not exactly conservative, ~1e-7 here);
- aerodynamic damping: the fore-aft tower mode's damping ratio from the eigenvalues of the exact
  Jacobian with wind is larger than without air; its increase matches the quasi-steady prediction
  Δζ = (∂T/∂U) φ² / (2 √(K M)) (φ: hub velocity along the shaft per unit fore-aft speed, K, M the
  fore-aft stiffness and mass) within 10 % (coupling with the rotor speed is left out of the
  prediction); a simulated free decay's logarithmic decrement confirms the eigenvalue (5 %);
- tower-base moments: rigid tower, steady rotation: TwrBsMyt = thrust (z_a c₁ₓ − x_a c₁_z) + g Σ m x,
  TwrBsMxt = Q c₁ₓ from the deck's geometry and masses (hand calculation, relative 1e-9); the sign
  convention is OpenFAST's (a downwind thrust gives a positive TwrBsMyt; checked against OpenFAST's
  steady states in benchmarks/operation_validation.py: within 0.5 %).
"""

from __future__ import annotations

import math

import casadi as ca
import numpy as np
import pytest

from mbsym.wind.operation.steady import steady_guess


def _graph(model):
    return model._part("graph")


def test_power_balance_along_a_simulated_trajectory(operating):
    from mbsym.wind.inflow import StepWind
    from mbsym.wind.operation.simulation import simulate_turbine

    model, dyn = operating, operating.dynamics()
    g = _graph(model)
    eom = model.structure.eom
    f = eom.functions
    energy = f.kinetic_energy(g.q, g.qd, g.u_s, g.p_s) + f.potential_energy(g.q, g.u_s, g.p_s)
    de_dt = ca.jtimes(energy, g.x, g.xd)            # inputs constant at the sampled states
    hub = g.kinematics_with_accelerations("hub")
    p_aero = g.thrust * ca.dot(hub["v"], g.shaft_axis) + g.torque * ca.dot(hub["w"], g.shaft_axis)
    shaft = g.kinematics_with_accelerations("shaft")          # + the disk's moment across the shaft (RotMomY/Z)
    p_aero += sum(g.loads.get(n, 0.0) * ca.dot(shaft["w"], shaft["R"][:, i]) for i, n in ((1, "RotMomY"),
                                                                                         (2, "RotMomZ")))
    p_gen = g.X["GenTq"] * model.gearbox_ratio * g.qd[eom.coordinates.index("GeAz")]
    loads_off = ca.substitute(g.structural_inputs(thrust=0.0, torque=0.0), g.X["GenTq"], 0.0)
    p_damp = f.power(g.q, g.qd, loads_off, g.p_s)
    p_engine = f.power(g.q, g.qd, g.u_s, g.p_s)      # the equations' own power of every non-conservative load
    check = ca.Function("check", [g.x, g.u, g.p], [de_dt, p_aero, p_gen, p_damp, p_engine])
    # a wind step with held commands (pitch 2 deg inside its limits, so the pitch actuator stays at rest)
    wind = StepWind(10.0, 13.0, 2.0)
    x0 = model.initial_state(10.0, pitch=math.radians(2.0))
    res = simulate_turbine(model, wind, 12.0, x0=x0, t_out=np.linspace(0.0, 12.0, 121))
    p = dyn.parameter_vector()
    eta = p[dyn.parameters.index("generator_efficiency")]
    loads, balance, scale = 0.0, 0.0, 0.0
    for k in np.flatnonzero(res.t > 2.5)[::5]:
        dE, Pa, Pg, Pd, Pe = (float(v) for v in check(res.x[k], res.u[k], p))
        gen_pwr = res.output("GenPwr")[k] * 1e3               # electrical power [W]
        assert gen_pwr == pytest.approx(eta * Pg, rel=1e-12)
        # the loads the composition applies do the work computed from the hub's kinematics (exact)
        loads = max(loads, abs(Pe - (Pa - Pg + Pd)))
        # aero power = generator power + generator losses + damping losses + d/dt (kinetic + potential)
        balance = max(balance, abs(Pa - (gen_pwr + (1 - eta) * Pg - Pd + dE)))
        scale = max(scale, abs(Pa))
    assert scale > 3e6                                         # MW flow through the rotor
    assert loads < 1e-10 * scale, (loads, scale)
    # ElastoDyn's tower-top kinematics (slope-rate angular velocity, docs/elastodyn_notes.md) are not exactly
    # conservative: T + V drifts at O(θ² θ̇) relative, here ~1e-7 of the power flow
    assert balance < 1e-6 * scale, (balance, scale)


def test_rotor_power_channel_is_torque_times_rotor_speed(operating):
    dyn = operating.dynamics()
    guess = steady_guess(operating, 9.0)
    y = dict(zip(dyn.output_names, dyn.output_value(guess.state, [9.0, guess.pitch, guess.torque])))
    assert y["RtAeroPwr"] == pytest.approx(y["RtAeroMxh"] * y["RotSpeed"] * math.pi / 30, rel=1e-12)
    assert y["RotPwr"] == pytest.approx(y["RotTorq"] * y["RotSpeed"] * math.pi / 30, rel=1e-12)
    assert y["GenPwr"] == pytest.approx(0.944 * y["GenTq"] * y["GenSpeed"] * math.pi / 30, rel=1e-12)


def _fore_aft_mode(model, x, u, p):
    """(damping ratio, natural frequency [rad/s]) of the eigenvalue pair dominated by TFA1."""
    dyn = model.dynamics()
    X = ca.SX.sym("x", dyn.n_x)
    A = np.asarray(ca.Function("A", [X], [ca.jacobian(dyn.rhs(X, u, p), X)])(x), dtype=float)
    w, V = np.linalg.eig(A)
    i = dyn.states.index("TFA1")
    cands = [k for k in range(w.size) if w[k].imag > 0.5]
    k = max(cands, key=lambda j: abs(V[i, j]) / np.linalg.norm(V[:, j]))
    return -w[k].real / abs(w[k]), abs(w[k])


@pytest.mark.parametrize("disk_moments", [False, True])
def test_aerodynamic_damping_of_the_tower_fore_aft_mode(quasi_steady, disk_moments):
    from mbsym.wind.operation import OperatingTurbine

    model = OperatingTurbine.nrel5mw(dynamic_inflow=False, disk_moments=True) if disk_moments else quasi_steady
    dyn = model.dynamics()
    guess = steady_guess(model, 14.0)
    u = np.array([14.0, guess.pitch, guess.torque])
    p = dyn.parameter_vector()
    p_still = dyn.parameter_vector({"air_density": 0.0})
    zeta_wind, omega = _fore_aft_mode(model, guess.state, u, p)
    zeta_still, omega_still = _fore_aft_mode(model, guess.state, u, p_still)
    assert zeta_wind > zeta_still + 0.01                      # aerodynamic damping: several % of critical
    # quasi-steady prediction from the rotor's thrust slope and the hub's velocity along the shaft
    g = _graph(model)
    eom = model.structure.eom
    i = eom.coordinates.index("TFA1")
    hub = g._kinematics("hub", g.u_s)
    phi = float(ca.Function("phi", [g.x, g.u, g.p], [ca.jacobian(ca.dot(hub["v"], g.shaft_axis), g.qd)[i]])(
        guess.state, u, p))
    y = dict(zip(dyn.output_names, dyn.output_value(guess.state, u)))
    rotor = model.rotor
    h = 1e-3
    omega_r = y["RotSpeed"] * math.pi / 30
    dT = (float(rotor.steady(y["RtVAvgxh"] + h, omega_r, guess.pitch)["thrust"])
          - float(rotor.steady(y["RtVAvgxh"] - h, omega_r, guess.pitch)["thrust"])) / (2 * h)
    M = eom.mass_matrix(guess.state[:eom.n_q], u=np.asarray(ca.Function("us", [g.x, g.u, g.p], [g.u_s])(
        guess.state, u, p)).reshape(-1))[i, i]
    # + the disk's moment against the shaft's tilt rate psi per unit TFA1 velocity: K = 1/2 dT/dU <r^2>, <r^2>
    # the BEM's thrust-weighted one, else (R^2 + r_hub^2)/2 (compose._disk_moments; OpenFAST's K checks it in
    # tests/identify/test_rotor_loads.py)
    shaft = g._kinematics("shaft", g.u_s)
    tilt = ca.vertcat(ca.dot(shaft["w"], shaft["R"][:, 1]), ca.dot(shaft["w"], shaft["R"][:, 2]))
    psi = np.asarray(ca.Function("psi", [g.x, g.u, g.p], [ca.jacobian(tilt, g.qd)[:, i]])(guess.state, u, p))
    r2 = rotor.thrust_radius2(y["RtVAvgxh"], omega_r, guess.pitch)
    r2 = 0.5 * (rotor.radius ** 2 + model.turbine.hub_radius ** 2) if r2 is None else float(ca.evalf(r2))
    K = 0.5 * dT * r2 if model.structure.hub_moments else 0.0
    predicted = (dT * phi**2 + K * float(np.sum(psi**2))) / (2 * omega_still * M)
    assert zeta_wind - zeta_still == pytest.approx(predicted, rel=0.10)
    assert omega == pytest.approx(omega_still, rel=0.02)


def test_free_decay_confirms_the_eigenvalue_damping(quasi_steady):
    from mbsym.wind.operation.simulation import simulate_turbine

    model, dyn = quasi_steady, quasi_steady.dynamics()
    guess = steady_guess(model, 14.0)
    u = np.array([14.0, guess.pitch, guess.torque])
    zeta, omega = _fore_aft_mode(model, guess.state, u, dyn.parameter_vector())
    x0 = guess.state.copy()
    x0[dyn.states.index("TFA1")] += 0.1
    t = np.linspace(0.0, 15.0, 3001)
    res = simulate_turbine(model, 14.0, 15.0, x0=x0, t_out=t, method="rk4", dt=0.005)
    y = res.output("TTDspFA") - guess.state[dyn.states.index("TFA1")]
    peaks = [k for k in range(1, t.size - 1) if y[k] > y[k - 1] and y[k] >= y[k + 1] and y[k] > 0.01]
    decrement = np.log(y[peaks[0]] / y[peaks[2]]) / 2
    measured = decrement / math.sqrt(4 * math.pi**2 + decrement**2)
    assert measured == pytest.approx(zeta, rel=0.05)


def test_tower_base_moments_against_a_hand_calculation(rigid_tower):
    model, dyn = rigid_tower, rigid_tower.dynamics()
    t = model.turbine
    x = model.initial_state(12.0, rotor_speed=12.1 * math.pi / 30, pitch=math.radians(4.0))
    u = np.array([12.0, math.radians(4.0), x[dyn.states.index("GenTq")]])
    assert dyn.rhs_value(x, u)[dyn.states.index("GeAz_d")] == pytest.approx(0.0, abs=1e-10)   # steady rotation
    y = dict(zip(dyn.output_names, dyn.output_value(x, u)))
    tilt = t.shaft_tilt
    c1 = np.array([math.cos(tilt), 0.0, math.sin(tilt)])
    top = np.array([0.0, 0.0, t.tower_height - t.tower_base_height])
    apex = top + np.array([0.0, 0.0, t.twr2shft]) + t.overhang * c1
    blade = model.structure.blade_data(0)
    m_b = np.append(np.asarray(blade.element_mass), blade.tip_mass)
    z_b = np.append(np.asarray(blade.span), blade.length)
    blade_com = float(m_b @ z_b / m_b.sum())
    cone = t.precone[0]
    masses = [(t.nacelle_mass, top + np.asarray(t.nacelle_cm)), (t.yaw_bearing_mass, top),
              (t.hub_mass, apex + t.hub_cm * c1),
              (3 * m_b.sum(), apex + (t.hub_radius + blade_com) * math.sin(cone) * c1)]
    g = t.simulation.gravity
    thrust = y["RtAeroFxh"]
    my = thrust * (apex[2] * c1[0] - apex[0] * c1[2]) + g * sum(m * r[0] for m, r in masses)
    assert y["TwrBsMyt"] == pytest.approx(my / 1e3, rel=1e-9)
    assert y["TwrBsMxt"] == pytest.approx(y["RtAeroMxh"] * c1[0] / 1e3, rel=1e-9)
    # ElastoDyn's LSS axial force: thrust plus the rotor's weight along the tilted shaft (OpenFAST at 4 m/s:
    # RotThrust - RtAeroFxh = 94.3 kN, with the tower top's small forward slope; rigid tower here: 93.5 kN)
    rotor_mass = t.hub_mass + 3 * m_b.sum()
    assert y["RotThrust"] == pytest.approx((thrust + rotor_mass * g * -c1[2]) / 1e3, rel=1e-9)
    assert 93.0 < rotor_mass * g * -c1[2] / 1e3 < 94.3
