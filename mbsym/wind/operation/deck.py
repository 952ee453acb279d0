"""An operating turbine from an OpenFAST deck (ElastoDyn + AeroDyn + InflowWind + ServoDyn), or built in.

:func:`operating_deck` reads what a ``.fst`` switches on:

* ElastoDyn: the structure, its DOFs and initial conditions;
* AeroDyn 15 (``CompAero = 2``): the rotor surfaces by mbsym's BEM
  (:meth:`RotorAero.from_openfast`, a few seconds, on first use) and its dynamic-inflow setting
  (:func:`~.dynamic_inflow.dbemt_settings`); without AeroDyn, the built-in NREL 5 MW rotor
  is *not* substituted: the deck is refused for operation;
* InflowWind (``CompInflow = 1``): the hub-height wind (steady or uniform wind file);
* HydroDyn (``CompHydro = 1``) with SeaState and a mooring (``CompMooring`` 1, MAP++, or 3, MoorDyn):
  the floating platform (:func:`mbsym.wind.offshore.floating_platform`: hydrostatics, radiation
  memory (mbsym's fit of the ``.1`` data, a few seconds, on first use), A∞, quasi-static catenaries);
  SubDyn, ice and soil modules are refused;
* ServoDyn (``CompServo = 1``): generator efficiency, the DISCON library and its input file,
  the controller time step (``DLL_DT``/``DT``/the glue ``DT``); ROSCO's ``DISCON.IN`` gives the
  actuator limits and the baseline controller's settings.

:func:`builtin_deck` is the NREL 5 MW from package data with :data:`~.model.OPERATING_DOFS`
and ROSCO 2.10.6's NREL 5 MW controller settings.
"""

from __future__ import annotations

import dataclasses
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Sequence

from ...exceptions import ControllerError, OpenFASTFormatError, ParameterError
from ..aero.rotor import RotorAero
from ..deck.parameters import TurbineParameters
from .actuators import ActuatorSettings
from .model import OPERATING_DOFS, OperatingTurbine

__all__ = ["OperatingDeck", "operating_deck", "builtin_deck", "ROSCO_HINT", "BUILTIN_DISCON_HINT", "AERO_MODELS"]

#: Aerodynamic models of an operating turbine: blade-element on every blade, or rotor-effective surfaces.
AERO_MODELS = ("blade", "rotor")
#: ElastoDyn OutList channels that only the load cuts give (OperatingTurbine(load_channels=True)).
_LOAD_CUT = re.compile(r"^(LSShftF[xyz][as]|YawBr[FM][xyz]p)$", re.IGNORECASE)
_LOAD_CUT_BLADE = re.compile(r"^(LSShftF[xyz][as]|YawBr[FM][xyz]p|RootF[xyz]c[1-3]|RootF[xy]b[1-3])$", re.IGNORECASE)

#: How to get ROSCO's library, for messages.
ROSCO_HINT = ("'pip download --no-deps rosco==2.10.6' gives a wheel (a zip) holding rosco/lib/libdiscon.so and its "
              "runtime rosco.libs/; unzip both side by side, or pass the library with --discon LIB.so")

#: Where a DISCON.IN for the built-in NREL 5 MW comes from, for messages.
BUILTIN_DISCON_HINT = ("mbsym.wind.operation.nrel5mw.write_nrel5mw_discon(folder) writes the package's ROSCO 2.10.6 "
                       "NREL 5 MW one; the rosco wheel holds the original as Examples/Test_Cases/NREL-5MW/DISCON.IN "
                       "with Cp_Ct_Cq.NREL5MW.txt beside it")


@dataclass(frozen=True)
class OperatingDeck:
    """Everything an operating simulation takes from a deck (see the module docstring).

    Attributes
    ----------
    turbine : TurbineParameters
    rotor_source : RotorAero or Path
        The rotor, or the ``.fst`` whose AeroDyn gives it (computed on first use of :attr:`rotor`).
    dofs : tuple of str or None
        The DOFs to model (None: the deck's own).
    dynamic_inflow : bool
        Whether AeroDyn runs dynamic BEMT (the model then adds :class:`~.dynamic_inflow.DynamicInflow`).
    dbemt : tuple (mode, tau1_const) or None
    actuators : ActuatorSettings
    controller_dt : float
        Controller sample time [s].
    servodyn : ServoDynSettings or None
    inflow : InflowWindSettings or None
    discon_in : Path or None
        ROSCO's input file (ServoDyn's DLL_InFile, or None).
    library : Path or None
        The DISCON library ServoDyn names (it may not exist).
    uses_library : bool
        Whether ServoDyn runs the DISCON library (PCMode or VSContrl 5).
    label : str
    path : Path or None
        The ``.fst`` (None for the built-in turbine).
    aerodyn : AeroDynInput or None
        The deck's AeroDyn input (None for the built-in turbine), audited by :meth:`model`.
    radiation : {"fit", "ss", "none"} or None
        The radiation memory of a floating deck (:func:`mbsym.wind.offshore.floating_platform`); None: what
        its HydroDyn ``RdtnMod`` asks for (0 none, 1 mbsym's fit of the convolution's data, 2 the ``.ss``).
    mooring_statics : {"lumped", "continuous"} or None
        The fairlead forces of a MoorDyn deck's lines (:func:`mbsym.wind.offshore.floating_platform`): its
        ``NumSegs`` lumped masses at rest or the continuous catenaries; None: the default there.
    mooring_lines : {"quasi-static", "dynamic"}
        A MoorDyn deck's lines quasi-static (default) or in motion beside the model in a simulation
        (:func:`mbsym.wind.offshore.floating_platform`, :mod:`mbsym.wind.offshore.lines_in_loop`).
    cut_out_wind_speed : float or None
        The turbine's cut-out wind speed [m/s] (:mod:`.cut_out`); None when unknown (an OpenFAST deck states none).
    cut_out_source : str
        Where :attr:`cut_out_wind_speed` comes from, for messages.
    exported_input : bool
        Whether :attr:`discon_in` was written by ``mbsym export-discon`` (it pairs with an exported library
        and holds no settings).
    settings_in : Path or None
        With :attr:`exported_input`: the ROSCO input file the exported law was built from (its comment),
        the source of :meth:`baseline_settings`.
    """

    turbine: TurbineParameters
    rotor_source: "RotorAero | Path"
    dofs: tuple[str, ...] | None
    dynamic_inflow: bool
    dbemt: tuple[int, float] | None
    actuators: ActuatorSettings
    controller_dt: float
    servodyn: object | None
    inflow: object | None
    discon_in: Path | None
    library: Path | None
    uses_library: bool
    label: str
    path: Path | None = None
    aerodyn: object | None = None
    radiation: str | None = None
    mooring_statics: str | None = None
    mooring_lines: str = "quasi-static"
    cut_out_wind_speed: float | None = None
    cut_out_source: str = ""
    exported_input: bool = False
    settings_in: Path | None = None

    @property
    def floating(self) -> bool:
        """Whether the deck has HydroDyn or a mooring (a floating platform)."""
        sim = self.turbine.simulation
        return bool(getattr(sim, "hydrodynamics_model", 0) or getattr(sim, "mooring_model", 0))

    def _check_mooring_lines(self) -> None:
        """Refuse :attr:`mooring_lines` other than quasi-static where there are no MoorDyn lines to move."""
        if self.mooring_lines == "quasi-static":
            return
        from ...exceptions import OptionError

        sim = self.turbine.simulation
        if int(getattr(sim, "substructure_model", 0) or 0) or int(getattr(sim, "mooring_model", 0) or 0) != 3:
            raise OptionError(f"mooring_lines={self.mooring_lines!r} moves a floating deck's MoorDyn lines; "
                              f"{self.label} has none (CompMooring = 3 with HydroDyn). Leave it 'quasi-static'.")

    @property
    def platform(self):
        """The platform's loads, built once: a floating platform (:class:`~mbsym.wind.offshore.FloatingPlatform`),
        a bottom-fixed SubDyn substructure (:class:`~mbsym.wind.offshore.bottom_fixed.BottomFixedPlatform`), or
        None."""
        if "_platform" not in self.__dict__:
            platform = None
            self._check_mooring_lines()
            if int(getattr(self.turbine.simulation, "substructure_model", 0) or 0):
                from ..offshore.bottom_fixed import bottom_fixed_platform

                platform = bottom_fixed_platform(self.turbine)
            elif self.floating:
                from ..offshore.operating import floating_platform

                platform = floating_platform(self.turbine, radiation=self.radiation,
                                             mooring_statics=self.mooring_statics, mooring_lines=self.mooring_lines)
            object.__setattr__(self, "_platform", platform)
        return self.__dict__["_platform"]

    @property
    def rotor(self) -> RotorAero:
        """The rotor aerodynamics (mbsym's BEM surfaces of the deck's AeroDyn: a few seconds, once)."""
        if not isinstance(self.rotor_source, RotorAero):
            object.__setattr__(self, "rotor_source", RotorAero.from_openfast(self.rotor_source))
        return self.rotor_source

    def model(self, *, dofs: Sequence[str] | None = None, aero: str | None = None, t_end: float | None = None,
              wind_given: bool = False, **options) -> OperatingTurbine:
        """The :class:`OperatingTurbine` (DOFs: ``dofs``, else the deck's; ``aero``: ``"blade"`` or
        ``"rotor"``, else :meth:`default_aero`), with ServoDyn's yaw spring and damper.

        ``wind_given``: the caller gives the wind (a trim at a hub-height speed), so a rotor-effective model is
        built whatever the deck's InflowWind holds (a full field is refused otherwise).

        ServoDyn's settings that act on the modelled DOFs before ``t_end`` [s] (default the deck's
        TMax) are modelled or refused (:func:`~mbsym.wind.deck.servo_audit.servo_audit`), and so are
        AeroDyn's (:func:`~mbsym.wind.deck.aero_audit.check_aerodyn`).

        Raises
        ------
        OpenFASTFormatError
            A ServoDyn or AeroDyn setting that would act and is not modelled (file, line, key).
        """
        from ..aero.nacelle import NacelleDrag
        from ..aero.sector_average import SectorAverage
        from ..aero.tower import TowerAero
        from ..deck.aero_audit import check_aerodyn

        dofs = self.dofs if dofs is None else dofs
        aero = self.default_aero(dofs) if aero is None else aero
        if aero not in AERO_MODELS:
            raise ParameterError(f"aero must be one of {list(AERO_MODELS)}; got {aero!r}.")
        if self.aerodyn is not None:
            check_aerodyn(self.aerodyn, rotor_effective=aero == "rotor")
            options.setdefault("tower_aero", TowerAero.from_aerodyn(self.aerodyn))
            options.setdefault("nacelle_drag", NacelleDrag.from_aerodyn(self.aerodyn))
            if aero == "blade":
                options.setdefault("sector_average", SectorAverage.from_aerodyn(self.aerodyn))
        self._yaw_drive(dofs, t_end, options)
        options.setdefault("load_channels", self.outlist_needs_load_channels(aero))
        options.setdefault("platform", self.platform)
        if aero == "blade":
            return self._blade_model(dofs, **options)
        if self.inflow is not None and self.inflow.wind_type not in (1, 2) and not wind_given:
            from ...exceptions import WindInputError

            raise WindInputError(f"{self.label}: the rotor-effective model (aero='rotor') takes a hub-height wind; the "
                                 f"deck's InflowWind has WindType {self.inflow.wind_type}. Drive it with the field's "
                                 "rotor-effective wind (mbsym.wind.rotor_effective_wind) or use aero='blade'.")
        from .dynamic_inflow import DynamicInflow

        inflow = False
        if self.dynamic_inflow:
            mode, tau1 = self.dbemt if self.dbemt is not None else (2, 0.0)
            inflow = DynamicInflow(self.rotor, mode=mode, tau1_const=tau1)
        options.setdefault("dynamic_inflow", inflow)
        options.setdefault("actuators", self.actuators)
        return OperatingTurbine(self.turbine, self.rotor, dofs=dofs, **options)

    def _yaw_drive(self, dofs, t_end: float | None, options: dict) -> None:
        """Audit ServoDyn for these DOFs and put its yaw spring and damper, its shaft brake when deployed before
        ``t_end`` and its nacelle and platform structural controllers (StCs) into ``options``."""
        from ..deck.servo_audit import servo_audit

        flags = dict(self.turbine.dofs)
        if dofs is not None:
            flags = {f: f in set(dofs) for f in flags} | {f: True for f in dofs}
        end = float(self.turbine.simulation.total_time if t_end is None else t_end)
        speed = abs(self.turbine.gearbox_ratio) * self.turbine.initial_conditions.rotor_speed     # HSS [rad/s]
        drive = servo_audit(self.servodyn, flags, end, generator_speed=speed)
        if drive is not None:
            options.setdefault("yaw_spring", drive.spring)
            options.setdefault("yaw_damping", drive.damping)
            options.setdefault("yaw_neutral", drive.neutral)
            if drive.control is not None:                 # ServoDyn's maneuver or library yaw (.yaw_control)
                options.setdefault("yaw_control", drive.control)
        s = self.servodyn
        if s is not None and flags.get("GenDOF") and s.hss_brake_mode == 1 and s.hss_brake_start_time < end:
            from .hss_brake import HssBrake                   # ServoDyn's brake ramp (HSSBrMode 1) within the run

            options.setdefault("hss_brake", HssBrake.from_servodyn(s))
        from ..structure.structural_control import structural_controls    # ServoDyn's StCs (or refused)

        stc = structural_controls(s, self.turbine)
        if stc is not None:
            options.setdefault("structural_controls", stc)

    def _blade_model(self, dofs, **options) -> OperatingTurbine:
        from ..aero.blade import BladeElementRotor
        from .wind_inputs import UniformWindInputs

        if self.path is None:
            raise ParameterError("aero='blade' needs an OpenFAST deck (AeroDyn blade files); the built-in turbine "
                                 "has only the rotor-effective model.")
        rotor = BladeElementRotor.from_openfast(self.path)
        wind = options.pop("wind", None)
        if wind is None and self.inflow is not None:
            field = self.inflow.field()
            wind = UniformWindInputs.from_field(field) if hasattr(field, "columns_at") else field
        options.setdefault("actuators", self.actuators)
        options.setdefault("output_nodes", self.output_nodes)
        options.setdefault("pitch", "individual" if self.individual_pitch_control else "collective")
        return OperatingTurbine(self.turbine, rotor, dofs=dofs, wind=wind, **options)

    def outlist_needs_load_channels(self, aero: str) -> bool:
        """Whether the deck's ElastoDyn OutList asks for a channel only the load cuts give (``LSShftF*``,
        ``YawBrF*p``/``YawBrM*p``, with blade-element aerodynamics ``RootF*``): the deck then runs with
        ``load_channels=True``, as written."""
        names = getattr(self.turbine, "output_channels", ()) if self.path is not None else ()
        pattern = _LOAD_CUT_BLADE if aero == "blade" else _LOAD_CUT
        return any(pattern.match(n) for n in names)

    @property
    def individual_pitch_control(self) -> bool:
        """Whether the deck's controller pitches the blades individually: ServoDyn ``Ptch_Cntrl = 1`` and ROSCO's
        ``IPC_ControlMode > 0`` in its DISCON.IN (with IPC off ROSCO commands every blade alike)."""
        source = self.settings_in if self.exported_input else self.discon_in
        if self.servodyn is None or source is None or not Path(source).is_file():
            return False
        if int(getattr(self.servodyn, "individual_pitch", 0) or 0) != 1:
            return False
        from ..deck.discon_in import read_discon_in

        value = read_discon_in(source).values.get("IPC_ControlMode", 0)
        try:
            return int(value) > 0
        except (TypeError, ValueError):
            return False

    @property
    def output_nodes(self) -> tuple[int, ...]:
        """AeroDyn's ``BlOutNd`` (the first ``NBlOuts``): blade-1 nodes with node channels ``B1N<j>*``."""
        if self.path is None:
            return ()
        from ..deck.aerodyn import read_aerodyn

        extra = read_aerodyn(self.turbine.source_files["aerodyn"], n_blades=self.turbine.number_of_blades).extra
        try:
            count = int(str(extra.get("NBlOuts", "0")).split()[0])
            nodes = [int(v) for v in str(extra.get("BlOutNd", "")).replace(",", " ").split()[:count]]
        except ValueError:
            return ()
        return tuple(nodes)

    def default_aero(self, dofs: Sequence[str] | None = None) -> str:
        """``"blade"`` when a rotor-effective model cannot represent the deck: a full-field wind, a wind with
        shear, direction, vertical speed or upflow, blade or yaw DOFs that the aerodynamics must load, or
        AeroDyn's tower disturbing the blade inflow (``TwrPotent``, ``TwrShadow``), sector-averaged inflow
        (``SectAvg``), or unsteady airfoil aerodynamics (``UA_Mod`` ≠ 0); ``"rotor"`` otherwise (uniform
        hub-height wind on a rigid rotor: the cheap rung is exact enough)."""
        if self.path is None:
            return "rotor"
        if self.wind_varies_over_rotor():
            return "blade"
        if self.aerodyn is not None:
            from ..aero.tower import TowerAero

            tower = TowerAero.from_aerodyn(self.aerodyn)
            if tower is not None and tower.disturbs_inflow or self.aerodyn.unsteady_model != 0:
                return "blade"
            if str(self.aerodyn.extra.get("SectAvg", "False")).strip().lower() in ("true", "t", ".true."):
                return "blade"
        flags = {f for f, on in self.turbine.dofs.items() if on} if dofs is None else set(dofs)
        return "blade" if flags & {"FlapDOF1", "FlapDOF2", "EdgeDOF", "YawDOF"} else "rotor"

    def wind_varies_over_rotor(self) -> bool:
        """Whether the deck's wind differs over the rotor (a full field, shear, direction, vertical flow or upflow),
        which only the blade-element rotor sees."""
        return self.inflow is not None and _varies_over_rotor(self.inflow)

    def wind(self):
        """The deck's hub-height wind (InflowWind), or None without InflowWind."""
        return None if self.inflow is None else self.inflow.wind()

    def lidar_measurement(self):
        """The InflowWind single-point lidar as ``t -> (speeds, positions)``
        (:func:`~mbsym.wind.inflow.lidar_measurements`), or None without one.

        The lidar sits at the hub's initial position (ElastoDyn: ``OverHang`` along the tilted shaft
        from the yaw axis, at the hub height, turned by the initial nacelle yaw); with
        ``ConsiderHubMotion = 1`` a :class:`~mbsym.exceptions.ModelWarning` says that the hub's
        displacement is not added.
        """
        import math
        import warnings

        from ...exceptions import ModelWarning
        from ..inflow.lidar import lidar_measurements

        lidar = getattr(self.inflow, "lidar", None) if self.inflow is not None else None
        if lidar is None:
            return None
        t = self.turbine
        x, yaw = t.overhang * math.cos(t.shaft_tilt), t.initial_conditions.nacelle_yaw
        hub = (x * math.cos(yaw), x * math.sin(yaw), t.hub_height)
        if lidar.hub_motion:
            warnings.warn(f"{self.inflow.path}: ConsiderHubMotion = 1: mbsym measures the lidar from the hub's "
                          "initial position (the hub's displacement, well under a metre, against focal distances "
                          f"of {lidar.upstream_distance:g} m, is not added).", ModelWarning, stacklevel=2)
        return lidar_measurements(lidar, self.inflow.field(), hub)

    def baseline_settings(self, *, discon_in: str | Path | None = None, dt: float | None = None):
        """Baseline controller settings: ``discon_in``, else the deck's DISCON.IN (for an exported library's input
        file, the DISCON.IN recorded in it), else the built-in NREL 5 MW."""
        from ..control.settings import BaselineSettings
        from .nrel5mw import nrel5mw_baseline_settings

        dt = self.controller_dt if dt is None else dt
        source = discon_in if discon_in is not None else self.discon_in
        if discon_in is None and self.exported_input:
            if self.settings_in is None or not self.settings_in.is_file():
                raise ControllerError(f"ServoDyn's DLL_InFile {self.discon_in} is the input file of a library exported "
                                      "by mbsym; the ROSCO DISCON.IN it was built from "
                                      + (f"({self.settings_in}) is missing" if self.settings_in is not None else
                                         "is not recorded in it") + ". Pass --discon-input DISCON.IN (the turbine's "
                                      "controller settings).")
            source = self.settings_in
        if source is None:
            return nrel5mw_baseline_settings(dt)
        if not Path(source).is_file():
            raise ControllerError(f"DISCON.IN not found: tried '{Path(source).absolute()}'"
                                  + (f" (ServoDyn DLL_InFile of {self.servodyn.path})" if discon_in is None and
                                     self.servodyn is not None else "") + ". Fix the path or pass --discon-input.")
        return BaselineSettings.from_discon(source, dt=dt)

    def discon_paths(self, library: str | Path | None = None, input_file: str | Path | None = None, *,
                     folder: str | Path | None = None) -> tuple[Path, Path]:
        """``(library, DISCON.IN)`` for the DISCON controller: the given ones, else the deck's.

        The built-in turbine names no input file: with ``folder`` (the run's output folder) the package's
        ROSCO 2.10.6 NREL 5 MW ``DISCON.IN`` and its performance file are written into
        ``folder/nrel5mw_rosco/`` (:func:`~.nrel5mw.write_nrel5mw_discon`) and that file is returned.

        Raises
        ------
        ControllerError
            No library or input file, or a file that does not exist (names the path and how to get it).
        """
        lib = Path(library) if library is not None else self.library
        infile = Path(input_file) if input_file is not None else self.discon_in
        where = f" (ServoDyn DLL_FileName of {self.servodyn.path})" if library is None and self.servodyn else ""
        if lib is None:
            raise ControllerError(f"no DISCON library: {self.label} names none; pass --discon LIB.so ({ROSCO_HINT}).")
        if not lib.is_file():
            raise ControllerError(f"DISCON library not found: tried '{lib.absolute()}'{where}. {ROSCO_HINT}.")
        if infile is None and self.path is None and folder is not None:
            from .nrel5mw import NREL5MW_DISCON_FOLDER, write_nrel5mw_discon

            infile = write_nrel5mw_discon(Path(folder) / NREL5MW_DISCON_FOLDER, dt=self.controller_dt)
        if infile is None:
            raise ControllerError(f"no controller input file: {self.label} names none; pass --discon-input "
                                  "DISCON.IN" + (f" ({BUILTIN_DISCON_HINT})" if self.path is None else "") + ".")
        if not infile.is_file():
            raise ControllerError(f"controller input file not found: tried '{infile.absolute()}'. Fix ServoDyn's "
                                  "DLL_InFile or pass --discon-input DISCON.IN.")
        return lib, infile


def _varies_over_rotor(inflow) -> bool:
    """Whether an InflowWind wind differs over the rotor (full field, shears, direction, vertical flow)."""
    from ..inflow import read_uniform_wind

    if inflow.wind_type not in (1, 2) or inflow.propagation_direction != 0.0 or inflow.upflow_angle != 0.0:
        return True
    if inflow.wind_type == 1:
        return inflow.steady_power_law_exponent != 0.0
    if inflow.uniform_file is None:
        return False                    # reported when the wind is read
    return bool(read_uniform_wind(inflow.uniform_file).unmodelled())


def operating_deck(fst: str | Path) -> OperatingDeck:
    """Read an OpenFAST deck for an operating simulation (see the module docstring).

    Raises
    ------
    OpenFASTFormatError
        A malformed file (file, line, key); a deck without AeroDyn 15 (``CompAero = 2``).
    """
    from ..deck.aerodyn import read_aerodyn
    from ..deck.discon_in import read_discon_in
    from ..control.discon_export import exported_settings
    from ..deck.inflowwind import deck_inflowwind
    from ..deck.openfast import read_openfast
    from ..deck.servodyn import deck_servodyn
    from .dynamic_inflow import dbemt_settings

    path = Path(fst)
    turbine = read_openfast(path)
    _refuse_modules(turbine, path)
    aerodyn_file = turbine.source_files.get("aerodyn")
    if aerodyn_file is None:
        raise OpenFASTFormatError(f"{path}: the deck has no AeroDyn 15 (CompAero must be 2 with an existing "
                                  "AeroFile); an operating simulation needs the rotor's aerodynamics. Add AeroDyn "
                                  "or run without a deck (built-in NREL 5 MW).")
    aerodyn = read_aerodyn(aerodyn_file, n_blades=turbine.number_of_blades)
    dbemt = dbemt_settings(aerodyn)
    servodyn, glue_dt = deck_servodyn(path)
    inflow = deck_inflowwind(path)
    discon_in = library = settings_in = None
    uses_library = exported = False
    dt = glue_dt
    discon = None
    if servodyn is not None:
        dt = servodyn.controller_time_step(glue_dt)
        uses_library = bool(servodyn.uses_library)
        if servodyn.library_name not in ("", "unused"):
            library = servodyn.library
        if servodyn.library_input_name not in ("", "unused"):
            discon_in = servodyn.library_input
            exported, settings_in = exported_settings(discon_in)
            if exported:                      # an exported library's input: the settings are in its source
                discon = read_discon_in(settings_in) if settings_in is not None and settings_in.is_file() else None
            elif discon_in.is_file():
                discon = read_discon_in(discon_in)
    actuators = ActuatorSettings.from_deck(servodyn, discon)
    return OperatingDeck(turbine=turbine, rotor_source=path, dofs=None, dynamic_inflow=dbemt is not None, dbemt=dbemt,
                         actuators=actuators, controller_dt=float(dt), servodyn=servodyn, inflow=inflow,
                         discon_in=discon_in, library=library, uses_library=uses_library, label=str(path),
                         path=path, aerodyn=aerodyn, exported_input=exported, settings_in=settings_in)


def _refuse_modules(turbine, path: Path) -> None:
    """Refuse modules an operating turbine does not model (a substructure other than SubDyn's, ice, soil); HydroDyn
    and the mooring are the floating platform's (:func:`mbsym.wind.offshore.floating_platform` checks them), SubDyn
    the bottom-fixed one's (:func:`mbsym.wind.offshore.bottom_fixed.bottom_fixed_platform`)."""
    from ..deck.checks import MODELLED, unmodelled_modules

    modelled = {**MODELLED, "CompSub": {0, 1}}             # SubDyn: mbsym.wind.offshore.bottom_fixed
    found = [m for m in unmodelled_modules(turbine.simulation, modelled)
             if m.startswith(("CompSub", "CompIce", "CompSoil"))]
    if found:
        from ...exceptions import UnsupportedFeatureError

        raise UnsupportedFeatureError(f"{path}: the deck switches on modules an operating turbine does not model: "
                                      f"{', '.join(found)}; set them to 0 in the .fst.")


def builtin_deck(*, dofs: Sequence[str] = OPERATING_DOFS) -> OperatingDeck:
    """The built-in NREL 5 MW: package data for the structure, the rotor (BEM surfaces, DBEMT as its
    AeroDyn deck) and ROSCO 2.10.6's controller settings; controller sample time
    :data:`~.nrel5mw.NREL5MW_CONTROLLER_DT`."""
    from ..aero.nrel5mw import nrel5mw_rotor
    from ..deck.nrel5mw import nrel5mw
    from ..deck.nrel5mw_aero import nrel5mw_aerodyn
    from .cut_out import NREL5MW_CUT_OUT
    from .dynamic_inflow import dbemt_settings
    from .nrel5mw import NREL5MW_CONTROLLER_DT

    dbemt = dbemt_settings(nrel5mw_aerodyn())
    return OperatingDeck(turbine=nrel5mw(), rotor_source=nrel5mw_rotor(), dofs=tuple(dofs),
                         dynamic_inflow=dbemt is not None,
                         dbemt=dbemt, actuators=ActuatorSettings.nrel5mw(), controller_dt=NREL5MW_CONTROLLER_DT,
                         servodyn=None, inflow=None, discon_in=None, library=None, uses_library=False,
                         label="NREL 5 MW onshore (built-in)", cut_out_wind_speed=NREL5MW_CUT_OUT[0],
                         cut_out_source=NREL5MW_CUT_OUT[1])


def replace(deck: OperatingDeck, **changes) -> OperatingDeck:
    """A copy of ``deck`` with some fields changed."""
    return dataclasses.replace(deck, **changes)
