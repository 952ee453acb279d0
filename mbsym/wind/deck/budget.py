"""The memory a deck implies, estimated from its sizes before anything large is read or built.

:func:`deck_memory_estimate` reads only the keys that size something (node and station counts,
table row counts, the TurbSim ``.bts`` header, file sizes, the run's ``TMax``/``DT_Out``) from the
``.fst`` and the files it names, and prices each with a constant measured on this code (below);
:func:`check_deck_memory` refuses a deck whose estimate is above
:func:`mbsym.simulate.monitor.memory_limit` (2 GiB, or ``$MBSYM_MEMORY_LIMIT`` bytes) with a
:class:`~mbsym.exceptions.DeckMemoryError` naming the file, line and key of the largest items.
:func:`~mbsym.wind.deck.openfast.read_openfast` calls it once the ``.fst`` and ElastoDyn keys are
read, before the tower, blade and module files are parsed, so every reader of a whole deck
(``operating_deck``, ``RotorAero.from_openfast``, the CLI) is covered; it leaves out the result of
the deck's own run (``run=False``: a run may be shorter, and checks its own result).

The estimate is tolerant: a file or key it cannot find or read costs nothing here (the readers
report it, with file/line/key). A file too large to be parsed within the limit is priced from its
size alone, without being read. What is priced (constants measured on the shared decks, peak
resident size ``VmHWM`` of a fresh process minus its size after ``import mbsym``, casadi 3.6):

* ElastoDyn ``TwrNodes``, ``BldNodes``: ~1.2 kB per analysis node (tower nodes 1e5: +118 MB,
  blade nodes 1e5: +125 MB for :class:`~mbsym.wind.TurbineModel`), plus the structural model
  itself (:data:`STRUCTURE_BYTES`: +11 MB for the shared ElastoDyn deck, every DOF; ElastoDyn has
  at most 24 DOFs, so the ~DOFs² graph has a fixed bound).
* Table rows from their count keys (``NTwInpSt``, ``NBlInpSt``, AeroDyn ``NumTwrNds``, airfoil
  ``NumAlf`` x columns, ROSCO ``PerfTableSize``): ~104 B per cell parsed (tracemalloc peak of
  ``read_openfast`` with a 1e5 x 4 tower table: 41.5 MB), and text files named by a key without a
  count (uniform wind, WAMIT, MoorDyn, MAP++, SeaState, HydroDyn, DISCON.IN, Cp/Ct/Cq): 6.7 bytes
  per byte of text (same measurement: 41.5 MB for a 6.2 MB file; the IEA 15 MW semi-submersible's WAMIT
  files, 2.1 MB: read_wamit peaks at 10.8 MB, priced 14.3 MB).
* AeroDyn ``NumBlNds``: the blade-element CasADi graph (``aero="blade"``) costs ~100 kB per node
  and blade (ff14_flex with the blade file resampled to 152 and 2000 nodes: +45 MB and +600 MB
  for ``OperatingTurbine.dynamics()``, linear in the nodes); airfoils ~140 kB each (the spline
  table: 1440 cells x 3 coefficients x 4 cubic terms x 8 B, mbsym.wind.aero.blade.polars).
* InflowWind ``FileName_BTS``: from the ``.bts`` header alone, the float32 field
  ``4 x 3 x (NZ x NY + NTwr) x NSteps`` bytes, plus the int16 file mapped while decoding and one
  4 MB block (mbsym.wind.inflow.turbsim: ff14.bts 100.5 MB field, +164 MB resident during the
  read). A header whose sizes do not fit the limit is refused before the data are read.
* The run's output: ``(TMax - TStart) / DT_Out + 1`` times x (OutList channels + the model's
  states and inputs, :data:`STATE_COLUMNS`) x 8 B x 3 copies (as
  :func:`mbsym.simulate.monitor.check_resources`).

Sizes mbsym reads but allocates nothing by: HydroDyn ``RdtnTMax``/``RdtnDT`` (radiation states are
fitted from the WAMIT frequencies, priced by the ``.1`` file size), SeaState ``WaveTMax``/``WaveDT``
and its grid (no wave kinematics are computed), MoorDyn ``NumSegs`` and MAP++ lines (quasi-static
catenaries), DISCON.IN ``*_N`` lists (one line each, priced with the file).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from collections.abc import Iterator
from typing import Any

from ...exceptions import ArgumentTypeError, DeckMemoryError, OptionError
from ._format import _TOKEN, _canon, _is_key, _real

__all__ = ["MemoryItem", "MemoryEstimate", "deck_memory_estimate", "check_deck_memory", "STRUCTURE_BYTES",
           "STATE_COLUMNS"]

#: Structural model of an ElastoDyn deck apart from its nodes [bytes] (measured +11 MB, rounded up).
STRUCTURE_BYTES = 16e6
#: Bytes per ElastoDyn analysis node (TwrNodes, BldNodes) [bytes] (measured 1.18-1.25 kB).
NODE_BYTES = 1300.0
#: Bytes per table cell parsed (measured 104 B).
CELL_BYTES = 110.0
#: Bytes per byte of a text file parsed (measured 6.7).
TEXT_FACTOR = 7.0
#: Bytes per AeroDyn blade node and blade of the blade-element graph (measured 93-100 kB).
BLADE_NODE_BYTES = 1.0e5
#: Transient peak of composing the blade-element model apart from its nodes [bytes] (measured 50 MB on steady_14).
BLADE_GRAPH_BYTES = 55e6
#: Bytes per AeroDyn blade node and point of the tip-speed-ratio x pitch grid of the rotor-effective surfaces
#: (``aero="rotor"``, mbsym.wind.aero.surfaces.performance_surface, 8 azimuths): the transient peak of
#: RotorAero.from_openfast, measured 239, 502 and 2081 MB for 19, 38 and 152 nodes on the default 61 x 46 grid.
SURFACE_BYTES = 4.8e3
#: Points of the default grid of the rotor-effective surfaces (61 tip-speed ratios x 46 pitch angles).
SURFACE_POINTS = 61 * 46
#: Aerodynamic models priced: "blade", "rotor", or None (the cheaper of the two: what any use of the deck needs).
AERO_MODELS = ("blade", "rotor")
#: Bytes per airfoil of the blade-element polars (1440 x 3 x 4 x 8 B).
AIRFOIL_BYTES = 1440 * 3 * 4 * 8.0
#: Columns of a result besides the OutList channels (time, states, inputs, controller states).
STATE_COLUMNS = 64
_COPIES = 3
_BLOCK = 4 << 20


@dataclass(frozen=True)
class MemoryItem:
    """One priced size of a deck.

    Attributes
    ----------
    what : str
        What is allocated (e.g. "ElastoDyn tower analysis nodes").
    bytes : float
        Estimated memory [bytes].
    file : str
        File holding the key.
    line : int
        Line of the key (1-based; 0 when the file as a whole is priced).
    key : str
        The key (as spelled in the file) whose value sets the size.
    value : str
        Its value, as written.
    fix : str
        How to need less.
    """

    what: str
    bytes: float
    file: str
    line: int
    key: str
    value: str
    fix: str

    def where(self) -> str:
        return f"{self.file}, line {self.line}, key '{self.key}'"


@dataclass(frozen=True)
class MemoryEstimate:
    """The memory a deck implies: the priced items and the limit they are compared with.

    Attributes
    ----------
    items : tuple of MemoryItem
        Largest first.
    limit : float
        :func:`mbsym.simulate.monitor.memory_limit` when estimated [bytes].
    """

    items: tuple[MemoryItem, ...]
    limit: float

    @property
    def total(self) -> float:
        """Sum of the items [bytes]."""
        return float(sum(i.bytes for i in self.items))

    def dominant(self, n: int = 3) -> tuple[MemoryItem, ...]:
        """The ``n`` largest items."""
        return self.items[:n]

    def check(self) -> MemoryEstimate:
        """Raise :class:`~mbsym.exceptions.DeckMemoryError` when :attr:`total` exceeds :attr:`limit`."""
        if self.total <= self.limit:
            return self
        top = self.items[0]
        others = "; ".join(f"{i.key} = {i.value} ({i.file}, line {i.line}): {i.what}, {_size(i.bytes)}"
                           for i in self.items[1:3] if i.bytes > 0.01 * self.total)
        raise DeckMemoryError(
            f"{top.where()}: {top.key} = {top.value} implies about {_size(top.bytes)} of memory ({top.what}); the "
            f"whole deck about {_size(self.total)}, above the limit of {_size(self.limit)}"
            + (f" (next: {others})" if others else "") + f". Fix: {top.fix}, or raise the limit with the "
            "environment variable MBSYM_MEMORY_LIMIT (bytes).", estimate=self)

    def __str__(self) -> str:
        rows = [f"{_size(i.bytes):>10}  {i.key} = {i.value}  ({i.what}; {Path(i.file).name}:{i.line})"
                for i in self.items]
        return "\n".join([f"about {_size(self.total)} (limit {_size(self.limit)})", *rows])


def _size(n_bytes: float) -> str:
    for unit, scale in (("TiB", 1024 ** 4), ("GiB", 1024 ** 3), ("MiB", 1024 ** 2)):
        if n_bytes >= scale:
            return f"{n_bytes / scale:.3g} {unit}"
    return f"{n_bytes / 1024:.3g} KiB"


# ----------------------------------------------------------------------------- reading keys
class _Keys:
    """The ``<values> Key`` lines of a text file (first occurrence of each key), read leniently."""

    def __init__(self, path: Path, until: str | None = None) -> None:
        self.path = path
        self.lines: list[str] = []
        self.entries: dict[str, tuple[list[str], int, str]] = {}
        self.outlist = 0
        stop = None if until is None else _canon(until)
        inside = False
        with path.open(encoding="latin-1") as fh:      # line by line: a table after ``until`` is not read
            for number, text in enumerate(fh, start=1):
                text = text.rstrip("\r\n")
                self.lines.append(text)
                if number <= 2 or text.lstrip().startswith(("!", "#", "--", "==")):
                    continue
                tokens = _TOKEN.findall(text.strip())
                if not tokens:
                    continue
                if inside:
                    inside = text.strip()[:3].upper() != "END"
                    names = tokens[: tokens.index("-") if "-" in tokens else None] if inside else []
                    self.outlist += sum(len(t.strip("\"'").replace(",", " ").split()) for t in names)
                    continue
                if tokens[0].lower() == "outlist":
                    inside = True
                    continue
                j = next((j for j in range(1, len(tokens)) if _is_key(tokens[j])), None)
                if j is not None:
                    key = _canon(tokens[j])
                    self.entries.setdefault(key, ([t.strip("\"'") for t in tokens[:j]], number, tokens[j]))
                    if key == stop:
                        break

    def raw(self, key: str) -> tuple[str, int, str] | None:
        entry = self.entries.get(_canon(key))
        return None if entry is None or not entry[0] else (entry[0][0], entry[1], entry[2])

    def number(self, key: str) -> tuple[float, int, str, str] | None:
        """``(value, line, key as spelled, text)`` of a numeric key, or None."""
        entry = self.raw(key)
        value = None if entry is None else _real(entry[0])
        return None if value is None else (value, entry[1], entry[2], entry[0])

    def file(self, key: str) -> tuple[Path, int, str, str] | None:
        """``(path, line, key, name)`` of an existing file named by ``key`` (relative to this file), or None."""
        entry = self.raw(key)
        if entry is None or entry[0].lower() in ("unused", "none", ""):
            return None
        path = Path(entry[0].replace("\\", "/"))
        path = path if path.is_absolute() else self.path.parent / path
        return (path, entry[1], entry[2], entry[0]) if path.is_file() else None


class _Pricer:
    """Collects :class:`MemoryItem` s; reads a file only when its text fits the limit."""

    def __init__(self, limit: float) -> None:
        self.limit = limit
        self.items: list[MemoryItem] = []
        self.priced: set[Path] = set()

    def add(self, what: str, n_bytes: float, keys: _Keys, found, fix: str) -> None:
        if found is not None and n_bytes > 0:
            _, line, key, text = found
            self.items.append(MemoryItem(what, float(n_bytes), str(keys.path), line, key, text, fix))

    def count(self, keys: _Keys, key: str, per_unit: float, what: str, fix: str, factor: float = 1.0) -> float:
        """Price ``key``'s value x ``factor`` units of ``per_unit`` bytes; return the value (0 when absent)."""
        found = keys.number(key)
        if found is None or not found[0] > 0:
            return 0.0
        self.add(what, found[0] * factor * per_unit, keys, found, fix)
        return found[0]

    def open(self, keys: _Keys | None, key: str, what: str, *, read: bool = True,
             until: str | None = None) -> _Keys | None:
        """The keys of the file ``key`` names (when ``read``); its text priced once; not read beyond the limit."""
        found = None if keys is None else keys.file(key)
        if found is None:
            return None
        path = found[0]
        size = path.stat().st_size
        if path.resolve() not in self.priced:
            self.priced.add(path.resolve())
            self.add(f"parsing the {what} ({size} bytes of text)", TEXT_FACTOR * size, keys, found,
                     f"a smaller {what}")
        if not read or TEXT_FACTOR * size > self.limit:
            return None
        try:
            return _Keys(path, until)
        except (OSError, UnicodeError):
            return None


# ----------------------------------------------------------------------------- the deck
def deck_memory_estimate(fst: str | Path | Any, *, aero: str | None = None, surface_points: int = SURFACE_POINTS,
                         run: bool = True) -> MemoryEstimate:
    """Estimate the memory an OpenFAST deck implies (see the module docstring for what is priced).

    Parameters
    ----------
    fst : str, Path, TurbineParameters or OperatingDeck
        The main ``.fst`` file, or what was read from it (its ``source_files["fst"]`` or ``path``).
    aero : {"blade", "rotor"} or None, optional, keyword-only
        The aerodynamic model to price (AeroDyn decks): the blade-element graph, the rotor-effective
        surfaces, or (None) the cheaper of the two.
    surface_points : int, optional, keyword-only
        Points of the tip-speed-ratio x pitch grid of the rotor-effective surfaces.
    run : bool, optional, keyword-only
        Price the result of a run of the deck's own ``TMax`` with outputs every ``DT_Out``. The readers
        leave it out (a run may be shorter: ``--tmax``, ``t_end``): the run checks its own result
        (:func:`mbsym.simulate.monitor.check_resources`, naming the deck's TMax/DT_Out or the flags).

    Returns
    -------
    MemoryEstimate
        The priced items (largest first) and :func:`mbsym.simulate.monitor.memory_limit`. Files or keys
        that cannot be read are left out (the readers report them).
    """
    from ...simulate.monitor import memory_limit

    if aero not in (None, *AERO_MODELS):
        raise OptionError(f"aero must be one of {list(AERO_MODELS)} or None; got {aero!r}.")
    pricer = _Pricer(memory_limit())
    path = _fst_path(fst)
    main = _Keys(path) if path.is_file() else None
    if main is not None:
        channels = 0
        ed = pricer.open(main, "EDFile", "ElastoDyn file")
        if ed is not None:
            pricer.add("the structural model (at most 24 ElastoDyn DOFs; fixed)", STRUCTURE_BYTES, main,
                       main.file("EDFile"), "nothing (a fixed cost)")
        channels += _elastodyn(pricer, ed)
        if _switch(main, "CompAero") == 2:
            ad = pricer.open(main, "AeroFile", "AeroDyn file")
            channels += _aerodyn(pricer, ad, _n_blades(ed), aero, surface_points)
        if _switch(main, "CompInflow") == 1:
            channels += _inflow(pricer, pricer.open(main, "InflowFile", "InflowWind file"))
        if _switch(main, "CompServo") == 1:
            channels += _servo(pricer, pricer.open(main, "ServoFile", "ServoDyn file"))
        for switch, key, what in (("CompHydro", "HydroFile", "HydroDyn file"), ("CompSeaSt", "SeaStFile", "SeaState file"),
                                  ("CompMooring", "MooringFile", "mooring file")):
            if _switch(main, switch):
                module = pricer.open(main, key, what, read=switch == "CompHydro")
                _wamit(pricer, module)
        if run:
            _output(pricer, main, channels)
    items = tuple(sorted(pricer.items, key=lambda i: -i.bytes))
    return MemoryEstimate(items, pricer.limit)


def _fst_path(deck: Any) -> Path:
    if isinstance(deck, (str, Path)):
        return Path(deck)
    sources = getattr(deck, "source_files", None) or getattr(getattr(deck, "turbine", None), "source_files", None)
    if sources and sources.get("fst"):
        return Path(sources["fst"])
    if getattr(deck, "path", None) is not None:
        return Path(deck.path)
    raise ArgumentTypeError(f"expected the path of a .fst, TurbineParameters or an OperatingDeck read from one; got "
                    f"{type(deck).__name__}.")


def check_deck_memory(fst: str | Path | Any, *, aero: str | None = None, surface_points: int = SURFACE_POINTS,
                      run: bool = True) -> MemoryEstimate:
    """:func:`deck_memory_estimate`, refused above the limit.

    Raises
    ------
    DeckMemoryError
        The estimate is above :func:`mbsym.simulate.monitor.memory_limit`; names the file, line and key
        of the largest item, the estimate, the limit and how to need less.
    """
    return deck_memory_estimate(fst, aero=aero, surface_points=surface_points, run=run).check()


def _switch(keys: _Keys, key: str) -> int:
    found = keys.number(key)
    return int(found[0]) if found is not None else 0


def _n_blades(ed: _Keys | None) -> int:
    found = None if ed is None else ed.number("NumBl")
    return int(found[0]) if found is not None and found[0] in (1, 2, 3) else 3


def _elastodyn(p: _Pricer, ed: _Keys | None) -> int:
    if ed is None:
        return 0
    p.count(ed, "TwrNodes", NODE_BYTES, "ElastoDyn tower analysis nodes", "fewer TwrNodes (decks use 10-100)")
    p.count(ed, "BldNodes", NODE_BYTES, "ElastoDyn blade analysis nodes", "fewer BldNodes (decks use 10-100)")
    tower = p.open(ed, "TwrFile", "ElastoDyn tower file", until="NTwInpSt")
    if tower is not None:
        p.count(tower, "NTwInpSt", CELL_BYTES, "tower input stations parsed (x 4 columns)", "fewer NTwInpSt rows", 4)
    seen: set[Path] = set()
    for k in range(1, _n_blades(ed) + 1):
        found = ed.file(f"BldFile({k})")
        if found is None or found[0].resolve() in seen:
            continue
        seen.add(found[0].resolve())
        blade = p.open(ed, f"BldFile({k})", "ElastoDyn blade file", until="NBlInpSt")
        if blade is not None:
            p.count(blade, "NBlInpSt", CELL_BYTES, "blade input stations parsed (x 6 columns)", "fewer NBlInpSt rows", 6)
    return ed.outlist


def _aerodyn(p: _Pricer, ad: _Keys | None, n_blades: int, aero: str | None, surface_points: int) -> int:
    if ad is None:
        return 0
    p.count(ad, "NumTwrNds", CELL_BYTES, "AeroDyn tower nodes parsed (x 3 columns)", "fewer NumTwrNds", 3)
    n_af = p.count(ad, "NumAFfiles", AIRFOIL_BYTES if aero != "rotor" else 0.0,
                   "airfoil tables of the blade-element model", "fewer NumAFfiles")
    for name in _airfoil_names(ad, int(min(n_af, 10_000))):
        _airfoil(p, ad, name)
    files: dict[Path, tuple[str, int]] = {}
    for k in range(1, n_blades + 1):
        found = ad.file(f"ADBlFile({k})")
        if found is not None:
            key, count = files.get(found[0].resolve(), (f"ADBlFile({k})", 0))
            files[found[0].resolve()] = (key, count + 1)
    for key, count in files.values():
        blade = p.open(ad, key, "AeroDyn blade file", until="NumBlNds")
        if blade is not None:
            _aero_model(p, blade, count, aero, surface_points)
            p.count(blade, "NumBlNds", CELL_BYTES, "AeroDyn blade table parsed (x 7 columns)", "fewer NumBlNds", 7)
    return ad.outlist


def _aero_model(p: _Pricer, blade: _Keys, count: int, aero: str | None, surface_points: int) -> None:
    """The blade-element graph (``count`` blades use this file) or the rotor-effective surfaces (the first)."""
    found = blade.number("NumBlNds")
    if found is None or not found[0] > 0:
        return
    graph = BLADE_GRAPH_BYTES + BLADE_NODE_BYTES * count * found[0]
    surfaces = SURFACE_BYTES * surface_points * found[0]
    if aero == "blade" or (aero is None and graph <= surfaces):
        p.add(f"blade-element CasADi graph (aero='blade'; {count} blade(s) x ~100 kB per node + "
              f"{BLADE_GRAPH_BYTES / 1e6:.0f} MB)", graph, blade, found, "fewer NumBlNds (AeroDyn decks use 15-50)")
    else:
        p.add(f"rotor-effective surfaces (aero='rotor'; {surface_points} grid points x ~4.8 kB per node)", surfaces,
              blade, found, "fewer NumBlNds (AeroDyn decks use 15-50), or aero='blade'")


def _airfoil_names(ad: _Keys, count: int) -> Iterator[tuple[str, int]]:
    """``(name, line)`` of the AFNames entries: the key's line, then one name per line."""
    entry = ad.entries.get("afnames")
    if entry is None or not entry[0] or count < 1:
        return
    yield entry[0][0], entry[1]
    for number in range(entry[1] + 1, min(entry[1] + count, len(ad.lines) + 1)):
        tokens = _TOKEN.findall(ad.lines[number - 1].strip())
        if not tokens or ad.lines[number - 1].lstrip().startswith(("--", "==")):
            return
        yield tokens[0].strip("\"'"), number


def _airfoil(p: _Pricer, ad: _Keys, name_line: tuple[str, int]) -> None:
    name, line = name_line
    path = Path(name.replace("\\", "/"))
    path = path if path.is_absolute() else ad.path.parent / path
    if not path.is_file():
        return
    size = path.stat().st_size
    if size * TEXT_FACTOR > p.limit:
        p.items.append(MemoryItem(f"parsing the airfoil file ({size} bytes of text)", TEXT_FACTOR * size,
                                  str(ad.path), line, "AFNames", name, "a smaller airfoil file"))
        return
    try:
        af = _Keys(path, until="NumAlf")
    except (OSError, UnicodeError):
        return
    columns = max((int(ad.number(c)[0]) for c in ("InCol_Alfa", "InCol_Cl", "InCol_Cd", "InCol_Cm")
                   if ad.number(c) is not None), default=4)
    found = af.number("NumAlf")
    if found is not None and found[0] > 0:
        p.items.append(MemoryItem(f"airfoil table parsed (x {columns} columns)", found[0] * columns * CELL_BYTES,
                                  str(path), found[1], found[2], found[3], "fewer NumAlf rows"))


def _inflow(p: _Pricer, ifw: _Keys | None) -> int:
    if ifw is None:
        return 0
    wind_type = _switch(ifw, "WindType")
    if wind_type == 2:
        p.open(ifw, "Filename_Uni", "uniform wind file", read=False)
    if wind_type == 3:
        found = ifw.file("FileName_BTS")
        if found is not None:
            _turbsim(p, ifw, found)
    if wind_type == 5:
        _hawc(p, ifw)
    if wind_type == 4:
        _bladed(p, ifw)
    return ifw.outlist


def _bladed(p: _Pricer, ifw: _Keys) -> None:
    """Price TurbSim's Bladed-style box from its size: float32 velocities, twice the int16 file, plus the file
    mapped while decoding."""
    entry = ifw.raw("FileNameRoot")
    if entry is None:
        return
    path = Path(entry[0].replace("\\", "/") + ".wnd")
    path = path if path.is_absolute() else ifw.path.parent / path
    if path.is_file():
        size = path.stat().st_size
        p.add(f"Bladed-style full field from its size ({size} bytes of int16: float32 velocities, plus the file "
              "mapped while decoding)", 3.0 * size + _BLOCK, ifw, (path, entry[1], entry[2], entry[0]),
              "a smaller or shorter wind box (fewer grid points or time steps)")


def _hawc(p: _Pricer, ifw: _Keys) -> None:
    """Price a HAWC box from its InflowWind keys: the float32 grid plus one component's copy while reading."""
    sizes = [ifw.number(k) for k in ("nx", "ny", "nz")]
    if any(s is None or not s[0] >= 1 for s in sizes):
        return                                          # the reader refuses them
    values = 3.0 * sizes[0][0] * sizes[1][0] * sizes[2][0]
    p.add(f"HAWC box: {sizes[0][3]} x {sizes[1][3]} x {sizes[2][3]} points x 3 components (float32, plus one "
          "component while reading)", 4.0 * values * 4.0 / 3.0, ifw, sizes[0],
          "a smaller HAWC box (fewer points: nx, ny, nz)")


def _turbsim(p: _Pricer, ifw: _Keys, found: tuple[Path, int, str, str]) -> None:
    """Price a TurbSim field from its header alone (``mbsym.wind.inflow.turbsim`` layout)."""
    import numpy as np

    from ..inflow.turbsim import _HEADER

    path, line, key, name = found
    with path.open("rb") as fh:
        head = fh.read(_HEADER.itemsize)
    if len(head) < _HEADER.itemsize:
        return                                          # the reader reports a short file
    h = np.frombuffer(head, dtype=_HEADER)[0]
    nz, ny, ntwr, nt = (int(h[k]) for k in ("nz", "ny", "ntwr", "nt"))
    if min(nz, ny, nt) < 1 or ntwr < 0:
        return                                          # an invalid header: the reader refuses it
    values = 3 * (nz * ny + ntwr) * nt
    field = 4.0 * values + 2.0 * values + _BLOCK        # float32 field + int16 file mapped + one block
    p.items.append(MemoryItem(
        f"TurbSim full field from its header: {nz} x {ny} grid + {ntwr} tower points x {nt} steps x 3 components "
        "(float32, plus the int16 file mapped while decoding)", field, str(ifw.path), line, key, name,
        "a smaller or shorter TurbSim field (fewer grid points or time steps)"))


def _servo(p: _Pricer, srvd: _Keys | None) -> int:
    if srvd is None:
        return 0
    discon = p.open(srvd, "DLL_InFile", "controller input file", until="PerfTableSize")
    entry = None if discon is None else discon.entries.get("perftablesize")
    sizes = [_real(v) for v in entry[0][:2]] if entry is not None else []
    if len(sizes) == 2 and all(s is not None and s > 0 for s in sizes):
        p.items.append(MemoryItem("Cp/Ct/Cq tables parsed (3 tables)", 3 * sizes[0] * sizes[1] * CELL_BYTES,
                                  str(discon.path), entry[1], entry[2], " ".join(entry[0][:2]),
                                  "a smaller PerfTableSize (and Cp/Ct/Cq file)"))
    p.open(discon, "PerfFileName", "Cp/Ct/Cq file", read=False)
    return srvd.outlist


def _wamit(p: _Pricer, hd: _Keys | None) -> None:
    """Price the WAMIT files (``PotFile`` roots + .1, .3, .hst) by their text."""
    entry = None if hd is None else hd.entries.get("potfile")
    if entry is None or not entry[0]:
        return
    root = Path(entry[0][0].replace("\\", "/"))
    root = root if root.is_absolute() else hd.path.parent / root
    for suffix in (".1", ".3", ".hst"):
        path = root.with_name(root.name + suffix)
        if path.is_file():
            size = path.stat().st_size
            p.items.append(MemoryItem(f"parsing WAMIT {path.name} ({size} bytes of text)", TEXT_FACTOR * size,
                                      str(hd.path), entry[1], entry[2], entry[0][0], f"a smaller WAMIT {suffix} file"))


def _output(p: _Pricer, main: _Keys, channels: int) -> None:
    """The result a run of ``TMax`` with outputs every ``DT_Out`` holds."""
    tmax, dt = main.number("TMax"), main.number("DT")
    dt_out = main.number("DT_Out") or dt
    start = main.number("TStart")
    if tmax is None or dt_out is None or not dt_out[0] > 0 or not math.isfinite(tmax[0]):
        return
    span = max(tmax[0] - (start[0] if start is not None else 0.0), 0.0)
    n_out = math.floor(span / dt_out[0] + 1e-9) + 1
    n_bytes = n_out * (channels + STATE_COLUMNS) * 8.0 * _COPIES
    p.items.append(MemoryItem(f"the result: {n_out:.4g} output times x ({channels} OutList channels + "
                              f"{STATE_COLUMNS} states and inputs) x 8 B x {_COPIES} copies", n_bytes,
                              str(main.path), dt_out[1], dt_out[2], dt_out[3],
                              f"a larger {dt_out[2]} or a shorter TMax (line {tmax[1]})"))
