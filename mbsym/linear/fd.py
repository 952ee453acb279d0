"""Central-difference Jacobians as CasADi Functions, and the hook for a model's own linearization steps.

Used by ``method="fd"`` and ``method="elastodyn-fd"`` of :func:`mbsym.linear.linearize`,
:func:`mbsym.linear.linearize_batch` and :func:`mbsym.linear.sensitivities`;
:func:`elastodyn_steps` is public as :func:`mbsym.linear.elastodyn_steps`.
"""

from __future__ import annotations

import casadi as ca

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
    """The model's own central-difference steps of ``method="elastodyn-fd"``, by coordinate name.

    A model object supplies them through its hook ``linearization_steps()`` — a wind
    turbine (:class:`mbsym.wind.TurbineModel`) returns ElastoDyn's steps
    (``ED_Init_Jacobian_x``: 2° for platform rotations, 0.02°·TwrFlexL for first tower
    modes, …; :func:`mbsym.wind.structure.steps.elastodyn_steps`).

    Raises
    ------
    ModelDefinitionError
        If the model has no such hook.
    """
    hook = getattr(model, "linearization_steps", None)
    if not callable(hook):
        raise ModelDefinitionError(f"method='elastodyn-fd' needs a model that supplies ElastoDyn's steps (a wind "
                                   f"TurbineModel); got {type(model).__name__}. Use method='fd' with steps=... "
                                   "instead.")
    return dict(hook())
