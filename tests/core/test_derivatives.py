"""Jacobians of the engine's CasADi Functions against central finite differences.

Reference: central differences (f(x + h e_i) - f(x - h e_i)) / 2h of the *numeric* Functions with
h = 1e-6; truncation error O(h^2) ~ 1e-12 and round-off ~ eps |f| / h ~ 1e-10 |f|, so the
tolerance is 1e-6 relative to max(1, max |J|) (Pinocchio uses tolerance ~ sqrt(step)).
Exact identities are checked exactly (to 1e-12): de/dqdd = -M, and d(rhs)/dqd has the identity
in its upper block.

Models: (a) a 5-DOF tree mixing prismatic and revolute joints with non-trivial axes, springs,
dampers, velocity- and input-dependent forces and torques; (b) a 6-DOF Free body with com
offset under gravity; (c) a 9-link chain whose rhs is the MX numeric-solve path (> 8 DOF).
"""

from __future__ import annotations

import casadi as ca
import numpy as np
import pytest

import mbsym as mb

from ._reference import random_spd

H = 1e-6
RTOL = 1e-6


def tree_model() -> mb.EquationsOfMotion:
    rng = np.random.default_rng(11)
    sys = mb.System(gravity=[0.1, -0.3, -9.81])
    x, a, b, s, c = sys.coordinates("x a b s c")
    m0, m1, k, L = sys.parameters("m0 m1 k L", values=[2.0, 1.2, 15.0, 0.7])
    f, tau = sys.inputs("f tau")
    cart = mb.RigidBody("cart", mass=m0, inertia=random_spd(rng))
    arm = mb.RigidBody("arm", mass=m1, com=[0.1, 0.0, -L], inertia=random_spd(rng, 0.3))
    fore = mb.RigidBody("fore", mass=0.8, com=[0.0, 0.2, -0.3], inertia=random_spd(rng, 0.2))
    slider = mb.RigidBody("slider", mass=0.5, com=[0.05, 0.0, 0.0], inertia=random_spd(rng, 0.1))
    side = mb.RigidBody("side", mass=0.6, com=[0.0, -0.2, 0.1], inertia=random_spd(rng, 0.1))
    sys.add_joint(mb.Prismatic(sys.ground, cart, axis=[1, 0.2, 0], coordinate=x))
    sys.add_joint(mb.Revolute(cart, arm, axis=[0.3, 1, 0.1], coordinate=a, offset=[0, 0, 0.2]))
    sys.add_joint(mb.Revolute(arm, fore, axis=[1, 0, 0.5], coordinate=b, offset=[0, 0, -L]))
    sys.add_joint(mb.Prismatic(arm, slider, axis=[0, 0, 1], coordinate=s, offset=[0.1, 0, -0.2]))
    sys.add_joint(mb.Revolute(cart, side, axis=[0, 0, 1], coordinate=c, offset=[0.3, 0.1, 0]))
    sys.add_spring(x, k, rest=0.2)
    sys.add_spring(s, 2 * k)
    sys.add_damper(a, 0.3)
    sys.add_damper(c, 0.1)
    xd, bd = sys.speed(x), sys.speed(b)
    sys.add_force(fore, [f, 0.2 * bd * ca.sin(a), -0.1 * xd**2], point=[0, 0.1, -0.3], frame=arm)
    sys.add_torque(side, [0, 0, tau - 0.2 * ca.cos(c)])
    sys.add_generalized_force(b, -0.05 * bd**3)
    return sys.equations()


def free_model() -> mb.EquationsOfMotion:
    sys = mb.System(gravity=[0.0, 0.0, -9.81])
    coords = sys.coordinates("x y z a b c")
    m = sys.parameters("m", values=[1.4])
    body = mb.RigidBody("body", mass=m, com=[0.2, -0.1, 0.3],
                        inertia=[[1.0, 0.1, 0.0], [0.1, 2.0, -0.2], [0.0, -0.2, 1.5]])
    sys.add_joint(mb.Free(sys.ground, body, coordinates=coords, sequence="zyx"))
    return sys.equations()


def chain_model(n: int = 9) -> mb.EquationsOfMotion:
    rng = np.random.default_rng(12)
    sys = mb.System(gravity=[0.0, 0.0, -9.81])
    qs = sys.coordinates([f"q{i}" for i in range(n)])
    parent = sys.ground
    for i in range(n):
        body = mb.RigidBody(f"l{i}", mass=1.0 + 0.1 * i, com=[0, 0, -0.3], inertia=random_spd(rng, 0.05))
        sys.add_joint(mb.Revolute(parent, body, axis=rng.normal(size=3).tolist(), coordinate=qs[i],
                                  offset=[0, 0, -0.4 if i else 0.0]))
        parent = body
    for i in range(n):
        sys.add_damper(qs[i], 0.05)
    return sys.equations()


MODELS = {"tree": tree_model, "free": free_model, "chain9": chain_model}


@pytest.fixture(scope="module", params=list(MODELS))
def eom(request):
    return MODELS[request.param]()


def _point(eom, seed=0):
    rng = np.random.default_rng(seed)
    n = eom.n_q
    q = rng.uniform(-1.0, 1.0, n)
    return dict(q=q, qd=rng.normal(size=n), qdd=rng.normal(size=n), u=rng.normal(size=eom.n_u),
                p=eom.parameter_vector())


def central_difference(fun, args: list, k: int) -> np.ndarray:
    """d vec(fun(*args)) / d args[k] by central differences with step H."""
    x0 = np.asarray(args[k], dtype=float)
    cols = []
    for i in range(x0.size):
        plus, minus = list(args), list(args)
        xp, xm = x0.copy(), x0.copy()
        xp[i] += H
        xm[i] -= H
        plus[k], minus[k] = xp, xm
        fp = np.array(fun(*plus)).reshape(-1, order="F")
        fm = np.array(fun(*minus)).reshape(-1, order="F")
        cols.append((fp - fm) / (2 * H))
    return np.column_stack(cols)


def ad_jacobian(fun: ca.Function, args: list, k: int) -> np.ndarray:
    """CasADi's Jacobian of vec(output) w.r.t. input k, via symbolic call + ca.jacobian."""
    syms = [ca.MX.sym(f"a{i}", ca.Sparsity.dense(fun.size_in(i))) for i in range(fun.n_in())]
    out = ca.vec(fun(*syms))
    J = ca.Function("J", syms, [ca.jacobian(out, syms[k])])
    return np.array(J(*args))


def assert_jacobian(fun, args, k):
    J = ad_jacobian(fun, args, k)
    J_fd = central_difference(fun, args, k)
    assert J.shape == J_fd.shape
    np.testing.assert_allclose(J, J_fd, rtol=0, atol=RTOL * max(1.0, np.abs(J_fd).max()))
    return J


def test_dF_dq_and_dF_dqd(eom):
    """dF/dq and dF/dqd (forcing), both non-trivial, vs central differences (1e-6 rel.)."""
    pt = _point(eom)
    args = [pt["q"], pt["qd"], pt["u"], pt["p"]]
    for k in (0, 1):
        J = assert_jacobian(eom.functions.forcing, args, k)
        assert np.abs(J).max() > 1e-3


def test_dM_dq(eom):
    """d vec(M)/dq vs central differences (1e-6 rel.)."""
    pt = _point(eom, 1)
    J = assert_jacobian(eom.functions.mass_matrix, [pt["q"], pt["p"]], 0)
    assert np.abs(J).max() > 1e-3


def test_residual_jacobians(eom):
    """de/dq, de/dqd, de/du, de/dp vs central differences; de/dqdd = -M exactly (1e-12)."""
    pt = _point(eom, 2)
    args = [pt["q"], pt["qd"], pt["qdd"], pt["u"], pt["p"]]
    for k in (0, 1, 3, 4):
        if np.size(args[k]):
            assert_jacobian(eom.functions.residual, args, k)
    J = ad_jacobian(eom.functions.residual, args, 2)
    M = np.array(eom.functions.mass_matrix(pt["q"], pt["p"]))
    np.testing.assert_allclose(J, -M, rtol=0, atol=1e-12 * np.abs(M).max())


def test_rhs_jacobians(eom):
    """d(rhs)/dx, d(rhs)/du, d(rhs)/dp vs central differences; upper block [0, I] exactly.
    For the 9-DOF chain the rhs is the MX numeric-solve Function (derivative of a linear solve)."""
    pt = _point(eom, 3)
    n = eom.n_q
    x = np.concatenate([pt["q"], pt["qd"]])
    args = [x, pt["u"], pt["p"]]
    J = assert_jacobian(eom.functions.rhs, args, 0)
    np.testing.assert_array_equal(J[:n, :n], 0.0)
    np.testing.assert_array_equal(J[:n, n:], np.eye(n))
    for k in (1, 2):
        if np.size(args[k]):
            assert_jacobian(eom.functions.rhs, args, k)


def test_energy_gradients(eom):
    """dT/dq, dT/dqd (= M qd, exactly to 1e-12) and dV/dq vs central differences."""
    pt = _point(eom, 4)
    f = eom.functions
    assert_jacobian(f.kinetic_energy, [pt["q"], pt["qd"], pt["u"], pt["p"]], 0)
    J = assert_jacobian(f.kinetic_energy, [pt["q"], pt["qd"], pt["u"], pt["p"]], 1)
    Mqd = np.array(f.mass_matrix(pt["q"], pt["p"])) @ pt["qd"]
    np.testing.assert_allclose(J.reshape(-1), Mqd, rtol=1e-12, atol=1e-12)
    assert_jacobian(f.potential_energy, [pt["q"], pt["u"], pt["p"]], 0)


def test_function_jacobian_method_agrees(eom):
    """``Function.jacobian()`` (CasADi's own Jacobian Function) gives the same dF/dq as above."""
    pt = _point(eom, 5)
    f = eom.functions.forcing
    jf = f.jacobian()
    outs = jf(q=pt["q"], qd=pt["qd"], u=pt["u"], p=pt["p"], out_F=np.zeros(eom.n_q))
    J = np.array(outs["jac_F_q"])
    np.testing.assert_allclose(J, central_difference(f, [pt["q"], pt["qd"], pt["u"], pt["p"]], 0),
                               rtol=0, atol=RTOL * max(1.0, np.abs(J).max()))
