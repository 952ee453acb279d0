"""Point kinematics Functions: closed form of the double pendulum and finite differences.

Reference: positions/velocities of the quick-start double pendulum by hand
(x = -(l1 sin q1 + l2 sin(q1+q2)), z = -(l1 cos q1 + l2 cos(q1+q2))), and the
acceleration as the central difference of the velocity along (qd, qdd), step 1e-6,
tolerance 1e-7.
"""

import numpy as np
import pytest

import mbsym as mb
from mbsym.demo import double_pendulum

P = [2.0, 1.0, 1.0, 0.5]   # m1, m2, l1, l2


@pytest.fixture(scope="module")
def kin():
    return double_pendulum().equations().point_kinematics("b2", [0.0, 0.0, -0.5])


def test_position_velocity_closed_form(kin):
    q, qd = np.array([0.3, -0.2]), np.array([0.1, 0.4])
    r, R, v, w, a, wd = (np.array(x) for x in kin(q, qd, [0, 0], [], P))
    s1, s12, c1, c12 = np.sin(q[0]), np.sin(q.sum()), np.cos(q[0]), np.cos(q.sum())
    np.testing.assert_allclose(r.ravel(), [-(s1 + 0.5 * s12), 0.0, -(c1 + 0.5 * c12)], atol=1e-14)
    xd = -(c1 * qd[0] + 0.5 * c12 * qd.sum())
    zd = s1 * qd[0] + 0.5 * s12 * qd.sum()
    np.testing.assert_allclose(v.ravel(), [xd, 0.0, zd], atol=1e-14)
    np.testing.assert_allclose(w.ravel(), [0.0, qd.sum(), 0.0], atol=1e-14)
    np.testing.assert_allclose(R @ R.T, np.eye(3), atol=1e-14)


def test_acceleration_is_derivative_of_velocity(kin):
    q, qd, qdd = np.array([0.3, -0.2]), np.array([0.1, 0.4]), np.array([-1.2, 0.7])
    h = 1e-6
    vp = np.array(kin(q + h * qd, qd + h * qdd, qdd, [], P)[2])
    vm = np.array(kin(q - h * qd, qd - h * qdd, qdd, [], P)[2])
    a = np.array(kin(q, qd, qdd, [], P)[4])
    np.testing.assert_allclose(a, (vp - vm) / (2 * h), atol=1e-7)
    wd = np.array(kin(q, qd, qdd, [], P)[5])
    np.testing.assert_allclose(wd.ravel(), [0.0, qdd.sum(), 0.0], atol=1e-14)


def test_unknown_body_is_named():
    with pytest.raises(mb.ModelDefinitionError, match="no body named 'b3'"):
        double_pendulum().equations().point_kinematics("b3")
