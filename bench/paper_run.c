/* paper_run.c - what bench/instr.sh counts instructions per step of:
     paper_run T [E]             the deployment at the paper's settings (paper sec. 5) for T seconds
     paper_run --free N K [E [P]] one free link of N elements (as in BENCHMARKS.md section 1), K steps;
                                 P: solver.in_place (0 auto, the default; 1 on; 2 off)
     paper_run --two-link F K    the feature-cost scene of BENCHMARKS.md section 5, K steps: F = 0 bare,
                                 1 "everything on" (spring, damping, friction, table, adaptive limits
                                 free, 8 layers); the load rows: 2 gravity (0, -9.81), 3 the caller's
                                 torque 0.1 N m on joint 2, 4 the caller's force (0, -1) N on link 2's
                                 tip, 5 a load (0, -1) N there, 6 a follower load (0, 1) N there with a
                                 4-point table; 7 mass_damping 1 1/s on both links, 8 Kelvin-Voigt
                                 damping = 0.02 5 on both (bench.c's FT_ALPHA, FT_ZETA)
   E: solver.energy_every (default 1) */
#define REVJOINT_IMPLEMENTATION
#include "revjoint.h"
#include "examples/scenes.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int main(int argc, char **argv)
{
    rj_model *m;
    rj_state *s;
    rj_error err;
    rj_result r = RJ_OK;
    const int ee = argc > 2 && strcmp(argv[1], "--free") ? atoi(argv[2]) : argc > 4 ? atoi(argv[4]) : 1;
    if (argc > 3 && !strcmp(argv[1], "--two-link")) {
        /* as bench.c's ft_scene */
        const int all = atoi(argv[2]);
        const long steps = atol(argv[3]);
        rj_link_def L[2];
        rj_joint_def J[2];
        rj_load_def LD = rj_default_load_def();
        rj_scene_def sc;
        long k;
        int i;
        for (i = 0; i < 2; i++) {
            L[i] = rj_default_link_def();
            L[i].length = 1.0; L[i].elements = 10; L[i].height = 0.02; L[i].width = 0.05; L[i].layers = all == 1 ? 8 : 1;
            if (all == 7) L[i].mass_damping = 1.0;
            if (all == 8) { L[i].damping[0] = 0.02; L[i].damping[1] = 5.0; }
        }
        J[0] = rj_default_joint_def();
        J[0].body1 = -1; J[0].body2 = 0; J[0].angle0 = rj_rad(180.0); J[0].rate0 = 2.0;
        J[1] = rj_default_joint_def();
        J[1].body1 = 0; J[1].body2 = 1; J[1].angle0 = rj_rad(180.0); J[1].rate0 = 0.2;
        if (all == 1) {
            J[1].spring_k = 5.0; J[1].spring_free_angle = rj_rad(180.0); J[1].damping = 0.5; J[1].friction = 0.2;
            J[1].table_count = 8;
            for (i = 0; i < 8; i++) { J[1].table_angle[i] = 6.283185307179586 * i / 7.0; J[1].table_torque[i] = 0.1 + 0.05 * (i % 3); }
            J[1].method = RJ_METHOD_ADAPTIVE; J[1].restitution = 0.0;
            J[1].has_forward = 1; J[1].forward = rj_rad(240.0); J[1].has_reverse = 1; J[1].reverse = rj_rad(120.0);
        }
        sc = rj_default_scene_def();
        sc.links = L; sc.link_count = 2; sc.joints = J; sc.joint_count = 2;
        if (all == 2) sc.solver.gravity[1] = -9.81;
        LD.link = 1; LD.force[1] = all == 6 ? 1.0 : -1.0; LD.follower = all == 6;
        LD.table_count = all == 6 ? 4 : 0;
        for (i = 0; i < LD.table_count; i++) { LD.table_time[i] = 4.0 * i; LD.table_factor[i] = i == 0 ? 0 : i == 2 ? -1 : 1; }
        if (all == 5 || all == 6) { sc.loads = &LD; sc.load_count = 1; }
        if (rj_model_create(&sc, &m, &err, NULL) != RJ_OK) { fprintf(stderr, "paper_run: %s\n", err.msg); return 1; }
        if (rj_state_create(m, &s, NULL) != RJ_OK) { rj_model_destroy(m, NULL); return 1; }
        if (all == 3) rj_state_joint_torques(m, s)[1] = 0.1;
        if (all == 4) rj_state_node_forces(m, s)[3 * rj_model_node_index(m, 1, -1) + 1] = -1.0;
        for (k = 0; k < steps && r == RJ_OK; k++) r = rj_step(m, s);
    } else if (argc > 3 && !strcmp(argv[1], "--free")) {
        rj_link_def L = rj_default_link_def();
        rj_scene_def sc = rj_default_scene_def();
        long k, steps = atol(argv[3]);
        L.height = 0.01; L.elements = atoi(argv[2]); L.omega = 1.0;
        sc.links = &L; sc.link_count = 1; sc.solver.energy_every = ee; sc.solver.in_place = argc > 5 ? atoi(argv[5]) : RJ_IN_PLACE_AUTO;
        if (rj_model_create(&sc, &m, &err, NULL) != RJ_OK) { fprintf(stderr, "paper_run: %s\n", err.msg); return 1; }
        if (rj_state_create(m, &s, NULL) != RJ_OK) { rj_model_destroy(m, NULL); return 1; }
        for (k = 0; k < steps && r == RJ_OK; k++) r = rj_step(m, s);
    } else {
        const double t_end = argc > 1 ? atof(argv[1]) : 6.0;
        deploy_opts o = deploy_default_opts();
        o.energy_every = ee;
        if (deploy_build(&o, &m, &err) != RJ_OK) { fprintf(stderr, "paper_run: %s\n", err.msg); return 1; }
        if (rj_state_create(m, &s, NULL) != RJ_OK) { rj_model_destroy(m, NULL); return 1; }
        r = rj_run(m, s, t_end, 0.0, NULL, NULL);
    }
    printf("paper_run: %s at t = %.6f s\n", rj_result_str(r), rj_state_time(s));
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
    return r == RJ_OK ? 0 : 1;
}
