"""FlexibleBody inside Kane's method, against independent references.

References
----------
- Euler-Bernoulli clamped-free beam with a tip mass: frequency equation
  ``1 + cos b cosh b + mu b (cos b sinh b - sin b cosh b) = 0`` (mu = M_tip / (m L)),
  e.g. Blevins, *Formulas for natural frequency and mode shape*, Table 8-8.
- Uniform rotating cantilever, zero hub radius, non-rotating 1st mode as Ritz shape:
  Southwell coefficient 1.193336 (flap); in-plane (edge) 1.193336 - 1
  (shared/guide/REFERENCE_NUMBERS.md).
- Energy conservation and central finite differences (invariants).
"""

import casadi as ca
import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.linalg import eigh
from scipy.optimize import brentq

import mbsym as mb
from mbsym.beam import cantilever_modes, shape_integrals
from mbsym.bodies.flexible import FlexibleBody

L, MU_L, EI = 10.0, 2.0, 1.0e4     # uniform beam [m, kg/m, N m^2]
Z = np.linspace(0.0, L, 201)


def _beam_sid(n_modes=3, direction="x", **kw):
    modes = cantilever_modes(Z, MU_L, EI, n_modes=n_modes, n_elements=60, direction=direction)
    return shape_integrals(Z, MU_L, EI, EI, modes.shapes(), quadrature="simpson", **kw)


def _linear_mk(eom, q0, qd0):
    """M and K = -dF/dq at (q0, qd0) (zero inputs, default parameters)."""
    d = eom.symbolic
    K = ca.Function("K", [d.q, d.qd], [-ca.jacobian(d.F, d.q)])
    return eom.mass_matrix(q0), np.array(K(q0, qd0))


def test_tip_mass_on_deflected_end_matches_frequency_equation():
    """Rigid tip body at the deflected beam end, 6 bare-beam modes as Ritz basis: 1st frequency
    within 1e-4 of the exact one (measured 2.4e-5; 1 mode: 3.8e-3, 3 modes: 1.9e-4), from above."""
    m_tip = 5.0
    sys = mb.System()
    qe = sys.coordinates("e1 e2 e3 e4 e5 e6")
    beam = FlexibleBody("beam", _beam_sid(n_modes=6), qe)
    sys.add_joint(mb.Fixed(sys.ground, beam))
    sys.add_joint(mb.Fixed(beam, mb.RigidBody("tip", mass=m_tip), offset=[0, 0, L]))
    M, K = _linear_mk(sys.equations(), np.zeros(6), np.zeros(6))
    w = np.sqrt(eigh(K, M, eigvals_only=True))
    mu = m_tip / (MU_L * L)
    eq = lambda b: 1 + np.cos(b) * np.cosh(b) + mu * b * (np.cos(b) * np.sinh(b) - np.sin(b) * np.cosh(b))
    b1 = brentq(eq, 0.5, 3.0)
    w_exact = b1**2 * np.sqrt(EI / (MU_L * L**4))
    assert w[0] == pytest.approx(w_exact, rel=1e-4)
    assert w[0] > w_exact * (1 - 1e-9)      # Ritz: from above


@pytest.mark.parametrize("direction, expected", [("x", 1.193336), ("y", 1.193336 - 1.0)])
def test_rotating_beam_southwell(direction, expected):
    """Beam along z spinning about x: flap (x) stiffens by 1.1933 Ω², edge (y) by 0.1933 Ω²."""
    sys = mb.System()
    psi, qe = sys.coordinates("psi qe")
    hub = mb.RigidBody("hub", mass=1.0, inertia=[10.0, 10.0, 10.0])
    sys.add_joint(mb.Revolute(sys.ground, hub, axis=[1, 0, 0], coordinate=psi))
    beam = FlexibleBody("beam", _beam_sid(n_modes=1, direction=direction), [qe])
    sys.add_joint(mb.Fixed(hub, beam))
    eom = sys.equations()
    M, K0 = _linear_mk(eom, np.zeros(2), np.zeros(2))
    omega = 3.0
    _, K1 = _linear_mk(eom, np.zeros(2), np.array([omega, 0.0]))
    k_omega = (K1[1, 1] - K0[1, 1]) / (M[1, 1] * omega**2)
    assert k_omega == pytest.approx(expected, abs=2e-4)


def _flexible_pendulum(**kw):
    sys = mb.System(gravity=[0.0, 0.0, -9.81])
    th, e1, e2 = sys.coordinates("th e1 e2")
    sid = _beam_sid(n_modes=2)
    beam = FlexibleBody("beam", sid, [e1, e2], damping=np.zeros((2, 2)), **kw)
    sys.add_joint(mb.Revolute(sys.ground, beam, axis=[0, 1, 0], coordinate=th,
                              rotation=mb.rotation("x", np.pi)))   # hanging down
    sys.add_joint(mb.Fixed(beam, mb.RigidBody("tip", mass=3.0, inertia=[0.5, 0.5, 0.5]), offset=[0, 0, L]))
    return sys.equations()


def test_energy_of_free_flexible_pendulum_is_conserved():
    """No damping, no stiffening, exact inertia (taylor_order=2, linear displacement field):
    T + V constant to 1e-8 of the swing energy over 3 s (DOP853, rtol 1e-11). The paper's
    first-order truncation (taylor_order=1) drifts by ~1e-3 here: it drops -∫ũũ dm in Mθθ."""
    eom = _flexible_pendulum(gravity_stiffening=False, centrifugal_stiffening=False, taylor_order=2)
    rhs, pv = eom.functions.rhs, []
    x0 = np.array([0.8, 0.05, -0.01, 0.0, 0.0, 0.0])
    sol = solve_ivp(lambda t, x: np.asarray(rhs(x, [], pv)).ravel(), (0, 3.0), x0,
                    method="DOP853", rtol=1e-11, atol=1e-12, dense_output=True)
    assert sol.success
    E = [eom.kinetic_energy(x[:3], x[3:]) + eom.potential_energy(x[:3]) for x in sol.sol(np.linspace(0, 3, 31)).T]
    scale = abs(eom.potential_energy(np.zeros(3)) - eom.potential_energy(x0[:3]))
    assert np.max(np.abs(np.array(E) - E[0])) / scale < 1e-8


def test_kinetic_energy_is_half_qd_M_qd():
    eom = _flexible_pendulum()
    rng = np.random.default_rng(1)
    q, qd = rng.normal(size=3) * [1, 0.1, 0.1], rng.normal(size=3)
    assert eom.kinetic_energy(q, qd) == pytest.approx(0.5 * qd @ eom.mass_matrix(q) @ qd, rel=1e-12)
    M = eom.mass_matrix(q)
    np.testing.assert_array_equal(M, M.T)
    assert np.all(np.linalg.eigvalsh(M) > 0)


def test_jacobians_match_central_differences():
    """dF/dq and dF/dqd of a flexible model with stiffening vs central FD (h=1e-6, rtol 1e-6)."""
    eom = _flexible_pendulum()
    d = eom.symbolic
    Jq = ca.Function("Jq", [d.q, d.qd], [ca.jacobian(d.F, d.q), ca.jacobian(d.F, d.qd)])
    rng = np.random.default_rng(2)
    q, qd = rng.normal(size=3) * [1, 0.2, 0.2], rng.normal(size=3)
    A, B = (np.array(m) for m in Jq(q, qd))
    h = 1e-6
    for j in range(3):
        dq = np.zeros(3)
        dq[j] = h
        fd_q = (eom.forcing(q + dq, qd) - eom.forcing(q - dq, qd)) / (2 * h)
        fd_v = (eom.forcing(q, qd + dq) - eom.forcing(q, qd - dq)) / (2 * h)
        np.testing.assert_allclose(A[:, j], fd_q, rtol=1e-6, atol=1e-6 * np.abs(A).max())
        np.testing.assert_allclose(B[:, j], fd_v, rtol=1e-6, atol=1e-6 * np.abs(B).max())


def test_residual_jacobian_is_minus_mass_matrix():
    """M = -de/dqdd (paper Eq. 22) for a model mixing rigid and flexible bodies."""
    eom = _flexible_pendulum()
    d = eom.symbolic
    f = ca.Function("dM", [d.q], [-ca.jacobian(d.F - d.M @ d.qdd, d.qdd)])
    q = np.array([0.3, 0.1, -0.05])
    np.testing.assert_allclose(np.array(f(q)), eom.mass_matrix(q), rtol=1e-14, atol=1e-9)


def test_flexible_errors():
    sys = mb.System()
    a, b = sys.coordinates("a b")
    sid = _beam_sid(n_modes=1)
    with pytest.raises(mb.ModelDefinitionError, match="1 shape functions but 2 coordinates"):
        FlexibleBody("beam", sid, [a, b])
    beam = FlexibleBody("beam", sid, [a])
    sys.add_joint(mb.Fixed(sys.ground, beam))
    tip = mb.RigidBody("tip", mass=1.0, inertia=[1.0, 1.0, 1.0])
    with pytest.raises(mb.ModelDefinitionError, match="root .* or at its end"):
        sys.add_joint(mb.Revolute(beam, tip, axis=[1, 0, 0], coordinate=b, offset=[0, 0, 3.0]))
    sys.add_joint(mb.Revolute(beam, tip, axis=[1, 0, 0], coordinate=b, offset=[0, 0, L]))  # unchanged, works
    with pytest.raises(mb.ModelDefinitionError, match="root .* or at its end"):
        sys.add_force(beam, [1.0, 0, 0], point=[0, 0, 5.0])
    assert len(sys.loads) == 0
    assert sys.equations().n_q == 2


# ------------------------------------------------------------------ distributed loads
def _loaded_cantilever(n_modes=6, base_slides=False):
    from mbsym.beam import distributed_load_integrals
    modes = cantilever_modes(Z, MU_L, EI, n_modes=n_modes, n_elements=60, direction="x")
    sid = shape_integrals(Z, MU_L, EI, EI, modes.shapes(), quadrature="simpson")
    sys = mb.System()
    w = sys.inputs("w")
    qe = sys.coordinates([f"e{j}" for j in range(n_modes)])
    beam = FlexibleBody("beam", sid, qe)
    if base_slides:
        x = sys.coordinates("x")
        base = mb.RigidBody("base", mass=10.0)
        sys.add_joint(mb.Prismatic(sys.ground, base, axis=[1, 0, 0], coordinate=x))
        sys.add_joint(mb.Fixed(base, beam))
    else:
        sys.add_joint(mb.Fixed(sys.ground, beam))
    sys.add_distributed_load(beam, distributed_load_integrals(Z, modes.shapes(), direction="x"), w)
    return sys.equations(), sid


def test_uniform_load_static_tip_deflection():
    """Uniform load w on a cantilever: static tip deflection w L^4 / (8 EI) (Euler-Bernoulli),
    6 bare-beam modes as Ritz basis, tolerance 1e-3 (measured ~3e-5)."""
    eom, sid = _loaded_cantilever()
    w = 3.0
    lin = mb.linearize(eom, np.zeros(6), u0=[w])
    q = np.linalg.solve(lin.K, eom.forcing(np.zeros(6), np.zeros(6), [w]))
    tip = float(sid.end_displacement[0] @ q)
    assert tip == pytest.approx(w * L**4 / (8 * EI), rel=1e-3)


def test_distributed_load_resultant_and_power():
    """On a sliding base the load's resultant w L drives the base; power = q̇ᵀ Q for random states."""
    eom, _ = _loaded_cantilever(n_modes=2, base_slides=True)
    w = 2.5
    q = np.zeros(3)
    F = eom.forcing(q, np.zeros(3), [w])
    assert F[-1] == pytest.approx(w * L, rel=1e-12)      # prismatic equation: total force
    rng = np.random.default_rng(4)
    q, qd = rng.normal(size=3) * 0.1, rng.normal(size=3)
    P = float(eom.functions.power(q, qd, [w], []))
    Fw = eom.forcing(q, qd, [w]) - eom.forcing(q, qd, [0.0])
    assert P == pytest.approx(qd @ Fw, rel=1e-12)


def test_distributed_load_errors():
    from mbsym.beam import distributed_load_integrals
    sys = mb.System()
    a, b = sys.coordinates("a b")
    sid = _beam_sid(n_modes=1)
    beam = FlexibleBody("beam", sid, [a])
    sys.add_joint(mb.Fixed(sys.ground, beam))
    rigid = mb.RigidBody("tip", mass=1.0, inertia=[1, 1, 1])
    sys.add_joint(mb.Revolute(beam, rigid, axis=[1, 0, 0], coordinate=b, offset=[0, 0, L]))
    modes = cantilever_modes(Z, MU_L, EI, n_modes=2)
    two = distributed_load_integrals(Z, modes.shapes())
    with pytest.raises(mb.ModelDefinitionError, match="computed for 2 shape functions, but body 'beam' has 1"):
        sys.add_distributed_load(beam, two, 1.0)
    with pytest.raises(mb.ModelDefinitionError, match="needs a flexible body"):
        sys.add_distributed_load(rigid, two, 1.0)
    with pytest.raises(mb.BeamDataError, match="one per station"):
        distributed_load_integrals(Z, modes.shapes(), profile=np.ones(3))
    assert sys.loads == ()


def test_symbolic_stiffness_parameter_gives_exact_gradient():
    """FlexibleBody(stiffness=k_scale * Ke): K0 = k_scale Ke + Kg, so dK0/dk_scale = Ke exactly
    (automatic differentiation through the parameter), and the gravity part does not move."""
    sid = _beam_sid(n_modes=2)
    sys = mb.System(gravity=[0.0, 0.0, -9.81])
    e1, e2 = sys.coordinates("e1 e2")
    k_scale = sys.parameters("k_scale", values=[1.0])
    beam = FlexibleBody("beam", sid, [e1, e2], stiffness=k_scale * sid.ke, top_mass=4.0)
    sys.add_joint(mb.Fixed(sys.ground, beam))
    eom = sys.equations()
    assert eom.parameters == ("k_scale",)
    d = eom.symbolic
    dK = ca.Function("dK", [d.q, d.p], [ca.jacobian(ca.vec(-ca.jacobian(d.F, d.q)), d.p)])
    np.testing.assert_allclose(np.array(dK(np.zeros(2), [1.7])).reshape(2, 2, order="F"), sid.ke, rtol=1e-12)
    K1 = mb.linearize(eom, np.zeros(2), p={"k_scale": 1.0}).K
    K2 = mb.linearize(eom, np.zeros(2), p={"k_scale": 2.0}).K
    np.testing.assert_allclose(K2 - K1, sid.ke, rtol=1e-10, atol=1e-12 * np.abs(sid.ke).max())


def test_power_balance_with_elastic_damping_and_stiffening():
    """d(T+V)/dt = power of the non-conservative forces, including elastic damping and geometric
    stiffening of a flexible body (AD of the energy Functions, 1e-9 relative)."""
    sys = mb.System(gravity=[0.0, 0.0, -9.81])
    th, e1, e2 = sys.coordinates("th e1 e2")
    beam = FlexibleBody("beam", _beam_sid(n_modes=2), [e1, e2], damping=5.0 * np.eye(2), taylor_order=2)
    sys.add_joint(mb.Revolute(sys.ground, beam, axis=[0, 1, 0], coordinate=th, rotation=mb.rotation("x", np.pi)))
    eom = sys.equations()
    d = eom.symbolic
    E = d.T + d.V
    Edot = ca.jacobian(E, d.q) @ d.qd + ca.jacobian(E, d.qd) @ d.qdd
    f = ca.Function("f", [d.q, d.qd, d.qdd, d.u, d.p], [Edot, d.power])
    q, qd = np.array([0.4, 0.05, -0.02]), np.array([0.7, 0.3, -0.4])
    qdd = eom.accelerations(q, qd)
    edot, power = (float(v) for v in f(q, qd, qdd, [], []))
    assert edot == pytest.approx(power, rel=1e-9)
    assert power < 0


def test_distributed_load_stations_must_lie_on_the_beam():
    from mbsym.beam import distributed_load_integrals
    modes = cantilever_modes(Z, MU_L, EI, n_modes=1)
    with pytest.raises(mb.BeamDataError, match="outside the beam"):
        distributed_load_integrals(np.linspace(0, 3 * L, 31), modes.shapes())
    one = distributed_load_integrals(Z, modes.shape(0), direction="X")      # one shape, any case
    assert one.n_e == 1
