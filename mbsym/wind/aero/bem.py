"""Steady blade-element momentum (BEM) theory with AeroDyn 15's options.

The model follows AeroDyn 15's BEMT with ``BEM_Mod = 1`` (legacy
"NoSweepPitchTwist" frame) for a rigid rotor in uniform inflow:

* **Geometry.** Node ``j`` of a blade sits at ``p = (R_hub + BlSpn) e_s +
  BlCrvAC e_n - BlSwpAC e_t`` in the rotating frame (``e_x`` along the shaft,
  downwind; ``e_s = cos c e_r + sin c e_x`` the coned span axis with cone
  ``c = precone + BlCrvAng``; ``e_n = -sin c e_r + cos c e_x`` its normal; ``e_t``
  the direction of rotation; BlSwpAC is positive towards the trailing edge).  The
  local radius ``r = sqrt(p_r² + p_t²)`` and the rotor radius ``R = max r``
  (AeroDyn's ``rmax``) are in-plane distances; the Prandtl constants use the arc
  length ``z`` along the blade (AeroDyn's ``zLocal``, ``zHub``, ``zTip``).
* **Velocities and skew.** ``V`` is the wind component along the shaft and
  ``χ0`` the angle between wind and shaft (a horizontal wind on a shaft tilted by
  ``tilt`` has ``χ0 = |tilt|``; this is AeroDyn's skew angle ``RtSkew``).  The
  in-plane component ``V tan χ0`` makes the element velocities depend on the
  blade azimuth ψ (measured from the in-plane wind direction):
  ``Vx = V (cos c - tan χ0 sin c cos ψ)``, ``Vy = Ω p_r + V tan χ0 sin ψ``; the
  rotor loads are averaged over ``n_azimuth`` positions (what a 3-bladed rotor
  averages over a revolution).  AeroDyn's Pitt/Peters redistribution of the axial
  induction, ``a (1 + 15π/32 tan(χ/2) r/R cos ψ)`` with ``χ = (0.6 a + 1) χ0``, is
  applied after the solve, as AeroDyn does with ``BEM_Mod = 1``.  The skew matters
  at low TSR (about -0.9 % on Ct at TSR 3.3 for the NREL 5 MW) and hardly at
  TSR 7.6 (0.02 %).
* **Induction.** Ning's (2014) residual in the inflow angle φ, as AeroDyn's
  ``inductionFactors0``: momentum region with Buhl's high-thrust correction,
  propeller-brake region, Prandtl tip and hub loss ``F`` (``F >= 1e-4``), optional
  tangential induction, and drag left out of the induction unless ``axial_drag`` /
  ``tangential_drag``.  The residual is bracketed in ``[ε, π/2-ε]``, then
  ``[-π/4, -ε]``, then ``[π/2+ε, π-ε]`` and solved by a safeguarded
  regula falsi (Anderson-Björck), so it always converges where a bracket exists;
  otherwise the element takes zero induction (AeroDyn's "invalid solution").  The
  tip and hub nodes, where a Prandtl constant is zero, get ``a = 1, a' = 0`` as
  in AeroDyn.  Below TSR 2 the induction is blended to zero (cosine, TSR 1 → 2),
  as AeroDyn's ``check_turnOffBEMT`` does.
* **Loads.** Lift, drag (always) and pitching moment at ``α = φ - θ``
  (``θ = twist + pitch``; on a curved blade AeroDyn's Euler angle, :func:`aerodyn_theta`), airfoil polars
  interpolated linearly in α (AeroDyn's
  default).  Per unit length: ``fn = q c (Cl cos φ + Cd sin φ)`` along ``e_n``,
  ``ft = q c (Cl sin φ - Cd cos φ)`` along ``e_t``, ``m = q c² Cm`` about ``e_s``.
  Thrust ``T = ∫ fn cos c`` and torque ``Q = ∫ (p × f + m e_s)·e_x`` are
  integrated exactly for loads and positions linear between nodes (AeroDyn's
  Line2-to-Point mesh mapping).

Everything is vectorized over operating points × azimuths × nodes (numpy).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ...exceptions import ParameterError
from ..deck.aerodyn import AeroDynInput, freeze_blade_geometry, read_aerodyn
from ..deck.airfoils import AirfoilPolar
from ._induction import _Elements, _induction, _lookup, _polar_tables, _solve_phi

__all__ = ["BEMRotor", "BEMSolution", "solve_bem", "rotor_coefficients", "aerodyn_theta"]

_A_LIMITS = (-1.0, 1.5)  # AeroDyn's limits of the axial induction
_AP_LIMITS = (-1.0, 1.0)  # ... and of the tangential induction


@dataclass(frozen=True, eq=False)
class BEMRotor:
    """A rigid rotor for the steady BEM: blade geometry, polars and options.

    Attributes
    ----------
    n_blades : int
        Number of blades B.
    hub_radius : float
        Distance from the rotor centre to the blade root along the coned pitch
        axis [m] (ElastoDyn HubRad).
    precone : float
        Cone angle of the pitch axis [rad] (ElastoDyn PreCone; negative = upwind).
    span, curve_ac, sweep_ac, curve_angle, twist, chord : ndarray, shape (n,)
        AeroDyn blade-file columns in SI units (m, m, m, rad, rad, m).
    polars : tuple of AirfoilPolar
        The polar of each node (length n).
    tip_loss, hub_loss, tangential_induction : bool
        AeroDyn TipLoss, HubLoss, TanInd.
    axial_drag, tangential_drag : bool
        AeroDyn AIDrag, TIDrag (drag in the induction equations).
    pitching_moment : bool
        Include the airfoil pitching moment in the shaft torque (AeroDyn UseBlCm).
    shaft_tilt : float
        Shaft tilt [rad] (ElastoDyn ShftTilt): the default skew of the inflow (a
        horizontal wind on the tilted shaft), see :func:`solve_bem`.
    skew_correction : bool
        AeroDyn's Pitt/Peters skewed-wake redistribution of the axial induction
        (Skew_Mod = 1 with SkewRedistr_Mod = 1).
    skew_factor : float
        Its constant (AeroDyn SkewRedistrFactor, default 15π/32).
    low_tsr_blend : bool
        Blend the induction to zero between TSR 2 and 1, as AeroDyn.
    source : str or None
        Where the data came from (not compared).
    """

    n_blades: int
    hub_radius: float
    precone: float
    span: np.ndarray
    curve_ac: np.ndarray
    sweep_ac: np.ndarray
    curve_angle: np.ndarray
    twist: np.ndarray
    chord: np.ndarray
    polars: tuple[AirfoilPolar, ...]
    tip_loss: bool = True
    hub_loss: bool = True
    tangential_induction: bool = True
    axial_drag: bool = False
    tangential_drag: bool = False
    pitching_moment: bool = True
    shaft_tilt: float = 0.0
    skew_correction: bool = True
    skew_factor: float = 15.0 * math.pi / 32.0
    low_tsr_blend: bool = True
    source: str | None = field(default=None, compare=False)

    def __post_init__(self) -> None:
        if not isinstance(self.n_blades, int) or self.n_blades < 1:
            raise ParameterError(f"BEMRotor.n_blades must be a positive integer; got "
                                 f"{self.n_blades!r}.")
        for name in ("hub_radius", "precone", "shaft_tilt", "skew_factor"):
            value = getattr(self, name)
            if not isinstance(value, (int, float)) or not math.isfinite(value):
                raise ParameterError(f"BEMRotor.{name} must be a finite number; got {value!r}.")
        if self.hub_radius < 0 or abs(self.precone) >= math.pi / 2:
            raise ParameterError("BEMRotor.hub_radius must be >= 0 and |precone| < 90 deg.")
        span = freeze_blade_geometry(self, "BEMRotor")
        polars = tuple(self.polars)
        if len(polars) != span.size or not all(isinstance(p, AirfoilPolar) for p in polars):
            raise ParameterError(f"BEMRotor.polars must hold {span.size} AirfoilPolar objects "
                                 "(one per node).")
        object.__setattr__(self, "polars", polars)
        object.__setattr__(self, "_geometry", _geometry(self))
        object.__setattr__(self, "_tables", _polar_tables(polars))

    # ------------------------------------------------------------------ constructors
    @classmethod
    def from_aerodyn(cls, aerodyn: AeroDynInput, *, hub_radius: float, precone: float,
                     n_blades: int = 3, shaft_tilt: float = 0.0, blade: int = 0) -> "BEMRotor":
        """Build the rotor of an AeroDyn deck (blade ``blade``, all blades alike).

        Parameters
        ----------
        aerodyn : AeroDynInput
            From :func:`mbsym.wind.deck.aerodyn.read_aerodyn`.
        hub_radius, precone, shaft_tilt : float
            ElastoDyn HubRad [m], PreCone and ShftTilt [rad].
        n_blades : int, optional
            ElastoDyn NumBl.
        blade : int, optional
            Which AeroDyn blade to use (0-based).

        Raises
        ------
        ParameterError
            If the deck asks for a model this BEM does not reproduce (BEM_Mod = 2,
            Wake_Mod = 3 (OLAF), AFTabMod = 2 with several tables in an airfoil file).
        """
        if aerodyn.wake_model not in (1, 2) or aerodyn.bem_model != 1:
            raise ParameterError(
                f"{aerodyn.source}: mbsym's BEM reproduces AeroDyn with Wake_Mod 1 or 2 (BEMT, "
                f"DBEMT: same steady state) and BEM_Mod = 1; this deck has Wake_Mod = "
                f"{aerodyn.wake_model}, BEM_Mod = {aerodyn.bem_model}. Change the deck or compute the table "
                "elsewhere.")
        several = [a.name for a in aerodyn.airfoils if a.n_tables > 1]
        if aerodyn.airfoil_table_mode == 2 and several:
            raise ParameterError(
                f"{aerodyn.source}: AFTabMod = 2 interpolates the airfoil tables in Reynolds number and "
                f"{', '.join(several[:3])} have several; mbsym's BEM reads one table per airfoil. Set AFTabMod = 1 "
                "(the first table) or give one table per file.")
        b = aerodyn.blades[blade]
        return cls(n_blades=n_blades, hub_radius=float(hub_radius), precone=float(precone),
                   span=b.span, curve_ac=b.curve_ac, sweep_ac=b.sweep_ac,
                   curve_angle=b.curve_angle, twist=b.twist, chord=b.chord,
                   polars=tuple(aerodyn.airfoils[i - 1] for i in b.airfoil_id),
                   tip_loss=aerodyn.tip_loss, hub_loss=aerodyn.hub_loss,
                   tangential_induction=aerodyn.tangential_induction,
                   axial_drag=aerodyn.axial_drag, tangential_drag=aerodyn.tangential_drag,
                   pitching_moment=aerodyn.use_pitching_moment, shaft_tilt=float(shaft_tilt),
                   skew_correction=aerodyn.skew_redistribution,
                   skew_factor=aerodyn.skew_redistribution_factor, source=aerodyn.source)

    @classmethod
    def from_openfast(cls, fst: str | Path) -> "BEMRotor":
        """Build the rotor of an OpenFAST deck (``.fst`` with CompAero = 2, AeroDyn 15).

        Hub radius, precone (blade 1), shaft tilt and number of blades come from
        ElastoDyn; everything else from the AeroDyn files.
        """
        from ..deck.openfast import read_openfast

        params = read_openfast(fst)
        aerodyn_file = params.source_files.get("aerodyn")
        if aerodyn_file is None:
            raise ParameterError(f"{fst}: the deck names no AeroDyn file (CompAero must be 2 and "
                                 "AeroFile must exist).")
        aerodyn = read_aerodyn(aerodyn_file, n_blades=params.number_of_blades)
        return cls.from_aerodyn(aerodyn, hub_radius=params.hub_radius,
                                precone=params.precone[0], n_blades=params.number_of_blades,
                                shaft_tilt=params.shaft_tilt)

    # ------------------------------------------------------------------ geometry
    @property
    def radius(self) -> float:
        """Rotor radius R [m]: the largest in-plane node radius (AeroDyn's ``rmax``)."""
        return float(self._geometry["r"].max())  # type: ignore[attr-defined]

    @property
    def local_radius(self) -> np.ndarray:
        """In-plane radius of each node [m] (AeroDyn's ``rLocal``)."""
        return self._geometry["r"].copy()  # type: ignore[attr-defined]

    def __repr__(self) -> str:
        return (f"BEMRotor(B={self.n_blades}, R={self.radius:.4f} m, {self.span.size} nodes, "
                f"precone={math.degrees(self.precone):g} deg, source={self.source!r})")


def aerodyn_theta(twist: Any, curve_angle: Any, pitch: Any, *, sin=np.sin, cos=np.cos, atan2=np.arctan2) -> Any:
    """AeroDyn's twist + pitch angle θ [rad] of a node of a curved (prebent) rigid blade (``BEM_Mod = 1``).

    AeroDyn (AeroDyn.f90 ``Init_u``, ``Calculate_MeshOrientation_NoSweepPitchTwist``) orients node ``j`` at
    ``EulerConstruct(0, BlCrvAng, −BlTwist)`` relative to the pitched root and takes θ as minus the z angle of
    the z-y-x decomposition (NWTC ``EulerExtract``) of that orientation relative to the root without pitch,
    ``EulerConstruct(0, γ, −τ) · EulerConstruct(0, 0, −β)``:

        θ = atan2(cos γ sin τ cos β + cos τ sin β, cos γ cos τ cos β − sin τ sin β),

    ``τ + β`` for a straight blade (γ = 0), and larger for a curved one at pitch: on the IEA 15 MW at 8.2° pitch
    +0.03° at 87 % span (γ = −5°, τ = −2.1°), which OpenFAST's node outputs show (docs/blade_aero.md §2).

    Parameters
    ----------
    twist, curve_angle, pitch : array_like or SX
        ``BlTwist`` τ, ``BlCrvAng`` γ and the blade pitch β [rad] (broadcast).
    sin, cos, atan2 : callable, optional
        The functions to use (``casadi.sin`` … for SX).
    """
    cg, ct, st, cb, sb = cos(curve_angle), cos(twist), sin(twist), cos(pitch), sin(pitch)
    return atan2(cg * st * cb + ct * sb, cg * ct * cb - st * sb)


def _geometry(rotor: BEMRotor) -> dict[str, np.ndarray]:
    """Node positions, frames and Prandtl constants (see the module docstring)."""
    cone = rotor.precone + rotor.curve_angle
    z_axis = rotor.hub_radius + rotor.span
    # components in the rotating frame (e_r, e_t, e_x)
    pos = np.stack([z_axis * np.cos(rotor.precone) - rotor.curve_ac * np.sin(rotor.precone),
                    -rotor.sweep_ac,
                    z_axis * np.sin(rotor.precone) + rotor.curve_ac * np.cos(rotor.precone)],
                   axis=-1)
    normal = np.stack([-np.sin(cone), np.zeros_like(cone), np.cos(cone)], axis=-1)
    spanwise = np.stack([np.cos(cone), np.zeros_like(cone), np.sin(cone)], axis=-1)
    r = np.hypot(pos[:, 0], pos[:, 1])
    root = np.array([rotor.hub_radius * math.cos(rotor.precone), 0.0,
                     rotor.hub_radius * math.sin(rotor.precone)])
    z_local = rotor.hub_radius + np.linalg.norm(pos[0] - root) + np.concatenate(
        ([0.0], np.cumsum(np.linalg.norm(np.diff(pos, axis=0), axis=1))))
    z_hub, z_tip = rotor.hub_radius, z_local[-1]
    b = rotor.n_blades
    with np.errstate(divide="ignore", invalid="ignore"):
        tip_const = b * (z_tip - z_local) / (2.0 * z_local)
        hub_const = b * (z_local - z_hub) / (2.0 * z_hub) if z_hub > 0 else np.full_like(r, np.inf)
    fixed = ((rotor.tip_loss & np.isclose(tip_const, 0.0, atol=1e-12))
             | (rotor.hub_loss & np.isclose(hub_const, 0.0, atol=1e-12)))
    return {"pos": pos, "normal": normal, "spanwise": spanwise, "r": r, "r_rad": pos[:, 0],
            "cos_cone": np.cos(cone), "tip_const": tip_const, "hub_const": hub_const,
            "fixed": fixed, "length": np.linalg.norm(np.diff(pos, axis=0), axis=1)}


# ----------------------------------------------------------------------------- solution
@dataclass(frozen=True, eq=False)
class BEMSolution:
    """Steady BEM solution at operating points (``...``) × nodes (``n``).

    Per-node quantities are for a wind speed along the shaft of 1 m/s and an air
    density of 1 kg/m^3 (loads scale with ρ V²); the rotor coefficients are
    dimensionless.

    Attributes
    ----------
    tsr, pitch : ndarray, shape (...)
        Tip-speed ratio Ω R / V [-] and collective pitch [rad] of each point.
    cp, ct, cq : ndarray, shape (...)
        Power, thrust and torque coefficients based on R and V (AeroDyn's
        RtAeroCp, RtAeroCt, RtAeroCq conventions).
    phi, alpha, a, ap : ndarray, shape (..., n_azimuth, n)
        Inflow angle [rad], angle of attack [rad], axial and tangential induction,
        per azimuth position (1 if the wind is along the shaft) and node.
    fn, ft, m : ndarray, shape (..., n_azimuth, n)
        Normal and tangential force [N/m] and pitching moment [N m/m] per length.
    converged : ndarray of bool, shape (..., n_azimuth, n)
        False where no bracket held a root (zero induction was used) -- AeroDyn's
        "invalid solution"; fixed (tip/hub) nodes count as converged.
    """

    tsr: np.ndarray
    pitch: np.ndarray
    cp: np.ndarray
    ct: np.ndarray
    cq: np.ndarray
    phi: np.ndarray
    alpha: np.ndarray
    a: np.ndarray
    ap: np.ndarray
    fn: np.ndarray
    ft: np.ndarray
    m: np.ndarray
    converged: np.ndarray


def _line_integral(values: np.ndarray, length: np.ndarray) -> np.ndarray:
    """∫ v ds for v linear between nodes (trapezoid); values (..., n), length (n-1,)."""
    return 0.5 * np.sum((values[..., 1:] + values[..., :-1]) * length, axis=-1)


def _torque(pos: np.ndarray, force: np.ndarray, moment: np.ndarray, length: np.ndarray
            ) -> np.ndarray:
    """Shaft component of ∫ (p × f + m) ds, p and f linear between nodes (exact)."""
    def cross_x(p: np.ndarray, f: np.ndarray) -> np.ndarray:  # x (= e_x) component of p × f
        return p[..., 0] * f[..., 1] - p[..., 1] * f[..., 0]
    p1, p2, f1, f2 = pos[:-1], pos[1:], force[..., :-1, :], force[..., 1:, :]
    arm = (2 * cross_x(p1, f1) + cross_x(p1, f2) + cross_x(p2, f1) + 2 * cross_x(p2, f2)) / 6.0
    return np.sum(arm * length, axis=-1) + _line_integral(moment, length)


def _velocities(rotor: BEMRotor, tsr: np.ndarray, skew: float, n_azimuth: int, change=None
                ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Vx, Vy (..., n_azimuth, n) for a shaft-axial wind of 1 m/s, and cos of the azimuth.

    The azimuth ψ of a blade is measured from the direction of the in-plane wind
    component ``tan(skew)`` (the downwind side of the skewed disk is ψ = 0). ``change``:
    ``(dvx, dvy)`` (n_azimuth, n) added (the tower's, :mod:`.tower_average`).
    """
    g = rotor._geometry  # type: ignore[attr-defined]
    psi = 2.0 * math.pi * (np.arange(n_azimuth) + 0.5) / n_azimuth if n_azimuth > 1 else \
        np.zeros(1)
    cos_psi, sin_psi = np.cos(psi)[:, None], np.sin(psi)[:, None]
    in_plane = math.tan(skew)
    sin_cone = np.sin(rotor.precone + rotor.curve_angle)
    omega = tsr[..., None, None] / rotor.radius
    vx = g["cos_cone"] - in_plane * sin_cone * cos_psi + 0.0 * omega
    vy = omega * g["r_rad"] + in_plane * sin_psi
    if change is not None:
        vx, vy = vx + change[0], vy + change[1]
    return vx, vy, np.broadcast_to(cos_psi, vx.shape)


def solve_bem(rotor: BEMRotor, tsr: Any, pitch: Any, *, skew: float | None = None,
              n_azimuth: int = 8, inflow_change: tuple[np.ndarray, np.ndarray] | None = None,
              airfoil_loads: Any = None) -> BEMSolution:
    """Solve the steady BEM at tip-speed ratios ``tsr`` and pitch angles ``pitch``.

    Parameters
    ----------
    rotor : BEMRotor
        Geometry, polars and options.
    tsr : array_like
        Tip-speed ratio Ω R / V [-], R = ``rotor.radius``, V = wind speed along the
        shaft; > 0.
    pitch : array_like
        Collective blade pitch [rad]; broadcast against ``tsr``.
    skew : float, optional
        Angle between the wind and the shaft [rad]; default ``|rotor.shaft_tilt|``
        (a horizontal wind on a tilted shaft).  Its in-plane component ``V tan(skew)``
        varies the blade velocities with azimuth.
    n_azimuth : int, optional
        Azimuth positions averaged when ``skew != 0`` (8 reproduce 36 within 0.01 %).
    inflow_change : (ndarray, ndarray), optional
        ``(dvx, dvy)`` (n_azimuth, n_nodes): added to each node's velocities at each azimuth, per m/s
        of wind along the shaft (the tower's potential flow and shadow,
        :func:`~mbsym.wind.aero.tower_average.tower_inflow_change`, made for the default skew).
    airfoil_loads : callable, optional
        ``(alpha, speed, coefficients) -> coefficients``: the coefficients (..., n, 3: Cl, Cd, Cm) that load
        the blade at the induced angle of attack ``alpha`` [rad] and relative speed ``speed`` [per m/s of wind
        along the shaft] (..., n), given the static ones; the induction is solved with the static polars, as
        AeroDyn's BEMT does (the steady state of unsteady airfoils,
        :func:`~mbsym.wind.aero.blade.ua_steady.steady_airfoil_loads`).

    Returns
    -------
    BEMSolution

    Raises
    ------
    ParameterError
        If a TSR is not a positive finite number, a pitch is not finite, or the
        skew or n_azimuth is invalid.
    """
    if not isinstance(rotor, BEMRotor):
        raise TypeError(f"solve_bem needs a BEMRotor; got {type(rotor).__name__}.")
    tsr_a, pitch_a = np.broadcast_arrays(np.asarray(tsr, dtype=float),
                                         np.asarray(pitch, dtype=float))
    if not (np.all(np.isfinite(tsr_a)) and np.all(tsr_a > 0)):
        raise ParameterError("tsr must hold positive finite tip-speed ratios.")
    if not np.all(np.isfinite(pitch_a)):
        raise ParameterError("pitch must hold finite angles [rad].")
    skew = abs(rotor.shaft_tilt) if skew is None else skew
    if not (isinstance(skew, (int, float)) and 0 <= abs(skew) < math.radians(60)):
        raise ParameterError(f"skew must be an angle in (-60, 60) deg [rad]; got {skew!r}.")
    if not (isinstance(n_azimuth, int) and n_azimuth >= 1):
        raise ParameterError(f"n_azimuth must be a positive integer; got {n_azimuth!r}.")
    if inflow_change is not None:
        inflow_change = _checked_change(rotor, inflow_change, n_azimuth, skew)
    n_azimuth = n_azimuth if skew or inflow_change is not None else 1
    g = rotor._geometry  # type: ignore[attr-defined]
    vx, vy, cos_psi = _velocities(rotor, tsr_a, abs(skew), n_azimuth, inflow_change)
    shape = vx.shape
    theta = np.broadcast_to(aerodyn_theta(rotor.twist, rotor.curve_angle, pitch_a[..., None, None]), shape)
    flat = _Elements(
        vx=vx.ravel(), vy=vy.ravel(), theta=theta.ravel(),
        sigma=np.broadcast_to(rotor.n_blades * rotor.chord / (2 * math.pi * g["r"]), shape).ravel(),
        tip_const=np.broadcast_to(g["tip_const"], shape).ravel(),
        hub_const=np.broadcast_to(g["hub_const"], shape).ravel(),
        rows=np.broadcast_to(rotor._tables["which"], shape).ravel(),  # type: ignore[attr-defined]
        tables=rotor._tables, n_blades=rotor.n_blades,  # type: ignore[attr-defined]
        tip_loss=rotor.tip_loss, hub_loss=rotor.hub_loss,
        tangential_induction=rotor.tangential_induction, axial_drag=rotor.axial_drag,
        tangential_drag=rotor.tangential_drag)
    fixed = np.broadcast_to(g["fixed"], shape)
    free = np.flatnonzero(~fixed.ravel())
    phi = np.full(vx.size, np.nan)
    phi[free] = _solve_phi(flat.take(free))[0]
    found = np.isfinite(phi)
    ind = _induction(np.where(found, phi, 0.1), flat)
    ok = (found & ind["valid"]).reshape(shape) & ~fixed
    a = np.where(fixed, 1.0, np.where(ok, np.clip(ind["a"].reshape(shape), *_A_LIMITS), 0.0))
    ap = np.where(ok, np.clip(ind["ap"].reshape(shape), *_AP_LIMITS), 0.0)
    if rotor.skew_correction and skew:  # AeroDyn's Pitt/Peters redistribution (legacy BEM)
        chi = (0.6 * a + 1.0) * abs(skew)
        tan_half = np.where(np.abs(chi) > math.pi / 2, np.sign(chi), np.tan(chi / 2.0))
        correction = rotor.skew_factor * tan_half * g["r"] / rotor.radius * cos_psi
        a = np.where(fixed, a, a * (1.0 + correction))
    if rotor.low_tsr_blend:  # AeroDyn check_turnOffBEMT: cosine blend of the induction
        x = np.clip(tsr_a[..., None, None] - 1.0, 0.0, 1.0)
        weight = 0.5 * (1.0 - np.cos(math.pi * x))
        a, ap = np.where(fixed, a, a * weight), ap * weight
    ux, uy = vx * (1.0 - a), vy * (1.0 + ap)
    phi = np.arctan2(ux, uy)
    alpha = phi - theta
    coef = _lookup(rotor._tables, alpha, rotor._tables["which"])  # type: ignore[attr-defined]
    if airfoil_loads is not None:
        coef = airfoil_loads(alpha, np.hypot(ux, uy), coef)
    cl, cd, cm = coef[..., 0], coef[..., 1], coef[..., 2]
    q = 0.5 * (ux**2 + uy**2)
    fn = q * rotor.chord * (cl * np.cos(phi) + cd * np.sin(phi))
    ft = q * rotor.chord * (cl * np.sin(phi) - cd * np.cos(phi))
    m = q * rotor.chord**2 * cm if rotor.pitching_moment else np.zeros_like(q)
    force = fn[..., None] * g["normal"] + ft[..., None] * np.array([0.0, 1.0, 0.0])
    thrust = _line_integral(fn * g["cos_cone"], g["length"]).mean(axis=-1)
    torque = _torque(g["pos"], force, m * g["spanwise"][:, 2], g["length"]).mean(axis=-1)
    area = math.pi * rotor.radius**2
    ct = rotor.n_blades * thrust / (0.5 * area)
    cq = rotor.n_blades * torque / (0.5 * area * rotor.radius)
    return BEMSolution(tsr=tsr_a, pitch=pitch_a, cp=cq * tsr_a, ct=ct, cq=cq, phi=phi,
                       alpha=np.mod(alpha + math.pi, 2 * math.pi) - math.pi, a=a, ap=ap,
                       fn=fn, ft=ft, m=m, converged=ok | fixed)


def _checked_change(rotor: BEMRotor, change, n_azimuth: int, skew: float) -> tuple[np.ndarray, np.ndarray]:
    """``inflow_change`` of :func:`solve_bem`, checked against the azimuths and the skew it was made for."""
    dvx, dvy = (np.asarray(v, dtype=float) for v in change)
    shape = (n_azimuth, rotor.span.size)
    if dvx.shape != shape or dvy.shape != shape or not (np.all(np.isfinite(dvx)) and np.all(np.isfinite(dvy))):
        raise ParameterError(f"inflow_change must be two finite arrays of shape (n_azimuth, n_nodes) = {shape}; got "
                             f"{dvx.shape} and {dvy.shape}.")
    if not math.isclose(abs(skew), abs(rotor.shaft_tilt), abs_tol=1e-12):
        raise ParameterError("inflow_change is made for the wind along the ground (skew = |shaft_tilt|); got skew "
                             f"{math.degrees(skew):.4g} deg for a tilt of {math.degrees(rotor.shaft_tilt):.4g} deg.")
    return dvx, dvy


def rotor_coefficients(rotor: BEMRotor, tsr: Any, pitch: Any, **options: Any
                       ) -> tuple[np.ndarray, ...]:
    """Steady (cp, ct, cq) of ``rotor`` at ``tsr`` [-] and ``pitch`` [rad] (broadcast).

    See :func:`solve_bem` (whose keyword options are accepted); the coefficients use
    AeroDyn's conventions: radius ``rotor.radius`` (in-plane tip radius), wind speed
    along the shaft.
    """
    solution = solve_bem(rotor, tsr, pitch, **options)
    return solution.cp, solution.ct, solution.cq
