"""Lazy public names of a package (PEP 562): ``import mbsym`` stays cheap.

A package lists the public names that live in heavy modules (scipy, python-control,
matplotlib behind them) with the modules that define them; the first access imports
the module and caches the attribute in the package. Measure with
``python -X importtime -c "import mbsym"`` (``benchmarks/startup.py`` compares it with
``import casadi, numpy``).
"""

from __future__ import annotations

import importlib
from typing import Callable, Mapping, Sequence

__all__ = ["lazy_attributes", "installed_version"]


def lazy_attributes(package: str, table: Mapping[str, Sequence[str]],
                    namespace: dict) -> tuple[Callable[[str], object], Callable[[], list[str]]]:
    """``(__getattr__, __dir__)`` for ``package`` resolving the names of ``table`` on first use.

    Parameters
    ----------
    package : str
        The package's ``__name__``.
    table : mapping name -> sequence of module names (relative to ``package``, without the dot)
        Where each lazy name lives; the first module that defines it wins (so a name keeps
        working when a module moves, e.g. into a sub-package). The special entry
        ``"__version__"`` maps to ``("__version__",)`` and reads the installed version.
    namespace : dict
        The package's ``globals()``: resolved names are stored there (later accesses are plain
        attribute lookups).

    Returns
    -------
    (__getattr__, __dir__)
        Module-level hooks to assign in the package.
    """

    def __getattr__(name: str):
        if name == "__version__" and name in table:
            value = installed_version(package.split(".")[0])
        elif name in table:
            value = None
            for module in table[name]:
                mod = importlib.import_module(f"{package}.{module}")
                if hasattr(mod, name):
                    value = getattr(mod, name)
                    break
            else:
                raise AttributeError(f"module {package!r} has no attribute {name!r} (looked in {list(table[name])})")
        else:
            try:                                   # a sub-module accessed as an attribute: mbsym.linear
                value = importlib.import_module(f"{package}.{name}")
            except ModuleNotFoundError as exc:
                if exc.name != f"{package}.{name}":
                    raise
                raise AttributeError(f"module {package!r} has no attribute {name!r}") from None
        namespace[name] = value
        return value

    def __dir__() -> list[str]:
        return sorted(set(namespace) | set(table))

    return __getattr__, __dir__


def installed_version(distribution: str) -> str:
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version(distribution)
    except PackageNotFoundError:  # pragma: no cover - running from a source tree
        return "0.0.0+unknown"
