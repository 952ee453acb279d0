"""Rotor performance surfaces Cp, Ct, Cq over tip-speed ratio × pitch from the steady BEM, and the disk's
steady moment.

:func:`performance_surface` evaluates :func:`mbsym.wind.aero.bem.solve_bem` on a
grid and returns a :class:`~mbsym.wind.deck.performance.PerformanceTable`, which
:func:`~mbsym.wind.deck.performance.write_performance_table` writes in ROSCO's
``Cp_Ct_Cq`` format.  The coefficients follow AeroDyn's conventions (radius =
in-plane tip radius ``rotor.radius``, wind speed along the shaft), so ``cq`` is
exactly ``cp / tsr``.

:func:`disk_moment_surface` integrates the same azimuth-resolved solution into the **steady moment** of the
disk in a skewed flow (:class:`DiskMomentTable`): with the in-plane wind ``V tan χ`` along ``e_w`` (the
blade azimuth ψ = 0, the disk's downwind side) and ``e_p = e_x × e_w``, the loads vary with ψ (the coned
blades meet the flow at ``Vx = V (cos c − tan χ sin c cos ψ)``, Pitt and Peters' redistribution moves the
induction downwind) and their moment about the apex, averaged over the revolution,

    M = B ⟨∫ p × f ds⟩_ψ = ½ ρ V² π R³ tan χ (c_w e_w + c_p e_p)

is, to first order in ``tan χ``, ``c_w``, ``c_p`` times ``tan χ``: the table holds the coefficients at the
BEM's skew divided by its ``tan χ``. The same loads add up to the disk's steady **in-plane force**

    F = B ⟨∫ f_⊥ ds⟩_ψ = ½ ρ V² π R² tan χ (h_w e_w + h_p e_p)

(``f_⊥`` the load's part in the rotor plane; the thrust is the rest): on the floating IEA 15 MW at 13 m/s,
8.75° of skew from the shaft tilt and the platform pitch, 9.9 kN along ``e_w`` (up) and 4.5 kN across,
which the thrust and torque surfaces do not hold. A rotor-effective model applies moment and force with the
skew of its own relative wind (compose ``_disk_moments``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.interpolate import RectBivariateSpline

from ...exceptions import ParameterError

from ..deck.performance import PerformanceTable
from .bem import BEMRotor, _lookup, _velocities, solve_bem
from .tower_average import TOWER_AZIMUTHS

__all__ = ["performance_surface", "disk_moment_surface", "rotor_surfaces", "DiskMomentTable", "thrust_radius2",
           "DEFAULT_TSR", "DEFAULT_PITCH"]

#: Default tip-speed-ratio grid: 1 to 16 in steps of 0.25 (61 values).
DEFAULT_TSR = np.round(np.arange(1.0, 16.0 + 1e-9, 0.25), 12)
#: Default pitch grid [rad]: -5 to 40 deg in steps of 1 deg (46 values).
DEFAULT_PITCH = np.deg2rad(np.arange(-5.0, 40.0 + 1e-9, 1.0))


def _axis(values: Any, name: str) -> np.ndarray:
    axis = np.asarray(values, dtype=float)
    if axis.ndim != 1 or axis.size < 2 or not np.all(np.isfinite(axis)) or \
            np.any(np.diff(axis) <= 0):
        raise ParameterError(f"{name} must be a 1-D array of at least 2 strictly increasing "
                             f"finite values; got {values!r}.")
    return axis


def performance_surface(rotor: BEMRotor, tsr: Any = None, pitch: Any = None, *,
                        skew: float | None = None, n_azimuth: int = 8,
                        wind_speed: float | None = None) -> PerformanceTable:
    """Cp, Ct, Cq of ``rotor`` on the grid ``tsr`` × ``pitch``.

    Parameters
    ----------
    rotor : BEMRotor
        The rotor (e.g. ``BEMRotor.from_openfast(fst)``).
    tsr : array_like, optional
        Strictly increasing tip-speed ratios [-]; default :data:`DEFAULT_TSR`.
    pitch : array_like, optional
        Strictly increasing collective pitch angles [rad]; default
        :data:`DEFAULT_PITCH`.
    skew, n_azimuth : optional
        As in :func:`~mbsym.wind.aero.bem.solve_bem` (default: the shaft tilt, 8).
    wind_speed : float, optional
        The informational "z axis" wind speed of ROSCO's format [m/s].

    Returns
    -------
    PerformanceTable
        ``cq = cp / tsr``; ``source`` describes the rotor and options.

    Raises
    ------
    ParameterError
        If a grid is not strictly increasing or a TSR is not positive.

    Examples
    --------
    >>> import numpy as np
    >>> from mbsym.wind.aero import nrel5mw_bem_rotor, performance_surface
    >>> table = performance_surface(nrel5mw_bem_rotor(), tsr=[6.0, 7.5],
    ...                             pitch=np.radians([0.0, 2.0]))
    >>> table.cp.shape
    (2, 2)
    """
    return rotor_surfaces(rotor, tsr, pitch, skew=skew, n_azimuth=n_azimuth, wind_speed=wind_speed)[0]


@dataclass(frozen=True, eq=False)
class DiskMomentTable:
    """The disk's steady moment per unit ``tan χ`` over TSR × pitch (module docstring).

    Attributes
    ----------
    tsr, pitch : ndarray
        Axes [-], [rad].
    cw, cp : ndarray (n_tsr, n_pitch)
        ``M·e_w`` and ``M·e_p`` over ``½ ρ V² π R³ tan χ`` [-] (``e_w`` the in-plane wind's direction,
        ``e_p = e_x × e_w``, ``e_x`` the shaft downwind; ``V`` the wind along the shaft, ``R`` the radius).
    skew : float
        The BEM's skew χ [rad] the coefficients come from (0: an untilted shaft, whose table holds only the
        tower's part).
    source : str or None
    hw, hp : ndarray (n_tsr, n_pitch) or None
        The in-plane force ``F·e_w``, ``F·e_p`` over ``½ ρ V² π R² tan χ`` [-] (None: not tabulated).
    r2 : ndarray (n_tsr, n_pitch) or None
        The second radial moment of the blades' frozen-wake thrust derivative over ``R²`` [-]:
        ``⟨r²⟩_T / R² = Σ ∫ (∂f_n/∂u) r² ds / (Σ ∫ (∂f_n/∂u) ds R²)``, the radius of gyration of the thrust's
        response to a wind change, which sets the disk's damping against tilt and yaw rates (compose
        ``_disk_moments``). None: not tabulated.
    tower : dict or None
        The part of the disk's moment and in-plane force the tower's inflow disturbance adds
        (:mod:`.tower_average`), which does not scale with the skew: ``"mu"``, ``"ms"`` (moment along the disk's
        "up" ``e_u``, perpendicular to the shaft in the nacelle's vertical plane, and along ``e_x × e_u``, over
        ``½ ρ V² π R³``) and ``"fu"``, ``"fs"`` (the force, over ``½ ρ V² π R²``), each (n_tsr, n_pitch); None
        without the tower's disturbance.
    """

    tsr: np.ndarray
    pitch: np.ndarray
    cw: np.ndarray
    cp: np.ndarray
    skew: float
    source: str | None = None
    hw: np.ndarray | None = None
    hp: np.ndarray | None = None
    tower: dict | None = None
    r2: np.ndarray | None = None


def rotor_surfaces(rotor: BEMRotor, tsr: Any = None, pitch: Any = None, *, skew: float | None = None,
                   n_azimuth: int = 8, wind_speed: float | None = None, tower: Any = None, unsteady: Any = None
                   ) -> tuple[PerformanceTable, DiskMomentTable | None]:
    """:func:`performance_surface` and :func:`disk_moment_surface` from one BEM solve (None: no skew).

    ``tower``: ``(TowerAero, RotorPlacement)`` whose potential flow or shadow disturbs the blade inflow; the
    thrust and torque surfaces then hold its azimuth average (:mod:`.tower_average`). ``unsteady``:
    ``(UnsteadyNodes, tip speed [m/s])`` of one blade with ``UA_Mod = 3``; the surfaces then hold the airfoils'
    steady state (:mod:`.blade.ua_steady`). Both enter as corrections (:func:`_corrections`).
    """
    tsr_axis = _axis(DEFAULT_TSR if tsr is None else tsr, "tsr")
    pitch_axis = _axis(DEFAULT_PITCH if pitch is None else pitch, "pitch")
    grid_tsr, grid_pitch = np.meshgrid(tsr_axis, pitch_axis, indexing="ij")
    solution = solve_bem(rotor, grid_tsr, grid_pitch, skew=skew, n_azimuth=n_azimuth)
    used_skew = abs(rotor.shaft_tilt) if skew is None else abs(skew)
    source = (f"mbsym steady BEM of {rotor.source or 'a BEMRotor'} (R = {rotor.radius:.4f} m, "
              f"skew {math.degrees(used_skew):.3g} deg, {n_azimuth if used_skew else 1} azimuths)")
    ct, cq = solution.ct, solution.cq
    if tower is not None and skew is not None and not math.isclose(used_skew, abs(rotor.shaft_tilt), abs_tol=1e-12):
        raise ParameterError("the tower's inflow disturbance is averaged for the wind along the ground: leave skew at "
                             "its default (the shaft tilt).")
    if tower is not None or unsteady is not None:
        changes = _corrections(rotor, tsr_axis, pitch_axis, tower, unsteady)
        ct, cq = ct + changes["ct"], cq + changes["cq"]
        if tower is not None:
            source += f"; the tower's potential flow/shadow averaged over {TOWER_AZIMUTHS} azimuths"
        if unsteady is not None:
            source += f"; UA_Mod 3 at its steady state (tip speed {unsteady[1]:g} m/s)"
    table = PerformanceTable(tsr=tsr_axis, pitch=pitch_axis, cp=cq * grid_tsr, ct=ct,
                             cq=cq, wind_speed=wind_speed, source=source)
    extra = {k: changes[k] for k in ("mu", "ms", "fu", "fs")} if tower is not None else None
    if used_skew < 1e-6 or n_azimuth < 2:
        if extra is None:
            return table, None
        zero = np.zeros_like(ct)                # no skew: only the tower's part of the disk's moment
        return table, DiskMomentTable(tsr=tsr_axis, pitch=pitch_axis, cw=zero, cp=zero, skew=0.0, source=source,
                                      hw=zero, hp=zero, tower=extra, r2=thrust_radius2(rotor, solution, used_skew))
    cw, cp, hw, hp = _disk_moment(rotor, solution.fn, solution.ft, used_skew)   # the tower's part: module docstring
    return table, DiskMomentTable(tsr=tsr_axis, pitch=pitch_axis, cw=cw, cp=cp, skew=used_skew, source=source,
                                  hw=hw, hp=hp, tower=extra, r2=thrust_radius2(rotor, solution, used_skew))


def thrust_radius2(rotor: BEMRotor, solution, skew: float) -> np.ndarray:
    """``⟨r²⟩_T / R²`` (:class:`DiskMomentTable` ``r2``) at every point of a :func:`~.bem.solve_bem` solution.

    The wake frozen (each element's induced velocities held, as over a tower period), a change ``δu`` of the
    wind along the shaft changes an element's normal load by ``(∂f_n/∂u) δu``; a tilt or yaw rate ``ω⊥`` moves
    it along the shaft at ``ω⊥ r cos ψ``, so the disk's moment changes by ``−½ Σ ∫ (∂f_n/∂u) r² ds ω⊥``.
    With the derivative ∝ ``r`` along a blade (element speed ∝ r) the ratio would be ``½ (1 + r_hub²/R²)``; the
    chord's taper and the tip loss make it smaller: 0.82-0.85 of that on the NREL 5 MW over its operating
    range (wind 10-18 m/s), which the OpenFAST v5 run of docs/identification.md confirms: the rotor's
    tilt moment against the tower-top rate there is 7.43e7 N m s, this ratio gives 7.2e7, ``½ (R² + r_hub²)/2``
    8.6e7. ``∂f_n/∂u`` by a central difference of the element's normal load at its solved induction.
    """
    g = rotor._geometry  # type: ignore[attr-defined]
    n_azimuth = solution.phi.shape[-2]
    vx, vy, _ = _velocities(rotor, solution.tsr, abs(skew), n_azimuth, None)
    ux, uy = vx * (1.0 - solution.a), vy * (1.0 + solution.ap)
    theta = solution.phi - solution.alpha

    def normal(dux: float) -> np.ndarray:
        phi = np.arctan2(ux + dux, uy)
        coef = _lookup(rotor._tables, phi - theta, rotor._tables["which"])  # type: ignore[attr-defined]
        return 0.5 * ((ux + dux) ** 2 + uy**2) * rotor.chord * (coef[..., 0] * np.cos(phi) + coef[..., 1] * np.sin(phi))

    step = 1e-4
    d = np.nan_to_num((normal(step) - normal(-step)) / (2.0 * step)) * g["cos_cone"]
    d = np.where(np.asarray(g["fixed"]), 0.0, d).mean(axis=-2)            # the azimuth average (..., n)
    length, r = g["length"], g["r"]

    def line(values: np.ndarray) -> np.ndarray:
        return 0.5 * np.sum((values[..., 1:] + values[..., :-1]) * length, axis=-1)

    total = line(d)
    ratio = line(d * r**2) / np.where(np.abs(total) > 1e-12, total, 1.0) / rotor.radius**2
    fallback = 0.5 * (1.0 + (rotor.hub_radius / rotor.radius) ** 2)
    return np.where((np.abs(total) > 1e-12) & np.isfinite(ratio) & (ratio > 0.0) & (ratio < 1.0), ratio, fallback)


def _coarse(axis: np.ndarray, n: int = 16) -> np.ndarray:
    """About ``n`` points of ``axis``, its ends included."""
    return axis[np.unique(np.round(np.linspace(0, axis.size - 1, min(n, axis.size))).astype(int))]


def _corrections(rotor: BEMRotor, tsr: np.ndarray, pitch: np.ndarray, tower: Any = None, unsteady: Any = None
                 ) -> dict[str, np.ndarray]:
    """The change of ``ct``, ``cq`` on the grid ``tsr`` × ``pitch`` by the tower's inflow disturbance (``tower``:
    ``(TowerAero, RotorPlacement)``) and the unsteady airfoils' steady state (``unsteady``: ``(UnsteadyNodes,
    tip speed [m/s])``, :mod:`.blade.ua_steady`, the wind at each tip-speed ratio ``tip speed / λ``); with the tower
    also its disk moment and in-plane force (``mu``, ``ms``, ``fu``, ``fs``: :class:`DiskMomentTable`'s ``tower``).

    Solved with and without them on a coarse grid of ~16 × 16 points (the changes are smooth in both axes) and
    spline-interpolated (cubic where 4 points allow), with :data:`~.tower_average.TOWER_AZIMUTHS` azimuths when the
    tower is in (else 8): a quarter of the full-grid cost; against the full grid on the IEA 15 MW within 6e-5 in
    ``ct`` and 8e-6 in ``cq`` (tests/wind/aero/test_tower_average.py).
    """
    from .blade.ua_steady import steady_airfoil_loads
    from .tower_average import tower_inflow_change

    n_az = TOWER_AZIMUTHS if tower is not None else 8
    change = None if tower is None else tower_inflow_change(
        rotor._geometry, rotor.precone + rotor.curve_angle, tower[1], tower[0], n_az)  # type: ignore[attr-defined]
    ct_, pt_ = _coarse(tsr), _coarse(pitch)
    g_t, g_p = np.meshgrid(ct_, pt_, indexing="ij")
    loads = None if unsteady is None else steady_airfoil_loads(rotor, unsteady[0],
                                                                reference_wind=(unsteady[1] / g_t)[..., None])
    plain = solve_bem(rotor, g_t, g_p, n_azimuth=n_az)
    changed = solve_bem(rotor, g_t, g_p, n_azimuth=n_az, inflow_change=change, airfoil_loads=loads)
    deltas = {"ct": changed.ct - plain.ct, "cq": changed.cq - plain.cq}
    if tower is not None:
        up = -1.0 if tower[1].shaft_tilt > 0 else 1.0               # e_w (the BEM's ψ = 0) is ±e_u: tower_average
        with_tower, without = (_in_plane(rotor, sol.fn, sol.ft) for sol in (changed, plain))
        for key, a, b in zip(("mu", "ms", "fu", "fs"), with_tower, without):
            deltas[key] = up * (a - b)
    out = {}
    for name, delta in deltas.items():
        spline = RectBivariateSpline(ct_, pt_, delta, kx=min(3, ct_.size - 1), ky=min(3, pt_.size - 1))
        out[name] = spline(tsr, pitch)
    return out


def _in_plane(rotor: BEMRotor, fn: np.ndarray, ft: np.ndarray) -> tuple[np.ndarray, ...]:
    """The disk's moment (over ``½ ρ V² π R³``) and in-plane force (over ``½ ρ V² π R²``) along ``e_w``, ``e_p``
    from per-azimuth loads (..., n_azimuth, n) of a 1 m/s, 1 kg/m³ solve (as :func:`_disk_moment`, not per
    ``tan χ``)."""
    cw, cp, hw, hp = _disk_moment(rotor, fn, ft, math.pi / 4.0)       # tan(π/4) = 1
    return cw, cp, hw, hp


def disk_moment_surface(rotor: BEMRotor, tsr: Any = None, pitch: Any = None, *, skew: float | None = None,
                        n_azimuth: int = 8) -> DiskMomentTable:
    """The disk's steady moment coefficients per unit ``tan χ`` (module docstring) on the grid.

    Parameters
    ----------
    rotor, tsr, pitch, skew, n_azimuth
        As :func:`performance_surface` (the skew must be nonzero: default the shaft tilt).

    Raises
    ------
    ParameterError
        A zero skew (no moment to tabulate) or fewer than 2 azimuths.
    """
    table = rotor_surfaces(rotor, tsr, pitch, skew=skew, n_azimuth=n_azimuth)[1]
    if table is None:
        raise ParameterError("the disk's steady moment needs a skewed flow (skew, or the shaft tilt, nonzero) and "
                             "n_azimuth >= 2.")
    return table


def _disk_moment(rotor: BEMRotor, fn: np.ndarray, ft: np.ndarray, skew: float) -> tuple[np.ndarray, ...]:
    """``(c_w, c_p, h_w, h_p)`` per unit ``tan χ`` from the per-azimuth loads (..., n_azimuth, n) of a 1 m/s,
    1 kg/m³ solve: the moment's and the in-plane force's coefficients (module docstring)."""
    g = rotor._geometry  # type: ignore[attr-defined]
    n_azimuth = fn.shape[-2]
    psi = 2.0 * math.pi * (np.arange(n_azimuth) + 0.5) / n_azimuth       # as bem._velocities
    force = fn[..., None] * g["normal"] + ft[..., None] * np.array([0.0, 1.0, 0.0])   # (e_r, e_t, e_x)
    moment = np.cross(g["pos"], force)
    c, s = np.cos(psi)[:, None], np.sin(psi)[:, None]                    # e_r = c e_w + s e_p, e_t = -s e_w + c e_p
    m_w = moment[..., 0] * c - moment[..., 1] * s
    m_p = moment[..., 0] * s + moment[..., 1] * c
    length = g["length"]

    def total(values: np.ndarray) -> np.ndarray:
        per_blade = 0.5 * np.sum((values[..., 1:] + values[..., :-1]) * length, axis=-1)
        return rotor.n_blades * per_blade.mean(axis=-1)

    scale = 0.5 * math.pi * rotor.radius**3 * math.tan(skew)           # ½ ρ V² π R³ tan χ with ρ = V = 1
    f_w = force[..., 0] * c - force[..., 1] * s                          # the in-plane force, e_w and e_p
    f_p = force[..., 0] * s + force[..., 1] * c
    return (total(m_w) / scale, total(m_p) / scale, total(f_w) * rotor.radius / scale,
            total(f_p) * rotor.radius / scale)
