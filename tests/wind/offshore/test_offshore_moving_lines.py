"""MoorDyn's lines in motion beside the floating operating turbine (lines_in_loop, ``--mooring-lines``).

References: the shared OpenFAST v5.0.0 run of fl_steady_13 (its first 20 s carry MoorDyn's start: the lines
relaxed to 0.1 % and still swinging at t = 0), and the quasi-static rung of the same model (the lines at rest give
the same statics: a model with moving lines trims where the quasi-static one does).
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from mbsym.exceptions import OptionError, ParameterError

from .conftest import FLOATING


def _deck():
    fst = FLOATING / "cases" / "fl_steady_13" / "fl_steady_13.fst"
    if not fst.is_file():
        pytest.skip(f"shared floating deck not found at {fst}")
    return fst


def test_the_deck_as_written_starts_as_openfast_with_moordyns_relaxed_lines(tmp_path):
    """``mbsym simulate fl_steady_13.fst`` (rotor-effective rung for speed, 20 s): by default MoorDyn's lines move,
    relaxed as MoorDyn relaxes them. Against the shared OpenFAST run over 0-20 s: surge within 1 cm and the fairlead
    tensions within 15 kN at every output (observed 4.7 mm, 6.0 / 5.4 / 5.4 kN; the quasi-static lines, which start
    at rest, are 0.108 m and 17.7 / 45.5 kN off: the bounds catch them)."""
    from mbsym.cli import main
    from mbsym.wind.analysis.compare import read_csv

    fst = _deck()
    ref_csv = FLOATING / "fl_steady_13.csv"
    if not ref_csv.is_file():
        pytest.skip(f"shared floating reference not found at {ref_csv}")
    out = tmp_path / "lines.csv"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert main(["simulate", str(fst), "--controller", "baseline", "--aero", "rotor", "--tmax", "20",
                     "--out", str(out)]) == 0
    ours, ref = read_csv(out), read_csv(ref_csv)
    t, tr = np.asarray(ours.time), np.asarray(ref.time)
    keep = tr <= 20.0
    for name, bound in (("PtfmSurge", 0.01), ("FAIRTEN1", 1.5e4), ("FAIRTEN2", 1.5e4), ("FAIRTEN3", 1.5e4)):
        mine = np.interp(tr[keep], t, np.asarray(ours.channel(name)))
        err = np.max(np.abs(mine - np.asarray(ref.channel(name))[keep]))
        assert err < bound, (name, err)


def test_moving_lines_hold_the_quasi_static_statics(tmp_path):
    """The platform with moving lines (their dynamic part as inputs, zero at rest) loads the platform exactly as the
    quasi-static lumped lines at any position (its trims and linear models are theirs), and it carries the fairlead
    nodes' mass (m l/2 + added mass, 6.4 t per line here) in its mass matrix instead of the lines' drag and inertia."""
    from mbsym.wind.deck.openfast import read_openfast
    from mbsym.wind.offshore.operating import floating_platform

    turbine = read_openfast(_deck())
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        quasi = floating_platform(turbine)
        moving = floating_platform(turbine, mooring_lines="dynamic")
    assert moving.moving_lines is not None and moving.mooring.dynamics is None
    assert moving.sea_inputs[-9:] == ("MoorDFxi", "MoorDFyi", "MoorDFzi", "MoorDMxi", "MoorDMyi", "MoorDMzi",
                                      "MoorDTen1", "MoorDTen2", "MoorDTen3")
    q = np.array([16.3, 0.4, -0.44, 0.01, 0.05, -0.02])
    a = quasi.loads(q, np.zeros(6), np.zeros(quasi.n_radiation))
    b = moving.loads(q, np.zeros(6), np.zeros(moving.n_radiation))
    np.testing.assert_allclose(np.asarray(b["load"]), np.asarray(a["load"]), rtol=1e-12, atol=1e-6)
    np.testing.assert_allclose(np.asarray(b["tension"]), np.asarray(a["tension"]), rtol=1e-12)
    surge_mass = float(np.asarray(b["mass"])[0, 0])
    line = moving.moving_lines.lines[0]
    node = line.mass_per_length * line.segment_length / 2
    assert 3 * node < surge_mass < 3 * node * 1.2, surge_mass          # plus the nodes' added mass across
    with pytest.raises(ParameterError, match="mooring_lines"):
        floating_platform(turbine, mooring_lines="moving")


def test_the_flag_is_refused_where_it_would_do_nothing(capsys):
    from mbsym.cli import main
    from mbsym.cli.mooring_lines import with_mooring_lines

    assert main(["simulate", "--wind", "steady:12", "--mooring-lines", "dynamic", "--tmax", "1"]) == 2
    assert "built-in NREL 5 MW stands on land" in capsys.readouterr().err
    with pytest.raises(OptionError, match="built-in NREL 5 MW"):
        with_mooring_lines(None, "quasi-static")
    decay = FLOATING / "cases" / "fl_decay_a" / "fl_decay_a.fst"
    if decay.is_file():            # --structure-only: ElastoDyn alone, no mooring
        assert main(["simulate", str(decay), "--structure-only", "--mooring-lines", "dynamic", "--tmax", "1"]) == 2
        assert "no MoorDyn lines to move" in capsys.readouterr().err


def test_the_decay_deck_as_written_moves_moordyns_lines(tmp_path):
    """``mbsym simulate fl_decay_a.fst`` (no AeroDyn: the structure with the water and the mooring) moves MoorDyn's
    lines by default too. Against the shared OpenFAST run over 0-30 s, rms error / range: surge, heave, pitch within
    0.2 % and TTDspFA within 0.5 % (observed 0.03, 0.06, 0.02, 0.02 %; quasi-static lines 0.51, 0.22, 0.21, 3.8 %:
    the tower's 0.5 Hz ringing is damped by the lines' own motion), FAIRTEN1 within 2 % (observed 0.34 %;
    quasi-static 26 %: they start at rest where MoorDyn's swing). Over 600 s the run is within 0.09 % on every
    platform and tower channel (docs/offshore.md §3c)."""
    from mbsym.cli import main
    from mbsym.wind.analysis.compare import read_csv

    decay = FLOATING / "cases" / "fl_decay_a" / "fl_decay_a.fst"
    ref_csv = FLOATING / "fl_decay_a.csv"
    if not (decay.is_file() and ref_csv.is_file()):
        pytest.skip(f"shared floating decay not found at {decay}")
    out = tmp_path / "decay.csv"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert main(["simulate", str(decay), "--tmax", "30", "--out", str(out)]) == 0
    ours, ref = read_csv(out), read_csv(ref_csv)
    t, tr = np.asarray(ours.time), np.asarray(ref.time)
    keep = tr <= 30.0 + 1e-9
    for name, bound in (("PtfmSurge", 0.002), ("PtfmHeave", 0.002), ("PtfmPitch", 0.002), ("TTDspFA", 0.005),
                        ("FAIRTEN1", 0.02)):
        want = np.asarray(ref.channel(name))[keep]
        got = np.interp(tr[keep], t, np.asarray(ours.channel(name)))
        assert np.sqrt(np.mean((got - want) ** 2)) / np.ptp(want) < bound, name


def test_a_deck_without_moordyn_refuses_moving_lines():
    from mbsym.wind.operation.deck import builtin_deck, replace

    with pytest.raises(OptionError, match="has none"):
        replace(builtin_deck(), mooring_lines="dynamic").platform
