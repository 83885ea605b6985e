/* fuzz_state.c - libFuzzer target for checkpoint loading (rj_state_load).
   Build and run from the repository root (one process: the machine's cores are shared):
     clang -g -O1 -fsanitize=fuzzer,address,undefined tests/fuzz_state.c -I. -o /tmp/fuzz_state -lm
     mkdir -p /tmp/fuzz_work_state && /tmp/fuzz_state -jobs=1 -max_total_time=600 -max_len=4096 /tmp/fuzz_work_state tests/fuzz_corpus_state
   The same file with -DFUZZ_STATE_CORPUS (no -fsanitize=fuzzer) is a program that writes the
   seed corpus into the directory it is given: one valid checkpoint of each model, raw and
   with a few checksummed edits (the last switches both input blocks on and sets a value).
   Six fixed small models are built once, stepped, and checkpointed with rj_state_save
   (version 5): a flexible two-link chain with limits and locks; a mixed rigid and flexible
   scene stepping with the caller's node forces on; an all-rigid chain with a model load,
   the caller's joint torques and node forces on; an inextensible link with a joint torque
   on; a flexible link stepping in place; and a flexible link carrying a rigid one under
   gravity, three model loads (a tip force scaled by a time table, a follower force and
   moment, a constant moment), joint torques and node forces on. So the checkpoints hold
   both input blocks switched off, and on with nonzero torques, forces and "last applied"
   forces. Input: byte 0 picks the model, byte 1 the mode, the rest is
     mode 0: the checkpoint itself (raw bytes, exact-size copy so over-reads are caught);
     mode 1: the payload of the model's valid checkpoint, header and checksum kept valid;
     mode 2: edits to the valid checkpoint (steps, a double or int of the frame, a value or
             a switch of the input blocks, any byte, the size), then the checksum recomputed
             (FNV-1a, as rj_state_save does), so the input reaches the validation behind the
             checksum;
     mode 3: the same edits, checksum not recomputed.
   A successful load must give a state whose every public query is finite and within its
   documented range, that saves back to the same bytes (the whole checkpoint: frame and
   both input blocks), and that steps: each rj_step returns an error with a message and the
   state unchanged (its saved bytes, inputs included), or RJ_OK with one more step, a time
   not earlier, and a state that passes the same checks. A failed load must name the error
   and leave the state as it was (its saved bytes, error and warning text). Every violation
   prints "fuzz_state: <what>" and aborts.
   With -DRJ_FUZZ_STEP_ONLY the loaded state's own values are not checked (the load lets
   any finite number and any flag through, which stops a run at once): only what the steps
   do with them (sanitizers, finite nodes after RJ_OK, a failed step changing nothing).
   With -DFUZZ_STATE_PRINT (no -fsanitize=fuzzer) the file is a program that prints how an
   input's checkpoint differs from the valid one, value by value, then runs the checks,
   saying whether the load and each step succeeded:
     clang -g -O1 -fsanitize=address,undefined -DFUZZ_STATE_PRINT tests/fuzz_state.c -I. -o /tmp/fuzz_state_print -lm */
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
#include "../examples/scenes.h"

#define FZ_MODELS 6
#define FZ_HEAD 24          /* "RJCK", version, model hash, payload length (rj_state_save) */
#define FZ_SCALARS 13       /* the frame's scalars (fz_slot_name) */
#define FZ_JD 16            /* doubles per joint in the frame (fz_slot_name) */
#define FZ_STEPS 5

typedef struct fz_model {
    const char *name;
    rj_model *m;
    rj_state *base;         /* the checkpointed state */
    rj_state *s, *keep;     /* loaded into / copy for the step checks */
    unsigned char *ck;      /* its checkpoint */
    size_t n;               /* checkpoint bytes */
    size_t nd, ni;          /* frame doubles and ints in the payload */
    size_t in_at, nin;      /* the input blocks: their offset, their doubles (switch + nj
                               torques, switch + 3 nn forces + 3 nn last applied) */
} fz_model;

static fz_model fz_m[FZ_MODELS];
static int fz_ready;
static const char *fz_what = "";   /* the current input's model and mode, for the messages */
static int fz_verbose;             /* the printer: say what the load and the steps did */

static void fz_fail(const char *fmt, ...)
{
    va_list ap;
    fprintf(stderr, "fuzz_state: [%s] ", fz_what);
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fprintf(stderr, "\n");
    abort();
}

static int fz_finite(double x) { return x == x && x - x == 0.0; }

/* FNV-1a 64 over the header and payload, the checkpoint's checksum (rj_state_save) */
static void fz_checksum(unsigned char *b, size_t n)
{
    unsigned long long h = 14695981039346656037ULL;
    size_t i;
    if (n < FZ_HEAD + 8) return;
    for (i = 0; i < n - 8; i++) { h ^= b[i]; h *= 1099511628211ULL; }
    memcpy(b + n - 8, &h, 8);
}

/* ---------------------------------------------------------------- the models */
static rj_scene_def fz_scene(rj_link_def *L, int nl, rj_joint_def *J, int nj)
{
    rj_scene_def sc = rj_default_scene_def();
    sc.links = L; sc.link_count = nl; sc.joints = J; sc.joint_count = nj;
    return sc;
}

/* the caller's inputs a model's state steps with (before its first step): joint torques
   and node forces, nonzero where set */
typedef struct fz_inputs {
    int torques, forces;    /* switch on */
    int nt, nf;
    int t_at[3], f_at[4];   /* joint; node-force entry (3 per node: fx, fy, moment) */
    double t_val[3], f_val[4];
} fz_inputs;

/* the paper's deployment at 3 elements per link: springs drive both joints into their locks */
static rj_scene_def fz_chain(rj_link_def L[2], rj_joint_def J[2])
{
    deploy_opts o = deploy_default_opts();
    rj_scene_def sc;
    o.elements = 3; o.dt = 0.0;
    deploy_scene(&o, L, J, &sc);
    J[1].penalty_k = 1000.0;
    return sc;
}

/* rigid link 0 swinging from ground, flexible link 1 pinned to its tip */
static rj_scene_def fz_mixed(rj_link_def L[2], rj_joint_def J[2])
{
    L[0] = rj_default_link_def(); L[0].fidelity = RJ_LINK_RIGID; L[0].elements = 2; L[0].length = 0.5;
    L[1] = rj_default_link_def(); L[1].elements = 4; L[1].height = 0.02; L[1].tip_mass = 0.5;
    J[0] = rj_default_joint_def(); J[0].body1 = -1; J[0].body2 = 0; J[0].angle0 = 0.0; J[0].rate0 = 4.0;
    J[0].has_forward = 1; J[0].forward = 0.3; J[0].method = RJ_METHOD_MOMENTUM; J[0].restitution = 0.5;
    J[1] = rj_default_joint_def(); J[1].body1 = 0; J[1].body2 = 1; J[1].spring_k = 50.0; J[1].damping = 0.01;
    J[1].has_reverse = 1; J[1].reverse = 2.8; J[1].method = RJ_METHOD_FORCED; J[1].friction = 0.1;
    return fz_scene(L, 2, J, 2);
}

/* three rigid links from ground: a limit that locks, a spring with a table, a penalty limit;
   a constant force on the last link's tip */
static rj_scene_def fz_rigid(rj_link_def L[3], rj_joint_def J[3], rj_load_def D[1])
{
    rj_scene_def sc;
    int i;
    for (i = 0; i < 3; i++) { L[i] = rj_default_link_def(); L[i].fidelity = RJ_LINK_RIGID; L[i].elements = 2; L[i].length = 0.4; }
    for (i = 0; i < 3; i++) { J[i] = rj_default_joint_def(); J[i].body1 = i - 1; J[i].body2 = i; }
    J[0].angle0 = 0.0; J[0].rate0 = 3.0; J[0].has_forward = 1; J[0].forward = 1.0; J[0].lock = 1; J[0].method = RJ_METHOD_FORCED;
    J[1].spring_k = 20.0; J[1].damping = 0.05; J[1].friction = 0.05; J[1].rate0 = -2.0;
    J[1].table_count = 3; J[1].table_angle[0] = 0.0; J[1].table_angle[1] = 3.0; J[1].table_angle[2] = 6.0;
    J[1].table_torque[0] = 0.1; J[1].table_torque[1] = 0.3; J[1].table_torque[2] = 0.0;
    J[2].has_reverse = 1; J[2].reverse = 2.9; J[2].method = RJ_METHOD_PENALTY; J[2].penalty_k = 500.0; J[2].rate0 = -5.0;
    D[0] = rj_default_load_def(); D[0].link = 2; D[0].force[0] = 0.3; D[0].force[1] = -0.8;
    sc = fz_scene(L, 3, J, 3);
    sc.loads = D; sc.load_count = 1;
    return sc;
}

/* an inextensible link turning from ground into a penalty limit, with a table torque */
static rj_scene_def fz_inext(rj_link_def L[1], rj_joint_def J[1])
{
    L[0] = rj_default_link_def(); L[0].fidelity = RJ_LINK_INEXTENSIBLE; L[0].elements = 5; L[0].height = 0.02;
    J[0] = rj_default_joint_def(); J[0].angle0 = 0.0; J[0].rate0 = 5.0;
    J[0].has_forward = 1; J[0].forward = 0.05; J[0].method = RJ_METHOD_PENALTY; J[0].penalty_k = 2e4;
    J[0].table_count = 2; J[0].table_angle[0] = 0.0; J[0].table_angle[1] = 1.0; J[0].table_torque[0] = 0.5; J[0].table_torque[1] = 0.5;
    return fz_scene(L, 1, J, 1);
}

/* a flexible link stepping in place, energies every 4 steps, on a damped ground spring */
static rj_scene_def fz_inplace(rj_link_def L[1], rj_joint_def J[1])
{
    rj_scene_def sc;
    L[0] = rj_default_link_def(); L[0].elements = 6; L[0].height = 0.02; L[0].omega = 1.0;
    J[0] = rj_default_joint_def(); J[0].angle0 = 0.5; J[0].rate0 = 2.0; J[0].spring_k = 100.0; J[0].spring_free_angle = 0.0; J[0].damping = 0.1;
    J[0].has_reverse = 1; J[0].reverse = 0.2; J[0].method = RJ_METHOD_ENERGY;
    sc = fz_scene(L, 1, J, 1);
    sc.solver.in_place = RJ_IN_PLACE_ON; sc.solver.energy_every = 4;
    return sc;
}

/* a flexible link on a damped ground spring carrying a rigid link at its tip, under gravity
   and loads: a force on the rigid tip rising and falling by a table, a follower force and
   moment on the flexible link's middle, a constant moment at its root */
static rj_scene_def fz_loaded(rj_link_def L[2], rj_joint_def J[2], rj_load_def D[3])
{
    rj_scene_def sc;
    L[0] = rj_default_link_def(); L[0].elements = 4; L[0].length = 0.6; L[0].height = 0.02;
    L[1] = rj_default_link_def(); L[1].fidelity = RJ_LINK_RIGID; L[1].elements = 2; L[1].length = 0.3; L[1].height = 0.02;
    J[0] = rj_default_joint_def(); J[0].spring_k = 200.0; J[0].damping = 0.05;
    J[1] = rj_default_joint_def(); J[1].body1 = 0; J[1].body2 = 1; J[1].spring_k = 5.0; J[1].friction = 0.01;
    J[1].has_reverse = 1; J[1].reverse = 2.5;
    D[0] = rj_default_load_def(); D[0].link = 1; D[0].force[0] = 2.0; D[0].force[1] = -5.0;
    D[0].table_count = 3; D[0].table_time[0] = 0.0; D[0].table_time[1] = 0.02; D[0].table_time[2] = 0.1;
    D[0].table_factor[0] = 0.0; D[0].table_factor[1] = 1.0; D[0].table_factor[2] = 0.5;
    D[1] = rj_default_load_def(); D[1].link = 0; D[1].node = 2; D[1].follower = 1; D[1].force[0] = 0.5; D[1].force[1] = 3.0; D[1].moment = 0.2;
    D[2] = rj_default_load_def(); D[2].link = 0; D[2].node = 0; D[2].force[1] = 0.0; D[2].moment = -0.5;
    sc = fz_scene(L, 2, J, 2);
    sc.loads = D; sc.load_count = 3;
    sc.solver.gravity[1] = -9.81;
    return sc;
}

static void fz_build(int k)
{
    rj_link_def L[3];
    rj_joint_def J[3];
    rj_load_def D[3];
    rj_scene_def sc;
    rj_error err;
    fz_model *f = &fz_m[k];
    fz_inputs in;
    long i, steps = 2000;
    memset(&in, 0, sizeof in);
    switch (k) {
    case 0: sc = fz_chain(L, J); f->name = "chain"; steps = 400000; break;
    case 1:
        sc = fz_mixed(L, J); f->name = "mixed";
        in.forces = 1; in.nf = 3;                                      /* the rigid link's tip, the flexible tip */
        in.f_at[0] = 3 * 2 + 1; in.f_val[0] = -0.5;
        in.f_at[1] = 3 * 7 + 0; in.f_val[1] = 0.2; in.f_at[2] = 3 * 7 + 2; in.f_val[2] = 0.01;
        break;
    case 2:
        sc = fz_rigid(L, J, D); f->name = "rigid";
        in.torques = 1; in.nt = 2; in.t_at[0] = 0; in.t_val[0] = 0.1; in.t_at[1] = 2; in.t_val[1] = -0.05;
        in.forces = 1; in.nf = 2; in.f_at[0] = 3 * 5 + 1; in.f_val[0] = -0.3; in.f_at[1] = 3 * 8 + 2; in.f_val[1] = 0.02;
        break;
    case 3:
        sc = fz_inext(L, J); f->name = "inextensible";
        in.torques = 1; in.nt = 1; in.t_at[0] = 0; in.t_val[0] = 0.2;
        break;
    case 4: sc = fz_inplace(L, J); f->name = "in-place"; break;
    default:
        sc = fz_loaded(L, J, D); f->name = "loaded";
        in.torques = 1; in.nt = 2; in.t_at[0] = 0; in.t_val[0] = 0.3; in.t_at[1] = 1; in.t_val[1] = -0.1;
        in.forces = 1; in.nf = 4;                                      /* flexible tip, rigid tip */
        in.f_at[0] = 3 * 4 + 0; in.f_val[0] = 0.4; in.f_at[1] = 3 * 4 + 2; in.f_val[1] = 0.05;
        in.f_at[2] = 3 * 7 + 1; in.f_val[2] = -1.0; in.f_at[3] = 3 * 1 + 1; in.f_val[3] = 0.7;
        break;
    }
    if (rj_model_create(&sc, &f->m, &err, NULL) != RJ_OK) { fprintf(stderr, "fuzz_state: model %s: %s\n", f->name, err.msg); abort(); }
    if (rj_state_create(f->m, &f->base, NULL) != RJ_OK || rj_state_create(f->m, &f->s, NULL) != RJ_OK
        || rj_state_create(f->m, &f->keep, NULL) != RJ_OK) { fprintf(stderr, "fuzz_state: states of %s\n", f->name); abort(); }
    if (in.torques) {
        double *tq = rj_state_joint_torques(f->m, f->base);
        for (i = 0; i < in.nt; i++) tq[in.t_at[i]] = in.t_val[i];
    }
    if (in.forces) {
        double *fn = rj_state_node_forces(f->m, f->base);
        for (i = 0; i < in.nf; i++) {
            if (in.f_at[i] >= 3 * rj_model_node_count(f->m)) { fprintf(stderr, "fuzz_state: model %s: node force %d\n", f->name, in.f_at[i]); abort(); }
            fn[in.f_at[i]] = in.f_val[i];
        }
    }
    /* step into the interesting part: the chain until its first joint has locked (then a
       little more), the others a fixed number of steps; stop at an error */
    for (i = 0; i < steps; i++) {
        if (rj_step(f->m, f->base) != RJ_OK) break;
        if (k == 0 && rj_joint_flag(f->m, f->base, 0) == RJ_LOCKED && i + 200 < steps) steps = i + 200;
    }
    f->n = rj_state_save(f->m, f->base, NULL, 0);
    f->ck = (unsigned char *)malloc(f->n);
    if (!f->ck || rj_state_save(f->m, f->base, f->ck, f->n) != f->n) abort();
    f->ni = (size_t)rj_model_joint_count(f->m) + 1;
    f->nin = (size_t)rj_model_joint_count(f->m) + 1 + 6 * (size_t)rj_model_node_count(f->m) + 1;
    f->nd = (f->n - FZ_HEAD - 8 - 8 - sizeof(int) * f->ni - sizeof(double) * f->nin) / sizeof(double);
    f->in_at = FZ_HEAD + 8 + sizeof(double) * f->nd + sizeof(int) * f->ni;
    if (f->in_at + sizeof(double) * f->nin + 8 != f->n) { fprintf(stderr, "fuzz_state: model %s: checkpoint layout\n", f->name); abort(); }
}

static void fz_init(void)
{
    int k;
    if (fz_ready) return;
    for (k = 0; k < FZ_MODELS; k++) fz_build(k);
    fz_ready = 1;
}

/* ---------------------------------------------------------------- the checks */
#ifndef RJ_FUZZ_STEP_ONLY
/* every public query of a state: finite, and within its documented range */
static void fz_check_state(const rj_model *m, const rj_state *s, const char *when)
{
    int l, i, j, c;
    double t = rj_state_time(s), xy[2], v[2];
    rj_energy e;
    if (rj_state_steps(s) < 0) fz_fail("%s: step count %ld < 0", when, rj_state_steps(s));
    if (!fz_finite(t) || t < 0) fz_fail("%s: time %g", when, t);
    /* energies are taken at a time already reached (time - dt at most); a later one would
       postpone the next accounts, and with them the blow-up checks (solver.energy_every) */
    if (!fz_finite(rj_state_energy_time(s)) || rj_state_energy_time(s) > t) fz_fail("%s: energy time %g, time %g", when, rj_state_energy_time(s), t);
    if (rj_state_warning_count(s) < 0) fz_fail("%s: warning count %ld < 0", when, rj_state_warning_count(s));
    if (memchr(rj_state_error(s), 0, 640) == NULL || memchr(rj_state_warning(s), 0, 200) == NULL) fz_fail("%s: error or warning text not terminated", when);
    rj_state_energy(m, s, &e);
    if (!fz_finite(e.kinetic) || !fz_finite(e.strain) || !fz_finite(e.spring) || !fz_finite(e.gravity) || !fz_finite(e.work_applied)
        || !fz_finite(e.lost_damping) || !fz_finite(e.lost_friction) || !fz_finite(e.lost_limit) || !fz_finite(e.total) || !fz_finite(e.balance))
        fz_fail("%s: energy not finite: kinetic %g strain %g spring %g gravity %g work %g lost %g %g %g total %g balance %g", when,
                e.kinetic, e.strain, e.spring, e.gravity, e.work_applied, e.lost_damping, e.lost_friction, e.lost_limit, e.total, e.balance);
    for (l = 0; l < rj_model_link_count(m); l++) for (i = 0; i < rj_link_node_count(m, l); i++) {
        double r, w;
        rj_node_position(m, s, l, i, xy);
        rj_node_velocity(m, s, l, i, v);
        r = rj_node_rotation(m, s, l, i);
        w = rj_node_rate(m, s, l, i);
        if (!fz_finite(xy[0]) || !fz_finite(xy[1])) fz_fail("%s: link %d node %d position (%g, %g)", when, l, i, xy[0], xy[1]);
        if (!fz_finite(v[0]) || !fz_finite(v[1])) fz_fail("%s: link %d node %d velocity (%g, %g)", when, l, i, v[0], v[1]);
        if (!fz_finite(r) || !fz_finite(w)) fz_fail("%s: link %d node %d rotation %g rate %g", when, l, i, r, w);
    }
    for (j = 0; j < rj_model_joint_count(m); j++) {
        const rj_joint_def *d = rj_model_joint_def(m, j);
        int flag = rj_joint_flag(m, s, j);
        double th = rj_joint_theta(m, s, j), ev, rel, pp;
        if (flag < RJ_FREE || flag > RJ_LOCKED) fz_fail("%s: joint %d flag %d outside 0..3", when, j, flag);
        if ((flag == RJ_AT_FORWARD && !d->has_forward) || (flag == RJ_AT_REVERSE && !d->has_reverse)
            || (flag == RJ_LOCKED && !(d->lock && (d->has_forward || d->has_reverse))))
            fz_fail("%s: joint %d flag %d but has_forward %d has_reverse %d lock %d", when, j, flag, d->has_forward, d->has_reverse, d->lock);
        rj_joint_position(m, s, j, xy);
        if (!fz_finite(xy[0]) || !fz_finite(xy[1])) fz_fail("%s: joint %d position (%g, %g)", when, j, xy[0], xy[1]);
        if (!(th >= 0 && th < 2 * 3.14159265358979323846)) fz_fail("%s: joint %d theta %g outside [0, 2 pi)", when, j, th);
        if (!fz_finite(rj_joint_theta_running(m, s, j)) || !fz_finite(rj_joint_rate(m, s, j)))
            fz_fail("%s: joint %d running angle %g rate %g", when, j, rj_joint_theta_running(m, s, j), rj_joint_rate(m, s, j));
        for (c = 0; c < RJ_TORQUE_COUNT; c++)
            if (!fz_finite(rj_joint_torque(m, s, j, c))) fz_fail("%s: joint %d torque %d = %g", when, j, c, rj_joint_torque(m, s, j, c));
        if (!fz_finite(rj_joint_penetration(m, s, j)) || !fz_finite(rj_joint_contact_penetration(m, s, j)))
            fz_fail("%s: joint %d penetration %g contact penetration %g", when, j, rj_joint_penetration(m, s, j), rj_joint_contact_penetration(m, s, j));
        pp = rj_joint_peak_penetration(m, s, j);
        if (!fz_finite(pp) || pp < 0) fz_fail("%s: joint %d peak penetration %g", when, j, pp);
        ev = rj_joint_event_time(m, s, j); rel = rj_joint_release_time(m, s, j);
        if (!(ev == -1 || (fz_finite(ev) && ev >= 0)) || !(rel == -1 || (fz_finite(rel) && rel >= 0)))
            fz_fail("%s: joint %d event time %g release time %g (-1 or a time)", when, j, ev, rel);
    }
}
#endif

/* the state's saved bytes (steps and frame), to compare a state before and after a call */
static unsigned char *fz_save(const fz_model *f, const rj_state *s)
{
    unsigned char *b = (unsigned char *)malloc(f->n);
    if (!b || rj_state_save(f->m, s, b, f->n) != f->n) abort();
    return b;
}

/* ---------------------------------------------------------------- input decoding */
typedef struct fz_in { const uint8_t *p; size_t n, at; } fz_in;
static unsigned fz_u8(fz_in *in) { return in->at < in->n ? in->p[in->at++] : 0u; }
static unsigned fz_u16(fz_in *in) { unsigned a = fz_u8(in); return a | fz_u8(in) << 8; }

static double fz_special(unsigned k)
{
    static const double v[] = {
        0.0, -0.0, 1.0, -1.0, 0.5, 3.0, 7.0, 64.0, 3.14159265358979323846, 6.28318530717958647692, 1e6, -1e6, 1e20,
        9.3e18, -9.3e18, 9223372036854775808.0, 4.9e-324, 2.2250738585072014e-308, 1e-300, 1e300, -1e300, 1e308, -1e308, DBL_MAX, -DBL_MAX,
        HUGE_VAL, -HUGE_VAL, 0.0 /* NaN, below */
    };
    const unsigned n = sizeof v / sizeof v[0];
    k %= n;
    if (k == n - 1) return nan("");
    return v[k];
}
static long long fz_special_steps(unsigned k)
{
    static const long long v[] = { 0, 1, 2, -1, -2, 63, 64, 65, 1000, 1LL << 40, 1LL << 62, LLONG_MAX, LLONG_MAX - 1, LLONG_MIN, LLONG_MIN + 1 };
    return v[k % (sizeof v / sizeof v[0])];
}
static int fz_special_int(unsigned k)
{
    static const int v[] = { 0, 1, 2, 3, 4, 7, -1, -2, 255, 256, 65536, INT_MAX, INT_MIN };
    return v[k % (sizeof v / sizeof v[0])];
}
/* an input block's switch: 0 or 1 (the only ones rj_state_save writes), and near misses */
static double fz_special_switch(unsigned k)
{
    static const double v[] = { 1.0, 0.0, -0.0, 2.0, 0.5, -1.0, 1.0000000000000002, 4.9e-324, HUGE_VAL, 0.0 /* NaN, below */ };
    const unsigned n = sizeof v / sizeof v[0];
    k %= n;
    if (k == n - 1) return nan("");
    return v[k];
}

/* edits to a copy of the valid checkpoint; returns the buffer and its size in *size */
static unsigned char *fz_edit(const fz_model *f, fz_in *in, size_t *size)
{
    size_t n = f->n, cap = f->n + 256;
    unsigned char *b = (unsigned char *)calloc(cap, 1);
    int ops = 0;
    if (!b) abort();
    memcpy(b, f->ck, f->n);
    while (in->at < in->n && ops++ < 64) {
        unsigned op = fz_u8(in) % 9;
        size_t at;
        if (op == 0) {                                  /* the step counter */
            long long st = fz_special_steps(fz_u8(in));
            memcpy(b + FZ_HEAD, &st, 8);
        } else if (op == 1 || op == 2) {                /* a frame double: special or raw bytes */
            double v = 0;
            at = FZ_HEAD + 8 + sizeof(double) * (fz_u16(in) % f->nd);
            if (op == 1) v = fz_special(fz_u8(in));
            else { unsigned char r[8]; int i; for (i = 0; i < 8; i++) r[i] = (unsigned char)fz_u8(in); memcpy(&v, r, 8); }
            memcpy(b + at, &v, 8);
        } else if (op == 3) {                           /* a frame int (the joint flags) */
            int v;
            at = FZ_HEAD + 8 + sizeof(double) * f->nd + sizeof(int) * (fz_u8(in) % f->ni);
            v = fz_special_int(fz_u8(in));
            memcpy(b + at, &v, sizeof v);
        } else if (op == 7) {                           /* a value of the input blocks (switches included) */
            double v;
            at = f->in_at + sizeof(double) * (fz_u16(in) % f->nin);
            v = fz_special(fz_u8(in));
            memcpy(b + at, &v, 8);
        } else if (op == 8) {                           /* an input block's switch */
            const size_t nj = f->ni - 1;
            double v;
            at = f->in_at + (fz_u8(in) & 1 ? sizeof(double) * (nj + 1) : 0);
            v = fz_special_switch(fz_u8(in));
            memcpy(b + at, &v, 8);
        } else if (op == 4 || op == 5) {                /* any byte, header included */
            at = fz_u16(in) % n;
            if (op == 4) b[at] = (unsigned char)fz_u8(in); else b[at] ^= (unsigned char)(1u << (fz_u8(in) % 8));
        } else {                                        /* the size: shorter, or longer with zeros */
            int d = (int)(fz_u8(in) % 33) - 16;
            n = (size_t)((long)f->n + d);
        }
    }
    *size = n;
    return b;
}

/* ---------------------------------------------------------------- the target */
/* The checkpoint an input stands for (malloc'd, *n bytes), its model and mode. */
static unsigned char *fz_make(const uint8_t *data, size_t size, fz_model **fm, unsigned *mode, size_t *n)
{
    fz_in in;
    fz_model *f = &fz_m[data[0] % FZ_MODELS];
    unsigned char *buf;
    *fm = f;
    *mode = data[1] % 4;
    in.p = data + 2; in.n = size - 2; in.at = 0;
    if (*mode == 0) {
        *n = in.n;
        buf = (unsigned char *)malloc(in.n ? in.n : 1);
        if (!buf) abort();
        if (in.n) memcpy(buf, in.p, in.n);
    } else if (*mode == 1) {
        *n = f->n;
        buf = (unsigned char *)malloc(f->n);
        if (!buf) abort();
        memcpy(buf, f->ck, f->n);
        memcpy(buf + FZ_HEAD, in.p, in.n < f->n - FZ_HEAD - 8 ? in.n : f->n - FZ_HEAD - 8);
        fz_checksum(buf, f->n);
    } else {
        buf = fz_edit(f, &in, n);
        if (*mode == 2) fz_checksum(buf, *n);
    }
    return buf;
}

/* finite nodes: what rj_step promises of every state it returns RJ_OK for */
static void fz_check_nodes(const rj_model *m, const rj_state *s, const char *when)
{
    int l, i;
    for (l = 0; l < rj_model_link_count(m); l++) for (i = 0; i < rj_link_node_count(m, l); i++) {
        double xy[2], v[2], r;
        rj_node_position(m, s, l, i, xy);
        rj_node_velocity(m, s, l, i, v);
        r = rj_node_rotation(m, s, l, i);
        if (!fz_finite(xy[0]) || !fz_finite(xy[1]) || !fz_finite(v[0]) || !fz_finite(v[1]) || !fz_finite(r))
            fz_fail("%s: link %d node %d position (%g, %g) velocity (%g, %g) rotation %g", when, l, i, xy[0], xy[1], v[0], v[1], r);
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static char what[64];
    fz_model *f;
    unsigned mode;
    unsigned char *buf, *pre, *post;
    size_t n;
    char err_before[320], warn_before[200];
    rj_error err;
    rj_result r;
    int k;
    fz_init();
    if (size < 2) return 0;
    buf = fz_make(data, size, &f, &mode, &n);
    snprintf(what, sizeof what, "model %s, mode %u", f->name, mode);
    fz_what = what;
    /* the state before: a valid one, saved and with its texts */
    if (rj_state_copy(f->m, f->s, f->base) != RJ_OK) abort();
    pre = fz_save(f, f->s);
    memcpy(err_before, rj_state_error(f->s), sizeof err_before);
    memcpy(warn_before, rj_state_warning(f->s), sizeof warn_before);
    memset(&err, 0, sizeof err);
    r = rj_state_load(f->m, f->s, buf, n, &err);
    if (fz_verbose) printf("load: %s\n", r == RJ_OK ? "ok" : err.msg);
    if (r != RJ_OK) {
        if (r != RJ_ERR_CHECKPOINT) fz_fail("load returned %d, not RJ_ERR_CHECKPOINT", (int)r);
        if (err.code != r || err.msg[0] == 0 || err.field[0] == 0 || memchr(err.msg, 0, sizeof err.msg) == NULL)
            fz_fail("failed load: error code %d field \"%s\" message \"%s\"", (int)err.code, err.field, err.msg);
        post = fz_save(f, f->s);
        if (memcmp(pre, post, f->n) != 0) fz_fail("failed load (%s) changed the state", err.msg);
        if (memcmp(err_before, rj_state_error(f->s), sizeof err_before) != 0 || memcmp(warn_before, rj_state_warning(f->s), sizeof warn_before) != 0)
            fz_fail("failed load (%s) changed the state's error or warning text", err.msg);
        free(post);
    } else {
#ifndef RJ_FUZZ_STEP_ONLY
        fz_check_state(f->m, f->s, "after load");
#endif
        if (rj_state_error(f->s)[0] != 0) fz_fail("after load: error text \"%s\"", rj_state_error(f->s));
        post = fz_save(f, f->s);
        if (n < f->n || memcmp(post, buf, f->n) != 0) fz_fail("a loaded checkpoint does not save back to the same bytes");
        free(post);
        for (k = 0; k < FZ_STEPS; k++) {
            long before = rj_state_steps(f->s);
            double t = rj_state_time(f->s);
            unsigned char *b0 = fz_save(f, f->s);
            r = rj_step(f->m, f->s);
            if (fz_verbose) printf("step %d: %s\n", k, r == RJ_OK ? "ok" : rj_state_error(f->s));
            if (r != RJ_OK) {
                unsigned char *b1 = fz_save(f, f->s);
                if (rj_state_error(f->s)[0] == 0) fz_fail("step %d returned %d without an error message", k, (int)r);
                if (memcmp(b0, b1, f->n) != 0) fz_fail("failed step %d (%s) changed the state", k, rj_state_error(f->s));
                free(b0); free(b1);
                break;
            }
            free(b0);
            /* every RJ_OK step leaves finite nodes (rj_step checks what it writes) */
            fz_check_nodes(f->m, f->s, "after a step");
#ifndef RJ_FUZZ_STEP_ONLY
            fz_check_state(f->m, f->s, "after a step");
#endif
#ifndef RJ_FUZZ_STEP_ONLY
            if ((unsigned long)rj_state_steps(f->s) != (unsigned long)before + 1u) fz_fail("step count %ld after %ld", rj_state_steps(f->s), before);
            if (!(rj_state_time(f->s) >= t)) fz_fail("time %.17g after %.17g", rj_state_time(f->s), t);
#else
            (void)before; (void)t;
#endif
        }
    }
    free(pre);
    free(buf);
    return 0;
}

#ifdef FUZZ_STATE_PRINT
/* the name of payload value k of model f: the frame layout of revjoint.h's rj_state
   (scalars, node arrays, element arrays, per-joint records, rigid bodies), as it is today */
static void fz_slot_name(const fz_model *f, size_t k, char *out, size_t size)
{
    static const char *sc[FZ_SCALARS] = { "time", "energy time", "kinetic", "strain", "spring", "lost damping", "lost friction", "lost limit",
                                          "initial energy", "warnings", "pending limit loss", "gravity potential", "work applied" };
    static const char *na[] = { "x", "y", "phi", "vx", "vy", "w" }, *ea[] = { "beta", "chord x", "chord y" };
    static const char *jd[FZ_JD] = { "theta", "rate", "lock angle", "event time", "release time", "peak penetration", "contact penetration", "qdd",
                                     "impulse", "input torque applied", "torque table", "torque spring", "torque damping", "torque friction",
                                     "torque limit", "torque total" };
    const size_t nn = (size_t)rj_model_node_count(f->m), nl = (size_t)rj_model_link_count(f->m), ne = nn - nl, nj = f->ni - 1;
    if (k < FZ_SCALARS) { snprintf(out, size, "%s", sc[k]); return; }
    k -= FZ_SCALARS;
    if (k < 6 * nn) { snprintf(out, size, "node %lu %s", (unsigned long)(k % nn), na[k / nn]); return; }
    k -= 6 * nn;
    if (k < 3 * ne) { snprintf(out, size, "element %lu %s", (unsigned long)(k % ne), ea[k / ne]); return; }
    k -= 3 * ne;
    if (k < FZ_JD * nj) { snprintf(out, size, "joint %lu %s", (unsigned long)(k / FZ_JD), jd[k % FZ_JD]); return; }
    k -= FZ_JD * nj;
    snprintf(out, size, "rigid body %lu value %lu", (unsigned long)(k / 6), (unsigned long)(k % 6));
}
/* the name of input-block value k (rj_state_save's version 5 blocks) */
static void fz_input_name(const fz_model *f, size_t k, char *out, size_t size)
{
    static const char *comp[] = { "fx", "fy", "moment" };
    const size_t nn = (size_t)rj_model_node_count(f->m), nj = f->ni - 1;
    if (k == 0) { snprintf(out, size, "joint torques' switch"); return; }
    if (k <= nj) { snprintf(out, size, "joint %lu input torque", (unsigned long)(k - 1)); return; }
    k -= nj + 1;
    if (k == 0) { snprintf(out, size, "node forces' switch"); return; }
    k -= 1;
    if (k < 3 * nn) { snprintf(out, size, "node %lu input %s", (unsigned long)(k / 3), comp[k % 3]); return; }
    k -= 3 * nn;
    snprintf(out, size, "node %lu %s the last step applied", (unsigned long)(k / 3), comp[k % 3]);
}
/* prints how an input file's checkpoint differs from its model's valid one, then runs the
   checks on it */
int main(int argc, char **argv)
{
    static uint8_t data[1 << 16];
    size_t size, n, k, m;
    fz_model *f;
    unsigned mode;
    unsigned char *b;
    FILE *in;
    if (argc != 2 || !(in = fopen(argv[1], "rb"))) { fprintf(stderr, "usage: %s INPUT\n", argv[0]); return 2; }
    size = fread(data, 1, sizeof data, in);
    fclose(in);
    if (size < 2) { printf("input of %lu bytes: nothing to load\n", (unsigned long)size); return 0; }
    fz_init();
    b = fz_make(data, size, &f, &mode, &n);
    printf("model %s, mode %u: %lu bytes (valid: %lu)\n", f->name, mode, (unsigned long)n, (unsigned long)f->n);
    m = n < f->n ? n : f->n;
    for (k = 0; k < FZ_HEAD && k < m; k++) if (b[k] != f->ck[k]) printf("header byte %lu: %02x (valid %02x)\n", (unsigned long)k, b[k], f->ck[k]);
    if (m >= FZ_HEAD + 8 && memcmp(b + FZ_HEAD, f->ck + FZ_HEAD, 8)) {
        long long a, v;
        memcpy(&a, b + FZ_HEAD, 8); memcpy(&v, f->ck + FZ_HEAD, 8);
        printf("steps: %lld (valid %lld)\n", a, v);
    }
    for (k = 0; k < f->nd; k++) {
        size_t at = FZ_HEAD + 8 + 8 * k;
        double a, v;
        char name[64];
        if (at + 8 > m || !memcmp(b + at, f->ck + at, 8)) continue;
        memcpy(&a, b + at, 8); memcpy(&v, f->ck + at, 8);
        fz_slot_name(f, k, name, sizeof name);
        printf("value %lu (%s): %.17g (valid %.17g)\n", (unsigned long)k, name, a, v);
    }
    for (k = 0; k < f->ni; k++) {
        size_t at = FZ_HEAD + 8 + 8 * f->nd + sizeof(int) * k;
        int a, v;
        if (at + sizeof(int) > m || !memcmp(b + at, f->ck + at, sizeof(int))) continue;
        memcpy(&a, b + at, sizeof a); memcpy(&v, f->ck + at, sizeof v);
        printf("int %lu (%s): %d (valid %d)\n", (unsigned long)k, k + 1 < f->ni ? "joint flag" : "unused", a, v);
    }
    for (k = 0; k < f->nin; k++) {
        size_t at = f->in_at + 8 * k;
        double a, v;
        char name[64];
        if (at + 8 > m || !memcmp(b + at, f->ck + at, 8)) continue;
        memcpy(&a, b + at, 8); memcpy(&v, f->ck + at, 8);
        fz_input_name(f, k, name, sizeof name);
        printf("input %lu (%s): %.17g (valid %.17g)\n", (unsigned long)k, name, a, v);
    }
    if (m >= 8 && memcmp(b + n - 8, f->ck + f->n - 8, 8)) printf("checksum differs%s\n", mode == 2 || mode == 1 ? " (recomputed)" : "");
    free(b);
    fz_verbose = 1;
    fflush(stdout);
    return LLVMFuzzerTestOneInput(data, size);
}
#endif

#ifdef FUZZ_STATE_CORPUS
/* writes the seed corpus: per model a raw valid checkpoint and three checksummed edits */
int main(int argc, char **argv)
{
    int k;
    char path[512];
    if (argc != 2) { fprintf(stderr, "usage: %s DIR\n", argv[0]); return 2; }
    fz_init();
    for (k = 0; k < FZ_MODELS; k++) {
        const fz_model *f = &fz_m[k];
        /* steps 1; time 64 s; both input blocks on (switch 1) and the last node's input fy 3 N */
        unsigned char edits[3][10] = { { 0, 1, 0, 1 }, { 1, 0, 0, 7 }, { 8, 0, 0, 8, 1, 0, 7, 0, 0, 5 } };
        static const size_t elen[3] = { 4, 4, 10 };
        const unsigned fy = (unsigned)(f->ni - 1 + 2 + 3 * (size_t)(rj_model_node_count(f->m) - 1) + 1);
        FILE *o;
        int e;
        edits[2][7] = (unsigned char)(fy & 255); edits[2][8] = (unsigned char)(fy >> 8);
        snprintf(path, sizeof path, "%s/ck_%d_raw", argv[1], k);
        if (!(o = fopen(path, "wb"))) return 1;
        fputc(k, o); fputc(0, o); fwrite(f->ck, 1, f->n, o); fclose(o);
        for (e = 0; e < 3; e++) {
            snprintf(path, sizeof path, "%s/ck_%d_edit%d", argv[1], k, e);
            if (!(o = fopen(path, "wb"))) return 1;
            fputc(k, o); fputc(2, o); fwrite(edits[e], 1, elen[e], o); fclose(o);
        }
        printf("%s: %lu bytes, %lu frame doubles, %lu ints, %lu input doubles, %ld steps, t = %g s, %d loads%s%s\n", f->name,
               (unsigned long)f->n, (unsigned long)f->nd, (unsigned long)f->ni, (unsigned long)f->nin, rj_state_steps(f->base),
               rj_state_time(f->base), rj_model_load_count(f->m), rj_state_error(f->base)[0] ? "; stopped: " : "", rj_state_error(f->base));
    }
    return 0;
}
#endif
