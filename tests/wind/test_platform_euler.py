"""Combined platform rotations: ElastoDyn v4+/v5's yaw–pitch–roll Euler sequence (issue 10).

References
----------
- Kinematics (docs/elastodyn_notes.md §4, issue 10): R = Rz(Y) Ry(P) Rx(R), ω = Ẏ z + Ṗ y′ + Ṙ x″.
  Checked against central differences of R (ω = vee(Ṙ Rᵀ), 1e-8) and the closed form (a pitch P
  turns the platform by P itself, 1e-15).
- t = 0 accelerations against an independent numpy Newton–Euler replica of the ElastoDyn chain
  (tests/wind/_elastodyn_reference.py: Euler-sequence platform, tower point masses at
  z + Φq − ½qᵀAxq, SmllRotTrans tower top turning with the slope rates, rigid RNA and blades),
  at roll −2°, pitch 1.5°, yaw −4° with tower FA + SS deflected, a spinning generator and random
  rates of every DOF: 1e-9 relative (observed ~3e-12).
- Energy: a rigid platform on a free yaw–pitch–roll joint is a conservative system; the template
  (PtfmRDOF, PtfmPDOF, PtfmYDOF, GenDOF, gravity) keeps T + V to 1e-8 of its kinetic energy over
  20 s (cvodes rtol 1e-11). The same chain with an exact lumped tower (FA + SS) whose top turns
  with its orientation (end_angular_velocity="exact") also conserves energy (1e-8).
  (ElastoDyn's own tower top, whose angular velocity is the slope rates and not the rate of its
  SmllRotTrans orientation, is not conservative at order θ²θ̇; it is checked against the replica.)
- Linearization at the static equilibrium with yaw −4° and the rotor spinning (a relative
  equilibrium of a conservative gyroscopic system): yaw about the vertical is a symmetry, so A's
  yaw column is zero (1e-12) and there are exactly four rigid eigenvalues (yaw and azimuth, |λ| <
  1e-6 rad/s); the platform roll/pitch modes are undamped (|ζ| < 1e-5) and nothing grows
  (Re λ < 1e-9). The pre-v4 small-rotation matrix with fixed-axis rates gave a yaw stiffness and
  platform modes with ζ = ±0.017 there.
"""

from __future__ import annotations

import dataclasses
import sys
from pathlib import Path

import casadi as ca
import numpy as np
import pytest
from scipy.optimize import root

import mbsym as mb
from mbsym.wind import nrel5mw
from mbsym.wind.structure.elastodyn_bodies import tower_shape_integrals
from mbsym.wind.structure.platform import PlatformJoint, platform_angular_velocity, platform_rotation
from mbsym.wind.structure.turbine import TurbineModel

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _elastodyn_reference import reference_accelerations  # noqa: E402

DOFS = ["PtfmRDOF", "PtfmPDOF", "PtfmYDOF", "TwFADOF1", "TwSSDOF1", "GenDOF"]


def _floating(**ic):
    """NREL 5 MW on the paper46 spar values (docs/elastodyn_notes.md §8.3), initial conditions ``ic``."""
    t = dataclasses.replace(nrel5mw(), platform_mass=7.5e6, platform_roll_inertia=4.2e9,
                            platform_pitch_inertia=4.2e9, platform_yaw_inertia=1.6e8,
                            platform_cm=(0.0, 0.0, -90.0), platform_reference=(0.0, 0.0, 20.0),
                            tower_base_height=20.0)
    return dataclasses.replace(t, initial_conditions=dataclasses.replace(t.initial_conditions, **ic))


OFFSETS = dict(platform_roll=np.deg2rad(-2.0), platform_pitch=np.deg2rad(1.5), platform_yaw=np.deg2rad(-4.0),
               tower_top_fa_displacement=0.3, tower_top_ss_displacement=0.4, rotor_speed=8 * np.pi / 30)


def _inputs(model):
    d = model.input_defaults()
    return np.array([d[n](0.0) if callable(d[n]) else d[n] for n in model.eom.inputs], dtype=float)


def _rhs(model, x):
    eom = model.eom
    return np.array(eom.functions.rhs(x, _inputs(model), eom.parameter_vector({}))).ravel()


def test_euler_sequence_and_rates():
    R_, P_, Y_ = ca.SX.sym("R"), ca.SX.sym("P"), ca.SX.sym("Y")
    ang = ca.vertcat(R_, P_, Y_)
    rates = ca.SX.sym("rates", 3)
    Rm = platform_rotation(R_, P_, Y_)
    w = platform_angular_velocity([R_, P_, Y_], [rates[0], rates[1], rates[2]])
    f = ca.Function("f", [ang, rates], [Rm, w])
    rng = np.random.default_rng(3)
    for _ in range(5):
        a, ad = rng.uniform(-0.5, 0.5, 3), rng.normal(size=3)
        h = 1e-6
        Rp, Rm_ = (np.array(f(a + s * h * ad, ad)[0]) for s in (1, -1))
        R0, w0 = (np.array(v) for v in f(a, ad))
        W = (Rp - Rm_) / (2 * h) @ R0.T
        np.testing.assert_allclose([W[2, 1], W[0, 2], W[1, 0]], w0.ravel(), atol=1e-8)
        np.testing.assert_allclose(R0.T @ R0, np.eye(3), atol=1e-14)
    R0 = np.array(f([0.0, 0.1, 0.0], [0, 0, 0])[0])
    np.testing.assert_allclose(R0[:, 0], [np.cos(0.1), 0.0, -np.sin(0.1)], atol=1e-15)   # pitched by P, not atan P


def test_initial_accelerations_match_newton_euler_replica():
    t = _floating(**OFFSETS)
    model = TurbineModel(t, dofs=DOFS)
    eom = model.eom
    n = eom.n_q
    x = model.initial_state()
    assert eom.coordinates == ("R", "P", "Y", "TFA1", "TSS1", "GeAz")
    for rates in (np.zeros(n), np.random.default_rng(7).normal(scale=[0.02, 0.02, 0.02, 0.3, 0.3, 0.1])):
        x[n:] = rates + np.r_[np.zeros(n - 1), OFFSETS["rotor_speed"]]
        qdd = _rhs(model, x)[n:]
        ref = reference_accelerations(t, eom.coordinates, x[:n], x[n:])
        np.testing.assert_allclose(qdd, ref, rtol=0, atol=1e-9 * np.abs(ref).max())


def _energy(eom, result, u=()):
    """Kinetic and potential energy [J] along a simulation."""
    f, p = eom.functions, eom.parameter_vector({})

    def call(fn, q, qd):
        values = dict(q=q, qd=qd, u=np.asarray(u, dtype=float), p=p)
        return float(fn(*[values[fn.name_in(i)] for i in range(fn.n_in())]))

    T = np.array([call(f.kinetic_energy, q, qd) for q, qd in zip(result.q, result.qd)])
    V = np.array([call(f.potential_energy, q, qd) for q, qd in zip(result.q, result.qd)])
    return T, V


def test_template_platform_conserves_energy():
    t = _floating(**OFFSETS)
    model = TurbineModel(t, dofs=["PtfmRDOF", "PtfmPDOF", "PtfmYDOF", "GenDOF"])
    x0 = model.initial_state()
    x0[model.eom.n_q:model.eom.n_q + 3] = [0.01, -0.02, 0.015]           # platform rates too
    r = mb.simulate(model, 20.0, x0=x0, method="cvodes", rtol=1e-11, atol=1e-12, dt=0.1)
    T, V = _energy(model.eom, r, _inputs(model))
    assert np.ptp(T) > 1e4                      # the platform swings: energy moves between T and V
    assert np.ptp(T + V) <= 1e-8 * T.max(), (np.ptp(T + V), T.max())


def test_platform_with_exact_lumped_tower_conserves_energy():
    """PlatformJoint + ElastoDyn's lumped tower (FA + SS, kinematics='exact') + a spinning RNA."""
    t = nrel5mw()
    sys_ = mb.System(gravity=[0, 0, -9.80665])
    r_, p_, y_, fa, ss, psi = sys_.coordinates("r p y fa ss psi")
    plat = mb.RigidBody("platform", mass=7.5e6, com=[0, 0, -110.0], inertia=[4.2e9, 4.2e9, 1.6e8])
    sys_.add_joint(PlatformJoint(sys_.ground, plat, values=[0.0, 0.0, 0.0, r_, p_, y_], offset=[0, 0, 20.0]))
    sid = tower_shape_integrals(t, dofs=["TwFADOF1", "TwSSDOF1"])
    tower = mb.FlexibleBody("tower", sid, [fa, ss], kinematics="exact", end_rotation_order="elastodyn",
                            end_angular_velocity="exact", damping=np.zeros((2, 2)))
    sys_.add_joint(mb.Fixed(plat, tower))
    top = sid.end_position.tolist()
    nacelle = mb.RigidBody("nacelle", mass=2.4e5, com=[1.9, 0.1, 1.75], inertia=[1e6, 2e6, 2.6e6])
    sys_.add_joint(mb.Fixed(tower, nacelle, offset=top))
    rotor = mb.RigidBody("rotor", mass=1.1e5, com=[0.0, 0.0, 0.0], inertia=[3.9e7, 2e7, 2e7])
    sys_.add_joint(mb.Revolute(nacelle, rotor, axis=[1, 0, 0], coordinate=psi, offset=[-5.0, 0.0, 2.4]))
    eom = sys_.equations()
    x0 = np.array([-0.035, 0.026, -0.07, 0.3, 0.4, 0.0, 0.01, -0.01, 0.02, 0.1, -0.2, 0.9])
    r = mb.simulate(eom, 20.0, x0=x0, method="cvodes", rtol=1e-11, atol=1e-12, dt=0.1)
    T, V = _energy(eom, r)
    assert np.ptp(V) > 1e5
    assert np.ptp(T + V) <= 1e-8 * T.max(), (np.ptp(T + V), T.max())


@pytest.fixture(scope="module")
def equilibrium():
    t = _floating(**OFFSETS)
    model = TurbineModel(t, dofs=DOFS)
    eom = model.eom
    n = eom.n_q
    x = model.initial_state()
    u, p = _inputs(model), dict(zip(eom.parameters, eom.parameter_vector({})))
    free = [eom.coordinates.index(c) for c in ("R", "P", "TFA1", "TSS1")]

    def residual(z):
        q = x[:n].copy()
        q[free] = z
        return np.array(eom.accelerations(q, x[n:], u, p)).ravel()[free]

    sol = root(residual, x[:n][free], tol=1e-14)
    assert sol.success
    x[:n][free] = sol.x
    return model, x, u, p


def test_no_spurious_rigid_mode_at_equilibrium(equilibrium):
    model, x, u, p = equilibrium
    eom = model.eom
    n = eom.n_q
    assert np.abs(np.array(eom.accelerations(x[:n], x[n:], u, p))).max() < 1e-10
    assert x[eom.coordinates.index("Y")] == pytest.approx(np.deg2rad(-4.0))
    lin = mb.linearize(model, x[:n], x[n:], u, p, method="exact")
    yaw = eom.coordinates.index("Y")
    assert np.abs(lin.A[:, yaw]).max() <= 1e-12 * np.abs(lin.A).max()
    lam = np.linalg.eigvals(lin.A)
    rigid = lam[np.abs(lam) < 1e-6]
    assert rigid.size == 4, np.sort(np.abs(lam))[:6]
    assert lam.real.max() < 1e-9
    platform = lam[(np.abs(lam) > 1e-6) & (np.abs(lam) < 2 * np.pi * 0.1)]
    assert platform.size == 4                   # roll and pitch, about 0.045 Hz
    assert np.all(np.abs(platform.real / np.abs(platform)) < 1e-5)
