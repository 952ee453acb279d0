"""Compiled evaluation of CasADi Functions: generated C, the system compiler, a disk cache.

:func:`compile_function` turns a CasADi ``Function`` into a shared library
(CasADi's ``CodeGenerator``, then the system C compiler, ``-O1`` by default) and
loads it back with ``casadi.external``. Libraries are cached on disk under a key
derived from the serialized Function, the compiler command (every word, the
first resolved to its path, and its version line), the flags, the CasADi
version and the platform (``platform.machine()``, ``sys.platform``), so a second
preparation of the same Function, in this process or a later one, skips the
compiler. A cached library that exists but does not load (truncated, built for
another ABI) is deleted and rebuilt once. Without a working compiler the
original Function is returned (CasADi's virtual machine) with a
:class:`CompilationWarning`; results are the same, only slower.

Cache directory: ``$MBSYM_CACHE_DIR``, else ``$XDG_CACHE_HOME/mbsym``, else
``~/.cache/mbsym``; bounded in size (``$MBSYM_CACHE_MAX_MB``, default 2000 MB: the least recently
used libraries are deleted after a build, :mod:`mbsym.codegen_cache`). Compiler: ``compiler=``,
else ``$MBSYM_CC``, else ``$CC``, else ``gcc`` or ``cc`` on the ``PATH``; a command of several words (``"ccache
gcc"``, ``"gcc -march=native"``) is used whole. ``MBSYM_NO_COMPILE=1`` turns
compilation off (fallback without a warning, checked before any other work).

Functions defined in hand-written or generated C (CasADi Externals, e.g. a wind field) can be
called from SX/MX graphs; when :func:`compile_function` generates C for such a graph, CasADi declares
``int <name>(const casadi_real** arg, casadi_real** res, casadi_int* iw, casadi_real* w, int mem);``
and calls it. :func:`register_c_source` tells this module where that definition lives: the source is
compiled into the same library and its content is part of the cache key.

Measured on the CI machine kind (paper45 turbine, 3 DOFs): the RK4 step of
~6000 SX instructions compiles in ~0.8 s at ``-O1`` and runs 600 steps in
1.6 ms instead of ~30 ms in the virtual machine.
"""

from __future__ import annotations

import contextlib
import functools
import os
import shlex
import sys
import threading
import time
import warnings
import weakref
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Iterator, Sequence

import casadi as ca

# hashlib, platform, shutil, subprocess and tempfile are imported where used: `import mbsym` stays light

__all__ = [
    "CompilationWarning",
    "CompiledFunction",
    "DEFAULT_FLAGS",
    "cache_dir",
    "find_compiler",
    "compiler_command",
    "function_key",
    "compile_function",
    "clear_disk_cache",
    "cached_library",
    "compile_disabled",
    "compile_in_background",
    "wait_for_background",
    "estimate_compile_seconds",
    "set_identity",
    "register_c_source",
    "registered_c_sources",
]

#: Compiler flags: -O1 compiles large straight-line SX code fast and runs it nearly as fast as -O2/-O3.
#: -fno-math-errno lets the compiler emit sqrt (and keep other math calls) without the errno bookkeeping the
#: generated code never reads: results are bit-identical, the blade-element aerodynamics of the ff14_flex deck
#: (64 600 SX instructions, 736 sqrt) run ~20 % faster, compile time unchanged (benchmarks/README.md,
#: "blade-loop-speed").
DEFAULT_FLAGS: tuple[str, ...] = ("-O1", "-fno-math-errno")
#: Seconds after which a compilation is abandoned (then: the virtual machine, with a warning).
COMPILE_TIMEOUT_S = 600.0
_TEMP_PREFIX = "mbsym_cg_"


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
        Cache key (hex digest); empty when nothing was compiled or loaded.
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


def compiler_command(compiler: str | None = None) -> tuple[str, ...] | None:
    """The C compiler command to use, as words with the first resolved to an absolute path; None if absent.

    A compiler named explicitly (argument, ``$MBSYM_CC``, ``$CC``) is used or
    nothing: it is never silently replaced by another one. Every word is kept
    (``"ccache gcc"`` runs ``ccache gcc ...``).

    Examples
    --------
    >>> cmd = compiler_command("env cc -DEXAMPLE")
    >>> cmd is None or cmd[1:] == ("cc", "-DEXAMPLE")
    True
    """
    named = compiler or os.environ.get("MBSYM_CC") or os.environ.get("CC")
    return _resolve_compiler(named or "", os.environ.get("PATH", ""))


@functools.lru_cache(maxsize=16)
def _resolve_compiler(named: str, path_env: str) -> tuple[str, ...] | None:
    """:func:`compiler_command` for a named compiler ("" = default) and a PATH (cached: ~1 ms of stat calls)."""
    import shutil

    if named:
        words = shlex.split(named)
        path = shutil.which(words[0], path=path_env) if words else None
        return (path, *words[1:]) if path else None
    path = shutil.which("gcc", path=path_env) or shutil.which("cc", path=path_env)
    return (path,) if path else None


def find_compiler(compiler: str | None = None) -> str | None:
    """Absolute path of the first word of :func:`compiler_command` (the program run), or None."""
    cmd = compiler_command(compiler)
    return cmd[0] if cmd else None


@functools.lru_cache(maxsize=8)
def _compiler_version(command: tuple[str, ...]) -> str:
    """First line of ``<compiler> --version``. For a plain compiler path (one word) it is remembered on disk
    (``compilers.json`` in the cache directory) under the executable's path, size and modification time, so
    that a new process does not run the compiler (~10 ms) just to look a library up."""
    import subprocess

    stamp = _executable_stamp(command)
    known = _read_versions() if stamp else {}
    if stamp and stamp in known:
        return known[stamp]
    try:
        out = subprocess.run([*command, "--version"], capture_output=True, text=True, timeout=30)
        version = out.stdout.splitlines()[0] if out.stdout else out.stderr.strip()
    except (OSError, subprocess.SubprocessError):
        return "unknown"
    if stamp:
        _write_version(stamp, version)
    return version


def _executable_stamp(command: tuple[str, ...]) -> str:
    """``path|size|mtime_ns`` of a one-word compiler command ("" for wrappers such as ``env cc`` or ``ccache``)."""
    if len(command) != 1 or Path(command[0]).name in ("env", "ccache", "sccache", "distcc"):
        return ""
    try:
        st = os.stat(command[0])
    except OSError:
        return ""
    return f"{command[0]}|{st.st_size}|{st.st_mtime_ns}"


def _read_versions() -> dict:
    import json

    try:
        data = json.loads((cache_dir() / "compilers.json").read_text())
        return data if isinstance(data, dict) else {}
    except (OSError, ValueError):
        return {}


def _write_version(stamp: str, version: str) -> None:
    import json
    import tempfile

    folder = cache_dir()
    try:
        folder.mkdir(parents=True, exist_ok=True)
        data = {**_read_versions(), stamp: version}
        fd, tmp = tempfile.mkstemp(dir=folder, prefix=".compilers", suffix=".json")
        with os.fdopen(fd, "w") as fh:
            json.dump(data, fh)
        os.replace(tmp, folder / "compilers.json")          # atomic: concurrent writers never corrupt it
    except OSError:
        pass


def function_key(f: ca.Function, flags: Sequence[str] = DEFAULT_FLAGS, compiler: str | Sequence[str] | None = None,
                 *, jacobian: bool = False) -> str:
    """Cache key of ``f`` compiled with ``flags`` by ``compiler``: SHA-256 over all of them.

    ``compiler`` is a command (a string split like a shell does, or words).
    Includes the serialized Function (its whole graph and name), every word of
    the compiler command and its version line, the flags, whether the Jacobian
    is included, the CasADi version and the platform (machine, OS), and the registered C sources
    (:func:`register_c_source`) of the Functions ``f`` calls.
    """
    import hashlib
    import platform

    words = tuple(shlex.split(compiler) if isinstance(compiler, str) else (compiler or ()))
    h = hashlib.sha256()
    identity = _IDENTITY.get(f)
    for part in (f.serialize() if identity is None else identity, "\0".join(words), _compiler_version(words) if words else "",
                 "\0".join(flags), "jacobian" if jacobian else "", ca.__version__, platform.machine(), sys.platform,
                 _sources_part(f)):
        h.update(part.encode())
        h.update(b"\0")
    return h.hexdigest()


_C_SOURCES: dict[str, Path] = {}
_C_SOURCES_LOCK = threading.Lock()


def register_c_source(function_name: str, source_path: str | os.PathLike) -> None:
    """Declare that the C function ``function_name`` (CasADi's external-function API) is defined in ``source_path``.

    When :func:`compile_function` compiles a Function whose graph calls a Function of that name
    (an ``External`` loaded with ``casadi.external``), the generated C declares and calls it; the
    registered source is then compiled into the same library, and its content takes part in the cache
    key. Registering a name again replaces its source.

    Raises
    ------
    ValueError
        The name is not a C identifier or the file does not exist.

    Examples
    --------
    >>> register_c_source("my_external", "my_external.c")  # doctest: +SKIP
    """
    import re

    if not isinstance(function_name, str) or not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", function_name):
        raise ValueError(f"function_name must be a C identifier; got {function_name!r}.")
    path = Path(source_path)
    if not path.is_file():
        raise ValueError(f"C source for {function_name!r} not found: tried '{path.absolute()}'.")
    with _C_SOURCES_LOCK:
        _C_SOURCES[function_name] = path.absolute()


def registered_c_sources(f: ca.Function) -> list[tuple[str, Path]]:
    """The registered C sources (name, path) of the Functions ``f``'s graph calls, sorted by name."""
    with _C_SOURCES_LOCK:
        known = dict(_C_SOURCES)
    if not known:
        return []
    names = {g.name() for g in f.find_functions()}
    return sorted((n, known[n]) for n in names if n in known)


def _sources_part(f: ca.Function) -> str:
    """Cache-key text of the registered sources ``f`` uses: names and SHA-256 of their contents."""
    import hashlib

    parts = []
    for name, path in registered_c_sources(f):
        try:
            digest = hashlib.sha256(path.read_bytes()).hexdigest()
        except OSError:
            digest = "missing"
        parts.append(f"{name}={digest}")
    return "\0".join(parts)


def _library_path(f: ca.Function, key: str, directory: str | os.PathLike | None) -> Path:
    folder = Path(directory).expanduser() if directory is not None else cache_dir()
    return folder / f"{f.name()}_{key[:20]}.so"


def compile_disabled() -> bool:
    """Whether ``MBSYM_NO_COMPILE`` turns compilation off."""
    return os.environ.get("MBSYM_NO_COMPILE", "").strip() not in ("", "0")


def cached_library(f: ca.Function, *, flags: Sequence[str] = DEFAULT_FLAGS, compiler: str | None = None,
                   directory: str | os.PathLike | None = None, jacobian: bool = False) -> Path | None:
    """The library :func:`compile_function` would load for ``f`` from the disk cache, or None (nothing compiled).

    Costs the cache key (serializing ``f``: ~4 ms for the MX RK4 step of paper45); None as well when
    compilation is off (``MBSYM_NO_COMPILE``) or no compiler is found.
    """
    if os.environ.get("MBSYM_NO_COMPILE", "").strip() not in ("", "0"):
        return None
    cc = compiler_command(compiler)
    if cc is None:
        return None
    library = _library_path(f, _memo_key(f, tuple(str(x) for x in flags), cc, jacobian), directory)
    return library if library.exists() else None


_KEYS: "weakref.WeakKeyDictionary[ca.Function, dict]" = weakref.WeakKeyDictionary()
_IDENTITY: "weakref.WeakKeyDictionary[ca.Function, str]" = weakref.WeakKeyDictionary()


def set_identity(f: ca.Function, identity: str) -> ca.Function:
    """Key ``f``'s library by ``identity`` instead of its serialization; returns ``f``.

    For Functions built deterministically from a smaller one (mbsym's mapped output blocks: the map
    wrapper serializes to 3x the size of the output Function it maps). ``identity`` must determine
    ``f`` completely: the construction (with a version tag) and the serialization of what it wraps.
    """
    _IDENTITY[f] = str(identity)
    return f


def _memo_key(f: ca.Function, flags: tuple[str, ...], cc: tuple[str, ...], jacobian: bool) -> str:
    """:func:`function_key`, remembered per Function object (serializing a large Function takes milliseconds)."""
    memo = _KEYS.setdefault(f, {})
    k = (flags, cc, jacobian)
    if k not in memo:
        memo[k] = function_key(f, flags, cc, jacobian=jacobian)
    return memo[k]


#: Calibration of :func:`estimate_compile_seconds` on the CI machine kind (gcc -O1): a fixed cost [s] and
#: seconds per byte of the serialized Function (a proxy of the generated C). Measured on the paper45 RK4 step
#: (MX, 143 kB serialized): 0.5-0.8 s unloaded (benchmarks/work_precision.py, "compilation" lines).
COMPILE_FIXED_S, COMPILE_S_PER_BYTE = 0.1, 4e-6


def estimate_compile_seconds(f: ca.Function) -> float:
    """Rough wall time [s] to generate and compile ``f`` (see :data:`COMPILE_S_PER_BYTE`)."""
    return COMPILE_FIXED_S + COMPILE_S_PER_BYTE * len(f.serialize())


_BACKGROUND: dict[str, threading.Thread] = {}
_BACKGROUND_LOCK = threading.Lock()


def compile_in_background(f: ca.Function, *, flags: Sequence[str] = DEFAULT_FLAGS, compiler: str | None = None,
                          directory: str | os.PathLike | None = None, jacobian: bool = False) -> bool:
    """Compile ``f`` into the disk cache in a background thread (no result: later calls find the library).

    Used by the accuracy-driven default of :func:`mbsym.simulate` when compiling does not pay off within
    the call but would over later ones. The thread is not a daemon: the interpreter waits for it at exit
    (at most :data:`COMPILE_TIMEOUT_S`), so that the library lands in the cache (a daemon thread would
    lose its temporary build directory to the interpreter's exit clean-up). Returns whether a
    compilation was started (not when compilation is off, no compiler exists, or one for ``f`` is
    already running). Failures are silent (the next call compiles again, or uses the virtual machine).
    """
    if os.environ.get("MBSYM_NO_COMPILE", "").strip() not in ("", "0") or compiler_command(compiler) is None:
        return False
    key = f"{f.name()}:{id(f)}"
    with _BACKGROUND_LOCK:
        running = _BACKGROUND.get(key)
        if running is not None and running.is_alive():
            return False

        def work():
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", CompilationWarning)
                try:
                    compile_function(f, flags=flags, compiler=compiler, directory=directory, jacobian=jacobian)
                except Exception:  # noqa: BLE001 - a background warm-up must never disturb the caller
                    pass

        thread = threading.Thread(target=work, name=f"mbsym-compile-{f.name()}", daemon=False)
        _BACKGROUND[key] = thread
        thread.start()
    return True


def wait_for_background(timeout: float | None = COMPILE_TIMEOUT_S) -> None:
    """Wait for the background compilations started by :func:`compile_in_background` (e.g. in benchmarks)."""
    deadline = None if timeout is None else time.monotonic() + timeout
    for thread in list(_BACKGROUND.values()):
        thread.join(None if deadline is None else max(deadline - time.monotonic(), 0.0))


def _fallback(f: ca.Function, key: str, t0: float, message: str, warn: bool) -> CompiledFunction:
    if warn:
        warnings.warn(f"{message} Using CasADi's virtual machine for {f.name()!r} (same results, slower).",
                      CompilationWarning, stacklevel=3)
    return CompiledFunction(f, False, False, key, None, time.perf_counter() - t0, message)


#: Compilations estimated to take longer than this [s] are announced to :func:`announcing`'s callback.
ANNOUNCE_FROM_S = 20.0
_ANNOUNCE: list = []


@contextlib.contextmanager
def announcing(say: Callable[[str], None]) -> Iterator[None]:
    """Within the block, say ``compiling <name> to C (~N s estimated, once: cached on disk)`` through ``say`` before
    a compilation estimated (:func:`estimate_compile_seconds`) to take more than :data:`ANNOUNCE_FROM_S` (a
    command line's way to explain a long silence; libraries found in the cache are not announced)."""
    _ANNOUNCE.append(say)
    try:
        yield
    finally:
        _ANNOUNCE.remove(say)


def _announce(f: ca.Function) -> None:
    if not _ANNOUNCE:
        return
    seconds = estimate_compile_seconds(f)
    if seconds > ANNOUNCE_FROM_S:
        _ANNOUNCE[-1](f"compiling {f.name()} to C (~{seconds:.0f} s estimated, once: cached on disk)")


def compile_function(f: ca.Function, *, flags: Sequence[str] = DEFAULT_FLAGS, compiler: str | None = None,
                     directory: str | os.PathLike | None = None, jacobian: bool = False) -> CompiledFunction:
    """Compile ``f`` to C and load it, through the disk cache; fall back to ``f`` itself.

    Parameters
    ----------
    f : casadi.Function
        Any Function CasADi can generate C code for (SX Functions, MX glue of
        them, ``map``/``mapaccum``, linear solvers ``qr``/``ldl``).
    flags : sequence of str, optional, keyword-only
        Compiler flags (default :data:`DEFAULT_FLAGS`, ``("-O1", "-fno-math-errno")``); ``-shared -fPIC`` and
        ``-lm`` are added.
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
    if f.class_name() == "External":
        return CompiledFunction(f, True, True, "", None, time.perf_counter() - t0)
    if os.environ.get("MBSYM_NO_COMPILE", "").strip() not in ("", "0"):     # before serializing f (costly)
        return _fallback(f, "", t0, "MBSYM_NO_COMPILE is set.", warn=False)
    cc = compiler_command(compiler)
    if cc is None:
        return _fallback(f, "", t0, "No C compiler found (set MBSYM_CC or CC, or install gcc).", warn=True)
    flags = tuple(str(s) for s in flags)
    key = _memo_key(f, flags, cc, jacobian)
    library = _library_path(f, key, directory)
    from . import codegen_cache

    bound = codegen_cache.limit_bytes()               # a bad $MBSYM_CACHE_MAX_MB is refused before any work
    if library.exists():
        try:
            loaded = CompiledFunction(ca.external(f.name(), str(library)), True, True, key, library,
                                      time.perf_counter() - t0)
            codegen_cache.mark_used(library)
            return loaded
        except RuntimeError:
            library.unlink(missing_ok=True)        # exists but does not load (truncated, other ABI): rebuild once
    import subprocess

    _announce(f)
    try:
        _build(f, cc, flags, library, jacobian)
    except (OSError, subprocess.SubprocessError, RuntimeError) as exc:
        return _fallback(f, key, t0, f"Compiling {f.name()!r} with {shlex.join(cc)} failed: {_tail(exc)}", warn=True)
    codegen_cache.prune(library.parent, keep=library, limit=bound, stale_after=2.0 * COMPILE_TIMEOUT_S,
                        temp_prefix=_TEMP_PREFIX)
    try:
        g = ca.external(f.name(), str(library))
    except RuntimeError as exc:
        return _fallback(f, key, t0, f"Loading {library} failed: {_tail(exc)}", warn=True)
    return CompiledFunction(g, True, False, key, library, time.perf_counter() - t0)


def _build(f: ca.Function, cc: tuple[str, ...], flags: tuple[str, ...], library: Path, jacobian: bool) -> None:
    """Generate C in a private temporary directory, compile, move the library into place atomically."""
    import tempfile

    library.parent.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix=_TEMP_PREFIX, dir=library.parent) as tmp:
        source = Path(tmp) / f"{f.name()}.c"
        cg = ca.CodeGenerator(source.name, {"with_header": False})
        cg.add(f)
        if jacobian:
            cg.add(f.jacobian())
        cg.generate(tmp + os.sep)
        out = Path(tmp) / library.name
        extra = [str(path) for _, path in registered_c_sources(f)]
        cmd = [*cc, *flags, "-shared", "-fPIC", "-o", str(out), str(source), *extra, "-lm"]
        returncode, stderr = _run_compiler(cmd, COMPILE_TIMEOUT_S)
        if returncode != 0:
            raise RuntimeError(f"exit code {returncode}: {stderr.strip()}")
        os.replace(out, library)          # atomic: concurrent runs never see a partial library


def _run_compiler(cmd: list[str], timeout: float) -> tuple[int, str]:
    """Run the compiler in a process group of its own; on ``timeout`` [s] kill the whole group.

    ``subprocess.run(timeout=...)`` kills the driver (``gcc``) only: its compiler proper (``cc1``) went on, once
    at 14.5 GB and a full core after the 600 s limit on a 1385-state model. Raises ``subprocess.TimeoutExpired``
    as ``subprocess.run`` does.
    """
    import signal
    import subprocess

    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            start_new_session=os.name == "posix")
    try:
        _, stderr = proc.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        if os.name == "posix":
            with contextlib.suppress(ProcessLookupError):
                os.killpg(proc.pid, signal.SIGKILL)
        else:  # pragma: no cover - no process groups
            proc.kill()
        proc.communicate()
        raise
    return proc.returncode, stderr


def _tail(exc: BaseException, n: int = 300) -> str:
    text = " ".join(str(exc).split())
    return text if len(text) <= n else "..." + text[-n:]


def clear_disk_cache(directory: str | os.PathLike | None = None) -> int:
    """Delete the cached libraries (``*.so``) in ``directory`` (default :func:`cache_dir`); return how many.

    Also deletes the stale build directories (``mbsym_cg_*``, left by an interrupted
    compilation): those older than :data:`COMPILE_TIMEOUT_S`, so that a build running
    in another process is left alone.
    """
    from .codegen_cache import remove_stale_builds

    folder = Path(directory).expanduser() if directory is not None else cache_dir()
    if not folder.is_dir():
        return 0
    count = 0
    for lib in folder.glob("*.so"):
        lib.unlink(missing_ok=True)
        count += 1
    remove_stale_builds(folder, COMPILE_TIMEOUT_S, _TEMP_PREFIX)
    return count
