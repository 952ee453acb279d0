"""Bad input gives typed errors naming what is wrong; a failed call leaves the object unchanged."""

import casadi as ca
import numpy as np
import pytest

import mbsym as mb
from mbsym.control import MHE, NMPC, OCP, EKF
from mbsym.exceptions import ControlDefinitionError, DimensionError, MbsymError, ParameterError


@pytest.fixture()
def dyn():
    x, u, p = ca.SX.sym("x", 2), ca.SX.sym("u", 2), ca.SX.sym("p", 1)
    f = ca.Function("f", [x, u, p], [ca.vertcat(x[1], -p[0] * x[0] + u[0] + u[1])])
    y = ca.Function("y", [x, u, p], [ca.vertcat(x[0], u[0])])
    return mb.Dynamics(f, states=["pos", "vel"], inputs=["force", "wind"], parameters=["k"], defaults={"k": 1.0},
                       outputs=y, output_names=["pos_out", "force_out"])


def ocp(dyn):
    return OCP(dyn, horizon=5, dt=0.1, controls=["force"]).track({"pos": 1.0, "force": 0.1})


@pytest.mark.parametrize("kwargs,match", [
    ({"horizon": 0, "dt": 0.1}, "horizon"),
    ({"horizon": 2.5, "dt": 0.1}, "horizon"),
    ({"horizon": 5, "dt": -0.1}, "dt"),
    ({"horizon": 5, "dt": float("nan")}, "dt"),
    ({"horizon": 5, "dt": 0.1, "controls": ["thrust"]}, "unknown names"),
    ({"horizon": 5, "dt": 0.1, "method": "euler"}, "method"),
    ({"horizon": 5, "dt": 0.1, "substeps": 0}, "substeps"),
])
def test_ocp_construction_errors(dyn, kwargs, match):
    with pytest.raises(ControlDefinitionError, match=match):
        OCP(dyn, **kwargs)


def test_ocp_unknown_keyword_and_model_type(dyn):
    with pytest.raises(TypeError):
        OCP(dyn, horizon=5, dt=0.1, sample_time=0.1)
    with pytest.raises(TypeError, match="model must be"):
        OCP("not a model", horizon=5, dt=0.1)


def test_cost_and_bound_errors_leave_ocp_unchanged(dyn):
    o = OCP(dyn, horizon=5, dt=0.1, controls=["force"])
    with pytest.raises(ControlDefinitionError, match="unknown signal 'speed'"):
        o.track({"speed": 1.0})
    with pytest.raises(ControlDefinitionError, match="non-negative"):
        o.track({"pos": -1.0})
    with pytest.raises(ControlDefinitionError, match="positive semi-definite"):
        o.track(names=["pos", "vel"], matrix=[[1.0, 2.0], [2.0, 1.0]])
    with pytest.raises(ControlDefinitionError, match="symmetric"):
        o.track(names=["pos", "vel"], matrix=[[1.0, 0.5], [0.0, 1.0]])
    with pytest.raises(ControlDefinitionError, match="exceeds"):
        o.bound("pos", 1.0, -1.0)
    with pytest.raises(ControlDefinitionError, match="disturbance"):
        o.bound("wind", 0.0, 1.0)
    with pytest.raises(ControlDefinitionError, match="unknown names"):
        o.limit_rate("wind", -1.0, 1.0)
    with pytest.raises(ControlDefinitionError, match="depend on the controls"):
        o.track({"force_out": 1.0}, terminal=True)
    with pytest.raises(ControlDefinitionError, match="no cost"):
        o.transcribe()                                   # nothing was added by the failed calls
    with pytest.raises(ControlDefinitionError, match="must return 1"):
        o.add_cost(stage=lambda x, u, p: ca.vertcat(x[0], x[1]))
    with pytest.raises(ControlDefinitionError, match="not tracked"):
        o.track({"pos": 1.0}, reference={"vel": 1.0})


def test_nmpc_option_and_step_errors(dyn):
    with pytest.raises(ControlDefinitionError, match="solver must be one of"):
        NMPC(ocp(dyn), solver="acados", compile=False)
    with pytest.raises(ControlDefinitionError, match="qp_solver"):
        NMPC(ocp(dyn), qp_solver="gurobi", compile=False)
    with pytest.raises(ControlDefinitionError, match="fatrop computes its own Hessian"):
        NMPC(ocp(dyn), solver="fatrop", hessian="gauss-newton", compile=False)
    with pytest.raises(TypeError, match="OCP"):
        NMPC(dyn)
    with pytest.raises(TypeError):
        NMPC(ocp(dyn), horizon=3)
    mpc = NMPC(ocp(dyn), compile=False)
    with pytest.raises(DimensionError, match="expected 2"):
        mpc.step([1.0, 2.0, 3.0])
    with pytest.raises(DimensionError, match="finite"):
        mpc.step([np.nan, 0.0])
    with pytest.raises(ControlDefinitionError, match="unknown"):
        mpc.step([0.0, 0.0], preview={"gust": 1.0})
    with pytest.raises(ControlDefinitionError, match="6"):
        mpc.step([0.0, 0.0], preview={"wind": np.zeros(4)})
    with pytest.raises(ParameterError, match="unknown parameters"):
        mpc.step([0.0, 0.0], p={"mass": 1.0})
    assert mpc.stats == []                               # failed calls recorded nothing
    u = mpc.step([0.0, 0.0], preview={"wind": np.linspace(0, 1, 6)})
    assert u.shape == (1,) and mpc.stats[-1].success


def test_estimator_errors(dyn):
    kw = dict(dt=0.1, measurements=["pos_out"], process_noise={"vel": 0.1}, measurement_noise={"pos_out": 0.1})
    with pytest.raises(ControlDefinitionError, match="must be > 0"):
        EKF(dyn, **{**kw, "measurement_noise": {"pos_out": 0.0}})
    with pytest.raises(ControlDefinitionError, match="unknown names"):
        EKF(dyn, **{**kw, "process_noise": {"speed": 0.1}})
    with pytest.raises(ControlDefinitionError, match="unknown names"):
        EKF(dyn, **{**kw, "measurements": ["height"]})
    with pytest.raises(ControlDefinitionError, match="window"):
        MHE(dyn, window=0, **kw, compile=False)
    with pytest.raises(ControlDefinitionError, match="bounds"):
        MHE(dyn, window=3, bounds={"height": (0, 1)}, **kw, compile=False)
    with pytest.raises(ControlDefinitionError, match="dt"):
        MHE(dyn, window=3, measurements=["pos_out"], process_noise={"vel": 0.1}, measurement_noise={"pos_out": 0.1},
            compile=False)
    ekf = EKF(dyn, **kw)
    with pytest.raises(DimensionError, match="expected 1"):
        ekf.step([0.0, 1.0], [0.0, 0.0])
    with pytest.raises(DimensionError, match="u"):
        ekf.step([0.0], [0.0])
    assert all(issubclass(e, MbsymError) for e in (ControlDefinitionError, DimensionError, ParameterError))
