/* Every joint's pin force at once (rj_joint_pin_forces) on a chain of n inextensible
   links of e elements each (0.1 m, hanging from the ground under gravity, released a
   little off the vertical), after 100 steps: a call's median time over 7 batches, each
   at least 20 ms, and a step's with and without the run's peaks tracked
   (rj_state_track_peaks, which takes every joint's pin force each step, as rj run does).
   The public API alone, so the same file builds against an older revjoint.h:
     build/pin_forces [N ...]     (default 10 50 200; E = 4)
     build/pin_forces -e E N ...  (E elements a link) */
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

/* The chain of n links of e elements, stepped 100 times. */
static rj_result chain(int n, int e, rj_model **m, rj_state **s)
{
    rj_link_def *L = (rj_link_def *)malloc(sizeof *L * (size_t)n);
    rj_joint_def *J = (rj_joint_def *)malloc(sizeof *J * (size_t)n);
    rj_scene_def sc = rj_default_scene_def();
    rj_error err;
    rj_result res;
    int i;
    if (!L || !J) abort();
    for (i = 0; i < n; i++) {
        L[i] = rj_default_link_def();
        L[i].length = 0.1; L[i].elements = e; L[i].fidelity = RJ_LINK_INEXTENSIBLE;
        J[i] = rj_default_joint_def();
        J[i].body1 = i - 1; J[i].body2 = i; J[i].angle0 = i ? rj_rad(181.0) : rj_rad(-80.0);
    }
    sc.links = L; sc.link_count = n; sc.joints = J; sc.joint_count = n;
    sc.solver.gravity[1] = -9.81;
    res = rj_model_create(&sc, m, &err, NULL);
    if (res != RJ_OK) fprintf(stderr, "pin_forces: %d links: %s\n", n, err.msg);
    if (res == RJ_OK) res = rj_state_create(*m, s, NULL);
    for (i = 0; res == RJ_OK && i < 100; i++) res = rj_step(*m, *s);
    free(L);
    free(J);
    return res;
}

/* batch calls of what: 0 rj_joint_pin_forces, 1 rj_step (peaks tracked or not, as
   the state is set); the seconds they took. */
static double run_batch(const rj_model *m, rj_state *s, double *forces, int what, int batch)
{
    double t0 = now();
    int i;
    for (i = 0; i < batch; i++) {
        if (what == 0) rj_joint_pin_forces(m, s, forces);
        else rj_step(m, s);
    }
    return now() - t0;
}

/* One call's median time over 7 batches, each at least 20 ms (or 2^24 calls). what: 0
   rj_joint_pin_forces, 1 rj_step, 2 rj_step with the peaks tracked. */
static double median_time(const rj_model *m, rj_state *s, double *forces, int what)
{
    double b[7];
    int batch = 1, r;
    rj_state_track_peaks(m, s, what == 2);
    while (run_batch(m, s, forces, what != 0, batch) < 0.02 && batch < 1 << 24) batch *= 2;
    for (r = 0; r < 7; r++) b[r] = run_batch(m, s, forces, what != 0, batch) / batch;
    rj_state_track_peaks(m, s, 0);
    qsort(b, 7, sizeof b[0], cmp_double);
    return b[3];
}

int main(int argc, char **argv)
{
    static const int sizes[] = { 10, 50, 200 };
    int first = 1, e = 4, count, i;
    if (argc > 2 && strcmp(argv[1], "-e") == 0) {
        e = atoi(argv[2]);
        first = 3;
    }
    count = argc > first ? argc - first : (int)(sizeof sizes / sizeof sizes[0]);
    printf("| links | nodes | rj_joint_pin_forces (us) | step (us) | step with peaks (us) |\n");
    printf("|---:|---:|---:|---:|---:|\n");
    for (i = 0; i < count; i++) {
        const int n = argc > first ? atoi(argv[first + i]) : sizes[i];
        rj_model *m = NULL;
        rj_state *s = NULL;
        double *forces, all, step, peaks;
        if (n < 1 || e < 1 || chain(n, e, &m, &s) != RJ_OK) continue;
        forces = (double *)malloc(sizeof(double) * 2 * (size_t)n);
        if (!forces) abort();
        all = median_time(m, s, forces, 0);
        step = median_time(m, s, forces, 1);
        peaks = median_time(m, s, forces, 2);
        printf("| %d | %d | %.4g | %.4g | %.4g |\n", n, n * (e + 1), 1e6 * all, 1e6 * step,
               1e6 * peaks);
        fflush(stdout);
        free(forces);
        rj_state_destroy(s, NULL);
        rj_model_destroy(m, NULL);
    }
    return 0;
}
