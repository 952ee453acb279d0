"""A stated deadline per NMPC step (issue 22 item 14): a late solution is not applied, the miss is counted.

References: the previous step's own plan (``NMPC.prediction()``): a step that misses its deadline applies
that plan's next input, exactly; the exact discrete double integrator (RK4 is exact for it), on
which the loop with every step late is a one-sample-delayed MPC that must still bring the state to
the origin. Speed is not asserted: a deadline of 0 s makes every step after the first late.
"""

import math

import numpy as np
import pytest

from mbsym.control import NMPC
from mbsym.exceptions import ControlDefinitionError

from test_failures import base_ocp

A = np.array([[1.0, 0.1], [0.0, 1.0]])            # exact 0.1 s map of the double integrator (RK4 is exact)
B = np.array([0.005, 0.1])


def test_late_steps_apply_the_previous_plan_and_are_counted():
    mpc = NMPC(base_ocp(), compile=False, deadline=0.0)
    x = np.array([1.0, 0.0])
    u = mpc.step(x)                                # the start-up: not held to the deadline
    assert mpc.stats[-1].success and mpc.deadline_misses == 0
    for k in range(150):
        plan = mpc.prediction()["u"][0].copy()
        x = A @ x + B * u[0]
        u = mpc.step(x)
        st = mpc.stats[-1]
        assert st.fallback and st.status.startswith("fallback (deadline missed") and not st.success
        np.testing.assert_allclose(u, [plan[1]], rtol=0, atol=1e-12)      # the previous plan's next input
    assert mpc.deadline_misses == 150 and mpc.failures == 0
    s = mpc.summary()
    assert s["deadline_misses"] == 150 and s["deadline_s"] == 0.0
    # every input one sample late: the loop still settles at the target within 15 s (|u| <= 0.1 m/s² needs ~6 s
    # to cross 1 m): below 1 % of the 1 m start (on time: 0.11 %, late: 0.24 %, measured)
    assert abs(x[0]) < 0.01 and abs(x[1]) < 0.01


def test_no_deadline_by_default_and_bad_deadlines_refused():
    mpc = NMPC(base_ocp(), compile=False)
    for _ in range(3):
        mpc.step([1.0, 0.0])
    assert mpc.deadline is None and mpc.deadline_misses == 0 and all(s.success for s in mpc.stats)
    for bad in (-1.0, math.nan, "fast"):
        with pytest.raises(ControlDefinitionError, match="deadline"):
            NMPC(base_ocp(), compile=False, deadline=bad)
    with pytest.raises(Exception, match="hold"):
        NMPC(base_ocp(), compile=False, hold=[0.0, 1.0])
