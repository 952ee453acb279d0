"""Non-holonomic (velocity) constraints: Kane's method with dependent speeds, as first-order dynamics.

With the tree's equations ``M(q) q̈ = F(q, q̇)`` and velocity constraints ``A(q) q̇ + b(q) = 0`` (m rows,
:meth:`mbsym.System.add_velocity_constraint`), the speeds of the coordinates named independent, ``s``,
determine the others:

``q̇ = C s + e``,  rows S of C the identity, rows D ``-A_D⁻¹ A_S``;  ``e_D = -A_D⁻¹ b``,

and ``q̈ = C ṡ + c₀`` with ``c₀_D = -A_D⁻¹ (Ȧ q̇ + ḃ)``. Kane's equations of the independent speeds are

``M_r ṡ = F_r``,  ``M_r = Cᵀ M C``,  ``F_r = Cᵀ (F - M c₀)``,

and the constraint forces ``λ = A_D⁻ᵀ (M q̈ - F)_D``. The coordinates are not reduced (the
constraint does not integrate), so the state ``x = [q; s]`` has more coordinates than speeds: the
result is a :class:`~mbsym.dynamics.Dynamics` (``ẋ = [C s + e; M_r⁻¹ F_r]``, outputs the dependent
speeds and the multipliers), which simulation (first-order methods), control, estimation,
identification and sweeps take; the uses that need second-order equations ``M q̈ = F`` in
``x = [q; q̇]`` (``mb.linearize``, Newmark, generalized-α, IDAS's residual form) refuse it with a typed
error. Holonomic closures in the same system are not combined with velocity constraints
(``UnsupportedFeatureError``).
"""

from __future__ import annotations

from typing import Sequence

import casadi as ca

from ..dynamics import Dynamics
from ..exceptions import ConstraintError, UnsupportedFeatureError
from ..kane import derive

__all__ = ["nonholonomic_dynamics"]


def nonholonomic_dynamics(system, *, name: str = "mbsym", independent_speeds: Sequence[str] | None = None,
                          independent=None, guess=None) -> Dynamics:
    """First-order dynamics of a system with velocity constraints (module docstring).

    Parameters
    ----------
    system : mbsym.System
    name : str
    independent_speeds : sequence of str
        Coordinates whose speeds are independent: one per coordinate minus constraint row.

    Raises
    ------
    ConstraintError
        Missing or wrong ``independent_speeds``; constraint rows that do not determine the other
        speeds (a singular ``A_D``, checked at q = 0 and at a generic configuration).
    UnsupportedFeatureError
        Holonomic closures, prescribed or locked coordinates, ``independent``/``guess`` with
        velocity constraints.
    """
    from ..constraints import VelocityConstraint

    vel = [c for c in system.constraints if isinstance(c, VelocityConstraint)]
    st = system.symbols
    if len(vel) != len(system.constraints) or independent is not None or guess is not None or st.prescribed() \
            or st.locked():
        raise UnsupportedFeatureError(
            "velocity constraints are modelled on a tree without holonomic closures, prescribed or locked "
            "coordinates (and take independent_speeds=, not independent=/guess=); close loops with "
            "add_closure in a system without velocity constraints.")
    d = derive(system)
    coords = list(d.names["coordinate"])
    rows = ca.vertcat(*[c.expression for c in vel])
    row_names = [n for c in vel for n in c.row_names]
    m, n = rows.numel(), len(coords)
    if not vel:
        raise ConstraintError("independent_speeds= is for systems with velocity constraints "
                              "(sys.add_velocity_constraint); this system has none.")
    if independent_speeds is None or isinstance(independent_speeds, str) \
            or sorted(set(independent_speeds)) != sorted(independent_speeds) \
            or any(c not in coords for c in independent_speeds) or len(independent_speeds) != n - m:
        raise ConstraintError(
            f"independent_speeds= must list {n - m} distinct coordinates (of {coords}) whose speeds are "
            f"independent: {n} speeds, {m} velocity constraint rows {row_names}; got {independent_speeds!r}.")
    S = [coords.index(c) for c in independent_speeds]
    D = [i for i in range(n) if i not in S]
    q, qd, p, u = d.q, d.qd, d.p, d.u
    A = ca.jacobian(rows, qd)
    b = ca.substitute(rows, qd, ca.DM.zeros(n))
    _check_determined(A[:, D], q, p, d, row_names, [coords[i] for i in D])
    s = ca.vertcat(*[ca.SX.sym(f"{coords[i]}_d") for i in S])
    C = ca.SX.zeros(n, n - m)
    C[S, :] = ca.SX.eye(n - m)
    C[D, :] = -ca.solve(A[:, D], A[:, S])
    e = ca.SX.zeros(n, 1)
    e[D] = -ca.solve(A[:, D], b)
    qd_full = C @ s + e
    rate = ca.substitute(ca.jtimes(rows, q, qd), qd, qd_full)          # Ȧ q̇ + ḃ along the motion
    c0 = ca.SX.zeros(n, 1)
    c0[D] = -ca.solve(A[:, D], rate)
    F = ca.substitute(d.F, qd, qd_full)
    Mr, Fr = C.T @ d.M @ C, C.T @ (F - d.M @ c0)
    sd = ca.solve(Mr, Fr)
    lam = ca.solve(A[:, D].T, (d.M @ (C @ sd + c0) - F)[D])
    x = ca.vertcat(q, s)
    states = coords + [f"{coords[i]}_d" for i in S]
    f = ca.Function(f"{name}_rhs", [x, u, p], [ca.vertcat(qd_full, sd)], ["x", "u", "p"], ["xd"], {"cse": True})
    y = ca.vertcat(qd_full[D], lam)
    h = ca.Function(f"{name}_outputs", [x, u, p], [y], ["x", "u", "p"], ["y"], {"cse": True})
    names = [f"{coords[i]}_d" for i in D] + row_names
    return Dynamics(f, states=states, inputs=d.names["input"], parameters=d.names["parameter"],
                    defaults=dict(d.defaults), outputs=h, output_names=names, name=name)


def _check_determined(AD: ca.SX, q: ca.SX, p: ca.SX, d, row_names, dependent) -> None:
    """``A_D`` must be invertible at a generic configuration (random, default parameters)."""
    import numpy as np

    f = ca.Function("AD", [q, p], [ca.densify(AD)])
    pv = np.array([d.defaults.get(k, 1.0) for k in d.names["parameter"]], dtype=float)
    qv = np.random.default_rng(0).uniform(-1.0, 1.0, q.numel())
    Av = np.array(f(qv, pv))
    if np.linalg.matrix_rank(Av) < Av.shape[0]:
        raise ConstraintError(f"the velocity constraints {row_names} do not determine the speeds of {dependent} (their "
                              "coefficient matrix is singular); choose other independent_speeds, or remove a "
                              "redundant row.")
