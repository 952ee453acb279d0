"""The waves' velocity at Morison members and their drag in waves (mbsym.wind.offshore.wave_kinematics; issue 20).

References, each independent of the code under test:
- Airy's closed forms for one regular component: ``u = ω A cosh κ(z+h)/sinh κh cos(ωt − κ·x)`` along the heading,
  ``w = −ω A sinh κ(z+h)/sinh κh sin(ωt − κ·x)``; at the surface ``w = dη/dt``, at the seabed ``w = 0``;
- SeaState's own output of the velocity at two points (``FVel1xi`` …, OpenFAST v5.0.0, the ``columns`` deck of
  test_offshore_morison.py in its ``WAVE_EDITS`` waves, 40 s; tests/data/openfast_morison/README.md): our reading of
  its grid must give its numbers, to its single precision and output format (measured: 3e-4 m/s RMS of 0.32 m/s; with
  SeaState's second-order kinematics on, 0.03 m/s: refused with members);
- the drag's closed form in a uniform current of the water instead of the platform (Galilean: the same load as the
  platform moving the other way), and none when the platform moves with the water;
- OpenFAST v5.0.0's decay of the ``columns`` deck in those waves (slow; tolerances there).
"""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np
import pytest

from mbsym.wind.offshore.wave_kinematics import flow_input_names, node_velocity, wave_flow
from mbsym.wind.offshore.waves import IncidentWaves, wave_number

from .conftest import FLOATING
from .test_offshore_morison import RHO, _drag, decks, wave_deck, write_deck  # noqa: F401 (the decks fixture)

DATA = Path(__file__).resolve().parents[2] / "data" / "openfast_morison"
G, H = 9.80665, 200.0


def _regular(amplitude: float, period: float, phase: float, heading: float, depth: float = H) -> IncidentWaves:
    n, dt = 400, 0.25
    k = round(n * dt / period)
    spectrum = np.zeros(n // 2 + 1, dtype=complex)
    spectrum[k] = 0.5 * n * amplitude * np.exp(1j * phase)
    return IncidentWaves(dt, spectrum, 2 * math.pi / (n * dt), heading, depth, G)


@pytest.mark.parametrize("depth", [H, 20.0, 5000.0])
def test_one_component_is_airys_wave(depth):
    waves = _regular(2.0, 10.0, 0.7, math.radians(30.0), depth)
    w = waves.frequencies[np.flatnonzero(waves.spectrum)[0]]
    kappa = wave_number(w, G, depth)
    t = waves.times()
    x, y, z = 12.0, -7.0, -8.0
    theta = w * t + 0.7 - kappa * (x * math.cos(math.radians(30.0)) + y * math.sin(math.radians(30.0)))
    v = node_velocity(waves, x, y, z)
    deep = kappa * depth > 700.0                    # cosh/sinh overflow: e^{κz}
    ch = math.exp(kappa * z) if deep else math.cosh(kappa * (z + depth)) / math.sinh(kappa * depth)
    sh = math.exp(kappa * z) if deep else math.sinh(kappa * (z + depth)) / math.sinh(kappa * depth)
    horizontal = 2.0 * w * ch * np.cos(theta)
    assert np.allclose(v[:, 0], math.cos(math.radians(30.0)) * horizontal, atol=1e-12)
    assert np.allclose(v[:, 1], math.sin(math.radians(30.0)) * horizontal, atol=1e-12)
    assert np.allclose(v[:, 2], -2.0 * w * sh * np.sin(theta), atol=1e-12)
    surface = node_velocity(waves, x, y, 0.0)[:, 2]                  # w = dη/dt at z = 0
    assert np.allclose(surface, -2.0 * w * np.sin(theta), atol=1e-12)
    if depth < 1000.0:
        assert np.allclose(node_velocity(waves, x, y, -depth)[:, 2], 0.0, atol=1e-12)   # no flow through the seabed


def _reference() -> dict[str, np.ndarray]:
    with (DATA / "waves_kinematics.csv").open() as fh:
        rows = list(csv.reader(fh))
    data = np.array(rows[1:], dtype=float)
    return {h.split("_[")[0]: data[:, k] for k, h in enumerate(rows[0])}


def test_velocity_read_off_seastates_grid_as_seastate_outputs_it(decks):
    from mbsym.wind.deck.seastate import read_seastate
    from mbsym.wind.offshore.waves import incident_waves

    fst = wave_deck(decks["columns"])
    sea = read_seastate(fst.parent / "fl_decay_a_SeaState.dat")
    waves = incident_waves(sea, gravity=G, water_depth=H)
    points = np.array([[-51.75, 0.0, -20.0], [-5.0, -5.0, -15.0], [0.0, 0.0, 3.0]])
    flow = wave_flow(waves, sea, points)
    ref = _reference()
    got = flow.at(ref["Time"])
    for j, name in ((0, "FVel1xi"), (2, "FVel1zi"), (3, "FVel2xi"), (5, "FVel2zi")):
        assert np.sqrt(np.mean((got[:, j] - ref[name]) ** 2)) < 2e-3 * np.std(ref[name]), name
    assert np.all(got[:, 6:] == 0.0)                                  # above the still-water level: none
    exact = node_velocity(waves, -51.75, 0.0, -20.0)                   # the grid's reading against the exact field
    assert 1e-4 < np.sqrt(np.mean((flow.velocity[:, 0, 0] - exact[:, 0]) ** 2)) / np.std(exact[:, 0]) < 0.02
    assert flow_input_names(2) == ("MorisonU1xi", "MorisonU1yi", "MorisonU1zi", "MorisonU2xi", "MorisonU2yi",
                                   "MorisonU2zi")


def test_drag_in_moving_water_is_the_drag_of_the_platform_moving_the_other_way(decks):
    drag = _drag(decks["columns"])
    rng = np.random.default_rng(3)
    current = np.tile([0.8, -0.3, 0.2], drag.n_flow)
    still = drag.load(np.zeros(6), [-0.8, 0.3, -0.2, 0, 0, 0])
    assert np.allclose(drag.load(np.zeros(6), np.zeros(6), current), still, rtol=1e-12, atol=1e-6)
    surge = drag.load(np.zeros(6), np.zeros(6), np.tile([1.0, 0.0, 0.0], drag.n_flow))
    assert surge[0] == pytest.approx(0.5 * RHO * 0.6 * (10.0 + 3 * 12.5) * 20.0, rel=1e-9)   # ½ρC_dDL U², +x
    flow = rng.normal(0.0, 0.5, 3 * drag.n_flow)
    q = np.array([1.0, -0.5, 0.2, 0.0, 0.0, 0.0])
    riding = drag.load(q, np.r_[flow[:3], 0, 0, 0], np.tile(flow[:3], drag.n_flow))      # moving with the water
    assert np.abs(riding).max() < 1e-3


def test_unmodelled_wave_settings_with_members_are_named(decks, tmp_path):
    from mbsym.wind.deck.hydrodyn import read_hydrodyn
    from mbsym.wind.deck.seastate import read_seastate
    from mbsym.wind.offshore.morison import morison_problems

    fst = wave_deck(decks["columns"])
    hd = read_hydrodyn(fst.parent / "fl_decay_a_HydroDyn.dat")
    path = fst.parent / "fl_decay_a_SeaState.dat"
    assert morison_problems(hd, read_seastate(path)) == []
    qtf = tmp_path / "qtf_SeaState.dat"
    qtf.write_text(path.read_text().replace("False     WvSumQTF", "True      WvSumQTF"))
    assert any("second-order kinematics" in p for p in morison_problems(hd, read_seastate(qtf)))
    moved = tmp_path / "moved_HydroDyn.dat"
    text = (fst.parent / "fl_decay_a_HydroDyn.dat").read_text()
    moved.write_text(text.replace("0   WaveDisp", "1   WaveDisp"))
    assert any("WaveDisp = 1" in p for p in morison_problems(read_hydrodyn(moved), read_seastate(path)))


@pytest.mark.slow
def test_decay_in_waves_with_members_matches_openfast(decks, tmp_path):
    """300 s of the ``columns`` decay in JONSWAP waves (Hs 4 m, Tp 10 s) on ``mbsym simulate`` against OpenFAST's
    (tests/data/openfast_morison/waves.csv), t ≥ 20 s: ε ≤ 1.5 % on surge, heave and pitch (measured 0.40 %,
    0.53 %, 0.70 %; with the waves' velocity at the members left out 4.8 %, 0.26 %, 1.6 %)."""
    from mbsym.cli import main
    from mbsym.wind.analysis.compare import error_metrics, read_csv

    ref = _reference_decay()
    out = tmp_path / "run.csv"
    assert main(["simulate", str(wave_deck(decks["columns"])), "--tmax", "300", "--out", str(out)]) == 0
    run = read_csv(out)
    late = ref["Time"] >= 20.0
    for channel, bound in (("PtfmSurge", 0.015), ("PtfmPitch", 0.015), ("PtfmHeave", 0.015)):
        eps, _ = error_metrics(run.time, run.channel(channel), ref["Time"][late], ref[channel][late])
        assert eps <= bound, (channel, eps)


def _reference_decay() -> dict[str, np.ndarray]:
    with (DATA / "waves.csv").open() as fh:
        rows = list(csv.reader(fh))
    data = np.array(rows[1:], dtype=float)
    return {h.split("_[")[0]: data[:, k] for k, h in enumerate(rows[0])}
