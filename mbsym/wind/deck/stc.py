"""Read ServoDyn's structural-controller (StC) input files and the list of them in a ServoDyn file.

An StC file (OpenFAST v5.0.0, ``StrucCtrl.f90``, ``StC_ParseInputFileInfo``) describes one tuned mass damper, a tuned
liquid column damper or a prescribed load, placed at ``StC_P_X/Y/Z`` [m] in the axes of the part it is attached to
(the nacelle for ``NStCfiles``, the tower base for ``TStCfiles``, the platform reference point for ``SStCfiles``,
each blade root for ``BStCfiles``). :func:`read_stc` reads every key of that format into :class:`StCSettings`
(SI units as in the file: m, kg, N/m, N/(m/s)); the spring-force table (``NKInpSt`` rows of ``X F_X Y F_Y Z F_Z``)
and the prescribed-force time series (``PrescribedForcesFile``: seven columns ``t Fx Fy Fz Mx My Mz``, comment lines
``#``/``!``/``%``) are read too. OpenFAST v5.0.0's ``StC_DOF_MODE`` numbers: 0 none, 1 independent X/Y/Z DOFs,
2 omni-directional XY, 3 omni-directional XYZ, 5 TLCD, 6 prescribed force, 7 force from the DLL (older documents
number TLCD 3 and the prescribed force 4; OpenFAST v5 refuses those numbers, and so does this reader). Older key
spellings the wheel's files still use (``StC_XY_M``, ``PrescribedForcesCoord``) are accepted for ``StC_Omni_M`` and
``PrescribedForcesCoordSys``, as OpenFAST reads these files by position.

What mbsym models of them is decided by :func:`mbsym.wind.structure.structural_control.structural_controls`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ...exceptions import OpenFASTFormatError
from ._format import _Deck, _Key, _REAL, _TOKEN, _TableSpec

__all__ = ["StCSettings", "read_stc", "servodyn_stc_files", "read_prescribed_forces", "DOF_MODES", "STC_KINDS"]

#: OpenFAST v5.0.0's StC_DOF_MODE values (StrucCtrl.f90 parameters ``DOFMode_*``).
DOF_MODES = {0: "none", 1: "independent X, Y, Z DOFs", 2: "omni-directional XY", 3: "omni-directional XYZ",
             5: "tuned liquid column damper (TLCD)", 6: "prescribed force time series", 7: "force from the DLL"}
#: The ServoDyn keys of the four kinds of StC: kind -> (count key, files key, what it is attached to).
STC_KINDS = {"B": ("NumBStC", "BStCfiles", "blade roots"), "N": ("NumNStC", "NStCfiles", "nacelle"),
             "T": ("NumTStC", "TStCfiles", "tower"), "S": ("NumSStC", "SStCfiles", "platform (substructure)")}

_k = _Key
_NONNEG = (lambda v: v >= 0, "must not be negative")
_FLOATS = ("StC_P_X", "StC_P_Y", "StC_P_Z", "StC_X_DSP", "StC_Y_DSP", "StC_Z_DSP", "StC_X_PSP", "StC_X_NSP",
           "StC_Y_PSP", "StC_Y_NSP", "StC_Z_PSP", "StC_Z_NSP")
_NONNEG_FLOATS = ("StC_X_M", "StC_Y_M", "StC_Z_M", "StC_X_K", "StC_Y_K", "StC_Z_K", "StC_X_C", "StC_Y_C", "StC_Z_C",
                  "StC_X_KS", "StC_Y_KS", "StC_Z_KS", "StC_X_CS", "StC_Y_CS", "StC_Z_CS")
_OPTIONAL = ("StC_X_C_HIGH", "StC_X_C_LOW", "StC_Y_C_HIGH", "StC_Y_C_LOW", "StC_Z_C_HIGH", "StC_Z_C_LOW",
             "StC_X_C_BRAKE", "StC_Y_C_BRAKE", "StC_Z_C_BRAKE", "L_X", "B_X", "area_X", "area_ratio_X",
             "headLossCoeff_X", "rho_X", "L_Y", "B_Y", "area_Y", "area_ratio_Y", "headLossCoeff_Y", "rho_Y")
_TABLE = _TableSpec("spring force", "NKInpSt", ("x",), (
    ("X", "x", None, True), ("F_X", "f_x", None, True), ("Y", "y", None, True), ("F_Y", "f_y", None, True),
    ("Z", "z", None, True), ("F_Z", "f_z", None, True)))


@dataclass(frozen=True)
class StCSettings:
    """One StC input file (module docstring); ``values`` holds every numeric key by its OpenFAST name.

    Attributes
    ----------
    path : str
    dof_mode : int
        ``StC_DOF_MODE`` (:data:`DOF_MODES`).
    dof : tuple of bool
        ``StC_X_DOF``, ``StC_Y_DOF``, ``StC_Z_DOF``.
    values : dict
        Key -> number (``StC_P_X`` [m], ``StC_X_M`` [kg], ``StC_X_K`` [N/m], ``StC_X_C`` [N s/m] …).
    z_preload : str
        ``StC_Z_PreLd`` as written ("none", "gravity" or a number [N]).
    use_table : bool
        ``Use_F_TBL``.
    table : ndarray, shape (NKInpSt, 6)
        The spring-force table ``X F_X Y F_Y Z F_Z`` [m, N].
    control_mode : int
        ``StC_CMODE``.
    prescribed_coordinates : int
        ``PrescribedForcesCoordSys`` (1 global, 2 local).
    prescribed_file : Path or None
        ``PrescribedForcesFile`` resolved against the StC file's folder.
    lines : dict
        Key -> line number, for messages.
    """

    path: str
    dof_mode: int
    dof: tuple[bool, bool, bool]
    values: dict
    z_preload: str
    use_table: bool
    table: np.ndarray
    control_mode: int
    semi_active_mode: int
    prescribed_coordinates: int
    prescribed_file: Path | None
    lines: dict = field(default_factory=dict, compare=False)

    def where(self, key: str) -> str:
        """``"<file>, line <n>, key '<key>'"`` for messages."""
        return f"{self.path}, line {self.lines.get(key, '?')}, key '{key}'"

    def vector(self, name: str) -> np.ndarray:
        """``values`` of ``StC_X_<name>``, ``StC_Y_<name>``, ``StC_Z_<name>`` (e.g. ``"K"``, ``"PSP"``)."""
        return np.array([float(self.values[f"StC_{c}_{name}"]) for c in "XYZ"])

    @property
    def position(self) -> np.ndarray:
        """``StC_P_X/Y/Z`` [m] in the axes of the part it is attached to."""
        return np.array([float(self.values[f"StC_P_{c}"]) for c in "XYZ"])


def read_stc(path) -> StCSettings:
    """Read one StC input file (module docstring).

    Raises
    ------
    OpenFASTFormatError
        Missing file or key, a malformed value, an ``StC_DOF_MODE`` OpenFAST v5 does not have, a
        spring-force table whose row count differs from ``NKInpSt``: file, line and key.
    """
    p = Path(path)
    if not p.is_file():
        raise OpenFASTFormatError(f"StC input file not found: tried '{p.absolute()}'. Check the file names in "
                                  "ServoDyn's NStCfiles/TStCfiles/SStCfiles/BStCfiles (relative to the ServoDyn file).")
    deck = _Deck(p, (_TABLE,))
    mode = deck.value(_k("StC_DOF_MODE", "", "int", check=(lambda v: v in DOF_MODES, "must be one of " + ", ".join(
        f"{k} ({v})" for k, v in DOF_MODES.items()) + " in OpenFAST v5")))
    dof = tuple(deck.value(_k(f"StC_{c}_DOF", "", "bool")) for c in "XYZ")
    values = {key: deck.value(_k(key, "")) for key in _FLOATS}
    values.update({key: deck.value(_k(key, "", check=_NONNEG)) for key in _NONNEG_FLOATS})
    omni = "StC_Omni_M" if "stc_omni_m" in deck.entries else "StC_XY_M"
    values["StC_Omni_M"] = deck.value(_k(omni, "", check=_NONNEG, default=0.0))
    values.update({key: deck.value(_k(key, "", default=0.0)) for key in _OPTIONAL})
    preload = str(deck.value(_k("StC_Z_PreLd", "", "str", default="none")))
    if preload.lower() not in ("none", "gravity") and not _REAL.match(preload):
        deck.problem(deck.line_of("StC_Z_PreLd"), "StC_Z_PreLd", f"must be \"gravity\", \"none\" or a number [N]; "
                     f"got {preload!r}. Fix the value in that line.")
    use_table = deck.value(_k("Use_F_TBL", "", "bool", default=False))
    deck.value(_k("NKInpSt", "", "int", default=0, check=_NONNEG))
    cmode = deck.value(_k("StC_CMODE", "", "int", default=0))
    deck.value(_k("StC_CChan", "", "floats", default=(0.0,)))
    sa_mode = deck.value(_k("StC_SA_MODE", "", "int", default=1))
    coord_key = "PrescribedForcesCoordSys" if "prescribedforcescoordsys" in deck.entries else "PrescribedForcesCoord"
    coords = deck.value(_k(coord_key, "", "int", default=1,
                           check=(lambda v: v in (1, 2), "must be 1 (global) or 2 (local)")))
    name = deck.value(_k("PrescribedForcesFile", "", "str", default=""))
    deck.raise_problems()
    rows = deck.tables.get("spring force")
    table = np.array(rows.rows, dtype=float).reshape(-1, 6) if rows is not None and rows.rows else np.zeros((0, 6))
    prescribed = None
    if name and name.lower() != "unused":
        prescribed = Path(name.replace("\\", "/"))
        prescribed = prescribed if prescribed.is_absolute() else p.parent / prescribed
    keys = ["StC_DOF_MODE", "StC_X_DOF", "StC_Y_DOF", "StC_Z_DOF", *values, "StC_Z_PreLd", "Use_F_TBL", "NKInpSt",
            "StC_CMODE", "StC_CChan", "StC_SA_MODE", "PrescribedForcesFile", omni, coord_key]
    lines = {key: deck.line_of(key) for key in keys if key.lower() in deck.entries}
    lines["StC_Omni_M"] = deck.line_of(omni)
    lines["PrescribedForcesCoordSys"] = deck.line_of(coord_key)
    return StCSettings(str(p), int(mode), tuple(bool(d) for d in dof), {k: float(v) for k, v in values.items()},
                       preload, bool(use_table), table, int(cmode), int(sa_mode), int(coords), prescribed, lines)


def servodyn_stc_files(servodyn) -> dict[str, list[tuple[Path, int]]]:
    """The StC files a ServoDyn file names: kind (``"B"``, ``"N"``, ``"T"``, ``"S"``) -> ``[(path, line)]``.

    Parameters
    ----------
    servodyn : ServoDynSettings
        As read by :func:`~mbsym.wind.deck.servodyn.read_servodyn` (its ``path`` is read again for the file lists).

    Raises
    ------
    OpenFASTFormatError
        A count ``Num?StC`` > 0 with fewer file names after it (file, line, key).
    """
    path = Path(servodyn.path)
    deck = _Deck(path)
    counts = {"B": servodyn.n_blade_structural_controllers, "N": servodyn.n_nacelle_structural_controllers,
              "T": servodyn.n_tower_structural_controllers, "S": servodyn.n_substructure_structural_controllers}
    out: dict[str, list[tuple[Path, int]]] = {}
    for kind, (count_key, files_key, _) in STC_KINDS.items():
        n = int(counts[kind] or 0)
        if n <= 0:
            continue
        entry = deck.entries.get(files_key.lower())
        names = [] if entry is None else [v for v in entry.values if v]
        if len(names) < n:
            line = entry.line if entry is not None else deck.line_of(count_key)
            raise OpenFASTFormatError(f"{path}, line {line}, key '{files_key}': {count_key} = {n} needs {n} quoted "
                                      f"file name(s); got {len(names)}. Give one StC input file per controller.")
        out[kind] = [(_resolve(path, names[k]), entry.line) for k in range(n)]
    return out


def _resolve(base: Path, name: str) -> Path:
    path = Path(name.replace("\\", "/"))
    return path if path.is_absolute() else base.parent / path


def read_prescribed_forces(path) -> np.ndarray:
    """The prescribed force file of ``StC_DOF_MODE`` 6: rows ``t Fx Fy Fz Mx My Mz`` [s, N, N m] (shape (n, 7)).

    Lines starting with ``#``, ``!`` or ``%`` (and blank lines) are comments; a value after the seventh on a
    row is a trailing comment.

    Raises
    ------
    OpenFASTFormatError
        Missing file, a row with fewer than seven numbers, times not increasing (file and line).
    """
    p = Path(path)
    if not p.is_file():
        raise OpenFASTFormatError(f"StC prescribed force file not found: tried '{p.absolute()}'. Check "
                                  "PrescribedForcesFile (relative to the StC file).")
    rows, lines = [], []
    for number, text in enumerate(p.read_text(encoding="latin-1").splitlines(), 1):
        text = text.strip()
        if not text or text.startswith(("#", "!", "%")):
            continue
        tokens = _TOKEN.findall(text)[:7]
        if len(tokens) < 7 or not all(_REAL.match(t) for t in tokens):
            raise OpenFASTFormatError(f"{p}, line {number}: expected seven numbers 't Fx Fy Fz Mx My Mz' "
                                      f"[s, N, N-m]; got {text!r}. Fix or comment out that line (#).")
        rows.append([float(t.replace("d", "e").replace("D", "E")) for t in tokens])
        lines.append(number)
    data = np.array(rows, dtype=float).reshape(-1, 7)
    if len(data) == 0:
        raise OpenFASTFormatError(f"{p}: no rows 't Fx Fy Fz Mx My Mz'. Give at least one.")
    bad = np.nonzero(np.diff(data[:, 0]) <= 0)[0]
    if len(bad):
        raise OpenFASTFormatError(f"{p}, line {lines[bad[0] + 1]}: times must increase; got {data[bad[0] + 1, 0]:g} s "
                                  f"after {data[bad[0], 0]:g} s. Sort the rows.")
    return data
