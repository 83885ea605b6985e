/* bench.c - speed against error for revjoint.h (issue 5): throughput of the step, and
   work-precision sweeps of the paper's two benchmarks (SPEC 9.2 deployment, SPEC 9.1
   impact) against converged references. Writes a markdown report (every number in it comes
   from this run) and PNG plots. bench/README.md says what is measured and how.

   build/bench [--out FILE.md] [--plot FILE.png] [--quick]

   Wall times are clock_gettime(CLOCK_MONOTONIC) around rj_step / rj_run only (model and
   state creation, resets and reference bookkeeping are outside the timed region). */
#define _POSIX_C_SOURCE 199309L
#define REVJOINT_IMPLEMENTATION
#include "../revjoint.h"
#include "../examples/scenes.h"
#include "../examples/rigid2.h"
#include "../render/rj_render.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <math.h>
#include <time.h>
#include <stdarg.h>

#ifndef BENCH_CFLAGS /* what `make bench` passes; -DBENCH_CFLAGS='"..."' overrides */
#define BENCH_CFLAGS "-std=c99 -O2 -Wall -Wextra -pedantic -Werror -ffp-contract=off"
#endif

static const char usage[] =
    "usage: bench [--out FILE.md] [--plot FILE.png] [--quick]\n"
    "  --out FILE.md    markdown report (default BENCHMARKS.md)\n"
    "  --plot FILE.png  work-precision plot of the deployment, q before joint 2 locks; a second\n"
    "                   plot (tip amplitude) goes to FILE_tip.png (default docs/work_precision.png)\n"
    "  --quick          a short smoke-test version (< 30 s); its numbers are not converged\n";

/* ------------------------------------------------------------------ settings */
typedef struct settings {
    int quick;
    /* throughput */
    int tp_runs;
    double tp_min_time;        /* s, each timed run at least this long */
    int paper_runs;            /* deployment at the paper's settings */
    /* deployment sweep */
    int d_el[4], d_nel;
    int d_ndt[4];              /* dt values per element count: top, top/2, top/4, ... */
    int d_ref_el;              /* reference: adaptive, d_ref_el elements, top / d_ref_div */
    double d_ref_div;
    double d_tend;
    /* impact sweep */
    int i_el[4], i_nel;
    int i_ndt;
    int i_ref_el;
    double i_ref_div;
    double i_tend;
    double budget;             /* s: above it, runs longer than 2 s are timed once */
} settings;

static settings S;
static double T_START;

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* how many timed runs for a run whose first timing was t1 seconds: >= 5 below 2 s */
static int runs_for(double t1)
{
    if (S.quick) return t1 < 0.05 ? 3 : 1;
    if (t1 < 0.01) return 21;              /* very short runs: more samples of the timer */
    if (t1 < 2.0) return 5;
    if (now() - T_START > S.budget) return 1;
    return t1 < 6.0 ? 3 : 1;
}

/* CPU time of this process: unlike the wall time it does not count time spent descheduled
   when other processes load the machine; both are reported */
static double cpu_now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static void loadavg(char *b, size_t n)
{
    FILE *f = fopen("/proc/loadavg", "r");
    double a = 0, c = 0, d = 0;
    snprintf(b, n, "unknown");
    if (!f) return;
    if (fscanf(f, "%lf %lf %lf", &a, &c, &d) == 3) snprintf(b, n, "%.2f %.2f %.2f", a, c, d);
    fclose(f);
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : (x > y ? 1 : 0);
}
static double median(const double *v, int n)
{
    double w[32];
    int i;
    if (n <= 0) return NAN;
    if (n > 32) n = 32;
    for (i = 0; i < n; i++) w[i] = v[i];
    qsort(w, (size_t)n, sizeof(double), cmp_double);
    return n % 2 ? w[n / 2] : 0.5 * (w[n / 2 - 1] + w[n / 2]);
}

/* ------------------------------------------------------------------ report buffer */
typedef struct sbuf { char *p; size_t n, cap; } sbuf;
static sbuf R;          /* report body */
static void md(const char *fmt, ...)
{
    va_list ap;
    int k;
    for (;;) {
        size_t room = R.cap - R.n;
        va_start(ap, fmt);
        k = R.p ? vsnprintf(R.p + R.n, room, fmt, ap) : -1;
        va_end(ap);
        if (R.p && k >= 0 && (size_t)k < room) { R.n += (size_t)k; return; }
        R.cap = R.cap ? 2 * R.cap + (k > 0 ? (size_t)k : 0) : 65536;
        R.p = (char *)realloc(R.p, R.cap);
        if (!R.p) { fputs("bench: out of memory\n", stderr); exit(1); }
    }
}
static void progress(const char *fmt, ...)
{
    va_list ap;
    fprintf(stderr, "[%6.1f s] ", now() - T_START);
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fputc('\n', stderr);
}

/* notes for the "what to look at" section: anything that does not behave as expected */
static char NOTES[32][800];
static int NNOTES;
static void note(const char *fmt, ...)
{
    va_list ap;
    if (NNOTES >= 32) return;
    va_start(ap, fmt);
    vsnprintf(NOTES[NNOTES++], sizeof NOTES[0], fmt, ap);
    va_end(ap);
}

static const char *method_name(int m)
{
    static const char *const n[] = { "penalty", "adaptive", "momentum", "forced", "energy" };
    return m >= 0 && m < 5 ? n[m] : "?";
}

/* Tip deflection of link l from the tangent at its root (node 0's rotation), the quantity
   a strain gauge at the root would see. scene_tip_defl measures it from the chord of the
   first element instead, which differs by about L kappa_root l / 2: first order in the
   element length l. Both are reported. */
static double tip_defl_tangent(const rj_model *m, const rj_state *s, int l)
{
    double p0[2], pt[2], ph = rj_node_rotation(m, s, l, 0);
    rj_node_position(m, s, l, 0, p0);
    rj_node_position(m, s, l, rj_link_node_count(m, l) - 1, pt);
    return cos(ph) * (pt[1] - p0[1]) - sin(ph) * (pt[0] - p0[0]);
}

/* ================================================================== 1. throughput */
typedef struct tp_row {
    int elements, runs; long steps;
    double dt, ns_med, ns_min, ns_max, ns_cpu, model_per_node, state_per_node, edrift;
    int nodes;
} tp_row;

static int free_link(int elements, tp_row *o)
{
    rj_link_def L = rj_default_link_def();
    rj_scene_def sc = rj_default_scene_def();
    rj_model *m; rj_state *s; rj_error err; rj_energy e0, e1;
    double t, c, ns[32], nc[32];
    long steps = 16, k;
    int r;
    L.height = 0.01; L.elements = elements; L.omega = 1.0;
    sc.links = &L; sc.link_count = 1; sc.joints = NULL; sc.joint_count = 0;
    memset(o, 0, sizeof *o);
    o->elements = elements;
    if (rj_model_create(&sc, &m, &err, NULL) != RJ_OK) { fprintf(stderr, "bench: free link: %s\n", err.msg); return -1; }
    if (rj_state_create(m, &s, NULL) != RJ_OK) { rj_model_destroy(m, NULL); return -1; }
    o->nodes = rj_model_node_count(m);
    o->model_per_node = (double)rj_model_size(&sc, NULL) / o->nodes;
    o->state_per_node = (double)rj_state_size(m) / o->nodes;
    o->dt = rj_model_dt(m);
    /* calibrate: the step count that takes at least tp_min_time */
    for (;;) {
        rj_state_reset(m, s);
        t = now();
        for (k = 0; k < steps; k++) if (rj_step(m, s) != RJ_OK) break;
        t = now() - t;
        if (k < steps) { fprintf(stderr, "bench: free link %d: %s\n", elements, rj_state_error(s)); return -1; }
        if (t >= S.tp_min_time) break;
        steps = (long)((double)steps * (t > 0 ? fmin(16.0, 1.25 * S.tp_min_time / t) : 16.0)) + 1;
    }
    for (r = 0; r < S.tp_runs; r++) {
        rj_state_reset(m, s);
        rj_step(m, s);
        rj_state_energy(m, s, &e0);
        rj_state_reset(m, s);
        t = now(); c = cpu_now();
        for (k = 0; k < steps; k++) if (rj_step(m, s) != RJ_OK) break;
        t = now() - t; c = cpu_now() - c;
        if (k < steps) { fprintf(stderr, "bench: free link %d: %s\n", elements, rj_state_error(s)); return -1; }
        ns[r] = 1e9 * t / ((double)steps * elements);
        nc[r] = 1e9 * c / ((double)steps * elements);
    }
    rj_state_energy(m, s, &e1);
    o->edrift = (e1.total - e0.total) / e0.total;
    o->runs = S.tp_runs; o->steps = steps;
    o->ns_med = median(ns, S.tp_runs);
    o->ns_cpu = median(nc, S.tp_runs);
    o->ns_min = o->ns_max = ns[0];
    for (r = 1; r < S.tp_runs; r++) { o->ns_min = fmin(o->ns_min, ns[r]); o->ns_max = fmax(o->ns_max, ns[r]); }
    rj_state_destroy(s, NULL); rj_model_destroy(m, NULL);
    return 0;
}

/* ================================================================== 2. deployment */
#define D_NS 6101                          /* 1 ms samples, t = 0 .. 6.1 s */
typedef struct dhist {
    int n;
    double q1[D_NS], q2[D_NS];             /* deg, moved to exactly k ms with the joint rates */
    double dc[D_NS], dtg[D_NS];            /* link 2 tip deflection, m: chord (scene_tip_defl), tangent */
    unsigned char have[D_NS];
} dhist;

static int d_sample(const rj_model *m, const rj_state *s, void *u)
{
    dhist *h = (dhist *)u;
    double t = rj_state_time(s), dtk;
    int k = (int)floor(t * 1000.0 + 0.5);
    if (k < 0 || k >= D_NS) return 0;
    dtk = 1e-3 * k - t;                    /* |dtk| <= dt / 2 */
    h->q1[k] = deploy_q1_deg(m, s) + rj_deg(rj_joint_rate(m, s, 0)) * dtk;
    h->q2[k] = deploy_q2_deg(m, s) + rj_deg(rj_joint_rate(m, s, 1)) * dtk;
    h->dc[k] = scene_tip_defl(m, s, 1);
    h->dtg[k] = tip_defl_tangent(m, s, 1);
    h->have[k] = 1;
    if (k + 1 > h->n) h->n = k + 1;
    return 0;
}

/* post-lock vibration of link 2's tip over [3.2 s, t_end] */
typedef struct dmet {
    double lock1, lock2;                   /* s, joint 1 / joint 2 lock (event) times */
    double rms_c, rms_t, peak_c, peak_t;   /* m */
    double freq_c, freq_t;                 /* Hz, zero crossings of the deflection minus its mean */
} dmet;
typedef struct derr {
    double dq;                             /* deg, max |q1 - q1ref|, |q2 - q2ref| for t < t_pre */
    double dlock, dlock1;                  /* s, lock2 - lock2ref, lock1 - lock1ref */
    double rms_c, rms_t, freq_c, freq_t;   /* relative (signed) */
} derr;

static double D_TPRE;                      /* rigid lock time of joint 2 - 10 ms */
static double D_RIGID_LOCK[2];

static void vib_stats(const dhist *h, const double *d, int k0, int k1, double *rms, double *peak, double *freq)
{
    double sum = 0, sum2 = 0, mean, pk = 0, tfirst = -1, tlast = -1, prev = 0;
    int k, n = 0, nc = 0, haveprev = 0;
    for (k = k0; k <= k1 && k < h->n; k++) if (h->have[k]) { sum += d[k]; sum2 += d[k] * d[k]; n++; if (fabs(d[k]) > pk) pk = fabs(d[k]); }
    if (n < 2) { *rms = *peak = *freq = NAN; return; }
    mean = sum / n;
    *rms = sqrt(sum2 / n);
    *peak = pk;
    for (k = k0; k <= k1 && k < h->n; k++) {
        double v;
        if (!h->have[k]) continue;
        v = d[k] - mean;
        if (haveprev && ((prev < 0 && v >= 0) || (prev >= 0 && v < 0))) {
            double tc = 1e-3 * (k - 1) + 1e-3 * prev / (prev - v);
            if (tfirst < 0) tfirst = tc;
            tlast = tc;
            nc++;
        }
        prev = v; haveprev = 1;
    }
    *freq = nc >= 3 ? (nc - 1) / (2.0 * (tlast - tfirst)) : NAN;
}

static void d_metrics(const dhist *h, double lock1, double lock2, dmet *o)
{
    int k0 = 3200, k1 = (int)floor(S.d_tend * 1000 + 0.5);
    o->lock1 = lock1; o->lock2 = lock2;
    vib_stats(h, h->dc, k0, k1, &o->rms_c, &o->peak_c, &o->freq_c);
    vib_stats(h, h->dtg, k0, k1, &o->rms_t, &o->peak_t, &o->freq_t);
}

static void d_errors(const dhist *h, const dmet *m, const dhist *rh, const dmet *rm, derr *e)
{
    int k;
    e->dq = 0;
    for (k = 0; k < h->n && k < rh->n && 1e-3 * k < D_TPRE; k++) {
        if (!h->have[k] || !rh->have[k]) continue;
        e->dq = fmax(e->dq, fmax(fabs(h->q1[k] - rh->q1[k]), fabs(h->q2[k] - rh->q2[k])));
    }
    e->dlock = m->lock2 - rm->lock2;
    e->dlock1 = m->lock1 - rm->lock1;
    e->rms_c = m->rms_c / rm->rms_c - 1; e->rms_t = m->rms_t / rm->rms_t - 1;
    e->freq_c = m->freq_c / rm->freq_c - 1; e->freq_t = m->freq_t / rm->freq_t - 1;
}

typedef struct drow {
    int method, el, paper, ok, runs;
    double dt, bound, K, wall, cpu;
    long steps;
    char msg[600];
    dmet m;
    derr e;
} drow;

/* 0.9 x the stability bound for this method and mesh: the largest step of the form the
   library picks itself (solver.dt = 0) that deploy_build accepts with joint 2's stiffness
   computed at that step (Eq 31 for penalty, Eq 21 for adaptive) */
static double d_top_dt(int method, int el)
{
    deploy_opts o = deploy_default_opts();
    rj_model *m; rj_error err; rj_result r;
    double dt;
    int i;
    o.elements = el; o.joint2_method = method; o.dt = 0;
    if (deploy_build(&o, &m, &err) != RJ_OK) { fprintf(stderr, "bench: deploy %d el: %s\n", el, err.msg); return -1; }
    dt = rj_model_dt(m);
    rj_model_destroy(m, NULL);
    for (i = 0; i < 60; i++) {
        o.dt = dt;
        r = deploy_build(&o, &m, &err);
        if (r == RJ_OK) { rj_model_destroy(m, NULL); return dt; }
        if (r != RJ_ERR_UNSTABLE_DT) break;
        dt *= 0.97;
    }
    fprintf(stderr, "bench: deploy %d el: no stable dt: %s\n", el, err.msg);
    return -1;
}

/* One deployment configuration: metrics from the first run, wall time the median of
   runs_for() runs. ref == NULL: no errors. */
static void d_run(drow *row, dhist *h, const dhist *rh, const dmet *rm, int force_runs)
{
    deploy_opts o = deploy_default_opts();
    rj_model *m; rj_state *s; rj_error err; rj_result r;
    double w[32], cw[32];
    int k, nr = 1;
    o.elements = row->el; o.dt = row->dt; o.joint2_method = row->method;
    row->ok = 0; row->runs = 0; row->msg[0] = 0;
    if (deploy_build(&o, &m, &err) != RJ_OK) { snprintf(row->msg, sizeof row->msg, "%s", err.msg); return; }
    if (rj_state_create(m, &s, NULL) != RJ_OK) { rj_model_destroy(m, NULL); snprintf(row->msg, sizeof row->msg, "no memory"); return; }
    row->bound = rj_model_dt_bound(m);
    row->K = rj_joint_stiffness(m, 1);
    for (k = 0; k < nr && k < 32; k++) {
        double t0, c0;
        rj_state_reset(m, s);
        memset(h, 0, sizeof *h);
        t0 = now(); c0 = cpu_now();
        r = rj_run(m, s, S.d_tend, 1e-3, d_sample, h);
        w[k] = now() - t0; cw[k] = cpu_now() - c0;
        if (r != RJ_OK) { snprintf(row->msg, sizeof row->msg, "%s: %s", rj_result_str(r), rj_state_error(s)); break; }
        if (k == 0) {
            row->steps = rj_state_steps(s);
            d_metrics(h, rj_joint_event_time(m, s, 0), rj_joint_event_time(m, s, 1), &row->m);
            if (rh) d_errors(h, &row->m, rh, rm, &row->e);
            nr = force_runs > 0 ? force_runs : runs_for(w[0]);
        } else if (rj_joint_event_time(m, s, 1) != row->m.lock2) {
            note("deployment %s %d el dt %.4g: a repeated run gave a different lock time (%.9f vs %.9f s): not deterministic",
                 method_name(row->method), row->el, row->dt, rj_joint_event_time(m, s, 1), row->m.lock2);
        }
    }
    if (k == nr) { row->ok = 1; row->runs = nr; row->wall = median(w, nr); row->cpu = median(cw, nr); }
    rj_state_destroy(s, NULL); rj_model_destroy(m, NULL);
}

static void r2_cb(const rigid2_sample *smp, void *u) { (void)smp; (void)u; }

/* ================================================================== 3. impact */
typedef struct irow {
    int method, el, ok, runs, contacts;
    long flips;                                   /* flag changes: RC13 chatter */
    double dt, bound, K, wall, cpu;
    long steps;
    double contact, release_last, release_first;  /* s */
    double peak_c, peak_t;                        /* m, max |tip deflection| of link 1, chord / tangent */
    double e_first, e_last, e_peak_c, e_peak_t;   /* s, s, relative, relative */
    char msg[600];
} irow;

typedef struct iacc { int prev; double t_free; double first; int contacts; long flips; double peak_c, peak_t; } iacc;

/* every step: peak deflection, and the first release that lasts (a free interval of at
   least 0.1 ms: RC13 chatter and adaptive contact toggle the flag step by step) */
static int i_sample(const rj_model *m, const rj_state *s, void *u)
{
    iacc *a = (iacc *)u;
    double t = rj_state_time(s), dc = fabs(scene_tip_defl(m, s, 1)), dg = fabs(tip_defl_tangent(m, s, 1));
    int f = rj_joint_flag(m, s, 0);
    if (dc > a->peak_c) a->peak_c = dc;
    if (dg > a->peak_t) a->peak_t = dg;
    if (f != a->prev) a->flips++;
    if (f != RJ_FREE && a->prev == RJ_FREE) { if (a->t_free < 0 || t - a->t_free >= 1e-4 || a->contacts == 0) a->contacts++; a->t_free = -1; }
    if (f == RJ_FREE && a->prev != RJ_FREE) a->t_free = t - rj_model_dt(m); /* the flag of step n -> n+1 is decided at t_n (as rj_joint_release_time) */
    if (f == RJ_FREE && a->t_free >= 0 && a->first < 0 && t - a->t_free >= 1e-4) a->first = a->t_free;
    a->prev = f;
    return 0;
}

static double i_top_dt(int method, int el)
{
    impact_opts o = impact_default_opts();
    rj_link_def L[2]; rj_joint_def J; rj_scene_def sc; rj_model *m; rj_error err;
    double dt;
    o.method = method; o.elements = el; o.dt = 0;
    impact_scene(&o, L, &J, &sc);
    if (rj_model_create(&sc, &m, &err, NULL) != RJ_OK) { fprintf(stderr, "bench: impact %d el: %s\n", el, err.msg); return -1; }
    dt = rj_model_dt(m);
    rj_model_destroy(m, NULL);
    return dt;
}

static void i_run(irow *row, int force_runs)
{
    impact_opts o = impact_default_opts();
    rj_link_def L[2]; rj_joint_def J; rj_scene_def sc; rj_model *m; rj_state *s; rj_error err; rj_result r;
    iacc a;
    double w[32], cw[32];
    int k, nr = 1;
    o.method = row->method; o.elements = row->el; o.dt = row->dt;
    impact_scene(&o, L, &J, &sc);
    row->ok = 0; row->msg[0] = 0;
    if (rj_model_create(&sc, &m, &err, NULL) != RJ_OK) { snprintf(row->msg, sizeof row->msg, "%s", err.msg); return; }
    rj_state_create(m, &s, NULL);
    row->bound = rj_model_dt_bound(m); row->K = rj_joint_stiffness(m, 0);
    for (k = 0; k < nr && k < 32; k++) {
        double t0, c0;
        rj_state_reset(m, s);
        memset(&a, 0, sizeof a); a.first = -1; a.t_free = -1; a.prev = RJ_FREE;
        t0 = now(); c0 = cpu_now();
        r = rj_run(m, s, S.i_tend, 0, i_sample, &a);
        w[k] = now() - t0; cw[k] = cpu_now() - c0;
        if (r != RJ_OK) { snprintf(row->msg, sizeof row->msg, "%s: %s", rj_result_str(r), rj_state_error(s)); break; }
        if (k == 0) {
            row->steps = rj_state_steps(s);
            row->contact = rj_joint_event_time(m, s, 0);
            row->release_last = rj_joint_release_time(m, s, 0);
            row->release_first = a.first;
            row->contacts = a.contacts;
            row->flips = a.flips;
            row->peak_c = a.peak_c; row->peak_t = a.peak_t;
            nr = force_runs > 0 ? force_runs : runs_for(w[0]);
        }
    }
    if (k == nr) { row->ok = 1; row->runs = nr; row->wall = median(w, nr); row->cpu = median(cw, nr); }
    rj_state_destroy(s, NULL); rj_model_destroy(m, NULL);
}

static void i_errors(irow *r, const irow *ref)
{
    r->e_first = r->release_first - ref->release_first;
    r->e_last = r->release_last - ref->release_last;
    r->e_peak_c = r->peak_c / ref->peak_c - 1;
    r->e_peak_t = r->peak_t / ref->peak_t - 1;
}

/* least wall time among a method's rows with dq < 0.1 deg and (crit 0) |RMS tangent| < 2 %,
   (crit 1) |RMS chord| < 2 %, (crit 2) no amplitude condition */
static const drow *d_cheapest(const drow *rows, int n, int method, int crit)
{
    const drow *b = NULL;
    int i;
    for (i = 0; i < n; i++) {
        const drow *r = &rows[i];
        double rr = crit == 0 ? r->e.rms_t : r->e.rms_c;
        if (!r->ok || r->method != method || !(r->e.dq < 0.1)) continue;
        if (crit < 2 && !(fabs(rr) < 0.02)) continue;
        if (!b || r->wall < b->wall) b = r;
    }
    return b;
}

/* ================================================================== plots */
static int pareto(const double *x, const double *y, int n, double *px, double *py)
{
    int idx[64], i, j, np = 0;
    double best = HUGE_VAL;
    for (i = 0; i < n && i < 64; i++) idx[i] = i;
    for (i = 1; i < n && i < 64; i++) for (j = i; j > 0 && x[idx[j]] < x[idx[j - 1]]; j--) { int t = idx[j]; idx[j] = idx[j - 1]; idx[j - 1] = t; }
    for (i = 0; i < n && i < 64; i++) {
        if (!(y[idx[i]] > 0) || !isfinite(x[idx[i]])) continue;
        if (y[idx[i]] < best) { best = y[idx[i]]; px[np] = x[idx[i]]; py[np] = best; np++; }
    }
    return np;
}

/* which: 0 = dq (deg); 1 = tip RMS (%): tangent points and fronts, chord fronts dashed */
static double plot_y(const drow *r, int which, int chord)
{
    if (which == 0) return r->e.dq;
    return 100 * fabs(chord ? r->e.rms_c : r->e.rms_t);
}

static int work_precision_plot(rjr_context *ctx, const char *path, const char *title, const char *ylabel,
                               const drow *rows, int nrows, int which, double threshold, char *err, size_t errlen)
{
    static double ax[2][64], ay[2][64], fx[2][64], fy[2][64], cx[2][64], cy[2][64], fcx[2][64], fcy[2][64], tx[2], ty[2];
    static char lab[6][80];
    static const rjr_rgb col[2] = { 0xd62728, 0x1f77b4 };
    rjr_plot_def p = rjr_plot_default();
    int mi, i, n, ns = 0;
    double xmin = HUGE_VAL, xmax = 0, ymin = HUGE_VAL, ymax = 0;
    for (mi = 0; mi < 2; mi++) {
        int meth = mi ? RJ_METHOD_ADAPTIVE : RJ_METHOD_PENALTY, nf, nfc;
        n = 0;
        for (i = 0; i < nrows; i++) {
            double y, yc;
            if (!rows[i].ok || rows[i].method != meth || n >= 64) continue;
            y = plot_y(&rows[i], which, 0); yc = plot_y(&rows[i], which, 1);
            ax[mi][n] = cx[mi][n] = rows[i].wall; ay[mi][n] = y; cy[mi][n] = yc; n++;
            xmin = fmin(xmin, rows[i].wall); xmax = fmax(xmax, rows[i].wall);
            if (y > 0 && isfinite(y)) { ymin = fmin(ymin, y); ymax = fmax(ymax, y); }
            if (which && yc > 0 && isfinite(yc)) { ymin = fmin(ymin, yc); ymax = fmax(ymax, yc); }
        }
        nf = pareto(ax[mi], ay[mi], n, fx[mi], fy[mi]);
        snprintf(lab[3 * mi], sizeof lab[0], "%s, every setting", method_name(meth));
        snprintf(lab[3 * mi + 1], sizeof lab[0], "%s, Pareto front%s", method_name(meth), which ? " (tangent)" : "");
        p.series[ns].x = ax[mi]; p.series[ns].y = ay[mi]; p.series[ns].n = n; p.series[ns].label = lab[3 * mi];
        p.series[ns].colour = col[mi]; p.series[ns].points = 1; p.series[ns].no_line = 1; p.series[ns].width_px = 3; ns++;
        p.series[ns].x = fx[mi]; p.series[ns].y = fy[mi]; p.series[ns].n = nf; p.series[ns].label = lab[3 * mi + 1];
        p.series[ns].colour = col[mi]; p.series[ns].points = 1; ns++;
        if (which) {
            nfc = pareto(cx[mi], cy[mi], n, fcx[mi], fcy[mi]);
            snprintf(lab[3 * mi + 2], sizeof lab[0], "%s, Pareto front (chord)", method_name(meth));
            p.series[ns].x = fcx[mi]; p.series[ns].y = fcy[mi]; p.series[ns].n = nfc; p.series[ns].label = lab[3 * mi + 2];
            p.series[ns].colour = col[mi]; p.series[ns].dashed = 1; p.series[ns].points = 1; ns++;
        }
    }
    if (threshold > 0 && xmax > 0) {
        tx[0] = pow(10.0, floor(log10(xmin))); tx[1] = pow(10.0, ceil(log10(xmax * 1.2))); ty[0] = ty[1] = threshold;
        p.series[ns].x = tx; p.series[ns].y = ty; p.series[ns].n = 2; p.series[ns].label = "criterion";
        p.series[ns].colour = 0x555555; p.series[ns].dashed = 1; ns++;
    }
    p.series_count = ns;
    p.title = title; p.xlabel = "wall time (s)"; p.ylabel = ylabel;
    p.logx = p.logy = 1;
    if (ymax > 0) {
        if (threshold > 0) { ymin = fmin(ymin, threshold); ymax = fmax(ymax, threshold); }
        p.ymin = pow(10.0, floor(log10(ymin)) - 1); /* a decade of room for the legend */
        p.ymax = pow(10.0, ceil(log10(ymax * 1.5)));
        p.xmin = pow(10.0, floor(log10(xmin)));
        p.xmax = pow(10.0, ceil(log10(xmax * 1.2)));
    }
    p.legend = RJR_LEGEND_BOTTOM_LEFT;
    if (rjr_plot(ctx, &p) || rjr_save_png(ctx, path, err, errlen)) {
        if (!err[0]) snprintf(err, errlen, "%s", rjr_error(ctx));
        return -1;
    }
    return 0;
}

/* ================================================================== machine */
static void machine(char *cpu, size_t cpulen, int *cores)
{
    FILE *f = fopen("/proc/cpuinfo", "r");
    char line[512];
    snprintf(cpu, cpulen, "unknown");
    *cores = 0;
    if (!f) return;
    while (fgets(line, sizeof line, f)) {
        if (!strncmp(line, "processor", 9)) (*cores)++;
        if (!strncmp(line, "model name", 10) && !strcmp(cpu, "unknown")) {
            char *c = strchr(line, ':'), *e;
            if (c) {
                c++;
                while (*c == ' ' || *c == '\t') c++;
                e = c + strlen(c);
                while (e > c && (e[-1] == '\n' || e[-1] == ' ')) *--e = 0;
                snprintf(cpu, cpulen, "%s", c);
            }
        }
    }
    fclose(f);
}

static const char *compiler(void)
{
#if defined(__clang__)
    return "clang " __VERSION__;
#elif defined(__GNUC__)
    return "gcc " __VERSION__;
#else
    return "unknown compiler";
#endif
}

static void fmt_dt(char *b, size_t n, double dt) { snprintf(b, n, "%.4g", dt * 1e6); }

/* path of file as seen from the directory of report (when file lies below it) */
static const char *rel_path(const char *file, const char *report)
{
    const char *slash = strrchr(report, '/');
    size_t n = slash ? (size_t)(slash - report) + 1 : 0;
    return n && !strncmp(file, report, n) ? file + n : file;
}

/* ================================================================== main */

/* ================================================================== rendering throughput */
/* Frames per second of a deployment frame (drawn at t = 3.1 s, just after joint 2 locks)
   at 640x480 and 1280x720, PNG writing included (zlib level 1, no filters, to /tmp):
   median of 3 batches of 30 frames, one context per size created once and not timed. */
static int cmp_dbl(const void *a, const void *b) { double x = *(const double *)a, y = *(const double *)b; return x < y ? -1 : x > y; }
static void bench_render(double fps[2], double draw_ms[2], char *renderer, size_t rlen)
{
    static const int sz[2][2] = { { 640, 480 }, { 1280, 720 } };
    deploy_opts o = deploy_default_opts();
    rj_model *m = NULL; rj_state *s = NULL; rj_error e;
    int k, b, f;
    renderer[0] = 0;
    fps[0] = fps[1] = draw_ms[0] = draw_ms[1] = 0;
    if (deploy_build(&o, &m, &e) != RJ_OK) return;
    rj_state_create(m, &s, NULL);
    rj_run(m, s, 3.1, 0, NULL, NULL);
    for (k = 0; k < 2; k++) {
        char err[256];
        double box[4] = { -1.2, -0.3, 1.3, 2.2 }, per[3], dr[3];
        rjr_view v = rjr_view_default();
        rjr_context *c = rjr_create(sz[k][0], sz[k][1], err, sizeof err);
        unsigned char *buf = (unsigned char *)malloc((size_t)sz[k][0] * sz[k][1] * 3);
        if (!c || !buf) { free(buf); if (c) rjr_destroy(c); continue; }
        if (!renderer[0]) snprintf(renderer, rlen, "%s, %s", rjr_gl_renderer(c), rjr_gl_version(c));
        rjr_view_fit_box(&v, box, sz[k][0], sz[k][1], 20);
        v.thickness_factor = 2.0;
        rjr_draw_state(c, m, s, &v);   /* warm-up: shader compilation */
        for (b = 0; b < 3; b++) {
            double t0 = now(), t1, t2;
            for (f = 0; f < 30; f++) { rjr_draw_state(c, m, s, &v); rjr_read_pixels(c, buf); }
            t1 = now();
            for (f = 0; f < 30; f++) {
                char path[64];
                snprintf(path, sizeof path, "/tmp/rj_bench_frame_%d.png", f % 4);
                rjr_draw_state(c, m, s, &v);
                rjr_save_png(c, path, err, sizeof err);
            }
            t2 = now();
            dr[b] = (t1 - t0) / 30 * 1e3;
            per[b] = (t2 - t1) / 30;
        }
        qsort(per, 3, sizeof per[0], cmp_dbl); qsort(dr, 3, sizeof dr[0], cmp_dbl);
        fps[k] = 1.0 / per[1]; draw_ms[k] = dr[1];
        free(buf);
        rjr_destroy(c);
    }
    rj_state_destroy(s, NULL); rj_model_destroy(m, NULL);
}

int main(int argc, char **argv)
{
    const char *out = "BENCHMARKS.md", *plot = "docs/work_precision.png";
    static char cmd[2048], plot2[1024], cpu[256], date[64], load0[64], load1[64];
    static dhist H, HREF, HCHK;
    static tp_row tp[3];
    static drow dr[64];
    static irow ir[64], iref[3], ichk[3][2];
    static const int tp_el[3] = { 20, 200, 2000 };
    static const int dmeth[2] = { RJ_METHOD_PENALTY, RJ_METHOD_ADAPTIVE };
    static const int imeth[3] = { RJ_METHOD_ADAPTIVE, RJ_METHOD_PENALTY, RJ_METHOD_MOMENTUM };
    drow dref, dchk[2], dpaper;
    double iref_unconverged[3] = { 0, 0, 0 };
    int i, j, k, ndr = 0, nir = 0, cores, plot_failed = 0;
    double paper_w[32], paper_c[32], paper_med = 0, paper_cpu = 0, t_total;
    long paper_steps = 0;
    double paper_lock[2] = { 0, 0 }, paper_model_pn = 0, paper_state_pn = 0;
    FILE *f;
    time_t tnow;

    T_START = now();
    loadavg(load0, sizeof load0);
    for (i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--out") && i + 1 < argc) out = argv[++i];
        else if (!strcmp(argv[i], "--plot") && i + 1 < argc) plot = argv[++i];
        else if (!strcmp(argv[i], "--quick")) S.quick = 1;
        else if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) { fputs(usage, stdout); return 0; }
        else { fprintf(stderr, "bench: unknown option or missing value: '%s'\n%s", argv[i], usage); return 2; }
    }
    for (i = 0; i < argc; i++) {
        size_t used = strlen(cmd);
        snprintf(cmd + used, sizeof cmd - used, "%s%s", i ? " " : "", argv[i]);
    }
    {
        const char *dot = strrchr(plot, '.');
        size_t stem = dot && dot > strrchr(plot, '/') ? (size_t)(dot - plot) : strlen(plot);
        snprintf(plot2, sizeof plot2, "%.*s_tip.png", (int)stem, plot);
    }

    if (!S.quick) {
        S.tp_runs = 7; S.tp_min_time = 0.2; S.paper_runs = 5;
        S.d_nel = 4; S.d_el[0] = 5; S.d_el[1] = 10; S.d_el[2] = 20; S.d_el[3] = 40;
        S.d_ndt[0] = 4; S.d_ndt[1] = 4; S.d_ndt[2] = 3; S.d_ndt[3] = 3;
        S.d_ref_el = 80; S.d_ref_div = 2; S.d_tend = 6.0;
        S.i_nel = 4; S.i_el[0] = 5; S.i_el[1] = 10; S.i_el[2] = 20; S.i_el[3] = 40;
        S.i_ndt = 4; S.i_ref_el = 160; S.i_ref_div = 2; S.i_tend = 0.02;
        S.budget = 360;
    } else {
        S.tp_runs = 3; S.tp_min_time = 0.02; S.paper_runs = 1;
        S.d_nel = 2; S.d_el[0] = 5; S.d_el[1] = 10;
        S.d_ndt[0] = 2; S.d_ndt[1] = 2;
        S.d_ref_el = 20; S.d_ref_div = 2; S.d_tend = 6.0;
        S.i_nel = 2; S.i_el[0] = 5; S.i_el[1] = 10;
        S.i_ndt = 2; S.i_ref_el = 20; S.i_ref_div = 2; S.i_tend = 0.02;
        S.budget = 20;
    }

    /* ---------------------------------------------------------------- 1 */
    for (i = 0; i < 3; i++) {
        if (free_link(tp_el[i], &tp[i])) return 1;
        progress("free link %4d elements: %.2f ns/element-step (median of %d x %ld steps)", tp_el[i], tp[i].ns_med, tp[i].runs, tp[i].steps);
    }
    {
        deploy_opts o = deploy_default_opts();
        rj_model *m; rj_state *s; rj_error err;
        if (deploy_build(&o, &m, &err) != RJ_OK) { fprintf(stderr, "bench: deploy: %s\n", err.msg); return 1; }
        rj_state_create(m, &s, NULL);
        for (k = 0; k < S.paper_runs; k++) {
            double t0, c0;
            rj_result r;
            rj_state_reset(m, s);
            t0 = now(); c0 = cpu_now();
            r = rj_run(m, s, 6.0, 0, NULL, NULL);
            paper_w[k] = now() - t0; paper_c[k] = cpu_now() - c0;
            if (r != RJ_OK) { fprintf(stderr, "bench: deploy: %s\n", rj_state_error(s)); return 1; }
        }
        paper_steps = rj_state_steps(s);
        paper_lock[0] = rj_joint_event_time(m, s, 0); paper_lock[1] = rj_joint_event_time(m, s, 1);
        paper_med = median(paper_w, S.paper_runs);
        paper_cpu = median(paper_c, S.paper_runs);
        dpaper.el = 10; dpaper.dt = rj_model_dt(m); dpaper.K = rj_joint_stiffness(m, 1); dpaper.bound = rj_model_dt_bound(m);
        dpaper.runs = S.paper_runs;
        /* memory of the deployment model */
        {
            rj_link_def L[2]; rj_joint_def J[2]; rj_scene_def sc;
            deploy_scene(&o, L, J, &sc);
            J[1].penalty_k = dpaper.K;
            paper_model_pn = (double)rj_model_size(&sc, NULL) / rj_model_node_count(m);
            paper_state_pn = (double)rj_state_size(m) / rj_model_node_count(m);
        }
        rj_state_destroy(s, NULL); rj_model_destroy(m, NULL);
        progress("deployment at the paper's settings: %.3f s for %ld steps (%.0f steps/s)", paper_med, paper_steps, paper_steps / paper_med);
    }

    /* ---------------------------------------------------------------- 2 */
    {
        double lr[2];
        rigid2_params rp;
        rigid2_default_params(&rp);
        if (rigid2_run(&rp, 6.0, 1e-2, r2_cb, NULL, lr) != RIGID2_OK) { fputs("bench: rigid reference failed\n", stderr); return 1; }
        D_RIGID_LOCK[0] = lr[0]; D_RIGID_LOCK[1] = lr[1];
        D_TPRE = lr[1] - 0.01;
    }
    /* reference: adaptive, fine mesh, top / div; checks: same mesh at 2x the step, half the mesh at the same fraction of its bound */
    memset(&dref, 0, sizeof dref); memset(dchk, 0, sizeof dchk);
    dref.method = RJ_METHOD_ADAPTIVE; dref.el = S.d_ref_el; dref.dt = d_top_dt(RJ_METHOD_ADAPTIVE, S.d_ref_el) / S.d_ref_div;
    if (dref.dt <= 0) return 1;
    d_run(&dref, &HREF, NULL, NULL, 1);
    if (!dref.ok) { fprintf(stderr, "bench: deployment reference: %s\n", dref.msg); return 1; }
    progress("deployment reference %d el dt %.4g us: %.1f s; joint 2 locks at %.6f s", dref.el, dref.dt * 1e6, dref.wall, dref.m.lock2);
    dchk[0] = dref; dchk[0].dt = dref.dt * 2;
    dchk[1] = dref; dchk[1].el = S.d_ref_el / 2; dchk[1].dt = d_top_dt(RJ_METHOD_ADAPTIVE, S.d_ref_el / 2) / S.d_ref_div;
    for (i = 0; i < 2; i++) {
        d_run(&dchk[i], &HCHK, &HREF, &dref.m, 1);
        if (!dchk[i].ok) { fprintf(stderr, "bench: deployment reference check: %s\n", dchk[i].msg); return 1; }
        progress("  check %d el dt %.4g us: max |dq| %.4f deg, lock %+.3g s, rms %+.3f%% / %+.3f%%", dchk[i].el, dchk[i].dt * 1e6, dchk[i].e.dq, dchk[i].e.dlock, 100 * dchk[i].e.rms_c, 100 * dchk[i].e.rms_t);
    }
    for (j = 0; j < 2; j++) {
        for (i = 0; i < S.d_nel; i++) {
            double top = d_top_dt(dmeth[j], S.d_el[i]);
            if (top <= 0) return 1;
            for (k = 0; k < S.d_ndt[i]; k++) {
                drow *r = &dr[ndr++];
                memset(r, 0, sizeof *r);
                r->method = dmeth[j]; r->el = S.d_el[i]; r->dt = top / (1 << k);
                d_run(r, &H, &HREF, &dref.m, 0);
                progress("deploy %-8s %2d el dt %7.4g us: %s wall %.3f s (%d runs) dq %.4f deg lock %+.2e s rms %+.2f%% / %+.2f%% freq %+.2f%%",
                         method_name(r->method), r->el, r->dt * 1e6, r->ok ? "ok" : r->msg, r->wall, r->runs, r->e.dq, r->e.dlock,
                         100 * r->e.rms_c, 100 * r->e.rms_t, 100 * r->e.freq_c);
                /* the paper's step, between top/2 and top/4 at 10 elements */
                if (S.d_el[i] == 10 && k == 1 && !S.quick) {
                    drow *q = &dr[ndr++];
                    memset(q, 0, sizeof *q);
                    q->method = dmeth[j]; q->el = 10; q->dt = 7.5e-6; q->paper = 1;
                    d_run(q, &H, &HREF, &dref.m, 0);
                    progress("deploy %-8s %2d el dt %7.4g us (paper): %s wall %.3f s dq %.4f deg rms %+.2f%%", method_name(q->method), q->el, q->dt * 1e6,
                             q->ok ? "ok" : q->msg, q->wall, q->e.dq, 100 * q->e.rms_c);
                }
            }
        }
    }

    /* ---------------------------------------------------------------- 3 */
    for (j = 0; j < 3; j++) {
        double top = i_top_dt(imeth[j], S.i_ref_el);
        memset(&iref[j], 0, sizeof iref[j]);
        iref[j].method = imeth[j]; iref[j].el = S.i_ref_el; iref[j].dt = top / S.i_ref_div;
        i_run(&iref[j], 1);
        if (!iref[j].ok) { fprintf(stderr, "bench: impact reference: %s\n", iref[j].msg); return 1; }
        ichk[j][0] = iref[j]; ichk[j][0].dt = iref[j].dt * 2;
        ichk[j][1] = iref[j]; ichk[j][1].el = S.i_ref_el / 2; ichk[j][1].dt = i_top_dt(imeth[j], S.i_ref_el / 2) / S.i_ref_div;
        for (i = 0; i < 2; i++) { i_run(&ichk[j][i], 1); if (ichk[j][i].ok) i_errors(&ichk[j][i], &iref[j]); }
        progress("impact reference %s %d el dt %.4g us: release %.5f ms (last %.5f ms), peak %.6g m; checks: release %+.3g / %+.3g ms, peak %+.2f%% / %+.2f%%",
                 method_name(imeth[j]), iref[j].el, iref[j].dt * 1e6, 1e3 * iref[j].release_first, 1e3 * iref[j].release_last, iref[j].peak_c,
                 1e3 * ichk[j][0].e_first, 1e3 * ichk[j][1].e_first, 100 * ichk[j][0].e_peak_c, 100 * ichk[j][1].e_peak_c);
        for (i = 0; i < S.i_nel; i++) {
            double t2 = i_top_dt(imeth[j], S.i_el[i]);
            if (t2 <= 0) return 1;
            for (k = 0; k < S.i_ndt; k++) {
                irow *r = &ir[nir++];
                memset(r, 0, sizeof *r);
                r->method = imeth[j]; r->el = S.i_el[i]; r->dt = t2 / (1 << k);
                i_run(r, 0);
                if (r->ok) i_errors(r, &iref[j]);
                progress("impact %-8s %2d el dt %7.4g us: %s wall %.4f s release %+.3g ms (last %+.3g ms) peak %+.2f%% / %+.2f%%", method_name(r->method), r->el, r->dt * 1e6,
                         r->ok ? "ok" : r->msg, r->wall, 1e3 * r->e_first, 1e3 * r->e_last, 100 * r->e_peak_c, 100 * r->e_peak_t);
            }
        }
    }

    /* ---------------------------------------------------------------- plots */
    {
        char err[512] = "";
        rjr_context *ctx = rjr_create(960, 720, err, sizeof err);
        if (!ctx) { fprintf(stderr, "bench: plot: %s\n", err); plot_failed = 1; }
        else {
            if (work_precision_plot(ctx, plot, "Deployment (SPEC 9.2): q1, q2 before joint 2 locks", "max abs(q - q_ref) (deg)", dr, ndr, 0, 0.1, err, sizeof err)) {
                fprintf(stderr, "bench: %s: %s\n", plot, err); plot_failed = 1;
            }
            err[0] = 0;
            if (work_precision_plot(ctx, plot2, "Deployment: link 2 tip RMS deflection after joint 2 locks", "abs(RMS / RMS_ref - 1) (%)", dr, ndr, 1, 2.0, err, sizeof err)) {
                fprintf(stderr, "bench: %s: %s\n", plot2, err); plot_failed = 1;
            }
            rjr_destroy(ctx);
        }
    }

    /* refinement checks: errors should fall as dt or the element length falls; anything
       else goes to the notes at the top of the report */
    {
        int nbad = 0;
        for (i = 0; i < ndr; i++) for (k = 0; k < ndr; k++) {
            const drow *a = &dr[i], *b = &dr[k];
            int halfdt, twiceel;
            if (!a->ok || !b->ok || a->method != b->method || a->paper || b->paper) continue;
            halfdt = a->el == b->el && fabs(b->dt / a->dt - 0.5) < 1e-9;
            twiceel = b->el == 2 * a->el && fabs(b->dt / b->bound - a->dt / a->bound) < 1e-3;
            if ((halfdt || twiceel) && b->e.dq > 1.05 * a->e.dq + 1e-4) {
                note("deployment %s: dq grows from %.4f deg (%d el, dt %.4g us) to %.4f deg (%d el, dt %.4g us)", method_name(a->method), a->e.dq, a->el, a->dt * 1e6,
                     b->e.dq, b->el, b->dt * 1e6);
                nbad++;
            }
            if ((halfdt || twiceel) && fabs(b->e.rms_t) > 1.1 * fabs(a->e.rms_t) + 0.002) {
                note("deployment %s: tip RMS (tangent) error grows from %+.2f %% (%d el, dt %.4g us) to %+.2f %% (%d el, dt %.4g us)", method_name(a->method), 100 * a->e.rms_t, a->el,
                     a->dt * 1e6, 100 * b->e.rms_t, b->el, b->dt * 1e6);
                nbad++;
            }
        }
        if (fabs(dchk[1].e.rms_c) > 3 * fabs(dchk[1].e.rms_t) && fabs(dchk[1].e.rms_c) > 0.005)
            note("deployment: the chord-based tip deflection (`scene_tip_defl`) converges at first order in the element length: with half the reference's mesh its RMS is off by %+.2f %%, "
                 "the tangent-based one by %+.3f %%; the difference is the chord-tangent angle of the first element (about kappa l / 2) times the link length. "
                 "Amplitude criteria on `scene_tip_defl` need a much finer mesh than the dynamics do.", 100 * dchk[1].e.rms_c, 100 * dchk[1].e.rms_t);
        if (fabs(dchk[0].e.dlock1) > 1e-3 || fabs(dchk[1].e.dlock1) > 1e-3)
            note("deployment: joint 1's lock time is sensitive: it moves by %+.2f ms with twice the reference's step and %+.2f ms with half its mesh (joint 2's by %+.3f / %+.3f ms)",
                 1e3 * dchk[0].e.dlock1, 1e3 * dchk[1].e.dlock1, 1e3 * dchk[0].e.dlock, 1e3 * dchk[1].e.dlock);
        for (j = 0; j < 3; j++) {
            double worst = fabs(ichk[j][0].e_first) > fabs(ichk[j][1].e_first) ? ichk[j][0].e_first : ichk[j][1].e_first;
            iref_unconverged[j] = fabs(worst) > 5e-5 ? worst : 0;
            if (iref_unconverged[j] != 0)
                note("impact %s: the reference's release time is not converged: twice its step moves the first lasting release by %+.3f ms and half its mesh by %+.3f ms. "
                     "After the rebound the link's root stays very close to the stop and the RC13 flag toggles (%ld flag changes in the reference run), "
                     "so whether a free interval of 0.1 ms opens is decided by tiny differences. Its release errors below are not meaningful; its peak deflection is.",
                     method_name(imeth[j]), 1e3 * ichk[j][0].e_first, 1e3 * ichk[j][1].e_first, iref[j].flips);
        }
        for (j = 0; j < 3; j++) {
            int seen = 0;
            for (i = 0; i < nir && !seen; i++) {
                const irow *r = &ir[i];
                if (!r->ok || r->method != imeth[j] || r->contacts == iref[j].contacts) continue;
                if (fabs(r->e_last) > 0.1e-3) {
                    note("impact %s: `rj_joint_release_time` (latest release) of the reference is %.4f ms with %d contact episode(s); %d el dt %.4g us has %d, and its latest release is off by %+.3f ms "
                         "(first lasting release: %+.4f ms). The link grazes the stop again after the rebound; whether it touches depends on the mesh.",
                         method_name(imeth[j]), 1e3 * iref[j].release_last, iref[j].contacts, r->el, r->dt * 1e6, r->contacts, 1e3 * r->e_last, 1e3 * r->e_first);
                    seen = 1;
                }
            }
            for (i = 0; i + S.i_ndt < nir; i++) {
                const irow *a = &ir[i], *b = &ir[i + S.i_ndt];
                if (!a->ok || !b->ok || a->method != imeth[j] || b->method != imeth[j] || b->el != 2 * a->el) continue;
                if (fabs(iref_unconverged[j]) > 0) break;   /* noted below instead */
                if (fabs(b->e_first) > 1.5 * fabs(a->e_first) + 5e-6) {
                    note("impact %s: first-release error grows with the mesh: %+.4f ms at %d el (dt %.4g us) to %+.4f ms at %d el (dt %.4g us)", method_name(imeth[j]),
                         1e3 * a->e_first, a->el, a->dt * 1e6, 1e3 * b->e_first, b->el, b->dt * 1e6);
                    nbad++;
                    break;
                }
            }
        }
        progress("refinement checks: %d pairs where an error grows with refinement", nbad);
    }

    /* ---------------------------------------------------------------- report */
    /* (written below: checks on refinement, cheapest settings, tables) */
    {
        char b1[32];
        md("## Headline\n\n");
        md("- Step cost, one free link: **%.1f / %.1f / %.1f ns per element-step** at %d / %d / %d elements (median of %d runs).\n",
           tp[0].ns_med, tp[1].ns_med, tp[2].ns_med, tp[0].elements, tp[1].elements, tp[2].elements, S.tp_runs);
        md("- Deployment at the paper's settings (10 elements per link, dt 7.5 us, 6 s): **%.3f s** wall (CPU %.3f s), **%.3g steps/s**.\n", paper_med, paper_cpu, paper_steps / paper_med);
        for (j = 0; j < 2; j++) {
            const drow *b = d_cheapest(dr, ndr, dmeth[j], 0);
            if (!b) { md("- Deployment, %s: no setting in the sweep keeps q within 0.1 deg and the tip RMS within 2 %%.\n", method_name(dmeth[j])); continue; }
            md("- Deployment, cheapest %s setting with q within 0.1 deg before joint 2 locks and the tip RMS within 2 %%: **%d elements per link, dt %.4g us, %.3f s** (CPU %.3f s; "
               "dq %.4f deg, tip RMS %+.2f %%, frequency %+.2f %%).\n", method_name(dmeth[j]), b->el, b->dt * 1e6, b->wall, b->cpu, b->e.dq, 100 * b->e.rms_t, 100 * b->e.freq_t);
        }
        md("- Deployment reference: adaptive, %d elements, dt %.4g us (%.1f s); against it, twice its step moves q by %.4f deg and half its mesh by %.4f deg.\n",
           dref.el, dref.dt * 1e6, dref.wall, dchk[0].e.dq, dchk[1].e.dq);
        md("\n");
        md("## 1. Throughput\n\n");
        md("One free flexible link (`rj_default_link_def()`, height 0.01 m, 1 m, spinning at omega = 1 rad/s, no joints), dt = 0.9 x its stability bound. "
           "Each timed run is `rj_step` in a loop of the given number of steps (at least %.2g s), from a reset state; median of %d runs. "
           "Energy drift: relative change of the total energy over one run (a check that the steps did real work and stayed stable).\n\n", S.tp_min_time, S.tp_runs);
        md("| elements | dt (us) | steps per run | ns / element-step (median) | min | max | CPU ns / element-step | model bytes / node | state bytes / node | energy drift |\n");
        md("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
        for (i = 0; i < 3; i++) {
            fmt_dt(b1, sizeof b1, tp[i].dt);
            md("| %d | %s | %ld | **%.2f** | %.2f | %.2f | %.2f | %.0f | %.0f | %.1e |\n", tp[i].elements, b1, tp[i].steps, tp[i].ns_med, tp[i].ns_min, tp[i].ns_max,
               tp[i].ns_cpu, tp[i].model_per_node, tp[i].state_per_node, tp[i].edrift);
        }
        md("\nDeployment at the paper's settings (`deploy_build` defaults: 10 elements per link, dt = 7.5 us, joint 2 penalty with K = Eq 31 = %.4g N m/rad; stability bound %.4g us), "
           "6 s simulated, `rj_run` without sampling, median of %d runs: **%.3f s** wall (CPU %.3f s), %ld steps, **%.0f steps/s** "
           "(%.1f ns per element-step over its 20 elements). Joint 2 locks at %.6f s, joint 1 at %.6f s. "
           "Model %.0f bytes / node, state %.0f bytes / node (22 nodes).\n\n",
           dpaper.K, dpaper.bound * 1e6, S.paper_runs, paper_med, paper_cpu, paper_steps, paper_steps / paper_med, 1e9 * paper_med / (paper_steps * 20.0),
           paper_lock[1], paper_lock[0], paper_model_pn, paper_state_pn);
    }

    /* rendering */
    {
        double fps[2], dms[2];
        char rname[256];
        bench_render(fps, dms, rname, sizeof rname);
        md("### Rendering (issue 4)\n\n");
        md("A deployment frame (t = 3.1 s) drawn with `render/rj_render.c` (4x MSAA) and written as PNG (zlib level 1, no filters), "
           "one context per size created once and not timed; median of 3 batches of 30 frames. Renderer: %s.\n\n", rname);
        md("| size | frames/s with PNG writing | draw + read back only (ms/frame) |\n|---|---:|---:|\n");
        md("| 640x480 | **%.0f** | %.2f |\n| 1280x720 | **%.0f** | %.2f |\n\n", fps[0], dms[0], fps[1], dms[1]);
    }

    /* deployment section */
    {
        char b1[32];
        md("## 2. Deployment (SPEC 9.2): speed against error\n\n");
        md("Joint 1 forced, joint 2 locked by the method named; 6 s simulated; wall time = `rj_run` with a 1 ms sample callback "
           "(median of 5 runs below 2 s, 3 below 6 s, else 1; the `runs` column says how many). "
           "dt: 0.9 x the stability bound `rj_model_dt_bound` of that mesh and method (the step the library picks itself), then halved; "
           "for penalty K = Eq 31 at that dt (`deploy_build` default), so K grows as 1/dt^2, as does adaptive's K_AP (Eq 21).\n\n");
        md("Errors against the reference:\n\n"
           "- **dq**: max |q1 - q1_ref|, |q2 - q2_ref| (deg) over the 1 ms samples with t < %.4f s (the rigid model's joint 2 lock, %.6f s, minus 10 ms); "
           "samples are moved to the exact millisecond with the joint rates (|shift| <= dt/2).\n"
           "- **lock**: joint 2 lock time minus the reference's (ms).\n"
           "- **RMS**: link 2 tip deflection RMS over t in [3.2, %.1f] s (after joint 2 locks; joint 1 locks near 4.1 s), relative to the reference: "
           "*chord* = `scene_tip_defl(m, s, 1)` (from the chord of link 2's first element), *tangent* = from the tangent at link 2's root (node 0's rotation). "
           "**freq**: dominant frequency from the zero crossings of the deflection minus its mean, relative.\n\n",
           D_TPRE, D_RIGID_LOCK[1], S.d_tend);
        md("### Reference and its convergence\n\n");
        md("Reference: adaptive, %d elements per link, dt = %.4g us (0.9 x bound / %g), %.1f s wall. Joint 2 locks at %.6f s (rigid model %.6f s), joint 1 at %.6f s (rigid %.6f s); "
           "tip RMS %.5g m (chord) / %.5g m (tangent), peak %.4g m, frequency %.4f Hz (chord) / %.4f Hz (tangent).\n\n",
           dref.el, dref.dt * 1e6, S.d_ref_div, dref.wall, dref.m.lock2, D_RIGID_LOCK[1], dref.m.lock1, D_RIGID_LOCK[0], dref.m.rms_c, dref.m.rms_t, dref.m.peak_c, dref.m.freq_c, dref.m.freq_t);
        md("| against the reference | wall (s) | dq (deg) | lock 2 (ms) | lock 1 (ms) | RMS tangent | RMS chord | freq tangent | freq chord |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|\n");
        for (i = 0; i < 2; i++) {
            fmt_dt(b1, sizeof b1, dchk[i].dt);
            md("| %s: %d elements, dt %s us | %.2f | %.4f | %+.4f | %+.3f | %+.3f %% | %+.3f %% | %+.3f %% | %+.3f %% |\n", i ? "half the mesh" : "twice the step", dchk[i].el, b1, dchk[i].wall, dchk[i].e.dq, 1e3 * dchk[i].e.dlock,
               1e3 * dchk[i].e.dlock1, 100 * dchk[i].e.rms_t, 100 * dchk[i].e.rms_c, 100 * dchk[i].e.freq_t, 100 * dchk[i].e.freq_c);
        }
        md("\nWith second-order convergence in the element length, the reference's own mesh error is about a third of the 'half the mesh' row, "
           "since error(l) - error(l/2) = 3 error(l/2). A first-order quantity, such as the chord-based deflection, keeps about all of it. "
           "So the reference is uncertain by about %.3f deg in dq (the step row plus a third of the mesh row), %.2f %% in tangent RMS and %.2f %% in frequency. "
           "Differences below these in the sweep are not resolved.\n\n",
           dchk[0].e.dq + dchk[1].e.dq / 3, 100 * (fabs(dchk[0].e.rms_t) + fabs(dchk[1].e.rms_t) / 3), 100 * (fabs(dchk[0].e.freq_t) + fabs(dchk[1].e.freq_t) / 3));

        md("### Sweep\n\n");
        md("| method | elements | dt (us) | dt / bound | K joint 2 (N m/rad) | steps | wall (s) | CPU (s) | runs | dq (deg) | lock 2 (ms) | lock 1 (ms) | RMS tangent | RMS chord | freq tangent | freq chord |\n");
        md("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
        for (i = 0; i < ndr; i++) {
            const drow *r = &dr[i];
            fmt_dt(b1, sizeof b1, r->dt);
            if (!r->ok) { md("| %s | %d | %s%s | failed: %s | | | | | | | | | | | | |\n", method_name(r->method), r->el, b1, r->paper ? " (paper)" : "", r->msg); continue; }
            md("| %s | %d | %s%s | %.3f | %.4g | %ld | %.3f | %.3f | %d | %s%.4f%s | %+.4f | %+.3f | %s%+.2f %%%s | %+.2f %% | %+.2f %% | %+.2f %% |\n", method_name(r->method), r->el, b1, r->paper ? " (paper)" : "",
               r->dt / r->bound, r->K, r->steps, r->wall, r->cpu, r->runs, r->e.dq < 0.1 ? "**" : "", r->e.dq, r->e.dq < 0.1 ? "**" : "", 1e3 * r->e.dlock, 1e3 * r->e.dlock1,
               fabs(r->e.rms_t) < 0.02 ? "**" : "", 100 * r->e.rms_t, fabs(r->e.rms_t) < 0.02 ? "**" : "", 100 * r->e.rms_c, 100 * r->e.freq_t, 100 * r->e.freq_c);
        }
        md("\nReading the sweep: before the lock, dq hardly changes with dt at a fixed mesh, because the error there comes from the mesh. At 0.9 x bound, dt is "
           "proportional to the element length (the axial Courant limit), so the step error (~dt^2) falls as fast as the mesh error (~l^2), and the two can have opposite signs. "
           "Where dq grows as dt shrinks (see the notes at the top), the step error had cancelled part of the mesh error. After the lock, penalty's K = Eq 31 "
           "is soft at large dt: the tip RMS, frequency and joint 1 lock time converge only as dt falls. Adaptive's K_AP is stiff at every dt.\n");
        md("\n### Cheapest settings\n\nLeast wall time among the sweep's settings that keep dq < 0.1 deg and the post-lock tip RMS within 2 %% of the reference. "
           "The tip amplitude is judged on the tangent-based deflection (it converges at second order, see above); the chord-based `scene_tip_defl` criterion and the "
           "dq criterion alone are listed for comparison.\n\n");
        md("| method | criterion | elements | dt (us) | wall (s) | dq (deg) | lock 2 (ms) | RMS tangent | RMS chord | freq tangent |\n|---|---|---:|---:|---:|---:|---:|---:|---:|---:|\n");
        for (j = 0; j < 2; j++) {
            int c;
            static const char *const cname[3] = { "dq < 0.1 deg, RMS tangent within 2 %", "dq < 0.1 deg, RMS chord within 2 %", "dq < 0.1 deg only" };
            for (c = 0; c < 3; c++) {
                const drow *b = d_cheapest(dr, ndr, dmeth[j], c);
                if (!b) { md("| %s | %s | none in the sweep | | | | | | | |\n", method_name(dmeth[j]), cname[c]); continue; }
                fmt_dt(b1, sizeof b1, b->dt);
                md("| %s | %s | %d | %s%s | %.3f | %.4f | %+.4f | %+.2f %% | %+.2f %% | %+.2f %% |\n", method_name(dmeth[j]), cname[c],
                   b->el, b1, b->paper ? " (paper)" : "", b->wall, b->e.dq, 1e3 * b->e.dlock, 100 * b->e.rms_t, 100 * b->e.rms_c, 100 * b->e.freq_t);
            }
        }
        md("\n![work-precision, deployment q](%s)\n\n![work-precision, deployment tip amplitude](%s)\n\n", rel_path(plot, out), rel_path(plot2, out));
    }

    /* impact section */
    {
        char b1[32];
        md("## 3. Impact on a reverse limit (SPEC 9.1): speed against error\n\n");
        md("`impact_scene` with `impact_default_opts()` (RC13, penalty K = 5e8 N m/rad), %.0f ms simulated, `rj_run` sampling every step "
           "(peak deflection and contact flags). dt: 0.9 x the bound of that mesh and method, then halved. Release: *first* = start of the first free "
           "interval of at least 0.1 ms (the contact's end; adaptive and RC13 toggle the flag step by step while in contact); *last* = `rj_joint_release_time` "
           "(latest release, which moves when the link touches the stop again). Peak: max |tip deflection| of the moving link, chord (`scene_tip_defl`) and tangent. "
           "Each method converges to its own solution (penalty with fixed K is a compliant stop; adaptive's K_AP grows as 1/dt^2; momentum is a plastic impact), "
           "so each is compared with its own reference: %d elements at 0.9 x bound / %g; the two checks are its mesh at twice the step and half its mesh at the same fraction of the bound. "
           "Peak deflection from the chord converges at first order in the element length (like the deployment's), from the tangent at second order.\n\n", 1e3 * S.i_tend, S.i_ref_el, S.i_ref_div);
        md("| reference | dt (us) | wall (s) | contact (ms) | release first (ms) | release last (ms) | contacts | peak chord (m) | peak tangent (m) | check: 2x step, release / peak chord / peak tangent | check: half mesh, release / peak chord / peak tangent |\n");
        md("|---|---:|---:|---:|---:|---:|---:|---:|---:|---|---|\n");
        for (j = 0; j < 3; j++) {
            fmt_dt(b1, sizeof b1, iref[j].dt);
            md("| %s | %s | %.2f | %.5f | %.5f | %.5f | %d | %.6f | %.6f | %+.4f ms / %+.2f %% / %+.2f %% | %+.4f ms / %+.2f %% / %+.2f %% |\n", method_name(imeth[j]), b1, iref[j].wall, 1e3 * iref[j].contact,
               1e3 * iref[j].release_first, 1e3 * iref[j].release_last, iref[j].contacts, iref[j].peak_c, iref[j].peak_t,
               1e3 * ichk[j][0].e_first, 100 * ichk[j][0].e_peak_c, 100 * ichk[j][0].e_peak_t, 1e3 * ichk[j][1].e_first, 100 * ichk[j][1].e_peak_c, 100 * ichk[j][1].e_peak_t);
        }
        md("\n| method | elements | dt (us) | dt / bound | steps | wall (s) | CPU (s) | runs | contacts | flag changes | release first (ms) | error (ms) | release last (ms) | error (ms) | peak chord (m) | error | peak tangent error |\n");
        md("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
        for (i = 0; i < nir; i++) {
            const irow *r = &ir[i];
            fmt_dt(b1, sizeof b1, r->dt);
            if (!r->ok) { md("| %s | %d | %s | failed: %s | | | | | | | | | | | | | |\n", method_name(r->method), r->el, b1, r->msg); continue; }
            md("| %s | %d | %s | %.3f | %ld | %.4f | %.4f | %d | %d | %ld | %.5f | %+.4f | %.5f | %+.4f | %.6f | %+.2f %% | %+.2f %% |\n", method_name(r->method), r->el, b1, r->dt / r->bound, r->steps, r->wall, r->cpu, r->runs,
               r->contacts, r->flips, 1e3 * r->release_first, 1e3 * r->e_first, 1e3 * r->release_last, 1e3 * r->e_last, r->peak_c, 100 * r->e_peak_c, 100 * r->e_peak_t);
        }
        md("\nCheapest settings per method with |first-release error| < 0.05 ms and |peak tangent deflection error| < 2 %% "
           "(on the peak alone where the reference's release time is not converged):\n\n");
        for (j = 0; j < 3; j++) {
            const irow *b = NULL;
            int use_release = iref_unconverged[j] == 0;
            for (i = 0; i < nir; i++) {
                const irow *r = &ir[i];
                if (!r->ok || r->method != imeth[j] || !(fabs(r->e_peak_t) < 0.02)) continue;
                if (use_release && !(fabs(r->e_first) < 5e-5)) continue;
                if (!b || r->wall < b->wall) b = r;
            }
            if (!b) { md("- %s: none in the sweep\n", method_name(imeth[j])); continue; }
            fmt_dt(b1, sizeof b1, b->dt);
            md("- %s%s: %d elements, dt %s us: %.4f s wall (CPU %.4f s), release %+.4f ms, peak %+.2f %% (tangent) / %+.2f %% (chord)\n", method_name(imeth[j]),
               use_release ? "" : " (peak only)", b->el, b1, b->wall, b->cpu, 1e3 * b->e_first, 100 * b->e_peak_t, 100 * b->e_peak_c);
        }
        md("\n");
    }

    t_total = now() - T_START;
    loadavg(load1, sizeof load1);
    tnow = time(NULL);
    strftime(date, sizeof date, "%Y-%m-%d %H:%M:%S UTC", gmtime(&tnow));
    machine(cpu, sizeof cpu, &cores);
    f = fopen(out, "w");
    if (!f) { fprintf(stderr, "bench: cannot write %s\n", out); return 1; }
    fprintf(f, "# revjoint.h benchmarks\n\n");
    fprintf(f, "Generated by `bench/bench.c` (`make bench`); do not edit by hand, every number below is rewritten by each run.%s\n\n",
            S.quick ? " **This is a `--quick` run: short timings and coarse references, for smoke tests only.**" : "");
    fprintf(f, "| | |\n|---|---|\n");
    fprintf(f, "| command | `%s` |\n| date | %s |\n| CPU | %s |\n| logical cores | %d |\n| compiler | %s |\n| flags (make bench) | `%s` |\n",
            cmd, date, cpu, cores, compiler(), BENCH_CFLAGS);
    fprintf(f, "| revjoint.h | %s |\n| whole run | %.0f s |\n| load average (1, 5, 15 min) | %s at the start, %s at the end |\n\n", RJ_VERSION, t_total, load0, load1);
    fprintf(f, "The machine may be shared, so every time is a median; runs are sequential, on one core. Wall times are `CLOCK_MONOTONIC`. The CPU columns "
               "(`CLOCK_PROCESS_CPUTIME_ID`) leave out time spent descheduled. When the load average is above the core count, trust CPU more than wall.\n\n");
    if (NNOTES) {
        fprintf(f, "**Found by this run (see below):**\n\n");
        for (i = 0; i < NNOTES; i++) fprintf(f, "- %s\n", NOTES[i]);
        fprintf(f, "\n");
    }
    fwrite(R.p, 1, R.n, f);
    fclose(f);
    progress("wrote %s%s%s%s%s (total %.1f s)", out, plot_failed ? "" : ", ", plot_failed ? "" : plot, plot_failed ? "" : ", ", plot_failed ? "" : plot2, t_total);
    free(R.p);
    return plot_failed ? 1 : 0;
}
