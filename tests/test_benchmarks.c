/* The paper's two benchmarks (secs. 4 and 5): what physics and the paper let us assert. */
#include "../revjoint.h"
#include "../examples/scenes.h"
#include "../examples/rigid2.h"
#include "rjt.h"
#include <stdlib.h>
#include <string.h>

static const char *mname[] = { "penalty", "adaptive", "momentum", "forced", "energy" };

typedef struct impact_result { double contact, release, peak, evib, wrigid; int ok, contacts, prev_flag; } impact_result;

/* counts the joint's contacts (a free joint that meets its limit) at every step */
static int count_contacts(const rj_model *m, const rj_state *s, void *user)
{
    impact_result *r = (impact_result *)user;
    const int flag = rj_joint_flag(m, s, 0);
    if (flag != RJ_FREE && r->prev_flag == RJ_FREE) r->contacts++;
    r->prev_flag = flag;
    return 0;
}


static impact_result impact_run(const impact_opts *o, double t_end)
{
    rj_link_def L[2]; rj_joint_def J; rj_scene_def sc; rj_model *m = NULL; rj_state *s = NULL; rj_error err;
    impact_result r;
    memset(&r, 0, sizeof r);
    impact_scene(o, L, &J, &sc);
    if (rj_model_create(&sc, &m, &err, NULL) != RJ_OK) { printf("  (%s)\n", err.msg); return r; }
    rj_state_create(m, &s, NULL);
    r.ok = rj_run(m, s, t_end, 0, count_contacts, &r) == RJ_OK;
    r.contact = rj_joint_event_time(m, s, 0); r.release = rj_joint_release_time(m, s, 0); r.peak = rj_joint_peak_penetration(m, s, 0);
    impact_rigid_part(m, s, &r.wrigid, &r.evib);
    rj_state_destroy(s, NULL); rj_model_destroy(m, NULL);
    return r;
}

static void test_impact(rjt_ctx *c)
{
    impact_opts o = impact_default_opts();
    rj_link_def L[2]; rj_joint_def J; rj_scene_def sc; rj_model *m = NULL; rj_state *s = NULL; rj_error err;
    double worst = 0, th0, w0, best_k = 0, best_e = 1e300, best_peak = 0, K;
    impact_result ad, r12, r13, mom[3];
    int k, steps = 0;
    /* before contact theta follows theta_0 + theta_dot_0 t */
    impact_scene(&o, L, &J, &sc);
    rj_model_create(&sc, &m, &err, NULL);
    rj_state_create(m, &s, NULL);
    th0 = rj_joint_theta_running(m, s, 0); w0 = o.rate0;
    for (;;) {
        double t, dev;
        rj_step(m, s);
        if (rj_joint_flag(m, s, 0) != RJ_FREE) break;
        t = rj_state_time(s);
        dev = fabs(rj_joint_theta_running(m, s, 0) - (th0 + w0 * t));
        if (dev > worst) worst = dev;
        steps++;
    }
    rjt_check(c, worst < 1e-6 && steps > 2000, "impact: before contact theta = theta_0 + theta_dot_0 t to 1e-6 rad", "max deviation %.3g rad over %d steps (contact at %.4f ms; t_L = 4 deg / 10 rad/s = %.4f ms)",
              worst, steps, 1e3 * rj_state_time(s), 1e3 * rj_rad(4) / 10);
    rj_state_destroy(s, NULL); rj_model_destroy(m, NULL);

    /* momentum balance (Eqs 23-24) in a free two-link system: the jumps keep I1 w1 + I2 w2,
       every other force is internal, so the total angular momentum sum m x^{n+1} x v^{n+1/2}
       + sum J w^{n+1/2} stays constant to round-off through the contacts */
    {
        rj_link_def L2[2]; rj_joint_def J2; rj_model *mm; rj_state *ss; double L0 = 0, drift = 0; int contacts = 0;
        L2[0] = rj_default_link_def(); L2[1] = rj_default_link_def();
        L2[0].height = L2[1].height = 0.05; L2[0].elements = L2[1].elements = 6; L2[0].x = -1; L2[0].omega = 1;
        J2 = rj_default_joint_def(); J2.body1 = 0; J2.body2 = 1; J2.rate0 = -12; J2.has_reverse = 1; J2.reverse = rj_rad(176);
        J2.method = RJ_METHOD_MOMENTUM; J2.restitution = 0.4;
        sc = rj_default_scene_def(); sc.links = L2; sc.link_count = 2; sc.joints = &J2; sc.joint_count = 1;
        rj_model_create(&sc, &mm, &err, NULL);
        rj_state_create(mm, &ss, NULL);
        for (k = 0; k < 20000; k++) {
            double Lz = 0, x[2], v[2], ms, Jr;
            int l, i;
            rj_step(mm, ss);
            if (rj_joint_flag(mm, ss, 0) != RJ_FREE) contacts++;
            for (l = 0; l < 2; l++) for (i = 0; i < rj_link_node_count(mm, l); i++) {
                rj_node_position(mm, ss, l, i, x); rj_node_velocity(mm, ss, l, i, v); rj_node_mass(mm, l, i, &ms, &Jr);
                Lz += ms * (x[0] * v[1] - x[1] * v[0]) + Jr * rj_node_rate(mm, ss, l, i);
            }
            if (k == 0) L0 = Lz;
            else if (fabs(Lz - L0) > drift) drift = fabs(Lz - L0);
        }
        rjt_check(c, contacts > 0 && drift < 1e-12 * fabs(L0), "momentum method (e = 0.4): total angular momentum conserved to round-off through the contacts",
                  "%d contact steps, L = %.12g kg m^2/s, max drift %.3g", contacts, L0, drift);
        rj_state_destroy(ss, NULL); rj_model_destroy(mm, NULL);
    }

    /* adaptive needs no parameter; its peak penetration is within a factor 2 of the best
       penalty run of a sweep. "Best" is what trial and error ends with: the stiffest K the
       step still accepts (the library refuses a K that breaks the stability bound), i.e.
       the least penetration a penalty can reach at this dt. */
    o = impact_default_opts(); o.release = RJ_RELEASE_RC13;
    printf("  penalty sweep (RC13): K, peak penetration, vibration energy\n");
    for (K = 1e7; K <= 1.01e10; K *= pow(10.0, 0.25)) {
        impact_result r;
        o.method = RJ_METHOD_PENALTY; o.K = K;
        r = impact_run(&o, 0.05);
        printf("  K %.3g N m/rad: %s peak %.4g rad, E_vib %.4g J\n", K, r.ok ? "ok" : "refused or stopped", r.peak, r.evib);
        if (r.ok && K > best_k) { best_k = K; best_peak = r.peak; best_e = r.evib; }
    }
    o.method = RJ_METHOD_ADAPTIVE;
    ad = impact_run(&o, 0.05);
    rjt_check(c, ad.ok && best_k > 0 && ad.peak < 2 * best_peak && ad.peak > 0.5 * best_peak, "adaptive peak penetration within a factor 2 of the best penalty run",
              "adaptive %.4g rad (E_vib %.4g J, no parameter); stiffest accepted penalty K = %.3g N m/rad: %.4g rad (E_vib %.4g J)", ad.peak, ad.evib, best_k, best_peak, best_e);

    /* the paper's sec. 4 findings: reported, not asserted (they are claims about the paper's
       element, and the margins here are small or reversed) */
    o.method = RJ_METHOD_ADAPTIVE; o.release = RJ_RELEASE_RC12; r12 = impact_run(&o, 0.05);
    o.release = RJ_RELEASE_RC13; r13 = impact_run(&o, 0.05);
    printf("REPORT (not asserted) paper: RC12 excites more than RC13 (adaptive): vibration energy RC12 %.4g J vs RC13 %.4g J -> %s\n", r12.evib, r13.evib, r12.evib > r13.evib ? "holds" : "does not hold");
    o.method = RJ_METHOD_MOMENTUM;
    for (k = 0; k < 3; k++) { o.e = 0.5 * k; mom[k] = impact_run(&o, 0.05); }
    printf("REPORT (not asserted) paper: momentum e = 0 excites least of the momentum family: E_vib e=0 %.4g, e=0.5 %.4g, e=1 %.4g J -> %s\n", mom[0].evib, mom[1].evib, mom[2].evib,
           mom[0].evib <= mom[1].evib && mom[0].evib <= mom[2].evib ? "holds" : "does not hold");
    /* why it need not hold here: the momentum balance (Eqs 23-24) exchanges rates between
       the pin nodes' rotary inertias only (RJ_REF_TANGENT), so with e > 0 the pin node
       rebounds alone and the rest of the link, still arriving, strikes it again and again;
       with e = 0 the pin stops once and the link's bending returns it */
    rjt_check(c, mom[0].contacts == 1 && mom[1].contacts > 10 && mom[2].contacts > 10,
              "momentum: e = 0 latches in one contact, e > 0 chatters at the pin (many contacts)",
              "contacts e=0 %d, e=0.5 %d, e=1 %d", mom[0].contacts, mom[1].contacts, mom[2].contacts);
    o.e = 0; o.K = impact_default_opts().K;
    for (k = 0; k < 5; k++) {
        impact_result r; o.method = k;
        r = impact_run(&o, 0.05);
        printf("REPORT %s RC13: contact %.4f ms, last release %.4f ms, peak %.4g rad, rigid rate after %.4g rad/s, E_vib %.4g J\n", mname[k], 1e3 * r.contact, 1e3 * r.release, r.peak, r.wrigid, r.evib);
    }
}

/* ---------------------------------------------------------------- deployment */
#define HMAX 8000
typedef struct hist { int n; double t[HMAX], q1[HMAX], q2[HMAX]; } hist;
static int hsample(const rj_model *m, const rj_state *s, void *u)
{
    hist *h = (hist *)u;
    if (h->n < HMAX) { h->t[h->n] = rj_state_time(s); h->q1[h->n] = deploy_q1_deg(m, s); h->q2[h->n] = deploy_q2_deg(m, s); h->n++; }
    return 0;
}
static void rsample(const rigid2_sample *s, void *u)
{
    hist *h = (hist *)u;
    if (h->n < HMAX) { h->t[h->n] = s->t; h->q1[h->n] = rj_deg(s->q[0]); h->q2[h->n] = rj_deg(s->q[1]); h->n++; }
}
static double deploy_run(int elements, double dt, hist *h)
{
    deploy_opts o = deploy_default_opts();
    rj_model *m = NULL; rj_state *s = NULL; rj_error err; double tl;
    o.elements = elements; o.dt = dt;
    if (deploy_build(&o, &m, &err) != RJ_OK) { printf("  (%s)\n", err.msg); return -1; }
    rj_state_create(m, &s, NULL);
    h->n = 0;
    rj_run(m, s, 3.2, 1e-3, hsample, h);
    tl = rj_joint_event_time(m, s, 1);
    rj_state_destroy(s, NULL); rj_model_destroy(m, NULL);
    return tl;
}
static double maxdev(const hist *a, const hist *b, double t_max)
{
    double d = 0;
    int i;
    for (i = 0; i < a->n && i < b->n; i++) {
        if (a->t[i] > t_max) break;
        if (fabs(a->q1[i] - b->q1[i]) > d) d = fabs(a->q1[i] - b->q1[i]);
        if (fabs(a->q2[i] - b->q2[i]) > d) d = fabs(a->q2[i] - b->q2[i]);
    }
    return d;
}

/* The segmented arm (rigid pieces and bending springs, deploy_segmented_scene) at the
   automatic step, its bending springs scaled by `stiffer`; q2 is read at joint
   segments + 1. */
#define SEG_MAX 6
static int seg_sample(const rj_model *m, const rj_state *s, void *u)
{
    hist *h = (hist *)u;
    const int segments = rj_model_joint_count(m) / 2 - 1;
    if (h->n < HMAX) {
        h->t[h->n] = rj_state_time(s);
        h->q1[h->n] = deploy_q1_deg(m, s);
        h->q2[h->n] = deploy_segmented_q2_deg(m, s, segments);
        h->n++;
    }
    return 0;
}
static int seg_run(int segments, double stiffer, hist *h)
{
    rj_link_def links[2 * (SEG_MAX + 1)];
    rj_joint_def joints[2 * (SEG_MAX + 1)];
    deploy_opts o = deploy_default_opts();
    rj_scene_def sc;
    rj_model *m = NULL;
    rj_state *s = NULL;
    rj_error err;
    int j;
    o.dt = 0;
    deploy_segmented_scene(&o, segments, links, joints, &sc);
    for (j = 0; j < sc.joint_count; j++) {
        if (j != 0 && j != segments + 1) joints[j].spring_k *= stiffer;
    }
    if (rj_model_create(&sc, &m, &err, NULL) != RJ_OK) { printf("  (%s)\n", err.msg); return 0; }
    rj_state_create(m, &s, NULL);
    h->n = 0;
    rj_run(m, s, 3.2, 1e-3, seg_sample, h);
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
    return 1;
}

static void test_deploy(rjt_ctx *c)
{
    static hist h10, h20, h40, hq, hr;
    rigid2_params p;
    double l10, l40, lq, lr[2], tb;
    l10 = deploy_run(10, 7.5e-6, &h10);
    l40 = deploy_run(40, 3.75e-6, &h40);
    deploy_run(20, 7.5e-6, &h20);
    lq = deploy_run(10, 7.5e-6 / 4, &hq);
    rigid2_default_params(&p);
    hr.n = 0;
    rigid2_run(&p, 3.2, 1e-3, rsample, &hr, lr);
    tb = lr[1] - 0.01;   /* before joint 2 locks */
    /* mesh: second-order convergence, and 20 elements within 0.1 deg of 40 (README: 10
       elements are 0.42 deg from 40 and 0.45 deg from 80, so 0.1 deg needs 20) */
    {
        double d10 = maxdev(&h10, &h40, tb), d20 = maxdev(&h20, &h40, tb);
        rjt_check(c, d20 < 0.1, "deploy: 20 elements within 0.1 deg of 40 elements before joint 2 locks", "max |dq| %.4f deg (10 elements: %.4f deg; t < %.3f s)", d20, d10, tb);
        rjt_check(c, d10 / d20 > 3.5, "deploy: mesh error falls at second order", "|q10 - q40| / |q20 - q40| = %.2f (5 for second order, 3 for first)", d10 / d20);
    }
    rjt_check(c, maxdev(&h10, &hq, tb) < 0.05, "deploy: dt 7.5 us within 0.05 deg of dt/4 before joint 2 locks", "max |dq| %.5f deg", maxdev(&h10, &hq, tb));
    rjt_check(c, maxdev(&h10, &hr, tb) < 2.0, "deploy: flexible within 2 deg of the rigid model before joint 2 locks", "max |dq| %.4f deg", maxdev(&h10, &hr, tb));
    rjt_check(c, fabs(l10 / lr[1] - 1) < 0.005, "deploy: joint 2 locks within 0.5% of the rigid time", "flexible %.5f s, rigid %.5f s (%+.3f%%); 40 el %.5f s, dt/4 %.5f s",
              l10, lr[1], 100 * (l10 / lr[1] - 1), l40, lq);
    /* rigid pieces with bending springs: with the springs 1000 x stiffer the arm is the
       rigid model of the independent solver (flexibility moves q by 1.3 deg, so a wrong
       layout or mass fails). The 0.047 deg left is the stiff chain's own fast vibration,
       not the step: it is 0.044 deg at a quarter of the step and falls as one over the
       root of the stiffness (0.015 deg at 10^4 x, as MuJoCo's pieces; docs/validation.md).
       As built, within 0.15 deg of 40 elements at 6 pieces per link (0.036 / 0.052 deg
       against 80 elements) */
    {
        static hist hs, hstiff;
        const int ok = seg_run(6, 1.0, &hs) && seg_run(6, 1000.0, &hstiff);
        const double dseg = ok ? maxdev(&hs, &h40, tb) : 1e9, dstiff = ok ? maxdev(&hstiff, &hr, tb) : 1e9;
        rjt_check(c, dstiff < 0.1, "deploy: rigid pieces with stiff springs within 0.1 deg of the rigid model before joint 2 locks", "max |dq| %.4f deg", dstiff);
        rjt_check(c, dseg < 0.15, "deploy: 6 rigid pieces per link within 0.15 deg of 40 elements before joint 2 locks", "max |dq| %.4f deg", dseg);
    }
}


/* ---------------------------------------------------------------- rigid links */
static void test_rigid(rjt_ctx *c)
{
    static hist h, hr;
    rigid2_params p;
    double lr[2], dev = 0;
    deploy_opts o = deploy_default_opts();
    rj_link_def L[2]; rj_joint_def J[2]; rj_scene_def sc; rj_model *m = NULL; rj_state *s = NULL; rj_error e;
    int i, k;
    rigid2_default_params(&p);
    hr.n = 0;
    rigid2_run(&p, 6.0, 1e-3, rsample, &hr, lr);
    for (k = 0; k < 2; k++) {
        double dt = k == 0 ? 1e-3 : 2e-3, e0;
        char name[128];
        rj_energy en;
        o.dt = dt;
        deploy_scene(&o, L, J, &sc);
        L[0].fidelity = L[1].fidelity = RJ_LINK_RIGID; L[0].elements = L[1].elements = 1;
        J[0].method = J[1].method = RJ_METHOD_MOMENTUM;   /* plastic locks, as the rigid reference */
        if (rj_model_create(&sc, &m, &e, NULL) != RJ_OK) { rjt_check(c, 0, "rigid deployment builds", "%s", e.msg); return; }
        rj_state_create(m, &s, NULL);
        h.n = 0;
        rj_run(m, s, 6.0, dt, hsample, &h);
        dev = 0;
        for (i = 0; i < h.n; i++) {
            int r = (int)floor(h.t[i] / 1e-3 + 0.5);
            if (h.t[i] > lr[1] - dt || r >= hr.n) break;
            if (fabs(h.q1[i] - hr.q1[r]) > dev) dev = fabs(h.q1[i] - hr.q1[r]);
            if (fabs(h.q2[i] - hr.q2[r]) > dev) dev = fabs(h.q2[i] - hr.q2[r]);
        }
        snprintf(name, sizeof name, "rigid links at dt = %g ms reproduce the rigid reference within 1e-3 deg before locking", 1e3 * dt);
        rjt_check(c, dev < 1e-3, name, "max |dq| %.3g deg", dev);
        snprintf(name, sizeof name, "rigid links at dt = %g ms lock within one step of the reference", 1e3 * dt);
        rjt_check(c, fabs(rj_joint_event_time(m, s, 1) - lr[1]) <= dt && fabs(rj_joint_event_time(m, s, 0) - lr[0]) <= 2 * dt, name,
                  "joint 2 %.4f s (reference %.6f), joint 1 %.4f s (reference %.6f)", rj_joint_event_time(m, s, 1), lr[1], rj_joint_event_time(m, s, 0), lr[0]);
        rj_state_energy(m, s, &en);
        e0 = en.total - en.balance + en.lost_damping + en.lost_friction + en.lost_limit;   /* initial */
        (void)e0;
        if (k == 0) rjt_check(c, fabs(en.balance) < 1e-3 * 1.755, "rigid links: energy balance (friction, plastic locks) closes to 1e-3 of E0",
                              "balance %.3g J; lost to friction %.4f J (reference %.4f), to locks %.4f J (reference 1.0525)", en.balance, en.lost_friction, 0.130769, en.lost_limit);
        rj_state_destroy(s, NULL); rj_model_destroy(m, NULL);
    }
    /* mixed scenes (a rigid link among flexible ones) are tests/test_mixed.c's */
}

/* inextensible links on the deployment: link 2's post-lock tip vibration against a
   converged flexible reference (20 elements per link, adaptive joint 2: within 0.02 % in
   RMS and 0.11 % in frequency of the 80-element reference, BENCHMARKS.md), at a step set
   by bending. The deflection is the tangent-based one (second order in the mesh). */
typedef struct vib { int n; double t[7000], d[7000]; } vib;
static int vib_sample(const rj_model *m, const rj_state *s, void *u)
{
    vib *v = (vib *)u;
    if (v->n < 7000) { v->t[v->n] = rj_state_time(s); v->d[v->n] = scene_tip_defl_tangent(m, s, 1); v->n++; }
    return 0;
}
/* RMS about the mean and frequency from the zero crossings, over t0 < t <= t1 */
static void vib_window(const vib *v, double t0, double t1, double *rms, double *freq)
{
    double mean = 0, sq = 0, ta = -1, tb = -1;
    int i, c = 0, zc = 0;
    for (i = 0; i < v->n; i++) if (v->t[i] > t0 && v->t[i] <= t1) { mean += v->d[i]; c++; }
    mean /= c;
    for (i = 1; i < v->n; i++) if (v->t[i] > t0 && v->t[i] <= t1) {
        double a = v->d[i] - mean, b = v->d[i - 1] - mean;
        sq += a * a;
        if (a * b < 0) { if (ta < 0) ta = v->t[i]; tb = v->t[i]; zc++; }
    }
    *rms = sqrt(sq / c); *freq = (zc - 1) / (2 * (tb - ta));
}
/* the same over t > t0 */
static void vib_stats(const vib *v, double t0, double *rms, double *freq)
{
    vib_window(v, t0, HUGE_VAL, rms, freq);
}
static int vib_run(int fidelity, int elements, int method, vib *v, double *dt, char *msg, size_t n)
{
    deploy_opts o = deploy_default_opts();
    rj_link_def L[2]; rj_joint_def J[2]; rj_scene_def sc; rj_model *m = NULL; rj_state *s = NULL; rj_error e;
    o.dt = 0; o.elements = elements;
    deploy_scene(&o, L, J, &sc);
    J[1].method = method;
    L[0].fidelity = L[1].fidelity = fidelity;
    if (rj_model_create(&sc, &m, &e, NULL) != RJ_OK) { snprintf(msg, n, "%s", e.msg); return 0; }
    *dt = rj_model_dt(m);
    rj_state_create(m, &s, NULL);
    v->n = 0;
    if (rj_run(m, s, 6.0, 1e-3, vib_sample, v) != RJ_OK) { snprintf(msg, n, "%s", rj_state_error(s)); rj_state_destroy(s, NULL); rj_model_destroy(m, NULL); return 0; }
    rj_state_destroy(s, NULL); rj_model_destroy(m, NULL);
    return 1;
}
static void test_inextensible_deploy(rjt_ctx *c)
{
    static vib vr, vi;
    double ar, fr, ai, fi, dtr, dti;
    char msg[700], name[200];
    int k;
    static const int els[2] = { 10, 5 };
    if (!vib_run(RJ_LINK_FLEXIBLE, 20, RJ_METHOD_ADAPTIVE, &vr, &dtr, msg, sizeof msg)) { rjt_check(c, 0, "deployment reference (20 elements) runs", "%s", msg); return; }
    vib_stats(&vr, 3.2, &ar, &fr);
    for (k = 0; k < 2; k++) {
        if (!vib_run(RJ_LINK_INEXTENSIBLE, els[k], RJ_METHOD_MOMENTUM, &vi, &dti, msg, sizeof msg)) { rjt_check(c, 0, "inextensible deployment runs", "%s", msg); return; }
        vib_stats(&vi, 3.2, &ai, &fi);
        snprintf(name, sizeof name, "inextensible links, %d elements: link 2's post-lock tip vibration within 2 %% of the converged flexible reference, at a step >= %d x the paper's 7.5 us",
                 els[k], k ? 40 : 10);
        rjt_check(c, fabs(ai / ar - 1) < 0.02 && fabs(fi / fr - 1) < 0.02 && dti >= (k ? 40 : 10) * 7.5e-6, name,
                  "RMS %.5f m vs %.5f m (%+.2f %%), frequency %.4f vs %.4f Hz (%+.2f %%), dt %.3g s (%.0f x 7.5 us; reference %.3g s)",
                  ai, ar, 100 * (ai / ar - 1), fi, fr, 100 * (fi / fr - 1), dti, dti / 7.5e-6, dtr);
    }
}

/* The segmented arm's latches in the joint-coordinate solver: after joint 1 locks it must
   stay at its lock angle while joint 2's latch acts in the same step (each impulse moves
   the other joint), and link 2's vibration after the locks must not depend on the step:
   at 1 ms (0.59 x the bound) its frequency within 0.3 % of the run at 0.1 ms, where the
   step's own error is 1 % of that. */
typedef struct latch_hist { vib v; double q_lock, drift; } latch_hist;
static int latch_sample(const rj_model *m, const rj_state *s, void *u)
{
    latch_hist *h = (latch_hist *)u;
    const int segments = rj_model_joint_count(m) / 2 - 1;
    const double q = rj_joint_theta_running(m, s, 0);
    if (rj_joint_flag(m, s, 0) == RJ_LOCKED) {
        if (h->q_lock > 1e30) h->q_lock = q;
        if (fabs(q - h->q_lock) > h->drift) h->drift = fabs(q - h->q_lock);
    }
    if (h->v.n < 7000) {
        h->v.t[h->v.n] = rj_state_time(s);
        h->v.d[h->v.n] = deploy_segmented_tip_defl(m, s, segments);
        h->v.n++;
    }
    return 0;
}
static int latch_run(double dt, latch_hist *h, char *msg, size_t n)
{
    enum { SEGMENTS = 5 };
    rj_link_def links[2 * (SEGMENTS + 1)];
    rj_joint_def joints[2 * (SEGMENTS + 1)];
    deploy_opts o = deploy_default_opts();
    rj_scene_def sc;
    rj_model *m = NULL;
    rj_state *s = NULL;
    rj_error err;
    int ok;
    o.dt = dt;
    deploy_segmented_scene(&o, SEGMENTS, links, joints, &sc);
    if (rj_model_create(&sc, &m, &err, NULL) != RJ_OK) {
        snprintf(msg, n, "%s", err.msg);
        return 0;
    }
    rj_state_create(m, &s, NULL);
    h->v.n = 0;
    h->q_lock = HUGE_VAL;
    h->drift = 0;
    ok = rj_run(m, s, 6.0, 1e-3, latch_sample, h) == RJ_OK;
    if (!ok) snprintf(msg, n, "%s", rj_state_error(s));
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
    return ok;
}
static void test_segmented_latch(rjt_ctx *c)
{
    static latch_hist coarse, fine;
    static const double windows[2][2] = { { 3.05, 3.95 }, { 4.5, 6.0 } };
    char msg[700];
    int w;
    if (!latch_run(1e-3, &coarse, msg, sizeof msg) || !latch_run(1e-4, &fine, msg, sizeof msg)) {
        rjt_check(c, 0, "segmented arm runs at 1 ms and 0.1 ms", "%s", msg);
        return;
    }
    rjt_check(c, coarse.drift < 1e-9 && fine.drift < 1e-9, "segmented arm: joint 1 stays at its lock angle while joint 2 is latched",
              "largest turn after the lock %.3g rad at 1 ms, %.3g rad at 0.1 ms", coarse.drift, fine.drift);
    for (w = 0; w < 2; w++) {
        double rms_a, f_a, rms_b, f_b;
        char name[200];
        vib_window(&coarse.v, windows[w][0], windows[w][1], &rms_a, &f_a);
        vib_window(&fine.v, windows[w][0], windows[w][1], &rms_b, &f_b);
        snprintf(name, sizeof name, "segmented arm: link 2's frequency at 1 ms within 0.3 %% of 0.1 ms, %.2f-%.2f s", windows[w][0], windows[w][1]);
        rjt_check(c, fabs(f_a / f_b - 1) < 0.003, name, "%.4f Hz vs %.4f Hz (%+.2f %%)", f_a, f_b, 100 * (f_a / f_b - 1));
    }
}

int main(int argc, char **argv)
{
    rjt_ctx c = { 0, 0 };
    int quick = argc > 1 && strcmp(argv[1], "--impact-only") == 0;
    test_impact(&c);
    if (!quick) test_deploy(&c);
    test_rigid(&c);
    if (!quick) test_segmented_latch(&c);
    if (!quick) test_inextensible_deploy(&c);
    return rjt_summary(&c, "test_benchmarks");
}
