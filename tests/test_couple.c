/* Cable loops (rj_coupling_def) against what we did not tune: two rigid panels on a stiff
   loop against the exact one-degree-of-freedom motion (Lagrange's equation with theta_2
   tied to theta_1, integrated here by RK4) and its exact constraint torque, the error
   falling as 1/stiffness; the cable's stretch against its compliance and the pair's
   relative frequency against the linearised sqrt(k vT M^-1 v); the energy balance with
   and without the cable's damping, whose loss is the integral of c (de/dt)^2, for every
   link model; the stability bound against the 2 x 2 eigenproblem (rigid) and the pin
   nodes' inertias (flexible), stable below it and stopped above it; refusals naming the
   field; scene files read, written back and read again, and their errors.
   Every check prints what it measured. */
#include "../revjoint.h"
#include "rjt.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846
#define TH10 (0.5 * PI)   /* hinge 1 starts at 90 deg: panel 1 stands up */
#define TH20 (2.0 * PI)   /* hinge 2 starts at 360 deg: panel 2 folded back on panel 1 */
#define RATIO (-2.0)      /* hinge 2 opens 360 -> 180 deg while hinge 1 opens 90 -> 180 */
#define K1 1.0            /* N m/rad, hinge 1's spring */
#define FREE1 (4.0 * PI / 3.0) /* its free angle, 240 deg */

/* A panel 1 m long, 0.1 x 0.01 m, 1000 kg/m^3: 1 kg. */
static rj_link_def panel(int fidelity)
{
    rj_link_def l = rj_default_link_def();
    l.length = 1.0;
    l.elements = fidelity == RJ_LINK_RIGID ? 1 : 4;
    l.E = 70e9;
    l.rho = 1000;
    l.section = RJ_SECTION_RECT;
    l.width = 0.1;
    l.height = 0.01;
    l.fidelity = fidelity;
    return l;
}

/* Two panels: hinge 1 ground -> p1 with the spring, hinge 2 p1 -> p2, and a loop tying
   hinge 2 to hinge 1 (stiffness k, damping c). The scene points into p: do not copy. */
typedef struct pair {
    rj_link_def link[2];
    rj_joint_def joint[2];
    rj_coupling_def cable;
    rj_scene_def scene;
} pair;

static void pair_make(pair *p, int fidelity, double k, double c)
{
    p->link[0] = panel(fidelity);
    p->link[1] = panel(fidelity);
    p->joint[0] = rj_default_joint_def();
    p->joint[0].body1 = -1;
    p->joint[0].body2 = 0;
    p->joint[0].angle0 = TH10;
    p->joint[0].spring_k = K1;
    p->joint[0].spring_free_angle = FREE1;
    p->joint[1] = rj_default_joint_def();
    p->joint[1].body1 = 0;
    p->joint[1].body2 = 1;
    p->joint[1].angle0 = TH20;
    p->cable = rj_default_coupling_def();
    p->cable.joint_a = 0;
    p->cable.joint_b = 1;
    p->cable.ratio = RATIO;
    p->cable.stiffness = k;
    p->cable.damping = c;
    p->scene = rj_default_scene_def();
    p->scene.links = p->link;
    p->scene.link_count = 2;
    p->scene.joints = p->joint;
    p->scene.joint_count = 2;
    p->scene.couplings = &p->cable;
    p->scene.coupling_count = 1;
}

/* Model and state of p; 0 with msg filled when either fails. */
static int pair_build(pair *p, rj_model **m, rj_state **s, char *msg, size_t n)
{
    rj_error err;
    if (rj_model_create(&p->scene, m, &err, NULL) != RJ_OK) {
        snprintf(msg, n, "rj_model_create: %s", err.msg);
        return 0;
    }
    if (rj_state_create(*m, s, NULL) != RJ_OK) {
        snprintf(msg, n, "rj_state_create failed");
        rj_model_destroy(*m, NULL);
        return 0;
    }
    return 1;
}

static void pair_free(rj_model *m, rj_state *s)
{
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
}

/* The cable's stretch e from the running angles. */
static double stretch(const rj_model *m, const rj_state *s, const rj_coupling_def *c)
{
    const double ta = rj_joint_theta_running(m, s, c->joint_a);
    const double tb = rj_joint_theta_running(m, s, c->joint_b);
    const double a0 = rj_model_joint_def(m, c->joint_a)->angle0;
    const double b0 = rj_model_joint_def(m, c->joint_b)->angle0;
    return (tb - b0) - c->ratio * (ta - a0) - c->offset;
}

/* ------------------------------------------------------------------ the exact pair */

/* Two uniform rods (mass m, length L) in joint coordinates: absolute angles a1 = theta1,
   a2 = theta1 + theta2 + pi. T = 1/2 A w1^2 + 1/2 B w2^2 - C cos(theta2) w1 w2 with
   w1 = theta1', w2 = theta1' + theta2', A = m1 L1^2 / 3 + m2 L1^2, B = m2 L2^2 / 3,
   C = m2 L1 L2 / 2. */
typedef struct rods {
    double A, B, C;
} rods;

static rods rods_of(const rj_link_def *l)
{
    const double m1 = l[0].rho * l[0].width * l[0].height * l[0].length;
    const double m2 = l[1].rho * l[1].width * l[1].height * l[1].length;
    const double L1 = l[0].length, L2 = l[1].length;
    rods r;
    r.A = m1 * L1 * L1 / 3 + m2 * L1 * L1;
    r.B = m2 * L2 * L2 / 3;
    r.C = 0.5 * m2 * L1 * L2;
    return r;
}

/* The 2 x 2 mass matrix in (theta1, theta2). */
static void rods_mass(const rods *r, double th2, double M[3])
{
    const double cc = r->C * cos(th2);
    M[0] = r->A + r->B - 2 * cc;
    M[1] = r->B - cc;
    M[2] = r->B;
}

/* theta2 held at TH20 + RATIO (q - TH10), q = theta1: one degree of freedom with
   J(q) = A + B u^2 - 2 C u cos(theta2), u = 1 + RATIO, and J q'' + J'/2 q'^2 =
   -K1 (q - FREE1). */
static double exact_accel(const rods *r, double q, double w)
{
    const double u = 1 + RATIO, th2 = TH20 + RATIO * (q - TH10);
    const double J = r->A + r->B * u * u - 2 * r->C * u * cos(th2);
    const double dJ = 2 * r->C * u * RATIO * sin(th2);
    return (-K1 * (q - FREE1) - 0.5 * dJ * w * w) / J;
}

/* The torque on hinge 2 that holds the tie: Lagrange's equation of theta2,
   Q2 = (B u - C cos theta2) q'' - C sin(theta2) q'^2. */
static double exact_torque(const rods *r, double q, double w)
{
    const double u = 1 + RATIO, th2 = TH20 + RATIO * (q - TH10);
    return (r->B * u - r->C * cos(th2)) * exact_accel(r, q, w) - r->C * sin(th2) * w * w;
}

/* One RK4 step of h on (q, w). */
static void exact_rk4(const rods *r, double *q, double *w, double h)
{
    const double q0 = *q, w0 = *w;
    const double k1q = w0, k1w = exact_accel(r, q0, w0);
    const double k2q = w0 + 0.5 * h * k1w;
    const double k2w = exact_accel(r, q0 + 0.5 * h * k1q, k2q);
    const double k3q = w0 + 0.5 * h * k2w;
    const double k3w = exact_accel(r, q0 + 0.5 * h * k2q, k3q);
    const double k4q = w0 + h * k3w;
    const double k4w = exact_accel(r, q0 + h * k3q, k4q);
    *q = q0 + h / 6 * (k1q + 2 * k2q + 2 * k3q + k4q);
    *w = w0 + h / 6 * (k1w + 2 * k2w + 2 * k3w + k4w);
}

/* The loop's inverse effective inertia vT M^-1 v, v = (-RATIO, 1), at theta2. */
static double inv_ieff(const rods *r, double th2)
{
    double M[3], det;
    rods_mass(r, th2, M);
    det = M[0] * M[2] - M[1] * M[1];
    return (RATIO * RATIO * M[2] + 2 * RATIO * M[1] + M[0]) / det;
}

/* The same pair held by the loop (k, c) instead, two degrees of freedom: M(theta2) a =
   Q - h with h1 = C sin(theta2) w2' (2 w1' + w2'), h2 = -C sin(theta2) w1'^2 (w' the
   joint rates), Q1 = -K1 (theta1 - FREE1) - RATIO tau, Q2 = tau, tau = -k e - c e'. y:
   theta1, theta2, their rates. */
typedef struct loop2 {
    rods r;
    double k, c;
} loop2;

static double loop2_torque(const loop2 *p, const double y[4])
{
    const double e = (y[1] - TH20) - RATIO * (y[0] - TH10);
    return -p->k * e - p->c * (y[3] - RATIO * y[2]);
}

static void loop2_rate(const loop2 *p, const double y[4], double dy[4])
{
    double M[3], q1, q2, det;
    const double tau = loop2_torque(p, y), s = p->r.C * sin(y[1]);
    rods_mass(&p->r, y[1], M);
    q1 = -K1 * (y[0] - FREE1) - RATIO * tau - s * y[3] * (2 * y[2] + y[3]);
    q2 = tau + s * y[2] * y[2];
    det = M[0] * M[2] - M[1] * M[1];
    dy[0] = y[2];
    dy[1] = y[3];
    dy[2] = (M[2] * q1 - M[1] * q2) / det;
    dy[3] = (M[0] * q2 - M[1] * q1) / det;
}

static void loop2_rk4(const loop2 *p, double y[4], double h)
{
    double k1[4], k2[4], k3[4], k4[4], t[4];
    int i;
    loop2_rate(p, y, k1);
    for (i = 0; i < 4; i++)
        t[i] = y[i] + 0.5 * h * k1[i];
    loop2_rate(p, t, k2);
    for (i = 0; i < 4; i++)
        t[i] = y[i] + 0.5 * h * k2[i];
    loop2_rate(p, t, k3);
    for (i = 0; i < 4; i++)
        t[i] = y[i] + h * k3[i];
    loop2_rate(p, t, k4);
    for (i = 0; i < 4; i++)
        y[i] += h / 6 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
}

/* ------------------------------------------------------------------ 1, 2: the 1-DOF limit */

#define T_END 1.5
#define T_SKIP 0.2 /* the start's transient in the torque has died out by then */

/* Largest differences over a run, [0] hinge 1's angle (rad, every step), [1] the loop's
   torque on hinge 2 (N m, t >= T_SKIP): lib_tie the model against the exact tie,
   lib_loop the model against the exact pair on its loop (both at t >= T_SKIP, past the
   start's fast transient), loop_tie the exact pair against the exact tie. */
typedef struct tie_run {
    double dt, lib_tie[2], lib_loop[2], loop_tie[2];
    double torque_peak, a_err, e_peak, exact_peak, theta_end;
} tie_run;

static void worse(double d[2], double angle, double torque, int late)
{
    d[0] = fmax(d[0], fabs(angle));
    if (late)
        d[1] = fmax(d[1], fabs(torque));
}

/* The rigid pair on a loop of stiffness k damped at zeta of its relative mode, to T_END,
   against the exact tie (1 DOF) and the exact pair on that loop (2 DOF, RK4 at <= 1e-5 s
   in step with the model): hinge 1's angle, and the loop's torque on hinge 2 (spring +
   damping components, which on hinge 2 are the loop's alone) against the exact
   constraint torque; hinge 1's (its components minus its own spring) against -RATIO
   times hinge 2's. The torques in a state are those of its previous time level (they
   act over the step to it), so they are compared there. */
static int tie_run_k(double k, double zeta, double dt, tie_run *o, char *msg, size_t n)
{
    pair p;
    loop2 two;
    rj_model *m;
    rj_state *s;
    double q = TH10, w = 0, q_prev = TH10, w_prev = 0, th1_prev = TH10, h;
    double y[4] = { TH10, TH20, 0, 0 }, tq2_prev;
    int sub, i;
    rj_result res = RJ_OK;
    pair_make(&p, RJ_LINK_RIGID, k, 0);
    two.r = rods_of(p.link);
    two.k = k;
    two.c = p.cable.damping = 2 * zeta * sqrt(k / inv_ieff(&two.r, TH20));
    p.scene.solver.dt = dt;
    if (!pair_build(&p, &m, &s, msg, n))
        return 0;
    memset(o, 0, sizeof *o);
    o->dt = rj_model_dt(m);
    sub = (int) ceil(o->dt / 1e-5);
    h = o->dt / sub;
    tq2_prev = loop2_torque(&two, y);
    while (rj_state_time(s) < T_END - 0.5 * o->dt) {
        double th1, tq_b, tq_a, ex;
        int late;
        if ((res = rj_step(m, s)) != RJ_OK)
            break;
        for (i = 0; i < sub; i++) {
            exact_rk4(&two.r, &q, &w, h);
            loop2_rk4(&two, y, h);
        }
        th1 = rj_joint_theta_running(m, s, 0);
        tq_b = rj_joint_torque(m, s, 1, RJ_TORQUE_SPRING) +
               rj_joint_torque(m, s, 1, RJ_TORQUE_DAMPING);
        tq_a = rj_joint_torque(m, s, 0, RJ_TORQUE_SPRING) +
               rj_joint_torque(m, s, 0, RJ_TORQUE_DAMPING) + K1 * (th1_prev - FREE1);
        ex = exact_torque(&two.r, q_prev, w_prev);
        late = rj_state_time(s) - o->dt >= T_SKIP;
        worse(o->lib_tie, th1 - q, tq_b - ex, late);
        if (late)
            worse(o->lib_loop, th1 - y[0], tq_b - tq2_prev, 1);
        worse(o->loop_tie, y[0] - q, tq2_prev - ex, late);
        o->a_err = fmax(o->a_err, fabs(tq_a + RATIO * tq_b));
        o->exact_peak = fmax(o->exact_peak, fabs(ex));
        o->e_peak = fmax(o->e_peak, fabs(stretch(m, s, &p.cable)));
        if (late)
            o->torque_peak = fmax(o->torque_peak, fabs(tq_b));
        q_prev = q;
        w_prev = w;
        th1_prev = th1;
        tq2_prev = loop2_torque(&two, y);
    }
    o->theta_end = rj_joint_theta_running(m, s, 0);
    if (res != RJ_OK)
        snprintf(msg, n, "rj_step: %s: %s", rj_result_str(res), rj_state_error(s));
    pair_free(m, s);
    return res == RJ_OK;
}

/* Check 1: the stiffer the loop, the closer to the exact tie, the error as 1/k; at each
   k the model follows the exact pair on that loop, so the difference to the tie is the
   cable's compliance. */
static void test_tie(rjt_ctx *c)
{
    static const double ks[4] = { 1e3, 1e4, 1e5, 1e6 };
    tie_run o[4];
    char msg[600] = "", name[160];
    int i;
    for (i = 0; i < 4; i++) {
        const tie_run *r = &o[i];
        double comp;
        snprintf(name, sizeof name, "rigid pair, loop %.0e N m/rad", ks[i]);
        if (!tie_run_k(ks[i], 0.5, 0, &o[i], msg, sizeof msg)) {
            rjt_check(c, 0, name, "%s", msg);
            return;
        }
        comp = r->exact_peak / ks[i];
        snprintf(name, sizeof name, "rigid pair, loop %.0e N m/rad: hinge 1 against "
                 "the exact tie", ks[i]);
        rjt_check(c, r->lib_tie[0] <= 2 * comp, name,
                  "dt %.3g s, max |theta1 - exact| %.3g rad <= 2 x peak torque / k = "
                  "%.3g rad (exact pair on the loop: %.3g; theta1 at %.1f s %.6f deg)",
                  r->dt, r->lib_tie[0], 2 * comp, r->loop_tie[0], T_END,
                  r->theta_end * 180 / PI);
        snprintf(name, sizeof name, "rigid pair, loop %.0e N m/rad: loop torque on "
                 "hinge 2 against the exact constraint torque", ks[i]);
        rjt_check(c, r->lib_tie[1] <= 1.2 * r->loop_tie[1] + 1e-3 * comp * ks[i], name,
                  "max |tau - exact| %.3g N m at t >= %.1f s (peak %.4f N m); the exact "
                  "pair on the loop %.3g", r->lib_tie[1], T_SKIP, r->torque_peak,
                  r->loop_tie[1]);
        snprintf(name, sizeof name, "rigid pair, loop %.0e N m/rad: the model against "
                 "the exact pair on the loop", ks[i]);
        rjt_check(c, r->lib_loop[0] <= 0.5 * r->loop_tie[0] &&
                  r->lib_loop[1] <= 0.2 * r->loop_tie[1], name,
                  "max |theta1 diff| %.3g rad (< 0.5 x %.3g), max |tau diff| %.3g N m "
                  "(< 0.2 x %.3g) at t >= %.1f s, against the loop's own difference to "
                  "the tie", r->lib_loop[0], r->loop_tie[0], r->lib_loop[1],
                  r->loop_tie[1], T_SKIP);
        snprintf(name, sizeof name, "rigid pair, loop %.0e N m/rad: hinge 1 takes -ratio "
                 "x hinge 2's loop torque", ks[i]);
        rjt_check(c, r->a_err <= 1e-12 * (1 + r->exact_peak), name,
                  "max |tau_1 - K1 part + ratio tau_2| %.3g N m", r->a_err);
        snprintf(name, sizeof name, "rigid pair, loop %.0e N m/rad: stretch within the "
                 "cable's compliance", ks[i]);
        rjt_check(c, r->e_peak <= 2.5 * comp && r->e_peak >= 0.4 * comp, name,
                  "max |e| %.3g rad, exact peak torque / k %.3g rad (ratio %.3f, in "
                  "[0.4, 2.5])", r->e_peak, comp, r->e_peak / comp);
    }
    for (i = 0; i + 1 < 4; i++) {
        const double ra = o[i].lib_tie[0] / o[i + 1].lib_tie[0];
        const double rt = o[i].lib_tie[1] / o[i + 1].lib_tie[1];
        snprintf(name, sizeof name, "rigid pair: errors fall as 1/k from %.0e to %.0e "
                 "N m/rad", ks[i], ks[i + 1]);
        rjt_check(c, ra >= 5 && ra <= 20 && rt >= 5 && rt <= 20, name,
                  "angle error / %.2f, torque error / %.2f (1/k: 10; within 5..20); "
                  "k x errors %.3g rad N m/rad, %.3g N m^2/rad", ra, rt,
                  ks[i] * o[i].lib_tie[0], ks[i] * o[i].lib_tie[1]);
    }
}

/* The model converges to the exact pair on its loop at second order in dt: k 1e4 N m/rad
   (its automatic step is the 1 ms cap) at 1, 0.5 and 0.25 ms. */
static void test_tie_order(rjt_ctx *c)
{
    static const double dts[3] = { 1e-3, 5e-4, 2.5e-4 };
    tie_run o[3];
    char msg[600] = "";
    int i;
    for (i = 0; i < 3; i++)
        if (!tie_run_k(1e4, 0.5, dts[i], &o[i], msg, sizeof msg)) {
            rjt_check(c, 0, "rigid pair, loop 1e4 N m/rad: order in dt", "%s", msg);
            return;
        }
    rjt_check(c, o[0].lib_loop[0] / o[1].lib_loop[0] > 3.5 &&
              o[1].lib_loop[0] / o[2].lib_loop[0] > 3.5 &&
              o[0].lib_loop[1] / o[1].lib_loop[1] > 3.5 &&
              o[1].lib_loop[1] / o[2].lib_loop[1] > 3.5,
              "rigid pair, loop 1e4 N m/rad: second order in dt to the exact pair",
              "theta1 diff %.3g, %.3g, %.3g rad; tau diff %.3g, %.3g, %.3g N m at dt 1, "
              "0.5, 0.25 ms (t >= %.1f s; ratios > 3.5)", o[0].lib_loop[0],
              o[1].lib_loop[0], o[2].lib_loop[0], o[0].lib_loop[1], o[1].lib_loop[1],
              o[2].lib_loop[1], T_SKIP);
}

/* Check 2: a loop pre-stretched by its offset, no spring, no damping: e rings at
   omega^2 = k vT M^-1 v (the loop's stiffness over the pair's effective inertia at the
   start), which the central difference turns into 2 / dt asin(omega dt / 2). Measured
   over 30 periods by e's zero crossings at dt = bound / 20. */
static void test_frequency(rjt_ctx *c)
{
    const double k = 1e4, offset = 1e-3;
    pair p;
    rods r;
    rj_model *m;
    rj_state *s;
    double omega, omega_cd, period, t_first = -1, t_last = -1, e_prev, t_prev, dt, bound;
    int crossings = 0;
    char msg[600] = "";
    pair_make(&p, RJ_LINK_RIGID, k, 0);
    p.joint[0].spring_k = 0;
    p.cable.offset = offset;
    r = rods_of(p.link);
    omega = sqrt(k * inv_ieff(&r, TH20));
    if (!pair_build(&p, &m, &s, msg, sizeof msg)) {
        rjt_check(c, 0, "rigid pair: relative frequency", "%s", msg);
        return;
    }
    bound = rj_model_dt_bound(m);
    pair_free(m, s);
    p.scene.solver.dt = bound / 20;
    if (!pair_build(&p, &m, &s, msg, sizeof msg)) {
        rjt_check(c, 0, "rigid pair: relative frequency", "%s", msg);
        return;
    }
    dt = rj_model_dt(m);
    omega_cd = 2 / dt * asin(0.5 * omega * dt);
    e_prev = stretch(m, s, &p.cable);
    t_prev = 0;
    while (crossings < 61 && rj_step(m, s) == RJ_OK) {
        const double e = stretch(m, s, &p.cable), t = rj_state_time(s);
        if ((e > 0) != (e_prev > 0)) {
            const double tc = t_prev + (t - t_prev) * e_prev / (e_prev - e);
            if (crossings++ == 0)
                t_first = tc;
            t_last = tc;
        }
        e_prev = e;
        t_prev = t;
    }
    period = 2 * (t_last - t_first) / (crossings - 1);
    rjt_check(c, crossings == 61 && fabs(2 * PI / period / omega - 1) < 2e-3,
              "rigid pair: relative frequency against sqrt(k vT M^-1 v)",
              "%d crossings, measured %.6g rad/s, linearised %.6g rad/s (rel %.2e), "
              "central difference's %.6g (rel %.2e), dt %.3g s", crossings,
              2 * PI / period, omega, 2 * PI / period / omega - 1, omega_cd,
              2 * PI / period / omega_cd - 1, dt);
    pair_free(m, s);
}

/* ------------------------------------------------------------------ 3: energy */

#define MIXED 99 /* a rigid panel p1 (a rigid body) carrying a flexible p2 */

/* The pair to 1 s on a 2000 N m/rad loop with damping c: [0] the largest |balance|
   against the spring's initial energy; [1] lost_damping against [2] the sum of
   c (de/dt)^2 dt over the steps (de/dt from e's change over each step), to the
   accounts' time (one step back); [3] dt; [4] the largest |E_spring - 1/2 K1 (theta1 -
   FREE1)^2 - 1/2 k e^2| at the accounts' time, relative. solver.dt = dt (0: automatic). */
static int energy_run(int fidelity, double c_loop, double dt, double out[5], char *msg,
                      size_t n)
{
    pair p;
    rj_model *m;
    rj_state *s;
    rj_energy en;
    double e_prev, th_prev, sum = 0, sum_prev = 0, worst = 0, e0;
    rj_result res = RJ_OK;
    pair_make(&p, fidelity == MIXED ? RJ_LINK_FLEXIBLE : fidelity, 2000, c_loop);
    if (fidelity == MIXED)
        p.link[0] = panel(RJ_LINK_RIGID);
    p.scene.solver.dt = dt;
    if (!pair_build(&p, &m, &s, msg, n))
        return 0;
    rj_state_energy(m, s, &en);
    e0 = en.total;
    e_prev = stretch(m, s, &p.cable);
    th_prev = rj_joint_theta_running(m, s, 0);
    out[4] = 0;
    while (rj_state_time(s) < 1.0 - 0.5 * rj_model_dt(m)) {
        double e, rate, want;
        if ((res = rj_step(m, s)) != RJ_OK)
            break;
        e = stretch(m, s, &p.cable);
        rate = (e - e_prev) / rj_model_dt(m);
        sum_prev = sum;
        sum += c_loop * rate * rate * rj_model_dt(m);
        rj_state_energy(m, s, &en);
        worst = fmax(worst, fabs(en.balance));
        want = 0.5 * K1 * (th_prev - FREE1) * (th_prev - FREE1) + 1000 * e_prev * e_prev;
        out[4] = fmax(out[4], fabs(en.spring - want) / want);
        e_prev = e;
        th_prev = rj_joint_theta_running(m, s, 0);
    }
    out[0] = worst / e0;
    out[1] = en.lost_damping;
    out[2] = sum_prev;
    out[3] = rj_model_dt(m);
    if (res != RJ_OK)
        snprintf(msg, n, "rj_step: %s: %s", rj_result_str(res), rj_state_error(s));
    pair_free(m, s);
    return res == RJ_OK;
}

static void test_energy(rjt_ctx *c, int fidelity, double c_loop, double tol,
                        const char *what)
{
    double a[5], b[5];
    char msg[600] = "", name[200];
    snprintf(name, sizeof name, "%s, loop damping %g N m s/rad: energy balance", what,
             c_loop);
    if (!energy_run(fidelity, c_loop, 0, a, msg, sizeof msg) ||
        !energy_run(fidelity, c_loop, 0.5 * a[3], b, msg, sizeof msg)) {
        rjt_check(c, 0, name, "%s", msg);
        return;
    }
    rjt_check(c, a[0] < tol && b[0] <= a[0], name,
              "max |balance| / E_spring(0) %.3g at dt %.3g s, %.3g at dt / 2 (ratio %.2f), "
              "< %.0e", a[0], a[3], b[0], a[0] / b[0], tol);
    snprintf(name, sizeof name, "%s, loop damping %g N m s/rad: E_spring holds 1/2 k e^2",
             what, c_loop);
    rjt_check(c, a[4] < 1e-12, name, "max |E_spring - 1/2 K1 (theta1 - free)^2 - "
              "1/2 k e^2| / that %.3g, < 1e-12", a[4]);
    if (c_loop > 0) {
        const double da = fabs(a[1] - a[2]) / a[2], db = fabs(b[1] - b[2]) / b[2];
        snprintf(name, sizeof name, "%s, loop damping %g N m s/rad: W_damping = "
                 "sum of c (de/dt)^2 dt", what, c_loop);
        rjt_check(c, a[1] > 0 && da < 0.1 && db < da / 3, name,
                  "%.9g J against %.9g J (rel %.2e) at dt, %.9g / %.9g (rel %.2e) at "
                  "dt / 2 (ratio %.2f; second order: 4; want < 0.1 and ratio > 3)", a[1],
                  a[2], da, b[1], b[2], db, da / db);
    }
}

/* ------------------------------------------------------------------ 4: stability */

/* The pair at solver.dt = dt (allow_unstable) for 0.2 s: rj_run's result, msg filled. */
static rj_result bound_run(pair *p, double dt, char *msg, size_t n)
{
    rj_model *m;
    rj_state *s;
    rj_result res;
    p->scene.solver.dt = dt;
    p->scene.solver.allow_unstable = 1;
    if (!pair_build(p, &m, &s, msg, n))
        return RJ_ERR_INVALID;
    res = rj_run(m, s, 0.2, 0, NULL, NULL);
    snprintf(msg, n, "rj_run: %s after %ld steps (t %.4g s)%s%.160s", rj_result_str(res),
             rj_state_steps(s), rj_state_time(s), res != RJ_OK ? ": " : "",
             rj_state_error(s));
    pair_free(m, s);
    return res;
}

/* The rigid pair on a 1e9 N m/rad loop: omega_max against the 2 x 2 problem
   (K = k v vT + diag(K1, 0), M at the start), the bound 0.98 x 2 / omega_max (the
   library's margin, RJ__DT_MARGIN); stable for 0.2 s at 0.95 x the bound, stopped at
   1.1 x; and the edge itself: stable at 0.99 x 2 / omega_max, stopped at 1.01 x. */
static void test_bound(rjt_ctx *c)
{
    const double k = 1e9, f[4] = { 0.95, 1.1, 0.99 / 0.98, 1.01 / 0.98 };
    pair p;
    rods r;
    rj_model *m;
    rj_state *s;
    double M[3], K[3], det, tr, omega, bound, om_lib;
    char msg[600] = "", name[160];
    int i;
    pair_make(&p, RJ_LINK_RIGID, k, 0);
    r = rods_of(p.link);
    rods_mass(&r, TH20, M);
    K[0] = k * RATIO * RATIO + K1;
    K[1] = -k * RATIO;
    K[2] = k;
    /* det(K - l M) = 0: l^2 det M - l (K0 M2 + K2 M0 - 2 K1 M1) + det K = 0 */
    det = M[0] * M[2] - M[1] * M[1];
    tr = K[0] * M[2] + K[2] * M[0] - 2 * K[1] * M[1];
    omega = sqrt((tr + sqrt(tr * tr - 4 * det * (K[0] * K[2] - K[1] * K[1]))) / (2 * det));
    if (!pair_build(&p, &m, &s, msg, sizeof msg)) {
        rjt_check(c, 0, "rigid pair on 1e9 N m/rad: bound", "%s", msg);
        return;
    }
    bound = rj_model_dt_bound(m);
    om_lib = rj_model_omega_max(m);
    pair_free(m, s);
    rjt_check(c, fabs(om_lib / omega - 1) < 1e-9 &&
              fabs(bound * omega / 2 / 0.98 - 1) < 1e-9,
              "rigid pair on 1e9 N m/rad: omega_max of the 2 x 2 problem",
              "rj_model_omega_max %.9g rad/s against %.9g (rel %.2e); rj_model_dt_bound "
              "%.9g s = %.6f x 2 / omega_max", om_lib, omega, om_lib / omega - 1, bound,
              bound * omega / 2);
    for (i = 0; i < 4; i++) {
        const rj_result res = bound_run(&p, f[i] * bound, msg, sizeof msg);
        const int stable = i == 0 || i == 2;
        snprintf(name, sizeof name, "rigid pair on 1e9 N m/rad at %.3f x the bound "
                 "(%.3f x 2 / omega_max): %s", f[i], 0.98 * f[i],
                 stable ? "stable" : "stopped");
        rjt_check(c, stable ? res == RJ_OK : res == RJ_ERR_BLOWUP || res == RJ_ERR_TUNNEL,
                  name, "%s", msg);
    }
}

/* Flexible panels on a 1e8 N m/rad loop: the loop acts on the pin nodes' rotations
   (tangent reference), v = (-RATIO, -1, 1) on p1's node 0, p1's last node and p2's
   node 0, so omega_max^2 ~ k sum v_i^2 / I_i with their lumped rotary inertias (the
   beams' own stiffness adds a little; Lanczos gives a lower estimate); stable for 0.2 s
   at 0.95 x the bound, stopped at 1.1 x. */
static void test_bound_flexible(rjt_ctx *c)
{
    const double k = 1e8;
    pair p;
    rj_model *m;
    rj_state *s;
    double mass, I[3], omega, bound, om_lib;
    char msg[600] = "";
    rj_result res[2];
    pair_make(&p, RJ_LINK_FLEXIBLE, k, 0);
    if (!pair_build(&p, &m, &s, msg, sizeof msg)) {
        rjt_check(c, 0, "flexible pair on 1e8 N m/rad: bound", "%s", msg);
        return;
    }
    rj_node_mass(m, 0, 0, &mass, &I[0]);
    rj_node_mass(m, 0, p.link[0].elements, &mass, &I[1]);
    rj_node_mass(m, 1, 0, &mass, &I[2]);
    omega = sqrt(k * (RATIO * RATIO / I[0] + 1 / I[1] + 1 / I[2]));
    bound = rj_model_dt_bound(m);
    om_lib = rj_model_omega_max(m);
    pair_free(m, s);
    res[0] = bound_run(&p, 0.95 * bound, msg, sizeof msg);
    res[1] = bound_run(&p, 1.1 * bound, msg, sizeof msg);
    rjt_check(c, fabs(om_lib / omega - 1) < 0.01 && res[0] == RJ_OK &&
              (res[1] == RJ_ERR_BLOWUP || res[1] == RJ_ERR_TUNNEL),
              "flexible pair on 1e8 N m/rad: the loop sets the bound",
              "omega_max %.6g rad/s against sqrt(k sum v^2 / I) %.6g (rel %.2e; pin "
              "nodes' I %.3g kg m^2); 0.95 x the bound %.3g s: %s; 1.1 x: %s", om_lib,
              omega, om_lib / omega - 1, I[0], bound, rj_result_str(res[0]), msg);
}

/* ------------------------------------------------------------------ 5: refusals */

static void refuse(rjt_ctx *c, const pair *p, const char *field, const char *what)
{
    rj_model *m = NULL;
    rj_error err;
    rj_result res = rj_model_create(&p->scene, &m, &err, NULL);
    char name[160];
    snprintf(name, sizeof name, "refused: %s", what);
    rjt_check(c, res == RJ_ERR_INVALID && m == NULL && strcmp(err.field, field) == 0, name,
              "%s, field '%s' (want '%s'): %s", rj_result_str(res),
              res == RJ_OK ? "" : err.field, field, res == RJ_OK ? "built" : err.msg);
    if (res == RJ_OK)
        rj_model_destroy(m, NULL);
}

static void test_refusals(rjt_ctx *c)
{
    pair p;
    pair_make(&p, RJ_LINK_RIGID, 100, 0);
    p.cable.joint_a = 2;
    refuse(c, &p, "couplings[0].joint_a", "joint_a out of range");
    pair_make(&p, RJ_LINK_RIGID, 100, 0);
    p.cable.joint_a = -1;
    refuse(c, &p, "couplings[0].joint_a", "joint_a negative");
    pair_make(&p, RJ_LINK_RIGID, 100, 0);
    p.cable.joint_b = 0;
    refuse(c, &p, "couplings[0].joint_b", "joint_b == joint_a");
    pair_make(&p, RJ_LINK_RIGID, -100, 0);
    refuse(c, &p, "couplings[0].stiffness", "negative stiffness");
    pair_make(&p, RJ_LINK_RIGID, 100, -1);
    refuse(c, &p, "couplings[0].damping", "negative damping");
    pair_make(&p, RJ_LINK_RIGID, 100, 0);
    p.cable.ratio = nan("");
    refuse(c, &p, "couplings[0].ratio", "NaN ratio");
    pair_make(&p, RJ_LINK_RIGID, 100, 0);
    p.cable.offset = INFINITY;
    refuse(c, &p, "couplings[0].offset", "infinite offset");
    pair_make(&p, RJ_LINK_RIGID, 100, 0);
    memset(&p.cable, 0, sizeof p.cable);
    p.cable.joint_b = 1;
    refuse(c, &p, "couplings[0]", "undefaulted struct");
    pair_make(&p, RJ_LINK_RIGID, 100, 0);
    p.scene.couplings = NULL;
    refuse(c, &p, "coupling_count", "coupling_count 1 with no array");
}

/* ------------------------------------------------------------------ 6: scene files */

/* Three flexible panels, two loops (one damped, one with an offset). */
static const char SCENE_HEAD[] =
    "solver\n  dt = 0\n"
    "link p1\n  length = 1  elements = 3  rho = 1000  width = 0.1  height = 0.01\n"
    "link p2\n  length = 1  elements = 3  rho = 1000  width = 0.1  height = 0.01\n"
    "link p3\n  length = 1  elements = 3  rho = 1000  width = 0.1  height = 0.01\n"
    "joint h1\n  body1 = ground  body2 = p1  angle0 = 90 deg  spring = 1 240 deg\n"
    "joint h2\n  body1 = p1  body2 = p2  angle0 = 360 deg\n"
    "joint h3\n  body1 = p2  body2 = p3  angle0 = 0 deg\n";
static const char SCENE_LOOPS[] =
    "coupling c12\n  joints = h1 h2  ratio = -2  stiffness = 500  damping = 0.3\n"
    "coupling c23\n  joints = h2 h3  ratio = -1  offset = 0.5 deg  stiffness = 300\n";

/* Parses SCENE_HEAD + tail; the result code, err filled. */
static rj_result parse_with(const char *tail, rj_scene_file *f, rj_error *err)
{
    char text[2048];
    snprintf(text, sizeof text, "%s%s", SCENE_HEAD, tail);
    return rj_scene_parse(text, strlen(text), "couple.rjs", f, err);
}

/* 2000 steps of a scene; every node and joint record into out (5 per node, 3 per
   joint); the count, or 0 when it fails. */
static size_t run_scene(const rj_scene_file *f, double *out, size_t cap)
{
    rj_scene_def d = rj_scene_file_def(f);
    rj_model *m;
    rj_state *s;
    size_t n = 0;
    int l, k, j, ok = 1;
    if (rj_model_create(&d, &m, NULL, NULL) != RJ_OK)
        return 0;
    if (rj_state_create(m, &s, NULL) != RJ_OK) {
        rj_model_destroy(m, NULL);
        return 0;
    }
    for (k = 0; k < 2000 && ok; k++)
        ok = rj_step(m, s) == RJ_OK;
    for (l = 0; l < rj_model_link_count(m) && ok; l++)
        for (k = 0; k < rj_link_node_count(m, l) && n + 5 <= cap; k++) {
            rj_node_position(m, s, l, k, out + n);
            rj_node_velocity(m, s, l, k, out + n + 2);
            out[n + 4] = rj_node_rotation(m, s, l, k);
            n += 5;
        }
    for (j = 0; j < rj_model_joint_count(m) && ok && n + 3 <= cap; j++) {
        out[n++] = rj_joint_theta_running(m, s, j);
        out[n++] = rj_joint_torque(m, s, j, RJ_TORQUE_SPRING);
        out[n++] = rj_joint_torque(m, s, j, RJ_TORQUE_DAMPING);
    }
    pair_free(m, s);
    return ok ? n : 0;
}

static void test_scene_roundtrip(rjt_ctx *c)
{
    rj_scene_file f, g;
    rj_error err;
    rj_scene_def d;
    const char *ln[3], *jn[3];
    char *buf = NULL;
    double ra[200], rb[200];
    size_t len = 0, na, nb;
    int i, same_defs = 0;
    if (parse_with(SCENE_LOOPS, &f, &err) != RJ_OK) {
        rjt_check(c, 0, "scene with couplings parses", "%s", err.msg);
        return;
    }
    rjt_check(c, f.coupling_count == 2 && f.couplings[0].joint_a == 0 &&
              f.couplings[0].joint_b == 1 && f.couplings[0].ratio == -2 &&
              f.couplings[0].damping == 0.3 && f.couplings[1].joint_a == 1 &&
              f.couplings[1].joint_b == 2 && f.couplings[1].offset == 0.5 * PI / 180 &&
              strcmp(f.coupling_names[1], "c23") == 0,
              "scene with couplings parses",
              "%d couplings: %s %d-%d ratio %g k %g c %g; %s %d-%d offset %.17g rad",
              f.coupling_count, f.coupling_names[0], f.couplings[0].joint_a,
              f.couplings[0].joint_b, f.couplings[0].ratio, f.couplings[0].stiffness,
              f.couplings[0].damping, f.coupling_names[1], f.couplings[1].joint_a,
              f.couplings[1].joint_b, f.couplings[1].offset);
    d = rj_scene_file_def(&f);
    for (i = 0; i < 3; i++) {
        ln[i] = f.link_names[i];
        jn[i] = f.joint_names[i];
    }
    len = rj_scene_write(&d, ln, jn, NULL, 0);
    buf = len ? malloc(len + 1) : NULL;
    if (!buf || rj_scene_write(&d, ln, jn, buf, len + 1) != len ||
        rj_scene_parse(buf, len, "written.rjs", &g, &err) != RJ_OK) {
        rjt_check(c, 0, "couplings written back and read again", "%zu bytes: %s", len,
                  buf ? err.msg : "rj_scene_write wrote nothing");
        free(buf);
        rj_scene_file_free(&f);
        return;
    }
    same_defs = g.coupling_count == 2;
    for (i = 0; i < 2 && same_defs; i++)
        same_defs = memcmp(&f.couplings[i], &g.couplings[i], sizeof f.couplings[i]) == 0;
    na = run_scene(&f, ra, 200);
    nb = run_scene(&g, rb, 200);
    rjt_check(c, same_defs && na > 0 && na == nb && memcmp(ra, rb, na * sizeof ra[0]) == 0 &&
              strstr(buf, "joints = h1 h2") && strstr(buf, "joints = h2 h3"),
              "couplings written back and read again: the same model",
              "%zu bytes, definitions %s, %zu values after 2000 steps %s (h3 at %.17g rad)",
              len, same_defs ? "equal bit for bit" : "DIFFER", na,
              na && na == nb && !memcmp(ra, rb, na * sizeof ra[0]) ? "equal bit for bit"
                                                                   : "DIFFER",
              na ? ra[na - 3] : 0.0);
    free(buf);
    rj_scene_file_free(&f);
    rj_scene_file_free(&g);
}

static void scene_error(rjt_ctx *c, const char *tail, const char *want, const char *what)
{
    rj_scene_file f;
    rj_error err;
    rj_result res = parse_with(tail, &f, &err);
    char name[160];
    snprintf(name, sizeof name, "scene refused: %s", what);
    rjt_check(c, res == RJ_ERR_PARSE && strcmp(err.field, "joints") == 0 &&
              strstr(err.msg, want) != NULL, name, "%s, field '%s': %s",
              rj_result_str(res), res == RJ_OK ? "" : err.field,
              res == RJ_OK ? "parsed" : err.msg);
    if (res == RJ_OK)
        rj_scene_file_free(&f);
}

static void test_scene_errors(rjt_ctx *c)
{
    scene_error(c, "coupling c\n  joints = h1\n  stiffness = 10\n",
                "couple.rjs:16:14:", "joints = A (missing the second)");
    scene_error(c, "coupling c\n  joints = h1 h9\n", "h9", "unknown joint name");
    scene_error(c, "coupling c\n  joints = h2 h2\n  stiffness = 10\n", "itself",
                "a joint tied to itself");
    scene_error(c, "coupling c\n  stiffness = 10\n", "no joints", "no joints key");
}

/* An exact coupling (a constraint, no cable): the rigid pair follows the exact tie at the
   scheme's second order in dt, the stretch is 0 to round-off and the balance closes, at
   1 and 0.5 ms; flexible panels keep the stretch at 0 to round-off too. */
static double exact_tie_error(int fidelity, double dt, double *e_peak, double *balance,
                              char *msg, size_t n)
{
    pair p;
    rods r;
    rj_model *m;
    rj_state *s;
    double q = TH10, w = 0, err = 0;
    int sub, i;
    pair_make(&p, fidelity, 0, 0);
    p.cable.exact = 1;
    p.scene.solver.dt = dt;
    r = rods_of(p.link);
    *e_peak = *balance = 0;
    if (!pair_build(&p, &m, &s, msg, n))
        return -1;
    sub = (int) ceil(rj_model_dt(m) / 1e-5);
    while (rj_state_time(s) < T_END - 0.5 * rj_model_dt(m)) {
        rj_energy e;
        if (rj_step(m, s) != RJ_OK) {
            snprintf(msg, n, "rj_step: %s", rj_state_error(s));
            pair_free(m, s);
            return -1;
        }
        for (i = 0; i < sub; i++)
            exact_rk4(&r, &q, &w, rj_model_dt(m) / sub);
        err = fmax(err, fabs(rj_joint_theta_running(m, s, 0) - q));
        *e_peak = fmax(*e_peak, fabs(stretch(m, s, &p.cable)));
        rj_state_energy(m, s, &e);
        *balance = fmax(*balance, fabs(e.balance));
    }
    pair_free(m, s);
    return err;
}

static void test_exact(rjt_ctx *c)
{
    char msg[300] = "";
    double e1, e2, b1, b2, ef, bf;
    const double d1 = exact_tie_error(RJ_LINK_RIGID, 1e-3, &e1, &b1, msg, sizeof msg);
    const double d2 = exact_tie_error(RJ_LINK_RIGID, 5e-4, &e2, &b2, msg, sizeof msg);
    const double df = exact_tie_error(RJ_LINK_FLEXIBLE, 0, &ef, &bf, msg, sizeof msg);
    /* the balance as test_energy's: within 1e-4 of the spring's initial energy, falling
       as dt^2 */
    const double e0 = 0.5 * K1 * (TH10 - FREE1) * (TH10 - FREE1);
    rjt_check(c, d1 > 0 && d2 > 0 && d1 / d2 > 3.5 && d1 / d2 < 4.5 && e1 < 1e-12 &&
                     e2 < 1e-12 && b1 < 1e-4 * e0 && b2 < 0.3 * b1,
              "exact coupling, rigid pair: the exact tie at second order in dt, the stretch "
              "0 to round-off",
              "max |theta1 - exact tie| %.3g rad at dt 1 ms, %.3g at 0.5 ms (ratio %.2f); "
              "max |e| %.3g, %.3g rad; max |balance| %.3g, %.3g J of %.3g J %s",
              d1, d2, d1 / d2, e1, e2, b1, b2, e0, msg);
    rjt_check(c, df >= 0 && ef < 1e-12 && bf < 1e-6 * e0,
              "exact coupling, flexible pair: the stretch 0 to round-off, the balance closed",
              "max |e| %.3g rad, max |balance| %.3g J (theta1 within %.3g rad of the rigid "
              "tie: the panels bend) %s", ef, bf, df, msg);
}

int main(void)
{
    rjt_ctx c = { 0, 0 };
    test_tie(&c);
    test_tie_order(&c);
    test_frequency(&c);
    test_energy(&c, RJ_LINK_RIGID, 0, 1e-4, "rigid panels");
    test_energy(&c, RJ_LINK_RIGID, 5, 1e-4, "rigid panels");
    test_energy(&c, RJ_LINK_FLEXIBLE, 0, 1e-4, "flexible panels");
    test_energy(&c, RJ_LINK_FLEXIBLE, 0.5, 1e-4, "flexible panels");
    test_energy(&c, RJ_LINK_INEXTENSIBLE, 0.5, 1e-4, "inextensible panels");
    test_energy(&c, MIXED, 0.5, 1e-4, "rigid p1, flexible p2");
    test_bound(&c);
    test_bound_flexible(&c);
    test_refusals(&c);
    test_scene_roundtrip(&c);
    test_scene_errors(&c);
    test_exact(&c);
    return rjt_summary(&c, "test_couple");
}
