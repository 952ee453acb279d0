"""MoorDyn's lumped-mass lines in motion (mbsym.wind.offshore.lumped_dynamics): closed forms, statics, OpenFAST's log.

Independent references: the transverse and axial vibration of one node between two stretched segments (closed
forms with the added mass and MoorDyn's damping-ratio convention), the lines at rest against the lumped statics of
:mod:`mbsym.wind.offshore.lumped_line` (a separate closed-form solution), and OpenFAST v5.0.0's own record of
MoorDyn's initial relaxation of the shared fl_steady_13 deck (tests/data/openfast_floating_surge).
"""

from __future__ import annotations

import math
import re
import warnings
from pathlib import Path

import numpy as np
import pytest

from mbsym.exceptions import ParameterError, UnsupportedFeatureError
from mbsym.wind.offshore.lumped_dynamics import DynamicLine, DynamicMooring, LineRelaxation

from .conftest import SEMI

DATA = Path(__file__).resolve().parents[2] / "data" / "openfast_floating_surge"
RHO, G = 1025.0, 9.80665


def _two_segments(*, damping_ratio=0.0, ca_n=0.8, ca_t=0.0, strain=0.01):
    """One node between two segments of 10 m, stretched horizontally by ``strain``, neutrally buoyant."""
    d, ea, l = 0.2, 1.0e8, 10.0
    m = RHO * math.pi * d ** 2 / 4                         # no wet weight: no sag
    ba = damping_ratio * l * math.sqrt(ea * m)
    span = 2 * l * (1 + strain)
    line = DynamicLine(np.array([0.0, 0.0, -50.0]), np.array([span, 0.0, -50.0]), 2 * l, 2, d, m, ea, ba,
                       0.0, 0.0, ca_n, ca_t)
    return DynamicMooring((line,), RHO, G, 1000.0, 3.0e6, 3.0e5, 1.0e-4, LineRelaxation(t_max=0.0)), line


def _run(moor, x0, seconds, n=100):
    f = moor.step(n)
    rf = moor.lines[0].fairlead.reshape(3, 1)
    xs, x = [x0], x0
    for _ in range(int(round(seconds / (n * moor.time_step)))):
        x = np.asarray(f(x, rf, np.zeros((3, 1)), moor.time_step, 1.0)[0], dtype=float).ravel()
        xs.append(x)
    return np.arange(len(xs)) * n * moor.time_step, np.array(xs)


def _period(t, z):
    """Mean period from the upward zero crossings of ``z`` [s]."""
    up = np.where((z[:-1] < 0) & (z[1:] >= 0))[0]
    tc = t[up] - z[up] * (t[up + 1] - t[up]) / (z[up + 1] - z[up])
    return float(np.mean(np.diff(tc)))


def test_a_stretched_node_vibrates_across_at_the_string_frequency_with_its_added_mass():
    """ω² = 2 T / (ℓ (m l + ρ A l C_an)), T = EA ε, ℓ the stretched half span: the drag off, no weight in water.
    Tolerance 0.2 %: the amplitude (1 cm on 10 m) and RK2 at 0.1 ms give well under it."""
    moor, line = _two_segments()
    l, strain = line.segment_length, 0.01
    x0 = np.array([l * (1 + strain), 0.0, -50.0 + 0.01, 0.0, 0.0, 0.0])
    sample = 0.01
    t, xs = _run(moor, x0, 20.0, n=int(round(sample / moor.time_step)))
    mass = line.mass_per_length * l + RHO * line.area * l * line.added_mass_normal
    omega = math.sqrt(2 * line.axial_stiffness * strain / (l * (1 + strain) * mass))
    period = _period(t, xs[:, 2] + 50.0)
    assert abs(period / (2 * math.pi / omega) - 1) < 2e-3, (period, 2 * math.pi / omega)


def test_a_negative_ba_is_moordyns_damping_ratio_of_a_segment():
    """BA = −ζ given: ``BA = ζ l √(EA m)`` (MoorDyn's convention). The node between two segments then vibrates
    along the line with stiffness 2EA/l and damping 2BA/l: damping ratio ζ/√2 (no axial added mass). The logarithmic
    decrement of the simulated motion gives it within 2 %."""
    zeta = 0.05
    moor, line = _two_segments(damping_ratio=zeta, ca_t=0.0)
    l = line.segment_length
    x0 = np.array([l * 1.01 + 0.001, 0.0, -50.0, 0.0, 0.0, 0.0])
    n = 2
    t, xs = _run(moor, x0, 0.6, n=n)
    u = xs[:, 0] - l * 1.01
    peaks = [i for i in range(1, len(u) - 1) if u[i] > u[i - 1] and u[i] >= u[i + 1] and u[i] > 0]
    a, b = peaks[0], peaks[3]
    delta = math.log(u[a] / u[b]) / 3
    measured = delta / math.sqrt(4 * math.pi ** 2 + delta ** 2)
    assert abs(measured / (zeta / math.sqrt(2)) - 1) < 0.02, measured


def _deck_lines(threshold=None, t_max=None):
    from dataclasses import replace

    from mbsym.wind.deck.moordyn import read_moordyn
    from mbsym.wind.offshore.lumped_dynamics import dynamic_mooring_from_moordyn
    from mbsym.wind.offshore.mooring import mooring_from_moordyn

    path = SEMI / "IEA-15-240-RWT-UMaineSemi_MoorDyn.dat"
    if not path.is_file():
        pytest.skip(f"shared floating deck not found at {path}")
    md = read_moordyn(path)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        system = mooring_from_moordyn(md, water_density=RHO, gravity=G, water_depth=200.0, line_statics="lumped")
    moving = dynamic_mooring_from_moordyn(md, system, gravity=G, depth=200.0, coupling_dt=0.025)
    if threshold is not None:
        moving = replace(moving, relaxation=replace(moving.relaxation, threshold=threshold, t_max=t_max))
    return system, moving


def _fairleads(system, q):
    from mbsym.wind.offshore._casadi import euler_zyx

    R = np.array(euler_zyx(q[3:6]), dtype=float)
    return np.stack([q[:3] + R @ p for p in system.fairleads], axis=1)


Q13 = np.array([16.3, 0.0, -0.44, 0.0, math.radians(2.87), 0.0])      # fl_steady_13's initial platform position


def test_the_relaxation_reproduces_moordyns_in_openfast_on_the_shared_deck():
    """The deck's own relaxation (dtIC 1 s, TmaxIC 60 s, CdScaleIC 4, threshIC 1e-3; the lines start on the
    catenaries to the undisplaced fairleads and are held at fl_steady_13's initial position) against OpenFAST
    v5.0.0's log of the same: the first check's tension (2.92014e8 N: the upwind line stretched 16 m at once) to 1e-4
    (observed 1.4e-6, the log's 6 digits), every one of the 216 checks within 0.1 % (observed 0.042 %), converged at
    the same 0.1 s check (21.6 s), and the fairlead forces it converged to within 0.1 % (observed 0.034 %)."""
    system, moving = _deck_lines()
    text = (DATA / "fl_steady_13_moordyn_init.log").read_text()
    log = {round(float(t), 1): float(v) for t, v in re.findall(r"t=([\d.]+)\s+FairTen 1: ([\d.E+-]+)", text)}
    rf = _fairleads(system, Q13)
    relaxed = moving.relax(rf)
    assert relaxed.converged and abs(relaxed.time - 21.6) < 1e-9, relaxed.time
    # the checks again, to compare each with the log
    x = moving.at_rest(np.stack([ln.fairlead for ln in moving.lines], axis=1))
    n, h = moving.substeps(0.1)
    step = moving.step(n)
    worst = 0.0
    for k in range(1, 217):
        out = step(x, rf, np.zeros((3, 3)), h, moving.relaxation.drag_scale)
        x, tension = np.asarray(out[0], dtype=float).ravel(), float(out[3][0])
        if k == 1:
            assert abs(tension / log[0.1] - 1) < 1e-4, (tension, log[0.1])
        worst = max(worst, abs(tension / log[round(0.1 * k, 1)] - 1))
    assert worst < 1e-3, worst
    forces = re.findall(r"Fairlead forces: ([-\d.E+]+), ([-\d.E+]+), ([-\d.E+]+)", text)
    ours = np.asarray(moving.rhs(relaxed.state, rf, np.zeros((3, 3)), 1.0)[1], dtype=float)
    for k, row in enumerate(forces):
        theirs = np.array([float(v) for v in row])
        assert np.linalg.norm(ours[:, k] - theirs) < 1e-3 * np.linalg.norm(theirs), (k, ours[:, k], theirs)


def test_relaxed_lines_pull_as_the_lumped_lines_at_rest():
    """Relaxed to 1e-5 the moving lines hold the platform with the fairlead forces of the lumped statics
    (:class:`LumpedLine`, an independent closed-form solution of the same chain): tensions within 3e-4 (the statics
    take the node where the line leaves the seabed as hanging: 1.1e-4 against a full nodal balance)."""
    system, moving = _deck_lines(threshold=1e-5, t_max=300.0)
    rf = _fairleads(system, Q13)
    relaxed = moving.relax(rf)
    assert relaxed.converged
    ours = np.asarray(moving.rhs(relaxed.state, rf, np.zeros((3, 3)), 1.0)[2], dtype=float).ravel()
    statics = system.tensions(Q13)
    assert np.all(np.abs(ours / statics - 1) < 3e-4), (ours, statics)


def test_bad_lines_and_options_are_refused():
    with pytest.raises(ParameterError, match="segments"):
        DynamicLine(np.zeros(3), np.ones(3), 10.0, 1, 0.1, 10.0, 1e8, 0.0, 1.0, 0.1, 1.0, 0.0)
    with pytest.raises(ParameterError, match="diameter"):
        DynamicLine(np.zeros(3), np.ones(3), 10.0, 4, -0.1, 10.0, 1e8, 0.0, 1.0, 0.1, 1.0, 0.0)
    with pytest.raises(ParameterError, match="threshold"):
        LineRelaxation(threshold=0.0)
    _, moving = _deck_lines()
    with pytest.raises(ParameterError, match="time_step"):
        from dataclasses import replace

        replace(moving, time_step=0.0)


def test_rk4_scheme_and_bending_stiffness_are_refused(tmp_path):
    from mbsym.wind.deck.moordyn import read_moordyn
    from mbsym.wind.offshore.lumped_dynamics import dynamic_mooring_from_moordyn

    system, _ = _deck_lines()
    text = (SEMI / "IEA-15-240-RWT-UMaineSemi_MoorDyn.dat").read_text()
    rk4 = tmp_path / "rk4.dat"
    rk4.write_text(text.replace("0.001    dtM", "RK4      tScheme\n0.001    dtM"))
    with pytest.raises(UnsupportedFeatureError, match="tScheme"):
        dynamic_mooring_from_moordyn(read_moordyn(rk4), system, gravity=G, depth=200.0, coupling_dt=0.025)
    bent = tmp_path / "ei.dat"
    bent.write_text(text.replace("-1.0      0    2.0", "-1.0      5e4  2.0"))
    with pytest.raises(UnsupportedFeatureError, match="EI"):
        dynamic_mooring_from_moordyn(read_moordyn(bent), system, gravity=G, depth=200.0, coupling_dt=0.025)
