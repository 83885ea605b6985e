/* Dynamics: conservation laws, energy balance, limit methods, locks, friction, damping. */
#include "../revjoint.h"
#include "../examples/scenes.h"
#include "rjt.h"
/* the library's default (its implementation is compiled once, without the macro) */
#ifndef RJ_IN_PLACE_NODES
#define RJ_IN_PLACE_NODES 400
#endif
#include <string.h>

static rj_model *build(rj_link_def *L, int nl, rj_joint_def *J, int nj, double dt)
{
    rj_scene_def sc = rj_default_scene_def();
    rj_model *m = NULL; rj_error err;
    sc.links = L; sc.link_count = nl; sc.joints = J; sc.joint_count = nj; sc.solver.dt = dt;
    if (rj_model_create(&sc, &m, &err, NULL) != RJ_OK) { printf("build failed: %s\n", err.msg); return NULL; }
    return m;
}

/* linear momentum of the whole model (a pinned node's copies each carry their own mass) */
static void momentum(const rj_model *m, const rj_state *s, double *px, double *py)
{
    int l, i;
    *px = 0; *py = 0;
    for (l = 0; l < rj_model_link_count(m); l++)
        for (i = 0; i < rj_link_node_count(m, l); i++) {
            double v[2], mm;
            rj_node_velocity(m, s, l, i, v);
            rj_node_mass(m, l, i, &mm, NULL);
            *px += mm * v[0]; *py += mm * v[1];
        }
}

/* free flexible two-link system, spinning, with a spring: energy conserved over 1e5
   steps. Leapfrog conserves a shadow energy; the error of the true energy is bounded and
   falls as dt^2, so the check runs three step sizes. */
static double energy_free_run(double frac, double *dt_used, int *ok)
{
    rj_link_def L[2]; rj_joint_def J[1]; rj_model *m; rj_state *s; rj_energy e;
    double E0, worst = 0, bound;
    long k;
    L[0] = rj_default_link_def(); L[1] = rj_default_link_def();
    L[0].height = L[1].height = 0.01; L[0].elements = L[1].elements = 8; L[0].omega = 2.0;
    J[0] = rj_default_joint_def(); J[0].body1 = 0; J[0].body2 = 1; J[0].angle0 = rj_rad(150); J[0].rate0 = 3.0;
    J[0].spring_k = 20.0; J[0].spring_free_angle = rj_rad(180);
    m = build(L, 2, J, 1, 0);
    bound = rj_model_dt_bound(m);
    rj_model_destroy(m, NULL);
    m = build(L, 2, J, 1, frac * bound);
    *dt_used = rj_model_dt(m);
    rj_state_create(m, &s, NULL);
    rj_step(m, s);
    rj_state_energy(m, s, &e);
    E0 = e.total;
    for (k = 1; k < 100000; k++) {
        if (rj_step(m, s) != RJ_OK) break;
        rj_state_energy(m, s, &e);
        if (fabs(e.total - E0) > worst) worst = fabs(e.total - E0);
    }
    *ok = k == 100000;
    rj_state_destroy(s, NULL); rj_model_destroy(m, NULL);
    return worst / E0;
}

static void test_energy_free(rjt_ctx *c)
{
    double e1, e2, e3, d1, d2, d3;
    int ok1, ok2, ok3;
    e1 = energy_free_run(0.45, &d1, &ok1);
    e2 = energy_free_run(0.225, &d2, &ok2);
    e3 = energy_free_run(0.1125, &d3, &ok3);
    rjt_check(c, ok1 && ok2 && ok3 && e2 < 1e-6, "free undamped flexible system: energy conserved to 1e-6 over 1e5 steps (dt = 0.225 x bound)",
              "max |E - E0|/E0 = %.3g at dt %.3g s; %.3g at %.3g s; %.3g at %.3g s", e2, d2, e1, d1, e3, d3);
    rjt_check(c, e1 / e2 > 3.2 && e1 / e2 < 4.8 && e2 / e3 > 3.2 && e2 / e3 < 4.8, "free energy error is bounded and second order in dt",
              "ratios %.2f, %.2f (4 = second order)", e1 / e2, e2 / e3);
}

/* pendulum on a ground joint with spring, damping and friction: the balance closes */
static void test_energy_balance(rjt_ctx *c)
{
    rj_link_def L[2]; rj_joint_def J[2]; rj_model *m; rj_state *s; rj_energy e;
    double E0 = 0, worst = 0;
    long k;
    L[0] = rj_default_link_def(); L[1] = rj_default_link_def();
    L[0].height = L[1].height = 0.02; L[0].elements = L[1].elements = 6; L[1].tip_mass = 0.5;
    J[0] = rj_default_joint_def(); J[0].body1 = -1; J[0].body2 = 0; J[0].angle0 = 0.3; J[0].rate0 = 2.0;
    J[0].spring_k = 50.0; J[0].spring_free_angle = 0; J[0].damping = 0.5; J[0].friction = 1.0;
    J[1] = rj_default_joint_def(); J[1].body1 = 0; J[1].body2 = 1; J[1].angle0 = rj_rad(200); J[1].rate0 = -4.0;
    J[1].spring_k = 20.0; J[1].spring_free_angle = rj_rad(180); J[1].damping = 0.2; J[1].friction = 0.3;
    m = build(L, 2, J, 2, 0);
    rj_state_create(m, &s, NULL);
    rj_state_energy(m, s, &e);
    E0 = e.total;
    for (k = 0; k < 100000; k++) {
        if (rj_step(m, s) != RJ_OK) break;
        rj_state_energy(m, s, &e);
        if (fabs(e.balance) > worst) worst = fabs(e.balance);
    }
    rj_state_energy(m, s, &e);
    rjt_check(c, k == 100000 && worst / E0 < 1e-6 && e.lost_damping > 0.05 * E0 && e.lost_friction > 0.05 * E0,
              "spring + damping + friction: energy balance closes to 1e-6 of E0", "max |balance| / E0 = %.3g; lost to damping %.4g J, friction %.4g J of E0 %.4g J",
              worst / E0, e.lost_damping, e.lost_friction, E0);
    rj_state_destroy(s, NULL); rj_model_destroy(m, NULL);
}

/* free flying two links hitting a limit with the adaptive method: linear momentum conserved
   to round-off (joint torques are pure torques; beam forces sum to zero) */
static void test_momentum_free(rjt_ctx *c)
{
    rj_link_def L[2]; rj_joint_def J[1]; rj_model *m; rj_state *s;
    double px0, py0, px1, py1, wp = 0;
    int k, hit = 0;
    L[0] = rj_default_link_def(); L[1] = rj_default_link_def();
    L[0].height = L[1].height = 0.02; L[0].elements = L[1].elements = 5; L[0].vx = 1.0; L[0].omega = 0.5;
    J[0] = rj_default_joint_def(); J[0].body1 = 0; J[0].body2 = 1; J[0].angle0 = rj_rad(180); J[0].rate0 = -20;
    J[0].has_reverse = 1; J[0].reverse = rj_rad(170); J[0].has_forward = 1; J[0].forward = rj_rad(190);
    m = build(L, 2, J, 1, 0);
    rj_state_create(m, &s, NULL);
    momentum(m, s, &px0, &py0);
    for (k = 0; k < 20000; k++) {
        rj_step(m, s);
        if (rj_joint_flag(m, s, 0)) hit++;
        momentum(m, s, &px1, &py1);
        if (fabs(px1 - px0) + fabs(py1 - py0) > wp) wp = fabs(px1 - px0) + fabs(py1 - py0);
    }
    rjt_check(c, hit > 0 && wp < 1e-11 * (1 + fabs(px0)), "adaptive limit contacts conserve linear momentum", "%d contact steps, max drift %.3g kg m/s", hit, wp);
    rj_state_destroy(s, NULL); rj_model_destroy(m, NULL);
}

/* adaptive stiffness removes a penetration in one step (Eq 21): at the step that detects
   the contact, the rate changes by exactly -p / dt (a stiff, short link against a fixed
   body, coming in slowly, so that the link's own elastic forces are negligible) */
static void test_adaptive_one_step(rjt_ctx *c)
{
    rj_link_def L[2]; rj_joint_def J[1]; rj_model *m; rj_state *s;
    double p = 0, r0 = 0, r1 = 0, dtm;
    int k;
    L[0] = rj_default_link_def(); L[1] = rj_default_link_def();
    L[0].length = L[1].length = 0.1; L[0].elements = L[1].elements = 1; L[0].height = L[1].height = 0.05;
    L[0].root = RJ_ROOT_FIXED; L[0].x = -0.1;
    J[0] = rj_default_joint_def(); J[0].body1 = 0; J[0].body2 = 1; J[0].angle0 = rj_rad(176.2); J[0].rate0 = -0.5;
    J[0].has_reverse = 1; J[0].reverse = rj_rad(176); J[0].method = RJ_METHOD_ADAPTIVE;
    m = build(L, 2, J, 1, 0);
    rj_state_create(m, &s, NULL);
    dtm = rj_model_dt(m);
    for (k = 0; k < 100000; k++) {
        double run = rj_joint_theta_running(m, s, 0);
        r0 = rj_joint_rate(m, s, 0);
        rj_step(m, s);
        if (rj_joint_flag(m, s, 0) != RJ_FREE) { p = rj_rad(176) - run; r1 = rj_joint_rate(m, s, 0); break; }
    }
    rjt_check(c, p > 0 && fabs((r1 - r0) * dtm - p) < 1e-3 * p, "adaptive stiffness: the contact step's rate change removes the penetration in one step",
              "penetration %.4g rad, rate change x dt = %.4g rad (after %d steps)", p, (r1 - r0) * dtm, k);
    rj_state_destroy(s, NULL); rj_model_destroy(m, NULL);
}

/* a lock never releases, even when a strong spring pulls the joint back out */
static void test_lock(rjt_ctx *c)
{
    rj_link_def L[1]; rj_joint_def J[1]; rj_model *m; rj_state *s;
    int k, m_ok = 1, f, method;
    static const char *names[] = { "penalty", "adaptive", "momentum", "forced", "energy" };
    for (method = 0; method < 5; method++) {
        double maxp = 0, t_lock;
        char name[96];
        L[0] = rj_default_link_def(); L[0].height = 0.02; L[0].elements = 4;
        J[0] = rj_default_joint_def(); J[0].body1 = -1; J[0].body2 = 0; J[0].angle0 = 0; J[0].rate0 = 3.0;
        J[0].has_forward = 1; J[0].forward = rj_rad(30); J[0].lock = 1; J[0].method = method; J[0].penalty_k = 1e5; J[0].rate0 = 40;
        J[0].spring_k = 300; J[0].spring_free_angle = rj_rad(-90); /* pulls back out of the lock */
        m = build(L, 1, J, 1, 0);
        rj_state_create(m, &s, NULL);
        m_ok = 1;
        for (k = 0; k < 40000; k++) {
            rj_step(m, s);
            f = rj_joint_flag(m, s, 0);
            if (rj_state_time(s) > 0.3 && f != RJ_LOCKED) m_ok = 0;
            if (f == RJ_LOCKED && fabs(rj_joint_penetration(m, s, 0)) > maxp) maxp = fabs(rj_joint_penetration(m, s, 0));
        }
        t_lock = rj_joint_event_time(m, s, 0);
        snprintf(name, sizeof name, "lock never releases (%s)", names[method]);
        rjt_check(c, m_ok && t_lock > 0 && t_lock < 0.3, name, "locked at %.5f s, flag %d after %d steps, max |p| %.3g rad", t_lock, rj_joint_flag(m, s, 0), k, maxp);
        rj_state_destroy(s, NULL); rj_model_destroy(m, NULL);
    }
}

/* friction holds a joint still under a torque below T_f and lets it slip above */
static void test_friction(rjt_ctx *c)
{
    rj_link_def L[1]; rj_joint_def J[1]; rj_model *m; rj_state *s;
    double th0, drift = 0, tau;
    int k;
    for (k = 0; k < 2; k++) {
        double frac = k == 0 ? 0.9 : 1.1;
        int i;
        L[0] = rj_default_link_def(); L[0].height = 0.02; L[0].elements = 6; L[0].tip_mass = 1;
        J[0] = rj_default_joint_def(); J[0].body1 = -1; J[0].body2 = 0; J[0].angle0 = 0;
        J[0].spring_k = 10.0; J[0].spring_free_angle = 1.0;   /* torque 10 N m on body 2 */
        J[0].friction = 10.0 / frac;
        m = build(L, 1, J, 1, 0);
        rj_state_create(m, &s, NULL);
        th0 = rj_joint_theta_running(m, s, 0);
        for (i = 0; i < (k == 0 ? 100000 : 200); i++) rj_step(m, s);
        drift = fabs(rj_joint_theta_running(m, s, 0) - th0);
        tau = rj_joint_torque(m, s, 0, RJ_TORQUE_FRICTION);
        if (k == 0) rjt_check(c, drift < 1e-9, "friction holds under 0.9 T_f (no creep over 1e5 steps)", "drift %.3g rad, friction torque %.6g N m", drift, tau);
        else rjt_check(c, drift > 1e-6 && fabs(fabs(tau) - J[0].friction) < 1e-9, "friction slips under 1.1 T_f at exactly T_f", "moved %.4g rad, friction torque %.9g N m (T_f %.9g)", drift, tau, J[0].friction);
        rj_state_destroy(s, NULL); rj_model_destroy(m, NULL);
    }
}

/* Eq 27: damping torque = -C theta_dot on body 2 */
static void test_damping(rjt_ctx *c)
{
    rj_link_def L[1]; rj_joint_def J[1]; rj_model *m; rj_state *s;
    double r0;
    L[0] = rj_default_link_def(); L[0].height = 0.02; L[0].elements = 4;
    J[0] = rj_default_joint_def(); J[0].body1 = -1; J[0].body2 = 0; J[0].angle0 = 0; J[0].rate0 = 2.5; J[0].damping = 0.7;
    m = build(L, 1, J, 1, 0);
    rj_state_create(m, &s, NULL);
    r0 = rj_joint_rate(m, s, 0);
    rj_step(m, s);
    rjt_near(c, "Eq 27: damping torque = -C theta_dot (rate at the step's start)", rj_joint_torque(m, s, 0, RJ_TORQUE_DAMPING), -0.7 * r0, 1e-12);
    rj_state_destroy(s, NULL); rj_model_destroy(m, NULL);
}

/* a spinning link crosses the 0/360 seam many times: the running angle is continuous and
   the wrapped theta stays in [0, 2 pi) */
static void test_seam(rjt_ctx *c)
{
    rj_link_def L[1]; rj_joint_def J[1]; rj_model *m; rj_state *s;
    double prev, jump = 0, tmin = 10, tmax = -10;
    int k;
    L[0] = rj_default_link_def(); L[0].height = 0.02; L[0].elements = 4;
    J[0] = rj_default_joint_def(); J[0].body1 = -1; J[0].body2 = 0; J[0].angle0 = rj_rad(350); J[0].rate0 = 40;
    m = build(L, 1, J, 1, 0);
    rj_state_create(m, &s, NULL);
    prev = rj_joint_theta_running(m, s, 0);
    for (k = 0; k < 50000; k++) {
        double th, w;
        rj_step(m, s);
        th = rj_joint_theta_running(m, s, 0); w = rj_joint_theta(m, s, 0);
        if (fabs(th - prev) > jump) jump = fabs(th - prev);
        if (w < tmin) tmin = w;
        if (w > tmax) tmax = w;
        prev = th;
    }
    rjt_check(c, jump < 40 * rj_model_dt(m) * 1.01 && rj_joint_theta_running(m, s, 0) > rj_rad(350) + 2 * 6.283 && tmin >= 0 && tmax < 6.2832,
              "running angle continuous across the 0/360 seam", "%.2f turns, largest step change %.3g rad (rate x dt = %.3g), wrapped in [%.4f, %.4f]",
              (rj_joint_theta_running(m, s, 0) - rj_rad(350)) / 6.2832, jump, 40 * rj_model_dt(m), tmin, tmax);
    rj_state_destroy(s, NULL); rj_model_destroy(m, NULL);
}


/* inextensible links: element lengths held, energy conserved, a step limited by bending */
static void test_inextensible(rjt_ctx *c)
{
    rj_link_def L[2]; rj_joint_def J[1]; rj_model *m, *mf; rj_state *s; rj_energy e;
    double E0 = 0, worst = 0, lerr = 0;
    int k, l, i;
    L[0] = rj_default_link_def(); L[1] = rj_default_link_def();
    L[0].height = L[1].height = 0.01; L[0].elements = L[1].elements = 8; L[0].omega = 2.0;
    J[0] = rj_default_joint_def(); J[0].body1 = 0; J[0].body2 = 1; J[0].angle0 = rj_rad(150); J[0].rate0 = 3.0;
    J[0].spring_k = 20.0; J[0].spring_free_angle = rj_rad(180);
    mf = build(L, 2, J, 1, 0);
    L[0].fidelity = L[1].fidelity = RJ_LINK_INEXTENSIBLE;
    m = build(L, 2, J, 1, 0);
    rjt_check(c, rj_model_dt_bound(m) > 3 * rj_model_dt_bound(mf), "inextensible links: the bound is set by bending, not the axial wave",
              "bound %.4g s against %.4g s flexible (x %.1f)", rj_model_dt_bound(m), rj_model_dt_bound(mf), rj_model_dt_bound(m) / rj_model_dt_bound(mf));
    rj_state_create(m, &s, NULL);
    for (k = 0; k < 20000; k++) {
        rj_step(m, s);
        rj_state_energy(m, s, &e);
        if (k == 0) E0 = e.total;
        else if (fabs(e.total - E0) > worst) worst = fabs(e.total - E0);
    }
    for (l = 0; l < 2; l++) for (i = 0; i < 8; i++) {
        double a[2], b[2], len;
        rj_node_position(m, s, l, i, a); rj_node_position(m, s, l, i + 1, b);
        len = sqrt((b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]));
        if (fabs(len / 0.125 - 1) > lerr) lerr = fabs(len / 0.125 - 1);
    }
    rjt_check(c, lerr < 1e-9, "inextensible links keep their element lengths (2e4 steps)", "max |l / l0 - 1| = %.3g after %.3g s", lerr, rj_state_time(s));
    rjt_check(c, worst / E0 < 1e-5, "inextensible links: energy conserved (constraint forces do no work)", "max |E - E0| / E0 = %.3g over 2e4 steps at dt %.3g s", worst / E0, rj_model_dt(m));
    rj_state_destroy(s, NULL); rj_model_destroy(m, NULL); rj_model_destroy(mf, NULL);
}


/* solver.energy_every K: the same bits as K = 1 in everything but when the energy accounts
   are taken. rj_run takes them before every sample and at its end, so its sampled energy
   histories and the saved state bytes must equal K = 1's exactly; between them rj_step
   keeps the last ones (rj_state_energy_time says when); a blow-up is still caught. */
typedef struct ee_rec { int n; double v[64][8]; } ee_rec;
static int ee_sample(const rj_model *m, const rj_state *s, void *user)
{
    ee_rec *r = (ee_rec *)user;
    rj_energy e;
    double xy[2];
    if (r->n >= 64) return 0;
    rj_state_energy(m, s, &e);
    rj_node_position(m, s, 1, rj_link_node_count(m, 1) - 1, xy);
    r->v[r->n][0] = e.kinetic; r->v[r->n][1] = e.strain; r->v[r->n][2] = e.spring; r->v[r->n][3] = e.total;
    r->v[r->n][4] = rj_state_energy_time(s); r->v[r->n][5] = xy[0]; r->v[r->n][6] = xy[1]; r->v[r->n][7] = rj_joint_theta_running(m, s, 1);
    r->n++;
    return 0;
}
static int ee_run(int fidelity, int every, ee_rec *rec, unsigned char *bytes, size_t cap, size_t *nb)
{
    deploy_opts o = deploy_default_opts();
    rj_link_def L[2]; rj_joint_def J[2]; rj_scene_def sc;
    rj_model *m; rj_state *s; rj_error err;
    int ok;
    o.energy_every = every;
    deploy_scene(&o, L, J, &sc);
    J[1].penalty_k = 1015.0;
    L[0].fidelity = L[1].fidelity = fidelity;
    if (rj_model_create(&sc, &m, &err, NULL) != RJ_OK) { printf("energy_every: %s\n", err.msg); return 0; }
    if (rj_state_create(m, &s, NULL) != RJ_OK) { rj_model_destroy(m, NULL); return 0; }
    rec->n = 0;
    ok = rj_run(m, s, 0.3005, 0.01, ee_sample, rec) == RJ_OK;
    *nb = rj_state_save(m, s, bytes, cap);
    rj_state_destroy(s, NULL); rj_model_destroy(m, NULL);
    return ok && *nb <= cap;
}
static void test_energy_every(rjt_ctx *c)
{
    static unsigned char b1[1 << 16], b16[1 << 16];
    static ee_rec r1, r16;
    static const int fid[3] = { RJ_LINK_FLEXIBLE, RJ_LINK_INEXTENSIBLE, RJ_LINK_RIGID };
    static const char *const fname[3] = { "flexible links", "inextensible links", "rigid links (joint coordinates)" };
    int f, k;
    for (f = 0; f < 3; f++) {
        size_t n1 = 0, n16 = 0;
        int ok = ee_run(fid[f], 1, &r1, b1, sizeof b1, &n1) && ee_run(fid[f], 16, &r16, b16, sizeof b16, &n16);
        const char *what = fname[f];
        char name[160];
        snprintf(name, sizeof name, "energy_every 16, %s: rj_run's %d sampled energies and tip positions equal K = 1's bit for bit", what, r1.n);
        rjt_check(c, ok && r1.n == 31 && r16.n == r1.n && memcmp(r1.v, r16.v, sizeof r1.v[0] * (size_t)r1.n) == 0, name,
                  "%d and %d samples, first kinetic %.17g vs %.17g", r1.n, r16.n, r1.v[1][0], r16.v[1][0]);
        snprintf(name, sizeof name, "energy_every 16, %s: the saved state after rj_run equals K = 1's byte for byte", what);
        rjt_check(c, ok && n1 == n16 && memcmp(b1, b16, n1) == 0, name, "%zu and %zu bytes", n1, n16);
    }
    {   /* rj_step: the accounts of every 16th step, kept in between, equal K = 1's then */
        deploy_opts o = deploy_default_opts();
        rj_model *m1 = NULL, *m16 = NULL; rj_state *s1 = NULL, *s16 = NULL; rj_error err;
        rj_energy e1, e16;
        int bad = 0, steps = 0;
        double lag_max = 0;
        deploy_build(&o, &m1, &err);
        o.energy_every = 16;
        deploy_build(&o, &m16, &err);
        rj_state_create(m1, &s1, NULL); rj_state_create(m16, &s16, NULL);
        for (k = 0; k < 200 && m1 && m16; k++) {
            if (rj_step(m1, s1) != RJ_OK || rj_step(m16, s16) != RJ_OK) { bad++; break; }
            steps++;
            rj_state_energy(m16, s16, &e16);
            if (k % 16 == 0) {   /* steps 0, 16, 32, ... took them */
                rj_state_energy(m1, s1, &e1);
                if (memcmp(&e1, &e16, sizeof e1) != 0 || rj_state_energy_time(s1) != rj_state_energy_time(s16)) bad++;
            }
            if (rj_state_time(s16) - rj_state_energy_time(s16) > lag_max) lag_max = rj_state_time(s16) - rj_state_energy_time(s16);
            if (rj_node_rotation(m1, s1, 1, 5) != rj_node_rotation(m16, s16, 1, 5)) bad++;
        }
        rjt_check(c, bad == 0 && steps == 200 && fabs(lag_max - 16 * rj_model_dt(m16)) < 1e-12, "energy_every 16, rj_step: accounts of every 16th step equal K = 1's, kept in between (at most 16 steps old), positions identical",
                  "%d mismatches in %d steps, largest lag %.3g s (16 dt = %.3g s)", bad, steps, lag_max, m16 ? 16 * rj_model_dt(m16) : 0.0);
        rj_state_destroy(s1, NULL); rj_state_destroy(s16, NULL); rj_model_destroy(m1, NULL); rj_model_destroy(m16, NULL);
    }
    {   /* a step above the bound still stops as a blow-up, at most 15 steps after K = 1 */
        long at[2] = { -1, -1 };
        int i;
        for (i = 0; i < 2; i++) {
            rj_link_def L = rj_default_link_def();
            rj_scene_def sc = rj_default_scene_def();
            rj_model *m = NULL; rj_state *s = NULL; rj_error err;
            rj_result r = RJ_OK;
            L.height = 0.01; L.elements = 20; L.omega = 1.0;
            sc.links = &L; sc.link_count = 1; sc.solver.energy_every = i ? 16 : 1;
            if (rj_model_create(&sc, &m, &err, NULL) != RJ_OK) break;
            sc.solver.dt = 1.2 * rj_model_dt_bound(m); sc.solver.allow_unstable = 1;
            rj_model_destroy(m, NULL);
            if (rj_model_create(&sc, &m, &err, NULL) != RJ_OK) break;
            rj_state_create(m, &s, NULL);
            for (k = 0; k < 100000 && r == RJ_OK; k++) r = rj_step(m, s);
            if (r == RJ_ERR_BLOWUP) at[i] = rj_state_steps(s);
            rj_state_destroy(s, NULL); rj_model_destroy(m, NULL);
        }
        rjt_check(c, at[0] > 0 && at[1] >= at[0] && at[1] <= at[0] + 15, "energy_every 16: a step 1.2 x the bound still stops with RJ_ERR_BLOWUP, at most 15 steps after K = 1",
                  "K = 1 at step %ld, K = 16 at step %ld", at[0], at[1]);
    }
}

/* solver.in_place: stepping in place gives the double-buffered step's bits, and a step that
   fails leaves the state as it was. In place keeps a copy of the state at most 64 steps old
   and takes the steps since it again after a failure, with rj_run's energy requests; the
   checks below fail without that (the saved bytes would hold the failed step's nodes). */
static int ip_sample(const rj_model *m, const rj_state *s, void *u) { (void)m; (void)s; (void)u; return 0; }
static rj_result ip_run(const rj_scene_def *sc0, int in_place, double t_end, double sample_dt, unsigned char *b, size_t cap, size_t *nb,
                        size_t *ssize, char *err_out, size_t errn)
{
    rj_scene_def sc = *sc0;
    rj_model *m = NULL; rj_state *s = NULL; rj_error err;
    rj_result r;
    sc.solver.in_place = in_place;
    if (rj_model_create(&sc, &m, &err, NULL) != RJ_OK) { printf("in_place: %s\n", err.msg); return RJ_ERR_INVALID; }
    if (rj_state_create(m, &s, NULL) != RJ_OK) { rj_model_destroy(m, NULL); return RJ_ERR_NOMEM; }
    *ssize = rj_state_size(m);
    r = rj_run(m, s, t_end, sample_dt, ip_sample, NULL);
    *nb = rj_state_save(m, s, b, cap);
    snprintf(err_out, errn, "%s", rj_state_error(s));
    rj_state_destroy(s, NULL); rj_model_destroy(m, NULL);
    return r;
}
static void test_in_place(rjt_ctx *c)
{
    static unsigned char b0[1 << 17], b1[1 << 17], b2[1 << 17];
    char e0[640], e1[640], e2[640], name[200];
    int k;
    {   /* the deployment with 200 elements per link (402 nodes: AUTO steps in place), rj_run
           with samples and energy_every 16 */
        deploy_opts o = deploy_default_opts();
        rj_link_def L[2]; rj_joint_def J[2]; rj_scene_def sc;
        size_t n0 = 0, n1 = 0, n2 = 0, z0 = 0, z1 = 0, z2 = 0;
        rj_result r0, r1, r2;
        o.elements = 200; o.dt = 0; o.energy_every = 16;
        deploy_scene(&o, L, J, &sc);
        J[1].penalty_k = 1015.0;
        r0 = ip_run(&sc, RJ_IN_PLACE_OFF, 0.02, 0.001, b0, sizeof b0, &n0, &z0, e0, sizeof e0);
        r1 = ip_run(&sc, RJ_IN_PLACE_AUTO, 0.02, 0.001, b1, sizeof b1, &n1, &z1, e1, sizeof e1);
        r2 = ip_run(&sc, RJ_IN_PLACE_ON, 0.02, 0.001, b2, sizeof b2, &n2, &z2, e2, sizeof e2);
        rjt_check(c, r0 == RJ_OK && r1 == RJ_OK && r2 == RJ_OK && n0 == n1 && n0 == n2 && n0 <= sizeof b0 && memcmp(b0, b1, n0) == 0 && memcmp(b0, b2, n0) == 0 && z1 > z0 && z2 == z1,
                  "in place: the deployment at 200 el/link (402 nodes) after rj_run with samples saves the same bytes as double-buffered, AUTO and ON alike",
                  "%s / %s / %s, %zu bytes; state %zu bytes double-buffered, %zu in place (a third frame)", rj_result_str(r0), rj_result_str(r1), rj_result_str(r2), n0, z0, z1);
        o.elements = 10;
        deploy_scene(&o, L, J, &sc);
        J[1].penalty_k = 1015.0;
        r0 = ip_run(&sc, RJ_IN_PLACE_OFF, 0.02, 0.001, b0, sizeof b0, &n0, &z0, e0, sizeof e0);
        r1 = ip_run(&sc, RJ_IN_PLACE_AUTO, 0.02, 0.001, b1, sizeof b1, &n1, &z1, e1, sizeof e1);
        /* (a build with -DRJ_IN_PLACE_NODES=0 steps it in place: then the third frame) */
        rjt_check(c, r0 == RJ_OK && r1 == RJ_OK && (RJ_IN_PLACE_NODES > 22 ? z1 == z0 : z1 > z0) && n0 == n1 && memcmp(b0, b1, n0) == 0,
                  "in place: AUTO leaves a 22-node model double-buffered below RJ_IN_PLACE_NODES (no third frame), the same bytes", "state %zu and %zu bytes; RJ_IN_PLACE_NODES %d", z0, z1, RJ_IN_PLACE_NODES);
    }
    /* a free link of 300 elements above its stability bound: the step that blows up, at
       several distances from the kept copy */
    {
        static const double f[4] = { 1.05, 1.2, 1.6, 3.0 };
        int fi, far = 0;
        for (fi = 0; fi < 4; fi++) {
            rj_link_def L = rj_default_link_def();
            rj_scene_def sc = rj_default_scene_def();
            rj_model *m = NULL, *mo = NULL; rj_state *s = NULL, *keep = NULL, *so = NULL; rj_error err;
            rj_result r = RJ_OK, ro = RJ_OK;
            long at = -1, ato = -1;
            size_t n = 0, nk = 0;
            int intact = 0, same = 0;
            L.height = 0.01; L.elements = 300; L.omega = 1.0;
            sc.links = &L; sc.link_count = 1;
            if (rj_model_create(&sc, &m, &err, NULL) != RJ_OK) break;
            sc.solver.dt = f[fi] * rj_model_dt_bound(m); sc.solver.allow_unstable = 1;
            rj_model_destroy(m, NULL);
            sc.solver.in_place = RJ_IN_PLACE_ON;
            if (rj_model_create(&sc, &m, &err, NULL) != RJ_OK) break;
            sc.solver.in_place = RJ_IN_PLACE_OFF;
            if (rj_model_create(&sc, &mo, &err, NULL) != RJ_OK) { rj_model_destroy(m, NULL); break; }
            rj_state_create(m, &s, NULL); rj_state_create(m, &keep, NULL); rj_state_create(mo, &so, NULL);
            for (k = 0; k < 100000 && r == RJ_OK; k++) { rj_state_copy(m, keep, s); r = rj_step(m, s); }
            for (k = 0; k < 100000 && ro == RJ_OK; k++) ro = rj_step(mo, so);
            if (r != RJ_OK) at = rj_state_steps(s);
            if (ro != RJ_OK) ato = rj_state_steps(so);
            n = rj_state_save(m, s, b0, sizeof b0); nk = rj_state_save(m, keep, b1, sizeof b1);
            intact = n == nk && n <= sizeof b0 && memcmp(b0, b1, n) == 0;
            rj_state_save(mo, so, b2, sizeof b2);
            same = intact && memcmp(b0, b2, n) == 0 && strcmp(rj_state_error(s), rj_state_error(so)) == 0;
            if (at >= 64) far = 1;
            snprintf(name, sizeof name, "in place: dt %.2f x the bound, the failed step leaves the state as it was, as double-buffered", f[fi]);
            rjt_check(c, r == RJ_ERR_BLOWUP && ro == r && at == ato && intact && same, name,
                      "%s at step %ld (double-buffered %s at %ld), state %s, %s: \"%s\"", rj_result_str(r), at, rj_result_str(ro), ato,
                      intact ? "intact" : "CHANGED", same ? "the same bytes and message" : "DIFFERENT from double-buffered", rj_state_error(s));
            rj_state_destroy(s, NULL); rj_state_destroy(keep, NULL); rj_state_destroy(so, NULL); rj_model_destroy(m, NULL); rj_model_destroy(mo, NULL);
        }
        rjt_check(c, far, "in place: some blow-up above comes 64 or more steps after the start (the kept copy was renewed)", "%s", far ? "yes" : "no");
    }
    {   /* rj_run with samples every 3 steps and energy_every 1000: the steps taken again after
           the failure must repeat rj_run's energy requests (the accounts are part of the state) */
        rj_link_def L = rj_default_link_def();
        rj_scene_def sc = rj_default_scene_def();
        rj_model *m = NULL; rj_error err;
        size_t n0 = 0, n2 = 0, z0, z2;
        rj_result r0, r2;
        L.height = 0.01; L.elements = 300; L.omega = 1.0;
        sc.links = &L; sc.link_count = 1; sc.solver.energy_every = 1000;
        if (rj_model_create(&sc, &m, &err, NULL) == RJ_OK) {
            sc.solver.dt = 1.05 * rj_model_dt_bound(m); sc.solver.allow_unstable = 1;
            rj_model_destroy(m, NULL);
            r0 = ip_run(&sc, RJ_IN_PLACE_OFF, 1.0, 3 * sc.solver.dt, b0, sizeof b0, &n0, &z0, e0, sizeof e0);
            r2 = ip_run(&sc, RJ_IN_PLACE_ON, 1.0, 3 * sc.solver.dt, b2, sizeof b2, &n2, &z2, e2, sizeof e2);
            rjt_check(c, r0 == RJ_ERR_BLOWUP && r2 == r0 && n0 == n2 && n0 <= sizeof b0 && memcmp(b0, b2, n0) == 0 && strcmp(e0, e2) == 0,
                      "in place: rj_run (samples every 3 steps, energy_every 1000) stops at the same blow-up with the same state bytes as double-buffered",
                      "%s / %s: \"%s\"", rj_result_str(r0), rj_result_str(r2), e2);
        }
    }
}

int main(void)
{
    rjt_ctx c = { 0, 0 };
    test_energy_free(&c);
    test_energy_balance(&c);
    test_momentum_free(&c);
    test_adaptive_one_step(&c);
    test_lock(&c);
    test_friction(&c);
    test_damping(&c);
    test_seam(&c);
    test_inextensible(&c);
    test_energy_every(&c);
    test_in_place(&c);
    return rjt_summary(&c, "test_dynamics");
}
