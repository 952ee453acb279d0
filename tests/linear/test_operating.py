"""Operating points: static equilibrium, steady rotation, azimuth sweeps with multi-blade coordinates.

References (closed forms, exact to the solver tolerance 1e-9)
--------------------------------------------------------------
- Mass m on a vertical spring k under gravity g: z = -m g / k.
- Pendulum (point mass m at l) with a constant torque τ: m g l sin θ = τ.
- Conical pendulum (point mass at l hanging from a shaft spinning at Ω, hinge on the axis):
  cos θ0 = g / (l Ω²); small oscillations of θ at fixed Ω (prescribed spin): ω² = Ω² sin² θ0
  (second derivative of the effective potential); with the spin free (angular momentum
  conserved, spherical pendulum): ω² = Ω² (1 + 3 cos² θ0).
- Three-bladed rotor, horizontal axis, gravity in the rotor plane, constant flap moment T:
  averaged over equally spaced azimuths the gravity moments cancel and every blade solves
  k β + m R² Ω² sin β cos β = T.
- Isotropic three-bladed rotor, hinged point-mass blades with flap springs, no gravity:
  rotating-frame flap frequency ω_r² = k/(m R²) + Ω²; in multi-blade coordinates the
  collective mode stays at ω_r and the cyclic pair appears at ω_r ± Ω (Bir 2008), and the
  transformed A does not depend on azimuth (1e-9).
"""

from __future__ import annotations

import numpy as np
import pytest

import mbsym as mb
from mbsym.linear import linearize_batch
from mbsym.linear import OperatingPoint, linearize_azimuths, static_equilibrium, steady_rotation

G = 9.81


def test_mass_on_spring():
    sys = mb.System(gravity=[0, 0, -G])
    z = sys.coordinates("z")
    sys.add_joint(mb.Prismatic(sys.ground, mb.RigidBody("m", 3.0), axis=[0, 0, 1], coordinate=z))
    sys.add_spring(z, 200.0)
    op = static_equilibrium(sys.equations())
    assert op.success, op.message
    assert op.q[0] == pytest.approx(-3.0 * G / 200.0, rel=1e-12)
    np.testing.assert_array_equal(op.qd, 0.0)


def test_pendulum_with_torque_and_linearization_there():
    sys = mb.System(gravity=[0, 0, -G])
    th = sys.coordinates("th")
    tau = sys.inputs("tau")
    sys.add_joint(mb.Revolute(sys.ground, mb.RigidBody("bob", 2.0, com=[0, 0, -1.5]), axis=[0, 1, 0], coordinate=th))
    sys.add_generalized_force(th, tau)
    eom = sys.equations()
    op = static_equilibrium(eom, [10.0], q0=[0.2])
    assert op.success, op.message
    assert abs(np.sin(op.q[0])) == pytest.approx(10.0 / (2.0 * G * 1.5), rel=1e-10)
    assert np.max(np.abs(eom.forcing(op.q, op.qd, op.u))) < 1e-9
    lin = mb.linearize(eom, op)                       # an OperatingPoint as q0
    np.testing.assert_array_equal(lin.operating_point["q"], op.q)
    assert lin.K[0, 0] == pytest.approx(2.0 * G * 1.5 * np.cos(op.q[0]), rel=1e-10)


def test_free_coordinate_with_net_force_is_reported():
    sys = mb.System()
    x, y = sys.coordinates("x y")
    F = sys.inputs("F")
    b = mb.RigidBody("b", 1.0)
    sys.add_joint(mb.Prismatic(sys.ground, b, axis=[1, 0, 0], coordinate=x))
    sys.add_joint(mb.Prismatic(b, mb.RigidBody("c", 1.0), axis=[0, 1, 0], coordinate=y))
    sys.add_spring(y, 5.0)
    sys.add_generalized_force(x, F)
    eom = sys.equations()
    ok = static_equilibrium(eom, [0.0])
    assert ok.success and ok.held == ("x",)
    bad = static_equilibrium(eom, [2.0])
    assert not bad.success
    assert "no static equilibrium" in bad.message and "x (2)" in bad.message


def test_newton_failure_is_reported():
    sys = mb.System()
    x = sys.coordinates("x")
    sys.add_joint(mb.Prismatic(sys.ground, mb.RigidBody("b", 1.0), axis=[1, 0, 0], coordinate=x))
    sys.add_generalized_force(x, np.exp(1.0) + 0.0 * x - (x - 1.0) ** 2 - 5.0)     # F < 0 everywhere: no root
    op = static_equilibrium(sys.equations(), q0=[0.5])
    assert not op.success
    assert "Newton's method found no equilibrium for ['x']" in op.message


def test_floating_platform_equilibrium(paper46):
    """paper46: surge has no stiffness (held); pitch and tower settle under the RNA overhang."""
    op = static_equilibrium(paper46)
    assert op.success, op.message
    assert op.held == ("Sg",)
    eom = paper46.eom
    assert np.max(np.abs(eom.forcing(op.q, op.qd, op.u))) < 1e-6        # [N, N m] on forces of ~1e8
    assert op.q[1] < 0 and op.q[2] < 0                                    # pitched and bent by the overhang
    lin = mb.linearize(paper46, op, method="exact")
    Minv = np.linalg.inv(lin.M)                                           # at equilibrium A agrees with M, C, K
    np.testing.assert_allclose(lin.A[3:], np.hstack([-Minv @ lin.K, -Minv @ lin.C]), rtol=1e-9, atol=1e-9)


def conical_pendulum(prescribed: bool):
    sys = mb.System(gravity=[0, 0, -G])
    th = sys.coordinates("th")
    psi = sys.prescribed("psi") if prescribed else sys.coordinates("psi")
    shaft = mb.RigidBody("shaft", 0.0)              # massless: the bob's own inertia carries psi
    sys.add_joint(mb.Revolute(sys.ground, shaft, axis=[0, 0, 1], coordinate=psi))
    sys.add_joint(mb.Revolute(shaft, mb.RigidBody("bob", 1.0, com=[0, 0, -1.0]), axis=[0, 1, 0], coordinate=th))
    return sys.equations()


@pytest.mark.parametrize("prescribed", [True, False])
def test_conical_pendulum_steady_rotation(prescribed):
    eom = conical_pendulum(prescribed)
    om = 5.0
    op = steady_rotation(eom, om, coordinate="psi", q0={"th": 0.8}, n_azimuth=4,
                         u0=[0.3, 0.0, 0.0] if prescribed else None)
    assert op.success, op.message
    th0 = op.q[eom.coordinates.index("th")]
    assert np.cos(th0) == pytest.approx(G / om**2, rel=1e-10)
    sweep = linearize_azimuths(eom, op, 3, coordinate="psi")
    np.testing.assert_allclose(sweep.batch.A, np.broadcast_to(sweep.batch.A[0], sweep.batch.A.shape), atol=1e-9)
    osc = [m for m in sweep.average().modes() if m.oscillatory]
    expected = om * np.sin(th0) if prescribed else om * np.sqrt(1 + 3 * np.cos(th0) ** 2)
    assert len(osc) == 1 and 2 * np.pi * osc[0].freq_hz == pytest.approx(expected, rel=1e-9)
    if prescribed:
        assert sweep.azimuths == pytest.approx(0.3 + 2 * np.pi * np.arange(3) / 3)


def test_steady_rotation_of_a_turbine(paper45):
    """GeAz spins at 12 rpm; the tower settles at its mean deflection (zero mean generalized force)."""
    om = 12 * np.pi / 30
    op = steady_rotation(paper45, om, n_azimuth=6)
    assert op.success, op.message
    assert op.qd[2] == om and op.held == ("GeAz",)
    assert np.max(np.abs(op.residual[:2])) < 1e-6
    sweep = linearize_azimuths(paper45, op, 6)
    assert sweep.blade_azimuths[0] == pytest.approx(op.q[2] + paper45.turbine.azimuth_blade1_up + np.pi / 2)
    avg = sweep.average()
    np.testing.assert_allclose(avg.A, sweep.batch.A.mean(axis=0))      # fixed-frame DOFs: plain average


def three_blade_rotor(k_flap=2.0e3, m=10.0, R=5.0, gravity=0.0, moment=0.0):
    sys = mb.System(gravity=[0.0, 0.0, -gravity])
    psi = sys.coordinates("GeAz")
    flaps = sys.coordinates("B1F1 B2F1 B3F1")
    hub = mb.RigidBody("hub", 50.0, inertia=(400.0, 200.0, 200.0))
    sys.add_joint(mb.Revolute(sys.ground, hub, axis=[1, 0, 0], coordinate=psi))
    for k, beta in enumerate(flaps):
        root = mb.RigidBody(f"root{k + 1}", 0.0)
        sys.add_joint(mb.Fixed(hub, root, rotation=mb.rotation("x", 2 * np.pi * k / 3)))
        sys.add_joint(mb.Revolute(root, mb.RigidBody(f"blade{k + 1}", m, com=[0, 0, R]), axis=[0, 1, 0],
                                  coordinate=beta))
        sys.add_spring(beta, k_flap)
        if moment:
            sys.add_generalized_force(beta, moment)
    return sys.equations(), k_flap / (m * R**2)


def test_steady_rotation_averages_gravity_over_azimuth():
    """Rotor axis horizontal, gravity in the rotor plane, a constant flap moment T on each blade:
    averaged over the azimuths the gravity moments cancel, so every blade flaps to the same β with
    k β + m R² Ω² sin β cos β = T; at a single azimuth (n_azimuth=1) they differ."""
    k, m, R, T, om = 2.0e3, 10.0, 5.0, 600.0, 3.0
    eom, _ = three_blade_rotor(k, m, R, gravity=G, moment=T)
    op = steady_rotation(eom, om, n_azimuth=12, q0={"GeAz": 0.3})
    assert op.success, op.message
    beta = op.q[1:]
    np.testing.assert_allclose(beta, beta[0], rtol=0, atol=1e-12)
    assert k * beta[0] + m * R**2 * om**2 * np.sin(beta[0]) * np.cos(beta[0]) == pytest.approx(T, rel=1e-10)
    single = steady_rotation(eom, om, n_azimuth=1, q0={"GeAz": 0.3})
    assert np.ptp(single.q[1:]) > 1e-3


def test_multi_blade_coordinates_average():
    pytest.importorskip("mbsym.wind.structure.mbc")
    eom, w0sq = three_blade_rotor()
    om = 3.0
    x = np.zeros(eom.n_x)
    x[eom.n_q] = om
    op = OperatingPoint(x[:4], x[4:], np.zeros(4), np.zeros(0), dict(eom.defaults), eom.coordinates, eom.inputs)
    from mbsym.wind.structure.mbc import BladeFrame

    assert linearize_azimuths(eom, op, 5, coordinate="GeAz").blade_indices == []    # the core knows no blades
    sweep = linearize_azimuths(eom, op, 5, coordinate="GeAz", frame=BladeFrame(eom.coordinates))
    assert sweep.blade_indices == [(1, 2, 3)]
    fixed = [sweep.frame.to_fixed_frame(sweep.batch[i], psi, om).A for i, psi in enumerate(sweep.blade_azimuths)]
    np.testing.assert_allclose(fixed, np.broadcast_to(fixed[0], (5, 8, 8)), atol=1e-9)
    wr = np.sqrt(w0sq + om**2)
    freqs = sorted(2 * np.pi * m.freq_hz for m in sweep.average().modes() if m.oscillatory)
    np.testing.assert_allclose(freqs, [wr - om, wr, wr + om], rtol=1e-9)
    # rotating frame, one azimuth: three blades at ω_r (no MBC)
    rot = sorted(2 * np.pi * m.freq_hz for m in sweep.batch[0].modes() if m.oscillatory)
    np.testing.assert_allclose(rot, [wr] * 3, rtol=1e-9)


def test_spinning_coordinate_must_be_named(chain_eom):
    with pytest.raises(mb.ModelDefinitionError, match="name the spinning coordinate"):
        steady_rotation(chain_eom, 1.0)
    with pytest.raises(mb.DimensionError, match="no coordinate 'rotor'"):
        steady_rotation(chain_eom, 1.0, coordinate="rotor")


def test_batch_of_azimuths_matches_linearize_batch(paper45):
    op = steady_rotation(paper45, 1.0, n_azimuth=1)
    sweep = linearize_azimuths(paper45, op, [0.0, 1.0])
    X = np.tile(op.x, (2, 1))
    X[:, 2] = [0.0, 1.0]
    np.testing.assert_array_equal(sweep.batch.A, linearize_batch(paper45, X, op.u, op.p).A)


class _CountingForcing:
    """Wraps the model's forcing Function and counts ``map`` (each builds a new CasADi Function)."""

    def __init__(self, f):
        self.f, self.maps = f, 0

    def map(self, *args):
        self.maps += 1
        return self.f.map(*args)

    def __getattr__(self, name):
        return getattr(self.f, name)


def test_forcing_map_built_once_per_solve():
    """static_equilibrium and steady_rotation build the sample map of F at most once each."""
    import dataclasses

    sys = mb.System(gravity=[0, 0, -G])
    z, psi = sys.coordinates("z psi")
    hub = mb.RigidBody("hub", 2.0)
    sys.add_joint(mb.Prismatic(sys.ground, hub, axis=[0, 0, 1], coordinate=z))
    sys.add_joint(mb.Revolute(hub, mb.RigidBody("rotor", 1.0, inertia=(1.0, 1.0, 1.0)), axis=[1, 0, 0],
                              coordinate=psi))
    sys.add_spring(z, 300.0)
    eom = sys.equations()
    counter = _CountingForcing(eom.functions.forcing)
    eom._functions = dataclasses.replace(eom.functions, forcing=counter)
    op = static_equilibrium(eom)
    assert op.success, op.message
    assert op.q[0] == pytest.approx(-3.0 * G / 300.0, rel=1e-12)          # -(m_hub + m_rotor) g / k
    assert counter.maps <= 1
    maps = counter.maps
    op = steady_rotation(eom, 2.0, coordinate="psi", n_azimuth=6)
    assert op.success, op.message
    assert counter.maps - maps <= 1


def test_held_coordinate_check_uses_tol():
    """A free x carrying F = 1e-8 N while z carries m g = 29 N: no equilibrium at tol = 1e-10
    (1e-8 > 1e-10 * 29 and > 1e-9), an equilibrium at tol = 1e-6."""
    sys = mb.System(gravity=[0, 0, -G])
    x, z = sys.coordinates("x z")
    F = sys.inputs("F")
    b = mb.RigidBody("b", 1.0)
    sys.add_joint(mb.Prismatic(sys.ground, b, axis=[1, 0, 0], coordinate=x))
    sys.add_joint(mb.Prismatic(b, mb.RigidBody("c", 3.0), axis=[0, 0, 1], coordinate=z))
    sys.add_spring(z, 50.0)
    sys.add_generalized_force(x, F)
    eom = sys.equations()
    strict = static_equilibrium(eom, [1e-8], tol=1e-10)
    assert not strict.success and "x (1e-08)" in strict.message
    loose = static_equilibrium(eom, [1e-8], tol=1e-6)
    assert loose.success, loose.message
    assert loose.q[1] == pytest.approx(-3.0 * G / 50.0, rel=1e-9)
