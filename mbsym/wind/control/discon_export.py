"""Export our baseline controller as a self-contained Bladed-style ``DISCON`` library.

:func:`export_discon` compiles :class:`~.baseline.BaselineController`'s law ``(xc, y) -> (xc_next, u)``
into a shared library that OpenFAST's ServoDyn (or mbsym's own :class:`~.discon.DisconController`)
loads like ROSCO's: C generated from the CasADi graph (``CodeGenerator``) plus a small hand-written
``DISCON`` wrapper (:mod:`._discon_c`), compiled with the system C compiler and linked against
``libm`` only: no Python, numpy or CasADi at run time, fixed (static) memory.

**Swap-array records** (1-based; :mod:`.swap`):

- read: 1 status (0 first call, 1 step, −1 last call), 2 time, 3 communication interval (ServoDyn's
  ``DLL_DT``), 10 pitch actuator type (must be 0: positions), 28 pitch control (must be 1 with IPC),
  49 size of ``avcMSG``, 50 length of ``accINFILE``, 61 number of blades; the measurements
  20 ``GenSpeed`` [rad/s], 21 ``RotSpeed`` [rad/s], 4 ``BldPitch1`` [rad], 15 ``GenPwr`` [W],
  27 ``Wind1VelX`` [m/s] and, with IPC, 30-32 ``RootMyc1..3`` [N m], 60 ``Azimuth`` [rad]; with the
  floating feedback 83 ``NcIMURAys`` [rad/s²] (Fl_Mode 2) or 53, 54 ``YawBrTAxp``, ``YawBrTAyp`` [m/s²]
  and 37 ``NacYaw`` [rad] (Fl_Mode 1);
- written: 42-44 pitch demands per blade [rad] (the collective demand on every blade without IPC),
  45 collective pitch demand (blade 1's with IPC), 47 generator torque demand [N m]; 35 = 1 (generator
  on), 36 = 0 (brake off), 41 = 0 (yaw torque), 46 = 0 (pitch rate), 48 = 0 (yaw rate), 55 = 56 = 0 (no
  pitch or torque override), 65 = 0 (no logging channels). ``avcOUTNAME`` is not touched.

**Sample time and decimation.** The law is compiled for the controller's sample time
``controller.dt`` (its filters' coefficients are constants). The host may call more often: the
communication interval (record 3) must divide the sample time; the law runs at the first call
(status 0) and at every call with ``t ≥ t₀ + k·dt − interval/2``; the calls in between return the
last commands (zero-order hold, as ServoDyn holds a library's commands).

**Input file** (read at status 0): ``value Key ! comment`` lines; ``Controller`` (``baseline``),
``SampleTime`` [s] and ``Fingerprint`` (a hash of the compiled law and its sample time). All three
are checked against the library, so a library is never run with another export's file or at a
sample time it was not built for: every setting of the law (gains, filters, limits, schedules, Cp
table, IPC) is baked into the library; the file only pairs the two and says so.

**Errors** (never a crash of the host): a missing or mismatched input file, a communication interval
that does not divide the sample time, record 10 ≠ 0, IPC without record 28 = 1 or 3 blades, a status
other than 0/1/−1, a step before the first call, a non-finite measurement → ``aviFAIL = -1`` and a
message in ``avcMSG`` (at most record 49 − 1 characters).

Precision: the swap array is single precision. The law computes in double on the float32
measurements and its commands are rounded to float32 when written (a pitch below 0.5 rad to within
1.5e-8 rad = 8.5e-7°, a 43 kN m torque to within 0.002 N m).
"""

from __future__ import annotations

import hashlib
import os
import subprocess
import tempfile
from pathlib import Path

import casadi as ca

from ...exceptions import ControllerError, ExportError
from ._discon_c import WRAPPER
from .baseline import BaselineController
from .settings import BaselineSettings
from .swap import MEASUREMENT_RECORDS

__all__ = ["export_discon", "prepare_export", "EXPORT_FLAGS", "LIBRARY_SUFFIX"]

#: Compiler flags: optimized, position independent, only ``DISCON`` visible.
EXPORT_FLAGS: tuple[str, ...] = ("-O2", "-fPIC", "-fvisibility=hidden")
#: Suffix of the library written (the host platform's shared-library suffix).
LIBRARY_SUFFIX = ".so"
_LAW = "mbsym_discon_law"


def export_discon(controller, out_dir, *, name: str = "baseline_discon", sample_time: float | None = None,
                  compiler: str | None = None) -> dict:
    """Compile a baseline controller into a ``DISCON`` library and write its input file.

    Parameters
    ----------
    controller : BaselineController, BaselineSettings, str or Path
        The controller, its settings, or a ROSCO ``DISCON.IN`` (then ``sample_time`` is required).
    out_dir : str or Path
        Directory for ``<name>.so``, ``<name>.IN`` and the C sources ``src/`` (created if missing).
    name : str, optional, keyword-only
        File name stem (letters, digits, ``_``, ``-``, ``.``).
    sample_time : float, optional, keyword-only
        Controller sample time [s] when ``controller`` is a ``DISCON.IN``; otherwise it must be
        None or equal the controller's.
    compiler : str, optional, keyword-only
        C compiler command (default: :func:`mbsym.codegen.compiler_command`).

    Returns
    -------
    dict
        ``{"library": str, "input": str, "controller": "baseline", "sample_time_s": float}``
        (absolute paths).

    Raises
    ------
    TypeError
        ``controller`` of another type.
    ControllerError
        No C compiler, a sample time mismatch, or a failed compilation (with the compiler's message).
    ExportError
        A bad ``name`` or an unwritable ``out_dir``.

    Examples
    --------
    >>> from mbsym.wind.control import export_discon
    >>> out = export_discon("DISCON.IN", "build", sample_time=0.00625)  # doctest: +SKIP
    >>> out["library"], out["input"]  # doctest: +SKIP
    ('/.../build/baseline_discon.so', '/.../build/baseline_discon.IN')
    """
    ctrl = _controller(controller, sample_time)
    cc, out = prepare_export(name, compiler, out_dir, "export_discon")
    fingerprint = _fingerprint(ctrl)
    law, wrapper = _write_sources(ctrl, out / "src", name, fingerprint)
    library = out / f"{name}{LIBRARY_SUFFIX}"
    _compile(cc, [law, wrapper], library)
    infile = out / f"{name}.IN"
    infile.write_text(_input_text(ctrl, fingerprint))
    return {"library": str(library.resolve()), "input": str(infile.resolve()), "controller": "baseline",
            "sample_time_s": float(ctrl.dt)}


def prepare_export(name, compiler, out_dir, what: str) -> tuple[list[str], Path]:
    """Checks shared by the DISCON exports: ``name`` a file-name stem, a C compiler found, ``out_dir/src``
    created; returns ``(compiler command, out_dir)``.

    Raises
    ------
    ExportError
        A bad name, or an output directory that cannot be created.
    ControllerError
        No C compiler (``what`` names the export in the message).
    """
    from ...codegen import compiler_command

    if not isinstance(name, str) or not name or not all(c.isalnum() or c in "_-." for c in name):
        raise ExportError(f"name must be a file name stem of letters, digits, '_', '-', '.'; got {name!r}.")
    cc = compiler_command(compiler)
    if cc is None:
        raise ControllerError(f"{what} needs a C compiler: none found (tried $MBSYM_CC, $CC, gcc, cc). "
                              "Install gcc or set CC.")
    out = Path(out_dir)
    try:
        (out / "src").mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise ExportError(f"cannot create the output directory {out}: {exc}.") from exc
    return cc, out


def _controller(controller, sample_time) -> BaselineController:
    if isinstance(controller, (str, os.PathLike)):
        if sample_time is None:
            raise ControllerError("export_discon from a DISCON.IN needs sample_time= (the controller sample time "
                                  "[s], ServoDyn's DLL_DT).")
        controller = BaselineSettings.from_discon(controller, dt=float(sample_time))
    if isinstance(controller, BaselineSettings):
        controller = BaselineController(controller)
    if not isinstance(controller, BaselineController):
        raise TypeError(f"controller must be a BaselineController, BaselineSettings or a DISCON.IN path; got "
                        f"{type(controller).__name__}. (Exporting the NMPC is not yet available.)")
    if sample_time is not None and float(sample_time) != controller.dt:
        raise ControllerError(f"sample_time = {sample_time!r} s differs from the controller's {controller.dt!r} s; "
                              "build the controller with the sample time you want (its filters depend on it).")
    return controller


def _fingerprint(ctrl: BaselineController) -> str:
    text = ctrl.function.serialize() + repr(float(ctrl.dt)) + ",".join(ctrl.measurements + ctrl.commands)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def _write_sources(ctrl: BaselineController, folder: Path, name: str, fingerprint: str) -> tuple[Path, Path]:
    """``<name>_law.c`` (CasADi's generated law, renamed) and ``<name>_discon.c`` (the wrapper)."""
    f = ctrl.function
    xc, y = ca.SX.sym("xc", f.size1_in(0)), ca.SX.sym("y", f.size1_in(1))
    law = ca.Function(_LAW, [xc, y], f(xc, y), {"cse": True})
    cg = ca.CodeGenerator(f"{name}_law.c", {"with_header": False, "with_export": False,
                                            "casadi_int": "long long int", "casadi_real": "double"})
    cg.add(law)
    cg.generate(str(folder) + os.sep)
    measured = list(ctrl.measurements)
    records = [MEASUREMENT_RECORDS[m][0] for m in measured]
    ipc = len(ctrl.commands) == 4
    written = "42-44 pitch per blade, 45 blade 1, 47 torque" if ipc else "42-45 collective pitch, 47 torque"
    text = WRAPPER.format(
        controller="baseline", measured=", ".join(f"{r} {m}" for r, m in zip(records, measured)),
        written=written, sample_time=float(ctrl.dt), n_x=f.size1_in(0), n_y=len(measured), n_u=f.size1_out(1),
        fingerprint=fingerprint, ipc=int(ipc), law=_LAW, x0=", ".join(repr(float(v)) for v in ctrl.x0),
        y_records=", ".join(str(r) for r in records), y_names=", ".join(f'"{m}"' for m in measured),
        sz_arg=max(law.sz_arg(), 1), sz_res=max(law.sz_res(), 1), sz_iw=max(law.sz_iw(), 1),
        sz_w=max(law.sz_w(), 1))
    wrapper = folder / f"{name}_discon.c"
    wrapper.write_text(text)
    return folder / f"{name}_law.c", wrapper


def _compile(cc, sources, library: Path) -> None:
    """Compile into a temporary file next to ``library``, then rename it into place."""
    fd, tmp = tempfile.mkstemp(dir=library.parent, prefix=f".{library.stem}.", suffix=LIBRARY_SUFFIX)
    os.close(fd)
    cmd = [*cc, *EXPORT_FLAGS, "-shared", "-o", tmp, *map(str, sources), "-lm"]
    try:
        proc = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
        if proc.returncode != 0:
            raise ControllerError(f"compiling the DISCON library failed (exit {proc.returncode}): "
                                  f"{' '.join(proc.stderr.split())[-800:]}; command: {' '.join(cmd)}")
        os.replace(tmp, library)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)


#: First line of every input file ``mbsym export-discon`` writes.
EXPORT_HEADER = "! mbsym DISCON input file"
#: The comment naming the ROSCO input file the compiled law's settings came from.
SETTINGS_COMMENT = "! controller settings from: "


def exported_settings(path: str | Path) -> tuple[bool, Path | None]:
    """``(is_export, settings)``: whether ``path`` is an input file written by ``mbsym export-discon``, and
    the ROSCO ``DISCON.IN`` its law was built from (None: settings given in Python, or not recorded).

    An exported library's input file holds only what pairs it with the library; a deck whose ServoDyn
    names it (``DLL_InFile``) still needs the turbine's controller settings (set-points, limits, the
    actuators' rates) for mbsym: they are in the file recorded here.
    """
    try:
        with open(path, encoding="utf-8", errors="replace") as f:
            head = [f.readline() for _ in range(3)]
    except OSError:
        return False, None
    if not head[0].startswith(EXPORT_HEADER):
        return False, None
    for line in head[1:]:
        if line.startswith(SETTINGS_COMMENT):
            source = line[len(SETTINGS_COMMENT):].strip()
            candidate = Path(source)
            return True, (candidate if candidate.is_absolute() and candidate.suffix.upper() == ".IN" else None)
    return True, None


def _absolute(source: str) -> str:
    """A settings file's absolute path (the input file may be read from another folder); other text as is."""
    p = Path(source)
    return str(p.resolve()) if p.is_file() else source


def _input_text(ctrl: BaselineController, fingerprint: str) -> str:
    s = ctrl.settings
    source = s.source or "settings given in Python"
    lines = [
        f"{EXPORT_HEADER}, written by mbsym export-discon (value  Key  ! comment)",
        f"{SETTINGS_COMMENT}{_absolute(source)}",
        "! every setting of the law is compiled into the library; these values are checked against it",
        f"{'baseline':<24} Controller   ! controller kind",
        f"{float(ctrl.dt)!r:<24} SampleTime   ! controller sample time [s]; the communication interval must divide it",
        f"{fingerprint:<24} Fingerprint  ! identity of the compiled law (pairs this file with its library)",
        "! measurements (swap records): "
        + ", ".join(f"{m} ({MEASUREMENT_RECORDS[m][0]})" for m in ctrl.measurements),
        f"! commands: {', '.join(ctrl.commands)}; IPC_ControlMode {s.ipc_mode}",
    ]
    return "\n".join(lines) + "\n"

