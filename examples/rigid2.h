/* rigid2.h - independent high-accuracy reference solver for a RIGID two-link planar arm
   with torsion springs, Coulomb friction (true stick/slip) and permanently latching joints.
   Used as the "exact solution (rigid model)" against which revjoint.h is compared.

   Header-only, every function static, no globals, no allocation, no I/O; C99 and C++,
   depends on libc/libm only.

USAGE
       rigid2_params p;
       double lock_time[2];
       rigid2_default_params(&p);               (Wong, Hamouda & Hashmi 2002, Table 3)
       rigid2_run(&p, 6.0, 0.01, my_cb, my_user, lock_time);
   my_cb(const rigid2_sample *s, void *user) is called at t = 0, dt_out, 2 dt_out, ...
   and at t_end.  rigid2_run_ex() additionally reports every discrete event (lock,
   stick, slip start, slip reversal) with the state just before and just after it.

MODEL (horizontal plane, no gravity)
   q1 = absolute angle of link 1 (CCW from +x), q2 = angle of link 2 relative to link 1
   (0 = straight, pi = folded back).  Joint 1 pins link 1 to ground at the origin, joint 2
   sits at link 1's tip.  Link i = uniform slender rod (m_i, L_i, rotary inertia
   m_i L_i^2/12 about its centre) + tip point mass M_i with its own rotary inertia J_i,
   located at the far end of link i and rotating with link i.

   Inertia constants (e_i = unit vector along link i, e_i' = e_i rotated +90 deg):
     I1  = m1 L1^2/3 + M1 L1^2 + J1       inertia of link 1 about joint 1
     mb2 = m2 + M2                        mass of link 2
     s2  = m2 L2/2 + M2 L2                first moment of link 2 about joint 2
     I2  = m2 L2^2/3 + M2 L2^2 + J2       inertia of link 2 about joint 2
     B   = L1 s2

   Kinetic energy.  Joint 2 moves with v_J = L1 qd1 e1'; link 2 turns at w2 = qd1+qd2.
   For link 2, T = 1/2 mb2 |v_J|^2 + v_J . (w2 k x s2 e2) + 1/2 I2 w2^2 and
   e1' . e2' = cos q2, hence
     T = 1/2 (I1 + mb2 L1^2) qd1^2 + B cos(q2) qd1 (qd1+qd2) + 1/2 I2 (qd1+qd2)^2
       = 1/2 qd^T M(q2) qd,
     M11 = I1 + mb2 L1^2 + I2 + 2 B cos q2,  M12 = I2 + B cos q2,  M22 = I2,
     det M = I2 (I1 + mb2 L1^2) - B^2 cos^2 q2  (> 0 since I2 mb2 >= s2^2).

   Lagrange's equations, with h = B sin q2 (dM11/dq2 = -2h, dM12/dq2 = -h):
     M11 qdd1 + M12 qdd2 - h (2 qd1 qd2 + qd2^2) = Q1
     M12 qdd1 + M22 qdd2 + h qd1^2               = Q2
   Generalised forces.  A torque tau_i acting on the outer body of joint i with the
   reaction on the inner body does virtual work tau_1 dq1 + tau_2 (dphi2 - dq1)
   = tau_1 dq1 + tau_2 dq2, so each joint torque enters only its own equation:
     Q_i = k_i (pre_i - q_i) + f_i,
   f_i = friction torque: -T_i sgn(qd_i) while slipping, and while stuck whatever torque
   |f_i| <= T_i keeps qdd_i = 0.  The generalised momenta are
     p1 = M11 qd1 + M12 qd2  = angular momentum of the whole arm about joint 1,
     p2 = M12 qd1 + M22 qd2  = angular momentum of link 2 about (the fixed point at) joint 2.

   Potential energy  V = sum 1/2 k_i (pre_i - q_i)^2.
   Friction work     W = integral sum T_i |qd_i| dt   (integrated as a 5th state).
   Energy balance    T + V + W + W_lock = T0 + V0.

FRICTION (event-driven, no regularisation)
   Each unlocked joint is in one of three modes: SLIP_POS, SLIP_NEG (friction -s T_i with
   the sign s frozen for the whole mode, so the right-hand side is smooth) or STICK
   (qd_i = qdd_i = 0, the constraint torque tau_i is computed from the equations above).
   Mode switches are state events located to machine precision:
     slip s  -> reversal/stop when s qd_i crosses 0,
     stick   -> break-away    when |tau_i| crosses T_i.
   At every event the modes of all unlocked joints with qd_i = 0 are chosen together by
   enumerating {stick, slip+, slip-} per joint and keeping the combination that satisfies
   every Coulomb condition (stick: |tau_i| <= T_i; slip s: s qdd_i >= 0).  With a positive
   definite M and constant friction limits this acceleration problem is the optimality
   condition of a strictly convex problem, so the consistent combination is unique (ties
   only at exact switching boundaries, where the event logic forbids the mode being left).
   Friction torques are bounded, so they transmit no impulse: a joint that is stuck when
   the other joint latches is set in motion by the impact.

LOCKS (perfectly plastic, permanent)
   Joint 1 latches when q1 increases through lock[0]; joint 2 when q2 decreases through
   lock[1] (set lock[0] = +HUGE_VAL / lock[1] = -HUGE_VAL to disable).  The impact makes the
   joint's relative rate 0 and conserves the momentum conjugate to the OTHER coordinate
   (the lock impulse is a pure generalised impulse on q_i):
     joint 2 locks, joint 1 free:  p1 conserved -> qd1+ = p1 / M11, qd2+ = 0
     joint 1 locks, joint 2 free:  p2 conserved -> qd2+ = p2 / M22, qd1+ = 0
     the second lock:              everything stops.
   The kinetic energy lost is added to wlock.  A locked joint never unlocks.

INTEGRATION
   Dormand-Prince 5(4), local extrapolation, FSAL, mixed error test
   |err_i| <= tol (1 + max(|y_i|, |y_i new|)) in the max norm, steps clipped to output times
   (so samples are integrator steps, no interpolation), maximum step 0.05 s (events are
   detected by a sign change between step ends; the cap keeps any event function from
   crossing and re-crossing zero unseen inside one step).  Events are located by Illinois
   (modified regula falsi) iteration on the step size: each trial evaluates the event
   function on a genuine RK step from the start of the step, so the event state has full
   5th-order accuracy.  The iteration stops when the bracket is a few ulps of t wide; the
   state is taken at the right end (event function already crossed), which makes the
   subsequent mode selection unambiguous.  Velocities are snapped to exactly 0 at
   reversal/stop events (error ~1e-15 rad/s), and a latched angle is set exactly to its lock
   angle (overshoot of a few ulps; the ~1e-16 J spring-energy change is booked in wlock).
   Default case: 130-150 steps per 6 s at tol 1e-8..1e-10 (605 with dt_out = 0.01), lock
   times agree to < 1e-9 s between tol 1e-8 and 1e-12.

LIMITATIONS
   A joint that starts exactly on or beyond its lock angle is not latched at t = 0 (a lock
   needs the angle to cross it in the approach direction during the run).  Static and
   kinetic friction limits are the same T_i.  Impacts are perfectly plastic (no rebound).
*/
#ifndef RIGID2_H
#define RIGID2_H

#include <math.h>
#include <float.h>
#include <string.h>

#if defined(__GNUC__) || defined(__clang__)
#define RIGID2_FN static __attribute__((unused))
#else
#define RIGID2_FN static
#endif

#define RIGID2_PI 3.14159265358979323846

/* joint modes (rigid2_sample.mode, rigid2_event) */
#define RIGID2_SLIP_NEG (-1)
#define RIGID2_STICK 0
#define RIGID2_SLIP_POS 1
#define RIGID2_LOCKED 2

/* event kinds */
#define RIGID2_EV_LOCK 1  /* joint latched */
#define RIGID2_EV_MODE 2  /* friction mode changed (stick, break-away, reversal) */

/* return codes */
#define RIGID2_OK 0
#define RIGID2_EPARAM 1    /* invalid parameter */
#define RIGID2_ESTEP 2     /* step size underflow */
#define RIGID2_EMAXSTEP 3  /* too many steps */
#define RIGID2_EZENO 4     /* too many events without time advancing */

typedef struct {
    double m[2];    /* rod masses (kg) */
    double L[2];    /* link lengths (m) */
    double M[2];    /* tip point masses (kg) */
    double J[2];    /* tip rotary inertias about their own centres (kg m^2) */
    double k[2];    /* torsion spring stiffnesses (N m / rad) */
    double pre[2];  /* spring free angles ("pre-rotation", rad); torque k (pre - q) */
    double T[2];    /* Coulomb friction torques (N m, >= 0) */
    double lock[2]; /* lock angles (rad): q1 rising to lock[0], q2 falling to lock[1] */
    double q0[2];   /* initial q1, q2 (rad) */
    double qd0[2];  /* initial rates (rad/s) */
    double tol;     /* integrator tolerance (relative and absolute) */
} rigid2_params;

typedef struct {
    double t;
    double q[2], qd[2];  /* q1 absolute, q2 relative (rad), rates (rad/s) */
    int locked[2];       /* 1 once latched */
    int mode[2];         /* RIGID2_SLIP_NEG / _STICK / _SLIP_POS / _LOCKED */
    double tip2[2];      /* position of link 2's tip (m) */
    double ke, pe;       /* kinetic and spring potential energy (J) */
    double wfric;        /* work dissipated by friction so far (J) */
    double wlock;        /* kinetic energy lost in lock impacts so far (J) */
    double p[2];         /* generalised momenta: p[0] about joint 1 (whole arm), p[1] link 2 about joint 2 */
} rigid2_sample;

typedef struct {
    int kind;              /* RIGID2_EV_LOCK or RIGID2_EV_MODE */
    int joint;             /* 0 or 1 */
    rigid2_sample before;  /* state just before the event (mode = old modes) */
    rigid2_sample after;   /* state just after (velocities after impact, new modes) */
} rigid2_event;

typedef struct {
    long steps, rejected, fevals, events;
} rigid2_stats;

/* ------------------------------------------------------------------------------------ */

RIGID2_FN void rigid2_default_params(rigid2_params *p)
{
    const double d = RIGID2_PI / 180.0;
    memset(p, 0, sizeof *p);
    p->L[0] = 1.006423; p->m[0] = 0.52334; p->M[0] = 1.2;   p->J[0] = 8.5948e-4;
    p->T[0] = 0.03825;  p->k[0] = 0.0789;  p->pre[0] = 300.0 * d;
    p->q0[0] = 0.0;     p->lock[0] = 90.0 * d;
    p->L[1] = 0.9945;   p->m[1] = 0.42958; p->M[1] = 0.336; p->J[1] = 9.256e-4;
    p->T[1] = 0.0225;   p->k[1] = 0.0768;  p->pre[1] = -60.0 * d;
    p->q0[1] = 180.0 * d; p->lock[1] = 0.0;
    p->qd0[0] = p->qd0[1] = 0.0;
    p->tol = 1e-10;
}

/* the "extra friction" variant of the same rig */
RIGID2_FN void rigid2_add_extra_friction(rigid2_params *p)
{
    p->T[0] += 0.175;
    p->T[1] += 0.008;
}

/* ---- internals ---------------------------------------------------------------------- */

typedef struct {
    const rigid2_params *p;
    double I1, mb2, s2, I2, B, A; /* A = I1 + mb2 L1^2 + I2 */
    int mode[2];
    long fevals;
} rigid2__sys;

#define RIGID2__N 5 /* state: q1 q2 qd1 qd2 wfric */

static void rigid2__init_sys(rigid2__sys *s, const rigid2_params *p)
{
    const double L1 = p->L[0], L2 = p->L[1];
    s->p = p;
    s->I1 = p->m[0] * L1 * L1 / 3.0 + p->M[0] * L1 * L1 + p->J[0];
    s->mb2 = p->m[1] + p->M[1];
    s->s2 = p->m[1] * L2 / 2.0 + p->M[1] * L2;
    s->I2 = p->m[1] * L2 * L2 / 3.0 + p->M[1] * L2 * L2 + p->J[1];
    s->B = L1 * s->s2;
    s->A = s->I1 + s->mb2 * L1 * L1 + s->I2;
    s->mode[0] = s->mode[1] = RIGID2_STICK;
    s->fevals = 0;
}

static void rigid2__mass(const rigid2__sys *s, double q2, double Mm[3])
{
    const double c = cos(q2);
    Mm[0] = s->A + 2.0 * s->B * c; /* M11 */
    Mm[1] = s->I2 + s->B * c;      /* M12 */
    Mm[2] = s->I2;                 /* M22 */
}

/* accelerations and constraint (stick / lock) torques for given modes.
   tau[i] is the torque the stuck or locked joint must supply (0 for slipping joints). */
static void rigid2__accel(const rigid2__sys *s, const int mode[2], const double *y,
                          double qdd[2], double tau[2])
{
    const rigid2_params *p = s->p;
    const double q1 = y[0], q2 = y[1], w1 = y[2], w2 = y[3];
    const double c = cos(q2), h = s->B * sin(q2);
    const double M11 = s->A + 2.0 * s->B * c, M12 = s->I2 + s->B * c, M22 = s->I2;
    double F1 = p->k[0] * (p->pre[0] - q1) + h * (2.0 * w1 * w2 + w2 * w2);
    double F2 = p->k[1] * (p->pre[1] - q2) - h * w1 * w1;
    const int c1 = (mode[0] == RIGID2_STICK || mode[0] == RIGID2_LOCKED);
    const int c2 = (mode[1] == RIGID2_STICK || mode[1] == RIGID2_LOCKED);
    if (!c1) F1 -= (double)mode[0] * p->T[0];
    if (!c2) F2 -= (double)mode[1] * p->T[1];
    tau[0] = tau[1] = 0.0;
    if (!c1 && !c2) {
        const double det = s->I2 * (s->A - s->I2) - s->B * s->B * c * c;
        qdd[0] = (M22 * F1 - M12 * F2) / det;
        qdd[1] = (M11 * F2 - M12 * F1) / det;
    } else if (!c1) {
        qdd[0] = F1 / M11;
        qdd[1] = 0.0;
        tau[1] = M12 * qdd[0] - F2;
    } else if (!c2) {
        qdd[0] = 0.0;
        qdd[1] = F2 / M22;
        tau[0] = M12 * qdd[1] - F1;
    } else {
        qdd[0] = qdd[1] = 0.0;
        tau[0] = -F1;
        tau[1] = -F2;
    }
}

static void rigid2__rhs(rigid2__sys *s, const double *y, double *dy)
{
    const rigid2_params *p = s->p;
    double qdd[2], tau[2];
    int i;
    rigid2__accel(s, s->mode, y, qdd, tau);
    dy[0] = y[2];
    dy[1] = y[3];
    dy[2] = qdd[0];
    dy[3] = qdd[1];
    dy[4] = 0.0;
    for (i = 0; i < 2; i++)
        if (s->mode[i] == RIGID2_SLIP_POS || s->mode[i] == RIGID2_SLIP_NEG)
            dy[4] += (double)s->mode[i] * p->T[i] * y[2 + i]; /* = T |qd| within the mode */
    s->fevals++;
}

static double rigid2__ke(const rigid2__sys *s, const double *y)
{
    double Mm[3];
    rigid2__mass(s, y[1], Mm);
    return 0.5 * (Mm[0] * y[2] * y[2] + 2.0 * Mm[1] * y[2] * y[3] + Mm[2] * y[3] * y[3]);
}

static double rigid2__pe(const rigid2__sys *s, const double *y)
{
    const rigid2_params *p = s->p;
    const double d1 = p->pre[0] - y[0], d2 = p->pre[1] - y[1];
    return 0.5 * p->k[0] * d1 * d1 + 0.5 * p->k[1] * d2 * d2;
}

static void rigid2__fill(const rigid2__sys *s, double t, const double *y, double wlock,
                         rigid2_sample *o)
{
    const rigid2_params *p = s->p;
    double Mm[3];
    int i;
    rigid2__mass(s, y[1], Mm);
    o->t = t;
    for (i = 0; i < 2; i++) {
        o->q[i] = y[i];
        o->qd[i] = y[2 + i];
        o->mode[i] = s->mode[i];
        o->locked[i] = (s->mode[i] == RIGID2_LOCKED);
    }
    o->tip2[0] = p->L[0] * cos(y[0]) + p->L[1] * cos(y[0] + y[1]);
    o->tip2[1] = p->L[0] * sin(y[0]) + p->L[1] * sin(y[0] + y[1]);
    o->ke = rigid2__ke(s, y);
    o->pe = rigid2__pe(s, y);
    o->wfric = y[4];
    o->wlock = wlock;
    o->p[0] = Mm[0] * y[2] + Mm[1] * y[3];
    o->p[1] = Mm[1] * y[2] + Mm[2] * y[3];
}

/* Choose modes for all unlocked joints.  Joints with qd != 0 slip in the direction of
   qd; joints with qd == 0 exactly are candidates, resolved jointly by enumeration.
   forbid[i] is a bit mask of options not allowed for candidate i:
   bit 0 = stick, bit 1 = slip+, bit 2 = slip-. */
static void rigid2__choose_modes(rigid2__sys *s, const double *y, const int forbid[2])
{
    static const int opt[3] = {RIGID2_STICK, RIGID2_SLIP_POS, RIGID2_SLIP_NEG};
    const rigid2_params *p = s->p;
    int cand[2], ncand = 0, i, a, b, trial[2], best[2];
    double best_viol = HUGE_VAL, Mm[3];
    rigid2__mass(s, y[1], Mm);
    for (i = 0; i < 2; i++) {
        if (s->mode[i] == RIGID2_LOCKED) continue;
        if (y[2 + i] > 0.0) s->mode[i] = RIGID2_SLIP_POS;
        else if (y[2 + i] < 0.0) s->mode[i] = RIGID2_SLIP_NEG;
        else cand[ncand++] = i;
    }
    if (ncand == 0) return;
    best[0] = s->mode[0];
    best[1] = s->mode[1];
    for (a = 0; a < 3; a++) {
        for (b = 0; b < (ncand > 1 ? 3 : 1); b++) {
            const int o[2] = {opt[a], opt[b]};
            double qdd[2], tau[2], viol = 0.0;
            int j, ok = 1;
            trial[0] = s->mode[0];
            trial[1] = s->mode[1];
            for (j = 0; j < ncand; j++) {
                const int oi = (o[j] == RIGID2_STICK) ? 0 : (o[j] == RIGID2_SLIP_POS ? 1 : 2);
                if (forbid[cand[j]] & (1 << oi)) ok = 0;
                trial[cand[j]] = o[j];
            }
            if (!ok) continue;
            rigid2__accel(s, trial, y, qdd, tau);
            for (j = 0; j < ncand; j++) {
                const int ji = cand[j];
                if (trial[ji] == RIGID2_STICK) {
                    const double e = fabs(tau[ji]) - p->T[ji];
                    if (e > 0.0) viol += e;
                } else {
                    const double e = -(double)trial[ji] * qdd[ji];
                    if (e > 0.0) viol += e * Mm[ji == 0 ? 0 : 2];
                }
            }
            if (viol < best_viol) {
                best_viol = viol;
                best[0] = trial[0];
                best[1] = trial[1];
                if (viol == 0.0) goto done; /* first consistent one (stick preferred) */
            }
        }
    }
done:
    s->mode[0] = best[0];
    s->mode[1] = best[1];
}

/* Dormand-Prince 5(4) tableau */
#define RIGID2__C2 (1.0 / 5.0)
#define RIGID2__C3 (3.0 / 10.0)
#define RIGID2__C4 (4.0 / 5.0)
#define RIGID2__C5 (8.0 / 9.0)

/* One DP5 step of size h from y (k1 = f(y) given).  Writes the 5th-order solution to y1.
   If err != NULL also evaluates k7 = f(y1) and the scaled max-norm error estimate. */
static void rigid2__dp_step(rigid2__sys *s, const double *y, const double *k1, double h,
                            double *y1, double *k7, double tol, double *err)
{
    double k2[RIGID2__N], k3[RIGID2__N], k4[RIGID2__N], k5[RIGID2__N], k6[RIGID2__N];
    double yt[RIGID2__N];
    int i;
    for (i = 0; i < RIGID2__N; i++) yt[i] = y[i] + h * (1.0 / 5.0) * k1[i];
    rigid2__rhs(s, yt, k2);
    for (i = 0; i < RIGID2__N; i++) yt[i] = y[i] + h * (3.0 / 40.0 * k1[i] + 9.0 / 40.0 * k2[i]);
    rigid2__rhs(s, yt, k3);
    for (i = 0; i < RIGID2__N; i++)
        yt[i] = y[i] + h * (44.0 / 45.0 * k1[i] - 56.0 / 15.0 * k2[i] + 32.0 / 9.0 * k3[i]);
    rigid2__rhs(s, yt, k4);
    for (i = 0; i < RIGID2__N; i++)
        yt[i] = y[i] + h * (19372.0 / 6561.0 * k1[i] - 25360.0 / 2187.0 * k2[i]
                            + 64448.0 / 6561.0 * k3[i] - 212.0 / 729.0 * k4[i]);
    rigid2__rhs(s, yt, k5);
    for (i = 0; i < RIGID2__N; i++)
        yt[i] = y[i] + h * (9017.0 / 3168.0 * k1[i] - 355.0 / 33.0 * k2[i]
                            + 46732.0 / 5247.0 * k3[i] + 49.0 / 176.0 * k4[i]
                            - 5103.0 / 18656.0 * k5[i]);
    rigid2__rhs(s, yt, k6);
    for (i = 0; i < RIGID2__N; i++)
        y1[i] = y[i] + h * (35.0 / 384.0 * k1[i] + 500.0 / 1113.0 * k3[i] + 125.0 / 192.0 * k4[i]
                            - 2187.0 / 6784.0 * k5[i] + 11.0 / 84.0 * k6[i]);
    /* stuck / locked joints: keep angle and rate bit-exact (their derivatives are 0) */
    for (i = 0; i < 2; i++)
        if (s->mode[i] == RIGID2_STICK || s->mode[i] == RIGID2_LOCKED) {
            y1[i] = y[i];
            y1[2 + i] = 0.0;
        }
    if (err) {
        double e = 0.0;
        rigid2__rhs(s, y1, k7);
        for (i = 0; i < RIGID2__N; i++) {
            const double ei = h * (71.0 / 57600.0 * k1[i] - 71.0 / 16695.0 * k3[i]
                                   + 71.0 / 1920.0 * k4[i] - 17253.0 / 339200.0 * k5[i]
                                   + 22.0 / 525.0 * k6[i] - 1.0 / 40.0 * k7[i]);
            const double ay = fabs(y[i]) > fabs(y1[i]) ? fabs(y[i]) : fabs(y1[i]);
            const double r = fabs(ei) / (tol * (1.0 + ay));
            if (r > e) e = r;
        }
        *err = e;
    }
}

/* Event functions: positive = nothing happened, negative = event has occurred.
   Index 3*i + 0: lock of joint i, 3*i + 1: slip reversal / stop, 3*i + 2: stick break-away.
   Inactive events return +HUGE_VAL. */
#define RIGID2__NEV 6

static void rigid2__events(const rigid2__sys *s, const double *y, double *g)
{
    const rigid2_params *p = s->p;
    int i;
    double qdd[2], tau[2];
    int need_tau = 0;
    for (i = 0; i < 2; i++) {
        g[3 * i] = g[3 * i + 1] = g[3 * i + 2] = HUGE_VAL;
        if (s->mode[i] == RIGID2_LOCKED) continue;
        g[3 * i] = (i == 0) ? p->lock[0] - y[0] : y[1] - p->lock[1];
        if (s->mode[i] == RIGID2_STICK) need_tau = 1;
        else if (p->T[i] > 0.0) g[3 * i + 1] = (double)s->mode[i] * y[2 + i];
        /* with T = 0 the slip direction is irrelevant: no reversal events */
    }
    if (need_tau) {
        rigid2__accel(s, s->mode, y, qdd, tau);
        for (i = 0; i < 2; i++)
            if (s->mode[i] == RIGID2_STICK) g[3 * i + 2] = p->T[i] - fabs(tau[i]);
    }
}

/* Illinois iteration on the step size for event function ev: g(0) >= 0, g(hb) < 0.
   Returns the right end of the final bracket (g < 0 there). */
static double rigid2__locate(rigid2__sys *s, const double *y, const double *k1, double t,
                             double hb, double ga, double gb, int ev)
{
    double a = 0.0, b = hb, yt[RIGID2__N], g[RIGID2__NEV];
    int side = 0, it;
    for (it = 0; it < 200; it++) {
        double x, gx;
        if (b - a <= 4.0 * DBL_EPSILON * (fabs(t) + fabs(b)) || b - a <= 0.0) break;
        x = (ga - gb != 0.0) ? b - gb * (b - a) / (gb - ga) : 0.5 * (a + b);
        if (!(x > a && x < b)) x = 0.5 * (a + b);
        if (it % 8 == 7) x = 0.5 * (a + b); /* safeguard: guaranteed shrinkage */
        rigid2__dp_step(s, y, k1, x, yt, NULL, 0.0, NULL);
        rigid2__events(s, yt, g);
        gx = g[ev];
        if (gx < 0.0) {
            b = x; gb = gx;
            if (side == -1) ga *= 0.5;
            side = -1;
        } else {
            a = x; ga = gx;
            if (side == 1) gb *= 0.5;
            side = 1;
        }
    }
    return b;
}

/* ---- public driver ---------------------------------------------------------------- */

RIGID2_FN int rigid2_check_params(const rigid2_params *p)
{
    int i;
    if (!p) return RIGID2_EPARAM;
    for (i = 0; i < 2; i++) {
        if (!(p->L[i] > 0.0) || !(p->m[i] >= 0.0) || !(p->M[i] >= 0.0) || !(p->J[i] >= 0.0)
            || !(p->T[i] >= 0.0) || !(fabs(p->k[i]) < HUGE_VAL) || !(fabs(p->pre[i]) < HUGE_VAL)
            || !(fabs(p->q0[i]) < HUGE_VAL) || !(fabs(p->qd0[i]) < HUGE_VAL) || p->lock[i] != p->lock[i])
            return RIGID2_EPARAM;
    }
    if (!(p->tol > 0.0 && p->tol < 1.0)) return RIGID2_EPARAM;
    if (!(p->m[0] + p->M[0] + p->J[0] > 0.0) || !(p->m[1] + p->M[1] + p->J[1] > 0.0))
        return RIGID2_EPARAM;
    return RIGID2_OK;
}

/* Integrate from 0 to t_end.  cb (may be NULL) gets samples at k*dt_out and t_end;
   ev_cb (may be NULL) gets every discrete event; lock_time (may be NULL) receives the
   latch times (-1 if never); st (may be NULL) receives counters. Returns RIGID2_OK or an
   error code (the callbacks have been called up to the failure time). */
RIGID2_FN int rigid2_run_ex(const rigid2_params *p, double t_end, double dt_out,
                            void (*cb)(const rigid2_sample *, void *),
                            void (*ev_cb)(const rigid2_event *, void *), void *user,
                            double lock_time[2], rigid2_stats *st)
{
    const double hmax = 0.05;
    const long max_steps = 50000000L;
    rigid2__sys s;
    double y[RIGID2__N], y1[RIGID2__N], k1[RIGID2__N], k7[RIGID2__N];
    double t = 0.0, h, wlock = 0.0, tl[2] = {-1.0, -1.0}, last_event_t = -1.0;
    long n_out, k_out = 1, steps = 0, rejected = 0, events = 0;
    int zero_forbid[2] = {0, 0}, zeno = 0, rc = RIGID2_OK, i;
    rigid2_sample smp;

    if (lock_time) lock_time[0] = lock_time[1] = -1.0;
    if (st) st->steps = st->rejected = st->fevals = st->events = 0;
    if (rigid2_check_params(p) != RIGID2_OK || !(t_end >= 0.0) || !(dt_out > 0.0)
        || !(t_end < HUGE_VAL))
        return RIGID2_EPARAM;

    rigid2__init_sys(&s, p);
    y[0] = p->q0[0]; y[1] = p->q0[1]; y[2] = p->qd0[0]; y[3] = p->qd0[1]; y[4] = 0.0;
    rigid2__choose_modes(&s, y, zero_forbid);

    /* output grid: k*dt_out for k*dt_out < t_end (less a hair), then t_end */
    n_out = (long)floor(t_end / dt_out * (1.0 - 1e-12));
    if ((double)n_out * dt_out >= t_end * (1.0 - 1e-12)) n_out--;
    if (n_out < 0) n_out = 0;
    /* samples: k = 0..n_out at k*dt_out, then t_end (index n_out+1) */

    if (cb) { rigid2__fill(&s, 0.0, y, wlock, &smp); cb(&smp, user); }
    if (t_end == 0.0) goto finish;

    rigid2__rhs(&s, y, k1);
    h = 0.01 * pow(p->tol, 0.2);
    if (h > hmax) h = hmax;

    for (;;) {
        const double t_target = (k_out <= n_out) ? (double)k_out * dt_out : t_end;
        double hs = h, err, g0[RIGID2__NEV], g1[RIGID2__NEV];
        int clipped = 0, ev, first = -1;
        double hfirst = HUGE_VAL;

        if (hs >= t_target - t) { hs = t_target - t; clipped = 1; }
        if (hs <= 0.0) { /* already at the target (can happen right after an event) */
            hs = 0.0;
            goto output;
        }
        if (steps++ > max_steps) { rc = RIGID2_EMAXSTEP; break; }
        rigid2__dp_step(&s, y, k1, hs, y1, k7, p->tol, &err);
        if (!(err <= 1.0)) {
            rejected++;
            h = hs * ((err < HUGE_VAL) ? fmax(0.1, 0.9 * pow(err, -0.2)) : 0.1);
            if (h < 1e-14 * (1.0 + fabs(t))) { rc = RIGID2_ESTEP; break; }
            continue;
        }

        /* event detection on the accepted step */
        rigid2__events(&s, y, g0);
        rigid2__events(&s, y1, g1);
        for (ev = 0; ev < RIGID2__NEV; ev++) {
            if (g0[ev] >= 0.0 && g1[ev] < 0.0) {
                const double he = rigid2__locate(&s, y, k1, t, hs, g0[ev], g1[ev], ev);
                if (he < hfirst) { hfirst = he; first = ev; }
            }
        }

        if (first >= 0) {
            /* ---- handle the event(s) at t + hfirst ---- */
            double ye[RIGID2__N], ge[RIGID2__NEV];
            int forbid[2] = {0, 0}, old_mode[2], fired_lock[2] = {0, 0}, j;
            rigid2_event E;
            rigid2__dp_step(&s, y, k1, hfirst, ye, NULL, 0.0, NULL);
            rigid2__events(&s, ye, ge);
            t = (clipped && hfirst == hs) ? t_target : t + hfirst;
            if (t - last_event_t <= 1e-12 * (1.0 + t)) {
                if (++zeno > 50) { rc = RIGID2_EZENO; break; }
            } else {
                zeno = 0;
            }
            last_event_t = t;
            events++;
            if (ev_cb) rigid2__fill(&s, t, ye, wlock, &E.before);
            old_mode[0] = s.mode[0];
            old_mode[1] = s.mode[1];
            for (j = 0; j < 2; j++) {
                if (g0[3 * j] >= 0.0 && ge[3 * j] < 0.0) fired_lock[j] = 1;
            }
            /* locks (plastic impacts) */
            if (fired_lock[0] || fired_lock[1]) {
                const double ke0 = rigid2__ke(&s, ye);
                double Mm[3];
                /* the located state overshoots the lock angle by a few ulps: snap it, and
                   book the (~1e-16 J) spring-energy change of the snap with the impact loss */
                const double pe0 = rigid2__pe(&s, ye);
                for (j = 0; j < 2; j++)
                    if (fired_lock[j]) { s.mode[j] = RIGID2_LOCKED; tl[j] = t; ye[j] = p->lock[j]; }
                rigid2__mass(&s, ye[1], Mm);
                if (s.mode[0] == RIGID2_LOCKED && s.mode[1] == RIGID2_LOCKED) {
                    ye[2] = ye[3] = 0.0;
                } else if (fired_lock[1]) { /* joint 2 latches, joint 1 free: p1 conserved */
                    ye[2] = (Mm[0] * ye[2] + Mm[1] * ye[3]) / Mm[0];
                    ye[3] = 0.0;
                } else { /* joint 1 latches, joint 2 free: p2 conserved */
                    ye[3] = (Mm[1] * ye[2] + Mm[2] * ye[3]) / Mm[2];
                    ye[2] = 0.0;
                }
                wlock += ke0 - rigid2__ke(&s, ye) + pe0 - rigid2__pe(&s, ye);
            }
            /* friction events of joints still unlocked */
            for (j = 0; j < 2; j++) {
                if (s.mode[j] == RIGID2_LOCKED || fired_lock[j]) continue;
                if (g0[3 * j + 1] >= 0.0 && ge[3 * j + 1] < 0.0) {
                    /* slip reversal / stop: velocity crossed zero, old direction forbidden */
                    ye[2 + j] = 0.0;
                    forbid[j] |= (s.mode[j] == RIGID2_SLIP_POS) ? 2 : 4;
                }
                if (g0[3 * j + 2] >= 0.0 && ge[3 * j + 2] < 0.0) forbid[j] |= 1; /* break-away */
            }
            rigid2__choose_modes(&s, ye, forbid);
            memcpy(y, ye, sizeof y);
            if (ev_cb) {
                rigid2__fill(&s, t, y, wlock, &E.after);
                for (j = 0; j < 2; j++) {
                    if (fired_lock[j]) {
                        E.kind = RIGID2_EV_LOCK; E.joint = j; ev_cb(&E, user);
                    } else if (s.mode[j] != old_mode[j] || forbid[j]) {
                        E.kind = RIGID2_EV_MODE; E.joint = j; ev_cb(&E, user);
                    }
                }
            }
            rigid2__rhs(&s, y, k1);
            if (!(clipped && hfirst == hs)) continue;
        } else {
            /* ---- plain accepted step ---- */
            double fac = (err > 0.0) ? 0.9 * pow(err, -0.2) : 5.0;
            double hn;
            if (fac > 5.0) fac = 5.0;
            if (fac < 0.2) fac = 0.2;
            hn = hs * fac;
            memcpy(y, y1, sizeof y);
            memcpy(k1, k7, sizeof k1);
            t = clipped ? t_target : t + hs;
            h = clipped ? (hn > h ? hn : h) : hn;
            if (h > hmax) h = hmax;
            if (!clipped) continue;
        }
    output:
        if (cb) { rigid2__fill(&s, t, y, wlock, &smp); cb(&smp, user); }
        if (k_out > n_out) break; /* that was t_end */
        k_out++;
    }

finish:
    for (i = 0; i < 2; i++)
        if (lock_time) lock_time[i] = tl[i];
    if (st) {
        st->steps = steps; st->rejected = rejected; st->fevals = s.fevals; st->events = events;
    }
    return rc;
}

RIGID2_FN int rigid2_run(const rigid2_params *p, double t_end, double dt_out,
                         void (*cb)(const rigid2_sample *, void *), void *user,
                         double lock_time[2])
{
    return rigid2_run_ex(p, t_end, dt_out, cb, NULL, user, lock_time, NULL);
}

#endif /* RIGID2_H */
