"""Drag and inertia of quasi-static mooring lines (mbsym.wind.offshore.line_dynamics) (issue 20).

References
----------
- The catenary's shape: its end is the fairlead (the span equations, 1e-9 m), and on the hanging part
  its slope dz/dx is the force ratio V(s)/H of a cable in equilibrium (central differences of the
  nodes, 1e-4 relative: the stretch term changes dx/ds and dz/ds alike, so the ratio is exact; the
  error is the difference quotient's, ~ (Δs/R)² with Δs = 0.01 m).
- A taut, nearly straight line (weight 1e-4 of its tension) pinned at the anchor turns about it when the
  fairlead moves: a node at arc fraction ξ moves with ξ ṙ. Morison drag on the nodes gives the fairlead
  force ½ ρ C_d D |v| v L Σ Δξ_i ξ_i³ (D = d across, π d along the line) and the mass
  (m + ρ π d²/4 C_a) L Σ Δξ_i ξ_i², Σ over the trapezoid weights: 1/4 + h²/4 and 1/3 + h²/6 exactly
  (h = 1/segments); tolerance 1e-3 (the sag and the tension's change along the line, ~1e-4).
- Drag dissipates: the power of the lines' drag load at the platform reference point, F·v + M·ω with
  the exact angular velocity ω ([ω×] = Ṙ Rᵀ), is < 0 for any motion (random positions and rates), and
  equals the nodes' own Σ f_i·v_i (1e-9 relative: virtual work).
- The nodes' velocities from the shape's sensitivity (implicit-function theorem) equal central
  differences of node positions from independent numeric catenary solutions (CasADi rootfinder) at
  displaced fairleads (step 0.01 m, tolerance 1e-4 of the largest velocity), lines resting on the
  seabed and lifted off it, with and without seabed friction.
"""

from __future__ import annotations

import math

import casadi as ca
import numpy as np
import pytest

from mbsym.wind.offshore.catenary import CatenaryLine, wet_weight
from mbsym.wind.offshore.line_dynamics import LineHydrodynamics, fairlead_terms, line_nodes
from mbsym.wind.offshore.mooring import MooringSystem

from .conftest import SEMI

W = wet_weight(685.0, 0.333, 1025.0, 9.81)     # MoorDyn's 'main' line of the VolturnUS-S deck
PROPS = LineHydrodynamics(0.333, 685.0, 2.0, 0.4, 0.82, 0.27, 50)
RHO = 1025.0


def _numeric_nodes(line, props, anchor, fairlead):
    d = np.asarray(fairlead) - np.asarray(anchor)
    H, V = line.solve(math.hypot(d[0], d[1]), d[2])
    points, _ = line_nodes(line, props.segments, H, V, anchor, np.asarray(fairlead, dtype=float))
    return np.array(ca.evalf(points))


@pytest.mark.parametrize("friction", [0.0, 1.0])
@pytest.mark.parametrize("spans", [(779.6, 186.0), (760.0, 186.0), (840.0, 190.0)])
def test_shape_ends_at_the_fairlead_and_hangs_in_equilibrium(spans, friction):
    line = CatenaryLine(850.0, W, 3.27e9, friction)
    H, V = line.solve(*spans)
    x, z = line.profile(H, V, np.array([850.0]))
    assert x[0] == pytest.approx(spans[0], abs=1e-9 * 1e3) and z[0] == pytest.approx(spans[1], abs=1e-9 * 1e3)
    lb = max(850.0 - V / W, 0.0)
    for s in np.linspace(lb + 5.0, 845.0, 7):
        xs, zs = line.profile(H, V, np.array([s - 0.01, s + 0.01]))
        assert np.diff(zs)[0] / np.diff(xs)[0] == pytest.approx((max(V - W * 850.0, 0) + W * (s - lb)) / H, rel=1e-4)


def test_taut_line_drag_and_mass_closed_form():
    L, n = 100.0, 50
    line = CatenaryLine(L, 1.0, 1e9)                         # w L / H ~ 1e-4: straight to 1e-4
    props = LineHydrodynamics(0.2, 50.0, 1.2, 0.5, 1.0, 0.3, n)
    fair = 1.001 * L * np.array([0.6, 0.0, 0.8])              # 0.1 % stretch: H ~ 6e5 N
    H, V = line.solve(math.hypot(fair[0], fair[1]), fair[2])
    f = fairlead_terms(line, props, RHO, np.zeros(3))
    cubic, square = 0.25 + 1 / (4 * n ** 2), 1 / 3 + 1 / (6 * n ** 2)
    v = 0.7
    drag, mass, _, _ = f(fair, [H, V], [0.0, v, 0.0])          # across the line's plane
    expected = -0.5 * RHO * 1.2 * 0.2 * v * v * L * cubic
    assert float(drag[1]) == pytest.approx(expected, rel=1e-3)
    assert abs(float(drag[0])) + abs(float(drag[2])) < 1e-6 * abs(expected)
    axis = fair / np.linalg.norm(fair)
    drag, _, _, _ = f(fair, [H, V], list(-v * axis))          # along the line, towards the anchor
    expected = 0.5 * RHO * math.pi * 0.5 * 0.2 * v * v * L * cubic
    assert float(ca.dot(drag, ca.DM(axis))) == pytest.approx(expected, rel=1e-3)
    area = math.pi * 0.2 ** 2 / 4
    mass = np.array(mass)
    assert mass[1, 1] == pytest.approx((50.0 + RHO * area * 1.0) * L * square, rel=1e-3)
    assert axis @ mass @ axis == pytest.approx((50.0 + RHO * area * 0.3) * L * square, rel=1e-3)


@pytest.mark.parametrize("friction", [0.0, 1.0])
@pytest.mark.parametrize("fair", [(779.6, 0.0, 186.0), (760.0, 30.0, 186.0), (836.0, -20.0, 190.0)])
def test_node_velocities_match_finite_differences(fair, friction):
    line = CatenaryLine(850.0, W, 3.27e9, friction)
    fair = np.asarray(fair)
    anchor = np.zeros(3)
    d = fair - anchor
    H, V = line.solve(math.hypot(d[0], d[1]), d[2])
    rdot = np.array([0.3, -0.2, 0.25])
    _, _, _, velocities = fairlead_terms(line, PROPS, RHO, anchor)(fair, [H, V], rdot)
    h = 0.01
    fd = (_numeric_nodes(line, PROPS, anchor, fair + h * rdot) - _numeric_nodes(line, PROPS, anchor, fair - h * rdot)) / (2 * h)
    velocities = np.array(velocities)
    assert np.abs(velocities - fd).max() <= 1e-4 * np.abs(fd).max()


def _system():
    lines = tuple(CatenaryLine(850.0, W, 3.27e9) for _ in range(3))
    angles = np.radians([180.0, 60.0, -60.0])
    anchors = np.array([[837.6 * math.cos(a), 837.6 * math.sin(a), -200.0] for a in angles])
    fairs = np.array([[58.0 * math.cos(a), 58.0 * math.sin(a), -14.0] for a in angles])
    return MooringSystem(lines, anchors, fairs, (PROPS,) * 3, RHO)


def test_line_drag_dissipates_power():
    system = _system()
    q, qd = ca.SX.sym("q", 6), ca.SX.sym("qd", 6)
    _, drag, mass, _ = system.line_loads(q, qd)
    from mbsym.wind.offshore._casadi import euler_zyx

    R = euler_zyx(q[3:6])
    w_skew = ca.mtimes(ca.reshape(ca.jtimes(ca.vec(R), q, qd), 3, 3), R.T)
    omega = ca.vertcat(w_skew[2, 1], w_skew[0, 2], w_skew[1, 0])
    power = ca.dot(drag[0:3], qd[0:3]) + ca.dot(drag[3:6], omega)
    f = ca.Function("p", [q, qd], [power, mass])
    rng = np.random.default_rng(7)
    for _ in range(20):
        q0 = np.concatenate([rng.uniform(-10, 10, 3), np.radians(rng.uniform(-5, 5, 3))])
        v0 = np.concatenate([rng.uniform(-1, 1, 3), rng.uniform(-0.05, 0.05, 3)])
        p, m = f(q0, v0)
        assert float(p) < 0
        m = np.array(m)
        assert np.abs(m - m.T).max() <= 1e-9 * np.abs(m).max()
        assert np.linalg.eigvalsh(m).min() > -1e-6 * np.abs(m).max()     # a mass: positive semidefinite


def test_fairlead_force_is_the_virtual_work_of_the_node_drag():
    line = CatenaryLine(850.0, W, 3.27e9)
    fair = np.array([779.6, 0.0, 186.0])
    H, V = line.solve(779.6, 186.0)
    rdot = np.array([0.4, 0.3, -0.2])
    from mbsym.wind.offshore.line_dynamics import node_drag

    drag, _, points, velocities = fairlead_terms(line, PROPS, RHO, np.zeros(3))(fair, [H, V], rdot)
    _, tangents = line_nodes(line, PROPS.segments, H, V, np.zeros(3), fair)
    forces = node_drag(PROPS, line.length, RHO, ca.evalf(tangents), velocities)
    node_power = float(ca.sum2(ca.sum1(forces * velocities)))
    assert float(ca.dot(drag, ca.DM(rdot))) == pytest.approx(node_power, rel=1e-9)
    assert node_power < 0


def test_line_properties_are_checked():
    from mbsym.exceptions import ParameterError

    with pytest.raises(ParameterError, match="segments"):
        LineHydrodynamics(0.333, 685.0, 2.0, 0.4, 0.82, 0.27, 0)
    with pytest.raises(ParameterError, match="drag_normal"):
        LineHydrodynamics(0.333, 685.0, -2.0, 0.4, 0.82, 0.27)


@pytest.mark.skipif(not SEMI.is_dir(), reason=f"shared floating deck not found at {SEMI}")
def test_moordyn_deck_gives_the_line_type():
    from mbsym.exceptions import ModelWarning
    from mbsym.wind.deck.moordyn import read_moordyn
    from mbsym.wind.offshore.mooring import mooring_from_moordyn

    md = read_moordyn(SEMI / "IEA-15-240-RWT-UMaineSemi_MoorDyn.dat")
    with pytest.warns(ModelWarning, match="quasi-static shape .* 10 segments per line"):
        system = mooring_from_moordyn(md, water_density=RHO, gravity=9.81)
    # the deck's LINE TYPES row 'main': Diam 0.333, MassDen 685, Cd 2.0, Ca 0.82, CdAx 0.4, CaAx 0.27
    assert system.dynamics == (LineHydrodynamics(0.333, 685.0, 2.0, 0.4, 0.82, 0.27, 10),) * 3
    with pytest.warns(ModelWarning, match="quasi-static shape .* NumSegs"):
        assert mooring_from_moordyn(md, water_density=RHO, gravity=9.81, line_segments=None).dynamics[0].segments == 50
    with pytest.warns(ModelWarning, match="line dynamics .* not modelled"):
        assert mooring_from_moordyn(md, water_density=RHO, gravity=9.81, line_dynamics=False).dynamics is None
    from mbsym.exceptions import OptionError

    with pytest.raises(OptionError, match="no effect with line_dynamics=False"):   # never silently ignored
        mooring_from_moordyn(md, water_density=RHO, gravity=9.81, line_dynamics=False, line_segments=30)
    with pytest.raises(OptionError, match="positive integer"):
        mooring_from_moordyn(md, water_density=RHO, gravity=9.81, line_segments=0)
