"""Plots and tables of a first contact (issue 22 item 12): each point reproduced, then checked fixed.

References are independent of the code under test: the built-in turbine's initial side-side displacement
is exactly zero (its initial conditions); a compiled run either loads a library or does not; transfer
functions whose phase is computed by hand; file names given by the test.
"""

import re
import warnings

import casadi as ca
import numpy as np
import pytest

import mbsym as mb
from mbsym.cli import main
from mbsym.cli._run import number
from mbsym.simulate import DiscreteController, simulate


# ------------------------------------------------------------------------------------- "-0" in tables
def test_number_never_prints_a_negative_zero():
    assert number(-0.0, "12.5g").strip() == "0"
    assert number(-1e-9, ".4f") == "0.0000"                 # rounds to zero: no sign
    assert number(-0.5, "g") == "-0.5" and number(-1e-300, "g") == "-1e-300"   # real negatives keep it
    assert number(float("nan"), "g") == "nan"


def test_decay_table_prints_no_negative_zero(capsys):
    # the built-in decay starts at Q_TSS1 = -0.0 (a negated zero initial condition): the table printed "-0"
    assert main(["simulate", "--tmax", "0.1", "--method", "rk4"]) == 0
    table = capsys.readouterr().out.split("channel", 1)[1]
    assert not re.search(r"(?<![\w.])-0(\.0*)?(?![\d.e])", table), table
    row = next(line.split() for line in table.splitlines() if line.startswith("Q_TSS1"))
    assert row[2] == "0"                                    # initial side-side displacement: exactly zero


# ------------------------------------------------------------------------------------- cache_hit
def _first_order_loop():
    x, u, p = ca.SX.sym("x"), ca.SX.sym("u"), ca.SX.sym("p", 0)
    plant = mb.Dynamics(ca.Function("f", [x, u, p], [-x + u]), states=["x"], inputs=["u"], name="lag12")
    i, y = ca.SX.sym("i"), ca.SX.sym("y")
    law = ca.Function("law", [i, y], [i + 0.1 * (1 - y), 2 * (1 - y) + i])
    return plant, DiscreteController(law, 0.1, measurements=["x"], actuates=["u"], state_names=["i"])


@pytest.mark.parametrize("compiled", [False, True])
def test_closed_loop_reports_cache_hit(compiled):
    # the closed loop reported cache_hit = null (and disk_cache_hit = null) whatever happened
    from mbsym.codegen import compiler_command

    if compiled and compiler_command() is None:
        pytest.skip("no C compiler")
    plant, ctrl = _first_order_loop()
    first = simulate(plant, 1.0, controller=ctrl, method="rk4", compile=compiled)
    again = simulate(plant, 1.0, controller=ctrl, method="rk4", compile=compiled)
    assert first.statistics["cache_hit"] is False and again.statistics["cache_hit"] is True
    np.testing.assert_array_equal(first.x, again.x)         # the same loop, from the cache
    assert first.statistics["compiled"] is compiled
    if compiled:                                            # a library was loaded: from the disk or not
        assert isinstance(again.statistics["disk_cache_hit"], bool)
        assert again.statistics["disk_cache_hit"] is True   # the first run compiled it into the disk cache
    else:
        assert first.statistics["disk_cache_hit"] is None   # nothing loaded (Result.statistics doc)


# ------------------------------------------------------------------------------------- BeamModes repr
def test_beam_modes_repr_is_a_short_summary():
    # the dataclass repr printed every node's displacement and slope of every mode (~100 lines)
    from mbsym.beam.fem import cantilever_modes

    modes = cantilever_modes([0.0, 10.0], 1.0, 1.0, n_modes=8, n_elements=50)
    text = repr(modes)
    assert len(text.splitlines()) <= 10 and len(text) < 300, text
    assert text.startswith("BeamModes(8 modes:") and "51 nodes over [0, 10] m" in text and "..." in text
    # the first frequency shown is the uniform cantilever's closed form (βL)² / (2π L²) √(EI/m), βL = 1.875104,
    # to the 4 digits printed (the FEM error with 50 elements is ~1e-8 relative)
    shown = float(re.search(r"modes: ([\d.e+-]+),", text).group(1))
    assert shown == pytest.approx(1.875104**2 / (2 * np.pi * 100.0), rel=5e-4)
