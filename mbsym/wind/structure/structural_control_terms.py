"""The structural controllers' (StC) terms in the structure's equations: P's motion, the loads, the state rates.

:func:`stc_terms` evaluates each StC of :mod:`.structural_control` at its point P: P's orientation, velocity,
angular velocity, acceleration and angular acceleration (ground axes) from the structure's kinematics — a point of
the nacelle or the platform (``EquationsOfMotion.point_kinematics``), or of the flexible tower
(:func:`tower_point_motion`) — then the StC's load on P (the masses' equations, or the prescribed load) and its
generalized forces ``Q = J_vᵀ F + J_ωᵀ M`` (``J_v = ∂v_P/∂q̇``, ``J_ω = ∂ω_P/∂q̇``). ``Q`` is linear in ``q̈``
(P's acceleration); its ``q̈`` part goes to the mass matrix. Everything is built once in SX and called as a CasADi
Function, so that the composition can be SX or MX.
"""

from __future__ import annotations

from typing import Any

import casadi as ca

from ...kinematics import elastodyn_rotation

__all__ = ["stc_terms", "tower_point_motion"]


def tower_point_motion(structure, point, q: Any, qd: Any, qdd: Any, u: Any, p: Any) -> tuple[Any, ...]:
    """A point of ElastoDyn's flexible tower: ``(R, v, w, a, wd)`` in ground axes (SX).

    Parameters
    ----------
    structure : TurbineModel
        The structure (its tower shapes and enabled DOFs).
    point : sequence of 3
        ``(x, y, h)`` [m]: the height ``h`` above the tower base along the undeflected axis and the offset ``(x, y)``
        from the axis, tower-base axes (a TStC's ``StC_P_X/Y/Z``). The point sits on the tower's axis at ``h``,
        moved by the tower's shapes there (interpolated linearly between ElastoDyn's nodes, with the axial
        shortening), and the offset turns with the axis' small rotation ``θ = (−Φ'_y q, Φ'_x q, 0)`` (ElastoDyn's
        ``SmllRotTrans``) and moves with the angular velocity ``θ̇`` relative to the base (ElastoDyn's slope rates,
        as the tower top carries the nacelle: not the derivative of the rotation once two slopes are nonzero).
    q, qd, qdd, u, p : SX
        The structure's coordinates, speeds, accelerations, inputs and parameters.

    Returns
    -------
    tuple
        ``R`` (3, 3) P's axes -> ground, ``v`` [m/s], ``w`` [rad/s], ``a`` [m/s²], ``wd`` [rad/s²] (3,), ground axes.
    """
    from .tower_points import tower_point_shapes

    eom = structure.eom
    _, R0, v0, w0, a0, wd0 = eom.point_kinematics("tower")(q, qd, qdd, u, p)
    x, y, h = (float(c) for c in point)
    shapes = tower_point_shapes(structure, [h])
    idx = [eom.coordinates.index(c) for c in shapes.coordinates]
    ne = len(idx)
    qe = ca.vertcat(*[q[i] for i in idx]) if ne else ca.SX(0, 1)
    qde = ca.vertcat(*[qd[i] for i in idx]) if ne else ca.SX(0, 1)
    qdde = ca.vertcat(*[qdd[i] for i in idx]) if ne else ca.SX(0, 1)
    phi, slope = ca.DM(shapes.displacement[:, 0, :].T), ca.DM(shapes.slope[:, 0, :].T)    # (2, ne)
    ax = ca.DM(shapes.axial_reduction[:, :, 0])
    if ne:
        axis = ca.vertcat(ca.mtimes(phi, qe), h - 0.5 * ca.mtimes([qe.T, ax, qe]))
        theta = ca.vertcat(-ca.mtimes(slope[1, :], qe), ca.mtimes(slope[0, :], qe), 0.0)
        rate = ca.vertcat(-ca.mtimes(slope[1, :], qde), ca.mtimes(slope[0, :], qde), 0.0)
        accel = ca.vertcat(-ca.mtimes(slope[1, :], qdde), ca.mtimes(slope[0, :], qdde), 0.0)
        turn = elastodyn_rotation(theta)
        arm = ca.mtimes(turn, ca.DM([x, y, 0.0]))        # the offset, carried rigidly with the slope rates θ̇
        da = ca.jacobian(axis, qe)                       # (ElastoDyn's node motion; OpenFAST's line-to-point map)
        s = axis + arm
        sd = ca.mtimes(da, qde) + ca.cross(rate, arm)
        sdd = ca.mtimes(ca.jacobian(ca.mtimes(da, qde), qe), qde) + ca.mtimes(da, qdde) + ca.cross(accel, arm) \
            + ca.cross(rate, ca.cross(rate, arm))
    else:                                               # a rigid tower
        s, sd, sdd = ca.SX(ca.DM([x, y, h])), ca.SX.zeros(3), ca.SX.zeros(3)
        turn, rate, accel = ca.SX.eye(3), ca.SX.zeros(3), ca.SX.zeros(3)
    S, Sd = ca.mtimes(R0, s), ca.mtimes(R0, sd)
    wr = ca.mtimes(R0, rate)
    v = v0 + ca.cross(w0, S) + Sd
    a = a0 + ca.cross(wd0, S) + ca.cross(w0, ca.cross(w0, S)) + 2 * ca.cross(w0, Sd) + ca.mtimes(R0, sdd)
    return ca.mtimes(R0, turn), v, w0 + wr, a, wd0 + ca.cross(w0, wr) + ca.mtimes(R0, accel)


def _motion(control, eom, structure, q, qd, qdd, u, p) -> tuple[Any, ...]:
    """``(R, v, w, a, wd)`` of the StC's point P (ground axes)."""
    if control.kind == "T":
        if structure is None:
            raise TypeError(f"{control.name}: a tower StC needs the structure (stc_terms(..., structure=...)).")
        return tower_point_motion(structure, control.settings.position, q, qd, qdd, u, p)
    _, R, v, w, a, wd = eom.point_kinematics(control.body, control.settings.position)(q, qd, qdd, u, p)
    return R, v, w, a, wd


def stc_terms(controls, eom, q: Any, qd: Any, u_s: Any, p_s: Any, x_stc: Any, gravity: Any, kind=ca.SX, *,
              u_stc: Any = None, structure=None) -> dict[str, Any]:
    """The StCs' contribution to the structure's equations (module docstring).

    Parameters
    ----------
    controls : StructuralControls
    eom : EquationsOfMotion
        The structure's equations (its ``point_kinematics``).
    q, qd, u_s, p_s : SX or MX
        The structure's coordinates, speeds, inputs and parameters.
    x_stc : SX or MX
        The StC states (``controls.state_names``).
    gravity : SX, MX or float
        g [m/s²].
    kind : casadi.SX or casadi.MX
        The kind of the arguments.
    u_stc : SX or MX, optional, keyword-only
        The prescribed loads (``controls.input_names``: N, N m); needed when there are any.
    structure : TurbineModel, optional, keyword-only
        The structure (its tower shapes); needed for a tower StC.

    Returns
    -------
    dict
        ``mass`` (n, n) to add to the mass matrix, ``force`` (n,) to add to the forcing, and the functions
        ``rates(qdd)`` (the StC state derivatives) and ``channels(qdd)`` (:meth:`StructuralControls.channel_names`
        rows: states [m, m/s], loads on P [kN, kN-m] in ground (``i``) and P's (``l``) axes) of the solved ``q̈``.
    """
    n, nx, nu = eom.n_q, len(controls.state_names), len(controls.input_names)
    Q_, Qd_, Qdd_ = ca.SX.sym("q", n), ca.SX.sym("qd", n), ca.SX.sym("qdd", n)
    U_, P_ = ca.SX.sym("u", eom.n_u), ca.SX.sym("p", eom.n_p)
    X_, F_, G_ = ca.SX.sym("x", nx), ca.SX.sym("f", nu), ca.SX.sym("g")
    gen, rates, chans = ca.SX.zeros(n), [], []
    g_ground = ca.vertcat(0.0, 0.0, -G_)
    ix = iu = 0
    for c in controls.controls:
        R, v, w, a, wd = _motion(c, eom, structure, Q_, Qd_, Qdd_, U_, P_)
        O = R.T                                            # ground -> P's axes (the mesh's Orientation)
        if c.prescribed:                                    # StC_DOF_MODE 6: the file's load, no states
            f, m = F_[iu:iu + 3], F_[iu + 3:iu + 6]
            iu += 6
            local = c.settings.prescribed_coordinates == 2
            F_g, M_g = (ca.mtimes(R, f), ca.mtimes(R, m)) if local else (f, m)
            x = ca.SX.zeros(6)
            F_l, M_l = f, m                                 # ServoDyn's m%F_P, m%M_P: the values as given
        else:
            x = X_[ix:ix + 6]
            ix += 6
            F_l, M_l, xd = c.local(x, ca.mtimes(O, a), ca.mtimes(O, w), ca.mtimes(O, wd), ca.mtimes(O, g_ground), G_)
            F_g, M_g = ca.mtimes(R, F_l), ca.mtimes(R, M_l)
            rates.append(xd)
        gen += ca.mtimes(ca.jacobian(v, Qd_).T, F_g) + ca.mtimes(ca.jacobian(w, Qd_).T, M_g)
        chans += [x, F_g / 1e3, M_g / 1e3, F_l / 1e3, M_l / 1e3]
    zero = ca.SX.zeros(n)
    mass = -ca.jacobian(gen, Qdd_)
    force = ca.substitute(gen, Qdd_, zero)
    rate_expr = ca.vertcat(*rates) if rates else ca.SX(0, 1)
    chan_expr = ca.vertcat(*chans) if chans else ca.SX(0, 1)
    fun = ca.Function("stc_terms", [Q_, Qd_, Qdd_, U_, P_, X_, F_, G_], [mass, force, rate_expr, chan_expr],
                      {"cse": True})
    x_stc = x_stc if x_stc is not None and x_stc.numel() == nx else kind.zeros(nx)
    u_stc = u_stc if u_stc is not None else kind.zeros(nu)
    if u_stc.numel() != nu:
        raise ValueError(f"u_stc must hold the {nu} prescribed StC loads {controls.input_names}; got {u_stc.numel()}.")
    args = (q, qd, kind.zeros(n), u_s, p_s, x_stc, u_stc, gravity)
    out = fun(*args)

    def at(solved, k):
        return fun(q, qd, solved, u_s, p_s, x_stc, u_stc, gravity)[k]

    return {"mass": out[0], "force": out[1], "rates": lambda solved: at(solved, 2),
            "channels": lambda solved: at(solved, 3)}
