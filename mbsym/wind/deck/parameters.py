"""Typed, immutable wind-turbine parameters in SI units.

These frozen dataclasses hold what an OpenFAST/ElastoDyn deck describes, under
descriptive names: lengths in m, masses in kg, inertias in kg m^2, angles in rad,
rotational speeds in rad/s, damping ratios as fractions of critical (ElastoDyn's
percent / 100) and gearbox efficiency as a fraction.  The one documented mapping
from OpenFAST keys to these names lives in :mod:`mbsym.wind.deck.openfast`; the only
ElastoDyn names used here are the degree-of-freedom flags (:data:`DOF_NAMES`),
which the whole package keeps verbatim (see DESIGN.md).

Distributed tower and blade properties are stored **as written in the deck**
(unadjusted), together with ElastoDyn's adjustment factors (AdjTwMa, AdjFASt,
AdjSSSt, AdjBlMs, AdjFlSt, AdjEdSt) kept explicitly; the ``adjusted_*``
properties apply them.  :mod:`mbsym.wind.structure.elastodyn_nodes` always uses the
adjusted values, as ElastoDyn does.

Arrays are read-only float64 copies; change a value with
:func:`dataclasses.replace`.  Equality compares every field exactly (arrays
element-wise) except :attr:`TurbineParameters.source_files`.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np

from ...exceptions import ParameterError
from ._record import _freeze_columns, _Record, _set_array

__all__ = [
    "DOF_NAMES",
    "SimulationSettings",
    "InitialConditions",
    "TowerParameters",
    "BladeParameters",
    "TurbineParameters",
]

#: ElastoDyn's degree-of-freedom flags, in ElastoDyn input-file order.
DOF_NAMES: tuple[str, ...] = (
    "FlapDOF1", "FlapDOF2", "EdgeDOF", "PitchDOF", "TeetDOF", "DrTrDOF", "GenDOF",
    "YawDOF", "TwFADOF1", "TwFADOF2", "TwSSDOF1", "TwSSDOF2", "PtfmSgDOF",
    "PtfmSwDOF", "PtfmHvDOF", "PtfmRDOF", "PtfmPDOF", "PtfmYDOF",
)


@dataclass(frozen=True, eq=False)
class SimulationSettings(_Record):
    """Glue-code settings from the main ``.fst`` file.

    Attributes
    ----------
    total_time : float
        Simulated time TMax [s].
    time_step : float
        Glue-code time step DT [s].
    gravity : float
        Gravitational acceleration [m/s^2] (from the ``.fst``; older decks keep it
        in the ElastoDyn file).
    output_time_step : float
        Output time step DT_Out [s] (``"default"`` resolved to ``time_step``).
    output_start_time : float
        Time at which output starts, TStart [s].
    structural_model, inflow_model, aerodynamics_model, servo_model, sea_state_model,
    hydrodynamics_model, substructure_model, mooring_model, ice_model, soil_model : int
        The module switches CompElast, CompInflow, CompAero, CompServo, CompSeaSt,
        CompHydro, CompSub, CompMooring, CompIce, CompSoil (0 where a layout lacks them).
    air_density, water_density : float or None
        [kg/m^3]; None if the ``.fst`` layout has no environment section.
    water_depth, msl_to_swl : float or None
        Water depth and MSL-to-SWL offset [m]; None if absent.
    linearize : bool
        Whether OpenFAST linearizes.
    linearization_times : tuple of float
        LinTimes [s] (first NLinTimes entries).
    elastodyn_file : str
        EDFile as written in the ``.fst`` (relative to its directory).
    interp_order : int
        InterpOrder (1 linear, 2 quadratic): how the glue code extrapolates module outputs between module
        evaluations; mbsym extrapolates the blade-element aerodynamics between theirs with it
        (:func:`mbsym.wind.operation.simulate_turbine`'s ``aero_order``).
    extra : dict of str to str
        Every other ``.fst`` key with its raw value text (nothing is dropped).
    """

    total_time: float
    time_step: float
    gravity: float
    output_time_step: float
    output_start_time: float
    structural_model: int
    inflow_model: int
    aerodynamics_model: int
    servo_model: int
    sea_state_model: int
    hydrodynamics_model: int
    substructure_model: int
    mooring_model: int
    ice_model: int
    soil_model: int
    air_density: float | None
    water_density: float | None
    water_depth: float | None
    msl_to_swl: float | None
    linearize: bool
    linearization_times: tuple[float, ...]
    elastodyn_file: str
    interp_order: int = 1
    extra: dict[str, str] = field(default_factory=dict)


@dataclass(frozen=True, eq=False)
class InitialConditions(_Record):
    """Initial (or fixed, if the DOF is off) state from ElastoDyn's input file.

    Attributes
    ----------
    blade_oop_tip_deflection, blade_ip_tip_deflection : float
        Out-of-plane and in-plane blade-tip deflection [m] (OoPDefl, IPDefl).
    blade_pitch : tuple of float
        Pitch angle per blade [rad] (BlPitch).
    teeter_angle : float
        [rad] (TeetDefl).
    azimuth : float
        Azimuth of blade 1 [rad].
    rotor_speed : float
        [rad/s] (RotSpeed, read in rpm).
    nacelle_yaw : float
        [rad] (NacYaw).
    tower_top_fa_displacement, tower_top_ss_displacement : float
        [m] (TTDspFA, TTDspSS).
    platform_surge, platform_sway, platform_heave : float
        [m].
    platform_roll, platform_pitch, platform_yaw : float
        [rad].
    """

    blade_oop_tip_deflection: float
    blade_ip_tip_deflection: float
    blade_pitch: tuple[float, ...]
    teeter_angle: float
    azimuth: float
    rotor_speed: float
    nacelle_yaw: float
    tower_top_fa_displacement: float
    tower_top_ss_displacement: float
    platform_surge: float
    platform_sway: float
    platform_heave: float
    platform_roll: float
    platform_pitch: float
    platform_yaw: float


@dataclass(frozen=True, eq=False)
class TowerParameters(_Record):
    """Distributed tower properties and mode shapes (ElastoDyn tower file).

    Attributes
    ----------
    station_fraction : ndarray, shape (n,)
        Height fraction of each input station along the flexible tower, 0 at the
        base (TowerBsHt) to 1 at the top (TowerHt) [-] (HtFract).
    mass_density : ndarray, shape (n,)
        Mass per length as written [kg/m] (TMassDen; not adjusted).
    fa_stiffness, ss_stiffness : ndarray, shape (n,)
        Fore-aft and side-to-side bending stiffness EI as written [N m^2].
    mass_factor, fa_stiffness_factor, ss_stiffness_factor : float
        Adjustment factors AdjTwMa, AdjFASt, AdjSSSt [-] (not applied to the arrays).
    fa_damping_ratio, ss_damping_ratio : ndarray, shape (2,)
        Structural damping of modes 1 and 2 as a fraction of critical [-].
    fa_stiffness_tuner, ss_stiffness_tuner : ndarray, shape (2,)
        Modal stiffness tuners FAStTunr, SSStTunr [-].
    fa_mode_shapes, ss_mode_shapes : ndarray, shape (2, 5)
        Coefficients of x^2 ... x^6 of modes 1 and 2, x = height fraction.
    point_mass_fraction, point_mass : ndarray, shape (m,)
        Optional concentrated masses (NTwCMass table) [-], [kg]; empty if absent.
        Kept, but not used by :mod:`mbsym.wind.structure.elastodyn_nodes`.
    extra_columns : dict of str to ndarray
        Further table columns (e.g. of FAST v7 layouts), by header name.
    extra : dict of str to str
        Unrecognised keys of the tower file with their raw values.
    """

    station_fraction: np.ndarray
    mass_density: np.ndarray
    fa_stiffness: np.ndarray
    ss_stiffness: np.ndarray
    mass_factor: float
    fa_stiffness_factor: float
    ss_stiffness_factor: float
    fa_damping_ratio: np.ndarray
    ss_damping_ratio: np.ndarray
    fa_stiffness_tuner: np.ndarray
    ss_stiffness_tuner: np.ndarray
    fa_mode_shapes: np.ndarray
    ss_mode_shapes: np.ndarray
    point_mass_fraction: np.ndarray = field(default_factory=lambda: np.zeros(0))
    point_mass: np.ndarray = field(default_factory=lambda: np.zeros(0))
    extra_columns: dict[str, np.ndarray] = field(default_factory=dict)
    extra: dict[str, str] = field(default_factory=dict)

    def __post_init__(self) -> None:
        n = len(np.atleast_1d(self.station_fraction))
        for name in ("station_fraction", "mass_density", "fa_stiffness", "ss_stiffness"):
            _set_array(self, name, (), n)
        for name in ("fa_damping_ratio", "ss_damping_ratio", "fa_stiffness_tuner",
                     "ss_stiffness_tuner"):
            _set_array(self, name, (), 2)
        _set_array(self, "fa_mode_shapes", (5,), 2)
        _set_array(self, "ss_mode_shapes", (5,), 2)
        m = len(np.atleast_1d(self.point_mass_fraction))
        _set_array(self, "point_mass_fraction", (), m)
        _set_array(self, "point_mass", (), m)
        _freeze_columns(self)

    @property
    def adjusted_mass_density(self) -> np.ndarray:
        """Mass per length times AdjTwMa [kg/m]."""
        return self.mass_density * self.mass_factor

    @property
    def adjusted_fa_stiffness(self) -> np.ndarray:
        """Fore-aft EI times AdjFASt [N m^2]."""
        return self.fa_stiffness * self.fa_stiffness_factor

    @property
    def adjusted_ss_stiffness(self) -> np.ndarray:
        """Side-to-side EI times AdjSSSt [N m^2]."""
        return self.ss_stiffness * self.ss_stiffness_factor


@dataclass(frozen=True, eq=False)
class BladeParameters(_Record):
    """Distributed blade properties and mode shapes (ElastoDyn blade file).

    Attributes
    ----------
    station_fraction : ndarray, shape (n,)
        Span fraction from the blade root (HubRad) to the tip (TipRad) [-] (BlFract).
    structural_twist : ndarray, shape (n,)
        [rad] (StrcTwst, read in degrees).
    mass_density : ndarray, shape (n,)
        Mass per length as written [kg/m] (BMassDen; not adjusted).
    flap_stiffness, edge_stiffness : ndarray, shape (n,)
        Flapwise and edgewise EI as written [N m^2] (FlpStff, EdgStff).
    pitch_axis : ndarray, shape (n,) or None
        PitchAxis column of older layouts [-]; None if the file has none.
    mass_factor, flap_stiffness_factor, edge_stiffness_factor : float
        Adjustment factors AdjBlMs, AdjFlSt, AdjEdSt [-] (not applied to the arrays).
    flap_damping_ratio : ndarray, shape (2,)
        Flap modes 1 and 2 damping as a fraction of critical [-].
    edge_damping_ratio : ndarray, shape (1,)
        Edge mode 1 damping as a fraction of critical [-].
    flap_stiffness_tuner : ndarray, shape (2,)
        FlStTunr [-].
    flap_mode_shapes : ndarray, shape (2, 5)
        Coefficients of x^2 ... x^6 of flap modes 1 and 2, x = span fraction.
    edge_mode_shapes : ndarray, shape (1, 5)
        Coefficients of x^2 ... x^6 of edge mode 1.
    extra_columns : dict of str to ndarray
        Further table columns (e.g. of FAST v7 layouts), by header name.
    extra : dict of str to str
        Unrecognised keys of the blade file with their raw values.
    """

    station_fraction: np.ndarray
    structural_twist: np.ndarray
    mass_density: np.ndarray
    flap_stiffness: np.ndarray
    edge_stiffness: np.ndarray
    pitch_axis: np.ndarray | None
    mass_factor: float
    flap_stiffness_factor: float
    edge_stiffness_factor: float
    flap_damping_ratio: np.ndarray
    edge_damping_ratio: np.ndarray
    flap_stiffness_tuner: np.ndarray
    flap_mode_shapes: np.ndarray
    edge_mode_shapes: np.ndarray
    extra_columns: dict[str, np.ndarray] = field(default_factory=dict)
    extra: dict[str, str] = field(default_factory=dict)

    def __post_init__(self) -> None:
        n = len(np.atleast_1d(self.station_fraction))
        for name in ("station_fraction", "structural_twist", "mass_density",
                     "flap_stiffness", "edge_stiffness"):
            _set_array(self, name, (), n)
        if self.pitch_axis is not None:
            _set_array(self, "pitch_axis", (), n)
        _set_array(self, "flap_damping_ratio", (), 2)
        _set_array(self, "edge_damping_ratio", (), 1)
        _set_array(self, "flap_stiffness_tuner", (), 2)
        _set_array(self, "flap_mode_shapes", (5,), 2)
        _set_array(self, "edge_mode_shapes", (5,), 1)
        _freeze_columns(self)

    @property
    def adjusted_mass_density(self) -> np.ndarray:
        """Mass per length times AdjBlMs [kg/m]."""
        return self.mass_density * self.mass_factor

    @property
    def adjusted_flap_stiffness(self) -> np.ndarray:
        """Flapwise EI times AdjFlSt [N m^2]."""
        return self.flap_stiffness * self.flap_stiffness_factor

    @property
    def adjusted_edge_stiffness(self) -> np.ndarray:
        """Edgewise EI times AdjEdSt [N m^2]."""
        return self.edge_stiffness * self.edge_stiffness_factor


@dataclass(frozen=True, eq=False)
class TurbineParameters(_Record):
    """Everything an ElastoDyn deck defines about a turbine, in SI units.

    Attributes are named after what they are; :data:`mbsym.wind.deck.openfast.KEY_MAP`
    lists the OpenFAST key behind each.  Per-blade quantities are tuples of length
    ``number_of_blades``; points are (x, y, z) tuples in ElastoDyn's frames.

    Attributes
    ----------
    simulation : SimulationSettings
    dofs : dict of str to bool
        ElastoDyn's DOF flags, keys :data:`DOF_NAMES`.
    initial_conditions : InitialConditions
    integration_method : int
        ElastoDyn Method: 1 RK4, 2 AB4, 3 ABM4.
    structural_time_step : float
        ElastoDyn DT [s] (``"default"`` resolved to the ``.fst`` DT).
    number_of_blades : int
    tip_radius, hub_radius : float
        Rotor apex to blade tip / blade root, along the coned blade axis [m].
    precone : tuple of float
        Cone angle per blade [rad].
    hub_cm, undersling, overhang, twr2shft : float
        Apex to hub mass; teeter pin to apex; yaw axis to apex (negative upwind);
        tower top to shaft, vertical [m].
    delta3, azimuth_blade1_up, shaft_tilt : float
        [rad] (ElastoDyn's sign: negative ShftTilt tilts the rotor up).
    nacelle_cm : tuple of float
        Tower top to nacelle mass centre (downwind, lateral, vertical) [m].
    tower_height, tower_base_height : float
        TowerHt, TowerBsHt above ground / MSL [m].
    platform_cm, platform_reference : tuple of float
        Ground/MSL to platform mass centre and to the platform reference point [m].
    tip_mass : tuple of float
        [kg] per blade.
    pitch_bearing_inertia, blade_pitch_inertia : tuple of float
        [kg m^2] per blade (0 in decks older than OpenFAST v5).
    hub_mass, nacelle_mass, yaw_bearing_mass, platform_mass : float
        [kg].
    hub_inertia, hub_teeter_inertia, generator_inertia, nacelle_yaw_inertia : float
        About the shaft; about the teeter axis; generator about the high-speed
        shaft; nacelle about the yaw (z) axis [kg m^2].
    platform_roll_inertia, platform_pitch_inertia, platform_yaw_inertia,
    platform_xy_inertia, platform_yz_inertia, platform_xz_inertia : float
        About the platform mass centre [kg m^2] (products of inertia = -int(xy dm)).
    n_blade_nodes, n_tower_nodes : int
        ElastoDyn analysis elements per blade (BldNodes) and tower (TwrNodes).
    teeter_model : int
    teeter_damper_position, teeter_soft_stop_position, teeter_hard_stop_position : float
        [rad].
    teeter_damping : float
        [N m s/rad].
    teeter_coulomb_damping : float
        [N m].
    teeter_soft_stop_stiffness, teeter_hard_stop_stiffness : float
        [N m/rad].
    gearbox_efficiency : float
        Fraction [-] (GBoxEff / 100).
    gearbox_ratio : float
        [-].
    drivetrain_stiffness, drivetrain_damping : float
        Low-speed-shaft torsion spring [N m/rad] and damper [N m s/rad].
    furling : bool
        Always False (furling decks are rejected by the reader).
    tower : TowerParameters
    blades : tuple of BladeParameters
        One per blade.
    output_channels, node_output_channels : tuple of str
        ElastoDyn OutList and blade-node OutList entries.
    extra : dict of str to str
        Unrecognised or unmodelled ElastoDyn keys (outputs, yaw friction, ...) with
        raw values.
    source_files : dict of str to str
        Files read, by role ("fst", "elastodyn", "tower", "blade1", ...), plus the
        module files the ``.fst`` switches on and that exist ("inflowwind",
        "aerodyn", "servodyn"; named, not read); not compared by ``==``.
    """

    simulation: SimulationSettings
    dofs: dict[str, bool]
    initial_conditions: InitialConditions
    integration_method: int
    structural_time_step: float
    number_of_blades: int
    tip_radius: float
    hub_radius: float
    precone: tuple[float, ...]
    hub_cm: float
    undersling: float
    delta3: float
    azimuth_blade1_up: float
    overhang: float
    shaft_tilt: float
    nacelle_cm: tuple[float, ...]
    twr2shft: float
    tower_height: float
    tower_base_height: float
    platform_cm: tuple[float, ...]
    platform_reference: tuple[float, ...]
    tip_mass: tuple[float, ...]
    pitch_bearing_inertia: tuple[float, ...]
    blade_pitch_inertia: tuple[float, ...]
    hub_mass: float
    hub_inertia: float
    hub_teeter_inertia: float
    generator_inertia: float
    nacelle_mass: float
    nacelle_yaw_inertia: float
    yaw_bearing_mass: float
    platform_mass: float
    platform_roll_inertia: float
    platform_pitch_inertia: float
    platform_yaw_inertia: float
    platform_xy_inertia: float
    platform_yz_inertia: float
    platform_xz_inertia: float
    n_blade_nodes: int
    n_tower_nodes: int
    teeter_model: int
    teeter_damper_position: float
    teeter_damping: float
    teeter_coulomb_damping: float
    teeter_soft_stop_position: float
    teeter_hard_stop_position: float
    teeter_soft_stop_stiffness: float
    teeter_hard_stop_stiffness: float
    gearbox_efficiency: float
    gearbox_ratio: float
    drivetrain_stiffness: float
    drivetrain_damping: float
    furling: bool
    tower: TowerParameters
    blades: tuple[BladeParameters, ...]
    output_channels: tuple[str, ...] = ()
    node_output_channels: tuple[str, ...] = ()
    extra: dict[str, str] = field(default_factory=dict)
    source_files: dict[str, str] = field(default_factory=dict, compare=False)

    def __post_init__(self) -> None:
        problems = []
        if set(self.dofs) != set(DOF_NAMES) or not all(isinstance(v, bool)
                                                      for v in self.dofs.values()):
            problems.append(f"`dofs` must map exactly {list(DOF_NAMES)} to True/False; "
                            f"got {self.dofs!r}")
        nb = self.number_of_blades
        per_blade = {"precone": self.precone, "tip_mass": self.tip_mass,
                     "pitch_bearing_inertia": self.pitch_bearing_inertia,
                     "blade_pitch_inertia": self.blade_pitch_inertia,
                     "blades": self.blades,
                     "initial_conditions.blade_pitch": self.initial_conditions.blade_pitch}
        for name, value in per_blade.items():
            if len(value) != nb:
                problems.append(f"`{name}` has {len(value)} entries; expected "
                                f"number_of_blades = {nb}")
        for name in ("nacelle_cm", "platform_cm", "platform_reference"):
            if len(getattr(self, name)) != 3:
                problems.append(f"`{name}` must be an (x, y, z) tuple")
        for f in dataclasses.fields(self):
            value = getattr(self, f.name)
            if isinstance(value, float) and not math.isfinite(value):
                problems.append(f"`{f.name}` must be finite; got {value}")
        if problems:
            raise ParameterError("Invalid TurbineParameters:\n  - " + "\n  - ".join(problems))

    @property
    def hub_height(self) -> float:
        """Undeflected rotor-apex height, TowerHt + Twr2Shft + OverHang sin(ShftTilt) [m]."""
        return self.tower_height + self.twr2shft + self.overhang * math.sin(self.shaft_tilt)

    @property
    def tower_flexible_length(self) -> float:
        """ElastoDyn's flexible tower length TowerHt - TowerBsHt [m]."""
        return self.tower_height - self.tower_base_height

    @property
    def blade_flexible_length(self) -> float:
        """ElastoDyn's flexible blade length TipRad - HubRad [m]."""
        return self.tip_radius - self.hub_radius
