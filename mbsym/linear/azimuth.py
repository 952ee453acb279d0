"""Linearizations of a spinning rotor at several azimuths, in one batch, and their average.

:func:`linearize_azimuths` linearizes at several values of the spinning coordinate
(:func:`mbsym.linear.linearize_batch`); :meth:`AzimuthSweep.average` averages them. A model
whose coordinates include rotating-frame ones (the blade DOFs of a rotor) supplies a
*rotating frame* — the hook ``rotating_frame()`` of a model object, or ``frame=`` — that
writes each azimuth's model in fixed-frame coordinates before the average (for wind turbines:
multi-blade coordinates, :class:`mbsym.wind.structure.mbc.BladeFrame`). This module knows
nothing of blades or turbines: a frame is any object with

``groups``
    index tuples of the rotating coordinates in ``q`` (may be empty);
``azimuths(psi, X) -> ndarray``
    the azimuth the transformation uses at each sample, from the values ``psi`` of the
    spinning coordinate and the sampled states ``X (n_s, n_x)``;
``to_fixed_frame(lin, azimuth, rotor_speed) -> LinearModel``
    one linear model in fixed-frame coordinates.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Sequence

import numpy as np

from .batch import LinearBatch, linearize_batch
from .model import LinearModel
from .operating import _azimuth_samples, _rotating_coordinate
from .point import OperatingPoint
from .target import Target

__all__ = ["AzimuthSweep", "linearize_azimuths"]


@dataclass(frozen=True)
class AzimuthSweep:
    """Linearizations of a spinning rotor at several azimuths.

    Attributes
    ----------
    azimuths : ndarray (n_s,)
        Values of the spinning coordinate [rad].
    blade_azimuths : ndarray (n_s,)
        Azimuth used by the rotating frame at each sample [rad] (blade 1's for a
        turbine; ``azimuths`` without a frame).
    rotor_speed : float
        [rad/s].
    batch : LinearBatch
        The linear models, one per azimuth.
    frame : object or None
        The rotating frame (module docstring), or None when every coordinate is in the
        fixed frame.
    """

    azimuths: np.ndarray
    blade_azimuths: np.ndarray
    rotor_speed: float
    batch: LinearBatch
    frame: Any = None

    @property
    def blade_indices(self) -> list:
        """Index tuples of the rotating-frame coordinates in ``q`` (empty without a frame)."""
        return list(self.frame.groups) if self.frame is not None else []

    def average(self) -> LinearModel:
        """The azimuth-averaged linear model.

        Without a rotating frame every coordinate is in the fixed frame and the matrices
        are averaged as they are; with one, each azimuth's model is first written in the
        frame's fixed-frame coordinates (for blades: collective, cosine, sine).
        """
        b = self.batch
        lins = [b[i] for i in range(len(b))]
        if self.blade_indices:
            lins = [self.frame.to_fixed_frame(lin, psi, self.rotor_speed)
                    for lin, psi in zip(lins, self.blade_azimuths)]
        keys = ("M", "C", "K", "Q", "A", "B", "Cy", "Dy")
        mean = {k: np.mean([getattr(lin, k) for lin in lins], axis=0) for k in keys}
        op = dict(lins[0].operating_point)
        op["azimuths"] = self.azimuths.copy()
        return LinearModel(mean["M"], mean["C"], mean["K"], mean["Q"], mean["A"], mean["B"], b.coordinates, b.states,
                           b.inputs, op, b.outputs, mean["Cy"], mean["Dy"], b.output_units, b.method,
                           units=dict(lins[0].units), input_units=lins[0].input_units)

    def modes(self) -> list:
        """Modes of the averaged model (:meth:`average`)."""
        return self.average().modes()


def linearize_azimuths(model, op: OperatingPoint | None = None, azimuths: int | Sequence[float] = 12, *,
                       coordinate: str | None = None, outputs=None, method: str = "exact", steps=None,
                       qdd0=None, frame: Any = None) -> AzimuthSweep:
    """Linearize at several azimuths of the spinning coordinate, all in one batch.

    Parameters
    ----------
    model : EquationsOfMotion or model object
        A model object may supply the rotating frame through its hook
        ``rotating_frame()`` (a wind turbine with blade DOFs does).
    op : OperatingPoint, optional
        E.g. from :func:`steady_rotation`; default: the model's default state and inputs.
    azimuths : int or sequence of float
        A number of equally spaced azimuths over a revolution, starting at the
        operating point's, or the coordinate values themselves [rad].
    coordinate : str, optional, keyword-only
        The spinning coordinate (default ``"GeAz"``).
    outputs, method, steps, qdd0 : optional, keyword-only
        As for :func:`mbsym.linearize`.
    frame : object, optional, keyword-only
        The rotating frame (module docstring); default: the model's hook, else none.

    Returns
    -------
    AzimuthSweep
        ``.average()`` gives the azimuth-averaged model (in the frame's fixed-frame
        coordinates when there is a frame).
    """
    target = Target(model)
    eom = target.eom
    name, prescribed = _rotating_coordinate(target, coordinate)
    if op is None:
        q, qd = target.state(None, None)
        u, p = target.inputs(None), None
    else:
        q, qd, u, p = op.q, op.qd, op.u, op.p
    if prescribed:
        psi0, speed = u[eom.inputs.index(name)], u[eom.inputs.index(f"{name}_d")]
    else:
        psi0, speed = q[eom.coordinates.index(name)], qd[eom.coordinates.index(name)]
    if np.ndim(azimuths) == 0:
        psi = psi0 + 2 * np.pi * np.arange(int(azimuths)) / int(azimuths)
    else:
        psi = np.asarray(azimuths, dtype=float).reshape(-1)
    X, U = _azimuth_samples(target, name, prescribed, q, qd, u, psi)
    batch = linearize_batch(model, X, U, p, outputs=outputs, method=method, steps=steps,
                            qdd0=qdd0)
    if frame is None:
        frame = target._hook("rotating_frame")
    frame_azimuths = psi if frame is None else np.asarray(frame.azimuths(psi, X), dtype=float).reshape(-1)
    return AzimuthSweep(psi, frame_azimuths, float(speed), batch, frame)
