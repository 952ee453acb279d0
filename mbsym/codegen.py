"""Compiled evaluation of CasADi Functions: generated C, the system compiler, a disk cache.

:func:`compile_function` turns a CasADi ``Function`` into a shared library
(CasADi's ``CodeGenerator``, then the system C compiler, ``-O1`` by default) and
loads it back with ``casadi.external``. Libraries are cached on disk under a key
derived from the serialized Function, the compiler (path and version), the
flags and the CasADi version, so a second preparation of the same Function, in
this process or a later one, skips the compiler. Without a working compiler the
original Function is returned (CasADi's virtual machine) with a
:class:`CompilationWarning`; results are the same, only slower.

Cache directory: ``$MBSYM_CACHE_DIR``, else ``$XDG_CACHE_HOME/mbsym``, else
``~/.cache/mbsym``. Compiler: ``compiler=``, else ``$MBSYM_CC``, else ``$CC``,
else ``gcc`` or ``cc`` on the ``PATH``. ``MBSYM_NO_COMPILE=1`` turns compilation
off (fallback without a warning).

Measured on the CI machine kind (paper45 turbine, 3 DOFs): the RK4 step of
~6000 SX instructions compiles in ~0.8 s at ``-O1`` and runs 600 steps in
1.6 ms instead of ~30 ms in the virtual machine.
"""

from __future__ import annotations

import functools
import hashlib
import os
import shlex
import shutil
import subprocess
import tempfile
import time
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import Sequence

import casadi as ca

__all__ = [
    "CompilationWarning",
    "CompiledFunction",
    "DEFAULT_FLAGS",
    "cache_dir",
    "find_compiler",
    "function_key",
    "compile_function",
    "clear_disk_cache",
]

#: Compiler flags: -O1 compiles large straight-line SX code fast and runs it nearly as fast as -O2/-O3.
DEFAULT_FLAGS: tuple[str, ...] = ("-O1",)
#: Seconds after which a compilation is abandoned (then: the virtual machine, with a warning).
COMPILE_TIMEOUT_S = 600.0


class CompilationWarning(UserWarning):
    """Compiled evaluation was requested but is not available: CasADi's virtual machine is used."""


@dataclass(frozen=True)
class CompiledFunction:
    """What :func:`compile_function` returns.

    Attributes
    ----------
    function : casadi.Function
        The compiled Function (``casadi.external``), or the original one when
        ``compiled`` is False. Same inputs and outputs either way.
    compiled : bool
        Whether ``function`` runs generated, compiled C.
    cache_hit : bool
        Whether the library came from the disk cache (no compiler run).
    key : str
        Cache key (hex digest).
    library : Path or None
        The shared library.
    wall_s : float
        Time spent here [s]: code generation and compilation, or loading.
    message : str
        Why the virtual machine is used (empty when compiled).
    """

    function: ca.Function
    compiled: bool
    cache_hit: bool
    key: str
    library: Path | None
    wall_s: float
    message: str = ""


def cache_dir() -> Path:
    """Directory of the compiled libraries (see the module docstring); not created here."""
    env = os.environ.get("MBSYM_CACHE_DIR")
    if env:
        return Path(env).expanduser()
    xdg = os.environ.get("XDG_CACHE_HOME")
    return (Path(xdg).expanduser() if xdg else Path.home() / ".cache") / "mbsym"


def find_compiler(compiler: str | None = None) -> str | None:
    """Absolute path of the C compiler to use, or None if there is none.

    A compiler named explicitly (argument, ``$MBSYM_CC``, ``$CC``) is used or
    nothing: it is never silently replaced by another one.
    """
    named = compiler or os.environ.get("MBSYM_CC") or os.environ.get("CC")
    if named:
        words = shlex.split(named)
        return shutil.which(words[0]) if words else None
    return shutil.which("gcc") or shutil.which("cc")


@functools.lru_cache(maxsize=8)
def _compiler_version(path: str) -> str:
    try:
        out = subprocess.run([path, "--version"], capture_output=True, text=True, timeout=30)
        return out.stdout.splitlines()[0] if out.stdout else out.stderr.strip()
    except (OSError, subprocess.SubprocessError):
        return "unknown"


def function_key(f: ca.Function, flags: Sequence[str] = DEFAULT_FLAGS, compiler: str | None = None, *,
                 jacobian: bool = False) -> str:
    """Cache key of ``f`` compiled with ``flags`` by ``compiler``: SHA-256 over all of them.

    Includes the serialized Function (its whole graph and name), the compiler's
    path and version line, the flags, whether the Jacobian is included and the
    CasADi version.
    """
    h = hashlib.sha256()
    for part in (f.serialize(), compiler or "", _compiler_version(compiler) if compiler else "",
                 "\0".join(flags), "jacobian" if jacobian else "", ca.__version__):
        h.update(part.encode())
        h.update(b"\0")
    return h.hexdigest()


def _fallback(f: ca.Function, key: str, t0: float, message: str, warn: bool) -> CompiledFunction:
    if warn:
        warnings.warn(f"{message} Using CasADi's virtual machine for {f.name()!r} (same results, slower).",
                      CompilationWarning, stacklevel=3)
    return CompiledFunction(f, False, False, key, None, time.perf_counter() - t0, message)


def compile_function(f: ca.Function, *, flags: Sequence[str] = DEFAULT_FLAGS, compiler: str | None = None,
                     directory: str | os.PathLike | None = None, jacobian: bool = False) -> CompiledFunction:
    """Compile ``f`` to C and load it, through the disk cache; fall back to ``f`` itself.

    Parameters
    ----------
    f : casadi.Function
        Any Function CasADi can generate C code for (SX Functions, MX glue of
        them, ``map``/``mapaccum``, linear solvers ``qr``/``ldl``).
    flags : sequence of str, optional, keyword-only
        Compiler flags (default ``("-O1",)``); ``-shared -fPIC`` and ``-lm`` are added.
    compiler : str, optional
        C compiler (name or path); default: see the module docstring.
    directory : path, optional
        Cache directory; default :func:`cache_dir`.
    jacobian : bool, optional
        Also compile ``f.jacobian()`` into the library (as ``jac_<name>``, where
        ``casadi.external`` finds it), so that CasADi solvers using the loaded
        Function (e.g. CVODES, IDAS) get its exact Jacobian as compiled code.

    Returns
    -------
    CompiledFunction
        ``.function`` is the Function to call.

    Warns
    -----
    CompilationWarning
        No compiler, a failed compilation or a library that does not load: the
        original Function is returned.

    Examples
    --------
    >>> import casadi as ca, tempfile
    >>> x = ca.SX.sym("x")
    >>> c = compile_function(ca.Function("square", [x], [x * x]), directory=tempfile.mkdtemp())
    >>> float(c.function(3.0))
    9.0
    """
    t0 = time.perf_counter()
    flags = tuple(str(s) for s in flags)
    cc = find_compiler(compiler)
    key = function_key(f, flags, cc, jacobian=jacobian)
    if f.class_name() == "External":
        return CompiledFunction(f, True, True, key, None, time.perf_counter() - t0)
    if os.environ.get("MBSYM_NO_COMPILE", "").strip() not in ("", "0"):
        return _fallback(f, key, t0, "MBSYM_NO_COMPILE is set.", warn=False)
    if cc is None:
        return _fallback(f, key, t0, "No C compiler found (set MBSYM_CC or CC, or install gcc).", warn=True)
    folder = Path(directory).expanduser() if directory is not None else cache_dir()
    library = folder / f"{f.name()}_{key[:20]}.so"
    hit = library.exists()
    if not hit:
        try:
            _build(f, cc, flags, library, jacobian)
        except (OSError, subprocess.SubprocessError, RuntimeError) as exc:
            return _fallback(f, key, t0, f"Compiling {f.name()!r} with {cc} failed: {_tail(exc)}", warn=True)
    try:
        g = ca.external(f.name(), str(library))
    except RuntimeError as exc:
        return _fallback(f, key, t0, f"Loading {library} failed: {_tail(exc)}", warn=True)
    return CompiledFunction(g, True, hit, key, library, time.perf_counter() - t0)


def _build(f: ca.Function, cc: str, flags: tuple[str, ...], library: Path, jacobian: bool) -> None:
    """Generate C in a private temporary directory, compile, move the library into place atomically."""
    library.parent.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix="mbsym_cg_", dir=library.parent) as tmp:
        source = Path(tmp) / f"{f.name()}.c"
        cg = ca.CodeGenerator(source.name, {"with_header": False})
        cg.add(f)
        if jacobian:
            cg.add(f.jacobian())
        cg.generate(tmp + os.sep)
        out = Path(tmp) / library.name
        cmd = [cc, *flags, "-shared", "-fPIC", "-o", str(out), str(source), "-lm"]
        proc = subprocess.run(cmd, capture_output=True, text=True, timeout=COMPILE_TIMEOUT_S)
        if proc.returncode != 0:
            raise RuntimeError(f"exit code {proc.returncode}: {proc.stderr.strip()}")
        os.replace(out, library)          # atomic: concurrent runs never see a partial library


def _tail(exc: BaseException, n: int = 300) -> str:
    text = " ".join(str(exc).split())
    return text if len(text) <= n else "..." + text[-n:]


def clear_disk_cache(directory: str | os.PathLike | None = None) -> int:
    """Delete the cached libraries (``*.so``) in ``directory`` (default :func:`cache_dir`); return how many."""
    folder = Path(directory).expanduser() if directory is not None else cache_dir()
    count = 0
    for lib in folder.glob("*.so") if folder.is_dir() else ():
        lib.unlink(missing_ok=True)
        count += 1
    return count
