"""FlexibleBody(kinematics="exact"): Kane's terms of point masses at their exact positions.

References
----------
- Brute force: for random nodes (positions z_J, masses, shapes Φ_J, symmetric Ax_J) and random
  q, q̇, ω, the body mass matrix Σ m BᵀB (B = [I, −s~, S]) and the velocity terms
  Σ m Bᵀ[ω×(ω×s) + 2ω×(S q̇) + Ṡq̇] summed node by node in numpy equal the polynomial terms of
  mbsym.bodies.lumped_terms to 1e-12 relative.
- Invariants: a lumped blade (ElastoDyn's NREL 5 MW nodes, F1 + F2 + E1, no damping) on a free
  hub under gravity, started with metres of tip deflection, conserves T + V to 1e-9 of its
  kinetic energy over 5 s (cvodes rtol 1e-12); T = ½ q̇ᵀ M q̇ (1e-10); M symmetric positive definite.
- The exact terms vanish at q = 0 (issue 10): the linearization about the undeflected state of a
  spinning lumped blade under gravity, and of a lumped tower carrying an offset rigid top body,
  equals that of the first-order shape-integral bodies with geometric stiffness (the tower with
  ``top_mass``) to 1e-9 relative.
- Bad input: kinematics="exact" without node data, or with options that only apply to shape
  integrals, raises ModelDefinitionError naming the fix.
"""

from __future__ import annotations

import casadi as ca
import numpy as np
import pytest

import mbsym as mb
from mbsym.beam import PolynomialShape, shape_integrals
from mbsym.beam.nodes import LumpedNodes
from mbsym.bodies.flexible import FlexibleBody
from mbsym.bodies.lumped_terms import exact_lumped_terms
from mbsym.exceptions import BeamDataError, ModelDefinitionError
from mbsym.wind import nrel5mw
from mbsym.wind.structure.elastodyn_bodies import blade_shape_integrals, tower_shape_integrals


def _skew(v):
    return np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])


@pytest.mark.parametrize("n_e", [1, 2, 3])
def test_polynomial_terms_equal_node_sums(n_e):
    rng = np.random.default_rng(n_e)
    N = 6
    A = rng.normal(size=(n_e, n_e, N))
    A = A + A.transpose(1, 0, 2)
    nodes = LumpedNodes(rng.uniform(0, 10, N), rng.uniform(1, 5, N), rng.normal(size=(n_e, N, 2)), A, A[:, :, -1])
    q, qd, w = ca.SX.sym("q", n_e), ca.SX.sym("qd", n_e), ca.SX.sym("w", 3)
    terms = exact_lumped_terms(nodes.moments(), q, qd)
    f = ca.Function("f", [q, qd, w], [terms.mass_matrix(), terms.velocity_terms(w)])
    for _ in range(3):
        qv, qdv, wv = rng.normal(size=n_e), rng.normal(size=n_e), rng.normal(size=3)
        Mb, k = (np.array(v) for v in f(qv, qdv, wv))
        s, S = nodes.positions(qv), nodes.partial_velocities(qv)
        M_ref, k_ref = np.zeros((6 + n_e,) * 2), np.zeros(6 + n_e)
        for J in range(N):
            B = np.hstack([np.eye(3), -_skew(s[J]), S[J]])
            h = np.array([0.0, 0.0, -qdv @ nodes.axial_reduction[:, :, J] @ qdv])
            acc = np.cross(wv, np.cross(wv, s[J])) + 2 * np.cross(wv, S[J] @ qdv) + h
            M_ref += nodes.mass[J] * B.T @ B
            k_ref += nodes.mass[J] * B.T @ acc
        np.testing.assert_allclose(Mb, M_ref, atol=1e-12 * np.abs(M_ref).max())
        np.testing.assert_allclose(k.ravel(), k_ref, atol=1e-12 * np.abs(k_ref).max())


def _blade_on_hub(kinematics: str, gravity: float = 9.80665):
    """One NREL 5 MW blade (F1, F2, E1; no damping) on a hub turning freely about x, 1.5 m from the axis."""
    sys = mb.System(gravity=[0, 0, -gravity])
    psi = sys.coordinates("psi")
    qe = sys.coordinates("f1 f2 e1")
    hub = mb.RigidBody("hub", mass=5.7e4, inertia=[1.2e5, 1e5, 1e5])
    sys.add_joint(mb.Revolute(sys.ground, hub, axis=[1, 0, 0], coordinate=psi, offset=[0, 0, 90.0]))
    sid = blade_shape_integrals(nrel5mw(), dofs=("FlapDOF1", "FlapDOF2", "EdgeDOF"))
    kw = {"kinematics": "exact"} if kinematics == "exact" else {}
    blade = FlexibleBody("blade", sid, qe, damping=np.zeros((3, 3)), **kw)
    sys.add_joint(mb.Fixed(hub, blade, offset=[0, 0, 1.5]))
    return sys.equations()


def test_large_deflection_blade_conserves_energy():
    eom = _blade_on_hub("exact")
    x0 = np.array([0.3, 4.0, 0.5, -1.0, 1.0, 0.0, 0.0, 0.0])       # tip ~4 m out of plane, spinning at 1 rad/s
    r = mb.simulate(eom, 5.0, x0=x0, method="cvodes", rtol=1e-12, atol=1e-12, dt=0.05)
    f, p = eom.functions, eom.parameter_vector({})

    def call(fn, q, qd):
        values = dict(q=q, qd=qd, u=np.zeros(0), p=p)
        return float(fn(*[values[fn.name_in(i)] for i in range(fn.n_in())]))

    T = np.array([call(f.kinetic_energy, q, qd) for q, qd in zip(r.q, r.qd)])
    V = np.array([call(f.potential_energy, q, qd) for q, qd in zip(r.q, r.qd)])
    assert np.ptp(T) > 1e5
    assert np.ptp(T + V) <= 1e-9 * T.max(), (np.ptp(T + V), T.max())
    q, qd = r.q[17], r.qd[17]
    M = np.array(eom.mass_matrix(q))
    np.testing.assert_allclose(M, M.T, rtol=0, atol=0)
    assert np.linalg.eigvalsh(M).min() > 0
    assert call(f.kinetic_energy, q, qd) == pytest.approx(0.5 * qd @ M @ qd, rel=1e-10)


def _linear(eom, x):
    n = eom.n_q
    lin = mb.linearize(eom, x[:n], x[n:], None, None, method="exact")
    return lin.M, lin.C, lin.K


def test_blade_linearization_at_zero_deflection_is_unchanged():
    x = np.array([0.4, 0.0, 0.0, 0.0, 1.2, 0.0, 0.0, 0.0])        # spinning at 1.2 rad/s, undeflected
    for A, B, name in zip(_linear(_blade_on_hub("exact"), x), _linear(_blade_on_hub("shape_integrals"), x), "MCK"):
        np.testing.assert_allclose(A, B, rtol=0, atol=1e-9 * np.abs(B).max(), err_msg=name)


def _tower_with_top(kinematics: str):
    t = nrel5mw()
    sys = mb.System(gravity=[0, 0, -9.80665])
    qe = sys.coordinates("fa ss")
    sid = tower_shape_integrals(t, dofs=["TwFADOF1", "TwSSDOF1"])
    top_mass = 3.5e5
    kw = {"kinematics": "exact"} if kinematics == "exact" else {"top_mass": top_mass}
    tower = FlexibleBody("tower", sid, qe, end_rotation_order="elastodyn", **kw)
    sys.add_joint(mb.Fixed(sys.ground, tower))
    top = mb.RigidBody("rna", mass=top_mass, com=[-0.4, 0.1, 1.9], inertia=[4e7, 2.5e7, 2.6e7])
    sys.add_joint(mb.Fixed(tower, top, offset=sid.end_position.tolist()))
    return sys.equations()


def test_tower_linearization_at_zero_deflection_is_unchanged():
    x = np.zeros(4)
    for A, B, name in zip(_linear(_tower_with_top("exact"), x), _linear(_tower_with_top("shape_integrals"), x), "MCK"):
        np.testing.assert_allclose(A, B, rtol=0, atol=1e-9 * np.abs(B).max(), err_msg=name)


def test_exact_kinematics_errors():
    z = np.linspace(0.0, 10.0, 21)
    continuous = shape_integrals(z, 2.0, 1e4, 1e4, [PolynomialShape([1.0], 10.0)])
    sys = mb.System()
    e = sys.coordinates("e")
    with pytest.raises(ModelDefinitionError, match="lumped_shape_integrals"):
        FlexibleBody("beam", continuous, [e], kinematics="exact")
    sid = tower_shape_integrals(nrel5mw(), dofs=["TwFADOF1"])
    with pytest.raises(ModelDefinitionError, match=r"\['taylor_order', 'top_mass'\].*remove them"):
        FlexibleBody("tower", sid, [e], kinematics="exact", taylor_order=1, top_mass=1.0)
    with pytest.raises(ModelDefinitionError, match="'shape_integrals' or 'exact'"):
        FlexibleBody("tower", sid, [e], kinematics="nodes")
    with pytest.raises(ModelDefinitionError, match="'exact' or 'slope_rates'"):
        FlexibleBody("tower", sid, [e], end_angular_velocity="elastodyn")


@pytest.mark.parametrize("change, match", [
    (dict(mass=[1.0, 2.0]), "mass has shape"),
    (dict(displacement=np.zeros((1, 3, 3))), "displacement has shape"),
    (dict(axial_reduction=np.array([[[1.0, 0, 0], [2.0, 0, 0]], [[0.0, 0, 0], [0.0, 0, 0]]])), "symmetric"),
    (dict(z=[0.0, np.nan, 1.0]), "NaN or Inf"),
    (dict(mass=[1.0, -1.0, 1.0]), ">= 0"),
])
def test_lumped_nodes_validation(change, match):
    good = dict(z=[0.0, 0.5, 1.0], mass=[1.0, 1.0, 1.0], displacement=np.zeros((2, 3, 2)),
                axial_reduction=np.zeros((2, 2, 3)), end_axial_reduction=np.zeros((2, 2)))
    good.update(change)
    with pytest.raises(BeamDataError, match=match):
        LumpedNodes(**good)
