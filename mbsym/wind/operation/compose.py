"""Build the :class:`mbsym.Dynamics` of an :class:`~.model.OperatingTurbine` (one CasADi graph).

The structure's equations ``M(q, u_s, p) q̈ = F(q, q̇, u_s, p)`` get their inputs ``u_s`` from
the new states and the rotor loads:

==============  ================================================================
``BlPitch``     pitch actuator state β; ``BlPitch_d``, ``BlPitch_dd`` = 0 (see below)
``GenTq``       generator torque actuator state
``RotThrust``   rotor thrust along the shaft (aero, or its lag state)
``RotTorq``     rotor torque about the shaft (aero, or its lag state)
``GeAz``        (GenDOF off) the azimuth state, turning at the parameter ``rotor_speed``
``PtfmFx…Mz``   (with ``model.platform``) the water's and the mooring's loads on the platform, the sea's
                excitation ``B1WvsFxi…Mzi`` and elevation ``Wave1Elev`` (inputs, after the others)
==============  ================================================================

The blades turn to the actuator's angle **without the pitch rate and acceleration in the structure's
kinematics**, as ElastoDyn does without ``PitchDOF`` (ElastoDyn.f90: the blade pitch enters ``SetCoordSy``
only; the pitch DOF's rate ``QDT(DOF_BP)`` stays out of every velocity and acceleration, and ``PitchIner`` is 0):
a pitching blade gets no ``β̇ × r`` velocity at its deflected nodes and no inertial loads from ``β̈``. With
flexible blades this is what OpenFAST's ``ff14_flex`` reference needs (benchmarks/README.md, "blade-validation":
R² of TTDspFA +0.02 to +0.04); the pitch actuator's own states keep β̇.

A floating turbine (``model.platform``, a :class:`~mbsym.wind.offshore.operating.FloatingPlatform`)
also adds A∞ (and its mooring lines' mass, when they have drag and inertia) to the platform block of
the mass matrix and its radiation states after the others.

so the first-order right-hand side is one expression of ``(x, u, p)``. Up to
:data:`~mbsym.equations.SYMBOLIC_SOLVE_MAX_DOF` structural DOFs everything is SX with the
symbolic solve of the structure's own ``rhs``; beyond, MX glue with a numeric linear solve
(as :class:`~mbsym.equations.EquationsOfMotion` does).
"""

from __future__ import annotations

from typing import Any

import casadi as ca
import numpy as np

from ...dynamics import Dynamics
from ...equations import SYMBOLIC_SOLVE_MAX_DOF
from ...exceptions import ModelDefinitionError
from ...held import HeldPart
from ...spd_solve import spd_solve
from .actuators import ACTUATOR_PARAMETERS, pitch_actuator_rhs, torque_actuator_rhs
from .channels import channel_rows
from .hss_brake import BRAKE_INPUT
from .tower_compose import nacelle_drag_loads, nacelle_load_inputs, tower_drag_loads, tower_load_inputs, tower_moves
from .units import input_units, state_units

__all__ = ["compose", "check_structure", "Graph", "WIRED_INPUTS"]

#: Structural inputs driven by the composition (the others stay inputs of the Dynamics).
WIRED_INPUTS = ("BlPitch", "BlPitch_d", "BlPitch_dd", "GenTq", "RotTorq", "RotThrust", "GeAz", "GeAz_d", "GeAz_dd",
                "RotMomY", "RotMomZ", "RotFrcY", "RotFrcZ")


class Graph:
    """Symbols and expressions of the composed model (SX or MX), shared by rhs and outputs."""

    def __init__(self, model, kind) -> None:
        s = model.structure
        eom = s.eom
        self.model, self.eom, self.kind = model, eom, kind
        self.platform = getattr(model, "platform", None)
        nq = eom.n_q
        platform_states = tuple(self.platform.state_names) if self.platform is not None else ()
        self.stc = getattr(model, "structural_controls", None)      # ServoDyn's StCs (.structural_control)
        stc_states = self.stc.state_names if self.stc is not None else ()
        self.states = tuple(eom.states) + tuple(self.extra_states()) + platform_states + stc_states
        wired = tuple(self.wired_inputs()) + (tuple(self.platform.inputs) if self.platform is not None else ())
        self.passthrough = tuple(n for n in eom.inputs if n not in wired)
        sea = tuple(getattr(self.platform, "sea_inputs", ())) if self.platform is not None else ()
        brake = (BRAKE_INPUT,) if getattr(model, "hss_brake", None) is not None else ()   # ServoDyn's HSS brake
        stc_inputs = self.stc.input_names if self.stc is not None else ()     # ServoDyn's prescribed StC loads
        self.inputs = tuple(self.wind_inputs()) + tuple(model.command_names) + self.passthrough + sea + brake \
            + stc_inputs
        extra_p = [*self.aero_parameters(), *ACTUATOR_PARAMETERS]
        if not model.spins_freely:
            extra_p.append("rotor_speed")
        self.parameters = tuple(eom.parameters) + tuple(extra_p)
        self.x = kind.sym("x", len(self.states))
        self.u = kind.sym("u", len(self.inputs))
        self.p = kind.sym("p", len(self.parameters))
        X = {n: self.x[i] for i, n in enumerate(self.states)}
        U = {n: self.u[i] for i, n in enumerate(self.inputs)}
        P = {n: self.p[i] for i, n in enumerate(self.parameters)}
        self.X, self.U, self.P = X, U, P
        self.q, self.qd = self.x[:nq], self.x[nq:2 * nq]
        self.p_s = self.p[:eom.n_p]
        self._build()

    # ------------------------------------------------------------------ names (hooks of the blade graph)
    def extra_states(self) -> list[str]:
        """States after the structure's: actuators, azimuth (GenDOF off), inflow states."""
        model = self.model
        extra = actuator_states(model)
        if not model.spins_freely:
            extra.append("GeAz")
        if model.dynamic_inflow is not None:
            extra += ["DBEMT_w", "DBEMT_v"]
        elif model.inflow_lag:
            extra += ["RotThrustLag", "RotTorqLag"]
        return extra

    def wired_inputs(self) -> tuple[str, ...]:
        """Structural inputs driven by the composition."""
        return WIRED_INPUTS + tower_load_inputs(self.model.structure) + nacelle_load_inputs(self.model.structure)

    def wind_inputs(self) -> tuple[str, ...]:
        """The wind inputs (first inputs of the Dynamics)."""
        return ("Wind1VelX",)

    def aero_parameters(self) -> tuple[str, ...]:
        return ("air_density", "cp_scale", "ct_scale")

    # ------------------------------------------------------------------ graph
    def _build(self) -> None:
        self._build_platform()
        self._build_drive()
        brake = getattr(self.model, "hss_brake", None)          # ServoDyn's HSS brake on the generator (.hss_brake)
        self.brake_torque = 0.0 if brake is None else \
            brake.torque_on_shaft(self.U[BRAKE_INPUT], self.generator_speed, self.model.brake_slip_speed)
        self._build_aero()
        self.loads.update(self._tower_loads())
        self.loads.update(self._nacelle_loads())
        self.u_s = self.structural_inputs(**self.loads)
        self.qdd = self._accelerations()
        self.xd = ca.vertcat(self.qd, self.qdd, *self._extra_rhs())

    def _build_platform(self) -> None:
        """The platform's loads (floating turbine) from the platform DOFs, their rates and the radiation states."""
        platform = self.platform
        self.platform_loads: dict[str, Any] = {}
        if platform is None:
            return
        from ..offshore.operating import platform_dofs

        index, fixed, self.platform_select = platform_dofs(self.eom.coordinates, self.model.turbine)
        self.platform_index = index            # None for a disabled DOF (held at its initial value, as ElastoDyn)
        qp = ca.vertcat(*[self.q[i] if i is not None else fixed[k] for k, i in enumerate(index)])
        vp = ca.vertcat(*[self.qd[i] if i is not None else 0.0 for i in index])
        xr = ca.vertcat(*[self.X[n] for n in platform.state_names]) if platform.state_names else self.kind(0, 1)
        sea = [self.U[n] for n in getattr(platform, "sea_inputs", ())]
        self.platform_terms = platform.loads(qp, vp, xr, *([ca.vertcat(*sea)] if sea else []))
        load = self.platform_terms["load"]
        self.platform_loads = {n: load[k] for k, n in enumerate(platform.inputs)}

    def _build_drive(self) -> None:
        """Actuators, rotor and generator speeds."""
        model, eom, X, U, P = self.model, self.eom, self.X, self.U, self.P
        width = model.saturation_width
        self.beta_dd = {n: pitch_actuator_rhs(X[n], X[f"{n}_d"], U[c], P, width)
                        for n, c in zip(model.pitch_names, model.command_names)}
        self.torque_d = torque_actuator_rhs(X["GenTq"], U["GenTqCom"], P, width)
        # rotor speed about the shaft [rad/s] (LSS) and generator speed relative to the nacelle (HSS)
        coords = eom.coordinates
        geaz_d = self.qd[coords.index("GeAz")] if model.spins_freely else P["rotor_speed"]
        hub_d = geaz_d + (self.qd[coords.index("DrTr")] if "DrTr" in coords else 0.0)
        self.rotor_speed, self.generator_speed = hub_d, model.gearbox_ratio * geaz_d

    def _build_aero(self) -> None:
        """Rotor-effective loads: thrust and torque on the hub from the relative wind along the shaft."""
        model, X, U, P = self.model, self.X, self.U, self.P
        beta, hub_d = X["BlPitch"], self.rotor_speed
        # structural inputs without loads: kinematics of the apex and the shaft axis
        zero_loads = self.structural_inputs(thrust=0.0, torque=0.0)
        hub = self._kinematics("hub", zero_loads)
        shaft = self._kinematics("shaft", zero_loads)
        c1 = shaft["R"][:, 0]
        self.shaft_axis = c1
        self.u_shaft = U["Wind1VelX"] * c1[0]                  # horizontal wind (U, 0, 0) along the shaft
        self.u_rel = self.u_shaft - ca.dot(hub["v"], c1)
        self.hub_wind_x = U["Wind1VelX"]
        rotor = model.rotor
        self.aero = rotor.loads(self.u_rel, hub_d, beta, P["air_density"], cp_scale=P["cp_scale"],
                                ct_scale=P["ct_scale"])
        scales = {"cp_scale": P["cp_scale"], "ct_scale": P["ct_scale"]}
        if model.dynamic_inflow is not None:
            state = ca.vertcat(X["DBEMT_w"], X["DBEMT_v"])
            self.lag_rhs, loads = model.dynamic_inflow.rhs(state, self.u_rel, hub_d, beta, P["air_density"], **scales)
            self.thrust, self.torque = loads["thrust"], loads["torque"]
            self.inflow_steady = ca.vertcat(*model.dynamic_inflow.steady_state(self.u_rel, hub_d, beta))
        elif model.inflow_lag:
            lag = ca.vertcat(X["RotThrustLag"], X["RotTorqLag"])
            self.lag_rhs, _ = rotor.inflow_lag_rhs(lag, self.u_rel, hub_d, beta, P["air_density"], **scales)
            self.thrust, self.torque = X["RotThrustLag"], X["RotTorqLag"]
            self.inflow_steady = ca.vertcat(self.aero["thrust"], self.aero["torque"])
        else:
            self.thrust, self.torque = self.aero["thrust"], self.aero["torque"]
        self.loads = {"thrust": self.thrust, "torque": self.torque, **self._disk_moments(shaft, hub)}

    def _disk_moments(self, shaft, hub) -> dict[str, Any]:
        """Aerodynamic moment of the rotor disk turning across the shaft (tilt and yaw rates), ``RotMomY/Z``, and
        its in-plane force against the hub moving across the shaft, ``RotFrcY/Z`` (comment below), and the
        disk's steady moment and in-plane force in the skewed relative flow when the rotor has a moment table
        (:meth:`~mbsym.wind.aero.rotor.RotorAero.disk_moment`: coned blades and Pitt and Peters' skewed wake).

        A rotation rate ``ω⊥`` of the shaft across its axis moves a blade element at radius ``r`` and
        azimuth ``ψ`` along the shaft at ``ω⊥ r cos ψ``: its load changes by ``(∂F/∂u) ω⊥ r cos ψ`` (the
        inflow frozen, as over a tower period), the thrust not at all (the cos ψ average is zero) but the
        moment by ``−K ω⊥`` with ``K = ½ Σ (∂F/∂u) r² = ½ (∂T/∂U) ⟨r²⟩``. ``∂T/∂U`` is the model's own
        thrust derivative (frozen with dynamic inflow); ``⟨r²⟩`` is the BEM's (:meth:`RotorAero.thrust_radius2
        <mbsym.wind.aero.rotor.RotorAero.thrust_radius2>`: 0.82-0.85 of ``(R² + r_hub²)/2``, the value for
        ``∂F/∂u ∝ r``, on the NREL 5 MW; that value without a BEM table). Without the moment the
        rotor-effective model damps the tower fore-aft mode at 14 m/s by 5.5 % against 7.3 % for the
        blade-element rotor (docs/identification.md).
        """
        if "RotMomY" not in self.eom.inputs:
            return {}
        c1, c2, c3 = shaft["R"][:, 0], shaft["R"][:, 1], shaft["R"][:, 2]
        thrust = self.thrust if self.model.dynamic_inflow is not None or not self.model.inflow_lag \
            else self.aero["thrust"]
        torque = self.torque if self.model.dynamic_inflow is not None or not self.model.inflow_lag \
            else self.aero["torque"]
        dT_dU = ca.jacobian(thrust, self.u)[:, self.inputs.index("Wind1VelX")] / c1[0]
        r2 = self.model.rotor.thrust_radius2(self.u_rel, self.rotor_speed, self.X["BlPitch"])
        if r2 is None:                                  # no BEM table (a Cp/Ct file): the derivative ∝ r
            r2 = 0.5 * (float(self.model.rotor.radius) ** 2 + float(self.model.turbine.hub_radius) ** 2)
        k = 0.5 * r2 * dT_dU
        w = shaft["w"]
        # the hub moving across the shaft at v⊥ moves each element along its rotation at v⊥ cos ψ: the
        # tangential forces change by (∂F_t/∂V_t) v⊥ cos ψ and add up to −c v⊥ in the rotor plane, with
        # c = −½ Σ ∂F_t/∂V_t = −½ (∂Q/∂Ω) / ⟨r²⟩ (∂Q/∂Ω = Σ r² ∂F_t/∂V_t; inflow frozen)
        dQ_dW = ca.jacobian(torque, self.x)[:, self.states.index("GeAz_d")] if "GeAz_d" in self.states else \
            ca.jacobian(torque, self.p)[:, self.parameters.index("rotor_speed")]
        c = -0.5 * dQ_dW / r2
        v = hub["v"]
        my, mz = -k * ca.dot(w, c2), -k * ca.dot(w, c3)
        # the steady moment of the disk in the skewed relative flow (coned blades, Pitt and Peters; aero.surfaces)
        rel = ca.vertcat(self.U["Wind1VelX"], 0.0, 0.0) - v
        steady = self.model.rotor.disk_moment(self.u_rel, rel - c1 * ca.dot(rel, c1), c1, self.rotor_speed,
                                              self.X["BlPitch"], self.P["air_density"])
        if steady is not None:
            my, mz = my + ca.dot(steady, c2), mz + ca.dot(steady, c3)
        # the tower's part of that moment and force (its inflow disturbance, aero.tower_average): along the disk's "up",
        # c3 (perpendicular to the shaft in the nacelle's vertical plane; c2 is lateral), and c1 × c3 = −c2
        tower = self.model.rotor.tower_loads(self.u_rel, self.rotor_speed, self.X["BlPitch"], self.P["air_density"])
        if tower is not None:
            my, mz = my - tower["moment_side"], mz + tower["moment_up"]
        fy, fz = -c * ca.dot(v, c2), -c * ca.dot(v, c3)
        if tower is not None:
            fy, fz = fy - tower["force_side"], fz + tower["force_up"]
        # and its steady in-plane force there (the loads' part in the rotor plane, aero.surfaces)
        force = self.model.rotor.disk_force(self.u_rel, rel - c1 * ca.dot(rel, c1), c1, self.rotor_speed,
                                            self.X["BlPitch"], self.P["air_density"])
        if force is not None:
            fy, fz = fy + ca.dot(force, c2), fz + ca.dot(force, c3)
        return {"RotMomY": my, "RotMomZ": mz, "RotFrcY": fy, "RotFrcZ": fz}

    def _tower_loads(self) -> dict[str, Any]:
        """AeroDyn's tower drag on the tower and platform DOFs (:mod:`.tower_compose`; zero when neither moves)."""
        names = tower_load_inputs(self.model.structure)
        if not names:
            return {}
        if not tower_moves(self.model.structure):
            return {n: 0.0 for n in names}
        unloaded = {n: 0.0 for n in self.eom.inputs if n not in self.U}     # positions and velocities need no load
        zero = self.structural_inputs(**{"thrust": 0.0, "torque": 0.0, **unloaded})
        frame = self._kinematics("tower", zero)
        return tower_drag_loads(self.model, frame, self.q, self.qd, self.tower_wind, self.P["air_density"])

    def _nacelle_loads(self) -> dict[str, Any]:
        """AeroDyn's nacelle drag at the yaw bearing (:mod:`.tower_compose`), from :meth:`tower_wind` there: kept as
        ``nacelle_drag`` (``force``, ``moment``, nacelle axes; ``R``) for the ``NcFd*`` channels."""
        self.nacelle_drag = None
        names = nacelle_load_inputs(self.model.structure)
        if not names:
            return {}
        unloaded = {n: 0.0 for n in self.eom.inputs if n not in self.U}
        frame = self._kinematics("nacelle", self.structural_inputs(**{"thrust": 0.0, "torque": 0.0, **unloaded}))
        out = nacelle_drag_loads(self.model, frame, self.tower_wind, self.P["air_density"])
        self.nacelle_drag = {"force": out.pop("force"), "moment": out.pop("moment"), "R": frame["R"]}
        return out

    def tower_wind(self, points: Any) -> Any:
        """The wind at ``points`` (3, N) [m/s]: the rotor-effective rung's hub wind at every height."""
        return ca.repmat(ca.vertcat(self.U["Wind1VelX"], 0.0, 0.0), 1, points.size2())

    def structural_inputs(self, *, thrust: Any, torque: Any, **loads: Any) -> Any:
        """The structure's input vector ``u_s`` (see the module docstring); ``loads`` by input name."""
        X, U, P = self.X, self.U, self.P
        values = {"GenTq": X["GenTq"] + self.brake_torque, "RotTorq": torque, "RotThrust": thrust, "RotMomY": 0.0,
                  "RotMomZ": 0.0,
                  "RotFrcY": 0.0, "RotFrcZ": 0.0, **{n: 0.0 for n in tower_load_inputs(self.model.structure)},
                  **{n: 0.0 for n in nacelle_load_inputs(self.model.structure)},
                  **self.platform_loads, **loads}
        for n in self.model.pitch_names:
            values.update({n: X[n], f"{n}_d": 0.0, f"{n}_dd": 0.0})         # ElastoDyn: quasi-static pitch
        if not self.model.spins_freely:
            values.update(GeAz=X["GeAz"], GeAz_d=P["rotor_speed"], GeAz_dd=0.0)
        rows = [values[n] if n in values else U[n] for n in self.eom.inputs]
        return ca.vertcat(*rows) if rows else self.kind(0, 1)

    def _kinematics(self, body: str, u_s, qdd=None) -> dict[str, Any]:
        """Position, orientation, velocity (and with ``qdd`` accelerations) of a body origin."""
        f = self.model._parts.get(f"kin_{body}")
        if f is None:
            f = self.eom.point_kinematics(body)
            self.model._parts[f"kin_{body}"] = f
        qdd = self.kind.zeros(self.eom.n_q) if qdd is None else qdd
        out = f(self.q, self.qd, qdd, u_s, self.p_s)
        return dict(zip(f.name_out(), out))

    def _accelerations(self) -> Any:
        f = self.eom.functions
        mass = f.mass_matrix
        M = mass(self.q, self.u_s, self.p_s) if mass.n_in() == 3 else mass(self.q, self.p_s)
        F = f.forcing(self.q, self.qd, self.u_s, self.p_s)
        if self.platform is not None:                  # A∞ on the platform DOFs (symbolic mass matrix)
            select = ca.DM(self.platform_select)
            added, bias = self._added_mass_terms(select)
            M, F = M + added, F - bias
            lines = self.platform_terms.get("mass")        # mooring lines' mass on the platform DOFs (if any)
            if lines is not None and not (isinstance(lines, (ca.SX, ca.MX, ca.DM)) and lines.is_zero()):
                M = M + ca.mtimes([select.T, lines, select])
        if self.stc is not None:                       # the StCs' loads, their q̈-dependent part in M
            from ..structure.structural_control import stc_terms

            x_stc = ca.vertcat(*[self.X[n] for n in self.stc.state_names])
            u_stc = ca.vertcat(*[self.U[n] for n in self.stc.input_names])
            self.stc_terms = stc_terms(self.stc, self.eom, self.q, self.qd, self.u_s, self.p_s, x_stc,
                                       self.P["gravity"], self.kind, u_stc=u_stc, structure=self.model.structure)
            M, F = M + self.stc_terms["mass"], F + self.stc_terms["force"]
        if self.kind is ca.SX:
            return ca.solve(M, F)
        if not self._symmetric_added_mass() or self.stc is not None:
            return ca.solve(M, F, "qr")        # WAMIT's A∞ as given, with its small asymmetry; the StCs' Euler terms
        return spd_solve(M, F)                 # M is symmetric positive definite (mbsym.spd_solve)

    def _added_mass_terms(self, select) -> tuple[Any, Any]:
        """``Jᵀ A∞ J`` and ``Jᵀ A∞ b`` on the DOFs: HydroDyn's ``−A∞ a`` with ``a = J q̈ + b`` the reference point's
        acceleration (``jac``, ``bias`` of the platform's loads: the Euler rates' angular acceleration, exact)."""
        A = ca.DM(self.platform.added_mass)
        jac, bias = self.platform_terms.get("jac"), self.platform_terms.get("bias")
        if jac is None:                                # a platform object without them: small angles
            return ca.sparsify(ca.mtimes([select.T, A, select])), ca.DM.zeros(select.size2())
        JS = ca.mtimes(jac, select)
        return ca.mtimes([JS.T, A, JS]), ca.mtimes([JS.T, A, bias])

    def _symmetric_added_mass(self) -> bool:
        """Whether the platform's A∞ (if any) is symmetric to rounding, so that M stays symmetric."""
        a = getattr(self.platform, "added_mass", None) if self.platform is not None else None
        if a is None:
            return True
        a = np.asarray(a, dtype=float)
        return bool(np.max(np.abs(a - a.T)) <= 1e-12 * max(np.max(np.abs(a)), 1e-300))

    def _extra_rhs(self) -> list:
        X = self.X
        rows = [r for n in self.model.pitch_names for r in (X[f"{n}_d"], self.beta_dd[n])] + [self.torque_d]
        if not self.model.spins_freely:
            rows.append(self.P["rotor_speed"])
        if hasattr(self, "lag_rhs"):
            rows.append(self.lag_rhs)
        if self.platform is not None and self.platform.state_names:
            xr_dot = self.platform_terms["xr_dot"]
            xr_acc = self.platform_terms.get("xr_acc")       # states driven by the platform's acceleration (SubDyn's
            if xr_acc is not None:                           # Craig-Bampton modes): + xr_acc (J q̈_p + b)
                ap = ca.vertcat(*[self.qdd[i] if i is not None else 0.0 for i in self.platform_index])
                xr_dot = xr_dot + ca.mtimes(xr_acc, ca.mtimes(self.platform_terms["jac"], ap)
                                            + self.platform_terms["bias"])
            rows.append(xr_dot)
        if self.stc is not None:
            rows.append(self.stc_terms["rates"](self.qdd))
        return rows

    def stc_channel_rows(self) -> list[tuple[str, str, Any]]:
        """ServoDyn's StC channels (``NStC1_XQ`` …; :mod:`.structural_control`), empty without StCs."""
        if self.stc is None:
            return []
        y = self.stc_terms["channels"](self.qdd)
        return [(n, u, y[k]) for k, (n, u) in enumerate(self.stc.channel_names())]

    def parts(self) -> dict[str, Any]:
        """Extra Functions the model keeps (by key in ``model._parts``)."""
        return {}

    #: The held symbol and its value (the blade-element graph's aerodynamics; None: nothing held).
    held_z: Any = None
    held_value: Any = None

    def close(self, exprs: list) -> list:
        """``exprs`` with the held symbol replaced by its value (unchanged when nothing is held)."""
        if self.held_z is None:
            return list(exprs)
        return ca.substitute(list(exprs), [self.held_z], [self.held_value])

    def kinematics_with_accelerations(self, body: str) -> dict[str, Any]:
        """Point kinematics of a body origin with the model's accelerations (for output channels)."""
        return self._kinematics(body, self.u_s, self.qdd)


def compose(model, graph: type | None = None) -> Dynamics:
    """The :class:`mbsym.Dynamics` of ``model`` (an :class:`~.model.OperatingTurbine`).

    ``graph`` is the :class:`Graph` class to build (default :class:`Graph`: the rotor-effective loads;
    :class:`~.blade_compose.BladeGraph` for blade-element aerodynamics).
    """
    check_structure(model)
    eom = model.structure.eom
    kind = ca.SX if eom.n_q <= SYMBOLIC_SOLVE_MAX_DOF else ca.MX
    g = (graph or Graph)(model, kind)
    opts = {"cse": True} if kind is ca.SX else {}
    rows = channel_rows(g) + g.stc_channel_rows()
    names = tuple(r[0] for r in rows)
    units = tuple(r[1] for r in rows)
    y = ca.vertcat(*[r[2] for r in rows])
    from .controllers import measurement_names
    measured_names = measurement_names(model)
    measured = ca.vertcat(*[y[names.index(n)] for n in measured_names])
    exprs = {"xd": g.xd, "y": y, "torque": g.torque, "measured": measured}
    if hasattr(g, "inflow_steady"):
        exprs["inflow_steady"] = g.inflow_steady
    closed = dict(zip(exprs, g.close(list(exprs.values()))))
    xup = [g.x, g.u, g.p]
    rhs = ca.Function(f"{model.name}_rhs", xup, [closed["xd"]], ["x", "u", "p"], ["xd"], opts)
    outputs = ca.Function(f"{model.name}_outputs", xup, [closed["y"]], ["x", "u", "p"], ["y"], opts)
    model._parts["aero_torque"] = ca.Function(f"{model.name}_aero_torque", xup, [closed["torque"]],
                                              ["x", "u", "p"], ["Q"], opts)
    model._parts["measurements"] = ca.Function(f"{model.name}_measurements", xup, [closed["measured"]],
                                               ["x", "u", "p"], ["y"], opts)
    model._parts["measurement_units"] = tuple(units[names.index(n)] for n in measured_names)
    model._parts["measurement_names"] = measured_names
    if "inflow_steady" in closed:
        model._parts["inflow_steady"] = ca.Function(f"{model.name}_inflow_steady", xup, [closed["inflow_steady"]],
                                                    ["x", "u", "p"], ["z"], opts)
    held = _held_part(model, g, y, measured, opts)
    model._parts.update(g.parts())
    model._parts["graph"] = g
    defaults = {**dict(eom.defaults), **_aero_defaults(model), **model.actuators.parameters()}
    if not model.spins_freely:
        defaults["rotor_speed"] = float(model.turbine.initial_conditions.rotor_speed)
    x0 = _deck_state(model, g)
    u0 = _input_defaults(model, g)
    wind = getattr(model, "wind", None)
    return Dynamics(rhs, states=g.states, inputs=g.inputs, parameters=g.parameters, defaults=defaults,
                    outputs=outputs, output_names=names, output_units=units, x0=x0, u0=u0, name=model.name, eom=eom,
                    held=held, state_units=state_units(g.states, eom.units),
                    input_units=input_units(g.inputs, wind.units() if wind is not None else None))


def _held_part(model, g: Graph, y: Any, measured: Any, opts: dict) -> HeldPart | None:
    """The split of the right-hand side at the graph's held symbol (blade-element aerodynamics), or None;
    the measurements with the held symbol are kept as ``model._parts["measurements_held"]``."""
    if g.held_z is None:
        return None
    xupz, names = [g.x, g.u, g.p, g.held_z], ["x", "u", "p", "z"]
    part = ca.Function(f"{model.name}_held_part", [g.x, g.u, g.p], [g.held_value], names[:3], ["z"], opts)
    rhs = ca.Function(f"{model.name}_held_rhs", xupz, [g.xd], names, ["xd"], opts)
    outputs = ca.Function(f"{model.name}_held_outputs", xupz, [y], names, ["y"], opts)
    model._parts["measurements_held"] = ca.Function(f"{model.name}_held_measurements", xupz, [measured], names,
                                                    ["y"], opts)
    return HeldPart(part, rhs, outputs, "blade-element aerodynamics")


def _input_defaults(model, g: Graph) -> list[float] | None:
    """Default inputs: the wind's (blade-element model), ServoDyn's commanded yaw at its neutral, zero otherwise."""
    wind, yaw = getattr(model, "wind", None), getattr(model, "yaw_control", None)
    if wind is None and yaw is None:
        return None
    values = {**(dict(wind.defaults) if wind is not None else {}), **({"YawPosCom": yaw.neutral} if yaw else {})}
    return [float(values.get(n, 0.0)) for n in g.inputs]


def _aero_defaults(model) -> dict[str, float]:
    if model.aero == "blade":
        rho = getattr(model.rotor, "air_density", None) or model.turbine.simulation.air_density or 1.225
        return {"air_density": float(rho)}
    return {"air_density": float(model.rotor.air_density), "cp_scale": 1.0, "ct_scale": 1.0}


def _deck_state(model, g: Graph) -> list[float]:
    """The deck's initial conditions; actuators at rest at the deck's pitch, zero torque and loads."""
    s = model.structure
    values = dict(zip(s.eom.states, s.initial_state()))
    for k, n in enumerate(model.pitch_names):
        values[n] = float(model.turbine.initial_conditions.blade_pitch[k])
    if not model.spins_freely:
        values["GeAz"] = s.initial_generator_azimuth()
    if g.stc is not None:
        values.update(zip(g.stc.state_names, g.stc.initial_state()))
    return [values.get(n, 0.0) for n in g.states]


#: Parameters the composition adds, for the clash check (aerodynamics, rotor speed).
_AERO_NAMES = ("air_density", "cp_scale", "ct_scale", "rotor_speed")


def actuator_states(model) -> list[str]:
    """The actuator states: per pitch actuator its angle and rate, then the generator torque."""
    return [s for n in model.pitch_names for s in (n, f"{n}_d")] + ["GenTq"]


def check_structure(model) -> None:
    """The structure drives what the composition needs and its parameter names do not clash with ours."""
    eom = model.structure.eom
    missing = [n for n in (*model.pitch_names, "RotThrust") if n not in eom.inputs]
    if missing:
        raise ModelDefinitionError(f"the structure lacks the inputs {missing} the operating turbine drives.")
    platform = getattr(model, "platform", None)
    if platform is not None:
        missing = [n for n in platform.inputs if n not in eom.inputs]
        if missing or not any(n in eom.coordinates for n in platform.coordinates):
            raise ModelDefinitionError(f"a floating platform needs at least one platform DOF and the platform's load "
                                       f"inputs; the structure lacks {missing or 'every platform DOF'}. Enable "
                                       "PtfmSgDOF … PtfmYDOF (dofs=…) or leave platform=None.")
    clash = sorted(set(eom.parameters) & (set(ACTUATOR_PARAMETERS) | set(_AERO_NAMES)))
    if clash:
        raise ModelDefinitionError(f"structural parameters {clash} clash with the operating turbine's parameters of "
                                   "the same names (aerodynamics, actuators, rotor_speed).")
