"""Export a model's equations as standalone C (CasADi's code generator) with a minimal ``main.c``.

Files written to the target directory (``name`` defaults to the model name):

- ``<name>.c``, ``<name>.h``: the functions of :mod:`mbsym.export.functions`,
  each as ``<name>_<function>`` with CasADi's calling convention
  (``int f(const double** arg, double** res, long long* iw, double* w, int mem)``,
  work sizes from ``<name>_<function>_work``); every output is dense, column-major.
  The code needs only the C standard library and ``libm`` (CasADi's ``qr`` linear
  solver, used by ``rhs`` beyond :data:`mbsym.equations.SYMBOLIC_SOLVE_MAX_DOF`
  coordinates and by the Jacobians, is generated inline).
- ``main.c``: reads ``x (n_x)``, ``u (n_u)``, ``p (n_p)`` from standard input
  (whitespace-separated; nothing at all: ``x = 0``, ``u = 0``, ``p`` the defaults),
  evaluates every function and prints one line per function:
  ``name rows cols v_1 ... v_rows*cols`` (column-major, ``%.17g``). ``residual``
  is evaluated at the ``qdd`` of ``rhs`` (so it prints zeros up to rounding).

Build: ``cc -O1 -o main main.c <name>.c -lm``.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

import casadi as ca

from ..exceptions import ExportError
from .functions import FUNCTION_NAMES, casadi_functions, check_names, export_specs

__all__ = ["ExportedC", "export_c"]


@dataclass(frozen=True)
class ExportedC:
    """Files written by :func:`export_c` and how to build them.

    Attributes
    ----------
    directory, source, header, main : Path
    prefix : str
        C name prefix: function ``f`` is ``<prefix>_f``.
    functions : tuple of str
        Exported function names (without the prefix).
    """

    directory: Path
    source: Path
    header: Path
    main: Path
    prefix: str
    functions: tuple[str, ...]

    def build_command(self, compiler: str = "cc", flags: tuple[str, ...] = ("-O1",)) -> list[str]:
        """The command compiling ``main`` (run it in :attr:`directory`)."""
        return [compiler, *flags, "-o", "main", self.main.name, self.source.name, "-lm"]


def export_c(eom, directory, *, name: str | None = None, functions=FUNCTION_NAMES, main: bool = True) -> ExportedC:
    """Write the model's functions as standalone C (see the module docstring for the files).

    Parameters
    ----------
    eom : EquationsOfMotion
    directory : str or Path
        Target directory (created if missing; existing files of the same names are replaced).
    name : str, optional, keyword-only
        File name and C prefix (a C identifier); default the model name.
    functions : sequence of str, optional, keyword-only
        Names from :data:`mbsym.export.functions.FUNCTION_NAMES` (default: all). The Jacobians of
        a large model are long C files (tens of seconds to compile beyond ~8 coordinates).
    main : bool, optional, keyword-only
        Also write ``main.c`` (default True).

    Returns
    -------
    ExportedC

    Raises
    ------
    ExportError
        An invalid name, unknown function names, or a directory that cannot be created.
    """
    prefix = eom.name if name is None else name
    if not isinstance(prefix, str) or not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", prefix):
        raise ExportError(f"name must be a C identifier (letters, digits, underscores; not starting with a digit); "
                          f"got {prefix!r}. Pass name='...' to export_c.")
    names = check_names(functions)
    directory = Path(directory)
    try:
        directory.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise ExportError(f"cannot create the directory {directory}: {exc}.") from exc
    funs = casadi_functions(eom, names, prefix=prefix)
    cg = ca.CodeGenerator(f"{prefix}.c", {"with_header": True})
    for fun in funs.values():
        cg.add(fun)
    cg.generate(str(directory) + "/")
    main_path = directory / "main.c"
    if main:
        main_path.write_text(main_source(eom, prefix, names))
    return ExportedC(directory, directory / f"{prefix}.c", directory / f"{prefix}.h", main_path, prefix, names)


_MAIN_HEAD = r"""/* Minimal driver of the mbsym export {prefix!s}: reads x, u, p from standard input, prints every function.
 *
 * Build:  cc -O1 -o main main.c {prefix}.c -lm
 * Run:    echo "x_1 ... x_{nx} u_1 ... u_{nu} p_1 ... p_{np}" | ./main      (no input: x = 0, u = 0, p = defaults)
 * Output: one line per function: name rows cols values (column-major).
 *
 * States x: {states}
 * Inputs u: {inputs}
 * Parameters p: {parameters}
 */
#include <stdio.h>
#include <stdlib.h>
#include "{prefix}.h"

#define NQ {nq}
#define NX {nx}
#define NU {nu}
#define NP {np}

typedef int (*fun_t)(const casadi_real**, casadi_real**, casadi_int*, casadi_real*, int);
typedef int (*work_t)(casadi_int*, casadi_int*, casadi_int*, casadi_int*);
typedef int (*checkout_t)(void);
typedef void (*release_t)(int);

/* Evaluate f on the n_in arguments args; write its (dense) output to out. Returns 0 on success. */
static int call(fun_t f, work_t work, checkout_t checkout, release_t release,
                const casadi_real** args, int n_in, casadi_real* out) {{
  casadi_int sz_arg, sz_res, sz_iw, sz_w, i;
  int flag, mem;
  const casadi_real** arg;
  casadi_real** res;
  casadi_int* iw;
  casadi_real* w;
  work(&sz_arg, &sz_res, &sz_iw, &sz_w);
  arg = calloc(sz_arg > n_in ? sz_arg : n_in, sizeof(*arg));
  res = calloc(sz_res > 1 ? sz_res : 1, sizeof(*res));
  iw = calloc(sz_iw > 0 ? sz_iw : 1, sizeof(*iw));
  w = calloc(sz_w > 0 ? sz_w : 1, sizeof(*w));
  if (!arg || !res || !iw || !w) return 1;
  for (i = 0; i < n_in; ++i) arg[i] = args[i];
  res[0] = out;
  mem = checkout();
  flag = f(arg, res, iw, w, mem);
  release(mem);
  free(arg); free(res); free(iw); free(w);
  return flag;
}}

static void print(const char* name, int rows, int cols, const casadi_real* v) {{
  int i;
  printf("%s %d %d", name, rows, cols);
  for (i = 0; i < rows * cols; ++i) printf(" %.17g", v[i]);
  printf("\n");
}}

#define CALL(fn, n_in, out) call(fn, fn##_work, fn##_checkout, fn##_release, args, n_in, out)

int main(void) {{
  casadi_real x[NX + 1] = {{0}}, u[NU + 1] = {{0}}, p[NP + 1] = {{{defaults}}};
  casadi_real in[NX + NU + NP + 1], qdd[NQ + 1] = {{0}};
  const casadi_real* q = x;
  const casadi_real* qd = x + NQ;
  const casadi_real* args[5];
  int n = 0, i;
  double v;
  while (n < NX + NU + NP && scanf("%lf", &v) == 1) in[n++] = v;
  if (n != 0 && n != NX + NU + NP) {{
    fprintf(stderr, "expected %d numbers (x: %d, u: %d, p: %d); got %d\n", NX + NU + NP, NX, NU, NP, n);
    return 2;
  }}
  if (n) {{
    for (i = 0; i < NX; ++i) x[i] = in[i];
    for (i = 0; i < NU; ++i) u[i] = in[NX + i];
    for (i = 0; i < NP; ++i) p[i] = in[NX + NU + i];
  }}
  (void)q; (void)qd; (void)qdd;
"""


def main_source(eom, prefix: str, names: tuple[str, ...]) -> str:
    """Source of ``main.c`` for the exported functions ``names``."""
    defaults = ", ".join(repr(float(eom.defaults.get(n, 0.0))) for n in eom.parameters) or "0"
    text = _MAIN_HEAD.format(prefix=prefix, nq=eom.n_q, nx=eom.n_x, nu=eom.n_u, np=eom.n_p,
                             states=" ".join(eom.states), inputs=" ".join(eom.inputs) or "(none)",
                             parameters=" ".join(eom.parameters) or "(none)", defaults=defaults)
    arrays = {"q": "q", "qd": "qd", "qdd": "qdd", "x": "x", "u": "u", "p": "p"}
    specs = {s.name: s for s in export_specs(eom, names)}
    order = [n for n in names if n == "rhs"] + [n for n in names if n != "rhs"]   # rhs first: residual uses its qdd
    lines = []
    for name in order:
        s = specs[name]
        rows, cols = s.shape
        fn = f"{prefix}_{name}"
        lines.append("  {")
        lines.append(f"    casadi_real out[{max(rows * cols, 1)}];")
        lines += [f"    args[{i}] = {arrays[a]};" for i, a in enumerate(s.args)]
        lines.append(f"    if (CALL({fn}, {len(s.args)}, out)) {{ fprintf(stderr, \"{fn} failed\\n\"); return 1; }}")
        if name == "rhs":
            lines.append("    for (i = 0; i < NQ; ++i) qdd[i] = out[NQ + i];")
        lines.append(f"    print(\"{name}\", {rows}, {cols}, out);")
        lines.append("  }")
    return text + "\n".join(lines) + "\n  return 0;\n}\n"
