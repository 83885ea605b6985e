/* paper_run.c - what bench/instr.sh counts instructions per step of:
     paper_run T [E]             the deployment at the paper's settings (SPEC 9.2) for T seconds
     paper_run --free N K [E]    one free link of N elements (as in BENCHMARKS.md section 1), K steps
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
    if (argc > 3 && !strcmp(argv[1], "--free")) {
        rj_link_def L = rj_default_link_def();
        rj_scene_def sc = rj_default_scene_def();
        long k, steps = atol(argv[3]);
        L.height = 0.01; L.elements = atoi(argv[2]); L.omega = 1.0;
        sc.links = &L; sc.link_count = 1; sc.solver.energy_every = ee;
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
