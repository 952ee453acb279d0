"""An NMPC (with or without a state estimator) as a controller in the loop of :func:`mbsym.simulate`.

``mb.simulate(model, T, controller=mpc)`` and ``controller=(estimator, mpc)`` accept them directly
(:func:`mbsym.simulate.controller.bind_controller` calls :func:`nmpc_controller` through
``NMPC.as_controller``). Every ``mpc.sample_time`` seconds, with zero-order hold on the controls:

- without an estimator the controller measures the model's states by name (full state feedback) and
  calls ``mpc.step(x)``;
- with an :class:`~mbsym.control.EKF`, :class:`~mbsym.control.UKF` or :class:`~mbsym.control.MHE`
  it measures the estimator's measurements, updates the estimate with them and the controls applied
  over the last sample, and calls ``mpc.step`` on the estimated states; estimated unknown inputs that
  are disturbances of the NMPC (a wind speed) are passed as its preview (held over the horizon).

The NMPC keeps its own statistics (``mpc.stats``, ``mpc.failures``; the estimator's too).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..exceptions import ControlDefinitionError

__all__ = ["nmpc_controller"]


def nmpc_controller(mpc, *, estimator: Any = None, name: str = "nmpc"):
    """A :class:`mbsym.simulate.DiscreteController` running ``mpc`` (and ``estimator``) every sample.

    Parameters
    ----------
    mpc : NMPC
    estimator : EKF, UKF or MHE, optional, keyword-only
        Estimates the NMPC's states from the estimator's measurements. Its model's states must
        include the NMPC model's states, its known inputs must be controls of the NMPC, and its
        sample time must equal the NMPC's.
    name : str, optional, keyword-only

    Returns
    -------
    DiscreteController
        A Python law; measures the NMPC model's states (no estimator) or the estimator's
        measurements; actuates ``mpc.inputs``.

    Raises
    ------
    ControlDefinitionError
        An estimator whose states, known inputs or sample time do not fit the NMPC.

    Examples
    --------
    >>> import casadi as ca, mbsym as mb
    >>> from mbsym.control import OCP, NMPC
    >>> x, u, p = ca.SX.sym("x", 2), ca.SX.sym("u"), ca.SX.sym("p", 0)
    >>> dyn = mb.Dynamics(ca.Function("f", [x, u, p], [ca.vertcat(x[1], u)]), states=["pos", "vel"], inputs=["force"])
    >>> ocp = OCP(dyn, horizon=20, dt=0.1).track({"pos": 1.0, "vel": 0.1, "force": 0.01}).bound("force", -1, 1)
    >>> res = mb.simulate(dyn, 8.0, x0=[1.0, 0.0], controller=NMPC(ocp, compile=False))
    >>> abs(float(res.state("pos")[-1])) < 0.1
    True
    """
    from ..simulate.controller import DiscreteController

    states = tuple(mpc.transcription.dynamics.states)
    controls = tuple(mpc.inputs)
    if estimator is None:
        def law(t, xc, y):
            return xc, mpc.step(np.asarray(y, dtype=float))

        return DiscreteController(law, mpc.sample_time, measurements=states, actuates=controls, name=name)
    model = estimator.model
    names = tuple(model.names)
    _check_estimator(model, names, states, controls, mpc.sample_time)
    pick = [names.index(s) for s in states]
    known = [controls.index(n) for n in model.known_inputs]
    disturbances = [n for n in mpc.transcription.disturbances if n in names]
    applied = {"u": np.zeros(len(controls))}

    def law(t, xc, y):                                           # noqa: ARG001 - time unused
        z = estimator.step(np.asarray(y, dtype=float), applied["u"][known])
        preview = {n: float(z[names.index(n)]) for n in disturbances} or None
        u = mpc.step(z[pick], preview=preview)
        applied["u"] = np.asarray(u, dtype=float)
        return xc, u

    return DiscreteController(law, mpc.sample_time, measurements=model.measurements, actuates=controls, name=name)


def _check_estimator(model, names, states, controls, dt) -> None:
    problems = []
    missing = [s for s in states if s not in names]
    if missing:
        problems.append(f"it does not estimate the NMPC's states {missing} (it estimates {list(names)})")
    extra = [n for n in model.known_inputs if n not in controls]
    if extra:
        problems.append(f"its known inputs {extra} are not controls of the NMPC ({list(controls)}); make them "
                        "unknown inputs of the estimator (estimated) or controls of the NMPC")
    if abs(model.dt - dt) > 1e-12 * max(dt, 1.0):
        problems.append(f"its sample time {model.dt:g} s differs from the NMPC's {dt:g} s")
    if problems:
        raise ControlDefinitionError("the estimator does not fit the NMPC in the loop: " + "; ".join(problems) + ".")
