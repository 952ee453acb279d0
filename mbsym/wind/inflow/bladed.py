"""Bladed-style full-field wind boxes (InflowWind ``WindType = 4`` and ``7``), read as OpenFAST v5.0.0 does.

One binary box, two ways in (``IfW_Bladed_Init`` and the routines it calls, OpenFAST v5.0.0
``modules/inflowwind/src/InflowWind_IO.f90``; TurbSim's writer ``WrBinBLADED``, ``modules/turbsim/src/TS_FileIO.f90``):

* :func:`read_bladed_wnd` (``WindType = 4``): TurbSim's ``<root>.wnd`` holds the whole velocity, normalized with the
  ``UBar`` and TIs of TurbSim's summary ``<root>.sum``; with ``TowerFile = True`` the tower file ``<root>.twr`` adds
  points below the grid.
* :func:`read_bladed_native` (``WindType = 7``): a native Bladed summary names the box, which holds normalized
  fluctuations: scaled to the summary's standard deviations at the grid centre, with a power-law mean (plus linear
  shears) added after interpolation; periodic, starting at ``XOffset``, going to zero at the ground below the grid;
  the summary's ``WDIR``/``FLINC`` replace the InflowWind file's ``PropagationDir``/``VFlowAng``.

The box (little-endian); its first int16 is the format, -99 (new style) or -1, -2, -3 (old style, minus the number of
components):

==================  ===================================================================================
new style (-99)     int16 -99, int16 ``TurbType``, then by type: 1, 2 (one component), 3, 5 (three): nothing;
                    4 (improved von Karman; TurbSim): int32 NComp, float32 latitude, z0, reference height, TI u,
                    v, w [%]; 7, 8 (general Kaimal, Mann): int32 header size, int32 NComp. Then float32 dz, dy,
                    dx [m], int32 NStepsHalf, float32 mean speed [m/s] and 3 length scales, int32 unused, seed, NZ,
                    NY; 6 more 4-byte values if NComp = 3; then 2 float32 (type 7) or 16 4-byte values (type 8)
old style (-1..-3)  13 int16: id, dz, dy, dx [mm], NStepsHalf, mean speed [0.1 m/s], 3 length scales, unused,
                    seed, 1000 NZ, 1000 NY; 6 more int16 if NComp = 3
data                int16 per time step ``(NZ, NY, NComp)``: component fastest, then y, then z (bottom row
                    first); ``2 NStepsHalf + 1`` steps, or ``2 NStepsHalf`` if the file has no more
==================  ===================================================================================

What InflowWind makes of it (``Bladed_ReadHeader0/1``, ``Bladed_ReadGrids``), reproduced here:

* ``dt = dx / U`` with ``U`` the box's mean speed (type 4) or the summary's ``UBAR`` (type 7), in float64 from the
  header's float32 values (TurbSim's ``dx = float32(dt U)``: ``dt`` is not exactly TurbSim's);
* values ``real(offset + scale n, SiKi)`` (float64, then rounded to float32): type 4: offset ``(U, 0, 0)``, scale
  ``0.001 U TI/100`` with the TIs [%] of the box (TurbType 4, where positive) or else of the ``.sum``, ``v``'s scale
  negated with the left-hand rule; type 7: scale ``(0.001, -0.001, 0.001)`` (always left-handed), then each
  component times ``TI UBAR / σ``, ``σ`` its standard deviation over time at the grid centre
  (``Grid3D_ScaleTurbulence``; ``(n + 1) // 2``, 1-based, in y and z);
* the clockwise flag reverses the lateral order; the grid is centred on the tower and on ``ZCenter`` = hub height -
  height offset (type 4) or ``REFHT`` (type 7): bottom ``ZCenter - (NZ - 1) dz / 2``;
* ``.sum`` (``Bladed_ReadTurbSimSummary``, a line scan in this order): ``CLOCKWISE`` (T/F or Y/N first on the line,
  only before the hub height), ``HUB HEIGHT`` or ``ZHUB`` (number first), ``UBAR`` (after ``=``) and the next three
  lines' TIs (between ``=`` and ``%``), ``HEIGHT OFFSET`` (after ``=``), then ``PERIODIC`` and ``BLADED LEFT-HAND
  RULE`` anywhere (seen only after the height offset); box and ``.sum`` speeds must agree within 0.1 m/s;
* ``.twr`` (``Bladed_ReadTower``): float32 dz, dx, top height, int32 steps, points, float32 mean speed, TI u, v, w
  [%], checked against the box (relative 1e-4); then int16 ``(points, 3)`` per step, ``U (offset + 1e-5 TI n)``
  (offset 1 for ``u``). InflowWind applies no left-hand rule there, so its tower ``v`` has the opposite sign of
  TurbSim's own (.bts) tower ``v`` (reproduced).

Checked against OpenFAST v5.0.0 (``tests/wind/inflow/test_bladed_wind.py``): at 9 points of 8 cases (both types, all
header styles, tower, clockwise, non-periodic, rotated, linear shears) mbsym's velocities rounded to float32 equal
every value OpenFAST writes.

Refused (:class:`~mbsym.exceptions.OpenFASTFormatError`, naming the file): boxes with one or two components
(InflowWind allocates NComp components, then addresses three), unknown ``TurbType`` (InflowWind warns and guesses a
layout), ``@`` includes and misplaced or malformed keys in a native summary (InflowWind would silently skip a value),
and everything InflowWind stops on. Bytes beyond the steps InflowWind reads are ignored with a warning, as InflowWind
ignores them.

Memory: the velocities are kept once as float32 (twice the int16 file); decoding runs over blocks of time steps
(4 MB of int16) of a memory map of the file.
"""

from __future__ import annotations

import math
import re
import struct
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...exceptions import OpenFASTFormatError, WindInputError
from .field import FullFieldWind
from .profile import MeanProfile

__all__ = ["read_bladed_wnd", "read_bladed_native", "BLADED_FILE_IDS", "BLADED_TURB_TYPES", "NATIVE_KEYS"]

#: The first int16 of a Bladed-style box: -99 new style; -1, -2, -3 old style (minus the number of components).
BLADED_FILE_IDS = (-99, -1, -2, -3)
#: ``TurbType`` of new-style boxes that InflowWind reads (Bladed_ReadHeader1).
BLADED_TURB_TYPES = {1: "von Karman (1 component)", 2: "Kaimal (1 component)", 3: "von Karman",
                     4: "improved von Karman", 5: "IEC-2 Kaimal", 7: "general Kaimal", 8: "Mann"}
#: The native summary's keys in the order InflowWind reads them (the last four optional).
NATIVE_KEYS = ("UBAR", "REFHT", "TI", "TI_V", "TI_W", "WDIR", "FLINC", "WINDF", "WSHEAR",
               "VLINSHEAR", "HLINSHEAR", "REFLENGTH", "XOFFSET")
_TOWER_TOL = 1.0e-4           # Bladed_ReadTower's tolerance on the tower file's header
_BLOCK_BYTES = 4 << 20
_EQUAL_TOL = 100.0 * np.finfo(float).eps / 2.0   # NWTC EqualRealNos: |a - b| <= max(|a + b|, 1) tol


def _fail(path, what: str, fix: str) -> OpenFASTFormatError:
    return OpenFASTFormatError(f"{path}: {what}. {fix}")


# ---------------------------------------------------------------------------------------------- the binary box
@dataclass(frozen=True)
class _Header:
    file_id: int
    turb_type: int | None
    n_comp: int
    dz: float
    dy: float
    dx: float
    n_half: int
    mean_speed: float            # the box's own (type 4; type 7 uses UBAR)
    nz: int
    ny: int
    ti: tuple | None             # TurbType 4's TIs [%]
    size: int                    # bytes before the data


def _read_header(path: Path) -> _Header:
    """The header of a Bladed-style box (``Bladed_ReadHeader0`` / ``Bladed_ReadHeader1``)."""
    with path.open("rb") as fh:
        head = fh.read(256)
    if len(head) < 2:
        raise _fail(path, "the file is empty or has a single byte; a Bladed-style box starts with an int16 "
                    "format identifier", "Check the file name (InflowWind's FileNameRoot + .wnd, or WINDF).")
    fid = int(np.frombuffer(head[:2], "<i2")[0])
    if fid not in BLADED_FILE_IDS:
        raise _fail(path, f"the first int16 is {fid}; a Bladed-style box starts with -99 (new style) or -1, -2, -3 "
                    "(old style)", "This is not a Bladed-style box (a TurbSim .bts starts with 7 or 8: use "
                    "WindType = 3).")

    def unpack(fmt: str, at: int, what: str) -> tuple:
        need = at + struct.calcsize(fmt)
        if len(head) < need:
            raise _fail(path, f"the file ends inside its header ({what}: {len(head)} bytes, at least {need} "
                        "needed)", "The file is truncated or not a Bladed-style box.")
        return struct.unpack_from(fmt, head, at)

    if fid != -99:
        v = unpack("<13h", 0, "old-style header")
        n_comp = -fid
        h = _Header(fid, None, n_comp, 0.001 * v[1], 0.001 * v[2], 0.001 * v[3], v[4], 0.1 * v[5],
                    int(v[11] / 1000), int(v[12] / 1000), None, 26 + (12 if n_comp == 3 else 0))
    else:
        turb = unpack("<h", 2, "TurbType")[0]
        at, ti = 4, None
        if turb in (1, 2):
            n_comp = 1
        elif turb in (3, 5):
            n_comp = 3
        elif turb == 4:                                  # NComp, latitude, z0, reference height, TI u v w [%]
            n_comp, *rest = unpack("<i6f", at, "TurbType 4 block")
            ti, at = tuple(rest[3:6]), at + 28
        elif turb in (7, 8):                             # header size, NComp
            n_comp = unpack("<2i", at, "TurbType 7/8 block")[1]
            at += 8
        else:
            raise _fail(path, f"TurbType (second int16) is {turb}; InflowWind knows 1-5, 7 and 8 and, for others, "
                        "only warns and guesses a 3-component layout", "Write the box with a known TurbType.")
        s = unpack("<3fi4f4i", at, "grid block")         # dz dy dx, NStepsHalf, U, 3 scales, unused seed NZ NY
        at += 48 + (24 if n_comp == 3 else 0) + {7: 8, 8: 64}.get(turb, 0)
        h = _Header(fid, turb, n_comp, s[0], s[1], s[2], s[3], s[4], s[10], s[11], ti, at)
    problems = []
    if h.n_comp != 3:
        problems.append(f"{h.n_comp} wind component(s) (mbsym, like InflowWind's tower and grid code, needs 3)")
    problems += [f"{k} = {getattr(h, k)} (at least 2)" for k in ("nz", "ny") if getattr(h, k) < 2]
    if h.n_half < 1:
        problems.append(f"NStepsHalf = {h.n_half} (at least 1)")
    problems += [f"{k} = {getattr(h, k):g} m (must be > 0)" for k in ("dz", "dy", "dx")
                 if not (math.isfinite(getattr(h, k)) and getattr(h, k) > 0.0)]
    if problems:
        raise _fail(path, "unsupported or invalid header: " + "; ".join(problems), "Check the box (TurbSim writes "
                    "3 components, at least 2 points per axis and positive spacings).")
    return h


def _step_count(path: Path, h: _Header) -> int:
    """InflowWind's ``NSteps``: it reads ``2 NStepsHalf + 1`` steps and accepts the last one missing."""
    per_step = 2 * h.n_comp * h.ny * h.nz
    data = path.stat().st_size - h.size
    full = max(data, 0) // per_step
    if full < 2 * h.n_half:
        raise _fail(path, f"the header announces {2 * h.n_half} (or {2 * h.n_half + 1}) time steps of a {h.ny} x "
                    f"{h.nz} grid ({per_step} bytes each) but the file holds {full} whole steps (truncated)",
                    "Regenerate or copy the file again.")
    n = min(full, 2 * h.n_half + 1)
    extra = data - n * per_step
    if extra:
        warnings.warn(f"{path}: {extra} bytes after the {n} time steps InflowWind reads (NStepsHalf = {h.n_half}) are "
                      "ignored, as InflowWind does.", stacklevel=3)
    return n


def _decode_grid(path: Path, h: _Header, n_steps: int, scale: np.ndarray, offset: np.ndarray,
                 clockwise: bool) -> np.ndarray:
    """float32 grid (n_steps, nz, ny, 3): ``real(offset + scale n, SiKi)`` per component, y reversed if clockwise."""
    raw = np.memmap(path, dtype="<i2", mode="r", offset=h.size, shape=(n_steps, h.nz, h.ny, 3))
    grid = np.empty((n_steps, h.nz, h.ny, 3), dtype=np.float32)
    block = max(1, _BLOCK_BYTES // (6 * h.ny * h.nz))
    for i in range(0, n_steps, block):
        chunk = np.asarray(raw[i:i + block], dtype=np.float64)
        if clockwise:
            chunk = chunk[:, :, ::-1]
        grid[i:i + block] = chunk * scale + offset
    del raw
    return grid


# ---------------------------------------------------------------------------------------------- Fortran-style reads
_REAL = re.compile(r"[+-]?(\d+\.?\d*|\.\d+)([EDQ][+-]?\d+|[+-]\d+)?$", re.IGNORECASE)


def _list_real(text: str):
    """A Fortran list-directed read of one real: the value, None for a null value (unchanged), or ValueError."""
    s = text.lstrip(" \t")
    if not s or s[0] in ",/":
        if not s:
            raise ValueError("no value")
        return None
    token = re.split(r"[ \t,/]", s, maxsplit=1)[0]
    repeat = re.match(r"\d+\*", token)                    # "r*c": c (r times); "r*": a null value
    if repeat:
        token = token[repeat.end():]
        if not token:
            return None
    if not _REAL.match(token):
        raise ValueError(f"{token!r} is not a number")
    mantissa, exponent = re.match(r"([+-]?[\d.]+)(.*)$", token).groups()
    value = float(mantissa + ("e" + exponent.lstrip("EeDdQq") if exponent else ""))
    if not math.isfinite(value):
        raise ValueError(f"{token!r} is not finite")
    return value


def _list_logical(text: str):
    """A Fortran list-directed read of one logical (``T``, ``.TRUE.``, ``F``, ...): bool, None (null) or ValueError."""
    s = text.lstrip(" \t")
    if not s:
        raise ValueError("no value")
    if s[0] in ",/":
        return None
    m = re.match(r"\.?([TF])", s, re.IGNORECASE)
    if not m:
        raise ValueError(f"{s.split()[0]!r} is not a logical")
    return m.group(1).upper() == "T"


# ---------------------------------------------------------------------------------------------- TurbSim summary
def _read_turbsim_summary(path: Path) -> dict:
    """``Bladed_ReadTurbSimSummary``: the line scan, key by key, as InflowWind does it."""
    if not path.is_file():
        raise OpenFASTFormatError(f"TurbSim summary file not found: tried '{path.absolute()}'. InflowWind's WindType = "
                                  "4 needs the .sum TurbSim wrote with the .wnd (same root name, same folder): it "
                                  "holds the hub height and the normalization of the box.")
    lines = [line[:1024].upper() for line in path.read_text(encoding="latin-1").splitlines()]
    out = dict(clockwise=False, hub_height=0.0, ubar=None, ti=None, z_offset=0.0, periodic=False, lhr=False)
    need_cw = need_hub = need_ubar = need_offset = need_periodic = True

    def value(reader, text: str, what: str, k: int):
        try:
            return reader(text)
        except ValueError as err:
            raise _fail(path, f"line {k + 1}: cannot read {what} ({err}): {lines[k].strip()!r}",
                        "Fix the summary file (TurbSim writes the value first or after '=').") from None

    k = 0
    while k < len(lines):
        line = lines[k]
        if need_hub:
            if need_cw and "CLOCKWISE" in line:
                try:
                    v = _list_logical(line)
                    out["clockwise"] = out["clockwise"] if v is None else v
                    need_cw = False
                except ValueError:
                    first = line.lstrip()[:1]
                    if first not in ("Y", "N"):
                        raise _fail(path, f"line {k + 1}: cannot read the rotation direction (CLOCKWISE): "
                                    f"{line.strip()!r}", "Start the line with T/F or Y/N.") from None
                    out["clockwise"] = first == "Y"
                    k += 1
                    continue
            if "HUB HEIGHT" in line or "ZHUB" in line:
                v = value(_list_real, line, "the hub height", k)
                out["hub_height"] = out["hub_height"] if v is None else v
                need_hub = False
        elif need_ubar:
            if "UBAR" in line:
                v = value(_list_real, line[line.find("=") + 1:], "UBar", k)
                out["ubar"] = v
                ti = []
                for i in range(3):
                    k += 1
                    if k >= len(lines):
                        raise _fail(path, "the file ends before the three TI lines after UBar",
                                    "Regenerate the summary with TurbSim.")
                    t = lines[k]
                    first, last = t.find("=") + 2, t.find("%")          # 1-based, as InflowWind
                    last = len(t) if last <= first else last
                    ti.append(value(_list_real, t[first - 1:last], f"TI({'uvw'[i]})", k))
                out["ti"], need_ubar = ti, False
        elif need_offset:
            if "HEIGHT OFFSET" in line:
                v = value(_list_real, line[line.find("=") + 1:], "the height offset", k)
                out["z_offset"] = out["z_offset"] if v is None else v
                need_offset = False
        else:
            if need_periodic and "PERIODIC" in line:
                out["periodic"], need_periodic = True, False
                k += 1
                continue
            if "BLADED LEFT-HAND RULE" in line:
                out["lhr"] = True
                break
        k += 1
    if need_hub or need_ubar:
        missing = "the hub height ('HUB HEIGHT' or 'ZHUB')" if need_hub else "UBar and the TIs ('UBAR')"
        raise _fail(path, f"{missing} not found", "Use the summary TurbSim wrote with the box.")
    if None in (out["ubar"], *out["ti"]):
        raise _fail(path, "UBar or a TI line has no value", "Use the summary TurbSim wrote with the box.")
    return out


# ---------------------------------------------------------------------------------------------- native summary
def _words(line: str) -> list:
    """NWTC ``GetWords`` (first two words; quotes, blanks, commas, semicolons and tabs separate)."""
    return [w for w in re.split(r"[\s,;\"']+", line) if w][:2]


def _read_native_summary(path: Path) -> dict:
    """``Bladed_ReadNativeSummary``: ``KEY value`` (or ``value KEY``) lines in a fixed order."""
    if not path.is_file():
        raise OpenFASTFormatError(f"native Bladed summary file not found: tried '{path.absolute()}'. WindType = 7 "
                                  "takes it from InflowWind's FileNameRoot (the file itself, no extension added).")
    rows = []
    for n, raw in enumerate(path.read_text(encoding="latin-1").splitlines(), start=1):
        cut = min([raw.find(c) for c in "!#%" if c in raw] + [len(raw)])
        text = raw[:cut].strip()
        if text.startswith("@"):
            raise _fail(path, f"line {n}: '@' includes another file", "Write the keys in the summary file itself.")
        if text:
            rows.append((n, text))
    found, k = {}, 0
    for key in NATIVE_KEYS:
        optional = key in NATIVE_KEYS[9:]
        words = _words(rows[k][1]) if k < len(rows) else []
        upper = [w[:20].upper() for w in words]
        if len(words) == 2 and key in upper:
            text = words[1] if upper[0] == key else words[0]
            if key != "WINDF":
                try:
                    text = _list_real(text)
                except ValueError:
                    text = None
                if text is None:
                    raise _fail(path, f"line {rows[k][0]}: {key} has no valid number: {rows[k][1]!r}",
                                "Write a finite number" + (" (InflowWind would silently use 0)." if optional else "."))
            found[key] = text
            k += 1
        elif not optional:
            where = f"line {rows[k][0]} ({rows[k][1]!r})" if k < len(rows) else "the end of the file"
            raise _fail(path, f"{key} expected at {where}", "InflowWind reads UBAR, REFHT, TI, TI_V, TI_W, WDIR, "
                        "FLINC, WINDF, WSHEAR on the first nine data lines, in this order, each as 'KEY value'.")
    for n, text in rows[k:]:
        hit = [w.upper() for w in _words(text) if w[:20].upper() in NATIVE_KEYS]
        if hit:
            raise _fail(path, f"line {n}: {hit[0]} is not where InflowWind reads it, so InflowWind would ignore it",
                        "Optional keys must follow WSHEAR in the order VLINSHEAR, HLINSHEAR, REFLENGTH, XOffset; "
                        "each key once.")
    return found


# ---------------------------------------------------------------------------------------------- tower file
def _read_tower(path: Path, box: Path, h: _Header, n_steps: int, mean_speed: float, dt: float,
                grid_bottom: float) -> np.ndarray | None:
    """``Bladed_ReadTower``: float32 tower velocities (n_steps, points, 3), or None with 0 points."""
    if not path.is_file():
        raise OpenFASTFormatError(f"tower file not found: tried '{path.absolute()}' (TowerFile = True for "
                                  f"{box.name}). Write it with TurbSim (WrADTWR = True) or set TowerFile = False.")
    head_t = np.dtype([("dz", "<f4"), ("dx", "<f4"), ("zmax", "<f4"), ("nt", "<i4"), ("nz", "<i4"),
                       ("uhub", "<f4"), ("ti", "<f4", (3,))])
    with path.open("rb") as fh:
        head = fh.read(head_t.itemsize)
    if len(head) < head_t.itemsize:
        raise _fail(path, f"the tower file has {len(head)} bytes, fewer than its {head_t.itemsize}-byte header",
                    "Regenerate it with TurbSim.")
    t = np.frombuffer(head, dtype=head_t)[0]
    dz, dx, zmax, uhub = (float(t[k]) for k in ("dz", "dx", "zmax", "uhub"))
    bad = []
    with np.errstate(divide="ignore", invalid="ignore"):
        if not abs(dz * (1.0 / h.dz) - 1.0) <= _TOWER_TOL:                  # the same arithmetic as InflowWind
            bad.append(f"dz {dz:g} m (box: {h.dz:g} m)")
        if not abs(dx * (1.0 / mean_speed) / dt - 1.0) <= _TOWER_TOL:
            bad.append(f"dx {dx:g} m (box: dt U = {dt * mean_speed:g} m)")
        if not abs(zmax / grid_bottom - 1.0) <= _TOWER_TOL:
            bad.append(f"top height {zmax:g} m (grid bottom: {grid_bottom:g} m)")
        if int(t["nt"]) != n_steps:
            bad.append(f"{int(t['nt'])} time steps (box: {n_steps})")
        if not abs(uhub * (1.0 / mean_speed) - 1.0) <= _TOWER_TOL:
            bad.append(f"mean speed {uhub:g} m/s (box: {mean_speed:g} m/s)")
    if bad:
        raise _fail(path, "the tower file does not match the box " + box.name + ": " + "; ".join(bad),
                    "Use the tower file TurbSim wrote with the box (InflowWind stops on this).")
    n_pts = int(t["nz"])
    if n_pts <= 0:
        return None
    need = head_t.itemsize + 6 * n_pts * n_steps
    if path.stat().st_size < need:
        raise _fail(path, f"the tower file holds {path.stat().st_size} bytes; {n_steps} steps of {n_pts} points need "
                    f"{need} (truncated)", "Regenerate it with TurbSim.")
    if path.stat().st_size > need:
        warnings.warn(f"{path}: {path.stat().st_size - need} bytes after the {n_steps} time steps InflowWind reads are "
                      "ignored, as InflowWind does.", stacklevel=3)
    raw = np.fromfile(path, dtype="<i2", count=3 * n_pts * n_steps, offset=head_t.itemsize)
    c = 1.0e-5 * t["ti"].astype(np.float64)                       # 0.00001 TI (double, as -fdefault-real-8)
    v = mean_speed * (np.array([1.0, 0.0, 0.0]) + c * raw.reshape(n_steps, n_pts, 3))
    return v.astype(np.float32)


# ---------------------------------------------------------------------------------------------- native scaling
def _scale_to_sigma(grid: np.ndarray, sigma: np.ndarray, where: str) -> None:
    """``Grid3D_ScaleTurbulence`` (standard deviation method): scale each component, in place, so that its standard
    deviation over time at the grid centre (1-based ``(n + 1) // 2`` in y and z) is ``sigma`` [m/s]."""
    nt, nz, ny, _ = grid.shape
    centre = grid[:, (nz + 1) // 2 - 1, (ny + 1) // 2 - 1, :].astype(np.float64)
    total = np.cumsum(centre, axis=0)[-1]                   # sequential sums, as the Fortran loop
    total2 = np.cumsum(centre * centre, axis=0)[-1]
    mean = total / nt
    actual = np.sqrt(np.abs(total2 / nt - mean * mean))
    factors = np.empty(3)
    for c in range(3):
        if abs(actual[c]) <= max(abs(actual[c]), 1.0) * _EQUAL_TOL:          # EqualRealNos(σ, 0)
            if abs(sigma[c]) > max(abs(sigma[c]), 1.0) * _EQUAL_TOL:
                raise WindInputError(f"{where}: component {'uvw'[c]} is constant at the grid centre (standard "
                                     f"deviation 0) but the summary asks for {sigma[c]:g} m/s; InflowWind stops. Use "
                                     "another box or a zero TI.")
            factors[c] = 0.0
        else:
            factors[c] = sigma[c] / actual[c]
    block = max(1, _BLOCK_BYTES // (8 * grid[0].size))
    for i in range(0, nt, block):
        grid[i:i + block] = grid[i:i + block].astype(np.float64) * factors


# ---------------------------------------------------------------------------------------------- public readers
def read_bladed_wnd(path: str | Path, *, tower_file: bool = False, propagation_direction: float = 0.0,
                    upflow_angle: float = 0.0) -> FullFieldWind:
    """Read TurbSim's Bladed-style box ``<root>.wnd`` with ``<root>.sum`` (and ``.twr``): InflowWind ``WindType = 4``.

    Parameters
    ----------
    path : str or Path
        The ``.wnd`` file (InflowWind's ``FileNameRoot`` + ``.wnd``); the summary is ``<root>.sum`` beside it.
    tower_file : bool, optional, keyword-only
        InflowWind's ``TowerFile``: read the tower points of ``<root>.twr`` (it must exist).
    propagation_direction, upflow_angle : float, optional, keyword-only
        InflowWind's ``PropagationDir`` and ``VFlowAng`` [rad].

    Returns
    -------
    FullFieldWind
        float32 velocities [m/s]; periodic as the summary says; reference height = the summary's hub height.

    Raises
    ------
    OpenFASTFormatError
        Missing box, summary or (with ``tower_file``) tower file; a wrong identifier or header; a truncated box;
        summary and box mean speeds more than 0.1 m/s apart; a tower file not matching the box. Names the file.

    Examples
    --------
    >>> from mbsym.wind.inflow.bladed import read_bladed_wnd
    >>> field = read_bladed_wnd("tower_periodic.wnd", tower_file=True)  # doctest: +SKIP
    >>> field.n_y, field.n_z, field.n_t, field.n_tower, field.periodic  # doctest: +SKIP
    (5, 15, 200, 3, True)
    """
    p = Path(path)
    if not p.is_file():
        raise OpenFASTFormatError(f"Bladed-style wind file not found: tried '{p.absolute()}' (InflowWind's "
                                  "FileNameRoot + '.wnd'). Check the path.")
    h = _read_header(p)
    root = p.with_suffix("")
    summary = _read_turbsim_summary(root.with_name(root.name + ".sum"))
    ti = list(summary["ti"])
    if h.ti is not None:                                   # the box's own TIs, where positive (TurbType 4)
        ti = [b if b > 0 else s for b, s in zip(h.ti, ti)]
    mean = h.mean_speed
    if not (math.isfinite(mean) and mean > 0.0):
        raise _fail(p, f"the box's mean wind speed is {mean:g} m/s", "It must be positive.")
    if abs(summary["ubar"] - mean) > 0.1:
        raise _fail(p, f"its mean wind speed {mean:g} m/s differs from UBar = {summary['ubar']:g} m/s of "
                    f"{root.name}.sum by more than 0.1 m/s (InflowWind stops: incompatible files)",
                    "Use the .sum TurbSim wrote together with this .wnd.")
    dt = h.dx / mean
    z_half = 0.5 * h.dz * (h.nz - 1)
    bottom = (summary["hub_height"] - summary["z_offset"]) - z_half
    if bottom < 0.0:
        warnings.warn(f"{p}: the grid bottom is at {bottom:g} m, below the ground; the wind there is 0 "
                      "(as InflowWind warns).", stacklevel=2)
    n_steps = _step_count(p, h)
    scale = np.array([0.001 * mean * t / 100.0 for t in ti])
    if summary["lhr"]:
        scale[1] = -scale[1]
    grid = _decode_grid(p, h, n_steps, scale, np.array([mean, 0.0, 0.0]), summary["clockwise"])
    tower = None
    if tower_file:
        tower = _read_tower(root.with_name(root.name + ".twr"), p, h, n_steps, mean, dt, bottom)
    kind = BLADED_TURB_TYPES.get(h.turb_type, "old-style") if h.turb_type else f"old-style ({h.file_id})"
    return FullFieldWind(grid, dy=h.dy, dz=h.dz, dt=dt, mean_speed=mean, reference_height=summary["hub_height"],
                         grid_bottom=bottom, tower=tower, periodic=summary["periodic"],
                         propagation_direction=propagation_direction, upflow_angle=upflow_angle, source=str(p),
                         description=f"Bladed-style box ({kind}) with {root.name}.sum"
                         + (", clockwise" if summary["clockwise"] else ""))


def read_bladed_native(path: str | Path) -> FullFieldWind:
    """Read a native Bladed summary and the box it names: InflowWind ``WindType = 7``.

    The summary (what InflowWind's ``FileNameRoot`` names for type 7) holds, after ``!``, ``#``, ``%`` comments and
    blank lines are dropped, one ``KEY value`` per line in this order: ``UBAR`` [m/s] (mean and advection speed),
    ``REFHT`` [m] (grid centre and profile reference), ``TI``, ``TI_V``, ``TI_W`` [-] (target standard deviations
    ``TI UBAR`` at the grid centre), ``WDIR``, ``FLINC`` [rad] (propagation direction and upflow), ``WINDF`` (the box,
    relative to the summary's folder), ``WSHEAR`` [-] (power-law exponent), then optionally ``VLINSHEAR``,
    ``HLINSHEAR`` [-], ``REFLENGTH`` [m] (linear shears) and ``XOffset`` [m] (``InitXPosition``).

    Parameters
    ----------
    path : str or Path
        The native Bladed summary file.

    Returns
    -------
    FullFieldWind
        Periodic, interpolated to zero at the ground below the grid, the power-law mean added after interpolation
        (:class:`~mbsym.wind.inflow.profile.MeanProfile`), ``x_offset = XOffset`` and the summary's angles.

    Raises
    ------
    OpenFASTFormatError
        A missing or malformed summary or box (names the file and line).
    WindInputError
        Values InflowWind refuses (``REFHT <= 0``, negative TIs, linear shears without ``REFLENGTH``, a component
        constant at the grid centre with a non-zero target); ``UBAR <= 0``.
    """
    p = Path(path)
    s = _read_native_summary(p)
    box = Path(s["WINDF"])
    if not box.is_absolute():
        box = p.parent / box
    if not box.is_file():
        raise OpenFASTFormatError(f"{p}: WINDF names the box '{s['WINDF']}', not found: tried '{box.absolute()}' "
                                  "(a relative name is relative to the summary's folder).")
    ubar, ref_height = s["UBAR"], s["REFHT"]
    sigma = np.array([s["TI"], s["TI_V"], s["TI_W"]]) * ubar
    bad = []
    if not ubar > 0.0:
        bad.append(f"UBAR = {ubar:g} m/s (must be > 0: it carries the box past the rotor)")
    if ref_height < 0.0 or abs(ref_height) <= _EQUAL_TOL:
        bad.append(f"REFHT = {ref_height:g} m (must be > 0)")
    if np.any(sigma < 0.0):
        bad.append(f"TI, TI_V, TI_W = {s['TI']:g}, {s['TI_V']:g}, {s['TI_W']:g} (must not be negative)")
    shears = s.get("VLINSHEAR", 0.0) != 0.0 or s.get("HLINSHEAR", 0.0) != 0.0
    if shears and not s.get("REFLENGTH", 0.0) > _EQUAL_TOL:
        bad.append(f"REFLENGTH = {s.get('REFLENGTH', 0.0):g} m with linear shears (must be > 0)")
    if bad:
        raise WindInputError(f"{p}: " + "; ".join(bad) + ". Fix the native Bladed summary.")
    h = _read_header(box)
    dt = h.dx / ubar
    bottom = ref_height - 0.5 * h.dz * (h.nz - 1)
    n_steps = _step_count(box, h)
    grid = _decode_grid(box, h, n_steps, np.array([0.001, -0.001, 0.001]), np.zeros(3), clockwise=False)
    _scale_to_sigma(grid, sigma, f"{p} (box {box.name})")
    d2r, r2d = math.pi / 180.0, 180.0 / math.pi          # InflowWind: R2D (summary), then D2R and MPi2Pi
    direction = math.fmod(d2r * (r2d * s["WDIR"]), 2.0 * math.pi)          # Fortran MODULO(a, 2 pi) ...
    direction = direction + 2.0 * math.pi if direction < 0.0 else direction
    direction = direction - 2.0 * math.pi if direction > math.pi else direction   # ... then into (-pi, pi]
    profile = MeanProfile(kind=2, speed=ubar, reference_height=ref_height, exponent=s["WSHEAR"],
                          vertical_linear_shear=s.get("VLINSHEAR", 0.0),
                          horizontal_linear_shear=s.get("HLINSHEAR", 0.0), reference_length=s.get("REFLENGTH", 0.0))
    kind = BLADED_TURB_TYPES.get(h.turb_type, "") if h.turb_type else f"old-style ({h.file_id})"
    return FullFieldWind(grid, dy=h.dy, dz=h.dz, dt=dt, mean_speed=ubar, reference_height=ref_height,
                         grid_bottom=bottom, periodic=True, propagation_direction=direction,
                         upflow_angle=d2r * (r2d * s["FLINC"]), interpolate_to_ground=True, source=str(p),
                         description=f"native Bladed box {box.name} ({kind})", mean_profile=profile,
                         x_offset=s.get("XOFFSET", 0.0))
