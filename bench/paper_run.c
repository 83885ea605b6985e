/* paper_run.c - the deployment at the paper's settings (SPEC 9.2) for T seconds, nothing
   else: the program bench/instr.sh counts instructions per step of. */
#define REVJOINT_IMPLEMENTATION
#include "revjoint.h"
#include "examples/scenes.h"
#include <stdio.h>
#include <stdlib.h>

int main(int argc, char **argv)
{
    const double t_end = argc > 1 ? atof(argv[1]) : 6.0;
    deploy_opts o = deploy_default_opts();
    rj_model *m;
    rj_state *s;
    rj_error err;
    rj_result r;
    if (deploy_build(&o, &m, &err) != RJ_OK) { fprintf(stderr, "paper_run: %s\n", err.msg); return 1; }
    if (rj_state_create(m, &s, NULL) != RJ_OK) { rj_model_destroy(m, NULL); return 1; }
    r = rj_run(m, s, t_end, 0.0, NULL, NULL);
    printf("paper_run: %s at t = %.6f s, q2 = %.9f deg\n", rj_result_str(r), rj_state_time(s), deploy_q2_deg(m, s));
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
    return r == RJ_OK ? 0 : 1;
}
