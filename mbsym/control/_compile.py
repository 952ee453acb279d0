"""Compiled NLP solvers: the derivative Functions of an ``nlpsol`` as generated C, cached on disk.

CasADi's NLP solvers evaluate their own Functions (``nlp_f``, ``nlp_g``,
``nlp_grad_f``, ``nlp_jac_g``, ``nlp_hess_l``, …). ``solver.generate_dependencies``
writes all of them as one C file; ``nlpsol(name, plugin, "lib.so", opts)`` loads
them back. The library goes to the same cache as :mod:`mbsym.codegen` (same
directory, compiler and flags), keyed by a SHA-256 of the generated source, the
compiler command and version, the flags and the CasADi version, so an unchanged
problem compiles once per machine.
"""

from __future__ import annotations

import hashlib
import os
import platform
import subprocess
import sys
import tempfile
import time
import warnings
from pathlib import Path
from typing import Any, Callable

import casadi as ca

from ..codegen import COMPILE_TIMEOUT_S, CompilationWarning, cache_dir, compiler_command

__all__ = ["compiled_nlpsol", "NLP_FLAGS"]

#: Compiler flags of NLP solver Functions. CasADi's own horizon derivatives of a mapped stage are large (2.9 MB of
#: C for the cart pendulum with RK4, N = 40: ~80 s of gcc CPU at -O1, ~6 s at -O0); the stage-level Functions of
#: :mod:`mbsym.control.nlpfunctions` that NlpSolver compiles instead are small enough for -O1.
NLP_FLAGS: tuple[str, ...] = ("-O1",)


def compiled_nlpsol(name: str, plugin: str, nlp: dict, options: dict[str, Any], *, compile: bool = True,
                    flags: tuple[str, ...] | None = None,
                    functions: Callable[[ca.Function], list] | None = None) -> tuple[ca.Function, bool, float]:
    """An ``nlpsol`` whose derivative Functions run compiled C when possible.

    ``functions(solver)``, if given, returns the Functions to compile in place of
    the solver's own (same names and signatures, plus the oracle ``"nlp"``).

    Returns
    -------
    (solver, compiled, seconds)
        ``compiled`` is False when compilation is off, failed (a
        :class:`~mbsym.codegen.CompilationWarning` says why) or ``MBSYM_NO_COMPILE`` is set.
    """
    t0 = time.perf_counter()
    flags = NLP_FLAGS if flags is None else tuple(flags)
    solver = ca.nlpsol(name, plugin, nlp, options)
    if not compile or os.environ.get("MBSYM_NO_COMPILE", "").strip() not in ("", "0"):
        return solver, False, time.perf_counter() - t0
    cc = compiler_command()
    if cc is None:
        warnings.warn("No C compiler found: the NLP Functions run in CasADi's virtual machine.", CompilationWarning,
                      stacklevel=2)
        return solver, False, time.perf_counter() - t0
    folder = cache_dir()
    folder.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix="mbsym_cg_", dir=folder) as tmp:
        source = Path(tmp) / f"{name}_nlp.c"
        cg = ca.CodeGenerator(source.name, {"with_header": False})
        if functions is not None:
            for fn in functions(solver):
                cg.add(fn)
        else:
            cg.add(solver.oracle())                  # "nlp": the loader looks for it
            for fname in solver.get_function():      # nlp_f, nlp_g, nlp_grad_f, nlp_jac_g, nlp_hess_l, ...
                cg.add(solver.get_function(fname))
        cg.generate(tmp + os.sep)
        text = source.read_text()
        key = _key(text, cc, flags)
        library = folder / f"{name}_nlp_{key[:20]}.so"
        if not library.exists():
            out = Path(tmp) / library.name
            proc = subprocess.run([*cc, *flags, "-shared", "-fPIC", "-o", str(out), str(source), "-lm"],
                                  capture_output=True, text=True, timeout=COMPILE_TIMEOUT_S)
            if proc.returncode != 0:
                warnings.warn(f"Compiling the NLP of {name!r} failed ({proc.stderr.strip()[-300:]}); using CasADi's "
                              f"virtual machine.", CompilationWarning, stacklevel=2)
                return solver, False, time.perf_counter() - t0
            os.replace(out, library)
    try:
        return ca.nlpsol(name, plugin, str(library), options), True, time.perf_counter() - t0
    except RuntimeError as exc:
        library.unlink(missing_ok=True)
        warnings.warn(f"Loading {library} failed ({str(exc)[-300:]}); using CasADi's virtual machine.",
                      CompilationWarning, stacklevel=2)
        return solver, False, time.perf_counter() - t0


def _key(source: str, cc: tuple[str, ...], flags: tuple[str, ...]) -> str:
    h = hashlib.sha256()
    for part in (source, "\0".join(cc), _version(cc), "\0".join(flags), ca.__version__, platform.machine(),
                 sys.platform):
        h.update(part.encode())
        h.update(b"\0")
    return h.hexdigest()


def _version(cc: tuple[str, ...]) -> str:
    try:
        out = subprocess.run([*cc, "--version"], capture_output=True, text=True, timeout=30)
        return out.stdout.splitlines()[0] if out.stdout else out.stderr.strip()
    except (OSError, subprocess.SubprocessError):
        return "unknown"
