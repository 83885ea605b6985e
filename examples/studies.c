/* studies - the measurements behind two README statements, as a program:
   1. mesh convergence of the deployment's joint angles with the two joint reference modes
      (RJ_REF_TANGENT, the default, against the paper's RJ_REF_CHORD), 10/20/40 elements
      against 80, dt = 0.9 x the bound, t < 2.99 s (before joint 2 locks);
   2. the deployment with rigid links at dt = 1 and 2 ms: wall time of rj_run over 6 s
      without sampling (median of 21) and its error against the rigid reference
      examples/rigid2.h.
   About a minute and a half. */
#define _POSIX_C_SOURCE 200809L
#define REVJOINT_IMPLEMENTATION
#include "../revjoint.h"
#include "scenes.h"
#include "rigid2.h"
#include "cli.h"
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

static const char usage[] =
    "usage: studies\n"
    "  Prints the measurements behind two README statements: mesh convergence of the\n"
    "  deployment's joint angles, and the deployment with rigid links. No options.\n";

typedef struct hist { int n; double q1[8000], q2[8000]; } hist;
static int sample(const rj_model *m, const rj_state *s, void *u)
{
    hist *h = (hist *)u;
    if (h->n < 8000) { h->q1[h->n] = deploy_q1_deg(m, s); h->q2[h->n] = deploy_q2_deg(m, s); h->n++; }
    return 0;
}
static void rsample(const rigid2_sample *s, void *u)
{
    hist *h = (hist *)u;
    if (h->n < 8000) { h->q1[h->n] = rj_deg(s->q[0]); h->q2[h->n] = rj_deg(s->q[1]); h->n++; }
}
static double now(void) { struct timespec t; clock_gettime(CLOCK_MONOTONIC, &t); return t.tv_sec + 1e-9 * t.tv_nsec; }
static int cmpd(const void *a, const void *b) { double x = *(const double *)a, y = *(const double *)b; return x < y ? -1 : x > y; }

static double maxdev(const hist *a, const hist *b, int upto)
{
    double d = 0;
    int i;
    for (i = 0; i < upto && i < a->n && i < b->n; i++) {
        if (fabs(a->q1[i] - b->q1[i]) > d) d = fabs(a->q1[i] - b->q1[i]);
        if (fabs(a->q2[i] - b->q2[i]) > d) d = fabs(a->q2[i] - b->q2[i]);
    }
    return d;
}

int main(int argc, char **argv)
{
    static hist h[4];
    static const int els[4] = { 10, 20, 40, 80 };
    int mode, k;
    cli c;
    cli_out out;
    const char *a;
    /* no options: a mistyped one must not start the whole run unnoticed */
    c.argc = argc; c.argv = argv; c.i = 0; c.usage = usage;
    while ((a = cli_next(&c)) != NULL) {
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) { fputs(usage, stdout); return 0; }
        else cli_die(&c, "unknown option '%s'%s", a, "");
    }
    cli_open(&out, "studies", NULL);
    printf("1. deployment joint angles, max |q - q(80 elements)| before joint 2 locks (deg), dt = 0.9 x bound\n");
    printf("| reference | 10 el | 20 el | 40 el | ratios |\n|---|---:|---:|---:|---|\n");
    for (mode = 0; mode < 2; mode++) {
        double d[3];
        for (k = 0; k < 4; k++) {
            deploy_opts o = deploy_default_opts();
            rj_link_def L[2]; rj_joint_def J[2]; rj_scene_def sc; rj_model *m = NULL; rj_state *s = NULL; rj_error e;
            o.elements = els[k]; o.dt = 0;
            deploy_scene(&o, L, J, &sc);
            J[1].penalty_k = 1000; J[0].reference = J[1].reference = mode ? RJ_REF_CHORD : RJ_REF_TANGENT;
            if (rj_model_create(&sc, &m, &e, NULL) != RJ_OK) { fprintf(stderr, "studies: %s\n", e.msg); return 1; }
            rj_state_create(m, &s, NULL);
            h[k].n = 0;
            rj_run(m, s, 2.99, 1e-3, sample, &h[k]);
            rj_state_destroy(s, NULL); rj_model_destroy(m, NULL);
        }
        for (k = 0; k < 3; k++) d[k] = maxdev(&h[k], &h[3], 2990);
        printf("| %s | %.3f | %.3f | %.3f | %.2f, %.2f |\n", mode ? "chord (paper)" : "tangent (default)", d[0], d[1], d[2], d[0] / d[1], d[1] / d[2]);
        cli_put(&out, fflush(stdout));
    }
    /* a table that could not be written (a full disk): stop before the second study */
    if (ferror(stdout)) return cli_close(&out, "studies");
    for (k = 0; k < 2; k++) {
        deploy_opts o = deploy_default_opts();
        rj_link_def L[2]; rj_joint_def J[2]; rj_scene_def sc; rj_model *m = NULL; rj_state *s = NULL; rj_error e;
        rigid2_params p;
        static hist hr, hf;
        double lr[2], t[21], dev;
        int r;
        o.dt = k ? 2e-3 : 1e-3;   /* the issue: within 1e-3 deg at 1 ms "or more" */
        deploy_scene(&o, L, J, &sc);
        L[0].fidelity = L[1].fidelity = RJ_LINK_RIGID; L[0].elements = L[1].elements = 1;
        J[0].method = J[1].method = RJ_METHOD_MOMENTUM;
        if (rj_model_create(&sc, &m, &e, NULL) != RJ_OK) { fprintf(stderr, "studies: %s\n", e.msg); return 1; }
        rj_state_create(m, &s, NULL);
        for (r = 0; r < 21; r++) {
            double t0;
            rj_state_reset(m, s);
            t0 = now();
            rj_run(m, s, 6.0, 0, NULL, NULL);
            t[r] = now() - t0;
        }
        qsort(t, 21, sizeof t[0], cmpd);
        rj_state_reset(m, s);
        hf.n = 0;
        rj_run(m, s, 6.0, o.dt, sample, &hf);   /* one sample per step, the reference at the same times */
        rigid2_default_params(&p);
        hr.n = 0;
        rigid2_run(&p, 6.0, o.dt, rsample, &hr, lr);
        dev = maxdev(&hf, &hr, (int)(lr[1] / o.dt) - 1);
        printf("%s2. deployment with rigid links, dt %g ms, 6 s: %.2f ms (median of 21, rj_run without sampling; fastest %.2f); "
               "max |q - q_rigid2| before joint 2 locks %.2g deg; locks %.4f / %.4f s (rigid2 %.6f / %.6f s)\n",
               k ? "" : "\n", 1e3 * o.dt, 1e3 * t[10], 1e3 * t[0], dev, rj_joint_event_time(m, s, 1), rj_joint_event_time(m, s, 0), lr[1], lr[0]);
        rj_state_destroy(s, NULL); rj_model_destroy(m, NULL);
    }
    /* the tables must have reached standard output */
    return cli_close(&out, "studies");
}
