"""Quasi-steady rotor loads from performance surfaces, as CasADi expressions.

:class:`RotorAero` turns the thrust and torque surfaces ``ct(λ, β)`` and
``cq(λ, β)`` into the aerodynamic thrust ``T`` and torque ``Q`` on the hub:

* ``U`` = **relative** wind speed along the shaft: the wind component along the
  shaft minus the hub velocity along the shaft (so tower fore-aft motion gives
  aerodynamic damping).  For a horizontal wind ``U∞`` on a shaft tilted by ``τ``
  (deck tilt plus any tower-top or platform rotation): ``U = U∞ cos τ - v_hub·e_shaft``.
* ``λ = Ω R / U``, ``T = ½ ρ π R² U² ct``, ``Q = ½ ρ π R³ U² cq``, ``P = Ω Q``,
  ``cp = λ cq`` (so the aerodynamic power is exactly ``Ω Q``: power balances hold).
* ``R`` is the radius the surfaces are normalized with (the in-plane tip radius
  for mbsym's BEM surfaces, AeroDyn's ``rmax``; ROSCO's tables use the blade
  length of its DISCON.IN), ``ρ`` the air density.
* Thrust acts along the shaft (downwind positive), torque about the shaft (in the
  direction of rotation positive).
* Optional scale factors ``cp_scale`` (on cq, so torque and power) and
  ``ct_scale`` (on thrust), for identification.

For very small ``U`` (no wind, or the hub running with the wind) the model is not
physical; ``U`` is floored smoothly at ``u_min`` (default 0.01 m/s; relative
error ``(u_min/U)²`` elsewhere) so the expressions stay finite.  Outside the
table, the surfaces continue linearly.

**Dynamic inflow (optional).**  :meth:`RotorAero.inflow_lag_rhs` gives the
right-hand side of a first-order lag ``τ ẋ = y_qs - x`` on thrust and torque with
``τ = k R / U`` (``k`` = ``lag_factor``, default 1.1, Øye's order of magnitude):
a smoothing of fast load changes -- not the overshoot of a physical dynamic-inflow
model.  It is off unless the integrator adds the two states.

See docs/aero.md for the assumptions (uniform inflow over the disk, rigid rotor,
quasi-steady, azimuth-averaged) and what is left out.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import casadi as ca
import numpy as np

from ...exceptions import ParameterError
from ..deck.performance import PerformanceTable
from .interpolant import SurfaceSpline

__all__ = ["RotorAero", "UA_TIP_SPEED"]

#: Tip speed [m/s] at which the surfaces of a deck with ``UA_Mod = 3`` hold the airfoils' steady state: 90 m/s, tip
#: Mach 0.26, between the NREL 5 MW's 80 m/s and the IEA 15 MW's 95 m/s at rated (the steady state's Mach
#: sensitivity: tests/wind/aero/test_ua_steady.py).
UA_TIP_SPEED = 90.0


def _positive(value: Any, name: str) -> float:
    if not isinstance(value, (int, float)) or isinstance(value, bool) or \
            not math.isfinite(value) or value <= 0:
        raise ParameterError(f"RotorAero.{name} must be a positive finite number; got {value!r}.")
    return float(value)


@dataclass(frozen=True, eq=False)
class RotorAero:
    """Rotor thrust and torque from ct and cq surfaces (CasADi SX expressions).

    Attributes
    ----------
    table : PerformanceTable
        The surfaces (TSR × pitch [rad]).
    radius : float
        Rotor radius R the table is normalized with [m].
    air_density : float
        Default air density ρ [kg/m^3] (the deck's AirDens).
    precone, shaft_tilt : float
        Cone and shaft tilt of the deck [rad] (ElastoDyn signs); the surfaces already
        include them -- kept for the integrator (load direction, wind along the shaft).
    degree : int
        Spline degree, 3 (C²) or 5 (C⁴).
    u_min : float
        Smooth floor of the relative wind speed [m/s].
    lag_factor : float
        ``k`` of the optional inflow lag time constant ``τ = k R / U``.
    source : str or None
        Where the table came from.
    moment_table : DiskMomentTable or None
        The disk's steady moment per unit ``tan χ`` (:func:`~mbsym.wind.aero.surfaces.disk_moment_surface`;
        :meth:`disk_moment`); None (default) when the surfaces come without it (ROSCO's tables).
    tower_inflow : bool
        The surfaces hold the azimuth average of the tower's potential flow and shadow (AeroDyn's ``TwrPotent``,
        ``TwrShadow``: :mod:`~mbsym.wind.aero.tower_average`); default False.
    """

    table: PerformanceTable
    radius: float
    air_density: float = 1.225
    precone: float = 0.0
    shaft_tilt: float = 0.0
    degree: int = 3
    u_min: float = 0.01
    lag_factor: float = 1.1
    source: str | None = None
    moment_table: Any = field(default=None, repr=False)
    tower_inflow: bool = False
    spline: SurfaceSpline = field(init=False, repr=False)

    def __post_init__(self) -> None:
        if not isinstance(self.table, PerformanceTable):
            raise TypeError(f"RotorAero.table must be a PerformanceTable; got "
                            f"{type(self.table).__name__}.")
        for name in ("radius", "air_density", "u_min", "lag_factor"):
            object.__setattr__(self, name, _positive(getattr(self, name), name))
        for name in ("precone", "shaft_tilt"):
            value = getattr(self, name)
            if not isinstance(value, (int, float)) or not abs(value) < math.pi / 2:
                raise ParameterError(f"RotorAero.{name} must be an angle in (-90, 90) deg [rad]; "
                                     f"got {value!r}.")
        if not isinstance(self.tower_inflow, bool):
            raise TypeError(f"RotorAero.tower_inflow must be a bool; got {type(self.tower_inflow).__name__}.")
        object.__setattr__(self, "spline", SurfaceSpline.from_table(
            self.table, names=("ct", "cq"), degree=self.degree))
        if self.source is None:
            object.__setattr__(self, "source", self.table.source)
        moments = self.moment_table
        object.__setattr__(self, "_moment_spline", None if moments is None else SurfaceSpline.from_values(
            moments.tsr, moments.pitch, {"cw": moments.cw, "cp": moments.cp}, degree=self.degree))
        forces = None if moments is None or getattr(moments, "hw", None) is None else SurfaceSpline.from_values(
            moments.tsr, moments.pitch, {"hw": moments.hw, "hp": moments.hp}, degree=self.degree)
        object.__setattr__(self, "_force_spline", forces)
        r2 = None if moments is None else getattr(moments, "r2", None)
        object.__setattr__(self, "_r2_spline", None if r2 is None else SurfaceSpline.from_values(
            moments.tsr, moments.pitch, {"r2": r2}, degree=self.degree))
        tower = None if moments is None else getattr(moments, "tower", None)
        object.__setattr__(self, "_tower_spline", None if tower is None else SurfaceSpline.from_values(
            moments.tsr, moments.pitch, tower, degree=self.degree))

    # ------------------------------------------------------------------ constructors
    @classmethod
    def from_openfast(cls, fst: str | Path, *, tsr: Any = None, pitch: Any = None,
                      degree: int = 3, ua_tip_speed: float = UA_TIP_SPEED) -> "RotorAero":
        """Compute the surfaces of an OpenFAST deck with mbsym's BEM (a few seconds; twice that when the deck's
        tower disturbs the blade inflow, whose azimuth average the surfaces then hold, or its airfoils run
        ``UA_Mod = 3``, whose steady state they then hold: :mod:`.blade.ua_steady`).

        Parameters
        ----------
        fst : str or Path
            ``.fst`` with CompAero = 2 (AeroDyn 15).
        tsr, pitch : array_like, optional
            Grids (default :data:`~mbsym.wind.aero.surfaces.DEFAULT_TSR`,
            :data:`~mbsym.wind.aero.surfaces.DEFAULT_PITCH`).
        degree : int, optional
            Spline degree (3 or 5).
        ua_tip_speed : float, optional
            With ``UA_Mod = 3``: the tip speed [m/s] at which the airfoils' steady state is taken (its Mach number
            enters; :data:`UA_TIP_SPEED`).

        Raises
        ------
        DeckMemoryError
            Computing the surfaces would take more memory than the limit (~4.8 kB per AeroDyn blade node and
            grid point: :func:`mbsym.wind.deck.budget.deck_memory_estimate` with ``aero="rotor"``).
        UnsupportedFeatureError
            ``UA_Mod`` other than 0 and 3 (:func:`~mbsym.wind.aero.blade.unsteady.unsteady_nodes`).
        """
        from ..deck.aerodyn import read_aerodyn
        from ..deck.budget import check_deck_memory
        from ..deck.openfast import read_openfast
        from .bem import BEMRotor
        from .surfaces import DEFAULT_PITCH, DEFAULT_TSR, rotor_surfaces

        params = read_openfast(fst)
        aerodyn_file = params.source_files.get("aerodyn")
        if aerodyn_file is None:
            raise ParameterError(f"{fst}: the deck names no AeroDyn file (CompAero must be 2 and "
                                 "AeroFile must exist).")
        _positive(ua_tip_speed, "ua_tip_speed")
        points = np.size(DEFAULT_TSR if tsr is None else tsr) * np.size(DEFAULT_PITCH if pitch is None else pitch)
        check_deck_memory(fst, aero="rotor", surface_points=int(points), run=False)   # the surfaces, before they are computed
        aerodyn = read_aerodyn(aerodyn_file, n_blades=params.number_of_blades)
        rotor = BEMRotor.from_aerodyn(aerodyn, hub_radius=params.hub_radius,
                                      precone=params.precone[0], n_blades=params.number_of_blades,
                                      shaft_tilt=params.shaft_tilt)
        density = aerodyn.air_density or params.simulation.air_density or 1.225
        tower, unsteady = _deck_corrections(params, aerodyn, rotor, float(ua_tip_speed))
        table, moments = rotor_surfaces(rotor, tsr, pitch, tower=tower, unsteady=unsteady)
        return cls(table, radius=rotor.radius, air_density=density, precone=rotor.precone,
                   shaft_tilt=rotor.shaft_tilt, degree=degree, moment_table=moments, tower_inflow=tower is not None)

    # ------------------------------------------------------------------ expressions
    def _speed(self, u_rel: Any) -> Any:
        """Smooth floor of U: ``u_min`` at U = 0, relative error ``(u_min / U)²`` for U >> u_min."""
        return 0.5 * (u_rel + ca.sqrt(u_rel**2 + (2.0 * self.u_min) ** 2))

    def loads(self, u_rel: Any, omega: Any, pitch: Any, rho: Any = None, *,
              cp_scale: Any = 1.0, ct_scale: Any = 1.0) -> dict[str, Any]:
        """Quasi-steady rotor loads as CasADi expressions.

        Parameters
        ----------
        u_rel : SX or float
            Relative wind speed along the shaft [m/s] (see the module docstring).
        omega : SX or float
            Rotor speed [rad/s].
        pitch : SX or float
            Collective blade pitch [rad].
        rho : SX or float, optional
            Air density [kg/m^3]; default :attr:`air_density`.
        cp_scale, ct_scale : SX or float, optional, keyword-only
            Factors on the torque/power coefficient and on the thrust coefficient.

        Returns
        -------
        dict of str to SX
            ``torque`` [N m], ``thrust`` [N], ``power`` [W], ``cp``, ``ct``, ``cq``,
            ``tsr`` [-] and ``u`` (the floored relative wind speed [m/s]).
        """
        rho = self.air_density if rho is None else rho
        u = self._speed(u_rel)
        tsr = omega * self.radius / u
        surfaces = self.spline(tsr, pitch)
        ct, cq = ct_scale * surfaces["ct"], cp_scale * surfaces["cq"]
        dynamic = 0.5 * rho * math.pi * self.radius**2 * u**2
        torque = dynamic * self.radius * cq
        return {"torque": torque, "thrust": dynamic * ct, "power": omega * torque,
                "cp": tsr * cq, "ct": ct, "cq": cq, "tsr": tsr, "u": u}

    def disk_moment(self, u_rel: Any, cross: Any, axis: Any, omega: Any, pitch: Any, rho: Any = None) -> Any:
        """The disk's steady moment in a skewed flow [N m] (:mod:`.surfaces`), a 3-vector, or None without a
        moment table.

        Parameters
        ----------
        u_rel : SX or float
            Relative wind along the shaft [m/s].
        cross : SX (3,)
            The relative wind's part across the shaft [m/s] (``V tan χ e_w``).
        axis : SX (3,)
            The shaft's unit axis ``e_x`` (downwind).
        omega, pitch, rho
            As :meth:`loads`.

        Returns
        -------
        SX (3,) or None
            ``½ ρ π R³ U (c_w V_⊥ + c_p e_x × V_⊥)``, in the axes of ``cross`` and ``axis``.
        """
        return self._skewed(self._moment_spline, ("cw", "cp"), 3, u_rel, cross, axis, omega, pitch,  # type: ignore
                            rho)

    def disk_force(self, u_rel: Any, cross: Any, axis: Any, omega: Any, pitch: Any, rho: Any = None) -> Any:
        """The disk's steady in-plane force in a skewed flow [N] (:mod:`.surfaces`), a 3-vector, or None when the
        moment table has no force coefficients.

        Parameters and axes as :meth:`disk_moment`; returns ``½ ρ π R² U (h_w V_⊥ + h_p e_x × V_⊥)``.
        """
        return self._skewed(self._force_spline, ("hw", "hp"), 2, u_rel, cross, axis, omega, pitch,  # type: ignore
                            rho)

    def thrust_radius2(self, u_rel: Any, omega: Any, pitch: Any) -> Any:
        """``⟨r²⟩_T`` [m²], the second radial moment of the thrust's frozen-wake response to the wind
        (:func:`~mbsym.wind.aero.surfaces.thrust_radius2`), or None without the table (then a caller assumes the
        derivative ∝ r: ``(R² + r_hub²)/2``)."""
        if self._r2_spline is None:  # type: ignore[attr-defined]
            return None
        tsr = omega * self.radius / self._speed(u_rel)
        return self.radius**2 * self._r2_spline(tsr, pitch)["r2"]  # type: ignore[attr-defined]

    def tower_loads(self, u_rel: Any, omega: Any, pitch: Any, rho: Any = None) -> Any:
        """The disk's steady moment [N m] and in-plane force [N] from the tower's inflow disturbance
        (:class:`~mbsym.wind.aero.surfaces.DiskMomentTable`'s ``tower``), or None without it.

        Returns
        -------
        dict or None
            ``moment_up``, ``moment_side`` (along the disk's "up" ``e_u``, perpendicular to the shaft in the
            nacelle's vertical plane, and along ``e_x × e_u``) ``½ ρ π R³ U² (mu, ms)`` and ``force_up``,
            ``force_side`` ``½ ρ π R² U² (fu, fs)``.
        """
        spline = getattr(self, "_tower_spline")
        if spline is None:
            return None
        rho = self.air_density if rho is None else rho
        u = self._speed(u_rel)
        k = spline(omega * self.radius / u, pitch)
        q = 0.5 * rho * math.pi * self.radius**2 * u**2
        return {"moment_up": q * self.radius * k["mu"], "moment_side": q * self.radius * k["ms"],
                "force_up": q * k["fu"], "force_side": q * k["fs"]}

    def _skewed(self, spline, names: tuple[str, str], power: int, u_rel, cross, axis, omega, pitch,
                rho) -> Any:
        """``½ ρ π R^power U (k_w V_⊥ + k_p e_x × V_⊥)``, ``(k_w, k_p)`` the spline's ``names`` (None: none)."""
        if spline is None:
            return None
        rho = self.air_density if rho is None else rho
        u = self._speed(u_rel)
        k = spline(omega * self.radius / u, pitch)
        side = ca.cross(axis, cross)
        return 0.5 * rho * math.pi * self.radius**power * u * (k[names[0]] * cross + k[names[1]] * side)

    def inflow_lag_rhs(self, state: Any, u_rel: Any, omega: Any, pitch: Any, rho: Any = None,
                       **scales: Any) -> tuple[Any, dict[str, Any]]:
        """Right-hand side of the optional first-order lag on (thrust, torque).

        Parameters
        ----------
        state : SX, shape (2,)
            Lagged thrust [N] and torque [N m] (the integrator's extra states).
        u_rel, omega, pitch, rho, **scales
            As in :meth:`loads`.

        Returns
        -------
        rhs : SX, shape (2,)
            ``(y_qs - state) / τ`` with ``τ = lag_factor R / U`` [s].
        loads : dict
            The quasi-steady loads of :meth:`loads`, plus ``time_constant`` [s] and
            ``thrust_lagged``/``torque_lagged`` (= the state) to apply to the hub.
        """
        quasi = self.loads(u_rel, omega, pitch, rho, **scales)
        tau = self.lag_factor * self.radius / quasi["u"]
        target = ca.vertcat(quasi["thrust"], quasi["torque"])
        rhs = (target - state) / tau
        return rhs, quasi | {"time_constant": tau, "thrust_lagged": state[0],
                             "torque_lagged": state[1]}

    def function(self, name: str = "rotor_aero") -> ca.Function:
        """A CasADi Function ``(u_rel, omega, pitch, rho) -> (torque, thrust, power, cp, ct, tsr)``."""
        u, w, b, r = (ca.SX.sym(n) for n in ("u_rel", "omega", "pitch", "rho"))
        out = self.loads(u, w, b, r)
        names = ("torque", "thrust", "power", "cp", "ct", "tsr")
        return ca.Function(name, [u, w, b, r], [out[n] for n in names],
                           ["u_rel", "omega", "pitch", "rho"], list(names))

    def steady(self, u_rel: Any, omega: Any, pitch: Any, rho: Any = None) -> dict[str, np.ndarray]:
        """Numeric loads (numpy, broadcast) -- e.g. for initial guesses of a trim."""
        arrays = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (
            u_rel, omega, pitch, self.air_density if rho is None else rho)))
        f = self.function().map(arrays[0].size)
        out = f(*(a.ravel()[None, :] for a in arrays))
        names = ("torque", "thrust", "power", "cp", "ct", "tsr")
        return {n: np.asarray(v).reshape(arrays[0].shape) for n, v in zip(names, out)}


def _deck_corrections(params, aerodyn, rotor, tip_speed: float) -> tuple[Any, Any]:
    """``(tower, unsteady)`` of :func:`~mbsym.wind.aero.surfaces.rotor_surfaces` for a deck: its tower when that
    disturbs the blade inflow, its UA nodes (one blade) with ``UA_Mod = 3``; None for each otherwise."""
    from .blade.unsteady import unsteady_nodes
    from .tower import TowerAero
    from .tower_average import RotorPlacement

    tower = TowerAero.from_aerodyn(aerodyn)
    tower = (tower, RotorPlacement.from_elastodyn(params)) if tower is not None and tower.disturbs_inflow else None
    extra = dict(aerodyn.extra or {})
    dt = _number(extra.get("DTAero"), params.simulation.time_step)
    sound = _number(extra.get("SpdSound"), _number(params.simulation.extra.get("SpdSound"), None))
    nodes = unsteady_nodes(aerodyn, rotor, 1, dt=dt, speed_of_sound=sound)
    return tower, None if nodes is None else (nodes, tip_speed)


def _number(text: Any, fallback: Any) -> Any:
    """``text`` as a float, or ``fallback`` ("default", missing)."""
    try:
        return float(str(text).strip().strip("\"'"))
    except (TypeError, ValueError):
        return fallback
