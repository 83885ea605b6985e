/* bench.c - speed against error for revjoint.h: throughput of the step, and
   work-precision sweeps of the paper's two benchmarks (the deployment of sec. 5 and the
   impact of sec. 4) against converged references. Writes a markdown report (every number in it comes
   from this run) and PNG plots. bench/README.md says what is measured and how.

   build/bench [--out FILE.md] [--plot FILE.png] [--quick] [--only fidelity|features]

   Sections: 1 throughput, 2 deployment and 3 impact (speed against error), 4 fidelity (which
   link model for which job), 5 feature cost (time per step with each joint or load
   feature), 6 model build, 7 side by side with a MuJoCo peer (build/peer_side's section,
   quoted by --peer).

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
    "usage: bench [--out FILE.md] [--plot FILE.png] [--quick] [--only fidelity|features|throughput|build] [--native FILE.md]\n"
    "             [--peer FILE.md]\n"
    "  --out FILE.md    markdown report (default BENCHMARKS.md)\n"
    "  --plot FILE.png  work-precision plot of the deployment, q before joint 2 locks; a second\n"
    "                   plot (tip amplitude) goes to FILE_tip.png (default docs/work_precision.png)\n"
    "  --quick          a short smoke-test version (< 40 s); its numbers are not converged\n"
    "  --only SECTION   one section alone: fidelity (section 4, about 80 s, with its own\n"
    "                   40-element deployment reference) or features (section 5, about 55 s);\n"
    "                   the report goes to standard output unless --out is given; throughput\n"
    "                   (section 1's step costs alone, as a fragment for --native), or build\n"
    "                   (section 6: model build time and memory, 10 to 10000 links)\n"
    "  --native FILE.md the throughput fragment of a build with other flags (make bench: -O3\n"
    "                   -march=native), quoted in section 1 and the headline\n"
    "  --peer FILE.md   the side-by-side section of build/peer_side (make bench, when MuJoCo is\n"
    "                   installed), quoted as section 7 of the full report\n";

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

static double CAL0, CAL1;   /* calibrate() at the start and the end, ms */
static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* The machine's speed at the moment: a fixed loop that does not involve the library, a
   chain of 5e7 dependent multiply-adds (no compiler can vectorise it, so -O2 and -O3
   -march=native builds time the same thing), best of 3, in ms. This VM's speed changes by
   up to 2x within minutes; the calibration says which phase a run saw, so that two runs'
   times can be compared. */
static double calibrate(void)
{
    double best = 1e30, x = 0.5;
    int r;
    long k;
    for (r = 0; r < 3; r++) {
        double t = now();
        for (k = 0; k < 50000000L; k++) x = x * 0.9999999 + 1e-8;
        t = now() - t;
        if (t < best) best = t;
    }
    return 1e3 * best + 0.0 * x;
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
static double tip_defl_tangent(const rj_model *m, const rj_state *s, int l) { return scene_tip_defl_tangent(m, s, l); }

/* ================================================================== 1. throughput */
typedef struct tp_row {
    int elements, runs; long steps;
    double dt, ns_med, ns_min, ns_max, ns_cpu, model_per_node, state_per_node, edrift;
    int nodes;
} tp_row;

/* One free link of the given size, timed with solver.energy_every 1 (o[0]) and 16 (o[1]),
   and with 16 double-buffered (o[2]: solver.in_place off; the others are AUTO, in place from
   400 nodes); the models' runs alternate so that all see the same phases of the machine. */
static int free_link(int elements, tp_row o[3])
{
    rj_link_def L = rj_default_link_def();
    rj_scene_def sc = rj_default_scene_def();
    rj_model *m[3] = { NULL, NULL, NULL }; rj_state *s[3] = { NULL, NULL, NULL }; rj_error err; rj_energy e0, e1;
    double t, c, ns[3][32], nc[3][32];
    long steps = 16, k;
    int r, v, rc = -1;
    L.height = 0.01; L.elements = elements; L.omega = 1.0;
    sc.links = &L; sc.link_count = 1; sc.joints = NULL; sc.joint_count = 0;
    for (v = 0; v < 3; v++) {
        memset(&o[v], 0, sizeof o[v]);
        o[v].elements = elements;
        sc.solver.energy_every = v ? 16 : 1;
        sc.solver.in_place = v == 2 ? RJ_IN_PLACE_OFF : RJ_IN_PLACE_AUTO;
        if (rj_model_create(&sc, &m[v], &err, NULL) != RJ_OK) { fprintf(stderr, "bench: free link: %s\n", err.msg); goto done; }
        if (rj_state_create(m[v], &s[v], NULL) != RJ_OK) goto done;
        o[v].nodes = rj_model_node_count(m[v]);
        o[v].model_per_node = (double)rj_model_size(&sc, NULL) / o[v].nodes;
        o[v].state_per_node = (double)rj_state_size(m[v]) / o[v].nodes;
        o[v].dt = rj_model_dt(m[v]);
    }
    /* calibrate: the step count that takes at least tp_min_time (with energy every step) */
    for (;;) {
        rj_state_reset(m[0], s[0]);
        t = now();
        for (k = 0; k < steps; k++) if (rj_step(m[0], s[0]) != RJ_OK) break;
        t = now() - t;
        if (k < steps) { fprintf(stderr, "bench: free link %d: %s\n", elements, rj_state_error(s[0])); goto done; }
        if (t >= S.tp_min_time) break;
        steps = (long)((double)steps * (t > 0 ? fmin(16.0, 1.25 * S.tp_min_time / t) : 16.0)) + 1;
    }
    for (r = 0; r < S.tp_runs; r++)
        for (v = 0; v < 3; v++) {
            rj_state_reset(m[v], s[v]);
            t = now(); c = cpu_now();
            for (k = 0; k < steps; k++) if (rj_step(m[v], s[v]) != RJ_OK) break;
            t = now() - t; c = cpu_now() - c;
            if (k < steps) { fprintf(stderr, "bench: free link %d: %s\n", elements, rj_state_error(s[v])); goto done; }
            ns[v][r] = 1e9 * t / ((double)steps * elements);
            nc[v][r] = 1e9 * c / ((double)steps * elements);
        }
    /* energy drift over one run, taken with energy every step (the same steps either way) */
    memset(&e0, 0, sizeof e0); memset(&e1, 0, sizeof e1);
    rj_state_reset(m[0], s[0]);
    rj_step(m[0], s[0]);
    rj_state_energy(m[0], s[0], &e0);
    for (k = 1; k < steps; k++) if (rj_step(m[0], s[0]) != RJ_OK) break;
    rj_state_energy(m[0], s[0], &e1);
    for (v = 0; v < 3; v++) {
        o[v].edrift = (e1.total - e0.total) / e0.total;
        o[v].runs = S.tp_runs; o[v].steps = steps;
        o[v].ns_med = median(ns[v], S.tp_runs);
        o[v].ns_cpu = median(nc[v], S.tp_runs);
        o[v].ns_min = o[v].ns_max = ns[v][0];
        for (r = 1; r < S.tp_runs; r++) { o[v].ns_min = fmin(o[v].ns_min, ns[v][r]); o[v].ns_max = fmax(o[v].ns_max, ns[v][r]); }
    }
    rc = 0;
done:
    for (v = 0; v < 3; v++) { rj_state_destroy(s[v], NULL); rj_model_destroy(m[v], NULL); }
    return rc;
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
    char msg[800];
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
    o.energy_every = 16;   /* as build/deploy: the same history, the accounts every 16th step */
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
    char msg[800];
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

/* ================================================================== 4. fidelity */
/* Which link model for which job: the deployment (paper sec. 5) and the solar array
   scene (examples/scenes/solar_array.rjs) at each link model, timed (rj_run without
   sampling, median of 5 runs, or 21 below 10 ms) and compared with a converged flexible
   reference (a separate run sampled every 1 ms). */
#define F_NJ 4                                 /* the solar array's hinges */
#define F_NS 8001                              /* 1 ms samples, t = 0 .. 8 s */
#define F_FRAME 0.033                          /* s, one frame at 30 frames/s */
#define F_MAXROWS 16

typedef struct shist {
    int n;
    double q[F_NJ][F_NS];                      /* deg, running angles moved to exactly k ms with the rates */
    double tip[F_NS];                          /* m, last panel's tip from the hub's axis (root tangent of the hub) */
    double d4[F_NS];                           /* m, last panel's own bending: its tip from its root tangent */
    unsigned char have[F_NS];
} shist;

typedef struct smet {
    double lock[F_NJ];                         /* s, rj_joint_event_time, -1 if never */
    double tw0;                                /* s, start of the post-lock window: 0.3 s after the last lock */
    double tip_sd, tip_mean, tip_freq;         /* m, m, Hz over the post-lock window */
    double d4_sd, d4_freq;
    double drift;                              /* deg/s, largest |least-squares slope| of a hinge angle over the window */
} smet;
typedef struct serr {
    double dq;                                 /* deg, before the reference's first lock */
    double dlock[F_NJ];                        /* s */
    double tip_sd, tip_freq, d4_sd;            /* relative */
} serr;

typedef struct frow {
    /* what */
    const char *level;                         /* "flexible", "inextensible", "rigid" */
    const char *note;                          /* short qualifier, e.g. "paper's settings" */
    int fid, el, method, hub_inext, hub_rigid, paper;
    double dt_req, K_req;                      /* s (0 = automatic, < 0: that fraction of the automatic dt); N m/rad for penalty (deployment, non-flexible) */
    double dt_frac;                            /* > 0: dt_req was this fraction of the automatic dt */
    /* results */
    int ok, runs, refused;                     /* refused: rj_model_create said no */
    long steps;
    double dt, bound, K, wall, cpu, last_lock;
    char msg[800];
    dmet dm; derr de;                          /* deployment */
    smet sm; serr se;                          /* solar array */
} frow;

typedef struct fconv {                         /* a reference and its two checks */
    const char *what;
    int el[3]; double dt[3], wall[3];
    double dq[2], dlock[2], rms[2], freq[2];   /* checks against the reference: max |lock diff| */
} fconv;

static struct {
    int ran;
    double d_tend, s_tend;                     /* s */
    frow d[F_MAXROWS], s[F_MAXROWS];
    int nd, ns;
    fconv dconv, sconv;
    int d_ref_from_sweep;                      /* 1: section 2's reference reused */
    double d_ref_lock[2], d_ref_rms, d_ref_freq, s_ref_tw0, s_ref_drift, s_ref_frac;
    double s_ref_lock[F_NJ], s_ref_tip_sd, s_ref_tip_freq, s_ref_d4_sd, s_ref_tip_mean;
    int s_first;                               /* hinge that locks first in the reference */
    char s_path[512], s_err[900];
    char s_hinge[F_NJ][RJ_SCENE_NAME_MAX];
    double wall_section;
} F;

static rj_scene_file F_SOLAR;
static int F_HUB = -1, F_LAST = -1;
static const char *f_row_name(const frow *r, char *b, size_t n, int solar);

/* mean, RMS about the mean and dominant frequency over samples k0..k1. The frequency counts
   zero crossings of d - mean with hysteresis: a crossing counts once the signal has gone
   beyond +-0.3 RMS on the other side, so the ripple of higher modes near zero (the solar
   array's tip carries some) does not add crossings. */
static void series_stats(const unsigned char *have, const double *d, int n, int k0, int k1, double *mean, double *sd, double *freq)
{
    double sum = 0, sum2 = 0, mu, h, tfirst = -1, tlast = -1, prev = 0, lastz = -1;
    int k, cnt = 0, nc = 0, haveprev = 0, side = 0;
    for (k = k0; k <= k1 && k < n; k++) if (have[k]) { sum += d[k]; cnt++; }
    if (cnt < 2) { *mean = *sd = *freq = NAN; return; }
    mu = sum / cnt;
    for (k = k0; k <= k1 && k < n; k++) if (have[k]) sum2 += (d[k] - mu) * (d[k] - mu);
    *mean = mu;
    *sd = sqrt(sum2 / cnt);
    h = 0.3 * *sd;
    for (k = k0; k <= k1 && k < n; k++) {
        double v;
        if (!have[k]) continue;
        v = d[k] - mu;
        if (haveprev && ((prev < 0 && v >= 0) || (prev >= 0 && v < 0))) lastz = 1e-3 * (k - 1) + 1e-3 * prev / (prev - v);
        if ((v > h && side < 0) || (v < -h && side > 0)) {
            if (tfirst < 0) tfirst = lastz;
            tlast = lastz;
            nc++;
        }
        if (v > h) side = 1;
        else if (v < -h) side = -1;
        prev = v; haveprev = 1;
    }
    *freq = nc >= 3 && *sd > 1e-9 && tlast > tfirst ? (nc - 1) / (2.0 * (tlast - tfirst)) : NAN;
}

/* tip of link lt from the root tangent of link lr (node 0's position and rotation) */
static double defl_from(const rj_model *m, const rj_state *s, int lr, int lt)
{
    double p0[2], pt[2], ph = rj_node_rotation(m, s, lr, 0);
    rj_node_position(m, s, lr, 0, p0);
    rj_node_position(m, s, lt, rj_link_node_count(m, lt) - 1, pt);
    return cos(ph) * (pt[1] - p0[1]) - sin(ph) * (pt[0] - p0[0]);
}

static int s_sample(const rj_model *m, const rj_state *s, void *u)
{
    shist *h = (shist *)u;
    double t = rj_state_time(s), dtk;
    int k = (int)floor(t * 1000.0 + 0.5), j;
    if (k < 0 || k >= F_NS) return 0;
    dtk = 1e-3 * k - t;
    for (j = 0; j < F_NJ; j++) h->q[j][k] = rj_deg(rj_joint_theta_running(m, s, j)) + rj_deg(rj_joint_rate(m, s, j)) * dtk;
    h->tip[k] = defl_from(m, s, F_HUB, F_LAST);
    h->d4[k] = tip_defl_tangent(m, s, F_LAST);
    h->have[k] = 1;
    if (k + 1 > h->n) h->n = k + 1;
    return 0;
}

static void s_locks(const rj_model *m, const rj_state *s, smet *o)
{
    int j;
    for (j = 0; j < F_NJ; j++) o->lock[j] = rj_joint_event_time(m, s, j);
}

/* vibration over the post-lock window: from 0.3 s after this run's last lock (rounded up to
   0.1 s) to the end; none when a hinge never locks or the window is shorter than 1 s */
static void s_window(const shist *h, smet *o)
{
    int j, k0, k1 = (int)floor(F.s_tend * 1000 + 0.5);
    double last = 0, mu;
    for (j = 0; j < F_NJ; j++) last = o->lock[j] < 0 ? HUGE_VAL : fmax(last, o->lock[j]);
    o->tw0 = ceil((last + 0.3) * 10.0) / 10.0;
    o->tip_sd = o->tip_mean = o->tip_freq = o->d4_sd = o->d4_freq = o->drift = NAN;
    if (!(o->tw0 <= F.s_tend - 1.0)) return;
    k0 = (int)floor(o->tw0 * 1000 + 0.5);
    series_stats(h->have, h->tip, h->n, k0, k1, &o->tip_mean, &o->tip_sd, &o->tip_freq);
    series_stats(h->have, h->d4, h->n, k0, k1, &mu, &o->d4_sd, &o->d4_freq);
    /* every hinge is latched in the window: its angle may vibrate, but should not drift */
    o->drift = 0;
    for (j = 0; j < F_NJ; j++) {
        double st = 0, sq = 0, stt = 0, stq = 0, cnt = 0, t;
        int k;
        for (k = k0; k <= k1 && k < h->n; k++) {
            if (!h->have[k]) continue;
            t = 1e-3 * k;
            st += t; sq += h->q[j][k]; stt += t * t; stq += t * h->q[j][k]; cnt++;
        }
        if (cnt > 2) o->drift = fmax(o->drift, fabs((cnt * stq - st * sq) / (cnt * stt - st * st)));
    }
}

static void s_errors(const shist *h, const smet *m, const shist *rh, const smet *rm, serr *e)
{
    int j, k;
    double tpre = rm->lock[F.s_first] - 0.01;
    e->dq = 0;
    for (k = 0; k < h->n && k < rh->n && 1e-3 * k < tpre; k++) {
        if (!h->have[k] || !rh->have[k]) continue;
        for (j = 0; j < F_NJ; j++) e->dq = fmax(e->dq, fabs(h->q[j][k] - rh->q[j][k]));
    }
    for (j = 0; j < F_NJ; j++) e->dlock[j] = m->lock[j] >= 0 && rm->lock[j] >= 0 ? m->lock[j] - rm->lock[j] : NAN;
    e->tip_sd = m->tip_sd / rm->tip_sd - 1;
    e->tip_freq = m->tip_freq / rm->tip_freq - 1;
    e->d4_sd = m->d4_sd / rm->d4_sd - 1;
}

static double s_max_dlock(const serr *e)
{
    double w = 0;
    int j;
    for (j = 0; j < F_NJ; j++) w = isnan(e->dlock[j]) ? HUGE_VAL : fmax(w, fabs(e->dlock[j]));
    return w;
}

/* the deployment at a row's link model */
static rj_result f_deploy_build(const frow *r, rj_model **m, rj_error *err)
{
    deploy_opts o = deploy_default_opts();
    rj_link_def L[2]; rj_joint_def J[2]; rj_scene_def sc;
    o.elements = r->el; o.dt = r->dt_req; o.joint2_method = r->method;
    o.energy_every = 16;   /* as build/deploy */
    if (r->fid == RJ_LINK_FLEXIBLE) return deploy_build(&o, m, err);
    /* as build/deploy --links rigid|inextensible */
    deploy_scene(&o, L, J, &sc);
    L[0].fidelity = L[1].fidelity = r->fid;
    if (r->fid == RJ_LINK_RIGID) L[0].elements = L[1].elements = 1;
    J[1].method = r->method; J[1].restitution = 0.0;
    if (r->method == RJ_METHOD_PENALTY) J[1].penalty_k = r->K_req;
    return rj_model_create(&sc, m, err, NULL);
}

/* the solar array at a row's link model: panels get r->el elements and r->fid; the hub
   (one element, root fixed) stays flexible unless the row is rigid or hub_inext is set;
   r->method < 0 keeps the file's hinge method */
static rj_result f_solar_build(const frow *r, rj_model **m, rj_error *err)
{
    rj_link_def L[RJ_SCENE_MAX_LINKS]; rj_joint_def J[RJ_SCENE_MAX_JOINTS];
    rj_scene_def sc = rj_scene_file_def(&F_SOLAR);
    int i;
    for (i = 0; i < sc.link_count; i++) {
        L[i] = F_SOLAR.links[i];
        if (i != F_HUB) { L[i].elements = r->el; L[i].fidelity = r->fid; }
        else if (r->fid == RJ_LINK_RIGID || r->hub_inext) L[i].fidelity = r->fid;
        else if (r->hub_rigid) L[i].fidelity = RJ_LINK_RIGID;   /* a mixed scene: rigid hub, flexible panels */
        if (r->fid == RJ_LINK_RIGID) L[i].elements = 1;
    }
    for (i = 0; i < sc.joint_count; i++) {
        J[i] = F_SOLAR.joints[i];
        if (r->method >= 0) { J[i].method = r->method; J[i].restitution = 0.0; }
    }
    sc.links = L; sc.joints = J;
    sc.solver.dt = r->dt_req;
    return rj_model_create(&sc, m, err, NULL);
}

/* One row: a sampled run for the errors, then timed runs without sampling. */
static void f_run(frow *r, int solar, void *hist, const void *rhist, const void *rmet, int ref)
{
    rj_model *m; rj_state *s; rj_error err; rj_result res;
    double w[32], cw[32], t_end = solar ? F.s_tend : F.d_tend;
    int k, nr;
    r->ok = 0; r->runs = 0; r->msg[0] = 0;
    if (r->dt_req < 0) {
        /* a fraction of the automatic dt */
        frow probe = *r;
        probe.dt_req = 0;
        res = solar ? f_solar_build(&probe, &m, &err) : f_deploy_build(&probe, &m, &err);
        if (res != RJ_OK) { r->refused = 1; snprintf(r->msg, sizeof r->msg, "%s: %s", rj_result_str(res), err.msg); return; }
        r->dt_frac = -r->dt_req;
        r->dt_req = r->dt_frac * rj_model_dt(m);
        rj_model_destroy(m, NULL);
    }
    res = solar ? f_solar_build(r, &m, &err) : f_deploy_build(r, &m, &err);
    if (res != RJ_OK) { r->refused = 1; snprintf(r->msg, sizeof r->msg, "%s: %s", rj_result_str(res), err.msg); return; }
    if (rj_state_create(m, &s, NULL) != RJ_OK) { rj_model_destroy(m, NULL); snprintf(r->msg, sizeof r->msg, "no memory"); return; }
    r->dt = rj_model_dt(m); r->bound = rj_model_dt_bound(m);
    r->K = rj_joint_stiffness(m, solar ? 0 : 1);
    w[0] = now(); cw[0] = cpu_now();
    if (solar) { memset(hist, 0, sizeof(shist)); res = rj_run(m, s, t_end, 1e-3, s_sample, hist); }
    else { memset(hist, 0, sizeof(dhist)); res = rj_run(m, s, t_end, 1e-3, d_sample, hist); }
    w[0] = now() - w[0]; cw[0] = cpu_now() - cw[0];
    if (res != RJ_OK) {
        snprintf(r->msg, sizeof r->msg, "%s: %s", rj_result_str(res), rj_state_error(s));
        rj_state_destroy(s, NULL); rj_model_destroy(m, NULL);
        return;
    }
    r->steps = rj_state_steps(s);
    if (solar) {
        int j;
        s_locks(m, s, &r->sm);
        s_window((const shist *)hist, &r->sm);
        r->last_lock = 0;
        for (j = 0; j < F_NJ; j++) r->last_lock = r->sm.lock[j] < 0 ? HUGE_VAL : fmax(r->last_lock, r->sm.lock[j]);
        if (rhist) s_errors((const shist *)hist, &r->sm, (const shist *)rhist, (const smet *)rmet, &r->se);
    } else {
        d_metrics((const dhist *)hist, rj_joint_event_time(m, s, 0), rj_joint_event_time(m, s, 1), &r->dm);
        if (rhist) d_errors((const dhist *)hist, &r->dm, (const dhist *)rhist, (const dmet *)rmet, &r->de);
    }
    /* a reference is timed once, with its sampling */
    if (ref) { r->ok = 1; r->runs = 1; r->wall = w[0]; r->cpu = cw[0]; rj_state_destroy(s, NULL); rj_model_destroy(m, NULL); return; }
    nr = 1;
    for (k = 0; k < nr && k < 32; k++) {
        double t0, c0;
        rj_state_reset(m, s);
        t0 = now(); c0 = cpu_now();
        res = rj_run(m, s, t_end, 0, NULL, NULL);
        w[k] = now() - t0; cw[k] = cpu_now() - c0;
        if (res != RJ_OK) { snprintf(r->msg, sizeof r->msg, "%s: %s", rj_result_str(res), rj_state_error(s)); break; }
        if (k == 0) nr = S.quick ? (w[0] < 0.05 ? 3 : 1) : (w[0] < 0.01 ? 21 : 5);
    }
    if (k == nr) { r->ok = 1; r->runs = nr; r->wall = median(w, nr); r->cpu = median(cw, nr); }
    rj_state_destroy(s, NULL); rj_model_destroy(m, NULL);
}

static frow *f_add(frow *rows, int *n, const char *level, const char *note_, int fid, int el, int method, double dt, double K)
{
    frow *r = &rows[(*n)++];
    memset(r, 0, sizeof *r);
    r->level = level; r->note = note_; r->fid = fid; r->el = el; r->method = method; r->dt_req = dt; r->K_req = K;
    return r;
}

/* rigid2 lock times (the deployment's dq window ends 10 ms before the rigid joint 2 lock) */
static int rigid_locks(void)
{
    double lr[2];
    rigid2_params rp;
    rigid2_default_params(&rp);
    if (rigid2_run(&rp, 6.0, 1e-2, r2_cb, NULL, lr) != RIGID2_OK) { fputs("bench: rigid reference failed\n", stderr); return -1; }
    D_RIGID_LOCK[0] = lr[0]; D_RIGID_LOCK[1] = lr[1];
    D_TPRE = lr[1] - 0.01;
    return 0;
}

/* The deployment reference (adaptive, S.d_ref_el elements per link, 0.9 x bound / S.d_ref_div) and
   its checks: the same mesh at twice the step, half the mesh at the same fraction of its bound. */
static int deploy_reference(drow *dref, dhist *href, drow dchk[2], dhist *hchk)
{
    int i;
    memset(dref, 0, sizeof *dref); memset(dchk, 0, 2 * sizeof *dchk);
    dref->method = RJ_METHOD_ADAPTIVE; dref->el = S.d_ref_el; dref->dt = d_top_dt(RJ_METHOD_ADAPTIVE, S.d_ref_el) / S.d_ref_div;
    if (dref->dt <= 0) return -1;
    d_run(dref, href, NULL, NULL, 1);
    if (!dref->ok) { fprintf(stderr, "bench: deployment reference: %s\n", dref->msg); return -1; }
    progress("deployment reference %d el dt %.4g us: %.1f s; joint 2 locks at %.6f s", dref->el, dref->dt * 1e6, dref->wall, dref->m.lock2);
    dchk[0] = *dref; dchk[0].dt = dref->dt * 2;
    dchk[1] = *dref; dchk[1].el = S.d_ref_el / 2; dchk[1].dt = d_top_dt(RJ_METHOD_ADAPTIVE, S.d_ref_el / 2) / S.d_ref_div;
    for (i = 0; i < 2; i++) {
        d_run(&dchk[i], hchk, href, &dref->m, 1);
        if (!dchk[i].ok) { fprintf(stderr, "bench: deployment reference check: %s\n", dchk[i].msg); return -1; }
        progress("  check %d el dt %.4g us: max |dq| %.4f deg, lock %+.3g s, rms %+.3f%% / %+.3f%%", dchk[i].el, dchk[i].dt * 1e6, dchk[i].e.dq, dchk[i].e.dlock, 100 * dchk[i].e.rms_c, 100 * dchk[i].e.rms_t);
    }
    return 0;
}

static int f_solar_load(const char *argv0)
{
    rj_error err;
    char cand[2][400];
    const char *slash = strrchr(argv0, '/');
    int i, j;
    snprintf(cand[0], sizeof cand[0], "examples/scenes/solar_array.rjs");
    snprintf(cand[1], sizeof cand[1], "%.*s/../examples/scenes/solar_array.rjs", slash ? (int)(slash - argv0) : 1, slash ? argv0 : ".");
    for (i = 0; i < 2; i++) {
        if (rj_scene_load(cand[i], &F_SOLAR, &err) == RJ_OK) {
            snprintf(F.s_path, sizeof F.s_path, "%.380s", cand[i]);
            F_HUB = rj_scene_link_index(&F_SOLAR, "hub");
            F_LAST = rj_scene_link_index(&F_SOLAR, "p4");
            if (F_HUB < 0 || F_LAST < 0 || F_SOLAR.joint_count != F_NJ) {
                snprintf(F.s_err, sizeof F.s_err, "%.380s: expected links 'hub' and 'p4' and %d joints", cand[i], F_NJ);
                rj_scene_file_free(&F_SOLAR);
                return -1;
            }
            for (j = 0; j < F_NJ; j++) snprintf(F.s_hinge[j], sizeof F.s_hinge[j], "%s", F_SOLAR.joint_names[j]);
            return 0;
        }
        snprintf(F.s_err, sizeof F.s_err, "%s", err.msg);
    }
    return -1;
}

/* href/dref/dchk: a converged deployment reference with its two checks (section 2's in a full
   run; computed here with --only) */
/* Section 4 on a work-precision plot: every deployment row that ran, CPU time against its
   error, one colour per link model; which = 0: joint angles before the latch (deg), 1: link
   2's post-lock tip RMS (|%|; rigid rows have no vibration and are left out). */
static int fidelity_plot(rjr_context *ctx, const char *path, int which, char *err, size_t errlen)
{
    static double x[3][32], y[3][32], tx[2], ty[2];
    static const char *const name[3] = { "flexible", "rigid (joint coordinates)", "inextensible" };
    static const rjr_rgb col[3] = { 0xd62728, 0x1f77b4, 0x2ca02c };
    rjr_plot_def p = rjr_plot_default();
    int i, k, n[3] = { 0, 0, 0 }, ns = 0;
    double xmin = HUGE_VAL, xmax = 0, ymin = HUGE_VAL, ymax = 0, crit = which ? 2.0 : 0.1;
    for (i = 0; i < F.nd; i++) {
        const frow *r = &F.d[i];
        double v;
        if (!r->ok || r->fid < 0 || r->fid > 2 || n[r->fid] >= 32) continue;
        if (which && r->fid == RJ_LINK_RIGID) continue;
        v = which ? 100 * fabs(r->de.rms_t) : r->de.dq;
        if (!(v > 0) || !isfinite(v)) continue;
        x[r->fid][n[r->fid]] = r->cpu; y[r->fid][n[r->fid]] = v; n[r->fid]++;
        xmin = fmin(xmin, r->cpu); xmax = fmax(xmax, r->cpu); ymin = fmin(ymin, v); ymax = fmax(ymax, v);
    }
    for (k = 0; k < 3; k++) if (n[k]) {
        p.series[ns].x = x[k]; p.series[ns].y = y[k]; p.series[ns].n = n[k]; p.series[ns].label = name[k];
        p.series[ns].colour = col[k]; p.series[ns].points = 1; p.series[ns].no_line = 1; p.series[ns].width_px = 4; ns++;
    }
    if (!ns) { snprintf(err, errlen, "no fidelity rows ran"); return -1; }
    tx[0] = pow(10.0, floor(log10(xmin))); tx[1] = pow(10.0, ceil(log10(xmax * 1.2))); ty[0] = ty[1] = crit;
    p.series[ns].x = tx; p.series[ns].y = ty; p.series[ns].n = 2; p.series[ns].label = which ? "criterion: 2 %" : "criterion: 0.1 deg";
    p.series[ns].colour = 0x555555; p.series[ns].dashed = 1; ns++;
    p.series_count = ns;
    p.title = which ? "Deployment by link model: link 2 tip RMS after the latch" : "Deployment by link model: q1, q2 before joint 2 latches";
    p.xlabel = "CPU time of the 6 s run (s)"; p.ylabel = which ? "abs(RMS / RMS_ref - 1) (%)" : "max abs(q - q_ref) (deg)";
    p.logx = p.logy = 1;
    ymin = fmin(ymin, crit); ymax = fmax(ymax, crit);
    p.ymin = pow(10.0, floor(log10(ymin)) - 1); p.ymax = pow(10.0, ceil(log10(ymax * 1.5)));
    p.xmin = tx[0]; p.xmax = tx[1];
    p.legend = RJR_LEGEND_BOTTOM_LEFT;
    if (rjr_plot(ctx, &p) || rjr_save_png(ctx, path, err, errlen)) {
        if (!err[0]) snprintf(err, errlen, "%s", rjr_error(ctx));
        return -1;
    }
    return 0;
}

/* section 4 as work-precision plots next to the others: FILE_fidelity.png, FILE_fidelity_tip.png */
static int fidelity_plots(const char *plot)
{
    char err[512] = "", p1[600], p2[600];
    const char *dot = strrchr(plot, '.');
    size_t stem = dot && dot > strrchr(plot, '/') ? (size_t)(dot - plot) : strlen(plot);
    rjr_context *ctx = rjr_create(960, 720, err, sizeof err);
    int bad = 0;
    snprintf(p1, sizeof p1, "%.*s_fidelity.png", (int)stem, plot);
    snprintf(p2, sizeof p2, "%.*s_fidelity_tip.png", (int)stem, plot);
    if (!ctx) { fprintf(stderr, "bench: plot: %s\n", err); return 1; }
    if (fidelity_plot(ctx, p1, 0, err, sizeof err)) { fprintf(stderr, "bench: %s: %s\n", p1, err); bad = 1; }
    err[0] = 0;
    if (fidelity_plot(ctx, p2, 1, err, sizeof err)) { fprintf(stderr, "bench: %s: %s\n", p2, err); bad = 1; }
    rjr_destroy(ctx);
    return bad;
}

static int fidelity_section(const dhist *href, const drow *dref, const drow dchk[2], int ref_from_sweep, const char *argv0)
{
    static dhist H;
    static shist SH, SREF, SCHK;
    double t0 = now();
    int i, j;
    frow sref, schk[2];
    memset(&F, 0, sizeof F);
    F.ran = 1;
    F.d_tend = S.d_tend;
    F.d_ref_from_sweep = ref_from_sweep;
    /* ---- deployment */
    F.dconv.what = "deployment";
    F.dconv.el[0] = dref->el; F.dconv.dt[0] = dref->dt; F.dconv.wall[0] = dref->wall;
    for (i = 0; i < 2; i++) {
        F.dconv.el[i + 1] = dchk[i].el; F.dconv.dt[i + 1] = dchk[i].dt; F.dconv.wall[i + 1] = dchk[i].wall;
        F.dconv.dq[i] = dchk[i].e.dq; F.dconv.dlock[i] = fmax(fabs(dchk[i].e.dlock), fabs(dchk[i].e.dlock1));
        F.dconv.rms[i] = dchk[i].e.rms_t; F.dconv.freq[i] = dchk[i].e.freq_t;
    }
    F.d_ref_lock[0] = dref->m.lock1; F.d_ref_lock[1] = dref->m.lock2; F.d_ref_rms = dref->m.rms_t; F.d_ref_freq = dref->m.freq_t;
    f_add(F.d, &F.nd, "flexible", "paper's settings", RJ_LINK_FLEXIBLE, 10, RJ_METHOD_PENALTY, 7.5e-6, 0)->paper = 1;
    f_add(F.d, &F.nd, "flexible", "automatic dt", RJ_LINK_FLEXIBLE, 10, RJ_METHOD_PENALTY, 0, 0);
    f_add(F.d, &F.nd, "flexible", "automatic dt", RJ_LINK_FLEXIBLE, 10, RJ_METHOD_ADAPTIVE, 0, 0);
    f_add(F.d, &F.nd, "inextensible", "automatic dt", RJ_LINK_INEXTENSIBLE, 10, RJ_METHOD_MOMENTUM, 0, 0);
    f_add(F.d, &F.nd, "inextensible", "automatic dt", RJ_LINK_INEXTENSIBLE, 10, RJ_METHOD_ADAPTIVE, 0, 0);
    f_add(F.d, &F.nd, "inextensible", "automatic dt", RJ_LINK_INEXTENSIBLE, 5, RJ_METHOD_MOMENTUM, 0, 0);
    f_add(F.d, &F.nd, "inextensible", "automatic dt", RJ_LINK_INEXTENSIBLE, 5, RJ_METHOD_ADAPTIVE, 0, 0);
    f_add(F.d, &F.nd, "rigid", "", RJ_LINK_RIGID, 1, RJ_METHOD_MOMENTUM, 2e-3, 0);
    f_add(F.d, &F.nd, "rigid", "", RJ_LINK_RIGID, 1, RJ_METHOD_MOMENTUM, 1e-3, 0);
    f_add(F.d, &F.nd, "rigid", "", RJ_LINK_RIGID, 1, RJ_METHOD_MOMENTUM, 2.5e-4, 0);
    f_add(F.d, &F.nd, "rigid", "", RJ_LINK_RIGID, 1, RJ_METHOD_ADAPTIVE, 1e-3, 0);
    f_add(F.d, &F.nd, "rigid", "", RJ_LINK_RIGID, 1, RJ_METHOD_PENALTY, 1e-3, 1015.0);
    for (i = 0; i < F.nd; i++) {
        frow *r = &F.d[i];
        f_run(r, 0, &H, href, &dref->m, 0);
        progress("fidelity deploy %-12s %2d el %-8s dt %8.4g us: %s wall %.4f s (%d runs) dq %.4f deg lock2 %+.2f ms lock1 %+.2f ms rms %+.2f%% freq %+.2f%%",
                 r->level, r->el, method_name(r->method), r->dt * 1e6, r->ok ? "ok" : r->msg, r->wall, r->runs, r->de.dq, 1e3 * r->de.dlock, 1e3 * r->de.dlock1,
                 100 * r->de.rms_t, 100 * r->de.freq_t);
    }
    /* ---- solar array */
    F.s_tend = S.quick ? 6.0 : 8.0;
    if (f_solar_load(argv0)) { progress("fidelity: solar array not loaded: %s", F.s_err); F.wall_section = now() - t0; return 0; }
    /* reference: flexible, 4 x the file's 4 elements per panel, at a quarter of the automatic dt
       (0.225 x the bound: the latched hinges' adaptive stiffness grows as 1/dt^2, and the post-lock
       vibration converges with dt more slowly than with the mesh); checks at twice its step and half its mesh */
    memset(&sref, 0, sizeof sref); memset(schk, 0, sizeof schk);
    sref.level = "flexible"; sref.fid = RJ_LINK_FLEXIBLE; sref.method = -1; sref.el = S.quick ? 8 : 16;
    {
        rj_model *m; rj_error err;
        frow probe = sref;
        if (f_solar_build(&probe, &m, &err) != RJ_OK) { snprintf(F.s_err, sizeof F.s_err, "%s", err.msg); F.wall_section = now() - t0; return 0; }
        sref.dt_req = 0.25 * rj_model_dt(m);
        rj_model_destroy(m, NULL);
        probe.el = sref.el / 2;
        if (f_solar_build(&probe, &m, &err) != RJ_OK) { snprintf(F.s_err, sizeof F.s_err, "%s", err.msg); F.wall_section = now() - t0; return 0; }
        schk[1] = sref; schk[1].el = sref.el / 2; schk[1].dt_req = 0.25 * rj_model_dt(m);
        rj_model_destroy(m, NULL);
        schk[0] = sref; schk[0].dt_req = 2 * sref.dt_req;
    }
    f_run(&sref, 1, &SREF, NULL, NULL, 1);
    if (!sref.ok) { snprintf(F.s_err, sizeof F.s_err, "reference: %s", sref.msg); F.wall_section = now() - t0; return 0; }
    F.s_first = 0;
    for (j = 0; j < F_NJ; j++) {
        F.s_ref_lock[j] = sref.sm.lock[j];
        if (sref.sm.lock[j] < sref.sm.lock[F.s_first]) F.s_first = j;
    }
    if (!(sref.sm.tip_sd > 0)) { snprintf(F.s_err, sizeof F.s_err, "reference: no post-lock window (last lock %.3f s, run to %.1f s)", sref.last_lock, F.s_tend); F.wall_section = now() - t0; return 0; }
    F.s_ref_tw0 = sref.sm.tw0; F.s_ref_drift = sref.sm.drift; F.s_ref_frac = sref.dt / sref.bound;
    F.s_ref_tip_sd = sref.sm.tip_sd; F.s_ref_tip_freq = sref.sm.tip_freq; F.s_ref_d4_sd = sref.sm.d4_sd; F.s_ref_tip_mean = sref.sm.tip_mean;
    progress("solar reference %d el/panel dt %.4g us: %.1f s; locks %.4f %.4f %.4f %.4f s; tip RMS %.4g m at %.4g Hz", sref.el, sref.dt * 1e6, sref.wall,
             sref.sm.lock[0], sref.sm.lock[1], sref.sm.lock[2], sref.sm.lock[3], sref.sm.tip_sd, sref.sm.tip_freq);
    F.sconv.what = "solar array";
    F.sconv.el[0] = sref.el; F.sconv.dt[0] = sref.dt; F.sconv.wall[0] = sref.wall;
    for (i = 0; i < 2; i++) {
        f_run(&schk[i], 1, &SCHK, &SREF, &sref.sm, 1);
        if (!schk[i].ok) { snprintf(F.s_err, sizeof F.s_err, "reference check: %s", schk[i].msg); F.wall_section = now() - t0; return 0; }
        F.sconv.el[i + 1] = schk[i].el; F.sconv.dt[i + 1] = schk[i].dt; F.sconv.wall[i + 1] = schk[i].wall;
        F.sconv.dq[i] = schk[i].se.dq; F.sconv.dlock[i] = s_max_dlock(&schk[i].se);
        F.sconv.rms[i] = schk[i].se.tip_sd; F.sconv.freq[i] = schk[i].se.tip_freq;
        progress("  check %d el dt %.4g us: dq %.4f deg, locks within %.3f ms, tip RMS %+.2f%%, freq %+.2f%%", schk[i].el, schk[i].dt * 1e6, schk[i].se.dq,
                 1e3 * F.sconv.dlock[i], 100 * schk[i].se.tip_sd, 100 * schk[i].se.tip_freq);
    }
    f_add(F.s, &F.ns, "flexible", "the file as written", RJ_LINK_FLEXIBLE, F_SOLAR.links[F_LAST].elements, -1, 0, 0)->paper = 1;
    f_add(F.s, &F.ns, "flexible", "the file's mesh, a quarter of the automatic dt", RJ_LINK_FLEXIBLE, F_SOLAR.links[F_LAST].elements, -1, -0.25, 0);
    f_add(F.s, &F.ns, "flexible", "automatic dt", RJ_LINK_FLEXIBLE, 5, -1, 0, 0);
    f_add(F.s, &F.ns, "flexible", "automatic dt", RJ_LINK_FLEXIBLE, 10, -1, 0, 0);
    f_add(F.s, &F.ns, "inextensible", "panels; hub flexible", RJ_LINK_INEXTENSIBLE, 5, -1, 0, 0);
    f_add(F.s, &F.ns, "inextensible", "panels; hub flexible", RJ_LINK_INEXTENSIBLE, 10, -1, 0, 0);
    f_add(F.s, &F.ns, "inextensible", "hub too", RJ_LINK_INEXTENSIBLE, 10, -1, 0, 0)->hub_inext = 1;
    f_add(F.s, &F.ns, "flexible", "panels; hub rigid (mixed)", RJ_LINK_FLEXIBLE, F_SOLAR.links[F_LAST].elements, -1, 0, 0)->hub_rigid = 1;
    f_add(F.s, &F.ns, "inextensible", "panels; hub rigid (mixed)", RJ_LINK_INEXTENSIBLE, 10, -1, 0, 0)->hub_rigid = 1;
    f_add(F.s, &F.ns, "rigid", "", RJ_LINK_RIGID, 1, RJ_METHOD_MOMENTUM, 1e-3, 0);
    f_add(F.s, &F.ns, "rigid", "", RJ_LINK_RIGID, 1, RJ_METHOD_MOMENTUM, 2.5e-4, 0);
    f_add(F.s, &F.ns, "rigid", "the file's method", RJ_LINK_RIGID, 1, -1, 1e-3, 0);
    f_add(F.s, &F.ns, "rigid", "the file's method, automatic dt", RJ_LINK_RIGID, 1, -1, 0, 0);
    for (i = 0; i < F.ns; i++) {
        frow *r = &F.s[i];
        f_run(r, 1, &SH, &SREF, &sref.sm, 0);
        progress("fidelity solar  %-12s %2d el %-8s dt %8.4g us: %s wall %.4f s (%d runs) dq %.4f deg locks within %.2f ms tip rms %+.2f%% freq %+.2f%%",
                 r->level, r->el, r->method < 0 ? "file" : method_name(r->method), r->dt * 1e6, r->ok ? "ok" : r->msg, r->wall, r->runs, r->se.dq,
                 1e3 * s_max_dlock(&r->se), 100 * r->se.tip_sd, 100 * r->se.tip_freq);
    }
    for (i = 0; i < F.ns; i++) {
        const frow *r = &F.s[i];
        char b1[300];
        if (r->ok && r->fid == RJ_LINK_RIGID && r->sm.drift > 0.01)
            note("solar array, %s: every hinge reports RJ_LOCKED after %.3f s, yet the latched hinges keep turning at up to %.3g deg/s to the end of the run (the flexible reference's latched hinges: %.2g deg/s). "
                 "In a rigid chain a momentum latch does not hold a joint that another joint's latch impulse later sets moving.", f_row_name(r, b1, sizeof b1, 1), r->last_lock, r->sm.drift, F.s_ref_drift);
    }
    for (i = 0; i < F.nd + F.ns; i++) {
        const frow *r = i < F.nd ? &F.d[i] : &F.s[i - F.nd];
        char b1[300];
        if (!r->ok) note("%s, %s: %s: %s", i < F.nd ? "deployment" : "solar array", f_row_name(r, b1, sizeof b1, i >= F.nd), r->refused ? "refused" : "fails", r->msg);
    }
    F.wall_section = now() - t0;
    return 0;
}

/* ------------------------------------------------------------------ fidelity: report */
static const char *f_method_label(const frow *r, char *b, size_t n, int solar)
{
    int meth = r->method;
    if (solar && meth < 0) {
        meth = F_SOLAR.joints[0].method;
        if (meth == RJ_METHOD_ADAPTIVE) { snprintf(b, n, "adaptive (the file's)"); return b; }
        snprintf(b, n, "%s (the file's)", method_name(meth));
        return b;
    }
    switch (meth) {
    case RJ_METHOD_PENALTY:
        if (r->fid == RJ_LINK_FLEXIBLE) snprintf(b, n, "penalty, K = Eq 31 at dt%s%.4g N m/rad", r->ok || r->K > 0 ? " = " : "", r->K);
        else snprintf(b, n, "penalty, K = %.4g N m/rad (fixed)", r->K_req);
        break;
    case RJ_METHOD_MOMENTUM: snprintf(b, n, "momentum, e = 0"); break;
    case RJ_METHOD_ADAPTIVE: snprintf(b, n, "adaptive"); break;
    default: snprintf(b, n, "%s", method_name(meth)); break;
    }
    return b;
}

static const char *f_level_label(const frow *r, char *b, size_t n)
{
    snprintf(b, n, "%s%s%s%s", r->paper ? "**" : "", r->level, r->note && r->note[0] ? ", " : "", r->note ? r->note : "");
    if (r->paper) { size_t k = strlen(b); snprintf(b + k, n - k, "**"); }
    return b;
}

/* md table cell text: '|' would end the cell */
static const char *f_cell(const char *msg, char *b, size_t n)
{
    size_t i, k = 0;
    for (i = 0; msg[i] && k + 2 < n; i++) {
        if (msg[i] == '|') { b[k++] = '/'; continue; }
        if (msg[i] == '\n') { b[k++] = ' '; continue; }
        b[k++] = msg[i];
    }
    b[k] = 0;
    return b;
}

static const char *f_rel(double v, char *b, size_t n)
{
    if (isnan(v)) snprintf(b, n, "n/a");
    else snprintf(b, n, "%+.1f %%", 100 * v);
    return b;
}

static const char *f_row_name(const frow *r, char *b, size_t n, int solar)
{
    char m1[96], nt[80] = "", el[48] = "";
    if (r->note && r->note[0] && strcmp(r->note, "automatic dt") && strcmp(r->note, "the file's method, automatic dt")) snprintf(nt, sizeof nt, " (%s)", r->note);
    else if (r->note && !strcmp(r->note, "the file's method, automatic dt")) snprintf(nt, sizeof nt, " (the file's method)");
    if (r->fid != RJ_LINK_RIGID) snprintf(el, sizeof el, ", %d elements per %s", r->el, solar ? "panel" : "link");
    if (r->dt_frac > 0) snprintf(b, n, "**%s%s%s, %s, dt %.4g us**", r->level, nt, el, f_method_label(r, m1, sizeof m1, solar), 1e6 * r->dt_req);
    else if (r->dt_req > 0) snprintf(b, n, "**%s%s%s, %s, dt %.4g us**", r->level, nt, el, f_method_label(r, m1, sizeof m1, solar), 1e6 * r->dt_req);
    else if (r->dt > 0) snprintf(b, n, "**%s%s%s, %s, automatic dt = %.4g us**", r->level, nt, el, f_method_label(r, m1, sizeof m1, solar), 1e6 * r->dt);
    else snprintf(b, n, "**%s%s%s, %s, automatic dt**", r->level, nt, el, f_method_label(r, m1, sizeof m1, solar));
    return b;
}

/* cheapest (CPU time) ok row passing a criterion; crit: 0 whole sequence, 1 up to the first lock, 2 vibration */
static const frow *f_cheapest(const frow *rows, int n, int solar, int crit)
{
    const frow *b = NULL;
    int i;
    for (i = 0; i < n; i++) {
        const frow *r = &rows[i];
        int pass;
        if (!r->ok) continue;
        if (solar) {
            if (crit == 0) pass = r->se.dq < 1.0 && s_max_dlock(&r->se) < F_FRAME;
            else if (crit == 1) pass = r->se.dq < 1.0 && fabs(r->se.dlock[F.s_first]) < F_FRAME;
            else pass = r->fid != RJ_LINK_RIGID && fabs(r->se.tip_sd) < 0.05 && fabs(r->se.tip_freq) < 0.02;
        } else {
            if (crit == 0) pass = r->de.dq < 1.0 && fabs(r->de.dlock) < F_FRAME && fabs(r->de.dlock1) < F_FRAME;
            else if (crit == 1) pass = r->de.dq < 1.0 && fabs(r->de.dlock) < F_FRAME;
            else pass = r->fid != RJ_LINK_RIGID && fabs(r->de.rms_t) < 0.05 && fabs(r->de.freq_t) < 0.02;
        }
        if (pass && (!b || r->cpu < b->cpu)) b = r;
    }
    return b;
}

/* the row with the smallest worst error relative to a criterion's tolerances */
static const frow *f_closest(const frow *rows, int n, int solar, int crit)
{
    const frow *b = NULL;
    double best = HUGE_VAL;
    int i;
    for (i = 0; i < n; i++) {
        const frow *r = &rows[i];
        double w;
        if (!r->ok) continue;
        if (crit == 2 && r->fid == RJ_LINK_RIGID) continue;
        if (solar) {
            if (crit == 0) w = fmax(r->se.dq / 1.0, s_max_dlock(&r->se) / F_FRAME);
            else if (crit == 1) w = fmax(r->se.dq / 1.0, fabs(r->se.dlock[F.s_first]) / F_FRAME);
            else w = fmax(fabs(r->se.tip_sd) / 0.05, fabs(r->se.tip_freq) / 0.02);
        } else {
            if (crit == 0) w = fmax(r->de.dq / 1.0, fmax(fabs(r->de.dlock), fabs(r->de.dlock1)) / F_FRAME);
            else if (crit == 1) w = fmax(r->de.dq / 1.0, fabs(r->de.dlock) / F_FRAME);
            else w = fmax(fabs(r->de.rms_t) / 0.05, fabs(r->de.freq_t) / 0.02);
        }
        if (w < best) { best = w; b = r; }
    }
    return b;
}

static const char *f_lockstr(const serr *e)
{
    static char b[160];
    int j;
    b[0] = 0;
    for (j = 0; j < F_NJ; j++) {
        size_t k = strlen(b);
        if (isnan(e->dlock[j])) snprintf(b + k, sizeof b - k, "%snever", j ? " / " : "");
        else snprintf(b + k, sizeof b - k, "%s%+.1f", j ? " / " : "", 1e3 * e->dlock[j]);
    }
    {
        size_t k = strlen(b);
        snprintf(b + k, sizeof b - k, " ms");
    }
    return b;
}

static const frow *f_find(const frow *rows, int n, int fid, int el, int method)
{
    int i;
    for (i = 0; i < n; i++) if (rows[i].fid == fid && rows[i].el == el && rows[i].method == method && !rows[i].paper && !rows[i].hub_inext && !rows[i].hub_rigid && rows[i].dt_req == 0) return &rows[i];
    return NULL;
}

/* uncertainty of a reference from its checks: the step check plus a third of the mesh check
   (second-order mesh error: error(l) - error(l/2) = 3 error(l/2)) */
static double f_unc(const double v[2]) { return fabs(v[0]) + fabs(v[1]) / 3; }

static void f_reading(const frow *rows, int n, int solar, const frow *base, const fconv *c)
{
    static const char *const what[3] = {
        "An **animation of the whole sequence** (joint angles within 1 deg until the first latch, every latch within one frame at 30 frames/s, 33 ms)",
        "An **animation of the motion up to the first latch** (angles within 1 deg, that latch within 33 ms)",
        "A **vibration study** (post-lock tip RMS within 5 %% and its frequency within 2 %% of the reference)" };
    const char *vs = solar ? "the file as written" : "the paper's settings";
    double ulock = f_unc(c->dlock), urms = f_unc(c->rms), ufreq = f_unc(c->freq);
    char b1[300];
    int cr, i;
    for (cr = 0; cr < 3; cr++) {
        const frow *b = f_cheapest(rows, n, solar, cr);
        md("- ");
        md(what[cr]);
        if (!b) {
            const frow *c2 = f_closest(rows, n, solar, cr);
            md(" is met by none of these levels%s.", cr == 2 ? " (rigid links have no tip vibration at all)" : "");
            if (c2 && cr == 2 && solar) md(" Closest: %s (tip RMS %+.1f %%, frequency %+.1f %%).", f_row_name(c2, b1, sizeof b1, solar), 100 * c2->se.tip_sd, 100 * c2->se.tip_freq);
            else if (c2 && cr == 2) md(" Closest: %s (tip RMS %+.1f %%, frequency %+.1f %%).", f_row_name(c2, b1, sizeof b1, solar), 100 * c2->de.rms_t, 100 * c2->de.freq_t);
            else if (c2 && solar) md(" Closest: %s (dq %.3f deg, latches %s).", f_row_name(c2, b1, sizeof b1, solar), c2->se.dq, f_lockstr(&c2->se));
            else if (c2) md(" Closest: %s (dq %.3f deg, latches %+.1f / %+.1f ms).", f_row_name(c2, b1, sizeof b1, solar), c2->de.dq, 1e3 * c2->de.dlock, 1e3 * c2->de.dlock1);
        }
        else {
            double sp = base->cpu / b->cpu;
            md(" needs at least %s: %.3g s CPU, %.3g x %s than %s", f_row_name(b, b1, sizeof b1, solar), b->cpu, sp >= 1 ? sp : 1 / sp, sp >= 1 ? "faster" : "slower", vs);
            if (cr == 0 && solar) md(" (dq %.3f deg, latches within %.1f ms).", b->se.dq, 1e3 * s_max_dlock(&b->se));
            else if (cr == 1 && solar) md(" (dq %.3f deg, first latch, %s, %+.1f ms; the later ones within %.0f ms).", b->se.dq, F.s_hinge[F.s_first], 1e3 * b->se.dlock[F.s_first], 1e3 * s_max_dlock(&b->se));
            else if (cr == 0) md(" (dq %.3f deg, latches %+.1f / %+.1f ms).", b->de.dq, 1e3 * b->de.dlock, 1e3 * b->de.dlock1);
            else if (cr == 1) md(" (dq %.3f deg, joint 2 latches %+.1f ms; joint 1 %+.1f ms).", b->de.dq, 1e3 * b->de.dlock, 1e3 * b->de.dlock1);
            else if (solar) md(" (tip RMS %+.1f %%, frequency %+.1f %%).", 100 * b->se.tip_sd, 100 * b->se.tip_freq);
            else md(" (tip RMS %+.1f %%, frequency %+.1f %%).", 100 * b->de.rms_t, 100 * b->de.freq_t);
        }
        if (cr == 0 && ulock > 0.5 * F_FRAME)
            md(" Caution: the reference's own latch times are uncertain by about %.0f ms (its checks above), so this verdict rests on latch differences the reference does not resolve.", 1e3 * ulock);
        if (cr == 2 && (urms > 0.025 || ufreq > 0.01))
            md(" Caution: the reference's own amplitude and frequency are uncertain by about %.1f %% and %.1f %% (its checks above), a large part of the tolerance.", 100 * urms, 100 * ufreq);
        md("\n");
    }
    /* the paper's settings (deployment) or the file (solar array) against the criteria */
    if (base->ok) {
        int p0 = f_cheapest(base, 1, solar, 0) != NULL, p2 = f_cheapest(base, 1, solar, 2) != NULL;
        const char *who = solar ? "The file as written" : "The paper's setting";
        if (p0 && p2) md("- %s meets both the whole-sequence and the vibration criterion.\n", who);
        else if (!p0 && !p2) md("- %s meets neither the whole-sequence nor the vibration criterion.\n", who);
        else md("- %s meets the %s criterion, not the %s one.\n", who, p0 ? "whole-sequence" : "vibration", p0 ? "vibration" : "whole-sequence");
    }
    /* rigid links: the first rigid row that ran (the default method and step) */
    for (i = 0; i < n; i++) {
        const frow *r = &rows[i];
        if (!r->ok || r->fid != RJ_LINK_RIGID) continue;
        if (solar) {
            md("- Rigid links (%s) take %.3g ms CPU (%.0f x faster than %s): angles within %.2f deg of the reference before the first latch, latches within %.0f ms. "
               "With every hinge latched, nothing should move; ", f_row_name(r, b1, sizeof b1, solar), 1e3 * r->cpu, base->cpu / r->cpu, vs, r->se.dq, 1e3 * s_max_dlock(&r->se));
            if (r->sm.drift > 0.01)
                md("**here the latched hinges still turn, at up to %.3g deg/s** (the reference's latched hinges: %.2g deg/s), so the tip keeps moving (RMS %.3g m about its mean). A library bug: see the notes at the top.\n",
                   r->sm.drift, F.s_ref_drift, r->sm.tip_sd);
            else md("nothing does (drift %.2g deg/s).\n", r->sm.drift);
        }
        else
            md("- Rigid links (%s) take %.3g ms CPU (%.0f x faster than %s): q within %.2f deg of the reference before joint 2 latches, joint 2 latches %+.1f ms and joint 1 %+.1f ms from it; "
               "link 2 cannot vibrate after the latch.\n", f_row_name(r, b1, sizeof b1, solar), 1e3 * r->cpu, base->cpu / r->cpu, vs, r->de.dq, 1e3 * r->de.dlock, 1e3 * r->de.dlock1);
        break;
    }
    /* inextensible against flexible on the same mesh and joint method */
    for (i = 5; i <= 10; i += 5) {
        const frow *fx = f_find(rows, n, RJ_LINK_FLEXIBLE, i, solar ? -1 : RJ_METHOD_ADAPTIVE);
        const frow *ix = f_find(rows, n, RJ_LINK_INEXTENSIBLE, i, solar ? -1 : RJ_METHOD_ADAPTIVE);
        if (fx && ix && fx->ok && ix->ok) {
            double rdt = ix->dt / fx->dt, rcpu = fx->cpu / ix->cpu;
            md("- Inextensible against flexible links, %d elements per %s, both adaptive: the step is %.2f x as long, each step costs %.2f x as much, so the run is %.2f x as fast.",
               i, solar ? "panel" : "link", rdt, (ix->cpu / ix->steps) / (fx->cpu / fx->steps), rcpu);
            if (rdt < 1.05) md(" Removing the axial wave left the bound where it was: bending sets it at this mesh, so the length constraints only add cost.");
            else md(" The axial wave set the bound of the flexible links; without it, bending does%s.", rcpu < 1 ? ", and the longer step does not pay for the constraints" : "");
            md("\n");
        }
    }
    if (!solar) {
        /* penalty latches: K = Eq 31 falls as 1/dt^2 */
        const frow *pp = &rows[0], *pa = f_find(rows, n, RJ_LINK_FLEXIBLE, 10, RJ_METHOD_PENALTY), *ad = f_find(rows, n, RJ_LINK_FLEXIBLE, 10, RJ_METHOD_ADAPTIVE);
        if (pp->ok && pa && pa->ok && ad && ad->ok)
            md("- With a penalty latch, K = Eq 31 falls as 1/dt^2: going from the paper's %.3g us to the automatic %.4g us lowers it from %.4g to %.4g N m/rad, "
               "and moves the tip RMS error from %+.1f %% to %+.1f %% and joint 1's latch from %+.1f to %+.1f ms. An adaptive latch at the same step: %+.1f %% and %+.1f ms.\n",
               1e6 * pp->dt, 1e6 * pa->dt, pp->K, pa->K, 100 * pp->de.rms_t, 100 * pa->de.rms_t, 1e3 * pp->de.dlock1, 1e3 * pa->de.dlock1, 100 * ad->de.rms_t, 1e3 * ad->de.dlock1);
    }
    if (solar) {
        /* what sets the post-latch vibration error: the step or the mesh? */
        const frow *a = &rows[0], *q = NULL, *fine = f_find(rows, n, RJ_LINK_FLEXIBLE, 10, -1);
        for (i = 0; i < n; i++) if (rows[i].ok && rows[i].fid == RJ_LINK_FLEXIBLE && rows[i].dt_frac > 0 && rows[i].el == a->el) q = &rows[i];
        if (a->ok && q && fine && fine->ok) {
            md("- At the file's mesh, a quarter of the automatic step moves the tip vibration's error from %+.1f %% to %+.1f %% (RMS) and from %+.1f %% to %+.1f %% (frequency); "
               "%d elements per panel at the automatic step give %+.1f %% and %+.1f %%. ", 100 * a->se.tip_sd, 100 * q->se.tip_sd, 100 * a->se.tip_freq, 100 * q->se.tip_freq,
               fine->el, 100 * fine->se.tip_sd, 100 * fine->se.tip_freq);
            if (fabs(q->se.tip_freq) < 0.5 * fabs(a->se.tip_freq) && !(fabs(fine->se.tip_freq) < 0.5 * fabs(a->se.tip_freq)))
                md("The step, not the mesh, sets the frequency error after the latches: the adaptive latches hold with K_AP = I1 I2 / ((I1 + I2) dt^2) (Eq 21), so at a larger step the latched hinges are softer.\n");
            else md("\n");
        }
        /* latch times that jump */
        for (i = 0; i < n; i++) {
            const frow *r = &rows[i];
            int j, w = 0;
            if (!r->ok || r->fid == RJ_LINK_RIGID || r->se.dq > 1.0) continue;
            for (j = 1; j < F_NJ; j++) if (fabs(r->se.dlock[j]) > fabs(r->se.dlock[w])) w = j;
            if (fabs(r->se.dlock[w]) > 3 * F_FRAME) {
                int last = 0;
                for (j = 1; j < F_NJ; j++) if (F.s_ref_lock[j] > F.s_ref_lock[last]) last = j;
                md("- Latch times can jump: %s follows the reference within %.2f deg before the first latch, yet latches %s %.0f ms %s it%s. "
                   "Such a latch time is sensitive to small differences in the motion before it, and says little about the model's accuracy.\n",
                   f_row_name(r, b1, sizeof b1, solar), r->se.dq, F.s_hinge[w], 1e3 * fabs(r->se.dlock[w]), r->se.dlock[w] > 0 ? "after" : "before",
                   w == last ? " (the last hinge to latch, which closes while the rest of the array already vibrates)" : "");
                {
                    /* does the amplitude after the last latch follow the latch time? */
                    double lo = HUGE_VAL, hi = -HUGE_VAL, jlo = HUGE_VAL, jhi = -HUGE_VAL;
                    int k, nj = 0, nn = 0;
                    for (k = 0; k < n; k++) {
                        const frow *x = &rows[k];
                        if (!x->ok || x->fid == RJ_LINK_RIGID || isnan(x->se.tip_sd)) continue;
                        if (s_max_dlock(&x->se) > 3 * F_FRAME) { jlo = fmin(jlo, x->se.tip_sd); jhi = fmax(jhi, x->se.tip_sd); nj++; }
                        else { lo = fmin(lo, x->se.tip_sd); hi = fmax(hi, x->se.tip_sd); nn++; }
                    }
                    if (nj && nn && (jhi < lo || jlo > hi))
                        md("  The rows with a latch more than %.0f ms off have tip vibration RMS errors of %+.0f .. %+.0f %%, the others %+.0f .. %+.0f %%: "
                           "the amplitude left after the last latch follows when that latch closes.\n", 3e3 * F_FRAME, 100 * jlo, 100 * jhi, 100 * lo, 100 * hi);
                }
                break;
            }
        }
    }
    /* failures */
    for (i = 0; i < n; i++) {
        const frow *r = &rows[i];
        if (r->ok) continue;
        md("- %s: %s (the library's message is in the table).\n", f_row_name(r, b1, sizeof b1, solar),
           r->refused ? "refused by `rj_model_create`" : "accepted, then fails during the run");
    }
}

static void f_conv_md(const fconv *c, const char *what_rms)
{
    md("Checks on the reference: twice its step (%d elements, dt %.4g us) moves the angles by %.4f deg, the latches by up to %.2f ms, the %s RMS by %+.2f %% and its frequency by %+.2f %%; "
       "half its mesh (%d elements, dt %.4g us) by %.4f deg, %.2f ms, %+.2f %% and %+.2f %%. "
       "Taking the mesh error as second order (a third of the half-mesh difference), the reference is good to about %.3f deg, %.1f ms, %.1f %% in RMS and %.1f %% in frequency; "
       "differences below these are not resolved.\n\n",
       c->el[1], c->dt[1] * 1e6, c->dq[0], 1e3 * c->dlock[0], what_rms, 100 * c->rms[0], 100 * c->freq[0],
       c->el[2], c->dt[2] * 1e6, c->dq[1], 1e3 * c->dlock[1], 100 * c->rms[1], 100 * c->freq[1],
       f_unc(c->dq), 1e3 * f_unc(c->dlock), 100 * f_unc(c->rms), 100 * f_unc(c->freq));
}

static void fidelity_report(void)
{
    char b1[160], b2[700], b3[32], b4[32], b5[32], mlab[96];
    const frow *base;
    int i, j;
    md("## 4. Fidelity: which link model for which job\n\n");
    md("Each scene at each link model (`rj_link_def.fidelity`): flexible (the paper's element), inextensible (length constraints, so the axial wave leaves the stability bound) "
       "and rigid (joint coordinates). **wall / CPU**: the whole run with `rj_run` and no sampling (`solver.energy_every = 16` as `build/deploy`), median of 5 runs (21 below 10 ms; the `runs` column). "
       "The errors come from a separate run sampled every 1 ms, against a converged flexible reference. "
       "The joint methods differ between levels, and the method column names each row's. Rigid links default to a velocity-level latch (momentum with e = 0, as `build/deploy --links rigid` does), "
       "because a penalty stiffness from Eq 31 has no meaning without the elements that Eq 31 is about. "
       "A row that the library refuses or that fails is kept, with the library's message. The readings under each table are generated from its numbers.\n\n");
    /* ---- deployment */
    md("### Deployment (paper sec. 5)\n\n");
    md("Joint 1 forced, joint 2 latched by the method named; %.0f s simulated. Errors as in section 2: **dq** = max |q - q_ref| of both joints (deg) for t < %.4f s (10 ms before the rigid joint 2 lock); "
       "**lock 2 / lock 1** = latch time minus the reference's (ms); **tip RMS / freq** = link 2's tangent-based tip deflection over [3.2, %.0f] s, relative to the reference. "
       "Speed-up: the paper's-settings row's time over the row's.\n\n", F.d_tend, D_TPRE, F.d_tend);
    md("Reference: adaptive, %d elements per link, dt %.4g us (0.9 x bound / %g), %s; %.1f s with sampling. Joint 2 latches at %.6f s, joint 1 at %.6f s; tip RMS %.5g m at %.4f Hz.\n\n",
       F.dconv.el[0], F.dconv.dt[0] * 1e6, S.d_ref_div, F.d_ref_from_sweep ? "section 2's reference, reused" : "computed for this section (the full run reuses section 2's 80-element one)",
       F.dconv.wall[0], F.d_ref_lock[1], F.d_ref_lock[0], F.d_ref_rms, F.d_ref_freq);
    f_conv_md(&F.dconv, "tip");
    base = &F.d[0];
    md("| level | joint 2 method | elements / link | dt (us) | dt / bound | steps | wall (s) | CPU (s) | runs | speed-up (wall / CPU) | dq (deg) | lock 2 (ms) | lock 1 (ms) | tip RMS | tip freq |\n");
    md("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    for (i = 0; i < F.nd; i++) {
        const frow *r = &F.d[i];
        int novib = !(r->dm.rms_t > 1e-9);
        f_level_label(r, b1, sizeof b1);
        f_method_label(r, mlab, sizeof mlab, 0);
        if (!r->ok) { md("| %s | %s | %d | %.4g | **%s** | | | | | | | | | | |\n", b1, mlab, r->el, (r->dt > 0 ? r->dt : r->dt_req) * 1e6, f_cell(r->msg, b2, sizeof b2)); continue; }
        md("| %s | %s | %d | %.4g | %.3g | %ld | %.4f | %.4f | %d | %.1f / %.1f | %.3f | %+.2f | %+.1f | %s | %s |\n", b1, mlab, r->el, r->dt * 1e6, r->dt / r->bound,
           r->steps, r->wall, r->cpu, r->runs, base->ok ? base->wall / r->wall : NAN, base->ok ? base->cpu / r->cpu : NAN, r->de.dq, 1e3 * r->de.dlock, 1e3 * r->de.dlock1,
           novib ? "no vibration" : f_rel(r->de.rms_t, b3, sizeof b3), novib ? "" : f_rel(r->de.freq_t, b4, sizeof b4));
    }
    md("\nReading:\n\n");
    if (base->ok) f_reading(F.d, F.nd, 0, base, &F.dconv);
    md("\n");
    /* ---- solar array */
    md("### Solar array (`%s`)\n\n", F.s_path[0] ? F.s_path : "examples/scenes/solar_array.rjs");
    if (F.s_err[0]) { md("Not run: %s\n\n", F.s_err); return; }
    md("A fixed hub (one element) and four 1 m sandwich panels that unfold and latch (adaptive, lock = yes, RC13); %.0f s simulated. The panels get the row's element count and link model; "
       "the hub stays flexible unless the row says otherwise (a rigid hub with flexible or inextensible panels is a mixed scene: the hub is one rigid body). "
       "**dq** = max |theta - theta_ref| over the four hinges (deg) for t < %.4f s (10 ms before the reference's first latch, %s); **latches** = latch time minus the reference's, %s / %s / %s / %s (ms). "
       "**tip vibration**: the last panel's tip measured from the hub's axis (the whole array's deflection): RMS about its mean and its frequency (zero crossings with hysteresis), "
       "from 0.3 s after the row's own last latch to the end, relative to the reference; "
       "**p4 bending**: RMS of the last panel's own tip deflection from its root tangent over the same window; "
       "**drift**: the largest least-squares slope of a hinge angle over that window, when every hinge is latched (vibration averages out; a latched hinge should not turn). Speed-up: against the file as written.\n\n",
       F.s_tend, F.s_ref_lock[F.s_first] - 0.01, F.s_hinge[F.s_first], F.s_hinge[0], F.s_hinge[1], F.s_hinge[2], F.s_hinge[3]);
    md("Reference: flexible, %d elements per panel (%g x the file's), dt %.4g us: a quarter of its automatic dt (the adaptive latches' stiffness, which grows as 1/dt^2, "
       "brings the bound down with dt: dt / bound = %.3g), %.1f s with sampling. Latches: ", F.sconv.el[0], (double)F.sconv.el[0] / F_SOLAR.links[F_LAST].elements,
       F.sconv.dt[0] * 1e6, F.s_ref_frac, F.sconv.wall[0]);
    for (j = 0; j < F_NJ; j++) md("%s %.4f s%s", F.s_hinge[j], F.s_ref_lock[j], j + 1 < F_NJ ? ", " : ". ");
    md("Tip vibration over [%.1f, %.0f] s: RMS %.4g m about a mean of %.4g m, %.4f Hz; p4 bending RMS %.4g m.\n\n", F.s_ref_tw0, F.s_tend, F.s_ref_tip_sd, F.s_ref_tip_mean, F.s_ref_tip_freq, F.s_ref_d4_sd);
    f_conv_md(&F.sconv, "tip vibration");
    base = &F.s[0];
    md("| level | hinge method | elements / panel | dt (us) | dt / bound | steps | wall (s) | CPU (s) | runs | speed-up (wall / CPU) | dq (deg) | latches %s / %s / %s / %s (ms) | tip vibration RMS | freq | p4 bending RMS | latched hinges' drift (deg/s) |\n",
       F.s_hinge[0], F.s_hinge[1], F.s_hinge[2], F.s_hinge[3]);
    md("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---:|---:|---:|---:|\n");
    for (i = 0; i < F.ns; i++) {
        const frow *r = &F.s[i];
        char lk[160];
        int novib;
        f_level_label(r, b1, sizeof b1);
        f_method_label(r, mlab, sizeof mlab, 1);
        if (!r->ok) { md("| %s | %s | %d | %.4g | **%s** | | | | | | | | | | | |\n", b1, mlab, r->el, (r->dt > 0 ? r->dt : r->dt_req) * 1e6, f_cell(r->msg, b2, sizeof b2)); continue; }
        snprintf(lk, sizeof lk, "%s", f_lockstr(&r->se));
        if (strlen(lk) > 3) lk[strlen(lk) - 3] = 0;   /* the column header gives the unit */
        novib = !(r->sm.tip_sd > 1e-6);
        md("| %s | %s | %d | %.4g | %.3g | %ld | %.4f | %.4f | %d | %.1f / %.1f | %.3f | %s | %s | %s | %s | %.2g |\n", b1, mlab, r->el, r->dt * 1e6, r->dt / r->bound,
           r->steps, r->wall, r->cpu, r->runs, base->ok ? base->wall / r->wall : NAN, base->ok ? base->cpu / r->cpu : NAN, r->se.dq, lk,
           isnan(r->sm.tip_sd) ? "no window" : novib ? "no vibration" : f_rel(r->se.tip_sd, b3, sizeof b3), novib ? "" : f_rel(r->se.tip_freq, b4, sizeof b4),
           !(r->sm.d4_sd > 1e-9) ? "none" : f_rel(r->se.d4_sd, b5, sizeof b5), r->sm.drift);
    }
    md("\nReading:\n\n");
    if (base->ok) f_reading(F.s, F.ns, 1, base, &F.sconv);
    md("\nThis section took %.0f s.\n\n", F.wall_section);
}

/* ================================================================== 5. feature cost */
/* Time per step of one small scene (two 10-element links, the root link pinned to ground,
   one joint between them) with one joint feature at a time on the joint between the links:
   a scene should pay only for what it uses. All scenes run at the same dt; the ladder is
   timed round-robin (every round runs every scene once) so that load changes on a shared
   machine hit all scenes alike. The load rows are the bare scene with one load feature
   instead: gravity, a caller's input (set on the state after every reset) or a load in
   the model. */
enum { FT_NONE = 0, FT_FREE, FT_LOCKED, FT_CONTACT };
/* load features (fspec.load) */
enum { FT_LOAD_NONE = 0, FT_GRAVITY, FT_JOINT_TORQUE, FT_NODE_FORCE, FT_LOAD_CONSTANT, FT_LOAD_FOLLOWER,
       FT_MASS_DAMPING, FT_KELVIN_VOIGT };
#define FT_ALPHA 1.0              /* 1/s, mass_damping on both links */
#define FT_ZETA 0.02              /* Kelvin-Voigt on both links: this ratio at FT_ZETA_HZ */
#define FT_ZETA_HZ 5.0
#define FT_GRAVITY_Y (-9.81)      /* m/s^2, solver.gravity (0, FT_GRAVITY_Y) */
#define FT_TORQUE 0.1             /* N m, the caller's constant torque on joint 2 */
#define FT_TIP_FORCE_Y (-1.0)     /* N, the caller's force and the constant load on link 2's tip (0, this) */
#define FT_FOLLOWER_Y 1.0         /* N, the follower load across link 2's tip (0, this) in the tip's frame */
static const double ft_follower_time[4] = { 0.0, 4.0, 8.0, 12.0 };   /* s, its table */
static const double ft_follower_factor[4] = { 0.0, 1.0, -1.0, 1.0 };
typedef struct fspec {
    const char *name;
    int spring, damping, friction, table, limit, lstate, layers, chord, fid;
    int load;                     /* FT_LOAD_NONE or one load feature */
} fspec;
typedef struct fres {
    int ok;
    char msg[800], state[200];
    double K, med, mn, mx, cpu;                /* ns / step: wall median, min, max; CPU median */
    double ratio, ratio_cpu, ratio_lo, ratio_hi; /* time / the bare scene's in the same round: median (wall, CPU), range (wall) */
    long steps;
    long samples, on, locked;                  /* joint 2's flag at the end of every chunk: count, not free, latched */
    int touched, released;                     /* runs with a contact (rj_joint_event_time), with a release (rj_joint_release_time) */
    double first_contact, tsim;                /* s, latest first contact over the runs; simulated time of a run */
    double acct;                               /* load rows: the load's account at the end of the last run (J) */
    int acted;                                 /* load rows: runs that ended with that account nonzero */
} fres;

#define FT_CHUNKS 100

#define FT_MAX 32
static struct {
    int ran, n, rounds;
    fspec spec[FT_MAX];
    fres res[FT_MAX];
    double dt, min_time, wall_section;
    double auto_refused[FT_MAX];   /* s: an automatic dt that the library refuses when given explicitly */
    double shortest;               /* s, the shortest timed run */
} FT;

static void ft_scene(const fspec *f, double dt, double K, rj_link_def L[2], rj_joint_def J[2], rj_load_def LD[1], rj_scene_def *sc)
{
    int i;
    for (i = 0; i < 2; i++) {
        L[i] = rj_default_link_def();
        L[i].length = 1.0; L[i].elements = 10; L[i].height = 0.02; L[i].width = 0.05;
        L[i].layers = f->layers > 1 ? f->layers : 1;
        L[i].fidelity = f->fid;
    }
    /* the chain spins about the ground pin at 2 rad/s; joint 1 starts straight, turning at 0.2 rad/s:
       the spin's centrifugal field keeps it near straight */
    J[0] = rj_default_joint_def();
    J[0].body1 = -1; J[0].body2 = 0; J[0].angle0 = rj_rad(180.0); J[0].rate0 = 2.0;
    J[1] = rj_default_joint_def();
    J[1].body1 = 0; J[1].body2 = 1; J[1].angle0 = rj_rad(180.0); J[1].rate0 = 0.2;
    if (f->chord) J[0].reference = J[1].reference = RJ_REF_CHORD;
    if (f->spring) { J[1].spring_k = 5.0; J[1].spring_free_angle = rj_rad(180.0); }
    if (f->damping) J[1].damping = 0.5;
    if (f->friction) J[1].friction = 0.2;
    if (f->table) {
        J[1].table_count = 8;
        for (i = 0; i < 8; i++) { J[1].table_angle[i] = 6.283185307179586 * i / 7.0; J[1].table_torque[i] = 0.1 + 0.05 * (i % 3); }
    }
    if (f->limit >= 0) {
        J[1].method = f->limit; J[1].penalty_k = K > 0 ? K : 1.0; J[1].restitution = 0.0;
        if (f->lstate == FT_FREE) { J[1].has_forward = 1; J[1].forward = rj_rad(240.0); J[1].has_reverse = 1; J[1].reverse = rj_rad(120.0); }
        else {
            /* starts on its forward limit, turning into it */
            J[1].has_forward = 1; J[1].forward = rj_rad(185.0); J[1].angle0 = rj_rad(185.0);
            if (f->lstate == FT_LOCKED) J[1].lock = 1;
            else { J[1].spring_k = 50.0; J[1].spring_free_angle = rj_rad(215.0); }   /* holds it on the stop */
        }
    }
    for (i = 0; i < 2; i++) {
        if (f->load == FT_MASS_DAMPING) L[i].mass_damping = FT_ALPHA;
        if (f->load == FT_KELVIN_VOIGT) { L[i].damping[0] = FT_ZETA; L[i].damping[1] = FT_ZETA_HZ; }
    }
    *sc = rj_default_scene_def();
    sc->links = L; sc->link_count = 2; sc->joints = J; sc->joint_count = 2;
    sc->solver.dt = dt;
    if (f->load == FT_GRAVITY) sc->solver.gravity[1] = FT_GRAVITY_Y;
    if (f->load == FT_LOAD_CONSTANT || f->load == FT_LOAD_FOLLOWER) {
        /* a load in the model on link 2's tip (node -1: its last node) */
        LD[0] = rj_default_load_def();
        LD[0].link = 1; LD[0].node = -1;
        if (f->load == FT_LOAD_CONSTANT) LD[0].force[1] = FT_TIP_FORCE_Y;
        else {
            LD[0].force[1] = FT_FOLLOWER_Y; LD[0].follower = 1;
            LD[0].table_count = 4;
            for (i = 0; i < 4; i++) { LD[0].table_time[i] = ft_follower_time[i]; LD[0].table_factor[i] = ft_follower_factor[i]; }
        }
        sc->loads = LD; sc->load_count = 1;
    }
}

/* rj_state_reset, then the caller's inputs of a load row: the reset zeroes them and switches
   them off, so they are set again after every reset (outside the timed region) */
static void ft_reset(const fspec *f, const rj_model *m, rj_state *s)
{
    rj_state_reset(m, s);
    if (f->load == FT_JOINT_TORQUE) rj_state_joint_torques(m, s)[1] = FT_TORQUE;
    if (f->load == FT_NODE_FORCE) rj_state_node_forces(m, s)[3 * rj_model_node_index(m, 1, -1) + 1] = FT_TIP_FORCE_Y;
}

/* a load row's account at the end of a run: gravity's potential, the work of the load or
   input, or the damping's loss */
static double ft_load_account(const fspec *f, const rj_model *m, const rj_state *s)
{
    rj_energy e;
    rj_state_energy(m, s, &e);
    if (f->load == FT_MASS_DAMPING || f->load == FT_KELVIN_VOIGT) return e.lost_structural;
    return f->load == FT_GRAVITY ? e.gravity : e.work_applied;
}

/* builds scene f at dt (0: automatic); penalty: K = Eq 31 at dt, halved until the bound accepts it */
static rj_result ft_build(const fspec *f, double dt, double *K, rj_model **m, rj_error *err)
{
    rj_link_def L[2]; rj_joint_def J[2]; rj_load_def LD[1]; rj_scene_def sc;
    rj_result r;
    int i;
    *K = 0;
    ft_scene(f, dt, 1.0, L, J, LD, &sc);
    r = rj_model_create(&sc, m, err, NULL);
    if (r != RJ_OK || f->limit != RJ_METHOD_PENALTY) return r;
    *K = rj_joint_kmax_eq31(*m, 1, rj_model_dt(*m));
    rj_model_destroy(*m, NULL);
    for (i = 0; i < 40; i++) {
        ft_scene(f, dt, *K, L, J, LD, &sc);
        r = rj_model_create(&sc, m, err, NULL);
        if (r != RJ_ERR_UNSTABLE_DT) return r;
        *K *= 0.5;
    }
    return r;
}

static void ft_add(const char *name, int spring, int damping, int friction, int table, int limit, int lstate, int layers, int chord, int fid)
{
    fspec *f = &FT.spec[FT.n++];
    f->name = name; f->spring = spring; f->damping = damping; f->friction = friction; f->table = table;
    f->limit = limit; f->lstate = lstate; f->layers = layers; f->chord = chord; f->fid = fid;
    f->load = FT_LOAD_NONE;
}

/* the bare scene with one load feature */
static void ft_add_load(const char *name, int load)
{
    ft_add(name, 0, 0, 0, 0, -1, FT_NONE, 1, 0, RJ_LINK_FLEXIBLE);
    FT.spec[FT.n - 1].load = load;
}

static void features_section(void)
{
    static rj_model *M[FT_MAX];
    static rj_state *ST[FT_MAX];
    static double W[FT_MAX][32], C[FT_MAX][32], best[FT_MAX];
    static long trial_n[FT_MAX];
    double t0 = now();
    int i, k, rounds;
    memset(&FT, 0, sizeof FT);
    FT.ran = 1;
    FT.min_time = S.quick ? 0.02 : 0.2;
    rounds = FT.rounds = S.quick ? 3 : 7;
    ft_add("bare: no joint features", 0, 0, 0, 0, -1, FT_NONE, 1, 0, RJ_LINK_FLEXIBLE);
    ft_add("+ torsion spring", 1, 0, 0, 0, -1, FT_NONE, 1, 0, RJ_LINK_FLEXIBLE);
    ft_add("+ viscous damping", 0, 1, 0, 0, -1, FT_NONE, 1, 0, RJ_LINK_FLEXIBLE);
    ft_add("+ Coulomb friction", 0, 0, 1, 0, -1, FT_NONE, 1, 0, RJ_LINK_FLEXIBLE);
    ft_add("+ torque table (Eq 4), 8 entries", 0, 0, 0, 1, -1, FT_NONE, 1, 0, RJ_LINK_FLEXIBLE);
    ft_add("+ limits, penalty, free", 0, 0, 0, 0, RJ_METHOD_PENALTY, FT_FREE, 1, 0, RJ_LINK_FLEXIBLE);
    ft_add("+ limits, adaptive, free", 0, 0, 0, 0, RJ_METHOD_ADAPTIVE, FT_FREE, 1, 0, RJ_LINK_FLEXIBLE);
    ft_add("+ limits, momentum, free", 0, 0, 0, 0, RJ_METHOD_MOMENTUM, FT_FREE, 1, 0, RJ_LINK_FLEXIBLE);
    ft_add("+ limit, penalty, latched (lock = 1)", 0, 0, 0, 0, RJ_METHOD_PENALTY, FT_LOCKED, 1, 0, RJ_LINK_FLEXIBLE);
    ft_add("+ limit, adaptive, latched (lock = 1)", 0, 0, 0, 0, RJ_METHOD_ADAPTIVE, FT_LOCKED, 1, 0, RJ_LINK_FLEXIBLE);
    ft_add("+ limit, momentum, latched (lock = 1)", 0, 0, 0, 0, RJ_METHOD_MOMENTUM, FT_LOCKED, 1, 0, RJ_LINK_FLEXIBLE);
    ft_add("+ limit, penalty, in contact (+ a spring holding it there)", 0, 0, 0, 0, RJ_METHOD_PENALTY, FT_CONTACT, 1, 0, RJ_LINK_FLEXIBLE);
    ft_add("+ limit, adaptive, in contact (+ a spring holding it there)", 0, 0, 0, 0, RJ_METHOD_ADAPTIVE, FT_CONTACT, 1, 0, RJ_LINK_FLEXIBLE);
    ft_add("+ limit, momentum, in contact (+ a spring holding it there)", 0, 0, 0, 0, RJ_METHOD_MOMENTUM, FT_CONTACT, 1, 0, RJ_LINK_FLEXIBLE);
    ft_add("layered section (8 layers) instead of 1", 0, 0, 0, 0, -1, FT_NONE, 8, 0, RJ_LINK_FLEXIBLE);
    ft_add("chord reference (both joints) instead of tangent", 0, 0, 0, 0, -1, FT_NONE, 1, 1, RJ_LINK_FLEXIBLE);
    ft_add("everything on: spring, damping, friction, table, adaptive limits (free), 8 layers", 1, 1, 1, 1, RJ_METHOD_ADAPTIVE, FT_FREE, 8, 0, RJ_LINK_FLEXIBLE);
    ft_add("everything on, chord reference (adaptive limits)", 1, 1, 1, 1, RJ_METHOD_ADAPTIVE, FT_FREE, 8, 1, RJ_LINK_FLEXIBLE);
    ft_add("everything on, chord reference, penalty limits", 1, 1, 1, 1, RJ_METHOD_PENALTY, FT_FREE, 8, 1, RJ_LINK_FLEXIBLE);
    ft_add("inextensible links (bare joints)", 0, 0, 0, 0, -1, FT_NONE, 1, 0, RJ_LINK_INEXTENSIBLE);
    ft_add("rigid links (bare joints)", 0, 0, 0, 0, -1, FT_NONE, 1, 0, RJ_LINK_RIGID);
    ft_add_load("+ gravity (solver.gravity 0 -9.81)", FT_GRAVITY);
    ft_add_load("+ caller's joint torques (rj_state_joint_torques, a constant 0.1 N m on joint 2)", FT_JOINT_TORQUE);
    ft_add_load("+ caller's node forces (rj_state_node_forces, a force on the tip)", FT_NODE_FORCE);
    ft_add_load("+ applied load at the tip, constant", FT_LOAD_CONSTANT);
    ft_add_load("+ applied load at the tip, follower, with a 4-point time table", FT_LOAD_FOLLOWER);
    ft_add_load("+ mass_damping 1 1/s on both links", FT_MASS_DAMPING);
    ft_add_load("+ Kelvin-Voigt damping = 0.02 5 on both links (implicit)", FT_KELVIN_VOIGT);
    /* one dt for all: the smallest automatic dt of the flexible scenes (penalty with K = Eq 31 at
       it) among those that the library also accepts when that dt is given explicitly */
    FT.dt = HUGE_VAL;
    for (i = 0; i < FT.n; i++) {
        rj_model *m; rj_error err; double K, dt;
        if (FT.spec[i].fid != RJ_LINK_FLEXIBLE) continue;
        if (ft_build(&FT.spec[i], 0, &K, &m, &err) != RJ_OK) continue;
        dt = rj_model_dt(m);
        rj_model_destroy(m, NULL);
        if (ft_build(&FT.spec[i], dt, &K, &m, &err) != RJ_OK) {
            FT.auto_refused[i] = dt;
            note("features, %s: the automatic dt (solver.dt = 0) is %.4g us, but the same dt given explicitly is refused: %s", FT.spec[i].name, 1e6 * dt, err.msg);
            continue;
        }
        rj_model_destroy(m, NULL);
        FT.dt = fmin(FT.dt, dt);
    }
    /* build, check and calibrate: each scene's step count takes about min_time */
    for (i = 0; i < FT.n; i++) {
        fres *o = &FT.res[i];
        rj_error err; rj_result r;
        long n = 20000, j;
        double t;
        M[i] = NULL; ST[i] = NULL;
        r = ft_build(&FT.spec[i], FT.dt, &o->K, &M[i], &err);
        if (r != RJ_OK) { snprintf(o->msg, sizeof o->msg, "%s: %s", rj_result_str(r), err.msg); M[i] = NULL; continue; }
        if (rj_state_create(M[i], &ST[i], NULL) != RJ_OK) { snprintf(o->msg, sizeof o->msg, "no memory"); rj_model_destroy(M[i], NULL); M[i] = NULL; continue; }
        /* a first trial run of at least a quarter of min_time */
        for (;;) {
            ft_reset(&FT.spec[i], M[i], ST[i]);
            t = now();
            for (j = 0; j < n; j++) if (rj_step(M[i], ST[i]) != RJ_OK) break;
            t = now() - t;
            if (j < n || t >= 0.25 * FT.min_time) break;
            n = (long)ceil(n * (t > 0 ? fmin(16.0, 0.3 * FT.min_time / t) : 16.0));
        }
        if (j < n) { snprintf(o->msg, sizeof o->msg, "%s", rj_state_error(ST[i])); rj_state_destroy(ST[i], NULL); rj_model_destroy(M[i], NULL); M[i] = NULL; continue; }
        trial_n[i] = n; best[i] = t / n;
        o->ok = 1;
    }
    /* two more trial passes over all scenes; each scene's step count then takes min_time with
       40 % to spare at the fastest per-step time seen, so a run takes at least min_time unless
       the machine gets more than that much faster (the report gives the shortest run) */
    for (k = 0; k < 2; k++)
        for (i = 0; i < FT.n; i++) {
            long j;
            double t;
            if (!FT.res[i].ok) continue;
            ft_reset(&FT.spec[i], M[i], ST[i]);
            t = now();
            for (j = 0; j < trial_n[i]; j++) if (rj_step(M[i], ST[i]) != RJ_OK) break;
            t = now() - t;
            if (j == trial_n[i]) best[i] = fmin(best[i], t / trial_n[i]);
        }
    for (i = 0; i < FT.n; i++) if (FT.res[i].ok) FT.res[i].steps = (long)ceil(1.4 * FT.min_time / best[i]);
    /* Each round runs every scene once from a reset state, in FT_CHUNKS chunks interleaved
       scene by scene (chunk 1 of every scene, then chunk 2, ...): a scene's run is the sum of its
       chunks, spread over the whole round, so a change of the machine's speed during a round
       (another process starting, the clock changing) reaches every scene of the round alike.
       The scene's cost relative to the bare scene is then taken round by round (paired). */
    for (k = 0; k < rounds; k++) {
        int q, c;
        for (i = 0; i < FT.n; i++) { W[i][k] = C[i][k] = 0; if (FT.res[i].ok) ft_reset(&FT.spec[i], M[i], ST[i]); }
        for (c = 0; c < FT_CHUNKS; c++) {
            for (q = 0; q < FT.n; q++) {
                fres *o;
                long j, j0, j1;
                double t, cp;
                i = (q + k + c) % FT.n;        /* the order rotates from chunk to chunk */
                o = &FT.res[i];
                if (!o->ok) continue;
                j0 = o->steps * c / FT_CHUNKS; j1 = o->steps * (c + 1) / FT_CHUNKS;
                t = now(); cp = cpu_now();
                for (j = j0; j < j1; j++) if (rj_step(M[i], ST[i]) != RJ_OK) break;
                t = now() - t; cp = cpu_now() - cp;
                if (j < j1) { o->ok = 0; snprintf(o->msg, sizeof o->msg, "%s", rj_state_error(ST[i])); continue; }
                W[i][k] += t; C[i][k] += cp;
                /* joint 2's flag at the end of the chunk (not timed) */
                {
                    int fl = rj_joint_flag(M[i], ST[i], 1);
                    o->samples++;
                    if (fl != RJ_FREE) o->on++;
                    if (fl == RJ_LOCKED) o->locked++;
                }
            }
        }
        for (i = 0; i < FT.n; i++) if (FT.res[i].ok) {
            fres *o = &FT.res[i];
            /* exact, from the library: first contact and latest release of this run */
            double te = rj_joint_event_time(M[i], ST[i], 1), tr = rj_joint_release_time(M[i], ST[i], 1);
            if (te >= 0) o->touched++;
            if (tr >= 0) o->released++;
            o->first_contact = fmax(o->first_contact, te);
            o->tsim = rj_state_time(ST[i]);
            if (FT.spec[i].load != FT_LOAD_NONE) {
                /* the load acted in the timed steps: its account is nonzero at the end of the run */
                o->acct = ft_load_account(&FT.spec[i], M[i], ST[i]);
                if (o->acct != 0) o->acted++;
            }
            if (FT.shortest == 0 || W[i][k] < FT.shortest) FT.shortest = W[i][k];
            W[i][k] *= 1e9 / FT.res[i].steps; C[i][k] *= 1e9 / FT.res[i].steps;
        }
        progress("features: round %d of %d", k + 1, rounds);
    }
    /* paired: this scene's time over the bare scene's in the same round */
    for (i = 0; i < FT.n; i++) {
        double rw[32], rc[32];
        if (!FT.res[i].ok || !FT.res[0].ok) continue;
        for (k = 0; k < rounds; k++) { rw[k] = W[i][k] / W[0][k]; rc[k] = C[i][k] / C[0][k]; }
        FT.res[i].ratio = median(rw, rounds); FT.res[i].ratio_cpu = median(rc, rounds);
        FT.res[i].ratio_lo = FT.res[i].ratio_hi = rw[0];
        for (k = 1; k < rounds; k++) { FT.res[i].ratio_lo = fmin(FT.res[i].ratio_lo, rw[k]); FT.res[i].ratio_hi = fmax(FT.res[i].ratio_hi, rw[k]); }
    }
    for (i = 0; i < FT.n; i++) {
        fres *o = &FT.res[i];
        const fspec *f = &FT.spec[i];
        if (M[i] && o->ok) {
            o->med = median(W[i], rounds); o->cpu = median(C[i], rounds);
            o->mn = o->mx = W[i][0];
            for (k = 1; k < rounds; k++) { o->mn = fmin(o->mn, W[i][k]); o->mx = fmax(o->mx, W[i][k]); }
            /* what joint 2 did: the library's first-contact and release times of every run, and its flag at every chunk end */
            if (f->load == FT_GRAVITY) snprintf(o->state, sizeof o->state, "%.3g s simulated; gravity's potential nonzero at the end of %d of %d runs (%.3g J)", o->tsim, o->acted, FT.rounds, o->acct);
            else if (f->load == FT_MASS_DAMPING || f->load == FT_KELVIN_VOIGT) snprintf(o->state, sizeof o->state, "%.3g s simulated; W_structural nonzero at the end of %d of %d runs (%.3g J)", o->tsim, o->acted, FT.rounds, o->acct);
            else if (f->load != FT_LOAD_NONE) snprintf(o->state, sizeof o->state, "%.3g s simulated; the load's work nonzero at the end of %d of %d runs (%.3g J)", o->tsim, o->acted, FT.rounds, o->acct);
            else if (f->limit < 0) snprintf(o->state, sizeof o->state, "%.3g s simulated", o->tsim);
            else if (f->lstate == FT_FREE && !o->touched) snprintf(o->state, sizeof o->state, "free throughout (%.3g s)", o->tsim);
            else if (f->lstate == FT_LOCKED && o->locked == o->samples && !o->released)
                snprintf(o->state, sizeof o->state, "latched from %.3g ms to the end (%.3g s)", 1e3 * o->first_contact, o->tsim);
            else snprintf(o->state, sizeof o->state, "%s on the limit at %.1f %% of %ld chunk ends; a release in %d of %d runs (%.3g s)", f->lstate == FT_FREE ? "**touched**:" : "in contact:",
                          100.0 * o->on / o->samples, o->samples, o->released, FT.rounds, o->tsim);
        }
        if (ST[i]) rj_state_destroy(ST[i], NULL);
        if (M[i]) rj_model_destroy(M[i], NULL);
        progress("feature %-60.60s %s %.1f ns/step (%s)", f->name, o->ok ? "ok" : o->msg, o->med, o->state);
    }
    FT.wall_section = now() - t0;
}

/* ---------------------------------------------------------------- model build */
/* A chain of n links of 4 elements each (fidelity as given), each hanging from the last;
   the memory it needs and the time to validate and build it. */
/* One step of model m, s, timed over batches that double until one takes 20 ms (a single
   step when that alone does). */
static double chain_step_time(const rj_model *m)
{
    rj_state *s = NULL;
    double t = 0;
    int batch = 1, i;
    if (rj_state_create(m, &s, NULL) != RJ_OK) return 0;
    for (;;) {
        double t0 = now();
        for (i = 0; i < batch; i++) rj_step(m, s);
        t = (now() - t0) / batch;
        if (t * batch >= 0.02 || batch >= 65536) break;
        batch *= 2;
    }
    rj_state_destroy(s, NULL);
    return t;
}

static void build_chain(int n, int fidelity, int runs, double *bytes, double *state_bytes, double *t_size, double *t_create, double *t_step, char *msg, size_t msize)
{
    rj_link_def *links = (rj_link_def *)malloc(sizeof *links * (size_t)n);
    rj_joint_def *joints = (rj_joint_def *)malloc(sizeof *joints * (size_t)n);
    rj_scene_def scene;
    double ts[5], tc[5];
    int r;
    msg[0] = 0;
    chain_scene(n, 4, fidelity, links, joints, &scene);
    *bytes = 0;
    *state_bytes = 0;
    for (r = 0; r < runs; r++) {
        rj_model *m = NULL;
        rj_error err;
        double t0 = now();
        *bytes = (double)rj_model_size(&scene, &err);
        ts[r] = now() - t0;
        t0 = now();
        if (rj_model_create(&scene, &m, &err, NULL) != RJ_OK) { snprintf(msg, msize, "%s", err.msg); break; }
        tc[r] = now() - t0;
        *state_bytes = (double)rj_state_size(m);
        if (r == runs - 1) *t_step = chain_step_time(m);
        rj_model_destroy(m, NULL);
    }
    *t_size = msg[0] ? 0 : median(ts, runs);
    *t_create = msg[0] ? 0 : median(tc, runs);
    free(links);
    free(joints);
}

/* Section 6: model build time and memory for chains of 10 .. 10000 links. Flexible and
   inextensible models are linear in the scene; so are rigid trees of 16 coordinates or
   more (articulated bodies: no dense mass matrix, a column of M^-1 and a row only for a
   joint that can latch), whose build is O(n) too (every joint's 1 / I_red from one pass
   over the articulated factor); smaller rigid scenes keep a dense nj x nj M. */
static void build_section(void)
{
    static const int sizes[4] = { 10, 100, 1000, 10000 };
    static const char *const kinds[3] = { "flexible", "inextensible", "rigid" };
    static const int fids[3] = { RJ_LINK_FLEXIBLE, RJ_LINK_INEXTENSIBLE, RJ_LINK_RIGID };
    int k, i;
    md("## 6. Model build: time and memory against scene size\n\n");
    md("A chain of n links of 4 elements (0.1 m, 0.01 m deep), each hanging from the last by a bare joint; `rj_model_size` (validation of every field) and "
       "`rj_model_create` (the joint graph's checks, the build and the stability bound: for flexible links Lanczos on the closed-form tangent, stopped once "
       "settled) timed apart, median of 3 runs (1 for the largest); a step of the model built, timed over batches doubled until one takes 20 ms, and the "
       "build in those steps. Rigid scenes integrate in joint coordinates, trees of 16 coordinates or more by articulated bodies (a step in O(n), "
       "the build in O(n): every joint's 1 / I_red from one pass over the articulated factor; memory linear in the links: "
       "a column of M^-1 and a row are kept only for a joint that can latch), smaller ones with a dense mass matrix.\n\n");
    md("| links | model | model bytes | bytes per link | state bytes | validate (ms) | build (ms) | build per link (us) | step (us) | build in steps |\n|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    for (k = 0; k < 3; k++) for (i = 0; i < 4; i++) {
        double bytes, state_bytes, t_size, t_create, t_step = 0;
        char msg[600];
        progress("model build: %s chain of %d links", kinds[k], sizes[i]);
        build_chain(sizes[i], fids[k], sizes[i] >= 10000 || (fids[k] == RJ_LINK_RIGID && sizes[i] >= 1000) ? 1 : 3, &bytes, &state_bytes, &t_size, &t_create, &t_step, msg, sizeof msg);
        if (msg[0]) { md("| %d | %s | not built: %s | | | | | | | |\n", sizes[i], kinds[k], msg); continue; }
        md("| %d | %s | %.0f | %.0f | %.0f | %.3f | %.2f | %.1f | %.3g | %.0f |\n", sizes[i], kinds[k], bytes, bytes / sizes[i], state_bytes,
           1e3 * t_size, 1e3 * t_create, 1e6 * t_create / sizes[i], 1e6 * t_step, t_step > 0 ? t_create / t_step : 0.0);
    }
    md("\n");
}

/* A whole markdown fragment (--peer), NULL when it cannot be read; the caller frees it. */
static char *read_fragment(const char *path)
{
    FILE *g = fopen(path, "r");
    char *p = NULL;
    size_t n = 0;
    size_t got;
    if (!g) return NULL;
    do {
        char *q = (char *)realloc(p, n + 4097);
        if (!q) {
            free(p);
            fclose(g);
            return NULL;
        }
        p = q;
        got = fread(p + n, 1, 4096, g);
        n += got;
    } while (got == 4096);
    p[n] = 0;
    fclose(g);
    return p;
}

static void features_report(void)
{
    const fres *b = &FT.res[0];
    char b2[700];
    int i;
    md("## 5. Feature cost: a scene pays only for what it uses\n\n");
    md("One small scene: two 1 m links of 10 elements (default material, 0.05 x 0.02 m), the first pinned to ground and spinning at 2 rad/s, the second pinned to its tip, "
       "starting straight and turning at 0.2 rad/s. One feature at a time on the joint between the links (the ground joint stays bare); "
       "all at the same dt = %.4g us (the smallest automatic dt among the flexible scenes; a penalty limit gets K = Eq 31 at that dt, halved until the bound accepts it). "
       "A run is `rj_step` in a loop of a fixed number of steps, calibrated to take at least %.2g s (the shortest run took %.3g s), from a reset state. %d rounds; in each, every scene makes one run, cut into %d chunks that are "
       "interleaved scene by scene, so that each run is spread over the whole round and a change in the machine's speed during the round reaches every scene alike. "
       "Time per step: median, minimum and maximum over the rounds (wall), and the CPU median (`CLOCK_PROCESS_CPUTIME_ID`). "
       "**vs bare**: the scene's time over the bare scene's in the same round, median over the rounds (wall; the range of the rounds in brackets; CPU in the last column). "
       "Joint 2's column checks that the scene did what its name says: the library's first-contact and release times after every run, "
       "and joint 2's flag at every chunk end (outside the timed region).\n\n",
       FT.dt * 1e6, FT.min_time, FT.shortest, FT.rounds, FT_CHUNKS);
    md("The load rows (after the link models) are the bare scene, joints bare, with one load feature instead: gravity (`solver.gravity` = (0, %g) m/s^2, in the plane of the motion); "
       "a caller's input, set on the state after every reset, outside the timed region (`rj_state_reset` zeroes the inputs and switches them off): "
       "%g N m on joint 2 (`rj_state_joint_torques`), or a force (0, %g) N on link 2's tip (`rj_state_node_forces`); "
       "or a load in the model on link 2's tip (`rj_scene_def.loads`): the same (0, %g) N, constant, or (0, %g) N in the tip's own frame (across the link; `follower` 1) "
       "scaled by the table (%g s, %g), (%g s, %g), (%g s, %g), (%g s, %g). They change the motion (joint 2 is free, so link 2 swings under them), which leaves the cost of a step "
       "alone; their column gives, instead of joint 2's limits, gravity's potential or the work of the load (`rj_energy`) at the end of every run: nonzero means it acted in the timed steps. "
       "The last two rows damp both links instead: `mass_damping` %g 1/s, or Kelvin-Voigt `damping = %g %g` (implicit, at the same dt), their column W_structural. "
       "The bare scene and the rows above them use none of these: their times are what a scene that does not use them pays.\n\n",
       FT_GRAVITY_Y, FT_TORQUE, FT_TIP_FORCE_Y, FT_TIP_FORCE_Y, FT_FOLLOWER_Y,
       ft_follower_time[0], ft_follower_factor[0], ft_follower_time[1], ft_follower_factor[1], ft_follower_time[2], ft_follower_factor[2], ft_follower_time[3], ft_follower_factor[3],
       FT_ALPHA, FT_ZETA, FT_ZETA_HZ);
    md("| scene | joint 2 during the run | steps per run | ns / step, wall median | wall min | wall max | CPU median | vs bare, wall (range) | vs bare, CPU |\n");
    md("|---|---|---:|---:|---:|---:|---:|---:|---:|\n");
    for (i = 0; i < FT.n; i++) {
        const fres *o = &FT.res[i];
        const fspec *f = &FT.spec[i];
        char name[200];
        snprintf(name, sizeof name, "%s", f->name);
        if (f->limit == RJ_METHOD_PENALTY && o->K > 0) { size_t n = strlen(name); snprintf(name + n, sizeof name - n, " (K = %.3g N m/rad)", o->K); }
        if (!o->ok) { md("| %s | **%s** | | | | | | | |\n", name, f_cell(o->msg, b2, sizeof b2)); continue; }
        if (i == 0) md("| **%s** | %s | %ld | **%.1f** | %.1f | %.1f | %.1f | | |\n", name, o->state, o->steps, o->med, o->mn, o->mx, o->cpu);
        else md("| %s | %s | %ld | **%.1f** | %.1f | %.1f | %.1f | **%+.1f %%** (%+.0f .. %+.0f %%) | %+.1f %% |\n", name, o->state, o->steps, o->med, o->mn, o->mx, o->cpu,
                100 * (o->ratio - 1), 100 * (o->ratio_lo - 1), 100 * (o->ratio_hi - 1), 100 * (o->ratio_cpu - 1));
    }
    md("\n");
    for (i = 0; i < FT.n; i++)
        if (FT.auto_refused[i] > 0)
            md("*%s*: with solver.dt = 0 the library picks dt = %.4g us, but refuses that same dt when it is given explicitly (message in the table, at the common dt): "
               "the automatic step of this scene is not one the library's own check accepts, so it is left out of the common dt.\n\n", FT.spec[i].name, 1e6 * FT.auto_refused[i]);
    /* reading */
    if (b->ok) {
        double spread = (b->mx - b->mn) / b->mn;
        int nbig = 0, nsmall = 0, nunc = 0;
        md("Reading: the bare scene costs %.0f ns per step (%.1f ns per node-step over its 22 nodes; its rounds spread by %.0f %%, max over min). ", b->med, b->med / 22.0, 100 * spread);
        md("Joint, section and load features that add more than 5 %% in every round: ");
        for (i = 1; i < FT.n; i++) {
            const fres *o = &FT.res[i];
            if (!o->ok || FT.spec[i].fid != RJ_LINK_FLEXIBLE) continue;
            if (o->ratio > 1.05 && o->ratio_lo > 1.05) { md("%s%s (%+.0f %%)", nbig ? "; " : "", FT.spec[i].name, 100 * (o->ratio - 1)); nbig++; }
        }
        if (!nbig) md("none");
        md(". Within 5 %% of the bare scene (median of the rounds): ");
        for (i = 1; i < FT.n; i++) {
            const fres *o = &FT.res[i];
            if (!o->ok || FT.spec[i].fid != RJ_LINK_FLEXIBLE) continue;
            if (fabs(o->ratio - 1) <= 0.05) { md("%s%s (%+.0f %%)", nsmall ? "; " : "", FT.spec[i].name, 100 * (o->ratio - 1)); nsmall++; }
        }
        if (!nsmall) md("none");
        md(". Between the two (more than 5 %% in the median, not in every round): ");
        for (i = 1; i < FT.n; i++) {
            const fres *o = &FT.res[i];
            if (!o->ok || FT.spec[i].fid != RJ_LINK_FLEXIBLE) continue;
            if (fabs(o->ratio - 1) > 0.05 && !(o->ratio > 1.05 && o->ratio_lo > 1.05)) { md("%s%s (%+.0f %%, rounds %+.0f .. %+.0f %%)", nunc ? "; " : "", FT.spec[i].name, 100 * (o->ratio - 1), 100 * (o->ratio_lo - 1), 100 * (o->ratio_hi - 1)); nunc++; }
        }
        if (!nunc) md("none");
        md(".\n\n");
    }
    md("This section took %.0f s.\n\n", FT.wall_section);
}

/* headline bullets for sections 4 and 5 */
static void headline_fidelity_features(void)
{
    char b1[300];
    if (F.ran && F.d[0].ok) {
        const frow *a = f_cheapest(F.d, F.nd, 0, 0), *v = f_cheapest(F.d, F.nd, 0, 2);
        md("- Fidelity (section 4), deployment: ");
        if (a) md("an animation of the whole sequence needs at least %s (%.3g x faster than the paper's settings, CPU)", f_row_name(a, b1, sizeof b1, 0), F.d[0].cpu / a->cpu);
        else md("no level meets the animation criterion");
        if (v) md("; a vibration study %s (%.3g x).\n", f_row_name(v, b1, sizeof b1, 0), F.d[0].cpu / v->cpu);
        else md("; no level meets the vibration criterion.\n");
    }
    if (FT.ran && FT.res[0].ok) {
        int i, w = -1, wl = -1;
        for (i = 1; i < FT.n; i++) {
            if (!FT.res[i].ok || FT.spec[i].fid != RJ_LINK_FLEXIBLE) continue;
            if (FT.spec[i].load == FT_LOAD_NONE) { if (w < 0 || FT.res[i].ratio > FT.res[w].ratio) w = i; }
            else if (wl < 0 || FT.res[i].ratio > FT.res[wl].ratio) wl = i;
        }
        md("- Feature cost (section 5): the bare two-link scene takes **%.0f ns per step**", FT.res[0].med);
        if (w >= 0) md("; the dearest combination of joint features is *%s* at %+.0f %%", FT.spec[w].name, 100 * (FT.res[w].ratio - 1));
        if (wl >= 0) md("; the dearest load feature is *%s* at %+.0f %%", FT.spec[wl].name, 100 * (FT.res[wl].ratio - 1));
        md(".\n");
    }
}

int main(int argc, char **argv)
{
    const char *out = "BENCHMARKS.md", *plot = "docs/work_precision.png";
    static char cmd[2048], plot2[1024], cpu[256], date[64], load0[64], load1[64];
    static dhist H, HREF, HCHK;
    static tp_row tp[3], tp16[3], tpdb[3];   /* solver.energy_every 1 (default) and 16; 16 double-buffered */
    static drow dr[64];
    static irow ir[64], iref[3], ichk[3][2];
    static const int tp_el[3] = { 20, 200, 2000 };
    static const int dmeth[2] = { RJ_METHOD_PENALTY, RJ_METHOD_ADAPTIVE };
    static const int imeth[3] = { RJ_METHOD_ADAPTIVE, RJ_METHOD_PENALTY, RJ_METHOD_MOMENTUM };
    drow dref, dchk[2], dpaper;
    double iref_unconverged[3] = { 0, 0, 0 };
    int i, j, k, ndr = 0, nir = 0, cores, plot_failed = 0, only = 0, out_given = 0, plot_given = 0;
    const char *native = NULL;
    const char *peer = NULL;
    char *peer_md = NULL;
    static char native_md[2048];
    double paper_w[32], paper_c[32], paper_med = 0, paper_cpu = 0, paper16_med = 0, paper16_cpu = 0, t_total;
    long paper_steps = 0;
    double paper_lock[2] = { 0, 0 }, paper_model_pn = 0, paper_state_pn = 0;
    FILE *f;
    time_t tnow;

    T_START = now();
    CAL0 = calibrate();
    native_md[0] = 0;
    memset(&dpaper, 0, sizeof dpaper);
    loadavg(load0, sizeof load0);
    for (i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--out") && i + 1 < argc) { out = argv[++i]; out_given = 1; }
        else if (!strcmp(argv[i], "--plot") && i + 1 < argc) { plot = argv[++i]; plot_given = 1; }
        else if (!strcmp(argv[i], "--quick")) S.quick = 1;
        else if (!strcmp(argv[i], "--native") && i + 1 < argc) native = argv[++i];
        else if (!strcmp(argv[i], "--peer") && i + 1 < argc) peer = argv[++i];
        else if (!strcmp(argv[i], "--only") && i + 1 < argc) {
            i++;
            if (!strcmp(argv[i], "fidelity")) only = 1;
            else if (!strcmp(argv[i], "features")) only = 2;
            else if (!strcmp(argv[i], "throughput")) only = 3;
            else if (!strcmp(argv[i], "build")) only = 4;
            else { fprintf(stderr, "bench: --only: unknown section '%s' (fidelity, features, throughput or build)\n%s", argv[i], usage); return 2; }
        }
        else if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) { fputs(usage, stdout); return 0; }
        else { fprintf(stderr, "bench: unknown option or missing value: '%s'\n%s", argv[i], usage); return 2; }
    }
    if (native) {
        FILE *g = fopen(native, "r");
        size_t n = g ? fread(native_md, 1, sizeof native_md - 1, g) : 0;
        native_md[n] = 0;
        if (g) fclose(g);
        else fprintf(stderr, "bench: --native %s: cannot read it; section 1 goes without it\n", native);
    }
    /* the MuJoCo side-by-side section of build/peer_side, quoted whole as section 7 */
    if (peer) {
        peer_md = read_fragment(peer);
        if (!peer_md) fprintf(stderr, "bench: --peer %s: cannot read it; the report goes without section 7\n", peer);
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

    if (!only || only == 3) {
        /* ---------------------------------------------------------------- 1 */
        for (i = 0; i < 3; i++) {
            tp_row three[3];
            if (free_link(tp_el[i], three)) return 1;
            tp[i] = three[0]; tp16[i] = three[1]; tpdb[i] = three[2];
            progress("free link %4d elements: %.2f ns/element-step, %.2f with energy_every 16, %.2f the same double-buffered (median of %d x %ld steps each, alternating)",
                     tp_el[i], tp[i].ns_med, tp16[i].ns_med, tpdb[i].ns_med, tp[i].runs, tp[i].steps);
        }
        {
            deploy_opts o = deploy_default_opts(), o16 = deploy_default_opts();
            rj_model *m, *m16; rj_state *s, *s16; rj_error err;
            double w16[32] = { 0 }, c16[32] = { 0 }; /* gcc 12 -O2 cannot tell the runs fill them */
            o16.energy_every = 16;
            if (deploy_build(&o, &m, &err) != RJ_OK || deploy_build(&o16, &m16, &err) != RJ_OK) { fprintf(stderr, "bench: deploy: %s\n", err.msg); return 1; }
            rj_state_create(m, &s, NULL); rj_state_create(m16, &s16, NULL);
            /* energy_every 1 and 16 alternate, so that both see the same phases of the machine */
            for (k = 0; k < S.paper_runs; k++) {
                double t0, c0;
                rj_result r;
                rj_state_reset(m, s);
                t0 = now(); c0 = cpu_now();
                r = rj_run(m, s, 6.0, 0, NULL, NULL);
                paper_w[k] = now() - t0; paper_c[k] = cpu_now() - c0;
                if (r != RJ_OK) { fprintf(stderr, "bench: deploy: %s\n", rj_state_error(s)); return 1; }
                rj_state_reset(m16, s16);
                t0 = now(); c0 = cpu_now();
                r = rj_run(m16, s16, 6.0, 0, NULL, NULL);
                w16[k] = now() - t0; c16[k] = cpu_now() - c0;
                if (r != RJ_OK) { fprintf(stderr, "bench: deploy: %s\n", rj_state_error(s16)); return 1; }
            }
            paper16_med = median(w16, S.paper_runs);
            paper16_cpu = median(c16, S.paper_runs);
            rj_state_destroy(s16, NULL); rj_model_destroy(m16, NULL);
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
        if (only == 3) {
            /* the fragment that a build with other flags contributes (--native) */
            FILE *g = out_given ? fopen(out, "w") : stdout;
            if (!g) { fprintf(stderr, "bench: cannot write %s\n", out); return 1; }
            fprintf(g, "| build `%s` (%s) | 20 elements | 200 | 2000 | deployment, paper's settings (wall / CPU) |\n|---|---:|---:|---:|---:|\n", BENCH_CFLAGS, compiler());
            fprintf(g, "| ns per element-step (median of %d) / s | **%.2f** | **%.2f** | **%.2f** | **%.3f s** / %.3f s |\n", S.tp_runs, tp[0].ns_med, tp[1].ns_med, tp[2].ns_med, paper_med, paper_cpu);
            fprintf(g, "| the same, `solver.energy_every = 16` | **%.2f** | **%.2f** | **%.2f** | **%.3f s** / %.3f s |\n", tp16[0].ns_med, tp16[1].ns_med, tp16[2].ns_med, paper16_med, paper16_cpu);
            fprintf(g, "| the same, `solver.in_place` off (double-buffered; only 2000 elements step in place with AUTO) | %.2f | %.2f | **%.2f** | |\n", tpdb[0].ns_med, tpdb[1].ns_med, tpdb[2].ns_med);
            fprintf(g, "\n(machine speed at this build's run: %.0f ms by `calibrate()`, comparable with the figures at the top)\n", CAL0);
            if (g != stdout) fclose(g);
            return 0;
        }

        /* ---------------------------------------------------------------- 2 */
        if (rigid_locks()) return 1;
        /* reference: adaptive, fine mesh, top / div; checks: same mesh at 2x the step, half the mesh at the same fraction of its bound */
        if (deploy_reference(&dref, &HREF, dchk, &HCHK)) return 1;
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
                if (work_precision_plot(ctx, plot, "Deployment (paper sec. 5): q1, q2 before joint 2 locks", "max abs(q - q_ref) (deg)", dr, ndr, 0, 0.1, err, sizeof err)) {
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
        fidelity_section(&HREF, &dref, dchk, 1, argv[0]);
        if (fidelity_plots(plot)) plot_failed = 1;
        features_section();
    } else if (only == 4) {
        /* written with the report, after section 5 */
    } else if (only == 1) {
        S.d_ref_el = S.quick ? 20 : 40;
        if (rigid_locks() || deploy_reference(&dref, &HREF, dchk, &HCHK)) return 1;
        fidelity_section(&HREF, &dref, dchk, 0, argv[0]);
        if (plot_given && fidelity_plots(plot)) plot_failed = 1;   /* --only: plots only when asked for */
    } else features_section();

    /* ---------------------------------------------------------------- report */
    /* (written below: checks on refinement, cheapest settings, tables) */
    if (!only) {
        {
            char b1[32];
            md("## Headline\n\n");
            md("- Step cost, one free link: **%.1f / %.1f / %.1f ns per element-step** at %d / %d / %d elements (median of %d runs).\n",
               tp[0].ns_med, tp[1].ns_med, tp[2].ns_med, tp[0].elements, tp[1].elements, tp[2].elements, S.tp_runs);
            md("- Deployment at the paper's settings (10 elements per link, dt 7.5 us, 6 s): **%.3f s** wall (CPU %.3f s), **%.3g steps/s**.\n", paper_med, paper_cpu, paper_steps / paper_med);
            md("- With `solver.energy_every = 16` (energy accounts and blow-up checks every 16th step and at every sample; the same results bit for bit): **%.1f / %.1f / %.1f ns per element-step**; the paper's settings in **%.3f s** (CPU %.3f s).\n",
               tp16[0].ns_med, tp16[1].ns_med, tp16[2].ns_med, paper16_med, paper16_cpu);
            md("- The %d-element link steps in place (`solver.in_place` AUTO: from 400 nodes on; the same results bit for bit). Double-buffered (`in_place` off, `energy_every = 16`, timed alternately with the rows above) it takes **%.1f ns per element-step**, against %.1f in place.\n",
               tp16[2].elements, tpdb[2].ns_med, tp16[2].ns_med);
            for (j = 0; j < 2; j++) {
                const drow *b = d_cheapest(dr, ndr, dmeth[j], 0);
                if (!b) { md("- Deployment, %s: no setting in the sweep keeps q within 0.1 deg and the tip RMS within 2 %%.\n", method_name(dmeth[j])); continue; }
                md("- Deployment, cheapest %s setting with q within 0.1 deg before joint 2 locks and the tip RMS within 2 %%: **%d elements per link, dt %.4g us, %.3f s** (CPU %.3f s; "
                   "dq %.4f deg, tip RMS %+.2f %%, frequency %+.2f %%).\n", method_name(dmeth[j]), b->el, b->dt * 1e6, b->wall, b->cpu, b->e.dq, 100 * b->e.rms_t, 100 * b->e.freq_t);
            }
            md("- Deployment reference: adaptive, %d elements, dt %.4g us (%.1f s); against it, twice its step moves q by %.4f deg and half its mesh by %.4f deg.\n",
               dref.el, dref.dt * 1e6, dref.wall, dchk[0].e.dq, dchk[1].e.dq);
            headline_fidelity_features();
            if (native_md[0]) md("\nThe same step costs from a build with `make bench`'s native flags (same code, same results bit for bit; only the compiler's vectorisation differs):\n\n%s", native_md);
            md("\n");
            md("## 1. Throughput\n\n");
            md("One free flexible link (`rj_default_link_def()`, height 0.01 m, 1 m, spinning at omega = 1 rad/s, no joints), dt = 0.9 x its stability bound. "
               "Each timed run is `rj_step` in a loop of the given number of steps (at least %.2g s), from a reset state; median of %d runs. "
               "Energy drift: relative change of the total energy over one run (a check that the steps did real work and stayed stable).\n\n", S.tp_min_time, S.tp_runs);
            md("| elements | dt (us) | steps per run | ns / element-step (median) | min | max | CPU ns / element-step | model bytes / node | state bytes / node | energy drift |\n");
            md("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
            for (i = 0; i < 9; i++) {
                const tp_row *w = i < 3 ? &tp[i] : i < 6 ? &tp16[i - 3] : &tpdb[i - 6];
                fmt_dt(b1, sizeof b1, w->dt);
                md("| %d%s | %s | %ld | **%.2f** | %.2f | %.2f | %.2f | %.0f | %.0f | %.1e |\n", w->elements,
                   i < 3 ? "" : i < 6 ? ", `energy_every = 16`" : ", `energy_every = 16`, `in_place` off", b1, w->steps, w->ns_med, w->ns_min, w->ns_max,
                   w->ns_cpu, w->model_per_node, w->state_per_node, w->edrift);
            }
            md("\nThe first six rows use `solver.in_place` AUTO: the 2000-element link (2001 nodes) steps in place, the others (under 400 nodes) double-buffered, so their rows with `in_place` off time the same code. "
               "In place keeps a third frame, hence the larger state per node at 2000 elements.\n");
            md("\nDeployment at the paper's settings (`deploy_build` defaults: 10 elements per link, dt = 7.5 us, joint 2 penalty with K = Eq 31 = %.4g N m/rad; stability bound %.4g us), "
               "6 s simulated, `rj_run` without sampling, median of %d runs: **%.3f s** wall (CPU %.3f s), %ld steps, **%.0f steps/s** "
               "(%.1f ns per element-step over its 20 elements). Joint 2 locks at %.6f s, joint 1 at %.6f s. "
               "Model %.0f bytes / node, state %.0f bytes / node (22 nodes). With `solver.energy_every = 16`: **%.3f s** wall (CPU %.3f s).\n\n",
               dpaper.K, dpaper.bound * 1e6, S.paper_runs, paper_med, paper_cpu, paper_steps, paper_steps / paper_med, 1e9 * paper_med / (paper_steps * 20.0),
               paper_lock[1], paper_lock[0], paper_model_pn, paper_state_pn, paper16_med, paper16_cpu);
            if (native_md[0])
                md("Built for this machine (`make bench` builds `build/bench_native` and runs `--only throughput`; the library's results do not change with these flags, "
                   "the golden histories are bit-identical under them):\n\n%s\n", native_md);
        }

        /* rendering */
        {
            double fps[2], dms[2];
            char rname[256];
            bench_render(fps, dms, rname, sizeof rname);
            md("### Rendering\n\n");
            md("A deployment frame (t = 3.1 s) drawn with `render/rj_render.c` (4x MSAA) and written as PNG (zlib level 1, no filters), "
               "one context per size created once and not timed; median of 3 batches of 30 frames. Renderer: %s.\n\n", rname);
            md("| size | frames/s with PNG writing | draw + read back only (ms/frame) |\n|---|---:|---:|\n");
            md("| 640x480 | **%.0f** | %.2f |\n| 1280x720 | **%.0f** | %.2f |\n\n", fps[0], dms[0], fps[1], dms[1]);
        }

        /* deployment section */
        {
            char b1[32];
            md("## 2. Deployment (paper sec. 5): speed against error\n\n");
            md("Joint 1 forced, joint 2 locked by the method named; 6 s simulated; wall time = `rj_run` with a 1 ms sample callback "
               "and `solver.energy_every = 16` as `build/deploy` runs it (the same histories bit for bit as 1; about 10 %% fewer instructions at the paper's settings, `sh bench/instr.sh -O2 \"\" 16`) "
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
            md("## 3. Impact on a reverse limit (paper sec. 4): speed against error\n\n");
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
    }
    if (F.ran) fidelity_report();
    if (FT.ran) features_report();
    /* section 6 times model builds itself; it runs last so its report follows section 5 */
    if (!only || only == 4) build_section();
    if (!only && peer_md) md("## 7. Side by side with a MuJoCo peer\n\n%s\n", peer_md);
    free(peer_md);


    t_total = now() - T_START;
    loadavg(load1, sizeof load1);
    CAL1 = calibrate();
    tnow = time(NULL);
    strftime(date, sizeof date, "%Y-%m-%d %H:%M:%S UTC", gmtime(&tnow));
    machine(cpu, sizeof cpu, &cores);
    /* --only without --out writes to standard output, so that it never overwrites the full report */
    if (only && !out_given) out = NULL;
    f = out ? fopen(out, "w") : stdout;
    if (!f) { fprintf(stderr, "bench: cannot write %s\n", out); return 1; }
    fprintf(f, "# revjoint.h benchmarks\n\n");
    if (only)
        fprintf(f, "Generated by `bench/bench.c --only %s`: only section %d; `make bench` writes every section.%s\n\n",
                only == 1 ? "fidelity" : only == 4 ? "build" : "features", only == 1 ? 4 : only == 4 ? 6 : 5,
                S.quick ? " **This is a `--quick` run: short timings and coarse references, for smoke tests only.**" : "");
    else
        fprintf(f, "Generated by `bench/bench.c` (`make bench`); do not edit by hand, every number below is rewritten by each run.%s\n\n",
                S.quick ? " **This is a `--quick` run: short timings and coarse references, for smoke tests only.**" : "");
    fprintf(f, "| | |\n|---|---|\n");
    fprintf(f, "| command | `%s` |\n| date | %s |\n| CPU | %s |\n| logical cores | %d |\n| compiler | %s |\n| flags (make bench) | `%s` |\n",
            cmd, date, cpu, cores, compiler(), BENCH_CFLAGS);
    fprintf(f, "| revjoint.h | %s |\n| whole run | %.0f s |\n| load average (1, 5, 15 min) | %s at the start, %s at the end |\n", RJ_VERSION, t_total, load0, load1);
    fprintf(f, "| machine speed (`calibrate()` in bench.c: a fixed loop, best of 3; smaller is faster) | %.0f ms at the start, %.0f ms at the end |\n\n", CAL0, CAL1);
    fprintf(f, "The machine may be shared, so every time is a median; runs are sequential, on one core. Wall times are `CLOCK_MONOTONIC`. The CPU columns "
               "(`CLOCK_PROCESS_CPUTIME_ID`) leave out time spent descheduled. When the load average is above the core count, trust CPU more than wall.\n\n");
    if (NNOTES) {
        fprintf(f, "**Found by this run (see below):**\n\n");
        for (i = 0; i < NNOTES; i++) fprintf(f, "- %s\n", NOTES[i]);
        fprintf(f, "\n");
    }
    fwrite(R.p, 1, R.n, f);
    if (f != stdout) fclose(f); else fflush(f);
    if (only) progress("wrote %s (total %.1f s)", out ? out : "the report to standard output", t_total);
    else progress("wrote %s%s%s%s%s (total %.1f s)", out, plot_failed ? "" : ", ", plot_failed ? "" : plot, plot_failed ? "" : ", ", plot_failed ? "" : plot2, t_total);
    free(R.p);
    return plot_failed ? 1 : 0;
}
