"""Export a model's equations as a dependency-free Python module (numpy only).

The module is written from the *algorithm* of each CasADi SX Function (its
instruction list: inputs, constants, one operation per work variable, outputs),
so it performs the very operations of CasADi's virtual machine in the same order:
with plain Python floats and :mod:`math` (the C library's functions, as CasADi's
VM), results agree with ``eom.functions`` to the last bit in practice. An
operation that Python refuses on floats (a division by zero, ``sqrt`` of a
negative number, an overflow) makes the function rerun on numpy scalars, which
follow IEEE rules (inf, nan) as CasADi does.

``rhs`` of a model beyond :data:`mbsym.equations.SYMBOLIC_SOLVE_MAX_DOF`
coordinates (an MX Function with a numeric linear solve in mbsym) becomes
``numpy.linalg.solve(M, F)``; the Jacobians of ``rhs`` use the residual form of
:mod:`mbsym.export.functions` with numpy solves.

The functions of the module (see :mod:`mbsym.export.functions`) are called like
``eom.functions``, with ``p`` the parameter vector in ``PARAMETERS`` order
(``parameter_vector({...})`` builds it from names and the defaults), and return
numpy arrays: 1-D for column vectors, 2-D for matrices, a float for scalars.
"""

from __future__ import annotations

import math
from pathlib import Path

import casadi as ca

from ..exceptions import ExportError
from .functions import FUNCTION_NAMES, check_names, export_specs, residual_jacobians

__all__ = ["export_python", "python_source"]

# Python expressions of CasADi's scalar operations (x, y: work variables; names bound from the ops namespace).
_TEMPLATES: dict[int, str] = {
    ca.OP_ASSIGN: "{x}", ca.OP_ADD: "{x} + {y}", ca.OP_SUB: "{x} - {y}", ca.OP_MUL: "{x} * {y}",
    ca.OP_DIV: "{x} / {y}", ca.OP_NEG: "-{x}", ca.OP_EXP: "exp({x})", ca.OP_LOG: "log({x})",
    ca.OP_POW: "pow({x}, {y})", ca.OP_CONSTPOW: "pow({x}, {y})", ca.OP_SQRT: "sqrt({x})", ca.OP_SQ: "{x} * {x}",
    ca.OP_TWICE: "2.0 * {x}", ca.OP_SIN: "sin({x})", ca.OP_COS: "cos({x})", ca.OP_TAN: "tan({x})",
    ca.OP_ASIN: "asin({x})", ca.OP_ACOS: "acos({x})", ca.OP_ATAN: "atan({x})",
    ca.OP_LT: "(1.0 if {x} < {y} else 0.0)", ca.OP_LE: "(1.0 if {x} <= {y} else 0.0)",
    ca.OP_EQ: "(1.0 if {x} == {y} else 0.0)", ca.OP_NE: "(1.0 if {x} != {y} else 0.0)",
    ca.OP_NOT: "(1.0 if {x} == 0.0 else 0.0)", ca.OP_AND: "(1.0 if ({x} != 0.0 and {y} != 0.0) else 0.0)",
    ca.OP_OR: "(1.0 if ({x} != 0.0 or {y} != 0.0) else 0.0)", ca.OP_FLOOR: "floor({x})", ca.OP_CEIL: "ceil({x})",
    ca.OP_FMOD: "fmod({x}, {y})", ca.OP_FABS: "abs({x})",
    ca.OP_SIGN: "(-1.0 if {x} < 0.0 else (1.0 if {x} > 0.0 else {x}))", ca.OP_COPYSIGN: "copysign({x}, {y})",
    ca.OP_IF_ELSE_ZERO: "({y} if {x} != 0.0 else 0.0)", ca.OP_ERF: "erf({x})", ca.OP_FMIN: "fmin({x}, {y})",
    ca.OP_FMAX: "fmax({x}, {y})", ca.OP_INV: "1.0 / {x}", ca.OP_SINH: "sinh({x})", ca.OP_COSH: "cosh({x})",
    ca.OP_TANH: "tanh({x})", ca.OP_ASINH: "asinh({x})", ca.OP_ACOSH: "acosh({x})", ca.OP_ATANH: "atanh({x})",
    ca.OP_ATAN2: "atan2({x}, {y})", ca.OP_LOG1P: "log1p({x})", ca.OP_EXPM1: "expm1({x})",
    ca.OP_HYPOT: "hypot({x}, {y})", ca.OP_REMAINDER: "remainder({x}, {y})",
}
_OP_NAMES = {getattr(ca, n): n[3:].lower() for n in dir(ca) if n.startswith("OP_")}
_NAMESPACE = ("exp", "log", "pow", "sqrt", "sin", "cos", "tan", "asin", "acos", "atan", "floor", "ceil", "fmod",
              "copysign", "erf", "fmin", "fmax", "sinh", "cosh", "tanh", "asinh", "acosh", "atanh", "atan2",
              "log1p", "expm1", "hypot", "remainder")


def sx_body(f: ca.Function, name: str) -> list[str]:
    """Python source lines of ``def name(a0, a1, ..., _m)`` evaluating the SXFunction ``f``.

    The body returns one list of nonzeros per output (CasADi's column-major order).

    Raises
    ------
    ExportError
        If ``f`` is not an SXFunction or uses an operation with no Python form here.
    """
    if not f.is_a("SXFunction"):
        raise ExportError(f"{f.name()} is not an SX Function; only SX algorithms are written as Python.")
    args = [f"a{i}" for i in range(f.n_in())]
    body: list[str] = []
    used: set[str] = set()
    for k in range(f.n_instructions()):
        op = f.instruction_id(k)
        o, i = f.instruction_output(k), f.instruction_input(k)
        if op == ca.OP_CONST:
            body.append(f"w{o[0]} = {_constant(f.instruction_constant(k))}")
        elif op == ca.OP_INPUT:
            body.append(f"w{o[0]} = a{i[0]}[{i[1]}]")
        elif op == ca.OP_OUTPUT:
            body.append(f"r{o[0]}[{o[1]}] = w{i[0]}")
        elif op in _TEMPLATES:
            expr = _TEMPLATES[op].format(x=f"w{i[0]}", y=f"w{i[1]}" if len(i) > 1 else "")
            used.update(n for n in _NAMESPACE if f"{n}(" in expr)
            body.append(f"w{o[0]} = {expr}")
        else:
            raise ExportError(f"{f.name()}: the operation {_OP_NAMES.get(op, op)!r} has no Python form in "
                              "mbsym.export.python; export C instead (eom.export_c).")
    head = [f"def {name}({', '.join(args + ['_m'])}):"]
    head += [f"    {n} = _m.{n}" for n in sorted(used)]
    head += [f"    r{j} = [0.0] * {f.nnz_out(j)}" for j in range(f.n_out())]
    tail = [f"    return ({''.join(f'r{j}, ' for j in range(f.n_out()))})"]
    return head + ["    " + line for line in body] + tail


def _constant(v: float) -> str:
    if math.isnan(v):
        return "_NAN"
    if math.isinf(v):
        return "_INF" if v > 0 else "-_INF"
    return repr(float(v))


_SCALARS = ("kinetic_energy", "potential_energy", "power")
_VECTORS = ("forcing", "residual", "rhs")


def _out_spec(f: ca.Function, j: int, name: str) -> str:
    """``(nrow, ncol, positions, kind)`` of output j: positions of the nonzeros in the column-major dense array
    (None: dense) and the kind of result (``"scalar"``, ``"vector"`` or ``"matrix"``)."""
    sp = f.sparsity_out(j)
    kind = "scalar" if name in _SCALARS else "vector" if name in _VECTORS else "matrix"
    if sp.is_dense():
        return f"({sp.size1()}, {sp.size2()}, None, {kind!r})"
    rows, cols = sp.get_triplet()
    return f"({sp.size1()}, {sp.size2()}, {[r + c * sp.size1() for r, c in zip(rows, cols)]}, {kind!r})"


_RUNTIME = '''
import math as _math

import numpy as _np

_INF, _NAN = float("inf"), float("nan")


def _fmin(a, b):
    return b if a != a else (a if b != b or a <= b else b)


def _fmax(a, b):
    return b if a != a else (a if b != b or a >= b else b)


class _MathOps:
    """Python floats and the C library (math): the fast path, as CasADi's virtual machine."""

    exp, log, pow, sqrt, sin, cos, tan = _math.exp, _math.log, _math.pow, _math.sqrt, _math.sin, _math.cos, _math.tan
    asin, acos, atan, atan2, fmod, copysign = _math.asin, _math.acos, _math.atan, _math.atan2, _math.fmod, _math.copysign
    sinh, cosh, tanh, asinh, acosh, atanh = _math.sinh, _math.cosh, _math.tanh, _math.asinh, _math.acosh, _math.atanh
    erf, log1p, expm1, hypot, remainder = _math.erf, _math.log1p, _math.expm1, _math.hypot, _math.remainder
    fmin, fmax = staticmethod(_fmin), staticmethod(_fmax)
    floor = staticmethod(lambda x: float(_math.floor(x)))
    ceil = staticmethod(lambda x: float(_math.ceil(x)))


class _NumpyOps:
    """numpy scalars: IEEE results (inf, nan) where Python floats raise."""

    exp, log, pow, sqrt, sin, cos, tan = _np.exp, _np.log, _np.power, _np.sqrt, _np.sin, _np.cos, _np.tan
    asin, acos, atan, atan2, fmod, copysign = _np.arcsin, _np.arccos, _np.arctan, _np.arctan2, _np.fmod, _np.copysign
    sinh, cosh, tanh, asinh, acosh, atanh = _np.sinh, _np.cosh, _np.tanh, _np.arcsinh, _np.arccosh, _np.arctanh
    erf = staticmethod(lambda x: _np.float64(_math.erf(x)))
    log1p, expm1, hypot, remainder = _np.log1p, _np.expm1, _np.hypot, _np.remainder
    fmin, fmax, floor, ceil = _np.fmin, _np.fmax, _np.floor, _np.ceil


def _vec(value, n, name):
    """A float vector of n entries (a copy) from any sequence; ValueError naming the argument otherwise."""
    if value is None and n == 0:
        return _np.zeros(0)
    arr = _np.array(value, dtype=float).reshape(-1)
    if arr.size != n:
        raise ValueError(f"{name} has {arr.size} entries; expected {n}.")
    return arr


def _call(body, args):
    """Run a generated body on Python floats; rerun on numpy scalars if Python raises (1/0, sqrt(-1), overflow)."""
    try:
        return body(*[a.tolist() for a in args], _MathOps)
    except (ArithmeticError, ValueError):
        with _np.errstate(all="ignore"):
            return body(*[list(a) for a in args], _NumpyOps)


def _dense(values, spec):
    """Nonzeros (column-major) to a float ("scalar"), a 1-D array ("vector") or a 2-D array ("matrix")."""
    nrow, ncol, positions, kind = spec
    if positions is None:
        out = _np.array(values, dtype=float)
    else:
        out = _np.zeros(nrow * ncol)
        out[positions] = values
    if kind == "scalar":
        return float(out[0])
    return out if kind == "vector" else out.reshape((nrow, ncol), order="F")


def parameter_vector(values=None):
    """The parameter vector p in PARAMETERS order: values by name (a dict), DEFAULTS for the others."""
    values = dict(values or {})
    unknown = sorted(set(values) - set(PARAMETERS))
    if unknown:
        raise KeyError(f"unknown parameters {unknown}; the parameters are {list(PARAMETERS)}.")
    missing = [n for n in PARAMETERS if n not in values and n not in DEFAULTS]
    if missing:
        raise KeyError(f"no value for parameters {missing} (they have no default).")
    return _np.array([float(values.get(n, DEFAULTS.get(n))) for n in PARAMETERS])
'''


def python_source(eom, *, functions=FUNCTION_NAMES) -> str:
    """The source text of the module :func:`export_python` writes."""
    from .._lazy import installed_version

    f = eom.functions
    specs = export_specs(eom, functions)
    header = [
        f'"""Equations of motion of the mbsym model {eom.name!r}, exported by mbsym {installed_version("mbsym")}.',
        "",
        "Dependency-free (numpy only). Functions are called like mbsym's eom.functions, with p the",
        "parameter vector in PARAMETERS order (parameter_vector({...}) fills in the DEFAULTS); they",
        "return numpy arrays (1-D for vectors, 2-D for matrices, float for scalars).",
        "",
        f"Functions: {', '.join(s.name for s in specs)}.",
        '"""',
        "",
        f"NAME = {eom.name!r}",
        f"COORDINATES = {tuple(eom.coordinates)!r}",
        f"SPEEDS = {tuple(eom.speeds)!r}",
        f"STATES = {tuple(eom.states)!r}",
        f"INPUTS = {tuple(eom.inputs)!r}",
        f"PARAMETERS = {tuple(eom.parameters)!r}",
        f"DEFAULTS = {dict(eom.defaults)!r}",
        f"N_Q, N_X, N_U, N_P = {eom.n_q}, {eom.n_x}, {eom.n_u}, {eom.n_p}",
        f"__all__ = {['parameter_vector'] + [s.name for s in specs]!r}",
    ]
    parts = ["\n".join(header), _RUNTIME]
    needs_jac = any(s.name.startswith("rhs_jacobian") for s in specs)
    sx_needed = {s.name for s in specs if not s.name.startswith("rhs_jacobian")}
    if needs_jac or ("rhs" in sx_needed and not f.rhs.is_a("SXFunction")):
        sx_needed |= {"mass_matrix", "forcing"}
    if "rhs" in sx_needed and not f.rhs.is_a("SXFunction"):
        sx_needed.discard("rhs")
    for name in FUNCTION_NAMES:
        if name in sx_needed:
            fun = getattr(f, name)
            parts.append("\n".join(sx_body(fun, f"_sx_{name}")))
            parts.append(f"_OUT_{name} = {_out_spec(fun, 0, name)}")
    if needs_jac:
        jac = residual_jacobians(eom)
        parts.append("\n".join(sx_body(jac, "_sx_residual_jacobians")))
        parts.append(f"_SQUARE = ({eom.n_q}, {eom.n_q}, None, 'matrix')")
    for spec in specs:
        parts.append(_public(eom, spec))
    return "\n\n\n".join(parts) + "\n"


def _public(eom, spec) -> str:
    """Source of the public function ``spec.name``: checks, the SX body or numpy glue, numpy output."""
    sig = ", ".join(spec.args)
    doc = [f"    \"\"\"{spec.doc}", "", "    Arguments: " + ", ".join(
        f"{a} ({n})" for a, n in zip(spec.args, spec.sizes)) + "; p in PARAMETERS order.", "    \"\"\""]
    checks = [f"    {a} = _vec({a}, {n}, {a!r})" for a, n in zip(spec.args, spec.sizes)]
    n = eom.n_q
    mass_call = "_call(_sx_mass_matrix, (q, u, p))" if eom.prescribed else "_call(_sx_mass_matrix, (q, p))"
    accel = [
        f"    q, qd = x[:{n}], x[{n}:]",
        f"    M = _dense({mass_call}[0], _OUT_mass_matrix)",
        "    F = _dense(_call(_sx_forcing, (q, qd, u, p))[0], _OUT_forcing)",
        "    qdd = _np.linalg.solve(M, F)",
    ]
    if spec.name == "rhs" and not eom.functions.rhs.is_a("SXFunction"):
        body = accel + ["    return _np.concatenate([qd, qdd])"]
    elif spec.name == "rhs_jacobian_x":
        body = accel + [
            "    e_q, e_qd, _ = _call(_sx_residual_jacobians, (q, qd, qdd, u, p))",
            "    lower = _np.linalg.solve(M, _np.hstack([_dense(e_q, _SQUARE), _dense(e_qd, _SQUARE)]))",
            f"    return _np.vstack([_np.hstack([_np.zeros(({n}, {n})), _np.eye({n})]), lower])",
        ]
    elif spec.name == "rhs_jacobian_u":
        nu = eom.n_u
        body = accel + [
            "    _, _, e_u = _call(_sx_residual_jacobians, (q, qd, qdd, u, p))",
            f"    lower = _np.linalg.solve(M, _np.array(e_u, dtype=float).reshape(({n}, {nu}), order='F'))",
            f"    return _np.vstack([_np.zeros(({n}, {nu})), lower])",
        ]
    else:
        body = [f"    return _dense(_call(_sx_{spec.name}, ({sig},))[0], _OUT_{spec.name})"]
    return "\n".join([f"def {spec.name}({sig}):"] + doc + checks + body)


def export_python(eom, path, *, functions=FUNCTION_NAMES) -> Path:
    """Write the model's functions as a numpy-only Python module.

    Parameters
    ----------
    eom : EquationsOfMotion
    path : str or Path
        File to write (``.py``); its parent directory must exist.
    functions : sequence of str, optional, keyword-only
        Names from :data:`mbsym.export.functions.FUNCTION_NAMES` (default: all).

    Returns
    -------
    Path
        The file written.

    Raises
    ------
    ExportError
        Unknown function names, a missing directory, or an operation with no Python form.
    """
    functions = check_names(functions)
    path = Path(path)
    if not path.parent.is_dir():
        raise ExportError(f"cannot write {path}: the directory {path.parent} does not exist; create it first.")
    path.write_text(python_source(eom, functions=functions))
    return path
