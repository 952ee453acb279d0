"""ServoDyn's structural controllers (StC): tuned mass dampers and prescribed loads on the nacelle, tower, platform.

Each StC is a point P fixed to a body of the structure (``NStC``: the nacelle, at ``StC_P_X/Y/Z`` in its axes from
the yaw-bearing point, ElastoDyn's ``NacelleMotion``; ``TStC``: the flexible tower, at ``StC_P_X/Y/Z`` from the tower
base ``(0, 0, TowerBsHt)`` in its axes, ElastoDyn's ``TowerLn2Mesh``; ``SStC``: the platform, from its reference
point ``(0, 0, PtfmRefzt)``, ElastoDyn's ``PlatformPtMesh``) carrying masses that move relative to P in P's axes. Their
states are ServoDyn's ``StC_x``: ``x, ẋ, y, ẏ, z, ż`` [m, m/s] (channels ``NStC1_XQ``, ``TStC1_XQD`` …). With P's
acceleration ``r̈``, angular velocity ω, angular acceleration α and gravity ``g`` (ground ``(0, 0, −g)``) all
resolved in P's axes (OpenFAST v5.0.0 ``StrucCtrl.f90``, ``StC_CalcContStateDeriv``; the facts only, the code is
mbsym's):

* ``StC_DOF_MODE = 1`` (independent X, Y, Z masses ``M_X``, ``M_Y``, ``M_Z``; a DOF switched off keeps its initial
  value): ``ẍ = (ω_y² + ω_z² − K_X/M_X) x − C_X/M_X ẋ + g_x − r̈_x + F_stop,x/M_X`` (and alike for y, z, the z one
  with ``+ PreLd/M_Z``). Each mass is rigid across its own DOF, so the structure gets its spring and damper force
  along the DOF and, across it, the mass's weight and inertia including the Euler and Coriolis terms of its offset
  (``StC_CalcOutput``); the moment about P is that of those transverse forces at the masses' offsets.
* ``StC_DOF_MODE = 2`` (one omni-directional mass ``StC_Omni_M`` in the XY plane, spring ``K_X``, ``K_Y``): the x
  and y equations above plus ``−(ω_xω_y ∓ α_z) y ± 2ω_z ẏ`` coupling; the structure gets ``K x + C ẋ − F_stop`` in
  the plane and the mass's vertical weight and inertia, the moment ``r × F`` with ``r = (x, y, 0)``.
* ``StC_DOF_MODE = 3`` (omni-directional XYZ): ``r̈ = (−K r − C ṙ + F_stop)/M + g − r̈_P − ω×(ω×r) − α×r − 2ω×ṙ``
  (plus ``PreLd/M`` along z), the structure gets ``K r + C ṙ − F_stop`` (minus ``PreLd`` along z) and ``r × F``.
* Stops: beyond ``StC_*_PSP`` or below ``StC_*_NSP`` a spring ``StC_*_KS`` pushes the mass back, and a damper
  ``StC_*_CS`` acts while it moves further out (``StC_CalcStopForce``).
* ``StC_DOF_MODE = 6`` (prescribed force): no states (ServoDyn holds them at zero; the channels ``*_XQ`` … are 0);
  the force and moment of ``PrescribedForcesFile`` (``t Fx Fy Fz Mx My Mz``, interpolated linearly in time and held
  beyond its ends, NWTC's ``InterpStp``) act at P, in ground axes (``PrescribedForcesCoordSys = 1``) or P's axes
  (2). mbsym gives the model the inputs ``<name>_Fx`` … ``<name>_Mz`` [N, N m] (:meth:`StructuralControls.tables`
  feeds them the file in a simulation; zero in trims and linear models unless given). The channels ``*l`` are the
  file's values as given (ServoDyn's ``m%F_P``), the channels ``*i`` the load in ground axes.

The tower point (TStC): OpenFAST maps ElastoDyn's tower line mesh onto P (``MapMotionMesh``, line-to-point:
displacements interpolated linearly between the tower nodes, the orientation by its log map, P's offset from the
tower axis carried rigidly) and the StC's load back onto the nearest of ElastoDyn's tower load points (``MapLoadMesh``
to ``TowerPtLoads``, the force with its moment about that node). mbsym moves P with ElastoDyn's tower shapes
interpolated linearly between the nodes as well (:func:`~mbsym.wind.structure.tower_points.tower_point_shapes`),
turns it by ElastoDyn's small rotation of the slopes there (``SmllRotTrans``; angular velocity the slope rates), and
applies the load at P itself: the same as OpenFAST's lumping when P is at a node height (``(k − ½) TowerHt /
TwrNodes`` above the base on an even grid), within ``O((Δh/H)²)`` of it otherwise (Δh the node spacing).

The StC's load on P is mapped onto the body as the glue code does (``MapLoadMesh``: force and its moment about the
body's reference point): mbsym applies it as generalized forces ``Q = J_vᵀ F + J_ωᵀ M`` (``J_v = ∂v_P/∂q̇``,
``J_ω = ∂ω/∂q̇``, exact). The load depends on P's acceleration (the masses' rigid directions) and so on ``q̈``:
OpenFAST v5 solves ServoDyn with StCs in its implicit input-output solve (``FAST_Solver.f90``: ServoDyn is an
"Option 1" module when it has StCs); mbsym moves that part to the mass matrix, ``(M − ∂Q/∂q̈) q̈ = F + Q|_{q̈=0}``,
and drives the StC states with the solved ``q̈``.

Not modelled (refused by :func:`structural_controls`, file/line/key): blade StCs (``NumBStC``), TLCD (mode 5),
forces from the DLL (mode 7), semi-active and active control (``StC_CMODE`` ≠ 0), the spring-force table
(``Use_F_TBL``), an SStC on a SubDyn substructure, a TStC off the tower's flexible length (``StC_P_Z``).
The ElastoDyn load channels computed from locked joints (``TwrBsMyt``, ``YawBr*p`` …) do not include the StC's
load; the motions do.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import casadi as ca
import numpy as np

from ...exceptions import UnsupportedFeatureError
from .structural_control_terms import stc_terms

__all__ = ["StructuralControl", "StructuralControls", "structural_controls", "stc_terms", "PRESCRIBED_INPUTS"]

#: The structure's body each kind of StC sits on.
_BODY = {"N": "nacelle", "T": "tower", "S": "platform"}
_STATES = ("XQ", "XQD", "YQ", "YQD", "ZQ", "ZQD")
#: The inputs of a prescribed-load StC (``StC_DOF_MODE = 6``), after its name: force [N] and moment [N m].
PRESCRIBED_INPUTS = ("Fx", "Fy", "Fz", "Mx", "My", "Mz")


@dataclass(frozen=True)
class StructuralControl:
    """One StC (module docstring): ``kind`` ``"N"``, ``"T"`` or ``"S"``, its 1-based ``index``, its file's settings
    and, for ``StC_DOF_MODE = 6``, the prescribed-load table ``forces`` (rows ``t Fx Fy Fz Mx My Mz`` [s, N, N m])."""

    kind: str
    index: int
    settings: Any
    forces: Any = None

    @property
    def prescribed(self) -> bool:
        """Whether it is a prescribed load (``StC_DOF_MODE = 6``: no states, six inputs)."""
        return self.settings.dof_mode == 6

    @property
    def input_names(self) -> tuple[str, ...]:
        """``<name>_Fx`` … ``<name>_Mz`` for a prescribed load, else empty."""
        return tuple(f"{self.name}_{c}" for c in PRESCRIBED_INPUTS) if self.prescribed else ()

    @property
    def name(self) -> str:
        """``NStC1``, ``SStC2`` … (ServoDyn's channel prefix)."""
        return f"{self.kind}StC{self.index}"

    @property
    def body(self) -> str:
        return _BODY[self.kind]

    @property
    def state_names(self) -> tuple[str, ...]:
        """``<name>_XQ`` … ``<name>_ZQD`` (none for a prescribed load)."""
        return () if self.prescribed else tuple(f"{self.name}_{s}" for s in _STATES)

    @property
    def z_active(self) -> bool:
        s = self.settings
        return (s.dof_mode == 1 and s.dof[2]) or s.dof_mode == 3

    def initial_state(self) -> np.ndarray:
        """``StC_X_DSP``, 0, ``StC_Y_DSP``, 0, ``StC_Z_DSP`` (only with a Z DOF), 0 [m, m/s] (``StC_Init``)."""
        if self.prescribed:
            return np.zeros(0)
        v = self.settings.values
        return np.array([v["StC_X_DSP"], 0.0, v["StC_Y_DSP"], 0.0, v["StC_Z_DSP"] if self.z_active else 0.0, 0.0])

    def preload(self, gravity: Any) -> Any:
        """``StC_Z_PreLd`` [N] (``StC_SetParameters``): only with a Z DOF; "gravity" is the mass's weight."""
        s = self.settings
        text = s.z_preload.strip().lower()
        if not self.z_active or text.startswith("none"):
            return 0.0
        if text.startswith("gravity"):
            return gravity * s.values["StC_Z_M" if s.dof_mode == 1 else "StC_Omni_M"]
        return float(text)

    def local(self, x: Any, acc: Any, omega: Any, alpha: Any, g_local: Any, gravity: Any) -> tuple[Any, Any, Any]:
        """``(F_P, M_P, ẋ)`` in P's axes from the states ``x`` (6), P's acceleration ``acc``, ω, α and gravity
        ``g_local`` (3, P's axes; ``gravity`` its magnitude, for the preload)."""
        s, v = self.settings, self.settings.values
        k, c = s.vector("K"), s.vector("C")
        d, dd = [x[0], x[2], x[4]], [x[1], x[3], x[5]]
        w, a = [omega[i] for i in range(3)], [alpha[i] for i in range(3)]
        rel = [g_local[i] - acc[i] for i in range(3)]          # gravity minus P's acceleration
        stop = [_stop(d[i], dd[i], s.vector("PSP")[i], s.vector("NSP")[i], s.vector("KS")[i], s.vector("CS")[i])
                for i in range(3)]
        pre = self.preload(gravity)
        if s.dof_mode == 1:
            m = [v["StC_X_M"], v["StC_Y_M"], v["StC_Z_M"]]
            # forces of the masses' rigid directions (each mass moves only along its own axis)
            fx = [0.0, -m[0] * (rel[1] - (a[2] + w[0] * w[1]) * d[0] - 2 * w[2] * dd[0]),
                  -m[0] * (rel[2] + (a[1] - w[0] * w[2]) * d[0] + 2 * w[1] * dd[0])]
            fy = [-m[1] * (rel[0] + (a[2] - w[0] * w[1]) * d[1] + 2 * w[2] * dd[1]), 0.0,
                  -m[1] * (rel[2] - (a[0] + w[1] * w[2]) * d[1] - 2 * w[0] * dd[1])]
            fz = [-m[2] * (rel[0] - (a[1] + w[0] * w[2]) * d[2] - 2 * w[1] * dd[2]),
                  -m[2] * (rel[1] + (a[0] - w[1] * w[2]) * d[2] + 2 * w[0] * dd[2]), 0.0]
            f = [k[0] * d[0] + c[0] * dd[0] - stop[0] - fy[0] - fz[0],
                 k[1] * d[1] + c[1] * dd[1] - stop[1] - fx[1] - fz[1],
                 k[2] * d[2] + c[2] * dd[2] - stop[2] - fx[2] - fy[2] - pre]
            mom = [-fy[2] * d[1] + fz[1] * d[2], fx[2] * d[0] - fz[0] * d[2], -fx[1] * d[0] + fy[0] * d[1]]
            spin = [w[1] ** 2 + w[2] ** 2, w[0] ** 2 + w[2] ** 2, w[0] ** 2 + w[1] ** 2]
            rates = []
            for i in range(3):
                if s.dof[i]:
                    load = stop[i] + (pre if i == 2 else 0.0)
                    acc_i = (spin[i] - k[i] / m[i]) * d[i] - c[i] / m[i] * dd[i] + rel[i] + load / m[i]
                    rates += [dd[i], acc_i]
                else:
                    rates += [0.0, 0.0]
            return ca.vertcat(*f), ca.vertcat(*mom), ca.vertcat(*rates)
        m = v["StC_Omni_M"]
        if s.dof_mode == 2:
            fz = -m * (rel[2] - (a[0] + w[1] * w[2]) * d[1] + (a[1] - w[0] * w[2]) * d[0] - 2 * w[0] * dd[1]
                       + 2 * w[1] * dd[0])
            f = ca.vertcat(k[0] * d[0] + c[0] * dd[0] - stop[0], k[1] * d[1] + c[1] * dd[1] - stop[1], -fz)
            ax = ((w[1] ** 2 + w[2] ** 2 - k[0] / m) * d[0] - c[0] / m * dd[0] + rel[0] + stop[0] / m
                  - (w[0] * w[1] - a[2]) * d[1] + 2 * w[2] * dd[1])
            ay = ((w[0] ** 2 + w[2] ** 2 - k[1] / m) * d[1] - c[1] / m * dd[1] + rel[1] + stop[1] / m
                  - (w[0] * w[1] + a[2]) * d[0] - 2 * w[2] * dd[0])
            rates = ca.vertcat(dd[0], ax, dd[1], ay, 0.0, 0.0)
            r = ca.vertcat(d[0], d[1], d[2])
            return f, ca.cross(r, f), rates
        # mode 3: omni-directional XYZ
        r, rd, om, al = ca.vertcat(*d), ca.vertcat(*dd), ca.vertcat(*w), ca.vertcat(*a)
        kk, cc, st = ca.DM(k), ca.DM(c), ca.vertcat(*stop)
        f = kk * r + cc * rd - st - ca.vertcat(0.0, 0.0, pre)
        accel = (-kk * r - cc * rd + st + ca.vertcat(0.0, 0.0, pre)) / m + ca.vertcat(*rel) \
            - ca.cross(om, ca.cross(om, r)) - ca.cross(al, r) - 2 * ca.cross(om, rd)
        rates = ca.vertcat(rd[0], accel[0], rd[1], accel[1], rd[2], accel[2])
        return f, ca.cross(r, f), rates


def _stop(x: Any, xd: Any, positive: float, negative: float, k: float, c: float) -> Any:
    """The stop force on the mass [N] (``StC_CalcStopForce``): spring beyond the stops, damper moving outward."""
    if k == 0.0 and c == 0.0:
        return 0.0
    spring = ca.if_else(x > positive, k * (positive - x), ca.if_else(x < negative, k * (negative - x), 0.0))
    out = ca.logic_or(ca.logic_and(x > positive, xd > 0), ca.logic_and(x < negative, xd < 0))
    return spring + ca.if_else(out, -c * xd, 0.0)


@dataclass(frozen=True)
class StructuralControls:
    """The StCs of a deck (:func:`structural_controls`)."""

    controls: tuple[StructuralControl, ...]

    @property
    def state_names(self) -> tuple[str, ...]:
        return tuple(n for c in self.controls for n in c.state_names)

    def initial_state(self) -> np.ndarray:
        return np.concatenate([c.initial_state() for c in self.controls]) if self.controls else np.zeros(0)

    @property
    def input_names(self) -> tuple[str, ...]:
        """The prescribed loads' inputs (``NStC1_Fx`` … ``NStC1_Mz`` …), in StC order."""
        return tuple(n for c in self.controls for n in c.input_names)

    @property
    def input_units(self) -> tuple[str, ...]:
        return tuple(u for c in self.controls if c.prescribed for u in ("N",) * 3 + ("N-m",) * 3)

    def tables(self, t_end: float) -> dict[str, tuple[np.ndarray, np.ndarray]]:
        """The prescribed loads as input tables over ``[0, t_end]`` [s] (the files' rows, their end values held as
        ``InterpStp`` holds them): input name -> ``(t, value)`` [s, N or N m]."""
        out = {}
        for c in self.controls:
            if not c.prescribed:
                continue
            data = np.asarray(c.forces, dtype=float)
            t = data[:, 0]
            lo, hi = min(0.0, float(t[0])) - 1.0, max(float(t_end), float(t[-1])) + 1.0
            grid = np.concatenate([[lo], t, [hi]])
            for k, name in enumerate(c.input_names):
                out[name] = (grid, np.concatenate([[data[0, k + 1]], data[:, k + 1], [data[-1, k + 1]]]))
        return out

    def channel_names(self) -> tuple[tuple[str, str], ...]:
        """ServoDyn's channels of each StC: name and unit (``ServoDyn_IO.f90``, ``Set_NStC_Outs_Instance``)."""
        units = ("m", "m/s") * 3 + ("kN",) * 3 + ("kN-m",) * 3 + ("kN",) * 3 + ("kN-m",) * 3
        tails = _STATES + tuple(f"{w}{c}{f}" for f in ("i", "l") for w in ("F", "M") for c in "xyz")
        return tuple((f"{c.name}_{t}", u) for c in self.controls for t, u in zip(tails, units))


def structural_controls(servodyn, turbine) -> StructuralControls | None:
    """The deck's nacelle, tower and platform StCs (module docstring), after refusing what mbsym does not model.

    Parameters
    ----------
    servodyn : ServoDynSettings or None
    turbine : TurbineParameters
        The deck (an SStC on a SubDyn substructure is refused; a TStC must lie on the tower's flexible length).

    Returns
    -------
    StructuralControls or None
        None when ServoDyn names no StC.

    Raises
    ------
    UnsupportedFeatureError
        Blade StCs, StC modes and settings not modelled (file, line, key and how to change it).
    OpenFASTFormatError
        A malformed StC file or prescribed-force file.
    """
    if servodyn is None:
        return None
    from ..deck.stc import read_prescribed_forces, read_stc, servodyn_stc_files

    files = servodyn_stc_files(servodyn)
    problems = []
    if "B" in files:
        problems.append(f"{servodyn.path}, line {servodyn.lines.get('NumBStC', '?')}, key 'NumBStC': blade structural "
                        "controllers are not modelled; set NumBStC = 0 (nacelle, tower and platform StCs are)")
    if "S" in files and int(getattr(turbine.simulation, "substructure_model", 0) or 0):
        problems.append(f"{servodyn.path}, line {servodyn.lines.get('NumSStC', '?')}, key 'NumSStC': an SStC on a "
                        "SubDyn substructure (CompSub = 1) is not modelled; set NumSStC = 0")
    controls = []
    flex = float(turbine.tower_height) - float(turbine.tower_base_height)
    for kind in ("N", "T", "S"):
        for index, (path, _) in enumerate(files.get(kind, ()), 1):
            s = read_stc(path)
            problems += _refusals(s)
            h = s.values["StC_P_Z"]
            if kind == "T" and not -1e-3 <= h <= flex + 1e-3:
                problems.append(f"{s.where('StC_P_Z')}: a tower StC must lie on the tower's flexible length, 0 to "
                                f"TowerHt - TowerBsHt = {flex:g} m above the tower base; got {h:g} m")
            forces = None
            if s.dof_mode == 6:
                if s.prescribed_file is None:
                    problems.append(f"{s.where('PrescribedForcesFile')}: StC_DOF_MODE = 6 needs a prescribed force "
                                    "file (seven columns t Fx Fy Fz Mx My Mz)")
                else:
                    forces = read_prescribed_forces(s.prescribed_file)
            if s.dof_mode != 0:
                controls.append(StructuralControl(kind, index, s, forces))
    if problems:
        raise UnsupportedFeatureError(problems[0] + "." if len(problems) == 1 else
                                      f"{len(problems)} structural-control settings mbsym does not model:\n  - "
                                      + "\n  - ".join(problems))
    return StructuralControls(tuple(controls)) if controls else None


def _refusals(s) -> list[str]:
    out = []
    if s.dof_mode in (5, 7):
        what = {5: "a tuned liquid column damper (TLCD)", 7: "a force from the DLL"}[s.dof_mode]
        out.append(f"{s.where('StC_DOF_MODE')}: StC_DOF_MODE = {s.dof_mode} ({what}) is not modelled; use 1 "
                   "(independent X/Y/Z masses), 2 (omni-directional XY), 3 (omni-directional XYZ) or 6 "
                   "(prescribed force time series)")
    if s.dof_mode in (1, 2, 3) and s.control_mode != 0:
        out.append(f"{s.where('StC_CMODE')}: StC_CMODE = {s.control_mode} (semi-active or active control) is not "
                   "modelled; set StC_CMODE = 0 (passive: StC_*_K and StC_*_C)")
    if s.dof_mode in (1, 2, 3) and s.use_table:
        out.append(f"{s.where('Use_F_TBL')}: the spring-force table (Use_F_TBL = True) is not modelled; set "
                   "Use_F_TBL = False (linear springs StC_*_K with the stops StC_*_PSP/NSP, StC_*_KS/CS)")
    v = s.values
    need = {1: [(f"StC_{c}_M", f"StC_{c}_K") for c, on in zip("XYZ", s.dof) if on], 2: [("StC_Omni_M", "StC_X_K"),
            ("StC_Omni_M", "StC_Y_K")], 3: [("StC_Omni_M", "StC_X_K"), ("StC_Omni_M", "StC_Y_K"),
                                            ("StC_Omni_M", "StC_Z_K")]}.get(s.dof_mode, [])
    for m, k in need:
        for key in (m, k):
            if not v[key] > 0:
                out.append(f"{s.where(key)}: must be > 0 for StC_DOF_MODE = {s.dof_mode} with this DOF "
                           f"(StrucCtrl's own check); got {v[key]:g}")
    return out


def structure_servodyn(turbine, t_end: float) -> StructuralControls | None:
    """ServoDyn on a structure without aerodynamics (``mbsym simulate`` of an offshore deck without AeroDyn): its
    StCs, after refusing every ServoDyn setting that would act and that such a run does not model.

    Parameters
    ----------
    turbine : TurbineParameters
        The deck; ``CompServo = 0`` gives None.
    t_end : float
        The simulated end time [s].

    Raises
    ------
    UnsupportedFeatureError
        A pitch or torque controller (``PCMode``, ``VSContrl`` ≠ 0 with GenDOF): a structure without
        aerodynamics runs no controller.
    OpenFASTFormatError
        What :func:`~mbsym.wind.deck.servo_audit.servo_audit` refuses.
    """
    if not int(getattr(turbine.simulation, "servo_model", 0) or 0):
        return None
    from ..deck.servo_audit import servo_audit
    from ..deck.servodyn import read_servodyn

    s = read_servodyn(turbine.source_files["servodyn"])
    dofs = dict(turbine.dofs)
    speed = abs(turbine.gearbox_ratio) * turbine.initial_conditions.rotor_speed
    servo_audit(s, dofs, float(t_end), generator_speed=speed)
    active = [k for k, v in (("PCMode", s.pitch_control_mode), ("VSContrl", s.torque_control_mode if
                                                                  dofs.get("GenDOF") else 0)) if v != 0]
    if active:
        raise UnsupportedFeatureError(f"{s.path}, line {s.lines.get(active[0], '?')}, key '{active[0]}': a structure "
                                      "without aerodynamics (no AeroDyn) runs no controller; set PCMode = 0 and "
                                      "VSContrl = 0 (ServoDyn then adds its yaw spring and its structural "
                                      "controllers), or add AeroDyn to run the operating turbine.")
    if dofs.get("YawDOF") and (s.yaw_spring or s.yaw_damping):
        raise UnsupportedFeatureError(f"{s.path}, line {s.lines.get('YawSpr', '?')}, key 'YawSpr': ServoDyn's yaw "
                                      "spring on a structure without aerodynamics is not wired; switch YawDOF off "
                                      "or add AeroDyn.")
    return structural_controls(s, turbine)
