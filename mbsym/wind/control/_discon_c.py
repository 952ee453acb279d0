"""The hand-written C of an exported DISCON library (private; see :mod:`.discon_export`).

:data:`WRAPPER` is a template (``str.format`` fields in ``{{...}}``-escaped C): the generated
controller law ``law(xc, y) -> (xc_next, u)`` (CasADi ``CodeGenerator``) is called from
``DISCON`` with the swap-array records as measurements, once per controller sample, its
commands held between samples. Fixed memory: every array is static and sized at generation time.

The template is assembled from parts that other exported controllers reuse (the NMPC's wrapper,
:mod:`mbsym.wind.mpc.discon_nmpc`): :data:`HEAD` (constants, static arrays, messages, the input
file: its three common keys, a controller's own through the hooks ``input_begin``, ``input_key`` and
``input_end``; :data:`NO_KEYS` the hooks of a controller with none), :data:`LAW` (the law called on
the swap records, its commands written), :data:`CHECK` (the
interface records) and :data:`ENTRY` (the ``DISCON`` entry point with its decimation, calling a
sample function that may warn: ``aviFAIL = 1``).
"""

from __future__ import annotations

__all__ = ["WRAPPER", "HEAD", "NO_KEYS", "LAW", "CHECK", "ENTRY"]

#: The C before the controller law: includes, constants, static arrays, messages and the input file.
HEAD = r"""/* DISCON entry point of an mbsym-exported controller ({controller}); written by mbsym export-discon.
 *
 * void DISCON(float *avrSWAP, int *aviFAIL, const char *accINFILE, char *avcOUTNAME, char *avcMSG)
 * Bladed-style interface as OpenFAST ServoDyn calls it (records 1-based as in the Bladed manual):
 *   reads   1 status, 2 time, 3 communication interval, 10 pitch actuator type (must be 0),
 *           28 pitch control (1 individual: needed with IPC), 49 message buffer size,
 *           50 input-file name length, 61 number of blades, and the measurements {measured};
 *   writes  {written}, 35 = 1, 36 = 0, 41 = 0, 46 = 0, 48 = 0, 55 = 0, 56 = 0, 65 = 0.
 * The law runs at status 0 (first call: reads the input file) and then once per sample time
 * {sample_time!r} s (the calls in between hold the last commands); status -1 ends the run.
 * Errors: aviFAIL = -1 with a message in avcMSG; the host is never stopped by this code.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#if defined(_WIN32)
#define EXPORT __declspec(dllexport)
#else
#define EXPORT __attribute__((visibility("default")))
#endif
#define N_X {n_x}
#define N_Y {n_y}
#define N_U {n_u}
#define SAMPLE_TIME {sample_time!r}
#define FINGERPRINT "{fingerprint}"
#define CONTROLLER "{controller}"
#define IPC {ipc}

typedef long long int casadi_int;
int {law}(const double** arg, double** res, casadi_int* iw, double* w, int mem);

static const double X0[N_X] = {{{x0}}};
static const int Y_RECORDS[N_Y] = {{{y_records}}};
static const char *Y_NAMES[N_Y] = {{{y_names}}};

static double xc[N_X], xc_next[N_X], y[N_Y], u[N_U], held[N_U];
static const double *arg[{sz_arg}];
static double *res[{sz_res}];
static casadi_int iw[{sz_iw}];
static double w[{sz_w}];
static int started = 0;
static double t_first, t_next, interval;

static void message(float *swap, char *msg, const char *text)
{{
    int n;
    if (msg == NULL || swap == NULL) return;
    n = (int)swap[48];                       /* record 49: size of avcMSG, NUL included */
    if (n > 4096) n = 4096;
    if (n < 1) return;
    strncpy(msg, text, (size_t)(n - 1));
    msg[n - 1] = '\0';
}}

static int fail(float *swap, int *status, char *msg, const char *text)
{{
    char buf[600];
    snprintf(buf, sizeof buf, "mbsym DISCON (%s): %s", CONTROLLER, text);
    message(swap, msg, buf);
    *status = -1;
    started = 0;
    return -1;
}}

/* The controller's own keys (input_begin resets them, input_key reads one: 1 read, -1 error in err; input_end
 * checks them together): defined by each exported controller after this part. */
static void input_begin(void);
static int input_key(const char *file, const char *value, const char *key, char *err, size_t n_err);
static int input_end(const char *file, char *err, size_t n_err);

/* The input file: lines "value  Key  ! comment"; keys Controller, SampleTime, Fingerprint and the controller's own
 * (input_key); an unknown or repeated key is an error. */
static int read_input(float *swap, const char *infile, char *err, size_t n_err)
{{
    char name[1024], line[512], value[256], key[64], seen[64][64];
    int length = (int)swap[49], i, got_kind = 0, got_dt = 0, got_id = 0, n_seen = 0;
    FILE *f;
    if (infile == NULL) {{ snprintf(err, n_err, "no input file name (accINFILE is NULL)"); return -1; }}
    if (length < 1 || length > (int)sizeof name) length = (int)sizeof name;
    for (i = 0; i < length - 1 && infile[i] != '\0'; ++i) name[i] = infile[i];
    name[i] = '\0';
    while (i > 0 && (name[i - 1] == ' ')) name[--i] = '\0';
    f = fopen(name, "r");
    if (f == NULL) {{
        snprintf(err, n_err, "cannot open the input file '%s' (ServoDyn DLL_InFile); give the file written "
                 "next to the library by mbsym export-discon", name);
        return -1;
    }}
    input_begin();
    while (fgets(line, sizeof line, f) != NULL) {{
        if (sscanf(line, "%255s %63s", value, key) != 2 || value[0] == '!' || value[0] == '#') continue;
        for (i = 0; i < n_seen; ++i) {{
            if (strcmp(seen[i], key) == 0) {{
                snprintf(err, n_err, "%s: key %s is given twice", name, key); fclose(f); return -1;
            }}
        }}
        if (n_seen < 64) strcpy(seen[n_seen++], key);
        if (strcmp(key, "Controller") == 0) {{
            got_kind = 1;
            if (strcmp(value, CONTROLLER) != 0) {{
                snprintf(err, n_err, "%s: Controller is '%s'; this library runs '%s'", name, value, CONTROLLER);
                fclose(f); return -1;
            }}
        }} else if (strcmp(key, "SampleTime") == 0) {{
            char *end; double dt = strtod(value, &end);
            got_dt = 1;
            if (*end != '\0' || !(fabs(dt - SAMPLE_TIME) <= 1e-9 * SAMPLE_TIME)) {{
                snprintf(err, n_err, "%s: SampleTime is '%s' s; this library's law is compiled for %.17g s "
                         "(export again with the sample time you need)", name, value, SAMPLE_TIME);
                fclose(f); return -1;
            }}
        }} else if (strcmp(key, "Fingerprint") == 0) {{
            got_id = 1;
            if (strcmp(value, FINGERPRINT) != 0) {{
                snprintf(err, n_err, "%s: Fingerprint %s does not match this library's %s: the input file "
                         "belongs to another export", name, value, FINGERPRINT);
                fclose(f); return -1;
            }}
        }} else if (input_key(name, value, key, err, n_err) < 0) {{
            fclose(f); return -1;
        }}
    }}
    fclose(f);
    if (!(got_kind && got_dt && got_id)) {{
        snprintf(err, n_err, "%s: missing key(s)%s%s%s; expected Controller, SampleTime and Fingerprint", name,
                 got_kind ? "" : " Controller", got_dt ? "" : " SampleTime", got_id ? "" : " Fingerprint");
        return -1;
    }}
    return input_end(name, err, n_err);
}}

"""

#: The input-file hooks of a controller with no keys of its own (the baseline: every setting compiled in).
NO_KEYS = r"""static void input_begin(void) {{ }}

static int input_key(const char *file, const char *value, const char *key, char *err, size_t n_err)
{{
    (void)value;
    snprintf(err, n_err, "%s: unknown key '%s'; this library reads Controller, SampleTime and Fingerprint (every "
             "setting of the law is compiled in)", file, key);
    return -1;
}}

static int input_end(const char *file, char *err, size_t n_err) {{ (void)file; (void)err; (void)n_err; return 0; }}

"""

#: The baseline law called on the swap records (``run_law``) and its commands written (``write_commands``).
LAW = r"""static int run_law(float *swap, double t, char *err, size_t n_err)
{{
    int i;
    for (i = 0; i < N_Y; ++i) {{
        y[i] = (double)swap[Y_RECORDS[i] - 1];
        if (!isfinite(y[i])) {{
            snprintf(err, n_err, "record %d (%s) is not finite at t = %g s", Y_RECORDS[i], Y_NAMES[i], t);
            return -1;
        }}
    }}
    arg[0] = xc; arg[1] = y; res[0] = xc_next; res[1] = u;
    if ({law}(arg, res, iw, w, 0) != 0) {{
        snprintf(err, n_err, "the controller law failed at t = %g s", t); return -1;
    }}
    for (i = 0; i < N_U; ++i) {{
        if (!isfinite(u[i])) {{ snprintf(err, n_err, "command %d is not finite at t = %g s", i + 1, t); return -1; }}
    }}
    memcpy(xc, xc_next, sizeof xc);
    memcpy(held, u, sizeof held);
    return 0;
}}

static void write_commands(float *swap)
{{
    int k;
    for (k = 0; k < 3; ++k) swap[41 + k] = (float)(IPC ? held[k] : held[0]);   /* records 42-44 */
    swap[44] = (float)held[0];                                                 /* 45 collective */
    swap[46] = (float)held[N_U - 1];                                           /* 47 torque */
    swap[34] = 1.0f; swap[35] = 0.0f; swap[40] = 0.0f; swap[45] = 0.0f;        /* 35, 36, 41, 46 */
    swap[47] = 0.0f; swap[54] = 0.0f; swap[55] = 0.0f; swap[64] = 0.0f;        /* 48, 55, 56, 65 */
}}

"""

#: ``check_records``: the interface records checked at the first call.
CHECK = r"""static int check_records(float *swap, char *err, size_t n_err)
{{
    double dt = (double)swap[2], ratio;
    int blades = (int)lround((double)swap[60]);
    if (!(isfinite(dt) && dt > 0.0)) {{
        snprintf(err, n_err, "record 3 (communication interval) is %g s; expected > 0", dt); return -1;
    }}
    ratio = SAMPLE_TIME / dt;
    if (ratio < 1.0 - 1e-4 || fabs(ratio - floor(ratio + 0.5)) > 1e-4 * ratio) {{
        snprintf(err, n_err, "the sample time %.9g s is not a multiple of the communication interval "
                 "(record 3) %.9g s; set ServoDyn's DLL_DT (or DT) to a divisor of it", SAMPLE_TIME, dt);
        return -1;
    }}
    if (swap[9] != 0.0f) {{
        snprintf(err, n_err, "record 10 is %g; this controller commands pitch positions (0)", swap[9]); return -1;
    }}
    if (IPC && (blades != 3 || swap[27] != 1.0f)) {{
        snprintf(err, n_err, "individual pitch control needs 3 blades (record 61: %d) and individual pitch "
                 "demands (record 28 = ServoDyn Ptch_Cntrl: %g; set it to 1)", blades, swap[27]);
        return -1;
    }}
    if (blades < 1 || blades > 3) {{
        snprintf(err, n_err, "record 61 (number of blades) is %d; expected 1, 2 or 3", blades); return -1;
    }}
    interval = dt;
    return 0;
}}

"""

#: The ``DISCON`` entry point; fields ``start`` (C run at the first call), ``sample`` (a function
#: ``int f(float *swap, double t, char *err, size_t n_err)``: 0 done, 1 warning, -1 error) and ``write``.
ENTRY = r"""/* One controller sample: {sample}() returns 0 (done), 1 (done with a warning in err: aviFAIL = 1) or -1 (error). */
static int sample(float *swap, int *status, char *msg, double t, char *err, size_t n_err)
{{
    int r = {sample}(swap, t, err, n_err);
    if (r < 0) {{ fail(swap, status, msg, err); return -1; }}
    if (r > 0) {{
        char buf[600];
        snprintf(buf, sizeof buf, "mbsym DISCON (%s): %s", CONTROLLER, err);
        message(swap, msg, buf);
        *status = 1;
    }}
    return 0;
}}

EXPORT void DISCON(float *avrSWAP, int *aviFAIL, const char *accINFILE, char *avcOUTNAME, char *avcMSG)
{{
    char err[512];
    int status;
    double t;
    (void)avcOUTNAME;
    if (aviFAIL == NULL) return;
    if (avrSWAP == NULL) {{ *aviFAIL = -1; return; }}
    *aviFAIL = 0;
    status = (int)lround((double)avrSWAP[0]);
    t = (double)avrSWAP[1];
    if ((double)status != (double)avrSWAP[0] || !isfinite(t)) {{
        snprintf(err, sizeof err, "record 1 (status) = %g, record 2 (time) = %g: expected status 0, 1 or -1 "
                 "and a finite time", avrSWAP[0], t);
        fail(avrSWAP, aviFAIL, avcMSG, err); return;
    }}
    if (status == -1) {{ started = 0; return; }}                        /* final call */
    if (status == 0) {{
        if (read_input(avrSWAP, accINFILE, err, sizeof err) || check_records(avrSWAP, err, sizeof err)) {{
            fail(avrSWAP, aviFAIL, avcMSG, err); return;
        }}
        {start}
        if (sample(avrSWAP, aviFAIL, avcMSG, t, err, sizeof err)) return;
        started = 1;
        t_first = t;
        t_next = t + SAMPLE_TIME;
        {write}(avrSWAP);
        return;
    }}
    if (status != 1) {{
        snprintf(err, sizeof err, "record 1 (status) is %d; supported: 0 (first call), 1 (step), -1 (last call); "
                 "checkpoints (-8, -9) are not", status);
        fail(avrSWAP, aviFAIL, avcMSG, err); return;
    }}
    if (!started) {{
        fail(avrSWAP, aviFAIL, avcMSG, "a step call (status 1) before the first call (status 0) or after a "
             "failure; start the run again");
        return;
    }}
    if ((double)avrSWAP[2] != interval) {{
        snprintf(err, sizeof err, "record 3 (communication interval) changed from %g s to %g s", interval,
                 avrSWAP[2]);
        fail(avrSWAP, aviFAIL, avcMSG, err); return;
    }}
    if (t >= t_next - 0.5 * interval) {{                                /* a controller sample */
        if (sample(avrSWAP, aviFAIL, avcMSG, t, err, sizeof err)) return;
        t_next = t_first + (floor((t - t_first) / SAMPLE_TIME + 0.5) + 1.0) * SAMPLE_TIME;
    }}
    {write}(avrSWAP);
}}
"""

#: The baseline controller's whole wrapper.
WRAPPER = (HEAD + NO_KEYS + LAW + CHECK + ENTRY).replace("{start}", "memcpy(xc, X0, sizeof xc);").replace(
    "{sample}", "run_law").replace("{write}", "write_commands")
