"""ElastoDyn-equivalent wind-turbine template: one System for any set of ElastoDyn DOFs.

:class:`TurbineModel` builds the structural model ElastoDyn builds for the degrees of
freedom a deck enables (or a list of ElastoDyn flag names), following ElastoDyn's
kinematic chain (docs/elastodyn_notes.md §4) in IEC axes (x downwind, z up):

ground → platform (Sg, Sw, Hv translations; R, P, Y as ElastoDyn v5's yaw–pitch–roll
Euler sequence with Euler-rate angular velocity, :mod:`.platform`) → tower (flexible:
TwFA/TwSS modes on ElastoDyn's nodes at their exact positions, the top turning with the
slope rates; or rigid) → yaw bearing and nacelle (YawDOF) → tilted shaft →
generator (geared, GenDOF azimuth) and low-speed shaft → hub (DrTrDOF torsion) →
coned and pitched blades (ElastoDyn's frame ``j``; flexible with FlapDOF1, FlapDOF2 and
EdgeDOF: lumped node masses with the twisted, curvature-integrated mode shapes of
:func:`~mbsym.wind.structure.elastodyn_bodies.blade_shape_integrals` at their exact positions
``z + Φq − ½qᵀAxq`` (``FlexibleBody(kinematics="exact")``), ElastoDyn's stiffness and
damping; rigid point-mass blades otherwise).

A disabled DOF keeps its initial value; a disabled GenDOF with a nonzero initial rotor
speed (or ``prescribed_azimuth=True``) spins the rotor through a prescribed azimuth
(inputs ``GeAz``, ``GeAz_d``, ``GeAz_dd``). Blade pitch is the deck's BlPitch, or with
``pitch_input=True`` a collective prescribed angle (inputs ``BlPitch``, ``BlPitch_d``,
``BlPitch_dd``). Coordinates carry ElastoDyn's DOF names (``TFA1``, ``GeAz``,
``B1F1`` …) in ElastoDyn's state order (notes §7: blade DOFs as B1F1, B2F1, B3F1, B1E1 …,
B1F2 …); side-side coordinates are positive along +y (ElastoDyn's internal ``Q_TSS1`` is
their negative, see :mod:`mbsym.wind.structure.channels`).

Centrifugal stiffening, spin softening, Coriolis and gravity loads on the blades are not
added as matrices: they come out of Kane's method from the blades' axial shortening and
the instantaneous rotor motion, as in ElastoDyn (notes §2.2).
"""

from __future__ import annotations

from typing import Callable, Sequence

import casadi as ca
import numpy as np

from ...bodies.base import Body
from ...bodies.flexible import FlexibleBody
from ...bodies.rigid import RigidBody
from ...exceptions import ModelDefinitionError
from ...joints import Fixed, Joint, Revolute
from ...kinematics import rotation
from ...system import System
from ..deck.parameters import TurbineParameters
from .dof_tables import (
    BLADE_FLAGS,
    MODELLED_DOFS,
    NON_BLADE_DOFS,
    PLATFORM_FLAGS as _PLATFORM,
    STATE_ORDER,
    SUPPORTED_DOFS,
    TOWER_FLAGS as _TOWER,
    blade_coordinate,
    resolve_dofs as _resolve_dofs,
    unsupported_features,
)
from .elastodyn_bodies import (
    BLADE_DOFS,
    ElastoDynBladeData,
    blade_elastodyn_data,
    blade_rotation,
    rigid_blade,
    blade_shape_integrals,
    tower_elastodyn_data,
    tower_shape_integrals,
)
from .elastodyn_nodes import rotor_mass_properties
from .initial_conditions import initial_blade_deflection
from .load_cuts import (
    BLADE_ROOT_FORCE_LOCKED,
    BLADE_ROOT_LOCKED,
    SHAFT_LOCKED,
    TOWER_BASE_LOCKED,
    YAW_BEARING_LOCKED,
    locked_chain,
)
from .mbc import BladeFrame
from .named_parameters import blade_matrices, parameter_defaults, tower_matrices
from .platform import PlatformJoint
from .steps import elastodyn_steps
from .gearbox import generator_inertia
from .load_inputs import BLADE_LOAD_INPUTS, TOWER_LOAD_INPUTS, add_load_inputs

__all__ = ["TurbineModel", "BLADE_LOAD_INPUTS", "TOWER_LOAD_INPUTS", "BLADE_ROOT_FORCE_LOCKED", "BLADE_ROOT_LOCKED", "PlatformJoint", "NON_BLADE_DOFS", "SUPPORTED_DOFS", "BLADE_FLAGS", "MODELLED_DOFS",
           "SHAFT_LOCKED", "STATE_ORDER", "TOWER_BASE_LOCKED", "YAW_BEARING_LOCKED", "blade_rotation", "blade_coordinate", "initial_blade_deflection", "unsupported_features"]


class TurbineModel:
    """ElastoDyn-equivalent structural model of a wind turbine.

    Parameters
    ----------
    turbine : TurbineParameters
        From :func:`mbsym.wind.read_openfast` or :func:`mbsym.wind.deck.nrel5mw`.
    dofs : sequence of str, optional
        ElastoDyn flag names to enable (e.g. ``["TwFADOF1", "GenDOF", "FlapDOF1"]``);
        default: the deck's own flags. :data:`MODELLED_DOFS` lists the flags modelled
        (PitchDOF and TeetDOF are not).
    yaw_spring, yaw_damping : float, optional, keyword-only
        Yaw-bearing spring [N m/rad] and damper [N m s/rad] about ``yaw_neutral``
        (ServoDyn's YawSpr/YawDamp; ElastoDyn alone has none).
    yaw_neutral : float, optional, keyword-only
        Yaw at which the spring is relaxed [rad] (ServoDyn's YawNeut); default the initial
        ``NacYaw``.
    yaw_command : bool, optional, keyword-only
        ServoDyn's commanded yaw as the inputs ``YawPosCom`` [rad], ``YawRateCom`` [rad/s]: the generalized force
        ``yaw_spring (YawPosCom - yaw_neutral) + yaw_damping YawRateCom`` on the yaw DOF
        (:mod:`mbsym.wind.deck.yaw_control`).
    pitch_input : bool, optional, keyword-only
        ``False`` (default): each blade pitched at the deck's BlPitch. ``True``: collective
        pitch as a prescribed coordinate (inputs ``BlPitch`` [rad], ``BlPitch_d``,
        ``BlPitch_dd``; default input the deck's pitch), turning every blade about its
        ``j3`` axis as ElastoDyn's pitch does (the blades must share one initial pitch).
        ``"individual"``: one prescribed pitch per blade (inputs ``BlPitch<k>``, ``BlPitch<k>_d``,
        ``BlPitch<k>_dd``; default inputs the deck's BlPitch(k)).
    prescribed_azimuth : bool, optional, keyword-only
        With GenDOF off, drive the rotor through the prescribed azimuth inputs (``GeAz``,
        ``GeAz_d``, ``GeAz_dd``) even when the deck's RotSpeed is 0 (Campbell diagrams at
        several speeds from one model). Default: only when RotSpeed is nonzero.
    tower_base_reactions : bool, optional, keyword-only
        Attach the tower to the platform through two *locked* rotations about the
        platform's x and y axes (:data:`TOWER_BASE_LOCKED`, ``sys.locked``): the equations
        are unchanged and ``eom.functions.reactions`` gives the moments the support
        exerts to hold them, i.e. minus the tower-base bending moments ``TwrBsMxt``,
        ``TwrBsMyt`` [N m] (:mod:`mbsym.wind.operation.channels`). Default False.
    blade_loads : bool, optional, keyword-only
        Loads on every blade as inputs (:data:`BLADE_LOAD_INPUTS`, for blade-element
        aerodynamics): per blade ``k`` a force ``B{k}AeroFx/Fy/Fz`` [N] at the blade root and a
        moment ``B{k}AeroMx/My/Mz`` [N m] about it, both in the blade's (pitched) body axes
        ``j1, j2, j3``, and per elastic coordinate ``c`` of the blade its generalized force
        ``{c}AeroQ`` [N] (the work of the distributed load on the mode shape). Default False.
    blade_root_reactions : bool, optional, keyword-only
        Attach every blade through three *locked* rotations about its root's coned axes
        ``i1, i2, i3`` (:data:`BLADE_ROOT_LOCKED`, after the tower-base ones): their reactions
        are minus ElastoDyn's ``RootMxc``, ``RootMyc``, ``RootMzc`` [N m]. Needs ``pitch_input``.
    blade_root_forces, shaft_reactions, yaw_bearing_reactions : bool, optional, keyword-only
        More *locked* joints (:mod:`.load_cuts`, equations unchanged): translations along each root's
        ``i1, i2, i3`` before its rotations (reactions: minus ``RootFxc..RootFzc`` [N]; needs
        ``pitch_input``), along the shaft axes between the shaft and the rotor (minus ``LSShftFxa``,
        ``LSShftFys``, ``LSShftFzs``), and along and about the tower-top axes between the tower and
        the nacelle (minus ``YawBrFxp..YawBrFzp`` [N], ``YawBrMxp..YawBrMzp`` [N m]). Default False.
    hub_moments : bool, optional, keyword-only
        Inputs ``RotMomY``, ``RotMomZ`` [N m] and ``RotFrcY``, ``RotFrcZ`` [N]: a moment on the rotor about
        the shaft frame's second and third axes (across the shaft) and a force along them (in the rotor
        plane), e.g. the aerodynamic damping of a rotor-effective model. Default False.
    tower_loads : bool, optional, keyword-only
        Loads along the tower as inputs (AeroDyn's tower drag): a force ``TwrAeroFx/Fy/Fz`` [N] at the tower base
        and a moment ``TwrAeroMx/My/Mz`` [N m] about it, tower-base axes, and per tower coordinate ``c`` its
        generalized force ``{c}AeroQ`` [N] (:mod:`.tower_points`). Default False.
    nacelle_loads : bool, optional, keyword-only
        A force ``NacAeroFx/Fy/Fz`` [N] at the yaw bearing and moment ``NacAeroMx/My/Mz`` [N m] about it, nacelle
        axes, as inputs (AeroDyn's nacelle drag, :mod:`.load_inputs`). Default False.

    Raises
    ------
    ModelDefinitionError
        Listing at once every deck feature that would change the dynamics of the enabled
        DOFs but that the template does not model (:func:`unsupported_features`), and
        unknown or unmodelled DOF flags.

    Attributes
    ----------
    system : System
        The description (add loads to it before calling :attr:`eom` if needed).
    dofs : tuple of str
        Enabled ElastoDyn flags, in ElastoDyn's state order.

    Examples
    --------
    >>> from mbsym.wind import nrel5mw
    >>> model = TurbineModel(nrel5mw(), dofs=["TwFADOF1", "GenDOF"])
    >>> model.eom.coordinates
    ('TFA1', 'GeAz')
    >>> TurbineModel(nrel5mw(), dofs=["FlapDOF1", "EdgeDOF"]).eom.coordinates
    ('B1F1', 'B2F1', 'B3F1', 'B1E1', 'B2E1', 'B3E1')
    """

    def __init__(self, turbine: TurbineParameters, dofs: Sequence[str] | None = None, *,
                 yaw_spring: float = 0.0, yaw_damping: float = 0.0, yaw_neutral: float | None = None,
                 yaw_command: bool = False, pitch_input: bool = False,
                 prescribed_azimuth: bool = False, tower_base_reactions: bool = False,
                 blade_loads: bool = False, blade_root_reactions: bool = False, blade_root_forces: bool = False,
                 shaft_reactions: bool = False, yaw_bearing_reactions: bool = False, nacelle_loads: bool = False,
                 hub_moments: bool = False, tower_loads: bool = False) -> None:
        if not isinstance(turbine, TurbineParameters):
            raise TypeError(f"turbine must be TurbineParameters (read_openfast or nrel5mw); got {type(turbine).__name__}.")
        self.turbine = turbine
        self.hub_moments = bool(hub_moments)
        self.tower_loads, self.nacelle_loads = bool(tower_loads), bool(nacelle_loads)
        self.dofs, problems = _resolve_dofs(turbine, dofs)
        problems += unsupported_features(turbine, self.dofs)
        if problems:
            raise ModelDefinitionError(
                f"the template cannot model this turbine as it stands ({len(problems)} problem"
                f"{'s' if len(problems) > 1 else ''}):\n" + "\n".join(f"  - {m}" for m in problems))
        self._blade_data: dict[int, ElastoDynBladeData] = {}
        self._yaw = (float(yaw_spring), float(yaw_damping),
                     float(turbine.initial_conditions.nacelle_yaw if yaw_neutral is None else yaw_neutral))
        self.yaw_command = bool(yaw_command)
        if pitch_input not in (True, False, "individual"):
            raise ModelDefinitionError(f"pitch_input must be False, True (collective) or 'individual'; got "
                                       f"{pitch_input!r}.")
        self.pitch_input = pitch_input if pitch_input == "individual" else bool(pitch_input)
        self.prescribed_azimuth = bool(prescribed_azimuth)
        self.tower_base_reactions = bool(tower_base_reactions)
        self.blade_loads = bool(blade_loads)
        self.blade_root_reactions = bool(blade_root_reactions)
        self.blade_root_forces = bool(blade_root_forces)
        self.shaft_reactions = bool(shaft_reactions)
        self.yaw_bearing_reactions = bool(yaw_bearing_reactions)
        for key in ("blade_root_reactions", "blade_root_forces"):
            if getattr(self, key) and not pitch_input:
                raise ModelDefinitionError(f"{key}=True needs pitch_input=True (the locked root joints carry the "
                                           "pitch bearing).")
        if self.pitch_input is True and len(set(turbine.initial_conditions.blade_pitch)) > 1:
            raise ModelDefinitionError(
                f"pitch_input=True drives all blades with one collective pitch, but the deck's BlPitch differ "
                f"({[float(np.rad2deg(b)) for b in turbine.initial_conditions.blade_pitch]} deg); "
                "set equal BlPitch or use pitch_input=False.")
        self.system = System()
        self.coords: dict[str, ca.SX] = {}
        self.prescribed: dict[str, Callable[[float], float]] = {}
        self.bodies: dict[str, Body] = {}
        self._eom = None
        self._channels = None
        self._build()

    # ------------------------------------------------------------------ public
    @property
    def eom(self):
        """EquationsOfMotion (derived on first use)."""
        if self._eom is None:
            self._eom = self.system.equations(name="turbine")
        return self._eom

    def initial_state(self) -> np.ndarray:
        """x0 = [q0; qd0] from ElastoDyn's initial-condition keys (notes §5)."""
        ic, eom = self.turbine.initial_conditions, self.eom
        q0 = {"Sg": ic.platform_surge, "Sw": ic.platform_sway, "Hv": ic.platform_heave,
              "R": ic.platform_roll, "P": ic.platform_pitch, "Y": ic.platform_yaw,
              "Yaw": ic.nacelle_yaw, "GeAz": self.initial_generator_azimuth(), "DrTr": 0.0}
        q0.update(self._tower_initial())
        q0.update(self._blade_initial())
        qd0 = {"GeAz": ic.rotor_speed}
        x0 = [q0.get(n, 0.0) for n in eom.coordinates] + [qd0.get(n, 0.0) for n in eom.coordinates]
        return np.array(x0, dtype=float)

    def initial_generator_azimuth(self) -> float:
        """ElastoDyn's q_GeAz = Azimuth - AzimB1Up - π/2, wrapped to [0, 2π) [rad]."""
        t = self.turbine
        return float(np.mod(t.initial_conditions.azimuth - t.azimuth_blade1_up - np.pi / 2, 2 * np.pi))

    def _tower_initial(self) -> dict[str, float]:
        """TTDspFA/TTDspSS go to mode 1, or to mode 2 when mode 1 is off (never split)."""
        ic = self.turbine.initial_conditions
        out = {}
        for value, modes in ((ic.tower_top_fa_displacement, ("TFA1", "TFA2")),
                             (ic.tower_top_ss_displacement, ("TSS1", "TSS2"))):
            for m in modes:
                if m in self.coords:
                    out[m] = value     # SS coordinates are positive along +y, as TTDspSS
                    break
        return out

    def _blade_initial(self) -> dict[str, float]:
        """Blade DOFs from OoPDefl/IPDefl with ElastoDyn's rule (notes §5), per blade."""
        t, out = self.turbine, {}
        ic = t.initial_conditions
        target = np.array([ic.blade_oop_tip_deflection, ic.blade_ip_tip_deflection], dtype=float)
        flags = [f for f in BLADE_FLAGS if self.dofs.get(f)]
        if not flags or not np.any(target):
            return out
        for k in range(t.number_of_blades):
            values = initial_blade_deflection(self.blade_data(k).tip_displacement,
                                              ic.blade_pitch[k], target, self.dofs, blade=k + 1)
            out.update({blade_coordinate(k, f): v for f, v in values.items() if self.dofs.get(f)})
        return out

    def blade_data(self, blade: int) -> ElastoDynBladeData:
        """ElastoDyn's nodes, shapes and matrices of blade ``blade`` (0-based), computed once per model."""
        if blade not in self._blade_data:
            self._blade_data[blade] = blade_elastodyn_data(self.turbine, blade)
        return self._blade_data[blade]

    def input_defaults(self) -> dict[str, float | Callable[[float], float]]:
        """Default value (number or function of time [s]) of every input of the model."""
        out: dict = {name: 0.0 for name in self.eom.inputs}
        out.update(self.prescribed)
        return out

    def resolve_parameter(self, key: str):
        """Named parameter ``key`` (ElastoDyn key such as ``"TwrFADmp(1)"`` or descriptive name) of this model.

        Returns the :class:`~mbsym.wind.structure.named_parameters.NamedParameter` (name, unit,
        ``factor`` = key value / model value); raises ParameterError if unknown or absent.
        """
        from .named_parameters import resolve

        return resolve(self.eom.parameters, key, dofs=self.dofs)

    # ------------------------------------------------------------------ simulation protocol
    def default_state(self) -> np.ndarray:
        """Initial state for :func:`mbsym.simulate` (same as :meth:`initial_state`)."""
        return self.initial_state()

    def default_inputs(self) -> dict[str, float | Callable[[float], float]]:
        """Inputs for :func:`mbsym.simulate`: zero loads, prescribed motions as functions of time."""
        return self.input_defaults()

    def input_units(self) -> dict[str, str]:
        """Units of the inputs by name (SI: :mod:`mbsym.wind.structure.units`; simulation protocol hook)."""
        from .units import structural_input_unit

        return {n: structural_input_unit(n) for n in self.eom.inputs}

    def output_function(self):
        """OpenFAST channels (:class:`mbsym.wind.structure.channels.Channels`: ``function``, ``names``, ``units``)."""
        if self._channels is None:
            from .channels import output_function

            self._channels = output_function(self)
        return self._channels

    @property
    def output_names(self) -> tuple[str, ...]:
        """OpenFAST channel names of :meth:`output_function`."""
        return self.output_function().names

    def __repr__(self) -> str:
        t = self.turbine
        dofs = [f for f, on in self.dofs.items() if on]
        source = t.source_files.get("fst", "built-in") if t.source_files else "built-in"
        return (f"TurbineModel({source.rsplit('/', 1)[-1]}: {len(t.blades)} blades, tip radius {t.tip_radius:g} m, "
                f"hub height {t.hub_height:.4g} m, rotor speed {t.initial_conditions.rotor_speed * 30 / np.pi:.4g} rpm; "
                f"DOFs {dofs or 'none'})")

    # ------------------------------------------------------------------ linearization hooks
    def linearization_steps(self) -> dict[str, float]:
        """ElastoDyn's central-difference steps by coordinate (``method="elastodyn-fd"``, :mod:`.steps`)."""
        return elastodyn_steps(self.turbine, self.eom.coordinates)

    def linearization_method(self) -> str:
        """Default method of :func:`mbsym.linearize`: ElastoDyn's central differences, as OpenFAST."""
        return "elastodyn-fd"

    def linearization_state(self) -> np.ndarray:
        """Default point of :func:`mbsym.linearize` (and ``mbsym linearize``): OpenFAST's undeflected one.

        The deck's rotor speed, azimuth and nacelle yaw with every tower, platform, drivetrain
        and blade displacement zero (OpenFAST's ``_lin0`` decks).
        """
        x = self.initial_state()
        n = self.eom.n_q
        keep = {"GeAz", "Yaw"}
        for i, c in enumerate(self.eom.coordinates):
            if c not in keep:
                x[i] = 0.0
                x[n + i] = 0.0
        return x

    def rotating_frame(self) -> BladeFrame:
        """Multi-blade coordinates of the blade DOFs for azimuth averages; blade-1 azimuth = GeAz + AzimB1Up + π/2."""
        return BladeFrame(self.eom.coordinates, offset=self.turbine.azimuth_blade1_up + np.pi / 2)

    # ------------------------------------------------------------------ build
    def _build(self) -> None:
        t, sys = self.turbine, self.system
        for flag, name in STATE_ORDER.items():
            if self.dofs.get(flag):
                self.coords[name] = sys.coordinates(name)
        for flag in BLADE_FLAGS:              # B1F1, B2F1, B3F1, B1E1, ... (notes §7)
            if self.dofs.get(flag):
                for k in range(t.number_of_blades):
                    name = blade_coordinate(k, flag)
                    self.coords[name] = sys.coordinates(name)
        self.p = self._parameters()
        sys.set_gravity([0.0, 0.0, -self.p["gravity"]])
        platform = self._platform()
        top = self._tower(platform)
        nacelle = self._nacelle(top)
        shaft = self._shaft(nacelle)
        hub = self._drivetrain(shaft)
        self._blades(hub)
        self._inputs(platform, nacelle, shaft, hub)

    def _parameters(self) -> dict[str, ca.SX]:
        """Named parameters with the deck's values as defaults (design studies, gradients)."""
        t = self.turbine
        values = {
            "gravity": t.simulation.gravity, "nacelle_mass": t.nacelle_mass,
            "nacelle_yaw_inertia": t.nacelle_yaw_inertia, "yaw_bearing_mass": t.yaw_bearing_mass,
            "hub_mass": t.hub_mass, "hub_inertia": t.hub_inertia, "generator_inertia": t.generator_inertia,
            "tower_stiffness_scale": 1.0,
        }
        if self.dofs.get("DrTrDOF"):
            values.update(drivetrain_stiffness=t.drivetrain_stiffness, drivetrain_damping=t.drivetrain_damping)
        if any(self.dofs.get(f) for f in _PLATFORM):
            values.update(platform_mass=t.platform_mass, platform_roll_inertia=t.platform_roll_inertia,
                          platform_pitch_inertia=t.platform_pitch_inertia,
                          platform_yaw_inertia=t.platform_yaw_inertia)
        # named physical parameters (ElastoDyn keys <-> names: named_parameters.py)
        values.update({k: v for k, v in parameter_defaults(t, self.dofs).items() if k not in values})
        syms = self.system.parameters(list(values), values=values)
        return dict(zip(values, syms if isinstance(syms, tuple) else (syms,)))

    def _add(self, joint: Joint) -> Body:
        self.system.add_joint(joint)
        self.bodies[joint.child.name] = joint.child
        return joint.child

    def _platform(self) -> Body:
        t, ic = self.turbine, self.turbine.initial_conditions
        init = [ic.platform_surge, ic.platform_sway, ic.platform_heave,
                ic.platform_roll, ic.platform_pitch, ic.platform_yaw]
        values = [self.coords.get(STATE_ORDER[f], v) for f, v in zip(_PLATFORM, init)]
        ref = np.asarray(t.platform_reference, dtype=float)
        if any(isinstance(v, ca.SX) for v in values):
            p = self.p
            com = [t.platform_cm[0] - ref[0], t.platform_cm[1] - ref[1], p["platform_cm_height"] - ref[2]]
            body = RigidBody("platform", mass=p["platform_mass"], com=com,      # products: ElastoDyn's -∫xy dm …
                             inertia=[p["platform_roll_inertia"], p["platform_pitch_inertia"],
                                      p["platform_yaw_inertia"], t.platform_xy_inertia, t.platform_yz_inertia,
                                      t.platform_xz_inertia])
        else:
            body = RigidBody("platform", mass=0.0)
        return self._add(PlatformJoint(self.system.ground, body, values=values, offset=ref))

    def _tower(self, platform: Body) -> tuple[Body, list[float]]:
        """Tower on the platform; returns (tower body, top offset in tower axes)."""
        t, p = self.turbine, self.p
        base = [0.0, 0.0, t.tower_base_height - t.platform_reference[2]]
        length = t.tower_height - t.tower_base_height
        active = [f for f in _TOWER if self.dofs.get(f)]
        if active:
            sid = tower_shape_integrals(t, dofs=active)
            ke, de, mass_scale = tower_matrices(t, active, p)
            tower = FlexibleBody("tower", sid, [self.coords[STATE_ORDER[f]] for f in active],
                                 kinematics="exact", end_rotation_order="elastodyn",
                                 end_angular_velocity="slope_rates",
                                 stiffness=p["tower_stiffness_scale"] * ke, damping=de, mass_scale=mass_scale)
        else:
            data = tower_elastodyn_data(t)
            m, h = np.asarray(data.element_mass), np.asarray(data.height)
            zc = float(m @ h / m.sum())
            i_xx = float(m @ (h - zc) ** 2)
            tower = RigidBody("tower", mass=float(m.sum()), com=[0, 0, zc], inertia=[i_xx, i_xx, 0.0])
        self._attach_tower(platform, tower, base)
        top = [0.0, 0.0, length]
        self._add(Fixed(tower, RigidBody("yaw_bearing", mass=p["yaw_bearing_mass"]), offset=top))
        return tower, top

    def _attach_tower(self, platform: Body, tower: Body, base) -> None:
        """Tower base on the platform: welded, or through locked rotations about x then y (reactions)."""
        if not self.tower_base_reactions:
            self._add(Fixed(platform, tower, offset=base))
            return
        rx, ry = self.system.locked(list(TOWER_BASE_LOCKED))
        hinge = RigidBody("tower_base", mass=0.0)
        self._add(Revolute(platform, hinge, axis=[1, 0, 0], coordinate=rx, offset=base))
        self._add(Revolute(hinge, tower, axis=[0, 1, 0], coordinate=ry))

    def _nacelle(self, tower_top) -> Body:
        t, p = self.turbine, self.p
        tower, top = tower_top
        cm = np.asarray(t.nacelle_cm, dtype=float)
        # ElastoDyn's only nacelle inertia: about the yaw axis through the CM (notes §4)
        i_zz = p["nacelle_yaw_inertia"] - p["nacelle_mass"] * (cm[0] ** 2 + cm[1] ** 2)
        nacelle = RigidBody("nacelle", mass=p["nacelle_mass"], com=cm, inertia=[0.0, 0.0, i_zz])
        if self.yaw_bearing_reactions:       # locked joints at the tower top: the yaw-bearing loads
            tower, top, _ = locked_chain(self, tower, YAW_BEARING_LOCKED, offset=top, rotation=None, label="yaw")
        if "Yaw" in self.coords:
            self._add(Revolute(tower, nacelle, axis=[0, 0, 1], coordinate=self.coords["Yaw"], offset=top))
            k, c, neutral = self._yaw
            if k:
                self.system.add_spring(self.coords["Yaw"], k, rest=neutral)
            if c:
                self.system.add_damper(self.coords["Yaw"], c)
            if self.yaw_command:                  # ServoDyn's commanded yaw and rate (deck.yaw_control)
                position, rate = self.system.inputs(["YawPosCom", "YawRateCom"])
                self.system.add_generalized_force(self.coords["Yaw"], k * (position - neutral) + c * rate)
        else:
            self._add(Fixed(tower, nacelle, offset=top, rotation=rotation("z", t.initial_conditions.nacelle_yaw)))
        return nacelle

    def _shaft(self, nacelle: Body) -> Body:
        """Massless shaft frame at the rotor apex: x along the shaft (c1), tilted by ShftTilt."""
        t = self.turbine
        tilt = t.shaft_tilt
        c1 = np.array([np.cos(tilt), 0.0, np.sin(tilt)])
        apex = np.array([0.0, 0.0, t.twr2shft]) + t.overhang * c1
        shaft = RigidBody("shaft", mass=0.0)
        return self._add(Fixed(nacelle, shaft, offset=apex, rotation=rotation("y", -tilt)))

    def _azimuth(self) -> ca.SX | float:
        """Generator azimuth: coordinate, prescribed input (spinning, GenDOF off) or constant."""
        if "GeAz" in self.coords:
            return self.coords["GeAz"]
        q0, om = self.initial_generator_azimuth(), self.turbine.initial_conditions.rotor_speed
        if om == 0.0 and not self.prescribed_azimuth:
            return q0
        psi = self.system.prescribed("GeAz")
        self.prescribed.update({"GeAz": lambda s, q0=q0, om=om: q0 + om * s,
                                "GeAz_d": lambda s, om=om: om, "GeAz_dd": lambda s: 0.0})
        return psi

    def _drivetrain(self, shaft: Body) -> Body:
        t, p = self.turbine, self.p
        psi = self._azimuth()
        ratio = abs(t.gearbox_ratio)
        gen = RigidBody("generator", mass=0.0, inertia=[generator_inertia(self), 0.0, 0.0])   # GBoxEff
        hub = RigidBody("hub", mass=p["hub_mass"], com=[t.hub_cm, 0.0, 0.0], inertia=[p["hub_inertia"], 0.0, 0.0])
        if isinstance(psi, ca.SX):
            self._add(Revolute(shaft, gen, axis=[1, 0, 0], coordinate=psi, gear_ratio=ratio))
        else:
            self._add(Fixed(shaft, gen, rotation=rotation("x", ratio * psi)))
        cut = shaft                          # the rotor's side of the shaft: locked joints for the shaft loads
        if self.shaft_reactions:
            cut = locked_chain(self, shaft, SHAFT_LOCKED, offset=[0.0, 0.0, 0.0], rotation=None, label="lss")[0]
        lss = cut
        if "DrTr" in self.coords:
            lss = RigidBody("lss", mass=0.0)
            self._joint_about_x(cut, lss, psi)
            self._add(Revolute(lss, hub, axis=[1, 0, 0], coordinate=self.coords["DrTr"]))
            self.system.add_spring(self.coords["DrTr"], p["drivetrain_stiffness"])
            self.system.add_damper(self.coords["DrTr"], p["drivetrain_damping"])
        else:
            self._joint_about_x(lss, hub, psi)
        return hub

    def _joint_about_x(self, parent: Body, child: Body, angle) -> None:
        if isinstance(angle, ca.SX):
            self._add(Revolute(parent, child, axis=[1, 0, 0], coordinate=angle))
        else:
            self._add(Fixed(parent, child, rotation=rotation("x", angle)))

    def _rotor_mass(self):
        """Hub + blades [kg] (ElastoDyn's RotMass), hub mass as a parameter."""
        return self.p["hub_mass"] + sum(rotor_mass_properties(self.turbine).blade_mass)

    def _blades(self, hub: Body) -> None:
        """Coned and pitched blades of ElastoDyn's lumped node masses (notes §1.8, §4).

        Flexible blades carry the enabled FlapDOF1/FlapDOF2/EdgeDOF shapes; with no blade
        DOF each blade is one rigid body with the same mass distribution.
        """
        t = self.turbine
        n = t.number_of_blades
        flags = [f for f in BLADE_DOFS if self.dofs.get(f)]            # body order F1, F2, E1
        pitch = self._pitch()
        for k in range(n):
            name = f"blade{k + 1}"
            if flags:
                sid = blade_shape_integrals(t, k, dofs=flags)
                mats = blade_matrices(t, k, flags, self.p)          # None: blades differ, numeric K, C
                blade = FlexibleBody(name, sid, [self.coords[blade_coordinate(k, f)] for f in flags],
                                     kinematics="exact",
                                     **({} if mats is None else {"stiffness": mats[0], "damping": mats[1]}))
            else:
                blade = rigid_blade(self.blade_data(k), name)
            root = (t.hub_radius * blade_rotation(2 * np.pi * k / n, t.precone[k], 0.0)[:, 2]).tolist()
            if pitch is not None:
                # pitch about -j3 (notes §4: j1 = cos i1 - sin i2) of a massless pitch frame; blades 2.. follow
                # the one prescribed angle through a unit gear ratio.
                bearing = RigidBody(f"pitch{k + 1}", mass=0.0)
                R0 = blade_rotation(2 * np.pi * k / n, t.precone[k], 0.0)
                parent, offset, rot = self._blade_root(hub, k, root, R0)
                own = isinstance(pitch, list)
                self._add(Revolute(parent, bearing, axis=[0, 0, -1], coordinate=pitch[k] if own else pitch,
                                   offset=offset, rotation=rot, gear_ratio=None if k == 0 or own else 1.0))
                self._add(Fixed(bearing, blade))
            else:
                R = blade_rotation(2 * np.pi * k / n, t.precone[k], t.initial_conditions.blade_pitch[k])
                self._add(Fixed(hub, blade, offset=root, rotation=R.tolist()))

    def _blade_root(self, hub: Body, k: int, root: list, R0: np.ndarray) -> tuple[Body, list, list]:
        """Parent, offset and rotation of blade ``k``'s pitch bearing: the hub, or with
        the locked root translations (``blade_root_forces``) and rotations (``blade_root_reactions``)."""
        names = (BLADE_ROOT_FORCE_LOCKED if self.blade_root_forces else ()) + \
            (BLADE_ROOT_LOCKED if self.blade_root_reactions else ())
        if not names:
            return hub, root, R0.tolist()
        return locked_chain(self, hub, [f"B{k + 1}{n}" for n in names], offset=root, rotation=R0.tolist(),
                            label=f"root{k + 1}")

    def _pitch(self) -> "ca.SX | list[ca.SX] | None":
        """Pitch: a collective prescribed coordinate, one per blade (``"individual"``), or None (deck's BlPitch)."""
        if not self.pitch_input:
            return None
        pitches = [float(b) for b in self.turbine.initial_conditions.blade_pitch]
        if self.pitch_input == "individual":
            names = [f"BlPitch{k + 1}" for k in range(self.turbine.number_of_blades)]
            coords = self.system.prescribed(names)
            coords = list(coords) if isinstance(coords, tuple) else [coords]
            for name, b0 in zip(names, pitches):
                self.prescribed.update({name: lambda s, b0=b0: b0, f"{name}_d": lambda s: 0.0,
                                        f"{name}_dd": lambda s: 0.0})
            return coords
        b0 = pitches[0]
        pitch = self.system.prescribed("BlPitch")
        self.prescribed.update({"BlPitch": lambda s, b0=b0: b0, "BlPitch_d": lambda s: 0.0,
                                "BlPitch_dd": lambda s: 0.0})
        return pitch

    def _inputs(self, platform: Body, nacelle: Body, shaft: Body, hub: Body) -> None:
        """Loads exposed as inputs, only where they can move an enabled DOF (:mod:`.load_inputs`)."""
        add_load_inputs(self, platform, shaft, hub)

    def blade_coordinates(self, blade: int) -> tuple[str, ...]:
        """Elastic coordinates of blade ``blade`` (0-based) in the body's shape order (F1, F2, E1)."""
        return tuple(blade_coordinate(blade, f) for f in BLADE_DOFS if self.dofs.get(f))
