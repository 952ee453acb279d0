"""Physical invariants on random trees of 2-6 rigid bodies (hypothesis, profile "ci").

Each example is a tree drawn from ``(n, seed)``: random parents, revolute or prismatic joints
with random axes and offsets, random masses, centres of mass and SPD inertia tensors, a spring on
every coordinate, gravity. References are laws of mechanics, not another code:

- M symmetric positive definite (Kane's M = sum B^T Mb B with Mb SPD and B injective on a tree);
- kinetic energy T = 1/2 qd^T M qd (Pinocchio's check), 1e-12 relative;
- T + V conserved without dampers/forces (scipy DOP853, rtol = atol = 1e-10, 1.5 s),
  drift <= 1e-8 of (1 + max T);
- power balance d(T+V)/dt = P_nc with dampers, a point force, a torque and a generalized force
  (d/dt by CasADi AD of the energy Functions, qdd from the engine), 1e-10 of the term sizes;
- invariance to the order joints are added (1e-11), to the order coordinates are declared
  (M -> P M P^T), and to a rigid rotation of the whole description, either by rotating every
  vector and tensor or through the root joints' ``rotation=`` (1e-10).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import casadi as ca
import numpy as np
from hypothesis import given
from hypothesis import strategies as st
from scipy.integrate import solve_ivp

import mbsym as mb

from ._reference import random_rotation, random_spd

GRAVITY = np.array([0.0, 0.0, -9.81])
N_BODIES = st.integers(min_value=2, max_value=6)
SEEDS = st.integers(min_value=0, max_value=2**32 - 1)


@dataclass(frozen=True)
class TreeSpec:
    parents: tuple          # parent index per body, -1 for the ground
    kinds: tuple            # "R" (revolute) or "P" (prismatic)
    axes: np.ndarray
    offsets: np.ndarray
    masses: np.ndarray
    coms: np.ndarray
    inertias: np.ndarray
    stiffness: np.ndarray
    damping: np.ndarray
    perm: tuple             # a random permutation of the bodies (for order invariance)
    rotation: np.ndarray    # a random rotation (for rotation invariance)

    @property
    def n(self) -> int:
        return len(self.parents)


@lru_cache(maxsize=None)
def make_spec(n: int, seed: int) -> TreeSpec:
    rng = np.random.default_rng(seed)
    axes = rng.normal(size=(n, 3))
    axes /= np.linalg.norm(axes, axis=1, keepdims=True)
    return TreeSpec(
        parents=tuple(-1 if i == 0 else (i - 1 if rng.random() < 0.5 else int(rng.integers(-1, i)))
                      for i in range(n)),
        kinds=tuple("R" if rng.random() < 0.6 else "P" for _ in range(n)),
        axes=axes,
        offsets=rng.uniform(-0.6, 0.6, (n, 3)),
        masses=rng.uniform(0.5, 2.0, n),
        coms=rng.uniform(-0.4, 0.4, (n, 3)),
        inertias=np.array([random_spd(rng, scale=rng.uniform(0.05, 0.3)) for _ in range(n)]),
        stiffness=rng.uniform(5.0, 30.0, n),
        damping=rng.uniform(0.1, 1.0, n),
        perm=tuple(int(i) for i in rng.permutation(n)),
        rotation=random_rotation(rng),
    )


def build(spec: TreeSpec, *, joint_order=None, coord_order=None, rotate=False, root_rotation=False,
          nonconservative=False) -> mb.EquationsOfMotion:
    """Build the tree. ``rotate``: turn every vector/tensor of the description by spec.rotation;
    ``root_rotation``: instead give the root joints ``rotation=Q`` and rotate root offsets."""
    n, Q = spec.n, spec.rotation
    Qv = Q if rotate else np.eye(3)
    g = Q @ GRAVITY if (rotate or root_rotation) else GRAVITY
    sys = mb.System(gravity=g.tolist())
    names = [f"q{i}" for i in range(n)]
    declared = list(range(n)) if coord_order is None else list(coord_order)
    syms = dict(zip(declared, sys.coordinates([names[i] for i in declared])))
    masses = sys.parameters([f"m{i}" for i in range(n)], values=spec.masses.tolist())
    bodies = [mb.RigidBody(f"b{i}", mass=masses[i], com=(Qv @ spec.coms[i]).tolist(),
                           inertia=Qv @ spec.inertias[i] @ Qv.T) for i in range(n)]
    for i in (range(n) if joint_order is None else joint_order):
        parent = sys.ground if spec.parents[i] < 0 else bodies[spec.parents[i]]
        offset = spec.offsets[i]
        kw = {}
        if rotate or (root_rotation and spec.parents[i] < 0):
            offset = Q @ offset
        if root_rotation and spec.parents[i] < 0:
            kw["rotation"] = Q
        joint = mb.Revolute if spec.kinds[i] == "R" else mb.Prismatic
        sys.add_joint(joint(parent, bodies[i], axis=(Qv @ spec.axes[i]).tolist(), coordinate=syms[i],
                            offset=offset.tolist(), **kw))
    for i in range(n):
        sys.add_spring(syms[i], float(spec.stiffness[i]), rest=0.1 * i)
    if nonconservative:
        u0, u1 = sys.inputs("u0 u1")
        qd = [sys.speed(syms[i]) for i in range(n)]
        for i in range(n):
            sys.add_damper(syms[i], float(spec.damping[i]))
        last, first = bodies[n - 1], bodies[0]
        sys.add_force(last, [u0 + 0.3 * qd[0], -0.5 * ca.sin(syms[n - 1]), 0.2], point=[0.1, -0.2, 0.3],
                      frame=last)
        sys.add_force(first, [0.4, u1, -0.1 * qd[n - 1]], point=[0.0, 0.3, 0.0])
        sys.add_torque(first, [0.1 * u1, 0.2 * qd[0], -0.3], frame=None)
        sys.add_torque(last, [0.05, 0.0, u0], frame=first)
        sys.add_generalized_force(syms[n - 1], -0.3 * qd[n - 1] ** 3 + u1)
    return sys.equations()


@lru_cache(maxsize=None)
def eom_for(n: int, seed: int, variant: str = "plain") -> mb.EquationsOfMotion:
    spec = make_spec(n, seed)
    if variant == "plain":
        return build(spec)
    if variant == "nonconservative":
        return build(spec, nonconservative=True)
    if variant == "joint_order":
        return build(spec, joint_order=spec.perm)
    if variant == "coord_order":
        return build(spec, coord_order=spec.perm, joint_order=spec.perm[::-1])
    if variant == "rotated":
        return build(spec, rotate=True)
    if variant == "root_rotation":
        return build(spec, root_rotation=True)
    raise ValueError(variant)


def random_states(n: int, seed: int, count: int = 3):
    rng = np.random.default_rng(seed + 1)
    return [(rng.normal(scale=0.8, size=n), rng.normal(scale=1.5, size=n)) for _ in range(count)]


# --------------------------------------------------------------------------- tests
@given(n=N_BODIES, seed=SEEDS)
def test_mass_matrix_symmetric_positive_definite(n, seed):
    """M = M^T to 1e-14 relative; Cholesky succeeds and min eigenvalue > 1e-10 max eigenvalue."""
    eom = eom_for(n, seed)
    for q, _ in random_states(n, seed):
        M = eom.mass_matrix(q)
        np.testing.assert_allclose(M, M.T, rtol=0, atol=1e-14 * np.abs(M).max())
        np.linalg.cholesky(M)
        w = np.linalg.eigvalsh(M)
        assert w.min() > 1e-10 * w.max(), w


@given(n=N_BODIES, seed=SEEDS)
def test_kinetic_energy_is_quadratic_form_of_mass_matrix(n, seed):
    """T(q, qd) = 1/2 qd^T M(q) qd to 1e-12 relative (T is summed from body velocities, M from
    partial velocities: two routes through the engine)."""
    eom = eom_for(n, seed)
    for q, qd in random_states(n, seed):
        T_ref = 0.5 * qd @ eom.mass_matrix(q) @ qd
        np.testing.assert_allclose(eom.kinetic_energy(q, qd), T_ref, rtol=1e-12)


@given(n=N_BODIES, seed=SEEDS)
def test_energy_conserved_along_trajectory(n, seed):
    """Gravity and springs only: T + V constant along DOP853 (rtol = atol = 1e-10, 1.5 s) to
    1e-8 * (1 + max T); motion must be non-trivial (T varies by > 1e-3 of its max)."""
    eom = eom_for(n, seed)
    q0, qd0 = random_states(n, seed, 1)[0]
    sol = solve_ivp(lambda _t, y: eom.rhs(y), (0.0, 1.5), np.concatenate([q0, qd0]), method="DOP853",
                    rtol=1e-10, atol=1e-10, t_eval=np.linspace(0.0, 1.5, 16))
    assert sol.success, sol.message
    T = np.array([eom.kinetic_energy(y[:n], y[n:]) for y in sol.y.T])
    V = np.array([eom.potential_energy(y[:n]) for y in sol.y.T])
    E = T + V
    assert np.ptp(T) > 1e-3 * T.max()
    np.testing.assert_allclose(E, E[0], rtol=0, atol=1e-8 * (1.0 + T.max()))


@lru_cache(maxsize=None)
def _energy_rate(n: int, seed: int) -> ca.Function:
    """d(T+V)/dt = dE/dq qd + dE/dqd qdd, by CasADi AD of the engine's energy Functions."""
    eom = eom_for(n, seed, "nonconservative")
    f = eom.functions
    q, qd, qdd = (ca.SX.sym(s, n) for s in ("q", "qd", "qdd"))
    p = ca.SX.sym("p", n)
    u = ca.SX.zeros(eom.n_u)    # no prescribed coordinates: the energies do not depend on u
    E = f.kinetic_energy(q, qd, u, p) + f.potential_energy(q, u, p)
    rate = ca.jacobian(E, q) @ qd + ca.jacobian(E, qd) @ qdd
    return ca.Function("Edot", [q, qd, qdd, p], [rate])


@given(n=N_BODIES, seed=SEEDS)
def test_power_balance(n, seed):
    """d(T+V)/dt = power of dampers, forces (ground and body axes), torques and a generalized
    force, with inputs, at random states: 1e-10 relative to the largest of |qd.M qdd|, |qd.F|, |P|, 1.
    The power must be non-negligible (max |P| > 1e-2) so a missing load would show."""
    eom = eom_for(n, seed, "nonconservative")
    f, rate = eom.functions, _energy_rate(n, seed)
    p = eom.parameter_vector()
    rng = np.random.default_rng(seed + 2)
    powers = []
    for q, qd in random_states(n, seed):
        u = rng.normal(size=2)
        qdd = eom.accelerations(q, qd, u)
        P = float(f.power(q, qd, u, p))
        Edot = float(rate(q, qd, qdd, p))
        scale = max(abs(P), abs(qd @ eom.mass_matrix(q) @ qdd), abs(qd @ eom.forcing(q, qd, u)), 1.0)
        powers.append(abs(P))
        np.testing.assert_allclose(Edot, P, rtol=0, atol=1e-10 * scale)
    assert max(powers) > 1e-2


@given(n=N_BODIES, seed=SEEDS)
def test_invariant_to_joint_addition_order(n, seed):
    """Joints added in a random permutation (children possibly before parents): same M, F (1e-11)."""
    a, b = eom_for(n, seed), eom_for(n, seed, "joint_order")
    for q, qd in random_states(n, seed):
        Ma, Fa = a.mass_matrix(q), a.forcing(q, qd)
        np.testing.assert_allclose(b.mass_matrix(q), Ma, rtol=1e-11, atol=1e-11 * np.abs(Ma).max())
        np.testing.assert_allclose(b.forcing(q, qd), Fa, rtol=1e-11, atol=1e-11 * np.abs(Fa).max())


@given(n=N_BODIES, seed=SEEDS)
def test_invariant_to_coordinate_declaration_order(n, seed):
    """Coordinates declared in permuted order P (and joints added reversed): M' = M[P][:, P],
    F' = F[P] with states permuted accordingly (1e-11)."""
    a, b = eom_for(n, seed), eom_for(n, seed, "coord_order")
    perm = list(make_spec(n, seed).perm)
    assert list(b.coordinates) == [f"q{i}" for i in perm]
    for q, qd in random_states(n, seed):
        Ma, Fa = a.mass_matrix(q), a.forcing(q, qd)
        Mb, Fb = b.mass_matrix(q[perm]), b.forcing(q[perm], qd[perm])
        np.testing.assert_allclose(Mb, Ma[np.ix_(perm, perm)], rtol=1e-11, atol=1e-11 * np.abs(Ma).max())
        np.testing.assert_allclose(Fb, Fa[perm], rtol=1e-11, atol=1e-11 * np.abs(Fa).max())


@given(n=N_BODIES, seed=SEEDS)
def test_invariant_to_rigid_rotation_of_description(n, seed):
    """Gravity, axes, offsets, coms rotated by Q and inertias by Q I Q^T: same M, F (1e-10).
    (Body k's orientation becomes Q R_k Q^T and every point Q r: a rigid rotation of the motion.)"""
    a, b = eom_for(n, seed), eom_for(n, seed, "rotated")
    for q, qd in random_states(n, seed):
        Ma, Fa = a.mass_matrix(q), a.forcing(q, qd)
        np.testing.assert_allclose(b.mass_matrix(q), Ma, rtol=1e-10, atol=1e-10 * np.abs(Ma).max())
        np.testing.assert_allclose(b.forcing(q, qd), Fa, rtol=1e-10, atol=1e-10 * np.abs(Fa).max())
        np.testing.assert_allclose(b.potential_energy(q) - b.potential_energy(np.zeros(n)),
                                   a.potential_energy(q) - a.potential_energy(np.zeros(n)), rtol=1e-10, atol=1e-10)


@given(n=N_BODIES, seed=SEEDS)
def test_invariant_to_root_joint_frame_rotation(n, seed):
    """Root joints given ``rotation=Q`` (offsets Q o) with gravity Q g: the whole tree is turned
    rigidly, so M and F are unchanged (1e-10)."""
    a, b = eom_for(n, seed), eom_for(n, seed, "root_rotation")
    for q, qd in random_states(n, seed):
        Ma, Fa = a.mass_matrix(q), a.forcing(q, qd)
        np.testing.assert_allclose(b.mass_matrix(q), Ma, rtol=1e-10, atol=1e-10 * np.abs(Ma).max())
        np.testing.assert_allclose(b.forcing(q, qd), Fa, rtol=1e-10, atol=1e-10 * np.abs(Fa).max())
