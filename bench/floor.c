/* floor.c - how fast the step's arithmetic alone can go on this machine: the element and
   node update of revjoint.h's beam pass (the same operations per element, 4-lane vectors,
   chunks of 128) for one uniform free link, with nothing else: no joints, no end nodes of
   their own, no energy, no step bookkeeping. Two variants of the same arithmetic:
     in place        every array is read and written where it is (9 arrays per node)
     double-buffered the results go to a second set of arrays, swapped each step (18), as
                     revjoint.h's step with solver.in_place off
   and, alternately with them, revjoint.h's own rj_step on that link (solver.energy_every
   16, in_place ON), to say how far the library is from its arithmetic alone.
   It measured the gap that led to solver.in_place (README, "Step cost"). Not part of make
   test or make bench; x86-64 with AVX2:
     cc -std=gnu99 -O2 -mavx2 -ffp-contract=off bench/floor.c -o build/floor -lm
     build/floor N [blocks]     prints min and median ns per element-step over the blocks
   (about 2 ms each), in place and double-buffered alternately, for a link of N elements
   (N a multiple of 4) at revjoint.h's stability bound for it, and the clock rate, from a
   chain of dependent 64-bit multiplies (3 cycles each on current x86 cores).
     build/floor paper [blocks] the same for the deployment at the paper's settings (paper sec. 5:
                                two links of 10 elements, dt = 7.5 us): the arithmetic for its
                                two links (where 4 does not divide 10: in place, whole lanes
                                then a scalar tail; double-buffered, the last 4 again, as
                                revjoint.h's passes do) against rj_step on the deployment (solver.energy_every
                                16, joints and all), alternately, in blocks that together take
                                the paper's 800 000 steps; prints ns per step and the seconds
                                the 800 000 steps took. */
#define _POSIX_C_SOURCE 199309L
#define REVJOINT_IMPLEMENTATION
#include "../revjoint.h"
#include "../examples/scenes.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

typedef double vd __attribute__((vector_size(32)));
typedef long long vl __attribute__((vector_size(32)));
#define LD(v, p) memcpy(&(v), (p), 32)
#define ST(p, v) memcpy((p), &(v), 32)
#define CH 128
#define FR (CH + 2)

typedef struct arrays { double *x, *y, *p, *vx, *vy, *w, *b, *cx, *cy; } arrays;
typedef struct link { int ne; arrays a, o; double kb, kax, l0sq, h, ti, ri, dt; } link;

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}
/* GHz from a chain of dependent multiplies, best of 5 runs of 2e8 */
static double clock_ghz(void)
{
    double best = 0;
    int r;
    for (r = 0; r < 5; r++) {
        volatile unsigned long long seed = 3;
        unsigned long long x = seed;
        long i;
        const double a = now();
        for (i = 0; i < 50000000L; i++) __asm__ volatile("imul %0, %0\n\timul %0, %0\n\timul %0, %0\n\timul %0, %0" : "+r"(x));
        {
            const double t = now() - a, g = 3.0 * 2e8 / t / 1e9;
            if (g > best) best = g;
        }
        seed = x;
    }
    return best;
}
static int cmp(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* One step: in place (dbl 0) or into L->o, then swapped (dbl 1). Where 4 does not divide
   the count, in place ends with a scalar tail and double-buffered with the last 4 elements
   (nodes) again, from the same inputs (the loop conditions' second half). Returns nonzero when a
   chord turned too far for the series (revjoint.h would take its exact path). */
static int step(link *L, int dbl)
{
    double FB[4 * FR], *FX = FB, *FY = FB + FR, *M1 = FB + 2 * FR, *M2 = FB + 3 * FR;
    const double kb = L->kb, kax = L->kax, l0sq = L->l0sq, h = L->h, dt = L->dt, ti = L->ti, ri = L->ri;
    const arrays *A = &L->a, *O = dbl ? &L->o : &L->a;
    int c0, k, bad = 0;
    FX[0] = FY[0] = -0.0; M1[0] = M2[0] = 0;
    for (c0 = 0; c0 < L->ne; c0 += CH) {
        const int nc = L->ne - c0 < CH ? L->ne - c0 : CH, last = c0 + nc == L->ne, cnt = nc + last;
        const double *x = A->x + c0, *y = A->y + c0, *p = A->p + c0, *b = A->b + c0, *cx = A->cx + c0, *cy = A->cy + c0;
        const double *vx = A->vx + c0, *vy = A->vy + c0, *w = A->w + c0;
        double *ox = O->x + c0, *oy = O->y + c0, *op = O->p + c0, *ob = O->b + c0, *ocx = O->cx + c0, *ocy = O->cy + c0;
        double *ovx = O->vx + c0, *ovy = O->vy + c0, *ow = O->w + c0;
        vl okv = { -1, -1, -1, -1 };
        int i;
        for (i = 0; i + 4 <= nc || (dbl && i < nc && nc >= 4 && (i = nc - 4, 1)); i += 4) {
            vd x0, x1, y0, y1, p0, p1, bb, ccx, ccy, ex, ey;
            LD(x0, x + i); LD(x1, x + i + 1); LD(y0, y + i); LD(y1, y + i + 1); LD(p0, p + i); LD(p1, p + i + 1);
            LD(bb, b + i); LD(ccx, cx + i); LD(ccy, cy + i);
            ex = x1 - x0; ey = y1 - y0;
            {
                const vd cr = ccx * ey - ccy * ex, dp = ccx * ex + ccy * ey, L2 = ex * ex + ey * ey, inv = 1.0 / (dp * L2);
                const vd r = cr * L2 * inv, invL2 = dp * inv, r2 = r * r;
                const vd bt = bb + r * (1.0 - r2 * (1.0 / 3.0 - r2 * (1.0 / 5.0)));
                const vd tha = p0 - bt, thb = p1 - bt, ma = kb * (4.0 * tha + 2.0 * thb), mb = kb * (2.0 * tha + 4.0 * thb);
                const vd eps = (L2 - l0sq) * h, nax = kax * eps, sv = (ma + mb) * invL2;
                const vd fx = -nax * ex - sv * ey, fy = -nax * ey + sv * ex;
                okv &= (r2 < 4e-6) & (dp > 0.0);
                ST(ob + i, bt); ST(ocx + i, ex); ST(ocy + i, ey);
                ST(FX + 1 + i, fx); ST(FY + 1 + i, fy); ST(M1 + 1 + i, ma); ST(M2 + 1 + i, mb);
            }
        }
        for (; i < nc; i++) {   /* the scalar tail (the paper's links of 10) */
            const double ex = x[i + 1] - x[i], ey = y[i + 1] - y[i];
            const double cr = cx[i] * ey - cy[i] * ex, dp = cx[i] * ex + cy[i] * ey, L2 = ex * ex + ey * ey, inv = 1.0 / (dp * L2);
            const double r = cr * L2 * inv, invL2 = dp * inv, r2 = r * r;
            const double bt = b[i] + r * (1.0 - r2 * (1.0 / 3.0 - r2 * (1.0 / 5.0)));
            const double tha = p[i] - bt, thb = p[i + 1] - bt, ma = kb * (4.0 * tha + 2.0 * thb), mb = kb * (2.0 * tha + 4.0 * thb);
            const double eps = (L2 - l0sq) * h, nax = kax * eps, sv = (ma + mb) * invL2;
            bad |= !(r2 < 4e-6) | !(dp > 0.0);
            ob[i] = bt; ocx[i] = ex; ocy[i] = ey;
            FX[1 + i] = -nax * ex - sv * ey; FY[1 + i] = -nax * ey + sv * ex; M1[1 + i] = ma; M2[1 + i] = mb;
        }
        for (k = 0; k < 4; k++) bad |= !okv[k];
        if (last) FX[nc + 1] = FY[nc + 1] = M1[nc + 1] = 0;
        for (k = 0; k + 4 <= cnt || (dbl && k < cnt && cnt >= 4 && (k = cnt - 4, 1)); k += 4) {
            vd f0, f1, g0, g1, m1, m2, fxv, fyv, mzv, v1, v2, v3, t;
            LD(f0, FX + k); LD(f1, FX + k + 1); LD(g0, FY + k); LD(g1, FY + k + 1); LD(m2, M2 + k); LD(m1, M1 + k + 1);
            fxv = f0 - f1; fyv = g0 - g1; mzv = -m2 - m1;
            LD(v1, vx + k); LD(v2, vy + k); LD(v3, w + k);
            v1 = v1 + dt * fxv * ti; v2 = v2 + dt * fyv * ti; v3 = v3 + dt * mzv * ri;
            ST(ovx + k, v1); ST(ovy + k, v2); ST(ow + k, v3);
            LD(t, x + k); t = t + dt * v1; ST(ox + k, t);
            LD(t, y + k); t = t + dt * v2; ST(oy + k, t);
            LD(t, p + k); t = t + dt * v3; ST(op + k, t);
        }
        for (; k < cnt; k++) {
            const double fxv = FX[k] - FX[k + 1], fyv = FY[k] - FY[k + 1], mzv = -M2[k] - M1[k + 1];
            ovx[k] = vx[k] + dt * fxv * ti; ovy[k] = vy[k] + dt * fyv * ti; ow[k] = w[k] + dt * mzv * ri;
            ox[k] = x[k] + dt * ovx[k]; oy[k] = y[k] + dt * ovy[k]; op[k] = p[k] + dt * ow[k];
        }
        FX[0] = FX[nc]; FY[0] = FY[nc]; M1[0] = M1[nc]; M2[0] = M2[nc];
    }
    if (dbl) { arrays t = L->a; L->a = L->o; L->o = t; }
    return bad;
}

/* One variant's arrays for link l of model m, from the model's initial state. */
static int setup(link *L, const rj_model *m, int l)
{
    const int n0 = m->link_first[l], e0 = m->link_efirst[l], N = m->link_efirst[l + 1] - e0;
    double *mem = (double *)calloc(18 * (size_t)(N + 8), sizeof(double));
    double **pa[9], **po[9];
    int i;
    if (!mem) return 0;
    pa[0] = &L->a.x; pa[1] = &L->a.y; pa[2] = &L->a.p; pa[3] = &L->a.vx; pa[4] = &L->a.vy; pa[5] = &L->a.w; pa[6] = &L->a.b; pa[7] = &L->a.cx; pa[8] = &L->a.cy;
    po[0] = &L->o.x; po[1] = &L->o.y; po[2] = &L->o.p; po[3] = &L->o.vx; po[4] = &L->o.vy; po[5] = &L->o.w; po[6] = &L->o.b; po[7] = &L->o.cx; po[8] = &L->o.cy;
    for (i = 0; i < 9; i++) { *pa[i] = mem + (size_t)i * (N + 8); *po[i] = mem + (size_t)(9 + i) * (N + 8); }
    L->ne = N;
    L->kb = m->link_kc[4 * l]; L->kax = m->link_kc[4 * l + 1]; L->l0sq = m->link_kc[4 * l + 2]; L->h = m->link_kc[4 * l + 3];
    L->ti = m->link_un[5 * l]; L->ri = m->link_un[5 * l + 1]; L->dt = rj_model_dt(m);
    for (i = 0; i <= N; i++) {
        L->a.x[i] = m->x0[n0 + i]; L->a.y[i] = m->y0[n0 + i]; L->a.p[i] = m->phi0[n0 + i];
        L->a.vx[i] = m->vx0[n0 + i]; L->a.vy[i] = m->vy0[n0 + i]; L->a.w[i] = m->w0[n0 + i];
    }
    for (i = 0; i < N; i++) {
        L->a.b[i] = m->beta0[e0 + i]; L->a.cx[i] = m->x0[n0 + i + 1] - m->x0[n0 + i]; L->a.cy[i] = m->y0[n0 + i + 1] - m->y0[n0 + i];
    }
    return 1;
}

int main(int argc, char **argv)
{
    const int paper = argc > 1 && !strcmp(argv[1], "paper");
    const int N = paper ? 20 : argc > 1 ? atoi(argv[1]) : 2000, B = argc > 2 ? atoi(argv[2]) : paper ? 101 : 201;
    const int nl = paper ? 2 : 1;
    rj_link_def ld = rj_default_link_def();
    rj_scene_def sc = rj_default_scene_def();
    deploy_opts o = deploy_default_opts();
    rj_model *m = NULL;
    rj_error err;
    link L[2][2];
    rj_model *ml = NULL;
    rj_state *sl;
    double *t[3], tot[3] = { 0, 0, 0 }, tip[2];
    long K, k;
    int v, b, l;
    if ((!paper && (N < 4 || N % 4)) || B < 1 || B > 100000) { fprintf(stderr, "usage: floor N [blocks]  (N a multiple of 4) | floor paper [blocks]\n"); return 2; }
    if (paper) {
        /* the deployment (examples/scenes.h), energy accounts every 16 steps; the floor uses
           its links' constants, dt and initial state */
        o.energy_every = 16;
        if (deploy_build(&o, &ml, &err) != RJ_OK) { fprintf(stderr, "floor: %s\n", err.msg); return 1; }
        m = ml;
    } else {
        /* the bench's free link (BENCHMARKS.md section 1), for its constants and dt */
        ld.height = 0.01; ld.elements = N; ld.omega = 1.0;
        sc.links = &ld; sc.link_count = 1;
        if (rj_model_create(&sc, &m, &err, NULL) != RJ_OK) { fprintf(stderr, "floor: %s\n", err.msg); return 1; }
        sc.solver.energy_every = 16; sc.solver.in_place = RJ_IN_PLACE_ON;
        if (rj_model_create(&sc, &ml, &err, NULL) != RJ_OK) { fprintf(stderr, "floor: %s\n", err.msg); return 1; }
    }
    if (rj_state_create(ml, &sl, NULL) != RJ_OK) return 1;
    t[2] = (double *)malloc(sizeof(double) * (size_t)B);
    if (!t[2]) return 1;
    for (v = 0; v < 2; v++) {
        for (l = 0; l < nl; l++) if (!setup(&L[v][l], m, l)) return 1;
        t[v] = (double *)malloc(sizeof(double) * (size_t)B);
        if (!t[v]) return 1;
    }
    /* blocks of about 2 ms; for the paper, blocks that add up to its 800 000 steps (the
       library's run is the paper's run, timed in pieces) */
    K = paper ? 800000 / B : 200000 / N + 1;
    if (!paper) {   /* warm-up */
        for (v = 0; v < 2; v++)
            for (k = 0; k < K; k++)
                if (step(&L[v][0], v)) { fprintf(stderr, "floor: a chord turned too far (step %ld)\n", k); return 1; }
        for (k = 0; k < K; k++) if (rj_step(ml, sl) != RJ_OK) { fprintf(stderr, "floor: %s\n", rj_state_error(sl)); return 1; }
    }
    for (b = 0; b < B; b++)
        for (v = 0; v < 3; v++) {
            const double a = now();
            double e;
            int bad = 0;
            if (v < 2) for (k = 0; k < K; k++) for (l = 0; l < nl; l++) bad |= step(&L[v][l], v);
            else for (k = 0; k < K; k++) bad |= rj_step(ml, sl) != RJ_OK;
            e = now() - a;
            t[v][b] = e * 1e9 / ((double)K * (paper ? 1 : N));
            tot[v] += e;
            if (bad) { fprintf(stderr, "floor: %s\n", v < 2 ? "a chord turned too far" : rj_state_error(sl)); return 1; }
        }
    for (v = 0; v < 3; v++) qsort(t[v], (size_t)B, sizeof(double), cmp);
    for (v = 0; v < 2; v++) tip[v] = L[v][nl - 1].a.y[L[v][nl - 1].ne];
    if (paper)
        printf("paper's settings (2 links of 10 elements, dt %.3g s), %d blocks of %ld steps (%ld in all, %.4g s simulated):\n"
               "  arithmetic in place: min %.1f median %.1f ns per step, %.3f s in all; double-buffered: min %.1f median %.1f, %.3f s (tip y %.9g, %.9g)\n"
               "  rj_step (energy_every 16): min %.1f median %.1f ns per step, %.3f s in all (t = %.6f s); clock %.2f GHz\n",
               rj_model_dt(ml), B, K, B * K, rj_state_time(sl), t[0][0], t[0][B / 2], tot[0], t[1][0], t[1][B / 2], tot[1], tip[0], tip[1],
               t[2][0], t[2][B / 2], tot[2], rj_state_time(sl), clock_ghz());
    else
        printf("%d elements, %d blocks of %ld steps: in place min %.2f median %.2f ns per element-step; double-buffered min %.2f median %.2f (tip y %.9g, %.9g); "
               "rj_step in place min %.2f median %.2f; clock %.2f GHz\n",
               N, B, K, t[0][0], t[0][B / 2], t[1][0], t[1][B / 2], tip[0], tip[1], t[2][0], t[2][B / 2], clock_ghz());
    free(t[2]); rj_state_destroy(sl, NULL);
    for (v = 0; v < 2; v++) {
        for (l = 0; l < nl; l++) free(L[v][l].a.x < L[v][l].o.x ? L[v][l].a.x : L[v][l].o.x);
        free(t[v]);
    }
    if (m != ml) rj_model_destroy(m, NULL);
    rj_model_destroy(ml, NULL);
    return 0;
}
