"""Central-difference Jacobians as CasADi Functions and ElastoDyn's linearization steps.

Used by ``method="fd"`` and ``method="elastodyn-fd"`` of :func:`mbsym.linear.linearize`,
:func:`mbsym.linear.linearize_batch` and :func:`mbsym.linear.sensitivities`;
:func:`elastodyn_steps` is public as :func:`mbsym.linear.elastodyn_steps`.
"""

from __future__ import annotations

import re

import casadi as ca
import numpy as np

from ..equations import EquationsOfMotion
from ..exceptions import ModelDefinitionError
from ._cache import cached

__all__ = ["elastodyn_steps", "fd_function", "fd_rhs"]


def fd_function(f: ca.Function, n_x: int, name: str) -> ca.Function:
    """``(x, u, p, h) -> (∂f/∂x)`` by central differences with per-state steps ``h``, as a Function.

    Differentiable in ``p`` (sensitivities of the finite-difference A) and mappable.
    """
    x, u, p, h = (ca.MX.sym(s, k) for s, k in (("x", n_x), ("u", f.size1_in(1)), ("p", f.size1_in(2)), ("h", n_x)))
    H = ca.diag(h)
    X = ca.horzcat(ca.repmat(x, 1, n_x) + H, ca.repmat(x, 1, n_x) - H)
    Y = f.map(2 * n_x)(X, u, p)
    J = (Y[:, :n_x] - Y[:, n_x:]) @ ca.diag(0.5 / h)
    return ca.Function(name, [x, u, p, h], [ca.densify(J)], ["x", "u", "p", "h"], ["J"])


def fd_rhs(eom: EquationsOfMotion) -> ca.Function:
    """``(x, u, p, h) -> ∂rhs/∂x`` by central differences, built once per model."""
    return cached(eom, "fd_rhs", lambda: fd_function(eom.functions.rhs, eom.n_x, f"{eom.name}_rhs_fd"))


def elastodyn_steps(model) -> dict[str, float]:
    """ElastoDyn's central-difference steps of its linearization, by coordinate name.

    ``ED_Init_Jacobian_x`` (docs/elastodyn_notes.md §7): platform translations
    0.2°·max(TowerHt, 1) [rad·m], platform rotations 2°, first tower modes
    0.02°·TwrFlexL, second tower modes 0.002°·TwrFlexL, yaw / generator azimuth /
    drivetrain 2°, blade first flap and edge modes 0.2°·BldFlexL, second flap
    0.02°·BldFlexL, each at least √eps. ElastoDyn perturbs a speed by the same number
    as its coordinate.

    Parameters
    ----------
    model : TurbineModel
        A wind-turbine model (attribute ``turbine``: TurbineParameters).

    Raises
    ------
    ModelDefinitionError
        If the model has no turbine data, or a coordinate has no ElastoDyn step.
    """
    t = getattr(model, "turbine", None)
    if t is None or not hasattr(t, "tower_height"):
        raise ModelDefinitionError(f"method='elastodyn-fd' needs a wind-turbine model (TurbineModel); got "
                                   f"{type(model).__name__}. Use method='fd' with steps=... instead.")
    deg = np.pi / 180.0
    twr = t.tower_height - t.tower_base_height
    bld = t.tip_radius - t.hub_radius
    table = {"Sg": 0.2 * deg * max(t.tower_height, 1.0), "R": 2 * deg, "TFA1": 0.02 * deg * twr,
             "TFA2": 0.002 * deg * twr, "Yaw": 2 * deg}
    table.update(Sw=table["Sg"], Hv=table["Sg"], P=table["R"], Y=table["R"], TSS1=table["TFA1"],
                 TSS2=table["TFA2"], GeAz=table["Yaw"], DrTr=table["Yaw"], RFrl=table["Yaw"], TFrl=table["Yaw"],
                 Teet=table["Yaw"])
    steps, missing = {}, []
    for c in model.eom.coordinates:
        blade = re.fullmatch(r"B\d+(F1|E1|F2)", c)
        value = table.get(c) if blade is None else (0.02 if blade.group(1) == "F2" else 0.2) * deg * bld
        if value is None:
            missing.append(c)
        else:
            steps[c] = max(value, np.sqrt(np.finfo(float).eps))
    if missing:
        raise ModelDefinitionError(f"no ElastoDyn linearization step for coordinates {missing}; pass "
                                   "method='fd' with steps={name: step} instead.")
    return steps
