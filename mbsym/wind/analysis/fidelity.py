"""Model no more than a scene needs: a ladder of turbine models of increasing DOF sets.

:func:`fidelity_ladder` builds one :class:`~mbsym.wind.structure.turbine.TurbineModel` per rung
(ElastoDyn flag sets, e.g. FA1 -> FA1 + SS1 -> + GenDOF -> + DrTrDOF -> + blades), runs
the same scene (the deck's initial conditions, ``tmax``) on each, and measures for the
chosen OpenFAST output channels

- the error against the richest rung that could be built, and
- the error against a reference time series (e.g. OpenFAST's output of the deck),

with ``ε = mean|y - y_ref| / range(y_ref)`` per channel (wrap-aware for ``Azimuth``
and ``Q_GeAz``; the paper's metric, :func:`mbsym.wind.analysis.compare.error_metrics`), and the
cost of each rung (model build, preparation, integration wall time).
:meth:`FidelityLadder.smallest` names the smallest rung within a tolerance.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Mapping, Sequence

import numpy as np

from ...exceptions import MbsymError
from .compare import WRAPPED, TimeSeries, error_metrics
from ..deck.parameters import TurbineParameters

__all__ = ["DEFAULT_LADDER", "Rung", "FidelityLadder", "fidelity_ladder"]

#: FA1 -> FA1 + SS1 -> + GenDOF -> + DrTrDOF -> + blades (1st/2nd flap, 1st edge).
DEFAULT_LADDER: tuple[tuple[str, ...], ...] = (
    ("TwFADOF1",),
    ("TwFADOF1", "TwSSDOF1"),
    ("TwFADOF1", "TwSSDOF1", "GenDOF"),
    ("TwFADOF1", "TwSSDOF1", "GenDOF", "DrTrDOF"),
    ("TwFADOF1", "TwSSDOF1", "GenDOF", "DrTrDOF", "FlapDOF1", "EdgeDOF", "FlapDOF2"),
)


@dataclass(frozen=True)
class Rung:
    """One model of the ladder and how it did.

    Attributes
    ----------
    dofs : tuple of str
        Enabled ElastoDyn flags.
    coordinates : tuple of str
        The model's coordinates (empty when the rung could not be built or run).
    errors : dict
        ε per output against the richest rung [-] (``inf`` when an output that
        varies in the richest rung is missing or constant here).
    reference_errors : dict
        ε per output against the reference series (outputs it contains).
    build_wall_s, prepare_wall_s, integration_wall_s : float
        Model build (System -> Functions), preparation and integration wall times [s].
    message : str
        Why the rung was skipped (empty otherwise).
    """

    dofs: tuple[str, ...]
    coordinates: tuple[str, ...] = ()
    errors: Mapping[str, float] = field(default_factory=dict)
    reference_errors: Mapping[str, float] = field(default_factory=dict)
    build_wall_s: float = float("nan")
    prepare_wall_s: float = float("nan")
    integration_wall_s: float = float("nan")
    message: str = ""

    @property
    def ok(self) -> bool:
        return not self.message

    @property
    def n_dofs(self) -> int:
        return len(self.coordinates)

    @property
    def error(self) -> float:
        """Largest ε over the outputs against the richest rung."""
        return max(self.errors.values(), default=float("nan"))

    @property
    def reference_error(self) -> float:
        """Largest ε over the outputs against the reference (NaN without one)."""
        return max(self.reference_errors.values(), default=float("nan"))

    @property
    def label(self) -> str:
        return " + ".join(_SHORT.get(f, f) for f in self.dofs)


_SHORT = {"TwFADOF1": "FA1", "TwSSDOF1": "SS1", "TwFADOF2": "FA2", "TwSSDOF2": "SS2", "GenDOF": "Gen",
          "DrTrDOF": "DrTr", "FlapDOF1": "Flap1", "FlapDOF2": "Flap2", "EdgeDOF": "Edge1", "YawDOF": "Yaw"}


@dataclass(frozen=True)
class FidelityLadder:
    """Result of :func:`fidelity_ladder`: the rungs, in the order given."""

    rungs: tuple[Rung, ...]
    outputs: tuple[str, ...]
    tolerance: float
    method: str

    @property
    def richest(self) -> Rung:
        return [r for r in self.rungs if r.ok][-1]

    def smallest(self, tolerance: float | None = None, *, against: str = "richest") -> Rung | None:
        """The first (smallest) rung whose largest ε is within ``tolerance`` (default: the ladder's).

        ``against="reference"`` uses the errors against the reference series.
        """
        tol = self.tolerance if tolerance is None else float(tolerance)
        for r in self.rungs:
            e = r.error if against == "richest" else r.reference_error
            if r.ok and e <= tol:
                return r
        return None

    def table(self) -> str:
        """Markdown table: DOFs, errors per output, cost."""
        head = ("| rung | DOFs | " + " | ".join(f"ε {o} vs richest" for o in self.outputs)
                + " | ε vs reference (max) | build [ms] | integration [ms] |")
        lines = [head, "|" + "---|" * (len(self.outputs) + 5)]
        for i, r in enumerate(self.rungs):
            if not r.ok:
                lines.append(f"| {i + 1} | {r.label} | " + " | ".join("—" for _ in self.outputs)
                             + f" | skipped: {r.message} | — | — |")
                continue
            errs = " | ".join(_fmt(r.errors.get(o, float("nan"))) for o in self.outputs)
            lines.append(f"| {i + 1} | {r.label} ({r.n_dofs}) | {errs} | {_fmt(r.reference_error)} | "
                         f"{1e3 * r.build_wall_s:.0f} | {1e3 * r.integration_wall_s:.1f} |")
        return "\n".join(lines)

    def plot(self, path, *, title: str = "") -> None:
        """Error vs integration cost, one point per rung (PNG)."""
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        from matplotlib.ticker import FormatStrFormatter, LogLocator

        ok = [(i + 1, r) for i, r in enumerate(self.rungs) if r.ok]
        fig, ax = plt.subplots(figsize=(9.5, 4.8))
        for key, label, marker in (("error", "vs richest rung", "o"), ("reference_error", "vs reference", "s")):
            pts = [(r.integration_wall_s, getattr(r, key), i) for i, r in ok
                   if np.isfinite(getattr(r, key)) and getattr(r, key) > 0]   # the richest vs itself: 0, left out
            if pts:
                ax.loglog([p[0] for p in pts], [p[1] for p in pts], marker + "-", label=label)
                for w, e, i in pts:
                    ax.annotate(str(i), (w, e), fontsize=8, xytext=(4, 4), textcoords="offset points")
        legend = "\n".join(f"{i}: {r.label} ({r.n_dofs} DOFs)" for i, r in ok)
        ax.text(1.02, 1.0, legend, transform=ax.transAxes, fontsize=7, va="top", family="monospace")
        ax.xaxis.set_minor_locator(LogLocator(subs=(2.0, 5.0)))
        ax.xaxis.set_minor_formatter(FormatStrFormatter("%.3g"))
        ax.axhline(self.tolerance, color="0.5", ls=":", lw=1, label=f"tolerance {self.tolerance:g}")
        ax.set_xlabel(f"integration wall time [s] ({self.method})")
        ax.set_ylabel(f"max ε over {', '.join(self.outputs)}")
        ax.set_title(title or "fidelity ladder", fontsize=9)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
        fig.subplots_adjust(left=0.09, right=0.55, bottom=0.11, top=0.92)
        fig.savefig(path, dpi=110)
        plt.close(fig)


def _fmt(v: float) -> str:
    if np.isnan(v):
        return "—"
    return "∞" if np.isinf(v) else f"{v:.2e}"


def fidelity_ladder(turbine: TurbineParameters, ladder: Sequence[Sequence[str]] = DEFAULT_LADDER, *,
                    outputs: Sequence[str] = ("TTDspFA", "TTDspSS", "RotSpeed"), tmax: float | None = None,
                    tolerance: float = 0.01, reference: TimeSeries | None = None, method: str = "cvodes",
                    dt: float | None = None, rtol: float = 1e-8, atol: float = 1e-10, compile: bool = False,
                    t_out: Sequence[float] | None = None, model_options: Mapping | None = None) -> FidelityLadder:
    """Run the scene of ``turbine`` on every rung of ``ladder`` and compare chosen outputs.

    Parameters
    ----------
    turbine : TurbineParameters
        The scene: turbine data and initial conditions (:func:`mbsym.wind.read_openfast`).
    ladder : sequence of sequences of str, optional
        ElastoDyn flag sets, from the smallest to the richest (default :data:`DEFAULT_LADDER`).
        A rung the template cannot build is reported as skipped.
    outputs : sequence of str, keyword-only
        OpenFAST channel names to compare (each must exist in every model built).
    tmax : float, optional
        Simulated time [s]; default the deck's TMax.
    tolerance : float
        ε threshold for :meth:`FidelityLadder.smallest` [-] (default 1 %).
    reference : TimeSeries, optional
        A reference (e.g. :func:`mbsym.wind.analysis.compare.read_csv` of OpenFAST's output).
    method, dt, rtol, atol, compile : optional
        Passed to :func:`mbsym.simulate` for every rung.
    t_out : array, optional
        Output times [s]; default every DT_Out of the deck.
    model_options : dict, optional
        Keyword arguments of :class:`~mbsym.wind.structure.turbine.TurbineModel` (e.g. ``yaw_spring``).

    Returns
    -------
    FidelityLadder

    Raises
    ------
    ValueError
        An empty ladder, no rung that could be built, or an unknown output name.

    Examples
    --------
    >>> from mbsym.wind import nrel5mw
    >>> lad = fidelity_ladder(nrel5mw(), [("TwFADOF1",), ("TwFADOF1", "GenDOF")], outputs=["TTDspFA"],
    ...                       tmax=2.0)
    >>> [r.n_dofs for r in lad.rungs], lad.smallest().label
    ([1, 2], 'FA1')
    """
    from ...simulate import simulate
    from ..structure.turbine import TurbineModel

    if not ladder:
        raise ValueError("ladder must contain at least one set of ElastoDyn DOF flags.")
    outputs = tuple(outputs)
    sim = turbine.simulation
    tmax = float(sim.total_time if tmax is None else tmax)
    if t_out is None:
        t_out = np.round(np.arange(0.0, tmax + sim.output_time_step / 2, sim.output_time_step), 10)
        t_out = t_out[t_out <= tmax + 1e-9]
    t_out = np.asarray(t_out, dtype=float)
    runs = []
    for dofs in ladder:
        dofs = tuple(dofs)
        try:
            t0 = time.perf_counter()
            model = TurbineModel(turbine, dofs=list(dofs), **dict(model_options or {}))
            eom = model.eom
            build = time.perf_counter() - t0
            res = simulate(model, tmax, method=method, dt=dt, rtol=rtol, atol=atol, t_out=t_out, compile=compile)
        except MbsymError as exc:
            runs.append((dofs, None, None, " ".join(str(exc).split())[:160]))
            continue
        missing = [o for o in outputs if o not in res.output_names]
        if missing:
            raise ValueError(f"outputs {missing} are not channels of the model {list(dofs)}; its channels are "
                             f"{list(res.output_names)}.")
        runs.append((dofs, res, (build, eom.coordinates), ""))
    if all(r[1] is None for r in runs):
        raise ValueError("no rung of the ladder could be built: " + "; ".join(r[3] for r in runs))
    richest = [r[1] for r in runs if r[1] is not None][-1]
    rungs = []
    for dofs, res, info, message in runs:
        if res is None:
            rungs.append(Rung(dofs, message=message))
            continue
        errors = {o: _epsilon(res.t, res.output(o), richest.t, richest.output(o), o) for o in outputs}
        ref_err = {}
        if reference is not None:
            ref_err = {o: _epsilon(res.t, res.output(o), reference.time, reference.channel(o), o)
                       for o in outputs if o in reference.names}
        s = res.statistics
        rungs.append(Rung(dofs, tuple(info[1]), errors, ref_err, info[0], s["prepare_wall_s"],
                          s["integration_wall_s"]))
    return FidelityLadder(tuple(rungs), outputs, float(tolerance), method)


def _epsilon(t, y, t_ref, y_ref, name: str) -> float:
    """ε of the paper; for a constant reference: 0 if equal (to 1e-9 relative), else inf."""
    eps, _ = error_metrics(t, y, t_ref, y_ref, period=WRAPPED.get(name))
    if np.isnan(eps):
        scale = 1.0 + float(np.max(np.abs(y_ref)))
        return 0.0 if float(np.max(np.abs(np.interp(t_ref, t, y) - y_ref))) <= 1e-9 * scale else float("inf")
    return eps
