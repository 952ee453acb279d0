"""Linearization at many operating points in one call (a CasADi ``map``).

:func:`linearize_batch` evaluates the same Functions as :func:`mbsym.linear.linearize`
over N operating points (optionally in parallel or as compiled C) and returns a
:class:`LinearBatch`. Both names are re-exported by :mod:`mbsym.linear`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Mapping, Sequence

import casadi as ca
import numpy as np

from ..exceptions import DimensionError, ParameterError, SolverError
from ..protocol import input_units as hook_input_units
from .fd import fd_rhs
from .functions import jacobian_function, linear_function
from .linearize import resolve_qdd, resolve_steps, rows
from .model import LinearModel, natural_frequencies
from .outputs import output_functions, resolve_outputs
from .target import Target

__all__ = ["LinearBatch", "linearize_batch", "compiled", "MAP_CHUNK"]


@dataclass(frozen=True)
class LinearBatch:
    """Linear models at N operating points, stacked along the first axis.

    Attributes
    ----------
    M, C, K : ndarray (N, n_q, n_q); Q : (N, n_q, n_u); A : (N, n_x, n_x); B : (N, n_x, n_u)
    Cy : (N, n_y, n_x); Dy : (N, n_y, n_u)
    x, u, p, y : ndarray (N, n_x), (N, n_u), (N, n_p), (N, n_y)
        Operating points (states, inputs, parameter vectors in the order of
        ``parameters``) and outputs there.
    qdd : ndarray (N, n_q)
        The accelerations at which M, C, K, Q were evaluated.
    xd : ndarray (N, n_x)
        The rhs ``[qd; q̈_op]`` at each point.
    coordinates, states, inputs, parameters, outputs : tuple of str
    method : str

    ``batch[i]`` is the :class:`LinearModel` of point i; ``len(batch)`` is N.
    """

    M: np.ndarray
    C: np.ndarray
    K: np.ndarray
    Q: np.ndarray
    A: np.ndarray
    B: np.ndarray
    Cy: np.ndarray
    Dy: np.ndarray
    x: np.ndarray
    u: np.ndarray
    p: np.ndarray
    y: np.ndarray
    qdd: np.ndarray
    xd: np.ndarray
    coordinates: tuple[str, ...]
    states: tuple[str, ...]
    inputs: tuple[str, ...]
    parameters: tuple[str, ...]
    outputs: tuple[str, ...] = ()
    output_units: tuple[str, ...] = ()
    method: str = "exact"
    units: Mapping[str, str] = field(default_factory=dict)
    input_units: tuple[str, ...] = ()

    def __len__(self) -> int:
        return self.A.shape[0]

    def __getitem__(self, i: int) -> LinearModel:
        n = len(self.coordinates)
        x = self.x[i]
        op = {"q": x[:n], "qd": x[n:], "qdd": self.qdd[i], "u": self.u[i], "x": x, "xd": self.xd[i],
              "y": self.y[i], "p": dict(zip(self.parameters, self.p[i].tolist()))}
        return LinearModel(self.M[i], self.C[i], self.K[i], self.Q[i], self.A[i], self.B[i], self.coordinates,
                           self.states, self.inputs, op, self.outputs, self.Cy[i], self.Dy[i], self.output_units,
                           self.method, units=dict(self.units), input_units=tuple(self.input_units))

    def frequencies(self) -> np.ndarray:
        """|λ|/2π [Hz] of the eigenvalues of every A, sorted, shape (N, n_max).

        Row i equals ``batch[i].frequencies()[0]`` (:meth:`LinearModel.frequencies`:
        the eigenvalues with Im λ ≥ 0, one per complex-conjugate pair and one per real
        eigenvalue); rows with fewer entries than the longest (fewer real eigenvalues)
        end in NaN. Use ``batch[i].modes()`` for shapes, damping and names.
        """
        return natural_frequencies(self.A)[0]


def _batch_parameters(target: Target, p, n_points: int) -> np.ndarray:
    """(N, n_p): a dict of numbers and/or length-N arrays (parameter sweeps).

    Names, missing values and finiteness are checked once, by the model's own
    resolution (ParameterError), with each swept array's first value standing in for it.
    """
    eom = target.eom
    if p is not None and not isinstance(p, Mapping):
        return np.tile(target.parameters(p), (n_points, 1))          # raises the ParameterError for a non-dict
    p = dict(p or {})
    arrays = {k: np.asarray(v, dtype=float).reshape(-1) for k, v in p.items() if np.ndim(v) > 0}
    first = {k: (v[0] if v.size else 0.0) for k, v in arrays.items()}
    P = np.tile(target.parameters({**p, **first}), (n_points, 1))
    for k, v in arrays.items():
        if v.size != n_points:
            raise DimensionError(f"parameter {k!r} has {v.size} values; expected {n_points} (one per point).")
        if not np.all(np.isfinite(v)):
            raise ParameterError(f"parameter {k!r} has non-finite values at points "
                                 f"{np.flatnonzero(~np.isfinite(v))[:5].tolist()}; all must be finite.")
        P[:, eom.parameters.index(k)] = v
    return P


def linearize_batch(model, x0, u0=None, p: Mapping[str, Any] | None = None, *, qdd0=None,
                    outputs: Sequence[str] | str | None = None, method: str = "exact", steps=None,
                    parallel: str = "serial", compile: bool = False) -> LinearBatch:
    """Linearize at N operating points in one call (a CasADi ``map`` over the linearization Functions).

    Parameters
    ----------
    model : EquationsOfMotion or model object
        As for :func:`linearize`.
    x0 : array (N, n_x)
        States ``[q; qd]``, one operating point per row.
    u0 : array (N, n_u) or (n_u,) or dict by name, optional
        Inputs (default: the model's default inputs at t = 0).
    p : dict, optional
        Parameter values by name: numbers (shared) or arrays of N values (sweeps).
    qdd0, outputs, method, steps : optional, keyword-only
        As for :func:`linearize`; ``qdd0`` may be ``"rhs"`` or an (N, n_q) array.
    parallel : {"serial", "thread", "openmp"}, keyword-only
        CasADi's map parallelization.
    compile : bool, keyword-only
        Evaluate the linearization Function as generated C, compiled once and cached
        on disk (:func:`mbsym.codegen.compile_function`; about 1 s the first time for
        the paper45 model, then ~10x faster than CasADi's virtual machine).

    Returns
    -------
    LinearBatch

    Examples
    --------
    >>> import numpy as np, mbsym as mb
    >>> from mbsym.linear import linearize_batch
    >>> sys = mb.System(gravity=[0, 0, -9.81])
    >>> th = sys.coordinates("th")
    >>> sys.add_joint(mb.Revolute(sys.ground, mb.RigidBody("b", 1.0, com=[0, 0, -1.0]),
    ...                           axis=[0, 1, 0], coordinate=th))
    >>> batch = linearize_batch(sys.equations(), [[0.0, 0.0], [np.pi / 3, 0.0]])
    >>> np.round(batch.K[:, 0, 0], 3)          # m g l cos(th)
    array([9.81 , 4.905])
    """
    target = Target(model)
    eom, n = target.eom, target.eom.n_q
    X = np.asarray(x0, dtype=float)
    if X.ndim != 2 or X.shape[1] != eom.n_x:
        raise DimensionError(f"x0 must have shape (N, {eom.n_x}) (states {list(eom.states)} in columns); "
                             f"got {X.shape}.")
    N = X.shape[0]
    X = rows(X, N, eom.n_x, "x0")
    if isinstance(u0, Mapping) or u0 is None:
        U = rows(target.inputs(u0), N, eom.n_u, "u0")
    else:
        U = rows(u0, N, eom.n_u, "u0")
    P = _batch_parameters(target, p, N)
    qdd_in = resolve_qdd(eom, qdd0, N)
    h = resolve_steps(target, method, steps)
    sel = resolve_outputs(target, outputs)
    f = linear_function(eom)
    if compile:
        f = compiled(f)
    res = _mapped(f, N, parallel, X[:, :n], X[:, n:], U, P)
    M, C, K, Q, A, B, xd = (_unstack(r, N) for r in res)
    qdd = np.zeros((N, n))
    if isinstance(qdd_in, str):
        qdd = xd[:, n:, 0]
        K, Q = -M @ A[:, n:, :n], M @ B[:, n:, :]
    elif qdd_in is not None:
        qdd = qdd_in
        jac = _mapped(jacobian_function(eom), N, parallel, X[:, :n], X[:, n:], qdd, U, P)
        K, Q = (_unstack(r, N) for r in jac[2:])
    if h is not None:
        A = _unstack(_mapped(fd_rhs(eom), N, parallel, X, U, P, np.tile(h, (N, 1)))[0], N)
    if not np.all(np.isfinite(A)):
        bad = np.flatnonzero(~np.all(np.isfinite(A.reshape(N, -1)), axis=1))
        raise SolverError(f"the linearization is not finite at {bad.size} points (first: {bad[:5].tolist()}); "
                          "is the mass matrix singular there? Check those states, inputs and parameters.")
    Y, Cy, Dy = _batch_outputs(target, sel, X, U, P, h, parallel)
    return LinearBatch(M, C, K, Q, A, B, Cy, Dy, X, U, P, Y, qdd, xd[:, :, 0], eom.coordinates, eom.states,
                       eom.inputs, eom.parameters, sel[0], sel[1], method, dict(eom.units),
                       hook_input_units(target.owner, eom.inputs))


#: Points per CasADi map in a batch: building a map costs ~N² for large N (0.8 s at N = 10 000
#: for the 16-DOF turbine), so batches run as maps of this size.
MAP_CHUNK = 500


def _mapped(f: ca.Function, N: int, parallel: str, *rows: np.ndarray) -> list[np.ndarray]:
    """``f.map(N)`` on arguments given as (N, k) rows, outputs as numpy arrays (r, N c).

    Evaluated in chunks of :data:`MAP_CHUNK` points through ``Function.buffer()``: CasADi
    reads and writes numpy memory directly, without DM conversions (which cost more
    than the evaluation for large batches).
    """
    rows = [np.ascontiguousarray(r, dtype=float) for r in rows]
    maps: dict[int, ca.Function] = {}
    parts = []
    for start in range(0, N, MAP_CHUNK):
        k = min(MAP_CHUNK, N - start)
        if k not in maps:
            maps[k] = f.map(k, parallel)
        fm = maps[k]
        buf, trigger = fm.buffer()
        args = [r[start:start + k].reshape(-1) for r in rows]      # (k, m) C order = (m, k) F order
        for i, a in enumerate(args):
            buf.set_arg(i, memoryview(a))
        outs = [np.empty(fm.numel_out(j)) for j in range(fm.n_out())]
        for j, o in enumerate(outs):
            buf.set_res(j, memoryview(o))
        trigger()
        parts.append([o.reshape(fm.size_out(j), order="F") for j, o in enumerate(outs)])
    return [np.concatenate([p[j] for p in parts], axis=1) for j in range(f.n_out())]


def _unstack(a: np.ndarray, N: int) -> np.ndarray:
    """CasADi's horizontally stacked (r, N c) result as (N, r, c)."""
    r = a.shape[0]
    c = a.shape[1] // N
    return a.reshape(r, c, N, order="F").transpose(2, 0, 1)


def _batch_outputs(target, sel, X, U, P, h, parallel):
    N, eom = X.shape[0], target.eom
    names, _, f_out, picks = sel
    Y, Cy, Dy = np.zeros((N, len(picks))), np.zeros((N, len(picks), eom.n_x)), np.zeros((N, len(picks), eom.n_u))
    if f_out is not None and any(k == "y" for k, _ in picks):
        jac, fd = output_functions(eom, f_out)
        y_all, cy_all, dy_all = _mapped(jac, N, parallel, X, U, P)
        cy_all, dy_all = _unstack(cy_all, N), _unstack(dy_all, N)
        if h is not None:
            cy_all = _unstack(_mapped(fd, N, parallel, X, U, P, np.tile(h, (N, 1)))[0], N)
    for r, (kind, i) in enumerate(picks):
        if kind == "y":
            Y[:, r], Cy[:, r], Dy[:, r] = y_all[i], cy_all[:, i], dy_all[:, i]
        else:
            Y[:, r], Cy[:, r, i] = X[:, i], 1.0
    return Y, Cy, Dy


def compiled(f: ca.Function) -> ca.Function:
    """``f`` as compiled C through :func:`mbsym.codegen.compile_function` (disk cache, gcc -O1).

    Falls back to ``f`` itself (with a ``CompilationWarning``) when no compiler works.
    """
    from ..codegen import compile_function

    return compile_function(f).function

