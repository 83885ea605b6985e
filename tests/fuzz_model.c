/* fuzz_model.c - libFuzzer target for model building (rj_model_size, rj_model_create) from
   definition structs.
   Build and run from the repository root (one process: the machine's cores are shared):
     clang -g -O1 -fsanitize=fuzzer,address,undefined tests/fuzz_model.c -I. -o /tmp/fuzz_model -lm
     mkdir -p /tmp/fuzz_work_model && /tmp/fuzz_model -jobs=1 -max_total_time=600 -max_len=1024 /tmp/fuzz_work_model
   The input is a stream that fills an rj_scene_def: 1..8 links and 0..8 joints, each from
   rj_default_link_def() / rj_default_joint_def() (links of 3 elements, not 10, for speed;
   joints default to a chain from ground),
   the solver from rj_default_solver_def(), then a few fields of each overwritten with values
   drawn from NaN, +-inf, denormals, huge and tiny numbers, zero, negatives, ordinary values
   and raw bytes (ints: small ones, INT_MIN, INT_MAX, element-count edges, raw bytes). After
   the joints, 0..3 applied loads (sc.loads, load_count; NULL when 0) from
   rj_default_load_def() (load i on link i mod the link count, its last node, force 0 -1 N),
   their fields drawn the same way (link, node, force, moment, follower, the time table's
   count and points, or a whole table with strictly increasing times 1 s .. 1 ns apart);
   one count byte in 64 instead gives a load_count from the int pool with loads NULL. Last,
   the caller's inputs of the state the checks step: a byte whose bits switch on
   rj_state_joint_torques / rj_state_node_forces, then for each up to 3 entries set from
   the same value pool (NaN and inf too: the step must refuse them). A read past the end of
   the input gives zeros, so an input that stops after the joints has no loads and no
   inputs.
   Scenes with a link of more than RJ_FUZZ_MAX_ELEMENTS elements are only validated
   (rj_model_size); one input in 16 is such a scene on purpose, with up to 4096 links copied
   from the first eight (so the node count can pass 2^31). Then:
   - a failure (rj_model_size 0, rj_model_create not RJ_OK) must fill rj_error with its code,
     a field and a message;
   - a size must be at least the 13 doubles per node the model's arrays take;
   - a built model must have a finite dt > 0, a finite bound > 0 (dt within it unless
     allow_unstable), solver.dt when one was given, finite node masses >= 0, and, with a
     flexible or inextensible link, an omega_max that is finite and at least half of
     sqrt(u.Au) for unit vectors u (a Rayleigh quotient of rj_model_apply_stiffness, whose
     every value must be finite), so a bound the model does not have is caught;
   - it must hold the scene's loads as given (rj_model_load_count, rj_model_load_def: the
     same bytes);
   - its state (rj_state_create) must be finite (node positions, velocities, rotations,
     energies, the applied work), and, with the decoded inputs set, each of a few rj_step
     calls must return an error with a message, or RJ_OK with a finite state after every
     step.
   Every violation prints "fuzz_model: <what>" and aborts. The same file with
   -DFUZZ_MODEL_PRINT (no -fsanitize=fuzzer) is a program that prints the scene an input
   file stands for (the fields that differ from the defaults) and then runs the checks on it:
     clang -g -O1 -fsanitize=address,undefined -DFUZZ_MODEL_PRINT tests/fuzz_model.c -I. -o /tmp/fuzz_model_print -lm */
#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define REVJOINT_IMPLEMENTATION
#include "../revjoint.h"

#ifndef RJ_FUZZ_MAX_ELEMENTS
#define RJ_FUZZ_MAX_ELEMENTS 64
#endif
#define FZ_MAX_LINKS 8
#define FZ_MAX_JOINTS 8
#define FZ_MAX_LOADS 3
#define FZ_MAX_INPUTS 3
#define FZ_HUGE_LINKS 4096
#define FZ_STEPS 5

static void fz_fail(const char *fmt, ...)
{
    va_list ap;
    fprintf(stderr, "fuzz_model: ");
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fprintf(stderr, "\n");
    abort();
}

static int fz_finite(double x) { return x == x && x - x == 0.0; }

/* ---------------------------------------------------------------- the stream */
typedef struct fz_in { const uint8_t *p; size_t n, at; } fz_in;
static unsigned fz_u8(fz_in *in) { return in->at < in->n ? in->p[in->at++] : 0u; }
static unsigned fz_u16(fz_in *in) { unsigned a = fz_u8(in); return a | fz_u8(in) << 8; }
static unsigned fz_u32(fz_in *in) { unsigned a = fz_u16(in); return a | fz_u16(in) << 16; }

static double fz_double(fz_in *in)
{
    static const double v[] = {
        0.0, -0.0, 1.0, -1.0, 0.5, 2.0, 3.0, 10.0, 0.05, 0.2, 0.9, 1e-3, 1e-6, 1e-9, 1e6, 1e9, 7e10, 2710.0,
        3.14159265358979323846, -3.14159265358979323846, 6.28318530717958647692, 6.2831853071795853 /* just below 2 pi */,
        4.9e-324, -4.9e-324, 2.2250738585072014e-308, 1e-45, 1e-100, 1e-160, 1e-300, -1e-300,
        1e20, -1e20, 1e300, -1e300, 1e308, -1e308, DBL_MAX, HUGE_VAL, -HUGE_VAL, 0.0 /* NaN, below */
    };
    const unsigned n = sizeof v / sizeof v[0];
    unsigned sel = fz_u8(in);
    if (sel < 96) {
        if (sel % n == n - 1) return nan("");
        return v[sel % n];
    }
    if (sel < 192) {                     /* ordinary: (0..15.9) x 10^(-20..20), either sign */
        double mant = fz_u8(in) / 16.0;
        int e = (int)(fz_u8(in) % 41) - 20;
        return (sel & 1 ? -1.0 : 1.0) * mant * pow(10.0, e);
    }
    {                                    /* raw bits */
        unsigned char r[8];
        double d;
        int i;
        for (i = 0; i < 8; i++) r[i] = (unsigned char)fz_u8(in);
        memcpy(&d, r, sizeof d);
        return d;
    }
}

static int fz_int(fz_in *in)
{
    static const int v[] = {
        INT_MIN, INT_MIN + 1, INT_MAX, INT_MAX - 1, -1000000, -1, 0, 1, 2, 31, 32, 33, 63, 64, 65, 100, 1000, 1001,
        100000, 100001, 1000000, 1000001, 2147, 65536
    };
    unsigned sel = fz_u8(in);
    if (sel < 128) return (int)(sel % 12) - 2;      /* -2..9: enums, indices, small counts */
    if (sel < 200) return v[sel % (sizeof v / sizeof v[0])];
    return (int)fz_u32(in);
}

/* ---------------------------------------------------------------- the definitions */
static void fz_link(fz_in *in, rj_link_def *L)
{
    int k, n = (int)(fz_u8(in) % 6);
    *L = rj_default_link_def();
    L->elements = 3;                                 /* fewer than the default 10: the bound's Lanczos runs take the time */
    for (k = 0; k < n; k++) {
        switch (fz_u8(in) % 21) {
        case 0: L->length = fz_double(in); break;
        case 1: L->elements = fz_int(in); break;
        case 2: L->E = fz_double(in); break;
        case 3: L->rho = fz_double(in); break;
        case 4: L->section = fz_int(in); break;
        case 5: L->width = fz_double(in); break;
        case 6: L->height = fz_double(in); break;
        case 7: L->layers = fz_int(in); break;
        case 8: L->area = fz_double(in); break;
        case 9: L->inertia = fz_double(in); break;
        case 10: L->tip_mass = fz_double(in); break;
        case 11: L->tip_inertia = fz_double(in); break;
        case 12: L->root = fz_int(in); break;
        case 13: L->x = fz_double(in); break;
        case 14: L->y = fz_double(in); break;
        case 15: L->angle = fz_double(in); break;
        case 16: L->vx = fz_double(in); break;
        case 17: L->vy = fz_double(in); break;
        case 18: L->omega = fz_double(in); break;
        case 19: L->fidelity = fz_int(in); break;
        default: if (fz_u8(in) == 0) L->cookie = fz_u32(in); break;   /* rarely: an undefaulted struct */
        }
    }
}

static void fz_joint(fz_in *in, rj_joint_def *J, int j, int nl)
{
    int k, n = (int)(fz_u8(in) % 6);
    *J = rj_default_joint_def();
    J->body2 = j < nl ? j : j % nl;                  /* a chain from ground */
    J->body1 = j < nl ? j - 1 : -1;
    for (k = 0; k < n; k++) {
        switch (fz_u8(in) % 27) {
        case 0: J->body1 = fz_int(in); break;
        case 1: J->node1 = fz_int(in); break;
        case 2: J->body2 = fz_int(in); break;
        case 3: J->ground_x = fz_double(in); break;
        case 4: J->ground_y = fz_double(in); break;
        case 5: J->ground_angle = fz_double(in); break;
        case 6: J->angle0 = fz_double(in); break;
        case 7: J->rate0 = fz_double(in); break;
        case 8: J->table_count = fz_int(in); break;
        case 9: J->table_angle[fz_u8(in) % RJ_TABLE_MAX] = fz_double(in); break;
        case 10: J->table_torque[fz_u8(in) % RJ_TABLE_MAX] = fz_double(in); break;
        case 11: J->spring_k = fz_double(in); break;
        case 12: J->spring_free_angle = fz_double(in); break;
        case 13: J->has_forward = fz_int(in); break;
        case 14: J->forward = fz_double(in); break;
        case 15: J->has_reverse = fz_int(in); break;
        case 16: J->reverse = fz_double(in); break;
        case 17: J->lock = fz_int(in); break;
        case 18: J->method = fz_int(in); break;
        case 19: J->release = fz_int(in); break;
        case 20: J->penalty_k = fz_double(in); break;
        case 21: J->restitution = fz_double(in); break;
        case 22: J->damping = fz_double(in); break;
        case 23: J->friction = fz_double(in); break;
        case 24: J->reference = fz_int(in); break;
        case 25: {                                   /* a whole valid-looking table */
            int c = 2 + (int)(fz_u8(in) % (RJ_TABLE_MAX - 1)), i;
            J->table_count = c;
            for (i = 0; i < c; i++) { J->table_angle[i] = 6.28318530717958647692 * i / (c - 1); J->table_torque[i] = fz_double(in); }
            break;
        }
        default: if (fz_u8(in) == 0) J->cookie = fz_u32(in); break;
        }
    }
}

/* load i starts on link i mod nl (fz_decode's count before the huge copies), its last
   node, with a force of 1 N down: the defaults' zero force would apply nothing */
static void fz_load(fz_in *in, rj_load_def *D, int i, int nl)
{
    int k, n = (int)(fz_u8(in) % 6);
    *D = rj_default_load_def();
    D->link = i % nl;
    D->force[1] = -1.0;
    for (k = 0; k < n; k++) {
        switch (fz_u8(in) % 11) {
        case 0: D->link = fz_int(in); break;
        case 1: D->node = fz_int(in); break;
        case 2: D->force[0] = fz_double(in); break;
        case 3: D->force[1] = fz_double(in); break;
        case 4: D->moment = fz_double(in); break;
        case 5: D->follower = fz_int(in); break;
        case 6: D->table_count = fz_int(in); break;
        case 7: D->table_time[fz_u8(in) % RJ_TABLE_MAX] = fz_double(in); break;
        case 8: D->table_factor[fz_u8(in) % RJ_TABLE_MAX] = fz_double(in); break;
        case 9: {                                    /* a whole valid-looking table: times 0, h, 2h, ... */
            int c = 1 + (int)(fz_u8(in) % RJ_TABLE_MAX), p;
            double h = pow(10.0, -(double)(fz_u8(in) % 10));
            D->table_count = c;
            for (p = 0; p < c; p++) { D->table_time[p] = h * p; D->table_factor[p] = fz_double(in); }
            break;
        }
        default: if (fz_u8(in) == 0) D->cookie = fz_u32(in); break;
        }
    }
}

static void fz_solver(fz_in *in, rj_solver_def *S)
{
    int k, n = (int)(fz_u8(in) % 4);
    *S = rj_default_solver_def();
    for (k = 0; k < n; k++) {
        switch (fz_u8(in) % 6) {
        case 0: S->dt = fz_double(in); break;
        case 1: S->allow_unstable = fz_int(in); break;
        case 2: S->energy_growth = fz_double(in); break;
        case 3: S->energy_every = fz_int(in); break;
        case 4: S->in_place = fz_int(in); break;
        default: if (fz_u8(in) == 0) S->cookie = fz_u32(in); break;
        }
    }
}

/* the caller's inputs set on the state before the steps: entry index (taken modulo the
   count of the model) and value; and, for the printer, the link count fz_load saw */
typedef struct fz_inputs {
    int torques_on, forces_on, nt, nf, nl0;
    unsigned t_at[FZ_MAX_INPUTS], f_at[FZ_MAX_INPUTS];
    double t_val[FZ_MAX_INPUTS], f_val[FZ_MAX_INPUTS];
} fz_inputs;

static void fz_read_inputs(fz_in *in, fz_inputs *I)
{
    unsigned sw = fz_u8(in);
    int k;
    memset(I, 0, sizeof *I);
    I->torques_on = sw & 1;
    I->forces_on = (sw >> 1) & 1;
    if (I->torques_on) {
        I->nt = (int)(fz_u8(in) % (FZ_MAX_INPUTS + 1));
        for (k = 0; k < I->nt; k++) { I->t_at[k] = fz_u16(in); I->t_val[k] = fz_double(in); }
    }
    if (I->forces_on) {
        I->nf = (int)(fz_u8(in) % (FZ_MAX_INPUTS + 1));
        for (k = 0; k < I->nf; k++) { I->f_at[k] = fz_u16(in); I->f_val[k] = fz_double(in); }
    }
}

/* ---------------------------------------------------------------- the checks */
static void fz_check_error(const char *call, rj_result r, const rj_error *err)
{
    if (err->code != r || err->msg[0] == 0 || err->field[0] == 0 || memchr(err->msg, 0, sizeof err->msg) == NULL || memchr(err->field, 0, sizeof err->field) == NULL)
        fz_fail("%s failed with %d: error code %d field \"%s\" message \"%s\"", call, (int)r, (int)err->code, err->field, err->msg);
}

static void fz_check_state(const rj_model *m, const rj_state *s, const char *when)
{
    int l, i, j;
    rj_energy e;
    for (l = 0; l < rj_model_link_count(m); l++) for (i = 0; i < rj_link_node_count(m, l); i++) {
        double xy[2], v[2], r;
        rj_node_position(m, s, l, i, xy);
        rj_node_velocity(m, s, l, i, v);
        r = rj_node_rotation(m, s, l, i);
        if (!fz_finite(xy[0]) || !fz_finite(xy[1])) fz_fail("%s: link %d node %d position (%g, %g)", when, l, i, xy[0], xy[1]);
        if (!fz_finite(v[0]) || !fz_finite(v[1]) || !fz_finite(r)) fz_fail("%s: link %d node %d velocity (%g, %g) rotation %g", when, l, i, v[0], v[1], r);
    }
    for (j = 0; j < rj_model_joint_count(m); j++) {
        int flag = rj_joint_flag(m, s, j);
        if (!fz_finite(rj_joint_theta_running(m, s, j)) || !fz_finite(rj_joint_rate(m, s, j)))
            fz_fail("%s: joint %d running angle %g rate %g", when, j, rj_joint_theta_running(m, s, j), rj_joint_rate(m, s, j));
        if (flag < RJ_FREE || flag > RJ_LOCKED) fz_fail("%s: joint %d flag %d", when, j, flag);
    }
    rj_state_energy(m, s, &e);
    if (!fz_finite(e.kinetic) || !fz_finite(e.strain) || !fz_finite(e.spring) || !fz_finite(e.gravity) || !fz_finite(e.work_applied)
        || !fz_finite(e.total) || !fz_finite(e.balance))
        fz_fail("%s: energy not finite: kinetic %g strain %g spring %g gravity %g work %g total %g balance %g", when,
                e.kinetic, e.strain, e.spring, e.gravity, e.work_applied, e.total, e.balance);
    if (!fz_finite(rj_state_time(s))) fz_fail("%s: time %g", when, rj_state_time(s));
}

/* a built model: its step, bound and masses, its linearisation, then a state and a few steps */
static void fz_check_model(const rj_scene_def *sc, const fz_inputs *I, rj_model *m)
{
    double dt = rj_model_dt(m), bound = rj_model_dt_bound(m), om = rj_model_omega_max(m), diag = 0;
    int l, i, nn = 0, flexible = 0, k;
    rj_state *s = NULL;
    rj_result r;
    if (!fz_finite(dt) || !(dt > 0)) fz_fail("model dt %g (bound %g, omega_max %g)", dt, bound, om);
    if (!fz_finite(bound) || !(bound > 0)) fz_fail("model bound %g (dt %g, omega_max %g)", bound, dt, om);
    if (!fz_finite(om) || om < 0) fz_fail("model omega_max %g", om);
    if (!sc->solver.allow_unstable && dt > bound) fz_fail("model dt %g above its bound %g without allow_unstable", dt, bound);
    if (sc->solver.dt > 0 && dt != sc->solver.dt) fz_fail("model dt %g, solver.dt %g", dt, sc->solver.dt);
    if (rj_model_link_count(m) != sc->link_count || rj_model_joint_count(m) != sc->joint_count) fz_fail("model counts");
    for (l = 0; l < sc->link_count; l++) {
        const rj_link_def *d = &sc->links[l];
        if (rj_link_node_count(m, l) != d->elements + 1) fz_fail("link %d has %d nodes", l, rj_link_node_count(m, l));
        nn += d->elements + 1;
        if (d->fidelity != RJ_LINK_RIGID && d->root != RJ_ROOT_FIXED) flexible = 1;
        for (i = 0; i <= d->elements; i++) {
            double ms, ri;
            rj_node_mass(m, l, i, &ms, &ri);
            if (!fz_finite(ms) || ms < 0 || !fz_finite(ri) || ri < 0) fz_fail("link %d node %d mass %g rotary inertia %g", l, i, ms, ri);
        }
    }
    if (rj_model_node_count(m) != nn) fz_fail("model node count %d, links give %d", rj_model_node_count(m), nn);
    if (rj_model_load_count(m) != sc->load_count) fz_fail("model has %d loads, the scene %d", rj_model_load_count(m), sc->load_count);
    for (l = 0; l < sc->load_count; l++)
        if (memcmp(rj_model_load_def(m, l), &sc->loads[l], sizeof(rj_load_def)) != 0) fz_fail("model's load %d differs from the scene's", l);
    if (flexible) {
        /* unit vectors on up to 48 DOFs spread over the model: each u.Au is a lower bound of omega_max^2 */
        const int n = 3 * nn, stride = n / 48 + 1;
        double *u = (double *)calloc((size_t)n, sizeof(double)), *out = (double *)malloc(sizeof(double) * (size_t)n);
        double *work = (double *)malloc(sizeof(double) * (rj_model_work_size(m) + 1));
        if (!u || !out || !work) abort();
        for (i = 0; i < n; i += stride) {
            int q;
            u[i] = 1.0;
            rj_model_apply_stiffness(m, u, out, work);
            u[i] = 0.0;
            for (q = 0; q < n; q++) if (!fz_finite(out[q])) fz_fail("linearised model: K u[%d] = %g at DOF %d (dt %g, bound %g)", i, out[q], q, dt, bound);
            if (out[i] > diag) diag = out[i];
        }
        free(u); free(out); free(work);
        if (!(om >= 0.5 * sqrt(diag))) fz_fail("omega_max %g below half of sqrt(u.Au) = %g: bound %g, dt %g", om, sqrt(diag), bound, dt);
    }
    r = rj_state_create(m, &s, NULL);
    if (r != RJ_OK) fz_fail("rj_state_create returned %d", (int)r);
    fz_check_state(m, s, "initial state");
    if (I->torques_on) {
        double *tq = rj_state_joint_torques(m, s);
        const int nj = rj_model_joint_count(m);
        for (k = 0; k < I->nt && nj > 0; k++) tq[I->t_at[k] % (unsigned)nj] = I->t_val[k];
    }
    if (I->forces_on) {
        double *fn = rj_state_node_forces(m, s);
        for (k = 0; k < I->nf; k++) fn[I->f_at[k] % (unsigned)(3 * nn)] = I->f_val[k];
    }
    for (k = 0; k < FZ_STEPS; k++) {
        const double t = rj_state_time(s);
        r = rj_step(m, s);
        if (r != RJ_OK) {
            if (rj_state_error(s)[0] == 0) fz_fail("step %d returned %d without an error message", k, (int)r);
            break;
        }
        /* every RJ_OK step leaves a finite state (rj_step checks what it writes) */
        (void)t;
        fz_check_state(m, s, "after a step");
    }
    rj_state_destroy(s, NULL);
}

/* ---------------------------------------------------------------- the target */
/* The scene an input stands for: links, joints and loads are malloc'd at their exact counts
   (so a read past them is caught); *build is 0 for scenes that are only validated; *I the
   caller's inputs for the steps. */
static rj_scene_def fz_decode(const uint8_t *data, size_t size, int *build, fz_inputs *I)
{
    fz_in in;
    rj_link_def tmpl[FZ_MAX_LINKS], *links;
    rj_joint_def *joints;
    rj_load_def *loads = NULL;
    rj_scene_def sc;
    int nl, nj, i, huge, nl0, nload;
    unsigned lsel;
    in.p = data; in.n = size; in.at = 0;
    nl = 1 + (int)(fz_u8(&in) % FZ_MAX_LINKS);
    nj = (int)(fz_u8(&in) % (FZ_MAX_JOINTS + 1));
    huge = fz_u8(&in) % 16 == 0;
    sc = rj_default_scene_def();
    fz_solver(&in, &sc.solver);
    for (i = 0; i < nl; i++) fz_link(&in, &tmpl[i]);
    nl0 = nl;
    *build = 1;
    if (huge) {                                      /* many copies of the links, validated only */
        int n = 1 + (int)(fz_u16(&in) % FZ_HUGE_LINKS);
        for (i = 0; i < nl; i++) if (fz_u8(&in) & 1) tmpl[i].elements = 1000000;
        links = (rj_link_def *)malloc(sizeof(rj_link_def) * (size_t)n);
        if (!links) abort();
        for (i = 0; i < n; i++) links[i] = tmpl[i % nl];
        nl = n;
        *build = 0;
    } else {
        links = (rj_link_def *)malloc(sizeof(rj_link_def) * (size_t)nl);
        if (!links) abort();
        memcpy(links, tmpl, sizeof(rj_link_def) * (size_t)nl);
    }
    joints = (rj_joint_def *)malloc(sizeof(rj_joint_def) * (size_t)(nj ? nj : 1));
    if (!joints) abort();
    for (i = 0; i < nj; i++) fz_joint(&in, &joints[i], i, nl);
    lsel = fz_u8(&in);
    if (lsel % 64 == 63) nload = fz_int(&in);         /* rarely: a count with no array */
    else {
        nload = (int)(lsel % (FZ_MAX_LOADS + 1));
        if (nload) {
            loads = (rj_load_def *)malloc(sizeof(rj_load_def) * (size_t)nload);
            if (!loads) abort();
            for (i = 0; i < nload; i++) fz_load(&in, &loads[i], i, nl0);
        }
    }
    fz_read_inputs(&in, I);
    I->nl0 = nl0;
    for (i = 0; i < nl; i++) if (links[i].elements > RJ_FUZZ_MAX_ELEMENTS) *build = 0;
    sc.links = links; sc.link_count = nl; sc.joints = joints; sc.joint_count = nj;
    sc.loads = loads; sc.load_count = nload;
    return sc;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    rj_scene_def sc;
    fz_inputs inputs;
    rj_error err;
    int i, build;
    double nodes = 0;
    size_t need;
    sc = fz_decode(data, size, &build, &inputs);
    for (i = 0; i < sc.link_count; i++) nodes += (double)sc.links[i].elements + 1.0;
    memset(&err, 0, sizeof err);
    need = rj_model_size(&sc, &err);
    if (need == 0) fz_check_error("rj_model_size", RJ_ERR_INVALID, &err);
    else if ((double)need < 13.0 * sizeof(double) * nodes) fz_fail("rj_model_size %lu bytes for %.0f nodes", (unsigned long)need, nodes);
    if (build) {
        rj_model *m = NULL;
        rj_result r;
        memset(&err, 0, sizeof err);
        r = rj_model_create(&sc, &m, &err, NULL);
        if (r == RJ_OK) {
            if (need == 0) fz_fail("rj_model_create accepted a scene rj_model_size rejected (%s)", err.msg);
            fz_check_model(&sc, &inputs, m);
            rj_model_destroy(m, NULL);
        } else {
            fz_check_error("rj_model_create", r, &err);
            if (r != RJ_ERR_INVALID && r != RJ_ERR_UNSTABLE_DT && r != RJ_ERR_NOMEM) fz_fail("rj_model_create returned %d", (int)r);
        }
    }
    free((void *)sc.links);
    free((void *)sc.joints);
    free((void *)sc.loads);
    return 0;
}

#ifdef FUZZ_MODEL_PRINT
/* prints the fields of the scene an input file stands for that differ from the defaults
   (%.17g), then runs the target on it */
static void fz_pd(const char *item, int i, const char *name, double v, double def)
{
    if (memcmp(&v, &def, sizeof v) != 0) printf("%s[%d].%s = %.17g\n", item, i, name, v);
}
static void fz_pi(const char *item, int i, const char *name, long v, long def)
{
    if (v != def) printf("%s[%d].%s = %ld\n", item, i, name, v);
}
int main(int argc, char **argv)
{
    static uint8_t buf[1 << 16];
    size_t n;
    int i, k, build, shown;
    rj_scene_def sc;
    fz_inputs inputs;
    rj_load_def D0 = rj_default_load_def();
    rj_link_def L0 = rj_default_link_def();
    rj_joint_def J0 = rj_default_joint_def();
    const rj_solver_def S0 = rj_default_solver_def();
    FILE *f;
    if (argc != 2 || !(f = fopen(argv[1], "rb"))) { fprintf(stderr, "usage: %s INPUT\n", argv[0]); return 2; }
    L0.elements = 3;                                 /* fz_link's starting point */
    n = fread(buf, 1, sizeof buf, f);
    fclose(f);
    sc = fz_decode(buf, n, &build, &inputs);
    printf("%d links, %d joints, %d loads%s%s\n", sc.link_count, sc.joint_count, sc.load_count,
           sc.load_count && !sc.loads ? " (no array)" : "", build ? "" : " (validated only)");
    fz_pd("solver", 0, "dt", sc.solver.dt, S0.dt); fz_pi("solver", 0, "allow_unstable", sc.solver.allow_unstable, S0.allow_unstable);
    fz_pd("solver", 0, "energy_growth", sc.solver.energy_growth, S0.energy_growth); fz_pi("solver", 0, "energy_every", sc.solver.energy_every, S0.energy_every);
    fz_pi("solver", 0, "in_place", sc.solver.in_place, S0.in_place); fz_pi("solver", 0, "cookie", (long)sc.solver.cookie, (long)S0.cookie);
    for (i = 0, shown = 0; i < sc.link_count && shown < 16; i++) {
        const rj_link_def *L = &sc.links[i];
        if (i >= 8 && memcmp(L, &sc.links[i % 8], sizeof *L) == 0) continue;
        shown++;
        fz_pd("links", i, "length", L->length, L0.length); fz_pi("links", i, "elements", L->elements, L0.elements);
        fz_pd("links", i, "E", L->E, L0.E); fz_pd("links", i, "rho", L->rho, L0.rho); fz_pi("links", i, "section", L->section, L0.section);
        fz_pd("links", i, "width", L->width, L0.width); fz_pd("links", i, "height", L->height, L0.height); fz_pi("links", i, "layers", L->layers, L0.layers);
        fz_pd("links", i, "area", L->area, L0.area); fz_pd("links", i, "inertia", L->inertia, L0.inertia);
        fz_pd("links", i, "tip_mass", L->tip_mass, L0.tip_mass); fz_pd("links", i, "tip_inertia", L->tip_inertia, L0.tip_inertia);
        fz_pi("links", i, "root", L->root, L0.root); fz_pd("links", i, "x", L->x, L0.x); fz_pd("links", i, "y", L->y, L0.y);
        fz_pd("links", i, "angle", L->angle, L0.angle); fz_pd("links", i, "vx", L->vx, L0.vx); fz_pd("links", i, "vy", L->vy, L0.vy);
        fz_pd("links", i, "omega", L->omega, L0.omega); fz_pi("links", i, "fidelity", L->fidelity, L0.fidelity); fz_pi("links", i, "cookie", (long)L->cookie, (long)L0.cookie);
    }
    for (i = 0; i < sc.joint_count; i++) {
        const rj_joint_def *J = &sc.joints[i];
        J0.body2 = i < sc.link_count ? i : i % sc.link_count;   /* fz_joint's chain */
        J0.body1 = i < sc.link_count ? i - 1 : -1;
        fz_pi("joints", i, "body1", J->body1, J0.body1); fz_pi("joints", i, "node1", J->node1, J0.node1); fz_pi("joints", i, "body2", J->body2, J0.body2);
        fz_pd("joints", i, "ground_x", J->ground_x, J0.ground_x); fz_pd("joints", i, "ground_y", J->ground_y, J0.ground_y);
        fz_pd("joints", i, "ground_angle", J->ground_angle, J0.ground_angle); fz_pd("joints", i, "angle0", J->angle0, J0.angle0);
        fz_pd("joints", i, "rate0", J->rate0, J0.rate0); fz_pi("joints", i, "table_count", J->table_count, J0.table_count);
        for (k = 0; k < RJ_TABLE_MAX; k++) {
            if (J->table_angle[k] != 0 || J->table_torque[k] != 0) printf("joints[%d].table[%d] = %.17g %.17g\n", i, k, J->table_angle[k], J->table_torque[k]);
        }
        fz_pd("joints", i, "spring_k", J->spring_k, J0.spring_k); fz_pd("joints", i, "spring_free_angle", J->spring_free_angle, J0.spring_free_angle);
        fz_pi("joints", i, "has_forward", J->has_forward, J0.has_forward); fz_pd("joints", i, "forward", J->forward, J0.forward);
        fz_pi("joints", i, "has_reverse", J->has_reverse, J0.has_reverse); fz_pd("joints", i, "reverse", J->reverse, J0.reverse);
        fz_pi("joints", i, "lock", J->lock, J0.lock); fz_pi("joints", i, "method", J->method, J0.method); fz_pi("joints", i, "release", J->release, J0.release);
        fz_pd("joints", i, "penalty_k", J->penalty_k, J0.penalty_k); fz_pd("joints", i, "restitution", J->restitution, J0.restitution);
        fz_pd("joints", i, "damping", J->damping, J0.damping); fz_pd("joints", i, "friction", J->friction, J0.friction);
        fz_pi("joints", i, "reference", J->reference, J0.reference); fz_pi("joints", i, "cookie", (long)J->cookie, (long)J0.cookie);
    }
    for (i = 0; sc.loads && i < sc.load_count; i++) {
        const rj_load_def *D = &sc.loads[i];
        D0.link = i % inputs.nl0; D0.force[1] = -1.0;   /* fz_load's starting point */
        fz_pi("loads", i, "link", D->link, D0.link); fz_pi("loads", i, "node", D->node, D0.node);
        fz_pd("loads", i, "force[0]", D->force[0], D0.force[0]); fz_pd("loads", i, "force[1]", D->force[1], D0.force[1]);
        fz_pd("loads", i, "moment", D->moment, D0.moment); fz_pi("loads", i, "follower", D->follower, D0.follower);
        fz_pi("loads", i, "table_count", D->table_count, D0.table_count);
        for (k = 0; k < RJ_TABLE_MAX; k++) {
            if (D->table_time[k] != 0 || D->table_factor[k] != 0 || k < D->table_count)
                printf("loads[%d].table[%d] = %.17g %.17g\n", i, k, D->table_time[k], D->table_factor[k]);
        }
        fz_pi("loads", i, "cookie", (long)D->cookie, (long)D0.cookie);
    }
    if (inputs.torques_on) {
        printf("joint torques on\n");
        for (k = 0; k < inputs.nt; k++) printf("joint torque [%u mod %d] = %.17g\n", inputs.t_at[k], sc.joint_count, inputs.t_val[k]);
    }
    if (inputs.forces_on) {
        printf("node forces on\n");
        long nn = 0;
        for (k = 0; k < sc.link_count; k++) nn += sc.links[k].elements + 1L;
        for (k = 0; k < inputs.nf; k++) printf("node force [%u mod %ld] = %.17g\n", inputs.f_at[k], 3 * nn, inputs.f_val[k]);
    }
    free((void *)sc.links);
    free((void *)sc.joints);
    free((void *)sc.loads);
    fflush(stdout);
    return LLVMFuzzerTestOneInput(buf, n);
}
#endif
