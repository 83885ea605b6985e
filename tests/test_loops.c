/* Closed loops against what we did not tune.
   - A crank-rocker four-bar of flexible bars under gravity, released from rest, against
     the exact one-degree-of-freedom motion of the same bars made rigid (Lagrange's
     equation in the crank angle, the loop closed by Newton at every evaluation, RK4):
     the crank's angle converges to it as E grows (the bars' own compliance, 1/E), the
     loop-closing joint's angle follows the rocker's and the coupler's, its pins stay
     together (one pin group), and the energy balance closes.
   - A joint pinning an interior node of its body2 (node2), and the refusals: a loop that
     does not close (the gap named), a loop joint at the wrong angle0 (the right one
     named), a loop through a rigid link, node2 on a chord joint.
   Every check prints what it measured. */
#include "../revjoint.h"
#include "rjt.h"

/* Under AddressSanitizer (build/test_loops_asan) the long runs are cut to a tenth: that
   build checks the memory the code paths touch, which the short runs reach; the plain
   build checks the numbers over the full lengths. */
#if defined(__SANITIZE_ADDRESS__)
#define LONG_RUN_STEPS 100000L
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define LONG_RUN_STEPS 100000L
#endif
#endif
#ifndef LONG_RUN_STEPS
#define LONG_RUN_STEPS 1000000L
#endif
/* the rigid four-bar's runs against the exact motion: 5 s, or 1 s under the sanitizer */
#define RIGID_SECONDS (LONG_RUN_STEPS > 100000L ? 5.0 : 1.0)
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846
#define G 9.81

/* The four-bar: ground pivots O2 = (0, 0) and O4 = (1, 0) m, crank a = 0.3 m, coupler
   b = 1 m, rocker c = 0.8 m (Grashof: 0.3 + 1 <= 0.8 + 1, the crank turns fully), all
   20 x 20 mm aluminium bars; the crank starts at 60 deg, the coupler and rocker where the
   loop closes (upper branch): computed by close_loop, written with 17 digits. */
#define BAR_A 0.3
#define BAR_B 1.0
#define BAR_C 0.8
#define GROUND_D 1.0
#define CRANK0 (PI / 3)

/* theta3, theta4 that close the loop at crank angle th2, by Newton from *t3, *t4. */
static int close_loop(double th2, double *t3, double *t4)
{
    int it;
    for (it = 0; it < 50; it++) {
        const double c3 = cos(*t3), s3 = sin(*t3), c4 = cos(*t4), s4 = sin(*t4);
        const double fx = BAR_A * cos(th2) + BAR_B * c3 - GROUND_D - BAR_C * c4;
        const double fy = BAR_A * sin(th2) + BAR_B * s3 - BAR_C * s4;
        /* d/dt3 (b c3, b s3) = (-b s3, b c3); d/dt4 -(c c4, c s4) = (c s4, -c c4) */
        const double j11 = -BAR_B * s3, j12 = BAR_C * s4, j21 = BAR_B * c3, j22 = -BAR_C * c4;
        const double det = j11 * j22 - j12 * j21;
        const double d3 = (fx * j22 - fy * j12) / det, d4 = (j11 * fy - j21 * fx) / det;
        *t3 -= d3;
        *t4 -= d4;
        if (fabs(d3) + fabs(d4) < 1e-15)
            return 1;
    }
    return 0;
}

/* A bar's rigid mass properties from the model's lumped nodes: mass, first moment and
   second moment (rotary inertias included) about its node 0 along the bar; a rigid
   link of a mixed scene (its nodes massless) as the uniform rod it is. */
typedef struct bar {
    double m, s, J;
} bar;

static bar bar_of(const rj_model *m, int link, double length)
{
    const int n = rj_link_node_count(m, link);
    const rj_link_def *d = rj_model_link_def(m, link);
    bar b = { 0, 0, 0 };
    int k;
    if (d->fidelity == RJ_LINK_RIGID) {
        b.m = d->rho * d->width * d->height * length;
        b.s = b.m * length / 2;
        b.J = b.m * length * length / 3;
        return b;
    }
    for (k = 0; k < n; k++) {
        double mass, rot;
        const double x = length * k / (n - 1);
        rj_node_mass(m, link, k, &mass, &rot);
        b.m += mass;
        b.s += mass * x;
        b.J += mass * x * x + rot;
    }
    return b;
}

/* The rigid four-bar: its bars, and the loop's last solution (Newton starts there). */
typedef struct rigid4 {
    bar crank, coupler, rocker;
    double t3, t4;
    double rotor;   /* a rotor's inertia on the loop joint's rate, kg m^2 */
    double k_cable; /* a cable loop's stiffness from the crank to the loop joint, N m/rad */
} rigid4;

/* Generalised mass M(th2) and potential V(th2), the loop closed at th2. */
static void mass_potential(rigid4 *r, double th2, double *M, double *V, double *t3, double *t4)
{
    double k3, k4, det, c3, s3, c4, s4;
    *t3 = r->t3;
    *t4 = r->t4;
    close_loop(th2, t3, t4);
    c3 = cos(*t3);
    s3 = sin(*t3);
    c4 = cos(*t4);
    s4 = sin(*t4);
    /* rates per unit crank rate: a w2 perp(e2) + b w3 perp(e3) - c w4 perp(e4) = 0 */
    det = (-BAR_B * s3) * (-BAR_C * c4) - (BAR_C * s4) * (BAR_B * c3);
    k3 = ((BAR_A * sin(th2)) * (-BAR_C * c4) - (BAR_C * s4) * (-BAR_A * cos(th2))) / det;
    k4 = ((-BAR_B * s3) * (-BAR_A * cos(th2)) - (BAR_B * c3) * (BAR_A * sin(th2))) / det;
    *M = r->crank.J + r->coupler.m * BAR_A * BAR_A +
         2 * BAR_A * k3 * r->coupler.s * cos(*t3 - th2) + r->coupler.J * k3 * k3 +
         r->rocker.J * k4 * k4;
    *V = G * (r->crank.s * sin(th2) + r->coupler.m * BAR_A * sin(th2) + r->coupler.s * s3 +
              r->rocker.s * s4);
    /* the loop joint's angle t4 - t3 - pi turns at k4 - k3 per crank radian; the cable
       loop stretches by its turn since the start (ratio 1) less the crank's */
    *M += r->rotor * (k4 - k3) * (k4 - k3);
    if (r->k_cable > 0) {
        double t3_0 = 0.5, t4_0 = 1.5, stretch;
        close_loop(CRANK0, &t3_0, &t4_0);
        stretch = ((*t4 - *t3) - (t4_0 - t3_0)) - (th2 - CRANK0);
        *V += 0.5 * r->k_cable * stretch * stretch;
    }
}

/* th2'' from Lagrange's equation M th2'' + M'/2 th2'^2 + V' = 0 (M', V' by central
   differences, step 1e-6 rad). */
static double crank_accel(rigid4 *r, double th2, double w2)
{
    const double h = 1e-6;
    double Mp, Vp, Mm, Vm, M, V, t3, t4;
    mass_potential(r, th2 + h, &Mp, &Vp, &t3, &t4);
    mass_potential(r, th2 - h, &Mm, &Vm, &t3, &t4);
    mass_potential(r, th2, &M, &V, &t3, &t4);
    r->t3 = t3;
    r->t4 = t4;
    return -(0.5 * (Mp - Mm) / (2 * h) * w2 * w2 + (Vp - Vm) / (2 * h)) / M;
}

static void rigid_rk4(rigid4 *r, double *q, double *w, double h)
{
    const double a1 = crank_accel(r, *q, *w);
    const double a2 = crank_accel(r, *q + 0.5 * h * *w, *w + 0.5 * h * a1);
    const double a3 = crank_accel(r, *q + 0.5 * h * (*w + 0.5 * h * a1), *w + 0.5 * h * a2);
    const double a4 = crank_accel(r, *q + h * (*w + 0.5 * h * a2), *w + h * a3);
    *q += h * (*w + h * (a1 + a2 + a3) / 6);
    *w += h * (a1 + 2 * a2 + 2 * a3 + a4) / 6;
    crank_accel(r, *q, *w);
}

/* The scene at modulus E (Pa), its links of the fidelity named ("" for the default,
   flexible, "inextensible"; two names for the crank and rocker, then the coupler:
   "flexible rigid"; three for the crank, the coupler and the rocker) at step dt (0:
   automatic), the loop's angles from close_loop. */
static void fourbar_text(double E, const char *fidelity, double dt, char *text, size_t n)
{
    double t3 = 0.5, t4 = 1.5;
    char key[64] = "", coupler[64] = "", rocker[64] = "", name[3][32] = { "", "", "" };
    const int names = sscanf(fidelity, "%31s %31s %31s", name[0], name[1], name[2]);
    if (names < 2)
        snprintf(name[1], sizeof name[1], "%s", name[0]);
    if (names < 3)
        snprintf(name[2], sizeof name[2], "%s", name[0]);
    if (name[0][0])
        snprintf(key, sizeof key, "  fidelity = %s\n", name[0]);
    if (name[1][0])
        snprintf(coupler, sizeof coupler, "  fidelity = %s\n", name[1]);
    if (name[2][0])
        snprintf(rocker, sizeof rocker, "  fidelity = %s\n", name[2]);
    close_loop(CRANK0, &t3, &t4);
    snprintf(text, n,
             "solver\n  dt = %.17g\n  gravity = 0 -9.81\n"
             "material al\n  E = %.17g  rho = 2700\n"
             "section bar\n  width = 0.02  height = 0.02\n"
             "link crank\n  length = %.17g  elements = 3  material = al  section = bar\n%s"
             "link coupler\n  length = %.17g  elements = 10  material = al  section = bar\n%s"
             "link rocker\n  length = %.17g  elements = 8  material = al  section = bar\n%s"
             "joint o2\n  body1 = ground  body2 = crank  angle0 = %.17g\n"
             "joint a\n  body1 = crank  body2 = coupler  angle0 = %.17g\n"
             "joint o4\n  body1 = ground  body2 = rocker  ground_x = %.17g  angle0 = %.17g\n"
             "joint b\n  body1 = coupler  body2 = rocker  node2 = last  angle0 = %.17g\n",
             dt, E, BAR_A, key, BAR_B, coupler, BAR_C, rocker, CRANK0, t3 - (CRANK0 + PI), GROUND_D, t4,
             t4 - (t3 + PI));
}

/* What a four-bar run measured against the rigid motion over t_end. */
typedef struct fourbar_run {
    double crank, loop_angle, gap, balance, energy;
    double stretch; /* the largest |element length - l0| / l0 */
    double dt;      /* the step taken */
    double midspan; /* the coupler's largest deflection from its chord, m */
    rj_result result;
    char msg[700];
} fourbar_run;

/* Builds the model of text; 0 with o->msg filled when it fails. */
static int build(const char *text, rj_model **m, rj_state **s, rj_error *err)
{
    rj_scene_file f;
    rj_scene_def d;
    rj_result r = rj_scene_parse(text, strlen(text), "fourbar.rjs", &f, err);
    if (r != RJ_OK)
        return 0;
    d = rj_scene_file_def(&f);
    r = rj_model_create(&d, m, err, NULL);
    rj_scene_file_free(&f);
    if (r != RJ_OK)
        return 0;
    rj_state_create(*m, s, NULL);
    return 1;
}

/* The largest relative change of an element's length over the scene's links. */
static double worst_stretch(const rj_model *m, const rj_state *s)
{
    double worst = 0;
    int l, k;
    for (l = 0; l < rj_model_link_count(m); l++) {
        const rj_link_def *d = rj_model_link_def(m, l);
        const double l0 = d->length / d->elements;
        for (k = 0; k + 1 < rj_link_node_count(m, l); k++) {
            double a[2], b[2];
            rj_node_position(m, s, l, k, a);
            rj_node_position(m, s, l, k + 1, b);
            worst = fmax(worst, fabs(hypot(b[0] - a[0], b[1] - a[1]) - l0) / l0);
        }
    }
    return worst;
}

/* The coupler's deflection at its middle node (5 of 10) from its chord, m. */
static double coupler_midspan(const rj_model *m, const rj_state *s)
{
    double a[2], mid[2], b[2], ux, uy;
    rj_node_position(m, s, 1, 0, a);
    rj_node_position(m, s, 1, 5, mid);
    rj_node_position(m, s, 1, 10, b);
    ux = b[0] - a[0];
    uy = b[1] - a[1];
    return ((mid[0] - a[0]) * uy - (mid[1] - a[1]) * ux) / hypot(ux, uy);
}

/* One step of both; the worst differences so far into o. */
static void compare_step(const rj_model *m, const rj_state *s, rigid4 *r, double q, fourbar_run *o)
{
    double xy1[2], xy2[2], theta_b;
    rj_energy e;
    o->crank = fmax(o->crank, fabs(rj_joint_theta_running(m, s, 0) - q));
    /* the loop joint: rocker against coupler reversed, 2 pi apart at most by its turns */
    theta_b = rj_joint_theta_running(m, s, 3);
    o->loop_angle = fmax(o->loop_angle, fabs(remainder(theta_b - (r->t4 - r->t3 - PI), 2 * PI)));
    rj_node_position(m, s, 1, rj_link_node_count(m, 1) - 1, xy1);
    rj_node_position(m, s, 2, rj_link_node_count(m, 2) - 1, xy2);
    o->gap = fmax(o->gap, hypot(xy1[0] - xy2[0], xy1[1] - xy2[1]));
    rj_state_energy(m, s, &e);
    o->balance = fmax(o->balance, fabs(e.balance));
    o->energy = fmax(o->energy, fabs(e.kinetic));
    o->stretch = fmax(o->stretch, worst_stretch(m, s));
    if (rj_model_link_def(m, 1)->fidelity != RJ_LINK_RIGID)
        o->midspan = fmax(o->midspan, fabs(coupler_midspan(m, s)));
}

/* The scene text against the exact motion (rigid4 of its own bars, bar_of, with a rotor's
   inertia on the loop joint and a cable loop from the crank to it) over t_end: the worst
   differences into o. */
static void run_against_exact(const char *text, double rotor, double k_cable, double t_end,
                              fourbar_run *o)
{
    rj_model *m = NULL;
    rj_state *s = NULL;
    rj_error err;
    rigid4 r;
    double q = CRANK0, w = 0;
    memset(o, 0, sizeof *o);
    if (!build(text, &m, &s, &err)) {
        o->result = err.code;
        snprintf(o->msg, sizeof o->msg, "%s", err.msg);
        return;
    }
    o->dt = rj_model_dt(m);
    r.crank = bar_of(m, 0, BAR_A);
    r.coupler = bar_of(m, 1, BAR_B);
    r.rocker = bar_of(m, 2, BAR_C);
    r.t3 = 0.5;
    r.t4 = 1.5;
    r.rotor = rotor;
    r.k_cable = k_cable;
    crank_accel(&r, q, w);
    while (rj_state_time(s) < t_end - 0.5 * o->dt && o->result == RJ_OK) {
        o->result = rj_step(m, s);
        rigid_rk4(&r, &q, &w, o->dt);
        compare_step(m, s, &r, q, o);
    }
    if (o->result != RJ_OK)
        snprintf(o->msg, sizeof o->msg, "t = %g s: %s", rj_state_time(s), rj_state_error(s));
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
}

static void run_fourbar(double E, const char *fidelity, double dt, double t_end, fourbar_run *o)
{
    char text[2048];
    fourbar_text(E, fidelity, dt, text, sizeof text);
    run_against_exact(text, 0, 0, t_end, o);
}

static void test_fourbar(rjt_ctx *c)
{
    static const double E[3] = { 7e8, 7e9, 7e10 };
    fourbar_run o[3];
    int k;
    for (k = 0; k < 3; k++)
        run_fourbar(E[k], "", 0, 1.0, &o[k]);
    for (k = 0; k < 3; k++)
        /* the pins one group (round-off apart); the balance the scheme's error */
        rjt_check(c, o[k].result == RJ_OK && o[k].gap < 1e-12 && o[k].balance < 1e-5 * o[k].energy &&
                         o[k].loop_angle < o[k].crank,
                  "four-bar of flexible bars: the loop closed, the balance closed",
                  "E %.0e Pa: max |crank - rigid| %.3g rad, max |loop joint - rigid| %.3g rad, "
                  "pin gap %.3g m, max |balance| %.3g J of %.3g J kinetic %s",
                  E[k], o[k].crank, o[k].loop_angle, o[k].gap, o[k].balance, o[k].energy,
                  o[k].msg);
    rjt_check(c, o[0].crank / o[1].crank > 5 && o[1].crank / o[2].crank > 5 && o[2].crank < 1e-2,
              "four-bar: the crank converges to the rigid motion as E grows",
              "max |crank - rigid| over 1 s: %.3g, %.3g, %.3g rad at E 7e8, 7e9, 7e10 Pa "
              "(ratios %.1f, %.1f)",
              o[0].crank, o[1].crank, o[2].crank, o[0].crank / o[1].crank,
              o[1].crank / o[2].crank);
    /* what is left of the rigid motion: the coupler bends as it swings, less as E grows */
    rjt_check(c, o[0].midspan > 0.01 && o[0].midspan / o[1].midspan > 5 &&
                     o[1].midspan / o[2].midspan > 5,
              "four-bar: the soft coupler bends as it swings, as 1/E",
              "the coupler's largest midspan deflection from its chord over 1 s: %.3g, %.3g, "
              "%.3g m at E 7e8, 7e9, 7e10 Pa",
              o[0].midspan, o[1].midspan, o[2].midspan);
}

/* Inextensible bars: the same convergence to the rigid motion (their bending is what
   is left), every element held at its length by SHAKE over the chains that meet at the
   loop's pin. */
static void test_fourbar_inextensible(rjt_ctx *c)
{
    static const double E[3] = { 7e8, 7e9, 7e10 };
    fourbar_run o[3], half;
    int k;
    for (k = 0; k < 3; k++)
        run_fourbar(E[k], "inextensible", 0, 1.0, &o[k]);
    for (k = 0; k < 3; k++)
        rjt_check(c, o[k].result == RJ_OK && o[k].gap < 1e-12 && o[k].stretch < 1e-12 &&
                         o[k].balance < 2e-5 * o[k].energy,
                  "four-bar of inextensible bars: the loop closed, the lengths held",
                  "E %.0e Pa: max |crank - rigid| %.3g rad, pin gap %.3g m, max element "
                  "stretch %.3g, max |balance| %.3g J of %.3g J kinetic %s",
                  E[k], o[k].crank, o[k].gap, o[k].stretch, o[k].balance, o[k].energy,
                  o[k].msg);
    rjt_check(c, o[0].crank / o[1].crank > 5 && o[1].crank / o[2].crank > 5 && o[2].crank < 1e-2,
              "four-bar of inextensible bars: the crank converges to the rigid motion",
              "max |crank - rigid| over 1 s: %.3g, %.3g, %.3g rad at E 7e8, 7e9, 7e10 Pa",
              o[0].crank, o[1].crank, o[2].crank);
    /* without the axial bound the soft bars step 10 times longer than flexible ones:
       their balance is the scheme's second-order error at that step */
    run_fourbar(E[0], "inextensible", 0.5 * o[0].dt, 1.0, &half);
    rjt_check(c, half.result == RJ_OK && half.balance < o[0].balance / 3,
              "four-bar of inextensible bars: the balance second order in dt",
              "E 7e8 Pa: max |balance| %.3g J at dt %.3g s, %.3g J at half (ratio %.2f) %s",
              o[0].balance, o[0].dt, half.balance, o[0].balance / half.balance, half.msg);
}

/* Rigid bodies among flexible bars (a loop through rigid bodies of a mixed scene): a
   rigid coupler; a rigid crank and coupler (joint a pins two bodies); a rigid coupler
   and rocker (the loop joint pins two bodies). The same convergence to the rigid motion
   as the flexible bars stiffen, the pins together, the balance closed. */
static void test_fourbar_mixed(rjt_ctx *c)
{
    static const double E[3] = { 7e8, 7e9, 7e10 };
    static const char *const models[3][2] = {
        { "flexible rigid", "a rigid coupler" },
        { "rigid rigid flexible", "a rigid crank and coupler" },
        { "flexible rigid rigid", "a rigid coupler and rocker" },
    };
    fourbar_run o[3];
    int k, v;
    for (v = 0; v < 3; v++) {
        int closed = 1;
        for (k = 0; k < 3; k++)
            run_fourbar(E[k], models[v][0], 0, 1.0, &o[k]);
        for (k = 0; k < 3; k++)
            closed &= o[k].result == RJ_OK && o[k].gap < 1e-12 &&
                      o[k].balance < 1e-5 * o[k].energy;
        rjt_check(c, closed && o[0].crank / o[1].crank > 5 && o[1].crank / o[2].crank > 5 &&
                         o[2].crank < 1e-2,
                  "four-bar with rigid bodies among flexible bars: the loop closed, the rigid "
                  "motion approached",
                  "%s: max |crank - rigid| over 1 s %.3g, %.3g, %.3g rad at E 7e8, 7e9, 7e10 "
                  "Pa; pin gap %.3g m; max |balance| %.3g J of %.3g J kinetic (at 7e10) %s%s",
                  models[v][1], o[0].crank, o[1].crank, o[2].crank, o[2].gap, o[2].balance,
                  o[2].energy, o[0].msg, o[2].msg);
    }
}

/* A tree of inextensible links that meet inside a link: a branch hanging from the middle
   of the first link, beside the link at its tip. Solved chain by chain, the branch's
   correction moved the first link's middle node after that link was done: lengths off
   by 1.6e-6 and energy created until the run stopped at 0.87 s. */
static void test_inextensible_tree(rjt_ctx *c)
{
    static const char text[] =
        "solver\n  dt = 0\n  gravity = 0 -9.81\n"
        "material al\n  E = 7e10  rho = 2700\n"
        "section bar\n  width = 0.02  height = 0.02\n"
        "link main\n  length = 1  elements = 10  material = al  section = bar\n"
        "  fidelity = inextensible\n"
        "link branch\n  length = 0.5  elements = 5  material = al  section = bar\n"
        "  fidelity = inextensible\n"
        "link end\n  length = 0.5  elements = 5  material = al  section = bar\n"
        "  fidelity = inextensible\n"
        "joint o\n  body1 = ground  body2 = main  angle0 = 0\n"
        "joint b\n  body1 = main  body2 = branch  node1 = 5  angle0 = 0.5\n"
        "joint c\n  body1 = main  body2 = end  angle0 = 0.3\n";
    rj_model *m = NULL;
    rj_state *s = NULL;
    rj_error err;
    rj_energy e0, e;
    rj_result r = RJ_OK;
    double stretch = 0, balance = 0, kinetic = 0;
    if (!build(text, &m, &s, &err)) {
        rjt_check(c, 0, "inextensible tree: lengths held where chains meet", "%s", err.msg);
        return;
    }
    rj_state_energy(m, s, &e0);
    while (rj_state_time(s) < 1.0 && r == RJ_OK) {
        r = rj_step(m, s);
        stretch = fmax(stretch, worst_stretch(m, s));
        rj_state_energy(m, s, &e);
        balance = fmax(balance, fabs(e.balance));
        kinetic = fmax(kinetic, e.kinetic);
    }
    rjt_check(c, r == RJ_OK && stretch < 1e-12 && balance < 1e-5 * kinetic,
              "inextensible tree: lengths held where chains meet",
              "1 s: max element stretch %.3g, max |balance| %.3g J of %.3g J kinetic %s",
              stretch, balance, kinetic, r == RJ_OK ? "" : rj_state_error(s));
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
}

/* Builds text with the edit applied (find replaced by put); the result and message. */
/* The four-bar's text at 7e10 Pa with find replaced by put into out; 0 without find. */
static int edited_text(const char *fidelity, const char *find, const char *put, char *out,
                       size_t n)
{
    char text[2048];
    const char *at;
    fourbar_text(7e10, fidelity, 0, text, sizeof text);
    at = strstr(text, find);
    if (!at)
        return 0;
    snprintf(out, n, "%.*s%s%s", (int) (at - text), text, put, at + strlen(find));
    return 1;
}

static rj_result edited(const char *fidelity, const char *find, const char *put, rj_error *err)
{
    char out[2048];
    rj_model *m = NULL;
    rj_state *s = NULL;
    if (!edited_text(fidelity, find, put, out, sizeof out)) {
        snprintf(err->msg, sizeof err->msg, "no '%s' in the scene", find);
        return RJ_ERR_PARSE;
    }
    if (!build(out, &m, &s, err))
        return err->code;
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
    err->msg[0] = 0;
    return RJ_OK;
}

/* A spring and damping on the loop joint between a rigid coupler and a rigid rocker (a
   joint between two bodies of a mixed scene takes torques): the pins together, the
   damping's loss in the balance. */
static void test_body_pair_torques(rjt_ctx *c)
{
    char text[2048];
    rj_model *m = NULL;
    rj_state *s = NULL;
    rj_error err;
    rj_energy e;
    double gap = 0, balance = 0, kinetic = 0;
    rj_result r = RJ_OK;
    if (!edited_text("flexible rigid rigid", "node2 = last",
                     "node2 = last  spring = 2 240 deg  damping = 0.05", text, sizeof text) ||
        !build(text, &m, &s, &err)) {
        rjt_check(c, 0, "four-bar: a spring and damping between two rigid bodies", "%s",
                  err.msg);
        return;
    }
    while (rj_state_time(s) < 2 && r == RJ_OK) {
        double xy1[2], xy2[2];
        r = rj_step(m, s);
        rj_node_position(m, s, 1, rj_link_node_count(m, 1) - 1, xy1);
        rj_node_position(m, s, 2, rj_link_node_count(m, 2) - 1, xy2);
        gap = fmax(gap, hypot(xy1[0] - xy2[0], xy1[1] - xy2[1]));
        rj_state_energy(m, s, &e);
        balance = fmax(balance, fabs(e.balance));
        kinetic = fmax(kinetic, e.kinetic);
    }
    rjt_check(c, r == RJ_OK && gap < 1e-12 && e.lost_damping > 0.01 && balance < 1e-5 * kinetic,
              "four-bar: a spring and damping between two rigid bodies",
              "2 s: pins %.3g m apart; W_damping %.4g J; max |balance| %.3g J of %.3g J "
              "kinetic %s",
              gap, e.lost_damping, balance, kinetic, r == RJ_OK ? "" : rj_state_error(s));
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
}

/* A motor on a flexible flap hanging from the middle of a rigid body, that body pinned
   to a second one whose pin carries a load: the pins between the bodies turn the first
   body after the joints' rates are taken. A constant torque's work is exactly the torque
   times the angle turned, which the accounts must book (they booked 40 % less, and the
   run stopped at its first step on the energy it seemed to create). */
static void test_body_pin_motor(rjt_ctx *c)
{
    static const char *const text =
        "link base\n  length = 0.5  elements = 4  root = clamped\n"
        "link r1\n  length = 0.25  elements = 2  fidelity = rigid  width = 0.01  height = 0.02\n"
        "link r2\n  length = 0.25  elements = 1  fidelity = rigid  width = 0.01  height = 0.02\n"
        "link flap\n  length = 0.2  elements = 2\n"
        "joint j\n  body1 = base  body2 = r1\n"
        "joint b\n  body1 = r1  body2 = r2  spring = 1866.67 180 deg\n"
        "joint k\n  body1 = r1  node1 = 1  body2 = flap  angle0 = 90 deg\n"
        "load push\n  link = r2  node = 0  force = 0 -10\n"
        "actuator drive\n  joint = k  torque = 0.1\n";
    rj_model *m = NULL;
    rj_state *s = NULL;
    rj_error err;
    rj_energy e;
    double theta0, turned, balance = 0, scale = 0;
    rj_result r = RJ_OK;
    if (!build(text, &m, &s, &err)) {
        rjt_check(c, 0, "motor on a body that pins between bodies turn", "%s", err.msg);
        return;
    }
    theta0 = rj_joint_theta_running(m, s, 2);
    while (rj_state_time(s) < 0.02 && r == RJ_OK) {
        r = rj_step(m, s);
        rj_state_energy(m, s, &e);
        balance = fmax(balance, fabs(e.balance));
        scale = fmax(scale, e.work_applied + fabs(e.work_drive));
    }
    /* the accounts lag the state by one step: the angle at their time */
    turned = rj_joint_theta_running(m, s, 2) - rj_joint_rate(m, s, 2) * rj_model_dt(m) - theta0;
    rjt_check(c, r == RJ_OK && balance < 1e-8 * scale &&
                     fabs(e.work_drive - 0.1 * turned) < 1e-6 * fabs(e.work_drive),
              "motor on a body that pins between bodies turn: its work is torque x angle",
              "%s %s; 0.02 s: W_drive %.9g J, 0.1 N m x %.9g rad turned; max |balance| %.3g J "
              "of %.3g J done",
              rj_result_str(r), r == RJ_OK ? "" : rj_state_error(s), e.work_drive, turned,
              balance, scale);
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
}

/* The base of the pair scenes below: a flexible cantilever, a rigid link hanging from
   its tip, a second rigid link pinned to the first's tip, under gravity; joint b joins
   the two bodies and takes the tail's parts. */
static int body_pair_scene(const char *tail, rj_model **m, rj_state **s, rj_error *err)
{
    char text[1536];
    snprintf(text, sizeof text,
             "solver\n  gravity = 0 -9.81\n"
             "link base\n  length = 0.5  elements = 4  root = clamped  height = 0.02  "
             "width = 0.02\n"
             "link r1\n  length = 0.3  elements = 2  fidelity = rigid  height = 0.02  "
             "width = 0.02\n"
             "link r2\n  length = 0.3  elements = 1  fidelity = rigid  height = 0.02  "
             "width = 0.02\n"
             "joint a\n  body1 = base  body2 = r1  angle0 = 90 deg\n"
             "joint b\n  body1 = r1  body2 = r2  angle0 = 90 deg  %s\n",
             tail);
    return build(text, m, s, err);
}

/* Runs a pair scene for t_end: the largest |balance| and joint b's angle's range. */
static rj_result body_pair_run(rj_model *m, rj_state *s, double t_end, double *balance,
                               double *lo, double *hi, rj_energy *e)
{
    rj_result r = RJ_OK;
    *balance = 0;
    *lo = *hi = rj_joint_theta_running(m, s, 1);
    while (rj_state_time(s) < t_end && r == RJ_OK) {
        r = rj_step(m, s);
        rj_state_energy(m, s, e);
        *balance = fmax(*balance, fabs(e->balance));
        *lo = fmin(*lo, rj_joint_theta_running(m, s, 1));
        *hi = fmax(*hi, rj_joint_theta_running(m, s, 1));
    }
    return r;
}

/* Friction, a penalty limit and cable loops on a joint between two rigid bodies of a
   mixed scene. Friction above the largest torque the tail's weight and swing need
   (under 1 N m) holds the joint: with each body's own give it crept 5.6e-3 rad in 1 s,
   with the pin's linear velocity 2.5e-5 rad. */
static void test_body_pair_parts(rjt_ctx *c)
{
    static const char *const tails[5] = {
        "friction = 2", "friction = 0.3",
        "method = penalty  penalty_k = 50  reverse = 60 deg  forward = 120 deg", "", ""
    };
    static const char *const names[5] = { "friction holds", "friction slips", "penalty limit",
                                           "elastic cable loop", "exact cable loop" };
    int k;
    for (k = 0; k < 5; k++) {
        rj_model *m = NULL;
        rj_state *s = NULL;
        rj_error err;
        rj_energy e;
        double balance, lo, hi, scale;
        rj_result r;
        char tail[256];
        snprintf(tail, sizeof tail, "%s%s", tails[k],
                 k == 3 ? "\ncoupling cl\n  joints = a b\n  ratio = -1\n  stiffness = 20  "
                          "damping = 0.01"
                 : k == 4 ? "\ncoupling cl\n  joints = a b\n  ratio = -1\n  exact = yes"
                          : "");
        if (!body_pair_scene(tail, &m, &s, &err)) {
            rjt_check(c, 0, "joint between two bodies", "%s: %s", names[k], err.msg);
            continue;
        }
        r = body_pair_run(m, s, 1.0, &balance, &lo, &hi, &e);
        scale = fabs(e.gravity) + e.kinetic;
        if (k == 0)
            rjt_check(c, r == RJ_OK && hi - lo < 1e-7 && balance < 1e-7 * scale,
                      "joint between two bodies: friction above the load holds it",
                      "1 s: angle within %.3g rad; max |balance| %.3g J of %.3g J",
                      hi - lo, balance, scale);
        if (k == 1)
            rjt_check(c, r == RJ_OK && hi - lo > 0.5 && e.lost_friction > 0.1 &&
                             balance < 1e-7 * scale,
                      "joint between two bodies: friction below the load slips, its loss booked",
                      "1 s: turned %.3g rad; W_friction %.4g J; max |balance| %.3g J of %.3g J",
                      hi - lo, e.lost_friction, balance, scale);
        if (k == 2)
            rjt_check(c, r == RJ_OK && hi < rj_rad(130) && hi > rj_rad(120) &&
                             e.lost_limit > 0.1 && balance < 1e-7 * scale,
                      "joint between two bodies: a penalty limit stops it",
                      "1 s: up to %.4f deg (limit 120, 50 N m/rad); W_limit %.4g J; max "
                      "|balance| %.3g J of %.3g J",
                      rj_deg(hi), e.lost_limit, balance, scale);
        if (k == 3)
            rjt_check(c, r == RJ_OK && e.lost_damping > 1e-3 && balance < 1e-7 * scale,
                      "joint between two bodies: an elastic cable loop ties it to another",
                      "1 s: W_damping %.4g J; max |balance| %.3g J of %.3g J",
                      e.lost_damping, balance, scale);
        if (k == 4) {
            /* the loop holds theta_b - 90 deg = -(theta_a - 90 deg) */
            const double e = rj_joint_theta_running(m, s, 1) + rj_joint_theta_running(m, s, 0) -
                             2 * rj_rad(90);
            rjt_check(c, r == RJ_OK && fabs(e) < 1e-9 && hi - lo > 1e-3 &&
                             balance < 1e-10 * scale,
                      "joint between two bodies: an exact cable loop holds it to another",
                      "1 s: the loop's stretch %.3g rad while joint b turned %.3g rad; max "
                      "|balance| %.3g J of %.3g J",
                      e, hi - lo, balance, scale);
        }
        if (r != RJ_OK)
            rjt_check(c, 0, "joint between two bodies", "%s: %s", names[k], rj_state_error(s));
        rj_state_destroy(s, NULL);
        rj_model_destroy(m, NULL);
    }
}

/* A rigid link on a fixed pin, a second one pinned to its tip and driven by a spring
   (5 N m/rad toward 200 deg) into joint b's limit at 150 deg, beside a flexible
   cantilever; tail: the limit's keys; dt 0: the automatic step. */
static void pinned_pair_text(double dt, const char *tail, char *text, size_t n)
{
    snprintf(text, n,
             "solver\n  dt = %.17g\n  gravity = 0 -9.81\n"
             "link base\n  length = 0.5  elements = 4  root = clamped  height = 0.02  "
             "width = 0.02\n"
             "link r1\n  length = 0.3  elements = 2  fidelity = rigid  height = 0.02  "
             "width = 0.02  root = pinned  x = 1  angle = -90 deg\n"
             "link r2\n  length = 0.3  elements = 1  fidelity = rigid  height = 0.02  "
             "width = 0.02\n"
             "joint b\n  body1 = r1  body2 = r2  angle0 = 90 deg  spring = 5 200 deg  "
             "forward = 150 deg  %s\n",
             dt, tail);
}

/* The pinned pair (pinned_pair_text) with the limit's keys tail, run 0.3 s at step dt
   (0: the automatic one): the joint's largest angle past the limit, its range once
   locked, the largest |balance| and the limit's loss. */
static rj_result pair_latch_run(const char *tail, double dt, double *past, double *range,
                                double *balance, double *lost)
{
    char text[1024];
    rj_model *m = NULL;
    rj_state *s = NULL;
    rj_error err;
    rj_energy e;
    rj_result r = RJ_OK;
    double lo = HUGE_VAL, hi = -HUGE_VAL;
    pinned_pair_text(dt, tail, text, sizeof text);
    *past = *range = *balance = *lost = 0;
    if (!build(text, &m, &s, &err))
        return RJ_ERR_INVALID;
    while (rj_state_time(s) < 0.3 && r == RJ_OK) {
        const double th = rj_joint_theta_running(m, s, 0);
        r = rj_step(m, s);
        rj_state_energy(m, s, &e);
        *balance = fmax(*balance, fabs(e.balance));
        *past = fmax(*past, th - rj_rad(150));
        if (rj_joint_flag(m, s, 0) == RJ_LOCKED) {
            lo = fmin(lo, rj_joint_theta_running(m, s, 0));
            hi = fmax(hi, rj_joint_theta_running(m, s, 0));
        }
    }
    *range = hi - lo;
    *lost = e.lost_limit;
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
    return r;
}

/* A bounce (momentum, restitution 0.5) between two rigid bodies: the rate the joint
   leaves its limit with is -0.5 times the rate it came with (the rates of the steps
   either side of the contact's, which gravity and the spring move by 0.2 % a step). */
static void test_body_pair_bounce(rjt_ctx *c)
{
    char text[1024];
    rj_model *m = NULL;
    rj_state *s = NULL;
    rj_error err;
    rj_energy e;
    rj_result r = RJ_OK;
    double before = 0, after = 0, balance = 0;
    int hit = 0;
    pinned_pair_text(0, "method = momentum  restitution = 0.5", text, sizeof text);
    if (!build(text, &m, &s, &err)) {
        rjt_check(c, 0, "joint between two bodies: a bounce", "%s", err.msg);
        return;
    }
    while (rj_state_time(s) < 0.1 && r == RJ_OK && hit < 2) {
        const double rate = rj_joint_rate(m, s, 0);
        r = rj_step(m, s);
        rj_state_energy(m, s, &e);
        balance = fmax(balance, fabs(e.balance));
        if (hit == 1)
            hit = 2;
        if (!hit && rj_joint_flag(m, s, 0) != RJ_FREE) {
            before = rate;
            hit = 1;
        }
        after = rj_joint_rate(m, s, 0);
    }
    rjt_check(c, r == RJ_OK && hit == 2 && fabs(after / before + 0.5) < 5e-3 &&
                     balance < 1e-3 * e.lost_limit,
              "joint between two bodies: a bounce leaves with -e times the rate it came with",
              "%.5g rad/s in, %.5g rad/s out (ratio %.5f); |balance| %.3g J of the %.4g J the "
              "limit took",
              before, after, after / before, balance, e.lost_limit);
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
}

/* Locks and plastic limits on a joint between two rigid bodies of a mixed scene act as
   torques that bring the pinned pair's rate to its target within the step. The latch's
   loss is booked to first order in dt (the pins' projection through the impact); a
   contact holds the limit. */
static void test_body_pair_latch(rjt_ctx *c)
{
    double past, range, bal1, bal2, lost, lost2;
    rj_result r1, r2;
    r1 = pair_latch_run("lock = yes  method = forced", 2e-5, &past, &range, &bal1, &lost);
    r2 = pair_latch_run("lock = yes  method = forced", 1e-5, &past, &range, &bal2, &lost2);
    rjt_check(c, r1 == RJ_OK && r2 == RJ_OK && range < 1e-6 && bal1 < 1e-3 * lost &&
                     bal2 / bal1 > 0.4 && bal2 / bal1 < 0.6,
              "joint between two bodies: a lock holds, its loss booked at first order in dt",
              "locked within %.3g rad; |balance| %.3g J at 20 us, %.3g J at 10 us, of the "
              "%.4g J the latch took",
              range, bal1, bal2, lost);
    r1 = pair_latch_run("method = momentum", 0, &past, &range, &bal1, &lost);
    rjt_check(c, r1 == RJ_OK && past < 2e-3 && lost > 1 && bal1 < 1e-3 * lost,
              "joint between two bodies: a plastic contact holds its limit",
              "at most %.3g rad past it; the contact took %.4g J, |balance| %.3g J", past,
              lost, bal1);
    test_body_pair_bounce(c);
    r1 = pair_latch_run("lock = yes  method = adaptive", 0, &past, &range, &bal1, &lost);
    rjt_check(c, r1 == RJ_OK && range < rj_rad(0.5) && bal1 < 1e-3 * lost,
              "joint between two bodies: an adaptive lock holds, as the stiff spring it is",
              "locked within %.3g deg; the lock took %.4g J, |balance| %.3g J", rj_deg(range),
              lost, bal1);
}

/* The four-bar with a flexible crank and a rigid coupler and rocker, its loop joint
   (between the two bodies) locking 0.05 rad from where it starts, the way it turns:
   the crank's tip rides on the coupler, which the lock stops at once. A lock there as a
   jump with a weld in the projection blew up within two steps; as a torque it holds. */
static void test_fourbar_pair_lock(rjt_ctx *c)
{
    char text[2048], out[2600];
    rj_model *m = NULL;
    rj_state *s = NULL;
    rj_error err;
    rj_energy e;
    rj_result r = RJ_OK;
    double th0, limit, lo = HUGE_VAL, hi = -HUGE_VAL, balance = 0, scale = 0;
    const char *at;
    int k, up;
    fourbar_text(7e10, "flexible rigid rigid", 0, text, sizeof text);
    if (!build(text, &m, &s, &err)) {
        rjt_check(c, 0, "four-bar: a lock between two rigid bodies", "%s", err.msg);
        return;
    }
    th0 = rj_joint_theta_running(m, s, 3);
    for (k = 0; k < 2000; k++)
        rj_step(m, s);
    up = rj_joint_theta_running(m, s, 3) > th0;
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
    limit = fmod(th0 + (up ? 0.05 : -0.05) + 4 * PI, 2 * PI);
    at = strstr(text, "node2 = last");
    snprintf(out, sizeof out, "%.*snode2 = last  %s = %.17g  lock = yes  method = forced%s",
             (int) (at - text), text, up ? "forward" : "reverse", limit,
             at + strlen("node2 = last"));
    if (!build(out, &m, &s, &err)) {
        rjt_check(c, 0, "four-bar: a lock between two rigid bodies", "%s", err.msg);
        return;
    }
    while (rj_state_time(s) < 2 && r == RJ_OK) {
        r = rj_step(m, s);
        rj_state_energy(m, s, &e);
        balance = fmax(balance, fabs(e.balance));
        scale = fmax(scale, e.kinetic + fabs(e.gravity));
        if (rj_joint_flag(m, s, 3) == RJ_LOCKED) {
            lo = fmin(lo, rj_joint_theta_running(m, s, 3));
            hi = fmax(hi, rj_joint_theta_running(m, s, 3));
        }
    }
    rjt_check(c, r == RJ_OK && hi - lo < 1e-9 && balance < 1e-5 * scale,
              "four-bar: a lock between a rigid coupler and rocker holds, a flexible crank on it",
              "%s %s; 2 s: locked within %.3g rad; max |balance| %.3g J of %.3g J; the latch "
              "took %.4g J",
              rj_result_str(r), r == RJ_OK ? "" : rj_state_error(s), hi - lo, balance, scale,
              e.lost_limit);
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
}

/* A prescribed profile (cycloidal, 60 deg in 0.5 s) on the joint between two rigid
   bodies hanging from a flexible cantilever: the joint follows the cycloid and the drive's
   work closes the balance. */
static void test_body_pair_prescribed(rjt_ctx *c)
{
    rj_model *m = NULL;
    rj_state *s = NULL;
    rj_error err;
    rj_energy e;
    rj_result r = RJ_OK;
    double worst = 0, balance = 0, scale = 0;
    if (!body_pair_scene("\nactuator drive\n  joint = b  type = prescribed  "
                         "profile = cycloidal 60 deg 0.5", &m, &s, &err)) {
        rjt_check(c, 0, "joint between two bodies: a prescribed profile", "%s", err.msg);
        return;
    }
    while (rj_state_time(s) < 1 && r == RJ_OK) {
        double t, u, want;
        r = rj_step(m, s);
        t = rj_state_time(s);
        u = fmin(t / 0.5, 1.0);
        want = rj_rad(90) + rj_rad(60) * (u - sin(2 * PI * u) / (2 * PI));
        worst = fmax(worst, fabs(rj_joint_theta_running(m, s, 1) - want));
        rj_state_energy(m, s, &e);
        balance = fmax(balance, fabs(e.balance));
        scale = fmax(scale, fabs(e.gravity) + e.kinetic + fabs(e.work_drive));
    }
    rjt_check(c, r == RJ_OK && worst < 1e-9 && balance < 1e-8 * scale,
              "joint between two bodies: a prescribed profile is followed, its work booked",
              "%s; 1 s: %.3g rad off the cycloid; W_drive %.4g J; max |balance| %.3g J of "
              "%.3g J",
              r == RJ_OK ? "ok" : rj_state_error(s), worst, e.work_drive, balance, scale);
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
}

static void test_refusals(rjt_ctx *c)
{
    static const char *const cases[][5] = {
        /* the links' fidelity, find, put, the message must hold, what */
        { "", "ground_x = 1 ", "ground_x = 1.01 ", "apart", "a loop that does not close" },
        { "", "node2 = last  angle0 = -2.13", "node2 = last  angle0 = -2.03",
          "joints[3].angle0", "a loop joint at the wrong angle0" },
        { "flexible rigid rigid", "node2 = last",
          "node2 = last  forward = 260 deg  method = energy", "method is not supported",
          "an energy-method limit on a loop joint between two rigid bodies of a mixed scene" },
        { "", "node2 = last", "node2 = last  reference = chord", "node2",
          "node2 on a chord joint" },
        { "", "node2 = last", "node2 = 9", "node2 = 9 is out of range",
          "node2 past the link's last" },
    };
    int k;
    for (k = 0; k < 5; k++) {
        rj_error err;
        const rj_result r = edited(cases[k][0], cases[k][1], cases[k][2], &err);
        rjt_check(c, r != RJ_OK && strstr(err.msg, cases[k][3]) != NULL,
                  "closed loops: bad input refused, the field named", "%s: %s", cases[k][4],
                  err.msg);
    }
}

/* rj_scene_assemble from angles a few degrees off: the crank (the loop's first joint)
   keeps 60 deg, the others land on close_loop's closed-form-free Newton solution to
   round-off, and the scene builds; a coupler too short to reach is refused, the gap
   named. */
static void test_assemble(rjt_ctx *c)
{
    char text[2048];
    rj_scene_file f;
    rj_scene_def d;
    rj_joint_def J[4];
    rj_error err;
    rj_model *m = NULL;
    rj_result r = RJ_ERR_PARSE, built = RJ_ERR_PARSE;
    double t3 = 0.5, t4 = 1.5, worst = 0, gap = 0;
    const double offs[4] = { 0, 0.05, -0.02, 0.07 };
    int k;
    close_loop(CRANK0, &t3, &t4);
    fourbar_text(7e10, "", 0, text, sizeof text);
    if (rj_scene_parse(text, strlen(text), "fourbar.rjs", &f, &err) == RJ_OK) {
        const double want[4] = { CRANK0, t3 - (CRANK0 + PI), t4, t4 - (t3 + PI) };
        d = rj_scene_file_def(&f);
        memcpy(J, d.joints, sizeof J);
        for (k = 0; k < 4; k++)
            J[k].angle0 += offs[k];
        r = rj_scene_assemble(&d, J, &err);
        for (k = 0; k < 4; k++)
            worst = fmax(worst, fabs(J[k].angle0 - want[k]));
        d.joints = J;
        built = rj_model_create(&d, &m, &err, NULL);
        if (built == RJ_OK)
            rj_model_destroy(m, NULL);
        /* a coupler of 0.05 m: the crank tip is 0.89 m from O4, beyond 0.05 + 0.8 */
        memcpy(J, rj_scene_file_def(&f).joints, sizeof J);
        ((rj_link_def *) d.links)[1].length = 0.05;
        d.joints = f.joints;
        if (rj_scene_assemble(&d, J, &err) == RJ_ERR_INVALID && strstr(err.msg, "joints[3]"))
            gap = err.value;
        rj_scene_file_free(&f);
    }
    rjt_check(c, r == RJ_OK && built == RJ_OK && worst < 1e-12,
              "assembly: a four-bar written 1 to 4 deg off closes to round-off",
              "max |angle0 - closed loop| %.3g rad (the crank held at 60 deg); model %s",
              worst, rj_result_str(built));
    {
        /* the least gap: the crank tip's distance from O4 less the two links' reach */
        const double reach = hypot(GROUND_D - BAR_A * cos(CRANK0), BAR_A * sin(CRANK0));
        const double least = reach - (0.05 + BAR_C);
        rjt_check(c, fabs(gap - least) < 1e-9 * least,
                  "assembly: a loop that cannot close is refused, its least gap named",
                  "%.9g m against %.9g m: %s", gap, least, err.msg);
    }
}

/* examples/scenes/scissor_boom.rjs, 1.5 s: the six crossings latched, the balance closed,
   and the deployed boom's span between its first and last crossings, averaged over its
   ringing after the latch (0.8 to 1.5 s), against the geometry of 120 deg crossings:
   5 units of 0.5 m cos 30 deg. */
/* The scissor boom of its file, its links of the fidelity given (RJ_LINK_RIGID: a mixed
   scene, the A links rigid bodies crossing flexible B links at their middle nodes). */
static void test_scissor(rjt_ctx *c, rj_fidelity fidelity)
{
    const char *name = fidelity == RJ_LINK_INEXTENSIBLE ? "inextensible"
                       : fidelity == RJ_LINK_RIGID  ? "rigid A and flexible B"
                                                    : "flexible";
    rj_scene_file f;
    rj_scene_def d;
    rj_error err;
    rj_model *m = NULL;
    rj_state *s = NULL;
    rj_energy e0, e;
    double balance = 0, sum = 0, want = 5 * 0.5 * cos(PI / 6), span;
    long count = 0;
    int j, locked = 0;
    rj_result r = rj_scene_load("examples/scenes/scissor_boom.rjs", &f, &err);
    if (r == RJ_OK) {
        d = rj_scene_file_def(&f);
        /* the file lists A0, B0, A1, B1, ...: the A links are the even ones */
        for (j = 0; j < d.link_count; j++)
            if (fidelity != RJ_LINK_RIGID || j % 2 == 0)
                ((rj_link_def *) d.links)[j].fidelity = fidelity;
        /* inextensible links have no axial bound: at the flexible links' step (2.2e-5 s,
           not 1.7e-4 s) the balance measures the same second-order error */
        if (fidelity == RJ_LINK_INEXTENSIBLE)
            ((rj_solver_def *) &d.solver)->dt = 2.2e-5;
        r = rj_model_create(&d, &m, &err, NULL);
        rj_scene_file_free(&f);
    }
    if (r != RJ_OK) {
        rjt_check(c, 0, "scissor boom: deploys and latches", "%s links: %s", name, err.msg);
        return;
    }
    rj_state_create(m, &s, NULL);
    rj_state_energy(m, s, &e0);
    while (rj_state_time(s) < 1.5 && r == RJ_OK) {
        double a[2], b[2];
        r = rj_step(m, s);
        rj_state_energy(m, s, &e);
        balance = fmax(balance, fabs(e.balance));
        if (rj_state_time(s) < 0.8)
            continue;
        rj_node_position(m, s, 0, 2, a);
        rj_node_position(m, s, 10, 2, b);
        sum += hypot(a[0] - b[0], a[1] - b[1]);
        count++;
    }
    for (j = 0; j < rj_model_joint_count(m); j++)
        locked += rj_joint_flag(m, s, j) == RJ_LOCKED;
    span = count ? sum / count : 0;
    rjt_check(c, r == RJ_OK && locked == 6 && balance < 1e-5 * e0.total &&
                     fabs(span - want) < 2e-3 * want,
              "scissor boom: five loops deploy and latch; the span the crossings give",
              "%s links: %d crossings locked; mean span %.6f m against %.6f m (%.2g relative; "
              "the links ring after the latch); max |balance| %.3g J of %.3g J",
              name, locked, span, want, (span - want) / want, balance, e0.total);
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
}

/* The four-bar of rigid bars at step dt, its loop joint b with extra keys (""): the text
   into out. */
static void rigid_text(double dt, const char *extra, char *out, size_t n)
{
    char text[2048], *w = out;
    const char *t = text;
    fourbar_text(7e10, "", 0, text, sizeof text);
    while (*t && w < out + n - 128) {
        if (!strncmp(t, "section = bar\n", 14)) {
            w += sprintf(w, "section = bar  fidelity = rigid\n");
            t += 14;
        } else if (!strncmp(t, "dt = 0\n", 7)) {
            w += sprintf(w, "dt = %.17g\n", dt);
            t += 7;
        } else if (!strncmp(t, "node2 = last", 12)) {
            w += sprintf(w, "node2 = last%s", extra);
            t += 12;
        } else
            *w++ = *t++;
    }
    *w = 0;
}

/* The rigid four-bar at step dt with the scene text tail appended (an actuator, a
   coupling), against the exact motion with a rotor's inertia on the loop joint and a
   cable loop from the crank to it (rigid4). */
static void run_rigid_with(double dt, const char *tail, double rotor, double k_cable,
                           fourbar_run *o)
{
    char out[2600];
    rigid_text(dt, "", out, sizeof out - strlen(tail));
    strcat(out, tail);
    run_against_exact(out, rotor, k_cable, RIGID_SECONDS, o);
}

/* The rigid four-bar with a plastic latch on the joint that closes its loop (forward
   limit 260 deg, lock, momentum with restitution 0: a row along the loop's gradient):
   it latches, and the whole mechanism stops (0 degrees of freedom left), its kinetic
   energy in the latch's loss. */
static void test_rigid_latch(rjt_ctx *c)
{
    char out[2600];
    rj_model *m = NULL;
    rj_state *s = NULL;
    rj_error err;
    double balance = 0, kinetic = 0, latched = -1;
    rj_result r = RJ_OK;
    rigid_text(1e-4, "  forward = 260 deg  lock = yes  method = momentum", out, sizeof out);
    if (!build(out, &m, &s, &err)) {
        rjt_check(c, 0, "rigid four-bar: a plastic latch on its loop joint", "%s", err.msg);
        return;
    }
    while (rj_state_time(s) < 2 && r == RJ_OK) {
        rj_energy e;
        r = rj_step(m, s);
        rj_state_energy(m, s, &e);
        balance = fmax(balance, fabs(e.balance));
        kinetic = fmax(kinetic, e.kinetic);
        if (latched < 0 && rj_joint_flag(m, s, 3) == RJ_LOCKED)
            latched = rj_state_time(s);
    }
    rjt_check(c, r == RJ_OK && latched > 0 && rj_joint_flag(m, s, 3) == RJ_LOCKED &&
                     fabs(rj_joint_rate(m, s, 0)) < 1e-9 && balance < 1e-5 * kinetic,
              "rigid four-bar: a plastic latch on its loop joint stops the mechanism",
              "latched at %.4f s at %.4f deg (limit 260 deg = -100 deg); crank rate at 2 s "
              "%.3g rad/s; max |balance| %.3g J of %.3g J kinetic %s",
              latched, rj_deg(rj_joint_theta_running(m, s, 3)), rj_joint_rate(m, s, 0), balance,
              kinetic, r == RJ_OK ? "" : rj_state_error(s));
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
}

/* The rigid four-bar for 1e6 steps of 0.1 ms (100 s, the crank turning over and over):
   the pins' gap and the balance, sampled every 100 steps. */
static void test_rigid_long(rjt_ctx *c)
{
    char out[2600];
    rj_model *m = NULL;
    rj_state *s = NULL;
    rj_error err;
    double balance = 0, kinetic = 0, gap = 0;
    rj_result r = RJ_OK;
    long k;
    rigid_text(1e-4, "", out, sizeof out);
    if (!build(out, &m, &s, &err)) {
        rjt_check(c, 0, "rigid four-bar: 1e6 steps", "%s", err.msg);
        return;
    }
    for (k = 0; k < LONG_RUN_STEPS && r == RJ_OK; k++) {
        double a[2], b[2];
        rj_energy e;
        r = rj_step(m, s);
        if (k % 100)
            continue;
        rj_state_energy(m, s, &e);
        balance = fmax(balance, fabs(e.balance));
        kinetic = fmax(kinetic, e.kinetic);
        rj_node_position(m, s, 1, rj_link_node_count(m, 1) - 1, a);
        rj_node_position(m, s, 2, rj_link_node_count(m, 2) - 1, b);
        gap = fmax(gap, hypot(a[0] - b[0], a[1] - b[1]));
    }
    rjt_check(c, r == RJ_OK && gap < 1e-12 && balance < 1e-5 * kinetic,
              "rigid four-bar: the loop closed and the balance kept over a long run",
              "%ld steps of 0.1 ms: pins at most %.3g m apart; max |balance| %.3g J of %.3g J "
              "kinetic %s",
              LONG_RUN_STEPS, gap, balance, kinetic, r == RJ_OK ? "" : rj_state_error(s));
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
}

/* The rigid four-bar with friction at its loop joint (1 N m): it swings down and loses
   its energy, the balance closed with friction's loss; with a DC motor there instead
   (0.5 N m stall, 10 rad/s): the balance closed with the motor's work. */
static void test_rigid_loop_joint_torques(rjt_ctx *c)
{
    static const char motor[] =
        "actuator m\n  joint = b  type = dc  stall_torque = 0.5  no_load_speed = 10\n";
    int k;
    for (k = 0; k < 2; k++) {
        char out[2600];
        rj_model *m = NULL;
        rj_state *s = NULL;
        rj_error err;
        rj_energy e;
        double balance = 0, scale = 0;
        rj_result r = RJ_OK;
        rigid_text(1e-4, k ? "" : "  friction = 1", out, sizeof out - sizeof motor);
        if (k)
            strcat(out, motor);
        if (!build(out, &m, &s, &err)) {
            rjt_check(c, 0, "rigid four-bar: friction or a motor at its loop joint", "%s",
                      err.msg);
            continue;
        }
        while (rj_state_time(s) < 10 && r == RJ_OK) {
            r = rj_step(m, s);
            rj_state_energy(m, s, &e);
            balance = fmax(balance, fabs(e.balance));
            scale = fmax(scale, fabs(k ? e.work_drive : e.lost_friction));
        }
        rjt_check(c, r == RJ_OK && scale > 0.1 && balance < 1e-5 * scale,
                  "rigid four-bar: friction or a motor at its loop joint, the balance closed",
                  "%s: %s %.4g J; max |balance| %.3g J %s", k ? "DC motor" : "friction 1 N m",
                  k ? "W_drive up to" : "W_friction", scale, balance,
                  r == RJ_OK ? "" : rj_state_error(s));
        rj_state_destroy(s, NULL);
        rj_model_destroy(m, NULL);
    }
}

/* The rigid four-bar driven at its crank (a prescribed ramp, -2 rad/s, 5 s: the crank
   turns 1.6 times): the rocker follows the loop's closed kinematics (close_loop at the
   crank's angle) to round-off, the balance closed with the drive's work. */
static void test_rigid_driven(rjt_ctx *c)
{
    static const char motor[] =
        "actuator m\n  joint = o2  type = prescribed  profile = ramp -2\n";
    char out[2600];
    rj_model *m = NULL;
    rj_state *s = NULL;
    rj_error err;
    double worst = 0, crank = 0, balance = 0, drive = 0, t3 = 0.5, t4 = 1.5;
    rj_result r = RJ_OK;
    rigid_text(1e-3, "", out, sizeof out - sizeof motor);
    strcat(out, motor);
    if (!build(out, &m, &s, &err)) {
        rjt_check(c, 0, "rigid four-bar driven at its crank", "%s", err.msg);
        return;
    }
    while (rj_state_time(s) < 5 && r == RJ_OK) {
        rj_energy e;
        double th2;
        r = rj_step(m, s);
        th2 = rj_joint_theta_running(m, s, 0);
        crank = fmax(crank, fabs(th2 - (CRANK0 - 2 * rj_state_time(s))));
        close_loop(th2, &t3, &t4);
        worst = fmax(worst, fabs(remainder(rj_joint_theta_running(m, s, 2) - t4, 2 * PI)));
        rj_state_energy(m, s, &e);
        balance = fmax(balance, fabs(e.balance));
        drive = fmax(drive, fabs(e.work_drive));
    }
    rjt_check(c, r == RJ_OK && crank < 1e-12 && worst < 1e-12 && balance < 1e-3 * drive,
              "rigid four-bar driven at its crank: the rocker on the loop's kinematics",
              "crank on its ramp to %.3g rad, rocker to %.3g rad of the closed loop over 5 s; "
              "max |balance| %.3g J of %.3g J of drive work %s",
              crank, worst, balance, drive, r == RJ_OK ? "" : rj_state_error(s));
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
}

/* Every node's position and velocity, bit for bit, as a number to compare. */
static unsigned long long state_bits(const rj_model *m, const rj_state *s)
{
    unsigned long long h = 1469598103934665603ULL;
    int l, k;
    size_t b;
    for (l = 0; l < rj_model_link_count(m); l++)
        for (k = 0; k < rj_link_node_count(m, l); k++) {
            double v[5];
            unsigned char bytes[sizeof v];
            rj_node_position(m, s, l, k, v);
            rj_node_velocity(m, s, l, k, v + 2);
            v[4] = rj_node_rotation(m, s, l, k);
            memcpy(bytes, v, sizeof v);
            for (b = 0; b < sizeof v; b++)
                h = (h ^ bytes[b]) * 1099511628211ULL;
        }
    return h;
}

/* A checkpoint taken at 0.3 s resumes bit for bit: loops of inextensible links (the
   sparse system's scratch is not state), pins between bodies, a rigid loop joint
   prescribed (its row's drive account travels). */
static void test_loop_checkpoints(rjt_ctx *c)
{
    static const char *const models[3][2] = {
        { "inextensible", "inextensible bars" },
        { "flexible rigid rigid", "rigid coupler and rocker" },
        { "rigid", "rigid bars, the loop joint prescribed" },
    };
    int v;
    for (v = 0; v < 3; v++) {
        char text[2600];
        rj_model *m = NULL;
        rj_state *s = NULL;
        rj_error err;
        unsigned long long straight, resumed = 0;
        void *buf = NULL;
        size_t size;
        int ok;
        if (v < 2)
            fourbar_text(7e10, models[v][0], 0, text, sizeof text);
        else {
            rigid_text(1e-3, "", text, sizeof text - 100);
            strcat(text, "actuator m\n  joint = b  type = prescribed  profile = ramp 0.2\n");
        }
        if (!build(text, &m, &s, &err)) {
            rjt_check(c, 0, "closed loops: a checkpoint resumes bit for bit", "%s: %s",
                      models[v][1], err.msg);
            continue;
        }
        rj_run(m, s, 0.3, 0.0, NULL, NULL);
        size = rj_state_save(m, s, NULL, 0);
        buf = malloc(size);
        ok = buf && rj_state_save(m, s, buf, size) == size;
        rj_run(m, s, 0.6, 0.0, NULL, NULL);
        straight = state_bits(m, s);
        if (ok && rj_state_load(m, s, buf, size, &err) == RJ_OK) {
            rj_run(m, s, 0.6, 0.0, NULL, NULL);
            resumed = state_bits(m, s);
        }
        rjt_check(c, ok && straight == resumed, "closed loops: a checkpoint resumes bit for bit",
                  "%s: %016llx straight, %016llx resumed at 0.3 s", models[v][1], straight,
                  resumed);
        free(buf);
        rj_state_destroy(s, NULL);
        rj_model_destroy(m, NULL);
    }
}

/* The four-bar of rigid bars (joint coordinates, the loop closed by rows on positions):
   the crank against the exact motion with the bars' exact mass properties (rods: m,
   m L / 2, m L^2 / 3 about node 0) over RIGID_SECONDS at dt, its largest error, the
   largest pin gap and |balance| into o. */
static void run_rigid(double dt, fourbar_run *o)
{
    run_rigid_with(dt, "", 0, 0, o);
}

/* A rotor on the loop joint (its inertia I on the loop's rate), and a cable loop from the
   crank to the loop joint: against the exact motion with I (k4 - k3)^2 in the generalised
   mass and the cable's k e^2 / 2 in the potential, each also against the motion without
   it (which the test could not tell apart were either ignored). */
static void test_rigid_loop_rotor_cable(rjt_ctx *c)
{
    static const char rotor[] =
        "actuator m\n  joint = b  type = torque  torque = 0  rotor_inertia = 0.05\n";
    static const char cable[] = "coupling k\n  joints = o2 b  ratio = 1  stiffness = 20\n";
    fourbar_run with, without, cabled, loose;
    run_rigid_with(5e-5, rotor, 0.05, 0, &with);
    run_rigid_with(5e-5, rotor, 0, 0, &without);
    run_rigid_with(5e-5, cable, 0, 20, &cabled);
    run_rigid_with(5e-5, cable, 0, 0, &loose);
    rjt_check(c, with.result == RJ_OK && with.crank < 1e-5 && without.crank > 1e-2 &&
                     with.balance < 1e-6 * with.energy,
              "rigid four-bar: a rotor on its loop joint",
              "0.05 kg m^2 on the loop's rate: max |crank - exact| %.3g rad over %g s at dt "
              "0.05 ms (%.3g rad from the motion without it); max |balance| %.3g J of %.3g J "
              "kinetic %s",
              with.crank, RIGID_SECONDS, without.crank, with.balance, with.energy, with.msg);
    rjt_check(c, cabled.result == RJ_OK && cabled.crank < 1e-5 && loose.crank > 1e-2 &&
                     cabled.balance < 1e-6 * cabled.energy,
              "rigid four-bar: a cable loop from its crank to its loop joint",
              "20 N m/rad: max |crank - exact| %.3g rad over %g s at dt 0.05 ms (%.3g rad from "
              "the motion without it); max |balance| %.3g J of %.3g J kinetic %s",
              cabled.crank, RIGID_SECONDS, loose.crank, cabled.balance, cabled.energy, cabled.msg);
}

/* The loop joint's limit by a bounce (momentum, e = 0.5) and by forced displacement:
   the loop's rate reversed at e, or the joint put back on its limit. */
static void run_rigid_limit(const char *keys, double *ratio, double *beyond, double *balance,
                            double *kinetic, char *msg, size_t n)
{
    char out[2600];
    rj_model *m = NULL;
    rj_state *s = NULL;
    rj_error err;
    const double limit = rj_rad(260) - 2 * PI;
    double rate_before = 0;
    rj_result r = RJ_OK;
    *ratio = *beyond = *balance = *kinetic = 0;
    msg[0] = 0;
    rigid_text(1e-5, keys, out, sizeof out);
    if (!build(out, &m, &s, &err)) {
        snprintf(msg, n, "%s", err.msg);
        *ratio = HUGE_VAL;
        return;
    }
    while (rj_state_time(s) < 1.5 && r == RJ_OK) {
        rj_energy e;
        const int free_before = rj_joint_flag(m, s, 3) == RJ_FREE;
        const double rate = rj_joint_rate(m, s, 3);
        r = rj_step(m, s);
        if (free_before && rj_joint_flag(m, s, 3) != RJ_FREE && *ratio == 0) {
            rate_before = rate;
            *ratio = rj_joint_rate(m, s, 3) / rate_before;
        }
        if (*ratio != 0)
            *beyond = fmax(*beyond, rj_joint_theta_running(m, s, 3) - limit);
        rj_state_energy(m, s, &e);
        *balance = fmax(*balance, fabs(e.balance));
        *kinetic = fmax(*kinetic, e.kinetic);
    }
    if (r != RJ_OK)
        snprintf(msg, n, "%s", rj_state_error(s));
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
}

static void test_rigid_loop_limits(rjt_ctx *c)
{
    double ratio, beyond, balance, kinetic;
    char msg[600];
    run_rigid_limit("  forward = 260 deg  method = momentum  restitution = 0.5", &ratio, &beyond,
                    &balance, &kinetic, msg, sizeof msg);
    rjt_check(c, fabs(ratio + 0.5) < 0.01 && beyond < 1e-3 && balance < 1e-5 * kinetic,
              "rigid four-bar: a bounce at its loop joint's limit",
              "the loop's rate after the contact step over the rate before: %.4f (e = 0.5; the "
              "step's kick between them); at most %.3g rad past the limit; max |balance| %.3g J "
              "of %.3g J kinetic %s",
              ratio, beyond, balance, kinetic, msg);
    run_rigid_limit("  forward = 260 deg  method = forced", &ratio, &beyond, &balance, &kinetic,
                    msg, sizeof msg);
    /* forced displacement moves the joint back without booking that work (the paper's
       method): the crank's own forced limit in a like place leaves 6.6e-5 J at any dt */
    rjt_check(c, fabs(ratio) < 0.01 && beyond < 1e-9 && balance < 1e-4 * kinetic,
              "rigid four-bar: forced displacement at its loop joint's limit",
              "the loop's rate after the contact step over the rate before: %.3g; at most "
              "%.3g rad past the limit after it; max |balance| %.3g J of %.3g J kinetic (the "
              "displacement's work is not booked) %s",
              ratio, beyond, balance, kinetic, msg);
}

/* The loop joint prescribed (a cycloidal turn of 20 deg over 1 s): the joint on its
   profile, the loop closed, the drive's work in the balance. */
static void test_rigid_loop_prescribed(rjt_ctx *c)
{
    static const char motor[] =
        "actuator m\n  joint = b  type = prescribed  profile = cycloidal 20 deg 1\n";
    char out[2600];
    rj_model *m = NULL;
    rj_state *s = NULL;
    rj_error err;
    double worst = 0, gap = 0, balance = 0, drive = 0, b0;
    rj_result r = RJ_OK;
    rigid_text(1e-3, "", out, sizeof out - sizeof motor);
    strcat(out, motor);
    if (!build(out, &m, &s, &err)) {
        rjt_check(c, 0, "rigid four-bar driven at its loop joint", "%s", err.msg);
        return;
    }
    b0 = rj_joint_theta_running(m, s, 3);
    while (rj_state_time(s) < 2 && r == RJ_OK) {
        rj_energy e;
        const double t = fmin(rj_state_time(s) + 0, 1.0);
        double want, xy1[2], xy2[2];
        r = rj_step(m, s);
        /* cycloidal: theta0 + A (t/T - sin(2 pi t/T) / (2 pi)) */
        want = b0 + rj_rad(20) * (fmin(rj_state_time(s), 1.0) -
                                  sin(2 * PI * fmin(rj_state_time(s), 1.0)) / (2 * PI));
        (void) t;
        worst = fmax(worst, fabs(rj_joint_theta_running(m, s, 3) - want));
        rj_node_position(m, s, 1, rj_link_node_count(m, 1) - 1, xy1);
        rj_node_position(m, s, 2, rj_link_node_count(m, 2) - 1, xy2);
        gap = fmax(gap, hypot(xy1[0] - xy2[0], xy1[1] - xy2[1]));
        rj_state_energy(m, s, &e);
        balance = fmax(balance, fabs(e.balance));
        drive = fmax(drive, fabs(e.work_drive));
    }
    rjt_check(c, r == RJ_OK && worst < 1e-10 && gap < 1e-12 && drive > 0.1 &&
                     balance < 1e-3 * drive,
              "rigid four-bar driven at its loop joint: on its profile, the loop closed",
              "the loop joint on its cycloidal profile to %.3g rad over 2 s; pins %.3g m apart; "
              "max |balance| %.3g J of %.3g J of drive work %s",
              worst, gap, balance, drive, r == RJ_OK ? "" : rj_state_error(s));
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
}

/* Pin forces in a loop of rigid bars: the loop joint's from its rows' impulses, the tree
   joints' from Newton's second law for the bars below them with the loop's force among
   the forces from outside. Those use the bars' forces alone, so each bar's moment balance
   about its centre, sum (pin - c) x F = I alpha (gravity has no moment there), checks them
   independently: every step of 0.2 s of the four-bar falling under gravity, at the step's
   configuration q^n and alpha = (omega^{n+1/2} - omega^{n-1/2}) / kick. */
static void test_rigid_pins(rjt_ctx *c)
{
    static const double len[3] = { BAR_A, BAR_B, BAR_C };
    /* fourbar_text's joints o2, a, o4, b: body 1 and body 2 (-1: the ground) */
    static const int body1[4] = { -1, 0, -1, 1 }, body2[4] = { 0, 1, 2, 2 };
    char text[4096];
    rj_model *m = NULL;
    rj_state *s = NULL;
    rj_error err;
    double worst = 0, scale = 0, F[8], loop_f = 0;
    int step, b, j, ok = 1, known_before = 0;
    fourbar_text(7e10, "rigid", 1e-4, text, sizeof text);
    if (!build(text, &m, &s, &err)) { rjt_check(c, 0, "rigid four-bar's pin forces: builds", "%s", err.msg); return; }
    known_before = rj_joint_pin_force(m, s, 3, F) == RJ_OK;
    for (step = 0; step < 2000 && ok; step++) {
        double cen[3][2], w0[3], pin[4][2], a[2], bnode[2];
        for (b = 0; b < 3; b++) {
            rj_node_position(m, s, b, 0, a);
            rj_node_position(m, s, b, rj_link_node_count(m, b) - 1, bnode);
            cen[b][0] = 0.5 * (a[0] + bnode[0]);
            cen[b][1] = 0.5 * (a[1] + bnode[1]);
            w0[b] = rj_node_rate(m, s, b, 0);
        }
        for (j = 0; j < 4; j++)
            rj_joint_position(m, s, j, pin[j]);
        ok = rj_step(m, s) == RJ_OK && rj_joint_pin_forces(m, s, F) == RJ_OK;
        for (b = 0; b < 3 && ok; b++) {
            const double mass = 2700 * 0.02 * 0.02 * len[b], I = mass * len[b] * len[b] / 12;
            double moment = 0;
            for (j = 0; j < 4; j++) {
                const double sgn = body2[j] == b ? 1.0 : (body1[j] == b ? -1.0 : 0.0);
                moment += sgn * ((pin[j][0] - cen[b][0]) * F[2 * j + 1] - (pin[j][1] - cen[b][1]) * F[2 * j]);
                scale = fmax(scale, fabs(F[2 * j]) * len[b]);
                scale = fmax(scale, fabs(F[2 * j + 1]) * len[b]);
            }
            /* the first step's kick is dt / 2 (from rest, rates at 0 to dt / 2) */
            const double kick = step == 0 ? 0.5 * rj_model_dt(m) : rj_model_dt(m);
            worst = fmax(worst, fabs(moment - I * (rj_node_rate(m, s, b, 0) - w0[b]) / kick));
        }
        loop_f = fmax(loop_f, hypot(F[6], F[7]));
    }
    rjt_check(c, ok && step == 2000 && worst < 1e-9 * scale && loop_f > 0 && !known_before,
              "rigid four-bar: pin forces from the loop's rows keep every bar's moment balance",
              "max |sum (pin - c) x F - I alpha| %.3g N m of %.3g (|F| L) over %d steps; the loop "
              "joint's force up to %.4g N; before the first step: %s",
              worst, scale, step, loop_f, known_before ? "answered (wrong)" : "unknown (right)");
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
}

/* The triangle of the statics below: bars from ground pivots A = (0, 0) and B = (0.8, 0) m
   meeting at C = (0.3, 0.4) m (bar 1 from A, bar 2 from B), 50 x 50 mm aluminium. */
#define TRI_CX 0.3
#define TRI_CY 0.4
#define TRI_D 0.8
#define TRI_H 0.05

/* The triangle's pin forces at rest under gravity by hand (frictionless pins, each bar's
   weight W at its middle): bar 2's moments about B and bar 1's about A give the force F
   bar 1 exerts on bar 2 at C, u x F = W2 u_x / 2 and v x F = -W1 v_x / 2 with u = C - B,
   v = C - A; the ground's on bar 1 at A is then F + W1 y, on bar 2 at B -F + W2 y. Into
   ground (A's, then B's) and apex (F). */
static void triangle_statics(double ground[4], double apex[2])
{
    const double ux = TRI_CX - TRI_D, uy = TRI_CY, vx = TRI_CX, vy = TRI_CY;
    const double weight = 2700 * TRI_H * TRI_H * G;
    const double W1 = weight * hypot(vx, vy), W2 = weight * hypot(ux, uy);
    const double r1 = W2 * ux / 2, r2 = -W1 * vx / 2, det = ux * vy - uy * vx;
    /* [-u_y u_x; -v_y v_x] F = [r1; r2] */
    apex[0] = (vx * r1 - ux * r2) / det;
    apex[1] = (vy * r1 - uy * r2) / det;
    ground[0] = apex[0];
    ground[1] = apex[1] + W1;
    ground[2] = -apex[0];
    ground[3] = -apex[1] + W2;
}

/* The triangle's scene, its bars of the fidelity given ("rigid": a mixed scene, with a
   flexible pendulum hanging at rest elsewhere): its loop closed at the apex C (at_b 0:
   joints o1, o2 and c, bar 1 to bar 2) or at B (at_b 1: o1, then c hanging bar 2 from
   bar 1's tip, then o2 pinning bar 2's last node to the ground, the loop). */
static void triangle_text(const char *fidelity, int at_b, char *text, size_t n)
{
    const double a1 = atan2(TRI_CY, TRI_CX), a2 = atan2(TRI_CY, TRI_CX - TRI_D);
    const int mixed = strcmp(fidelity, "rigid") == 0;
    char joints[512];
    if (!at_b)
        snprintf(joints, sizeof joints,
                 "joint o1\n  body1 = ground  body2 = bar1  angle0 = %.17g\n"
                 "joint o2\n  body1 = ground  body2 = bar2  ground_x = %.17g  angle0 = %.17g\n"
                 "joint c\n  body1 = bar1  body2 = bar2  node2 = last  angle0 = %.17g\n",
                 a1, TRI_D, a2, a2 - (a1 + PI));
    else
        snprintf(joints, sizeof joints,
                 "joint o1\n  body1 = ground  body2 = bar1  angle0 = %.17g\n"
                 "joint c\n  body1 = bar1  body2 = bar2  angle0 = %.17g\n"
                 "joint o2\n  body1 = ground  body2 = bar2  node2 = last  ground_x = %.17g  "
                 "angle0 = %.17g\n",
                 a1, a2 - PI - (a1 + PI), TRI_D, a2 - PI);
    snprintf(text, n,
             "solver\n  gravity = 0 -9.81\n"
             "material al\n  E = 7e10  rho = 2700\n"
             "section bar\n  width = %g  height = %g\n"
             "link bar1\n  length = %.17g  elements = 6  material = al  section = bar\n"
             "  fidelity = %s\n"
             "link bar2\n  length = %.17g  elements = 8  material = al  section = bar\n"
             "  fidelity = %s\n%s%s%s",
             TRI_H, TRI_H, hypot(TRI_CX, TRI_CY), fidelity, hypot(TRI_CX - TRI_D, TRI_CY),
             fidelity, mixed ? "link pendulum\n  length = 0.5  elements = 4  material = al  "
                               "section = bar\n" : "",
             joints,
             mixed ? "joint p\n  body1 = ground  body2 = pendulum  ground_x = 2  "
                     "angle0 = -90 deg\n" : "");
}

/* The triangle settled at rest (rj_settle to 1e-12), then one step: the largest
   |pin force - statics| / |statics| over its three joints into *worst; 0 (msg) when it
   fails. */
static int triangle_run(const char *fidelity, int at_b, double *worst, char *msg, size_t n)
{
    char text[2048];
    rj_model *m = NULL;
    rj_state *s = NULL;
    rj_error err;
    double ground[4], apex[2], want[6], F[8];
    int j, ok;
    triangle_text(fidelity, at_b, text, sizeof text);
    triangle_statics(ground, apex);
    /* joint order: o1, o2, c (at_b 0) or o1, c, o2 (at_b 1) */
    memcpy(want, ground, 2 * sizeof(double));
    memcpy(want + (at_b ? 4 : 2), ground + 2, 2 * sizeof(double));
    memcpy(want + (at_b ? 2 : 4), apex, 2 * sizeof(double));
    if (!build(text, &m, &s, &err)) {
        snprintf(msg, n, "%s", err.msg);
        return 0;
    }
    ok = rj_settle(m, s, 1e-12, 1000000) == RJ_OK && rj_step(m, s) == RJ_OK &&
         rj_joint_pin_forces(m, s, F) == RJ_OK;
    snprintf(msg, n, "%s", ok ? "" : rj_state_error(s));
    *worst = 0;
    for (j = 0; j < 3; j++)
        *worst = fmax(*worst, hypot(F[2 * j] - want[2 * j], F[2 * j + 1] - want[2 * j + 1]) /
                                  hypot(want[2 * j], want[2 * j + 1]));
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
    return ok && *worst == *worst;
}

/* Pin forces where a loop closes in node space, at rest against statics by hand
   (triangle_statics): a triangle of two bars pinned to the ground and to each other,
   under gravity. Its loop joint's force comes from the step's record of what closed it:
   inextensible bars meeting at the apex (SHAKE over the chains that meet), inextensible
   bars closed at a ground pivot (one chain held at both ends), rigid bodies of a mixed
   scene pinned at the apex (the pins between bodies), or bar 2 a rigid body pinned to
   the ground by the loop (its own balance less its pin to bar 1's pushes); the tree
   joints' from the bars below them with the loop's force among the forces from outside.
   The inextensible bars sag under their weight (about 1e-6 of their length), which
   moves the weights' lines a little; the rigid bodies' forces are exact but for the
   positions' round-off over dt^2. */
static void test_loop_statics(rjt_ctx *c)
{
    static const char *const fidelity[4] = { "inextensible", "inextensible", "rigid", "rigid" };
    static const int at_b[4] = { 0, 1, 0, 1 };
    static const double bound[4] = { 2e-5, 2e-5, 1e-6, 1e-6 };
    static const char *const what[4] = { "inextensible bars closed at the apex",
                                         "inextensible bars closed at a ground pivot",
                                         "rigid bodies of a mixed scene closed at the apex",
                                         "rigid bodies of a mixed scene closed at a ground "
                                         "pivot" };
    int k;
    for (k = 0; k < 4; k++) {
        char msg[700];
        double worst = 0;
        const int ran = triangle_run(fidelity[k], at_b[k], &worst, msg, sizeof msg);
        rjt_check(c, ran && worst < bound[k],
                  "pin forces of a loop in node space: a triangle at rest against statics",
                  "%s: the three joints within %.3g of the statics by hand (bound %g "
                  "relative) %s",
                  what[k], worst, bound[k], msg);
    }
}

/* The four-bar's text (fourbar_text at 7e10 Pa, the fidelities as there) and its loop's
   angles theta3, theta4 (close_loop); returns where the joint named by `from` starts,
   for the caller to write the joints from there another way. */
static char *fourbar_from(const char *fidelity, const char *from, char *text, size_t n,
                          double *t3, double *t4)
{
    *t3 = 0.5;
    *t4 = 1.5;
    fourbar_text(7e10, fidelity, 0, text, n);
    close_loop(CRANK0, t3, t4);
    return strstr(text, from);
}

/* The four-bar's text (fourbar_text at 7e10 Pa, the fidelities as there) with its loop
   joint b the other way round: body 1 the rocker at its last node, body 2 the coupler
   at its last. */
static void fourbar_reversed(const char *fidelity, char *text, size_t n)
{
    double t3, t4;
    char *at = fourbar_from(fidelity, "joint b\n", text, n, &t3, &t4);
    snprintf(at, n - (size_t) (at - text),
             "joint b\n  body1 = rocker  node1 = last  body2 = coupler  node2 = last  "
             "angle0 = %.17g\n",
             t3 - (t4 + PI));
}

/* Every node's velocity into v (2 a node, in node index order; 64 nodes at most). */
static void node_velocities(const rj_model *m, const rj_state *s, double *v)
{
    int l, k;
    for (l = 0; l < rj_model_link_count(m); l++)
        for (k = 0; k < rj_link_node_count(m, l); k++)
            rj_node_velocity(m, s, l, k, v + 2 * rj_model_node_index(m, l, k));
}

/* The scene's m a - m g at t^n (gravity -G in y) from every node's velocity before the
   step (before) and after it: a flexible or inextensible link's nodes' own; a rigid
   link's body's (its nodes are massless), rho A L at its middle, its acceleration the
   mean of its ends'. Into total. */
static void scene_momentum(const rj_model *m, const rj_state *s, const double *before,
                           double total[2])
{
    const double kick = rj_state_steps(s) == 1 ? 0.5 * rj_model_dt(m) : rj_model_dt(m);
    double after[128];
    int l, k, axis;
    node_velocities(m, s, after);
    total[0] = total[1] = 0;
    for (l = 0; l < rj_model_link_count(m); l++) {
        const rj_link_def *d = rj_model_link_def(m, l);
        const int a = rj_model_node_index(m, l, 0), b = rj_model_node_index(m, l, -1);
        for (axis = 0; axis < 2 && d->fidelity == RJ_LINK_RIGID; axis++)
            total[axis] += d->rho * d->width * d->height * d->length *
                           (0.5 * (after[2 * a + axis] + after[2 * b + axis] -
                                   before[2 * a + axis] - before[2 * b + axis]) / kick +
                            (axis ? G : 0.0));
        for (k = a; k <= b && d->fidelity != RJ_LINK_RIGID; k++) {
            double mass;
            rj_node_mass(m, l, k - a, &mass, NULL);
            for (axis = 0; axis < 2; axis++)
                total[axis] += mass * ((after[2 * k + axis] - before[2 * k + axis]) / kick +
                                       (axis ? G : 0.0));
        }
    }
}

/* The four-bar's text (fourbar_text at 7e10 Pa, the fidelities as there) with its loop
   closed at the rocker's ground pivot instead: joint b (coupler to rocker) hangs the
   rocker at its last node, and joint o4, last, pins the rocker's root to the ground. */
static void fourbar_ground_loop(const char *fidelity, char *text, size_t n)
{
    double t3, t4;
    char *at = fourbar_from(fidelity, "joint o4\n", text, n, &t3, &t4);
    snprintf(at, n - (size_t) (at - text),
             "joint b\n  body1 = coupler  body2 = rocker  node2 = last  angle0 = %.17g\n"
             "joint o4\n  body1 = ground  body2 = rocker  ground_x = %.17g  angle0 = %.17g\n",
             t4 - (t3 + PI), GROUND_D, t4);
}

/* Which pin forces a pair of four-bars compares (loop_sides_run): joint[0] of the first
   scene against joint[1] of the second, their sum (sign 1: the same pin seen from its
   two bodies) or difference (sign -1: the same pin's force by two routes); and the ground's
   pins (ground[0], ground[1]) of scene `scene` against its m a - m g. */
typedef struct sides_map {
    int joint[2];
    double sign;
    int scene;
    int ground[2];
} sides_map;

/* The loop joint b both ways round (fourbar_reversed): the ground's pins o2 and o4 of
   the first. */
static const sides_map REVERSED_B = { { 3, 3 }, 1.0, 0, { 0, 2 } };
/* The rocker's ground pin o4 as a tree joint and as the loop (fourbar_ground_loop): the
   ground's pins o2 and o4 of the second. */
static const sides_map GROUND_O4 = { { 2, 3 }, -1.0, 1, { 0, 3 } };

/* What a moving four-bar's pin forces showed over 0.2 s: one pin's force against the same
   pin's in the same four-bar written another way (sides_map), and the ground's pins
   against the scene's m a - m g. */
typedef struct loop_sides {
    double sides;  /* the largest |F + sign F'| */
    double ground; /* the largest |F_o2 + F_o4 - sum (m a - m g)| */
    double size;   /* the largest |F| */
    double total;  /* the largest |sum (m a - m g)| */
    double bound;  /* the round-off bound: 20 eps M (1 m) / dt^2, M the scene's mass */
    char msg[700];
} loop_sides;

/* One step of both four-bars; the differences into o. Returns 0 when one fails. */
static int loop_sides_step(rj_model *m[2], rj_state *s[2], const sides_map *map, loop_sides *o)
{
    double before[128], F[2][8], total[2];
    const double *a = F[0] + 2 * map->joint[0], *b = F[1] + 2 * map->joint[1];
    const double *g0 = F[map->scene] + 2 * map->ground[0];
    const double *g1 = F[map->scene] + 2 * map->ground[1];
    int k, known = 1;
    node_velocities(m[map->scene], s[map->scene], before);
    if (rj_step(m[0], s[0]) != RJ_OK || rj_step(m[1], s[1]) != RJ_OK)
        return 0;
    if (rj_joint_pin_forces(m[0], s[0], F[0]) != RJ_OK ||
        rj_joint_pin_forces(m[1], s[1], F[1]) != RJ_OK)
        return 0;
    scene_momentum(m[map->scene], s[map->scene], before, total);
    o->sides = fmax(o->sides, hypot(a[0] + map->sign * b[0], a[1] + map->sign * b[1]));
    o->ground = fmax(o->ground, hypot(g0[0] + g1[0] - total[0], g0[1] + g1[1] - total[1]));
    o->size = fmax(o->size, hypot(a[0], a[1]));
    o->total = fmax(o->total, hypot(total[0], total[1]));
    /* every joint of both has its force (the loop's ties none of them), the second's
       joint by joint as all at once */
    for (k = 0; k < 16; k++)
        known = known && F[k / 8][k % 8] == F[k / 8][k % 8];
    for (k = 0; k < 4 && known; k++) {
        double one[2];
        known = rj_joint_pin_force(m[1], s[1], k, one) == RJ_OK &&
                hypot(one[0] - F[1][2 * k], one[1] - F[1][2 * k + 1]) <= 1e-9 * o->bound;
    }
    return known && o->sides == o->sides && o->ground == o->ground;
}

/* The four-bar of the fidelities given, as fourbar_text writes it and as other writes
   it, over 0.2 s into o. */
static int loop_sides_run(const char *fidelity, void (*other)(const char *, char *, size_t),
                          const sides_map *map, loop_sides *o)
{
    char text[2][2048];
    rj_model *m[2] = { NULL, NULL };
    rj_state *s[2] = { NULL, NULL };
    rj_error err;
    int k, ok = 1;
    memset(o, 0, sizeof *o);
    fourbar_text(7e10, fidelity, 0, text[0], sizeof text[0]);
    other(fidelity, text[1], sizeof text[1]);
    for (k = 0; k < 2 && ok; k++)
        ok = build(text[k], &m[k], &s[k], &err);
    if (ok) {
        const double dt = rj_model_dt(m[0]), mass = 2700 * 0.02 * 0.02 * (BAR_A + BAR_B + BAR_C);
        o->bound = 20 * DBL_EPSILON * mass / (dt * dt);
        while (ok && rj_state_time(s[0]) < 0.2)
            ok = loop_sides_step(m, s, map, o);
        snprintf(o->msg, sizeof o->msg, "%s", ok ? "" : rj_state_error(s[0]));
    } else
        snprintf(o->msg, sizeof o->msg, "%s", err.msg);
    for (k = 0; k < 2; k++) {
        rj_state_destroy(s[k], NULL);
        rj_model_destroy(m[k], NULL);
    }
    return ok;
}

/* A check of three four-bars, each against the same written another way
   (loop_sides_run): the pin it follows, and the route it compares with. */
typedef struct sides_check {
    void (*other)(const char *, char *, size_t);
    const sides_map *map;
    const char *name;
    const char *pin;
    const char *route;
} sides_check;

/* The check for each fidelity (what: in words): the pins within the round-off bound, the
   ground's carrying the scene. */
static void check_loop_sides(rjt_ctx *c, const sides_check *check,
                             const char *const fidelity[3], const char *const what[3])
{
    int k;
    for (k = 0; k < 3; k++) {
        loop_sides o;
        const int ran = loop_sides_run(fidelity[k], check->other, check->map, &o);
        rjt_check(c, ran && o.sides < o.bound && o.ground < o.bound && o.size > 1,
                  check->name,
                  "%s: %s (up to %.4g N) %.3g N %s; the ground's pins %.3g N from the "
                  "scene's m a - m g (up to %.4g N); bound %.3g N (round-off) %s",
                  what[k], check->pin, o.size, o.sides, check->route, o.ground, o.total,
                  o.bound, o.msg);
    }
}

/* A moving four-bar's loop joint b from both of its sides: defined coupler to rocker, its
   force is read at the rocker's pin node; the other way round, at the coupler's, from
   other elements (the two give the same pin's force on opposite bodies). Inextensible
   bars: each side's constraint forces from its own link's SHAKE pushes; a flexible
   coupler and an inextensible rocker: the rocker's from them, the coupler's from its
   elements alone (no record). A flexible crank and a rigid coupler and rocker: the loop's
   force from the pin between the bodies, the rocker's ground pin from the rocker less
   it, the crank's from the crank's root node alone: their sum is the scene's m a - m g
   only with the loop's force right. The forces come from velocities that are position
   differences over dt: round-off of the positions over dt^2, on the scene's mass, bounds
   their agreement. */
static void test_loop_sides(rjt_ctx *c)
{
    static const char *const fidelity[3] = { "inextensible", "inextensible flexible inextensible",
                                             "flexible rigid" };
    static const char *const what[3] = { "inextensible bars",
                                         "a flexible coupler, inextensible crank and rocker",
                                         "a flexible crank, rigid coupler and rocker" };
    static const sides_check check = {
        fourbar_reversed, &REVERSED_B,
        "pin forces of a moving four-bar's loop in node space: from both sides, the ground's "
        "carrying the scene",
        "loop joint b", "from b the other way round"
    };
    check_loop_sides(c, &check, fidelity, what);
}

/* A moving four-bar whose loop pins a rigid rocker to the ground (fourbar_ground_loop):
   that pin's force from the rocker's own balance, less the forces of its pin to the
   coupler (the coupler's flexible node's balance, the pushes of a pin between two bodies,
   or an inextensible coupler's SHAKE pushes on its node the rocker carries), against the
   same pin's as a tree joint in the four-bar closed at b (the links below it less the
   loop's force); the ground's pins against the scene's m a - m g, where the crank's
   own (a flexible crank's root node) does not use the loop's force. Bound as above. */
static void test_loop_ground(rjt_ctx *c)
{
    static const char *const fidelity[3] = { "flexible flexible rigid", "flexible rigid rigid",
                                             "inextensible inextensible rigid" };
    static const char *const what[3] = { "a flexible crank and coupler, rigid rocker",
                                         "a flexible crank, rigid coupler and rocker",
                                         "an inextensible crank and coupler, rigid rocker" };
    static const sides_check check = {
        fourbar_ground_loop, &GROUND_O4,
        "pin forces of a loop pinning a rigid body to the ground: by two routes, the "
        "ground's carrying the scene",
        "the rocker's ground pin", "from the four-bar closed at b"
    };
    check_loop_sides(c, &check, fidelity, what);
}

/* A chain for the in-place pin forces: flexible links from a ground pin with a spring and
   damper (g), a pin between two of them with friction (p), one with a chord reference
   and a spring (c), a load on p's pin node; and a rigid arm pinned to the ground (r)
   carrying a flexible tail (t), a load at its tip. in_place: "on" or "off". */
static void chain_text(const char *in_place, char *text, size_t n)
{
    snprintf(text, n,
             "solver\n  gravity = 0 -9.81  in_place = %s\n"
             "material al\n  E = 7e10  rho = 2700\n"
             "section bar\n  width = 0.02  height = 0.02\n"
             "link l1\n  length = 0.6  elements = 12  material = al  section = bar\n"
             "link l2\n  length = 0.5  elements = 10  material = al  section = bar\n"
             "link l3\n  length = 0.4  elements = 8  material = al  section = bar\n"
             "link arm\n  length = 0.3  elements = 1  material = al  section = bar\n"
             "  fidelity = rigid\n"
             "link tail\n  length = 0.4  elements = 8  material = al  section = bar\n"
             "joint g\n  body1 = ground  body2 = l1  angle0 = -30 deg  spring = 5 -90 deg"
             "  damping = 0.01\n"
             "joint p\n  body1 = l1  body2 = l2  angle0 = 40 deg  friction = 0.05\n"
             "joint c\n  body1 = l2  body2 = l3  angle0 = 30 deg  reference = chord"
             "  spring = 2 30 deg\n"
             "joint r\n  body1 = ground  body2 = arm  ground_x = 1.5  angle0 = 0 deg\n"
             "joint t\n  body1 = arm  body2 = tail  angle0 = -60 deg\n"
             "load f\n  link = l2  node = 0  force = 3 0\n"
             "load h\n  link = arm  node = last  force = 0 -2\n",
             in_place);
}

/* The four-bar closed at its rigid rocker's ground pivot (fourbar_ground_loop) of a
   flexible crank and coupler, in place or not. */
static void ground_loop_text(const char *in_place, char *text, size_t n)
{
    char plain[2048];
    fourbar_ground_loop("flexible flexible rigid", plain, sizeof plain);
    snprintf(text, n, "solver\n  in_place = %s\n%s", in_place, plain + strlen("solver\n"));
}

/* What a scene showed stepped in place against double-buffered. */
typedef struct in_place_run {
    double worst;   /* the largest |F in place - F double-buffered| over the joints and steps */
    double size;    /* the largest |F| */
    double one;     /* the largest |rj_joint_pin_force - rj_joint_pin_forces| in place */
    double peak;    /* the largest |peak in place - peak double-buffered| over the joints */
    int known;      /* joints with a force in both at every step */
    int differ;     /* joint-steps with a force in one and not the other */
    int in_place;   /* the first steps in place, the second not */
    int same_bits;  /* the two states are the same bits after the run */
    int copied;     /* a copy of the in-place state has its pin forces, to the bit */
    int moments;    /* the in-place state tracked no link's moment (none known), the other did */
    char msg[700];
} in_place_run;

/* One step of both; the pin forces compared into o (F: 2 nj doubles each, one the
   joint-by-joint scratch). Returns 0 when a step fails. */
static int in_place_step(rj_model *m[2], rj_state *s[2], double *F[3], int *known,
                         in_place_run *o)
{
    const int nj = rj_model_joint_count(m[0]);
    int j, k;
    for (k = 0; k < 2; k++)
        if (rj_step(m[k], s[k]) != RJ_OK || rj_joint_pin_forces(m[k], s[k], F[k]) != RJ_OK)
            return 0;
    for (j = 0; j < nj; j++) {
        const double *a = F[0] + 2 * j, *b = F[1] + 2 * j;
        const int has = a[0] == a[0] && b[0] == b[0];
        o->differ += (a[0] == a[0]) != (b[0] == b[0]);
        known[j] = known[j] && has;
        if (!has)
            continue;
        o->worst = fmax(o->worst, hypot(a[0] - b[0], a[1] - b[1]));
        o->size = fmax(o->size, hypot(b[0], b[1]));
        if (rj_joint_pin_force(m[0], s[0], j, F[2]) == RJ_OK)
            o->one = fmax(o->one, hypot(F[2][0] - a[0], F[2][1] - a[1]));
        else
            o->one = HUGE_VAL;
    }
    return 1;
}

/* After the run: the peaks, the state's bits, a copy of the in-place state. */
static void in_place_after(rj_model *m[2], rj_state *s[2], double *F[3], in_place_run *o)
{
    const int nj = rj_model_joint_count(m[0]);
    rj_state *copy = NULL;
    int j, l;
    for (j = 0; j < nj; j++) {
        const rj_peak a = rj_joint_peak_pin_force(m[0], s[0], j);
        const rj_peak b = rj_joint_peak_pin_force(m[1], s[1], j);
        o->peak = fmax(o->peak, a.time == b.time ? fabs(a.value - b.value) : HUGE_VAL);
    }
    o->moments = 0;
    for (l = 0; l < rj_model_link_count(m[0]); l++)
        o->moments += rj_link_peak_moment(m[0], s[0], l).value == -1 &&
                      rj_link_peak_moment(m[1], s[1], l).value > 0;
    o->same_bits = state_bits(m[0], s[0]) == state_bits(m[1], s[1]);
    o->copied = rj_state_create(m[0], &copy, NULL) == RJ_OK &&
                rj_state_copy(m[0], copy, s[0]) == RJ_OK &&
                rj_joint_pin_forces(m[0], s[0], F[0]) == RJ_OK &&
                rj_joint_pin_forces(m[0], copy, F[2]) == RJ_OK &&
                memcmp(F[0], F[2], 2 * sizeof(double) * (size_t) nj) == 0;
    rj_state_destroy(copy, NULL);
}

/* A scene (text(in_place, ...)) stepped in place and double-buffered for `steps` steps,
   peaks tracked on both, into o. Returns 0 when one fails. */
static int in_place_compare(void (*text)(const char *, char *, size_t), int steps,
                            in_place_run *o)
{
    static const char *const mode[2] = { "on", "off" };
    char scene[2][2600];
    rj_model *m[2] = { NULL, NULL };
    rj_state *s[2] = { NULL, NULL };
    double F[3][32];
    double *pF[3] = { F[0], F[1], F[2] };
    int known[16], k, ok = 1, j;
    rj_error err;
    memset(o, 0, sizeof *o);
    for (j = 0; j < 16; j++)
        known[j] = 1;
    for (k = 0; k < 2 && ok; k++) {
        text(mode[k], scene[k], sizeof scene[k]);
        ok = build(scene[k], &m[k], &s[k], &err) &&
             rj_state_track_peaks(m[k], s[k], 1) == RJ_OK;
    }
    snprintf(o->msg, sizeof o->msg, "%s", ok ? "" : err.msg);
    if (ok) {
        o->in_place = rj_model_in_place(m[0]) && !rj_model_in_place(m[1]);
        for (k = 0; k < steps && ok; k++)
            ok = in_place_step(m, s, pF, known, o);
        for (j = 0; j < rj_model_joint_count(m[0]); j++)
            o->known += known[j];
        if (ok)
            in_place_after(m, s, pF, o);
        else
            snprintf(o->msg, sizeof o->msg, "%s", rj_state_error(s[0]));
    }
    for (k = 0; k < 2; k++) {
        rj_state_destroy(s[k], NULL);
        rj_model_destroy(m[k], NULL);
    }
    return ok;
}

/* Pin forces with in-place stepping: the step keeps the values at n of every joint's and
   link's end nodes and their forces, from which a pin node's balance follows, and a
   rigid body's pinned to the ground; the same scene stepped double-buffered (the same
   bits) gives them from its frame a step before. A chain (ground pin with a spring and
   damper, a pin between flexible links with friction, a chord reference, a rigid arm
   pinned to the ground carrying a flexible link, loads at pins) and the four-bar closed at
   its rigid rocker's ground pivot, 400 steps: every force agrees to round-off (the chord
   reference's too: in place from the step's node forces, double-buffered from its
   recorded torque on the chords at n, two independent routes), each joint's own query
   gives the all-at-once force,
   the peaks agree (in place no link's moment: no element loads at t^n), and a copy of
   the in-place state has its forces. */
static void test_in_place_pin_forces(rjt_ctx *c)
{
    static void (*const text[2])(const char *, char *, size_t) = { chain_text,
                                                                      ground_loop_text };
    static const char *const what[2] = { "a chain of flexible links and a rigid arm",
                                         "a four-bar closed at its rigid rocker's ground pivot" };
    static const int joints[2] = { 5, 4 };
    static const int links[2] = { 4, 2 };
    int k;
    for (k = 0; k < 2; k++) {
        in_place_run o;
        const int ran = in_place_compare(text[k], 400, &o);
        rjt_check(c, ran && o.in_place && o.same_bits && o.known == joints[k] && !o.differ &&
                         o.worst <= 1e-9 * o.size && o.one <= 1e-12 * o.size &&
                         o.peak <= 1e-9 * o.size && o.moments == links[k] && o.copied &&
                         o.size > 1,
                  "pin forces in place: the double-buffered step's to round-off",
                  "%s: %d joints known both ways at every step (%d in one only), in place "
                  "%.3g N from double-buffered (up to %.4g N), each alone %.3g N from all at "
                  "once, peaks %.3g N apart; moments tracked double-buffered only on %d "
                  "links; same bits %d, copy %d %s",
                  what[k], o.known, o.differ, o.worst, o.size, o.one, o.peak, o.moments,
                  o.same_bits, o.copied, o.msg);
    }
}

static void test_rigid_fourbar(rjt_ctx *c)
{
    fourbar_run a, b, fine;
    run_rigid(1e-4, &a);
    run_rigid(5e-5, &b);
    run_rigid(1.25e-5, &fine);
    rjt_check(c, a.result == RJ_OK && b.result == RJ_OK && a.crank / b.crank > 3.5 &&
                     a.crank / b.crank < 4.5 && fine.crank < 1e-6,
              "four-bar of rigid bars: the crank against the exact motion, second order in dt",
              "max |crank - exact| over %g s: %.3g, %.3g, %.3g rad at dt 0.1, 0.05, 0.0125 ms "
              "(ratio %.2f) %s%s",
              RIGID_SECONDS, a.crank, b.crank, fine.crank, a.crank / b.crank, a.msg, b.msg);
    rjt_check(c, fine.result == RJ_OK && a.gap < 1e-12 && fine.gap < 1e-12 &&
                     fine.loop_angle < 1e-6 && a.balance / b.balance > 3.5 &&
                     b.balance < 1e-6 * b.energy,
              "four-bar of rigid bars: the loop closed to round-off, the balance second order",
              "pin gap %.3g m over the run; loop joint within %.3g rad of the exact; max |balance| "
              "%.3g, %.3g J at dt 0.1, 0.05 ms of %.3g J kinetic %s",
              fine.gap, fine.loop_angle, a.balance, b.balance, b.energy, fine.msg);
}

/* The IFToMM multibody benchmark A02 (the N four-bar mechanism): 2N + 1 rigid bars of
   1 m and 1 kg under gravity, N + 1 cranks on a ground line 1 m apart and N couplers
   between their tips, released with the cranks upright and the first crank's tip B0
   moving at 1 m/s in x. Its windows are parallelograms, so every crank turns as the first
   (the exact motion: one pendulum of inertia m L^2 ((N + 1) / 3 + N), gravity's moment
   m g L cos(theta) ((N + 1) / 2 + N)), and it passes the flat position, where N loops'
   rows repeat each other, about every second. The scene's text into text (flat: the
   cranks along the ground line instead, the singular position). */
static void a02_text(int N, double dt, int flat, char *text, size_t n)
{
    const char *up = flat ? "0 deg" : "90 deg", *across = flat ? "180 deg" : "90 deg";
    const char *closing = flat ? "180 deg" : "270 deg";
    size_t at = 0;
    int i;
    at += (size_t) snprintf(text + at, n - at,
                            "solver\n  dt = %g\n  gravity = 0 -9.81\n"
                            "section bar\n  width = 0.01  height = 0.01\n", dt);
    for (i = 0; i <= N; i++)
        at += (size_t) snprintf(text + at, n - at,
                                "link c%d\n  length = 1  elements = 1  rho = 10000  section = bar"
                                "  fidelity = rigid\n", i);
    for (i = 1; i <= N; i++)
        at += (size_t) snprintf(text + at, n - at,
                                "link k%d\n  length = 1  elements = 1  rho = 10000  section = bar"
                                "  fidelity = rigid\n", i);
    at += (size_t) snprintf(text + at, n - at,
                            "joint g0\n  body1 = ground  body2 = c0  angle0 = %s  rate0 = -1\n",
                            up);
    for (i = 1; i <= N; i++)
        at += (size_t) snprintf(
            text + at, n - at,
            "joint a%d\n  body1 = c%d  body2 = k%d  angle0 = %s  rate0 = 1\n"
            "joint g%d\n  body1 = ground  body2 = c%d  ground_x = %d  angle0 = %s  rate0 = -1\n"
            "joint b%d\n  body1 = k%d  body2 = c%d  node2 = last  angle0 = %s\n",
            i, i - 1, i, across, i, i, i, up, i, i, i, closing);
}

/* The exact crank angle's acceleration of A02 with N windows. */
static double a02_accel(int N, double theta)
{
    return -G * cos(theta) * ((N + 1) / 2.0 + N) / ((N + 1) / 3.0 + N);
}

/* A02 with N windows for t_end at dt: the largest |B0 x - exact| and |balance|. */
static void run_a02(int N, double dt, double t_end, fourbar_run *o)
{
    static char text[64 * 1024];
    rj_model *m = NULL;
    rj_state *s = NULL;
    rj_error err;
    double th = PI / 2, w = -1;
    memset(o, 0, sizeof *o);
    a02_text(N, dt, 0, text, sizeof text);
    if (!build(text, &m, &s, &err)) {
        o->result = err.code;
        snprintf(o->msg, sizeof o->msg, "%s", err.msg);
        return;
    }
    while (rj_state_time(s) < t_end - 0.5 * dt && o->result == RJ_OK) {
        const double k1 = a02_accel(N, th), k2 = a02_accel(N, th + dt / 2 * w);
        const double k3 = a02_accel(N, th + dt / 2 * (w + dt / 2 * k1));
        const double k4 = a02_accel(N, th + dt * (w + dt / 2 * k2));
        double b0[2];
        rj_energy e;
        o->result = rj_step(m, s);
        th += dt * (w + dt * (k1 + k2 + k3) / 6);
        w += dt * (k1 + 2 * k2 + 2 * k3 + k4) / 6;
        rj_node_position(m, s, 0, 1, b0);
        o->crank = fmax(o->crank, fabs(b0[0] - cos(th)));
        rj_state_energy(m, s, &e);
        o->balance = fmax(o->balance, fabs(e.balance));
        o->energy = fmax(o->energy, fabs(e.kinetic));
    }
    if (o->result != RJ_OK)
        snprintf(o->msg, sizeof o->msg, "t = %g s: %s", rj_state_time(s), rj_state_error(s));
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
}

/* A02 at the benchmark's tolerance, 1e-3 m on B0 over 20 s, with 2 and 10 windows (40,
   the benchmark's own, runs in bench/a02.c: a dense step of 81 coordinates). */
static void test_a02(rjt_ctx *c)
{
    static const int windows[2] = { 2, 10 };
    int k;
    for (k = 0; k < 2; k++) {
        fourbar_run o;
        run_a02(windows[k], 1e-3, 20, &o);
        rjt_check(c, o.result == RJ_OK && o.crank < 1e-3,
                  "A02 N four-bar: through the flat position, B0 against the exact motion",
                  "N %d, dt 1 ms, 20 s: max |B0 x - exact| %.3g m (the benchmark's tolerance "
                  "1e-3 m); max |balance| %.3g J of %.3g J kinetic %s",
                  windows[k], o.crank, o.balance, o.energy, o.msg);
    }
}

/* rj_scene_mobility: the rank the loops' constraints have, and the mobility it leaves,
   against the mechanisms' own: a four-bar 1 (rank 2), the A02 mechanism with 2 windows
   1 upright (rank 4) and 3 flat (its N + 1 = 3: the windows' loops repeat each other),
   the free-floating scissor boom 4 (rank 10: three of them its motion as a whole). */
static void test_mobility(rjt_ctx *c)
{
    static char text[16 * 1024];
    rj_scene_file f;
    rj_error err;
    int got[4][2], k;
    for (k = 0; k < 4; k++) {
        rj_result r = RJ_ERR_PARSE;
        got[k][0] = got[k][1] = -1;
        if (k == 0)
            fourbar_text(7e10, "", 0, text, sizeof text);
        else if (k < 3)
            a02_text(2, 1e-3, k == 2, text, sizeof text);
        if (k == 3)
            r = rj_scene_load("examples/scenes/scissor_boom.rjs", &f, &err);
        else
            r = rj_scene_parse(text, strlen(text), "mobility.rjs", &f, &err);
        if (r == RJ_OK) {
            rj_scene_def d = rj_scene_file_def(&f);
            rj_scene_mobility(&d, &got[k][0], &got[k][1], &err);
            rj_scene_file_free(&f);
        }
    }
    rjt_check(c, got[0][0] == 1 && got[0][1] == 2 && got[1][0] == 1 && got[1][1] == 4 &&
                     got[3][0] == 4 && got[3][1] == 10,
              "mobility: the loops' rank and the freedom left",
              "four-bar %d (rank %d), A02 N = 2 upright %d (rank %d), scissor boom %d (rank %d)",
              got[0][0], got[0][1], got[1][0], got[1][1], got[3][0], got[3][1]);
    rjt_check(c, got[2][0] == 3 && got[2][1] == 2,
              "mobility: a parallelogram mechanism at its flat position, its rank dropped",
              "A02 N = 2 flat: mobility %d, rank %d (want 3 and 2) %s", got[2][0], got[2][1],
              got[2][0] < 0 ? err.msg : "");
}

/* The scissor boom of rigid strips, A0 held at 80 deg (rigid links must hang or be
   fixed): each crossing pins a link's middle node (a rigid link hanging at node 2), five
   loops in joint coordinates; the six crossings latch in one step, and the span between
   the first and last crossings is the geometry's, 5 x 0.5 m x cos 30 deg. */
static void test_rigid_scissor(rjt_ctx *c)
{
    rj_scene_file f;
    rj_scene_def d;
    rj_error err;
    rj_model *m = NULL;
    rj_state *s = NULL;
    rj_energy e0, e;
    double balance = 0, first = -1, last = -1, a[2], b[2], span = 0;
    const double want = 5 * 0.5 * cos(PI / 6);
    rj_result r = rj_scene_load("examples/scenes/scissor_boom.rjs", &f, &err);
    int l, j, locked = 0;
    if (r == RJ_OK) {
        d = rj_scene_file_def(&f);
        for (l = 0; l < d.link_count; l++)
            ((rj_link_def *) d.links)[l].fidelity = RJ_LINK_RIGID;
        ((rj_link_def *) d.links)[0].root = RJ_ROOT_FIXED;
        r = rj_model_create(&d, &m, &err, NULL);
        rj_scene_file_free(&f);
    }
    if (r != RJ_OK) {
        rjt_check(c, 0, "rigid scissor boom", "%s", err.msg);
        return;
    }
    rj_state_create(m, &s, NULL);
    rj_state_energy(m, s, &e0);
    while (rj_state_time(s) < 2 && r == RJ_OK) {
        int now = 0;
        r = rj_step(m, s);
        rj_state_energy(m, s, &e);
        balance = fmax(balance, fabs(e.balance));
        for (j = 0; j < rj_model_joint_count(m); j++)
            now += rj_joint_flag(m, s, j) == RJ_LOCKED;
        if (now > 0 && first < 0)
            first = rj_state_time(s);
        if (now == 6 && last < 0)
            last = rj_state_time(s);
    }
    for (j = 0; j < rj_model_joint_count(m); j++)
        locked += rj_joint_flag(m, s, j) == RJ_LOCKED;
    rj_node_position(m, s, 0, 2, a);
    rj_node_position(m, s, 10, 2, b);
    span = hypot(a[0] - b[0], a[1] - b[1]);
    rjt_check(c, r == RJ_OK && locked == 6 && first == last && fabs(span - want) < 1e-3 * want &&
                     balance < 1e-5 * e0.total,
              "rigid scissor boom: links hanging at their middle nodes, five loops, latching",
              "the six crossings latch at %.4f s (the last at %.4f s); span %.6f m against "
              "%.6f m; max |balance| %.3g J of %.3g J %s",
              first, last, span, want, balance, e0.total, r == RJ_OK ? "" : rj_state_error(s));
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
}

/* A rigid rod of 1 m pinned to the ground at node 1 of 4 (0.25 m from its end, its
   centre 0.25 m from the pin), released level under gravity: its period against the
   exact one of a physical pendulum, 4 sqrt(I_p / (m g d)) K(sin 45 deg) with
   I_p = m (L^2 / 12 + d^2); the time between the rate's first two zeros is half of it. */
static void test_rigid_interior_pin(rjt_ctx *c)
{
    static const char text[] =
        "solver\n  dt = 1e-4\n  gravity = 0 -9.81\n"
        "link rod\n  length = 1  elements = 4  rho = 10000  width = 0.01  height = 0.01"
        "  fidelity = rigid\n"
        "joint pin\n  body1 = ground  body2 = rod  node2 = 1  angle0 = 0 deg\n";
    const double K = 1.8540746773013719; /* K(sin 45 deg) */
    const double want = 4 * sqrt((1.0 / 12 + 0.0625) / (G * 0.25)) * K;
    rj_model *m = NULL;
    rj_state *s = NULL;
    rj_error err;
    double prev = 0, zero[2] = { -1, -1 }, t_prev = 0;
    int found = 0;
    if (!build(text, &m, &s, &err)) {
        rjt_check(c, 0, "rigid rod pinned at an interior node", "%s", err.msg);
        return;
    }
    while (rj_state_time(s) < 3 && found < 2 && rj_step(m, s) == RJ_OK) {
        const double rate = rj_joint_rate(m, s, 0), t = rj_state_time(s);
        /* the rate's zero between two steps, by linear interpolation */
        if (t_prev > 0 && ((prev < 0 && rate >= 0) || (prev > 0 && rate <= 0)))
            zero[found++] = t_prev + (t - t_prev) * prev / (prev - rate);
        prev = rate;
        t_prev = t;
    }
    rjt_check(c, found == 2 && fabs(2 * (zero[1] - zero[0]) - want) < 1e-5 * want,
              "rigid rod pinned at an interior node: the physical pendulum's period",
              "period %.9f s against %.9f s (%.2g relative)", 2 * (zero[1] - zero[0]), want,
              (2 * (zero[1] - zero[0]) - want) / want);
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
}

int main(void)
{
    rjt_ctx c = { 0, 0 };
    test_rigid_interior_pin(&c);
    test_rigid_scissor(&c);
    test_mobility(&c);
    test_a02(&c);
    test_scissor(&c, RJ_LINK_FLEXIBLE);
    test_scissor(&c, RJ_LINK_INEXTENSIBLE);
    test_scissor(&c, RJ_LINK_RIGID);
    test_rigid_fourbar(&c);
    test_rigid_pins(&c);
    test_loop_statics(&c);
    test_loop_sides(&c);
    test_loop_ground(&c);
    test_in_place_pin_forces(&c);
    test_rigid_latch(&c);
    test_rigid_driven(&c);
    test_rigid_loop_rotor_cable(&c);
    test_rigid_loop_limits(&c);
    test_rigid_loop_prescribed(&c);
    test_rigid_loop_joint_torques(&c);
    test_rigid_long(&c);
    test_fourbar(&c);
    test_fourbar_inextensible(&c);
    test_inextensible_tree(&c);
    test_fourbar_mixed(&c);
    test_body_pair_torques(&c);
    test_body_pin_motor(&c);
    test_body_pair_parts(&c);
    test_body_pair_latch(&c);
    test_fourbar_pair_lock(&c);
    test_body_pair_prescribed(&c);
    test_loop_checkpoints(&c);
    test_refusals(&c);
    test_assemble(&c);
    return rjt_summary(&c, "test_loops");
}
