/* peer_side - revjoint.h side by side with a MuJoCo peer (bench/peer_mujoco.c) on the
   two-link deployment (paper sec. 5, 6 s simulated), every setting measured against one
   converged reference and timed alternately in one run.

   The peer runs as a separate program (build/peer_mujoco, `make peer`), so this one builds
   without MuJoCo. Each setting runs once with 1 ms samples for its errors (the peer through
   --csv into a file beside the peer binary), then R rounds time every setting once in turn,
   so that all of them see the same phases of the machine; the report gives the median CPU.
   The errors are those of bench/deploy_errors.py, computed here:
     dq1, dq2   max |q - q_ref| (deg) over the reference's samples with t < 2.9939 s, the run
                interpolated linearly to the reference's times;
     frequency  link 2's tip deflection (from the tangent at its root) on a uniform 1 ms grid
                in 3.05-3.95 s and 4.5-6 s: the largest periodogram peak (Hann window, DFT
                on the bins of a 2^16-point FFT from 0.2 to 30 Hz), refined by golden-section
                search on the residual of a least-squares fit of a constant, a ramp and a
                sine pair at the candidate and at up to three other peaks (> 5 % of the
                largest); relative to the reference's;
     tip RMS    the same deflection's RMS about its mean over 3.2-6 s, relative.

   usage: peer_side [--peer PATH] [--out FILE.md] [--plot FILE.png] [--rounds R] [--quick] */
#define _POSIX_C_SOURCE 200809L
#define REVJOINT_IMPLEMENTATION
#include "../revjoint.h"
#include "../examples/scenes.h"
#include "../examples/cli.h"
#include "../render/rj_render.h"
#include <stdarg.h>
#include <time.h>
#include <sys/wait.h>

static const char usage[] =
    "usage: peer_side [--peer PATH] [--out FILE.md] [--plot FILE.png] [--rounds R] [--quick]\n"
    "  --peer PATH      the MuJoCo peer (default build/peer_mujoco, `make peer`); when it is\n"
    "                   missing or fails, the report has revjoint.h's rows alone and says so\n"
    "  --out FILE.md    the markdown section (default standard output)\n"
    "  --plot FILE.png  CPU time against max(dq1, dq2); FILE_freq.png: against the\n"
    "                   frequency error after both locks (default: no plots)\n"
    "  --rounds R       timing rounds, every setting once in each (default 5)\n"
    "  --quick          a smoke test: one round, reference at 40 elements, dt 1.3 us\n";

#define PI 3.14159265358979323846
#define T_END 6.0
#define SAMPLE_DT 1e-3
#define MAX_SAMPLES 6100
#define ENERGY_EVERY 16
#define T_PRE 2.9939
#define RMS_T0 3.2
#define RMS_T1 6.0
#define FFT_POINTS 65536
#define F_LO 0.2
#define F_HI 30.0
#define MAX_OTHERS 3
#define GOLDEN_STEPS 60
#define MAX_PIECES 20
#define MAX_ROUNDS 99
#define MAX_OUTPUT 4096

/* the frequency windows: between joint 2's lock and joint 1's, and after both */
static const double WINDOWS[2][2] = { { 3.05, 3.95 }, { 4.5, 6.0 } };

enum { KIND_PEER, KIND_SEGMENTED, KIND_FLEXIBLE, KIND_INEXTENSIBLE };

/* One setting: what runs, at which step (0: the library's choice). */
typedef struct spec {
    int kind;
    int size;      /* pieces per link (peer, segmented) or elements per link */
    int rk4;       /* peer: 1 = RK4, 0 = semi-implicit Euler */
    double dt;     /* s */
} spec;

/* The peer at its largest stable steps (bench/peer_mujoco.c), then revjoint.h. */
static const spec SPECS[] = {
    { KIND_PEER, 5, 0, 1e-3 },
    { KIND_PEER, 5, 1, 2e-3 },
    { KIND_PEER, 10, 0, 2.5e-4 },
    { KIND_PEER, 10, 1, 5e-4 },
    { KIND_PEER, 20, 0, 6.25e-5 },
    { KIND_PEER, 20, 1, 1.25e-4 },
    { KIND_SEGMENTED, 5, 0, 0 },
    { KIND_SEGMENTED, 6, 0, 0 },
    { KIND_SEGMENTED, 6, 0, 5e-4 },
    { KIND_SEGMENTED, 8, 0, 0 },
    { KIND_SEGMENTED, 10, 0, 0 },
    { KIND_SEGMENTED, 10, 0, 2e-4 },
    { KIND_SEGMENTED, 20, 0, 0 },
    { KIND_FLEXIBLE, 10, 0, 0 },
    { KIND_FLEXIBLE, 20, 0, 0 },
    { KIND_FLEXIBLE, 20, 0, 4e-6 },
    { KIND_FLEXIBLE, 40, 0, 0 },
    { KIND_FLEXIBLE, 40, 0, 2e-6 },
    { KIND_INEXTENSIBLE, 5, 0, 0 },
};
#define NSPECS ((int)(sizeof SPECS / sizeof SPECS[0]))

/* A 1 ms history: joint angles (deg) and link 2's tip deflection (m). */
typedef struct history {
    int n;
    double t[MAX_SAMPLES];
    double q1[MAX_SAMPLES];
    double q2[MAX_SAMPLES];
    double defl[MAX_SAMPLES];
} history;

/* What a history is measured by, alone. */
typedef struct measures {
    double freq[2];   /* Hz, per window */
    double rms;       /* m */
} measures;

/* A history against the reference. */
typedef struct errors {
    double dq1;       /* deg */
    double dq2;       /* deg */
    double freq[2];   /* relative */
    double rms;       /* relative */
} errors;

/* One row of the table, with its model (ours) and its timings. */
typedef struct row {
    spec sp;
    rj_model *m;
    rj_state *s;
    double dt;        /* s, the step in use */
    double bound;     /* s, ours: the stability bound */
    int ok;
    char msg[320];   /* why the row failed */
    errors e;
    double cpu[MAX_ROUNDS];
    int timed;
    double cpu_median;
} row;

/* The reference and its own convergence check. */
typedef struct reference {
    history *h;
    measures ms;
    spec sp;
    double cpu;       /* s, its sampled run */
    double lock[2];   /* s, joints 1 and 2 */
    spec check_sp;
    errors check;
} reference;

/* Command-line options. */
typedef struct options {
    const char *peer;
    const char *out;
    const char *plot;
    int rounds;
    int quick;
    char command[1024];
} options;

/* A growing text buffer for the report. */
typedef struct text {
    char *p;
    size_t n;
    size_t cap;
} text;

/* ------------------------------------------------------------------ small tools */

/* CPU time of this process: time spent descheduled does not count */
static double cpu_seconds(void)
{
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static int cmp_double(const void *a, const void *b)
{
    const double x = *(const double *)a;
    const double y = *(const double *)b;
    return (x > y) - (x < y);
}

/* median of n values; v is sorted in place */
static double median(double *v, int n)
{
    if (n <= 0) return NAN;
    qsort(v, (size_t)n, sizeof v[0], cmp_double);
    if (n % 2 == 1) return v[n / 2];
    return 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* printf onto the report; out of memory ends the program, there is nothing to salvage */
static void put(text *b, const char *fmt, ...)
{
    va_list ap;
    int k;
    for (;;) {
        const size_t room = b->cap - b->n;
        va_start(ap, fmt);
        k = b->p ? vsnprintf(b->p + b->n, room, fmt, ap) : -1;
        va_end(ap);
        if (b->p && k >= 0 && (size_t)k < room) break;
        b->cap = 2 * b->cap + 4096 + (k > 0 ? (size_t)k : 0);
        b->p = (char *)realloc(b->p, b->cap);
        if (!b->p) {
            fputs("peer_side: out of memory\n", stderr);
            exit(1);
        }
    }
    b->n += (size_t)k;
}

/* progress on stderr, so that the report can go to standard output */
static void progress(const char *fmt, ...)
{
    va_list ap;
    fputs("peer_side: ", stderr);
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fputc('\n', stderr);
}

/* ------------------------------------------------------------------ our models */

/* sampled quantities depend on the layout: rigid pieces number their joints differently */
typedef struct sampler {
    history *h;
    int kind;
    int pieces;
} sampler;

static int sample_ours(const rj_model *m, const rj_state *s, void *user)
{
    const sampler *w = (const sampler *)user;
    history *h = w->h;
    const int i = h->n;
    if (i >= MAX_SAMPLES) return 1;
    h->t[i] = rj_state_time(s);
    h->q1[i] = deploy_q1_deg(m, s);
    if (w->kind == KIND_SEGMENTED) {
        h->q2[i] = deploy_segmented_q2_deg(m, s, w->pieces);
        h->defl[i] = deploy_segmented_tip_defl(m, s, w->pieces);
    } else {
        h->q2[i] = deploy_q2_deg(m, s);
        h->defl[i] = scene_tip_defl_tangent(m, s, 1);
    }
    h->n = i + 1;
    return 0;
}

/* rigid pieces joined by bending springs, latched by momentum (bench/segmented.c) */
static rj_result build_segmented(const spec *sp, rj_model **m, rj_error *err)
{
    rj_link_def links[2 * (MAX_PIECES + 1)];
    rj_joint_def joints[2 * (MAX_PIECES + 1)];
    deploy_opts o = deploy_default_opts();
    rj_scene_def sc;
    o.dt = sp->dt;
    o.energy_every = ENERGY_EVERY;
    deploy_segmented_scene(&o, sp->size, links, joints, &sc);
    return rj_model_create(&sc, m, err, NULL);
}

/* flexible links as build/deploy runs them: joint 1 forced, joint 2 adaptive */
static rj_result build_flexible(const spec *sp, rj_model **m, rj_error *err)
{
    deploy_opts o = deploy_default_opts();
    o.elements = sp->size;
    o.dt = sp->dt;
    o.joint2_method = RJ_METHOD_ADAPTIVE;
    o.energy_every = ENERGY_EVERY;
    return deploy_build(&o, m, err);
}

/* inextensible links as `build/deploy --links inextensible` runs them: joint 2 momentum */
static rj_result build_inextensible(const spec *sp, rj_model **m, rj_error *err)
{
    deploy_opts o = deploy_default_opts();
    rj_link_def links[2];
    rj_joint_def joints[2];
    rj_scene_def sc;
    o.elements = sp->size;
    o.dt = sp->dt;
    o.energy_every = ENERGY_EVERY;
    deploy_scene(&o, links, joints, &sc);
    links[0].fidelity = RJ_LINK_INEXTENSIBLE;
    links[1].fidelity = RJ_LINK_INEXTENSIBLE;
    joints[1].method = RJ_METHOD_MOMENTUM;
    return rj_model_create(&sc, m, err, NULL);
}

/* model and state of one of our rows; the message says why not */
static int build_ours(row *r)
{
    rj_error err;
    rj_result res;
    if (r->sp.kind == KIND_SEGMENTED) res = build_segmented(&r->sp, &r->m, &err);
    else if (r->sp.kind == KIND_FLEXIBLE) res = build_flexible(&r->sp, &r->m, &err);
    else res = build_inextensible(&r->sp, &r->m, &err);
    if (res != RJ_OK) {
        snprintf(r->msg, sizeof r->msg, "%.300s", err.msg);
        r->m = NULL;
        return -1;
    }
    if (rj_state_create(r->m, &r->s, NULL) != RJ_OK) {
        snprintf(r->msg, sizeof r->msg, "no memory for the state");
        return -1;
    }
    r->dt = rj_model_dt(r->m);
    r->bound = rj_model_dt_bound(r->m);
    return 0;
}

/* one run of 6 s with 1 ms samples */
static int run_sampled(row *r, history *h)
{
    sampler w;
    rj_result res;
    w.h = h;
    w.kind = r->sp.kind;
    w.pieces = r->sp.size;
    h->n = 0;
    rj_state_reset(r->m, r->s);
    res = rj_run(r->m, r->s, T_END, SAMPLE_DT, sample_ours, &w);
    if (res == RJ_OK) return 0;
    snprintf(r->msg, sizeof r->msg, "%.300s", rj_state_error(r->s));
    return -1;
}

/* CPU seconds of a reset and a 6 s run without samples; -1 when the run fails */
static double time_ours(row *r)
{
    const double t0 = cpu_seconds();
    rj_result res;
    double spent;
    rj_state_reset(r->m, r->s);
    res = rj_run(r->m, r->s, T_END, 0, NULL, NULL);
    spent = cpu_seconds() - t0;
    if (res == RJ_OK) return spent;
    snprintf(r->msg, sizeof r->msg, "%.300s", rj_state_error(r->s));
    return -1;
}

/* ------------------------------------------------------------------ the peer */

/* Runs a shell command and keeps the start of its output (stdout and stderr); returns its
   exit status, or -1 when it could not run or was killed. */
static int run_command(const char *cmd, char *out, size_t cap)
{
    FILE *p = popen(cmd, "r");
    char sink[512];
    size_t n = 0;
    int status;
    out[0] = '\0';
    if (!p) return -1;
    while (n + 1 < cap && fgets(out + n, (int)(cap - n), p)) n += strlen(out + n);
    /* the rest is not kept, but the command must not block on a full pipe */
    while (fgets(sink, sizeof sink, p)) continue;
    status = pclose(p);
    if (status == -1 || !WIFEXITED(status)) return -1;
    return WEXITSTATUS(status);
}

/* "PEER --pieces N --integrator X --dt S TAIL 2>&1", the path quoted for the shell; -1
   when it does not fit */
static int peer_command(char *cmd, size_t cap, const char *peer, const spec *sp, const char *tail)
{
    const char *integrator = sp->rk4 ? "rk4" : "euler";
    const int n = snprintf(cmd, cap, "'%s' --pieces %d --integrator %s --dt %.9g %s 2>&1",
                           peer, sp->size, integrator, sp->dt, tail);
    return n > 0 && (size_t)n < cap ? 0 : -1;
}

/* why a peer run failed: unstable (its exit status 2), or the first line it printed */
static void peer_failure(row *r, int status, const char *out)
{
    const int len = (int)strcspn(out, "\n");
    if (status == 2) snprintf(r->msg, sizeof r->msg, "unstable (the peer's exit status 2)");
    else if (status < 0) snprintf(r->msg, sizeof r->msg, "the peer could not be run");
    else if (len > 0) snprintf(r->msg, sizeof r->msg, "%.*s", len < 300 ? len : 300, out);
    else snprintf(r->msg, sizeof r->msg, "the peer's exit status %d", status);
}

/* CPU seconds of one timed run of the peer's step loop (--repeat 1); -1 on failure */
static double time_peer(row *r, const char *peer)
{
    char cmd[1200];
    char out[MAX_OUTPUT] = "";
    const char *at;
    int status;
    status = peer_command(cmd, sizeof cmd, peer, &r->sp, "--repeat 1");
    if (status == 0) status = run_command(cmd, out, sizeof out);
    at = strstr(out, "cpu_median_s ");
    if (status != 0 || !at) {
        peer_failure(r, status, out);
        return -1;
    }
    return strtod(at + strlen("cpu_median_s "), NULL);
}

/* t,q1_deg,q2_deg,tip2_defl_m rows after a header line */
static int read_csv(const char *path, history *h)
{
    FILE *f = fopen(path, "r");
    char line[256];
    int ok;
    h->n = 0;
    if (!f) return -1;
    ok = fgets(line, sizeof line, f) != NULL;
    while (ok && h->n < MAX_SAMPLES && fgets(line, sizeof line, f)) {
        const int i = h->n;
        ok = sscanf(line, "%lf,%lf,%lf,%lf", &h->t[i], &h->q1[i], &h->q2[i], &h->defl[i]) == 4;
        h->n += ok;
    }
    fclose(f);
    return ok && h->n > 1 ? 0 : -1;
}

/* One sampled run of the peer through a CSV file beside its binary. */
static int run_peer_sampled(row *r, const char *peer, history *h)
{
    char csv[1100];
    char tail[1200];
    char cmd[2500];
    char out[MAX_OUTPUT] = "";
    const char *slash = strrchr(peer, '/');
    const int dir = slash ? (int)(slash - peer + 1) : 0;
    int status;
    snprintf(csv, sizeof csv, "%.*speer_side_%d_%s.csv", dir, peer, r->sp.size,
             r->sp.rk4 ? "rk4" : "euler");
    snprintf(tail, sizeof tail, "--csv '%s'", csv);
    status = peer_command(cmd, sizeof cmd, peer, &r->sp, tail);
    if (status == 0) status = run_command(cmd, out, sizeof out);
    if (status != 0) {
        peer_failure(r, status, out);
        remove(csv);
        return -1;
    }
    status = read_csv(csv, h);
    remove(csv);
    if (status != 0) snprintf(r->msg, sizeof r->msg, "cannot read the peer's %.270s", csv);
    r->dt = r->sp.dt;
    return status;
}

/* ------------------------------------------------------------------ errors */

/* y(at) by linear interpolation, held constant beyond the ends (as numpy.interp); *k is a
   cursor that makes a sweep of increasing times linear */
static double interp(const double *t, const double *y, int n, double at, int *k)
{
    int i = *k;
    if (at <= t[0]) return y[0];
    if (at >= t[n - 1]) return y[n - 1];
    if (t[i] > at) i = 0;
    while (t[i + 1] <= at) i++;
    *k = i;
    return y[i] + (y[i + 1] - y[i]) * (at - t[i]) / (t[i + 1] - t[i]);
}

/* y on the grid t0 + k SAMPLE_DT, k < count */
static void resample(const history *h, const double *y, double t0, int count, double *out)
{
    int cursor = 0;
    int k;
    for (k = 0; k < count; k++) out[k] = interp(h->t, y, h->n, t0 + k * SAMPLE_DT, &cursor);
}

/* max |q - q_ref| before joint 2 locks, at the reference's times; NaN stays NaN */
static double max_diff(const history *run, const double *q, const history *ref,
                       const double *q_ref)
{
    double worst = 0;
    int cursor = 0;
    int i;
    for (i = 0; i < ref->n && ref->t[i] < T_PRE; i++) {
        const double d = fabs(interp(run->t, q, run->n, ref->t[i], &cursor) - q_ref[i]);
        if (!(d <= worst)) worst = d;
    }
    return worst;
}

/* |DFT| of y at bin j of FFT_POINTS, the phasor (zr, zi) turned one sample at a time */
static double dft_magnitude(const double *y, int n, int j)
{
    const double angle = 2 * PI * j / FFT_POINTS;
    const double turn_r = cos(angle);
    const double turn_i = -sin(angle);
    double zr = 1;
    double zi = 0;
    double re = 0;
    double im = 0;
    int k;
    for (k = 0; k < n; k++) {
        const double next_r = zr * turn_r - zi * turn_i;
        re += y[k] * zr;
        im += y[k] * zi;
        zi = zr * turn_i + zi * turn_r;
        zr = next_r;
    }
    return sqrt(re * re + im * im);
}

/* the Hann-windowed signal about its mean (numpy.hanning's window) */
static void hann_about_mean(const double *y, int n, double *out)
{
    double mean = 0;
    int k;
    for (k = 0; k < n; k++) mean += y[k];
    mean /= n;
    for (k = 0; k < n; k++) out[k] = (y[k] - mean) * (0.5 - 0.5 * cos(2 * PI * k / (n - 1)));
}

/* keeps the 1 + MAX_OTHERS largest peaks, largest first (ties: the lower frequency
   first, as a stable sort of the ascending bins); returns how many are kept */
static int keep_peak(double *f, double *mag, int count, double fj, double magj)
{
    int i;
    if (count == 1 + MAX_OTHERS && mag[count - 1] >= magj) return count;
    if (count < 1 + MAX_OTHERS) count++;
    for (i = count - 1; i > 0 && mag[i - 1] < magj; i--) {
        f[i] = f[i - 1];
        mag[i] = mag[i - 1];
    }
    f[i] = fj;
    mag[i] = magj;
    return count;
}

/* The periodogram's local maxima above 5 % of its largest value, from F_LO to F_HI on the
   bins of an FFT zero-padded to FFT_POINTS, largest first; d is the sampling interval.
   Returns how many (at most 1 + MAX_OTHERS) are in f. */
static int spectrum_peaks(const double *yy, int n, double d, double *f)
{
    const double df = 1.0 / (FFT_POINTS * d);
    const int first_bin = (int)ceil(F_LO / df) - 1;
    const int bins = (int)floor(F_HI / df) + 2 - first_bin;
    double *windowed = (double *)malloc(sizeof(double) * (size_t)(n + bins));
    double *mag = windowed + n;
    double kept[1 + MAX_OTHERS];
    double top = 0;
    int count = 0;
    int j;
    if (!windowed) return 0;
    hann_about_mean(yy, n, windowed);
    for (j = 0; j < bins; j++) {
        mag[j] = dft_magnitude(windowed, n, first_bin + j);
        if (mag[j] > top) top = mag[j];
    }
    /* the first and last bins only border the band: they are not peaks themselves */
    for (j = 1; j < bins - 1; j++) {
        const int peak = mag[j] > mag[j - 1] && mag[j] >= mag[j + 1];
        const double fj = (first_bin + j) * df;
        if (peak && mag[j] > 0.05 * top) count = keep_peak(f, kept, count, fj, mag[j]);
    }
    free(windowed);
    return count;
}

/* x -= 2 v (v.x) / (v.v), over rows j .. n-1: one Householder reflection */
static void reflect(const double *v, double *x, int j, int n)
{
    double vx = 0;
    double vv = 0;
    double scale;
    int i;
    for (i = j; i < n; i++) {
        vx += v[i] * x[i];
        vv += v[i] * v[i];
    }
    scale = 2 * vx / vv;
    for (i = j; i < n; i++) x[i] -= scale * v[i];
}

/* The residual sum of squares of the least-squares fit of y by the p columns of a
   (column-major, n rows), by Householder QR: accurate where the normal equations would
   square the condition number. a and y are overwritten. */
static double lsq_residual(double *a, int n, int p, double *y)
{
    double sum = 0;
    int i;
    int j;
    int c;
    for (j = 0; j < p; j++) {
        double *v = a + (size_t)j * n;
        double norm = 0;
        for (i = j; i < n; i++) norm += v[i] * v[i];
        if (norm == 0) continue;
        norm = sqrt(norm);
        v[j] += v[j] >= 0 ? norm : -norm;
        for (c = j + 1; c < p; c++) reflect(v, a + (size_t)c * n, j, n);
        reflect(v, y, j, n);
    }
    for (i = p; i < n; i++) sum += y[i] * y[i];
    return sum;
}

/* The residual of yy against a constant, a ramp about the mean time and a cosine and
   sine pair per frequency. work holds n (4 + 2 nf) doubles. */
static double fit_residual(const double *tt, const double *yy, int n, const double *f, int nf,
                           double *work)
{
    const int columns = 2 + 2 * nf;
    double *a = work;
    double *y = work + (size_t)n * columns;
    double mean = 0;
    int i;
    int j;
    for (i = 0; i < n; i++) mean += tt[i];
    mean /= n;
    for (i = 0; i < n; i++) {
        a[i] = 1;
        a[n + i] = tt[i] - mean;
        y[i] = yy[i];
    }
    for (j = 0; j < nf; j++) {
        double *cosine = a + (size_t)(2 + 2 * j) * n;
        double *sine = cosine + n;
        for (i = 0; i < n; i++) {
            cosine[i] = cos(2 * PI * f[j] * tt[i]);
            sine[i] = sin(2 * PI * f[j] * tt[i]);
        }
    }
    return lsq_residual(a, n, columns, y);
}

/* f[0] refined by golden-section search in [0.9, 1.1] f[0] on the fit's residual, with
   the other peaks f[1 .. nf-1] fitted alongside */
static double refine(const double *tt, const double *yy, int n, double *f, int nf, double *work)
{
    const double g = (sqrt(5.0) - 1) / 2;
    double lo = 0.9 * f[0];
    double hi = 1.1 * f[0];
    int k;
    for (k = 0; k < GOLDEN_STEPS; k++) {
        const double a = hi - g * (hi - lo);
        const double b = lo + g * (hi - lo);
        double ra;
        double rb;
        f[0] = a;
        ra = fit_residual(tt, yy, n, f, nf, work);
        f[0] = b;
        rb = fit_residual(tt, yy, n, f, nf, work);
        if (ra < rb) hi = b;
        else lo = a;
    }
    return 0.5 * (lo + hi);
}

/* The dominant frequency (Hz) of link 2's tip deflection over window w, on the grid
   numpy.arange(t0, t1, 1e-3) gives; NaN when there is no peak. */
static double frequency(const history *h, int w)
{
    const double t0 = WINDOWS[w][0];
    const int n = (int)ceil((WINDOWS[w][1] - t0) / SAMPLE_DT);
    const int most = 2 + 2 * (1 + MAX_OTHERS);
    double *tt = (double *)malloc(sizeof(double) * (size_t)n * (most + 3));
    double *yy = tt + n;
    double f[1 + MAX_OTHERS];
    double found = NAN;
    int count;
    int k;
    if (!tt) return NAN;
    for (k = 0; k < n; k++) tt[k] = t0 + k * SAMPLE_DT;
    resample(h, h->defl, t0, n, yy);
    count = spectrum_peaks(yy, n, tt[1] - tt[0], f);
    if (count > 0) found = refine(tt, yy, n, f, count, yy + n);
    free(tt);
    return found;
}

/* RMS of link 2's tip deflection about its mean over [RMS_T0, RMS_T1], 1 ms grid */
static double tip_rms(const history *h)
{
    const int n = (int)floor((RMS_T1 - RMS_T0) / SAMPLE_DT + 0.5) + 1;
    double *y = (double *)malloc(sizeof(double) * (size_t)n);
    double mean = 0;
    double sum = 0;
    int k;
    if (!y) return NAN;
    resample(h, h->defl, RMS_T0, n, y);
    for (k = 0; k < n; k++) mean += y[k];
    mean /= n;
    for (k = 0; k < n; k++) sum += (y[k] - mean) * (y[k] - mean);
    free(y);
    return sqrt(sum / n);
}

static void measure(const history *h, measures *ms)
{
    ms->freq[0] = frequency(h, 0);
    ms->freq[1] = frequency(h, 1);
    ms->rms = tip_rms(h);
}

/* a run's errors against the reference */
static void compare(const history *run, const reference *ref, errors *e)
{
    measures ms;
    measure(run, &ms);
    e->dq1 = max_diff(run, run->q1, ref->h, ref->h->q1);
    e->dq2 = max_diff(run, run->q2, ref->h, ref->h->q2);
    e->freq[0] = ms.freq[0] / ref->ms.freq[0] - 1;
    e->freq[1] = ms.freq[1] / ref->ms.freq[1] - 1;
    e->rms = ms.rms / ref->ms.rms - 1;
}

/* ------------------------------------------------------------------ names */

/* a step in ms, or in us below 0.1 ms */
static void format_dt(char *b, size_t n, double dt)
{
    if (dt >= 1e-4) snprintf(b, n, "%.4g ms", 1e3 * dt);
    else snprintf(b, n, "%.4g us", 1e6 * dt);
}

/* "MuJoCo, 5 pieces, Euler, dt 1 ms", "revjoint.h, 6 rigid pieces, dt 1 ms (auto: ...)" */
static void row_name(const row *r, char *b, size_t n)
{
    char dt[32];
    char step[96];
    const char *how = r->sp.dt > 0 ? "" : "auto: ";
    format_dt(dt, sizeof dt, r->sp.kind == KIND_PEER ? r->sp.dt : r->dt);
    if (r->sp.kind == KIND_PEER) {
        snprintf(b, n, "MuJoCo, %d pieces, %s, dt %s", r->sp.size,
                 r->sp.rk4 ? "RK4" : "Euler", dt);
        return;
    }
    if (r->m) snprintf(step, sizeof step, "dt %s (%s%.2f x bound)", dt, how, r->dt / r->bound);
    else snprintf(step, sizeof step, "dt %s", r->sp.dt > 0 ? dt : "auto");
    if (r->sp.kind == KIND_SEGMENTED)
        snprintf(b, n, "revjoint.h, %d rigid pieces, %s", r->sp.size, step);
    else if (r->sp.kind == KIND_FLEXIBLE)
        snprintf(b, n, "revjoint.h, flexible, %d elements, joint 2 adaptive, %s", r->sp.size, step);
    else
        snprintf(b, n, "revjoint.h, inextensible, %d elements, joint 2 momentum, %s", r->sp.size,
                 step);
}

/* ------------------------------------------------------------------ runs */

/* The converged reference (flexible, joint 2 adaptive, fine mesh and step): its history,
   lock times and measures, and the CPU time of its sampled run. */
static int run_reference(reference *ref)
{
    row r;
    double t0;
    int failed;
    memset(&r, 0, sizeof r);
    r.sp = ref->sp;
    t0 = cpu_seconds();
    failed = build_ours(&r) != 0 || run_sampled(&r, ref->h) != 0;
    ref->cpu = cpu_seconds() - t0;
    if (failed) {
        fprintf(stderr, "peer_side: reference: %s\n", r.msg);
        return -1;
    }
    ref->lock[0] = rj_joint_event_time(r.m, r.s, 0);
    ref->lock[1] = rj_joint_event_time(r.m, r.s, 1);
    measure(ref->h, &ref->ms);
    rj_state_destroy(r.s, NULL);
    rj_model_destroy(r.m, NULL);
    progress("reference %d elements, dt %g s: %.2f s CPU, %.4f Hz / %.4f Hz, RMS %.6f m",
             ref->sp.size, ref->sp.dt, ref->cpu, ref->ms.freq[0], ref->ms.freq[1], ref->ms.rms);
    return 0;
}

/* the reference's own convergence: half its mesh at twice its step, against it */
static int run_check(reference *ref, history *h)
{
    row r;
    memset(&r, 0, sizeof r);
    r.sp = ref->check_sp;
    if (build_ours(&r) != 0 || run_sampled(&r, h) != 0) {
        fprintf(stderr, "peer_side: convergence check: %s\n", r.msg);
        return -1;
    }
    compare(h, ref, &ref->check);
    rj_state_destroy(r.s, NULL);
    rj_model_destroy(r.m, NULL);
    return 0;
}

/* the row's errors from one sampled run; the peer is asked only when it is there */
static void sample_row(row *r, const reference *ref, const char *peer, history *h)
{
    char name[200];
    if (r->sp.kind == KIND_PEER) r->ok = peer && run_peer_sampled(r, peer, h) == 0;
    else r->ok = build_ours(r) == 0 && run_sampled(r, h) == 0;
    row_name(r, name, sizeof name);
    if (!r->ok) {
        progress("%s: failed: %s", name, peer || r->sp.kind != KIND_PEER ? r->msg : "no peer");
        return;
    }
    compare(h, ref, &r->e);
    progress("%s: dq %.4f / %.4f deg, frequency %+.2f %% / %+.2f %%", name, r->e.dq1, r->e.dq2,
             100 * r->e.freq[0], 100 * r->e.freq[1]);
}

/* Each round runs every setting once, in turn, so that a slow phase of the machine
   reaches all of them alike; a row that fails a timed run is dropped. */
static void time_rounds(row *rows, int n, const char *peer, int rounds)
{
    int k;
    int i;
    for (k = 0; k < rounds; k++) {
        for (i = 0; i < n; i++) {
            row *r = &rows[i];
            double spent;
            if (!r->ok) continue;
            spent = r->sp.kind == KIND_PEER ? time_peer(r, peer) : time_ours(r);
            if (spent < 0) {
                r->ok = 0;
                continue;
            }
            r->cpu[r->timed++] = spent;
        }
        progress("timing round %d of %d done", k + 1, rounds);
    }
    /* median() sorts the times: the least and the most are then at the ends */
    for (i = 0; i < n; i++) rows[i].cpu_median = median(rows[i].cpu, rows[i].timed);
}

/* ------------------------------------------------------------------ report */

/* What is compared, and how. */
static void report_intro(text *b, const options *o)
{
    put(b, "revjoint.h and a MuJoCo peer (`bench/peer_mujoco.c`, run as `%s`) on the two-link "
           "deployment (paper sec. 5), 6 s simulated. The peer cuts each link into N rigid "
           "pieces joined by bending springs (rigid finite elements) and integrates them with "
           "MuJoCo's semi-implicit Euler or RK4 at the largest step found stable for that N "
           "(the notes in `bench/peer_mujoco.c`); its latches are joint equalities switched on "
           "at the lock angles. revjoint.h runs the same rigid-piece layout "
           "(`deploy_segmented_scene` in `examples/scenes.h`: joint coordinates, both latches "
           "by momentum), flexible links (joint 1 forced, joint 2 adaptive, as `build/deploy`) "
           "and inextensible links (joint 2 momentum, as `build/deploy --links "
           "inextensible`); `solver.energy_every = 16` throughout.\n\n", o->peer);
    put(b, "Errors, against the reference below:\n\n"
           "- **dq1, dq2**: max |q - q_ref| (deg) over the reference's 1 ms samples with "
           "t < %.4f s (before joint 2 locks), the run interpolated linearly.\n"
           "- **frequency**: the dominant frequency of link 2's tip deflection (from the "
           "tangent at its root) in %.2f-%.2f s (joint 2 locked, joint 1 not yet) and "
           "%.1f-%.0f s (both locked), relative to the reference's: the largest periodogram "
           "peak refined by least squares with the other peaks fitted alongside, as "
           "`bench/deploy_errors.py`.\n"
           "- **tip RMS**: the same deflection's RMS about its mean over %.1f-%.0f s, "
           "relative.\n\n", T_PRE, WINDOWS[0][0], WINDOWS[0][1], WINDOWS[1][0], WINDOWS[1][1],
        RMS_T0, RMS_T1);
    put(b, "CPU: the median of %d round%s; in each round every setting runs once, in turn, so "
           "that all of them see the same phases of the machine. The peer times its own step "
           "loop (`--repeat 1`: process start and model compilation not counted); revjoint.h "
           "times `rj_state_reset` and `rj_run` without samples. The errors come from one "
           "sampled run of each setting.\n\n", o->rounds, o->rounds == 1 ? "" : "s");
}

/* The reference and how far it is from its own half mesh. */
static void report_reference(text *b, const reference *ref)
{
    char dt[32];
    char check_dt[32];
    format_dt(dt, sizeof dt, ref->sp.dt);
    format_dt(check_dt, sizeof check_dt, ref->check_sp.dt);
    put(b, "Reference: flexible links, %d elements per link, dt %s, joint 1 forced, joint 2 "
           "adaptive (`build/deploy --elements %d --dt %g`), %.1f s CPU with its samples. "
           "Joint 2 locks at %.6f s, joint 1 at %.6f s; link 2's tip vibrates at %.4f Hz "
           "(%.2f-%.2f s) and "
           "%.4f Hz (%.1f-%.0f s), RMS %.5f m.\n\n", ref->sp.size, dt, ref->sp.size,
        ref->sp.dt, ref->cpu, ref->lock[1], ref->lock[0], ref->ms.freq[0], WINDOWS[0][0],
        WINDOWS[0][1], ref->ms.freq[1], WINDOWS[1][0], WINDOWS[1][1], ref->ms.rms);
    put(b, "The reference's own convergence: %d elements at dt %s differ from it by dq1 "
           "%.4f deg, dq2 %.4f deg, frequency %+.3f %% / %+.3f %%, tip RMS %+.3f %%. With "
           "second-order convergence in the element length the reference's own error is "
           "about a third of these, so differences below about %.4f deg in dq2 are not "
           "resolved.\n\n", ref->check_sp.size, check_dt, ref->check.dq1, ref->check.dq2,
        100 * ref->check.freq[0], 100 * ref->check.freq[1], 100 * ref->check.rms,
        ref->check.dq2 / 3);
}

/* "36.6 (35.9-38.2)": the median and the range of a row's CPU times, in ms */
static void format_cpu(char *b, size_t n, const row *r)
{
    const double least = 1e3 * r->cpu[0];
    const double most = 1e3 * r->cpu[r->timed - 1];
    if (r->timed > 1) snprintf(b, n, "%.1f (%.1f-%.1f)", 1e3 * r->cpu_median, least, most);
    else snprintf(b, n, "%.1f", 1e3 * r->cpu_median);
}

/* One line per setting; failed rows keep their message; the peer's rows are left out when
   the peer is missing. */
static void report_table(text *b, const row *rows, int n, int rounds, int peer_missing)
{
    char name[200];
    char cpu[64];
    int i;
    put(b, "| setting | CPU (ms): median of %d (range) | dq1 (deg) | dq2 (deg) | frequency "
           "%.2f-%.2f s | frequency %.1f-%.0f s | tip RMS |\n", rounds, WINDOWS[0][0],
        WINDOWS[0][1], WINDOWS[1][0], WINDOWS[1][1]);
    put(b, "|---|---:|---:|---:|---:|---:|---:|\n");
    for (i = 0; i < n; i++) {
        const row *r = &rows[i];
        if (peer_missing && r->sp.kind == KIND_PEER) continue;
        row_name(r, name, sizeof name);
        if (!r->ok) {
            put(b, "| %s | failed: %s | | | | | |\n", name, r->msg);
            continue;
        }
        format_cpu(cpu, sizeof cpu, r);
        put(b, "| %s | %s | %.4f | %.4f | %+.2f %% | %+.2f %% | %+.2f %% |\n", name, cpu,
            r->e.dq1, r->e.dq2, 100 * r->e.freq[0], 100 * r->e.freq[1], 100 * r->e.rms);
    }
    put(b, "\n");
}

/* Is ours at least as accurate as peer on all five measures, up to what the reference
   resolves (a third of its own convergence check in each)? */
static int as_accurate(const row *ours, const row *peer, const reference *ref)
{
    const double angle = ref->check.dq2 / 3;
    const double freq[2] = { fabs(ref->check.freq[0]) / 3, fabs(ref->check.freq[1]) / 3 };
    const double rms = fabs(ref->check.rms) / 3;
    if (ours->e.dq1 > peer->e.dq1 + angle || ours->e.dq2 > peer->e.dq2 + angle) return 0;
    if (fabs(ours->e.freq[0]) > fabs(peer->e.freq[0]) + freq[0]) return 0;
    if (fabs(ours->e.freq[1]) > fabs(peer->e.freq[1]) + freq[1]) return 0;
    return fabs(ours->e.rms) <= fabs(peer->e.rms) + rms;
}

/* For each of the peer's settings, the cheapest of ours that is at least as accurate on
   every measure, and the ratio of their CPU times. */
static void report_verdict(text *b, const row *rows, int n, const reference *ref)
{
    char name[200], mine[200];
    int i, k;
    put(b, "For each of the peer's settings, the cheapest revjoint.h setting above that is at "
           "least as accurate on all five measures (each within what the reference resolves, "
           "a third of its own convergence check):\n\n");
    put(b, "| the peer | CPU (ms) | revjoint.h | CPU (ms) | time ratio |\n");
    put(b, "|---|---:|---|---:|---:|\n");
    for (i = 0; i < n; i++) {
        const row *peer = &rows[i];
        const row *best = NULL;
        if (peer->sp.kind != KIND_PEER || !peer->ok) continue;
        for (k = 0; k < n; k++) {
            const row *r = &rows[k];
            if (r->sp.kind == KIND_PEER || !r->ok || !as_accurate(r, peer, ref)) continue;
            if (!best || r->cpu_median < best->cpu_median) best = r;
        }
        row_name(peer, name, sizeof name);
        if (!best) {
            put(b, "| %s | %.1f | none | | |\n", name, 1e3 * peer->cpu_median);
            continue;
        }
        row_name(best, mine, sizeof mine);
        put(b, "| %s | %.1f | %s | %.1f | %.2f |\n", name, 1e3 * peer->cpu_median, mine,
            1e3 * best->cpu_median, peer->cpu_median / best->cpu_median);
    }
    put(b, "\n");
}

/* the plots, the command and, when it was missing, why the peer has no rows */
static void report_tail(text *b, const options *o, const char *freq_plot, const char *missing)
{
    if (missing[0])
        put(b, "The peer was not available (%s): the table has revjoint.h's rows alone.\n\n",
            missing);
    if (o->plot)
        put(b, "![CPU time against angle error](%s)\n\n"
               "![CPU time against frequency error](%s)\n\n", o->plot, freq_plot);
    put(b, "Command: `%s`%s\n", o->command,
        o->quick ? " (a `--quick` run: one round and a coarse reference, a smoke test)" : "");
}

/* ------------------------------------------------------------------ plots */

/* 10^floor(log10(v)) and 10^ceil(log10(v)): whole decades around the data */
static double decade_below(double v)
{
    return pow(10.0, floor(log10(v)));
}

static double decade_above(double v)
{
    return pow(10.0, ceil(log10(v)));
}

/* which 0: max(dq1, dq2) in deg; 1: |frequency error| after both locks, in % */
static double plot_error(const row *r, int which)
{
    if (which == 0) return r->e.dq1 > r->e.dq2 ? r->e.dq1 : r->e.dq2;
    return 100 * fabs(r->e.freq[1]);
}

/* One series of points (no line: the settings are not a sequence). */
static void add_points(rjr_plot_def *p, const double *x, const double *y, int n,
                       const char *label, rjr_rgb colour)
{
    rjr_series *s = &p->series[p->series_count++];
    s->x = x;
    s->y = y;
    s->n = n;
    s->label = label;
    s->colour = colour;
    s->points = 1;
    s->no_line = 1;
    s->width_px = 3;
}

/* whole decades around the plotted points, and a decade of room above for the legend */
static void plot_ranges(rjr_plot_def *p, const double *x, const double *y, int n)
{
    double xmin = HUGE_VAL;
    double xmax = 0;
    double ymin = HUGE_VAL;
    double ymax = 0;
    int i;
    for (i = 0; i < n; i++) {
        if (!(x[i] > 0 && y[i] > 0 && isfinite(x[i]) && isfinite(y[i]))) continue;
        xmin = fmin(xmin, x[i]);
        xmax = fmax(xmax, x[i]);
        ymin = fmin(ymin, y[i]);
        ymax = fmax(ymax, y[i]);
    }
    if (!(xmax > 0)) return;
    p->xmin = decade_below(xmin);
    p->xmax = decade_above(1.2 * xmax);
    p->ymin = decade_below(ymin);
    p->ymax = 10 * decade_above(1.5 * ymax);
}

/* CPU time against one error, the peer's settings and ours as two series */
static int plot_one(rjr_context *ctx, const char *path, const row *rows, int n, int which,
                    char *err, size_t errlen)
{
    double x[NSPECS];
    double y[NSPECS];
    rjr_plot_def p = rjr_plot_default();
    int npeer = 0;
    int total = 0;
    int pass;
    int i;
    /* the peer's points first, then ours, so that each series is one stretch of x and y */
    for (pass = 0; pass < 2; pass++) {
        for (i = 0; i < n && total < NSPECS; i++) {
            const int ours = rows[i].sp.kind != KIND_PEER;
            if (!rows[i].ok || ours != pass) continue;
            x[total] = 1e3 * rows[i].cpu_median;
            y[total] = plot_error(&rows[i], which);
            total++;
        }
        if (pass == 0) npeer = total;
    }
    if (npeer > 0) add_points(&p, x, y, npeer, "MuJoCo peer (rigid pieces)", 0xd62728);
    add_points(&p, x + npeer, y + npeer, total - npeer, "revjoint.h", 0x1f77b4);
    plot_ranges(&p, x, y, total);
    p.title = which ? "Deployment: link 2 tip frequency after both locks"
                    : "Deployment: joint angles before joint 2 locks";
    p.xlabel = "CPU time of 6 s simulated (ms, median)";
    p.ylabel = which ? "abs(f / f_ref - 1) (%)" : "max abs(q - q_ref) (deg)";
    p.logx = 1;
    p.logy = 1;
    p.legend = RJR_LEGEND_TOP_RIGHT;
    if (rjr_plot(ctx, &p) == 0 && rjr_save_png(ctx, path, err, errlen) == 0) return 0;
    if (!err[0]) snprintf(err, errlen, "%s", rjr_error(ctx));
    return -1;
}

/* FILE.png -> FILE_freq.png (the suffix after the last dot of the name is replaced) */
static void freq_plot_path(const char *plot, char *b, size_t n)
{
    const char *dot = strrchr(plot, '.');
    const char *slash = strrchr(plot, '/');
    const int stem = dot && (!slash || dot > slash) ? (int)(dot - plot) : (int)strlen(plot);
    snprintf(b, n, "%.*s_freq.png", stem, plot);
}

/* both plots; 0, or -1 with the reason printed */
static int plots(const char *plot, const char *freq_plot, const row *rows, int n)
{
    char err[256] = "";
    rjr_context *ctx = rjr_create(900, 560, err, sizeof err);
    int failed;
    if (!ctx) {
        fprintf(stderr, "peer_side: no plots: %s\n", err);
        return -1;
    }
    failed = cli_mkparent("peer_side", plot) != 0;
    failed = failed || plot_one(ctx, plot, rows, n, 0, err, sizeof err) != 0;
    failed = failed || plot_one(ctx, freq_plot, rows, n, 1, err, sizeof err) != 0;
    if (failed && err[0]) fprintf(stderr, "peer_side: plot: %s\n", err);
    rjr_destroy(ctx);
    return failed ? -1 : 0;
}

/* ------------------------------------------------------------------ main */

/* the options, and the command line for the report */
static void parse_options(int argc, char **argv, options *o)
{
    cli c;
    const char *a;
    int rounds_given = 0;
    int i;
    o->peer = "build/peer_mujoco";
    o->out = NULL;
    o->plot = NULL;
    o->rounds = 5;
    o->quick = 0;
    c.argc = argc;
    c.argv = argv;
    c.i = 0;
    c.usage = usage;
    while ((a = cli_next(&c)) != NULL) {
        if (!strcmp(a, "--peer")) o->peer = cli_str(&c, a);
        else if (!strcmp(a, "--out")) o->out = cli_str(&c, a);
        else if (!strcmp(a, "--plot")) o->plot = cli_str(&c, a);
        else if (!strcmp(a, "--rounds")) {
            o->rounds = cli_int(&c, a, 1, MAX_ROUNDS);
            rounds_given = 1;
        } else if (!strcmp(a, "--quick")) o->quick = 1;
        else if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            fputs(usage, stdout);
            exit(0);
        } else cli_die(&c, "unknown option '%s'%s", a, "");
    }
    /* the peer's path goes into a shell command between single quotes */
    if (strchr(o->peer, '\''))
        cli_die(&c, "option --peer: a path without quotes ('), please: %s%s", o->peer, "");
    if (o->quick && !rounds_given) o->rounds = 1;
    o->command[0] = '\0';
    for (i = 0; i < argc; i++) {
        const size_t used = strlen(o->command);
        snprintf(o->command + used, sizeof o->command - used, "%s%s", i ? " " : "", argv[i]);
    }
}

/* The reference as `build/deploy --elements 80 --dt 6.482e-7` runs it; --quick: 40
   elements at 1.3 us. Its check is half the mesh at twice the step. */
static void setup_reference(reference *ref, int quick, history *h)
{
    memset(ref, 0, sizeof *ref);
    ref->h = h;
    ref->sp.kind = KIND_FLEXIBLE;
    ref->sp.size = quick ? 40 : 80;
    ref->sp.dt = quick ? 1.3e-6 : 6.482e-7;
    ref->check_sp = ref->sp;
    ref->check_sp.size = quick ? 20 : 40;
    ref->check_sp.dt = quick ? 2.6e-6 : 1.3e-6;
}

/* NULL when the peer cannot be run, with the reason in missing */
static const char *peer_check(const char *peer, char *missing, size_t n)
{
    if (access(peer, X_OK) == 0) return peer;
    snprintf(missing, n, "%s: %s", peer, strerror(errno));
    return NULL;
}

/* Every row's sampled run; a peer whose every run fails counts as missing. Returns the
   peer to time, or NULL. */
static const char *sample_rows(row *rows, const reference *ref, const char *peer,
                               history *h, char *missing, size_t n)
{
    int peer_ok = 0;
    int first_peer = -1;
    int i;
    for (i = 0; i < NSPECS; i++) {
        memset(&rows[i], 0, sizeof rows[i]);
        rows[i].sp = SPECS[i];
        sample_row(&rows[i], ref, peer, h);
        if (rows[i].sp.kind != KIND_PEER) continue;
        peer_ok += rows[i].ok;
        if (first_peer < 0) first_peer = i;
    }
    if (!peer || peer_ok > 0) return peer;
    snprintf(missing, n, "%s: every run failed, the first with: %s", peer,
             rows[first_peer].msg);
    return NULL;
}

/* the whole section into FILE.md or standard output; 0 when written */
static int write_report(const options *o, const reference *ref, const row *rows,
                        const char *missing, const char *freq_plot)
{
    text b;
    cli_out out;
    memset(&b, 0, sizeof b);
    report_intro(&b, o);
    report_reference(&b, ref);
    report_table(&b, rows, NSPECS, o->rounds, missing[0] != '\0');
    if (!missing[0]) report_verdict(&b, rows, NSPECS, ref);
    report_tail(&b, o, freq_plot, missing);
    if (o->out && cli_mkparent("peer_side", o->out) != 0) return -1;
    if (cli_open(&out, "peer_side", o->out) != 0) return -1;
    cli_put(&out, fputs(b.p, out.f));
    free(b.p);
    return cli_close(&out, "peer_side") ? -1 : 0;
}

static void free_rows(row *rows)
{
    int i;
    for (i = 0; i < NSPECS; i++) {
        if (rows[i].s) rj_state_destroy(rows[i].s, NULL);
        if (rows[i].m) rj_model_destroy(rows[i].m, NULL);
    }
}

int main(int argc, char **argv)
{
    options o;
    reference ref;
    row rows[NSPECS];
    char missing[400] = "";
    char freq_plot[1100] = "";
    history *h = (history *)malloc(sizeof *h);
    history *ref_h = (history *)malloc(sizeof *ref_h);
    const char *peer;
    int failed;
    parse_options(argc, argv, &o);
    if (!h || !ref_h) {
        fputs("peer_side: out of memory\n", stderr);
        return 1;
    }
    setup_reference(&ref, o.quick, ref_h);
    if (run_reference(&ref) != 0 || run_check(&ref, h) != 0) return 1;
    peer = peer_check(o.peer, missing, sizeof missing);
    peer = sample_rows(rows, &ref, peer, h, missing, sizeof missing);
    if (missing[0]) progress("the peer is not available (%s)", missing);
    time_rounds(rows, NSPECS, peer, o.rounds);
    if (o.plot) freq_plot_path(o.plot, freq_plot, sizeof freq_plot);
    failed = write_report(&o, &ref, rows, missing, freq_plot) != 0;
    if (o.plot) failed |= plots(o.plot, freq_plot, rows, NSPECS) != 0;
    free_rows(rows);
    free(h);
    free(ref_h);
    return failed;
}
