"""Flexible bodies in Wallrapp's standard-input-data (SID) form.

A :class:`FlexibleBody` is described by the shape integrals of paper Appendix A
(Branlard & Geisler 2022), held in a :class:`mbsym.beam.ShapeIntegrals`, each a
Taylor expansion ``T0 + sum_j T1_j q_e,j`` (Appendix D3, order 0 or 1). Its
elastic coordinates ``q_e`` are coordinates of the system owned by the body.

Kane contribution (paper Eqs. 12-21), written in the body frame (primes) and
rotated to ground axes by ``T = diag(R, R, I)``::

    Mb' = [[m I,  Mxθ,  Ctᵀ],        k' = [2 ω̃ Ctᵀ q̇e + ω̃ ω̃ S,
           [Mθx,  Mθθ,  Crᵀ],              ω̃ Mθθ ω + (Σ Gr_j q̇e_j) ω,
           [Ct,   Cr,   Me ]]              [ωᵀ Oe_j ω]_j + (Σ Ge_j q̇e_j) ω + Ke qe + De q̇e + Kg qe]

    f' = [m g', S̃ g', Ct g']        (gravity, A17-A19; S = ∫ s_P dm = -vee(Mxθ))

Geometric stiffening ``Kg`` (Appendix C, C2) is evaluated with the gravity
field and the velocity-dependent acceleration of the body origin (``a - g``,
including the load of a declared ``top_mass`` on the end) and with the body's
angular velocity (centrifugal term); both can be switched off. The parts of the
accelerations proportional to q̈ are left out: they would put unsymmetric
entries in M, and they multiply q_e, so they vanish in linearizations about
undeflected states.
"""

from __future__ import annotations

import dataclasses
from typing import Sequence

import casadi as ca
import numpy as np

from ..exceptions import ModelDefinitionError
from ..kinematics import _scalar, elastodyn_rotation, skew, small_rotation, vee
from .base import Body
from .lumped_terms import exact_lumped_terms

__all__ = ["FlexibleBody"]


def _dm(a) -> ca.SX:
    """numpy array (any shape up to 2-D) or SX -> SX."""
    if isinstance(a, (ca.SX, ca.MX)):
        return ca.SX(a)
    return ca.SX(ca.DM(np.asarray(a, dtype=float)))


def _taylor(term, qe: ca.SX, order: int, shape2: tuple[int, int]) -> ca.SX:
    """Evaluate a Taylor term (order0 of shape ``shape2``) symbolically."""
    out = _dm(np.asarray(term.order0).reshape(shape2))
    if order >= 1 and term.order1 is not None:
        for j in range(qe.numel()):
            out = out + _dm(np.asarray(term.order1[j]).reshape(shape2)) * qe[j]
    return out


class FlexibleBody(Body):
    """A flexible body described by shape integrals.

    Parameters
    ----------
    name : str
        Unique body name.
    sid : mbsym.beam.ShapeIntegrals
        Shape integrals in the body frame about the body origin (see
        :mod:`mbsym.beam`); the beam lies along body z from the origin.
    coordinates : sequence of SX
        One system coordinate per shape function (``q_e``) [m for shapes
        normalized to unit tip deflection].
    kinematics : {"shape_integrals", "exact"}, optional
        ``"shape_integrals"`` (default): the SID Taylor terms below, with geometric
        stiffening. ``"exact"``: for lumped bodies (``sid.nodes``, e.g. from
        :func:`mbsym.beam.lumped_shape_integrals`), Kane's terms of the point masses at
        their exact positions ``z e_z + Φ q − ½ qᵀ Ax q e_z`` (every order in ``q_e``:
        ``Σ m (Ax q)(Ax q)ᵀ`` in ``M_e``, inertia reduced by the axial shortening, …;
        :mod:`mbsym.bodies.lumped_terms`), and an end attachment that follows the axial
        shortening of the end. Geometric stiffening then comes out of the kinematics
        (gravity, accelerations, rotation, and the loads of bodies attached at the end), so
        ``taylor_order``, ``gravity_stiffening``, ``centrifugal_stiffening`` and
        ``top_mass`` do not apply.
    taylor_order : {0, 1, 2}, optional
        Keep only the undeflected shape integrals (0), add the terms linear in
        ``q_e`` (1, default, the paper's choice), or also the quadratic term of
        ``Mθθ`` (2): with it, the equations of a linear displacement field are
        exact and conserve energy.
    gravity_stiffening : bool, optional
        Geometric stiffness from gravity and the origin's acceleration: self
        weight, the weight of ``top_mass``, and e.g. the centripetal
        acceleration of a blade root away from the rotor axis (default True).
    centrifugal_stiffening : bool, optional
        Geometric stiffness from the body's rotation ``ω'ᵀ Kgω ω'`` (default True).
    top_mass : float or SX, optional
        Mass [kg] carried at the body's end whose weight loads the body
        axially (e.g. the rotor-nacelle assembly on a tower), default 0.
    end_rotation_order : int, None or "elastodyn", optional
        Orientation of a child attached at the end: ``None`` exact rotation of
        the slope vector, ``n`` its small-angle series to order n (default 1:
        ``I + [θ~]``), ``"elastodyn"`` ElastoDyn's closest orthonormal matrix
        (rotation by ``atan|θ|``, :func:`mbsym.kinematics.elastodyn_rotation`).
    end_angular_velocity : {"exact", "slope_rates"}, optional
        Angular velocity of a child attached at the end, relative to the body:
        ``"exact"`` (default) that of the end orientation, ``vee(Ṙ Rᵀ)``;
        ``"slope_rates"`` the rates of the slope vector, ``θ̇ = Ψ q̇e`` along constant body
        axes, ElastoDyn's tower-top convention (it is not the derivative of the end
        orientation once two slopes are nonzero: no ``θ × θ̇`` term about the beam axis).
    stiffness, damping : array or SX, optional
        Override ``sid.ke`` / ``sid.de`` (n_e x n_e), e.g. with expressions of
        parameters for design studies.
    mass_scale : float or SX, optional
        Factor on every inertial shape integral (mass, first and second moments,
        ``Ct``, ``Cr``, ``Me``, ``Gr``, ``Ge``, ``Oe`` and the self-weight and
        centrifugal geometric stiffness; not ``kg_tip``, which the top mass loads):
        the body with its mass density scaled, e.g. ElastoDyn's AdjTwMa as a
        parameter. Default: none (the shape integrals as given).

    Examples
    --------
    See ``examples/paper_4_4_two_dof.py``.
    """

    def __init__(self, name: str, sid, coordinates: Sequence, *, kinematics: str = "shape_integrals",
                 taylor_order: int | None = None, gravity_stiffening: bool | None = None,
                 centrifugal_stiffening: bool | None = None, top_mass=None, end_rotation_order: int | None = 1,
                 end_angular_velocity: str = "exact", stiffness=None, damping=None,
                 mass_scale=None) -> None:
        super().__init__(name)
        coordinates = tuple(coordinates)
        if len(coordinates) != sid.n_e:
            raise ModelDefinitionError(
                f"flexible body {name!r} has {sid.n_e} shape functions but {len(coordinates)} coordinates; "
                "give one coordinate per shape function."
            )
        self.kinematics = _check_kinematics(name, sid, kinematics, taylor_order=taylor_order, top_mass=top_mass,
                                            gravity_stiffening=gravity_stiffening,
                                            centrifugal_stiffening=centrifugal_stiffening)
        taylor_order = 1 if taylor_order is None else taylor_order
        gravity_stiffening = True if gravity_stiffening is None else gravity_stiffening
        centrifugal_stiffening = True if centrifugal_stiffening is None else centrifugal_stiffening
        top_mass = 0.0 if top_mass is None else top_mass
        if taylor_order not in (0, 1, 2):
            raise ModelDefinitionError(f"taylor_order of {name!r} must be 0, 1 or 2; got {taylor_order!r}.")
        if taylor_order == 2 and getattr(sid, "mtt2", None) is None:
            raise ModelDefinitionError(
                f"taylor_order=2 for {name!r} needs the second-order inertia integrals sid.mtt2; "
                "compute the shape integrals with mbsym.beam.shape_integrals or use taylor_order=1."
            )
        self._sid = sid
        self._qe = coordinates
        self.taylor_order = taylor_order
        self.gravity_stiffening = bool(gravity_stiffening)
        self.centrifugal_stiffening = bool(centrifugal_stiffening)
        self.end_rotation_order = end_rotation_order
        if end_angular_velocity not in ("exact", "slope_rates"):
            raise ModelDefinitionError(f"end_angular_velocity of {name!r} must be 'exact' or 'slope_rates'; "
                                       f"got {end_angular_velocity!r}.")
        self.end_angular_velocity = end_angular_velocity
        self._top_mass = _scalar(top_mass, f"top_mass of {name!r}")
        self._mass_scale = None if mass_scale is None else _scalar(mass_scale, f"mass_scale of {name!r}")
        ne = sid.n_e
        self._ke = self._square(stiffness, sid.ke, "stiffness", ne)
        self._de = self._square(damping, sid.de, "damping", ne)

    def _square(self, value, default, what: str, ne: int) -> ca.SX:
        m = _dm(default if value is None else value)
        if m.shape != (ne, ne):
            raise ModelDefinitionError(f"{what} of {self.name!r} has shape {m.shape}; expected ({ne}, {ne}).")
        return m

    @property
    def sid(self):
        """The shape integrals (read-only)."""
        return self._sid

    @property
    def elastic_coordinates(self) -> tuple:
        return self._qe

    @property
    def n_e(self) -> int:
        return self._sid.n_e

    def symbolic_values(self) -> list:
        scale = [] if self._mass_scale is None else [self._mass_scale]
        return [self._top_mass, self._ke, self._de, *scale]

    # ------------------------------------------------------------ attachment
    def attachment(self, offset: ca.SX) -> tuple[ca.SX, ca.SX]:
        """Root (origin) or end (deflected tip, rotated by its slope) of the body."""
        off = np.array(ca.evalf(offset)).reshape(-1) if offset.is_constant() else None
        end = np.asarray(self._sid.end_position, dtype=float).reshape(-1)
        if off is not None and np.allclose(off, 0.0, atol=1e-12):
            return offset, ca.SX.eye(3)
        if off is not None and np.allclose(off, end, rtol=1e-9, atol=1e-9):
            qe = ca.vertcat(*self._qe)
            disp = _dm(self._sid.end_displacement) @ qe
            if self.kinematics == "exact":     # the end follows the axial shortening
                disp[2] -= 0.5 * qe.T @ _dm(self._sid.nodes.end_axial_reduction) @ qe
            theta = _dm(self._sid.end_rotation) @ qe
            if self.end_rotation_order == "elastodyn":
                return offset + disp, elastodyn_rotation(theta)
            return offset + disp, small_rotation(theta, order=self.end_rotation_order)
        raise ModelDefinitionError(
            f"joints and point loads on flexible body {self.name!r} must be at its root [0, 0, 0] or at its "
            f"end {end.tolist()} (body coordinates); got {off.tolist() if off is not None else offset}."
        )

    def attachment_angular_velocity(self, offset: ca.SX, speed) -> ca.SX | None:
        """``Ψ q̇e`` at the end with ``end_angular_velocity="slope_rates"``; otherwise None (exact)."""
        if self.end_angular_velocity != "slope_rates" or not offset.is_constant():
            return None
        off = np.array(ca.evalf(offset)).reshape(-1)
        if not np.allclose(off, np.asarray(self._sid.end_position, dtype=float).reshape(-1), rtol=1e-9, atol=1e-9):
            return None
        qde = ca.vertcat(*[speed(c) for c in self._qe])
        return _dm(self._sid.end_rotation) @ qde

    # ------------------------------------------------------------ Kane terms
    def kane_terms(self, kin) -> dict:
        """Stacked velocities ``[v_O; ω; q̇e]`` and the callback giving Mb, f_net, T, V."""
        f = kin.frame(self)
        qe = ca.vertcat(*self._qe)
        idx = [kin.q_index(c) for c in self._qe]
        qde = ca.vertcat(*[kin.qd[i] for i in idx])
        V = ca.vertcat(f.v, f.w, qde)

        def terms(a0: ca.SX, g: ca.SX):
            if self.kinematics == "exact":
                return self._exact_terms(f, qe, qde, a0, g)
            return self._terms(f, qe, qde, a0, g)

        return {"V": V, "terms": terms}

    def _terms(self, f, qe, qde, a0, g):
        sid, ne, o = self._sid, self.n_e, self.taylor_order
        R = f.R
        w = R.T @ f.w
        gb = R.T @ g
        m = _scalar(float(sid.mass), "mass")
        Mxt = _taylor(sid.mxt, qe, o, (3, 3))
        Mtt = _taylor(sid.mtt, qe, o, (3, 3))
        if o == 2:
            # -∫ ũ ũ dm = Σ_ij q_i q_j mtt2[i, j]
            Mtt += sum((_dm(sid.mtt2[i][j]) * qe[i] * qe[j] for i in range(ne) for j in range(ne)), ca.SX.zeros(3, 3))
        Cr = _taylor(sid.cr, qe, o, (ne, 3))
        Ct = _dm(sid.ct)
        Me = _dm(sid.me)
        Gr = sum((_taylor(_slice(sid.gr, j), qe, o, (3, 3)) * qde[j] for j in range(ne)), ca.SX.zeros(3, 3))
        Ge = sum((_dm(sid.ge[j]) * qde[j] for j in range(ne)), ca.SX.zeros(ne, 3))
        Oe = [_taylor(_slice(sid.oe, j), qe, o, (3, 3)) for j in range(ne)]
        if self._mass_scale is not None:        # every inertial integral is linear in the mass density
            c = self._mass_scale
            m, Mxt, Mtt, Cr, Ct, Me, Gr, Ge = (c * v for v in (m, Mxt, Mtt, Cr, Ct, Me, Gr, Ge))
            Oe = [c * v for v in Oe]
        S = vee(-Mxt)                      # first moment of mass ∫ s_P dm
        Mb = ca.blockcat([[m * ca.SX.eye(3), Mxt, Ct.T], [Mxt.T, Mtt, Cr.T], [Ct, Cr, Me]])
        W = skew(w)
        k_x = 2 * W @ Ct.T @ qde + W @ W @ S
        k_t = W @ Mtt @ w + Gr @ w
        k_e = ca.vertcat(*[w.T @ Oe[j] @ w for j in range(ne)]) + Ge @ w
        Tm = ca.diagcat(R, R, ca.SX.eye(ne))
        a0b = Tm.T @ a0
        f_nc = -self._de @ qde - self._geometric_stiffness(w, gb, a0b[:3], a0b[3:6]) @ qe
        k_e += self._ke @ qe - f_nc
        f_app = ca.vertcat(m * gb, ca.cross(S, gb), Ct @ gb)
        f_net = f_app - ca.vertcat(k_x, k_t, k_e) - Mb @ a0b
        Vb = ca.vertcat(R.T @ f.v, w, qde)
        t_kin = 0.5 * Vb.T @ Mb @ Vb
        v_pot = -ca.dot(g, m * f.r + R @ S) + 0.5 * qe.T @ self._ke @ qe
        p_nc = ca.dot(f_nc, qde)    # power of elastic damping and geometric stiffening (not in V)
        return Tm @ Mb @ Tm.T, Tm @ f_net, t_kin, v_pot, p_nc

    def _exact_terms(self, f, qe, qde, a0, g):
        """Kane terms of the point masses at their exact positions (:mod:`.lumped_terms`)."""
        R = f.R
        w, gb = R.T @ f.w, R.T @ g
        t = exact_lumped_terms(self._sid.nodes.moments(), qe, qde)
        c = 1.0 if self._mass_scale is None else self._mass_scale   # every inertial term is linear in the node masses
        m = c * float(self._sid.nodes.moments().mass)
        S, C = c * t.c, c * t.C
        Mb = c * t.mass_matrix()
        f_nc = -self._de @ qde
        k = c * t.velocity_terms(w) + ca.vertcat(ca.SX.zeros(6, 1), self._ke @ qe - f_nc)
        Tm = ca.diagcat(R, R, ca.SX.eye(self.n_e))
        f_app = ca.vertcat(m * gb, ca.cross(S, gb), C.T @ gb)
        f_net = f_app - k - Mb @ (Tm.T @ a0)
        Vb = ca.vertcat(R.T @ f.v, w, qde)
        t_kin = 0.5 * Vb.T @ Mb @ Vb
        v_pot = -ca.dot(g, m * f.r + R @ S) + 0.5 * qe.T @ self._ke @ qe
        return Tm @ Mb @ Tm.T, Tm @ f_net, t_kin, v_pot, ca.dot(f_nc, qde)

    def _geometric_stiffness(self, w: ca.SX, gb: ca.SX, acc: ca.SX, wdot: ca.SX) -> ca.SX:
        """Kg (n_e x n_e) of paper Eq. C2, body axes.

        ``acc`` and ``wdot`` are the velocity-dependent parts of the origin's
        acceleration and of the angular acceleration (the parts proportional to
        qdd are left out so that M stays symmetric).
        """
        sid, ne = self._sid, self.n_e
        c = 1.0 if self._mass_scale is None else self._mass_scale     # own-mass terms scale with the density
        Kg = ca.SX.zeros(ne, ne)
        if self.gravity_stiffening:
            # (a - g) kg_t for the body's own mass; the top mass pushes on the tip
            # with F = -top_mass (a - g).
            for a in range(3):
                load = acc[a] - gb[a]
                Kg += c * load * _dm(sid.kg_t[a]) - self._top_mass * load * _dm(sid.kg_tip[a])
                kr = np.asarray(sid.kg_r[a])
                if np.any(kr):
                    Kg += c * wdot[a] * _dm(kr)
        if self.centrifugal_stiffening:
            for a in range(3):
                for b in range(3):
                    kab = np.asarray(sid.kg_omega[a][b])
                    if np.any(kab):
                        Kg += c * w[a] * w[b] * _dm(kab)
        return Kg


def _check_kinematics(name: str, sid, kinematics: str, **options) -> str:
    """The kinematics option, with the options that only apply to shape-integral bodies."""
    if kinematics not in ("shape_integrals", "exact"):
        raise ModelDefinitionError(f"kinematics of {name!r} must be 'shape_integrals' or 'exact'; got {kinematics!r}.")
    if kinematics == "exact":
        if getattr(sid, "nodes", None) is None:
            raise ModelDefinitionError(
                f"kinematics='exact' for {name!r} needs the point masses of a lumped body (sid.nodes); build the "
                "shape integrals with mbsym.beam.lumped_shape_integrals or use kinematics='shape_integrals'.")
        given = [k for k, v in options.items() if v is not None]
        if given:
            raise ModelDefinitionError(
                f"{given} of {name!r} apply to kinematics='shape_integrals' only: with kinematics='exact' the "
                "exact node positions carry every order in q_e and the geometric stiffening (gravity, rotation, "
                "and the loads of bodies attached at the end); remove them.")
    return kinematics


def _slice(term, j: int):
    """The j-th member of a stacked Taylor term (order0[j], order1[:, j])."""
    o1 = None if term.order1 is None else np.asarray(term.order1)[:, j]
    return dataclasses.replace(term, order0=np.asarray(term.order0)[j], order1=o1)

