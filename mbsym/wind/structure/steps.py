"""ElastoDyn's central-difference steps of its linearization (``ED_Init_Jacobian_x``).

Used by :meth:`mbsym.wind.TurbineModel.linearization_steps`, the hook behind
``method="elastodyn-fd"`` of :func:`mbsym.linearize` (docs/elastodyn_notes.md §7).
"""

from __future__ import annotations

import math
from typing import Sequence

import numpy as np

from ...exceptions import ModelDefinitionError
from ..deck.parameters import TurbineParameters
from .dofs import blade_dof

__all__ = ["elastodyn_steps"]


def elastodyn_steps(turbine: TurbineParameters, coordinates: Sequence[str]) -> dict[str, float]:
    """ElastoDyn's central-difference steps by coordinate name.

    Platform translations 0.2°·max(TowerHt, 1) [rad·m], platform rotations 2°, first tower
    modes 0.02°·TwrFlexL, second tower modes 0.002°·TwrFlexL, yaw / generator azimuth /
    drivetrain 2°, blade first flap and edge modes 0.2°·BldFlexL, second flap 0.02°·BldFlexL,
    each at least √eps. ElastoDyn perturbs a speed by the same number as its coordinate.

    Parameters
    ----------
    turbine : TurbineParameters
    coordinates : sequence of str
        The model's coordinates (ElastoDyn names: ``Sg``, ``P``, ``TFA1``, ``GeAz``, ``B1F1``, …).

    Raises
    ------
    ModelDefinitionError
        If a coordinate has no ElastoDyn step.
    """
    deg = math.pi / 180.0
    twr = turbine.tower_height - turbine.tower_base_height
    bld = turbine.tip_radius - turbine.hub_radius
    table = {"Sg": 0.2 * deg * max(turbine.tower_height, 1.0), "R": 2 * deg, "TFA1": 0.02 * deg * twr,
             "TFA2": 0.002 * deg * twr, "Yaw": 2 * deg}
    table.update(Sw=table["Sg"], Hv=table["Sg"], P=table["R"], Y=table["R"], TSS1=table["TFA1"],
                 TSS2=table["TFA2"], GeAz=table["Yaw"], DrTr=table["Yaw"], RFrl=table["Yaw"], TFrl=table["Yaw"],
                 Teet=table["Yaw"])
    steps, missing = {}, []
    for c in coordinates:
        blade = blade_dof(c)
        value = table.get(c) if blade is None else (0.02 if blade[1] == "F2" else 0.2) * deg * bld
        if value is None:
            missing.append(c)
        else:
            steps[c] = max(value, float(np.sqrt(np.finfo(float).eps)))
    if missing:
        raise ModelDefinitionError(f"no ElastoDyn linearization step for coordinates {missing}; pass "
                                   "method='fd' with steps={name: step} instead.")
    return steps
