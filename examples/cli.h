/* cli.h - strict option parsing for the example programs: every option takes a value or is
   a flag; unknown options and malformed numbers print usage and exit with status 2. */
#ifndef RJ_CLI_H
#define RJ_CLI_H
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <errno.h>
#include <math.h>

typedef struct cli { int argc, i; char **argv; const char *usage; } cli;

static inline void cli_die(const cli *c, const char *fmt, const char *a, const char *b)
{
    fprintf(stderr, "%s: ", c->argv[0]);
    fprintf(stderr, fmt, a, b);
    fprintf(stderr, "\n%s", c->usage);
    exit(2);
}
/* current option name, or NULL at the end */
static inline const char *cli_next(cli *c) { return ++c->i < c->argc ? c->argv[c->i] : NULL; }
static inline const char *cli_str(cli *c, const char *opt)
{
    if (c->i + 1 >= c->argc) cli_die(c, "option %s needs a value%s", opt, "");
    return c->argv[++c->i];
}
/* finite number in [lo, hi] */
static inline double cli_num(cli *c, const char *opt, double lo, double hi)
{
    const char *s = cli_str(c, opt);
    char *end;
    double v;
    errno = 0;
    v = strtod(s, &end);
    if (end == s || *end || errno || !(v >= lo && v <= hi)) {
        char range[96];
        snprintf(range, sizeof range, " (need a number in [%g, %g])", lo, hi);
        fprintf(stderr, "%s: option %s: bad value '%s'%s\n%s", c->argv[0], opt, s, range, c->usage);
        exit(2);
    }
    return v;
}
static inline int cli_int(cli *c, const char *opt, int lo, int hi)
{
    double v = cli_num(c, opt, lo, hi);
    if (v != floor(v)) cli_die(c, "option %s needs an integer, got '%s'", opt, c->argv[c->i]);
    return (int)v;
}
/* value must be one of names[0..n-1]; returns its index */
static inline int cli_choice(cli *c, const char *opt, const char *const *names, int n)
{
    const char *s = cli_str(c, opt);
    int k;
    for (k = 0; k < n; k++) if (strcmp(s, names[k]) == 0) return k;
    cli_die(c, "option %s: unknown value '%s'", opt, s);
    return -1;
}
static const char *const cli_methods[] = { "penalty", "adaptive", "momentum", "forced", "energy" };
static const char *const cli_releases[] = { "rc12", "rc13" };
#endif
