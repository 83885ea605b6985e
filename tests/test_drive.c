/* Actuators on joints (rj_actuator_def) against what we did not tune: a DC motor
   spinning up a rigid arm against its exact solution (and the order of the error in dt),
   the same motor deploying the arm into a latch at the closed-form time, the end-of-travel
   cutoff, a servo's static droop under gravity (P control: m g d / kp) and its clamp, a
   tabled torque on a flexible link and the energy balance; then bad actuators are refused
   naming the field, scene files read and write actuators, and W_drive is an account of
   the models with actuators only. Prescribed motion: a cycloidal stroke on a rigid arm
   under gravity takes I alpha + M1 g cos(theta) to the scheme's truncation and round-off,
   on a flexible arm (with and without a rotor) the pin follows the profile to round-off
   with the balance closed, and rj_settle holds a profile at its start. */
#include "../revjoint.h"
#include "rjt.h"
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define G 9.81
#define PI 3.14159265358979323846

/* The DC motor of checks 1-3: stall torque and no-load speed. */
#define TS 0.5
#define W0 2.0

/* An aluminium arm 1 m long, 20 mm wide, 10 mm deep in the plane. */
static rj_link_def arm(int fidelity, int elements)
{
    rj_link_def l = rj_default_link_def();
    l.length = 1.0;
    l.elements = elements;
    l.E = 70e9;
    l.rho = 2700;
    l.section = RJ_SECTION_RECT;
    l.width = 0.02;
    l.height = 0.01;
    l.fidelity = fidelity;
    return l;
}

/* First moment of mass about the root of a rigid arm, from its definition. */
static double arm_moment(const rj_link_def *l)
{
    const double rod = l->rho * l->width * l->height * l->length;
    return rod * 0.5 * l->length + l->tip_mass * l->length;
}

/* Rotary inertia about the pin: the rod's rho A L^3 / 3 and the tip's. */
static double arm_inertia(const rj_link_def *l)
{
    const double L = l->length;
    return l->rho * l->width * l->height * L * L * L / 3 +
           l->tip_mass * L * L + l->tip_inertia;
}

/* A scene of up to two links, two joints and two actuators. */
typedef struct bench {
    rj_link_def l[2];
    rj_joint_def j[2];
    rj_actuator_def a[2];
    rj_scene_def sc;
} bench;

/* One arm pinned to the ground at the origin, theta = its angle from +x, starting
   at 0 deg, and one default actuator on that joint. No gravity, no limits. */
static void one_arm(bench *b, int fidelity, int elements)
{
    b->l[0] = arm(fidelity, elements);
    b->l[1] = arm(RJ_LINK_FLEXIBLE, 10);
    b->j[0] = rj_default_joint_def();
    b->j[0].body1 = -1;
    b->j[0].body2 = 0;
    b->j[0].angle0 = 0;
    b->j[1] = rj_default_joint_def();
    b->a[0] = rj_default_actuator_def();
    b->a[1] = rj_default_actuator_def();
    b->sc = rj_default_scene_def();
    b->sc.links = b->l;
    b->sc.link_count = 1;
    b->sc.joints = b->j;
    b->sc.joint_count = 1;
    b->sc.actuators = b->a;
    b->sc.actuator_count = 1;
}

/* A DC motor (TS, W0) on joint 0. */
static void dc_motor(bench *b)
{
    b->a[0].type = RJ_ACTUATOR_DC;
    b->a[0].stall_torque = TS;
    b->a[0].no_load_speed = W0;
}

/* Builds the model and a state; on failure says why in msg. */
static int open_bench(const bench *b, rj_model **m, rj_state **s, char *msg,
                      size_t n)
{
    rj_error err;
    if (rj_model_create(&b->sc, m, &err, NULL) != RJ_OK) {
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

static void close_bench(rj_model *m, rj_state *s)
{
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
}

/* |balance| over the largest account it closes (kinetic, works, gravity). */
static double balance_ratio(const rj_energy *e)
{
    double scale = fabs(e->kinetic) + fabs(e->work_drive) + fabs(e->gravity) +
                   fabs(e->lost_limit) + fabs(e->strain) + fabs(e->spring);
    return scale > 0 ? fabs(e->balance) / scale : fabs(e->balance);
}

/* ------------------------------------------------------------------ 1: the DC motor */

/* A DC motor turning an arm of inertia I with nothing else on it:
   I w' = Ts (1 - w / w0), so w = w0 (1 - exp(-t / tau)) with tau = I w0 / Ts, and
   theta = angle0 + w0 (t - tau (1 - exp(-t / tau))). */
static double dc_rate(double t, double tau)
{
    return -W0 * expm1(-t / tau);
}

static double dc_angle(double t, double tau)
{
    return W0 * (t + tau * expm1(-t / tau));
}

/* What the step makes of it. The torque reads the rate at n - 1/2 (the one damping
   reads), so the rates w^{n+1/2} = w^{n-1/2} + dt (Ts / I) (1 - w^{n-1/2} / w0) are
   forward Euler on the half-step grid: first order. Its leading error solves
   e' = -e / tau - (dt / 2) w'' with w'' = -(w0 / tau^2) exp(-t / tau), so
   e(t) = (dt / 2) (w0 / tau^2) t exp(-t / tau) (the rate runs ahead), largest at t = tau:
   dt w0 / (2 e tau). The angle takes the midpoint rule on those rates (second order
   itself) and integrates their error: (dt w0 / 2) (1 - (1 + t / tau) exp(-t / tau)),
   growing to dt w0 / 2. */
static double pred_rate_err(double dt, double tau, double t_end)
{
    const double t = t_end < tau ? t_end : tau;
    return 0.5 * dt * W0 / (tau * tau) * t * exp(-t / tau);
}

static double pred_angle_err(double dt, double tau, double t)
{
    return 0.5 * dt * W0 * (1 - (1 + t / tau) * exp(-t / tau));
}

typedef struct dc_result {
    double dt, tau;
    double rate_err, angle_err;   /* largest |numerical - exact| over the run */
    double rate_err_t;            /* the rate against w(t) instead of w(t - dt/2) */
    double balance, work, kinetic;
    long steps;
    int ok;
} dc_result;

/* The motor on a rigid arm for t_end, rates compared at the middle of each step
   (w^{n+1/2} belongs to t - dt / 2), angles at its end. mixed: the arm is a rigid body
   of a mixed scene (a flexible link clamped beside it); dt 0 then takes the model's. */
static dc_result dc_run(double dt, double t_end, int mixed, char *msg, size_t n)
{
    bench b;
    rj_model *m;
    rj_state *s;
    rj_energy e;
    dc_result r;
    double I;
    memset(&r, 0, sizeof r);
    one_arm(&b, RJ_LINK_RIGID, 1);
    dc_motor(&b);
    if (mixed) {
        b.l[1].root = RJ_ROOT_CLAMPED;
        b.l[1].y = 2;
        b.sc.link_count = 2;
    }
    b.sc.solver.dt = dt;
    I = arm_inertia(&b.l[0]);
    r.tau = I * W0 / TS;
    if (!open_bench(&b, &m, &s, msg, n))
        return r;
    r.dt = rj_model_dt(m);
    while (rj_state_time(s) < t_end - 0.5 * r.dt) {
        double t, ew, ewt, ea;
        if (rj_step(m, s) != RJ_OK) {
            snprintf(msg, n, "step: %s", rj_state_error(s));
            close_bench(m, s);
            return r;
        }
        t = rj_state_time(s);
        ew = fabs(rj_joint_rate(m, s, 0) - dc_rate(t - 0.5 * r.dt, r.tau));
        ewt = fabs(rj_joint_rate(m, s, 0) - dc_rate(t, r.tau));
        ea = fabs(rj_joint_theta_running(m, s, 0) - dc_angle(t, r.tau));
        if (ew > r.rate_err) r.rate_err = ew;
        if (ewt > r.rate_err_t) r.rate_err_t = ewt;
        if (ea > r.angle_err) r.angle_err = ea;
    }
    rj_state_energy(m, s, &e);
    r.balance = e.balance;
    r.work = e.work_drive;
    r.kinetic = e.kinetic;
    r.steps = rj_state_steps(s);
    r.ok = 1;
    close_bench(m, s);
    return r;
}

static void test_dc_exact(rjt_ctx *c)
{
    static const double dts[3] = { 1e-3, 1e-4, 1e-5 };
    const double t_end = 2.0;
    dc_result r[3];
    char msg[600] = "", name[240];
    int k;
    for (k = 0; k < 3; k++) {
        double pr, pa;
        r[k] = dc_run(dts[k], t_end, 0, msg, sizeof msg);
        snprintf(name, sizeof name,
                 "DC motor on a rigid arm, dt %g: errors against the exact "
                 "spin-up are the first-order ones the lagged rate predicts",
                 dts[k]);
        if (!r[k].ok) {
            rjt_check(c, 0, name, "%s", msg);
            return;
        }
        pr = pred_rate_err(dts[k], r[k].tau, t_end);
        pa = pred_angle_err(dts[k], r[k].tau, t_end);
        rjt_check(c, fabs(r[k].rate_err / pr - 1) < 0.05 &&
                      fabs(r[k].angle_err / pa - 1) < 0.05,
                  name,
                  "tau %.6g s, %ld steps: max rate error %.4g rad/s "
                  "(predicted dt w0 / (2 e tau) %.4g, ratio %.4f; against w(t) "
                  "rather than w(t - dt/2): %.4g), max angle error %.4g rad "
                  "(predicted %.4g, ratio %.4f), both within 5%%",
                  r[k].tau, r[k].steps, r[k].rate_err, pr, r[k].rate_err / pr,
                  r[k].rate_err_t, r[k].angle_err, pa, r[k].angle_err / pa);
    }
    for (k = 0; k < 2; k++) {
        const double qr = r[k].rate_err / r[k + 1].rate_err;
        const double qa = r[k].angle_err / r[k + 1].angle_err;
        snprintf(name, sizeof name,
                 "DC motor on a rigid arm: errors shrink 10x per 10x dt "
                 "(first order), dt %g -> %g", dts[k], dts[k + 1]);
        rjt_check(c, qr > 9 && qr < 11 && qa > 9 && qa < 11, name,
                  "rate error ratio %.4f, angle error ratio %.4f (each in (9, 11))",
                  qr, qa);
    }
    rjt_check(c, r[2].angle_err < 1e-5,
              "DC motor on a rigid arm, dt 1e-5: angle error below 1e-5 rad",
              "max |theta - exact| %.4g rad over %.1f s (end value %.4g rad "
              "predicted by dt w0 / 2 (1 - (1 + t/tau) exp(-t/tau)))",
              r[2].angle_err, t_end, pred_angle_err(1e-5, r[2].tau, t_end));
    for (k = 0; k < 3; k++) {
        /* the kinetic account is the pair's 1/2 I w^{n-1/2} w^{n+1/2}; from rest it
           starts at -1/2 I (w^{1/2})^2 (w^{-1/2} = -w^{1/2}), which the balance keeps
           as the initial energy */
        snprintf(name, sizeof name,
                 "DC motor on a rigid arm, dt %g: the balance closes with W_drive",
                 dts[k]);
        rjt_check(c, fabs(r[k].balance) <= 1e-12 * r[k].work, name,
                  "W_drive %.15g J, kinetic %.15g J, balance %.3g J (within 1e-12 "
                  "of W_drive)", r[k].work, r[k].kinetic, r[k].balance);
    }
}

/* The same motor on a rigid body of a mixed scene (a flexible link clamped beside it
   sets the step): the same exact solution, the same first-order error. */
static void test_dc_mixed(rjt_ctx *c)
{
    char msg[600] = "";
    dc_result r = dc_run(0, 2.0, 1, msg, sizeof msg);
    double pa, pr;
    if (!r.ok) {
        rjt_check(c, 0, "DC motor on a rigid body of a mixed scene", "%s", msg);
        return;
    }
    pr = pred_rate_err(r.dt, r.tau, 2.0);
    pa = pred_angle_err(r.dt, r.tau, 2.0);
    rjt_check(c, r.rate_err < 1.1 * pr && r.angle_err < 1.1 * pa &&
                  fabs(r.balance) <= 1e-9 * r.work,
              "DC motor on a rigid body of a mixed scene: within the first-order "
              "error of the exact spin-up, the balance closes",
              "dt %.4g s (the flexible link's), %ld steps: max rate error %.4g rad/s "
              "(first-order prediction %.4g), max angle error %.4g rad (%.4g), "
              "W_drive %.12g J, balance %.3g J",
              r.dt, r.steps, r.rate_err, pr, r.angle_err, pa, r.work, r.balance);
}

/* ------------------------------------------------------------------ 2: into a latch */

/* The time the exact spin-up reaches angle a (Newton on dc_angle, increasing). */
static double dc_time_at(double a, double tau)
{
    double t = a / W0 + tau;
    int k;
    for (k = 0; k < 60; k++) {
        const double w = dc_rate(t, tau);
        const double dt = (dc_angle(t, tau) - a) / w;
        t -= dt;
        if (fabs(dt) < 1e-15 * t)
            break;
    }
    return t;
}

/* The motor deploys the arm into a latch at 90 deg (forward limit, lock = yes) with
   the adaptive method, or the momentum method (restitution 0: a plastic latch).
   The joint's event time is the start of the first step whose angle is at or past the
   limit (the element reads theta^n), so it is the first multiple of dt at or after the
   numerical angle's crossing; that angle leads the exact one by the first-order
   d = pred_angle_err, so it crosses d / w* earlier (w* the rate there): the event lies in
   [t* - d / w*, t* - d / w* + dt], taken with 5% on d.
   After the lock: the adaptive latch is a spring of I / dt^2 (Eq 21) that nothing but
   the motor's slope damps, so the arm rings in it within its peak penetration; the
   plastic latch stops it dead, the motor stalls at Ts and the latch holds it, impulse
   -Ts dt per step, and W_drive stops moving. */
static void test_latch(rjt_ctx *c, int method, double dt)
{
    bench b;
    rj_model *m;
    rj_state *s;
    rj_energy e;
    const double fwd = 0.5 * PI;
    const int adaptive = method == RJ_METHOD_ADAPTIVE;
    const char *what = adaptive ? "adaptive" : "momentum, e = 0";
    double tau, ts, ws, lead, lo, hi, ev, drive, imp, rate, pen, off, w_lock, e0;
    char msg[600] = "", name[240];
    int flag, ok;
    one_arm(&b, RJ_LINK_RIGID, 1);
    dc_motor(&b);
    b.j[0].has_forward = 1;
    b.j[0].forward = fwd;
    b.j[0].lock = 1;
    b.j[0].method = method;
    b.sc.solver.dt = dt;
    tau = arm_inertia(&b.l[0]) * W0 / TS;
    snprintf(name, sizeof name,
             "DC motor deploys a rigid arm into a latch at 90 deg (%s), dt %g: "
             "locks at the closed-form time", what, dt);
    if (!open_bench(&b, &m, &s, msg, sizeof msg)) {
        rjt_check(c, 0, name, "%s", msg);
        return;
    }
    ok = rj_run(m, s, 4.0, 0, NULL, NULL) == RJ_OK;
    ts = dc_time_at(fwd, tau);
    ws = dc_rate(ts, tau);
    lead = pred_angle_err(dt, tau, ts) / ws;
    lo = ts - 1.05 * lead;
    hi = ts - 0.95 * lead + dt;
    ev = rj_joint_event_time(m, s, 0);
    rjt_check(c, ok && ev >= lo && ev <= hi, name,
              "event %.9g s, exact crossing t* %.9g s (rate there %.6g rad/s); "
              "event - t* = %.4g s, window [%.4g, %.4g] (lead %.3g s, dt %g) %s",
              ev, ts, ws, ev - ts, lo - ts, hi - ts, lead, dt, rj_state_error(s));
    flag = rj_joint_flag(m, s, 0);
    drive = rj_joint_torque(m, s, 0, RJ_TORQUE_DRIVE);
    imp = rj_joint_latch_impulse(m, s, 0);
    rate = rj_joint_rate(m, s, 0);
    pen = rj_joint_peak_penetration(m, s, 0);
    off = rj_joint_theta_running(m, s, 0) - fwd;
    rj_state_energy(m, s, &e);
    w_lock = dc_rate(ev, tau);
    /* from rest the kinetic account starts at -1/2 I (w^{1/2})^2, w^{1/2} = dt Ts / 2I
       (dc_exact): at rest again, W_limit = W_drive less that */
    e0 = 0.125 * dt * dt * TS * TS / arm_inertia(&b.l[0]);
    if (adaptive) {
        snprintf(name, sizeof name,
                 "DC motor against an adaptive latch, dt %g: locked at 4 s, ringing "
                 "within its peak penetration, the balance closes", dt);
        rjt_check(c, ok && flag == RJ_LOCKED && fabs(off) <= pen &&
                      fabs(e.balance) <= 1e-9 * e.work_drive,
                  name,
                  "flag %d, theta - 90 deg %.3g rad (peak penetration %.3g), rate "
                  "%.3g rad/s, drive %.9g N m, limit %.6g N m; W_drive %.9g J, "
                  "W_limit %.9g J, kinetic left %.3g J of 1/2 I w*^2 %.6g J, "
                  "balance %.3g J",
                  flag, off, pen, rate, drive,
                  rj_joint_torque(m, s, 0, RJ_TORQUE_LIMIT), e.work_drive,
                  e.lost_limit, e.kinetic,
                  0.5 * arm_inertia(&b.l[0]) * ws * ws, e.balance);
    } else {
        snprintf(name, sizeof name,
                 "DC motor against a plastic latch, dt %g: at rest, the motor "
                 "stalls at Ts, the latch holds -Ts dt per step, W_limit takes "
                 "the impact", dt);
        rjt_check(c, ok && flag == RJ_LOCKED && rate == 0 && drive == TS &&
                      fabs(imp + TS * dt) <= 1e-12 * TS * dt &&
                      e.kinetic == 0 &&
                      fabs(e.lost_limit - e.work_drive + e0) <= 1e-12 * e.work_drive &&
                      fabs(e.balance) <= 1e-9 * e.work_drive,
                  name,
                  "flag %d, theta - 90 deg %.3g rad, rate %g rad/s, drive %.15g N m, "
                  "latch impulse / dt %.15g N m; kinetic %g J, W_drive %.12g J, "
                  "W_limit %.12g J = W_drive less %.4g J "
                  "(1/2 I w^2 at the event %.12g J), balance %.3g J",
                  flag, off, rate, drive, imp / dt, e.kinetic, e.work_drive,
                  e.lost_limit, e0, 0.5 * arm_inertia(&b.l[0]) * w_lock * w_lock,
                  e.balance);
    }
    close_bench(m, s);
}

/* ------------------------------------------------------------------ 3: the cutoff */

/* A DC motor with its cutoff at 45 deg and no limit, driving forward from 0 deg, or
   backward from 90 deg (stall torque and no-load speed negative: the first crossing of
   45 deg going down). The torque the step reports was taken at the angle the step
   started from: it is 0 exactly from the first step that starts at or past 45 deg, not
   before; then nothing acts on the arm and the rate holds to the bit. The coasting
   rate is the exact spin-up's at 45 deg, within the first-order rate error and one
   step's push (dt Ts / I). */
static void test_cutoff(rjt_ctx *c, int backward)
{
    bench b;
    rj_model *m;
    rj_state *s;
    rj_energy e;
    const double dt = 1e-4, cut = 0.25 * PI;
    double tau, I, w_off = 0, w_cut, tol, w_drift = 0, work_off = 0, th0;
    char msg[600] = "", name[240];
    long on_past = 0, off_before = 0, off_steps = 0, work_moved = 0;
    int ok = 1;
    one_arm(&b, RJ_LINK_RIGID, 1);
    dc_motor(&b);
    b.a[0].has_cutoff = 1;
    b.a[0].cutoff = cut;
    if (backward) {
        b.j[0].angle0 = 0.5 * PI;
        b.a[0].stall_torque = -TS;
        b.a[0].no_load_speed = -W0;
    }
    b.sc.solver.dt = dt;
    I = arm_inertia(&b.l[0]);
    tau = I * W0 / TS;
    snprintf(name, sizeof name,
             "DC motor with a cutoff at 45 deg, driving %s: off from the first step "
             "past it, then the arm coasts at a constant rate",
             backward ? "backward from 90 deg" : "forward from 0 deg");
    if (!open_bench(&b, &m, &s, msg, sizeof msg)) {
        rjt_check(c, 0, name, "%s", msg);
        return;
    }
    th0 = b.j[0].angle0;
    while (ok && rj_state_time(s) < 2.0 - 0.5 * dt) {
        const double before = rj_joint_theta_running(m, s, 0);
        const int past = backward ? before <= cut : before >= cut;
        double tq;
        rj_energy ek;
        ok = rj_step(m, s) == RJ_OK;
        tq = rj_joint_torque(m, s, 0, RJ_TORQUE_DRIVE);
        rj_state_energy(m, s, &ek);
        if (past && tq != 0) on_past++;
        if (!past && tq == 0) off_before++;
        if (!past) continue;
        if (off_steps++ == 0) {
            w_off = rj_joint_rate(m, s, 0);
            work_off = ek.work_drive;
        }
        if (fabs(rj_joint_rate(m, s, 0) - w_off) > w_drift)
            w_drift = fabs(rj_joint_rate(m, s, 0) - w_off);
        if (ek.work_drive != work_off) work_moved++;
    }
    rj_state_energy(m, s, &e);
    w_cut = dc_rate(dc_time_at(fabs(cut - th0), tau), tau);
    if (backward) w_cut = -w_cut;
    tol = pred_rate_err(dt, tau, 2.0) + dt * TS / I;
    rjt_check(c, ok && off_steps > 1000 && on_past == 0 && off_before == 0 &&
                  w_drift == 0 && work_moved == 0 && fabs(w_off - w_cut) <= tol &&
                  fabs(e.balance) <= 1e-12 * fabs(e.work_drive),
              name,
              "%ld steps off, %ld on past 45 deg, %ld off before; coasting rate "
              "%.12g rad/s, drift %.3g, exact rate at 45 deg %.12g (|diff| %.3g <= "
              "%.3g); W_drive %.12g J, moved %ld times after the cutoff; "
              "theta at 2 s %.6g deg, balance %.3g J %s",
              off_steps, on_past, off_before, w_off, w_drift, w_cut,
              fabs(w_off - w_cut), tol, e.work_drive, work_moved,
              rj_deg(rj_joint_theta_running(m, s, 0)), e.balance, rj_state_error(s));
    close_bench(m, s);
}

/* ------------------------------------------------------------------ 4: the servo */

/* A rigid arm with a 0.2 kg tip mass, pinned at the origin, starting horizontal
   (angle0 0 deg, ground_angle 0: theta is the arm's angle from +x) under gravity
   (0, -9.81), held by a servo with target 0 deg. Gravity's torque on the arm is
   -m g d cos(theta), d the centre of mass's distance from the pin, so at rest
   kp (0 - theta) = m g d cos(theta): theta* = -delta cos(theta*), delta = m g d / kp,
   the static droop of P control (delta itself to delta^3 / 2). The step's static
   equilibrium is the exact one (at rest its rate is 0), so theta after settling is
   theta* within the oscillation left: half the range over the last second. */
static void test_servo(rjt_ctx *c)
{
    bench b;
    rj_model *m;
    rj_state *s;
    rj_energy e;
    const double kp = 200, kd = 4, dt = 1e-4;
    double mgd, delta, th, lo = HUGE_VAL, hi = -HUGE_VAL, amp, tq, zeta;
    char msg[600] = "";
    int k, ok = 1;
    one_arm(&b, RJ_LINK_RIGID, 1);
    b.l[0].tip_mass = 0.2;
    b.a[0].type = RJ_ACTUATOR_SERVO;
    b.a[0].kp = kp;
    b.a[0].kd = kd;
    b.a[0].target = 0;
    b.sc.solver.gravity[1] = -G;
    b.sc.solver.dt = dt;
    mgd = G * arm_moment(&b.l[0]);
    delta = mgd / kp;
    zeta = kd / (2 * sqrt(kp * arm_inertia(&b.l[0])));
    th = -delta;
    for (k = 0; k < 50; k++)
        th -= (th + delta * cos(th)) / (1 - delta * sin(th));
    if (!open_bench(&b, &m, &s, msg, sizeof msg)) {
        rjt_check(c, 0, "servo holding an arm against gravity", "%s", msg);
        return;
    }
    ok = rj_run(m, s, 19.0, 0, NULL, NULL) == RJ_OK;
    while (ok && rj_state_time(s) < 20.0 - 0.5 * dt) {
        double q;
        ok = rj_step(m, s) == RJ_OK;
        q = rj_joint_theta_running(m, s, 0);
        if (q < lo) lo = q;
        if (q > hi) hi = q;
    }
    amp = 0.5 * (hi - lo);
    tq = rj_joint_torque(m, s, 0, RJ_TORQUE_DRIVE);
    rj_state_energy(m, s, &e);
    rjt_check(c, ok && fabs(rj_joint_theta_running(m, s, 0) - th) <= amp + 1e-13 &&
                  fabs(tq - mgd * cos(th)) <= 1e-12 * mgd,
              "servo holding a rigid arm against gravity: its droop is P control's "
              "closed form theta* = -(m g d / kp) cos(theta*)",
              "kp %g N m/rad, kd %g N m s/rad (damping ratio %.3f), m g d %.12g N m: "
              "theta at 20 s %.15g rad, theta* %.15g (m g d / kp %.15g), |diff| %.3g "
              "<= oscillation left %.3g + 1e-13; drive %.15g N m against m g d "
              "cos(theta*) %.15g; balance %.3g J %s",
              kp, kd, zeta, mgd, rj_joint_theta_running(m, s, 0), th, delta,
              fabs(rj_joint_theta_running(m, s, 0) - th), amp, tq, mgd * cos(th),
              e.balance, rj_state_error(s));
    close_bench(m, s);
}

/* The same servo with torque_max 0.8 m g d, less than gravity's pull at the start: the
   arm falls, and the drive torque saturates at torque_max and never passes it. */
static void test_servo_clamp(rjt_ctx *c)
{
    bench b;
    rj_model *m;
    rj_state *s;
    rj_energy e;
    const double dt = 1e-4;
    double mgd, cap, peak = 0, worst = 0, low = 0;
    char msg[600] = "";
    long at_cap = 0;
    int ok = 1;
    one_arm(&b, RJ_LINK_RIGID, 1);
    b.l[0].tip_mass = 0.2;
    b.a[0].type = RJ_ACTUATOR_SERVO;
    b.a[0].kp = 200;
    b.a[0].kd = 4;
    b.a[0].target = 0;
    b.sc.solver.gravity[1] = -G;
    b.sc.solver.dt = dt;
    mgd = G * arm_moment(&b.l[0]);
    cap = 0.8 * mgd;
    b.a[0].torque_max = cap;
    if (!open_bench(&b, &m, &s, msg, sizeof msg)) {
        rjt_check(c, 0, "servo torque_max", "%s", msg);
        return;
    }
    while (ok && rj_state_time(s) < 5.0 - 0.5 * dt) {
        double tq, q;
        rj_energy ek;
        ok = rj_step(m, s) == RJ_OK;
        tq = fabs(rj_joint_torque(m, s, 0, RJ_TORQUE_DRIVE));
        q = rj_joint_theta_running(m, s, 0);
        if (tq > peak) peak = tq;
        if (tq == cap) at_cap++;
        if (q < low) low = q;
        rj_state_energy(m, s, &ek);
        if (balance_ratio(&ek) > worst) worst = balance_ratio(&ek);
    }
    rj_state_energy(m, s, &e);
    rjt_check(c, ok && peak == cap && at_cap > 1000 && worst < 1e-9,
              "servo with torque_max below gravity's pull: the drive torque "
              "saturates at torque_max and never passes it, the balance closes",
              "torque_max %.15g N m, largest |drive| %.15g N m, %ld of %ld steps at "
              "the bound; the arm fell to %.4g deg (-acos(0.8) = %.4g deg is where "
              "the bound holds it); |balance| at most %.3g of the accounts; "
              "W_drive %.6g J, gravity %.6g J %s",
              cap, peak, at_cap, rj_state_steps(s), rj_deg(low),
              -rj_deg(acos(0.8)), worst, e.work_drive, e.gravity, rj_state_error(s));
    close_bench(m, s);
}

/* ------------------------------------------------------------------ 5: a torque table */

/* The table of check 5: 0 0, 0.1 1, 0.2 1, 0.3 0 (a trapezoid in time). */
static const double TAB_T[4] = { 0.0, 0.1, 0.2, 0.3 };
static const double TAB_F[4] = { 0.0, 1.0, 1.0, 0.0 };

/* The trapezoid written out. */
static double tab_factor(double t)
{
    if (t <= 0) return 0;
    if (t < 0.1) return t / 0.1;
    if (t < 0.2) return 1;
    if (t < 0.3) return (0.3 - t) / 0.1;
    return 0;
}

/* A torque actuator with the table on a flexible arm (10 elements) pinned to the
   ground: the torque reported after each step is torque x factor at the time the step
   started from (every component of the joint's torque is the one of theta^n, t^n); the
   balance closes with W_drive; W_drive is the sum of torque x the joint's turn over
   each step, and stops moving when the table has ended. */
static void test_torque_table(rjt_ctx *c)
{
    bench b;
    rj_model *m;
    rj_state *s;
    rj_energy e;
    const double T = 2.0, t_end = 0.5;
    double w_sum = 0, f_err = 0, f_err_end = 0, worst = 0, w_03 = 0;
    double tv = 0, prev = 0, wmax = 0, dt, tol;
    char msg[600] = "";
    long moved = 0;
    int ok = 1;
    one_arm(&b, RJ_LINK_FLEXIBLE, 10);
    b.a[0].type = RJ_ACTUATOR_TORQUE;
    b.a[0].torque = T;
    b.a[0].table_count = 4;
    memcpy(b.a[0].table_time, TAB_T, sizeof TAB_T);
    memcpy(b.a[0].table_factor, TAB_F, sizeof TAB_F);
    if (!open_bench(&b, &m, &s, msg, sizeof msg)) {
        rjt_check(c, 0, "torque table on a flexible arm", "%s", msg);
        return;
    }
    dt = rj_model_dt(m);
    while (ok && rj_state_time(s) < t_end - 0.5 * dt) {
        const double t0 = rj_state_time(s);
        const double q0 = rj_joint_theta_running(m, s, 0);
        double tq, d;
        rj_energy ek;
        ok = rj_step(m, s) == RJ_OK;
        tq = rj_joint_torque(m, s, 0, RJ_TORQUE_DRIVE);
        d = fabs(tq - T * tab_factor(t0));
        if (d > f_err) f_err = d;
        d = fabs(tq - T * tab_factor(rj_state_time(s)));
        if (d > f_err_end) f_err_end = d;
        w_sum += tq * (rj_joint_theta_running(m, s, 0) - q0);
        tv += fabs(tq - prev);
        prev = tq;
        if (fabs(rj_joint_rate(m, s, 0)) > wmax) wmax = fabs(rj_joint_rate(m, s, 0));
        rj_state_energy(m, s, &ek);
        if (fabs(ek.balance) > worst) worst = fabs(ek.balance);
        if (t0 > 0.3 + dt) {
            if (w_03 == 0) w_03 = ek.work_drive;
            if (ek.work_drive != w_03) moved++;
        }
    }
    rj_state_energy(m, s, &e);
    rjt_check(c, ok && f_err <= 1e-13 * T,
              "torque actuator with a table on a flexible arm: the drive torque "
              "is torque x factor(t) at the start of each step",
              "dt %.4g s, %ld steps: largest |drive - %g factor(t^n)| %.3g N m "
              "(within 1e-13 of the torque); against factor at the step's end it "
              "would be %.3g N m",
              dt, rj_state_steps(s), T, f_err, f_err_end);
    /* two quadratures of the same integral of torque d(theta): the library's
       dt/2 sum tau^n (w^{n-1/2} + w^{n+1/2}) (in the form that closes the balance)
       and sum tau^n (theta^{n+1} - theta^n) = dt sum tau^n w^{n+1/2} differ by
       dt/2 sum tau^n (w^{n+1/2} - w^{n-1/2}), which by parts (the torque is 0 at both
       ends) is -dt/2 sum w (tau^{n+1} - tau^n): at most dt/2 x the torque's total
       variation x the largest rate. (Measured: the difference halves with dt.) */
    tol = 0.5 * dt * tv * wmax + 1e-12;
    rjt_check(c, ok && fabs(e.work_drive - w_sum) <= tol &&
                  worst < 1e-6 * e.work_drive && moved == 0 && e.work_drive > 0,
              "torque actuator with a table on a flexible arm: W_drive is the "
              "integral of torque x rate and closes the balance",
              "W_drive %.12g J, sum of torque x turn %.12g J, |diff| %.3g <= dt/2 x "
              "total variation %.4g N m x largest rate %.4g rad/s = %.3g; "
              "largest |balance| %.3g J (within 1e-6 of W_drive), at 0.5 s "
              "%.3g J; strain %.4g J, kinetic %.6g J; W_drive moved %ld times "
              "after the table ended",
              e.work_drive, w_sum, fabs(e.work_drive - w_sum), tv, wmax, tol, worst,
              e.balance, e.strain, e.kinetic, moved);
    close_bench(m, s);
}

/* ------------------------------------------------------------------ 6: refusals */

/* Two flexible links (4 elements each): joint 0 ground -> link 0, joint 1 link 0 ->
   link 1, and the actuators given. */
static void two_links(bench *b)
{
    one_arm(b, RJ_LINK_FLEXIBLE, 4);
    b->l[1] = arm(RJ_LINK_FLEXIBLE, 4);
    b->j[1].body1 = 0;
    b->j[1].body2 = 1;
    b->sc.link_count = 2;
    b->sc.joint_count = 2;
}

/* rj_model_create refuses the scene with RJ_ERR_INVALID, err.field naming field. */
static void refuse(rjt_ctx *c, const bench *b, const char *field, const char *what)
{
    rj_model *m = NULL;
    rj_error err;
    rj_result r;
    char name[240];
    memset(&err, 0, sizeof err);
    r = rj_model_create(&b->sc, &m, &err, NULL);
    snprintf(name, sizeof name, "an actuator with %s is refused, err.field \"%s\"",
             what, field);
    rjt_check(c, r == RJ_ERR_INVALID && m == NULL && strcmp(err.field, field) == 0,
              name, "%s, field \"%s\": %s", rj_result_str(r), err.field, err.msg);
    if (m) rj_model_destroy(m, NULL);
}

static void test_refusals(rjt_ctx *c)
{
    bench b, base;
    rj_model *m = NULL;
    rj_error err;
    two_links(&base);
    dc_motor(&base);
    base.a[0].kp = NAN; /* a servo's field on a DC motor: not read, not checked */
    b = base;
    rjt_check(c, rj_model_create(&b.sc, &m, &err, NULL) == RJ_OK,
              "the refusals' scene builds (a DC motor on joint 0, its kp NaN: a "
              "servo's field, ignored)", "%s", m ? "built" : err.msg);
    if (m) rj_model_destroy(m, NULL);
    b = base; b.sc.links = b.l; b.sc.joints = b.j; b.sc.actuators = b.a;
    b.a[0].joint = 2;
    refuse(c, &b, "actuators[0].joint", "joint 2 of a two-joint scene");
    b.a[0].joint = -1;
    refuse(c, &b, "actuators[0].joint", "joint -1");
    b = base; b.sc.links = b.l; b.sc.joints = b.j; b.sc.actuators = b.a;
    b.a[1] = b.a[0];
    b.sc.actuator_count = 2;
    refuse(c, &b, "actuators[1].joint", "the joint of another actuator");
    b = base; b.sc.links = b.l; b.sc.joints = b.j; b.sc.actuators = b.a;
    b.a[0].no_load_speed = 0;
    refuse(c, &b, "actuators[0].no_load_speed", "no_load_speed 0");
    b.a[0].no_load_speed = -W0;
    refuse(c, &b, "actuators[0].no_load_speed",
           "no_load_speed of the stall torque's opposite sign");
    b.a[0].no_load_speed = W0;
    b.a[0].cutoff = 7.0;
    b.a[0].has_cutoff = 1;
    refuse(c, &b, "actuators[0].cutoff", "a cutoff of 7 rad");
    b = base; b.sc.links = b.l; b.sc.joints = b.j; b.sc.actuators = b.a;
    b.a[0].type = RJ_ACTUATOR_SERVO;
    b.a[0].kp = -1;
    refuse(c, &b, "actuators[0].kp", "kp -1");
    b.a[0].kp = 10;
    b.a[0].kd = NAN;
    refuse(c, &b, "actuators[0].kd", "a NaN kd");
    b.a[0].type = 4; /* past RJ_ACTUATOR_PRESCRIBED */
    refuse(c, &b, "actuators[0].type", "type 4");
    b.a[0].type = -1;
    refuse(c, &b, "actuators[0].type", "type -1");
    memset(&b.a[0], 0, sizeof b.a[0]);
    b.a[0].type = RJ_ACTUATOR_TORQUE;
    b.a[0].torque = 1;
    refuse(c, &b, "actuators[0]", "no rj_default_actuator_def() (the cookie)");
    b.a[0] = rj_default_actuator_def();
    b.a[0].torque = NAN;
    refuse(c, &b, "actuators[0].torque", "a NaN torque");
    b.a[0].torque = 1;
    b.a[0].table_count = 2;
    b.a[0].table_time[0] = 0.5;
    b.a[0].table_time[1] = 0.5;
    b.a[0].table_factor[0] = b.a[0].table_factor[1] = 1;
    refuse(c, &b, "actuators[0].table_time[1]", "table times not increasing");
    b = base; b.sc.links = b.l; b.sc.joints = b.j;
    b.sc.actuators = NULL;
    refuse(c, &b, "actuator_count", "actuator_count 1 and actuators NULL");
}

/* ------------------------------------------------------------------ 7: scene files */

/* Three rigid links in a chain under gravity, an actuator of each type (units as a
   person writes them: deg, deg/s). */
static const char SCENE[] =
    "title = \"three motors\"\n"
    "solver\n"
    "  dt = 1e-4  gravity = 0 -9.81\n"
    "link base\n"
    "  length = 1  elements = 1  fidelity = rigid\n"
    "  width = 0.02  height = 0.01  rho = 2700\n"
    "link mid\n"
    "  length = 0.8  elements = 1  fidelity = rigid\n"
    "  width = 0.02  height = 0.01  rho = 2700\n"
    "link tip\n"
    "  length = 0.5  elements = 1  fidelity = rigid\n"
    "  width = 0.02  height = 0.01  rho = 2700\n"
    "joint shoulder\n"
    "  body1 = ground  body2 = base  angle0 = 0 deg\n"
    "joint elbow\n"
    "  body1 = base  body2 = mid  angle0 = 180 deg  forward = 270 deg  lock = yes\n"
    "joint wrist\n"
    "  body1 = mid  body2 = tip  angle0 = 180 deg\n"
    "actuator push   # a tabled torque\n"
    "  joint = shoulder  type = torque  torque = 2\n"
    "  table = 0 0, 0.05 1, 0.1 1, 0.15 0\n"
    "actuator motor\n"
    "  joint = elbow  type = dc  stall_torque = 0.5\n"
    "  no_load_speed = 120 deg/s  cutoff = 260 deg\n"
    "actuator hold\n"
    "  joint = wrist  type = servo  kp = 50  kd = 0.5  torque_max = 3\n"
    "  target = 170 deg\n";

/* Two actuators' every field the model reads, bit for bit. */
static int same_actuator(const rj_actuator_def *a, const rj_actuator_def *b)
{
    const int n = a->table_count;
    return a->joint == b->joint && a->type == b->type && n == b->table_count &&
           memcmp(&a->torque, &b->torque, sizeof a->torque) == 0 &&
           memcmp(a->table_time, b->table_time, (size_t) n * sizeof(double)) == 0 &&
           memcmp(a->table_factor, b->table_factor, (size_t) n * sizeof(double)) == 0 &&
           memcmp(&a->stall_torque, &b->stall_torque, sizeof(double)) == 0 &&
           memcmp(&a->no_load_speed, &b->no_load_speed, sizeof(double)) == 0 &&
           a->has_cutoff == b->has_cutoff &&
           memcmp(&a->cutoff, &b->cutoff, sizeof(double)) == 0 &&
           memcmp(&a->kp, &b->kp, sizeof(double)) == 0 &&
           memcmp(&a->kd, &b->kd, sizeof(double)) == 0 &&
           memcmp(&a->torque_max, &b->torque_max, sizeof(double)) == 0 &&
           memcmp(&a->target, &b->target, sizeof(double)) == 0;
}

/* Builds the file's model and runs it 0.2 s: the ends of the three links and the
   energy accounts into pos (3 x 2 x 2 doubles) and e. */
static int run_file(const rj_scene_file *f, double *pos, rj_energy *e, char *msg,
                    size_t n)
{
    rj_scene_def d = rj_scene_file_def(f);
    rj_model *m;
    rj_state *s;
    rj_error err;
    int l, ok;
    if (rj_model_create(&d, &m, &err, NULL) != RJ_OK) {
        snprintf(msg, n, "%s", err.msg);
        return 0;
    }
    if (rj_state_create(m, &s, NULL) != RJ_OK) {
        rj_model_destroy(m, NULL);
        return 0;
    }
    ok = rj_run(m, s, 0.2, 0, NULL, NULL) == RJ_OK;
    if (!ok) snprintf(msg, n, "%s", rj_state_error(s));
    for (l = 0; l < 3; l++) {
        rj_node_position(m, s, l, 0, pos + 4 * l);
        rj_node_position(m, s, l, rj_link_node_count(m, l) - 1, pos + 4 * l + 2);
    }
    rj_state_energy(m, s, e);
    close_bench(m, s);
    return ok;
}

static void test_scene_file(rjt_ctx *c)
{
    rj_scene_file f, g;
    rj_error err;
    rj_energy e[2];
    double pos[2][12];
    char buf[8192], msg[600] = "";
    const char *ln[3], *jn[3];
    size_t n;
    int k, ok, same = 0, read;
    ok = rj_scene_parse(SCENE, sizeof SCENE - 1, "m.rjs", &f, &err) == RJ_OK;
    read = ok && f.actuator_count == 3 && f.actuators[0].type == RJ_ACTUATOR_TORQUE &&
           f.actuators[0].joint == 0 && f.actuators[0].table_count == 4 &&
           f.actuators[0].table_time[3] == 0.15 &&
           f.actuators[1].type == RJ_ACTUATOR_DC && f.actuators[1].joint == 1 &&
           f.actuators[1].no_load_speed == rj_rad(120.0) &&
           f.actuators[1].has_cutoff && f.actuators[1].cutoff == rj_rad(260.0) &&
           f.actuators[2].type == RJ_ACTUATOR_SERVO && f.actuators[2].joint == 2 &&
           f.actuators[2].target == rj_rad(170.0) && f.actuators[2].torque_max == 3 &&
           strcmp(f.actuator_names[1], "motor") == 0;
    rjt_check(c, read, "scene file: actuator sections of each type are read",
              "%s", ok ? (read ? "3 actuators as written (deg/s and deg converted "
                                 "by rj_rad)" : "values differ") : err.msg);
    if (!ok)
        return;
    for (k = 0; k < 3; k++) {
        ln[k] = f.link_names[k];
        jn[k] = f.joint_names[k];
    }
    {
        rj_scene_def d = rj_scene_file_def(&f);
        n = rj_scene_write(&d, ln, jn, buf, sizeof buf);
    }
    ok = n > 0 && n < sizeof buf &&
         rj_scene_parse(buf, n, "w.rjs", &g, &err) == RJ_OK;
    if (ok) {
        same = g.actuator_count == 3;
        for (k = 0; k < 3 && same; k++)
            same = same_actuator(&f.actuators[k], &g.actuators[k]);
    }
    rjt_check(c, ok && same,
              "scene file: actuators are written back (rj_scene_write) and read the "
              "same bits", "%s; %zu bytes", ok ? (same ? "same" : "DIFFER") : err.msg, n);
    if (ok) {
        ok = run_file(&f, pos[0], &e[0], msg, sizeof msg) &&
             run_file(&g, pos[1], &e[1], msg, sizeof msg);
        if (!ok) {
            rjt_check(c, 0, "scene file: the written scene runs the same bits",
                      "%s", msg);
        } else {
            rjt_check(c, memcmp(pos[0], pos[1], sizeof pos[0]) == 0 &&
                          memcmp(&e[0], &e[1], sizeof e[0]) == 0 &&
                          e[0].work_drive != 0,
                      "scene file: the written scene runs the same bits for 0.2 s",
                      "tip (%.15g, %.15g) / (%.15g, %.15g) m, W_drive %.15g / %.15g "
                      "J, balance %.3g J", pos[0][10], pos[0][11], pos[1][10],
                      pos[1][11], e[0].work_drive, e[1].work_drive, e[0].balance);
        }
        rj_scene_file_free(&g);
    }
    rj_scene_file_free(&f);
}

/* rj_scene_write of actuators made in C (a servo's target and a DC motor's no-load
   speed and cutoff are written in deg and deg/s where those round-trip): the text
   reads back to the same bits. */
static void test_written_units(rjt_ctx *c)
{
    bench b;
    rj_scene_file f;
    rj_error err;
    char buf[8192];
    size_t n;
    int ok, same = 0;
    two_links(&b);
    dc_motor(&b);
    b.a[0].no_load_speed = rj_rad(120.0);
    b.a[0].has_cutoff = 1;
    b.a[0].cutoff = rj_rad(80.0);
    b.a[1].joint = 1;
    b.a[1].type = RJ_ACTUATOR_SERVO;
    b.a[1].kp = 20;
    b.a[1].target = rj_rad(90.0);
    b.sc.actuator_count = 2;
    n = rj_scene_write(&b.sc, NULL, NULL, buf, sizeof buf);
    ok = n > 0 && n < sizeof buf &&
         rj_scene_parse(buf, n, "w.rjs", &f, &err) == RJ_OK;
    if (ok) {
        same = f.actuator_count == 2 && same_actuator(&f.actuators[0], &b.a[0]) &&
               same_actuator(&f.actuators[1], &b.a[1]);
        rj_scene_file_free(&f);
    }
    rjt_check(c, ok && same,
              "scene file: rj_scene_write's text for a DC motor and a servo (deg, "
              "deg/s) reads back to the same bits",
              "%s (%zu bytes)", ok ? (same ? "same" : "DIFFER") : err.msg, n);
}

/* Scene-file errors, each at its line and column (a key that does not apply at its
   value, as the parser places every "does not apply": node1, width). */
static void test_scene_errors(rjt_ctx *c)
{
    static const char head[] = "link a\n  length = 1  elements = 2\n"
                               "joint shoulder\n  body1 = ground  body2 = a\n";
    static const struct {
        const char *tail, *what, *needle[2];
    } bad[] = {
        { "actuator m\n  joint = shouldr  type = dc  stall_torque = 1\n",
          "an unknown joint name", { "m.rjs:6:11: ", "did you mean 'shoulder'" } },
        { "actuator s\n  joint = shoulder  type = servo\n  kp = 10  stall_torque = 1\n",
          "a DC motor's key in a servo", { "m.rjs:7:27: ",
                                           "does not apply to type = servo" } },
        { "actuator s\n  stall_torque = 1\n  joint = shoulder  type = servo\n",
          "a DC motor's key above type = servo", { "m.rjs:6:18: ",
                                                   "does not apply to type = servo" } },
        { "actuator m\n  type = dc  stall_torque = 1\n",
          "an actuator with no joint", { "m.rjs:5:1: ", "has no joint" } },
        { "actuator m\n  joint = shoulder  type = dc  stall_torque = 1\n"
          "actuator n\n  joint = shoulder  torque = 1\n",
          "two actuators on one joint", { "m.rjs:8:", "at most one actuator" } },
        { "actuator m\n  joint = shoulder  type = dc  stall_torque = 1\n"
          "  no_load_speed = -3\n",
          "a no-load speed against the stall torque", { "m.rjs:7:", "no_load_speed" } },
        { "actuator m\n  joint = shoulder  type = stepper\n",
          "an unknown type", { "m.rjs:6:", "type" } },
    };
    char text[1024], name[200];
    rj_scene_file f;
    rj_error err;
    size_t k;
    for (k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        int ok;
        snprintf(text, sizeof text, "%s%s", head, bad[k].tail);
        ok = rj_scene_parse(text, strlen(text), "m.rjs", &f, &err) != RJ_OK;
        snprintf(name, sizeof name, "scene file: %s is refused, located", bad[k].what);
        rjt_check(c, ok && strstr(err.msg, bad[k].needle[0]) == err.msg &&
                      strstr(err.msg, bad[k].needle[1]) != NULL,
                  name, "%s", ok ? err.msg : "accepted");
        if (!ok) rj_scene_file_free(&f);
    }
}

/* ------------------------------------------------------------------ 8: W_drive */

/* The account W_drive moves only in models with actuators. */
static void test_account(rjt_ctx *c)
{
    bench b;
    rj_model *m[2] = { NULL, NULL };
    rj_error err;
    int k, wd = -1, in[2] = { -1, -1 }, count[2] = { -1, -1 }, i;
    for (k = 0; k < rj_energy_account_count(); k++)
        if (strcmp(rj_energy_account_name(k), "W_drive") == 0) wd = k;
    for (i = 0; i < 2; i++) {
        one_arm(&b, RJ_LINK_RIGID, 1);
        dc_motor(&b);
        b.sc.actuator_count = i;
        if (i == 0) b.sc.actuators = NULL;
        if (rj_model_create(&b.sc, &m[i], &err, NULL) != RJ_OK) {
            rjt_check(c, 0, "W_drive account", "%s", err.msg);
            return;
        }
        count[i] = rj_model_actuator_count(m[i]);
        in[i] = wd >= 0 && rj_energy_account_in(m[i], wd);
        rj_model_destroy(m[i], NULL);
    }
    rjt_check(c, wd >= 0 && count[0] == 0 && !in[0] && count[1] == 1 && in[1],
              "W_drive is an account of the models with actuators only",
              "account %d is W_drive; without actuators: %d actuators, in %d; with "
              "one: %d, in %d", wd, count[0], in[0], count[1], in[1]);
}

/* A checkpoint of a state with a DC motor running resumes bit for bit in a fresh
   state (the motor's torque and work are in the frame). */
static void test_checkpoint(rjt_ctx *c)
{
    bench b;
    rj_model *m;
    rj_state *s, *s2;
    rj_energy e[2];
    unsigned char *buf;
    size_t n;
    char msg[600] = "";
    int ok;
    one_arm(&b, RJ_LINK_FLEXIBLE, 6);
    dc_motor(&b);
    b.a[0].has_cutoff = 1;
    b.a[0].cutoff = rj_rad(30.0);
    if (!open_bench(&b, &m, &s, msg, sizeof msg) ||
        rj_state_create(m, &s2, NULL) != RJ_OK) {
        rjt_check(c, 0, "checkpoint with a DC motor", "%s", msg);
        return;
    }
    rj_run(m, s, 0.3, 0, NULL, NULL);
    n = rj_state_save(m, s, NULL, 0);
    buf = (unsigned char *) malloc(n);
    ok = buf && rj_state_save(m, s, buf, n) == n &&
         rj_state_load(m, s2, buf, n, NULL) == RJ_OK;
    rj_run(m, s, 1.0, 0, NULL, NULL);
    if (ok) rj_run(m, s2, 1.0, 0, NULL, NULL);
    rj_state_energy(m, s, &e[0]);
    rj_state_energy(m, s2, &e[1]);
    rjt_check(c, ok && memcmp(&e[0], &e[1], sizeof e[0]) == 0 &&
                  rj_joint_theta_running(m, s, 0) == rj_joint_theta_running(m, s2, 0) &&
                  e[0].work_drive > 0,
              "a checkpoint taken with a DC motor running resumes bit for bit",
              "%s; theta %.15g / %.15g rad, W_drive %.15g / %.15g J",
              ok ? "loaded" : "not loaded", rj_joint_theta_running(m, s, 0),
              rj_joint_theta_running(m, s2, 0), e[0].work_drive, e[1].work_drive);
    free(buf);
    rj_state_destroy(s2, NULL);
    close_bench(m, s);
}

/* ------------------------------------------------------------------ prescribed motion */

/* A cycloidal stroke's angle and acceleration, A (x - sin(2 pi x) / 2 pi), x = tau / T. */
static double cyc_angle(double A, double T, double tau)
{
    const double x = tau / T;
    return tau <= 0 ? 0 : tau >= T ? A : A * (x - sin(2 * PI * x) / (2 * PI));
}
static double cyc_accel(double A, double T, double tau)
{
    return tau <= 0 || tau >= T ? 0 : A * 2 * PI / (T * T) * sin(2 * PI * tau / T);
}

/* A rigid arm under gravity on a cycloidal profile (90 deg in 1 s from t = 0.1 s): the
   angle is the profile's to round-off, and the drive torque at each step's start is
   I alpha + M1 g cos(theta) (M1 the arm's first moment) within the truncation and the
   round-off of the angle's second difference; the balance closes with W_drive. */
static void test_prescribed_rigid(rjt_ctx *c)
{
    const double A = PI / 2, T = 1.0, start = 0.1, dt = 5e-5;
    bench b;
    rj_model *m;
    rj_state *s;
    char msg[300] = "";
    double I, M1, worst_angle = 0, worst_torque = 0, peak = 0, bal = 0, trunc, round_off;
    long k;
    one_arm(&b, RJ_LINK_RIGID, 4);
    b.a[0].type = RJ_ACTUATOR_PRESCRIBED;
    b.a[0].profile = RJ_PROFILE_CYCLOIDAL;
    b.a[0].profile_value = A;
    b.a[0].profile_time = T;
    b.a[0].start = start;
    b.sc.solver.dt = dt;
    b.sc.solver.gravity[1] = -G;
    I = arm_inertia(&b.l[0]);
    M1 = arm_moment(&b.l[0]);
    if (!open_bench(&b, &m, &s, msg, sizeof msg)) {
        rjt_check(c, 0, "prescribed cycloidal stroke on a rigid arm", "%s", msg);
        return;
    }
    for (k = 0; k < (long) (1.5 / dt); k++) {
        const double t0 = rj_state_time(s);
        double want, got, th;
        rj_energy e;
        if (rj_step(m, s) != RJ_OK)
            break;
        th = rj_joint_theta_running(m, s, 0);
        if (fabs(th - cyc_angle(A, T, rj_state_time(s) - start)) > worst_angle)
            worst_angle = fabs(th - cyc_angle(A, T, rj_state_time(s) - start));
        want = I * cyc_accel(A, T, t0 - start) + M1 * G * cos(cyc_angle(A, T, t0 - start));
        got = rj_joint_torque(m, s, 0, RJ_TORQUE_DRIVE);
        if (fabs(want) > peak)
            peak = fabs(want);
        /* not the step that starts the stroke or the one that ends it: the profile's jerk
           jumps there, and the step's second difference of the angle is I alpha one step
           later (9e-5 N m here) */
        if (fabs(t0 - start) > 1.5 * dt && fabs(t0 - start - T) > 1.5 * dt &&
            fabs(got - want) > worst_torque)
            worst_torque = fabs(got - want);
        rj_state_energy(m, s, &e);
        if (fabs(e.balance) > bal)
            bal = fabs(e.balance);
    }
    /* the step's torque is I times the angle's second difference: off I alpha by
       I dt^2 / 12 max|theta^(4)| (truncation) and by the round-off of the angles'
       differences, 8 eps A / dt^2 times I at most */
    trunc = I * dt * dt / 12 * A * pow(2 * PI / T, 3) / T;
    round_off = I * 8 * DBL_EPSILON * A / (dt * dt);
    rjt_check(c, worst_angle < 1e-12 && worst_torque < trunc + round_off &&
                     bal < 1e-8 * M1 * G, /* of the lift's work, second order in dt */
              "prescribed cycloidal stroke on a rigid arm under gravity: angle to round-off, "
              "torque = I alpha + M1 g cos(theta) within the scheme's truncation and round-off",
              "%ld steps of %g s: max |theta - profile| %.3g rad, max |torque - exact| %.3g N m "
              "= %.2g of the peak %.6g N m (bound: truncation %.3g + round-off %.3g N m; I %.6g "
              "kg m^2), max |balance| %.3g J",
              k, dt, worst_angle, worst_torque, worst_torque / peak, peak, trunc, round_off, I,
              bal);
    close_bench(m, s);
}

/* The same stroke on a flexible arm: the pin's angle is the profile's to round-off (the
   arm bends behind it) and the balance closes; a rotor behind a gear changes neither. */
static void test_prescribed_flexible(rjt_ctx *c, double rotor)
{
    const double A = PI / 2, T = 1.0;
    bench b;
    rj_model *m;
    rj_state *s;
    char msg[300] = "", name[160];
    double worst = 0, bal = 0, work = 0, peak = 0;
    long k = 0;
    one_arm(&b, RJ_LINK_FLEXIBLE, 8);
    b.a[0].type = RJ_ACTUATOR_PRESCRIBED;
    b.a[0].profile = RJ_PROFILE_CYCLOIDAL;
    b.a[0].profile_value = A;
    b.a[0].profile_time = T;
    b.a[0].rotor_inertia = rotor;
    b.a[0].gear_ratio = 50;
    snprintf(name, sizeof name,
             "prescribed cycloidal stroke on a flexible arm%s: the pin's angle to round-off, "
             "the balance closed", rotor > 0 ? " with a rotor" : "");
    if (!open_bench(&b, &m, &s, msg, sizeof msg)) {
        rjt_check(c, 0, name, "%s", msg);
        return;
    }
    while (rj_state_time(s) < 1.5) {
        rj_energy e;
        double d;
        if (rj_step(m, s) != RJ_OK)
            break;
        d = fabs(rj_joint_theta_running(m, s, 0) - cyc_angle(A, T, rj_state_time(s)));
        if (d > worst)
            worst = d;
        rj_state_energy(m, s, &e);
        if (fabs(e.balance) > bal)
            bal = fabs(e.balance);
        if (e.work_drive > peak)
            peak = e.work_drive;
        work = e.work_drive;
        k++;
    }
    rjt_check(c, rj_state_time(s) >= 1.5 && worst < 1e-12 && bal < 1e-7 * peak, name,
              "%ld steps to t = %.4g s: max |theta - profile| %.3g rad, max |balance| %.3g J "
              "(W_drive peak %.6g J, at the end %.3g J: the stroke gives back what it put in "
              "but the arm's ringing)",
              k, rj_state_time(s), worst, bal, peak, work);
    close_bench(m, s);
}

/* rj_settle holds a prescribed joint at its start: a ramp that would turn the arm at
   1 rad/s leaves it at angle0 while the arm settles under gravity. */
static void test_prescribed_settle(rjt_ctx *c)
{
    bench b;
    rj_model *m;
    rj_state *s;
    char msg[300] = "";
    rj_result r;
    one_arm(&b, RJ_LINK_FLEXIBLE, 4);
    b.a[0].type = RJ_ACTUATOR_PRESCRIBED;
    b.a[0].profile = RJ_PROFILE_RAMP;
    b.a[0].profile_value = 1.0;
    b.sc.solver.gravity[1] = -G;
    if (!open_bench(&b, &m, &s, msg, sizeof msg)) {
        rjt_check(c, 0, "rj_settle holds a prescribed joint at its start", "%s", msg);
        return;
    }
    r = rj_settle(m, s, 1e-10, 2000000);
    rjt_check(c, r == RJ_OK && fabs(rj_joint_theta_running(m, s, 0)) < 1e-12,
              "rj_settle holds a prescribed joint at its start",
              "result %d at t = %.4g s, theta %.3g rad (angle0 0)", (int) r, rj_state_time(s),
              rj_joint_theta_running(m, s, 0));
    close_bench(m, s);
}

/* The spin-up beam of Simo and Vu-Quoc (1986): 10 m, EA 2.8e7 N, EI 1.4e4 N m^2,
   rho A 1.2 kg/m, clamped to a hub spun up to OMEGA = 4 rad/s in 15 s. The tip's
   deflection in the rotating frame over 20 s, at elements: its peak and when, and the
   largest after the spin-up. */
typedef struct spin_result {
    double peak, t_peak, after;
    int ok;
} spin_result;

static spin_result spin_run(int elements)
{
    bench b;
    rj_model *m;
    rj_state *s;
    char msg[200];
    spin_result r = { 0, 0, 0, 0 };
    one_arm(&b, RJ_LINK_FLEXIBLE, elements);
    b.l[0].length = 10;
    b.l[0].E = 2.8e11;
    b.l[0].rho = 12000;
    b.l[0].section = RJ_SECTION_GENERAL;
    b.l[0].area = 1e-4;
    b.l[0].inertia = 5e-8;
    b.a[0].type = RJ_ACTUATOR_PRESCRIBED;
    b.a[0].profile = RJ_PROFILE_SPINUP;
    b.a[0].profile_value = 4;
    b.a[0].profile_time = 15;
    if (!open_bench(&b, &m, &s, msg, sizeof msg))
        return r;
    while (rj_state_time(s) < 20) {
        double tip[2], th, d;
        if (rj_step(m, s) != RJ_OK) {
            close_bench(m, s);
            return r;
        }
        rj_node_position(m, s, 0, elements, tip);
        th = rj_joint_theta_running(m, s, 0);
        d = -tip[0] * sin(th) + tip[1] * cos(th);
        if (fabs(d) > fabs(r.peak)) {
            r.peak = d;
            r.t_peak = rj_state_time(s);
        }
        if (rj_state_time(s) > 16 && fabs(d) > r.after)
            r.after = fabs(d);
    }
    r.ok = 1;
    close_bench(m, s);
    return r;
}

/* The spin-up: the tip lags (negative), peaking near the largest angular acceleration at
   7.5 s at about the quasi-static 11 rho A alpha L^5 / (120 EI) = 0.417 m, on meshes of 8
   and 16 elements that agree within 2 %, and stays within 2 cm after the spin-up: the
   co-rotational element keeps the geometric stiffening that a linear floating frame
   lacks. */
static void test_spinup(rjt_ctx *c)
{
    const spin_result a = spin_run(8), b = spin_run(16);
    const double alpha = 2 * 4.0 / 15, quasi = 11 * 1.2 * alpha * 1e5 / (120 * 1.4e4);
    rjt_check(c, a.ok && b.ok && b.peak < 0 && fabs(b.peak / quasi + 1) < 0.1 &&
                     fabs(a.peak / b.peak - 1) < 0.02 && fabs(b.t_peak - 7.5) < 1 &&
                     b.after < 0.02,
              "spin-up beam (Simo and Vu-Quoc): the tip lags to the quasi-static deflection "
              "and stays near 0 after, on converged meshes",
              "peak %.5f m at %.3f s (8 elements: %.5f m at %.3f s); quasi-static at the peak "
              "acceleration %.4f m; largest after 16 s %.4f m (8 elements %.4f m)",
              b.peak, b.t_peak, a.peak, a.t_peak, -quasi, b.after, a.after);
}

/* examples/scenes/servo_arm.rjs: a servo with a geared rotor swings a flexible arm along
   a cycloidal target to 60 deg and settles on it, feeding back the joint's own rate; its
   automatic step is the links' (without the rotor the derivative gain on the pin node's
   small inertia takes it down). */
static void test_servo_arm(rjt_ctx *c)
{
    rj_scene_file f;
    rj_scene_def sc;
    rj_model *m = NULL, *m0 = NULL;
    rj_state *s;
    rj_error err;
    rj_actuator_def bare;
    double dt_rotor = 0, dt_bare = 0, worst = 0;
    if (rj_scene_load("examples/scenes/servo_arm.rjs", &f, &err) != RJ_OK) {
        rjt_check(c, 0, "servo_arm.rjs: a servo with a rotor settles on its target", "%s",
                  err.msg);
        return;
    }
    sc = rj_scene_file_def(&f);
    if (rj_model_create(&sc, &m, &err, NULL) == RJ_OK && rj_state_create(m, &s, NULL) == RJ_OK) {
        dt_rotor = rj_model_dt(m);
        while (rj_state_time(s) < 3 && rj_step(m, s) == RJ_OK)
            if (rj_state_time(s) > 2.5 &&
                fabs(rj_joint_theta_running(m, s, 0) - PI / 3) > worst)
                worst = fabs(rj_joint_theta_running(m, s, 0) - PI / 3);
        rjt_check(c, rj_state_time(s) >= 3 && worst < 1e-5,
                  "servo_arm.rjs: a servo with a rotor swings a flexible arm to 60 deg and "
                  "settles on it with the joint's own rate fed back",
                  "t %.4g s, max |theta - 60 deg| after 2.5 s %.3g rad, dt %.4g s",
                  rj_state_time(s), worst, dt_rotor);
        rj_state_destroy(s, NULL);
    }
    bare = f.actuators[0];
    f.actuators[0].rotor_inertia = 0;
    if (rj_model_create(&sc, &m0, &err, NULL) == RJ_OK)
        dt_bare = rj_model_dt(m0);
    f.actuators[0] = bare;
    rjt_check(c, m && dt_bare > 0 && dt_rotor > 2 * dt_bare,
              "servo_arm.rjs: the rotor keeps the automatic step (the derivative gain acts "
              "on the pin node's inertia without it)",
              "dt %.4g s with the rotor, %.4g s without", dt_rotor, dt_bare);
    rj_model_destroy(m, NULL);
    rj_model_destroy(m0, NULL);
    rj_scene_file_free(&f);
}

/* A prescribed table (0 0, 0.5 0.3, 1 1.2, 1.5 pi/2 rad) on a rigid arm: the angle passes
   through every point to round-off and is held after the last, the spline's rate and
   acceleration (the drive torque over I) are continuous across the points (no jump beyond
   the step's own change), and a ramp from rest (a rate jump at t = 0) closes its balance
   from the first step. */
static void test_prescribed_table(rjt_ctx *c)
{
    static const double tt[4] = { 0, 0.5, 1.0, 1.5 }, ta[4] = { 0, 0.3, 1.2, PI / 2 };
    const double dt = 1e-4;
    bench b;
    rj_model *m;
    rj_state *s;
    char msg[300] = "";
    double worst_point = 0, jump = 0, last_tq = 0, bal = 0, held = 0;
    int k, step = 0;
    one_arm(&b, RJ_LINK_RIGID, 4);
    b.a[0].type = RJ_ACTUATOR_PRESCRIBED;
    b.a[0].profile = RJ_PROFILE_TABLE;
    b.a[0].table_count = 4;
    for (k = 0; k < 4; k++) {
        b.a[0].table_time[k] = tt[k];
        b.a[0].table_factor[k] = ta[k];
    }
    b.sc.solver.dt = dt;
    if (!open_bench(&b, &m, &s, msg, sizeof msg)) {
        rjt_check(c, 0, "a prescribed table on a rigid arm", "%s", msg);
        return;
    }
    while (rj_state_time(s) < 2 - 0.5 * dt && rj_step(m, s) == RJ_OK) {
        const double t = rj_state_time(s), tq = rj_joint_torque(m, s, 0, RJ_TORQUE_DRIVE);
        rj_energy e;
        for (k = 0; k < 4; k++)
            if (fabs(t - tt[k]) < 0.5 * dt)
                worst_point = fmax(worst_point, fabs(rj_joint_theta_running(m, s, 0) - ta[k]));
        if (t > 1.5 + dt)
            held = fmax(held, fabs(rj_joint_theta_running(m, s, 0) - ta[3]));
        if (step > 1 && t < 1.5 - dt)
            jump = fmax(jump, fabs(tq - last_tq));
        last_tq = tq;
        rj_state_energy(m, s, &e);
        bal = fmax(bal, fabs(e.balance));
        step++;
    }
    rjt_check(c, rj_state_time(s) > 2 - dt && worst_point < 1e-12 && held < 1e-12 &&
                     jump < 1e-2 && bal < 1e-9,
              "a prescribed table on a rigid arm: through its points, held after, rate and "
              "acceleration continuous, the balance closed",
              "%d steps: max |theta - point| %.3g rad, after the last %.3g rad; largest "
              "change of the drive torque between steps %.3g N m (a jump in acceleration "
              "would show I x its size); max |balance| %.3g J",
              step, worst_point, held, jump, bal);
    close_bench(m, s);
    /* a profile that starts at a rate: the impulse at t = 0 is the drive's */
    one_arm(&b, RJ_LINK_RIGID, 4);
    b.a[0].type = RJ_ACTUATOR_PRESCRIBED;
    b.a[0].profile_value = 1.0;
    b.sc.solver.dt = dt;
    bal = 0;
    if (!open_bench(&b, &m, &s, msg, sizeof msg))
        return;
    while (rj_state_time(s) < 0.5 && rj_step(m, s) == RJ_OK) {
        rj_energy e;
        rj_state_energy(m, s, &e);
        bal = fmax(bal, fabs(e.balance));
    }
    {
        rj_energy e;
        rj_state_energy(m, s, &e);
        rjt_check(c, rj_state_time(s) >= 0.5 && bal < 1e-12 &&
                         fabs(e.work_drive - 0.5 * arm_inertia(&b.l[0])) < 1e-12,
                  "a ramp from rest on a rigid arm: the start's impulse is the drive's work, "
                  "1/2 I w^2, and the balance closes from the first step",
                  "t %.4g s, W_drive %.15g J against 1/2 I w^2 = %.15g J, max |balance| "
                  "%.3g J", rj_state_time(s), e.work_drive, 0.5 * arm_inertia(&b.l[0]), bal);
    }
    close_bench(m, s);
}

int main(void)
{
    rjt_ctx c = { 0, 0 };
    test_dc_exact(&c);
    test_dc_mixed(&c);
    test_latch(&c, RJ_METHOD_ADAPTIVE, 1e-4);
    test_latch(&c, RJ_METHOD_ADAPTIVE, 1e-5);
    test_latch(&c, RJ_METHOD_MOMENTUM, 1e-4);
    test_cutoff(&c, 0);
    test_cutoff(&c, 1);
    test_servo(&c);
    test_servo_clamp(&c);
    test_torque_table(&c);
    test_refusals(&c);
    test_scene_file(&c);
    test_written_units(&c);
    test_scene_errors(&c);
    test_account(&c);
    test_checkpoint(&c);
    test_prescribed_rigid(&c);
    test_prescribed_flexible(&c, 0);
    test_prescribed_flexible(&c, 1e-4);
    test_prescribed_settle(&c);
    test_spinup(&c);
    test_servo_arm(&c);
    test_prescribed_table(&c);
    return rjt_summary(&c, "test_drive");
}
