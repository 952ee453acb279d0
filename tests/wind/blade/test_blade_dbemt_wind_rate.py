"""AeroDyn v5's DBEMT (modes 1 and 2) leaves the wind's rate of ``Vx``, ``Vy`` out of Øye's rate term.

References:

* the ODE's closed form (``dw/dt`` gains exactly ``-k wind_rate``);
* the fundamental theorem of calculus for the wind's rate along a path: its integral over an interval equals
  the change of the wind between the path's ends, computed by the numpy field (:meth:`FullFieldWind.velocity`)
  or the numpy uniform wind, independently of the graph's rate;
* OpenFAST v5.0.0's own record of the shared ``ff14_rigid`` deck (TurbSim full field, the real ROSCO library):
  mbsym's aerodynamics on OpenFAST's structural motion, with the DBEMT states integrated along it, must give
  OpenFAST's rotor torque and thrust. Measured when written (10-30 s, 0.05 s steps): RtAeroMxh ε 0.21 % and
  RtAeroFxh 0.15 % with the wind's rate left out (AeroDyn's way, the default), 1.35 % and 1.07 % with Øye's
  filter on the whole rate.
"""

import dataclasses
import sys
from pathlib import Path

import casadi as ca
import numpy as np
import pytest

from mbsym.exceptions import ParameterError
from mbsym.wind.aero import nrel5mw_bem_rotor
from mbsym.wind.aero.blade import BladeElementRotor
from mbsym.wind.aero.blade.dbemt import OYE_K, derivatives

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "operation"))
from _op_data import AERO, INPUTS, need  # noqa: E402


def test_defaults_follow_aerodyn_and_bad_values_are_refused():
    bem = nrel5mw_bem_rotor()
    assert BladeElementRotor(bem, dbemt_mode=1, tau1_const=4.0).dbemt_wind_rate is False
    assert BladeElementRotor(bem, dbemt_mode=2).dbemt_wind_rate is False
    assert BladeElementRotor(bem, dbemt_mode=3, tau1_const=4.0).dbemt_wind_rate is True
    assert BladeElementRotor(bem, dbemt_mode=2, dbemt_wind_rate=True).options["dbemt_wind_rate"] is True
    with pytest.raises(ParameterError, match="dbemt_wind_rate"):
        BladeElementRotor(bem, dbemt_mode=2, dbemt_wind_rate="yes")


def test_wind_rate_enters_the_reduced_state_only():
    """dw/dt = ((1-k) v_s - w)/τ₁ - k r, dv/dt unchanged: exact (tolerance: rounding)."""
    rng = np.random.default_rng(1)
    n = 4
    x, v_s, r = rng.normal(size=4 * n), rng.normal(size=(n, 2)), rng.normal(size=(n, 2))
    ratio = rng.uniform(0.2, 1.0, (n, 1))
    plain = np.asarray(derivatives(ca.DM(x), ca.DM(v_s), 5.0, ratio)).reshape(n, 4)
    with_rate = np.asarray(derivatives(ca.DM(x), ca.DM(v_s), 5.0, ratio, wind_rate=ca.DM(r))).reshape(n, 4)
    np.testing.assert_allclose(with_rate[:, :2], plain[:, :2], rtol=0, atol=1e-14)
    np.testing.assert_allclose(with_rate[:, 2:], plain[:, 2:] - OYE_K * r, rtol=0, atol=1e-14)


def _path(t):
    """A point circling like a blade node (radius 40 m, 1.2 rad/s about a hub at 90 m) and drifting downwind."""
    c, s = np.cos(1.2 * t), np.sin(1.2 * t)
    return np.array([0.3 * t, 40.0 * s, 90.0 + 40.0 * c]), np.array([0.3, 48.0 * c, -48.0 * s])


def _line(t):
    """A point on a straight path across the rotor disk (y -20 → 40 m, z 100 → 60 m over 2 s)."""
    v = np.array([0.3, 30.0, -20.0])
    return np.array([0.0, -20.0, 100.0]) + v * (t - 100.0), v


def _integrated_rate(wind, t0, t1, inputs, n=4000, path=_path):
    """∫ path_rate dt over [t0, t1] (trapezoids on n intervals) from the graph."""
    p, v = ca.SX.sym("p", 3), ca.SX.sym("v", 3)
    syms = {name: ca.SX.sym(name) for name in wind.inputs}
    f = ca.Function("rate", [p, v, *syms.values()], [wind.path_rate(p, v, syms)])
    ts = np.linspace(t0, t1, n + 1)
    rates = np.array([np.asarray(f(*path(t), *[inputs(t)[k] for k in syms])).ravel() for t in ts])
    return np.sum(0.5 * (rates[1:] + rates[:-1]) * np.diff(ts)[:, None], axis=0)


def test_field_path_rate_of_a_linear_field_is_its_derivative_along_the_path():
    """A field linear in time, height and lateral position (within its grid): the rate of the wind seen by a
    moving point is exactly ∂W/∂t (1 - ẋ/URef, Taylor's advection) + ∂W/∂y ẏ + ∂W/∂z ż, which for a linear field
    equals the numpy field's change along the straight path over a whole second. Tolerance 1e-4 m/s²: the
    float32 storage of the grid (1e-7 of 20 m/s over the 50 ms difference)."""
    from mbsym.wind.inflow import FullFieldWind
    from mbsym.wind.operation.wind_inputs import FieldWindInputs

    n_t, n_z, n_y, dt, dy, dz = 200, 9, 9, 0.05, 10.0, 10.0
    k, i, j = np.meshgrid(np.arange(n_t), np.arange(n_z), np.arange(n_y), indexing="ij")
    base = 10.0 + 0.4 * k * dt + 0.05 * i * dz - 0.03 * j * dy
    grid = np.stack([base, 0.5 * base - 4.0, 0.2 * base - 2.0], axis=-1)
    field = FullFieldWind(grid, dy=dy, dz=dz, dt=dt, mean_speed=10.0, reference_height=90.0, grid_bottom=50.0)
    wind = FieldWindInputs(field)
    p, v, t = ca.SX.sym("p", 3), ca.SX.sym("v", 3), ca.SX.sym("t")
    f = ca.Function("rate", [p, v, t], [wind.path_rate(p, v, {"WindTime": t})])
    rng = np.random.default_rng(4)
    for _ in range(10):
        point = np.array([rng.uniform(-5, 5), rng.uniform(-20, 20), rng.uniform(70, 110)])
        velocity = np.array([rng.uniform(-2, 2), rng.uniform(-10, 10), rng.uniform(-10, 10)])
        time = rng.uniform(1.0, 3.0)
        want = field.velocity(time + 1.0, point + velocity) - field.velocity(time, point)
        got = np.asarray(f(point, velocity, time)).ravel()
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-4)
    # within dt/2 of the field's first and last slices (the point's advected time 0.01 s from either end) the
    # difference turns one-sided instead of reaching beyond the data: still the derivative, no domain error
    point, velocity = np.array([0.0, 5.0, 90.0]), np.array([0.5, 8.0, -6.0])
    lag = (field.initial_x - point[0]) / field.mean_speed
    for time, step in ((0.01 - lag, 0.01), (field.total_time - 0.01 - lag, -0.01)):
        want = (field.velocity(time + step, point + step * velocity) - field.velocity(time, point)) / step
        np.testing.assert_allclose(np.asarray(f(point, velocity, time)).ravel(), want, rtol=0, atol=1e-3)


def test_field_path_rate_integrates_to_the_change_along_the_path():
    """On the TurbSim field ff14 along a straight path across the disk: the rate is the central difference over
    the field's step h = 50 ms, so its integral over [t0, t1] is the change of the wind averaged along the path
    over ±h/2 around the ends, computed here from the numpy field (:meth:`FullFieldWind.velocity`, 400
    trapezoids). Tolerance 1e-4 of the change's scale (the quadratures; the change of the point values differs
    by a few % of it: the smoothing of h)."""
    from mbsym.wind.inflow import read_turbsim_bts
    from mbsym.wind.operation.wind_inputs import FieldWindInputs

    field = read_turbsim_bts(need(AERO / "wind" / "ff14.bts"))
    wind = FieldWindInputs(field)
    h = field.dt

    def averaged(t):
        s = np.linspace(t - h / 2, t + h / 2, 401)
        w = np.array([field.velocity(si, _line(si)[0]) for si in s])
        return np.sum(0.5 * (w[1:] + w[:-1]) * np.diff(s)[:, None], axis=0) / h

    for t0, t1 in ((100.0, 102.0), (100.5, 101.3)):
        got = _integrated_rate(wind, t0, t1, lambda t: {"WindTime": t}, path=_line)
        want = averaged(t1) - averaged(t0)
        scale = max(np.abs(want).max(), 1.0)
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-4 * scale)


def test_uniform_path_rate_integrates_to_the_change_along_the_path():
    """Power-law and linear shears, direction and upflow: the exact rate integrates to the change between the
    path's ends of the numpy uniform wind at fixed columns (tolerance: the trapezoids, 1e-6 m/s)."""
    from mbsym.wind.operation.wind_inputs import UNIFORM_INPUTS, UniformWindInputs

    wind = UniformWindInputs(90.0, 126.0)
    values = {"Wind1VelX": 12.0, "WindDir": 0.2, "WindVertVel": 0.4, "HLinShr": 0.1, "VShrExp": 0.2,
              "VLinShr": 0.05, "Upflow": 0.03, "GustSpd": 0.0}
    got = _integrated_rate(wind, 0.0, 3.0, lambda t: values)
    points = ca.SX.sym("p", 3)
    f = ca.Function("w", [points], [wind.velocity(points, {k: values[k] for k in UNIFORM_INPUTS})])
    want = np.asarray(f(_path(3.0)[0])).ravel() - np.asarray(f(_path(0.0)[0])).ravel()
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-6)


def _open_loop(model, deck, t_end):
    """RtAeroMxh, RtAeroFxh [N m, N] of mbsym's aerodynamics on OpenFAST's ff14_rigid motion (shared csv,
    0.05 s), the DBEMT states integrated along it by the midpoint rule (τ₂ ≥ 1 s: 0.05 s steps resolve it)."""
    from mbsym.wind.analysis.compare import read_csv

    ref = read_csv(need(AERO / "ff14_rigid.csv"))
    keep = np.asarray(ref.time) <= t_end + 1e-9
    t = np.asarray(ref.time)[keep]
    eom = model.structure.eom
    dyn = model.dynamics()
    f = model._parts["blade_aero"]
    names = list(f.name_out())
    p0 = np.array([dyn.defaults[n] for n in eom.parameters], float)
    nq, nu = eom.n_q, len(eom.inputs)
    rows = np.zeros((2 * nq + nu, t.size))
    for i, c in enumerate(eom.coordinates):
        sign = -1.0 if c.startswith("TSS") else 1.0           # ElastoDyn's side-side sign
        rows[i] = sign * np.asarray(ref.channel(f"Q_{c}"))[keep]
        rows[nq + i] = sign * np.asarray(ref.channel(f"QD_{c}"))[keep]
    rows[2 * nq + eom.inputs.index("BlPitch")] = np.deg2rad(np.asarray(ref.channel("BldPitch1"))[keep])
    shaft = eom.point_kinematics("shaft")

    def aero(a, time, s):
        return dict(zip(names, f(a[:nq], a[nq:2 * nq], a[2 * nq:], p0, s, time, 1.225)))

    first = aero(rows[:, 0], t[0], np.zeros(len(model.rotor.state_names)))
    s = np.asarray(model.rotor.steady_states(*[np.asarray(first[k]) for k in
                                               ("node_vx", "node_vy", "node_r_local", "node_theta")])).ravel()
    out = []
    for n in range(t.size - 1):
        a0, h = rows[:, n], t[n + 1] - t[n]
        o = aero(a0, t[n], s)
        axis = np.asarray(shaft(a0[:nq], a0[nq:2 * nq], np.zeros(nq), a0[2 * nq:], p0)[1])[:, 0]
        out.append([float(np.dot(np.asarray(o[k]).ravel(), axis)) for k in ("rotor_moment", "rotor_force")])
        half = s + 0.5 * h * np.asarray(o["states_dot"]).ravel()
        mid = aero(0.5 * (a0 + rows[:, n + 1]), t[n] + 0.5 * h, half)
        s = s + h * np.asarray(mid["states_dot"]).ravel()
    return t[:-1], np.array(out).T, ref, keep


def test_rotor_loads_on_openfasts_motion_match_openfasts():
    """ff14_rigid, 10-30 s: ε = mean|Δ| / range of OpenFAST's. Bounds 0.6 % (RtAeroMxh) and 0.5 % (RtAeroFxh):
    measured 0.21 / 0.15 % with AeroDyn's rate (default), 1.35 / 1.07 % with Øye's whole rate, which must fail
    them (checked here too)."""
    from mbsym.wind import OperatingTurbine
    from mbsym.wind.operation.deck import operating_deck

    deck = operating_deck(need(INPUTS / "ff14_rigid" / "ff14_rigid.fst"))
    model = deck.model(aero="blade")
    assert model.rotor.dbemt_mode == 2 and model.rotor.dbemt_wind_rate is False
    whole = OperatingTurbine(deck.turbine, dataclasses.replace(model.rotor, dbemt_wind_rate=True), dofs=deck.dofs,
                             wind=model.wind, actuators=deck.actuators, output_nodes=deck.output_nodes)
    eps = {}
    for label, m in (("aerodyn", model), ("whole", whole)):
        t, y, ref, keep = _open_loop(m, deck, 30.0)
        w = t >= 10.0
        for j, name in enumerate(("RtAeroMxh", "RtAeroFxh")):
            r = np.asarray(ref.channel(name))[keep][:-1]
            eps[label, name] = np.mean(np.abs(y[j][w] - r[w])) / np.ptp(r[w])
    assert eps["aerodyn", "RtAeroMxh"] < 0.006 < eps["whole", "RtAeroMxh"], eps
    assert eps["aerodyn", "RtAeroFxh"] < 0.005 < eps["whole", "RtAeroFxh"], eps
