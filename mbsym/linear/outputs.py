"""Output channels of a linear model: selection by name and their Jacobians ``Cy``, ``Dy``."""

from __future__ import annotations

import re
from typing import Any

import casadi as ca
import numpy as np

from ..equations import EquationsOfMotion
from ..exceptions import DimensionError
from ._cache import cached
from .fd import fd_function
from .target import Target

__all__ = ["resolve_outputs", "output_functions", "output_matrices"]


def resolve_outputs(target: Target, outputs) -> tuple[tuple[str, ...], tuple[str, ...], Any, list]:
    """Selected output names, units, the channel Function (or None) and, per output, a channel or state index."""
    if outputs is None:
        return (), (), None, []
    eom = target.eom
    chan = target.output_function()
    if isinstance(outputs, str):
        outputs = None if outputs == "all" else [outputs]
        if outputs is None:
            if chan is None:
                raise DimensionError("outputs='all' needs a model with output_function(); name states instead.")
            outputs = list(chan[1])
    names, units, picks, unknown = [], [], [], []
    for raw in outputs:
        name = re.sub(r"_\[[^\]]*\]$", "", str(raw))        # accept OpenFAST headers 'TTDspFA_[m]'
        if chan is not None and name in chan[1]:
            i = chan[1].index(name)
            picks.append(("y", i))
            units.append(chan[2][i])
        elif name in eom.states:
            picks.append(("x", eom.states.index(name)))
            units.append("")
        else:
            unknown.append(raw)
        names.append(name)
    if unknown:
        known = list(chan[1]) if chan is not None else []
        raise DimensionError(f"unknown outputs {unknown}; choose output channels {known} or states {list(eom.states)}.")
    return tuple(names), tuple(units), (chan[0] if chan is not None else None), picks


def output_functions(eom: EquationsOfMotion, f_out: ca.Function) -> tuple[ca.Function, ca.Function]:
    """``(x, u, p) -> (y, ∂y/∂x, ∂y/∂u)`` and the central-difference ``∂y/∂x``, cached per Function."""
    def build():
        x, u, p = (ca.MX.sym(s, f_out.size1_in(i)) for i, s in enumerate("xup"))
        y = ca.densify(ca.vertcat(*[ca.vec(v) for v in f_out.call([x, u, p])]))      # one or several outputs
        stacked = ca.Function("outputs", [x, u, p], [y])
        jac = ca.Function("outputs_linear", [x, u, p],
                          [y, ca.densify(ca.jacobian(y, x)), ca.densify(ca.jacobian(y, u))])
        return f_out, jac, fd_function(stacked, eom.n_x, "outputs_fd")

    # keyed by id: the entry holds f_out itself, so that id cannot be reused by another object
    _, jac, fd = cached(eom, ("output_jacobians", id(f_out)), build)
    return jac, fd


def output_matrices(target: Target, sel, x, u, p, h=None):
    """(y0, Cy, Dy) of the selected outputs; Cy by central differences with steps h if given."""
    names, _, f_out, picks = sel
    n_x, n_u = target.eom.n_x, target.eom.n_u
    y0, Cy, Dy = np.zeros(len(picks)), np.zeros((len(picks), n_x)), np.zeros((len(picks), n_u))
    if f_out is not None and any(k == "y" for k, _ in picks):
        jac, fd = output_functions(target.eom, f_out)
        y_all, cy_all, dy_all = (np.array(v) for v in jac(x, u, p))
        if h is not None:
            cy_all = np.array(fd(x, u, p, h))
    for r, (kind, i) in enumerate(picks):
        if kind == "y":
            y0[r], Cy[r], Dy[r] = y_all[i, 0], cy_all[i], dy_all[i]
        else:
            y0[r], Cy[r, i] = x[i], 1.0
    return y0, Cy, Dy
