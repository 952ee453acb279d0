"""AeroDyn's sector-averaged inflow (mbsym.wind.aero.sector_average): points, weights, rates, deck keys, refusal.

AeroDyn v5.0.0 ``SetSectAvgInflow`` (AeroDyn.f90): N points on the node's circle about the hub axis at
``ψ_bwd … ψ_fwd`` (defaults 5, −60°, 60°), uniform weights 1/N.
"""

from __future__ import annotations

import math
import re
import shutil
from pathlib import Path

import casadi as ca
import numpy as np
import pytest

from mbsym.exceptions import ParameterError
from mbsym.wind.aero.sector_average import SectorAverage

SHARED = Path(__file__).resolve().parents[3].parent / "shared" / "openfast"


def _np(x) -> np.ndarray:
    return np.asarray(ca.DM(x))


def test_points_lie_on_the_nodes_circle_ahead_and_behind_the_blade():
    sector = SectorAverage()
    hub, axis = ca.DM([5.0, 0.0, 90.0]), ca.DM([1.0, 0.0, 0.0])
    nodes = ca.DM([[5.5, 5.5], [0.0, 0.0], [130.0, 110.0]])            # two nodes above the hub, 0.5 m downwind
    p = _np(sector.points(nodes, hub, axis))
    assert p.shape == (3, 10)
    psi = np.deg2rad([-60.0, -30.0, 0.0, 30.0, 60.0])
    for j, r in enumerate((40.0, 20.0)):
        cols = p[:, j::2]                                               # sector by sector: node j every 2nd column
        want = np.vstack([np.full(5, 5.5), -r * np.sin(psi), 90.0 + r * np.cos(psi)])   # x̂ × ẑ = −ŷ: ahead
        assert cols == pytest.approx(want, abs=1e-12)


def test_average_of_a_sheared_wind_is_the_closed_form():
    sector = SectorAverage()
    hub, axis = ca.DM([0.0, 0.0, 90.0]), ca.DM([1.0, 0.0, 0.0])
    nodes = ca.DM([[0.0], [0.0], [150.0]])
    pts = sector.points(nodes, hub, axis)
    wind = ca.vertcat(10.0 + 0.05 * (pts[2, :] - 90.0), ca.DM.zeros(2, pts.size2()))      # linear shear
    avg = _np(sector.average(wind))
    mean_cos = np.mean(np.cos(np.deg2rad([-60.0, -30.0, 0.0, 30.0, 60.0])))            # 0.7464
    assert avg[:, 0] == pytest.approx([10.0 + 0.05 * 60.0 * mean_cos, 0.0, 0.0], rel=1e-12)
    assert mean_cos == pytest.approx(0.746410, abs=1e-6)


def test_point_velocities_turn_rigidly_with_the_node():
    sector = SectorAverage(7, math.radians(-40.0), math.radians(80.0))
    axis = ca.DM([math.cos(0.1), 0.0, math.sin(0.1)])                # a tilted shaft
    hub, v_hub, omega = ca.DM([1.0, 2.0, 90.0]), ca.DM([0.3, -0.2, 0.1]), 1.2
    nodes = ca.DM([[3.0, -2.0], [10.0, 30.0], [120.0, 60.0]])
    v_nodes = ca.horzcat(*[v_hub + omega * ca.cross(axis, nodes[:, j] - hub) for j in range(2)])
    got = _np(sector.velocities(nodes, v_nodes, hub, v_hub, axis))
    pts = sector.points(nodes, hub, axis)
    want = _np(ca.horzcat(*[v_hub + omega * ca.cross(axis, pts[:, i] - hub) for i in range(pts.size2())]))
    assert got == pytest.approx(want, abs=1e-12)


def test_invalid_sectors_are_refused():
    with pytest.raises(ParameterError, match=">= 2"):
        SectorAverage(1)
    with pytest.raises(ParameterError, match="psi_backward <= 0"):
        SectorAverage(5, 0.2, 1.0)


@pytest.mark.skipif(not (SHARED / "aero").is_dir(), reason="shared NREL 5 MW deck missing")
def test_deck_keys_defaults_and_the_rotor_effective_refusal(tmp_path):
    from mbsym.wind.deck.aero_audit import aerodyn_problems
    from mbsym.wind.deck.aerodyn import read_aerodyn

    deck = tmp_path / "deck"
    shutil.copytree(SHARED / "aero" / "openfast_inputs" / "deck", deck)
    path = deck / "NRELOffshrBsline5MW_Onshore_AeroDyn15.dat"
    assert SectorAverage.from_aerodyn(read_aerodyn(path)) is None
    path.write_text(re.sub(r"^False(\s+SectAvg\s)", r"True\1", path.read_text(), count=1, flags=re.M))
    ad = read_aerodyn(path)
    assert SectorAverage.from_aerodyn(ad) == SectorAverage(5, math.radians(-60.0), math.radians(60.0))
    assert aerodyn_problems(ad, rotor_effective=False) == []
    (problem,) = aerodyn_problems(ad, rotor_effective=True)
    assert "line 36, key 'SectAvg'" in problem and "uniform over the disk" in problem
    text = re.sub(r"^default(\s+SectAvgNPoints)", r"9\1", path.read_text(), count=1, flags=re.M)
    path.write_text(re.sub(r"^default(\s+SectAvgPsiBwd)", r"-30\1", text, count=1, flags=re.M))
    assert SectorAverage.from_aerodyn(read_aerodyn(path)) == SectorAverage(9, math.radians(-30.0), math.radians(60.0))
    path.write_text(re.sub(r"^1(\s+SectAvgWeighting)", r"2\1", path.read_text(), count=1, flags=re.M))
    with pytest.raises(ParameterError, match="uniform weighting"):
        SectorAverage.from_aerodyn(read_aerodyn(path))
