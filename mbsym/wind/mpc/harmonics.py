"""The blade-passing (nP) ripple of an operating turbine's measurements as states of its estimator.

A rotor sweeping a sheared, turbulent field sees the wind change as each blade passes: the
aerodynamic torque and thrust ripple at the blade-passing frequency ``n Ω`` (3P on a three-bladed
rotor, 0.6 Hz on the NREL 5 MW at rated speed). The rotor-effective model an estimator runs cannot
make that ripple (its wind is one number for the whole disk), so an EKF fed the raw generator speed
and tower-top acceleration explains it as wind and tower motion, and an NMPC on that estimate pitches
at 3P: on OpenFAST's flexible NREL 5 MW in a 16 m/s TurbSim field (seed 1618) the NMPC's pitch rate
had 0.43 deg/s RMS between 0.45 and 0.75 Hz against ROSCO's 0.19 (whose speed filter takes it out),
most of its pitch-rate RMS, and the tower base 1.12x ROSCO's load in that band (measured,
benchmarks/README.md). The ripple is large against the sensors' noise: 2.7-3.1 rpm RMS of generator
speed and 0.14-0.15 m/s² of tower-top acceleration in that band, against the EKF's 0.5 rpm and
0.02 m/s² measurement noise.

:func:`with_blade_passing` adds, for each measured channel, a pair of states ``(c, s)`` that rotate
at ``n Ω`` (``ċ = −nΩ s``, ``ṡ = nΩ c``, with ``Ω`` the estimated rotor speed) and adds ``c`` to the
channel's output: the internal model of a sinusoid at the blade-passing frequency, whose amplitude
and phase a random walk lets drift. An EKF on that model is a notch at ``n Ω`` that follows the
rotor speed: the ripple goes into ``(c, s)`` and stays out of the wind and tower estimates. How wide
the notch is follows from the walk of ``(c, s)`` against the channel's measurement noise
(:class:`~.estimator.EstimatorTuning`, ``harmonic_speed_walk``, ``harmonic_accel_walk``).
"""

from __future__ import annotations

from typing import Sequence

import casadi as ca

from ...dynamics import Dynamics
from ...exceptions import ControlDefinitionError

__all__ = ["with_blade_passing", "harmonic_states", "SPEED_STATE"]

#: The estimation state that is the rotor speed [rad/s] (ElastoDyn's ``QD_GeAz``, rotor side).
SPEED_STATE = "GeAz_d"


def harmonic_states(channels: Sequence[str], order: int) -> tuple[str, ...]:
    """Names of the ripple states: ``H3c_GenSpeed``, ``H3s_GenSpeed``, … (order 3) in channel order."""
    return tuple(f"H{order}{part}_{ch}" for ch in channels for part in ("c", "s"))


def with_blade_passing(dyn: Dynamics, channels: Sequence[str], order: int) -> Dynamics:
    """``dyn`` with a ripple at ``order`` times the rotor speed added to the outputs ``channels``.

    Parameters
    ----------
    dyn : Dynamics
        An estimation model with the rotor speed state :data:`SPEED_STATE` [rad/s].
    channels : sequence of str
        Outputs of ``dyn`` that carry the ripple (each gets two states, :func:`harmonic_states`).
    order : int
        Harmonic of the rotor speed (the number of blades for the blade-passing frequency).

    Returns
    -------
    Dynamics
        States ``dyn.states`` then the ripple states (initially zero); same inputs, parameters and
        outputs, each of ``channels`` plus its ripple ``c`` (in the channel's unit).

    Raises
    ------
    ControlDefinitionError
        No rotor-speed state, an unknown channel or an order below 1.
    """
    if isinstance(order, bool) or not isinstance(order, int) or order < 1:
        raise ControlDefinitionError(f"order must be an integer >= 1 (the harmonic of the rotor speed); got {order!r}.")
    if SPEED_STATE not in dyn.states:
        raise ControlDefinitionError(f"the blade-passing ripple turns at the rotor speed {SPEED_STATE!r}, which the "
                                     f"estimation model does not have (states: {list(dyn.states)}).")
    unknown = [c for c in channels if c not in dyn.output_names]
    if unknown or not channels:
        raise ControlDefinitionError(f"channels must name outputs of the estimation model; got {list(channels)} "
                                     f"(unknown: {unknown}).")
    n, m = dyn.n_x, 2 * len(channels)
    S = ca.SX if dyn.rhs.is_a("SXFunction") and dyn.outputs.is_a("SXFunction") else ca.MX
    x, u, p = S.sym("x", n + m), S.sym("u", dyn.n_u), S.sym("p", dyn.n_p)
    base, ripple = x[:n], x[n:]
    omega = order * base[dyn.states.index(SPEED_STATE)]
    turn = ca.vertcat(*[v for k in range(len(channels)) for v in (-omega * ripple[2 * k + 1], omega * ripple[2 * k])])
    rhs = ca.vertcat(dyn.rhs(base, u, p), turn)
    y = dyn.outputs(base, u, p)
    rows = {dyn.output_names.index(c): ripple[2 * k] for k, c in enumerate(channels)}
    y = ca.vertcat(*[y[i] + rows[i] if i in rows else y[i] for i in range(dyn.n_y)])
    opts = {"cse": True} if S is ca.SX else {}
    name = f"{dyn.name}_h{order}"
    f = ca.Function(f"{name}_rhs", [x, u, p], [rhs], ["x", "u", "p"], ["xd"], opts)
    h = ca.Function(f"{name}_outputs", [x, u, p], [y], ["x", "u", "p"], ["y"], opts)
    units = dict(zip(dyn.output_names, dyn.output_units))
    return Dynamics(f, states=tuple(dyn.states) + harmonic_states(channels, order), inputs=dyn.inputs,
                    parameters=dyn.parameters, defaults=dict(dyn.defaults), outputs=h, output_names=dyn.output_names,
                    output_units=dyn.output_units, x0=list(dyn.x0) + [0.0] * m, name=name,
                    state_units=list(dyn.state_units) + [units[c] for c in channels for _ in "cs"],
                    input_units=dyn.input_units)
