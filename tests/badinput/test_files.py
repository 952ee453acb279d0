"""Files are never destroyed nor misreported, and doubtful input is said aloud (issue 11.1, 11.2, 11.5).

References: the shared paper44 deck and its OpenFAST v5 CSV (../shared/openfast); exact
expectations (file names, row counts, times k·dt) need no tolerance.
"""

from __future__ import annotations

import csv
import re

import numpy as np
import pytest

from .conftest import run_cli, set_key


def test_a_failing_later_output_writes_nothing(deck, monkeypatch):
    """--plot fails while writing (after --out was written to its temporary): neither file appears,
    an existing --out keeps its content, no temporary is left."""
    import mbsym.wind.analysis.compare as compare

    def broken(path, *a, **k):
        raise OSError("disk full (simulated)")

    monkeypatch.setattr(compare, "overlay_plot", broken)
    out = deck.dir / "out.csv"
    out.write_text("previous run\n")
    before = deck.files()
    code, _, err = run_cli(["simulate", deck.fst, "--tmax", "0.1", "--out", out, "--plot", deck.dir / "p.png"])
    assert code == 2 and "disk full" in err
    assert deck.files() == before and out.read_text() == "previous run\n"


def test_outputs_written_atomically_and_named_as_written(deck):
    out, plot = deck.dir / "out.csv", deck.dir / "decay"
    code, stdout, _ = run_cli(["simulate", deck.fst, "--tmax", "0.2", "--out", out, "--plot", plot])
    assert code == 0
    assert f"wrote {out} (" in stdout and f"wrote {plot}.png" in stdout      # the name actually written
    assert out.is_file() and (deck.dir / "decay.png").is_file() and not plot.exists()
    assert not [p for p in deck.dir.iterdir() if p.name.startswith(".")]        # no temporaries left
    assert oct(out.stat().st_mode & 0o777) != oct(0o600)                       # ordinary permissions


def test_campbell_plot_without_suffix_reports_the_png(deck):
    target = deck.dir / "campbell"
    code, stdout, _ = run_cli(["campbell", deck.fst, "--rpm", "0,6", "--azimuths", "3", "--plot", target])
    assert code == 0 and f"wrote {target}.png" in stdout and (deck.dir / "campbell.png").is_file()


def test_time_has_digits_for_the_step(deck):
    """--dt 1e-5 used to collapse the times to 0.0000 (and a comparison against that file to ε 964 %)."""
    out = deck.dir / "fine.csv"
    assert run_cli(["simulate", deck.fst, "--tmax", "0.0005", "--dt", "1e-5", "--method", "rk4", "--out", out])[0] == 0
    with out.open() as fh:
        t = np.array([float(r[0]) for r in list(csv.reader(fh))[1:]])
    np.testing.assert_allclose(t, 1e-5 * np.arange(t.size), rtol=0, atol=1e-12)
    code, stdout, _ = run_cli(["simulate", deck.fst, "--tmax", "0.0005", "--dt", "1e-5", "--method", "rk4",
                               "--compare", out])
    eps = [float(m) for m in re.findall(r"^Q_TFA1\s+(\d+\.\d+)\s", stdout, flags=re.M)]
    assert code == 0 and eps and eps[0] < 1e-6                               # the file compares with itself


def test_comparison_reports_ranges_and_non_finite_samples(deck):
    lines = deck.csv.read_text().splitlines(keepends=True)
    header = lines[0].split(",")
    col = header.index("Q_TFA1_[m]")
    cells = lines[3].split(",")
    cells[col] = "nan"
    lines[3] = ",".join(cells)
    ref = deck.dir / "ref.csv"
    ref.write_text("".join(lines[:52]))                                          # 1 s of reference, one NaN
    code, stdout, _ = run_cli(["simulate", deck.fst, "--tmax", "2", "--compare", ref])
    assert code == 0
    assert re.search(r"the simulation runs to 2 s but the reference ends at 1 s: compared on \[0, 1\] s only", stdout)
    assert re.search(r"samples left out .*Q_TFA1 \(1\)", stdout)
    code, stdout, _ = run_cli(["simulate", deck.fst, "--tmax", "0.5", "--compare", deck.csv])
    assert "the reference runs to 60 s but the simulation ends at 0.5 s" in stdout


def test_structure_only_runs_with_a_warning(deck):
    set_key(deck.fst, "CompAero", "2")
    set_key(deck.fst, "CompServo", "1")
    code, stdout, err = run_cli(["simulate", deck.fst, "--tmax", "0.1", "--structure-only"])
    assert code == 0 and "Q_TFA1" in stdout
    warnings = [line for line in err.splitlines() if line.startswith("mbsym simulate: warning:")]
    assert len(warnings) == 1 and "CompAero = 2" in warnings[0] and "CompServo = 1" in warnings[0]


@pytest.mark.parametrize("edits, message", [
    ({"TeetDOF": "True"}, r"TeetDOF = True ignored: only two-bladed rotors teeter"),     # was refused
    ({"TwFADOF2": "True", "TwFADOF1": "False"}, r"TwFADOF2 = True without TwFADOF1"),   # ElastoDyn warns
    ({"PtfmHvDOF": "True"}, r"PtfmHvDOF = True with no hydrostatics or mooring.*falls freely"),
    ({"PtfmSgDOF": "True"}, r"PtfmMass = 0 and zero platform inertias"),
])
def test_doubtful_decks_run_with_a_warning(deck, edits, message):
    for key, value in edits.items():
        set_key(deck.ed, key, value)
    code, stdout, err = run_cli(["simulate", deck.fst, "--tmax", "0.05", "--method", "rk4"])
    assert code == 0, err
    assert any(re.search(message, line) for line in err.splitlines() if "warning:" in line), err


def test_free_fall_is_what_the_warning_says(deck):
    """The warned heave DOF does fall at g: Hv(t) = -g t^2 / 2 to 1e-6 relative (closed form)."""
    from mbsym import simulate
    from mbsym.exceptions import ModelWarning
    from mbsym.wind import read_openfast
    from mbsym.wind.structure.turbine import TurbineModel

    set_key(deck.ed, "PtfmHvDOF", "True")
    set_key(deck.ed, "TwFADOF1", "False")
    set_key(deck.ed, "GenDOF", "False")
    set_key(deck.ed, "RotSpeed", "0")
    with pytest.warns(ModelWarning, match="falls freely"):
        model = TurbineModel(read_openfast(deck.fst))
    res = simulate(model, 1.0, method="rk4", dt=0.01)
    g = model.turbine.simulation.gravity
    np.testing.assert_allclose(res.state("Hv")[-1], -0.5 * g, rtol=1e-6)


def test_decay_plot_titles_and_panels(deck, monkeypatch):
    """No absolute path in the title; channels constant in both series get no (empty) panel."""
    from matplotlib.figure import Figure

    seen = {}

    def capture(fig, path, *a, **k):
        seen["titles"] = [ax.get_title() for ax in fig.axes]
        seen["labels"] = [ax.get_ylabel().split("\n")[0] for ax in fig.axes]
        open(path, "wb").close()

    monkeypatch.setattr(Figure, "savefig", capture)
    assert run_cli(["simulate", deck.fst, "--tmax", "0.5", "--plot", deck.dir / "p.png", "--compare", deck.csv])[0] == 0
    assert seen["titles"][0] == deck.fst.name and "/" not in "".join(seen["titles"])
    assert "RotSpeed" not in seen["labels"]            # paper44 spins at a constant 5 rpm in both
    assert "Q_TFA1" in seen["labels"] and "Q_GeAz" in seen["labels"]


def test_campbell_plot_colours_by_family_and_styles_by_whirl(tmp_path, monkeypatch):
    from matplotlib.figure import Figure

    from mbsym.wind.analysis.campbell_diagram import CampbellDiagram, CampbellMode, mode_family

    labels = ["1st tower fore-aft", "1st flap collective", "1st flap forward whirl", "1st flap backward whirl",
              "1st edge forward whirl", "1st edge backward whirl", "2nd tower fore-aft"]
    rpm = np.array([0.0, 5.0, 10.0])
    modes = tuple(CampbellMode(lab, np.array([1.0, 1.1, 1.2]) + i, np.zeros(3)) for i, lab in enumerate(labels))
    lines = {}

    def capture(fig, path, *a, **k):
        for line in fig.axes[0].get_lines():
            if line.get_label() in labels:
                lines[line.get_label()] = (line.get_color(), line.get_linestyle())

    monkeypatch.setattr(Figure, "savefig", capture)
    CampbellDiagram(rpm, modes).plot(tmp_path / "c.png")
    assert lines["1st flap collective"][1] == "-" and lines["1st flap forward whirl"][1] == "--"
    assert lines["1st flap backward whirl"][1] == ":"
    assert len({lines[lab][0] for lab in labels[1:4]}) == 1                  # one family, one colour
    families = {mode_family(lab)[0]: lines[lab][0] for lab in labels}
    assert len(set(families.values())) == len(families) == 4                  # distinct colours per family
