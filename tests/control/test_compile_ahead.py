"""Shorter cold starts (issue 22 item 8): chained step Jacobians of estimation models, compilations in the background.

References: central finite differences of the RK4 step (step 1e-6, error ~1e-10 for these smooth
maps) and CasADi's own Jacobian of the expanded step (two independent differentiations of one map);
the MHE built on the expanded Jacobian (the formulation used before) for the chained one; the
virtual machine's evaluation for a compiled library. Reproduction: before the fix the turbine
estimator's linearization expanded the Jacobian of its RK4 step (95 000 SX instructions, 7.7 MB of C,
~90 s of gcc) and every library compiled one after the other, silently.
"""

from __future__ import annotations

import importlib

import casadi as ca
import numpy as np
import pytest

import mbsym as mb
from mbsym.control.estimation import EstimationModel
from mbsym.control.mhe import MHE

disc_module = importlib.import_module("mbsym.control.discretize")     # the module, not the function
DT = 0.05


def large_model() -> mb.Dynamics:
    """A damped oscillator driven by an unknown wind-like input through a 60-term series (> 500 SX instructions)."""
    x, u, p = ca.SX.sym("x", 2), ca.SX.sym("u", 2), ca.SX.sym("p", 1)
    series = sum(ca.sin(k * 0.05 * x[0] + 0.01 * k * u[0]) / k ** 2 for k in range(1, 61))
    rhs = ca.vertcat(x[1], -p[0] * x[0] - 0.4 * x[1] + series + 0.1 * u[0] ** 2 + u[1])
    f = ca.Function("large", [x, u, p], [rhs])
    y = ca.Function("large_y", [x, u, p], [ca.vertcat(x[0], rhs[1])])
    return mb.Dynamics(f, states=["pos", "vel"], inputs=["wind", "force"], parameters=["k"], defaults={"k": 4.0},
                       outputs=y, output_names=["pos_meas", "acc_meas"])


def test_large_rhs_gets_a_chained_step_jacobian_equal_to_finite_differences():
    dyn = large_model()
    assert dyn.rhs.n_instructions() > disc_module.CHAIN_THRESHOLD
    m = EstimationModel(dyn, dt=DT, measurements=["pos_meas", "acc_meas"], unknown_inputs=["wind"])
    assert m.step_jacobian is not None
    z, u = np.array([0.3, -0.2, 7.0]), np.array([0.5])
    zn, F, y, H = (np.asarray(v, dtype=float) for v in m.linearization(z, u, m.p_rest))
    assert np.allclose(zn.ravel(), np.asarray(m.step_function(z, u, m.p_rest)).ravel(), rtol=0, atol=1e-14)
    h = 1e-6
    F_fd = np.column_stack([(np.asarray(m.step_function(z + h * e, u, m.p_rest)) -
                             np.asarray(m.step_function(z - h * e, u, m.p_rest))).ravel() / (2 * h)
                            for e in np.eye(3)])
    assert np.allclose(F, F_fd, rtol=0, atol=1e-8)                 # central differences: error ~h² and 1e-16/h
    zs, us, ps = ca.SX.sym("z", 3), ca.SX.sym("u", 1), ca.SX.sym("p", 1)
    F_ad = ca.Function("F", [zs, us, ps], [ca.jacobian(m.step_function(zs, us, ps), zs)])(z, u, m.p_rest)
    assert np.allclose(F, np.asarray(F_ad), rtol=0, atol=1e-12)     # same derivative, other route: rounding only
    assert np.allclose(y.ravel(), np.asarray(m.measurement_function(z, u, m.p_rest)).ravel(), atol=1e-14)
    assert H.shape == (2, 3) and np.allclose(H[0], [1.0, 0.0, 0.0])


def test_estimated_parameters_keep_the_expanded_jacobian():
    m = EstimationModel(large_model(), dt=DT, measurements=["pos_meas"], unknown_inputs=["wind"], parameters=["k"])
    assert m.step_jacobian is None                                   # chained sensitivities have no ∂/∂p
    assert np.asarray(m.linearization([0.1, 0.0, 6.0, 4.0], [0.0], m.p_rest)[1]).shape == (4, 4)


def _mhe_estimates(monkeypatch, threshold: int) -> tuple[np.ndarray, bool]:
    monkeypatch.setattr(disc_module, "CHAIN_THRESHOLD", threshold)
    dyn = large_model()
    m = EstimationModel(dyn, dt=DT, measurements=["pos_meas", "acc_meas"], unknown_inputs=["wind"])
    mhe = MHE(m, window=8, process_noise={"vel": 0.01, "wind": 0.2}, measurement_noise={"pos_meas": 0.01,
                                                                                         "acc_meas": 0.05},
              x0=[0.0, 0.0, 5.0], P0={"pos": 0.1, "vel": 0.1, "wind": 2.0}, compile=False)
    sim = EstimationModel(dyn, dt=DT, measurements=["pos_meas", "acc_meas"], unknown_inputs=["wind"])
    z, out = np.array([0.2, 0.0, 7.0]), []
    for k in range(20):
        u = np.array([np.sin(0.4 * k)])
        out.append(mhe.step(np.asarray(sim.measurement_function(z, u, sim.p_rest)).ravel(), u))
        z = np.asarray(sim.step_function(z, u, sim.p_rest)).ravel()
    return np.array(out), mhe._P.dynamics_jacobian is not None


def test_mhe_on_the_chained_jacobian_equals_the_mhe_on_the_expanded_one(monkeypatch):
    chained, has_chain = _mhe_estimates(monkeypatch, 500)
    expanded, has_none = _mhe_estimates(monkeypatch, 10 ** 9)
    assert has_chain and not has_none
    # same QPs up to rounding of two derivative routes; 20 real-time iterations amplify it little
    assert np.allclose(chained, expanded, rtol=0, atol=1e-9)


@pytest.fixture
def cache(tmp_path, monkeypatch):
    from mbsym import codegen

    if codegen.compiler_command() is None or codegen.compile_disabled():
        pytest.skip("no C compiler (or MBSYM_NO_COMPILE): nothing compiles")
    monkeypatch.setenv("MBSYM_CACHE_DIR", str(tmp_path))
    return tmp_path


def test_background_compilation_reports_what_it_compiles_then_loads_from_the_cache(cache):
    from mbsym.codegen_async import compile_async, pending_compilations, wait_for_compilations

    x = ca.SX.sym("x", 3)
    f = ca.Function("ahead_probe", [x], [ca.sin(x) * ca.exp(x[0]) + ca.sumsqr(x)])
    job = compile_async(f)
    assert not job.cached and job.estimate_s > 0
    lines: list[str] = []
    wait_for_compilations(lines.append)
    assert not pending_compilations()
    assert lines[0].startswith("compiling 1 solver libraries (ahead_probe)") and "about" in lines[0]
    assert str(cache) in lines[0] and lines[-1].startswith("compiled 1 libraries in")
    c = job.result()
    assert c.compiled and not c.cache_hit
    v = [0.3, -1.2, 2.0]
    assert np.allclose(np.asarray(c.function(v)), np.asarray(f(v)), rtol=1e-15, atol=0)
    again = compile_async(f)                              # now cached: loaded, nothing to report
    lines.clear()
    wait_for_compilations(lines.append)
    assert again.cached and again.estimate_s == 0 and lines == [] and again.result().cache_hit
