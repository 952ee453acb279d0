"""First-contact ergonomics of issue 11.5: summary reprs with units, labelled frequencies, mode labels
that tell the 1st tower mode from the 2nd, help texts without reStructuredText markup.

References: units follow the joints (revolute -> rad, prismatic -> m); the NREL 5 MW tower's 1st and
2nd fore-aft frequencies (0.327 Hz: OpenFAST v5 linearization of paper44, ../shared/openfast README;
the 2nd well above 1 Hz) and the kinetic energy of each mode, which must sit mostly (> 90 %) in the
coordinate that names it.
"""

from __future__ import annotations

import contextlib
import io
import re

import numpy as np
import pytest

import mbsym as mb


@pytest.fixture(scope="module")
def tower():
    from mbsym.wind import nrel5mw
    from mbsym.wind.structure.turbine import TurbineModel

    return TurbineModel(nrel5mw(), dofs=["TwFADOF1", "TwFADOF2", "GenDOF"])


def test_system_and_eom_units():
    sys = mb.System(gravity=[0.0, 0.0, -9.81])
    th, x = sys.coordinates("th x")
    b = mb.RigidBody("b", 1.0, com=[0, 0, -1.0])
    sys.add_joint(mb.Revolute(sys.ground, b, axis=[0, 1, 0], coordinate=th))
    sys.add_joint(mb.Prismatic(b, mb.RigidBody("s", 0.5), axis=[1, 0, 0], coordinate=x))
    assert "th [rad]" in repr(sys) and "x [m]" in repr(sys) and "2 bodies" in repr(sys)
    assert sys.equations().units == {"th": "rad", "x": "m", "th_d": "rad/s", "x_d": "m/s"}


def test_result_and_turbine_reprs_have_units(tower):
    assert re.search(r"TurbineModel\(.*tip radius 63 m.*DOFs \['TwFADOF1', 'TwFADOF2', 'GenDOF'\]", repr(tower))
    res = mb.simulate(tower, 0.05)
    assert res.unit("Q_TFA1") == "m" and res.unit("RotSpeed") == "rpm" and res.unit("GeAz_d") == "rad/s"
    assert "TFA1 [m]" in repr(res) and "GeAz [rad]" in repr(res) and len(repr(res)) < 600


def test_linear_model_repr_and_labelled_frequencies(tower):
    from mbsym.linear.model import natural_frequencies

    lin = mb.linearize(tower, outputs=["TTDspFA"])
    f, zeta = lin.frequencies()                              # still unpacks as a pair
    freq = lin.frequencies()
    ref_f, ref_z = natural_frequencies(lin.A[np.newaxis])
    np.testing.assert_allclose(freq.freq_hz, ref_f[0], rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(freq.damping_ratio, ref_z[0], rtol=1e-9, atol=1e-12)
    assert freq.labels == ("GeAz", "TFA1", "TFA2")
    assert f[1] == pytest.approx(0.327, rel=2e-3) and f[2] > 1.0
    text = repr(lin)
    assert "TFA1 [m]" in text and "GeAz [rad]" in text and "TTDspFA [m]" in text and "(TFA2)" in text


def test_linearize_cli_labels_first_and_second_tower_modes():
    """The 2nd fore-aft mode's largest shape entry is TFA1 (units mix), but its energy is in TFA2."""
    from mbsym.cli.linearize import _model, linear_report

    model, _ = _model(None, None)
    rep = linear_report(model)
    by_label = {m["label"]: m for m in rep["modes"]}
    assert by_label["1st tower fore-aft"]["freq_hz"] == pytest.approx(0.327, rel=2e-3)
    second = by_label["2nd tower fore-aft"]
    assert second["freq_hz"] > 1.0 and second["dominant_dof"] == "TFA1"      # the old, misleading label
    labels = [m["label"] for m in rep["modes"]]
    assert len(set(labels)) == len(labels)


@pytest.mark.parametrize("command", ["simulate", "linearize", "campbell", "demo"])
def test_help_has_no_rst_markup(command):
    from mbsym.cli import main

    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        assert main([command, "--help"]) == 0
    text = out.getvalue()
    assert "``" not in text and not re.search(r":(func|class|mod|data|meth):`", text), text
