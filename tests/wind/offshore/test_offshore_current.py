"""SeaState's steady current on the members' drag (mbsym.wind.offshore.current, .morison).

References, each independent of the code under test:
- the closed form of SeaState's standard profile (sub-surface 1/7 power law, linear near-surface part, uniform
  part, each along its heading; zero below the seabed and above the still-water level: ``Current.f90``);
- at the nodes of SeaState's cosine-spaced kinematics grid the interpolated current equals the profile (the
  interpolation is exact there);
- the drag of a steady current on a vertical cylinder at rest, ``½ ρ C_d D Σ |U| U Δl``, and its first-order
  damping of the platform's motion, ``∂F/∂ẋ = −½ ρ C_d D Σ (|U| I + U Uᵀ/|U|) Δl`` across the member (a finite
  difference of the load);
- OpenFAST v5.0.0 runs with ``CurrMod`` 1 (tests/data/openfast_morison/README.md, "With a current").
"""

from __future__ import annotations

import math
import re
import shutil
from pathlib import Path

import numpy as np
import pytest

from mbsym.exceptions import ParameterError, UnsupportedFeatureError
from mbsym.wind.deck.seastate import read_seastate
from mbsym.wind.offshore.current import SeaCurrent, current_at, sea_current

from .test_offshore_morison import CASE, RHO, _reference, needs_deck, wave_deck, write_deck

#: The profile of the OpenFAST runs: three parts at three headings.
CURRENT = {"CurrMod": "1", "CurrSSV0": "0.6", "CurrSSDir": "10", "CurrNSRef": "20", "CurrNSV0": "0.4",
           "CurrNSDir": "30", "CurrDIV": "0.3", "CurrDIDir": "-60"}


def edit(path: Path, edits: dict[str, str]) -> Path:
    """Set ``<value>  <key>`` lines of an OpenFAST input file."""
    text = path.read_text()
    for key, value in edits.items():
        text, n = re.subn(rf"^\s*\S+(\s+{key}\b)", lambda m, v=value: f"{v:>12}{m.group(1)}", text, count=1,
                          flags=re.M)
        assert n == 1, key
    path.write_text(text)
    return path


def seastate(tmp_path: Path, **edits: str):
    path = tmp_path / "sea.dat"
    shutil.copy(CASE / "fl_decay_a_SeaState.dat", path)
    return read_seastate(edit(path, CURRENT | edits))


def _profile(z: float) -> np.ndarray:
    """SeaState's CurrMod 1 written out for :data:`CURRENT` and a 200 m depth."""
    parts = ((0.6 * ((z + 200.0) / 200.0) ** (1 / 7), 10.0), (max(0.4 * (z + 20.0) / 20.0, 0.0), 30.0),
             (0.3, -60.0))
    return np.array([sum(v * math.cos(math.radians(d)) for v, d in parts),
                     sum(v * math.sin(math.radians(d)) for v, d in parts), 0.0])


@needs_deck
def test_profile_matches_seastate_closed_form(tmp_path):
    current = sea_current(seastate(tmp_path), 200.0)
    for z in (0.0, -5.0, -20.0, -35.0, -199.0, -200.0):
        assert np.allclose(current.velocity(z)[0], _profile(z), atol=1e-12), z
    assert not current.velocity([0.5, -200.5]).any()                            # above the water, below the seabed


@needs_deck
def test_grid_interpolation_is_exact_at_the_grid_levels(tmp_path):
    """NZ = 15 cosine-spaced levels from −200 m to 0 (in single precision, as SeaState holds them: the deepest is
    the seabed, where the sub-surface current is zero): at the levels the current is the profile, between them the
    grid's interpolant (off by up to a few per cent near the seabed, where the levels are 22 m apart)."""
    sea = seastate(tmp_path)
    current = sea_current(sea, 200.0)
    levels = [float(np.float32(-(1.0 - math.cos(k * math.pi / 28)) * 200.0)) for k in range(15)]   # single, as SeaState
    got = current_at(current, sea, [(30.0 * k, -7.0, z) for k, z in enumerate(levels)])
    assert np.allclose(got, current.velocity(levels), atol=1e-12)       # off the x-y grid too: clamped, same value
    between = current_at(current, sea, [(0, 0, -10.0), (0, 0, -190.0)])
    assert np.allclose(between[0], _profile(-10.0), atol=2e-3)            # dense near the surface
    assert not np.allclose(between[1], _profile(-190.0), atol=1e-2)      # coarse near the seabed


@needs_deck
def test_unmodelled_and_invalid_currents_are_refused(tmp_path):
    with pytest.raises(UnsupportedFeatureError, match="CurrMod = 2"):
        sea_current(seastate(tmp_path, CurrMod="2"), 200.0)
    with pytest.raises(ParameterError, match="DEFAULT"):
        sea_current(seastate(tmp_path, CurrSSDir='"DEFAULT"'), 200.0)        # still water: SeaState refuses it
    with pytest.raises(ParameterError, match="CurrNSV0"):
        sea_current(seastate(tmp_path, CurrNSV0="-0.1"), 200.0)
    with pytest.raises(ParameterError, match="CurrNSRef"):
        sea_current(seastate(tmp_path, CurrNSRef="0"), 200.0)
    assert sea_current(seastate(tmp_path, CurrMod="0"), 200.0) is None


def test_current_drag_and_its_damping_on_a_vertical_cylinder():
    """A 20 m wet column (D 10 m, C_d 0.6) in a uniform 0.8 m/s current at 30°: the load at rest and its slope in
    the platform's velocity against the closed forms."""
    from mbsym.wind.offshore.morison import MorisonDrag

    n = 21
    length = np.full(n, 1.0)
    length[[0, -1]] = 0.5
    heading = math.radians(30.0)
    u = 0.8 * np.array([math.cos(heading), math.sin(heading), 0.0])
    drag = MorisonDrag(np.column_stack([np.zeros(n), np.zeros(n), np.linspace(-20.0, 0.0, n)]),
                       np.tile([0.0, 0.0, 1.0], (n, 1)), length, np.zeros(n), np.full(n, 0.6 * 10.0), np.zeros(n),
                       np.zeros((0, 3)), np.zeros((0, 3)), np.zeros(0), np.zeros(0, dtype=bool), RHO,
                       current=np.tile(u, (n, 1)))
    scale = 0.5 * RHO * 0.6 * 10.0 * 20.0
    f = np.asarray(drag.load(np.zeros(6), np.zeros(6)), dtype=float).ravel()
    assert np.allclose(f[:3], scale * 0.8 * u, rtol=1e-9)
    assert f[3] == pytest.approx(10.0 * scale * 0.8 * u[1], rel=1e-9)             # (0, 0, −10) × F
    assert f[4] == pytest.approx(-10.0 * scale * 0.8 * u[0], rel=1e-9)
    h = 1e-6
    slope = np.column_stack([(np.asarray(drag.load(np.zeros(6), h * e), dtype=float).ravel()[:3] - f[:3]) / h
                             for e in np.eye(6)[:3]])
    across = np.diag([1.0, 1.0, 0.0])
    expected = -scale * (0.8 * across + np.outer(u, u) / 0.8)
    assert np.allclose(slope, expected, rtol=1e-5, atol=1e-3 * scale)


def test_seacurrent_is_zero_outside_the_water_column():
    current = SeaCurrent(1.0, 0.0, 10.0, 0.0, 0.0, 0.0, 0.0, 50.0)
    assert np.allclose(current.velocity([0.0, -50.0, -50.1, 0.1])[:, 0], [1.0, 0.0, 0.0, 0.0])


def current_deck(root: Path, variant: str, waves: bool) -> Path:
    """:func:`write_deck`'s ``variant`` with :data:`CURRENT` in its SeaState (and :func:`wave_deck`'s sea, the
    sub-surface current along the waves' heading 15°: ``CurrSSDir = DEFAULT``): the decks of the OpenFAST runs."""
    fst = write_deck(root, variant)
    sea = fst.parent / "fl_decay_a_SeaState.dat"
    if waves:
        wave_deck(fst)
        edit(sea, CURRENT | {"CurrSSDir": '"DEFAULT"', "WaveDir": "15"})
    else:
        edit(sea, CURRENT)
    return fst


def _compare(fst: Path, reference: str, tmp_path: Path, bounds: dict[str, float]) -> dict[str, float]:
    from mbsym.cli import main
    from mbsym.wind.analysis.compare import error_metrics, read_csv

    ref = _reference(reference)
    out = tmp_path / "run.csv"
    assert main(["simulate", str(fst), "--tmax", "300", "--out", str(out)]) == 0
    run = read_csv(out)
    for channel, bound in bounds.items():
        eps, _ = error_metrics(run.time, run.channel(channel), ref["Time"], ref[channel])
        assert eps <= bound, (channel, eps)
    return {"PtfmSurge": float(run.channel("PtfmSurge").mean()), "HydroFxi": float(run.channel("HydroFxi").mean())}


@needs_deck
def test_decay_in_a_current_matches_openfast(tmp_path):
    """The ``braces`` members (drag across inclined braces, tapered column, one-sided plates) in still water with
    the three-part current, 300 s against OpenFAST v5.0.0 (tests/data/openfast_morison/braces_current.csv).
    Measured ε: surge 0.21 %, heave 0.30 %, pitch 0.32 %, sway 1.96 %, yaw 2.5 % (ranges 0.5 m and 0.02°); means
    of surge 4.431 m (OpenFAST 4.426 m) and HydroFxi 293.5 kN (293.6 kN). Bounds: 1.5 % as the decays without a
    current (test_offshore_morison.py), 4 % on sway and yaw, 0.5 % on the means. The current moves OpenFAST's mean
    surge from 0.7 to 4.4 m (its run without the current against this one: ε 45 %)."""
    got = _compare(current_deck(tmp_path / "deck", "braces", waves=False), "braces_current", tmp_path,
                   {"PtfmSurge": 0.015, "PtfmHeave": 0.015, "PtfmPitch": 0.015, "PtfmSway": 0.04, "PtfmYaw": 0.04})
    ref = _reference("braces_current")
    for channel, value in got.items():
        assert value == pytest.approx(ref[channel].mean(), rel=5e-3), channel
    still = _reference("braces")                                    # OpenFAST without the current: far off
    assert abs(still["PtfmSurge"][still["Time"] > 150].mean() - ref["PtfmSurge"][ref["Time"] > 150].mean()) > 3.0


@pytest.mark.slow
@needs_deck
def test_strip_theory_platform_in_waves_and_a_current_matches_openfast(tmp_path):
    """``morison_only`` (``PotMod`` 0: columns and pontoons as strip-theory members) in JONSWAP waves (Hs 4 m) from
    15° with the current, the sub-surface part along the waves (``DEFAULT``), against OpenFAST v5.0.0
    (morison_only_current_waves.csv). Measured ε: surge 0.39 %, heave 0.26 %, pitch 1.12 %, sway 2.2 %, yaw 1.6 %;
    without the current in mbsym surge is off by ε 101 %. Bounds: 1.5 % (2 % on pitch, as in still water's
    decays of this deck 1.05 %), 4 % on sway and yaw; mean surge (6.29 m) within 0.5 %."""
    got = _compare(current_deck(tmp_path / "deck", "morison_only", waves=True), "morison_only_current_waves",
                   tmp_path, {"PtfmSurge": 0.015, "PtfmHeave": 0.015, "PtfmPitch": 0.02, "PtfmSway": 0.04,
                              "PtfmYaw": 0.04})
    assert got["PtfmSurge"] == pytest.approx(_reference("morison_only_current_waves")["PtfmSurge"].mean(), rel=5e-3)


@needs_deck
def test_floating_current_example_runs_and_matches_its_closed_form():
    """examples/floating_current.py: the drag at rest equals ½ ρ C_d Σ D L U² (its own closed form, printed beside
    it, to the printed 0.1 kN), and the mean surge grows with the current."""
    import subprocess
    import sys

    root = Path(__file__).resolve().parents[3]
    out = subprocess.run([sys.executable, str(root / "examples" / "floating_current.py")], capture_output=True,
                         text=True, timeout=300, check=True).stdout
    rows = [[float(v) for v in line.split()] for line in out.splitlines()[1:6]]
    assert all(abs(drag - closed) <= 0.11 for _, drag, closed, _ in rows)
    assert all(b[3] > a[3] > 0 for a, b in zip(rows, rows[1:]))
