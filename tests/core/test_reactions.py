"""Locked coordinates and their reaction generalized forces (sys.locked, eom.functions.reactions).

References:
- Newton–Euler by hand: a body hanging from a locked pivot on an accelerating cart needs the
  support torque τ_y = -m l a about the pivot (its centre of mass is l below the pivot); the
  pivot force is (m a, 0, m g).
- Two formulations: the reaction of a locked coordinate equals minus the residual row of the
  same coordinate made free, evaluated at zero angle, speed and acceleration with the other
  accelerations taken from the locked model (Kane's equations of the free coordinate).
"""

from __future__ import annotations

import numpy as np
import pytest

import mbsym as mb

G = 9.81


def cart_with_locked_pendulum(locked: bool):
    sys = mb.System(gravity=[0, 0, -G])
    x = sys.coordinates("x")
    th = sys.locked("th") if locked else sys.coordinates("th")
    F = sys.inputs("F")
    m_c, m, l, Jc = 3.0, 2.0, 1.5, 0.4
    cart = mb.RigidBody("cart", m_c)
    bob = mb.RigidBody("bob", m, com=[0, 0, -l], inertia=(Jc, Jc, Jc))
    sys.add_joint(mb.Prismatic(sys.ground, cart, axis=[1, 0, 0], coordinate=x))
    sys.add_joint(mb.Revolute(cart, bob, axis=[0, 1, 0], coordinate=th, offset=[0.2, 0, 0.5]))
    sys.add_generalized_force(x, F)
    return sys.equations(), (m_c, m, l)


def test_pendulum_on_accelerating_cart_against_newton_euler():
    eom, (m_c, m, l) = cart_with_locked_pendulum(True)
    assert eom.coordinates == ("x",) and eom.locked == ("th",) and eom.inputs == ("F",)
    F = 10.0
    qdd = eom.accelerations([0.3], [0.7], [F])
    a = F / (m_c + m)                       # the whole system translates rigidly
    assert qdd[0] == pytest.approx(a, rel=1e-14)
    lam = eom.reactions([0.3], [0.7], qdd, [F])
    assert lam.shape == (1,) and lam[0] == pytest.approx(-m * l * a, rel=1e-12)


def test_reaction_equals_free_coordinate_residual():
    locked, _ = cart_with_locked_pendulum(True)
    free, _ = cart_with_locked_pendulum(False)
    rng = np.random.default_rng(3)
    for _ in range(5):
        x, xd, F = rng.normal(size=3)
        qdd = locked.accelerations([x], [xd], [F])
        lam = locked.reactions([x], [xd], qdd, [F])
        e = free.residual([x, 0.0], [xd, 0.0], [qdd[0], 0.0], [F])
        assert e[0] == pytest.approx(0.0, abs=1e-12)       # the x equation holds in the free model too
        assert lam[0] == pytest.approx(-e[1], rel=1e-12, abs=1e-12)


def test_spinning_rotor_on_locked_tilt_is_gyroscopic():
    """A rotor spinning at Ω about x on a yawing base (ψ̇ about z) needs the gyroscopic support
    torque τ_y = J_x Ω ψ̇ about y (Euler: dH/dt = ω_base × H with H = J_x Ω e_x)."""
    sys = mb.System()
    yaw, spin = sys.coordinates("yaw spin")
    tilt = sys.locked("tilt")
    Jx, Jt = 5.0, 2.5                  # a disc: Jx = 2 Jt (a rigid body has Jx <= 2 Jt)
    base = mb.RigidBody("base", 1.0, inertia=(1.0, 1.0, 1.0))
    frame = mb.RigidBody("frame", 0.5, inertia=(0.1, 0.1, 0.1))
    rotor = mb.RigidBody("rotor", 3.0, inertia=(Jx, Jt, Jt))
    sys.add_joint(mb.Revolute(sys.ground, base, axis=[0, 0, 1], coordinate=yaw))
    sys.add_joint(mb.Revolute(base, frame, axis=[0, 1, 0], coordinate=tilt))
    sys.add_joint(mb.Revolute(frame, rotor, axis=[1, 0, 0], coordinate=spin))
    eom = sys.equations()
    Om, psid = 4.0, 0.3
    qd = [psid, Om]
    qdd = eom.accelerations([0.1, 0.2], qd)
    lam = eom.reactions([0.1, 0.2], qd, qdd)
    assert qdd == pytest.approx([0.0, 0.0], abs=1e-14)
    assert lam[0] == pytest.approx(Jx * Om * psid, rel=1e-12)


def test_no_locked_coordinates_means_no_reactions():
    eom, _ = cart_with_locked_pendulum(False)
    assert eom.functions.reactions is None and eom.locked == ()
    with pytest.raises(mb.ModelDefinitionError, match="no locked coordinates"):
        eom.reactions([0, 0], [0, 0], [0, 0], [0.0])


def test_locked_coordinate_cannot_deflect_a_flexible_body_or_drive_two_joints():
    sys = mb.System()
    a = sys.locked("a")
    sys.add_joint(mb.Revolute(sys.ground, mb.RigidBody("b1", 1.0), axis=[0, 0, 1], coordinate=a))
    with pytest.raises(mb.ModelDefinitionError, match="already moves body"):
        sys.add_joint(mb.Revolute(sys.ground, mb.RigidBody("b2", 1.0), axis=[0, 0, 1], coordinate=a))


def test_point_kinematics_of_a_model_with_locked_coordinates_equals_the_welded_model():
    """Locked coordinates are held at zero: a point's kinematics equal those of the same chain with the
    locked joint welded (the pendulum hanging straight on the cart, moving with it)."""
    locked, _ = cart_with_locked_pendulum(True)
    sys = mb.System(gravity=[0, 0, -G])
    x = sys.coordinates("x")
    F = sys.inputs("F")
    cart, bob = mb.RigidBody("cart", 3.0), mb.RigidBody("bob", 2.0, com=[0, 0, -1.5], inertia=(0.4, 0.4, 0.4))
    sys.add_joint(mb.Prismatic(sys.ground, cart, axis=[1, 0, 0], coordinate=x))
    sys.add_joint(mb.Fixed(cart, bob, offset=[0.2, 0, 0.5]))
    sys.add_generalized_force(x, F)
    welded = sys.equations()
    args = ([0.3], [0.7], [1.1], [10.0], [])
    for a, b in zip(locked.point_kinematics("bob", [0.1, 0.0, -1.5])(*args),
                    welded.point_kinematics("bob", [0.1, 0.0, -1.5])(*args)):
        np.testing.assert_allclose(np.asarray(a), np.asarray(b), rtol=0, atol=1e-14)
