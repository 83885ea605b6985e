/* rjt.h - the project's tiny test macros. Each check prints one line PASS/FAIL with the
   measured value and its bound, so a person can see how close each check is. */
#ifndef RJT_H
#define RJT_H
#include <stdio.h>
#include <math.h>
#include <stdarg.h>

typedef struct rjt_ctx { int pass, fail; } rjt_ctx;

/* check cond; message printed either way */
static inline int rjt_check(rjt_ctx *c, int cond, const char *name, const char *fmt, ...)
{
    va_list ap;
    printf("%s %s: ", cond ? "PASS" : "FAIL", name);
    va_start(ap, fmt);
    vprintf(fmt, ap);
    va_end(ap);
    printf("\n");
    if (cond) c->pass++; else c->fail++;
    fflush(stdout);
    return cond;
}
/* |got - want| <= tol */
static inline int rjt_near(rjt_ctx *c, const char *name, double got, double want, double tol)
{
    double d = fabs(got - want);
    return rjt_check(c, d <= tol && got == got, name, "got %.12g want %.12g |diff| %.3g <= %.3g", got, want, d, tol);
}
static inline int rjt_summary(const rjt_ctx *c, const char *suite)
{
    printf("%s: %d passed, %d failed\n", suite, c->pass, c->fail);
    return c->fail ? 1 : 0;
}
#endif
