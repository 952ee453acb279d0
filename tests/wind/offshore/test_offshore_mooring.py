"""Quasi-static elastic catenary mooring (MAP++'s line model) against independent references (issue 20).

References
----------
- The equilibrium of an elastic cable under its own weight integrated numerically (scipy
  ``solve_ivp``, rtol 1e-12) along the unstretched arclength from the anchor: the horizontal force H
  is constant on the hanging part, V grows by w per unit length, dx/ds = (H/T)(1 + T/EA),
  dz/ds = (V/T)(1 + T/EA); on the seabed the tension falls by the friction C_B w per unit length
  (never below 0) and dx/ds = 1 + T/EA. The closed forms must give the same spans (1e-9 relative).
- The two solvers (CasADi rootfinder, 30 fixed Newton steps in SX) agree to 1e-6 relative; the
  fairlead forces' derivatives from the implicit-function theorem agree with central differences
  (step 1e-4 m, tolerance 1e-5 relative ~ step²·curvature).
- OpenFAST v5 + MoorDyn (``fl_decay_a``, lumped-mass lines of 50 segments settled by dynamic
  relaxation to 0.1 %, seabed as a spring): FAIRTEN1..3 at t = 0 with the platform at its initial
  surge 10 m, heave 1.5 m, pitch 4°; tolerance 0.5 % (observed −0.11 %, −0.01 %, −0.01 %).
- A conservative force field has a symmetric stiffness: the 6×6 mooring stiffness K = Kᵀ to 1e-5
  of its largest entry at the undisplaced position; it equals central differences of the load.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from mbsym.wind.offshore.catenary import CatenaryLine, wet_weight

from .conftest import SEMI

W = wet_weight(685.0, 0.333, 1025.0, 9.81)   # MoorDyn's line type 'main' (MassDen, Diam), fl_decay_a's rho, g


def _integrate(line: CatenaryLine, H: float, V: float) -> tuple[float, float]:
    """Spans (l, h) of the cable ODE for fairlead forces (H, V) (see the module docstring)."""
    from scipy.integrate import solve_ivp

    w, L, EA, cb = line.weight, line.length, line.axial_stiffness, line.seabed_friction
    va = V - w * L
    lb = max(-va / w, 0.0)                   # resting length (V < w L)
    hang = lambda s, y: [H / math.hypot(H, max(va, 0.0) + w * (s - lb)) * (1 + math.hypot(H, max(va, 0.0) + w * (s - lb)) / EA),
                         (max(va, 0.0) + w * (s - lb)) / math.hypot(H, max(va, 0.0) + w * (s - lb))
                         * (1 + math.hypot(H, max(va, 0.0) + w * (s - lb)) / EA)]
    x0 = 0.0
    if lb > 0:
        rest = lambda s, y: [1 + max(H - cb * w * (lb - s), 0.0) / EA]
        x0 = solve_ivp(rest, (0.0, lb), [0.0], rtol=1e-12, atol=1e-12).y[0, -1]
    sol = solve_ivp(hang, (lb, L), [x0, 0.0], rtol=1e-12, atol=1e-10)
    return sol.y[0, -1], sol.y[1, -1]


@pytest.mark.parametrize("H, V, friction", [
    (2.0e6, 6.0e6, 0.0),       # lifted off the seabed: V > w L = 4.97e6 N
    (1.35e6, 2.03e6, 0.0),     # 503 m resting on a frictionless seabed (MoorDyn)
    (1.35e6, 2.03e6, 1.0),     # the same with MAP++'s C_B = 1: friction takes up H before the anchor
    (0.2e6, 2.03e6, 1.0),      # friction exhausts H on the resting part (the max(…, 0) branch)
])
def test_closed_forms_against_the_cable_ode(H, V, friction):
    line = CatenaryLine(850.0, W, 3.27e9, friction)
    l_ode, h_ode = _integrate(line, H, V)
    l, h = line.spans(H, V)
    assert (l, h) == pytest.approx((l_ode, h_ode), rel=1e-9)


def test_solvers_agree_and_round_trip():
    line = CatenaryLine(850.0, W, 3.27e9, 1.0)
    H, V = line.solve(779.6, 186.0)
    assert line.spans(H, V) == pytest.approx((779.6, 186.0), rel=1e-9)
    from mbsym.wind.offshore.mooring import _newton
    import casadi as ca

    Hn, Vn = _newton(line, ca.SX(779.6), ca.SX(186.0), 30)
    assert (float(ca.evalf(Hn)), float(ca.evalf(Vn))) == pytest.approx((H, V), rel=1e-6)


def test_fairlead_force_derivatives():
    import casadi as ca

    line = CatenaryLine(850.0, W, 3.27e9)
    f = line.function()
    lh = ca.MX.sym("lh", 2)
    jac = ca.Function("j", [lh], [ca.jacobian(ca.vertcat(*f(lh)), lh)])
    x = np.array([785.0, 180.0])
    exact = np.array(jac(x))
    step = 1e-4
    fd = np.column_stack([(np.array(ca.vertcat(*f(x + e))) - np.array(ca.vertcat(*f(x - e)))).ravel() / (2 * step)
                          for e in np.eye(2) * step])
    assert exact == pytest.approx(fd, rel=1e-5)
    assert exact[0, 0] > 0 and exact[1, 1] > 0   # pulled further: H grows; raised: more chain hangs, V grows


needs_deck = pytest.mark.skipif(not SEMI.is_dir(), reason=f"shared floating deck not found at {SEMI}")


@pytest.fixture(scope="module")
def moordyn_system():
    from mbsym.wind.deck.moordyn import read_moordyn
    from mbsym.wind.offshore.mooring import mooring_from_moordyn

    from mbsym.exceptions import ModelWarning

    md = read_moordyn(SEMI / "IEA-15-240-RWT-UMaineSemi_MoorDyn.dat")
    with pytest.warns(ModelWarning, match="line dynamics are modelled on the quasi-static shape"):
        return mooring_from_moordyn(md, water_density=1025.0, gravity=9.81)


@needs_deck
def test_fairlead_tensions_at_the_start_of_fl_decay_a(moordyn_system):
    # fl_decay_a.csv, t = 0: FAIRTEN1..3 from OpenFAST v5 + MoorDyn
    openfast = np.array([3.180983e6, 2.235681e6, 2.235681e6])
    q0 = np.array([10.0, 0.0, 1.5, 0.0, math.radians(4.0), 0.0])
    assert moordyn_system.tensions(q0) == pytest.approx(openfast, rel=5e-3)
    assert moordyn_system.tensions(q0, method="rootfinder") == pytest.approx(moordyn_system.tensions(q0), rel=1e-6)


@needs_deck
def test_mooring_stiffness_is_symmetric_and_exact(moordyn_system):
    K = moordyn_system.stiffness()
    assert np.abs(K - K.T).max() <= 1e-5 * np.abs(K).max()
    fd = np.column_stack([-(moordyn_system.load(e) - moordyn_system.load(-e)) / 2e-5 for e in np.eye(6) * 1e-5])
    assert K == pytest.approx(fd, rel=1e-4, abs=1e-6 * np.abs(K).max())
    assert K[0, 0] > 0 and K[2, 2] > 0 and np.all(np.linalg.eigvalsh((K + K.T) / 2) > 0)


@needs_deck
def test_map_deck_repeats_the_line():
    from mbsym.wind.deck.mapplusplus import read_map
    from mbsym.wind.offshore.mooring import mooring_from_map

    mp = read_map(SEMI / "IEA-15-240-RWT-UMaineSemi_MAP.dat")
    system = mooring_from_map(mp, water_density=1025.0, gravity=9.81, water_depth=200.0)
    assert len(system.lines) == 3 and system.lines[0].seabed_friction == 1.0
    tensions = system.tensions(np.zeros(6))
    assert tensions == pytest.approx(np.full(3, tensions[0]), rel=1e-9)      # three identical lines, 120 deg apart
    load = system.load(np.zeros(6))
    assert np.abs(load[[0, 1, 3, 4, 5]]).max() < 1e-6 * abs(load[2])        # symmetric: only a downward pull


@needs_deck
def test_default_newton_steps_converge_over_the_envelope(moordyn_system):
    """The fixed Newton steps found at build time (``newton_steps``: 10 for these lines, from 30 before) give the
    converged catenary (60 steps) to 1e-10 of the load anywhere in the envelope, and fewer steps do not."""
    from mbsym.wind.offshore.mooring import NEWTON_ENVELOPE

    steps = moordyn_system.newton_steps()
    assert 3 <= steps <= 20
    reach = NEWTON_ENVELOPE[0] * 186.0 * 0.9                 # inside the envelope (fairlead 186 m above the anchors)
    rng = np.random.default_rng(3)
    for _ in range(6):
        q = np.concatenate([rng.uniform(-reach, reach, 2), rng.uniform(-10.0, 10.0, 1), np.radians(rng.uniform(-5, 5, 3))])
        exact = moordyn_system.load(q, steps=60)
        assert np.abs(moordyn_system.load(q) - exact).max() <= 1e-10 * np.abs(exact).max()
    q = np.array([reach, 0.0, 0.0, 0.0, 0.0, 0.0])
    exact = moordyn_system.load(q, steps=60)
    assert np.abs(moordyn_system.load(q, steps=steps - 5) - exact).max() > 1e-8 * np.abs(exact).max()
