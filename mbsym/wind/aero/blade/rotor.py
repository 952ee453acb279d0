"""Blade-element aerodynamics of every node of every blade as CasADi SX expressions.

:class:`BladeElementRotor` is the contract between the AeroDyn 15 physics (BEMT with
``BEM_Mod = 1``, DBEMT, Pitt/Peters skewed wake) and a flexible multibody structure: the
integrator computes, per node, the relative flow velocity in the node's local frame, the local
radius and the twist + pitch angle; the rotor returns the loads per unit length and the time
derivatives of its dynamic-wake states. See docs/blade_aero.md for the model, the conventions
and the measured accuracy.

Vectors are SX columns over **all nodes of all blades, blade by blade** (length
``n = n_blades * n_nodes``; node ``j`` of blade ``b`` at ``b * n_nodes + j``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from types import MappingProxyType
from typing import Any, Mapping

import casadi as ca
import numpy as np

from ....exceptions import DimensionError, ParameterError, UnsupportedFeatureError
from ...deck.aerodyn import AeroDynInput, read_aerodyn
from ..bem import BEMRotor
from . import dbemt, rest, ua_continuous, unsteady
from .corrections import low_tsr_weight, skewed_wake
from .induction import A_LIMITS, AP_LIMITS, ElementData, induction, solve_phi
from .polars import NodePolars

__all__ = ["BladeElementRotor", "QS_GUESS_INDUCTION", "DEFAULT_NEWTON"]

#: Axial induction of the quasi-steady Newton start ``φ₀ = atan2(Vx (1 - a₀), Vy)``.
QS_GUESS_INDUCTION = 0.25
#: Default Newton steps: from ``a₀`` (quasi-steady) and from the DBEMT states' inflow angle. From the states two
#: steps leave 6e-4 of a (states off by 10-30 %) and zero at equilibrium; on ff14_flex against OpenFAST every
#: reported figure (ε, R², DELs, means) equals the 3-step run's, at ~13 % fewer instructions (benchmarks/README.md).
DEFAULT_NEWTON = {"quasi-steady": 4, "dbemt": 2}
_VX_EPS2 = 1e-6  # [m²/s²]: a = -v_x Vx / (Vx² + eps) instead of -v_x / Vx (relative error eps/Vx²)


def _dbemt_from_deck(aerodyn: AeroDynInput) -> tuple[int, float]:
    """``(DBEMT_Mod, tau1_const)`` as OpenFAST v5 runs the file (0: no dynamic wake)."""
    extra = dict(aerodyn.extra or {})
    try:
        mode = int(float(extra.get("DBEMT_Mod", 0)))
        tau = float(extra.get("tau1_const", 0.0))
    except ValueError as exc:
        raise ParameterError(f"{aerodyn.source}: DBEMT_Mod/tau1_const are not numbers ({exc}).") from None
    legacy = "WakeMod" in extra  # a legacy key: WakeMod = 1 turns DBEMT off, 2 on
    if aerodyn.wake_model == 2:
        return mode, tau
    if legacy and aerodyn.wake_model == 1:
        return 0, tau
    return mode, tau


@dataclass(frozen=True, eq=False)
class BladeElementRotor:
    """Per-node blade-element aerodynamics (AeroDyn 15 BEMT/DBEMT) as SX expressions.

    Build it with :meth:`from_aerodyn` or :meth:`from_openfast`.

    Attributes
    ----------
    bem : BEMRotor
        Blade geometry, polars and BEM options (the steady BEM's rotor, same data).
    dbemt_mode : int
        0 (quasi-steady: no states) or AeroDyn's DBEMT_Mod 1, 2, 3 (see :mod:`.dbemt`).
    tau1_const : float
        τ₁ [s] for DBEMT_Mod 1 and 3.
    polar_method : {"spline", "linear"}
        Airfoil polars (:mod:`.polars`): C² splines (default) or AeroDyn's linear.
    n_newton : int
        Newton steps of the induction solve in the graph.
    tip_radius : float
        Default rotor radius ``R_tip`` [m] (skew ``r/R``, DBEMT ``R``): the undeflected
        largest local radius (AeroDyn's ``rmax``) unless given.
    unsteady : UnsteadyNodes or None
        AeroDyn's unsteady airfoil aerodynamics ``UA_Mod = 3`` on these nodes (:mod:`.unsteady`); None: the
        static polars (``UA_Mod = 0``).
    ua_step_end_wind : bool
        As AeroDyn v5: UA's update sees the node's flow plus the wind's change along its path over the step
        (``wind_rate`` × ``DTAero``; :mod:`.unsteady`). False: the update sees the outputs' flow.
    dbemt_wind_rate : bool
        Whether the rate of the quasi-steady induced velocity caused by the wind changing along a
        node's path enters Øye's ``k τ₁ dv_s/dt`` (see :mod:`.dbemt`). Default (None) as AeroDyn
        v5: False for DBEMT_Mod 1 and 2 (both inputs of its finite-difference update are built
        with the wind of the step's end), True for 3 (its continuous form has no rate term).
    """

    bem: BEMRotor
    dbemt_mode: int = 0
    tau1_const: float = 0.0
    polar_method: str = "spline"
    n_newton: int | None = None
    tip_radius: float | None = None
    dbemt_wind_rate: bool | None = None
    unsteady: unsteady.UnsteadyNodes | None = None
    ua_step_end_wind: bool = True
    polars: NodePolars = field(init=False, repr=False)

    def __post_init__(self) -> None:
        if not isinstance(self.bem, BEMRotor):
            raise TypeError(f"BladeElementRotor.bem must be a BEMRotor; got {type(self.bem).__name__}.")
        if self.dbemt_mode not in (0, 1, 2, 3):
            raise ParameterError(f"dbemt_mode (DBEMT_Mod) must be 0 (quasi-steady), 1, 2 or 3; got "
                                 f"{self.dbemt_mode!r}.")
        if self.dbemt_mode in (1, 3) and not (math.isfinite(self.tau1_const) and self.tau1_const > 0):
            raise ParameterError(f"DBEMT_Mod {self.dbemt_mode} needs tau1_const > 0 [s]; got {self.tau1_const!r}.")
        n_newton = self.n_newton
        if n_newton is None:
            n_newton = DEFAULT_NEWTON["dbemt" if self.dbemt_mode else "quasi-steady"]
        if not (isinstance(n_newton, int) and 1 <= n_newton <= 50):
            raise ParameterError(f"n_newton must be an integer in [1, 50]; got {n_newton!r}.")
        object.__setattr__(self, "n_newton", n_newton)
        radius = self.bem.radius if self.tip_radius is None else self.tip_radius
        if not (isinstance(radius, (int, float)) and math.isfinite(radius) and radius > 0):
            raise ParameterError(f"tip_radius must be a positive length [m]; got {radius!r}.")
        object.__setattr__(self, "tip_radius", float(radius))
        wind_rate = self.dbemt_wind_rate
        if wind_rate is None:
            wind_rate = self.dbemt_mode not in (1, 2)
        if not isinstance(wind_rate, bool):
            raise ParameterError(f"dbemt_wind_rate must be True, False or None; got {self.dbemt_wind_rate!r}.")
        object.__setattr__(self, "dbemt_wind_rate", wind_rate)
        object.__setattr__(self, "polars", NodePolars(self.bem.polars, method=self.polar_method))
        object.__setattr__(self, "_cache", {})

    # ------------------------------------------------------------------ constructors
    @classmethod
    def from_aerodyn(cls, aerodyn: AeroDynInput, *, hub_radius: float, precone: float, n_blades: int,
                     tip_radius: float | None = None, dynamic_wake: bool | None = None,
                     polar_method: str = "spline", n_newton: int | None = None, ua_dt: float | None = None,
                     speed_of_sound: float | None = None) -> "BladeElementRotor":
        """The rotor of an AeroDyn 15 input (blade 1's data for all blades).

        Parameters
        ----------
        aerodyn : AeroDynInput
            From :func:`mbsym.wind.deck.aerodyn.read_aerodyn`.
        hub_radius, precone : float
            ElastoDyn HubRad [m] and PreCone [rad] (the Prandtl constants use the arc length
            from the rotor centre, as AeroDyn's ``zLocal``).
        n_blades : int
            Number of blades.
        tip_radius : float, optional
            ``R_tip`` [m]; default the undeflected largest local radius.
        dynamic_wake : bool, optional
            DBEMT on/off; default: as OpenFAST v5 runs the file (``Wake_Mod = 1`` with
            ``DBEMT_Mod > 0``).
        polar_method : {"spline", "linear"}, optional
        n_newton : int, optional
            Newton steps (default :data:`DEFAULT_NEWTON`).
        ua_dt, speed_of_sound : float, optional
            AeroDyn's step ``DTAero`` [s] and ``SpdSound`` [m/s]; needed with ``UA_Mod = 3`` (the file's own values
            when it gives numbers).

        Raises
        ------
        UnsupportedFeatureError
            Unsteady airfoil aerodynamics other than ``UA_Mod`` 3, 4 and 6 (:func:`.unsteady.unsteady_nodes`),
            ``Skew_Mod = -1``, frozen wake
            (``DBEMT_Mod = -1``), or anything :meth:`BEMRotor.from_aerodyn` refuses (BEM_Mod 2,
            OLAF).
        """
        problems = []
        if aerodyn.skew_model == -1:
            problems.append("Skew_Mod = -1 (the linearization-only orthogonal inflow: set Skew_Mod 0 or 1)")
        mode, tau = _dbemt_from_deck(aerodyn)
        if mode < 0 or mode > 3:
            problems.append(f"DBEMT_Mod = {mode} (only 0-3; -1 is the linearization's frozen wake)")
        if problems:
            raise UnsupportedFeatureError(f"{aerodyn.source}: the blade-element rotor does not model "
                                          + "; ".join(problems) + ".")
        bem = BEMRotor.from_aerodyn(aerodyn, hub_radius=hub_radius, precone=precone, n_blades=n_blades)
        if aerodyn.skew_model == 0:
            bem = _replace(bem, skew_correction=False)
        if dynamic_wake is not None:
            if not isinstance(dynamic_wake, bool):
                raise ParameterError(f"dynamic_wake must be True, False or None; got {dynamic_wake!r}.")
            if dynamic_wake and mode == 0:
                mode, tau = 2, tau
            mode = mode if dynamic_wake else 0
        ua_dt, speed_of_sound = _deck_number(aerodyn, "DTAero", ua_dt), _deck_number(aerodyn, "SpdSound",
                                                                                       speed_of_sound)
        ua = unsteady.unsteady_nodes(aerodyn, bem, n_blades, dt=ua_dt, speed_of_sound=speed_of_sound)
        return cls(bem, dbemt_mode=mode, tau1_const=tau, polar_method=polar_method, n_newton=n_newton,
                   tip_radius=tip_radius, unsteady=ua)

    @classmethod
    def from_openfast(cls, fst: str | Path, **options: Any) -> "BladeElementRotor":
        """The rotor of an OpenFAST deck: ElastoDyn HubRad, PreCone(1), NumBl; AeroDyn files.

        ``options`` are those of :meth:`from_aerodyn` (``tip_radius``, ``dynamic_wake``, ...). A deck whose graph
        would take more memory than the limit is refused first (:class:`~mbsym.exceptions.DeckMemoryError`,
        :func:`mbsym.wind.deck.budget.deck_memory_estimate` with ``aero="blade"``).
        """
        from ...deck.budget import check_deck_memory
        from ...deck.openfast import read_openfast

        params = read_openfast(fst)
        aerodyn_file = params.source_files.get("aerodyn")
        if aerodyn_file is None:
            raise ParameterError(f"{fst}: the deck names no AeroDyn file (CompAero must be 2 and AeroFile "
                                 "must exist).")
        check_deck_memory(fst, aero="blade", run=False)       # the graph, before it is built
        aerodyn = read_aerodyn(aerodyn_file, n_blades=params.number_of_blades)
        defaults = {"ua_dt": params.simulation.time_step,
                    "speed_of_sound": _number(params.simulation.extra.get("SpdSound"))}
        return cls.from_aerodyn(aerodyn, hub_radius=params.hub_radius, precone=params.precone[0],
                                n_blades=params.number_of_blades, **(defaults | options))

    # ------------------------------------------------------------------ geometry
    @property
    def n_blades(self) -> int:
        """Number of blades."""
        return self.bem.n_blades

    @property
    def n_nodes(self) -> int:
        """Nodes per blade (AeroDyn NumBlNds)."""
        return int(self.bem.span.size)

    @property
    def span(self) -> np.ndarray:
        """AeroDyn BlSpn [m]: distance from the blade root along the pitch axis."""
        return self.bem.span

    @property
    def chord(self) -> np.ndarray:
        """Chord [m] per node."""
        return self.bem.chord

    @property
    def twist(self) -> np.ndarray:
        """Aerodynamic twist [rad] per node (AeroDyn sign: positive to feather)."""
        return self.bem.twist

    @property
    def curve_ac(self) -> np.ndarray:
        """BlCrvAC [m]: out-of-plane offset of the aerodynamic centre (where the loads act)."""
        return self.bem.curve_ac

    @property
    def curve_angle(self) -> np.ndarray:
        """BlCrvAng [rad]: the node's out-of-plane curve angle (AeroDyn tilts its annulus by it)."""
        return self.bem.curve_angle

    @property
    def sweep_ac(self) -> np.ndarray:
        """BlSwpAC [m]: in-plane offset of the aerodynamic centre, positive towards the trailing edge."""
        return self.bem.sweep_ac

    @property
    def local_radius(self) -> np.ndarray:
        """Undeflected local radius of each node [m] (AeroDyn's initial ``rLocal``)."""
        return self.bem.local_radius

    @property
    def node_weights(self) -> np.ndarray:
        """Trapezoid weights [m] on the distances between the (undeflected) aerodynamic centres.

        ``Σ_j w_j f_j`` is the integral of a per-length load ``f`` linear between the nodes:
        what AeroDyn's Line2 load mesh carries (its mapping to ElastoDyn's point loads
        preserves this resultant).
        """
        length = self.bem._geometry["length"]  # type: ignore[attr-defined]
        w = np.zeros(self.n_nodes)
        w[:-1] += 0.5 * length
        w[1:] += 0.5 * length
        return w

    @property
    def options(self) -> Mapping[str, Any]:
        """The AeroDyn options used (read-only mapping)."""
        b = self.bem
        return MappingProxyType({
            "tip_loss": b.tip_loss, "hub_loss": b.hub_loss, "tangential_induction": b.tangential_induction,
            "axial_drag": b.axial_drag, "tangential_drag": b.tangential_drag,
            "pitching_moment": b.pitching_moment, "skew_correction": b.skew_correction,
            "skew_factor": b.skew_factor, "low_tsr_blend": b.low_tsr_blend, "dbemt_mode": self.dbemt_mode,
            "tau1_const": self.tau1_const, "polar_method": self.polar_method, "n_newton": self.n_newton,
            "tip_radius": self.tip_radius, "dbemt_wind_rate": self.dbemt_wind_rate})

    @property
    def needs_ua_wind_rate(self) -> bool:
        """Whether :meth:`evaluate` uses ``wind_rate`` for UA's update (UA on, ``ua_step_end_wind``)."""
        return self.unsteady is not None and self.ua_step_end_wind

    @property
    def state_names(self) -> tuple[str, ...]:
        """Names of the dynamic-wake states (:mod:`.dbemt`; none when quasi-steady), then of the unsteady
        airfoil states (:mod:`.unsteady`; none without UA)."""
        wake = dbemt.state_names(self.n_blades, self.n_nodes) if self.dbemt_mode else ()
        if self.unsteady is None:
            return wake
        ua = self.unsteady
        return wake + unsteady.state_names([(int(i) // self.n_nodes, int(i) % self.n_nodes) for i in ua.index],
                                           ua.mode)

    def __repr__(self) -> str:
        wake = f"DBEMT_Mod {self.dbemt_mode}" if self.dbemt_mode else "quasi-steady"
        return (f"BladeElementRotor(B={self.n_blades}, {self.n_nodes} nodes, R={self.tip_radius:.4f} m, {wake}, "
                f"polars={self.polar_method}, n_newton={self.n_newton})")

    # ------------------------------------------------------------------ evaluation
    def evaluate(self, vx: Any, vy: Any, r_local: Any, theta: Any, azimuth: Any, states: Any = None, *,
                 rho: Any, skew: Any = 0.0, skew_azimuth: Any = 0.0, tip_radius: Any = None,
                 tsr: Any = None, un_disk: Any = None, wind_rate: Any = None,
                 ua_omega: Any = None) -> dict[str, Any]:
        """Loads per unit length, state derivatives and diagnostics of every node (SX).

        Parameters
        ----------
        vx, vy, r_local, theta : SX (or array) column, length n
            Relative flow velocity along the local normal ``x_n`` (downwind positive) and in the
            local rotor plane against the rotation [m/s]; distance from the rotor axis [m];
            twist + pitch (+ elastic torsion) [rad], AeroDyn's sign.
        azimuth : SX (or array), length n_blades or n
            Blade azimuth ψ [rad], any convention shared with ``skew_azimuth`` (only the skewed-wake
            correction uses it).
        states : SX column, length ``len(state_names)``
            The DBEMT states (None or empty when quasi-steady).
        rho : SX or float
            Air density [kg/m^3].
        skew : SX or float, optional
            χ₀ >= 0 [rad]: angle between the disk-averaged relative wind and the shaft axis.
        skew_azimuth : SX or float, optional
            ψ_w [rad]: the azimuth at which a blade points along the in-plane component of that
            wind (docs/blade_aero.md).
        tip_radius : SX or float, optional
            ``R_tip`` [m] (default :attr:`tip_radius`).
        tsr : SX or float, optional
            Rotor tip-speed ratio ``Ω R / U_n``; when given, AeroDyn's low-TSR blend of the
            induction (TSR 1 to 2) is applied, else not.
        un_disk : SX or float, optional
            Disk-averaged relative wind along the shaft [m/s] for DBEMT_Mod 2's τ₁; default the
            mean of ``vx`` over all nodes.
        wind_rate : pair of SX columns, optional
            The rates of ``vx`` and ``vy`` [m/s²] caused by the wind changing along each node's
            path (the wind's own change in time and its change across the node's motion). Used
            when :attr:`dbemt_wind_rate` is False: that part of ``dv_s/dt`` is taken out of Øye's
            rate term (:mod:`.dbemt`). None: no such rate is known, the whole rate stays in. With UA
            (:attr:`ua_step_end_wind`) the update's flow gets ``DTAero`` times it (:mod:`.unsteady`).
        ua_omega : SX column, length n, optional
            ``UA_Mod`` 4, 6: each node's section rotation rate about AeroDyn's annulus z axis [rad/s] (BEMT's
            ``omega_z``; :mod:`.ua_continuous`); default 0.

        Returns
        -------
        dict of str to SX
            ``fn``, ``ft`` [N/m], ``m`` [N m/m], ``states_dot`` (empty when quasi-steady), and
            ``alpha``, ``phi`` [rad], ``vrel`` [m/s], ``axial_induction``, ``tangential_induction``,
            ``cl``, ``cd``, ``cm``, ``cx``, ``cy``, ``axial_induction_qs``,
            ``tangential_induction_qs``, ``tau1`` [s].
        """
        n = self.n_blades * self.n_nodes
        vx, vy, r_local, theta = (self._column(v, n, name) for v, name in
                                  ((vx, "vx"), (vy, "vy"), (r_local, "r_local"), (theta, "theta")))
        states, ua_states = self._split_states(self._states(states))
        tip_radius = self.tip_radius if tip_radius is None else tip_radius
        rate = ua_rate = None
        if wind_rate is not None and (self.dbemt_mode and not self.dbemt_wind_rate or self.needs_ua_wind_rate):
            given = tuple(self._column(v, n, name) for v, name in zip(wind_rate, ("wind_rate[0]", "wind_rate[1]")))
            rate = given if self.dbemt_mode and not self.dbemt_wind_rate else None
            ua_rate = given if self.needs_ua_wind_rate else None
        a_qs, ap_qs = self._quasi_steady(vx, vy, r_local, theta, states)
        out: dict[str, Any] = {"axial_induction_qs": a_qs, "tangential_induction_qs": ap_qs,
                               "states_dot": ca.SX(0, 1), "tau1": ca.SX(0)}
        a, ap = a_qs, ap_qs
        fixed = np.tile(self.bem._geometry["fixed"], self.n_blades)  # type: ignore[attr-defined]
        if self.dbemt_mode:
            un = ca.sum1(vx) / n if un_disk is None else un_disk
            tau_1 = dbemt.tau1(self.dbemt_mode, self.tau1_const, a_qs, self._disk_weights(), tip_radius, un)
            ratio = r_local / tip_radius if self.dbemt_mode == 2 else \
                np.tile(self.local_radius, self.n_blades).reshape(-1, 1) / self.bem.radius
            v_s = ca.horzcat(-a_qs * vx, ap_qs * vy)
            v_s_rate = None           # AeroDyn's v_s(t) = -a(φ(t)) Vx(t + Δt): the wind's rate of Vx, Vy only
            if rate is not None:
                v_s_rate = ca.horzcat(-a_qs * rate[0], ap_qs * rate[1])
            out["states_dot"] = dbemt.derivatives(states, v_s, tau_1, ratio, wind_rate=v_s_rate)
            out["tau1"] = tau_1
            x = ca.reshape(states, 4, -1).T
            a_dyn = ca.fmin(ca.fmax(-x[:, 0] * vx / (vx**2 + _VX_EPS2), A_LIMITS[0]), A_LIMITS[1])
            ap_dyn = ca.fmin(ca.fmax(x[:, 1] * vy / (vy**2 + _VX_EPS2), AP_LIMITS[0]), AP_LIMITS[1])
            keep = ca.DM(fixed.astype(float))
            a = keep * a_qs + (1 - keep) * a_dyn
            ap = keep * ap_qs + (1 - keep) * ap_dyn
        if self.bem.skew_correction and not _is_zero(skew):
            psi = self._per_node(azimuth, n)
            sin_psi_s = ca.cos(psi - skew_azimuth)
            skewed = skewed_wake(a, skew, sin_psi_s, r_local / tip_radius, self.bem.skew_factor)
            keep = ca.DM(fixed.astype(float))
            a = keep * a + (1 - keep) * skewed
        if tsr is not None and self.bem.low_tsr_blend:
            weight = low_tsr_weight(tsr)
            a, ap = a * weight, ap * weight
        loads = self._loads(vx, vy, theta, a, ap, rho, ua_states, ua_rate, ua_omega)
        out["states_dot"] = ca.vertcat(out["states_dot"], loads.pop("ua_states_dot"))
        out.update(loads)
        return out

    def _loads(self, vx: Any, vy: Any, theta: Any, a: Any, ap: Any, rho: Any, ua_states: Any = None,
               ua_rate: Any = None, ua_omega: Any = None) -> dict[str, Any]:
        """Loads and diagnostics at the final inductions (AeroDyn's SetOutputsFromBEMT, BEM_Mod 1), with the
        unsteady airfoil coefficients on the UA nodes."""
        n = self.n_blades * self.n_nodes
        ux, uy = vx * (1.0 - a), vy * (1.0 + ap)
        phi = ca.atan2(ux, uy)
        alpha = phi - theta
        coef = self.polars(alpha, np.tile(np.arange(self.n_nodes), self.n_blades))
        cl, cd, cm = coef["cl"], coef["cd"], coef["cm"]
        ua_dot, ua_inputs = ca.SX(0, 1), None
        if self.unsteady is not None:
            ua = self.unsteady
            idx = [int(i) for i in ua.index]
            speed = ca.sqrt(ux[idx]**2 + uy[idx]**2)
            update = None
            if ua_rate is not None:            # AeroDyn v5: the update sees the wind of the step's end (.unsteady)
                ux_u, uy_u = ux[idx] + ua.dt * ua_rate[0][idx], uy[idx] + ua.dt * ua_rate[1][idx]
                update = (ca.atan2(ux_u, uy_u) - theta[idx], ca.sqrt(ux_u**2 + uy_u**2))
            if ua.continuous:                                  # UA_Mod 4, 6: continuous states (.ua_continuous)
                w = ca.SX.zeros(len(idx), 1) if ua_omega is None else self._column(ua_omega, n, "ua_omega")[idx]
                chain = ua_continuous.evaluate(ua, self.polars, alpha[idx], speed, w, ua_states,
                                               None if update is None else (*update, w))
                chain["inputs"] = ca.vertcat(*(update or (alpha[idx], speed)), w)
            elif self.polar_method == "spline":                # one node's chain, mapped: a loop in the C code
                chain = unsteady.kelvin_chain_mapped(ua, alpha[idx], speed, ua_states, self.polars, update)
            else:
                static = self._static_polars(ua)
                chain = unsteady.kelvin_chain(ua, alpha[idx], speed, ua_states, static, lambda x: static(x)["cm"],
                                              update)
            cl, cd, cm = ca.SX(cl), ca.SX(cd), ca.SX(cm)
            cl[idx], cd[idx], cm[idx] = chain["cl"], chain["cd"], chain["cm"]
            ua_dot = chain["states_dot"]
            ua_inputs = chain.get("inputs")
        sin_phi, cos_phi = ca.sin(phi), ca.cos(phi)
        cx, cy = cl * cos_phi + cd * sin_phi, cl * sin_phi - cd * cos_phi
        vrel2 = ux**2 + uy**2
        chord = ca.DM(np.tile(self.chord, self.n_blades))
        q_c = 0.5 * rho * vrel2 * chord
        m = q_c * chord * cm if self.bem.pitching_moment else ca.SX.zeros(n, 1)
        return {"fn": q_c * cx, "ft": q_c * cy, "m": m, "alpha": alpha, "phi": phi, "vrel": ca.sqrt(vrel2),
                "axial_induction": a, "tangential_induction": ap, "cl": cl, "cd": cd, "cm": cm, "cx": cx,
                "cy": cy, "ua_states_dot": ua_dot, **({"ua_inputs": ua_inputs} if ua_inputs is not None else {})}

    def _static_polars(self, ua: unsteady.UnsteadyNodes):
        """``alpha (m, 1) -> {"cl", "cd", "cm"}`` of the UA nodes' static polars (the same polars as the BEM)."""
        nodes = [int(j) for j in ua.node]
        return lambda x: self.polars(x, nodes)

    def _quasi_steady(self, vx: Any, vy: Any, r_local: Any, theta: Any, states: Any) -> tuple[Any, Any]:
        """Quasi-steady ``(a, a')`` of every node (AeroDyn's limits; tip/hub nodes 1 and 0)."""
        g = self.bem._geometry  # type: ignore[attr-defined]
        b = self.bem
        fixed = np.tile(g["fixed"], self.n_blades)
        free = np.flatnonzero(~fixed).tolist()
        nodes = np.tile(np.arange(self.n_nodes), self.n_blades)[free]
        e = ElementData(vx=vx[free], vy=vy[free], sigma=b.n_blades * ca.DM(b.chord[nodes]) / (2 * math.pi * r_local[free]),
                        tip_const=np.tile(g["tip_const"], self.n_blades)[free].reshape(-1, 1),
                        hub_const=np.tile(g["hub_const"], self.n_blades)[free].reshape(-1, 1), nodes=nodes,
                        tip_loss=b.tip_loss, hub_loss=b.hub_loss, tangential_induction=b.tangential_induction,
                        axial_drag=b.axial_drag, tangential_drag=b.tangential_drag)
        if self.dbemt_mode:  # inflow angle of the induction the states hold
            x = ca.reshape(states, 4, -1).T
            guess = ca.atan2(e.vx + x[free, 0], e.vy + x[free, 1])
        else:
            guess = ca.atan2(e.vx * (1.0 - QS_GUESS_INDUCTION), e.vy)
        phi = solve_phi(guess, e, self.polars, theta[free], n_newton=self.n_newton)
        need_cd = b.axial_drag or b.tangential_drag
        coef = self.polars(phi - theta[free], nodes, lift_only=not need_cd)
        ind = induction(phi, coef["cl"], coef.get("cd"), e)
        a_free = ca.if_else(ind["valid"], ca.fmin(ca.fmax(ind["a"], A_LIMITS[0]), A_LIMITS[1]), 0.0)
        ap_free = ca.if_else(ind["valid"], ca.fmin(ca.fmax(ind["ap"], AP_LIMITS[0]), AP_LIMITS[1]), 0.0)
        n = fixed.size
        a, ap = ca.SX(ca.DM(fixed.astype(float))), ca.SX.zeros(n, 1)
        a[free] = a_free
        ap[free] = ap_free
        return a, ap

    # ------------------------------------------------------------------ numeric helpers
    def steady_states(self, vx: Any, vy: Any, r_local: Any, theta: Any, azimuth: Any = None, *,
                      tol: float = 1e-12, max_iter: int = 50, ua_omega: Any = None,
                      **ignored_rotor_inputs: Any) -> np.ndarray:
        """Equilibrium of the DBEMT states for numeric inputs (empty array when quasi-steady).

        At rest ``v = v_s`` and ``w = (1 - k) v_s`` whatever τ₁, τ₂ (and the skew, TSR and
        ``un_disk``, which do not enter DBEMT's input): the fixed point of the graph's own
        quasi-steady induction started from the states is found by iteration (the Newton
        solve is exact at its own root).

        Parameters
        ----------
        vx, vy, r_local, theta : array_like, length n
            As in :meth:`evaluate`, numbers.
        azimuth : ignored
            Accepted for symmetry with :meth:`evaluate` (the equilibrium does not depend on it).
        tol : float, optional
            Largest change of a state between iterations at convergence [m/s].
        max_iter : int, optional
        ua_omega : array_like, length n, optional
            The sections' rotation rate ``omega_z`` [rad/s] (as :meth:`evaluate`'s): the continuous UA models
            (``UA_Mod`` 4, 6) start from ``HGM_Steady`` at the 3/4-chord angle with it, as AeroDyn does at its
            first step; default 0.

        Returns
        -------
        ndarray, shape (len(state_names),)

        Raises
        ------
        DimensionError, ParameterError
            Wrong lengths, non-finite inputs, an unknown keyword, or no convergence.
        """
        unknown = set(ignored_rotor_inputs) - {"rho", "skew", "skew_azimuth", "tip_radius", "tsr", "un_disk"}
        if unknown:
            raise TypeError(f"steady_states() got unexpected keyword arguments {sorted(unknown)}.")
        n = self.n_blades * self.n_nodes
        args = [self._numeric(v, n, name) for v, name in ((vx, "vx"), (vy, "vy"), (r_local, "r_local"),
                                                           (theta, "theta"))]
        wake = rest.wake_states(self, args, tol, max_iter, QS_GUESS_INDUCTION) if self.dbemt_mode else np.zeros(0)
        if self.unsteady is None:
            return wake
        return np.concatenate([wake, rest.unsteady_states(self, args, azimuth, wake, ignored_rotor_inputs,
                                                          ua_omega)])

    def _disk_weights(self) -> np.ndarray:
        w = dbemt.integrate_weights(self.local_radius, self.n_blades)
        return np.tile(w, self.n_blades)

    # ------------------------------------------------------------------ input checks
    def _column(self, value: Any, n: int, name: str) -> Any:
        if isinstance(value, (ca.SX, ca.MX)):
            if value.shape != (n, 1):
                raise DimensionError(f"{name} has shape {value.shape}; expected ({n}, 1): one entry per node of "
                                     f"every blade ({self.n_blades} blades x {self.n_nodes} nodes), blade by blade.")
            if isinstance(value, ca.MX):
                raise TypeError(f"{name} is MX; BladeElementRotor builds SX expressions (pass SX symbols).")
            return value
        return ca.SX(ca.DM(self._numeric(value, n, name)))

    def _numeric(self, value: Any, n: int, name: str) -> np.ndarray:
        array = np.asarray(value, dtype=float).ravel()
        if array.size != n:
            raise DimensionError(f"{name} has {array.size} values; expected {n} (one per node of every blade: "
                                 f"{self.n_blades} blades x {self.n_nodes} nodes, blade by blade).")
        if not np.all(np.isfinite(array)):
            raise ParameterError(f"{name} must hold finite numbers.")
        return array

    def _split_states(self, states: Any) -> tuple[Any, Any]:
        """The DBEMT states (None when quasi-steady) and the UA states (None without UA)."""
        if self.unsteady is None:
            return states, None
        n_wake = 4 * self.n_blades * self.n_nodes if self.dbemt_mode else 0
        return (states[:n_wake] if self.dbemt_mode else None), states[n_wake:]

    def _states(self, states: Any) -> Any:
        n_states = len(self.state_names)
        if not self.dbemt_mode and self.unsteady is None:
            if states is not None and (isinstance(states, (ca.SX, ca.MX)) and states.numel() > 0
                                       or not isinstance(states, (ca.SX, ca.MX)) and np.size(states) > 0):
                raise DimensionError("this rotor is quasi-steady (no states); pass states=None or an empty vector.")
            return None
        if states is None:
            raise DimensionError(f"this rotor has {n_states} DBEMT and UA states (state_names); pass them.")
        return self._column(states, n_states, "states")

    def _per_node(self, azimuth: Any, n: int) -> Any:
        size = azimuth.numel() if isinstance(azimuth, (ca.SX, ca.MX)) else np.size(azimuth)
        if size == self.n_blades:
            column = ca.vec(azimuth) if isinstance(azimuth, ca.SX) else ca.DM(np.asarray(azimuth, float).ravel())
            return ca.vertcat(*[ca.repmat(column[b], self.n_nodes, 1) for b in range(self.n_blades)])
        if size == n:
            return self._column(azimuth, n, "azimuth")
        raise DimensionError(f"azimuth has {size} values; expected {self.n_blades} (one per blade) or {n} (per node).")


def _number(text: Any) -> float | None:
    """A deck value as a number, None if it is absent, "default" or not a number."""
    try:
        return float(str(text).strip().strip('"'))
    except (TypeError, ValueError):
        return None


def _deck_number(aerodyn: AeroDynInput, key: str, fallback: float | None) -> float | None:
    """AeroDyn's own ``key`` when the file gives a number (it overrides the glue code's), else ``fallback``."""
    value = _number(dict(aerodyn.extra or {}).get(key))
    return fallback if value is None else value


def _is_zero(value: Any) -> bool:
    if isinstance(value, (ca.SX, ca.MX)):
        return value.is_zero()
    return float(value) == 0.0


def _replace(bem: BEMRotor, **changes: Any) -> BEMRotor:
    import dataclasses

    return dataclasses.replace(bem, **changes)
