"""Bad input to mb.identify: typed errors that name what is wrong (each path exercised)."""

from __future__ import annotations

import numpy as np
import pytest

import mbsym as mb
from mbsym.exceptions import DataError, IdentificationOptionError, MbsymError, ParameterError

from .conftest import exact_decay

T = np.arange(0.0, 3.0, 0.05)
DATA = {"time": T, "pos": exact_decay(T, 5.0, 0.1)}        # c = 0.1: the default


def test_unknown_parameter_name(osc):
    with pytest.raises(ParameterError, match="unknown parameter 'mass'.*'k', 'c'"):
        mb.identify(osc, DATA, ["mass"], compile=False)


def test_unknown_deck_key(tower_model):
    with pytest.raises(ParameterError, match="unknown parameter key 'TwrFADmpX'.*TwrFADmp\\(1\\)"):
        mb.identify(tower_model, DATA, ["TwrFADmpX"], compile=False)


def test_key_not_in_the_model(tower_model):
    """PtfmPIner exists as a key but the onshore tower model has no platform DOF."""
    with pytest.raises(ParameterError, match="'PtfmPIner'.*not a parameter of this model.*PtfmPDOF"):
        mb.identify(tower_model, DATA, ["PtfmPIner"], compile=False)
    with pytest.raises(ParameterError, match="TwrFADmp\\(2\\).*TwFADOF2"):
        mb.identify(tower_model, DATA, ["TwrFADmp(2)"], compile=False)


def test_parameter_requested_twice(tower_model):
    with pytest.raises(ParameterError, match="more than once"):
        mb.identify(tower_model, DATA, ["TwrFADmp(1)", "tower_fa1_damping_ratio"], compile=False)


def test_data_channel_missing(osc):
    with pytest.raises(DataError, match="channels \\['spring_force'\\] are not in the data"):
        mb.identify(osc, DATA, ["k"], channels=["pos", "spring_force"], compile=False)
    with pytest.raises(DataError, match="'force' is neither an output nor a state"):
        mb.identify(osc, {**DATA, "force": DATA["pos"]}, ["k"], channels=["force"], compile=False)
    with pytest.raises(DataError, match="no data channel matches the model"):
        mb.identify(osc, {"time": T, "x": DATA["pos"]}, ["k"], compile=False)


def test_non_finite_data(osc):
    bad = DATA["pos"].copy()
    bad[7] = np.nan
    with pytest.raises(DataError, match="'pos' is not finite at t = 0.35 s"):
        mb.identify(osc, {"time": T, "pos": bad}, ["k"], compile=False)
    t = T.copy()
    t[3] = t[2]
    with pytest.raises(DataError, match="times must increase strictly"):
        mb.identify(osc, {"time": t, "pos": DATA["pos"]}, ["k"], compile=False)
    with pytest.raises(DataError, match="do not have 60 samples"):
        mb.identify(osc, {"time": T, "pos": DATA["pos"][:-1]}, ["k"], compile=False)


def test_bad_options(osc):
    with pytest.raises(IdentificationOptionError, match="unknown method 'newton'"):
        mb.identify(osc, DATA, ["k"], method="newton", compile=False)
    with pytest.raises(IdentificationOptionError, match="weights name channels \\['spring_force'\\]"):
        mb.identify(osc, DATA, ["k"], weights={"spring_force": 2.0}, compile=False)
    with pytest.raises(IdentificationOptionError, match="estimate_x0 names unknown states \\['w'\\]"):
        mb.identify(osc, DATA, ["k"], estimate_x0=["w"], compile=False)
    with pytest.raises(ParameterError, match="outside its bounds"):
        mb.identify(osc, DATA, ["k"], initial={"k": 5.0}, bounds={"k": (0.0, 4.0)}, compile=False)
    with pytest.raises(ParameterError, match="initial names \\['c'\\]"):
        mb.identify(osc, DATA, ["k"], initial={"c": 0.1}, compile=False)
    with pytest.raises(TypeError, match="unexpected keyword argument 'tolerance'"):
        mb.identify(osc, DATA, ["k"], tolerance=1e-6)


def test_errors_are_mbsym_errors_and_builtins(osc):
    with pytest.raises(ValueError):
        mb.identify(osc, DATA, ["mass"])
    with pytest.raises(MbsymError):
        mb.identify(osc, {"time": T, "x": DATA["pos"]}, ["k"])


def test_data_kinds(osc, tmp_path):
    """A CSV path (generic reader), a reader passed in, and an unsupported kind."""
    path = tmp_path / "decay.csv"
    np.savetxt(path, np.column_stack([T, DATA["pos"]]), delimiter=",", header="Time_[s],pos_[m]", comments="")
    res = mb.identify(osc, path, ["k"], compile=False)
    assert res.parameters["k"] == pytest.approx(5.0, rel=1e-4)
    calls = []
    res2 = mb.identify(osc, str(path), ["k"], reader=lambda p: calls.append(p) or DATA, compile=False)
    assert calls == [str(path)] and res2.parameters["k"] == pytest.approx(res.parameters["k"], rel=1e-6)
    with pytest.raises(TypeError, match="data record 0 must be"):
        mb.identify(osc, np.zeros((10, 2)), ["k"], compile=False)
    with pytest.raises(FileNotFoundError):
        mb.identify(osc, tmp_path / "missing.csv", ["k"], compile=False)


def test_failed_call_leaves_the_model_unchanged(tower_model):
    before = dict(mb.as_dynamics(tower_model).defaults)
    with pytest.raises(ParameterError):
        mb.identify(tower_model, DATA, ["NacMass", "PtfmMass"], compile=False)
    assert dict(mb.as_dynamics(tower_model).defaults) == before
