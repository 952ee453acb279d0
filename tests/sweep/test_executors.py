"""Every executor gives the serial run's numbers bit for bit, failures included.

Model: NREL 5 MW (built-in data), tower fore-aft + side-side + generator azimuth, free decay
from the deck's initial conditions, swept over the tower stiffness scale; one case with a
hugely negative stiffness diverges and must be reported in its row on every executor.
The Dask test starts a LocalCluster of 2 worker processes on 127.0.0.1 (bounded by timeouts).
"""

import numpy as np
import pytest

from mbsym.sweep import sweep

SCALES = [0.8, 1.0, 1.25, -1e8]


@pytest.fixture(scope="module")
def turbine():
    from mbsym.wind import TurbineModel, nrel5mw

    return TurbineModel(nrel5mw(), dofs=["TwFADOF1", "TwSSDOF1", "GenDOF"])


@pytest.fixture(scope="module")
def serial(turbine):
    return run(turbine, "serial")


def run(model, executor):
    return sweep(model, {"tower_stiffness_scale": SCALES}, tmax=1.0, dt=0.02, executor=executor, series=True,
                 chunk_size=2)


def same(a, b):
    assert a.table.columns == b.table.columns
    for c in a.table.columns:
        if c == "error":
            assert a.table[c] == b.table[c]
        else:
            np.testing.assert_array_equal(a.table[c], b.table[c], err_msg=c)       # bit for bit (NaN = NaN)
    for sa, sb in zip(a.series, b.series):
        assert (sa is None) == (sb is None)
        if sa is not None:
            np.testing.assert_array_equal(sa.x, sb.x)
            np.testing.assert_array_equal(sa.y, sb.y)


def test_serial_reports_the_diverging_case(serial):
    err = serial.table["error"]
    assert err[:3] == ["", "", ""] and err[3].startswith("IntegrationError")
    assert serial.series[3] is None and len(serial.table.columns) > 10      # OpenFAST channels summarized


def test_serial_matches_simulate(turbine, serial):
    """The sweep's RK4 is simulate's rk4: same trajectory (1e-12 relative)."""
    import mbsym as mb

    ref = mb.simulate(turbine, 1.0, p={"tower_stiffness_scale": 1.25}, method="rk4", dt=0.02)
    got = serial.series[2]
    np.testing.assert_allclose(got.x, ref.x, rtol=1e-12, atol=1e-12 * np.abs(ref.x).max())


def test_threads(turbine, serial):
    same(serial, run(turbine, "threads:2"))


def test_processes(turbine, serial):
    same(serial, run(turbine, "processes:2"))


def test_dask_local_cluster(turbine, serial):
    pytest.importorskip("distributed")
    res = run(turbine, "dask:2")
    assert res.executor == "dask:2"
    same(serial, res)
