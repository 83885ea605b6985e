/* test_lanes.c - the step's vector lanes against its scalar code: prints one hash of the
   full state per scene after a run. tests/lanes.sh builds this file five ways (gcc -O2
   with the AVX2 dispatch, gcc -O2 -DRJ_NO_DISPATCH, gcc -O3 -march=native, clang -O2,
   -DRJ_NO_SIMD) and fails unless all print the same hashes: every lane must do the scalar
   code's operations in the scalar code's order. Each scene runs twice, double-buffered
   (solver.in_place OFF) and in place (ON, where the scene allows it); the line says whether
   the two agree to the bit ("in place same"), and lanes.sh fails on "DIFFERS". */
#define REVJOINT_IMPLEMENTATION
#include "revjoint.h"
#include "examples/scenes.h"
#include <stdio.h>
#include <string.h>

static unsigned long long fnv(unsigned long long h, const void *p, size_t n)
{
    const unsigned char *c = (const unsigned char *)p;
    size_t k;
    for (k = 0; k < n; k++) { h ^= c[k]; h *= 1099511628211ULL; }
    return h;
}

/* positions, rotations, velocities and rates of every node, joint angles and rates, energy */
static unsigned long long state_hash(const rj_model *m, const rj_state *s)
{
    unsigned long long h = 1469598103934665603ULL;
    rj_energy e;
    int l, n, j;
    for (l = 0; l < rj_model_link_count(m); l++)
        for (n = 0; n < rj_link_node_count(m, l); n++) {
            double v[6];
            rj_node_position(m, s, l, n, v); v[2] = rj_node_rotation(m, s, l, n);
            rj_node_velocity(m, s, l, n, v + 3); v[5] = rj_node_rate(m, s, l, n);
            h = fnv(h, v, sizeof v);
        }
    for (j = 0; j < rj_model_joint_count(m); j++) {
        double v[2];
        v[0] = rj_joint_theta_running(m, s, j); v[1] = rj_joint_rate(m, s, j);
        h = fnv(h, v, sizeof v);
    }
    memset(&e, 0, sizeof e);
    rj_state_energy(m, s, &e);
    return fnv(h, &e, sizeof e);
}

/* One run to t_end: its result, end time, hash, and whether the model stepped in place. */
typedef struct { rj_result r; double t; unsigned long long h; int ip; } outcome;
static int run1(const char *name, const rj_scene_def *sc, int in_place, double t_end, outcome *o)
{
    rj_model *m = NULL;
    rj_state *s = NULL;
    rj_error err;
    rj_scene_def d = *sc;
    d.solver.in_place = in_place;
    if (rj_model_create(&d, &m, &err, NULL) != RJ_OK) { printf("%s: model: %s\n", name, err.msg); return 1; }
    if (rj_state_create(m, &s, NULL) != RJ_OK) { printf("%s: no state\n", name); rj_model_destroy(m, NULL); return 1; }
    o->r = rj_run(m, s, t_end, 0.0, NULL, NULL);
    o->t = rj_state_time(s); o->h = state_hash(m, s); o->ip = m->ip;
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
    return 0;
}

static int run(const char *name, const rj_scene_def *sc, double t_end)
{
    outcome a, b;
    if (run1(name, sc, RJ_IN_PLACE_OFF, t_end, &a) || run1(name, sc, RJ_IN_PLACE_ON, t_end, &b)) return 1;
    printf("%-28s %s t = %.6f hash %016llx, in place %s\n", name, rj_result_str(a.r), a.t, a.h,
           !b.ip ? "n/a" : a.r == b.r && a.t == b.t && a.h == b.h ? "same" : "DIFFERS");
    return 0;
}

static int run_file(const char *path, double t_end)
{
    rj_scene_file f;
    rj_error err;
    rj_scene_def sc;
    int rc;
    if (rj_scene_load(path, &f, &err) != RJ_OK) { printf("%s: %s\n", path, err.msg); return 1; }
    sc = rj_scene_file_def(&f);
    rc = run(path, &sc, t_end);
    rj_scene_file_free(&f);
    return rc;
}

int main(void)
{
    int rc = 0, i;
    {   /* the deployment at the paper's settings, through both locks (joint 2's Eq 31
           stiffness as deploy_build sets it) */
        deploy_opts o = deploy_default_opts();
        rj_link_def L[2];
        rj_joint_def J[2];
        rj_scene_def sc;
        rj_model *m;
        rj_error err;
        if (deploy_build(&o, &m, &err) != RJ_OK) { printf("deploy: %s\n", err.msg); return 1; }
        deploy_scene(&o, L, J, &sc);
        J[1].penalty_k = rj_model_joint_def(m, 1)->penalty_k;
        rj_model_destroy(m, NULL);
        rc |= run("deploy (paper)", &sc, 6.0);
    }
    {   /* free links of 1 .. 17 elements (every tail length of 4 and 8 lanes), 23, 200 and
           300 (two chunks); fast spin: chords turn more than the series covers, the exact path */
        static const int els[] = { 1, 2, 3, 4, 5, 6, 7, 8, 9, 13, 15, 16, 17, 23, 200, 300 };
        for (i = 0; i < (int)(sizeof els / sizeof els[0]); i++) {
            rj_link_def L = rj_default_link_def();
            rj_scene_def sc = rj_default_scene_def();
            char name[40];
            L.height = 0.01; L.elements = els[i]; L.omega = 1.0; L.vy = 0.3;
            sc.links = &L; sc.link_count = 1;
            snprintf(name, sizeof name, "free link %d el", els[i]);
            rc |= run(name, &sc, 0.05);
            L.omega = 3000.0;
            snprintf(name, sizeof name, "spinning link %d el", els[i]);
            rc |= run(name, &sc, 0.002);
        }
    }
    {   /* the impact problem, every method */
        static const rj_method meth[] = { RJ_METHOD_PENALTY, RJ_METHOD_ADAPTIVE, RJ_METHOD_MOMENTUM, RJ_METHOD_FORCED, RJ_METHOD_ENERGY };
        for (i = 0; i < 5; i++) {
            impact_opts o = impact_default_opts();
            rj_link_def links[2];
            rj_joint_def joint;
            rj_scene_def sc;
            char name[40];
            o.method = meth[i];
            impact_scene(&o, links, &joint, &sc);
            snprintf(name, sizeof name, "impact method %d", (int)meth[i]);
            rc |= run(name, &sc, 0.1);
        }
    }
    {   /* pins at inner nodes (the nodes the step advances again sit mid-chunk), chord and
           tangent references, friction, damping, a table, springs, a penalty limit */
        static const int refs[2] = { RJ_REF_TANGENT, RJ_REF_CHORD };
        for (i = 0; i < 2; i++) {
            rj_link_def L[3];
            rj_joint_def J[3];
            rj_scene_def sc = rj_default_scene_def();
            char name[48];
            int k;
            for (k = 0; k < 3; k++) {
                L[k] = rj_default_link_def();
                L[k].length = 1.0; L[k].elements = k == 0 ? 17 : 9; L[k].height = 0.02; L[k].width = 0.05;
                J[k] = rj_default_joint_def();
                J[k].reference = refs[i]; J[k].friction = 0.01; J[k].damping = 0.002; J[k].spring_k = 0.5;
            }
            L[0].omega = 0.5;
            J[0].body1 = -1; J[0].body2 = 0;
            J[1].body1 = 0; J[1].node1 = 6; J[1].body2 = 1; J[1].angle0 = 1.0;
            J[1].has_forward = 1; J[1].forward = 1.2; J[1].method = RJ_METHOD_PENALTY; J[1].penalty_k = 50.0;
            J[2].body1 = 0; J[2].node1 = 12; J[2].body2 = 2; J[2].angle0 = -1.0;
            J[2].table_count = 3;
            J[2].table_angle[0] = 0.0; J[2].table_angle[1] = 3.0; J[2].table_angle[2] = 6.0;
            J[2].table_torque[0] = 0.02; J[2].table_torque[1] = 0.0; J[2].table_torque[2] = 0.02;
            sc.links = L; sc.link_count = 3; sc.joints = J; sc.joint_count = 3;
            snprintf(name, sizeof name, "inner pins, %s reference", i ? "chord" : "tangent");
            rc |= run(name, &sc, 0.3);
        }
    }
    {   /* a pin in the middle chunk of a 300-element link: the forces of its node are kept
           only because the pass stores them in every chunk of such scenes (dn_inner) */
        rj_link_def L[2];
        rj_joint_def J[2];
        rj_scene_def sc = rj_default_scene_def();
        int k;
        for (k = 0; k < 2; k++) {
            L[k] = rj_default_link_def();
            L[k].length = k == 0 ? 3.0 : 0.5; L[k].elements = k == 0 ? 300 : 9; L[k].height = 0.02; L[k].width = 0.05;
            J[k] = rj_default_joint_def();
            J[k].friction = 0.01; J[k].damping = 0.002; J[k].spring_k = 0.5;
        }
        L[0].omega = 0.5;
        J[0].body1 = -1; J[0].body2 = 0;
        J[1].body1 = 0; J[1].node1 = 150; J[1].body2 = 1; J[1].angle0 = 1.0;
        sc.links = L; sc.link_count = 2; sc.joints = J; sc.joint_count = 2;
        rc |= run("pin mid-chunk, 300 elements", &sc, 0.02);
        /* the kernels without energy (solver.energy_every): rj_run takes the accounts at its
           end, so the hash must equal the line above */
        sc.solver.energy_every = 7;
        rc |= run("the same, energy_every 7", &sc, 0.02);
    }
    {   /* gravity and applied loads: a free link of 300 elements (two chunks) with a tip mass,
           thrown under gravity, a tabled follower force and moment on node 150 (inner: it is
           advanced again after the joints) and a dead force on its tip */
        rj_link_def L = rj_default_link_def();
        rj_load_def ld[2];
        rj_scene_def sc = rj_default_scene_def();
        L.height = 0.01; L.elements = 300; L.omega = 1.0; L.vy = 0.3; L.tip_mass = 0.5;
        ld[0] = rj_default_load_def();
        ld[0].node = 150; ld[0].force[1] = 40.0; ld[0].moment = 2.0; ld[0].follower = 1;
        ld[0].table_count = 3;
        ld[0].table_time[0] = 0.0; ld[0].table_time[1] = 0.01; ld[0].table_time[2] = 0.03;
        ld[0].table_factor[0] = 0.0; ld[0].table_factor[1] = 1.0; ld[0].table_factor[2] = -0.5;
        ld[1] = rj_default_load_def();
        ld[1].force[0] = -15.0;
        sc.links = &L; sc.link_count = 1; sc.loads = ld; sc.load_count = 2;
        sc.solver.gravity[0] = 2.0; sc.solver.gravity[1] = -9.81;
        rc |= run("gravity and loads 300 el", &sc, 0.05);
    }
    rc |= run_file("examples/scenes/flexible_pendulum.rjs", 0.5);
    rc |= run_file("examples/scenes/elastica.rjs", 0.2);
    rc |= run_file("examples/scenes/deploy.rjs", 1.0);
    rc |= run_file("examples/scenes/solar_array.rjs", 0.5);
    rc |= run_file("examples/scenes/solar_array_bus.rjs", 0.5);
    {   /* inextensible links (SHAKE), as build/deploy --links inextensible, through both
           latches; and the solar array with inextensible panels on a rigid hub (SHAKE with a
           body in the chain) */
        deploy_opts o = deploy_default_opts();
        rj_link_def L[RJ_SCENE_MAX_LINKS];
        rj_joint_def J[RJ_SCENE_MAX_JOINTS];
        rj_scene_def sc;
        rj_scene_file f;
        rj_error err;
        o.elements = 5; o.dt = 0;
        deploy_scene(&o, L, J, &sc);
        L[0].fidelity = L[1].fidelity = RJ_LINK_INEXTENSIBLE;
        J[1].method = RJ_METHOD_MOMENTUM;
        rc |= run("deploy inextensible 5 el", &sc, 6.0);
        if (rj_scene_load("examples/scenes/solar_array.rjs", &f, &err) != RJ_OK) { printf("solar_array.rjs: %s\n", err.msg); return 1; }
        sc = rj_scene_file_def(&f);
        for (i = 0; i < sc.link_count; i++) {
            L[i] = f.links[i];
            L[i].fidelity = i == rj_scene_link_index(&f, "hub") ? RJ_LINK_RIGID : RJ_LINK_INEXTENSIBLE;
        }
        for (i = 0; i < sc.joint_count; i++) J[i] = f.joints[i];
        sc.links = L; sc.joints = J;
        rc |= run("solar inextensible, rigid hub", &sc, 0.5);
        rj_scene_file_free(&f);
    }
    return rc;
}
