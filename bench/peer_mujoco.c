/* peer_mujoco.c - the two-link deployment of Wong, Hamouda & Hashmi (2002, sec. 5) in
   MuJoCo 2.2.2, as a benchmark peer for revjoint.h.

   MODEL
   Each link of length L is cut into N segments (l = L/N) and lumped into N + 1 rigid
   bodies of lengths l/2, l, ..., l, l/2 (rigid finite elements of Kruszewski and
   Wittbrodt): uniform thin rods of mass (m/L) l_p and rotary inertia m_p l_p^2/12, joined
   by z hinges of stiffness EI/l at the segment midpoints.  Joint 1 pins link 1's first
   piece to the ground, joint 2 joins link 1's last piece to link 2's first piece; both
   carry the preloaded torsion spring (stiffness + springref) and Coulomb friction
   (frictionloss).  Tip masses are bodies welded at the far end of each link's last piece.
   The latches are joint equalities, inactive at the start and switched on (eq_active) at
   the first step where q1 >= 90 deg or q2 <= 0.  Equalities and friction use
   solref = (2 dt, 1) and solimp = (0.9999, 0.9999, 0.001, 0.5, 2).  No gravity, no
   contacts.  q1 = qpos of joint 1, q2 = qpos of joint 2 (axis +z, 0 straight, pi folded).

   USAGE
   peer_mujoco --pieces N --integrator euler|rk4 --dt S [--t-end 6] [--csv FILE]
               [--repeat R] [--print-xml]
   Exit 0 ok, 1 bad arguments, 2 unstable run (NaN or MuJoCo warning), 3 other failure.

   RESULTS (MuJoCo 2.2.2, Debian libmujoco-dev, gcc 12 -O2, 2-core VM, one thread)
   1. Largest stable step on the grid 4, 2, 1, 0.5, 0.25, 0.125 ms (6 s without a warning,
      lock 2 in [2.9, 3.1] s, lock 1 in [3.9, 4.3] s); CPU = median of 5 runs of 6 s:
        N   integrator  dt         steps   CPU s    lock2 s   lock1 s
        5   euler       1 ms        6000   0.034    2.997000  4.057000
        5   rk4         2 ms        3000   0.067    3.000000  4.056000
        10  euler       0.25 ms    24000   0.297    2.996750  4.056250
        10  rk4         0.5 ms     12000   0.599    2.997500  4.056500
        20  euler       none on the grid (0.125 ms blows up at 6 ms); halving on:
                        0.0625 ms  96000   3.54     2.997562  4.057125
        20  rk4         0.125 ms   48000   6.96     2.997750  4.057250
      The limits are the explicit stiff-spring ones: the highest natural frequency of the
      chain at the start (power iteration on M^-1 K) is 1147, 4752, 19189 rad/s for N = 5,
      10, 20 (~N^2), i.e. dt < 2/w = 1.74, 0.42, 0.104 ms for Euler and dt < 2.83/w = 2.47,
      0.60, 0.147 ms for RK4, matching the grid results.
   2. Sanity checks (CSV every 1 ms, reference interpolated linearly in t):
      (a) EI x 1e4 (--ei-scale 1e4), N = 5, euler, dt 0.01 ms, against build/deploy --rigid:
          max |q1 - q1_rigid| = 0.0072 deg, max |q2 - q2_rigid| = 0.015 deg for t < 2.99 s
          (both at t = 2.989 s); locks 3.00379 / 4.19495 s vs rigid 3.003872 / 4.212324 s.
      (b) against deploy --elements 40 (locks 2.997260 / 4.060255 s), t < 2.99 s, and tip
          deflection RMS over [3.2, 6] s (peer: tangent-based; reference tip2_defl_m: chord-
          based, RMS 0.077657 m):
            N = 20 euler 0.25 ms: unstable (see 1); at 0.0625 ms: max|dq1| 0.021 deg,
                   max|dq2| 0.051 deg, RMS 0.080695 m; at 0.03125 ms: 0.023 / 0.050 deg,
                   RMS 0.080694 m (converged in dt, within 0.007 deg of 0.0625 ms)
            N = 20 rk4 0.125 ms:  0.034 / 0.071 deg, RMS 0.080696 m
            N = 10 euler 0.25 ms: 0.020 / 0.104 deg, RMS 0.080627 m
            N = 5 euler 1 ms:     0.052 / 0.092 deg, RMS 0.080294 m
   3. Latch violation |q - lock angle| (stderr line of a single run).  At the switch-on
      step the joint has overshot by up to one step of travel (N = 5 euler 1 ms: 0.025 deg
      joint 1, 0.008 deg joint 2; N = 20 euler 0.0625 ms: 0.0017 / 0.0082 deg); the
      constraint pulls it back within a few time constants (2 dt) and from 10 ms after the
      lock on it stays within 1.5e-3 / 6.9e-4 deg (N = 5 euler 1 ms), 2.8e-4 deg (N = 10
      euler 0.25 ms), 1.5e-4 deg (N = 20 euler 0.0625 ms), 5.8e-4 deg (N = 20 rk4 0.125 ms),
      7.5e-6 deg (stiff links, dt 0.01 ms); the settled violation scales about as dt^2.
   Friction uses the same stiff solref/solimp as the latches (solreffriction,
   solimpfriction), so frictionloss is close to ideal Coulomb friction.
*/
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <mujoco/mujoco.h>

#define PI 3.14159265358979323846
#define DEG (180.0 / PI)
#define SAMPLE_DT 1e-3
#define SETTLE_S 0.01
#define MAX_PIECES 2000
#define MAX_REPEAT 100000
#define XML_NAME "peer_deploy.xml"

/* Mechanism data (Wong, Hamouda & Hashmi 2002, Table 3), index 0 = link 1. */
static const double LEN[2] = {1.006423, 0.9945};
static const double EI[2] = {20.5879, 20.3819};
static const double MASS[2] = {0.52334, 0.42958};
static const double TIP_M[2] = {1.2, 0.336};
static const double TIP_J[2] = {8.5948e-4, 9.256e-4};
static const double FRIC[2] = {0.03825, 0.0225};
static const double SPRING_K[2] = {0.0789, 0.0768};
static const double PRE_DEG[2] = {300.0, -60.0};
static const double LOCK_DEG[2] = {90.0, 0.0};
static const double Q0_DEG[2] = {0.0, 180.0};

/* Command-line options. */
typedef struct {
    int pieces;
    int integrator; /* mjINT_EULER or mjINT_RK4 */
    double dt;
    double t_end;
    const char *csv;
    int repeat;
    int print_xml;
    double ei_scale; /* sanity check: stiffen the links (--ei-scale) */
} options;

/* A growing text buffer for the generated XML. */
typedef struct {
    char *s;
    size_t len;
    size_t cap;
} strbuf;

/* The loaded model and the indices the run loop needs. */
typedef struct {
    mjModel *m;
    mjData *d;
    int qadr[2];   /* qpos addresses of joints 1, 2 */
    int eq[2];     /* equality ids of the latches */
    int root2;     /* body id of link 2's first piece */
    int tip2;      /* body id of link 2's tip mass */
    long steps;
} sim;

/* What one run found. */
typedef struct {
    double lock_t[2];
    double viol_all[2];    /* max |q - lock| after the latch, deg */
    double viol_settle[2]; /* same, from SETTLE_S after the latch on */
    double q_end_deg[2];
} result;

/* ------------------------------------------------------------------ arguments */

/* The usage text goes to stderr on every argument error. */
static void usage(void)
{
    fputs("usage: peer_mujoco --pieces N --integrator euler|rk4 --dt S [--t-end T]\n"
          "                   [--csv FILE | --repeat R] [--print-xml] [--ei-scale F]\n"
          "  --pieces N       segments per link (bodies per link = N + 1), 1..2000\n"
          "  --integrator X   euler (MuJoCo semi-implicit Euler) or rk4\n"
          "  --dt S           time step in seconds (> 0)\n"
          "  --t-end T        simulated time in seconds (default 6)\n"
          "  --csv FILE       one run, t,q1_deg,q2_deg,tip2_defl_m every 1 ms\n"
          "  --repeat R       R timed runs, median CPU and wall time of the step loop\n"
          "  --print-xml      print the generated MJCF to stdout and exit\n"
          "  --ei-scale F     multiply EI by F (sanity check with stiff links)\n",
          stderr);
}

/* Strict integer parsing: the whole string, in range. */
static int parse_int(const char *s, int lo, int hi, int *out)
{
    char *end = NULL;
    long v;
    errno = 0;
    v = strtol(s, &end, 10);
    if (errno != 0 || end == s || *end != '\0' || v < lo || v > hi)
        return -1;
    *out = (int)v;
    return 0;
}

/* Strict floating-point parsing: the whole string, finite and positive. */
static int parse_pos(const char *s, double *out)
{
    char *end = NULL;
    double v;
    errno = 0;
    v = strtod(s, &end);
    if (errno != 0 || end == s || *end != '\0' || !isfinite(v) || v <= 0.0)
        return -1;
    *out = v;
    return 0;
}

/* The integrator name maps onto MuJoCo's enum. */
static int parse_integrator(const char *s, int *out)
{
    if (strcmp(s, "euler") == 0) {
        *out = mjINT_EULER;
        return 0;
    }
    if (strcmp(s, "rk4") == 0) {
        *out = mjINT_RK4;
        return 0;
    }
    return -1;
}

/* One option with its value; returns 0 if recognised and valid. */
static int parse_valued(options *o, const char *name, const char *val)
{
    if (strcmp(name, "--pieces") == 0)
        return parse_int(val, 1, MAX_PIECES, &o->pieces);
    if (strcmp(name, "--integrator") == 0)
        return parse_integrator(val, &o->integrator);
    if (strcmp(name, "--dt") == 0)
        return parse_pos(val, &o->dt);
    if (strcmp(name, "--t-end") == 0)
        return parse_pos(val, &o->t_end);
    if (strcmp(name, "--repeat") == 0)
        return parse_int(val, 1, MAX_REPEAT, &o->repeat);
    if (strcmp(name, "--ei-scale") == 0)
        return parse_pos(val, &o->ei_scale);
    if (strcmp(name, "--csv") == 0 && val[0] != '\0') {
        o->csv = val;
        return 0;
    }
    return -1;
}

/* The required options must be present and --csv excludes --repeat. */
static int check_options(const options *o)
{
    if (o->pieces <= 0 || o->integrator < 0 || o->dt <= 0.0) {
        fputs("peer_mujoco: --pieces, --integrator and --dt are required\n", stderr);
        return -1;
    }
    if (o->csv != NULL && o->repeat > 0) {
        fputs("peer_mujoco: --csv and --repeat exclude each other\n", stderr);
        return -1;
    }
    if (o->dt > o->t_end) {
        fputs("peer_mujoco: --dt is longer than --t-end\n", stderr);
        return -1;
    }
    return 0;
}

/* Parse argv into o; every error ends up as usage + exit 1 in main. */
static int parse_args(int argc, char **argv, options *o)
{
    int i;
    o->pieces = 0;
    o->integrator = -1;
    o->dt = 0.0;
    o->t_end = 6.0;
    o->csv = NULL;
    o->repeat = 0;
    o->print_xml = 0;
    o->ei_scale = 1.0;
    for (i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--print-xml") == 0) {
            o->print_xml = 1;
            continue;
        }
        if (i + 1 >= argc || parse_valued(o, argv[i], argv[i + 1]) != 0) {
            fprintf(stderr, "peer_mujoco: bad or incomplete option '%s'\n", argv[i]);
            return -1;
        }
        i++;
    }
    return check_options(o);
}

/* ------------------------------------------------------------------ XML */

/* Append printf-formatted text, growing the buffer as needed. */
static int sb_printf(strbuf *b, const char *fmt, ...)
{
    va_list ap;
    int n;
    va_start(ap, fmt);
    n = vsnprintf(b->s + b->len, b->cap - b->len, fmt, ap);
    va_end(ap);
    if (n < 0)
        return -1;
    if ((size_t)n >= b->cap - b->len) {
        size_t cap = 2 * (b->cap + (size_t)n);
        char *s = (char *)realloc(b->s, cap);
        if (s == NULL)
            return -1;
        b->s = s;
        b->cap = cap;
        va_start(ap, fmt);
        n = vsnprintf(b->s + b->len, b->cap - b->len, fmt, ap);
        va_end(ap);
    }
    b->len += (size_t)n;
    return 0;
}

/* Options: no gravity, no contacts, the chosen integrator and step. */
static int xml_head(strbuf *b, const options *o)
{
    const char *integ = o->integrator == mjINT_RK4 ? "RK4" : "Euler";
    int e = sb_printf(b, "<mujoco model=\"wong2002_deploy\">\n"
                         "  <compiler angle=\"radian\"/>\n"
                         "  <option timestep=\"%.17g\" integrator=\"%s\" gravity=\"0 0 0\">\n"
                         "    <flag contact=\"disable\"/>\n"
                         "  </option>\n"
                         "  <worldbody>\n",
                      o->dt, integ);
    return e;
}

/* The deployment joint on link k's root piece: spring, friction, stiff constraint. */
static int xml_deploy_joint(strbuf *b, int k, double dt)
{
    double spring_ref = PRE_DEG[k] / DEG;
    return sb_printf(b, "<joint name=\"j%d\" type=\"hinge\" axis=\"0 0 1\" "
                        "stiffness=\"%.17g\" springref=\"%.17g\" frictionloss=\"%.17g\" "
                        "solreffriction=\"%.17g 1\" "
                        "solimpfriction=\"0.9999 0.9999 0.001 0.5 2\"/>\n",
                     k + 1, SPRING_K[k], spring_ref, FRIC[k], 2.0 * dt);
}

/* Open piece j of link k (body, joint, inertial); the body is left open for nesting. */
static int xml_piece(strbuf *b, const options *o, int k, int j, double pos)
{
    int n = o->pieces;
    double l = LEN[k] / n;
    double lp = (j == 0 || j == n) ? 0.5 * l : l;
    double mp = MASS[k] / LEN[k] * lp;
    double ip = mp * lp * lp / 12.0;
    int e = sb_printf(b, "<body name=\"%c%d\" pos=\"%.17g 0 0\">\n", 'a' + k, j, pos);
    if (j == 0)
        e |= xml_deploy_joint(b, k, o->dt);
    else
        e |= sb_printf(b, "<joint name=\"f%c%d\" type=\"hinge\" axis=\"0 0 1\" "
                          "stiffness=\"%.17g\"/>\n",
                       'a' + k, j, o->ei_scale * EI[k] / l);
    e |= sb_printf(b, "<inertial pos=\"%.17g 0 0\" mass=\"%.17g\" "
                      "diaginertia=\"%.17g %.17g %.17g\"/>\n",
                   0.5 * lp, mp, 1e-3 * ip, ip, ip);
    return e;
}

/* The tip mass of link k, welded at the far end of its last piece. */
static int xml_tip(strbuf *b, int k, double pos)
{
    return sb_printf(b, "<body name=\"tip%d\" pos=\"%.17g 0 0\">"
                        "<inertial pos=\"0 0 0\" mass=\"%.17g\" "
                        "diaginertia=\"%.17g %.17g %.17g\"/></body>\n",
                     k + 1, pos, TIP_M[k], TIP_J[k], TIP_J[k], TIP_J[k]);
}

/* Open all pieces of link k; the last one is left open so link 2 nests inside. */
static int xml_link(strbuf *b, const options *o, int k, double root_pos)
{
    int n = o->pieces;
    double l = LEN[k] / n;
    int e = 0;
    int j;
    for (j = 0; j <= n; j++) {
        double pos = j == 0 ? root_pos : (j == 1 ? 0.5 * l : l);
        e |= xml_piece(b, o, k, j, pos);
    }
    e |= xml_tip(b, k, 0.5 * l);
    return e;
}

/* Close the 2 (N + 1) open bodies, then the latches (inactive at the start). */
static int xml_tail(strbuf *b, const options *o)
{
    int e = 0;
    int j;
    for (j = 0; j < 2 * (o->pieces + 1); j++)
        e |= sb_printf(b, "</body>\n");
    e |= sb_printf(b, "  </worldbody>\n  <equality>\n");
    for (j = 0; j < 2; j++)
        e |= sb_printf(b, "    <joint name=\"lock%d\" joint1=\"j%d\" active=\"false\" "
                          "polycoef=\"%.17g 0 0 0 0\" solref=\"%.17g 1\" "
                          "solimp=\"0.9999 0.9999 0.001 0.5 2\"/>\n",
                       j + 1, j + 1, LOCK_DEG[j] / DEG, 2.0 * o->dt);
    e |= sb_printf(b, "  </equality>\n</mujoco>\n");
    return e;
}

/* The whole MJCF text; the caller frees b->s. */
static int build_xml(strbuf *b, const options *o)
{
    double half1 = 0.5 * LEN[0] / o->pieces;
    int e;
    b->cap = 4096;
    b->len = 0;
    b->s = (char *)malloc(b->cap);
    if (b->s == NULL)
        return -1;
    b->s[0] = '\0';
    e = xml_head(b, o);
    e |= xml_link(b, o, 0, 0.0);
    e |= xml_link(b, o, 1, half1);
    e |= xml_tail(b, o);
    return e;
}

/* ------------------------------------------------------------------ model */

/* Compile the XML text through MuJoCo's virtual file system (no temp files). */
static mjModel *load_model(const strbuf *b)
{
    char err[1000] = "";
    mjModel *m = NULL;
    mjVFS *vfs = (mjVFS *)malloc(sizeof(mjVFS));
    if (vfs == NULL)
        return NULL;
    mj_defaultVFS(vfs);
    if (mj_makeEmptyFileVFS(vfs, XML_NAME, (int)b->len) == 0) {
        memcpy(vfs->filedata[mj_findFileVFS(vfs, XML_NAME)], b->s, b->len);
        m = mj_loadXML(XML_NAME, vfs, err, (int)sizeof(err));
    }
    if (m == NULL)
        fprintf(stderr, "peer_mujoco: model compile failed: %s\n", err);
    mj_deleteVFS(vfs);
    free(vfs);
    return m;
}

/* Look up the ids the run loop uses; -1 if any name is missing. */
static int find_ids(sim *s)
{
    const mjModel *m = s->m;
    int j1 = mj_name2id(m, mjOBJ_JOINT, "j1");
    int j2 = mj_name2id(m, mjOBJ_JOINT, "j2");
    s->eq[0] = mj_name2id(m, mjOBJ_EQUALITY, "lock1");
    s->eq[1] = mj_name2id(m, mjOBJ_EQUALITY, "lock2");
    s->root2 = mj_name2id(m, mjOBJ_BODY, "b0");
    s->tip2 = mj_name2id(m, mjOBJ_BODY, "tip2");
    if (j1 < 0 || j2 < 0 || s->eq[0] < 0 || s->eq[1] < 0 || s->root2 < 0 || s->tip2 < 0)
        return -1;
    s->qadr[0] = m->jnt_qposadr[j1];
    s->qadr[1] = m->jnt_qposadr[j2];
    return 0;
}

/* Start state: at rest, q1 = 0, q2 = 180 deg, latches off. */
static void reset_sim(sim *s)
{
    int k;
    mj_resetData(s->m, s->d);
    for (k = 0; k < 2; k++) {
        s->d->qpos[s->qadr[k]] = Q0_DEG[k] / DEG;
        s->m->eq_active[s->eq[k]] = 0;
    }
    s->steps = 0;
}

/* ------------------------------------------------------------------ running */

/* Unstable = any MuJoCo warning counted (bad qpos/qvel/qacc, singular inertia, ...). */
static int unstable(const mjData *d)
{
    int i;
    for (i = 0; i < mjNWARNING; i++)
        if (d->warning[i].number > 0)
            return 1;
    return 0;
}

/* Switch a latch on at the first step where its joint reaches the lock angle. */
static void latch(sim *s, result *r)
{
    double q1 = s->d->qpos[s->qadr[0]];
    double q2 = s->d->qpos[s->qadr[1]];
    double t = s->steps * s->m->opt.timestep;
    if (!s->m->eq_active[s->eq[0]] && q1 >= LOCK_DEG[0] / DEG) {
        s->m->eq_active[s->eq[0]] = 1;
        r->lock_t[0] = t;
    }
    if (!s->m->eq_active[s->eq[1]] && q2 <= LOCK_DEG[1] / DEG) {
        s->m->eq_active[s->eq[1]] = 1;
        r->lock_t[1] = t;
    }
}

/* Link 2's tip deflection from the tangent at its root (needs current kinematics). */
static double tip_defl(const sim *s)
{
    const mjData *d = s->d;
    const double *p0 = d->xpos + 3 * s->root2;
    const double *pt = d->xpos + 3 * s->tip2;
    const double *r = d->xmat + 9 * s->root2;
    double phi = atan2(r[3], r[0]);
    return cos(phi) * (pt[1] - p0[1]) - sin(phi) * (pt[0] - p0[0]);
}

/* One CSV row at the current state. */
static void csv_row(sim *s, FILE *f)
{
    double t = s->steps * s->m->opt.timestep;
    mj_kinematics(s->m, s->d);
    fprintf(f, "%.6f,%.10g,%.10g,%.10g\n", t, s->d->qpos[s->qadr[0]] * DEG,
            s->d->qpos[s->qadr[1]] * DEG, tip_defl(s));
}

/* Track how far each latched joint strays from its lock angle. */
static void observe(const sim *s, result *r)
{
    double t = s->steps * s->m->opt.timestep;
    int k;
    for (k = 0; k < 2; k++) {
        double v;
        if (!s->m->eq_active[s->eq[k]])
            continue;
        v = fabs(s->d->qpos[s->qadr[k]] * DEG - LOCK_DEG[k]);
        if (v > r->viol_all[k])
            r->viol_all[k] = v;
        if (t >= r->lock_t[k] + SETTLE_S && v > r->viol_settle[k])
            r->viol_settle[k] = v;
    }
}

/* Steps between CSV rows: 1 ms of simulated time, or every step if dt > 1 ms. */
static long sample_every(double dt)
{
    long k = lround(SAMPLE_DT / dt);
    return k < 1 ? 1 : k;
}

/* Clear a result before a run. */
static void result_init(result *r)
{
    int k;
    for (k = 0; k < 2; k++) {
        r->lock_t[k] = NAN;
        r->viol_all[k] = 0.0;
        r->viol_settle[k] = 0.0;
    }
}

/* Simulate nsteps from the reset state; csv and track may be NULL (timed runs).
   Returns 0, or 2 on an unstable run. */
static int run_sim(sim *s, long nsteps, FILE *csv, int track, result *r)
{
    long every = sample_every(s->m->opt.timestep);
    int k;
    reset_sim(s);
    result_init(r);
    if (csv != NULL)
        csv_row(s, csv);
    while (s->steps < nsteps) {
        mj_step(s->m, s->d);
        s->steps++;
        if (unstable(s->d))
            return 2;
        latch(s, r);
        if (track)
            observe(s, r);
        if (csv != NULL && s->steps % every == 0)
            csv_row(s, csv);
    }
    for (k = 0; k < 2; k++)
        r->q_end_deg[k] = s->d->qpos[s->qadr[k]] * DEG;
    return isfinite(r->q_end_deg[0]) && isfinite(r->q_end_deg[1]) ? 0 : 2;
}

/* ------------------------------------------------------------------ timing */

/* Seconds on the given clock. */
static double now(clockid_t c)
{
    struct timespec ts;
    clock_gettime(c, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* qsort comparator for doubles. */
static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a;
    double y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Median of n values (sorts in place). */
static double median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof(double), cmp_double);
    if (n % 2 == 1)
        return v[n / 2];
    return 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* R timed runs of the whole simulation; medians of CPU and wall time. */
static int timed_runs(sim *s, long nsteps, int reps, result *r, double *cpu, double *wall)
{
    double *c = (double *)malloc(sizeof(double) * (size_t)reps);
    double *w = (double *)malloc(sizeof(double) * (size_t)reps);
    int rc = 0;
    int i;
    if (c == NULL || w == NULL)
        rc = 3;
    for (i = 0; i < reps && rc == 0; i++) {
        double c0 = now(CLOCK_PROCESS_CPUTIME_ID);
        double w0 = now(CLOCK_MONOTONIC);
        rc = run_sim(s, nsteps, NULL, 0, r);
        c[i] = now(CLOCK_PROCESS_CPUTIME_ID) - c0;
        w[i] = now(CLOCK_MONOTONIC) - w0;
    }
    if (rc == 0) {
        *cpu = median(c, reps);
        *wall = median(w, reps);
    }
    free(c);
    free(w);
    return rc;
}

/* ------------------------------------------------------------------ main */

/* The one-line summary every mode prints. */
static void print_summary(const options *o, long nsteps, const result *r, double cpu, double wall)
{
    printf("pieces %d integrator %s dt %.9g steps %ld cpu_median_s %.6g wall_median_s %.6g "
           "lock1_s %.6f lock2_s %.6f\n",
           o->pieces, o->integrator == mjINT_RK4 ? "rk4" : "euler", o->dt, nsteps, cpu, wall,
           r->lock_t[0], r->lock_t[1]);
}

/* Diagnostics of a single run: the latch constraint violation and the end state. */
static void print_diag(const result *r)
{
    fprintf(stderr, "latch violation (deg): joint1 max %.3g, max from %g s after lock %.3g; "
                    "joint2 max %.3g, from %g s after lock %.3g; end q1 %.9g q2 %.9g\n",
            r->viol_all[0], SETTLE_S, r->viol_settle[0], r->viol_all[1], SETTLE_S,
            r->viol_settle[1], r->q_end_deg[0], r->q_end_deg[1]);
}

/* A single run, timed once, with CSV rows and latch diagnostics. */
static int single_run(sim *s, const options *o, long nsteps)
{
    result r;
    FILE *f = NULL;
    double c0;
    double w0;
    int rc;
    if (o->csv != NULL) {
        f = fopen(o->csv, "w");
        if (f == NULL) {
            fprintf(stderr, "peer_mujoco: cannot open %s\n", o->csv);
            return 3;
        }
        fputs("t,q1_deg,q2_deg,tip2_defl_m\n", f);
    }
    c0 = now(CLOCK_PROCESS_CPUTIME_ID);
    w0 = now(CLOCK_MONOTONIC);
    rc = run_sim(s, nsteps, f, 1, &r);
    c0 = now(CLOCK_PROCESS_CPUTIME_ID) - c0;
    w0 = now(CLOCK_MONOTONIC) - w0;
    if (f != NULL && fclose(f) != 0)
        rc = rc ? rc : 3;
    if (rc == 0) {
        print_summary(o, nsteps, &r, c0, w0);
        print_diag(&r);
    }
    return rc;
}

/* Run the requested mode on a compiled model. */
static int run_mode(sim *s, const options *o)
{
    long nsteps = lround(o->t_end / o->dt);
    result r;
    double cpu = 0.0;
    double wall = 0.0;
    int rc;
    if (o->repeat == 0)
        return single_run(s, o, nsteps);
    rc = timed_runs(s, nsteps, o->repeat, &r, &cpu, &wall);
    if (rc == 0)
        print_summary(o, nsteps, &r, cpu, wall);
    return rc;
}

/* MuJoCo prints its warnings to stdout by default; keep stdout for the summary. */
static void warn_to_stderr(const char *msg)
{
    fprintf(stderr, "MuJoCo warning: %s\n", msg);
}

/* Compile, run, report; the exit status says how it went. */
int main(int argc, char **argv)
{
    options o;
    strbuf b;
    sim s;
    int rc;
    mju_user_warning = warn_to_stderr;
    if (parse_args(argc, argv, &o) != 0) {
        usage();
        return 1;
    }
    if (build_xml(&b, &o) != 0) {
        fprintf(stderr, "peer_mujoco: out of memory\n");
        return 3;
    }
    if (o.print_xml) {
        fputs(b.s, stdout);
        free(b.s);
        return 0;
    }
    s.m = load_model(&b);
    free(b.s);
    if (s.m == NULL)
        return 3;
    s.d = mj_makeData(s.m);
    rc = s.d != NULL && find_ids(&s) == 0 ? run_mode(&s, &o) : 3;
    if (rc == 2)
        fprintf(stderr, "peer_mujoco: unstable run (NaN or MuJoCo warning) at t = %.6f s "
                        "(pieces %d, dt %g)\n",
                s.steps * o.dt, o.pieces, o.dt);
    mj_deleteData(s.d);
    mj_deleteModel(s.m);
    return rc;
}
