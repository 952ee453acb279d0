"""Identification on an operating turbine (issue 22, item 2).

References: OpenFAST v5 + AeroDyn 15 + ROSCO runs of the NREL 5 MW (``../shared/openfast/aero``, README there):
``step_10_14`` (wind 10 -> 14 m/s at 30 s, the deck's ``TwrFADmp(1)`` = 1 %). The measured-input model is checked
against its own full model (independent evaluation of the same physics through the actuator states) and the
torque balance of :meth:`OperatingTurbine.balancing_torque`.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest

import mbsym as mb
from mbsym.exceptions import ConvergenceWarning, DataError, IdentificationOptionError, SolverError

AERO = Path(__file__).resolve().parents[2].parent / "shared" / "openfast" / "aero"
STEP_FST = AERO / "openfast_inputs" / "step_10_14" / "step_10_14.fst"
STEP_CSV = AERO / "step_10_14.csv"


@pytest.fixture(scope="module")
def step():
    if not STEP_FST.is_file():
        pytest.skip(f"shared OpenFAST data not found at {STEP_FST}")
    from mbsym.wind.analysis.compare import read_csv

    return STEP_FST, read_csv(STEP_CSV)


@pytest.fixture(scope="module")
def window_csv(step, tmp_path_factory):
    """t = 28..45 s of step_10_14 (the step at 30 s and the first tower swings): a short operating record."""
    lines = STEP_CSV.read_text().splitlines()
    keep = [ln for ln in lines[1:] if 28.0 <= float(ln.split(",")[0]) <= 45.0]
    path = tmp_path_factory.mktemp("op") / "step_28_45.csv"
    path.write_text("\n".join([lines[0], *keep]) + "\n")
    return path


@pytest.fixture(scope="module")
def ua_deck(step, tmp_path_factory):
    """A copy of the step_10_14 deck with AeroDyn's unsteady airfoils on (``UA_Mod`` 3), as most stock decks have:
    the deck then simulates with blade elements (per-node DBEMT and UA states)."""
    import shutil

    root = tmp_path_factory.mktemp("ua")
    for name in ("step_10_14", "deck"):
        shutil.copytree(STEP_FST.parents[1] / name, root / name)
    aero = root / "deck" / "NRELOffshrBsline5MW_Onshore_AeroDyn15.dat"
    text = aero.read_text()
    edited = re.sub(r"(?m)^0(\s+UA_Mod\b)", r"3\1", text)
    assert edited != text
    aero.write_text(edited)
    return root / "step_10_14" / "step_10_14.fst"


@pytest.fixture(scope="module")
def measured():
    """The built-in NREL 5 MW, rotor-effective, quasi-steady inflow, driven by measured pitch and torque."""
    from mbsym.wind.operation import OperatingTurbine
    from mbsym.wind.operation.measured import MeasuredInputTurbine

    return MeasuredInputTurbine(OperatingTurbine.nrel5mw(dynamic_inflow=False))


# ---------------------------------------------------------------- the model
def test_measured_form_matches_the_full_model_with_actuators_at_rest(measured):
    """Same physics, other wiring: the full model with BlPitch = BlPitchCom, GenTq = GenTqCom, BlPitch_d = 0 has
    the same structural rates (to round-off) and zero actuator rates."""
    full, dyn = measured.full, measured.dynamics()
    x = dyn.x0.copy()
    x[dyn.states.index("GeAz_d")], x[dyn.states.index("TFA1_d")] = 1.2, 0.03
    u = np.array([13.0, 0.09, 4.1e4])
    xf = dict(zip(full.states, full.x0))
    xf.update(zip(dyn.states, x))
    xf.update(BlPitch=u[1], BlPitch_d=0.0, GenTq=u[2], GeAz=2.0)
    ref = full.rhs_value(np.array([xf[s] for s in full.states]), u)
    got = dyn.rhs_value(x, u)
    assert np.allclose(got, [ref[full.states.index(s)] for s in dyn.states], rtol=1e-12, atol=1e-12)
    assert abs(ref[full.states.index("BlPitch_d")]) < 1e-9 and abs(ref[full.states.index("GenTq")]) < 1e-6
    assert "GeAz" not in dyn.states and "Q_GeAz" not in dyn.output_names      # rotor-effective: azimuth dropped


def test_trim_balances_the_measured_torque(measured):
    """The trimmed rotor speed makes the aerodynamic torque equal N T_gen (OperatingTurbine.balancing_torque, an
    independent evaluation), within 1e-6 relative; every rate is zero."""
    dyn = measured.dynamics()
    u = np.array([14.0, np.deg2rad(8.6), 43093.0])
    x = measured.trim(u, guess={"GeAz_d": 1.27})
    assert np.max(np.abs(dyn.rhs_value(x, u))) < 1e-8
    full = measured.full
    xf = dict(zip(full.states, full.x0))
    xf.update(zip(dyn.states, x))
    xf.update(BlPitch=u[1], GenTq=u[2], BlPitch_d=0.0)
    balance = measured.turbine.balancing_torque(np.array([xf[s] for s in full.states]), 14.0)
    assert balance == pytest.approx(u[2], rel=1e-6)


@pytest.mark.parametrize("unsteady", [False, True], ids=["dbemt", "dbemt+ua"])
def test_blade_element_trim_balances_the_measured_torque(step, ua_deck, unsteady):
    """Blade-element rotor (per-node DBEMT states): the trim solves the structure and rotor speed only, the wake
    at equilibrium with their inflow. Checked: every structural rate zero, the aerodynamic torque equal to N T_gen
    (balancing_torque, an independent evaluation) within 1e-6, the wake's rates zero at that inflow. It had run a
    root over all states by finite differences (minutes, then "no steady state" on a deck with UA)."""
    from mbsym.wind.operation import OperatingTurbine
    from mbsym.wind.operation.measured import MeasuredInputTurbine

    model = MeasuredInputTurbine(OperatingTurbine.from_openfast(ua_deck if unsteady else step[0], aero="blade"))
    assert any("_ua_" in s for s in model.dynamics().states) == unsteady
    dyn = model.dynamics()
    u = dyn.u0.copy()
    for k, v in {"Wind1VelX": 14.0, "BlPitchMeas": np.deg2rad(8.57), "GenTqMeas": 43093.0}.items():
        u[dyn.inputs.index(k)] = v
    x = model.trim(u, guess={"GeAz_d": 1.2, "GeAz": 0.3})
    rates = dyn.rhs_value(x, u)
    mechanical = [i for i, s in enumerate(dyn.states) if s.endswith("_d") or s in ("TFA1", "TSS1")]
    assert np.max(np.abs(rates[mechanical])) < 1e-6
    wake = [i for i, s in enumerate(dyn.states) if "vind" in s]
    assert wake and np.max(np.abs(rates[wake])) < 1e-6
    assert x[dyn.states.index("GeAz")] == 0.3                                  # the azimuth is not solved for
    full = model.full
    xf = dict(zip(full.states, full.x0))
    xf.update(zip(dyn.states, x))
    xf.update(BlPitch=u[dyn.inputs.index("BlPitchMeas")], GenTq=43093.0, BlPitch_d=0.0)
    balance = model.turbine.balancing_torque(np.array([xf[s] for s in full.states]), 14.0)
    assert balance == pytest.approx(43093.0, rel=1e-6)


def test_blade_element_trim_in_a_full_field(step):
    """A full-field deck (ff14_rigid): the wind is the field at the record's time (``WindTime``), the trim balances
    the torque there (balancing_torque with the same wind, 1e-6) at the record's azimuth. (The CLI had then failed
    on its progress line with "tuple.index(x): x not in tuple": it printed the input Wind1VelX.)"""
    from mbsym.wind.analysis.compare import read_csv
    from mbsym.wind.operation import OperatingTurbine
    from mbsym.wind.operation.measured import MeasuredInputTurbine

    fst = AERO / "openfast_inputs" / "ff14_rigid" / "ff14_rigid.fst"
    series = read_csv(AERO / "ff14_rigid.csv")
    model = MeasuredInputTurbine(OperatingTurbine.from_openfast(fst, aero="blade"))
    dyn = model.dynamics()
    assert dyn.inputs == ("WindTime", "BlPitchMeas", "GenTqMeas")
    U = model.inputs_from(series)
    x = model.initial_state_from(series, U[0])
    rates = dyn.rhs_value(x, U[0])
    mechanical = [i for i, s in enumerate(dyn.states) if s.endswith("_d") or s in ("TFA1", "TSS1")]
    assert np.max(np.abs(rates[mechanical])) < 1e-6
    full = model.full
    xf = dict(zip(full.states, full.x0))
    xf.update(zip(dyn.states, x))
    xf.update(BlPitch=U[0, 1], GenTq=U[0, 2], BlPitch_d=0.0)
    balance = model.turbine.balancing_torque(np.array([xf[s] for s in full.states]), {"WindTime": U[0, 0]})
    assert balance == pytest.approx(U[0, 2], rel=1e-6)


@pytest.mark.parametrize("case, rung", [("step", "rotor"), ("ua", "rotor"), ("ff14_rigid", "blade"),
                                        ("ff14_flex", "blade")])
def test_identification_rung(step, ua_deck, case, rung, capsys):
    """The rung a fit takes by default: rotor-effective where the blade elements only carry AeroDyn's tower or UA
    (said), blade elements where the wind differs over the rotor (a full field: the record's hub wind is not the
    rotor's) or blade DOFs need their loads."""
    import argparse

    from mbsym.cli.identify import _fit_aero
    from mbsym.wind.operation.deck import operating_deck

    fst = {"step": step[0], "ua": ua_deck}.get(case) or AERO / "openfast_inputs" / case / f"{case}.fst"
    assert _fit_aero(argparse.Namespace(quiet=False), operating_deck(fst)) == rung
    assert ("rotor-effective aerodynamics for the fit" in capsys.readouterr().out) == (case == "ua")


def test_trim_without_a_steady_state_is_a_solver_error(measured):
    with pytest.raises(SolverError, match="no steady state at the record's first inputs"):
        measured.trim(np.array([14.0, 0.0, 1.0e6]), guess={"GeAz_d": 1.27})    # 97 MN m on the rotor: it stops


def test_inputs_from_a_record_convert_units(measured):
    rec = {"time": [0.0, 0.05], "Wind1VelX": [10.0, 10.5], "BldPitch1": [1.0, 2.0], "GenTq": [30.0, 31.0]}
    U = measured.inputs_from(rec)                                # dict: OpenFAST units (deg, kN-m)
    assert np.allclose(U, [[10.0, np.deg2rad(1.0), 3.0e4], [10.5, np.deg2rad(2.0), 3.1e4]], rtol=1e-15)
    with pytest.raises(DataError, match=r"input 'GenTqMeas' needs one of the data channels \['GenTq'\]"):
        measured.inputs_from({k: v for k, v in rec.items() if k != "GenTq"})


def test_channel_names_match_ignoring_case(measured):
    """OpenFAST's channel names are case-insensitive and its output repeats the OutList's spelling (the NREL
    2.8-127 deck's InflowWind writes ``Wind1Velx``): the same inputs either way; a missing channel's error lists
    a long record briefly."""
    rec = {"time": [0.0, 0.05], "Wind1VelX": [10.0, 10.5], "BldPitch1": [1.0, 2.0], "GenTq": [30.0, 31.0]}
    lower = {"time": rec["time"], "Wind1Velx": rec["Wind1VelX"], "bldpitch1": rec["BldPitch1"], "GENTQ": rec["GenTq"]}
    np.testing.assert_array_equal(measured.inputs_from(lower), measured.inputs_from(rec))
    many = {"time": rec["time"], **{f"Ch{k:03d}": [0.0, 0.0] for k in range(500)}}
    with pytest.raises(DataError, match=r"501 channels \(Ch000, .*, \.\.\.\)") as info:
        measured.inputs_from(many)
    assert len(str(info.value)) < 600


def test_individual_pitch_decks_take_one_pitch_only_when_the_blades_agree():
    """A deck whose controller pitches individually: the operating identification takes the record's BldPitch1 as
    the collective pitch when every blade is within 0.1 deg of it, and refuses otherwise (or without blades 2-3)."""
    from types import SimpleNamespace

    from mbsym.cli.identify import _pitch_spread

    names = ("Time", "BldPitch1", "BldPitch2", "bldpitch3")
    agree = SimpleNamespace(names=names, data=np.array([[0.0, 1.0, 1.05, 0.98], [0.05, 2.0, 2.0, 2.0]]))
    assert _pitch_spread(agree) == pytest.approx(0.05)
    apart = SimpleNamespace(names=names, data=np.array([[0.0, 1.0, 1.5, 1.0]]))
    with pytest.raises(DataError, match="0.5 deg apart"):
        _pitch_spread(apart)
    with pytest.raises(DataError, match="BldPitch2"):
        _pitch_spread(SimpleNamespace(names=("Time", "BldPitch1"), data=np.zeros((2, 2))))


# ---------------------------------------------------------------- the failures of issue 22 item 2
def test_structure_alone_on_operating_data_is_a_typed_error(step):
    """Before: LAPACK's 'DLASCL parameter number 4' and numpy's 'SVD did not converge'. The structure alone (no
    aerodynamics, no controller) cannot follow operating data: its trajectory leaves the finite range."""
    from mbsym.wind import read_openfast
    from mbsym.wind.structure.turbine import TurbineModel

    fst, series = step
    model = TurbineModel(read_openfast(fst))
    with pytest.raises(SolverError, match="not finite.*aerodynamics and measured pitch and torque"):
        mb.identify(model, series, ["TwrFADmp(1)"], channels=["Q_TFA1", "QD_TFA1", "Q_TSS1", "QD_TSS1", "QD_GeAz"])


def test_cli_models_the_operating_turbine(step, window_csv, capsys):
    """``mbsym identify`` on an AeroDyn deck: the operating turbine (measured pitch/torque/wind), progress lines, a tower fore-aft fit within 2 % (eps against OpenFAST's own series: 1.1 % measured on this window, the
    step's transient; 0.28 % on the whole record) and a finite damping estimate."""
    from mbsym.cli import main

    code = main(["identify", str(STEP_FST), "--data", str(window_csv), "--params", "TwrFADmp(1)", "--json"])
    cap = capsys.readouterr()
    assert code == 0, cap.err
    assert "operating turbine" in cap.out
    assert re.search(r"trimmed at the record's first inputs \(wind 10 m/s\)", cap.out)
    assert re.search(r"iteration 1: cost", cap.out)
    data = json.loads(cap.out.strip().splitlines()[-1])
    assert list(data["eps_pct"]) == ["Q_TFA1", "QD_TFA1"]
    assert all(v < 2.0 for v in data["eps_pct"].values())
    assert 0.0 < data["parameters"]["TwrFADmp(1)"] < 20.0


def test_cli_fits_the_rotor_effective_rung_of_a_deck_with_unsteady_airfoils(ua_deck, window_csv, capsys):
    """A deck that simulates with blade elements only for its inflow (UA_Mod 3, rigid blades) is fitted with the
    rotor-effective rung, and says so: the blade elements' ~700 wake and airfoil states made the fit's set-up run
    for minutes. The record is OpenFAST's without UA, so the fit is looser than on the deck as run (eps 2.5 %
    against 1.2 %: the rotor-effective surfaces hold UA's steady state); bound 3 %."""
    from mbsym.cli import main

    code = main(["identify", str(ua_deck), "--data", str(window_csv), "--params", "TwrFADmp(1)", "--json"])
    cap = capsys.readouterr()
    assert code == 0, cap.err
    assert "rotor-effective aerodynamics for the fit" in cap.out and "--aero blade" in cap.out
    data = json.loads(cap.out.strip().splitlines()[-1])
    assert all(v < 3.0 for v in data["eps_pct"].values())
    assert 0.0 <= data["parameters"]["TwrFADmp(1)"] < 20.0


def test_cli_structure_model_is_said(step, capsys):
    """``--model structure`` on an AeroDyn deck says what is left out; on the operating record it fails typed."""
    from mbsym.cli import main

    code = main(["identify", str(STEP_FST), "--data", str(STEP_CSV), "--params", "TwrFADmp(1)", "--model",
                 "structure"])
    cap = capsys.readouterr()
    assert code == 2
    assert "aerodynamics, controller and wind are NOT modelled" in cap.out
    assert cap.err.startswith("mbsym identify: error: the residuals")


def test_estimate_x0_on_operating_data_is_bounded_and_warned(step):
    """Before: ``estimate_x0=True`` on operating data ran 279 s and ended unconverged with GeAz = -5.2e10, silently
    (the OperatingTurbine with its default zero inputs). Now: the OperatingTurbine alone is refused (its inputs are
    not given); MeasuredInputTurbine reads the inputs and the trim off the record, has no azimuth state, and every
    estimated state is finite and near the data (tower within 5 cm of OpenFAST's Q_TFA1 at t = 28 s); a time limit
    stops the fit with a ConvergenceWarning."""
    from mbsym.wind.operation import OperatingTurbine
    from mbsym.wind.operation.measured import MeasuredInputTurbine

    fst, series = step
    m = (series.time >= 28.0) & (series.time <= 40.0)
    rec = {"time": series.time[m], **{n: series.data[m, i] for i, n in enumerate(series.names)}}
    plant = OperatingTurbine.from_openfast(fst)
    with pytest.raises(IdentificationOptionError, match="MeasuredInputTurbine"):
        mb.identify(plant, rec, ["tower_fa1_damping_ratio"], estimate_x0=True)
    model = MeasuredInputTurbine(plant)
    res = mb.identify(model, rec, ["TwrFADmp(1)"], channels=["Q_TFA1", "QD_TFA1"], estimate_x0=True)
    state = res.initial_states[0]
    assert "GeAz" not in state and all(np.isfinite(v) for v in state.values())
    assert abs(state["TFA1"] - rec["Q_TFA1"][0]) < 0.05
    assert res.success
    with pytest.warns(ConvergenceWarning, match="did not converge.*time limit"):
        res = mb.identify(model, rec, ["TwrFADmp(1)"], channels=["Q_TFA1", "QD_TFA1"], estimate_x0=True,
                          max_time=1e-9)
    assert not res.success
    with pytest.raises(IdentificationOptionError, match="max_time"):
        mb.identify(model, rec, ["TwrFADmp(1)"], max_time=-1)


@pytest.mark.slow
def test_tower_damping_from_the_step_within_10_percent(step, capsys):
    """Issue 22's check: TwrFADmp(1) from step_10_14 with the matching deck within 10 % of the deck's 1 %
    (measured 0.922 %, the default rotor-effective model). It missed (0.2-0.27 %) while the rotor-effective
    model's disk damping against the tower-top rate used ⟨r²⟩ = (R² + r_hub²)/2, 16 % above OpenFAST's
    (tests/identify/test_rotor_loads.py measures it); the BEM's thrust-weighted ⟨r²⟩ closes it."""
    from mbsym.cli import main

    code = main(["identify", str(STEP_FST), "--data", str(STEP_CSV), "--params", "TwrFADmp(1)", "--json"])
    data = json.loads(capsys.readouterr().out.strip().splitlines()[-1])
    assert code == 0
    assert data["parameters"]["TwrFADmp(1)"] == pytest.approx(1.0, rel=0.10)


@pytest.mark.slow
def test_recovers_the_damping_of_a_simulated_operating_turbine(step):
    """Self-consistency on the operating turbine: mbsym's own full model (actuators in the loop, commands = OpenFAST's
    measured pitch and torque, wind = its hub wind, t = 20..50 s, TwrFADmp(1) = 1 %) simulated by
    simulate_turbine; the measured-input identification from 2 % must recover 1 % within 2 % relative (measured
    1.0044 %: the actuators' own lag between command and position and the linear interpolation of the inputs
    between samples are the only differences)."""
    from mbsym.wind.operation import OperatingTurbine, simulate_turbine
    from mbsym.wind.operation.measured import MeasuredInputTurbine

    fst, series = step
    c, t = dict(zip(series.names, series.data.T)), series.time
    m = (t >= 20.0) & (t <= 50.0)
    tt = t[m] - 20.0
    plant = OperatingTurbine.from_openfast(fst, disk_moments=True)             # as mbsym identify fits it
    pitch = lambda s: np.interp(s, tt, np.deg2rad(c["BldPitch1"][m]))
    torque = lambda s: np.interp(s, tt, 1e3 * c["GenTq"][m])
    wind = lambda s: np.interp(s, tt, c["Wind1VelX"][m])
    x0 = plant.initial_state(10.0, rotor_speed=c["QD_GeAz"][m][0], pitch=pitch(0.0), torque=torque(0.0),
                             tower_fa=c["Q_TFA1"][m][0])
    sim = simulate_turbine(plant, wind, tt[-1], commands={"BlPitchCom": pitch, "GenTqCom": torque}, x0=x0, t_out=tt)
    rec = {"time": tt, **{n: np.asarray(sim.output(n)) for n in ("Wind1VelX", "BldPitch1", "GenTq", "Q_TFA1",
                                                                 "QD_TFA1", "QD_GeAz")}}
    model = MeasuredInputTurbine(plant)
    U = model.inputs_from(rec)
    x_trim = model.trim(U[0], guess={"GeAz_d": rec["QD_GeAz"][0], "TFA1": rec["Q_TFA1"][0]})
    res = mb.identify(model, rec, ["TwrFADmp(1)"], channels=["Q_TFA1", "QD_TFA1"], inputs=U, x0=x_trim,
                      initial={"TwrFADmp(1)": 2.0})
    assert res.success
    assert res.parameters["TwrFADmp(1)"] == pytest.approx(1.0, rel=0.02)


def _fore_aft_damping(model, u_values: dict, tower_fa: float) -> float:
    """Damping ratio of the eigenvalue pair dominated by TFA1 of a MeasuredInputTurbine, linearized at the deck's
    initial conditions with the inflow at equilibrium (blade-element model: at one azimuth; a three-bladed rotor in
    uniform wind, so nearly azimuth-independent)."""
    import casadi as ca

    dyn, full, plant = model.dynamics(), model.full, model.turbine
    u = dyn.u0.copy()
    for k, v in u_values.items():
        u[dyn.inputs.index(k)] = v
    xf = plant.initial_state(u_values["Wind1VelX"], rotor_speed=1.267, pitch=u_values["BlPitchMeas"],
                             tower_fa=tower_fa)
    x = np.array([xf[full.states.index(s)] for s in dyn.states])
    X = ca.SX.sym("x", dyn.n_x) if dyn.rhs.is_a("SXFunction") else ca.MX.sym("x", dyn.n_x)
    A = np.asarray(ca.Function("A", [X], [ca.jacobian(dyn.rhs(X, u, dyn.parameter_vector()), X)])(x), dtype=float)
    keep = [i for i, s in enumerate(dyn.states) if s != "GeAz"]
    A = A[np.ix_(keep, keep)]
    w, V = np.linalg.eig(A)
    i = [dyn.states[k] for k in keep].index("TFA1")
    k = max((j for j in range(w.size) if w[j].imag > 0.5), key=lambda j: abs(V[i, j]) / np.linalg.norm(V[:, j]))
    return float(-w[k].real / abs(w[k]))


@pytest.mark.slow
def test_rotor_effective_fore_aft_damping_matches_the_blade_element_rotor(step):
    """The rotor disk's moment against tilt and yaw rates (compose._disk_moments): with it, the rotor-effective
    model's tower fore-aft damping at 14 m/s (pitch 8.57 deg, 43.1 kN m: OpenFAST's steady state) is the
    blade-element rotor's within 0.5 points of critical (issue 22 item 6's like-for-like bound; measured 6.93 %
    vs 7.30 %; without the moment 5.5 %). It was 7.18 % with ⟨r²⟩ = (R² + r_hub²)/2, a moment 16 % above the one
    OpenFAST's time series show (tests/identify/test_rotor_loads.py), which made up for the rotor-averaged
    inflow's frozen thrust slope, about 5 % below the blade elements' (docs/operating_points.md)."""
    from mbsym.wind.operation import OperatingTurbine
    from mbsym.wind.operation.measured import MeasuredInputTurbine

    fst, _ = step
    u = {"Wind1VelX": 14.0, "BlPitchMeas": np.deg2rad(8.57), "GenTqMeas": 43093.0}
    plant = OperatingTurbine.from_openfast(fst, aero="rotor", disk_moments=True)
    rotor = _fore_aft_damping(MeasuredInputTurbine(plant), u, 0.239)
    blade = _fore_aft_damping(MeasuredInputTurbine(OperatingTurbine.from_openfast(fst, aero="blade")), u, 0.239)
    assert 0.06 < blade < 0.09
    assert rotor == pytest.approx(blade, abs=0.005)
    assert rotor < blade                              # the rotor-averaged inflow's lower frozen thrust slope


def test_cli_refuses_a_default_blade_element_fit_it_cannot_set_up_in_time(tmp_path, capsys):
    """A full-field deck (ff14_rigid: the blade elements' 234 states) by default: a typed error within seconds that
    says why and what works (--aero blade anyway; --model loads with recorded rotor loads), instead of a set-up of
    tens of minutes that --max-time does not bound (the stock NREL 5 MW deck's 1385 states: the compiler was stopped
    after 600 s, then CasADi's virtual machine)."""
    import time

    from mbsym.cli import main

    fst = AERO / "openfast_inputs" / "ff14_rigid" / "ff14_rigid.fst"
    lines = (AERO / "ff14_rigid.csv").read_text().splitlines()
    data = tmp_path / "ff14_rigid_window.csv"
    data.write_text("\n".join([lines[0], *[ln for ln in lines[1:] if 60.0 <= float(ln.split(",")[0]) <= 80.0]]) + "\n")
    t0 = time.perf_counter()
    code = main(["identify", str(fst), "--data", str(data), "--params", "TwrFADmp(1)"])
    err = capsys.readouterr().err
    assert code == 2 and time.perf_counter() - t0 < 60.0
    assert "234 states" in err and "Pass --aero blade to fit it anyway" in err and "--model loads" in err
