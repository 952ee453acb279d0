"""Closed loops against closed-form kinematics: a crank–rocker four-bar and a slider–crank.

References (independent of mbsym):

- crank–rocker (ground d = 2.5, crank a = 1, coupler b = 2, rocker c = 2 [m]; Grashof: a + d < b + c,
  so the crank turns fully): the coupler joint C is the intersection of the circles about the crank
  pin B (radius b) and the ground pivot O4 (radius c), on the branch above the line B–O4; the
  absolute link speeds follow from the velocity loop dotted with each link direction
  (ω2 = -a ω1 sin(φ3 - θ) / (b sin(φ3 - φ2)), ω3 = -a ω1 sin(φ2 - θ) / (c sin(φ2 - φ3))).
- slider–crank (crank R = 0.5, rod L = 1.5 [m]): x = R cos θ + sqrt(L² - R² sin² θ), rod angle
  φ = -asin(R sin θ / L), ẍ from SymPy's derivatives of x(θ); at rest under a slider force P held by
  the crank torque τ = -P dx/dθ (virtual work) the rod is a two-force member, so the pin force on the
  slider is (-P, -P tan φ); moving, the slider's own Newton law in x gives the pin force
  λ_x = m_s ẍ - P.

Tolerances: positions and speeds 1e-12 (closed forms in double precision, Newton-converged dependent
coordinates ~1e-15); reactions 1e-10 relative (solves with M_r). Angles are compared modulo 2π (a crank
that has turned k times has relative joint angles that differ by whole turns). Runtime ~2 s.
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sm

import mbsym as mb

A, B, C, D = 1.0, 2.0, 2.0, 2.5
R, L = 0.5, 1.5
M_SLIDER = 2.0


def wrap(a):
    return (np.asarray(a) + np.pi) % (2 * np.pi) - np.pi


def four_bar(lengths, guess, **options):
    a, b, c, d = lengths
    s = mb.System(gravity=[0.0, -9.81, 0.0])
    q1, q2, q3 = s.coordinates("q1 q2 q3")
    parent, offset = s.ground, [0.0, 0.0, 0.0]
    for name, q, l in zip(("crank", "coupler", "rocker"), (q1, q2, q3), (a, b, c)):
        body = mb.RigidBody(name, 1.0, com=[l / 2, 0, 0], inertia=np.diag([0.01, 0.1, 0.1]))
        s.add_joint(mb.Revolute(parent, body, axis=[0, 0, 1], coordinate=q, offset=offset))
        parent, offset = body, [l, 0.0, 0.0]
    s.add_closure(parent, [c, 0, 0], s.ground, [d, 0, 0], directions="xy")
    return s.equations(independent=["q1"], guess=guess, **options)


@pytest.fixture(scope="module")
def crank_rocker():
    return four_bar((A, B, C, D), {"q2": 1.2, "q3": -2.4})


def closed_form_crank_rocker(theta, w1, lengths=(A, B, C, D)):
    A, B, C, D = lengths
    Bp = A * np.array([np.cos(theta), np.sin(theta)])
    O4 = np.array([D, 0.0])
    e = O4 - Bp
    dist = np.linalg.norm(e)
    along = (B**2 - C**2 + dist**2) / (2 * dist)
    h = np.sqrt(B**2 - along**2)
    n = np.array([-e[1], e[0]]) / dist                      # left normal of B -> O4: the branch "above"
    Cp = Bp + along * e / dist + h * n
    phi2 = np.arctan2(*(Cp - Bp)[::-1])
    phi3 = np.arctan2(*(O4 - Cp)[::-1])
    w2 = -A * w1 * np.sin(phi3 - theta) / (B * np.sin(phi3 - phi2))
    w3 = -A * w1 * np.sin(phi2 - theta) / (C * np.sin(phi2 - phi3))
    return np.array([phi2 - theta, phi3 - phi2]), np.array([w2 - w1, w3 - w2])


@pytest.mark.parametrize("solver", ["series", "continuation"])
def test_crank_rocker_positions_and_speeds_over_two_turns(crank_rocker, solver):
    """Default: the crank's Fourier series + Newton; stages given: the path continuation (wrapped angle)."""
    eom = crank_rocker if solver == "series" else four_bar((A, B, C, D), {"q2": 1.2, "q3": -2.4}, stages=3)
    f = eom.output_function()
    for theta in np.linspace(-4 * np.pi, 4 * np.pi, 41) + 0.1:
        w1 = 1.7
        q_ref, qd_ref = closed_form_crank_rocker(theta, w1)
        y = np.asarray(f([theta, w1], [], [])).ravel()
        assert np.max(np.abs(wrap(y[:2] - q_ref))) < 1e-12, theta
        assert np.max(np.abs(y[2:4] - qd_ref)) < 1e-12 * max(1.0, np.max(np.abs(qd_ref))), theta
        assert y[-1] < 1e-12                                  # closure residual


def test_double_rocker_within_its_range():
    """Non-Grashof (crank 2, coupler 1, rocker 2, ground 2.5: a + d > b + c): q1 cannot turn fully (it
    assembles for cos q1 in [0.125, 0.925], q1 in [0.39, 1.45] rad on this side), so the dependent
    coordinates follow the path from the assembly at q1 = 0.9 (no series over a turn); closed form over
    [0.45, 1.4]."""
    lengths = (2.0, 1.0, 2.0, 2.5)
    q0, _ = closed_form_crank_rocker(0.9, 0.0, lengths)
    eom = four_bar(lengths, {"q1": 0.9, "q2": q0[0] + 0.1, "q3": q0[1] - 0.1})
    f = eom.output_function()
    for theta in np.linspace(0.45, 1.4, 15):
        q_ref, qd_ref = closed_form_crank_rocker(theta, 0.8, lengths)
        y = np.asarray(f([theta, 0.8], [], [])).ravel()
        assert np.max(np.abs(wrap(y[:2] - q_ref))) < 1e-12, theta
        assert np.max(np.abs(y[2:4] - qd_ref)) < 1e-12 * max(1.0, np.max(np.abs(qd_ref))), theta


def test_crank_rocker_closure_point_coincides(crank_rocker):
    """The rocker tip, as the tree sees it, sits on the ground pivot and does not move (point_kinematics)."""
    fk = crank_rocker.point_kinematics("rocker", [C, 0, 0])
    r, _, v, _, a, _ = (np.asarray(o).ravel() for o in fk([2.0], [1.3], [0.4], [], []))
    assert np.max(np.abs(r - [D, 0, 0])) < 1e-12
    assert np.max(np.abs(v)) < 1e-12 and np.max(np.abs(a)) < 1e-11


def slider_crank(P: float | None = None):
    s = mb.System()
    q1, q2, x = s.coordinates("q1 q2 x")
    s.add_joint(mb.Revolute(s.ground, mb.RigidBody("crank", 1.0, com=[R / 2, 0, 0],
                                                   inertia=np.diag([0.01, 0.05, 0.05])), axis=[0, 0, 1], coordinate=q1))
    rod = mb.RigidBody("rod", 0.8, com=[L / 2, 0, 0], inertia=np.diag([0.01, 0.2, 0.2]))
    s.add_joint(mb.Revolute(s.body("crank"), rod, axis=[0, 0, 1], coordinate=q2, offset=[R, 0, 0]))
    slider = mb.RigidBody("slider", M_SLIDER, com=[0, 0, 0], inertia=np.diag([0.01, 0.01, 0.01]))
    s.add_joint(mb.Prismatic(s.ground, slider, axis=[1, 0, 0], coordinate=x))
    s.add_closure(rod, [L, 0, 0], slider, [0, 0, 0], directions="xy", name="pin")
    if P is not None:
        s.add_force(slider, [P, 0, 0])
        tau = s.inputs("tau")
        s.add_torque(s.body("crank"), [0, 0, tau])
    return s.equations(independent=["q1"], guess={"x": R + L})


@pytest.fixture(scope="module")
def slider_forms():
    th = sm.symbols("theta")
    x = R * sm.cos(th) + sm.sqrt(L**2 - R**2 * sm.sin(th) ** 2)
    return {k: sm.lambdify(th, e) for k, e in (("x", x), ("dx", x.diff(th)), ("ddx", x.diff(th, 2)))}


def test_slider_crank_positions_speeds_and_moving_reaction(slider_forms):
    P = 10.0
    eom = slider_crank(P)
    f = eom.output_function()
    for theta, w, tau in [(0.3, 2.0, 1.0), (2.0, -3.0, 0.0), (4.0, 5.0, -2.0), (10.0, 1.0, 3.0)]:
        y = np.asarray(f([theta, w], [tau], [])).ravel()     # q2, x, q2_d, x_d, pin_Fx, pin_Fy, residual
        phi = -np.arcsin(R * np.sin(theta) / L)
        assert abs(wrap(theta + y[0] - phi)) < 1e-12
        assert abs(y[1] - slider_forms["x"](theta)) < 1e-12
        assert abs(y[3] - slider_forms["dx"](theta) * w) < 1e-12 * max(1.0, abs(w))
        alpha = eom.accelerations([theta], [w], [tau])[0]
        xdd = slider_forms["ddx"](theta) * w**2 + slider_forms["dx"](theta) * alpha
        assert abs(y[4] - (M_SLIDER * xdd - P)) < 1e-10 * max(1.0, abs(M_SLIDER * xdd))


def test_slider_crank_static_reaction_is_a_two_force_member(slider_forms):
    P = 10.0
    eom = slider_crank(P)
    for theta in (0.4, 1.9, -2.5):
        tau = -P * slider_forms["dx"](theta)                 # virtual work: holds the mechanism at rest
        assert abs(eom.accelerations([theta], [0.0], [tau])[0]) < 1e-12
        phi = -np.arcsin(R * np.sin(theta) / L)
        F = eom.constraint_forces([theta], [0.0], [tau])
        assert np.allclose(F, [-P, -P * np.tan(phi)], rtol=1e-10, atol=1e-10 * P), (F, phi)
