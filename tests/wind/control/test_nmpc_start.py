"""The exported NMPC's QP through a start far from steady operation: measured inside OpenFAST, replayed here.

Reference (independent of the code under test): OpenFAST v5.0.0's measurements of the ROSCO wheel's stock NREL
5 MW deck at a steady 16 m/s from its initial conditions (pitch 0, at rest and undeflected), closed on the
library ``mbsym export-discon NREL-5MW.fst --controller nmpc`` built before this change
(``tests/data/openfast_nrel5mw_nmpc_start16/README.md``). Inside OpenFAST that library's QP, capped at its
iteration count (the bounded worst case of a real-time step), failed at every NMPC sample from 2.7 to 6.6 s and
the plan of 2.6 s was held all along (the rotor at +29 %): the next QP was warm-started from the multipliers of
the last *accepted* QP every time, so the active-set search never got further than its cap. Now a capped QP's
multipliers are the next QP's start (the library's C and its Python mirror alike).

The library's Python mirror (:class:`mbsym.wind.mpc.sample.SampledLoop`, equal to the library to 1e-6 in
``test_nmpc_export.py``) of the same CLI export, fed the record's measurements (float32, as the swap array holds
them), replays the library's holds exactly as they were (0.1, 0.2, 0.9-1.2, 1.5-1.7, 2.7-6.5 s: 48 and then the
baseline) when the capped QP's multipliers are dropped, and holds 5 times when they are kept.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

RECORD = Path(__file__).resolve().parents[2] / "data" / "openfast_nrel5mw_nmpc_start16" / "record.csv"


@pytest.fixture(scope="module")
def exported():
    """The sample Functions, settings and sample time ``mbsym export-discon`` builds for the stock deck (captured
    where the CLI hands them to the C export)."""
    import contextlib
    import io

    import _rosco

    import mbsym.wind.mpc.discon_nmpc as dn
    from mbsym.cli import main
    from mbsym.wind.mpc.sample import sample_functions

    fst = _rosco.rosco_nrel5mw_deck()
    if fst is None:
        pytest.skip("the ROSCO 2.10.6 wheel is not cached and could not be fetched with pip")
    got = {}

    def capture(nmpc, estimator, baseline, out_dir, **options):
        got.update(nmpc=nmpc, estimator=estimator, baseline=baseline, **options)
        return {"library": "", "input": "", "controller": "nmpc", "sample_time_s": options["loop_dt"]}

    real, dn.export_nmpc_discon = dn.export_nmpc_discon, capture
    try:
        with contextlib.redirect_stdout(io.StringIO()):
            assert main(["export-discon", str(fst), "--controller", "nmpc", "--out", "unused"]) == 0
    finally:
        dn.export_nmpc_discon = real
    f = sample_functions(got["nmpc"], got["estimator"], got["loop_dt"], settings=got["baseline"].settings,
                         initial=got["initial"])
    return f, got["loop_dt"]


def _replay(f, dt):
    from mbsym.wind.mpc.sample import SampledLoop

    names = RECORD.read_text().splitlines()[0].split(",")
    data = np.loadtxt(RECORD, delimiter=",", skiprows=1)
    col = {n.split(" [")[0]: data[:, i] for i, n in enumerate(names)}
    f32 = lambda v: float(np.float32(v))                                       # noqa: E731 - the swap array
    loop = SampledLoop(f)
    for k in range(len(data)):
        loop.step(k * dt, f32(col["GenSpeed"][k] * math.pi / 30.0) * 30.0 / math.pi, f32(col["YawBrTAxp"][k]),
                  f32(math.radians(col["BldPitch1"][k])), f32(col["GenTq"][k] * 1e3), hub_wind=f32(col["Wind1VelX"][k]))
    return loop


def test_a_capped_qp_hands_its_active_set_to_the_next(exported):
    # Bound: 10 holds and no fallback in the 8 s (measured 5 holds; with the old warm start 48 holds in a row from
    # 2.7 s, then the baseline).
    f, dt = exported
    assert dt == pytest.approx(0.00625)
    loop = _replay(f, dt)
    assert len(loop.holds) <= 10 and not loop.failures, (loop.holds, loop.failures)
    assert not [h for h in loop.holds if 3.0 <= h <= 6.5]


def test_the_old_warm_start_reproduces_the_streak_openfast_saw(exported, monkeypatch):
    # The record is reproduced: with the capped QP's multipliers dropped (the library of the record), the mirror
    # holds at the NMPC samples where the library inside OpenFAST said it did (its messages: every 0.1 s from 2.7
    # to 6.5 s, 39 in a row, then the baseline at 6.6 s).
    from mbsym.wind.mpc.sample import SampledLoop

    f, dt = exported
    monkeypatch.setattr(SampledLoop, "_after_failure", staticmethod(lambda held, capped: held))
    loop = _replay(f, dt)
    streak = [h for h in loop.holds if 2.65 <= h <= 6.55]
    assert len(streak) == 39, loop.holds
    assert loop.failures == [pytest.approx(6.6, abs=0.01)]
