"""Read an OpenFAST HydroDyn input file (v5 layout): potential flow, additional loads, Morison tables.

HydroDyn reads its file line by line in a fixed order (``HydroDyn_Input.f90``), and so
does :func:`read_hydrodyn` (:class:`~mbsym.wind.deck._lines._Lines`): the floating-platform
section (``PotMod``, ``ExctnMod``, ``RdtnMod``, ``NBody``, ``PotFile`` resolved against the
file's directory, ``WAMITULEN``, ``PtfmRefxt/yt/zt``, ``PtfmRefztRot``, ``PtfmVol0``,
``PtfmCOBxt/yt``, ``NAddDOF``), the second-order switches (``MnDrift``, ``NewmanApp``,
``DiffQTF``, ``SumQTF``), the additional preload, stiffness and damping (``AddF0`` on
``NDOF`` lines, ``AddCLin``, ``AddBLin``, ``AddBQuad`` as ``NDOF`` rows each), the strip-theory
switches, every Morison table (axial coefficients, joints, cylindrical and rectangular
property sets, simple / depth-based / member-based coefficients, members, filled groups,
marine growth, member and joint outputs) and the output list.

Values are in SI units (deg → rad); the file's own names are kept in
:data:`HYDRODYN_KEYS`.  What mbsym does *not* model is decided where the data are used
(:mod:`mbsym.wind.offshore`), not here: the reader keeps everything.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ._lines import _Lines

__all__ = ["HydroDynInput", "HydroDynTable", "read_hydrodyn", "HYDRODYN_KEYS"]

_DEG = math.pi / 180.0

#: HydroDyn key → :class:`HydroDynInput` attribute.
HYDRODYN_KEYS = {
    "PotMod": "potential_model", "ExctnMod": "excitation_model", "ExctnDisp": "excitation_displaced",
    "ExctnCutOff": "excitation_cutoff_hz", "PtfmYMod": "yaw_model", "PtfmRefY": "reference_yaw",
    "PtfmYCutOff": "yaw_cutoff_hz", "NExctnHdg": "n_excitation_headings", "RdtnMod": "radiation_model",
    "RdtnTMax": "radiation_time_max", "RdtnDT": "radiation_time_step", "NBody": "n_bodies",
    "NBodyMod": "body_coupling", "PotFile": "potential_files", "WAMITULEN": "wamit_length",
    "PtfmRefxt": "reference_x", "PtfmRefyt": "reference_y", "PtfmRefzt": "reference_z",
    "PtfmRefztRot": "reference_rotation", "PtfmVol0": "displaced_volume", "PtfmCOBxt": "buoyancy_center_x",
    "PtfmCOByt": "buoyancy_center_y", "NAddDOF": "n_additional_dofs", "MnDrift": "mean_drift",
    "NewmanApp": "newman_approximation", "DiffQTF": "difference_qtf", "SumQTF": "sum_qtf",
    "AddF0": "add_force", "AddCLin": "add_stiffness", "AddBLin": "add_damping",
    "AddBQuad": "add_quadratic_damping", "WaveDisp": "wave_displaced", "AMMod": "added_mass_model",
    "HstMod": "hydrostatic_model", "HDSum": "summary", "OutAll": "output_all", "OutSwtch": "output_switch",
    "OutFmt": "output_format", "OutSFmt": "output_header_format",
}

# Morison tables in file order: (count key, table name, min columns, max columns, text columns).
_TABLES = (
    ("NAxCoef", "axial_coefficients", 4, 7, ()),
    ("NJoints", "joints", 6, 6, ()),
    ("NPropSetsCyl", "cylinder_properties", 3, 3, ()),
    ("NPropSetsRec", "rectangle_properties", 4, 4, ()),
    (None, "simple_cylinder_coefficients", 14, 14, (4, 5)),
    (None, "simple_rectangle_coefficients", 18, 18, (8, 9)),
    ("NCoefDpthCyl", "depth_cylinder_coefficients", 15, 15, ()),
    ("NCoefDpthRec", "depth_rectangle_coefficients", 19, 19, ()),
    ("NCoefMembersCyl", "member_cylinder_coefficients", 29, 29, ()),
    ("NCoefMembersRec", "member_rectangle_coefficients", 37, 37, ()),
    ("NMembers", "members", 11, 16, ()),
    ("NFillGroups", "fill_groups", 4, 99, tuple(range(99))),
    ("NMGDepths", "marine_growth", 3, 3, ()),
    ("NMOutputs", "member_outputs", 2, 12, ()),
)


@dataclass(frozen=True)
class HydroDynTable:
    """One Morison table as written: column names (first header line), rows, their line numbers."""

    columns: tuple[str, ...]
    rows: tuple[tuple, ...]
    lines: tuple[int, ...]

    def __len__(self) -> int:
        return len(self.rows)


@dataclass(frozen=True, eq=False)
class HydroDynInput:
    """HydroDyn settings in SI units (file key of each attribute: :data:`HYDRODYN_KEYS`).

    ``add_force`` is the ``NDOF`` vector ``AddF0`` [N, N m]; ``add_stiffness``,
    ``add_damping`` and ``add_quadratic_damping`` the ``NDOF × NDOF`` matrices ``AddCLin``
    [N/m, N/rad, N m/m, N m/rad], ``AddBLin`` [N/(m/s), …] and ``AddBQuad`` [N/(m/s)^2, …]
    (one column block per WAMIT object when ``NBodyMod > 1``).  ``potential_files`` are the
    ``PotFile`` roots resolved against the file's directory (WAMIT ``.hst``, ``.1``, ``.3``
    are ``root + ext``).  ``tables`` holds every Morison table by name (``members``,
    ``joints``, …; empty when its count is 0).
    """

    potential_model: int
    excitation_model: int
    excitation_displaced: int
    excitation_cutoff_hz: float
    yaw_model: int
    reference_yaw: float
    yaw_cutoff_hz: float
    n_excitation_headings: int
    radiation_model: int
    radiation_time_max: float
    radiation_time_step: float | str
    n_bodies: int
    body_coupling: int
    potential_files: tuple[Path, ...]
    wamit_length: tuple[float, ...]
    reference_x: tuple[float, ...]
    reference_y: tuple[float, ...]
    reference_z: tuple[float, ...]
    reference_rotation: tuple[float, ...]
    displaced_volume: tuple[float, ...]
    buoyancy_center_x: tuple[float, ...]
    buoyancy_center_y: tuple[float, ...]
    n_additional_dofs: tuple[int, ...]
    mean_drift: int
    newman_approximation: int
    difference_qtf: int
    sum_qtf: int
    add_force: np.ndarray
    add_stiffness: np.ndarray
    add_damping: np.ndarray
    add_quadratic_damping: np.ndarray
    wave_displaced: int
    added_mass_model: int
    hydrostatic_model: int
    tables: dict
    joint_outputs: tuple[int, ...]
    summary: bool
    output_all: bool
    output_switch: int
    output_format: str
    output_header_format: str
    outputs: tuple[str, ...]
    path: str
    lines: dict = field(default_factory=dict, compare=False)

    @property
    def has_morison_members(self) -> bool:
        """Whether the deck has strip-theory (Morison) members."""
        return len(self.tables["members"]) > 0

    @property
    def second_order(self) -> dict[str, int]:
        """The second-order switches that are on (``{"DiffQTF": 12}``; empty when first order only)."""
        found = {"MnDrift": self.mean_drift, "NewmanApp": self.newman_approximation,
                 "DiffQTF": self.difference_qtf, "SumQTF": self.sum_qtf}
        return {k: v for k, v in found.items() if v}


def _switch(*allowed: int):
    return (lambda v: v in allowed, f"must be one of {', '.join(map(str, allowed))}")


_POSITIVE = (lambda v: v > 0, "must be greater than 0")


def _platform(f: _Lines) -> dict:
    potential = f.key("PotMod", "int", check=_switch(0, 1, 2))
    out = {"potential_model": potential,
           "excitation_model": f.key("ExctnMod", "int", check=_switch(0, 1, 2)),
           "excitation_displaced": f.key("ExctnDisp", "int", check=_switch(0, 1, 2)),
           "excitation_cutoff_hz": f.key("ExctnCutOff", check=_POSITIVE),
           "yaw_model": f.key("PtfmYMod", "int", check=_switch(0, 1)),
           "reference_yaw": (f.key("PtfmRefY") or 0.0) * _DEG,
           "yaw_cutoff_hz": f.key("PtfmYCutOff"),
           "n_excitation_headings": f.key("NExctnHdg", "int"),
           "radiation_model": f.key("RdtnMod", "int", check=_switch(0, 1, 2)),
           "radiation_time_max": f.key("RdtnTMax", check=(lambda v: v >= 0, "must not be negative")),
           # OpenFAST reads RdtnDT only with potential flow (PotMod 1): a deck without it may leave 0 there
           "radiation_time_step": f.key("RdtnDT", "float|default", check=_POSITIVE if potential == 1 else None),
           "n_bodies": f.key("NBody", "int", check=(lambda v: v >= 1, "must be at least 1")),
           "body_coupling": f.key("NBodyMod", "int", check=_switch(1, 2, 3))}
    n_body = out["n_bodies"] or 1
    n_obj = 1 if out["body_coupling"] == 1 else n_body
    roots = f.key("PotFile", "strs", n=n_obj) or ("",) * n_obj
    out["potential_files"] = tuple(_resolve(f.path, r) for r in roots)
    out["wamit_length"] = f.key("WAMITULEN", "floats", n=n_obj)
    for key, attr, scale in (("PtfmRefxt", "reference_x", 1.0), ("PtfmRefyt", "reference_y", 1.0),
                             ("PtfmRefzt", "reference_z", 1.0), ("PtfmRefztRot", "reference_rotation", _DEG),
                             ("PtfmVol0", "displaced_volume", 1.0), ("PtfmCOBxt", "buoyancy_center_x", 1.0),
                             ("PtfmCOByt", "buoyancy_center_y", 1.0)):
        values = f.key(key, "floats", n=n_body)
        out[attr] = tuple(v * scale for v in values) if values else None
    dofs = f.key("NAddDOF", "floats", n=n_body) or (0.0,) * n_body
    out["n_additional_dofs"] = tuple(int(d) for d in dofs)
    return out


def _resolve(base: Path, name: str) -> Path:
    path = Path(name.replace("\\", "/"))
    return path if path.is_absolute() else base.parent / path


def _additional(f: _Lines, n_dof: int, n_obj: int) -> dict:
    force = np.array([f.numbers(n_obj, "AddF0") for _ in range(n_dof)])
    out = {"add_force": force[:, 0] if n_obj == 1 else force}
    for key, attr in (("AddCLin", "add_stiffness"), ("AddBLin", "add_damping"), ("AddBQuad", "add_quadratic_damping")):
        rows = np.array([f.numbers(n_dof * n_obj, key) for _ in range(n_dof)])
        out[attr] = rows if n_obj == 1 else np.stack([rows[:, k * n_dof:(k + 1) * n_dof] for k in range(n_obj)])
    return out


def _morison(f: _Lines) -> dict:
    tables = {}
    rules = iter(("AXIAL COEFFICIENTS", "MEMBER JOINTS", "CYLINDRICAL MEMBER CROSS-SECTION PROPERTIES",
                  "RECTANGULAR MEMBER CROSS-SECTION PROPERTIES", "SIMPLE CYLINDRICAL-MEMBER COEFFICIENTS",
                  "SIMPLE RECTANGULAR-MEMBER COEFFICIENTS", "DEPTH-BASED CYLINDRICAL-MEMBER COEFFICIENTS",
                  "DEPTH-BASED RECTANGULAR-MEMBER COEFFICIENTS", "MEMBER-BASED CYLINDRICAL-MEMBER COEFFICIENTS",
                  "MEMBER-BASED RECTANGULAR-MEMBER COEFFICIENTS", "MEMBERS", "FILLED MEMBERS", "MARINE GROWTH",
                  "MEMBER OUTPUT LIST"))
    for count_key, name, n_min, n_max, text in _TABLES:
        f.rule(next(rules))
        count = 1 if count_key is None else f.key(count_key, "int", check=(lambda v: v >= 0, "must not be negative"))
        header, rows, lines = f.table(count, count_key or name, n_min, n_max, text)
        tables[name] = HydroDynTable(tuple(header), tuple(tuple(r) for r in rows), tuple(lines))
    return tables


def read_hydrodyn(path) -> HydroDynInput:
    """Read a HydroDyn input file (see the module docstring).

    Parameters
    ----------
    path : str or Path
        The HydroDyn ``.dat`` file.

    Returns
    -------
    HydroDynInput

    Raises
    ------
    OpenFASTFormatError
        Missing file, a line out of order (the expected key and the one found), a malformed
        number or switch, a table with fewer rows than its count; names the file, line and key.

    Examples
    --------
    >>> from mbsym.wind.deck.hydrodyn import read_hydrodyn
    >>> hd = read_hydrodyn("IEA-15-240-RWT-UMaineSemi_HydroDyn.dat")  # doctest: +SKIP
    >>> hd.displaced_volume, hd.add_quadratic_damping[0, 0]  # doctest: +SKIP
    ((20206.34889,), 923000.0)
    """
    f = _Lines(Path(path), "HydroDyn input file")
    f.key("Echo", "bool")
    f.rule("FLOATING PLATFORM")
    values = _platform(f)
    f.rule("2ND-ORDER FLOATING PLATFORM FORCES")
    for key, attr in (("MnDrift", "mean_drift"), ("NewmanApp", "newman_approximation"),
                      ("DiffQTF", "difference_qtf"), ("SumQTF", "sum_qtf")):
        values[attr] = f.key(key, "int", check=_switch(0, 7, 8, 9, 10, 11, 12))
    f.rule("PLATFORM ADDITIONAL STIFFNESS AND DAMPING")
    n_body = values["n_bodies"] or 1
    n_obj = 1 if values["body_coupling"] == 1 else n_body
    n_dof = 6 + values["n_additional_dofs"][0] if n_body == 1 else 6 * (n_body if n_obj == 1 else 1)
    values.update(_additional(f, n_dof, n_obj))
    f.rule("STRIP THEORY OPTIONS")
    values["wave_displaced"] = f.key("WaveDisp", "int", check=_switch(0, 1))
    values["added_mass_model"] = f.key("AMMod", "int", check=_switch(0, 1, 2))
    values["hydrostatic_model"] = f.key("HstMod", "int", check=_switch(0, 1))
    values["tables"] = _morison(f)
    f.rule("JOINT OUTPUT LIST")
    n_joint_out = f.key("NJOutputs", "int", check=(lambda v: 0 <= v < 10, "must be 0 to 9")) or 0
    joints = f.key("JOutLst", "floats", n=max(n_joint_out, 1)) or ()
    values["joint_outputs"] = tuple(int(j) for j in joints[:n_joint_out])
    f.rule("OUTPUT")
    values["summary"] = f.key("HDSum", "bool")
    values["output_all"] = f.key("OutAll", "bool")
    values["output_switch"] = f.key("OutSwtch", "int", check=_switch(1, 2, 3))
    values["output_format"] = f.key("OutFmt", "str")
    values["output_header_format"] = f.key("OutSFmt", "str")
    f.rule("OUTPUT CHANNELS")
    values["outputs"] = tuple(f.outlist())
    f.raise_problems()
    return HydroDynInput(**values, path=str(f.path), lines=dict(f.line_of))
