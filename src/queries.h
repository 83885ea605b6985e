/* ------------------------------------------------------------------ inputs and queries */
RJDEF double *rj_state_joint_torques(const rj_model *m, rj_state *s)
{
    RJ_ASSERT(m && s);
    (void) m;
    s->inputs = 1;
    return s->input_torque;
}

RJDEF double *rj_state_node_forces(const rj_model *m, rj_state *s)
{
    RJ_ASSERT(m && s);
    (void) m;
    s->node_inputs = 1;
    return s->input_node;
}

RJDEF const char *rj_state_error(const rj_state *s)
{
    return s->err;
}
RJDEF long rj_state_warning_count(const rj_state *s)
{
    return (long) s->fd[s->cur][RJ__FS_WARN];
}
RJDEF const char *rj_state_warning(const rj_state *s)
{
    return s->warn;
}

/* ------------------------------------------------------------------ queries */
RJDEF int rj_model_warning_count(const rj_model *m)
{
    return m->nwarn;
}
RJDEF const char *rj_model_warnings(const rj_model *m)
{
    return m->warnings;
}
RJDEF double rj_model_dt(const rj_model *m)
{
    return m->dt;
}
RJDEF double rj_model_dt_bound(const rj_model *m)
{
    return m->dt_bound;
}
RJDEF double rj_model_omega_max(const rj_model *m)
{
    return m->omega_max;
}
RJDEF int rj_model_link_count(const rj_model *m)
{
    return m->nl;
}
RJDEF int rj_model_joint_count(const rj_model *m)
{
    return m->nj;
}
RJDEF int rj_model_node_count(const rj_model *m)
{
    return m->nn;
}
RJDEF int rj_model_in_place(const rj_model *m)
{
    return m->ip;
}
RJDEF const rj_link_def *rj_model_link_def(const rj_model *m, int l)
{
    RJ_ASSERT(l >= 0 && l < m->nl);
    return &m->ldef[l];
}
RJDEF const rj_joint_def *rj_model_joint_def(const rj_model *m, int j)
{
    RJ_ASSERT(j >= 0 && j < m->nj);
    return &m->jdef[j];
}
RJDEF int rj_link_node_count(const rj_model *m, int l)
{
    RJ_ASSERT(l >= 0 && l < m->nl);
    return m->ldef[l].elements + 1;
}
RJDEF int rj_model_node_index(const rj_model *m, int l, int k)
{
    if (!m || l < 0 || l >= m->nl || k < -1 || k > m->ldef[l].elements)
        return -1;
    return m->link_first[l] + (k < 0 ? m->ldef[l].elements : k);
}
RJDEF int rj_model_load_count(const rj_model *m)
{
    return m->nload;
}
RJDEF const rj_load_def *rj_model_load_def(const rj_model *m, int k)
{
    RJ_ASSERT(k >= 0 && k < m->nload);
    return &m->load[k];
}
RJDEF const rj_actuator_def *rj_model_actuator_def(const rj_model *m, int k)
{
    RJ_ASSERT(k >= 0 && k < m->nact);
    return &m->act[k];
}
RJDEF int rj_model_coupling_count(const rj_model *m)
{
    return m->ncp;
}
RJDEF const rj_coupling_def *rj_model_coupling_def(const rj_model *m, int k)
{
    RJ_ASSERT(k >= 0 && k < m->ncp);
    return &m->cp[k];
}
RJDEF double rj_link_EA(const rj_model *m, int l)
{
    RJ_ASSERT(l >= 0 && l < m->nl);
    return m->link_EA[l];
}
RJDEF double rj_link_EI(const rj_model *m, int l)
{
    RJ_ASSERT(l >= 0 && l < m->nl);
    return m->link_EI[l];
}
RJDEF double rj_model_dt_eq28(const rj_model *m)
{
    return m->dt_eq28;
}
RJDEF size_t rj_model_work_size(const rj_model *m)
{
    return 6 * (size_t) m->nn + 4 * (size_t) m->ne;
}
RJDEF void rj_model_apply_stiffness(const rj_model *m, const double *u, double *out, double *work)
{
    rj__lz_scales(m, work);
    rj__lz_apply(m, work, u, out, work + 3 * (size_t) m->nn);
}

/* the smaller of the joint's two links by rho I l (ground is infinitely large) */
static double rj__eq31_rho_i_l(const rj_model *m, int j)
{
    const rj_joint_def *d = &m->jdef[j];
    double v2 = m->link_rho[d->body2] * m->link_I[d->body2] * m->link_l0[d->body2], v1;
    if (d->body1 < 0)
        return v2;
    v1 = m->link_rho[d->body1] * m->link_I[d->body1] * m->link_l0[d->body1];
    return v1 < v2 ? v1 : v2;
}
RJDEF double rj_joint_dt_eq29(const rj_model *m, int j, double K)
{
    const rj_joint_def *d;
    double t, c, t2;
    RJ_ASSERT(j >= 0 && j < m->nj);
    d = &m->jdef[j];
    c = sqrt(m->ldef[d->body2].E / m->ldef[d->body2].rho);
    t = m->link_l0[d->body2] / c;
    if (d->body1 >= 0) {
        double t1 = m->link_l0[d->body1] / sqrt(m->ldef[d->body1].E / m->ldef[d->body1].rho);
        if (t1 < t)
            t = t1;
    }
    if (!(K > 0))
        return t;
    t2 = sqrt(rj__eq31_rho_i_l(m, j) / K);
    return t2 < t ? t2 : t;
}
RJDEF double rj_joint_kmax_eq31(const rj_model *m, int j, double dt)
{
    RJ_ASSERT(j >= 0 && j < m->nj);
    return 0.81 * rj__eq31_rho_i_l(m, j) / (dt * dt);
}
RJDEF void rj_joint_inertias(const rj_model *m, int j, double *I1, double *I2)
{
    RJ_ASSERT(j >= 0 && j < m->nj);
    if (I1)
        *I1 = m->jnt[j].I1;
    if (I2)
        *I2 = m->jnt[j].I2;
}
RJDEF double rj_joint_stiffness(const rj_model *m, int j)
{
    RJ_ASSERT(j >= 0 && j < m->nj);
    return m->jnt[j].k_limit;
}

RJDEF double rj_state_time(const rj_state *s)
{
    return s->fd[s->cur][RJ__FS_TIME];
}

RJDEF long rj_state_steps(const rj_state *s)
{
    return s->steps;
}

/* Rigid scenes: the pose and motion of link l from the joint coordinates of a frame,
   walking up to the ground (used by the node queries; the step itself stores only q). */
static void rj__rig_pose(const rj_model *m, const double *f, int l, double *phi, double *rx,
                         double *ry, double *om, double *vx, double *vy)
{
    int j = m->rb_pjoint[l], p;
    double ph, x, y, o, ux, uy;
    if (j < 0) {
        const rj_link_def *d = &m->ldef[l];
        *phi = d->angle;
        *rx = d->x;
        *ry = d->y;
        *om = 0;
        *vx = 0;
        *vy = 0;
        return;
    }
    p = m->jdef[j].body1;
    if (p < 0) {
        ph = m->jdef[j].ground_angle;
        x = m->jdef[j].ground_x;
        y = m->jdef[j].ground_y;
        o = 0;
        ux = uy = 0;
    } else {
        double pp, px, py, po, pvx, pvy, c, sn;
        rj__rig_pose(m, f, p, &pp, &px, &py, &po, &pvx, &pvy);
        c = cos(pp);
        sn = sin(pp);
        x = px + m->jpin[j] * c;
        y = py + m->jpin[j] * sn;
        ux = pvx - po * m->jpin[j] * sn;
        uy = pvy + po * m->jpin[j] * c;
        ph = pp + m->jref[j];
        o = po;
    }
    *phi = ph + RJ__FJ(m, f, j)[RJ__JD_THETA];
    *om = o + RJ__FJ(m, f, j)[RJ__JD_RATE];
    /* a pin at node at: the root at -at l0 along the link */
    if (m->jnt[j].nJ != m->link_first[l]) {
        const double off = (m->jnt[j].nJ - m->link_first[l]) * m->link_l0[l];
        const double c = cos(*phi), sn = sin(*phi);
        x -= off * c;
        y -= off * sn;
        ux += *om * off * sn;
        uy -= *om * off * c;
    }
    *rx = x;
    *ry = y;
    *vx = ux;
    *vy = uy;
}
/* Rigid scenes: every hanging link's angle, rate, angular acceleration, root and the
   root's acceleration (7 per link in k), down the tree in joint order (parents first):
   O(nl). The angles from frame fq, the rates from frame fr's rates and accelerations
   (RJ__JD_RATE + ahead RJ__JD_QDD: the step's predicted rates at n when fr is the frame at
   n and ahead dt / 2), the accelerations from frame fa. Each hanging link's direction
   (cos, sin of its angle: 2 per link in dir) is taken once, for its children's pins and
   its centre (rj__rig_pin_forces). */
static void rj__rig_accels(const rj_model *m, const double *fq, const double *fr, double ahead,
                           const double *fa, double *k, double *dir)
{
    int q, l;
    /* a link no joint hangs (fixed, or a free root in joint coordinates) stays put; the
       joints below write all of a hanging link's record */
    for (l = 0; l < m->nl; l++) {
        double *kl = k + RJ__KA_N * (size_t) l;
        if (m->rb_pjoint[l] >= 0)
            continue;
        memset(kl, 0, sizeof(double) * RJ__KA_N);
        kl[RJ__KA_PHI] = m->ldef[l].angle;
        kl[RJ__KA_RX] = m->ldef[l].x;
        kl[RJ__KA_RY] = m->ldef[l].y;
    }
    for (q = 0; q < m->nq; q++) {
        const int j = m->jorder[q], l = m->jdef[j].body2, p = m->jdef[j].body1;
        const double *jq = RJ__FJ(m, fq, j), *jr = RJ__FJ(m, fr, j), *ja = RJ__FJ(m, fa, j);
        double *kl = k + RJ__KA_N * (size_t) l, pin[2], a_pin[2], e[2], ph, om, al, off;
        if (p < 0) {
            ph = m->jdef[j].ground_angle;
            om = al = 0;
            pin[0] = m->jdef[j].ground_x;
            pin[1] = m->jdef[j].ground_y;
            a_pin[0] = a_pin[1] = 0;
        } else {
            const double *kp = k + RJ__KA_N * (size_t) p;
            /* a hanging parent's direction came before (parents first); a fixed link's */
            const int hangs = m->rb_pjoint[p] >= 0;
            const double cp = hangs ? dir[2 * p] : cos(kp[RJ__KA_PHI]);
            const double sp = hangs ? dir[2 * p + 1] : sin(kp[RJ__KA_PHI]);
            const double d[2] = { m->jpin[j] * cp, m->jpin[j] * sp };
            ph = kp[RJ__KA_PHI] + m->jref[j];
            om = kp[RJ__KA_OM];
            al = kp[RJ__KA_AL];
            pin[0] = kp[RJ__KA_RX] + d[0];
            pin[1] = kp[RJ__KA_RY] + d[1];
            /* the pin on body 1: a_root + alpha perp(d) - omega^2 d */
            a_pin[0] = kp[RJ__KA_AX] - al * d[1] - om * om * d[0];
            a_pin[1] = kp[RJ__KA_AY] + al * d[0] - om * om * d[1];
        }
        ph += jq[RJ__JD_THETA];
        om += jr[RJ__JD_RATE] + ahead * jr[RJ__JD_QDD];
        al += ja[RJ__JD_QDD];
        /* the root sits off the pin by the pin node's distance along the link */
        off = (m->jnt[j].nJ - m->link_first[l]) * m->link_l0[l];
        e[0] = cos(ph);
        e[1] = sin(ph);
        dir[2 * l] = e[0];
        dir[2 * l + 1] = e[1];
        kl[RJ__KA_PHI] = ph;
        kl[RJ__KA_OM] = om;
        kl[RJ__KA_AL] = al;
        kl[RJ__KA_RX] = pin[0] - off * e[0];
        kl[RJ__KA_RY] = pin[1] - off * e[1];
        kl[RJ__KA_AX] = a_pin[0] + off * (al * e[1] + om * om * e[0]);
        kl[RJ__KA_AY] = a_pin[1] + off * (-al * e[0] + om * om * e[1]);
    }
}

/* The loop joints' pin forces (rj__rig_loop_forces) into forces, and as forces from
   outside the tree on their bodies into the subtrees' sums: F on body 2, -F on body 1. */
static void rj__rig_loop_pins(const rj_model *m, const rj_state *s, double *sum, double *forces)
{
    int j, axis;
    for (j = 0; j < m->nj && m->nloop; j++) {
        const int b1 = m->jdef[j].body1, b2 = m->jdef[j].body2;
        if (m->jq[j] >= 0)
            continue;
        for (axis = 0; axis < 2; axis++) {
            const double F = s->loop_force[2 * j + axis];
            forces[2 * j + axis] = F;
            sum[2 * b2 + axis] -= F;
            if (b1 >= 0)
                sum[2 * b1 + axis] += F;
        }
    }
}

/* Rigid scenes: every joint's pin force (2 per joint in forces), the force body 1 exerts
   on body 2: the sum over the links below of m (a_c - g) less the loads, the caller's
   forces and the loops' pin forces on them (Newton's second law for the subtree; the rates
   at n + 1/2, the step's accelerations), gathered up the tree in reverse joint order; a
   loop joint's own from its rows (rj__rig_loop_forces). work: 9 nl doubles. */
static void rj__rig_pin_forces(const rj_model *m, const rj_state *s, double *work,
                               double *forces)
{
    const double *f = s->fd[s->cur];
    double *k = work, *sum = work + RJ__KA_N * (size_t) m->nl;
    int l, q, i;
    /* with loops, the step's configuration and predicted rates at n, where the rows'
       impulses act; else the new frame's (the forces at n + 1 of a tree) */
    if (m->nloop) {
        const double *at_n = s->fd[1 - s->cur];
        rj__rig_accels(m, at_n, at_n, s->steps == 1 ? 0.0 : 0.5 * m->dt, f, k, sum);
    } else
        rj__rig_accels(m, f, f, 0.0, f, k, sum);
    for (l = 0; l < m->nl; l++) {
        const double *kl = k + RJ__KA_N * (size_t) l, dc = m->rb_dcm[l];
        double e[2];
        if (m->rb_pjoint[l] < 0) {
            sum[2 * l] = sum[2 * l + 1] = 0;
            continue;
        }
        /* sum holds a hanging link's direction (rj__rig_accels) until its sum replaces it */
        e[0] = sum[2 * l];
        e[1] = sum[2 * l + 1];
        /* the centre: a_root + alpha perp(dc e) - omega^2 dc e */
        sum[2 * l] = m->rb_mass[l] * (kl[RJ__KA_AX] - kl[RJ__KA_AL] * dc * e[1] -
                                      kl[RJ__KA_OM] * kl[RJ__KA_OM] * dc * e[0] -
                                      m->solver.gravity[0]);
        sum[2 * l + 1] = m->rb_mass[l] * (kl[RJ__KA_AY] + kl[RJ__KA_AL] * dc * e[0] -
                                          kl[RJ__KA_OM] * kl[RJ__KA_OM] * dc * e[1] -
                                          m->solver.gravity[1]);
        for (i = 0; i <= m->ldef[l].elements && s->node_inputs; i++) {
            const double *in = s->input_node + 3 * (size_t) (m->link_first[l] + i);
            sum[2 * l] -= in[0];
            sum[2 * l + 1] -= in[1];
        }
    }
    for (q = 0; q < m->nload; q++) {
        double value[3];
        l = m->load[q].link;
        if (m->rb_pjoint[l] < 0)
            continue;
        rj__load_value(&m->load[q], RJ__FS(m, f)[RJ__FS_TIME], k[RJ__KA_N * (size_t) l], value);
        sum[2 * l] -= value[0];
        sum[2 * l + 1] -= value[1];
    }
    rj__rig_loop_pins(m, s, sum, forces);
    for (q = m->nq - 1; q >= 0; q--) {
        const int j = m->jorder[q], l2 = m->jdef[j].body2, p = m->jdef[j].body1;
        forces[2 * j] = sum[2 * l2];
        forces[2 * j + 1] = sum[2 * l2 + 1];
        if (p >= 0) {
            sum[2 * p] += sum[2 * l2];
            sum[2 * p + 1] += sum[2 * l2 + 1];
        }
    }
}

/* What the material path adds to element e (local) of link l at n (src/beam_material.h):
   its axial law and its layers' plastic strains at n (kept in the current frame, as the
   chord angles), their largest outer-fibre stress into *smax; the viscous part, lagged
   on the rates at n - 1/2, or implicit as the step kept it (src/viscous.h). */
static void rj__elem_material_at_n(const rj_model *m, const rj_state *s, int l, int e,
                                   double ex, double ey, double tha, double thb,
                                   rj__elem_force *f, double *smax)
{
    const double *at_n = s->fd[1 - s->cur];
    const double *vx = RJ__FVX(m, at_n), *vy = RJ__FVY(m, at_n), *w = RJ__FW(m, at_n);
    const int a = m->link_first[l] + e;
    const double inv_l2 = 1.0 / (ex * ex + ey * ey);
    rj__material mt;
    rj__elem_force v;
    const double *ep = m->link_pl[l] < 0 ? NULL
                                         : s->fd[s->cur] + m->pl_off + m->link_pl[l] +
                                               2 * (size_t) m->ldef[l].layers * (size_t) e;
    rj__material_of(m, l, &mt);
    rj__elem_material(&mt, ex, ey, tha, thb, ep, NULL, f, smax);
    if (RJ__LD(m, l)[RJ__LD_IMPLICIT] > 0) {
        const double *kept = s->visc_force + 4 * ((size_t) m->link_efirst[l] + (size_t) e);
        v.fx = kept[0];
        v.fy = kept[1];
        v.ma = kept[2];
        v.mb = kept[3];
    } else
        rj__elem_viscous(m->link_kc + 4 * (size_t) l, RJ__LD(m, l)[RJ__LD_LAGGED], ex, ey,
                         inv_l2, vx[a + 1] - vx[a], vy[a + 1] - vy[a], w[a], w[a + 1], &v);
    f->fx += v.fx;
    f->fy += v.fy;
    f->ma += v.ma;
    f->mb += v.mb;
}

/* Node space: element e (local) of link l at n, as the beam pass gives it: the force on
   its second node, its end moments (the positions and rotations at n, the chord angle
   the step took there, and what its material adds); its chord's unit vector into unit;
   a yielding link's largest outer-fibre stress at its sections into *smax (else 0). */
static void rj__elem_at_n(const rj_model *m, const rj_state *s, int l, int e,
                          rj__elem_force *f, double unit[2], double *smax)
{
    const double *at_n = s->fd[1 - s->cur];
    const double *x = RJ__FX(m, at_n), *y = RJ__FY(m, at_n), *phi = RJ__FPHI(m, at_n);
    const double *beta = RJ__FBETA(m, s->fd[s->cur]);
    const int a = m->link_first[l] + e;
    const double ex = x[a + 1] - x[a], ey = y[a + 1] - y[a], len = sqrt(ex * ex + ey * ey);
    rj__elems c;
    memset(&c, 0, sizeof c);
    c.kb = m->link_kc[4 * (size_t) l];
    c.kax = m->link_kc[4 * (size_t) l + 1];
    c.l0sq = m->link_kc[4 * (size_t) l + 2];
    c.half_inv_l0sq = m->link_kc[4 * (size_t) l + 3];
    const double bt = beta[m->link_efirst[l] + e];
    rj__elem_forces(&c, ex, ey, bt, 1.0 / (len * len), phi[a], phi[a + 1], f);
    *smax = 0;
    if (m->link_path[l] == RJ__PATH_MATERIAL)
        rj__elem_material_at_n(m, s, l, e, ex, ey, phi[a] - bt, phi[a + 1] - bt, f, smax);
    unit[0] = ex / len;
    unit[1] = ey / len;
}

/* Element e of a flexible link's loads at t^n (rj_element_loads, without its checks). */
static void rj__element_loads(const rj_model *m, const rj_state *s, int link, int element,
                              double loads[5])
{
    const rj_link_def *d = &m->ldef[link];
    rj__elem_force f;
    double unit[2], A, I, smax;
    rj__elem_at_n(m, s, link, element, &f, unit, &smax);
    /* the part beyond each section on the part before: -(the force on the second node) */
    loads[0] = -(f.fx * unit[0] + f.fy * unit[1]);
    loads[1] = -(-f.fx * unit[1] + f.fy * unit[0]);
    loads[2] = -f.ma;
    loads[3] = f.mb;
    A = m->link_EA[link] / d->E;
    I = m->link_EI[link] / d->E;
    if (d->yield > 0)
        loads[4] = smax;
    else if (d->section == RJ_SECTION_RECT)
        loads[4] = fabs(loads[0]) / A + fmax(fabs(loads[2]), fabs(loads[3])) * 0.5 * d->height / I;
    else
        loads[4] = NAN;
}

RJDEF rj_result rj_element_loads(const rj_model *m, const rj_state *s, int link, int element,
                                 double loads[5])
{
    const rj_link_def *d;
    int k;
    RJ_ASSERT(m && s && loads && link >= 0 && link < m->nl);
    for (k = 0; k < 5; k++)
        loads[k] = 0;
    d = &m->ldef[link];
    if (element < 0 || element >= d->elements || d->fidelity != RJ_LINK_FLEXIBLE ||
        s->at_n != RJ__AT_N_FRAME)
        return RJ_ERR_INVALID;
    rj__element_loads(m, s, link, element, loads);
    return RJ_OK;
}

RJDEF double rj_element_plastic_strain(const rj_model *m, const rj_state *s, int link,
                                       int element, int section, int layer)
{
    const rj_link_def *d;
    RJ_ASSERT(m && s && link >= 0 && link < m->nl);
    d = &m->ldef[link];
    if (element < 0 || element >= d->elements || section < 0 || section > 1 || layer < 0 ||
        layer >= d->layers)
        return NAN;
    if (m->link_pl[link] < 0)
        return 0.0;
    return s->fd[s->cur][m->pl_off + (size_t) m->link_pl[link] +
                         2 * (size_t) d->layers * (size_t) element +
                         (size_t) d->layers * (size_t) section + (size_t) layer];
}

/* Node space: the force on node k from its own link's elements at n (the positions and
   rotations at n, the chord angles the step took there), as the beam pass gives it. */
static void rj__elem_node_force(const rj_model *m, const rj_state *s, int k, double out[2])
{
    int link, node, side;
    rj__node_of(m, k, &link, &node);
    out[0] = out[1] = 0;
    /* the element before the node (the node its second) and the one after (its first) */
    for (side = 0; side < 2; side++) {
        const int local = side ? node : node - 1;
        rj__elem_force f;
        double unit[2], smax;
        if (local < 0 || local >= m->ldef[link].elements)
            continue;
        rj__elem_at_n(m, s, link, local, &f, unit, &smax);
        out[0] += side ? -f.fx : f.fx;
        out[1] += side ? -f.fy : f.fy;
    }
}

/* Node space: applied load q's force at t^n, a step before the state's time (on its
   node's rotation then). */
static void rj__load_at_n(const rj_model *m, const rj_state *s, int q, double value[3])
{
    const double *at_n = s->fd[1 - s->cur];
    const double t = RJ__FS(m, s->fd[s->cur])[RJ__FS_TIME] - m->dt;
    rj__load_value(&m->load[q], t, RJ__FPHI(m, at_n)[m->load_node[q]], value);
}

/* Node space: what node k (of link l) asks of the forces not yet counted (its elements,
   the pins at it), at t^n: m a - m g less its loads (with loads set; the all-joints pass
   takes them by load), the caller's force and its mass-proportional damping (a from the
   rates at n - 1/2 and n + 1/2, the step's kick). */
static void rj__node_ask(const rj_model *m, const rj_state *s, int l, int k, int loads,
                         double out[2])
{
    const double *now = s->fd[s->cur], *at_n = s->fd[1 - s->cur];
    const double kick = s->steps == 1 ? 0.5 * m->dt : m->dt;
    int q;
    out[0] = m->mass[k] * ((RJ__FVX(m, now)[k] - RJ__FVX(m, at_n)[k]) / kick -
                           m->solver.gravity[0]);
    out[1] = m->mass[k] * ((RJ__FVY(m, now)[k] - RJ__FVY(m, at_n)[k]) / kick -
                           m->solver.gravity[1]);
    for (q = 0; loads && q < m->nload; q++)
        if (m->load_node[q] == k) {
            double value[3];
            rj__load_at_n(m, s, q, value);
            out[0] -= value[0];
            out[1] -= value[1];
        }
    if (s->node_inputs) {
        out[0] -= s->input_node[3 * (size_t) k];
        out[1] -= s->input_node[3 * (size_t) k + 1];
    }
    if (m->link_path[l] == RJ__PATH_MATERIAL) {
        const double alpha = RJ__LD(m, l)[RJ__LD_MASS];
        out[0] += alpha * m->mass[k] * RJ__FVX(m, at_n)[k];
        out[1] += alpha * m->mass[k] * RJ__FVY(m, at_n)[k];
    }
}

/* Node space: node k's momentum ask with its loads (rj__node_ask). */
static void rj__node_momentum(const rj_model *m, const rj_state *s, int k, double out[2])
{
    int link, node;
    rj__node_of(m, k, &link, &node);
    rj__node_ask(m, s, link, k, 1, out);
}

/* The frame that holds the nodes' values at n (rj_state.at_n): the other one after a
   double-buffered step; after an in-place one the third, for m->dnode's nodes only
   (every joint's and every link's end nodes). */
static const double *rj__nodes_at_n(const rj_state *s)
{
    return s->at_n == RJ__AT_N_KEPT ? s->fd[2] : s->fd[1 - s->cur];
}

/* A rigid body's own link (rod and tip mass; mixed scenes): its momentum's ask, M (a_c -
   g) with a_c from its end nodes' rates at n - 1/2 and n + 1/2 (the body moves them), the
   centre a fraction of the way along them. Its nodes carry no mass of their own; the
   nodes of other links it carries count as theirs. */
static void rj__body_momentum(const rj_model *m, const rj_state *s, int c, double out[2])
{
    const rj_link_def *d = &m->ldef[c];
    const int n0 = m->link_first[c], nt = m->link_first[c + 1] - 1;
    const double rod = d->rho * rj__plain_area(d) * d->length, own = rod + d->tip_mass;
    const double along = (rod * 0.5 + d->tip_mass) / own;
    const double *now = s->fd[s->cur], *at_n = rj__nodes_at_n(s);
    const double kick = s->steps == 1 ? 0.5 * m->dt : m->dt;
    int axis;
    for (axis = 0; axis < 2; axis++) {
        const double *v1 = axis ? RJ__FVY(m, now) : RJ__FVX(m, now);
        const double *v0 = axis ? RJ__FVY(m, at_n) : RJ__FVX(m, at_n);
        const double after = v1[n0] + along * (v1[nt] - v1[n0]);
        const double before = v0[n0] + along * (v0[nt] - v0[n0]);
        out[axis] = own * ((after - before) / kick - m->solver.gravity[axis]);
    }
}

/* In place: the force node k's pins put on it at n (k one of m->dnode), m a - m g less
   every other force the step put on it: s->fx, fy keep the sum the step moved the node
   with (its elements', its loads', its mass-proportional damping), with m g where the
   node moves on its own (its kinetic mass); a from v^{n-1/2}, which the third frame
   keeps, and v^{n+1/2}. */
static void rj__kept_node_balance(const rj_model *m, const rj_state *s, int k, double out[2])
{
    const double *now = s->fd[s->cur], *at_n = s->fd[2];
    const double kick = s->steps == 1 ? 0.5 * m->dt : m->dt;
    const double *g = m->solver.gravity;
    const double ax = (RJ__FVX(m, now)[k] - RJ__FVX(m, at_n)[k]) / kick;
    const double ay = (RJ__FVY(m, now)[k] - RJ__FVY(m, at_n)[k]) / kick;
    out[0] = m->mass[k] * (ax - g[0]) - (s->fx[k] - m->kmass[k] * g[0]);
    out[1] = m->mass[k] * (ay - g[1]) - (s->fy[k] - m->kmass[k] * g[1]);
}

/* Node space: what the chord-reference joints' torques put on node k in the step that
   led here, into out: each joint's torque (its components and the caller's, as the step
   recorded them) as the force couples rj__apply_torque made of it on the chords at n.
   Returns 0 where node k is a chord's far node (K or L), whose latches move it by jumps
   (rj__spin) that no record keeps. */
static int rj__chord_forces_at(const rj_model *m, const rj_state *s, int k, double out[2])
{
    const double *at_n = rj__nodes_at_n(s);
    const double *x = RJ__FX(m, at_n), *y = RJ__FY(m, at_n);
    int j, c;
    out[0] = out[1] = 0;
    for (j = 0; j < m->nj; j++) {
        const rj__joint *J = &m->jnt[j];
        const double *rec = RJ__FJ(m, s->fd[s->cur], j);
        double tau = rec[RJ__JD_INPUT], bx, by, b2;
        if (!J->chord || (k != J->nI && k != J->nJ && k != J->nK && k != J->nL))
            continue;
        if (k == J->nK || k == J->nL)
            return 0;
        for (c = 0; c < RJ_TORQUE_COUNT; c++)
            if (c != RJ_TORQUE_TOTAL)
                tau += rec[RJ__JD_TQ0 + c];
        /* body 2's chord J -> L takes the torque, body 1's I -> K its opposite */
        bx = k == J->nJ ? x[J->nL] - x[J->nJ] : x[J->nK] - x[J->nI];
        by = k == J->nJ ? y[J->nL] - y[J->nJ] : y[J->nK] - y[J->nI];
        b2 = bx * bx + by * by;
        if (k == J->nI)
            tau = -tau;
        out[0] += tau * by / b2;
        out[1] -= tau * bx / b2;
    }
    return 1;
}

/* Node space: the force node k's pins put on it at n, its momentum's ask less its own
   link's elements (rj__node_momentum; a rigid body's own node has no elements) and what
   chord-reference joints' torques put on it (rj__chord_forces_at); in place from the
   step's forces, which hold those (rj__kept_node_balance). */
static void rj__pin_node_balance(const rj_model *m, const rj_state *s, int k, double out[2])
{
    double elements[2] = { 0, 0 }, chords[2];
    if (s->at_n == RJ__AT_N_KEPT) {
        rj__kept_node_balance(m, s, k, out);
        return;
    }
    if (!rj__own_body_node(m, k))
        rj__elem_node_force(m, s, k, elements);
    rj__node_momentum(m, s, k, out);
    if (m->nchord && rj__chord_forces_at(m, s, k, chords)) {
        elements[0] += chords[0];
        elements[1] += chords[1];
    }
    out[0] -= elements[0];
    out[1] -= elements[1];
}

/* Node space, flexible links: the force on body 2's pin node from the rest of the pin
   (rj__pin_node_balance), at n. When body 2 is a rigid body of a mixed scene, the same
   on body 1's node, reversed (rj__balance_node). */
static void rj__node_pin_force(const rj_model *m, const rj_state *s, int j, double force[2])
{
    double sign;
    const int k = rj__balance_node(m, j, &sign);
    rj__pin_node_balance(m, s, k, force);
    force[0] *= sign;
    force[1] *= sign;
}

/* Whether node n is one rigid body c carries but does not own: a node of another link
   pinned to it, whose translation the body's pin gives. */
static int rj__body_carries(const rj_model *m, int c, int n)
{
    return n >= 0 && m->node_cl[n] == c && !RJ__CL_RIGID(m, n);
}

/* Whether rigid body c's balance (rj__body_ground_force) has the forces of its pins to
   the nodes it carries: not where such a node is pinned to the ground too (that pin
   shares the body's), nor where a chord reference's torque acts on one as forces. */
static int rj__body_pins_known(const rj_model *m, int c)
{
    int j, k;
    for (j = 0; j < m->nj; j++) {
        const rj__joint *J = &m->jnt[j];
        const int nodes[4] = { J->nI, J->nK, J->nJ, J->nL };
        if (J->nI < 0 && rj__body_carries(m, c, J->nJ))
            return 0;
        for (k = 0; k < 4 && J->chord; k++)
            if (rj__body_carries(m, c, nodes[k]))
                return 0;
    }
    return 1;
}

/* Node space: the force the ground puts on rigid body c of a mixed scene at the pin it
   turns about (its anchor) at t^n, from the body's Newton's second law: its own link's
   momentum ask (rj__body_momentum) and its own nodes' (their loads and the caller's
   forces), less the forces its other pins put on it: on each node it carries, the
   reverse of that node's pin's force (rj__pin_node_balance), and where the step
   projected (rec, its record: rj__loop_body_push) the pushes of its pins to other bodies
   and of the carried links' lengths. Returns 0 where unknown (force 0): a held body, or
   one whose pins' forces are not known (rj__body_pins_known). */
static int rj__body_ground_force(const rj_model *m, const rj_state *s, int c,
                                 const double *rec, double force[2])
{
    int q;
    force[0] = force[1] = 0;
    if (m->cl_fix[c] != 1 || !rj__body_pins_known(m, c))
        return 0;
    rj__body_momentum(m, s, c, force);
    for (q = m->cl_first[c]; q < m->cl_first[c + 1]; q++) {
        double pin[2];
        rj__pin_node_balance(m, s, m->cl_node[q], pin);
        force[0] += pin[0];
        force[1] += pin[1];
    }
    if (rec) {
        force[0] -= rec[0];
        force[1] -= rec[1];
    }
    return 1;
}

/* Node space: loop joint j's pin force (rj__loop_side): its pin node's balance
   (rj__node_pin_force) less what the node's own link's lengths put on it in the step;
   between two rigid bodies the pin's pushes; pinning a rigid body to the ground, the
   body's balance less its pins' pushes (rj__body_ground_force); each from the step's
   record (rj__loop_records). Returns 0 where it has none, force 0: none is known there
   (rj__loop_side: a chord reference; rj__body_ground_force), or no record of the step
   that led here (needed with inextensible links, between bodies, and on a body with
   pins to others). */
static int rj__loop_pin_force(const rj_model *m, const rj_state *s, int j, double force[2])
{
    const double *rec = s->loop_force + 2 * j;
    const int recorded = s->loop_force[2 * m->nj] == (double) s->steps;
    double sign;
    int node;
    const int kind = rj__loop_side(m, j, &node, &sign);
    const int needs =
        kind == RJ__LOOP_BODIES || m->any_inext || (kind == RJ__LOOP_GROUND && m->nbp);
    force[0] = force[1] = 0;
    if (kind == RJ__LOOP_NONE || (!recorded && needs))
        return 0;
    if (kind == RJ__LOOP_BODIES) {
        force[0] = rec[0];
        force[1] = rec[1];
        return 1;
    }
    if (kind == RJ__LOOP_GROUND)
        return rj__body_ground_force(m, s, m->node_cl[m->jnt[j].nJ], m->project ? rec : NULL,
                                     force);
    rj__node_pin_force(m, s, j, force);
    if (m->any_inext) {
        force[0] -= sign * rec[0];
        force[1] -= sign * rec[1];
    }
    return 1;
}

/* The links below joint j (its body 2 and the links that hang from them, down the joint
   tree) marked 1 in below (nl). */
static void rj__links_below(const rj_model *m, int j, double *below)
{
    int l, k, grew = 1;
    for (l = 0; l < m->nl; l++)
        below[l] = l == m->jdef[j].body2;
    while (grew) {
        grew = 0;
        for (k = 0; k < m->nj; k++) {
            const int b1 = m->jdef[k].body1, b2 = m->jdef[k].body2;
            if (!m->jnt[k].loop && b1 >= 0 && below[b1] != 0 && below[b2] == 0) {
                below[b2] = 1;
                grew = 1;
            }
        }
    }
}

/* The loop joints that tie the links marked in below to the rest, their pin forces on
   them as forces from outside: subtracted from the links' sum in force (F on body 2, -F
   on body 1). Returns 0 where one has none (rj__loop_pin_force). */
static int rj__loops_across(const rj_model *m, const rj_state *s, const double *below,
                            double force[2])
{
    int k;
    for (k = 0; k < m->nj; k++) {
        const int b1 = m->jdef[k].body1, b2 = m->jdef[k].body2;
        const int in1 = b1 >= 0 && below[b1] != 0, in2 = below[b2] != 0;
        const double sign = in2 ? 1.0 : -1.0;
        double loop[2];
        if (!m->jnt[k].loop || in1 == in2)
            continue;
        if (!rj__loop_pin_force(m, s, k, loop))
            return 0;
        force[0] -= sign * loop[0];
        force[1] -= sign * loop[1];
    }
    return 1;
}

/* Node space with inextensible links or rigid bodies: joint j's pin force as Newton's
   second law for the links below it, the sum of their nodes' momentum asks
   (rj__node_momentum) and their bodies' (rj__body_momentum) less the forces of the loops
   that tie them to the rest (rj__loops_across): the elements' forces, their lengths'
   constraint forces and the pins among them are internal and cancel. below: nl doubles
   of scratch. Returns 0 where such a loop has no force, or a held body is among them. */
static int rj__subtree_pin_force(const rj_model *m, const rj_state *s, int j, double *below,
                                 double force[2])
{
    int l, k;
    force[0] = force[1] = 0;
    rj__links_below(m, j, below);
    for (l = 0; l < m->nl; l++) {
        if (below[l] == 0)
            continue;
        if (m->link_path[l] == RJ__PATH_RIGID) {
            double ask[2];
            if (m->cl_fix[l] == 2)
                return 0;
            rj__body_momentum(m, s, l, ask);
            force[0] += ask[0];
            force[1] += ask[1];
        }
        for (k = m->link_first[l]; k < m->link_first[l + 1]; k++) {
            double ask[2];
            rj__node_momentum(m, s, k, ask);
            force[0] += ask[0];
            force[1] += ask[1];
        }
    }
    return rj__loops_across(m, s, below, force);
}

/* Whether node space takes joint j's pin force from the links below it
   (rj__subtree_pin_force): with inextensible links (their lengths' forces), and at a pin
   between two rigid bodies or a rigid body and the ground (their projection's); never
   at a loop joint (rj__loop_pin_force). */
static int rj__pin_by_subtree(const rj_model *m, int j)
{
    const rj__joint *J = &m->jnt[j];
    if (J->loop)
        return 0;
    return m->any_inext ||
           (rj__own_body_node(m, J->nJ) && (J->nI < 0 || rj__own_body_node(m, J->nI)));
}

/* Where rj_joint_pin_force has no answer yet: no state a step before (rj_state.at_n:
   before a step, after a failed one); a chord reference (the joint's forces on the pin
   node) on the pin node's own balance; in node space, a loop joint without a force
   (rj__loop_pin_force), or one tying the links below the joint to the rest, or a held
   body among them (rj__subtree_pin_force, NaN; in place rj__kept_body_pin_force's);
   loops of rigid links before a step (their rows' forces). */
static int rj__pin_force_unknown(const rj_model *m, const rj_state *s, int j)
{
    const rj__joint *J = &m->jnt[j];
    if (m->rigid)
        return m->nloop > 0 && s->loop_force[2 * m->nj] != (double) s->steps;
    double sign, chords[2];
    if (s->at_n == RJ__AT_N_NONE)
        return 1;
    if (J->loop || rj__pin_by_subtree(m, j) || !m->nchord)
        return 0;
    return !rj__chord_forces_at(m, s, rj__balance_node(m, j, &sign), chords);
}

/* The scratch doubles rj__pin_forces needs: rigid scenes' kinematics, the all-joints
   pass's arrays with inextensible links or rigid bodies (rj__pin_pass). */
static size_t rj__pin_work_size(const rj_model *m)
{
    if (m->rigid)
        return (RJ__KA_N + 2) * ((size_t) m->nl + 1);
    return m->any_inext || m->ncl ? RJ__PIN_PASS_N * ((size_t) m->nl + 1) : 0;
}

/* Node space's all-joints pass (rj__pin_pass_run): Newton's second law for every
   subtree of the joint tree at once, children before parents, so all joints cost one
   walk of the nodes. Its arrays, nl + 1 doubles each (RJ__PIN_PASS_N of them, carved
   from the pin-force scratch; indices and marks kept as doubles, exact). */
typedef struct rj__pin_pass {
    double *need;    /* 1 where a joint's force needs the link's ask (rj__pin_pass_need) */
    double *fx, *fy; /* each link's subtree's momentum ask (NaN: a held body in it) */
    double *up;      /* the tree joint it hangs from, -1 for a root */
    double *wait;    /* its children not yet summed; then its children's next place */
    double *order;   /* the links, each after its children */
    double *size;    /* its subtree's links */
    double *pre;     /* its place in a preorder: its subtree's are pre .. pre + size - 1 */
    double *lo, *hi; /* the lowest and highest place of a loop's far end inside it */
} rj__pin_pass;

/* The pass's arrays in work (rj__pin_work_size doubles). */
static rj__pin_pass rj__pin_pass_of(const rj_model *m, double *work)
{
    const size_t n = (size_t) m->nl + 1;
    rj__pin_pass p;
    p.fx = work;
    p.fy = work + n;
    p.up = work + 2 * n;
    p.wait = work + 3 * n;
    p.order = work + 4 * n;
    p.size = work + 5 * n;
    p.pre = work + 6 * n;
    p.lo = work + 7 * n;
    p.hi = work + 8 * n;
    p.need = work + 9 * n;
    return p;
}

/* The link link l hangs from in the joint tree (-1: ground, or l a root). */
static int rj__pin_pass_up(const rj_model *m, const rj__pin_pass *p, int l)
{
    const int j = (int) p->up[l];
    return j >= 0 ? m->jdef[j].body1 : -1;
}

/* The pass's order: each link's tree joint, then the links each after its children
   (leaves first; a parent once its last child is placed). The tree joints form a forest
   (rj__validate_graph), so every link is placed. */
static void rj__pin_pass_order(const rj_model *m, const rj__pin_pass *p)
{
    int l, j, head, tail = 0;
    for (l = 0; l < m->nl; l++) {
        p->up[l] = -1;
        p->wait[l] = 0;
    }
    /* a link's first joint as body2 hangs it; a later one closes a loop */
    for (j = 0; j < m->nj; j++) {
        const int b1 = m->jdef[j].body1;
        if (m->jnt[j].loop)
            continue;
        p->up[m->jdef[j].body2] = j;
        if (b1 >= 0)
            p->wait[b1] += 1;
    }
    /* the leaves first, then each parent once its last child is placed */
    for (l = 0; l < m->nl; l++)
        if (p->wait[l] == 0)
            p->order[tail++] = l;
    for (head = 0; head < tail; head++) {
        const int up = rj__pin_pass_up(m, p, (int) p->order[head]);
        if (up < 0)
            continue;
        p->wait[up] -= 1;
        if (p->wait[up] == 0)
            p->order[tail++] = up;
    }
}

/* The links whose asks a joint's force needs, marked 1 in need: those below a joint
   rj__pin_by_subtree takes (every tree joint with inextensible links; in a mixed scene the
   pins to and between rigid bodies, whose flexible neighbours' nodes are left out).
   Parents before children (the pass's order backwards): a child of a marked link is. */
static void rj__pin_pass_need(const rj_model *m, const rj__pin_pass *p)
{
    int l, j, i;
    for (l = 0; l < m->nl; l++)
        p->need[l] = 0;
    /* the joints the pass gives mark their body 2, which marks the links below it */
    for (j = 0; j < m->nj; j++)
        if (rj__pin_by_subtree(m, j))
            p->need[m->jdef[j].body2] = 1;
    for (i = m->nl - 1; i >= 0; i--) {
        const int child = (int) p->order[i], up = rj__pin_pass_up(m, p, child);
        if (up >= 0 && p->need[up] != 0)
            p->need[child] = 1;
    }
}

/* Link l's own momentum ask but for its applied loads: its rigid body's
   (rj__body_momentum) and its nodes' (rj__node_ask). A held body has none (NaN, which
   every sum that holds it keeps: rj__subtree_pin_force gives none there either). */
static void rj__link_momentum(const rj_model *m, const rj_state *s, int l, double out[2])
{
    int k;
    out[0] = out[1] = 0;
    if (m->link_path[l] == RJ__PATH_RIGID && m->cl_fix[l] == 2) {
        out[0] = out[1] = NAN;
        return;
    }
    if (m->link_path[l] == RJ__PATH_RIGID)
        rj__body_momentum(m, s, l, out);
    for (k = m->link_first[l]; k < m->link_first[l + 1]; k++) {
        double ask[2];
        rj__node_ask(m, s, l, k, 0, ask);
        out[0] += ask[0];
        out[1] += ask[1];
    }
}

/* The loop joints' pin forces (forces; NaN where none) on the links where needed, as
   forces from outside the tree: each link's own sum less them (F on body 2, -F on body
   1; a subtree holding both ends gets none). Those without one tie the subtrees they
   cross to the rest (rj__pin_pass_loops). */
static void rj__pin_pass_loop_forces(const rj_model *m, const rj__pin_pass *p,
                                     const double *forces)
{
    int j;
    for (j = 0; j < m->nj; j++) {
        const int b1 = m->jdef[j].body1, b2 = m->jdef[j].body2;
        const double *F = forces + 2 * j;
        if (!m->jnt[j].loop || F[0] != F[0])
            continue;
        if (p->need[b2] != 0) {
            p->fx[b2] -= F[0];
            p->fy[b2] -= F[1];
        }
        if (b1 >= 0 && p->need[b1] != 0) {
            p->fx[b1] += F[0];
            p->fy[b1] += F[1];
        }
    }
}

/* Every subtree's momentum ask (where needed) less the loops' forces on it, and its
   size, children before parents (the pass's order): each link's own plus its children's
   subtrees'. */
static void rj__pin_pass_sums(const rj_model *m, const rj_state *s, const rj__pin_pass *p,
                              const double *forces)
{
    int l, q, i;
    for (l = 0; l < m->nl; l++) {
        double own[2] = { 0, 0 };
        if (p->need[l] != 0)
            rj__link_momentum(m, s, l, own);
        p->fx[l] = own[0];
        p->fy[l] = own[1];
        p->size[l] = 1;
    }
    /* the applied loads once each, off their nodes' links, not node by node */
    for (q = 0; q < m->nload; q++) {
        double value[3];
        int link, node;
        if (m->load_node[q] < 0)
            continue;
        rj__node_of(m, m->load_node[q], &link, &node);
        if (p->need[link] == 0)
            continue;
        rj__load_at_n(m, s, q, value);
        p->fx[link] -= value[0];
        p->fy[link] -= value[1];
    }
    rj__pin_pass_loop_forces(m, p, forces);
    /* a child's subtree is summed once its own children's are in it */
    for (i = 0; i < m->nl; i++) {
        const int child = (int) p->order[i], up = rj__pin_pass_up(m, p, child);
        if (up < 0)
            continue;
        p->fx[up] += p->fx[child];
        p->fy[up] += p->fy[child];
        p->size[up] += p->size[child];
    }
}

/* With loops: each link's place in a preorder, parents before children (the pass's
   order backwards), each subtree's places one run: a root's after the roots before it,
   a child's the next its parent has free (wait, all 0 once the order is taken). */
static void rj__pin_pass_preorder(const rj_model *m, const rj__pin_pass *p)
{
    double next_root = 0;
    int i;
    for (i = m->nl - 1; i >= 0; i--) {
        const int l = (int) p->order[i], up = rj__pin_pass_up(m, p, l);
        if (up < 0) {
            p->pre[l] = next_root;
            next_root += p->size[l];
        } else {
            p->pre[l] = p->wait[up];
            p->wait[up] += p->size[l];
        }
        p->wait[l] = p->pre[l] + 1;
    }
}

/* A loop joint's end on link l, its far end's place far (-1 for ground): into l's
   lowest and highest far places. */
static void rj__pin_pass_far(const rj__pin_pass *p, int l, double far)
{
    p->lo[l] = fmin(p->lo[l], far);
    p->hi[l] = fmax(p->hi[l], far);
}

/* With loops that have no pin force (forces NaN): each subtree's lowest and highest
   place of such a loop joint's far end, from the ends inside it (children before
   parents). A subtree such a loop ties to the rest has one outside its own places
   (ground's, -1, is outside every subtree). */
static void rj__pin_pass_loops(const rj_model *m, const rj__pin_pass *p, const double *forces)
{
    int l, j, i;
    for (l = 0; l < m->nl; l++) {
        p->lo[l] = m->nl;
        p->hi[l] = -1;
    }
    /* each such loop joint's two ends, each seeing the other's place */
    for (j = 0; j < m->nj; j++) {
        const int b1 = m->jdef[j].body1, b2 = m->jdef[j].body2;
        if (!m->jnt[j].loop || forces[2 * j] == forces[2 * j])
            continue;
        rj__pin_pass_far(p, b2, b1 >= 0 ? p->pre[b1] : -1.0);
        if (b1 >= 0)
            rj__pin_pass_far(p, b1, p->pre[b2]);
    }
    /* a subtree's ends are its own link's and its children's subtrees' */
    for (i = 0; i < m->nl; i++) {
        const int child = (int) p->order[i], up = rj__pin_pass_up(m, p, child);
        if (up < 0)
            continue;
        p->lo[up] = fmin(p->lo[up], p->lo[child]);
        p->hi[up] = fmax(p->hi[up], p->hi[child]);
    }
}

/* The all-joints pass over work (rj__pin_work_size doubles): every subtree's sums with
   the loop joints' forces (forces, NaN where none), and with loops the places that tell
   which subtrees a loop without a force ties to the rest. */
static void rj__pin_pass_run(const rj_model *m, const rj_state *s, double *work,
                             const double *forces)
{
    const rj__pin_pass p = rj__pin_pass_of(m, work);
    rj__pin_pass_order(m, &p);
    rj__pin_pass_need(m, &p);
    rj__pin_pass_sums(m, s, &p, forces);
    if (!m->nloop)
        return;
    rj__pin_pass_preorder(m, &p);
    rj__pin_pass_loops(m, &p, forces);
}

/* Joint j's pin force from the pass over work: its body 2's subtree's sum
   (rj__subtree_pin_force's, in another order). Returns 0 where a loop without a force
   ties that subtree to the rest. */
static int rj__pin_pass_force(const rj_model *m, double *work, int j, double force[2])
{
    const rj__pin_pass p = rj__pin_pass_of(m, work);
    const int b = m->jdef[j].body2;
    force[0] = p.fx[b];
    force[1] = p.fy[b];
    if (!m->nloop)
        return 1;
    return p.lo[b] >= p.pre[b] && p.hi[b] < p.pre[b] + p.size[b];
}

/* Whether rj__pin_forces takes the all-joints pass: node space, the rates at n - 1/2
   there, and a joint whose force it gives (rj__pin_by_subtree). */
static int rj__pin_pass_wanted(const rj_model *m, const rj_state *s)
{
    int j;
    if (m->rigid || s->at_n != RJ__AT_N_FRAME)
        return 0;
    for (j = 0; j < m->nj; j++)
        if (rj__pin_by_subtree(m, j))
            return 1;
    return 0;
}

/* In place: joint j's pin force where node space takes it from the links below
   (rj__pin_by_subtree), whose nodes' values at n the step does not keep: a rigid body's
   pin to the ground (the only such joint in place, which projects nothing), from the
   body's own balance (rj__body_ground_force). Returns 0 where it has none, force 0. */
static int rj__kept_body_pin_force(const rj_model *m, const rj_state *s, int j,
                                   double force[2])
{
    const rj__joint *J = &m->jnt[j];
    force[0] = force[1] = 0;
    if (J->nI >= 0 || !rj__own_body_node(m, J->nJ))
        return 0;
    return rj__body_ground_force(m, s, m->node_cl[J->nJ], NULL, force);
}

/* Node space: joint j's pin force into force (NaN where unknown): a loop joint's own
   (rj__loop_pin_force); else from the all-joints pass over work where it takes the
   joint (rj__pin_by_subtree; in place from the body, rj__kept_body_pin_force), else from
   its pin node's balance. */
static void rj__node_joint_force(const rj_model *m, const rj_state *s, double *work, int j,
                                 double force[2])
{
    int known = !rj__pin_force_unknown(m, s, j);
    force[0] = force[1] = 0.0;
    if (known && m->jnt[j].loop)
        known = rj__loop_pin_force(m, s, j, force);
    else if (known && rj__pin_by_subtree(m, j) && s->at_n == RJ__AT_N_KEPT)
        known = rj__kept_body_pin_force(m, s, j, force);
    else if (known && rj__pin_by_subtree(m, j))
        known = rj__pin_pass_force(m, work, j, force);
    else if (known)
        rj__node_pin_force(m, s, j, force);
    if (!known)
        force[0] = force[1] = NAN;
}

/* Every joint's pin force into forces (2 a joint, NaN where unknown), with work
   (rj__pin_work_size doubles; allocated when NULL). */
static rj_result rj__pin_forces(const rj_model *m, const rj_state *s, double *work,
                                double *forces)
{
    double *own = NULL;
    int j;
    if (!work && rj__pin_work_size(m)) {
        own = (double *) RJ_MALLOC(sizeof(double) * rj__pin_work_size(m), NULL);
        if (!own)
            return RJ_ERR_NOMEM;
        work = own;
    }
    /* node space: the loop joints' first, which the pass takes as forces from outside;
       then the subtrees all at once, before the other joints read them */
    for (j = 0; j < m->nj && !m->rigid; j++)
        if (m->jnt[j].loop)
            rj__node_joint_force(m, s, work, j, forces + 2 * j);
    if (rj__pin_pass_wanted(m, s))
        rj__pin_pass_run(m, s, work, forces);
    for (j = 0; j < m->nj && !m->rigid; j++)
        if (!m->jnt[j].loop)
            rj__node_joint_force(m, s, work, j, forces + 2 * j);
    /* rigid scenes: the joints' kinematics come down the tree for all of them at once */
    for (j = 0; j < m->nj && m->rigid; j++) {
        const double none = rj__pin_force_unknown(m, s, j) ? NAN : 0.0;
        forces[2 * j] = forces[2 * j + 1] = none;
    }
    if (m->rigid && m->nj && !rj__pin_force_unknown(m, s, 0))
        rj__rig_pin_forces(m, s, work, forces);
    if (own)
        RJ_FREE(own, NULL);
    return RJ_OK;
}

RJDEF rj_result rj_joint_pin_forces(const rj_model *m, const rj_state *s, double *forces)
{
    RJ_ASSERT(m && s && forces);
    return rj__pin_forces(m, s, NULL, forces);
}

/* Node space: joint j's pin force from the links below it alone
   (rj__subtree_pin_force, which rj__pin_forces' pass gives for all joints at once):
   RJ_ERR_INVALID, force 0, where it has none. */
static rj_result rj__one_subtree_pin_force(const rj_model *m, const rj_state *s, int j,
                                           double force[2])
{
    double *below = (double *) RJ_MALLOC(sizeof(double) * ((size_t) m->nl + 1), NULL);
    int known;
    if (!below)
        return RJ_ERR_NOMEM;
    known = rj__subtree_pin_force(m, s, j, below, force);
    RJ_FREE(below, NULL);
    if (known)
        return RJ_OK;
    force[0] = force[1] = 0;
    return RJ_ERR_INVALID;
}

RJDEF rj_result rj_joint_pin_force(const rj_model *m, const rj_state *s, int j, double force[2])
{
    double *all;
    rj_result r;
    RJ_ASSERT(m && s && force && j >= 0 && j < m->nj);
    force[0] = force[1] = 0;
    if (rj__pin_force_unknown(m, s, j))
        return RJ_ERR_INVALID;
    if (!m->rigid && m->jnt[j].loop)
        return rj__loop_pin_force(m, s, j, force) ? RJ_OK : RJ_ERR_INVALID;
    if (!m->rigid && !rj__pin_by_subtree(m, j)) {
        rj__node_pin_force(m, s, j, force);
        return RJ_OK;
    }
    if (!m->rigid && s->at_n == RJ__AT_N_KEPT)
        return rj__kept_body_pin_force(m, s, j, force) ? RJ_OK : RJ_ERR_INVALID;
    if (!m->rigid)
        return rj__one_subtree_pin_force(m, s, j, force);
    /* rigid scenes: the joints' kinematics come down the tree for all of them at once */
    all = (double *) RJ_MALLOC(sizeof(double) * 2 * (size_t) m->nj, NULL);
    if (!all)
        return RJ_ERR_NOMEM;
    r = rj_joint_pin_forces(m, s, all);
    if (r == RJ_OK && all[2 * j] != all[2 * j])
        r = RJ_ERR_INVALID;
    else if (r == RJ_OK) {
        force[0] = all[2 * j];
        force[1] = all[2 * j + 1];
    }
    RJ_FREE(all, NULL);
    return r;
}
static void rj__rig_node(const rj_model *m, const rj_state *s, int l, int n, double xy[2],
                         double v[2], double *phi)
{
    double ph, rx, ry, om, vx, vy, c, sn, d = n * m->link_l0[l];
    rj__rig_pose(m, s->fd[s->cur], l, &ph, &rx, &ry, &om, &vx, &vy);
    if (phi)
        *phi = ph;
    if (!xy && !v)
        return;
    c = cos(ph);
    sn = sin(ph);
    if (xy) {
        xy[0] = rx + d * c;
        xy[1] = ry + d * sn;
    }
    if (v) {
        v[0] = vx - om * d * sn;
        v[1] = vy + om * d * c;
    }
}

static int rj__node(const rj_model *m, int l, int n)
{
    RJ_ASSERT(l >= 0 && l < m->nl);
    RJ_ASSERT(n >= 0 && n <= m->ldef[l].elements);
    return m->link_first[l] + n;
}
RJDEF void rj_node_position(const rj_model *m, const rj_state *s, int l, int n, double xy[2])
{
    const double *f = s->fd[s->cur];
    int i = rj__node(m, l, n);
    if (m->rigid) {
        rj__rig_node(m, s, l, n, xy, NULL, NULL);
        return;
    }
    xy[0] = RJ__FX(m, f)[i];
    xy[1] = RJ__FY(m, f)[i];
}
RJDEF void rj_node_velocity(const rj_model *m, const rj_state *s, int l, int n, double v[2])
{
    const double *f = s->fd[s->cur];
    int i = rj__node(m, l, n);
    if (m->rigid) {
        rj__rig_node(m, s, l, n, NULL, v, NULL);
        return;
    }
    v[0] = RJ__FVX(m, f)[i];
    v[1] = RJ__FVY(m, f)[i];
}
RJDEF double rj_node_rotation(const rj_model *m, const rj_state *s, int l, int n)
{
    double ph;
    if (m->rigid) {
        rj__node(m, l, n);
        rj__rig_node(m, s, l, n, NULL, NULL, &ph);
        return ph;
    }
    return RJ__FPHI(m, s->fd[s->cur])[rj__node(m, l, n)];
}
RJDEF double rj_node_rate(const rj_model *m, const rj_state *s, int l, int n)
{
    if (m->rigid) {
        double ph, rx, ry, om, vx, vy;
        rj__node(m, l, n);
        rj__rig_pose(m, s->fd[s->cur], l, &ph, &rx, &ry, &om, &vx, &vy);
        return om;
    }
    return RJ__FW(m, s->fd[s->cur])[rj__node(m, l, n)];
}
RJDEF void rj_node_mass(const rj_model *m, int l, int n, double *mass, double *rinertia)
{
    int i = rj__node(m, l, n);
    if (mass)
        *mass = m->mass[i];
    if (rinertia)
        *rinertia = m->rinertia[i];
}
RJDEF void rj_joint_position(const rj_model *m, const rj_state *s, int j, double xy[2])
{
    const double *f = s->fd[s->cur];
    RJ_ASSERT(j >= 0 && j < m->nj);
    if (m->rigid) {
        rj__rig_node(m, s, m->jdef[j].body2, m->jnt[j].nJ - m->link_first[m->jdef[j].body2], xy,
                     NULL, NULL);
        return;
    }
    xy[0] = RJ__FX(m, f)[m->jnt[j].nJ];
    xy[1] = RJ__FY(m, f)[m->jnt[j].nJ];
}
RJDEF double rj_joint_theta_running(const rj_model *m, const rj_state *s, int j)
{
    RJ_ASSERT(j >= 0 && j < m->nj);
    return RJ__FJ(m, s->fd[s->cur], j)[RJ__JD_THETA];
}
RJDEF double rj_joint_theta(const rj_model *m, const rj_state *s, int j)
{
    return rj__mod2pi(rj_joint_theta_running(m, s, j));
}
RJDEF double rj_joint_rate(const rj_model *m, const rj_state *s, int j)
{
    RJ_ASSERT(j >= 0 && j < m->nj);
    return RJ__FJ(m, s->fd[s->cur], j)[RJ__JD_RATE];
}
RJDEF int rj_joint_flag(const rj_model *m, const rj_state *s, int j)
{
    RJ_ASSERT(j >= 0 && j < m->nj);
    return s->fi[s->cur][j];
}
RJDEF double rj_joint_torque(const rj_model *m, const rj_state *s, int j, int c)
{
    const double *jd;
    double t = 0;
    int k;
    RJ_ASSERT(j >= 0 && j < m->nj);
    RJ_ASSERT(c >= 0 && c < RJ_TORQUE_COUNT);
    jd = RJ__FJ(m, s->fd[s->cur], j);
    if (c != RJ_TORQUE_TOTAL)
        return jd[RJ__JD_TQ0 + c];
    for (k = 0; k < RJ_TORQUE_COUNT; k++)
        if (k != RJ_TORQUE_TOTAL)
            t += jd[RJ__JD_TQ0 + k];
    return t;
}
RJDEF double rj_joint_penetration(const rj_model *m, const rj_state *s, int j)
{
    const double *jd;
    int flag;
    RJ_ASSERT(j >= 0 && j < m->nj);
    jd = RJ__FJ(m, s->fd[s->cur], j);
    flag = s->fi[s->cur][j];
    if (flag == RJ_AT_FORWARD)
        return m->jnt[j].fwd - jd[RJ__JD_THETA];
    if (flag == RJ_AT_REVERSE)
        return m->jnt[j].rev - jd[RJ__JD_THETA];
    if (flag == RJ_LOCKED)
        return jd[RJ__JD_LOCK] - jd[RJ__JD_THETA];
    return 0.0;
}
RJDEF double rj_joint_latch_impulse(const rj_model *m, const rj_state *s, int j)
{
    RJ_ASSERT(j >= 0 && j < m->nj);
    return RJ__FJ(m, s->fd[s->cur], j)[RJ__JD_IMPULSE];
}
RJDEF double rj_joint_event_time(const rj_model *m, const rj_state *s, int j)
{
    RJ_ASSERT(j >= 0 && j < m->nj);
    return RJ__FJ(m, s->fd[s->cur], j)[RJ__JD_EVENT];
}
RJDEF double rj_joint_release_time(const rj_model *m, const rj_state *s, int j)
{
    RJ_ASSERT(j >= 0 && j < m->nj);
    return RJ__FJ(m, s->fd[s->cur], j)[RJ__JD_RELEASE];
}
RJDEF double rj_joint_overlap_time(const rj_model *m, const rj_state *s, int j)
{
    RJ_ASSERT(j >= 0 && j < m->nj);
    return RJ__FJ(m, s->fd[s->cur], j)[RJ__JD_OVERLAP];
}
RJDEF double rj_joint_peak_penetration(const rj_model *m, const rj_state *s, int j)
{
    RJ_ASSERT(j >= 0 && j < m->nj);
    return RJ__FJ(m, s->fd[s->cur], j)[RJ__JD_PEAKP];
}
RJDEF double rj_joint_contact_penetration(const rj_model *m, const rj_state *s, int j)
{
    RJ_ASSERT(j >= 0 && j < m->nj);
    return RJ__FJ(m, s->fd[s->cur], j)[RJ__JD_P0];
}
RJDEF void rj_state_energy(const rj_model *m, const rj_state *s, rj_energy *e)
{
    (void) m;
    e->balance = rj__accounts_read(RJ__FS(m, s->fd[s->cur]), e, &e->total);
}
RJDEF double rj_state_energy_time(const rj_state *s)
{
    return s->fd[s->cur][RJ__FS_ETIME];
}

