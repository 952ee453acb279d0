"""A flexible link in a closed loop: the reduced Kane equations against the multiplier (DAE) formulation.

Model: a four-bar in the x-z plane whose coupler is a flexible beam (two cantilever FEM modes, 2 m,
2 kg/m, EI = 2e3 N m^2), closed at the rocker tip; independent coordinates q1 and the two modal
amplitudes. Reference (SymPy's "minimal vs constrained" check, TESTING.md): the open tree's own
equations ``M q̈ = F + Gᵀ λ`` with the constraint acceleration ``G q̈ + Ġ q̇ = 0`` solved as one linear
system, where ``G`` and ``Ġ q̇`` come from the tree's point kinematics of the closure point (velocity
``G q̇`` is linear in q̇, acceleration at q̈ = 0 is ``Ġ q̇``): a formulation with multipliers and all five
accelerations, against mbsym's projection on the independent speeds with the dependent coordinates
solved in the graph. Tolerance 1e-9 relative (both exact; the dependent coordinates are Newton-converged
to ~1e-15). (Energy is not a reference here: the flexible-body model drops the q̈ parts of geometric
stiffening, so even the open tree does not conserve it exactly.) Runtime ~1 s.
"""

from __future__ import annotations

import numpy as np
import pytest

import mbsym as mb
from mbsym.beam import cantilever_modes, shape_integrals

LC = 2.0


def build(closed: bool):
    z = np.linspace(0.0, LC, 21)
    modes = cantilever_modes(z, 2.0, 2e3, n_modes=2, n_elements=10, direction="x")
    sid = shape_integrals(z, 2.0, 2e3, 2e3, modes.shapes(), quadrature="simpson")
    s = mb.System(gravity=[0.0, 0.0, -9.81])
    q1, q2, q3, e1, e2 = s.coordinates("q1 q2 q3 e1 e2")
    crank = mb.RigidBody("crank", 1.0, com=[0, 0, 0.5], inertia=np.diag([0.1, 0.1, 0.01]))
    coupler = mb.FlexibleBody("coupler", sid, [e1, e2])
    rocker = mb.RigidBody("rocker", 1.0, com=[0, 0, 1.0], inertia=np.diag([0.3, 0.3, 0.01]))
    s.add_joint(mb.Revolute(s.ground, crank, axis=[0, 1, 0], coordinate=q1))
    s.add_joint(mb.Revolute(crank, coupler, axis=[0, 1, 0], coordinate=q2, offset=[0, 0, 1.0]))
    s.add_joint(mb.Revolute(coupler, rocker, axis=[0, 1, 0], coordinate=q3, offset=[0, 0, LC]))
    if not closed:
        return s.equations()
    s.add_closure(rocker, [0, 0, 2.0], s.ground, [0, 0, 2.5], directions="xz")
    return s.equations(independent=["q1", "e1", "e2"], guess={"q2": -1.2, "q3": 2.4})


@pytest.fixture(scope="module")
def models():
    return build(True), build(False)


@pytest.mark.parametrize("qi,vi", [([0.3, 0.01, -0.002], [2.0, 0.3, -1.0]), ([2.0, -0.02, 0.004], [-1.0, 0.0, 2.0])])
def test_flexible_loop_matches_multiplier_formulation(models, qi, vi):
    loop, tree = models
    q = loop.configuration(qi)
    y = np.asarray(loop.output_function()(np.r_[qi, vi], [], [])).ravel()
    qd = q.copy()
    qd[[0, 3, 4]], qd[[1, 2]] = vi, y[2:4]                    # coordinates order q1 q2 q3 e1 e2
    tip = tree.point_kinematics("rocker", [0, 0, 2.0])
    G = -np.column_stack([np.asarray(tip(q, e, np.zeros(5), [], [])[2]).ravel() for e in np.eye(5)])[[0, 2]]
    gamma = -np.asarray(tip(q, qd, np.zeros(5), [], [])[4]).ravel()[[0, 2]]
    M, F = tree.mass_matrix(q), tree.forcing(q, qd)
    K = np.block([[M, -G.T], [G, np.zeros((2, 2))]])
    sol = np.linalg.solve(K, np.r_[F, -gamma])
    qdd, lam = sol[:5], sol[5:]
    assert np.max(np.abs(G @ qd)) < 1e-12                    # the loop's dependent speeds satisfy G q̇ = 0
    acc = loop.accelerations(qi, vi)
    assert np.allclose(acc, qdd[[0, 3, 4]], rtol=1e-9, atol=1e-9 * np.max(np.abs(qdd)))
    assert np.allclose(loop.constraint_forces(qi, vi), lam, rtol=1e-9, atol=1e-9 * np.max(np.abs(lam)))
