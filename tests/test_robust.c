/* test_robust.c - defects found by trying the library as a new user and as an attacker
   would: each check here failed before its fix. Joint damping in the stability bound,
   node counts that overflowed an int, validation and model memory that grew faster than
   the scene, models with no usable step, non-finite states returned as RJ_OK, checkpoint
   contents trusted once the checksum matched, blow-up messages naming causes the model
   does not have, and limits a joint never reaches. */
#include "../revjoint.h"
#include "rjt.h"
#include "../examples/scenes.h"
#include <stdlib.h>
#include <string.h>
#include <ctype.h>

static rjt_ctx T;

/* One 1 m aluminium strip of 10 elements pinned to ground by a spring and a damper: the
   README's strip. */
static rj_result strip_model(double k, double c, double dt, rj_model **m, rj_error *err)
{
    rj_link_def link = rj_default_link_def();
    rj_joint_def joint = rj_default_joint_def();
    rj_scene_def scene = rj_default_scene_def();
    link.height = 0.01;
    joint.body1 = -1;
    joint.body2 = 0;
    joint.angle0 = 0;
    joint.spring_k = k;
    joint.spring_free_angle = rj_rad(90);
    joint.damping = c;
    scene.links = &link;
    scene.link_count = 1;
    scene.joints = &joint;
    scene.joint_count = 1;
    scene.solver.dt = dt;
    scene.solver.allow_unstable = dt > 0;
    return rj_model_create(&scene, m, err, NULL);
}

/* Runs a model from its start to t_end; RJ_OK or the step's error. */
static rj_result run_for(const rj_model *m, double t_end, char *msg, size_t size)
{
    rj_state *s;
    rj_result r = RJ_OK;
    if (rj_state_create(m, &s, NULL) != RJ_OK) return RJ_ERR_NOMEM;
    while (rj_state_time(s) < t_end && (r = rj_step(m, s)) == RJ_OK) {}
    snprintf(msg, size, "%s", rj_state_error(s));
    rj_state_destroy(s, NULL);
    return r;
}

/* The automatic step is stable with joint damping, and the bound is a bound: the largest
   stable step, found by bisection, is at or above it. */
static void test_damping_bound(void)
{
    static const double cases[][2] = { { 20, 1.5 }, { 20, 2 }, { 200, 5 }, { 0, 50 }, { 20, 1000 } };
    int i;
    for (i = 0; i < 5; i++) {
        rj_model *m;
        rj_error err;
        char msg[640], name[120];
        rj_result r = strip_model(cases[i][0], cases[i][1], 0, &m, &err);
        if (r != RJ_OK) {
            snprintf(name, sizeof name, "damping: strip k %g c %g builds", cases[i][0], cases[i][1]);
            rjt_check(&T, 0, name, "%s", err.msg);
            continue;
        }
        /* 1 s, or 2e6 steps where the damping makes the step tiny (c = 1000 would take
           3.3e7): an unstable step grows within a few hundred */
        r = run_for(m, fmin(1.0, 2e6 * rj_model_dt(m)), msg, sizeof msg);
        snprintf(name, sizeof name, "damping: strip k %g N m/rad c %g N m s/rad runs 1 s (or 2e6 steps) at the automatic dt", cases[i][0], cases[i][1]);
        rjt_check(&T, r == RJ_OK, name, "dt %.4g s, bound %.4g s: %s", rj_model_dt(m), rj_model_dt_bound(m), r == RJ_OK ? "ok" : msg);
        rj_model_destroy(m, NULL);
    }
    for (i = 1; i < 4; i++) {
        double lo = 1e-9, hi = 1e-4, bound = 0;
        int it;
        char name[120];
        for (it = 0; it < 24; it++) {
            const double mid = sqrt(lo * hi);
            rj_model *m;
            rj_error err;
            char msg[640];
            if (strip_model(cases[i][0], cases[i][1], mid, &m, &err) != RJ_OK) { hi = mid; continue; }
            bound = rj_model_dt_bound(m);
            if (run_for(m, 0.05, msg, sizeof msg) == RJ_OK) lo = mid;
            else hi = mid;
            rj_model_destroy(m, NULL);
        }
        snprintf(name, sizeof name, "damping: the bound is below the largest stable step (k %g, c %g)", cases[i][0], cases[i][1]);
        rjt_check(&T, bound > 0 && bound <= lo, name, "largest stable step %.4g s (0.05 s runs, bisection), bound %.4g s, ratio %.3f",
                  lo, bound, lo / bound);
    }
}

/* Node counts past an int are refused by name, not wrapped into a small block. */
static void test_counts(void)
{
    static const int counts[2] = { 4295, 2148 };
    int i, k;
    for (k = 0; k < 2; k++) {
        const int n = counts[k];
        rj_link_def *links = (rj_link_def *)malloc(sizeof *links * (size_t)n);
        rj_scene_def scene = rj_default_scene_def();
        rj_error err;
        size_t size;
        char name[120];
        for (i = 0; i < n; i++) {
            links[i] = rj_default_link_def();
            links[i].elements = 1000000;
        }
        scene.links = links;
        scene.link_count = n;
        size = rj_model_size(&scene, &err);
        snprintf(name, sizeof name, "counts: %d links of 1e6 elements are refused, the total named", n);
        rjt_check(&T, size == 0 && strcmp(err.field, "links") == 0 && strstr(err.msg, "nodes") != NULL, name,
                  "size %lu, [%s] %s", (unsigned long)size, err.field, err.msg);
        free(links);
    }
}

/* A chain of n links of 2 elements each (flexible or rigid), with a closing joint from the
   last link back to the first when loop is set. */
static size_t chain_size(int n, int fidelity, int loop, rj_result *created, rj_error *err)
{
    rj_link_def *links = (rj_link_def *)malloc(sizeof *links * (size_t)n);
    rj_joint_def *joints = (rj_joint_def *)malloc(sizeof *joints * (size_t)n);
    rj_scene_def scene;
    rj_model *m = NULL;
    size_t size;
    chain_scene(n, 2, fidelity, links, joints, &scene);
    if (loop) joints[0].body1 = n - 1;
    size = rj_model_size(&scene, err);
    *created = rj_model_create(&scene, &m, err, NULL);
    if (*created == RJ_OK) rj_model_destroy(m, NULL);
    free(links);
    free(joints);
    return size;
}

/* The model's memory grows with the scene, not its square; the joint graph is checked
   whole in a long chain. Time is measured by make bench (model build time), not here. */
static void test_linear(void)
{
    rj_result r400, r4000, rloop;
    rj_error err;
    const size_t s400 = chain_size(400, RJ_LINK_FLEXIBLE, 0, &r400, &err);
    const size_t s4000 = chain_size(4000, RJ_LINK_FLEXIBLE, 0, &r4000, &err);
    const double ratio = (double)s4000 / (10.0 * (double)s400);
    rjt_check(&T, r400 == RJ_OK && r4000 == RJ_OK && ratio < 1.01, "linear: model bytes per link the same at 400 and 4000 links",
              "%.0f and %.0f bytes per link (ratio %.4f, < 1.01)", s400 / 400.0, s4000 / 4000.0, ratio);
    chain_size(20000, RJ_LINK_FLEXIBLE, 1, &rloop, &err);
    rjt_check(&T, rloop == RJ_ERR_INVALID && strstr(err.msg, "form a loop through link") != NULL, "linear: a loop through a 20000-link chain is refused",
              "%s", err.msg);
}

/* A single free link of the given length and E, in a model or its refusal. */
static rj_result one_link(double length, double E, rj_error *err)
{
    rj_link_def link = rj_default_link_def();
    rj_scene_def scene = rj_default_scene_def();
    rj_model *m = NULL;
    rj_result r;
    link.length = length;
    link.E = E;
    scene.links = &link;
    scene.link_count = 1;
    r = rj_model_create(&scene, &m, err, NULL);
    if (r == RJ_OK) rj_model_destroy(m, NULL);
    return r;
}

/* FNV-1a on from h, as the checkpoint's checksum. */
static unsigned long long fnv_on(unsigned long long h, const void *bytes, size_t n)
{
    const unsigned char *p = (const unsigned char *) bytes;
    size_t i;
    for (i = 0; i < n; i++) {
        h ^= p[i];
        h *= 1099511628211ULL;
    }
    return h;
}
static unsigned long long fnv(const unsigned char *p, size_t n)
{
    return fnv_on(14695981039346656037ULL, p, n);
}

/* Re-seals an edited checkpoint: a checksum is no protection, which is the point. */
static void reseal(unsigned char *ck, size_t size)
{
    const unsigned long long h = fnv(ck, size - 8);
    memcpy(ck + size - 8, &h, 8);
}

/* Offsets in a checkpoint: the frame's doubles start after the 24-byte header and the
   step count; its 13 scalars first (time at 0, the warning count at 9), then the nodes'
   x values. */
#define CK_DOUBLES 32
#define CK_TIME 0
#define CK_WARN 9
#define CK_X0 13

static void test_no_usable_step(void)
{
    static const double lengths[4] = { 1e-45, 1e-100, 1e-160, 1e-3 };
    static const double moduli[4] = { 70e9, 70e9, 70e9, 1e30 };
    int i;
    for (i = 0; i < 4; i++) {
        rj_error err;
        char name[120];
        const rj_result r = one_link(lengths[i], moduli[i], &err);
        snprintf(name, sizeof name, "no usable step: a link of %g m, E %g Pa, is refused by name", lengths[i], moduli[i]);
        rjt_check(&T, r == RJ_ERR_INVALID && strcmp(err.field, "links[0]") == 0, name, "[%s] %s", err.field, err.msg);
    }
    {
        /* the longest link validation allows: the bound's finite differences must move its
           heavy nodes by more than its coordinates resolve (they did not, and the bound
           came out 4e5 times too long) */
        rj_link_def link = rj_default_link_def();
        rj_joint_def pin = rj_default_joint_def();
        rj_scene_def scene = rj_default_scene_def();
        rj_model *m;
        rj_error err;
        char msg[640];
        rj_result r;
        link.length = 1e6;
        link.elements = 3;
        pin.body1 = -1;
        pin.body2 = 0;
        scene.links = &link;
        scene.link_count = 1;
        scene.joints = &pin;
        scene.joint_count = 1;
        r = rj_model_create(&scene, &m, &err, NULL);
        if (r == RJ_OK) {
            r = run_for(m, 200 * rj_model_dt(m), msg, sizeof msg);
            rjt_check(&T, r == RJ_OK && rj_model_dt_bound(m) < 2 * rj_model_dt_eq28(m), "no usable step: a 1e6 m link gets a true bound and runs",
                      "bound %.4g s, Eq 28 %.4g s; 200 steps: %s", rj_model_dt_bound(m), rj_model_dt_eq28(m), r == RJ_OK ? "ok" : msg);
            rj_model_destroy(m, NULL);
        } else rjt_check(&T, 0, "no usable step: a 1e6 m link gets a true bound and runs", "%s", err.msg);
        link = rj_default_link_def();
        link.x = 1e12;
        pin.ground_x = 1e12;
        r = rj_model_create(&scene, &m, &err, NULL);
        if (r == RJ_OK) rj_model_destroy(m, NULL);
        rjt_check(&T, r == RJ_ERR_INVALID && strstr(err.msg, "resolve") != NULL, "no usable step: a link placed where doubles do not resolve its elements is refused",
                  "[%s] %s", err.field, err.msg);
    }
    {
        /* omega_max scales as 1/sqrt(rho) exactly; the Lanczos norms squared underflowed
           from rho ~ 1e150 kg/m^3 on and cut omega_max by 6 */
        double worst = 0, base = 0;
        int k;
        for (k = 0; k <= 24; k += 4) {
            rj_link_def link = rj_default_link_def();
            rj_scene_def scene = rj_default_scene_def();
            rj_model *m;
            rj_error err;
            double scaled;
            link.length = 1e6;
            link.elements = 3;
            link.rho = 2710 * pow(10, k);
            scene.links = &link;
            scene.link_count = 1;
            if (rj_model_create(&scene, &m, &err, NULL) != RJ_OK) { worst = HUGE_VAL; continue; }
            scaled = rj_model_omega_max(m) * sqrt(link.rho / 2710);
            if (k == 0) base = scaled;
            if (fabs(scaled / base - 1) > worst) worst = fabs(scaled / base - 1);
            rj_model_destroy(m, NULL);
        }
        rjt_check(&T, worst < 1e-6, "no usable step: omega_max scales as 1/sqrt(rho) from 2.7e3 to 2.7e27 kg/m^3",
                  "omega sqrt(rho / 2710) = %.9g rad/s at 2710 kg/m^3, worst relative departure %.3g", base, worst);
    }
    {
        /* a 1 nm link of E = 2.4e-187 Pa beside four default ones: the bound is the default
           links' (about the bound of one of them alone); differenced with the tiny link's
           step, their moves fell below what their coordinates resolve and the bound came
           out 3329 s */
        rj_link_def links[5];
        rj_joint_def joints[5];
        rj_scene_def scene;
        rj_model *m, *one;
        rj_error err;
        double b_all = 0, b_one = 0;
        chain_scene(5, 10, RJ_LINK_FLEXIBLE, links, joints, &scene);
        scene.joint_count = 4;
        scene.joints = joints + 1;
        links[0].length = 1e-9;
        links[0].E = 2.44e-187;
        joints[1].body1 = 0;
        if (rj_model_create(&scene, &m, &err, NULL) == RJ_OK) {
            b_all = rj_model_dt_bound(m);
            rj_model_destroy(m, NULL);
        }
        scene.link_count = 1;
        scene.links = links + 1;
        scene.joint_count = 0;
        if (rj_model_create(&scene, &one, &err, NULL) == RJ_OK) {
            b_one = rj_model_dt_bound(one);
            rj_model_destroy(one, NULL);
        }
        rjt_check(&T, b_all > 0 && b_all <= 1.01 * b_one, "no usable step: a 1 nm link beside normal ones leaves their bound in place",
                  "bound %.4g s with the tiny link, %.4g s for one normal link alone", b_all, b_one);
    }
    {
        /* a root link turned by 1e9 rad: the bound's rotations of 1e-7 rad are below what
           that angle resolves (the bound came out 8.5 times too long); refused by name */
        rj_error err;
        rj_link_def link = rj_default_link_def();
        rj_scene_def scene = rj_default_scene_def();
        rj_model *m = NULL;
        rj_result r;
        link.angle = 1e9;
        scene.links = &link;
        scene.link_count = 1;
        r = rj_model_create(&scene, &m, &err, NULL);
        if (r == RJ_OK) rj_model_destroy(m, NULL);
        rjt_check(&T, r == RJ_ERR_INVALID && strcmp(err.field, "links[0].angle") == 0, "no usable step: a link angle of 1e9 rad is refused by name",
                  "[%s] %s", err.field, err.msg);
    }
    {
        /* time where the step no longer moves it: a crafted checkpoint at t = 1e15 s */
        rj_model *m;
        rj_state *s;
        rj_error err;
        unsigned char *ck;
        size_t size;
        double t = 1e15;
        rj_result r;
        strip_model(20, 0, 0, &m, &err);
        rj_state_create(m, &s, NULL);
        rj_step(m, s);
        size = rj_state_save(m, s, NULL, 0);
        ck = (unsigned char *)malloc(size);
        rj_state_save(m, s, ck, size);
        memcpy(ck + CK_DOUBLES + 8 * CK_TIME, &t, 8);
        reseal(ck, size);
        r = rj_state_load(m, s, ck, size, &err);
        if (r == RJ_OK) r = rj_step(m, s);
        rjt_check(&T, r == RJ_ERR_INVALID && strstr(rj_state_error(s), "no longer advances time") != NULL,
                  "no usable step: a step that no longer advances time stops", "%s: %s", rj_result_str(r), rj_state_error(s));
        free(ck);
        rj_state_destroy(s, NULL);
        rj_model_destroy(m, NULL);
    }
}

/* Every node's position and velocity is finite. */
static int state_finite(const rj_model *m, const rj_state *s)
{
    int l, n;
    for (l = 0; l < rj_model_link_count(m); l++)
        for (n = 0; n < rj_link_node_count(m, l); n++) {
            double p[2], v[2];
            rj_node_position(m, s, l, n, p);
            rj_node_velocity(m, s, l, n, v);
            if (!isfinite(p[0] + p[1] + v[0] + v[1] + rj_node_rotation(m, s, l, n))) return 0;
        }
    return 1;
}

/* A scene run far above its bound: every step that returns RJ_OK leaves a finite state,
   and the blow-up is reported. */
static void nonfinite_case(const char *what, rj_scene_def *scene)
{
    rj_model *m;
    rj_state *s;
    rj_error err;
    rj_result r = RJ_OK;
    long ok_steps = 0, bad_ok = 0;
    char name[160];
    if (rj_model_create(scene, &m, &err, NULL) != RJ_OK) {
        rjt_check(&T, 0, what, "%s", err.msg);
        return;
    }
    rj_state_create(m, &s, NULL);
    while (ok_steps < 200000 && (r = rj_step(m, s)) == RJ_OK) {
        ok_steps++;
        if (!state_finite(m, s)) bad_ok++;
    }
    snprintf(name, sizeof name, "non-finite: %s: no RJ_OK step leaves a non-finite state, and the blow-up is reported", what);
    rjt_check(&T, bad_ok == 0 && r != RJ_OK, name, "%ld steps returned RJ_OK, %ld of them non-finite; then %s: %s", ok_steps, bad_ok,
              rj_result_str(r), rj_state_error(s));
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
}

static void test_nonfinite(void)
{
    rj_link_def links[2] = { rj_default_link_def(), rj_default_link_def() };
    rj_joint_def joints[2] = { rj_default_joint_def(), rj_default_joint_def() };
    rj_scene_def scene = rj_default_scene_def();
    rj_model *m;
    rj_error err;
    double bound;
    /* a free flexible strip at 3 x its bound, energy taken every 1000 steps */
    links[0].height = 0.01;
    links[0].omega = 1;
    scene.links = links;
    scene.link_count = 1;
    rj_model_create(&scene, &m, &err, NULL);
    bound = rj_model_dt_bound(m);
    rj_model_destroy(m, NULL);
    scene.solver.dt = 3 * bound;
    scene.solver.allow_unstable = 1;
    scene.solver.energy_every = 1000;
    nonfinite_case("flexible strip at 3 x its bound, energy_every 1000", &scene);
    /* a rigid hub (massless nodes) carrying a flexible panel, above the bound */
    links[0] = rj_default_link_def();
    links[0].fidelity = RJ_LINK_RIGID;
    links[0].root = RJ_ROOT_PINNED;
    links[0].omega = 5;
    links[1].height = 0.01;
    joints[0].body1 = 0;
    joints[0].body2 = 1;
    joints[0].spring_k = 50;
    scene.link_count = 2;
    scene.joints = joints;
    scene.joint_count = 1;
    scene.solver = rj_default_solver_def();
    rj_model_create(&scene, &m, &err, NULL);
    bound = rj_model_dt_bound(m);
    rj_model_destroy(m, NULL);
    scene.solver.dt = 2.5 * bound;
    scene.solver.allow_unstable = 1;
    nonfinite_case("rigid hub with a flexible panel at 2.5 x the bound", &scene);
    {
        /* a crafted state whose rigid hub node sits at y = -1e308: the body's pose puts it
           back, and the velocity taken from the two positions is infinite while both are
           finite; the step must not return RJ_OK with it */
        rj_state *s;
        unsigned char *ck;
        size_t size;
        double far = -1e308;
        rj_result r;
        scene.solver = rj_default_solver_def();
        rj_model_create(&scene, &m, &err, NULL);
        rj_state_create(m, &s, NULL);
        size = rj_state_save(m, s, NULL, 0);
        ck = (unsigned char *)malloc(size);
        rj_state_save(m, s, ck, size);
        memcpy(ck + CK_DOUBLES + 8 * (CK_X0 + rj_model_node_count(m) + 1), &far, 8);
        reseal(ck, size);
        r = rj_state_load(m, s, ck, size, &err);
        if (r == RJ_OK) r = rj_step(m, s);
        rjt_check(&T, r != RJ_OK || state_finite(m, s), "non-finite: a step from a rigid node at y = -1e308 does not return RJ_OK with an infinite velocity",
                  "%s: %s", rj_result_str(r), r == RJ_OK ? "" : rj_state_error(s));
        free(ck);
        rj_state_destroy(s, NULL);
        rj_model_destroy(m, NULL);
    }
}

/* A model with a lock, friction, a spring and both limits, for the checkpoint checks. */
static rj_model *ck_model(double friction, int method, double spring, double E, int has_reverse)
{
    rj_link_def links[2] = { rj_default_link_def(), rj_default_link_def() };
    rj_joint_def joints[2] = { rj_default_joint_def(), rj_default_joint_def() };
    rj_scene_def scene = rj_default_scene_def();
    rj_model *m = NULL;
    rj_error err;
    links[0].height = links[1].height = 0.01;
    links[0].E = links[1].E = E;
    joints[0].body1 = -1;
    joints[0].body2 = 0;
    joints[0].angle0 = 0;
    joints[0].spring_k = 20;
    joints[0].spring_free_angle = rj_rad(90);
    joints[1].body1 = 0;
    joints[1].body2 = 1;
    joints[1].has_forward = 1;
    joints[1].forward = rj_rad(200);
    joints[1].has_reverse = has_reverse;
    joints[1].reverse = rj_rad(150);
    joints[1].method = method;
    joints[1].friction = friction;
    joints[1].spring_k = spring;
    joints[1].spring_free_angle = rj_rad(90);
    scene.links = links;
    scene.link_count = 2;
    scene.joints = joints;
    scene.joint_count = 2;
    if (rj_model_create(&scene, &m, &err, NULL) != RJ_OK) printf("ck_model: %s\n", err.msg);
    return m;
}

/* Loads an edited checkpoint and checks that it is refused with the state unchanged. */
static void ck_refused(const char *what, const char *expect, const rj_model *m, rj_state *s, const unsigned char *ck, size_t size)
{
    rj_error err;
    unsigned char *before, *after;
    const size_t n = rj_state_save(m, s, NULL, 0);
    rj_result r;
    char name[160];
    before = (unsigned char *)malloc(n);
    after = (unsigned char *)malloc(n);
    rj_state_save(m, s, before, n);
    memset(&err, 0, sizeof err);
    r = rj_state_load(m, s, ck, size, &err);
    rj_state_save(m, s, after, n);
    snprintf(name, sizeof name, "checkpoint: %s is refused, the state unchanged", what);
    rjt_check(&T, r == RJ_ERR_CHECKPOINT && memcmp(before, after, n) == 0 && strstr(err.msg, expect) != NULL, name,
              "%s [%s] %s", rj_result_str(r), err.field, err.msg);
    free(before);
    free(after);
}

static void test_checkpoints(void)
{
    rj_model *m = ck_model(0.1, RJ_METHOD_ADAPTIVE, 5, 70e9, 1);
    rj_model *others[5];
    static const char *const differ[5] = { "friction", "method", "spring", "E", "limits" };
    rj_state *s;
    unsigned char *ck, *edit;
    size_t size, frame_doubles;
    unsigned long long pay;
    double v;
    int i, flag = 7;
    long long steps = (long long)1 << 62;
    rj_state_create(m, &s, NULL);
    for (i = 0; i < 50; i++) rj_step(m, s);
    size = rj_state_save(m, s, NULL, 0);
    ck = (unsigned char *)malloc(size + 16);
    edit = (unsigned char *)malloc(size + 16);
    rj_state_save(m, s, ck, size);
    memcpy(&pay, ck + 16, 8);
    /* 2 joint flags and a spare; after them the inputs' switch and the 2 joints' torques,
       then the node forces' switch, 3 values per node, and 3 per node the last step
       applied; then the peaks' switch, 2 per joint and 7 per link */
    frame_doubles = (size_t)(pay - 8 - sizeof(int) * 3 - 8 * 3 - 8 * (6 * (size_t)rj_model_node_count(m) + 1) -
                             8 * (1 + 2 * 2 + 7 * 2)) / 8;
    /* crafted values behind a valid checksum */
    memcpy(edit, ck, size);
    memcpy(edit + CK_DOUBLES + 8 * frame_doubles + sizeof(int), &flag, sizeof flag);
    reseal(edit, size);
    ck_refused("joint flag 7", "flag", m, s, edit, size);
    /* the inputs' switch as -0: it would load and save back other bytes */
    memcpy(edit, ck, size);
    v = -0.0;
    memcpy(edit + CK_DOUBLES + 8 * frame_doubles + sizeof(int) * 3, &v, 8);
    reseal(edit, size);
    ck_refused("an inputs switch of -0", "switch of the input torques", m, s, edit, size);
    /* the node forces' switch as -0, and a node force of NaN */
    memcpy(edit, ck, size);
    memcpy(edit + CK_DOUBLES + 8 * frame_doubles + sizeof(int) * 3 + 8 * 3, &v, 8);
    reseal(edit, size);
    ck_refused("a node forces' switch of -0", "switch of the input node forces", m, s, edit, size);
    memcpy(edit, ck, size);
    v = NAN;
    memcpy(edit + CK_DOUBLES + 8 * frame_doubles + sizeof(int) * 3 + 8 * 4 + 8 * 5, &v, 8);
    reseal(edit, size);
    ck_refused("a node force of NaN", "input node force 5 is nan", m, s, edit, size);
    /* the peaks' switch as -0, and a link's peak at an element it does not have (the
       first link's moment: its value, time, element) */
    {
        const size_t peaks = CK_DOUBLES + 8 * frame_doubles + sizeof(int) * 3 + 8 * 3 +
                             8 * (6 * (size_t)rj_model_node_count(m) + 1);
        const double bad[3] = { 1.0, 0.5, 1e9 };
        memcpy(edit, ck, size);
        v = -0.0;
        memcpy(edit + peaks, &v, 8);
        reseal(edit, size);
        ck_refused("a peaks switch of -0", "switch of the peaks", m, s, edit, size);
        memcpy(edit, ck, size);
        memcpy(edit + peaks + 8 * (1 + 2 * 2), bad, sizeof bad);
        reseal(edit, size);
        ck_refused("a peak at element 1e9", "element 1e+09", m, s, edit, size);
    }
    memcpy(edit, ck, size);
    v = HUGE_VAL;
    memcpy(edit + CK_DOUBLES + 8 * (CK_X0 + 3), &v, 8);
    reseal(edit, size);
    ck_refused("a position of +inf", "not finite", m, s, edit, size);
    memcpy(edit, ck, size);
    v = 1e300;
    memcpy(edit + CK_DOUBLES + 8 * CK_WARN, &v, 8);
    reseal(edit, size);
    ck_refused("a warning count of 1e300", "beyond the 1e100", m, s, edit, size);
    memcpy(edit, ck, size);
    v = 2.5;
    memcpy(edit + CK_DOUBLES + 8 * CK_WARN, &v, 8);
    reseal(edit, size);
    ck_refused("a warning count of 2.5", "warning count", m, s, edit, size);
    memcpy(edit, ck, size);
    memcpy(edit + 24, &steps, 8);
    reseal(edit, size);
    ck_refused("a step count of 2^62", "steps", m, s, edit, size);
    memcpy(edit, ck, size);
    memset(edit + size, 0, 16);
    ck_refused("a checkpoint with 16 trailing bytes", "after its end", m, s, edit, size + 16);
    /* another model: each one field apart */
    others[0] = ck_model(0.2, RJ_METHOD_ADAPTIVE, 5, 70e9, 1);
    others[1] = ck_model(0.1, RJ_METHOD_MOMENTUM, 5, 70e9, 1);
    others[2] = ck_model(0.1, RJ_METHOD_ADAPTIVE, 6, 70e9, 1);
    others[3] = ck_model(0.1, RJ_METHOD_ADAPTIVE, 5, 69e9, 1);
    others[4] = ck_model(0.1, RJ_METHOD_ADAPTIVE, 5, 70e9, 0);
    for (i = 0; i < 5; i++) {
        rj_state *o = NULL;
        char what[120];
        rj_state_create(others[i], &o, NULL);
        snprintf(what, sizeof what, "a checkpoint of a model with another %s", differ[i]);
        ck_refused(what, "another model", others[i], o, ck, size);
        rj_state_destroy(o, NULL);
        rj_model_destroy(others[i], NULL);
    }
    {
        /* another model of another size: "another model", not "truncated" */
        rj_link_def link = rj_default_link_def();
        rj_scene_def scene = rj_default_scene_def();
        rj_model *small;
        rj_state *o = NULL;
        rj_error err;
        scene.links = &link;
        scene.link_count = 1;
        rj_model_create(&scene, &small, &err, NULL);
        rj_state_create(small, &o, NULL);
        ck_refused("a checkpoint of a larger model", "another model", small, o, ck, size);
        rj_state_destroy(o, NULL);
        rj_model_destroy(small, NULL);
    }
    free(ck);
    free(edit);
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
}

/* A rigid chain of 256 links turning fast, with no limits, blows up at a coarse step: the
   message names no limit method and ends at a whole word. */
static void test_messages(void)
{
    enum { N = 256 };
    static rj_link_def links[N];
    static rj_joint_def joints[N];
    rj_scene_def scene;
    rj_model *m;
    rj_state *s;
    rj_error err;
    rj_result r = RJ_OK;
    const char *e;
    size_t len;
    int i;
    chain_scene(N, 1, RJ_LINK_RIGID, links, joints, &scene);
    for (i = 0; i < N; i++) {
        joints[i].angle0 = rj_rad(170);
        joints[i].method = RJ_METHOD_MOMENTUM;
    }
    joints[0].rate0 = 10;
    scene.solver.dt = 1e-3;
    if (rj_model_create(&scene, &m, &err, NULL) != RJ_OK) {
        rjt_check(&T, 0, "messages: the rigid chain builds", "%s", err.msg);
        return;
    }
    rj_state_create(m, &s, NULL);
    for (i = 0; i < 20000 && (r = rj_step(m, s)) == RJ_OK; i++) {}
    e = rj_state_error(s);
    len = strlen(e);
    rjt_check(&T, r == RJ_ERR_BLOWUP && strstr(e, "RJ_METHOD_MOMENTUM") == NULL && strstr(e, "penalty") == NULL && strstr(e, "at a limit") == NULL
              && strstr(e, "fast rotation") != NULL,
              "messages: a blow-up without limits names fast rotation, not a limit, as its cause", "%s: %s", rj_result_str(r), e);
    rjt_check(&T, len > 0 && (e[len - 1] == '.' || isalnum((unsigned char)e[len - 1]) || e[len - 1] == ')'),
              "messages: the blow-up message ends at a whole word", "%lu characters, ends '%s'", (unsigned long)len, len > 12 ? e + len - 12 : e);
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
    rjt_check(&T, strstr(rj_result_str(RJ_ERR_TUNNEL), "quarter") != NULL, "messages: the tunnel rule is a quarter revolution",
              "%s", rj_result_str(RJ_ERR_TUNNEL));
    {
        /* a joint without limits that turns too far in one step is not told of limits */
        rj_model *sm;
        char msg[640];
        strip_model(0, 0, 0, &sm, &err);
        rj_model_destroy(sm, NULL);
        links[0] = rj_default_link_def();
        links[0].height = 0.01;
        joints[0] = rj_default_joint_def();
        joints[0].body1 = -1;
        joints[0].body2 = 0;
        joints[0].rate0 = 4e5;
        scene = rj_default_scene_def();
        scene.links = links;
        scene.link_count = 1;
        scene.joints = joints;
        scene.joint_count = 1;
        rj_model_create(&scene, &sm, &err, NULL);
        r = run_for(sm, 0.01, msg, sizeof msg);
        rjt_check(&T, r != RJ_OK && strstr(msg, "tunnel") == NULL, "messages: a joint without limits is not told its limits could be tunnelled",
                  "%s: %s", rj_result_str(r), msg);
        rj_model_destroy(sm, NULL);
    }
}

/* A lock needs a limit; a limit the joint never reaches is a warning. */
static void test_limits(void)
{
    rj_link_def link = rj_default_link_def();
    rj_joint_def joint = rj_default_joint_def();
    rj_scene_def scene = rj_default_scene_def();
    rj_model *m;
    rj_error err;
    rj_result r;
    link.height = 0.01;
    joint.body1 = -1;
    joint.body2 = 0;
    joint.lock = 1;
    scene.links = &link;
    scene.link_count = 1;
    scene.joints = &joint;
    scene.joint_count = 1;
    r = rj_model_create(&scene, &m, &err, NULL);
    rjt_check(&T, r == RJ_ERR_INVALID && strcmp(err.field, "joints[0].lock") == 0, "limits: a lock without a limit is refused",
              "[%s] %s", err.field, err.msg);
    /* the far side: from 360 deg the forward limit at 180 deg is met at 540 deg, and the
       spring rests at 180 deg */
    joint.angle0 = rj_rad(360);
    joint.has_forward = 1;
    joint.forward = rj_rad(180);
    joint.spring_k = 10;
    joint.spring_free_angle = rj_rad(180);
    r = rj_model_create(&scene, &m, &err, NULL);
    rjt_check(&T, r == RJ_OK && rj_model_warning_count(m) == 1 && strstr(rj_model_warnings(m), "never") != NULL,
              "limits: a forward limit on the far side of the motion is a warning", "%d: %s", r == RJ_OK ? rj_model_warning_count(m) : -1,
              r == RJ_OK ? rj_model_warnings(m) : err.msg);
    if (r == RJ_OK) rj_model_destroy(m, NULL);
    /* the deployment's way: spring past the latch, which it reaches */
    joint.angle0 = rj_rad(90);
    joint.spring_free_angle = rj_rad(200);
    r = rj_model_create(&scene, &m, &err, NULL);
    rjt_check(&T, r == RJ_OK && rj_model_warning_count(m) == 0, "limits: a latch the spring drives to gives no warning", "%d warnings: %s",
              r == RJ_OK ? rj_model_warning_count(m) : -1, r == RJ_OK ? rj_model_warnings(m) : err.msg);
    if (r == RJ_OK) rj_model_destroy(m, NULL);
    /* a start past the limit */
    joint.angle0 = rj_rad(185);
    r = rj_model_create(&scene, &m, &err, NULL);
    rjt_check(&T, r == RJ_OK && rj_model_warning_count(m) == 1 && strstr(rj_model_warnings(m), "past its forward limit") != NULL,
              "limits: a start past the limit is a warning", "%s", r == RJ_OK ? rj_model_warnings(m) : err.msg);
    if (r == RJ_OK) rj_model_destroy(m, NULL);
}

/* Link 1's angular momentum about the pin (the origin) in the step's conserved form:
   masses at x^{n+1} times v^{n+1/2}, plus the nodes' rotary inertias times their rates. */
static double impact_momentum(const rj_model *m, const rj_state *s)
{
    double L = 0, x[2], v[2], mass, rot;
    int i;
    for (i = 0; i < rj_link_node_count(m, 1); i++) {
        rj_node_position(m, s, 1, i, x);
        rj_node_velocity(m, s, 1, i, v);
        rj_node_mass(m, 1, i, &mass, &rot);
        L += mass * (x[0] * v[1] - x[1] * v[0]) + rot * rj_node_rate(m, s, 1, i);
    }
    return L;
}

/* The latch's load, by the conservation of angular momentum about the pin (the ground's
   pin forces have no moment about it): over the impact, the link's angular momentum
   changes by the sum of the latch impulses (velocity-level methods) or of the limit
   torque times dt (penalty, adaptive), to round-off. */
static void test_latch_load(void)
{
    static const int methods[5] = { RJ_METHOD_PENALTY, RJ_METHOD_ADAPTIVE, RJ_METHOD_MOMENTUM, RJ_METHOD_FORCED, RJ_METHOD_ENERGY };
    static const char *const names[5] = { "penalty", "adaptive", "momentum", "forced", "energy" };
    int k;
    for (k = 0; k < 5; k++) {
        impact_opts o = impact_default_opts();
        rj_link_def links[2];
        rj_joint_def joint;
        rj_scene_def scene;
        rj_model *m;
        rj_state *s;
        rj_error err;
        double L0, sum = 0, worst = 0, peak = 0;
        char name[160];
        o.method = methods[k];
        impact_scene(&o, links, &joint, &scene);
        rj_model_create(&scene, &m, &err, NULL);
        rj_state_create(m, &s, NULL);
        rj_step(m, s);
        L0 = impact_momentum(m, s);
        while (rj_state_time(s) < 0.02 && rj_step(m, s) == RJ_OK) {
            const double impulse = rj_joint_latch_impulse(m, s, 0) + rj_joint_torque(m, s, 0, RJ_TORQUE_LIMIT) * rj_model_dt(m);
            const double drift = fabs(impact_momentum(m, s) - L0 - sum - impulse);
            sum += impulse;
            if (drift > worst) worst = drift;
            if (fabs(impulse) > peak) peak = fabs(impulse);
        }
        snprintf(name, sizeof name, "latch load (%s): the link's angular momentum changes by the latch's impulses", names[k]);
        rjt_check(&T, worst < 1e-11 * fabs(L0) && fabs(sum) > 0.5 * fabs(L0), name,
                  "L from %.6g to %.6g kg m^2/s, impulses sum to %.6g N m s (peak %.4g in one step, %.4g N m as a mean torque); worst mismatch %.3g",
                  L0, impact_momentum(m, s), sum, peak, peak / rj_model_dt(m), worst);
        rj_state_destroy(s, NULL);
        rj_model_destroy(m, NULL);
    }
}

/* The step search counts every joint's springs and tables with its adaptive limits, the
   301st as the first: a chain of 300 links whose one stiff joint (a steep table and
   adaptive limits) sets the step, given first or last in the joints array. (The search
   once kept the first 256 joints' stiffness only; the last one's table went missing and
   its step came out longer.) */
static rj_result chain_model(int special_last, rj_model **m, rj_error *err)
{
    enum { N = 300 };
    static rj_link_def L[N];
    static rj_joint_def J[N];
    rj_scene_def sc = rj_default_scene_def();
    const int special = N / 2;
    int i;
    for (i = 0; i < N; i++) {
        const int slot = special_last ? (i == special ? N - 1 : i > special ? i - 1 : i) : i;
        L[i] = rj_default_link_def();
        L[i].length = 0.1;
        L[i].elements = 1;
        L[i].height = 0.02;
        L[i].width = 0.02;
        J[slot] = rj_default_joint_def();
        J[slot].body1 = i - 1;
        J[slot].body2 = i;
        J[slot].angle0 = 3.14159265358979323846;
        if (i != special)
            continue;
        J[slot].table_count = 3;
        J[slot].table_angle[0] = 3.0;
        J[slot].table_angle[1] = 3.14159265358979323846;
        J[slot].table_angle[2] = 3.3;
        J[slot].table_torque[0] = -2e5;
        J[slot].table_torque[1] = 0;
        J[slot].table_torque[2] = 2e5;
        J[slot].has_forward = 1;
        J[slot].forward = 4.0;
        J[slot].method = RJ_METHOD_ADAPTIVE;
    }
    sc.links = L;
    sc.link_count = N;
    sc.joints = J;
    sc.joint_count = N;
    return rj_model_create(&sc, m, err, NULL);
}

static void test_many_joints(void)
{
    rj_model *first = NULL, *last = NULL;
    rj_error err;
    const int ok = chain_model(0, &first, &err) == RJ_OK && chain_model(1, &last, &err) == RJ_OK;
    const double a = ok ? rj_model_dt(first) : 0, b = ok ? rj_model_dt(last) : 0;
    rjt_check(&T, ok && fabs(b / a - 1) < 1e-9,
              "step search: the 300th joint's table counts as the first's (300 joints, adaptive limits)",
              "dt %.10g s with the stiff joint first, %.10g s last (%+.2e) %s", a, b, ok ? b / a - 1 : 0.0,
              ok ? "" : err.msg);
    if (first) rj_model_destroy(first, NULL);
    if (last) rj_model_destroy(last, NULL);
}

/* rj_model_init into the caller's memory: no block and a short block are refused with
   their own words, the exact size builds. */
static void test_model_block(void)
{
    rj_link_def l = rj_default_link_def();
    rj_scene_def sc = rj_default_scene_def();
    rj_model *m = NULL;
    rj_error err;
    size_t size;
    void *mem;
    rj_result r;
    sc.links = &l;
    sc.link_count = 1;
    size = rj_model_size(&sc, &err);
    r = rj_model_init(&sc, NULL, size, &m, &err);
    rjt_check(&T, r == RJ_ERR_NOMEM && strcmp(err.field, "mem") == 0 && strstr(err.msg, "NULL") != NULL,
              "rj_model_init: no block is refused as no block", "[%s] %s", err.field, err.msg);
    mem = malloc(size);
    r = rj_model_init(&sc, mem, size - 1, &m, &err);
    rjt_check(&T, r == RJ_ERR_NOMEM && strcmp(err.field, "size") == 0 && strstr(err.msg, "smaller") != NULL,
              "rj_model_init: a block one byte short is refused naming both sizes", "[%s] %s", err.field, err.msg);
    r = rj_model_init(&sc, mem, size, &m, &err);
    rjt_check(&T, r == RJ_OK && m != NULL && rj_model_node_count(m) == l.elements + 1,
              "rj_model_init: the size rj_model_size gives builds the model", "%s", r == RJ_OK ? "built" : err.msg);
    free(mem);
}

/* The model of a scene file's text, or NULL with a FAIL line naming the check. */
static rj_model *model_of_text(const char *check, const char *text)
{
    rj_scene_file f;
    rj_scene_def def;
    rj_error err;
    rj_model *m = NULL;
    if (rj_scene_parse(text, strlen(text), check, &f, &err) != RJ_OK) {
        rjt_check(&T, 0, check, "the scene is refused: %s", err.msg);
        return NULL;
    }
    def = rj_scene_file_def(&f);
    if (rj_model_create(&def, &m, &err, NULL) != RJ_OK) {
        rjt_check(&T, 0, check, "the model is refused: %s", err.msg);
        m = NULL;
    }
    rj_scene_file_free(&f);
    return m;
}

/* ------------------------------------------------------------------ a failed step in place */

/* The model of these links and joints under gravity g (down), or NULL with a FAIL line
   that names the check and the refusal. */
static rj_model *model_of(const char *check, rj_link_def *links, int link_count,
                          rj_joint_def *joints, int joint_count, double g)
{
    rj_scene_def scene = rj_default_scene_def();
    rj_model *m = NULL;
    rj_error err;
    scene.links = links;
    scene.link_count = link_count;
    scene.joints = joints;
    scene.joint_count = joint_count;
    scene.solver.gravity[1] = -g;
    if (rj_model_create(&scene, &m, &err, NULL) != RJ_OK) {
        rjt_check(&T, 0, check, "the model is refused: %s", err.msg);
        return NULL;
    }
    return m;
}

/* What a state is, for comparing two: every node's position and velocity, every joint's
   angle, rate and flag, time and steps, hashed bit for bit. */
static unsigned long long state_digest(const rj_model *m, const rj_state *s)
{
    unsigned long long h = 14695981039346656037ULL;
    const double t = rj_state_time(s);
    const long steps = rj_state_steps(s);
    int l, k, j;
    h = fnv_on(h, &t, sizeof t);
    h = fnv_on(h, &steps, sizeof steps);
    for (l = 0; l < rj_model_link_count(m); l++)
        for (k = 0; k < rj_link_node_count(m, l); k++) {
            double p[2], v[2], r[2];
            rj_node_position(m, s, l, k, p);
            rj_node_velocity(m, s, l, k, v);
            r[0] = rj_node_rotation(m, s, l, k);
            r[1] = rj_node_rate(m, s, l, k);
            h = fnv_on(h, p, sizeof p);
            h = fnv_on(h, v, sizeof v);
            h = fnv_on(h, r, sizeof r);
        }
    for (j = 0; j < rj_model_joint_count(m); j++) {
        const double th = rj_joint_theta_running(m, s, j), w = rj_joint_rate(m, s, j);
        const int flag = rj_joint_flag(m, s, j);
        h = fnv_on(h, &th, sizeof th);
        h = fnv_on(h, &w, sizeof w);
        h = fnv_on(h, &flag, sizeof flag);
    }
    return h;
}

/* Two flexible links of 300 elements: a model that steps in place. */
static rj_model *in_place_model(void)
{
    rj_link_def links[2];
    rj_joint_def joints[2];
    int i;
    for (i = 0; i < 2; i++) {
        links[i] = rj_default_link_def();
        links[i].height = 0.01;
        links[i].elements = 300;
        joints[i] = rj_default_joint_def();
        joints[i].body1 = i - 1;
        joints[i].body2 = i;
        joints[i].spring_k = 20;
        joints[i].spring_free_angle = rj_rad(90);
    }
    joints[1].angle0 = rj_rad(180);
    return model_of("rollback: model", links, 2, joints, 2, 0);
}

/* A step that fails leaves the state as it was, in place too: a bad torque is refused
   before anything moves, and a torque that makes a later step fail does not replay the
   steps before it with itself. */
static void test_in_place_rollback(void)
{
    rj_model *m = in_place_model();
    rj_state *s;
    double *torque;
    unsigned long long before;
    const double bad[3] = { NAN, INFINITY, 1e101 };
    long k, failed_at = -1;
    int i, same = 1;
    if (!rjt_check(&T, m != NULL && rj_model_in_place(m), "rollback: the model steps in place",
                   "in place %d", m ? rj_model_in_place(m) : -1))
        return;
    rj_state_create(m, &s, NULL);
    torque = rj_state_joint_torques(m, s);
    for (k = 0; k < 500; k++)
        rj_step(m, s);
    before = state_digest(m, s);
    for (i = 0; i < 3; i++) {
        rj_result r;
        torque[1] = bad[i];
        r = rj_step(m, s);
        same &= r == RJ_ERR_INVALID && state_digest(m, s) == before && rj_state_steps(s) == 500;
    }
    rjt_check(&T, same, "rollback: a NaN, infinite or 1e101 torque leaves the state at step 500",
              "steps %ld", rj_state_steps(s));
    /* a valid but huge torque: the step that fails must leave the state of the step before */
    torque[1] = 2e5;
    for (k = 0; k < 5000 && failed_at < 0; k++) {
        before = state_digest(m, s);
        if (rj_step(m, s) != RJ_OK)
            failed_at = rj_state_steps(s);
    }
    rjt_check(&T, failed_at > 500 && state_digest(m, s) == before,
              "rollback: the step a 2e5 N m torque makes fail leaves the state before it",
              "failed at step %ld (state %s)", failed_at,
              state_digest(m, s) == before ? "as it was" : "changed");
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
}

/* ------------------------------------------------------------------ rj_settle */

/* A scene already at rest settles at once: one unloaded link, no gravity, no springs. */
static void test_settle_at_rest(void)
{
    rj_link_def link = rj_default_link_def();
    rj_joint_def joint = rj_default_joint_def();
    rj_model *m;
    rj_state *s;
    rj_result r;
    joint.body1 = -1;
    joint.body2 = 0;
    m = model_of("settle at rest: model", &link, 1, &joint, 1, 0);
    if (!m || rj_state_create(m, &s, NULL) != RJ_OK)
        return;
    r = rj_settle(m, s, 1e-12, 1000);
    rjt_check(&T, r == RJ_OK, "settle: a scene at rest settles within 1000 steps", "%s (%s)",
              rj_result_str(r), rj_state_error(s));
    /* a fine cantilever under gravity is not at rest: its first steps' kinetic energy
       (2e-15 J at 2000 elements) is far below the sag's, and it must not pass for rest */
    {
        rj_link_def fine = rj_default_link_def();
        rj_model *mf;
        rj_state *sf;
        fine.elements = 2000;
        fine.width = 0.02;
        fine.height = 0.01;
        fine.root = RJ_ROOT_CLAMPED;
        mf = model_of("settle: fine cantilever model", &fine, 1, NULL, 0, 9.81);
        if (mf && rj_state_create(mf, &sf, NULL) == RJ_OK) {
            r = rj_settle(mf, sf, 1e-12, 1000);
            rjt_check(&T, r == RJ_ERR_NOT_CONVERGED,
                      "settle: a 2000-element cantilever under gravity is not at rest in 1000 "
                      "steps", "%s after %.3g s", rj_result_str(r), rj_state_time(sf));
            rj_state_destroy(sf, NULL);
        }
        rj_model_destroy(mf, NULL);
    }
    /* bad arguments are named, not the previous error kept */
    r = rj_settle(m, s, 0, 1000);
    rjt_check(&T, r == RJ_ERR_INVALID && strstr(rj_state_error(s), "tol = 0") != NULL,
              "settle: tol 0 is refused by name", "%s", rj_state_error(s));
    r = rj_settle(m, s, 1e-12, 0);
    rjt_check(&T, r == RJ_ERR_INVALID && strstr(rj_state_error(s), "max_steps = 0") != NULL,
              "settle: max_steps 0 is refused by name", "%s", rj_state_error(s));
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
}

/* A link falling under gravity onto an adaptive limit just below it: every restart from
   rest starts the accounts again while the limit holds energy, which it then gives back;
   measured against the energy of the last restart that read as energy created. */
static void test_settle_on_a_limit(void)
{
    static const int starts[3] = { 60, 300, 330 };
    int i, settled = 0;
    char last[200] = "";
    for (i = 0; i < 3; i++) {
        rj_link_def link = rj_default_link_def();
        rj_joint_def joint = rj_default_joint_def();
        rj_model *m;
        rj_state *s;
        link.height = 0.01;
        joint.body1 = -1;
        joint.body2 = 0;
        joint.angle0 = rj_rad(starts[i]);
        joint.has_reverse = 1;
        joint.reverse = rj_rad(starts[i] - 1);
        joint.lock = 1;
        m = model_of("settle on a limit: model", &link, 1, &joint, 1, 9.81);
        if (!m || rj_state_create(m, &s, NULL) != RJ_OK)
            continue;
        if (rj_settle(m, s, 1e-12, 300000) == RJ_OK)
            settled++;
        else
            snprintf(last, sizeof last, "from %d deg: %.150s", starts[i], rj_state_error(s));
        rj_state_destroy(s, NULL);
        rj_model_destroy(m, NULL);
    }
    rjt_check(&T, settled == 3, "settle: a link falling onto a locking adaptive limit settles",
              "%d of 3 %s", settled, last);
}

/* The elastica's load is ramped on by a table over 0.5 s. The settled state keeps its
   time, so the run goes on under the load it settled under: the tip stays where it
   settled (a reset to t = 0, where the table gives 0, whips it up). */
static void test_settle_keeps_time(void)
{
    static const char text[] =
        "link beam\n  length = 1\n  elements = 20\n  E = 70e9\n  rho = 2700\n"
        "  width = 0.02\n  height = 0.004\n  root = clamped\n"
        "load tip\n  link = beam\n  node = last\n  force = 0 -74.66666666666667\n"
        "  table = 0 0, 0.5 1\n";
    rj_model *m = model_of_text("settle keeps time: scene", text);
    rj_state *s;
    double tip0[2], tip[2], worst = 0, t0;
    int k;
    if (!m || rj_state_create(m, &s, NULL) != RJ_OK)
        return;
    if (!rjt_check(&T, rj_settle(m, s, 1e-12, 10000000L) == RJ_OK, "settle keeps time: settles",
                   "%s", rj_state_error(s)))
        return;
    t0 = rj_state_time(s);
    rj_node_position(m, s, 0, 20, tip0);
    for (k = 0; k < 2000; k++) {
        rj_step(m, s);
        rj_node_position(m, s, 0, 20, tip);
        if (fabs(tip[1] - tip0[1]) > worst)
            worst = fabs(tip[1] - tip0[1]);
    }
    rjt_check(&T, t0 > 0.5 && worst < 1e-6,
              "settle keeps time: past the ramp, the tip stays where it settled",
              "time %.4g s, tip y %.5f m, moves %.3g m in 2000 steps (<= 1e-6)", t0, tip0[1],
              worst);
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
}

/* ------------------------------------------------------------------ damping with latches */

/* The README's two-link strip with a damper on both hinges and the adaptive latch:
   the automatic step exists (the damping's dt d falls with dt while the latch's omega dt
   stays), and the run at it is stable. */
static void test_damped_latch_step(void)
{
    static const double kc[3][2] = { { 20, 2 }, { 200, 5 }, { 20, 20 } };
    int i;
    for (i = 0; i < 3; i++) {
        rj_link_def links[2] = { rj_default_link_def(), rj_default_link_def() };
        rj_joint_def joints[2] = { rj_default_joint_def(), rj_default_joint_def() };
        rj_scene_def scene = rj_default_scene_def();
        rj_model *m;
        rj_state *s;
        rj_error err;
        rj_result r;
        char name[96];
        links[0].height = links[1].height = 0.01;
        joints[0].body1 = -1;
        joints[0].body2 = 0;
        joints[0].angle0 = 0;
        joints[0].spring_k = kc[i][0];
        joints[0].spring_free_angle = rj_rad(90);
        joints[0].damping = kc[i][1];
        joints[1].body1 = 0;
        joints[1].body2 = 1;
        joints[1].has_reverse = 1;
        joints[1].reverse = rj_rad(150);
        joints[1].lock = 1;
        joints[1].spring_k = 5;
        joints[1].spring_free_angle = rj_rad(90);
        joints[1].damping = kc[i][1];
        scene.links = links;
        scene.link_count = 2;
        scene.joints = joints;
        scene.joint_count = 2;
        snprintf(name, sizeof name, "damped latch: k = %g, c = %g has an automatic step",
                 kc[i][0], kc[i][1]);
        r = rj_model_create(&scene, &m, &err, NULL);
        if (!rjt_check(&T, r == RJ_OK, name, "%.200s", r == RJ_OK ? "" : err.msg))
            continue;
        rjt_check(&T, rj_model_dt(m) <= rj_model_dt_bound(m), name, "dt %.4g s <= bound %.4g s",
                  rj_model_dt(m), rj_model_dt_bound(m));
        rj_state_create(m, &s, NULL);
        r = rj_run(m, s, 0.5, 0, NULL, NULL);
        /* c = 20 damps the hinge so hard that it has not reached its latch in 0.5 s */
        snprintf(name, sizeof name, "damped latch: k = %g, c = %g runs 0.5 s%s", kc[i][0],
                 kc[i][1], i < 2 ? " and latches" : "");
        rjt_check(&T, r == RJ_OK && (i == 2 || rj_joint_flag(m, s, 1) == RJ_LOCKED), name,
                  "%s, flag %d %.150s", rj_result_str(r), rj_joint_flag(m, s, 1),
                  rj_state_error(s));
        rj_state_destroy(s, NULL);
        rj_model_destroy(m, NULL);
    }
}

/* ------------------------------------------------------------------ pins reached twice */

/* Three flexible links: L1 hangs from L0's tip, and L2 is pinned to node 0 of L1, which
   is the node L1 hangs by. All three nodes are one pin: under gravity they must stay
   together and the energy balance close (two groups for one node tore the pin apart). */
static void test_pin_on_a_pinned_root(void)
{
    rj_link_def links[3];
    rj_joint_def joints[3];
    rj_model *m;
    rj_state *s;
    rj_result r;
    rj_energy e;
    double a[2], b[2], c[2], gap;
    int i;
    for (i = 0; i < 3; i++) {
        links[i] = rj_default_link_def();
        links[i].height = 0.01;
        joints[i] = rj_default_joint_def();
        joints[i].body2 = i;
    }
    joints[0].body1 = -1;
    joints[1].body1 = 0;
    joints[1].angle0 = rj_rad(150);
    joints[2].body1 = 1;
    joints[2].node1 = 0;
    joints[2].angle0 = rj_rad(90);
    m = model_of("pin on a pinned root: model", links, 3, joints, 3, 9.81);
    if (!m || rj_state_create(m, &s, NULL) != RJ_OK)
        return;
    r = rj_run(m, s, 0.2, 0, NULL, NULL);
    rj_node_position(m, s, 0, rj_link_node_count(m, 0) - 1, a);
    rj_node_position(m, s, 1, 0, b);
    rj_node_position(m, s, 2, 0, c);
    gap = fabs(a[0] - b[0]) + fabs(a[1] - b[1]) + fabs(b[0] - c[0]) + fabs(b[1] - c[1]);
    rj_state_energy(m, s, &e);
    rjt_check(&T, r == RJ_OK && gap == 0 && fabs(e.balance) < 1e-6 * (fabs(e.gravity) + 1),
              "pin on a pinned root: one pin for three links, the balance closed",
              "%s, pins %.3g m apart, balance %.3g J %.150s", rj_result_str(r), gap, e.balance,
              rj_state_error(s));
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
}

/* ------------------------------------------------------------------ numbers carried */

/* What validation accepts, the step, the accounts and a checkpoint can carry: values
   beyond are refused by name (they built models whose checkpoints were refused, loads
   that read as zero, gravity that blew up at the automatic step). */
static void test_bounds_carried(void)
{
    static const char *const texts[5] = {
        "link a\n  length = 1\n  rho = 1e300\n",
        "solver\n  gravity = 1e6 -1e6\nlink a\n  length = 1\n",
        "link a\n  length = 1\nload f\n  link = a\n  node = last\n  force = 0 -1\n"
        "  table = 0 0, 1e100 1\n",
        "link a\n  length = 1\nload f\n  link = a\n  node = last\n  force = 0 -1e200\n",
        "link a\n  length = 1\n  E = 1e300\n",
    };
    static const char *const fields[5] = { "rho", "gravity", "1e+100", "force = -1e200", "E" };
    int i;
    for (i = 0; i < 5; i++) {
        rj_scene_file f;
        rj_error err;
        rj_result r = rj_scene_parse(texts[i], strlen(texts[i]), "bounds", &f, &err);
        char name[96];
        if (r == RJ_OK) {
            rj_scene_def def = rj_scene_file_def(&f);
            rj_model *m;
            r = rj_model_create(&def, &m, &err, NULL);
            if (r == RJ_OK)
                rj_model_destroy(m, NULL);
            rj_scene_file_free(&f);
        }
        snprintf(name, sizeof name, "bounds: %s beyond what a run carries is refused by name",
                 fields[i]);
        rjt_check(&T, r != RJ_OK && strstr(err.msg, fields[i]) != NULL, name, "%s",
                  r == RJ_OK ? "accepted" : err.msg);
    }
    {
        /* nan spelled out as a second component is a number that is not finite, not a unit */
        static const char nan_text[] = "solver\n  gravity = 0 nan\n";
        rj_scene_file f;
        rj_error err;
        const rj_result r = rj_scene_parse(nan_text, sizeof nan_text - 1, "nan", &f, &err);
        if (r == RJ_OK)
            rj_scene_file_free(&f);
        rjt_check(&T, r != RJ_OK && strstr(err.msg, "not a finite number") != NULL,
                  "bounds: gravity = 0 nan is named a non-finite number", "%s",
                  r == RJ_OK ? "accepted" : err.msg);
    }
    {
        /* a model at the largest density and gravity: its own checkpoint loads back */
        rj_link_def link = rj_default_link_def();
        rj_joint_def pin = rj_default_joint_def();
        rj_model *m;
        rj_state *s;
        rj_error err;
        unsigned char *ck;
        size_t size;
        rj_result r;
        link.rho = 1e30;
        link.length = 1e6;
        link.height = 1e6;
        link.width = 1e6;
        pin.body1 = -1;
        pin.body2 = 0;
        pin.angle0 = 0.5;
        m = model_of("bounds: the largest model", &link, 1, &pin, 1, 1e5);
        if (!m || rj_state_create(m, &s, NULL) != RJ_OK)
            return;
        while (rj_state_steps(s) < 100 && rj_step(m, s) == RJ_OK) {
        }
        size = rj_state_save(m, s, NULL, 0);
        ck = (unsigned char *) malloc(size);
        rj_state_save(m, s, ck, size);
        r = rj_state_load(m, s, ck, size, &err);
        rjt_check(&T, r == RJ_OK, "bounds: the largest model's checkpoint loads back", "%s",
                  r == RJ_OK ? "ok" : err.msg);
        free(ck);
        rj_state_destroy(s, NULL);
        rj_model_destroy(m, NULL);
    }
}

/* A blow-up the loads cause is blamed on them, and a rigid chain's names its fastest
   joint and what helps. */
static void test_blowup_causes(void)
{
    static const char text[] =
        "link a\n  length = 1\n  height = 0.01\n  root = clamped\n"
        "load f\n  link = a\n  node = last\n  force = 0 -1e12\n";
    rj_model *m = model_of_text("causes: model", text);
    rj_state *s;
    rj_result r;
    if (!m || rj_state_create(m, &s, NULL) != RJ_OK)
        return;
    r = rj_run(m, s, 1000 * rj_model_dt(m), 0, NULL, NULL);
    rjt_check(&T, r != RJ_OK && strstr(rj_state_error(s), "applied loads") != NULL,
              "causes: a 1e12 N load's blow-up is blamed on the loads", "%.300s",
              rj_state_error(s));
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
}

/* ------------------------------------------------------------------ links passing through */

/* Two links whose hinge spring drives the second through 360 deg, where it lies over the
   first: reported once, with its time and a warning. The same links stowed folded at
   360 deg and opening to 180 deg never pass through. */
static void test_links_pass_through(void)
{
    int pass;
    for (pass = 0; pass < 2; pass++) {
        rj_link_def links[2] = { rj_default_link_def(), rj_default_link_def() };
        rj_joint_def joints[2] = { rj_default_joint_def(), rj_default_joint_def() };
        rj_model *m;
        rj_state *s;
        rj_result r;
        double t_over;
        links[0].height = links[1].height = 0.01;
        joints[0].body1 = -1;
        joints[0].body2 = 0;
        joints[1].body1 = 0;
        joints[1].body2 = 1;
        joints[1].angle0 = rj_rad(pass == 0 ? 300 : 360);
        joints[1].spring_k = 5;
        joints[1].spring_free_angle = rj_rad(pass == 0 ? 420 : 180);
        joints[1].damping = 0.05;
        m = model_of("pass through: model", links, 2, joints, 2, 0);
        if (!m || rj_state_create(m, &s, NULL) != RJ_OK)
            return;
        r = rj_run(m, s, 0.5, 0, NULL, NULL);
        t_over = rj_joint_overlap_time(m, s, 1);
        if (pass == 0)
            rjt_check(&T, r == RJ_OK && t_over > 0 && rj_state_warning_count(s) >= 1 &&
                              strstr(rj_state_warning(s), "passed through each other") != NULL &&
                              rj_joint_overlap_time(m, s, 0) < 0,
                      "pass through: a hinge turned through 360 deg is reported once",
                      "t %.4g s, %ld warnings: %s", t_over, rj_state_warning_count(s),
                      rj_state_warning(s));
        else
            rjt_check(&T, r == RJ_OK && t_over < 0 && rj_state_warning_count(s) == 0,
                      "pass through: a hinge opening from folded at 360 deg is not",
                      "t %.4g s, angle %.1f deg, %ld warnings", t_over,
                      rj_deg(rj_joint_theta_running(m, s, 1)), rj_state_warning_count(s));
        rj_state_destroy(s, NULL);
        rj_model_destroy(m, NULL);
    }
}

/* ------------------------------------------------------------------ the account table */

/* The accounts by number are rj_energy's fields, in rj run's order, and the total and the
   balance are theirs: a link swinging under gravity on a damped hinge with friction. */
static void test_account_table(void)
{
    static const char *const names[11] = { "E_kin",     "E_strain",  "E_spring",
                                          "E_gravity", "W_applied", "W_drive",
                                          "W_damping", "W_friction", "W_limit",
                                          "W_structural", "W_plastic" };
    rj_link_def link = rj_default_link_def();
    rj_joint_def joint = rj_default_joint_def();
    rj_model *m;
    rj_state *s;
    rj_energy e;
    double fields[11];
    int k, same = rj_energy_account_count() == 11;
    link.height = 0.01;
    joint.body1 = -1;
    joint.body2 = 0;
    joint.angle0 = 0;
    joint.damping = 0.01;
    joint.friction = 0.02;
    m = model_of("accounts: model", &link, 1, &joint, 1, 9.81);
    if (!m || rj_state_create(m, &s, NULL) != RJ_OK)
        return;
    rj_run(m, s, 0.2, 0, NULL, NULL);
    rj_state_energy(m, s, &e);
    fields[0] = e.kinetic;
    fields[1] = e.strain;
    fields[2] = e.spring;
    fields[3] = e.gravity;
    fields[4] = e.work_applied;
    fields[5] = e.work_drive;
    fields[6] = e.lost_damping;
    fields[7] = e.lost_friction;
    fields[8] = e.lost_limit;
    fields[9] = e.lost_structural;
    fields[10] = e.lost_plastic;
    for (k = 0; same && k < 11; k++)
        same = strcmp(rj_energy_account_name(k), names[k]) == 0 &&
               rj_energy_account(&e, k) == fields[k];
    rjt_check(&T, same && e.total == e.kinetic + e.strain + e.spring + e.gravity &&
                      e.lost_damping > 0 && e.lost_friction > 0 &&
                      fabs(e.balance) < 1e-6 * (fabs(e.gravity) + 1),
              "accounts: the table gives rj_energy's fields in rj run's order, and their sums",
              "%d accounts, damping %.3g J, friction %.3g J, balance %.3g J",
              rj_energy_account_count(), e.lost_damping, e.lost_friction, e.balance);
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
}

int main(void)
{
    test_damping_bound();
    test_counts();
    test_linear();
    test_no_usable_step();
    test_nonfinite();
    test_checkpoints();
    test_messages();
    test_limits();
    test_latch_load();
    test_many_joints();
    test_model_block();
    test_in_place_rollback();
    test_settle_at_rest();
    test_settle_on_a_limit();
    test_settle_keeps_time();
    test_damped_latch_step();
    test_pin_on_a_pinned_root();
    test_bounds_carried();
    test_blowup_causes();
    test_links_pass_through();
    test_account_table();
    return rjt_summary(&T, "test_robust");
}
