/* segmented - the deployment (paper sec. 5) with each link cut into rigid pieces joined by
   bending springs (the rigid-finite-element layout, deploy_segmented_scene() in
   examples/scenes.h), integrated in joint coordinates by the library's rigid-link solver.
   Prints the CPU time of the 6 s run (least of 5, no sampling) and writes
   t,q1_deg,q2_deg,tip2_defl_m every 1 ms (tip deflection from the tangent at link 2's
   root) for bench/deploy_errors.py.
   usage: segmented SEGMENTS DT CSV [penalty K]   (DT 0: 0.9 x the stability bound) */
#define _POSIX_C_SOURCE 200809L
#define REVJOINT_IMPLEMENTATION
#include "../revjoint.h"
#include "../examples/scenes.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define MAX_SEGMENTS 100

typedef struct sampler {
    FILE *out;
    int segments;
} sampler;

static int sample(const rj_model *m, const rj_state *s, void *user)
{
    const sampler *w = (const sampler *)user;
    fprintf(w->out, "%.6f,%.10g,%.10g,%.10g\n", rj_state_time(s), deploy_q1_deg(m, s),
            deploy_segmented_q2_deg(m, s, w->segments), deploy_segmented_tip_defl(m, s, w->segments));
    return 0;
}

static double cpu_seconds(void)
{
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

/* least CPU time of five 6 s runs without sampling; -1 when a run fails */
static double time_runs(const rj_model *m, rj_state *s)
{
    double best = 1e30;
    int r;
    for (r = 0; r < 5; r++) {
        double t0, spent;
        rj_state_reset(m, s);
        t0 = cpu_seconds();
        if (rj_run(m, s, 6.0, 0, NULL, NULL) != RJ_OK) return -1;
        spent = cpu_seconds() - t0;
        if (spent < best) best = spent;
    }
    return best;
}

int main(int argc, char **argv)
{
    static rj_link_def links[2 * (MAX_SEGMENTS + 1)];
    static rj_joint_def joints[2 * (MAX_SEGMENTS + 1)];
    deploy_opts o = deploy_default_opts();
    rj_scene_def sc;
    rj_model *m;
    rj_state *s;
    rj_error err;
    sampler w;
    double cpu;
    if (argc != 4 && !(argc == 6 && !strcmp(argv[4], "penalty"))) {
        fputs("usage: segmented SEGMENTS DT CSV [penalty K]\n", stderr);
        return 1;
    }
    w.segments = atoi(argv[1]);
    o.dt = atof(argv[2]);
    o.energy_every = 16;
    if (w.segments < 1 || w.segments > MAX_SEGMENTS || !(o.dt >= 0)) {
        fputs("segmented: SEGMENTS in 1..100, DT >= 0\n", stderr);
        return 1;
    }
    deploy_segmented_scene(&o, w.segments, links, joints, &sc);
    /* a penalty latch instead of the momentum one, on both deployment joints */
    if (argc == 6) {
        joints[0].method = joints[w.segments + 1].method = RJ_METHOD_PENALTY;
        joints[0].penalty_k = joints[w.segments + 1].penalty_k = atof(argv[5]);
    }
    if (rj_model_create(&sc, &m, &err, NULL) != RJ_OK) {
        fprintf(stderr, "segmented: %s\n", err.msg);
        return 1;
    }
    if (rj_state_create(m, &s, NULL) != RJ_OK) return 1;
    cpu = time_runs(m, s);
    if (cpu < 0) {
        fprintf(stderr, "segmented: %s\n", rj_state_error(s));
        return 1;
    }
    printf("segments %d dt %.6g bound %.6g cpu_s %.4f lock1_s %.6f lock2_s %.6f\n", w.segments,
           rj_model_dt(m), rj_model_dt_bound(m), cpu, rj_joint_event_time(m, s, 0),
           rj_joint_event_time(m, s, w.segments + 1));
    rj_state_reset(m, s);
    w.out = fopen(argv[3], "w");
    if (!w.out) return 1;
    fputs("t,q1_deg,q2_deg,tip2_defl_m\n", w.out);
    rj_run(m, s, 6.0, 1e-3, sample, &w);
    if (fclose(w.out) != 0) return 1;
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
    return 0;
}
