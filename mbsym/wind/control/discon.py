"""Call any Bladed-style ``DISCON`` controller library (e.g. ROSCO's ``libdiscon.so``) through ctypes.

The entry point is ``void DISCON(float *avrSWAP, int *aviFAIL, const char
*accINFILE, char *avcOUTNAME, char *avcMSG)``; the swap-array records are listed
in :mod:`mbsym.wind.control.swap`.  A :class:`DisconController` follows
ServoDyn's life cycle:

1. **load** the library (a private copy, see below) and resolve ``DISCON``;
2. **initialization call** (status 0) at the first time, with the first measurements:
   the library reads its input file and returns its first commands;
3. **step calls** (status 1), once per controller time step ``dt``; the commands
   are to be held (zero-order hold) until the next call, as OpenFAST does;
4. **final call** (status −1) in :meth:`DisconController.finish` (also on
   :meth:`~DisconController.close`, ``with`` exit and garbage collection), then the copy is unloaded.

**Several instances.** A DISCON library keeps its state in static (process-global)
memory, and ROSCO refuses a second initialization ("This ROSCO dynamic library
has already been loaded").  By default (``private_copy=True``) every instance
therefore loads its own copy of the library file: the file is copied to a
temporary directory, loaded, and the copy deleted at once (the mapping stays
valid), so each instance has its own static memory and several controllers —
several turbines, or a reference and a test — can run side by side in one
process.  The library's own dependencies (e.g. the gfortran runtime that the
``rosco`` wheel bundles and finds through ``$ORIGIN``) are loaded once from the
original location, so the copies find them by name.  With ``private_copy=False``
the file is loaded in place and a second live instance of the same file raises
:class:`~mbsym.exceptions.ControllerError`.

**Output.** The library's console output at the initialization and final calls
(ROSCO's banner and warnings) is captured into :attr:`DisconController.messages`
unless ``quiet=False``.

Errors: a library that cannot be loaded, a missing ``DISCON`` symbol, a call
returning ``aviFAIL < 0`` (with the library's message), unknown or non-finite
measurements, a call after :meth:`~DisconController.finish` →
:class:`~mbsym.exceptions.ControllerError` / :class:`~mbsym.exceptions.ParameterError`.
"""

from __future__ import annotations

import contextlib
import ctypes
import math
import os
import shutil
import sys
import tempfile
import threading
import weakref
from pathlib import Path
from typing import Mapping

import numpy as np

from ...exceptions import ControllerError, ParameterError
from ..inflow.lidar import lidar_records
from .swap import (COLLECTIVE_PITCH_RECORD, COMMAND_RECORDS, CONSTANT_RECORDS, MEASUREMENT_RECORDS, SWAP_SIZE,
                   fill_constants)

__all__ = ["DisconController", "REQUIRED_MEASUREMENTS"]

#: Measurements a call needs (others default to 0): what ROSCO's baseline reads.
REQUIRED_MEASUREMENTS = ("GenSpeed", "RotSpeed", "BldPitch1", "GenPwr", "Wind1VelX")
_MESSAGE_SIZE = 1024
_OUTNAME_SIZE = 300 * 2 * 21 + 1    # ServoDyn: MaxLoggingChannels * 2 * (1 + ChanLen) + 1
_ANCHORS: dict[str, ctypes.CDLL] = {}     # original libraries loaded once, so copies find their dependencies
_IN_PLACE: set[str] = set()              # files loaded in place by a live instance
_LOCK = threading.Lock()
_FLOAT_P = ctypes.POINTER(ctypes.c_float)


def _flush_native() -> None:
    """Flush C stdio and every loaded gfortran runtime (Fortran buffers writes to non-terminals)."""
    with contextlib.suppress(Exception):
        ctypes.CDLL(None).fflush(None)
    with contextlib.suppress(OSError):
        with open("/proc/self/maps") as maps:
            paths = {line.split()[-1] for line in maps if "libgfortran" in line and "/" in line}
        for path in paths:
            with contextlib.suppress(OSError, AttributeError):
                ctypes.CDLL(path)._gfortran_flush_i4(None)   # NULL unit: flush all units


@contextlib.contextmanager
def _captured_stdout(enabled: bool):
    """Redirect file descriptor 1 (where Fortran writes) to a temporary file; yield a list for the text."""
    text: list[str] = []
    if not enabled:
        yield text
        return
    sys.stdout.flush()
    saved = os.dup(1)
    with tempfile.TemporaryFile(mode="w+b") as sink:
        os.dup2(sink.fileno(), 1)
        try:
            yield text
        finally:
            _flush_native()
            os.dup2(saved, 1)
            os.close(saved)
            sink.seek(0)
            text.append(sink.read().decode("latin-1", "replace"))


def _load(path: Path, private_copy: bool) -> tuple[ctypes.CDLL, int]:
    real = str(path.resolve())
    mode = getattr(os, "RTLD_LOCAL", 0) | getattr(os, "RTLD_NOW", 2)
    try:
        with _LOCK:
            if not private_copy:
                if real in _IN_PLACE:
                    raise ControllerError(f"the DISCON library {path} is already in use by another controller in "
                                          "this process; its state is process-global. Use private_copy=True to "
                                          "give each controller its own copy.")
                lib = ctypes.CDLL(real, mode=mode)
                _IN_PLACE.add(real)
                return lib, 0
            if real not in _ANCHORS:
                _ANCHORS[real] = ctypes.CDLL(real, mode=mode)
            folder = tempfile.mkdtemp(prefix="mbsym_discon_")
            try:
                copy = Path(folder) / f"{path.stem}_copy{path.suffix}"
                shutil.copyfile(real, copy)
                lib = ctypes.CDLL(str(copy), mode=mode)
            finally:
                shutil.rmtree(folder, ignore_errors=True)
            return lib, 1
    except OSError as exc:
        raise ControllerError(f"cannot load the DISCON library {path}: {exc}. Check that it is a shared library "
                              "for this platform and that its dependencies can be found.") from exc


def _unload(lib: ctypes.CDLL | None, real: str, private: int) -> None:
    if lib is None:
        return
    if not private:
        _IN_PLACE.discard(real)
    try:
        import _ctypes
        _ctypes.dlclose(lib._handle)
    except (ImportError, AttributeError, OSError):  # pragma: no cover - platform without dlclose
        pass


class _Handle:
    """The loaded library and its final call, shared with the finalizer (no reference to the controller)."""

    def __init__(self, lib, real, private, entry, swap, fail, infile, outname, message):
        self.lib, self.real, self.private, self.entry = lib, real, private, entry
        self.swap, self.fail, self.infile, self.outname, self.message = swap, fail, infile, outname, message
        self.started = self.finished = False

    def call(self) -> None:
        self.fail.value = 0
        self.entry(self.swap.ctypes.data_as(_FLOAT_P), ctypes.byref(self.fail), self.infile, self.outname,
                   self.message)

    def close(self) -> None:
        if self.started and not self.finished:
            self.finished = True
            self.swap[0] = -1.0
            with contextlib.suppress(Exception), _captured_stdout(True):
                self.call()
        _unload(self.lib, self.real, self.private)
        self.lib = self.entry = None


class DisconController:
    """A Bladed-style DISCON library in the loop (see the module docstring).

    Parameters
    ----------
    library : str or Path
        The shared library (``.so``/``.dll``/``.dylib``).
    input_file : str or Path
        The controller's input file (``DISCON.IN`` for ROSCO), passed as ``accINFILE``.
    dt : float
        Controller time step [s] (record 3; ServoDyn's ``DLL_DT``).
    n_blades : int, optional
        Number of blades (record 61).
    individual_pitch : bool, optional
        Record 28 (ServoDyn ``Ptch_Cntrl``): read the pitch demands of records 42-44
        (True) or the collective demand of record 45 (False).
    constants : mapping, optional
        Values of :data:`~mbsym.wind.control.swap.CONSTANT_RECORDS` (SI units; default 0).
    torque_table : (speeds, torques), optional
        ServoDyn's torque-speed look-up table [rad/s, N m] (records 165 on).
    procedure : str, optional
        Name of the entry point (ServoDyn ``DLL_ProcName``).
    run_name : str, optional
        Simulation root name (``avcOUTNAME``), with an extension as ServoDyn sends it
        (``<root>.SrvD``): ROSCO strips the extension (and with it the C string's
        terminating NUL) and writes its debug files (``LoggingLevel > 0``) to
        ``<root>.RO.dbg``, relative to the working directory.
    private_copy : bool, optional
        Load a private copy so instances do not share state (default; see above).
    quiet : bool, optional
        Capture the library's console output at the initialization and final calls.
    lidar : callable, optional
        ``t -> (speeds, positions)``: a single-point lidar's measurement at each call
        (:func:`mbsym.wind.inflow.lidar_measurements`), written to the extended records 2001… as
        OpenFAST's ServoDyn writes them (:func:`mbsym.wind.inflow.lidar_records`).

    Attributes
    ----------
    measurement_names, command_names : tuple of str
        Names (SI units: :data:`~mbsym.wind.control.swap.MEASUREMENT_UNITS`, ``COMMAND_UNITS``).
    dt : float
        Time step [s].
    swap : ndarray
        The float32 swap array (read-only view; for inspection).
    messages : list of str
        Captured console output and warnings (``aviFAIL > 0``) of the library.

    Examples
    --------
    >>> from mbsym.wind.control import DisconController
    >>> ctrl = DisconController("libdiscon.so", "DISCON.IN", dt=0.00625)  # doctest: +SKIP
    >>> y = {"GenSpeed": 116.6, "RotSpeed": 1.2025, "BldPitch1": 0.0075, "GenPwr": 3.46e6, "Wind1VelX": 10.0}
    >>> u = ctrl.step(0.0, y)  # doctest: +SKIP
    >>> sorted(u)  # doctest: +SKIP
    ['BlPitchCom1', 'BlPitchCom2', 'BlPitchCom3', 'BrakeStatus', 'GenState', 'GenTqCom', 'YawRateCom']
    >>> ctrl.close()  # doctest: +SKIP
    """

    measurement_names = tuple(MEASUREMENT_RECORDS)
    command_names = tuple(COMMAND_RECORDS)

    def __init__(self, library, input_file, *, dt: float, n_blades: int = 3, individual_pitch: bool = True,
                 constants: Mapping[str, float] | None = None, torque_table=None, procedure: str = "DISCON",
                 run_name: str = "mbsym.SrvD", private_copy: bool = True, quiet: bool = True,
                 lidar=None) -> None:
        self._handle = None
        if lidar is not None and not callable(lidar):
            raise ParameterError(f"lidar must be a callable t -> (speeds, positions) (mbsym.wind.inflow."
                                 f"lidar_measurements); got {type(lidar).__name__}.")
        self.lidar = lidar
        path = Path(library)
        if not path.is_file():
            raise ControllerError(f"DISCON library not found: tried '{path.absolute()}'. Check the path (ServoDyn's "
                                  "DLL_FileName); for ROSCO, 'pip download --no-deps rosco==2.10.6' gives a wheel "
                                  "holding rosco/lib/libdiscon.so.")
        infile = Path(input_file)
        if not infile.is_file():
            raise ControllerError(f"controller input file not found: tried '{infile.absolute()}'. Check the path "
                                  "(ServoDyn's DLL_InFile).")
        if not (isinstance(dt, (int, float)) and math.isfinite(dt) and dt > 0):
            raise ParameterError(f"dt must be a finite time step > 0 [s]; got {dt!r}.")
        if n_blades not in (1, 2, 3):
            raise ParameterError(f"n_blades must be 1, 2 or 3; got {n_blades!r}.")
        constants = dict(constants or {})
        unknown = sorted(set(constants) - set(CONSTANT_RECORDS))
        if unknown:
            raise ParameterError(f"unknown constants {unknown}; known: {sorted(CONSTANT_RECORDS)}.")
        table = (np.zeros(0), np.zeros(0)) if torque_table is None else \
            tuple(np.asarray(a, dtype=float).reshape(-1) for a in torque_table)
        if table[0].shape != table[1].shape:
            raise ParameterError("torque_table must be two arrays (speeds [rad/s], torques [N m]) of equal length.")
        self.library, self.input_file, self.dt = path, infile, float(dt)
        self.n_blades, self.individual_pitch, self.quiet = n_blades, bool(individual_pitch), quiet
        self.messages: list[str] = []
        self.time: float | None = None
        swap = np.zeros(SWAP_SIZE, dtype=np.float32)
        name = os.fsencode(str(infile))
        run = run_name.encode("latin-1")
        fill_constants(swap, dt=self.dt, n_blades=n_blades, individual_pitch=self.individual_pitch,
                       infile_length=len(name), outname_length=len(run), outname_buffer=_OUTNAME_SIZE,
                       message_buffer=_MESSAGE_SIZE + 1, constants=constants, torque_table=table)
        swap[34], swap[35] = 1.0, 0.0   # records 35, 36: generator contactor on, brake off
        lib, private = _load(path, private_copy)
        try:
            entry = getattr(lib, procedure)
        except AttributeError:
            _unload(lib, str(path.resolve()), private)
            raise ControllerError(f"the library {path} has no function {procedure!r} (ServoDyn's DLL_ProcName).") \
                from None
        entry.restype = None
        entry.argtypes = [_FLOAT_P, ctypes.POINTER(ctypes.c_int), ctypes.c_char_p, ctypes.c_char_p, ctypes.c_char_p]
        self._handle = _Handle(lib, str(path.resolve()), private, entry, swap, ctypes.c_int(0),
                               ctypes.create_string_buffer(name, len(name) + 1),
                               ctypes.create_string_buffer(run, _OUTNAME_SIZE),
                               ctypes.create_string_buffer(_MESSAGE_SIZE + 1))
        self._finalizer = weakref.finalize(self, _Handle.close, self._handle)

    # ------------------------------------------------------------------ calls
    @property
    def swap(self) -> np.ndarray:
        view = self._live().swap.view()
        view.setflags(write=False)
        return view

    @property
    def started(self) -> bool:
        """Whether the initialization call has been made."""
        return self._handle is not None and self._handle.started

    def _live(self) -> _Handle:
        if self._handle is None or self._handle.lib is None:
            raise ControllerError(f"the DISCON controller {self.library.name} is closed; create a new one.")
        return self._handle

    def step(self, t: float, measurements: Mapping[str, float]) -> dict[str, float]:
        """Call the library at time ``t`` [s] with ``measurements`` (SI units) → commands (SI units).

        The first call is the initialization call (status 0), later ones are steps
        (status 1).  Required measurements: :data:`REQUIRED_MEASUREMENTS`; others
        (see ``measurement_names``) default to 0; ``BldPitch2``/``BldPitch3`` default
        to ``BldPitch1``.  The commands are to be held for ``dt``.

        Raises
        ------
        ParameterError
            Unknown, missing or non-finite measurements.
        ControllerError
            The library reports a failure (``aviFAIL < 0``) or was finished.
        """
        handle = self._live()
        if handle.finished:
            raise ControllerError(f"the DISCON controller {self.library.name} has been finished; create a new one.")
        self._write(handle.swap, float(t), measurements)
        if self.lidar is not None:
            for record, value in lidar_records(*self.lidar(float(t))).items():
                handle.swap[record - 1] = value
        first = not handle.started
        handle.swap[0] = 0.0 if first else 1.0
        with _captured_stdout(self.quiet and first) as text:
            handle.call()
        if text and text[0].strip():
            self.messages.append(text[0])
        handle.started = True
        self.time = float(t)
        return self._read(handle)

    __call__ = step

    def _write(self, swap: np.ndarray, t: float, y: Mapping[str, float]) -> None:
        unknown = sorted(set(y) - set(MEASUREMENT_RECORDS))
        missing = [n for n in REQUIRED_MEASUREMENTS if n not in y]
        if unknown or missing:
            raise ParameterError(f"measurements: unknown {unknown}, missing {missing}; required: "
                                 f"{list(REQUIRED_MEASUREMENTS)}, optional: the rest of {list(MEASUREMENT_RECORDS)}.")
        values = {}
        for name, value in y.items():
            v = float(value)
            if not math.isfinite(v):
                raise ParameterError(f"measurement {name!r} must be finite; got {v} at t = {t:g} s.")
            values[name] = v
        if not math.isfinite(t):
            raise ParameterError(f"time must be finite; got {t}.")
        values.setdefault("BldPitch2", values["BldPitch1"])
        values.setdefault("BldPitch3", values["BldPitch1"])
        for name, (record, _, _) in MEASUREMENT_RECORDS.items():
            swap[record - 1] = values.get(name, 0.0)
        swap[1] = t
        swap[2] = self.dt

    def _read(self, handle: _Handle) -> dict[str, float]:
        fail = handle.fail.value
        if fail != 0:
            text = handle.message.value.decode("latin-1", "replace").strip()
            if fail < 0:
                raise ControllerError(f"the DISCON library {self.library.name} failed at t = {self.time:g} s "
                                      f"(aviFAIL = {fail}): {text or '(no message)'}")
            self.messages.append(text)
        swap = handle.swap
        out = {name: float(swap[record - 1]) for name, (record, _, _) in COMMAND_RECORDS.items()}
        if not self.individual_pitch:
            for k in (1, 2, 3):
                out[f"BlPitchCom{k}"] = float(swap[COLLECTIVE_PITCH_RECORD - 1])
        swap[10] = out["BlPitchCom1"]   # record 11: previous pitch demand of blade 1, as ServoDyn sends it
        if swap[54] != 0.0 or swap[55] != 0.0:
            raise ControllerError(f"the DISCON library {self.library.name} requests a pitch or torque override "
                                  "(records 55/56), which is not supported (as in ServoDyn).")
        return out

    def callable(self, measurements=("GenSpeed", "RotSpeed", "BldPitch1", "GenPwr", "Wind1VelX"),
                 commands=("BlPitchCom1", "GenTqCom")):
        """A vector form ``f(t, y) -> u`` of :meth:`step` for simulation loops.

        ``y`` holds ``measurements`` in order (default: the order of
        :attr:`BaselineController.measurement_names <mbsym.wind.control.BaselineController>`),
        ``u`` the ``commands`` in order (default: blade-1 pitch demand [rad], generator
        torque demand [N m]).
        """
        measurements, commands = tuple(measurements), tuple(commands)
        bad = sorted(set(measurements) - set(MEASUREMENT_RECORDS)) + sorted(set(commands) - set(COMMAND_RECORDS))
        if bad:
            raise ParameterError(f"unknown measurement or command names {bad}; measurements: "
                                 f"{list(MEASUREMENT_RECORDS)}, commands: {list(COMMAND_RECORDS)}.")

        def step(t: float, y) -> np.ndarray:
            values = np.asarray(y, dtype=float).reshape(-1)
            if values.size != len(measurements):
                raise ParameterError(f"y has {values.size} entries; expected {len(measurements)} {list(measurements)}.")
            out = self.step(t, dict(zip(measurements, values.tolist())))
            return np.array([out[name] for name in commands])
        return step

    def finish(self) -> None:
        """Make the final call (status −1) if the library was started; further steps raise."""
        handle = self._live()
        if handle.started and not handle.finished:
            handle.finished = True
            handle.swap[0] = -1.0
            with _captured_stdout(self.quiet) as text:
                handle.call()
            if text and text[0].strip():
                self.messages.append(text[0])

    def close(self) -> None:
        """Finish (if started) and unload the library; idempotent."""
        if self._handle is not None:
            self._finalizer()
            self._handle = None

    def __enter__(self) -> DisconController:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def __repr__(self) -> str:
        state = "closed" if self._handle is None else ("running" if self.started else "loaded")
        return f"DisconController({self.library.name}, {self.input_file.name}, dt={self.dt:g} s, {state})"

    # ------------------------------------------------------------------ construction from a deck
    @classmethod
    def from_servodyn(cls, servodyn, *, glue_time_step: float | None = None, n_blades: int = 3,
                      **options) -> DisconController:
        """Build from a ServoDyn file (path or :class:`~mbsym.wind.deck.servodyn.ServoDynSettings`).

        Uses ``DLL_FileName``, ``DLL_InFile``, ``DLL_ProcName``, ``DLL_DT`` (``"default"``
        → ``DT`` → ``glue_time_step``), ``Ptch_Cntrl`` and the swap-array parameters
        (records 5-9, 13, 16-19, 22 and the torque-speed table).
        """
        from ..deck.servodyn import ServoDynSettings, read_servodyn

        srv = servodyn if isinstance(servodyn, ServoDynSettings) else read_servodyn(servodyn)
        if not srv.uses_library:
            raise ControllerError(f"{srv.path}: PCMode = {srv.pitch_control_mode} and VSContrl = "
                                  f"{srv.torque_control_mode}; neither is 5 (Bladed-style DLL).")
        if glue_time_step is None and "default" in (srv.library_time_step, srv.time_step) and \
                srv.library_time_step == "default" and srv.time_step == "default":
            raise ControllerError(f"{srv.path}: DLL_DT and DT are 'default'; give glue_time_step (the .fst DT).")
        constants = {name: getattr(srv, name) for name in CONSTANT_RECORDS if hasattr(srv, name)}
        return cls(srv.library, srv.library_input, dt=srv.controller_time_step(glue_time_step or 0.0),
                   n_blades=n_blades, individual_pitch=bool(srv.individual_pitch), constants=constants,
                   torque_table=(srv.torque_table_speed, srv.torque_table_torque),
                   procedure=srv.procedure_name, **options)
