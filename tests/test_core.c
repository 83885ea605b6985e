/* The element's equations against hand-worked numbers, and validation of every field. */
#include "../revjoint.h"
#include "../examples/scenes.h"
#include "rjt.h"
#include <string.h>
#include <stdlib.h>

#define D2R(x) rj_rad(x)

static void test_rotary_location(rjt_ctx *c)
{
    /* a along +x; b at every quadrant, on the axes and across the seam */
    static const double deg[] = { 0, 30, 90, 135, 180, 225, 270, 315, 359.999, 0.001 };
    int i;
    char name[80];
    for (i = 0; i < (int)(sizeof deg / sizeof deg[0]); i++) {
        double b = D2R(deg[i]), got = rj_rotary_location(1, 0, cos(b), sin(b));
        snprintf(name, sizeof name, "Eqs 1-3: theta at %g deg (a = +x)", deg[i]);
        rjt_near(c, name, rj_deg(got), deg[i], 1e-9);
    }
    /* a rotated: a at 100 deg, b at 10 deg -> 270; lengths do not matter */
    rjt_near(c, "Eqs 1-3: a at 100 deg, b at 10 deg (|a| = 3, |b| = 0.2)", rj_deg(rj_rotary_location(3 * cos(D2R(100)), 3 * sin(D2R(100)), 0.2 * cos(D2R(10)), 0.2 * sin(D2R(10)))), 270, 1e-9);
    /* straight continuation: a points back along link 1 (-x), b along +x: 180 */
    rjt_near(c, "Eqs 1-3: straight links give 180 deg", rj_deg(rj_rotary_location(-1, 0, 1, 0)), 180, 1e-12);
    rjt_near(c, "Eqs 1-3: folded links give 0 deg", rj_deg(rj_rotary_location(-1, 0, -1, 0)), 0, 1e-12);
}

static void test_table(rjt_ctx *c)
{
    /* two overlapping segments: (0,0)-(2,4) and (1,10)-(3,0) as separate points in one
       table: 0:0, 2:4, 1:10 is decreasing -> use a valid table with a repeated point:
       segments [0,1] 0->2, [1,2] 2->2, [2,2] step, [2,3] 5->1 */
    double a[] = { 0, 1, 2, 2, 3 }, t[] = { 0, 2, 2, 5, 1 };
    /* overlapping: segment [1,2] and [2,2] (zero width, skipped) and at theta = 2 both
       [1,2] (value 2) and [2,3] (value 5) contain it: 7 */
    rjt_near(c, "Eq 4: inside first segment", rj_table_torque(a, t, 5, 0.5), 1.0, 1e-15);
    rjt_near(c, "Eq 4: shared point of two segments adds both (overlap)", rj_table_torque(a, t, 5, 1.0), 2.0 + 2.0, 1e-15);
    rjt_near(c, "Eq 4: overlap at the step", rj_table_torque(a, t, 5, 2.0), 2.0 + 5.0, 1e-15);
    rjt_near(c, "Eq 4: last segment", rj_table_torque(a, t, 5, 2.5), 3.0, 1e-15);
    rjt_near(c, "Eq 4: outside the table", rj_table_torque(a, t, 5, 3.5), 0.0, 0);
    {
        /* overlapping segments: a fall in the angles starts a new run of segments that
           overlaps the earlier ones; [0, 2] rises 0 -> 4, [2, 1] is empty, [1, 3] falls 10 -> 0 */
        double a2[] = { 0, 2, 1, 3 }, t2[] = { 0, 4, 10, 0 };
        rjt_near(c, "Eq 4: overlapping segments add (1.5 lies in [0,2] and [1,3])", rj_table_torque(a2, t2, 4, 1.5), 3.0 + 7.5, 1e-14);
        rjt_near(c, "Eq 4: only the first segment below the overlap", rj_table_torque(a2, t2, 4, 0.5), 1.0, 1e-15);
        rjt_near(c, "Eq 4: only the second segment above it", rj_table_torque(a2, t2, 4, 2.5), 2.5, 1e-15);
    }
}

static void test_blimit(rjt_ctx *c)
{
    /* Fig 4: forward 200 > reverse 160: free range (160, 200) */
    rjt_check(c, !rj_blimit(D2R(180), D2R(200), D2R(160)), "Eq 6 backward-constrained: 180 free", "free range (160,200)");
    rjt_check(c, rj_blimit(D2R(200), D2R(200), D2R(160)), "Eq 6 backward-constrained: 200 at forward", "");
    rjt_check(c, rj_blimit(D2R(10), D2R(200), D2R(160)), "Eq 6 backward-constrained: 10 limited", "");
    rjt_check(c, rj_blimit(D2R(160), D2R(200), D2R(160)), "Eq 6 backward-constrained: 160 at reverse", "");
    /* Fig 5: forward 30 < reverse 330: free range wraps (330, 360) u [0, 30) */
    rjt_check(c, !rj_blimit(D2R(350), D2R(30), D2R(330)), "Eq 6 forward-constrained: 350 free", "free range wraps through 0");
    rjt_check(c, !rj_blimit(D2R(10), D2R(30), D2R(330)), "Eq 6 forward-constrained: 10 free", "");
    rjt_check(c, rj_blimit(D2R(180), D2R(30), D2R(330)), "Eq 6 forward-constrained: 180 limited", "");
    rjt_check(c, rj_blimit(D2R(30), D2R(30), D2R(330)), "Eq 6 forward-constrained: 30 at forward", "");
}

static void test_flags(rjt_ctx *c)
{
    /* RC12: stays at the limit while penetrated, whatever the rate */
    int f = RJ_FREE;
    f = rj_flag_next(f, 1, 0, +1.0, 0, RJ_RELEASE_RC12); rjt_check(c, f == RJ_AT_FORWARD, "RC12: contact at forward with rate >= 0 -> 1", "%d", f);
    f = rj_flag_next(f, 1, 0, -1.0, 0, RJ_RELEASE_RC12); rjt_check(c, f == RJ_AT_FORWARD, "RC12: penetrated, moving out -> stays 1", "%d", f);
    f = rj_flag_next(f, 0, 0, -1.0, 0, RJ_RELEASE_RC12); rjt_check(c, f == RJ_FREE, "RC12: back in the free range -> 0", "%d", f);
    f = rj_flag_next(RJ_FREE, 0, 1, -1.0, 0, RJ_RELEASE_RC12); rjt_check(c, f == RJ_AT_REVERSE, "RC12: contact at reverse with rate <= 0 -> 2", "%d", f);
    f = rj_flag_next(RJ_FREE, 1, 0, -1.0, 0, RJ_RELEASE_RC12); rjt_check(c, f == RJ_FREE, "RC12: beyond forward but leaving from free -> 0", "%d", f);
    /* RC13: releases as soon as the motion points out */
    f = rj_flag_next(RJ_FREE, 0, 1, -2.0, 0, RJ_RELEASE_RC13); rjt_check(c, f == RJ_AT_REVERSE, "RC13: contact at reverse -> 2", "%d", f);
    f = rj_flag_next(f, 0, 1, -0.5, 0, RJ_RELEASE_RC13); rjt_check(c, f == RJ_AT_REVERSE, "RC13: still moving in -> 2", "%d", f);
    f = rj_flag_next(f, 0, 1, +0.5, 0, RJ_RELEASE_RC13); rjt_check(c, f == RJ_FREE, "RC13: penetrated but moving out -> 0 (released)", "%d", f);
    f = rj_flag_next(f, 0, 1, -0.1, 0, RJ_RELEASE_RC13); rjt_check(c, f == RJ_AT_REVERSE, "RC13: moving in again while penetrated -> 2", "%d", f);
    /* lock: latches and never releases */
    f = rj_flag_next(RJ_FREE, 0, 1, -1.0, 1, RJ_RELEASE_RC13); rjt_check(c, f == RJ_LOCKED, "lock: reaching a limit with bLock -> 3", "%d", f);
    f = rj_flag_next(f, 0, 0, +5.0, 1, RJ_RELEASE_RC13); rjt_check(c, f == RJ_LOCKED, "lock: back in the free range, moving out -> still 3", "%d", f);
    f = rj_flag_next(f, 0, 0, +5.0, 0, RJ_RELEASE_RC12); rjt_check(c, f == RJ_LOCKED, "lock: L_prev = 3 -> 3 under RC12 too", "%d", f);
}

static void test_methods(rjt_ctx *c)
{
    double I1 = 2.0, I2 = 0.5, w1, w2, L0, L1, E0, E1;
    /* Eq 21 */
    rjt_near(c, "Eq 21: K_AP = I1 I2 / ((I1 + I2) dt^2)", rj_k_adaptive(I1, I2, 1e-3), 2.0 * 0.5 / 2.5 / 1e-6, 1e-6);
    rjt_near(c, "Eq 21: ground (I1 infinite) gives I2/dt^2", rj_k_adaptive(HUGE_VAL, I2, 1e-3), 0.5e6, 1e-9);
    /* Eqs 23-24, e = 0.3: momentum conserved to round-off, relative velocity -e times */
    w1 = 1.5; w2 = -4.0;
    L0 = I1 * w1 + I2 * w2;
    rj_momentum_balance(I1, I2, 0.3, &w1, &w2);
    L1 = I1 * w1 + I2 * w2;
    rjt_check(c, fabs(L1 - L0) <= 4e-16 * fabs(L0) + 1e-15, "Eqs 23-24: angular momentum conserved to round-off", "before %.17g after %.17g", L0, L1);
    rjt_near(c, "Eqs 23-24: relative velocity reversed and scaled by e", w2 - w1, -0.3 * (-4.0 - 1.5), 1e-14);
    /* hand numbers: w2' = (w2 (I2 - I1 e) + I1 w1 (1 + e)) / (I1 + I2) */
    rjt_near(c, "Eq 23 hand value", w2, (-4.0 * (0.5 - 2.0 * 0.3) + 2.0 * 1.5 * 1.3) / 2.5, 1e-14);
    w1 = 1.5; w2 = -4.0;
    rj_momentum_balance(I1, I2, 0.0, &w1, &w2);
    rjt_near(c, "Eqs 23-24, e = 0: common velocity", w1 - w2, 0, 1e-15);
    /* Eqs 25-26: kinetic energy kept, common velocity */
    w1 = 1.5; w2 = -4.0;
    E0 = 0.5 * I1 * w1 * w1 + 0.5 * I2 * w2 * w2;
    rj_energy_balance(I1, I2, &w1, &w2);
    E1 = 0.5 * (I1 + I2) * w1 * w1;
    rjt_near(c, "Eqs 25-26: s = (I1 w1|w1| + I2 w2|w2|)/(I1+I2), w = sign(s) sqrt|s|", w1, -sqrt(fabs((2.0 * 1.5 * 1.5 - 0.5 * 16.0) / 2.5)), 1e-14);
    rjt_check(c, w1 == w2, "Eqs 25-26: one common velocity", "%g %g", w1, w2);
    rjt_check(c, E1 < E0 + 1e-12, "Eqs 25-26: energy as the paper states it (see README: not conserved in general)", "before %.6g after %.6g J", E0, E1);
}

static void test_stability_paper(rjt_ctx *c)
{
    /* sec. 5: 10 elements, dt 15 us: Eq 31 gives a bound above 150 N m/rad; 7.5 us above 600 */
    deploy_opts o = deploy_default_opts();
    rj_link_def links[2]; rj_joint_def joints[2]; rj_scene_def sc; rj_model *m; rj_error err;
    double k15, k75, rIl, dt29;
    o.dt = 15e-6;
    deploy_scene(&o, links, joints, &sc);
    joints[1].penalty_k = 150;
    if (rj_model_create(&sc, &m, &err, NULL) != RJ_OK) { rjt_check(c, 0, "deployment builds at 15 us", "%s", err.msg); return; }
    k15 = rj_joint_kmax_eq31(m, 1, 15e-6);
    k75 = rj_joint_kmax_eq31(m, 1, 7.5e-6);
    /* hand: smaller rho I l of the two links: link 2, rho = 0.42958/(1.7748e-4 * 0.9945) */
    rIl = 0.42958 / (1.7748e-4 * 0.9945) * 2.9117e-10 * 0.09945;
    rjt_near(c, "Eq 31 at 15 us: 0.81 rho I l / dt^2 (link 2 is the smaller)", k15, 0.81 * rIl / (15e-6 * 15e-6), 1e-9 * k15);
    rjt_check(c, k15 > 150, "Eq 31 at 15 us allows the paper's 150 N m/rad", "K_max %.1f N m/rad", k15);
    rjt_check(c, k75 > 600, "Eq 31 at 7.5 us allows the paper's 600 N m/rad", "K_max %.1f N m/rad", k75);
    dt29 = rj_joint_dt_eq29(m, 1, 150);
    rjt_near(c, "Eq 29: min(l/c, sqrt(rho I l / K)) at K = 150", dt29, fmin(0.09945 / sqrt(7e10 / (0.42958 / (1.7748e-4 * 0.9945))), sqrt(rIl / 150)), 1e-15);
    rjt_near(c, "Eq 28: l/c of the shortest element", rj_model_dt_eq28(m), fmin(0.09945 / sqrt(7e10 / (0.42958 / (1.7748e-4 * 0.9945))), 0.1006423 / sqrt(7e10 / (0.52334 / (1.78076e-4 * 1.006423)))), 1e-15);
    rjt_check(c, rj_model_dt_bound(m) > 15e-6, "library's own bound admits the paper's 15 us", "bound %.4g s", rj_model_dt_bound(m));
    rj_model_destroy(m, NULL);
}

/* every invalid field of every definition struct is rejected, names the field, leaves the
   caller's structs unchanged, and builds nothing */
/* field-by-field bitwise comparison (struct padding is indeterminate, so no memcmp of
   whole structs: valgrind rightly objects) */
#define SAMEF(a, b, f) (memcmp(&(a).f, &(b).f, sizeof (a).f) == 0)
static int same_link(const rj_link_def *a, const rj_link_def *b)
{
    return SAMEF(*a, *b, length) && SAMEF(*a, *b, elements) && SAMEF(*a, *b, E) && SAMEF(*a, *b, rho) && SAMEF(*a, *b, section)
        && SAMEF(*a, *b, width) && SAMEF(*a, *b, height) && SAMEF(*a, *b, layers) && SAMEF(*a, *b, area) && SAMEF(*a, *b, inertia)
        && SAMEF(*a, *b, tip_mass) && SAMEF(*a, *b, tip_inertia) && SAMEF(*a, *b, root) && SAMEF(*a, *b, x) && SAMEF(*a, *b, y)
        && SAMEF(*a, *b, angle) && SAMEF(*a, *b, vx) && SAMEF(*a, *b, vy) && SAMEF(*a, *b, omega) && SAMEF(*a, *b, fidelity) && SAMEF(*a, *b, cookie);
}
static int same_joint(const rj_joint_def *a, const rj_joint_def *b)
{
    return SAMEF(*a, *b, body1) && SAMEF(*a, *b, node1) && SAMEF(*a, *b, body2) && SAMEF(*a, *b, ground_x) && SAMEF(*a, *b, ground_y)
        && SAMEF(*a, *b, ground_angle) && SAMEF(*a, *b, angle0) && SAMEF(*a, *b, rate0) && SAMEF(*a, *b, table_count)
        && SAMEF(*a, *b, table_angle) && SAMEF(*a, *b, table_torque) && SAMEF(*a, *b, spring_k) && SAMEF(*a, *b, spring_free_angle)
        && SAMEF(*a, *b, has_forward) && SAMEF(*a, *b, forward) && SAMEF(*a, *b, has_reverse) && SAMEF(*a, *b, reverse)
        && SAMEF(*a, *b, lock) && SAMEF(*a, *b, method) && SAMEF(*a, *b, release) && SAMEF(*a, *b, penalty_k)
        && SAMEF(*a, *b, restitution) && SAMEF(*a, *b, damping) && SAMEF(*a, *b, friction) && SAMEF(*a, *b, reference) && SAMEF(*a, *b, cookie);
}
static int same_solver(const rj_solver_def *a, const rj_solver_def *b)
{
    return SAMEF(*a, *b, dt) && SAMEF(*a, *b, allow_unstable) && SAMEF(*a, *b, energy_growth) && SAMEF(*a, *b, energy_every) && SAMEF(*a, *b, in_place) && SAMEF(*a, *b, cookie);
}

typedef struct badcase { const char *field; int which; int idx; double value; } badcase;

static void test_validation(rjt_ctx *c)
{
    rj_link_def L0[2], L[2];
    rj_joint_def J0[1], J[1];
    rj_scene_def sc;
    impact_opts io = impact_default_opts();
    const double nan = strtod("nan", NULL), inf = HUGE_VAL;
    struct { const char *field; void *ptr; int isint; double bad; } cases[64];
    int n = 0, i;
    impact_scene(&io, L0, &J0[0], &sc);
#define BAD(f, p, isi, v) do { cases[n].field = f; cases[n].ptr = (void *)&(p); cases[n].isint = isi; cases[n].bad = v; n++; } while (0)
    BAD("links[1].length", L[1].length, 0, 0.0); BAD("links[1].length", L[1].length, 0, -1.0); BAD("links[1].length", L[1].length, 0, nan);
    BAD("links[1].elements", L[1].elements, 1, 0); BAD("links[1].elements", L[1].elements, 1, -3);
    BAD("links[1].E", L[1].E, 0, 0.0); BAD("links[1].E", L[1].E, 0, inf); BAD("links[1].rho", L[1].rho, 0, -2710);
    BAD("links[1].width", L[1].width, 0, 0.0); BAD("links[1].height", L[1].height, 0, nan); BAD("links[1].layers", L[1].layers, 1, 0);
    BAD("links[1].section", L[1].section, 1, 7);
    BAD("links[1].tip_mass", L[1].tip_mass, 0, -1); BAD("links[1].tip_inertia", L[1].tip_inertia, 0, nan);
    BAD("links[0].root", L[0].root, 1, 9); BAD("links[0].x", L[0].x, 0, inf); BAD("links[0].angle", L[0].angle, 0, nan);
    BAD("links[0].omega", L[0].omega, 0, nan);
    BAD("joints[0].body1", J[0].body1, 1, 5); BAD("joints[0].body2", J[0].body2, 1, -1); BAD("joints[0].body2", J[0].body2, 1, 0);
    BAD("joints[0].node1", J[0].node1, 1, 11); BAD("joints[0].angle0", J[0].angle0, 0, nan); BAD("joints[0].rate0", J[0].rate0, 0, inf);
    BAD("joints[0].table_count", J[0].table_count, 1, 1); BAD("joints[0].table_count", J[0].table_count, 1, 99);
    BAD("joints[0].spring_k", J[0].spring_k, 0, -1); BAD("joints[0].reverse", J[0].reverse, 0, rj_rad(360)); BAD("joints[0].reverse", J[0].reverse, 0, -0.1);
    BAD("joints[0].forward", J[0].forward, 0, nan); BAD("joints[0].method", J[0].method, 1, 5); BAD("joints[0].release", J[0].release, 1, 2);
    BAD("joints[0].restitution", J[0].restitution, 0, 1.5); BAD("joints[0].damping", J[0].damping, 0, -0.1); BAD("joints[0].friction", J[0].friction, 0, nan);
    BAD("joints[0].lock", J[0].lock, 1, 2); BAD("joints[0].has_reverse", J[0].has_reverse, 1, 3);
    BAD("solver.dt", sc.solver.dt, 0, -1e-6); BAD("solver.dt", sc.solver.dt, 0, nan); BAD("solver.energy_growth", sc.solver.energy_growth, 0, 0.5);
    BAD("solver.energy_every", sc.solver.energy_every, 1, 0); BAD("solver.energy_every", sc.solver.energy_every, 1, -16); BAD("solver.energy_every", sc.solver.energy_every, 1, 1001);
    BAD("solver.in_place", sc.solver.in_place, 1, -1); BAD("solver.in_place", sc.solver.in_place, 1, 3);
    for (i = 0; i < n; i++) {
        rj_error err;
        rj_model *m = NULL;
        rj_result r;
        char name[120];
        rj_link_def snapL[2]; rj_joint_def snapJ[1];
        rj_solver_def keep;
        memcpy(L, L0, sizeof L); memcpy(J, J0, sizeof J);
        sc = rj_default_scene_def(); sc.links = L; sc.link_count = 2; sc.joints = J; sc.joint_count = 1; sc.solver.dt = 2.5e-6;
        if (cases[i].isint) *(int *)cases[i].ptr = (int)cases[i].bad; else *(double *)cases[i].ptr = cases[i].bad;
        snapL[0] = L[0]; snapL[1] = L[1]; snapJ[0] = J[0];
        keep = sc.solver;
        r = rj_model_create(&sc, &m, &err, NULL);
        snprintf(name, sizeof name, "invalid %s = %g rejected, named", cases[i].field, cases[i].bad);
        rjt_check(c, r == RJ_ERR_INVALID && m == NULL && strcmp(err.field, cases[i].field) == 0 && strstr(err.msg, cases[i].field) != NULL
                  && same_link(&snapL[0], &L[0]) && same_link(&snapL[1], &L[1]) && same_joint(&snapJ[0], &J[0]) && same_solver(&keep, &sc.solver),
                  name, "\"%s\"", err.msg);
    }
    /* a def that was never defaulted */
    {
        rj_error err; rj_model *m = NULL;
        memcpy(L, L0, sizeof L); memcpy(J, J0, sizeof J);
        memset(&L[1], 0, sizeof L[1]);
        sc = rj_default_scene_def(); sc.links = L; sc.link_count = 2; sc.joints = J; sc.joint_count = 1;
        rjt_check(c, rj_model_create(&sc, &m, &err, NULL) == RJ_ERR_INVALID && strcmp(err.field, "links[1]") == 0, "undefaulted link def caught by its cookie", "\"%s\"", err.msg);
    }
    /* a table point outside [0, 2 pi] */
    {
        rj_error err; rj_model *m = NULL;
        memcpy(L, L0, sizeof L); memcpy(J, J0, sizeof J);
        J[0].table_count = 3; J[0].table_angle[0] = 0; J[0].table_angle[1] = 2; J[0].table_angle[2] = 7;
        sc = rj_default_scene_def(); sc.links = L; sc.link_count = 2; sc.joints = J; sc.joint_count = 1; sc.solver.dt = 2.5e-6;
        rjt_check(c, rj_model_create(&sc, &m, &err, NULL) == RJ_ERR_INVALID && strcmp(err.field, "joints[0].table_angle[2]") == 0, "table angle above 2 pi rejected", "\"%s\"", err.msg);
    }
    /* dt above the bound is refused, with the bound in the message; override accepted */
    {
        rj_error err; rj_model *m = NULL; rj_result r;
        memcpy(L, L0, sizeof L); memcpy(J, J0, sizeof J);
        sc = rj_default_scene_def(); sc.links = L; sc.link_count = 2; sc.joints = J; sc.joint_count = 1; sc.solver.dt = 15e-6;
        rjt_check(c, rj_model_create(&sc, &m, &err, NULL) == RJ_ERR_UNSTABLE_DT && strcmp(err.field, "solver.dt") == 0, "dt above the bound refused", "\"%s\"", err.msg);
        sc.solver.allow_unstable = 1;
        r = rj_model_create(&sc, &m, &err, NULL);
        rjt_check(c, r == RJ_OK, "dt above the bound accepted with allow_unstable", "%s", r == RJ_OK ? "built" : err.msg);
        rj_model_destroy(m, NULL);
    }
}

int main(void)
{
    rjt_ctx c = { 0, 0 };
    test_rotary_location(&c);
    test_table(&c);
    test_blimit(&c);
    test_flags(&c);
    test_methods(&c);
    test_stability_paper(&c);
    test_validation(&c);
    return rjt_summary(&c, "test_core");
}
