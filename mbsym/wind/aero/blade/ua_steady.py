"""The steady state of AeroDyn's unsteady airfoils (``UA_Mod = 3``), for the rotor-effective surfaces.

At constant angle of attack and speed the Beddoes–Leishman recursion of :mod:`.unsteady` settles at its fixed
point (:func:`~.unsteady.steady_states`). There its coefficients are the static polar's wherever AeroDyn's
separation functions invert the polar (``f < 1``, ``f_c < 1.44``); where AeroDyn caps them (near the zero-lift
angle of thick airfoils, and in their negative stall) they are not: on the IEA 15 MW up to 0.015 in Cl at 0-2°
and 0.3 at −4 to −8° (tests/wind/aero/test_ua_steady.py). AeroDyn's BEMT solves the induction with the static
polars and loads the blade with UA's coefficients, so a steady rotor with ``UA_Mod = 3`` carries the fixed point's
loads at the static polar's induction: :func:`steady_airfoil_loads` gives :func:`mbsym.wind.aero.bem.solve_bem`
exactly that (its ``airfoil_loads``).

The fixed point depends on the Mach number through the Prandtl–Glauert slope ``C_nα/β``; the surfaces are
dimensionless, so the relative speed is taken at a reference wind along the shaft (``reference_wind``, default
10 m/s: Mach 0.26 at the IEA 15 MW's tip at rated). The cap moves with ``β = √(1 − M²)``: the fixed point's
deviation from the polar changes with ``M²``, a few % of a deviation that is itself small where rotors operate.
A node whose leading edge has separated at rest has no fixed point (its vortex clock runs); its coefficients are
those one step after rest (:func:`~.unsteady.steady_states`).
"""

from __future__ import annotations

from typing import Any, Callable

import casadi as ca
import numpy as np

from ....exceptions import ParameterError
from . import unsteady
from .polars import NodePolars

__all__ = ["steady_airfoil_loads", "REFERENCE_WIND"]

#: Wind along the shaft [m/s] at which the relative speeds of the dimensionless surfaces are taken (module docstring).
REFERENCE_WIND = 10.0


def _fixed_point_function(nodes: unsteady.UnsteadyNodes, polars: NodePolars) -> ca.Function:
    """``(alpha (m), speed (m)) -> (cl, cd, cm)`` (m each) at the recursion's fixed point, for the UA nodes."""
    m = nodes.size
    alpha, speed = ca.SX.sym("alpha", m), ca.SX.sym("speed", m)
    static = lambda x: polars(x, [int(j) for j in nodes.node])              # noqa: E731
    states = unsteady.steady_states(nodes, alpha, speed, static)
    out = unsteady.kelvin_chain(nodes, alpha, speed, states, static, lambda x: static(x)["cm"])
    return ca.Function("ua_fixed_point", [alpha, speed], [out["cl"], out["cd"], out["cm"]])


def steady_airfoil_loads(bem: Any, nodes: unsteady.UnsteadyNodes | None, *,
                         reference_wind: Any = REFERENCE_WIND) -> Callable | None:
    """The ``airfoil_loads`` of :func:`~mbsym.wind.aero.bem.solve_bem` for ``UA_Mod = 3`` (module docstring).

    Parameters
    ----------
    bem : BEMRotor
        The rotor (its per-node static polars: the same linear tables as the BEM's).
    nodes : UnsteadyNodes or None
        One blade's UA nodes (:func:`~.unsteady.unsteady_nodes` with ``n_blades = 1``); None: no UA (returns None).
    reference_wind : float or ndarray, optional, keyword-only
        The wind along the shaft [m/s] (:data:`REFERENCE_WIND`), or one per operating point (an array that
        broadcasts against ``alpha[..., 0]``).

    Returns
    -------
    callable or None
        ``(alpha (..., n), speed (..., n) per m/s of wind, coefficients (..., n, 3)) -> coefficients``.
    """
    if nodes is None or nodes.continuous:   # UA_Mod 4, 6: the static polar at rest (.ua_continuous)
        return None
    wind = np.asarray(reference_wind, dtype=float)
    if not (np.all(np.isfinite(wind)) and np.all(wind > 0)):
        raise ParameterError(f"reference_wind must hold positive wind speeds [m/s]; got {reference_wind!r}.")
    columns = np.asarray(nodes.node, dtype=int)
    if columns.size != np.unique(columns).size:
        raise ParameterError("steady_airfoil_loads takes one blade's UA nodes (unsteady_nodes(..., n_blades=1)).")
    f = _fixed_point_function(nodes, NodePolars(bem.polars, method="linear"))

    def loads(alpha: np.ndarray, speed: np.ndarray, coef: np.ndarray) -> np.ndarray:
        a = np.asarray(alpha, dtype=float)[..., columns].reshape(-1, columns.size)
        u = (np.asarray(speed, dtype=float)[..., columns] * wind[..., None]).reshape(-1, columns.size)
        out = f.map(a.shape[0])(a.T, u.T)
        new = np.array(coef, dtype=float, copy=True)
        for k, value in enumerate(out):
            new[..., columns, k] = np.asarray(value).T.reshape(new.shape[:-2] + (columns.size,))
        return new

    return loads
