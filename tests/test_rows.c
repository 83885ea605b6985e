/* Constraint rows (src/rows.h) against what we did not tune: exact relations.
   - Rows that meet: a prescribed hinge with two exact couplings down a chain of three
     panels (each coupling shares a joint with the next row): every angle on its
     profile times the chain of ratios to round-off, at every step, for flexible,
     inextensible and rigid panels; the balance closed with the drive's work.
   - Redundant rows: two prescribed hinges tied by an exact coupling their profiles
     already obey (rigid: a singular system, solved as least squares): both on their
     profiles.
   - Rows and latches together: the four-panel array with exact cable loops
     (examples/scenes/solar_array_ccl.rjs, couplings made exact): every loop's e at 0 to
     round-off through the deployment and the four latches, flexible and rigid, the
     balance closed.
   Every check prints what it measured. */
#include "../revjoint.h"
#include "rjt.h"
#include <math.h>
#include <stdio.h>
#include <string.h>

#define PI 3.14159265358979323846

/* Three panels 1 m long; h1 turns 90 deg cycloidally in 2 s from 90 deg; h2 turns -2
   times as far from 360 deg, h3 -1 times h2's from 0 deg. */
static const char CHAIN[] =
    "solver\n  dt = 0\n"
    "link p1\n  length = 1  elements = 3  rho = 1000  width = 0.1  height = 0.01\n"
    "link p2\n  length = 1  elements = 3  rho = 1000  width = 0.1  height = 0.01\n"
    "link p3\n  length = 1  elements = 3  rho = 1000  width = 0.1  height = 0.01\n"
    "joint h1\n  body1 = ground  body2 = p1  angle0 = 90 deg\n"
    "joint h2\n  body1 = p1  body2 = p2  angle0 = 360 deg\n"
    "joint h3\n  body1 = p2  body2 = p3  angle0 = 0 deg\n"
    "actuator m1\n  joint = h1  type = prescribed  profile = cycloidal 90 deg 2\n";
static const char CHAIN_LOOPS[] =
    "coupling c12\n  joints = h1 h2  ratio = -2  exact = yes\n"
    "coupling c23\n  joints = h2 h3  ratio = -1  exact = yes\n";
/* h2 prescribed as well, on the profile c12 asks of it: the rows repeat each other */
static const char CHAIN_REDUNDANT[] =
    "actuator m2\n  joint = h2  type = prescribed  profile = cycloidal -180 deg 2\n"
    "coupling c12\n  joints = h1 h2  ratio = -2  exact = yes\n";

/* The cycloidal profile: angle A over T from rest to rest. */
static double cycloid(double A, double T, double t)
{
    if (t >= T)
        return A;
    return A * (t / T - sin(2 * PI * t / T) / (2 * PI));
}

/* What a run measured: the largest miss of each joint's expected angle, of each
   coupling's e, the largest |balance| and the largest work of the drive. */
typedef struct measured {
    double angle, e, balance, drive;
    rj_result result;
    char msg[700];
} measured;

/* Model and state of scene text with every link given fidelity (-1: as written). */
static int build(const char *text, int fidelity, rj_model **m, rj_state **s, measured *o)
{
    rj_scene_file f;
    rj_scene_def d;
    rj_error err;
    int l;
    if (rj_scene_parse(text, strlen(text), "rows.rjs", &f, &err) != RJ_OK) {
        snprintf(o->msg, sizeof o->msg, "parse: %s", err.msg);
        return 0;
    }
    d = rj_scene_file_def(&f);
    for (l = 0; l < d.link_count && fidelity >= 0; l++)
        ((rj_link_def *) d.links)[l].fidelity = fidelity;
    o->result = rj_model_create(&d, m, &err, NULL);
    rj_scene_file_free(&f);
    if (o->result != RJ_OK) {
        snprintf(o->msg, sizeof o->msg, "model: %s", err.msg);
        return 0;
    }
    rj_state_create(*m, s, NULL);
    return 1;
}

/* The energy measures after a step. */
static void energy(const rj_model *m, const rj_state *s, measured *o)
{
    rj_energy e;
    rj_state_energy(m, s, &e);
    o->balance = fmax(o->balance, fabs(e.balance));
    o->drive = fmax(o->drive, fabs(e.work_drive));
}

/* The chain for 3 s (the profile and a second at rest): h1 against angle0 + cycloid,
   h2 against -2 times h1's turn, h3 against -1 times h2's, e of both loops. */
static void run_chain(const char *text, int fidelity, measured *o)
{
    rj_model *m = NULL;
    rj_state *s = NULL;
    memset(o, 0, sizeof *o);
    if (!build(text, fidelity, &m, &s, o))
        return;
    while (rj_state_time(s) < 3.0 && o->result == RJ_OK) {
        double t, turn1, turn2, turn3, want1;
        o->result = rj_step(m, s);
        t = rj_state_time(s);
        want1 = cycloid(0.5 * PI, 2.0, t);
        turn1 = rj_joint_theta_running(m, s, 0) - 0.5 * PI;
        turn2 = rj_joint_theta_running(m, s, 1) - 2 * PI;
        turn3 = rj_joint_theta_running(m, s, 2);
        o->angle = fmax(o->angle, fabs(turn1 - want1));
        o->e = fmax(o->e, fabs(turn2 + 2 * turn1));
        if (rj_model_joint_count(m) > 2 && strstr(text, "c23"))
            o->e = fmax(o->e, fabs(turn3 + turn2));
        energy(m, s, o);
    }
    if (o->result != RJ_OK)
        snprintf(o->msg, sizeof o->msg, "t = %g s: %s", rj_state_time(s), rj_state_error(s));
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
}

static void test_meeting_rows(rjt_ctx *c)
{
    static const int fidelity[3] = { RJ_LINK_FLEXIBLE, RJ_LINK_INEXTENSIBLE, RJ_LINK_RIGID };
    static const char *name[3] = { "flexible", "inextensible", "rigid" };
    char text[2048];
    int k;
    snprintf(text, sizeof text, "%s%s", CHAIN, CHAIN_LOOPS);
    for (k = 0; k < 3; k++) {
        measured o;
        run_chain(text, fidelity[k], &o);
        /* round-off: a few ulps of the angles (about 6 rad); the balance is the scheme's
           second-order error (test_rows_order), within 1e-4 of the energy as in
           test_couple */
        rjt_check(c, o.result == RJ_OK && o.angle < 1e-12 && o.e < 1e-12 && o.drive > 0 &&
                         o.balance < 1e-4 * o.drive,
                  "rows that meet: a prescribed hinge and two exact loops down a chain",
                  "%s: max |h1 - profile| %.3g rad, max |e| %.3g rad, max |balance| %.3g J "
                  "of a drive's work up to %.3g J %s",
                  name[k], o.angle, o.e, o.balance, o.drive, o.msg);
    }
}

/* The chain with p2 a rigid link among flexible ones (a rigid body of a mixed scene,
   whose rotation its two joints share). */
static void test_mixed_rows(rjt_ctx *c)
{
    char text[2048], *p;
    measured o;
    snprintf(text, sizeof text, "%s%s", CHAIN, CHAIN_LOOPS);
    p = strstr(text, "link p2");
    p = strstr(p, "height = 0.01") + strlen("height = 0.01");
    memmove(p + strlen("  fidelity = rigid"), p, strlen(p) + 1);
    memcpy(p, "  fidelity = rigid", strlen("  fidelity = rigid"));
    run_chain(text, -1, &o);
    rjt_check(c, o.result == RJ_OK && o.angle < 1e-12 && o.e < 1e-12 && o.drive > 0 &&
                     o.balance < 1e-4 * o.drive,
              "rows that meet on a rigid body of a mixed scene",
              "max |h1 - profile| %.3g rad, max |e| %.3g rad, max |balance| %.3g J of a "
              "drive's work up to %.3g J %s", o.angle, o.e, o.balance, o.drive, o.msg);
}

/* An exact coupling is refused, naming its field, with stiffness or on a chord joint. */
static void test_refusals(rjt_ctx *c)
{
    static const char *tails[2] = {
        "coupling c12\n  joints = h1 h2  ratio = -2  exact = yes  stiffness = 10\n",
        "coupling c12\n  joints = h1 h2  ratio = -2  exact = yes\n"
    };
    int k;
    for (k = 0; k < 2; k++) {
        char text[2048];
        rj_scene_file f;
        rj_scene_def d;
        rj_error err;
        rj_model *m = NULL;
        rj_result r;
        snprintf(text, sizeof text, "%s%s", CHAIN, tails[k]);
        /* the file's reader refuses what the model would, with line and column */
        if (rj_scene_parse(text, strlen(text), "rows.rjs", &f, &err) != RJ_OK) {
            rjt_check(c, err.code == RJ_ERR_INVALID && strstr(err.msg, "couplings[0].exact"),
                      "exact coupling refused with its field named", "%s (scene file): %s",
                      k ? "chord reference" : "stiffness", err.msg);
            continue;
        }
        d = rj_scene_file_def(&f);
        if (k == 1)
            ((rj_joint_def *) d.joints)[1].reference = RJ_REF_CHORD;
        r = rj_model_create(&d, &m, &err, NULL);
        rjt_check(c, r == RJ_ERR_INVALID && strstr(err.msg, "couplings[0].exact") != NULL,
                  "exact coupling refused with its field named",
                  "%s: %s", k ? "chord reference" : "stiffness", err.msg);
        if (r == RJ_OK)
            rj_model_destroy(m, NULL);
        rj_scene_file_free(&f);
    }
}

/* The chain's text with solver.dt = dt. */
static void chain_at(double dt, char *text, size_t n)
{
    const char *rest = strstr(CHAIN, "dt = 0") + strlen("dt = 0");
    snprintf(text, n, "solver\n  dt = %g%s%s", dt, rest, CHAIN_LOOPS);
}

/* The rigid chain's balance with the rows is the scheme's error, second order in dt: a
   quarter at half the step. */
static void test_rows_order(rjt_ctx *c)
{
    char text[2048];
    measured a, b;
    chain_at(4e-4, text, sizeof text);
    run_chain(text, RJ_LINK_RIGID, &a);
    chain_at(2e-4, text, sizeof text);
    run_chain(text, RJ_LINK_RIGID, &b);
    rjt_check(c, a.result == RJ_OK && b.result == RJ_OK && a.balance / b.balance > 3.5 &&
                     a.balance / b.balance < 4.5 && a.angle < 1e-12 && b.angle < 1e-12,
              "rows that meet, rigid: the balance second order in dt",
              "max |balance| %.3g J at dt 0.4 ms, %.3g J at 0.2 ms (ratio %.2f) of a drive's "
              "work up to %.3g J %s%s", a.balance, b.balance, a.balance / b.balance, a.drive,
              a.msg, b.msg);
}

static void test_redundant_rows(rjt_ctx *c)
{
    static const int fidelity[2] = { RJ_LINK_RIGID, RJ_LINK_FLEXIBLE };
    static const char *name[2] = { "rigid", "flexible" };
    char text[2048];
    int k;
    snprintf(text, sizeof text, "%s%s", CHAIN, CHAIN_REDUNDANT);
    for (k = 0; k < 2; k++) {
        measured o;
        run_chain(text, fidelity[k], &o);
        rjt_check(c, o.result == RJ_OK && o.angle < 1e-12 && o.e < 1e-12,
                  "redundant rows: two prescribed hinges tied by a loop they obey",
                  "%s: max |h1 - profile| %.3g rad, max |h2 + 2 h1| %.3g rad %s", name[k],
                  o.angle, o.e, o.msg);
    }
}

/* The array of examples/scenes/solar_array_ccl.rjs with its loops exact, for 3 s (every
   hinge latched by 2.3 s): the loops' largest |e|, the largest |balance| and the
   initial energy; rigid panels take the momentum method at their latches (rigid links
   refuse the adaptive one). */
static void run_array(int rigid, measured *o, double *e0, int *latched)
{
    rj_scene_file f;
    rj_scene_def d;
    rj_error err;
    rj_model *m = NULL;
    rj_state *s = NULL;
    int k;
    memset(o, 0, sizeof *o);
    *e0 = 0;
    *latched = 0;
    if (rj_scene_load("examples/scenes/solar_array_ccl.rjs", &f, &err) != RJ_OK) {
        snprintf(o->msg, sizeof o->msg, "%s", err.msg);
        o->result = err.code;
        return;
    }
    d = rj_scene_file_def(&f);
    for (k = 0; k < d.coupling_count; k++) {
        rj_coupling_def *cp = (rj_coupling_def *) &d.couplings[k];
        cp->exact = 1;
        cp->stiffness = cp->damping = 0;
    }
    for (k = 0; k < d.link_count && rigid; k++)
        ((rj_link_def *) d.links)[k].fidelity = RJ_LINK_RIGID;
    for (k = 0; k < d.joint_count && rigid; k++)
        ((rj_joint_def *) d.joints)[k].method = RJ_METHOD_MOMENTUM;
    o->result = rj_model_create(&d, &m, &err, NULL);
    if (o->result != RJ_OK) {
        snprintf(o->msg, sizeof o->msg, "%s", err.msg);
        rj_scene_file_free(&f);
        return;
    }
    rj_state_create(m, &s, NULL);
    {
        rj_energy e;
        rj_state_energy(m, s, &e);
        *e0 = e.total;
    }
    while (rj_state_time(s) < 3.0 && o->result == RJ_OK) {
        o->result = rj_step(m, s);
        for (k = 0; k < d.coupling_count; k++) {
            const rj_coupling_def *cp = &d.couplings[k];
            const double ta = rj_joint_theta_running(m, s, cp->joint_a) - d.joints[cp->joint_a].angle0;
            const double tb = rj_joint_theta_running(m, s, cp->joint_b) - d.joints[cp->joint_b].angle0;
            o->e = fmax(o->e, fabs(tb - cp->ratio * ta - cp->offset));
        }
        energy(m, s, o);
    }
    for (k = 0; k < d.joint_count; k++)
        *latched += rj_joint_flag(m, s, k) == RJ_LOCKED;
    if (o->result != RJ_OK)
        snprintf(o->msg, sizeof o->msg, "t = %g s: %s", rj_state_time(s), rj_state_error(s));
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
    rj_scene_file_free(&f);
}

static void test_array(rjt_ctx *c)
{
    int rigid;
    for (rigid = 0; rigid < 2; rigid++) {
        measured o;
        double e0;
        int latched;
        run_array(rigid, &o, &e0, &latched);
        rjt_check(c, o.result == RJ_OK && latched == 4 && o.e < 1e-12 &&
                         o.balance < (rigid ? 1e-3 : 1e-6) * e0,
                  "rows and latches: the four-panel array on exact cable loops",
                  "%s: %d hinges latched at 3 s, max |e| %.3g rad, max |balance| %.3g J of "
                  "%.3g J %s",
                  rigid ? "rigid" : "flexible", latched, o.e, o.balance, e0, o.msg);
    }
}

int main(void)
{
    rjt_ctx c = { 0, 0 };
    test_meeting_rows(&c);
    test_rows_order(&c);
    test_mixed_rows(&c);
    test_refusals(&c);
    test_redundant_rows(&c);
    test_array(&c);
    return rjt_summary(&c, "test_rows");
}
