"""``mbsym export-discon``: a controller as a self-contained Bladed-style DISCON library.

Contract (kept for acceptance checks)::

    mbsym export-discon [DECK] --controller baseline|nmpc [--estimator ekf|mhe] --out DIR
                        [--discon-input DISCON.IN] [--sample-time S] [--name NAME] [--initial-wind V]
                        [--preview auto|lidar|none]

writes the library ``DIR/NAME.so`` and its input file ``DIR/NAME.IN`` (with the C sources in
``DIR/src``) and prints one JSON object on its last line: ``{"library": "<path>.so", "input":
"<path>", "controller": "baseline"|"nmpc", "sample_time_s": ...}``. Putting the two paths into a ServoDyn
file (``DLL_FileName``, ``DLL_InFile``; ``PCMode`` and ``VSContrl`` 5, ``DLL_DT`` a divisor of the
sample time, ``Ptch_Cntrl`` 1 with IPC) is all OpenFAST needs.

The deck configures the controller exactly as ``mbsym simulate DECK --controller baseline`` does:
its ServoDyn ``DLL_InFile`` (ROSCO's ``DISCON.IN``; ``--discon-input`` instead) and its controller
sample time (``DLL_DT``, else ServoDyn's ``DT``, else the glue ``DT``; ``--sample-time`` instead).
Without a deck: ROSCO 2.10.6's NREL 5 MW settings at 0.01 s (the built-in turbine of ``mbsym
simulate``).

``--controller nmpc`` (:func:`mbsym.wind.mpc.discon_nmpc.export_nmpc_discon`): the turbine NMPC as
``mbsym simulate DECK --controller nmpc`` runs it without preview (:class:`~mbsym.wind.mpc.TurbineNMPC`
with the tuning :func:`~mbsym.cli.controller_model.nmpc_tuning` gives the deck: ``NMPCTuning.estimated_wind()``
on land, ``NMPCTuning.floating()`` on a floating platform, whose EKF also reads the nacelle IMU and the
platform's pitch and surge from OpenFAST's swap records 83, 1005 and 1001; one real-time iteration per 0.1 s) with its
EKF (``--estimator ekf``, the default; 20 Hz) and the baseline controller of the deck as its fallback
on a QP failure, all generated as C. The library's sample time is the controller sample time above.
The EKF starts (and restarts, should its wind estimate leave the plausible range) from the steady
operation at the hub wind measured at its first sample (swap record 27), or at ``--initial-wind`` V
m/s when given. For a deck whose plant needs blade-element aerodynamics (full field, shear, blade DOFs)
the controller's models are the deck's rotor-effective model with the DOFs they use (GenDOF,
TwFADOF1, TwSSDOF1, DrTrDOF: the estimator's model carries the drivetrain torsion where the deck has it).
A deck whose plant is blade-element (a full field, flexible blades, shear, AeroDyn's tower or unsteady airfoils)
gets the tunings made for such a plant (``NMPCTuning.full_field``, ``EstimatorTuning.full_field``: measured
inside OpenFAST on the flexible-blade NREL 5 MW, benchmarks/nmpc_openfast.py; a floating deck keeps
``NMPCTuning.floating`` and the default ``EstimatorTuning``). ``--estimator mhe`` exports the
moving-horizon estimator of ``mbsym simulate DECK --controller nmpc --estimator mhe`` instead (the same
tuning; a window of ``EstimatorTuning.window`` intervals, one Gauss–Newton QP per sample by qrqp, the EKF's
estimate while the window fills or when a solve is rejected: :mod:`mbsym.wind.mpc.sample_mhe`).

``--preview`` (nmpc): ``lidar`` reads the deck's single-point lidar (InflowWind ``SensorType = 1``) from
OpenFAST's extended swap records and previews the wind over the NMPC's horizon
(:mod:`mbsym.wind.mpc.lidar_preview`; OpenFAST v5 always fills those records: its ServoDyn hard-codes
``EXavrSWAP = True``). ``auto`` (the default) does so when the deck has a lidar, ``none`` never.

The NMPC's input file holds its **run-time settings**: the cost scales, the limits of the demands and their rates
(narrowed within the exported ones) and the preview source, read at the first call; editing them retunes the
library without exporting again (:mod:`mbsym.wind.mpc.runtime_settings`, docs/discon_export.md).
"""

from __future__ import annotations

import dataclasses
import json
import math

from .controller_model import blade_element_plant, full_field_wind  # noqa: F401 (full_field_wind: public here)

__all__ = ["add_parser", "run"]

CONTROLLERS = ("baseline", "nmpc")


def add_parser(sub) -> None:
    p = sub.add_parser("export-discon", help="compile a controller into a DISCON library (.so) and its input file "
                                             "for OpenFAST/ServoDyn", description=__doc__.split("\n\n")[0],
                       epilog="nmpc: the input file's cost scales, limits and preview source are read at run time; "
                              "edit them to retune without exporting again (docs/discon_export.md).")
    p.add_argument("deck", nargs="?", help="main OpenFAST input file (.fst) whose ServoDyn DISCON.IN and controller "
                                           "sample time configure the controller; default: built-in NREL 5 MW")
    p.add_argument("--controller", required=True, choices=CONTROLLERS,
                   help="baseline (our ROSCO-scheme controller) or nmpc (the turbine NMPC with its EKF and the "
                        "baseline as fallback)")
    p.add_argument("--estimator", choices=("ekf", "mhe"), help="the NMPC's estimator (nmpc only; default ekf; mhe: "
                                                               "moving horizon, one real-time iteration per sample)")
    p.add_argument("--out", required=True, metavar="DIR", help="directory for the library, its input file and src/")
    p.add_argument("--discon-input", metavar="DISCON.IN", help="ROSCO controller input file instead of the deck's "
                                                               "(ServoDyn DLL_InFile)")
    p.add_argument("--sample-time", type=float, metavar="S",
                   help="controller sample time [s] (default: the deck's DLL_DT/DT; built-in 0.01)")
    p.add_argument("--name", help="file name stem (default baseline_discon or nmpc_discon)")
    p.add_argument("--initial-wind", type=float, metavar="V",
                   help="nmpc: wind [m/s] of the steady operation the EKF starts from (default: the hub wind "
                        "measured at the first sample, swap record 27)")
    p.add_argument("--preview", choices=("auto", "lidar", "none"), default="auto",
                   help="nmpc: preview the wind from the deck's single-point lidar (InflowWind SensorType 1); "
                        "auto (default): when the deck has one")


def run(args) -> int:
    """Export and print the JSON line (see the module docstring)."""
    from ..exceptions import OptionError

    if args.sample_time is not None and not (math.isfinite(args.sample_time) and args.sample_time > 0):
        raise OptionError(f"--sample-time must be a positive finite time [s]; got {args.sample_time:g}.")
    if args.controller == "nmpc":
        return _run_nmpc(args)
    if args.initial_wind is not None:
        raise OptionError("--initial-wind is the NMPC's EKF prior; the baseline controller has none. Drop it.")
    if args.estimator is not None:
        raise OptionError(f"--estimator {args.estimator} belongs to --controller nmpc; the baseline controller has "
                          "its own wind-speed estimator (set by WE_Mode in its DISCON.IN). Drop --estimator.")
    from ..wind.control.baseline import BaselineController
    from ..wind.control.discon_export import export_discon
    from ..wind.operation.deck import builtin_deck, operating_deck

    deck = operating_deck(args.deck) if args.deck is not None else builtin_deck()
    settings = deck.baseline_settings(discon_in=args.discon_input, dt=args.sample_time)
    controller = BaselineController(settings)
    source = settings.source or "built-in NREL 5 MW"
    print(f"mbsym export-discon: baseline controller from {source}, sample time {controller.dt:g} s, "
          f"{len(controller.state_names)} states, measurements {', '.join(controller.measurements)}")
    out = export_discon(controller, args.out, name=args.name or "baseline_discon")
    print(f"wrote {out['library']}\nwrote {out['input']}\nServoDyn: DLL_FileName \"{out['library']}\", "
          f"DLL_InFile \"{out['input']}\", DLL_DT a divisor of {controller.dt:g} s"
          + (", Ptch_Cntrl 1" if controller.ipc else ""))
    print(json.dumps(out))
    return 0


def _run_nmpc(args) -> int:
    """``--controller nmpc``: the NMPC with its EKF and the baseline as fallback (module docstring)."""
    import numpy as np

    from ..exceptions import OptionError
    from ..wind.control.baseline import BaselineController
    from ..wind.mpc import (
        PredictionModel,
        SetPoints,
        TurbineEstimator,
        TurbineNMPC,
        estimation_model,
    )
    from ..wind.mpc.discon_nmpc import export_nmpc_discon
    from ..wind.operation.deck import builtin_deck, operating_deck
    from .controller_model import controller_model, estimator_tuning, flexible_nacelle, nmpc_tuning
    from .operate_mpc import _initial_estimate

    wind0 = 10.0 if args.initial_wind is None else args.initial_wind
    if not (math.isfinite(wind0) and 3.0 <= wind0 <= 30.0):
        raise OptionError(f"--initial-wind must be a wind speed in [3, 30] m/s; got {wind0:g}.")
    initial = "hub-wind" if args.initial_wind is None else "fixed"
    deck = operating_deck(args.deck) if args.deck is not None else builtin_deck()
    settings = deck.baseline_settings(discon_in=args.discon_input, dt=args.sample_time)
    if settings.ipc_mode:                           # the NMPC pitches collectively, its fallback too
        print(f"mbsym export-discon: the fallback baseline leaves out the deck's individual pitch control "
              f"(IPC_ControlMode {settings.ipc_mode}): the NMPC commands one collective pitch to every blade")
        settings = dataclasses.replace(settings, ipc_mode=0)
    baseline = BaselineController(settings)
    model = controller_model(deck, say=lambda line: print(f"mbsym export-discon: {line}"))
    observed = estimation_model(model)
    field = blade_element_plant(deck)
    kind = args.estimator or "ekf"
    flexible = flexible_nacelle(deck.turbine.dofs if deck.dofs is None else deck.dofs)
    estimator = TurbineEstimator(observed, kind, compile=False,
                                 tuning=estimator_tuning(observed, field=field, flexible=flexible),
                                 x0=_initial_estimate(model, observed, lambda t: np.full_like(
                                     np.asarray(t, dtype=float), wind0), settings))
    setpoints = SetPoints.from_settings(settings, model.rotor)
    prediction = PredictionModel(model)
    preview = _preview(args, deck)
    tuning = nmpc_tuning(prediction, field=field, lidar=preview is not None)
    nmpc = TurbineNMPC(prediction, setpoints, tuning=tuning.for_turbine(setpoints))
    floating = any(d.startswith("Ptfm") for d in prediction.dofs)
    if field:
        print("mbsym export-discon: the deck's plant is blade-element: " + (
            "the floating NMPC's tunings (NMPCTuning.floating, EstimatorTuning"
            f"{'.flexible_floating()' if flexible else '()'})" if floating else
            "the NMPC and EKF tunings made for it (NMPCTuning.full_field"
            f"{'_lidar' if preview is not None else ''}, EstimatorTuning.full_field)"))
    source = settings.source or "built-in NREL 5 MW"
    what = "EKF" if kind == "ekf" else f"MHE, window {estimator.tuning.window} intervals,"
    print(f"mbsym export-discon: NMPC ({nmpc.dt:g} s, {nmpc.horizon} stages) with its {what} ({estimator.dt:g} s) and "
          f"the baseline from {source} as fallback; library sample time {baseline.dt:g} s")
    out = export_nmpc_discon(nmpc, estimator, baseline, args.out, loop_dt=baseline.dt, name=args.name or "nmpc_discon",
                             initial=initial, preview=preview)
    print(f"wrote {out['library']}\nwrote {out['input']}\nServoDyn: DLL_FileName \"{out['library']}\", "
          f"DLL_InFile \"{out['input']}\", DLL_DT a divisor of {baseline.dt:g} s, PCMode 5, VSContrl 5")
    print(json.dumps(out))
    return 0


def _preview(args, deck):
    """The lidar preview's settings (``--preview``), or None."""
    from ..exceptions import OptionError
    from ..wind.mpc.lidar_preview import PreviewSettings

    choice = getattr(args, "preview", "auto")
    lidar = getattr(deck.inflow, "lidar", None) if deck.inflow is not None else None
    if choice == "none" or (choice == "auto" and lidar is None):
        return None
    if lidar is None:
        raise OptionError("--preview lidar: the deck's InflowWind has no single-point lidar (SensorType = 1, "
                          "NumBeam, FocalDistanceX/Y/Z). Add one, or use --preview none.")
    settings = PreviewSettings.for_lidar(lidar)
    print(f"mbsym export-discon: lidar preview: {lidar.n_beams} beams {settings.distance:g} m upstream, every NMPC "
          f"sample (moving average {settings.window:g} s)")
    return settings
