"""mbsym.linearize: closed forms, finite-difference Jacobians, outputs, state space, errors.

References
----------
- Closed form: the two-mass chain (``conftest.chain``) is linear, so linearizing returns it:
  M = [[m1 + m2, m2], [m2, m2]], C = diag(c1, c2), K = diag(k1, k2), Q = [1, 1]
  (python-control's practice: linearizing a linear system returns it unchanged), exactly (1e-12).
- Central finite differences of the numeric residual/rhs/outputs with h = 1e-6 (truncation
  O(h²), round-off ~eps/h): tolerance 1e-6 relative to the largest entry (Pinocchio: ~√step).
- OpenFAST-style finite differences: central differences with ElastoDyn's steps, computed
  here independently in numpy from the steps table of docs/elastodyn_notes.md §7.
"""

from __future__ import annotations

import numpy as np
import pytest

import mbsym as mb
from mbsym.exceptions import DimensionError, SingularMassMatrixError

from .conftest import central

RTOL = 1e-6


def _close(a, b, rtol=RTOL):
    a, b = np.asarray(a), np.asarray(b)
    assert a.shape == b.shape
    np.testing.assert_allclose(a, b, rtol=0, atol=rtol * max(1.0, float(np.max(np.abs(b)))))


def test_linear_system_returns_itself(chain_eom):
    p = dict(chain_eom.defaults)
    lin = mb.linearize(chain_eom, [0.3, -0.1], [0.5, 0.2], [2.0])
    m1, m2, k1, k2, c1, c2 = (p[n] for n in ("m1", "m2", "k1", "k2", "c1", "c2"))
    M = np.array([[m1 + m2, m2], [m2, m2]])
    K, C = np.diag([k1, k2]), np.diag([c1, c2])
    np.testing.assert_allclose(lin.M, M, atol=1e-12)
    np.testing.assert_allclose(lin.C, C, atol=1e-12)
    np.testing.assert_allclose(lin.K, K, atol=1e-12)
    np.testing.assert_allclose(lin.Q, [[1.0], [1.0]], atol=1e-12)
    Minv = np.linalg.inv(M)
    A = np.block([[np.zeros((2, 2)), np.eye(2)], [-Minv @ K, -Minv @ C]])
    np.testing.assert_allclose(lin.A, A, atol=1e-12)
    np.testing.assert_allclose(lin.B, np.vstack([np.zeros((2, 1)), Minv @ [[1.0], [1.0]]]), atol=1e-12)
    # and the state space built from it is the same system
    ss = lin.to_statespace()
    np.testing.assert_allclose(ss.A, A, atol=1e-12)
    np.testing.assert_allclose(ss.C, np.eye(4))


def test_positional_signature_and_qdd0_kept(pendulum_eom):
    """The historical call ``linearize(eom, q0, qd0, u0, p, qdd0=...)`` still works."""
    q, qd = [0.4, -0.3], [0.1, 0.2]
    lin = mb.linearize(pendulum_eom, q, qd, [0.7], {"m1": 2.5})
    assert lin.operating_point["p"]["m1"] == 2.5
    np.testing.assert_array_equal(lin.operating_point["qdd"], [0.0, 0.0])
    qdd = pendulum_eom.accelerations(q, qd, [0.7], {"m1": 2.5})
    lin2 = mb.linearize(pendulum_eom, q, qd, {"tau": 0.7}, {"m1": 2.5}, qdd0=qdd)
    np.testing.assert_allclose(lin2.A, lin.A, atol=1e-12)          # A never depends on qdd0
    np.testing.assert_allclose(lin2.M, lin.M, atol=1e-12)
    assert not np.allclose(lin2.K, lin.K)                           # K does: -∂e/∂q at qdd0


def test_residual_jacobians_against_finite_differences(pendulum_eom):
    eom = pendulum_eom
    q, qd, qdd, u = np.array([0.4, -0.9]), np.array([0.3, -0.2]), np.array([0.5, 1.0]), np.array([0.7])
    lin = mb.linearize(eom, q, qd, u, qdd0=qdd)
    e = eom.residual
    _close(lin.K, -central(lambda z: e(z, qd, qdd, u), q, 1e-6))
    _close(lin.C, -central(lambda z: e(q, z, qdd, u), qd, 1e-6))
    _close(lin.M, -central(lambda z: e(q, qd, z, u), qdd, 1e-6))
    _close(lin.Q, central(lambda z: e(q, qd, qdd, z), u, 1e-6))


def test_first_order_jacobians_against_finite_differences(pendulum_eom):
    """A, B are the Jacobians of the nonlinear rhs, also away from equilibrium (q̈_op ≠ 0)."""
    eom = pendulum_eom
    x, u = np.array([0.4, -0.9, 0.3, -0.2]), np.array([0.7])
    lin = mb.linearize(eom, x[:2], x[2:], u)
    _close(lin.A, central(lambda z: eom.rhs(z, u), x, 1e-6))
    _close(lin.B, central(lambda z: eom.rhs(x, z), u, 1e-6))
    # with qdd0="rhs", M, C, K are consistent with A exactly
    lin2 = mb.linearize(eom, x[:2], x[2:], u, qdd0="rhs")
    Minv = np.linalg.inv(lin2.M)
    np.testing.assert_allclose(lin2.A[2:], np.hstack([-Minv @ lin2.K, -Minv @ lin2.C]), atol=1e-10)
    np.testing.assert_allclose(lin2.B[2:], Minv @ lin2.Q, atol=1e-12)
    np.testing.assert_allclose(lin2.operating_point["qdd"], eom.accelerations(x[:2], x[2:], u), atol=1e-12)


def test_turbine_jacobians_and_outputs_against_finite_differences(paper45):
    """paper45 (3 DOF, tower SIDs): A, B and C, D of OpenFAST-named channels, at a deflected, spinning state."""
    eom = paper45.eom
    x = np.array([0.3, -0.2, 1.0, 0.05, 0.02, 0.6])
    u = np.array([1e3, 2e5, 3e5])              # GenTq, RotTorq, RotThrust
    names = ["TTDspFA", "QD2_TFA1", "RotSpeed", "GenSpeed", "YawBrTDyp"]
    lin = mb.linearize(paper45, x[:3], x[3:], u, outputs=names)
    _close(lin.A, central(lambda z: eom.rhs(z, u), x, 1e-6))
    _close(lin.B, central(lambda z: eom.rhs(x, z), u, 1e-2), rtol=1e-6)     # rhs is linear in u
    f = paper45.output_function()
    rows = [f.names.index(n) for n in names]
    y = lambda z, v: np.array(f.function(z, v, eom.parameter_vector())).reshape(-1)[rows]  # noqa: E731
    _close(lin.Cy, central(lambda z: y(z, u), x, 1e-6))
    _close(lin.Dy, central(lambda z: y(x, z), u, 1e-2))
    np.testing.assert_allclose(lin.operating_point["y"], y(x, u), rtol=1e-12)
    assert lin.output_units == ("m", "m/s^2", "rpm", "rpm", "m")


def test_elastodyn_fd_is_central_differences_with_elastodyn_steps(paper46):
    """method='elastodyn-fd' = central differences of the rhs with ElastoDyn's steps (notes §7)."""
    eom, t = paper46.eom, paper46.turbine
    deg = np.pi / 180
    steps = {"Sg": 0.2 * deg * t.tower_height, "P": 2 * deg,
             "TFA1": 0.02 * deg * (t.tower_height - t.tower_base_height)}
    h = np.array([steps[c] for c in eom.coordinates] * 2)
    x0 = paper46.initial_state()
    u = np.zeros(eom.n_u)
    A_ref = central(lambda z: eom.rhs(z, u), x0, h)
    lin = mb.linearize(paper46, method="elastodyn-fd")
    np.testing.assert_allclose(lin.A, A_ref, rtol=1e-12, atol=1e-12)
    assert mb.linear.elastodyn_steps(paper46) == pytest.approx(steps, rel=1e-15)
    lin_fd = mb.linearize(paper46, method="fd", steps=steps)
    np.testing.assert_array_equal(lin_fd.A, lin.A)
    exact = mb.linearize(paper46, method="exact")
    assert np.max(np.abs(exact.A - lin.A)) > 1.0          # the 2° platform step matters (notes §8.3)


def test_free_dof_is_a_rigid_body_mode_not_an_error():
    """A DOF with mass but no stiffness (singular K) gives a rigid-body mode of frequency 0."""
    sys = mb.System()
    x, y = sys.coordinates("x y")
    b1, b2 = mb.RigidBody("b1", 1.0), mb.RigidBody("b2", 2.0)
    sys.add_joint(mb.Prismatic(sys.ground, b1, axis=[1, 0, 0], coordinate=x))   # free
    sys.add_joint(mb.Prismatic(b1, b2, axis=[0, 1, 0], coordinate=y))
    sys.add_spring(y, 8.0)
    lin = mb.linearize(sys.equations(), [0.0, 0.0])
    modes = lin.modes()
    assert [m.rigid_body for m in modes] == [True, False]
    assert modes[0].freq_hz == 0.0 and modes[0].dominant_dof == "x"
    assert modes[1].freq_hz == pytest.approx(np.sqrt(8.0 / 2.0) / (2 * np.pi), rel=1e-12)
    assert modes[1].dominant_dof == "y"


def test_named_signals_round_trip(paper45):
    lin = mb.linearize(paper45, outputs=["TTDspFA_[m]", "RotSpeed", "TSS1_d"])
    ss = lin.to_statespace(name="paper45")
    assert ss.state_labels == list(paper45.eom.states)
    assert ss.input_labels == ["GenTq", "RotTorq", "RotThrust"]
    assert ss.output_labels == ["TTDspFA", "RotSpeed", "TSS1_d"]
    np.testing.assert_array_equal(ss.C[2], np.eye(6)[4])                    # a state as an output
    sub = ss[["RotSpeed"], ["GenTq"]]                                        # python-control indexing by name
    np.testing.assert_array_equal(sub.B, lin.B[:, :1])
    np.testing.assert_array_equal(sub.C, lin.Cy[1:2])
    op = ss.operating_point
    np.testing.assert_array_equal(op["x"], paper45.initial_state())
    assert op["p"]["tower_stiffness_scale"] == 1.0
    assert set(op) >= {"q", "qd", "qdd", "u", "x", "xd", "y", "p"}


@pytest.mark.parametrize("kwargs, error, match", [
    ({"outputs": ["NoSuchChannel"]}, DimensionError, "unknown outputs"),
    ({"method": "spline"}, ValueError, "unknown linearization method"),
    ({"method": "fd"}, TypeError, "needs steps"),
    ({"steps": [1e-3] * 2}, TypeError, "only with method='fd'"),
    ({"method": "fd", "steps": [1e-3]}, DimensionError, "steps must be"),
    ({"qdd0": "equilibrium"}, ValueError, "qdd0 must be"),
    ({"method": "elastodyn-fd"}, mb.ModelDefinitionError, "supplies ElastoDyn.s steps"),
])
def test_errors(pendulum_eom, kwargs, error, match):
    with pytest.raises(error, match=match):
        mb.linearize(pendulum_eom, [0.0, 0.0], **kwargs)


def test_singular_mass_matrix_is_named():
    sys = mb.System()
    x = sys.coordinates("x")
    sys.add_joint(mb.Prismatic(sys.ground, mb.RigidBody("massless", 0.0), axis=[1, 0, 0], coordinate=x))
    sys.add_spring(x, 1.0)
    with pytest.raises(SingularMassMatrixError, match=r"\['x'\]"):
        mb.linearize(sys.equations(), [0.0])


def test_model_without_eom_is_rejected():
    with pytest.raises(TypeError, match="EquationsOfMotion"):
        mb.linearize(object(), [0.0])


def _response_error(model, op, lin, ss, delta, t):
    """max |y_nonlinear - y0 - y_linear| and max |y_linear| for an initial perturbation delta."""
    import control

    res = mb.simulate(model, float(t[-1]), x0=op.x + delta, inputs=op.u, method="cvodes", rtol=1e-11,
                      atol=1e-13, t_out=t)
    rows = [res.output_names.index(n) for n in lin.outputs]
    y_nl = res.y[:, rows] - lin.operating_point["y"]
    y_lin = control.initial_response(ss, T=t, X0=delta).outputs.T
    return np.max(np.abs(y_nl - y_lin)), np.max(np.abs(y_lin))


def test_nonlinear_simulation_vs_linear_response(paper45):
    """paper45 about its static equilibrium: a tower-top perturbation of a few mm, 20 s.

    The linear model's response (python-control initial_response) follows the nonlinear
    simulation (CVODES, rtol 1e-11) to within 1 % of the response, and the difference is
    second order: halving the perturbation divides it by ~4 (3 to 5 accepted).
    """
    from mbsym.linear import static_equilibrium

    op = static_equilibrium(paper45)
    assert op.success, op.message
    lin = mb.linearize(paper45, op, outputs=["TTDspFA", "TTDspSS", "QD2_TFA1", "YawBrTDxp"], method="exact")
    ss = lin.to_statespace()
    t = np.linspace(0.0, 20.0, 401)
    delta = np.array([4e-3, -3e-3, 0.0, 0.0, 2e-3, 0.0])
    err1, amp1 = _response_error(paper45, op, lin, ss, delta, t)
    err2, amp2 = _response_error(paper45, op, lin, ss, delta / 2, t)
    assert err1 < 1e-2 * amp1
    assert 3.0 < err1 / err2 < 5.0


@pytest.mark.parametrize("steps, match", [
    ({"q1": 0.0, "q2": 1e-6}, r"positive finite.*'q1': 0\.0"),
    ({"q1": 1e-6, "q2": -1e-6}, r"positive finite.*'q2': -1e-06"),
    ({"q1": np.nan, "q2": 1e-6}, r"positive finite.*'q1': nan"),
    ({"q1": 1e-6}, r"missing \['q2'\]"),
    ({"q1": 1e-6, "q2": 1e-6, "q3": 1e-6}, r"unknown \['q3'\]"),
])
def test_step_dict_is_validated(pendulum_eom, steps, match):
    """Finite-difference steps by name: every coordinate, finite and > 0, bad ones named."""
    with pytest.raises(DimensionError, match=match):
        mb.linearize(pendulum_eom, [0.1, 0.2], method="fd", steps=steps)
    lin = mb.linearize(pendulum_eom, [0.1, 0.2], method="fd", steps={"q1": 1e-6, "q2": 1e-6})
    _close(lin.A, mb.linearize(pendulum_eom, [0.1, 0.2]).A)          # central differences, h = 1e-6


def _cache_exercise(eom):
    from mbsym.linear import linearize_batch, sensitivities
    from mbsym.linear import static_equilibrium

    mb.linearize(eom, [0.1, 0.2], outputs=["q1"])
    mb.linearize(eom, [0.1, 0.2], qdd0=[0.3, -0.2])
    mb.linearize(eom, [0.1, 0.2], method="fd", steps=[1e-6, 1e-6])
    sensitivities(eom, ["m1"], [0.1, 0.2])
    sensitivities(eom, ["m1"], [0.1, 0.2], method="fd", steps=[1e-6, 1e-6])
    linearize_batch(eom, np.zeros((2, 4)), qdd0=np.ones((2, 2)))
    static_equilibrium(eom, [0.0])


def test_derived_functions_live_in_one_private_cache():
    """Linearizing leaves the model unchanged except one private dict; a second use builds nothing."""
    from mbsym.linear import jacobian_function, linear_function

    from .conftest import double_pendulum

    eom = double_pendulum()
    before = dict(vars(eom))
    _cache_exercise(eom)
    after = vars(eom)
    assert set(after) - set(before) == {"_mbsym_cache"}
    assert all(after[k] is v for k, v in before.items())
    cache = after["_mbsym_cache"]
    size = len(cache)
    assert jacobian_function(eom) is jacobian_function(eom) and linear_function(eom) is linear_function(eom)
    _cache_exercise(eom)
    assert len(cache) == size


def test_jacobian_function_is_the_residual_jacobian(pendulum_eom):
    """Against an independent derivation: CasADi's jacobian of e = F - M qdd (M depends on q), 1e-12."""
    import casadi as ca

    from mbsym.linear import jacobian_function

    d = pendulum_eom.symbolic
    e = d.F - d.M @ d.qdd
    ref = ca.Function("ref", [d.q, d.qd, d.qdd, d.u, d.p],
                      [-ca.jacobian(e, d.qdd), -ca.jacobian(e, d.qd), -ca.jacobian(e, d.q), ca.jacobian(e, d.u)])
    rng = np.random.default_rng(4)
    pp = pendulum_eom.parameter_vector()
    for _ in range(3):
        args = [rng.normal(size=2), rng.normal(size=2), rng.normal(size=2), rng.normal(size=1), pp]
        for got, want in zip(jacobian_function(pendulum_eom)(*args), ref(*args)):
            _close(np.array(got), np.array(ca.densify(want)), rtol=1e-12)


def test_one_symbolic_derivation_for_both_linearization_functions(monkeypatch):
    """jacobian_function and linear_function share one common-subexpression pass per model."""
    import casadi as ca

    from mbsym.linear import jacobian_function, linear_function

    from .conftest import double_pendulum

    eom = double_pendulum()
    calls = []
    cse = ca.cse
    monkeypatch.setattr(ca, "cse", lambda *a, **k: calls.append(1) or cse(*a, **k))
    linear_function(eom)
    jacobian_function(eom)
    assert len(calls) == 1
