/* stress.c - the numerical-stability suite (see tests/stress.md for the design and the
   readings behind every number).

     build/stress                  full suite (1e6 / 1e7-step runs; several minutes)
     build/stress --short          the version inside `make test` (well under 20 s)
     build/stress --table FILE     also write the markdown results table to FILE
     build/stress --only N         run check N only (1-8; 9 = blow-up detection)

   Every case runs every limit method (penalty, adaptive, momentum, forced, energy) and both
   release rules where they apply, and adds one row per run to a markdown table (printed at
   the end): stable or not, peak energy relative to the initial, largest |energy balance|,
   peak penetration, and the first thing that went wrong (error or warning text, or a
   blow-up the library did not report). Each check prints one PASS/FAIL line (tests/rjt.h);
   the comment above each check names the protection in the library it exercises, i.e. what
   has to be removed or broken for it to fail. */
#define _POSIX_C_SOURCE 200112L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <math.h>
#include <time.h>
#include "../revjoint.h"
/* pi as the library writes it (the stress scenes place angles with it) */
#define ST_PI 3.14159265358979323846
#include "../examples/scenes.h"
#include "rjt.h"

/* ------------------------------------------------------------------ options, clock */
static int g_short = 0;

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static const char *method_name(int m)
{
    static const char *n[] = { "penalty", "adaptive", "momentum", "forced", "energy" };
    return m >= 0 && m < 5 ? n[m] : "-";
}
static const char *release_name(int r) { return r == RJ_RELEASE_RC12 ? "rc12" : r == RJ_RELEASE_RC13 ? "rc13" : "-"; }

/* ------------------------------------------------------------------ the results table */
typedef struct row {
    char kase[96], method[12], release[8], stable[24], first[600];
    double dt, dt_ratio, epeak, bal, pen;
} row;
/* first problem: up to ~400 characters */
#define MAX_ROWS 600
static row g_rows[MAX_ROWS];
static int g_nrows = 0;

/* ------------------------------------------------------------------ scenes */
#define MAXL 12
typedef struct scn { rj_link_def L[MAXL]; rj_joint_def J[MAXL]; rj_scene_def sc; } scn;

static void scn_fix(scn *b) { b->sc.links = b->L; b->sc.joints = b->J; }
static rj_result scn_make(scn *b, double dt, int allow, rj_model **m, rj_error *e)
{
    scn_fix(b);
    b->sc.solver.dt = dt;
    b->sc.solver.allow_unstable = allow;
    return rj_model_create(&b->sc, m, e, NULL);
}
/* method / release on every joint that has a limit or a lock */
static void scn_method(scn *b, int method, int release)
{
    int j;
    for (j = 0; j < b->sc.joint_count; j++) {
        if (!b->J[j].has_forward && !b->J[j].has_reverse) continue;
        b->J[j].method = method;
        b->J[j].release = release;
        if (method == RJ_METHOD_PENALTY && !(b->J[j].penalty_k > 0)) b->J[j].penalty_k = 1.0;
    }
}
/* The stability bound that goes with a step dt (for adaptive limits the bound depends on dt,
   K_AP = I_red / dt^2). */
static double bound_at(scn *b, double dt)
{
    rj_model *m; rj_error e; double bd;
    if (scn_make(b, dt, 1, &m, &e) != RJ_OK) return -1;
    bd = rj_model_dt_bound(m);
    rj_model_destroy(m, NULL);
    return bd;
}
static int scn_has_adaptive(const scn *b)
{
    int j;
    for (j = 0; j < b->sc.joint_count; j++)
        if ((b->J[j].has_forward || b->J[j].has_reverse) && b->J[j].method == RJ_METHOD_ADAPTIVE) return 1;
    return 0;
}
/* dt = f x bound. With adaptive limits the bound depends on dt (K_AP = I_red / dt^2 puts
   that joint at omega dt ~ 1 by construction), so f is taken of the links' bound (the same
   scene with velocity-level limits); *bound is the scene's own bound at that dt. */
static double dt_for_factor(scn *b, double f, double *bound)
{
    double dt;
    if (scn_has_adaptive(b)) {
        scn t = *b;
        int j;
        for (j = 0; j < t.sc.joint_count; j++) if (t.J[j].method == RJ_METHOD_ADAPTIVE) t.J[j].method = RJ_METHOD_MOMENTUM;
        dt = f * bound_at(&t, 0);
        scn_fix(b);
    } else dt = f * bound_at(b, 0);
    if (bound) *bound = bound_at(b, dt);
    return dt;
}
/* The stiffest penalty the library accepts at dt: penalty_k = s K_AP (Eq 21 at dt, from the
   joint's own I1, I2) on every limited joint, s bisected on acceptance by rj_model_create.
   Leaves the scene at that stiffness and returns s (0 when even s = 1e-9 is refused). */
static double scn_penalty_max(scn *b, double dt)
{
    double kap[MAXL], lo = 1e-9, hi = 1e3, I1, I2;
    rj_model *m; rj_error e;
    int j, it, nj = b->sc.joint_count;
    scn t = *b;
    scn_method(&t, RJ_METHOD_MOMENTUM, RJ_RELEASE_RC13);
    if (scn_make(&t, dt, 1, &m, &e) != RJ_OK) return 0;
    for (j = 0; j < nj; j++) { rj_joint_inertias(m, j, &I1, &I2); kap[j] = rj_k_adaptive(I1, I2, dt); }
    rj_model_destroy(m, NULL);
    for (it = 0; it < 60; it++) {
        double s = it == 0 ? lo : sqrt(lo * hi);
        int ok;
        for (j = 0; j < nj; j++) if (b->J[j].has_forward || b->J[j].has_reverse) b->J[j].penalty_k = s * kap[j];
        ok = scn_make(b, dt, 0, &m, &e) == RJ_OK;
        if (ok) rj_model_destroy(m, NULL);
        if (it == 0) { if (!ok) return 0; continue; }
        if (ok) lo = s; else hi = s;
        if (hi / lo < 1.0 + 1e-6) break;
    }
    for (j = 0; j < nj; j++) if (b->J[j].has_forward || b->J[j].has_reverse) b->J[j].penalty_k = lo * kap[j];
    return lo;
}

/* ------------------------------------------------------------------ the watch: one step, every test */
typedef struct watch {
    double growth;
    long steps;
    rj_result r;
    double e0; int have_e0;
    double epeak, bal, uratio;
    long warns; double t_warn; char warn[256];
    double t_err; char err[400];
    int undet; double t_undet, undet_u, undet_lim;
    int nonfinite; double t_nonfinite;
    double wall;
} watch;

static int state_finite(const rj_model *m, const rj_state *s)
{
    int l, i, j;
    for (l = 0; l < rj_model_link_count(m); l++)
        for (i = 0; i < rj_link_node_count(m, l); i++) {
            double p[2], v[2], a, w;
            rj_node_position(m, s, l, i, p); rj_node_velocity(m, s, l, i, v);
            a = rj_node_rotation(m, s, l, i); w = rj_node_rate(m, s, l, i);
            if (!(isfinite(p[0]) && isfinite(p[1]) && isfinite(v[0]) && isfinite(v[1]) && isfinite(a) && isfinite(w))) return 0;
        }
    for (j = 0; j < rj_model_joint_count(m); j++)
        if (!(isfinite(rj_joint_theta_running(m, s, j)) && isfinite(rj_joint_rate(m, s, j)))) return 0;
    return 1;
}

static void watch_init(watch *w, const rj_model *m)
{
    memset(w, 0, sizeof *w);
    w->growth = 10.0;   /* rj_default_solver_def().energy_growth; every scene here keeps it */
    (void)m;
    w->r = RJ_OK;
    w->epeak = -HUGE_VAL;
}

/* One rj_step plus the bookkeeping every run shares. Besides the library's own verdict it
   applies the documented blow-up rule (solver.energy_growth: "blow-up when total energy
   exceeds 10 x max(initial energy, energy put in by springs)") to the physical energies:
   the strain energy (>= 0) and |kinetic| (the true kinetic energy is at least that) must
   stay below energy_growth x (|E0| + spring energy). A step that exceeds UNDET_GRACE times
   that and still returns RJ_OK is recorded as an undetected blow-up; the grace keeps a
   report that comes a step or two late from counting, a blow-up that runs on does. */
#define UNDET_GRACE 2.0
static rj_result watch_step(watch *w, const rj_model *m, rj_state *s)
{
    rj_result r = rj_step(m, s);
    rj_energy e;
    double u, lim;
    long c;
    if (r != RJ_OK) {
        if (w->r == RJ_OK) { w->r = r; snprintf(w->err, sizeof w->err, "%s", rj_state_error(s)); w->t_err = rj_state_time(s); }
        return r;
    }
    w->steps++;
    rj_state_energy(m, s, &e);
    if (!w->have_e0) { w->e0 = e.total + e.lost_damping + e.lost_friction + e.lost_limit - e.balance; w->have_e0 = 1; }
    if (!(isfinite(e.total) && isfinite(e.balance))) {
        if (!w->nonfinite) { w->nonfinite = 1; w->t_nonfinite = rj_state_time(s); }
    } else {
        double d = fabs(w->e0) > 0 ? fabs(w->e0) : 1e-300;
        if (e.total / d > w->epeak) w->epeak = e.total / d;
        if (fabs(e.balance) / d > w->bal) w->bal = fabs(e.balance) / d;
    }
    u = e.strain > fabs(e.kinetic) ? e.strain : fabs(e.kinetic);
    lim = w->growth * (fabs(w->e0) + 2.0 * fabs(e.spring) + 1e-9);
    if (u / lim > w->uratio) w->uratio = u / lim;
    if (!(u <= UNDET_GRACE * lim) && !w->undet) { w->undet = 1; w->t_undet = rj_state_energy_time(s); w->undet_u = u; w->undet_lim = lim; }
    c = rj_state_warning_count(s);
    if (c > w->warns) {
        if (w->warns == 0) { w->t_warn = rj_state_time(s); snprintf(w->warn, sizeof w->warn, "%s", rj_state_warning(s)); }
        w->warns = c;
    }
    return r;
}
/* n steps or until the first error */
static rj_result watch_run(watch *w, const rj_model *m, rj_state *s, long n)
{
    long k;
    double t0 = now_s();
    rj_result r = RJ_OK;
    for (k = 0; k < n && r == RJ_OK; k++) r = watch_step(w, m, s);
    if (r == RJ_OK && !state_finite(m, s) && !w->nonfinite) { w->nonfinite = 1; w->t_nonfinite = rj_state_time(s); }
    w->wall += now_s() - t0;
    return r;
}
static double state_peak_pen(const rj_model *m, const rj_state *s)
{
    double p = 0;
    int j;
    for (j = 0; j < rj_model_joint_count(m); j++) if (rj_joint_peak_penetration(m, s, j) > p) p = rj_joint_peak_penetration(m, s, j);
    return p;
}
/* stable: no error, finite, no undetected blow-up, energy within elim x E0 */
static int watch_stable(const watch *w, double elim)
{
    return w->r == RJ_OK && !w->nonfinite && !w->undet && w->epeak <= elim;
}
static void clean(char *t)
{
    for (; *t; t++) if (*t == '|' || *t == '\n') *t = '/';
}
/* the table row of one run; stable_txt overrides the yes/no column when given */
static void row_add(const char *kase, int method, int release, double dt, double bound, const watch *w, double pen, const char *stable_txt, double elim)
{
    row *r;
    char ev[3][400];
    double tv[3];
    int n = 0, i, k;
    if (g_nrows >= MAX_ROWS) return;
    r = &g_rows[g_nrows++];
    memset(r, 0, sizeof *r);
    snprintf(r->kase, sizeof r->kase, "%s", kase);
    snprintf(r->method, sizeof r->method, "%s", method_name(method));
    snprintf(r->release, sizeof r->release, "%s", release_name(release));
    r->dt = dt; r->dt_ratio = bound > 0 ? dt / bound : 0;
    r->epeak = w ? w->epeak : 0; r->bal = w ? w->bal : 0; r->pen = pen;
    if (stable_txt) snprintf(r->stable, sizeof r->stable, "%s", stable_txt);
    else if (w && watch_stable(w, elim)) snprintf(r->stable, sizeof r->stable, "yes");
    else if (w && (w->undet || w->nonfinite)) snprintf(r->stable, sizeof r->stable, "NO (undetected)");
    else if (w && w->r != RJ_OK) snprintf(r->stable, sizeof r->stable, "no (detected)");
    else snprintf(r->stable, sizeof r->stable, "NO (energy grew)");
    if (w) {
        /* everything that went wrong, earliest first */
        if (w->warns) { tv[n] = w->t_warn; snprintf(ev[n++], 400, "warning x%ld, first: %s", w->warns, w->warn); }
        if (w->undet) { tv[n] = w->t_undet; snprintf(ev[n++], 400, "UNDETECTED blow-up at t = %.6g s: strain or kinetic energy %.3g J > 2 x %.3g J (10 x E0) while rj_step returned RJ_OK", w->t_undet, w->undet_u, w->undet_lim); }
        if (w->r != RJ_OK) { tv[n] = w->t_err; snprintf(ev[n++], 400, "%s: %s", w->r == RJ_ERR_TUNNEL ? "RJ_ERR_TUNNEL" : w->r == RJ_ERR_BLOWUP ? "RJ_ERR_BLOWUP" : rj_result_str(w->r), w->err); }
        for (i = 0; i < n; i++) for (k = i + 1; k < n; k++) if (tv[k] < tv[i]) {
            char tmp[400]; double t = tv[i];
            memcpy(tmp, ev[i], 400); memcpy(ev[i], ev[k], 400); memcpy(ev[k], tmp, 400);
            tv[i] = tv[k]; tv[k] = t;
        }
        if (n == 0) snprintf(r->first, sizeof r->first, "none");
        else if (n == 1) snprintf(r->first, sizeof r->first, "%s", ev[0]);
        else snprintf(r->first, sizeof r->first, "%.230s; then %.160s", ev[0], ev[1]);
    } else snprintf(r->first, sizeof r->first, "-");
    clean(r->first);
}
static void row_note(const char *kase, int method, int release, double dt, double bound, const char *stable_txt, const char *text)
{
    row_add(kase, method, release, dt, bound, NULL, 0, stable_txt, 0);
    snprintf(g_rows[g_nrows - 1].first, sizeof g_rows[g_nrows - 1].first, "%s", text);
    clean(g_rows[g_nrows - 1].first);
}
static void table_print(FILE *f)
{
    int i;
    fprintf(f, "| case | method | release | dt (us) | dt/bound | stable | peak E/E0 | max \\|balance\\|/E0 | peak penetration rad (deg) | first problem |\n");
    fprintf(f, "|---|---|---|---:|---:|---|---:|---:|---:|---|\n");
    for (i = 0; i < g_nrows; i++) {
        const row *r = &g_rows[i];
        fprintf(f, "| %s | %s | %s | %.4g | %.4g | %s | %.7g | %.2g | %.3g (%.3g) | %s |\n", r->kase, r->method, r->release,
                r->dt * 1e6, r->dt_ratio, r->stable, r->epeak, r->bal, r->pen, rj_deg(r->pen), r->first);
    }
}

/* ------------------------------------------------------------------ model builders */
/* A free flexible link (aluminium, 1 m, 10 elements, 50 mm wide, depth H) in rigid motion:
   1 m/s along x and 2 rad/s. No joints: its bound is the link's own. */
static void build_free(scn *b, double H)
{
    memset(b, 0, sizeof *b);
    b->L[0] = rj_default_link_def();
    b->L[0].height = H; b->L[0].vx = 1.0; b->L[0].omega = 2.0;
    b->sc = rj_default_scene_def();
    b->sc.link_count = 1; b->sc.joint_count = 0;
    scn_fix(b);
}
/* A flexible strip (1 m, 10 elements, 50 x 10 mm) pinned to ground, 3 rad/s, swinging on a
   torsion spring (50 N m/rad, free angle 0.5 rad): no limits, so the link bound rules. */
static void build_pinned(scn *b)
{
    memset(b, 0, sizeof *b);
    b->L[0] = rj_default_link_def();
    b->L[0].height = 0.01;
    b->J[0] = rj_default_joint_def();
    b->J[0].body1 = -1; b->J[0].body2 = 0; b->J[0].angle0 = 0.0; b->J[0].rate0 = 3.0;
    b->J[0].spring_k = 50.0; b->J[0].spring_free_angle = 0.5;
    b->sc = rj_default_scene_def();
    b->sc.link_count = 1; b->sc.joint_count = 1;
    scn_fix(b);
}
/* The deployment (paper sec. 5, examples/scenes.h) with one limit method on both joints and,
   for penalty, K fixed at Eq 31 for the paper's 7.5 us (so the scene does not change with
   dt): its bound is the links' (Eq 31 K is far below what the bound admits). */
static double g_deploy_K[2];
static void deploy_eq31(void)
{
    deploy_opts o = deploy_default_opts();
    rj_model *m; rj_error e;
    o.joint2_K = 1.0;
    if (deploy_build(&o, &m, &e) != RJ_OK) { printf("deployment does not build: %s\n", e.msg); exit(2); }
    g_deploy_K[0] = rj_joint_kmax_eq31(m, 0, 7.5e-6);
    g_deploy_K[1] = rj_joint_kmax_eq31(m, 1, 7.5e-6);
    rj_model_destroy(m, NULL);
}
static void build_deploy(scn *b, int method)
{
    deploy_opts o = deploy_default_opts();
    memset(b, 0, sizeof *b);
    deploy_scene(&o, b->L, b->J, &b->sc);
    b->J[0].method = method; b->J[1].method = method;
    b->J[0].penalty_k = g_deploy_K[0]; b->J[1].penalty_k = g_deploy_K[1];
    scn_fix(b);
}

/* ------------------------------------------------------------------ step-by-step with a kept copy */
typedef struct keepres {
    int stopped;        /* rj_step returned an error */
    int intact;         /* ... and the state equals the copy taken before that step */
    int warn_same;      /* ... and the warning text too */
    int silent_nonfinite; /* some RJ_OK step left a non-finite value in the state */
    long at_step;
} keepres;

static int same_frame(const rj_model *m, const rj_state *a, const rj_state *b)
{
    size_t n = rj_state_save(m, a, NULL, 0);
    unsigned char *ba = (unsigned char *)malloc(n), *bb = (unsigned char *)malloc(n);
    int same;
    rj_state_save(m, a, ba, n); rj_state_save(m, b, bb, n);
    same = memcmp(ba, bb, n) == 0;
    free(ba); free(bb);
    return same;
}

/* Steps n times or until an error, copying the state before every step (rj_state_copy) and
   checking after every RJ_OK step that the state is finite. */
static rj_result run_keep(const rj_model *m, rj_state *s, long n, watch *w, keepres *kr)
{
    rj_state *keep;
    rj_result r = RJ_OK;
    long k;
    double t0 = now_s();
    memset(kr, 0, sizeof *kr);
    rj_state_create(m, &keep, NULL);
    for (k = 0; k < n; k++) {
        rj_state_copy(m, keep, s);
        r = watch_step(w, m, s);
        if (r == RJ_OK) {
            if (!state_finite(m, s)) { kr->silent_nonfinite = 1; if (!w->nonfinite) { w->nonfinite = 1; w->t_nonfinite = rj_state_time(s); } break; }
            continue;
        }
        kr->stopped = 1; kr->at_step = k;
        kr->intact = same_frame(m, s, keep) && rj_state_time(s) == rj_state_time(keep) && state_finite(m, s);
        kr->warn_same = strcmp(rj_state_warning(s), rj_state_warning(keep)) == 0;
        break;
    }
    rj_state_destroy(keep, NULL);
    w->wall += now_s() - t0;
    return r;
}

/* ------------------------------------------------------------------ check 1: dt against the bound */
/* Runs the scene at f x bound for n steps; returns 1 when it blew up (detected or not, or
   energy above 1.5 E0). */
static int blows_up(scn *b, double f, long n)
{
    rj_model *m; rj_state *s = NULL; rj_error e; watch w;
    double dt = dt_for_factor(b, f, NULL);
    int bad;
    if (scn_make(b, dt, 1, &m, &e) != RJ_OK) return 1;
    rj_state_create(m, &s, NULL);
    watch_init(&w, m);
    watch_run(&w, m, s, n);
    bad = w.r != RJ_OK || w.undet || w.nonfinite || w.epeak > 1.5;
    rj_state_destroy(s, NULL); rj_model_destroy(m, NULL);
    return bad;
}
/* smallest factor of the bound that blows up within n steps, bisected between lo (stable)
   and hi (unstable); hi is widened first if needed */
static double threshold(scn *b, double lo, double hi, long n, int iters)
{
    int i;
    while (!blows_up(b, hi, n) && hi < 8.0) { lo = hi; hi *= 1.25; }
    for (i = 0; i < iters; i++) {
        double mid = 0.5 * (lo + hi);
        if (blows_up(b, mid, n)) hi = mid; else lo = mid;
    }
    return 0.5 * (lo + hi);
}

/* CHECK 1. Protection exercised: the stability bound computed by rj_model_create
   (Lanczos on the linearised model, 0.98 x 2/omega_max) and its refusal RJ_ERR_UNSTABLE_DT,
   the solver.allow_unstable override, and rj_step's blow-up detection (RJ_ERR_BLOWUP, message
   naming the step above the bound). Fails if the bound is not conservative (energy grows at
   <= 1.0 x bound), if the refusal is removed (1.1 x accepted without allow_unstable), or if
   the blow-up at 1.1 x goes unreported, leaves a broken state, or does not name the cause. */
static void check1(rjt_ctx *c)
{
    static const double fac[3] = { 0.5, 0.9, 1.0 };
    long n = g_short ? 100000L : 1000000L;
    int model, fi;
    char name[48], what[200];
    printf("\n## check 1: time step at 0.5 / 0.9 / 1.0 / 1.1 x rj_model_dt_bound (%ld steps)\n", n);
    deploy_eq31();
    for (model = 0; model < 9; model++) {
        scn b;
        int meth = -1, relv = -1;
        double elim, bd, dt, thr;
        rj_model *m; rj_state *s = NULL; rj_error e; rj_result r; watch w; keepres kr;
        if (model == 0) { build_free(&b, 0.05); snprintf(name, sizeof name, "free link H=0.05"); elim = 1.001; }
        else if (model == 1) { build_pinned(&b); snprintf(name, sizeof name, "pinned link"); elim = 1.001; }
        else if (model < 7) { meth = model - 2; build_deploy(&b, meth); snprintf(name, sizeof name, "deployment"); elim = 1.0 + 1e-6; }
        else {
            /* the impact benchmark with the default penalty K = 5e8 N m/rad: here the limit, counted
               4 K in the bound, is what limits, so 1.1 x bound may well be stable */
            impact_opts io = impact_default_opts();
            memset(&b, 0, sizeof b);
            io.method = meth = RJ_METHOD_PENALTY; io.release = relv = model == 7 ? RJ_RELEASE_RC12 : RJ_RELEASE_RC13;
            impact_scene(&io, b.L, &b.J[0], &b.sc);
            scn_fix(&b);
            snprintf(name, sizeof name, "impact H=0.2 K=5e8 %s", release_name(io.release));
            elim = 1.001;
        }
        for (fi = 0; fi < 3; fi++) {
            char kase[96];
            dt = dt_for_factor(&b, fac[fi], &bd);
            snprintf(kase, sizeof kase, "1: %.47s, %.1f x bound", name, fac[fi]);
            r = scn_make(&b, dt, 0, &m, &e);
            if (r != RJ_OK) {
                snprintf(what, sizeof what, "%s %s: rj_model_create accepts dt = %.1f x bound", name, method_name(meth), fac[fi]);
                if (meth == RJ_METHOD_ADAPTIVE && r == RJ_ERR_UNSTABLE_DT && dt > bd)
                    rjt_check(c, 1, what, "refused, consistently: dt %.6g us > its own bound %.6g us (K_AP at this dt adds to the links' omega_max): \"%s\"", dt * 1e6, bd * 1e6, e.msg);
                else
                    rjt_check(c, 0, what, "refused: %s", e.msg);
                row_note(kase, meth, relv, dt, bd, "refused", e.msg);
                continue;
            }
            rj_state_create(m, &s, NULL);
            watch_init(&w, m);
            watch_run(&w, m, s, n);
            row_add(kase, meth, relv, dt, bd, &w, state_peak_pen(m, s), NULL, elim);
            snprintf(what, sizeof what, "%s %s at %.1f x bound: %ld steps, energy bounded", name, method_name(meth), fac[fi], n);
            rjt_check(c, watch_stable(&w, elim) && w.steps == n, what,
                      "dt %.4g us (bound %.4g us), %ld steps = %.3g s, E_peak/E0 = %.9f <= %.6g, |balance|/E0 <= %.2g, strain/limit %.2g, %.2f s wall%s%s",
                      dt * 1e6, bd * 1e6, w.steps, rj_state_time(s), w.epeak, elim, w.bal, w.uratio, w.wall,
                      w.r != RJ_OK ? "; error: " : "", w.r != RJ_OK ? w.err : "");
            rj_state_destroy(s, NULL); rj_model_destroy(m, NULL);
        }
        /* 1.1 x: refused, then overridden */
        dt = dt_for_factor(&b, 1.1, &bd);
        r = scn_make(&b, dt, 0, &m, &e);
        if (r == RJ_OK) rj_model_destroy(m, NULL);
        snprintf(what, sizeof what, "%s %s at 1.1 x bound: rj_model_create refuses with RJ_ERR_UNSTABLE_DT", name, method_name(meth));
        rjt_check(c, r == RJ_ERR_UNSTABLE_DT && strstr(e.msg, "above the stability bound") != NULL, what, "\"%s\"", r == RJ_OK ? "(accepted)" : e.msg);
        r = scn_make(&b, dt, 1, &m, &e);
        if (r != RJ_OK) { rjt_check(c, 0, "allow_unstable accepts 1.1 x bound", "%s", e.msg); continue; }
        rj_state_create(m, &s, NULL);
        watch_init(&w, m);
        r = run_keep(m, s, n, &w, &kr);
        {
            char kase[96];
            snprintf(kase, sizeof kase, "1: %.47s, 1.1 x bound", name);
            row_add(kase, meth, relv, dt, bd, &w, state_peak_pen(m, s), NULL, elim);
        }
        if (r == RJ_ERR_BLOWUP) {
            snprintf(what, sizeof what, "%s %s at 1.1 x bound with allow_unstable: blow-up detected, named, last good state kept", name, method_name(meth));
            rjt_check(c, kr.intact && strstr(w.err, "above the stability bound") != NULL && strstr(w.err, "t = ") != NULL, what,
                      "after %ld steps: \"%s\"", w.steps, w.err);
            snprintf(what, sizeof what, "%s %s at 1.1 x bound: blow-up reported before the energy passed 2 x the documented 10 x E0", name, method_name(meth));
            if (w.undet)
                rjt_check(c, 0, what, "NOT: rj_step returned RJ_OK at t = %.6g s with strain/kinetic energy %.4g J > 2 x %.4g J (= 10 x (E0 + springs)); the largest on an RJ_OK step was %.3g x 10 E0, reported %ld steps later",
                          w.t_undet, w.undet_u, w.undet_lim, w.uratio, (long)floor((w.t_err - w.t_undet) / dt + 0.5));
            else
                rjt_check(c, 1, what, "largest (strain or |kinetic|) on an RJ_OK step: %.3g x 10 E0", w.uratio);
        } else {
            snprintf(what, sizeof what, "%s %s at 1.1 x bound with allow_unstable: blow-up detected as RJ_ERR_BLOWUP", name, method_name(meth));
            if (r == RJ_OK && watch_stable(&w, 1.5))
                rjt_check(c, 1, what, "no: STABLE for %ld steps (E_peak/E0 = %.6f): the bound is conservative here, see the threshold below", w.steps, w.epeak);
            else
                rjt_check(c, 0, what, "result %s after %ld steps, undetected %d, E_peak/E0 %.4g: \"%s\"", rj_result_str(r), w.steps, w.undet, w.epeak, w.err);
        }
        rj_state_destroy(s, NULL); rj_model_destroy(m, NULL);
        /* the real threshold, so the margin of the bound is on record */
        thr = threshold(&b, 1.0, 1.1, g_short ? n / 4 : n, g_short ? 6 : 10);
        snprintf(what, sizeof what, "%s %s: the real stability threshold lies at or above the bound", name, method_name(meth));
        rjt_check(c, thr >= 1.0, what, "blow-up within %ld steps from %.4f x bound (bound %.4g us, threshold %.4g us; linear theory 1/0.98 = 1.0204)%s",
                  g_short ? n / 4 : n, thr, bd * 1e6, thr * bd * 1e6, thr > 1.1 ? "; 1.1 x bound is STABLE for this model" : "");
    }
}

/* ------------------------------------------------------------------ one run of one scene */
typedef int (*step_hook)(const rj_model *m, const rj_state *s, void *user);
typedef struct caseres {
    rj_result create; char create_msg[520];
    watch w;
    double dt, bound, pen;
    double t_event[MAXL], t_release[MAXL], p0[MAXL], theta[MAXL];
    int flag[MAXL];
    long warns;
} caseres;

/* Builds the scene at dt (0 = automatic), runs it for t_end seconds (or until an error or
   until hook returns nonzero), adds the table row. */
static void run_case(scn *b, double dt, double t_end, const char *kase, int method, int release, double elim,
                     caseres *cr, step_hook hook, void *user)
{
    rj_model *m; rj_state *s = NULL; rj_error e;
    long n, k;
    int j;
    memset(cr, 0, sizeof *cr);
    cr->create = scn_make(b, dt, 0, &m, &e);
    if (cr->create != RJ_OK) {
        snprintf(cr->create_msg, sizeof cr->create_msg, "%s", e.msg);
        row_note(kase, method, release, dt, bound_at(b, dt), "refused", e.msg);
        return;
    }
    cr->dt = rj_model_dt(m); cr->bound = rj_model_dt_bound(m);
    rj_state_create(m, &s, NULL);
    watch_init(&cr->w, m);
    n = (long)ceil(t_end / cr->dt - 1e-9);
    {
        double t0 = now_s();
        for (k = 0; k < n; k++) {
            if (watch_step(&cr->w, m, s) != RJ_OK) break;
            if (hook && hook(m, s, user)) break;
        }
        if (cr->w.r == RJ_OK && !state_finite(m, s)) { cr->w.nonfinite = 1; cr->w.t_nonfinite = rj_state_time(s); }
        cr->w.wall = now_s() - t0;
    }
    cr->pen = state_peak_pen(m, s);
    for (j = 0; j < rj_model_joint_count(m) && j < MAXL; j++) {
        cr->t_event[j] = rj_joint_event_time(m, s, j); cr->t_release[j] = rj_joint_release_time(m, s, j);
        cr->p0[j] = rj_joint_contact_penetration(m, s, j); cr->theta[j] = rj_joint_theta_running(m, s, j);
        cr->flag[j] = rj_joint_flag(m, s, j);
    }
    cr->warns = rj_state_warning_count(s);
    row_add(kase, method, release, cr->dt, cr->bound, &cr->w, cr->pen, NULL, elim);
    rj_state_destroy(s, NULL); rj_model_destroy(m, NULL);
}

/* ------------------------------------------------------------------ check 2: long-contact impact */
/* CHECK 2. The impact benchmark with a 0.05 m deep link (64 x softer in bending than the
   paper's 0.2 m, so the contact lasts long and the link whips against the stop), every method
   and release rule, at the benchmark's 2.5 us and at 0.9 x the link's own bound; penalty K is
   the stiffest rj_model_create accepts at that dt. Protection exercised: the limit methods'
   energy accounting (every method may only remove energy: E <= E0), the contact bookkeeping
   (no late contact at 10 rad/s), the 4 K rule for penalty limits and K_AP for adaptive, and
   blow-up detection. Fails if a method pumps energy into the link, a contact is caught late,
   or a run blows up (detected or not). */
static void check2(rjt_ctx *c)
{
    double t_end = g_short ? 0.05 : 0.2, dts[2];
    int di, meth, rel;
    char what[256], kase[96];
    printf("\n## check 2: long-contact impact, H = 0.05 m, %.3g s\n", t_end);
    {
        scn b; impact_opts io = impact_default_opts();
        io.H = 0.05; io.method = RJ_METHOD_MOMENTUM;
        memset(&b, 0, sizeof b);
        impact_scene(&io, b.L, &b.J[0], &b.sc);
        dts[0] = 2.5e-6;
        dts[1] = 0.9 * bound_at(&b, 0);
    }
    for (di = 0; di < 2; di++) {
      char badbal[256] = "";
      for (meth = 0; meth < 5; meth++) for (rel = 0; rel < 2; rel++) {
        scn b; impact_opts io = impact_default_opts(); caseres cr; double sK = 0;
        io.H = 0.05; io.method = meth; io.release = rel;
        memset(&b, 0, sizeof b);
        impact_scene(&io, b.L, &b.J[0], &b.sc);
        scn_fix(&b);
        if (meth == RJ_METHOD_PENALTY) sK = scn_penalty_max(&b, dts[di]);
        snprintf(kase, sizeof kase, "2: impact H=0.05, dt %s", di == 0 ? "2.5 us" : "0.9 x link bound");
        run_case(&b, dts[di], t_end, kase, meth, rel, 1.0 + 1e-3, &cr, NULL, NULL);
        snprintf(what, sizeof what, "impact H=0.05 dt %.4g us %s %s", dts[di] * 1e6, method_name(meth), release_name(rel));
        if (cr.create != RJ_OK) {
            /* adaptive at the link's own dt: K_AP = I/dt^2 on top of the link's omega_max */
            rjt_check(c, meth == RJ_METHOD_ADAPTIVE && cr.create == RJ_ERR_UNSTABLE_DT, what, "refused by rj_model_create: \"%s\"", cr.create_msg);
            continue;
        }
        rjt_check(c, watch_stable(&cr.w, 1.0 + 1e-3) && cr.warns == 0 && cr.t_event[0] > 0, what,
                  "%s; E_peak/E0 %.6f <= 1.001, |balance|/E0 %.2g; contact %.4f ms, last release %.4f ms, contact penetration %.3g rad, peak %.4g rad (%.3g deg); late warnings %ld%s%s",
                  watch_stable(&cr.w, 1.0 + 1e-3) ? "stable" : "NOT stable", cr.w.epeak, cr.w.bal, cr.t_event[0] * 1e3, cr.t_release[0] * 1e3,
                  cr.p0[0], cr.pen, rj_deg(cr.pen), cr.warns,
                  cr.w.r != RJ_OK ? "; " : "", cr.w.r != RJ_OK ? cr.w.err : "");
        if (cr.w.bal > 1e-3) {
            size_t len = strlen(badbal);
            snprintf(badbal + len, sizeof badbal - len, "%s%s/%s %.3g", len ? ", " : "", method_name(meth), release_name(rel), cr.w.bal);
        }
        if (meth == RJ_METHOD_PENALTY) {
            double I1, I2; rj_model *m; rj_error e;
            if (scn_make(&b, dts[di], 0, &m, &e) == RJ_OK) {
                rj_joint_inertias(m, 0, &I1, &I2);
                printf("  (penalty K = %.4g N m/rad = %.3g x K_AP: the stiffest the bound accepts at %.4g us; Eq 31 gives %.4g)\n",
                       rj_joint_stiffness(m, 0), sK, dts[di] * 1e6, rj_joint_kmax_eq31(m, 0, dts[di]));
                rj_model_destroy(m, NULL);
            }
        }
      }
      /* Protection: the energy accounts (lost_limit) of rj_state_energy. Fails when the work
         of a limit method is booked wrongly, so that total + lost - E0 drifts. */
      snprintf(what, sizeof what, "impact H=0.05 dt %.4g us: energy balance closes for every method (|balance| <= 1e-3 E0)", dts[di] * 1e6);
      rjt_check(c, badbal[0] == 0, what, badbal[0] ? "max |balance|/E0: %s" : "all within 1e-3", badbal);
    }
}

/* ------------------------------------------------------------------ check 3: mixed chain */
/* 8 links, masses 30.9 kg ... 0.027 kg (1144:1), lengths 1.0 ... 0.1 m (10:1), densities 19300
   (tungsten-like) ... 300 kg/m^3 (a stiff foam-core composite), E 400 ... 20 GPa, sections
   50x20 ... 20x20 mm. The light links are short and stiff, so they carry the preloads
   (bending rotation under the largest spring torque < 0.05 rad): the stress is the mass
   ratio at the joints, not a strip folding up. Link 0 is pinned to ground, link k hangs
   from link k-1's tip; the chain starts straight and at rest, and every joint has a torsion
   spring preloaded 1 rad (alternating sides), torque = 100 rad/s^2 x the inertia beyond it. */
#define CH_N 8
static const double ch_L[CH_N] = { 1.0, 0.5, 0.1, 0.8, 0.2, 1.0, 0.3, 0.6 };
static const int ch_ne[CH_N] = { 10, 5, 2, 8, 2, 10, 3, 6 };
static const double ch_rho[CH_N] = { 19300, 7850, 300, 7850, 1200, 2710, 600, 7850 };
static const double ch_E[CH_N] = { 400e9, 210e9, 70e9, 210e9, 20e9, 70e9, 30e9, 210e9 };
static const double ch_w[CH_N] = { 0.04, 0.03, 0.03, 0.04, 0.03, 0.05, 0.03, 0.03 };
static const double ch_h[CH_N] = { 0.04, 0.03, 0.03, 0.02, 0.03, 0.02, 0.03, 0.03 };
#define CH_ALPHA 100.0

static void build_chain(scn *b)
{
    int i;
    double mass[CH_N], beyond = 0;
    memset(b, 0, sizeof *b);
    for (i = 0; i < CH_N; i++) {
        b->L[i] = rj_default_link_def();
        b->L[i].length = ch_L[i]; b->L[i].elements = ch_ne[i]; b->L[i].rho = ch_rho[i]; b->L[i].E = ch_E[i];
        b->L[i].width = ch_w[i]; b->L[i].height = ch_h[i];
        mass[i] = ch_rho[i] * ch_w[i] * ch_h[i] * ch_L[i];
    }
    for (i = CH_N - 1; i >= 0; i--) {
        double I = mass[i] * ch_L[i] * ch_L[i] / 3.0 + beyond * ch_L[i] * ch_L[i];
        double sgn = (i % 2) ? -1.0 : 1.0;
        beyond += mass[i];
        b->J[i] = rj_default_joint_def();
        b->J[i].body1 = i - 1; b->J[i].body2 = i;
        b->J[i].angle0 = i == 0 ? 0.0 : ST_PI;
        b->J[i].spring_k = CH_ALPHA * I;          /* N m/rad; torque at start = k x 1 rad */
        b->J[i].spring_free_angle = b->J[i].angle0 + sgn * 1.0;
    }
    b->sc = rj_default_scene_def();
    b->sc.link_count = CH_N; b->sc.joint_count = CH_N;
    scn_fix(b);
}
typedef struct traj { double d[CH_N]; double dmax[CH_N]; } traj;
static int traj_hook(const rj_model *m, const rj_state *s, void *user)
{
    traj *t = (traj *)user;
    int j;
    for (j = 0; j < CH_N; j++) {
        t->d[j] = rj_joint_theta_running(m, s, j) - rj_model_joint_def(m, j)->angle0;
        if (fabs(t->d[j]) > t->dmax[j]) t->dmax[j] = fabs(t->d[j]);
    }
    return 0;
}
/* Limits placed where each joint is at t = 20 ms in the same run without limits (the near
   limit; the far one 30 deg the other way), so that all eight reach their limits together. */
static void chain_limits(scn *b, double dt, double tstar, int lock)
{
    scn t = *b;
    traj tr;
    caseres cr;
    int j, nr = g_nrows;
    memset(&tr, 0, sizeof tr);
    run_case(&t, dt, tstar, "3: chain, no limits (placing the limits)", -1, -1, 1.01, &cr, traj_hook, &tr);
    g_nrows = nr;   /* the placing run is not a result */
    for (j = 0; j < CH_N; j++) {
        double a0 = b->J[j].angle0, d = tr.d[j];
        b->J[j].has_forward = b->J[j].has_reverse = 1;
        b->J[j].lock = lock;
        if (d > 0) { b->J[j].forward = fmod(a0 + d + 4 * ST_PI, 2 * ST_PI); b->J[j].reverse = fmod(a0 - rj_rad(30) + 4 * ST_PI, 2 * ST_PI); }
        else { b->J[j].reverse = fmod(a0 + d + 4 * ST_PI, 2 * ST_PI); b->J[j].forward = fmod(a0 + rj_rad(30) + 4 * ST_PI, 2 * ST_PI); }
        printf("  joint %d: moves %+.4f deg by %.0f ms (max %.4f), %s limit at %.4f deg\n", j, rj_deg(d), tstar * 1e3, rj_deg(tr.dmax[j]),
               d > 0 ? "forward" : "reverse", rj_deg(d > 0 ? b->J[j].forward : b->J[j].reverse));
    }
}
/* largest number of first contacts inside any window of width w */
static int events_within(const double *t, int n, double w, double *lo, double *hi)
{
    int i, k, best = 0;
    for (i = 0; i < n; i++) {
        int cnt = 0;
        double a = 1e300, z = -1e300;
        if (t[i] < 0) continue;
        for (k = 0; k < n; k++) if (t[k] >= t[i] && t[k] <= t[i] + w) { cnt++; if (t[k] < a) a = t[k]; if (t[k] > z) z = t[k]; }
        if (cnt > best) { best = cnt; *lo = a; *hi = z; }
    }
    return best;
}

/* CHECK 3. Protection exercised: the bound over a model whose stiffest element and lightest
   link sit next to 1000 x heavier ones (Lanczos on the whole model, springs included), the
   limit methods acting on eight joints in the same step with wildly different I1/I2, the
   pin groups, and blow-up detection. Each run must be stable (no error, energy <= 1.01 E0)
   or stop with a detected, named blow-up; an undetected one (or NaN) fails. */
static void check3(rjt_ctx *c)
{
    double t_end = g_short ? 0.05 : 1.0, tstar = 0.020, dt;
    int variant, meth, rel;
    char what[256], kase[96];
    scn base;
    printf("\n## check 3: chain of 8 links, masses 1144:1, lengths 10:1, every joint limited, %.3g s\n", t_end);
    build_chain(&base);
    {
        rj_model *m; rj_error e; int i; double mmin = 1e300, mmax = 0;
        if (scn_make(&base, 0, 0, &m, &e) != RJ_OK) { rjt_check(c, 0, "chain builds", "%s", e.msg); return; }
        dt = rj_model_dt(m);
        for (i = 0; i < CH_N; i++) {
            double mi = ch_rho[i] * ch_w[i] * ch_h[i] * ch_L[i];
            if (mi < mmin) mmin = mi;
            if (mi > mmax) mmax = mi;
        }
        printf("  link masses %.4g ... %.4g kg (%.0f:1), lengths 0.1 ... 1.0 m, spring torques %.3g ... %.3g N m; dt = 0.9 x bound = %.4g us (bound %.4g us, links and springs)\n",
               mmin, mmax, mmax / mmin, base.J[CH_N - 1].spring_k, base.J[0].spring_k, dt * 1e6, rj_model_dt_bound(m) * 1e6);
        rj_model_destroy(m, NULL);
    }
    for (variant = 0; variant < 2; variant++) {
        scn b = base;
        int nrel = variant == 0 ? 2 : 1;
        char deep[500] = "";
        double pmax_ok = 0;
        chain_limits(&b, dt, tstar, variant == 1);
        for (meth = 0; meth < 5; meth++) for (rel = 0; rel < nrel; rel++) {
            scn t = b; caseres cr; double sK = 0, lo = 0, hi = 0; int within;
            int relv = variant == 0 ? rel : -1;
            scn_method(&t, meth, variant == 0 ? rel : RJ_RELEASE_RC13);
            if (meth == RJ_METHOD_PENALTY) sK = scn_penalty_max(&t, dt);
            snprintf(kase, sizeof kase, "3: chain 8 links, %s", variant == 0 ? "limits" : "locks");
            run_case(&t, dt, t_end, kase, meth, relv, 1.01, &cr, NULL, NULL);
            snprintf(what, sizeof what, "chain (%s) %s %s", variant == 0 ? "limits" : "locks", method_name(meth), release_name(relv));
            if (cr.create != RJ_OK) {
                rjt_check(c, cr.create == RJ_ERR_UNSTABLE_DT && strstr(cr.create_msg, "above the stability bound") != NULL, what,
                          "refused by rj_model_create at dt %.4g us (a clear, detected refusal): \"%s\"", dt * 1e6, cr.create_msg);
                continue;
            }
            within = events_within(cr.t_event, CH_N, 1e-3, &lo, &hi);
            if (watch_stable(&cr.w, 1.01))
                rjt_check(c, 1, what, "STABLE: E_peak/E0 %.6f, |balance|/E0 %.2g, peak penetration %.4g rad (%.3g deg), %d joints first hit within 1 ms (%.4f - %.4f ms), late warnings %ld",
                          cr.w.epeak, cr.w.bal, cr.pen, rj_deg(cr.pen), within, lo * 1e3, hi * 1e3, cr.warns);
            else if (cr.w.r != RJ_OK && !cr.w.undet && !cr.w.nonfinite)
                rjt_check(c, strstr(cr.w.err, "t = ") != NULL, what, "UNSTABLE, DETECTED: \"%s\" (E_peak/E0 %.4g; %d joints had hit within 1 ms)", cr.w.err, cr.w.epeak, within);
            else if (cr.w.undet)
                rjt_check(c, 0, what, "UNSTABLE, REPORTED LATE: RJ_OK at t = %.6g s with %.3g J > 2 x %.3g J (10 x E0), %ld steps before \"%s\" (E_peak/E0 %.4g, peak penetration %.3g rad)",
                          cr.w.t_undet, cr.w.undet_u, cr.w.undet_lim, (long)floor((cr.w.t_err - cr.w.t_undet) / dt + 0.5), cr.w.err, cr.w.epeak, cr.pen);
            else
                rjt_check(c, 0, what, "UNSTABLE, NOT DETECTED: the energy grew to %.4g x E0 by t = %.3g s and rj_step never reported it (its threshold is 10 x); |balance|/E0 %.2g, peak penetration %.3g rad (%.3g deg)%s",
                          cr.w.epeak, t_end, cr.w.bal, cr.pen, rj_deg(cr.pen), cr.w.nonfinite ? "; NON-FINITE values" : "");
            if (meth == RJ_METHOD_MOMENTUM && rel == 1) {
                /* the scenario itself: several joints reach their limits together */
                snprintf(what, sizeof what, "chain (%s): several joints reach their limits within 1 ms of each other", variant == 0 ? "limits" : "locks");
                rjt_check(c, within >= 3, what, "%d of 8 first contacts in %.4f - %.4f ms (%.0f steps apart at most)", within, lo * 1e3, hi * 1e3, (hi - lo) / dt);
            }
            if (meth == RJ_METHOD_PENALTY) printf("  (penalty K_j = %.3g x K_AP_j at dt: the stiffest the bound accepts)\n", sK);
            if (cr.pen > 0.1) {
                size_t len = strlen(deep);
                snprintf(deep + len, sizeof deep - len, " %s/%s %.3g rad (%.1f deg, %ld late re-contacts)%s;", method_name(meth), release_name(relv), cr.pen, rj_deg(cr.pen), cr.warns,
                         cr.w.r != RJ_OK ? " before the blow-up" : "");
            } else if (cr.pen > pmax_ok) pmax_ok = cr.pen;
        }
        /* Protection: the limit methods hold a joint at its stop (velocity methods: no motion
           into the limit while flagged; penalty: K p). Fails when a joint ratchets through. */
        snprintf(what, sizeof what, "chain (%s): every limit holds (peak penetration < 0.1 rad = 5.7 deg)", variant == 0 ? "limits" : "locks");
        rjt_check(c, deep[0] == 0, what, deep[0] ? "DEEPER:%s others <= %.3g rad" : "largest peak penetration %.3g rad (%.3g deg)", deep[0] ? deep : "", pmax_ok, rj_deg(pmax_ok));
    }
}

/* ------------------------------------------------------------------ check 4: tunnelling */
/* A short stiff link (0.1 m, one element, 20 x 5 mm aluminium) pinned to ground, spinning
   counter-clockwise from 85 deg; the limited arc is [100, 110] deg (forward 100, reverse 110:
   free range 350 deg). One element, so the centrifugal stiffening of a fast spin stays
   inside the bound for a few steps; dt = 0.9 x bound. */
static void build_spinner(scn *b, double deg_per_step, double dt, int lock)
{
    memset(b, 0, sizeof *b);
    b->L[0] = rj_default_link_def();
    b->L[0].length = 0.1; b->L[0].elements = 1; b->L[0].width = 0.02; b->L[0].height = 0.005;
    b->J[0] = rj_default_joint_def();
    b->J[0].body1 = -1; b->J[0].body2 = 0; b->J[0].angle0 = rj_rad(85.0);
    b->J[0].rate0 = dt > 0 ? rj_rad(deg_per_step) / dt : 0.0;
    b->J[0].has_forward = 1; b->J[0].forward = rj_rad(100.0);
    b->J[0].has_reverse = 1; b->J[0].reverse = rj_rad(110.0);
    b->J[0].lock = lock;
    b->sc = rj_default_scene_def();
    b->sc.link_count = 1; b->sc.joint_count = 1;
    scn_fix(b);
}
typedef struct tun { double run_min, run_max; int caught_step, step; int flagged; } tun;
static int tun_hook(const rj_model *m, const rj_state *s, void *user)
{
    tun *t = (tun *)user;
    double r = rj_joint_theta_running(m, s, 0);
    t->step++;
    if (r < t->run_min) t->run_min = r;
    if (r > t->run_max) t->run_max = r;
    if (!t->flagged && rj_joint_flag(m, s, 0) != RJ_FREE) { t->flagged = 1; t->caught_step = t->step; }
    return 0;
}

/* CHECK 4. Protection exercised: the late-contact detection in rj_step (a contact first seen
   more than 0.05 rad past its limit, or past the whole limited range, is flagged and counted
   in rj_state_warning_count with "late" in the text), the running angle (a joint that jumps
   over the 10 deg arc is still seen past its forward limit, not inside the free range), and
   the RJ_ERR_TUNNEL stop for more than 90 deg in one step. Fails if the limit is passed
   silently (no flag, no warning), if the joint escapes through the stop (running angle more
   than one step's rotation past either limit), or if a > 90 deg step is not stopped. */
static void check4(rjt_ctx *c)
{
    static const double degs[3] = { 20.0, 35.0, 60.0 };
    int di, meth, rel, lock;
    long nsteps = g_short ? 400 : 4000;
    char what[256], kase[96];
    double dt;
    printf("\n## check 4: tunnelling: a joint turning 20-60 deg per step at a 10 deg limited arc; > 90 deg per step\n");
    {
        scn b; rj_model *m; rj_error e;
        build_spinner(&b, 0, 0, 0);
        scn_method(&b, RJ_METHOD_MOMENTUM, RJ_RELEASE_RC13);
        scn_make(&b, 0, 0, &m, &e);
        dt = rj_model_dt(m);
        printf("  link 0.1 m, 1 element; dt %.4g us = 0.9 x bound; 20/35/60 deg per step = %.4g / %.4g / %.4g rad/s\n",
               dt * 1e6, rj_rad(20) / dt, rj_rad(35) / dt, rj_rad(60) / dt);
        rj_model_destroy(m, NULL);
    }
    for (di = 0; di < 3; di++) for (lock = 0; lock < 2; lock++) {
        char miss[400] = "", thru[400] = "", undet[400] = "", det[400] = "";
        int nrun = 0, nstable = 0, ndet = 0, ngrew = 0;
        double pmin = 1e300, pmax = 0, land = 85.0 + degs[di], fwd = rj_rad(100.0), rev = rj_rad(-250.0);
        for (meth = 0; meth < 5; meth++) for (rel = 0; rel < 2; rel++) {
            scn b; caseres cr; tun t;
            int relv = lock ? -1 : rel;
            size_t len;
            if (lock && rel) continue;
            build_spinner(&b, degs[di], dt, lock);
            scn_method(&b, meth, lock ? RJ_RELEASE_RC13 : rel);
            if (meth == RJ_METHOD_PENALTY) scn_penalty_max(&b, dt);
            memset(&t, 0, sizeof t); t.run_min = 1e300; t.run_max = -1e300;
            snprintf(kase, sizeof kase, "4: tunnelling %.0f deg/step%s", degs[di], lock ? ", lock" : "");
            run_case(&b, dt, nsteps * dt, kase, meth, relv, 1.05, &cr, tun_hook, &t);
            if (cr.create != RJ_OK) { len = strlen(miss); snprintf(miss + len, sizeof miss - len, " %s/%s refused: %.80s", method_name(meth), release_name(relv), cr.create_msg); continue; }
            nrun++;
            /* caught: flag set on the step after landing past the limit, a "late" warning */
            if (!(t.flagged && t.caught_step <= 2 && cr.warns > 0 && strstr(cr.w.warn, "late") != NULL)) {
                len = strlen(miss);
                snprintf(miss + len, sizeof miss - len, " %s/%s (flag %d at step %d, %ld warnings)", method_name(meth), release_name(relv), t.flagged, t.caught_step, cr.warns);
            }
            if (fabs(cr.p0[0]) < pmin) pmin = fabs(cr.p0[0]);
            if (fabs(cr.p0[0]) > pmax) pmax = fabs(cr.p0[0]);
            /* passed through: carried on into the free range beyond the stop (half a turn past it) */
            if (t.run_max > fwd + ST_PI || t.run_min < rev - ST_PI) {
                len = strlen(thru);
                snprintf(thru + len, sizeof thru - len, " %s/%s [%.1f, %.1f] deg", method_name(meth), release_name(relv), rj_deg(t.run_min), rj_deg(t.run_max));
            }
            if (watch_stable(&cr.w, 1.05)) nstable++;
            else if (cr.w.r == RJ_OK && cr.w.epeak <= 2.0 && !cr.w.undet && !cr.w.nonfinite) ngrew++;
            else if (cr.w.r != RJ_OK && !cr.w.undet && !cr.w.nonfinite) {
                ndet++;
                len = strlen(det);
                if (len < 300) snprintf(det + len, sizeof det - len, " %s/%s at %.3g ms", method_name(meth), release_name(relv), cr.w.t_err * 1e3);
            } else {
                len = strlen(undet);
                if (cr.w.undet && cr.w.r != RJ_OK)
                    snprintf(undet + len, sizeof undet - len, " %s/%s (%.3g J = %.3g x the documented limit at %.4g ms, reported %ld steps later)", method_name(meth), release_name(relv),
                             cr.w.undet_u, cr.w.undet_u / cr.w.undet_lim, cr.w.t_undet * 1e3, (long)floor((cr.w.t_err - cr.w.t_undet) / cr.dt + 0.5));
                else
                    snprintf(undet + len, sizeof undet - len, " %s/%s (E_peak %.3g E0, never reported)", method_name(meth), release_name(relv), cr.w.epeak);
            }
        }
        snprintf(what, sizeof what, "tunnel %.0f deg/step%s: the limit is caught, late, by every method", degs[di], lock ? " (lock)" : "");
        rjt_check(c, miss[0] == 0 && nrun > 0, what, "%d runs: lands at %.0f deg (%.4g rad past the forward limit%s); flag set on the next step, \"late\" warning; contact penetration %.4g ... %.4g rad%s%s",
                  nrun, land, rj_rad(land - 100.0), land > 110.0 ? ", past the whole 10 deg range" : "", pmin, pmax, miss[0] ? "; MISSED:" : "", miss);
        snprintf(what, sizeof what, "tunnel %.0f deg/step%s: no joint passes through the stop", degs[di], lock ? " (lock)" : "");
        if (thru[0]) rjt_check(c, 0, what, "passed through:%s", thru);
        else rjt_check(c, 1, what, "the running angle of every run stayed within half a turn of the limits (%ld steps)", nsteps);
        snprintf(what, sizeof what, "tunnel %.0f deg/step%s: the aftermath is stable or a detected stop", degs[di], lock ? " (lock)" : "");
        rjt_check(c, undet[0] == 0, what, "%d stable, %d with energy growth below 2 E0 (not reported), %d stopped with a reported error%s%s%s", nstable, ngrew, ndet,
                  det[0] ? " (" : "", det, det[0] ? ")" : "", undet[0] ? "; NOT REPORTED in time: see below" : "");
        if (undet[0]) printf("   not reported in time:%s\n", undet);
    }
    /* more than 90 deg in one step: RJ_ERR_TUNNEL at once, the state left at t = 0 */
    for (meth = 0; meth < 5; meth++) {
        scn b; rj_model *m; rj_state *s = NULL; rj_error e; rj_result r; keepres kr; watch w;
        build_spinner(&b, 100.0, dt, 0);
        scn_method(&b, meth, RJ_RELEASE_RC13);
        if (meth == RJ_METHOD_PENALTY) scn_penalty_max(&b, dt);
        if (scn_make(&b, dt, 0, &m, &e) != RJ_OK) { rjt_check(c, 0, "tunnel 100 deg/step builds", "%s", e.msg); continue; }
        rj_state_create(m, &s, NULL);
        watch_init(&w, m);
        r = run_keep(m, s, 10, &w, &kr);
        snprintf(what, sizeof what, "tunnel 100 deg/step %s: rj_step stops with RJ_ERR_TUNNEL, state kept", method_name(meth));
        rjt_check(c, r == RJ_ERR_TUNNEL && kr.intact && kr.at_step == 0 && strstr(w.err, "turned") != NULL, what,
                  "%s at step %ld, state %s: \"%s\"", rj_result_str(r), kr.at_step, kr.intact ? "intact" : "CHANGED", w.err);
        snprintf(kase, sizeof kase, "4: tunnelling 100 deg/step");
        row_add(kase, meth, RJ_RELEASE_RC13, dt, rj_model_dt_bound(m), &w, state_peak_pen(m, s), r == RJ_ERR_TUNNEL ? "no (detected)" : NULL, 1.05);
        rj_state_destroy(s, NULL); rj_model_destroy(m, NULL);
    }
}

/* ------------------------------------------------------------------ check 5: the 0/360 seam */
/* A 0.5 m strip (5 elements, 20 x 10 mm) pinned to ground turning at 2 rad/s towards a limit
   next to the seam. Eq 6's two configurations: A: forward 358 > reverse 2 deg (free range
   (2, 358), the limited arc straddles 0); B: forward 20 < reverse 340 deg (free range wraps
   through 0: the joint crosses the seam before it reaches the limit). Each approached from
   both sides, and once with angle0 given as a negative angle. */
typedef struct seam_case { const char *name; double fwd, rev, angle0, rate, limit_run; int flag; } seam_case;
static const seam_case seam_cases[6] = {
    { "A+ (fwd 358 > rev 2, from 340 up)", 358, 2, 340, 2.0, 358, RJ_AT_FORWARD },
    { "A- (fwd 358 > rev 2, from 20 down)", 358, 2, 20, -2.0, 2, RJ_AT_REVERSE },
    { "A+ (angle0 = -20 deg)", 358, 2, -20, 2.0, -2, RJ_AT_FORWARD },
    { "B+ (fwd 20 < rev 340, from 350 up across 0)", 20, 340, 350, 2.0, 380, RJ_AT_FORWARD },
    { "B- (fwd 20 < rev 340, from 10 down across 0)", 20, 340, 10, -2.0, -20, RJ_AT_REVERSE },
    { "B+ (angle0 = -10 deg)", 20, 340, -10, 2.0, 20, RJ_AT_FORWARD },
};
typedef struct seam_obs { int hit, flag; double t, theta, run, p0; } seam_obs;
static int seam_hook(const rj_model *m, const rj_state *s, void *user)
{
    seam_obs *o = (seam_obs *)user;
    if (!o->hit && rj_joint_flag(m, s, 0) != RJ_FREE) {
        o->hit = 1; o->flag = rj_joint_flag(m, s, 0);
        o->t = rj_joint_event_time(m, s, 0);      /* the step that found the contact starts here */
        o->theta = rj_joint_theta(m, s, 0); o->run = rj_joint_theta_running(m, s, 0);
        o->p0 = rj_joint_contact_penetration(m, s, 0);
    }
    return 0;
}
/* angle wrapped into (-pi, pi] */
static double wrap_pi(double a)
{
    double r = fmod(a + ST_PI, 2 * ST_PI);
    if (r < 0) r += 2 * ST_PI;
    return r - ST_PI;
}
static void build_seam(scn *b, const seam_case *sc, int lock)
{
    memset(b, 0, sizeof *b);
    b->L[0] = rj_default_link_def();
    b->L[0].length = 0.5; b->L[0].elements = 5; b->L[0].width = 0.02; b->L[0].height = 0.01;
    b->J[0] = rj_default_joint_def();
    b->J[0].body1 = -1; b->J[0].body2 = 0;
    b->J[0].angle0 = rj_rad(sc->angle0); b->J[0].rate0 = sc->rate;
    b->J[0].has_forward = 1; b->J[0].forward = rj_rad(sc->fwd);
    b->J[0].has_reverse = 1; b->J[0].reverse = rj_rad(sc->rev);
    b->J[0].lock = lock;
    b->sc = rj_default_scene_def();
    b->sc.link_count = 1; b->sc.joint_count = 1;
    scn_fix(b);
}

/* CHECK 5. Protection exercised: the running (unwrapped) angle and the running limits built
   from Eq 6's two configurations in rj_model_create, the side-aware flags (flag 1 only past
   the forward limit, 2 only past the reverse one), rj_joint_theta = running angle mod 360.
   Fails if the seam makes the joint see the wrong limit, miss it, hit it a turn early or
   late, or report a contact far from the limit angle. */
static void check5(rjt_ctx *c)
{
    int ci, meth, rel, lock;
    char what[256], kase[96];
    printf("\n## check 5: limits across the 0/360 seam, both configurations of Eq 6, both directions\n");
    for (ci = 0; ci < 6; ci++) {
        const seam_case *sc = &seam_cases[ci];
        char bad[600] = "";
        double gap = fabs(sc->limit_run - sc->angle0), tpred = rj_rad(gap) / fabs(sc->rate);
        double worst_dt = 0, worst_run = 0, worst_p0 = 0, maxpen = 0, dt_used = 0;
        int nrun = 0;
        for (lock = 0; lock < 2; lock++) for (meth = 0; meth < 5; meth++) for (rel = 0; rel < 2; rel++) {
            scn b; caseres cr; seam_obs o;
            int relv = lock ? -1 : rel, want = lock ? RJ_LOCKED : sc->flag;
            double step, lim = rj_rad(sc->limit_run), dtheta, drun, dtt;
            size_t len;
            if (lock && rel) continue;
            build_seam(&b, sc, lock);
            scn_method(&b, meth, lock ? RJ_RELEASE_RC13 : rel);
            if (meth == RJ_METHOD_PENALTY) scn_penalty_max(&b, bound_at(&b, 0) * 0.9);
            memset(&o, 0, sizeof o);
            snprintf(kase, sizeof kase, "5: seam %.2s%s", sc->name, lock ? " lock" : "");
            run_case(&b, 0, tpred + 0.05, kase, meth, relv, 1.001, &cr, seam_hook, &o);
            len = strlen(bad);
            if (cr.create != RJ_OK) { snprintf(bad + len, sizeof bad - len, " %s/%s refused", method_name(meth), release_name(relv)); continue; }
            nrun++;
            step = fabs(sc->rate) * cr.dt;
            dt_used = cr.dt;
            if (!o.hit) { snprintf(bad + len, sizeof bad - len, " %s/%s: NO CONTACT", method_name(meth), release_name(relv)); continue; }
            /* the step that found the contact read theta at o.t: within one step past the limit */
            dtheta = fabs(o.p0);
            drun = fabs(o.run - (rj_rad(sc->angle0) + sc->rate * (o.t + cr.dt)));
            dtt = fabs(o.t - tpred);
            if (dtt > worst_dt) worst_dt = dtt;
            if (drun > worst_run) worst_run = drun;
            if (dtheta > worst_p0) worst_p0 = dtheta;
            if (cr.pen > maxpen) maxpen = cr.pen;
            if (o.flag != want || dtheta > step * 1.01 + 1e-9 || (sc->flag == RJ_AT_FORWARD ? o.p0 > 0 : o.p0 < 0) || dtt > 2 * cr.dt + 1e-6 ||
                drun > 1e-3 || fabs(wrap_pi(o.run - o.theta)) > 1e-9 ||
                cr.warns != 0 || !watch_stable(&cr.w, 1.001) || fabs(o.run - lim) > 2 * step) {
                snprintf(bad + len, sizeof bad - len, " %s/%s: flag %d (want %d) at t %.6f s (predicted %.6f), running %.4f deg, theta %.4f deg, p0 %.3g rad, %ld warnings%s",
                         method_name(meth), release_name(relv), o.flag, want, o.t, tpred, rj_deg(o.run), rj_deg(o.theta), o.p0, cr.warns,
                         watch_stable(&cr.w, 1.001) ? "" : ", NOT stable (E_peak/E0 > 1.001)");
            }
        }
        snprintf(what, sizeof what, "seam %s: limit caught at the right angle", sc->name);
        rjt_check(c, bad[0] == 0 && nrun == 15, what,
                  "%d runs (5 methods x rc12/rc13 + lock): limit at running %.0f deg (theta %.0f); contact at t = %.5f s +- %.2g s (predicted gap/rate %.5f s, dt %.3g us), |p0| <= %.3g rad (one step %.3g rad), running angle within %.2g rad of angle0 + rate t, peak penetration %.3g rad (%.3g deg)%s%s",
                  nrun, sc->limit_run, fmod(sc->limit_run + 720.0, 360.0), tpred, worst_dt, tpred, dt_used * 1e6, worst_p0, fabs(sc->rate) * dt_used, worst_run, maxpen, rj_deg(maxpen),
                  bad[0] ? "; BAD:" : "", bad);
    }
}

/* ------------------------------------------------------------------ check 6: locks above Eq 31 */
typedef struct lockobs { int locked; double t_lock; int unlocked_after; } lockobs;
static int lock_hook(const rj_model *m, const rj_state *s, void *user)
{
    lockobs *o = (lockobs *)user;
    int fl = rj_joint_flag(m, s, rj_model_joint_count(m) - 1);   /* the latch under test is the last joint */
    if (!o->locked && fl == RJ_LOCKED) { o->locked = 1; o->t_lock = rj_state_time(s); }
    else if (o->locked && fl != RJ_LOCKED) o->unlocked_after = 1;
    return 0;
}
/* largest penalty_k on joint j that rj_model_create accepts at dt (log bisection) */
static double kmax_accepted(scn *b, int j, double dt, double lo, double hi)
{
    int it;
    rj_model *m; rj_error e;
    for (it = 0; it < 80 && hi / lo > 1.0 + 1e-7; it++) {
        double k = sqrt(lo * hi);
        b->J[j].penalty_k = k;
        if (scn_make(b, dt, 0, &m, &e) == RJ_OK) { rj_model_destroy(m, NULL); lo = k; } else hi = k;
    }
    b->J[j].penalty_k = lo;
    return lo;
}

/* CHECK 6. Protection exercised: the penalty stiffness in the stability bound (4 K on the
   joint's own degree of freedom, Lanczos) and the refusal message, which must name the joint
   and Eq 31 when a joint stiffness is the cause. Two scenes, one each way: the deployment's
   latch (joint 1, the paper's Eq 31 = 1015 N m/rad at 7.5 us is far below what the bound
   admits: the bound accepts a much stiffer lock, which must then run stable through the
   latch), and the impact joint as a lock at 2.5 us (there Eq 31 is above the bound: refused).
   Fails if a stiffness the bound accepts blows up, if a refused one is accepted, or if the
   refusal does not say which joint and Eq 31. */
static void check6(rjt_ctx *c)
{
    char what[256];
    printf("\n## check 6: locking with a penalty stiffness above Eq 31\n");
    {   /* deployment, joint 1 (the latch at link 1's root), dt 7.5 us */
        scn b; deploy_opts o = deploy_default_opts(); caseres cr; lockobs lo; rj_model *m; rj_error e; rj_result r;
        double dt = 7.5e-6, eq31, kacc, t_end = g_short ? 3.2 : 6.0;
        memset(&b, 0, sizeof b);
        deploy_scene(&o, b.L, b.J, &b.sc);
        scn_fix(&b);
        b.J[1].penalty_k = 1.0;
        scn_make(&b, dt, 0, &m, &e);
        eq31 = rj_joint_kmax_eq31(m, 1, dt);
        rj_model_destroy(m, NULL);
        kacc = kmax_accepted(&b, 1, dt, eq31, 1e9);
        printf("  deployment joint 1 at dt %.3g us: Eq 31 K_max = %.6g N m/rad; the library's bound accepts up to K = %.6g N m/rad (%.1f x Eq 31)\n", dt * 1e6, eq31, kacc, kacc / eq31);
        /* just above: refused, naming the joint and Eq 31 */
        b.J[1].penalty_k = kacc * 1.01;
        r = scn_make(&b, dt, 0, &m, &e);
        if (r == RJ_OK) rj_model_destroy(m, NULL);
        snprintf(what, sizeof what, "deployment lock K = 1.01 x the largest accepted (%.4g N m/rad = %.1f x Eq 31): refused, message names joint 1 and Eq 31", kacc * 1.01, kacc * 1.01 / eq31);
        rjt_check(c, r == RJ_ERR_UNSTABLE_DT && strstr(e.msg, "joint 1") != NULL && strstr(e.msg, "Eq 31") != NULL, what, "\"%s\"", r == RJ_OK ? "accepted" : e.msg);
        b.J[1].penalty_k = kacc * 4.0;
        r = scn_make(&b, dt, 0, &m, &e);
        if (r == RJ_OK) rj_model_destroy(m, NULL);
        snprintf(what, sizeof what, "deployment lock K = 4 x the largest accepted (%.4g N m/rad): refused, message names joint 1 and Eq 31", kacc * 4.0);
        rjt_check(c, r == RJ_ERR_UNSTABLE_DT && strstr(e.msg, "joint 1") != NULL && strstr(e.msg, "Eq 31") != NULL, what, "\"%s\"", r == RJ_OK ? "accepted" : e.msg);
        /* at the largest accepted: stable through the latch */
        b.J[1].penalty_k = kacc;
        memset(&lo, 0, sizeof lo);
        run_case(&b, dt, t_end, "6: deployment, lock K = largest accepted", RJ_METHOD_PENALTY, -1, 1.0 + 1e-6, &cr, lock_hook, &lo);
        snprintf(what, sizeof what, "deployment lock K = %.4g N m/rad (%.1f x Eq 31, the largest the bound accepts): accepted, stable through the latch", kacc, kacc / eq31);
        rjt_check(c, cr.create == RJ_OK && watch_stable(&cr.w, 1.0 + 1e-6) && lo.locked && !lo.unlocked_after, what,
                  "latched at %.6f s and stayed; to %.2f s: E_peak/E0 %.9f, |balance|/E0 %.2g, peak penetration %.4g rad (%.3g deg), %ld warnings%s%s",
                  lo.t_lock, t_end, cr.w.epeak, cr.w.bal, cr.pen, rj_deg(cr.pen), cr.warns, cr.w.r != RJ_OK ? "; " : "", cr.w.err);
        b.J[1].penalty_k = eq31;
        memset(&lo, 0, sizeof lo);
        run_case(&b, dt, t_end, "6: deployment, lock K = Eq 31", RJ_METHOD_PENALTY, -1, 1.0 + 1e-6, &cr, lock_hook, &lo);
        snprintf(what, sizeof what, "deployment lock K = Eq 31 = %.4g N m/rad (reference)", eq31);
        rjt_check(c, cr.create == RJ_OK && watch_stable(&cr.w, 1.0 + 1e-6) && lo.locked && !lo.unlocked_after, what,
                  "latched at %.6f s; E_peak/E0 %.9f, peak penetration %.4g rad (%.3g deg)", lo.t_lock, cr.w.epeak, cr.pen, rj_deg(cr.pen));
    }
    {   /* the impact joint as a lock, H = 0.2 m, dt 2.5 us */
        scn b; impact_opts io = impact_default_opts(); caseres cr; lockobs lo; rj_model *m; rj_error e; rj_result r;
        double dt = 2.5e-6, eq31, kacc;
        memset(&b, 0, sizeof b);
        io.method = RJ_METHOD_PENALTY;
        impact_scene(&io, b.L, &b.J[0], &b.sc);
        scn_fix(&b);
        b.J[0].lock = 1;
        b.J[0].penalty_k = 1.0;
        scn_make(&b, dt, 0, &m, &e);
        eq31 = rj_joint_kmax_eq31(m, 0, dt);
        rj_model_destroy(m, NULL);
        kacc = kmax_accepted(&b, 0, dt, 1.0, eq31 * 10);
        printf("  impact joint (lock) at dt %.3g us: Eq 31 K_max = %.6g N m/rad; the library's bound accepts up to K = %.6g N m/rad (%.2f x Eq 31)\n", dt * 1e6, eq31, kacc, kacc / eq31);
        b.J[0].penalty_k = eq31;
        r = scn_make(&b, dt, 0, &m, &e);
        if (r == RJ_OK) rj_model_destroy(m, NULL);
        snprintf(what, sizeof what, "impact lock K = Eq 31 = %.4g N m/rad (%.2f x the largest accepted): %s", eq31, eq31 / kacc, eq31 > kacc ? "refused, message names joint 0 and Eq 31" : "accepted");
        if (eq31 > kacc)
            rjt_check(c, r == RJ_ERR_UNSTABLE_DT && strstr(e.msg, "joint 0") != NULL && strstr(e.msg, "Eq 31") != NULL, what, "\"%s\"", r == RJ_OK ? "accepted" : e.msg);
        else
            rjt_check(c, r == RJ_OK, what, "%s", r == RJ_OK ? "accepted" : e.msg);
        if (r == RJ_ERR_UNSTABLE_DT) {
            /* the refusal advises "accepts a penalty K up to about X": X should then be accepted */
            const char *q = strstr(e.msg, "up to about ");
            double adv = q ? atof(q + 12) : 0;
            rj_result r2;
            b.J[0].penalty_k = adv;
            r2 = adv > 0 ? scn_make(&b, dt, 0, &m, &e) : RJ_ERR_INVALID;
            if (r2 == RJ_OK) rj_model_destroy(m, NULL);
            rjt_check(c, r2 == RJ_OK, "impact lock: the K the refusal message advises (\"accepts a penalty K up to about ...\") is accepted",
                      "advised K = %.6g N m/rad: %s%s", adv, r2 == RJ_OK ? "accepted" : "REFUSED again: ", r2 == RJ_OK ? "" : e.msg);
        }
        b.J[0].penalty_k = kacc;
        memset(&lo, 0, sizeof lo);
        run_case(&b, dt, g_short ? 0.05 : 0.2, "6: impact H=0.2 as a lock, K = largest accepted", RJ_METHOD_PENALTY, -1, 1.0 + 1e-6, &cr, lock_hook, &lo);
        snprintf(what, sizeof what, "impact lock K = %.4g N m/rad (largest accepted, %.2f x Eq 31): stable, stays latched", kacc, kacc / eq31);
        rjt_check(c, cr.create == RJ_OK && watch_stable(&cr.w, 1.0 + 1e-6) && lo.locked && !lo.unlocked_after, what,
                  "latched at %.6f s; E_peak/E0 %.9f, |balance|/E0 %.2g, peak penetration %.4g rad (%.3g deg), %ld warnings%s%s",
                  lo.t_lock, cr.w.epeak, cr.w.bal, cr.pen, rj_deg(cr.pen), cr.warns, cr.w.r != RJ_OK ? "; " : "", cr.w.err);
    }
}

/* ------------------------------------------------------------------ check 7: stick-slip */
/* A 0.5 m strip (5 elements, 20 x 10 mm aluminium) pinned to ground, horizontal, at rest;
   Coulomb friction T_f = 0.5 N m at the pin; a constant torque T on the link from a joint
   table that is flat over the whole turn (table_torque = -T from 0 to 2 pi: the resistive
   table torque is -table, so +T acts on the link). The API has no time-varying load, so the
   "slowly rising torque" is a staircase: separate runs at T/T_f = 0.98, 0.99, 1.01, 1.02
   (1e5 steps each) and a bisection of the breakaway ratio. Limits at +-20 deg with every
   method: the slipping runs reach the forward one. */
#define SS_TF 0.5
static void build_stickslip(scn *b, double ratio)
{
    memset(b, 0, sizeof *b);
    b->L[0] = rj_default_link_def();
    b->L[0].length = 0.5; b->L[0].elements = 5; b->L[0].width = 0.02; b->L[0].height = 0.01;
    b->J[0] = rj_default_joint_def();
    b->J[0].body1 = -1; b->J[0].body2 = 0; b->J[0].angle0 = rj_rad(90.0);
    b->J[0].friction = SS_TF;
    b->J[0].table_count = 2;
    b->J[0].table_angle[0] = 0.0; b->J[0].table_angle[1] = 2 * ST_PI;
    b->J[0].table_torque[0] = b->J[0].table_torque[1] = -ratio * SS_TF;
    b->J[0].has_forward = 1; b->J[0].forward = rj_rad(110.0);
    b->J[0].has_reverse = 1; b->J[0].reverse = rj_rad(70.0);
    b->sc = rj_default_scene_def();
    b->sc.link_count = 1; b->sc.joint_count = 1;
    scn_fix(b);
}
typedef struct ssobs { double a0, drift, t1, th1, tlim; } ssobs;
static int ss_hook(const rj_model *m, const rj_state *s, void *user)
{
    ssobs *o = (ssobs *)user;
    double d = fabs(rj_joint_theta_running(m, s, 0) - o->a0);
    if (d > o->drift) o->drift = d;
    if (o->th1 == 0 && rj_state_time(s) >= o->t1) o->th1 = rj_joint_theta_running(m, s, 0) - o->a0;
    if (o->tlim < 0 && rj_joint_flag(m, s, 0) != RJ_FREE) o->tlim = rj_state_time(s);
    return 0;
}
/* 1 if the joint moves more than 1e-9 rad within n steps at T = ratio T_f */
static int ss_slips(double ratio, long n)
{
    scn b; rj_model *m; rj_state *s = NULL; rj_error e; long k; int moved = 0;
    double a0;
    build_stickslip(&b, ratio);
    scn_method(&b, RJ_METHOD_MOMENTUM, RJ_RELEASE_RC13);
    if (scn_make(&b, 0, 0, &m, &e) != RJ_OK) return -1;
    rj_state_create(m, &s, NULL);
    a0 = rj_joint_theta_running(m, s, 0);
    for (k = 0; k < n && !moved; k++) {
        if (rj_step(m, s) != RJ_OK) break;
        moved = fabs(rj_joint_theta_running(m, s, 0) - a0) > 1e-9;
    }
    rj_state_destroy(s, NULL); rj_model_destroy(m, NULL);
    return moved;
}

/* CHECK 7. Protection exercised: the friction step (the torque that would stop the relative
   rotation within the step, capped at T_f, applied before the velocity update), which holds
   a stuck joint exactly and lets it go at T_f. Fails if a stuck joint creeps (> 1e-9 rad over
   1e5 steps), if it breaks away more than 1 % away from T_f, or if a slipping joint does not
   accelerate as (T - T_f)/I. */
static void check7(rjt_ctx *c)
{
    static const double ratios[4] = { 0.98, 0.99, 1.01, 1.02 };
    long n = 100000;
    int ri, meth, rel;
    char what[256], kase[96];
    double Irig;
    printf("\n## check 7: stick-slip, T_f = %.2g N m, constant torques 0.98 / 0.99 / 1.01 / 1.02 T_f, %ld steps each\n", SS_TF, n);
    Irig = 2710.0 * 0.02 * 0.01 * 0.5 * 0.5 * 0.5 / 3.0;
    for (ri = 0; ri < 4; ri++) {
        double dmax = 0, dmin = 1e300, th1min = 1e300, th1max = -1e300, tl_min = 1e300, tl_max = -1e300, t1 = 1.0;
        char bad[400] = "";
        int nrun = 0, slip = ratios[ri] > 1.0;
        for (meth = 0; meth < 5; meth++) for (rel = 0; rel < 2; rel++) {
            scn b; caseres cr; ssobs o; double dt;
            if (g_short && rel == RJ_RELEASE_RC12) continue;   /* short version: rc13 only */
            build_stickslip(&b, ratios[ri]);
            scn_method(&b, meth, rel);
            dt = bound_at(&b, 0) * 0.9;
            if (meth == RJ_METHOD_PENALTY) scn_penalty_max(&b, dt);
            memset(&o, 0, sizeof o);
            o.a0 = rj_rad(90.0); o.t1 = t1; o.tlim = -1;
            snprintf(kase, sizeof kase, "7: stick-slip T = %.2f T_f", ratios[ri]);
            run_case(&b, meth == RJ_METHOD_ADAPTIVE ? 0 : dt, n * dt, kase, meth, rel, 1.0 + 1e-6, &cr, ss_hook, &o);
            if (cr.create != RJ_OK) { size_t len = strlen(bad); snprintf(bad + len, sizeof bad - len, " %s/%s refused", method_name(meth), release_name(rel)); continue; }
            nrun++;
            if (o.drift > dmax) dmax = o.drift;
            if (o.drift < dmin) dmin = o.drift;
            if (o.th1 < th1min) th1min = o.th1;
            if (o.th1 > th1max) th1max = o.th1;
            if (o.tlim >= 0 && o.tlim < tl_min) tl_min = o.tlim;
            if (o.tlim > tl_max) tl_max = o.tlim;
            if (cr.w.r != RJ_OK || cr.w.undet || cr.w.nonfinite) { size_t len = strlen(bad); snprintf(bad + len, sizeof bad - len, " %s/%s: %s", method_name(meth), release_name(rel), cr.w.err); }
        }
        if (!slip) {
            snprintf(what, sizeof what, "stick-slip %.2f T_f: stuck, no creep over %ld steps (every method)", ratios[ri], n);
            rjt_check(c, nrun == (g_short ? 5 : 10) && dmax < 1e-9 && !bad[0], what, "largest |theta - theta0| %.3g rad (%.3g deg) <= 1e-9 rad in %d runs%s", dmax, rj_deg(dmax), nrun, bad);
        } else {
            double pred = (ratios[ri] - 1.0) * SS_TF * t1 * t1 / (2.0 * Irig);
            snprintf(what, sizeof what, "stick-slip %.2f T_f: slips and accelerates as (T - T_f)/I", ratios[ri]);
            rjt_check(c, nrun == (g_short ? 5 : 10) && dmin > 1e-6 && fabs(th1min / pred - 1.0) < 0.05 && fabs(th1max / pred - 1.0) < 0.05 && !bad[0], what,
                      "theta - theta0 at %.1f s: %.6g ... %.6g rad, rigid-rod (T - T_f) t^2 / 2I = %.6g rad (I = %.4g kg m^2); %s %.4f ... %.4f s%s",
                      t1, th1min, th1max, pred, Irig, tl_max > 0 ? "reaches the +20 deg limit at" : "does not reach the +20 deg limit in the run", tl_max > 0 ? tl_min : 0.0, tl_max > 0 ? tl_max : 0.0, bad);
        }
    }
    {   /* breakaway ratio by bisection: smallest T/T_f that moves the joint within 2e4 steps */
        double lo = 0.9, hi = 1.1;
        int it;
        for (it = 0; it < 30; it++) {
            double mid = 0.5 * (lo + hi);
            if (ss_slips(mid, 20000)) hi = mid; else lo = mid;
        }
        rjt_check(c, fabs(hi - 1.0) <= 0.01, "stick-slip: the joint breaks away within 1 % of T_f",
                  "breakaway between %.10f and %.10f T_f (bisection, moved > 1e-9 rad within 2e4 steps)", lo, hi);
    }
}

/* ------------------------------------------------------------------ check 8: a long lock */
/* Two 0.25 m strips (2 elements each, 20 x 10 mm aluminium): joint 0 ground -> link 0 with a
   forward limit 3 deg ahead, joint 1 link 0 -> link 1 with a reverse limit 3 deg behind, both
   locks, springs (2 and 1 N m/rad, preloaded 1 rad) driving them into the latch. */
static void build_locked(scn *b)
{
    int i;
    memset(b, 0, sizeof *b);
    for (i = 0; i < 2; i++) {
        b->L[i] = rj_default_link_def();
        b->L[i].length = 0.25; b->L[i].elements = 2; b->L[i].width = 0.02; b->L[i].height = 0.01;
        b->J[i] = rj_default_joint_def();
        b->J[i].body1 = i - 1; b->J[i].body2 = i; b->J[i].lock = 1;
    }
    b->J[0].angle0 = 0.0; b->J[0].has_forward = 1; b->J[0].forward = rj_rad(3.0);
    b->J[0].spring_k = 2.0; b->J[0].spring_free_angle = 1.0;
    b->J[1].angle0 = ST_PI; b->J[1].has_reverse = 1; b->J[1].reverse = rj_rad(177.0);
    b->J[1].spring_k = 1.0; b->J[1].spring_free_angle = ST_PI - 1.0;
    b->sc = rj_default_scene_def();
    b->sc.link_count = 2; b->sc.joint_count = 2;
    scn_fix(b);
}
typedef struct lkobs { long steps, latched_at, bad; double e_early, e_late, pen; } lkobs;
static int lk_hook(const rj_model *m, const rj_state *s, void *user)
{
    lkobs *o = (lkobs *)user;
    int both = rj_joint_flag(m, s, 0) == RJ_LOCKED && rj_joint_flag(m, s, 1) == RJ_LOCKED;
    o->steps++;
    if (!o->latched_at && both) o->latched_at = o->steps;
    else if (o->latched_at && !both) o->bad++;
    if (o->latched_at) {
        double p = fabs(rj_joint_penetration(m, s, 0)) > fabs(rj_joint_penetration(m, s, 1)) ? fabs(rj_joint_penetration(m, s, 0)) : fabs(rj_joint_penetration(m, s, 1));
        if (p > o->pen) o->pen = p;
    }
    return 0;
}

/* CHECK 8. Protection exercised: locks are permanent (Eq 7, flag 3 never released), the lock
   angle and the methods' holding action over a very long run (no drift, no slow pumping),
   and the step's determinism over 1e7 steps. Fails if a flag changes, if the energy rises
   above its initial value, or if the lock creeps (penetration growing without bound). */
static void check8(rjt_ctx *c)
{
    long n = g_short ? 100000L : 10000000L;
    int meth;
    char what[256];
    printf("\n## check 8: %ld steps in a locked configuration\n", n);
    for (meth = 0; meth < 5; meth++) {
        scn b; caseres cr; lkobs o; double dt;
        build_locked(&b);
        scn_method(&b, meth, RJ_RELEASE_RC13);
        dt = meth == RJ_METHOD_ADAPTIVE ? 0 : bound_at(&b, 0) * 0.9;
        if (meth == RJ_METHOD_PENALTY) { scn_penalty_max(&b, dt); dt = bound_at(&b, dt) * 0.9; }
        memset(&o, 0, sizeof o);
        {
            rj_model *m; rj_error e;
            if (scn_make(&b, dt, 0, &m, &e) == RJ_OK) { dt = rj_model_dt(m); rj_model_destroy(m, NULL); }
        }
        run_case(&b, dt, n * dt, "8: two locks, long run", meth, -1, 1.0 + 1e-6, &cr, lk_hook, &o);
        if (meth == 0) {
            /* the bare step, without this suite's per-step bookkeeping */
            rj_model *m; rj_state *s = NULL; rj_error e; long k; double t0;
            if (scn_make(&b, dt, 0, &m, &e) == RJ_OK) {
                rj_state_create(m, &s, NULL);
                t0 = now_s();
                for (k = 0; k < 200000; k++) rj_step(m, s);
                printf("  bare rj_step on this model: %.0f ns/step (1e7 steps: %.1f s)\n", (now_s() - t0) / 200000 * 1e9, (now_s() - t0) / 200000 * 1e7);
                rj_state_destroy(s, NULL); rj_model_destroy(m, NULL);
            }
        }
        snprintf(what, sizeof what, "locked %ld steps %s: flags stay locked, energy bounded", n, method_name(meth));
        rjt_check(c, cr.create == RJ_OK && o.latched_at > 0 && o.bad == 0 && watch_stable(&cr.w, 1.0 + 1e-6) && o.steps == n, what,
                  "both latched at step %ld (%.4g ms), %ld steps (%.4g s simulated at dt %.4g us) with %ld flag changes; E_peak/E0 %.9f, |balance|/E0 %.2g, largest lock penetration %.4g rad (%.3g deg); %.2f s wall (%.0f ns/step)%s%s",
                  o.latched_at, o.latched_at * cr.dt * 1e3, o.steps, o.steps * cr.dt, cr.dt * 1e6, o.bad, cr.w.epeak, cr.w.bal, o.pen, rj_deg(o.pen),
                  cr.w.wall, 1e9 * cr.w.wall / (o.steps > 0 ? o.steps : 1), cr.w.r != RJ_OK ? "; " : "", cr.w.err);
        /* Protection: the energy accounts while locked (lost_limit). */
        snprintf(what, sizeof what, "locked %ld steps %s: energy balance closes (|balance| <= 1e-3 E0)", n, method_name(meth));
        rjt_check(c, cr.w.bal <= 1e-3, what, "max |total + lost - E0| / E0 = %.3g", cr.w.bal);
    }
}

/* ------------------------------------------------------------------ check 9: blow-ups far above the bound */
/* CHECK 9 ("the step never returns non-finite numbers silently"). Scenes run with dt far
   above their bound (solver.allow_unstable = 1) until rj_step stops. Before every step the
   state is copied (rj_state_copy); after every RJ_OK step all node and joint values must be
   finite; the stop must be RJ_ERR_BLOWUP (or RJ_ERR_TUNNEL), leave the state equal to the
   copy (rj_state_save of both, byte for byte), and the message must give the time and the
   likely cause ("the step is above the stability bound"). Protection exercised: rj_step's
   non-finite and energy-growth checks, the commit-after-check of the two frames, the
   message. A second line per scene reports how far the energy had run past the documented
   limit (energy_growth x E0) while rj_step still returned RJ_OK. */
static void check9(rjt_ctx *c)
{
    static const double facs[3] = { 2.0, 4.0, 10.0 };
    long nmax = g_short ? 20000L : 200000L;
    int model, fi;
    char what[256], kase[96];
    printf("\n## check 9: blow-ups at 2 / 4 / 10 x the bound with allow_unstable: detected, state kept, message\n");
    deploy_eq31();
    for (model = 0; model < 13; model++) {
        scn b;
        int meth = -1;
        char name[48], bad[500] = "", late[500] = "";
        int nrun = 0;
        double worst = 0;
        if (model == 0) { build_free(&b, 0.05); snprintf(name, sizeof name, "free link"); }
        else if (model == 1) { build_pinned(&b); snprintf(name, sizeof name, "pinned link"); }
        else if (model < 7) {
            impact_opts io = impact_default_opts();
            memset(&b, 0, sizeof b);
            io.method = meth = model - 2;
            impact_scene(&io, b.L, &b.J[0], &b.sc);
            scn_fix(&b);
            snprintf(name, sizeof name, "impact H=0.2 %s", method_name(meth));
        } else if (model < 12) { meth = model - 7; build_deploy(&b, meth); snprintf(name, sizeof name, "deployment %s", method_name(meth)); }
        else { build_chain(&b); snprintf(name, sizeof name, "chain (no limits)"); }
        for (fi = 0; fi < 3; fi++) {
            rj_model *m; rj_state *s = NULL; rj_error e; rj_result r; watch w; keepres kr;
            double bd, dt = dt_for_factor(&b, facs[fi], &bd);
            size_t len = strlen(bad);
            if (scn_make(&b, dt, 1, &m, &e) != RJ_OK) { snprintf(bad + len, sizeof bad - len, " %.0fx: not built (%.160s)", facs[fi], e.msg); continue; }
            rj_state_create(m, &s, NULL);
            watch_init(&w, m);
            r = run_keep(m, s, nmax, &w, &kr);
            nrun++;
            snprintf(kase, sizeof kase, "9: %s, %.1f x bound", name, facs[fi]);
            row_add(kase, meth, meth >= 0 ? RJ_RELEASE_RC13 : -1, dt, bd, &w, state_peak_pen(m, s), NULL, 1.001);
            if (kr.silent_nonfinite)
                snprintf(bad + len, sizeof bad - len, " %.1fx: NON-FINITE state after an RJ_OK step at t = %.6g s;", facs[fi], w.t_nonfinite);
            else if (!kr.stopped)
                snprintf(bad + len, sizeof bad - len, " %.1fx: NOT STOPPED in %ld steps (E_peak/E0 %.3g);", facs[fi], w.steps, w.epeak);
            else if (!(r == RJ_ERR_BLOWUP || r == RJ_ERR_TUNNEL) || !kr.intact || strstr(w.err, "t = ") == NULL ||
                     (r == RJ_ERR_BLOWUP && strstr(w.err, "above the stability bound") == NULL))
                snprintf(bad + len, sizeof bad - len, " %.1fx: %s after %ld steps, state %s: \"%.150s\";", facs[fi], rj_result_str(r), w.steps,
                         kr.intact ? "intact" : "CHANGED", w.err);
            if (!kr.warn_same && kr.stopped) printf("  note: %s %.1fx: the failed step changed rj_state_warning() (the frame is intact)\n", name, facs[fi]);
            if (w.uratio > worst) worst = w.uratio;
            if (w.undet) {
                len = strlen(late);
                snprintf(late + len, sizeof late - len, " %.1fx: %.3g x at t = %.4g ms, reported %ld steps later;", facs[fi], w.uratio, w.t_undet * 1e3,
                         (long)floor((w.t_err - w.t_undet) / dt + 0.5));
            }
            rj_state_destroy(s, NULL); rj_model_destroy(m, NULL);
        }
        snprintf(what, sizeof what, "%s far above the bound: every blow-up stopped, named, last good state kept, never non-finite", name);
        rjt_check(c, bad[0] == 0 && nrun == 3, what, "%d runs (2, 4, 10 x bound) stopped within %ld steps with RJ_ERR_BLOWUP/TUNNEL naming the time and the step above the bound; states byte-identical to the copy%s%s",
                  nrun, nmax, bad[0] ? "; BAD:" : "", bad);
        snprintf(what, sizeof what, "%s far above the bound: stopped before the energy passed 2 x the documented 10 x E0", name);
        rjt_check(c, late[0] == 0, what, "largest (strain or |kinetic|) on an RJ_OK step: %.3g x (10 x E0)%s%s", worst, late[0] ? "; LATE:" : "", late);
    }
}

/* ------------------------------------------------------------------ main */
int main(int argc, char **argv)
{
    rjt_ctx c = { 0, 0 };
    const char *table = NULL;
    int only = 0, i;
    double t0 = now_s();
    for (i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--short")) g_short = 1;
        else if (!strcmp(argv[i], "--table") && i + 1 < argc) table = argv[++i];
        else if (!strcmp(argv[i], "--only") && i + 1 < argc) only = atoi(argv[++i]);
        else { fprintf(stderr, "usage: %s [--short] [--table FILE] [--only N]\n", argv[0]); return 2; }
    }
    printf("# revjoint stress suite (%s)\n", g_short ? "short" : "full");
    {
        static void (*const checks[9])(rjt_ctx *) = { check1, check2, check3, check4, check5, check6, check7, check8, check9 };
        for (i = 0; i < 9; i++) {
            double tc = now_s();
            if (only && only != i + 1) continue;
            checks[i](&c);
            printf("  (check %d: %.1f s wall)\n", i + 1, now_s() - tc);
        }
    }
    printf("\n## results table\n\n");
    table_print(stdout);
    if (table) {
        FILE *f = fopen(table, "w");
        if (!f) { printf("FAIL cannot write %s\n", table); c.fail++; }
        else { table_print(f); fclose(f); }
    }
    printf("\nstress (%s): %.1f s wall\n", g_short ? "short" : "full", now_s() - t0);
    return rjt_summary(&c, "stress");
}
