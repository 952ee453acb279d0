"""The operating turbine with blade-element aerodynamics (OperatingTurbine(aero='blade')) against independent data.

References: OpenFAST v5 + AeroDyn 15 steady state at 14 m/s (shared/openfast/aero/steady_states.csv: rigid
blades, uniform wind without shear); the TurbSim field itself (numpy interpolation of the .bts, which the
graph's compiled External must reproduce at the hub point); symmetry of an axisymmetric rotor.
"""

import csv
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "operation"))
from _op_data import AERO, INPUTS, need  # noqa: E402


@pytest.fixture(scope="module")
def steady14():
    import mbsym as mb

    fst = need(INPUTS / "steady_14" / "steady_14.fst")
    model = mb.wind.OperatingTurbine.from_openfast(fst, aero="blade", dofs=["GenDOF"])
    model.dynamics()
    return model


def _openfast_row(speed: float) -> dict[str, float]:
    with open(need(AERO / "steady_states.csv")) as fh:
        for row in csv.DictReader(fh):
            if float(row["WindSpeed_[m/s]"]) == speed:
                return {k.split("_[")[0]: float(v) for k, v in row.items()}
    raise AssertionError(f"no {speed} m/s row")


def _outputs(model, x: np.ndarray, wind: dict) -> dict[str, float]:
    d = model.dynamics()
    s = dict(zip(d.states, x))
    u = d.input_vector({**wind, "BlPitchCom": s["BlPitch"], "GenTqCom": s["GenTq"]})
    return dict(zip(d.output_names, np.asarray(d.outputs(x, u, d.parameter_vector())).ravel()))


def test_rotor_loads_match_aerodyn_at_14_mps(steady14):
    """RtAeroFxh and RtAeroMxh at OpenFAST's steady 14 m/s state (pitch 8.566 deg, 12.1 rpm), wake at equilibrium.

    Tolerance 1 %: mbsym's BEM agrees with AeroDyn's rotor Cp within 0.5-0.8 % (docs/aero.md), and this model's
    tower is rigid where OpenFAST's leans 0.24 m forward (RtSkew 5.25 vs 5.0 deg).
    """
    of = _openfast_row(14.0)
    wind = {"Wind1VelX": 14.0}
    x = steady14.initial_state(wind, pitch=np.deg2rad(of["BldPitch1"]), rotor_speed=of["RotSpeed"] * np.pi / 30)
    y = _outputs(steady14, x, wind)
    assert y["RtAeroFxh"] == pytest.approx(of["RtAeroFxh"], rel=0.01)
    assert y["RtAeroMxh"] == pytest.approx(of["RtAeroMxh"], rel=0.01)
    assert y["RtVAvgxh"] == pytest.approx(of["RtVAvgxh"], rel=0.002)   # 14 cos(5 deg) against 13.94 (tower lean)
    assert y["RtAeroPwr"] == pytest.approx(y["RtAeroMxh"] * of["RotSpeed"] * np.pi / 30, rel=1e-9)


def test_blades_share_the_load_of_an_axisymmetric_inflow(steady14):
    """Uniform wind without shear: the three root out-of-plane moments are equal up to the 5 deg tilt's 1P part.

    The tilt gives each blade a skewed inflow depending on azimuth; the *sum* over the blades must not depend on the
    azimuth beyond the 3P ripple (0.1 % here), and the rotor loads at azimuths 120 deg apart must be equal (exact:
    the rotor is symmetric), 1e-9 relative.
    """
    wind = {"Wind1VelX": 14.0}
    d = steady14.dynamics()
    x0 = steady14.initial_state(wind, pitch=np.deg2rad(8.566))
    i = d.states.index("GeAz")
    loads = []
    for az in (0.3, 0.3 + 2 * np.pi / 3):
        x = x0.copy()
        x[i] = az
        s = dict(zip(d.states, x))
        s.update(steady14.wake_equilibrium(s, wind, None))
        x = np.array([s[n] for n in d.states])
        y = _outputs(steady14, x, wind)
        loads.append([y["RtAeroFxh"], y["RtAeroMxh"], y["RootMyc1"] + y["RootMyc2"] + y["RootMyc3"]])
    np.testing.assert_allclose(loads[0], loads[1], rtol=1e-9)


def test_full_field_hub_wind_channel_is_the_field_at_the_hub_point():
    """Wind1VelX/Y/Z of a full-field model = the field at (0, 0, hub height) (numpy reference; float32 data: 1e-5)."""
    import mbsym as mb

    fst = need(INPUTS / "ff14_rigid" / "ff14_rigid.fst")
    model = mb.wind.OperatingTurbine.from_openfast(fst, aero="blade", dofs=["GenDOF"])
    d = model.dynamics()
    field = model.wind.field
    hub = np.array([[0.0, 0.0, float(model.turbine.hub_height)]])
    for t in (0.0, 37.5, 123.456):
        x = model.initial_state({"WindTime": t})
        y = _outputs(model, x, {"WindTime": t})
        v = field.velocity(t, hub)[0]
        assert y["Wind1VelX"] == pytest.approx(float(v[0]), rel=1e-5)
        assert y["Wind1VelY"] == pytest.approx(float(v[1]), abs=1e-5 * abs(float(v[0])))
        assert y["Wind1VelZ"] == pytest.approx(float(v[2]), abs=1e-5 * abs(float(v[0])))
    assert "WindTime" in d.inputs and "Wind1VelX" not in d.inputs


def test_held_split_is_the_same_model(steady14):
    """The blade-element aerodynamics as the held part (mbsym.held, method "rk4-held"): rhs, outputs and
    measurements with the held part substituted equal the composed model's own, at a perturbed state
    (rounding: 1e-12 relative); the held part does not depend on the controller's commands, so the closed
    loop may evaluate it once per sample for measurement, step and outputs."""
    d = steady14.dynamics()
    h = d.held
    assert h is not None and h.description == "blade-element aerodynamics"
    wind = {"Wind1VelX": 13.0}
    x = steady14.initial_state(wind, pitch=np.deg2rad(7.0))
    x = x + 1e-3 * np.random.default_rng(3).standard_normal(x.size) * np.maximum(np.abs(x), 1.0)
    u = d.input_vector({**wind, "BlPitchCom": 0.1, "GenTqCom": 4e4})
    p = d.parameter_vector()
    z = h.part(x, u, p)
    for full, held in ((d.rhs, h.rhs), (d.outputs, h.outputs)):
        a, b = np.asarray(full(x, u, p)).ravel(), np.asarray(held(x, u, p, z)).ravel()
        np.testing.assert_allclose(b, a, rtol=1e-12, atol=1e-12 * np.max(np.abs(a)))
    m = steady14.measurement_dynamics()
    np.testing.assert_allclose(np.asarray(m.held.outputs(x, u, p, z)).ravel(), np.asarray(m.outputs(x, u, p)).ravel(),
                               rtol=1e-12)
    commands = [d.inputs.index(n) for n in steady14.command_names]
    assert not h.depends_on_inputs(commands) and h.depends_on_inputs([d.inputs.index("Wind1VelX")])


def test_default_aero_interval_is_two_degrees_of_rotation(steady14):
    """default_aero_dt: the largest whole number of controller samples over which the rotor turns at most 2 deg
    (closed form: floor(2° / (Ω dt))), at the faster of the state's rotor speed and 80 m/s over the tip radius."""
    from mbsym.wind.operation.simulation import default_aero_dt

    d = steady14.dynamics()
    omega = 12.1 * np.pi / 30.0                      # 72.6 deg/s: 2 deg in 27.5 ms
    x = np.array(steady14.initial_state({"Wind1VelX": 14.0}, rotor_speed=omega), dtype=float)
    assert default_aero_dt(steady14, 0.00625, x) == pytest.approx(4 * 0.00625)       # 25 ms
    assert default_aero_dt(steady14, 0.01, x) == pytest.approx(2 * 0.01)
    assert default_aero_dt(steady14, 0.05, x) == pytest.approx(0.05)                  # never below one sample
    x_fast = x.copy()
    x_fast[d.states.index("GeAz_d")] = 2 * omega     # twice as fast: half the interval
    assert default_aero_dt(steady14, 0.00625, x_fast) == pytest.approx(2 * 0.00625)
    x_idle = x.copy()
    x_idle[d.states.index("GeAz_d")] = 0.0           # at rest: 80 m/s tip speed, 1.27 rad/s on this 63 m rotor
    tip = float(steady14.rotor.tip_radius)
    expected = np.floor(np.radians(2.0) / (80.0 / tip * 0.00625)) * 0.00625
    assert default_aero_dt(steady14, 0.00625, x_idle) == pytest.approx(expected)
    # extrapolated quadratically (InterpOrder 2): 4 deg, 55 ms at 12.1 rpm -> 8 samples
    assert default_aero_dt(steady14, 0.00625, x, order=2) == pytest.approx(8 * 0.00625)
    assert default_aero_dt(steady14, 0.00625, x, order=1) == pytest.approx(4 * 0.00625)


def test_deck_interp_order_is_read_and_checked(tmp_path):
    """InterpOrder of the .fst (the shared full-field decks: 2) reaches SimulationSettings; other values than 1 and
    2 are refused with the file, line and key (OpenFAST accepts only those two)."""
    from mbsym.exceptions import OpenFASTFormatError
    from mbsym.wind.deck.openfast import read_openfast

    fst = need(INPUTS / "ff14_flex" / "ff14_flex.fst")
    assert read_openfast(fst).simulation.interp_order == 2
    case = tmp_path / "case"
    case.mkdir()
    (tmp_path / "deck").symlink_to(INPUTS / "deck")            # the deck's relative paths: ../deck/...
    for f in fst.parent.iterdir():
        (case / f.name).write_bytes(f.read_bytes())
    lines = fst.read_text().splitlines(keepends=True)
    lines = [ln.replace("2", "3", 1) if "InterpOrder" in ln else ln for ln in lines]
    (case / fst.name).write_text("".join(lines))
    with pytest.raises(OpenFASTFormatError, match="InterpOrder"):
        read_openfast(case / fst.name)


def test_a_run_extrapolates_the_aerodynamics_with_the_decks_interp_order(steady14):
    """simulate_turbine with the compiled-loop baseline controller: the aerodynamics every default interval,
    extrapolated with the deck's InterpOrder (the statistics say so); an explicit aero_order wins."""
    from mbsym.wind.control.baseline import BaselineController
    from mbsym.wind.operation.controllers import baseline_in_loop
    from mbsym.wind.operation.simulation import default_aero_dt, simulate_turbine

    ctrl = baseline_in_loop(BaselineController.from_discon(need(INPUTS / "deck" / "DISCON.IN"), dt=0.00625))
    order = steady14.turbine.simulation.interp_order
    x0 = steady14.initial_state({"Wind1VelX": 14.0})
    res = simulate_turbine(steady14, 14.0, 0.1, controller=ctrl, x0=x0, compile=False)
    st = res.statistics
    assert st["held_order"] == order
    assert st["held_dt"] == pytest.approx(default_aero_dt(steady14, 0.00625, steady14.dynamics().state_vector(x0),
                                                          order=order))
    res0 = simulate_turbine(steady14, 14.0, 0.1, controller=ctrl, x0=x0, compile=False, aero_order=0, aero_dt=0.0125)
    assert res0.statistics["held_order"] == 0 and res0.statistics["held_dt"] == pytest.approx(0.0125)


def test_default_method_is_the_decks_elastodyn_method(steady14):
    """The deck says ElastoDyn Method 3 (ABM4): simulate_turbine with the compiled-loop baseline controller runs
    "abm4-held" and says so; the same loop by "rk4-held" (the method given, which the message states against the
    deck's) agrees over 0.25 s from the steady state at 14 m/s: both are the same discretized loop to their
    truncation errors and the commands' zero-order hold (measured 5.4e-7 rad/s in GeAz_d; tolerance 1e-4 of the
    12.1 rpm = 1.27 rad/s speed)."""
    from mbsym.wind.control.baseline import BaselineController
    from mbsym.wind.operation.controllers import baseline_in_loop
    from mbsym.wind.operation.simulation import deck_method, simulate_turbine

    assert deck_method(steady14) == 3
    ctrl = baseline_in_loop(BaselineController.from_discon(need(INPUTS / "deck" / "DISCON.IN"), dt=0.00625))
    x0 = steady14.initial_state({"Wind1VelX": 14.0})
    res = simulate_turbine(steady14, 14.0, 0.25, controller=ctrl, x0=x0, compile=False)
    st = res.statistics
    assert st["method"] == "abm4-held" and st["deck_method"] == "ABM4 (ElastoDyn Method 3)"
    assert "The deck asks" not in st["message"]
    ref = simulate_turbine(steady14, 14.0, 0.25, controller=ctrl, x0=x0, compile=False, method="rk4-held")
    assert "The deck asks ElastoDyn Method 3 (ABM4); this run integrates with rk4-held (the method given)" in \
        ref.statistics["message"]
    speed = res.state("GeAz_d")
    assert np.max(np.abs(speed - ref.state("GeAz_d"))) < 1e-4 * 1.27


def test_rotor_effective_run_says_it_integrates_with_rk4():
    """The rotor-effective model of the same deck has no held part: it runs "rk4" and its message says the deck
    asks ABM4 (nothing a user gives is silently ignored)."""
    import mbsym as mb
    from mbsym.wind.control.baseline import BaselineController
    from mbsym.wind.operation.controllers import baseline_in_loop
    from mbsym.wind.operation.simulation import simulate_turbine

    model = mb.wind.OperatingTurbine.from_openfast(need(INPUTS / "steady_14" / "steady_14.fst"), aero="rotor",
                                                   dofs=["GenDOF"])
    ctrl = baseline_in_loop(BaselineController.from_discon(need(INPUTS / "deck" / "DISCON.IN"), dt=0.00625))
    res = simulate_turbine(model, 14.0, 0.05, controller=ctrl, compile=False)
    st = res.statistics
    assert st["method"] == "rk4" and st["deck_method"] == "ABM4 (ElastoDyn Method 3)"
    assert "this run integrates with rk4 (the multistep methods are modelled for blade-element aerodynamics only)" \
        in st["message"]


def test_ab4_refused_where_the_torque_lag_is_outside_its_stability_interval(steady14):
    """AB4 is stable for real eigenvalues |λ| h < 0.30 (its characteristic polynomial); the generator-torque lag
    of the actuator model (τ = 0.01 s: |λ| h = 0.625 at 6.25 ms) is not: run, it settles into a bounded 1.7 kN m
    limit cycle at the torque rate limit (measured), a wrong answer that is not a divergence, so it is refused."""
    from mbsym.exceptions import SimulationOptionError
    from mbsym.wind.control.baseline import BaselineController
    from mbsym.wind.operation.controllers import baseline_in_loop
    from mbsym.wind.operation.simulation import simulate_turbine

    ctrl = baseline_in_loop(BaselineController.from_discon(need(INPUTS / "deck" / "DISCON.IN"), dt=0.00625))
    with pytest.raises(SimulationOptionError, match="generator-torque lag"):
        simulate_turbine(steady14, 14.0, 0.1, controller=ctrl, method="ab4-held", compile=False)


def test_deck_asking_ab4_runs_rk4_held_and_says_why(steady14):
    """A deck with ElastoDyn Method 2 (AB4): AB4 is unstable for the generator-torque lag at 6.25 ms (the test
    above), so the default is "rk4-held" and the message gives the reason with the numbers (|λ| h = 0.625)."""
    import copy
    import dataclasses

    from mbsym.wind.control.baseline import BaselineController
    from mbsym.wind.operation.controllers import baseline_in_loop
    from mbsym.wind.operation.simulation import deck_method, simulate_turbine

    model = copy.copy(steady14)
    model.turbine = dataclasses.replace(steady14.turbine, integration_method=2)
    assert deck_method(model) == 2
    ctrl = baseline_in_loop(BaselineController.from_discon(need(INPUTS / "deck" / "DISCON.IN"), dt=0.00625))
    res = simulate_turbine(model, 14.0, 0.05, controller=ctrl, compile=False)
    st = res.statistics
    assert st["method"] == "rk4-held" and st["deck_method"] == "AB4 (ElastoDyn Method 2)"
    # the pitch actuator (50 rad/s, ζ = 0.7: |λ| h = 0.31) is inside AB4's interval in its direction (0.325)
    assert "this run integrates with rk4-held (AB4 is unstable here: the generator-torque lag |λ| h = 0.625 > 0.3)." \
        in st["message"]
