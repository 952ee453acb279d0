"""The EKF's side of the exported NMPC (:mod:`.sample`): its sample and its start table as CasADi Functions.

- :func:`ekf_function`: ``(z, P, y, u, predict) -> (z, P)``, one sample of :meth:`mbsym.control.EKF.step` (the
  time update over the last interval with the mean measured pitch and torque ``u``, skipped when ``predict`` is 0,
  then the measurement update with ``y``), plain arithmetic in C;
- :func:`init_function`: ``wind -> z``, the estimate of steady operation at a hub wind (a table every
  :data:`INIT_STEP` m/s over the NMPC's reference winds, interpolated linearly, the wind clipped to that range): the
  estimator's start and restart.
"""

from __future__ import annotations

import casadi as ca
import numpy as np

from .sample_mhe import small_solve

__all__ = ["INIT_STEP", "ekf_function", "init_function"]

#: Wind step of the steady-estimate table of ``init`` [m/s].
INIT_STEP = 1.0


def init_function(estimator, grid: np.ndarray, settings) -> ca.Function:
    """``wind -> z``: steady estimates every :data:`INIT_STEP` m/s over ``grid``'s range, interpolated linearly."""
    from .estimator import steady_estimate

    lo, hi = float(grid[0]), float(grid[-1])
    winds = np.unique(np.append(np.arange(lo, hi, INIT_STEP), hi))
    table = np.array([estimator.complete(steady_estimate(estimator.prediction, u, settings=settings)) for u in winds])
    wind = ca.MX.sym("wind")
    w = ca.fmin(ca.fmax(wind, lo), hi)
    rows = [ca.interpolant(f"init_{i}", "linear", [winds], table[:, i])(w) for i in range(table.shape[1] - 1)]
    return ca.Function("nmpc_init", [wind], [ca.vertcat(*rows, w)], ["wind"], ["z"])


def ekf_function(estimator) -> ca.Function:
    """``(z, P, y, u, predict) -> (z, P)``: :meth:`mbsym.control.EKF.step` as one Function."""
    from ...control import EstimationModel

    m = estimator.model
    # a fresh, uncompiled copy: the filter's own linearization may be a compiled library (no graph to generate)
    lin = EstimationModel(estimator.dynamics, dt=estimator.dt, measurements=m.measurements,
                          unknown_inputs=m.unknown_inputs, compile=False).linearization
    f = getattr(estimator.filter, "_ekf", estimator.filter)         # an MHE's own EKF
    n, ny, nu = m.n_z, m.n_y, len(m.known_inputs)
    z, y, u, flag = ca.MX.sym("z", n), ca.MX.sym("y", ny), ca.MX.sym("u", nu), ca.MX.sym("predict")
    P = ca.MX.sym("P", n, n)
    pr = ca.DM(m.p_rest)
    zn, F, _, _ = lin(z, u, pr)
    zp = ca.if_else(flag, zn, z)
    Pp = ca.if_else(flag, ca.mtimes([F, P, F.T]) + ca.DM(f.Q), P)
    _, _, yh, H = lin(zp, u, pr)
    R = ca.DM(f.R)
    S = ca.mtimes([H, Pp, H.T]) + R
    HP = ca.mtimes(H, Pp)
    K = small_solve(S, HP).T
    I_KH = ca.DM.eye(n) - ca.mtimes(K, H)
    z_new = zp + ca.mtimes(K, y - yh)
    P_new = ca.mtimes([I_KH, Pp, I_KH.T]) + ca.mtimes([K, R, K.T])
    return ca.Function("nmpc_ekf", [z, P, y, u, flag], [z_new, P_new], ["z", "P", "y", "u", "predict"], ["z_next", "P_next"])
