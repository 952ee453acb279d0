"""A bottom-fixed substructure (SubDyn, ``CompSub = 1``) under the platform of a turbine: a platform-loads object.

OpenFAST couples SubDyn to ElastoDyn's six platform DOFs at the transition piece (TP), ElastoDyn's platform
reference point (:mod:`.substructure`). :class:`BottomFixedPlatform` puts SubDyn's output equation with a
**Guyan** reduction (``Nmodes = 0``; the IEA 15 MW monopile's) on those DOFs, the way the operation layer
takes a floating platform (:class:`~.operating.FloatingPlatform`; :mod:`mbsym.wind.operation.compose`):

* the TP load ``Y1 = F_g + G u − K_BB u − C_BB u̇`` on the inputs ``PtfmFx … PtfmMz`` (the reference point,
  inertial axes), then SubDyn's translation correction ``Y1_M −= u_T × Y1_F`` — ``u`` the TP displacement and
  small rotations (SubDyn's ``GetSmllRotAngs`` of ElastoDyn's platform orientation: its roll, pitch and yaw to first
  order, the yaw about roll × pitch / 2 apart), ``u̇`` its velocity and angular velocity (exact, from the Euler rates:
  :func:`~._casadi.body_motion`), ``F_g`` the TP's share of the substructure's weight, ``G`` the lever arms of
  the nodal weights on the Guyan displacements (:meth:`~.substructure.ReducedSubstructure.lever_arm_stiffness`);
* ``M_BB`` in the platform block of the symbolic mass matrix as ``Jᵀ M_BB J`` (with ``−Jᵀ M_BB b``), where a
  floating platform has A∞: SubDyn's ``−M_BB ü``;
* channels ``Intf1FXss … Intf1MZss`` (SubDyn's: ``−Y1`` with the inertia) and the base reactions ``ReactFXss …
  ReactMZss`` (SubDyn's: the elastic forces of the elements at the reaction joint, without inertia, on the node
  displacements ``Φ_TP u`` plus the static improvement of the gravity loads, ``SttcSolve``) about
  ``(0, 0, −WtrDpth)``, SubDyn's ``WtrDpth`` being SeaState's with HydroDyn and 0 without (OpenFAST's glue code):
  here, without HydroDyn, the origin at the mean sea level.

**HydroDyn on the substructure** (``CompHydro = 1`` with ``PotMod = 0``; :mod:`.substructure_water`: HydroDyn's
Morison loads mapped onto SubDyn's nodes as OpenFAST maps them): its nodal added mass ``A`` joins the mass matrix at
the TP as ``Φ_TPᵀ A Φ_TP`` (symmetric part; HydroDyn's is asymmetric by 1e-5), its static loads (buoyancy, the
filled fluid, marine growth, a steady current's drag) join ``Y1`` through ``Φ_TPᵀ`` with their lever arms, the
drag's mean slope ``B`` on the nodes' velocity (the current's and the waves'; :mod:`.substructure_current`) damps
the structure as ``−Φ_TPᵀ B Φ_TP u̇`` (and through the CB modes, below), and the sea enters as inputs:
``TPWaveFxi … TPWaveMzi`` (the waves' loads on the structure at rest, ``Φ_TPᵀ F``), ``HydroWaveFxi … HydroWaveMzi``
(their sum about the origin, for HydroDyn's ``HydroFxi … HydroMzi`` channels), ``ReactWaveFXss … ReactWaveMZss``
(their share of the base reactions) and ``Wave1Elev``, tabulated from SeaState's sea by :meth:`sea_tables` (the drag
of the water's velocity at rest, waves and current). The base reactions and HydroDyn's sums also take the water's
added-mass and drag-slope loads on the interior through SubDyn's static improvement (``R_a ü``, ``R_b u̇``).

**Craig–Bampton modes** (``Nmodes > 0``): their coordinates ``q`` and rates are states ``SSqm01 …``, ``SSqmd01 …``
with SubDyn's ``q̈ = Φ_mᵀ F − M_mB ü − C_mm q̇ − K_mm q`` (``F`` the nodal loads with their lever arms). With the
water's nodal added mass ``A`` among the loads this is ``N q̈ = g − P ü`` (``N = I + Φ_mᵀ A Φ_m``, ``P = M_mB +
Φ_mᵀ A Φ_TP``, ``g`` the rest) and ``Y1 −= Q q̈`` (``Q = M_Bm + Φ_TPᵀ A Φ_m``): ``−Q N⁻¹ g`` is a load and
``Q N⁻¹ P`` leaves the TP's mass (the coupled mass matrix's Schur complement); the turbine adds ``−N⁻¹ P (J q̈_p +
b)`` to the modes' accelerations once the structure's are solved (``xr_acc``). The waves' modal loads are inputs
``CBWave01 …``. The drag's slope ``B`` adds ``−Φ_mᵀ B (Φ_TP u̇ + Φ_m q̇)`` to ``g`` and ``−Φ_TPᵀ B Φ_m q̇`` to
``Y1``. The base reactions take ``K_C Φ_CB q`` (and the water's added-mass loads of ``q̈`` through the static
improvement), which is SubDyn's with the modes' part taken out.

Left out (second order in the TP motion, millimetres here): SubDyn's translation correction of the inertia and
damping parts of ``Y1`` (``u_T × (M_BB ü + C_BB u̇)``), the concentrated masses' rotated offsets beyond first order
and the wave loads' lever arms. Refused (:class:`~mbsym.exceptions.UnsupportedFeatureError`): a mooring on the
substructure, what :func:`~.substructure_water.substructure_water_problems` refuses of HydroDyn.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path
from typing import Any

import casadi as ca
import numpy as np

from ...exceptions import ModelWarning, UnsupportedFeatureError
from ._casadi import body_motion, euler_zyx
from .operating import HYDRO_CHANNELS, PLATFORM_COORDINATES, PLATFORM_INPUTS

__all__ = ["BottomFixedPlatform", "bottom_fixed_platform", "SUBDYN_CHANNELS", "SEA_INPUTS"]

#: The sea's inputs of a bottom-fixed platform with HydroDyn's waves (module docstring) [N, N m, m].
SEA_INPUTS = (*(f"TPWave{c}i" for c in ("Fx", "Fy", "Fz", "Mx", "My", "Mz")),
              *(f"HydroWave{c}i" for c in ("Fx", "Fy", "Fz", "Mx", "My", "Mz")),
              *(f"ReactWave{c}ss" for c in ("FX", "FY", "FZ", "MX", "MY", "MZ")), "Wave1Elev")

#: SubDyn's channels this platform writes (OpenFAST's units).
SUBDYN_CHANNELS = {**{f"Intf1{c}ss": u for c, u in (("FX", "N"), ("FY", "N"), ("FZ", "N"), ("MX", "N-m"),
                                                      ("MY", "N-m"), ("MZ", "N-m"))},
                   **{f"React{c}ss": u for c, u in (("FX", "N"), ("FY", "N"), ("FZ", "N"), ("MX", "N-m"),
                                                      ("MY", "N-m"), ("MZ", "N-m"))}}


def _small_angles(dcm):
    """OpenFAST's ``GetSmllRotAngs`` of a DCM (global → rotated axes), as SubDyn takes the TP's rotation from
    ElastoDyn's orientation: ``(d₁₂ − d₂₁, d₂₀ − d₀₂, d₀₁ − d₁₀) / √(tr d + 1)`` (0-based); ElastoDyn's roll, pitch
    and yaw to first order (the yaw differs by about roll × pitch / 2)."""
    return ca.vertcat(dcm[1, 2] - dcm[2, 1], dcm[2, 0] - dcm[0, 2], dcm[0, 1] - dcm[1, 0]) / \
        ca.sqrt(dcm[0, 0] + dcm[1, 1] + dcm[2, 2] + 1.0)


def _cross(v) -> np.ndarray:
    x, y, z = v
    return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])


def _translation(force6) -> np.ndarray:
    """The slope of SubDyn's translation correction ``M −= u_T × F`` for a constant TP force ``F`` (6 × 6)."""
    out = np.zeros((6, 6))
    out[3:, :3] = _cross(np.asarray(force6, dtype=float)[:3])
    return out


def _nodal_lever_change(reduced, nodal_forces) -> np.ndarray:
    """SubDyn's lever-arm moments ``Δu_k × f_k`` of constant nodal forces at the nodes per unit TP DOF (6 N × 6)."""
    n = reduced.frame.n_nodes
    forces = np.asarray(nodal_forces, dtype=float).reshape(n, 6)[:, :3]
    shapes = np.asarray(reduced.tp_shapes, dtype=float).reshape(n, 6, 6)
    change = np.zeros((n, 6, 6))
    for k in range(n):
        change[k, 3:] = -_cross(forces[k]) @ shapes[k, :3]
    return change.reshape(6 * n, 6)


def _lever_arms(reduced, nodal_forces) -> np.ndarray:
    """``Φ_TPᵀ`` of SubDyn's lever-arm moments ``Δu_k × f_k`` of constant nodal forces, per unit TP DOF (6 × 6)."""
    return np.asarray(reduced.tp_shapes, dtype=float).T @ _nodal_lever_change(reduced, nodal_forces)


def _reactions(sub, nodal) -> np.ndarray:
    """SubDyn's base reactions ``(..., 6)`` of the substructure held at rest (TP and modes at 0) under gravity and
    ``nodal`` loads ``(..., 6 N)``: the elements' elastic forces at the reaction joints on SubDyn's static improvement
    of the interior (``SttcSolve``; none without it), less the joints' own external loads, about the base point."""
    reduced, frame = sub.reduce(), sub.frame
    loads = np.atleast_2d(np.asarray(nodal, dtype=float))
    fixed = np.asarray(sub.fixed_dofs, dtype=int)
    k_c = np.asarray(frame.stiffness, dtype=float)[fixed]
    gravity = np.asarray(frame.gravity_load, dtype=float)
    out = np.zeros((len(loads), 6))
    for row, external in zip(out, loads):
        disp = reduced.node_displacements(np.zeros(6), static_loads=external + gravity).reshape(-1) \
            if sub.settings.static_improvement else np.zeros(len(gravity))
        row += _to_base(sub, k_c @ disp - external[fixed])
    return out.reshape(*np.shape(nodal)[:-1], 6)


def _to_base(sub, forces) -> np.ndarray:
    """Loads at the reaction joints' DOFs (``6 n_c``, or ``(6 n_c, m)``) moved to the base point (SubDyn's
    ``TIreact``)."""
    fixed = np.asarray(sub.fixed_dofs, dtype=int)
    forces = np.asarray(forces, dtype=float)
    out = np.zeros((6, *forces.shape[1:]))
    for k in range(len(fixed) // 6):
        move = np.eye(6)
        move[3:, :3] = _cross(np.asarray(sub.frame.positions[fixed[6 * k] // 6], dtype=float)
                              - np.asarray(sub.base_point, dtype=float))
        out += move @ forces[6 * k:6 * k + 6]
    return out


def _wave_reactions(sub, nodal) -> np.ndarray:
    """The waves' share of SubDyn's base reactions ``(len, 6)``: the reactions under the loads less those at rest."""
    return _reactions(sub, nodal) - _reactions(sub, np.zeros(nodal.shape[1]))


def _water_terms(sub, reduced, water, drag_damping: bool = True) -> dict:
    """The water's TP-level arrays (:class:`BottomFixedPlatform`'s ``water_terms``; with CB modes also their modal
    parts: ``A_mm``, ``A_mB``, ``A_Bm``, ``modal_static``, ``modal_lever``, ``reaction_qdd``, ``hydro_qdd``; with
    ``drag_damping`` and a nonzero slope of the drag, :meth:`~.substructure_water.SubstructureWater.drag_damping`
    ``B`` as ``damping`` = ``Φ_TPᵀ B Φ_TP``, ``reaction_vel``, ``hydro_vel`` and the modes' ``B_mm``, ``B_mB``,
    ``B_Bm``, ``reaction_qd``, ``hydro_qd``)."""
    shapes, modes = np.asarray(reduced.tp_shapes, dtype=float), np.asarray(reduced.modal_shapes, dtype=float)
    static = np.asarray(water.static_loads, dtype=float)
    added = np.asarray(water.added_mass, dtype=float)
    per_acc = -added @ shapes                                          # nodal loads per unit TP acceleration
    rest = _reactions(sub, np.zeros(len(static)))
    terms = {"mass": water.tp_added_mass(symmetric=True), "static": shapes.T @ static,
             "lever": _lever_arms(reduced, static), "reaction_acc": (_reactions(sub, per_acc.T) - rest).T,
             "hydro_static": water.resultant(static), "hydro_acc": water.resultant(per_acc.T).T}
    if reduced.n_modes:
        per_qdd = -added @ modes                                       # ... per unit CB acceleration
        terms.update(A_mm=modes.T @ added @ modes, A_mB=modes.T @ added @ shapes, A_Bm=shapes.T @ added @ modes,
                     modal_static=modes.T @ static, modal_lever=modes.T @ _nodal_lever_change(reduced, static),
                     reaction_qdd=(_reactions(sub, per_qdd.T) - rest).T, hydro_qdd=water.resultant(per_qdd.T).T)
    damping = water.drag_damping() if drag_damping else None
    if damping is not None and np.any(damping):                        # the drag's slope on the nodes' velocities
        per_vel = -damping @ shapes
        terms.update(damping=shapes.T @ damping @ shapes, reaction_vel=(_reactions(sub, per_vel.T) - rest).T,
                     hydro_vel=water.resultant(per_vel.T).T)
        if reduced.n_modes:
            per_qd = -damping @ modes
            terms.update(B_mm=modes.T @ damping @ modes, B_mB=modes.T @ damping @ shapes,
                         B_Bm=shapes.T @ damping @ modes, reaction_qd=(_reactions(sub, per_qd.T) - rest).T,
                         hydro_qd=water.resultant(per_qd.T).T)
    return terms


@dataclass(frozen=True, eq=False)
class BottomFixedPlatform:
    """SubDyn's Guyan-reduced substructure on the platform DOFs (module docstring).

    Parameters
    ----------
    reduced : ReducedSubstructure
        :meth:`~.substructure.Substructure.guyan` of the deck's SubDyn file (``Nmodes = 0``).
    reaction : (6, 6) ndarray
        The base reaction per unit TP displacement [N/m, N/rad, N m/m, N m/rad] (SubDyn's ``ReactF*ss``).
    reaction_static : (6,) ndarray
        The base reaction at ``u = 0`` [N, N m] (the gravity loads with the static improvement).
    source : str
        The SubDyn file.
    water : SubstructureWater, optional
        HydroDyn's loads on the nodes (:func:`~.substructure_water.substructure_hydrodynamics`).
    substructure : Substructure, optional
        The full model (for the waves' share of the base reactions).
    water_terms : dict
        The water's TP-level arrays (:func:`_water_terms`): ``mass``, ``static``, ``lever``, ``reaction_acc``,
        ``hydro_static``, ``hydro_acc``.
    modal_reaction : (6, n) ndarray, optional
        The base reaction per CB coordinate (Craig–Bampton modes).

    Examples
    --------
    >>> platform = bottom_fixed_platform(read_openfast("IEA-15-240-RWT-Monopile.fst"))  # doctest: +SKIP
    >>> model = OperatingTurbine(turbine, rotor, platform=platform)                      # doctest: +SKIP
    """

    reduced: Any
    reaction: np.ndarray
    reaction_static: np.ndarray
    source: str = ""
    water: Any = None
    substructure: Any = None
    water_terms: dict = field(default_factory=dict)
    modal_reaction: np.ndarray | None = None

    coordinates = PLATFORM_COORDINATES
    inputs = PLATFORM_INPUTS
    #: Not a floating platform: controllers' prediction models leave its DOFs out (:mod:`mbsym.wind.mpc`).
    floating = False
    n_radiation = 0
    n_lines = 0

    @property
    def n_modes(self) -> int:
        """Craig–Bampton modes kept (``Nmodes``)."""
        return int(self.reduced.n_modes)

    @property
    def state_names(self) -> tuple[str, ...]:
        """The CB coordinates ``SSqm01 …`` [√kg m] and their rates ``SSqmd01 …`` (SubDyn's names); () for Guyan."""
        n = self.n_modes
        return tuple(f"SSqm{k:02d}" for k in range(1, n + 1)) + tuple(f"SSqmd{k:02d}" for k in range(1, n + 1))

    @property
    def waves(self):
        """SeaState's sea (:class:`~.waves.IncidentWaves`), None in still water or without HydroDyn."""
        return None if self.water is None else self.water.waves

    @property
    def sea_inputs(self) -> tuple[str, ...]:
        """:data:`SEA_INPUTS` with HydroDyn's waves (and the waves' modal loads ``CBWave01 …`` with CB modes), else
        ()."""
        if self.waves is None:
            return ()
        return SEA_INPUTS + tuple(f"CBWave{k:02d}" for k in range(1, self.n_modes + 1))

    @cached_property
    def modal(self) -> dict:
        """The CB modes' couplings with the water's added mass ``A`` (module docstring): ``N⁻¹ = (I + Φ_mᵀ A Φ_m)⁻¹``,
        ``P = M_mB + Φ_mᵀ A Φ_TP`` (n × 6), ``Q = M_Bm + Φ_TPᵀ A Φ_m`` (6 × n)."""
        r, w, n = self.reduced, self.water_terms, self.n_modes
        coupling = np.asarray(r.mass_coupling, dtype=float).reshape(6, n)
        N = np.eye(n) + w.get("A_mm", np.zeros((n, n)))
        return {"N_inv": np.linalg.inv(N), "P": coupling.T + w.get("A_mB", np.zeros((n, 6))),
                "Q": coupling + w.get("A_Bm", np.zeros((6, n)))}

    @property
    def added_mass(self) -> np.ndarray:
        """``M_BB + Φ_TPᵀ A Φ_TP − Q N⁻¹ P`` (6 × 6) [kg, kg m, kg m²] about the platform reference point: the TP's
        inertia with the water's added mass, less the CB modes' share, which their states carry (module docstring;
        symmetric part)."""
        m = self.modal
        out = np.asarray(self.reduced.mass, dtype=float) + self.water_terms.get("mass", 0.0)
        out = out - m["Q"] @ m["N_inv"] @ m["P"]
        return 0.5 * (out + out.T)

    @cached_property
    def stiffness(self) -> np.ndarray:
        """``K_BB − G`` (the weights' and the water's static loads' lever arms, the translation correction of the TP's
        static force) (6 × 6): the load's slope at rest [SI]."""
        g_full, _ = self.reduced.lever_arm_stiffness()
        water = self.water_terms.get("lever", 0.0)
        static = self.water_terms.get("static", np.zeros(6))
        return np.asarray(self.reduced.stiffness, dtype=float) - g_full - water - _translation(static)

    def sea_tables(self, t_end: float) -> dict[str, tuple[np.ndarray, np.ndarray]]:
        """Inputs ``name → (t, values)`` of :attr:`sea_inputs` on SeaState's grid over ``[0, t_end]`` [s] ({} in still
        water): the waves' loads at the TP, their sum about the origin, their share of the base reactions, the
        elevation at the origin."""
        if self.waves is None:
            return {}
        grid = self.water.times()
        t = grid[: int(np.searchsorted(grid, t_end, side="right")) + 1]
        nodal = self.water.wave_loads(t)
        columns = np.column_stack([nodal @ np.asarray(self.reduced.tp_shapes, dtype=float),
                                   self.water.resultant(nodal), _wave_reactions(self.substructure, nodal),
                                   np.interp(t, self.waves.times(), self.waves.elevation()),
                                   nodal @ np.asarray(self.reduced.modal_shapes, dtype=float)])
        return {name: (t, columns[:, k]) for k, name in enumerate(self.sea_inputs)}

    @cached_property
    def function(self) -> ca.Function:
        """``(qp, vp, xr, sea) → (load, hydro, xr_dot, tension, mass, sea_out, jac, bias, react)`` (SX, built once);
        the names of :meth:`~.operating.FloatingPlatform.function` plus ``react``, the base reaction."""
        r, w, n = self.reduced, self.water_terms, self.n_modes
        qp, vp = ca.SX.sym("qp", 6), ca.SX.sym("vp", 6)
        xr, sea = ca.SX.sym("xr", 2 * n), ca.SX.sym("sea", len(self.sea_inputs))
        body, jac, bias = body_motion(qp, vp)
        u = ca.vertcat(qp[:3], _small_angles(euler_zyx(qp[3:6]).T))   # SubDyn's u_TP from ElastoDyn's DCM
        static = np.asarray(r.gravity_load, dtype=float) + w.get("static", 0.0)
        g_full, _ = r.lever_arm_stiffness()
        lever = g_full - _translation(np.asarray(r.gravity_load, dtype=float)) + w.get("lever", 0.0)  # step 5 below
        y = (ca.DM(static) + ca.mtimes(ca.DM(lever - np.asarray(r.stiffness)), u)
             - ca.mtimes(ca.DM(np.asarray(r.damping)), body))
        react = ca.DM(self.reaction_static) + ca.mtimes(ca.DM(self.reaction), u)
        hydro = ca.DM(w.get("hydro_static", np.zeros(6)))
        if "damping" in w:                            # the drag's slope on the structure's velocity (current)
            y = y - ca.mtimes(ca.DM(w["damping"]), body)
            react = react + ca.mtimes(ca.DM(w["reaction_vel"]), body)
            hydro = hydro + ca.mtimes(ca.DM(w["hydro_vel"]), body)
        if self.sea_inputs:                           # the waves' loads on the structure at rest (module docstring)
            y, hydro, react = y + sea[0:6], hydro + sea[6:12], react + sea[12:18]
        xr_dot, xr_acc = ca.SX(0, 1), ca.SX(0, 6)
        if n:                                         # CB modes: N q̈ = g − P ü; Y1 −= Q q̈ (Q N⁻¹ P out of the mass)
            q, qd, m = xr[:n], xr[n:], self.modal
            _, modal_lever = r.lever_arm_stiffness()
            g = (ca.DM(r.modal_gravity_load + w.get("modal_static", 0.0))
                 + ca.mtimes(ca.DM(modal_lever + w.get("modal_lever", 0.0)), u)
                 - ca.DM(2.0 * r.damping_ratios * r.frequencies) * qd - ca.DM(r.frequencies ** 2) * q)
            if self.sea_inputs:
                g = g + sea[len(SEA_INPUTS):]
            if "damping" in w:
                g = g - ca.mtimes(ca.DM(w["B_mB"]), body) - ca.mtimes(ca.DM(w["B_mm"]), qd)
                y = y - ca.mtimes(ca.DM(w["B_Bm"]), qd)
                react = react + ca.mtimes(ca.DM(w["reaction_qd"]), qd)
                hydro = hydro + ca.mtimes(ca.DM(w["hydro_qd"]), qd)
            free = ca.mtimes(ca.DM(m["N_inv"]), g)
            y = y - ca.mtimes(ca.DM(m["Q"]), free)
            react = react + ca.mtimes(ca.DM(self.modal_reaction), q)
            xr_dot = ca.vertcat(qd, free)
            xr_acc = ca.vertcat(ca.DM.zeros(n, 6), -ca.DM(m["N_inv"] @ m["P"]))
        load = ca.vertcat(y[:3], y[3:] - ca.cross(u[:3], y[:3]))
        return ca.Function("substructure_loads", [qp, vp, xr, sea],
                           [load, hydro, xr_dot, ca.SX(0, 1), ca.SX.zeros(6, 6), sea, jac, bias, react, xr_acc],
                           ["qp", "vp", "xr", "sea"],
                           ["load", "hydro", "xr_dot", "tension", "mass", "sea_out", "jac", "bias", "react",
                            "xr_acc"], {"cse": True})

    def loads(self, qp: Any, vp: Any, xr: Any = None, sea: Any = None) -> dict[str, Any]:
        """The outputs of :attr:`function` by name (CasADi or numeric arguments; ``xr`` default the CB modes at 0,
        ``sea`` default 0: still water). Without CB modes ``xr_acc`` is left out."""
        sea = ca.DM.zeros(len(self.sea_inputs)) if sea is None else sea
        xr = ca.DM.zeros(2 * self.n_modes) if xr is None or not self.n_modes else xr
        out = dict(zip(self.function.name_out(), self.function(qp, vp, xr, sea)))
        if not self.n_modes:
            out.pop("xr_acc")
        return out

    def channel_rows(self, loads: dict[str, Any], ap: Any) -> list[tuple[str, str, Any]]:
        """``Intf1FXss … Intf1MZss`` (``−Y1`` with ``−M_BB ü``, ``ü`` from the platform accelerations ``ap``) and
        ``ReactFXss … ReactMZss`` [N, N-m]."""
        acc = ca.mtimes(loads["jac"], ap) + loads["bias"]
        intf = -(loads["load"] - ca.mtimes(ca.DM(self.added_mass), acc))
        react = loads["react"] + ca.mtimes(ca.DM(self.water_terms.get("reaction_acc", np.zeros((6, 6)))), acc)
        n, qdd = self.n_modes, None
        if n and self.water is not None:              # the water's added-mass loads of the modes' accelerations
            qdd = loads["xr_dot"][n:] + ca.mtimes(loads["xr_acc"][n:, :], acc)
            react = react + ca.mtimes(ca.DM(self.water_terms["reaction_qdd"]), qdd)
        names = list(SUBDYN_CHANNELS.items())
        rows = [(n, u, intf[k]) for k, (n, u) in enumerate(names[:6])]
        rows += [(n, u, react[k]) for k, (n, u) in enumerate(names[6:])]
        if self.water is not None:                  # HydroDyn's total about the origin, with its added mass
            hydro = loads["hydro"] + ca.mtimes(ca.DM(self.water_terms["hydro_acc"]), acc)
            if qdd is not None:
                hydro = hydro + ca.mtimes(ca.DM(self.water_terms["hydro_qdd"]), qdd)
            rows += [(n, u, hydro[k]) for k, (n, u) in enumerate(HYDRO_CHANNELS.items())]
        if self.sea_inputs:
            rows.append(("Wave1Elev", "m", loads["sea_out"][18]))
        return rows

    def for_prediction(self) -> "BottomFixedPlatform":
        """The same (no states of its own)."""
        return self

    def __repr__(self) -> str:
        hz = ", ".join(f"{f:.3g}" for f in self.reduced.guyan_frequencies()[:3])
        mass = float(self.reduced.mass[0, 0])
        water = "" if self.water is None else (", HydroDyn in still water" if self.waves is None else
                                               ", HydroDyn in waves")
        return f"BottomFixedPlatform(Guyan, TP mass {mass / 1e3:.4g} t, first Guyan frequencies {hz} Hz{water})"


def _base_reaction(sub, static_loads=None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """SubDyn's ``ReactF*ss`` as ``R u + R_m q + r0``: the elastic forces of the full model at the reaction joints on
    the node displacements ``Φ_TP u + Φ_CB q`` (the locked DOFs' rows of the stiffness: the elements meeting there are
    the only ones that touch them), moved to the base point ``(0, 0, −WtrDpth)`` of ``sub`` (SubDyn's ``TIreact``),
    and at rest under gravity and ``static_loads`` (6 N; :func:`_reactions`)."""
    frame, reduced = sub.frame, sub.reduce()
    k_c = np.asarray(frame.stiffness, dtype=float)[np.asarray(sub.fixed_dofs, dtype=int)]
    R = _to_base(sub, k_c @ np.asarray(reduced.tp_shapes, dtype=float))
    R_m = _to_base(sub, k_c @ np.asarray(reduced.modal_shapes, dtype=float)) if reduced.n_modes else np.zeros((6, 0))
    static = np.zeros(6 * frame.n_nodes) if static_loads is None else np.asarray(static_loads, dtype=float)
    return R, _reactions(sub, static), R_m


def bottom_fixed_platform(turbine) -> BottomFixedPlatform | None:
    """The :class:`BottomFixedPlatform` of a deck's SubDyn file (``CompSub = 1``), or None without it.

    Parameters
    ----------
    turbine : TurbineParameters
        A deck read by :func:`mbsym.wind.read_openfast` (``CompSub``, ``SubFile``, ``CompHydro``, ``HydroFile``,
        ``SeaStFile``, ``Gravity``, ``WtrDens``, ``WtrDpth``, the platform reference point).

    Raises
    ------
    UnsupportedFeatureError
        ``CompSub = 2``, a mooring with SubDyn, Craig-Bampton modes, and what the SubDyn and HydroDyn readers,
        :class:`~.substructure.Substructure` and :func:`~.substructure_water.substructure_hydrodynamics` refuse.
    """
    from ..deck.subdyn import read_subdyn
    from .substructure import Substructure

    sim, files = turbine.simulation, turbine.source_files
    mode = int(getattr(sim, "substructure_model", 0) or 0)
    if not mode:
        return None
    where = files.get("fst", "the deck")
    if mode != 1:
        raise UnsupportedFeatureError(f"{where}: CompSub = {mode} (external platform MCKF) is not modelled; use "
                                      "CompSub = 1 (SubDyn) or 0.")
    if int(sim.mooring_model or 0):
        raise UnsupportedFeatureError(f"{where}: CompMooring = {sim.mooring_model} with CompSub = 1: mooring lines on "
                                      "a SubDyn substructure's nodes are not modelled by mbsym; set CompMooring = 0.")
    for key, name in (("subdyn", "CompSub = 1 (SubDyn)"), *((("hydrodyn", "CompHydro = 1 (HydroDyn)"),)
                                                            if sim.hydrodynamics_model else ())):
        if key not in files:
            raise UnsupportedFeatureError(f"{where}: {name} needs its input file, but the .fst names none that "
                                          "exists; give the file or set the switch to 0.")
    settings = read_subdyn(Path(files["subdyn"]))
    hydro, sea, depth = _hydrodyn_inputs(turbine) if sim.hydrodynamics_model else (None, None, 0.0)
    # SubDyn's WtrDpth (the point of its base reactions): SeaState's with HydroDyn, else 0 (the glue code's
    # FAST_Subs.f90, OpenFAST v5.0.0)
    sub = Substructure(settings, reference_point=tuple(turbine.platform_reference), gravity=float(sim.gravity),
                       water_depth=depth)
    reduced = sub.reduce()
    water, terms = None, {}
    if hydro is not None:
        from .substructure_water import substructure_hydrodynamics


        water = substructure_hydrodynamics(hydro, sea, sub, water_density=float(sim.water_density),
                                           gravity=float(sim.gravity), water_depth=depth,
                                           msl_to_swl=float(sim.msl_to_swl or 0.0))
        terms = _water_terms(sub, reduced, water)
    static = None if water is None else water.static_loads
    R, r0, R_m = _base_reaction(sub, static)
    platform = BottomFixedPlatform(reduced, R, r0, source=str(files["subdyn"]), water=water, substructure=sub,
                                   water_terms=terms, modal_reaction=R_m)
    _warn_channels(settings, files["subdyn"])
    return platform


def _hydrodyn_inputs(turbine):
    """HydroDyn's and SeaState's inputs of the deck and SeaState's water depth (its own, else the ``.fst``'s)."""
    from ..deck.hydrodyn import read_hydrodyn
    from ..deck.seastate import read_seastate
    from .platform import _depth

    files, sim = turbine.source_files, turbine.simulation
    sea = read_seastate(Path(files["seastate"])) if "seastate" in files else None
    depth = _depth(sea, sim.water_depth)
    if depth is None:
        raise UnsupportedFeatureError(f"{files.get('fst', 'the deck')}: HydroDyn on SubDyn needs the water depth "
                                      "(SeaState's WtrDpth or the .fst's); give one.")
    return read_hydrodyn(Path(files["hydrodyn"])), sea, depth


def _warn_channels(settings, path) -> None:
    """SubDyn's ``SSOutList`` channels mbsym does not write are named, not dropped silently."""
    requested = [str(c) for c in getattr(settings, "outputs", ()) or ()]
    known = {n.lower() for n in SUBDYN_CHANNELS}
    missing = [c for c in requested if c.lstrip("-").lower().removeprefix("m") not in known
               and c.lstrip("-").lower() not in known]
    if missing:
        warnings.warn(f"{path}: SSOutList channels {missing} are not written by mbsym (it writes "
                      f"{', '.join(SUBDYN_CHANNELS)}).", ModelWarning, stacklevel=3)
