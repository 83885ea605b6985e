/* Mixed scenes: rigid links (one rigid body each) among flexible and inextensible links.
   Checked against things not tuned here: the closed-form torsion pendulum, uniform motion
   of a free body, conservation of linear and angular momentum and the energy accounts of
   a free-floating bus deploying an array, and the all-flexible model as its stiff link
   tends to rigid. Run from the repository root (it reads examples/scenes). */
#define REVJOINT_IMPLEMENTATION
#include "../revjoint.h"
#include "../examples/scenes.h"
#include "rjt.h"
#include <string.h>

static rjt_ctx T;

static rj_model *build(rj_link_def *L, int nl, rj_joint_def *J, int nj, double dt, char *msg, size_t n)
{
    rj_scene_def sc = rj_default_scene_def();
    rj_model *m = NULL;
    rj_error err;
    sc.links = L; sc.link_count = nl; sc.joints = J; sc.joint_count = nj; sc.solver.dt = dt;
    if (rj_model_create(&sc, &m, &err, NULL) != RJ_OK) { snprintf(msg, n, "%s", err.msg); return NULL; }
    msg[0] = 0;
    return m;
}

/* 1. A rigid link pinned to the ground on a torsion spring, no gravity: theta(t) =
   theta0 cos(sqrt(k / I_pin) t) exactly (the spring is linear in the angle). A free
   flexible link elsewhere makes the scene a mixed one. */
static void test_pendulum(void)
{
    rj_link_def L[2];
    rj_joint_def J[1];
    rj_model *m;
    rj_state *s = NULL;
    char msg[600];
    const double len = 0.8, rho = 2700, w = 0.02, h = 0.01, tip = 0.3, tipJ = 2e-3, k = 5.0, th0 = 0.4;
    double mr, Ip, om, worst = 0, t;
    int i;
    L[0] = rj_default_link_def();
    L[0].length = len; L[0].elements = 3; L[0].rho = rho; L[0].width = w; L[0].height = h;
    L[0].tip_mass = tip; L[0].tip_inertia = tipJ; L[0].fidelity = RJ_LINK_RIGID;
    L[1] = rj_default_link_def();
    L[1].x = 5; L[1].height = 0.01;
    J[0] = rj_default_joint_def();
    J[0].body1 = -1; J[0].body2 = 0; J[0].angle0 = th0; J[0].spring_k = k; J[0].spring_free_angle = 0;
    m = build(L, 2, J, 1, 0, msg, sizeof msg);
    if (!rjt_check(&T, m != NULL, "torsion pendulum: a rigid link and a flexible one build a model", "%s", msg)) return;
    rj_state_create(m, &s, NULL);
    mr = rho * w * h * len;
    Ip = mr * len * len / 3.0 + tip * len * len + tipJ;
    om = sqrt(k / Ip);
    for (i = 1; i <= 40; i++) {
        double err;
        if (rj_run(m, s, 0.05 * i, 0, NULL, NULL) != RJ_OK) break;
        t = rj_state_time(s);
        err = fabs(rj_joint_theta_running(m, s, 0) - th0 * cos(om * t));
        if (err > worst) worst = err;
    }
    rjt_check(&T, i > 40 && worst < 1e-6 * th0, "torsion pendulum (rigid link, pinned): theta(t) = theta0 cos(sqrt(k/I_pin) t) over 2 s",
              "max |error| %.3g rad (bound 1e-6 theta0 = %.1g), period %.4f s, dt %.3g s", worst, 1e-6 * th0, 2 * RJ__PI / om, rj_model_dt(m));
    rj_state_destroy(s, NULL); rj_model_destroy(m, NULL);
}

/* 2. A free rigid link moving and spinning: exact uniform motion of its centre and angle. */
static void test_free_body(void)
{
    rj_link_def L[2];
    rj_model *m;
    rj_state *s = NULL;
    char msg[600];
    double p0[2], p1[2], c0x, c0y, err = 0, th;
    const double vx = 0.3, vy = -0.2, om = 1.7, len = 1.2, tend = 3.0;
    L[0] = rj_default_link_def();
    L[0].length = len; L[0].elements = 2; L[0].fidelity = RJ_LINK_RIGID; L[0].vx = vx; L[0].vy = vy; L[0].omega = om;
    L[1] = rj_default_link_def();
    L[1].x = 5; L[1].height = 0.01;
    m = build(L, 2, NULL, 0, 0, msg, sizeof msg);
    if (!rjt_check(&T, m != NULL, "free rigid link builds", "%s", msg)) return;
    rj_state_create(m, &s, NULL);
    rj_node_position(m, s, 0, 1, p0);          /* the middle node is the centre (no tip mass) */
    c0x = p0[0]; c0y = p0[1];
    rj_run(m, s, tend, 0, NULL, NULL);
    rj_node_position(m, s, 0, 1, p1);
    /* vx, vy are the root's velocity: the centre, 0.6 m along +x, moves at v + omega x r */
    err = hypot(p1[0] - (c0x + vx * rj_state_time(s)), p1[1] - (c0y + (vy + om * 0.5 * len) * rj_state_time(s)));
    th = rj_node_rotation(m, s, 0, 0);
    /* round-off: the angle and the centre are sums of dt x rate over 1e5 steps */
    rjt_check(&T, err < 1e-9 && fabs(th - om * rj_state_time(s)) < 1e-9 && fabs(rj_node_rate(m, s, 0, 2) - om) < 1e-12,
              "free rigid link: centre moves at its velocity, angle turns at its rate (to accumulated round-off, 1e-9)",
              "centre off by %.3g m, angle off by %.3g rad after %.3f s (%ld steps)", err, th - om * rj_state_time(s), rj_state_time(s), rj_state_steps(s));
    {
        double a[2], b[2];
        rj_node_position(m, s, 0, 0, a); rj_node_position(m, s, 0, 2, b);
        rjt_check(&T, fabs(hypot(b[0] - a[0], b[1] - a[1]) - len) < 1e-12, "free rigid link stays rigid", "length %.15g m (rest %.15g)", hypot(b[0] - a[0], b[1] - a[1]), len);
    }
    rj_state_destroy(s, NULL); rj_model_destroy(m, NULL);
}

/* linear and angular momentum about the origin (at the half step: positions x^n, rates
   v^{n-1/2}); bodies from their records, nodes on a body counted there */
static void momenta(const rj_model *m, const rj_state *s, double *px, double *py, double *lz)
{
    const double *f = s->fd[s->cur];
    const double *x = RJ__FX(m, f), *y = RJ__FY(m, f), *vx = RJ__FVX(m, f), *vy = RJ__FVY(m, f), *w = RJ__FW(m, f);
    int i, c;
    *px = *py = *lz = 0;
    for (i = 0; i < m->nn; i++) {
        if (m->node_cl[i] >= 0) { if (!RJ__CL_RIGID(m, i)) *lz += m->rinertia[i] * w[i]; continue; }
        *px += m->mass[i] * vx[i]; *py += m->mass[i] * vy[i];
        *lz += m->mass[i] * (x[i] * vy[i] - y[i] * vx[i]) + m->rinertia[i] * w[i];
    }
    for (c = 0; c < m->ncl; c++) {
        const double *b = RJ__FCL(m, f, c);
        if (m->cl_first[c] == m->cl_first[c + 1]) continue;
        *px += m->cl_M[c] * b[2]; *py += m->cl_M[c] * b[3];
        *lz += m->cl_M[c] * (b[0] * b[3] - b[1] * b[2]) + m->cl_I[c] * b[4];
    }
}

/* 3. The solar array on a free-floating rigid bus (examples/scenes/solar_array_bus.rjs). */
static void test_bus(void)
{
    rj_scene_file f;
    rj_scene_def sd;
    rj_model *m;
    rj_state *s = NULL;
    rj_error e;
    rj_energy en;
    double px0, py0, l0, px, py, lz, worst_p = 0, worst_l = 0, pscale = 0, lscale = 0, bus0, bus1;
    int k, locked = 0;
    if (!rjt_check(&T, rj_scene_load("examples/scenes/solar_array_bus.rjs", &f, &e) == RJ_OK, "solar_array_bus.rjs parses", "%s", e.msg)) return;
    sd = rj_scene_file_def(&f);
    if (!rjt_check(&T, rj_model_create(&sd, &m, &e, NULL) == RJ_OK, "solar_array_bus.rjs builds (rigid bus, flexible panels)", "%s", e.msg)) { rj_scene_file_free(&f); return; }
    rj_state_create(m, &s, NULL);
    momenta(m, s, &px0, &py0, &l0);
    bus0 = rj_node_rotation(m, s, 0, 0);
    for (k = 1; k <= 100; k++) {
        int i;
        if (rj_run(m, s, 0.1 * k, 0, NULL, NULL) != RJ_OK) break;
        momenta(m, s, &px, &py, &lz);
        if (hypot(px - px0, py - py0) > worst_p) worst_p = hypot(px - px0, py - py0);
        if (fabs(lz - l0) > worst_l) worst_l = fabs(lz - l0);
        for (i = 0; i < m->nn; i++) {
            const double *fr = s->fd[s->cur];
            double v = hypot(RJ__FVX(m, fr)[i], RJ__FVY(m, fr)[i]) * m->mass[i];
            if (m->node_cl[i] < 0 && v > pscale) pscale = v;
            if (m->node_cl[i] < 0 && fabs(RJ__FX(m, fr)[i] * RJ__FVY(m, fr)[i] * m->mass[i]) > lscale) lscale = fabs(RJ__FX(m, fr)[i] * RJ__FVY(m, fr)[i] * m->mass[i]);
        }
    }
    rjt_check(&T, k > 100, "solar_array_bus.rjs runs 10 s", "%s (t = %.3f s)", rj_state_error(s), rj_state_time(s));
    for (k = 0; k < 4; k++) locked += rj_joint_flag(m, s, k) == RJ_LOCKED;
    rjt_check(&T, locked == 4, "solar_array_bus.rjs: every hinge locks", "%d of 4 locked; lock times %.3f %.3f %.3f %.3f s", locked,
              rj_joint_event_time(m, s, 0), rj_joint_event_time(m, s, 1), rj_joint_event_time(m, s, 2), rj_joint_event_time(m, s, 3));
    rjt_check(&T, worst_p < 1e-12 * (pscale + 1e-300) * 1e3 && worst_p < 1e-10, "free-floating bus: linear momentum conserved (to round-off)",
              "max |P - P0| %.3g kg m/s; largest node momentum %.3g", worst_p, pscale);
    rjt_check(&T, worst_l < 1e-6 * lscale, "free-floating bus: angular momentum conserved",
              "max |L - L0| %.3g kg m^2/s (L0 = %.3g); largest node moment of momentum %.3g, bound 1e-6 of it", worst_l, l0, lscale);
    bus1 = rj_node_rotation(m, s, 0, 0);
    rjt_check(&T, fabs(bus1 - bus0) > 0.05, "free-floating bus turns against the opening array", "bus turned %.2f deg", rj_deg(bus1 - bus0));
    rj_state_energy(m, s, &en);
    rjt_check(&T, fabs(en.balance) < 1e-3, "free-floating bus: energy accounts close (bound 1e-3 J, as for solar_array.rjs)",
              "balance %.3g J; kinetic %.4g, strain %.4g, springs %.4g, lost to friction %.4g, to limits %.4g J", en.balance, en.kinetic, en.strain, en.spring, en.lost_friction, en.lost_limit);
    {
        /* the bus stays rigid: its two nodes keep their distance */
        double a[2], b[2];
        rj_node_position(m, s, 0, 0, a); rj_node_position(m, s, 0, 1, b);
        rjt_check(&T, fabs(hypot(b[0] - a[0], b[1] - a[1]) - 0.6) < 1e-12, "the bus stays rigid", "length %.15g m", hypot(b[0] - a[0], b[1] - a[1]));
    }
    rj_state_destroy(s, NULL); rj_model_destroy(m, NULL); rj_scene_file_free(&f);
}

/* q1, q2 (deg) every 0.25 s up to 2.75 s (joint 2 locks near 3.0 s) */
static int deploy_q(int f0, int f1, double E1, double rho_scale, int el1, double q[11][2], double *dt, double *lock2)
{
    deploy_opts o = deploy_default_opts();
    rj_link_def l[2];
    rj_joint_def j[2];
    rj_scene_def sc;
    rj_model *m;
    rj_state *s = NULL;
    rj_error err;
    int k;
    o.joint2_method = RJ_METHOD_ADAPTIVE;
    deploy_scene(&o, l, j, &sc);
    l[0].fidelity = f0; l[1].fidelity = f1; l[1].E *= E1;
    l[1].rho *= rho_scale; l[1].elements = el1;
    sc.solver.dt = 0;
    if (rj_model_create(&sc, &m, &err, NULL) != RJ_OK) { printf("deploy_q: %s\n", err.msg); return 0; }
    rj_state_create(m, &s, NULL);
    for (k = 0; k < 11; k++) {
        if (rj_run(m, s, 0.25 * (k + 1), 0, NULL, NULL) != RJ_OK) { printf("deploy_q: %s\n", rj_state_error(s)); return 0; }
        q[k][0] = deploy_q1_deg(m, s); q[k][1] = deploy_q2_deg(m, s);
    }
    rj_run(m, s, 3.1, 0, NULL, NULL);
    *dt = rj_model_dt(m);
    *lock2 = rj_joint_event_time(m, s, 1);
    rj_state_destroy(s, NULL); rj_model_destroy(m, NULL);
    return 1;
}

static double qdiff(double a[11][2], double b[11][2], int n)
{
    double d = 0;
    int k;
    for (k = 0; k < n; k++) { d = fmax(d, fabs(a[k][0] - b[k][0])); d = fmax(d, fabs(a[k][1] - b[k][1])); }
    return d;
}

/* 4. The deployment with a rigid link 2 against a one-element flexible link 2 made 10,
   100 and 1000 times stiffer, up to 2.25 s (joint 2 locks near 2.53 s). Link 2's rod is
   made 1e5 times lighter: a one-element link lumps its rod at its ends, which changes its
   inertia about the pin by m_rod L^2 / 6, 2e-4 of the total at a 1e3 times lighter rod and
   a 0.03 deg gap that no stiffness closes (measured); the tip mass and inertia are the same
   in both models. Link 1 is flexible throughout. The gap must close with the stiffness. */
static void test_stiff_limit(void)
{
    double qr[11][2], q[3][11][2], dtr, dt[3], l2r, l2[3], d[3];
    int i;
    if (!deploy_q(RJ_LINK_FLEXIBLE, RJ_LINK_RIGID, 1, 1e-5, 1, qr, &dtr, &l2r)) { rjt_check(&T, 0, "deployment, rigid link 2", "failed"); return; }
    for (i = 0; i < 3; i++) {
        if (!deploy_q(RJ_LINK_FLEXIBLE, RJ_LINK_FLEXIBLE, pow(10.0, i + 1), 1e-5, 1, q[i], &dt[i], &l2[i])) { rjt_check(&T, 0, "deployment, stiff link 2", "failed"); return; }
        d[i] = qdiff(qr, q[i], 9);
    }
    rjt_check(&T, d[2] < 0.01 && d[2] < 0.3 * d[0], "deployment, rigid link 2 = the limit of a stiffening flexible link 2 (light rod)",
              "max |q - q_rigid| up to 2.25 s: EI x10 %.4f deg, x100 %.4f deg, x1000 %.5f deg (bound: x1000 < 0.01 and < 0.3 x the x10 gap); "
              "joint 2 locks %.5f (rigid) / %.5f / %.5f / %.5f s; dt %.3g / %.3g / %.3g / %.3g s",
              d[0], d[1], d[2], l2r, l2[0], l2[1], l2[2], dtr, dt[0], dt[1], dt[2]);
}

/* 5. Rigid link 1 with an inextensible link 2 against rigid link 1 with a flexible link 2. */
static void test_rigid_inext(void)
{
    double qf[11][2], qi[11][2], dtf, dti, lf, li, d;
    if (!deploy_q(RJ_LINK_RIGID, RJ_LINK_FLEXIBLE, 1, 1, 10, qf, &dtf, &lf) || !deploy_q(RJ_LINK_RIGID, RJ_LINK_INEXTENSIBLE, 1, 1, 10, qi, &dti, &li)) {
        rjt_check(&T, 0, "deployment, rigid link 1 with flexible / inextensible link 2", "failed");
        return;
    }
    d = qdiff(qf, qi, 11);
    rjt_check(&T, d < 0.05 && fabs(li - lf) < 2e-3 && dti > 4 * dtf, "deployment: rigid link 1 + inextensible link 2 follows rigid link 1 + flexible link 2 at a larger step",
              "max |dq| %.4f deg (bound 0.05), joint 2 locks %.5f vs %.5f s, dt %.3g vs %.3g s", d, li, lf, dti, dtf);
}

/* 6. What a mixed scene refuses, by name. */
static void test_refusals(void)
{
    rj_link_def L[3];
    rj_joint_def J[2];
    rj_scene_def sc = rj_default_scene_def();
    rj_model *m = NULL;
    rj_error err;
    rj_result r, pair;
    int i;
    for (i = 0; i < 3; i++) { L[i] = rj_default_link_def(); L[i].height = 0.01; }
    L[0].root = RJ_ROOT_PINNED; L[1].fidelity = RJ_LINK_RIGID; L[2].fidelity = RJ_LINK_RIGID;
    J[0] = rj_default_joint_def(); J[0].body1 = 0; J[0].body2 = 1;
    J[1] = rj_default_joint_def(); J[1].body1 = 1; J[1].body2 = 2;
    sc.links = L; sc.link_count = 3; sc.joints = J; sc.joint_count = 2;
    r = rj_model_create(&sc, &m, &err, NULL);
    pair = r;
    if (r == RJ_OK)
        rj_model_destroy(m, NULL);
    /* their joint takes torques, a penalty limit among them, but no jump in the rates
       (the rows' gives do not see their pin) */
    J[1].has_forward = 1;
    J[1].forward = 1.0;
    J[1].method = RJ_METHOD_ENERGY;
    r = rj_model_create(&sc, &m, &err, NULL);
    rjt_check(&T, pair == RJ_OK && r == RJ_ERR_INVALID && strstr(err.msg, "pins two rigid links") && !strcmp(err.field, "joints[1].method"),
              "mixed scene: two rigid links pinned together build; an energy-method limit on their joint is refused, naming its method", "%s: %s", err.field, err.msg);
    J[1].method = RJ_METHOD_PENALTY;
    J[1].penalty_k = 1e3;
    J[1].friction = 0.1;
    r = rj_model_create(&sc, &m, &err, NULL);
    rjt_check(&T, r == RJ_OK, "mixed scene: a penalty limit and friction on the joint of two rigid links build", "%s", r == RJ_OK ? "ok" : err.msg);
    if (r == RJ_OK)
        rj_model_destroy(m, NULL);
    J[1].lock = 1;
    J[1].method = RJ_METHOD_MOMENTUM;
    r = rj_model_create(&sc, &m, &err, NULL);
    rjt_check(&T, r == RJ_OK, "mixed scene: a plastic lock on the joint of two rigid links builds", "%s", r == RJ_OK ? "ok" : err.msg);
    if (r == RJ_OK)
        rj_model_destroy(m, NULL);
    J[1] = rj_default_joint_def(); J[1].body1 = 1; J[1].body2 = 2;
    sc.link_count = 2; sc.joint_count = 1; J[0].reference = RJ_REF_CHORD;
    r = rj_model_create(&sc, &m, &err, NULL);
    rjt_check(&T, r == RJ_ERR_INVALID && strstr(err.msg, "RJ_REF_TANGENT") && !strcmp(err.field, "joints[0].reference"),
              "mixed scene: a chord reference on a rigid link is refused, naming the field", "%s: %s", err.field, err.msg);
    J[0].reference = RJ_REF_TANGENT;
    r = rj_model_create(&sc, &m, &err, NULL);
    rjt_check(&T, r == RJ_OK, "mixed scene: a flexible link carrying a rigid one builds", "%s", r == RJ_OK ? "ok" : err.msg);
    if (r == RJ_OK) rj_model_destroy(m, NULL);
}

/* 7. A checkpoint of a mixed scene resumes bit for bit (the bodies' records travel with it). */
static void test_checkpoint(void)
{
    rj_link_def L[2];
    rj_joint_def J[1];
    rj_model *m;
    rj_state *a = NULL, *b = NULL;
    char msg[600], buf[1 << 16];
    size_t n;
    double pa[2], pb[2];
    L[0] = rj_default_link_def(); L[0].fidelity = RJ_LINK_RIGID; L[0].root = RJ_ROOT_FREE; L[0].omega = 0.5; L[0].height = 0.05;
    L[1] = rj_default_link_def(); L[1].height = 0.01; L[1].elements = 6;
    J[0] = rj_default_joint_def(); J[0].body1 = 0; J[0].body2 = 1; J[0].angle0 = 2.0; J[0].spring_k = 3; J[0].spring_free_angle = 3.0;
    J[0].has_forward = 1; J[0].forward = 2.6; J[0].lock = 1; J[0].method = RJ_METHOD_MOMENTUM;
    m = build(L, 2, J, 1, 0, msg, sizeof msg);
    if (!rjt_check(&T, m != NULL, "checkpoint scene builds", "%s", msg)) return;
    rj_state_create(m, &a, NULL); rj_state_create(m, &b, NULL);
    rj_run(m, a, 0.5, 0, NULL, NULL);
    n = rj_state_save(m, a, buf, sizeof buf);
    rj_state_load(m, b, buf, n, NULL);
    rj_run(m, a, 2.0, 0, NULL, NULL); rj_run(m, b, 2.0, 0, NULL, NULL);
    rj_node_position(m, a, 1, 6, pa); rj_node_position(m, b, 1, 6, pb);
    rjt_check(&T, n > 0 && pa[0] == pb[0] && pa[1] == pb[1] && memcmp(a->fd[a->cur], b->fd[b->cur], sizeof(double) * m->frame_doubles) == 0,
              "mixed scene: a checkpoint resumes bit for bit", "tip %.17g %.17g vs %.17g %.17g; joint %s", pa[0], pa[1], pb[0], pb[1],
              rj_joint_flag(m, a, 0) == RJ_LOCKED ? "locked" : "not locked");
    rj_state_destroy(a, NULL); rj_state_destroy(b, NULL); rj_model_destroy(m, NULL);
}

/* 8. A nearly massless rigid link between two flexible ones (rod 1e-6 of its density),
   with stiff joint springs: the automatic step must stay stable, the accounts close. */
static void test_light_body(void)
{
    rj_link_def L[3];
    rj_joint_def J[2];
    rj_model *m;
    rj_state *s = NULL;
    rj_energy en;
    rj_result r;
    char msg[600];
    int i;
    for (i = 0; i < 3; i++) { L[i] = rj_default_link_def(); L[i].height = 0.01; L[i].elements = 8; }
    L[0].root = RJ_ROOT_PINNED; L[0].omega = 3; L[1].fidelity = RJ_LINK_RIGID; L[1].rho *= 1e-6; L[1].length = 0.2;
    for (i = 0; i < 2; i++) { J[i] = rj_default_joint_def(); J[i].body1 = i; J[i].body2 = i + 1; J[i].angle0 = 3.0 - 0.5 * i; J[i].spring_k = 200; }
    m = build(L, 3, J, 2, 0, msg, sizeof msg);
    if (!rjt_check(&T, m != NULL, "light rigid link between flexible ones builds", "%s", msg)) return;
    rj_state_create(m, &s, NULL);
    r = rj_run(m, s, 2.0, 0, NULL, NULL);
    rj_state_energy(m, s, &en);
    /* an unstable mode would grow by orders of magnitude; a stable run keeps the leapfrog's
       O(dt^2) energy error: 9e-5 here, 1.5e-4 with the rod at its normal density and 7e-6
       for three flexible links at their own (6x smaller) step */
    rjt_check(&T, r == RJ_OK && fabs(en.balance) < 1e-3 * en.total, "light rigid link (1e-6 density) between flexible ones: stable at the automatic step",
              "%s%s; dt %.3g s; energy balance %.3g J of %.4g J (bound 1e-3 of it)", rj_result_str(r), rj_state_error(s), rj_model_dt(m), en.balance, en.total);
    rj_state_destroy(s, NULL); rj_model_destroy(m, NULL);
}

/* 9. An inextensible link held fixed with an inextensible child: the chain's elements
   between two fixed nodes are not constraints to solve (they were a division by zero). */
static void test_fixed_inextensible(void)
{
    rj_link_def L[2];
    rj_joint_def J[1];
    rj_model *m;
    rj_state *s = NULL;
    rj_energy en;
    rj_result r;
    char msg[600];
    double worst = 0;
    int i;
    for (i = 0; i < 2; i++) { L[i] = rj_default_link_def(); L[i].height = 0.01; L[i].elements = 6; L[i].fidelity = RJ_LINK_INEXTENSIBLE; }
    L[0].root = RJ_ROOT_FIXED;
    J[0] = rj_default_joint_def(); J[0].body1 = 0; J[0].body2 = 1; J[0].angle0 = 2.0; J[0].rate0 = 3.0; J[0].spring_k = 5;
    m = build(L, 2, J, 1, 0, msg, sizeof msg);
    if (!rjt_check(&T, m != NULL, "fixed inextensible link with an inextensible child builds", "%s", msg)) return;
    rj_state_create(m, &s, NULL);
    r = rj_run(m, s, 1.0, 0, NULL, NULL);
    for (i = 0; i < 6; i++) {
        double a[2], b[2];
        rj_node_position(m, s, 1, i, a); rj_node_position(m, s, 1, i + 1, b);
        worst = fmax(worst, fabs(hypot(b[0] - a[0], b[1] - a[1]) / (1.0 / 6) - 1));
    }
    rj_state_energy(m, s, &en);
    rjt_check(&T, r == RJ_OK && worst < 1e-12 && fabs(en.balance) < 1e-4 * en.total, "fixed inextensible link with an inextensible child: runs, keeps the child's lengths, conserves energy",
              "%s%s; element lengths within %.2g; balance %.3g J of %.4g J", rj_result_str(r), rj_state_error(s), worst, en.balance, en.total);
    rj_state_destroy(s, NULL); rj_model_destroy(m, NULL);
}

/* 10. The automatic step with adaptive limits is one the library accepts when given
   explicitly (it was not, for a chord-reference scene: the search stopped after six passes
   with a stale K_AP); rigid links whose adaptive limits have no stable step say so. */
static void test_adaptive_auto_dt(void)
{
    int ref, ok = 1, k = 0;
    char d[600];
    size_t o = 0;
    for (ref = 0; ref < 2; ref++) {
        deploy_opts op = deploy_default_opts();
        rj_link_def l[2];
        rj_joint_def j[2];
        rj_scene_def sc;
        rj_model *m;
        rj_error err;
        double dt;
        op.joint2_method = RJ_METHOD_ADAPTIVE; op.joint1_method = RJ_METHOD_ADAPTIVE;
        deploy_scene(&op, l, j, &sc);
        j[0].reference = j[1].reference = ref ? RJ_REF_CHORD : RJ_REF_TANGENT;
        j[0].friction = j[1].friction = 0.05; j[1].damping = 0.01;
        sc.solver.dt = 0;
        if (rj_model_create(&sc, &m, &err, NULL) != RJ_OK) { ok = 0; o += (size_t)snprintf(d + o, sizeof d - o, "%s: %s; ", ref ? "chord" : "tangent", err.msg); continue; }
        dt = rj_model_dt(m);
        rj_model_destroy(m, NULL);
        sc.solver.dt = dt;
        if (rj_model_create(&sc, &m, &err, NULL) != RJ_OK) { ok = 0; o += (size_t)snprintf(d + o, sizeof d - o, "%s: automatic %.6g s refused explicitly: %s; ", ref ? "chord" : "tangent", dt, err.msg); continue; }
        o += (size_t)snprintf(d + o, sizeof d - o, "%s: %.6g s accepted; ", ref ? "chord" : "tangent", dt);
        rj_model_destroy(m, NULL);
        k++;
    }
    rjt_check(&T, ok && k == 2, "adaptive limits: the automatic step is accepted when given explicitly (tangent and chord references)", "%s", d);
    {
        deploy_opts op = deploy_default_opts();
        rj_link_def l[2];
        rj_joint_def j[2];
        rj_scene_def sc;
        rj_model *m = NULL;
        rj_error err;
        rj_result r;
        op.joint2_method = RJ_METHOD_ADAPTIVE; op.joint1_method = RJ_METHOD_ADAPTIVE;
        deploy_scene(&op, l, j, &sc);
        l[0].fidelity = l[1].fidelity = RJ_LINK_RIGID;
        sc.solver.dt = 0;
        r = rj_model_create(&sc, &m, &err, NULL);
        if (r == RJ_OK) rj_model_destroy(m, NULL);
        rjt_check(&T, r == RJ_ERR_UNSTABLE_DT ? strstr(err.msg, "no stable step for the adaptive limits") != NULL : r == RJ_OK,
                  "rigid links with adaptive limits: a stable automatic step, or a refusal that says why", "%s", r == RJ_OK ? "built" : err.msg);
    }
}

/* 11. The stability bound's operator: the elements' tangent in closed form
   (rj__lz_elements) against central differences of the beam pass itself, on every node
   DOF at once along a random move, at the scenes' starts and at a start stretched 1 % and
   bent (a stressed start: the axial force's and the moments' geometric terms); and the
   element-by-element bound above omega_max^2. */
static void bound_bend(rj_model *m, double stretch, double bend)
{
    int l, i, k;
    for (l = 0; l < m->nl; l++) {
        const int n0 = m->link_first[l];
        for (i = n0 + 1; i < m->link_first[l + 1]; i++) {
            m->x0[i] = m->x0[n0] + stretch * (m->x0[i] - m->x0[n0]);
            m->y0[i] = m->y0[n0] + stretch * (m->y0[i] - m->y0[n0]);
            m->phi0[i] += bend * (i - n0);
        }
        for (k = m->link_efirst[l]; k < m->link_efirst[l + 1]; k++) {
            const int a = n0 + (k - m->link_efirst[l]);
            const double chord = atan2(m->y0[a + 1] - m->y0[a], m->x0[a + 1] - m->x0[a]);
            m->beta0[k] = m->phi0[a] + rj__wrap(chord - m->phi0[a]);
        }
    }
}

/* f += -(forces at x0 + h d) / (2 h), sign s = +1 or -1 (central differences), by root. */
static void bound_fd_side(const rj_model *m, const double *d, double h, double *f, double *w)
{
    const int nn = m->nn, ne = m->ne;
    double *x = w, *y = x + nn, *p = y + nn, *fx = p + nn, *fy = fx + nn, *mz = fy + nn;
    double *cx = mz + nn, *cy = cx + ne, *eu = cy + ne, *bt = eu + ne, *cxo = bt + ne, *cyo = cxo + ne;
    int i, l, k;
    for (i = 0; i < nn; i++) {
        const int r = 3 * rj__ub_root(m, i);
        x[i] = m->x0[i] + h * d[r];
        y[i] = m->y0[i] + h * d[r + 1];
        p[i] = m->phi0[i] + h * d[3 * i + 2];
    }
    for (l = 0; l < m->nl; l++)
        for (k = m->link_efirst[l]; k < m->link_efirst[l + 1]; k++) {
            const int a = m->link_first[l] + (k - m->link_efirst[l]);
            cx[k] = m->x0[a + 1] - m->x0[a];
            cy[k] = m->y0[a + 1] - m->y0[a];
        }
    rj__beam_pass(m, x, y, p, m->beta0, cx, cy, eu, bt, cxo, cyo, fx, fy, mz, NULL);
    for (i = 0; i < nn; i++) {
        const int r = 3 * rj__ub_root(m, i);
        f[r] += -fx[i] / (2 * h);
        f[r + 1] += -fy[i] / (2 * h);
        f[3 * i + 2] += -mz[i] / (2 * h);
    }
}

static void bound_scene(const char *path, double stretch, double bend)
{
    rj_scene_file file;
    rj_scene_def sc;
    rj_error err;
    rj_model *m = NULL;
    double *d, *fc, *fd, *w, num = 0, den = 0, upper, om2;
    char name[200];
    int i, n;
    unsigned seed = 12345;
    if (rj_scene_load(path, &file, &err) != RJ_OK) { rjt_check(&T, 0, path, "%s", err.msg); return; }
    sc = rj_scene_file_def(&file);
    if (rj_model_create(&sc, &m, &err, NULL) != RJ_OK) { rjt_check(&T, 0, path, "%s", err.msg); rj_scene_file_free(&file); return; }
    n = 3 * m->nn;
    d = (double *)calloc((size_t)n, sizeof(double)); fc = (double *)calloc((size_t)n, sizeof(double));
    fd = (double *)calloc((size_t)n, sizeof(double)); w = (double *)calloc((size_t)(6 * m->nn + 6 * m->ne + 8), sizeof(double));
    if (!d || !fc || !fd || !w) abort();
    if (stretch != 1 || bend != 0) bound_bend(m, stretch, bend);
    /* a move of each DOF in its own scale: a tenth of its link's element, or 0.1 rad */
    for (i = 0; i < m->nn; i++) {
        int link, node, c;
        rj__node_of(m, i, &link, &node);
        for (c = 0; c < 3; c++) {
            seed = seed * 1103515245u + 12345u;
            d[3 * i + c] = ((double)(seed >> 8) / 16777216.0 - 0.5) * (c == 2 ? 0.2 : 0.2 * m->link_l0[link]);
        }
    }
    rj__lz_elements(m, d, fc);
    bound_fd_side(m, d, 1e-6, fd, w);
    bound_fd_side(m, d, -1e-6, fd, w);
    for (i = 0; i < m->nn; i++) {
        const int r = 3 * rj__ub_root(m, i);
        int c;
        if (r != 3 * i) continue; /* a grouped node's translation is its root's */
        for (c = 0; c < 3; c++) { num += (fc[3 * i + c] - fd[3 * i + c]) * (fc[3 * i + c] - fd[3 * i + c]); den += fd[3 * i + c] * fd[3 * i + c]; }
    }
    for (i = 0; i < m->nn; i++) { num += (fc[3 * i + 2] - fd[3 * i + 2]) * (fc[3 * i + 2] - fd[3 * i + 2]) * (3 * rj__ub_root(m, i) != 3 * i); }
    snprintf(name, sizeof name, "bound operator: closed-form tangent = differences of the beam pass, %s%s", path,
             stretch != 1 ? " stretched 1 % and bent" : "");
    rjt_check(&T, den > 0 && sqrt(num / den) < 1e-6, name, "relative difference %.2e over %d DOFs", sqrt(num / den), n);
    if (stretch == 1 && bend == 0) {
        upper = rj__omega2_upper(m, w);
        om2 = rj_model_omega_max(m) * rj_model_omega_max(m);
        snprintf(name, sizeof name, "element-by-element bound above Lanczos's omega_max^2, %s", path);
        rjt_check(&T, upper >= om2 * (1 - 1e-9) && upper < HUGE_VAL, name, "upper %.6g, omega_max^2 %.6g (x %.4f)", upper, om2, upper / om2);
    }
    free(d); free(fc); free(fd); free(w);
    rj_model_destroy(m, NULL);
    rj_scene_file_free(&file);
}

static void test_bound(void)
{
    static const char *const scenes[] = { "examples/scenes/deploy.rjs", "examples/scenes/elastica.rjs",
                                          "examples/scenes/solar_array_yield.rjs", "examples/scenes/scissor_boom.rjs",
                                          "examples/scenes/solar_array_ccl.rjs" };
    int i;
    for (i = 0; i < 5; i++) bound_scene(scenes[i], 1.0, 0.0);
    bound_scene("examples/scenes/deploy.rjs", 1.01, 0.02);
    bound_scene("examples/scenes/elastica.rjs", 1.01, 0.02);
}

/* 12. Rigid trees by articulated bodies (rj__aba_*), against the dense M and its Cholesky
   factor on the same model: a branched tree of 16 links (a trunk of 8, a branch of 4 from
   the third link's middle, one of 4 from the sixth's tip) with springs, dampers,
   friction, latches by momentum, a servo with a rotor, gravity and tip masses. M^-1 b and
   M x at the start, and whole runs. */
static rj_result tree_scene(rj_link_def *L, rj_joint_def *J, rj_actuator_def *A, rj_model **m)
{
    rj_scene_def sc = rj_default_scene_def();
    rj_error err;
    int i;
    for (i = 0; i < 16; i++) {
        L[i] = rj_default_link_def();
        L[i].length = 0.2 + 0.01 * i; L[i].elements = 2; L[i].rho = 2700; L[i].width = 0.02; L[i].height = 0.01;
        L[i].fidelity = RJ_LINK_RIGID; L[i].tip_mass = 0.05 * (i % 3);
        J[i] = rj_default_joint_def();
        J[i].body1 = i - 1; J[i].body2 = i; J[i].angle0 = rj_rad(180.0 + 10.0 * ((i % 4) - 1.5));
        J[i].spring_k = 2.0 + 0.3 * i; J[i].spring_free_angle = rj_rad(180.0); J[i].damping = 0.002 * (i % 2);
        J[i].friction = i % 3 == 0 ? 0.01 : 0.0;
    }
    J[0].body1 = -1; J[0].angle0 = rj_rad(-80.0); J[0].spring_free_angle = rj_rad(-60.0);
    J[8].body1 = 2; J[8].node1 = 1;   /* a branch from the third link's middle */
    J[12].body1 = 5; J[12].node1 = -1; /* and one from the sixth's tip */
    J[4].has_forward = 1; J[4].forward = rj_rad(184.0); J[4].method = RJ_METHOD_MOMENTUM; J[4].restitution = 0.3;
    J[10].has_reverse = 1; J[10].reverse = rj_rad(170.0); J[10].method = RJ_METHOD_MOMENTUM; J[10].lock = 1;
    A[0] = rj_default_actuator_def();
    A[0].joint = 6; A[0].type = RJ_ACTUATOR_SERVO; A[0].kp = 3.0; A[0].kd = 0.05; A[0].target = rj_rad(170.0);
    A[0].rotor_inertia = 1e-5; A[0].gear_ratio = 20;
    sc.links = L; sc.link_count = 16; sc.joints = J; sc.joint_count = 16;
    sc.actuators = A; sc.actuator_count = 1;
    sc.solver.gravity[1] = -9.81; sc.solver.dt = 2e-4;
    return rj_model_create(&sc, m, &err, NULL);
}

static void test_articulated(void)
{
    rj_link_def L[16];
    rj_joint_def J[16];
    rj_actuator_def A[1];
    rj_model *ma = NULL, *md = NULL;
    rj_state *sa = NULL, *sd = NULL;
    rj__rig ra, rd;
    double b[16], xa[16], xd[16], ya[16], yd[16], worst_x = 0, worst_y = 0, big_x = 0, big_y = 0, worst_q = 0, ea = 0, ed = 0;
    int k, step, contacts4 = 0;
    if (tree_scene(L, J, A, &ma) != RJ_OK || tree_scene(L, J, A, &md) != RJ_OK) { rjt_check(&T, 0, "articulated tree: builds", "no model"); return; }
    rjt_check(&T, ma->rig_tree == 1 && ma->nq == 16, "articulated tree: a 16-coordinate rigid tree is solved by articulated bodies", "rig_tree %d, nq %d (from %d)", ma->rig_tree, ma->nq, RJ__RIG_TREE_MIN);
    md->rig_tree = 0; /* the same model, solved densely: its state, made after, holds M and L */
    if (rj_state_create(ma, &sa, NULL) != RJ_OK || rj_state_create(md, &sd, NULL) != RJ_OK) return;
    /* M^-1 b and M x at the start: articulated bodies in ma's scratch, which holds no n x n
       matrix, the dense M in md's */
    rj__rig_map(ma, sa->rsc, &ra, 1);
    rj__rig_map(md, sd->rsc, &rd, 1);
    rjt_check(&T, ra.M == NULL && ra.L == NULL && rd.M != NULL &&
                  rj_state_size(ma) < rj_state_size(md),
              "articulated tree: its scratch holds no n x n M or factor, the dense solver's does",
              "M %p L %p (dense M %p); state %lu bytes, dense %lu",
              (void *)ra.M, (void *)ra.L, (void *)rd.M,
              (unsigned long)rj_state_size(ma), (unsigned long)rj_state_size(md));
    for (k = 0; k < 16; k++) {
        ra.q[k] = rd.q[k] = ma->jdef[ma->qj[k]].angle0;
        ra.qd[k] = ra.qdp[k] = rd.qd[k] = rd.qdp[k] = 0;
        b[k] = sin(1.0 + k);
    }
    rj__rig_kin(ma, &ra, ra.q, ra.qd, ra.qdp);
    rj__rig_kin(md, &rd, rd.q, rd.qd, rd.qdp);
    rj__rig_factor(ma, &ra); rj__rig_solve(ma, &ra, b, xa); rj__rig_mul(ma, &ra, b, ya);
    rj__rig_factor(md, &rd); rj__rig_solve(md, &rd, b, xd); rj__rig_mul(md, &rd, b, yd);
    for (k = 0; k < 16; k++) {
        if (fabs(xa[k] - xd[k]) > worst_x) worst_x = fabs(xa[k] - xd[k]);
        if (fabs(ya[k] - yd[k]) > worst_y) worst_y = fabs(ya[k] - yd[k]);
        if (fabs(xd[k]) > big_x) big_x = fabs(xd[k]);
        if (fabs(yd[k]) > big_y) big_y = fabs(yd[k]);
    }
    /* both solves are backward stable, so they differ by about cond(M) eps: 5.5e-13 of the
       largest entry for this tree */
    rjt_check(&T, worst_x <= 1e-10 * big_x, "articulated tree: M^-1 b equals the dense Cholesky solve", "max |diff| %.2e of %.3g", worst_x, big_x);
    rjt_check(&T, worst_y <= 1e-12 * big_y, "articulated tree: M x equals the dense product", "max |diff| %.2e of %.3g", worst_y, big_y);
    /* 1 s: both latch (joint 4 bounces, joint 10 locks), the servo's rotor turns */
    for (step = 0; step < 5000; step++) {
        if (rj_step(ma, sa) != RJ_OK || rj_step(md, sd) != RJ_OK) break;
        for (k = 0; k < 16; k++) {
            const double d = fabs(rj_joint_theta_running(ma, sa, k) - rj_joint_theta_running(md, sd, k));
            if (d > worst_q) worst_q = d;
        }
        contacts4 += rj_joint_flag(ma, sa, 4) != RJ_FREE;
    }
    {
        rj_energy e1, e2;
        rj_state_energy(ma, sa, &e1); rj_state_energy(md, sd, &e2);
        ea = e1.balance; ed = e2.balance;
    }
    rjt_check(&T, step == 5000 && worst_q < 1e-9 && contacts4 > 0 && rj_joint_flag(ma, sa, 10) == RJ_LOCKED,
              "articulated tree: 1 s of springs, friction, latches and a servo's rotor follow the dense solve",
              "%d steps, max |theta - theta_dense| %.2e rad; joint 4 at its limit in %d steps, joint 10 flag %d (locked %d)",
              step, worst_q, contacts4, rj_joint_flag(ma, sa, 10), RJ_LOCKED);
    rjt_check(&T, fabs(ea - ed) < 1e-9, "articulated tree: the energy balance is the dense one's", "balance %.6e J (dense %.6e J)", ea, ed);
    rj_state_destroy(sa, NULL); rj_state_destroy(sd, NULL);
    rj_model_destroy(ma, NULL); rj_model_destroy(md, NULL);
}

/* 13. Rigid chains in memory linear in their links: n rigid links (0.1 m, one element,
   hanging under gravity), a spring on every joint, friction on every fifth, and a latch
   by momentum (a reverse limit 0.5 deg back, met at 1 rad/s, e = 0.3) on every 97th,
   which locks there on the odd ones; joint 0 has friction and a latch. Articulated
   bodies keep a column of M^-1 for each latching joint alone and size the rows' system
   by them. */
/* The chain's latching joints: every 97th from joint 0. */
static int chain_latches(int n)
{
    return (n + 96) / 97;
}

/* The chain of n links, its rj_model_size into *bytes. */
static rj_result long_chain(int n, rj_link_def *L, rj_joint_def *J, rj_model **m,
                            size_t *bytes)
{
    rj_scene_def sc = rj_default_scene_def();
    rj_error err;
    int i;
    for (i = 0; i < n; i++) {
        L[i] = rj_default_link_def();
        L[i].length = 0.1; L[i].elements = 1; L[i].fidelity = RJ_LINK_RIGID;
        J[i] = rj_default_joint_def();
        J[i].body1 = i - 1; J[i].body2 = i; J[i].angle0 = rj_rad(i ? 185.0 : 300.0);
        J[i].spring_k = 1.0; J[i].spring_free_angle = rj_rad(i ? 180.0 : 270.0);
        J[i].friction = i % 5 == 0 ? 1e-3 : 0.0;
        if (i % 97 == 0) {
            J[i].has_reverse = 1; J[i].reverse = rj_rad(i ? 184.5 : 299.5); J[i].rate0 = -1.0;
            J[i].method = RJ_METHOD_MOMENTUM; J[i].restitution = 0.3; J[i].lock = i % 2;
        }
    }
    sc.links = L; sc.link_count = n; sc.joints = J; sc.joint_count = n;
    sc.solver.gravity[1] = -9.81; sc.solver.dt = 1e-4;
    *bytes = rj_model_size(&sc, &err);
    return rj_model_create(&sc, m, &err, NULL);
}

/* Steps model m from state s; returns the steps made (of count) and counts in *latched
   the steps that end with a latching joint off its free flag. */
static int chain_run(const rj_model *m, rj_state *s, int count, int *latched)
{
    int step, j;
    for (step = 0; step < count; step++) {
        if (rj_step(m, s) != RJ_OK)
            break;
        for (j = 0; j < m->nj; j += 97)
            *latched += rj_joint_flag(m, s, j) != RJ_FREE;
    }
    return step;
}

/* A chain of 1000 links: its model and state below 8 kB a link (measured 4.1 kB; one n x n
   matrix of doubles alone adds 8 kB a link at this n, so the bound fails with any, as it
   did with the dense scratch's, 92 kB a link), and 300 steps. */
static void test_chain_memory(void)
{
    const int n = 1000;
    rj_link_def *L = (rj_link_def *)malloc(sizeof *L * (size_t)n);
    rj_joint_def *J = (rj_joint_def *)malloc(sizeof *J * (size_t)n);
    rj_model *m = NULL;
    rj_state *s = NULL;
    size_t model_bytes = 0, state_bytes;
    int steps, latched = 0;
    if (!L || !J || long_chain(n, L, J, &m, &model_bytes) != RJ_OK ||
        rj_state_create(m, &s, NULL) != RJ_OK) {
        rjt_check(&T, 0, "rigid chain of 1000 links: builds", "no model or state");
        free(L); free(J); rj_model_destroy(m, NULL);
        return;
    }
    state_bytes = rj_state_size(m);
    rjt_check(&T, model_bytes + state_bytes < 8000 * (size_t)n,
              "rigid chain of 1000 links: model and state below 8 kB a link (linear in the links)",
              "model %lu + state %lu bytes = %.0f bytes a link",
              (unsigned long)model_bytes, (unsigned long)state_bytes,
              (double)(model_bytes + state_bytes) / n);
    rjt_check(&T, m->rig_tree && m->nwcol == chain_latches(n) && m->rig_rows == chain_latches(n),
              "rigid chain of 1000 links: a column of M^-1 and a row for each latching joint alone",
              "rig_tree %d, columns %d, rows %d, latching joints %d",
              m->rig_tree, m->nwcol, m->rig_rows, chain_latches(n));
    steps = chain_run(m, s, 300, &latched);
    rjt_check(&T, steps == 300 && latched > 0,
              "rigid chain of 1000 links: 300 steps, its latches engaged",
              "%d steps (%s), %d joint-steps off the free flag", steps, rj_state_error(s), latched);
    rj_state_destroy(s, NULL); rj_model_destroy(m, NULL);
    free(L); free(J);
}

/* The same chain of 100 links by articulated bodies and by the dense solver (the switch
   flipped before the state is made): 400 steps of friction, bounces and a lock alike. */
static void test_chain_dense(void)
{
    enum { N = 100 };
    static rj_link_def L[N];
    static rj_joint_def J[N];
    rj_model *ma = NULL, *md = NULL;
    rj_state *sa = NULL, *sd = NULL;
    size_t bytes;
    double worst = 0, big = 0;
    int k, steps = 0, latched = 0, dense_latched = 0;
    if (long_chain(N, L, J, &ma, &bytes) != RJ_OK || long_chain(N, L, J, &md, &bytes) != RJ_OK) {
        rjt_check(&T, 0, "rigid chain of 100 links: builds", "no model");
        rj_model_destroy(ma, NULL);
        return;
    }
    md->rig_tree = 0;
    if (rj_state_create(ma, &sa, NULL) == RJ_OK && rj_state_create(md, &sd, NULL) == RJ_OK)
        for (steps = 0; steps < 400; steps++) {
            if (chain_run(ma, sa, 1, &latched) != 1 || chain_run(md, sd, 1, &dense_latched) != 1)
                break;
            for (k = 0; k < N; k++) {
                const double a = rj_joint_theta_running(ma, sa, k);
                const double d = rj_joint_theta_running(md, sd, k);
                worst = fmax(worst, fabs(a - d));
                big = fmax(big, fabs(d - J[k].angle0));
            }
        }
    rjt_check(&T, steps == 400 && latched > 0 && latched == dense_latched && worst < 1e-9 &&
              rj_joint_flag(ma, sa, 97) == RJ_LOCKED && rj_joint_flag(md, sd, 97) == RJ_LOCKED,
              "rigid chain of 100 links: articulated bodies step as the dense solver "
              "(friction, bounces, a lock)",
              "%d steps; max |theta - theta_dense| %.2e rad (turns up to %.3g rad); "
              "latched joint-steps %d (dense %d); joint 97's flag %d (dense %d, locked %d)",
              steps, worst, big, latched, dense_latched,
              rj_joint_flag(ma, sa, 97), rj_joint_flag(md, sd, 97), RJ_LOCKED);
    rj_state_destroy(sa, NULL); rj_state_destroy(sd, NULL);
    rj_model_destroy(ma, NULL); rj_model_destroy(md, NULL);
}

/* The implicit damping's element matrix (rj__visc_elem, src/viscous.h) against the
   viscous forces of the lagged path and of the loads queries (rj__elem_viscous): -C_e q
   is node a's (-f, -m_a) and node b's (f, -m_b), for chords and rates drawn at random
   (axial and bending constants of a 0.1 m aluminium strip, eta 1e-3 s). A sign or a
   factor wrong in either would show at once. */
static void test_viscous_matrix(void)
{
    const double kc[4] = { 116.7 / 0.1, 70e9 * 2e-4 / 0.1, 0.01, 1.0 / (2 * 0.01) };
    const double eta = 1e-3;
    double worst = 0;
    unsigned seed = 12345u;
    int t, p;
    for (t = 0; t < 200; t++) {
        double r[8], C[27], q[6], cq[6];
        rj__elem_force f;
        for (p = 0; p < 8; p++) {
            seed = seed * 1103515245u + 12345u;
            r[p] = (double) ((seed >> 8) % 20001) / 10000.0 - 1.0;
        }
        /* a chord near 0.1 m in any direction, node rates in m/s and rad/s */
        r[0] = 0.1 * cos(3.2 * r[0]) + 0.001 * r[1];
        r[1] = 0.1 * sin(3.2 * r[1]) + 0.001 * r[0];
        for (p = 0; p < 6; p++)
            q[p] = r[2 + p];
        rj__visc_elem(kc, eta, r[0], r[1], C);
        for (p = 0; p < 3; p++) {
            int k;
            cq[p] = cq[p + 3] = 0;
            for (k = 0; k < 3; k++) {
                cq[p] += C[3 * p + k] * q[k] + C[9 + 3 * p + k] * q[3 + k];
                cq[p + 3] += C[9 + 3 * k + p] * q[k] + C[18 + 3 * p + k] * q[3 + k];
            }
        }
        rj__elem_viscous(kc, eta, r[0], r[1], 1.0 / (r[0] * r[0] + r[1] * r[1]), q[3] - q[0],
                         q[4] - q[1], q[2], q[5], &f);
        {
            const double want[6] = { f.fx, f.fy, f.ma, -f.fx, -f.fy, f.mb };
            double scale = 0;
            for (p = 0; p < 6; p++)
                scale = fmax(scale, fabs(want[p]));
            for (p = 0; p < 6; p++)
                worst = fmax(worst, fabs(cq[p] - want[p]) / scale);
        }
    }
    rjt_check(&T, worst < 1e-12, "implicit damping: C_e q is the lagged path's viscous forces",
              "200 elements: largest difference %.3g of the largest force", worst);
}

/* The largest eigenvalue of a symmetric 6 x 6 matrix by cyclic Jacobi (the test's own
   reference). */
static double jacobi6_top(double A[36])
{
    int sweep, p, q, k;
    double top;
    for (sweep = 0; sweep < 50; sweep++)
        for (p = 0; p < 5; p++)
            for (q = p + 1; q < 6; q++) {
                const double apq = A[6 * p + q];
                double theta, t, cs, sn;
                if (apq == 0)
                    continue;
                theta = (A[6 * q + q] - A[6 * p + p]) / (2.0 * apq);
                t = (theta >= 0 ? 1.0 : -1.0) / (fabs(theta) + sqrt(theta * theta + 1.0));
                cs = 1.0 / sqrt(t * t + 1.0);
                sn = t * cs;
                for (k = 0; k < 6; k++) {
                    const double akp = A[6 * k + p], akq = A[6 * k + q];
                    A[6 * k + p] = cs * akp - sn * akq;
                    A[6 * k + q] = sn * akp + cs * akq;
                }
                for (k = 0; k < 6; k++) {
                    const double apk = A[6 * p + k], aqk = A[6 * q + k];
                    A[6 * p + k] = cs * apk - sn * aqk;
                    A[6 * q + k] = sn * apk + cs * aqk;
                }
            }
    top = A[0];
    for (p = 1; p < 6; p++)
        if (A[7 * p] > top)
            top = A[7 * p];
    return top;
}

/* The upper bound's 6 x 6 eigenvalue (rj__ub_eig6: Householder, then Newton from above)
   against Jacobi on 1000 symmetric matrices: random ones, rank 3 (an element's stiffness
   without its rigid motions), ones with a double top, and a NaN entry. */
static void test_eig6(void)
{
    unsigned long long z = 777;
    double worst = 0;
    int t, i, j, bad = 0;
    for (t = 0; t < 1000; t++) {
        double A[36], B[36], C[36], top, ref, big = 0;
        for (i = 0; i < 6; i++)
            for (j = 0; j <= i; j++) {
                z = z * 6364136223846793005ULL + 1442695040888963407ULL;
                A[6 * i + j] = A[6 * j + i] = (double) (z >> 11) / 9007199254740992.0 - 0.5;
            }
        if (t % 3 == 1) {
            /* G G^T with G 6 x 3: rank 3, positive semidefinite */
            for (i = 0; i < 6; i++)
                for (j = 0; j < 6; j++)
                    B[6 * i + j] = A[6 * i] * A[6 * j] + A[6 * i + 1] * A[6 * j + 1] +
                                   A[6 * i + 2] * A[6 * j + 2];
            memcpy(A, B, sizeof A);
        } else if (t % 3 == 2) {
            /* diag(2, 2, 1, ...) turned by a Householder reflection: a double top */
            double v[6], nv = 0;
            for (i = 0; i < 6; i++) {
                v[i] = A[i];
                nv += v[i] * v[i];
            }
            for (i = 0; i < 6; i++)
                for (j = 0; j < 6; j++) {
                    double sum = 0;
                    int k;
                    for (k = 0; k < 6; k++) {
                        const double hik = (i == k) - 2.0 * v[i] * v[k] / nv;
                        const double hjk = (j == k) - 2.0 * v[j] * v[k] / nv;
                        sum += hik * (k < 2 ? 2.0 : 1.0 / (k + 1)) * hjk;
                    }
                    A[6 * i + j] = sum;
                }
        }
        for (i = 0; i < 36; i++)
            if (fabs(A[i]) > big)
                big = fabs(A[i]);
        memcpy(B, A, sizeof A);
        memcpy(C, A, sizeof A);
        top = rj__ub_eig6(B);
        ref = jacobi6_top(C);
        if (!(fabs(top - ref) <= 1e-12 * big))
            bad++;
        if (fabs(top - ref) / big > worst)
            worst = fabs(top - ref) / big;
    }
    {
        double A[36] = { 0 };
        A[7] = NAN;
        rjt_check(&T, bad == 0 && rj__ub_eig6(A) != rj__ub_eig6(A),
                  "upper bound's 6 x 6 top eigenvalue: Jacobi's to 1e-12 on 1000 matrices, NaN for a NaN entry",
                  "%d off; worst %.2e of the largest entry", bad, worst);
    }
}

/* Each joint's 1 / I_red of an articulated tree, taken in O(n) from the factor
   (rj__rig_tree_minv), against the diagonal of M^-1 column by column (rj__rig_unit, a
   solve with b = e_k) on the 16-coordinate tree with branches and a servo's rotor. */
static void test_tree_minv(void)
{
    rj_link_def L[16];
    rj_joint_def J[16];
    rj_actuator_def A[1];
    rj_model *m = NULL;
    rj_state *s = NULL;
    rj__rig r;
    double col[16], worst = 0, big = 0;
    int k;
    if (tree_scene(L, J, A, &m) != RJ_OK || rj_state_create(m, &s, NULL) != RJ_OK) {
        rjt_check(&T, 0, "tree 1 / I_red: builds", "no model");
        return;
    }
    rj__rig_map(m, s->rsc, &r, 1);
    for (k = 0; k < m->nq; k++) {
        r.q[k] = m->jdef[m->qj[k]].angle0;
        r.qd[k] = r.qdp[k] = 0;
    }
    rj__rig_kin(m, &r, r.q, r.qd, r.qdp);
    rj__rig_factor(m, &r);
    for (k = 0; k < m->nq; k++) {
        const double minv = m->jnt[m->qj[k]].minv;
        rj__rig_unit(m, &r, k, col);
        if (fabs(minv - col[k]) > worst)
            worst = fabs(minv - col[k]);
        if (fabs(col[k]) > big)
            big = fabs(col[k]);
    }
    rjt_check(&T, m->rig_tree && big > 0 && worst <= 1e-12 * big,
              "articulated tree: each 1 / I_red in O(n) equals M^-1's diagonal by columns",
              "max |diff| %.2e of %.3g over %d coordinates", worst, big, m->nq);
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
}

/* The convergence checks' top eigenvalue (rj__tridiag_top: bisection to isolate it, then
   Newton from above) against plain bisection to 1e-14 on 2000 tridiagonal matrices:
   random ones, ones with their top two eigenvalues 1e-9 apart (a clustered top), and
   scales from 1e-160 to 1e160. It must be within 1e-11 of itself above the top, never
   below it by more than round-off; and the bisection it spares counts
   (rj__tridiag_max_near) must give the bits of the one that counts every time. */
static void test_tridiag_top(void)
{
    double worst_above = 0, worst_below = 0;
    unsigned long long z = 12345;
    int t, i, bad = 0, differ = 0;
    for (t = 0; t < 2000; t++) {
        double al[RJ__LANCZOS_ITERS], be[RJ__LANCZOS_ITERS], ref, top, scale;
        const int k = 2 + t % 60;
        scale = pow(10.0, -160.0 + 320.0 * (t % 17) / 16.0);
        for (i = 0; i < k; i++) {
            z = z * 6364136223846793005ULL + 1442695040888963407ULL;
            al[i] = scale * (double) (z >> 11) / 9007199254740992.0;
            z = z * 6364136223846793005ULL + 1442695040888963407ULL;
            be[i] = scale * 0.5 * (double) (z >> 11) / 9007199254740992.0;
        }
        if (t % 3 == 1) {
            /* two uncoupled blocks with the same top: a cluster of two */
            be[k / 2 - 1] = 0;
            al[0] = al[k / 2] = 3.0 * scale;
            al[k / 2] += 1e-9 * al[0];
        }
        ref = rj__tridiag_max(al, be, k);
        top = rj__tridiag_top(al, be, k, 1e-11);
        differ += rj__tridiag_max_near(al, be, k, top) != ref;
        if (!((top - ref) / ref <= 1e-11 && (ref - top) / ref <= 1e-14))
            bad++;
        if ((top - ref) / ref > worst_above)
            worst_above = (top - ref) / ref;
        if ((ref - top) / ref > worst_below)
            worst_below = (ref - top) / ref;
    }
    rjt_check(&T, bad == 0,
              "tridiagonal top by Newton from above: within 1e-11 of bisection on 2000 matrices",
              "%d off; worst %.2e above, %.2e below", bad, worst_above, worst_below);
    rjt_check(&T, differ == 0,
              "tridiagonal top: bisection that skips the counts Newton settles, the same bits",
              "%d of 2000 differ", differ);
}

int main(void)
{
    test_pendulum();
    test_free_body();
    test_bus();
    test_stiff_limit();
    test_rigid_inext();
    test_refusals();
    test_checkpoint();
    test_light_body();
    test_fixed_inextensible();
    test_adaptive_auto_dt();
    test_bound();
    test_articulated();
    test_chain_memory();
    test_chain_dense();
    test_viscous_matrix();
    test_tridiag_top();
    test_tree_minv();
    test_eig6();
    return rjt_summary(&T, "test_mixed");
}
