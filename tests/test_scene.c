/* test_scene.c - tests of the scene-file parser and writer (src/scene_parse.h,
   src/scene_write.h). One line per check, "PASS name: details" or "FAIL name: details",
   then "test_scene: N passed, M failed"; exit status 1 when any failed. Built by make
   (build/test_scene, build/test_scene_asan), linked with tests/rjt_impl_hooked.c.
   Run from the repository root, or pass the directory holding deploy.rjs etc.:
     build/test_scene [examples/scenes] */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <math.h>
#include <locale.h>
#include <time.h>
#include <errno.h>

/* every allocation of the library and the parser goes through here (the implementation
   is tests/rjt_impl_hooked.c): live blocks are counted, and a context can make the n-th
   allocation fail */
#include "rjt_alloc.h"
typedef struct talloc { long live, total, fail_at; } talloc;
static talloc g_alloc;
void *rjt_malloc(size_t sz, void *ctx)
{
    talloc *a = ctx ? (talloc *)ctx : &g_alloc;
    if (a->fail_at > 0 && a->total + 1 == a->fail_at) { a->total++; return NULL; }
    a->total++; a->live++;
    return malloc(sz);
}
void rjt_free(void *p, void *ctx)
{
    talloc *a = ctx ? (talloc *)ctx : &g_alloc;
    if (p) a->live--;
    free(p);
}
#include "../revjoint.h"
#include "../examples/scenes.h"

static int g_pass, g_fail;
static void check(int ok, const char *name, const char *details)
{
    printf("%s %s: %s\n", ok ? "PASS" : "FAIL", name, details);
    if (ok) g_pass++; else g_fail++;
    fflush(stdout);
}

static const char *g_dir = "examples/scenes";

/* ------------------------------------------------------------------ field-by-field */
/* first differing field into why; 1 when equal. Compares bits (-0.0 is not 0.0, a NaN
   equals the same NaN) of every field the model uses;
   fields the model ignores (per section kind, disabled limits, node1/ground_* where they do
   not apply) only when `all` is set. */
static int same_link(const rj_link_def *a, const rj_link_def *b, int all, char *why, size_t n)
{
#define RJ_T(f) if (memcmp(&a->f, &b->f, sizeof a->f)) { snprintf(why, n, "%s: %.17g vs %.17g", #f, (double)a->f, (double)b->f); return 0; }
    RJ_T(length) RJ_T(elements) RJ_T(E) RJ_T(rho) RJ_T(section) RJ_T(height) RJ_T(tip_mass) RJ_T(tip_inertia)
    RJ_T(root) RJ_T(x) RJ_T(y) RJ_T(angle) RJ_T(vx) RJ_T(vy) RJ_T(omega) RJ_T(fidelity) RJ_T(cookie)
    if (all || a->section == RJ_SECTION_RECT) { RJ_T(width) RJ_T(layers) }
    if (all || a->section == RJ_SECTION_GENERAL) { RJ_T(area) RJ_T(inertia) }
    return 1;
}
static int same_joint(const rj_joint_def *a, const rj_joint_def *b, int all, char *why, size_t n)
{
    int k;
    RJ_T(body1) RJ_T(body2) RJ_T(angle0) RJ_T(rate0) RJ_T(table_count) RJ_T(spring_k) RJ_T(spring_free_angle)
    RJ_T(has_forward) RJ_T(has_reverse) RJ_T(lock) RJ_T(method) RJ_T(release) RJ_T(penalty_k) RJ_T(restitution)
    RJ_T(damping) RJ_T(friction) RJ_T(reference) RJ_T(cookie)
    if (all || a->body1 >= 0) { RJ_T(node1) }
    if (all || a->body1 < 0) { RJ_T(ground_x) RJ_T(ground_y) RJ_T(ground_angle) }
    if (all || a->has_forward) { RJ_T(forward) }
    if (all || a->has_reverse) { RJ_T(reverse) }
    for (k = 0; k < a->table_count; k++) { RJ_T(table_angle[k]) RJ_T(table_torque[k]) }
    return 1;
}
static int same_solver(const rj_solver_def *a, const rj_solver_def *b, char *why, size_t n)
{
    RJ_T(dt) RJ_T(allow_unstable) RJ_T(energy_growth) RJ_T(energy_every) RJ_T(in_place) RJ_T(cookie)
    return 1;
#undef RJ_T
}
static int same_scene(const rj_scene_def *a, const rj_scene_def *b, int all, char *why, size_t n)
{
    int i;
    char w[200];
    if (a->link_count != b->link_count || a->joint_count != b->joint_count) { snprintf(why, n, "counts %d/%d vs %d/%d", a->link_count, a->joint_count, b->link_count, b->joint_count); return 0; }
    if (!same_solver(&a->solver, &b->solver, w, sizeof w)) { snprintf(why, n, "solver.%s", w); return 0; }
    for (i = 0; i < a->link_count; i++) if (!same_link(&a->links[i], &b->links[i], all, w, sizeof w)) { snprintf(why, n, "links[%d].%s", i, w); return 0; }
    for (i = 0; i < a->joint_count; i++) if (!same_joint(&a->joints[i], &b->joints[i], all, w, sizeof w)) { snprintf(why, n, "joints[%d].%s", i, w); return 0; }
    snprintf(why, n, "%d links, %d joints, every field equal", a->link_count, a->joint_count);
    return 1;
}

static int zeroed(const rj_scene_file *f)
{
    rj_scene_file z;
    memset(&z, 0, sizeof z);
    return memcmp(f, &z, sizeof z) == 0;
}

/* ------------------------------------------------------------------ the example files */
static int load_example(const char *name, rj_scene_file *f)
{
    char path[512];
    rj_error e;
    rj_result r;
    snprintf(path, sizeof path, "%s/%s", g_dir, name);
    r = rj_scene_load(path, f, &e);
    {
        char d[400], n[80];
        snprintf(n, sizeof n, "load %s", name);
        snprintf(d, sizeof d, "%s", r == RJ_OK ? "parsed" : e.msg);
        if (r == RJ_OK) snprintf(d, sizeof d, "%d links, %d joints", f->link_count, f->joint_count);
        check(r == RJ_OK, n, d);
    }
    return r == RJ_OK;
}

static void test_deploy(void)
{
    rj_scene_file f;
    rj_model *m = NULL;
    rj_error e;
    deploy_opts o = deploy_default_opts();
    rj_link_def links[2];
    rj_joint_def joints[2];
    rj_scene_def sc, fd;
    char why[300];
    int i;
    if (!load_example("deploy.rjs", &f)) return;
    fd = rj_scene_file_def(&f);
    /* deploy_build: Eq 31 stiffness at dt for joint 2, computed by the library */
    if (deploy_build(&o, &m, &e) != RJ_OK) { check(0, "deploy builder", e.msg); rj_scene_file_free(&f); return; }
    deploy_scene(&o, links, joints, &sc);
    for (i = 0; i < 2; i++) { links[i] = *rj_model_link_def(m, i); joints[i] = *rj_model_joint_def(m, i); }
    check(same_scene(&fd, &sc, 1, why, sizeof why), "deploy.rjs = deploy_build(deploy_default_opts) field by field", why);
    snprintf(why, sizeof why, "file %.17g, Eq 31 at %.3g s %.17g", f.joints[1].penalty_k, rj_model_dt(m), rj_joint_kmax_eq31(m, 1, rj_model_dt(m)));
    check(f.joints[1].penalty_k == rj_joint_kmax_eq31(m, 1, rj_model_dt(m)), "deploy.rjs joint 2 penalty_k is Eq 31 at 7.5 us", why);
    snprintf(why, sizeof why, "arm1 %.17g, arm2 %.17g kg/m^3", f.links[0].rho, f.links[1].rho);
    check(f.links[0].rho == 0.52334 / (1.78076e-4 * 1.006423) && f.links[1].rho == 0.42958 / (1.7748e-4 * 0.9945), "deploy.rjs densities are the link masses over A l, full precision", why);
    check(rj_scene_link_index(&f, "arm2") == 1 && rj_scene_joint_index(&f, "j2") == 1 && rj_scene_link_index(&f, "ground") == -1 && rj_scene_joint_index(&f, "nope") == -1,
          "names: rj_scene_link_index / rj_scene_joint_index", "arm2 -> 1, j2 -> 1, unknown -> -1");
    rj_model_destroy(m, NULL);
    rj_scene_file_free(&f);
    check(zeroed(&f), "rj_scene_file_free zeroes the struct", "all fields 0");
    rj_scene_file_free(&f);   /* a second free is a no-op */
}

static void test_impact(void)
{
    rj_scene_file f;
    impact_opts o = impact_default_opts();
    rj_link_def links[2];
    rj_joint_def joint;
    rj_scene_def sc, fd;
    rj_model *m;
    rj_error e;
    char why[300];
    if (!load_example("impact.rjs", &f)) return;
    fd = rj_scene_file_def(&f);
    impact_scene(&o, links, &joint, &sc);
    check(same_scene(&fd, &sc, 1, why, sizeof why), "impact.rjs = impact_scene(impact_default_opts) field by field", why);
    if (rj_model_create(&fd, &m, &e, NULL) == RJ_OK) {
        snprintf(why, sizeof why, "dt %g s, bound %g s", rj_model_dt(m), rj_model_dt_bound(m));
        check(1, "impact.rjs builds a model", why);
        rj_model_destroy(m, NULL);
    } else check(0, "impact.rjs builds a model", e.msg);
    rj_scene_file_free(&f);
}

static void test_solar(void)
{
    rj_scene_file f;
    rj_model *m;
    rj_state *s = NULL;
    rj_error e;
    rj_scene_def fd;
    rj_result r;
    rj_energy en;
    char d[400];
    int j, all = 1, o = 0;
    clock_t c0;
    if (!load_example("solar_array.rjs", &f)) return;
    fd = rj_scene_file_def(&f);
    if (rj_model_create(&fd, &m, &e, NULL) != RJ_OK) { rj_scene_file_locate(&f, &e); check(0, "solar_array.rjs builds a model", e.msg); rj_scene_file_free(&f); return; }
    rj_state_create(m, &s, NULL);
    c0 = clock();
    r = rj_run(m, s, 10.0, 0.0, NULL, NULL);
    snprintf(d, sizeof d, "%s%s%s; t = %.3f s, dt %.3g s, %ld steps, %.2f s wall", rj_result_str(r), rj_state_error(s)[0] ? " " : "", rj_state_error(s), rj_state_time(s), rj_model_dt(m), rj_state_steps(s),
             (double)(clock() - c0) / CLOCKS_PER_SEC);
    check(r == RJ_OK && rj_state_time(s) > 9.99, "solar_array.rjs runs to 10 s", d);
    for (j = 0; j < f.joint_count; j++) {
        double t = rj_joint_event_time(m, s, j);
        if (!(rj_joint_flag(m, s, j) == RJ_LOCKED && t >= 0 && t < 5.0)) all = 0;
        o += snprintf(d + o, sizeof d - (size_t)o, "%s%s %.4f s (%.2f deg)", j ? ", " : "", f.joint_names[j], t, rj_deg(rj_joint_theta_running(m, s, j)));
    }
    check(all && f.joint_count == 4, "solar_array.rjs: every hinge locks within 5 s", d);
    rj_state_energy(m, s, &en);
    snprintf(d, sizeof d, "balance %.3g J of %.4g J stored in the springs at the start", en.balance, en.balance - en.total - en.lost_damping - en.lost_friction - en.lost_limit > 0 ? 0.0 : -(en.balance - en.total - en.lost_damping - en.lost_friction - en.lost_limit));
    check(fabs(en.balance) < 1e-3, "solar_array.rjs energy accounts close", d);
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
    rj_scene_file_free(&f);
}

/* ------------------------------------------------------------------ writer round trips */
static void roundtrip(const char *name, const rj_scene_def *sc, const char *const *ln, const char *const *jn)
{
    size_t n = rj_scene_write(sc, ln, jn, NULL, 0), n2;
    char *buf = (char *)malloc(n + 1), why[300], d[400];
    rj_scene_file f;
    rj_error e;
    n2 = rj_scene_write(sc, ln, jn, buf, n + 1);
    if (n == 0 || n2 != n || strlen(buf) != n) { snprintf(d, sizeof d, "size query %lu, write %lu, strlen %lu", (unsigned long)n, (unsigned long)n2, (unsigned long)strlen(buf)); check(0, name, d); free(buf); return; }
    if (rj_scene_parse(buf, n, name, &f, &e) != RJ_OK) { check(0, name, e.msg); free(buf); return; }
    {
        rj_scene_def fd = rj_scene_file_def(&f);
        int ok = same_scene(&fd, sc, 0, why, sizeof why), k;
        for (k = 0; ln && k < f.link_count; k++) if (strcmp(ln[k], f.link_names[k])) ok = 0;
        for (k = 0; jn && k < f.joint_count; k++) if (strcmp(jn[k], f.joint_names[k])) ok = 0;
        snprintf(d, sizeof d, "%lu bytes; %s", (unsigned long)n, why);
        check(ok, name, d);
    }
    rj_scene_file_free(&f);
    free(buf);
}

static void file_roundtrip(const char *file)
{
    rj_scene_file f;
    char name[100];
    if (!load_example(file, &f)) return;
    {
        rj_scene_def fd = rj_scene_file_def(&f);
        const char *ln[RJ_SCENE_MAX_LINKS], *jn[RJ_SCENE_MAX_JOINTS];
        int k;
        for (k = 0; k < f.link_count; k++) ln[k] = f.link_names[k];
        for (k = 0; k < f.joint_count; k++) jn[k] = f.joint_names[k];
        snprintf(name, sizeof name, "round trip %s -> rj_scene_write -> parse", file);
        roundtrip(name, &fd, ln, jn);
    }
    rj_scene_file_free(&f);
}

static unsigned long g_rng = 12345;
static double urand(void) { g_rng = g_rng * 6364136223846793005UL + 1442695040888963407UL; return (double)((g_rng >> 11) & ((1UL << 53) - 1)) / 9007199254740992.0; }
static int irand(int n) { return (int)(urand() * n); }

static void test_writer(void)
{
    deploy_opts o = deploy_default_opts();
    impact_opts io = impact_default_opts();
    rj_link_def links[8];
    rj_joint_def joints[8];
    rj_scene_def sc;
    static const char *const dl[] = { "arm1", "arm2" }, *const dj[] = { "j1", "j2" };
    char small[16], d[300];
    size_t n;
    int t, bad = 0;
    deploy_scene(&o, links, joints, &sc);
    joints[1].penalty_k = 1014.8544308316433;
    roundtrip("round trip deploy_scene (C) -> rj_scene_write -> parse", &sc, dl, dj);
    impact_scene(&io, links, joints, &sc);
    roundtrip("round trip impact_scene (C) -> rj_scene_write -> parse, generated names", &sc, NULL, NULL);
    n = rj_scene_write(&sc, NULL, NULL, small, sizeof small);
    snprintf(d, sizeof d, "returns %lu, wrote \"%s\" (%lu chars) into 16 bytes", (unsigned long)n, small, (unsigned long)strlen(small));
    check(n > 100 && strlen(small) == 15, "rj_scene_write truncates like snprintf", d);
    {
        static const char *const badn[] = { "1abc", "b" }, *const dupn[] = { "x", "x" }, *const grn[] = { "ground", "b" };
        rj_scene_def z = sc;
        int r1 = (int)rj_scene_write(&sc, badn, NULL, small, sizeof small), r2 = (int)rj_scene_write(&sc, dupn, NULL, small, sizeof small), r3 = (int)rj_scene_write(&sc, grn, NULL, small, sizeof small);
        int r4, r5;
        links[0].length = HUGE_VAL;
        r4 = (int)rj_scene_write(&sc, NULL, NULL, small, sizeof small);
        links[0].length = 1.0;
        z.link_count = 0;
        r5 = (int)rj_scene_write(&z, NULL, NULL, small, sizeof small);
        snprintf(d, sizeof d, "bad name %d, duplicate %d, 'ground' %d, inf %d, no links %d; buffer \"%s\"", r1, r2, r3, r4, r5, small);
        check(!r1 && !r2 && !r3 && !r4 && !r5 && small[0] == 0, "rj_scene_write refuses what it cannot write", d);
    }
    /* random scenes: every field the model uses, angles in and out of deg-exact values */
    for (t = 0; t < 300; t++) {
        int nl = 1 + irand(5), nj = irand(nl + 1), i, k;
        size_t len;
        char *buf;
        rj_scene_file f;
        rj_error e;
        rj_scene_def fd;
        char why[300];
        sc = rj_default_scene_def();
        if (irand(2)) sc.solver.dt = urand() * 1e-4;
        if (irand(4) == 0) sc.solver.allow_unstable = 1;
        if (irand(4) == 0) sc.solver.energy_growth = 1.0 + urand() * 100;
        if (irand(4) == 0) sc.solver.energy_every = 1 + irand(1000);
        if (irand(4) == 0) sc.solver.in_place = irand(3);
        for (i = 0; i < nl; i++) {
            rj_link_def *L = &links[i];
            *L = rj_default_link_def();
            L->length = urand() * 10 + 1e-3; L->elements = 1 + irand(20); L->E = 1e9 + urand() * 1e11; L->rho = 100 + urand() * 8000;
            if (irand(2)) { L->section = RJ_SECTION_GENERAL; L->area = urand() * 1e-3 + 1e-9; L->inertia = urand() * 1e-6 + 1e-15; L->height = irand(2) ? 0.0 : urand(); }
            else { L->width = urand() + 1e-6; L->height = urand() + 1e-6; L->layers = 1 + irand(5); }
            if (irand(2)) { L->tip_mass = urand(); L->tip_inertia = irand(2) ? 0.0 : urand() * 1e-3; }
            L->root = irand(4); L->fidelity = irand(3); L->x = (urand() - 0.5) * 10; L->y = irand(2) ? 0.0 : (urand() - 0.5);
            L->angle = irand(2) ? rj_rad((double)(irand(720) - 360)) : (urand() - 0.5) * 20;
            if (irand(3) == 0) { L->vx = urand(); L->vy = -urand(); L->omega = irand(2) ? rj_rad(irand(1000)) : urand() * 50; }
        }
        for (i = 0; i < nj; i++) {
            rj_joint_def *J = &joints[i];
            *J = rj_default_joint_def();
            J->body2 = i < nl ? i : nl - 1;
            J->body1 = i == 0 || irand(3) == 0 ? -1 : irand(i);
            if (J->body1 == J->body2) J->body1 = -1;
            if (J->body1 >= 0 && irand(2)) J->node1 = irand(links[J->body1].elements + 1);
            if (J->body1 < 0 && irand(2)) { J->ground_x = urand(); J->ground_y = -urand(); J->ground_angle = irand(2) ? rj_rad(irand(360)) : urand(); }
            J->angle0 = irand(2) ? rj_rad((double)irand(721)) : (urand() - 0.3) * 30;
            if (irand(3) == 0) J->rate0 = irand(2) ? -rj_rad(irand(1000)) : (urand() - 0.5) * 100;
            if (irand(2)) {
                J->table_count = 2 + irand(RJ_TABLE_MAX - 1);
                for (k = 0; k < J->table_count; k++) {
                    J->table_angle[k] = (double)k / (J->table_count - 1) * 6.283185307179586 * (irand(2) ? 1.0 : urand());
                    if (k && J->table_angle[k] < J->table_angle[k - 1]) J->table_angle[k] = J->table_angle[k - 1];
                    if (irand(2)) J->table_angle[k] = rj_rad(floor(rj_deg(J->table_angle[k])));
                    if (k && J->table_angle[k] < J->table_angle[k - 1]) J->table_angle[k] = J->table_angle[k - 1];
                    J->table_torque[k] = (urand() - 0.5) * 1e3;
                }
            }
            if (irand(2)) { J->spring_k = urand(); J->spring_free_angle = (urand() - 0.5) * 20; }
            if (irand(2)) { J->has_forward = 1; J->forward = irand(2) ? rj_rad(irand(360)) : urand() * 6.28; }
            if (irand(2)) { J->has_reverse = 1; J->reverse = irand(2) ? rj_rad(irand(360)) : urand() * 6.28; }
            J->lock = irand(2); J->method = irand(5); J->release = irand(2); J->reference = irand(2);
            if (irand(2)) J->penalty_k = urand() * 1e6;
            if (irand(2)) J->restitution = urand();
            if (irand(2)) J->damping = urand();
            if (irand(2)) J->friction = urand();
        }
        sc.links = links; sc.link_count = nl; sc.joints = joints; sc.joint_count = nj;
        len = rj_scene_write(&sc, NULL, NULL, NULL, 0);
        buf = (char *)malloc(len + 1);
        rj_scene_write(&sc, NULL, NULL, buf, len + 1);
        /* the model may reject a random scene (e.g. a root that is not free on a body2,
           penalty without stiffness); then the parser reports that, else it must match */
        if (rj_scene_parse(buf, len, "random.rjs", &f, &e) != RJ_OK) {
            rj_error me;
            rj_model *rm = NULL;
            const rj_result mr = rj_model_create(&sc, &rm, &me, NULL);
            if (mr == RJ_OK || e.code != me.code || strstr(e.msg, me.msg) == NULL) {
                if (!bad++) { printf("  random scene %d:\n%s\n  error: %s\n  model: %s\n", t, buf, e.msg, me.msg); }
            }
            if (mr == RJ_OK) rj_model_destroy(rm, NULL);
        } else {
            fd = rj_scene_file_def(&f);
            if (!same_scene(&fd, &sc, 0, why, sizeof why)) { if (!bad++) printf("  random scene %d: %s\n%s\n", t, why, buf); }
            rj_scene_file_free(&f);
        }
        free(buf);
    }
    snprintf(d, sizeof d, "300 random scenes (angles deg-exact and not, tables, every key); %d mismatches", bad);
    check(bad == 0, "round trip random scenes bit for bit (units: deg/rad, deg/s/rad/s)", d);
}

/* ------------------------------------------------------------------ what the model accepts */
static int g_stepped;   /* runs whose last step succeeded */

/* builds both scenes and takes `steps` steps: 1 when both build alike and every node's
   position, rotation and velocity is the same bits after each step */
static int same_run(const rj_scene_def *a, const rj_scene_def *b, int steps, char *why, size_t n)
{
    rj_model *ma = NULL, *mb = NULL;
    rj_state *sa = NULL, *sb = NULL;
    rj_error ea, eb;
    rj_result ra = rj_model_create(a, &ma, &ea, NULL), rb = rj_model_create(b, &mb, &eb, NULL);
    int ok = ra == rb, t, l, k;
    snprintf(why, n, "models: %s / %s", rj_result_str(ra), rj_result_str(rb));
    if (ok && ra == RJ_OK) {
        rj_state_create(ma, &sa, NULL);
        rj_state_create(mb, &sb, NULL);
        for (t = 0; ok && t < steps; t++) {
            rj_result r1 = rj_step(ma, sa), r2 = rj_step(mb, sb);
            ok = r1 == r2;
            if (r1 == RJ_OK && t == steps - 1) g_stepped++;
            for (l = 0; ok && l < a->link_count; l++) for (k = 0; ok && k < rj_link_node_count(ma, l); k++) {
                double p[2], q[2], v[2], w[2], r1 = rj_node_rotation(ma, sa, l, k), r2 = rj_node_rotation(mb, sb, l, k);
                rj_node_position(ma, sa, l, k, p); rj_node_position(mb, sb, l, k, q);
                rj_node_velocity(ma, sa, l, k, v); rj_node_velocity(mb, sb, l, k, w);
                ok = !memcmp(p, q, sizeof p) && !memcmp(v, w, sizeof v) && !memcmp(&r1, &r2, sizeof r1);
                if (!ok) snprintf(why, n, "step %d, link %d node %d: x %.17g vs %.17g", t + 1, l, k, p[0], q[0]);
            }
        }
        if (ok) snprintf(why, n, "%d steps, every node the same bits", steps);
        rj_state_destroy(sa, NULL); rj_state_destroy(sb, NULL);
    }
    if (ma) rj_model_destroy(ma, NULL);
    if (mb) rj_model_destroy(mb, NULL);
    return ok;
}

/* write -> parse -> same fields (bits) -> same steps; 1 when all hold, why says what */
static int model_roundtrip(const rj_scene_def *sc, char *why, size_t n, char **text)
{
    size_t len = rj_scene_write(sc, NULL, NULL, NULL, 0);
    char *buf = (char *)malloc(len + 1), w[300];
    rj_scene_file f;
    rj_error e;
    int ok;
    *text = buf;
    buf[0] = 0;
    if (len == 0) { snprintf(why, n, "rj_scene_write returned 0"); return 0; }
    rj_scene_write(sc, NULL, NULL, buf, len + 1);
    if (rj_scene_parse(buf, len, "w.rjs", &f, &e) != RJ_OK) { snprintf(why, n, "parse: %s", e.msg); return 0; }
    {
        rj_scene_def fd = rj_scene_file_def(&f);
        ok = same_scene(&fd, sc, 0, w, sizeof w) && same_run(sc, &fd, 20, w, sizeof w);
        snprintf(why, n, "%s", w);
    }
    rj_scene_file_free(&f);
    return ok;
}

static void check_model_roundtrip(const char *name, const rj_scene_def *sc)
{
    char why[400], *text = NULL;
    rj_error e;
    int ok;
    if (rj_model_size(sc, &e) == 0) { check(0, name, e.msg); return; }
    ok = model_roundtrip(sc, why, sizeof why, &text);
    if (!ok) printf("%s", text);
    check(ok, name, why);
    free(text);
}

/* a pinned link with a joint whose table falls (a fall starts a new run, Eq 4) */
static void test_writer_falling_table(void)
{
    rj_link_def L[2];
    rj_joint_def J = rj_default_joint_def();
    rj_scene_def sc = rj_default_scene_def();
    static const double ang[5] = { 0, 180, 90, 270, 45 }, tq[5] = { 0.5, 2, -1, 3, 0.25 };
    int k;
    L[0] = rj_default_link_def(); L[1] = rj_default_link_def();
    L[0].root = RJ_ROOT_CLAMPED; L[0].elements = 4; L[1].elements = 4;
    J.body1 = 0; J.body2 = 1; J.angle0 = rj_rad(170); J.rate0 = 5;
    J.table_count = 5;
    for (k = 0; k < 5; k++) { J.table_angle[k] = rj_rad(ang[k]); J.table_torque[k] = tq[k]; }
    sc.links = L; sc.link_count = 2; sc.joints = &J; sc.joint_count = 1;
    check_model_roundtrip("round trip: a table whose angles fall (Eq 4) writes, parses and steps the same bits", &sc);
    {
        rj_scene_file f;
        rj_error e;
        static const char *t = "link a\nlink b\njoint j\n  body1 = a  body2 = b\n  table = 90 deg 1, 45 deg 2\n";
        rj_result r = rj_scene_parse(t, strlen(t), "t.rjs", &f, &e);
        check(r == RJ_OK && f.joints[0].table_count == 2 && f.joints[0].table_angle[1] == rj_rad(45), "a table whose angles fall parses, as rj_model_create takes it",
              r == RJ_OK ? "table = 90 deg 1, 45 deg 2" : e.msg);
        rj_scene_file_free(&f);
    }
}

/* NaN (and nonsense) in fields rj__validate does not look at: the writer leaves them out */
static void test_writer_ignored(void)
{
    rj_link_def L[3];
    rj_joint_def J[2];
    rj_scene_def sc = rj_default_scene_def();
    double nan = strtod("nan", NULL);
    int k;
    for (k = 0; k < 3; k++) { L[k] = rj_default_link_def(); L[k].elements = 3; }
    L[0].section = RJ_SECTION_GENERAL; L[0].area = 1e-4; L[0].inertia = 1e-9; L[0].width = nan; L[0].layers = -7;
    L[1].area = nan; L[1].inertia = nan;                                       /* rectangular */
    L[2].section = RJ_SECTION_GENERAL; L[2].area = 2e-4; L[2].inertia = 3e-9; L[2].height = 0; L[2].width = -1;
    J[0] = rj_default_joint_def(); J[1] = rj_default_joint_def();
    J[0].body1 = -1; J[0].body2 = 1; J[0].node1 = 12345;                        /* node1 of a ground joint */
    J[0].forward = 1.0; J[0].reverse = 2.0;                                    /* disabled limits */
    J[0].table_count = 2; J[0].table_angle[1] = 1.0; J[0].table_torque[0] = 0.1;
    for (k = 2; k < RJ_TABLE_MAX; k++) { J[0].table_angle[k] = nan; J[0].table_torque[k] = nan; }
    J[1].body1 = 1; J[1].body2 = 2; J[1].ground_x = 7; J[1].ground_angle = 1;   /* ground_* of a link-to-link joint */
    sc.links = L; sc.link_count = 3; sc.joints = J; sc.joint_count = 2;
    check_model_roundtrip("round trip: NaN in fields the model ignores (width/layers of a general section, area/inertia of a rectangle, ...)", &sc);
}

/* -0.0 in every field that takes it reads back as -0.0 (it reaches the node positions) */
static void test_writer_negative_zero(void)
{
    rj_link_def L[2];
    rj_joint_def J = rj_default_joint_def();
    rj_scene_def sc = rj_default_scene_def();
    double z = -0.0;
    L[0] = rj_default_link_def(); L[1] = rj_default_link_def();
    L[0].elements = 2; L[1].elements = 2;
    L[0].x = z; L[0].y = z; L[0].angle = z; L[0].vx = z; L[0].vy = z; L[0].omega = z; L[0].tip_mass = z; L[0].tip_inertia = z;
    J.body1 = -1; J.body2 = 1; J.ground_x = z; J.ground_y = z; J.ground_angle = z; J.rate0 = z; J.spring_k = z;
    J.penalty_k = z; J.restitution = z; J.damping = z; J.friction = z;
    J.table_count = 2; J.table_angle[0] = z; J.table_torque[0] = z; J.table_angle[1] = 1; J.table_torque[1] = z;
    sc.solver.dt = z;
    sc.links = L; sc.link_count = 2; sc.joints = &J; sc.joint_count = 1;
    check_model_roundtrip("round trip: -0.0 reads back as -0.0, bit for bit", &sc);
}

/* a random number, sometimes -0.0 */
static double rz(double v) { return irand(8) == 0 ? -0.0 : v; }

static void rand_link(rj_link_def *L)
{
    double nan = strtod("nan", NULL);
    *L = rj_default_link_def();
    L->length = urand() * 2 + 0.1; L->elements = 1 + irand(8); L->E = 1e9 + urand() * 1e11; L->rho = 100 + urand() * 8000;
    if (irand(2)) {
        L->section = RJ_SECTION_GENERAL; L->area = urand() * 1e-3 + 1e-6; L->inertia = urand() * 1e-7 + 1e-10; L->height = rz(urand() * 0.01);
        if (irand(2)) { L->width = nan; L->layers = irand(3) - 1; }
    } else {
        L->width = urand() * 0.1 + 1e-3; L->height = urand() * 0.01 + 1e-3; L->layers = 1 + irand(3);
        if (irand(2)) { L->area = nan; L->inertia = -1; }
    }
    if (irand(2)) { L->tip_mass = rz(urand()); L->tip_inertia = rz(irand(2) ? 0.0 : urand() * 1e-3); }
    L->fidelity = irand(4) ? RJ_LINK_FLEXIBLE : irand(3);
    L->x = rz((urand() - 0.5) * 10); L->y = rz(urand() - 0.5); L->angle = irand(2) ? rj_rad((double)(irand(720) - 360)) : rz(urand() * 6);
    if (irand(3) == 0) { L->vx = rz(urand()); L->vy = rz(-urand()); L->omega = irand(2) ? rj_rad(irand(100)) : rz(urand()); }
}

/* joint i hangs link body2 from ground or from an earlier link */
static void rand_joint(rj_joint_def *J, int body2, const rj_link_def *links)
{
    double nan = strtod("nan", NULL);
    int k;
    *J = rj_default_joint_def();
    J->body2 = body2;
    J->body1 = irand(3) == 0 ? -1 : irand(body2 + 1) - 1;
    if (J->body1 >= 0 && irand(2)) J->node1 = irand(links[J->body1].elements + 1);
    if (J->body1 < 0 && irand(2)) J->node1 = 1000 + irand(1000);        /* ignored */
    if (irand(2)) { J->ground_x = rz(urand()); J->ground_y = rz(-urand()); J->ground_angle = irand(2) ? rj_rad(irand(360)) : rz(urand()); }
    J->angle0 = irand(2) ? rj_rad((double)irand(361)) : urand() * 6.28;
    if (irand(3) == 0) J->rate0 = irand(2) ? -rj_rad(irand(100)) : rz((urand() - 0.5) * 10);
    if (irand(2)) {   /* angles in any order: falls start new runs */
        J->table_count = 2 + irand(RJ_TABLE_MAX - 1);
        for (k = 0; k < J->table_count; k++) {
            J->table_angle[k] = irand(2) ? rj_rad(irand(361)) : rz(urand() * 6.283185307179586);
            J->table_torque[k] = rz((urand() - 0.5) * 10);
        }
        for (; k < RJ_TABLE_MAX; k++) J->table_angle[k] = J->table_torque[k] = nan;
    }
    if (irand(2)) { J->spring_k = rz(urand()); J->spring_free_angle = (urand() - 0.5) * 20; }
    J->has_forward = irand(2); J->forward = irand(2) ? rj_rad(irand(360)) : urand() * 6.28;
    J->has_reverse = irand(2); J->reverse = irand(2) ? rj_rad(irand(360)) : urand() * 6.28;
    J->lock = irand(2); J->method = irand(5); J->release = irand(2); J->reference = irand(2);
    J->penalty_k = J->method == RJ_METHOD_PENALTY || irand(2) ? 1e2 + urand() * 1e3 : rz(0);
    if (irand(2)) J->restitution = rz(urand());
    if (irand(2)) J->damping = rz(urand() * 0.01);
    if (irand(2)) J->friction = rz(urand() * 0.01);
}

/* random scenes that rj_model_create accepts: write, parse, the same fields, the same steps */
static void test_writer_random_models(void)
{
    rj_link_def links[5];
    rj_joint_def joints[5];
    int t, tried = 0, bad = 0, i, s0 = g_stepped;
    for (t = 0; t < 300; tried++) {
        rj_scene_def sc = rj_default_scene_def();
        int nl = 1 + irand(5), nj = irand(nl);
        rj_error e;
        char why[400], *text = NULL;
        if (tried > 100000) break;
        if (irand(4) == 0) sc.solver.dt = rz(0);
        if (irand(4) == 0) sc.solver.energy_growth = 1.0 + urand() * 100;
        if (irand(4) == 0) sc.solver.energy_every = 1 + irand(20);
        if (irand(4) == 0) sc.solver.in_place = irand(3);
        for (i = 0; i < nl; i++) rand_link(&links[i]);
        for (i = 0; i < nj; i++) rand_joint(&joints[i], nl - nj + i, links);
        for (i = 0; i < nl - nj; i++) links[i].root = irand(4);
        sc.links = links; sc.link_count = nl; sc.joints = joints; sc.joint_count = nj;
        {   /* what the model accepts: rj_model_create (rj_model_size leaves the joint graph to it) */
            rj_model *m = NULL;
            if (rj_model_create(&sc, &m, &e, NULL) != RJ_OK) continue;
            rj_model_destroy(m, NULL);
        }
        t++;
        if (!model_roundtrip(&sc, why, sizeof why, &text) && !bad++) printf("  random scene %d: %s\n%s", t, why, text);
        free(text);
    }
    {
        char d[200];
        snprintf(d, sizeof d, "%d scenes rj_model_create accepts (of %d drawn), %d of them step 20 times without error; %d differ", t, tried, g_stepped - s0, bad);
        check(t == 300 && bad == 0, "round trip random scenes the model accepts: write, parse, same fields and 20 steps bit for bit", d);
    }
}

/* ------------------------------------------------------------------ parsing details */
static rj_result parse_str(const char *text, rj_scene_file *f, rj_error *e)
{
    return rj_scene_parse(text, strlen(text), "t.rjs", f, e);
}

static void test_units(void)
{
    static const char *text =
        "link a\n"
        "  angle = 90 deg  omega = 573 deg/s  x = 1.5\n"
        "link b\n"
        "link c\n"
        "joint j\n"
        "  body1 = ground  body2 = a  ground_angle = 90deg\n"
        "  angle0 = 1.5707963267948966 rad  rate0 = -10 rad/s\n"
        "  spring = 2 -30 deg  forward = 1.5  reverse = 0 deg\n"
        "joint k\n"
        "  body1 = a  body2 = b  angle0 = 1.5  rate0 = 2  forward = 359.5deg\n"
        "joint l\n"
        "  body1 = a  body2 = c  angle0 = 90 rad  rate0 = 10deg/s  forward = 6.2831 rad\n";
    rj_scene_file f;
    rj_error e;
    char d[300];
    if (parse_str(text, &f, &e) != RJ_OK) { check(0, "units", e.msg); return; }
    snprintf(d, sizeof d, "angle %.17g omega %.17g ground_angle %.17g angle0 %.17g rate0 %.17g free %.17g", f.links[0].angle, f.links[0].omega,
             f.joints[0].ground_angle, f.joints[0].angle0, f.joints[0].rate0, f.joints[0].spring_free_angle);
    check(f.links[0].angle == rj_rad(90) && f.links[0].omega == rj_rad(573) && f.links[0].x == 1.5 && f.joints[0].ground_angle == rj_rad(90)
          && f.joints[0].angle0 == 1.5707963267948966 && f.joints[0].rate0 == -10 && f.joints[0].spring_free_angle == rj_rad(-30) && f.joints[0].spring_k == 2,
          "units: deg and deg/s convert with rj_rad, rad and rad/s are as written, glued units work", d);
    snprintf(d, sizeof d, "forward %.17g, reverse %g (has %d), angle0 %g, rate0 %g; 359.5deg -> %.17g, 90 rad -> %g, 10deg/s -> %.17g, 6.2831 rad -> %g",
             f.joints[0].forward, f.joints[0].reverse, f.joints[0].has_reverse, f.joints[1].angle0, f.joints[1].rate0, f.joints[1].forward,
             f.joints[2].angle0, f.joints[2].rate0, f.joints[2].forward);
    check(f.joints[0].forward == 1.5 && f.joints[0].reverse == 0 && f.joints[0].has_reverse && f.joints[1].angle0 == 1.5 && f.joints[1].rate0 == 2
          && f.joints[1].forward == rj_rad(359.5) && f.joints[2].angle0 == 90 && f.joints[2].rate0 == rj_rad(10) && f.joints[2].forward == 6.2831,
          "units: no unit means rad (and rad/s)", d);
    rj_scene_file_free(&f);
}

static void test_comments(void)
{
    static const char *plain =
        "solver\ndt = 1e-5\nmaterial m\nE = 2e11\nrho = 7800\nsection s\nwidth = 0.02\nheight = 0.01\nlink a\nlength = 0.5\nelements = 3\nmaterial = m\nsection = s\n"
        "link b\nlength = 0.5\nelements = 3\nmaterial = m\nsection = s\nrho = 100\njoint j1\nbody1 = ground\nbody2 = a\nangle0 = 0.5\njoint j2\nbody1 = a\nbody2 = b\n"
        "table = 0 1, 1 2, 2 3\n";
    static const char *fancy =
        "# a comment line\r\n"
        "\r\n"
        "   \t  \r\n"
        "solver   # trailing comment after a section keyword\r\n"
        "\tdt=1e-5#no spaces at all\r\n"
        "material m\r\n"
        "  E = 2e11 rho = 7800   # two keys on a line\r\n"
        "\r\n"
        "section s\r\n"
        "  width = 0.02  height = 0.01\r\n"
        "# between sections\r\n"
        "link a\r\n"
        "  length = 0.5  elements = 3  material = m  section = s\r\n"
        "link b   \r\n"
        "  length = 0.5\r\n"
        "  # a comment inside a section\r\n"
        "  elements = 3\r\n"
        "  material = m  section = s  rho = 100   # the link's own rho overrides the material\r\n"
        "joint j1\r\n"
        "  body1 = ground  body2 = a  angle0 = 0.5\r\n"
        "joint j2\r\n"
        "  body1 = a  body2 = b\r\n"
        "  table = 0 1,      # a table may continue after a ','\r\n"
        "          1 2,\r\n"
        "          2 3\r\n"
        "# last line without a newline";
    rj_scene_file a, b;
    rj_error e;
    char why[300];
    if (parse_str(plain, &a, &e) != RJ_OK) { check(0, "comments: plain scene", e.msg); return; }
    if (parse_str(fancy, &b, &e) != RJ_OK) { check(0, "comments: commented scene", e.msg); rj_scene_file_free(&a); return; }
    {
        rj_scene_def da = rj_scene_file_def(&a), db = rj_scene_file_def(&b);
        int ok = same_scene(&da, &db, 1, why, sizeof why);
        check(ok && b.links[1].rho == 100 && b.links[0].rho == 7800 && b.links[0].E == 2e11 && b.links[0].width == 0.02 && b.joints[1].table_count == 3,
              "comments, blank lines, CRLF, tabs, several keys per line, continued table: same scene", why);
    }
    rj_scene_file_free(&a);
    rj_scene_file_free(&b);
    {   /* input need not be NUL-terminated: parse a prefix of a longer buffer */
        static const char buf[] = "link a\n  length = 2\nGARBAGE THAT IS NOT PART OF THE INPUT";
        rj_result r = rj_scene_parse(buf, strlen("link a\n  length = 2\n"), "t.rjs", &a, &e);
        check(r == RJ_OK && a.links[0].length == 2, "input is (text, len): bytes past len are not read", r == RJ_OK ? "parsed the 20-byte prefix" : e.msg);
        rj_scene_file_free(&a);
        r = rj_scene_parse(buf, strlen("link a\n  length = 2"), "t.rjs", &a, &e);
        check(r == RJ_OK && a.links[0].length == 2, "input without a final newline", r == RJ_OK ? "parsed" : e.msg);
        rj_scene_file_free(&a);
    }
}

/* one error case: code, "t.rjs:L:C: " prefix, a substring of the message, the field */
static void err_case(const char *name, const char *text, size_t len, rj_result code, int line, int col, const char *sub, const char *field)
{
    rj_scene_file f;
    rj_error e;
    rj_result r;
    char pre[64], d[600];
    int ok;
    long live0 = g_alloc.live;
    memset(&f, 0x5a, sizeof f);
    r = rj_scene_parse(text, len ? len : strlen(text), "t.rjs", &f, &e);
    snprintf(pre, sizeof pre, "t.rjs:%d:%d: ", line, col);
    ok = r == code && e.code == code && strncmp(e.msg, pre, strlen(pre)) == 0 && strstr(e.msg, sub) != NULL
         && (!field || strcmp(e.field, field) == 0) && zeroed(&f) && g_alloc.live == live0;
    snprintf(d, sizeof d, "%s [field '%s', code %s]%s%s", r == RJ_OK ? "parsed without error" : e.msg, r == RJ_OK ? "" : e.field, rj_result_str(r),
             g_alloc.live != live0 ? " LEAK" : "", zeroed(&f) ? "" : " *out not zeroed");
    check(ok, name, d);
    if (r == RJ_OK) rj_scene_file_free(&f);
}
#define EP(name, text, line, col, sub, field) err_case(name, text, 0, RJ_ERR_PARSE, line, col, sub, field)
#define J2 "link a\nlink b\njoint j\n  body1 = a  body2 = b\n"

static char *line_of(const char *head, char c, int n, const char *tail)
{
    size_t h = strlen(head), t = strlen(tail);
    char *s = (char *)malloc(h + (size_t)n + t + 1);
    memcpy(s, head, h);
    memset(s + h, c, (size_t)n);
    memcpy(s + h + (size_t)n, tail, t + 1);
    return s;
}

static char *repeat(const char *head, const char *fmt, int n, const char *tail)
{
    size_t cap = strlen(head) + strlen(tail) + (size_t)n * (strlen(fmt) + 16) + 1, o;
    char *s = (char *)malloc(cap);
    int i;
    o = (size_t)sprintf(s, "%s", head);
    for (i = 0; i < n; i++) o += (size_t)sprintf(s + o, fmt, i, i);
    sprintf(s + o, "%s", tail);
    return s;
}

static void test_errors(void)
{
    char *s;
    /* structure */
    EP("error: unknown section", "link a\nfoo bar\n", 2, 1, "unknown key or section 'foo'", "");
    EP("error: unknown section at the top", "foo bar\n", 1, 1, "unknown section 'foo' (expected solver, material, section, link, joint, load, actuator or coupling)", "");
    EP("error: key outside any section", "length = 1\nlink a\n", 1, 1, "key 'length' outside any section", "");
    EP("error: line starts with '='", "link a\n = 3\n", 2, 2, "expected a key or a section keyword, found '='", "");
    EP("error: section name missing", "link\n", 1, 5, "missing name after 'link'", "link");
    EP("error: invalid name", "link 1abc\n", 1, 6, "invalid name '1abc' after 'link'", "link");
    EP("error: name too long (32 characters)", "link abcdefghijabcdefghijabcdefghijab\n", 1, 6, "invalid name 'abcdefghijabcdefghijabcdefghijab'", "link");
    EP("error: trailing garbage after a section name", "link a b\n", 1, 8, "unexpected 'b' after the name of link", "");
    EP("error: solver takes no name", "solver fast\nlink a\n", 1, 8, "unexpected 'fast' after 'solver'", "");
    EP("error: duplicate solver", "solver\nlink a\nsolver\n", 3, 1, "duplicate solver section (first on line 1)", "solver");
    EP("error: duplicate link name", "link a\nlink b\nlink a\n", 3, 6, "duplicate link name 'a' (first defined on line 1)", "link");
    EP("error: duplicate joint name", J2 "joint j\n", 5, 7, "duplicate joint name 'j' (first defined on line 3)", "joint");
    EP("error: duplicate material name", "material m\nmaterial m\n", 2, 10, "duplicate material name 'm'", "material");
    EP("error: duplicate section name", "section s\nsection s\n", 2, 9, "duplicate section name 's'", "section");
    EP("error: a link named ground", "link ground\n", 1, 6, "a link cannot be named 'ground'", "link");
    EP("error: no links", "# nothing but a comment\n\n", 2, 1, "the scene has no links", "link_count");
    EP("error: empty input", "", 1, 1, "the scene has no links", "link_count");
    /* keys and values */
    EP("error: unknown key", "link arm1\n  length = 1\n  lenght = 1.1\n", 3, 3, "unknown key 'lenght' in link 'arm1'; did you mean 'length'?", "lenght");
    EP("error: key of another section", "material m\n  length = 1\n", 2, 3, "unknown key 'length' in material 'm'", "length");
    EP("error: duplicate key", "link a\n  length = 1\n  length = 2\n", 3, 3, "duplicate key 'length' in link 'a' (first set on line 2)", "length");
    EP("error: duplicate key on one line", "link a\n  x = 1  x = 2\n", 2, 10, "duplicate key 'x' in link 'a'", "x");
    EP("error: missing value", "link a\n  length =\n", 2, 11, "missing value for 'length' in link 'a'", "length");
    EP("error: missing value before the next key", "link a\n  length = elements = 3\n", 2, 11, "missing value for 'length'", "length");
    EP("error: missing '='", "link a\n  length 1\n", 2, 9, "missing '=' after 'length' in link 'a'", "length");
    EP("error: trailing garbage after a value", "link a\n  length = 1 m\n", 2, 14, "unexpected 'm' after the value of 'length' in link 'a'", "length");
    EP("error: trailing ',' after a value", "link a\n  length = 1,\n", 2, 13, "unexpected ',' after the value of 'length'", "length");
    EP("error: malformed number", "link a\n  length = 1.2.3\n", 2, 12, "malformed number '1.2.3' for 'length' in link 'a'", "length");
    EP("error: hex is not a number here", "link a\n  length = 0x10\n", 2, 12, "malformed number '0x10'", "length");
    EP("error: exponent without digits", "link a\n  E = 1e\n", 2, 7, "malformed number '1e'", "E");
    EP("error: a lone sign", "link a\n  x = -\n", 2, 7, "malformed number '-'", "x");
    EP("error: not a number", "link a\n  rho = heavy\n", 2, 9, "malformed number 'heavy'", "rho");
    EP("error: NaN", "link a\n  length = nan\n", 2, 12, "not a finite number: 'nan'", "length");
    EP("error: inf", "link a\n  E = -inf\n", 2, 7, "not a finite number: '-inf'", "E");
    EP("error: Infinity", "link a\n  x = Infinity\n", 2, 7, "not a finite number: 'Infinity'", "x");
    EP("error: number overflows", "link a\n  E = 1e999\n", 2, 7, "number out of range: '1e999'", "E");
    EP("error: angle overflows", "link a\n  angle = 1e400 deg\n", 2, 11, "number out of range: '1e400'", "angle");
    EP("error: integer expected", "link a\n  elements = 2.5\n", 2, 14, "expected an integer, found '2.5'", "elements");
    EP("error: integer too large", "link a\n  elements = 99999999999\n", 2, 14, "elements = 99999999999 is out of range in link 'a': must be 1..1000000", "elements");
    EP("error: zero elements", "link a\n  elements = 0\n", 2, 14, "elements = 0 is out of range in link 'a': must be 1..1000000", "elements");
    EP("error: negative length", "link a\n  length = -1\n", 2, 12, "length = -1 is out of range in link 'a': must be in (0, 1e6] m", "length");
    EP("error: zero E", "material m\n  E = 0\n", 2, 7, "E = 0 is out of range in material 'm': must be in (0, 1e30] Pa", "E");
    EP("error: zero layers", "section s\n  layers = 0\n", 2, 12, "layers = 0 is out of range in section 's'", "layers");
    EP("error: negative tip mass", "link a\n  tip_mass = -0.1\n", 2, 14, "tip_mass = -0.1 is out of range", "tip_mass");
    EP("error: unknown root", "link a\n  root = welded\n", 2, 10, "unknown value 'welded' for 'root' in link 'a' (expected free, pinned, clamped or fixed)", "root");
    EP("error: unknown fidelity", "link a\n  fidelity = floppy\n", 2, 14, "unknown value 'floppy' for 'fidelity' in link 'a' (expected flexible, rigid, inextensible or pieces)", "fidelity");
    EP("error: fidelity is a link key, not a material key", "material m\n  fidelity = rigid\n", 2, 3, "unknown key 'fidelity' in material 'm'", "fidelity");
    EP("error: dt above 1 s", "solver\n  dt = 2\nlink a\n", 2, 8, "dt = 2 is out of range in solver: must be 0 (automatic) or a step in (0, 1] s", "dt");
    EP("error: energy_growth 1", "solver\n  energy_growth = 1\nlink a\n", 2, 19, "energy_growth = 1 is out of range in solver: must be > 1", "energy_growth");
    EP("error: energy_every 0", "solver\n  energy_every = 0\nlink a\n", 2, 18, "energy_every = 0 is out of range in solver", "energy_every");
    EP("error: energy_every not an integer", "solver\n  energy_every = 2.5\nlink a\n", 2, 18, "energy_every", "energy_every");
    EP("error: in_place sideways", "solver\n  in_place = sideways\nlink a\n", 2, 14, "unknown value 'sideways' for 'in_place' in solver (expected auto, on or off)", "in_place");
    EP("error: bad boolean", "solver\n  allow_unstable = maybe\nlink a\n", 2, 20, "unknown value 'maybe' for 'allow_unstable' in solver (expected no, yes, false or true)", "allow_unstable");
    EP("error: limit at 360 deg", J2 "  forward = 360 deg\n", 5, 13, "forward = 360 deg is out of range in joint 'j': a limit must be in [0, 2 pi) rad, [0, 360) deg, or none", "forward");
    EP("error: negative limit", J2 "  reverse = -1deg\n", 5, 13, "reverse = -1deg is out of range", "reverse");
    EP("error: limit of 2 pi rad", J2 "  forward = 6.283185307179586\n", 5, 13, "out of range", "forward");
    EP("error: restitution above 1", J2 "  restitution = 1.5\n", 5, 17, "restitution = 1.5 is out of range in joint 'j': must be in [0, 1]", "restitution");
    EP("error: negative friction", J2 "  friction = -0.1\n", 5, 14, "friction = -0.1 is out of range", "friction");
    EP("error: negative damping", J2 "  damping = -1\n", 5, 13, "damping = -1 is out of range", "damping");
    EP("error: negative penalty_k", J2 "  penalty_k = -5\n", 5, 15, "penalty_k = -5 is out of range", "penalty_k");
    EP("error: angle0 too large", J2 "  angle0 = 2e6\n", 5, 12, "angle0 = 2e6 is out of range", "angle0");
    EP("error: unknown unit", J2 "  forward = 90 degrees\n", 5, 16, "unknown unit 'degrees' for 'forward' in joint 'j' (deg or rad)", "forward");
    EP("error: rate with an angle unit", J2 "  rate0 = 10 deg\n", 5, 14, "unknown unit 'deg' for 'rate0' in joint 'j' (deg/s or rad/s)", "rate0");
    EP("error: unknown method", J2 "  method = foo\n", 5, 12, "unknown value 'foo' for 'method' in joint 'j' (expected penalty, adaptive, momentum, forced or energy)", "method");
    EP("error: unknown release", J2 "  release = rc14\n", 5, 13, "unknown value 'rc14'", "release");
    EP("error: unknown reference", J2 "  reference = normal\n", 5, 15, "unknown value 'normal'", "reference");
    EP("error: spring without free angle", J2 "  spring = 1\n", 5, 13, "missing free angle after the stiffness in joint 'j' (spring = k angle)", "spring");
    EP("error: negative spring", J2 "  spring = -1 90 deg\n", 5, 12, "spring = -1 is out of range", "spring");
    EP("error: table with one point", J2 "  table = 0 deg 1\n", 5, 11, "a table needs at least 2 points", "table");
    EP("error: table angle above 360 deg", J2 "  table = 0 deg 1, 400 deg 2\n", 5, 20, "table = 400 deg is out of range in joint 'j': table angles must be in [0, 360] deg", "table");
    EP("error: table without torque", J2 "  table = 0 deg 1, 90 deg\n", 5, 26, "missing torque after the table angle", "table");
    EP("error: table pairs need ','", J2 "  table = 0 deg 1 90 deg 2\n", 5, 19, "expected ',' or the end of the table, found '90'", "table");
    EP("error: table ends with ','", J2 "  table = 0 deg 1, 90 deg 2,\n", 5, 28, "table ends with ','", "table");
    EP("error: error on a continuation line", J2 "  table = 0 deg 1,\n     400 deg 2\n", 6, 6, "table = 400 deg is out of range", "table");
    s = repeat(J2 "  table = ", "%d deg %d, ", 32, "359 deg 0\n");   /* the 33rd point starts at column 1 + strstr offset */
    EP("error: table with 33 points", s, 5, (int)(strstr(s, "359 deg") - strstr(s, "  table")) + 1, "table has more than 32 points in joint 'j'", "table");
    free(s);
    /* references */
    EP("error: unknown material", "link a\n  material = steel\n", 2, 14, "unknown material 'steel' in link 'a' (define it above the link)", "material");
    EP("error: unknown section reference", "link a\n  section = tube\n", 2, 13, "unknown section 'tube' in link 'a'", "section");
    EP("error: material defined after its link", "link a\n  material = m\nmaterial m\n", 2, 14, "unknown material 'm'", "material");
    EP("error: unknown link", "link a\njoint j\n  body1 = a  body2 = c\n", 3, 22, "unknown link 'c' for 'body2' in joint 'j' (define links above the joints that use them)", "body2");
    EP("error: body2 = ground", "link a\njoint j\n  body1 = a  body2 = ground\n", 3, 22, "body2 must be a link, not 'ground' in joint 'j'", "body2");
    EP("error: body1 = body2", "link a\njoint j\n  body1 = a  body2 = a\n", 3, 22, "joint 'j' connects link 'a' to itself (body1 = body2)", "body2");
    EP("error: joint without body2", "link a\njoint j\n  body1 = ground\nlink b\n", 2, 1, "joint 'j' has no body2 (a link)", "body2");
    EP("error: joint without body1", "link a\njoint j\n  body2 = a\n", 2, 1, "joint 'j' has no body1 (ground or a link)", "body1");
    EP("error: node1 out of range", "link a\n  elements = 2\nlink b\njoint j\n  body1 = a  body2 = b  node1 = 3\n", 5, 33, "node1 = 3 is out of range in joint 'j': link 'a' has nodes 0..2", "node1");
    EP("error: node1 with ground", "link a\njoint j\n  body1 = ground  body2 = a  node1 = 1\n", 3, 38, "node1 applies only when body1 is a link, in joint 'j'", "node1");
    EP("error: ground_x with a link body1", J2 "  ground_x = 1\n", 5, 14, "ground_x applies only when body1 = ground, in joint 'j'", "ground_x");
    /* sections */
    EP("error: general section without inertia", "section s\n  area = 1e-4\nlink a\n", 2, 10, "section 's' sets area but not inertia", "area");
    EP("error: width with area/inertia", "link a\n  area = 1e-4  inertia = 1e-8  width = 0.1\n", 2, 40, "link 'a' mixes width with area/inertia", "width");
    EP("error: link area over a rectangular section", "section s\n  width = 0.1  height = 0.01\nlink a\n  section = s  area = 1e-4  inertia = 1e-9\n", 2, 11,
       "link 'a' mixes width with area/inertia", "width");
    EP("error: rectangular section with height 0", "link a\n  height = 0\n", 2, 12, "link 'a' has height = 0: a rectangular section needs height > 0", "height");
    /* limits */
    s = repeat("", "link l%d\n", 257, "");
    EP("error: too many links", s, 257, 1, "too many link sections (at most 256)", "link");
    free(s);
    s = repeat("link a\n", "joint j%d\n  body1 = ground  body2 = a\n", 257, "");
    EP("error: too many joints", s, 514, 1, "too many joint sections (at most 256)", "joint");
    free(s);
    s = repeat("", "material m%d\n", 65, "");
    EP("error: too many materials", s, 65, 1, "too many material sections (at most 64)", "material");
    free(s);
    s = repeat("", "section s%d\n", 65, "");
    EP("error: too many sections", s, 65, 1, "too many section sections (at most 64)", "section");
    free(s);
    s = line_of("link a\n  # ", 'x', 1100, "\n");
    EP("error: line longer than 1024", s, 2, 1025, "line is longer than 1024 characters", "");
    free(s);
    s = line_of("link a\n  # ", 'x', 1020, "\r\n");    /* 2 + 2 + 1020 = 1024 characters and CR LF: fine */
    {
        rj_scene_file f;
        rj_error e;
        rj_result r = parse_str(s, &f, &e);
        check(r == RJ_OK, "a line of exactly 1024 characters is fine", r == RJ_OK ? "parsed" : e.msg);
        rj_scene_file_free(&f);
    }
    free(s);
    /* 5 tokens on the first table line, 30 on each continuation line: token 513 is the
       28th of the 17th continuation line (file line 22), at column 1 + 9 x 5 */
    s = repeat(J2 "  table = 0 0,\n", "0 0, 0 0, 0 0, 0 0, 0 0, 0 0, 0 0, 0 0, 0 0, 0 0,\n", 30, "0 0\n");
    EP("error: statement with more than 512 tokens", s, 22, 46, "statement has more than 512 tokens", "");
    free(s);
    /* bytes */
    err_case("error: NUL byte", "link a\n  length = 1\0\n", 21, RJ_ERR_PARSE, 2, 13, "not a text scene file: byte 0x00 at byte offset 19 is a NUL", "");
    EP("error: control character", "link a\x01\n", 1, 7, "not a text scene file: byte 0x01 at byte offset 6 is a control character", "");
    EP("error: control character in a comment", "link a\n# \x1b[1mbold\n", 2, 3, "not a text scene file: byte 0x1b at byte offset 9", "");
    EP("error: control byte after a syntax error", "lnk a\nlink b\x7f\n", 2, 7, "not a text scene file: byte 0x7f at byte offset 12", "");
    err_case("error: binary file (PNG signature)", "\x89PNG\r\n\x1a\n\0\0\0\rIHDR", 16, RJ_ERR_PARSE, 2, 1, "not a text scene file: byte 0x1a at byte offset 6", "");
    {   /* no line end in the first 1100 bytes: once reported as a line over 1024 characters */
        char bin[3000];
        int k;
        for (k = 0; k < (int)sizeof bin; k++) bin[k] = (char)(k < 1100 ? 'A' + k % 26 : (k * 7 + 3) & 255);
        err_case("error: binary file without a line end in its first 1024 bytes", bin, sizeof bin, RJ_ERR_PARSE, 1, 1101,
                 "not a text scene file: byte 0x17 at byte offset 1100", "");
    }
    EP("error: carriage return inside a line", "link a\r  length = 1\n", 1, 7, "invalid character 0x0d", "");
    EP("error: non-ASCII name", "link caf\xc3\xa9\n", 1, 6, "invalid name 'caf\\xc3\\xa9'", "link");
    /* the model's own validation, located in the file */
    err_case("model error: penalty limit without stiffness (points at method)", J2 "  forward = 90 deg\n  method = penalty\n", 0, RJ_ERR_INVALID, 6, 12,
             "joints[0].penalty_k = 0 is invalid: RJ_METHOD_PENALTY with a limit needs a stiffness > 0 (joint 'j')", "joints[0].penalty_k");
    err_case("model error: equal limits", J2 "  forward = 90 deg  reverse = 90 deg\n", 0, RJ_ERR_INVALID, 5, 13, "(joint 'j')", "joints[0].forward");
    err_case("model error: body2 with a root support", "link a\nlink b\n  root = pinned\njoint j\n  body1 = a  body2 = b\n", 0, RJ_ERR_INVALID, 3, 10,
             "its root must be RJ_ROOT_FREE (link 'b')", "links[1].root");
    err_case("model error: closed loop", "link a\nlink b\njoint j1\n  body1 = a  body2 = b\njoint j2\n  body1 = b  body2 = a\n", 0, RJ_ERR_INVALID, 1, 1,
             "form a loop through link 0 that no joint holds", "links[0]");
    {   /* unstable dt passes the parser; rj_model_create refuses it; locate points at dt */
        static const char *t = "solver\n  dt = 0.01\nlink a\n  elements = 4\n";
        rj_scene_file f;
        rj_error e;
        rj_model *m;
        rj_scene_def d;
        if (parse_str(t, &f, &e) != RJ_OK) check(0, "model error: unstable dt located at the dt line", e.msg);
        else {
            rj_result r;
            d = rj_scene_file_def(&f);
            r = rj_model_create(&d, &m, &e, NULL);
            if (r == RJ_OK) rj_model_destroy(m, NULL);
            rj_scene_file_locate(&f, &e);
            check(r == RJ_ERR_UNSTABLE_DT && strncmp(e.msg, "t.rjs:2:8: solver.dt = 0.01 s is above the stability bound", 58) == 0,
                  "model error: unstable dt located at the dt line (rj_scene_file_locate)", e.msg);
            rj_scene_file_free(&f);
        }
    }
}

/* "did you mean" for a name within a few edits of one valid there, and none otherwise */
static void test_suggestions(void)
{
    static const char *const none[][2] = {
        { "unknown section far from every keyword", "foo bar\n" },
        { "unknown key far from every key", "link a\n  colour = 1\n" },
        { "a key of another kind of section", "material m\n  length = 1\n" },
        { "a tie (arm3: arm1 and arm2 are both 1 edit away)", "link arm1\nlink arm2\njoint j\n  body1 = ground  body2 = arm3\n" },
        { "a short key 2 edits away (vz)", "link a\n  vz = 1\n" },
    };
    rj_scene_file f;
    rj_error e;
    size_t k;
    EP("did you mean: swapped letters in a key", "link arm1\n  lenght = 1\n", 2, 3, "unknown key 'lenght' in link 'arm1'; did you mean 'length'?", "lenght");
    EP("did you mean: a key in the wrong case", "material m\n  e = 7e10\n", 2, 3, "unknown key 'e' in material 'm'; did you mean 'E'?", "e");
    EP("did you mean: a dropped letter in a solver key", "solver\n  energy_evry = 4\nlink a\n", 2, 3, "; did you mean 'energy_every'?", "energy_evry");
    EP("did you mean: a section keyword", "lnk a\n", 1, 1, "unknown section 'lnk' (expected solver, material, section, link, joint, load, actuator or coupling); did you mean 'link'?", "");
    EP("did you mean: a section keyword inside a section", "link a\njiont j\n", 2, 1, "unknown key or section 'jiont' (a key needs '= value'; sections are solver, material, section, link, joint, load, actuator, coupling); did you mean 'joint'?", "");
    EP("did you mean: a key without '=' and misspelt", "link a\n  lenth 1\n", 2, 3, "unknown key or section 'lenth' (a key needs '= value'; sections are solver, material, section, link, joint, load, actuator, coupling); did you mean 'length'?", "");
    EP("did you mean: a method", J2 "  method = adaptiv\n", 5, 12, "unknown value 'adaptiv' for 'method' in joint 'j' (expected penalty, adaptive, momentum, forced or energy); did you mean 'adaptive'?", "method");
    EP("did you mean: a boolean", J2 "  lock = Yes\n", 5, 10, "; did you mean 'yes'?", "lock");
    EP("did you mean: a root support", "link a\n  root = clampd\n", 2, 10, "; did you mean 'clamped'?", "root");
    EP("did you mean: a link name", "link arm1\nlink arm2\njoint j\n  body1 = ground  body2 = amr2\n", 4, 27, "unknown link 'amr2' for 'body2' in joint 'j' (define links above the joints that use them); did you mean 'arm2'?", "body2");
    EP("did you mean: a material name", "material steel\nlink a\n  material = stel\n", 3, 14, "unknown material 'stel' in link 'a' (define it above the link); did you mean 'steel'?", "material");
    for (k = 0; k < sizeof none / sizeof none[0]; k++) {
        char n[120];
        rj_result r = parse_str(none[k][1], &f, &e);
        snprintf(n, sizeof n, "did you mean: nothing suggested for %s", none[k][0]);
        check(r == RJ_ERR_PARSE && strstr(e.msg, "did you mean") == NULL, n, r == RJ_OK ? "parsed" : e.msg);
        if (r == RJ_OK) rj_scene_file_free(&f);
    }
}

/* a unit word after a number, or glued to it: numbers are SI without one */
static void test_unit_words(void)
{
#define SI ": quantities are plain numbers in SI units, without a unit word"
    EP("unit word: length = 1 m", "link a\n  length = 1 m\n", 2, 14, "unexpected 'm' after the value of 'length' in link 'a'" SI " (length is in m already: write 1)", "length");
    EP("unit word: length = 1mm", "link a\n  length = 1mm\n", 2, 12, "malformed number '1mm' for 'length' in link 'a'" SI " (length is in m: write 1e-3 for 1 mm)", "length");
    EP("unit word: E = 70 GPa", "material m\n  E = 70 GPa\n", 2, 10, "unexpected 'GPa' after the value of 'E' in material 'm'" SI " (E is in Pa: write 70e9 for 70 GPa)", "E");
    EP("unit word: E = 70GPa", "link a\n  E = 70GPa\n", 2, 7, "malformed number '70GPa' for 'E' in link 'a'" SI " (E is in Pa: write 70e9 for 70 GPa)", "E");
    EP("unit word: reported before the range (dt = 10 us)", "solver\n  dt = 10 us\nlink a\n", 2, 11, "unexpected 'us' after the value of 'dt' in solver" SI " (dt is in s: write 10e-6 for 10 us)", "dt");
    EP("unit word: a unit word it does not convert", "link a\n  rho = 2.7 g/cm^3\n", 2, 13, SI " (rho is in kg/m^3)", "rho");
    EP("unit word: a key without a unit", J2 "  restitution = 0.5 units\n", 5, 21, "unexpected 'units' after the value of 'restitution' in joint 'j'" SI, "restitution");
    EP("unit word: a spring stiffness", J2 "  spring = 0.1 Nm 90 deg\n", 5, 16, SI " (spring is in N m/rad)", "spring");
    EP("unit word: a table torque", J2 "  table = 0 deg 1 Nm, 90 deg 2\n", 5, 19, "found 'Nm' in joint 'j' (table = angle torque, angle torque, ...)" SI " (a torque is in N m)", "table");
    EP("unit word: an angle with a unit it does not know, glued", "link a\n  angle = 90degrees\n", 2, 11,
       "malformed number '90degrees' for 'angle' in link 'a': an angle is a number in rad, or a number and deg or rad: '90 deg' or '90 rad'", "angle");
    EP("unit word: a rate", "link a\n  omega = 5rpm\n", 2, 11, "a rate is a number in rad/s, or a number and deg/s or rad/s: '5 deg/s' or '5 rad/s'", "omega");
#undef SI
}

/* ------------------------------------------------------------------ the title */
/* title = "..." before the first section: what it holds, and where the parser says no */
static void test_title_parse(void)
{
    static const char *text =
        "# a comment and a blank line first\n"
        "\n"
        "title = \"Two-link deployment, # and = inside (Wong 2002)\"   # a comment after it\n"
        "link a\n";
    rj_scene_file f;
    rj_error e;
    rj_result r = parse_str(text, &f, &e);
    check(r == RJ_OK && strcmp(f.title, "Two-link deployment, # and = inside (Wong 2002)") == 0,
          "title: a quoted string keeps its spaces, ',', '#' and '='", r == RJ_OK ? f.title : e.msg);
    if (r == RJ_OK) rj_scene_file_free(&f);
    r = parse_str("link a\n", &f, &e);
    check(r == RJ_OK && f.title[0] == 0, "title: none gives \"\"", r == RJ_OK ? "empty" : e.msg);
    if (r == RJ_OK) rj_scene_file_free(&f);
    r = parse_str("title = \"\"\nlink a\n", &f, &e);
    check(r == RJ_OK && f.title[0] == 0, "title: \"\" is allowed and is the same as none", r == RJ_OK ? "empty" : e.msg);
    if (r == RJ_OK) rj_scene_file_free(&f);
    {   /* the longest title: RJ_SCENE_TITLE_MAX - 1 bytes */
        char *s = line_of("title = \"", 'x', RJ_SCENE_TITLE_MAX - 1, "\"\nlink a\n");
        r = parse_str(s, &f, &e);
        free(s);
        check(r == RJ_OK && strlen(f.title) == RJ_SCENE_TITLE_MAX - 1, "title: 127 bytes fit", r == RJ_OK ? "parsed" : e.msg);
        if (r == RJ_OK) rj_scene_file_free(&f);
    }
}

static void test_title_errors(void)
{
    char *s = line_of("title = \"", 'x', RJ_SCENE_TITLE_MAX, "\"\nlink a\n");
    EP("title error: 128 bytes are too long", s, 1, 9, "title of 128 bytes is too long (at most 127)", "title");
    free(s);
    EP("title error: unterminated quote", "title = \"Solar array\nlink a\n", 1, 9, "unterminated string: no closing '\"' on this line", "");
    EP("title error: a quote does not run past the line end", "title = \"Solar\n array\"\nlink a\n", 1, 9, "unterminated string", "");
    EP("title error: inside a section", "link a\ntitle = \"x\"\n", 2, 1, "unknown key 'title' in link 'a' (a title goes at the top of the file, before the first section)", "title");
    EP("title error: after the solver section", "solver\ntitle = \"x\"\nlink a\n", 2, 1, "unknown key 'title' in solver (a title goes at the top", "title");
    EP("title error: twice", "title = \"a\"\ntitle = \"b\"\nlink a\n", 2, 1, "duplicate title (first set on line 1)", "title");
    EP("title error: not quoted", "title = Solar\nlink a\n", 1, 9, "expected a quoted string, found 'Solar' for 'title' (write title = \"text\")", "title");
    EP("title error: missing '='", "title \"Solar\"\nlink a\n", 1, 6, "missing '=' after 'title'", "title");
    EP("title error: missing value", "title =\nlink a\n", 1, 8, "missing value for 'title'", "title");
    EP("title error: text after the closing quote", "title = \"Solar\" array\nlink a\n", 1, 17, "unexpected 'array' after the value of 'title'", "title");
    EP("title error: a tab inside", "title = \"Solar\tarray\"\nlink a\n", 1, 15, "byte 0x09 in the title: a title is printable text (no tabs)", "title");
    EP("title error: misspelt key at the top", "titel = \"x\"\nlink a\n", 1, 1, "key 'titel' outside any section (start one with solver, material, section, link, joint, load, actuator or coupling); did you mean 'title'?", "");
    EP("title error: a quoted string where a number goes", "link a\n  length = \"1\"\n", 2, 12, "expected a number, found '\"1\"' for 'length' in link 'a'", "length");
    EP("title error: a quoted name", "link \"a b\"\n", 1, 6, "invalid name '\"a b\"' after 'link'", "link");
}

/* rj_scene_write_ex writes the title; parsing gives it back, and rj_scene_write is
   rj_scene_write_ex without one */
static void test_title_write(void)
{
    static const char *const titles[] = { "Three-panel solar array", " spaces kept at both ends ", "a#b = c, d", "" };
    rj_link_def L = rj_default_link_def();
    rj_scene_def sc = rj_default_scene_def();
    char buf[4000], buf2[4000], d[300], *lng;
    size_t k, n;
    rj_scene_file f;
    rj_error e;
    sc.links = &L;
    sc.link_count = 1;
    for (k = 0; k < sizeof titles / sizeof titles[0]; k++) {
        char name[120];
        rj_result r;
        n = rj_scene_write_ex(&sc, NULL, NULL, titles[k], buf, sizeof buf);
        r = n ? rj_scene_parse(buf, n, "w.rjs", &f, &e) : RJ_ERR_PARSE;
        snprintf(name, sizeof name, "title round trip: \"%s\"", titles[k]);
        snprintf(d, sizeof d, "%lu bytes; read back \"%s\"", (unsigned long)n, r == RJ_OK ? f.title : e.msg);
        check(n > 0 && r == RJ_OK && strcmp(f.title, titles[k]) == 0, name, d);
        if (r == RJ_OK) rj_scene_file_free(&f);
    }
    n = rj_scene_write(&sc, NULL, NULL, buf, sizeof buf);
    rj_scene_write_ex(&sc, NULL, NULL, NULL, buf2, sizeof buf2);
    check(n > 0 && strcmp(buf, buf2) == 0 && strstr(buf, "title") == NULL, "title: rj_scene_write = rj_scene_write_ex with NULL, no title line", "same text");
    lng = line_of("", 'x', RJ_SCENE_TITLE_MAX, "");
    snprintf(d, sizeof d, "quote %lu, tab %lu, newline %lu, 128 bytes %lu, 127 bytes %lu",
             (unsigned long)rj_scene_write_ex(&sc, NULL, NULL, "a \"b\"", buf, sizeof buf), (unsigned long)rj_scene_write_ex(&sc, NULL, NULL, "a\tb", buf, sizeof buf),
             (unsigned long)rj_scene_write_ex(&sc, NULL, NULL, "a\nb", buf, sizeof buf), (unsigned long)rj_scene_write_ex(&sc, NULL, NULL, lng, buf, sizeof buf),
             (unsigned long)rj_scene_write_ex(&sc, NULL, NULL, lng + 1, buf, sizeof buf));
    check(rj_scene_write_ex(&sc, NULL, NULL, "a \"b\"", buf, sizeof buf) == 0 && rj_scene_write_ex(&sc, NULL, NULL, "a\tb", buf, sizeof buf) == 0
          && rj_scene_write_ex(&sc, NULL, NULL, "a\nb", buf, sizeof buf) == 0 && rj_scene_write_ex(&sc, NULL, NULL, lng, buf, sizeof buf) == 0
          && buf[0] == 0 && rj_scene_write_ex(&sc, NULL, NULL, lng + 1, buf, sizeof buf) > 0,
          "title: the writer refuses what a file cannot hold ('\"', tab, line end, 128 bytes) and writes nothing", d);
    free(lng);
}

/* every example file has a title, and the writer carries it through */
static void test_title_examples(void)
{
    static const char *const files[] = { "deploy.rjs", "impact.rjs", "solar_array.rjs", "solar_array_bus.rjs" };
    size_t k;
    for (k = 0; k < sizeof files / sizeof files[0]; k++) {
        rj_scene_file f, g;
        rj_scene_def fd;
        rj_error e;
        char *buf, name[120], d[400];
        size_t n;
        rj_result r;
        if (!load_example(files[k], &f)) continue;
        fd = rj_scene_file_def(&f);
        n = rj_scene_write_ex(&fd, NULL, NULL, f.title, NULL, 0);
        buf = (char *)malloc(n + 1);
        rj_scene_write_ex(&fd, NULL, NULL, f.title, buf, n + 1);
        r = rj_scene_parse(buf, n, files[k], &g, &e);
        snprintf(name, sizeof name, "title of %s, and through rj_scene_write_ex", files[k]);
        snprintf(d, sizeof d, "\"%s\" -> \"%s\"", f.title, r == RJ_OK ? g.title : e.msg);
        check(f.title[0] != 0 && r == RJ_OK && strcmp(f.title, g.title) == 0, name, d);
        if (r == RJ_OK) rj_scene_file_free(&g);
        free(buf);
        rj_scene_file_free(&f);
    }
}

static void test_api(void)
{
    rj_scene_file f;
    rj_error e;
    rj_result r;
    char d[300];
    talloc ctx;
    int n, ok_all = 1, nomem_seen = 0;
    long live0 = g_alloc.live;
    r = rj_scene_parse(NULL, 0, NULL, &f, &e);
    check(r == RJ_ERR_PARSE && strncmp(e.msg, "<input>:1:1: ", 13) == 0, "NULL text with length 0 is an empty file named <input>", e.msg);
    r = rj_scene_parse(NULL, 5, "x", &f, &e);
    check(r == RJ_ERR_INVALID && zeroed(&f), "NULL text with length > 0 is invalid", e.msg);
    r = rj_scene_parse("link a\n", 7, "x", NULL, &e);
    check(r == RJ_ERR_INVALID, "NULL out is invalid", e.msg);
    r = rj_scene_parse("link a\n  length = -1\n", 21, "x", &f, NULL);
    check(r == RJ_ERR_PARSE && zeroed(&f), "err may be NULL", rj_result_str(r));
    r = rj_scene_parse(J2 "  forward = 1\n  method = penalty\n", strlen(J2 "  forward = 1\n  method = penalty\n"), "x", &f, NULL);
    check(r == RJ_ERR_INVALID && zeroed(&f), "err may be NULL (model validation error keeps its code)", rj_result_str(r));
    {   /* rj_scene_load says why it cannot read a file: the path and strerror */
        char want[300];
        r = rj_scene_load("no/such/file.rjs", &f, &e);
        snprintf(want, sizeof want, "no/such/file.rjs: cannot open the file for reading: %s", strerror(ENOENT));
        check(r == RJ_ERR_PARSE && strcmp(e.msg, want) == 0 && e.value == ENOENT && strcmp(e.field, "path") == 0 && zeroed(&f), "rj_scene_load of a missing file names the path and the reason", e.msg);
        r = rj_scene_load(g_dir, &f, &e);
        snprintf(want, sizeof want, ": %s", strerror(EISDIR));
        check(r == RJ_ERR_PARSE && strncmp(e.msg, g_dir, strlen(g_dir)) == 0 && strstr(e.msg, want) != NULL && zeroed(&f), "rj_scene_load of a directory names the path and the reason", e.msg);
    }
    check(g_alloc.live == live0, "no allocation left behind by the calls above", "live blocks unchanged");
    /* alloc_ctx reaches RJ_MALLOC; every allocation failure is clean */
    memset(&ctx, 0, sizeof ctx);
    r = rj_scene_parse_ex(J2, strlen(J2), "x", &f, &e, &ctx);
    snprintf(d, sizeof d, "%s; %ld allocations through the context, %ld live", rj_result_str(r), ctx.total, ctx.live);
    check(r == RJ_OK && ctx.total >= 1 && ctx.live == 1, "rj_scene_parse_ex allocates through alloc_ctx", d);
    rj_scene_file_free(&f);
    check(ctx.live == 0, "rj_scene_file_free returns the block to its context", "live 0");
    for (n = 1; n <= 4; n++) {
        memset(&ctx, 0, sizeof ctx);
        ctx.fail_at = n;
        r = rj_scene_parse_ex(J2, strlen(J2), "x", &f, &e, &ctx);
        if (r == RJ_ERR_NOMEM) nomem_seen++;
        if (!((r == RJ_ERR_NOMEM && zeroed(&f)) || r == RJ_OK) || (r != RJ_OK && ctx.live != 0)) ok_all = 0;
        if (r == RJ_OK) rj_scene_file_free(&f);
    }
    snprintf(d, sizeof d, "%d of the first 4 allocations failing give RJ_ERR_NOMEM (3 are made), nothing leaked", nomem_seen);
    check(ok_all && nomem_seen == 3, "allocation failures: RJ_ERR_NOMEM and nothing left allocated", d);
    {   /* a 257-item file that fails leaves nothing behind either (ASan/LSan would also say) */
        char *s = repeat("", "link l%d\n", 257, "");
        long before = g_alloc.live;
        r = parse_str(s, &f, &e);
        free(s);
        check(r == RJ_ERR_PARSE && g_alloc.live == before, "failed parse of a large file frees its blocks", e.msg);
    }
}

static void test_locale(void)
{
    static const char *const names[] = { "de_DE.UTF-8", "de_DE.utf8", "fr_FR.UTF-8", "fr_FR.utf8", "de_DE", "fr_FR" };
    size_t k;
    const char *got = NULL;
    char t[16];
    for (k = 0; k < sizeof names / sizeof names[0] && !got; k++) got = setlocale(LC_NUMERIC, names[k]);
    snprintf(t, sizeof t, "%.1f", 1.5);
    if (!got || strcmp(t, "1,5") != 0) {
        printf("SKIP locale: no comma-decimal locale installed (not counted)\n");
        setlocale(LC_NUMERIC, "C");
        return;
    }
    {
        rj_scene_file a;
        rj_error e;
        rj_result r = parse_str("link a\n  length = 1.25  angle = 2.5 deg\n", &a, &e);
        char d[400];
        snprintf(d, sizeof d, "%s: %s", got, r == RJ_OK ? "parsed" : e.msg);
        check(r == RJ_OK && a.links[0].length == 1.25 && a.links[0].angle == rj_rad(2.5), "locale with a decimal comma: numbers still use '.'", d);
        if (r == RJ_OK) {
            rj_scene_def sd = rj_scene_file_def(&a);
            char buf[1000];
            rj_scene_write(&sd, NULL, NULL, buf, sizeof buf);
            check(strstr(buf, "length = 1.25") != NULL && strstr(buf, "2.5 deg") != NULL, "locale with a decimal comma: the writer writes '.'",
                  strstr(buf, "length = 1.25") ? "length = 1.25 ... angle = 2.5 deg" : "no 'length = 1.25' in the written text");
            rj_scene_file_free(&a);
        }
    }
    setlocale(LC_NUMERIC, "C");
}

/* Changes on top of a text (rj_scene_parse_set): a solver change where the text has no
   solver section takes the defaults' place; a section's change reaches the links that
   name it; a link's replaces its own key; more than RJ_SCENE_MAX_SETS changes, or a NULL
   one, are refused naming nsets; nothing is left allocated. */
static void test_parse_set(void)
{
    static const char text[] = "section strip\n  width = 0.05  height = 0.01\n"
                               "link a\n  length = 1  section = strip  E = 7e10\n";
    const char *sets[3] = { "solver.gravity=0 -9.81", "section.strip.width=0.02", "link.a.E=6e10" };
    const char *many[RJ_SCENE_MAX_SETS + 1];
    rj_scene_file f;
    rj_error e;
    char d[300];
    int k, ok;
    ok = rj_scene_parse_set(text, sizeof text - 1, "s.rjs", sets, 3, &f, &e) == RJ_OK;
    snprintf(d, sizeof d, "%s: gravity %g, width %g, E %g", ok ? "read" : e.msg,
             ok ? f.solver.gravity[1] : NAN, ok ? f.links[0].width : NAN, ok ? f.links[0].E : NAN);
    check(ok && f.solver.gravity[1] == -9.81 && f.links[0].width == 0.02 && f.links[0].E == 6e10,
          "parse_set: the solver's, a section's and a link's changes all taken", d);
    if (ok)
        rj_scene_file_free(&f);
    for (k = 0; k <= RJ_SCENE_MAX_SETS; k++)
        many[k] = "link.a.E=6e10";
    ok = rj_scene_parse_set(text, sizeof text - 1, "s.rjs", many, RJ_SCENE_MAX_SETS + 1, &f, &e) ==
             RJ_ERR_INVALID &&
         strcmp(e.field, "nsets") == 0;
    many[1] = NULL;
    ok = ok && rj_scene_parse_set(text, sizeof text - 1, "s.rjs", many, 2, &f, &e) == RJ_ERR_INVALID;
    check(ok, "parse_set: 65 changes, or a NULL one, refused naming nsets", e.msg);
}

/* ------------------------------------------------------------------ fidelity = pieces */
/* deploy_segmented_scene as build/deploy --links pieces sets it up: 10 pieces a link, dt 0
   (0.9 x the bound), energy_every 16. deploy_scene leaves joint 2's penalty_k at the
   placeholder 1 N m/rad that deploy_build replaces by Eq 31; momentum does not use it, and
   the file leaves it at the default, 0. */
static void pieces_c(rj_link_def *links, rj_joint_def *joints, rj_scene_def *sc)
{
    deploy_opts o = deploy_default_opts();
    o.dt = 0;
    o.energy_every = 16;
    deploy_segmented_scene(&o, 10, links, joints, sc);
    joints[11].penalty_k = 0.0;
}

/* both scenes built and run to t_end: 1 when they take the same steps and end with every
   joint's running angle and rate the same bits */
static int pieces_same_run(const rj_scene_def *a, const rj_scene_def *b, double t_end,
                           char *why, size_t n)
{
    rj_model *ma = NULL, *mb = NULL;
    rj_state *sa = NULL, *sb = NULL;
    rj_error e;
    int ok = 0, j;
    snprintf(why, n, "a model was not built");
    if (rj_model_create(a, &ma, &e, NULL) == RJ_OK && rj_model_create(b, &mb, &e, NULL) == RJ_OK) {
        rj_state_create(ma, &sa, NULL);
        rj_state_create(mb, &sb, NULL);
        ok = rj_run(ma, sa, t_end, 0.0, NULL, NULL) == RJ_OK;
        ok = ok && rj_run(mb, sb, t_end, 0.0, NULL, NULL) == RJ_OK;
        ok = ok && rj_state_steps(sa) == rj_state_steps(sb);
        for (j = 0; ok && j < a->joint_count; j++) {
            const double ta = rj_joint_theta_running(ma, sa, j), tb = rj_joint_theta_running(mb, sb, j);
            const double ra = rj_joint_rate(ma, sa, j), rb = rj_joint_rate(mb, sb, j);
            ok = !memcmp(&ta, &tb, sizeof ta) && !memcmp(&ra, &rb, sizeof ra);
            if (!ok) snprintf(why, n, "joint %d: %.17g vs %.17g rad", j, ta, tb);
        }
        if (ok) snprintf(why, n, "%ld steps of %.4g s to t = %.4f s; joint 2 (index 11) at %.6f deg",
                         rj_state_steps(sa), rj_model_dt(ma), rj_state_time(sa), rj_deg(rj_joint_theta_running(ma, sa, 11)));
        rj_state_destroy(sa, NULL);
        rj_state_destroy(sb, NULL);
    } else
        snprintf(why, n, "%s", e.msg);
    if (ma) rj_model_destroy(ma, NULL);
    if (mb) rj_model_destroy(mb, NULL);
    return ok;
}

/* deploy_pieces.rjs is deploy_segmented_scene field by field, its pieces and springs
   named after the arms, and runs the same bits; an inner piece of 2 elements (as a node
   reference in its middle gives it) moves the same bits too */
static void test_pieces_deploy(void)
{
    rj_link_def links[22];
    rj_joint_def joints[22];
    rj_scene_def sc, fd;
    rj_scene_file f;
    char why[300], want[40];
    int i, k, names = 1;
    if (!load_example("deploy_pieces.rjs", &f)) return;
    fd = rj_scene_file_def(&f);
    pieces_c(links, joints, &sc);
    check(same_scene(&fd, &sc, 1, why, sizeof why) && fd.load_count == 0 && fd.actuator_count == 0,
          "deploy_pieces.rjs = deploy_segmented_scene (10 pieces, as build/deploy --links pieces) field by field", why);
    for (i = 0; i < 2 && f.link_count == 22 && f.joint_count == 22; i++)
        for (k = 0; k <= 10; k++) {
            snprintf(want, sizeof want, k ? "arm%d_p%d" : "arm%d", i + 1, k);
            names = names && strcmp(f.link_names[11 * i + k], want) == 0;
            snprintf(want, sizeof want, k ? "arm%d_b%d" : "j%d", i + 1, k);
            names = names && strcmp(f.joint_names[11 * i + k], want) == 0;
        }
    snprintf(why, sizeof why, "links %s %s .. %s, joints %s %s .. %s %s", f.link_names[0], f.link_names[1], f.link_names[21],
             f.joint_names[0], f.joint_names[1], f.joint_names[11], f.joint_names[21]);
    check(names && rj_scene_joint_index(&f, "j2") == 11 && rj_scene_link_index(&f, "arm2") == 11,
          "deploy_pieces.rjs names: arm1, arm1_p1 .. arm1_p10; j1, arm1_b1 .. arm1_b10, j2, arm2_b1 ..", why);
    check(pieces_same_run(&fd, &sc, 0.5, why, sizeof why), "deploy_pieces.rjs runs deploy_segmented_scene's joint angles bit for bit (0.5 s)", why);
    f.links[5].elements = 2;
    check(pieces_same_run(&fd, &sc, 0.5, why, sizeof why), "a rigid piece of 2 elements moves as of 1 (mass and inertia do not depend on them): the same bits", why);
    f.links[5].elements = 1;
    rj_scene_file_free(&f);
}

/* what fidelity = pieces refuses, naming the file:line:col, the key and the value */
static void test_pieces_errors(void)
{
    char *s;
    EP("pieces: elements = 0 refused", "link a\n  fidelity = pieces  elements = 0\n", 2, 33,
       "elements = 0 is out of range in link 'a': must be 1..1000000", "elements");
    EP("pieces: a misspelt fidelity lists pieces", "link a\n  fidelity = piece\n", 2, 14,
       "(expected flexible, rigid, inextensible or pieces); did you mean 'pieces'?", "fidelity");
    EP("pieces: a joint's node2 on a cut link cannot be placed",
       "link a\n  fidelity = pieces  elements = 4\nlink b\njoint j\n  body1 = b  body2 = a  node2 = 2\n", 5, 33,
       "node2 = 2 in joint 'j' cannot be placed: link 'a' is cut into pieces (fidelity = pieces), which hang from its node 0", "node2");
    EP("pieces: node2 = last on a cut link cannot be placed either",
       "link a\n  fidelity = pieces  elements = 4\nlink b\njoint j\n  body1 = b  body2 = a  node2 = last\n", 5, 33,
       "node2 = last in joint 'j' cannot be placed", "node2");
    EP("pieces: a piece's name taken by another link",
       "link a\n  fidelity = pieces  elements = 2\nlink a_p1\n", 2, 14,
       "fidelity = pieces in link 'a' names its piece 1 'a_p1', which the link on line 3 has too", "fidelity");
    EP("pieces: a spring's name taken by another joint",
       "link a\n  fidelity = pieces  elements = 2\njoint a_b2\n  body1 = ground  body2 = a\n", 2, 14,
       "fidelity = pieces in link 'a' names its bending joint 2 'a_b2', which the joint on line 3 has too", "fidelity");
    EP("pieces: a link name too long for its pieces' names",
       "link abcdefghijabcdefghijabcdefghij\n  fidelity = pieces\n", 1, 1,
       "link name 'abcdefghijabcdefghijabcdefghij' is too long for fidelity = pieces: its last piece would be 'abcdefghijabcdefghijabcdefghij_p10'", "link");
    EP("pieces: more links than a scene may have", "link a\n  fidelity = pieces  elements = 300\n", 2, 33,
       "elements = 300 in link 'a' (fidelity = pieces) makes 301 rigid pieces: the scene would have 301 links, more than the 256 a scene may have", "elements");
    EP("pieces: more links than a scene may have, counting a link after the cut one",
       "link a\n  fidelity = pieces  elements = 255\nlink b\n", 2, 33,
       "elements = 255 in link 'a' (fidelity = pieces) makes 256 rigid pieces: the scene would have 257 links", "elements");
    s = repeat("link a\n  fidelity = pieces  elements = 200\nlink b\n", "joint j%d\n  body1 = ground  body2 = b\n", 60, "");
    EP("pieces: more joints than a scene may have", s, 2, 33,
       "elements = 200 in link 'a' (fidelity = pieces) makes 200 bending joints: the scene would have 260 joints, more than the 256 a scene may have", "elements");
    free(s);
}

/* changes (--set) reach every piece: E doubled doubles every bending spring of that arm,
   elements = 4 cuts the other into 5 pieces */
static void test_pieces_set(void)
{
    const char *sets[2] = { "link.arm1.E=1.4e11", "link.arm2.elements=4" };
    char path[512], d[300];
    rj_scene_file a, b;
    rj_error e;
    int k, ok;
    snprintf(path, sizeof path, "%s/deploy_pieces.rjs", g_dir);
    if (rj_scene_load(path, &a, &e) != RJ_OK) { check(0, "pieces --set: deploy_pieces.rjs", e.msg); return; }
    if (rj_scene_load_set(path, sets, 2, &b, &e) != RJ_OK) { check(0, "pieces --set: deploy_pieces.rjs with changes", e.msg); rj_scene_file_free(&a); return; }
    ok = b.link_count == 16 && b.joint_count == 16;
    for (k = 0; ok && k < 16; k++)
        ok = b.links[k].E == (k <= 10 ? 1.4e11 : 7e10);
    for (k = 1; ok && k <= 10; k++)
        ok = b.joints[k].spring_k == 2 * a.joints[k].spring_k;
    snprintf(d, sizeof d, "%d links, %d joints; arm1_b1 k %.17g N m/rad (was %.17g)", b.link_count, b.joint_count,
             b.joints[1].spring_k, a.joints[1].spring_k);
    check(ok, "pieces --set link.arm1.E=1.4e11: every piece of arm1 takes it, every bending spring of arm1 doubles", d);
    ok = b.link_count == 16 && b.joint_count == 16 && strcmp(b.link_names[15], "arm2_p4") == 0 && strcmp(b.joint_names[15], "arm2_b4") == 0;
    for (k = 0; ok && k <= 4; k++)
        ok = b.links[11 + k].length == (k == 0 || k == 4 ? 0.5 : 1.0) * (0.9945 / 4) && b.links[11 + k].elements == 1;
    for (k = 12; ok && k <= 15; k++)
        ok = b.joints[k].spring_k == 7e10 * 2.9117e-10 / (0.9945 / 4) && b.joints[k].body2 == k;
    snprintf(d, sizeof d, "arm2 .. %s, springs .. %s; arm2_b1 k %.17g N m/rad", b.link_count == 16 ? b.link_names[15] : "?",
             b.joint_count == 16 ? b.joint_names[15] : "?", b.joint_count == 16 ? b.joints[12].spring_k : 0.0);
    check(ok, "pieces --set link.arm2.elements=4: arm2 in 5 pieces (l/2, l, l, l, l/2), 4 springs E I / l", d);
    rj_scene_file_free(&a);
    rj_scene_file_free(&b);
}

/* a cut link among flexible ones (a mixed scene): its springs between two rigid pieces are
   accepted; a joint's node1 and a load's node inside it go to the middle of the piece
   holding them (which then has 2 elements), exactly where they were; a cut root link's
   springs come after the file's joints; actuators and couplings follow their joints */
static void test_pieces_mixed(void)
{
    static const char text[] =
        "link base\n  length = 0.5  elements = 4  root = clamped\n"
        "link arm\n  length = 1  elements = 4  fidelity = pieces  width = 0.01  height = 0.02\n"
        "link flap\n  length = 0.2  elements = 2\n"
        "joint j\n  body1 = base  body2 = arm  spring = 50 180 deg\n"
        "joint k\n  body1 = arm  node1 = 1  body2 = flap  angle0 = 90 deg\n"
        "load push\n  link = arm  node = 2  force = 0 -10\n";
    static const char root[] = "link a\n  fidelity = pieces  elements = 2  root = fixed\n"
                               "link b\njoint j\n  body1 = a  body2 = b\n";
    static const char refs[] = "link a\n  fidelity = pieces  elements = 2\nlink b\n"
                               "joint ja\n  body1 = ground  body2 = a\n"
                               "joint jb\n  body1 = a  body2 = b\n"
                               "actuator m\n  joint = jb  torque = 0.1\n"
                               "coupling c\n  joints = ja jb\n";
    rj_scene_file f;
    rj_error e;
    rj_model *m = NULL;
    rj_state *s = NULL;
    rj_scene_def sd;
    double p[2], q[2];
    char d[400];
    int ok;
    if (parse_str(text, &f, &e) != RJ_OK) { check(0, "pieces in a mixed scene: parsed", e.msg); return; }
    ok = f.link_count == 7 && f.joint_count == 6 && strcmp(f.joint_names[5], "k") == 0 && f.joints[5].body1 == 2 &&
         f.joints[5].node1 == 1 && f.loads[0].link == 3 && f.loads[0].node == 1 && f.links[2].elements == 2 &&
         f.links[3].elements == 2 && f.links[4].elements == 1;
    snprintf(d, sizeof d, "k: body1 %d node1 %d; push: link %d node %d", f.joints[5].body1, f.joints[5].node1,
             f.loads[0].link, f.loads[0].node);
    check(ok, "pieces in a mixed scene: node1 = 1 and a load's node = 2 go to the middles of arm_p1 and arm_p2", d);
    sd = rj_scene_file_def(&f);
    if (rj_model_create(&sd, &m, &e, NULL) != RJ_OK) {
        rj_scene_file_locate(&f, &e);
        check(0, "pieces in a mixed scene: the model builds", e.msg);
        rj_scene_file_free(&f);
        return;
    }
    rj_state_create(m, &s, NULL);
    rj_node_position(m, s, 2, 1, p);
    rj_node_position(m, s, 3, 1, q);
    snprintf(d, sizeof d, "arm node 1 at (%.17g, %.3g), node 2 at (%.17g, %.3g): 0.75 and 1 m along +x", p[0], p[1], q[0], q[1]);
    check(fabs(p[0] - 0.75) < 1e-15 && fabs(p[1]) < 1e-15 && fabs(q[0] - 1.0) < 1e-15 && fabs(q[1]) < 1e-15,
          "pieces in a mixed scene: the middle nodes sit where the link's nodes 1 and 2 were", d);
    ok = rj_run(m, s, 0.05, 0.0, NULL, NULL) == RJ_OK;
    snprintf(d, sizeof d, "%s%s; %ld steps of %.3g s", ok ? "ran" : "failed: ", rj_state_error(s), rj_state_steps(s), rj_model_dt(m));
    check(ok, "pieces in a mixed scene: the springs between rigid pieces accepted, 0.05 s run", d);
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
    rj_scene_file_free(&f);
    if (parse_str(root, &f, &e) != RJ_OK) { check(0, "pieces: a cut root link", e.msg); return; }
    ok = f.link_count == 4 && f.joint_count == 3 && strcmp(f.joint_names[1], "a_b1") == 0 && f.joints[0].body1 == 2 &&
         f.joints[0].body2 == 3 && f.links[0].root == RJ_ROOT_FIXED && f.links[1].root == RJ_ROOT_FREE;
    snprintf(d, sizeof d, "joints %s %s %s; j: %d -> %d", f.joint_names[0], f.joint_names[1], f.joint_names[2], f.joints[0].body1, f.joints[0].body2);
    check(ok, "pieces: a cut root link keeps its root on the first piece, its springs after the file's joints", d);
    rj_scene_file_free(&f);
    if (parse_str(refs, &f, &e) != RJ_OK) { check(0, "pieces: an actuator and a coupling follow their joints", e.msg); return; }
    ok = f.joint_count == 4 && strcmp(f.joint_names[3], "jb") == 0 && f.actuators[0].joint == 3 &&
         f.couplings[0].joint_a == 0 && f.couplings[0].joint_b == 3;
    snprintf(d, sizeof d, "m: joint %d; c: joints %d %d", f.actuators[0].joint, f.couplings[0].joint_a, f.couplings[0].joint_b);
    check(ok, "pieces: an actuator and a coupling follow their joints past the springs (jb: 1 -> 3)", d);
    rj_scene_file_free(&f);
}

int main(int argc, char **argv)
{
    if (argc > 1) g_dir = argv[1];
    else {
        FILE *f = fopen("examples/scenes/deploy.rjs", "rb");
        if (f) fclose(f); else g_dir = "../examples/scenes";
    }
    test_deploy();
    test_impact();
    test_solar();
    file_roundtrip("deploy.rjs");
    file_roundtrip("impact.rjs");
    file_roundtrip("solar_array.rjs");
    file_roundtrip("solar_array_bus.rjs");
    test_writer();
    test_writer_falling_table();
    test_writer_ignored();
    test_writer_negative_zero();
    test_writer_random_models();
    test_units();
    test_comments();
    test_errors();
    test_suggestions();
    test_unit_words();
    test_title_parse();
    test_title_errors();
    test_title_write();
    test_title_examples();
    test_api();
    test_locale();
    test_parse_set();
    test_pieces_deploy();
    file_roundtrip("deploy_pieces.rjs");
    test_pieces_errors();
    test_pieces_set();
    test_pieces_mixed();
    {
        char d[100];
        snprintf(d, sizeof d, "%ld blocks live after every test", g_alloc.live);
        check(g_alloc.live == 0, "nothing allocated is left over", d);
    }
    printf("test_scene: %d passed, %d failed\n", g_pass, g_fail);
    return g_fail ? 1 : 0;
}
