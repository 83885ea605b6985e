/* test_rigid2.c - standalone checks of examples/rigid2.h (the rigid two-link reference).
   Build:  gcc -std=c99 -O2 -Wall -Wextra -pedantic -Werror -Iexamples tests/test_rigid2.c -lm
   Prints one "PASS name ..." / "FAIL name ..." line per check (plus "INFO" lines) and exits
   with status 0 only if every check passed.

   Energies and angular momenta are recomputed here from the body kinematics (rods and tip
   masses one by one), independently of the mass matrix used inside the solver. */
#include <stdio.h>
#include <math.h>
#include <time.h>
#include "../examples/rigid2.h"

static int n_fail = 0;

static void check(int ok, const char *name, const char *fmt, double a, double b, double c)
{
    printf("%s %s ", ok ? "PASS" : "FAIL", name);
    printf(fmt, a, b, c);
    printf("\n");
    if (!ok) n_fail++;
}

static double deg(double r) { return r * 180.0 / RIGID2_PI; }

/* ---- independent body-by-body kinematics ---------------------------------------------- */
typedef struct { double m, Ic, x, y, vx, vy, w; int link; } body;

static void bodies(const rigid2_params *p, const double q[2], const double qd[2], body b[4])
{
    const double L1 = p->L[0], L2 = p->L[1], a2 = q[0] + q[1], w2 = qd[0] + qd[1];
    const double c1 = cos(q[0]), s1 = sin(q[0]), c2 = cos(a2), s2 = sin(a2);
    const double jx = L1 * c1, jy = L1 * s1, jvx = -L1 * s1 * qd[0], jvy = L1 * c1 * qd[0];
    int i;
    /* rod 1, tip 1, rod 2, tip 2 */
    b[0].m = p->m[0]; b[0].Ic = p->m[0] * L1 * L1 / 12.0; b[0].w = qd[0]; b[0].link = 0;
    b[0].x = 0.5 * jx; b[0].y = 0.5 * jy; b[0].vx = 0.5 * jvx; b[0].vy = 0.5 * jvy;
    b[1].m = p->M[0]; b[1].Ic = p->J[0]; b[1].w = qd[0]; b[1].link = 0;
    b[1].x = jx; b[1].y = jy; b[1].vx = jvx; b[1].vy = jvy;
    for (i = 2; i < 4; i++) {
        const double r = (i == 2) ? 0.5 * L2 : L2;
        b[i].m = (i == 2) ? p->m[1] : p->M[1];
        b[i].Ic = (i == 2) ? p->m[1] * L2 * L2 / 12.0 : p->J[1];
        b[i].w = w2; b[i].link = 1;
        b[i].x = jx + r * c2; b[i].y = jy + r * s2;
        b[i].vx = jvx - r * s2 * w2; b[i].vy = jvy + r * c2 * w2;
    }
}

static double ke_indep(const rigid2_params *p, const double q[2], const double qd[2])
{
    body b[4];
    double e = 0.0;
    int i;
    bodies(p, q, qd, b);
    for (i = 0; i < 4; i++) e += 0.5 * b[i].m * (b[i].vx * b[i].vx + b[i].vy * b[i].vy) + 0.5 * b[i].Ic * b[i].w * b[i].w;
    return e;
}

/* angular momentum about the fixed point (ox, oy) of the bodies of link >= first_link */
static double hmom(const rigid2_params *p, const double q[2], const double qd[2], int first_link,
                   double ox, double oy)
{
    body b[4];
    double H = 0.0;
    int i;
    bodies(p, q, qd, b);
    for (i = 0; i < 4; i++) {
        if (b[i].link < first_link) continue;
        H += b[i].m * ((b[i].x - ox) * b[i].vy - (b[i].y - oy) * b[i].vx) + b[i].Ic * b[i].w;
    }
    return H;
}

static double h_about_j1(const rigid2_params *p, const rigid2_sample *s)
{
    return hmom(p, s->q, s->qd, 0, 0.0, 0.0);
}

static double h_link2_about_j2(const rigid2_params *p, const rigid2_sample *s)
{
    return hmom(p, s->q, s->qd, 1, p->L[0] * cos(s->q[0]), p->L[0] * sin(s->q[0]));
}

static double pe_indep(const rigid2_params *p, const double q[2])
{
    return 0.5 * p->k[0] * (p->pre[0] - q[0]) * (p->pre[0] - q[0])
         + 0.5 * p->k[1] * (p->pre[1] - q[1]) * (p->pre[1] - q[1]);
}

/* ---- callback recorder ------------------------------------------------------------------- */
typedef struct {
    const rigid2_params *p;
    double E0, Hj1_0;
    double max_bal_prelock;   /* |ke+pe+wf - E0| / E0 before any lock */
    double max_bal_all;       /* |ke+pe+wf+wlock - E0| / E0 everywhere */
    double max_ke_diff;       /* |ke (solver) - ke (bodies)| / E0 */
    double max_h_drift;       /* |H_j1 - H_j1(0)| / scale */
    double q_at[4][2];        /* q at t = 1, 2, 3, 6 */
    double qmax_move;         /* max |q - q0| */
    int n_samples, any_lock_seen;
    double last_t;
    int order_ok;
    /* events */
    int n_events, n_lock_events, n_mode_events;
    double lock2_Hb, lock2_Ha, lock2_t; int lock2_j1_free;
    double lock1_Hb, lock1_Ha, lock1_t; int lock1_j2_free;
    double mode_t[16]; int mode_j[16], mode_from[16], mode_to[16];
} rec;

static void rec_init(rec *r, const rigid2_params *p)
{
    memset(r, 0, sizeof *r);
    r->p = p;
    r->last_t = -1.0;
    r->order_ok = 1;
    r->lock2_t = r->lock1_t = -1.0;
}

static void on_sample(const rigid2_sample *s, void *u)
{
    rec *r = (rec *)u;
    const rigid2_params *p = r->p;
    const double ke = ke_indep(p, s->q, s->qd), pe = pe_indep(p, s->q);
    const double H = h_about_j1(p, s);
    double d;
    int i;
    if (r->n_samples == 0) { r->E0 = ke + pe; r->Hj1_0 = H; }
    if (!(s->t > r->last_t)) r->order_ok = 0;
    r->last_t = s->t;
    r->n_samples++;
    if (s->locked[0] || s->locked[1]) r->any_lock_seen = 1;
    if (!r->any_lock_seen) {
        d = fabs(ke + pe + s->wfric - r->E0) / r->E0;
        if (d > r->max_bal_prelock) r->max_bal_prelock = d;
    }
    d = fabs(ke + pe + s->wfric + s->wlock - r->E0) / r->E0;
    if (d > r->max_bal_all) r->max_bal_all = d;
    d = fabs(ke - s->ke) / r->E0;
    if (d > r->max_ke_diff) r->max_ke_diff = d;
    d = fabs(H - r->Hj1_0) / (fabs(r->Hj1_0) > 1e-300 ? fabs(r->Hj1_0) : 1.0);
    if (d > r->max_h_drift) r->max_h_drift = d;
    for (i = 0; i < 2; i++) {
        d = fabs(s->q[i] - p->q0[i]) + fabs(s->qd[i]);
        if (d > r->qmax_move) r->qmax_move = d;
    }
    {
        static const double tt[4] = {1.0, 2.0, 3.0, 6.0};
        for (i = 0; i < 4; i++)
            if (fabs(s->t - tt[i]) < 1e-9) { r->q_at[i][0] = s->q[0]; r->q_at[i][1] = s->q[1]; }
    }
}

static void on_event(const rigid2_event *e, void *u)
{
    rec *r = (rec *)u;
    const rigid2_params *p = r->p;
    r->n_events++;
    if (e->kind == RIGID2_EV_LOCK) {
        r->n_lock_events++;
        if (e->joint == 1) {
            r->lock2_t = e->after.t;
            r->lock2_Hb = h_about_j1(p, &e->before);
            r->lock2_Ha = h_about_j1(p, &e->after);
            r->lock2_j1_free = !e->after.locked[0];
        } else {
            r->lock1_t = e->after.t;
            r->lock1_Hb = h_link2_about_j2(p, &e->before);
            r->lock1_Ha = h_link2_about_j2(p, &e->after);
            r->lock1_j2_free = !e->after.locked[1];
        }
    } else {
        if (r->n_mode_events < 16) {
            r->mode_t[r->n_mode_events] = e->after.t;
            r->mode_j[r->n_mode_events] = e->joint;
            r->mode_from[r->n_mode_events] = e->before.mode[e->joint];
            r->mode_to[r->n_mode_events] = e->after.mode[e->joint];
        }
        r->n_mode_events++;
    }
}

static int run(const rigid2_params *p, double t_end, double dt, rec *r, double lt[2], rigid2_stats *st)
{
    rec_init(r, p);
    return rigid2_run_ex(p, t_end, dt, on_sample, on_event, r, lt, st);
}

static const char *mode_name(int m)
{
    switch (m) {
    case RIGID2_SLIP_NEG: return "slip-";
    case RIGID2_STICK: return "stick";
    case RIGID2_SLIP_POS: return "slip+";
    default: return "locked";
    }
}

/* ---- checks --------------------------------------------------------------------------- */

/* Lock times at three tolerances.  Samples only every second so that the step sizes are
   chosen by the error control (and hmax), not by the output grid. */
static void lock_time_study(const char *name, int extra, double t_end)
{
    static const double tols[3] = {1e-8, 1e-9, 1e-10};
    double lt[3][2];
    char nm[96];
    int i, rc_all = 0;
    rec r;
    for (i = 0; i < 3; i++) {
        rigid2_params p;
        rigid2_stats st;
        int rc;
        rigid2_default_params(&p);
        if (extra) rigid2_add_extra_friction(&p);
        p.tol = tols[i];
        rc = run(&p, t_end, 1.0, &r, lt[i], &st);
        rc_all |= rc;
        printf("INFO %s tol=%g rc=%d lock1=%.12f s lock2=%.12f s steps=%ld rejected=%ld fevals=%ld events=%ld\n",
               name, tols[i], rc, lt[i][0], lt[i][1], st.steps, st.rejected, st.fevals, st.events);
        if (i == 2) {
            int k;
            printf("INFO %s tol=1e-10 q1,q2 (deg) t=1: %.6f %.6f  t=2: %.6f %.6f  t=3: %.6f %.6f  t=6: %.6f %.6f\n", name,
                   deg(r.q_at[0][0]), deg(r.q_at[0][1]), deg(r.q_at[1][0]), deg(r.q_at[1][1]),
                   deg(r.q_at[2][0]), deg(r.q_at[2][1]), deg(r.q_at[3][0]), deg(r.q_at[3][1]));
            for (k = 0; k < r.n_mode_events && k < 16; k++)
                printf("INFO %s mode event t=%.9f joint %d: %s -> %s\n", name, r.mode_t[k],
                       r.mode_j[k] + 1, mode_name(r.mode_from[k]), mode_name(r.mode_to[k]));
        }
    }
    sprintf(nm, "%s_lock_times_converged", name);
    {
        const double d1 = fabs(lt[0][0] - lt[2][0]), d2 = fabs(lt[0][1] - lt[2][1]);
        check(rc_all == 0 && lt[2][0] > 0.0 && lt[2][1] > 0.0 && d1 < 1e-6 && d2 < 1e-6, nm,
              "|dt_lock1(1e-8 vs 1e-10)|=%.3e |dt_lock2|=%.3e (lock1=%.9f)", d1, d2, lt[2][0]);
    }
    sprintf(nm, "%s_lock_order", name);
    check(lt[2][1] > 2.0 && lt[2][1] < 4.5 && lt[2][0] > lt[2][1], nm,
          "lock2=%.6f s first, lock1=%.6f s later (gap %.4f s)", lt[2][1], lt[2][0], lt[2][0] - lt[2][1]);
}

int main(void)
{
    rigid2_params p;
    rigid2_stats st;
    rec r;
    double lt[2];
    int rc;

    /* 1. lock times vs tolerance */
    lock_time_study("default", 0, 6.0);
    lock_time_study("extra_friction", 1, 10.0); /* joint 1 latches after 6 s */

    /* 2. energy balance and impact momentum, default case at tol 1e-10 */
    rigid2_default_params(&p);
    p.tol = 1e-10;
    rc = run(&p, 6.0, 0.001, &r, lt, &st);
    check(rc == 0 && r.order_ok && r.n_samples == 6001, "default_run_samples", "rc=%g samples=%g ordered=%g",
          (double)rc, (double)r.n_samples, (double)r.order_ok);
    check(r.max_bal_prelock < 1e-8, "energy_balance_before_first_lock",
          "max |ke+pe+wfric-E0|/E0 = %.3e (E0 = %.9f J, ke vs bodies %.1e)", r.max_bal_prelock, r.E0, r.max_ke_diff);
    check(r.max_bal_all < 1e-8, "energy_balance_incl_lock_losses",
          "max |ke+pe+wfric+wlock-E0|/E0 = %.3e over 0..6 s (%g lock events)", r.max_bal_all,
          (double)r.n_lock_events, 0.0);
    check(r.max_ke_diff < 1e-13, "kinetic_energy_matches_bodies", "max |ke_solver-ke_bodies|/E0 = %.3e",
          r.max_ke_diff, 0.0, 0.0);
    {
        const double d = fabs(r.lock2_Ha - r.lock2_Hb) / fabs(r.lock2_Hb);
        check(r.lock2_t > 0.0 && r.lock2_j1_free && d < 1e-12, "angular_momentum_j1_across_lock2",
              "t=%.9f H_before=%.12f rel change %.2e", r.lock2_t, r.lock2_Hb, d);
    }

    /* 3. joint 1 locks first (joint 2 lock disabled): link 2 momentum about joint 2 */
    rigid2_default_params(&p);
    p.lock[1] = -HUGE_VAL;
    rc = run(&p, 6.0, 0.01, &r, lt, &st);
    {
        const double d = fabs(r.lock1_Ha - r.lock1_Hb) / fabs(r.lock1_Hb);
        check(rc == 0 && r.lock1_t > 0.0 && r.lock1_j2_free && d < 1e-12, "link2_momentum_j2_across_lock1",
              "t=%.9f H_before=%.12f rel change %.2e", r.lock1_t, r.lock1_Hb, d);
        check(r.max_bal_all < 1e-8, "energy_balance_lock1_first", "max rel %.3e (wlock incl.)",
              r.max_bal_all, 0.0, 0.0);
    }

    /* 4. frictionless, springless, initial rates: energy and H about joint 1 conserved */
    rigid2_default_params(&p);
    p.k[0] = p.k[1] = 0.0;
    p.T[0] = p.T[1] = 0.0;
    p.lock[0] = HUGE_VAL;
    p.lock[1] = -HUGE_VAL;
    p.q0[0] = 0.3; p.q0[1] = 1.0;
    p.qd0[0] = 1.5; p.qd0[1] = -4.0;
    p.tol = 1e-10;
    rc = run(&p, 6.0, 0.01, &r, lt, &st);
    check(rc == 0 && r.max_bal_all < 1e-9 && r.max_h_drift < 1e-9, "free_conservation",
          "energy rel drift %.3e, H_j1 rel drift %.3e (E0=%.6f)", r.max_bal_all, r.max_h_drift, r.E0);

    /* 5. friction above the spring torques: nothing moves, ever */
    rigid2_default_params(&p);
    p.T[0] = 0.5;  /* spring torque at q1=0: 0.0789*300deg = 0.413 N m */
    p.T[1] = 0.35; /* spring torque at q2=180: 0.0768*240deg = 0.322 N m */
    rc = run(&p, 6.0, 0.01, &r, lt, &st);
    check(rc == 0 && r.qmax_move == 0.0 && lt[0] < 0.0 && lt[1] < 0.0, "stick_never_moves",
          "max |q-q0|+|qd| = %.3e, lock times %g %g", r.qmax_move, lt[0], lt[1]);

    /* 6. joint 1 held by friction while link 2 swings (stick with a varying reaction) */
    rigid2_default_params(&p);
    p.T[0] = 0.45;
    rc = run(&p, 6.0, 0.01, &r, lt, &st);
    printf("INFO stick_slip_mixed rc=%d lock1=%.9f lock2=%.9f events=%ld mode events=%d\n", rc, lt[0],
           lt[1], st.events, r.n_mode_events);
    {
        int k;
        for (k = 0; k < r.n_mode_events && k < 16; k++)
            printf("INFO stick_slip_mixed mode event t=%.9f joint %d: %s -> %s\n", r.mode_t[k],
                   r.mode_j[k] + 1, mode_name(r.mode_from[k]), mode_name(r.mode_to[k]));
    }
    check(rc == 0 && r.max_bal_all < 1e-8, "stick_slip_mixed_energy", "max rel %.3e, %g mode events",
          r.max_bal_all, (double)r.n_mode_events, 0.0);

    /* 7. timing of one default 6 s run */
    {
        static const double tols[2] = {1e-8, 1e-10};
        int i, n;
        for (i = 0; i < 2; i++) {
            clock_t c0 = clock();
            double sec;
            rigid2_default_params(&p);
            p.tol = tols[i];
            for (n = 0; n < 20; n++) rigid2_run_ex(&p, 6.0, 0.01, NULL, NULL, NULL, lt, &st);
            sec = (double)(clock() - c0) / CLOCKS_PER_SEC / 20.0;
            printf("INFO timing default 6 s run, dt_out 0.01, tol %g: %.3f ms (%ld steps, %ld fevals)\n",
                   tols[i], 1e3 * sec, st.steps, st.fevals);
        }
    }

    printf("%s: %d failure(s)\n", n_fail ? "FAILED" : "ALL PASSED", n_fail);
    return n_fail ? 1 : 0;
}
