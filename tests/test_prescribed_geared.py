"""Prescribed (rheonomic) coordinates, geared joints and ElastoDyn's small rotation.

References
----------
- Two formulations of one system agree: with a coordinate ψ made prescribed, the remaining
  equations must equal the full model's rows with ψ, ψ̇, ψ̈ moved to the right-hand side:
  F_presc = F_full,φ - M_full,φψ ψ̈ and M_presc = M_full,φφ (1e-12).
- Bead on a rod spinning at Ω about z: F = m r Ω² (closed form).
- Rotor of inertia J_r driving a generator of inertia J_g through a gear N: M = J_r + N² J_g.
- SmllRotTrans: orthonormal, rotation angle atan|θ| about θ (ElastoDyn's definition).
"""

import casadi as ca
import numpy as np
import pytest

import mbsym as mb
from mbsym.kinematics import elastodyn_rotation


def _arm(prescribed: bool):
    sys = mb.System(gravity=[0.0, -9.81, 0.0])
    psi = sys.prescribed("psi") if prescribed else sys.coordinates("psi")
    phi = sys.coordinates("phi")
    hub = mb.RigidBody("hub", mass=2.0, com=[0.3, 0.0, 0.1], inertia=[1.0, 2.0, 3.0])
    link = mb.RigidBody("link", mass=1.5, com=[0.8, 0.1, 0.0], inertia=[0.2, 0.3, 0.4, 0.01, 0.02, 0.03])
    sys.add_joint(mb.Revolute(sys.ground, hub, axis=[0, 0, 1], coordinate=psi))
    sys.add_joint(mb.Revolute(hub, link, axis=[0.3, 0.2, 1.0], coordinate=phi, offset=[1.0, 0.0, 0.2]))
    return sys.equations()


def test_prescribed_equals_full_model_rows():
    full, presc = _arm(False), _arm(True)
    assert presc.coordinates == ("phi",) and presc.inputs == ("psi", "psi_d", "psi_dd")
    rng = np.random.default_rng(3)
    for _ in range(3):
        psi, phi, psid, phid, psidd = rng.normal(size=5)
        Mf = full.mass_matrix([psi, phi])
        Ff = full.forcing([psi, phi], [psid, phid])
        Mp = presc.mass_matrix([phi], u=[psi, psid, psidd])
        Fp = presc.forcing([phi], [phid], [psi, psid, psidd])
        assert Mp[0, 0] == pytest.approx(Mf[1, 1], rel=1e-12)
        assert Fp[0] == pytest.approx(Ff[1] - Mf[1, 0] * psidd, rel=1e-12, abs=1e-12)


def test_bead_on_spinning_rod():
    sys = mb.System()
    psi = sys.prescribed("psi")
    r = sys.coordinates("r")
    rod = mb.RigidBody("rod", mass=1.0, inertia=[1, 1, 1])
    sys.add_joint(mb.Revolute(sys.ground, rod, axis=[0, 0, 1], coordinate=psi))
    sys.add_joint(mb.Prismatic(rod, mb.RigidBody("bead", mass=0.7), axis=[1, 0, 0], coordinate=r))
    eom = sys.equations()
    om = 2.3
    assert eom.forcing([0.4], [0.0], [0.1, om, 0.0])[0] == pytest.approx(0.7 * 0.4 * om**2, rel=1e-12)
    assert eom.speeds == ("r_d",) and sys.speed(psi).name() == "psi_d"


def test_geared_generator_inertia():
    sys = mb.System()
    th = sys.coordinates("th")
    frame = mb.RigidBody("frame", mass=0.0)
    rotor = mb.RigidBody("rotor", mass=10.0, inertia=[4.0, 2.0, 2.0])
    gen = mb.RigidBody("gen", mass=5.0, inertia=[0.02, 0.01, 0.01])
    sys.add_joint(mb.Fixed(sys.ground, frame))
    sys.add_joint(mb.Revolute(frame, rotor, axis=[1, 0, 0], coordinate=th))
    sys.add_joint(mb.Revolute(frame, gen, axis=[1, 0, 0], coordinate=th, gear_ratio=97.0))
    eom = sys.equations()
    assert eom.mass_matrix([0.3])[0, 0] == pytest.approx(4.0 + 97.0**2 * 0.02, rel=1e-12)
    assert eom.kinetic_energy([0.3], [2.0]) == pytest.approx(0.5 * (4.0 + 97.0**2 * 0.02) * 4.0, rel=1e-12)


def test_second_joint_on_a_coordinate_needs_gear_ratio():
    sys = mb.System()
    th = sys.coordinates("th")
    a, b = mb.RigidBody("a", 1.0, inertia=[1, 1, 1]), mb.RigidBody("b", 1.0, inertia=[1, 1, 1])
    sys.add_joint(mb.Revolute(sys.ground, a, axis=[1, 0, 0], coordinate=th))
    with pytest.raises(mb.ModelDefinitionError, match="already moves body 'a'"):
        sys.add_joint(mb.Revolute(sys.ground, b, axis=[1, 0, 0], coordinate=th))
    with pytest.raises(mb.ModelDefinitionError, match="gear_ratio .* nonzero"):
        mb.Revolute(sys.ground, b, axis=[1, 0, 0], coordinate=th, gear_ratio=0.0)


@pytest.mark.parametrize("theta", [[0.0, 0.0, 0.0], [0.1, -0.2, 0.05], [0.0, 0.0, 1.0], [1.5, 2.0, -0.3]])
def test_elastodyn_rotation_is_atan_rotation(theta):
    R = np.array(ca.evalf(elastodyn_rotation(theta)))
    np.testing.assert_allclose(R @ R.T, np.eye(3), atol=1e-14)
    assert np.linalg.det(R) == pytest.approx(1.0, abs=1e-14)
    th = np.asarray(theta)
    n = np.linalg.norm(th)
    if n > 0:
        np.testing.assert_allclose(R @ th, th, atol=1e-14)          # axis is θ
        angle = np.arccos(np.clip((np.trace(R) - 1) / 2, -1, 1))
        assert angle == pytest.approx(np.arctan(n), abs=1e-12)


def test_geared_joint_carrying_a_flexible_body():
    """A geared joint whose child owns elastic coordinates (regression: SX compared with ==)."""
    from mbsym.beam import PolynomialShape, shape_integrals
    sys = mb.System()
    a, qe = sys.coordinates("a qe")
    hub = mb.RigidBody("hub", 1.0, inertia=[1, 1, 1])
    sys.add_joint(mb.Revolute(sys.ground, hub, axis=[1, 0, 0], coordinate=a))
    sid = shape_integrals(np.linspace(0, 10, 11), 1.0, 1e4, 1e4, [PolynomialShape([1.0], 10.0)])
    blade = mb.FlexibleBody("blade", sid, [qe])
    sys.add_joint(mb.Revolute(hub, blade, axis=[0, 0, 1], coordinate=a, gear_ratio=1.0))
    assert sys.equations().coordinates == ("a", "qe")


def test_exact_small_rotation_is_smooth_at_zero():
    """small_rotation(order=None) has finite derivatives at θ = 0 (a flexible end with an exact
    end rotation can be linearized at rest) and agrees with its series to machine precision."""
    from mbsym.kinematics import small_rotation
    th = ca.SX.sym("th", 3)
    R = small_rotation(th, order=None)
    J = ca.Function("J", [th], [ca.jacobian(ca.vec(R), th), ca.jacobian(ca.jacobian(ca.vec(R), th)[:, 0], th)])
    for t in ([0.0, 0.0, 0.0], [1e-9, 0.0, 0.0], [0.3, -0.2, 0.1]):
        d1, d2 = (np.array(m) for m in J(t))
        assert np.all(np.isfinite(d1)) and np.all(np.isfinite(d2))
    Rn = np.array(ca.Function("R", [th], [R])([1e-5, 2e-5, -1e-5]))
    Rs = np.array(ca.evalf(small_rotation([1e-5, 2e-5, -1e-5], order=6)))
    np.testing.assert_allclose(Rn, Rs, atol=1e-15)


def test_joint_rotation_must_be_a_rotation():
    sys = mb.System()
    th = sys.coordinates("th")
    with pytest.raises(mb.ModelDefinitionError, match="not a proper rotation matrix"):
        mb.Revolute(sys.ground, mb.RigidBody("b", 1.0, inertia=[1, 1, 1]), axis=[1, 0, 0], coordinate=th,
                    rotation=2 * np.eye(3))
    with pytest.raises(mb.ModelDefinitionError, match="gear_ratio .* must be a number"):
        mb.Revolute(sys.ground, mb.RigidBody("b", 1.0), axis=[1, 0, 0], coordinate=th, gear_ratio="abc")


def test_energy_inputs_required_with_prescribed_coordinates():
    presc = _arm(True)
    with pytest.raises(mb.DimensionError, match="prescribed coordinates \\['psi'\\]"):
        presc.mass_matrix([0.1])
    T = presc.kinetic_energy([0.1], [0.2], {}, u=[0.0, 1.0, 0.0])
    assert T > 0
