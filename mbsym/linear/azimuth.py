"""Linearizations of a spinning rotor at several azimuths, in one batch, and their average.

:func:`linearize_azimuths` linearizes at several values of the spinning coordinate
(:func:`mbsym.linear.linearize_batch`); :meth:`AzimuthSweep.average` averages them, in
multi-blade coordinates (:func:`mbsym.wind.analysis.mbc.mbc_transform`) when the model has
rotating-frame blade DOFs.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Callable, Sequence

import numpy as np

from .batch import LinearBatch, linearize_batch
from .model import LinearModel
from .operating import _azimuth_samples, _rotating_coordinate
from .point import OperatingPoint
from .target import Target

__all__ = ["AzimuthSweep", "linearize_azimuths"]


_BLADE = re.compile(r"B(\d+)(F1|E1|F2)")


def blade_indices(coordinates: Sequence[str]) -> list[tuple[int, ...]]:
    """Index triplets (blades 1, 2, 3) per blade DOF type, from names ``B<k>F1``, ``B<k>E1``, ``B<k>F2``."""
    groups: dict[str, dict[int, int]] = {}
    for i, c in enumerate(coordinates):
        m = _BLADE.fullmatch(c)
        if m:
            groups.setdefault(m.group(2), {})[int(m.group(1))] = i
    return [tuple(g[k] for k in sorted(g)) for g in groups.values()]


@dataclass(frozen=True)
class AzimuthSweep:
    """Linearizations of a spinning rotor at several azimuths.

    Attributes
    ----------
    azimuths : ndarray (n_s,)
        Values of the spinning coordinate [rad].
    blade_azimuths : ndarray (n_s,)
        Azimuth of blade 1 [rad] (for multi-blade coordinates).
    rotor_speed : float
        [rad/s].
    batch : LinearBatch
        The linear models, one per azimuth.
    blade_indices : list of tuple
        Rotating-frame blade DOF triplets in ``q`` (empty without blade DOFs).
    """

    azimuths: np.ndarray
    blade_azimuths: np.ndarray
    rotor_speed: float
    batch: LinearBatch
    blade_indices: list

    def average(self, *, mbc: Callable | None = None) -> LinearModel:
        """The azimuth-averaged linear model.

        Without rotating-frame DOFs every coordinate is in the fixed frame and the
        matrices are averaged as they are. With blade DOFs each azimuth's model is
        first written in multi-blade coordinates (Coleman): ``mbc(A, blade_indices,
        azimuth, rotor_speed, B=B) -> (A_B, B_B)`` (default
        :func:`mbsym.wind.analysis.mbc.mbc_transform`), M, C, K by
        :func:`mbsym.wind.analysis.mbc.mbc_second_order`, outputs by ``Cy T``; blade
        coordinates then read collective, cosine, sine.
        """
        b = self.batch
        lins = [b[i] for i in range(len(b))]
        if self.blade_indices:
            lins = [self._to_fixed_frame(lin, psi, mbc) for lin, psi in zip(lins, self.blade_azimuths)]
        keys = ("M", "C", "K", "Q", "A", "B", "Cy", "Dy")
        mean = {k: np.mean([getattr(lin, k) for lin in lins], axis=0) for k in keys}
        op = dict(lins[0].operating_point)
        op["azimuths"] = self.azimuths.copy()
        return LinearModel(mean["M"], mean["C"], mean["K"], mean["Q"], mean["A"], mean["B"], b.coordinates, b.states,
                           b.inputs, op, b.outputs, mean["Cy"], mean["Dy"], b.output_units, b.method)

    def _to_fixed_frame(self, lin: LinearModel, psi: float, mbc) -> LinearModel:
        from ..wind.analysis.mbc import coleman_matrices, mbc_second_order, mbc_transform

        mbc = mbc or mbc_transform
        om, n = self.rotor_speed, len(lin.coordinates)
        A, B = mbc(lin.A, self.blade_indices, psi, om, B=lin.B)
        M, C, K = mbc_second_order(lin.M, lin.C, lin.K, self.blade_indices, psi, om)
        T = coleman_matrices(n, self.blade_indices, psi)
        Tx = np.block([[T.T1, np.zeros((n, n))], [om * T.T2, T.T1]])
        Q = np.linalg.solve(T.T1, lin.Q)
        return LinearModel(M, C, K, Q, A, B, lin.coordinates, lin.states, lin.inputs, lin.operating_point,
                           lin.outputs, lin.Cy @ Tx, lin.Dy, lin.output_units, lin.method)

    def modes(self, **kw) -> list:
        """Modes of the averaged model (:meth:`average`)."""
        return self.average(**kw).modes()


def linearize_azimuths(model, op: OperatingPoint | None = None, azimuths: int | Sequence[float] = 12, *,
                       coordinate: str | None = None, outputs=None, method: str = "exact", steps=None,
                       qdd0=None) -> AzimuthSweep:
    """Linearize at several azimuths of the spinning coordinate, all in one batch.

    Parameters
    ----------
    model : EquationsOfMotion or model object
    op : OperatingPoint, optional
        E.g. from :func:`steady_rotation`; default: the model's default state and inputs.
    azimuths : int or sequence of float
        A number of equally spaced azimuths over a revolution, starting at the
        operating point's, or the coordinate values themselves [rad].
    coordinate : str, optional, keyword-only
        The spinning coordinate (default ``"GeAz"``).
    outputs, method, steps, qdd0 : optional, keyword-only
        As for :func:`mbsym.linearize`.

    Returns
    -------
    AzimuthSweep
        ``.average()`` gives the azimuth-averaged model (multi-blade coordinates
        with blade DOFs).
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
    offset = _blade1_offset(target, name)
    if not prescribed and "DrTr" in eom.coordinates:
        offset_q = X[:, eom.coordinates.index("DrTr")]
    else:
        offset_q = 0.0
    return AzimuthSweep(psi, psi + offset_q + offset, float(speed), batch, blade_indices(eom.coordinates))


def _blade1_offset(target: Target, name: str) -> float:
    """Azimuth of blade 1 minus the spinning coordinate: ElastoDyn's AzimB1Up + π/2 for a turbine's GeAz."""
    turbine = getattr(target.owner, "turbine", None)
    if name == "GeAz" and turbine is not None and hasattr(turbine, "azimuth_blade1_up"):
        return float(turbine.azimuth_blade1_up + np.pi / 2)
    return 0.0
