"""A four-bar linkage (closed loop) against sympy.physics.mechanics.KanesMethod with dependent coordinates.

Reference: the planar four-bar of SymPy's documentation (crank A, coupler B, rocker C hinged about z,
the rocker tip P3 closing on the ground pivot at l4 along x), built in this test with rigid bodies
and gravity along -y, configuration constraints ``fh = [loop·x, loop·y]``, velocity constraints
``fnh = [v_P3·x, v_P3·y]``, q1/u1 independent, q2, q3, u2, u3 dependent (``q_dependent=``,
``u_dependent=``), generalized speeds u = q'. SymPy's ``mass_matrix`` M_s (3x3) stacks the one
reduced dynamic row ``k_d`` and the two differentiated velocity constraints, so its reduced
quantities in the independent speed are ``M_r = k_d C_s`` (``C_s = [1; A_rs]``, A_rs from SymPy's
velocity constraints) and ``F_r = M_r u1'`` with ``u' = M_s⁻¹ F_s``; its constrained
linearization (``to_linearizer().linearize(A_and_B=True)``) gives A and B in the independent states
[q1, u1] and the crank's motor torque T (an input on both sides). mbsym's model is a tree of three revolute joints about z closed with
``add_closure(..., directions="xy")``.

Tolerance 1e-10 (relative to the largest entry): both sides are exact expressions of the same
numbers evaluated in double precision by different routes; the dependent coordinates are solved
by Newton to ~1e-15 (SymPy's linearizer works in 40-digit Floats, see the test). Runtime: ~9 s by
default (SymPy's derivation ~2 s, one SymPy linearization ~6 s); two more linearizations, moving and
with torque, are marked slow.
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sm
import sympy.physics.mechanics as me

import mbsym as mb

L = (1.0, 2.0, 2.0, 2.5)            # crank, coupler, rocker, ground link [m]
MASS = (1.0, 2.0, 1.5)              # [kg]
IZZ = (0.1, 0.6, 0.4)               # about each com [kg m^2]
G = 9.81
GUESS = {"q2": 1.2, "q3": -2.4}     # the branch with the coupler above the x axis


def mbsym_fourbar() -> mb.ClosedLoopEquations:
    s = mb.System(gravity=[0.0, -G, 0.0])
    q1, q2, q3 = s.coordinates("q1 q2 q3")
    parent, offset = s.ground, [0.0, 0.0, 0.0]
    for name, q, l, m, izz in zip(("crank", "coupler", "rocker"), (q1, q2, q3), L, MASS, IZZ):
        body = mb.RigidBody(name, m, com=[l / 2, 0, 0], inertia=np.diag([0.01, 0.01 + izz, izz]))
        s.add_joint(mb.Revolute(parent, body, axis=[0, 0, 1], coordinate=q, offset=offset))
        parent, offset = body, [l, 0.0, 0.0]
    s.add_closure(parent, [L[2], 0, 0], s.ground, [L[3], 0, 0], directions="xy")
    tau = s.inputs("tau")
    s.add_torque(s.body("crank"), [0, 0, tau])
    return s.equations(independent=["q1"], guess=GUESS)


def sympy_fourbar():
    q1, q2, q3 = me.dynamicsymbols("q1:4")
    u1, u2, u3 = me.dynamicsymbols("u1:4")
    t = me.dynamicsymbols._t
    N = me.ReferenceFrame("N")
    A = N.orientnew("A", "Axis", [q1, N.z])
    B = A.orientnew("B", "Axis", [q2, A.z])
    C = B.orientnew("C", "Axis", [q3, B.z])
    A.set_ang_vel(N, u1 * N.z)
    B.set_ang_vel(A, u2 * A.z)
    C.set_ang_vel(B, u3 * B.z)
    O = me.Point("O")
    O.set_vel(N, 0)
    l1, l2, l3, l4 = (sm.Float(v, 40) for v in L)
    P1 = O.locatenew("P1", l1 * A.x)
    P2 = P1.locatenew("P2", l2 * B.x)
    P3 = P2.locatenew("P3", l3 * C.x)
    P1.v2pt_theory(O, N, A)
    P2.v2pt_theory(P1, N, B)
    P3.v2pt_theory(P2, N, C)
    bodies, loads = [], []
    for (frame, root, l, m, izz, nm) in zip((A, B, C), (O, P1, P2), (l1, l2, l3), MASS, IZZ, "ABC"):
        Gc = root.locatenew(f"G{nm}", l / 2 * frame.x)
        Gc.v2pt_theory(root, N, frame)
        I = me.inertia(frame, sm.Float(0.01, 40), sm.Float(0.01 + izz, 40), sm.Float(izz, 40))
        bodies.append(me.RigidBody(nm, Gc, frame, sm.Float(m, 40), (I, Gc)))
        loads.append((Gc, -sm.Float(m, 40) * sm.Float(G, 40) * N.y))
    T = me.dynamicsymbols("T")
    loads.append((A, T * N.z))                          # the crank's motor torque (the input)
    loop = P3.pos_from(O) - l4 * N.x
    fh = [loop.dot(N.x), loop.dot(N.y)]
    fnh = [P3.vel(N).dot(N.x), P3.vel(N).dot(N.y)]
    kd = [q1.diff(t) - u1, q2.diff(t) - u2, q3.diff(t) - u3]
    km = me.KanesMethod(N, q_ind=[q1], u_ind=[u1], kd_eqs=kd, q_dependent=[q2, q3], configuration_constraints=fh,
                        u_dependent=[u2, u3], velocity_constraints=fnh)
    km.kanes_equations(bodies, loads)
    q, u = [q1, q2, q3], [u1, u2, u3]
    Mf = sm.lambdify([q], km.mass_matrix, "numpy")
    Ff = sm.lambdify([q, u, T], km.forcing, "numpy")
    Jnh = sm.Matrix(fnh).jacobian(u)
    Jf = sm.lambdify([q], Jnh, "numpy")
    return dict(km=km, M=Mf, F=Ff, J=Jf, q=q, u=u, t=t, T=T)


@pytest.fixture(scope="module")
def both():
    return mbsym_fourbar(), sympy_fourbar()


def _close(a, b, tol=1e-10):
    a, b = np.asarray(a, float), np.asarray(b, float)
    assert np.max(np.abs(a - b)) <= tol * max(1.0, np.max(np.abs(b))), (a, b)


def _sympy_state(eom, ref, q1, u1):
    q = eom.configuration([q1])
    J = np.asarray(ref["J"](q), float)
    Ars = -np.linalg.solve(J[:, 1:], J[:, :1])
    u = np.concatenate([[u1], (Ars * u1).ravel()])
    return q, u, np.vstack([[1.0], Ars])


CONFIGS = [(0.3, 0.0, 0.0), (1.1, -0.7, 2.0), (2.4, 1.5, -1.0), (-1.0, 2.0, 0.5)]     # q1, u1, torque


@pytest.mark.parametrize("q1,u1,tau", CONFIGS)
def test_mass_matrix_and_forcing_match_sympy(both, q1, u1, tau):
    eom, ref = both
    q, u, Cs = _sympy_state(eom, ref, q1, u1)
    Ms = np.asarray(ref["M"](q), float)
    Fs = np.asarray(ref["F"](q, u, tau), float).ravel()
    ud = np.linalg.solve(Ms, Fs)
    Mr = Ms[:1] @ Cs                                  # SymPy's reduced mass matrix in the independent speed
    _close(eom.mass_matrix([q1]), Mr)
    _close(eom.forcing([q1], [u1], [tau]), Mr @ ud[:1])
    _close(eom.accelerations([q1], [u1], [tau]), ud[:1])
    y = eom.output_function()(np.array([q1, u1]), [tau], [])
    _close(np.asarray(y).ravel()[2:4], u[1:])          # dependent speeds from SymPy's velocity constraints


@pytest.mark.parametrize("q1,u1,tau", [CONFIGS[0], pytest.param(*CONFIGS[2], marks=pytest.mark.slow),
                                       pytest.param(*CONFIGS[3], marks=pytest.mark.slow)])   # ~6-11 s each
def test_linearized_A_and_B_match_sympy(both, q1, u1, tau):
    eom, ref = both
    q, u, _ = _sympy_state(eom, ref, q1, u1)
    Ms = np.asarray(ref["M"](q), float)
    ud = np.linalg.solve(Ms, np.asarray(ref["F"](q, u, tau), float).ravel())
    t = ref["t"]
    # SymPy's linearizer manipulates the substituted expressions symbolically: with 15-digit Floats its
    # cancellations lose ~5 digits (A off by 3e-7 relative), so the operating point is given in 40 digits
    hp = [{k: sm.Float(float(v), 40) for k, v in zip(keys, vals)} for keys, vals in
          ((ref["q"], q), (ref["u"], u), ([ui.diff(t) for ui in ref["u"]], ud), ([ref["T"]], [tau]))]
    lin = ref["km"].to_linearizer()
    A_s, B_s = lin.linearize(op_point=hp, A_and_B=True, simplify=False)
    assert list(lin.r) == [ref["T"]]                       # B's column: the motor torque
    lm = mb.linearize(eom, [q1], [u1], [tau], {})
    _close(lm.A, np.asarray(A_s.evalf(40), float))
    _close(lm.B, np.asarray(B_s.evalf(40), float))
