"""The periodic operating point of a blade-element turbine, and exact Jacobians at its azimuths.

With blade-element aerodynamics the operating state in steady wind is periodic, not constant:
gravity, the shaft tilt, the cone and the shear load each blade differently around the
revolution. :func:`periodic_point` finds that periodic state as OpenFAST's ``CalcSteady``
does — converge on the state one revolution apart — with held commands (pitch and generator
torque from the rotor-effective trim of the same deck, or given):

1. start from the deck's initial conditions with the commanded pitch and torque, the given
   rotor speed and tower deflection, and every node's dynamic wake at equilibrium
   (:meth:`~mbsym.wind.operation.OperatingTurbine.initial_state`); run ``warmup`` revolutions;
2. one revolution is RK4 with a fixed number of steps (a multiple of the number of azimuths,
   so that the samples are equally spaced); the state where blade 1 is back at its starting
   azimuth (a Poincaré section) minus the starting state is the residual;
3. the lightly damped modes (blade edge, tower side-side) and the rotor speed (held torque and
   pitch: it settles with the aerodynamic torque slope) would take minutes of simulated time to
   decay, so the start is corrected by a chord-Newton step: the monodromy of the periodic
   system is taken as ``exp(Ā T)`` of the azimuth-averaged model in multi-blade coordinates
   (the model :mod:`.blade_linear` returns, azimuth left out), computed once at the first
   revolution: ``δx₀ = -T_x (exp(Ā T) - I)⁻¹ T_x⁻¹ r`` (``T_x`` the multi-blade transformation
   at the section). Each step costs one revolution; the linear rate is the mismatch between
   the true monodromy and ``exp(Ā T)``.

The residual is reported per state and as ``max |r_i| / s_i`` with ``s_i`` the largest
``|x_i|`` over the revolution (at least :data:`RESIDUAL_FLOOR`).

:func:`azimuth_jacobians` gives ``A, B, C, D`` of ``ẋ = f(x, u, p)``, ``y = h(x, u, p)`` at the
sampled states, exact (CasADi AD of the same graph) and cheap: the dynamic-wake states of one
node act on their own rows only, so the rows other than the structural accelerations are
obtained by forward sweeps with compressed seeds (one per colour of the columns, ~50 instead
of ~265) and the dense rows (accelerations, outputs) by reverse sweeps, all azimuths in one
mapped call.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Mapping, Sequence

import casadi as ca
import numpy as np
from scipy.linalg import expm

from ...exceptions import ModelDefinitionError, ParameterError

__all__ = ["PeriodicPoint", "periodic_point", "azimuth_jacobians", "RESIDUAL_FLOOR"]

#: Directions per forward AD call (fewer calls of CasADi's virtual machine; more build time).
FORWARD_DIRECTIONS = 8
#: Threads of the mapped evaluation over the azimuths.
MAP_THREADS = 2
#: Smallest scale [state units] of a state in the relative residual.
RESIDUAL_FLOOR = 1e-6
_START_KEYS = {"pitch": "rad", "torque": "N m (high-speed shaft)", "rotor_speed": "rad/s", "tower_fa": "m"}


@dataclass(frozen=True)
class PeriodicPoint:
    """A periodic operating point of a blade-element turbine (module docstring).

    Attributes
    ----------
    wind : mapping
        The wind inputs by name (InflowWind's uniform-wind columns, SI).
    commands : mapping
        The held commands (``BlPitchCom`` or ``BlPitchCom1..3`` [rad], ``GenTqCom`` [N m]).
    inputs : ndarray (n_u,)
        The model's input vector.
    parameters : mapping
        Parameter values by name.
    states : ndarray (n_azimuth, n_x)
        The states at ``n_azimuth`` equally spaced instants of the last revolution (the first
        at the section).
    blade_azimuths : ndarray (n_azimuth,)
        Blade-1 azimuth of each sample [rad] (ElastoDyn's ``Azimuth``, unwrapped).
    rotor_speed : float
        Mean rotor speed over the revolution [rad/s].
    period : float
        Duration of the revolution [s].
    residual : ndarray (n_x,)
        State one revolution later minus the state at the section.
    residual_norm : float
        ``max |r_i| / s_i`` (module docstring).
    converged : bool
        ``residual_norm <= tol``.
    iterations, revolutions : int
        Newton steps taken, revolutions simulated in all.
    state_names, input_names : tuple of str
    seconds : float
        Wall time [s].
    """

    wind: Mapping[str, float]
    commands: Mapping[str, float]
    inputs: np.ndarray
    parameters: Mapping[str, float]
    states: np.ndarray
    blade_azimuths: np.ndarray
    rotor_speed: float
    period: float
    residual: np.ndarray
    residual_norm: float
    converged: bool
    iterations: int
    revolutions: int
    state_names: tuple[str, ...]
    input_names: tuple[str, ...]
    seconds: float = 0.0
    history: tuple[float, ...] = field(default=(), repr=False)

    def mean(self, state: str) -> float:
        """Mean of a state over the samples."""
        return float(np.mean(self.states[:, self.state_names.index(state)]))

    def __repr__(self) -> str:
        wind = ", ".join(f"{k}={v:g}" for k, v in self.wind.items() if v)
        return (f"PeriodicPoint({wind}; {self.rotor_speed * 30 / math.pi:.4g} rpm, residual {self.residual_norm:.2e} "
                f"after {self.revolutions} revolutions ({self.iterations} Newton steps), "
                f"{'converged' if self.converged else 'NOT converged'})")


def periodic_point(model, wind: "float | Mapping[str, float]", *, start, n_azimuth: int = 12,
                   steps_per_revolution: int = 240, tol: float = 1e-4, max_revolutions: int = 12,
                   warmup: int = 1, newton: bool = True, p: Mapping[str, float] | None = None,
                   compile: bool = True) -> PeriodicPoint:
    """The periodic steady state of a blade-element turbine with held commands (module docstring).

    Parameters
    ----------
    model : OperatingTurbine
        ``aero="blade"`` with uniform-wind inputs and GenDOF on.
    wind : float or dict
        Hub-height wind ``Wind1VelX`` [m/s], or uniform-wind inputs by name (e.g.
        ``{"Wind1VelX": 14.0, "VShrExp": 0.2}``; the others keep their defaults).
    start : TrimPoint or dict, keyword-only
        A trim of the rotor-effective model of the same deck (:func:`mbsym.wind.operation.trim`:
        its pitch, generator torque, rotor speed and tower-top deflection), or a dict with
        ``pitch`` [rad], ``torque`` [N m, high-speed shaft], ``rotor_speed`` [rad/s] and optionally
        ``tower_fa`` [m]. Pitch and torque are held; the rotor speed is where the search starts.
    n_azimuth : int, keyword-only
        Samples per revolution (default 12).
    steps_per_revolution : int, keyword-only
        RK4 steps per revolution (rounded up to a multiple of ``n_azimuth``); default 240
        (20 ms at 12 rpm).
    tol : float, keyword-only
        Relative residual to stop at (default 1e-4).
    max_revolutions : int, keyword-only
        Revolutions to simulate at most (warm-up included).
    warmup : int, keyword-only
        Plain revolutions before the first Newton step (default 1).
    newton : bool, keyword-only
        Chord-Newton steps (default); False: plain revolutions, as CalcSteady without trim.
    p : dict, optional, keyword-only
        Parameter values by name.
    compile : bool, keyword-only
        Compile the RK4 step (default; ~25 s once, then disk-cached, against ~7 s per revolution in CasADi's
        virtual machine); False or no working compiler: the virtual machine.

    Returns
    -------
    PeriodicPoint
        ``converged`` False when ``max_revolutions`` were not enough (the residual says how far).

    Raises
    ------
    ModelDefinitionError
        Not a blade-element model with uniform wind and a free rotor.
    ParameterError
        Bad ``start``, ``wind`` or numbers.
    """
    t0 = time.perf_counter()
    dyn = model.dynamics()
    _check_model(model)
    for name, value, low in (("n_azimuth", n_azimuth, 3), ("steps_per_revolution", steps_per_revolution, 12),
                             ("max_revolutions", max_revolutions, 1), ("warmup", warmup, 0)):
        if not isinstance(value, (int, np.integer)) or value < low:
            raise ParameterError(f"{name} must be an integer >= {low}; got {value!r}.")
    if not (isinstance(tol, float) and tol > 0):
        raise ParameterError(f"tol must be a positive float; got {tol!r}.")
    wind_in = _wind_inputs(model, wind)
    s = _start_values(start)
    commands = {c: s["pitch"] for c in model.command_names if c != "GenTqCom"}
    commands["GenTqCom"] = s["torque"]
    x = model.initial_state(wind_in, rotor_speed=s["rotor_speed"], pitch=s["pitch"], torque=s["torque"],
                            tower_fa=s.get("tower_fa"), p=p)
    u = dyn.input_vector({**wind_in, **commands})
    pv = dyn.parameter_vector(p)
    ia, iw = dyn.states.index("GeAz"), dyn.states.index("GeAz_d")
    m = -(-int(steps_per_revolution) // int(n_azimuth))
    n_steps = m * int(n_azimuth)
    rev = _revolution_function(dyn, n_steps, compile)
    period = 2 * math.pi / x[iw]
    chord = None
    history: list[float] = []
    revolutions = iterations = 0
    while True:
        X = np.asarray(rev(x, u, pv, period / n_steps), dtype=float)
        revolutions += 1
        traj = np.column_stack([x, X[:, :-1]])
        end = X[:, -1]
        turned = end[ia] - x[ia]
        xd_end = np.asarray(dyn.rhs(end, u, pv), dtype=float).reshape(-1)
        section = end - xd_end * (turned - 2 * math.pi) / xd_end[ia]
        r = section - x
        r[ia] = 0.0
        scale = np.maximum(np.max(np.abs(traj), axis=1), RESIDUAL_FLOOR)
        norm = float(np.max(np.abs(r) / scale))
        history.append(norm)
        period *= 2 * math.pi / turned
        samples = traj[:, ::m].T.copy()
        done = norm <= tol or revolutions >= max_revolutions
        if done:
            break
        if not newton or revolutions <= warmup:
            x = section
            x[ia] = samples[0, ia]
            continue
        if chord is None:
            chord = _chord(model, samples, u, pv, period)
        x = x + chord(x, r)
        iterations += 1
    frame = model.structure.rotating_frame()
    psi = np.asarray(frame.azimuths(samples[:, ia], samples[:, :model.structure.eom.n_q]), dtype=float)
    names = tuple(dyn.parameters)
    return PeriodicPoint(MappingProxyType(dict(wind_in)), MappingProxyType(dict(commands)), u,
                         MappingProxyType(dict(zip(names, pv.tolist()))), samples, psi,
                         float(2 * math.pi / period), float(period), r, norm, norm <= tol, iterations, revolutions,
                         tuple(dyn.states), tuple(dyn.inputs), time.perf_counter() - t0, tuple(history))


def _check_model(model) -> None:
    if getattr(model, "aero", None) != "blade":
        raise ModelDefinitionError("periodic operating points are for blade-element turbines "
                                   "(OperatingTurbine.from_openfast(fst, aero='blade')); the rotor-effective model has "
                                   "a constant operating point (mbsym.wind.operation.trim).")
    if "WindTime" in model.wind.inputs:
        raise ModelDefinitionError("a periodic operating point needs steady wind: the model carries a full field "
                                   "(WindTime input); build it with uniform wind (wind=UniformWindInputs(...)).")
    if not model.spins_freely:
        raise ModelDefinitionError("a periodic operating point needs the rotor speed as a DOF (GenDOF on); the model "
                                   "turns at a prescribed speed.")
    if model.turbine.number_of_blades != 3:
        raise ModelDefinitionError(f"multi-blade coordinates need 3 blades; the deck has "
                                   f"{model.turbine.number_of_blades}.")


def _wind_inputs(model, wind) -> dict[str, float]:
    values = dict(model.wind.defaults) if hasattr(model.wind, "defaults") else {}
    if isinstance(wind, Mapping):
        unknown = sorted(set(wind) - set(model.wind.inputs))
        if unknown:
            raise ParameterError(f"unknown wind inputs {unknown}; the model's are {list(model.wind.inputs)}.")
        values.update({k: float(v) for k, v in wind.items()})
    else:
        values["Wind1VelX"] = float(wind)
    if not (np.isfinite(values.get("Wind1VelX", np.nan)) and values["Wind1VelX"] > 0):
        raise ParameterError(f"the hub wind Wind1VelX must be a positive number [m/s]; got {values.get('Wind1VelX')!r}.")
    return values


def _start_values(start) -> dict[str, float]:
    if hasattr(start, "x") and hasattr(start, "success"):          # a TrimPoint of the rotor-effective model
        if not start.success:
            raise ParameterError(f"the start point is a failed trim ({start.message}).")
        x = start.x()
        if "GeAz_d" not in x:
            raise ParameterError("the start trim has no rotor-speed state GeAz_d (GenDOF off); give a dict instead.")
        return {"pitch": float(x["BlPitch"]), "torque": float(x["GenTq"]), "rotor_speed": float(x["GeAz_d"]),
                "tower_fa": float(start["TTDspFA"]) if "TTDspFA" in start.channels else None}
    if not isinstance(start, Mapping):
        raise ParameterError(f"start must be a TrimPoint or a dict with keys {list(_START_KEYS)}; got "
                             f"{type(start).__name__}.")
    unknown = sorted(set(start) - set(_START_KEYS))
    missing = [k for k in ("pitch", "torque", "rotor_speed") if k not in start]
    if unknown or missing:
        raise ParameterError(f"start: unknown keys {unknown}, missing {missing}; expected "
                             f"{ {k: u for k, u in _START_KEYS.items()} }.")
    out = {k: float(v) for k, v in start.items()}
    if not (out["rotor_speed"] > 0 and all(np.isfinite(list(out.values())))):
        raise ParameterError(f"start values must be finite with rotor_speed > 0 [rad/s]; got {out}.")
    out.setdefault("tower_fa", None)
    return out


def _revolution_function(dyn, n_steps: int, compile: bool = True) -> ca.Function:
    """``(x0, u, p, h) -> X (n_x, n_steps)``: RK4 with constant inputs (cached on the Dynamics). The step is
    compiled when ``compile`` and a compiler works (disk-cached; the blade-element right-hand side costs ~7 ms
    in CasADi's virtual machine, ~0.2 ms compiled: a revolution of 240 steps 7 s against 0.2 s)."""
    from ...simulate.base import maybe_compile

    cache = dyn.__dict__.setdefault("_mbsym_revolution", {})
    if (n_steps, compile) not in cache:
        x, u, p, h = ca.MX.sym("x", dyn.n_x), ca.MX.sym("u", dyn.n_u), ca.MX.sym("p", dyn.n_p), ca.MX.sym("h")
        k1 = dyn.rhs(x, u, p)
        k2 = dyn.rhs(x + h / 2 * k1, u, p)
        k3 = dyn.rhs(x + h / 2 * k2, u, p)
        k4 = dyn.rhs(x + h * k3, u, p)
        step = ca.Function(f"{dyn.name}_rk4_step", [x, u, p, h], [x + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)])
        step, _ = maybe_compile(step, compile)
        cache[(n_steps, compile)] = step.mapaccum("revolution", n_steps)
    return cache[(n_steps, compile)]


def _chord(model, samples: np.ndarray, u: np.ndarray, pv: np.ndarray, period: float):
    """The Newton correction ``r -> δx₀`` from the azimuth-averaged model at the samples (module docstring, 3)."""
    from .blade_linear import mbc_average

    dyn = model.dynamics()
    jac = azimuth_jacobians(dyn, samples, u, pv, outputs=())
    frame = model.structure.rotating_frame()
    ia = dyn.states.index("GeAz")
    psi = np.asarray(frame.azimuths(samples[:, ia], samples[:, :model.structure.eom.n_q]), dtype=float)
    omega = 2 * math.pi / period
    avg = mbc_average(jac, dyn.states, dyn.inputs, (), psi, omega, keep_azimuth=True)
    keep = [i for i in range(dyn.n_x) if i != ia]
    A = avg["A"][np.ix_(keep, keep)]
    M = expm(A * period) - np.eye(len(keep))
    lu = np.linalg.inv(M)
    T, _ = avg["T_at"](psi[0])

    def correction(x, r):
        rz = np.linalg.solve(T, r)
        dz = np.zeros_like(rz)
        dz[keep] = -lu @ rz[keep]
        return T @ dz

    return correction


# ---------------------------------------------------------------------- Jacobians
def azimuth_jacobians(dyn, X, u, p, *, outputs: Sequence[str] = ()) -> dict:
    """Exact ``A, B, C, D`` of a Dynamics at several states (module docstring).

    Parameters
    ----------
    dyn : Dynamics
    X : array (n_s, n_x)
        The states.
    u : array (n_u,)
        The inputs (the same at every state).
    p : array (n_p,)
        Parameter vector.
    outputs : sequence of str, keyword-only
        Output channels for ``C``, ``D``.

    Returns
    -------
    dict
        ``A`` (n_s, n_x, n_x), ``B`` (n_s, n_x, n_u), ``C`` (n_s, n_y, n_x), ``D`` (n_s, n_y, n_u),
        ``xd`` (n_s, n_x), ``y`` (n_s, n_y).
    """
    X = np.atleast_2d(np.asarray(X, dtype=float))
    names = tuple(outputs)
    unknown = [n for n in names if n not in dyn.output_names]
    if unknown:
        raise ParameterError(f"unknown output channels {unknown}; the model has {list(dyn.output_names)}.")
    J = _CompressedJacobian.of(dyn, names)
    return J(X, np.asarray(u, dtype=float), np.asarray(p, dtype=float))


class _CompressedJacobian:
    """Compressed forward and reverse AD sweeps of ``(x, u) -> (ẋ, y)`` (module docstring)."""

    @classmethod
    def of(cls, dyn, names: tuple[str, ...]) -> "_CompressedJacobian":
        cache = dyn.__dict__.setdefault("_mbsym_compressed_jacobian", {})
        if names not in cache:
            cache[names] = cls(dyn, names)
        return cache[names]

    def __init__(self, dyn, names: tuple[str, ...]) -> None:
        nx, nu = dyn.n_x, dyn.n_u
        self.nx, self.nu, self.ny = nx, nu, len(names)
        x, u, p = ca.MX.sym("x", nx), ca.MX.sym("u", nu), ca.MX.sym("p", dyn.n_p)
        xd = dyn.rhs(x, u, p)
        y = dyn.outputs(x, u, p)[[dyn.output_names.index(n) for n in names]] if names else ca.MX(0, 1)
        W = ca.Function("w", [x, u, p], [xd, y])
        z = ca.vertcat(x, u)
        e = W(z[:nx], z[nx:], p)
        S = ca.jacobian_sparsity(ca.vertcat(e[0], e[1]), z)
        pattern = np.asarray(ca.DM(S, 1), dtype=float) != 0
        dense = pattern.sum(axis=1) > (nx + nu) // 4                                   # e.g. the accelerations
        dense[nx:] = True                                                             # outputs: reverse
        self.rev_rows = np.flatnonzero(dense)
        fwd_rows = np.flatnonzero(~dense)
        rows, cols = np.nonzero(pattern[fwd_rows])
        S_f = ca.Sparsity.triplet(fwd_rows.size, nx + nu, rows.tolist(), cols.tolist())
        coloring = S_f.uni_coloring()
        self.n_colors = coloring.size2()
        seed = np.asarray(ca.DM(coloring, 1), dtype=float)
        self.color = np.argmax(seed, axis=1)
        self.f_rows, self.f_cols = fwd_rows[rows], cols
        Wx = ca.Function("wx", [x, u, p], [xd])
        Wy = ca.Function("wy", [x, u, p], [y])
        nf = min(FORWARD_DIRECTIONS, max(self.n_colors, 1))
        self.n_calls = -(-max(self.n_colors, 1) // nf)
        seed = np.hstack([seed, np.zeros((nx + nu, self.n_calls * nf - self.n_colors))])
        sf = ca.DM(seed)
        df = Wx.forward(nf).map(self.n_calls)(x, u, p, xd, sf[:nx, :], sf[nx:, :], ca.DM.zeros(dyn.n_p, nf))
        acc = self.rev_rows[self.rev_rows < nx]
        adj = np.zeros((nx, max(acc.size, 1)))
        adj[acc, np.arange(acc.size)] = 1.0
        dr = Wx.reverse(1).map(adj.shape[1])(x, u, p, xd, ca.DM(adj))
        rev_blocks = [ca.vertcat(dr[0], dr[1])]
        if self.ny:
            dy = Wy.reverse(1).map(self.ny)(x, u, p, y, ca.DM.eye(self.ny))
            rev_blocks.append(ca.vertcat(dy[0], dy[1]))
        self.function = ca.Function("compressed_jacobian", [x, u, p], [xd, y, df, ca.horzcat(*rev_blocks)])
        self._maps: dict[int, ca.Function] = {}

    def __call__(self, X: np.ndarray, u: np.ndarray, p: np.ndarray) -> dict:
        n_s, nx, nu, ny = X.shape[0], self.nx, self.nu, self.ny
        if n_s not in self._maps:
            self._maps[n_s] = self.function.map(n_s, "thread", MAP_THREADS)
        xd, y, F, R = (np.asarray(v, dtype=float) for v in self._maps[n_s](X.T, u, p))
        nc = F.shape[1] // n_s
        acc = self.rev_rows[self.rev_rows < nx]
        nr = R.shape[1] // n_s
        J = np.zeros((n_s, nx + ny, nx + nu))
        for k in range(n_s):
            Fk, Rk = F[:, k * nc:(k + 1) * nc], R[:, k * nr:(k + 1) * nr]
            J[k, self.f_rows, self.f_cols] = Fk[self.f_rows, self.color[self.f_cols]]
            J[k, acc, :] = Rk[:, :acc.size].T
            J[k, nx:, :] = Rk[:, nr - ny:].T
        return {"A": J[:, :nx, :nx], "B": J[:, :nx, nx:], "C": J[:, nx:, :nx], "D": J[:, nx:, nx:],
                "xd": xd.reshape(nx, n_s).T, "y": y.reshape(ny, n_s).T if ny else np.zeros((n_s, 0))}
