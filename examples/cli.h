/* cli.h - strict option parsing for the example programs: every option takes a value or is
   a flag; unknown options and malformed values print usage and exit with status 2.
   Also what the programs share around a run: outputs whose every write is checked, the
   frames directory (created whole, old frames removed) and the bound on a run's length.
   Needs POSIX (mkdir, opendir, lstat, unlink): define _POSIX_C_SOURCE 200809L before the
   first #include. */
#ifndef RJ_CLI_H
#define RJ_CLI_H
#if !defined(_POSIX_C_SOURCE) || _POSIX_C_SOURCE < 200112L
#error "cli.h: define _POSIX_C_SOURCE 200809L before the first #include"
#endif
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <limits.h>
#include <sys/types.h>
#include <sys/stat.h>
#include <dirent.h>
#include <unistd.h>

typedef struct cli { int argc, i; char **argv; const char *usage; } cli;

static inline void cli_die(const cli *c, const char *fmt, const char *a, const char *b)
{
    fprintf(stderr, "%s: ", c->argv[0]);
    fprintf(stderr, fmt, a, b);
    fprintf(stderr, "\n%s", c->usage);
    exit(2);
}
/* "option OPT: bad value 'S' (need NEED)", usage, exit 2 */
static inline void cli_bad(const cli *c, const char *opt, const char *s, const char *need)
{
    fprintf(stderr, "%s: option %s: bad value '%s' (need %s)\n%s",
            c->argv[0], opt, s, need, c->usage);
    exit(2);
}
/* current option name, or NULL at the end */
static inline const char *cli_next(cli *c) { return ++c->i < c->argc ? c->argv[c->i] : NULL; }
static inline const char *cli_str(cli *c, const char *opt)
{
    const char *v;
    if (c->i + 1 >= c->argc) cli_die(c, "option %s needs a value%s", opt, "");
    v = c->argv[++c->i];
    /* "--csv --plot x" is a forgotten value, not a file named "--plot" */
    if (v[0] == '-' && v[1] == '-') cli_die(c, "option %s needs a value, got option '%s'", opt, v);
    return v;
}
/* Whether s is a decimal number as people write it: an optional sign, digits with an
   optional point, an optional exponent; nothing else. strtod also reads hex ("0x10" is
   16), "nan", "inf" and leading blanks, none of which a command line means as a number. */
static inline int cli_is_decimal(const char *s)
{
    int digits = 0;
    if (*s == '+' || *s == '-') s++;
    for (; isdigit((unsigned char)*s); s++) digits++;
    if (*s == '.') s++;
    for (; isdigit((unsigned char)*s); s++) digits++;
    if (!digits) return 0;
    if (*s != 'e' && *s != 'E') return *s == '\0';
    s++;
    if (*s == '+' || *s == '-') s++;
    if (!isdigit((unsigned char)*s)) return 0;
    while (isdigit((unsigned char)*s)) s++;
    return *s == '\0';
}
/* finite decimal number in [lo, hi]; the whole text must be the number (no blanks, hex,
   nan or inf) */
static inline double cli_num(cli *c, const char *opt, double lo, double hi)
{
    const char *s = cli_str(c, opt);
    char *end;
    double v = 0;
    int ok = cli_is_decimal(s);
    if (ok) {
        errno = 0;
        v = strtod(s, &end);
        ok = end != s && !*end && !errno && v >= lo && v <= hi;
    }
    if (!ok) {
        char range[96];
        snprintf(range, sizeof range, "a finite decimal number in [%g, %g]", lo, hi);
        cli_bad(c, opt, s, range);
    }
    return v;
}
/* Decimal digits of a non-negative integer at s, up to stop (the separator, or '\0' at the
   end): no sign, blanks, exponent or hex. Returns 0 and sets *v, or -1. */
static inline int cli_digits(const char *s, char stop, const char **rest, long long *v)
{
    char *end;
    /* strtoll would take blanks, a sign and, with base 0, hex: only digits here */
    if (*s < '0' || *s > '9') return -1;
    errno = 0;
    *v = strtoll(s, &end, 10);
    if (errno || *end != stop) return -1;
    *rest = end;
    return 0;
}
/* integer in [lo, hi], written as decimal digits with an optional leading '-' */
static inline long long cli_long(cli *c, const char *opt, long long lo, long long hi)
{
    const char *s = cli_str(c, opt);
    const char *rest;
    const int neg = s[0] == '-';
    long long v;
    char range[96];
    if (cli_digits(s + neg, '\0', &rest, &v) == 0) {
        v = neg ? -v : v;
        if (v >= lo && v <= hi) return v;
    }
    snprintf(range, sizeof range, "an integer in [%lld, %lld]", lo, hi);
    cli_bad(c, opt, s, range);
    return 0;
}
static inline int cli_int(cli *c, const char *opt, int lo, int hi)
{
    return (int)cli_long(c, opt, lo, hi);
}
/* Two integers "AsepB" with nothing around them (--size 640x480, --shard 1/4), with
   lim = { a's least, a's most, b's least, b's most }; what says the form in the message. */
static inline void cli_pair(cli *c, const char *opt, char sep, int *a, int *b,
                            const int lim[4], const char *what)
{
    const char *s = cli_str(c, opt);
    const char *rest;
    long long x = 0, y = 0;
    int ok = cli_digits(s, sep, &rest, &x) == 0;
    ok = ok && cli_digits(rest + 1, '\0', &rest, &y) == 0;
    ok = ok && x >= lim[0] && x <= lim[1];
    ok = ok && y >= lim[2] && y <= lim[3];
    if (!ok) cli_bad(c, opt, s, what);
    *a = (int)x;
    *b = (int)y;
}
/* ---- "did you mean": the nearest name to a misspelt one -----------------------------------
   The rule of the scene parser (revjoint.h, rj__sp_near): a suggestion is within 2 edits
   (insertions, deletions, changes, swaps of neighbours; case ignored) of a name of 5 or
   more characters, 1 of 3 or 4, case only of a shorter one, and the only one that near:
   a tie suggests nothing rather than a guess. */
static inline int cli_lower(int ch) { return tolower((unsigned char)ch); }
/* The optimal-string-alignment distance between a and b; 99 when their lengths differ by
   more than 2 or b is long (no suggestion is that far). */
static inline int cli_dist(const char *a, const char *b)
{
    int r[3][66], i, j;
    const int n = (int)strlen(a), m = (int)strlen(b);
    if (n - m > 2 || m - n > 2 || m > 64) return 99;
    for (j = 0; j <= m; j++) r[0][j] = j;
    for (i = 1; i <= n; i++) {
        int *cur = r[i % 3], *up = r[(i + 2) % 3], *up2 = r[(i + 1) % 3];
        cur[0] = i;
        for (j = 1; j <= m; j++) {
            int v = up[j - 1] + (cli_lower(a[i - 1]) != cli_lower(b[j - 1]));
            if (up[j] + 1 < v) v = up[j] + 1;
            if (cur[j - 1] + 1 < v) v = cur[j - 1] + 1;
            /* two neighbours swapped are one edit */
            if (i > 1 && j > 1 && cli_lower(a[i - 1]) == cli_lower(b[j - 2]) &&
                cli_lower(a[i - 2]) == cli_lower(b[j - 1]) && up2[j - 2] + 1 < v)
                v = up2[j - 2] + 1;
            cur[j] = v;
        }
    }
    return r[n % 3][m];
}
/* The one name among names[0..n-1] near s by the rule above, or NULL. */
static inline const char *cli_nearest(const char *s, const char *const *names, int n)
{
    const char *best = NULL;
    int k, bd = 99, ties = 0;
    for (k = 0; k < n; k++) {
        const int len = (int)strlen(names[k]), lim = len >= 5 ? 2 : len >= 3 ? 1 : 0;
        const int d = cli_dist(s, names[k]);
        if (d > lim || d > bd) continue;
        if (d == bd) {
            ties++;
            continue;
        }
        best = names[k];
        bd = d;
        ties = 0;
    }
    return ties ? NULL : best;
}
/* "unknown WHAT 'S'; did you mean 'NAME'?" (without the suggestion when none is near),
   then the usage; exits 2. what is "option" or "subcommand". */
static inline void cli_unknown(const cli *c, const char *what, const char *s, const char *const *names, int n)
{
    const char *near = cli_nearest(s, names, n);
    fprintf(stderr, "%s: unknown %s '%s'", c->argv[0], what, s);
    if (near) fprintf(stderr, "; did you mean '%s'?", near);
    fprintf(stderr, "\n%s", c->usage);
    exit(2);
}
/* value must be one of names[0..n-1]; returns its index. Else the message lists them all,
   with the nearest suggested. */
static inline int cli_choice(cli *c, const char *opt, const char *const *names, int n)
{
    const char *s = cli_str(c, opt);
    const char *near = cli_nearest(s, names, n);
    int k;
    for (k = 0; k < n; k++) if (strcmp(s, names[k]) == 0) return k;
    fprintf(stderr, "%s: option %s: unknown value '%s' (one of: ", c->argv[0], opt, s);
    for (k = 0; k < n; k++) fprintf(stderr, "%s%s", k ? ", " : "", names[k]);
    fputc(')', stderr);
    if (near) fprintf(stderr, "; did you mean '%s'?", near);
    fprintf(stderr, "\n%s", c->usage);
    exit(2);
    return -1;
}
static const char *const cli_methods[] = { "penalty", "adaptive", "momentum", "forced", "energy" };
static const char *const cli_releases[] = { "rc12", "rc13" };

/* ---- outputs: every write checked --------------------------------------------------------
   A full disk shows up as a failed fprintf (once the buffer is flushed) or only at fflush
   or fclose; a history that silently stops is worse than none, so the first error is kept
   with its errno and reported, and the program exits 1. */
typedef struct cli_out { FILE *f; const char *name; int err; } cli_out;

/* Opens path for writing, or standard output when path is NULL; prints why not. */
static inline int cli_open(cli_out *o, const char *prog, const char *path)
{
    o->err = 0;
    o->name = path ? path : "standard output";
    o->f = path ? fopen(path, "w") : stdout;
    if (o->f) return 0;
    fprintf(stderr, "%s: cannot open %s for writing: %s\n", prog, o->name, strerror(errno));
    return -1;
}
/* Takes the result of one fprintf/fputs; a negative one is a write error, errno says why.
   Returns nonzero once any write has failed, so a run can stop early. */
static inline int cli_put(cli_out *o, int rc)
{
    if (rc < 0 && !o->err) o->err = errno ? errno : EIO;
    return o->err;
}
/* Flushes and closes (standard output is flushed, not closed) and reports the first
   error, "prog: cannot write NAME: reason". Returns 0 when everything was written, else 1. */
static inline int cli_close(cli_out *o, const char *prog)
{
    if (!o->f) return 0;
    errno = 0;
    if (fflush(o->f) != 0 && !o->err) o->err = errno ? errno : EIO;
    /* an error flag without a failed call here: an earlier write failed */
    if (ferror(o->f) && !o->err) o->err = EIO;
    if (o->f != stdout && fclose(o->f) != 0 && !o->err) o->err = errno ? errno : EIO;
    o->f = NULL;
    if (!o->err) return 0;
    fprintf(stderr, "%s: cannot write %s: %s\n", prog, o->name, strerror(o->err));
    return 1;
}

/* ---- frames directories ------------------------------------------------------------------
   The frames are DIR/frame_%05d.png. The directory is created with its parents (mkdir -p),
   and the frames of an earlier run are removed first: left there, a shorter run's video
   would carry on with the old run's last frames. Only names "frame_%05d.png" can produce
   are removed, nothing else in the directory. */

/* Creates the missing directories above a file's path ("out/a/x.csv": out/a), so that an
   output may name a folder that does not exist yet. */
static inline int cli_mkdirs(const char *prog, const char *path);
static inline int cli_mkparent(const char *prog, const char *path)
{
    char dir[4096];
    const char *slash = strrchr(path, '/');
    size_t n;
    if (!slash || slash == path) return 0;
    n = (size_t)(slash - path);
    if (n >= sizeof dir) return 0;
    memcpy(dir, path, n);
    dir[n] = '\0';
    if (cli_mkdirs(prog, dir) == 0) return 0;
    fprintf(stderr, "%s: cannot write %s: its folder cannot be made\n", prog, path);
    return -1;
}

/* Creates path and its missing parents; an existing component must be a directory.
   Prints "prog: cannot create directory P: reason" and returns -1 on failure. */
static inline int cli_mkdirs(const char *prog, const char *path)
{
    char p[4096];
    size_t n = strlen(path), i;
    if (n == 0 || n >= sizeof p) {
        fprintf(stderr, "%s: bad directory name '%s'\n", prog, path);
        return -1;
    }
    memcpy(p, path, n + 1);
    /* each prefix ending before a '/' (and the whole path), skipping repeated slashes */
    for (i = 1; i <= n; i++) {
        struct stat st;
        int e;
        if (p[i] != '/' && p[i] != '\0') continue;
        if (p[i - 1] == '/') continue;
        p[i] = '\0';
        if (mkdir(p, 0777) != 0) {
            e = errno;
            /* EEXIST is fine when it is a directory (checked: it may be a file) */
            if (e == EEXIST && (stat(p, &st) != 0 || !S_ISDIR(st.st_mode))) e = ENOTDIR;
            if (e != EEXIST) {
                fprintf(stderr, "%s: cannot create directory %s: %s\n", prog, p, strerror(e));
                return -1;
            }
        }
        p[i] = i < n ? '/' : '\0';
    }
    return 0;
}
/* Whether name is one "frame_%05d.png" writes: five digits, or more without a leading 0. */
static inline int cli_is_frame_name(const char *name)
{
    size_t d = 6;
    if (strncmp(name, "frame_", 6) != 0) return 0;
    while (name[d] >= '0' && name[d] <= '9') d++;
    if (d - 6 < 5) return 0;
    if (d - 6 > 5 && name[6] == '0') return 0;
    return strcmp(name + d, ".png") == 0;
}
/* DIR/frame_K.png into buf; -1 (and a message) when it does not fit. */
static inline int cli_frame_path(const char *prog, char *buf, size_t n, const char *dir, int k)
{
    int len = snprintf(buf, n, "%s/frame_%05d.png", dir, k);
    if (len >= 0 && (size_t)len < n) return 0;
    fprintf(stderr, "%s: frame path too long: %s/frame_%05d.png\n", prog, dir, k);
    return -1;
}
/* Creates dir (mkdir -p) and removes the frames there from an earlier run: regular files
   and symbolic links with frame names (a link would redirect the new frame elsewhere).
   Anything else with such a name is left and the write onto it reports the error.
   Returns 0, or -1 after printing the path and the reason. */
static inline int cli_frames_dir(const char *prog, const char *dir)
{
    char p[4096];
    DIR *d;
    struct dirent *de;
    int rc = 0;
    if (cli_mkdirs(prog, dir) != 0) return -1;
    d = opendir(dir);
    if (!d) {
        fprintf(stderr, "%s: cannot read directory %s: %s\n", prog, dir, strerror(errno));
        return -1;
    }
    for (;;) {
        struct stat st;
        int len;
        errno = 0;
        de = readdir(d);
        if (!de) break;
        if (!cli_is_frame_name(de->d_name)) continue;
        len = snprintf(p, sizeof p, "%s/%s", dir, de->d_name);
        if (len < 0 || (size_t)len >= sizeof p) continue;
        if (lstat(p, &st) != 0) continue;
        if (!S_ISREG(st.st_mode) && !S_ISLNK(st.st_mode)) continue;
        if (unlink(p) != 0 && errno != ENOENT) {
            fprintf(stderr, "%s: cannot remove old frame %s: %s\n", prog, p, strerror(errno));
            rc = -1;
            break;
        }
    }
    /* readdir returns NULL at the end and on an error; errno tells them apart */
    if (!de && errno) {
        fprintf(stderr, "%s: cannot read directory %s: %s\n", prog, dir, strerror(errno));
        rc = -1;
    }
    closedir(d);
    return rc;
}

/* ---- bounds on a run's length ------------------------------------------------------------
   A value in range can still mean a run that never ends: --dt 1e-12, or a penalty K that
   drives the stable step to 1e-19 s. The documented runs take at most a few million steps
   (deploy --paper: 800 000; the 80-element mesh of build/studies: 2.3 million) and the
   two-link deployment steps in 0.2-0.35 us, so 1e8 steps is 40x the longest documented
   run and half a minute of CPU for the smallest model (more for any larger one): above
   it, the step or the time is almost certainly not what was meant; --force runs it. */
#define CLI_MAX_STEPS 1e8
/* A frame costs about 11 ms at 640x480 (render and PNG, README) against a step's
   fraction of a microsecond: 100 000 frames are 20 minutes or more and 1 GB of PNG. */
#define CLI_MAX_FRAMES 1e5

/* Exits 2 with the estimate when t_end / dt steps exceed CLI_MAX_STEPS, unless force. */
static inline void cli_check_steps(const char *prog, double t_end, double dt, int force)
{
    const double n = t_end / dt;
    if (force || !(n > CLI_MAX_STEPS)) return;
    fprintf(stderr, "%s: about %.3g steps (t-end %g s / dt %.3g s), more than the %.0e steps "
            "run without asking; --force runs it anyway\n", prog, n, t_end, dt, CLI_MAX_STEPS);
    exit(2);
}
/* cli_check_steps with up to extra steps before the run (rj run --settle's settling,
   counted at its most, what says what they are): exits 2 when the two together exceed
   CLI_MAX_STEPS, unless force. */
static inline void cli_check_steps_plus(const char *prog, double t_end, double dt, double extra,
                                        const char *what, int force)
{
    const double n = t_end / dt;
    if (force || !(n + extra > CLI_MAX_STEPS)) return;
    fprintf(stderr, "%s: about %.3g steps (t-end %g s / dt %.3g s) and up to %.3g %s, more than "
            "the %.0e steps run without asking; --force runs it anyway\n", prog, n, t_end, dt, extra,
            what, CLI_MAX_STEPS);
    exit(2);
}
/* Exits 2 when about n frames exceed CLI_MAX_FRAMES, unless force. */
static inline void cli_check_frames(const char *prog, double n, int force)
{
    if (force || !(n > CLI_MAX_FRAMES)) return;
    fprintf(stderr, "%s: about %.3g frames, more than the %.0e written without asking; "
            "--force writes them anyway\n", prog, n, CLI_MAX_FRAMES);
    exit(2);
}
#endif
