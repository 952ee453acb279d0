"""The floating structure: mbsym's ElastoDyn model with the water, the sea and the mooring on its platform.

Not the operating turbine (no aerodynamics, no controller: a parked rotor, as OpenFAST runs a deck with
``CompAero = 0`` and ``CompServo = 0``): the structural model of a deck
(:class:`~mbsym.wind.structure.turbine.TurbineModel`, whose platform force and moment inputs ``PtfmFx … PtfmMz``
act at the platform reference point in inertial axes) with the loads of a
:class:`~.operating.FloatingPlatform` on them — hydrostatics and buoyancy, HydroDyn's additional loads, the
radiation memory as states, the quasi-static mooring with its lines' drag and inertia, the sea's excitation
(inputs ``B1WvsFxi … B1WvsMzi``, ``Wave1Elev``) — and A∞ (with the lines' mass) in the platform block of the
mass matrix. :meth:`FloatingStructure.dynamics` is an :class:`mbsym.Dynamics` (``mbsym simulate`` runs it for a
floating deck without AeroDyn; :func:`mbsym.simulate` with :meth:`FloatingStructure.sea_tables` as inputs);
:meth:`FloatingStructure.simulate` integrates with fixed-step RK4 in one CasADi ``mapaccum``.

Approximations (those of :mod:`.operating`): the water's loads see the platform's exact velocity and acceleration
(the Euler rates' angular velocity, :func:`~._casadi.body_motion`; A∞ as ``Jᵀ A∞ J`` and ``−Jᵀ A∞ b``); the lines
are quasi-static, with their drag and inertia on that shape when the mooring has ``dynamics``
(:mod:`.line_dynamics`); the excitation at the undisplaced platform.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import casadi as ca
import numpy as np

from ...dynamics import Dynamics
from ...exceptions import ModelDefinitionError
from .mooring import MooringSystem
from .operating import PLATFORM_COORDINATES, PLATFORM_INPUTS, FloatingPlatform, platform_dofs, sea_input_unit
from .platform import PlatformHydrodynamics
from .radiation import RadiationStateSpace

__all__ = ["FloatingStructure", "floating_structure"]


@dataclass(frozen=True, eq=False)
class FloatingStructure:
    """Structure + water + sea + mooring as one first-order system ``ẋ = f(x, u, p)``, ``x = [q, q̇, x_rad]``.

    Parameters
    ----------
    model : TurbineModel
        With its platform DOFs (a disabled one is held at its initial value, as ElastoDyn holds it).
    hydro : PlatformHydrodynamics
    mooring : MooringSystem or None
    radiation : RadiationStateSpace or None
    platform_loads : object, optional
        Another platform-loads object instead of ``hydro``/``mooring``/``radiation``: a bottom-fixed SubDyn
        substructure (:class:`~.bottom_fixed.BottomFixedPlatform`, ``hydro=None``).
    structural_controls : StructuralControls, optional
        ServoDyn's nacelle, tower and platform tuned mass dampers and prescribed loads
        (:mod:`mbsym.wind.structure.structural_control`): their states, inputs (``NStC1_Fx`` …) and channels
        (``NStC1_XQ`` …) after the others.
    """

    model: Any
    hydro: PlatformHydrodynamics | None
    mooring: MooringSystem | None = None
    radiation: RadiationStateSpace | None = None
    platform_loads: Any = None
    structural_controls: Any = None
    _cache: dict = field(default_factory=dict, repr=False, compare=False)

    def __post_init__(self) -> None:
        eom = self.model.eom
        missing = [u for u in PLATFORM_INPUTS if u not in eom.inputs]
        if missing or not any(c in eom.coordinates for c in PLATFORM_COORDINATES):
            raise ModelDefinitionError(f"the structural model lacks {missing or 'every platform DOF'}: enable the "
                                       "platform DOFs (PtfmSgDOF … PtfmYDOF) in the deck or in TurbineModel(dofs=…).")

    # ------------------------------------------------------------------ what the CLI and simulate use
    @property
    def platform(self) -> FloatingPlatform:
        """The platform's loads (:class:`~.operating.FloatingPlatform`, built once)."""
        if "platform" not in self._cache:
            self._cache["platform"] = self.platform_loads if self.platform_loads is not None else \
                FloatingPlatform(self.hydro, self.mooring, self.radiation)
        return self._cache["platform"]

    @property
    def turbine(self):
        return self.model.turbine

    @property
    def dofs(self) -> dict[str, bool]:
        return self.model.dofs

    @property
    def eom(self):
        return self.model.eom

    @property
    def n_radiation(self) -> int:
        """The platform's own states: radiation and (``ExctnMod = 2``) excitation."""
        return len(self.platform.state_names)

    def sea_tables(self, t_end: float) -> dict[str, tuple[np.ndarray, np.ndarray]]:
        """The deck's input tables over ``[0, t_end]`` [s]: its sea ({} in still water) and ServoDyn's prescribed
        StC loads (:meth:`~mbsym.wind.structure.structural_control.StructuralControls.tables`)."""
        tables = dict(self.platform.sea_tables(t_end))
        if self.structural_controls is not None:
            tables.update(self.structural_controls.tables(t_end))
        return tables

    def output_function(self):
        """The channels (``names``, ``units``, ``function`` of the Dynamics' ``(x, u, p)``)."""
        from ..structure.channels import Channels

        dyn = self.dynamics()
        return Channels(dyn.outputs, tuple(dyn.output_names), tuple(dyn.output_units))

    # ------------------------------------------------------------------ the graph
    def dynamics(self) -> Dynamics:
        """The floating structure as an :class:`mbsym.Dynamics` (built once).

        States: the structure's ``[q; q̇]``, then ``Rdtn1 …``. Inputs: the structure's inputs other than the
        platform loads, then :data:`~.operating.SEA_INPUTS`. Outputs: ElastoDyn's channels (with the
        accelerations of this mass matrix), ``HydroFxi … HydroMzi``, ``FAIRTEN<k>``, ``B1Wvs…``, ``Wave1Elev``.
        """
        if "dynamics" not in self._cache:
            self._cache["dynamics"] = self._build()
        return self._cache["dynamics"]

    def _build(self) -> Dynamics:
        from ..structure.channels import channel_function
        from ..structure.units import structural_input_unit

        eom, platform = self.model.eom, self.platform
        n, nr = eom.n_q, self.n_radiation
        index, fixed, select = platform_dofs(eom.coordinates, self.model.turbine)
        other = [u for u in eom.inputs if u not in PLATFORM_INPUTS]
        stc = self.structural_controls
        ns = len(stc.state_names) if stc is not None else 0
        stc_inputs = stc.input_names if stc is not None else ()
        x = ca.SX.sym("x", 2 * n + nr + ns)
        sea_inputs = platform.sea_inputs
        n_sea = len(other) + len(sea_inputs)
        u = ca.SX.sym("u", n_sea + len(stc_inputs))
        p = ca.SX.sym("p", eom.n_p)
        q, qd, xr = x[:n], x[n:2 * n], x[2 * n:2 * n + nr]
        qp = ca.vertcat(*[q[i] if i is not None else fixed[k] for k, i in enumerate(index)])
        vp = ca.vertcat(*[qd[i] if i is not None else 0.0 for i in index])
        loads = platform.loads(qp, vp, xr if nr else ca.DM(0, 1), u[len(other):n_sea])
        values = {name: u[k] for k, name in enumerate(other)}
        values.update({name: loads["load"][k] for k, name in enumerate(PLATFORM_INPUTS)})
        us = ca.vertcat(*[values[name] for name in eom.inputs])
        S = ca.DM(select)
        f_m = eom.functions.mass_matrix
        JS = ca.mtimes(loads["jac"], S)                 # A∞ with the exact angular acceleration J q̈ + b
        M = (f_m(q, p) if f_m.n_in() == 2 else f_m(q, us, p)) \
            + ca.mtimes([JS.T, ca.DM(platform.added_mass), JS]) + ca.mtimes([S.T, loads["mass"], S])
        forcing = eom.functions.forcing(q, qd, us, p) - ca.mtimes([JS.T, ca.DM(platform.added_mass), loads["bias"]])
        if stc is not None:                             # ServoDyn's StCs: their loads, the q̈-dependent part in M
            from ..structure.structural_control import stc_terms

            terms = stc_terms(stc, eom, q, qd, us, p, x[2 * n + nr:], p[eom.parameters.index("gravity")],
                              u_stc=u[n_sea:], structure=self.model)
            M, forcing = M + terms["mass"], forcing + terms["force"]
        qdd = ca.solve(M, forcing)
        xr_dot = loads["xr_dot"]
        if nr and "xr_acc" in loads:                     # SubDyn's Craig-Bampton modes follow the TP's acceleration
            ap = ca.vertcat(*[qdd[i] if i is not None else 0.0 for i in index])
            xr_dot = xr_dot + ca.mtimes(loads["xr_acc"], ca.mtimes(loads["jac"], ap) + loads["bias"])
        xd = ca.vertcat(qd, qdd, xr_dot) if nr else ca.vertcat(qd, qdd)
        if stc is not None:
            xd = ca.vertcat(xd, terms["rates"](qdd))
        f_y, names, units = channel_function(self.model)
        rows = platform.channel_rows(loads, ca.vertcat(*[qdd[i] if i is not None else 0.0 for i in index]))
        if stc is not None:
            rows += [(nm, un, terms["channels"](qdd)[k]) for k, (nm, un) in enumerate(stc.channel_names())]
        y = ca.vertcat(f_y(q, qd, qdd, us, p), *[r[2] for r in rows])
        names, units = names + tuple(r[0] for r in rows), units + tuple(r[1] for r in rows)
        opts = {"cse": True}
        rhs = ca.Function("floating_rhs", [x, u, p], [xd], ["x", "u", "p"], ["xd"], opts)
        outputs = ca.Function("floating_outputs", [x, u, p], [y], ["x", "u", "p"], ["y"], opts)
        inputs = tuple(other) + sea_inputs + stc_inputs
        return Dynamics(rhs, states=tuple(eom.states) + platform.state_names + (stc.state_names if ns else ()),
                        inputs=inputs,
                        parameters=tuple(eom.parameters), defaults=dict(eom.defaults), outputs=outputs,
                        output_names=names, output_units=units, x0=self.initial_state(),
                        name="floating_structure",
                        input_units=[structural_input_unit(n) for n in other] + [sea_input_unit(n) for n in sea_inputs]
                        + list(stc.input_units if stc is not None else ()))

    def rhs(self) -> ca.Function:
        """``x → ẋ`` (SX), the deck's parameter values bound, other inputs zero (still water)."""
        dyn = self.dynamics()
        x = ca.SX.sym("x", dyn.n_x)
        xd = dyn.rhs(x, ca.DM.zeros(dyn.n_u), ca.DM(self.model.eom.parameter_vector()))
        return ca.Function("floating_rhs_x", [x], [xd], ["x"], ["xd"])

    def initial_state(self) -> np.ndarray:
        """The deck's initial q and q̇ (``TurbineModel.default_state``), radiation states 0."""
        x0 = np.asarray(self.model.default_state(), dtype=float)
        stc = self.structural_controls.initial_state() if self.structural_controls is not None else np.zeros(0)
        return np.concatenate([x0, np.zeros(self.n_radiation), stc])

    def simulate(self, t_end: float, dt: float, x0=None) -> tuple[np.ndarray, np.ndarray]:
        """Fixed-step RK4 in still water from ``x0`` (default :meth:`initial_state`): times [s] and states (columns)."""
        f = self.rhs()
        x = ca.SX.sym("x", f.size1_in(0))
        k1 = f(x)
        k2 = f(x + dt / 2 * k1)
        k3 = f(x + dt / 2 * k2)
        k4 = f(x + dt * k3)
        step = ca.Function("rk4", [x], [x + dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4)])
        steps = int(round(t_end / dt))
        start = self.initial_state() if x0 is None else np.asarray(x0, dtype=float)
        states = np.array(step.mapaccum("floating_sim", steps)(start))
        return dt * np.arange(1, steps + 1), states


def floating_structure(turbine, *, radiation: str | None = None, structural_controls=None,
                       mooring_statics: str | None = None, mooring_lines: str = "quasi-static") -> FloatingStructure:
    """The :class:`FloatingStructure` of a deck (its ElastoDyn DOFs, HydroDyn, SeaState and MoorDyn/MAP++ files), or
    of a bottom-fixed deck its ElastoDyn DOFs on the SubDyn substructure (``CompSub = 1``,
    :func:`~.bottom_fixed.bottom_fixed_platform`).

    Parameters
    ----------
    turbine : TurbineParameters
        A floating deck (:func:`mbsym.wind.read_openfast`) with all six platform DOFs.
    radiation : {"fit", "ss", "none"} or None, keyword-only
        As :func:`~.operating.floating_platform` (None: the deck's ``RdtnMod``).
    structural_controls : StructuralControls, optional, keyword-only
        ServoDyn's nacelle and platform StCs (:func:`mbsym.wind.structure.structural_control.structural_controls`).
    mooring_statics : {"lumped", "continuous"} or None, keyword-only
        As :func:`~.operating.floating_platform` (None: its default).
    mooring_lines : {"quasi-static", "dynamic"}, keyword-only
        As :func:`~.operating.floating_platform`: with ``"dynamic"`` the structure's platform has MoorDyn's moving
        lines (:attr:`~.operating.FloatingPlatform.moving_lines`), which a simulation runs beside it
        (:func:`~.lines_in_loop.with_moving_lines`).

    Raises
    ------
    UnsupportedFeatureError
        What :func:`~.operating.floating_platform` refuses, or a deck without HydroDyn and mooring.
    """
    from ...exceptions import UnsupportedFeatureError
    from ..structure.turbine import TurbineModel
    from .operating import floating_platform

    if int(getattr(turbine.simulation, "substructure_model", 0) or 0):        # SubDyn: bottom-fixed
        from .bottom_fixed import bottom_fixed_platform

        return FloatingStructure(TurbineModel(turbine), None, platform_loads=bottom_fixed_platform(turbine),
                                 structural_controls=structural_controls)
    platform = floating_platform(turbine, radiation=radiation, mooring_statics=mooring_statics,
                                 mooring_lines=mooring_lines)
    if platform is None:
        raise UnsupportedFeatureError(f"{turbine.source_files.get('fst', 'the deck')}: CompHydro and CompMooring are "
                                      "0; a floating structure needs HydroDyn (and usually a mooring).")
    moving = platform if platform.moving_lines is not None else None
    return FloatingStructure(TurbineModel(turbine), platform.hydro, platform.mooring, platform.radiation,
                             platform_loads=moving, structural_controls=structural_controls)
