"""MoorDyn's lumped-mass line at rest (``mbsym.wind.offshore.lumped_line``, issue 20).

References (independent of the closed-form spans the module solves):

- one segment: a straight elastic bar, ``T = EA (ℓ/L − 1)``, with the fairlead node's half weight (hand formula);
- a fully suspended line: the lumped chain tends to the continuous elastic catenary as the segments shrink, at
  second order in 1/N (midpoint-rule quadrature of the catenary's integrals): measured error in H 1.6e-4, 9.9e-6,
  6.1e-7 at N = 50, 200, 800 (ratio 16 per 4x);
- the full nodal balance of the VolturnUS-S line with MoorDyn's seabed springs (every internal node's position
  solved by Newton's method in numpy, a dense 98 x 98 Jacobian by finite differences): (H, V) within 1.5e-4 (observed
  2e-5 to 1.0e-4 with the position of the node leaving the seabed, which its spring partly carries and the closed
  form takes as hanging) and the stiffness ∂H/∂l
  within 1.5 % of the catenary's (observed 0.9 %) where it ripples by ±4-5 %.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from mbsym.exceptions import OptionError, ParameterError
from mbsym.wind.offshore.catenary import CatenaryLine, wet_weight
from mbsym.wind.offshore.lumped_line import LumpedLine

from .conftest import SEMI

WEIGHT = wet_weight(685.0, 0.333, 1025.0, 9.80665)       # the VolturnUS-S chain (its MoorDyn file)
LINE = CatenaryLine(850.0, WEIGHT, 3.27e9)
PENETRATION = WEIGHT / (3.0e6 * 0.333)                   # w / (kBot d)


def test_one_segment_is_an_elastic_bar_with_half_the_weight_at_the_fairlead():
    line = CatenaryLine(100.0, 500.0, 1.0e8)
    l, h = 90.0, 50.0                                    # chord 102.96 m > 100 m: taut
    chord = math.hypot(l, h)
    tension = 1.0e8 * (chord / 100.0 - 1.0)
    h0, v0 = line.solve(l, h)
    H, V = LumpedLine(line, 1, steps=12).forces(l, h, h0, v0)
    assert H == pytest.approx(tension * l / chord, rel=1e-9)
    assert V == pytest.approx(tension * h / chord + 0.5 * 500.0 * 100.0, rel=1e-9)


def test_a_suspended_line_tends_to_the_catenary_at_second_order():
    l, h = 826.0, 186.0                                  # the line is clear of the seabed here
    h0, v0 = LINE.solve(l, h)
    assert v0 > LINE.weight * LINE.length
    errors = [abs(LumpedLine(LINE, n, steps=8).forces(l, h, h0, v0)[0] / h0 - 1.0) for n in (50, 200, 800)]
    assert errors[0] / errors[1] == pytest.approx(16.0, rel=0.2)
    assert errors[1] / errors[2] == pytest.approx(16.0, rel=0.2)
    assert errors[2] < 1e-6


def _nodal_balance(l: float, h: float, segments: int = 50) -> tuple[float, float]:
    """(H, V) of MoorDyn's chain with every internal node solved (seabed springs kBot d l0 per node)."""
    l0, ea, kd = LINE.length / segments, LINE.axial_stiffness, 3.0e6 * 0.333

    def residual(p):
        nodes = np.vstack([[0.0, 0.0], p.reshape(-1, 2), [l, h]])
        step = np.diff(nodes, axis=0)
        length = np.linalg.norm(step, axis=1)
        pull = (ea * np.maximum(length / l0 - 1.0, 0.0) / length)[:, None] * step
        force = pull[1:] - pull[:-1]
        z = nodes[1:-1, 1]
        force[:, 1] += -WEIGHT * l0 - np.where(z < 0.0, z * kd * l0, 0.0)
        return force.ravel()

    h0, v0 = LINE.solve(l, h)
    px, pz = LINE.profile(h0, v0, np.linspace(0.0, LINE.length, segments + 1)[1:-1])
    p = np.column_stack([px, np.where(pz < 1e-6, -PENETRATION, pz)]).ravel()
    for _ in range(40):
        f = residual(p)
        jac = np.empty((p.size, p.size))
        for j in range(p.size):
            q = p.copy()
            q[j] += 1e-7
            jac[:, j] = (residual(q) - f) / 1e-7
        dp = np.linalg.solve(jac, -f)
        p += dp
        if np.abs(dp).max() < 1e-9:
            break
    last = np.array([l, h]) - p[-2:]
    size = np.linalg.norm(last)
    tension = ea * (size / l0 - 1.0)
    return tension * last[0] / size, tension * last[1] / size + 0.5 * WEIGHT * l0


def test_closed_form_spans_against_the_full_nodal_balance_with_seabed_springs():
    lumped = LumpedLine(LINE, 50, PENETRATION)
    spans = np.arange(794.0, 796.51, 0.25)
    mine, full, smooth = [], [], []
    for l in spans:
        h0, v0 = LINE.solve(l, 186.0)
        mine.append(lumped.forces(l, 186.0, h0, v0))
        full.append(_nodal_balance(l, 186.0))
        smooth.append(h0)
    mine, full = np.array(mine), np.array(full)
    assert np.abs(mine / full - 1.0).max() < 1.5e-4
    k_mine, k_full, k_cat = (np.gradient(x, spans) for x in (mine[:, 0], full[:, 0], np.array(smooth)))
    assert np.abs((k_mine - k_full) / k_cat).max() < 0.015
    ripple = k_full / k_cat - 1.0
    assert ripple.max() > 0.03 and ripple.min() < -0.02      # what the lumped line models and the catenary lacks


def test_four_newton_steps_reach_the_converged_spans_over_the_envelope():
    four, many = LumpedLine(LINE, 50, PENETRATION).function(), LumpedLine(LINE, 50, PENETRATION, steps=30).function()
    worst = 0.0
    for l in np.arange(735.0, 826.0, 2.3):
        for h in (167.0, 186.0, 205.0):
            h0, v0 = LINE.solve(l, h)
            a, b = np.array(four(l, h, h0, v0), dtype=float).ravel(), np.array(many(l, h, h0, v0), dtype=float).ravel()
            worst = max(worst, float(np.max(np.abs(a / b - 1.0))))
    assert worst < 1e-10


@pytest.mark.parametrize("kwargs, match", [({"segments": 0}, "segments"), ({"segments": 2.5}, "segments"),
                                           ({"steps": 0}, "steps"), ({"penetration": -1.0}, "penetration")])
def test_bad_parameters_are_refused(kwargs, match):
    args = {"catenary": LINE, "segments": 50} | kwargs
    with pytest.raises(ParameterError, match=match):
        LumpedLine(**args)
    with pytest.raises(ParameterError, match="friction"):
        LumpedLine(CatenaryLine(850.0, WEIGHT, 3.27e9, 0.5), 50)


@pytest.mark.skipif(not SEMI.is_dir(), reason="shared floating decks not found")
def test_moordyn_system_with_lumped_lines():
    from mbsym.wind.deck.moordyn import read_moordyn
    from mbsym.wind.offshore.mooring import mooring_from_moordyn

    md = read_moordyn(SEMI / "IEA-15-240-RWT-UMaineSemi_MoorDyn.dat")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        lumped = mooring_from_moordyn(md, water_density=1025.0, gravity=9.80665, water_depth=200.0,
                                      line_statics="lumped")
        smooth = mooring_from_moordyn(md, water_density=1025.0, gravity=9.80665, water_depth=200.0)
        with pytest.raises(OptionError, match="line_statics"):
            mooring_from_moordyn(md, water_density=1025.0, gravity=9.80665, water_depth=200.0, line_statics="fine")
    assert [ln.segments for ln in lumped.lumped] == [50, 50, 50] and smooth.lumped is None
    assert [ln.steps for ln in lumped.lumped] == [4, 4, 4]          # mooring.lumped_steps over the envelope
    q = np.array([16.5, 0.0, -0.44, 0.0, math.radians(2.87), 0.0])     # the 13 m/s operating offset
    assert np.allclose(lumped.load(q)[:3], smooth.load(q)[:3], rtol=0, atol=3e-3 * abs(smooth.load(q)[0]))
    assert np.allclose(lumped.load(q, method="rootfinder"), lumped.load(q), rtol=1e-9, atol=1e-3)
    k_lumped, k_smooth = lumped.stiffness(q)[0, 0], smooth.stiffness(q)[0, 0]
    assert 1.01 < k_lumped / k_smooth < 1.06          # a node lifting off near this offset: +2.8 % observed
    with_drag = lumped.with_dynamics(lumped.dynamics, 1025.0)
    assert with_drag.lumped == lumped.lumped


@pytest.mark.skipif(not SEMI.is_dir(), reason="shared floating decks not found")
def test_too_few_segments_fall_back_to_the_catenaries_with_a_warning(tmp_path):
    """NumSegs 10 on the VolturnUS-S line: the lumped lines at rest do not converge over the fairlead's envelope
    (30 segments and more do, in 5 steps): asked for, refused; by default, the catenaries with a ModelWarning."""
    import shutil

    from mbsym.exceptions import ModelWarning
    from mbsym.wind import read_openfast
    from mbsym.wind.offshore import floating_platform
    from mbsym.wind.offshore.mooring import LumpedStaticsError

    from .conftest import FLOATING

    for name in ("IEA-15-240-RWT", "IEA-15-240-RWT-UMaineSemi", "cases"):
        shutil.copytree(FLOATING / name, tmp_path / name)
    moordyn = tmp_path / "IEA-15-240-RWT-UMaineSemi" / "IEA-15-240-RWT-UMaineSemi_MoorDyn.dat"
    text = moordyn.read_text()
    assert text.count("850.00      50 ") == 3
    moordyn.write_text(text.replace("850.00      50 ", "850.00      10 "))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        turbine = read_openfast(tmp_path / "cases" / "fl_decay_a" / "fl_decay_a.fst")
    with pytest.warns(ModelWarning, match="continuous catenaries are used"):
        platform = floating_platform(turbine, radiation="none")
    assert platform.mooring.lumped is None
    with pytest.raises(LumpedStaticsError, match="10-segment line .* does not converge"):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            floating_platform(turbine, radiation="none", mooring_statics="lumped")
