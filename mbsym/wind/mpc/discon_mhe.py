"""The C of an exported NMPC's MHE (:mod:`.sample_mhe`): its memory, its sample and its restart.

:func:`mhe_part` fills :data:`MHE_PART` for the Functions of :func:`~.sample_mhe.mhe_functions`; the
wrapper of :mod:`.discon_nmpc` calls ``mhe_sample`` where it would call the EKF and ``mhe_reset``
where it restarts the estimator. Without an MHE the part only defines ``MHE_ON 0``.

``mhe_sample`` mirrors :meth:`~.sample_mhe.MHEMirror.step`: ``mhe_push`` (the EKF, the arrival cost, the window's
buffers), then with a full window ``mhe_first`` (no window yet) or the real-time iteration ``mhe_rti`` (the QP's KKT
system without its bounds), and where that leaves a bound the same steps with the bounds (``mhe_window0`` or
``mhe_shift``, then ``mhe_qp_data``, ``mhe_qp`` (qrqp; its return code is not an error: a capped QP is judged by its
step's violation), ``mhe_finish``). A rejected solve gives the EKF's estimate and is counted (``mhe_failures``), and
the next full window starts with ``mhe_first`` again."""

from __future__ import annotations

from .sample_mhe import FIRST_ITERATIONS

__all__ = ["MHE_PART", "mhe_functions_of", "mhe_part"]

MHE_PART = r"""
/* ---- the MHE (generated: mhe_push, mhe_first, mhe_rti, mhe_shift, mhe_window0, mhe_qp_data, mhe_qp,
        mhe_finish) ---- */
#define MHE_ON 1
#define MS {n_s}
#define MWN {n_w}
#define MNA {n_a}
#define M_COUNT {i_count}
#define M_FULL {full}
#define FIRST_ITERATIONS {first_iterations}
int mhe_push(const double** arg, double** res, casadi_int* iw, double* w, int mem);
int mhe_first(const double** arg, double** res, casadi_int* iw, double* w, int mem);
int mhe_rti(const double** arg, double** res, casadi_int* iw, double* w, int mem);
int mhe_shift(const double** arg, double** res, casadi_int* iw, double* w, int mem);
int mhe_window0(const double** arg, double** res, casadi_int* iw, double* w, int mem);
int mhe_qp_data(const double** arg, double** res, casadi_int* iw, double* w, int mem);
int mhe_qp(const double** arg, double** res, casadi_int* iw, double* w, int mem);
int mhe_finish(const double** arg, double** res, casadi_int* iw, double* w, int mem);
static double ms[MS], ms_next[MS], mwin[MWN], mwin_next[MWN], mw0[MWN], mz[NZ], mz_ekf[NZ], mviol;
static double mh[{nnz_h}], mg[MWN], ma[{nnz_a}], mlba[MNA], muba[MNA], mlbx[MWN], mubx[MWN], mdw[MWN], mcost;
static double mlam_x[MWN], mlam_a[MNA];
static int have_window;
static long mhe_failures, mhe_bounded_solves;

/* A (re)start at the estimate z0: the prior covariance in the EKF and the arrival cost, an empty window. */
static void mhe_reset(const double *z0)
{{
    memset(ms, 0, sizeof ms);
    memcpy(ms + {i_z}, z0, sizeof(double) * NZ);
    memcpy(ms + {i_p}, P0, sizeof(double) * NZ * NZ);
    memcpy(ms + {i_zbar}, z0, sizeof(double) * NZ);
    memcpy(ms + {i_pbar}, P0, sizeof(double) * NZ * NZ);
    have_window = 0;
}}

/* Whether a solve (return code r) gave a finite window within the acceptance test. */
static int mhe_accepted(int r)
{{
    return r == 0 && all_finite(mwin_next, MWN) && all_finite(mz, NZ) && mviol <= QP_ACCEPT;
}}

/* `iterations` full steps of the window's QP with its bounds (qrqp) from mw0: the window into mwin_next, the
   estimate into mz, the largest violation into mviol (NaN kept). qrqp's own return code is not an error: a capped
   QP is judged by its step's violation. */
static int mhe_bounded(int iterations)
{{
    int r = 0, i, k;
    double worst = 0.0;
    ++mhe_bounded_solves;
    for (i = 0; i < iterations && r == 0; ++i) {{
        if (i > 0) memcpy(mw0, mwin_next, sizeof mw0);
        narg[0] = mw0; narg[1] = ms;
        nres[0] = mh; nres[1] = mg; nres[2] = ma; nres[3] = mlba; nres[4] = muba; nres[5] = mlbx; nres[6] = mubx;
        r = mhe_qp_data(narg, nres, niw, nw, 0);
        if (r) break;
        narg[0] = mh; narg[1] = mg; narg[2] = ma; narg[3] = mlba; narg[4] = muba; narg[5] = mlbx; narg[6] = mubx;
        for (k = 7; k < 12; ++k) narg[k] = 0;
        nres[0] = mdw; nres[1] = &mcost; nres[2] = mlam_a; nres[3] = mlam_x;
        (void)mhe_qp(narg, nres, niw, nw, 0);
        narg[0] = mw0; narg[1] = mdw; narg[2] = ma; narg[3] = mlba; narg[4] = muba; narg[5] = mlbx; narg[6] = mubx;
        nres[0] = mwin_next; nres[1] = mz; nres[2] = &mviol;
        r = mhe_finish(narg, nres, niw, nw, 0);
        if (!(mviol <= worst)) worst = mviol;
    }}
    mviol = worst;
    return r;
}}

/* One estimator sample: the estimate into z_out, the EKF's covariance into P_out; *fell = 1 when the MHE's solve
   was rejected (the EKF's estimate given instead). Nonzero when the EKF's own sample failed. */
static int mhe_sample(const double *y, const double *u, double flag, double *z_out, double *P_out, int *fell)
{{
    int r;
    *fell = 0;
    narg[0] = ms; narg[1] = y; narg[2] = u; narg[3] = &flag;
    nres[0] = ms_next; nres[1] = mz_ekf;
    if (mhe_push(narg, nres, niw, nw, 0)) return -1;
    memcpy(ms, ms_next, sizeof ms);
    memcpy(P_out, ms + {i_p}, sizeof(double) * NZ * NZ);
    if (ms[M_COUNT] < M_FULL) {{ memcpy(z_out, mz_ekf, sizeof(double) * NZ); return 0; }}
    if (have_window) {{                /* the real-time iteration, its QP's bounds left out */
        narg[0] = mwin; narg[1] = ms;
        nres[0] = mwin_next; nres[1] = mz; nres[2] = &mviol;
        r = mhe_rti(narg, nres, niw, nw, 0);
        if (!mhe_accepted(r)) {{        /* a bound left: one step of the QP with its bounds */
            narg[0] = mwin; narg[1] = ms; nres[0] = mw0;
            r = mhe_shift(narg, nres, niw, nw, 0);
            if (r == 0) r = mhe_bounded(1);
        }}
    }} else {{                          /* the first solve of a full window */
        narg[0] = ms;
        nres[0] = mwin_next; nres[1] = mz; nres[2] = &mviol;
        r = mhe_first(narg, nres, niw, nw, 0);
        if (!mhe_accepted(r)) {{
            narg[0] = ms; nres[0] = mw0;
            r = mhe_window0(narg, nres, niw, nw, 0);
            if (r == 0) r = mhe_bounded(FIRST_ITERATIONS);
        }}
    }}
    if (mhe_accepted(r)) {{
        memcpy(mwin, mwin_next, sizeof mwin);
        memcpy(z_out, mz, sizeof(double) * NZ);
        have_window = 1;
    }} else {{
        memcpy(z_out, mz_ekf, sizeof(double) * NZ);
        have_window = 0;
        ++mhe_failures;
        *fell = 1;
    }}
    return 0;
}}
"""


def mhe_part(fns) -> str:
    """:data:`MHE_PART` for the :class:`~.sample.SampleFunctions` ``fns`` (``#define MHE_ON 0`` without an MHE)."""
    m = fns.mhe
    if m is None:
        return "\n#define MHE_ON 0\n"
    L = m.layout
    n_a = m.qp.sparsity_in(2).size1()
    return MHE_PART.format(first_iterations=FIRST_ITERATIONS, n_s=m.n_s, n_w=m.n_W, n_a=n_a,
                           i_count=L["count"].start, full=m.window + 1, nnz_h=m.qp.sparsity_in(0).nnz(),
                           nnz_a=m.qp.sparsity_in(2).nnz(), i_z=L["z"].start,
                           i_p=L["P"].start, i_zbar=L["zbar"].start, i_pbar=L["Pbar"].start)


def mhe_functions_of(fns) -> tuple:
    """The MHE's Functions to generate (none without an MHE)."""
    return () if fns.mhe is None else fns.mhe.functions()
