"""The size bound of the compiled-library disk cache: the least recently used libraries go first.

:func:`mbsym.codegen.compile_function` keeps every library it builds in the cache directory
(:func:`mbsym.codegen.cache_dir`), so that later runs skip the compiler. Without a bound the directory
only grows: every changed model, tuning or parameter set leaves a library behind (a development
machine here held 1.5 GB of them, 505 files, after a few days; one blade-element loop is 10-30 MB).
After each build :func:`prune` deletes the least recently used libraries until the cache holds at most
:func:`limit_bytes` (the library just built is always kept), and the build directories an interrupted
compilation left behind (a killed process cannot remove its own; one held a 343 MB C file).

A library counts as used when it is built or loaded from the cache (:func:`mark_used` sets its
modification time). Deleting a library another process has loaded is safe on POSIX systems (the
mapping stays valid); a later run that needs it compiles it again.

The bound: ``$MBSYM_CACHE_MAX_MB`` (megabytes, 10**6 bytes; ``inf`` for none), else
:data:`DEFAULT_LIMIT_MB`. Only the cache's own libraries (``*.so``, ``*.dylib``, ``*.dll`` at its top level)
and its stale build directories are touched; other files and subdirectories (e.g. the full-field wind
data under ``fullfield/``) are left alone.
"""

from __future__ import annotations

import math
import os
import time
from pathlib import Path

from .exceptions import OptionError

__all__ = ["DEFAULT_LIMIT_MB", "LIBRARY_SUFFIXES", "limit_bytes", "mark_used", "prune", "remove_stale_builds",
           "usage"]

#: Default bound of the cache [MB]: room for about a hundred blade-element loops.
DEFAULT_LIMIT_MB = 2000.0
#: File name endings of the cache's libraries.
LIBRARY_SUFFIXES = (".so", ".dylib", ".dll")
#: Pruning goes down to this fraction of the bound, so that the next builds do not prune again at once.
_LOW_WATER = 0.9


def limit_bytes() -> float:
    """The cache's bound [bytes] from ``$MBSYM_CACHE_MAX_MB`` (``math.inf``: no bound).

    Raises
    ------
    OptionError
        The variable is set to something other than a positive number of megabytes or ``inf``.
    """
    text = os.environ.get("MBSYM_CACHE_MAX_MB", "").strip()
    if not text:
        return DEFAULT_LIMIT_MB * 1e6
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not value > 0:
        raise OptionError(f"MBSYM_CACHE_MAX_MB={text!r}: expected the compiled-library cache's bound as a positive "
                          f"number of megabytes (e.g. 500) or 'inf' for none; unset it for the default "
                          f"{DEFAULT_LIMIT_MB:g} MB.")
    return value * 1e6


def mark_used(library: Path) -> None:
    """Record that ``library`` was used now (its modification time), so that pruning keeps it longest."""
    try:
        os.utime(library, None)
    except OSError:           # read-only cache, or removed meanwhile: nothing to record
        pass


def usage(directory: Path) -> list[tuple[float, int, Path]]:
    """``(last use [s since the epoch], size [bytes], path)`` of every library in ``directory``, oldest first."""
    out = []
    for entry in _entries(directory):
        if entry.is_file() and entry.name.endswith(LIBRARY_SUFFIXES):
            try:
                st = entry.stat()
            except OSError:   # removed meanwhile
                continue
            out.append((st.st_mtime, st.st_size, Path(entry.path)))
    return sorted(out)


def prune(directory: Path, *, keep: Path | None = None, limit: float | None = None,
          stale_after: float = 600.0, temp_prefix: str = "mbsym_cg_") -> list[Path]:
    """Delete the least recently used libraries of ``directory`` while it holds more than ``limit`` bytes.

    Parameters
    ----------
    directory : Path
        The cache directory.
    keep : Path, optional, keyword-only
        A library never deleted (the one just built).
    limit : float, optional, keyword-only
        Bound [bytes]; default :func:`limit_bytes`. Above it, libraries go oldest first until the
        cache holds 90 % of it.
    stale_after : float, optional, keyword-only
        Build directories (``temp_prefix*``) older than this [s] are deleted: their compilation was
        interrupted (a running one is younger than the compiler's timeout).
    temp_prefix : str, optional, keyword-only
        Name prefix of the build directories.

    Returns
    -------
    list of Path
        The libraries deleted.
    """
    remove_stale_builds(directory, stale_after, temp_prefix)
    bound = limit_bytes() if limit is None else float(limit)
    libraries = usage(directory)
    total = sum(size for _, size, _ in libraries)
    if total <= bound:
        return []
    target, removed = _LOW_WATER * bound, []
    for _, size, path in libraries:
        if total <= target:
            break
        if keep is not None and path == keep:
            continue
        try:
            path.unlink()
        except FileNotFoundError:       # pruned by another process meanwhile
            pass
        except OSError:
            continue
        total -= size
        removed.append(path)
    return removed


def _entries(directory: Path) -> list[os.DirEntry]:
    try:
        with os.scandir(directory) as it:
            return list(it)
    except OSError:
        return []


def remove_stale_builds(directory: Path, stale_after: float, temp_prefix: str = "mbsym_cg_") -> None:
    """Delete the build directories ``temp_prefix*`` of ``directory`` older than ``stale_after`` [s]."""
    import shutil

    now = time.time()
    for entry in _entries(directory):
        if not entry.name.startswith(temp_prefix):
            continue
        try:
            stale = entry.is_dir() and now - entry.stat().st_mtime > stale_after
        except OSError:
            continue
        if stale:
            shutil.rmtree(entry.path, ignore_errors=True)
