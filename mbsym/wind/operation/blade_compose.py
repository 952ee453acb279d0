"""The operating turbine with blade-element aerodynamics on every blade, as one CasADi graph.

:class:`BladeGraph` composes the ElastoDyn-equivalent structure (blade-load inputs, locked blade-root
and tower-base rotations for the reactions), the blade-element rotor
(:class:`~mbsym.wind.aero.blade.BladeElementRotor`), the wind at the nodes' current positions
(:mod:`.wind_inputs`) and the actuators:

1. every AeroDyn node of every blade moves with the structure (:mod:`mbsym.wind.structure.blade_points`:
   ElastoDyn's shapes interpolated to the node, as OpenFAST's mesh mapping does), so its position, velocity
   and deflected span direction are expressions of ``(q, q̇)``; AeroDyn's node is the aerodynamic centre, off
   the pitch axis by ``BlCrvAC``, ``BlSwpAC`` (:func:`aerodynamic_centres`);
2. the wind at the aerodynamic centre's position (with ``SectAvg``, its average over the node's sector:
   :mod:`mbsym.wind.aero.sector_average`) minus its velocity is the relative flow; in AeroDyn's
   ``BEM_Mod = 1`` axes without sweep, pitch and twist (:func:`annulus_axes`: the unpitched root's in-plane
   axis ``y``, the normal ``x`` tilted by the section's out-of-plane angle; not turned by in-plane bending) it
   gives ``Vx`` and ``Vy``, with the node's distance from the shaft axis ``r_local`` and ``θ`` = aerodynamic
   twist + pitch + the second-order twist AeroDyn reads from ElastoDyn's bent section (:func:`elastic_twist`).
   On OpenFAST's own structural states this reproduces AeroDyn's ``Vx``, ``Vy`` within 0.043 m/s
   (tests/wind/blade/test_blade_node_inflow.py);
3. the rotor's BEM with dynamic wake gives forces per unit length along ``x`` and ``−y`` and the
   pitching moment about AeroDyn's annulus z axis (``x_n × y_n``: the coned root's span axis turned by the
   node's curve angle, as AeroDyn's ``SetOutputsFromBEMT`` with ``BEM_Mod = 1``); integrated with the rotor's
   node weights they become each blade's
   root force, root moment (about the root, with the aerodynamic centres' arms) and elastic generalized
   forces (the structure's blade-load inputs, with the pitch axis' shapes: the aerodynamic centres differ
   from them only along the span, where these loads have no component).

The aerodynamic part is one SX Function (``blade_aero``) called by the composed graph, so the
structure may be SX or MX (MX beyond :data:`~mbsym.equations.SYMBOLIC_SOLVE_MAX_DOF` DOFs).
"""

from __future__ import annotations

from typing import Any

import casadi as ca
import numpy as np

from ..aero.bem import aerodyn_theta
from ..structure.blade_points import blade_point_kinematics, blade_point_loads, blade_point_shapes
from ..structure.turbine import BLADE_LOAD_INPUTS
from .compose import WIRED_INPUTS, Graph, actuator_states
from .tower_compose import nacelle_load_inputs, tower_line, tower_load_inputs

__all__ = ["BladeGraph", "blade_load_inputs", "aerodynamic_centres", "annulus_axes", "elastic_twist",
           "HUB_POINT_OUTPUTS", "INFLOW_OUTPUTS"]

#: Aerodynamic quantities of the ``blade_aero`` Function besides the structural loads.
HUB_POINT_OUTPUTS = ("rotor_force", "rotor_moment", "disk_velocity", "hub_wind")
#: The inflow of every node and the rotor-level inputs of ``BladeElementRotor.evaluate`` (``blade_inflow``).
INFLOW_OUTPUTS = ("node_vx", "node_vy", "node_r_local", "node_theta", "node_azimuth", "rotor_skew",
                  "rotor_skew_azimuth", "rotor_un_disk")


def blade_load_inputs(structure) -> tuple[str, ...]:
    """Names of the structure's blade-load inputs (``B{k}AeroFx`` …, ``{coordinate}AeroQ``)."""
    names = []
    for k in range(structure.turbine.number_of_blades):
        names += [f"B{k + 1}Aero{c}" for c in BLADE_LOAD_INPUTS]
        names += [f"{c}AeroQ" for c in structure.blade_coordinates(k)]
    return tuple(names)


def _cross(a: Any, B: Any) -> Any:
    """``a × B[:, j]`` for every column (a: 3 x 1 or 3 x N)."""
    if a.size2() == 1:
        a = ca.repmat(a, 1, B.size2())
    return ca.vertcat(a[1, :] * B[2, :] - a[2, :] * B[1, :], a[2, :] * B[0, :] - a[0, :] * B[2, :],
                      a[0, :] * B[1, :] - a[1, :] * B[0, :])


def _dot(A: Any, B: Any) -> Any:
    """Column-wise dot products (1 x N)."""
    return ca.sum1(A * B)


def _unit(A: Any) -> Any:
    return A / ca.repmat(ca.sqrt(ca.sum1(A**2)), 3, 1)


class BladeGraph(Graph):
    """Symbols and expressions of the blade-element operating turbine (see the module docstring)."""

    def extra_states(self) -> list[str]:
        extra = actuator_states(self.model)
        if not self.model.spins_freely:
            extra.append("GeAz")
        return extra + list(self.model.rotor.state_names)

    def wired_inputs(self) -> tuple[str, ...]:
        pitch = tuple(f"{n}{sfx}" for n in self.model.pitch_names for sfx in ("", "_d", "_dd"))
        structure = self.model.structure
        return (WIRED_INPUTS + pitch + blade_load_inputs(structure) + tower_load_inputs(structure)
                + nacelle_load_inputs(structure))

    def wind_inputs(self) -> tuple[str, ...]:
        return tuple(self.model.wind.inputs)

    def aero_parameters(self) -> tuple[str, ...]:
        return ("air_density",)

    def tower_wind(self, points: Any) -> Any:
        """The wind over the rotor (:mod:`.wind_inputs`) at ``points`` (3, N) [m/s]."""
        names = self.model.wind.inputs
        key = ("tower_wind", points.size2())
        f = self.model._parts.get(key)
        if f is None:                           # an SX Function: the wind's expressions are SX, the graph may be MX
            at, u = ca.SX.sym("points", 3, points.size2()), ca.SX.sym("wind", len(names))
            f = self.model._parts[key] = ca.Function(
                "tower_wind", [at, u], [self.model.wind.velocity(at, {n: u[i] for i, n in enumerate(names)})])
        return f(points, ca.vertcat(*[self.U[n] for n in names]))

    # ------------------------------------------------------------------ graph
    def _build_aero(self) -> None:
        model = self.model
        rotor = model.rotor
        f = self.aero_function()
        states = ca.vertcat(*[self.X[n] for n in rotor.state_names])
        wind = ca.vertcat(*[self.U[n] for n in model.wind.inputs])
        zero = self.structural_inputs(thrust=0.0, torque=0.0, **{n: 0.0 for n in blade_load_inputs(model.structure)})
        out = self._held(f, f(self.q, self.qd, zero, self.p_s, states, wind, self.P["air_density"]))
        names = blade_load_inputs(model.structure)
        self.loads = {"thrust": 0.0, "torque": 0.0, **{n: out["loads"][i] for i, n in enumerate(names)}}
        self.lag_rhs = out["states_dot"]
        ua = getattr(rotor, "unsteady", None)
        if ua is not None and ua.continuous:     # UA_Mod 4, 6: ż at the live states, the held part's inputs
            from ..aero.blade.ua_continuous import rates_function

            n_ua = len([n for n in rotor.state_names if "_ua_" in n])
            live = ca.vertcat(*[self.X[n] for n in rotor.state_names[-n_ua:]])
            self.lag_rhs = ca.vertcat(self.lag_rhs[:self.lag_rhs.numel() - n_ua],
                                      rates_function(ua, rotor.polars)(live, out["ua_inputs"]))
        self.blade_aero = out
        shaft = self._kinematics("shaft", zero)
        hub = self._kinematics("hub", zero)
        c1 = shaft["R"][:, 0]
        self.shaft_axis, self.hub_frame = c1, hub["R"]
        self.thrust = ca.dot(out["rotor_force"], c1)
        self.torque = ca.dot(out["rotor_moment"], c1)
        self.u_rel = ca.dot(out["disk_velocity"], c1)
        self.u_shaft = self.u_rel
        self.hub_wind_x = out["hub_wind"][0]
        self.skew = out["rotor_skew"]
        u = 0.5 * (self.u_rel + ca.sqrt(self.u_rel**2 + 0.02**2))
        self.aero = {"u": u}

    def _held(self, f: ca.Function, values: list) -> dict[str, Any]:
        """The outputs of the aerodynamics by name, as slices of the held symbol ``held_z`` whose value is
        ``held_value`` (every output of ``f``, stacked): the composition builds the full right-hand side by
        substitution (:meth:`close`) and the held-part split from the same graph (:mod:`mbsym.held`)."""
        self.held_value = ca.vertcat(*[ca.vec(v) for v in values])
        self.held_z = self.kind.sym("z", self.held_value.numel())
        out, k = {}, 0
        for name, v in zip(f.name_out(), values):
            out[name] = ca.reshape(self.held_z[k:k + v.numel()], v.size1(), v.size2())
            k += v.numel()
        return out

    def parts(self) -> dict[str, Any]:
        """``blade_inflow``: ``(x, u, p) ->`` :data:`INFLOW_OUTPUTS` (wake equilibrium, diagnostics), and with
        ``UA_Mod`` 4 or 6 ``node_ua_omega``: the sections' ``omega_z`` their states start from (``HGM_Steady``)."""
        names = INFLOW_OUTPUTS + tuple(k for k in ("node_ua_omega",) if k in self.blade_aero)
        f = ca.Function(f"{self.model.name}_blade_inflow", [self.x, self.u, self.p],
                        self.close([self.blade_aero[k] for k in names]), ["x", "u", "p"], list(names))
        return {"blade_inflow": f}

    def aero_function(self) -> ca.Function:
        """``blade_aero(q, qd, u_s, p_s, states, wind, rho)``: the aerodynamics as one SX Function (cached)."""
        parts = self.model._parts
        if "blade_aero" not in parts:
            parts["blade_aero"] = _AeroBuilder(self.model, self).function()
        return parts["blade_aero"]


class _AeroBuilder:
    """Builds the SX Function of the rotor's aerodynamics (module docstring, steps 1–3)."""

    def __init__(self, model, graph: BladeGraph) -> None:
        self.model, self.rotor, self.eom = model, model.rotor, model.structure.eom
        self.graph = graph

    def function(self) -> ca.Function:
        model, rotor, eom = self.model, self.rotor, self.eom
        q, qd = ca.SX.sym("q", eom.n_q), ca.SX.sym("qd", eom.n_q)
        u_s, p_s = ca.SX.sym("u_s", len(eom.inputs)), ca.SX.sym("p_s", eom.n_p)
        states = ca.SX.sym("states", len(rotor.state_names))
        wind = ca.SX.sym("wind", len(model.wind.inputs))
        rho = ca.SX.sym("rho")
        zeros = ca.SX.zeros(eom.n_q)
        pitch = ca.vertcat(*[u_s[eom.inputs.index(n)] for n in model.pitch_names])
        kin = self._kinematics(q, qd, u_s, p_s, zeros, pitch)
        U = {n: wind[i] for i, n in enumerate(model.wind.inputs)}
        hub_point = ca.DM([0.0, 0.0, float(model.turbine.hub_height)])
        W = model.wind.velocity(ca.horzcat(kin["r_ac"], hub_point), U)
        n = kin["r"].size2()
        sector = getattr(model, "sector_average", None)
        if sector is not None:                                  # AeroDyn's SectAvg (aero/sector_average.py)
            hub = (kin["hub"]["r"], kin["hub"]["R"][:, 0])
            W = ca.horzcat(sector.average(model.wind.velocity(sector.points(kin["r_ac"], *hub), U)), W[:, n:])
        tower = model.tower_aero
        if tower is not None and tower.disturbs_inflow:          # AeroDyn's TwrPotent, TwrShadow (aero/tower.py)
            f = eom.point_kinematics("tower")
            line = tower_line(model, dict(zip(f.name_out(), f(q, qd, zeros, u_s, p_s))), q, qd)
            W = ca.horzcat(W[:, :n] + tower.disturbance(kin["r_ac"], W[:, :n], **line), W[:, n:])
        rel = W[:, :n] - kin["v_ac"]
        frames = self._frames(kin, rel)
        per_node = ca.repmat(pitch.T, rotor.n_nodes, 1)[:] if pitch.numel() > 1 else pitch      # blade by blade
        twist = ca.DM(np.tile(np.asarray(rotor.twist, dtype=float), rotor.n_blades)).T
        curve = ca.DM(np.tile(np.asarray(rotor.curve_angle, dtype=float), rotor.n_blades)).T
        theta = (aerodyn_theta(twist, curve, per_node.T, sin=ca.sin, cos=ca.cos, atan2=ca.atan2)
                 + elastic_twist(kin["slope"][0, :], kin["slope"][1, :], per_node.T))
        wind_rate = None
        if rotor.dbemt_mode and not rotor.dbemt_wind_rate or rotor.needs_ua_wind_rate:
            # the wind's rate along each node's path (DBEMT's rate term, UA's update: AeroDyn v5's wind copy)
            if sector is None:
                rate = model.wind.path_rate(kin["r_ac"], kin["v_ac"], U)
            else:                                               # the average's rate: the points turn with the node
                v = sector.velocities(kin["r_ac"], kin["v_ac"], kin["hub"]["r"], kin["hub"]["v"], kin["hub"]["R"][:, 0])
                rate = sector.average(model.wind.path_rate(sector.points(kin["r_ac"], *hub), v, U))
            wind_rate = (_dot(rate, frames["x_n"]).T, _dot(rate, frames["y_n"]).T)
        extra = {}
        if getattr(rotor, "unsteady", None) is not None and rotor.unsteady.continuous:
            # BEMT's omega_z: the section's rotation rate about the annulus z axis x_n × y_n (UA_Mod 4, 6)
            extra["ua_omega"] = _dot(kin["w_ac"], _pair_cross(frames["x_n"], frames["y_n"])).T
        aero = rotor.evaluate(frames["vx"].T, frames["vy"].T, frames["r_local"].T, theta.T, frames["azimuth"].T,
                              states, rho=rho, wind_rate=wind_rate, **frames["rotor"], **extra)
        force = frames["x_n"] * ca.repmat(aero["fn"].T, 3, 1) - frames["y_n"] * ca.repmat(aero["ft"].T, 3, 1)
        # AeroDyn (BEM_Mod 1, BEMT.f90 SetOutputsFromBEMT) puts the airfoil's pitching moment along the annulus z axis,
        # x_n × y_n: the coned root's span axis turned by the node's curve angle (not the bent or straight span
        # tangent); on the prebent IEA 15 MW the tangent lost 36 % of Cm's share of the rotor torque (0.15 %)
        moment = _pair_cross(frames["x_n"], frames["y_n"]) * ca.repmat(aero["m"].T, 3, 1)
        loads, rotor_force, rotor_moment = self._loads(kin, force, moment)
        outs = {"loads": ca.vertcat(*loads), "states_dot": aero["states_dot"], "rotor_force": rotor_force,
                "rotor_moment": rotor_moment, "disk_velocity": frames["disk_velocity"], "hub_wind": W[:, n],
                }
        if "ua_inputs" in aero:
            outs["ua_inputs"] = aero["ua_inputs"]
        if "ua_omega" in extra:                     # the rate HGM_Steady starts the states from (rest.py)
            outs["node_ua_omega"] = extra["ua_omega"]
        for key in ("alpha", "vrel", "phi", "axial_induction", "tangential_induction", "cl", "cd", "fn", "ft"):
            if key in aero:
                outs[f"node_{key}"] = aero[key]
        outs["node_vx"], outs["node_vy"] = frames["vx"].T, frames["vy"].T
        outs["node_r_local"], outs["node_theta"], outs["node_azimuth"] = frames["r_local"].T, theta.T, \
            frames["azimuth"].T
        for key, value in frames["rotor"].items():
            outs[f"rotor_{key}"] = value
        return ca.Function("blade_aero", [q, qd, u_s, p_s, states, wind, rho], list(outs.values()),
                           ["q", "qd", "u_s", "p_s", "states", "wind", "rho"], list(outs),
                           {"never_inline": True})      # cse: 10 s of build for 4 % fewer instructions

    def _kinematics(self, q, qd, u_s, p_s, qdd, pitch) -> dict[str, Any]:
        """Every node of every blade (columns blade by blade), and the hub and shaft frames.

        Besides the pitch-axis points (``r``, ``v``, ``tangent``, ``slope``: the structure's shapes), the
        aerodynamic centres where AeroDyn's nodes sit (``r_ac``, ``v_ac``: :func:`aerodynamic_centres`) and
        AeroDyn's local axes (``x_ann``, ``y_ann``: :func:`annulus_axes`)."""
        model, rotor, eom = self.model, self.rotor, self.eom
        cache = model._parts.setdefault("blade_shapes", {})
        rows = {"r": [], "v": [], "tangent": [], "slope": [], "r_ac": [], "v_ac": [], "w_ac": [], "x_ann": [],
                "y_ann": []}
        offsets = np.vstack([rotor.curve_ac, rotor.sweep_ac])
        self.blades = []
        for k in range(rotor.n_blades):
            shapes = cache.get(k)
            if shapes is None:
                shapes = cache[k] = blade_point_shapes(model.structure, k, rotor.span)
            f = eom.point_kinematics(f"blade{k + 1}")
            frame = dict(zip(f.name_out(), f(q, qd, qdd, u_s, p_s)))
            idx = [eom.coordinates.index(c) for c in shapes.coordinates]
            qe, qde = (q[idx], qd[idx]) if idx else (ca.SX(0, 1), ca.SX(0, 1))
            kin = blade_point_kinematics(shapes, frame, qe, qde)
            self.blades.append((shapes, frame, kin))
            kin = {**kin, **aerodynamic_centres(shapes, frame, kin, qde, offsets)}
            beta = pitch[k] if pitch.numel() > 1 else pitch[0]
            kin["x_ann"], kin["y_ann"] = annulus_axes(frame["R"], kin["tangent"], beta, rotor.curve_angle)
            for key in rows:
                rows[key].append(kin[key])
        out = {key: ca.horzcat(*v) for key, v in rows.items()}
        for body in ("hub", "shaft"):
            f = eom.point_kinematics(body)
            out[body] = dict(zip(f.name_out(), f(q, qd, qdd, u_s, p_s)))
        return out

    def _frames(self, kin: dict[str, Any], rel: Any) -> dict[str, Any]:
        """AeroDyn's local frames and inflow of every node (BEM_Mod = 1, ``Calculate_MeshOrientation_
        NoSweepPitchTwist``): ``Vx``, ``Vy`` along the annulus axes, the local radius of the aerodynamic
        centre from the shaft axis, the node's azimuth."""
        c1 = kin["shaft"]["R"][:, 0]
        apex = kin["hub"]["r"]
        n = kin["r"].size2()
        d = kin["r_ac"] - ca.repmat(apex, 1, n)
        d_perp = d - ca.repmat(c1, 1, n) * ca.repmat(_dot(ca.repmat(c1, 1, n), d), 3, 1)
        r_local = ca.sqrt(ca.sum1(d_perp**2))
        e_r = d_perp / ca.repmat(r_local, 3, 1)
        x_n, y_n = kin["x_ann"], kin["y_ann"]
        vx, vy = _dot(rel, x_n), _dot(rel, y_n)
        up = ca.DM([0.0, 0.0, 1.0]) - c1 * c1[2]
        up = up / ca.norm_2(up)
        side = ca.cross(c1, up)
        azimuth = ca.atan2(_dot(e_r, ca.repmat(side, 1, n)), _dot(e_r, ca.repmat(up, 1, n)))
        disk = ca.sum2(rel) / n
        rotor_inputs = self._rotor_inputs(c1, disk, up, side)
        return {"vx": vx, "vy": vy, "r_local": r_local, "x_n": x_n, "y_n": y_n, "azimuth": azimuth,
                "disk_velocity": disk, "rotor": rotor_inputs}

    def _rotor_inputs(self, c1: Any, disk: Any, up: Any, side: Any) -> dict[str, Any]:
        """Rotor-level inputs of ``evaluate``: skew of the disk-averaged relative flow and its azimuth (the
        blade azimuth, measured like ``azimuth``, at which a blade points along the flow's in-plane part),
        and the disk-averaged relative wind along the shaft."""
        along = ca.dot(disk, c1)
        cross = disk - c1 * along
        return {"skew": ca.atan2(ca.sqrt(ca.sumsqr(cross) + 1e-12), along),
                "skew_azimuth": ca.atan2(ca.dot(cross, side), ca.dot(cross, up)),
                "un_disk": along}

    def _loads(self, kin: dict[str, Any], force: Any, moment: Any) -> tuple[list, Any, Any]:
        rotor = self.rotor
        loads, cols, arms = [], rotor.n_nodes, []
        # AeroDyn's loads act at the aerodynamic centres: BlCrvAC along j1 (downwind at zero pitch), BlSwpAC along j2
        offsets = np.vstack([rotor.curve_ac, rotor.sweep_ac, np.zeros(cols)])
        for k, (shapes, frame, bk) in enumerate(self.blades):
            sl = slice(k * cols, (k + 1) * cols)
            out = blade_point_loads(bk, frame["R"], force[:, sl], moment[:, sl], rotor.node_weights, offsets=offsets)
            loads += ca.vertsplit(out["F"]) + ca.vertsplit(out["M"]) + list(out["Q"])
            arms.append(frame["R"] @ ca.DM(offsets))
        w = ca.repmat(ca.DM(np.tile(np.asarray(rotor.node_weights, dtype=float), rotor.n_blades)).T, 3, 1)
        apex = kin["hub"]["r"]
        d = kin["r"] - ca.repmat(apex, 1, kin["r"].size2()) + ca.horzcat(*arms)
        total_force = ca.sum2(force * w)
        total_moment = ca.sum2(_pair_cross(d, force * w) + moment * w)
        return loads, total_force, total_moment


def aerodynamic_centres(shapes, frame: dict[str, Any], kin: dict[str, Any], qde: Any, offsets) -> dict[str, Any]:
    """Positions and velocities of AeroDyn's nodes: the aerodynamic centres, off the pitch axis.

    AeroDyn places node ``j`` at ``(BlCrvAC, BlSwpAC, BlSpn)`` in the blade root's axes (AeroDyn.f90
    ``Init_u``) and OpenFAST's mesh mapping carries it rigidly with ElastoDyn's section: the offset ``o``
    turns with the blade and with the section's small bending rotation ``(−s_y, s_x, 0)`` (body axes,
    ``s`` the slopes). So ``r_ac = r + R o'`` with ``o' = o + (−s_y, s_x, 0) × o`` and ``v_ac = v + ω × R o'
    + R ((−ṡ_y, ṡ_x, 0) × o)``. The in-plane offset (``BlSwpAC``, −0.1 … −0.6 m on the NREL 5 MW) gives the
    node a radial velocity ``−Ω BlSwpAC`` (OpenFAST's ``B1N…STVz``, −0.7 m/s at 18 m of span) that the annulus
    normal, tilted by cone and flap slope, turns partly into ``Vx`` (:func:`annulus_axes`).

    Parameters
    ----------
    shapes : BladePointShapes
    frame : dict
        The blade body frame (``R`` body -> ground, ``w`` angular velocity [rad/s]).
    kin : dict
        :func:`~mbsym.wind.structure.blade_points.blade_point_kinematics` of the pitch-axis points.
    qde : SX (n_e,)
        The blade's elastic speeds, shape order.
    offsets : array_like (2, N)
        ``BlCrvAC``, ``BlSwpAC`` [m] along the body axes ``x``, ``y``.

    Returns
    -------
    dict
        ``r_ac``, ``v_ac`` (3, N), ground axes [m], [m/s]; ``w_ac`` (3, N): the section's angular velocity [rad/s]
        (the blade's plus the bending slopes' rates).
    """
    n = kin["r"].size2()
    o = ca.vertcat(ca.DM(np.asarray(offsets, dtype=float)), ca.DM.zeros(1, n))
    sx, sy = kin["slope"][0, :], kin["slope"][1, :]
    rate = [ca.DM.zeros(1, n), ca.DM.zeros(1, n)]
    for i in range(len(shapes.coordinates)):
        for a in range(2):
            rate[a] = rate[a] + ca.DM(shapes.slope[i][:, a].reshape(1, -1)) * qde[i]
    bend = ca.vertcat(-sy, sx, ca.SX.zeros(1, n))
    bend_d = ca.vertcat(-rate[1], rate[0], ca.SX.zeros(1, n))
    arm = frame["R"] @ (o + _pair_cross(bend, o))
    w = ca.repmat(frame["w"], 1, n)
    return {"r_ac": kin["r"] + arm, "v_ac": kin["v"] + _pair_cross(w, arm) + frame["R"] @ _pair_cross(bend_d, o),
            "w_ac": w + frame["R"] @ bend_d}


def annulus_axes(R: Any, tangent: Any, pitch: Any, curve_angle: Any = None) -> tuple[Any, Any]:
    """AeroDyn's local normal and tangential axes of the nodes of one blade (``BEM_Mod = 1``).

    AeroDyn (AeroDyn.f90 ``Calculate_MeshOrientation_NoSweepPitchTwist``) starts from the blade root's
    axes without pitch ``i1, i2, i3`` (``i1`` downwind of the coned root, ``i3`` along it) and turns them
    about ``i2`` by the y Euler angle θ₂ of the node (NWTC ``EulerExtract``); the live sweep of in-plane
    bending and the twist are left out. So the normal is ``x = cos θ₂ i1 − sin θ₂ i3`` and the in-plane axis
    is the root's ``y = i2``, whatever the node's in-plane deflection (``Vy`` against the rotation, ``Vx``
    downwind). The node's orientation is ElastoDyn's section ``S`` (relative to the unpitched root) carried
    through the node's reference orientation ``EulerConstruct(0, BlCrvAng, −BlTwist)`` (``Init_u``), so
    ``sin θ₂ = sin(BlCrvAng) S₁₁ + cos(BlCrvAng) S₃₁`` with ``S₃₁`` the deflected span direction's component
    along ``i1`` and ``S₁₁`` the section's normal's, ``cos β`` to first order in the bending slopes (a prebent
    blade's curve of −5° reduces its power by ~1.4 % at a given pitch: the IEA 15 MW).

    Parameters
    ----------
    R : SX (3, 3)
        The pitched blade frame, body -> ground (columns ``j1, j2, j3``; ``j1 = cos β i1 − sin β i2``,
        ``j2 = sin β i1 + cos β i2``).
    tangent : SX (3, N)
        Unit deflected span directions, ground axes.
    pitch : SX
        Blade pitch β [rad].
    curve_angle : array_like (N,), optional
        AeroDyn's ``BlCrvAng`` of the nodes [rad] (None or zeros: a straight blade).

    Returns
    -------
    x, y : SX (3, N)
        The normal and in-plane axes, ground axes.
    """
    n = tangent.size2()
    c, s = ca.cos(pitch), ca.sin(pitch)
    i1, i2, i3 = c * R[:, 0] + s * R[:, 1], -s * R[:, 0] + c * R[:, 1], R[:, 2]
    sin_y = ca.mtimes(i1.T, tangent)
    curve = np.zeros(n) if curve_angle is None else np.asarray(curve_angle, dtype=float).reshape(-1)
    if np.any(curve != 0.0):
        sin_y = ca.DM(np.sin(curve)).T * c + ca.DM(np.cos(curve)).T * sin_y
    cos_y = ca.sqrt(1.0 - sin_y**2)
    x = ca.repmat(i1, 1, n) * ca.repmat(cos_y, 3, 1) - ca.repmat(i3, 1, n) * ca.repmat(sin_y, 3, 1)
    return x, ca.repmat(i2, 1, n)


def elastic_twist(slope_x: Any, slope_y: Any, pitch: Any) -> Any:
    """The elastic part of AeroDyn's local twist angle θ [rad] of a node of a bent ElastoDyn blade.

    ElastoDyn orients a blade section by one small rotation (``SmllRotTrans``, an orthonormal matrix,
    ElastoDyn.f90 ``SetCoordSy``) about the axis ``(−s_y, s_x, 0)`` of the pitched blade axes ``j1, j2``,
    where ``s_x``, ``s_y`` are the bending slopes ``Φ' q`` along ``j1`` (out of plane) and ``j2``. AeroDyn
    (``BEM_Mod = 1``, AeroDyn.f90 ``Calculate_MeshOrientation_NoSweepPitchTwist``) takes θ as minus the
    z angle of the z-y-x Euler decomposition (NWTC ``EulerExtract``) of the section's orientation relative
    to the root without pitch. That angle is twist + pitch plus ``½ ω₁ ω₂``, where ``ω₁, ω₂`` are the
    rotation vector's components along the unpitched root axes ``i1, i2`` (``j1 = cos β i1 − sin β i2``,
    ``j2 = sin β i1 + cos β i2``, β the pitch): a second-order term that feathers a blade bent downwind
    and back (about 0.1–0.2° at 60 m of the NREL 5 MW at 4–6 m of tip deflection in OpenFAST's node
    output ``B1N…Theta``). With the slopes of the pitched axes (relative error ``ω₂²/2`` against AeroDyn's
    angle, below 1 % for slopes up to 0.12 rad; tests/wind/blade/test_blade_elastic_twist.py):

        ½ ω₁ ω₂ = ¼ sin 2β (s_x² − s_y²) − ½ cos 2β s_x s_y.

    Parameters
    ----------
    slope_x, slope_y : SX or float
        Bending slopes along ``j1`` and ``j2`` [rad].
    pitch : SX or float
        Blade pitch β [rad].

    Returns
    -------
    SX or float
        The elastic twist [rad], positive to feather (added to twist + pitch).
    """
    return 0.25 * ca.sin(2 * pitch) * (slope_x**2 - slope_y**2) - 0.5 * ca.cos(2 * pitch) * slope_x * slope_y


def _pair_cross(A: Any, B: Any) -> Any:
    return ca.vertcat(A[1, :] * B[2, :] - A[2, :] * B[1, :], A[2, :] * B[0, :] - A[0, :] * B[2, :],
                      A[0, :] * B[1, :] - A[1, :] * B[0, :])
