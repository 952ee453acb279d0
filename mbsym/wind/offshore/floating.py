"""A first floating structure: mbsym's ElastoDyn model with the water and the mooring on its platform.

Not the operating turbine (no aerodynamics, no controller): the structural model of a deck
(:class:`~mbsym.wind.structure.turbine.TurbineModel`, whose platform force and moment inputs
``PtfmFx … PtfmMz`` act at the platform reference point in inertial axes) with

* hydrostatics, buoyancy and HydroDyn's additional loads (:class:`~.platform.PlatformHydrodynamics`),
* the quasi-static mooring (:class:`~.mooring.MooringSystem`, fixed Newton steps in SX),
* the radiation memory as states (:class:`~.radiation.RadiationStateSpace`),
* A∞ added to the platform block of the mass matrix.

Approximations of this first layer (stated, to be removed when it joins the operating turbine):
the platform's translational and angular velocity and acceleration are taken as the DOF rates
(``q̇``, ``q̈`` of surge…yaw), exact at zero rotation and first order in the angles; the lines
are quasi-static, with their drag and inertia on that shape when the mooring has ``dynamics``
(:mod:`.line_dynamics`: the fairlead's exact velocity, the lines' mass added to the platform block
of the mass matrix). :meth:`FloatingStructure.simulate` integrates with fixed-step
RK4 in one CasADi ``mapaccum``.
"""

from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np

from ...exceptions import ModelDefinitionError
from .mooring import MooringSystem
from .platform import PlatformHydrodynamics
from .radiation import RadiationStateSpace

__all__ = ["FloatingStructure"]

_PLATFORM = ("Sg", "Sw", "Hv", "R", "P", "Y")
_INPUTS = ("PtfmFx", "PtfmFy", "PtfmFz", "PtfmMx", "PtfmMy", "PtfmMz")


@dataclass(frozen=True, eq=False)
class FloatingStructure:
    """Structure + water + mooring as one first-order system ``ẋ = f(x)``, ``x = [q, q̇, x_rad]``.

    Parameters
    ----------
    model : TurbineModel
        With all six platform DOFs enabled.
    hydro : PlatformHydrodynamics
    mooring : MooringSystem or None
    radiation : RadiationStateSpace or None
    """

    model: object
    hydro: PlatformHydrodynamics
    mooring: MooringSystem | None = None
    radiation: RadiationStateSpace | None = None

    def __post_init__(self) -> None:
        eom = self.model.eom
        missing = [c for c in _PLATFORM if c not in eom.coordinates] + [u for u in _INPUTS if u not in eom.inputs]
        if missing:
            raise ModelDefinitionError(f"the structural model lacks {missing}: enable all six platform DOFs "
                                       "(PtfmSgDOF … PtfmYDOF) in the deck or in TurbineModel(dofs=…).")

    @property
    def n_radiation(self) -> int:
        return 0 if self.radiation is None else self.radiation.n_states

    def rhs(self) -> ca.Function:
        """``x → ẋ`` (SX), the deck's parameter values bound, other structural inputs zero."""
        eom = self.model.eom
        n, nr = eom.n_q, self.n_radiation
        index = [eom.coordinates.index(c) for c in _PLATFORM]
        x = ca.SX.sym("x", 2 * n + nr)
        q, qd, xr = x[:n], x[n:2 * n], x[2 * n:]
        qp, vp = ca.vertcat(*[q[i] for i in index]), ca.vertcat(*[qd[i] for i in index])
        load = self.hydro.hydrostatics.load(qp) + self.hydro.additional.load(qp, vp)
        line_mass = ca.SX.zeros(6, 6)
        if self.mooring is not None:
            static, drag, line_mass, _ = self.mooring.line_loads(qp, vp)
            load = load + static + drag
        if self.radiation is not None:
            load = load + ca.mtimes(ca.sparsify(ca.DM(self.radiation.C)), xr)
        u = [0.0] * eom.n_u
        for k, name in enumerate(_INPUTS):
            u[eom.inputs.index(name)] = load[k]
        u = ca.vertcat(*u)
        p = ca.DM(eom.parameter_vector())
        f_m = eom.functions.mass_matrix
        select = np.zeros((6, n))
        select[range(6), index] = 1.0
        S = ca.DM(select)
        M = (f_m(q, p) if f_m.n_in() == 2 else f_m(q, u, p)) + ca.mtimes([S.T, ca.DM(self.hydro.added_mass) + line_mass, S])
        qdd = ca.solve(M, eom.functions.forcing(q, qd, u, p))
        parts = [qd, qdd]
        if self.radiation is not None:
            parts.append(ca.mtimes(ca.sparsify(ca.DM(self.radiation.A)), xr)
                         + ca.mtimes(ca.sparsify(ca.DM(self.radiation.B)), vp))
        return ca.Function("floating_rhs", [x], [ca.vertcat(*parts)], ["x"], ["xd"])

    def initial_state(self) -> np.ndarray:
        """The deck's initial q and q̇ (``TurbineModel.default_state``), radiation states 0."""
        x0 = np.asarray(self.model.default_state(), dtype=float)
        return np.concatenate([x0, np.zeros(self.n_radiation)])

    def simulate(self, t_end: float, dt: float, x0=None) -> tuple[np.ndarray, np.ndarray]:
        """Fixed-step RK4 from ``x0`` (default :meth:`initial_state`): times [s] and states (columns)."""
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
