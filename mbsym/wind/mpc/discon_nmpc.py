"""Export the turbine NMPC with its EKF (or MHE) as a self-contained Bladed-style ``DISCON`` library.

:func:`export_nmpc_discon` generates C for the fixed-work Functions of :mod:`.sample` (the EKF
sample, or the MHE's of :mod:`.sample_mhe` with its C part :mod:`.discon_mhe`; the first sample's start-up
iterations and one real-time iteration with CasADi's ``qrqp``, warm-started from the previous sample's multipliers)
and for the baseline controller's law (the fallback), and compiles them with a hand-written
wrapper (:mod:`mbsym.wind.control._discon_c`'s parts and :data:`NMPC_PART`) into one shared
library linked against ``libm`` only: no Python, numpy or CasADi at run time, fixed (static) memory.

**Why qrqp.** Of CasADi 3.8's QP plugins, ``qrqp`` is the one whose C CasADi generates in full
(``hpipm``, ``osqp``, ``daqp`` generate calls into their own libraries, shipped with CasADi as
shared libraries only, which the library would then need at run time).

**Swap-array records** (1-based): read: 1 status, 2 time, 3 communication interval, 10 pitch
actuator type (must be 0), 49 size of ``avcMSG``, 50 length of ``accINFILE``, 61 number of blades;
the measurements 20 ``GenSpeed`` [rad/s] (the estimator reads it in rpm), 53 ``YawBrTAxp`` [m/s²],
4 ``BldPitch1`` [rad], 23 ``GenTq`` (measured generator torque) [N m], and for the baseline law
(run at every sample, so its filters are current when it takes over) 21 ``RotSpeed`` [rad/s],
15 ``GenPwr`` [W], 27 ``Wind1VelX`` [m/s] (also the EKF's start and restart, :mod:`.sample`). On a floating
platform the EKF also reads 83 ``NcIMURAys`` [rad/s²] and OpenFAST's extended records 1005 ``PtfmPitch`` [rad]
and 1001 ``PtfmSurge`` [m] (:data:`FLOATING_RECORDS`; OpenFAST v5's ServoDyn always fills them; a swap array
shorter than that, record 129, is an error), and the fallback baseline its floating feedback's records. Written:
42-45 the collective pitch demand [rad], 47 the generator torque demand [N m]; 35 = 1, 36 = 0, 41 = 0, 46 = 0,
48 = 0, 55 = 56 = 0, 65 = 0.

**Schedule** (:class:`~.sample.SampledLoop`, :class:`~.loop.TurbineLoop`): the library's sample time
is the loop's; the initialization call (status 0) is answered with the baseline's commands (OpenFAST
v5.0.0's ServoDyn makes it before the first time step with the inputs of its initialization: a
tower-top acceleration of -1.36 m/s² where the first step has 0.002 m/s², and zero measured torque,
which drove the EKF's wind estimate to -0.6 m/s in 0.05 s, measured), and the schedule starts at the
first step call (status 1); the EKF runs every ``ke`` samples on the mean measured pitch and torque of its
interval, the NMPC every ``kn`` samples on the estimate and the measured pitch and torque; between
NMPC samples the demands ramp at the NMPC's rates with the actuators' lead. The host may call more
often (the communication interval divides the sample time; commands held in between).

**QP failure** (the generated QP returns an error, a non-finite result, or a step violating the
QP's constraints by more than :data:`~.sample.QP_ACCEPT` relative): the previous plan's next rates
are applied (the ramps go on from where they are; the plan moves one stage ahead,
:meth:`~.sample.SampleFunctions.hold`) and the next QP starts from the failed QP's own multipliers when
they are finite (a QP stopped at its iteration cap hands its active set on; from the held plan's
multipliers every QP restarted the same search: 39 failures in a row on the stock NREL 5 MW's start in
OpenFAST, tests/wind/control/test_nmpc_start.py), at most ``N - 1`` samples in a row; after that, or when the
EKF restarts, the baseline law's commands until the next NMPC sample, which starts again with the
start-up iterations, reached from the NMPC's last demands at the NMPC's rate bounds (the baseline's
integrator is not synchronized with the NMPC's pitch). Each hold and fallback is counted and reported
through ``aviFAIL = 1`` and ``avcMSG``; the host is never stopped.

**Lidar preview** (``preview``, :mod:`.lidar_preview`): at every NMPC sample the library reads a
single-point lidar from OpenFAST's extended records (129 the array size, 2001 sensor type 1, 2002
the beams, 2005… their speeds; InflowWind ``SensorType = 1``: OpenFAST v5's ServoDyn always fills them)
and gives the NMPC the stage winds of :class:`~.lidar_preview.LidarPreview`. Without those records
it says so once (``aviFAIL = 1``) and holds the estimate over the horizon.

**Input file**: ``Controller`` (``nmpc``), ``SampleTime`` [s] and ``Fingerprint``, checked as for
the baseline export; the run-time settings (cost scales, limits, preview source) read at the first call, and
the compiled-in horizon, sample times and estimator, checked (:mod:`.runtime_settings`).
"""

from __future__ import annotations

import hashlib
import math
import os

import casadi as ca
import numpy as np

from ...exceptions import ControllerError
from ..control._discon_c import CHECK, ENTRY, HEAD, LAW
from ..control.swap import MEASUREMENT_RECORDS
from .discon_mhe import mhe_functions_of, mhe_part
from .lidar_preview import preview_c
from .runtime_settings import input_lines, settings_c
from .sample import QP_ACCEPT, sample_functions

__all__ = ["NMPC_PART", "NMPC_RECORDS", "RTI_PART", "export_nmpc_discon", "rti_part"]

#: Swap records the NMPC and its EKF read (besides the baseline law's).
NMPC_RECORDS = {"GenSpeed": 20, "YawBrTAxp": 53, "BldPitch1": 4, "GenTq": 23}
#: A floating estimator's further measurements (:data:`~.estimator.FLOATING_MEASUREMENTS`): record and factor from
#: the record's SI unit to the estimator's (OpenFAST v5's ServoDyn: record 83 ``NcIMURAys`` [rad/s²]; the extended
#: records 1005 and 1001, the platform's small-angle pitch [rad] and surge [m], ``BladedInterface_EX.f90``).
FLOATING_RECORDS = {"NcIMURAys": (83, 180.0 / math.pi), "PtfmPitch": (1005, 180.0 / math.pi), "PtfmSurge": (1001, 1.0)}

NMPC_PART = r"""
/* ---- the NMPC with its EKF (generated: nmpc_ekf, nmpc_startup, nmpc_qp_data, nmpc_qp, nmpc_finish) ---- */
#define NZ {n_z}
#define NW {n_w}
#define NLAM {n_lam}
#define KE {ke}
#define KN {kn}
#define QP_ACCEPT {qp_accept!r}
#define INIT_HUB_WIND {init_hub_wind}
#define WIND_LO {wind_lo!r}
#define WIND_HI {wind_hi!r}
#define NXS {n_xs}
#define NUS {n_us}
#define NCS {n_cs}
#define NSTAGE {n_stage}
#define NY {n_y_est}
#define HOLD_MAX (NSTAGE - 1)
int nmpc_ekf(const double** arg, double** res, casadi_int* iw, double* w, int mem);
int nmpc_init(const double** arg, double** res, casadi_int* iw, double* w, int mem);
int nmpc_startup(const double** arg, double** res, casadi_int* iw, double* w, int mem);
int nmpc_qp_data(const double** arg, double** res, casadi_int* iw, double* w, int mem);
int nmpc_qp(const double** arg, double** res, casadi_int* iw, double* w, int mem);
int nmpc_finish(const double** arg, double** res, casadi_int* iw, double* w, int mem);

static const double Z0[NZ] = {{{z0}}};
static const double P0[NZ * NZ] = {{{p0}}};
static const double LEAD[2] = {{{lead}}};
static double z[NZ], P[NZ * NZ], z_next[NZ], P_next[NZ * NZ], plan[NW], plan_next[NW], rates[2], viol;
static double lam[NLAM], lam_next[NLAM];

static double acc[2], ramp0[2], rate[2], cmd[2];
static long k_loop, k_a, n_acc, fallbacks, holds;
static int have_plan, nmpc_on, init_call, streak, slew;
static const double *narg[{n_arg}];
static double *nres[{n_res}];
static casadi_int niw[{n_iw}];
static double nw[{n_w_work}];
{settings_part}
{rti_part}
static int nmpc_rti(const double *wind_or_null, double pitch, double torque)
{{
    return rti_parts(plan, z, pitch, torque, settings, wind_or_null, lam, plan_next, rates, &viol, lam_next);
}}

static double clip(double v, double lo, double hi) {{ return v < lo ? lo : (v > hi ? hi : v); }}
{preview}

static void nmpc_start(void)
{{
    memcpy(xc, X0, sizeof xc);
    memcpy(z, Z0, sizeof z);
    memcpy(P, P0, sizeof P);
    acc[0] = acc[1] = 0.0;
    k_loop = n_acc = fallbacks = holds = 0;
    have_plan = nmpc_on = streak = slew = 0;
    init_call = 1;
#if PV_ON
    pv_reset();
#endif
}}

/* N blocks of `block` values moved one block earlier, the last block repeated (the rest of v untouched). */
static void shift_stages(double *v, int block)
{{
    if (NSTAGE > 1) memmove(v, v + block, sizeof(double) * (size_t)((NSTAGE - 1) * block));
}}

/* After a failed QP: the stored plan's first rates (clipped), the plan and multipliers one more stage ahead
   (the caller then takes the failed QP's multipliers when they are finite). */
static void plan_hold(void)
{{
    rates[0] = clip(plan[NXS], RATE_LIM[0], RATE_LIM[1]);
    rates[1] = clip(plan[NXS + 1], RATE_LIM[2], RATE_LIM[3]);
    shift_stages(plan, NXS + NUS);
    memcpy(plan + (NSTAGE - 1) * (NXS + NUS), plan + NSTAGE * (NXS + NUS), sizeof(double) * NXS);
    shift_stages(lam, NXS + NUS);
    shift_stages(lam + NW, NXS + NCS);
}}

/* The NMPC's ramps hand over to the baseline: the demands move to the baseline's at the NMPC's rate bounds. */
static void nmpc_off(void)
{{
    slew = slew || nmpc_on;
    have_plan = nmpc_on = streak = 0;
}}

static int all_finite(const double *v, int n)
{{
    int i;
    for (i = 0; i < n; ++i) if (!isfinite(v[i])) return 0;
    return 1;
}}
{mhe_part}
/* The estimator's start and restart: steady operation at the measured hub wind (record 27), or the fixed prior. */
static void estimator_restart(const float *swap)
{{
    double hub = (double)swap[26];
    memcpy(P, P0, sizeof P);
    narg[0] = &hub; nres[0] = z;
    if (!(INIT_HUB_WIND && isfinite(hub) && nmpc_init(narg, nres, niw, nw, 0) == 0 && all_finite(z, NZ)))
        memcpy(z, Z0, sizeof z);
#if MHE_ON
    mhe_reset(z);
#endif
}}

/* One loop sample: the baseline law, the EKF every KE samples, the NMPC every KN samples, the demands. */
static int nmpc_sample(float *swap, double t, char *err, size_t n_err)
{{
    double yv[NY], mean[2], flag, pitch, torque, el, since;
    int r, accepted, warn = 0, note = 0, fell = 0;
    if (run_law(swap, t, err, n_err)) return -1;                  /* baseline: held[] are its commands */
    if (init_call) {{               /* the initialization call (status 0): the baseline answers it, see the docs */
        init_call = 0;
        cmd[0] = held[0]; cmd[1] = held[N_U - 1];
        return 0;
    }}
    yv[0] = (double)swap[19] * 30.0 / 3.14159265358979323846;     /* record 20 GenSpeed [rad/s] -> rpm */
    yv[1] = (double)swap[52];                                      /* record 53 YawBrTAxp [m/s^2] */
    pitch = (double)swap[3];                                       /* record 4 BldPitch1 [rad] */
    torque = (double)swap[22];                                     /* record 23 GenTq [N m] */
    if (!(isfinite(yv[0]) && isfinite(yv[1]) && isfinite(pitch) && isfinite(torque))) {{
        snprintf(err, n_err, "records 20, 53, 4, 23 (GenSpeed, YawBrTAxp, BldPitch1, GenTq) must be finite at "
                 "t = %g s", t);
        return -1;
    }}
{read_more}    if (k_loop == 0) estimator_restart(swap);
    else {{ acc[0] += pitch; acc[1] += torque; ++n_acc; }}
    if (k_loop % KE == 0) {{
        if (n_acc > 0) {{ mean[0] = acc[0] / n_acc; mean[1] = acc[1] / n_acc; }}
        else {{ mean[0] = pitch; mean[1] = torque; }}
        flag = k_loop > 0 ? 1.0 : 0.0;
#if MHE_ON
        r = mhe_sample(yv, mean, flag, z_next, P_next, &fell);
        if (fell) {{
            note = 1;
            snprintf(err, n_err, "the MHE's solve was rejected at t = %g s (violation %.3g): the EKF's estimate "
                     "applied (%ld times so far)", t, mviol, mhe_failures);
        }}
#else
        (void)fell;
        narg[0] = z; narg[1] = P; narg[2] = yv; narg[3] = mean; narg[4] = &flag;
        nres[0] = z_next; nres[1] = P_next;
        r = nmpc_ekf(narg, nres, niw, nw, 0);
#endif
        if (r == 0 && all_finite(z_next, NZ) && all_finite(P_next, NZ * NZ) && z_next[NZ - 1] >= WIND_LO
            && z_next[NZ - 1] <= WIND_HI) {{
            memcpy(z, z_next, sizeof z); memcpy(P, P_next, sizeof P);
        }} else {{
            estimator_restart(swap);
            nmpc_off();
            ++fallbacks;
            snprintf(err, n_err, "the EKF's estimate became non-finite or its wind left [%g, %g] m/s at t = %g s: "
                     "estimator restarted, baseline commands applied (%ld fallbacks so far)", WIND_LO, WIND_HI, t,
                     fallbacks);
            warn = 1;
        }}
        acc[0] = acc[1] = 0.0; n_acc = 0;
    }}
#if PV_ON
    if (k_loop % KN == 0) {{                /* the lidar's sample and the stage winds (after the EKF) */
        if (pv_use && pv_push(swap, (double)k_loop * SAMPLE_TIME) && !pv_missing) {{
            pv_missing = 1;
            note = 1;
            snprintf(err, n_err, "no single-point lidar of %d beams in the extended swap records (2001: 1, 2002: %d; "
                     "InflowWind SensorType = 1 and NumBeam) at t = %g s: the NMPC holds the estimated "
                     "wind over its horizon", PV_NB, PV_NB, t);
        }}
        pv_horizon((double)k_loop * SAMPLE_TIME, z[NZ - 1]);
    }}
#endif
    if (k_loop % KN == 0 && !warn) {{
        if (have_plan) {{
#if PV_ON
            r = nmpc_rti(windv, pitch, torque);
#else
            r = nmpc_rti(0, pitch, torque);
#endif
        }} else {{
            nres[0] = plan_next; nres[1] = rates; nres[2] = &viol; nres[3] = lam_next;
            narg[0] = z; narg[1] = &pitch; narg[2] = &torque; narg[3] = settings;
#if PV_ON
            narg[4] = windv;
#endif
            r = nmpc_startup(narg, nres, niw, nw, 0);
        }}
        accepted = r == 0 && all_finite(plan_next, NW) && all_finite(rates, 2) && viol <= QP_ACCEPT;
        if (accepted) {{
            memcpy(plan, plan_next, sizeof plan);
            memcpy(lam, lam_next, sizeof lam);
            streak = 0;
        }} else if (have_plan && streak < HOLD_MAX) {{     /* hold: the previous plan's next rates */
            plan_hold();
            if (r == 0 && all_finite(lam_next, NLAM))    /* the capped QP's active set: the next QP goes on from it */
                memcpy(lam, lam_next, sizeof lam);
            ++streak; ++holds;
            snprintf(err, n_err, "the NMPC's QP failed at t = %g s (code %d, violation %.3g): the previous plan's "
                     "next rates applied (%d in a row, at most %d; %ld holds so far)", t, r, viol, streak, HOLD_MAX,
                     holds);
            warn = 1;
        }} else {{
            nmpc_off();
            ++fallbacks;
            snprintf(err, n_err, "the NMPC's QP failed at t = %g s (code %d, violation %.3g) with no plan to hold: "
                     "baseline commands applied until the next NMPC sample (%ld fallbacks so far)", t, r, viol,
                     fallbacks);
            warn = 1;
        }}
        if (have_plan || accepted) {{
            if (nmpc_on) {{                     /* the new ramps start where the previous ones are now */
                since = (double)(k_loop - k_a) * SAMPLE_TIME;
                ramp0[0] = clip(ramp0[0] + rate[0] * since, LIMITS[0], LIMITS[1]);
                ramp0[1] = clip(ramp0[1] + rate[1] * since, LIMITS[2], LIMITS[3]);
            }} else {{ ramp0[0] = pitch; ramp0[1] = torque; }}
            k_a = k_loop; rate[0] = rates[0]; rate[1] = rates[1];
            have_plan = nmpc_on = 1;
            slew = 0;
        }}
    }}
    if (nmpc_on) {{            /* elapsed time from the sample count: the swap array's time is float32 */
        el = (double)(k_loop - k_a) * SAMPLE_TIME;
        cmd[0] = clip(ramp0[0] + rate[0] * (el + LEAD[0]), LIMITS[0], LIMITS[1]);
        cmd[1] = clip(ramp0[1] + rate[1] * (el + LEAD[1]), LIMITS[2], LIMITS[3]);
    }} else if (slew) {{      /* from the NMPC's last demands to the baseline's at the rate bounds */
        cmd[0] += clip(held[0] - cmd[0], RATE_LIM[0] * SAMPLE_TIME, RATE_LIM[1] * SAMPLE_TIME);
        cmd[1] += clip(held[N_U - 1] - cmd[1], RATE_LIM[2] * SAMPLE_TIME, RATE_LIM[3] * SAMPLE_TIME);
        slew = !(cmd[0] == held[0] && cmd[1] == held[N_U - 1]);
    }} else {{ cmd[0] = held[0]; cmd[1] = held[N_U - 1]; }}
    ++k_loop;
    return warn || note;
}}

static void nmpc_write(float *swap)
{{
    int k;
    for (k = 0; k < 3; ++k) swap[41 + k] = (float)cmd[0];                    /* records 42-44 */
    swap[44] = (float)cmd[0];                                                 /* 45 collective */
    swap[46] = (float)cmd[1];                                                 /* 47 torque */
    swap[34] = 1.0f; swap[35] = 0.0f; swap[40] = 0.0f; swap[45] = 0.0f;       /* 35, 36, 41, 46 */
    swap[47] = 0.0f; swap[54] = 0.0f; swap[55] = 0.0f; swap[64] = 0.0f;       /* 48, 55, 56, 65 */
}}

"""


#: One real-time iteration from its three generated parts (:meth:`~.sample.SampleFunctions.rti`), for a C file
#: that declares ``narg``, ``nres``, ``niw``, ``nw`` (sized for the generated Functions) and defines ``NW``, ``NLAM``
#: (format fields ``nnz_h``, ``nnz_a``). The QP's own return code is not an error here: a QP stopped at its
#: iteration cap returns -1 with its iterate, which the step's violation and finiteness then judge.
RTI_PART = r"""
static double lam_qp[NLAM], qh[{nnz_h}], qg[NW], qa[{nnz_a}], qlba[NLAM - NW], quba[NLAM - NW], qlbx[NW], qubx[NW];
static double qdw[NW], qcost;

static int rti_parts(const double *w_in, const double *z_in, double pitch, double torque, const double *set,
                     const double *wind, const double *lam_in, double *w_next, double *rates_out, double *viol_out,
                     double *lam_out)
{{
    int r;
    narg[0] = w_in; narg[1] = z_in; narg[2] = &pitch; narg[3] = &torque; narg[4] = set; narg[5] = wind;
    nres[0] = qh; nres[1] = qg; nres[2] = qa; nres[3] = qlba; nres[4] = quba; nres[5] = qlbx; nres[6] = qubx;
    r = nmpc_qp_data(narg, nres, niw, nw, 0);
    if (r) return r;
    narg[0] = qh; narg[1] = qg; narg[2] = qa; narg[3] = qlba; narg[4] = quba; narg[5] = qlbx; narg[6] = qubx;
    narg[7] = 0; narg[8] = lam_in; narg[9] = lam_in + NW; narg[10] = 0; narg[11] = 0;
    nres[0] = qdw; nres[1] = &qcost; nres[2] = lam_qp + NW; nres[3] = lam_qp;
    (void)nmpc_qp(narg, nres, niw, nw, 0);
    narg[0] = w_in; narg[1] = qdw; narg[2] = lam_qp; narg[3] = qa; narg[4] = qlba; narg[5] = quba; narg[6] = qlbx;
    narg[7] = qubx; narg[8] = set;
    nres[0] = w_next; nres[1] = rates_out; nres[2] = viol_out; nres[3] = lam_out;
    return nmpc_finish(narg, nres, niw, nw, 0);
}}
"""


def rti_part(fns) -> str:
    """:data:`RTI_PART` for the Functions ``fns`` (:class:`~.sample.SampleFunctions`)."""
    return RTI_PART.format(nnz_h=fns.qp.sparsity_in(0).nnz(), nnz_a=fns.qp.sparsity_in(2).nnz())


def _floats(values) -> str:
    return ", ".join(repr(float(v)) for v in np.asarray(values, dtype=float).reshape(-1, order="F"))


def export_nmpc_discon(nmpc, estimator, baseline, out_dir, *, loop_dt: float, name: str = "nmpc_discon",
                       compiler: str | None = None, initial: str = "hub-wind", preview=None) -> dict:
    """Compile the NMPC with its EKF (and the baseline as its fallback) into a ``DISCON`` library.

    Parameters
    ----------
    nmpc : TurbineNMPC
        Solver ``"rti"``.
    estimator : TurbineEstimator
        Kind ``"ekf"``, or ``"mhe"`` (its real-time iterations, :mod:`.sample_mhe`).
    baseline : BaselineController
        Without IPC, sample time ``loop_dt``: the fallback law.
    out_dir : str or Path
        Directory for ``<name>.so``, ``<name>.IN`` and ``src/``.
    loop_dt : float, keyword-only
        The library's sample time [s] (the loop's: ``deck.controller_dt``).
    name : str, keyword-only
        File name stem.
    compiler : str, optional, keyword-only
        C compiler command (default :func:`mbsym.codegen.compiler_command`).
    initial : {"hub-wind", "fixed"}, keyword-only
        How the EKF starts and restarts: steady operation at the measured hub wind (record 27; the
        default) or the estimator's own prior (:mod:`.sample`).
    preview : PreviewSettings, optional, keyword-only
        Read a single-point lidar from the extended swap records and give the NMPC its preview
        (:mod:`.lidar_preview`; default None: the estimated wind held over the horizon).

    Returns
    -------
    dict
        ``{"library", "input", "controller": "nmpc", "sample_time_s"}`` (absolute paths).

    Raises
    ------
    ControllerError
        No C compiler, a baseline of another sample time or with IPC, a failed compilation.
    ControlDefinitionError
        What :func:`~.sample.sample_functions` refuses (an MHE, a solver other than ``"rti"``, ...).
    ExportError
        A bad ``name`` or an unwritable ``out_dir``.
    """
    from ..control.baseline import BaselineController
    from ..control.discon_export import _compile, _write_sources, prepare_export

    if not isinstance(baseline, BaselineController):
        raise TypeError(f"baseline must be a BaselineController; got {type(baseline).__name__}.")
    if not math.isclose(baseline.dt, loop_dt, rel_tol=1e-12) or baseline.ipc:
        raise ControllerError(f"the fallback baseline must run at the loop sample time {loop_dt:g} s without IPC; "
                              f"got {baseline.dt:g} s{' with IPC' if baseline.ipc else ''}.")
    fns = sample_functions(nmpc, estimator, loop_dt, initial=initial, settings=baseline.settings, preview=preview)
    cc, out = prepare_export(name, compiler, out_dir, "exporting the NMPC")
    gen = (fns.ekf, fns.startup, fns.qp_data, fns.qp, fns.finish, fns.init, *mhe_functions_of(fns))
    fingerprint = hashlib.sha256("".join([baseline.function.serialize(), *(f.serialize() for f in gen),
                                          repr(float(loop_dt)), initial, repr(preview)]).encode()).hexdigest()[:16]
    law, _ = _write_sources(baseline, out / "src", name, fingerprint)
    cg = ca.CodeGenerator(f"{name}_nmpc.c", {"with_header": False, "with_export": False,
                                             "casadi_int": "long long int", "casadi_real": "double"})
    for f in gen:
        cg.add(f)
    cg.generate(str(out / "src") + os.sep)
    wrapper = out / "src" / f"{name}_discon.c"
    wrapper.write_text(_wrapper_text(baseline, fns, fingerprint))
    library = out / f"{name}.so"
    _compile(cc, [law, out / "src" / f"{name}_nmpc.c", wrapper], library)
    infile = out / f"{name}.IN"
    infile.write_text(_input_text(nmpc, estimator, baseline, loop_dt, fingerprint, fns))
    return {"library": str(library.resolve()), "input": str(infile.resolve()), "controller": "nmpc",
            "sample_time_s": float(loop_dt)}


def _read_more(measurements) -> str:
    """C that reads a floating estimator's further measurements into ``yv[2…]`` (:data:`FLOATING_RECORDS`), with
    the array-size check of the extended records (record 129) and a finiteness check."""
    extra = list(measurements[2:])
    if not extra:
        return ""
    unknown = [m for m in extra if m not in FLOATING_RECORDS]
    if unknown:
        raise ControllerError(f"the exported EKF cannot read {unknown} from the swap array (it reads "
                              f"{list(NMPC_RECORDS)} and {list(FLOATING_RECORDS)}).")
    records = [FLOATING_RECORDS[m][0] for m in extra]
    names = ", ".join(f"{r} {m}" for m, r in zip(extra, records))
    need = max(records)
    lines = [f"    if ((long)swap[128] < {need}) {{",
             f'        snprintf(err, n_err, "the swap array has %ld records; the floating EKF reads {names} (OpenFAST '
             'v5 ServoDyn fills the extended records 1001-1018 with the platform motion)", (long)swap[128]);',
             "        return -1;", "    }"]
    for k, m in enumerate(extra, start=2):
        rec, factor = FLOATING_RECORDS[m]
        lines.append(f"    yv[{k}] = (double)swap[{rec - 1}] * {factor!r};{' ' * 8}/* record {rec} {m} */")
    finite = " && ".join(f"isfinite(yv[{k}])" for k in range(2, 2 + len(extra)))
    lines += [f"    if (!({finite})) {{",
              f'        snprintf(err, n_err, "records {", ".join(str(r) for r in records)} ({", ".join(extra)}) must '
              'be finite at t = %g s", t);', "        return -1;", "    }"]
    return "\n".join(lines) + "\n"


def _wrapper_text(baseline, fns, fingerprint: str) -> str:
    from ..control.discon_export import _LAW

    f = baseline.function
    xs, ys = ca.SX.sym("xc", f.size1_in(0)), ca.SX.sym("y", f.size1_in(1))
    base = ca.Function(_LAW, [xs, ys], f(xs, ys), {"cse": True})        # as discon_export generates it
    measured = list(baseline.measurements)
    records = [MEASUREMENT_RECORDS[m][0] for m in measured]
    gens = (fns.ekf, fns.startup, fns.qp_data, fns.qp, fns.finish, fns.init, *mhe_functions_of(fns))
    common = dict(
        controller="nmpc", sample_time=float(fns.loop_dt), n_x=f.size1_in(0), n_y=len(measured), n_u=f.size1_out(1),
        fingerprint=fingerprint, ipc=0, law=_LAW, x0=_floats(baseline.x0),
        y_records=", ".join(str(r) for r in records), y_names=", ".join(f'"{m}"' for m in measured),
        sz_arg=max(base.sz_arg(), 1), sz_res=max(base.sz_res(), 1), sz_iw=max(base.sz_iw(), 1),
        sz_w=max(base.sz_w(), 1),
        measured=", ".join(f"{r} {m}" for m, r in _nmpc_records(fns).items()) + " (NMPC, EKF); "
        + ", ".join(f"{r} {m}" for r, m in zip(records, measured)) + " (baseline fallback)",
        written="42-45 collective pitch, 47 torque")
    nmpc = dict(n_y_est=len(fns.measurements), read_more=_read_more(fns.measurements), n_z=fns.z0.size,
                n_w=fns.n_w, n_lam=fns.n_lam, rti_part=rti_part(fns), ke=fns.ke, kn=fns.kn, qp_accept=QP_ACCEPT,
                z0=_floats(fns.z0),
                init_hub_wind=int(fns.initial == "hub-wind"), wind_lo=float(fns.wind_range[0]),
                wind_hi=float(fns.wind_range[1]),
                p0=_floats(fns.P0), lead=_floats(fns.lead), settings_part=settings_c(fns.layout),
                n_xs=fns.stage[0], n_us=fns.stage[1],
                n_cs=fns.stage[2], n_stage=fns.horizon,
                n_arg=max(g.sz_arg() for g in gens), n_res=max(g.sz_res() for g in gens),
                n_iw=max(max(g.sz_iw() for g in gens), 1), n_w_work=max(max(g.sz_w() for g in gens), 1),
                preview=preview_c(fns.preview, fns.nmpc_dt, fns.horizon), mhe_part=mhe_part(fns))
    entry = ENTRY.replace("{start}", "nmpc_start();").replace("{sample}", "nmpc_sample").replace("{write}",
                                                                                                 "nmpc_write")
    return (HEAD + LAW + CHECK).format(**common) + NMPC_PART.format(**nmpc) + entry.format(**common)


def _input_text(nmpc, estimator, baseline, loop_dt: float, fingerprint: str, fns) -> str:
    e = estimator.tuning
    from ..control.discon_export import EXPORT_HEADER, SETTINGS_COMMENT, _absolute

    lines = [
        f"{EXPORT_HEADER}, written by mbsym export-discon (value  Key  ! comment)",
        f"{SETTINGS_COMMENT}{_absolute(baseline.settings.source or 'settings given in Python')}",
        "! the NMPC's model, its estimator and the fallback baseline are compiled into the library",
        f"{'nmpc':<24} Controller   ! controller kind",
        f"{float(loop_dt)!r:<24} SampleTime   ! library (loop) sample time [s]; the communication interval must "
        "divide it",
        f"{fingerprint:<24} Fingerprint  ! identity of the compiled controller (pairs this file with its library)",
        *input_lines(fns.layout),
        f"!   NMPC: real-time iteration with qrqp; estimator: {_estimator_label(estimator)}; references: steady "
        + ("operation with the controller's peak-shaving minimum pitch" if nmpc.tuning.peak_shaving else
           "operation at fine pitch below rated"),
        f"!   EKF noise: wind_walk {e.wind_walk:g}, gen_speed_sd {e.gen_speed_sd:g} rpm, accel_sd {e.accel_sd:g}"
        + (f"; blade-passing ripple states, walks {e.harmonic_speed_walk:g} rpm, {e.harmonic_accel_walk:g} m/s^2"
           if e.blade_passing else ""),
        f"!   EKF model states: {', '.join(estimator.names)}",
        "!   EKF start and restart: " + ("steady operation at the measured hub wind (record 27)"
                                         if fns.initial == "hub-wind" else
                                         f"fixed prior at {fns.z0[-1]:g} m/s")
        + f"; restarted when its wind leaves [{fns.wind_range[0]:g}, {fns.wind_range[1]:g}] m/s",
        f"!   fallback: baseline controller from {baseline.settings.source or 'settings given in Python'}",
        "!   preview: " + ("none (the estimated wind held over the horizon)" if fns.preview is None else
                           f"single-point lidar, {fns.preview.n_beams} beams {fns.preview.distance:g} m upstream "
                           f"(records 2001-{2004 + 4 * fns.preview.n_beams}), moving average {fns.preview.window:g} s, "
                           f"advection filter {fns.preview.advection_time:g} s"),
        "! measurements (swap records): " + ", ".join(f"{m} ({r})" for m, r in _nmpc_records(fns).items())
        + "; baseline: " + ", ".join(f"{m} ({MEASUREMENT_RECORDS[m][0]})" for m in baseline.measurements),
    ]
    return "\n".join(lines) + "\n"


def _estimator_label(estimator) -> str:
    """``EKF`` or ``MHE (window M intervals, one real-time iteration per sample)``."""
    if estimator.kind == "mhe":
        return f"MHE (window {estimator.tuning.window} intervals, one real-time iteration per sample with qrqp)"
    return "EKF"


def _nmpc_records(fns) -> dict[str, int]:
    """Measurement name -> swap record of what the NMPC and its EKF read (:data:`NMPC_RECORDS`, a floating
    estimator's :data:`FLOATING_RECORDS`)."""
    return {**NMPC_RECORDS, **{m: FLOATING_RECORDS[m][0] for m in fns.measurements[2:]}}
