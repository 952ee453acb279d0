"""Named symbols of a system: coordinates, speeds, inputs and parameters.

A :class:`SymbolTable` owns every CasADi symbol a :class:`~mbsym.System` hands
out, so that any expression a user builds can be checked for stray symbols
before a CasADi Function is made.
"""

from __future__ import annotations

import keyword
from dataclasses import dataclass
from typing import Iterable, Mapping, Sequence

import casadi as ca
import numpy as np

from .exceptions import ModelDefinitionError, ParameterError

__all__ = ["SymbolTable", "split_names", "free_symbols"]

KINDS = ("coordinate", "input", "parameter", "locked")


def split_names(names: str | Sequence[str], what: str) -> list[str]:
    """Split ``"a b, c"`` or ``["a", "b"]`` into a list of valid, unique names."""
    if isinstance(names, str):
        items = names.replace(",", " ").split()
    else:
        try:
            items = list(names)
        except TypeError as exc:
            raise ModelDefinitionError(
                f"{what} names must be a string like 'q1 q2' or a list of strings; got {names!r}."
            ) from exc
    if not items:
        raise ModelDefinitionError(f"no {what} names given; pass e.g. 'q1 q2'.")
    for n in items:
        if not isinstance(n, str) or not n.isidentifier() or keyword.iskeyword(n):
            raise ModelDefinitionError(
                f"{what} name {n!r} is not a valid identifier; use letters, digits and '_' "
                "(not starting with a digit)."
            )
    dup = sorted({n for n in items if items.count(n) > 1})
    if dup:
        raise ModelDefinitionError(f"{what} names {dup} are given more than once.")
    return items


def free_symbols(expr) -> list[ca.SX]:
    """Symbolic primitives an SX expression (or list of them) depends on."""
    if isinstance(expr, (list, tuple)):
        exprs = [ca.SX(e) for e in expr if isinstance(e, (ca.SX, ca.DM))]
        if not exprs:
            return []
        expr = ca.vertcat(*[ca.vec(e) for e in exprs])
    if not isinstance(expr, ca.SX):
        return []
    return ca.symvar(expr)


@dataclass(frozen=True)
class _Entry:
    name: str
    kind: str
    sym: ca.SX
    default: float | None = None


class SymbolTable:
    """Registry of named scalar symbols of one system."""

    def __init__(self) -> None:
        self._entries: dict[str, _Entry] = {}
        self._order: dict[str, list[str]] = {k: [] for k in KINDS}
        self._speed: dict[str, ca.SX] = {}
        self._accel: dict[str, ca.SX] = {}
        self._by_sym: dict[int, _Entry] = {}
        self._prescribed: dict[str, tuple[ca.SX, ca.SX, ca.SX]] = {}
        self._locked: dict[str, tuple[ca.SX, ca.SX, ca.SX]] = {}

    # -- creation -------------------------------------------------------
    def declare(self, names: Iterable[str], kind: str, defaults: Mapping[str, float] | None = None) -> list[ca.SX]:
        """Declare new symbols (all or nothing) and return them."""
        names = list(names)
        taken = [n for n in names if n in self._entries or n in self._derived_names()]
        if taken:
            raise ModelDefinitionError(
                f"{kind} names {taken} are already used in this system; choose different names."
            )
        if kind == "coordinate":
            # each coordinate also names its speed '<q>_d' and acceleration '<q>_dd'
            derived = {f"{n}{suffix}": n for n in names for suffix in ("_d", "_dd")}
            clash = sorted(d for d in derived if d in self._entries or d in names)
            if clash:
                raise ModelDefinitionError(
                    f"coordinates {sorted({derived[d] for d in clash})} would create speed/acceleration "
                    f"names {clash}, which are already used; rename the coordinate or the other symbol."
                )
        defaults = dict(defaults or {})
        unknown = sorted(set(defaults) - set(names))
        if unknown:
            raise ParameterError(f"default values given for {unknown}, which are not among the names {names}.")
        checked = {n: check_finite_number(v, f"default value of {n!r}") for n, v in defaults.items()}
        out = []
        for n in names:
            entry = _Entry(n, kind, ca.SX.sym(n), checked.get(n))
            self._entries[n] = entry
            self._order[kind].append(n)
            self._by_sym[_key(entry.sym)] = entry
            out.append(entry.sym)
            if kind == "coordinate":
                self._speed[n] = ca.SX.sym(f"{n}_d")
                self._accel[n] = ca.SX.sym(f"{n}_dd")
        return out

    def _derived_names(self) -> set[str]:
        return {f"{n}_d" for n in self._speed} | {f"{n}_dd" for n in self._speed}

    def declare_prescribed(self, names: Iterable[str]) -> list[ca.SX]:
        """Declare prescribed coordinates: inputs ``n``, ``n_d``, ``n_dd`` (value, speed, acceleration)."""
        names = list(names)
        triples = [(n, f"{n}_d", f"{n}_dd") for n in names]
        flat = [x for t in triples for x in t]
        self.declare(flat, "input")         # all-or-nothing name checks happen here
        out = []
        for n, nd, ndd in triples:
            syms = tuple(self._entries[k].sym for k in (n, nd, ndd))
            self._prescribed[n] = syms
            out.append(syms[0])
        return out

    def declare_locked(self, names: Iterable[str]) -> list[ca.SX]:
        """Declare locked coordinates: held at zero, their reaction generalized forces reported."""
        out = self.declare(names, "locked")
        for sym in out:
            n = sym.name()
            self._locked[n] = (sym, ca.SX.sym(f"{n}_d"), ca.SX.sym(f"{n}_dd"))
        return out

    def locked(self) -> dict[str, tuple[ca.SX, ca.SX, ca.SX]]:
        """Locked coordinates by name: (value, speed, acceleration) symbols, all zero in the equations."""
        return dict(self._locked)

    def prescribed(self) -> dict[str, tuple[ca.SX, ca.SX, ca.SX]]:
        """Prescribed coordinates by name: (value, speed, acceleration) input symbols."""
        return dict(self._prescribed)

    def is_prescribed(self, sym) -> bool:
        entry = self.lookup(sym)
        return entry is not None and entry.name in self._prescribed

    # -- queries --------------------------------------------------------
    def names(self, kind: str) -> list[str]:
        return list(self._order[kind])

    def symbols(self, kind: str) -> list[ca.SX]:
        return [self._entries[n].sym for n in self._order[kind]]

    def speeds(self) -> list[ca.SX]:
        return [self._speed[n] for n in self._order["coordinate"]]

    def accelerations(self) -> list[ca.SX]:
        return [self._accel[n] for n in self._order["coordinate"]]

    def defaults(self) -> dict[str, float]:
        return {n: self._entries[n].default for n in self._order["parameter"] if self._entries[n].default is not None}

    def lookup(self, sym) -> _Entry | None:
        """Entry of a declared symbol (coordinate, input or parameter), else None."""
        if not isinstance(sym, ca.SX) or sym.numel() != 1 or not sym.is_symbolic():
            return None
        return self._by_sym.get(_key(sym))

    def speed_of(self, coordinate) -> ca.SX:
        entry = self.lookup(coordinate)
        if entry is not None and entry.name in self._prescribed:
            return self._prescribed[entry.name][1]
        if entry is not None and entry.kind == "locked":
            return self._locked[entry.name][1]
        if entry is None or entry.kind != "coordinate":
            raise ModelDefinitionError(
                f"{coordinate!r} is not a coordinate of this system; declare it with sys.coordinates(...)."
            )
        return self._speed[entry.name]

    def allowed(self, *, speeds: bool = True, inputs: bool = True) -> set[int]:
        """Keys of the symbols an expression may contain."""
        keys = {_key(self._entries[n].sym) for n in self._order["coordinate"] + self._order["parameter"]}
        if speeds:
            keys |= {_key(s) for s in self._speed.values()}
        if inputs:
            keys |= {_key(self._entries[n].sym) for n in self._order["input"]}
        return keys

    def check_expression(self, expr, what: str, *, speeds: bool = True, inputs: bool = True,
                         coordinates: bool = True) -> None:
        """Raise if ``expr`` contains symbols this system did not declare, or of a kind not allowed."""
        allowed = self.allowed(speeds=speeds, inputs=inputs)
        syms = free_symbols(expr)
        stray = [s.name() for s in syms if _key(s) not in allowed]
        if stray:
            kinds = "coordinates, speeds, inputs or parameters" if speeds and inputs else "coordinates or parameters"
            raise ModelDefinitionError(
                f"{what} contains symbols {sorted(set(stray))} that are not {kinds} of this system. "
                "Declare them with sys.parameters(...), sys.inputs(...) or sys.coordinates(...), "
                "or use the symbols those calls return."
            )
        if not coordinates:
            moving = sorted({s.name() for s in syms if (e := self.lookup(s)) is not None and e.kind == "coordinate"})
            if moving:
                raise ModelDefinitionError(
                    f"{what} depends on coordinates {moving}, but it must be constant (numbers or "
                    "parameters only). Model the motion with a joint instead."
                )


def _key(sym: ca.SX) -> int:
    """Identity of a symbolic primitive (stable across SX copies)."""
    return sym.element_hash()


def check_finite_number(value, what: str) -> float:
    """Return ``value`` as a float, raising ParameterError if not a finite real number."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, float, np.integer, np.floating)):
        arr = np.asarray(value) if isinstance(value, np.ndarray) else None
        if arr is None or arr.size != 1 or arr.dtype.kind not in "iuf":
            raise ParameterError(f"{what} is {value!r} ({type(value).__name__}); expected a real number.")
        value = arr.item()
    v = float(value)
    if not np.isfinite(v):
        raise ParameterError(f"{what} is {v}; expected a finite number.")
    return v
