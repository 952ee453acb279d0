"""TurbineModel against OpenFAST v5 at large motions (issue 10): combined platform rotations and
large blade deflections.

References
----------
- shared/openfast/cases/platform_rpy_gen (PtfmR/P/Y, TwFA1, TwSS1, GenDOF; roll −2°, pitch 1.5°,
  yaw −4°, TTDspSS 0.4 m, 8 rpm) and blades_large_deflection (FlapDOF1, EdgeDOF, GenDOF; OoPDefl 3 m,
  IPDefl −0.8 m, 9 rpm): 30 s free decays, OpenFAST v5.0.0 ElastoDyn only. Acceptance (issue 10):
  ε = mean|y − y_OF| / range(y_OF) ≤ 0.3 % on every channel the model outputs (observed ≤ 0.01 %).
- The t = 0 row of every shared case with ``QD2_*`` channels: the initial accelerations equal
  OpenFAST's to 2e-6 relative (observed ≤ 9e-7 with a tower, ~1e-12 blades only; ElastoDyn computes
  much of the tower in single precision). Before issue 10 these were off by 7e-5 to 5 %.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import mbsym as mb
from mbsym.wind import read_openfast
from mbsym.wind.analysis.compare import TimeSeries, compare, read_csv
from mbsym.wind.structure.turbine import TurbineModel

SHARED = Path(__file__).resolve().parents[2].parent / "shared" / "openfast" / "cases"
NEW_CASES = ["platform_rpy_gen", "blades_large_deflection"]
ALL_CASES = ["paper44_fa_gen", "paper45_fa_ss_gen", "paper46_floating"] + NEW_CASES


def _case(name):
    fst = SHARED / name / f"{name}.fst"
    if not fst.is_file():
        pytest.skip(f"shared OpenFAST case {name} not available")
    return read_openfast(fst), read_csv(SHARED / name / f"{name}.csv")


def _inputs(model):
    d = model.input_defaults()
    return np.array([d[n](0.0) if callable(d[n]) else d[n] for n in model.eom.inputs], dtype=float)


@pytest.mark.parametrize("case", NEW_CASES)
def test_free_decay_matches_openfast(case):
    turbine, ref = _case(case)
    model = TurbineModel(turbine)
    r = mb.simulate(model, float(ref.time[-1]), method="cvodes", rtol=1e-8, atol=1e-10, t_out=ref.time)
    ch = model.output_function()
    units = dict(zip(ch.names, ch.units))
    ours = TimeSeries(r.t, r.output_names, tuple(units[n] for n in r.output_names), r.y)
    rows = compare(ours, ref)
    assert len(rows) >= 15
    for row in rows:
        assert not np.isnan(row["epsilon"]), row          # every reference channel moves in these cases
        assert row["epsilon"] <= 3e-3, row


@pytest.mark.parametrize("case", ALL_CASES)
def test_initial_accelerations_match_openfast(case):
    turbine, ref = _case(case)
    model = TurbineModel(turbine)
    eom = model.eom
    n = eom.n_q
    qdd = np.array(eom.functions.rhs(model.initial_state(), _inputs(model), eom.parameter_vector({}))).ravel()[n:]
    checked = 0
    for i, name in enumerate(eom.coordinates):
        channel = f"QD2_{name}"
        if channel in ref.names:
            sign = -1.0 if name.startswith("TSS") else 1.0     # ElastoDyn's Q_TSS1 = -ours
            expected = ref.channel(channel)[0]
            assert sign * qdd[i] == pytest.approx(expected, rel=2e-6), (name, sign * qdd[i], expected)
            checked += 1
    assert checked >= 1
