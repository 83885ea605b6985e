/* build_run.c - what bench/build_steps.sh counts the instructions of: one model built, then
   K steps of it.
     build_run SCENE.rjs K [KEY=VALUE ...]   a scene file, with rj run's --set changes
     build_run --chain N F K [S [C]]         examples/scenes.h's chain of N links of 4
                                             elements, fidelity F (0 flexible, 1 rigid,
                                             2 inextensible), with a spring of S N m/rad
                                             and a damper of C N m s/rad on every joint
   Prints the step in use and the node count. */
#define REVJOINT_IMPLEMENTATION
#include "revjoint.h"
#include "examples/scenes.h"
#include <stdio.h>
#include <stdlib.h>

static int run(const rj_scene_def *sc, long steps)
{
    rj_model *m;
    rj_state *s;
    rj_error err;
    long k;
    if (rj_model_create(sc, &m, &err, NULL) != RJ_OK || rj_state_create(m, &s, NULL) != RJ_OK) {
        printf("refused: %s\n", err.msg);
        return 1;
    }
    for (k = 0; k < steps; k++)
        rj_step(m, s);
    printf("dt %.9g s, %d nodes\n", rj_model_dt(m), rj_model_node_count(m));
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
    return 0;
}

static int chain(int argc, char **argv)
{
    const int n = atoi(argv[2]), fidelity = atoi(argv[3]);
    rj_link_def *links = (rj_link_def *) malloc(sizeof *links * (size_t) n);
    rj_joint_def *joints = (rj_joint_def *) malloc(sizeof *joints * (size_t) n);
    rj_scene_def sc;
    int k, r;
    chain_scene(n, 4, fidelity, links, joints, &sc);
    for (k = 0; k < n; k++) {
        joints[k].spring_k = argc > 5 ? atof(argv[5]) : 0.0;
        joints[k].damping = argc > 6 ? atof(argv[6]) : 0.0;
    }
    r = run(&sc, atol(argv[4]));
    free(links);
    free(joints);
    return r;
}

int main(int argc, char **argv)
{
    rj_scene_file f;
    rj_scene_def sc;
    rj_error err;
    int r;
    if (argc >= 5 && !strcmp(argv[1], "--chain"))
        return chain(argc, argv);
    if (argc < 3) {
        puts("usage: build_run SCENE.rjs K [KEY=VALUE ...] | build_run --chain N F K [S [C]]");
        return 2;
    }
    if (rj_scene_load_set(argv[1], (const char *const *) (argv + 3), argc - 3, &f, &err) !=
        RJ_OK) {
        printf("refused: %s\n", err.msg);
        return 1;
    }
    sc = rj_scene_file_def(&f);
    r = run(&sc, atol(argv[2]));
    rj_scene_file_free(&f);
    return r;
}
