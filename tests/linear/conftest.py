"""Models shared by the linearization tests, each built once per session.

OpenFAST reference data live in ``../shared/openfast/cases`` (next to the repository);
tests that need them skip cleanly when they are absent.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import mbsym as mb

CASES = Path(__file__).resolve().parents[2].parent / "shared" / "openfast" / "cases"


def chain(with_inputs: bool = True) -> mb.EquationsOfMotion:
    """Two masses on springs and dampers along x (a linear system): ground-k1-m1-k2-m2, force F on m2.

    Prismatic joints in series: x1 absolute, x2 relative to m1. Parameters m1 m2 k1 k2 c1 c2.
    """
    sys = mb.System(gravity=[0.0, 0.0, -9.81])          # gravity normal to the motion: still linear
    x1, x2 = sys.coordinates("x1 x2")
    m1, m2, k1, k2, c1, c2 = sys.parameters("m1 m2 k1 k2 c1 c2",
                                            values=[2.0, 1.0, 40.0, 15.0, 0.3, 0.2])
    b1, b2 = mb.RigidBody("b1", m1), mb.RigidBody("b2", m2)
    sys.add_joint(mb.Prismatic(sys.ground, b1, axis=[1, 0, 0], coordinate=x1))
    sys.add_joint(mb.Prismatic(b1, b2, axis=[1, 0, 0], coordinate=x2))
    sys.add_spring(x1, k1)
    sys.add_spring(x2, k2)
    sys.add_damper(x1, c1)
    sys.add_damper(x2, c2)
    if with_inputs:
        F = sys.inputs("F")
        sys.add_force(b2, [F, 0.0, 0.0])
    return sys.equations(name="chain")


def double_pendulum() -> mb.EquationsOfMotion:
    """Planar double pendulum with a torque input at the first joint and a damper at the second."""
    sys = mb.System(gravity=[0.0, 0.0, -9.81])
    q1, q2 = sys.coordinates("q1 q2")
    m1, m2, l1, l2 = sys.parameters("m1 m2 l1 l2", values=[2.0, 1.0, 1.0, 0.5])
    tau = sys.inputs("tau")
    b1 = mb.RigidBody("b1", mass=m1, com=[0, 0, -l1], inertia=(0.15, 0.2, 0.05))
    b2 = mb.RigidBody("b2", mass=m2, com=[0, 0, -l2], inertia=(0.05, 0.03, 0.02))
    sys.add_joint(mb.Revolute(sys.ground, b1, axis=[0, 1, 0], coordinate=q1))
    sys.add_joint(mb.Revolute(b1, b2, axis=[0, 1, 0], coordinate=q2, offset=[0, 0, -l1]))
    sys.add_damper(q2, 0.05)
    sys.add_generalized_force(q1, tau)
    return sys.equations(name="double_pendulum")


def central(f, x0: np.ndarray, h) -> np.ndarray:
    """Central differences of a vector function: columns (f(x + h e_j) - f(x - h e_j)) / 2h."""
    x0 = np.asarray(x0, dtype=float)
    h = np.broadcast_to(np.asarray(h, dtype=float), x0.shape)
    cols = []
    for j in range(x0.size):
        e = np.zeros_like(x0)
        e[j] = h[j]
        cols.append((np.asarray(f(x0 + e)) - np.asarray(f(x0 - e))) / (2 * h[j]))
    return np.stack(cols, axis=-1)


def case_deck(case: str, suffix: str = "_lin0") -> Path:
    path = CASES / case / f"{case}{suffix}.fst"
    if not path.is_file():
        pytest.skip(f"shared OpenFAST reference data not found at {path}")
    return path


def undeflected_reference(case: str) -> dict:
    path = CASES / case / f"{case}_lin.json"
    if not path.is_file():
        pytest.skip(f"shared OpenFAST reference data not found at {path}")
    return json.loads(path.read_text())["undeflected"]


@pytest.fixture(scope="session")
def chain_eom():
    return chain()


@pytest.fixture(scope="session")
def pendulum_eom():
    return double_pendulum()


@pytest.fixture(scope="session")
def paper45():
    """TurbineModel of paper45_fa_ss_gen lin0 (TFA1, TSS1, GeAz; undeflected, 0 rpm)."""
    from mbsym.wind import read_openfast
    from mbsym.wind.structure.turbine import TurbineModel

    return TurbineModel(read_openfast(case_deck("paper45_fa_ss_gen")))


@pytest.fixture(scope="session")
def paper46():
    """TurbineModel of paper46_floating lin0 (Sg, P, TFA1; undeflected)."""
    from mbsym.wind import read_openfast
    from mbsym.wind.structure.turbine import TurbineModel

    return TurbineModel(read_openfast(case_deck("paper46_floating")))
