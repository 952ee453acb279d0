"""Fixtures of the operating-turbine tests: models built once per session (derivation + surfaces ~3 s each)."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "control"))


@pytest.fixture(scope="session")
def operating():
    """The built-in NREL 5 MW with GenDOF, TwFADOF1, TwSSDOF1 and dynamic inflow."""
    from mbsym.wind.operation import OperatingTurbine

    model = OperatingTurbine.nrel5mw()
    model.dynamics()
    return model


@pytest.fixture(scope="session")
def quasi_steady():
    """The same without dynamic inflow (quasi-steady rotor loads)."""
    from mbsym.wind.operation import OperatingTurbine

    model = OperatingTurbine.nrel5mw(dynamic_inflow=False)
    model.dynamics()
    return model


@pytest.fixture(scope="session")
def trimmed_14(operating):
    """``operating`` trimmed at 14 m/s under the built-in controller's settings (OperatingPoints)."""
    from mbsym.wind.analysis.operating_points import operating_points
    from mbsym.wind.operation import SteadyControl

    ops = operating_points(operating, [14.0], SteadyControl.nrel5mw())
    assert ops.success
    return ops


@pytest.fixture(scope="session")
def rigid_tower():
    """The built-in NREL 5 MW with GenDOF only (rigid tower), quasi-steady rotor loads."""
    from mbsym.wind.operation import OperatingTurbine

    model = OperatingTurbine.nrel5mw(dofs=["GenDOF"], dynamic_inflow=False)
    model.dynamics()
    return model


@pytest.fixture(scope="session")
def rosco_lib():
    """ROSCO 2.10.6's libdiscon.so (skips without it and without registry access)."""
    import _rosco

    lib = _rosco.rosco_library()
    if lib is None:
        pytest.skip("the ROSCO 2.10.6 library is not cached and could not be fetched with pip")
    return lib


@pytest.fixture(scope="session")
def rosco_deck():
    """ROSCO 2.10.6's own OpenFAST NREL 5 MW deck (Examples/Test_Cases/NREL-5MW/NREL-5MW.fst), skipping without
    the wheel and registry access."""
    import _rosco

    fst = _rosco.rosco_nrel5mw_deck()
    if fst is None:
        pytest.skip("the ROSCO 2.10.6 wheel is not cached and could not be fetched with pip")
    return fst
