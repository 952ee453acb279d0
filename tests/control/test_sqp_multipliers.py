"""The line search's penalty of the Gauss–Newton SQP uses the QP's true multipliers (issue 22 item 14).

Reference: the KKT system of the equality-constrained QP, ``[H Aᵀ; A 0] [Δw; λ] = [−g; b]``, solved
densely with numpy (independent of the SQP code and of the QP solver). Reproduction: CasADi 3.8's hpipm
returns ``lam_a = 0``; the ℓ₁ merit's penalty stayed at μ = 1 while the multipliers of the turbine MHE's
dynamics were ~2400, the line search failed and the first solves after the window filled ended
"infeasible" (11 of the first 11 in the seeded run of the issue).
"""

from __future__ import annotations

import casadi as ca
import numpy as np

from mbsym.control.estimation import EstimationModel
from mbsym.control.mhe import MHE

from test_compile_ahead import DT, large_model


def _mhe(meas_sd: float) -> MHE:
    m = EstimationModel(large_model(), dt=DT, measurements=["pos_meas", "acc_meas"], unknown_inputs=["wind"])
    mhe = MHE(m, window=6, process_noise={"vel": 0.01, "wind": 0.2}, measurement_noise={"pos_meas": meas_sd,
                                                                                         "acc_meas": meas_sd},
              x0=[0.0, 0.0, 5.0], P0={"pos": 0.1, "vel": 0.1, "wind": 2.0}, compile=False)
    z = np.array([0.2, 0.0, 7.0])
    for k in range(6):                          # window not yet full: EKF only
        u = np.array([np.sin(0.4 * k)])
        mhe.step(np.asarray(m.measurement_function(z, u, m.p_rest)).ravel() + 0.01, u)
        z = np.asarray(m.step_function(z, u, m.p_rest)).ravel()
    mhe._data.append(mhe._data[-1])             # a full window of data, solved by hand below
    mhe._history.append(mhe._history[-1])
    return mhe


def test_penalty_is_the_largest_kkt_multiplier_of_the_qp():
    mhe = _mhe(1e-3)                             # small noise: multipliers far above 1
    eng, P = mhe._engine, mhe._P
    D, p = mhe._parameters()
    eng.set_iterate(mhe._initial_window())
    eng.prepare(D, p, P.bounds())
    ok, _, _, _ = eng.feedback(None, apply=False)
    assert ok
    o = eng._out
    H = np.array(ca.DM(eng._H_sp, o["H"]))
    A = np.array(ca.DM(eng._A_sp, o["A"]))
    assert np.allclose(o["lba"], o["uba"])       # the MHE's constraints are its dynamics: equalities
    n, m = H.shape[0], A.shape[0]
    K = np.block([[H, A.T], [A, np.zeros((m, m))]])
    sol = np.linalg.solve(K, np.concatenate([-o["g"], o["lba"]]))
    dw, lam = sol[:n], sol[n:]
    assert np.allclose(eng._dw, dw, rtol=0, atol=1e-8 * max(1.0, np.abs(dw).max()))   # QP solved (hpipm tolerance)
    true = np.abs(lam).max()
    assert true > 10.0                            # the case of the issue: μ = 1 was too small
    assert eng._multipliers_missing()             # what hpipm returns (the line search then asks for them)
    np.testing.assert_allclose(eng._multiplier_norm(stationary=True), true, rtol=1e-5)        # hpipm's step accuracy
