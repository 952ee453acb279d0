"""The mass matrix and forcing of a small model in LaTeX, with the model's symbol names.

Each entry of ``M`` and ``F`` (the SX expressions of the derivation) is expanded
into a sum of monomials of *atoms* (symbols, and functions such as sin or cos of
an expanded argument) with numeric coefficients, then simplified where it is
cheap:

- like terms are collected (a term whose coefficient cancels to rounding level,
  ``|c1 + c2| <= 1e-13 max(|c1|, |c2|)``, is dropped);
- ``sin^2 + cos^2 = 1``: of the expression itself and its two normal forms
  (every ``sin(a)^k``, k >= 2, rewritten with ``1 - cos(a)^2``, or every
  ``cos(a)^k`` with ``1 - sin(a)^2``) the one with the fewest terms is kept;
- angle sums are folded back: ``sin a cos b + cos a sin b = sin(a + b)``,
  ``cos a cos b - sin a sin b = cos(a + b)`` (and the differences);
- a factor common to every term is written once in front.

Names: coordinates as given (a trailing number becomes a subscript, Greek
names become letters: ``q1`` → ``q_{1}``, ``theta`` → ``\\theta``), speeds
``\\dot{q}_{1}``, parameters and inputs by name, multi-letter names upright
(``\\mathrm{GeAz}``). The expansion is meant for models of a few coordinates:
beyond ``max_terms`` terms in any intermediate expression it stops with an
:class:`~mbsym.exceptions.ExportError` (use :func:`mbsym.export.export_python`
or :func:`mbsym.export.export_c` for large models).
"""

from __future__ import annotations

import math
import re
from fractions import Fraction

import casadi as ca

from ..exceptions import ExportError

__all__ = ["latex", "latex_entries", "latex_name"]

_GREEK = {"alpha", "beta", "gamma", "delta", "epsilon", "zeta", "eta", "theta", "iota", "kappa", "lambda", "mu",
          "nu", "xi", "pi", "rho", "sigma", "tau", "upsilon", "phi", "chi", "psi", "omega", "Gamma", "Delta",
          "Theta", "Lambda", "Xi", "Pi", "Sigma", "Upsilon", "Phi", "Psi", "Omega"}
_FUNCS = {ca.OP_SIN: "sin", ca.OP_COS: "cos", ca.OP_TAN: "tan", ca.OP_EXP: "exp", ca.OP_LOG: "ln",
          ca.OP_SQRT: "sqrt", ca.OP_FABS: "abs", ca.OP_ASIN: "arcsin", ca.OP_ACOS: "arccos", ca.OP_ATAN: "arctan",
          ca.OP_SINH: "sinh", ca.OP_COSH: "cosh", ca.OP_TANH: "tanh"}
_CANCEL = 1e-13


def latex_name(name: str) -> str:
    """LaTeX of a symbol name: ``q1`` → ``q_{1}``, ``m_2`` → ``m_{2}``, ``theta`` → ``\\theta``, ``GeAz`` → ``\\mathrm{GeAz}``."""
    m = re.fullmatch(r"([A-Za-z]+?)_?(\d+)", name) or re.fullmatch(r"([A-Za-z]+)_([A-Za-z0-9]+)", name)
    base, sub = (m.group(1), m.group(2)) if m else (name, "")
    if base in _GREEK:
        head = "\\" + base
    elif re.fullmatch(r"[A-Za-z]", base):
        head = base
    else:
        head = "\\mathrm{" + base.replace("_", "\\_") + "}"
    return head + (f"_{{{sub}}}" if sub else "")


class _Algebra:
    """Polynomials in atoms: ``{monomial: coefficient}``, a monomial a sorted tuple of ``(atom id, power)``."""

    def __init__(self, max_terms: int) -> None:
        self.max_terms = max_terms
        self.atoms: list[tuple] = []            # id -> (kind, payload, latex, sort key)
        self.ids: dict = {}                     # structural key -> id

    # ---------------------------------------------------------------- atoms
    def atom(self, key, kind: str, payload, tex: str, rank: int, order: int = 0) -> int:
        if key not in self.ids:
            self.ids[key] = len(self.atoms)
            self.atoms.append((kind, payload, tex, (rank, order, tex)))
        return self.ids[key]

    def function(self, name: str, arg: dict) -> dict:
        """``name(arg)`` as a polynomial (sin/cos arguments normalized to a positive leading term)."""
        if not arg:
            return self.const({"sin": 0.0, "cos": 1.0, "tan": 0.0, "exp": 1.0, "sqrt": 0.0, "abs": 0.0,
                               "arcsin": 0.0, "arctan": 0.0, "sinh": 0.0, "tanh": 0.0,
                               "cosh": 1.0}.get(name, math.nan))
        sign = 1.0
        if name in ("sin", "cos", "tan", "abs") and self._leading(arg) < 0:
            arg = self.scale(arg, -1.0)
            sign = -1.0 if name in ("sin", "tan") else 1.0
        key = ("f", name, frozenset(arg.items()))
        inner = self.tex(arg)
        tex = {"sqrt": f"\\sqrt{{{inner}}}", "abs": f"\\left|{inner}\\right|"}.get(
            name, f"\\{name}\\left({inner}\\right)")
        return {((self.atom(key, name, arg, tex, 2), 1),): sign}

    def _leading(self, p: dict) -> float:
        return p[min(p, key=self._mono_key)]

    # ---------------------------------------------------------------- arithmetic
    @staticmethod
    def const(c: float) -> dict:
        return {(): float(c)} if c != 0.0 else {}

    def add(self, a: dict, b: dict) -> dict:
        out = dict(a)
        for m, c in b.items():
            if m in out:
                s = out[m] + c
                if abs(s) <= _CANCEL * max(abs(out[m]), abs(c)):
                    del out[m]
                else:
                    out[m] = s
            else:
                out[m] = c
        self._check(out)
        return out

    def scale(self, a: dict, k: float) -> dict:
        return {m: c * k for m, c in a.items()} if k != 0.0 else {}

    def mul(self, a: dict, b: dict) -> dict:
        out: dict = {}
        for ma, ca_ in a.items():
            for mb, cb in b.items():
                out = self.add(out, {self._mono_mul(ma, mb): ca_ * cb})
        return out

    def _mono_mul(self, ma: tuple, mb: tuple) -> tuple:
        powers = dict(ma)
        for i, k in mb:
            powers[i] = powers.get(i, 0) + k
        return tuple(sorted(((i, k) for i, k in powers.items() if k != 0), key=lambda t: self.atoms[t[0]][3]))

    def power(self, a: dict, n: int) -> dict:
        if n >= 0:
            out = self.const(1.0)
            for _ in range(n):
                out = self.mul(out, a)
            return out
        if len(a) == 1:
            (m, c), = a.items()
            return {tuple((i, k * n) for i, k in m): c ** n}
        key = ("inv", frozenset(a.items()))
        return {((self.atom(key, "inv", a, self.tex(a), 6), -n),): 1.0} if n < 0 else {}

    def _check(self, p: dict) -> None:
        if len(p) > self.max_terms:
            raise ExportError(f"an expression of this model expands to more than {self.max_terms} terms: latex() "
                              "is meant for small models; pass a larger max_terms, or use export_python/export_c.")

    def _mono_key(self, m: tuple):
        return tuple((self.atoms[i][3], -k) for i, k in m)

    # ---------------------------------------------------------------- printing
    def tex(self, p: dict, digits: int | None = 6, factor: bool = False) -> str:
        if not p:
            return "0"
        if factor and len(p) > 1:
            common, rest = self._common(p)
            if common:
                return self._term(common, 1.0, digits) + " \\left(" + self.tex(rest, digits) + "\\right)"
        terms = sorted(p.items(), key=lambda mc: (-sum(k for _, k in mc[0] if k > 0), self._mono_key(mc[0])))
        out = ""
        for j, (m, c) in enumerate(terms):
            t = self._term(m, abs(c), digits)
            out += ("-" if c < 0 else "") + t if j == 0 else (" - " if c < 0 else " + ") + t
        return out

    def _common(self, p: dict) -> tuple[tuple, dict]:
        """The monomial (positive powers) dividing every term, and the quotient."""
        monos = list(p)
        common = dict(monos[0])
        for m in monos[1:]:
            d = dict(m)
            common = {i: min(k, d.get(i, 0)) for i, k in common.items() if k > 0 and d.get(i, 0) > 0}
        common = {i: k for i, k in common.items() if k > 0}
        if not common:
            return (), p
        cm = tuple(sorted(common.items(), key=lambda t: self.atoms[t[0]][3]))
        inv = tuple((i, -k) for i, k in cm)
        return cm, {self._mono_mul(m, inv): c for m, c in p.items()}

    def _term(self, m: tuple, c: float, digits: int | None) -> str:
        num = [self._factor(i, k) for i, k in m if k > 0]
        den = [self._factor(i, -k) for i, k in m if k < 0]
        coef = _number(c, digits)
        if den:
            top = " ".join(([coef] if coef != "1" else []) + num) or "1"
            return f"\\frac{{{top}}}{{{' '.join(den)}}}"
        if not num:
            return coef
        return " ".join(([coef] if coef != "1" else []) + num)

    def _factor(self, i: int, k: int) -> str:
        kind, _, tex, _ = self.atoms[i]
        if kind == "inv":
            tex = f"\\left({tex}\\right)"
        if k == 1:
            return tex
        if kind in ("sin", "cos", "tan", "sinh", "cosh", "tanh", "ln", "exp", "arcsin", "arccos", "arctan"):
            return tex.replace(f"\\{kind}", f"\\{kind}^{{{k}}}", 1)
        if kind not in ("sym",):
            tex = f"\\left({tex}\\right)" if kind != "inv" else tex
        return f"{tex}^{{{k}}}"


def _number(c: float, digits: int | None) -> str:
    """A positive coefficient: integers and simple fractions exactly, else ``digits`` significant digits."""
    if c == round(c) and c < 1e6:
        return str(int(round(c)))
    frac = Fraction(c).limit_denominator(12)
    if frac.denominator > 1 and abs(float(frac) - c) <= 1e-12 * c:
        return f"\\frac{{{frac.numerator}}}{{{frac.denominator}}}"
    text = repr(c) if digits is None else f"{c:.{digits}g}"
    if "e" in text:
        mant, exp = text.split("e")
        return f"{mant} \\cdot 10^{{{int(exp)}}}"
    return text


# ---------------------------------------------------------------------------- SX -> polynomial
def _binary(alg: _Algebra, op: int, a: dict, b: dict) -> dict:
    if op == ca.OP_ADD:
        return alg.add(a, b)
    if op == ca.OP_SUB:
        return alg.add(a, alg.scale(b, -1.0))
    if op == ca.OP_MUL:
        return alg.mul(a, b)
    if op == ca.OP_DIV:
        return alg.mul(a, alg.power(b, -1))
    if op in (ca.OP_POW, ca.OP_CONSTPOW):
        k = b.get((), 0.0) if set(b) <= {()} else None
        if k is not None and k == round(k) and abs(k) <= 12:
            return alg.power(a, int(round(k)))
        if k == 0.5:
            return alg.function("sqrt", a)
    raise ExportError(f"latex(): the operation {_op_name(op)!r} with these operands has no LaTeX form here.")


def _unary(alg: _Algebra, op: int, a: dict) -> dict:
    if op == ca.OP_NEG:
        return alg.scale(a, -1.0)
    if op == ca.OP_ASSIGN:
        return a
    if op == ca.OP_SQ:
        return alg.mul(a, a)
    if op == ca.OP_TWICE:
        return alg.scale(a, 2.0)
    if op == ca.OP_INV:
        return alg.power(a, -1)
    if op in _FUNCS:
        return alg.function(_FUNCS[op], a)
    raise ExportError(f"latex(): the operation {_op_name(op)!r} has no LaTeX form here.")


def _op_name(op: int) -> str:
    return next((n[3:].lower() for n in dir(ca) if n.startswith("OP_") and getattr(ca, n) == op), str(op))


def _convert(alg: _Algebra, expr: ca.SX, symbols: dict, memo: dict) -> dict:
    """The polynomial of a scalar SX expression (iterative post-order walk, shared nodes converted once)."""
    stack = [expr]
    while stack:
        node = stack[-1]
        h = node.element_hash()
        if h in memo:
            stack.pop()
            continue
        if node.is_constant():
            memo[h] = alg.const(float(node))
        elif node.is_symbolic():
            if h not in symbols:
                raise ExportError(f"latex(): the symbol {node.name()!r} is not a coordinate, speed, input or parameter.")
            memo[h] = symbols[h]
        else:
            deps = [node.dep(i) for i in range(node.n_dep())]
            todo = [d for d in deps if d.element_hash() not in memo]
            if todo:
                stack.extend(todo)
                continue
            args = [memo[d.element_hash()] for d in deps]
            memo[h] = _unary(alg, node.op(), args[0]) if len(args) == 1 else _binary(alg, node.op(), *args)
        stack.pop()
    return memo[expr.element_hash()]


# ---------------------------------------------------------------------------- simplification
def _pythagoras(alg: _Algebra, p: dict, kind: str) -> dict:
    """Normal form with every ``kind(a)^k`` (k >= 2) rewritten through ``1 - other(a)^2``."""
    other = "cos" if kind == "sin" else "sin"
    out: dict = {}
    work = list(p.items())
    while work:
        m, c = work.pop()
        hit = next(((i, k) for i, k in m if alg.atoms[i][0] == kind and k >= 2), None)
        if hit is None:
            out = alg.add(out, {m: c})
            continue
        i = hit[0]
        (pm, _), = alg.function(other, alg.atoms[i][1]).items()
        base = alg._mono_mul(m, ((i, -2),))
        work.append((base, c))
        work.append((alg._mono_mul(base, ((pm[0][0], 2),)), -c))
    return out


def _fold_angle_sums(alg: _Algebra, p: dict) -> dict:
    """``sin a cos b ± cos a sin b → sin(a ± b)``, ``cos a cos b ∓ sin a sin b → cos(a ± b)``, until none is left."""
    p = dict(p)
    changed = True
    while changed:
        changed = False
        for m, c in list(p.items()):
            found = _fold_one(alg, p, m, c)
            if found:
                changed = True
                break
    return p


def _fold_one(alg: _Algebra, p: dict, m: tuple, c: float) -> bool:
    trig = [i for i, k in m if k == 1 and alg.atoms[i][0] in ("sin", "cos")]
    for x in range(len(trig)):
        for y in range(len(trig)):
            i1, i2 = trig[x], trig[y]
            k1, k2 = alg.atoms[i1][0], alg.atoms[i2][0]
            if i1 == i2 or (k1, k2) not in (("sin", "cos"), ("cos", "cos")) or (k1 == "cos" and x > y):
                continue
            a, b = alg.atoms[i1][1], alg.atoms[i2][1]
            if a == b:
                continue
            swap = ("cos", "sin") if k1 == "sin" else ("sin", "sin")
            j1, j2 = alg.ids.get(("f", swap[0], frozenset(a.items()))), alg.ids.get(("f", swap[1], frozenset(b.items())))
            if j1 is None or j2 is None:
                continue
            rest = alg._mono_mul(m, ((i1, -1), (i2, -1)))
            partner = alg._mono_mul(rest, ((j1, 1), (j2, 1)))
            cp = p.get(partner)
            if cp is None or abs(abs(cp) - abs(c)) > 1e-12 * abs(c):
                continue
            same = (cp > 0) == (c > 0)
            if k1 == "sin":        # sin a cos b + s cos a sin b
                arg = alg.add(a, b if same else alg.scale(b, -1.0))
                new = alg.function("sin", arg)
            else:                  # cos a cos b + s sin a sin b
                arg = alg.add(a, alg.scale(b, -1.0) if same else b)
                new = alg.function("cos", arg)
            del p[m], p[partner]
            for key, val in alg.mul({rest: c}, new).items():
                merged = alg.add({key: p[key]} if key in p else {}, {key: val})
                p.pop(key, None)
                p.update(merged)
            return True
    return False


def _simplify(alg: _Algebra, p: dict) -> dict:
    candidates = [p, _pythagoras(alg, p, "sin"), _pythagoras(alg, p, "cos")]
    best = min(candidates, key=len)
    return _fold_angle_sums(alg, best)


# ---------------------------------------------------------------------------- public
def _symbols(alg: _Algebra, eom) -> dict:
    """Polynomials of every symbol of the derivation, keyed by SX element hash."""
    d = eom.symbolic
    groups = [(d.p, eom.parameters, 0, ""), (d.u, eom.inputs, 1, ""), (d.q, eom.coordinates, 3, ""),
              (d.qd, eom.coordinates, 4, "dot"), (d.qdd, eom.coordinates, 5, "ddot")]
    presc = set(eom.prescribed)
    texs: list[str] = []
    rows = []
    for vec, names, rank, accent in groups:
        for i, name in enumerate(names):
            acc = accent
            if rank == 1:
                for suffix, a in (("_dd", "ddot"), ("_d", "dot")):
                    if name.endswith(suffix) and name[: -len(suffix)] in presc:
                        name, acc = name[: -len(suffix)], a
                        break
            head, _, sub = latex_name(name).partition("_{")
            tex = (f"\\{acc}{{{head}}}" if acc else head) + (f"_{{{sub}" if sub else "")
            rows.append((vec[i], rank, i, tex))
            texs.append(tex)
    out = {}
    for sym, rank, i, tex in rows:
        if texs.count(tex) > 1:          # two names with one LaTeX form: keep them apart, verbatim
            tex = "\\mathrm{" + sym.name().replace("_", "\\_") + "}"
        out[sym.element_hash()] = {((alg.atom(("s", rank, i), "sym", None, tex, rank, i), 1),): 1.0}
    return out


def latex_entries(eom, *, digits: int | None = 6, max_terms: int = 400) -> tuple[list[list[str]], list[str]]:
    """LaTeX of every entry of ``M`` (n_q × n_q, symmetric) and ``F`` (n_q), simplified (module docstring).

    Parameters
    ----------
    eom : EquationsOfMotion
    digits : int or None, optional, keyword-only
        Significant digits of coefficients that are not integers or simple fractions (None: all,
        ``repr``).
    max_terms : int, optional, keyword-only
        Largest number of terms of any intermediate expansion.

    Raises
    ------
    ExportError
        A model too large for ``max_terms``, or an operation with no LaTeX form.
    """
    if digits is not None and (not isinstance(digits, int) or digits < 1):
        raise ExportError(f"digits must be a positive integer or None; got {digits!r}.")
    alg = _Algebra(int(max_terms))
    symbols = _symbols(alg, eom)
    memo: dict = {}
    d = eom.symbolic
    n = eom.n_q
    M = [[""] * n for _ in range(n)]
    for i in range(n):
        for j in range(i + 1):
            M[i][j] = M[j][i] = alg.tex(_simplify(alg, _convert(alg, d.M[i, j], symbols, memo)), digits, True)
    F = [alg.tex(_simplify(alg, _convert(alg, d.F[i], symbols, memo)), digits, True) for i in range(n)]
    return M, F


def latex(eom, *, form: str = "entries", digits: int | None = 6, max_terms: int = 400) -> str:
    """The equations ``M(q) qdd = F(q, qd, u)`` of a small model in LaTeX.

    Parameters
    ----------
    eom : EquationsOfMotion
    form : {"entries", "matrix"}, optional, keyword-only
        ``"entries"``: an ``aligned`` block with one line per entry (lower triangle of M, then F);
        ``"matrix"``: ``M`` and ``F`` as ``bmatrix`` (for very small models).
    digits, max_terms
        As :func:`latex_entries`.

    Returns
    -------
    str
        LaTeX math (without surrounding ``$``/``\\[``), ready for an ``equation*`` environment.

    Examples
    --------
    >>> import mbsym as mb
    >>> sys = mb.System(gravity=[0, 0, -9.81])
    >>> th = sys.coordinates("theta")
    >>> m, l = sys.parameters("m l")
    >>> sys.add_joint(mb.Revolute(sys.ground, mb.RigidBody("b", m, com=[0, 0, -l]), axis=[0, 1, 0],
    ...                           coordinate=th))
    >>> print(latex_entries(sys.equations())[0][0][0])
    m l^{2}
    """
    if form not in ("entries", "matrix"):
        raise ExportError(f"form must be 'entries' or 'matrix'; got {form!r}.")
    M, F = latex_entries(eom, digits=digits, max_terms=max_terms)
    n = eom.n_q
    names = [latex_name(c) for c in eom.coordinates]
    qvec = "\\begin{bmatrix} " + " & ".join(names) + " \\end{bmatrix}^{T}"
    if form == "matrix":
        rows = " \\\\\n".join(" & ".join(r) for r in M)
        fvec = " \\\\\n".join(F)
        return (f"\\mathbf{{q}} = {qvec}, \\quad\n\\mathbf{{M}} = \\begin{{bmatrix}}\n{rows}\n\\end{{bmatrix}}, "
                f"\\quad\n\\mathbf{{F}} = \\begin{{bmatrix}}\n{fvec}\n\\end{{bmatrix}}")
    lines = [f"\\mathbf{{M}}(\\mathbf{{q}})\\,\\ddot{{\\mathbf{{q}}}} &= \\mathbf{{F}}, \\qquad \\mathbf{{q}} = {qvec}"]
    for i in range(n):
        for j in range(i + 1):
            label = f"M_{{{i + 1}{j + 1}}}" if i == j else f"M_{{{i + 1}{j + 1}}} = M_{{{j + 1}{i + 1}}}"
            lines.append(f"{label} &= {M[i][j]}")
    lines += [f"F_{{{i + 1}}} &= {F[i]}" for i in range(n)]
    return "\\begin{aligned}\n" + " \\\\\n".join(lines) + "\n\\end{aligned}"
