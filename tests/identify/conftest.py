"""Models and data shared by the identification tests (built once per session).

Reference data: OpenFAST free decays in ``../shared/openfast/cases`` (next to the
repository); tests that need them skip cleanly when they are absent.
"""

from __future__ import annotations

from pathlib import Path

import casadi as ca
import numpy as np
import pytest

import mbsym as mb

CASES = Path(__file__).resolve().parents[2].parent / "shared" / "openfast" / "cases"


def oscillator() -> mb.Dynamics:
    """``q'' = -k q - c q' + F`` with an output ``y = [q, k q]`` (a channel that depends on a parameter)."""
    x, u, p = ca.SX.sym("x", 2), ca.SX.sym("u", 1), ca.SX.sym("p", 2)
    f = ca.Function("osc", [x, u, p], [ca.vertcat(x[1], -p[0] * x[0] - p[1] * x[1] + u[0])])
    h = ca.Function("osc_y", [x, u, p], [ca.vertcat(x[0], p[0] * x[0])])
    return mb.Dynamics(f, states=["q", "v"], inputs=["F"], parameters=["k", "c"], defaults={"k": 4.0, "c": 0.1},
                       outputs=h, output_names=["pos", "spring_force"], x0=[1.0, 0.0])


def exact_decay(t: np.ndarray, k: float, c: float) -> np.ndarray:
    """Closed-form free decay of the oscillator from q = 1, v = 0 (underdamped)."""
    s, wd = c / 2, np.sqrt(k - c * c / 4)
    return np.exp(-s * t) * (np.cos(wd * t) + s / wd * np.sin(wd * t))


@pytest.fixture(scope="session")
def osc() -> mb.Dynamics:
    return oscillator()


@pytest.fixture(scope="session")
def tower_model():
    """NREL 5 MW (built-in deck) with the first FA and SS tower modes, released from 1 m / 0.5 m."""
    import dataclasses

    from mbsym.wind import nrel5mw
    from mbsym.wind.structure.turbine import TurbineModel

    t = nrel5mw()
    ic = dataclasses.replace(t.initial_conditions, tower_top_fa_displacement=1.0, tower_top_ss_displacement=0.5)
    return TurbineModel(dataclasses.replace(t, initial_conditions=ic), dofs=["TwFADOF1", "TwSSDOF1"])


@pytest.fixture(scope="session")
def paper45():
    """(deck path, csv path) of the shared paper45 case; skips if absent."""
    fst = CASES / "paper45_fa_ss_gen" / "paper45_fa_ss_gen.fst"
    if not fst.is_file():
        pytest.skip(f"shared OpenFAST data not found at {fst}")
    return fst, fst.with_suffix(".csv")
