/* rj_scene.h - scene files for revjoint.h: a small, strict, line-oriented text format
   (scene/README.md) parsed into the library's definition structs, and written back.

   Include after revjoint.h. Two blocks, each to be pasted into revjoint.h as it is:
     PUBLIC PART    types and prototypes: into the declarations, before the closing
                    extern "C" brace (it carries its own extern "C" so it also works here);
     IMPLEMENTATION static rj__ helpers and RJDEF functions: into the implementation section.
   The implementation uses only the public API of revjoint.h, RJ_MALLOC / RJ_FREE, and
   <string.h>, <stdlib.h> (strtod), <math.h>, <stdio.h> (snprintf; fopen/fread only in
   rj_scene_load). No globals, nothing printed, nothing allocated except by RJ_MALLOC. */

/* ================================================================== PUBLIC PART */
#ifndef RJ_SCENE_H
#define RJ_SCENE_H

#ifdef __cplusplus
extern "C" {
#endif

#define RJ_SCENE_MAX_LINKS 256
#define RJ_SCENE_MAX_JOINTS 256
#define RJ_SCENE_MAX_MATERIALS 64
#define RJ_SCENE_MAX_SECTIONS 64
#define RJ_SCENE_MAX_LINE 1024        /* characters per line, line end excluded */
#define RJ_SCENE_MAX_TOKENS 512       /* tokens per statement (a statement may continue after a ',') */
#define RJ_SCENE_NAME_MAX 32          /* names are 1..31 characters */
#define RJ_SCENE_MAX_BYTES (64u << 20) /* input size */

/* A place in the file: 1-based line and column (column counts bytes); line 0 = nowhere. */
typedef struct rj_scene_pos { int line, col; } rj_scene_pos;

/* A parsed scene. Everything lives in one block from RJ_MALLOC; rj_scene_file_free
   releases it. links[i] and link_names[i] are the i-th link section in order of
   appearance, likewise for joints. The fields ending in _ are private. */
typedef struct rj_scene_file {
    rj_link_def *links; int link_count;
    rj_joint_def *joints; int joint_count;
    rj_solver_def solver;
    char (*link_names)[RJ_SCENE_NAME_MAX];
    char (*joint_names)[RJ_SCENE_NAME_MAX];
    char filename[96];                /* as given to rj_scene_parse (truncated) */
    rj_scene_pos *link_pos_, *joint_pos_; /* per item: header, then the value of each key */
    rj_scene_pos solver_pos_[4];      /* header, then dt, allow_unstable, energy_growth */
    void *block_, *alloc_ctx_;
} rj_scene_file;

/* Parses len bytes of text (need not be NUL-terminated) named filename in messages
   (NULL: "<input>"). On success fills *out. On failure returns RJ_ERR_PARSE (syntax, a value
   out of range, an unknown name, a limit exceeded) or the code of rj_model_create's
   validation (RJ_ERR_INVALID) for a scene that parses but that the model rejects, with
   err->msg "file:line:col: message" (the line and column of the offending text), err->field
   the key (or the model's field), err->value the offending number (NaN when not numeric);
   nothing is left allocated and *out is zeroed (rj_scene_file_free on it is a no-op).
   alloc_ctx is passed to RJ_MALLOC / RJ_FREE (rj_scene_parse passes NULL). */
RJDEF rj_result rj_scene_parse(const char *text, size_t len, const char *filename, rj_scene_file *out, rj_error *err);
RJDEF rj_result rj_scene_parse_ex(const char *text, size_t len, const char *filename, rj_scene_file *out, rj_error *err, void *alloc_ctx);
/* Reads the file at path (at most RJ_SCENE_MAX_BYTES) and parses it. */
RJDEF rj_result rj_scene_load(const char *path, rj_scene_file *out, rj_error *err);
/* A scene definition pointing into f (valid until rj_scene_file_free). */
RJDEF rj_scene_def rj_scene_file_def(const rj_scene_file *f);
RJDEF void rj_scene_file_free(rj_scene_file *f);
/* Index of the link or joint with that name, -1 if none. */
RJDEF int rj_scene_link_index(const rj_scene_file *f, const char *name);
RJDEF int rj_scene_joint_index(const rj_scene_file *f, const char *name);
/* For an error from rj_model_create (or rj_model_size/init) on rj_scene_file_def(f): puts
   "file:line:col: " before err->msg, pointing at the key its err->field names (or at the
   link's or joint's section line), and the item's name after it. Call once per error;
   an error whose field names no item gets "file: " only. */
RJDEF void rj_scene_file_locate(const rj_scene_file *f, rj_error *err);
/* Writes the scene as scene-file text into buf (size bytes, always NUL-terminated when
   size > 0) and returns the length of the whole text (excluding the NUL), like snprintf:
   call with size 0 to learn the size. link_names / joint_names may be NULL ("link0", ...,
   "joint0", ...); given names must be valid (1..31 of [A-Za-z0-9_.-], not starting with a
   digit, '.' or '-'; a link not named "ground") and unique. Returns 0 (and writes nothing)
   for an unwritable scene: counts outside 1..RJ_SCENE_MAX_LINKS / 0..RJ_SCENE_MAX_JOINTS,
   a body index out of range, a non-finite number, a bad name. Reading the text back with
   rj_scene_parse gives every field the model uses bit for bit (numbers are written in their
   shortest round-trip form, angles in deg when that round-trips, else in rad); fields the
   model ignores (width/layers of a general section, area/inertia of a rectangular one, the
   value of a disabled limit, node1 and ground_* where they do not apply) come back as their
   defaults. */
RJDEF size_t rj_scene_write(const rj_scene_def *scene, const char *const *link_names, const char *const *joint_names, char *buf, size_t size);

#ifdef __cplusplus
}
#endif
#endif /* RJ_SCENE_H */

/* ================================================================== IMPLEMENTATION */
#if defined(REVJOINT_IMPLEMENTATION) && !defined(RJ_SCENE_IMPLEMENTATION_DONE)
#define RJ_SCENE_IMPLEMENTATION_DONE
#include <string.h>
#include <stdlib.h>
#include <math.h>
#include <stdio.h>

/* keys; index 0 of an item's position array is its section line, key k is at 1 + k */
enum {
    RJ__LK_LENGTH, RJ__LK_ELEMENTS, RJ__LK_MATERIAL, RJ__LK_SECTION, RJ__LK_E, RJ__LK_RHO,
    RJ__LK_AREA, RJ__LK_INERTIA, RJ__LK_WIDTH, RJ__LK_HEIGHT, RJ__LK_LAYERS, RJ__LK_TIP_MASS,
    RJ__LK_TIP_INERTIA, RJ__LK_ROOT, RJ__LK_X, RJ__LK_Y, RJ__LK_ANGLE, RJ__LK_VX, RJ__LK_VY,
    RJ__LK_OMEGA, RJ__LK_N
};
enum {
    RJ__JK_BODY1, RJ__JK_BODY2, RJ__JK_NODE1, RJ__JK_GROUND_X, RJ__JK_GROUND_Y, RJ__JK_GROUND_ANGLE,
    RJ__JK_ANGLE0, RJ__JK_RATE0, RJ__JK_TABLE, RJ__JK_SPRING, RJ__JK_FORWARD, RJ__JK_REVERSE,
    RJ__JK_LOCK, RJ__JK_METHOD, RJ__JK_RELEASE, RJ__JK_PENALTY_K, RJ__JK_RESTITUTION,
    RJ__JK_DAMPING, RJ__JK_FRICTION, RJ__JK_REFERENCE, RJ__JK_N
};
enum { RJ__VK_DT, RJ__VK_ALLOW_UNSTABLE, RJ__VK_ENERGY_GROWTH, RJ__VK_N };
enum { RJ__SK_NONE, RJ__SK_SOLVER, RJ__SK_MATERIAL, RJ__SK_SECTION, RJ__SK_LINK, RJ__SK_JOINT };

/* char arrays, not pointer arrays: read-only data without relocations */
static const char rj__sk_kind[6][10] = { "", "solver", "material", "section", "link", "joint" };
static const char rj__sk_link[RJ__LK_N][12] = {
    "length", "elements", "material", "section", "E", "rho", "area", "inertia", "width", "height",
    "layers", "tip_mass", "tip_inertia", "root", "x", "y", "angle", "vx", "vy", "omega"
};
static const char rj__sk_joint[RJ__JK_N][13] = {
    "body1", "body2", "node1", "ground_x", "ground_y", "ground_angle", "angle0", "rate0", "table",
    "spring", "forward", "reverse", "lock", "method", "release", "penalty_k", "restitution",
    "damping", "friction", "reference"
};
static const char rj__sk_solver[RJ__VK_N][15] = { "dt", "allow_unstable", "energy_growth" };
static const char rj__sk_root[4][8] = { "free", "pinned", "clamped", "fixed" };
static const char rj__sk_method[5][9] = { "penalty", "adaptive", "momentum", "forced", "energy" };
static const char rj__sk_release[2][5] = { "rc12", "rc13" };
static const char rj__sk_reference[2][8] = { "tangent", "chord" };

#define RJ__SK_MAT_KEYS ((1u << RJ__LK_E) | (1u << RJ__LK_RHO))
#define RJ__SK_SEC_KEYS ((1u << RJ__LK_AREA) | (1u << RJ__LK_INERTIA) | (1u << RJ__LK_WIDTH) | (1u << RJ__LK_HEIGHT) | (1u << RJ__LK_LAYERS))

typedef struct rj__stok { const char *s; int len, line, col; char kind; } rj__stok; /* kind 'w', '=' or ',' */

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
    char dp[8];                 /* the C library's decimal point in the current locale */
    int dplen;
    rj__stok *tok;
    int ntok;
    rj_scene_file *f;
    int cap_links, cap_joints;
    rj__spart *mat, *sec;
    int nmat, nsec, cap_mat, cap_sec;
    int kind, item;             /* current section: kind and index (materials, sections, links, joints) */
    unsigned seen;              /* keys set in the current section */
    int link_mat, link_sec;     /* current link's material and section, -1 none */
    int solver_seen;
    char where[80], forkey[128];  /* message pieces */
    rj_result code;             /* of the first error */
} rj__sp;

/* ------------------------------------------------------------------ small helpers */
static double rj__sp_nan(void) { return strtod("nan", NULL); }

static void rj__sp_locale(char *dp, int *dplen)
{
    char t[16];
    int n = snprintf(t, sizeof t, "%.1f", 1.5), k;
    *dplen = 0;
    if (n >= 3 && n - 2 < 7) for (k = 1; k < n - 1; k++) dp[(*dplen)++] = t[k];
    if (*dplen == 0) { dp[0] = '.'; *dplen = 1; }
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
    if (n <= 0) return 0;
    {
        int j = (s[0] == '+' || s[0] == '-') ? 1 : 0, m = n - j;
        const char *w = s + j;
        if ((m == 3 || m == 8) && (((w[0] | 32) == 'i' && (w[1] | 32) == 'n' && (w[2] | 32) == 'f')
                                   || (m == 3 && (w[0] | 32) == 'n' && (w[1] | 32) == 'a' && (w[2] | 32) == 'n'))) {
            if (m == 3) return -1;
            if (((w[3] | 32) == 'i' && (w[4] | 32) == 'n' && (w[5] | 32) == 'i' && (w[6] | 32) == 't' && (w[7] | 32) == 'y')) return -1;
        }
    }
    if (s[i] == '+' || s[i] == '-') i++;
    while (i < n && s[i] >= '0' && s[i] <= '9') { i++; digits++; }
    if (i < n && s[i] == '.') { i++; while (i < n && s[i] >= '0' && s[i] <= '9') { i++; digits++; } }
    if (!digits) return 0;
    if (i < n && (s[i] == 'e' || s[i] == 'E')) {
        int ed = 0;
        i++;
        if (i < n && (s[i] == '+' || s[i] == '-')) i++;
        while (i < n && s[i] >= '0' && s[i] <= '9') { i++; ed++; }
        if (!ed) return 0;
    }
    if (i != n) return 0;
    if (n + dplen >= (int)sizeof buf) return -3;
    for (k = 0; k < n; k++) {
        if (s[k] == '.') { memcpy(buf + o, dp, (size_t)dplen); o += dplen; }
        else buf[o++] = s[k];
    }
    buf[o] = 0;
    v = strtod(buf, &end);
    if (end != buf + o) return 0;
    if (!(v == v) || v - v != 0.0) return -2;
    *out = v;
    return 1;
}

/* strict integer: [+-]? d+ ; returns 1 ok, 0 malformed, -2 beyond +-2e9 */
static int rj__sp_strtoint(const char *s, int n, int *out)
{
    int i = 0, neg = 0, big = 0;
    long v = 0;
    if (n <= 0) return 0;
    if (s[0] == '+' || s[0] == '-') { neg = s[0] == '-'; i = 1; }
    if (i == n) return 0;
    for (; i < n; i++) {
        if (s[i] < '0' || s[i] > '9') return 0;
        if (v > 200000000L) big = 1; else v = v * 10 + (s[i] - '0');
    }
    if (big || v > 2000000000L) return -2;
    *out = (int)(neg ? -v : v);
    return 1;
}

/* text for messages: at most 40 characters, control and non-ASCII bytes as \xNN */
static void rj__sp_quote(char *dst, size_t size, const char *s, int n)
{
    size_t o = 0;
    int i;
    for (i = 0; i < n && o + 5 < size; i++) {
        unsigned char c = (unsigned char)s[i];
        if (i >= 40) { if (o + 4 < size) { memcpy(dst + o, "...", 3); o += 3; } break; }
        if (c < 0x20 || c >= 0x7f) { snprintf(dst + o, size - o, "\\x%02x", c); o += 4; }
        else dst[o++] = (char)c;
    }
    dst[o < size ? o : size - 1] = 0;
}

/* message builder: concatenates up to 7 pieces (NULL skipped) into dst, truncating */
static void rj__sp_cat(char *dst, size_t size, const char *a, const char *b, const char *c, const char *d, const char *e, const char *f, const char *g)
{
    const char *pc[7];
    size_t o = 0;
    int k;
    pc[0] = a; pc[1] = b; pc[2] = c; pc[3] = d; pc[4] = e; pc[5] = f; pc[6] = g;
    if (!size) return;
    for (k = 0; k < 7; k++) {
        size_t n, room;
        if (!pc[k]) continue;
        n = strlen(pc[k]);
        room = size - 1 - o;
        if (n > room) n = room;
        memcpy(dst + o, pc[k], n);
        o += n;
    }
    dst[o] = 0;
}

static const char *rj__sp_itoa(char *buf, long v)   /* buf: 24 bytes */
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
        rj__sp_cat(P->err->msg, sizeof P->err->msg, P->fname, ":", rj__sp_itoa(l, line), ":", rj__sp_itoa(c, col), ": ", msg);
    }
    return 0;
}

/* msg = a b c d e */
static int rj__sp_err(rj__sp *P, int line, int col, const char *key, double value, const char *a, const char *b, const char *c, const char *d, const char *e)
{
    char m[256];
    rj__sp_cat(m, sizeof m, a, b, c, d, e, NULL, NULL);
    return rj__sp_fail(P, line, col, key, value, m);
}

/* msg = pre 'token text' b c d e */
static int rj__sp_err_tok5(rj__sp *P, const rj__stok *t, const char *key, double value, const char *pre, const char *b, const char *c, const char *d, const char *e)
{
    char q[200], m1[256], m[256];
    rj__sp_quote(q, sizeof q, t->s, t->len);
    rj__sp_cat(m1, sizeof m1, pre, "'", q, "'", NULL, NULL, NULL);
    rj__sp_cat(m, sizeof m, m1, b, c, d, e, NULL, NULL);
    return rj__sp_fail(P, t->line, t->col, key, value, m);
}

/* msg = pre 'token text' b c d */
static int rj__sp_err_tok(rj__sp *P, const rj__stok *t, const char *key, double value, const char *pre, const char *b, const char *c, const char *d)
{
    char q[200], m[256];
    rj__sp_quote(q, sizeof q, t->s, t->len);
    rj__sp_cat(m, sizeof m, pre, "'", q, "'", b, c, d);
    return rj__sp_fail(P, t->line, t->col, key, value, m);
}

static const char *rj__sp_item_name(const rj__sp *P)
{
    switch (P->kind) {
    case RJ__SK_MATERIAL: return P->mat[P->item].name;
    case RJ__SK_SECTION: return P->sec[P->item].name;
    case RJ__SK_LINK: return P->f->link_names[P->item];
    case RJ__SK_JOINT: return P->f->joint_names[P->item];
    }
    return "";
}

/* " in link 'arm1'" for messages, into P->where */
static const char *rj__sp_where(rj__sp *P)
{
    if (P->kind == RJ__SK_SOLVER) rj__sp_cat(P->where, sizeof P->where, " in solver", NULL, NULL, NULL, NULL, NULL, NULL);
    else if (P->kind == RJ__SK_NONE) P->where[0] = 0;
    else rj__sp_cat(P->where, sizeof P->where, " in ", rj__sk_kind[P->kind], " '", rj__sp_item_name(P), "'", NULL, NULL);
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
    return t->kind == 'w' && (size_t)t->len == n && memcmp(t->s, s, n) == 0;
}

static int rj__sp_name_ok(const char *s, int n)
{
    int i;
    if (n < 1 || n >= RJ_SCENE_NAME_MAX) return 0;
    for (i = 0; i < n; i++) {
        char c = s[i];
        int alpha = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_';
        int other = (c >= '0' && c <= '9') || c == '.' || c == '-';
        if (!alpha && !(i > 0 && other)) return 0;
    }
    return 1;
}

static rj_scene_pos *rj__sp_pos(rj__sp *P, int k)   /* position slot of key k of the current item */
{
    switch (P->kind) {
    case RJ__SK_SOLVER: return &P->f->solver_pos_[1 + k];
    case RJ__SK_MATERIAL: return &P->mat[P->item].pos[1 + k];
    case RJ__SK_SECTION: return &P->sec[P->item].pos[1 + k];
    case RJ__SK_LINK: return &P->f->link_pos_[(size_t)P->item * (1 + RJ__LK_N) + 1 + k];
    default: return &P->f->joint_pos_[(size_t)P->item * (1 + RJ__JK_N) + 1 + k];
    }
}

/* ------------------------------------------------------------------ values */
static int rj__sp_num(rj__sp *P, const rj__stok *t, const char *key, double *out)
{
    int r;
    if (t->kind != 'w') return rj__sp_err_tok(P, t, key, rj__sp_nan(), "expected a number, found ", rj__sp_for(P, key), NULL, NULL);
    r = rj__sp_strtonum(t->s, t->len, P->dp, P->dplen, out);
    if (r == 1) return 1;
    return rj__sp_err_tok(P, t, key, rj__sp_nan(),
                          r == -1 ? "not a finite number: " : r == -2 ? "number out of range: " : r == -3 ? "number too long: " : "malformed number ",
                          rj__sp_for(P, key), NULL, NULL);
}

static int rj__sp_int(rj__sp *P, const rj__stok *t, const char *key, int lo, int hi, int *out)
{
    char a[24], b[24], q[200], m[256], m2[256];
    int v = 0, r = t->kind == 'w' ? rj__sp_strtoint(t->s, t->len, &v) : 0;
    if (r == 1 && v >= lo && v <= hi) { *out = v; return 1; }
    if (r == 1 || r == -2) {
        rj__sp_quote(q, sizeof q, t->s, t->len);
        rj__sp_cat(m, sizeof m, key, " = ", q, " is out of range", rj__sp_where(P), ": must be ", rj__sp_itoa(a, lo));
        rj__sp_cat(m2, sizeof m2, m, "..", rj__sp_itoa(b, hi), NULL, NULL, NULL, NULL);
        return rj__sp_fail(P, t->line, t->col, key, r == 1 ? (double)v : rj__sp_nan(), m2);
    }
    return rj__sp_err_tok(P, t, key, rj__sp_nan(), "expected an integer, found ", rj__sp_for(P, key), NULL, NULL);
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
            if (rj__sp_is(u, ud)) { v = rj_rad(v); (*i)++; }
            else if (rj__sp_is(u, ur)) (*i)++;
            else if ((u->s[0] >= 'a' && u->s[0] <= 'z') || (u->s[0] >= 'A' && u->s[0] <= 'Z'))
                return rj__sp_err_tok(P, u, key, v, "unknown unit ", rj__sp_for(P, key), rate ? " (deg/s or rad/s)" : " (deg or rad)", NULL);
        }
        if (!(v - v == 0.0)) return rj__sp_err_tok(P, t, key, rj__sp_nan(), "number out of range: ", rj__sp_for(P, key), NULL, NULL);
        *out = v;
        return 1;
    }
    /* unit glued to the number */
    if (t->kind == 'w' && t->len > ul) {
        int isd = memcmp(t->s + t->len - ul, ud, (size_t)ul) == 0, isr = memcmp(t->s + t->len - ul, ur, (size_t)ul) == 0;
        if ((isd || isr) && rj__sp_strtonum(t->s, t->len - ul, P->dp, P->dplen, &v) == 1) {
            if (isd) v = rj_rad(v);
            if (!(v - v == 0.0)) return rj__sp_err_tok(P, t, key, rj__sp_nan(), "number out of range: ", rj__sp_for(P, key), NULL, NULL);
            (*i)++;
            *out = v;
            return 1;
        }
    }
    return rj__sp_num(P, t, key, &v);   /* reports the right error */
}

/* range check on an already parsed value; the message shows the text of toks[a..e) */
static int rj__sp_range(rj__sp *P, int a, int e, const char *key, double v, int ok, const char *rule)
{
    char q[200], m[256];
    const rj__stok *t = &P->tok[a], *z = &P->tok[e - 1];
    if (ok) return 1;
    if (z->line == t->line && z->s >= t->s) rj__sp_quote(q, sizeof q, t->s, (int)(z->s + z->len - t->s));
    else rj__sp_quote(q, sizeof q, t->s, t->len);
    rj__sp_cat(m, sizeof m, key, " = ", q, " is out of range", rj__sp_where(P), ": ", rule);
    return rj__sp_fail(P, t->line, t->col, key, v, m);
}

static int rj__sp_enum(rj__sp *P, const rj__stok *t, const char *key, const char *names, size_t stride, int count, int *out)
{
    char list[100], tmp[100], q[200], m[256], m2[256];
    int k;
    for (k = 0; k < count; k++) if (rj__sp_is(t, names + stride * (size_t)k)) { *out = k; return 1; }
    list[0] = 0;
    for (k = 0; k < count; k++) {
        rj__sp_cat(tmp, sizeof tmp, list, k ? (k == count - 1 ? " or " : ", ") : "", names + stride * (size_t)k, NULL, NULL, NULL, NULL);
        memcpy(list, tmp, sizeof list);
    }
    rj__sp_quote(q, sizeof q, t->s, t->len);
    rj__sp_cat(m, sizeof m, "unknown value '", q, "'", rj__sp_for(P, key), " (expected ", NULL, NULL);
    rj__sp_cat(m2, sizeof m2, m, list, ")", NULL, NULL, NULL, NULL);
    return rj__sp_fail(P, t->line, t->col, key, rj__sp_nan(), m2);
}

static int rj__sp_bool(rj__sp *P, const rj__stok *t, const char *key, int *out)
{
    static const char names[4][6] = { "no", "yes", "false", "true" };
    int k = 0;
    if (!rj__sp_enum(P, t, key, names[0], sizeof names[0], 4, &k)) return 0;
    *out = k & 1;
    return 1;
}

static int rj__sp_name_ref(rj__sp *P, const rj__stok *t, const char *key)
{
    if (t->kind == 'w' && rj__sp_name_ok(t->s, t->len)) return 1;
    return rj__sp_err_tok(P, t, key, rj__sp_nan(), "expected a name, found ", rj__sp_for(P, key), NULL, NULL);
}

static int rj__sp_find(const char *s, int n, const char *names, size_t stride, int count)
{
    int k;
    for (k = 0; k < count; k++) {
        const char *nm = names + stride * (size_t)k;
        if ((int)strlen(nm) == n && memcmp(nm, s, (size_t)n) == 0) return k;
    }
    return -1;
}

/* ------------------------------------------------------------------ keys */
#define RJ__SP_RULE(cond, rule) rj__sp_range(P, a, *i, key, v, (cond), (rule))

static int rj__sp_link_key(rj__sp *P, int k, int a, int *i, int b, rj_link_def *d)
{
    const char *key = rj__sk_link[k];
    const rj__stok *t = &P->tok[a];
    double v = 0;
    switch (k) {
    case RJ__LK_ELEMENTS: if (!rj__sp_int(P, t, key, 1, 1000000, &d->elements)) return 0; (*i)++; return 1;
    case RJ__LK_LAYERS: if (!rj__sp_int(P, t, key, 1, 1000, &d->layers)) return 0; (*i)++; return 1;
    case RJ__LK_ROOT: if (!rj__sp_enum(P, t, key, rj__sk_root[0], sizeof rj__sk_root[0], 4, &d->root)) return 0; (*i)++; return 1;
    case RJ__LK_MATERIAL: case RJ__LK_SECTION: {
        int idx;
        if (!rj__sp_name_ref(P, t, key)) return 0;
        if (k == RJ__LK_MATERIAL) idx = P->nmat ? rj__sp_find(t->s, t->len, P->mat[0].name, sizeof(rj__spart), P->nmat) : -1;
        else idx = P->nsec ? rj__sp_find(t->s, t->len, P->sec[0].name, sizeof(rj__spart), P->nsec) : -1;
        if (idx < 0) return rj__sp_err_tok(P, t, key, rj__sp_nan(), k == RJ__LK_MATERIAL ? "unknown material " : "unknown section ",
                                           rj__sp_where(P), " (define it above the link)", NULL);
        if (k == RJ__LK_MATERIAL) P->link_mat = idx; else P->link_sec = idx;
        (*i)++;
        return 1;
    }
    case RJ__LK_ANGLE: return rj__sp_angle(P, i, b, key, 0, &d->angle);
    case RJ__LK_OMEGA: return rj__sp_angle(P, i, b, key, 1, &d->omega);
    }
    if (!rj__sp_num(P, t, key, &v)) return 0;
    (*i)++;
    switch (k) {
    case RJ__LK_LENGTH: if (!RJ__SP_RULE(v > 0 && v <= 1e6, "must be > 0 and <= 1e6 m")) return 0; d->length = v; break;
    case RJ__LK_E: if (!RJ__SP_RULE(v > 0, "must be > 0 Pa")) return 0; d->E = v; break;
    case RJ__LK_RHO: if (!RJ__SP_RULE(v > 0, "must be > 0 kg/m^3")) return 0; d->rho = v; break;
    case RJ__LK_AREA: if (!RJ__SP_RULE(v > 0, "must be > 0 m^2")) return 0; d->area = v; break;
    case RJ__LK_INERTIA: if (!RJ__SP_RULE(v > 0, "must be > 0 m^4")) return 0; d->inertia = v; break;
    case RJ__LK_WIDTH: if (!RJ__SP_RULE(v > 0, "must be > 0 m")) return 0; d->width = v; break;
    case RJ__LK_HEIGHT: if (!RJ__SP_RULE(v >= 0, "must be >= 0 m (> 0 for a rectangular section)")) return 0; d->height = v; break;
    case RJ__LK_TIP_MASS: if (!RJ__SP_RULE(v >= 0, "must be >= 0 kg")) return 0; d->tip_mass = v; break;
    case RJ__LK_TIP_INERTIA: if (!RJ__SP_RULE(v >= 0, "must be >= 0 kg m^2")) return 0; d->tip_inertia = v; break;
    case RJ__LK_X: d->x = v; break;
    case RJ__LK_Y: d->y = v; break;
    case RJ__LK_VX: d->vx = v; break;
    case RJ__LK_VY: d->vy = v; break;
    }
    return 1;
}

static int rj__sp_limit(rj__sp *P, int a, int *i, int b, const char *key, int *has, double *lim)
{
    double v = 0;
    if (rj__sp_is(&P->tok[a], "none")) { *has = 0; *lim = 0; (*i)++; return 1; }
    if (!rj__sp_angle(P, i, b, key, 0, &v)) return 0;
    if (!RJ__SP_RULE(v >= 0 && v < 2.0 * 3.14159265358979323846, "a limit must be in [0, 360) deg, or none")) return 0;
    *has = 1; *lim = v;
    return 1;
}

static int rj__sp_table(rj__sp *P, int a, int *i, int b, rj_joint_def *d)
{
    const char *key = "table";
    char nb[24];
    int n = 0;
    for (;;) {
        double v = 0, tq = 0;
        int s = *i;
        if (n == RJ_TABLE_MAX)
            return rj__sp_err(P, P->tok[s].line, P->tok[s].col, key, rj__sp_nan(), "table has more than ", rj__sp_itoa(nb, RJ_TABLE_MAX), " points", rj__sp_where(P), NULL);
        if (!rj__sp_angle(P, i, b, key, 0, &v)) return 0;
        a = s;
        if (!RJ__SP_RULE(v >= 0 && v <= 2.0 * 3.14159265358979323846, "table angles must be in [0, 360] deg")) return 0;
        if (n > 0 && !RJ__SP_RULE(v >= d->table_angle[n - 1], "table angles must not decrease")) return 0;
        if (*i >= b) {
            const rj__stok *z = &P->tok[*i - 1];
            return rj__sp_err(P, z->line, z->col + z->len, key, rj__sp_nan(), "missing torque after the table angle", rj__sp_where(P), " (table = angle torque, angle torque, ...)", NULL, NULL);
        }
        if (!rj__sp_num(P, &P->tok[*i], key, &tq)) return 0;
        (*i)++;
        d->table_angle[n] = v; d->table_torque[n] = tq; n++;
        if (*i >= b) break;
        if (P->tok[*i].kind != ',')
            return rj__sp_err_tok(P, &P->tok[*i], key, rj__sp_nan(), "expected ',' or the end of the table, found ", rj__sp_where(P), " (table = angle torque, angle torque, ...)", NULL);
        (*i)++;
        if (*i >= b) {
            const rj__stok *z = &P->tok[*i - 1];
            return rj__sp_err(P, z->line, z->col, key, rj__sp_nan(), "table ends with ','", rj__sp_where(P), NULL, NULL, NULL);
        }
    }
    if (n < 2) return rj__sp_err(P, P->tok[a].line, P->tok[a].col, key, rj__sp_nan(), "a table needs at least 2 points", rj__sp_where(P), NULL, NULL, NULL);
    d->table_count = n;
    return 1;
}

static int rj__sp_joint_key(rj__sp *P, int k, int a, int *i, int b, rj_joint_def *d)
{
    const char *key = rj__sk_joint[k];
    const rj__stok *t = &P->tok[a];
    double v = 0;
    switch (k) {
    case RJ__JK_BODY1: case RJ__JK_BODY2: {
        int idx;
        if (!rj__sp_name_ref(P, t, key)) return 0;
        if (rj__sp_is(t, "ground")) {
            if (k == RJ__JK_BODY2) return rj__sp_err_tok(P, t, key, rj__sp_nan(), "body2 must be a link, not ", rj__sp_where(P), " (body1 may be ground)", NULL);
            d->body1 = -1; (*i)++; return 1;
        }
        idx = P->f->link_count ? rj__sp_find(t->s, t->len, (const char *)P->f->link_names, RJ_SCENE_NAME_MAX, P->f->link_count) : -1;
        if (idx < 0) return rj__sp_err_tok(P, t, key, rj__sp_nan(), "unknown link ", rj__sp_for(P, key), " (define links above the joints that use them)", NULL);
        if (k == RJ__JK_BODY1) d->body1 = idx; else d->body2 = idx;
        (*i)++;
        return 1;
    }
    case RJ__JK_NODE1:
        if (rj__sp_is(t, "last")) { d->node1 = -1; (*i)++; return 1; }
        if (!rj__sp_int(P, t, key, 0, 1000000, &d->node1)) return 0;
        (*i)++; return 1;
    case RJ__JK_GROUND_ANGLE: return rj__sp_angle(P, i, b, key, 0, &d->ground_angle);
    case RJ__JK_ANGLE0:
        if (!rj__sp_angle(P, i, b, key, 0, &v)) return 0;
        if (!RJ__SP_RULE(v >= -1e6 && v <= 1e6, "must be within +-1e6 rad")) return 0;
        d->angle0 = v; return 1;
    case RJ__JK_RATE0: return rj__sp_angle(P, i, b, key, 1, &d->rate0);
    case RJ__JK_TABLE: return rj__sp_table(P, a, i, b, d);
    case RJ__JK_SPRING:
        if (!rj__sp_num(P, t, key, &v)) return 0;
        (*i)++;
        if (!RJ__SP_RULE(v >= 0, "the spring stiffness must be >= 0 N m/rad")) return 0;
        d->spring_k = v;
        if (*i >= b) return rj__sp_err(P, t->line, t->col + t->len, key, rj__sp_nan(), "missing free angle after the stiffness", rj__sp_where(P), " (spring = k angle)", NULL, NULL);
        a = *i;
        if (!rj__sp_angle(P, i, b, key, 0, &v)) return 0;
        if (!RJ__SP_RULE(v >= -1e6 && v <= 1e6, "the free angle must be within +-1e6 rad")) return 0;
        d->spring_free_angle = v; return 1;
    case RJ__JK_FORWARD: return rj__sp_limit(P, a, i, b, key, &d->has_forward, &d->forward);
    case RJ__JK_REVERSE: return rj__sp_limit(P, a, i, b, key, &d->has_reverse, &d->reverse);
    case RJ__JK_LOCK: if (!rj__sp_bool(P, t, key, &d->lock)) return 0; (*i)++; return 1;
    case RJ__JK_METHOD: if (!rj__sp_enum(P, t, key, rj__sk_method[0], sizeof rj__sk_method[0], 5, &d->method)) return 0; (*i)++; return 1;
    case RJ__JK_RELEASE: if (!rj__sp_enum(P, t, key, rj__sk_release[0], sizeof rj__sk_release[0], 2, &d->release)) return 0; (*i)++; return 1;
    case RJ__JK_REFERENCE: if (!rj__sp_enum(P, t, key, rj__sk_reference[0], sizeof rj__sk_reference[0], 2, &d->reference)) return 0; (*i)++; return 1;
    }
    if (!rj__sp_num(P, t, key, &v)) return 0;
    (*i)++;
    switch (k) {
    case RJ__JK_GROUND_X: d->ground_x = v; break;
    case RJ__JK_GROUND_Y: d->ground_y = v; break;
    case RJ__JK_PENALTY_K: if (!RJ__SP_RULE(v >= 0, "must be >= 0 N m/rad")) return 0; d->penalty_k = v; break;
    case RJ__JK_RESTITUTION: if (!RJ__SP_RULE(v >= 0 && v <= 1, "must be in [0, 1]")) return 0; d->restitution = v; break;
    case RJ__JK_DAMPING: if (!RJ__SP_RULE(v >= 0, "must be >= 0 N m s/rad")) return 0; d->damping = v; break;
    case RJ__JK_FRICTION: if (!RJ__SP_RULE(v >= 0, "must be >= 0 N m")) return 0; d->friction = v; break;
    }
    return 1;
}

static int rj__sp_solver_key(rj__sp *P, int k, int a, int *i, rj_solver_def *s)
{
    const char *key = rj__sk_solver[k];
    const rj__stok *t = &P->tok[a];
    double v = 0;
    if (k == RJ__VK_ALLOW_UNSTABLE) { if (!rj__sp_bool(P, t, key, &s->allow_unstable)) return 0; (*i)++; return 1; }
    if (!rj__sp_num(P, t, key, &v)) return 0;
    (*i)++;
    if (k == RJ__VK_DT) { if (!RJ__SP_RULE(v >= 0 && v <= 1, "must be 0 (automatic) or a step in (0, 1] s")) return 0; s->dt = v; }
    else { if (!RJ__SP_RULE(v > 1, "must be > 1")) return 0; s->energy_growth = v; }
    return 1;
}

/* ------------------------------------------------------------------ sections */
static int rj__sp_key_index(int kind, const rj__stok *t)
{
    int k;
    switch (kind) {
    case RJ__SK_SOLVER: for (k = 0; k < RJ__VK_N; k++) if (rj__sp_is(t, rj__sk_solver[k])) return k; break;
    case RJ__SK_MATERIAL: case RJ__SK_SECTION: case RJ__SK_LINK: {
        unsigned allowed = kind == RJ__SK_MATERIAL ? RJ__SK_MAT_KEYS : kind == RJ__SK_SECTION ? RJ__SK_SEC_KEYS : ~0u;
        for (k = 0; k < RJ__LK_N; k++) if ((allowed >> k & 1u) && rj__sp_is(t, rj__sk_link[k])) return k;
        break;
    }
    case RJ__SK_JOINT: for (k = 0; k < RJ__JK_N; k++) if (rj__sp_is(t, rj__sk_joint[k])) return k; break;
    }
    return -1;
}

static const char *rj__sp_key_name(int kind, int k)
{
    if (kind == RJ__SK_SOLVER) return rj__sk_solver[k];
    if (kind == RJ__SK_JOINT) return rj__sk_joint[k];
    return rj__sk_link[k];
}

/* section rules shared by sections and links: eff = keys in effect, pos[k] where key k came from */
static int rj__sp_check_shape(rj__sp *P, unsigned eff, const rj_link_def *d, const rj_scene_pos *pos, rj_scene_pos head, const char *what)
{
    unsigned gen = (1u << RJ__LK_AREA) | (1u << RJ__LK_INERTIA);
    if (eff & gen) {
        int k;
        if ((eff & gen) != gen) {
            int has = (eff >> RJ__LK_AREA & 1u) ? RJ__LK_AREA : RJ__LK_INERTIA;
            rj_scene_pos p = pos[has].line ? pos[has] : head;
            return rj__sp_err(P, p.line, p.col, rj__sk_link[has], rj__sp_nan(), what, " sets ", rj__sk_link[has],
                              has == RJ__LK_AREA ? " but not inertia" : " but not area", ": a general section needs both area and inertia");
        }
        for (k = RJ__LK_WIDTH; k <= RJ__LK_LAYERS; k++) if (k != RJ__LK_HEIGHT && (eff >> k & 1u)) {
            rj_scene_pos p = pos[k].line ? pos[k] : head;
            return rj__sp_err(P, p.line, p.col, rj__sk_link[k], rj__sp_nan(), what, " mixes ", rj__sk_link[k],
                              " with area/inertia: ", "width and layers apply only to rectangular sections");
        }
    } else if ((eff >> RJ__LK_HEIGHT & 1u) && !(d->height > 0)) {
        return rj__sp_err(P, pos[RJ__LK_HEIGHT].line, pos[RJ__LK_HEIGHT].col, "height", d->height, what,
                          " has height = 0: a rectangular section needs height > 0", NULL, NULL, NULL);
    }
    return 1;
}

/* checks and completes the section that ends here */
static int rj__sp_finish(rj__sp *P)
{
    char what[80];
    switch (P->kind) {
    case RJ__SK_NONE: case RJ__SK_SOLVER: break;
    case RJ__SK_MATERIAL: P->mat[P->item].mask = P->seen; break;
    case RJ__SK_SECTION: {
        rj__spart *s = &P->sec[P->item];
        s->mask = P->seen;
        rj__sp_cat(what, sizeof what, "section '", s->name, "'", NULL, NULL, NULL, NULL);
        if (!rj__sp_check_shape(P, s->mask, &s->d, s->pos + 1, s->pos[0], what)) return 0;
        break;
    }
    case RJ__SK_LINK: {
        rj_link_def *d = &P->f->links[P->item];
        rj_scene_pos *pos = &P->f->link_pos_[(size_t)P->item * (1 + RJ__LK_N)];
        unsigned eff = P->seen;
        int k;
        if (P->link_mat >= 0) {
            const rj__spart *s = &P->mat[P->link_mat];
            if (!(eff >> RJ__LK_E & 1u) && (s->mask >> RJ__LK_E & 1u)) { d->E = s->d.E; pos[1 + RJ__LK_E] = s->pos[1 + RJ__LK_E]; }
            if (!(eff >> RJ__LK_RHO & 1u) && (s->mask >> RJ__LK_RHO & 1u)) { d->rho = s->d.rho; pos[1 + RJ__LK_RHO] = s->pos[1 + RJ__LK_RHO]; }
            eff |= s->mask;
        }
        if (P->link_sec >= 0) {
            const rj__spart *s = &P->sec[P->link_sec];
            for (k = RJ__LK_AREA; k <= RJ__LK_LAYERS; k++) {
                if ((eff >> k & 1u) || !(s->mask >> k & 1u)) continue;
                switch (k) {
                case RJ__LK_AREA: d->area = s->d.area; break;
                case RJ__LK_INERTIA: d->inertia = s->d.inertia; break;
                case RJ__LK_WIDTH: d->width = s->d.width; break;
                case RJ__LK_HEIGHT: d->height = s->d.height; break;
                default: d->layers = s->d.layers; break;
                }
                pos[1 + k] = s->pos[1 + k];
            }
            eff |= s->mask;
        }
        rj__sp_cat(what, sizeof what, "link '", P->f->link_names[P->item], "'", NULL, NULL, NULL, NULL);
        if (!rj__sp_check_shape(P, eff, d, pos + 1, pos[0], what)) return 0;
        d->section = (eff & ((1u << RJ__LK_AREA) | (1u << RJ__LK_INERTIA))) ? RJ_SECTION_GENERAL : RJ_SECTION_RECT;
        break;
    }
    case RJ__SK_JOINT: {
        rj_joint_def *d = &P->f->joints[P->item];
        rj_scene_pos *pos = &P->f->joint_pos_[(size_t)P->item * (1 + RJ__JK_N)];
        const char *jn = P->f->joint_names[P->item];
        char a[24], b[24];
        int k;
        for (k = RJ__JK_BODY1; k <= RJ__JK_BODY2; k++) if (!(P->seen >> k & 1u))
            return rj__sp_err(P, pos[0].line, pos[0].col, rj__sk_joint[k], rj__sp_nan(), "joint '", jn, "' has no ", rj__sk_joint[k],
                              k == RJ__JK_BODY1 ? " (ground or a link)" : " (a link)");
        if (d->body1 == d->body2)
            return rj__sp_err(P, pos[1 + RJ__JK_BODY2].line, pos[1 + RJ__JK_BODY2].col, "body2", d->body2, "joint '", jn, "' connects link '",
                              P->f->link_names[d->body2], "' to itself (body1 = body2)");
        if (d->body1 < 0 && (P->seen >> RJ__JK_NODE1 & 1u))
            return rj__sp_err(P, pos[1 + RJ__JK_NODE1].line, pos[1 + RJ__JK_NODE1].col, "node1", d->node1,
                              "node1 applies only when body1 is a link, in joint '", jn, "' (body1 = ground)", NULL, NULL);
        if (d->body1 >= 0) {
            for (k = RJ__JK_GROUND_X; k <= RJ__JK_GROUND_ANGLE; k++) if (P->seen >> k & 1u)
                return rj__sp_err(P, pos[1 + k].line, pos[1 + k].col, rj__sk_joint[k], rj__sp_nan(), rj__sk_joint[k],
                                  " applies only when body1 = ground, in joint '", jn, "'", NULL);
            if (d->node1 > P->f->links[d->body1].elements) {
                char m[256];
                rj__sp_cat(m, sizeof m, "node1 = ", rj__sp_itoa(a, d->node1), " is out of range in joint '", jn, "': link '",
                           P->f->link_names[d->body1], "' has nodes 0..");
                return rj__sp_err(P, pos[1 + RJ__JK_NODE1].line, pos[1 + RJ__JK_NODE1].col, "node1", d->node1, m,
                                  rj__sp_itoa(b, P->f->links[d->body1].elements), NULL, NULL, NULL);
            }
        }
        break;
    }
    }
    P->kind = RJ__SK_NONE;
    return 1;
}

static int rj__sp_header(rj__sp *P)
{
    const rj__stok *t0 = &P->tok[0], *nt;
    char nb[24];
    int kind = 0, k, cap = 0, count = 0, dup = -1;
    for (k = RJ__SK_SOLVER; k <= RJ__SK_JOINT; k++) if (rj__sp_is(t0, rj__sk_kind[k])) kind = k;
    if (!kind) {
        if (P->kind != RJ__SK_NONE && rj__sp_key_index(P->kind, t0) >= 0) {
            const char *kn = rj__sp_key_name(P->kind, rj__sp_key_index(P->kind, t0));
            return rj__sp_err(P, t0->line, t0->col + t0->len, kn, rj__sp_nan(), "missing '=' after '", kn, "'", rj__sp_where(P), NULL);
        }
        return rj__sp_err_tok(P, t0, "", rj__sp_nan(), P->kind != RJ__SK_NONE ? "unknown key or section " : "unknown section ",
                              P->kind != RJ__SK_NONE ? " (a key needs '= value'; sections are solver, material, section, link, joint)"
                                                     : " (expected solver, material, section, link or joint)", NULL, NULL);
    }
    if (!rj__sp_finish(P)) return 0;
    if (kind == RJ__SK_SOLVER) {
        if (P->ntok > 1) return rj__sp_err_tok(P, &P->tok[1], "", rj__sp_nan(), "unexpected ", " after 'solver' (the solver section has no name)", NULL, NULL);
        if (P->solver_seen)
            return rj__sp_err(P, t0->line, t0->col, "solver", rj__sp_nan(), "duplicate solver section (first on line ",
                              rj__sp_itoa(nb, P->f->solver_pos_[0].line), ")", NULL, NULL);
        P->solver_seen = 1;
        P->f->solver_pos_[0].line = t0->line; P->f->solver_pos_[0].col = t0->col;
        P->kind = kind; P->item = 0; P->seen = 0;
        return 1;
    }
    if (P->ntok < 2) return rj__sp_err(P, t0->line, t0->col + t0->len, rj__sk_kind[kind], rj__sp_nan(), "missing name after '", rj__sk_kind[kind], "'", NULL, NULL);
    nt = &P->tok[1];
    if (nt->kind != 'w' || !rj__sp_name_ok(nt->s, nt->len))
        return rj__sp_err_tok(P, nt, rj__sk_kind[kind], rj__sp_nan(), "invalid name ", " after '", rj__sk_kind[kind],
                              "' (1..31 of A-Z a-z 0-9 _ . -, starting with a letter or _)");
    if (P->ntok > 2) return rj__sp_err_tok(P, &P->tok[2], "", rj__sp_nan(), "unexpected ", " after the name of ", rj__sk_kind[kind], " (one statement per line)");
    switch (kind) {
    case RJ__SK_MATERIAL: cap = RJ_SCENE_MAX_MATERIALS; count = P->nmat; if (count) dup = rj__sp_find(nt->s, nt->len, P->mat[0].name, sizeof(rj__spart), count); break;
    case RJ__SK_SECTION: cap = RJ_SCENE_MAX_SECTIONS; count = P->nsec; if (count) dup = rj__sp_find(nt->s, nt->len, P->sec[0].name, sizeof(rj__spart), count); break;
    case RJ__SK_LINK: cap = RJ_SCENE_MAX_LINKS; count = P->f->link_count; if (count) dup = rj__sp_find(nt->s, nt->len, (const char *)P->f->link_names, RJ_SCENE_NAME_MAX, count); break;
    default: cap = RJ_SCENE_MAX_JOINTS; count = P->f->joint_count; if (count) dup = rj__sp_find(nt->s, nt->len, (const char *)P->f->joint_names, RJ_SCENE_NAME_MAX, count); break;
    }
    if (dup >= 0) {
        int line = kind == RJ__SK_MATERIAL ? P->mat[dup].pos[0].line : kind == RJ__SK_SECTION ? P->sec[dup].pos[0].line
                 : kind == RJ__SK_LINK ? P->f->link_pos_[(size_t)dup * (1 + RJ__LK_N)].line : P->f->joint_pos_[(size_t)dup * (1 + RJ__JK_N)].line;
        char pre[40];
        rj__sp_cat(pre, sizeof pre, "duplicate ", rj__sk_kind[kind], " name ", NULL, NULL, NULL, NULL);
        return rj__sp_err_tok(P, nt, rj__sk_kind[kind], rj__sp_nan(), pre, " (first defined on line ", rj__sp_itoa(nb, line), ")");
    }
    if (kind == RJ__SK_LINK && rj__sp_is(nt, "ground")) return rj__sp_err_tok(P, nt, "link", rj__sp_nan(), "a link cannot be named ", " (reserved for body1 = ground)", NULL, NULL);
    {   /* the counting pass sized the arrays; it never counts fewer items than there are */
        int room = kind == RJ__SK_MATERIAL ? P->cap_mat : kind == RJ__SK_SECTION ? P->cap_sec : kind == RJ__SK_LINK ? P->cap_links : P->cap_joints;
        if (count >= cap || count >= room)
            return rj__sp_err(P, t0->line, t0->col, rj__sk_kind[kind], count + 1, "too many ", rj__sk_kind[kind], " sections (at most ", rj__sp_itoa(nb, cap), ")");
    }
    {
        rj_scene_pos head;
        head.line = t0->line; head.col = t0->col;
        switch (kind) {
        case RJ__SK_MATERIAL: case RJ__SK_SECTION: {
            rj__spart *s = kind == RJ__SK_MATERIAL ? &P->mat[P->nmat++] : &P->sec[P->nsec++];
            memset(s, 0, sizeof *s);
            memcpy(s->name, nt->s, (size_t)nt->len);
            s->d = rj_default_link_def();
            s->pos[0] = head;
            break;
        }
        case RJ__SK_LINK: {
            int n = P->f->link_count++;
            memcpy(P->f->link_names[n], nt->s, (size_t)nt->len);
            P->f->link_names[n][nt->len] = 0;
            P->f->links[n] = rj_default_link_def();
            P->f->link_pos_[(size_t)n * (1 + RJ__LK_N)] = head;
            P->link_mat = -1; P->link_sec = -1;
            break;
        }
        default: {
            int n = P->f->joint_count++;
            memcpy(P->f->joint_names[n], nt->s, (size_t)nt->len);
            P->f->joint_names[n][nt->len] = 0;
            P->f->joints[n] = rj_default_joint_def();
            P->f->joint_pos_[(size_t)n * (1 + RJ__JK_N)] = head;
            break;
        }
        }
        P->kind = kind; P->item = count; P->seen = 0;
    }
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
        while (j < P->ntok && !(P->tok[j].kind == 'w' && j + 1 < P->ntok && P->tok[j + 1].kind == '=')) j++;
        if (P->kind == RJ__SK_NONE)
            return rj__sp_err_tok(P, kt, "", rj__sp_nan(), "key ", " outside any section (start one with solver, material, section, link or joint)", NULL, NULL);
        k = rj__sp_key_index(P->kind, kt);
        if (k < 0) {
            char q[64];
            rj__sp_quote(q, sizeof q, kt->s, kt->len);
            return rj__sp_err_tok(P, kt, q, rj__sp_nan(), "unknown key ", rj__sp_where(P), NULL, NULL);
        }
        kn = rj__sp_key_name(P->kind, k);
        if (P->seen >> k & 1u)
            return rj__sp_err_tok5(P, kt, kn, rj__sp_nan(), "duplicate key ", rj__sp_where(P), " (first set on line ", rj__sp_itoa(nb, rj__sp_pos(P, k)->line), ")");
        if (j == i + 2) {
            const rj__stok *eq = &P->tok[i + 1];
            return rj__sp_err(P, eq->line, eq->col + 1, kn, rj__sp_nan(), "missing value for '", kn, "'", rj__sp_where(P), NULL);
        }
        v = i + 2;
        switch (P->kind) {
        case RJ__SK_SOLVER: if (!rj__sp_solver_key(P, k, i + 2, &v, &P->f->solver)) return 0; break;
        case RJ__SK_MATERIAL: if (!rj__sp_link_key(P, k, i + 2, &v, j, &P->mat[P->item].d)) return 0; break;
        case RJ__SK_SECTION: if (!rj__sp_link_key(P, k, i + 2, &v, j, &P->sec[P->item].d)) return 0; break;
        case RJ__SK_LINK: if (!rj__sp_link_key(P, k, i + 2, &v, j, &P->f->links[P->item])) return 0; break;
        default: if (!rj__sp_joint_key(P, k, i + 2, &v, j, &P->f->joints[P->item])) return 0; break;
        }
        if (v < j) return rj__sp_err_tok5(P, &P->tok[v], kn, rj__sp_nan(), "unexpected ", " after the value of '", kn, "'", rj__sp_where(P));
        P->seen |= 1u << k;
        rj__sp_pos(P, k)->line = P->tok[i + 2].line;
        rj__sp_pos(P, k)->col = P->tok[i + 2].col;
        i = j;
    }
    return 1;
}

/* ------------------------------------------------------------------ lines */
static int rj__sp_is_sep(unsigned char c) { return c == ' ' || c == '\t' || c == '=' || c == ',' || c == '#' || c < 0x20 || c == 0x7f; }

/* next statement into P->tok: returns 1 (maybe empty), 0 at the end, -1 on error.
   A line whose last token is ',' continues on the next line. */
static int rj__sp_next(rj__sp *P)
{
    P->ntok = 0;
    if (P->at >= P->len) return 0;
    for (;;) {
        size_t start = P->at, end = start, n, k;
        char m[120];
        while (end < P->len && P->text[end] != '\n') end++;
        n = end - start;
        if (n && P->text[end - 1] == '\r') n--;
        P->lineno++;
        P->at = end < P->len ? end + 1 : end;
        if (n > RJ_SCENE_MAX_LINE) {
            snprintf(m, sizeof m, "line is longer than %d characters", RJ_SCENE_MAX_LINE);
            rj__sp_fail(P, P->lineno, RJ_SCENE_MAX_LINE + 1, "", rj__sp_nan(), m);
            return -1;
        }
        for (k = 0; k < n;) {
            const char *s = P->text + start + k;
            unsigned char c = (unsigned char)*s;
            if (c == '#') {
                for (; k < n; k++) if (P->text[start + k] == 0) {
                    rj__sp_fail(P, P->lineno, (int)k + 1, "", rj__sp_nan(), "NUL byte in a comment (not a text file?)");
                    return -1;
                }
                break;
            }
            if (c == ' ' || c == '\t') { k++; continue; }
            if (c < 0x20 || c == 0x7f) {
                snprintf(m, sizeof m, "invalid character 0x%02x (a text file has only tabs, spaces and printable characters)", c);
                rj__sp_fail(P, P->lineno, (int)k + 1, "", rj__sp_nan(), m);
                return -1;
            }
            if (P->ntok == RJ_SCENE_MAX_TOKENS) {
                snprintf(m, sizeof m, "statement has more than %d tokens", RJ_SCENE_MAX_TOKENS);
                rj__sp_fail(P, P->lineno, (int)k + 1, "", rj__sp_nan(), m);
                return -1;
            }
            {
                rj__stok *t = &P->tok[P->ntok++];
                t->s = s; t->line = P->lineno; t->col = (int)k + 1;
                if (c == '=' || c == ',') { t->kind = (char)c; t->len = 1; k++; }
                else {
                    size_t e = k + 1;
                    while (e < n && !rj__sp_is_sep((unsigned char)P->text[start + e])) e++;
                    t->kind = 'w'; t->len = (int)(e - k); k = e;
                }
            }
        }
        if (!(P->ntok > 0 && P->tok[P->ntok - 1].kind == ',' && P->at < P->len)) return 1;
    }
}

/* counting pass: an upper bound on each kind of section (a first word that is a section
   keyword and is not followed by '='), capped one above the limits */
static void rj__sp_count(const char *text, size_t len, int counts[6])
{
    size_t at = 0;
    int k;
    for (k = 0; k < 6; k++) counts[k] = 0;
    while (at < len) {
        size_t e, w;
        while (at < len && (text[at] == ' ' || text[at] == '\t')) at++;
        w = at;
        while (at < len && !rj__sp_is_sep((unsigned char)text[at])) at++;
        e = at;
        while (at < len && (text[at] == ' ' || text[at] == '\t')) at++;
        if (e > w && !(at < len && text[at] == '=')) {
            for (k = RJ__SK_MATERIAL; k <= RJ__SK_JOINT; k++) {
                size_t n = strlen(rj__sk_kind[k]);
                if (e - w == n && memcmp(text + w, rj__sk_kind[k], n) == 0) {
                    int cap = k == RJ__SK_MATERIAL ? RJ_SCENE_MAX_MATERIALS : k == RJ__SK_SECTION ? RJ_SCENE_MAX_SECTIONS : k == RJ__SK_LINK ? RJ_SCENE_MAX_LINKS : RJ_SCENE_MAX_JOINTS;
                    if (counts[k] < cap) counts[k]++;
                }
            }
        }
        while (at < len && text[at] != '\n') at++;
        if (at < len) at++;
    }
}

static size_t rj__sp_carve(size_t *off, size_t n, size_t el)
{
    size_t at = (*off + 15) / 16 * 16;
    *off = at + n * el;
    return at;
}

/* field "links[3].rho" / "joints[1].table_angle[2]" / "solver.dt" -> position in f */
static int rj__sp_field_pos(const rj_scene_file *f, const char *field, rj_scene_pos *pos, char *item, size_t isize)
{
    int idx = 0, k, digits = 0, joint;
    const char *p;
    char name[40];
    size_t n = 0;
    item[0] = 0;
    if (strncmp(field, "solver.", 7) == 0) {
        for (k = 0; k < RJ__VK_N; k++) if (strcmp(field + 7, rj__sk_solver[k]) == 0 && f->solver_pos_[1 + k].line) { *pos = f->solver_pos_[1 + k]; return 1; }
        if (f->solver_pos_[0].line) { *pos = f->solver_pos_[0]; return 1; }
        return 0;
    }
    if (strncmp(field, "links[", 6) == 0) { joint = 0; p = field + 6; }
    else if (strncmp(field, "joints[", 7) == 0) { joint = 1; p = field + 7; }
    else return 0;
    while (*p >= '0' && *p <= '9' && digits < 7) { idx = idx * 10 + (*p - '0'); p++; digits++; }
    if (!digits || *p != ']') return 0;
    p++;
    if (joint ? idx >= f->joint_count : idx >= f->link_count) return 0;
    if (*p == '.') {
        p++;
        while (p[n] && p[n] != '[' && n + 1 < sizeof name) { name[n] = p[n]; n++; }
    }
    name[n] = 0;
    rj__sp_cat(item, isize, joint ? " (joint '" : " (link '", joint ? f->joint_names[idx] : f->link_names[idx], "')", NULL, NULL, NULL, NULL);
    if (!joint) {
        const rj_scene_pos *lp = &f->link_pos_[(size_t)idx * (1 + RJ__LK_N)];
        *pos = lp[0];
        for (k = 0; k < RJ__LK_N; k++) if (strcmp(name, rj__sk_link[k]) == 0 && lp[1 + k].line) *pos = lp[1 + k];
        if (strcmp(name, "section") == 0) {
            if (lp[1 + RJ__LK_SECTION].line) *pos = lp[1 + RJ__LK_SECTION];
            else if (lp[1 + RJ__LK_AREA].line) *pos = lp[1 + RJ__LK_AREA];
        }
    } else {
        const rj_scene_pos *jp = &f->joint_pos_[(size_t)idx * (1 + RJ__JK_N)];
        int key = -1;
        *pos = jp[0];
        for (k = 0; k < RJ__JK_N; k++) if (strcmp(name, rj__sk_joint[k]) == 0) key = k;
        if (strncmp(name, "table_", 6) == 0) key = RJ__JK_TABLE;
        if (strncmp(name, "spring_", 7) == 0) key = RJ__JK_SPRING;
        if (strcmp(name, "has_forward") == 0) key = RJ__JK_FORWARD;
        if (strcmp(name, "has_reverse") == 0) key = RJ__JK_REVERSE;
        if (key == RJ__JK_PENALTY_K && !jp[1 + key].line) key = RJ__JK_METHOD;
        if (key == RJ__JK_FORWARD && !jp[1 + key].line) key = RJ__JK_REVERSE;
        if (key >= 0 && jp[1 + key].line) *pos = jp[1 + key];
    }
    return pos->line > 0;
}

/* ------------------------------------------------------------------ public */
RJDEF void rj_scene_file_locate(const rj_scene_file *f, rj_error *err)
{
    char m[sizeof err->msg], item[80];
    rj_scene_pos pos;
    if (!f || !err) return;
    if (rj__sp_field_pos(f, err->field, &pos, item, sizeof item))
    {
        char l[24], c[24], m1[sizeof err->msg];
        rj__sp_cat(m1, sizeof m1, f->filename, ":", rj__sp_itoa(l, pos.line), ":", rj__sp_itoa(c, pos.col), ": ", NULL);
        rj__sp_cat(m, sizeof m, m1, err->msg, item, NULL, NULL, NULL, NULL);
    }
    else
        rj__sp_cat(m, sizeof m, f->filename, ": ", err->msg, NULL, NULL, NULL, NULL);
    memcpy(err->msg, m, sizeof m);
}

RJDEF rj_result rj_scene_parse_ex(const char *text, size_t len, const char *filename, rj_scene_file *out, rj_error *err, void *alloc_ctx)
{
    rj__sp P;
    rj_scene_file F;
    int counts[6], r;
    size_t off = 0, o_links, o_joints, o_lpos, o_jpos, o_lnames, o_jnames, w_tok, w_mat, w_sec;
    char *block = NULL, *work = NULL;
    memset(&P, 0, sizeof P);
    memset(&F, 0, sizeof F);
    if (err) { err->code = RJ_OK; err->field[0] = 0; err->msg[0] = 0; err->value = 0; }
    P.fname = filename ? filename : "<input>";
    P.err = err;
    if (!out || (!text && len)) {
        if (err) { err->code = RJ_ERR_INVALID; snprintf(err->field, sizeof err->field, "%s", out ? "text" : "out"); err->value = 0; snprintf(err->msg, sizeof err->msg, "%s is NULL", out ? "text" : "out"); }
        if (out) memset(out, 0, sizeof *out);
        return RJ_ERR_INVALID;
    }
    memset(out, 0, sizeof *out);
    if (len > RJ_SCENE_MAX_BYTES) {
        char m[120];
        snprintf(m, sizeof m, "input of %lu bytes is larger than the %lu a scene file may have", (unsigned long)len, (unsigned long)RJ_SCENE_MAX_BYTES);
        rj__sp_fail(&P, 1, 1, "", (double)len, m);
        return RJ_ERR_PARSE;
    }
    P.text = text ? text : ""; P.len = len;
    rj__sp_locale(P.dp, &P.dplen);
    rj__sp_count(P.text, len, counts);
    P.cap_links = counts[RJ__SK_LINK]; P.cap_joints = counts[RJ__SK_JOINT];
    P.cap_mat = counts[RJ__SK_MATERIAL]; P.cap_sec = counts[RJ__SK_SECTION];
    /* the result block */
    o_links = rj__sp_carve(&off, (size_t)P.cap_links, sizeof(rj_link_def));
    o_joints = rj__sp_carve(&off, (size_t)P.cap_joints, sizeof(rj_joint_def));
    o_lpos = rj__sp_carve(&off, (size_t)P.cap_links * (1 + RJ__LK_N), sizeof(rj_scene_pos));
    o_jpos = rj__sp_carve(&off, (size_t)P.cap_joints * (1 + RJ__JK_N), sizeof(rj_scene_pos));
    o_lnames = rj__sp_carve(&off, (size_t)P.cap_links, RJ_SCENE_NAME_MAX);
    o_jnames = rj__sp_carve(&off, (size_t)P.cap_joints, RJ_SCENE_NAME_MAX);
    block = (char *)RJ_MALLOC(off + 16, alloc_ctx);
    /* the parser's workspace: tokens, materials, sections */
    off = 0;
    w_tok = rj__sp_carve(&off, RJ_SCENE_MAX_TOKENS, sizeof(rj__stok));
    w_mat = rj__sp_carve(&off, (size_t)P.cap_mat, sizeof(rj__spart));
    w_sec = rj__sp_carve(&off, (size_t)P.cap_sec, sizeof(rj__spart));
    work = block ? (char *)RJ_MALLOC(off + 16, alloc_ctx) : NULL;
    if (!block || !work) {
        if (block) RJ_FREE(block, alloc_ctx);
        if (err) { err->code = RJ_ERR_NOMEM; snprintf(err->field, sizeof err->field, "size"); err->value = (double)off; rj__sp_cat(err->msg, sizeof err->msg, P.fname, ": out of memory", NULL, NULL, NULL, NULL, NULL); }
        return RJ_ERR_NOMEM;
    }
    memset(block, 0, o_jnames + (size_t)P.cap_joints * RJ_SCENE_NAME_MAX);
    F.links = (rj_link_def *)(void *)(block + o_links);
    F.joints = (rj_joint_def *)(void *)(block + o_joints);
    F.link_pos_ = (rj_scene_pos *)(void *)(block + o_lpos);
    F.joint_pos_ = (rj_scene_pos *)(void *)(block + o_jpos);
    F.link_names = (char (*)[RJ_SCENE_NAME_MAX])(void *)(block + o_lnames);
    F.joint_names = (char (*)[RJ_SCENE_NAME_MAX])(void *)(block + o_jnames);
    F.solver = rj_default_solver_def();
    F.block_ = block; F.alloc_ctx_ = alloc_ctx;
    rj__sp_cat(F.filename, sizeof F.filename, P.fname, NULL, NULL, NULL, NULL, NULL, NULL);
    P.f = &F;
    P.tok = (rj__stok *)(void *)(work + w_tok);
    P.mat = (rj__spart *)(void *)(work + w_mat);
    P.sec = (rj__spart *)(void *)(work + w_sec);
    P.kind = RJ__SK_NONE;

    while ((r = rj__sp_next(&P)) > 0) {
        if (!P.ntok) continue;
        if (P.tok[0].kind != 'w') { rj__sp_err_tok(&P, &P.tok[0], "", rj__sp_nan(), "expected a key or a section keyword, found ", NULL, NULL, NULL); goto fail; }
        if (P.ntok >= 2 && P.tok[1].kind == '=') { if (!rj__sp_assignments(&P)) goto fail; }
        else if (!rj__sp_header(&P)) goto fail;
    }
    if (r < 0 || !rj__sp_finish(&P)) goto fail;
    if (F.link_count == 0) {
        rj__sp_fail(&P, P.lineno > 0 ? P.lineno : 1, 1, "link_count", 0, "the scene has no links (a scene needs at least one 'link' section)");
        goto fail;
    }
    RJ_FREE(work, alloc_ctx);
    work = NULL;
    {   /* the model's own validation, located in the file */
        rj_scene_def sd = rj_scene_file_def(&F);
        rj_error me;
        if (rj_model_size(&sd, &me) == 0) {
            rj_scene_file_locate(&F, &me);
            P.code = me.code;
            if (err) *err = me;
            goto fail;
        }
    }
    *out = F;
    return RJ_OK;
fail:
    if (work) RJ_FREE(work, alloc_ctx);
    RJ_FREE(block, alloc_ctx);
    memset(out, 0, sizeof *out);
    return P.code != RJ_OK ? P.code : RJ_ERR_PARSE;
}

RJDEF rj_result rj_scene_parse(const char *text, size_t len, const char *filename, rj_scene_file *out, rj_error *err)
{
    return rj_scene_parse_ex(text, len, filename, out, err, NULL);
}

RJDEF rj_result rj_scene_load(const char *path, rj_scene_file *out, rj_error *err)
{
    FILE *fp;
    char *buf = NULL;
    size_t cap = 0, n = 0;
    rj_result r;
    if (out) memset(out, 0, sizeof *out);
    if (!path || !out) {
        if (err) { err->code = RJ_ERR_INVALID; snprintf(err->field, sizeof err->field, "%s", path ? "out" : "path"); err->value = 0; snprintf(err->msg, sizeof err->msg, "%s is NULL", path ? "out" : "path"); }
        return RJ_ERR_INVALID;
    }
    fp = fopen(path, "rb");
    if (!fp) {
        if (err) { err->code = RJ_ERR_PARSE; snprintf(err->field, sizeof err->field, "path"); err->value = rj__sp_nan(); rj__sp_cat(err->msg, sizeof err->msg, path, ": cannot open the file for reading", NULL, NULL, NULL, NULL, NULL); }
        return RJ_ERR_PARSE;
    }
    for (;;) {
        size_t got;
        if (n == cap) {
            size_t nc = cap ? cap * 2 : 65536;
            char *nb;
            if (nc > (size_t)RJ_SCENE_MAX_BYTES + 1) nc = (size_t)RJ_SCENE_MAX_BYTES + 1;
            if (cap > RJ_SCENE_MAX_BYTES) {
                if (err) { err->code = RJ_ERR_PARSE; snprintf(err->field, sizeof err->field, "path"); err->value = (double)n; rj__sp_cat(err->msg, sizeof err->msg, path, ": the file is larger than 64 MiB (RJ_SCENE_MAX_BYTES)", NULL, NULL, NULL, NULL, NULL); }
                if (buf) RJ_FREE(buf, NULL);
                fclose(fp);
                return RJ_ERR_PARSE;
            }
            nb = (char *)RJ_MALLOC(nc, NULL);
            if (!nb) {
                if (err) { err->code = RJ_ERR_NOMEM; snprintf(err->field, sizeof err->field, "size"); err->value = (double)nc; rj__sp_cat(err->msg, sizeof err->msg, path, ": out of memory reading the file", NULL, NULL, NULL, NULL, NULL); }
                if (buf) RJ_FREE(buf, NULL);
                fclose(fp);
                return RJ_ERR_NOMEM;
            }
            if (n) memcpy(nb, buf, n);
            if (buf) RJ_FREE(buf, NULL);
            buf = nb; cap = nc;
        }
        got = fread(buf + n, 1, cap - n, fp);
        n += got;
        if (got == 0) break;
    }
    if (ferror(fp)) {
        if (err) { err->code = RJ_ERR_PARSE; snprintf(err->field, sizeof err->field, "path"); err->value = rj__sp_nan(); rj__sp_cat(err->msg, sizeof err->msg, path, ": read error", NULL, NULL, NULL, NULL, NULL); }
        RJ_FREE(buf, NULL);
        fclose(fp);
        return RJ_ERR_PARSE;
    }
    fclose(fp);
    r = rj_scene_parse_ex(buf, n, path, out, err, NULL);
    RJ_FREE(buf, NULL);
    return r;
}

RJDEF rj_scene_def rj_scene_file_def(const rj_scene_file *f)
{
    rj_scene_def d = rj_default_scene_def();
    if (!f) return d;
    d.links = f->links; d.link_count = f->link_count;
    d.joints = f->joints; d.joint_count = f->joint_count;
    d.solver = f->solver;
    return d;
}

RJDEF void rj_scene_file_free(rj_scene_file *f)
{
    if (!f) return;
    if (f->block_) RJ_FREE(f->block_, f->alloc_ctx_);
    memset(f, 0, sizeof *f);
}

RJDEF int rj_scene_link_index(const rj_scene_file *f, const char *name)
{
    int k;
    if (!f || !name) return -1;
    for (k = 0; k < f->link_count; k++) if (strcmp(f->link_names[k], name) == 0) return k;
    return -1;
}

RJDEF int rj_scene_joint_index(const rj_scene_file *f, const char *name)
{
    int k;
    if (!f || !name) return -1;
    for (k = 0; k < f->joint_count; k++) if (strcmp(f->joint_names[k], name) == 0) return k;
    return -1;
}

/* ------------------------------------------------------------------ writer */
typedef struct rj__sw { char *buf; size_t size, n; char dp[8]; int dplen; } rj__sw;

static void rj__sw_put(rj__sw *W, const char *s)
{
    size_t k = strlen(s);
    if (W->n < W->size) {
        size_t room = W->size - 1 - W->n, c = k < room ? k : room;
        memcpy(W->buf + W->n, s, c);
        W->buf[W->n + c] = 0;
    }
    W->n += k;
}

/* text of v with '.' whatever the locale; returns whether it reads back as target
   (through rj_rad when deg) */
static int rj__sw_fmt(const rj__sw *W, double v, int fixed, int p, int deg, double target, char *out, size_t size)
{
    char t[400];
    double back = 0;
    int k, o = 0, n = snprintf(t, sizeof t, fixed ? "%.*f" : "%.*g", p, v);
    if (n < 0 || n >= (int)sizeof t) n = 0;
    for (k = 0; k < n && o + 1 < (int)size; ) {
        if (W->dp[0] != '.' && k + W->dplen <= n && memcmp(t + k, W->dp, (size_t)W->dplen) == 0) { out[o++] = '.'; k += W->dplen; }
        else out[o++] = t[k++];
    }
    out[o] = 0;
    return k == n && rj__sp_strtonum(out, o, W->dp, W->dplen, &back) == 1 && (deg ? rj_rad(back) : back) == target;
}

/* shortest text of v that reads back as target: %.Ng (N = 1..17) or, for moderate
   magnitudes, %.Nf (N = 0..17) when that is no longer; returns 0 when none reads back */
static int rj__sw_num_try(const rj__sw *W, double v, int deg, double target, char *out, size_t size)
{
    char g[64], f[64];
    int p, okg = 0, okf = 0;
    for (p = 1; p <= 17 && !okg; p++) okg = rj__sw_fmt(W, v, 0, p, deg, target, g, sizeof g);
    if (fabs(v) < 1e15) for (p = 0; p <= 17 && !okf; p++) okf = rj__sw_fmt(W, v, 1, p, deg, target, f, sizeof f);
    if (okf && (!okg || strlen(f) <= strlen(g))) { memcpy(out, f, strlen(f) + 1 < size ? strlen(f) + 1 : size); out[size - 1] = 0; return 1; }
    if (okg) { memcpy(out, g, strlen(g) + 1 < size ? strlen(g) + 1 : size); out[size - 1] = 0; return 1; }
    rj__sw_fmt(W, v, 0, 17, deg, target, out, size);
    return 0;
}

static void rj__sw_num(rj__sw *W, double v)
{
    char s[64];
    rj__sw_num_try(W, v, 0, v, s, sizeof s);
    rj__sw_put(W, s);
}

/* an angle in the shorter of its exact deg and rad forms ("90 deg", "-10 rad/s") */
static void rj__sw_angle(rj__sw *W, double v, int rate)
{
    char d[64], r[64];
    rj__sw_num_try(W, v, 0, v, r, sizeof r);
    if (rj__sw_num_try(W, rj_deg(v), 1, v, d, sizeof d) && strlen(d) <= strlen(r)) {
        rj__sw_put(W, d);
        rj__sw_put(W, rate ? " deg/s" : " deg");
        return;
    }
    rj__sw_put(W, r);
    rj__sw_put(W, rate ? " rad/s" : " rad");
}

static void rj__sw_key(rj__sw *W, const char *key) { rj__sw_put(W, "  "); rj__sw_put(W, key); rj__sw_put(W, " = "); }

static int rj__sw_finite(double v) { return v - v == 0.0; }

RJDEF size_t rj_scene_write(const rj_scene_def *sc, const char *const *link_names, const char *const *joint_names, char *buf, size_t size)
{
    rj__sw W;
    rj_link_def L0 = rj_default_link_def();
    rj_joint_def J0 = rj_default_joint_def();
    rj_solver_def S0 = rj_default_solver_def();
    char nm[40];
    int i, k;
    if (buf && size) buf[0] = 0;
    if (!sc || sc->link_count < 1 || sc->link_count > RJ_SCENE_MAX_LINKS || !sc->links
        || sc->joint_count < 0 || sc->joint_count > RJ_SCENE_MAX_JOINTS || (sc->joint_count && !sc->joints)) return 0;
    /* names and numbers first: write nothing for a scene that cannot be written */
    for (k = 0; k < 2; k++) {
        const char *const *names = k ? joint_names : link_names;
        int n = k ? sc->joint_count : sc->link_count, a, b;
        if (!names) continue;
        for (a = 0; a < n; a++) {
            if (!names[a] || !rj__sp_name_ok(names[a], (int)strlen(names[a]))) return 0;
            if (!k && strcmp(names[a], "ground") == 0) return 0;
            for (b = 0; b < a; b++) if (names[b] && strcmp(names[a], names[b]) == 0) return 0;
        }
    }
    if (!rj__sw_finite(sc->solver.dt) || !rj__sw_finite(sc->solver.energy_growth) || (sc->solver.allow_unstable != 0 && sc->solver.allow_unstable != 1)) return 0;
    for (i = 0; i < sc->link_count; i++) {
        const rj_link_def *d = &sc->links[i];
        double v[14];
        v[0] = d->length; v[1] = d->E; v[2] = d->rho; v[3] = d->width; v[4] = d->height; v[5] = d->area; v[6] = d->inertia;
        v[7] = d->tip_mass; v[8] = d->tip_inertia; v[9] = d->x; v[10] = d->y; v[11] = d->angle; v[12] = d->vx; v[13] = d->vy;
        for (k = 0; k < 14; k++) if (!rj__sw_finite(v[k])) return 0;
        if (!rj__sw_finite(d->omega) || d->root < 0 || d->root > 3 || (d->section != RJ_SECTION_RECT && d->section != RJ_SECTION_GENERAL)) return 0;
    }
    for (i = 0; i < sc->joint_count; i++) {
        const rj_joint_def *d = &sc->joints[i];
        double v[13];
        if (d->body1 < -1 || d->body1 >= sc->link_count || d->body2 < 0 || d->body2 >= sc->link_count) return 0;
        if ((d->lock & ~1) || (d->has_forward & ~1) || (d->has_reverse & ~1)) return 0;
        if (d->table_count < 0 || d->table_count > RJ_TABLE_MAX || d->method < 0 || d->method > 4 || d->release < 0 || d->release > 1 || d->reference < 0 || d->reference > 1) return 0;
        v[0] = d->ground_x; v[1] = d->ground_y; v[2] = d->ground_angle; v[3] = d->angle0; v[4] = d->rate0; v[5] = d->spring_k;
        v[6] = d->spring_free_angle; v[7] = d->forward; v[8] = d->reverse; v[9] = d->penalty_k; v[10] = d->restitution; v[11] = d->damping; v[12] = d->friction;
        for (k = 0; k < 13; k++) if (!rj__sw_finite(v[k])) return 0;
        for (k = 0; k < d->table_count; k++) if (!rj__sw_finite(d->table_angle[k]) || !rj__sw_finite(d->table_torque[k])) return 0;
    }
    W.buf = buf; W.size = buf ? size : 0; W.n = 0;
    rj__sp_locale(W.dp, &W.dplen);
    rj__sw_put(&W, "# revjoint scene (written by rj_scene_write, revjoint.h " RJ_VERSION ")\n");
    if (sc->solver.dt != S0.dt || sc->solver.allow_unstable || sc->solver.energy_growth != S0.energy_growth) {
        rj__sw_put(&W, "solver\n");
        if (sc->solver.dt != S0.dt) { rj__sw_key(&W, "dt"); rj__sw_num(&W, sc->solver.dt); rj__sw_put(&W, "\n"); }
        if (sc->solver.allow_unstable) { rj__sw_key(&W, "allow_unstable"); rj__sw_put(&W, "yes\n"); }
        if (sc->solver.energy_growth != S0.energy_growth) { rj__sw_key(&W, "energy_growth"); rj__sw_num(&W, sc->solver.energy_growth); rj__sw_put(&W, "\n"); }
    }
    for (i = 0; i < sc->link_count; i++) {
        const rj_link_def *d = &sc->links[i];
        int root_link = 1;
        for (k = 0; k < sc->joint_count; k++) if (sc->joints[k].body2 == i) root_link = 0;
        if (link_names) snprintf(nm, sizeof nm, "%s", link_names[i]); else snprintf(nm, sizeof nm, "link%d", i);
        rj__sw_put(&W, "link "); rj__sw_put(&W, nm); rj__sw_put(&W, "\n");
        rj__sw_key(&W, "length"); rj__sw_num(&W, d->length);
        snprintf(nm, sizeof nm, "  elements = %d\n", d->elements); rj__sw_put(&W, nm);
        rj__sw_key(&W, "E"); rj__sw_num(&W, d->E); rj__sw_put(&W, "  rho = "); rj__sw_num(&W, d->rho); rj__sw_put(&W, "\n");
        if (d->section == RJ_SECTION_GENERAL) {
            rj__sw_key(&W, "area"); rj__sw_num(&W, d->area); rj__sw_put(&W, "  inertia = "); rj__sw_num(&W, d->inertia);
            if (d->height != L0.height) { rj__sw_put(&W, "  height = "); rj__sw_num(&W, d->height); }
            rj__sw_put(&W, "\n");
        } else {
            rj__sw_key(&W, "width"); rj__sw_num(&W, d->width); rj__sw_put(&W, "  height = "); rj__sw_num(&W, d->height);
            if (d->layers != L0.layers) { snprintf(nm, sizeof nm, "  layers = %d", d->layers); rj__sw_put(&W, nm); }
            rj__sw_put(&W, "\n");
        }
        if (d->tip_mass != 0 || d->tip_inertia != 0) {
            rj__sw_key(&W, "tip_mass"); rj__sw_num(&W, d->tip_mass); rj__sw_put(&W, "  tip_inertia = "); rj__sw_num(&W, d->tip_inertia); rj__sw_put(&W, "\n");
        }
        if (d->root != L0.root) { rj__sw_key(&W, "root"); rj__sw_put(&W, rj__sk_root[d->root]); rj__sw_put(&W, "\n"); }
        if (d->x != 0 || d->y != 0 || d->angle != 0) {
            rj__sw_key(&W, "x"); rj__sw_num(&W, d->x); rj__sw_put(&W, "  y = "); rj__sw_num(&W, d->y);
            rj__sw_put(&W, "  angle = "); rj__sw_angle(&W, d->angle, 0); rj__sw_put(&W, root_link ? "\n" : "   # unused: the link hangs from a joint\n");
        }
        if (d->vx != 0 || d->vy != 0 || d->omega != 0) {
            rj__sw_key(&W, "vx"); rj__sw_num(&W, d->vx); rj__sw_put(&W, "  vy = "); rj__sw_num(&W, d->vy);
            rj__sw_put(&W, "  omega = "); rj__sw_angle(&W, d->omega, 1); rj__sw_put(&W, "\n");
        }
    }
    for (i = 0; i < sc->joint_count; i++) {
        const rj_joint_def *d = &sc->joints[i];
        if (joint_names) snprintf(nm, sizeof nm, "%s", joint_names[i]); else snprintf(nm, sizeof nm, "joint%d", i);
        rj__sw_put(&W, "joint "); rj__sw_put(&W, nm); rj__sw_put(&W, "\n");
        rj__sw_key(&W, "body1");
        if (d->body1 < 0) rj__sw_put(&W, "ground");
        else if (link_names) rj__sw_put(&W, link_names[d->body1]);
        else { snprintf(nm, sizeof nm, "link%d", d->body1); rj__sw_put(&W, nm); }
        rj__sw_put(&W, "  body2 = ");
        if (link_names) rj__sw_put(&W, link_names[d->body2]);
        else { snprintf(nm, sizeof nm, "link%d", d->body2); rj__sw_put(&W, nm); }
        if (d->body1 >= 0 && d->node1 != -1) { snprintf(nm, sizeof nm, "  node1 = %d", d->node1); rj__sw_put(&W, nm); }
        rj__sw_put(&W, "\n");
        if (d->body1 < 0 && (d->ground_x != 0 || d->ground_y != 0 || d->ground_angle != 0)) {
            rj__sw_key(&W, "ground_x"); rj__sw_num(&W, d->ground_x); rj__sw_put(&W, "  ground_y = "); rj__sw_num(&W, d->ground_y);
            rj__sw_put(&W, "  ground_angle = "); rj__sw_angle(&W, d->ground_angle, 0); rj__sw_put(&W, "\n");
        }
        rj__sw_key(&W, "angle0"); rj__sw_angle(&W, d->angle0, 0);
        if (d->rate0 != 0) { rj__sw_put(&W, "  rate0 = "); rj__sw_angle(&W, d->rate0, 1); }
        rj__sw_put(&W, "\n");
        if (d->table_count > 0) {
            rj__sw_key(&W, "table");
            for (k = 0; k < d->table_count; k++) {
                if (k) rj__sw_put(&W, k % 4 == 0 ? ",\n    " : ", ");
                rj__sw_angle(&W, d->table_angle[k], 0); rj__sw_put(&W, " "); rj__sw_num(&W, d->table_torque[k]);
            }
            rj__sw_put(&W, "\n");
        }
        if (d->spring_k != J0.spring_k || d->spring_free_angle != J0.spring_free_angle) {
            rj__sw_key(&W, "spring"); rj__sw_num(&W, d->spring_k); rj__sw_put(&W, " "); rj__sw_angle(&W, d->spring_free_angle, 0); rj__sw_put(&W, "\n");
        }
        if (d->has_forward) { rj__sw_key(&W, "forward"); rj__sw_angle(&W, d->forward, 0); rj__sw_put(&W, "\n"); }
        if (d->has_reverse) { rj__sw_key(&W, "reverse"); rj__sw_angle(&W, d->reverse, 0); rj__sw_put(&W, "\n"); }
        if (d->lock) { rj__sw_key(&W, "lock"); rj__sw_put(&W, "yes\n"); }
        rj__sw_key(&W, "method"); rj__sw_put(&W, rj__sk_method[d->method]);
        if (d->release != J0.release) { rj__sw_put(&W, "  release = "); rj__sw_put(&W, rj__sk_release[d->release]); }
        if (d->reference != J0.reference) { rj__sw_put(&W, "  reference = "); rj__sw_put(&W, rj__sk_reference[d->reference]); }
        rj__sw_put(&W, "\n");
        if (d->penalty_k != 0) { rj__sw_key(&W, "penalty_k"); rj__sw_num(&W, d->penalty_k); rj__sw_put(&W, "\n"); }
        if (d->restitution != 0) { rj__sw_key(&W, "restitution"); rj__sw_num(&W, d->restitution); rj__sw_put(&W, "\n"); }
        if (d->damping != 0) { rj__sw_key(&W, "damping"); rj__sw_num(&W, d->damping); rj__sw_put(&W, "\n"); }
        if (d->friction != 0) { rj__sw_key(&W, "friction"); rj__sw_num(&W, d->friction); rj__sw_put(&W, "\n"); }
    }
    return W.n;
}

#endif /* REVJOINT_IMPLEMENTATION */
