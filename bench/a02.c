/* a02.c - the IFToMM multibody benchmark A02, the N four-bar mechanism, in joint
   coordinates: 2N + 1 rigid bars of 1 m and 1 kg under gravity, the cranks upright at
   the start and the first crank's tip B0 moving at 1 m/s in x; every crank turns as the
   first (parallelogram windows), so B0's exact motion is one pendulum's. Prints the
   largest |B0 x - exact| over the run against the benchmark's tolerance (1e-3 m) and the
   CPU time of the run (the median of three).
     build/a02 [N [DT [T_END]]]      defaults 40, 1e-3 s, 20 s (the benchmark's) */
#define REVJOINT_IMPLEMENTATION
#include "../revjoint.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <math.h>
#include <time.h>

#define PI 3.14159265358979323846

/* The scene: N + 1 cranks c0..cN on the ground line, N couplers k1..kN between their
   tips, each window's loop closed by joint b_i at crank c_i's tip. */
static size_t scene_text(int N, double dt, char *text, size_t n)
{
    size_t at = 0;
    int i;
    at += (size_t) snprintf(text + at, n - at,
                            "solver\n  dt = %g\n  gravity = 0 -9.81\n"
                            "section bar\n  width = 0.01  height = 0.01\n", dt);
    for (i = 0; i <= N; i++)
        at += (size_t) snprintf(text + at, n - at, "link c%d\n  length = 1  elements = 1  "
                                "rho = 10000  section = bar  fidelity = rigid\n", i);
    for (i = 1; i <= N; i++)
        at += (size_t) snprintf(text + at, n - at, "link k%d\n  length = 1  elements = 1  "
                                "rho = 10000  section = bar  fidelity = rigid\n", i);
    at += (size_t) snprintf(text + at, n - at,
                            "joint g0\n  body1 = ground  body2 = c0  angle0 = 90 deg  rate0 = -1\n");
    for (i = 1; i <= N; i++)
        at += (size_t) snprintf(text + at, n - at,
                                "joint a%d\n  body1 = c%d  body2 = k%d  angle0 = 90 deg  rate0 = 1\n"
                                "joint g%d\n  body1 = ground  body2 = c%d  ground_x = %d  "
                                "angle0 = 90 deg  rate0 = -1\n"
                                "joint b%d\n  body1 = k%d  body2 = c%d  node2 = last  "
                                "angle0 = 270 deg\n",
                                i, i - 1, i, i, i, i, i, i, i);
    return at;
}

/* The exact crank angle's acceleration. */
static double accel(int N, double th)
{
    return -9.81 * cos(th) * ((N + 1) / 2.0 + N) / ((N + 1) / 3.0 + N);
}

/* One run: its CPU seconds; the largest B0 error into *err. */
static double run(const rj_model *m, int N, double t_end, double *err)
{
    rj_state *s = NULL;
    double th = PI / 2, w = -1, dt = rj_model_dt(m), cpu;
    clock_t start;
    *err = 0;
    rj_state_create(m, &s, NULL);
    start = clock();
    while (rj_state_time(s) < t_end - 0.5 * dt) {
        const double k1 = accel(N, th), k2 = accel(N, th + dt / 2 * w);
        const double k3 = accel(N, th + dt / 2 * (w + dt / 2 * k1));
        const double k4 = accel(N, th + dt * (w + dt / 2 * k2));
        double b0[2];
        if (rj_step(m, s) != RJ_OK) {
            fprintf(stderr, "a02: %s\n", rj_state_error(s));
            *err = HUGE_VAL;
            break;
        }
        th += dt * (w + dt * (k1 + k2 + k3) / 6);
        w += dt * (k1 + 2 * k2 + 2 * k3 + k4) / 6;
        rj_node_position(m, s, 0, 1, b0);
        *err = fmax(*err, fabs(b0[0] - cos(th)));
    }
    cpu = (double) (clock() - start) / CLOCKS_PER_SEC;
    rj_state_destroy(s, NULL);
    return cpu;
}

int main(int argc, char **argv)
{
    const int N = argc > 1 ? atoi(argv[1]) : 40;
    const double dt = argc > 2 ? atof(argv[2]) : 1e-3, t_end = argc > 3 ? atof(argv[3]) : 20;
    static char text[256 * 1024];
    rj_scene_file f;
    rj_scene_def d;
    rj_model *m = NULL;
    rj_error e;
    double cpu[3], err = 0, t;
    int k;
    if (N < 1 || N > 500 || !(dt > 0) || !(t_end > 0)) {
        fprintf(stderr, "usage: a02 [N 1..500 [DT [T_END]]]\n");
        return 2;
    }
    scene_text(N, dt, text, sizeof text);
    if (rj_scene_parse(text, strlen(text), "a02.rjs", &f, &e) != RJ_OK) {
        fprintf(stderr, "a02: %s\n", e.msg);
        return 1;
    }
    d = rj_scene_file_def(&f);
    if (rj_model_create(&d, &m, &e, NULL) != RJ_OK) {
        fprintf(stderr, "a02: %s\n", e.msg);
        return 1;
    }
    for (k = 0; k < 3; k++)
        cpu[k] = run(m, N, t_end, &err);
    /* the median of three */
    t = cpu[0] + cpu[1] + cpu[2] - fmax(cpu[0], fmax(cpu[1], cpu[2])) -
        fmin(cpu[0], fmin(cpu[1], cpu[2]));
    printf("A02, N = %d (%d bars, %d loops), dt %g s, %g s: max |B0 x - exact| %.3g m "
           "(tolerance 1e-3 m: %s); CPU %.3f s (median of 3; %.0f us a step)\n",
           N, 2 * N + 1, N, dt, t_end, err, err < 1e-3 ? "within" : "beyond", t,
           1e6 * t * dt / t_end);
    rj_model_destroy(m, NULL);
    rj_scene_file_free(&f);
    return err < 1e-3 ? 0 : 1;
}
