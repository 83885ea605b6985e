/* scenes.h - the paper's two benchmarks as scene builders, shared by the examples, the
   tests and the benchmarks (one definition of each problem in the project).
   Include after revjoint.h. Everything static; no allocation. */
#ifndef RJ_SCENES_H
#define RJ_SCENES_H

#include <math.h>
#include <string.h>

/* ---------------------------------------------------------------- impact (paper sec. 4) */
typedef struct impact_opts {
    int method;        /* rj_method, default adaptive */
    int release;       /* rj_release, default RC13 */
    double K;          /* penalty stiffness N m/rad, default 5e8: the stiffest the bound accepts at 2.5 us (README) */
    double e;          /* restitution, default 0 */
    int elements;      /* per link, default 10 */
    double dt;         /* s, default 2.5e-6 (see README: 15 us is above the bound of a 0.2 m deep EB beam) */
    double H;          /* in-plane depth, m, default 0.2 */
    double W;          /* width, m, default 0.05 */
    double rate0;      /* rad/s, default -10 */
} impact_opts;

static inline impact_opts impact_default_opts(void)
{
    impact_opts o;
    o.method = RJ_METHOD_ADAPTIVE; o.release = RJ_RELEASE_RC13; o.K = 5e8; o.e = 0.0;
    o.elements = 10; o.dt = 2.5e-6; o.H = 0.2; o.W = 0.05; o.rate0 = -10.0;
    return o;
}

/* Link 0 held fixed along -x ending at the origin, link 1 starting straight (theta = 180 deg)
   in rigid rotation about the joint at rate0, reverse limit at 176 deg, no forward limit. */
static inline void impact_scene(const impact_opts *o, rj_link_def links[2], rj_joint_def *joint, rj_scene_def *sc)
{
    int i;
    for (i = 0; i < 2; i++) {
        links[i] = rj_default_link_def();
        links[i].length = 1.0; links[i].elements = o->elements; links[i].E = 70e9; links[i].rho = 2710.0;
        links[i].section = RJ_SECTION_RECT; links[i].width = o->W; links[i].height = o->H; links[i].layers = 1;
    }
    links[0].root = RJ_ROOT_FIXED; links[0].x = -1.0; links[0].y = 0.0; links[0].angle = 0.0;
    *joint = rj_default_joint_def();
    joint->body1 = 0; joint->node1 = -1; joint->body2 = 1;
    joint->angle0 = rj_rad(180.0); joint->rate0 = o->rate0;
    joint->has_reverse = 1; joint->reverse = rj_rad(176.0);
    joint->method = o->method; joint->release = o->release; joint->penalty_k = o->K; joint->restitution = o->e;
    *sc = rj_default_scene_def();
    sc->links = links; sc->link_count = 2; sc->joints = joint; sc->joint_count = 1;
    sc->solver.dt = o->dt;
}

/* Distance of link `l`'s tip from the line through its node 0 along its first element,
   positive counter-clockwise (times `sign`). */
static inline double scene_tip_defl(const rj_model *m, const rj_state *s, int l)
{
    double p0[2], p1[2], pt[2], ux, uy, n;
    int last = rj_link_node_count(m, l) - 1;
    rj_node_position(m, s, l, 0, p0);
    rj_node_position(m, s, l, 1, p1);
    rj_node_position(m, s, l, last, pt);
    ux = p1[0] - p0[0]; uy = p1[1] - p0[1];
    n = sqrt(ux * ux + uy * uy);
    return (ux * (pt[1] - p0[1]) - uy * (pt[0] - p0[0])) / n;
}

/* The same deflection measured from the tangent at node 0 (its rotation) instead of the
   first element's chord: it converges at second order in the element length, the chord
   one at first order (BENCHMARKS.md), so coarse meshes should be judged with this one. */
static inline double scene_tip_defl_tangent(const rj_model *m, const rj_state *s, int l)
{
    double p0[2], pt[2], ph = rj_node_rotation(m, s, l, 0);
    rj_node_position(m, s, l, 0, p0);
    rj_node_position(m, s, l, rj_link_node_count(m, l) - 1, pt);
    return cos(ph) * (pt[1] - p0[1]) - sin(ph) * (pt[0] - p0[0]);
}

/* The impact's link 2 after the contact: its rigid-body angular velocity about the joint
   (angular momentum over rigid inertia) and the energy left in vibration (kinetic + strain
   minus the rigid kinetic energy). */
static inline void impact_rigid_part(const rj_model *m, const rj_state *s, double *omega, double *evib)
{
    double p[2], Lz = 0, I = 0;
    int i, n = rj_link_node_count(m, 1);
    rj_energy e;
    rj_joint_position(m, s, 0, p);
    for (i = 1; i < n; i++) {   /* node 0 is the pin, which does not move */
        double x[2], v[2], mm, rx, ry;
        rj_node_position(m, s, 1, i, x); rj_node_velocity(m, s, 1, i, v); rj_node_mass(m, 1, i, &mm, NULL);
        rx = x[0] - p[0]; ry = x[1] - p[1];
        Lz += mm * (rx * v[1] - ry * v[0]); I += mm * (rx * rx + ry * ry);
    }
    *omega = Lz / I;
    rj_state_energy(m, s, &e);
    *evib = e.kinetic + e.strain - 0.5 * I * (*omega) * (*omega);
}

/* ---------------------------------------------------------------- deployment (paper sec. 5) */
typedef struct deploy_opts {
    int elements;        /* per link, default 10 */
    double dt;           /* s, default 7.5e-6 */
    int joint1_method;   /* rj_method for joint 1 (ground), default forced */
    int joint2_method;   /* rj_method for joint 2, default penalty with K from Eq 31 */
    double joint2_K;     /* N m/rad; <= 0: Eq 31 at dt */
    int extra_friction;  /* sec. 5's +0.175 / +0.008 N m */
    int energy_every;    /* solver.energy_every, default 1 */
} deploy_opts;

static inline deploy_opts deploy_default_opts(void)
{
    deploy_opts o;
    o.elements = 10; o.dt = 7.5e-6; o.joint1_method = RJ_METHOD_FORCED; o.joint2_method = RJ_METHOD_PENALTY;
    o.joint2_K = 0.0; o.extra_friction = 0; o.energy_every = 1;
    return o;
}

/* Table 3: link i = length, area, thickness, I, link mass, tip mass, tip rotary inertia. */
static inline void deploy_links(int elements, rj_link_def links[2])
{
    static const double len[2] = { 1.006423, 0.9945 }, area[2] = { 1.78076e-4, 1.7748e-4 };
    static const double th[2] = { 4.4519e-3, 4.437e-3 }, I[2] = { 2.94113e-10, 2.9117e-10 };
    static const double mass[2] = { 0.52334, 0.42958 }, tip[2] = { 1.2, 0.336 }, tipJ[2] = { 8.5948e-4, 9.256e-4 };
    int i;
    for (i = 0; i < 2; i++) {
        links[i] = rj_default_link_def();
        links[i].length = len[i]; links[i].elements = elements; links[i].E = 7e10;
        links[i].section = RJ_SECTION_GENERAL; links[i].area = area[i]; links[i].inertia = I[i]; links[i].height = th[i];
        links[i].rho = mass[i] / (area[i] * len[i]);
        links[i].tip_mass = tip[i]; links[i].tip_inertia = tipJ[i];
    }
}

/* Joint 1: ground to link 0, q1 = theta from +x, 0 -> lock at 90 deg (forward limit).
   Joint 2: link 0 tip to link 1, theta = q2 + 180 deg: starts at 360 (folded), locks at
   180 (reverse limit). Springs k (pre - q) drive both into their locks. */
static inline void deploy_scene(const deploy_opts *o, rj_link_def links[2], rj_joint_def joints[2], rj_scene_def *sc)
{
    deploy_links(o->elements, links);
    joints[0] = rj_default_joint_def();
    joints[0].body1 = -1; joints[0].body2 = 0; joints[0].ground_angle = 0.0;
    joints[0].angle0 = 0.0;
    joints[0].spring_k = 0.0789; joints[0].spring_free_angle = rj_rad(300.0);
    joints[0].has_forward = 1; joints[0].forward = rj_rad(90.0); joints[0].lock = 1;
    joints[0].method = o->joint1_method; joints[0].friction = 0.03825 + (o->extra_friction ? 0.175 : 0.0);
    joints[1] = rj_default_joint_def();
    joints[1].body1 = 0; joints[1].node1 = -1; joints[1].body2 = 1;
    joints[1].angle0 = rj_rad(360.0);
    joints[1].spring_k = 0.0768; joints[1].spring_free_angle = rj_rad(-60.0 + 180.0);
    joints[1].has_reverse = 1; joints[1].reverse = rj_rad(180.0); joints[1].lock = 1;
    joints[1].method = o->joint2_method; joints[1].friction = 0.0225 + (o->extra_friction ? 0.008 : 0.0);
    joints[1].penalty_k = 1.0; /* placeholder; deploy_build sets Eq 31 */
    *sc = rj_default_scene_def();
    sc->links = links; sc->link_count = 2; sc->joints = joints; sc->joint_count = 2;
    sc->solver.dt = o->dt; sc->solver.energy_every = o->energy_every;
}

/* Builds the deployment model; joint 2's penalty stiffness defaults to Eq 31 at dt, which
   needs the model's link data: build once with a placeholder, then rebuild. */
static inline rj_result deploy_build(const deploy_opts *o, rj_model **m, rj_error *err)
{
    rj_link_def links[2];
    rj_joint_def joints[2];
    rj_scene_def sc;
    rj_result r;
    deploy_scene(o, links, joints, &sc);
    if (o->joint2_K > 0) joints[1].penalty_k = o->joint2_K;
    r = rj_model_create(&sc, m, err, NULL);
    if (r != RJ_OK || o->joint2_K > 0 || o->joint2_method != RJ_METHOD_PENALTY) return r;
    joints[1].penalty_k = rj_joint_kmax_eq31(*m, 1, rj_model_dt(*m));
    rj_model_destroy(*m, NULL);
    return rj_model_create(&sc, m, err, NULL);
}

/* ---------------------------------------------------------------- chains */
/* A chain of n links (0.1 m, 0.01 m deep, `elements` each, of the given fidelity), each
   hanging from the last by a bare joint, the first from ground: the scene the model-size
   checks and the build benchmark grow. links and joints hold n each. */
static inline void chain_scene(int n, int elements, int fidelity, rj_link_def *links, rj_joint_def *joints, rj_scene_def *sc)
{
    int i;
    for (i = 0; i < n; i++) {
        links[i] = rj_default_link_def();
        links[i].elements = elements;
        links[i].length = 0.1;
        links[i].height = 0.01;
        links[i].fidelity = fidelity;
        joints[i] = rj_default_joint_def();
        joints[i].body1 = i - 1;
        joints[i].body2 = i;
    }
    *sc = rj_default_scene_def();
    sc->links = links;
    sc->link_count = n;
    sc->joints = joints;
    sc->joint_count = n;
}

/* Experiment's convention: q1 absolute angle of link 1, q2 relative (0 straight, 180 folded). */
static inline double deploy_q1_deg(const rj_model *m, const rj_state *s) { return rj_deg(rj_joint_theta_running(m, s, 0)); }
static inline double deploy_q2_deg(const rj_model *m, const rj_state *s) { return rj_deg(rj_joint_theta_running(m, s, 1)) - 180.0; }


/* ---------------------------------------------------------------- segmented deployment */
/* The deployment with each link cut into `segments` rigid pieces joined by torsion
   springs, the rigid-finite-element layout (Kruszewski, Wittbrodt): segments + 1 rigid
   links of lengths l/2, l, ..., l, l/2 (l = L / segments), each pair joined at a segment
   midpoint by a joint of stiffness EI / l about the straight line. A scene of rigid links
   only is integrated in joint coordinates, so the springs alone set the step. Joint 0 and
   joint segments + 1 are the deployment joints; link 2 * segments + 1 carries link 2's
   tip mass. links and joints hold 2 (segments + 1) each. */
static inline void deploy_segmented_scene(const deploy_opts *o, int segments, rj_link_def *links,
                                          rj_joint_def *joints, rj_scene_def *sc)
{
    rj_link_def whole[2];
    rj_joint_def deploy[2];
    const int per_link = segments + 1;
    int i, k;
    deploy_scene(o, whole, deploy, sc);
    for (i = 0; i < 2; i++) {
        const double l = whole[i].length / segments;
        const double EI = whole[i].E * whole[i].inertia;
        for (k = 0; k < per_link; k++) {
            const int n = i * per_link + k;
            const int end = k == 0 || k == segments;
            links[n] = whole[i];
            links[n].elements = 1;
            links[n].fidelity = RJ_LINK_RIGID;
            links[n].length = end ? 0.5 * l : l;
            /* the tip mass rides on the last piece */
            links[n].tip_mass = k == segments ? whole[i].tip_mass : 0.0;
            links[n].tip_inertia = k == segments ? whole[i].tip_inertia : 0.0;
            joints[n] = rj_default_joint_def();
            joints[n].body1 = n - 1;
            joints[n].body2 = n;
            joints[n].node1 = -1;
            /* a bending spring: straight (theta = pi) is its free angle */
            joints[n].angle0 = rj_rad(180.0);
            joints[n].spring_k = EI / l;
            joints[n].spring_free_angle = rj_rad(180.0);
        }
    }
    /* the deployment joints keep their data; rigid links latch by momentum with e = 0 */
    joints[0] = deploy[0];
    joints[per_link] = deploy[1];
    joints[per_link].body1 = per_link - 1;
    joints[per_link].body2 = per_link;
    joints[per_link].node1 = -1;
    joints[0].method = RJ_METHOD_MOMENTUM;
    joints[per_link].method = RJ_METHOD_MOMENTUM;
    sc->links = links;
    sc->link_count = 2 * per_link;
    sc->joints = joints;
    sc->joint_count = 2 * per_link;
}

/* The segmented arm's q2 (experiment's convention) and link 2's tip deflection from the
   tangent at its root: the root piece's direction, as for the flexible links' node 0. */
static inline double deploy_segmented_q2_deg(const rj_model *m, const rj_state *s, int segments)
{
    return rj_deg(rj_joint_theta_running(m, s, segments + 1)) - 180.0;
}
static inline double deploy_segmented_tip_defl(const rj_model *m, const rj_state *s, int segments)
{
    const int root = segments + 1, tip = 2 * segments + 1;
    double p0[2], pt[2];
    const double ph = rj_node_rotation(m, s, root, 0);
    rj_node_position(m, s, root, 0, p0);
    rj_node_position(m, s, tip, rj_link_node_count(m, tip) - 1, pt);
    return cos(ph) * (pt[1] - p0[1]) - sin(ph) * (pt[0] - p0[0]);
}

#endif
