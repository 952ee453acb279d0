"""N-link 3-D pendulum chain against sympy.physics.mechanics.KanesMethod (N = 3, 5).

Reference: the same chain built independently with SymPy's Kane implementation (frames by
``orient_axis``, points by ``locatenew``/``v2pt_theory``, ``RigidBody`` with full inertia
dyadics, gravity loads, generalized speeds u = qd with kinematic equations u_i - q_i' = 0).
SymPy's ``mass_matrix`` and ``forcing`` are the dynamic equations ``M u' = F``, the same
convention as mbsym. Geometry and mass constants are SymPy symbols (faster to derive than
floats) that receive the numbers at evaluation; mbsym keeps masses as parameters with defaults.

Each link i hangs from the previous one by a revolute joint about a fixed unit axis of the
parent: N = 5 uses x, y, z, x, (1, 2, 2)/3; N = 3 uses (1, 2, 2)/3, y, (2, -3, 6)/7. The joint
sits at a 3-D offset in the parent, the com is off the axis and the inertia about the com is a
full (non-diagonal) SPD matrix.

Tolerance: 1e-10 relative to the largest entry (both sides are exact expressions of the same
numbers, evaluated in double precision by different routes). Runtime: ~4 s (N=3), ~7 s (N=5).
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sm
import sympy.physics.mechanics as me

import mbsym as mb

from ._reference import random_spd

G = 9.81
R = sm.Rational
AXES = {
    3: [(R(1, 3), R(2, 3), R(2, 3)), (0, 1, 0), (R(2, 7), R(-3, 7), R(6, 7))],
    5: [(1, 0, 0), (0, 1, 0), (0, 0, 1), (1, 0, 0), (R(1, 3), R(2, 3), R(2, 3))],
}


def chain_data(N: int) -> dict:
    rng = np.random.default_rng(100 + N)
    return dict(
        axes=AXES[N],
        offsets=[rng.uniform(-0.3, 0.3, 3) + [0, 0, -0.6 if i else 0.0] for i in range(N)],
        coms=[rng.uniform(-0.2, 0.2, 3) + [0, 0, -0.4] for _ in range(N)],
        masses=rng.uniform(0.5, 2.0, N),
        inertias=[random_spd(rng, 0.2) for _ in range(N)],
    )


def mbsym_chain(N: int, data: dict) -> mb.EquationsOfMotion:
    sys = mb.System(gravity=[0.0, 0.0, -G])
    qs = sys.coordinates([f"q{i}" for i in range(N)])
    ms = sys.parameters([f"m{i}" for i in range(N)], values=data["masses"].tolist())
    parent = sys.ground
    for i in range(N):
        body = mb.RigidBody(f"link{i}", mass=ms[i], com=data["coms"][i].tolist(), inertia=data["inertias"][i])
        sys.add_joint(mb.Revolute(parent, body, axis=[float(a) for a in data["axes"][i]], coordinate=qs[i],
                                  offset=data["offsets"][i].tolist()))
        parent = body
    return sys.equations()


def sympy_chain(N: int, data: dict):
    """Return (M(q), F(q, u), constants) with M, F lambdified from SymPy's KanesMethod."""
    q = me.dynamicsymbols(f"q0:{N}")
    u = me.dynamicsymbols(f"u0:{N}")
    Nf = me.ReferenceFrame("N")
    O = me.Point("O")
    O.set_vel(Nf, 0)
    pf, pp = Nf, O
    bodies, loads, consts, values = [], [], [], []
    for i in range(N):
        o, c = sm.symbols(f"o{i}_0:3"), sm.symbols(f"c{i}_0:3")
        J, m = sm.symbols(f"J{i}_0:6"), sm.Symbol(f"m{i}")
        I = data["inertias"][i]
        consts += [*o, *c, *J, m]
        values += [*data["offsets"][i], *data["coms"][i],
                   I[0, 0], I[1, 1], I[2, 2], I[0, 1], I[1, 2], I[0, 2], data["masses"][i]]
        B = me.ReferenceFrame(f"B{i}")
        ax = data["axes"][i]
        B.orient_axis(pf, ax[0] * pf.x + ax[1] * pf.y + ax[2] * pf.z, q[i])
        P = pp.locatenew(f"P{i}", o[0] * pf.x + o[1] * pf.y + o[2] * pf.z)
        P.v2pt_theory(pp, Nf, pf)
        Gc = P.locatenew(f"G{i}", c[0] * B.x + c[1] * B.y + c[2] * B.z)
        Gc.v2pt_theory(P, Nf, B)
        # me.inertia(frame, ixx, iyy, izz, ixy, iyz, izx): entries of the dyadic (tensor) itself.
        bodies.append(me.RigidBody(f"link{i}", Gc, B, m, (me.inertia(B, *J), Gc)))
        loads.append((Gc, -m * G * Nf.z))
        pf, pp = B, P
    kane = me.KanesMethod(Nf, q_ind=q, u_ind=u, kd_eqs=[u[i] - q[i].diff() for i in range(N)])
    kane.kanes_equations(bodies, loads)
    M = sm.lambdify([q, consts], kane.mass_matrix, "numpy", cse=True)
    F = sm.lambdify([q, u, consts], kane.forcing, "numpy", cse=True)
    return M, F, np.array(values, dtype=float)


@pytest.mark.parametrize("N", [3, pytest.param(5, marks=pytest.mark.slow)])    # 5 links: 20 s of SymPy
def test_chain_matches_sympy_kane(N):
    """M(q) and F(q, qd) at 4 random states equal SymPy's to 1e-10 (relative to max entry)."""
    data = chain_data(N)
    eom = mbsym_chain(N, data)
    M_ref, F_ref, consts = sympy_chain(N, data)
    rng = np.random.default_rng(N)
    for _ in range(4):
        q, qd = rng.uniform(-np.pi, np.pi, N), rng.normal(scale=2.0, size=N)
        Ms = np.array(M_ref(q, consts), dtype=float)
        Fs = np.array(F_ref(q, qd, consts), dtype=float).reshape(-1)
        M, F = eom.mass_matrix(q), eom.forcing(q, qd)
        assert np.abs(F - eom.forcing(q, np.zeros(N))).max() > 1e-3   # velocity terms present
        np.testing.assert_allclose(M, Ms, rtol=0, atol=1e-10 * np.abs(Ms).max())
        np.testing.assert_allclose(F, Fs, rtol=0, atol=1e-10 * np.abs(Fs).max())
