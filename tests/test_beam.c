/* Link model against beam theory: cantilever bending frequencies (Euler-Bernoulli), axial
   wave speed sqrt(E/rho), static tip deflection F L^3 / 3EI, and the stability bound. */
#include "../revjoint.h"
#include "rjt.h"
#include <stdlib.h>
#include <string.h>

/* dense symmetric eigenvalues by cyclic Jacobi */
static void jacobi(double *A, int n, double *ev)
{
    int sweep, p, q, k;
    for (sweep = 0; sweep < 100; sweep++) {
        double off = 0;
        for (p = 0; p < n; p++) for (q = p + 1; q < n; q++) off += A[p * n + q] * A[p * n + q];
        if (off < 1e-22) break;
        for (p = 0; p < n; p++) for (q = p + 1; q < n; q++) {
            double apq = A[p * n + q], app, aqq, th, t, c, s;
            if (fabs(apq) < 1e-300) continue;
            app = A[p * n + p]; aqq = A[q * n + q];
            th = (aqq - app) / (2 * apq);
            t = (th >= 0 ? 1.0 : -1.0) / (fabs(th) + sqrt(th * th + 1));
            c = 1 / sqrt(t * t + 1); s = t * c;
            for (k = 0; k < n; k++) {
                double akp = A[k * n + p], akq = A[k * n + q];
                A[k * n + p] = c * akp - s * akq; A[k * n + q] = s * akp + c * akq;
            }
            for (k = 0; k < n; k++) {
                double apk = A[p * n + k], aqk = A[q * n + k];
                A[p * n + k] = c * apk - s * aqk; A[q * n + k] = s * apk + c * aqk;
            }
        }
    }
    for (p = 0; p < n; p++) ev[p] = A[p * n + p];
}
static int cmpd(const void *a, const void *b) { double x = *(const double *)a, y = *(const double *)b; return x < y ? -1 : x > y; }

static rj_model *cantilever(int ne, double h)
{
    rj_link_def L = rj_default_link_def();
    rj_scene_def sc = rj_default_scene_def();
    rj_model *m; rj_error err;
    L.root = RJ_ROOT_CLAMPED; L.elements = ne; L.height = h; L.width = 0.05; L.length = 1.0;
    sc.links = &L; sc.link_count = 1;
    if (rj_model_create(&sc, &m, &err, NULL) != RJ_OK) { printf("build failed: %s\n", err.msg); exit(1); }
    return m;
}

/* sorted omega^2 of the linearised model; returns count of nonzero */
static int spectrum(const rj_model *m, double *om2)
{
    int n = 3 * rj_model_node_count(m), i, j, k = 0;
    double *A = (double *)calloc((size_t)n * n, sizeof(double)), *u = (double *)calloc((size_t)n, sizeof(double));
    double *o = (double *)calloc((size_t)n, sizeof(double)), *w = (double *)calloc(rj_model_work_size(m), sizeof(double));
    double *ev = (double *)calloc((size_t)n, sizeof(double)), mx = 0;
    for (j = 0; j < n; j++) {
        u[j] = 1; rj_model_apply_stiffness(m, u, o, w); u[j] = 0;
        for (i = 0; i < n; i++) A[i * n + j] = o[i];
    }
    for (i = 0; i < n; i++) for (j = i + 1; j < n; j++) { double a = 0.5 * (A[i * n + j] + A[j * n + i]); A[i * n + j] = A[j * n + i] = a; }
    jacobi(A, n, ev);
    qsort(ev, (size_t)n, sizeof(double), cmpd);
    for (i = 0; i < n; i++) if (fabs(ev[i]) > mx) mx = fabs(ev[i]);
    for (i = 0; i < n; i++) if (ev[i] > 1e-9 * mx) om2[k++] = ev[i];
    free(A); free(u); free(o); free(w); free(ev);
    return k;
}

int main(void)
{
    rjt_ctx c = { 0, 0 };
    static const double bl[3] = { 1.87510406871196, 4.69409113297418, 7.85475743823761 };
    double E = 70e9, rho = 2710, h = 0.01, A = 0.05 * h, I = 0.05 * h * h * h / 12;
    double om2[200], err10[3], err20[3], err40[3];
    int ne, k, n;
    char name[96];
    for (ne = 10; ne <= 40; ne *= 2) {
        rj_model *m = cantilever(ne, h);
        n = spectrum(m, om2);
        for (k = 0; k < 3 && k < n; k++) {
            double th = bl[k] * bl[k] * sqrt(E * I / (rho * A));
            double e = sqrt(om2[k]) / th - 1;
            if (ne == 10) err10[k] = e; else if (ne == 20) err20[k] = e; else err40[k] = e;
        }
        /* Lanczos bound agrees with the dense largest eigenvalue */
        snprintf(name, sizeof name, "omega_max Lanczos vs dense, %d elements", ne);
        rjt_check(&c, fabs(rj_model_omega_max(m) / sqrt(om2[n - 1]) - 1) < 1e-4, name, "Lanczos %.8g dense %.8g rad/s", rj_model_omega_max(m), sqrt(om2[n - 1]));
        rj_model_destroy(m, NULL);
    }
    rjt_check(&c, fabs(err10[0]) < 0.01, "cantilever mode 1 at 10 elements within 1%", "error %+.4f%%", 100 * err10[0]);
    for (k = 0; k < 3; k++) {
        snprintf(name, sizeof name, "cantilever mode %d at 20 elements within 1%%", k + 1);
        rjt_check(&c, fabs(err20[k]) < 0.01, name, "error %+.4f%% (10 el: %+.4f%%)", 100 * err20[k], 100 * err10[k]);
    }
    for (k = 0; k < 3; k++) {
        double ratio = err10[k] / err20[k], ratio2 = err20[k] / err40[k];
        snprintf(name, sizeof name, "mode %d error falls at second order", k + 1);
        rjt_check(&c, ratio > 3.0 && ratio < 5.5 && ratio2 > 3.0 && ratio2 < 5.5, name, "err10/err20 = %.2f, err20/err40 = %.2f (4 = second order)", ratio, ratio2);
    }
    /* axial: first clamped-free mode pi/2 c/L; identify it as the eigenvalue nearest */
    {
        rj_model *m = cantilever(20, h);
        double th = 0.5 * 3.14159265358979 * sqrt(E / rho), best = 1e300;
        n = spectrum(m, om2);
        for (k = 0; k < n; k++) if (fabs(sqrt(om2[k]) - th) < fabs(best - th)) best = sqrt(om2[k]);
        rjt_check(&c, fabs(best / th - 1) < 0.01, "axial mode 1 = (pi/2) sqrt(E/rho)/L within 1% at 20 elements", "got %.6g want %.6g rad/s (%+.3f%%)", best, th, 100 * (best / th - 1));
        /* stability bound is the axial Courant limit for a slender link: dt = 0.98 l/c */
        rjt_check(&c, fabs(rj_model_dt_bound(m) / (0.98 * (1.0 / 20) / sqrt(E / rho)) - 1) < 0.01, "bound of a slender link = 0.98 l/c (axial)", "bound %.6g s, l/c %.6g s", rj_model_dt_bound(m), (1.0 / 20) / sqrt(E / rho));
        rj_model_destroy(m, NULL);
    }
    /* static tip load: solve the linearised K u = f for a tip force; F L^3/3EI */
    {
        rj_model *m = cantilever(10, h);
        int N = 3 * rj_model_node_count(m), i, j, r, piv;
        double *Km = (double *)calloc((size_t)N * N, sizeof(double)), *u = (double *)calloc((size_t)N, sizeof(double));
        double *o = (double *)calloc((size_t)N, sizeof(double)), *w = (double *)calloc(rj_model_work_size(m), sizeof(double));
        double *b = (double *)calloc((size_t)N, sizeof(double));
        double F = 1.0, mass_tip, want = F * 1.0 / (3 * E * I), got;
        int tip = rj_model_node_count(m) - 1;
        /* M^-1/2 K M^-1/2 q = M^-1/2 f with q = M^1/2 u; free DOFs only */
        for (j = 0; j < N; j++) { u[j] = 1; rj_model_apply_stiffness(m, u, o, w); u[j] = 0; for (i = 0; i < N; i++) Km[i * N + j] = o[i]; }
        rj_node_mass(m, 0, tip, &mass_tip, NULL);
        for (i = 0; i < N; i++) if (Km[i * N + i] == 0) Km[i * N + i] = 1; /* fixed DOFs */
        b[3 * tip + 1] = F / sqrt(mass_tip);
        for (r = 0; r < N; r++) { /* Gaussian elimination with partial pivoting */
            double mx = 0, t;
            piv = r;
            for (i = r; i < N; i++) if (fabs(Km[i * N + r]) > mx) { mx = fabs(Km[i * N + r]); piv = i; }
            for (j = 0; j < N; j++) { t = Km[r * N + j]; Km[r * N + j] = Km[piv * N + j]; Km[piv * N + j] = t; }
            t = b[r]; b[r] = b[piv]; b[piv] = t;
            for (i = r + 1; i < N; i++) { double f = Km[i * N + r] / Km[r * N + r]; for (j = r; j < N; j++) Km[i * N + j] -= f * Km[r * N + j]; b[i] -= f * b[r]; }
        }
        for (r = N - 1; r >= 0; r--) { double sum = b[r]; for (j = r + 1; j < N; j++) sum -= Km[r * N + j] * b[j]; b[r] = sum / Km[r * N + r]; }
        got = b[3 * tip + 1] / sqrt(mass_tip);
        rjt_check(&c, fabs(got / want - 1) < 1e-4, "static tip load F L^3 / 3EI", "got %.8g want %.8g m (%+.2e rel)", got, want, got / want - 1);
        free(Km); free(u); free(o); free(w); free(b);
        rj_model_destroy(m, NULL);
    }
    /* layers reproduce EA and EI exactly for an elastic rectangle */
    {
        rj_link_def L = rj_default_link_def();
        rj_scene_def sc = rj_default_scene_def();
        rj_model *m; rj_error err;
        L.layers = 7; L.root = RJ_ROOT_CLAMPED;
        sc.links = &L; sc.link_count = 1;
        rj_model_create(&sc, &m, &err, NULL);
        rjt_check(&c, fabs(rj_link_EA(m, 0) / (70e9 * 0.05 * 0.2) - 1) < 1e-14, "layers: EA exact", "%.15g", rj_link_EA(m, 0));
        rjt_check(&c, fabs(rj_link_EI(m, 0) / (70e9 * 0.05 * 0.008 / 12) - 1) < 1e-13, "layers: EI exact", "%.15g", rj_link_EI(m, 0));
        rj_model_destroy(m, NULL);
    }
    return rjt_summary(&c, "test_beam");
}
