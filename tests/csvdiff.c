/* csvdiff - compares a CSV history with its golden file column by column.
   usage: csvdiff GOLDEN ACTUAL [--rel R] [--abs A] [--exact COL]...
   A value passes when |actual - golden| <= abs_c + rel |golden|, with abs_c = A times the
   column's range in the golden file (so one tolerance fits columns of any unit); columns
   named with --exact (status flags) must match exactly. Prints one PASS/FAIL line naming
   the worst column, its row and time; exit 0 pass, 1 fail, 2 usage or read error. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <math.h>

#define MAXC 32

typedef struct tab { int nc, nr, cap; char names[MAXC][64]; double *v; } tab;

static int load(const char *path, tab *t)
{
    FILE *f = fopen(path, "r");
    char line[4096];
    if (!f) return -1;
    t->nc = 0; t->nr = 0; t->cap = 1024; t->v = (double *)malloc(sizeof(double) * MAXC * (size_t)t->cap);
    if (!fgets(line, sizeof line, f)) { fclose(f); return -1; }
    {
        char *p = strtok(line, ",\r\n");
        while (p && t->nc < MAXC) { snprintf(t->names[t->nc++], 64, "%s", p); p = strtok(NULL, ",\r\n"); }
    }
    while (fgets(line, sizeof line, f)) {
        char *p = line, *end;
        int c;
        if (t->nr == t->cap) { t->cap *= 2; t->v = (double *)realloc(t->v, sizeof(double) * MAXC * (size_t)t->cap); }
        for (c = 0; c < t->nc; c++) {
            t->v[(size_t)t->nr * MAXC + c] = strtod(p, &end);
            if (end == p) { fclose(f); return -2; }
            p = end;
            if (*p == ',') p++;
        }
        t->nr++;
    }
    fclose(f);
    return 0;
}

int main(int argc, char **argv)
{
    tab g, a;
    double rel = 1e-9, absf = 1e-9, worst = 0;
    int exact[MAXC] = { 0 }, i, c, wc = -1, wr = -1, nexact = 0;
    const char *ex[MAXC];
    if (argc < 3) { fprintf(stderr, "usage: csvdiff GOLDEN ACTUAL [--rel R] [--abs A] [--exact COL]...\n"); return 2; }
    for (i = 3; i < argc; i++) {
        if (!strcmp(argv[i], "--rel") && i + 1 < argc) rel = atof(argv[++i]);
        else if (!strcmp(argv[i], "--abs") && i + 1 < argc) absf = atof(argv[++i]);
        else if (!strcmp(argv[i], "--exact") && i + 1 < argc && nexact < MAXC) ex[nexact++] = argv[++i];
        else { fprintf(stderr, "csvdiff: unknown option %s\n", argv[i]); return 2; }
    }
    if (load(argv[1], &g) || load(argv[2], &a)) { printf("FAIL csvdiff %s: cannot read %s or %s\n", argv[2], argv[1], argv[2]); return 1; }
    if (g.nc != a.nc || g.nr != a.nr) { printf("FAIL golden %s: shape %dx%d, golden %dx%d\n", argv[2], a.nr, a.nc, g.nr, g.nc); return 1; }
    for (c = 0; c < g.nc; c++) {
        int k;
        if (strcmp(g.names[c], a.names[c])) { printf("FAIL golden %s: column %d is %s, golden %s\n", argv[2], c, a.names[c], g.names[c]); return 1; }
        for (k = 0; k < nexact; k++) if (!strcmp(ex[k], g.names[c])) exact[c] = 1;
    }
    for (c = 0; c < g.nc; c++) {
        double lo = 1e300, hi = -1e300, tol_abs;
        for (i = 0; i < g.nr; i++) { double v = g.v[(size_t)i * MAXC + c]; if (v < lo) lo = v; if (v > hi) hi = v; }
        tol_abs = absf * (hi - lo);
        for (i = 0; i < g.nr; i++) {
            double gv = g.v[(size_t)i * MAXC + c], av = a.v[(size_t)i * MAXC + c], d = fabs(av - gv);
            double tol = exact[c] ? 0.0 : tol_abs + rel * fabs(gv), ratio = d > tol ? (tol > 0 ? d / tol : 1e300) : 0;
            if (!(d == d)) ratio = 1e300;
            if (ratio > worst) { worst = ratio; wc = c; wr = i; }
        }
    }
    if (wc < 0) { printf("PASS golden %s: %d rows x %d columns identical within tolerance (rel %g, abs %g of range)\n", argv[2], g.nr, g.nc, rel, absf); return 0; }
    printf("FAIL golden %s: column %s row %d (t = %g): actual %.12g golden %.12g (%.3g x tolerance); rendered by make golden? see README\n",
           argv[2], g.names[wc], wr + 1, g.v[(size_t)wr * MAXC], a.v[(size_t)wr * MAXC + wc], g.v[(size_t)wr * MAXC + wc], worst);
    return 1;
}
