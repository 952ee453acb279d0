"""Discrete-time estimation models and the Kalman-type filters ``EKF`` and ``UKF``.

An :class:`EstimationModel` augments a model for estimation: the state estimated
is ``z = [x; d; θ]`` with ``x`` the model state, ``d`` *unknown inputs* modelled
as random walks (``d⁺ = d`` plus process noise, e.g. a rotor-effective wind
speed) and ``θ`` *estimated parameters* (constant, optional random walk). The
other inputs are *known* (measured or commanded) and given at every step. One
sample is the RK4 map of the model over ``dt`` (zero-order hold of the inputs);
the measurements are model outputs or states by name.

Timing convention of ``step(y, u)`` (EKF, UKF, MHE): ``y`` is measured at the
current sample time ``t_k``; ``u`` are the known inputs held over the interval
that just ended, ``[t_{k-1}, t_k)``; they are also used in the measurement
equation (feedthrough). The first call only corrects the prior with ``y``.
"""

from __future__ import annotations

from typing import Any, Mapping, Sequence

import casadi as ca
import numpy as np

from ..dynamics import Dynamics, as_dynamics
from ..exceptions import ControlDefinitionError, DimensionError
from ._checks import check_names, finite_number, vector
from .discretize import discretize, symbolic_function

__all__ = ["EstimationModel", "EKF", "UKF", "noise_matrix"]


def noise_matrix(value: Any, names: Sequence[str], what: str, *, allow_zero: bool = True) -> np.ndarray:
    """A covariance matrix from standard deviations by name (dict; missing: 0) or an n×n matrix.

    Raises
    ------
    ControlDefinitionError
        Unknown names, negative or non-finite values, a non-symmetric or indefinite matrix.
    """
    n = len(names)
    if isinstance(value, Mapping):
        unknown = sorted(set(value) - set(names))
        if unknown:
            raise ControlDefinitionError(f"{what}: unknown names {unknown}; expected names from {list(names)}.")
        std = np.array([finite_number(value.get(k, 0.0), f"{what} of {k!r}", nonnegative=True) for k in names])
        if not allow_zero and np.any(std == 0):
            zero = [k for k, s in zip(names, std) if s == 0]
            raise ControlDefinitionError(f"{what} must be > 0 for every entry; {zero} are 0 or missing.")
        return np.diag(std ** 2)
    try:
        M = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise ControlDefinitionError(f"{what} must be a dict of standard deviations or a matrix; got {value!r}.") \
            from None
    if M.shape != (n, n) or not np.all(np.isfinite(M)):
        raise ControlDefinitionError(f"{what} must be a finite {n}×{n} covariance matrix (order {list(names)}); "
                                     f"got shape {M.shape}.")
    if not np.allclose(M, M.T, atol=1e-12 * max(1.0, np.abs(M).max())):
        raise ControlDefinitionError(f"{what} must be symmetric.")
    lam = np.linalg.eigvalsh(M)
    if lam.min() < -1e-12 * max(1.0, lam.max()) or (not allow_zero and lam.min() <= 0):
        need = "positive definite" if not allow_zero else "positive semi-definite"
        raise ControlDefinitionError(f"{what} must be {need}; smallest eigenvalue {lam.min():.3g}.")
    return 0.5 * (M + M.T)


class EstimationModel:
    """A model augmented with random-walk unknown inputs and estimated parameters, in discrete time.

    Parameters
    ----------
    model : Dynamics, EquationsOfMotion or model object
    dt : float, keyword-only
        Sample time [s].
    measurements : sequence of str, keyword-only
        Output or state names (outputs first when a name is both).
    unknown_inputs : sequence of str, keyword-only
        Inputs estimated as random-walk states.
    parameters : sequence of str, keyword-only
        Parameters estimated as constant states.
    p : dict, optional, keyword-only
        Values of the other parameters (model defaults fill the gaps).
    substeps : int, keyword-only
        RK4 sub-steps per sample.
    compile : bool, keyword-only
        Compile the linearization to C (codegen cache; default False). An EKF step
        evaluates the linearization twice; compiled, a 9-state turbine model's costs 0.1 ms instead
        of about 1 ms in CasADi's virtual machine.

    Attributes
    ----------
    names : tuple of str
        Names of ``z``: states, then unknown inputs, then estimated parameters.
    known_inputs : tuple of str
    step_function : casadi.Function
        ``(z, u_known, p_rest) -> z_next``.
    measurement_function : casadi.Function
        ``(z, u_known, p_rest) -> y``.
    step_jacobian : casadi.Function or None
        ``(z, u_known, p_rest) -> (z_next, ∂z_next/∂z)`` from chained RK4 sensitivities (MX calling the rhs
        and its Jacobian) when the right-hand side is large (:data:`mbsym.control.discretize.CHAIN_THRESHOLD`)
        and no parameter is estimated; else None (the Jacobian of the expanded step is used).
    """

    def __init__(self, model: Any, *, dt: float, measurements: Sequence[str], unknown_inputs: Sequence[str] = (),
                 parameters: Sequence[str] = (), p: Mapping[str, float] | None = None, substeps: int = 1,
                 compile: bool = False) -> None:
        dyn: Dynamics = as_dynamics(model)
        self.dynamics = dyn
        self.dt = finite_number(dt, "dt [s]", positive=True)
        self.unknown_inputs = check_names(unknown_inputs, dyn.inputs, "unknown_inputs")
        self.estimated_parameters = check_names(parameters, dyn.parameters, "parameters")
        self.known_inputs = tuple(n for n in dyn.inputs if n not in self.unknown_inputs)
        self.fixed_parameters = tuple(n for n in dyn.parameters if n not in self.estimated_parameters)
        if isinstance(measurements, str):
            measurements = measurements.split()
        self.measurements = tuple(measurements)
        if not self.measurements:
            raise ControlDefinitionError("measurements must name at least one output or state.")
        check_names(self.measurements, tuple(dyn.output_names) + tuple(dyn.states), "measurements")
        self.names = tuple(dyn.states) + self.unknown_inputs + self.estimated_parameters
        start = {n: 0.0 for n in self.estimated_parameters if n not in dyn.defaults}   # initial guesses only
        pv = dyn.parameter_vector({**start, **dict(p or {})})
        self.p_rest = pv[[dyn.parameters.index(n) for n in self.fixed_parameters]]
        self._p_full = pv
        self._build(substeps)
        self._compiled = False
        self._job = None
        if compile:                  # numeric use only (the filters); compiled in the background until first use
            from ..codegen_async import compile_async

            self._job = compile_async(self._linearization)

    @property
    def linearization(self) -> ca.Function:
        """``(z, u_known, p_rest) -> (z_next, F, y, H)``; compiled when asked (waits for the compilation)."""
        if self._job is not None:
            c = self._job.result()
            self._job = None
            self._linearization, self._compiled = c.function, c.compiled
        return self._linearization

    @property
    def compiled(self) -> bool:
        """Whether :attr:`linearization` runs compiled C."""
        return self.linearization is not None and self._compiled

    @property
    def n_z(self) -> int:
        return len(self.names)

    @property
    def n_y(self) -> int:
        return len(self.measurements)

    def _build(self, substeps: int) -> None:
        dyn = self.dynamics
        disc = discretize(dyn.rhs, self.dt, method="rk4", substeps=substeps)
        sym = disc.sym
        if dyn.outputs is not None and symbolic_function(dyn.outputs)[1] is ca.MX:
            sym = ca.MX
        z = sym.sym("z", self.n_z)
        uk = sym.sym("u", len(self.known_inputs))
        pr = sym.sym("p", len(self.fixed_parameters))
        x = z[: dyn.n_x]
        d = z[dyn.n_x: dyn.n_x + len(self.unknown_inputs)]
        th = z[dyn.n_x + len(self.unknown_inputs):]
        u = ca.vertcat(*[d[self.unknown_inputs.index(n)] if n in self.unknown_inputs else
                         uk[self.known_inputs.index(n)] for n in dyn.inputs]) if dyn.n_u else sym(0, 1)
        p = ca.vertcat(*[th[self.estimated_parameters.index(n)] if n in self.estimated_parameters else
                         pr[self.fixed_parameters.index(n)] for n in dyn.parameters]) if dyn.n_p else sym(0, 1)
        z_next = ca.vertcat(disc.step(x, sym(0, 1), u, p), d, th)
        y_all = dyn.outputs(x, u, p) if dyn.outputs is not None else sym(0, 1)
        y = ca.vertcat(*[y_all[dyn.output_names.index(n)] if n in dyn.output_names else x[dyn.states.index(n)]
                         for n in self.measurements])
        self.step_function = ca.Function("estimation_step", [z, uk, pr], [z_next], ["z", "u", "p"], ["z_next"])
        self.measurement_function = ca.Function("measurement", [z, uk, pr], [y], ["z", "u", "p"], ["y"])
        self.step_jacobian = self._chained_step_jacobian(disc)
        if self.step_jacobian is None:
            self._linearization = ca.Function("estimation_linearization", [z, uk, pr],
                                              [z_next, ca.jacobian(z_next, z), y, ca.jacobian(y, z)],
                                              ["z", "u", "p"], ["z_next", "F", "y", "H"])
        else:            # the RK4 step's Jacobian from chained sensitivities: one copy of the rhs Jacobian in C
            meas = ca.Function("measurement_jacobian", [z, uk, pr], [y, ca.densify(ca.jacobian(y, z))])
            zm, um, pm = (ca.MX.sym(s, n) for s, n in (("z", self.n_z), ("u", uk.numel()), ("p", pr.numel())))
            zn, F = self.step_jacobian(zm, um, pm)
            ym, H = meas(zm, um, pm)
            self._linearization = ca.Function("estimation_linearization", [zm, um, pm], [zn, F, ym, H],
                                              ["z", "u", "p"], ["z_next", "F", "y", "H"])

    def _chained_step_jacobian(self, disc) -> ca.Function | None:
        """``(z, u, p) -> (z_next, ∂z_next/∂z)`` from the RK4 sensitivities (MX glue), or None.

        None when the discretization has no chained sensitivities (small right-hand sides: automatic
        differentiation of the expanded step is small too) or parameters are estimated (the chained
        sensitivities do not differentiate with respect to parameters). For the 7-state turbine estimation model
        the expanded Jacobian had 95 000 SX instructions (7.7 MB of C, 90 s of gcc -O1); chained, one copy of
        the rhs Jacobian.
        """
        dyn = self.dynamics
        if disc.sensitivity is None or self.estimated_parameters:
            return None
        nx, nd = dyn.n_x, len(self.unknown_inputs)
        z = ca.MX.sym("z", self.n_z)
        uk, pr = ca.MX.sym("u", len(self.known_inputs)), ca.MX.sym("p", len(self.fixed_parameters))
        x, d = z[:nx], z[nx:nx + nd]
        u = ca.vertcat(*[d[self.unknown_inputs.index(n)] if n in self.unknown_inputs else
                         uk[self.known_inputs.index(n)] for n in dyn.inputs]) if dyn.n_u else ca.MX(0, 1)
        p = ca.vertcat(*[pr[self.fixed_parameters.index(n)] for n in dyn.parameters]) if dyn.n_p else ca.MX(0, 1)
        x_next, Sx, Su = disc.sensitivity(x, u, p)
        cols = [Su[:, dyn.inputs.index(n)] for n in self.unknown_inputs]
        top = ca.horzcat(Sx, *cols) if cols else Sx
        F = ca.vertcat(top, ca.horzcat(ca.MX(nd, nx), ca.MX.eye(nd))) if nd else top
        return ca.Function("estimation_step_jacobian", [z, uk, pr], [ca.vertcat(x_next, d), ca.densify(F)],
                           ["z", "u", "p"], ["z_next", "F"])

    def known_input_vector(self, u) -> np.ndarray:
        """Known inputs as an array: None (model nominal values), a dict by name, or numbers in order."""
        dyn = self.dynamics
        nominal = dyn.u0[[dyn.inputs.index(n) for n in self.known_inputs]]
        if u is None:
            return nominal
        if isinstance(u, Mapping):
            unknown = sorted(set(u) - set(self.known_inputs))
            if unknown:
                raise DimensionError(f"u names unknown entries {unknown}; known inputs are {list(self.known_inputs)}.")
            out = nominal.copy()
            for i, n in enumerate(self.known_inputs):
                if n in u:
                    out[i] = vector([u[n]], 1, f"u[{n!r}]")[0]
            return out
        return vector(u, len(self.known_inputs), "u (known inputs)", self.known_inputs)

    def measurement_vector(self, y) -> np.ndarray:
        """Measurements as an array: a dict by name or numbers in the order of :attr:`measurements`."""
        if isinstance(y, Mapping):
            missing = [n for n in self.measurements if n not in y]
            extra = sorted(set(y) - set(self.measurements))
            if missing or extra:
                raise DimensionError(f"y must give every measurement {list(self.measurements)}; missing {missing}, "
                                     f"unknown {extra}.")
            y = [y[n] for n in self.measurements]
        return vector(y, self.n_y, "y (measurements)", self.measurements)

    def state_vector(self, z, what: str = "x0") -> np.ndarray:
        """``z`` from numbers (order :attr:`names`) or a dict (model defaults, nominal inputs, parameter values)."""
        dyn = self.dynamics
        default = np.concatenate([dyn.x0, dyn.u0[[dyn.inputs.index(n) for n in self.unknown_inputs]],
                                  self._p_full[[dyn.parameters.index(n) for n in self.estimated_parameters]]])
        if z is None:
            return default
        if isinstance(z, Mapping):
            unknown = sorted(set(z) - set(self.names))
            if unknown:
                raise DimensionError(f"{what} names unknown entries {unknown}; expected names from {list(self.names)}.")
            for i, n in enumerate(self.names):
                if n in z:
                    default[i] = vector([z[n]], 1, f"{what}[{n!r}]")[0]
            return default
        return vector(z, self.n_z, what, self.names)


class _Filter:
    """Shared set-up of the EKF and UKF."""

    def __init__(self, model: Any, *, dt: float, measurements: Sequence[str], process_noise: Any,
                 measurement_noise: Any, x0=None, P0=None, unknown_inputs: Sequence[str] = (),
                 parameters: Sequence[str] = (), p: Mapping[str, float] | None = None, substeps: int = 1) -> None:
        self.model = model if isinstance(model, EstimationModel) else EstimationModel(
            model, dt=dt, measurements=measurements, unknown_inputs=unknown_inputs, parameters=parameters, p=p,
            substeps=substeps)
        m = self.model
        self.Q = noise_matrix(process_noise, m.names, "process_noise")
        self.R = noise_matrix(measurement_noise, m.measurements, "measurement_noise", allow_zero=False)
        self.x = m.state_vector(x0)
        self.P = noise_matrix(P0, m.names, "P0") if P0 is not None else np.eye(m.n_z)
        self._first = True
        self.innovation = np.zeros(m.n_y)

    names = property(lambda self: self.model.names, doc="Names of the estimated vector.")

    def estimate(self) -> dict:
        """The current estimate by name."""
        return dict(zip(self.model.names, self.x.tolist()))


class EKF(_Filter):
    """Extended Kalman filter with exact Jacobians (automatic differentiation of the RK4 map).

    Parameters
    ----------
    model : model or EstimationModel
    dt, measurements, unknown_inputs, parameters, p, substeps
        See :class:`EstimationModel`.
    process_noise : dict or array, keyword-only
        Standard deviations per sample by name (missing: 0) or the covariance ``Q`` (n_z × n_z).
    measurement_noise : dict or array, keyword-only
        Standard deviations by measurement name (all > 0) or the covariance ``R``.
    x0 : array or dict, optional, keyword-only
        Prior mean (default: model defaults).
    P0 : dict or array, optional, keyword-only
        Prior standard deviations or covariance (default: identity).

    Examples
    --------
    >>> import casadi as ca, mbsym as mb
    >>> x, u, p = ca.SX.sym("x", 2), ca.SX.sym("u"), ca.SX.sym("p", 0)
    >>> dyn = mb.Dynamics(ca.Function("f", [x, u, p], [ca.vertcat(x[1], u)]), states=["pos", "vel"], inputs=["a"])
    >>> ekf = EKF(dyn, dt=0.1, measurements=["pos"], process_noise={"vel": 0.01}, measurement_noise={"pos": 0.1})
    >>> ekf.step([0.0], [0.0]).shape
    (2,)
    """

    def step(self, y, u=None) -> np.ndarray:
        """Predict over the last interval with ``u`` (not at the first call), correct with ``y``; the estimate."""
        m = self.model
        yv, uv = m.measurement_vector(y), m.known_input_vector(u)
        if not self._first:
            self.predict(uv)
        self._first = False
        self.correct(yv, uv)
        return self.x.copy()

    def predict(self, u) -> None:
        """Time update ``z ← f(z, u)``, ``P ← F P Fᵀ + Q``."""
        zn, F, _, _ = self.model.linearization(self.x, u, self.model.p_rest)
        F = np.asarray(F)
        self.x = np.asarray(zn, dtype=float).reshape(-1)
        self.P = F @ self.P @ F.T + self.Q

    def correct(self, y, u) -> None:
        """Measurement update (Joseph form)."""
        _, _, yh, H = self.model.linearization(self.x, u, self.model.p_rest)
        H = np.asarray(H)
        e = y - np.asarray(yh, dtype=float).reshape(-1)
        S = H @ self.P @ H.T + self.R
        K = np.linalg.solve(S, H @ self.P).T
        I_KH = np.eye(self.model.n_z) - K @ H
        self.x = self.x + K @ e
        self.P = I_KH @ self.P @ I_KH.T + K @ self.R @ K.T
        self.innovation = e


class UKF(_Filter):
    """Unscented Kalman filter (2n+1 sigma points; one mapped CasADi call per transform).

    Same parameters as :class:`EKF`. Sigma-point spread ``α = 1``, ``κ = 0``
    (positive weights) and ``β = 2`` (Gaussian prior).
    """

    ALPHA, BETA, KAPPA = 1.0, 2.0, 0.0

    def __init__(self, *args, **kwargs) -> None:
        super().__init__(*args, **kwargs)
        n = self.model.n_z
        self._lam = self.ALPHA ** 2 * (n + self.KAPPA) - n
        self._wm = np.full(2 * n + 1, 1.0 / (2 * (n + self._lam)))
        self._wm[0] = self._lam / (n + self._lam)
        self._wc = self._wm.copy()
        self._wc[0] += 1.0 - self.ALPHA ** 2 + self.BETA
        self._f_map = self.model.step_function.map(2 * n + 1)
        self._h_map = self.model.measurement_function.map(2 * n + 1)

    def _sigma(self) -> np.ndarray:
        n = self.model.n_z
        L = np.linalg.cholesky((n + self._lam) * self.P + 1e-12 * np.eye(n))
        return np.concatenate([self.x[:, None], self.x[:, None] + L, self.x[:, None] - L], axis=1)

    def step(self, y, u=None) -> np.ndarray:
        """Unscented predict (not at the first call) and correct; the estimate."""
        m = self.model
        yv, uv = m.measurement_vector(y), m.known_input_vector(u)
        pr = m.p_rest
        if not self._first:
            Z = np.asarray(self._f_map(self._sigma(), uv, pr))
            self.x = Z @ self._wm
            dZ = Z - self.x[:, None]
            self.P = (self._wc * dZ) @ dZ.T + self.Q
        self._first = False
        S_pts = self._sigma()
        Y = np.asarray(self._h_map(S_pts, uv, pr)).reshape(m.n_y, -1)
        yh = Y @ self._wm
        dY, dZ = Y - yh[:, None], S_pts - self.x[:, None]
        S = (self._wc * dY) @ dY.T + self.R
        C = (self._wc * dZ) @ dY.T
        K = np.linalg.solve(S, C.T).T
        self.innovation = yv - yh
        self.x = self.x + K @ self.innovation
        self.P = self.P - K @ S @ K.T
        self.P = 0.5 * (self.P + self.P.T)
        return self.x.copy()
