"""The turbine model an NMPC and a state estimator predict with: a reduced operating turbine.

A :class:`PredictionModel` is an :class:`~mbsym.wind.operation.OperatingTurbine` with fewer DOFs
than the plant (default :data:`PREDICTION_DOFS`: generator and first tower fore-aft mode, with the
plant's rotor aerodynamics, dynamic inflow and actuator limits), rewritten in two first-order forms
from the **same CasADi graph** (nothing is derived again):

``control`` — inputs ``Wind1VelX`` [m/s], ``BlPitchRate`` [rad/s], ``GenTqRate`` [N m/s]
    The controller decides the *rates* of the pitch and torque it commands; the pitch ``BlPitch``
    and torque ``GenTq`` are states integrating them. The plant's actuators are kept exact: the
    composed model is evaluated with the actuator speed ``BlPitch_d = r_β`` and the demands
    ``BlPitchCom = β + (2ζ/ω) r_β``, ``GenTqCom = T + τ r_T``, for which the plant's pitch
    (second-order, ``ω``, ``ζ``) and torque (lag ``τ``) actuators move at exactly the rates
    ``r_β``, ``r_T`` (zero pitch acceleration) inside their limits. Applied to the plant the same
    way (a ramp of the command with that lead, :meth:`PredictionModel.commands`), a rate held
    over a sample moves the plant's actuators as the model predicts, and the pitch and torque
    rate limits are simple bounds on the inputs. The stiff actuator poles (50 rad/s, 0.01 s)
    leave the prediction model, so RK4 at 0.1 s steps is stable and accurate.

``estimation`` — inputs ``Wind1VelX``, ``BlPitchMeas`` [rad], ``GenTqMeas`` [N m] (and, floating, the
    waves' loads on the platform DOFs, :attr:`PredictionModel.wave_inputs`, which an estimator
    estimates as it estimates the wind)
    The measured pitch and torque drive the structure and rotor (actuators at rest at the
    measured values): what a wind-speed estimator knows. States: the structure's and the inflow's.

**A floating plant** (``OperatingTurbine(..., platform=...)``): the default DOFs add the platform's
surge and pitch (:data:`FLOATING_PREDICTION_DOFS`), with the platform as a controller holds it
(``FloatingPlatform.for_prediction``: hydrostatics, A∞, HydroDyn's additional loads and the
quasi-static mooring, no radiation states, no line drag); the sea's inputs are zero in the control
form (the waves are a disturbance it does not preview), and the estimation form takes the waves' loads
on its platform DOFs as inputs for an estimator to estimate.

The rotor azimuth ``GeAz`` is dropped from both: the rotor's loads are azimuth-averaged and its
inertia axisymmetric, so no right-hand side depends on it (checked at construction).
Outputs: every OpenFAST channel of the reduced turbine, in OpenFAST units.
"""

from __future__ import annotations

from typing import Mapping, Sequence

import casadi as ca
import numpy as np

from ...dynamics import Dynamics
from ...exceptions import ModelDefinitionError, ParameterError

__all__ = ["PredictionModel", "PREDICTION_DOFS", "FLOATING_PREDICTION_DOFS", "CONTROL_INPUTS", "ESTIMATION_INPUTS"]

#: ElastoDyn DOFs of the default prediction model (the fidelity ladder's choice, docs/turbine_nmpc.md).
PREDICTION_DOFS = ("GenDOF", "TwFADOF1")
#: The default for a floating plant: the platform's surge and pitch too (docs/turbine_nmpc.md, "Floating").
FLOATING_PREDICTION_DOFS = ("GenDOF", "TwFADOF1", "PtfmSgDOF", "PtfmPDOF")
#: Inputs of :attr:`PredictionModel.control`.
CONTROL_INPUTS = ("Wind1VelX", "BlPitchRate", "GenTqRate")
#: Inputs of :attr:`PredictionModel.estimation`.
ESTIMATION_INPUTS = ("Wind1VelX", "BlPitchMeas", "GenTqMeas")
#: Units of the inputs of the two forms (SI, docs/units.md).
INPUT_UNITS = {"Wind1VelX": "m/s", "BlPitchRate": "rad/s", "GenTqRate": "N m/s", "BlPitchMeas": "rad",
               "GenTqMeas": "N m"}
_DROPPED = ("GeAz", "BlPitch_d")


class PredictionModel:
    """A reduced operating turbine in rate-input (control) and measured-actuator (estimation) form.

    Parameters
    ----------
    plant : OperatingTurbine
        The turbine controlled (its structure data, rotor, actuators and inflow model are used).
    dofs : sequence of str, optional, keyword-only
        ElastoDyn DOF flags of the prediction model (must include ``GenDOF``); default
        :data:`PREDICTION_DOFS`, for a floating plant :data:`FLOATING_PREDICTION_DOFS`.
    dynamic_inflow : bool, optional, keyword-only
        Keep the plant's dynamic inflow (default: as the plant). The rotor disk's across-shaft terms
        (``disk_moments``) and the tower's drag (``tower_aero``) are the plant's: without the drag the floating IEA
        15 MW's prediction model settled 0.54 m of surge and 0.09° of platform pitch short of the plant at 13 m/s,
        and the NMPC, penalizing the platform's predicted return, held the power 3.6-3.9 % above rated.
    p : dict, optional, keyword-only
        Parameter values by name (those the reduced model has; e.g. the plant's own values).

    Attributes
    ----------
    turbine : OperatingTurbine
        The reduced turbine.
    control, estimation : Dynamics
        See the module docstring.

    Raises
    ------
    TypeError
        ``plant`` is not an OperatingTurbine.
    ModelDefinitionError
        DOFs without ``GenDOF``; a right-hand side that depends on the azimuth.
    """

    def __init__(self, plant, *, dofs: Sequence[str] | None = None, dynamic_inflow: bool | None = None,
                 p: Mapping[str, float] | None = None) -> None:
        from ..operation.model import OperatingTurbine

        if not isinstance(plant, OperatingTurbine):
            raise TypeError(f"plant must be an OperatingTurbine; got {type(plant).__name__}.")
        platform = plant.platform
        if dofs is None:                # a bottom-fixed substructure (floating = False) is held still like land
            floats = platform is not None and getattr(platform, "floating", True)
            on = plant.dofs                                    # those the plant has (a deck without a tower DOF)
            dofs = tuple(d for d in (FLOATING_PREDICTION_DOFS if floats else PREDICTION_DOFS) if on.get(d, False))
        dofs = tuple(dofs)
        if "GenDOF" not in dofs:
            raise ModelDefinitionError(f"the prediction model needs GenDOF (the rotor speed is what it controls); "
                                       f"got dofs {list(dofs)}.")
        keep_inflow = plant.dynamic_inflow is not None if dynamic_inflow is None else bool(dynamic_inflow)
        if keep_inflow and plant.dynamic_inflow is None:
            raise ParameterError("dynamic_inflow=True: the plant has no dynamic inflow to share; build the plant "
                                 "with it or pass dynamic_inflow=False.")
        self.plant = plant
        self.dofs = dofs
        if platform is not None and not any(d.startswith("Ptfm") for d in dofs):
            platform = None                              # a platform held still: no water, no mooring
        elif platform is not None and hasattr(platform, "for_prediction"):
            platform = platform.for_prediction()
        self.turbine = OperatingTurbine(plant.turbine, plant.rotor, dofs=dofs, actuators=plant.actuators,
                                        dynamic_inflow=plant.dynamic_inflow if keep_inflow else False,
                                        saturation_width=plant.saturation_width, platform=platform,
                                        disk_moments=plant.structure.hub_moments, tower_aero=plant.tower_aero,
                                        nacelle_drag=getattr(plant, "nacelle_drag", None), name="prediction")
        full = self.turbine.dynamics()
        self.full = full
        self._p = dict(p or {})
        unknown = sorted(set(self._p) - set(full.parameters))
        if unknown:
            raise ParameterError(f"parameters {unknown} are not parameters of the prediction model; its parameters "
                                 f"are {list(full.parameters)}.")
        self.states = tuple(s for s in full.states if s not in _DROPPED)
        self.estimation_states = tuple(s for s in self.states if s not in ("BlPitch", "GenTq"))
        self.control = self._control_form(full)
        self.estimation = self._estimation_form(full)
        self._check_azimuth(full)
        self._pv = self.control.parameter_vector()
        self._lead = self.lead(self._pv)
        b = plant.bounds()
        self._demand_limits = (b["BlPitchCom"], b["GenTqCom"])

    # ------------------------------------------------------------------ forms
    def _symbols(self, full: Dynamics, n_z: int, n_u: int = 3):
        S = ca.SX if full.rhs.is_a("SXFunction") and full.outputs.is_a("SXFunction") else ca.MX
        z, u, p = S.sym("x", n_z), S.sym("u", n_u), S.sym("p", full.n_p)
        P = {n: p[i] for i, n in enumerate(full.parameters)}
        return S, z, u, p, P

    def _control_form(self, full: Dynamics) -> Dynamics:
        S, z, u, p, P = self._symbols(full, len(self.states))
        Z = {n: z[i] for i, n in enumerate(self.states)}
        rb, rt = u[1], u[2]
        x = ca.vertcat(*[0.0 if s == "GeAz" else rb if s == "BlPitch_d" else Z[s] for s in full.states])
        demand = ca.vertcat(u[0], Z["BlPitch"] + 2.0 * P["pitch_damping"] / P["pitch_frequency"] * rb,
                            Z["GenTq"] + P["torque_time_constant"] * rt, ca.DM.zeros(full.n_u - 3))
        xd = full.rhs(x, demand, p)
        rows = [rb if s == "BlPitch" else rt if s == "GenTq" else xd[full.states.index(s)] for s in self.states]
        return self._dynamics(full, S, z, u, p, ca.vertcat(*rows), full.outputs(x, demand, p), self.states,
                              CONTROL_INPUTS, "prediction_control")

    @property
    def wave_inputs(self) -> tuple[str, ...]:
        """The sea's loads on the model's platform DOFs (``B1WvsFxi`` for surge, ``B1WvsMyi`` for pitch, …),
        inputs of the estimation form after :data:`ESTIMATION_INPUTS`; () on land."""
        pairs = (("Sg", "B1WvsFxi"), ("Sw", "B1WvsFyi"), ("Hv", "B1WvsFzi"), ("R", "B1WvsMxi"), ("P", "B1WvsMyi"),
                 ("Y", "B1WvsMzi"))
        inputs = self.full.inputs
        return tuple(load for dof, load in pairs if dof in self.estimation_states and load in inputs)

    def _estimation_form(self, full: Dynamics) -> Dynamics:
        waves = self.wave_inputs
        S, z, u, p, P = self._symbols(full, len(self.estimation_states), 3 + len(waves))
        Z = {n: z[i] for i, n in enumerate(self.estimation_states)}
        Z.update(BlPitch=u[1], GenTq=u[2], BlPitch_d=0.0, GeAz=0.0)
        x = ca.vertcat(*[Z[s] for s in full.states])
        given = {name: u[3 + k] for k, name in enumerate(waves)}
        demand = ca.vertcat(u[0], u[1], u[2], *[given.get(n, 0.0) for n in full.inputs[3:]])   # actuators at rest
        xd = full.rhs(x, demand, p)
        rows = [xd[full.states.index(s)] for s in self.estimation_states]
        return self._dynamics(full, S, z, u, p, ca.vertcat(*rows), full.outputs(x, demand, p),
                              self.estimation_states, ESTIMATION_INPUTS + waves, "prediction_estimation")

    def _dynamics(self, full, S, z, u, p, rhs, y, states, inputs, name) -> Dynamics:
        opts = {"cse": True} if S is ca.SX else {}
        f = ca.Function(f"{name}_rhs", [z, u, p], [rhs], ["x", "u", "p"], ["xd"], opts)
        h = ca.Function(f"{name}_outputs", [z, u, p], [y], ["x", "u", "p"], ["y"], opts)
        defaults = {**dict(full.defaults), **self._p}
        x0 = [full.x0[full.states.index(s)] for s in states]
        state_units = dict(zip(full.states, full.state_units))
        units = {**dict(zip(full.inputs, full.input_units)), **INPUT_UNITS}
        return Dynamics(f, states=states, inputs=inputs, parameters=full.parameters, defaults=defaults, outputs=h,
                        output_names=full.output_names, output_units=full.output_units, x0=x0, name=name,
                        state_units=[state_units.get(s, "") for s in states], input_units=[units.get(n, "") for n in inputs])

    def _check_azimuth(self, full: Dynamics) -> None:
        """The right-hand side must not depend on the azimuth (it is dropped)."""
        if "GeAz" not in full.states:
            return
        rng = np.random.default_rng(0)
        x = full.x0.copy()
        x[full.states.index("GeAz_d")] = 1.2
        u = np.concatenate([[12.0, 0.05, 4e4], np.zeros(full.n_u - 3)])
        a, b = x.copy(), x.copy()
        a[full.states.index("GeAz")], b[full.states.index("GeAz")] = 0.0, float(rng.uniform(0.5, 5.5))
        fa, fb = full.rhs_value(a, u), full.rhs_value(b, u)
        keep = [i for i, s in enumerate(full.states) if s != "GeAz"]
        if not np.allclose(fa[keep], fb[keep], rtol=1e-9, atol=1e-9):
            raise ModelDefinitionError(f"the right-hand side of the prediction model {list(self.dofs)} depends on the "
                                       "rotor azimuth; it cannot be dropped. Use DOFs without blade or yaw motion.")

    # ------------------------------------------------------------------ plant <-> model
    def state_from_plant(self, x_plant, plant_states: Sequence[str]) -> np.ndarray:
        """The control state picked by name from a plant state vector."""
        x = np.asarray(x_plant, dtype=float).reshape(-1)
        return np.array([x[list(plant_states).index(s)] for s in self.states])

    def parameter_vector(self, p: Mapping[str, float] | None = None) -> np.ndarray:
        """Parameters of both forms: the model's defaults, the values given at construction, then ``p``."""
        return self.control.parameter_vector(p)

    def lead(self, p: np.ndarray | None = None) -> tuple[float, float]:
        """``(2ζ/ω, τ)`` [s]: the command lead of the pitch and torque actuators."""
        pv = self.parameter_vector() if p is None else p
        names = self.control.parameters
        return (2.0 * pv[names.index("pitch_damping")] / pv[names.index("pitch_frequency")],
                float(pv[names.index("torque_time_constant")]))

    def commands(self, pitch: float, torque: float, pitch_rate: float, torque_rate: float,
                 elapsed: float) -> tuple[float, float]:
        """Plant demands ``(BlPitchCom [rad], GenTqCom [N m])`` for rates held since ``elapsed`` seconds.

        ``pitch``, ``torque``: the actuator values when the rates started. The demands ramp at
        the rates with the actuators' lead (module docstring; the parameters given at
        construction), clipped to the plant's demand limits.
        """
        lb, lt = self._lead
        (b0, b1), (t0, t1) = self._demand_limits
        beta = pitch + pitch_rate * (elapsed + lb)
        tq = torque + torque_rate * (elapsed + lt)
        return (min(max(beta, b0), b1), min(max(tq, t0), t1))

    def __repr__(self) -> str:
        inflow = "dynamic inflow" if self.turbine.dynamic_inflow is not None else "quasi-steady inflow"
        return f"PredictionModel(dofs={list(self.dofs)}, {inflow}, states={list(self.states)})"
