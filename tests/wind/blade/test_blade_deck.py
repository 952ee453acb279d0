"""Decks and controllers with the blade-element rotor: which rung a deck runs, its wind, its controller wiring.

References: the shared OpenFAST decks (what their InflowWind/ElastoDyn/ServoDyn files say), the real ROSCO 2.10.6
library (the swap array it receives from a blade-element plant must carry the plant's own root moments and
azimuth; skipped without registry access), and closed forms of InflowWind's power-law shear.
"""

import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "operation"))
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "control"))
from _op_data import DECK, INPUTS, need  # noqa: E402


def _deck(case: str):
    from mbsym.wind.operation.deck import operating_deck

    return operating_deck(need(INPUTS / case / f"{case}.fst"))


@pytest.mark.parametrize("case, aero", [("steady_14", "rotor"), ("ss14_shear_flex", "blade"),
                                        ("ss14_yaw10_flex", "blade"), ("ff14_rigid", "blade"),
                                        ("ff14_flex", "blade")])
def test_default_rung_follows_what_the_deck_needs(case, aero):
    """Uniform hub-height wind on rigid blades -> rotor-effective; shear, yaw, full field or blade DOFs -> blade."""
    assert _deck(case).default_aero() == aero


def test_rotor_rung_refuses_a_full_field_with_advice():
    from mbsym.exceptions import WindInputError

    with pytest.raises(WindInputError, match="rotor_effective_wind"):
        _deck("ff14_rigid").model(aero="rotor")


def test_blade_rung_refuses_unknown_names_and_the_rotor_options():
    import mbsym as mb
    from mbsym.exceptions import ParameterError

    deck = _deck("ss14_shear_flex")
    with pytest.raises(ParameterError, match="aero must be one of"):
        deck.model(aero="vortex")
    with pytest.raises(ParameterError, match="own dynamic wake"):
        deck.model(aero="blade", dynamic_inflow=True)
    with pytest.raises(ParameterError, match="pitch must be one of"):
        deck.model(aero="blade", pitch="cyclic")
    with pytest.raises(ParameterError, match="individual"):
        mb.wind.OperatingTurbine(mb.wind.nrel5mw(), pitch="individual")
    with pytest.raises(ParameterError, match="BlOutNd"):
        deck.model(aero="blade", output_nodes=(0, 3))


def test_uniform_wind_inputs_follow_inflowwinds_power_law():
    """The deck's PLexp becomes the default of VShrExp; the wind at a node height z is V (z / H)^PLexp."""
    import casadi as ca

    model = _deck("ss14_shear_flex").model(aero="blade", dofs=["GenDOF"])
    wind = model.wind
    assert wind.defaults["VShrExp"] == pytest.approx(0.2)
    U = {n: ca.DM(v) for n, v in wind.defaults.items()}
    points = ca.DM([[0.0, 0.0, 30.0], [0.0, 0.0, 90.0], [0.0, 10.0, 150.0]]).T
    v = np.asarray(ca.evalf(wind.velocity(points, U)))
    np.testing.assert_allclose(v[0], 14.0 * (np.array([30.0, 90.0, 150.0]) / 90.0) ** 0.2, rtol=1e-12)
    np.testing.assert_allclose(v[1:], 0.0, atol=1e-12)


def test_discon_library_receives_the_blade_plants_root_moments():
    """One call of ROSCO's library from a blade-element plant: records 30-32 carry RootMyc1-3 [N m], 60 the
    azimuth [rad] (float32 swap array: 1e-6 relative)."""
    from _rosco import rosco_library
    from mbsym.wind.control import DisconController
    from mbsym.wind.operation.controllers import discon_in_loop

    lib = rosco_library()
    if lib is None:
        pytest.skip("ROSCO 2.10.6 library not available (no registry access)")
    model = _deck("ss14_shear_flex").model(aero="blade", dofs=["GenDOF"])
    d = model.dynamics()
    x = model.initial_state({"Wind1VelX": 14.0, "VShrExp": 0.2})
    meas = model.measurement_dynamics()
    from mbsym.wind.operation.controllers import held_commands

    u = d.input_vector({"Wind1VelX": 14.0, "VShrExp": 0.2, **held_commands(model, x)})
    y = np.asarray(meas.outputs(x, u, d.parameter_vector())).ravel()
    names = list(meas.output_names)
    with DisconController(lib, need(DECK / "DISCON.IN"), dt=0.00625) as handle:
        ctrl = discon_in_loop(handle, model=model)
        assert set(("RootMyc1", "RootMyc2", "RootMyc3", "Azimuth")) <= set(ctrl.measurements)
        assert set(("GenTq", "YawBrTAxp")) <= set(ctrl.measurements)        # records 23 and 53, as from ServoDyn
        ctrl.law(0.0, np.zeros(0), np.array([y[names.index(m)] for m in ctrl.measurements]))
        swap = handle.swap
        for k in range(3):
            assert swap[29 + k] == pytest.approx(1e3 * y[names.index(f"RootMyc{k + 1}")], rel=1e-6)
        assert swap[59] == pytest.approx(np.deg2rad(y[names.index("Azimuth")]), rel=1e-6)


def test_cli_runs_the_full_field_flexible_deck_as_written_and_tracks_openfast(tmp_path, capsys):
    """``mbsym simulate ff14_flex.fst`` (flap, edge, drivetrain, 2 tower modes; the TurbSim field; the deck's
    ElastoDyn Method 3) runs the blade-element rung with ABM4 and says so; its channels over the first 10 s against
    OpenFAST v5 + ROSCO's own record of the same deck (shared ff14_flex.csv). Measured when written, ε = mean|Δ| /
    range: TTDspFA 2.6 %, TTDspSS 1.3 %, RootMyc1 1.7 %, TwrBsMyt 2.5 %. Bound 5 %: over 660 s the issue's target
    is 3 % (met: 1.4-1.8 %); the first seconds add the start-up of two different controllers (ROSCO's library in
    the reference, our baseline here: their first-call filter states differ), which is why the speed and power
    loop channels are not checked on this short window."""
    from mbsym.cli import main
    from mbsym.wind.analysis.compare import read_csv

    fst = need(INPUTS / "ff14_flex" / "ff14_flex.fst")
    reference = need(INPUTS.parent / "ff14_flex.csv")
    out = tmp_path / "out.csv"
    assert main(["simulate", str(fst), "--controller", "baseline", "--tmax", "10", "--out", str(out)]) == 0
    text = capsys.readouterr().out
    assert "method abm4-held" in text and "ElastoDyn Method 3" in text
    ours, ref = read_csv(out), read_csv(reference)
    t = ref.time[ref.time <= 10.0 + 1e-9]
    for name in ("TTDspFA", "TTDspSS", "RootMyc1", "TwrBsMyt"):
        y_ref = ref.channel(name)[:t.size]
        eps = np.mean(np.abs(np.interp(t, ours.time, ours.channel(name)) - y_ref)) / np.ptp(y_ref)
        assert eps < 0.05, (name, eps)
