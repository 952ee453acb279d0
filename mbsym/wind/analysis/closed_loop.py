"""Closed-loop linear models: the operating turbine with its baseline controller, about each trim.

At a trimmed operating point (:mod:`mbsym.wind.operation.trim`, the controller's steady laws from its own
settings: :meth:`SteadyControl.from_baseline`) two linear models meet:

* the **plant**: the operating turbine linearized about the trim (:func:`.trim_linear.linearize_point`:
  rotor-effective aerodynamics, actuators, dynamic inflow, the free azimuth left out, SI units), a
  continuous-time model with inputs ``Wind1VelX`` [m/s], ``BlPitchCom`` [rad], ``GenTqCom`` [N m];
* the **controller**: :class:`~mbsym.wind.control.BaselineController` linearized about its fixed point at
  the trim's measurements and commands (:func:`mbsym.wind.control.linear.linearize_controller`), a
  discrete-time model at its sample time ``dt``.

Everything is **discrete-time at the controller's sample time**, because that is the loop that runs
(:mod:`mbsym.simulate.controller`): at ``t_k`` the controller reads the measurements, its commands are held
over ``[t_k, t_k + dt)``. The plant is discretized exactly for that zero-order hold (matrix exponential),
so the closed loop has no approximation beyond the linearization itself; margins and poles include the
hold and the controller's Tustin filters as they are. (A continuous equivalent would have to approximate
both; at ``dt`` = 0.01 s the difference is small below a few Hz but grows towards the Nyquist frequency.)
Closed-loop eigenvalues ``z`` are reported with the continuous equivalent ``s = ln(z)/dt``: natural
frequency ``|s|/2π`` [Hz] and damping ratio ``−Re s/|s|``; an eigenvalue at ``z = 0`` (a pure one-sample
memory of the controller's realization) has no such equivalent and is only counted.

**Loops.** Each loop is broken at the actuator command, the other one closed (the "loop-at-a-time"
margins at the plant input): the **pitch loop** at ``BlPitchCom``, the **torque loop** at ``GenTqCom``.
The loop transfer function is ``L(z) = −(command out of the controller) / (command into the plant)``, so
that ``1 + L`` is the return difference and python-control's negative-feedback conventions hold
(``control.feedback(L, 1)`` is the loop closed again). Gain and phase margins come from
``control.stability_margins`` on ``L``'s frequency response on a dense grid (:data:`MARGIN_GRID_HZ`) up
to the Nyquist frequency. A loop whose command does not respond to the measurements at the point (the
pitch saturated at its minimum in region 2: ``L ≡ 0``) is *inactive*: no margins. A margin that does not
exist (no crossover of unit gain, or of −180°, below the Nyquist frequency) is infinite; JSON has no
infinity, so :meth:`ClosedLoopSweep.to_dict` writes ``null`` for infinite or undefined margins.

**Closed loop** (:attr:`ClosedLoopLinear.closed_loop`, a discrete python-control ``StateSpace``): inputs
``Wind1VelX`` [m/s] and the command disturbances ``BlPitchCom_dist`` [rad], ``GenTqCom_dist`` [N m]
(added to the controller's commands at the plant input); outputs the plant's channels (SI) and the
controller's commands ``BlPitchCom``, ``GenTqCom``; states the plant's then ``baseline.<state>``.
All signals are deviations from the operating point.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from typing import Mapping, Sequence

import numpy as np

from ...exceptions import DimensionError, ModelDefinitionError, SolverError, UnsupportedFeatureError
from ..control.baseline import BaselineController
from ..control.linear import LinearizedController, linearize_controller
from ..operation.steady_control import SteadyControl

__all__ = ["ClosedLoopLinear", "ClosedLoopSweep", "LoopMargins", "ClosedLoopPole", "closed_loop_linear",
           "closed_loop_sweep", "LOOPS", "PLANT_OUTPUTS", "MARGIN_GRID_HZ", "DEADBEAT"]

#: Loop name -> the actuator command where it is broken.
LOOPS = {"pitch": "BlPitchCom", "torque": "GenTqCom"}
#: Plant channels of the closed-loop model (those the model has), after the controller's measurements.
PLANT_OUTPUTS = ("RotSpeed", "GenSpeed", "BldPitch1", "GenTq", "GenPwr", "RtAeroFxh", "TTDspFA", "TwrBsMyt")
#: Frequency grid of the margins: (lowest [Hz], points per decade); it ends just below the Nyquist frequency.
MARGIN_GRID_HZ = (1e-4, 100)
#: Closed-loop eigenvalues with |z| below this are one-sample memories (z = 0): counted, not listed. A k-fold
#: eigenvalue at 0 (a Tustin filter's input memories) comes out of the eigensolver as a ring of radius
#: ~eps^(1/k) (3e-6 for k = 3, 1e-4 for k = 4); |z| = 1e-3 is a continuous equivalent of 110 Hz at dt = 0.01 s,
#: far above every physical mode of the model (the torque actuator's 16 Hz is the fastest).
DEADBEAT = 1e-3
#: Distance from the unit circle [-] within which an eigenvalue no input reaches counts as marginal, not unstable
#: (:attr:`ClosedLoopLinear.unreached`; a pure integrator's comes out within ~1e-11 of z = 1).
MARGINAL = 1e-9
#: Names of the closed loop's command-disturbance inputs.
_DIST = {"BlPitchCom": "BlPitchCom_dist", "GenTqCom": "GenTqCom_dist"}


@dataclass(frozen=True)
class LoopMargins:
    """Stability margins of one loop (module docstring).

    Attributes
    ----------
    active : bool
        Whether the loop transfer function is nonzero at the point.
    gain_margin_db : float
        ``20 log10(gm)`` [dB]; ``inf`` without a −180° crossover, ``nan`` for an inactive loop.
    phase_margin_deg : float
        [deg]; ``inf`` without a unit-gain crossover, ``nan`` for an inactive loop.
    phase_crossover_hz, gain_crossover_hz : float
        Frequencies [Hz] of the −180° and of the unit-gain crossover (``nan`` where none).
    """

    active: bool
    gain_margin_db: float
    phase_margin_deg: float
    phase_crossover_hz: float
    gain_crossover_hz: float


@dataclass(frozen=True)
class ClosedLoopPole:
    """One closed-loop eigenvalue (a complex pair once, Im z >= 0).

    Attributes
    ----------
    z : complex
        Discrete-time eigenvalue.
    s : complex
        Continuous equivalent ``ln(z)/dt`` [rad/s].
    freq_hz : float
        ``|s|/2π`` [Hz].
    damping_ratio : float
        ``−Re s/|s|`` [-].
    dominant_state : str
        State group with the largest participation factor (:mod:`mbsym.linear.state_modes`).
    label : str
        Words for it (:func:`.trim_linear.mode_label`).
    """

    z: complex
    s: complex
    freq_hz: float
    damping_ratio: float
    dominant_state: str
    label: str

    def as_dict(self) -> dict:
        """``{"freq_hz", "damping_ratio", "z": [re, im], "dominant_state", "label"}`` (plain floats, for JSON)."""
        return {"freq_hz": float(self.freq_hz), "damping_ratio": float(self.damping_ratio),
                "z": [float(self.z.real), float(self.z.imag)], "dominant_state": self.dominant_state,
                "label": self.label}


@dataclass(frozen=True)
class ClosedLoopLinear:
    """The operating turbine and its baseline controller linearized about one trim (module docstring).

    Attributes
    ----------
    wind_speed : float
        [m/s].
    region : str
        The trim's region (``"2"``, ``"2.5"``, ``"3"`` ...).
    dt : float
        Sample time [s] of every discrete model here.
    plant : LinearModel
        The continuous-time plant (SI), outputs: the controller's measurements then :data:`PLANT_OUTPUTS`.
    controller : LinearizedController
    closed_loop : control.StateSpace
        Discrete closed loop (module docstring).
    loops : dict of str to control.StateSpace
        ``"pitch"``, ``"torque"``: the SISO loop transfer functions ``L(z)`` (discrete ``StateSpace``: with
        tens of states a polynomial ``TransferFunction`` would be ill-conditioned; ``control.ss2tf`` converts).
    margins : dict of str to LoopMargins
    poles : tuple of ClosedLoopPole
        Sorted by frequency; eigenvalues at z = 0 left out (:attr:`deadbeat`).
    deadbeat : int
        How many closed-loop eigenvalues are at z = 0.
    point : TrimPoint
    """

    wind_speed: float
    region: str
    dt: float
    plant: object = field(repr=False)
    controller: LinearizedController = field(repr=False)
    closed_loop: object = field(repr=False)
    loops: Mapping = field(repr=False)
    margins: Mapping
    poles: tuple = field(repr=False)
    deadbeat: int = 0
    point: object = field(default=None, repr=False)

    @property
    def pitch_loop(self):
        """The pitch loop's ``L(z)`` (broken at ``BlPitchCom``)."""
        return self.loops["pitch"]

    @property
    def torque_loop(self):
        """The torque loop's ``L(z)`` (broken at ``GenTqCom``)."""
        return self.loops["torque"]

    @property
    def spectral_radius(self) -> float:
        """Largest ``|z|`` of the closed loop (< 1: stable)."""
        return float(np.max(np.abs(np.linalg.eigvals(self.closed_loop.A)), initial=0.0))

    @property
    def stable(self) -> bool:
        """Whether every closed-loop eigenvalue lies inside the unit circle, but marginal ones no input reaches
        (:attr:`unreached`)."""
        z = np.linalg.eigvals(self.closed_loop.A)
        outside = z[np.abs(z) >= 1.0]
        return all(any(abs(v - u) <= MARGINAL for u in self.unreached) for v in outside)

    @property
    def unreached(self) -> tuple[complex, ...]:
        """Eigenvalues on the unit circle (within :data:`MARGINAL`) that no input of the closed loop reaches (a left
        eigenvector orthogonal to ``B`` to 1e-9): a controller integrator behind a high-pass filter, e.g. ROSCO's
        floating feedback (nacelle acceleration → high-pass → integral → pitch), whose pole at ``z = 1`` the filter's
        zero leaves in the realization. Such a state stays where it starts; the loop is stable without it."""
        cl = self.closed_loop
        w, V = np.linalg.eig(np.asarray(cl.A).T)
        B = np.asarray(cl.B)
        scale = float(np.linalg.norm(B)) or 1.0
        return tuple(complex(z) for z, v in zip(w, V.T)
                     if abs(abs(z) - 1.0) <= MARGINAL and np.linalg.norm(v @ B) <= 1e-9 * scale * np.linalg.norm(v))

    def least_damped(self) -> ClosedLoopPole | None:
        """The oscillating or real pole with the smallest damping ratio, the :attr:`unreached` ones left out."""
        skip = self.unreached
        return min((p for p in self.poles if p.freq_hz > 0 and not any(abs(p.z - u) <= MARGINAL for u in skip)),
                   key=lambda p: p.damping_ratio, default=None)

    def step_response(self, input: str = "Wind1VelX", amplitude: float = 0.1, duration: float = 30.0) -> dict:
        """Deviations after a step of ``amplitude`` in ``input`` at t = 0 (discrete simulation of the closed loop).

        Returns
        -------
        dict
            ``"time"`` [s] (the samples ``k dt``) and every output of :attr:`closed_loop` by name (SI).
        """
        cl = self.closed_loop
        if input not in cl.input_labels:
            raise DimensionError(f"unknown input {input!r}; the closed loop's inputs are {cl.input_labels}.")
        n = int(round(duration / self.dt)) + 1
        j = cl.input_labels.index(input)
        A, b, C, d = cl.A, cl.B[:, j] * amplitude, cl.C, cl.D[:, j] * amplitude
        x = np.zeros(A.shape[0])
        Y = np.empty((n, C.shape[0]))
        for k in range(n):
            Y[k] = C @ x + d
            x = A @ x + b
        return {"time": np.arange(n) * self.dt, **{name: Y[:, i] for i, name in enumerate(cl.output_labels)}}

    def frequency_response(self, loop: str = "pitch"):
        """``L(e^{jω dt})`` of ``loop`` ("pitch" or "torque") on the margins' grid up to just below the Nyquist
        frequency, refined where the phase moves fast (:func:`mbsym.linear.frequency_response`: continuous phase
        from (−180°, 180°], and :meth:`~mbsym.linear.FrequencyResponse.wrapped_phase_deg` for a plot)."""
        from ...linear.frequency import frequency_response

        if loop not in self.loops:
            raise DimensionError(f"unknown loop {loop!r}; the loops are {list(self.loops)}.")
        L = self.loops[loop]
        return frequency_response(lambda f: _response(L, 2.0 * math.pi * np.asarray(f), self.dt), _grid_hz(self.dt))

    def bode_plot(self, path, *, title: str | None = None) -> None:
        """Bode plot of both loops, phase in (−360°, 0°] (:func:`.closed_loop_plot.plot_loop_bode`)."""
        from .closed_loop_plot import plot_loop_bode

        plot_loop_bode(self, path, title=title)

    def __repr__(self) -> str:
        m = ", ".join(f"{k}: GM {v.gain_margin_db:.3g} dB, PM {v.phase_margin_deg:.3g} deg" if v.active
                      else f"{k}: inactive" for k, v in self.margins.items())
        least = self.least_damped()
        worst = f", least damped {least.label} {least.freq_hz:.3g} Hz ζ {least.damping_ratio:.3g}" if least else ""
        return (f"ClosedLoopLinear(U={self.wind_speed:g} m/s, region {self.region}, dt={self.dt:g} s, {m}, "
                f"{'stable' if self.stable else 'UNSTABLE'}{worst})")


def _default_controller(controller) -> BaselineController:
    if controller is None:
        from ..operation.nrel5mw import nrel5mw_baseline_settings

        return BaselineController(nrel5mw_baseline_settings())
    if not isinstance(controller, BaselineController):
        raise TypeError(f"controller must be a BaselineController (or None: the built-in NREL 5 MW's); got "
                        f"{type(controller).__name__}.")
    return controller


def _check_model(model) -> None:
    from ..operation.model import OperatingTurbine

    if not isinstance(model, OperatingTurbine):
        raise TypeError(f"model must be an OperatingTurbine; got {type(model).__name__}.")
    if model.aero != "rotor":
        raise UnsupportedFeatureError(f"closed-loop linear models need the rotor-effective aerodynamics "
                                      f"(aero='rotor'); the model has aero={model.aero!r}, whose operating point "
                                      "is periodic. Build it with OperatingTurbine(..., aero='rotor').")
    if "BlPitchCom" not in model.dynamics().inputs:
        raise UnsupportedFeatureError("closed-loop linear models need a collective pitch input BlPitchCom; the "
                                      f"model's inputs are {list(model.dynamics().inputs)}.")


def closed_loop_sweep(model, wind_speeds: Sequence[float], controller: BaselineController | None = None, *,
                      outputs: Sequence[str] | None = None) -> "ClosedLoopSweep":
    """Closed-loop linear models at each wind speed (trims by continuation, module docstring).

    Parameters
    ----------
    model : OperatingTurbine
        With rotor-effective aerodynamics.
    wind_speeds : sequence of float
        [m/s].
    controller : BaselineController, optional
        Default: the built-in NREL 5 MW's (ROSCO 2.10.6 settings, 0.01 s).
    outputs : sequence of str, optional, keyword-only
        Plant channels of the closed loop besides the measurements (default :data:`PLANT_OUTPUTS`).

    Returns
    -------
    ClosedLoopSweep
        A point whose trim or controller fixed point fails is kept with its message (``None`` model).

    Examples
    --------
    >>> from mbsym.wind.operation import OperatingTurbine
    >>> sweep = closed_loop_sweep(OperatingTurbine.nrel5mw(), [8.0, 16.0])  # doctest: +SKIP
    >>> [v and round(v, 1) for v in sweep.to_dict()["pitch_phase_margin_deg"]]   # doctest: +SKIP
    [None, 38.9]
    """
    from .operating_points import operating_points

    ctrl = _default_controller(controller)
    _check_model(model)
    ops = operating_points(model, wind_speeds, SteadyControl.from_baseline(ctrl.settings))
    models, messages = [], []
    for point in ops:
        if not point.success:
            models.append(None)
            messages.append(f"no trim: {point.message}")
            continue
        try:
            models.append(_closed_loop_at(ops.trimmer, point, ctrl, outputs))
            messages.append("")
        except SolverError as err:
            models.append(None)
            messages.append(str(err))
    return ClosedLoopSweep(np.array([p.wind_speed for p in ops]), tuple(models), tuple(messages), ctrl.dt)


def closed_loop_linear(model, wind_speed: float, controller: BaselineController | None = None, *,
                       outputs: Sequence[str] | None = None) -> ClosedLoopLinear:
    """The closed-loop linear model of ``model`` with ``controller`` about its trim at ``wind_speed``.

    Parameters
    ----------
    model : OperatingTurbine
    wind_speed : float
        Hub-height wind [m/s].
    controller : BaselineController, optional
        Default: the built-in NREL 5 MW's.
    outputs : sequence of str, optional, keyword-only
        As in :func:`closed_loop_sweep`.

    Raises
    ------
    SolverError
        No trim, or no controller fixed point at it.
    UnsupportedFeatureError
        Blade-element aerodynamics or individual pitch.

    Examples
    --------
    >>> from mbsym.wind.operation import OperatingTurbine
    >>> cl = closed_loop_linear(OperatingTurbine.nrel5mw(), 16.0)           # doctest: +SKIP
    >>> round(cl.margins["pitch"].gain_margin_db, 1), cl.stable            # doctest: +SKIP
    (9.7, True)
    """
    sweep = closed_loop_sweep(model, [wind_speed], controller, outputs=outputs)
    if sweep.models[0] is None:
        raise SolverError(f"no closed-loop model at {wind_speed:g} m/s: {sweep.messages[0]}")
    return sweep.models[0]


# ------------------------------------------------------------------------------------------ assembly
def _closed_loop_at(trimmer, point, ctrl: BaselineController, outputs) -> ClosedLoopLinear:
    from .trim_linear import linearize_point

    dyn = trimmer.dyn
    extra = PLANT_OUTPUTS if outputs is None else tuple(outputs)
    names = tuple(dict.fromkeys(tuple(ctrl.measurements) + tuple(extra)))
    unknown = [n for n in names if n not in dyn.output_names]
    if unknown:
        raise DimensionError(f"unknown output channels {unknown}; the model has {list(dyn.output_names)}.")
    plant = linearize_point(trimmer, point, outputs=names)
    y_op = dict(zip(plant.outputs, np.asarray(plant.operating_point["y"], dtype=float)))
    u_op = dict(zip(point.input_names, point.inputs))
    lc = linearize_controller(ctrl, {m: y_op[m] for m in ctrl.measurements}, {c: u_op[c] for c in ctrl.commands})
    Ad, Bd = _zoh(plant.A, plant.B, ctrl.dt)
    parts = _Parts(plant, lc, Ad, Bd)
    loops = {loop: parts.loop(command) for loop, command in LOOPS.items()}
    margins = {loop: _margins(L, ctrl.dt) for loop, L in loops.items()}
    closed = parts.closed_loop()
    poles, deadbeat = _poles(closed, ctrl.dt)
    return ClosedLoopLinear(float(point.wind_speed), point.region, ctrl.dt, plant, lc, closed, loops, margins,
                            poles, deadbeat, point)


def _zoh(A: np.ndarray, B: np.ndarray, dt: float) -> tuple[np.ndarray, np.ndarray]:
    """Exact zero-order-hold discretization: ``expm([[A, B], [0, 0]] dt)``."""
    import scipy.linalg

    n, m = B.shape
    M = np.zeros((n + m, n + m))
    M[:n, :n], M[:n, n:] = A, B
    E = scipy.linalg.expm(M * dt)
    return E[:n, :n], E[:n, n:]


class _Parts:
    """The discrete plant and controller, and their interconnections (module docstring)."""

    def __init__(self, plant, lc: LinearizedController, Ad: np.ndarray, Bd: np.ndarray) -> None:
        inputs = list(plant.inputs)
        self.iw = inputs.index("Wind1VelX")
        self.iu = [inputs.index(c) for c in lc.commands]
        outs = list(plant.outputs)
        meas = [outs.index(m) for m in lc.measurements]
        C, D = plant.Cy, plant.Dy
        if np.any(D[np.ix_(meas, self.iu)] != 0.0):
            bad = [lc.measurements[i] for i in np.flatnonzero(np.any(D[np.ix_(meas, self.iu)] != 0.0, axis=1))]
            raise ModelDefinitionError(f"the measurements {bad} feed through from the commands; the closed-loop "
                                       "model assumes they depend on the plant's states and the wind only.")
        self.plant, self.lc, self.Ad, self.Bd = plant, lc, Ad, Bd
        self.Cm, self.Dmw = C[meas], D[meas, self.iw]
        self.n, self.nc = Ad.shape[0], lc.A.shape[0]

    def _matrices(self, closed: Sequence[bool]):
        """``(A, B, C, D)`` of the loop with the commands ``closed[i]`` connected; inputs ``[w, v]`` (wind, command
        disturbances), outputs ``[plant outputs, controller commands]``."""
        lc, S = self.lc, np.diag(np.asarray(closed, dtype=float))
        Bw, Bu = self.Bd[:, self.iw], self.Bd[:, self.iu]
        Cz, Dzw, Dzu = self.plant.Cy, self.plant.Dy[:, self.iw], self.plant.Dy[:, self.iu]
        Dc = lc.D
        A = np.block([[self.Ad + Bu @ S @ Dc @ self.Cm, Bu @ S @ lc.C], [lc.B @ self.Cm, lc.A]])
        B = np.block([[(Bw + Bu @ S @ Dc @ self.Dmw)[:, None], Bu], [(lc.B @ self.Dmw)[:, None],
                                                                      np.zeros((self.nc, len(self.iu)))]])
        Cu = np.hstack([Dc @ self.Cm, lc.C])
        Du = np.hstack([(Dc @ self.Dmw)[:, None], np.zeros((len(self.iu), len(self.iu)))])
        C = np.vstack([np.hstack([Cz + Dzu @ S @ Dc @ self.Cm, Dzu @ S @ lc.C]), Cu])
        D = np.vstack([np.hstack([(Dzw + Dzu @ S @ Dc @ self.Dmw)[:, None], Dzu]), Du])
        return A, B, C, D

    def states(self) -> list[str]:
        return list(self.plant.states) + [f"baseline.{s}" for s in self.lc.states]

    def closed_loop(self):
        import control

        A, B, C, D = self._matrices([True] * len(self.iu))
        return control.ss(A, B, C, D, self.lc.dt, states=self.states(),
                          inputs=["Wind1VelX"] + [_DIST[c] for c in self.lc.commands],
                          outputs=list(self.plant.outputs) + list(self.lc.commands), name="closed_loop")

    def loop(self, command: str):
        """``L(z) = −(controller command ← plant command)`` with the loop of ``command`` open, the others closed."""
        import control

        k = self.lc.commands.index(command)
        closed = [i != k for i in range(len(self.iu))]
        A, B, C, D = self._matrices(closed)
        row, col = len(self.plant.outputs) + k, 1 + k
        return control.ss(A, B[:, [col]], -C[[row], :], -D[[row], [col]].reshape(1, 1), self.lc.dt,
                          states=self.states(), inputs=[command], outputs=[command], name=f"{command}_loop")


def _margins(L, dt: float) -> LoopMargins:
    """Margins of ``L`` from python-control on its frequency response (module docstring)."""
    import warnings

    import control

    w = 2.0 * math.pi * _grid_hz(dt)
    resp = _response(L, w, dt)
    nan = float("nan")
    if not np.any(np.abs(resp) > 1e-12 * max(1.0, float(np.max(np.abs(L.D), initial=0.0)))):
        return LoopMargins(False, nan, nan, nan, nan)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")          # python-control warns about the FRD interpolation
        gm, pm, _, wpc, wgc, _ = control.stability_margins(control.frd(resp, w, dt=dt, smooth=True))
    gm_db = 20.0 * math.log10(gm) if np.isfinite(gm) and gm > 0 else math.inf
    return LoopMargins(True, gm_db, float(pm) if np.isfinite(pm) else math.inf,
                       float(wpc) / (2 * math.pi) if np.isfinite(wpc) else nan,
                       float(wgc) / (2 * math.pi) if np.isfinite(wgc) else nan)


def _grid_hz(dt: float) -> np.ndarray:
    """The margins' frequency grid [Hz] (:data:`MARGIN_GRID_HZ`), ending just below the Nyquist frequency."""
    f_low, per_decade = MARGIN_GRID_HZ
    f_nyq = 0.5 / dt
    return np.logspace(math.log10(f_low), math.log10(f_nyq * (1.0 - 1e-6)), int(per_decade * math.log10(f_nyq / f_low)) + 1)


def _response(L, w: np.ndarray, dt: float) -> np.ndarray:
    """``L(e^{jω dt})`` at the angular frequencies ``w`` (one eigen-decomposition of A, then diagonal solves)."""
    A, B, C, D = L.A, L.B[:, 0], L.C[0], complex(L.D[0, 0])
    lam, V = np.linalg.eig(A)
    if np.linalg.cond(V) > 1e10:     # a nearly defective A: solve per frequency
        z = np.exp(1j * w * dt)
        return np.array([C @ np.linalg.solve(zk * np.eye(A.shape[0]) - A, B) + D for zk in z])
    cv, vb = C @ V, np.linalg.solve(V, B)
    z = np.exp(1j * w * dt)
    return (cv[None, :] * vb[None, :] / (z[:, None] - lam[None, :])).sum(axis=1) + D


def _poles(closed, dt: float) -> tuple[tuple[ClosedLoopPole, ...], int]:
    """Closed-loop eigenvalues with their continuous equivalents and dominant states (module docstring)."""
    from ...linear.state_modes import StateMode, participation_factors
    from .trim_linear import mode_label, numbered_labels, whirl_labels

    lam, P = participation_factors(closed.A)
    groups = _groups(closed.state_labels)
    names = list(dict.fromkeys(groups))
    G = np.zeros((len(names), len(groups)))
    for i, g in enumerate(groups):
        G[names.index(g), i] = 1.0
    poles, deadbeat = [], 0
    for k in np.flatnonzero(lam.imag >= 0):
        z = complex(lam[k])
        if abs(z) < DEADBEAT:
            deadbeat += 1
            continue
        s = complex(np.log(z)) / dt
        share = G @ P[:, k]
        dominant = names[int(np.argmax(share))]
        wn = abs(s)
        zeta = -s.real / wn if wn > 0 else 1.0
        label = mode_label(StateMode(wn / (2 * math.pi), zeta, abs(s.imag) / (2 * math.pi), s, dominant))
        poles.append(ClosedLoopPole(z, s, wn / (2 * math.pi), zeta, dominant, label))
    freqs = [p.freq_hz for p in poles]
    labels = numbered_labels(whirl_labels([p.label for p in poles], freqs), freqs)
    poles = [dataclasses.replace(p, label=label) for p, label in zip(poles, labels)]
    return tuple(sorted(poles, key=lambda p: p.freq_hz)), deadbeat


def _groups(states: Sequence[str]) -> list[str]:
    """State groups: ``x`` with ``x_d``; a controller block (``baseline.<block>[i]``) as one group."""
    from ...linear.state_modes import state_groups

    return [g.split("[")[0] for g in state_groups(list(states))]


# ------------------------------------------------------------------------------------------ the sweep
@dataclass(frozen=True)
class ClosedLoopSweep:
    """Closed-loop linear models over wind speed (:func:`closed_loop_sweep`).

    Attributes
    ----------
    wind_speed : ndarray
        [m/s], in the order asked.
    models : tuple of ClosedLoopLinear or None
        None where the trim or the controller's fixed point failed (:attr:`messages`).
    messages : tuple of str
        Empty for a success.
    dt : float
        Controller sample time [s].
    """

    wind_speed: np.ndarray
    models: tuple
    messages: tuple
    dt: float

    def __len__(self) -> int:
        return len(self.models)

    def __getitem__(self, i: int) -> ClosedLoopLinear | None:
        return self.models[i]

    @property
    def success(self) -> bool:
        return all(m is not None for m in self.models)

    def to_dict(self) -> dict:
        """The ``mbsym linearize --closed-loop --json`` object (layout in docs/operating_points.md)."""
        def num(v: float):
            return float(v) if np.isfinite(v) else None

        out: dict = {"wind_speed": [float(u) for u in self.wind_speed], "sample_time": float(self.dt),
                     "region": [m.region if m else None for m in self.models],
                     "success": [m is not None for m in self.models], "message": list(self.messages)}
        for loop in LOOPS:
            ms = [m.margins[loop] if m else None for m in self.models]
            out[f"{loop}_active"] = [bool(v.active) if v else None for v in ms]
            out[f"{loop}_gain_margin_db"] = [num(v.gain_margin_db) if v else None for v in ms]
            out[f"{loop}_phase_margin_deg"] = [num(v.phase_margin_deg) if v else None for v in ms]
            out[f"{loop}_phase_crossover_hz"] = [num(v.phase_crossover_hz) if v else None for v in ms]
            out[f"{loop}_gain_crossover_hz"] = [num(v.gain_crossover_hz) if v else None for v in ms]
        out["stable"] = [bool(m.stable) if m else None for m in self.models]
        out["spectral_radius"] = [m.spectral_radius if m else None for m in self.models]
        out["closed_loop_poles"] = [[p.as_dict() for p in m.poles] if m else [] for m in self.models]
        out["deadbeat_poles"] = [m.deadbeat if m else None for m in self.models]
        out["units"] = {"wind_speed": "m/s", "sample_time": "s", "gain_margin_db": "dB", "phase_margin_deg": "deg",
                        "crossover_hz": "Hz", "freq_hz": "Hz", "damping_ratio": "-", "z": "-"}
        return out

    def table(self) -> str:
        """A text table: margins, stability and the least-damped closed-loop pole per wind speed."""
        def fmt(v: float) -> str:
            return "inf" if v == math.inf else ("-" if not np.isfinite(v) else f"{v:.3g}")

        lines = [f"{'U [m/s]':>8} {'region':>6}  {'pitch GM [dB]':>13} {'PM [deg]':>8}  {'torque GM [dB]':>14} "
                 f"{'PM [deg]':>8}  {'stable':>6}  least-damped pole"]
        for u, m, msg in zip(self.wind_speed, self.models, self.messages):
            if m is None:
                lines.append(f"{u:8.3g}  failed: {msg}")
                continue
            p, t = m.margins["pitch"], m.margins["torque"]
            least = m.least_damped()
            pole = f"{least.label} {least.freq_hz:.3g} Hz, zeta {least.damping_ratio:.3g}" if least else "-"
            lines.append(f"{u:8.3g} {m.region:>6}  {fmt(p.gain_margin_db):>13} {fmt(p.phase_margin_deg):>8}  "
                         f"{fmt(t.gain_margin_db):>14} {fmt(t.phase_margin_deg):>8}  {str(m.stable):>6}  {pole}")
        return "\n".join(lines)

    def plot(self, path, *, title: str | None = None) -> None:
        """Margins and closed-loop poles over wind speed (:func:`.closed_loop_plot.plot_closed_loop`)."""
        from .closed_loop_plot import plot_closed_loop

        plot_closed_loop(self, path, title=title)
