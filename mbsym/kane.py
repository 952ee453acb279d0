"""Kinematics of the tree and Kane's method (paper Eqs. 4-10, 22).

For every body we build, in ground axes, the origin position ``r``, the
orientation ``R`` (body -> ground), the angular velocity ``w`` and the velocity
``v``, recursively from the root. Velocities are linear in the speeds ``qd``,
so the partial velocities are ``J = d[v; w]/d(qd)`` and the acceleration is
``a = J qdd + a0`` with ``a0 = d[v; w]/dq . qd``. Each body then contributes

``M += Bᵀ Mb B`` and ``F += Bᵀ (f_applied - Mb a0 - k_w)``,

with ``B`` its partial velocities, ``Mb`` its 6x6 (rigid) or (6+n_e) (flexible)
mass matrix and ``k_w`` its quadratic-velocity loads. This is the residual
``e = F - M qdd`` of Eq. 22 with ``M = -de/dqdd`` assembled directly.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import casadi as ca
import numpy as np

from .bodies.base import Body
from .bodies.rigid import RigidBody
from .composite import MassProperties, composite_bodies
from .exceptions import ModelDefinitionError, SingularMassMatrixError
from .kinematics import skew, vee
from .loads import Damper, DistributedLoad, GeneralizedForce, PointForce, Spring, Torque

__all__ = ["Frame", "Derivation", "derive"]


@dataclass(frozen=True)
class Frame:
    """Kinematics of a body frame, all in ground axes (SX)."""

    r: ca.SX   # origin position [m] (3x1)
    R: ca.SX   # orientation, body -> ground (3x3)
    v: ca.SX   # origin velocity [m/s] (3x1)
    w: ca.SX   # angular velocity [rad/s] (3x1)


@dataclass
class Derivation:
    """Symbolic result of Kane's method, consumed by :class:`EquationsOfMotion`."""

    q: ca.SX
    qd: ca.SX
    qdd: ca.SX
    u: ca.SX
    p: ca.SX
    names: dict[str, list[str]]
    defaults: dict[str, float]
    M: ca.SX
    F: ca.SX
    T: ca.SX
    V: ca.SX
    power: ca.SX
    frames: dict[str, Frame] = field(default_factory=dict)
    bodies: dict[str, Body] = field(default_factory=dict)
    kinematics: "_Kinematics | None" = None
    prescribed: tuple[str, ...] = ()
    reactions: ca.SX | None = None      # (n_locked,) reaction generalized forces, of q, qd, qdd, u, p


class _Kinematics:
    """Recursive frame kinematics of a system's tree."""

    def __init__(self, system, q: ca.SX, qd: ca.SX, qp: ca.SX, qdp: ca.SX) -> None:
        self.q, self.qd = q, qd
        self.q_all, self.qd_all = ca.vertcat(q, qp), ca.vertcat(qd, qdp)
        self._index = {q[i].element_hash(): i for i in range(q.numel())}
        self._speed = {self.q_all[i].element_hash(): self.qd_all[i] for i in range(self.q_all.numel())}
        ground = system.ground
        zero = ca.SX.zeros(3, 1)
        self.frames: dict[int, Frame] = {id(ground): Frame(zero, ca.SX.eye(3), zero, zero)}
        self.order: list[Body] = []
        # attachment orientations that turn with a declared angular velocity (see _turning)
        self._held: list[tuple[ca.SX, ca.SX, ca.SX]] = []
        pending = list(system.joints)
        while pending:
            ready = [j for j in pending if id(j.parent) in self.frames]
            for j in ready:
                self.frames[id(j.child)] = self._child_frame(j)
                self.order.append(j.child)
            pending = [j for j in pending if id(j.child) not in self.frames]

    def _dt(self, expr: ca.SX) -> ca.SX:
        """Time derivative of an expression of q only."""
        if expr.is_constant():
            return ca.SX.zeros(expr.shape)
        return ca.reshape(ca.jtimes(ca.vec(expr), self.q_all, self.qd_all), expr.shape)

    def _rel_omega(self, R: ca.SX) -> ca.SX:
        """Angular velocity of a q-dependent rotation, in its reference axes."""
        if R.is_constant():
            return ca.SX.zeros(3, 1)
        return vee(self._dt(R) @ R.T)

    def _child_frame(self, joint) -> Frame:
        P = self.frames[id(joint.parent)]
        pos, R_att = joint.parent.attachment(joint.offset)
        s = P.R @ pos
        r_J = P.r + s
        w_att = joint.parent.attachment_angular_velocity(joint.offset, self.speed)
        if w_att is None:
            w_att = self._rel_omega(R_att)
        else:
            R_att = self._turning(joint.child.name, R_att, w_att)
        R_J = P.R @ R_att @ joint.rotation
        w_J = P.w + P.R @ w_att
        v_J = P.v + ca.cross(P.w, s) + P.R @ self._dt(pos)
        d, R_rel = joint.relative()
        dg = R_J @ d
        w_rel = joint.angular_velocity(self.speed)
        if w_rel is None:
            w_rel = self._rel_omega(R_rel)
        return Frame(
            r=r_J + dg,
            R=R_J @ R_rel,
            v=v_J + ca.cross(w_J, dg) + R_J @ self._dt(d),
            w=w_J + R_J @ w_rel,
        )

    def _turning(self, name: str, R_att: ca.SX, w_att: ca.SX) -> ca.SX:
        """A placeholder for an attachment orientation that turns with a declared angular velocity.

        When a body declares the angular velocity of an attachment (e.g. ElastoDyn's tower top:
        the slope rates), the frames above it move with that angular velocity, and so do their
        accelerations, as in ElastoDyn: a vector ``ρ`` fixed in the attachment frame changes at
        ``ω × ρ`` with the declared ``ω``, not at the rate of the orientation matrix ``R_att(q)``.
        The orientation is therefore held as a symbol while differentiating, with the rate
        ``[w_att~] R_att`` (:meth:`rate`), and replaced by ``R_att(q)`` afterwards (:meth:`resolve`).
        """
        held = ca.SX.sym(f"R_attachment_{name}", 3, 3)
        self._held.append((held, R_att, skew(w_att) @ held))
        return held

    def rate(self, expr: ca.SX, x: ca.SX, xd: ca.SX) -> ca.SX:
        """Time derivative of ``expr`` along ``x' = xd``, held attachment orientations turning as declared."""
        out = ca.jtimes(expr, x, xd)
        for held, _, held_rate in self._held:
            out += ca.jtimes(expr, ca.vec(held), ca.vec(held_rate))
        return out

    def resolve(self, exprs: list[ca.SX]) -> list[ca.SX]:
        """``exprs`` with every held attachment orientation replaced by its value ``R_att(q)``."""
        if not self._held:
            return list(exprs)
        return ca.substitute(list(exprs), [h for h, _, _ in self._held], [v for _, v, _ in self._held])

    def speed(self, coordinate: ca.SX) -> ca.SX:
        """Speed symbol of a coordinate (or prescribed coordinate) symbol."""
        return self._speed[coordinate.element_hash()]

    def q_index(self, coordinate: ca.SX) -> int:
        """Index of a coordinate symbol in q."""
        return self._index[coordinate.element_hash()]

    def frame(self, body: Body) -> Frame:
        return self.frames[id(body)]

    def point_velocity(self, body: Body, point: ca.SX) -> tuple[ca.SX, ca.SX]:
        """Position and velocity of a material point of a body, in ground axes.

        ``point`` is the undeflected position in body coordinates; flexible
        bodies move it with their deflection (see ``Body.attachment``).
        """
        f = self.frame(body)
        pos, _ = body.attachment(point)
        s = f.R @ pos
        return f.r + s, f.v + ca.cross(f.w, s) + f.R @ self._dt(pos)


def derive(system) -> Derivation:
    """Derive M(q, p) and F(q, qd, u, p) of a validated system by Kane's method."""
    st = system.symbols
    q = ca.vertcat(*st.symbols("coordinate"))
    qd = ca.vertcat(*st.speeds())
    qdd = ca.vertcat(*st.accelerations())
    u = ca.vertcat(*st.symbols("input")) if st.names("input") else ca.SX(0, 1)
    p = ca.vertcat(*st.symbols("parameter")) if st.names("parameter") else ca.SX(0, 1)
    n = q.numel()
    presc = st.prescribed()
    qp = ca.vertcat(*[v[0] for v in presc.values()]) if presc else ca.SX(0, 1)
    qdp = ca.vertcat(*[v[1] for v in presc.values()]) if presc else ca.SX(0, 1)
    qddp = ca.vertcat(*[v[2] for v in presc.values()]) if presc else ca.SX(0, 1)
    locked = st.locked()
    ql, qdl = (ca.vertcat(*[v[k] for v in locked.values()]) if locked else ca.SX(0, 1) for k in (0, 1))
    kin = _Kinematics(system, q, qd, ca.vertcat(qp, ql), ca.vertcat(qdp, qdl))
    g = system.gravity

    composites, merged = composite_bodies(system.joints)
    blocks, V_rows = [], []
    for body in kin.order:
        if id(body) in merged:
            continue        # welded to a rigid ancestor: counted in its composite
        contrib = _body_velocities(body, kin, composites)
        blocks.append((body, contrib))
        V_rows.append(contrib["V"])
    Vall = ca.vertcat(*V_rows) if V_rows else ca.SX(0, 1)
    J = ca.jacobian(Vall, qd)
    Jl = ca.jacobian(Vall, qdl)             # partial velocities of the locked speeds (reactions)
    # velocity-dependent accelerations; prescribed coordinates add their accelerations
    A0 = kin.rate(Vall, kin.q_all, kin.qd_all)
    if presc:
        A0 += ca.jtimes(Vall, qdp, qddp)

    M = ca.SX.zeros(n, n)
    F = ca.SX.zeros(n, 1)
    E_locked = ca.SX.zeros(qdl.numel(), 1)
    T = ca.SX(0)
    Vpot = ca.SX(0)
    p_body = ca.SX(0)   # power of body-internal non-conservative forces (elastic damping, ...)
    row = 0
    for body, c in blocks:
        k = c["V"].numel()
        B, a0 = J[row:row + k, :], A0[row:row + k]
        Mb, f_net, t_kin, v_pot, p_nc = c["terms"](a0, g)
        M += B.T @ Mb @ B
        F += B.T @ f_net
        if locked:
            E_locked += Jl[row:row + k, :].T @ (f_net - Mb @ (B @ qdd))
        row += k
        T += t_kin
        Vpot += v_pot
        p_body += p_nc

    F_all, Vpot, power = _apply_loads(system, kin, q, ca.vertcat(qd, qdl), ca.vertcat(F, E_locked), Vpot)
    F, E_locked = F_all[:n], F_all[n:]
    power += p_body
    M, F, T, Vpot, power, E_locked = kin.resolve([M, F, T, Vpot, power, E_locked])
    M = ca.tril2symm(ca.tril(M))
    reactions = None
    frames = {b.name: Frame(*kin.resolve([f.r, f.R, f.v, f.w])) for b in kin.order for f in [kin.frame(b)]}
    if locked:                              # held at zero: the reaction is minus the locked rows' residual
        reactions = -E_locked
        zero = ca.SX.zeros(2 * ql.numel(), 1)
        lz = ca.vertcat(ql, qdl)
        M, F, T, Vpot, power, reactions = ca.substitute([M, F, T, Vpot, power, reactions], [lz], [zero])
        frames = {k: Frame(*ca.substitute([f.r, f.R, f.v, f.w], [lz], [zero])) for k, f in frames.items()}
    _check_structural_mass(M, st.names("coordinate"))
    bodies = {b.name: b for b in kin.order}
    names = {k: st.names(k) for k in ("coordinate", "input", "parameter", "locked")}
    return Derivation(q, qd, qdd, u, p, names, st.defaults(), M, F, T, Vpot, power, frames, bodies, kin,
                      tuple(presc), reactions)


def _body_velocities(body: Body, kin: _Kinematics, composites: dict) -> dict:
    """Stacked velocities of a body's reference point and its Kane terms callback."""
    if isinstance(body, RigidBody):
        return _rigid(body, kin, composites[id(body)])
    hook = getattr(body, "kane_terms", None)
    if hook is None:
        raise ModelDefinitionError(f"body {body.name!r} of type {type(body).__name__} has no Kane contribution.")
    return hook(kin)


def _rigid(body: RigidBody, kin: _Kinematics, props: MassProperties) -> dict:
    """Rigid (composite) body about its origin O (paper Eqs. 6-9 moved to O), ground axes.

    With S = m c the first moment and I_O the inertia about O (ground axes), the inertial
    force is -(m a_O + α × S + ω × (ω × S)) and the inertial torque about O is
    -(S × a_O + I_O α + ω × I_O ω).
    """
    f = kin.frame(body)
    m = props.mass
    S = f.R @ props.first_moment
    I_O = f.R @ props.inertia @ f.R.T

    def terms(a0: ca.SX, g: ca.SX):
        Sx = skew(S)
        Mb = ca.blockcat([[m * ca.SX.eye(3), -Sx], [Sx, I_O]])
        w = f.w
        f_lin = m * g - m * a0[:3] - ca.cross(a0[3:], S) - ca.cross(w, ca.cross(w, S))
        f_ang = ca.cross(S, g) - ca.cross(S, a0[:3]) - I_O @ a0[3:] - ca.cross(w, I_O @ w)
        t_kin = 0.5 * (m * ca.dot(f.v, f.v) + 2 * ca.dot(f.v, ca.cross(w, S)) + ca.dot(w, I_O @ w))
        v_pot = -ca.dot(g, m * f.r + S)
        return Mb, ca.vertcat(f_lin, f_ang), t_kin, v_pot, ca.SX(0)

    return {"V": ca.vertcat(f.v, f.w), "terms": terms}


def _apply_loads(system, kin: _Kinematics, q, qd, F, Vpot):
    """Add point forces, torques, generalized forces, springs and dampers.

    ``qd`` may continue past the coordinates' speeds (locked speeds, for reactions): F has
    one row per entry of ``qd``; generalized forces, springs and dampers act on the first rows.
    """
    power = ca.SX(0)
    for load in system.loads:
        if isinstance(load, PointForce):
            fg = load.force if load.frame is None else kin.frame(load.frame).R @ load.force
            _, vP = kin.point_velocity(load.body, load.point)
            F += ca.jacobian(vP, qd).T @ fg
            power += ca.dot(fg, vP)
        elif isinstance(load, Torque):
            tg = load.torque if load.frame is None else kin.frame(load.frame).R @ load.torque
            w = kin.frame(load.body).w
            F += ca.jacobian(w, qd).T @ tg
            power += ca.dot(tg, w)
        elif isinstance(load, DistributedLoad):
            F, power = _distributed(load, kin, qd, F, power)
        elif isinstance(load, GeneralizedForce):
            F[load.index] += load.value
            power += load.value * qd[load.index]
        elif isinstance(load, Spring):
            x = q[load.index] - load.rest
            F[load.index] += -load.stiffness * x
            Vpot += 0.5 * load.stiffness * x**2
        elif isinstance(load, Damper):
            F[load.index] += -load.damping * qd[load.index]
            power += -load.damping * qd[load.index] ** 2
    return F, Vpot, power


def _distributed(load, kin: _Kinematics, qd, F, power):
    """Resultant, moment (about the deflected body) and elastic forces of a distributed load."""
    f = kin.frame(load.body)
    li, P = load.integrals, load.magnitude
    qe = [kin.q[kin.q_index(c)] for c in load.body.elastic_coordinates]
    idx = [kin.q_index(c) for c in load.body.elastic_coordinates]
    moment = ca.DM(np.asarray(li.moment.order0, dtype=float))
    for j, qj in enumerate(qe):
        moment = moment + ca.DM(np.asarray(li.moment.order1[j], dtype=float)) * qj
    fx = f.R @ ca.DM(np.asarray(li.force, dtype=float)) * P
    ft = f.R @ moment * P
    F += ca.jacobian(f.v, qd).T @ fx + ca.jacobian(f.w, qd).T @ ft
    power += ca.dot(fx, f.v) + ca.dot(ft, f.w)
    for j, i in enumerate(idx):
        F[i] += float(li.generalized[j]) * P
        power += float(li.generalized[j]) * P * qd[i]
    return F, power


def _check_structural_mass(M: ca.SX, names: list[str]) -> None:
    """Name the coordinates whose mass-matrix column is identically zero."""
    dead = [names[i] for i in range(M.shape[0]) if all(M[j, i].is_zero() for j in range(M.shape[0]))]
    if dead:
        raise SingularMassMatrixError(
            f"coordinates {dead} move no mass (their mass-matrix columns are identically zero), so the "
            "mass matrix is singular. Attach a body with mass or inertia to them, or remove them."
        )
