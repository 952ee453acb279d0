"""Shared helpers for the beam preprocessing tests.

Reference data under ``../shared/openfast`` is read here, in the tests only; tests
that need it are skipped when it is absent (the package never needs it).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

SHARED = Path(__file__).resolve().parents[3] / "shared" / "openfast"
NREL5MW = SHARED / "NREL5MW"



@pytest.fixture(scope="session")
def nrel5mw_dir() -> Path:
    """Directory of the NREL 5 MW ElastoDyn reference deck (may not exist)."""
    return NREL5MW


@pytest.fixture(scope="session")
def beta_l() -> np.ndarray:
    """Clamped-free uniform beam roots of cos(x) cosh(x) = -1 (textbook; checked in test_fem)."""
    return np.array([1.8751040687119611, 4.6940911329741745, 7.8547574382376126])


def _table_and_keys(path: Path, header: str, n_key: str) -> tuple[np.ndarray, dict[str, float]]:
    lines = path.read_text().splitlines()
    keys: dict[str, float] = {}
    for ln in lines:
        parts = ln.split()
        if len(parts) >= 2:
            try:
                keys[parts[1]] = float(parts[0])
            except ValueError:
                pass
    start = next(i for i, ln in enumerate(lines) if ln.split() and ln.split()[0] == header) + 2
    n = int(keys[n_key])
    table = np.array([[float(v) for v in lines[start + k].split()] for k in range(n)])
    return table, keys


@pytest.fixture(scope="session")
def nrel_tower() -> dict:
    """NREL 5 MW onshore tower: stations, properties (adjustment factors applied), FA1 coefficients."""
    path = NREL5MW / "NRELOffshrBsline5MW_Onshore_ElastoDyn_Tower.dat"
    if not path.exists():
        pytest.skip(f"reference file {path} not available")
    tab, keys = _table_and_keys(path, "HtFract", "NTwInpSt")
    length = 87.6 - 0.0  # TowerHt - TowerBsHt (paper Sect. 4.4)
    return {
        "length": length, "z": tab[:, 0] * length,
        "m": tab[:, 1] * keys["AdjTwMa"], "ei_fa": tab[:, 2] * keys["AdjFASt"], "ei_ss": tab[:, 3] * keys["AdjSSSt"],
        "fa1": [keys[f"TwFAM1Sh({k})"] for k in range(2, 7)],
    }


@pytest.fixture(scope="session")
def nrel_blade() -> dict:
    """NREL 5 MW blade: stations, properties (AdjBlMs applied), flap1, edge1, flap2 coefficients."""
    path = NREL5MW / "NRELOffshrBsline5MW_Blade.dat"
    if not path.exists():
        pytest.skip(f"reference file {path} not available")
    tab, keys = _table_and_keys(path, "BlFract", "NBlInpSt")
    length = 63.0 - 1.5  # TipRad - HubRad of NREL5MW_ElastoDyn_Onshore.dat
    return {
        "length": length, "hub_radius": 1.5, "z": tab[:, 0] * length, "twist_deg": tab[:, 1],
        "m": tab[:, 2] * keys["AdjBlMs"], "ei_flap": tab[:, 3] * keys["AdjFlSt"], "ei_edge": tab[:, 4] * keys["AdjEdSt"],
        "flap1": [keys[f"BldFl1Sh({k})"] for k in range(2, 7)],
        "flap2": [keys[f"BldFl2Sh({k})"] for k in range(2, 7)],
        "edge1": [keys[f"BldEdgSh({k})"] for k in range(2, 7)],
    }
