"""Locate (or fetch once) the real ROSCO controller library for tests and benchmarks.

Not part of the package: the ``rosco`` wheel is fetched with ``pip download
--no-deps rosco==<version>`` (no dependency tree is installed) into a cache, and
only ``rosco/lib/libdiscon.so`` with its bundled gfortran runtime (``rosco.libs/``,
found through ``$ORIGIN/../../rosco.libs``) and the NREL 5 MW inputs are extracted.

Cache: ``$MBSYM_ROSCO_DIR`` if set, else ``~/.cache/mbsym/rosco/<version>``.
Without registry access (or on a platform without a wheel) :func:`rosco_library`
returns None and callers skip.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import tempfile
import zipfile
from pathlib import Path

VERSION = "2.10.6"
_MEMBERS = ("rosco/lib/", "rosco.libs/", "Examples/Test_Cases/NREL-5MW/DISCON.IN",
            "Examples/Test_Cases/NREL-5MW/Cp_Ct_Cq.NREL5MW.txt")


def cache_dir(version: str = VERSION) -> Path:
    root = os.environ.get("MBSYM_ROSCO_DIR")
    return Path(root) if root else Path.home() / ".cache" / "mbsym" / "rosco" / version


def _library(folder: Path) -> Path:
    return folder / "rosco" / "lib" / ("libdiscon.dylib" if sys.platform == "darwin" else "libdiscon.so")


def rosco_library(version: str = VERSION, *, fetch: bool = True, timeout: float = 180.0) -> Path | None:
    """Path of ROSCO's ``libdiscon.so`` (extracted from the cached wheel), or None if unavailable."""
    folder = cache_dir(version)
    lib = _library(folder)
    if lib.is_file():
        return lib
    wheels = sorted(folder.glob(f"rosco-{version}-*.whl")) if folder.is_dir() else []
    if not wheels and fetch:
        folder.mkdir(parents=True, exist_ok=True)
        try:
            subprocess.run([sys.executable, "-m", "pip", "download", "--no-deps", "--quiet",
                            "--disable-pip-version-check", f"rosco=={version}", "-d", str(folder)],
                           check=True, timeout=timeout,
                           stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        except (subprocess.SubprocessError, OSError):
            return None
        wheels = sorted(folder.glob(f"rosco-{version}-*.whl"))
    if not wheels:
        return None
    with tempfile.TemporaryDirectory(dir=folder) as tmp, zipfile.ZipFile(wheels[-1]) as wheel:
        names = [n for n in wheel.namelist() if n.startswith(_MEMBERS)]
        wheel.extractall(tmp, members=names)
        for top in ("rosco", "rosco.libs", "Examples"):
            if (Path(tmp) / top).exists() and not (folder / top).exists():
                shutil.move(str(Path(tmp) / top), str(folder / top))
    return lib if lib.is_file() else None


def rosco_nrel5mw_discon(version: str = VERSION) -> Path | None:
    """The wheel's own NREL 5 MW ``DISCON.IN`` (after :func:`rosco_library`), or None."""
    path = cache_dir(version) / "Examples" / "Test_Cases" / "NREL-5MW" / "DISCON.IN"
    return path if path.is_file() else None


def rosco_nrel5mw_deck(version: str = VERSION, *, fetch: bool = True) -> Path | None:
    """The wheel's whole OpenFAST NREL 5 MW test case (``Examples/Test_Cases/NREL-5MW/NREL-5MW.fst`` with its
    ElastoDyn, ServoDyn, AeroDyn, InflowWind and airfoil files), extracted once into the cache; None if the
    wheel is not available (callers skip)."""
    return rosco_test_case("NREL-5MW", "NREL-5MW.fst", version, fetch=fetch)


def rosco_test_case(case: str, fst_name: str, version: str = VERSION, *, fetch: bool = True) -> Path | None:
    """The ``.fst`` of the wheel's OpenFAST test case ``Examples/Test_Cases/<case>/`` (every file of the folder;
    ``fst_name`` relative to it), extracted once into the cache; None if the wheel is not available (callers
    skip)."""
    folder = cache_dir(version)
    fst = folder / "deck" / case / fst_name
    if fst.is_file():
        return fst
    if rosco_library(version, fetch=fetch) is None:
        return None
    wheels = sorted(folder.glob(f"rosco-{version}-*.whl"))
    if not wheels:
        return None
    prefix = f"Examples/Test_Cases/{case}/"
    (folder / "deck").mkdir(exist_ok=True)
    with tempfile.TemporaryDirectory(dir=folder / "deck") as tmp, zipfile.ZipFile(wheels[-1]) as wheel:
        wheel.extractall(tmp, members=[n for n in wheel.namelist() if n.startswith(prefix)])
        root = folder / "deck" / case
        if not root.exists() and (Path(tmp) / prefix).is_dir():
            shutil.move(str(Path(tmp) / prefix), str(root))
    return fst if fst.is_file() else None
