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

Left out (second order in the TP motion, millimetres here): SubDyn's translation correction of the inertia and
damping parts of ``Y1`` (``u_T × (M_BB ü + C_BB u̇)``) and the concentrated masses' rotated offsets beyond
first order. Refused (:class:`~mbsym.exceptions.UnsupportedFeatureError`): Craig–Bampton modes (``Nmodes > 0``:
their states couple through the TP acceleration), HydroDyn or a mooring on the substructure (``CompHydro``,
``CompMooring``: the water's loads act on its nodes), ``SttcSolve = False`` with ``ReactF*`` channels.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path
from typing import Any

import casadi as ca
import numpy as np

from ...exceptions import ModelWarning, UnsupportedFeatureError
from ._casadi import body_motion, euler_zyx
from .operating import PLATFORM_COORDINATES, PLATFORM_INPUTS

__all__ = ["BottomFixedPlatform", "bottom_fixed_platform", "SUBDYN_CHANNELS"]

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

    Examples
    --------
    >>> platform = bottom_fixed_platform(read_openfast("IEA-15-240-RWT-Monopile.fst"))  # doctest: +SKIP
    >>> model = OperatingTurbine(turbine, rotor, platform=platform)                      # doctest: +SKIP
    """

    reduced: Any
    reaction: np.ndarray
    reaction_static: np.ndarray
    source: str = ""

    coordinates = PLATFORM_COORDINATES
    inputs = PLATFORM_INPUTS
    state_names: tuple[str, ...] = ()
    sea_inputs: tuple[str, ...] = ()
    #: Not a floating platform: controllers' prediction models leave its DOFs out (:mod:`mbsym.wind.mpc`).
    floating = False
    n_radiation = 0
    n_lines = 0
    waves = None

    def __post_init__(self) -> None:
        if self.reduced.n_modes:
            raise UnsupportedFeatureError(f"{self.source}: Nmodes = {self.reduced.n_modes} Craig-Bampton modes are "
                                          "not coupled to mbsym's turbine (their states follow the TP's "
                                          "acceleration); set Nmodes = 0 (a Guyan reduction).")

    @property
    def added_mass(self) -> np.ndarray:
        """M_BB (6 × 6) [kg, kg m, kg m²] about the platform reference point: SubDyn's ``−M_BB ü``."""
        return np.asarray(self.reduced.mass, dtype=float)

    @cached_property
    def stiffness(self) -> np.ndarray:
        """``K_BB − G`` plus the translation correction of the weight (6 × 6): the load's slope at rest [SI]."""
        g_full, _ = self.reduced.lever_arm_stiffness()
        return np.asarray(self.reduced.stiffness, dtype=float) - g_full

    def sea_tables(self, t_end: float) -> dict:
        """No sea inputs: {} (HydroDyn on the substructure is refused)."""
        return {}

    @cached_property
    def function(self) -> ca.Function:
        """``(qp, vp, xr, sea) → (load, hydro, xr_dot, tension, mass, sea_out, jac, bias, react)`` (SX, built once);
        the names of :meth:`~.operating.FloatingPlatform.function` plus ``react``, the base reaction."""
        r = self.reduced
        qp, vp = ca.SX.sym("qp", 6), ca.SX.sym("vp", 6)
        xr, sea = ca.SX.sym("xr", 0), ca.SX.sym("sea", 0)
        body, jac, bias = body_motion(qp, vp)
        u = ca.vertcat(qp[:3], _small_angles(euler_zyx(qp[3:6]).T))   # SubDyn's u_TP from ElastoDyn's DCM
        g_full, _ = r.lever_arm_stiffness()
        lever = g_full.copy()
        lever[3:, :3] -= _cross(np.asarray(r.gravity_load[:3], dtype=float))   # step 5 exactly, below
        y = (ca.DM(r.gravity_load) + ca.mtimes(ca.DM(lever - np.asarray(r.stiffness)), u)
             - ca.mtimes(ca.DM(np.asarray(r.damping)), body))
        load = ca.vertcat(y[:3], y[3:] - ca.cross(u[:3], y[:3]))
        react = ca.DM(self.reaction_static) + ca.mtimes(ca.DM(self.reaction), u)
        zero6 = ca.SX.zeros(6)
        return ca.Function("substructure_loads", [qp, vp, xr, sea],
                           [load, zero6, ca.SX(0, 1), ca.SX(0, 1), ca.SX.zeros(6, 6), ca.SX(0, 1), jac, bias, react],
                           ["qp", "vp", "xr", "sea"],
                           ["load", "hydro", "xr_dot", "tension", "mass", "sea_out", "jac", "bias", "react"],
                           {"cse": True})

    def loads(self, qp: Any, vp: Any, xr: Any = None, sea: Any = None) -> dict[str, Any]:
        """The outputs of :attr:`function` by name (CasADi or numeric arguments)."""
        out = self.function(qp, vp, ca.DM(0, 1), ca.DM(0, 1))
        return dict(zip(self.function.name_out(), out))

    def channel_rows(self, loads: dict[str, Any], ap: Any) -> list[tuple[str, str, Any]]:
        """``Intf1FXss … Intf1MZss`` (``−Y1`` with ``−M_BB ü``, ``ü`` from the platform accelerations ``ap``) and
        ``ReactFXss … ReactMZss`` [N, N-m]."""
        inertia = ca.mtimes(ca.DM(self.added_mass), ca.mtimes(loads["jac"], ap) + loads["bias"])
        intf = -(loads["load"] - inertia)
        names = list(SUBDYN_CHANNELS.items())
        rows = [(n, u, intf[k]) for k, (n, u) in enumerate(names[:6])]
        rows += [(n, u, loads["react"][k]) for k, (n, u) in enumerate(names[6:])]
        return rows

    def for_prediction(self) -> "BottomFixedPlatform":
        """The same (no states of its own)."""
        return self

    def __repr__(self) -> str:
        hz = ", ".join(f"{f:.3g}" for f in self.reduced.guyan_frequencies()[:3])
        mass = float(self.reduced.mass[0, 0])
        return f"BottomFixedPlatform(Guyan, TP mass {mass / 1e3:.4g} t, first Guyan frequencies {hz} Hz)"


def _base_reaction(sub) -> tuple[np.ndarray, np.ndarray]:
    """SubDyn's ``ReactF*ss`` as ``R u + r0``: the elastic forces of the full model at the reaction joints, on the
    node displacements ``Φ_TP u`` + the static improvement of the gravity loads, minus their own nodal loads, moved
    to the base point ``(0, 0, −WtrDpth)`` of ``sub`` (SubDyn's ``TIreact``). The full stiffness's rows of the
    locked DOFs give the elements' forces at those joints (the elements meeting there are the only ones that touch
    them)."""
    frame, reduced = sub.frame, sub.reduce()
    fixed = np.asarray(sub.fixed_dofs, dtype=int)
    k_c = np.asarray(frame.stiffness, dtype=float)[fixed]
    shapes = np.asarray(reduced.tp_shapes, dtype=float)
    static = reduced.node_displacements(np.zeros(6), static_loads=frame.gravity_load).reshape(-1)
    forces_u = k_c @ shapes                                   # (6 n_c, 6)
    forces_0 = k_c @ static - np.asarray(frame.gravity_load, dtype=float)[fixed]
    base = np.asarray(sub.base_point, dtype=float)
    R, r0 = np.zeros((6, 6)), np.zeros(6)
    for k in range(len(fixed) // 6):
        node = frame.positions[fixed[6 * k] // 6]
        move = np.eye(6)
        move[3:, :3] = _cross(np.asarray(node, dtype=float) - base)
        R += move @ forces_u[6 * k:6 * k + 6]
        r0 += move @ forces_0[6 * k:6 * k + 6]
    return R, r0


def bottom_fixed_platform(turbine) -> BottomFixedPlatform | None:
    """The :class:`BottomFixedPlatform` of a deck's SubDyn file (``CompSub = 1``), or None without it.

    Parameters
    ----------
    turbine : TurbineParameters
        A deck read by :func:`mbsym.wind.read_openfast` (``CompSub``, ``SubFile``, ``Gravity``, ``WtrDpth``, the
        platform reference point).

    Raises
    ------
    UnsupportedFeatureError
        ``CompSub = 2``, HydroDyn or a mooring with SubDyn, Craig-Bampton modes, and what the SubDyn reader
        and :class:`~.substructure.Substructure` refuse.
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
    on = [f"{k} = {v}" for k, v in (("CompHydro", int(sim.hydrodynamics_model or 0)),
                                     ("CompMooring", int(sim.mooring_model or 0))) if v]
    if on:
        raise UnsupportedFeatureError(f"{where}: {', '.join(on)} with CompSub = 1: the water's and the lines' loads "
                                      "on a SubDyn substructure's nodes are not modelled by mbsym yet; set them to 0 "
                                      "(the substructure in air) or run the deck in OpenFAST.")
    if "subdyn" not in files:
        raise UnsupportedFeatureError(f"{where}: CompSub = 1 (SubDyn) needs its input file, but SubFile names none "
                                      "that exists; give the file or set CompSub = 0.")
    settings = read_subdyn(Path(files["subdyn"]))
    # SubDyn's WtrDpth (the point of its base reactions): SeaState's with HydroDyn, else 0 (the glue code's
    # FAST_Subs.f90, OpenFAST v5.0.0); HydroDyn is refused above, so 0
    sub = Substructure(settings, reference_point=tuple(turbine.platform_reference), gravity=float(sim.gravity),
                       water_depth=0.0)
    reduced = sub.reduce()
    platform = BottomFixedPlatform(reduced, *_base_reaction(sub), source=str(files["subdyn"]))
    _warn_channels(settings, files["subdyn"])
    return platform


def _warn_channels(settings, path) -> None:
    """SubDyn's ``SSOutList`` channels mbsym does not write are named, not dropped silently."""
    requested = [str(c) for c in getattr(settings, "outputs", ()) or ()]
    known = {n.lower() for n in SUBDYN_CHANNELS}
    missing = [c for c in requested if c.lstrip("-").lower().removeprefix("m") not in known
               and c.lstrip("-").lower() not in known]
    if missing:
        warnings.warn(f"{path}: SSOutList channels {missing} are not written by mbsym (it writes "
                      f"{', '.join(SUBDYN_CHANNELS)}).", ModelWarning, stacklevel=3)
