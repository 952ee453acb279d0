"""A ROSCO input with flap control where ServoDyn sends no airfoil commands is named before the library runs.

Reference: the `rosco` 2.10.6 wheel's BAR_10 deck (``Flp_Mode`` 2, ServoDyn ``AfCmode`` 0): its library stops with
a segmentation fault at the first call, in OpenFAST v5.0.0 and in mbsym's DISCON loop (benchmarks/README.md, "The
`rosco` wheel's own decks"); with ``Flp_Mode`` 0 both run. A crash inside the library cannot be caught, so mbsym
says it first.
"""

from __future__ import annotations

import re
import warnings
from pathlib import Path
from types import SimpleNamespace

import pytest

from mbsym.cli.operate import _warn_flap_control
from mbsym.exceptions import ModelWarning

SHARED_DISCON = Path(__file__).resolve().parents[3].parent / "shared" / "openfast" / "aero" / "openfast_inputs" / \
    "deck" / "DISCON.IN"


def test_flap_control_without_airfoil_commands_is_named(tmp_path):
    if not SHARED_DISCON.is_file():
        pytest.skip(f"shared reference data not found at {SHARED_DISCON}")
    text = SHARED_DISCON.read_text()
    flap = tmp_path / "DISCON.IN"
    flap.write_text(re.sub(r"^(\s*)\S+(\s+!\s*Flp_Mode\b)", r"\g<1>2\2", text, count=1, flags=re.M))
    deck = SimpleNamespace(servodyn=SimpleNamespace(airfoil_control_mode=0))
    with pytest.warns(ModelWarning, match=r"Flp_Mode = 2 asks ROSCO for flap control.*AfCmode is 0"):
        _warn_flap_control(flap, deck)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        _warn_flap_control(SHARED_DISCON, deck)                    # Flp_Mode 0: nothing
        _warn_flap_control(tmp_path / "missing.in", deck)          # not a ROSCO input: nothing
