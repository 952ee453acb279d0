"""A :class:`~mbsym.wind.inflow.field.FullFieldWind` inside CasADi graphs: a generated C External.

:func:`full_field_function` returns ``name(t [1x1, s], xyz [3 x n, m, ground axes]) -> uvw [3 x n, m/s]``:

- **compiled** (a C compiler is found and ``MBSYM_NO_COMPILE`` is not set): C generated for this field
  (dimensions, spacing, time step, offsets, rotation baked in as constants) that repeats
  :meth:`FullFieldWind.velocity` operation for operation. The velocities are written once as a raw
  float32 file ``<cache>/fullfield/<data hash>.f32`` (the grid ``(n_t, n_z, n_y, 3)``, then the tower
  ``(n_t, n_tower, 3)``, C order) and memory-mapped by the C code on its first call (shared by every
  process and every Function of the same field). The library is cached as
  ``<cache>/fullfield/<name>_<key>.so`` and loaded with ``casadi.external(name, lib, {"enable_fd": True})``.
  The C source is registered with :func:`mbsym.codegen.register_c_source`, so a Function that calls this
  External and is compiled by :func:`mbsym.codegen.compile_function` gets it compiled into the same library.
  A missing or wrong-sized data file, or a point where InflowWind stops (see the field module), make the
  call return non-zero: CasADi raises ``RuntimeError`` ("Evaluation failed"), the C code prints the point
  and time to stderr.
- **fallback**: a ``casadi.Callback`` that calls :meth:`FullFieldWind.velocity` (same numbers; not usable
  by code generation), with a :class:`~mbsym.codegen.CompilationWarning` unless ``MBSYM_NO_COMPILE`` is set.

Derivatives are finite differences (``enable_fd``): the field is piecewise linear in space and time.
The name is ``ffwind_<20 hex digits of the content hash>_<n>``.

Measured (this machine kind, gcc -O1, ff14, 51 rotor-like points marching in time): 3.6-6.3 µs per call of
the External inside a compiled loop (best of 5 over 20000 calls, depending on the load of the 2 cores); a
call from Python costs ~60 µs (CasADi's argument conversion), :meth:`FullFieldWind.velocity` ~0.7 ms (the
Callback fallback costs that plus the call). Preparing the External the first time takes ~1.1 s (content
hash 0.2 s, writing the 100.5 MB data file, generating and compiling the C ~0.5 s); a library in the cache
loads in milliseconds after the hash.
"""

from __future__ import annotations

import os
import warnings
from pathlib import Path

import casadi as ca
import numpy as np

from ... import codegen
from ...exceptions import DimensionError
from .field import GRID_TOLERANCE, FullFieldWind, rotation_to_wind

__all__ = ["full_field_function", "full_field_c_source", "FULL_FIELD_C_VERSION"]

#: Version of the generated C (part of the library's cache key).
FULL_FIELD_C_VERSION = "2"
_FUNCTIONS: dict[tuple, ca.Function] = {}       # keeps Callbacks alive and reuses loaded libraries


def _folder() -> Path:
    return codegen.cache_dir() / "fullfield"


def function_name(field: FullFieldWind, n_points: int) -> str:
    """The Function (and C symbol) name of ``field`` evaluated at ``n_points`` points."""
    return f"ffwind_{field.content_hash[:20]}_{n_points}"


def full_field_function(field: FullFieldWind, n_points: int) -> ca.Function:
    """See the module docstring; ``FullFieldWind.casadi_function`` calls this."""
    if isinstance(n_points, bool) or not isinstance(n_points, (int, np.integer)) or n_points < 1:
        raise DimensionError(f"n_points must be a positive integer; got {n_points!r}.")
    n_points = int(n_points)
    name = function_name(field, n_points)
    cc = None if codegen.compile_disabled() else codegen.compiler_command()
    memo = (name, cc, str(codegen.cache_dir()), codegen.compile_disabled())
    known = _FUNCTIONS.get(memo)
    if known is not None:
        return known
    if codegen.compile_disabled():
        f = _callback(field, n_points, name)
    else:
        f = _callback(field, n_points, name, warn="No C compiler found (set MBSYM_CC or CC, or install gcc).") \
            if cc is None else _external(field, n_points, name, cc)
    _FUNCTIONS[memo] = f
    return f


def _external(field: FullFieldWind, n_points: int, name: str, cc: tuple[str, ...]) -> ca.Function:
    import hashlib
    import subprocess
    import tempfile

    folder = _folder()
    folder.mkdir(parents=True, exist_ok=True)
    data = _data_file(field, folder)
    source = folder / f"{name}.c"
    text = full_field_c_source(field, n_points, name, data)
    if not source.is_file() or source.read_text() != text:
        _atomic_write(source, text.encode())
    flags = tuple(codegen.DEFAULT_FLAGS)
    key = hashlib.sha256("\0".join([text, *cc, *flags, ca.__version__]).encode()).hexdigest()[:16]
    library = folder / f"{name}_{key}.so"
    codegen.register_c_source(name, source)
    if not library.is_file():
        with tempfile.TemporaryDirectory(prefix="mbsym_ff_", dir=folder) as tmp:
            out = Path(tmp) / library.name
            proc = subprocess.run([*cc, *flags, "-shared", "-fPIC", "-o", str(out), str(source), "-lm"],
                                  capture_output=True, text=True, timeout=codegen.COMPILE_TIMEOUT_S)
            if proc.returncode != 0:
                return _callback(field, n_points, name, warn=f"Compiling {source} failed: {proc.stderr[-300:]}")
            os.replace(out, library)
    try:
        return ca.external(name, str(library), {"enable_fd": True})
    except RuntimeError as exc:
        library.unlink(missing_ok=True)
        return _callback(field, n_points, name, warn=f"Loading {library} failed: {exc}")


def _data_file(field: FullFieldWind, folder: Path) -> Path:
    """The float32 data file of ``field`` (written once, atomically)."""
    path = folder / f"{field.data_hash}.f32"
    if path.is_file() and path.stat().st_size == field.nbytes:
        return path
    import tempfile

    fd, tmp = tempfile.mkstemp(dir=folder, prefix=".ff_", suffix=".f32")
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(memoryview(field.grid).cast("B"))
            if field.tower is not None:
                fh.write(memoryview(field.tower).cast("B"))
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)
    return path


def _atomic_write(path: Path, data: bytes) -> None:
    import tempfile

    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=".src_", suffix=path.suffix)
    with os.fdopen(fd, "wb") as fh:
        fh.write(data)
    os.replace(tmp, path)


def _c_string(text: str) -> str:
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'


def full_field_c_source(field: FullFieldWind, n_points: int, name: str, data_path: Path) -> str:
    """The C source of the External (CasADi's external-function API; no CasADi header needed)."""
    rot = rotation_to_wind(field.propagation_direction, field.upflow_angle)
    consts = {
        "NT": field.n_t, "NZ": field.n_z, "NY": field.n_y, "NTWR": field.n_tower, "NP": n_points,
        "PERIODIC": int(field.periodic), "GROUND": int(field.interpolate_to_ground), "ROTATED": int(field.rotated),
    }
    reals = {
        "DT": field.dt, "DY": field.dy, "DZ": field.dz, "MWS": field.mean_speed, "X0": field.initial_x,
        "YHW": field.half_width, "ZBASE": field.grid_bottom, "REFZ": field.reference_height, "TOL": GRID_TOLERANCE,
    }
    lines = [f"#define {k} {v}LL" for k, v in consts.items()] + [f"#define {k} {float(v)!r}" for k, v in reals.items()]
    profile = field.mean_profile
    lines.append(f"#define PROFILE {int(profile is not None)}")
    lines.append(profile.c_source() if profile is not None else "static double mean_profile(double y, double z) "
                 "{ (void)y; (void)z; return 0.0; }")
    lines.append("static const double ROT[9] = {" + ", ".join(repr(float(v)) for v in rot.reshape(-1)) + "};")
    lines.append(f"#define DATA_PATH {_c_string(str(data_path))}")
    lines.append(f"#define DATA_BYTES {field.nbytes}LL")
    sparsity = [3, n_points] + [3 * j for j in range(n_points + 1)] + [0, 1, 2] * n_points
    lines.append("static const casadi_int SP_XYZ[] = {" + ", ".join(map(str, sparsity)) + "};")
    cubic = _CUBIC_TIME if field.cubic else ""          # linear: the source of before, byte for byte
    return _C_TEMPLATE.replace("@CONSTANTS@", "\n".join(lines)).replace("@NAME@", name).replace("@CUBIC@", cubic)


#: VelInterpCubic: InflowWind's Hermite step between the two slices, zero slopes (mbsym/wind/inflow/cubic.py).
_CUBIC_TIME = r"""
  { double s = (xt + 1.0) / 2.0; xt = 2.0 * (-2.0 * s * s * s + 3.0 * s * s) - 1.0; }"""


_C_TEMPLATE = r"""/* Full-field wind evaluated as OpenFAST v5 InflowWind (Grid3D, linear): generated by mbsym
   (mbsym/wind/inflow/field_casadi.py); the same operations as FullFieldWind.velocity. */
#include <math.h>
#include <stdio.h>
#include <fcntl.h>
#include <unistd.h>
#include <sys/mman.h>
#include <sys/stat.h>

typedef double casadi_real;
typedef long long int casadi_int;

@CONSTANTS@

static const casadi_int SP_T[] = {1, 1, 0, 1, 0};
static const float* grid_data = 0;
static const float* tower_data = 0;

static int load_data(void) {
  struct stat st;
  void* mem;
  int fd;
  if (grid_data) return 0;
  fd = open(DATA_PATH, O_RDONLY);
  if (fd < 0) { fprintf(stderr, "@NAME@: wind field data file %s cannot be opened\n", DATA_PATH); return 1; }
  if (fstat(fd, &st) != 0 || (long long)st.st_size != DATA_BYTES) {
    fprintf(stderr, "@NAME@: wind field data file %s has the wrong size (expected %lld bytes)\n", DATA_PATH,
            (long long)DATA_BYTES);
    close(fd);
    return 1;
  }
  mem = mmap(0, (size_t)DATA_BYTES, PROT_READ, MAP_SHARED, fd, 0);
  close(fd);
  if (mem == MAP_FAILED) { fprintf(stderr, "@NAME@: cannot map %s\n", DATA_PATH); return 1; }
  tower_data = (const float*)mem + (size_t)NT * NZ * NY * 3;
  grid_data = (const float*)mem;
  return 0;
}

static const float* g_at(long long it, long long iz, long long iy) {  /* 1-based indices */
  return grid_data + (((size_t)(it - 1) * NZ + (size_t)(iz - 1)) * NY + (size_t)(iy - 1)) * 3;
}

static const float* w_at(long long it, long long iz) {
  return tower_data + ((size_t)(it - 1) * NTWR + (size_t)(iz - 1)) * 3;
}

static double modulo(double a, double p) { return a - floor(a / p) * p; }

/* Returns 0, or 1 time exhausted, 2 below the grid, 3 above, 4 beside. */
static int point_velocity(double t, const double* pg, double* out) {
  double p[3], v[3] = {0.0, 0.0, 0.0};
  double tg, xt, zg, xz, yg, xy;
  long long tl, th, zl, zh, yl, yh;
  int k, c, tower = 0, ground = 0;
  if (ROTATED) {
    double d[3] = {pg[0], pg[1], pg[2] - REFZ};
    for (k = 0; k < 3; ++k) p[k] = ROT[3 * k] * d[0] + ROT[3 * k + 1] * d[1] + ROT[3 * k + 2] * d[2];
    p[2] += REFZ;
  } else {
    p[0] = pg[0]; p[1] = pg[1]; p[2] = pg[2];
  }
  if (!(p[2] > 0.0)) { out[0] = out[1] = out[2] = 0.0; return 0; }
  /* time (GetBoundsT) */
  tg = (t + (X0 - p[0]) * (1.0 / MWS)) * (1.0 / DT);
  if (PERIODIC) tg = modulo(modulo(tg, (double)NT), (double)NT);
  tl = (long long)floor(tg) + 1;
  th = tl + 1;
  xt = 2.0 * (tg - trunc(tg)) - 1.0;
  if (tl >= 1 && th <= NT) {
  } else if (tl == NT) {
    if (PERIODIC) th = 1;
    else if (xt <= TOL) { th = tl; xt = -1.0; }
    else { tl = NT - 1; th = NT; }
  } else return 1;@CUBIC@
  /* height (GetBoundsZ) */
  zg = (p[2] - ZBASE) * (1.0 / DZ) + 1.0;
  zl = (long long)floor(zg);
  zh = zl + 1;
  xz = zg - trunc(zg);
  if (zl >= 1 && zh <= NZ) {
    xz = 2.0 * xz - 1.0;
  } else if (zl < 1) {
    if (zl == 0 && xz >= 1.0 - TOL) { zl = 1; zh = 2; xz = -1.0; }
    else if (GROUND) { ground = 1; zl = 0; zh = 1; xz = 2.0 * (p[2] / ZBASE) - 1.0; }
    else if (NTWR > 0) {
      tower = 1;
      zl = (long long)trunc(-(zg - 1.0)) + 1;
      if (zl >= NTWR) { zl = NTWR; xz = 1.0 - 2.0 * (p[2] / (ZBASE - (NTWR - 1) / (1.0 / DZ))); }
      else xz = 2.0 * ((double)(2 - zl) - zg) - 1.0;
      zh = zl + 1;
    } else return 2;
  } else {
    if (zh == NZ + 1 && xz <= TOL) { zl = NZ - 1; zh = NZ; xz = 1.0; }
    else return 3;
  }
  if (tower) {
    double w1 = (1.0 - xz) * (1.0 - xt) / 4.0, w2 = (1.0 + xz) * (1.0 - xt) / 4.0;
    double w3 = (1.0 - xz) * (1.0 + xt) / 4.0, w4 = (1.0 + xz) * (1.0 + xt) / 4.0;
    const float *c1 = w_at(tl, zl), *c3 = w_at(th, zl);
    for (c = 0; c < 3; ++c) {
      double c2 = zh > NTWR ? 0.0 : (double)w_at(tl, zh)[c];
      double c4 = zh > NTWR ? 0.0 : (double)w_at(th, zh)[c];
      v[c] = (double)c1[c] * w1 + c2 * w2 + (double)c3[c] * w3 + c4 * w4;
    }
  } else {
    /* lateral (GetBoundsY) */
    double ny[2], nz[2], nt[2];
    yg = (p[1] + YHW) * (1.0 / DY) + 1.0;
    yl = (long long)floor(yg);
    yh = yl + 1;
    xy = yg - trunc(yg);
    if (yl >= 1 && yh <= NY) xy = 2.0 * xy - 1.0;
    else if (yl == 0 && xy >= 1.0 - TOL) { yl = 1; yh = 2; xy = -1.0; }
    else if (yl == NY && xy <= TOL) { yl = NY - 1; yh = NY; xy = 1.0; }
    else return 4;
    ny[0] = 1.0 - xy; ny[1] = 1.0 + xy;
    nz[0] = 1.0 - xz; nz[1] = 1.0 + xz;
    nt[0] = (1.0 - xt) / 8.0; nt[1] = (1.0 + xt) / 8.0;
    for (k = 0; k < 8; ++k) {
      long long it = (k >> 2) ? th : tl, iz = ((k >> 1) & 1) ? zh : zl, iy = (k & 1) ? yh : yl;
      double w = ny[k & 1] * nz[(k >> 1) & 1] * nt[k >> 2];
      if (ground && iz == 0) continue;   /* the ground: zero velocity */
      {
        const float* cell = g_at(it, ground ? 1 : iz, iy);
        for (c = 0; c < 3; ++c) v[c] += (double)cell[c] * w;
      }
    }
  }
  if (PROFILE) v[0] += mean_profile(p[1], p[2]);   /* InflowWind's AddMeanAfterInterp */
  if (ROTATED) {
    for (k = 0; k < 3; ++k) out[k] = ROT[k] * v[0] + ROT[3 + k] * v[1] + ROT[6 + k] * v[2];
  } else {
    out[0] = v[0]; out[1] = v[1]; out[2] = v[2];
  }
  return 0;
}

int @NAME@(const casadi_real** arg, casadi_real** res, casadi_int* iw, casadi_real* w, int mem) {
  static const char* what[] = {"", "time outside the field", "below the grid without tower points",
                               "above the grid", "beside the grid"};
  const double zero[3] = {0.0, 0.0, 0.0};
  double t = arg[0] ? arg[0][0] : 0.0;
  casadi_int j;
  (void)iw; (void)w; (void)mem;
  if (!res[0]) return 0;
  if (load_data()) return 1;
  for (j = 0; j < NP; ++j) {
    const double* pj = arg[1] ? arg[1] + 3 * j : zero;
    int code = point_velocity(t, pj, res[0] + 3 * j);
    if (code) {
      fprintf(stderr, "@NAME@: InflowWind stops at point %lld (%g, %g, %g) m, t = %g s: %s\n", (long long)j,
              pj[0], pj[1], pj[2], t, what[code]);
      return 1;
    }
  }
  return 0;
}

casadi_int @NAME@_n_in(void) { return 2; }
casadi_int @NAME@_n_out(void) { return 1; }
const char* @NAME@_name_in(casadi_int i) { return i == 0 ? "t" : i == 1 ? "xyz" : 0; }
const char* @NAME@_name_out(casadi_int i) { return i == 0 ? "uvw" : 0; }
const casadi_int* @NAME@_sparsity_in(casadi_int i) { return i == 0 ? SP_T : i == 1 ? SP_XYZ : 0; }
const casadi_int* @NAME@_sparsity_out(casadi_int i) { return i == 0 ? SP_XYZ : 0; }
int @NAME@_work(casadi_int* sz_arg, casadi_int* sz_res, casadi_int* sz_iw, casadi_int* sz_w) {
  if (sz_arg) *sz_arg = 2;
  if (sz_res) *sz_res = 1;
  if (sz_iw) *sz_iw = 0;
  if (sz_w) *sz_w = 0;
  return 0;
}
"""


class _FieldCallback(ca.Callback):
    """The numpy fallback: ``FullFieldWind.velocity`` behind CasADi's Callback interface."""

    def __init__(self, name: str, field: FullFieldWind, n_points: int) -> None:
        ca.Callback.__init__(self)
        self._field, self._n = field, n_points
        self.construct(name, {"enable_fd": True})

    def get_n_in(self):
        return 2

    def get_n_out(self):
        return 1

    def get_name_in(self, i):
        return ("t", "xyz")[i]

    def get_name_out(self, i):
        return "uvw"

    def get_sparsity_in(self, i):
        return ca.Sparsity.dense(1, 1) if i == 0 else ca.Sparsity.dense(3, self._n)

    def get_sparsity_out(self, i):
        return ca.Sparsity.dense(3, self._n)

    def eval(self, arg):
        xyz = np.asarray(arg[1], dtype=float).reshape(3, self._n, order="F")
        v = self._field.velocity(float(arg[0]), xyz.T)
        return [ca.DM(np.ascontiguousarray(v.T))]


def _callback(field: FullFieldWind, n_points: int, name: str, warn: str = "") -> ca.Function:
    if warn:
        warnings.warn(f"{warn} Using a numpy Callback for {name!r} (same results, slower; not code-generated).",
                      codegen.CompilationWarning, stacklevel=4)
    return _FieldCallback(name, field, n_points)
