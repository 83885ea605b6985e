/* ------------------------------------------------------------------ scene files */
#ifndef RJ_NO_SCENE_FILES
#include <string.h>
#include <stdlib.h>
#include <math.h>
#include <stdio.h>
#include <errno.h>

enum {
    RJ__SK_NONE,
    RJ__SK_SOLVER,
    RJ__SK_MATERIAL,
    RJ__SK_SECTION,
    RJ__SK_LINK,
    RJ__SK_JOINT,
    RJ__SK_LOAD,
    RJ__SK_ACTUATOR,
    RJ__SK_COUPLING,
    RJ__SK_COUNT
};

/* char arrays, not pointer arrays: read-only data without relocations */
static const char rj__sk_kind[RJ__SK_COUNT][10] = { "",     "solver", "material", "section",
                                                    "link", "joint",  "load",     "actuator",
                                                    "coupling" };
#define RJ__SK_MAT_KEYS                                                                            \
    ((1u << RJ__LK_E) | (1u << RJ__LK_RHO) | (1u << RJ__LK_ETA) | (1u << RJ__LK_DAMPING) |        \
     (1u << RJ__LK_MASS_DAMPING) | (1u << RJ__LK_YIELD) | (1u << RJ__LK_HARDENING) |              \
     (1u << RJ__LK_STRAIN))
#define RJ__SK_SEC_KEYS                                                                            \
    ((1u << RJ__LK_AREA) | (1u << RJ__LK_INERTIA) | (1u << RJ__LK_WIDTH) | (1u << RJ__LK_HEIGHT) | \
     (1u << RJ__LK_LAYERS))

typedef struct rj__stok {
    const char *s;
    int len, line, col;
    char kind;
} rj__stok; /* kind 'w', '=', ',' or 'q' (a quoted string, quotes included) */

/* a material or a section: a partial link definition */
typedef struct rj__spart {
    char name[RJ_SCENE_NAME_MAX];
    rj_link_def d;
    unsigned mask;
    rj_scene_pos pos[1 + RJ__LK_N];
} rj__spart;

typedef struct rj__sp {
    const char *text, *fname;
    size_t len, at;
    int lineno;
    rj_error *err;
    char dp[8]; /* the C library's decimal point in the current locale */
    int dplen;
    rj__stok *tok;
    int ntok;
    rj_scene_file *f;
    int cap_links, cap_joints, cap_loads, cap_acts, cap_cps;
    rj__spart *mat, *sec;
    int nmat, nsec, cap_mat, cap_sec;
    int kind, item; /* current section: kind and index (materials, sections, links, joints) */
    unsigned seen;  /* keys set in the current section */
    int link_mat, link_sec; /* current link's material and section, -1 none */
    int solver_seen;
    int title_line;              /* line of the title statement, 0 none yet */
    char where[80], forkey[128]; /* message pieces */
    rj_result code;              /* of the first error */
    const char *const *sets;     /* rj_scene_parse_set's changes, each taken at its section's end */
    int nsets;
    unsigned long long sets_done; /* bit k: sets[k] taken */
    rj__stok *set_tok;            /* their tokens */
    unsigned char pieces[RJ_SCENE_MAX_LINKS]; /* link k says fidelity = pieces (rj__sp_cut) */
} rj__sp;

/* ------------------------------------------------------------------ small helpers */
static double rj__sp_nan(void)
{
    return strtod("nan", NULL);
}

static void rj__sp_locale(char *dp, int *dplen)
{
    char t[16];
    int n = snprintf(t, sizeof t, "%.1f", 1.5), k;
    *dplen = 0;
    if (n >= 3 && n - 2 < 7)
        for (k = 1; k < n - 1; k++)
            dp[(*dplen)++] = t[k];
    if (*dplen == 0) {
        dp[0] = '.';
        *dplen = 1;
    }
    dp[*dplen] = 0;
}

/* strict decimal number: [+-]? (d+ (. d*)? | . d+) ([eE] [+-]? d+)?
   returns 1 ok, 0 malformed, -1 nan/inf spelled out, -2 out of range, -3 too long */
static int rj__sp_strtonum(const char *s, int n, const char *dp, int dplen, double *out)
{
    char buf[160];
    int i = 0, digits = 0, k, o = 0;
    double v;
    char *end;
    if (n <= 0)
        return 0;
    {
        int j = (s[0] == '+' || s[0] == '-') ? 1 : 0, m = n - j;
        const char *w = s + j;
        if ((m == 3 || m == 8) &&
            (((w[0] | 32) == 'i' && (w[1] | 32) == 'n' && (w[2] | 32) == 'f') ||
             (m == 3 && (w[0] | 32) == 'n' && (w[1] | 32) == 'a' && (w[2] | 32) == 'n'))) {
            if (m == 3)
                return -1;
            if (((w[3] | 32) == 'i' && (w[4] | 32) == 'n' && (w[5] | 32) == 'i' &&
                 (w[6] | 32) == 't' && (w[7] | 32) == 'y'))
                return -1;
        }
    }
    if (s[i] == '+' || s[i] == '-')
        i++;
    while (i < n && s[i] >= '0' && s[i] <= '9') {
        i++;
        digits++;
    }
    if (i < n && s[i] == '.') {
        i++;
        while (i < n && s[i] >= '0' && s[i] <= '9') {
            i++;
            digits++;
        }
    }
    if (!digits)
        return 0;
    if (i < n && (s[i] == 'e' || s[i] == 'E')) {
        int ed = 0;
        i++;
        if (i < n && (s[i] == '+' || s[i] == '-'))
            i++;
        while (i < n && s[i] >= '0' && s[i] <= '9') {
            i++;
            ed++;
        }
        if (!ed)
            return 0;
    }
    if (i != n)
        return 0;
    if (n + dplen >= (int) sizeof buf)
        return -3;
    for (k = 0; k < n; k++) {
        if (s[k] == '.') {
            memcpy(buf + o, dp, (size_t) dplen);
            o += dplen;
        } else
            buf[o++] = s[k];
    }
    buf[o] = 0;
    v = strtod(buf, &end);
    if (end != buf + o)
        return 0;
    if (!(v == v) || v - v != 0.0)
        return -2;
    *out = v;
    return 1;
}

/* strict integer: [+-]? d+ ; returns 1 ok, 0 malformed, -2 beyond +-2e9 */
static int rj__sp_strtoint(const char *s, int n, int *out)
{
    int i = 0, neg = 0, big = 0;
    long v = 0;
    if (n <= 0)
        return 0;
    if (s[0] == '+' || s[0] == '-') {
        neg = s[0] == '-';
        i = 1;
    }
    if (i == n)
        return 0;
    for (; i < n; i++) {
        if (s[i] < '0' || s[i] > '9')
            return 0;
        if (v > 200000000L)
            big = 1;
        else
            v = v * 10 + (s[i] - '0');
    }
    if (big || v > 2000000000L)
        return -2;
    *out = (int) (neg ? -v : v);
    return 1;
}

/* text for messages: at most 40 characters, control and non-ASCII bytes as \xNN */
static void rj__sp_quote(char *dst, size_t size, const char *s, int n)
{
    size_t o = 0;
    int i;
    for (i = 0; i < n && o + 5 < size; i++) {
        unsigned char c = (unsigned char) s[i];
        if (i >= 40) {
            if (o + 4 < size) {
                memcpy(dst + o, "...", 3);
                o += 3;
            }
            break;
        }
        if (c < 0x20 || c >= 0x7f) {
            snprintf(dst + o, size - o, "\\x%02x", c);
            o += 4;
        } else
            dst[o++] = (char) c;
    }
    dst[o < size ? o : size - 1] = 0;
}

/* message builder: concatenates up to 7 pieces (NULL skipped) into dst, truncating */
static void rj__sp_cat(char *dst, size_t size, const char *a, const char *b, const char *c,
                       const char *d, const char *e, const char *f, const char *g)
{
    const char *pc[7];
    size_t o = 0;
    int k;
    pc[0] = a;
    pc[1] = b;
    pc[2] = c;
    pc[3] = d;
    pc[4] = e;
    pc[5] = f;
    pc[6] = g;
    if (!size)
        return;
    for (k = 0; k < 7; k++) {
        size_t n, room;
        if (!pc[k])
            continue;
        n = strlen(pc[k]);
        room = size - 1 - o;
        if (n > room)
            n = room;
        memcpy(dst + o, pc[k], n);
        o += n;
    }
    dst[o] = 0;
}

static const char *rj__sp_itoa(char *buf, long v) /* buf: 24 bytes */
{
    snprintf(buf, 24, "%ld", v);
    return buf;
}

static int rj__sp_fail(rj__sp *P, int line, int col, const char *key, double value, const char *msg)
{
    char l[24], c[24];
    P->code = RJ_ERR_PARSE;
    if (P->err) {
        P->err->code = RJ_ERR_PARSE;
        rj__sp_cat(P->err->field, sizeof P->err->field, key, NULL, NULL, NULL, NULL, NULL, NULL);
        P->err->value = value;
        rj__sp_cat(P->err->msg, sizeof P->err->msg, P->fname, ":", rj__sp_itoa(l, line), ":",
                   rj__sp_itoa(c, col), ": ", msg);
    }
    return 0;
}

/* msg = a b c d e */
static int rj__sp_err(rj__sp *P, int line, int col, const char *key, double value, const char *a,
                      const char *b, const char *c, const char *d, const char *e)
{
    char m[256];
    rj__sp_cat(m, sizeof m, a, b, c, d, e, NULL, NULL);
    return rj__sp_fail(P, line, col, key, value, m);
}

/* msg = pre 'token text' b c d e */
static int rj__sp_err_tok5(rj__sp *P, const rj__stok *t, const char *key, double value,
                           const char *pre, const char *b, const char *c, const char *d,
                           const char *e)
{
    char q[200], m1[256], m[256];
    rj__sp_quote(q, sizeof q, t->s, t->len);
    rj__sp_cat(m1, sizeof m1, pre, "'", q, "'", NULL, NULL, NULL);
    rj__sp_cat(m, sizeof m, m1, b, c, d, e, NULL, NULL);
    return rj__sp_fail(P, t->line, t->col, key, value, m);
}

/* msg = pre 'token text' b c d */
static int rj__sp_err_tok(rj__sp *P, const rj__stok *t, const char *key, double value,
                          const char *pre, const char *b, const char *c, const char *d)
{
    char q[200], m[256];
    rj__sp_quote(q, sizeof q, t->s, t->len);
    rj__sp_cat(m, sizeof m, pre, "'", q, "'", b, c, d);
    return rj__sp_fail(P, t->line, t->col, key, value, m);
}

static const char *rj__sp_item_name(const rj__sp *P)
{
    switch (P->kind) {
    case RJ__SK_MATERIAL:
        return P->mat[P->item].name;
    case RJ__SK_SECTION:
        return P->sec[P->item].name;
    case RJ__SK_LINK:
        return P->f->link_names[P->item];
    case RJ__SK_JOINT:
        return P->f->joint_names[P->item];
    case RJ__SK_LOAD:
        return P->f->load_names[P->item];
    case RJ__SK_ACTUATOR:
        return P->f->actuator_names[P->item];
    case RJ__SK_COUPLING:
        return P->f->coupling_names[P->item];
    }
    return "";
}

/* " in link 'arm1'" for messages, into P->where */
static const char *rj__sp_where(rj__sp *P)
{
    if (P->kind == RJ__SK_SOLVER)
        rj__sp_cat(P->where, sizeof P->where, " in solver", NULL, NULL, NULL, NULL, NULL, NULL);
    else if (P->kind == RJ__SK_NONE)
        P->where[0] = 0;
    else
        rj__sp_cat(P->where, sizeof P->where, " in ", rj__sk_kind[P->kind], " '",
                   rj__sp_item_name(P), "'", NULL, NULL);
    return P->where;
}

/* " for 'key' in link 'arm1'" into P->forkey */
static const char *rj__sp_for(rj__sp *P, const char *key)
{
    rj__sp_cat(P->forkey, sizeof P->forkey, " for '", key, "'", rj__sp_where(P), NULL, NULL, NULL);
    return P->forkey;
}

static int rj__sp_is(const rj__stok *t, const char *s)
{
    size_t n = strlen(s);
    return t->kind == 'w' && (size_t) t->len == n && memcmp(t->s, s, n) == 0;
}

static int rj__sp_name_ok(const char *s, int n)
{
    int i;
    if (n < 1 || n >= RJ_SCENE_NAME_MAX)
        return 0;
    for (i = 0; i < n; i++) {
        char c = s[i];
        int alpha = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_';
        int other = (c >= '0' && c <= '9') || c == '.' || c == '-';
        if (!alpha && !(i > 0 && other))
            return 0;
    }
    return 1;
}

static rj_scene_pos *rj__sp_pos(rj__sp *P, int k) /* position slot of key k of the current item */
{
    switch (P->kind) {
    case RJ__SK_SOLVER:
        return &P->f->solver_pos_[1 + k];
    case RJ__SK_MATERIAL:
        return &P->mat[P->item].pos[1 + k];
    case RJ__SK_SECTION:
        return &P->sec[P->item].pos[1 + k];
    case RJ__SK_LINK:
        return &P->f->link_pos_[(size_t) P->item * (1 + RJ__LK_N) + 1 + k];
    case RJ__SK_LOAD:
        return &P->f->load_pos_[(size_t) P->item * (1 + RJ__AK_N) + 1 + k];
    case RJ__SK_ACTUATOR:
        return &P->f->actuator_pos_[(size_t) P->item * (1 + RJ__CK_N) + 1 + k];
    case RJ__SK_COUPLING:
        return &P->f->coupling_pos_[(size_t) P->item * (1 + RJ__PK_N) + 1 + k];
    default:
        return &P->f->joint_pos_[(size_t) P->item * (1 + RJ__JK_N) + 1 + k];
    }
}

/* ------------------------------------------------------------------ suggestions */
static int rj__sp_lower(int c)
{
    return c >= 'A' && c <= 'Z' ? c + ('a' - 'A') : c;
}

/* edit distance of s[0..n) and b, ignoring case: insertions, deletions, substitutions and
   swaps of two neighbours (optimal string alignment), so 'lenght' is 1 from 'length'.
   99 when the lengths differ by more than 2 (never near enough to suggest). */
static int rj__sp_dist(const char *s, int n, const char *b)
{
    int m = (int) strlen(b), r[3][RJ_SCENE_NAME_MAX + 2], i, j;
    if (n - m > 2 || m - n > 2 || m > RJ_SCENE_NAME_MAX)
        return 99;
    for (j = 0; j <= m; j++)
        r[0][j] = j;
    for (i = 1; i <= n; i++) {
        int *cur = r[i % 3], *up = r[(i + 2) % 3], *up2 = r[(i + 1) % 3];
        int ca = rj__sp_lower((unsigned char) s[i - 1]);
        cur[0] = i;
        for (j = 1; j <= m; j++) {
            int cb = rj__sp_lower((unsigned char) b[j - 1]), v = up[j - 1] + (ca != cb);
            if (up[j] + 1 < v)
                v = up[j] + 1;
            if (cur[j - 1] + 1 < v)
                v = cur[j - 1] + 1;
            if (i > 1 && j > 1 && ca == rj__sp_lower((unsigned char) b[j - 2]) &&
                rj__sp_lower((unsigned char) s[i - 2]) == cb && up2[j - 2] + 1 < v)
                v = up2[j - 2] + 1;
            cur[j] = v;
        }
    }
    return r[n % 3][m];
}

/* The nearest so far (*best at *bd edits, *ties others as near) with name nm also
   weighed: a suggestion must be within 2 edits of a name of 5 or more characters, 1 of 3
   or 4, and differ only in case from a shorter one. */
static void rj__sp_weigh(const char *s, int n, const char *nm, const char **best, int *bd,
                         int *ties)
{
    const int len = (int) strlen(nm), lim = len >= 5 ? 2 : len >= 3 ? 1 : 0;
    const int d = rj__sp_dist(s, n, nm);
    if (d > lim || d > *bd)
        return;
    if (d == *bd) {
        (*ties)++;
        return;
    }
    *best = nm;
    *bd = d;
    *ties = 0;
}

/* The name among names[k] (stride apart, k < count) nearest to s[0..n), or NULL when none
   is near (rj__sp_weigh) or two are as near (a tie suggests nothing rather than a guess). */
static const char *rj__sp_near(const char *s, int n, const char *names, size_t stride, int count)
{
    const char *best = NULL;
    int k, bd = 99, ties = 0;
    for (k = 0; k < count; k++)
        rj__sp_weigh(s, n, names + stride * (size_t) k, &best, &bd, &ties);
    return ties ? NULL : best;
}

/* The same among the keys of rows (the first count; for k < 32 only those in mask). */
static const char *rj__sp_near_row(const char *s, int n, const rj__field *rows, int count,
                                   unsigned mask)
{
    const char *best = NULL;
    int k, bd = 99, ties = 0;
    for (k = 0; k < count; k++)
        if (k >= 32 || (mask >> k & 1u))
            rj__sp_weigh(s, n, rows[k].key, &best, &bd, &ties);
    return ties ? NULL : best;
}

/* the key of the current section nearest to t (rj__sp_near_row), NULL when none is */
static const char *rj__sp_near_key(const rj__sp *P, const rj__stok *t)
{
    switch (P->kind) {
    case RJ__SK_SOLVER:
        return rj__sp_near_row(t->s, t->len, rj__solver_fields, RJ__VK_N, ~0u);
    case RJ__SK_JOINT:
        return rj__sp_near_row(t->s, t->len, rj__joint_fields, RJ__JK_N, ~0u);
    case RJ__SK_MATERIAL:
        return rj__sp_near_row(t->s, t->len, rj__link_fields, RJ__LK_N, RJ__SK_MAT_KEYS);
    case RJ__SK_SECTION:
        return rj__sp_near_row(t->s, t->len, rj__link_fields, RJ__LK_N, RJ__SK_SEC_KEYS);
    case RJ__SK_LINK:
        return rj__sp_near_row(t->s, t->len, rj__link_fields, RJ__LK_N, ~0u);
    case RJ__SK_LOAD:
        return rj__sp_near_row(t->s, t->len, rj__load_fields, RJ__AK_N, ~0u);
    case RJ__SK_ACTUATOR:
        return rj__sp_near_row(t->s, t->len, rj__actuator_fields, RJ__CK_N, ~0u);
    case RJ__SK_COUPLING:
        return rj__sp_near_row(t->s, t->len, rj__coupling_fields, RJ__PK_N, ~0u);
    }
    return NULL;
}

/* "; did you mean 'name'?" into buf (buf: 48 bytes), "" when name is NULL */
static const char *rj__sp_mean(char *buf, const char *name)
{
    buf[0] = 0;
    if (name)
        rj__sp_cat(buf, 48, "; did you mean '", name, "'?", NULL, NULL, NULL, NULL);
    return buf;
}

/* ------------------------------------------------------------------ unit words
   Numbers are SI without a unit ("length = 1", not "1 m"); only angles and rates take one.
   A unit word after a number, or glued to it, gets a message that says so. */
static int rj__sp_alpha(unsigned char c)
{
    return ((c | 32) >= 'a' && (c | 32) <= 'z') || c >= 0x80;
}

/* the SI unit of key (a key of any section's rows), "" when it has none */
static const char *rj__sp_unit(const char *key)
{
    int kind, n, k;
    for (kind = RJ__DEF_LINK; kind <= RJ__DEF_COUPLING; kind++) {
        const rj__field *t = rj__fields(kind, &n);
        for (k = 0; k < n; k++)
            if (strcmp(key, t[k].key) == 0)
                return t[k].unit;
    }
    return "";
}

/* the end of the number that starts t when a word is glued to it ("1mm" -> 1), else 0 */
static int rj__sp_glued(const rj__sp *P, const rj__stok *t)
{
    int p;
    double x;
    for (p = t->len - 1; p > 0; p--)
        if (rj__sp_alpha((unsigned char) t->s[p]) &&
            rj__sp_strtonum(t->s, p, P->dp, P->dplen, &x) == 1)
            return p;
    return 0;
}

/* why the word w after the number num is wrong, into buf (200 bytes): what the key takes,
   and for a prefixed SI unit the number to write ("E is in Pa: write 70e9 for 70 GPa") */
static const char *rj__sp_unit_hint(char *buf, const char *what, const char *unit, const char *num,
                                    int nn, const char *w, int wn)
{
    static const char pre[8] = "GMkcmun",
                      ex[7][4] = { "e9", "e6", "e3", "e-2", "e-3", "e-6", "e-9" };
    char q[200], u[200], t[200];
    const char *p = w[0] ? strchr(pre, w[0]) : NULL;
    int ul = (int) strlen(unit);
    rj__sp_quote(q, sizeof q, num, nn);
    rj__sp_quote(u, sizeof u, w, wn);
    if (strcmp(unit, "rad") == 0 || strcmp(unit, "rad/s") == 0) {
        rj__sp_cat(t, sizeof t, "'", q, ul == 3 ? " deg' or '" : " deg/s' or '", q,
                   ul == 3 ? " rad'" : " rad/s'", NULL, NULL);
        rj__sp_cat(buf, 200,
                   ul == 3 ? ": an angle is a number in rad, or a number and deg or rad: "
                           : ": a rate is a number in rad/s, or a number and deg/s or rad/s: ",
                   t, NULL, NULL, NULL, NULL, NULL);
        return buf;
    }
    t[0] = 0;
    if (ul && wn == ul && memcmp(w, unit, (size_t) ul) == 0)
        rj__sp_cat(t, sizeof t, " is in ", unit, " already: write ", q, NULL, NULL, NULL);
    else if (ul && p && wn == ul + 1 && memcmp(w + 1, unit, (size_t) ul) == 0 &&
             !memchr(num, 'e', (size_t) nn) && !memchr(num, 'E', (size_t) nn)) {
        char n2[220];
        rj__sp_cat(n2, sizeof n2, q, ex[p - pre], " for ", q, " ", u, NULL);
        rj__sp_cat(t, sizeof t, " is in ", unit, ": write ", n2, NULL, NULL, NULL);
    } else if (ul)
        rj__sp_cat(t, sizeof t, " is in ", unit, NULL, NULL, NULL, NULL, NULL);
    rj__sp_cat(buf, 200, ": quantities are plain numbers in SI units, without a unit word",
               ul ? " (" : "", ul ? what : "", t, ul ? ")" : "", NULL, NULL);
    return buf;
}

/* ------------------------------------------------------------------ values */
/* a number that did not read (r from rj__sp_strtonum); unit: what key takes, for the hint */
static int rj__sp_num_err(rj__sp *P, const rj__stok *t, const char *key, int r, const char *unit)
{
    char h[200];
    int p = r == 0 ? rj__sp_glued(P, t) : 0;
    h[0] = 0;
    if (p)
        rj__sp_unit_hint(h, key, unit, t->s, p, t->s + p, t->len - p);
    return rj__sp_err_tok(P, t, key, rj__sp_nan(),
                          r == -1   ? "not a finite number: "
                          : r == -2 ? "number out of range: "
                          : r == -3 ? "number too long: "
                                    : "malformed number ",
                          rj__sp_for(P, key), h, NULL);
}

static int rj__sp_num(rj__sp *P, const rj__stok *t, const char *key, double *out)
{
    int r;
    if (t->kind != 'w')
        return rj__sp_err_tok(P, t, key, rj__sp_nan(), "expected a number, found ",
                              rj__sp_for(P, key), NULL, NULL);
    r = rj__sp_strtonum(t->s, t->len, P->dp, P->dplen, out);
    if (r == 1)
        return 1;
    return rj__sp_num_err(P, t, key, r, rj__sp_unit(key));
}

/* an int in lo..hi; out of range, the sentence rule (NULL: "must be lo..hi") */
static int rj__sp_int(rj__sp *P, const rj__stok *t, const char *key, int lo, int hi,
                      const char *rule, int *out)
{
    char a[24], b[24], q[200], m[256], m2[256];
    int v = 0, r = t->kind == 'w' ? rj__sp_strtoint(t->s, t->len, &v) : 0;
    if (r == 1 && v >= lo && v <= hi) {
        *out = v;
        return 1;
    }
    if (r == 1 || r == -2) {
        rj__sp_quote(q, sizeof q, t->s, t->len);
        rj__sp_cat(m, sizeof m, key, " = ", q, " is out of range", rj__sp_where(P), ": ", NULL);
        if (rule)
            rj__sp_cat(m2, sizeof m2, m, rule, NULL, NULL, NULL, NULL, NULL);
        else
            rj__sp_cat(m2, sizeof m2, m, "must be ", rj__sp_itoa(a, lo), "..", rj__sp_itoa(b, hi),
                       NULL, NULL);
        return rj__sp_fail(P, t->line, t->col, key, r == 1 ? (double) v : rj__sp_nan(), m2);
    }
    return rj__sp_err_tok(P, t, key, rj__sp_nan(), "expected an integer, found ",
                          rj__sp_for(P, key), NULL, NULL);
}

/* a value with an optional unit: "1.5", "90 deg", "90deg"; units are "deg"/"rad" (angles)
   or "deg/s"/"rad/s" (rates), rad when none. Reads toks[*i..b), advances *i. */
static int rj__sp_angle(rj__sp *P, int *i, int b, const char *key, int rate, double *out)
{
    const rj__stok *t = &P->tok[*i];
    const char *ud = rate ? "deg/s" : "deg", *ur = rate ? "rad/s" : "rad";
    int ul = rate ? 5 : 3;
    double v;
    if (t->kind == 'w' && rj__sp_strtonum(t->s, t->len, P->dp, P->dplen, &v) == 1) {
        (*i)++;
        if (*i < b && P->tok[*i].kind == 'w') {
            const rj__stok *u = &P->tok[*i];
            if (rj__sp_is(u, ud)) {
                v = rj_rad(v);
                (*i)++;
            } else if (rj__sp_is(u, ur))
                (*i)++;
            else if ((u->s[0] >= 'a' && u->s[0] <= 'z') || (u->s[0] >= 'A' && u->s[0] <= 'Z'))
                return rj__sp_err_tok(P, u, key, v, "unknown unit ", rj__sp_for(P, key),
                                      rate ? " (deg/s or rad/s)" : " (deg or rad)", NULL);
        }
        if (!(v - v == 0.0))
            return rj__sp_err_tok(P, t, key, rj__sp_nan(),
                                  "number out of range: ", rj__sp_for(P, key), NULL, NULL);
        *out = v;
        return 1;
    }
    /* unit glued to the number */
    if (t->kind == 'w' && t->len > ul) {
        int isd = memcmp(t->s + t->len - ul, ud, (size_t) ul) == 0,
            isr = memcmp(t->s + t->len - ul, ur, (size_t) ul) == 0;
        if ((isd || isr) && rj__sp_strtonum(t->s, t->len - ul, P->dp, P->dplen, &v) == 1) {
            if (isd)
                v = rj_rad(v);
            if (!(v - v == 0.0))
                return rj__sp_err_tok(P, t, key, rj__sp_nan(),
                                      "number out of range: ", rj__sp_for(P, key), NULL, NULL);
            (*i)++;
            *out = v;
            return 1;
        }
    }
    if (t->kind != 'w')
        return rj__sp_num(P, t, key, &v); /* reports the right error */
    return rj__sp_num_err(P, t, key, rj__sp_strtonum(t->s, t->len, P->dp, P->dplen, &v),
                          rate ? "rad/s" : "rad");
}

/* range check on an already parsed value; the message shows the text of toks[a..e) */
static int rj__sp_range(rj__sp *P, int a, int e, const char *key, double v, int ok,
                        const char *rule)
{
    char q[200], m[256];
    const rj__stok *t = &P->tok[a], *z = &P->tok[e - 1];
    if (ok)
        return 1;
    if (z->line == t->line && z->s >= t->s)
        rj__sp_quote(q, sizeof q, t->s, (int) (z->s + z->len - t->s));
    else
        rj__sp_quote(q, sizeof q, t->s, t->len);
    rj__sp_cat(m, sizeof m, key, " = ", q, " is out of range", rj__sp_where(P), ": ", rule);
    return rj__sp_fail(P, t->line, t->col, key, v, m);
}

static int rj__sp_enum(rj__sp *P, const rj__stok *t, const char *key, const char *names,
                       size_t stride, int count, int *out)
{
    char list[100], tmp[100], q[200], m[256], m2[256], mean[48];
    int k;
    for (k = 0; k < count; k++)
        if (rj__sp_is(t, names + stride * (size_t) k)) {
            *out = k;
            return 1;
        }
    list[0] = 0;
    for (k = 0; k < count; k++) {
        rj__sp_cat(tmp, sizeof tmp, list, k ? (k == count - 1 ? " or " : ", ") : "",
                   names + stride * (size_t) k, NULL, NULL, NULL, NULL);
        memcpy(list, tmp, sizeof list);
    }
    rj__sp_quote(q, sizeof q, t->s, t->len);
    rj__sp_cat(m, sizeof m, "unknown value '", q, "'", rj__sp_for(P, key), " (expected ", NULL,
               NULL);
    rj__sp_cat(m2, sizeof m2, m, list, ")",
               rj__sp_mean(mean, rj__sp_near(t->s, t->len, names, stride, count)), NULL, NULL,
               NULL);
    return rj__sp_fail(P, t->line, t->col, key, rj__sp_nan(), m2);
}

static int rj__sp_bool(rj__sp *P, const rj__stok *t, const char *key, int *out)
{
    static const char names[4][6] = { "no", "yes", "false", "true" };
    int k = 0;
    if (!rj__sp_enum(P, t, key, names[0], sizeof names[0], 4, &k))
        return 0;
    *out = k & 1;
    return 1;
}

static int rj__sp_name_ref(rj__sp *P, const rj__stok *t, const char *key)
{
    if (t->kind == 'w' && rj__sp_name_ok(t->s, t->len))
        return 1;
    return rj__sp_err_tok(P, t, key, rj__sp_nan(), "expected a name, found ", rj__sp_for(P, key),
                          NULL, NULL);
}

static int rj__sp_find(const char *s, int n, const char *names, size_t stride, int count)
{
    int k;
    for (k = 0; k < count; k++) {
        const char *nm = names + stride * (size_t) k;
        if ((int) strlen(nm) == n && memcmp(nm, s, (size_t) n) == 0)
            return k;
    }
    return -1;
}

/* ------------------------------------------------------------------ keys */
#define RJ__SP_RULE(cond, rule) rj__sp_range(P, a, *i, key, v, (cond), (rule))

/* whether v is in row r's range */
static int rj__sp_in_range(const rj__field *r, double v)
{
    return (r->lo_in ? v >= r->lo : v > r->lo) && (r->hi_in ? v <= r->hi : v < r->hi);
}

/* key = x y: two numbers, each in row r's range */
static int rj__sp_vec2(rj__sp *P, const rj__field *r, int a, int *i, int b, void *def)
{
    const char *key = r->key;
    char shape[64];
    int c;
    for (c = 0; c < 2; c++) {
        double v = 0;
        if (c == 1 && *i >= b) {
            const rj__stok *z = &P->tok[*i - 1];
            const char x[2] = { key[0], 0 };
            rj__sp_cat(shape, sizeof shape, " (", key, " = ", x, "x ", x, "y, in ");
            return rj__sp_err(P, z->line, z->col + z->len, key, rj__sp_nan(),
                              "missing y component after the x component", rj__sp_where(P),
                              shape, r->unit, ")");
        }
        a = *i;
        if (!rj__sp_num(P, &P->tok[*i], key, &v))
            return 0;
        (*i)++;
        if (!RJ__SP_RULE(rj__sp_in_range(r, v), r->rule))
            return 0;
        rj__row_set_real(def, r, c, v);
    }
    return 1;
}

/* a key whose row r says all (a number, an angle or rate, an int, an enum, a yes/no, a
   vector): a value of its type in its range, into def */
static int rj__sp_row(rj__sp *P, const rj__field *r, int a, int *i, int b, void *def)
{
    const char *key = r->key;
    const rj__stok *t = &P->tok[a];
    double v = 0;
    int n = 0;
    switch (r->type) {
    case RJ__FT_INT:
        if (!rj__sp_int(P, t, key, (int) r->lo, (int) r->hi, r->rule, &n))
            return 0;
        rj__row_set_int(def, r, n);
        (*i)++;
        return 1;
    case RJ__FT_ENUM:
        if (!rj__sp_enum(P, t, key, rj__names_of(r->names), r->stride, r->count, &n))
            return 0;
        rj__row_set_int(def, r, n);
        (*i)++;
        return 1;
    case RJ__FT_BOOL:
        if (!rj__sp_bool(P, t, key, &n))
            return 0;
        rj__row_set_int(def, r, n);
        (*i)++;
        return 1;
    case RJ__FT_VEC2:
        return rj__sp_vec2(P, r, a, i, b, def);
    case RJ__FT_ANGLE:
    case RJ__FT_RATE:
        if (!rj__sp_angle(P, i, b, key, r->type == RJ__FT_RATE, &v))
            return 0;
        break;
    default:
        if (!rj__sp_num(P, t, key, &v))
            return 0;
        (*i)++;
    }
    if (!RJ__SP_RULE(rj__sp_in_range(r, v), r->rule))
        return 0;
    rj__row_set_real(def, r, 0, v);
    return 1;
}

/* material = NAME, section = NAME: a part defined above the link */
static int rj__sp_part(rj__sp *P, int k, const rj__stok *t)
{
    const char *key = rj__link_fields[k].key;
    const rj__spart *parts = k == RJ__LK_MATERIAL ? P->mat : P->sec;
    int idx, np = k == RJ__LK_MATERIAL ? P->nmat : P->nsec;
    char mean[48];
    if (!rj__sp_name_ref(P, t, key))
        return 0;
    idx = np ? rj__sp_find(t->s, t->len, parts[0].name, sizeof(rj__spart), np) : -1;
    if (idx < 0)
        return rj__sp_err_tok(P, t, key, rj__sp_nan(),
                              k == RJ__LK_MATERIAL ? "unknown material " : "unknown section ",
                              rj__sp_where(P), " (define it above the link)",
                              np ? rj__sp_mean(mean, rj__sp_near(t->s, t->len, parts[0].name,
                                                                 sizeof(rj__spart), np))
                                 : "");
    if (k == RJ__LK_MATERIAL)
        P->link_mat = idx;
    else
        P->link_sec = idx;
    return 1;
}

/* fidelity = flexible | rigid | inextensible, the model's (rj__sk_fidelity, in its
   order), or pieces, the file's own: a link cut into rigid pieces after the file is read
   (rj__sp_cut). Its pieces are rigid links, so the link is one until then. */
static int rj__sp_fidelity(rj__sp *P, const rj__stok *t, rj_link_def *d)
{
    static const char names[4][13] = { "flexible", "rigid", "inextensible", "pieces" };
    int n = 0;
    if (!rj__sp_enum(P, t, "fidelity", names[0], sizeof names[0], 4, &n))
        return 0;
    P->pieces[P->item] = n == 3;
    d->fidelity = n == 3 ? RJ_LINK_RIGID : n;
    return 1;
}

static int rj__sp_link_key(rj__sp *P, int k, int a, int *i, int b, rj_link_def *d)
{
    /* only a link section takes fidelity (not a material or a section) */
    if (k == RJ__LK_FIDELITY && P->kind == RJ__SK_LINK) {
        if (!rj__sp_fidelity(P, &P->tok[a], d))
            return 0;
        (*i)++;
        return 1;
    }
    if (rj__link_fields[k].type == RJ__FT_PART) {
        if (!rj__sp_part(P, k, &P->tok[a]))
            return 0;
        (*i)++;
        return 1;
    }
    return rj__sp_row(P, &rj__link_fields[k], a, i, b, d);
}

/* forward / reverse / cutoff = an angle in row r's range, or none */
static int rj__sp_limit(rj__sp *P, const rj__field *r, int a, int *i, int b, int *has,
                        double *lim)
{
    const char *key = r->key;
    char rule[96];
    double v = 0;
    if (rj__sp_is(&P->tok[a], "none")) {
        *has = 0;
        *lim = 0;
        (*i)++;
        return 1;
    }
    if (!rj__sp_angle(P, i, b, key, 0, &v))
        return 0;
    rj__sp_cat(rule, sizeof rule, r->rule, ", or none", NULL, NULL, NULL, NULL, NULL);
    if (!RJ__SP_RULE(rj__sp_in_range(r, v), rule))
        return 0;
    *has = 1;
    *lim = v;
    return 1;
}

/* a link defined above the statement, named by t, into *link; users: what names links
   (the message's "define links above the joints that use them") */
static int rj__sp_link_ref(rj__sp *P, const rj__stok *t, const char *key, const char *users,
                           int *link)
{
    const int idx = P->f->link_count ? rj__sp_find(t->s, t->len, (const char *) P->f->link_names,
                                                   RJ_SCENE_NAME_MAX, P->f->link_count)
                                     : -1;
    char mean[48], tail[64];
    if (idx >= 0) {
        *link = idx;
        return 1;
    }
    rj__sp_mean(mean, P->f->link_count ? rj__sp_near(t->s, t->len, (const char *) P->f->link_names,
                                                     RJ_SCENE_NAME_MAX, P->f->link_count)
                                       : NULL);
    rj__sp_cat(tail, sizeof tail, " (define links above the ", users, " that use them)", NULL, NULL,
               NULL, NULL);
    return rj__sp_err_tok(P, t, key, rj__sp_nan(), "unknown link ", rj__sp_for(P, key), tail, mean);
}

/* a node of a link: last (-1) or its index (the link's range is checked when its section
   ends) */
static int rj__sp_node_ref(rj__sp *P, const rj__stok *t, const char *key, int *i, int *node)
{
    if (rj__sp_is(t, "last"))
        *node = -1;
    else if (!rj__sp_int(P, t, key, 0, 1000000, NULL, node))
        return 0;
    (*i)++;
    return 1;
}

/* What a table's pairs hold: the first an angle (deg or rad, in [0, 360] deg) or a plain
   number, the second a plain number; their names and the second's unit for messages; the
   fewest points a table has. */
typedef struct rj__sp_form {
    int angles;
    const char *first, *second, *second_what, *second_unit, *shape;
    int fewest;
} rj__sp_form;

/* the first value of a table's pair into *v (a: where it starts, for the range rule) */
static int rj__sp_pair_first(rj__sp *P, int *i, int b, const rj__sp_form *t, double *out)
{
    const char *key = "table";
    const int a = *i;
    double v = 0;
    if (!t->angles) {
        if (!rj__sp_num(P, &P->tok[*i], key, out))
            return 0;
        (*i)++;
        return 1;
    }
    if (!rj__sp_angle(P, i, b, key, 0, &v))
        return 0;
    /* angles may fall: as in rj_model_create, a fall starts a new run (Eq 4) */
    if (!RJ__SP_RULE(v >= 0 && v <= 2.0 * 3.14159265358979323846,
                     "table angles must be in [0, 360] deg"))
        return 0;
    *out = v;
    return 1;
}

/* after a pair: the end of the table, or ',' and another pair; "1 Nm" gets why the
   second takes no unit word. Returns 1 at the end, 2 for another pair, 0 on an error. */
static int rj__sp_pair_next(rj__sp *P, int *i, int b, const rj__sp_form *t)
{
    const char *key = "table";
    if (*i >= b)
        return 1;
    if (P->tok[*i].kind != ',') {
        const rj__stok *u = &P->tok[*i], *q = &P->tok[*i - 1];
        char h[200];
        h[0] = 0;
        if (t->second_unit && u->kind == 'w' && rj__sp_alpha((unsigned char) u->s[0]))
            rj__sp_unit_hint(h, t->second_what, t->second_unit, q->s, q->len, u->s, u->len);
        return rj__sp_err_tok(P, u, key, rj__sp_nan(),
                              "expected ',' or the end of the table, found ", rj__sp_where(P),
                              t->shape, h);
    }
    (*i)++;
    if (*i >= b) {
        const rj__stok *z = &P->tok[*i - 1];
        return rj__sp_err(P, z->line, z->col, key, rj__sp_nan(), "table ends with ','",
                          rj__sp_where(P), NULL, NULL, NULL);
    }
    return 2;
}

/* table = a b, a b, ...: t->fewest .. RJ_TABLE_MAX pairs into first[] and second[] */
static int rj__sp_pairs(rj__sp *P, int *i, int b, const rj__sp_form *t, double *first,
                        double *second, int *count)
{
    const char *key = "table";
    char nb[24], missing[64];
    int n = 0, a = *i, more = 2;
    while (more == 2) {
        a = *i;
        if (n == RJ_TABLE_MAX)
            return rj__sp_err(P, P->tok[a].line, P->tok[a].col, key, rj__sp_nan(),
                              "table has more than ", rj__sp_itoa(nb, RJ_TABLE_MAX), " points",
                              rj__sp_where(P), NULL);
        if (!rj__sp_pair_first(P, i, b, t, &first[n]))
            return 0;
        if (*i >= b || P->tok[*i].kind == ',') {
            const rj__stok *z = &P->tok[*i - 1];
            rj__sp_cat(missing, sizeof missing, "missing ", t->second, " after the table ",
                       t->first, NULL, NULL, NULL);
            return rj__sp_err(P, z->line, z->col + z->len, key, rj__sp_nan(), missing,
                              rj__sp_where(P), t->shape, NULL, NULL);
        }
        if (!rj__sp_num(P, &P->tok[*i], key, &second[n]))
            return 0;
        (*i)++;
        n++;
        more = rj__sp_pair_next(P, i, b, t);
        if (!more)
            return 0;
    }
    if (n < t->fewest)
        return rj__sp_err(P, P->tok[a].line, P->tok[a].col, key, rj__sp_nan(),
                          "a table needs at least 2 points", rj__sp_where(P), NULL, NULL, NULL);
    *count = n;
    return 1;
}

/* a joint's table = angle torque, angle torque, ... (Eq 4) */
static int rj__sp_table(rj__sp *P, int *i, int b, rj_joint_def *d)
{
    const rj__sp_form form = { 1,          "angle", "torque",
                               "a torque", "N m",   " (table = angle torque, angle torque, ...)",
                               2 };
    return rj__sp_pairs(P, i, b, &form, d->table_angle, d->table_torque, &d->table_count);
}

/* body1 = ground or a link, body2 = a link */
static int rj__sp_body(rj__sp *P, int k, const rj__stok *t, rj_joint_def *d)
{
    const char *key = rj__joint_fields[k].key;
    int idx;
    if (!rj__sp_name_ref(P, t, key))
        return 0;
    if (rj__sp_is(t, "ground")) {
        if (k == RJ__JK_BODY2)
            return rj__sp_err_tok(P, t, key, rj__sp_nan(), "body2 must be a link, not ",
                                  rj__sp_where(P), " (body1 may be ground)", NULL);
        d->body1 = -1;
        return 1;
    }
    if (!rj__sp_link_ref(P, t, key, "joints", &idx))
        return 0;
    if (k == RJ__JK_BODY1)
        d->body1 = idx;
    else
        d->body2 = idx;
    return 1;
}

/* spring = k angle: a stiffness and a free angle, each in its row's range */
static int rj__sp_spring(rj__sp *P, int a, int *i, int b, rj_joint_def *d)
{
    const rj__field *rk = &rj__joint_fields[RJ__JK_SPRING];
    const rj__field *ra = &rj__joint_fields[RJ__JF_FREE_ANGLE];
    const char *key = rk->key;
    const rj__stok *t = &P->tok[a];
    char rule[128];
    double v = 0;
    if (!rj__sp_num(P, t, key, &v))
        return 0;
    (*i)++;
    rj__sp_cat(rule, sizeof rule, "the spring stiffness ", rk->rule, NULL, NULL, NULL, NULL,
               NULL);
    if (!RJ__SP_RULE(rj__sp_in_range(rk, v), rule))
        return 0;
    d->spring_k = v;
    if (*i >= b)
        return rj__sp_err(P, t->line, t->col + t->len, key, rj__sp_nan(),
                          "missing free angle after the stiffness", rj__sp_where(P),
                          " (spring = k angle)", NULL, NULL);
    a = *i;
    if (!rj__sp_angle(P, i, b, key, 0, &v))
        return 0;
    rj__sp_cat(rule, sizeof rule, "the free angle ", ra->rule, NULL, NULL, NULL, NULL, NULL);
    if (!RJ__SP_RULE(rj__sp_in_range(ra, v), rule))
        return 0;
    d->spring_free_angle = v;
    return 1;
}

static int rj__sp_joint_key(rj__sp *P, int k, int a, int *i, int b, rj_joint_def *d)
{
    const rj__field *r = &rj__joint_fields[k];
    switch (r->type) {
    case RJ__FT_LINK:
        if (!rj__sp_body(P, k, &P->tok[a], d))
            return 0;
        (*i)++;
        return 1;
    case RJ__FT_NODE:
        return rj__sp_node_ref(P, &P->tok[a], r->key, i, k == RJ__JK_NODE2 ? &d->node2 : &d->node1);
    case RJ__FT_TABLE:
        return rj__sp_table(P, i, b, d);
    case RJ__FT_LIMIT:
        return k == RJ__JK_FORWARD ? rj__sp_limit(P, r, a, i, b, &d->has_forward, &d->forward)
                                   : rj__sp_limit(P, r, a, i, b, &d->has_reverse, &d->reverse);
    }
    if (k == RJ__JK_SPRING)
        return rj__sp_spring(P, a, i, b, d);
    return rj__sp_row(P, r, a, i, b, d);
}

static int rj__sp_solver_key(rj__sp *P, int k, int a, int *i, int b, rj_solver_def *s)
{
    return rj__sp_row(P, &rj__solver_fields[k], a, i, b, s);
}

/* a load's table = time factor, time factor, ...: 1..RJ_TABLE_MAX points, times in s
   (strictly increasing: rj_model_create checks it, naming the point) */
static int rj__sp_load_table(rj__sp *P, int *i, int b, rj_load_def *d)
{
    const rj__sp_form form = { 0,    "time", "factor",
                               NULL, NULL,   " (table = time factor, time factor, ...)",
                               1 };
    return rj__sp_pairs(P, i, b, &form, d->table_time, d->table_factor, &d->table_count);
}

static int rj__sp_load_key(rj__sp *P, int k, int a, int *i, int b, rj_load_def *d)
{
    const rj__field *r = &rj__load_fields[k];
    const rj__stok *t = &P->tok[a];
    switch (r->type) {
    case RJ__FT_LINK:
        if (!rj__sp_name_ref(P, t, r->key) || !rj__sp_link_ref(P, t, r->key, "loads", &d->link))
            return 0;
        (*i)++;
        return 1;
    case RJ__FT_NODE:
        return rj__sp_node_ref(P, t, r->key, i, &d->node);
    case RJ__FT_TABLE:
        return rj__sp_load_table(P, i, b, d);
    }
    return rj__sp_row(P, r, a, i, b, d);
}

/* joint = NAME: a joint defined above the actuator */
static int rj__sp_joint_ref(rj__sp *P, const rj__stok *t, const char *key, int *joint)
{
    const char *users = P->kind == RJ__SK_COUPLING ? " (define joints above the couplings that "
                                                     "tie them)"
                                                   : " (define joints above the actuators "
                                                     "that drive them)";
    const int idx = P->f->joint_count
                        ? rj__sp_find(t->s, t->len, (const char *) P->f->joint_names,
                                      RJ_SCENE_NAME_MAX, P->f->joint_count)
                        : -1;
    char mean[48];
    if (!rj__sp_name_ref(P, t, key))
        return 0;
    if (idx >= 0) {
        *joint = idx;
        return 1;
    }
    rj__sp_mean(mean, P->f->joint_count
                          ? rj__sp_near(t->s, t->len, (const char *) P->f->joint_names,
                                        RJ_SCENE_NAME_MAX, P->f->joint_count)
                          : NULL);
    return rj__sp_err_tok(P, t, key, rj__sp_nan(), "unknown joint ", rj__sp_for(P, key), users,
                          mean);
}

/* an actuator's table = time factor, time factor, ... (as a load's) */
static int rj__sp_actuator_table(rj__sp *P, int *i, int b, rj_actuator_def *d)
{
    const rj__sp_form form = { 0,    "time", "factor",
                               NULL, NULL,   " (table = time factor, time factor, ...)",
                               1 };
    return rj__sp_pairs(P, i, b, &form, d->table_time, d->table_factor, &d->table_count);
}

/* profile = ramp RATE | cycloidal ANGLE DURATION | spinup OMEGA TS: the name, then its
   numbers in their rows' ranges (rates and angles may say deg/s or deg) */
static int rj__sp_profile(rj__sp *P, int a, int *i, int b, rj_actuator_def *d)
{
    const rj__field *rv = &rj__actuator_fields[RJ__CF_PROFILE_VALUE];
    const rj__field *rt = &rj__actuator_fields[RJ__CF_PROFILE_TIME];
    const char *key = "profile";
    static const char shape[] = " (profile = ramp RATE, cycloidal ANGLE DURATION, spinup "
                                "OMEGA TS or table)";
    double v = 0;
    if (!rj__sp_enum(P, &P->tok[a], key, rj__sk_profile[0], sizeof rj__sk_profile[0], 4,
                     &d->profile))
        return 0;
    (*i)++;
    if (d->profile == RJ_PROFILE_TABLE) /* its points are the table's */
        return 1;
    if (*i >= b)
        return rj__sp_err(P, P->tok[a].line, P->tok[a].col + P->tok[a].len, key, rj__sp_nan(),
                          "missing the profile's numbers", rj__sp_where(P), shape, NULL, NULL);
    a = *i;
    if (!rj__sp_angle(P, i, b, key, d->profile != RJ_PROFILE_CYCLOIDAL, &v))
        return 0;
    if (!RJ__SP_RULE(rj__sp_in_range(rv, v), rv->rule))
        return 0;
    d->profile_value = v;
    if (d->profile == RJ_PROFILE_RAMP)
        return 1;
    if (*i >= b)
        return rj__sp_err(P, P->tok[a].line, P->tok[a].col + P->tok[a].len, key, rj__sp_nan(),
                          "missing the profile's time", rj__sp_where(P), shape, NULL, NULL);
    a = *i;
    if (!rj__sp_num(P, &P->tok[a], key, &v))
        return 0;
    (*i)++;
    if (!RJ__SP_RULE(rj__sp_in_range(rt, v), rt->rule))
        return 0;
    d->profile_time = v;
    return 1;
}

static int rj__sp_actuator_key(rj__sp *P, int k, int a, int *i, int b, rj_actuator_def *d)
{
    const rj__field *r = &rj__actuator_fields[k];
    switch (r->type) {
    case RJ__FT_PROFILE:
        return rj__sp_profile(P, a, i, b, d);
    case RJ__FT_JOINT:
        if (!rj__sp_joint_ref(P, &P->tok[a], r->key, &d->joint))
            return 0;
        (*i)++;
        return 1;
    case RJ__FT_TABLE:
        return rj__sp_actuator_table(P, i, b, d);
    case RJ__FT_LIMIT:
        return rj__sp_limit(P, r, a, i, b, &d->has_cutoff, &d->cutoff);
    }
    return rj__sp_row(P, r, a, i, b, d);
}

/* an actuator names its joint, and sets only keys of its type */
static int rj__sp_finish_actuator(rj__sp *P)
{
    const rj_actuator_def *d = &P->f->actuators[P->item];
    const rj_scene_pos *pos = &P->f->actuator_pos_[(size_t) P->item * (1 + RJ__CK_N)];
    const char *name = P->f->actuator_names[P->item];
    int k;
    if (!(P->seen >> RJ__CK_JOINT & 1u))
        return rj__sp_err(P, pos[0].line, pos[0].col, "joint", rj__sp_nan(), "actuator '", name,
                          "' has no joint (the joint it drives)", NULL, NULL);
    for (k = 0; k < RJ__CK_N; k++) {
        const rj__field *r = &rj__actuator_fields[k];
        char m[128];
        if (!(P->seen >> k & 1u) || rj__row_applies(r, d->type, 0, 0))
            continue;
        rj__sp_cat(m, sizeof m, r->key, " does not apply to type = ", rj__sk_actuator[d->type],
                   ", in actuator '", name, "'", NULL);
        return rj__sp_err(P, pos[1 + k].line, pos[1 + k].col, r->key, rj__sp_nan(), m, NULL, NULL,
                          NULL, NULL);
    }
    return 1;
}

/* joints = A B: two joints defined above the coupling */
static int rj__sp_coupling_key(rj__sp *P, int k, int a, int *i, int b, rj_coupling_def *d)
{
    const rj__field *r = &rj__coupling_fields[k];
    if (k != RJ__PK_JOINTS)
        return rj__sp_row(P, r, a, i, b, d);
    if (!rj__sp_joint_ref(P, &P->tok[a], r->key, &d->joint_a))
        return 0;
    (*i)++;
    if (*i >= b) {
        const rj__stok *z = &P->tok[a];
        return rj__sp_err(P, z->line, z->col + z->len, r->key, rj__sp_nan(),
                          "missing the second joint", rj__sp_where(P), " (joints = A B)", NULL,
                          NULL);
    }
    if (!rj__sp_joint_ref(P, &P->tok[*i], r->key, &d->joint_b))
        return 0;
    (*i)++;
    return 1;
}

/* a coupling names its two joints, and they differ */
static int rj__sp_finish_coupling(rj__sp *P)
{
    const rj_coupling_def *d = &P->f->couplings[P->item];
    const rj_scene_pos *pos = &P->f->coupling_pos_[(size_t) P->item * (1 + RJ__PK_N)];
    const char *name = P->f->coupling_names[P->item];
    if (!(P->seen >> RJ__PK_JOINTS & 1u))
        return rj__sp_err(P, pos[0].line, pos[0].col, "joints", rj__sp_nan(), "coupling '",
                          name, "' has no joints (joints = A B)", NULL, NULL);
    if (d->joint_a == d->joint_b)
        return rj__sp_err(P, pos[1 + RJ__PK_JOINTS].line, pos[1 + RJ__PK_JOINTS].col, "joints",
                          rj__sp_nan(), "coupling '", name, "' ties joint '",
                          P->f->joint_names[d->joint_a], "' to itself");
    return 1;
}

/* ------------------------------------------------------------------ sections */
static int rj__sp_key_index(int kind, const rj__stok *t)
{
    int k;
    switch (kind) {
    case RJ__SK_SOLVER:
        for (k = 0; k < RJ__VK_N; k++)
            if (rj__sp_is(t, rj__solver_fields[k].key))
                return k;
        break;
    case RJ__SK_MATERIAL:
    case RJ__SK_SECTION:
    case RJ__SK_LINK: {
        unsigned allowed = kind == RJ__SK_MATERIAL  ? RJ__SK_MAT_KEYS
                           : kind == RJ__SK_SECTION ? RJ__SK_SEC_KEYS
                                                    : ~0u;
        for (k = 0; k < RJ__LK_N; k++)
            if ((allowed >> k & 1u) && rj__sp_is(t, rj__link_fields[k].key))
                return k;
        break;
    }
    case RJ__SK_JOINT:
        for (k = 0; k < RJ__JK_N; k++)
            if (rj__sp_is(t, rj__joint_fields[k].key))
                return k;
        break;
    case RJ__SK_LOAD:
        for (k = 0; k < RJ__AK_N; k++)
            if (rj__sp_is(t, rj__load_fields[k].key))
                return k;
        break;
    case RJ__SK_ACTUATOR:
        for (k = 0; k < RJ__CK_N; k++)
            if (rj__sp_is(t, rj__actuator_fields[k].key))
                return k;
        break;
    case RJ__SK_COUPLING:
        for (k = 0; k < RJ__PK_N; k++)
            if (rj__sp_is(t, rj__coupling_fields[k].key))
                return k;
        break;
    }
    return -1;
}

static const char *rj__sp_key_name(int kind, int k)
{
    if (kind == RJ__SK_SOLVER)
        return rj__solver_fields[k].key;
    if (kind == RJ__SK_JOINT)
        return rj__joint_fields[k].key;
    if (kind == RJ__SK_LOAD)
        return rj__load_fields[k].key;
    if (kind == RJ__SK_ACTUATOR)
        return rj__actuator_fields[k].key;
    if (kind == RJ__SK_COUPLING)
        return rj__coupling_fields[k].key;
    return rj__link_fields[k].key;
}

/* section rules shared by sections and links: eff = keys in effect, pos[k] where key k came from */
static int rj__sp_check_shape(rj__sp *P, unsigned eff, const rj_link_def *d,
                              const rj_scene_pos *pos, rj_scene_pos head, const char *what)
{
    unsigned gen = (1u << RJ__LK_AREA) | (1u << RJ__LK_INERTIA);
    if (eff & gen) {
        int k;
        if ((eff & gen) != gen) {
            int has = (eff >> RJ__LK_AREA & 1u) ? RJ__LK_AREA : RJ__LK_INERTIA;
            rj_scene_pos p = pos[has].line ? pos[has] : head;
            return rj__sp_err(P, p.line, p.col, rj__link_fields[has].key, rj__sp_nan(), what, " sets ",
                              rj__link_fields[has].key,
                              has == RJ__LK_AREA ? " but not inertia" : " but not area",
                              ": a general section needs both area and inertia");
        }
        for (k = RJ__LK_WIDTH; k <= RJ__LK_LAYERS; k++)
            if (k != RJ__LK_HEIGHT && (eff >> k & 1u)) {
                rj_scene_pos p = pos[k].line ? pos[k] : head;
                return rj__sp_err(
                    P, p.line, p.col, rj__link_fields[k].key, rj__sp_nan(), what, " mixes ", rj__link_fields[k].key,
                    " with area/inertia: ", "width and layers apply only to rectangular sections");
            }
    } else if ((eff >> RJ__LK_HEIGHT & 1u) && !(d->height > 0)) {
        return rj__sp_err(P, pos[RJ__LK_HEIGHT].line, pos[RJ__LK_HEIGHT].col, "height", d->height,
                          what, " has height = 0: a rectangular section needs height > 0", NULL,
                          NULL, NULL);
    }
    return 1;
}

/* a load names its link, and a node the link has */
static int rj__sp_finish_load(rj__sp *P)
{
    const rj_load_def *d = &P->f->loads[P->item];
    const rj_scene_pos *pos = &P->f->load_pos_[(size_t) P->item * (1 + RJ__AK_N)];
    const char *name = P->f->load_names[P->item];
    char a[24], b[24], m[256];
    if (!(P->seen >> RJ__AK_LINK & 1u))
        return rj__sp_err(P, pos[0].line, pos[0].col, "link", rj__sp_nan(), "load '", name,
                          "' has no link (the link it acts on)", NULL, NULL);
    if (d->node <= P->f->links[d->link].elements)
        return 1;
    rj__sp_cat(m, sizeof m, "node = ", rj__sp_itoa(a, d->node), " is out of range in load '", name,
               "': link '", P->f->link_names[d->link], "' has nodes 0..");
    return rj__sp_err(P, pos[1 + RJ__AK_NODE].line, pos[1 + RJ__AK_NODE].col, "node", d->node, m,
                      rj__sp_itoa(b, P->f->links[d->link].elements), " (or last)", NULL, NULL);
}

/* A link's material: each material key the link leaves out (its keys so far, eff) comes
   from the material, with its place in the file; returns the keys the link has now. */
static unsigned rj__sp_take_material(const rj__spart *s, unsigned eff, rj_link_def *d,
                                     rj_scene_pos *pos)
{
    int k;
    for (k = 0; k < RJ__LK_N; k++) {
        const rj__field *r = &rj__link_fields[k];
        if (!(RJ__SK_MAT_KEYS >> k & 1u) || (eff >> k & 1u) || !(s->mask >> k & 1u))
            continue;
        rj__row_set_real(d, r, 0, rj__row_real(&s->d, r, 0));
        if (r->type == RJ__FT_VEC2)
            rj__row_set_real(d, r, 1, rj__row_real(&s->d, r, 1));
        pos[1 + k] = s->pos[1 + k];
    }
    return eff | s->mask;
}

/* ------------------------------------------------------------------ changes (--set) */
static int rj__sp_next(rj__sp *P);
static int rj__sp_assignments(rj__sp *P);

/* A change "KIND.NAME.KEY=VALUE" ("solver.KEY=VALUE"): its section kind, its item's name
   and its key, each a start and a length (a name may hold dots: the key follows the last
   one before the '='). Returns 0 when it is not of that form. */
typedef struct rj__sp_set {
    int kind;
    const char *name, *key;
    int nlen, klen;
} rj__sp_set;

static int rj__sp_set_split(const char *s, rj__sp_set *o)
{
    const char *eq = strchr(s, '=');
    const char *dot = strchr(s, '.');
    const char *last = NULL, *c;
    int k;
    if (!eq || !dot || dot > eq)
        return 0;
    o->kind = 0;
    for (k = RJ__SK_SOLVER; k <= RJ__SK_COUPLING; k++)
        if (strlen(rj__sk_kind[k]) == (size_t) (dot - s) &&
            strncmp(s, rj__sk_kind[k], (size_t) (dot - s)) == 0)
            o->kind = k;
    for (c = dot; c < eq; c++)
        if (*c == '.')
            last = c;
    o->name = dot + 1;
    o->nlen = o->kind == RJ__SK_SOLVER ? 0 : (int) (last - dot - 1);
    o->key = o->kind == RJ__SK_SOLVER ? dot + 1 : last + 1;
    o->klen = (int) (eq - o->key);
    return o->kind && o->klen > 0 && (o->kind == RJ__SK_SOLVER || o->nlen > 0);
}

/* Change k into the current item, as a statement written last in its section (its key,
   if the file set it, set again; its position none, for validation's messages): read
   from the change's own text, "--set" line k + 1 in messages. */
static int rj__sp_set_take(rj__sp *P, int k, const rj__sp_set *o)
{
    const char *text = P->text, *fname = P->fname;
    const size_t len = P->len, at = P->at;
    const int lineno = P->lineno, ntok = P->ntok;
    rj__stok *tok = P->tok;
    int ok, key = -1;
    P->text = P->sets[k];
    P->len = strlen(P->sets[k]);
    P->at = 0;
    P->lineno = k;
    P->fname = "--set";
    P->tok = P->set_tok;
    ok = rj__sp_next(P) > 0 && P->ntok >= 2 && P->tok[1].kind == '=';
    if (ok) {
        /* the statement's key: the change's last part before '=' */
        P->tok[0].col += (int) (o->key - P->sets[k]);
        P->tok[0].s = o->key;
        P->tok[0].len = o->klen;
        key = rj__sp_key_index(P->kind, &P->tok[0]);
        if (key >= 0)
            P->seen &= ~(1u << key);
        ok = rj__sp_assignments(P);
        if (ok && key >= 0)
            rj__sp_pos(P, key)->line = 0;
    } else if (P->code == RJ_OK)
        rj__sp_fail(P, k + 1, 1, "set", rj__sp_nan(), "expected KIND.NAME.KEY=VALUE");
    P->text = text;
    P->len = len;
    P->at = at;
    P->lineno = lineno;
    P->fname = fname;
    P->tok = tok;
    P->ntok = ntok;
    P->sets_done |= 1ull << k;
    return ok;
}

/* The changes for the section that ends here (its kind and its item's name). */
static int rj__sp_sets(rj__sp *P)
{
    int k;
    for (k = 0; k < P->nsets; k++) {
        rj__sp_set o;
        const char *name = rj__sp_item_name(P);
        if ((P->sets_done >> k & 1u) || !rj__sp_set_split(P->sets[k], &o) || o.kind != P->kind)
            continue;
        if (o.kind != RJ__SK_SOLVER &&
            (strlen(name) != (size_t) o.nlen || strncmp(name, o.name, (size_t) o.nlen) != 0))
            continue;
        if (!rj__sp_set_take(P, k, &o))
            return 0;
    }
    return 1;
}

/* Change k refused at column col of its own text ("--set:K:COL:"). */
static int rj__sp_set_fail(rj__sp *P, int k, int col, const char *msg)
{
    P->fname = "--set";
    return rj__sp_fail(P, k + 1, col, "set", rj__sp_nan(), msg);
}

/* After the file: changes of the solver when it has no section (the defaults take them),
   and a change that named no item of the file, or no kind: refused, naming it. */
static int rj__sp_sets_left(rj__sp *P)
{
    int k;
    for (k = 0; k < P->nsets; k++) {
        rj__sp_set o;
        char name[RJ_SCENE_NAME_MAX], m[200];
        if (P->sets_done >> k & 1u)
            continue;
        if (!rj__sp_set_split(P->sets[k], &o))
            return rj__sp_set_fail(P, k, 1,
                                   "a change is KIND.NAME.KEY=VALUE, or solver.KEY=VALUE; KIND "
                                   "is material, section, link, joint, load, actuator or "
                                   "coupling");
        if (o.kind == RJ__SK_SOLVER) {
            P->kind = RJ__SK_SOLVER;
            P->seen = 0;
            if (!rj__sp_set_take(P, k, &o))
                return 0;
            continue;
        }
        snprintf(name, sizeof name, "%.*s", o.nlen < RJ_SCENE_NAME_MAX ? o.nlen : 0, o.name);
        snprintf(m, sizeof m, "the file has no %s '%s' to change", rj__sk_kind[o.kind], name);
        return rj__sp_set_fail(P, k, (int) (o.name - P->sets[k]) + 1, m);
    }
    return 1;
}

/* checks and completes the section that ends here */
static int rj__sp_finish(rj__sp *P)
{
    char what[80];
    if (P->nsets && P->kind != RJ__SK_NONE && !rj__sp_sets(P))
        return 0;
    switch (P->kind) {
    case RJ__SK_NONE:
    case RJ__SK_SOLVER:
        break;
    case RJ__SK_MATERIAL:
        P->mat[P->item].mask = P->seen;
        break;
    case RJ__SK_SECTION: {
        rj__spart *s = &P->sec[P->item];
        s->mask = P->seen;
        rj__sp_cat(what, sizeof what, "section '", s->name, "'", NULL, NULL, NULL, NULL);
        if (!rj__sp_check_shape(P, s->mask, &s->d, s->pos + 1, s->pos[0], what))
            return 0;
        break;
    }
    case RJ__SK_LINK: {
        rj_link_def *d = &P->f->links[P->item];
        rj_scene_pos *pos = &P->f->link_pos_[(size_t) P->item * (1 + RJ__LK_N)];
        unsigned eff = P->seen;
        int k;
        if (P->link_mat >= 0)
            eff = rj__sp_take_material(&P->mat[P->link_mat], eff, d, pos);
        if (P->link_sec >= 0) {
            const rj__spart *s = &P->sec[P->link_sec];
            for (k = RJ__LK_AREA; k <= RJ__LK_LAYERS; k++) {
                if ((eff >> k & 1u) || !(s->mask >> k & 1u))
                    continue;
                switch (k) {
                case RJ__LK_AREA:
                    d->area = s->d.area;
                    break;
                case RJ__LK_INERTIA:
                    d->inertia = s->d.inertia;
                    break;
                case RJ__LK_WIDTH:
                    d->width = s->d.width;
                    break;
                case RJ__LK_HEIGHT:
                    d->height = s->d.height;
                    break;
                default:
                    d->layers = s->d.layers;
                    break;
                }
                pos[1 + k] = s->pos[1 + k];
            }
            eff |= s->mask;
        }
        rj__sp_cat(what, sizeof what, "link '", P->f->link_names[P->item], "'", NULL, NULL, NULL,
                   NULL);
        if (!rj__sp_check_shape(P, eff, d, pos + 1, pos[0], what))
            return 0;
        d->section = (eff & ((1u << RJ__LK_AREA) | (1u << RJ__LK_INERTIA))) ? RJ_SECTION_GENERAL
                                                                            : RJ_SECTION_RECT;
        break;
    }
    case RJ__SK_JOINT: {
        rj_joint_def *d = &P->f->joints[P->item];
        rj_scene_pos *pos = &P->f->joint_pos_[(size_t) P->item * (1 + RJ__JK_N)];
        const char *jn = P->f->joint_names[P->item];
        char a[24], b[24];
        int k;
        for (k = RJ__JK_BODY1; k <= RJ__JK_BODY2; k++)
            if (!(P->seen >> k & 1u))
                return rj__sp_err(P, pos[0].line, pos[0].col, rj__joint_fields[k].key, rj__sp_nan(),
                                  "joint '", jn, "' has no ", rj__joint_fields[k].key,
                                  k == RJ__JK_BODY1 ? " (ground or a link)" : " (a link)");
        if (d->body1 == d->body2)
            return rj__sp_err(P, pos[1 + RJ__JK_BODY2].line, pos[1 + RJ__JK_BODY2].col, "body2",
                              d->body2, "joint '", jn, "' connects link '",
                              P->f->link_names[d->body2], "' to itself (body1 = body2)");
        if (d->body1 < 0 && (P->seen >> RJ__JK_NODE1 & 1u))
            return rj__sp_err(P, pos[1 + RJ__JK_NODE1].line, pos[1 + RJ__JK_NODE1].col, "node1",
                              d->node1, "node1 applies only when body1 is a link, in joint '", jn,
                              "' (body1 = ground)", NULL, NULL);
        if (d->node2 > P->f->links[d->body2].elements) {
            char m[256];
            rj__sp_cat(m, sizeof m, "node2 = ", rj__sp_itoa(a, d->node2),
                       " is out of range in joint '", jn, "': link '",
                       P->f->link_names[d->body2], "' has nodes 0..");
            return rj__sp_err(P, pos[1 + RJ__JK_NODE2].line, pos[1 + RJ__JK_NODE2].col, "node2",
                              d->node2, m, rj__sp_itoa(b, P->f->links[d->body2].elements), NULL,
                              NULL, NULL);
        }
        if (d->body1 >= 0) {
            for (k = RJ__JK_GROUND_X; k <= RJ__JK_GROUND_ANGLE; k++)
                if (P->seen >> k & 1u)
                    return rj__sp_err(P, pos[1 + k].line, pos[1 + k].col, rj__joint_fields[k].key,
                                      rj__sp_nan(), rj__joint_fields[k].key,
                                      " applies only when body1 = ground, in joint '", jn, "'",
                                      NULL);
            if (d->node1 > P->f->links[d->body1].elements) {
                char m[256];
                rj__sp_cat(m, sizeof m, "node1 = ", rj__sp_itoa(a, d->node1),
                           " is out of range in joint '", jn, "': link '",
                           P->f->link_names[d->body1], "' has nodes 0..");
                return rj__sp_err(P, pos[1 + RJ__JK_NODE1].line, pos[1 + RJ__JK_NODE1].col, "node1",
                                  d->node1, m, rj__sp_itoa(b, P->f->links[d->body1].elements), NULL,
                                  NULL, NULL);
            }
        }
        break;
    }
    case RJ__SK_LOAD:
        if (!rj__sp_finish_load(P))
            return 0;
        break;
    case RJ__SK_ACTUATOR:
        if (!rj__sp_finish_actuator(P))
            return 0;
        break;
    case RJ__SK_COUPLING:
        if (!rj__sp_finish_coupling(P))
            return 0;
        break;
    }
    P->kind = RJ__SK_NONE;
    return 1;
}

static int rj__sp_header(rj__sp *P)
{
    const rj__stok *t0 = &P->tok[0], *nt;
    char nb[24];
    int kind = 0, k, cap = 0, count = 0, dup = -1;
    for (k = RJ__SK_SOLVER; k <= RJ__SK_COUPLING; k++)
        if (rj__sp_is(t0, rj__sk_kind[k]))
            kind = k;
    if (!kind) {
        /* "title Solar array": the key without its '=' */
        if (P->kind == RJ__SK_NONE && rj__sp_is(t0, "title"))
            return rj__sp_err(P, t0->line, t0->col + t0->len, "title", rj__sp_nan(),
                              "missing '=' after 'title' (write title = \"text\")", NULL, NULL,
                              NULL, NULL);
        if (P->kind != RJ__SK_NONE && rj__sp_key_index(P->kind, t0) >= 0) {
            const char *kn = rj__sp_key_name(P->kind, rj__sp_key_index(P->kind, t0));
            return rj__sp_err(P, t0->line, t0->col + t0->len, kn, rj__sp_nan(),
                              "missing '=' after '", kn, "'", rj__sp_where(P), NULL);
        }
        { /* a near section keyword, else a near key of the current section */
            const char *near =
                rj__sp_near(t0->s, t0->len, rj__sk_kind[1], sizeof rj__sk_kind[0], 8);
            char mean[48];
            if (!near && P->kind != RJ__SK_NONE)
                near = rj__sp_near_key(P, t0);
            return rj__sp_err_tok(
                P, t0, "", rj__sp_nan(),
                P->kind != RJ__SK_NONE ? "unknown key or section " : "unknown section ",
                P->kind != RJ__SK_NONE ? " (a key needs '= value'; sections are solver, material, "
                                         "section, link, joint, load, actuator, coupling)"
                                       : " (expected solver, material, section, link, joint, "
                                         "load, actuator or coupling)",
                rj__sp_mean(mean, near), NULL);
        }
    }
    if (!rj__sp_finish(P))
        return 0;
    if (kind == RJ__SK_SOLVER) {
        if (P->ntok > 1)
            return rj__sp_err_tok(P, &P->tok[1], "", rj__sp_nan(), "unexpected ",
                                  " after 'solver' (the solver section has no name)", NULL, NULL);
        if (P->solver_seen)
            return rj__sp_err(P, t0->line, t0->col, "solver", rj__sp_nan(),
                              "duplicate solver section (first on line ",
                              rj__sp_itoa(nb, P->f->solver_pos_[0].line), ")", NULL, NULL);
        P->solver_seen = 1;
        P->f->solver_pos_[0].line = t0->line;
        P->f->solver_pos_[0].col = t0->col;
        P->kind = kind;
        P->item = 0;
        P->seen = 0;
        return 1;
    }
    if (P->ntok < 2)
        return rj__sp_err(P, t0->line, t0->col + t0->len, rj__sk_kind[kind], rj__sp_nan(),
                          "missing name after '", rj__sk_kind[kind], "'", NULL, NULL);
    nt = &P->tok[1];
    if (nt->kind != 'w' || !rj__sp_name_ok(nt->s, nt->len))
        return rj__sp_err_tok(P, nt, rj__sk_kind[kind], rj__sp_nan(), "invalid name ", " after '",
                              rj__sk_kind[kind],
                              "' (1..31 of A-Z a-z 0-9 _ . -, starting with a letter or _)");
    if (P->ntok > 2)
        return rj__sp_err_tok(P, &P->tok[2], "", rj__sp_nan(), "unexpected ", " after the name of ",
                              rj__sk_kind[kind], " (one statement per line)");
    switch (kind) {
    case RJ__SK_MATERIAL:
        cap = RJ_SCENE_MAX_MATERIALS;
        count = P->nmat;
        if (count)
            dup = rj__sp_find(nt->s, nt->len, P->mat[0].name, sizeof(rj__spart), count);
        break;
    case RJ__SK_SECTION:
        cap = RJ_SCENE_MAX_SECTIONS;
        count = P->nsec;
        if (count)
            dup = rj__sp_find(nt->s, nt->len, P->sec[0].name, sizeof(rj__spart), count);
        break;
    case RJ__SK_LINK:
        cap = RJ_SCENE_MAX_LINKS;
        count = P->f->link_count;
        if (count)
            dup = rj__sp_find(nt->s, nt->len, (const char *) P->f->link_names, RJ_SCENE_NAME_MAX,
                              count);
        break;
    case RJ__SK_LOAD:
        cap = RJ_SCENE_MAX_LOADS;
        count = P->f->load_count;
        if (count)
            dup = rj__sp_find(nt->s, nt->len, (const char *) P->f->load_names, RJ_SCENE_NAME_MAX,
                              count);
        break;
    case RJ__SK_ACTUATOR:
        cap = RJ_SCENE_MAX_ACTUATORS;
        count = P->f->actuator_count;
        if (count)
            dup = rj__sp_find(nt->s, nt->len, (const char *) P->f->actuator_names,
                              RJ_SCENE_NAME_MAX, count);
        break;
    case RJ__SK_COUPLING:
        cap = RJ_SCENE_MAX_COUPLINGS;
        count = P->f->coupling_count;
        if (count)
            dup = rj__sp_find(nt->s, nt->len, (const char *) P->f->coupling_names,
                              RJ_SCENE_NAME_MAX, count);
        break;
    default:
        cap = RJ_SCENE_MAX_JOINTS;
        count = P->f->joint_count;
        if (count)
            dup = rj__sp_find(nt->s, nt->len, (const char *) P->f->joint_names, RJ_SCENE_NAME_MAX,
                              count);
        break;
    }
    if (dup >= 0) {
        int line = kind == RJ__SK_MATERIAL  ? P->mat[dup].pos[0].line
                   : kind == RJ__SK_SECTION ? P->sec[dup].pos[0].line
                   : kind == RJ__SK_LINK    ? P->f->link_pos_[(size_t) dup * (1 + RJ__LK_N)].line
                   : kind == RJ__SK_LOAD    ? P->f->load_pos_[(size_t) dup * (1 + RJ__AK_N)].line
                   : kind == RJ__SK_ACTUATOR
                       ? P->f->actuator_pos_[(size_t) dup * (1 + RJ__CK_N)].line
                   : kind == RJ__SK_COUPLING
                       ? P->f->coupling_pos_[(size_t) dup * (1 + RJ__PK_N)].line
                                            : P->f->joint_pos_[(size_t) dup * (1 + RJ__JK_N)].line;
        char pre[40];
        rj__sp_cat(pre, sizeof pre, "duplicate ", rj__sk_kind[kind], " name ", NULL, NULL, NULL,
                   NULL);
        return rj__sp_err_tok(P, nt, rj__sk_kind[kind], rj__sp_nan(), pre,
                              " (first defined on line ", rj__sp_itoa(nb, line), ")");
    }
    if (kind == RJ__SK_LINK && rj__sp_is(nt, "ground"))
        return rj__sp_err_tok(P, nt, "link", rj__sp_nan(), "a link cannot be named ",
                              " (reserved for body1 = ground)", NULL, NULL);
    { /* the counting pass sized the arrays; it never counts fewer items than there are */
        int room = kind == RJ__SK_MATERIAL  ? P->cap_mat
                   : kind == RJ__SK_SECTION ? P->cap_sec
                   : kind == RJ__SK_LINK    ? P->cap_links
                   : kind == RJ__SK_LOAD    ? P->cap_loads
                   : kind == RJ__SK_ACTUATOR ? P->cap_acts
                   : kind == RJ__SK_COUPLING ? P->cap_cps
                                            : P->cap_joints;
        if (count >= cap || count >= room)
            return rj__sp_err(P, t0->line, t0->col, rj__sk_kind[kind], count + 1, "too many ",
                              rj__sk_kind[kind], " sections (at most ", rj__sp_itoa(nb, cap), ")");
    }
    {
        rj_scene_pos head;
        head.line = t0->line;
        head.col = t0->col;
        switch (kind) {
        case RJ__SK_MATERIAL:
        case RJ__SK_SECTION: {
            rj__spart *s = kind == RJ__SK_MATERIAL ? &P->mat[P->nmat++] : &P->sec[P->nsec++];
            memset(s, 0, sizeof *s);
            memcpy(s->name, nt->s, (size_t) nt->len);
            s->d = rj_default_link_def();
            s->pos[0] = head;
            break;
        }
        case RJ__SK_LINK: {
            int n = P->f->link_count++;
            memcpy(P->f->link_names[n], nt->s, (size_t) nt->len);
            P->f->link_names[n][nt->len] = 0;
            P->f->links[n] = rj_default_link_def();
            P->f->link_pos_[(size_t) n * (1 + RJ__LK_N)] = head;
            P->link_mat = -1;
            P->link_sec = -1;
            break;
        }
        case RJ__SK_LOAD: {
            int n = P->f->load_count++;
            memcpy(P->f->load_names[n], nt->s, (size_t) nt->len);
            P->f->load_names[n][nt->len] = 0;
            P->f->loads[n] = rj_default_load_def();
            P->f->load_pos_[(size_t) n * (1 + RJ__AK_N)] = head;
            break;
        }
        case RJ__SK_ACTUATOR: {
            int n = P->f->actuator_count++;
            memcpy(P->f->actuator_names[n], nt->s, (size_t) nt->len);
            P->f->actuator_names[n][nt->len] = 0;
            P->f->actuators[n] = rj_default_actuator_def();
            P->f->actuator_pos_[(size_t) n * (1 + RJ__CK_N)] = head;
            break;
        }
        case RJ__SK_COUPLING: {
            int n = P->f->coupling_count++;
            memcpy(P->f->coupling_names[n], nt->s, (size_t) nt->len);
            P->f->coupling_names[n][nt->len] = 0;
            P->f->couplings[n] = rj_default_coupling_def();
            P->f->coupling_pos_[(size_t) n * (1 + RJ__PK_N)] = head;
            break;
        }
        default: {
            int n = P->f->joint_count++;
            memcpy(P->f->joint_names[n], nt->s, (size_t) nt->len);
            P->f->joint_names[n][nt->len] = 0;
            P->f->joints[n] = rj_default_joint_def();
            P->f->joint_pos_[(size_t) n * (1 + RJ__JK_N)] = head;
            break;
        }
        }
        P->kind = kind;
        P->item = count;
        P->seen = 0;
    }
    return 1;
}

/* text after a complete value of key kn at toks[v]; a unit word right after a number
   ("length = 1 m", "E = 70 GPa") gets why numbers take none */
static int rj__sp_trailing(rj__sp *P, int v, const char *kn)
{
    const rj__stok *t = &P->tok[v], *n = &P->tok[v - 1];
    char q[200], h[200], m[256];
    double x;
    h[0] = 0;
    if (t->kind == 'w' && rj__sp_alpha((unsigned char) t->s[0]) && n->kind == 'w' &&
        rj__sp_strtonum(n->s, n->len, P->dp, P->dplen, &x) == 1)
        rj__sp_unit_hint(h, kn, rj__sp_unit(kn), n->s, n->len, t->s, t->len);
    rj__sp_quote(q, sizeof q, t->s, t->len);
    rj__sp_cat(m, sizeof m, "unexpected '", q, "' after the value of '", kn, "'", rj__sp_where(P),
               h);
    return rj__sp_fail(P, t->line, t->col, kn, rj__sp_nan(), m);
}

/* whether toks[v] is a unit word after the number that starts the value of kn: checked
   before the value, so "dt = 10 us" says so instead of that 10 s is out of range. Not for
   angles and tables, whose numbers take deg or rad. */
static int rj__sp_unit_word(const rj__sp *P, int v, const char *kn)
{
    const rj__stok *t = &P->tok[v], *n = &P->tok[v - 1];
    const char *u = rj__sp_unit(kn);
    double x;
    if (strcmp(u, "rad") == 0 || strcmp(u, "rad/s") == 0 || strcmp(kn, "table") == 0)
        return 0;
    /* nan and inf spelled out are numbers, not units: the value's parse names them */
    if (t->kind == 'w' && rj__sp_strtonum(t->s, t->len, P->dp, P->dplen, &x) == -1)
        return 0;
    return t->kind == 'w' && rj__sp_alpha((unsigned char) t->s[0]) && n->kind == 'w' &&
           rj__sp_strtonum(n->s, n->len, P->dp, P->dplen, &x) == 1;
}

/* ------------------------------------------------------------------ title */
/* The first byte of a title that a file cannot hold on one line (a control byte: tab, CR),
   -1 when there is none. The writer refuses the same bytes, so what it writes reads back. */
static int rj__sp_title_bad(const char *s, int n)
{
    int k;
    for (k = 0; k < n; k++) {
        unsigned char c = (unsigned char) s[k];
        if (c < 0x20 || c == 0x7f)
            return k;
    }
    return -1;
}

/* a title's value: one quoted string, at most RJ_SCENE_TITLE_MAX - 1 bytes of text */
static int rj__sp_title_value(rj__sp *P, const rj__stok *v)
{
    char a[24], b[24], m[120];
    int n = v->len - 2;
    int bad;
    if (v->kind != 'q')
        return rj__sp_err_tok(P, v, "title", rj__sp_nan(), "expected a quoted string, found ",
                              " for 'title' (write title = \"text\")", NULL, NULL);
    if (n >= RJ_SCENE_TITLE_MAX) {
        rj__sp_cat(m, sizeof m, "title of ", rj__sp_itoa(a, n), " bytes is too long (at most ",
                   rj__sp_itoa(b, RJ_SCENE_TITLE_MAX - 1), ")", NULL, NULL);
        return rj__sp_fail(P, v->line, v->col, "title", (double) n, m);
    }
    bad = rj__sp_title_bad(v->s + 1, n);
    if (bad >= 0) {
        snprintf(m, sizeof m, "byte 0x%02x in the title: a title is printable text (no tabs)",
                 (unsigned char) v->s[1 + bad]);
        return rj__sp_fail(P, v->line, v->col + 1 + bad, "title", rj__sp_nan(), m);
    }
    memcpy(P->f->title, v->s + 1, (size_t) n);
    P->f->title[n] = 0;
    return 1;
}

/* title = "text", before the first section (toks[i..j)): once, a value, nothing after it */
static int rj__sp_title(rj__sp *P, int i, int j)
{
    const rj__stok *kt = &P->tok[i];
    char nb[24];
    if (P->title_line)
        return rj__sp_err(P, kt->line, kt->col, "title", rj__sp_nan(),
                          "duplicate title (first set on line ", rj__sp_itoa(nb, P->title_line),
                          ")", NULL, NULL);
    if (j == i + 2)
        return rj__sp_err(P, P->tok[i + 1].line, P->tok[i + 1].col + 1, "title", rj__sp_nan(),
                          "missing value for 'title'", NULL, NULL, NULL, NULL);
    if (!rj__sp_title_value(P, &P->tok[i + 2]))
        return 0;
    if (j > i + 3)
        return rj__sp_trailing(P, i + 3, "title");
    P->title_line = kt->line;
    return 1;
}

static int rj__sp_assignments(rj__sp *P)
{
    int i = 0;
    char nb[24];
    while (i < P->ntok) {
        const rj__stok *kt = &P->tok[i];
        const char *kn;
        int j = i + 2, k, v;
        while (j < P->ntok &&
               !(P->tok[j].kind == 'w' && j + 1 < P->ntok && P->tok[j + 1].kind == '='))
            j++;
        /* the one statement outside a section: the title, before the first section */
        if (P->kind == RJ__SK_NONE && rj__sp_is(kt, "title")) {
            if (!rj__sp_title(P, i, j))
                return 0;
            i = j;
            continue;
        }
        if (P->kind == RJ__SK_NONE) {
            char mean[48];
            return rj__sp_err_tok(
                P, kt, "", rj__sp_nan(), "key ",
                " outside any section (start one with solver, material, section, link, joint, "
                "load, actuator or coupling)",
                rj__sp_mean(mean, rj__sp_near(kt->s, kt->len, "title", 6, 1)), NULL);
        }
        k = rj__sp_key_index(P->kind, kt);
        /* a title inside a section: say where it belongs */
        if (k < 0 && rj__sp_is(kt, "title"))
            return rj__sp_err_tok(
                P, kt, "title", rj__sp_nan(), "unknown key ", rj__sp_where(P),
                " (a title goes at the top of the file, before the first section)", NULL);
        if (k < 0) {
            char q[64], mean[48];
            rj__sp_quote(q, sizeof q, kt->s, kt->len);
            return rj__sp_err_tok(P, kt, q, rj__sp_nan(), "unknown key ", rj__sp_where(P),
                                  rj__sp_mean(mean, rj__sp_near_key(P, kt)), NULL);
        }
        kn = rj__sp_key_name(P->kind, k);
        if (P->seen >> k & 1u)
            return rj__sp_err_tok5(P, kt, kn, rj__sp_nan(), "duplicate key ", rj__sp_where(P),
                                   " (first set on line ", rj__sp_itoa(nb, rj__sp_pos(P, k)->line),
                                   ")");
        if (j == i + 2) {
            const rj__stok *eq = &P->tok[i + 1];
            return rj__sp_err(P, eq->line, eq->col + 1, kn, rj__sp_nan(), "missing value for '", kn,
                              "'", rj__sp_where(P), NULL);
        }
        if (j > i + 3 && rj__sp_unit_word(P, i + 3, kn))
            return rj__sp_trailing(P, i + 3, kn);
        v = i + 2;
        switch (P->kind) {
        case RJ__SK_SOLVER:
            if (!rj__sp_solver_key(P, k, i + 2, &v, j, &P->f->solver))
                return 0;
            break;
        case RJ__SK_MATERIAL:
            if (!rj__sp_link_key(P, k, i + 2, &v, j, &P->mat[P->item].d))
                return 0;
            break;
        case RJ__SK_SECTION:
            if (!rj__sp_link_key(P, k, i + 2, &v, j, &P->sec[P->item].d))
                return 0;
            break;
        case RJ__SK_LINK:
            if (!rj__sp_link_key(P, k, i + 2, &v, j, &P->f->links[P->item]))
                return 0;
            break;
        case RJ__SK_LOAD:
            if (!rj__sp_load_key(P, k, i + 2, &v, j, &P->f->loads[P->item]))
                return 0;
            break;
        case RJ__SK_ACTUATOR:
            if (!rj__sp_actuator_key(P, k, i + 2, &v, j, &P->f->actuators[P->item]))
                return 0;
            break;
        case RJ__SK_COUPLING:
            if (!rj__sp_coupling_key(P, k, i + 2, &v, j, &P->f->couplings[P->item]))
                return 0;
            break;
        default:
            if (!rj__sp_joint_key(P, k, i + 2, &v, j, &P->f->joints[P->item]))
                return 0;
            break;
        }
        if (v < j)
            return rj__sp_trailing(P, v, kn);
        P->seen |= 1u << k;
        rj__sp_pos(P, k)->line = P->tok[i + 2].line;
        rj__sp_pos(P, k)->col = P->tok[i + 2].col;
        i = j;
    }
    return 1;
}

/* ------------------------------------------------------------------ lines */
static int rj__sp_is_sep(unsigned char c)
{
    return c == ' ' || c == '\t' || c == '=' || c == ',' || c == '#' || c < 0x20 || c == 0x7f;
}

/* Text is printable bytes, tabs and line ends (LF, CR). A NUL or another control byte
   anywhere, comments included, means the input is not a scene file, most likely a binary
   one: say so, with the first such byte and where it is, before parsing reports whatever
   its first "line" happens to look like (often one longer than RJ_SCENE_MAX_LINE). */
static int rj__sp_text(rj__sp *P)
{
    size_t k, bol = 0;
    int line = 1;
    for (k = 0; k < P->len; k++) {
        unsigned char c = (unsigned char) P->text[k];
        char m[200];
        if (c == '\n') {
            line++;
            bol = k + 1;
            continue;
        }
        if ((c >= 0x20 && c != 0x7f) || c == '\t' || c == '\r')
            continue;
        snprintf(m, sizeof m,
                 "not a text scene file: byte 0x%02x at byte offset %lu is a %s (a scene file has "
                 "only printable characters, tabs and line ends)",
                 c, (unsigned long) k, c ? "control character" : "NUL");
        return rj__sp_fail(P, line, (int) (k - bol) + 1, "", (double) c, m);
    }
    return 1;
}

/* a quoted string at s (its opening '"'), rest bytes to the line end, at column *k + 1:
   a 'q' token with the quotes, *k past it; 0 (the error set) when the line has no closing
   '"'. Titles need spaces, which separate tokens everywhere else. */
static int rj__sp_quoted(rj__sp *P, const char *s, size_t rest, size_t *k)
{
    const char *close = rest > 1 ? (const char *) memchr(s + 1, '"', rest - 1) : NULL;
    rj__stok *t = &P->tok[P->ntok];
    if (!close)
        return rj__sp_fail(P, P->lineno, (int) *k + 1, "", rj__sp_nan(),
                           "unterminated string: no closing '\"' on this line");
    t->s = s;
    t->len = (int) (close - s) + 1;
    t->line = P->lineno;
    t->col = (int) *k + 1;
    t->kind = 'q';
    P->ntok++;
    *k += (size_t) t->len;
    return 1;
}

/* next statement into P->tok: returns 1 (maybe empty), 0 at the end, -1 on error.
   A line whose last token is ',' continues on the next line. */
static int rj__sp_next(rj__sp *P)
{
    P->ntok = 0;
    if (P->at >= P->len)
        return 0;
    for (;;) {
        size_t start = P->at, end = start, n, k;
        char m[120];
        while (end < P->len && P->text[end] != '\n')
            end++;
        n = end - start;
        if (n && P->text[end - 1] == '\r')
            n--;
        P->lineno++;
        P->at = end < P->len ? end + 1 : end;
        if (n > RJ_SCENE_MAX_LINE) {
            snprintf(m, sizeof m, "line is longer than %d characters", RJ_SCENE_MAX_LINE);
            rj__sp_fail(P, P->lineno, RJ_SCENE_MAX_LINE + 1, "", rj__sp_nan(), m);
            return -1;
        }
        for (k = 0; k < n;) {
            const char *s = P->text + start + k;
            unsigned char c = (unsigned char) *s;
            if (c == '#')
                break;
            if (c == ' ' || c == '\t') {
                k++;
                continue;
            }
            if (c < 0x20 || c == 0x7f) { /* only a CR gets here: rj__sp_text let no other through */
                snprintf(m, sizeof m,
                         "invalid character 0x%02x (a carriage return ends a line only before a "
                         "line feed)",
                         c);
                rj__sp_fail(P, P->lineno, (int) k + 1, "", rj__sp_nan(), m);
                return -1;
            }
            if (P->ntok == RJ_SCENE_MAX_TOKENS) {
                snprintf(m, sizeof m, "statement has more than %d tokens", RJ_SCENE_MAX_TOKENS);
                rj__sp_fail(P, P->lineno, (int) k + 1, "", rj__sp_nan(), m);
                return -1;
            }
            /* a quoted string runs to the next '"' on the same line (no escapes) */
            if (c == '"') {
                if (!rj__sp_quoted(P, s, n - k, &k))
                    return -1;
                continue;
            }
            {
                rj__stok *t = &P->tok[P->ntok++];
                t->s = s;
                t->line = P->lineno;
                t->col = (int) k + 1;
                if (c == '=' || c == ',') {
                    t->kind = (char) c;
                    t->len = 1;
                    k++;
                } else {
                    size_t e = k + 1;
                    while (e < n && !rj__sp_is_sep((unsigned char) P->text[start + e]))
                        e++;
                    t->kind = 'w';
                    t->len = (int) (e - k);
                    k = e;
                }
            }
        }
        if (!(P->ntok > 0 && P->tok[P->ntok - 1].kind == ',' && P->at < P->len))
            return 1;
    }
}

/* counting pass: an upper bound on each kind of section (a first word that is a section
   keyword and is not followed by '='), capped one above the limits */
static void rj__sp_count(const char *text, size_t len, int counts[RJ__SK_COUNT])
{
    size_t at = 0;
    int k;
    for (k = 0; k < RJ__SK_COUNT; k++)
        counts[k] = 0;
    while (at < len) {
        size_t e, w;
        while (at < len && (text[at] == ' ' || text[at] == '\t'))
            at++;
        w = at;
        while (at < len && !rj__sp_is_sep((unsigned char) text[at]))
            at++;
        e = at;
        while (at < len && (text[at] == ' ' || text[at] == '\t'))
            at++;
        if (e > w && !(at < len && text[at] == '=')) {
            for (k = RJ__SK_MATERIAL; k <= RJ__SK_COUPLING; k++) {
                size_t n = strlen(rj__sk_kind[k]);
                if (e - w == n && memcmp(text + w, rj__sk_kind[k], n) == 0) {
                    int cap = k == RJ__SK_MATERIAL  ? RJ_SCENE_MAX_MATERIALS
                              : k == RJ__SK_SECTION ? RJ_SCENE_MAX_SECTIONS
                              : k == RJ__SK_LINK    ? RJ_SCENE_MAX_LINKS
                              : k == RJ__SK_LOAD    ? RJ_SCENE_MAX_LOADS
                              : k == RJ__SK_ACTUATOR ? RJ_SCENE_MAX_ACTUATORS
                              : k == RJ__SK_COUPLING ? RJ_SCENE_MAX_COUPLINGS
                                                    : RJ_SCENE_MAX_JOINTS;
                    if (counts[k] < cap)
                        counts[k]++;
                }
            }
        }
        while (at < len && text[at] != '\n')
            at++;
        if (at < len)
            at++;
    }
}

static size_t rj__sp_carve(size_t *off, size_t n, size_t el)
{
    size_t at = (*off + 15) / 16 * 16;
    *off = at + n * el;
    return at;
}

/* field "loads[2].force[1]" (prefix "loads[") -> position in f: the key's value, else
   the item's section line. Items of count, their positions (1 + nk per item), names,
   kind's rows; what: "load". */
static int rj__sp_item_pos(const char *field, const char *prefix, int count,
                           const rj_scene_pos *all, char (*names)[RJ_SCENE_NAME_MAX], int kind,
                           const char *what, rj_scene_pos *pos, char *item, size_t isize)
{
    const rj_scene_pos *ap;
    const char *p = field + strlen(prefix);
    const int nk = rj__key_count(kind);
    int n, idx = 0, digits = 0, k;
    const rj__field *rows = rj__fields(kind, &n);
    while (*p >= '0' && *p <= '9' && digits < 7) {
        idx = idx * 10 + (*p - '0');
        p++;
        digits++;
    }
    if (!digits || *p != ']' || idx >= count)
        return 0;
    p++;
    ap = &all[(size_t) idx * (1 + nk)];
    *pos = ap[0];
    for (k = 0; k < n && *p == '.'; k++) {
        /* the member's name, or the key's at its start ("table" of "table_time[2]") */
        const int key = rows[k].part_of >= 0 ? rows[k].part_of : k;
        const char *member = rows[k].member[0] ? rows[k].member : rows[k].key;
        const size_t len = strlen(member), klen = strlen(rows[k].key);
        const int named = strncmp(p + 1, member, len) == 0 &&
                          (p[1 + len] == 0 || p[1 + len] == '[');
        if (key < nk && (named || strncmp(p + 1, rows[k].key, klen) == 0) && ap[1 + key].line)
            *pos = ap[1 + key];
    }
    rj__sp_cat(item, isize, " (", what, " '", names[idx], "')", NULL, NULL);
    return pos->line > 0;
}

/* field "links[3].rho" / "joints[1].table_angle[2]" / "solver.dt" -> position in f */
static int rj__sp_field_pos(const rj_scene_file *f, const char *field, rj_scene_pos *pos,
                            char *item, size_t isize)
{
    int idx = 0, k, digits = 0, joint;
    const char *p;
    char name[40];
    size_t n = 0;
    item[0] = 0;
    if (strncmp(field, "solver.", 7) == 0) {
        for (k = 0; k < RJ__VK_N; k++)
            if (strcmp(field + 7, rj__solver_fields[k].key) == 0 && f->solver_pos_[1 + k].line) {
                *pos = f->solver_pos_[1 + k];
                return 1;
            }
        if (f->solver_pos_[0].line) {
            *pos = f->solver_pos_[0];
            return 1;
        }
        return 0;
    }
    if (strncmp(field, "loads[", 6) == 0)
        return rj__sp_item_pos(field, "loads[", f->load_count, f->load_pos_, f->load_names,
                               RJ__DEF_LOAD, "load", pos, item, isize);
    if (strncmp(field, "couplings[", 10) == 0)
        return rj__sp_item_pos(field, "couplings[", f->coupling_count, f->coupling_pos_,
                               f->coupling_names, RJ__DEF_COUPLING, "coupling", pos, item, isize);
    if (strncmp(field, "actuators[", 10) == 0)
        return rj__sp_item_pos(field, "actuators[", f->actuator_count, f->actuator_pos_,
                               f->actuator_names, RJ__DEF_ACTUATOR, "actuator", pos, item, isize);
    if (strncmp(field, "links[", 6) == 0) {
        joint = 0;
        p = field + 6;
    } else if (strncmp(field, "joints[", 7) == 0) {
        joint = 1;
        p = field + 7;
    } else
        return 0;
    while (*p >= '0' && *p <= '9' && digits < 7) {
        idx = idx * 10 + (*p - '0');
        p++;
        digits++;
    }
    if (!digits || *p != ']')
        return 0;
    p++;
    if (joint ? idx >= f->joint_count : idx >= f->link_count)
        return 0;
    if (*p == '.') {
        p++;
        while (p[n] && p[n] != '[' && n + 1 < sizeof name) {
            name[n] = p[n];
            n++;
        }
    }
    name[n] = 0;
    rj__sp_cat(item, isize, joint ? " (joint '" : " (link '",
               joint ? f->joint_names[idx] : f->link_names[idx], "')", NULL, NULL, NULL, NULL);
    if (!joint) {
        const rj_scene_pos *lp = &f->link_pos_[(size_t) idx * (1 + RJ__LK_N)];
        *pos = lp[0];
        for (k = 0; k < RJ__LK_N; k++)
            if (strcmp(name, rj__link_fields[k].key) == 0 && lp[1 + k].line)
                *pos = lp[1 + k];
        if (strcmp(name, "section") == 0) {
            if (lp[1 + RJ__LK_SECTION].line)
                *pos = lp[1 + RJ__LK_SECTION];
            else if (lp[1 + RJ__LK_AREA].line)
                *pos = lp[1 + RJ__LK_AREA];
        }
    } else {
        const rj_scene_pos *jp = &f->joint_pos_[(size_t) idx * (1 + RJ__JK_N)];
        int key = -1;
        *pos = jp[0];
        /* the key of the member's row, or of the key it is a part of */
        for (k = 0; k < RJ__JF_N; k++)
            if (strcmp(name, rj__joint_fields[k].member) == 0)
                key = rj__joint_fields[k].part_of >= 0 ? rj__joint_fields[k].part_of : k;
        if (strncmp(name, "table_", 6) == 0)
            key = RJ__JK_TABLE;
        if (key == RJ__JK_PENALTY_K && !jp[1 + key].line)
            key = RJ__JK_METHOD;
        if (key == RJ__JK_FORWARD && !jp[1 + key].line)
            key = RJ__JK_REVERSE;
        if (key >= 0 && jp[1 + key].line)
            *pos = jp[1 + key];
    }
    return pos->line > 0;
}

/* ------------------------------------------------------------------ links cut into pieces
   fidelity = pieces is the file's own link model, the rigid-finite-element layout of
   deploy_segmented_scene (examples/scenes.h): once the file and its changes are read, a
   link of N = elements segments of l = length / N becomes N + 1 rigid links (the two end
   pieces l / 2 long, the others l; the tip mass on the last) joined by N joints with a
   bending spring E I / l, free and started straight (180 deg). The pieces take the link's
   place among the links, named NAME (the first), NAME_p1 .. NAME_pN; its springs NAME_b1 ..
   NAME_bN follow the first joint that holds the link as body2 (else the file's joints).
   Node k of the link (at k l from its root) is piece k's middle for 0 < k < N (that
   piece then has 2 elements: a rigid link's mass and inertia do not depend on them),
   node 0 the first piece's root, node N the last piece's tip. The arrays grow in place:
   the counting pass gave them the most links and joints a scene may have when the text
   says "pieces" (rj__sp_says_pieces). */
typedef struct rj__sp_plan {
    int n[RJ_SCENE_MAX_LINKS];             /* each file link's segments when cut, else 0 */
    int base[RJ_SCENE_MAX_LINKS];          /* its first link after the cut */
    int bend[RJ_SCENE_MAX_LINKS];          /* a cut link's first spring joint, -1 none yet */
    double k[RJ_SCENE_MAX_LINKS];          /* a cut link's spring stiffness E I / l */
    int jnew[RJ_SCENE_MAX_JOINTS];         /* each file joint's index after the cut */
    unsigned char mid[RJ_SCENE_MAX_LINKS]; /* links after the cut with a middle node */
    int tail;                              /* the first spring that follows no file joint */
    int links, joints;                     /* the counts after the cut */
} rj__sp_plan;

/* whether "pieces" is anywhere in the text or the changes (in a comment too: that only
   costs the room) */
static int rj__sp_says_pieces(const char *text, size_t len, const char *const *sets, int nsets)
{
    size_t k;
    int s;
    for (k = 0; k + 6 <= len; k++)
        if (text[k] == 'p' && memcmp(text + k, "pieces", 6) == 0)
            return 1;
    for (s = 0; s < nsets; s++)
        if (strstr(sets[s], "pieces"))
            return 1;
    return 0;
}

/* where key k of file link i is written: its value, else the link's section line */
static rj_scene_pos rj__sp_link_at(const rj_scene_file *f, int i, int k)
{
    const rj_scene_pos *p = &f->link_pos_[(size_t) i * (1 + RJ__LK_N)];
    return p[1 + k].line ? p[1 + k] : p[0];
}

/* node k of a link cut into n segments (-1: its last): the piece holding it and that
   piece's node (the middle, 1, of an inner piece; -1 stays last) */
static void rj__sp_piece_node(int n, int k, int *piece, int *node)
{
    *piece = k < 0 ? n : k;
    *node = k < 0 ? -1 : k == 0 ? 0 : 1;
}

/* "NAME", or "NAME_p3" (tag "_p", k 3) */
static void rj__sp_piece_name(char *dst, const char *name, const char *tag, int k)
{
    char nb[24];
    rj__sp_cat(dst, RJ_SCENE_NAME_MAX, name, k ? tag : NULL, k ? rj__sp_itoa(nb, k) : NULL, NULL,
               NULL, NULL, NULL);
}

/* more links (links 1) or joints (0) after the cut, total, than a scene may have, max:
   refused at the elements of the link cut into the most pieces, naming the counts */
static int rj__sp_cut_over(rj__sp *P, const rj__sp_plan *pl, int links, int total, int max)
{
    const rj_scene_file *f = P->f;
    char a[24], b[24], c[24], d[24], m[256], m2[256];
    rj_scene_pos at;
    int i, big = 0;
    for (i = 1; i < f->link_count; i++)
        if (pl->n[i] > pl->n[big])
            big = i;
    at = rj__sp_link_at(f, big, RJ__LK_ELEMENTS);
    rj__sp_cat(m, sizeof m, "elements = ", rj__sp_itoa(a, pl->n[big]), " in link '",
               f->link_names[big], "' (fidelity = pieces) makes ",
               rj__sp_itoa(b, pl->n[big] + links), links ? " rigid pieces" : " bending joints");
    rj__sp_cat(m2, sizeof m2, m, ": the scene would have ", rj__sp_itoa(c, total),
               links ? " links" : " joints", ", more than the ", rj__sp_itoa(d, max), NULL);
    return rj__sp_err(P, at.line, at.col, "elements", pl->n[big], m2, " a scene may have", NULL,
                      NULL, NULL);
}

/* The links after the cut: where each file link goes, its segments and spring stiffness;
   refused when they are more than a scene may have (the cap is RJ_SCENE_MAX_LINKS when
   the text says "pieces") or a piece's name would be too long. */
static int rj__sp_plan_links(rj__sp *P, rj__sp_plan *pl)
{
    const rj_scene_file *f = P->f;
    int i, at = 0;
    for (i = 0; i < f->link_count; i++) {
        pl->n[i] = P->pieces[i] ? f->links[i].elements : 0;
        pl->base[i] = at;
        pl->bend[i] = -1;
        at += pl->n[i] + 1;
    }
    if (at > P->cap_links)
        return rj__sp_cut_over(P, pl, 1, at, P->cap_links);
    pl->links = at;
    for (i = 0; i < f->link_count; i++) {
        const rj_link_def *d = &f->links[i];
        char nb[24], last[64];
        double A, I;
        if (!pl->n[i])
            continue;
        rj__sp_cat(last, sizeof last, f->link_names[i], "_p", rj__sp_itoa(nb, pl->n[i]), NULL, NULL,
                   NULL, NULL);
        if (strlen(last) >= RJ_SCENE_NAME_MAX) {
            const rj_scene_pos h = f->link_pos_[(size_t) i * (1 + RJ__LK_N)];
            return rj__sp_err(P, h.line, h.col, "link", rj__sp_nan(), "link name '",
                              f->link_names[i],
                              "' is too long for fidelity = pieces: its last piece would be '",
                              last, "' (names are 1..31 characters)");
        }
        /* the flexible link's E I (rj__link_section), over the segment's length */
        rj__link_section(d, &A, &I);
        pl->k[i] = d->E * I / (d->length / pl->n[i]);
    }
    return 1;
}

/* A joint's body2 on cut link: the first piece's root, node2 = 0, the one node it can be
   (the pieces hang from it, each from the one before) */
static int rj__sp_cut_node2(rj__sp *P, int j)
{
    const rj_scene_file *f = P->f;
    const rj_joint_def *d = &f->joints[j];
    const rj_scene_pos *p = &f->joint_pos_[(size_t) j * (1 + RJ__JK_N)];
    const rj_scene_pos at = p[1 + RJ__JK_NODE2].line ? p[1 + RJ__JK_NODE2] : p[0];
    char a[24], m[256];
    rj__sp_cat(m, sizeof m, "node2 = ", d->node2 < 0 ? "last" : rj__sp_itoa(a, d->node2),
               " in joint '", f->joint_names[j], "' cannot be placed: link '",
               f->link_names[d->body2], "' is cut into pieces (fidelity = pieces)");
    return rj__sp_err(P, at.line, at.col, "node2", d->node2, m,
                      ", which hang from its node 0: a joint holds it there (node2 = 0)", NULL,
                      NULL, NULL);
}

/* The joints after the cut (as many as the file's and the cut links' segments; the cap
   is RJ_SCENE_MAX_JOINTS when the text says "pieces"): each file joint's index, each cut
   link's springs after the first joint that holds it as body2 (else after the file's
   joints); the inner pieces a joint's node1 or a load's node sits in the middle of. */
static int rj__sp_plan_joints(rj__sp *P, rj__sp_plan *pl)
{
    const rj_scene_file *f = P->f;
    int i, j, at = 0;
    pl->joints = f->joint_count;
    for (i = 0; i < f->link_count; i++)
        pl->joints += pl->n[i];
    if (pl->joints > P->cap_joints)
        return rj__sp_cut_over(P, pl, 0, pl->joints, P->cap_joints);
    for (j = 0; j < f->joint_count; j++) {
        const rj_joint_def *d = &f->joints[j];
        pl->jnew[j] = at++;
        if (pl->n[d->body2] && d->node2 != 0)
            return rj__sp_cut_node2(P, j);
        if (pl->n[d->body2] && pl->bend[d->body2] < 0) {
            pl->bend[d->body2] = at;
            at += pl->n[d->body2];
        }
        if (d->body1 >= 0 && d->node1 > 0 && d->node1 < pl->n[d->body1])
            pl->mid[pl->base[d->body1] + d->node1] = 1;
    }
    pl->tail = at;
    for (i = 0; i < f->link_count; i++)
        if (pl->n[i] && pl->bend[i] < 0) {
            pl->bend[i] = at;
            at += pl->n[i];
        }
    for (i = 0; i < f->load_count; i++) {
        const rj_load_def *d = &f->loads[i];
        if (d->node > 0 && d->node < pl->n[d->link])
            pl->mid[pl->base[d->link] + d->node] = 1;
    }
    return 1;
}

/* piece k of the link d cut into n segments (mid: it has a middle node); the first
   keeps the link's root, placement and initial motion, the others hang from springs */
static rj_link_def rj__sp_piece(const rj_link_def *d, int n, int k, int mid)
{
    const double l = d->length / n;
    const rj_link_def z = rj_default_link_def();
    rj_link_def p = *d;
    p.elements = mid ? 2 : 1;
    p.fidelity = RJ_LINK_RIGID;
    p.length = k == 0 || k == n ? 0.5 * l : l;
    /* the tip mass rides on the last piece */
    p.tip_mass = k == n ? d->tip_mass : 0.0;
    p.tip_inertia = k == n ? d->tip_inertia : 0.0;
    if (k == 0)
        return p;
    p.root = z.root;
    p.x = z.x;
    p.y = z.y;
    p.angle = z.angle;
    p.vx = z.vx;
    p.vy = z.vy;
    p.omega = z.omega;
    return p;
}

/* The links after the cut, written from the last back: each lands at or after where it
   was, so none is overwritten before it is read. Every piece keeps the link's places in
   the file, for messages. */
static void rj__sp_move_links(rj__sp *P, const rj__sp_plan *pl)
{
    rj_scene_file *f = P->f;
    const size_t np = 1 + RJ__LK_N;
    int i, k;
    for (i = f->link_count - 1; i >= 0; i--) {
        const rj_link_def d = f->links[i];
        rj_scene_pos pos[1 + RJ__LK_N];
        char name[RJ_SCENE_NAME_MAX];
        memcpy(pos, &f->link_pos_[(size_t) i * np], sizeof pos);
        memcpy(name, f->link_names[i], sizeof name);
        for (k = pl->n[i]; k >= 0; k--) {
            const int x = pl->base[i] + k;
            f->links[x] = pl->n[i] ? rj__sp_piece(&d, pl->n[i], k, pl->mid[x]) : d;
            memcpy(&f->link_pos_[(size_t) x * np], pos, sizeof pos);
            rj__sp_piece_name(f->link_names[x], name, "_p", k);
        }
    }
    f->link_count = pl->links;
}

/* cut file link i's springs (the links not moved yet: its name and places are the
   file's), each at the fidelity key (else the link's section line) for messages */
static void rj__sp_put_bend(rj__sp *P, const rj__sp_plan *pl, int i)
{
    rj_scene_file *f = P->f;
    const rj_scene_pos at = rj__sp_link_at(f, i, RJ__LK_FIDELITY);
    int k;
    for (k = 1; k <= pl->n[i]; k++) {
        const int x = pl->bend[i] + k - 1;
        rj_scene_pos *pos = &f->joint_pos_[(size_t) x * (1 + RJ__JK_N)];
        rj_joint_def *d = &f->joints[x];
        *d = rj_default_joint_def();
        d->body1 = pl->base[i] + k - 1;
        d->node1 = -1;
        d->body2 = pl->base[i] + k;
        /* a bending spring: straight (theta = pi) is its free angle */
        d->angle0 = rj_rad(180.0);
        d->spring_k = pl->k[i];
        d->spring_free_angle = rj_rad(180.0);
        memset(pos, 0, sizeof(rj_scene_pos) * (1 + RJ__JK_N));
        pos[0] = at;
        rj__sp_piece_name(f->joint_names[x], f->link_names[i], "_b", k);
    }
}

/* a joint's bodies after the cut: on a cut link body1's node goes to the piece holding
   it (rj__sp_piece_node), body2 is the first piece */
static void rj__sp_remap_joint(const rj__sp_plan *pl, rj_joint_def *d)
{
    int piece = 0;
    if (d->body1 >= 0 && pl->n[d->body1])
        rj__sp_piece_node(pl->n[d->body1], d->node1, &piece, &d->node1);
    if (d->body1 >= 0)
        d->body1 = pl->base[d->body1] + piece;
    d->body2 = pl->base[d->body2];
}

/* The joints after the cut, written from the last back as the links are: first the
   springs after every file joint, then each file joint and the springs that follow it. */
static void rj__sp_move_joints(rj__sp *P, const rj__sp_plan *pl)
{
    rj_scene_file *f = P->f;
    const size_t np = 1 + RJ__JK_N;
    int i, j;
    for (i = 0; i < f->link_count; i++)
        if (pl->n[i] && pl->bend[i] >= pl->tail)
            rj__sp_put_bend(P, pl, i);
    for (j = f->joint_count - 1; j >= 0; j--) {
        rj_joint_def d = f->joints[j];
        rj_scene_pos pos[1 + RJ__JK_N];
        char name[RJ_SCENE_NAME_MAX];
        const int b2 = d.body2, x = pl->jnew[j];
        memcpy(pos, &f->joint_pos_[(size_t) j * np], sizeof pos);
        memcpy(name, f->joint_names[j], sizeof name);
        if (pl->n[b2] && pl->bend[b2] == x + 1)
            rj__sp_put_bend(P, pl, b2);
        rj__sp_remap_joint(pl, &d);
        f->joints[x] = d;
        memcpy(&f->joint_pos_[(size_t) x * np], pos, sizeof pos);
        memcpy(f->joint_names[x], name, sizeof name);
    }
    f->joint_count = pl->joints;
}

/* loads, actuators and couplings: their links' nodes and their joints after the cut */
static void rj__sp_remap_rest(rj__sp *P, const rj__sp_plan *pl)
{
    rj_scene_file *f = P->f;
    int i;
    for (i = 0; i < f->load_count; i++) {
        rj_load_def *d = &f->loads[i];
        int piece = 0;
        if (pl->n[d->link])
            rj__sp_piece_node(pl->n[d->link], d->node, &piece, &d->node);
        d->link = pl->base[d->link] + piece;
    }
    for (i = 0; i < f->actuator_count; i++)
        f->actuators[i].joint = pl->jnew[f->actuators[i].joint];
    for (i = 0; i < f->coupling_count; i++) {
        f->couplings[i].joint_a = pl->jnew[f->couplings[i].joint_a];
        f->couplings[i].joint_b = pl->jnew[f->couplings[i].joint_b];
    }
}

/* names[x], the name made for piece or spring k of a cut link whose first piece is link
   f0 after the cut, that another of the count names (the links' or the joints', their
   places pos) has too: refused at the link's fidelity key, naming both */
static int rj__sp_cut_clash(rj__sp *P, char (*names)[RJ_SCENE_NAME_MAX], int count, int x, int f0,
                            const char *what, int k, const rj_scene_pos *pos)
{
    const rj_scene_file *f = P->f;
    const rj_scene_pos *fp = &f->link_pos_[(size_t) f0 * (1 + RJ__LK_N)];
    const int link = names == f->link_names;
    const size_t np = link ? 1 + RJ__LK_N : 1 + RJ__JK_N;
    const rj_scene_pos at = fp[1 + RJ__LK_FIDELITY].line ? fp[1 + RJ__LK_FIDELITY] : fp[0];
    char a[24], b[24], m[256], m2[256];
    int y;
    for (y = 0; y < count; y++)
        if (y != x && strcmp(names[y], names[x]) == 0)
            break;
    if (y == count)
        return 1;
    rj__sp_cat(m, sizeof m, "fidelity = pieces in link '", f->link_names[f0], "' names its ", what,
               " ", rj__sp_itoa(a, k), " '");
    rj__sp_cat(m2, sizeof m2, m, names[x], "', which the ", link ? "link" : "joint", " on line ",
               rj__sp_itoa(b, pos[(size_t) y * np].line), " has too");
    return rj__sp_err(P, at.line, at.col, "fidelity", rj__sp_nan(), m2,
                      " (rename one: a link's pieces are NAME_p1.., its springs NAME_b1..)", NULL,
                      NULL, NULL);
}

/* The names made for the pieces (NAME_pK) and the springs (NAME_bK) after the cut: none
   may be another link's or joint's. */
static int rj__sp_cut_names(rj__sp *P, const rj__sp_plan *pl, int file_links)
{
    rj_scene_file *f = P->f;
    int i, k;
    for (i = 0; i < file_links; i++)
        for (k = 1; k <= pl->n[i]; k++) {
            if (!rj__sp_cut_clash(P, f->link_names, f->link_count, pl->base[i] + k, pl->base[i],
                                  "piece", k, f->link_pos_))
                return 0;
            if (!rj__sp_cut_clash(P, f->joint_names, f->joint_count, pl->bend[i] + k - 1,
                                  pl->base[i], "bending joint", k, f->joint_pos_))
                return 0;
        }
    return 1;
}

/* The file's links with fidelity = pieces cut into their pieces and springs, the other
   items following them (see the top of this part); 1 when there are none. */
static int rj__sp_cut(rj__sp *P)
{
    rj__sp_plan pl;
    const int file_links = P->f->link_count;
    int i, any = 0;
    for (i = 0; i < file_links; i++)
        any |= P->pieces[i];
    if (!any)
        return 1;
    memset(&pl, 0, sizeof pl);
    if (!rj__sp_plan_links(P, &pl) || !rj__sp_plan_joints(P, &pl))
        return 0;
    /* the joints first: their springs take the file links' names and places */
    rj__sp_move_joints(P, &pl);
    rj__sp_move_links(P, &pl);
    rj__sp_remap_rest(P, &pl);
    return rj__sp_cut_names(P, &pl, file_links);
}

/* ------------------------------------------------------------------ public */
RJDEF void rj_scene_file_locate(const rj_scene_file *f, rj_error *err)
{
    char m[sizeof err->msg], item[80];
    rj_scene_pos pos;
    if (!f || !err)
        return;
    if (rj__sp_field_pos(f, err->field, &pos, item, sizeof item)) {
        char l[24], c[24], m1[sizeof err->msg];
        rj__sp_cat(m1, sizeof m1, f->filename, ":", rj__sp_itoa(l, pos.line), ":",
                   rj__sp_itoa(c, pos.col), ": ", NULL);
        rj__sp_cat(m, sizeof m, m1, err->msg, item, NULL, NULL, NULL, NULL);
    } else
        rj__sp_cat(m, sizeof m, f->filename, ": ", err->msg, NULL, NULL, NULL, NULL);
    memcpy(err->msg, m, sizeof m);
}

/* The parser: rj_scene_parse_ex, with the changes sets (nsets, 0..RJ_SCENE_MAX_SETS)
   taken at their sections' ends. */
static rj_result rj__sp_parse(const char *text, size_t len, const char *filename,
                              const char *const *sets, int nsets, rj_scene_file *out,
                              rj_error *err, void *alloc_ctx)
{
    rj__sp P;
    rj_scene_file F;
    int counts[RJ__SK_COUNT], r;
    size_t off = 0, o_links, o_joints, o_lpos, o_jpos, o_lnames, o_jnames, w_tok, w_mat, w_sec, w_set;
    size_t o_loads, o_apos, o_anames, o_acts, o_cpos, o_cnames, o_cps, o_ppos, o_pnames;
    char *block = NULL, *work = NULL;
    memset(&P, 0, sizeof P);
    memset(&F, 0, sizeof F);
    if (err) {
        err->code = RJ_OK;
        err->field[0] = 0;
        err->msg[0] = 0;
        err->value = 0;
    }
    P.fname = filename ? filename : "<input>";
    P.err = err;
    if (!out || (!text && len)) {
        if (err) {
            err->code = RJ_ERR_INVALID;
            snprintf(err->field, sizeof err->field, "%s", out ? "text" : "out");
            err->value = 0;
            snprintf(err->msg, sizeof err->msg, "%s is NULL", out ? "text" : "out");
        }
        if (out)
            memset(out, 0, sizeof *out);
        return RJ_ERR_INVALID;
    }
    memset(out, 0, sizeof *out);
    if (len > RJ_SCENE_MAX_BYTES) {
        char m[120];
        snprintf(m, sizeof m, "input of %lu bytes is larger than the %lu a scene file may have",
                 (unsigned long) len, (unsigned long) RJ_SCENE_MAX_BYTES);
        rj__sp_fail(&P, 1, 1, "", (double) len, m);
        return RJ_ERR_PARSE;
    }
    P.text = text ? text : "";
    P.len = len;
    if (!rj__sp_text(&P))
        return RJ_ERR_PARSE;
    rj__sp_locale(P.dp, &P.dplen);
    rj__sp_count(P.text, len, counts);
    P.cap_links = counts[RJ__SK_LINK];
    P.cap_joints = counts[RJ__SK_JOINT];
    P.cap_mat = counts[RJ__SK_MATERIAL];
    P.cap_sec = counts[RJ__SK_SECTION];
    P.cap_loads = counts[RJ__SK_LOAD];
    P.cap_acts = counts[RJ__SK_ACTUATOR];
    P.cap_cps = counts[RJ__SK_COUPLING];
    /* links cut into pieces (rj__sp_cut) grow the links and joints in place */
    if (rj__sp_says_pieces(P.text, len, sets, nsets)) {
        P.cap_links = RJ_SCENE_MAX_LINKS;
        P.cap_joints = RJ_SCENE_MAX_JOINTS;
    }
    /* the result block */
    o_links = rj__sp_carve(&off, (size_t) P.cap_links, sizeof(rj_link_def));
    o_joints = rj__sp_carve(&off, (size_t) P.cap_joints, sizeof(rj_joint_def));
    o_lpos = rj__sp_carve(&off, (size_t) P.cap_links * (1 + RJ__LK_N), sizeof(rj_scene_pos));
    o_jpos = rj__sp_carve(&off, (size_t) P.cap_joints * (1 + RJ__JK_N), sizeof(rj_scene_pos));
    o_lnames = rj__sp_carve(&off, (size_t) P.cap_links, RJ_SCENE_NAME_MAX);
    o_loads = rj__sp_carve(&off, (size_t) P.cap_loads, sizeof(rj_load_def));
    o_apos = rj__sp_carve(&off, (size_t) P.cap_loads * (1 + RJ__AK_N), sizeof(rj_scene_pos));
    o_anames = rj__sp_carve(&off, (size_t) P.cap_loads, RJ_SCENE_NAME_MAX);
    o_acts = rj__sp_carve(&off, (size_t) P.cap_acts, sizeof(rj_actuator_def));
    o_cpos = rj__sp_carve(&off, (size_t) P.cap_acts * (1 + RJ__CK_N), sizeof(rj_scene_pos));
    o_cnames = rj__sp_carve(&off, (size_t) P.cap_acts, RJ_SCENE_NAME_MAX);
    o_cps = rj__sp_carve(&off, (size_t) P.cap_cps, sizeof(rj_coupling_def));
    o_ppos = rj__sp_carve(&off, (size_t) P.cap_cps * (1 + RJ__PK_N), sizeof(rj_scene_pos));
    o_pnames = rj__sp_carve(&off, (size_t) P.cap_cps, RJ_SCENE_NAME_MAX);
    o_jnames = rj__sp_carve(&off, (size_t) P.cap_joints, RJ_SCENE_NAME_MAX);
    block = (char *) RJ_MALLOC(off + 16, alloc_ctx);
    /* the parser's workspace: tokens, materials, sections */
    off = 0;
    w_tok = rj__sp_carve(&off, RJ_SCENE_MAX_TOKENS, sizeof(rj__stok));
    w_mat = rj__sp_carve(&off, (size_t) P.cap_mat, sizeof(rj__spart));
    w_sec = rj__sp_carve(&off, (size_t) P.cap_sec, sizeof(rj__spart));
    w_set = rj__sp_carve(&off, nsets ? RJ_SCENE_MAX_TOKENS : 0, sizeof(rj__stok));
    work = block ? (char *) RJ_MALLOC(off + 16, alloc_ctx) : NULL;
    if (!block || !work) {
        if (block)
            RJ_FREE(block, alloc_ctx);
        if (err) {
            err->code = RJ_ERR_NOMEM;
            snprintf(err->field, sizeof err->field, "size");
            err->value = (double) off;
            rj__sp_cat(err->msg, sizeof err->msg, P.fname, ": out of memory", NULL, NULL, NULL,
                       NULL, NULL);
        }
        return RJ_ERR_NOMEM;
    }
    memset(block, 0, o_jnames + (size_t) P.cap_joints * RJ_SCENE_NAME_MAX);
    F.links = (rj_link_def *) (void *) (block + o_links);
    F.joints = (rj_joint_def *) (void *) (block + o_joints);
    F.link_pos_ = (rj_scene_pos *) (void *) (block + o_lpos);
    F.joint_pos_ = (rj_scene_pos *) (void *) (block + o_jpos);
    F.link_names = (char(*)[RJ_SCENE_NAME_MAX])(void *) (block + o_lnames);
    F.joint_names = (char(*)[RJ_SCENE_NAME_MAX])(void *) (block + o_jnames);
    F.loads = (rj_load_def *) (void *) (block + o_loads);
    F.load_pos_ = (rj_scene_pos *) (void *) (block + o_apos);
    F.load_names = (char(*)[RJ_SCENE_NAME_MAX])(void *) (block + o_anames);
    F.actuators = (rj_actuator_def *) (void *) (block + o_acts);
    F.actuator_pos_ = (rj_scene_pos *) (void *) (block + o_cpos);
    F.actuator_names = (char(*)[RJ_SCENE_NAME_MAX])(void *) (block + o_cnames);
    F.couplings = (rj_coupling_def *) (void *) (block + o_cps);
    F.coupling_pos_ = (rj_scene_pos *) (void *) (block + o_ppos);
    F.coupling_names = (char(*)[RJ_SCENE_NAME_MAX])(void *) (block + o_pnames);
    F.solver = rj_default_solver_def();
    F.block_ = block;
    F.alloc_ctx_ = alloc_ctx;
    rj__sp_cat(F.filename, sizeof F.filename, P.fname, NULL, NULL, NULL, NULL, NULL, NULL);
    P.f = &F;
    P.tok = (rj__stok *) (void *) (work + w_tok);
    P.mat = (rj__spart *) (void *) (work + w_mat);
    P.sec = (rj__spart *) (void *) (work + w_sec);
    P.set_tok = (rj__stok *) (void *) (work + w_set);
    P.sets = sets;
    P.nsets = nsets;
    P.kind = RJ__SK_NONE;

    while ((r = rj__sp_next(&P)) > 0) {
        if (!P.ntok)
            continue;
        if (P.tok[0].kind != 'w') {
            rj__sp_err_tok(&P, &P.tok[0], "", rj__sp_nan(),
                           "expected a key or a section keyword, found ", NULL, NULL, NULL);
            goto fail;
        }
        if (P.ntok >= 2 && P.tok[1].kind == '=') {
            if (!rj__sp_assignments(&P))
                goto fail;
        } else if (!rj__sp_header(&P))
            goto fail;
    }
    if (r < 0 || !rj__sp_finish(&P) || (nsets && !rj__sp_sets_left(&P)))
        goto fail;
    if (F.link_count == 0) {
        rj__sp_fail(&P, P.lineno > 0 ? P.lineno : 1, 1, "link_count", 0,
                    "the scene has no links (a scene needs at least one 'link' section)");
        goto fail;
    }
    if (!rj__sp_cut(&P))
        goto fail;
    RJ_FREE(work, alloc_ctx);
    work = NULL;
    { /* the model's own validation, located in the file */
        rj_scene_def sd = rj_scene_file_def(&F);
        rj_error me;
        if (rj__validate_all(&sd, &me, alloc_ctx) != RJ_OK) {
            rj_scene_file_locate(&F, &me);
            P.code = me.code;
            if (err)
                *err = me;
            goto fail;
        }
    }
    *out = F;
    return RJ_OK;
fail:
    if (work)
        RJ_FREE(work, alloc_ctx);
    RJ_FREE(block, alloc_ctx);
    memset(out, 0, sizeof *out);
    return P.code != RJ_OK ? P.code : RJ_ERR_PARSE;
}

RJDEF rj_result rj_scene_parse_ex(const char *text, size_t len, const char *filename,
                                  rj_scene_file *out, rj_error *err, void *alloc_ctx)
{
    return rj__sp_parse(text, len, filename, NULL, 0, out, err, alloc_ctx);
}

RJDEF rj_result rj_scene_parse(const char *text, size_t len, const char *filename,
                               rj_scene_file *out, rj_error *err)
{
    return rj_scene_parse_ex(text, len, filename, out, err, NULL);
}

/* The changes' own checks: a count in 0..RJ_SCENE_MAX_SETS, each a string of a line's
   length at most. */
static int rj__sp_sets_ok(const char *const *sets, int nsets, rj_error *err)
{
    int k;
    const char *bad = nsets < 0 || nsets > RJ_SCENE_MAX_SETS || (nsets && !sets)
                          ? "must be 0..64 changes, and the array there"
                          : NULL;
    for (k = 0; !bad && k < nsets; k++)
        if (!sets[k] || strlen(sets[k]) > RJ_SCENE_MAX_LINE)
            bad = "a change is a string of at most RJ_SCENE_MAX_LINE characters";
    if (!bad)
        return 1;
    if (err) {
        err->code = RJ_ERR_INVALID;
        snprintf(err->field, sizeof err->field, "nsets");
        err->value = nsets;
        snprintf(err->msg, sizeof err->msg, "nsets = %d: %s", nsets, bad);
    }
    return 0;
}

RJDEF rj_result rj_scene_parse_set(const char *text, size_t len, const char *filename,
                                   const char *const *sets, int nsets, rj_scene_file *out,
                                   rj_error *err)
{
    if (out)
        memset(out, 0, sizeof *out);
    if (!rj__sp_sets_ok(sets, nsets, err))
        return RJ_ERR_INVALID;
    return rj__sp_parse(text, len, filename, sets, nsets, out, err, NULL);
}

/* a failure of rj_scene_load: "path: what: the system's reason" when errnum is set (the
   user needs to know whether the file is missing, unreadable or a directory) */
static rj_result rj__sp_load_fail(rj_error *err, rj_result code, const char *path, const char *what,
                                  int errnum, double value)
{
    if (!err)
        return code;
    err->code = code;
    snprintf(err->field, sizeof err->field, "%s", code == RJ_ERR_NOMEM ? "size" : "path");
    err->value = value;
    rj__sp_cat(err->msg, sizeof err->msg, path, ": ", what, errnum ? ": " : "",
               errnum ? strerror(errnum) : "", NULL, NULL);
    return code;
}

/* reads all of fp into *buf (RJ_MALLOC; the caller frees it, also on failure), at most
   RJ_SCENE_MAX_BYTES */
static rj_result rj__sp_read(FILE *fp, const char *path, char **buf, size_t *n, rj_error *err)
{
    size_t cap = 0;
    *buf = NULL;
    *n = 0;
    for (;;) {
        size_t got;
        if (*n == cap) {
            size_t nc = cap ? cap * 2 : 65536;
            char *nb;
            if (nc > (size_t) RJ_SCENE_MAX_BYTES + 1)
                nc = (size_t) RJ_SCENE_MAX_BYTES + 1;
            if (cap > RJ_SCENE_MAX_BYTES)
                return rj__sp_load_fail(err, RJ_ERR_PARSE, path,
                                        "the file is larger than 64 MiB (RJ_SCENE_MAX_BYTES)", 0,
                                        (double) *n);
            nb = (char *) RJ_MALLOC(nc, NULL);
            if (!nb)
                return rj__sp_load_fail(err, RJ_ERR_NOMEM, path, "out of memory reading the file",
                                        0, (double) nc);
            if (*n)
                memcpy(nb, *buf, *n);
            if (*buf)
                RJ_FREE(*buf, NULL);
            *buf = nb;
            cap = nc;
        }
        errno = 0;
        got = fread(*buf + *n, 1, cap - *n, fp);
        *n += got;
        if (got == 0)
            break;
    }
    if (ferror(fp))
        return rj__sp_load_fail(err, RJ_ERR_PARSE, path, "cannot read the file", errno, errno);
    return RJ_OK;
}

RJDEF rj_result rj_scene_load_set(const char *path, const char *const *sets, int nsets,
                                  rj_scene_file *out, rj_error *err)
{
    FILE *fp;
    char *buf = NULL;
    size_t n = 0;
    rj_result r;
    if (out)
        memset(out, 0, sizeof *out);
    if (!path || !out) {
        if (err) {
            err->code = RJ_ERR_INVALID;
            snprintf(err->field, sizeof err->field, "%s", path ? "out" : "path");
            err->value = 0;
            snprintf(err->msg, sizeof err->msg, "%s is NULL", path ? "out" : "path");
        }
        return RJ_ERR_INVALID;
    }
    if (!rj__sp_sets_ok(sets, nsets, err))
        return RJ_ERR_INVALID;
    errno = 0;
    fp = fopen(path, "rb");
    if (!fp)
        return rj__sp_load_fail(err, RJ_ERR_PARSE, path, "cannot open the file for reading", errno,
                                errno);
    r = rj__sp_read(fp, path, &buf, &n, err);
    fclose(fp);
    if (r == RJ_OK)
        r = rj__sp_parse(buf, n, path, sets, nsets, out, err, NULL);
    if (buf)
        RJ_FREE(buf, NULL);
    return r;
}

RJDEF rj_result rj_scene_load(const char *path, rj_scene_file *out, rj_error *err)
{
    return rj_scene_load_set(path, NULL, 0, out, err);
}

RJDEF rj_scene_def rj_scene_file_def(const rj_scene_file *f)
{
    rj_scene_def d = rj_default_scene_def();
    if (!f)
        return d;
    d.links = f->links;
    d.link_count = f->link_count;
    d.joints = f->joints;
    d.joint_count = f->joint_count;
    d.solver = f->solver;
    d.loads = f->loads;
    d.load_count = f->load_count;
    d.actuators = f->actuators;
    d.actuator_count = f->actuator_count;
    d.couplings = f->couplings;
    d.coupling_count = f->coupling_count;
    return d;
}

RJDEF void rj_scene_file_free(rj_scene_file *f)
{
    if (!f)
        return;
    if (f->block_)
        RJ_FREE(f->block_, f->alloc_ctx_);
    memset(f, 0, sizeof *f);
}

RJDEF int rj_scene_link_index(const rj_scene_file *f, const char *name)
{
    int k;
    if (!f || !name)
        return -1;
    for (k = 0; k < f->link_count; k++)
        if (strcmp(f->link_names[k], name) == 0)
            return k;
    return -1;
}

RJDEF int rj_scene_joint_index(const rj_scene_file *f, const char *name)
{
    int k;
    if (!f || !name)
        return -1;
    for (k = 0; k < f->joint_count; k++)
        if (strcmp(f->joint_names[k], name) == 0)
            return k;
    return -1;
}

