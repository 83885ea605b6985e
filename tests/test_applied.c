/* Applied loads (rj_load_def) and the caller's node forces (rj_state_node_forces), against
   what we did not tune: the elastica of a cantilever under a dead and under a follower tip
   load (tests/elastica_ref.py, which reproduces Mattiasson's 1981 table), the exact period
   of a pendulum driven by a dead force instead of gravity, and the energy balance; then the
   two ways of giving a force agree, checkpoints and copies keep the node forces, bad loads
   and bad node forces are refused naming them, and stepping in place changes no bit. */
#include "../revjoint.h"
#include "rjt.h"
#include <math.h>
#include "rjt_loads.h"
#include <stdlib.h>
#include <string.h>

#define G 9.81
#define PI 3.14159265358979323846

/* An aluminium bar 1 m long, 20 mm wide, `height` deep in the plane. */
static rj_link_def bar(int fidelity, int elements, double height)
{
    rj_link_def l = rj_default_link_def();
    l.length = 1.0;
    l.elements = elements;
    l.E = 70e9;
    l.rho = 2700;
    l.section = RJ_SECTION_RECT;
    l.width = 0.02;
    l.height = height;
    l.fidelity = fidelity;
    return l;
}


/* ------------------------------------------------------------------ 1, 2: the elastica */

/* The cantilever of the elastica: 1 m, E 70 GPa, 20 x 4 mm. Slender, so that the axial
   stretch P / EA = k h^2 / (12 L^2) (1.33e-5 at k = 10), which the inextensible elastica
   leaves out, stays below 2e-5 of the deflection (checked below against the inextensible
   link). */
#define EL_HEIGHT 0.004

/* Tip v/L, u/L and rotation of the elastica, from tests/elastica_ref.py (run
   `/usr/bin/python3 tests/elastica_ref.py --csv`: shooting, solve_bvp and the closed forms
   of Bisshopp & Drucker agree to 1e-13; its dead-load rows round to Mattiasson's 1981
   table). k = P L^2 / EI. */
typedef struct elastica_ref {
    int follower;
    double k, v, u, angle;
} elastica_ref;

static const elastica_ref ELASTICA[] = {
    { 0, 1, 0.301720773800, 0.056433236283, 0.461351949712 },
    { 0, 2, 0.493457480397, 0.160641720825, 0.781749831557 },
    { 0, 5, 0.713791523612, 0.387628360724, 1.215368117612 },
    { 0, 10, 0.810609024880, 0.554995597754, 1.430285538804 },
    { 1, 2, 0.573839062561, 0.232637808465, 0.968238802517 },
    { 1, 10, 0.546983264594, 1.092123181189, 2.992714816235 },
};

/* The cantilever clamped along +x at the origin under a tip force (0, -k EI / L^2), dead or
   follower (then in the tip's frame: perpendicular to the tip), settled by rj_settle: its
   tip's v/L, u/L and rotation (clockwise positive) into out. Returns 0 with msg filled when
   something fails. */
static int elastica_tip(int follower, double k, int fidelity, int elements, double out[3], char *msg,
                        size_t n)
{
    rj_link_def l = bar(fidelity, elements, EL_HEIGHT);
    rj_load_def load = rj_default_load_def();
    rj_scene_def sc = rj_default_scene_def();
    const double EI = l.E * l.width * pow(l.height, 3) / 12;
    rj_model *m;
    rj_state *s;
    rj_error err;
    rj_result r;
    double tip[2];
    l.root = RJ_ROOT_CLAMPED;
    load.force[1] = -k * EI / (l.length * l.length);
    load.follower = follower;
    sc.links = &l;
    sc.link_count = 1;
    sc.loads = &load;
    sc.load_count = 1;
    if (rj_model_create(&sc, &m, &err, NULL) != RJ_OK) {
        snprintf(msg, n, "%s", err.msg);
        return 0;
    }
    if (rj_state_create(m, &s, NULL) != RJ_OK) {
        snprintf(msg, n, "rj_state_create failed");
        rj_model_destroy(m, NULL);
        return 0;
    }
    r = rj_settle(m, s, 1e-12, 5000000);
    rj_node_position(m, s, 0, elements, tip);
    out[0] = -tip[1] / l.length;
    out[1] = 1 - tip[0] / l.length;
    out[2] = -rj_node_rotation(m, s, 0, elements);
    if (r != RJ_OK) snprintf(msg, n, "rj_settle: %s: %.400s", rj_result_str(r), rj_state_error(s));
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
    return r == RJ_OK;
}

/* The flexible cantilever at 10, 20 and 40 elements against the elastica: for each of v/L,
   u/L and the tip rotation, the error falls at second order (at least 3x per halving; 4x
   is second order's), and the 40-element error is within what second order predicts from
   the 10-element one, |e10| / 16, with the slack of that ratio (|e10| / 9) plus the stretch
   P / EA. A ratio means something only while the error is well above the stretch: where the
   20-element error is below 2 P / EA (u/L at k = 10 under the dead load, whose error is 50x
   smaller than v/L's and not yet in second order's range at 10 elements: the inextensible
   link's ratios are 2.2, 3.6 and 4.1 from 10 to 80 elements) only the bound is checked.
   Returns the 10-element errors and the
   20-element values (3 each) for the inextensible comparison. */
static void test_elastica(rjt_ctx *c, const elastica_ref *ref, double e10[3], double flex20[3])
{
    static const int meshes[3] = { 10, 20, 40 };
    static const char *const what[3] = { "tip deflection v/L", "tip shortening u/L", "tip rotation (rad)" };
    const double stretch = ref->k * EL_HEIGHT * EL_HEIGHT / 12; /* P / EA */
    const double want[3] = { ref->v, ref->u, ref->angle };
    const char *load = ref->follower ? "follower" : "dead";
    double got[3][3], err[3][3];
    char msg[600] = "", name[240];
    int i, q;
    for (q = 0; q < 3; q++)
        e10[q] = flex20[q] = NAN;
    for (i = 0; i < 3; i++) {
        if (!elastica_tip(ref->follower, ref->k, RJ_LINK_FLEXIBLE, meshes[i], got[i], msg, sizeof msg)) {
            snprintf(name, sizeof name, "elastica, %s load k = %g, %d elements", load, ref->k, meshes[i]);
            rjt_check(c, 0, name, "%s", msg);
            return;
        }
        for (q = 0; q < 3; q++)
            err[i][q] = got[i][q] - want[q];
    }
    for (q = 0; q < 3; q++) {
        const double r1 = err[0][q] / err[1][q], r2 = err[1][q] / err[2][q];
        const double bound = fabs(err[0][q]) / 9 + stretch;
        const int ratios = fabs(err[1][q]) >= 2 * stretch;
        const int ok = fabs(err[2][q]) <= bound && (!ratios || (r1 > 3 && r2 > 3));
        snprintf(name, sizeof name,
                 "elastica, %s load k = %g, flexible link: %s converges at second order to tests/elastica_ref.py",
                 load, ref->k, what[q]);
        rjt_check(c, ok, name,
                  "%.8f / %.8f / %.8f at 10 / 20 / 40 elements against %.8f: errors %+.3e / %+.3e / %+.3e, "
                  "ratios %.2f %.2f (%s), 40 elements |%.3e| <= %.3e (|e10|/9 + P/EA %.3g)",
                  got[0][q], got[1][q], got[2][q], want[q], err[0][q], err[1][q], err[2][q], r1, r2,
                  ratios ? "each above 3" : "not checked: e20 below 2 P/EA", fabs(err[2][q]), bound, stretch);
        e10[q] = err[0][q];
        flex20[q] = got[1][q];
    }
}

/* The inextensible link at 20 elements, k = 10, dead load: it differs from the flexible one
   only by the axial stretch, which must be small (below 2e-5 of the deflection, and within
   2 P / EA in every quantity; stretching lengthens the beam, so it deflects more), and its
   deflection and rotation are within one halving (3x) of the flexible 10-element errors. */
static void test_elastica_inextensible(rjt_ctx *c, const elastica_ref *ref, const double e10[3],
                                       const double flex20[3])
{
    const double stretch = ref->k * EL_HEIGHT * EL_HEIGHT / 12;
    double got[3], d[3], err[3];
    char msg[600] = "";
    if (!elastica_tip(ref->follower, ref->k, RJ_LINK_INEXTENSIBLE, 20, got, msg, sizeof msg)) {
        rjt_check(c, 0, "elastica, dead load k = 10, inextensible link, 20 elements", "%s", msg);
        return;
    }
    d[0] = flex20[0] - got[0];
    d[1] = flex20[1] - got[1];
    d[2] = flex20[2] - got[2];
    err[0] = got[0] - ref->v;
    err[1] = got[1] - ref->u;
    err[2] = got[2] - ref->angle;
    rjt_check(c, d[0] > 0 && d[0] < 2e-5 * got[0] && fabs(d[1]) < 2 * stretch && fabs(d[2]) < 2 * stretch,
              "elastica, dead load k = 10, 20 elements: flexible minus inextensible (the axial stretch) is below 2e-5 of the deflection",
              "v/L %+.3e (%.3g of v/L, within 0..2e-5), u/L %+.3e, rotation %+.3e rad (each within 2 P/EA = %.3g)",
              d[0], d[0] / got[0], d[1], d[2], 2 * stretch);
    rjt_check(c, fabs(err[0]) < fabs(e10[0]) / 3 && fabs(err[2]) < fabs(e10[2]) / 3,
              "elastica, dead load k = 10, inextensible link, 20 elements: v/L and rotation against tests/elastica_ref.py within second order of the 10-element errors",
              "v/L %.8f against %.8f (%+.3e, within |e10|/3 = %.3e), rotation %.8f against %.8f (%+.3e, within %.3e); u/L %.8f (%+.3e)",
              got[0], ref->v, err[0], fabs(e10[0]) / 3, got[2], ref->angle, err[2], fabs(e10[2]) / 3, got[1], err[1]);
}

/* ------------------------------------------------------------------ 3: the force pendulum */


/* A bar pinned at the origin, no gravity, a dead force (0, -P) on its last node, released
   from rest 150 deg from the force's direction: I phi'' = -P L sin(phi), so its period is
   4 sqrt(I / (P L)) K(sin 75 deg), I the model's own lumped inertia about the pin (for
   rigid links the continuous rod's). A stiff bar (20 x 20 mm, P L^2 / EI = 3.2e-3): the
   bending under the force moves the non-rigid links' period by about 1.2e-5, within the
   1e-4 of tests/test_loads.c; the rigid links' error is the step's, about (w dt)^2 / 24 with
   w = sqrt(P L / I) = 2.9 rad/s, so 1e-6. mixed: a free flexible bar far away makes the
   scene a mixed one. Also the force's work: P times the tip's drop at the accounts' time
   (rj_state_energy_time, a step back), to within the step's second-order error on a swing,
   P L (w dt)^2. */
static void test_force_pendulum(rjt_ctx *c, int fidelity, int elements, double dt, int mixed, double tol,
                                const char *what)
{
    const double amplitude = 150.0 * PI / 180.0, P = 3.0;
    rj_link_def l[2];
    rj_joint_def j = rj_default_joint_def();
    rj_load_def load = rj_default_load_def();
    rj_scene_def sc = rj_default_scene_def();
    rj_model *m;
    rj_state *s;
    rj_error err;
    swing w;
    double mass, moment, inertia, exact, period, tip0[2];
    char name[240];
    l[0] = bar(fidelity, elements, 0.02);
    l[1] = bar(RJ_LINK_FLEXIBLE, 4, 0.02);
    l[1].x = 5.0;
    j.body1 = -1;
    j.body2 = 0;
    j.angle0 = amplitude - 0.5 * PI;
    load.force[1] = -P;
    sc.links = l;
    sc.link_count = mixed ? 2 : 1;
    sc.joints = &j;
    sc.joint_count = 1;
    sc.loads = &load;
    sc.load_count = 1;
    sc.solver.dt = dt;
    snprintf(name, sizeof name, "pendulum under a dead tip force from 150 deg, %s: period against the elliptic integral", what);
    if (rj_model_create(&sc, &m, &err, NULL) != RJ_OK) {
        rjt_check(c, 0, name, "%s", err.msg);
        return;
    }
    if (rj_state_create(m, &s, NULL) != RJ_OK) {
        rjt_check(c, 0, name, "rj_state_create failed");
        rj_model_destroy(m, NULL);
        return;
    }
    lumped_body(m, s, 0, &mass, &moment, &inertia);
    if (fidelity == RJ_LINK_RIGID)
        inertia = l[0].rho * l[0].width * l[0].height * pow(l[0].length, 3) / 3;
    exact = 4.0 * sqrt(inertia / (P * l[0].length)) * elliptic_k(sin(0.5 * amplitude));
    rj_node_position(m, s, 0, elements, tip0);
    memset(&w, 0, sizeof w);
    w.phi_prev = amplitude;
    w.tip_node = elements;
    if (rj_run(m, s, 2.2 * exact, 0, swing_sample, &w) != RJ_OK || w.crossings < 2) {
        rjt_check(c, 0, name, "%s (%d crossings)", rj_state_error(s), w.crossings);
    } else {
        rj_energy e;
        double drop, slack;
        period = w.crossing[1] - w.crossing[0];
        rjt_check(c, fabs(period / exact - 1) < tol, name,
                  "%.7f s against %.7f s (%+.2e; within %.0e), I about the pin %.6g kg m^2, dt %.3g s",
                  period, exact, period / exact - 1, tol, inertia, rj_model_dt(m));
        rj_state_energy(m, s, &e);
        drop = P * (tip0[1] - w.tip_before[1]);
        slack = P * l[0].length * (P * l[0].length / inertia) * rj_model_dt(m) * rj_model_dt(m);
        snprintf(name, sizeof name, "pendulum under a dead tip force, %s: its work is P times the tip's drop, and the balance closes", what);
        rjt_check(c, fabs(e.work_applied - drop) <= slack && fabs(e.balance) < 1e-6 * fabs(e.work_applied) && e.work_applied != 0,
                  name, "work %.9g J against P x drop %.9g J at t %.6f s (|diff| %.3g <= P L (w dt)^2 %.3g), balance %.3g J (within 1e-6 of it), kinetic %.9g J",
                  e.work_applied, drop, rj_state_energy_time(s), fabs(e.work_applied - drop), slack, e.balance, e.kinetic);
    }
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
}

/* ------------------------------------------------------------------ 4: the energy balance */

/* A bar pinned at the origin, starting horizontal, under gravity, with two inner-node
   inputs: a follower force and moment on node 3 scaled by a table in time, and (in the
   state) the caller's force on node 7, changed every 0.1 s as a controller would. A rigid
   link here is integrated in joint coordinates (its nodes are report points). */
static int loaded_bar(int fidelity, rj_model **m, rj_state **s)
{
    rj_link_def l = bar(fidelity, 10, 0.01);
    rj_joint_def j = rj_default_joint_def();
    rj_load_def load = rj_default_load_def();
    rj_scene_def sc = rj_default_scene_def();
    rj_error err;
    static const double times[4] = { 0.0, 0.3, 0.6, 1.0 }, factors[4] = { 0.0, 1.0, -0.5, 0.8 };
    j.body1 = -1;
    j.body2 = 0;
    j.angle0 = 0;
    load.node = 3;
    load.force[0] = 1.0;
    load.force[1] = 4.0;
    load.moment = 0.8;
    load.follower = 1;
    load.table_count = 4;
    memcpy(load.table_time, times, sizeof times);
    memcpy(load.table_factor, factors, sizeof factors);
    sc.links = &l;
    sc.link_count = 1;
    sc.joints = &j;
    sc.joint_count = 1;
    sc.loads = &load;
    sc.load_count = 1;
    sc.solver.gravity[1] = -G;
    sc.solver.dt = fidelity == RJ_LINK_RIGID ? 2.5e-4 : 0;
    if (rj_model_create(&sc, m, &err, NULL) != RJ_OK) {
        printf("  (%s)\n", err.msg);
        return 0;
    }
    if (rj_state_create(*m, s, NULL) != RJ_OK) {
        rj_model_destroy(*m, NULL);
        return 0;
    }
    return 1;
}

/* The caller's force on node 7 for the k-th 0.1 s. */
static void controller(const rj_model *m, rj_state *s, int k)
{
    double *f = rj_state_node_forces(m, s) + 3 * rj_model_node_index(m, 0, 7);
    f[0] = 2.0 * cos(1.3 * k);
    f[1] = 3.0 * sin(0.7 * k) - 1.0;
    f[2] = 0.3 * cos(k);
}

static void test_balance(rjt_ctx *c, int fidelity, const char *what)
{
    rj_model *m;
    rj_state *s;
    rj_energy e;
    double scale, worst = 0, peak = 0;
    char name[240];
    int k;
    if (!loaded_bar(fidelity, &m, &s)) {
        rjt_check(c, 0, "energy balance with loads", "the model did not build");
        return;
    }
    for (k = 0; k < 10; k++) {
        controller(m, s, k);
        if (rj_run(m, s, 0.1 * (k + 1), 0, NULL, NULL) != RJ_OK) break;
        rj_state_energy(m, s, &e);
        scale = fabs(e.work_applied) + e.kinetic + fabs(e.gravity);
        if (fabs(e.balance) / scale > worst) worst = fabs(e.balance) / scale;
        if (e.kinetic > peak) peak = e.kinetic;
    }
    snprintf(name, sizeof name,
             "energy balance, %s under gravity with a tabled follower load and a changing node force: the loads' work closes it", what);
    rjt_check(c, k == 10 && fabs(e.work_applied) > 0.1 && worst < 1e-6, name,
              "every 0.1 s to %.3f s: |balance| at most %.3g of |work| + kinetic + |gravity| (within 1e-6); at the end work %.6g J, "
              "balance %.3g J, kinetic %.6g J (largest %.6g J), gravity %.6g J, strain %.3g J %s",
              rj_state_time(s), worst, e.work_applied, e.balance, e.kinetic, peak, e.gravity, e.strain, rj_state_error(s));
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
}

/* ------------------------------------------------------------------ 5: two ways, one force */

/* A cantilever (10 elements, 20 x 10 mm) with a constant force (3, -20) N on node `node`,
   given as a model load (by_load) or as the caller's node force; after 2000 steps: the tip
   and the loaded node (positions) and the loads' work. */
static int cantilever_force(int node, int by_load, double tip[2], double at[2], double tip0[2], double *work)
{
    rj_link_def l = bar(RJ_LINK_FLEXIBLE, 10, 0.01);
    rj_load_def load = rj_default_load_def();
    rj_scene_def sc = rj_default_scene_def();
    rj_model *m;
    rj_state *s;
    rj_error err;
    rj_energy e;
    int k, ok = 1;
    l.root = RJ_ROOT_CLAMPED;
    load.node = node;
    load.force[0] = 3.0;
    load.force[1] = -20.0;
    sc.links = &l;
    sc.link_count = 1;
    sc.loads = &load;
    sc.load_count = by_load ? 1 : 0;
    if (rj_model_create(&sc, &m, &err, NULL) != RJ_OK) {
        printf("  (%s)\n", err.msg);
        return 0;
    }
    if (rj_state_create(m, &s, NULL) != RJ_OK) {
        rj_model_destroy(m, NULL);
        return 0;
    }
    rj_node_position(m, s, 0, 10, tip0);
    if (!by_load) {
        double *f = rj_state_node_forces(m, s) + 3 * rj_model_node_index(m, 0, node);
        f[0] = 3.0;
        f[1] = -20.0;
    }
    for (k = 0; k < 2000 && ok; k++)
        ok = rj_step(m, s) == RJ_OK;
    rj_node_position(m, s, 0, 10, tip);
    rj_node_position(m, s, 0, node < 0 ? 10 : node, at);
    rj_state_energy(m, s, &e);
    *work = e.work_applied;
    if (!ok) printf("  (%s)\n", rj_state_error(s));
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
    return ok;
}

static void test_two_ways(rjt_ctx *c)
{
    double tip[2][2], at[2][2], tip0[2], work[2], defl, diff;
    int ok = cantilever_force(-1, 1, tip[0], at[0], tip0, &work[0]) && cantilever_force(-1, 0, tip[1], at[1], tip0, &work[1]);
    rjt_check(c, ok && memcmp(tip[0], tip[1], sizeof tip[0]) == 0,
              "a force on the last node as a model load and as the caller's node force: the same tip bits after 2000 steps",
              "tip (%.17g, %.17g) against (%.17g, %.17g) m; work %.17g / %.17g J",
              tip[0][0], tip[0][1], tip[1][0], tip[1][1], work[0], work[1]);
    ok = cantilever_force(5, 1, tip[0], at[0], tip0, &work[0]) && cantilever_force(5, 0, tip[1], at[1], tip0, &work[1]);
    defl = hypot(tip[0][0] - tip0[0], tip[0][1] - tip0[1]);
    diff = fmax(hypot(tip[0][0] - tip[1][0], tip[0][1] - tip[1][1]), hypot(at[0][0] - at[1][0], at[0][1] - at[1][1]));
    rjt_check(c, ok && diff <= 1e-9 * defl && fabs(work[0] - work[1]) <= 1e-9 * fabs(work[0]) && defl > 1e-3,
              "a force on an inner node as a model load and as the caller's node force (another path): the same motion within 1e-9",
              "tip and node 5 differ by %.3g m (%.3g of the tip's displacement %.4g m), work %.12g / %.12g J (%.3g)",
              diff, diff / defl, defl, work[0], work[1], work[0] / work[1] - 1);
}

/* ------------------------------------------------------------------ 6: checkpoints, copies */

static int same_nodes(const rj_model *m, const rj_state *a, const rj_state *b)
{
    const int n = rj_link_node_count(m, 0);
    int k;
    for (k = 0; k < n; k++) {
        double xa[2], xb[2];
        rj_node_position(m, a, 0, k, xa);
        rj_node_position(m, b, 0, k, xb);
        if (memcmp(xa, xb, sizeof xa) != 0) return 0;
        if (rj_node_rotation(m, a, 0, k) != rj_node_rotation(m, b, 0, k)) return 0;
    }
    return 1;
}

/* A checkpoint taken with node forces set resumes bit for bit in a state that never asked
   for them, and rj_state_copy carries them the same way; the forces come back the same. */
static void test_checkpoint(rjt_ctx *c, int fidelity, const char *what)
{
    rj_model *m;
    rj_state *s, *s2 = NULL, *s3 = NULL;
    double tip[3][2];
    unsigned char *buf = NULL;
    size_t n = 0, nf;
    char name[240];
    int k, loaded, same_forces, same_bits;
    if (!loaded_bar(fidelity, &m, &s) || rj_state_create(m, &s2, NULL) != RJ_OK ||
        rj_state_create(m, &s3, NULL) != RJ_OK) {
        rjt_check(c, 0, "checkpoints with node forces", "the model did not build");
        return;
    }
    nf = 3 * (size_t) rj_model_node_count(m);
    for (k = 0; k < 3; k++) {
        controller(m, s, k);
        rj_run(m, s, 0.1 * (k + 1), 0, NULL, NULL);
    }
    n = rj_state_save(m, s, NULL, 0);
    buf = (unsigned char *) malloc(n);
    loaded = buf && rj_state_save(m, s, buf, n) == n && rj_state_load(m, s2, buf, n, NULL) == RJ_OK;
    rj_state_copy(m, s3, s);
    rj_run(m, s, 0.5, 0, NULL, NULL);
    if (loaded) rj_run(m, s2, 0.5, 0, NULL, NULL);
    rj_run(m, s3, 0.5, 0, NULL, NULL);
    for (k = 0; k < 3; k++)
        rj_node_position(m, k == 0 ? s : k == 1 ? s2 : s3, 0, 10, tip[k]);
    same_bits = loaded && same_nodes(m, s, s2);
    same_forces = memcmp(rj_state_node_forces(m, s), rj_state_node_forces(m, s2), nf * sizeof(double)) == 0;
    snprintf(name, sizeof name, "checkpoint with node forces set resumes bit for bit in a fresh state, %s", what);
    rjt_check(c, same_bits && same_forces && rj_state_node_forces(m, s2)[3 * 7 + 1] != 0, name,
              "%s; tip (%.15g, %.15g) against (%.15g, %.15g) m at t %.3f s; node forces %s (node 7 fy %g N)",
              loaded ? "loaded" : "not loaded", tip[0][0], tip[0][1], tip[1][0], tip[1][1], rj_state_time(s2),
              same_forces ? "the same" : "differ", rj_state_node_forces(m, s2)[3 * 7 + 1]);
    same_bits = same_nodes(m, s, s3);
    same_forces = memcmp(rj_state_node_forces(m, s), rj_state_node_forces(m, s3), nf * sizeof(double)) == 0;
    snprintf(name, sizeof name, "rj_state_copy with node forces set: the copy runs on the same bits, %s", what);
    rjt_check(c, same_bits && same_forces, name, "tip (%.15g, %.15g) against (%.15g, %.15g) m; node forces %s",
              tip[0][0], tip[0][1], tip[2][0], tip[2][1], same_forces ? "the same" : "differ");
    free(buf);
    rj_state_destroy(s, NULL);
    rj_state_destroy(s2, NULL);
    rj_state_destroy(s3, NULL);
    rj_model_destroy(m, NULL);
}

/* ------------------------------------------------------------------ 7: refusals */

/* A node force that is not a number stops the step, naming rj_state_node_forces(), and
   leaves the state as it was. */
static void test_nan_force(rjt_ctx *c, int fidelity, const char *what)
{
    rj_model *m;
    rj_state *s;
    double *f;
    unsigned char *before, *after;
    size_t n;
    rj_result r;
    char name[240];
    if (!loaded_bar(fidelity, &m, &s)) {
        rjt_check(c, 0, "a NaN node force", "the model did not build");
        return;
    }
    controller(m, s, 0);
    rj_run(m, s, 0.05, 0, NULL, NULL);
    f = rj_state_node_forces(m, s);
    f[3 * rj_model_node_index(m, 0, 5) + 1] = NAN;
    n = rj_state_save(m, s, NULL, 0);
    before = (unsigned char *) malloc(n);
    after = (unsigned char *) malloc(n);
    if (!before || !after) {
        rjt_check(c, 0, "a NaN node force", "out of memory");
    } else {
        rj_state_save(m, s, before, n);
        r = rj_step(m, s);
        rj_state_save(m, s, after, n);
        snprintf(name, sizeof name, "a NaN node force is refused by the step, naming rj_state_node_forces(), the state unchanged, %s", what);
        rjt_check(c, r == RJ_ERR_INVALID && strstr(rj_state_error(s), "rj_state_node_forces()") != NULL &&
                  memcmp(before, after, n) == 0, name, "%s (%s); checkpoint bytes %s",
                  rj_result_str(r), rj_state_error(s), memcmp(before, after, n) == 0 ? "unchanged" : "CHANGED");
    }
    free(before);
    free(after);
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
}

/* rj_model_create refuses a bad load with RJ_ERR_INVALID, err.field naming the field. */
static void refuse(rjt_ctx *c, const rj_load_def *loads, int count, const char *field, const char *what)
{
    rj_link_def l = bar(RJ_LINK_FLEXIBLE, 10, 0.01);
    rj_scene_def sc = rj_default_scene_def();
    rj_model *m = NULL;
    rj_error err;
    rj_result r;
    char name[240];
    memset(&err, 0, sizeof err);
    l.root = RJ_ROOT_CLAMPED;
    sc.links = &l;
    sc.link_count = 1;
    sc.loads = loads;
    sc.load_count = count;
    r = rj_model_create(&sc, &m, &err, NULL);
    snprintf(name, sizeof name, "a load with %s is refused, err.field \"%s\"", what, field);
    rjt_check(c, r == RJ_ERR_INVALID && m == NULL && strcmp(err.field, field) == 0, name, "%s, field \"%s\": %s",
              rj_result_str(r), err.field, err.msg);
    if (m) rj_model_destroy(m, NULL);
}

static void test_refusals(rjt_ctx *c)
{
    rj_load_def d = rj_default_load_def(), bad;
    d.force[1] = -10;
    bad = d; bad.link = 1;
    refuse(c, &bad, 1, "loads[0].link", "link 1 of a one-link scene");
    bad = d; bad.node = 11;
    refuse(c, &bad, 1, "loads[0].node", "node 11 of a 10-element link");
    bad = d; bad.force[1] = NAN;
    refuse(c, &bad, 1, "loads[0].force[1]", "a NaN force");
    bad = d; bad.table_count = 3;
    bad.table_time[0] = 0; bad.table_time[1] = 0; bad.table_time[2] = 1;
    bad.table_factor[0] = bad.table_factor[1] = bad.table_factor[2] = 1;
    refuse(c, &bad, 1, "loads[0].table_time[1]", "table times not increasing (0, 0, 1)");
    bad = d; bad.follower = 2;
    refuse(c, &bad, 1, "loads[0].follower", "follower 2");
    bad = d; bad.table_count = 40;
    refuse(c, &bad, 1, "loads[0].table_count", "table_count 40");
    memset(&bad, 0, sizeof bad);
    bad.node = -1;
    bad.force[1] = -10;
    refuse(c, &bad, 1, "loads[0]", "no rj_default_load_def() (the cookie)");
    refuse(c, NULL, 1, "load_count", "load_count 1 and loads NULL");
}

/* ------------------------------------------------------------------ 8: in place */

/* A 32-element cantilever, no gravity, under a tabled follower tip load and (second run)
   the caller's force on an inner node: in_place ON gives the same bits as OFF. */
static void test_in_place(rjt_ctx *c, int node_force)
{
    rj_link_def l = bar(RJ_LINK_FLEXIBLE, 32, 0.01);
    rj_load_def load = rj_default_load_def();
    rj_scene_def sc = rj_default_scene_def();
    rj_model *m[2];
    rj_state *s[2];
    rj_error err;
    rj_energy e[2];
    double tip[2][2];
    char name[240];
    int k, i, same = 1;
    l.root = RJ_ROOT_CLAMPED;
    load.force[1] = -30;
    load.moment = 2;
    load.follower = 1;
    load.table_count = 2;
    load.table_time[0] = 0;
    load.table_time[1] = 2e-3;
    load.table_factor[0] = 0.2;
    load.table_factor[1] = 1.0;
    sc.links = &l;
    sc.link_count = 1;
    sc.loads = &load;
    sc.load_count = 1;
    snprintf(name, sizeof name, "a tabled follower tip load%s with solver.in_place on: the same bits as off after 800 steps",
             node_force ? " and a caller's force on node 20" : "");
    for (k = 0; k < 2; k++) {
        sc.solver.in_place = k == 0 ? RJ_IN_PLACE_ON : RJ_IN_PLACE_OFF;
        if (rj_model_create(&sc, &m[k], &err, NULL) != RJ_OK || rj_state_create(m[k], &s[k], NULL) != RJ_OK) {
            rjt_check(c, 0, name, "%s", err.msg);
            return;
        }
        if (node_force) {
            double *f = rj_state_node_forces(m[k], s[k]) + 3 * rj_model_node_index(m[k], 0, 20);
            f[0] = 5;
            f[1] = 12;
            f[2] = -0.5;
        }
        for (i = 0; i < 800; i++)
            if (rj_step(m[k], s[k]) != RJ_OK) break;
        rj_node_position(m[k], s[k], 0, 32, tip[k]);
        rj_state_energy(m[k], s[k], &e[k]);
    }
    for (i = 0; i <= 32 && same; i++) {
        double a[2], b[2];
        rj_node_position(m[0], s[0], 0, i, a);
        rj_node_position(m[1], s[1], 0, i, b);
        same = memcmp(a, b, sizeof a) == 0 && rj_node_rotation(m[0], s[0], 0, i) == rj_node_rotation(m[1], s[1], 0, i);
    }
    rjt_check(c, same && e[0].work_applied == e[1].work_applied && rj_state_steps(s[0]) == 800 && rj_state_steps(s[1]) == 800 &&
              fabs(e[0].balance) < 1e-6 * fabs(e[0].work_applied), name,
              "every node %s; tip (%.15g, %.15g) / (%.15g, %.15g) m, work %.15g / %.15g J, balance %.3g J, %ld / %ld steps",
              same ? "the same" : "DIFFERS", tip[0][0], tip[0][1], tip[1][0], tip[1][1], e[0].work_applied, e[1].work_applied,
              e[0].balance, rj_state_steps(s[0]), rj_state_steps(s[1]));
    for (k = 0; k < 2; k++) {
        rj_state_destroy(s[k], NULL);
        rj_model_destroy(m[k], NULL);
    }
}

int main(void)
{
    rjt_ctx c = { 0, 0 };
    double e10[3], flex20[3];
    size_t i;
    for (i = 0; i < sizeof ELASTICA / sizeof ELASTICA[0]; i++) {
        test_elastica(&c, &ELASTICA[i], e10, flex20);
        if (!ELASTICA[i].follower && ELASTICA[i].k == 10)
            test_elastica_inextensible(&c, &ELASTICA[i], e10, flex20);
    }
    test_force_pendulum(&c, RJ_LINK_RIGID, 1, 2.5e-4, 0, 1e-6, "rigid link (joint coordinates)");
    test_force_pendulum(&c, RJ_LINK_INEXTENSIBLE, 20, 0, 0, 1e-4, "inextensible link, 20 elements");
    test_force_pendulum(&c, RJ_LINK_FLEXIBLE, 20, 0, 0, 1e-4, "stiff flexible link, 20 elements");
    test_force_pendulum(&c, RJ_LINK_RIGID, 1, 0, 1, 1e-6, "rigid body in a mixed scene");
    test_balance(&c, RJ_LINK_FLEXIBLE, "flexible link");
    test_balance(&c, RJ_LINK_RIGID, "rigid link (joint coordinates)");
    test_two_ways(&c);
    test_checkpoint(&c, RJ_LINK_FLEXIBLE, "flexible link");
    test_checkpoint(&c, RJ_LINK_RIGID, "rigid link (joint coordinates)");
    test_nan_force(&c, RJ_LINK_FLEXIBLE, "flexible link");
    test_nan_force(&c, RJ_LINK_RIGID, "rigid link (joint coordinates)");
    test_refusals(&c);
    test_in_place(&c, 0);
    test_in_place(&c, 1);
    return rjt_summary(&c, "test_applied");
}
