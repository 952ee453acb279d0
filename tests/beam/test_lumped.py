"""Shape integrals of lumped point-mass bodies (mbsym.beam.lumped).

References
----------
- The continuous shape integrals of the same beam (``mbsym.beam.shape_integrals``,
  Simpson on 2001 stations): the lumped mid-point sums converge to them as O(h^2).
- The exact quasi-static potential of point masses moving on
  ``s_J(q) = z_J e_z + Phi(J) q - 1/2 q^T Ax(J) q e_z`` in an accelerating, rotating
  frame, differentiated twice by central finite differences (no use of the derivation
  in the module).
- Hand sums for one or two point masses.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import cumulative_trapezoid

from mbsym.beam import CallableShape, PolynomialShape, shape_integrals, spin_softening
from mbsym.beam.lumped import lumped_shape_integrals
from mbsym.exceptions import BeamDataError

L_BEAM = 7.0
M_TIP = 1.5


def _shapes(L: float) -> list:
    """Shapes with x and y components so that every cross term is non-zero."""
    return [PolynomialShape([0.6, 0.4], L, "x", name="x-poly"),
            PolynomialShape([1.0], L, "y", name="y-poly"),
            CallableShape(lambda z: np.vstack([0.3 * (z / L) ** 3, -(1 - np.cos(np.pi * z / (2 * L)))]), L,
                          direction=None, name="vector")]


def _mass(z: np.ndarray) -> np.ndarray:
    return 2.0 + 0.3 * z


def _lumped_version(n_nodes: int, ke: np.ndarray):
    """Mid-point nodes, masses m(z) dz; Ax(z) = int_0^z Phi'.Phi' on a fine grid (trapezoid, 40001 pts)."""
    shapes = _shapes(L_BEAM)
    dz = L_BEAM / n_nodes
    z = (np.arange(n_nodes) + 0.5) * dz
    disp = np.stack([s.evaluate(z).T for s in shapes])                       # (n_e, N, 3)
    zf = np.linspace(0.0, L_BEAM, 40001)
    slopes = np.stack([s.evaluate(zf, 1) for s in shapes])                    # (n_e, 3, nf)
    ax_fine = cumulative_trapezoid(np.einsum("iaf,jaf->ijf", slopes, slopes), zf, initial=0.0, axis=-1)
    ax = np.stack([[np.interp(z, zf, ax_fine[i, j]) for j in range(3)] for i in range(3)])
    tip_u = np.stack([s.evaluate([L_BEAM])[:, 0] for s in shapes])
    tip_s = np.stack([s.evaluate([L_BEAM], 1)[:, 0] for s in shapes])
    return lumped_shape_integrals(z, _mass(z) * dz, disp, ax, length=L_BEAM, tip_displacement=tip_u,
                                  tip_slope=tip_s, tip_axial_reduction=ax_fine[:, :, -1], stiffness=ke,
                                  tip_mass=M_TIP)


@pytest.fixture(scope="module")
def continuous():
    z = np.linspace(0.0, L_BEAM, 9)
    return shape_integrals(z, _mass(z), 3e3, 2e3, _shapes(L_BEAM), tip_mass=M_TIP, quadrature="simpson",
                           n_points=2001)


_FIELDS = ["mxt.order0", "mxt.order1", "mtt.order0", "mtt.order1", "mtt2", "ct", "cr.order0", "cr.order1",
           "me", "gr.order0", "gr.order1", "ge", "oe.order0", "oe.order1", "kg_t", "kg_r", "kg_omega",
           "kg_tip", "end_position", "end_displacement", "end_rotation"]


def _field(sid, name: str) -> np.ndarray:
    obj = sid
    for part in name.split("."):
        obj = getattr(obj, part)
    return np.asarray(obj)


def test_every_field_converges_to_the_continuous_integrals(continuous):
    """Uniform-in-form beam (m = 2 + 0.3 z, tip mass 1.5 kg), 3 vector shapes: every field of the
    lumped SID with 400 mid-point nodes equals the continuous one to 1e-5 of the field's scale
    (mid-point rule O(h^2): measured 5.7e-7 .. 5.9e-6), including the signs of kg_t, kg_omega,
    kg_tip; and the difference shrinks 4x (3.5 .. 4.5) when the nodes are doubled (200 -> 400);
    kg_tip and end_* are exact up to the 40001-point reference integral (measured 6e-10)."""
    coarse = _lumped_version(200, continuous.ke)
    fine = _lumped_version(400, continuous.ke)
    assert fine.mass == pytest.approx(continuous.mass, rel=1e-12)
    for name in _FIELDS:
        ref = _field(continuous, name)
        scale = max(np.abs(ref).max(), 1e-300)
        err_fine = np.abs(_field(fine, name) - ref).max() / scale
        err_coarse = np.abs(_field(coarse, name) - ref).max() / scale
        assert err_fine < 1e-5, name
        if err_coarse > 1e-8:        # exact fields (kg_tip, end_*, zero kg_r) have nothing to converge
            assert 3.5 < err_coarse / err_fine < 4.5, name
    # signs: tension from (a - g) along -z is positive, centrifugal stiffening positive
    assert np.all(np.diag(fine.kg_t[2]) < 0) and np.all(np.diag(fine.kg_omega[0, 0]) > 0)
    assert np.all(np.diag(fine.kg_tip[2]) > 0)


def _random_body(seed: int = 3):
    rng = np.random.default_rng(seed)
    n_e, n = 3, 5
    z = np.sort(rng.uniform(0.5, 4.0, n))
    masses = rng.uniform(1.0, 3.0, n)
    disp = np.concatenate([rng.normal(size=(n_e, n, 2)), np.zeros((n_e, n, 1))], axis=-1)
    b = rng.normal(size=(n, n_e, n_e))
    ax = np.moveaxis(b @ np.swapaxes(b, 1, 2), 0, -1) / 3                  # SPD per node
    tip_u, tip_s = rng.normal(size=(n_e, 2)), rng.normal(size=(n_e, 2))
    bt = rng.normal(size=(n_e, n_e))
    ax_tip = bt @ bt.T
    return z, masses, disp, ax, tip_u, tip_s, ax_tip


def test_geometric_stiffness_is_the_hessian_of_the_exact_potential():
    """Point masses on s_J(q) = z_J e_z + Phi(J) q - 1/2 q^T Ax(J) q e_z (plus a tip mass), frame with
    origin acceleration a, gravity g, angular velocity w and a tip force F: the Hessian in q at q = 0
    of V = sum m (a - g).s - 1/2 m |w x s|^2 - F.s_tip (central differences, step 1e-4) equals
    K_g(a, g, w, F) + sum_ab w_a w_b oe.order1 (spin softening) to 1e-6 relative."""
    z, masses, disp, ax, tip_u, tip_s, ax_tip = _random_body()
    L, m_tip = 5.0, 0.7
    sid = lumped_shape_integrals(z, masses, disp, ax, length=L, tip_displacement=tip_u, tip_slope=tip_s,
                                 tip_axial_reduction=ax_tip, stiffness=np.eye(3), tip_mass=m_tip)
    a, g = np.array([0.3, -0.4, 1.2]), np.array([0.0, 0.2, -9.81])
    w, force = np.array([0.7, -0.5, 0.4]), np.array([0.2, -0.3, 2.5])
    tip_u3 = np.concatenate([tip_u, np.zeros((3, 1))], axis=1)
    pts_m = np.append(masses, m_tip)

    def potential(q: np.ndarray) -> float:
        s = np.stack([np.array([0.0, 0.0, zz]) for zz in z] + [np.array([0.0, 0.0, L])])
        s[:-1] += np.einsum("jJa,j->Ja", disp, q)
        s[:-1, 2] -= 0.5 * np.einsum("i,ijJ,j->J", q, ax, q)
        s[-1] += tip_u3.T @ q
        s[-1, 2] -= 0.5 * q @ ax_tip @ q
        v = pts_m @ (s @ (a - g)) - 0.5 * pts_m @ np.sum(np.cross(w, s) ** 2, axis=1)
        return float(v - force @ s[-1])

    h, eye = 1e-4, np.eye(3)
    hess = np.array([[(potential(h * (eye[i] + eye[j])) - potential(h * (eye[i] - eye[j]))
                       - potential(h * (eye[j] - eye[i])) + potential(-h * (eye[i] + eye[j]))) / (4 * h * h)
                      for j in range(3)] for i in range(3)])
    kg = sid.geometric_stiffness(acceleration=a, gravity=g, angular_velocity=w, tip_force=force)
    soft = np.einsum("a,b,jiab->ij", w, w, sid.oe.order1)
    np.testing.assert_allclose(kg + soft, hess, rtol=0, atol=1e-6 * np.abs(hess).max())
    # about a single axis, the softening is the documented spin_softening()
    e = w / np.linalg.norm(w)
    np.testing.assert_allclose(np.einsum("a,b,jiab->ij", e, e, sid.oe.order1), spin_softening(sid, e),
                               atol=1e-12)


def test_single_point_mass_hand_sums():
    """One 2 kg mass at z = 3 of a 4 m body moved by (1, 0.5) per q plus a 0.5 kg tip mass moved by
    (2, 0): M = 2 + 0.5 (1 + 0.25) ... by hand; Ax = 0.4 at the node, 0.9 at the tip."""
    sid = lumped_shape_integrals([3.0], [2.0], [[[1.0, 0.5, 0.0]]], [[[0.4]]], length=4.0,
                                 tip_displacement=[[2.0, 0.0]], tip_slope=[[0.6, -0.2]],
                                 tip_axial_reduction=[[0.9]], stiffness=[[10.0]], damping=[[0.3]], tip_mass=0.5)
    assert sid.mass == pytest.approx(2.5)
    np.testing.assert_allclose(sid.center_of_mass, [0, 0, (2 * 3 + 0.5 * 4) / 2.5])
    assert sid.me[0, 0] == pytest.approx(2 * 1.25 + 0.5 * 4)
    np.testing.assert_allclose(sid.ct[0], [2 * 1 + 0.5 * 2, 2 * 0.5, 0])
    # C_r = sum m s x Phi: s = 3 e_z, Phi = (1, .5, 0) -> (-1.5, 3, 0); tip 4 e_z x (2, 0, 0) = (0, 8, 0)
    np.testing.assert_allclose(sid.cr.order0[0], 2 * np.array([-1.5, 3.0, 0]) + 0.5 * np.array([0, 8.0, 0]))
    np.testing.assert_allclose(sid.mtt.order0, np.diag([2 * 9 + 0.5 * 16] * 2 + [0.0]))
    assert sid.kg_t[2, 0, 0] == pytest.approx(-(2 * 0.4 + 0.5 * 0.9))
    assert sid.kg_omega[0, 0, 0, 0] == sid.kg_omega[1, 1, 0, 0] == pytest.approx(2 * 3 * 0.4 + 0.5 * 4 * 0.9)
    assert sid.kg_tip[2, 0, 0] == pytest.approx(0.9)
    mask = np.ones((3, 3), bool)
    mask[0, 0] = mask[1, 1] = False
    assert not np.any(sid.kg_omega[mask]) and not np.any(sid.kg_t[:2]) and not np.any(sid.kg_r)
    np.testing.assert_allclose(sid.end_rotation[:, 0], [0.2, 0.6, 0.0])
    np.testing.assert_allclose(sid.end_displacement[:, 0], [2.0, 0.0, 0.0])
    assert sid.de[0, 0] == 0.3 and sid.frequencies_hz[0] == pytest.approx(np.sqrt(10 / 4.5) / (2 * np.pi))


def _good() -> dict:
    return dict(z=[1.0, 2.0], masses=[1.0, 1.0], displacements=np.ones((1, 2, 3)) * [1, 0, 0],
                axial_reduction=np.ones((1, 1, 2)), length=2.5, tip_displacement=[[1.0, 0.0]],
                tip_slope=[[1.0, 0.0]], tip_axial_reduction=[[1.0]], stiffness=[[1.0]])


@pytest.mark.parametrize("change, match", [
    (dict(z=[1.0, 3.0]), r"node 1 is at z = 3 m, outside the beam"),
    (dict(z=[1.0, np.nan]), r"`z` entry \(1,\) is nan"),
    (dict(masses=[1.0, -1.0]), r"`masses` at node 1 is -1 kg"),
    (dict(masses=[0.0, 0.0]), r"the body has no mass"),
    (dict(masses=[1.0]), r"`masses` has shape \(1,\); expected \(2,\)"),
    (dict(length=0.0), r"`length` must be a positive"),
    (dict(displacements=np.ones((1, 2, 3))), r"non-zero z \(axial\) component"),
    (dict(displacements=np.ones((2, 3))), r"`displacements` has shape \(2, 3\); expected \(n_e, 2, 3\)"),
    (dict(axial_reduction=np.ones((1, 1, 3))), r"`axial_reduction` has shape \(1, 1, 3\); expected \(1, 1, 2\)"),
    (dict(tip_axial_reduction=[[1.0, 2.0]]), r"`tip_axial_reduction` has shape"),
    (dict(stiffness=[[np.inf]]), r"`stiffness` entry \(0, 0\) is inf"),
    (dict(tip_mass=-1.0), r"`tip_mass` must be finite and >= 0"),
    (dict(displacements=np.zeros((1, 2, 3))), r"generalized mass .* is singular"),
])
def test_bad_input_raises_beam_data_error(change, match):
    kw = _good()
    kw.update(change)
    with pytest.raises(BeamDataError, match=match):
        lumped_shape_integrals(kw.pop("z"), kw.pop("masses"), kw.pop("displacements"),
                               kw.pop("axial_reduction"), **kw)


def test_non_symmetric_axial_reduction_is_rejected():
    kw = _good()
    kw.update(displacements=np.ones((2, 2, 3)) * [1, 0, 0] + np.array([0, 1, 0])[None, None] * [[[0]], [[1]]],
              axial_reduction=np.array([[[1, 1], [0, 0]], [[1, 1], [1, 1]]], float),
              tip_displacement=np.eye(2), tip_slope=np.eye(2), tip_axial_reduction=np.eye(2), stiffness=np.eye(2))
    with pytest.raises(BeamDataError, match=r"`axial_reduction` must be symmetric"):
        lumped_shape_integrals(kw.pop("z"), kw.pop("masses"), kw.pop("displacements"),
                               kw.pop("axial_reduction"), **kw)
