/* Where the rigid solvers cross: a chain of n rigid links (0.1 m, hanging from the ground
   under gravity, every joint a spring, with friction on every joint or none) stepped by
   the dense mass matrix and its Cholesky factor and by articulated bodies, on the same
   model (the internal switch m->rig_tree, flipped after the build). Prints a step's
   median time of 7 batches for each, and the build with the library's own choice.
     build/rigid_cross [N ...]     (default 2 4 8 12 16 24 32 64 128 256 1000)
   With --memory, the memory of the library's choice instead: rj_model_size and
   rj_state_size of the chain bare, with friction on every joint and with a latch (a
   limit by momentum) on every joint.
     build/rigid_cross --memory [N ...]     (default 100 1000 10000) */
#define _POSIX_C_SOURCE 199309L
#define REVJOINT_IMPLEMENTATION
#include "../revjoint.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static int cmp_double(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The chain of n links; on every joint, by kind: nothing more (0), friction (1), or a
   latch (2: a reverse limit 30 deg back, by momentum, e = 0.5). Its rj_model_size into
   *bytes when bytes is not NULL. */
static rj_result chain(int n, int kind, rj_model **m, double *build_s, size_t *bytes)
{
    rj_link_def *L = (rj_link_def *)malloc(sizeof *L * (size_t)n);
    rj_joint_def *J = (rj_joint_def *)malloc(sizeof *J * (size_t)n);
    rj_scene_def sc = rj_default_scene_def();
    rj_error err;
    rj_result res;
    double t0;
    int i;
    if (!L || !J) abort();
    for (i = 0; i < n; i++) {
        L[i] = rj_default_link_def();
        L[i].length = 0.1; L[i].elements = 1; L[i].fidelity = RJ_LINK_RIGID;
        J[i] = rj_default_joint_def();
        J[i].body1 = i - 1; J[i].body2 = i; J[i].angle0 = i ? rj_rad(185.0) : rj_rad(-60.0);
        J[i].spring_k = 1.0; J[i].spring_free_angle = i ? rj_rad(180.0) : rj_rad(-90.0);
        J[i].friction = kind == 1 ? 1e-3 : 0.0;
        if (kind == 2) {
            J[i].has_reverse = 1; J[i].reverse = i ? rj_rad(155.0) : rj_rad(270.0);
            J[i].method = RJ_METHOD_MOMENTUM; J[i].restitution = 0.5;
        }
    }
    sc.links = L; sc.link_count = n; sc.joints = J; sc.joint_count = n;
    sc.solver.gravity[1] = -9.81; sc.solver.dt = 1e-4;
    if (bytes)
        *bytes = rj_model_size(&sc, &err);
    t0 = now();
    res = rj_model_create(&sc, m, &err, NULL);
    *build_s = now() - t0;
    if (res != RJ_OK) fprintf(stderr, "rigid_cross: %d links: %s\n", n, err.msg);
    free(L);
    free(J);
    return res;
}

/* A step's median time over 7 batches, each at least 5 ms (or one step). */
static double step_time(const rj_model *m)
{
    rj_state *s = NULL;
    double b[7];
    int batch = 1, r, i;
    if (rj_state_create(m, &s, NULL) != RJ_OK) return 0;
    for (;;) {
        double t0 = now();
        for (i = 0; i < batch; i++) rj_step(m, s);
        if (now() - t0 >= 0.005 || batch >= 1 << 20) break;
        batch *= 2;
    }
    for (r = 0; r < 7; r++) {
        double t0 = now();
        for (i = 0; i < batch; i++) rj_step(m, s);
        b[r] = (now() - t0) / batch;
    }
    rj_state_destroy(s, NULL);
    qsort(b, 7, sizeof b[0], cmp_double);
    return b[3];
}

/* The chain's model and state bytes: bare, with friction on every joint, with a latch on
   every joint. */
static void memory_row(int n)
{
    static const char *const names[3] = { "none", "friction, every joint", "latch, every joint" };
    int kind;
    for (kind = 0; kind < 3; kind++) {
        rj_model *m = NULL;
        double build_s, model, state;
        size_t bytes = 0;
        if (n < 1 || chain(n, kind, &m, &build_s, &bytes) != RJ_OK) continue;
        model = (double)bytes;
        state = (double)rj_state_size(m);
        printf("| %d | %s | %.0f | %.0f | %.0f | %.0f |\n", n, names[kind], model, state,
               model + state, (model + state) / n);
        fflush(stdout);
        rj_model_destroy(m, NULL);
    }
}

static int memory_table(int argc, char **argv)
{
    static const int sizes[] = { 100, 1000, 10000 };
    const int count = argc > 2 ? argc - 2 : (int)(sizeof sizes / sizeof sizes[0]);
    int i;
    printf("| links | joints | model bytes | state bytes | total | per link |\n");
    printf("|---:|---|---:|---:|---:|---:|\n");
    for (i = 0; i < count; i++)
        memory_row(argc > 2 ? atoi(argv[i + 2]) : sizes[i]);
    return 0;
}

int main(int argc, char **argv)
{
    static const int sizes[] = { 2, 4, 8, 12, 16, 24, 32, 64, 128, 256, 1000 };
    const int count = argc > 1 ? argc - 1 : (int)(sizeof sizes / sizeof sizes[0]);
    int i, friction;
    if (argc > 1 && !strcmp(argv[1], "--memory"))
        return memory_table(argc, argv);
    printf("| links | friction | dense step (us) | articulated step (us) | dense / articulated | build (ms), the library's choice |\n");
    printf("|---:|---|---:|---:|---:|---:|\n");
    for (i = 0; i < count; i++) {
        const int n = argc > 1 ? atoi(argv[i + 1]) : sizes[i];
        for (friction = 0; friction < 2; friction++) {
            rj_model *m = NULL;
            double build_s, dense, tree;
            int chosen;
            if (n < 1 || chain(n, friction, &m, &build_s, NULL) != RJ_OK) continue;
            chosen = m->rig_tree;
            m->rig_tree = 0;
            dense = n <= 256 ? step_time(m) : 0;
            m->rig_tree = 1;
            tree = step_time(m);
            m->rig_tree = chosen;
            if (dense > 0)
                printf("| %d | %s | %.3g | %.3g | %.2f | %.3g |\n", n, friction ? "every joint" : "none",
                       1e6 * dense, 1e6 * tree, dense / tree, 1e3 * build_s);
            else
                printf("| %d | %s | (not run) | %.3g | | %.3g |\n", n, friction ? "every joint" : "none",
                       1e6 * tree, 1e3 * build_s);
            fflush(stdout);
            rj_model_destroy(m, NULL);
        }
    }
    return 0;
}
