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
    from mbsym.beam.fem import BeamModes

    # the uniform cantilever's frequencies (βL)² / (2π L²) √(EI/m), L = 10 m, EI = m = 1, for 8 modes
    beta_l = np.array([1.875104, 4.694091, 7.854757] + [(k - 0.5) * np.pi for k in range(4, 9)])
    f = beta_l**2 / (2 * np.pi * 100.0)
    nodes = np.linspace(0.0, 10.0, 51)
    modes = BeamModes(f, nodes, np.ones((8, 51)), np.zeros((8, 51)), "x")
    text = repr(modes)
    assert len(text.splitlines()) <= 10 and len(text) < 300, text
    assert text.startswith("BeamModes(8 modes:") and "51 nodes over [0, 10] m" in text and "..." in text
    shown = [float(v) for v in re.search(r"modes: (.*), \.\.\. Hz", text).group(1).split(", ")]
    np.testing.assert_allclose(shown, f[:6], rtol=5e-4)     # the first six, to the 4 digits printed


# ------------------------------------------------------------------------------------- plots: labels, styles
def _series(names, columns, t):
    from mbsym.wind.analysis.compare import TimeSeries

    return TimeSeries(np.asarray(t, float), tuple(names), tuple("m" for _ in names), np.column_stack(columns))


def _lines(fig):
    """(label, linestyle) of every line of the first panel, and the figure's title."""
    ax = fig.axes[0]
    return [(line.get_label(), line.get_linestyle()) for line in ax.get_lines()], ax.get_title()


def test_single_run_is_solid_and_labelled_as_given():
    # a run without a reference was drawn dashed ("--") and called only "mbsym"
    import matplotlib.pyplot as plt

    from mbsym.wind.analysis.compare import overlay_figure

    t = np.linspace(0.0, 1.0, 11)
    ours = _series(["Q_TFA1"], [np.cos(t)], t)
    fig = overlay_figure(ours, title="deck.fst in steady 14 m/s, baseline controller",
                         label="mbsym (rotor-effective, baseline controller)")
    lines, title = _lines(fig)
    plt.close(fig)
    assert lines == [("mbsym (rotor-effective, baseline controller)", "-")]
    assert title == "deck.fst in steady 14 m/s, baseline controller"


def test_reference_is_labelled_by_its_file():
    # --compare labelled any CSV "OpenFAST"; the CLI now passes the file's stem
    import matplotlib.pyplot as plt

    from mbsym.cli._run import compare_label
    from mbsym.wind.analysis.compare import overlay_figure

    t = np.linspace(0.0, 1.0, 11)
    ours, ref = _series(["Q_TFA1"], [np.cos(t)], t), _series(["Q_TFA1"], [np.cos(t) + 0.01], t)
    fig = overlay_figure(ours, ref, label="mbsym", ref_label=compare_label("/data/runs/ff14_flex.csv"))
    lines, _ = _lines(fig)
    plt.close(fig)
    assert lines == [("ff14_flex", "-"), ("mbsym", "--")]        # reference solid, ours dashed over it


@pytest.mark.parametrize("spec, words", [
    ("steady:14", "steady 14 m/s"),
    ("step:10:14:30", "step 10 to 14 m/s at 30 s"),
    ("ramp:8:12:10:20", "ramp 8 to 12 m/s over 10-20 s"),
    ("kaimal:14:16%:3", "Kaimal 14 m/s TI 16 % seed 3"),
    ("eog:14:10:5", "EOG at 14 m/s, gust 5 m/s from 10 s"),
])
def test_plot_title_names_the_wind(spec, words):
    from types import SimpleNamespace

    from mbsym.cli.operate import _wind_words
    from mbsym.wind.inflow import parse_wind_spec

    # the numbers in the expected words are those of the spec, typed by hand
    assert _wind_words(SimpleNamespace(wind=spec), None, parse_wind_spec(spec, duration=20.0)) == words


def test_plot_title_names_a_deck_wind_file_and_the_controller():
    from pathlib import Path
    from types import SimpleNamespace

    from mbsym.cli.operate import _controller_words
    from mbsym.cli.operate_mpc import MpcOptions

    from mbsym.cli.operate import _wind_words

    ff = SimpleNamespace(wind_type=3, full_field_file_name="Wind/ff14.bts", uniform_file_name="")
    assert _wind_words(SimpleNamespace(wind=None), SimpleNamespace(inflow=ff), None) == "ff14.bts (InflowWind)"
    steady = SimpleNamespace(wind_type=1, steady_speed=11.4)
    assert _wind_words(SimpleNamespace(wind=None), SimpleNamespace(inflow=steady), None) == \
        "steady 11.4 m/s (InflowWind)"
    args, deck = SimpleNamespace(discon=None), SimpleNamespace(library=Path("/x/libdiscon.so"))
    assert _controller_words("discon", args, deck, MpcOptions("discon", None, None)) == "DISCON libdiscon.so"
    assert _controller_words("baseline", args, deck, MpcOptions("baseline", None, None)) == "baseline controller"
    assert _controller_words("nmpc", args, deck, MpcOptions("nmpc", None, "ekf")) == "NMPC, ekf estimator"
    assert _controller_words("none", args, deck, MpcOptions("none", None, None)).startswith("no controller")


# ------------------------------------------------------------------------------------- comparison table
def test_comparison_table_summarizes_channels_constant_in_both(capsys):
    # 40 channels that are zero in both series printed 40 "const" rows; one line now says so
    from mbsym.cli._run import report_comparison

    t = np.linspace(0.0, 2.0, 21)
    zeros = [f"Load{i}" for i in range(40)]
    names = ["Q_TFA1", "TTDspSS", "Offset"] + zeros
    ours = _series(names, [np.cos(t), 1e-3 * np.sin(t), np.full_like(t, 1.0)] + [0 * t] * 40, t)
    ref = _series(names, [np.cos(t), 0 * t, np.full_like(t, 2.0)] + [0 * t] * 40, t)
    report_comparison(ours, ref)
    out = capsys.readouterr().out
    rows = [line.split()[0] for line in out.splitlines()[2:] if line and not line.startswith("40 ")]
    assert rows == ["Q_TFA1", "TTDspSS", "Offset"]      # moving in one, or constant but different: kept
    assert "40 channels constant and equal in both (not in the table): Load0, Load1," in out
    assert out.count("\n") == 6, out                    # blank, header, 3 rows, the summary line


def test_cli_plot_and_table_of_a_compared_csv(tmp_path, monkeypatch, capsys):
    # the free decay against a CSV named by the test: legend, title and the table's summary line
    import mbsym.wind.analysis.compare as compare

    seen = {}
    monkeypatch.setattr(compare, "overlay_plot", lambda path, *a, **k: seen.update(k) or open(path, "wb").close())
    csv = tmp_path / "ff14_flex.csv"
    t = np.arange(0.0, 0.21, 0.05)
    np.savetxt(csv, np.column_stack([t, 0.5 * np.cos(t), 0 * t]), delimiter=",", comments="",
               header="Time_[s],Q_TFA1_[m],PtfmPitch_[deg]")
    png = tmp_path / "p.png"
    assert main(["simulate", "--tmax", "0.2", "--method", "rk4", "--compare", str(csv), "--plot", str(png)]) == 0
    out = capsys.readouterr().out
    assert seen["ref_label"] == "ff14_flex" and seen["label"].startswith("mbsym (rk4")
    assert "1 channel constant and equal in both (not in the table): PtfmPitch" in out
    assert not re.search(r"^PtfmPitch\s+const", out, re.M)


# ------------------------------------------------------------------------------------- loop failures
def test_estimator_failures_are_a_warning_not_only_a_stats_key():
    # "estimator_failures": 7 appeared only in --stats; simulate_with_loop now warns with every run
    from mbsym.exceptions import ConvergenceWarning
    from mbsym.wind.mpc.loop import warn_failures

    with pytest.warns(ConvergenceWarning, match="the mhe estimator failed 7 times; it fell back to the EKF"):
        warn_failures({"estimator": "mhe", "estimator_failures": 7, "controller_failures": 0})
    with pytest.warns(ConvergenceWarning, match="the NMPC failed 2 of 300 steps"):
        warn_failures({"controller_failures": 2, "controller_steps": 300})
    with warnings.catch_warnings():
        warnings.simplefilter("error")                      # no failure: no warning at all
        assert warn_failures({"estimator": "ekf", "estimator_failures": 0, "controller_failures": 0}) == []


# ------------------------------------------------------------------------------------- cut-out
@pytest.mark.parametrize("spec, words", [
    ("steady:30", "the wind is 30 m/s"),
    ("step:20:30:50", "the wind is 30 m/s from t = 50 s"),
    ("ramp:20:30:10:20", "the wind is 30 m/s from t = 20 s"),
    ("eog:26:10:5", "the wind is 26 m/s before the gust"),
    ("steady:25", None),                                    # at cut-out: still operating
    ("step:10:24:5", None),
    ("eog:20:10:8", None),                                  # a gust above 25 m/s is a transient, not a mean
])
def test_wind_above_cut_out_is_named(spec, words):
    from mbsym.wind.inflow import parse_wind_spec
    from mbsym.wind.operation.cut_out import above_cut_out

    assert above_cut_out(parse_wind_spec(spec, duration=60.0), 60.0, 25.0) == words


def test_turbulent_wind_is_judged_by_its_mean():
    # a table whose samples swing 20..30 m/s around a mean of 25 m/s +- 2: the 10-min means decide (IEC 61400-1)
    from mbsym.wind.inflow import TabulatedWind
    from mbsym.wind.operation.cut_out import above_cut_out

    t = np.arange(0.0, 60.05, 0.05)
    swing = 5.0 * np.sin(2 * np.pi * t)                     # zero mean over whole periods
    assert above_cut_out(TabulatedWind(t, 24.0 + swing), 60.0, 25.0) is None       # peaks 29 m/s, mean 24
    assert above_cut_out(TabulatedWind(t, 26.0 + swing), 60.0, 25.0) == "the mean wind over the run is 26 m/s"


def test_cut_out_warning_says_value_and_source_and_none_when_unknown():
    from mbsym.exceptions import ModelWarning
    from mbsym.wind.inflow import SteadyWind
    from mbsym.wind.operation.cut_out import NREL5MW_CUT_OUT, warn_above_cut_out

    assert NREL5MW_CUT_OUT[0] == 25.0                       # Jonkman et al. 2009, Table 1-1
    with pytest.warns(ModelWarning, match=r"30 m/s, above the NREL 5 MW's cut-out wind speed \(Jonkman .*\), "
                                          r"25 m/s: a real turbine would be shut down"):
        warn_above_cut_out(SteadyWind(30.0), 60.0, *NREL5MW_CUT_OUT)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert warn_above_cut_out(SteadyWind(30.0), 60.0, None, "") is None   # a deck states no cut-out


@pytest.mark.slow
def test_cli_steady_30_on_the_builtin_turbine_warns_and_titles_its_plot(tmp_path, monkeypatch, capsys):
    # `mbsym simulate --wind steady:30` ran above the NREL 5 MW's 25 m/s cut-out without a word, and its plot was
    # titled with the turbine alone (builds the built-in operating model: ~10 s)
    import mbsym.wind.analysis.compare as compare

    seen = {}
    monkeypatch.setattr(compare, "overlay_plot", lambda path, *a, **k: seen.update(k) or open(path, "wb").close())
    assert main(["simulate", "--wind", "steady:30", "--tmax", "1", "--plot", str(tmp_path / "p.png")]) == 0
    err = capsys.readouterr().err
    warning = [line for line in err.splitlines() if "cut-out" in line]
    assert len(warning) == 1 and warning[0].startswith("mbsym simulate: warning: the wind is 30 m/s, above the "
                                                       "NREL 5 MW's cut-out wind speed"), err
    assert seen["title"] == "NREL 5 MW onshore (built-in) in steady 30 m/s, baseline controller"
    assert seen["label"] == "mbsym (rotor-effective, baseline controller)"


# ------------------------------------------------------------------------------------- Bode phase
def test_bode_phase_of_an_integrator_with_two_lags_by_hand():
    # L(s) = 1 / (s (1 + s/ω1)²), ω1 = 2π rad/s: phase −90° − 2 atan(ω/ω1), from −90° towards −270°
    from mbsym.linear import frequency_response

    w1 = 2 * np.pi
    f = np.logspace(-3, 3, 61)
    r = frequency_response(lambda f: 1 / (2j * np.pi * f * (1 + 2j * np.pi * f / w1) ** 2), f)
    np.testing.assert_allclose(r.phase_deg, -90 - 2 * np.degrees(np.arctan(2 * np.pi * r.freq_hz / w1)),
                               atol=1e-9)               # exact but for rounding
    assert -90 > r.phase_deg[0] > -90.2 and -270 < r.phase_deg[-1] < -269.8


def test_bode_phase_of_a_sampled_integrator_by_hand():
    # ZOH integrator dt / (z − 1) at z = exp(jθ), θ = 2π f dt: phase −90° − θ/2 [deg], −180° at the Nyquist frequency
    from mbsym.linear import frequency_response

    dt = 0.01
    f = np.linspace(0.01, 50.0 * (1 - 1e-9), 40)
    r = frequency_response(lambda f: dt / (np.exp(2j * np.pi * f * dt) - 1), f)
    np.testing.assert_allclose(r.phase_deg, -90 - 180 * r.freq_hz * dt, atol=1e-9)


def test_bode_phase_through_lightly_damped_modes_is_resolved():
    # two coincident modes 1/(s² + 2ζ s + 1)², ζ = 1e-3: the phase falls by 360° within a relative band of
    # ~0.2 %; unwrapping a grid of 10 points per decade sees no change at all (it loses 360°), the refined
    # response follows −2 atan2(2ζω, 1 − ω²) (by hand) to the end
    from mbsym.linear import frequency_response

    zeta = 1e-3

    def h(f):
        s = 2j * np.pi * f
        return 1 / (s**2 + 2 * zeta * s + 1) ** 2

    f = np.logspace(-2, 1, 31)
    naive = np.degrees(np.unwrap(np.angle(h(f))))
    assert abs(naive[-1]) < 1.0                             # the coarse-grid artifact this fixes
    r = frequency_response(h, f)
    w = 2 * np.pi * r.freq_hz
    np.testing.assert_allclose(r.phase_deg, -2 * np.degrees(np.arctan2(2 * zeta * w, 1 - w**2)), atol=1e-6)
    assert r.phase_deg[-1] == pytest.approx(-360.0, abs=0.1)
    assert np.all(np.abs(np.diff(r.phase_deg)) <= 10.0 + 1e-9)   # every step resolved (max_phase_step_deg)


def test_wrapped_phase_band_and_the_start_band():
    from mbsym.linear import FrequencyResponse, anchored_phase_deg

    r = FrequencyResponse(np.arange(5.0), np.ones(5), np.zeros(5), np.array([0.0, -90.0, -180.0, -360.0, -810.0]))
    np.testing.assert_allclose(r.wrapped_phase_deg(), [0.0, -90.0, -180.0, 0.0, -90.0])
    np.testing.assert_allclose(r.wrapped_phase_deg(low=-180.0), [0.0, -90.0, 180.0, 0.0, -90.0])
    # −1/s is +90° (j/ω), not −270°: the first sample is anchored in (−180°, 180°]
    assert anchored_phase_deg(np.array([1j, 1j]))[0] == pytest.approx(90.0)
    assert anchored_phase_deg(np.array([-1.0 + 0j]))[0] == pytest.approx(180.0)


@pytest.mark.slow
def test_nrel5mw_pitch_loop_phase_is_true_and_plotted_wrapped(tmp_path):
    # the −810° at the Nyquist frequency is the loop's real continuous phase: the sum of the angles of its
    # poles and zeros (generalized eigenvalues of the system pencil) along the unit circle gives the same
    import scipy.linalg

    from mbsym.wind.analysis.closed_loop import closed_loop_linear
    from mbsym.wind.operation import OperatingTurbine

    cl = closed_loop_linear(OperatingTurbine.nrel5mw(), 16.0)
    r = cl.frequency_response("pitch")
    L = cl.pitch_loop
    n = L.A.shape[0]
    N = np.zeros((n + 1, n + 1))
    N[:n, :n] = np.eye(n)
    zeros = scipy.linalg.eigvals(np.block([[L.A, L.B], [L.C, L.D]]), N)
    zeros, poles = zeros[np.isfinite(zeros)], np.linalg.eigvals(L.A)
    z = np.exp(2j * np.pi * r.freq_hz * cl.dt)
    angle = sum(np.unwrap(np.angle(z - q)) for q in zeros) - sum(np.unwrap(np.angle(z - p)) for p in poles)
    angle = np.degrees(angle - angle[0]) + r.phase_deg[0]
    np.testing.assert_allclose(r.phase_deg, angle, atol=1e-3)          # eigenvalue round-off only
    wrapped = r.wrapped_phase_deg()
    assert np.all((wrapped > -360.0) & (wrapped <= 0.0))
    # at python-control's phase crossover (the gain margin) the wrapped phase is −180°
    f180 = cl.margins["pitch"].phase_crossover_hz
    assert np.interp(f180, r.freq_hz, wrapped) == pytest.approx(-180.0, abs=0.5)
    cl.bode_plot(tmp_path / "bode.png")
    assert (tmp_path / "bode.png").stat().st_size > 10_000


def test_cli_bode_needs_the_closed_loop_and_one_wind_speed(tmp_path, capsys):
    png = str(tmp_path / "b.png")
    assert main(["linearize", "--wind", "16", "--bode", png]) == 2
    assert "--bode need" in capsys.readouterr().err
    assert main(["linearize", "--wind", "8:16:8", "--closed-loop", "--bode", png]) == 2
    assert "gives 2 wind speeds. Give one" in capsys.readouterr().err
    assert not (tmp_path / "b.png").exists()


@pytest.mark.slow
def test_cli_bode_of_the_builtin_loops(tmp_path, capsys):
    png = tmp_path / "b.png"
    assert main(["linearize", "--wind", "16", "--closed-loop", "--bode", str(png)]) == 0
    assert f"wrote {png}" in capsys.readouterr().out and png.stat().st_size > 10_000
