"""The Functions every export writes: names, signatures and how each is computed.

One table serves the C and the Python exports so that both give the same set,
named and called like :attr:`mbsym.EquationsOfMotion.functions`:

==================  =====================  =========================================
name                arguments              returns
==================  =====================  =========================================
mass_matrix         (q, p) or (q, u, p)    M (n_q, n_q); ``u`` only with prescribed
                                           coordinates, as ``eom.functions``
forcing             (q, qd, u, p)          F (n_q)
residual            (q, qd, qdd, u, p)     e = F - M qdd (n_q)
rhs                 (x, u, p)              xd = [qd; M^-1 F] (n_x)
rhs_jacobian_x      (x, u, p)              A = d rhs / d x (n_x, n_x)
rhs_jacobian_u      (x, u, p)              B = d rhs / d u (n_x, n_u)
kinetic_energy      (q, qd, u, p)          T [J]
potential_energy    (q, u, p)              V [J]
power               (q, qd, u, p)          power of the non-conservative loads [W]
==================  =====================  =========================================

The Jacobians of ``rhs`` use the residual form (as :func:`mbsym.linearize`):
with ``qdd = M^-1 F``, ``d qdd / d(q, qd, u) = M^-1 d e / d(q, qd, u)`` at fixed
``qdd``, so only the SX Jacobians of the residual are differentiated (the
solve-then-differentiate expression grows much faster with the number of
coordinates) and the solves are numeric.
"""

from __future__ import annotations

from dataclasses import dataclass

import casadi as ca

from ..exceptions import ExportError

__all__ = ["ExportSpec", "FUNCTION_NAMES", "export_specs", "residual_jacobians", "dense_sx", "casadi_functions",
           "check_names"]

#: Every exported function, in the order they are written.
FUNCTION_NAMES: tuple[str, ...] = ("mass_matrix", "forcing", "residual", "rhs", "rhs_jacobian_x", "rhs_jacobian_u",
                                   "kinetic_energy", "potential_energy", "power")

_DOC = {
    "mass_matrix": "Mass matrix M [kg, kg m, kg m^2], shape (n_q, n_q).",
    "forcing": "Forcing F (generalized forces minus velocity terms) [N, N m], shape (n_q,).",
    "residual": "Residual e = F - M qdd [N, N m], shape (n_q,).",
    "rhs": "First-order right-hand side xd = [qd; qdd], shape (n_x,).",
    "rhs_jacobian_x": "A = d rhs / d x, shape (n_x, n_x).",
    "rhs_jacobian_u": "B = d rhs / d u, shape (n_x, n_u).",
    "kinetic_energy": "Kinetic energy T [J].",
    "potential_energy": "Potential energy of gravity and springs V [J].",
    "power": "Power of the non-conservative loads [W].",
}


@dataclass(frozen=True)
class ExportSpec:
    """One exported function: its name, argument names and sizes, output shape and docstring line."""

    name: str
    args: tuple[str, ...]
    sizes: tuple[int, ...]
    shape: tuple[int, int]
    doc: str


def _sizes(eom) -> dict[str, int]:
    return {"q": eom.n_q, "qd": eom.n_q, "qdd": eom.n_q, "x": eom.n_x, "u": eom.n_u, "p": eom.n_p}


def export_specs(eom, names=FUNCTION_NAMES) -> list[ExportSpec]:
    """Signatures of the exported functions of ``eom`` (argument lists mirror ``eom.functions``)."""
    f = eom.functions
    size = _sizes(eom)
    out = []
    for name in names:
        if name.startswith("rhs_jacobian"):
            args = ("x", "u", "p")
            shape = (eom.n_x, eom.n_x if name.endswith("_x") else eom.n_u)
        else:
            fun = getattr(f, name)
            args = tuple(fun.name_in())
            shape = tuple(fun.size_out(0))
        out.append(ExportSpec(name, args, tuple(size[a] for a in args), shape, _DOC[name]))
    return out


def residual_jacobians(eom) -> ca.Function:
    """SX ``(q, qd, qdd, u, p) -> (de/dq, de/dqd, de/du)``, dense, of the residual ``e = F - M qdd``."""
    d = eom.symbolic
    q, qd, qdd, u, p = d.q, d.qd, d.qdd, d.u, d.p
    e = eom.functions.residual(q, qd, qdd, u, p)
    jac = [ca.densify(ca.jacobian(e, v)) for v in (q, qd, u)]
    return ca.Function(f"{eom.name}_residual_jacobians", [q, qd, qdd, u, p], jac,
                       ["q", "qd", "qdd", "u", "p"], ["e_q", "e_qd", "e_u"], {"cse": True})


def dense_sx(f: ca.Function, name: str) -> ca.Function:
    """``f`` (an SXFunction) with dense outputs, as a new SXFunction named ``name``."""
    args = [ca.SX.sym(f.name_in(i), f.sparsity_in(i)) for i in range(f.n_in())]
    outs = [ca.densify(o) for o in f.call(args)]
    return ca.Function(name, args, outs, f.name_in(), f.name_out(), {"cse": True})


def casadi_functions(eom, names=FUNCTION_NAMES, *, prefix: str) -> dict[str, ca.Function]:
    """The exported functions as CasADi Functions with dense outputs, named ``<prefix>_<name>``.

    SX Functions stay SX; ``rhs`` of a model beyond
    :data:`mbsym.equations.SYMBOLIC_SOLVE_MAX_DOF` coordinates and the Jacobians are
    MX glue around SX Functions with CasADi's ``qr`` linear solver (which CasADi
    generates as plain C).
    """
    f = eom.functions
    out: dict[str, ca.Function] = {}
    for name in names:
        full = f"{prefix}_{name}"
        if name.startswith("rhs_jacobian"):
            out[name] = _rhs_jacobian(eom, name, full)
            continue
        fun = getattr(f, name)
        if fun.is_a("SXFunction"):
            out[name] = dense_sx(fun, full)
        else:
            args = [ca.MX.sym(fun.name_in(i), fun.sparsity_in(i)) for i in range(fun.n_in())]
            out[name] = ca.Function(full, args, [ca.densify(o) for o in fun.call(args)], fun.name_in(),
                                    fun.name_out())
    return out


def _rhs_jacobian(eom, which: str, full: str) -> ca.Function:
    """MX ``(x, u, p) -> A`` (``which`` = rhs_jacobian_x) or ``-> B`` in residual form with ``qr`` solves."""
    n = eom.n_q
    f = eom.functions
    x, u, p = ca.MX.sym("x", eom.n_x), ca.MX.sym("u", eom.n_u), ca.MX.sym("p", eom.n_p)
    q, qd = x[:n], x[n:]
    M = f.mass_matrix(q, u, p) if f.mass_matrix.n_in() == 3 else f.mass_matrix(q, p)
    qdd = ca.solve(M, f.forcing(q, qd, u, p), "qr")
    e_q, e_qd, e_u = residual_jacobians(eom)(q, qd, qdd, u, p)
    if which == "rhs_jacobian_x":
        lower = ca.solve(M, ca.horzcat(e_q, e_qd), "qr")
        out, label = ca.vertcat(ca.horzcat(ca.MX.zeros(n, n), ca.MX.eye(n)), lower), "A"
    else:
        lower = ca.solve(M, e_u, "qr") if eom.n_u else ca.MX.zeros(n, 0)
        out, label = ca.vertcat(ca.MX.zeros(n, eom.n_u), lower), "B"
    return ca.Function(full, [x, u, p], [ca.densify(out)], ["x", "u", "p"], [label])


def check_names(functions) -> tuple[str, ...]:
    """The requested names, in :data:`FUNCTION_NAMES` order; ExportError for unknown ones."""
    if isinstance(functions, str):
        functions = (functions,)
    names = tuple(functions)
    unknown = [n for n in names if n not in FUNCTION_NAMES]
    if unknown or not names:
        raise ExportError(f"unknown functions {unknown or '(none given)'}; choose from {list(FUNCTION_NAMES)}.")
    return tuple(n for n in FUNCTION_NAMES if n in names)
