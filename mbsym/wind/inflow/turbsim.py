"""TurbSim binary full-field wind files (``.bts``): read (and write, for tests and tools).

Layout (little-endian, as TurbSim writes it and InflowWind's ``IfW_TurbSim_Init`` reads it;
OpenFAST v5.0.0 ``modules/inflowwind/src/InflowWind_IO.f90`` and
``modules/turbsim/src/TS_FileIO.f90``):

==========================  ===========  ====================================================
field                       type         meaning
==========================  ===========  ====================================================
FileID                      int16        7: not periodic, 8: periodic
NZ, NY, NTwr, NSteps        4 x int32    grid points vertically, laterally, tower points, steps
dz, dy, dt                  3 x float32  spacing [m], [m], time step [s]
MeanWS, RefHt, GridBase     3 x float32  URef [m/s], reference (hub) height [m], grid bottom [m]
slope/offset u, v, w        6 x float32  ``velocity = (int16 - offset) / slope`` per component
DescLen, description        int32, text  free text
then per time step          int16        grid ``(NZ, NY, 3)`` (component fastest, then y,
                                         then z, bottom row first), then tower ``(NTwr, 3)``
==========================  ===========  ====================================================

The grid spans ``y`` in ``[-(NY-1) dy/2, +(NY-1) dy/2]`` (centred on the tower) and ``z`` from
``GridBase`` up by ``dz``; tower point ``k`` (0-based) is at ``GridBase - k dz``.

Velocities are decoded in float32 exactly as InflowWind does (``(real(raw, SiKi) - offset) /
slope`` in single precision), so the stored numbers are InflowWind's, bit for bit.

Memory: the grid is kept as float32 (4 bytes per value, twice the int16 file) and nothing
float64 of the whole field is ever made; decoding runs over blocks of time steps (4 MB) of a
memory map of the file. Measured for ``ff14.bts`` (25 x 25 grid, 13400 steps of 0.05 s = 670 s,
50.25 MB on disk): the field holds 100.5 MB (``FullFieldWind.nbytes``); reading allocates at most
117 MB (``tracemalloc`` peak: the field plus one decoding block and its finiteness check) while the
50 MB file is mapped (maximum resident size +164 MB during the read), and takes 0.25 s with the file
in the page cache (0.8 s cold).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ...exceptions import OpenFASTFormatError
from .field import FullFieldWind

__all__ = ["read_turbsim_bts", "write_turbsim_bts", "TURBSIM_FILE_IDS"]

#: TurbSim file identifiers: 7 = not periodic, 8 = periodic (TS_FileIO.f90, InflowWind_IO.f90).
TURBSIM_FILE_IDS = {7: False, 8: True}
_HEADER = np.dtype([("file_id", "<i2"), ("nz", "<i4"), ("ny", "<i4"), ("ntwr", "<i4"), ("nt", "<i4"),
                    ("dz", "<f4"), ("dy", "<f4"), ("dt", "<f4"), ("mws", "<f4"), ("ref_height", "<f4"),
                    ("grid_base", "<f4"), ("scale", "<f4", (6,)), ("desc_len", "<i4")])
_BLOCK_BYTES = 4 << 20          # decode 4 MB of int16 at a time


def _fail(path: Path, what: str, fix: str) -> OpenFASTFormatError:
    return OpenFASTFormatError(f"{path}: {what}. {fix}")


def _header(path: Path, raw: bytes) -> dict:
    if len(raw) < _HEADER.itemsize:
        raise _fail(path, f"the file has {len(raw)} bytes, fewer than the {_HEADER.itemsize}-byte header of a "
                    "TurbSim binary full-field file", "Check that it is a complete .bts file.")
    h = np.frombuffer(raw[:_HEADER.itemsize], dtype=_HEADER)[0]
    fid = int(h["file_id"])
    if fid not in TURBSIM_FILE_IDS:
        raise _fail(path, f"file identifier (first int16) is {fid}; a TurbSim .bts file has 7 (not periodic) or "
                    "8 (periodic)", "Check that it is a TurbSim binary full-field file (WindType = 3).")
    out = {k: int(h[k]) for k in ("nz", "ny", "ntwr", "nt", "desc_len")}
    out.update({k: float(h[k]) for k in ("dz", "dy", "dt", "mws", "ref_height", "grid_base")})
    out["scale"] = np.array(h["scale"], dtype=np.float32)
    out["periodic"] = TURBSIM_FILE_IDS[fid]
    problems = [f"{k} = {out[k]}" for k in ("nz", "ny", "nt") if out[k] < 2]
    problems += [f"{k} = {out[k]}" for k in ("ntwr", "desc_len") if out[k] < 0]
    problems += [f"{k} = {out[k]:g}" for k in ("dz", "dy", "dt", "mws")
                 if not (math.isfinite(out[k]) and out[k] > 0.0)]
    problems += [f"{k} = {out[k]:g}" for k in ("ref_height", "grid_base") if not math.isfinite(out[k])]
    slopes = out["scale"][0::2]
    if not (np.all(np.isfinite(out["scale"])) and np.all(slopes != 0.0)):
        problems.append(f"scaling slope/offset = {out['scale'].tolist()}")
    if problems:
        raise _fail(path, "invalid header: " + ", ".join(problems) + " (expected at least 2 grid points "
                    "and time steps, positive spacings and mean speed, finite non-zero scaling slopes)",
                    "The file is not a valid TurbSim .bts file or is corrupted.")
    return out


def read_turbsim_bts(path, *, propagation_direction: float = 0.0, upflow_angle: float = 0.0) -> FullFieldWind:
    """Read a TurbSim binary full-field file (``.bts``; InflowWind ``WindType = 3``).

    Parameters
    ----------
    path : str or Path
        The ``.bts`` file.
    propagation_direction, upflow_angle : float, optional, keyword-only
        InflowWind's ``PropagationDir`` and ``VFlowAng`` [rad] (see :class:`FullFieldWind`).

    Returns
    -------
    FullFieldWind
        The field (float32 velocities, see the module docstring for the memory it takes).

    Raises
    ------
    OpenFASTFormatError
        Missing file, a wrong file identifier, an invalid header, a file shorter or longer than
        its header says; names the file.

    Examples
    --------
    >>> from mbsym.wind.inflow import read_turbsim_bts
    >>> field = read_turbsim_bts("ff14.bts")  # doctest: +SKIP
    >>> field.n_y, field.n_z, field.n_t, field.periodic  # doctest: +SKIP
    (25, 25, 13400, False)
    """
    p = Path(path)
    if not p.is_file():
        raise OpenFASTFormatError(f"TurbSim full-field file not found: tried '{p.absolute()}'. Check the path.")
    size = p.stat().st_size
    with p.open("rb") as fh:
        head = fh.read(_HEADER.itemsize)
    h = _header(p, head)
    start = _HEADER.itemsize + h["desc_len"]
    per_step = 3 * (h["ny"] * h["nz"] + h["ntwr"])
    expected = start + 2 * per_step * h["nt"]
    if size != expected:
        short = size < expected
        raise _fail(p, f"the header announces {h['nt']} time steps of a {h['ny']} x {h['nz']} grid with "
                    f"{h['ntwr']} tower points ({expected} bytes in all) but the file has {size} bytes "
                    f"({'truncated' if short else 'extra bytes at the end'})",
                    "Regenerate or copy the file again." if short else "Remove the extra bytes or regenerate it.")
    with p.open("rb") as fh:
        fh.seek(_HEADER.itemsize)
        description = fh.read(h["desc_len"]).decode("latin-1").strip()
    raw = np.memmap(p, dtype="<i2", mode="r", offset=start, shape=(h["nt"], per_step))
    grid, tower = _decode(raw, h)
    del raw
    return FullFieldWind(grid, dy=h["dy"], dz=h["dz"], dt=h["dt"], mean_speed=h["mws"],
                         reference_height=h["ref_height"], grid_bottom=h["grid_base"], tower=tower,
                         periodic=h["periodic"], propagation_direction=propagation_direction,
                         upflow_angle=upflow_angle, source=str(p), description=description)


def _decode(raw: np.ndarray, h: dict) -> tuple[np.ndarray, np.ndarray | None]:
    """float32 grid (nt, nz, ny, 3) and tower (nt, ntwr, 3) from the int16 records, block by block."""
    nt, nz, ny, ntwr = h["nt"], h["nz"], h["ny"], h["ntwr"]
    slope, offset = h["scale"][0::2], h["scale"][1::2]         # float32, as InflowWind's SiKi arithmetic
    n_grid = 3 * ny * nz
    grid = np.empty((nt, nz, ny, 3), dtype=np.float32)
    tower = np.empty((nt, ntwr, 3), dtype=np.float32) if ntwr > 0 else None
    block = max(1, _BLOCK_BYTES // (2 * raw.shape[1]))
    for i in range(0, nt, block):
        chunk = np.asarray(raw[i:i + block])
        g = chunk[:, :n_grid].reshape(-1, nz, ny, 3).astype(np.float32)
        np.subtract(g, offset, out=g)
        np.divide(g, slope, out=grid[i:i + block])
        if tower is not None:
            w = chunk[:, n_grid:].reshape(-1, ntwr, 3).astype(np.float32)
            np.subtract(w, offset, out=w)
            np.divide(w, slope, out=tower[i:i + block])
    return grid, tower


def write_turbsim_bts(path, field: FullFieldWind, *, description: str = "written by mbsym") -> Path:
    """Write ``field`` as a TurbSim ``.bts`` file (int16 with per-component scaling, as TurbSim does).

    The scaling follows TurbSim (``TS_FileIO.f90``: the int16 range spans each component's range
    with a margin), so values come back within half a quantisation step, ``range / 64000`` [m/s]
    per component. ``field.propagation_direction``/``upflow_angle`` are not stored (the InflowWind
    file carries them).

    Returns
    -------
    Path
        The file written.
    """
    if not isinstance(field, FullFieldWind):
        raise TypeError(f"field must be a FullFieldWind; got {type(field).__name__}.")
    grid, tower = field.grid, field.tower
    parts = [grid.reshape(field.n_t, -1, 3)] + ([tower] if tower is not None else [])
    lo = np.min([np.min(a, axis=(0, 1)) for a in parts], axis=0).astype(np.float64)
    hi = np.max([np.max(a, axis=(0, 1)) for a in parts], axis=0).astype(np.float64)
    span = np.maximum(hi - lo, 1e-6)
    slope = (64000.0 / span).astype(np.float32)                     # int16 range with margin
    offset = (-32000.0 - lo * slope.astype(np.float64)).astype(np.float32)
    text = description.encode("latin-1", errors="replace")
    n_twr = 0 if tower is None else tower.shape[1]
    header = np.zeros((), dtype=_HEADER)
    header["file_id"] = 8 if field.periodic else 7
    header["nz"], header["ny"], header["ntwr"], header["nt"] = field.n_z, field.n_y, n_twr, field.n_t
    header["dz"], header["dy"], header["dt"] = field.dz, field.dy, field.dt
    header["mws"], header["ref_height"], header["grid_base"] = field.mean_speed, field.reference_height, field.grid_bottom
    header["scale"] = np.column_stack([slope, offset]).reshape(-1)
    header["desc_len"] = len(text)
    out = Path(path)
    with out.open("wb") as fh:
        fh.write(header.tobytes())
        fh.write(text)
        for i in range(field.n_t):
            rows = [grid[i].reshape(-1, 3)] + ([tower[i]] if tower is not None else [])
            v = np.concatenate(rows).astype(np.float64)
            fh.write(np.rint(v * slope + offset).clip(-32768, 32767).astype("<i2").tobytes())
    return out
