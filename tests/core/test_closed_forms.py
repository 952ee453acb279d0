"""Closed-form equations of motion of small systems against the engine.

References (independent of mbsym):
- simple / double pendulum, pendulum on a cart, spring-mass-damper, heavy symmetric top:
  M and F written out by hand from the Lagrangian (formulas in each test); the top's steady
  precession condition ``m g L = Omega (C w3 - A_O Omega cos(theta))`` is Goldstein,
  *Classical Mechanics*, 3rd ed., Sect. 5.7 (Eq. 5.75 with theta-dot = 0).
- torque-free and free bodies: Newton-Euler equations evaluated in numpy
  (``_reference.free_body_residual``: Euler's equations ``I w' + w x I w = tau`` in body axes,
  Newton's ``m a_G = m g``) projected on hand-written partial velocities.
- damped oscillator: exact solution of ``m x'' + c x' + k x = m g.a``.

Tolerances: 1e-12 relative (+1e-12 absolute) where both sides are closed-form expressions
evaluated in double precision; 1e-10 for Newton-Euler comparisons (more arithmetic, rotations);
1e-8 where a numerical integration (rtol 1e-11) is involved.
"""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import mbsym as mb

from ._reference import free_body_residual, random_spd, rodrigues, xyz_body_rates

G = 9.81
TIGHT = dict(rtol=1e-12, atol=1e-12)


# --------------------------------------------------------------------------- pendulums
def test_simple_pendulum_with_inertia():
    """Pendulum about y, com at -l along z, inertia Jyy about the com.

    Closed form: M = m l^2 + Jyy, F = -m g l sin(q) (velocity terms vanish for one DOF).
    """
    sys = mb.System(gravity=[0.0, 0.0, -G])
    q = sys.coordinates("q")
    m, l, J = sys.parameters("m l J", values={"m": 1.7, "l": 0.8})
    sys.add_joint(mb.Revolute(sys.ground, mb.RigidBody("b", mass=m, com=[0, 0, -l], inertia=[0.2, J, 0.2]),
                              axis=[0, 1, 0], coordinate=q))
    eom = sys.equations()
    p = {"J": 0.05}
    for th, thd in [(0.0, 0.0), (0.4, -1.3), (2.9, 3.0), (-1.2, 0.7)]:
        np.testing.assert_allclose(eom.mass_matrix([th], p), [[1.7 * 0.8**2 + 0.05]], **TIGHT)
        np.testing.assert_allclose(eom.forcing([th], [thd], p), [-1.7 * G * 0.8 * np.sin(th)], **TIGHT)
        np.testing.assert_allclose(eom.potential_energy([th], p), -1.7 * G * 0.8 * np.cos(th), **TIGHT)
        np.testing.assert_allclose(eom.kinetic_energy([th], [thd], p),
                                   0.5 * (1.7 * 0.8**2 + 0.05) * thd**2, **TIGHT)


def double_pendulum_reference(q, qd, m1, m2, l1, l2, g=G):
    """Planar double pendulum, point masses, relative angle q2 (Lagrange, by hand).

    Positions: (x1, z1) = (-l1 s1, -l1 c1), (x2, z2) = (x1 - l2 s12, z1 - l2 c12) for rotations
    about +y. With h = m2 l1 l2:
      M = [[(m1+m2) l1^2 + m2 l2^2 + 2 h c2, m2 l2^2 + h c2], [., m2 l2^2]]
      F1 = h s2 (2 qd1 qd2 + qd2^2) - (m1+m2) g l1 s1 - m2 g l2 s12
      F2 = -h s2 qd1^2 - m2 g l2 s12
    """
    q1, q2 = q
    u1, u2 = qd
    c2, s2, s1, s12 = np.cos(q2), np.sin(q2), np.sin(q1), np.sin(q1 + q2)
    h = m2 * l1 * l2
    M = np.array([[(m1 + m2) * l1**2 + m2 * l2**2 + 2 * h * c2, m2 * l2**2 + h * c2],
                  [m2 * l2**2 + h * c2, m2 * l2**2]])
    F = np.array([h * s2 * (2 * u1 * u2 + u2**2) - (m1 + m2) * g * l1 * s1 - m2 * g * l2 * s12,
                  -h * s2 * u1**2 - m2 * g * l2 * s12])
    return M, F


def _double_pendulum():
    # The README quick-start snippet, verbatim.
    sys = mb.System(gravity=[0.0, 0.0, -9.81])
    q1, q2 = sys.coordinates("q1 q2")
    m1, m2, l1, l2 = sys.parameters("m1 m2 l1 l2")
    b1 = mb.RigidBody("b1", mass=m1, com=[0, 0, -l1])      # point mass at the end of a massless link
    b2 = mb.RigidBody("b2", mass=m2, com=[0, 0, -l2])
    sys.add_joint(mb.Revolute(sys.ground, b1, axis=[0, 1, 0], coordinate=q1))
    sys.add_joint(mb.Revolute(b1, b2, axis=[0, 1, 0], coordinate=q2, offset=[0, 0, -l1]))
    return sys.equations()


def test_double_pendulum_readme_contract():
    """README snippet: m1=2, m2=1, l1=1, l2=0.5, q=[0.3,-0.2], qd=[0.1,0.4]; 1e-12 vs hand closed form."""
    eom = _double_pendulum()
    p = {"m1": 2.0, "m2": 1.0, "l1": 1.0, "l2": 0.5}
    M = eom.mass_matrix([0.3, -0.2], p)
    F = eom.forcing([0.3, -0.2], [0.1, 0.4], p)
    assert isinstance(M, np.ndarray) and M.shape == (2, 2)
    assert isinstance(F, np.ndarray) and F.shape == (2,)
    M_ref, F_ref = double_pendulum_reference([0.3, -0.2], [0.1, 0.4], 2.0, 1.0, 1.0, 0.5)
    np.testing.assert_allclose(M, M_ref, **TIGHT)
    np.testing.assert_allclose(F, F_ref, **TIGHT)


def test_double_pendulum_other_states_and_parameters():
    """Same closed form at states with large velocities (Coriolis terms dominate), 1e-12."""
    eom = _double_pendulum()
    rng = np.random.default_rng(1)
    for _ in range(5):
        m1, m2, l1, l2 = 0.5 + 2 * rng.random(4)
        q, qd = rng.uniform(-3, 3, 2), rng.uniform(-5, 5, 2)
        p = {"m1": m1, "m2": m2, "l1": l1, "l2": l2}
        M_ref, F_ref = double_pendulum_reference(q, qd, m1, m2, l1, l2)
        np.testing.assert_allclose(eom.mass_matrix(q, p), M_ref, **TIGHT)
        np.testing.assert_allclose(eom.forcing(q, qd, p), F_ref, rtol=1e-12, atol=1e-11)
        qdd = rng.normal(size=2)
        np.testing.assert_allclose(eom.residual(q, qd, qdd, p), F_ref - M_ref @ qdd, rtol=1e-12, atol=1e-11)


# --------------------------------------------------------------------------- spring-mass-damper
AXIS = np.array([1.0, 2.0, 2.0]) / 3.0
GVEC = np.array([0.3, -1.2, -9.81])


def _smd():
    sys = mb.System(gravity=GVEC.tolist())
    x = sys.coordinates("x")
    m, k, c, r = sys.parameters("m k c r", values=[2.0, 50.0, 1.5, 0.1])
    sys.add_joint(mb.Prismatic(sys.ground, mb.RigidBody("mass", mass=m, inertia=[1.0, 2.0, 3.0]),
                               axis=(3 * AXIS).tolist(), coordinate=x, offset=[0.5, -0.2, 1.0]))
    sys.add_spring(x, k, rest=r)
    sys.add_damper(x, c)
    return sys.equations()


def test_spring_mass_damper_closed_form():
    """Prismatic along unit axis a: M = m, F = -k (x - r) - c xd + m g.a (1e-12).

    Also T = m xd^2 / 2, V = k (x-r)^2 / 2 - m g.(offset + a x), power = -c xd^2.
    """
    eom = _smd()
    m, k, c, r = 2.0, 50.0, 1.5, 0.1
    for x, xd in [(0.0, 0.0), (0.3, -0.7), (-1.1, 2.5)]:
        np.testing.assert_allclose(eom.mass_matrix([x]), [[m]], **TIGHT)
        np.testing.assert_allclose(eom.forcing([x], [xd]), [-k * (x - r) - c * xd + m * GVEC @ AXIS], **TIGHT)
        np.testing.assert_allclose(eom.kinetic_energy([x], [xd]), 0.5 * m * xd**2, **TIGHT)
        V_ref = 0.5 * k * (x - r) ** 2 - m * GVEC @ (np.array([0.5, -0.2, 1.0]) + AXIS * x)
        np.testing.assert_allclose(eom.potential_energy([x]), V_ref, **TIGHT)
        np.testing.assert_allclose(float(eom.functions.power([x], [xd], [], [m, k, c, r])), -c * xd**2, **TIGHT)


def test_spring_mass_damper_free_decay_matches_exact_solution():
    """rhs integrated (DOP853, rtol 1e-11) vs the exact underdamped solution, 1e-8 absolute."""
    eom = _smd()
    m, k, c, r = 2.0, 50.0, 1.5, 0.1
    x_eq = r + m * GVEC @ AXIS / k
    wn, zeta = np.sqrt(k / m), c / (2 * np.sqrt(k * m))
    wd = wn * np.sqrt(1 - zeta**2)
    x0, v0 = 0.4, -0.3
    A = x0 - x_eq
    B = (v0 + zeta * wn * A) / wd
    t = np.linspace(0.0, 2.0, 41)
    exact = x_eq + np.exp(-zeta * wn * t) * (A * np.cos(wd * t) + B * np.sin(wd * t))
    sol = solve_ivp(lambda _t, y: eom.rhs(y), (0.0, 2.0), [x0, v0], method="DOP853",
                    rtol=1e-11, atol=1e-12, t_eval=t)
    assert sol.success
    np.testing.assert_allclose(sol.y[0], exact, rtol=0, atol=1e-8)


# --------------------------------------------------------------------------- pendulum on a cart
def test_pendulum_on_cart_closed_form():
    """Cart (mass mc) along x, pendulum about y: bob com at -l along z, inertia J about its com.

    Lagrange by hand: M = [[mc+m, -m l cos th], [-m l cos th, m l^2 + J]],
    F = [-m l sin(th) thd^2 + u, -m g l sin(th)] with u a horizontal input force on the cart.
    """
    sys = mb.System(gravity=[0.0, 0.0, -G])
    x, th = sys.coordinates("x th")
    mc, m, l, J = sys.parameters("mc m l J", values=[3.0, 0.7, 0.9, 0.04])
    u = sys.inputs("u")
    cart = mb.RigidBody("cart", mass=mc, inertia=[1.0, 1.0, 1.0])
    bob = mb.RigidBody("bob", mass=m, com=[0, 0, -l], inertia=[0.5, J, 0.5])
    sys.add_joint(mb.Prismatic(sys.ground, cart, axis=[1, 0, 0], coordinate=x))
    sys.add_joint(mb.Revolute(cart, bob, axis=[0, 1, 0], coordinate=th, offset=[0.0, 0.0, 0.0]))
    sys.add_force(cart, [u, 0, 0])
    eom = sys.equations()
    rng = np.random.default_rng(2)
    for _ in range(4):
        q, qd, uu = rng.uniform(-3, 3, 2), rng.uniform(-4, 4, 2), rng.normal(size=1)
        c, s = np.cos(q[1]), np.sin(q[1])
        M_ref = np.array([[3.7, -0.7 * 0.9 * c], [-0.7 * 0.9 * c, 0.7 * 0.81 + 0.04]])
        F_ref = np.array([-0.7 * 0.9 * s * qd[1] ** 2 + uu[0], -0.7 * G * 0.9 * s])
        np.testing.assert_allclose(eom.mass_matrix(q), M_ref, **TIGHT)
        np.testing.assert_allclose(eom.forcing(q, qd, uu), F_ref, **TIGHT)
        np.testing.assert_allclose(float(eom.functions.power(q, qd, uu, [3.0, 0.7, 0.9, 0.04])),
                                   uu[0] * qd[0], **TIGHT)


# --------------------------------------------------------------------------- torque-free body
INERTIA = np.array([[2.0, 0.3, -0.2], [0.3, 3.0, 0.4], [-0.2, 0.4, 4.5]])   # asymmetric, full


def _free_body(com, gravity):
    sys = mb.System(gravity=list(gravity))
    coords = sys.coordinates("x y z a b c")
    m = sys.parameters("m", values=[1.3])
    sys.add_joint(mb.Free(sys.ground, mb.RigidBody("body", mass=m, com=list(com), inertia=INERTIA),
                          coordinates=coords, sequence="xyz"))
    return sys.equations()


def _states(rng, n):
    for _ in range(n):
        q = np.concatenate([rng.normal(size=3), rng.uniform(-1.2, 1.2, 3)])   # b away from +-pi/2
        yield q, rng.normal(scale=2.0, size=6), rng.normal(size=6)


def test_torque_free_body_satisfies_euler_equations():
    """Accelerations from the engine turned into body rates must satisfy I w' + w x I w = 0.

    The gyroscopic term w x I w is checked to be O(1) so that the test can fail; 1e-10 relative
    to |w x I w|. Translations: no force, so x'' = 0 (1e-12).
    """
    eom = _free_body([0, 0, 0], [0, 0, 0])
    rng = np.random.default_rng(3)
    for q, qd, _ in _states(rng, 5):
        qdd = eom.accelerations(q, qd)
        _, E, Ed = xyz_body_rates(q[3:], qd[3:])
        w, wd = E @ qd[3:], E @ qdd[3:] + Ed
        gyro = np.cross(w, INERTIA @ w)
        assert np.linalg.norm(gyro) > 0.1
        np.testing.assert_allclose(INERTIA @ wd + gyro, 0.0, atol=1e-10 * np.linalg.norm(gyro))
        np.testing.assert_allclose(qdd[:3], 0.0, atol=1e-12)


def test_torque_free_body_residual_matches_newton_euler():
    """e(q, qd, qdd) at arbitrary qdd vs -E^T (I w' + w x I w) and -m x'' (numpy), 1e-10."""
    eom = _free_body([0, 0, 0], [0, 0, 0])
    rng = np.random.default_rng(4)
    for q, qd, qdd in _states(rng, 5):
        ref = free_body_residual(q, qd, qdd, mass=1.3, com=[0, 0, 0], inertia=INERTIA, gravity=[0, 0, 0])
        np.testing.assert_allclose(eom.residual(q, qd, qdd), ref, rtol=1e-10, atol=1e-10)


def test_torque_free_body_conserves_angular_momentum():
    """Integrated 2 s (DOP853, rtol 1e-11): H = R I w (ground axes) and T stay constant, 1e-8."""
    eom = _free_body([0, 0, 0], [0, 0, 0])
    q0 = np.array([0.0, 0.0, 0.0, 0.2, -0.3, 0.1])
    qd0 = np.array([0.0, 0.0, 0.0, 0.3, 0.5, 1.5])
    sol = solve_ivp(lambda _t, y: eom.rhs(y), (0.0, 2.0), np.concatenate([q0, qd0]), method="DOP853",
                    rtol=1e-11, atol=1e-12, t_eval=np.linspace(0, 2, 21))
    assert sol.success
    H, T = [], []
    for y in sol.y.T:
        R, E, _ = xyz_body_rates(y[3:6], y[9:])
        w = E @ y[9:]
        H.append(R @ INERTIA @ w)
        T.append(0.5 * w @ INERTIA @ w)
    H, T = np.array(H), np.array(T)
    assert np.ptp(sol.y[3:6], axis=1).max() > 0.5            # the body really tumbles
    np.testing.assert_allclose(H, np.broadcast_to(H[0], H.shape), rtol=0, atol=1e-8 * np.linalg.norm(H[0]))
    np.testing.assert_allclose(T, T[0], rtol=1e-8)


# --------------------------------------------------------------------------- heavy symmetric top
TOP = dict(m=1.5, L=0.4, A=0.03, C=0.05)   # com at L on the symmetry axis; A, C about the com (C <= 2A)


def _top():
    """Pivot at the ground origin; Euler angles z (psi), x (theta), z (phi) via massless yokes."""
    sys = mb.System(gravity=[0.0, 0.0, -G])
    psi, th, phi = sys.coordinates("psi theta phi")
    m, L, A, C = sys.parameters("m L A C", values=TOP)
    y1, y2 = mb.RigidBody("yoke1", mass=0.0), mb.RigidBody("yoke2", mass=0.0)
    top = mb.RigidBody("top", mass=m, com=[0, 0, L], inertia=[A, A, C])
    sys.add_joint(mb.Revolute(sys.ground, y1, axis=[0, 0, 1], coordinate=psi))
    sys.add_joint(mb.Revolute(y1, y2, axis=[1, 0, 0], coordinate=th))
    sys.add_joint(mb.Revolute(y2, top, axis=[0, 0, 1], coordinate=phi))
    return sys.equations()


def test_heavy_top_closed_form():
    """Lagrangian with A_O = A + m L^2 and w3 = phid + psid cos(th) (by hand):

    M = [[A_O s^2 + C c^2, 0, C c], [0, A_O, 0], [C c, 0, C]];
    F_psi = -(2 A_O s c thd psid - C s thd w3 - C s c psid thd), F_th = A_O psid^2 s c - C w3 psid s
    + m g L s, F_phi = C psid s thd. 1e-12.
    """
    eom = _top()
    m, L, A, C = TOP.values()
    AO = A + m * L**2
    rng = np.random.default_rng(5)
    for _ in range(5):
        q, qd = rng.uniform(-3, 3, 3), rng.uniform(-20, 20, 3)
        c, s = np.cos(q[1]), np.sin(q[1])
        psid, thd, phid = qd
        w3 = phid + psid * c
        M_ref = np.array([[AO * s * s + C * c * c, 0, C * c], [0, AO, 0], [C * c, 0, C]])
        F_ref = np.array([-(2 * AO * s * c * thd * psid - C * s * thd * w3 - C * s * c * psid * thd),
                          AO * psid**2 * s * c - C * w3 * psid * s + m * G * L * s,
                          C * psid * s * thd])
        np.testing.assert_allclose(eom.mass_matrix(q), M_ref, **TIGHT)
        np.testing.assert_allclose(eom.forcing(q, qd), F_ref, rtol=1e-12, atol=1e-11)


@pytest.mark.parametrize("theta, Omega", [(0.5, 3.0), (1.2, -2.0), (2.5, 4.0)])
def test_heavy_top_steady_precession(theta, Omega):
    """Goldstein Eq. 5.75: with theta fixed, psid = Omega, the spin w3 = (m g L + A_O Omega^2 cos th)
    / (C Omega) gives steady precession, so all accelerations vanish (1e-10 relative to the
    gravity term m g L / A_O); a 1 % change of the spin must break it (the test can fail)."""
    eom = _top()
    m, L, A, C = TOP.values()
    AO = A + m * L**2
    w3 = (m * G * L + AO * Omega**2 * np.cos(theta)) / (C * Omega)
    phid = w3 - Omega * np.cos(theta)
    scale = m * G * L / AO
    qdd = eom.accelerations([0.3, theta, -0.7], [Omega, 0.0, phid])
    np.testing.assert_allclose(qdd, 0.0, atol=1e-10 * scale)
    off = eom.accelerations([0.3, theta, -0.7], [Omega, 0.0, 1.01 * phid])
    assert abs(off[1]) > 1e-4 * scale


# --------------------------------------------------------------------------- free body under gravity
GRAV = [0.2, -0.5, -9.81]


def test_free_body_com_at_origin_falls_with_g():
    """Com at the body origin: M block-diagonal (no translation-rotation coupling), F_trans = m g,
    x'' = g whatever the rotation state (1e-12); rotation obeys the torque-free Euler equations."""
    eom = _free_body([0, 0, 0], GRAV)
    rng = np.random.default_rng(6)
    for q, qd, _ in _states(rng, 4):
        M = eom.mass_matrix(q)
        np.testing.assert_allclose(M[:3, 3:], 0.0, atol=1e-12)
        np.testing.assert_allclose(M[:3, :3], 1.3 * np.eye(3), **TIGHT)
        np.testing.assert_allclose(eom.forcing(q, qd)[:3], 1.3 * np.array(GRAV), **TIGHT)
        qdd = eom.accelerations(q, qd)
        np.testing.assert_allclose(qdd[:3], GRAV, rtol=1e-12, atol=1e-12)
        _, E, Ed = xyz_body_rates(q[3:], qd[3:])
        w, wd = E @ qd[3:], E @ qdd[3:] + Ed
        np.testing.assert_allclose(INERTIA @ wd + np.cross(w, INERTIA @ w), 0.0, atol=1e-10)


def test_free_body_with_com_offset_matches_newton_euler():
    """Com offset from the body origin: residual vs numpy Newton-Euler at random (q, qd, qdd), 1e-10."""
    com = [0.3, -0.4, 0.25]
    eom = _free_body(com, GRAV)
    rng = np.random.default_rng(7)
    for q, qd, qdd in _states(rng, 6):
        ref = free_body_residual(q, qd, qdd, mass=1.3, com=com, inertia=INERTIA, gravity=GRAV)
        np.testing.assert_allclose(eom.residual(q, qd, qdd), ref, rtol=1e-10, atol=1e-10)
    # At the engine's accelerations the Newton-Euler residual vanishes.
    q, qd, _ = next(_states(rng, 1))
    ref = free_body_residual(q, qd, eom.accelerations(q, qd), mass=1.3, com=com, inertia=INERTIA, gravity=GRAV)
    np.testing.assert_allclose(ref, 0.0, atol=1e-10)


def test_free_joint_with_rotated_joint_frame_matches_newton_euler():
    """Free joint with a constant joint ``rotation`` Q and offset o: translations along Q's axes.

    Equivalent description for the reference: gravity expressed in joint axes (Q^T g); the
    residual is frame-independent because the generalized coordinates are the same. 1e-10.
    """
    Q = rodrigues([1.0, -2.0, 0.5], 0.8)
    com = [0.1, 0.2, -0.3]
    sys = mb.System(gravity=GRAV)
    coords = sys.coordinates("x y z a b c")
    sys.add_joint(mb.Free(sys.ground, mb.RigidBody("body", mass=1.3, com=com, inertia=INERTIA),
                          coordinates=coords, offset=[1.0, 2.0, 3.0], rotation=Q))
    eom = sys.equations()
    rng = np.random.default_rng(8)
    for q, qd, qdd in _states(rng, 4):
        ref = free_body_residual(q, qd, qdd, mass=1.3, com=com, inertia=INERTIA, gravity=Q.T @ np.array(GRAV))
        np.testing.assert_allclose(eom.residual(q, qd, qdd), ref, rtol=1e-10, atol=1e-10)



def test_free_body_loads_in_ground_and_body_axes_match_newton_euler():
    """Point forces and torques with components in ground axes (frame=None / sys.ground) and in
    body axes (frame=body), converted to ground axes in numpy with R = Rx Ry Rz; 1e-10."""
    com = [0.3, -0.4, 0.25]
    f_b, p_b, f_g, p_g = [0.7, -1.1, 0.4], [0.5, 0.1, -0.2], [-0.3, 0.2, 0.9], [0.0, -0.3, 0.4]
    t_b, t_g = [0.2, 0.5, -0.8], [0.6, -0.1, 0.3]
    sys = mb.System(gravity=GRAV)
    coords = sys.coordinates("x y z a b c")
    body = mb.RigidBody("body", mass=1.3, com=com, inertia=INERTIA)
    sys.add_joint(mb.Free(sys.ground, body, coordinates=coords))
    sys.add_force(body, f_b, point=p_b, frame=body)
    sys.add_force(body, f_g, point=p_g, frame=sys.ground)
    sys.add_torque(body, t_b, frame=body)
    sys.add_torque(body, t_g)
    eom = sys.equations()
    rng = np.random.default_rng(9)
    for q, qd, qdd in _states(rng, 4):
        R, _, _ = xyz_body_rates(q[3:], qd[3:])
        ref = free_body_residual(q, qd, qdd, mass=1.3, com=com, inertia=INERTIA, gravity=GRAV,
                                 forces=[(R @ f_b, p_b), (f_g, p_g)], torques=[R @ t_b, t_g])
        np.testing.assert_allclose(eom.residual(q, qd, qdd), ref, rtol=1e-10, atol=1e-10)


def test_force_in_axes_of_another_body():
    """Double pendulum (README geometry) with a force P along b1's x axis at b2's com [0, 0, -l2].

    By hand: r = -l1 (s1, 0, c1) - l2 (s12, 0, c12), f = P (c1, 0, -s1), so the generalized forces
    are Q1 = -P (l1 + l2 cos q2), Q2 = -P l2 cos q2 (added to the closed-form F); 1e-12.
    """
    sys = mb.System(gravity=[0.0, 0.0, -9.81])
    q1, q2 = sys.coordinates("q1 q2")
    b1 = mb.RigidBody("b1", mass=2.0, com=[0, 0, -1.0])
    b2 = mb.RigidBody("b2", mass=1.0, com=[0, 0, -0.5])
    sys.add_joint(mb.Revolute(sys.ground, b1, axis=[0, 1, 0], coordinate=q1))
    sys.add_joint(mb.Revolute(b1, b2, axis=[0, 1, 0], coordinate=q2, offset=[0, 0, -1.0]))
    sys.add_force(b2, [0.8, 0.0, 0.0], point=[0, 0, -0.5], frame=b1)
    eom = sys.equations()
    rng = np.random.default_rng(10)
    for _ in range(4):
        q, qd = rng.uniform(-3, 3, 2), rng.normal(size=2)
        _, F_ref = double_pendulum_reference(q, qd, 2.0, 1.0, 1.0, 0.5)
        F_ref += -0.8 * np.array([1.0 + 0.5 * np.cos(q[1]), 0.5 * np.cos(q[1])])
        np.testing.assert_allclose(eom.forcing(q, qd), F_ref, **TIGHT)

def test_random_inertia_helper_is_spd():
    """Guard for the reference helper used by other modules (eigenvalues in [0.6, 1.2]: a rigid body's)."""
    w = np.linalg.eigvalsh(random_spd(np.random.default_rng(0)))
    assert w.min() >= 0.6 - 1e-12 and w.max() <= 1.2 + 1e-12 and w[2] <= w[0] + w[1]
