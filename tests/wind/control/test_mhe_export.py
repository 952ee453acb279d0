"""The exported NMPC with its MHE (``mbsym.wind.mpc.sample_mhe``, ``export-discon --estimator mhe``).

Reference: :class:`mbsym.control.MHE` as :class:`TurbineEstimator` runs it (real-time iterations driven from Python:
hpipm, its first solve a line-search SQP converged to 1e-8, the EKFs in numpy): an independent path to the same
estimates. The exported MHE is the same algorithm as fixed-work CasADi Functions (the EKF and the arrival cost's
update in the graph, :data:`FIRST_ITERATIONS` full Gauss–Newton steps for the first window, then one QP per sample,
from its KKT system, with qrqp where a bound is active), then generated C behind the swap-array wrapper.

Tolerances. The first full window: the Python MHE stops its SQP when a step is below 1e-8 (1 + ‖w‖∞), about 2e-7
here (the wind, ~18 m/s, dominates ‖w‖∞), and Gauss–Newton converges linearly, so its estimate is a few 1e-6 from
the converged one the exported six full steps reach (observed 4.5e-6 m/s on the side-side velocity, 2.8e-6 of that
state's largest value): 1e-4 of each state's largest value. Then every sample both sides solve the same QP, hpipm to
about 1e-8 of its solution, the KKT solve exactly, and the real-time iteration contracts the first difference within
ten samples: from the tenth sample after the first solve on, 1e-6 relative (observed 1.3e-8). Through the library
the commands are float32 (test_nmpc_export.py's module docstring): pitch 1e-6 relative plus 1e-8 rad, torque 1e-6
relative (observed 8.1e-9 rad and 5.1e-8 over 10 s)."""

from __future__ import annotations

import json
import math
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
from _mpc_setup import turbine

from mbsym.codegen import compiler_command

LOOP_SI = (math.pi / 30.0, math.pi / 30.0, math.pi / 180.0, 1e3, 1.0, 1e3, 1.0)   # LOOP_CHANNELS -> SI
F32 = np.float32


def _wind(seconds):
    from mbsym.wind.inflow import kaimal_wind

    return kaimal_wind(14.0, 0.14, 3, duration=seconds + 1.0)


def _start(wind):
    """The plant's steady start at the first wind and the estimate there."""
    from mbsym.wind.mpc import estimation_model
    from mbsym.wind.operation.steady import steady_guess

    t = turbine()
    x0 = steady_guess(t.plant, float(wind(0.0))).state
    dyn, observed = t.plant.dynamics(), estimation_model(t.plant)
    z0 = [x0[dyn.states.index(s)] for s in observed.estimation_states] + [float(wind(0.0))]
    return x0, observed, z0


def _estimator_samples(seconds):
    """Measurements and mean inputs of every estimator sample (0.05 s) of a baseline run of the plant (0.01 s)."""
    from mbsym.wind.control import BaselineController
    from mbsym.wind.mpc import TurbineLoop, simulate_with_loop

    t = turbine()
    wind = _wind(seconds)
    x0, _, _ = _start(wind)
    loop = TurbineLoop(t.plant, 0.01, baseline=BaselineController(t.deck.baseline_settings()))
    law, rows = loop.law, []

    def recording(tt, xc, y):
        rows.append(np.array(y, dtype=float))
        return law(tt, xc, y)

    loop.law = recording
    simulate_with_loop(t.plant, wind, seconds, loop, x0=x0, compile=True)
    ys, us, acc, n = [], [], np.zeros(2), 0
    for k, y in enumerate(rows):
        pitch, torque = math.radians(y[2]), y[5] * 1e3
        if k:
            acc, n = acc + (pitch, torque), n + 1
        if k % 5 == 0:
            ys.append([y[0], y[6]])
            us.append(acc / n if n else np.array([pitch, torque]))
            acc, n = np.zeros(2), 0
    return np.array(ys), np.array(us)


def _mhe(observed, z0):
    from mbsym.wind.mpc import TurbineEstimator

    return TurbineEstimator(observed, "mhe", x0=z0, compile=False)


def test_mhe_sample_equals_the_python_mhe():
    from mbsym.control import EKF
    from mbsym.wind.mpc.sample import QP_ACCEPT
    from mbsym.wind.mpc.sample_mhe import MHEMirror, mhe_functions

    ys, us = _estimator_samples(12.0)
    _, observed, z0 = _start(_wind(12.0))
    ref = _mhe(observed, z0)
    mirror = MHEMirror(mhe_functions(_mhe(observed, z0)), np.array(z0), QP_ACCEPT)
    ekf = EKF(ref.model, dt=ref.dt, measurements=ref.measurements, process_noise=ref.filter._ekf.Q,
              measurement_noise=ref.filter._ekf.R, x0=z0, P0=ref.filter._ekf.P)
    got, want, alone = [], [], []
    for k, (y, u) in enumerate(zip(ys, us)):
        want.append(ref.step(y[0], y[1], u[0], u[1]))
        got.append(mirror.step(y, u, 0.0 if k == 0 else 1.0))
        alone.append(ekf.step(y, u))
    got, want, alone = np.array(got), np.array(want), np.array(alone)
    window = ref.tuning.window
    assert mirror.failures == ref.failures() == 0 and len(ys) == 240
    assert np.allclose(got[:window], alone[:window], rtol=1e-12, atol=1e-14)      # the window fills: the EKF
    first = np.abs(got - want) / np.max(np.abs(want), axis=0)                # the first window's solve, on
    assert np.max(first) < 1e-4, np.max(first, axis=0)
    rel = np.abs(got[window + 10:] - want[window + 10:]) / np.maximum(np.abs(want[window + 10:]), 1e-3)
    assert np.max(rel) < 1e-6, np.max(rel, axis=0)                    # see the module docstring
    wind = ref.names.index("Wind1VelX")
    assert np.max(np.abs(got[window:, wind] - alone[window:, wind])) > 0.01    # m/s: the MHE is not its EKF


def test_an_active_bound_is_solved_with_the_bounds():
    # A wind bound the estimate runs into (lower bound 14.2 m/s in a 14 m/s Kaimal wind): the step without the bounds
    # leaves it, and the sample is solved again with them (qrqp), as the Python MHE (hpipm) solves it with them.
    # Tolerance 1e-4 relative after the first window's solve: qrqp's active set puts the wind on the bound exactly;
    # hpipm's interior point (mode speed_abs) stops at a small complementarity gap, which at an active bound with a
    # small multiplier moves the solution by more than its 1e-8 elsewhere (measured 1.6e-5 relative, 4.5e-7 m/s on
    # the tower's velocity, at samples with the bound active; 1e-8 at the others).
    from mbsym.wind.mpc.sample import QP_ACCEPT
    from mbsym.wind.mpc.sample_mhe import MHEMirror, mhe_functions

    ys, us = _estimator_samples(6.0)
    _, observed, z0 = _start(_wind(6.0))

    ref = _bounded_mhe(observed, z0, 14.2)
    mirror = MHEMirror(mhe_functions(_bounded_mhe(observed, z0, 14.2)), np.array(z0), QP_ACCEPT)
    got = np.array([mirror.step(y, u, 0.0 if k == 0 else 1.0) for k, (y, u) in enumerate(zip(ys, us))])
    want = np.array([ref.step(y[0], y[1], u[0], u[1]) for y, u in zip(ys, us)])
    wind, start = ref.names.index("Wind1VelX"), ref.tuning.window + 10
    assert mirror.bounded >= 10 and mirror.failures == ref.failures() == 0
    assert np.min(got[start:, wind]) >= 14.2 - 1e-9 and np.sum(np.isclose(got[start:, wind], 14.2)) >= 5
    rel = np.abs(got[start:] - want[start:]) / np.maximum(np.abs(want[start:]), 1e-3)
    assert np.max(rel) < 1e-4, np.max(rel, axis=0)


def test_rejected_solves_give_the_ekfs_estimate():
    # Every solve rejected (acceptance below zero): the estimate is the EKF's at every sample, each full-window
    # sample counts a failure, and each starts again from the first-window solve.
    from mbsym.control import EKF
    from mbsym.wind.mpc.sample_mhe import MHEMirror, mhe_functions

    ys, us = _estimator_samples(2.0)
    _, observed, z0 = _start(_wind(2.0))
    est = _mhe(observed, z0)
    mirror = MHEMirror(mhe_functions(est), np.array(z0), accept=-1.0)
    ekf = EKF(est.model, dt=est.dt, measurements=est.measurements, process_noise=est.filter._ekf.Q,
              measurement_noise=est.filter._ekf.R, x0=z0, P0=est.filter._ekf.P)
    for k, (y, u) in enumerate(zip(ys, us)):
        z = mirror.step(y, u, 0.0 if k == 0 else 1.0)
        assert np.allclose(z, ekf.step(y, u), rtol=1e-10, atol=1e-12), k
        assert mirror.W is None
    assert mirror.failures == len(ys) - est.tuning.window


def _bounded_mhe(observed, z0, lower):
    """The MHE of :func:`_mhe` with the wind bounded below by ``lower`` [m/s]."""
    from mbsym.control import MHE

    est = _mhe(observed, z0)
    f = est.filter
    est.filter = MHE(est.model, window=f.window, process_noise=f._ekf.Q, measurement_noise=f._ekf.R, x0=z0,
                     P0=f._ekf.P, bounds={"Wind1VelX": (lower, 60.0)}, compile=False)
    return est


@pytest.fixture(scope="module", params=[None, 14.2], ids=["default", "wind-bound-active"])
def library(request, tmp_path_factory):
    if compiler_command() is None:
        pytest.skip("no C compiler (gcc/cc, $CC): the NMPC cannot be exported here")
    from mbsym.wind.control import BaselineController
    from mbsym.wind.mpc import NMPCTuning, TurbineNMPC
    from mbsym.wind.mpc.discon_nmpc import export_nmpc_discon

    t = turbine()
    _, observed, z0 = _start(_wind(1.0))
    est = _mhe(observed, z0) if request.param is None else _bounded_mhe(observed, z0, request.param)
    nmpc = TurbineNMPC(t.prediction, t.setpoints, tuning=NMPCTuning.estimated_wind(), references=t.references)
    out = export_nmpc_discon(nmpc, est, BaselineController(t.deck.baseline_settings()),
                             tmp_path_factory.mktemp("nmpc_mhe"), loop_dt=t.deck.controller_dt)
    return {**out, "lower": request.param}


@pytest.mark.slow
def test_cli_contract_nmpc_mhe(tmp_path, capsys):
    if compiler_command() is None:
        pytest.skip("no C compiler (gcc/cc, $CC): the NMPC cannot be exported here")
    from mbsym.cli import main

    assert main(["export-discon", "--controller", "nmpc", "--estimator", "mhe", "--out", str(tmp_path)]) == 0
    out = json.loads(capsys.readouterr().out.strip().splitlines()[-1])
    assert set(out) == {"library", "input", "controller", "sample_time_s"}
    assert out["controller"] == "nmpc" and out["sample_time_s"] == 0.01 and out["library"].endswith(".so")
    assert "estimator: MHE (window 20 intervals" in Path(out["input"]).read_text()
    if shutil.which("ldd") is not None:
        needed = subprocess.run(["ldd", out["library"]], capture_output=True, text=True, check=True).stdout
        assert "casadi" not in needed and "python" not in needed and "hpipm" not in needed, needed


@pytest.mark.slow
def test_library_in_mbsyms_discon_loop_equals_the_python_nmpc_with_its_mhe(library):
    # The library closed on the plant in mbsym's DISCON loop (ctypes, float32 swap array), 10 s; then its mirror
    # (SampledLoop) and, with the default bounds, the Python loop (TurbineLoop: hpipm RTI for the NMPC and the MHE,
    # numpy EKFs) fed the same float32 measurements, the estimators started where the library starts its own (the
    # steady estimate at the hub wind of the first step call). With the wind bounded below by 14.2 m/s the library
    # takes its bounded path (qrqp) at more than 10 samples. Tolerance: module docstring.
    from _mpc_setup import library_closed_loop

    from mbsym.wind.mpc import NMPCTuning, TurbineLoop, TurbineNMPC
    from mbsym.wind.mpc.sample import SampledLoop, sample_functions

    t, seconds = turbine(), 10.0
    wind = _wind(seconds)
    x0, observed, z0 = _start(wind)
    rows, res, messages = library_closed_loop(library, wind, seconds, x0)
    assert not any("rejected" in m or "failed" in m or "fallback" in m for m in messages), messages

    def nmpc():
        return TurbineNMPC(t.prediction, t.setpoints, tuning=NMPCTuning.estimated_wind(), references=t.references,
                           deadline=math.inf)

    def estimator(z):
        lower = library["lower"]
        return _mhe(observed, z) if lower is None else _bounded_mhe(observed, z, lower)

    got = np.array([u for _, _, u in rows[1:]])
    # the library's mirror (SampledLoop on the Functions it is generated from) on the same float32 measurements
    mirror = SampledLoop(sample_functions(nmpc(), estimator(z0), 0.01, settings=t.deck.baseline_settings()))
    ref = np.array([mirror.step(tt - rows[1][0], y[0] * 30.0 / math.pi, y[6], y[2], y[5], hub_wind=y[4])
                    for tt, y, _ in rows[1:]])
    assert mirror.mhe.failures == 0 and not mirror.holds and not mirror.failures
    assert (mirror.mhe.bounded > 10) == (library["lower"] is not None), mirror.mhe.bounded
    assert np.max(np.abs(got[:, 0] - ref[:, 0]) - 1e-6 * np.abs(ref[:, 0])) < 1e-8
    assert np.max(np.abs(got[:, 1] - ref[:, 1]) / np.abs(ref[:, 1])) < 1e-6
    assert np.ptp(res.output("BldPitch1")) > 1.0                      # deg: the library pitches the rotor
    if library["lower"] is not None:
        return                # with a bound active the Python MHE (hpipm) agrees to 1e-4 only (test above)
    start = mirror.f.init(rows[1][1][4])
    est = estimator(np.asarray(start, dtype=float).ravel())
    loop = TurbineLoop(t.plant, 0.01, nmpc=nmpc(), estimator=est)
    xc, ref = loop.controller().x0, []
    for tt, y32, _ in rows[1:]:
        xc, u = loop.law(tt - rows[1][0], xc, y32 / np.asarray(LOOP_SI))
        ref.append(u)
    ref = np.array(ref)
    assert est.failures() == 0 and loop.nmpc.nmpc.failures == 0
    assert np.max(np.abs(got[:, 0] - ref[:, 0]) - 1e-6 * np.abs(ref[:, 0])) < 1e-8
    assert np.max(np.abs(got[:, 1] - ref[:, 1]) / np.abs(ref[:, 1])) < 1e-6
