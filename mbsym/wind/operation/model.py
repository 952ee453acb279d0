"""The operating turbine: structure + rotor aerodynamics + actuators + generator as one :class:`mbsym.Dynamics`.

:class:`OperatingTurbine` composes

* the ElastoDyn-equivalent structure (:class:`~mbsym.wind.structure.turbine.TurbineModel`
  with the deck's DOFs, collective pitch as a prescribed coordinate, and the tower attached
  through locked rotations whose reactions are the tower-base moments);
* the rotor loads of :class:`~mbsym.wind.aero.RotorAero` from the **relative** wind along the
  shaft, ``U_rel = W·c₁ − v_hub·c₁`` (``W = (U, 0, 0)`` the horizontal hub-height wind,
  ``c₁`` the actual shaft axis including the tower-top rotation, ``v_hub`` the velocity of
  the rotor apex): thrust along ``c₁`` on the hub (the structure's ``RotThrust``) and torque
  about it (``RotTorq``). Tower motion changes ``U_rel``, which is the aerodynamic damping;
* the pitch and generator-torque actuators and the generator efficiency
  (:mod:`.actuators`);
* the rotor-averaged dynamic inflow of :mod:`.dynamic_inflow` (AeroDyn's DBEMT on the
  surfaces; two states, on by default as in AeroDyn 15 decks with ``DBEMT_Mod = 2``), or the
  simpler first-order lag of :meth:`RotorAero.inflow_lag_rhs` on thrust and torque (two
  states), or neither (quasi-steady loads).

States: the structure's ``[q; q̇]``, then ``BlPitch`` [rad], ``BlPitch_d`` [rad/s],
``GenTq`` [N m] (high-speed shaft), ``GeAz`` [rad] when GenDOF is off (the rotor turns at
the parameter ``rotor_speed``), ``DBEMT_w``, ``DBEMT_v`` [m/s] with the dynamic inflow
(Øye's intermediate state and the rotor-averaged induced velocity), or ``RotThrustLag`` [N],
``RotTorqLag`` [N m] with the inflow lag.

Inputs: ``Wind1VelX`` [m/s] (hub-height wind), ``BlPitchCom`` [rad], ``GenTqCom`` [N m],
then any structural input not driven here (platform loads), in the structure's order.

Parameters: the structure's (``gravity``, masses, ...), ``air_density`` [kg/m^3],
``cp_scale``, ``ct_scale`` [-] (factors on the torque and thrust coefficients), the
actuator parameters of :data:`~mbsym.wind.operation.actuators.ACTUATOR_PARAMETERS`, and
``rotor_speed`` [rad/s] when GenDOF is off.

Outputs: OpenFAST channels with OpenFAST's names and units (:mod:`.channels`).

**Floating** (``platform`` a :class:`~mbsym.wind.offshore.operating.FloatingPlatform`, or
``OperatingTurbine.from_openfast(fst)`` on a deck with HydroDyn and a mooring): the water's and the
mooring's loads drive the structure's platform inputs ``PtfmFx … PtfmMz`` (no longer inputs of the
model), A∞ joins the platform block of the mass matrix, the radiation states ``Rdtn1 …`` follow the
other states, and the channels grow by ``HydroFxi … HydroMzi``, ``FAIRTEN1..n``, ``Wave1Elev`` and the
nacelle's pitching acceleration ``NcIMURAys`` (ROSCO's floating feedback measures it).

**The blade-element rung** (``rotor`` a :class:`~mbsym.wind.aero.blade.BladeElementRotor`, or
``OperatingTurbine.from_openfast(fst, aero="blade")``): instead of thrust and torque on the hub, BEM with
dynamic wake on every AeroDyn node of every blade, in the wind at the node's current position
(:mod:`.blade_compose`). The structure then has blade-load inputs and locked blade-root rotations (root
moments ``RootM*c<k>``); the states add the rotor's wake states (``rotor.state_names``) instead of the
rotor-averaged inflow; the wind inputs are InflowWind's uniform columns (:data:`.wind_inputs.UNIFORM_INPUTS`)
or a full field's time ``WindTime`` (:mod:`.wind_inputs`); ``pitch="individual"`` gives every blade its own
actuator (states ``BlPitch<k>``, inputs ``BlPitchCom<k>``).
"""

from __future__ import annotations

import warnings
from typing import TYPE_CHECKING, Any, Mapping, Sequence

import numpy as np

from ...dynamics import Dynamics
from ...exceptions import ParameterError
from ...held import HeldPart
from ..aero.rotor import RotorAero
from ..deck.parameters import TurbineParameters
from ..structure.gearbox import generator_torque_at_shaft, has_losses, hss_torque_for
from ..structure.turbine import TurbineModel
from .actuators import ActuatorSettings
from .dynamic_inflow import DynamicInflow
from ..deck.yaw_control import checked_yaw_control

if TYPE_CHECKING:
    from ..aero.blade import BladeElementRotor

__all__ = ["OperatingTurbine", "OPERATING_DOFS", "COMMANDS", "AERO_PARAMETERS"]

#: The DOFs of the built-in operating NREL 5 MW: the ones the rotor loads (thrust and torque on the hub)
#: and the generator torque reaction act on, and those of the OpenFAST reference runs.
OPERATING_DOFS = ("GenDOF", "TwFADOF1", "TwSSDOF1")
#: Commands (inputs after the wind), SI units.
COMMANDS = {"BlPitchCom": "rad", "GenTqCom": "N m"}
#: Pitch actuation: one collective actuator, or one per blade (inputs ``BlPitchCom<k>``; blade-element rotor only).
PITCH_MODES = ("collective", "individual")
#: Aerodynamic parameters: name -> unit.
AERO_PARAMETERS = {"air_density": "kg/m^3", "cp_scale": "-", "ct_scale": "-"}
_UNLOADED = ("FlapDOF1", "FlapDOF2", "EdgeDOF", "YawDOF")


class OperatingTurbine:
    """An operating wind turbine (see the module docstring) with its :meth:`dynamics`.

    Parameters
    ----------
    turbine : TurbineParameters
        Structure (:func:`mbsym.wind.read_openfast`, :func:`mbsym.wind.nrel5mw`).
    rotor : RotorAero, optional
        Rotor aerodynamics; default the built-in NREL 5 MW (:func:`mbsym.wind.aero.nrel5mw_rotor`).
    dofs : sequence of str, optional, keyword-only
        ElastoDyn DOF flags; default the deck's own. The rotor loads act on the hub only:
        blade and yaw DOFs get no aerodynamic load (a warning says so).
    actuators : ActuatorSettings, optional, keyword-only
        Default :meth:`ActuatorSettings.nrel5mw`.
    dynamic_inflow : bool or DynamicInflow, optional, keyword-only
        Rotor-averaged dynamic inflow (:class:`~.dynamic_inflow.DynamicInflow`; True: AeroDyn's
        ``DBEMT_Mod = 2`` with Øye's time constants). Default True.
    inflow_lag : bool, optional, keyword-only
        Instead, the first-order lag on thrust and torque of :meth:`RotorAero.inflow_lag_rhs`
        (two states). Default False.
    yaw_spring, yaw_damping : float, optional, keyword-only
        Yaw bearing spring [N m/rad] and damper [N m s/rad] (with YawDOF).
    yaw_neutral : float, optional, keyword-only
        Yaw where the spring is relaxed [rad] (ServoDyn's YawNeut; default the initial NacYaw).
    yaw_control : YawManeuver or DllYaw, optional, keyword-only
        ServoDyn's commanded yaw (:mod:`.yaw_control`): the inputs ``YawPosCom``, ``YawRateCom`` move the spring.
    saturation_width : float, optional, keyword-only
        Relative half-width of the smooth saturation corners (:func:`~.actuators.smooth_clip`).
    wind : UniformWindInputs, FieldWindInputs or FullFieldWind, optional, keyword-only
        Blade-element rotor only: the wind over the rotor (:mod:`.wind_inputs`); default uniform wind
        with InflowWind's columns as inputs at the hub height.
    output_nodes : sequence of int, optional, keyword-only
        Blade-element rotor only: AeroDyn's ``BlOutNd`` (node channels ``B1N<j>*``).
    pitch : {"collective", "individual"}, optional, keyword-only
        One pitch actuator (input ``BlPitchCom``), or one per blade (inputs ``BlPitchCom1..3``, states
        ``BlPitch1..3``, ``BlPitch1_d..``; blade-element rotor only, for individual pitch control).
    load_channels : bool, optional, keyword-only
        Add the locked joints (:mod:`mbsym.wind.structure.load_cuts`) whose reactions give the channels
        ``LSShftFxa``, ``LSShftFys``, ``LSShftFzs``, ``YawBrFxp`` … ``YawBrMzp`` and, with the blade-element
        rotor, ``RootFxc<k>`` … ``RootFzc<k>``, ``RootFxb<k>``, ``RootFyb<k>``. The right-hand side is unchanged;
        the output Function grows (benchmarks/README.md, "Load channels"). Default False.
    disk_moments : bool or None, optional, keyword-only
        Rotor-effective model only: the aerodynamic moment of the rotor disk against its tilt and yaw
        rates, its steady moment and in-plane force in a skewed flow (the rotor's ``moment_table``, when its
        surfaces have one) and its in-plane force against the hub's velocity across the shaft (``RotMomY``, ``RotMomZ``,
        ``RotFrcY``, ``RotFrcZ`` on the hub; :meth:`.compose.Graph._disk_moments`), which the blade-element
        rotor has by construction. It raises the tower fore-aft damping at 14 m/s from 5.5 % to 6.9 % from a
        deck (7.2 % for the built-in turbine's Cp/Ct-file rotor; blade-element rotor: 7.3 %). Default None: on for a floating turbine (``platform``; its roll, yaw
        and sway move the rotor across its shaft: docs/offshore.md §7c), off on land for now
        (docs/operation.md); ``mbsym identify``, ``mbsym linearize`` and ``mbsym operating-points`` switch it on
        (OpenFAST's linearization: docs/operating_points.md).
    tower_aero : TowerAero, optional, keyword-only
        AeroDyn's tower (:class:`~mbsym.wind.aero.tower.TowerAero`, ``TowerAero.from_aerodyn``): with ``drag`` its
        drag loads the tower and platform DOFs (both rotors; the rotor-effective rung's wind is the hub wind at
        every height); with ``potential`` or ``shadow`` it disturbs the blades' inflow (blade-element rotor only).
        Default None: no tower aerodynamics.
    nacelle_drag : NacelleDrag, optional, keyword-only
        AeroDyn's nacelle drag (:class:`~mbsym.wind.aero.nacelle.NacelleDrag`, ``NacelleDrag.from_aerodyn``): a force
        at the yaw bearing and its moment, from the wind there (both rotors, as ``tower_aero``'s drag), and the
        channels ``NcFdx`` … ``NcMzi``. Default None.
    sector_average : SectorAverage, optional, keyword-only
        AeroDyn's ``SectAvg`` (:class:`~mbsym.wind.aero.sector_average.SectorAverage`): every blade node takes the
        wind averaged over its sector. Blade-element rotor only. Default None.
    platform : FloatingPlatform, optional, keyword-only
        The water and the mooring on the platform (:func:`mbsym.wind.offshore.floating_platform`); the
        structure needs all six platform DOFs. Default None (no platform loads: they stay inputs).
    hss_brake : HssBrake, optional, keyword-only
        ServoDyn's high-speed shaft brake (:class:`~.hss_brake.HssBrake`): the input ``HSSBrTqC`` [N m] (the
        deck's ramp in :func:`~.simulation.simulate_turbine`, zero in trims) and the channel ``HSSBrTq``; needs
        GenDOF. Default None.
    structural_controls : StructuralControls, optional, keyword-only
        ServoDyn's nacelle and platform tuned mass dampers (:mod:`~.structural_control`, from the deck by
        :func:`~.structural_control.structural_controls`): their states ``NStC1_XQ`` … after the others and their
        channels. Default None.
    name : str, optional, keyword-only

    Raises
    ------
    TypeError
        Arguments of the wrong type.
    ModelDefinitionError
        DOFs the structure cannot model; blades with different initial pitch.

    Examples
    --------
    >>> from mbsym.wind import nrel5mw
    >>> from mbsym.wind.operation import OperatingTurbine, OPERATING_DOFS
    >>> model = OperatingTurbine(nrel5mw(), dofs=OPERATING_DOFS)
    >>> dyn = model.dynamics()
    >>> dyn.inputs
    ('Wind1VelX', 'BlPitchCom', 'GenTqCom')
    >>> dyn.states[6:]
    ('BlPitch', 'BlPitch_d', 'GenTq', 'DBEMT_w', 'DBEMT_v')
    """

    def __init__(self, turbine: TurbineParameters, rotor: "RotorAero | BladeElementRotor | None" = None, *,
                 dofs: Sequence[str] | None = None, actuators: ActuatorSettings | None = None,
                 dynamic_inflow: "bool | DynamicInflow | None" = None, inflow_lag: bool = False,
                 yaw_spring: float = 0.0, yaw_damping: float = 0.0, yaw_neutral: float | None = None,
                 yaw_control=None, saturation_width: float = 1e-4,
                 wind=None, output_nodes: Sequence[int] = (), pitch: str = "collective",
                 load_channels: bool = False, disk_moments: bool | None = None, platform=None,
                 tower_aero=None, nacelle_drag=None, sector_average=None, hss_brake=None, structural_controls=None,
                 name: str = "operating_turbine") -> None:
        if not isinstance(turbine, TurbineParameters):
            raise TypeError(f"turbine must be TurbineParameters (read_openfast or nrel5mw); got {type(turbine).__name__}.")
        if rotor is None:
            from ..aero.nrel5mw import nrel5mw_rotor
            rotor = nrel5mw_rotor()
        blade = _is_blade_rotor(rotor)
        if not (blade or isinstance(rotor, RotorAero)):
            raise TypeError(f"rotor must be a RotorAero (nrel5mw_rotor(), RotorAero.from_openfast(fst)) or a "
                            f"BladeElementRotor (BladeElementRotor.from_openfast(fst)); got {type(rotor).__name__}.")
        actuators = ActuatorSettings.nrel5mw() if actuators is None else actuators
        if not isinstance(actuators, ActuatorSettings):
            raise TypeError(f"actuators must be an ActuatorSettings; got {type(actuators).__name__}.")
        if not (isinstance(saturation_width, float) and 0 < saturation_width < 0.1):
            raise ParameterError(f"saturation_width must be a float in (0, 0.1); got {saturation_width!r}.")
        self.turbine, self.rotor, self.actuators = turbine, rotor, actuators
        self.aero = "blade" if blade else "rotor"
        if pitch not in PITCH_MODES:
            raise ParameterError(f"pitch must be one of {list(PITCH_MODES)}; got {pitch!r}.")
        if pitch == "individual" and not blade:
            raise ParameterError("pitch='individual' needs the blade-element rotor (aero='blade'): the rotor-effective "
                                 "model has one collective pitch.")
        self.pitch = pitch
        n = turbine.number_of_blades
        self.pitch_names = tuple(f"BlPitch{k + 1}" for k in range(n)) if pitch == "individual" else ("BlPitch",)
        self.command_names = tuple(f"BlPitchCom{k + 1}" for k in range(n)) if pitch == "individual" else \
            ("BlPitchCom",)
        self.command_names += ("GenTqCom",)
        self.inflow_lag = bool(inflow_lag)
        if blade:
            if dynamic_inflow is not None or self.inflow_lag:
                raise ParameterError("dynamic_inflow and inflow_lag belong to the rotor-effective model; a blade-element "
                                     "rotor carries its own dynamic wake (BladeElementRotor options).")
            self.dynamic_inflow = None
            self.wind = _blade_wind(turbine, rotor, wind)
        else:
            if wind is not None:
                raise ParameterError("wind= describes the wind over the rotor for a blade-element rotor; the "
                                     "rotor-effective model takes the hub wind as the input Wind1VelX.")
            self.wind = None
            self.dynamic_inflow = _rotor_inflow(rotor, dynamic_inflow, self.inflow_lag)
        self.saturation_width = saturation_width
        if not isinstance(load_channels, bool):
            raise TypeError(f"load_channels must be True or False; got {load_channels!r}.")
        if disk_moments is None:                # default: on for a floating rotor-effective turbine (docs/offshore.md §7c)
            disk_moments = platform is not None and not blade
        if not isinstance(disk_moments, bool):
            raise TypeError(f"disk_moments must be True, False or None; got {disk_moments!r}.")
        if disk_moments and blade:
            raise ParameterError("disk_moments belongs to the rotor-effective model: a blade-element rotor's loads "
                                 "already give the disk's moments (leave disk_moments False).")
        self.name = str(name)
        self.platform = _platform(platform)
        self.hss_brake = _hss_brake(hss_brake, turbine, dofs)
        from ..structure.structural_control import StructuralControls

        if structural_controls is not None and not isinstance(structural_controls, StructuralControls):
            raise TypeError(f"structural_controls must be a StructuralControls or None; got "
                            f"{type(structural_controls).__name__}.")
        self.structural_controls = structural_controls
        self.brake_slip_speed = 0.0
        self.tower_aero = _tower_aero(tower_aero, blade, getattr(rotor, "tower_inflow", False))
        _check_tower_in_field(self.tower_aero, self.wind)
        from ..aero.nacelle import NacelleDrag

        if nacelle_drag is not None and not isinstance(nacelle_drag, NacelleDrag):
            raise TypeError(f"nacelle_drag must be a NacelleDrag or None; got {type(nacelle_drag).__name__}.")
        self.nacelle_drag = nacelle_drag
        from ..aero.sector_average import SectorAverage

        if sector_average is not None and (not isinstance(sector_average, SectorAverage) or not blade):
            raise ParameterError("sector_average must be a SectorAverage, with a blade-element rotor (aero='blade'): "
                                 "the rotor-effective rung's wind is one hub-height speed, uniform over the disk.")
        self.sector_average = sector_average
        self.structure = TurbineModel(turbine, dofs, pitch_input="individual" if pitch == "individual" else True,
                                      tower_base_reactions=True,
                                      yaw_spring=yaw_spring, yaw_damping=yaw_damping, yaw_neutral=yaw_neutral,
                                      yaw_command=yaw_control is not None,
                                      prescribed_azimuth=True,
                                      blade_loads=blade, blade_root_reactions=blade,
                                      blade_root_forces=blade and bool(load_channels),
                                      shaft_reactions=bool(load_channels), yaw_bearing_reactions=bool(load_channels),
                                      hub_moments=bool(disk_moments),
                                      tower_loads=self.tower_aero is not None and self.tower_aero.drag,
                                      nacelle_loads=nacelle_drag is not None)
        self.yaw_control = checked_yaw_control(yaw_control, self.structure)
        if self.hss_brake is not None:                  # its slip zone against the inertia it turns (.hss_brake)
            self.brake_slip_speed = self.hss_brake.slip_speed(_brake_inertia(self.structure, self.gearbox_ratio))
        unloaded = [f for f in _UNLOADED if self.structure.dofs.get(f)]
        if unloaded and not blade:
            warnings.warn(f"DOFs {unloaded} get no aerodynamic load: the rotor model applies thrust and torque on the "
                          "hub only (rigid-rotor performance surfaces); their motion is structural only. The "
                          "blade-element rotor (aero='blade') loads them.", UserWarning, stacklevel=2)
        self.output_nodes = _output_nodes(output_nodes, rotor if blade else None)
        self._dynamics: Dynamics | None = None
        self._parts: dict[str, Any] = {}

    # ------------------------------------------------------------------ description
    @property
    def dofs(self) -> dict[str, bool]:
        """ElastoDyn flags -> enabled (the structure's)."""
        return self.structure.dofs

    @property
    def gearbox_ratio(self) -> float:
        return abs(float(self.turbine.gearbox_ratio))

    @property
    def spins_freely(self) -> bool:
        """Whether the rotor speed is a DOF (GenDOF on); else it turns at ``rotor_speed``."""
        return "GeAz" in self.structure.coords

    def bounds(self) -> dict[str, tuple[float, float]]:
        """Actuator limits for optimization (:meth:`ActuatorSettings.bounds`)."""
        return self.actuators.bounds()

    def dynamics(self) -> Dynamics:
        """The composed model as an :class:`mbsym.Dynamics` (built once; see the module docstring)."""
        if self._dynamics is None:
            from .compose import compose

            graph = None
            if self.aero == "blade":
                from .blade_compose import BladeGraph as graph
            self._dynamics = compose(self, graph)
        return self._dynamics

    def measurement_dynamics(self) -> Dynamics:
        """The same dynamics with only the controllers' measurements as outputs (cheap to evaluate in a loop).

        Outputs :func:`~.controllers.measurement_names` (OpenFAST units); every channel is evaluated
        afterwards from the states (:func:`~.simulation.simulate_turbine` does).
        """
        if "measurement_dynamics" not in self._parts:
            d = self.dynamics()
            held = None
            if d.held is not None:
                held = HeldPart(d.held.part, d.held.rhs, self._parts["measurements_held"], d.held.description)
            self._parts["measurement_dynamics"] = Dynamics(
                d.rhs, states=d.states, inputs=d.inputs, parameters=d.parameters, defaults=dict(d.defaults),
                outputs=self._parts["measurements"], output_names=self._parts["measurement_names"],
                output_units=self._parts["measurement_units"], x0=d.x0, u0=d.u0, name=f"{d.name}_measured",
                eom=d.eom, held=held, state_units=d.state_units, input_units=d.input_units)
        return self._parts["measurement_dynamics"]

    # ------------------------------------------------------------------ initial states
    def initial_state(self, wind_speed: float | None = None, *, rotor_speed: float | None = None,
                      pitch: float | None = None, torque: float | None = None,
                      tower_fa: float | None = None, tower_ss: float | None = None,
                      p: Mapping[str, float] | None = None) -> np.ndarray:
        """A state vector from the deck's initial conditions (ElastoDyn's keys), with overrides.

        Parameters
        ----------
        wind_speed : float or dict, optional
            Wind at t = 0 [m/s]: the generator torque starts at the value that balances the
            aerodynamic torque (the rotor starts without acceleration), within the torque
            limits. Without it the torque starts at ``torque`` or 0. For a blade-element model,
            the wind inputs by name (a number is ``Wind1VelX``, or ``WindTime`` [s] for a full
            field); its wake states then start at equilibrium.
        rotor_speed, pitch, torque, tower_fa, tower_ss : float, optional, keyword-only
            Override RotSpeed [rad/s], BlPitch [rad], the generator torque [N m] (HSS),
            TTDspFA, TTDspSS [m].
        p : dict, optional, keyword-only
            Parameter values by name for the balances (default: the model's).

        With the wind given, the dynamic-inflow (or lag) states start at equilibrium and, with
        DrTrDOF, the drivetrain starts twisted by the balancing torque (``N T_gen / k``).
        """
        dyn = self.dynamics()
        x = dict(zip(dyn.states, dyn.x0))
        coords = self.structure.eom.coordinates
        if rotor_speed is not None:
            if self.spins_freely:
                x["GeAz_d"] = float(rotor_speed)
            else:
                raise ParameterError("rotor_speed: GenDOF is off, the rotor turns at the parameter 'rotor_speed'; "
                                     "pass p={'rotor_speed': ...} to the simulation instead.")
        if pitch is not None:
            x.update(dict.fromkeys(self.pitch_names, float(pitch)))
        for value, modes in ((tower_fa, ("TFA1", "TFA2")), (tower_ss, ("TSS1", "TSS2"))):
            if value is not None:
                mode = next((m for m in modes if m in coords), None)
                if mode is None:
                    raise ParameterError(f"no tower DOF to set {modes[0][:3]} displacement {value!r} on; the "
                                         f"coordinates are {list(coords)}.")
                x[mode] = float(value)
        if wind_speed is not None and self.aero == "blade":
            x.update(self.wake_equilibrium(x, wind_speed, p))
        elif wind_speed is not None:
            vec = np.array([x[s] for s in dyn.states])
            u = dyn.input_vector(self._wind_inputs(wind_speed))
            if self.dynamic_inflow is not None or self.inflow_lag:
                names = ("DBEMT_w", "DBEMT_v") if self.dynamic_inflow is not None else ("RotThrustLag", "RotTorqLag")
                eq = np.asarray(self._part("inflow_steady")(vec, u, dyn.parameter_vector(p)), dtype=float)
                x.update(zip(names, eq.reshape(-1)))
        if torque is not None:
            x["GenTq"] = float(torque)
        elif wind_speed is not None:
            x["GenTq"] = self.balancing_torque(np.array([x[s] for s in dyn.states]), wind_speed, p)
        if "DrTr" in coords and (wind_speed is not None or torque is not None):
            stiffness = dict(zip(dyn.parameters, dyn.parameter_vector(p)))["drivetrain_stiffness"]
            x["DrTr"] = self.gearbox_ratio * generator_torque_at_shaft(x["GenTq"], self.gearbox_efficiency) / stiffness
        return np.array([x[s] for s in dyn.states])

    def wake_equilibrium(self, x: dict, wind, p: Mapping[str, float] | None = None) -> dict[str, float]:
        """Blade-element rotor: the wake (DBEMT) and unsteady-airfoil states at equilibrium with the inflow of state
        ``x`` (states by name; wind: hub speed [m/s] or the wind inputs by name), by name."""
        dyn = self.dynamics()
        vec = np.array([x[s] for s in dyn.states])
        u = dyn.input_vector(self._wind_inputs(wind))
        inflow = self._part("blade_inflow")
        values = dict(zip(inflow.name_out(), (np.asarray(v, dtype=float).ravel()
                                               for v in inflow(vec, u, dyn.parameter_vector(p)))))
        rotor = {k: float(values[f"rotor_{k}"][0]) for k in ("skew", "skew_azimuth", "un_disk")
                 if f"rotor_{k}" in values}
        states = self.rotor.steady_states(values["node_vx"], values["node_vy"], values["node_r_local"],
                                          values["node_theta"], values["node_azimuth"],
                                          ua_omega=values.get("node_ua_omega"), **rotor)
        return dict(zip(self.rotor.state_names, np.asarray(states, dtype=float).ravel()))

    def _wind_inputs(self, wind) -> dict[str, float]:
        """Wind inputs by name: a number is the hub speed ``Wind1VelX`` (or, for a field, the time ``WindTime``)."""
        if isinstance(wind, Mapping):
            return {k: float(v) for k, v in wind.items()}
        if self.wind is not None and "WindTime" in self.wind.inputs:
            return {"WindTime": float(wind)}
        return {"Wind1VelX": float(wind)}

    def balancing_torque(self, x: np.ndarray, wind_speed: "float | Mapping[str, float]",
                         p: Mapping[str, float] | None = None) -> float:
        """Generator torque [N m] (HSS) balancing the aerodynamic torque at state ``x`` and wind [m/s], clipped
        to the torque limits."""
        f = self._part("aero_torque")
        dyn = self.dynamics()
        q_aero = float(f(x, dyn.input_vector(self._wind_inputs(wind_speed)), dyn.parameter_vector(p)))
        a = self.actuators
        torque = hss_torque_for(q_aero, self.gearbox_ratio, self.gearbox_efficiency)
        return float(np.clip(torque, a.torque_min, a.torque_max))

    @property
    def gearbox_efficiency(self) -> float:
        """GBoxEff / 100 where the gearbox losses act (a generator DOF), else 1 (:mod:`..structure.gearbox`)."""
        return float(self.turbine.gearbox_efficiency) if has_losses(self.structure) else 1.0

    def _part(self, key: str):
        self.dynamics()
        return self._parts[key]

    def __repr__(self) -> str:
        on = [f for f, v in self.dofs.items() if v]
        if self.aero == "blade":
            return f"OperatingTurbine(dofs={on}, rotor={self.rotor!r}, wind={self.wind!r})"
        inflow = "dynamic" if self.dynamic_inflow is not None else ("lag" if self.inflow_lag else "quasi-steady")
        floating = "" if self.platform is None else f", platform={self.platform!r}"
        return f"OperatingTurbine(dofs={on}, rotor={self.rotor.source!r}, inflow={inflow!r}{floating})"

    # ------------------------------------------------------------------ constructors
    @classmethod
    def from_openfast(cls, fst, *, aero: str | None = None, dofs: Sequence[str] | None = None,
                      **options) -> "OperatingTurbine":
        """The operating turbine an OpenFAST deck describes (ElastoDyn, AeroDyn 15, InflowWind, ServoDyn).

        Parameters
        ----------
        fst : str or Path
            The ``.fst`` (``CompAero = 2``).
        aero : {"blade", "rotor"}, optional, keyword-only
            ``"blade"``: blade-element aerodynamics on every blade (:class:`~mbsym.wind.aero.blade.
            BladeElementRotor`) in the deck's wind over the rotor (full field, or uniform wind with its
            shears as inputs); ``"rotor"``: the rotor-effective model (Cp/Ct surfaces of the deck's
            blades, hub-height wind). Default: :meth:`~.deck.OperatingDeck.default_aero` (``"blade"``
            whenever the deck's wind or DOFs need it).
        dofs : sequence of str, optional, keyword-only
            ElastoDyn DOF flags (default: the deck's).
        **options
            Passed to the constructor (``actuators`` default the deck's).
        """
        from .deck import operating_deck

        return operating_deck(fst).model(dofs=dofs, aero=aero, **options)

    @classmethod
    def nrel5mw(cls, *, dofs: Sequence[str] = OPERATING_DOFS, **options) -> "OperatingTurbine":
        """The built-in NREL 5 MW (package data) with :data:`OPERATING_DOFS` by default."""
        from ..deck.nrel5mw import nrel5mw

        return cls(nrel5mw(), dofs=dofs, **options)


#: What the operation layer uses of a platform-loads object (:class:`mbsym.wind.offshore.FloatingPlatform`).
_PLATFORM_PROTOCOL = ("coordinates", "inputs", "state_names", "added_mass", "loads", "channel_rows")


def _platform(platform):
    """``platform`` if it offers what the composition uses (:data:`_PLATFORM_PROTOCOL`), or None."""
    if platform is None:
        return None
    missing = [a for a in _PLATFORM_PROTOCOL if not hasattr(platform, a)]
    if missing:
        raise TypeError(f"platform must be a FloatingPlatform (mbsym.wind.offshore.floating_platform); "
                        f"{type(platform).__name__} lacks {missing}.")
    return platform


def _hss_brake(brake, turbine, dofs):
    """``brake`` (an HssBrake or None), checked: it acts on the generator DOF."""
    if brake is None:
        return None
    from .hss_brake import HssBrake

    if not isinstance(brake, HssBrake):
        raise TypeError(f"hss_brake must be an HssBrake (mbsym.wind.operation.hss_brake) or None; got "
                        f"{type(brake).__name__}.")
    enabled = set(dofs) if dofs is not None else {f for f, on in turbine.dofs.items() if on}
    if "GenDOF" not in enabled:
        raise ParameterError("hss_brake acts on the generator: enable GenDOF (the brake of a turbine at a prescribed "
                             "rotor speed does nothing).")
    return brake


def _brake_inertia(structure, ratio: float) -> float:
    """The inertia [kg m²] the HSS brake turns against, about the high-speed shaft: ``1 / (M⁻¹)_GeAz / N²`` at the
    initial state (the whole drivetrain with a rigid shaft, the generator alone with DrTrDOF)."""
    eom = structure.eom
    mass = eom.functions.mass_matrix
    q0 = np.asarray(structure.initial_state(), dtype=float)[:eom.n_q]
    p = eom.parameter_vector()
    M = np.asarray(mass(q0, p) if mass.n_in() == 2 else mass(q0, np.zeros(len(eom.inputs)), p), dtype=float)
    i = eom.coordinates.index("GeAz")
    return float(1.0 / np.linalg.inv(M)[i, i] / ratio ** 2)


def _tower_aero(tower, blade: bool, averaged: bool = False):
    """``tower`` (a TowerAero or None), checked against the rotor: its inflow disturbance needs blade nodes, or
    rotor-effective surfaces that hold its azimuth average (``averaged``: ``RotorAero.tower_inflow``)."""
    if tower is None:
        return None
    from ..aero.tower import TowerAero

    if not isinstance(tower, TowerAero):
        raise TypeError(f"tower_aero must be a TowerAero (mbsym.wind.aero.tower.TowerAero.from_aerodyn); got "
                        f"{type(tower).__name__}.")
    if tower.disturbs_inflow and not blade and not averaged:
        raise ParameterError("the tower's potential flow and shadow (TwrPotent, TwrShadow) disturb the flow at the "
                             "blade nodes: they need the blade-element rotor (aero='blade') or rotor-effective "
                             "surfaces that hold their azimuth average (RotorAero.from_openfast of a deck with "
                             "them: RotorAero.tower_inflow). Otherwise the rotor-effective model takes the tower's "
                             "drag only (TowerAero(..., potential=0, shadow=0)).")
    return tower


def _check_tower_in_field(tower, wind) -> None:
    """The tower's drag samples the wind at AeroDyn's tower nodes: a full field must reach them (tower points, or
    its grid down to the lowest node), as OpenFAST's InflowWind requires (a fatal error there, at the first step)."""
    field = getattr(wind, "field", None)
    if tower is None or not tower.drag or getattr(field, "grid_bottom", None) is None:
        return
    if getattr(field, "tower", None) is not None or getattr(field, "interpolate_to_ground", False):
        return
    bottom = float(field.grid_bottom)
    if float(tower.elevation[0]) < bottom - 1e-6:
        from ...exceptions import WindInputError

        raise WindInputError(f"AeroDyn's tower drag (TwrAero = True) needs the wind at its tower nodes from "
                             f"TwrElev = {tower.elevation[0]:g} m up, but the full field's grid starts at {bottom:g} m "
                             "and has no tower points (OpenFAST's InflowWind stops on it too). Generate the field with "
                             "tower points (TurbSim WrADTWR = True) or set TwrAero = False in the AeroDyn file.")


def _output_nodes(nodes: Sequence[int], rotor) -> tuple[int, ...]:
    """AeroDyn's ``BlOutNd``: 1-based node numbers of blade 1 with node channels (blade-element rotor only)."""
    nodes = tuple(nodes)
    if not nodes:
        return ()
    if rotor is None:
        raise ParameterError("output_nodes lists AeroDyn node channels of a blade-element rotor (aero='blade'); the "
                             "rotor-effective model has no nodes.")
    bad = [n for n in nodes if not isinstance(n, (int, np.integer)) or not 1 <= n <= rotor.n_nodes]
    if bad or len(nodes) > 9:
        raise ParameterError(f"output_nodes must be at most 9 node numbers in 1..{rotor.n_nodes} (AeroDyn's "
                             f"BlOutNd); got {list(nodes)}.")
    return tuple(int(n) for n in nodes)


def _is_blade_rotor(rotor) -> bool:
    try:
        from ..aero.blade import BladeElementRotor
    except ImportError:            # pragma: no cover - the room ships with the package
        return False
    return isinstance(rotor, BladeElementRotor)


def _rotor_inflow(rotor: RotorAero, dynamic_inflow, inflow_lag: bool) -> "DynamicInflow | None":
    """The rotor-effective model's inflow: DBEMT on the surfaces by default, or a lag, or none."""
    if dynamic_inflow is None:
        dynamic_inflow = not inflow_lag
    if isinstance(dynamic_inflow, bool):
        dynamic_inflow = DynamicInflow(rotor) if dynamic_inflow else None
    if dynamic_inflow is not None and not isinstance(dynamic_inflow, DynamicInflow):
        raise TypeError(f"dynamic_inflow must be True, False or a DynamicInflow; got "
                        f"{type(dynamic_inflow).__name__}.")
    if dynamic_inflow is not None and dynamic_inflow.rotor is not rotor:
        raise ParameterError("dynamic_inflow was built for another rotor; build it from this one.")
    if dynamic_inflow is not None and inflow_lag:
        raise ParameterError("choose one inflow model: dynamic_inflow or inflow_lag, not both.")
    return dynamic_inflow


def _blade_wind(turbine: TurbineParameters, rotor, wind):
    """The wind of a blade-element model: given, or uniform inputs at the hub height (shear reference = diameter)."""
    from .wind_inputs import FieldWindInputs, UniformWindInputs

    if wind is None:
        return UniformWindInputs(float(turbine.hub_height), 2.0 * float(turbine.tip_radius))
    if isinstance(wind, (UniformWindInputs, FieldWindInputs)):
        return wind
    if hasattr(wind, "casadi_function") and hasattr(wind, "velocity"):
        return FieldWindInputs(wind)
    raise TypeError(f"wind must be a UniformWindInputs, a FieldWindInputs or a full field (read_turbsim_bts); got "
                    f"{type(wind).__name__}.")
