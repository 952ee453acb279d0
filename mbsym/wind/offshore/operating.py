"""The water and the mooring of a floating *operating* turbine: a platform-loads object for the operation layer.

:class:`FloatingPlatform` gathers what acts on the platform of an operating turbine besides its
structure and the rotor:

* hydrostatics, buoyancy, HydroDyn's additional loads and its members' viscous drag
  (:class:`~.platform.PlatformHydrodynamics`, :mod:`.morison`);
* the radiation memory as linear states (:class:`~.radiation.RadiationStateSpace`, states
  ``Rdtn1 … RdtnN``), driven by the platform velocities;
* the quasi-static catenary mooring (:class:`~.mooring.MooringSystem`, fixed Newton steps in SX), with
  its lines' drag and inertia on their quasi-static shape for a MoorDyn deck (:mod:`.line_dynamics`);
* the infinite-frequency added mass A∞, which the operating turbine adds to the platform block of
  its symbolic mass matrix (so trims and linear models see it);
* the sea: the first-order wave excitation ``B1WvsFxi … B1WvsMzi`` and the elevation ``Wave1Elev`` are
  **inputs** of the model (:data:`SEA_INPUTS`; linear models get them as disturbance inputs), fed by a
  simulation from the deck's waves (:meth:`FloatingPlatform.sea_tables`, HydroDyn's own time series:
  :mod:`.excitation`); zero in still water.

The operation layer (:mod:`mbsym.wind.operation.compose`) takes such an object as
``OperatingTurbine(..., platform=...)``: the loads go on the structure's platform inputs
``PtfmFx … PtfmMz`` (at the platform reference point, inertial axes), the radiation states join the
state vector and the channels of :meth:`FloatingPlatform.channel_rows` (``HydroFxi … HydroMzi``,
``FAIRTEN1..n``, ``B1WvsFxi … B1WvsMzi``, ``Wave1Elev``) join the outputs. This module imports only :mod:`mbsym.wind.deck`
and the offshore room; :func:`floating_platform` builds the object from a deck's HydroDyn, SeaState
and MoorDyn/MAP++ files.

Approximations (stated in docs/offshore.md): the lines are quasi-static, with MoorDyn's drag and
inertia on that shape when the mooring has ``dynamics`` (:mod:`.line_dynamics`); the wave excitation at the
undisplaced platform (HydroDyn's ``ExctnDisp = 0``). The water's loads see the platform's exact velocity and
acceleration, as HydroDyn gets them from ElastoDyn: the Euler rates' angular velocity ``T(θ) θ̇`` and its
derivative (:func:`~._casadi.body_motion`), so A∞ enters the DOFs as ``Jᵀ A∞ J`` with ``J = diag(I, T)``.
"""

from __future__ import annotations

import re
import warnings
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path
from typing import Any

import casadi as ca
import numpy as np

from ...exceptions import ModelWarning, UnsupportedFeatureError
from ._casadi import body_motion
from .excitation import EXCITATION_CHANNELS
from .strip_theory import WAVE_INERTIA_INPUTS, WAVE_INERTIA_UNITS
from .wave_kinematics import flow_input_names
from .lumped_dynamics import DynamicMooring, dynamic_mooring_from_moordyn, fairlead_node_mass
from .mooring import MooringSystem, mooring_from_map, mooring_from_moordyn
from .platform import PlatformHydrodynamics, platform_hydrodynamics
from .radiation import RadiationStateSpace

__all__ = ["FloatingPlatform", "floating_platform", "PLATFORM_COORDINATES", "PLATFORM_INPUTS",
           "HYDRO_CHANNELS", "RADIATION_MODELS", "MOORING_STATICS", "DEFAULT_MOORING_STATICS", "SEA_INPUTS",
           "SEA_INPUT_UNITS", "sea_input_unit", "ELEVATION_AHEAD", "platform_dofs", "deck_radiation",
           "MOORING_LINES", "MOVING_LINE_INPUTS"]

#: The structure's platform coordinates, in the order of the loads (surge, sway, heave, roll, pitch, yaw).
PLATFORM_COORDINATES = ("Sg", "Sw", "Hv", "R", "P", "Y")
#: The structure's platform load inputs the platform drives [N, N m] (reference point, inertial axes).
PLATFORM_INPUTS = ("PtfmFx", "PtfmFy", "PtfmFz", "PtfmMx", "PtfmMy", "PtfmMz")
#: HydroDyn's total-load channels (with their OpenFAST units).
HYDRO_CHANNELS = {"HydroFxi": "N", "HydroFyi": "N", "HydroFzi": "N", "HydroMxi": "N-m", "HydroMyi": "N-m",
                  "HydroMzi": "N-m"}
#: The sea's inputs of a floating model: HydroDyn's first-order excitation [N, N m] and SeaState's elevation [m].
SEA_INPUTS = (*EXCITATION_CHANNELS, "Wave1Elev")
#: Their units as inputs (mbsym's input convention: "N m" for moments).
SEA_INPUT_UNITS = {"B1WvsFxi": "N", "B1WvsFyi": "N", "B1WvsFzi": "N", "B1WvsMxi": "N m", "B1WvsMyi": "N m",
                   "B1WvsMzi": "N m", "Wave1Elev": "m", "WaveElevAhead": "m"}
def sea_input_unit(name: str) -> str:
    """The unit of a sea input (:data:`SEA_INPUT_UNITS`; ``m/s`` for the waves' velocity at a Morison point), or ""."""
    if name in SEA_INPUT_UNITS:
        return SEA_INPUT_UNITS[name]
    if name in MOVING_LINE_INPUTS or name.startswith("MoorDTen"):
        return "N m" if name[5] == "M" else "N"
    if name in WAVE_INERTIA_UNITS:
        return WAVE_INERTIA_UNITS[name]
    return "m/s" if re.fullmatch(r"MorisonU\d+[xyz]i", name) else ""


#: The input of HydroDyn's state-space excitation (``ExctnMod = 2``): the elevation at the platform ``Tc`` ahead [m].
ELEVATION_AHEAD = "WaveElevAhead"
#: How :func:`floating_platform` models the radiation memory.
RADIATION_MODELS = ("fit", "ss", "none")
#: How the fairlead forces of MoorDyn's lines are found (:func:`floating_platform`).
MOORING_STATICS = ("lumped", "continuous")
#: The default for MoorDyn decks: the deck's ``NumSegs`` lumped masses at rest, as OpenFAST runs them.
DEFAULT_MOORING_STATICS = "lumped"
#: How MoorDyn's lines move (:func:`floating_platform`): quasi-static shapes, or their nodes in motion.
MOORING_LINES = ("quasi-static", "dynamic")
#: The inputs that carry the moving lines' dynamic load (less the quasi-static one) [N, N m].
MOVING_LINE_INPUTS = ("MoorDFxi", "MoorDFyi", "MoorDFzi", "MoorDMxi", "MoorDMyi", "MoorDMzi")


def platform_dofs(coordinates, turbine) -> tuple[list[int | None], list[float], np.ndarray]:
    """Where the platform's six DOFs are among a structure's ``coordinates``, and what the disabled ones hold.

    ElastoDyn holds a disabled platform DOF at its initial value (``PtfmSurge`` … ``PtfmYaw``); the water and
    the mooring see the platform there, and their loads act on the enabled DOFs only.

    Returns
    -------
    index : list
        Per DOF (surge … yaw) its position in ``coordinates``, or None when disabled.
    fixed : list of float
        Per DOF the value a disabled one keeps [m, rad] (the deck's initial condition).
    select : (6, len(coordinates)) ndarray
        ``select[k, index[k]] = 1`` for the enabled DOFs: ``selectᵀ A select`` puts a 6×6 platform matrix on them.

    Raises
    ------
    ModelDefinitionError
        No platform DOF enabled.
    """
    from ...exceptions import ModelDefinitionError

    index = [coordinates.index(c) if c in coordinates else None for c in PLATFORM_COORDINATES]
    if all(i is None for i in index):
        raise ModelDefinitionError("a floating platform needs at least one platform DOF (PtfmSgDOF … PtfmYDOF) "
                                   "enabled; enable them in the deck or in dofs=…, or leave platform=None.")
    ic = turbine.initial_conditions
    fixed = [float(v) for v in (ic.platform_surge, ic.platform_sway, ic.platform_heave, ic.platform_roll,
                                ic.platform_pitch, ic.platform_yaw)]
    select = np.zeros((6, len(coordinates)))
    for k, i in enumerate(index):
        if i is not None:
            select[k, i] = 1.0
    return index, fixed, select


@dataclass(frozen=True, eq=False)
class FloatingPlatform:
    """The water's and the mooring's loads on the platform of an operating turbine (module docstring).

    Parameters
    ----------
    hydro : PlatformHydrodynamics
    mooring : MooringSystem or None
    radiation : RadiationStateSpace or None
        None: no radiation memory (only A∞ acts; decays are less damped than HydroDyn's).
    mooring_steps : int or None
        Newton steps of the catenary solution in SX; None (default): as many as the lines need over a wide
        envelope (:meth:`~.mooring.MooringSystem.newton_steps`: 10 for the VolturnUS-S, converged to 1e-12).
    moving_lines : DynamicMooring or None
        MoorDyn's lines in motion (:mod:`.lumped_dynamics`), run beside the model in a simulation
        (:mod:`.lines_in_loop`); the model then has the inputs :meth:`mooring_inputs`, the lines' dynamic part
        (their load and tensions less the quasi-static ones of ``mooring``, which has no drag or inertia of its
        own then), zero at rest: trims and linear models are the quasi-static lines'. None (default): quasi-static.

    Examples
    --------
    >>> platform = floating_platform(read_openfast("fl_steady_13.fst"))  # doctest: +SKIP
    >>> model = OperatingTurbine(turbine, rotor, platform=platform)      # doctest: +SKIP
    """

    hydro: PlatformHydrodynamics
    mooring: MooringSystem | None = None
    radiation: RadiationStateSpace | None = None
    mooring_steps: int | None = None
    moving_lines: DynamicMooring | None = None

    coordinates = PLATFORM_COORDINATES
    inputs = PLATFORM_INPUTS

    @property
    def n_radiation(self) -> int:
        return 0 if self.radiation is None else self.radiation.n_states

    @property
    def excitation_fit(self):
        """HydroDyn's state-space excitation (``ExctnMod = 2``: :class:`~mbsym.wind.deck.wamit.ExcitationFit`) or None."""
        return getattr(self.hydro, "excitation_fit", None)

    @property
    def n_excitation(self) -> int:
        return 0 if self.excitation_fit is None else len(self.excitation_fit.B)

    @property
    def sea_inputs(self) -> tuple[str, ...]:
        """:data:`SEA_INPUTS`, with the state-space excitation the elevation ``Tc`` ahead
        (:data:`ELEVATION_AHEAD`), with Morison members in waves the water's velocity at them
        (:func:`~.wave_kinematics.flow_input_names`), with strip-theory members in waves their wave inertia
        (:data:`~.strip_theory.WAVE_INERTIA_INPUTS`)."""
        flow = getattr(self.hydro, "flow", None)
        return SEA_INPUTS + ((ELEVATION_AHEAD,) if self.excitation_fit is not None else ()) + \
            (flow_input_names(flow.n_points) if flow is not None else ()) + \
            (WAVE_INERTIA_INPUTS if getattr(self.hydro, "strip_waves", None) is not None else ()) + \
            self.mooring_inputs

    @property
    def mooring_inputs(self) -> tuple[str, ...]:
        """With :attr:`moving_lines`: the lines' dynamic part as inputs, :data:`MOVING_LINE_INPUTS` (load at the
        reference point, inertial axes [N, N m]) then ``MoorDTen1 …`` (fairlead tensions [N]); else ()."""
        if self.moving_lines is None:
            return ()
        return MOVING_LINE_INPUTS + tuple(f"MoorDTen{k + 1}" for k in range(self.n_lines))

    @property
    def state_names(self) -> tuple[str, ...]:
        """The radiation states ``Rdtn1 … RdtnN`` [N s, N m s: the fit's internal units], then the state-space
        excitation's ``Exctn1 …`` (``ExctnMod = 2``)."""
        return tuple(f"Rdtn{k + 1}" for k in range(self.n_radiation)) + \
            tuple(f"Exctn{k + 1}" for k in range(self.n_excitation))

    @property
    def added_mass(self) -> np.ndarray:
        """A∞ (6 × 6) [kg, kg m, kg m²] about the platform reference point."""
        return np.asarray(self.hydro.added_mass, dtype=float)

    @property
    def n_lines(self) -> int:
        return 0 if self.mooring is None else len(self.mooring.lines)

    @property
    def waves(self):
        """The deck's sea (:class:`~.excitation.WaveExcitation`), None in still water."""
        return self.hydro.waves

    def sea_tables(self, t_end: float) -> dict[str, tuple[np.ndarray, np.ndarray]]:
        """Simulation inputs ``name → (t, values)`` of :attr:`sea_inputs` over ``[0, t_end]`` [s]; {} in still water.

        With the state-space excitation the elevation at the origin ``Tc`` ahead, read linearly between the
        ``WaveDT`` samples as HydroDyn's ``SS_Excitation`` reads it (its forces come from the states)."""
        if self.waves is None:
            return {}
        tables = self.waves.tables(t_end)
        fit = self.excitation_fit
        t = tables["Wave1Elev"][0]
        if fit is not None:
            sea = self.waves.waves
            tables[ELEVATION_AHEAD] = (t, np.interp((t + fit.delay) % sea.period, sea.times(), sea.elevation()))
        flow = getattr(self.hydro, "flow", None)
        if flow is not None:
            tables.update(flow.tables(t))
        inertia = getattr(self.hydro, "strip_waves", None)
        if inertia is not None:
            tables.update(inertia.tables(t))
        return tables

    @cached_property
    def function(self) -> ca.Function:
        """``(qp, vp, xr, sea) → (load, hydro, xr_dot, tension, mass, sea_out)`` (SX, built once).

        ``qp``, ``vp``: the platform DOFs [m, rad] and their rates; ``xr``: the radiation states; ``sea``:
        the values of :data:`SEA_INPUTS` (the excitation joins ``load`` and ``hydro``).
        ``load`` [N, N m]: everything but the added mass (hydrostatics, buoyancy, additional loads, the
        members' drag, radiation, mooring with its lines' drag); ``hydro``: HydroDyn's part of it (no mooring, no added
        mass); ``tension``: the fairlead tensions [N]; ``mass``: the mooring lines' mass and added mass on
        the platform DOFs (6 × 6, zero for quasi-static lines without ``dynamics``), which the operating
        turbine adds to its mass matrix with A∞; ``jac``, ``bias``: the reference point's velocity and angular
        velocity are ``jac q̇``, its accelerations ``jac q̈ + bias`` (:func:`~._casadi.body_motion`: the Euler
        rates' angular velocity, as ElastoDyn gives HydroDyn), so A∞ enters the DOFs as ``jacᵀ A∞ jac`` and
        ``−jacᵀ A∞ bias``; the water's loads see those velocities.
        """
        qp, vp = ca.SX.sym("qp", 6), ca.SX.sym("vp", 6)
        nr = self.n_radiation
        xr = ca.SX.sym("xr", nr + self.n_excitation)
        sea = sea_in = ca.SX.sym("sea", len(self.sea_inputs))
        excitation = sea[:6]
        xr_dot = ca.SX(0, 1)
        if self.excitation_fit is not None:            # HydroDyn's SS_Excitation: ẋ = A x + B η(t + Tc), F = C x
            fit, xe = self.excitation_fit, xr[nr:]
            excitation = excitation + ca.mtimes(ca.DM(fit.C), xe)
            xe_dot = ca.mtimes(ca.DM(fit.A), xe) + ca.DM(fit.B) * sea[len(SEA_INPUTS)]
        n_sea = len(SEA_INPUTS) + (1 if self.excitation_fit is not None else 0)
        n_strip = len(WAVE_INERTIA_INPUTS) if getattr(self.hydro, "strip_waves", None) is not None else 0
        n_moving = len(self.mooring_inputs)
        moving = sea[sea.numel() - n_moving:]
        sea = sea[:sea.numel() - n_moving]
        n_flow = sea.numel() - n_sea - n_strip
        flow = sea[n_sea:n_sea + n_flow] if n_flow else None    # the waves' velocity at the Morison members
        strip = sea[n_sea + n_flow:] if n_strip else None        # the strip-theory members' wave inertia
        body, jac, bias = body_motion(qp, vp)                   # HydroDyn's velocities: angular ones exact
        hydro = self.hydro.load(qp, body, flow, strip) + excitation   # hydrostatics, additional loads, members
        if self.radiation is not None:
            hydro = hydro + ca.mtimes(ca.sparsify(ca.DM(self.radiation.C)), xr[:nr])
            xr_dot = (ca.mtimes(ca.sparsify(ca.DM(self.radiation.A)), xr[:nr])
                      + ca.mtimes(ca.sparsify(ca.DM(self.radiation.B)), body))
        if self.excitation_fit is not None:
            xr_dot = ca.vertcat(xr_dot, xe_dot)
        sea = ca.vertcat(excitation, sea[6:])                  # the channels B1Wvs*: HydroDyn's total excitation
        load, tension, mass = hydro, ca.SX(0, 1), ca.SX.zeros(6, 6)
        if self.mooring is not None:
            static, drag, mass, tension = self.mooring.line_loads(qp, vp, steps=self.mooring_steps)
            load = load + static + drag
            if self.moving_lines is not None:         # the lines' dynamic part, from the loop (.lines_in_loop)
                load = load + moving[:6]
                tension = tension + moving[6:]
                mass = mass + fairlead_node_mass(self.moving_lines, qp)
        return ca.Function("platform_loads", [qp, vp, xr, sea_in],
                           [load, hydro, xr_dot, tension, mass, sea, jac, bias],
                           ["qp", "vp", "xr", "sea"],
                           ["load", "hydro", "xr_dot", "tension", "mass", "sea_out", "jac", "bias"], {"cse": True})

    def loads(self, qp: Any, vp: Any, xr: Any, sea: Any = None) -> dict[str, Any]:
        """The outputs of :attr:`function` by name, for CasADi (SX or MX) or numeric arguments (``sea``
        default 0: still water)."""
        sea = ca.DM.zeros(len(self.sea_inputs)) if sea is None else sea
        out = self.function(qp, vp, xr if self.state_names else ca.DM(0, 1), sea)
        return dict(zip(self.function.name_out(), out))

    def channel_rows(self, loads: dict[str, Any], ap: Any) -> list[tuple[str, str, Any]]:
        """``(name, unit, expression)`` of the platform channels.

        ``HydroFxi … HydroMzi``: HydroDyn's total load at the reference point (with ``−A∞ a``, ``a`` the reference
        point's acceleration from ``ap``, the platform DOF accelerations); ``FAIRTEN<k>`` [N]; ``B1WvsFxi … B1WvsMzi`` [N, N-m] and ``Wave1Elev`` [m]
        (the sea inputs).
        """
        hydro = loads["hydro"] - ca.mtimes(ca.DM(self.added_mass), ca.mtimes(loads["jac"], ap) + loads["bias"])
        rows = [(n, u, hydro[k]) for k, (n, u) in enumerate(HYDRO_CHANNELS.items())]
        rows += [(f"FAIRTEN{k + 1}", "N", loads["tension"][k]) for k in range(self.n_lines)]
        sea = loads["sea_out"]
        rows += [(n, u, sea[k]) for k, (n, u) in enumerate(EXCITATION_CHANNELS.items())]
        rows.append(("Wave1Elev", "m", sea[6]))
        return rows

    def for_prediction(self) -> "FloatingPlatform":
        """This platform as a controller's or estimator's model holds it: no states of its own.

        Kept: hydrostatics and buoyancy, A∞, HydroDyn's additional loads (``AddF0``, ``AddCLin``,
        ``AddBLin``, ``AddBQuad``), the members' viscous drag (:mod:`.morison`) and the quasi-static catenaries. Left out: the radiation memory
        (169 states for the VolturnUS-S; at the platform's surge and pitch periods, 30–140 s, its
        damping is small against the rotor's), the lines' drag and inertia (40 % of the step) and the
        sea (its inputs stay, to be given as zero or as an estimate). The platform's stiffness and
        inertia are exactly the plant's, so its natural periods are, to the radiation's share.
        """
        from dataclasses import replace

        mooring = None if self.mooring is None else self.mooring.with_dynamics(None, self.mooring.water_density)
        hydro = replace(self.hydro, waves=None, excitation_fit=None, flow=None, strip_waves=None)
        return FloatingPlatform(hydro, mooring, None, self.mooring_steps)    # moving lines: their statics

    def __repr__(self) -> str:
        sea = "still water" if self.waves is None else self.waves.waves.description
        strip = getattr(self.hydro, "strip", None)
        buoyancy = self.hydro.hydrostatics.buoyancy + (0.0 if strip is None else strip.buoyancy)
        return (f"FloatingPlatform(radiation states={self.n_radiation}, mooring lines={self.n_lines}, "
                f"buoyancy={buoyancy / 1e6:.2f} MN, {sea})")


def floating_platform(turbine, *, radiation: str | None = None, mooring_statics: str | None = None,
                      mooring_lines: str = "quasi-static") -> FloatingPlatform | None:
    """The :class:`FloatingPlatform` of a deck's HydroDyn, SeaState and mooring files, or None without them.

    Parameters
    ----------
    turbine : TurbineParameters
        A deck read by :func:`mbsym.wind.read_openfast` (``CompHydro``, ``CompMooring``, the files in
        ``source_files``, ``WtrDens``, ``WtrDpth``, ``Gravity``).
    radiation : {"fit", "ss", "none"} or None, keyword-only
        The radiation memory: mbsym's own fit of the ``.1`` data (:func:`~.radiation_fit.fit_radiation`,
        2 % per entry up to 4 rad/s, a few seconds), the deck's ``.ss`` file (9–24 % off, not passive:
        docs/offshore.md §4), or none (a :class:`~mbsym.exceptions.ModelWarning` says so when the deck
        asks for radiation). None (default): what HydroDyn's ``RdtnMod`` asks for (:func:`deck_radiation`:
        0 none, 1 the convolution of the ``.1`` data, modelled by the fit, 2 the deck's ``.ss``).
    mooring_statics : {"lumped", "continuous"} or None, keyword-only
        The fairlead forces of MoorDyn's lines: ``"lumped"``, those of its ``NumSegs`` lumped masses at rest
        (:class:`~.lumped_line.LumpedLine`: what OpenFAST computes for the deck as written; with few segments
        the stiffness ripples as nodes lift off the seabed), or ``"continuous"``, the elastic catenaries (their
        limit for many segments). None (default): :data:`DEFAULT_MOORING_STATICS` for MoorDyn (where its lumped
        lines do not converge at rest, too few segments for the line, the catenaries with a ModelWarning), the
        catenaries for MAP++ (its model); ``"lumped"`` on a MAP++ deck is refused.
    mooring_lines : {"quasi-static", "dynamic"}, keyword-only
        ``"quasi-static"`` (default): the lines' shapes follow the fairleads at once, with MoorDyn's drag and
        inertia on them (:mod:`.line_dynamics`). ``"dynamic"``: MoorDyn's lumped-mass lines in motion, with its
        initial relaxation (:mod:`.lumped_dynamics`, :attr:`FloatingPlatform.moving_lines`): a simulation runs them
        beside the model at MoorDyn's ``dtM`` (:mod:`.lines_in_loop`); MoorDyn decks only.

    Raises
    ------
    UnsupportedFeatureError
        ``CompMooring`` 2 or 4 (FEAMooring, OrcaFlex), mooring without HydroDyn, and what
        :func:`~.platform.platform_hydrodynamics` refuses (Morison members other than potential-flow ones in
        still water, second-order forces, …).
    """
    from ...exceptions import ParameterError
    from ..deck.mapplusplus import read_map
    from ..deck.moordyn import read_moordyn

    if mooring_lines not in MOORING_LINES:
        raise ParameterError(f"mooring_lines must be one of {list(MOORING_LINES)}; got {mooring_lines!r}.")
    if mooring_statics is not None and mooring_statics not in MOORING_STATICS:
        raise ParameterError(f"mooring_statics must be one of {list(MOORING_STATICS)} or None (the default); got "
                             f"{mooring_statics!r}.")
    if radiation is not None and radiation not in RADIATION_MODELS:
        raise ParameterError(f"radiation must be one of {list(RADIATION_MODELS)} or None (the deck's RdtnMod); "
                             f"got {radiation!r}.")
    sim, files = turbine.simulation, turbine.source_files
    hydro_on, mooring_model = int(sim.hydrodynamics_model or 0), int(sim.mooring_model or 0)
    if not hydro_on and not mooring_model:
        return None
    where = files.get("fst", "the deck")
    names = {1: "MAP++", 2: "FEAMooring", 3: "MoorDyn", 4: "OrcaFlex"}
    mooring_label = f"CompMooring = {mooring_model} ({names.get(mooring_model, 'unknown module')})"
    if not hydro_on:
        raise UnsupportedFeatureError(f"{where}: {mooring_label} without HydroDyn (CompHydro = 0): a floating "
                                      "platform needs the water's buoyancy; set CompHydro = 1.")
    if mooring_model not in (0, 1, 3):
        raise UnsupportedFeatureError(f"{where}: {mooring_label} is not modelled (only 1, MAP++, and 3, MoorDyn, as "
                                      "quasi-static catenaries). Use one of those or 0.")
    for key, name, label in (("hydrodyn", "HydroFile", "CompHydro = 1 (HydroDyn)"),
                             ("mooring", "MooringFile", mooring_label)):
        if key not in files and (key == "hydrodyn" or mooring_model):
            raise UnsupportedFeatureError(f"{where}: {label} needs its input file, but {name} names none that exists; "
                                          f"give the file in {name} or set the switch to 0.")
    rho, g = float(sim.water_density), float(sim.gravity)
    if radiation is None:
        radiation = deck_radiation(files["hydrodyn"])
    with warnings.catch_warnings():
        if radiation != "none":          # the radiation memory is modelled here: no "left out" warning
            warnings.filterwarnings("ignore", message=r"RdtnMod", category=ModelWarning)
        hydro = platform_hydrodynamics(Path(files["hydrodyn"]), water_density=rho, gravity=g,
                                       seastate=files.get("seastate"), water_depth=float(sim.water_depth),
                                       platform_reference=tuple(turbine.platform_reference))
    mooring = None
    if mooring_model == 3:       # MoorDyn gets SeaState's WtrDens/WtrDpth and the .fst's Gravity (FAST_Subs.f90)
        sea = {"water_density": rho, "water_depth": float(sim.water_depth)}
        if files.get("seastate"):
            from ..deck.seastate import read_seastate

            sea = read_seastate(Path(files["seastate"])).resolved(rho, float(sim.water_depth))
        md = read_moordyn(Path(files["mooring"]))
        if mooring_lines == "dynamic":
            return _with_moving_lines(md, sea, g, mooring_statics, float(sim.time_step),
                                      FloatingPlatform(hydro, None, _radiation(hydro, radiation, files["hydrodyn"])))
        mooring = _moordyn_mooring(md, sea, g, mooring_statics)
    elif mooring_model == 1:
        if mooring_lines == "dynamic":
            raise UnsupportedFeatureError(f"{where}: mooring_lines='dynamic' moves MoorDyn's lumped-mass lines; the "
                                          "deck's MAP++ lines are quasi-static. Drop the option or use a MoorDyn deck "
                                          "(CompMooring = 3).")
        if mooring_statics == "lumped":
            raise UnsupportedFeatureError(f"{where}: mooring_statics='lumped' is MoorDyn's segmented line; the deck's "
                                          "MAP++ lines are continuous catenaries. Drop the option or use a MoorDyn "
                                          "deck (CompMooring = 3).")
        mooring = mooring_from_map(read_map(Path(files["mooring"])), water_density=rho, gravity=g,
                                   water_depth=float(sim.water_depth))
    return FloatingPlatform(hydro, mooring, _radiation(hydro, radiation, files["hydrodyn"]))


def _moordyn_mooring(md, sea: dict, gravity: float, statics: str | None):
    """A MoorDyn deck's lines with ``statics`` (None: :data:`DEFAULT_MOORING_STATICS`; where the default's lumped
    lines do not converge, too few segments, the continuous catenaries with a ModelWarning saying so)."""
    from .mooring import LumpedStaticsError

    args = {"water_density": sea["water_density"], "gravity": gravity, "water_depth": sea["water_depth"]}
    try:
        return mooring_from_moordyn(md, line_statics=statics or DEFAULT_MOORING_STATICS, **args)
    except LumpedStaticsError as err:
        if statics is not None:
            raise
        warnings.warn(f"{err} The continuous catenaries are used (mooring_statics='continuous'): the limit of many "
                      "segments, without the segmented line's stiffness ripple.", ModelWarning, stacklevel=3)
        return mooring_from_moordyn(md, line_statics="continuous", **args)


def _with_moving_lines(md, sea: dict, gravity: float, statics: str | None, coupling_dt: float,
                       platform: FloatingPlatform) -> FloatingPlatform:
    """``platform`` with MoorDyn's lines in motion: their statics (no drag, no inertia: the moving lines have
    them) in the graph, the lines themselves as :attr:`FloatingPlatform.moving_lines`."""
    from dataclasses import replace

    from ..deck.moordyn_audit import moordyn_environment

    with warnings.catch_warnings():                 # the quasi-static lines' "not modelled" note is not true here
        warnings.filterwarnings("ignore", message=r".*MoorDyn's line dynamics", category=ModelWarning)
        mooring = _moordyn_mooring(md, sea, gravity, statics)
    env = moordyn_environment(md, water_density=sea["water_density"], gravity=gravity,
                              water_depth=sea["water_depth"])
    moving = dynamic_mooring_from_moordyn(md, mooring, gravity=env.gravity, depth=float(env.water_depth),
                                          coupling_dt=coupling_dt)
    return replace(platform, mooring=mooring.with_dynamics(None, mooring.water_density), moving_lines=moving)


def deck_radiation(hydrodyn_file) -> str:
    """The radiation model a HydroDyn file asks for: ``RdtnMod`` 0 → ``"none"``, 1 → ``"fit"``, 2 → ``"ss"``.

    ``RdtnMod = 1`` (HydroDyn's convolution of the ``.1`` data's retardation kernel) is modelled by mbsym's
    state-space fit of the same data (:func:`~.radiation_fit.fit_radiation`; a convolution has no states
    to linearize); ``RdtnMod = 2`` is HydroDyn's own state-space block from the deck's ``.ss`` file.
    """
    from ..deck.hydrodyn import read_hydrodyn

    hd = read_hydrodyn(Path(hydrodyn_file))
    if hd.potential_model == 0:            # no potential flow: HydroDyn has no radiation either
        return "none"
    return {0: "none", 1: "fit", 2: "ss"}[int(hd.radiation_model)]


def _radiation(hydro: PlatformHydrodynamics, model: str, hydrodyn_file) -> RadiationStateSpace | None:
    if model == "none":
        return None
    if hydro.wamit is None:
        raise UnsupportedFeatureError(f"{hydrodyn_file}: radiation={model!r} needs WAMIT data; the deck has PotMod = 0 "
                                      "(strip theory only, no radiation). Use radiation='none' or None.")
    if model == "fit":
        from .radiation_fit import fit_radiation_cached

        return fit_radiation_cached(hydro.wamit)
    from ..deck.hydrodyn import read_hydrodyn
    from ..deck.wamit import read_wamit_ss

    root = read_hydrodyn(Path(hydrodyn_file)).potential_files[0]
    path = Path(f"{root}.ss")
    if not path.is_file():
        raise UnsupportedFeatureError(f"{hydrodyn_file}: radiation='ss' needs the state-space fit '{path}'; it does "
                                      "not exist. Use radiation='fit' (mbsym's own fit of the .1 data).")
    return RadiationStateSpace.from_fit(read_wamit_ss(path))
