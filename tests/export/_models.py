"""Models shared by the export tests, and the comparison rule.

References: the CasADi Functions of each model (``eom.functions``, evaluated by CasADi's
virtual machine) and, for the rhs Jacobians, CasADi's own automatic differentiation of
``eom.functions.rhs`` (independent of the residual form the exports use).
"""

from __future__ import annotations

import casadi as ca
import numpy as np

import mbsym as mb

#: Agreement required between an export and the CasADi Functions, relative to the largest entry (and to 1).
RTOL = 1e-12


def close(got, ref, what: str = "") -> None:
    got, ref = np.asarray(got, dtype=float), np.asarray(ref, dtype=float)
    assert got.shape == ref.shape, (what, got.shape, ref.shape)
    scale = max(1.0, float(np.max(np.abs(ref), initial=0.0)))
    err = float(np.max(np.abs(got - ref), initial=0.0))
    assert err <= RTOL * scale, f"{what}: max error {err:.3g} > {RTOL:g} x {scale:.3g}"


def pendulum():
    sys = mb.System(gravity=[0.0, 0.0, -9.81])
    th = sys.coordinates("theta")
    m, l = sys.parameters("m l", values={"m": 1.5, "l": 0.7})
    u = sys.inputs("T")
    b = mb.RigidBody("b", mass=m, com=[0, 0, -l])
    sys.add_joint(mb.Revolute(sys.ground, b, axis=[0, 1, 0], coordinate=th))
    sys.add_generalized_force(th, u)
    sys.add_damper(th, 0.3)
    return sys.equations(name="pendulum")


def double_pendulum():
    from mbsym.demo import double_pendulum as build

    return build().equations(name="double_pendulum")


def flexible_beam():
    """A cantilever of two FEM modes on a revolute hub (rotating beam): flexible + rigid coordinates."""
    from mbsym.beam import cantilever_modes, shape_integrals

    z = np.linspace(0.0, 10.0, 41)
    modes = cantilever_modes(z, 20.0, 5e5, n_modes=2, n_elements=20, direction="x")
    sid = shape_integrals(z, 20.0, 5e5, 5e5, modes.shapes(), quadrature="simpson")
    sys = mb.System(gravity=[0.0, 0.0, -9.81])
    psi, e1, e2 = sys.coordinates("psi e1 e2")
    beam = mb.FlexibleBody("beam", sid, [e1, e2])
    sys.add_joint(mb.Revolute(sys.ground, beam, axis=[0, 1, 0], coordinate=psi))
    return sys.equations(name="beam")


def chain(n: int = 9):
    """n links on alternating axes: beyond 8 coordinates rhs is an MX Function (numeric solve)."""
    sys = mb.System(gravity=[0, 0, -9.81])
    qs = sys.coordinates(" ".join(f"q{i}" for i in range(n)))
    parent = sys.ground
    for i in range(n):
        b = mb.RigidBody(f"b{i}", mass=1.0 + 0.1 * i, com=[0, 0, -0.5], inertia=[0.1, 0.1, 0.1])
        sys.add_joint(mb.Revolute(parent, b, axis=[0, 1, 0] if i % 2 == 0 else [1, 0, 0], coordinate=qs[i],
                                  offset=[0, 0, -1.0] if i else [0, 0, 0]))
        parent = b
    return sys.equations(name="chain")


def turbine(prescribed: bool = False):
    """NREL 5 MW (built-in data): tower FA + SS + generator, or tower FA + flap with a prescribed azimuth."""
    from mbsym.wind import TurbineModel, nrel5mw

    dofs = ["TwFADOF1", "FlapDOF1"] if prescribed else ["TwFADOF1", "TwSSDOF1", "GenDOF"]
    return TurbineModel(nrel5mw(), dofs=dofs, prescribed_azimuth=prescribed).eom


def four_bar():
    """A closed loop (crank 1, coupler 2, rocker 2, ground 2.5 m): 1 independent coordinate, a torque input."""
    sys = mb.System(gravity=[0.0, -9.81, 0.0])
    qs = sys.coordinates("q1 q2 q3")
    tau = sys.inputs("tau")
    parent, offset = sys.ground, [0.0, 0.0, 0.0]
    for i, (q, l) in enumerate(zip(qs, (1.0, 2.0, 2.0))):
        body = mb.RigidBody(f"link{i}", 1.0, com=[l / 2, 0, 0], inertia=[0.01, 0.1, 0.1])
        sys.add_joint(mb.Revolute(parent, body, axis=[0, 0, 1], coordinate=q, offset=offset))
        parent, offset = body, [l, 0.0, 0.0]
    sys.add_torque(sys.body("link0"), [0, 0, tau])
    sys.add_closure(parent, [2.0, 0, 0], sys.ground, [2.5, 0, 0], directions="xy")
    return sys.equations(name="four_bar", independent=["q1"], guess={"q2": 1.2, "q3": -2.4})


def random_point(eom, seed: int = 0):
    """Random q, qd, qdd, u and p (parameters: defaults scaled by 0.8..1.2, else 0.5..2)."""
    rng = np.random.default_rng(seed)
    n = eom.n_q
    p = np.array([eom.defaults.get(k, 1.0) for k in eom.parameters]) * rng.uniform(0.8, 1.2, eom.n_p)
    if not eom.defaults:
        p = rng.uniform(0.5, 2.0, eom.n_p)
    return {"q": rng.normal(scale=0.5, size=n), "qd": rng.normal(size=n), "qdd": rng.normal(size=n),
            "u": rng.normal(size=eom.n_u), "p": p}


def references(eom, pt) -> dict[str, np.ndarray]:
    """Every exported function evaluated by CasADi (the Jacobians by AD of eom.functions.rhs)."""
    f = eom.functions
    q, qd, qdd, u, p = (pt[k] for k in ("q", "qd", "qdd", "u", "p"))
    x = np.concatenate([q, qd])
    M = f.mass_matrix(q, u, p) if eom.prescribed else f.mass_matrix(q, p)
    X, U = ca.MX.sym("x", eom.n_x), ca.MX.sym("u", eom.n_u)
    xd = f.rhs(X, U, p)
    jac = ca.Function("rhs_jacobians", [X, U], [ca.jacobian(xd, X), ca.jacobian(xd, U)])
    A, B = jac(x, u)
    out = {"mass_matrix": M, "forcing": f.forcing(q, qd, u, p), "residual": f.residual(q, qd, qdd, u, p),
           "rhs": f.rhs(x, u, p), "rhs_jacobian_x": A, "rhs_jacobian_u": B,
           "kinetic_energy": f.kinetic_energy(q, qd, u, p), "potential_energy": f.potential_energy(q, u, p),
           "power": f.power(q, qd, u, p)}
    return {k: np.array(ca.densify(ca.DM(v))) for k, v in out.items()}


def arguments(eom, pt, name: str) -> list:
    x = np.concatenate([pt["q"], pt["qd"]])
    table = {"q": pt["q"], "qd": pt["qd"], "qdd": pt["qdd"], "u": pt["u"], "p": pt["p"], "x": x}
    if name.startswith("rhs_jacobian"):
        return [x, pt["u"], pt["p"]]
    return [table[a] for a in getattr(eom.functions, name).name_in()]
