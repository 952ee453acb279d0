"""The accuracy-driven default of simulate (issue 10.3): error bound met against independent references.

References: the damped oscillator's closed form (``_reference.sdof_response``, textbook solution); the
pendulum and the stiff two-mass chain against cvodes at rtol = atol = 1e-12 (its error is ~1e-10, four
orders below the bounds checked); RK4's stability limits on the real and imaginary axes (2.785 and
2*sqrt(2), roots of |1 + z + z^2/2 + z^3/6 + z^4/24| = 1, Hairer & Wanner, Solving ODEs II, Fig. IV.2.1).
Tolerances: the achieved error must be below the requested accuracy (the contract); the a-posteriori
estimate must be within a factor 3 of the achieved error (Richardson is asymptotically exact).
"""

import numpy as np
import pytest

import mbsym as mb
from mbsym import codegen
from mbsym.simulate import SimulationOptionError, simulate
from mbsym.simulate import auto
from mbsym.simulate.auto import epsilon, predict_rk4_error, rk4_stability_limit

from ._reference import sdof_response
from .conftest import OSC, pendulum

M, K, C = OSC["m"], OSC["k"], OSC["c"]


def _closed_form_error(res):
    x, v = sdof_response(res.t, M, C, K, x0=0.1, v0=-0.3)
    return epsilon(res.x, np.column_stack([x, v]))


@pytest.mark.parametrize("accuracy", [1e-2, 1e-3, 1e-5, 1e-7])
def test_oscillator_meets_the_requested_accuracy(osc, accuracy):
    res = simulate(osc, 10.0, x0=[0.1, -0.3], accuracy=accuracy)
    achieved = _closed_form_error(res)
    s = res.statistics
    assert achieved <= accuracy, (achieved, s["selection"])
    assert achieved >= accuracy / 200                      # least cost: not far more accurate than asked
    assert s["error_estimate"] / 3 <= achieved <= 3 * s["error_estimate"]
    assert s["method"] == "rk4" and s["accuracy"] == accuracy


def test_default_accuracy_is_1e_3(osc):
    res = simulate(osc, 10.0, x0=[0.1, -0.3])
    assert res.statistics["accuracy"] == 1e-3 and _closed_form_error(res) <= 1e-3


def test_linear_prediction_is_rk4s_error_on_a_linear_model(osc):
    """On a linear model the prediction (RK4's stability polynomial vs the exponential) is the error itself."""
    J = np.array([[0.0, 1.0], [-K / M, -C / M]])
    t_out = np.linspace(0.0, 10.0, 1001)
    for h in (0.05, 0.1, 0.2):
        res = simulate(osc, 10.0, x0=[0.1, -0.3], method="rk4", dt=h, t_out=t_out)
        x, v = sdof_response(t_out, M, C, K, x0=0.1, v0=-0.3)
        measured = epsilon(res.x, np.column_stack([x, v]))
        # the prediction starts from the initial deviation: y' = J y + f0 with f0 = J x0
        predicted = predict_rk4_error(J, J @ np.array([0.1, -0.3]), 10.0, h)
        assert predicted == pytest.approx(measured, rel=0.15), (h, predicted, measured)


def test_rk4_stability_limits():
    assert rk4_stability_limit(np.array([-1.0])) == pytest.approx(2.7853, abs=1e-4)
    assert rk4_stability_limit(np.array([2j, -2j])) == pytest.approx(np.sqrt(2), abs=1e-6)   # 2 sqrt(2) / 2
    assert rk4_stability_limit(np.array([0.0, 1e-12])) == np.inf                           # rigid-body modes


def test_nonlinear_pendulum_is_refined_by_the_check():
    """Released at 2 rad the linearization is unstable (cos 2 < 0) and mispredicts the step; the step-doubling
    check catches it and refines until the estimate meets the accuracy."""
    pend = pendulum()
    res = simulate(pend, 20.0, x0=[2.0, 0.0], accuracy=1e-3)
    ref = simulate(pend, 20.0, x0=[2.0, 0.0], method="cvodes", rtol=1e-12, atol=1e-12, t_out=res.t)
    assert epsilon(res.x, ref.x) <= 1e-3
    assert "refined" in res.statistics["selection"]
    assert res.statistics["error_estimate"] <= 1e-3


def stiff_chain():
    """Two masses: a slow mode (1 rad/s) and a stiff, strongly damped one (k2 = 1e6 N/m): rk4 stability-bound."""
    sys = mb.System()
    x1, x2 = sys.coordinates("x1 x2")
    sys.add_joint(mb.Prismatic(sys.ground, b1 := mb.RigidBody("b1", 1.0), axis=[1, 0, 0], coordinate=x1))
    sys.add_joint(mb.Prismatic(b1, mb.RigidBody("b2", 1.0), axis=[1, 0, 0], coordinate=x2))
    sys.add_spring(x1, 1.0)
    sys.add_spring(x2, 1e6)
    sys.add_damper(x2, 2e3)
    return sys.equations(name="stiff_chain")


def test_stiff_model_goes_to_bdf():
    eom = stiff_chain()
    res = simulate(eom, 20.0, x0=[0.5, 0.0, 0.0, 0.0], accuracy=1e-3)
    ref = simulate(eom, 20.0, x0=[0.5, 0.0, 0.0, 0.0], method="cvodes", rtol=1e-12, atol=1e-12, t_out=res.t)
    assert res.statistics["method"] == "cvodes" and "stiff" in res.statistics["selection"]
    assert epsilon(res.x[:, [0, 2]], ref.x[:, [0, 2]]) <= 1e-3          # the moving states
    assert res.statistics["error_estimate"] is not None


def test_outputs_between_steps_are_interpolated(osc):
    """The step is decoupled from the output spacing: 1 ms outputs, a step of ~0.07 s."""
    t_out = np.linspace(0.0, 10.0, 10001)
    res = simulate(osc, 10.0, x0=[0.1, -0.3], t_out=t_out)
    assert res.statistics["dt"] > 50 * (t_out[1] - t_out[0])
    assert _closed_form_error(res) <= 1e-3


def test_explicit_choices_are_honoured_exactly(osc):
    r = simulate(osc, 1.0, x0=[0.1, 0.0], method="rk4", dt=0.01)
    assert r.statistics["method"] == "rk4" and r.statistics["steps"] == 100 and r.statistics["dt"] == 0.01
    r = simulate(osc, 1.0, x0=[0.1, 0.0], dt=0.05)                     # dt alone: rk4 with that step
    assert r.statistics["method"] == "rk4" and r.statistics["dt"] == 0.05 and "accuracy" not in r.statistics
    r = simulate(osc, 1.0, x0=[0.1, 0.0], rtol=1e-7)                   # tolerances alone: cvodes
    assert r.statistics["method"] == "cvodes" and r.statistics["rtol"] == 1e-7
    r = simulate(osc, 1.0, x0=[0.1, 0.0], method="cvodes")
    assert r.statistics["rtol"] == 1e-6 and not r.statistics["compiled"]


@pytest.mark.parametrize("kwargs, match", [
    ({"accuracy": 1e-3, "method": "rk4"}, "cannot be combined with method='rk4'"),
    ({"accuracy": 1e-3, "dt": 0.01}, "cannot be combined with dt=0.01"),
    ({"accuracy": 1e-3, "rtol": 1e-6}, "cannot be combined with rtol"),
    ({"accuracy": 0.0}, "accuracy must be a positive"),
    ({"accuracy": 2.0}, r"outside \[1e-10, 0.5\]"),
    ({"accuracy": 1e-14}, r"outside \[1e-10, 0.5\]"),
    ({"accuracy": "high"}, "accuracy must be a positive number"),
])
def test_bad_accuracy_options(osc, kwargs, match):
    with pytest.raises(SimulationOptionError, match=match):
        simulate(osc, 1.0, **kwargs)


def test_compile_must_be_a_bool_or_none(osc):
    with pytest.raises(TypeError, match="compile must be True, False or None"):
        simulate(osc, 1.0, compile="auto")


@pytest.mark.skipif(codegen.find_compiler() is None, reason="no C compiler")
def test_compiles_from_the_disk_cache_once_warmed(osc, tmp_path, monkeypatch):
    """Below the threshold nothing is compiled; with the threshold at 0 the first run warms the disk cache in
    the background and the next one (a new process would do the same) runs compiled; results agree to 1e-12."""
    monkeypatch.setenv("MBSYM_CACHE_DIR", str(tmp_path))
    monkeypatch.delenv("MBSYM_NO_COMPILE", raising=False)
    first = simulate(osc, 10.0, x0=[0.1, -0.3])
    assert not first.statistics["compiled"] and not first.statistics["background_compile"]
    monkeypatch.setattr(auto, "BACKGROUND_COMPILE_MIN_S", 0.0)
    warm = simulate(osc, 10.0, x0=[0.1, -0.3])
    assert warm.statistics["background_compile"] and not warm.statistics["compiled"]
    codegen.wait_for_background()
    again = simulate(osc, 10.0, x0=[0.1, -0.3])
    assert again.statistics["compiled"] and "disk cache" in again.statistics["compile_choice"]
    np.testing.assert_allclose(again.x, warm.x, rtol=0, atol=1e-12)


def test_no_compile_environment_is_respected(osc, monkeypatch):
    monkeypatch.setenv("MBSYM_NO_COMPILE", "1")
    monkeypatch.setattr(auto, "BACKGROUND_COMPILE_MIN_S", 0.0)
    res = simulate(osc, 10.0, x0=[0.1, -0.3])
    assert not res.statistics["compiled"] and not res.statistics["background_compile"]
    assert "unavailable" in res.statistics["compile_choice"]
