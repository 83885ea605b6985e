/* Loads: gravity on every link model, against what we did not tune: the pendulum's exact
   period (complete elliptic integral), the free fall's parabola, beam theory's sag of a
   cantilever, and the energy balance. */
#include "../revjoint.h"
#include "rjt.h"
#include <math.h>
#include "rjt_loads.h"
#include <string.h>
#include <stdlib.h>

#define G 9.81
#define PI 3.14159265358979323846

/* An aluminium bar 1 m long, 20 x 10 mm. */
static rj_link_def bar(int fidelity, int elements)
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

/* The scene of a bar clamped horizontal at the origin under gravity (l outlives sc). */
static void cantilever_scene(rj_link_def *l, rj_scene_def *sc)
{
    l->root = RJ_ROOT_CLAMPED;
    sc->links = l;
    sc->link_count = 1;
    sc->solver.gravity[1] = -G;
}



/* A bar pinned at the origin, released from rest at 150 deg from the downward vertical:
   its period against 4 sqrt(I / (m g d)) K(sin(75 deg)) with the model's own lumped I and
   m d (for rigid links the continuous rod's). */
static void test_pendulum(rjt_ctx *c, int fidelity, int elements, double dt, double tol,
                          const char *what)
{
    const double amplitude = 150.0 * PI / 180.0;
    rj_link_def l = bar(fidelity, elements);
    rj_joint_def j = rj_default_joint_def();
    rj_scene_def sc = rj_default_scene_def();
    rj_model *m;
    rj_state *s;
    rj_error err;
    swing w;
    double mass, moment, inertia, exact, period;
    char name[200];
    j.body1 = -1;
    j.body2 = 0;
    j.angle0 = amplitude - 0.5 * PI;
    sc.links = &l;
    sc.link_count = 1;
    sc.joints = &j;
    sc.joint_count = 1;
    sc.solver.dt = dt;
    sc.solver.gravity[1] = -G;
    snprintf(name, sizeof name, "pendulum from 150 deg, %s: period against the elliptic integral", what);
    if (rj_model_create(&sc, &m, &err, NULL) != RJ_OK) {
        rjt_check(c, 0, name, "%s", err.msg);
        return;
    }
    rj_state_create(m, &s, NULL);
    lumped_body(m, s, 0, &mass, &moment, &inertia);
    if (fidelity == RJ_LINK_RIGID) {
        const double rod = l.rho * l.width * l.height * l.length;
        mass = rod;
        moment = rod * l.length / 2;
        inertia = rod * l.length * l.length / 3;
    }
    exact = 4.0 * sqrt(inertia / (moment * G)) * elliptic_k(sin(0.5 * amplitude));
    memset(&w, 0, sizeof w);
    w.phi_prev = amplitude;
    if (rj_run(m, s, 2.2 * exact, 0, swing_sample, &w) != RJ_OK || w.crossings < 2) {
        rjt_check(c, 0, name, "%s (%d crossings)", rj_state_error(s), w.crossings);
    } else {
        rj_energy e;
        period = w.crossing[1] - w.crossing[0];
        rjt_check(c, fabs(period / exact - 1) < tol, name, "%.7f s against %.7f s (%+.2e; within %.0e), dt %.3g s",
                  period, exact, period / exact - 1, tol, rj_model_dt(m));
        rj_state_energy(m, s, &e);
        snprintf(name, sizeof name, "pendulum, %s: the energy balance with gravity closes", what);
        rjt_check(c, fabs(e.balance) < 1e-6 * (fabs(e.gravity) + e.kinetic) && e.gravity != 0, name,
                  "balance %.3g J (within 1e-6 of %.4g J), gravity's potential %.6g J, kinetic %.6g J",
                  e.balance, fabs(e.gravity) + e.kinetic, e.gravity, e.kinetic);
    }
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
}

/* The same pendulum as a rigid body in a mixed scene (a free flexible bar beside it makes
   the scene mixed): the body's update takes gravity at its centre. */
static void test_mixed_pendulum(rjt_ctx *c)
{
    const double amplitude = 150.0 * PI / 180.0;
    rj_link_def l[2];
    rj_joint_def j = rj_default_joint_def();
    rj_scene_def sc = rj_default_scene_def();
    rj_model *m;
    rj_state *s;
    rj_error err;
    swing w;
    double rod, exact, period;
    const char *name = "pendulum from 150 deg, rigid body in a mixed scene: period against the elliptic integral";
    l[0] = bar(RJ_LINK_RIGID, 1);
    l[1] = bar(RJ_LINK_FLEXIBLE, 4);
    l[1].x = 5.0;
    j.body1 = -1;
    j.body2 = 0;
    j.angle0 = amplitude - 0.5 * PI;
    sc.links = l;
    sc.link_count = 2;
    sc.joints = &j;
    sc.joint_count = 1;
    sc.solver.gravity[1] = -G;
    if (rj_model_create(&sc, &m, &err, NULL) != RJ_OK) {
        rjt_check(c, 0, name, "%s", err.msg);
        return;
    }
    rj_state_create(m, &s, NULL);
    rod = l[0].rho * l[0].width * l[0].height * l[0].length;
    exact = 4.0 * sqrt(rod * l[0].length * l[0].length / 3 / (rod * l[0].length / 2 * G)) *
            elliptic_k(sin(0.5 * amplitude));
    memset(&w, 0, sizeof w);
    w.phi_prev = amplitude;
    if (rj_run(m, s, 2.2 * exact, 0, swing_sample, &w) != RJ_OK || w.crossings < 2) {
        rjt_check(c, 0, name, "%s (%d crossings)", rj_state_error(s), w.crossings);
    } else {
        period = w.crossing[1] - w.crossing[0];
        rjt_check(c, fabs(period / exact - 1) < 1e-4, name, "%.7f s against %.7f s (%+.2e), dt %.3g s", period,
                  exact, period / exact - 1, rj_model_dt(m));
    }
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
}

/* A free bar thrown with a spin: its centre of mass on the exact parabola, its chord
   turning uniformly. */
static void test_free_flight(rjt_ctx *c)
{
    rj_link_def l = bar(RJ_LINK_FLEXIBLE, 8);
    rj_scene_def sc = rj_default_scene_def();
    rj_model *m;
    rj_state *s;
    rj_error err;
    double c0[2] = { 0, 0 }, v0[2] = { 0, 0 }, total = 0, worst = 0, worst_turn = 0, theta0;
    int k, n, step;
    l.vx = 3.0;
    l.vy = 4.0;
    l.omega = 2.0;
    l.angle = 0.3;
    sc.links = &l;
    sc.link_count = 1;
    sc.solver.gravity[0] = 1.5;
    sc.solver.gravity[1] = -G;
    if (rj_model_create(&sc, &m, &err, NULL) != RJ_OK) {
        rjt_check(c, 0, "free flight under gravity", "%s", err.msg);
        return;
    }
    rj_state_create(m, &s, NULL);
    n = rj_link_node_count(m, 0);
    for (k = 0; k < n; k++) {
        double mk, jk, xk[2], vk[2];
        rj_node_mass(m, 0, k, &mk, &jk);
        rj_node_position(m, s, 0, k, xk);
        rj_node_velocity(m, s, 0, k, vk);
        c0[0] += mk * xk[0];
        c0[1] += mk * xk[1];
        v0[0] += mk * vk[0];
        v0[1] += mk * vk[1];
        total += mk;
    }
    c0[0] /= total;
    c0[1] /= total;
    v0[0] /= total;
    v0[1] /= total;
    theta0 = l.angle;
    for (step = 0; step < 200; step++) {
        double cm[2] = { 0, 0 }, a[2], b[2], t, want[2], turn;
        if (rj_run(m, s, rj_state_time(s) + 0.005, 0, NULL, NULL) != RJ_OK) break;
        t = rj_state_time(s);
        for (k = 0; k < n; k++) {
            double mk, jk, xk[2];
            rj_node_mass(m, 0, k, &mk, &jk);
            rj_node_position(m, s, 0, k, xk);
            cm[0] += mk * xk[0] / total;
            cm[1] += mk * xk[1] / total;
        }
        want[0] = c0[0] + v0[0] * t + 0.5 * 1.5 * t * t;
        want[1] = c0[1] + v0[1] * t - 0.5 * G * t * t;
        if (hypot(cm[0] - want[0], cm[1] - want[1]) > worst) worst = hypot(cm[0] - want[0], cm[1] - want[1]);
        rj_node_position(m, s, 0, 0, a);
        rj_node_position(m, s, 0, n - 1, b);
        turn = atan2(b[1] - a[1], b[0] - a[0]) - (theta0 + l.omega * t);
        turn = atan2(sin(turn), cos(turn));
        if (fabs(turn) > worst_turn) worst_turn = fabs(turn);
    }
    rjt_check(c, step == 200 && worst < 1e-9, "free flight under gravity: the centre of mass on the exact parabola for 1 s",
              "largest distance %.3g m after %d of 200 samples", worst, step);
    rjt_check(c, step == 200 && worst_turn < 1e-6, "free flight under gravity: the chord turns uniformly (gravity puts no moment on it)",
              "largest departure %.3g rad", worst_turn);
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
}

/* A horizontal cantilever under its own weight, settled (rj_settle): its tip sag against
   w L^4 / (8 EI) (small deflection: 0.6 % of the length, where the large-deflection
   correction is below 1e-5). */
static double settled_sag(int elements, char *msg, size_t n)
{
    rj_link_def l = bar(RJ_LINK_FLEXIBLE, elements);
    rj_scene_def sc = rj_default_scene_def();
    rj_model *m;
    rj_state *s;
    rj_error err;
    double tip[2];
    rj_result r;
    cantilever_scene(&l, &sc);
    if (rj_model_create(&sc, &m, &err, NULL) != RJ_OK) {
        snprintf(msg, n, "%s", err.msg);
        return NAN;
    }
    if (rj_state_create(m, &s, NULL) != RJ_OK) {
        rj_model_destroy(m, NULL);
        return NAN;
    }
    r = rj_settle(m, s, 1e-12, 2000000);
    rj_node_position(m, s, 0, elements, tip);
    if (r != RJ_OK) snprintf(msg, n, "%.600s", rj_state_error(s));
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
    return r == RJ_OK ? -tip[1] : NAN;
}

/* The tip deflection of lumped loads w L / N on a beam theory cantilever: the load the
   model's lumped masses put on it, for its own discretisation error. */
static double lumped_load_sag(int n, double w, double L, double EI)
{
    const double h = L / n;
    double sum = 0;
    int k;
    for (k = 1; k <= n; k++) {
        const double P = k < n ? w * h : 0.5 * w * h, x = k * h;
        sum += P * x * x * (3 * L - x) / (6 * EI);
    }
    return sum;
}

static void test_sag(rjt_ctx *c)
{
    rj_link_def l = bar(RJ_LINK_FLEXIBLE, 1);
    const double A = l.width * l.height, I = l.width * l.height * l.height * l.height / 12;
    const double w = l.rho * A * G, sag = w * pow(l.length, 4) / (8 * l.E * I);
    static const int meshes[3] = { 5, 10, 20 };
    double err[3];
    char msg[700] = "", name[200];
    int k;
    for (k = 0; k < 3; k++) {
        const double got = settled_sag(meshes[k], msg, sizeof msg);
        const double lumped = lumped_load_sag(meshes[k], w, l.length, l.E * I);
        err[k] = got / sag - 1;
        snprintf(name, sizeof name, "cantilever sag under its own weight, %d elements (rj_settle): tip against beam theory with the model's lumped loads", meshes[k]);
        rjt_check(c, fabs(got / lumped - 1) < 1e-4, name, "%.7g m against %.7g m (%+.4f %%; w L^4 / (8 EI) %.7g m, %+.4f %%) %s",
                  got, lumped, 100 * (got / lumped - 1), sag, 100 * err[k], msg);
    }
    rjt_check(c, fabs(err[2]) < fabs(err[1]) && fabs(err[1]) < fabs(err[0]) && fabs(err[2]) < 1e-3 && fabs(err[0] / err[1]) > 3.5,
              "cantilever sag: against w L^4 / (8 EI) the error falls at second order, below 0.1 % at 20 elements",
              "%+.4f / %+.4f / %+.4f %% at 5 / 10 / 20 elements", 100 * err[0], 100 * err[1], 100 * err[2]);
}

/* A model that would step in place steps double-buffered under gravity (the kinetic
   energy needs every node's velocity at n): the same bits as in_place off. */
static void test_in_place(rjt_ctx *c)
{
    rj_link_def l = bar(RJ_LINK_FLEXIBLE, 30);
    rj_scene_def sc = rj_default_scene_def();
    rj_model *m[2];
    rj_state *s[2];
    rj_error err;
    double tip[2][2];
    rj_energy e[2];
    int k;
    cantilever_scene(&l, &sc);
    for (k = 0; k < 2; k++) {
        sc.solver.in_place = k == 0 ? RJ_IN_PLACE_ON : RJ_IN_PLACE_OFF;
        if (rj_model_create(&sc, &m[k], &err, NULL) != RJ_OK || rj_state_create(m[k], &s[k], NULL) != RJ_OK) {
            rjt_check(c, 0, "gravity with solver.in_place on", "%s", err.msg);
            return;
        }
        rj_run(m[k], s[k], 0.05, 0, NULL, NULL);
        rj_node_position(m[k], s[k], 0, 30, tip[k]);
        rj_state_energy(m[k], s[k], &e[k]);
    }
    rjt_check(c, tip[0][0] == tip[1][0] && tip[0][1] == tip[1][1] && e[0].balance == e[1].balance && fabs(e[0].balance) < 1e-9,
              "gravity with solver.in_place on: the same bits as off, the balance closed",
              "tip y %.12g / %.12g m, balance %.3g / %.3g J", tip[0][1], tip[1][1], e[0].balance, e[1].balance);
    for (k = 0; k < 2; k++) {
        rj_state_destroy(s[k], NULL);
        rj_model_destroy(m[k], NULL);
    }
}

/* A pinned bar under gravity driven by the caller's joint torque, flexible or rigid. */
static int driven_bar(int fidelity, rj_model **m, rj_state **s)
{
    rj_link_def l = bar(fidelity, fidelity == RJ_LINK_RIGID ? 1 : 10);
    rj_joint_def j = rj_default_joint_def();
    rj_scene_def sc = rj_default_scene_def();
    rj_error err;
    j.body1 = -1;
    j.body2 = 0;
    j.angle0 = 0;
    j.friction = 0.2;
    j.damping = fidelity == RJ_LINK_RIGID ? 0.05 : 0;
    sc.links = &l;
    sc.link_count = 1;
    sc.joints = &j;
    sc.joint_count = 1;
    sc.solver.gravity[1] = -G;
    sc.solver.dt = fidelity == RJ_LINK_RIGID ? 2.5e-4 : 0;
    if (rj_model_create(&sc, m, &err, NULL) != RJ_OK) {
        printf("  (%s)\n", err.msg);
        return 0;
    }
    return rj_state_create(*m, s, NULL) == RJ_OK;
}

/* The caller's torques: their work closes the energy balance (with gravity, friction and
   damping at work too), and a checkpoint taken with them set resumes bit for bit. */
static void test_inputs(rjt_ctx *c)
{
    int fidelity;
    for (fidelity = 0; fidelity < 2; fidelity++) {
        const int fid = fidelity ? RJ_LINK_RIGID : RJ_LINK_FLEXIBLE;
        const char *what = fidelity ? "rigid link (joint coordinates)" : "flexible link";
        rj_model *m;
        rj_state *s, *s2;
        rj_energy e;
        double *torque, tip_a[2], tip_b[2];
        unsigned char buf[1 << 16];
        char name[200];
        size_t n;
        int k, same;
        if (!driven_bar(fid, &m, &s) || rj_state_create(m, &s2, NULL) != RJ_OK) {
            rjt_check(c, 0, "the caller's joint torques", "the model did not build");
            return;
        }
        torque = rj_state_joint_torques(m, s);
        /* a torque that changes every 0.1 s, as a controller's would */
        for (k = 0; k < 10; k++) {
            torque[0] = 3.0 + 2.0 * sin(k);
            rj_run(m, s, 0.1 * (k + 1), 0, NULL, NULL);
        }
        rj_state_energy(m, s, &e);
        snprintf(name, sizeof name, "caller's joint torque on a %s under gravity: its work closes the balance", what);
        rjt_check(c, e.work_applied > 0.5 && fabs(e.balance) < 1e-6 * e.work_applied, name,
                  "work %.6g J, balance %.3g J (kinetic %.4g, gravity %.4g, friction %.4g, damping %.4g J)",
                  e.work_applied, e.balance, e.kinetic, e.gravity, e.lost_friction, e.lost_damping);
        n = rj_state_save(m, s, buf, sizeof buf);
        rj_run(m, s, 1.5, 0, NULL, NULL);
        same = n <= sizeof buf && rj_state_load(m, s2, buf, n, NULL) == RJ_OK;
        if (same) rj_run(m, s2, 1.5, 0, NULL, NULL);
        rj_node_position(m, s, 0, rj_link_node_count(m, 0) - 1, tip_a);
        rj_node_position(m, s2, 0, rj_link_node_count(m, 0) - 1, tip_b);
        snprintf(name, sizeof name, "checkpoint with the caller's torque set resumes bit for bit, %s", what);
        rjt_check(c, same && tip_a[0] == tip_b[0] && tip_a[1] == tip_b[1] && rj_state_joint_torques(m, s2)[0] == torque[0],
                  name, "tip (%.12g, %.12g) against (%.12g, %.12g)", tip_a[0], tip_a[1], tip_b[0], tip_b[1]);
        /* a torque that is not a number stops the step, naming it, the state unchanged */
        {
            unsigned char before[1 << 16], after[1 << 16];
            size_t nb;
            rj_result r;
            torque[0] = NAN;
            nb = rj_state_save(m, s, before, sizeof before);
            r = rj_step(m, s);
            rj_state_save(m, s, after, sizeof after);
            snprintf(name, sizeof name, "a caller's torque that is NaN is refused by the step, the state unchanged, %s", what);
            rjt_check(c, r == RJ_ERR_INVALID && strstr(rj_state_error(s), "rj_state_joint_torques()[0]") != NULL &&
                      memcmp(before, after, nb) == 0, name, "%s: %s", rj_result_str(r), rj_state_error(s));
        }
        rj_state_destroy(s, NULL);
        rj_state_destroy(s2, NULL);
        rj_model_destroy(m, NULL);
    }
}

/* Bad gravity is refused naming the field. */
static void test_refusals(rjt_ctx *c)
{
    rj_link_def l = bar(RJ_LINK_FLEXIBLE, 4);
    rj_scene_def sc = rj_default_scene_def();
    rj_model *m = NULL;
    rj_error err;
    sc.links = &l;
    sc.link_count = 1;
    sc.solver.gravity[0] = NAN;
    rjt_check(c, rj_model_create(&sc, &m, &err, NULL) == RJ_ERR_INVALID && strstr(err.msg, "gravity") != NULL,
              "a non-finite gravity is refused, naming the field", "%s", err.msg);
    if (m) rj_model_destroy(m, NULL);
}

/* Scene files: gravity = gx gy in the solver section, written back as read; a missing
   component or a bad value is refused naming the key. */
static void test_scene_file(rjt_ctx *c)
{
    static const char text[] = "solver\n  gravity = 0.5 -9.81\nlink a\n  length = 1\n"
                               "  elements = 2\n  E = 7e10\n  rho = 2700\n  area = 2e-4\n"
                               "  inertia = 1.6e-9\n";
    static const char missing[] = "solver\n  gravity = -9.81\nlink a\n  length = 1\n";
    static const char nan_text[] = "solver\n  gravity = 0 nan\nlink a\n  length = 1\n";
    rj_scene_file f, g;
    rj_error err;
    char buf[4096];
    size_t n;
    int ok = rj_scene_parse(text, sizeof text - 1, "g.rjs", &f, &err) == RJ_OK;
    rjt_check(c, ok && f.solver.gravity[0] == 0.5 && f.solver.gravity[1] == -9.81,
              "scene file: gravity = gx gy is read", "%g %g", ok ? f.solver.gravity[0] : NAN,
              ok ? f.solver.gravity[1] : NAN);
    if (ok) {
        rj_scene_def d = rj_scene_file_def(&f);
        n = rj_scene_write(&d, NULL, NULL, buf, sizeof buf);
        ok = n > 0 && n <= sizeof buf && rj_scene_parse(buf, n - 1, "w.rjs", &g, &err) == RJ_OK;
        rjt_check(c, ok && g.solver.gravity[0] == 0.5 && g.solver.gravity[1] == -9.81,
                  "scene file: gravity is written back and reads the same", "%s", ok ? "same" : err.msg);
        if (ok) rj_scene_file_free(&g);
        rj_scene_file_free(&f);
    }
    ok = rj_scene_parse(missing, sizeof missing - 1, "m.rjs", &f, &err) == RJ_ERR_PARSE;
    rjt_check(c, ok && strstr(err.msg, "gravity") != NULL && strstr(err.msg, "missing") != NULL,
              "scene file: gravity with one component is refused", "%s", err.msg);
    if (!ok) rj_scene_file_free(&f);
    ok = rj_scene_parse(nan_text, sizeof nan_text - 1, "n.rjs", &f, &err) == RJ_ERR_PARSE;
    rjt_check(c, ok && strstr(err.msg, "gravity") != NULL, "scene file: a non-finite gravity is refused",
              "%s", err.msg);
    if (!ok) rj_scene_file_free(&f);
}

/* Scene files: load sections read into rj_load_def, written back and read the same; a
   load with no link, a node the link does not have, a table that goes back in time, a
   misspelt key and a force with one component are refused at their line and column. */
static void test_load_sections(rjt_ctx *c)
{
    static const char text[] = "link beam\n  length = 1\n  elements = 20\n  root = clamped\n"
                               "load tip\n  link = beam  node = last\n  force = 0 -1166.5\n"
                               "  table = 0 0, 0.1 1\n"
                               "load twist\n  link = beam\n  node = 10\n  moment = 2.5\n"
                               "  follower = yes\n";
    static const struct {
        const char *text, *what, *needle;
    } bad[5] = {
        { "link a\n  length = 1\nload l\n  force = 1 2\n", "a load with no link", "g.rjs:3:1: load 'l' has no link" },
        { "link a\n  length = 1\n  elements = 4\nload l\n  link = a\n  node = 5\n", "a node the link does not have",
          "g.rjs:6:10: node = 5 is out of range in load 'l': link 'a' has nodes 0..4" },
        { "link a\n  length = 1\nload l\n  link = a\n  force = 1 0\n  table = 0 0, 1 1, 0.5 2\n",
          "a table that goes back in time", "g.rjs:6:11: loads[0].table_time[2] = 0.5 is invalid" },
        { "link a\n  length = 1\nload l\n  link = a\n  forse = 1 0\n", "a misspelt key", "did you mean 'force'" },
        { "link a\n  length = 1\nload l\n  link = a\n  force = 1\n", "a force with one component",
          "missing y component" },
    };
    rj_scene_file f, g;
    rj_error err;
    char buf[4096], name[160];
    size_t n;
    int ok = rj_scene_parse(text, sizeof text - 1, "g.rjs", &f, &err) == RJ_OK, k;
    rjt_check(c, ok && f.load_count == 2 && f.loads[0].link == 0 && f.loads[0].node == -1 &&
                  f.loads[0].force[1] == -1166.5 && f.loads[0].table_count == 2 && f.loads[0].table_time[1] == 0.1 &&
                  f.loads[1].node == 10 && f.loads[1].moment == 2.5 && f.loads[1].follower == 1 &&
                  strcmp(f.load_names[1], "twist") == 0,
              "scene file: load sections are read", "%s", ok ? "2 loads as written" : err.msg);
    if (ok) {
        rj_scene_def d = rj_scene_file_def(&f);
        n = rj_scene_write(&d, NULL, NULL, buf, sizeof buf);
        ok = n > 0 && n < sizeof buf && rj_scene_parse(buf, n, "w.rjs", &g, &err) == RJ_OK;
        rjt_check(c, ok && g.load_count == 2 && memcmp(g.loads, f.loads, 2 * sizeof(rj_load_def)) == 0,
                  "scene file: loads are written back and read the same bits", "%s", ok ? "same" : err.msg);
        if (ok) rj_scene_file_free(&g);
        rj_scene_file_free(&f);
    }
    for (k = 0; k < 5; k++) {
        ok = rj_scene_parse(bad[k].text, strlen(bad[k].text), "g.rjs", &f, &err) != RJ_OK;
        snprintf(name, sizeof name, "scene file: %s is refused, located", bad[k].what);
        rjt_check(c, ok && strstr(err.msg, bad[k].needle) != NULL, name, "%s", err.msg);
        if (!ok) rj_scene_file_free(&f);
    }
}

/* rj_settle refuses bad arguments, and says so when it has not settled in its steps. */
static void test_settle_arguments(rjt_ctx *c)
{
    rj_link_def l = bar(RJ_LINK_FLEXIBLE, 4);
    rj_scene_def sc = rj_default_scene_def();
    rj_model *m;
    rj_state *s;
    rj_error err;
    rj_result r0, r1, r2;
    cantilever_scene(&l, &sc);
    if (rj_model_create(&sc, &m, &err, NULL) != RJ_OK || rj_state_create(m, &s, NULL) != RJ_OK) {
        rjt_check(c, 0, "rj_settle's arguments", "%s", err.msg);
        return;
    }
    r0 = rj_settle(m, s, 0, 100);
    r1 = rj_settle(m, s, 1e-12, 0);
    r2 = rj_settle(m, s, 1e-12, 3);
    rjt_check(c, r0 == RJ_ERR_INVALID && r1 == RJ_ERR_INVALID, "rj_settle refuses tol 0 and max_steps 0",
              "%s, %s", rj_result_str(r0), rj_result_str(r1));
    rjt_check(c, r2 == RJ_ERR_NOT_CONVERGED && strstr(rj_state_error(s), "not settled") != NULL,
              "rj_settle reports a state not settled within its steps", "%s: %s", rj_result_str(r2),
              rj_state_error(s));
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
}

/* A chain of n rigid 1 m bars (test's bar) from a pin at the origin, the first at angle
   a0 from the x axis, the rest straight on, at step dt. */
static int rigid_chain(int n, double a0, double dt, rj_link_def *l, rj_joint_def *j,
                       rj_model **m, rj_state **s, rj_error *err)
{
    rj_scene_def sc = rj_default_scene_def();
    int k;
    for (k = 0; k < n; k++) {
        l[k] = bar(RJ_LINK_RIGID, 1);
        j[k] = rj_default_joint_def();
        j[k].body1 = k - 1;
        j[k].body2 = k;
        j[k].angle0 = k ? PI : a0;
    }
    sc.links = l;
    sc.link_count = n;
    sc.joints = j;
    sc.joint_count = n;
    sc.solver.dt = dt;
    sc.solver.gravity[1] = -G;
    if (rj_model_create(&sc, m, err, NULL) != RJ_OK)
        return 0;
    rj_state_create(*m, s, NULL);
    return 1;
}

/* Joint 0's pin force as the joint passes a quarter turn from where it starts (a link
   released level, at the vertical): the force is at t^n, a step behind the angle, so
   between the forces of the two states around the crossing, linearly. Returns 0 when it
   did not get there within 1 s. */
static int pin_force_quarter_turn(const rj_model *m, rj_state *s, double at[2])
{
    const double level = rj_joint_theta_running(m, s, 0);
    double turned = 0, after[2];
    while (rj_state_time(s) < 1.0 && rj_step(m, s) == RJ_OK) {
        const double turn = fabs(rj_joint_theta_running(m, s, 0) - level);
        if (turned < 0.5 * PI && turn >= 0.5 * PI) {
            const double w = (0.5 * PI - turned) / (turn - turned);
            rj_joint_pin_force(m, s, 0, at);
            rj_step(m, s);
            rj_joint_pin_force(m, s, 0, after);
            at[0] += w * (after[0] - at[0]);
            at[1] += w * (after[1] - at[1]);
            return 1;
        }
        turned = turn;
    }
    return 0;
}

/* A flexible rod of 20 elements released level, of modulus E: at the vertical, the pin
   force against M g + S omega^2 with omega^2 = 2 g S / J (the energy; M, S, J the model's
   lumped mass, first moment and inertia about the pin), the rigid rod's law, which the
   rod approaches as it stiffens (its bending vibration is what is left). Returns the
   relative miss of the vertical force, HUGE_VAL when it did not get there; its
   horizontal force over m g into sideways. */
static double pin_force_rod(int fidelity, double E, double *sideways, char *msg, size_t n)
{
    rj_link_def l = bar(fidelity, 20);
    rj_joint_def j = rj_default_joint_def();
    rj_scene_def sc = rj_default_scene_def();
    rj_model *m = NULL;
    rj_state *s = NULL;
    rj_error err;
    double mass, moment, inertia, want, at[2] = { 0, 0 };
    double miss = HUGE_VAL;
    l.E = E;
    j.body1 = -1;
    j.body2 = 0;
    sc.links = &l;
    sc.link_count = 1;
    sc.joints = &j;
    sc.joint_count = 1;
    sc.solver.gravity[1] = -G;
    *sideways = HUGE_VAL;
    if (rj_model_create(&sc, &m, &err, NULL) != RJ_OK) {
        snprintf(msg, n, "%.150s", err.msg);
        return miss;
    }
    rj_state_create(m, &s, NULL);
    lumped_body(m, s, 0, &mass, &moment, &inertia);
    want = mass * G + moment * 2 * G * moment / inertia;
    /* level at the start; the vertical a quarter turn on */
    if (pin_force_quarter_turn(m, s, at)) {
        miss = at[1] / want - 1;
        *sideways = fabs(at[0]) / (mass * G);
        snprintf(msg, n, "(%.5g, %.6g) N against (0, %.6g) N", at[0], at[1], want);
    }
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
    return miss;
}

static void test_pin_force_rod(rjt_ctx *c)
{
    double side[3], miss[3];
    char msg[3][200];
    int k;
    for (k = 0; k < 3; k++)
        miss[k] =
            pin_force_rod(RJ_LINK_FLEXIBLE, 70e9 * pow(10.0, k), &side[k], msg[k], sizeof msg[k]);
    rjt_check(c, fabs(miss[0]) > fabs(miss[2]) && side[0] > side[2] && fabs(miss[2]) < 1e-3,
              "pin force: a flexible rod released level approaches the rigid rod's at the "
              "vertical as it stiffens",
              "vertical force off M g + S omega^2 by %+.2e, %+.2e, %+.2e and horizontal %.2e, "
              "%.2e, %.2e m g at E 7e10, 7e11, 7e12 Pa: %s; %s; %s",
              miss[0], miss[1], miss[2], side[0], side[1], side[2], msg[0], msg[1], msg[2]);
}

/* A mixed scene: a rigid rod hanging from the tip of a clamped flexible cantilever,
   settled (rj_settle): the pin carries the rod's weight, the force the cantilever's
   node takes from the rod reversed (the rod's own node is massless, its body carries
   it). */
static void test_pin_force_mixed(rjt_ctx *c)
{
    rj_link_def l[2];
    rj_joint_def j = rj_default_joint_def();
    rj_scene_def sc = rj_default_scene_def();
    rj_model *m = NULL;
    rj_state *s = NULL;
    rj_error err;
    double F[2] = { 0, 0 }, rod;
    rj_result r = RJ_ERR_INVALID;
    l[0] = bar(RJ_LINK_FLEXIBLE, 10);
    l[0].root = RJ_ROOT_CLAMPED;
    l[1] = bar(RJ_LINK_RIGID, 1);
    l[1].length = 0.5;
    rod = 2700 * 0.02 * 0.01 * 0.5;
    j.body1 = 0;
    j.node1 = -1;
    j.body2 = 1;
    j.angle0 = 0.5 * PI;
    sc.links = l;
    sc.link_count = 2;
    sc.joints = &j;
    sc.joint_count = 1;
    sc.solver.gravity[1] = -G;
    if (rj_model_create(&sc, &m, &err, NULL) == RJ_OK) {
        rj_state_create(m, &s, NULL);
        if (rj_settle(m, s, 1e-12, 10000000L) == RJ_OK) {
            rj_step(m, s);
            r = rj_joint_pin_force(m, s, 0, F);
        }
        rj_state_destroy(s, NULL);
        rj_model_destroy(m, NULL);
    }
    /* settled to 1e-12 of the potential moved, the tip keeps an acceleration of about
       3e-4 m/s^2: a few 1e-6 of the weight */
    rjt_check(c, r == RJ_OK && fabs(F[1] / (rod * G) - 1) < 1e-5 && fabs(F[0]) < 1e-5 * rod * G,
              "pin force: a rigid rod hanging from a flexible cantilever carries its weight",
              "(%.3g, %.9g) N against (0, %.9g) N (%+.2e), settled %s", F[0], F[1], rod * G,
              F[1] / (rod * G) - 1,
              r == RJ_OK ? "" : "(failed)");
}

/* A cantilever of 10 flexible elements under a tip load P (no gravity), settled: every
   element's section loads against the statics of the deflected shape (the tip load's
   moment about each node, its components along and across each chord), which hold
   whatever the beam theory; the first element's at the clamp are the clamp's reaction. */
static void test_element_loads(rjt_ctx *c)
{
    rj_link_def l = bar(RJ_LINK_FLEXIBLE, 10);
    rj_load_def load = rj_default_load_def();
    rj_scene_def sc = rj_default_scene_def();
    rj_model *m = NULL;
    rj_state *s = NULL;
    rj_error err;
    const double P = 2.0;
    double worst = 0, tip[2], root[5] = { 0, 0, 0, 0, 0 };
    int e, ok = 0;
    l.root = RJ_ROOT_CLAMPED;
    load.link = 0;
    load.node = -1;
    load.force[1] = -P;
    sc.links = &l;
    sc.link_count = 1;
    sc.loads = &load;
    sc.load_count = 1;
    if (rj_model_create(&sc, &m, &err, NULL) == RJ_OK) {
        rj_state_create(m, &s, NULL);
        ok = rj_settle(m, s, 1e-15, 10000000L) == RJ_OK && rj_step(m, s) == RJ_OK;
        rj_node_position(m, s, 0, 10, tip);
        for (e = 0; e < 10 && ok; e++) {
            double a[2], b[2], loads[5], u[2], len, want[4];
            rj_node_position(m, s, 0, e, a);
            rj_node_position(m, s, 0, e + 1, b);
            len = hypot(b[0] - a[0], b[1] - a[1]);
            u[0] = (b[0] - a[0]) / len;
            u[1] = (b[1] - a[1]) / len;
            ok = rj_element_loads(m, s, 0, e, loads) == RJ_OK;
            /* the tip load (0, -P) on the part before each section */
            want[0] = -P * u[1];
            want[1] = -P * u[0];
            want[2] = -P * (tip[0] - a[0]);
            want[3] = -P * (tip[0] - b[0]);
            worst = fmax(worst, fmax(fabs(loads[0] - want[0]), fabs(loads[1] - want[1])) / P);
            worst = fmax(worst, fmax(fabs(loads[2] - want[2]), fabs(loads[3] - want[3])) / P);
            if (e == 0)
                memcpy(root, loads, sizeof root);
        }
        rj_state_destroy(s, NULL);
        rj_model_destroy(m, NULL);
    }
    rjt_check(c, ok && worst < 1e-6,
              "element loads: a cantilever under a tip load, against the statics of its shape",
              "P = %g N, 10 elements: N, V, M at every element's ends within %.3g of P (N, m); "
              "at the clamp N %.3g N, V %.6g N, M %.6g N m (P L = %g N m), outer-fibre stress "
              "%.6g Pa",
              P, worst, root[0], root[1], root[2], P * l.length, root[4]);
}


/* Inextensible links: Newton's second law for the links below the joint (their lengths'
   forces cancel inside them): a rod of 20 inextensible elements released level passes
   the vertical with M g + S omega^2 of its lumped masses, and its sideways force (the
   bending vibration since the release) is the flexible rod's of the same E (its pin node's
   own balance) to 0.005 m g; a chain of two such rods hanging at rest carries 2 m g at
   its root and m g between. */
static void test_pin_force_inextensible(rjt_ctx *c)
{
    rj_link_def l[2];
    rj_joint_def j[2];
    rj_scene_def sc = rj_default_scene_def();
    rj_model *m;
    rj_state *s;
    rj_error err;
    double side, side_flex, miss, F[2] = { 0, 0 }, F2[2] = { 0, 0 }, weight;
    char msg[200];
    int k;
    pin_force_rod(RJ_LINK_FLEXIBLE, 7e12, &side_flex, msg, sizeof msg);
    miss = pin_force_rod(RJ_LINK_INEXTENSIBLE, 7e12, &side, msg, sizeof msg);
    rjt_check(c, fabs(miss) < 1e-3 && fabs(side - side_flex) < 0.005,
              "pin force: an inextensible rod released level passes the vertical with M g + S omega^2",
              "vertical off by %+.2e, horizontal %.2e m g (the flexible rod's %.2e): %s", miss,
              side, side_flex, msg);
    for (k = 0; k < 2; k++) {
        l[k] = bar(RJ_LINK_INEXTENSIBLE, 4);
        j[k] = rj_default_joint_def();
        j[k].body1 = k - 1;
        j[k].body2 = k;
        j[k].angle0 = k ? PI : -0.5 * PI;
    }
    sc.links = l;
    sc.link_count = 2;
    sc.joints = j;
    sc.joint_count = 2;
    sc.solver.gravity[1] = -G;
    if (rj_model_create(&sc, &m, &err, NULL) != RJ_OK) {
        rjt_check(c, 0, "pin force: inextensible chain", "%s", err.msg);
        return;
    }
    rj_state_create(m, &s, NULL);
    rj_run(m, s, 0.01, 0, NULL, NULL);
    rj_joint_pin_force(m, s, 0, F);
    rj_joint_pin_force(m, s, 1, F2);
    weight = 2700 * 0.02 * 0.01 * G;
    rjt_check(c, fabs(F[1] / (2 * weight) - 1) < 1e-9 && fabs(F2[1] / weight - 1) < 1e-9 &&
                     fabs(F[0]) < 1e-9 * weight,
              "pin force: a chain of two inextensible rods hanging at rest carries 2 m g, then m g",
              "root (%.3g, %.12g) N, middle (%.3g, %.12g) N against %.12g and %.12g N", F[0],
              F[1], F2[0], F2[1], 2 * weight, weight);
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
}


/* A mixed scene's rigid bodies (a clamped flexible strip beside makes the scene mixed):
   Newton's second law for the bodies below the joint. A chain of two rigid rods hanging
   at rest (a pin between two bodies: their projection holds it) carries 2 m g at its
   root and m g between; one rod on a ground pin released level passes the vertical with
   2.5 m g. */
static void test_pin_force_bodies(rjt_ctx *c)
{
    rj_link_def l[3];
    rj_joint_def j[2];
    rj_scene_def sc = rj_default_scene_def();
    rj_model *m;
    rj_state *s;
    rj_error err;
    double F[2] = { 0, 0 }, F2[2] = { 0, 0 }, at[2] = { 0, 0 };
    const double weight = 2700 * 0.02 * 0.01 * G;
    int k, rods;
    for (rods = 2; rods >= 1; rods--) {
        for (k = 0; k < 2; k++) {
            l[k] = bar(RJ_LINK_RIGID, 1);
            j[k] = rj_default_joint_def();
            j[k].body1 = k - 1;
            j[k].body2 = k;
            j[k].angle0 = k ? PI : (rods == 2 ? -0.5 * PI : 0.0);
        }
        l[rods] = bar(RJ_LINK_FLEXIBLE, 4);
        l[rods].root = RJ_ROOT_CLAMPED;
        l[rods].y = 2.0;
        sc.links = l;
        sc.link_count = rods + 1;
        sc.joints = j;
        sc.joint_count = rods;
        sc.solver.gravity[1] = -G;
        if (rj_model_create(&sc, &m, &err, NULL) != RJ_OK) {
            rjt_check(c, 0, "pin force: bodies", "%s", err.msg);
            return;
        }
        rj_state_create(m, &s, NULL);
        if (rods == 2) {
            rj_run(m, s, 0.01, 0, NULL, NULL);
            rj_joint_pin_force(m, s, 0, F);
            rj_joint_pin_force(m, s, 1, F2);
            rjt_check(c, fabs(F[1] / (2 * weight) - 1) < 1e-9 && fabs(F2[1] / weight - 1) < 1e-9,
                      "pin force: two rigid bodies of a mixed scene hanging at rest carry 2 m g, then m g",
                      "root (%.3g, %.12g) N, between the bodies (%.3g, %.12g) N against %.12g, %.12g N",
                      F[0], F[1], F2[0], F2[1], 2 * weight, weight);
        } else {
            pin_force_quarter_turn(m, s, at);
            rjt_check(c, fabs(at[1] / (2.5 * weight) - 1) < 1e-3,
                      "pin force: a rigid body of a mixed scene on a ground pin passes the vertical with 2.5 m g",
                      "(%.4g, %.6g) N against (0, %.6g) N (%+.1e)", at[0], at[1], 2.5 * weight,
                      at[1] / (2.5 * weight) - 1);
        }
        rj_state_destroy(s, NULL);
        rj_model_destroy(m, NULL);
    }
}

/* A joint of the branched scenes below: body2's node 0 on body1's node1 (-1: its last). */
static rj_joint_def tree_joint(int body1, int node1, int body2, double angle0)
{
    rj_joint_def j = rj_default_joint_def();
    j.body1 = body1;
    j.node1 = node1;
    j.body2 = body2;
    j.angle0 = angle0;
    return j;
}

/* A link of the branched scenes: a bar of that model, elements and length. */
static rj_link_def tree_link(int fidelity, int elements, double length)
{
    rj_link_def l = bar(fidelity, elements);
    l.length = length;
    return l;
}

/* An inextensible link from the ground with two inextensible links hanging from its
   interior nodes, a third from the first of them. */
static void pin_tree_inextensible(rj_link_def *l, rj_joint_def *j, rj_scene_def *sc)
{
    const int inext = RJ_LINK_INEXTENSIBLE;
    l[0] = tree_link(inext, 6, 1.0);
    l[1] = tree_link(inext, 4, 0.5);
    l[2] = tree_link(inext, 3, 0.4);
    l[3] = tree_link(inext, 2, 0.3);
    j[0] = tree_joint(-1, 0, 0, -0.2 * PI);
    j[1] = tree_joint(0, 2, 1, 0.3 * PI);
    j[2] = tree_joint(0, 4, 2, -0.4 * PI);
    j[3] = tree_joint(1, -1, 3, 0.5 * PI);
    sc->link_count = sc->joint_count = 4;
}

/* A mixed scene: a rigid body from the ground carrying a flexible link at its middle
   node and a rigid body at its tip, that one carrying two flexible links. */
static void pin_tree_mixed(rj_link_def *l, rj_joint_def *j, rj_scene_def *sc)
{
    l[0] = tree_link(RJ_LINK_RIGID, 2, 1.0);
    l[1] = tree_link(RJ_LINK_FLEXIBLE, 4, 0.5);
    l[2] = tree_link(RJ_LINK_RIGID, 1, 0.5);
    l[3] = tree_link(RJ_LINK_FLEXIBLE, 3, 0.4);
    l[4] = tree_link(RJ_LINK_FLEXIBLE, 3, 0.4);
    j[0] = tree_joint(-1, 0, 0, -0.2 * PI);
    j[1] = tree_joint(0, 1, 1, 0.3 * PI);
    j[2] = tree_joint(0, -1, 2, -0.4 * PI);
    j[3] = tree_joint(2, -1, 3, 0.5 * PI);
    j[4] = tree_joint(2, -1, 4, -0.5 * PI);
    sc->link_count = sc->joint_count = 5;
}

/* An inextensible four-bar (crank, coupler, rocker) whose coupler carries a link from
   its middle with a triangle below it (a second loop): a link straight down, one across
   from its tip, one slanting back up to it (its last node the loop's pin), and one
   hanging from that. The pass places the slanting side's subtree before the downward
   one's, so their loop's far end lies below the places of the subtree it leaves. The
   loops' joints as rj_scene_assemble closes them. */
static int pin_tree_loops(rj_link_def *l, rj_joint_def *j, rj_scene_def *sc, rj_error *err)
{
    const int inext = RJ_LINK_INEXTENSIBLE;
    const double slant = atan2(-0.4, 0.3);
    static const int elements[8] = { 4, 10, 4, 2, 4, 3, 5, 2 };
    static const double length[8] = { 0.5, 1.0, 0.5, 0.2, 0.4, 0.3, 0.5, 0.2 };
    int k;
    for (k = 0; k < 8; k++)
        l[k] = tree_link(inext, elements[k], length[k]);
    j[0] = tree_joint(-1, 0, 0, 0.5 * PI);
    j[1] = tree_joint(0, -1, 1, -1.5 * PI);
    j[2] = tree_joint(-1, 0, 2, 0.5 * PI);
    j[2].ground_x = 1.0;
    j[3] = tree_joint(1, -1, 2, -0.5 * PI);
    j[3].node2 = -1;
    j[4] = tree_joint(1, 5, 3, -1.5 * PI);
    j[5] = tree_joint(3, -1, 4, -PI);
    j[6] = tree_joint(4, -1, 5, -0.5 * PI);
    j[7] = tree_joint(3, -1, 6, slant - 0.5 * PI);
    j[8] = tree_joint(5, -1, 6, slant - PI);
    j[8].node2 = -1;
    j[9] = tree_joint(6, 2, 7, 0.3 * PI);
    sc->link_count = 8;
    sc->joint_count = 10;
    sc->links = l;
    sc->joints = j;
    return rj_scene_assemble(sc, j, err) == RJ_OK;
}

/* Branched scene which (0 pin_tree_inextensible, 1 pin_tree_mixed, 2 pin_tree_loops),
   released under gravity with two loads on links below others. Returns the joint
   count, 0 (err filled) when refused. */
static int pin_tree_scene(int which, rj_link_def *l, rj_joint_def *j, rj_load_def *load,
                          rj_scene_def *sc, rj_error *err)
{
    *sc = rj_default_scene_def();
    sc->solver.gravity[1] = -G;
    if (which == 0)
        pin_tree_inextensible(l, j, sc);
    else if (which == 1)
        pin_tree_mixed(l, j, sc);
    else if (!pin_tree_loops(l, j, sc, err))
        return 0;
    sc->links = l;
    sc->joints = j;
    load[0] = rj_default_load_def();
    load[0].link = 1;
    load[0].node = 2;
    load[0].force[0] = 3.0;
    load[0].force[1] = 1.0;
    load[1] = rj_default_load_def();
    load[1].link = which == 2 ? 4 : 2;
    load[1].force[0] = -2.0;
    sc->loads = load;
    sc->load_count = 2;
    return sc->joint_count;
}

/* What the all-joints pin forces (rj_joint_pin_forces: one pass up the joint tree)
   showed against each joint's own query (rj_joint_pin_force: the links below it summed
   alone) over a run, and the ground's pins against the scene's momentum. */
typedef struct pin_pass_check {
    double worst;  /* the largest |all - own| / |own| */
    long finite;   /* the forces compared */
    long mismatch; /* joints where one has a force and the other none */
    double ground; /* the largest |sum of the ground's pin forces - sum (m a - m g) - loads| */
    double total;  /* the largest |sum (m a - m g) - loads| */
} pin_pass_check;

/* Every node's velocity into v (2 a node, in node index order). */
static void pin_pass_velocities(const rj_model *m, const rj_state *s, double *v)
{
    int l, k;
    for (l = 0; l < rj_model_link_count(m); l++)
        for (k = 0; k < rj_link_node_count(m, l); k++)
            rj_node_velocity(m, s, l, k, v + 2 * rj_model_node_index(m, l, k));
}

/* The scene's m a - m g less its loads at t^n, from every node's velocity before the
   step (before) and after it (the scene's nodes carry all its mass: no rigid bodies),
   into total. */
static void pin_pass_momentum(const rj_model *m, const rj_state *s, const double *before,
                              double total[2])
{
    const double kick = rj_state_steps(s) == 1 ? 0.5 * rj_model_dt(m) : rj_model_dt(m);
    double after[2 * 64];
    int i, q;
    pin_pass_velocities(m, s, after);
    total[0] = total[1] = 0;
    for (i = 0; i < rj_model_node_count(m); i++) {
        int link = 0;
        double mass;
        while (rj_model_node_index(m, link, -1) < i)
            link++;
        rj_node_mass(m, link, i - rj_model_node_index(m, link, 0), &mass, NULL);
        total[0] += mass * (after[2 * i] - before[2 * i]) / kick;
        total[1] += mass * ((after[2 * i + 1] - before[2 * i + 1]) / kick + G);
    }
    for (q = 0; q < rj_model_load_count(m); q++) {
        total[0] -= rj_model_load_def(m, q)->force[0];
        total[1] -= rj_model_load_def(m, q)->force[1];
    }
}

/* The ground's pins' forces in all (2 a joint) less the scene's total, into o. */
static void pin_pass_ground(const rj_model *m, const double *all, const double total[2],
                            pin_pass_check *o)
{
    double sum[2] = { 0, 0 };
    int q;
    for (q = 0; q < rj_model_joint_count(m); q++)
        if (rj_model_joint_def(m, q)->body1 < 0) {
            sum[0] += all[2 * q];
            sum[1] += all[2 * q + 1];
        }
    o->ground = fmax(o->ground, hypot(sum[0] - total[0], sum[1] - total[1]));
    o->total = fmax(o->total, hypot(total[0], total[1]));
}

/* Both queries after each of 500 steps of branched scene which into o; 0 when refused. */
static int pin_pass_run(int which, pin_pass_check *o, char *msg, size_t n)
{
    rj_link_def l[8];
    rj_joint_def j[10];
    rj_load_def load[2];
    rj_scene_def sc;
    rj_model *m = NULL;
    rj_state *s = NULL;
    rj_error err;
    double all[20], before[2 * 64], total[2];
    int k, q;
    const int nj = pin_tree_scene(which, l, j, load, &sc, &err);
    memset(o, 0, sizeof *o);
    if (!nj || rj_model_create(&sc, &m, &err, NULL) != RJ_OK) {
        snprintf(msg, n, "%.150s", err.msg);
        return 0;
    }
    rj_state_create(m, &s, NULL);
    for (k = 0; k < 500; k++) {
        pin_pass_velocities(m, s, before);
        if (rj_step(m, s) != RJ_OK)
            break;
        rj_joint_pin_forces(m, s, all);
        pin_pass_momentum(m, s, before, total);
        pin_pass_ground(m, all, total, o);
        for (q = 0; q < nj; q++) {
            double own[2] = { 0, 0 };
            const int known = rj_joint_pin_force(m, s, q, own) == RJ_OK;
            const double miss = hypot(all[2 * q] - own[0], all[2 * q + 1] - own[1]);
            o->mismatch += known != (all[2 * q] == all[2 * q]);
            if (!known)
                continue;
            o->finite++;
            o->worst = fmax(o->worst, miss / hypot(own[0], own[1]));
        }
    }
    snprintf(msg, n, "%d steps", k);
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
    return 1;
}

/* rj_joint_pin_forces sums every subtree once, children before parents; each joint's
   own query sums the links below it: the same sums in another order, so equal to
   round-off, with none at the same joints. Scene 2's loops give every joint a force:
   each loop joint's own from the step's record of its pin node's constraint forces, a
   subtree's sum less the forces of the loops that tie it to the rest. Its ground pins
   then carry the whole scene: their sum is its m a - m g less the loads (a loop's force
   in the subtrees' sums with the wrong sign, or missed, leaves it there). The rigid
   bodies' masses are not their nodes': scene 1's total is not taken. */
static void test_pin_forces_pass(rjt_ctx *c)
{
    static const char *const what[3] = { "an inextensible tree", "a mixed tree of rigid bodies",
                                         "inextensible loops" };
    static const long want[3] = { 500L * 4, 500L * 5, 500L * 10 };
    int which;
    for (which = 0; which < 3; which++) {
        pin_pass_check o;
        char msg[200], ground[120] = "";
        const int ran = pin_pass_run(which, &o, msg, sizeof msg);
        const int closed = which == 1 || o.ground < 1e-9 * o.total;
        if (which != 1)
            snprintf(ground, sizeof ground,
                     "; the ground's pins less the scene's m a - m g - loads %.3g N of %.4g N "
                     "(bound 1e-9 relative)",
                     o.ground, o.total);
        rjt_check(c, ran && o.finite == want[which] && !o.mismatch && o.worst < 1e-12 && closed,
                  "pin forces: all joints at once as each joint's own, on a branched scene",
                  "%s: %ld forces (want %ld) within %.3g of each joint's own (bound 1e-12 "
                  "relative), %ld with a force in one query only%s; %s",
                  what[which], o.finite, want[which], o.worst, o.mismatch, ground, msg);
    }
}

/* The pin force (rj_joint_pin_force) against Newton: a rod hanging at rest carries m g;
   a chain of two hanging rods carries 2 m g at its root, m g at its middle; a rod
   released level passes the vertical with 2.5 m g (omega^2 = 3 g / L there, the centre
   at L / 2). A flexible scene is refused, for now. */
static void test_pin_force(rjt_ctx *c)
{
    rj_link_def l[2];
    rj_joint_def j[2];
    rj_model *m = NULL;
    rj_state *s = NULL;
    rj_error err;
    const double mass = 2700 * 0.02 * 0.01 * 1.0;
    double F[2], F2[2], before[2] = { 0, 0 }, at[2] = { 0, 0 }, phi_prev = 0;
    rj_result r;
    if (!rigid_chain(2, -0.5 * PI, 1e-4, l, j, &m, &s, &err)) {
        rjt_check(c, 0, "pin force: hanging chain", "%s", err.msg);
        return;
    }
    rj_run(m, s, 0.1, 0, NULL, NULL);
    r = rj_joint_pin_force(m, s, 0, F);
    rj_joint_pin_force(m, s, 1, F2);
    rjt_check(c, r == RJ_OK && fabs(F[1] / (2 * mass * G) - 1) < 1e-12 && fabs(F[0]) < 1e-12 &&
                     fabs(F2[1] / (mass * G) - 1) < 1e-12,
              "pin force: a hanging chain of two rods carries 2 m g at its root, m g between",
              "root (%.6g, %.9g) N, middle (%.6g, %.9g) N against 2 m g = %.9g N, m g = %.9g N",
              F[0], F[1], F2[0], F2[1], 2 * mass * G, mass * G);
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
    if (!rigid_chain(1, 0.0, 1e-4, l, j, &m, &s, &err)) {
        rjt_check(c, 0, "pin force: rod released level", "%s", err.msg);
        return;
    }
    while (rj_state_time(s) < 1.0) {
        double phi;
        rj_joint_pin_force(m, s, 0, before);
        rj_step(m, s);
        phi = rj_joint_theta_running(m, s, 0);
        if (phi_prev > -0.5 * PI && phi <= -0.5 * PI) {
            /* between the two steps, linearly at the vertical */
            const double w = (phi_prev + 0.5 * PI) / (phi_prev - phi);
            rj_joint_pin_force(m, s, 0, at);
            at[0] = before[0] + w * (at[0] - before[0]);
            at[1] = before[1] + w * (at[1] - before[1]);
            break;
        }
        phi_prev = phi;
    }
    rjt_check(c, fabs(at[1] / (2.5 * mass * G) - 1) < 1e-3 && fabs(at[0]) < 1e-3 * mass * G,
              "pin force: a rod released level passes the vertical with 2.5 m g",
              "(%.6g, %.6g) N against (0, %.6g) N (%+.2e), dt 0.1 ms", at[0], at[1],
              2.5 * mass * G, at[1] / (2.5 * mass * G) - 1);
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
    test_pin_force_rod(c);
    test_pin_force_mixed(c);
    test_pin_force_inextensible(c);
    test_pin_force_bodies(c);
    test_pin_forces_pass(c);
}

/* A scene of one link alone: its model, a state and the caller's node forces (the
   refusal's message into msg). */
static int strip_model(rj_link_def *link, rj_model **m, rj_state **s, double **F, char *msg,
                       size_t size)
{
    rj_scene_def sc = rj_default_scene_def();
    rj_error err;
    sc.links = link;
    sc.link_count = 1;
    if (rj_model_create(&sc, m, &err, NULL) != RJ_OK) {
        snprintf(msg, size, "model refused: %.200s", err.msg);
        return 0;
    }
    rj_state_create(*m, s, NULL);
    *F = rj_state_node_forces(*m, *s);
    return 1;
}

/* ---- structural damping: free decay against eta omega_n / 2 and alpha / (2 omega_n) */

/* Mode n (1, 2) of a clamped-free Euler-Bernoulli beam at u = x / L. */
static double cantilever_mode(int n, double u)
{
    const double b = n == 1 ? 1.87510406871196 : 4.69409113297418;
    const double sg = (sinh(b) - sin(b)) / (cosh(b) + cos(b));
    return cosh(b * u) - cos(b * u) - sg * (sinh(b * u) - sin(b * u));
}

/* Link 0's deflection projected on mode n with the lumped masses: its modal coordinate. */
static double modal_coordinate(const rj_model *m, const rj_state *s, int n, int elements)
{
    double num = 0, den = 0;
    int k;
    for (k = 0; k <= elements; k++) {
        const double shape = cantilever_mode(n, (double) k / elements);
        double mass, rot, xy[2];
        rj_node_mass(m, 0, k, &mass, &rot);
        rj_node_position(m, s, 0, k, xy);
        num += mass * shape * xy[1];
        den += mass * shape * shape;
    }
    return num / den;
}

/* What a free decay gives: the mode's undamped omega and ratio from its peaks, and the
   accounts at the end. */
typedef struct decay {
    double omega, zeta;
    rj_energy e;
    int peaks;
} decay;

/* The peaks' decay rate sigma and period, by least squares on ln(peak) against time
   (the first peak, inside the pulse, left out): omega = sqrt(omega_d^2 + sigma^2). */
static void decay_fit(const double *t, const double *y, int n, decay *d)
{
    double st = 0, sy = 0, stt = 0, sty = 0, sigma, wd;
    int i;
    const int c = n - 1;
    for (i = 1; i < n; i++) {
        st += t[i];
        sy += log(y[i]);
        stt += t[i] * t[i];
        sty += t[i] * log(y[i]);
    }
    sigma = -(c * sty - st * sy) / (c * stt - st * st);
    wd = 2 * PI * (n - 2) / (t[n - 1] - t[1]);
    d->omega = sqrt(wd * wd + sigma * sigma);
    d->zeta = sigma / d->omega;
    d->peaks = n;
}

/* A stubby aluminium cantilever (1 m, 100 mm deep: its axial modes 200 times its first
   bending one, so that eta's bound leaves a usable step) struck by a short pulse of
   forces m_i phi_n(x_i), which the other modes hardly see, then left to ring until
   t_end. link: its damping. */
static int free_decay(rj_link_def link, int n, double t_end, decay *d, char *msg, size_t size)
{
    rj_model *m;
    rj_state *s;
    double *F, t[400], y[400], before = 0, last = 0, last_t = 0;
    int k, count = 0;
    link.length = 1.0;
    link.E = 70e9;
    link.rho = 2700;
    link.width = 0.02;
    link.height = 0.1;
    link.root = RJ_ROOT_CLAMPED;
    if (!strip_model(&link, &m, &s, &F, msg, size))
        return 0;
    for (k = 0; k <= link.elements; k++) {
        double mass, rot;
        rj_node_mass(m, 0, k, &mass, &rot);
        F[3 * k + 1] = 1e3 * mass * cantilever_mode(n, (double) k / link.elements);
    }
    while (rj_state_time(s) < 2e-4)
        rj_step(m, s);
    for (k = 0; k <= link.elements; k++)
        F[3 * k + 1] = 0;
    /* the modal coordinate's maxima */
    while (rj_state_time(s) < t_end && rj_step(m, s) == RJ_OK) {
        const double q = modal_coordinate(m, s, n, link.elements);
        if (last > before && last >= q && last > 0 && count < 400) {
            t[count] = last_t;
            y[count++] = last;
        }
        before = last;
        last = q;
        last_t = rj_state_time(s);
    }
    rj_state_energy(m, s, &d->e);
    snprintf(msg, size, "dt %.3g s, %.200s", rj_model_dt(m), rj_state_error(s));
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
    if (count < 4)
        return 0;
    decay_fit(t, y, count, d);
    return 1;
}

/* What swing_links gives: the tip after 0.1 s (NaN when refused), the model's step and
   stability bound, the accounts at the end. */
typedef struct swing_out {
    double tip[2];
    double dt, bound;
    rj_energy e;
} swing_out;

/* Two links of 10 elements hanging from a pin under gravity, released level, the first
   and second given (NULL: bar's flexible one); dt: given, or 0. Into out, the message
   into msg. */
static rj_result swing_links(const rj_link_def *first, const rj_link_def *second, double dt,
                             swing_out *out, char *msg, size_t size)
{
    rj_link_def l[2];
    rj_joint_def j[2];
    rj_scene_def sc = rj_default_scene_def();
    rj_model *m;
    rj_state *s;
    rj_error err;
    rj_result r;
    int k;
    for (k = 0; k < 2; k++) {
        l[k] = bar(RJ_LINK_FLEXIBLE, 10);
        j[k] = rj_default_joint_def();
        j[k].body1 = k - 1;
        j[k].body2 = k;
    }
    j[0].angle0 = 0;
    if (first)
        l[0] = *first;
    if (second)
        l[1] = *second;
    sc.links = l;
    sc.link_count = 2;
    sc.joints = j;
    sc.joint_count = 2;
    sc.solver.gravity[1] = -G;
    sc.solver.dt = dt;
    memset(out, 0, sizeof *out);
    out->tip[0] = out->tip[1] = NAN;
    r = rj_model_create(&sc, &m, &err, NULL);
    snprintf(msg, size, "%.300s", r == RJ_OK ? "" : err.msg);
    if (r != RJ_OK)
        return r;
    out->dt = rj_model_dt(m);
    out->bound = rj_model_dt_bound(m);
    rj_state_create(m, &s, NULL);
    r = rj_run(m, s, 0.1, 0, NULL, NULL);
    rj_node_position(m, s, 1, 10, out->tip);
    rj_state_energy(m, s, &out->e);
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
    return r;
}

/* swing_links with bar's first link: the tip after 0.1 s into tip. */
static rj_result swing_two(const rj_link_def *second, double dt, double tip[2], char *msg,
                           size_t size)
{
    swing_out out;
    const rj_result r = swing_links(NULL, second, dt, &out, msg, size);
    tip[0] = out.tip[0];
    tip[1] = out.tip[1];
    return r;
}

/* The damped path computes the elastic forces and moves the nodes as the fused kernels
   do: with damping too small to move a bit (eta 1e-300 s, mass_damping 1e-300 1/s) the
   tip lands on the undamped run's bits. */
static void test_damping_path(rjt_ctx *c)
{
    double plain[2], damped[2];
    char msg[320];
    rj_link_def second = bar(RJ_LINK_FLEXIBLE, 10);
    swing_two(NULL, 0, plain, msg, sizeof msg);
    second.mass_damping = 1e-300;
    second.eta = 1e-300;
    swing_two(&second, 0, damped, msg, sizeof msg);
    rjt_check(c, plain[0] == damped[0] && plain[1] == damped[1],
              "damping: the damped path without damping gives the fused kernels' bits",
              "tip (%.17g, %.17g) and (%.17g, %.17g)", plain[0], plain[1], damped[0], damped[1]);
}

/* Kelvin-Voigt damping on the rates at n + 1/2 (src/viscous.h) keeps the undamped links'
   bound whatever eta: eta 1e-3 s damps their fastest mode (omega_max near 1e5 rad/s) at
   about 50 times critical, and the swing runs at 0.9 of the undamped bound, its balance
   closed by W_structural (a loss of about 1e-4 of the swing's kinetic energy: the
   ringing the release starts). The link pinned to a rigid body takes eta on the lagged rates,
   which shortens the bound: a step the undamped links take is refused, naming it. */
static void test_damping_bound(rjt_ctx *c)
{
    rj_link_def second = bar(RJ_LINK_FLEXIBLE, 10), body = bar(RJ_LINK_RIGID, 10);
    swing_out plain, damped, carried, refused;
    char msg[320], msg2[320];
    rj_result r, r2;
    swing_links(NULL, NULL, 0, &plain, msg, sizeof msg);
    second.eta = 1e-3;
    r = swing_links(NULL, &second, 0, &damped, msg, sizeof msg);
    rjt_check(c, r == RJ_OK && damped.bound == plain.bound && damped.dt == plain.dt &&
                     damped.e.lost_structural > 1e-6 * damped.e.kinetic &&
                     fabs(damped.e.balance) < 1e-9 * damped.e.kinetic &&
                     fabs(damped.tip[1] - plain.tip[1]) > 1e-6,
              "damping: implicit Kelvin-Voigt keeps the undamped bound at 50 x critical",
              "result %d (%s): bound %.6g s against %.6g s undamped, dt %.6g s; W_structural "
              "%.4g J of kinetic %.4g J, balance %.3g J; tip y %.6f m against %.6f m undamped",
              (int) r, msg, damped.bound, plain.bound, damped.dt, damped.e.lost_structural,
              damped.e.kinetic, damped.e.balance, damped.tip[1], plain.tip[1]);
    swing_links(&body, NULL, 0, &carried, msg, sizeof msg);
    r = swing_links(&body, &second, carried.dt, &refused, msg, sizeof msg);
    r2 = swing_links(&body, NULL, carried.dt, &carried, msg2, sizeof msg2);
    rjt_check(c, r == RJ_ERR_UNSTABLE_DT && strstr(msg, "structural damping") && r2 == RJ_OK,
              "damping: eta on a link a rigid body carries is lagged: it shortens the bound",
              "result %d at the undamped step %.4g s (%d): %s", (int) r, carried.dt, (int) r2,
              msg);
}

/* How a cantilever's root is held in held_period. */
enum { HOLD_CLAMP, HOLD_LOCK, HOLD_FRICTION, HOLD_PROFILE, HOLD_COUNT };

/* A bar of 10 elements with a 0.5 kg tip mass at 0.5 rad, no gravity, held at its root
   by hold, Kelvin-Voigt eta: its tip struck for 10 ms, then the period of its ringing
   across the bar (upward zero crossings, 3 s at most); 0 when it fails (msg). */
static double held_period(int hold, double eta, char *msg, size_t size)
{
    rj_link_def l = bar(RJ_LINK_FLEXIBLE, 10);
    rj_joint_def j = rj_default_joint_def();
    rj_actuator_def a = rj_default_actuator_def();
    rj_scene_def sc = rj_default_scene_def();
    rj_model *m;
    rj_state *s;
    rj_error err;
    double prev = 0, t_prev = 0, up[10], *F;
    int ups = 0;
    l.tip_mass = 0.5;
    l.eta = eta;
    sc.links = &l;
    sc.link_count = 1;
    j.body1 = -1;
    j.body2 = 0;
    j.angle0 = 0.5;
    if (hold == HOLD_CLAMP) {
        l.root = RJ_ROOT_CLAMPED;
        l.angle = 0.5;
    } else {
        sc.joints = &j;
        sc.joint_count = 1;
    }
    /* a latch locked at its first step, friction that sticks, a profile at rest */
    if (hold == HOLD_LOCK) {
        j.has_forward = 1;
        j.forward = 0.5;
        j.lock = 1;
        j.method = RJ_METHOD_FORCED;
        j.rate0 = 0.01;
    }
    if (hold == HOLD_FRICTION)
        j.friction = 100;
    if (hold == HOLD_PROFILE) {
        a.type = RJ_ACTUATOR_PRESCRIBED;
        a.profile = RJ_PROFILE_RAMP;
        sc.actuators = &a;
        sc.actuator_count = 1;
    }
    if (rj_model_create(&sc, &m, &err, NULL) != RJ_OK) {
        snprintf(msg, size, "%.200s", err.msg);
        return 0;
    }
    rj_state_create(m, &s, NULL);
    F = rj_state_node_forces(m, s);
    F[3 * 10 + 1] = 5;
    while (rj_state_time(s) < 0.01)
        rj_step(m, s);
    F[3 * 10 + 1] = 0;
    while (rj_state_time(s) < 3 && ups < 10 && rj_step(m, s) == RJ_OK) {
        double p[2], q;
        rj_node_position(m, s, 0, 10, p);
        q = -sin(0.5) * p[0] + cos(0.5) * p[1];
        if (prev < 0 && q >= 0)
            up[ups++] = t_prev + (rj_state_time(s) - t_prev) * (-prev) / (q - prev);
        prev = q;
        t_prev = rj_state_time(s);
    }
    snprintf(msg, size, "%.200s", rj_state_error(s));
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
    return ups < 10 ? 0 : (up[9] - up[1]) / 8;
}

/* A cantilever held at its root by a joint rings as the clamped one, with Kelvin-Voigt
   damping taken implicitly too: the held pin's rotation is held in the damping's solve
   (src/viscous.h). When it was not, the light pin node followed the damping there and
   the hold undid it, so that the damping forces came from rates the step did not take:
   the locked root rang 40 % slower at eta 1e-3 s and blew up at 1e-2 s. eta 1e-2 s is
   12 % of critical on the first mode, which moves its period by 0.7 % (to 0.2684 s). */
static void test_damping_held_root(rjt_ctx *c)
{
    static const char *const name[HOLD_COUNT] = { "clamped", "forced lock", "friction",
                                                  "prescribed" };
    double period[HOLD_COUNT], plain;
    char msg[240];
    int k;
    plain = held_period(HOLD_CLAMP, 0, msg, sizeof msg);
    for (k = 0; k < HOLD_COUNT; k++)
        period[k] = held_period(k, 1e-2, msg, sizeof msg);
    for (k = 1; k < HOLD_COUNT; k++)
        rjt_check(c, period[0] > 0 && fabs(period[k] / period[0] - 1) < 1e-5,
                  "damping: a root held by a joint rings as the clamped one with Kelvin-Voigt",
                  "%s: period %.7f s against %.7f s clamped (%.2g; within 1e-5), %.7f s "
                  "undamped; %s",
                  name[k], period[k], period[0], period[k] / period[0] - 1, plain, msg);
}

/* The chain of `make bench`'s feature rows (two links of 10 elements, 1 m, 50 x 20 mm,
   the first pinned to the ground and spinning at 2 rad/s, the second turning at 0.2
   rad/s on it) with Kelvin-Voigt damping = 0.02 5 on both, at dt (0: automatic) to 0.2
   s: how far its tip is from link 2's middle node, less 0.5 m (the centrifugal stretch
   of the outer half of link 2), and the step. */
static double spin_stretch(double dt, double *dt_used)
{
    rj_link_def L[2];
    rj_joint_def J[2];
    rj_scene_def sc = rj_default_scene_def();
    rj_model *m;
    rj_state *s;
    rj_error err;
    double tip[2], mid[2];
    int i;
    for (i = 0; i < 2; i++) {
        L[i] = rj_default_link_def();
        L[i].length = 1.0;
        L[i].elements = 10;
        L[i].height = 0.02;
        L[i].width = 0.05;
        L[i].damping[0] = 0.02;
        L[i].damping[1] = 5;
        J[i] = rj_default_joint_def();
        J[i].body1 = i - 1;
        J[i].body2 = i;
        J[i].angle0 = PI;
    }
    J[0].rate0 = 2.0;
    J[1].rate0 = 0.2;
    sc.links = L;
    sc.link_count = 2;
    sc.joints = J;
    sc.joint_count = 2;
    sc.solver.dt = dt;
    if (rj_model_create(&sc, &m, &err, NULL) != RJ_OK)
        return NAN;
    *dt_used = rj_model_dt(m);
    rj_state_create(m, &s, NULL);
    rj_run(m, s, 0.2, 0, NULL, NULL);
    rj_node_position(m, s, 1, 10, tip);
    rj_node_position(m, s, 1, 5, mid);
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
    return hypot(tip[0] - mid[0], tip[1] - mid[1]) - 0.5;
}

/* Implicit Kelvin-Voigt damping is objective: a link turning rigidly has no strain rate.
   The strains' rates are taken along the chord at n + 1/2; along the chord at n, where
   v^{n+1/2} is not square to it, the spinning chain showed an axial rate of omega^2 dt / 2
   relative, and the axial viscosity made the stretch of link 2's outer half 6.5e-8 m at
   the automatic step against 3.8e-8 m at a 40 times smaller one (70 % off). */
static void test_damping_spin(rjt_ctx *c)
{
    double dt_big, dt_small;
    const double big = spin_stretch(0, &dt_big);
    const double small = spin_stretch(dt_big / 40, &dt_small);
    rjt_check(c, fabs(big / small - 1) < 0.01,
              "damping: implicit Kelvin-Voigt on a spinning chain stretches it as a 40 times smaller step",
              "stretch %.5g m at dt %.4g s against %.5g m at %.4g s (%+.2g; within 1 %%)", big,
              dt_big, small, dt_small, big / small - 1);
}

/* Two flexible links of 10 elements hanging from a pin under gravity, released level,
   both joints chord-referenced (l, j outlive sc). */
static void chord_pair_scene(rj_link_def l[2], rj_joint_def j[2], rj_scene_def *sc)
{
    int k;
    for (k = 0; k < 2; k++) {
        l[k] = bar(RJ_LINK_FLEXIBLE, 10);
        j[k] = rj_default_joint_def();
        j[k].body1 = k - 1;
        j[k].body2 = k;
        j[k].reference = RJ_REF_CHORD;
    }
    j[0].angle0 = 0;
    *sc = rj_default_scene_def();
    sc->links = l;
    sc->link_count = 2;
    sc->joints = j;
    sc->joint_count = 2;
    sc->solver.gravity[1] = -G;
}

/* Joints with the chord reference (the paper's literal form: a joint's torque acts as
   force couples on the chords I -> K and J -> L): two links of 10 elements hanging from a
   pin under gravity, released level, both joints chord-referenced with a spring, a damper
   and friction on the second. Each step the ground pin's force is what the whole chain's
   nodes gain, sum m (a - g), and the second joint's what link 2's gain: the couples on the
   pin nodes are not the pin's. Largest miss over 2000 steps against the largest force. */
static void test_chord_pin_forces(rjt_ctx *c)
{
    rj_link_def l[2];
    rj_joint_def j[2];
    rj_scene_def sc;
    rj_model *m;
    rj_state *s;
    rj_error err;
    double before[2][11][2], miss = 0, peak = 0;
    int k, q, i, known = 1;
    chord_pair_scene(l, j, &sc);
    j[1].spring_k = 20;
    j[1].spring_free_angle = 2.5;
    j[1].damping = 0.05;
    j[1].friction = 0.2;
    if (rj_model_create(&sc, &m, &err, NULL) != RJ_OK) {
        rjt_check(c, 0, "chord reference: the pin forces' scene builds", "%s", err.msg);
        return;
    }
    rj_state_create(m, &s, NULL);
    for (q = 0; q < 2000; q++) {
        double F[4], gain[2][2] = { { 0, 0 }, { 0, 0 } };
        const double kick = q == 0 ? 0.5 * rj_model_dt(m) : rj_model_dt(m);
        for (k = 0; k < 2; k++)
            for (i = 0; i <= 10; i++)
                rj_node_velocity(m, s, k, i, before[k][i]);
        if (rj_step(m, s) != RJ_OK)
            break;
        known &= rj_joint_pin_forces(m, s, F) == RJ_OK && F[0] == F[0] && F[2] == F[2];
        /* what each link's nodes gained, m (a - g) */
        for (k = 0; k < 2; k++)
            for (i = 0; i <= 10; i++) {
                double v[2], mass;
                rj_node_velocity(m, s, k, i, v);
                rj_node_mass(m, k, i, &mass, NULL);
                gain[k][0] += mass * (v[0] - before[k][i][0]) / kick;
                gain[k][1] += mass * ((v[1] - before[k][i][1]) / kick + G);
            }
        for (i = 0; i < 2; i++) {
            miss = fmax(miss, fabs(F[i] - gain[0][i] - gain[1][i]));
            miss = fmax(miss, fabs(F[2 + i] - gain[1][i]));
            peak = fmax(peak, fmax(fabs(F[i]), fabs(F[2 + i])));
        }
    }
    rjt_check(c, q == 2000 && known && miss < 1e-9 * peak && peak > 1,
              "chord reference: the pin forces are what the links below gain",
              "%d steps, every force known %d; largest miss %.3g N of %.4g N (within 1e-9); %s",
              q, known, miss, peak, rj_state_error(s));
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
}

/* Friction holding a chord-referenced joint stuck under gravity: two flexible links
   hanging from a pin, the second bent at 2.5 rad on a joint with 50 N m of friction
   (about 40 times what holds it). The rate friction stops is predicted from the chords'
   nodes, the pin node's with its group's gravity: without it the prediction saw a rate
   of kick g across the chord that was not there, and the joint crept 5.9e-4 rad in 1 s. */
static void test_chord_friction_stuck(rjt_ctx *c)
{
    rj_link_def l[2];
    rj_joint_def j[2];
    rj_scene_def sc;
    rj_model *m;
    rj_state *s;
    rj_error err;
    double start, moved;
    chord_pair_scene(l, j, &sc);
    j[1].angle0 = 2.5;
    j[1].friction = 50;
    if (rj_model_create(&sc, &m, &err, NULL) != RJ_OK) {
        rjt_check(c, 0, "chord reference: friction holds a stuck joint", "%s", err.msg);
        return;
    }
    rj_state_create(m, &s, NULL);
    rj_step(m, s);
    start = rj_joint_theta_running(m, s, 1);
    rj_run(m, s, 1.0, 0, NULL, NULL);
    moved = rj_joint_theta_running(m, s, 1) - start;
    rjt_check(c, fabs(moved) < 1e-9 && rj_state_time(s) >= 1.0,
              "chord reference: friction holds a stuck joint under gravity",
              "joint 2 moved %.3g rad in 1 s (within 1e-9), friction %.4g N m; %s", moved,
              rj_joint_torque(m, s, 1, RJ_TORQUE_FRICTION), rj_state_error(s));
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
}

/* Kelvin-Voigt damping set as 1 % of critical at the beam theory's first frequency
   (damping = 0.01 82.26 Hz): each of the first two modes decays at eta omega_n / 2 of its
   own omega; mass-proportional damping at alpha / (2 omega_n); the energy balance holds
   with the loss in W_structural. */
static void test_damping_decay(rjt_ctx *c)
{
    static const struct {
        int mode, elements;
        double ratio, alpha, t_end, tol;
    } cases[] = {
        { 1, 10, 0.01, 0, 0.3, 1e-3 },  { 2, 20, 0.01, 0, 0.02, 2e-3 },
        { 1, 10, 0, 20.0, 0.3, 1e-3 }, { 2, 20, 0, 200.0, 0.1, 1e-3 },
    };
    /* f1 = (1.8751^2 / 2 pi) sqrt(E I / (rho A)) / L^2 */
    const double f1 = 1.87510406871196 * 1.87510406871196 / (2 * PI) *
                      sqrt(70e9 / 2700 * 0.1 * 0.1 / 12.0);
    size_t k;
    for (k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        rj_link_def link = rj_default_link_def();
        decay d;
        char msg[300];
        double eta, want;
        int ok;
        link.elements = cases[k].elements;
        link.damping[0] = cases[k].ratio;
        link.damping[1] = f1;
        link.mass_damping = cases[k].alpha;
        eta = cases[k].ratio / (PI * f1);
        memset(&d, 0, sizeof d);
        ok = free_decay(link, cases[k].mode, cases[k].t_end, &d, msg, sizeof msg);
        want = eta * d.omega / 2 + cases[k].alpha / (2 * d.omega);
        rjt_check(c, ok && fabs(d.zeta / want - 1) < cases[k].tol &&
                         fabs(d.e.balance) < 1e-9 * d.e.lost_structural &&
                         d.e.lost_structural > 0.9 * (d.e.lost_structural + d.e.kinetic + d.e.strain),
                  cases[k].ratio > 0 ? "damping: Kelvin-Voigt decay of a cantilever mode is eta omega / 2"
                                     : "damping: mass-proportional decay of a cantilever mode is alpha / (2 omega)",
                  "mode %d, %d elements: zeta %.6f against %.6f (%.2g off, within %g) at %.2f Hz, "
                  "%d peaks; W_structural %.4g J, balance %.3g J; %s",
                  cases[k].mode, cases[k].elements, d.zeta, want, d.zeta / want - 1, cases[k].tol,
                  d.omega / (2 * PI), d.peaks, d.e.lost_structural, d.e.balance, msg);
    }
}

/* ---- elastic-plastic layers: the section law against the continuum's, collapse, the
   residual of unloading, the balance with the plastic work */

/* The strip of the plastic tests: aluminium-like, 0.5 m, 20 x 10 mm, yield 100 MPa,
   clamped; M_y = sigma_y b h^2 / 6 = 33.3 N m, M_p = sigma_y b h^2 / 4 = 50 N m. Its
   first mode is near 33 Hz. */
#define PL_L 0.5
#define PL_E 70e9
#define PL_B 0.02
#define PL_H 0.01
#define PL_YIELD 100e6
#define PL_I (PL_B * PL_H * PL_H * PL_H / 12.0)
#define PL_MY (PL_YIELD * PL_B * PL_H * PL_H / 6.0)
#define PL_MP (PL_YIELD * PL_B * PL_H * PL_H / 4.0)

/* What a slow ramp of a tip load gives: the load and the root section's moment when a
   layer first yielded, the last sample's root-section curvature and moment, the
   accounts. */
typedef struct ramp_out {
    double first_yield;   /* the load when a plastic strain first appeared (-1: never) */
    double yield_moment;  /* N m, |the root section's moment| then */
    double kappa;         /* 1/m, element 0's curvature at its first section, at the end */
    double moment;        /* N m, the bending moment there (statics: rj_element_loads) */
    double tip;           /* m, the tip's y */
    double peak_kappa;    /* 1/m, the curvature at the peak load */
    rj_energy e;
} ramp_out;

/* Element 0's curvature at its first Gauss section, from its nodes' rotations and chord:
   ((6 xi - 4) th_a + (6 xi - 2) th_b) / l0. */
static double root_kappa(const rj_model *m, const rj_state *s, double l0)
{
    const double xi = 0.21132486540518713;
    double a[2], b[2], chord, tha, thb;
    rj_node_position(m, s, 0, 0, a);
    rj_node_position(m, s, 0, 1, b);
    chord = atan2(b[1] - a[1], b[0] - a[0]);
    tha = rj_node_rotation(m, s, 0, 0) - chord;
    thb = rj_node_rotation(m, s, 0, 1) - chord;
    return ((6 * xi - 4) * tha + (6 * xi - 2) * thb) / l0;
}

/* The bending moment at element 0's first section (statics: rj_element_loads, linear
   along the element). */
static double root_moment(const rj_model *m, const rj_state *s)
{
    const double xi = 0.21132486540518713;
    double loads[5];
    rj_element_loads(m, s, 0, 0, loads);
    return fabs(loads[2] * (1 - xi) + loads[3] * xi);
}

/* A clamped strip of `elements` elements and `layers` layers (hardening H), its tip loaded
   by a moment (moment set) or a downward force of `peak`, ramped up over 0.5 s, held
   0.25 s, and with `unload` ramped back to 0 over 0.5 s and held 0.25 s; mass_damping
   200 1/s (about half critical on the first mode) keeps the ramp quasi-static. */
static int plastic_ramp(int layers, int elements, double H, int moment, double peak,
                        int unload, ramp_out *out, char *msg, size_t size)
{
    rj_link_def link = rj_default_link_def();
    rj_model *m;
    rj_state *s;
    const double t_end = unload ? 1.5 : 0.75;
    double *F;
    rj_result r = RJ_OK;
    link.length = PL_L;
    link.elements = elements;
    link.E = PL_E;
    link.rho = 2700;
    link.width = PL_B;
    link.height = PL_H;
    link.layers = layers;
    link.yield = PL_YIELD;
    link.hardening = H;
    link.mass_damping = 200;
    link.root = RJ_ROOT_CLAMPED;
    if (!strip_model(&link, &m, &s, &F, msg, size))
        return 0;
    out->first_yield = -1;
    while (rj_state_time(s) < t_end && r == RJ_OK) {
        const double t = rj_state_time(s);
        /* cosine ramps: no jump in the load's rate to ring the axial modes, which the
           mass-proportional damping hardly touches and whose ringing ratchets the layers
           (a linear ramp's start of unloading added 0.6 % to the plastic strain) */
        const double up = t < 0.5 ? 0.5 - 0.5 * cos(PI * t / 0.5) : 1.0;
        const double down = t > 0.75 ? (t < 1.25 ? 0.5 + 0.5 * cos(PI * (t - 0.75) / 0.5) : 0.0)
                                     : 1.0;
        const double load = peak * up * down;
        F[3 * elements + (moment ? 2 : 1)] = moment ? load : -load;
        r = rj_step(m, s);
        if (out->first_yield < 0 && rj_element_plastic_strain(m, s, 0, 0, 0, 0) != 0) {
            out->first_yield = load;
            out->yield_moment = root_moment(m, s);
        }
        if (t < 0.75)
            out->peak_kappa = root_kappa(m, s, PL_L / elements);
    }
    out->moment = root_moment(m, s);
    out->kappa = root_kappa(m, s, PL_L / elements);
    {
        double xy[2];
        rj_node_position(m, s, 0, elements, xy);
        out->tip = xy[1];
    }
    rj_state_energy(m, s, &out->e);
    snprintf(msg, size, "%.200s", r == RJ_OK ? "" : rj_state_error(s));
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
    return r == RJ_OK;
}

/* Pure bending (a tip moment: every section carries it, whatever the shape): the layered
   section's first yield where its outer layer's mid-depth reaches the yield stress,
   M_y / (1 - 1/n); its curvature at 1.35 M_y against the continuum's elastic-perfectly-
   plastic kappa_y / sqrt(3 - 2 M / M_y) as the layers are refined; the balance with
   the plastic work. */
static void test_plastic_bending(rjt_ctx *c)
{
    static const int layers[3] = { 8, 16, 32 };
    const double ky = PL_MY / (PL_E * PL_I);
    const double exact = ky / sqrt(3 - 2 * 1.35);
    const double first = PL_MY / (1 - 1.0 / 8);
    double err[3];
    ramp_out below, above, o;
    char msg[256];
    int k, ok;
    ok = plastic_ramp(8, 2, 0, 1, 0.99 * first, 0, &below, msg, sizeof msg) &&
         plastic_ramp(8, 2, 0, 1, 1.01 * first, 0, &above, msg, sizeof msg);
    rjt_check(c, ok && below.first_yield < 0 && above.first_yield > 0.99 * first,
              "plastic: 8 layers in pure bending first yield at M_y / (1 - 1/8), the outer layer's mid-depth",
              "none at 0.99 of %.4g N m; at 1.01 from %.4g N m (%.4f of it); %s", first,
              above.first_yield, above.first_yield / first, msg);
    for (k = 0; k < 3; k++) {
        ok = plastic_ramp(layers[k], 2, 0, 1, 1.35 * PL_MY, 0, &o, msg, sizeof msg);
        err[k] = ok ? o.kappa / exact - 1 : NAN;
    }
    rjt_check(c, fabs(err[2]) < 0.01 && fabs(err[1]) < fabs(err[0]) && fabs(err[2]) < fabs(err[1]),
              "plastic: the layered section's curvature at 1.35 M_y approaches the continuum's as the layers are refined",
              "kappa off kappa_y / sqrt(3 - 2.7) = %.5g 1/m by %+.2e, %+.2e, %+.2e at 8, 16, 32 layers",
              exact, err[0], err[1], err[2]);
    /* the balance: the step's forces at x^n take the plastic strains returned there, the
       elastic part's trapezoid the ones before; first order in dt, 9.2e-5 measured */
    rjt_check(c, fabs(o.e.balance) < 1e-3 * o.e.lost_plastic && o.e.lost_plastic > 0,
              "plastic: the energy balance closes with the plastic work (W_plastic)",
              "32 layers at 1.35 M_y: balance %.3g J, W_plastic %.4g J, W_structural %.4g J, work %.4g J",
              o.e.balance, o.e.lost_plastic, o.e.lost_structural, o.e.work_applied);
}

/* Unloading is elastic: the curvature left when the moment is taken off is the loaded one
   less M / EI, to the ramp's dynamics; against the continuum's kappa_y (1 / sqrt(3 - 2 M /
   M_y) - M / M_y) as the layers are refined. With hardening the section carries more at
   the same curvature. */
static void test_plastic_unloading(rjt_ctx *c)
{
    const double ky = PL_MY / (PL_E * PL_I), M = 1.35 * PL_MY;
    const double continuum = ky * (1 / sqrt(3 - 2 * 1.35) - 1.35);
    ramp_out o, hard;
    char msg[256];
    int ok = plastic_ramp(32, 2, 0, 1, M, 1, &o, msg, sizeof msg);
    const double elastic = o.peak_kappa - M / (PL_E * PL_I);
    rjt_check(c, ok && fabs(o.kappa / elastic - 1) < 1e-3 && fabs(o.kappa / continuum - 1) < 0.03,
              "plastic: unloading is elastic and leaves the bilinear model's residual curvature",
              "residual %.6g 1/m; loaded %.6g less M / EI: %.6g (%+.1e); continuum %.6g (%+.1e); %s",
              o.kappa, o.peak_kappa, elastic, o.kappa / elastic - 1, continuum,
              o.kappa / continuum - 1, msg);
    ok = plastic_ramp(32, 2, 0.1 * PL_E, 1, M, 0, &hard, msg, sizeof msg) &&
         plastic_ramp(32, 2, 0, 1, M, 0, &o, msg, sizeof msg);
    rjt_check(c, ok && hard.kappa < o.kappa && hard.kappa > M / (PL_E * PL_I),
              "plastic: kinematic hardening (H = E / 10) stiffens the yielding section",
              "curvature at 1.35 M_y %.5g 1/m with it, %.5g without, %.5g elastic", hard.kappa,
              o.kappa, M / (PL_E * PL_I));
}

/* A cantilever under a slowly rising tip load: its root yields first where the moment at
   its first section reaches the layered first-yield moment (the continuum's sigma_y b
   h^2 / 6 as the layers are refined), and at a curvature of 10 kappa_y there (a hinge
   forming) the section carries a moment approaching M_p = sigma_y b h^2 / 4: the tip load
   approaching M_p / L, the collapse load. */
static void test_plastic_collapse(rjt_ctx *c)
{
    static const int layers[3] = { 8, 16, 32 };
    const double first = PL_MY / (1 - 1.0 / 32);
    double at[3];
    ramp_out o;
    char msg[256];
    int k, ok = 1;
    for (k = 0; k < 3; k++) {
        ok &= plastic_ramp(layers[k], 10, 0, 0, 1.2 * PL_MP / PL_L, 0, &o, msg, sizeof msg);
        at[k] = o.moment;
    }
    rjt_check(c, ok && fabs(o.yield_moment / first - 1) < 0.01,
              "plastic: a cantilever's root first yields under the layered first-yield moment (sigma_y b h^2 / 6 as layers refine)",
              "32 layers: at P = %.4g N (M_y / L = %.4g N), the root section's moment %.5g N m against M_y / (1 - 1/32) = %.5g N m (%+.1e), M_y = %.4g N m; %s",
              o.first_yield, PL_MY / PL_L, o.yield_moment, first, o.yield_moment / first - 1, PL_MY, msg);
    rjt_check(c, ok && at[2] < at[1] && at[1] < at[0] && at[2] / PL_MP - 1 < 0.05,
              "plastic: the root's moment under 1.2 M_p / L approaches M_p as the layers are refined",
              "root section's moment %.4g, %.4g, %.4g N m at 8, 16, 32 layers against M_p = %.4g N m",
              at[0], at[1], at[2], PL_MP);
}

/* With a yield stress no stress reaches, the layered material path gives the elastic
   element's bits (the same layers: their sums make EA and EI). */
static void test_plastic_elastic_limit(rjt_ctx *c)
{
    double plain[2], layered[2];
    char msg[320];
    rj_link_def second = bar(RJ_LINK_FLEXIBLE, 10);
    second.layers = 4;
    swing_two(&second, 0, plain, msg, sizeof msg);
    second.yield = 1e30;
    swing_two(&second, 0, layered, msg, sizeof msg);
    rjt_check(c, plain[0] == layered[0] && plain[1] == layered[1],
              "plastic: layers that never yield give the elastic element's bits",
              "tip (%.17g, %.17g) and (%.17g, %.17g) %s", plain[0], plain[1], layered[0], layered[1],
              msg);
}

/* The axial laws against their exact statics: a soft clamped bar pulled along its axis by
   P = 0.03 EA settles at the engineering strain e that solves EA e = P (Biot) or
   EA (e + e^2/2)(1 + e) = P (Green, bisected here). At 0.1 EA the Green bar stiffens by
   30 % and outruns the bound taken at its start: the step stops, energy created. */
static void test_axial_laws(rjt_ctx *c)
{
    int law;
    for (law = 0; law < 2; law++) {
        rj_link_def link = bar(RJ_LINK_FLEXIBLE, 4);
        rj_scene_def sc = rj_default_scene_def();
        rj_model *m;
        rj_state *s;
        rj_error err;
        double *F, xy[2], EA, P, e, lo = 0, hi = 0.2;
        int k;
        link.E = 1e6;
        link.root = RJ_ROOT_CLAMPED;
        link.strain = law ? RJ_STRAIN_BIOT : RJ_STRAIN_GREEN;
        EA = link.E * link.width * link.height;
        P = 0.03 * EA;
        sc.links = &link;
        sc.link_count = 1;
        if (rj_model_create(&sc, &m, &err, NULL) != RJ_OK) {
            rjt_check(c, 0, "axial law: model", "%s", err.msg);
            return;
        }
        rj_state_create(m, &s, NULL);
        F = rj_state_node_forces(m, s);
        F[3 * 4] = P;
        rj_settle(m, s, 1e-14, 1000000);
        rj_node_position(m, s, 0, 4, xy);
        for (k = 0; k < 200 && !law; k++) {
            const double mid = 0.5 * (lo + hi);
            if (EA * (mid + 0.5 * mid * mid) * (1 + mid) > P)
                hi = mid;
            else
                lo = mid;
        }
        e = law ? P / EA : 0.5 * (lo + hi);
        rjt_check(c, fabs(xy[0] - (1 + e)) < 1e-7,
                  law ? "axial law: Biot, a bar pulled by 0.03 EA stretches by P / EA"
                      : "axial law: Green, a bar pulled by 0.03 EA stretches by EA (e + e^2/2)(1 + e) = P",
                  "tip x %.9f m against %.9f m (%+.1e)", xy[0], 1 + e, xy[0] - (1 + e));
        rj_state_destroy(s, NULL);
        rj_model_destroy(m, NULL);
    }
}

/* Scene files: the material keys of damping and yielding layers on a material, taken by
   a link and written back so that they read the same; the material's ratio becomes the
   model's eta = ratio / (pi f). Bad combinations are refused naming the field. */
static void test_material_keys(rjt_ctx *c)
{
    static const char text[] = "material steel\n  E = 2e11  rho = 7800  damping = 0.02 8\n"
                               "  mass_damping = 0.5  yield = 2.5e8  hardening = 2e9\n"
                               "  strain = biot\n"
                               "link a\n  length = 1  elements = 4  layers = 6\n"
                               "  material = steel\n  root = clamped\n";
    static const struct {
        const char *text, *field;
    } bad[] = {
        { "link a\n  fidelity = rigid  eta = 1e-4\n", "eta" },
        { "link a\n  damping = 0.02 0\n", "damping" },
        { "link a\n  eta = 1e-4  damping = 0.02 8\n", "damping" },
        { "link a\n  yield = 2e8\n", "layers" },
        { "link a\n  area = 1e-4  inertia = 1e-9  yield = 2e8\n", "yield" },
        { "link a\n  fidelity = inextensible  strain = biot\n", "strain" },
        { "link a\n  strain = hooke\n", "strain" },
        { "link a\n  yield = -1\n", "yield" },
    };
    rj_scene_file f, g;
    rj_error err;
    char buf[4096];
    size_t n, k;
    int ok = rj_scene_parse(text, sizeof text - 1, "m.rjs", &f, &err) == RJ_OK;
    const rj_link_def *d = ok ? &f.links[0] : NULL;
    rjt_check(c, ok && d->damping[0] == 0.02 && d->damping[1] == 8 && d->mass_damping == 0.5 &&
                     d->yield == 2.5e8 && d->hardening == 2e9 && d->strain == RJ_STRAIN_BIOT,
              "material keys: damping, mass_damping, yield, hardening and strain pass to the link",
              "%s", ok ? "read" : err.msg);
    if (!ok)
        return;
    {
        rj_scene_def def = rj_scene_file_def(&f);
        n = rj_scene_write(&def, NULL, NULL, buf, sizeof buf);
        ok = n > 0 && n <= sizeof buf && rj_scene_parse(buf, n - 1, "w.rjs", &g, &err) == RJ_OK;
        rjt_check(c, ok && g.links[0].damping[0] == 0.02 && g.links[0].damping[1] == 8 &&
                         g.links[0].yield == 2.5e8 && g.links[0].strain == RJ_STRAIN_BIOT &&
                         g.links[0].mass_damping == 0.5 && g.links[0].hardening == 2e9,
                  "material keys: written back, they read the same", "%s",
                  ok ? "same" : err.msg);
        if (ok)
            rj_scene_file_free(&g);
    }
    rj_scene_file_free(&f);
    for (k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        rj_result r = rj_scene_parse(bad[k].text, strlen(bad[k].text), "b.rjs", &f, &err);
        if (r == RJ_OK) {
            rj_scene_def def = rj_scene_file_def(&f);
            rj_model *m = NULL;
            r = rj_model_create(&def, &m, &err, NULL);
            if (m)
                rj_model_destroy(m, NULL);
            rj_scene_file_free(&f);
        }
        rjt_check(c, r != RJ_OK && strstr(err.msg, bad[k].field) != NULL,
                  "material keys: a bad combination is refused, naming the field",
                  "case %d (%s): %s", (int) k, bad[k].field, err.msg);
    }
}

/* ---- peaks in the state */

/* A rigid rod released level, tracking peaks: its largest pin force is 2.5 m g, at the
   vertical (a quarter of the swing's period, the elliptic integral's K(sin 45 deg)
   sqrt(I / (m g d))); before tracking, none. */
static void test_peaks_rigid(rjt_ctx *c)
{
    rj_link_def l[1];
    rj_joint_def j[1];
    rj_model *m;
    rj_state *s;
    rj_error err;
    rj_peak before, p;
    double mass, rot, quarter;
    if (!rigid_chain(1, 0.0, 1e-4, l, j, &m, &s, &err)) {
        rjt_check(c, 0, "peaks: rod", "%s", err.msg);
        return;
    }
    mass = 2700 * 0.02 * 0.01;
    before = rj_joint_peak_pin_force(m, s, 0);
    rj_state_track_peaks(m, s, 1);
    rj_run(m, s, 0.6, 0, NULL, NULL);
    p = rj_joint_peak_pin_force(m, s, 0);
    /* I / (m g d) = (L^2 / 3) / (g L / 2); K(sin 45 deg) = 1.8540746773 */
    quarter = 1.8540746773013719 * sqrt(2.0 / (3.0 * G));
    (void) rot;
    rjt_check(c, before.value == -1 && fabs(p.value / (2.5 * mass * G) - 1) < 1e-3 &&
                     fabs(p.time - quarter) < 2e-4 && p.element == -1,
              "peaks: a rigid rod released level peaks at 2.5 m g at the vertical",
              "before tracking %g; %.6g N against %.6g N (%+.1e) at t = %.5f s against %.5f s",
              before.value, p.value, 2.5 * mass * G, p.value / (2.5 * mass * G) - 1, p.time,
              quarter);
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
}

/* A cantilever struck by a tip load held on: its largest bending moment is the largest
   of rj_element_loads over every element's ends and every step, to the bit, at the clamp
   (element 0, its first node), above the static P L (the first swing overshoots); a
   checkpoint taken halfway resumes to the same peaks; every 4th step's accounts
   (solver.energy_every 4) give peaks no larger; in place, no moments. */
static void test_peaks_flexible(rjt_ctx *c)
{
    rj_link_def l = bar(RJ_LINK_FLEXIBLE, 10);
    rj_scene_def sc = rj_default_scene_def();
    rj_model *m, *m4;
    rj_state *s, *r, *s4;
    rj_error err;
    rj_peak a, b, q;
    double *F, largest = -1;
    size_t n;
    void *ck;
    int same, e, end;
    l.root = RJ_ROOT_CLAMPED;
    sc.links = &l;
    sc.link_count = 1;
    if (rj_model_create(&sc, &m, &err, NULL) != RJ_OK)
        return;
    rj_state_create(m, &s, NULL);
    rj_state_create(m, &r, NULL);
    rj_state_track_peaks(m, s, 1);
    F = rj_state_node_forces(m, s);
    F[3 * 10 + 1] = -1.0;
    rj_run(m, s, 0.05, 0, NULL, NULL);
    n = rj_state_save(m, s, NULL, 0);
    ck = malloc(n);
    rj_state_save(m, s, ck, n);
    largest = rj_link_peak_moment(m, s, 0).value;
    while (rj_state_time(s) < 0.1 - 0.5 * rj_model_dt(m)) {
        rj_step(m, s);
        for (e = 0; e < 10; e++) {
            double loads[5];
            rj_element_loads(m, s, 0, e, loads);
            for (end = 0; end < 2; end++)
                if (fabs(loads[2 + end]) > largest)
                    largest = fabs(loads[2 + end]);
        }
    }
    a = rj_link_peak_moment(m, s, 0);
    rj_state_load(m, r, ck, n, NULL);
    {
        /* a loaded state has no state a step before: no loads at t^n until it steps; a
           copy has the original's */
        double lr[5], ls[5], lc[5];
        rj_state *copy;
        const rj_result at_load = rj_element_loads(m, r, 0, 0, lr);
        rj_state_create(m, &copy, NULL);
        rj_state_copy(m, copy, s);
        rj_element_loads(m, s, 0, 0, ls);
        rj_element_loads(m, copy, 0, 0, lc);
        rjt_check(c, at_load == RJ_ERR_INVALID && memcmp(ls, lc, sizeof ls) == 0,
                  "element loads: none on a state just loaded; a copy's are the original's",
                  "loaded: result %d; M0 %.9g and %.9g", (int) at_load, ls[2], lc[2]);
        rj_state_destroy(copy, NULL);
    }
    rj_run(m, r, 0.1, 0, NULL, NULL);
    b = rj_link_peak_moment(m, r, 0);
    same = a.value == b.value && a.time == b.time && a.element == b.element && a.end == b.end;
    rjt_check(c, a.element == 0 && a.end == 0 && a.value == largest && a.value > 1.0 && same &&
                     rj_link_peak_stress(m, s, 0).value > 0,
              "peaks: a struck cantilever's largest moment is at its clamp, resumed alike from a checkpoint",
              "%.6g N m (every step's largest %.6g; static P L = 1 N m) at element %d end %d, "
              "t %.5f s; resumed %.6g at %.5f s; stress %.4g Pa",
              a.value, largest, a.element, a.end, a.time, b.value, b.time,
              rj_link_peak_stress(m, s, 0).value);
    sc.solver.energy_every = 4;
    if (rj_model_create(&sc, &m4, &err, NULL) == RJ_OK) {
        rj_state_create(m4, &s4, NULL);
        rj_state_track_peaks(m4, s4, 1);
        rj_state_node_forces(m4, s4)[3 * 10 + 1] = -1.0;
        rj_run(m4, s4, 0.1, 0, NULL, NULL);
        q = rj_link_peak_moment(m4, s4, 0);
        rjt_check(c, q.value <= a.value && q.value > 0.99 * a.value,
                  "peaks: with energy_every 4 they are taken on every 4th step, no larger",
                  "%.6g N m against %.6g every step", q.value, a.value);
        rj_state_destroy(s4, NULL);
        rj_model_destroy(m4, NULL);
    }
    sc.solver.energy_every = 1;
    sc.solver.in_place = RJ_IN_PLACE_ON;
    if (rj_model_create(&sc, &m4, &err, NULL) == RJ_OK) {
        const rj_result on = rj_state_create(m4, &s4, NULL) == RJ_OK
                                 ? rj_state_track_peaks(m4, s4, 1)
                                 : RJ_ERR_NOMEM;
        rj_run(m4, s4, 0.01, 0, NULL, NULL);
        rjt_check(c, on == RJ_OK && rj_link_peak_moment(m4, s4, 0).value == -1,
                  "peaks: in-place stepping tracks the pin forces' alone (no element loads "
                  "at t^n)",
                  "result %d, the link's peak moment %g (-1: none)", (int) on,
                  rj_link_peak_moment(m4, s4, 0).value);
        rj_state_destroy(s4, NULL);
        rj_model_destroy(m4, NULL);
    }
    free(ck);
    rj_state_destroy(r, NULL);
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
}

int main(void)
{
    rjt_ctx c = { 0, 0 };
    test_pendulum(&c, RJ_LINK_RIGID, 1, 2.5e-4, 1e-4, "rigid link (joint coordinates)");
    test_pendulum(&c, RJ_LINK_INEXTENSIBLE, 20, 0, 1e-4, "inextensible link, 20 elements");
    test_pendulum(&c, RJ_LINK_FLEXIBLE, 20, 0, 1e-4, "stiff flexible link, 20 elements");
    test_mixed_pendulum(&c);
    test_free_flight(&c);
    test_sag(&c);
    test_in_place(&c);
    test_inputs(&c);
    test_refusals(&c);
    test_scene_file(&c);
    test_load_sections(&c);
    test_settle_arguments(&c);
    test_pin_force(&c);
    test_element_loads(&c);
    test_damping_decay(&c);
    test_damping_path(&c);
    test_damping_bound(&c);
    test_damping_held_root(&c);
    test_damping_spin(&c);
    test_chord_pin_forces(&c);
    test_chord_friction_stuck(&c);
    test_plastic_elastic_limit(&c);
    test_plastic_bending(&c);
    test_plastic_unloading(&c);
    test_plastic_collapse(&c);
    test_axial_laws(&c);
    test_material_keys(&c);
    test_peaks_rigid(&c);
    test_peaks_flexible(&c);
    return rjt_summary(&c, "test_loads");
}
