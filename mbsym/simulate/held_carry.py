"""The held part carried from controller sample to sample, held or extrapolated ("rk4-held").

In a compiled closed loop with the method ``"rk4-held"`` the plant's held part ``z = g(x, u, p)``
(:class:`mbsym.held.HeldPart`, e.g. blade-element aerodynamics) may be evaluated less often than every
controller sample (``held_dt``), and between its evaluations it may be held or extrapolated in time
(``held_order``), as OpenFAST's glue code extrapolates a module's outputs over the steps of the others
(its ``InterpOrder``):

* ``held_order = 0``: ``z`` keeps the value of the last evaluation;
* ``held_order = k`` (1 or 2): ``z(t)`` is the degree-``k`` polynomial through the last ``k + 1``
  evaluations (Lagrange form on their times), evaluated at each RK4 stage time and at the measurement;
  until ``k + 1`` evaluations exist, the polynomial through those there are.

Only the entries of ``z`` that the right-hand side or the controller's measurements read are carried
(the blade-element aerodynamics hold some 1100 values, of which ~260 drive the structure: the others are
per-node diagnostics for the output channels, which are only asked for at samples where ``z`` is fresh).

The carried vector is ``[z_0; z_1; ...; z_k; a_1; ...; a_k; count; tau]``: the selected entries at the
last ``k + 1`` evaluations (newest first), the ages ``a_i = t_0 - t_i`` [s] of the older ones, the number
of evaluations so far (at most ``k + 1``) and the time ``tau`` [s] since the newest.
"""

from __future__ import annotations

import casadi as ca
import numpy as np

from ..exceptions import SimulationOptionError

__all__ = ["HeldCarry", "HELD_ORDERS"]

#: Orders of the extrapolation between evaluations: hold, linear, quadratic.
HELD_ORDERS = (0, 1, 2)


def check_held_order(order) -> int:
    """``order`` as an int of :data:`HELD_ORDERS`, else SimulationOptionError."""
    if isinstance(order, bool) or not isinstance(order, (int, np.integer)) or int(order) not in HELD_ORDERS:
        raise SimulationOptionError(f"held_order must be one of {HELD_ORDERS} (0: hold the held part between its "
                                    f"evaluations, 1: linear, 2: quadratic extrapolation, as OpenFAST's "
                                    f"InterpOrder); got {order!r}.")
    return int(order)


class HeldCarry:
    """The carried history of a plant's held part and its extrapolation (module docstring).

    Parameters
    ----------
    plant : Plant
        With a :class:`mbsym.held.HeldPart` ``plant.held``.
    measure_held : casadi.Function
        ``(x, u, p, z) -> y``: the controller's measurements with the held part as an argument.
    order : int
        0, 1 or 2 (:data:`HELD_ORDERS`).
    interval : float
        The nominal time between evaluations [s] (the ages of the filled history at the start).
    """

    def __init__(self, plant, measure_held: ca.Function, order: int, interval: float) -> None:
        held = plant.held
        self.plant, self.order, self.interval = plant, check_held_order(order), float(interval)
        self.n_z = held.n_z
        used = _used_columns(held.rhs.sparsity_jac(3, 0)) | _used_columns(measure_held.sparsity_jac(3, 0))
        self.sel = np.array(sorted(used), dtype=int)
        self.n_sel = int(self.sel.size)
        self.n_carry = (self.order + 1) * self.n_sel + self.order + 2
        self.refresh = self._refresh_function()

    # ------------------------------------------------------------------ graph pieces
    def scatter(self, zs):
        """The full held vector (n_z) with the carried entries ``zs`` in place and zeros elsewhere (an indexed
        assignment: ~0.4 µs for the blade-element turbine's 1068 entries, against ~2 µs for a sparse product)."""
        z = ca.MX.zeros(self.n_z)
        if self.n_sel:
            z[self.sel.tolist()] = zs
        return z

    def _refresh_function(self) -> ca.Function:
        """``(index, x, u, p, carry) -> (carry', z_full)``: index 0 keeps ``carry`` (z_full zeros), 1 evaluates
        the held part and pushes it into the history, 2 does so and also returns the full held vector (for the
        output channels). One ``conditional``: only the chosen case runs."""
        plant, held, k = self.plant, self.plant.held, self.order
        x, u, p = (ca.MX.sym(s, n) for s, n in (("x", plant.n_x), ("u", plant.n_u), ("p", plant.n_p)))
        carry = ca.MX.sym("carry", self.n_carry)
        args, names = [x, u, p, carry], ["x", "u", "p", "carry"]
        zero = ca.MX.zeros(self.n_z)
        keep = ca.Function("held_keep", args, [carry, zero], names, ["carry_next", "z"])
        full = held.part(x, u, p)
        pushed = self._push(carry, full[self.sel.tolist()] if self.n_sel else ca.MX(0, 1))
        fresh = ca.Function("held_fresh", args, [pushed, zero], names, ["carry_next", "z"])
        wanted = ca.Function("held_fresh_full", args, [pushed, full], names, ["carry_next", "z"])
        return ca.Function.conditional(f"{plant.name}_held_refresh_{k}", [keep, fresh], wanted)

    def _push(self, carry, z_new):
        """The history with ``z_new`` as the newest evaluation (now: tau = 0; one more evaluation counted)."""
        n, k = self.n_sel, self.order
        hist = [carry[i * n:(i + 1) * n] for i in range(k + 1)]
        ages = [carry[(k + 1) * n + i] for i in range(k)]
        count, tau = carry[-2], carry[-1]
        new_ages = [tau] + [a + tau for a in ages[:-1]] if k else []
        return ca.vertcat(z_new, *hist[:k], *new_ages, ca.fmin(count + 1, k + 1), ca.MX(0.0))

    def stage_values(self, carry, offsets):
        """The carried entries extrapolated to ``tau + s`` for each ``s`` of ``offsets`` [s] (MX columns): the
        polynomial through the last ``min(count, order + 1)`` evaluations."""
        n, k = self.n_sel, self.order
        hist = [carry[i * n:(i + 1) * n] for i in range(k + 1)]
        if k == 0:
            return [hist[0] for _ in offsets]
        nodes = [0.0] + [-carry[(k + 1) * n + i] for i in range(k)]
        count, tau = carry[-2], carry[-1]
        out = []
        for s in offsets:
            t = tau + s
            weights = [1.0] + [0.0] * k                       # one evaluation: hold it
            for e in range(1, k + 1):                         # e + 1 evaluations: degree e
                w_e = [_lagrange_weight(nodes[:e + 1], i, t) for i in range(e + 1)] + [0.0] * (k - e)
                weights = [ca.if_else(count >= e + 1, a, b) for a, b in zip(w_e, weights)]
            out.append(sum(w * v for w, v in zip(weights, hist)))
        return out

    def advanced(self, carry, h):
        """``carry`` after a step of ``h`` [s] (tau grows)."""
        return ca.vertcat(carry[:-1], carry[-1] + h)

    # ------------------------------------------------------------------ numbers
    def initial(self) -> np.ndarray:
        """The carry before the first sample: no evaluation yet (count 0; the first sample always evaluates),
        nominal ages (distinct, so the unused weights stay finite)."""
        k = self.order
        return np.concatenate([np.zeros((k + 1) * self.n_sel), self.interval * np.arange(1, k + 1), [0.0, 0.0]])


def _lagrange_weight(nodes: list, i: int, t):
    """Weight of node ``i`` of the Lagrange polynomial through ``nodes`` at ``t``."""
    w = 1.0
    for j, xj in enumerate(nodes):
        if j != i:
            w = w * (t - xj) / (nodes[i] - xj)
    return w


def _used_columns(sp: ca.Sparsity) -> set[int]:
    """Columns of a Jacobian sparsity with at least one structural nonzero."""
    colind = np.asarray(sp.colind())
    return set(np.flatnonzero(np.diff(colind) > 0).tolist())
