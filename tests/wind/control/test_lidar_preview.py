"""The single-point lidar (InflowWind ``SensorType = 1``) and the NMPC's lidar preview.

References: the field itself (a lidar speed is ``|v|`` of the field at its focal point, evaluated
independently here), OpenFAST v5's record layout (``BladedInterface_EX.f90``), closed forms for the
preview (a signal that reaches the rotor a known time after the lidar saw it), and the shared TurbSim
field for what a few points upstream can tell of the rotor's wind.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest

SHARED = Path(__file__).resolve().parents[3].parent / "shared" / "openfast" / "aero"


def _lidar(**changes):
    from mbsym.wind.inflow import PointLidar

    args = dict(focal=[[-60.0, 0.0, 0.0], [-60.0, 44.0, 0.0], [-60.0, -44.0, 0.0], [-60.0, 0.0, 44.0],
                       [-60.0, 0.0, -44.0]], apex_offset=[0.0, 0.0, 0.0], interval=0.1)
    args.update(changes)
    return PointLidar(**args)


def test_lidar_speed_is_the_fields_speed_at_the_focal_point_upstream():
    # A field whose u grows along its time axis: a point d metres upstream sees it d/URef seconds ahead
    # (Taylor), so the lidar at t must read the hub's wind of t + d/URef (closed form), and |v| with v, w.
    from mbsym.wind.inflow import FullFieldWind

    nt, ny, nz = 400, 5, 5
    time = 0.5 * np.arange(nt)
    grid = np.zeros((nt, nz, ny, 3), dtype=np.float32)
    grid[..., 0] = (10.0 + 0.02 * time)[:, None, None]
    grid[..., 1] = 1.0
    grid[..., 2] = -2.0
    f = FullFieldWind(grid, dy=40.0, dz=40.0, dt=0.5, mean_speed=10.0, reference_height=90.0, grid_bottom=10.0)
    lid = _lidar()
    hub = [-5.0, 0.0, 90.0]
    t = 12.3
    got = lid.measure(f, t, hub)
    x = -5.0 - 60.0
    tau = t + (f.initial_x - x) / 10.0                  # the grid time of the focal points
    u = 10.0 + 0.02 * tau
    assert np.allclose(got, math.sqrt(u * u + 1.0 + 4.0), rtol=1e-6)
    assert lid.upstream_distance == 60.0
    assert np.allclose(lid.positions(hub)[:, 0], x)


def test_lidar_equals_openfasts_windmeas_on_the_shared_field(tmp_path):
    # tests/data/openfast_lidar/README.md: OpenFAST v5.0.0's WindMeas1-5 over 30 s on ff14 with this lidar. mbsym's
    # deck (the hub from ElastoDyn's geometry) called every DT = 0.00625 s as ServoDyn calls a library; the
    # measurement times follow InflowWind's exact-multiple test (18.2 s is skipped there: 0.46 m/s off at 99 %
    # with a tolerant test). Tolerance: OpenFAST's 7 printed digits (1e-6 of 19 m/s) and float32 field data.
    import shutil

    from mbsym.wind.operation.deck import operating_deck

    ref = np.loadtxt(Path(__file__).resolve().parents[2] / "data" / "openfast_lidar" / "ff14_lidar_windmeas.csv",
                     delimiter=",", skiprows=1)
    src = SHARED / "openfast_inputs"
    if not (src / "ff14_flex" / "ff14_flex.fst").is_file():
        pytest.skip(f"needs {src} (../shared)")
    for name in ("deck", "ff14_flex"):
        shutil.copytree(src / name, tmp_path / "openfast_inputs" / name)
    (tmp_path / "wind").symlink_to(SHARED / "wind")
    ifw = tmp_path / "openfast_inputs" / "ff14_flex" / "ff14_flex_IfW.dat"
    ifw.write_text(_ifw(tmp_path).read_text().replace("0.25                   MeasurementInterval",
                                                      "0.1                    MeasurementInterval")
                   .replace("1                      ConsiderHubMotion", "0                      ConsiderHubMotion"))
    deck = operating_deck(tmp_path / "openfast_inputs" / "ff14_flex" / "ff14_flex.fst")
    assert deck.inflow.lidar.interval == 0.1 and not deck.inflow.lidar.hub_motion
    measure = deck.lidar_measurement()
    got = np.array([measure(k * 0.00625)[0] for k in range(int(round(30.0 / 0.00625)) + 1)])[::8]
    assert got.shape == ref[:, 1:].shape
    assert np.max(np.abs(got - ref[:, 1:])) < 3e-6 * np.max(ref[:, 1:])
    assert np.ptp(ref[:, 1:]) > 5.0


def test_lidar_measures_at_exact_multiples_and_refuses_bad_beams():
    from mbsym.exceptions import WindInputError

    lid = _lidar(interval=0.25)
    assert lid.measures_at(0.0) and lid.measures_at(1.0) and not lid.measures_at(1.2)
    assert not _lidar(interval=0.1).measures_at(2912 * 0.00625)       # 18.2 s: 18.2 / 0.1 = 181.999... in binary
    with pytest.raises(WindInputError, match="1 to 5 beams"):
        _lidar(focal=np.zeros((6, 3)))
    with pytest.raises(WindInputError, match="MeasurementInterval"):
        _lidar(interval=0.0)


def test_lidar_records_follow_openfasts_extended_layout():
    # BladedInterface_EX.f90 (SetEXavrSWAP_LidarSensors): 2001 type, 2002 beams, 2003 gates, 2004 zero, then the
    # n speeds, the n x, the n y and the n z of the focal points.
    from mbsym.wind.inflow import lidar_records

    rec = lidar_records([11.0, 12.0], [[-65.0, 1.0, 90.0], [-66.0, 2.0, 91.0]])
    assert rec[2001] == 1.0 and rec[2002] == 2.0 and rec[2003] == 1.0 and rec[2004] == 0.0
    assert [rec[r] for r in range(2005, 2013)] == [11.0, 12.0, -65.0, -66.0, 1.0, 2.0, 90.0, 91.0]


def _ifw(tmp_path, sensor="1", beams="5", x="-60 -60 -60 -60 -60"):
    src = SHARED / "openfast_inputs" / "ff14_flex" / "ff14_flex_IfW.dat"
    if not src.is_file():
        pytest.skip(f"needs {src} (../shared)")
    s = src.read_text()
    s = re.sub(r"^0(\s+SensorType)", sensor + r"\1", s, flags=re.M)
    s = re.sub(r"^0(\s+NumBeam)", beams + r"\1", s, flags=re.M)
    s = re.sub(r"^-200(\s+FocalDistanceX)", x + r"\1", s, flags=re.M)
    s = re.sub(r"^0(\s+FocalDistanceY)", r"0 44 -44 0 0\1", s, flags=re.M)
    s = re.sub(r"^0(\s+FocalDistanceZ)", r"0 0 0 44 -44\1", s, flags=re.M)
    s = s.replace('"../../wind/ff14.bts"', f'"{SHARED / "wind" / "ff14.bts"}"')
    p = tmp_path / "ifw.dat"
    p.write_text(s)
    return p


def test_deck_reads_the_single_point_lidar_and_refuses_the_others(tmp_path):
    from mbsym.exceptions import OpenFASTFormatError
    from mbsym.wind.deck.inflowwind import read_inflowwind

    s = read_inflowwind(_ifw(tmp_path))
    assert s.lidar is not None and s.lidar.n_beams == 5 and s.lidar.interval == 0.25 and s.lidar.hub_motion
    assert np.allclose(s.lidar.focal[:, 1], [0, 44, -44, 0, 0])
    with pytest.raises(OpenFASTFormatError, match=r"line \d+, key 'SensorType'.*pulsed"):
        read_inflowwind(_ifw(tmp_path, sensor="3"))
    with pytest.raises(OpenFASTFormatError, match="FocalDistanceX.*needs 5 values"):
        read_inflowwind(_ifw(tmp_path, x="-60 -60"))
    assert read_inflowwind(SHARED / "openfast_inputs" / "ff14_flex" / "ff14_flex_IfW.dat").lidar is None


def _preview(window=0.1, distance=40.5, horizon=40):
    from mbsym.wind.mpc.lidar_preview import LidarPreview, PreviewSettings

    return LidarPreview(PreviewSettings(distance=distance, n_beams=1, window=window), 0.1, horizon, (1.0, 40.0))


def test_preview_gives_the_change_the_lidar_saw_ahead():
    # A wind f reaches the lidar d/U = 4.05 s before the rotor: pushed at t it is f(t + 4.05). After 100 s of
    # steady U (the advection filter settled), a sinusoid: the stage winds must be est + f(t + k dt) - f(t),
    # the stages beyond the lead holding the last value. Tolerance 5e-3 A: linear interpolation between samples
    # 0.1 s apart (dt^2/8 max|f''| = 1.2e-4 A) and the advection filter's ripple (A / (omega T) = A/19 on U:
    # the lead off by 4.05 s x 0.026 / 10 = 0.011 s, f off by A omega 0.011 = 3.4e-3 A).
    A, U, d = 0.5, 10.0, 40.5
    f = lambda t: U + (t > 100.0) * A * np.sin(2 * np.pi * (t - 100.0) / 20.0)          # noqa: E731
    pv = _preview(distance=d)
    n = 1500
    for k in range(n):
        pv.push(0.1 * k, [f(0.1 * k + d / U)])
    t, est = 0.1 * (n - 1), 13.0
    w = pv.horizon(t, est)
    lead = np.minimum(0.1 * np.arange(41), d / U)
    want = est + f(t + lead) - f(t)
    assert w[0] == est
    assert np.max(np.abs(w - want)) < 5e-3 * A
    assert np.ptp(w) > 0.5 * A                                       # the preview moves


def test_preview_moving_average_keeps_its_timing():
    # A ramp through a centred moving average of 10 samples is the ramp itself once delayed by 4.5 samples:
    # the arrival time takes the delay back, so the stage winds climb exactly with the ramp.
    pv = _preview(window=1.0, distance=50.0)
    rate = 0.3                                                     # m/s per s
    for k in range(100):
        pv.push(0.1 * k, [8.0 + rate * (0.1 * k + 5.0)])           # arrives 50 / U later (U = 8 + ...)
    w = pv.horizon(9.9, 10.0)
    assert np.allclose(np.diff(w[:20]), rate * 0.1, rtol=0.02)     # U grows by 0.3 m/s per s: lead shortens 2 %
    assert pv.horizon(9.9, 10.0)[0] == 10.0


def test_preview_without_measurements_holds_the_estimate_and_clips():
    pv = _preview()
    assert np.all(pv.horizon(3.0, 12.5) == 12.5)
    assert np.all(pv.horizon(3.0, 80.0) == 40.0)
    pv.push(0.0, [np.nan, -99.0])                                 # no valid beam: no sample
    assert pv.count == 0


def test_five_points_upstream_predict_the_rotors_wind_change(tmp_path):
    # The shared 14 m/s TurbSim field (frozen turbulence): the change of the rotor-effective wind over the next
    # 3 s, predicted from the lidar's 5 points 60 m upstream, against persistence (no change). A preview that
    # looked the wrong way in time, or at the wrong lead, does no better than persistence; measured 0.55-0.6.
    from mbsym.wind.deck.inflowwind import read_inflowwind
    from mbsym.wind.inflow import rotor_effective_wind
    from mbsym.wind.mpc.lidar_preview import LidarPreview, PreviewSettings

    ifw = read_inflowwind(_ifw(tmp_path))
    field, lid = ifw.field(), ifw.lidar
    hub = [-5.0, 0.0, 90.0]
    times = np.arange(20.0, 500.0, 0.1)
    v = field.velocity(times, lid.positions(hub))
    speeds = np.sqrt(np.sum(v * v, axis=2))
    rotor = rotor_effective_wind(field, times=times, radius=63.0, hub_height=90.0, hub_x=-5.0)["average"]
    pv = LidarPreview(PreviewSettings.for_lidar(lid), 0.1, 40, (1.0, 40.0))
    pred, true = [], []
    for i, t in enumerate(times):
        pv.push(t, speeds[i])
        if t > 40.0 and i + 30 < len(times):
            w = pv.horizon(t, rotor[i])
            pred.append(w[30] - w[0])
            true.append(rotor[i + 30] - rotor[i])
    pred, true = np.array(pred), np.array(true)
    ratio = np.sqrt(np.mean((pred - true) ** 2)) / np.sqrt(np.mean(true ** 2))
    assert ratio < 0.75, ratio


@pytest.mark.slow
def test_library_with_lidar_preview_equals_its_python_mirror(tmp_path):
    # The NMPC exported with a lidar preview, closed on the built-in turbine in mbsym's DISCON loop whose lidar
    # (5 beams, records 2001-2024) reads the Kaimal wind 4 s ahead with a different offset per beam; the Python
    # mirror (SampledLoop with the same LidarPreview arithmetic, CasADi's virtual machine) fed the same float32
    # records sample by sample. Tolerances: tests/wind/control/test_nmpc_export.py (float32 commands). And the
    # preview must change the commands: against the same library's run without lidar records. ~2 min (compile).
    import sys

    sys.path.insert(0, str(Path(__file__).parent))
    from _mpc_setup import library_closed_loop, turbine
    from test_nmpc_export import T_RUN, _controllers, _wind

    from mbsym.codegen import compiler_command
    from mbsym.wind.control import BaselineController
    from mbsym.wind.mpc.discon_nmpc import export_nmpc_discon
    from mbsym.wind.mpc.lidar_preview import PreviewSettings
    from mbsym.wind.mpc.sample import SampledLoop, sample_functions

    if compiler_command() is None:
        pytest.skip("no C compiler (gcc/cc, $CC): the NMPC cannot be exported here")
    t = turbine()
    wind = _wind(T_RUN + 5.0)
    est, nmpc, x0 = _controllers(wind)
    settings = PreviewSettings(distance=56.0, n_beams=5, window=1.0)
    baseline = BaselineController(t.deck.baseline_settings())
    lib = export_nmpc_discon(nmpc, est, baseline, tmp_path, loop_dt=0.01, preview=settings)
    offsets = np.array([0.0, 0.3, -0.2, 0.5, -0.4])

    def run(with_lidar, infile=None):
        seen = []

        def lidar(tt):
            s = float(wind(tt + 4.0)) + offsets
            seen.append(np.asarray(s, dtype=np.float32).astype(float))
            return s, np.zeros((5, 3))

        rows, _, messages = library_closed_loop({**lib, "input": infile or lib["input"]}, wind, T_RUN, x0,
                                                lidar=lidar if with_lidar else None)
        return rows, seen, messages

    rows, seen, messages = run(True)
    assert not any("fallback" in m or "failed" in m or "lidar" in m for m in messages), messages
    est, nmpc, _ = _controllers(wind)
    mirror = SampledLoop(sample_functions(nmpc, est, 0.01, settings=t.deck.baseline_settings(), preview=settings))
    got, ref = [], []
    for (tt, y, u), s in zip(rows[1:], seen[1:]):           # the library answers status 0 with the baseline
        out = mirror.step(tt, y[0] * 30.0 / math.pi, y[6], y[2], y[5], hub_wind=y[4], lidar=s)
        if out is not None:
            got.append(u)
            ref.append(out)
    got, ref = np.array(got), np.array(ref)
    assert len(got) == len(rows) - 1
    assert np.max(np.abs(got[:, 0] - ref[:, 0]) - 1e-6 * np.abs(ref[:, 0])) < 1e-8
    assert np.max(np.abs(got[:, 1] - ref[:, 1]) / np.abs(ref[:, 1])) < 1e-6
    assert np.ptp(mirror.stage_winds) > 0.1                   # the stage winds follow the lidar
    plain, _, messages = run(False)                           # no records: said once, the estimate held
    assert any("no single-point lidar" in m for m in messages), messages
    pitch = np.array([u[0] for _, _, u in rows])
    pitch0 = np.array([u[0] for _, _, u in plain])
    assert np.max(np.abs(pitch - pitch0)) > math.radians(0.1)
    # run-time settings (docs/discon_export.md): the lidar's records there but PreviewSource none is the run without
    # them (no message); a focal distance edited in the input file is what the mirror does with it
    text = Path(lib["input"]).read_text()
    for changes in ({"PreviewSource": "none"}, {"LidarDistance": "80.0"}):
        edited = tmp_path / "edited.IN"
        edited.write_text("".join(f"{changes[line.split()[1]]} {line.split()[1]}\n"
                                  if len(line.split()) > 1 and line.split()[1] in changes else line
                                  for line in text.splitlines(True)))
        rows_e, seen_e, messages = run(True, str(edited))
        assert not any("lidar" in m for m in messages), messages
        if "PreviewSource" in changes:
            assert np.array_equal([u for _, _, u in rows_e], [u for _, _, u in plain])
            continue
        mirror = SampledLoop(mirror.f, changes)
        got = np.array([u for _, _, u in rows_e[1:]])
        ref = np.array([mirror.step(tt, y[0] * 30.0 / math.pi, y[6], y[2], y[5], hub_wind=y[4], lidar=s)
                        for (tt, y, _), s in zip(rows_e[1:], seen_e[1:])], dtype=float)
        assert np.max(np.abs(got[:, 0] - ref[:, 0]) - 1e-6 * np.abs(ref[:, 0])) < 1e-8
        assert np.max(np.abs(got[:, 0] - pitch[1:])) > math.radians(0.01)      # the distance changes the commands


def test_turbine_loop_refuses_a_lidar_it_cannot_use():
    from mbsym.exceptions import SimulationOptionError
    from mbsym.wind.mpc import TurbineLoop
    from mbsym.wind.mpc.lidar_preview import PreviewSettings

    settings = PreviewSettings(distance=60.0, n_beams=5)
    with pytest.raises(SimulationOptionError, match="both lidar="):
        TurbineLoop(None, 0.01, nmpc=object(), lidar=lambda t: ([10.0] * 5, None))
    with pytest.raises(SimulationOptionError, match="NMPC with an estimator"):
        TurbineLoop(None, 0.01, nmpc=object(), lidar=lambda t: ([10.0] * 5, None), lidar_preview=settings)


def test_cli_run_with_another_wind_leaves_the_decks_lidar_out(tmp_path):
    from types import SimpleNamespace

    from mbsym.cli.operate import run_lidar
    from mbsym.exceptions import ModelWarning
    from mbsym.wind.deck.inflowwind import read_inflowwind

    deck = SimpleNamespace(inflow=read_inflowwind(_ifw(tmp_path)), lidar_measurement=lambda: "measured")
    with pytest.warns(ModelWarning, match="--wind steady:12"):
        assert run_lidar(SimpleNamespace(wind="steady:12"), deck) is None
    assert run_lidar(SimpleNamespace(wind=None), deck) == "measured"
    assert run_lidar(SimpleNamespace(wind=None), SimpleNamespace(inflow=None)) is None


def test_example_runs_and_shows_the_4_s_average_predicting():
    import subprocess
    import sys

    if not (SHARED / "wind" / "ff14.bts").is_file():
        pytest.skip("needs ../shared's ff14.bts (the example's default field)")
    example = Path(__file__).resolve().parents[3] / "examples" / "lidar_preview.py"
    out = subprocess.run([sys.executable, str(example)], capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr[-2000:]
    row = next(line for line in out.stdout.splitlines() if line.strip().startswith("4 s"))
    ratios = [float(v) for v in row.split("|")[1].split()]
    assert len(ratios) == 4 and max(ratios[1:]) < 0.8               # better than persistence 2-4 s ahead
