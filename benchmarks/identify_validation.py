"""Validation of mb.identify (issue 14.5): synthetic data with noise, and OpenFAST free decays.

(a) Synthetic: the paper45 turbine simulated by mbsym (CVODES, rtol 1e-10) for 60 s at 0.02 s
    with known parameters (the deck's TwrFADmp(1), FAStTunr(1), TwrSSDmp(1)), Gaussian noise of
    0.5 % of each channel's range added; identified from 20 % off. Over ``--runs`` noise
    realizations: how often each estimate is within 3 standard errors of the truth, and the
    mean reported standard error against the Monte-Carlo spread of the estimates.
(b) OpenFAST: the shared paper45 and paper46 free decays (OpenFAST v5, ElastoDyn only), starting
    20 % off the deck's values: tower damping ratio and stiffness tuner (paper45, FA and SS), and
    the platform pitch inertia (paper46, alone and with the tower FA parameters). For each: the
    estimate, its error against the deck, the standard error, the fit ε and, for comparison, the
    ε of mbsym simulated with the deck's values (the model-form difference the fit can absorb), and
    the same identification on mbsym's own simulation of the deck (no model-form difference).

Writes the tables into benchmarks/README.md between the ``identify-validation`` markers.
Needs ../shared/openfast. Run: ``python benchmarks/identify_validation.py [--runs 50] [--no-write]``.
"""

from __future__ import annotations

import argparse
import time
import warnings
from pathlib import Path

import numpy as np
from _report import write_section

import mbsym as mb
from mbsym.exceptions import IdentifiabilityWarning
from mbsym.identify.result import fit_error
from mbsym.wind import read_openfast
from mbsym.wind.analysis.compare import read_csv
from mbsym.wind.structure import named_parameters as npar
from mbsym.wind.structure.turbine import TurbineModel

HERE = Path(__file__).resolve().parent
CASES = HERE.parent.parent / "shared" / "openfast" / "cases"
P45_CH = ["Q_TFA1", "QD_TFA1", "Q_TSS1", "QD_TSS1", "QD_GeAz"]
P46_CH = ["Q_Sg", "QD_Sg", "Q_P", "QD_P", "Q_TFA1", "QD_TFA1"]


def _case(name):
    return TurbineModel(read_openfast(CASES / name / f"{name}.fst")), read_csv(CASES / name / f"{name}.csv")


def _simulate(model, t, channels, p=None):
    out = mb.simulate(model, float(t[-1]), p=p, method="cvodes", t_out=t, rtol=1e-10, atol=1e-12)
    return {"time": t, **{c: out.y[:, out.output_names.index(c)] for c in channels}}


def synthetic(runs: int) -> str:
    model, ref = _case("paper45_fa_ss_gen")
    keys = ["TwrFADmp(1)", "FAStTunr(1)", "TwrSSDmp(1)"]
    truth = {k: npar.deck_value(model.turbine, k) for k in keys}
    clean = _simulate(model, ref.time, P45_CH)
    sigma = {c: 0.005 * np.ptp(clean[c]) for c in P45_CH}
    rng = np.random.default_rng(14)
    est, std, walls = [], [], []
    for _ in range(runs):
        data = {"time": ref.time, **{c: clean[c] + sigma[c] * rng.normal(size=ref.time.size) for c in P45_CH}}
        t0 = time.perf_counter()
        res = mb.identify(model, data, keys, channels=P45_CH, initial={k: 0.8 * v for k, v in truth.items()})
        walls.append(time.perf_counter() - t0)
        est.append([res.parameters[k] for k in keys])
        std.append([res.std[k] for k in keys])
    est, std = np.array(est), np.array(std)
    tv = np.array([truth[k] for k in keys])
    spread = est.std(axis=0, ddof=1)
    rows = [f"Synthetic paper45 data (mbsym, CVODES), noise 0.5 % of each channel's range, {runs} realizations, "
            f"start 20 % off; median wall per identification {np.median(walls):.2f} s.", "",
            "| parameter | truth | first run: estimate ± std | first run: abs(error) / std | runs within 3 std | "
            "mean reported std | Monte-Carlo spread | std / spread |", "|---|---:|---:|---:|---:|---:|---:|---:|"]
    for j, k in enumerate(keys):
        rows.append(f"| {k} | {tv[j]:g} | {est[0, j]:.6g} ± {std[0, j]:.2g} | {abs(est[0, j] - tv[j]) / std[0, j]:.2f} | "
                    f"{np.mean(np.abs(est[:, j] - tv[j]) <= 3 * std[:, j]) * 100:.0f} % | {std[:, j].mean():.3g} | "
                    f"{spread[j]:.3g} | {std[:, j].mean() / spread[j]:.2f} |")
    return "\n".join(rows)


def _row(label, model, ref, keys, channels, deck):
    init = {k: 0.8 * v for k, v in deck.items()}
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", IdentifiabilityWarning)
        res = mb.identify(model, ref, keys, channels=channels, initial=init)
    warned = any(issubclass(w.category, IdentifiabilityWarning) for w in caught)
    ours = _simulate(model, ref.time, channels)
    Y = np.column_stack([ref.channel(c) for c in channels])
    eps_deck = fit_error(np.column_stack([ours[c] for c in channels]), Y, np.zeros(len(channels)))
    self_fit = mb.identify(model, ours, keys, channels=channels, initial=init)
    cells = []
    for k in keys:
        e = 100 * (res.parameters[k] / deck[k] - 1)
        s = 100 * (self_fit.parameters[k] / deck[k] - 1)
        cells.append(f"{k}: {res.parameters[k]:.6g} ({e:+.3f} %, std {res.std[k]:.2g}; on mbsym data {s:+.1e} %)")
    return (f"| {label} | {'<br>'.join(cells)} | {max(res.eps_pct.values()):.3f} | {100 * max(eps_deck):.3f} | "
            f"{res.iterations} | {res.wall_s:.2f} | {'yes' if warned else 'no'} |")


def openfast() -> str:
    rows = ["| case: parameters (start 20 % off) | estimate (error vs deck, std; error when fitted to mbsym's own "
            "simulation of the deck) | fit max ε [%] | ε at deck values [%] | iterations | wall [s] | "
            "collinearity warning |", "|---|---|---:|---:|---:|---:|---|"]
    m45, r45 = _case("paper45_fa_ss_gen")
    m46, r46 = _case("paper46_floating")
    for label, model, ref, keys, ch in (
            ("paper45: FA damping + tuner", m45, r45, ["TwrFADmp(1)", "FAStTunr(1)"], P45_CH),
            ("paper45: SS damping + tuner", m45, r45, ["TwrSSDmp(1)", "SSStTunr(1)"], P45_CH),
            ("paper45: FA + SS damping + tuners", m45, r45, ["TwrFADmp(1)", "FAStTunr(1)", "TwrSSDmp(1)",
                                                          "SSStTunr(1)"], P45_CH),
            ("paper46: platform pitch inertia", m46, r46, ["PtfmPIner"], P46_CH),
            ("paper46: pitch inertia + tower FA damping + tuner", m46, r46, ["PtfmPIner", "TwrFADmp(1)",
                                                                              "FAStTunr(1)"], P46_CH)):
        deck = {k: npar.deck_value(model.turbine, k) for k in keys}
        rows.append(_row(label, model, ref, keys, ch, deck))
    return "\n".join(rows)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--runs", type=int, default=50)
    ap.add_argument("--no-write", action="store_true")
    args = ap.parse_args()
    text = "(a) " + synthetic(args.runs) + "\n\n(b) OpenFAST free decays:\n\n" + openfast()
    print(text)
    if not args.no_write:
        write_section("identify-validation", text)


if __name__ == "__main__":
    main()
