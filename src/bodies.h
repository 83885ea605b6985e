/* ------------------------------------------------------------------ rigid bodies in mixed scenes */
/* A rigid link among flexible ones is one rigid body. It carries its own nodes, whose
   translation and rotation follow it, and the nodes pinned to them, whose translation
   follows it while their rotation stays free (the pin). The body's state is its anchor
   (the centre of mass, or the fixed pin it turns about), the anchor's velocity, its rate
   and its angle; node forces act on it at their points, node moments on its own nodes
   add to its torque. Its nodes are massless attachment points; the body's mass and
   inertia are the link's exact ones (rod, tip mass and inertia) plus the pinned nodes'
   lumped masses. The step is the same central difference: rates at half steps, the
   nodes placed by the exact rotation, so the body stays rigid to round-off. */
#define RJ__FCL(m, f, c) ((f) + (m)->cl_off + 6 * (size_t) (c))
#define RJ__CL_RIGID(m, n)                                                                         \
    ((m)->node_cl[n] >= 0 && (n) >= (m)->link_first[(m)->node_cl[n]] &&                            \
     (n) < (m)->link_first[(m)->node_cl[n] + 1])

/* A section's area as the rigid bodies take it: width x height for a rectangle (not its
   layers' sum), else the given area. */
static double rj__plain_area(const rj_link_def *d)
{
    return d->section == RJ_SECTION_RECT ? d->width * d->height : d->area;
}

/* The link and the node within it of global node i (binary search on link_first). */
static void rj__node_of(const rj_model *m, int i, int *link, int *node)
{
    int lo = 0, hi = m->nl - 1;
    while (lo < hi) {
        const int mid = lo + (hi - lo + 1) / 2;
        if (m->link_first[mid] <= i)
            lo = mid;
        else
            hi = mid - 1;
    }
    *link = lo;
    *node = i - m->link_first[lo];
}

/* Whether node n is one of a rigid link's own nodes (its link is a body of the scene). */
static int rj__rigid_own(const rj_model *m, int n)
{
    int link, node;
    rj__node_of(m, n, &link, &node);
    return m->ldef[link].fidelity == RJ_LINK_RIGID;
}

/* A rigid body's own node in a mixed scene (massless: its body carries it)? */
static int rj__own_body_node(const rj_model *m, int k)
{
    return k >= 0 && m->ncl && RJ__CL_RIGID(m, k);
}

/* A pin group holding nodes of two rigid links: a pin between two bodies (rj__body_pins
   keeps them together), from body l's node mine to every own node of a later rigid link
   in the group; a body's members are its own nodes and the group's other nodes. */
static void rj__body_pin_group(rj_model *m, int l, int gi, int mine)
{
    int k;
    for (k = m->grp_first[gi]; k < m->grp_first[gi + 1]; k++) {
        const int n = m->grp_node[k];
        int link, node;
        if (!rj__rigid_own(m, n))
            continue;
        rj__node_of(m, n, &link, &node);
        if (link <= l)
            continue;
        m->bp_node[2 * m->nbp] = mine;
        m->bp_node[2 * m->nbp + 1] = n;
        m->nbp++;
    }
}

static int rj__clusters(rj_model *m, rj_error *err)
{
    int l, i, gi, k, cnt = 0, ng = 0, q = 0;
    m->nbp = 0;
    for (l = 0; l < m->nl; l++) {
        const rj_link_def *d = &m->ldef[l];
        const int n0 = m->link_first[l], nt = m->link_first[l + 1] - 1;
        double A, mr, mt, dc, ux, uy, cx, cy, vcx, vcy, M, ax, ay, vax, vay, I, w0 = m->w0[n0];
        int nfix = 0, fixn = -1, held = 0;
        m->cl_first[l] = cnt;
        if (d->fidelity != RJ_LINK_RIGID)
            continue;
        for (i = n0; i <= nt; i++) {
            m->cl_node[cnt++] = i;
            m->node_cl[i] = l;
        }
        for (gi = 0; gi < m->ng; gi++) {
            int has = 0, mine = -1;
            for (k = m->grp_first[gi]; k < m->grp_first[gi + 1]; k++)
                if (m->grp_node[k] >= n0 && m->grp_node[k] <= nt) {
                    has = 1;
                    mine = m->grp_node[k];
                }
            if (!has)
                continue;
            rj__body_pin_group(m, l, gi, mine);
            if (m->grp_inv[gi] == 0) {
                nfix++;
                fixn = m->grp_node[m->grp_first[gi]];
            } /* pinned to something fixed */
            for (k = m->grp_first[gi]; k < m->grp_first[gi + 1]; k++) {
                const int n = m->grp_node[k];
                /* another body's own node is that body's: a pin between the two */
                if (m->node_cl[n] < 0 && !rj__rigid_own(m, n)) {
                    m->cl_node[cnt++] = n;
                    m->node_cl[n] = l;
                }
            }
        }
        for (i = n0; i <= nt; i++) {
            if (m->rinv[i] == 0)
                held = 1; /* clamped or fixed */
            if (m->node_grp[i] < 0 && m->tinv[i] == 0) {
                nfix++;
                fixn = i;
            }
        }
        /* the link as a body: rod plus tip mass, as in scenes of rigid links */
        A = rj__plain_area(d);
        mr = d->rho * A * d->length;
        mt = mr + d->tip_mass;
        dc = (mr * 0.5 * d->length + d->tip_mass * d->length) / mt;
        ux = (m->x0[nt] - m->x0[n0]) / d->length;
        uy = (m->y0[nt] - m->y0[n0]) / d->length;
        cx = m->x0[n0] + dc * ux;
        cy = m->y0[n0] + dc * uy;
        vcx = m->vx0[n0] - w0 * (cy - m->y0[n0]);
        vcy = m->vy0[n0] + w0 * (cx - m->x0[n0]);
        M = mt;
        ax = mt * cx;
        ay = mt * cy;
        vax = mt * vcx;
        vay = mt * vcy;
        for (k = m->cl_first[l]; k < cnt; k++) {
            const int n = m->cl_node[k];
            if (n >= n0 && n <= nt)
                continue;
            M += m->mass[n];
            ax += m->mass[n] * m->x0[n];
            ay += m->mass[n] * m->y0[n];
            vax += m->mass[n] * m->vx0[n];
            vay += m->mass[n] * m->vy0[n];
        }
        ax /= M;
        ay /= M;
        vax /= M;
        vay /= M;
        m->cl_fix[l] = held || nfix > 1 ? 2 : nfix;
        if (nfix >= 1) {
            ax = m->x0[fixn];
            ay = m->y0[fixn];
            vax = vay = 0;
        }
        if (m->cl_fix[l] == 2) {
            vax = vay = 0;
            w0 = 0;
        }
        I = mr * d->length * d->length / 12.0 +
            mr * (0.5 * d->length - dc) * (0.5 * d->length - dc) +
            d->tip_mass * (d->length - dc) * (d->length - dc) + d->tip_inertia +
            mt * ((cx - ax) * (cx - ax) + (cy - ay) * (cy - ay));
        for (k = m->cl_first[l]; k < cnt; k++) {
            const int n = m->cl_node[k];
            if (n < n0 || n > nt)
                I += m->mass[n] *
                     ((m->x0[n] - ax) * (m->x0[n] - ax) + (m->y0[n] - ay) * (m->y0[n] - ay));
        }
        m->cl_M[l] = M;
        m->cl_I[l] = I;
        m->cl_th0[3 * l] = m->phi0[n0];
        m->cl_th0[3 * l + 1] = vax;
        m->cl_th0[3 * l + 2] = vay;
        for (k = m->cl_first[l]; k < cnt; k++) {
            const int n = m->cl_node[k];
            const int own = n >= n0 && n <= nt;
            m->cl_rx[n] = m->x0[n] - ax;
            m->cl_ry[n] = m->y0[n] - ay;
            m->einv[n] = 0;
            m->kmass[n] = 0;
            /* a pinned node's translation is the body's point there: its largest inverse
               mass (1/M + r^2/I) stands in for it in the stability bound and in the rate
               predictions of joints between flexible links at that node; the body's
               update overwrites what the node update does with it */
            m->tinv[n] = own || m->cl_fix[l] == 2
                             ? 0.0
                             : (m->cl_fix[l] == 0 ? 1.0 / M : 0.0) +
                                   (m->cl_rx[n] * m->cl_rx[n] + m->cl_ry[n] * m->cl_ry[n]) / I;
            /* the initial velocities of the rigid motion */
            m->vx0[n] = vax - w0 * m->cl_ry[n];
            m->vy0[n] = vay + w0 * m->cl_rx[n];
            if (own) {
                m->krot[n] = 0;
                m->mass[n] = 0;
                m->rinertia[n] = I;
                m->rinv[n] = m->cl_fix[l] == 2 ? 0.0 : 1.0 / I;
                m->w0[n] = w0;
            }
        }
    }
    m->cl_first[m->nl] = cnt;
    /* pin groups holding a body's node are the body's now */
    for (gi = 0; gi < m->ng; gi++) {
        const int f0 = m->grp_first[gi], f1 = m->grp_first[gi + 1];
        int absorbed = m->node_cl[m->grp_node[f0]] >= 0;
        if (absorbed) {
            for (k = f0; k < f1; k++)
                m->node_grp[m->grp_node[k]] = -1;
            continue;
        }
        m->grp_inv[ng] = m->grp_inv[gi];
        for (k = f0; k < f1; k++) {
            m->grp_node[q++] = m->grp_node[k];
            m->node_grp[m->grp_node[k]] = ng;
        }
        m->grp_first[++ng] = q;
    }
    m->ng = ng;
    (void) err;
    return 1;
}

/* Twice a body's kinetic energy in the v^{n-1/2}.v^{n+1/2} form (first step: v(0) given). */
static double rj__cl_ke2(const rj_model *m, int c, const double *oc, const double *nc, int first)
{
    const double vx = first ? 2 * oc[2] - nc[2] : oc[2], vy = first ? 2 * oc[3] - nc[3] : oc[3],
                 w = first ? 2 * oc[4] - nc[4] : oc[4];
    return (m->cl_fix[c] == 0 ? m->cl_M[c] * (vx * nc[2] + vy * nc[3]) : 0.0) +
           m->cl_I[c] * w * nc[4];
}

/* The body's torque about its anchor and force from the node loads (x, y at step n). */
static void rj__cl_load(const rj_model *m, int c, const double *oc, const double *x,
                        const double *y, const double *fx, const double *fy, const double *mz,
                        double *Fx, double *Fy, double *T)
{
    int k;
    *Fx = *Fy = *T = 0;
    for (k = m->cl_first[c]; k < m->cl_first[c + 1]; k++) {
        const int n = m->cl_node[k];
        *Fx += fx[n];
        *Fy += fy[n];
        *T += (x[n] - oc[0]) * fy[n] - (y[n] - oc[1]) * fx[n];
        if (RJ__CL_RIGID(m, n))
            *T += mz[n];
    }
}

/* One body of a pinned pair at the pin: its point r from the anchor, the pin's velocity
   (the step's, rj__pair_side_at), its inverse mass and inertia (0 where held). */
typedef struct rj__pair_side {
    double r[2], v[2], tinv, rinv;
} rj__pair_side;

/* The give of a torque pair on two bodies pinned together, c = 1/I_a + 1/I_b -
   u^T K^-1 u, with K the pin's mobility (the sum of 1/M + perp(r) perp(r)^T / I) and
   u = sum perp(r) / I: a torque turns both, and the pin's impulse keeps its points
   together. K (xx, xy, yy), u and det K are left for the pin's impulse; det 0 where the
   pin adds nothing (two bodies turning about one point, or held), c then 1/I_a + 1/I_b. */
static double rj__pair_give(const rj__pair_side *a, const rj__pair_side *b, double *K,
                            double *u, double *det)
{
    K[0] = a->tinv + b->tinv + a->rinv * a->r[1] * a->r[1] + b->rinv * b->r[1] * b->r[1];
    K[1] = -(a->rinv * a->r[1] * a->r[0] + b->rinv * b->r[1] * b->r[0]);
    K[2] = a->tinv + b->tinv + a->rinv * a->r[0] * a->r[0] + b->rinv * b->r[0] * b->r[0];
    u[0] = -(a->rinv * a->r[1] + b->rinv * b->r[1]);
    u[1] = a->rinv * a->r[0] + b->rinv * b->r[0];
    *det = K[0] * K[2] - K[1] * K[1];
    if (!(*det > 1e-12 * (K[0] + K[2]) * (K[0] + K[2]))) {
        *det = 0;
        return a->rinv + b->rinv;
    }
    return a->rinv + b->rinv -
           (K[2] * u[0] * u[0] - 2 * K[1] * u[0] * u[1] + K[0] * u[1] * u[1]) / *det;
}

/* Joint J's give between two rigid bodies without their pin, 1/I_a + 1/I_b (about the
   anchors): the inertia an adaptive limit's stiffness takes there (Eq 21). The pinned
   pair's (rj__pair_give, smaller) made the limit too stiff for the stability bound,
   which sees the pair's bodies through their nodes (omega dt 2.21 with the limits
   counted, the adaptive limits' search found no step); with this one the limit's true
   omega dt stays below 1. */
static double rj__pair_free_give(const rj_model *m, const rj__joint *J)
{
    const int a = m->node_cl[J->nI], b = m->node_cl[J->nJ];
    const double ra = m->cl_fix[a] != 2 ? 1.0 / m->cl_I[a] : 0.0;
    const double rb = m->cl_fix[b] != 2 ? 1.0 / m->cl_I[b] : 0.0;
    return ra + rb;
}

/* Body c's record pushed by the impulse imp (x, y, and angular about its anchor), as
   SHAKE and the pins between bodies push it: the anchor and the angle move by imp over
   the body's mass and inertia, and its rates by that over dt (positions and rates stay
   each other's chord); a body turning about a fixed pin keeps its anchor. */
static void rj__cl_push(const rj_model *m, int c, const double *imp, double dt, double *nc)
{
    if (m->cl_fix[c] == 0) {
        nc[0] += imp[0] / m->cl_M[c];
        nc[1] += imp[1] / m->cl_M[c];
        nc[2] += imp[0] / (m->cl_M[c] * dt);
        nc[3] += imp[1] / (m->cl_M[c] * dt);
    }
    nc[5] += imp[2] / m->cl_I[c];
    nc[4] += imp[2] / (m->cl_I[c] * dt);
}

/* Places the body's members at its record (anchor, angle); with setv the node velocities
   become the chord velocities (x^{n+1} - x^n)/dt and its own nodes take its rate. */
static double rj__cl_pose(const rj_model *m, int c, const double *nc, const double *x,
                          const double *y, double dt, int setv, double *nx, double *ny,
                          double *nphi, double *nvx, double *nvy, double *nw)
{
    const double th0 = m->cl_th0[3 * c], co = cos(nc[5] - th0), sn = sin(nc[5] - th0);
    double sum = nc[4]; /* the positions written and the rate: finite while they all are */
    int k;
    for (k = m->cl_first[c]; k < m->cl_first[c + 1]; k++) {
        const int n = m->cl_node[k];
        const double px = nc[0] + co * m->cl_rx[n] - sn * m->cl_ry[n],
                     py = nc[1] + sn * m->cl_rx[n] + co * m->cl_ry[n];
        if (setv) {
            nvx[n] = (px - x[n]) / dt;
            nvy[n] = (py - y[n]) / dt;
        }
        nx[n] = px;
        ny[n] = py;
        if (RJ__CL_RIGID(m, n)) {
            nphi[n] = nc[5] + (m->phi0[n] - th0);
            if (setv)
                nw[n] = nc[4];
        }
        sum += (px + py) + nphi[n];
        /* the velocities come from positions here, not the other way round: a position of
           1e308 m at n (a crafted state) makes them infinite while both positions are finite */
        if (setv)
            sum += nvx[n] + nvy[n];
    }
    return sum;
}

/* The inverse mass of DOF k of node i (0, 1: translation, its group's when grouped; 2:
   rotation), as the stability bound's operator takes it (rj__lz_apply). */
static double rj__lz_inv(const rj_model *m, int i, int k)
{
    if (k == 2)
        return m->rinv[i];
    if (m->node_grp[i] >= 0)
        return m->grp_inv[m->node_grp[i]];
    return m->tinv[i];
}

/* A joint's rate change per unit torque impulse at the start (1/I_red): (M^-1)_jj in
   joint coordinates for rigid scenes, else from the pin nodes (rj__joint_compliance). */
static double rj__joint_compliance0(const rj_model *m, int j)
{
    rj__jgeo g;
    if (m->rigid)
        return m->jnt[j].minv;
    rj__joint_geo(m, &m->jnt[j], m->x0, m->y0, &g);
    return rj__joint_compliance(m, &m->jnt[j], &g);
}

/* The fastest damping rate a joint's damper gives the bodies it joins, 1/s: C times the
   rate change per unit torque impulse (1/I_red), the largest over the joints. */
static double rj__damping_rate(const rj_model *m)
{
    double worst = 0;
    int j;
    for (j = 0; j < m->nj; j++) {
        double rate;
        if (!(m->jnt[j].c_lin > 0))
            continue;
        rate = m->jnt[j].c_lin * rj__joint_compliance0(m, j);
        if (rate > worst)
            worst = rate;
    }
    /* a cable loop's damper acts on both joints' rates, joint a through the ratio */
    for (j = 0; j < m->ncp; j++) {
        const rj_coupling_def *c = &m->cp[j];
        const double rate = c->damping * (rj__joint_compliance0(m, c->joint_b) +
                                          c->ratio * c->ratio *
                                              rj__joint_compliance0(m, c->joint_a));
        if (rate > worst)
            worst = rate;
    }
    return worst;
}

/* Central differences with damping on the lagged velocity are stable for a mode of
   frequency omega and damping ratio zeta while dt <= (2/omega)(sqrt(1 + zeta^2) - zeta);
   with 2 zeta omega = d (the damping rate) that is dt <= 2 / (d/2 + sqrt(omega^2 + d^2/4)),
   which holds for omega = 0 too (dt <= 2/d). The fastest mode paired with the fastest
   damping rate bounds every pairing the model can have. No stiffness and no damping:
   nothing bounds the step (rigid bodies alone), 1 s stands for that. */
static double rj__dt_bound_of(double omega, double damp_rate)
{
    const double half = 0.5 * damp_rate;
    const double denom = half + sqrt(omega * omega + half * half);
    if (denom == 0)
        return 1.0;
    return RJ__DT_MARGIN * 2.0 / denom; /* NaN or 0 when omega is NaN or infinite */
}

/* omega from the eigenvalue estimate: a round-off negative is 0; NaN stays NaN, so that
   a model whose stiffness or mass leaves doubles behind is refused, not given a bound */
static double rj__omega_of(double om2)
{
    if (om2 == om2 && om2 < 0)
        return 0;
    return sqrt(om2);
}

static unsigned long long rj__fnv(unsigned long long h, const void *p, size_t n)
{
    const unsigned char *c = (const unsigned char *) p;
    size_t i;
    for (i = 0; i < n; i++) {
        h ^= c[i];
        h *= 1099511628211ULL;
    }
    return h;
}

/* FNV-1a of a double or an int (their bytes), one value at a time. */
static unsigned long long rj__fnv_d(unsigned long long h, double v)
{
    return rj__fnv(h, &v, sizeof v);
}
static unsigned long long rj__fnv_i(unsigned long long h, int v)
{
    return rj__fnv(h, &v, sizeof v);
}

/* Row r of def into the hash: as its hash form says (an int as a double or as an int;
   a vector's two components; a table's count and its pairs). */
static unsigned long long rj__fnv_row(unsigned long long h, const rj__field *r, const void *def)
{
    int k, n;
    if (r->type == RJ__FT_TABLE) {
        const double *first = (const double *) (const void *) ((const char *) def + r->aux);
        n = rj__row_int(def, r);
        h = rj__fnv_i(h, n);
        for (k = 0; k < n; k++) {
            h = rj__fnv_d(h, first[k]);
            h = rj__fnv_d(h, first[RJ_TABLE_MAX + k]);
        }
        return h;
    }
    if (rj__row_is_real(r)) {
        const double v0 = rj__row_real(def, r, 0);
        const double v1 = r->type == RJ__FT_VEC2 ? rj__row_real(def, r, 1) : r->def;
        /* 'z': hashed only when it differs from its default */
        if (r->hash_as == 'z' && v0 == r->def && v1 == r->def)
            return h;
        h = rj__fnv_d(h, v0);
        return r->type == RJ__FT_VEC2 ? rj__fnv_d(h, rj__row_real(def, r, 1)) : h;
    }
    memcpy(&n, (const char *) def + r->offset, sizeof n);
    /* 'z': an int hashed only when it differs from its default */
    if (r->hash_as == 'z')
        return n == (int) r->def ? h : rj__fnv_i(h, n);
    return r->hash_as == 'i' ? rj__fnv_i(h, n) : rj__fnv_d(h, (double) n);
}

/* The rows of kind in the order of their hash places: into order (room for 64), their
   count returned. */
static int rj__hash_order(int kind, const rj__field **order)
{
    int n, k, at, count = 0;
    const rj__field *t = rj__fields(kind, &n);
    for (at = 0; count < 64; at++) {
        const int before = count;
        for (k = 0; k < n && count < 64; k++)
            if (t[k].hash_at == at)
                order[count++] = &t[k];
        if (count == before)
            return count;
    }
    return count;
}

/* A definition into the hash: its rows in hash order (rj__hash_order). */
static unsigned long long rj__fnv_def(unsigned long long h, const rj__field *const *order,
                                      int count, const void *def)
{
    int k;
    for (k = 0; k < count; k++)
        h = rj__fnv_row(h, order[k], def);
    return h;
}

/* The model's identity for checkpoints: every definition member that a state's meaning
   depends on (member by member, in the order of the rows' hash places: a struct's
   padding bytes are not defined), the step in use, and the masses and start positions
   derived from them. */
static unsigned long long rj__model_hash(const rj_model *m)
{
    unsigned long long h = 14695981039346656037ULL;
    const rj__field *lo[64], *jo[64], *so[64], *ao[64];
    const int nlo = rj__hash_order(RJ__DEF_LINK, lo), njo = rj__hash_order(RJ__DEF_JOINT, jo);
    const int nso = rj__hash_order(RJ__DEF_SOLVER, so), nao = rj__hash_order(RJ__DEF_LOAD, ao);
    const rj__field *co[64], *po[64];
    const int nco = rj__hash_order(RJ__DEF_ACTUATOR, co);
    const int npo = rj__hash_order(RJ__DEF_COUPLING, po);
    int l, j, k;
    h = rj__fnv_i(h, m->nn);
    h = rj__fnv_i(h, m->ne);
    h = rj__fnv_i(h, m->nj);
    h = rj__fnv_d(h, m->dt);
    for (l = 0; l < m->nl; l++)
        h = rj__fnv_def(h, lo, nlo, &m->ldef[l]);
    for (j = 0; j < m->nj; j++)
        h = rj__fnv_def(h, jo, njo, &m->jdef[j]);
    h = rj__fnv(h, m->mass, sizeof(double) * (size_t) m->nn);
    h = rj__fnv(h, m->x0, sizeof(double) * (size_t) m->nn);
    h = rj__fnv_def(h, so, nso, &m->solver);
    for (k = 0; k < m->nload; k++)
        h = rj__fnv_def(h, ao, nao, &m->load[k]);
    for (k = 0; k < m->nact; k++)
        h = rj__fnv_def(h, co, nco, &m->act[k]);
    for (k = 0; k < m->ncp; k++)
        h = rj__fnv_def(h, po, npo, &m->cp[k]);
    return h;
}

/* The first place in m->dnode (ascending) whose node is n or after. */
static int rj__dnode_from(const rj_model *m, int n)
{
    int lo = 0, hi = m->ndn;
    while (lo < hi) {
        const int mid = lo + (hi - lo) / 2;
        if (m->dnode[mid] < n)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}

/* Is node n one of m->dnode? */
static int rj__is_dnode(const rj_model *m, int n)
{
    const int at = rj__dnode_from(m, n);
    return at < m->ndn && m->dnode[at] == n;
}

/* A link whose sizes and material leave doubles behind (an element length whose square
   underflows, a stiffness or a mass that overflows or vanishes) has no usable step or no
   finite energy: refused here, naming the link and the quantity, before anything uses it. */
static int rj__check_links(const rj_model *m, rj_error *err)
{
    char f[64];
    int l, k;
    for (l = 0; l < m->nl; l++) {
        const rj_link_def *d = &m->ldef[l];
        const double *kc = m->link_kc + 4 * (size_t) l;
        const int n0 = m->link_first[l];
        const char *what = NULL;
        double value = 0;
        if (!(kc[2] >= DBL_MIN) || !rj__finite(kc[3])) {
            what = "its element length squared";
            value = kc[2];
        } else if (!(m->link_EA[l] >= DBL_MIN) || !rj__finite(m->link_EA[l])) {
            what = "its axial stiffness EA (N)";
            value = m->link_EA[l];
        } else if (!(m->link_EI[l] >= DBL_MIN) || !rj__finite(m->link_EI[l])) {
            what = "its bending stiffness EI (N m^2)";
            value = m->link_EI[l];
        } else if (!rj__finite(kc[0]) || !rj__finite(kc[1])) {
            what = "its element stiffness EI/l0 or EA/l0";
            value = rj__finite(kc[0]) ? kc[1] : kc[0];
        }
        for (k = 0; !what && k <= d->elements; k++) {
            const double mass = m->mass[n0 + k], rot = m->rinertia[n0 + k];
            if (!(mass >= DBL_MIN) || !rj__finite(mass) || !rj__finite(1.0 / mass)) {
                what = "a node's mass (kg)";
                value = mass;
            } else if (!(rot >= DBL_MIN) || !rj__finite(rot) || !rj__finite(1.0 / rot)) {
                what = "a node's rotary inertia (kg m^2)";
                value = rot;
            }
        }
        if (!what)
            continue;
        RJ__FIELD(f, "links[%d]", l);
        rj__fail(err, RJ_ERR_INVALID, f, value,
                 "links[%d] (length %g m, %d elements, E %g Pa, rho %g kg/m^3) gives %s = %g, "
                 "which is zero, infinite or below what doubles resolve: no step is usable; scale "
                 "the link's sizes or material into range",
                 l, d->length, d->elements, d->E, d->rho, what, value);
        return 0;
    }
    return 1;
}

/* Adds one warning line to the model's list (as much as fits). */
static void rj__model_warn(rj_model *m, const char *fmt, ...)
{
    char line[320];
    va_list ap;
    int wanted;
    va_start(ap, fmt);
    wanted = vsnprintf(line, sizeof line, fmt, ap);
    va_end(ap);
    rj__fit_words(line, sizeof line, wanted);
    m->nwarn++;
    if (strlen(m->warnings) + strlen(line) + 2 > sizeof m->warnings)
        return;
    rj__cat(m->warnings, sizeof m->warnings, line);
    rj__cat(m->warnings, sizeof m->warnings, "\n");
}

/* Limits a careful engineer would question: one the joint starts past, and one its spring
   never drives it to (the spring comes to rest at its free angle first, or turns the joint
   away from its only limit). Running angles (the limits as the joint meets them from
   angle0, J->fwd and J->rev), in degrees in the text. */
static void rj__limit_warnings(rj_model *m)
{
    int j;
    for (j = 0; j < m->nj; j++) {
        const rj_joint_def *d = &m->jdef[j];
        const rj__joint *J = &m->jnt[j];
        const double start = d->angle0, rest = d->spring_free_angle;
        const int drive = d->spring_k > 0 ? (rest > start) - (rest < start) : 0;
        if (!d->has_forward && !d->has_reverse)
            continue;
        if (d->has_forward && start > J->fwd)
            rj__model_warn(m, "joints[%d] starts %.4g deg past its forward limit", j,
                           rj_deg(start - J->fwd));
        else if (d->has_reverse && start < J->rev)
            rj__model_warn(m, "joints[%d] starts %.4g deg past its reverse limit", j,
                           rj_deg(J->rev - start));
        else if (drive > 0 && d->has_forward && J->fwd > rest)
            rj__model_warn(m,
                           "joints[%d]: its spring turns it forward from %.4g deg and rests at "
                           "%.4g deg, short of its forward limit, met at %.4g deg: the spring "
                           "alone never brings it there%s",
                           j, rj_deg(start), rj_deg(rest), rj_deg(J->fwd),
                           d->lock ? " (it never latches)" : "");
        else if (drive < 0 && d->has_reverse && J->rev < rest)
            rj__model_warn(m,
                           "joints[%d]: its spring turns it in reverse from %.4g deg and rests at "
                           "%.4g deg, short of its reverse limit, met at %.4g deg: the spring "
                           "alone never brings it there%s",
                           j, rj_deg(start), rj_deg(rest), rj_deg(J->rev),
                           d->lock ? " (it never latches)" : "");
        else if (drive > 0 && !d->has_forward)
            rj__model_warn(
                m,
                "joints[%d]: its spring turns it forward from %.4g deg, away from its only limit "
                "(reverse, met at %.4g deg): the spring alone never brings it there%s",
                j, rj_deg(start), rj_deg(J->rev), d->lock ? " (it never latches)" : "");
        else if (drive < 0 && !d->has_reverse)
            rj__model_warn(
                m,
                "joints[%d]: its spring turns it in reverse from %.4g deg, away from its only "
                "limit (forward, met at %.4g deg): the spring alone never brings it there%s",
                j, rj_deg(start), rj_deg(J->fwd), d->lock ? " (it never latches)" : "");
    }
}

/* The root of node's set (union-find, each path pointed at its root as it is walked). */
static int rj__set_root(int *set, int node)
{
    int root = node;
    while (set[root] != root)
        root = set[root];
    while (set[node] != root) {
        const int next = set[node];
        set[node] = root;
        node = next;
    }
    return root;
}

/* Adds node to group g at its cursor unless it is a member already (mark[node] = g). */
static void rj__group_add(rj_model *m, int *mark, int *cursor, int g, int node)
{
    if (mark[node] >= 0)
        return;
    mark[node] = g;
    m->grp_node[cursor[g]++] = node;
}

/* Pin groups: the nodes that joints pin together, each set of them one group, in the
   order of their first joint. Its first member is its anchor: the first body1 pin (in
   joint order) that no joint pins as a body2 node (a chain's top), else the first body1
   pin (a loop); then the body2 pins in joint order, then any other body1 pin. In a scene
   without loops that is each body1 pin node with the body2 nodes pinned to it however
   they are reached. Linear in the joints, with scratch of 4 nn + ng ints (each node's
   set, mark, anchor and group, then each group's fill cursor); node_grp is -1 on entry.
   Returns the number of groups. */
static int rj__pin_groups(rj_model *m, int *scratch)
{
    const int nn = m->nn;
    int *set = scratch, *mark = scratch + nn, *anchor = scratch + 2 * (size_t) nn;
    int *gid = scratch + 3 * (size_t) nn, *cursor = scratch + 4 * (size_t) nn;
    int ng = 0, j, i, g;
    for (i = 0; i < nn; i++) {
        set[i] = i;
        mark[i] = -1;
        anchor[i] = -1;
        gid[i] = -1;
    }
    /* the sets, and the body2 pins marked -2 */
    for (j = 0; j < m->nj; j++) {
        const rj__joint *J = &m->jnt[j];
        if (J->nI < 0)
            continue;
        set[rj__set_root(set, J->nJ)] = rj__set_root(set, J->nI);
        mark[J->nJ] = -2;
    }
    /* each set's anchor and group number */
    for (j = 0; j < m->nj; j++) {
        const int pin = m->jnt[j].nI;
        int r;
        if (pin < 0)
            continue;
        r = rj__set_root(set, pin);
        if (anchor[r] < 0 || (mark[anchor[r]] == -2 && mark[pin] != -2))
            anchor[r] = pin;
        if (gid[r] < 0)
            gid[r] = ng++;
    }
    /* counts, then the fill */
    for (g = 0; g <= ng; g++)
        m->grp_first[g] = 0;
    for (i = 0; i < nn; i++) {
        const int r = rj__set_root(set, i);
        if (gid[r] >= 0)
            m->grp_first[gid[r] + 1]++;
    }
    for (g = 0; g < ng; g++) {
        m->grp_first[g + 1] += m->grp_first[g];
        cursor[g] = m->grp_first[g];
    }
    for (i = 0; i < nn; i++)
        mark[i] = -1;
    for (j = 0; j < m->nj; j++) {
        const rj__joint *J = &m->jnt[j];
        int r;
        if (J->nI < 0)
            continue;
        r = rj__set_root(set, J->nI);
        rj__group_add(m, mark, cursor, gid[r], anchor[r]);
    }
    for (j = 0; j < m->nj; j++)
        if (m->jnt[j].nI >= 0)
            rj__group_add(m, mark, cursor, gid[rj__set_root(set, m->jnt[j].nI)], m->jnt[j].nJ);
    for (j = 0; j < m->nj; j++)
        if (m->jnt[j].nI >= 0)
            rj__group_add(m, mark, cursor, gid[rj__set_root(set, m->jnt[j].nI)], m->jnt[j].nI);
    return ng;
}

/* Inextensible chains: each starts at an inextensible link not hanging from the tip of
   another inextensible link, and follows while the tip carries exactly one inextensible
   child. Linear in the scene, with scratch of 2 nl + 2 nn ints: each link's use and
   joint, each node's count of inextensible children and its last one. */
static void rj__inext_chains(rj_model *m, int *scratch)
{
    int *used = scratch, *joint_of = scratch + m->nl;
    int *children = scratch + 2 * (size_t) m->nl, *child_of = children + m->nn;
    int cnt = 0, l, j, k;
    for (l = 0; l < m->nl; l++) {
        used[l] = 0;
        joint_of[l] = -1;
    }
    for (k = 0; k < m->nn; k++) {
        children[k] = 0;
        child_of[k] = -1;
    }
    for (j = 0; j < m->nj; j++) {
        /* a joint closing a loop neither hangs a link nor continues a chain */
        if (m->jnt[j].loop)
            continue;
        joint_of[m->jdef[j].body2] = j;
        if (m->jnt[j].nI < 0 || m->ldef[m->jdef[j].body2].fidelity != RJ_LINK_INEXTENSIBLE)
            continue;
        children[m->jnt[j].nI]++;
        child_of[m->jnt[j].nI] = m->jdef[j].body2;
    }
    m->nch = 0;
    m->ch_first[0] = 0;
    for (l = 0; l < m->nl; l++) {
        const int pj = joint_of[l];
        int cur = l;
        if (m->ldef[l].fidelity != RJ_LINK_INEXTENSIBLE || used[l])
            continue;
        if (pj >= 0) {
            const int b1 = m->jdef[pj].body1;
            /* the only inextensible child at an inextensible parent's tip continues its chain */
            if (b1 >= 0 && m->ldef[b1].fidelity == RJ_LINK_INEXTENSIBLE &&
                m->jnt[pj].nI == m->link_first[b1 + 1] - 1 && children[m->jnt[pj].nI] == 1)
                continue;
        }
        for (;;) {
            const int n0 = m->link_first[cur], ne = m->ldef[cur].elements,
                      first = cnt == m->ch_first[m->nch];
            const int tip = n0 + ne;
            used[cur] = 1;
            for (k = first ? 0 : 1; k <= ne; k++) {
                m->ch_node[cnt] = n0 + k;
                m->ch_l0sq[cnt] = m->link_l0[cur] * m->link_l0[cur];
                cnt++;
            }
            if (children[tip] != 1 || used[child_of[tip]])
                break;
            cur = child_of[tip];
        }
        m->ch_first[++m->nch] = cnt;
    }
}

/* Places one link (its joint j, or its own root placement when j < 0) from its parent's
   nodes, which are placed already. */
static void rj__place_link(rj_model *m, int l, int j)
{
    const rj_link_def *ld = &m->ldef[l];
    const rj_joint_def *d;
    const rj__joint *J;
    double px, py, refang, om1 = 0, vpx = 0, vpy = 0;
    if (j < 0) {
        rj__place(m, l, 0, ld->x, ld->y, ld->angle, ld->vx, ld->vy, ld->omega, m->x0, m->y0, m->phi0,
                  m->vx0, m->vy0, m->w0);
        return;
    }
    d = &m->jdef[j];
    J = &m->jnt[j];
    if (d->body1 < 0) {
        px = d->ground_x;
        py = d->ground_y;
        refang = d->ground_angle;
    } else {
        px = m->x0[J->nI];
        py = m->y0[J->nI];
        refang = atan2(m->y0[J->nK] - py, m->x0[J->nK] - px);
        om1 = m->w0[J->nI];
        vpx = m->vx0[J->nI];
        vpy = m->vy0[J->nI];
        if (m->ldef[d->body1].root == RJ_ROOT_FIXED) {
            om1 = 0;
            vpx = 0;
            vpy = 0;
        }
    }
    rj__place(m, l, J->nJ - m->link_first[l], px, py, refang + d->angle0, vpx, vpy, om1 + d->rate0,
              m->x0, m->y0, m->phi0,
              m->vx0, m->vy0, m->w0);
}

/* Initial placement of every link after the link it hangs from (its first joint as body2:
   the joints that close loops place nothing), in time linear in the scene: scratch of
   3 nl ints (placed flags, each link's joint, a path of links still to place). */
static void rj__place_all(rj_model *m, int *scratch)
{
    int *placed = scratch, *joint_of = scratch + m->nl, *path = scratch + 2 * (size_t) m->nl;
    int l, j;
    for (l = 0; l < m->nl; l++) {
        placed[l] = 0;
        joint_of[l] = -1;
    }
    for (j = 0; j < m->nj; j++)
        if (!m->jnt[j].loop)
            joint_of[m->jdef[j].body2] = j;
    for (l = 0; l < m->nl; l++) {
        int depth = 0, cur = l;
        /* up to the first placed link or a root, then down again */
        while (cur >= 0 && !placed[cur]) {
            path[depth++] = cur;
            cur = joint_of[cur] >= 0 ? m->jdef[joint_of[cur]].body1 : -1;
        }
        while (depth > 0) {
            cur = path[--depth];
            rj__place_link(m, cur, joint_of[cur]);
            placed[cur] = 1;
        }
    }
}

/* Every element's placed chord has its rest length to 1e-8: far from the origin the
   coordinates no longer resolve an element (a root at x = 1e12 m rounds 0.1 m elements by
   1e-3), and the rounding would start as strain energy that the step then releases. */
static int rj__placement_resolved(const rj_model *m, rj_error *err)
{
    int l, k;
    for (l = 0; l < m->nl; l++) {
        const double l0 = m->link_l0[l];
        for (k = m->link_first[l]; k < m->link_first[l + 1] - 1; k++) {
            const double chord = hypot(m->x0[k + 1] - m->x0[k], m->y0[k + 1] - m->y0[k]);
            char f[64];
            if (fabs(chord - l0) <= 1e-8 * l0)
                continue;
            RJ__FIELD(f, "links[%d]", l);
            rj__fail(err, RJ_ERR_INVALID, f, m->x0[k],
                     "links[%d] is placed where doubles do not resolve its %g m elements (node %d "
                     "at x = %g m, y = %g m, spacing %g m): place the mechanism nearer the origin",
                     l, l0, k - m->link_first[l], m->x0[k], m->y0[k], fabs(m->x0[k]) * DBL_EPSILON);
            return 0;
        }
    }
    return 1;
}

/* Where joint J pins body 1 at the start, its velocity there, and the direction theta
   is measured from (ground: the fixed point and direction). */
static void rj__pin1_start(const rj_model *m, const rj_joint_def *d, const rj__joint *J,
                           double p[2], double v[2], double *ref)
{
    if (d->body1 < 0) {
        p[0] = d->ground_x;
        p[1] = d->ground_y;
        v[0] = v[1] = 0;
        *ref = d->ground_angle;
        return;
    }
    p[0] = m->x0[J->nI];
    p[1] = m->y0[J->nI];
    v[0] = m->vx0[J->nI];
    v[1] = m->vy0[J->nI];
    *ref = atan2(m->y0[J->nK] - p[1], m->x0[J->nK] - p[0]);
}

/* A joint that closes a loop must find its pins together where the other joints place
   the links (within 1e-9 of the longest link), moving together, at its angle0 (within
   1e-9 rad): otherwise the gap, the velocity or the angle it finds is named. */
static int rj__loops_closed(const rj_model *m, rj_error *err)
{
    double longest = 0;
    int j, l;
    char f[64];
    for (l = 0; l < m->nl; l++)
        longest = fmax(longest, m->ldef[l].length);
    for (j = 0; j < m->nj; j++) {
        const rj_joint_def *d = &m->jdef[j];
        const rj__joint *J = &m->jnt[j];
        double p[2], v[2], ref, gap, slip, turn;
        if (!J->loop)
            continue;
        rj__pin1_start(m, d, J, p, v, &ref);
        gap = hypot(m->x0[J->nJ] - p[0], m->y0[J->nJ] - p[1]);
        slip = hypot(m->vx0[J->nJ] - v[0], m->vy0[J->nJ] - v[1]);
        turn = remainder(m->phi0[J->nJ] - ref - d->angle0, RJ__TWO_PI);
        if (gap > 1e-9 * longest) {
            RJ__FIELD(f, "joints[%d]", j);
            rj__fail(err, RJ_ERR_INVALID, f, gap,
                     "joints[%d] closes a loop, but the other joints place its pins %.6g m apart "
                     "(body1 at %.9g, %.9g m; body2 at %.9g, %.9g m): the loop does not close at "
                     "these angle0",
                     j, gap, p[0], p[1], m->x0[J->nJ], m->y0[J->nJ]);
            return 0;
        }
        if (slip > 1e-9 * (1 + hypot(v[0], v[1]))) {
            RJ__FIELD(f, "joints[%d]", j);
            rj__fail(err, RJ_ERR_INVALID, f, slip,
                     "joints[%d] closes a loop, but its pins start %.6g m/s apart: the rate0 of "
                     "the loop's joints do not close it",
                     j, slip);
            return 0;
        }
        if (fabs(turn) > 1e-9) {
            RJ__FIELD(f, "joints[%d].angle0", j);
            rj__fail(err, RJ_ERR_INVALID, f, d->angle0,
                     "%s = %.12g rad (%.9g deg) is not the angle its loop places it at, %.12g rad "
                     "(%.9g deg)",
                     f, d->angle0, rj_deg(d->angle0), d->angle0 + turn, rj_deg(d->angle0 + turn));
            return 0;
        }
    }
    return 1;
}

/* The links alone have a usable bound, so a joint's stiffness or damping takes it below
   RJ__MIN_BOUND: named, with what it gives on its own. */
static int rj__joint_unusable(const rj_model *m, rj_error *err)
{
    int j, worst = 0;
    double fastest = -1;
    char f[64];
    for (j = 0; j < m->nj; j++) {
        const double c = rj__joint_compliance0(m, j);
        const double rate = sqrt(m->jnt[j].k_lin * c) + m->jnt[j].c_lin * c;
        if (rate > fastest) {
            fastest = rate;
            worst = j;
        }
    }
    RJ__FIELD(f, "joints[%d]", worst);
    rj__fail(err, RJ_ERR_INVALID, f, m->dt_bound,
             "no usable step: the stability bound is %g s (at least 1e-15 s is needed); the links "
             "alone would allow %g s, and joints[%d] (spring %g N m/rad, penalty K %g N m/rad, "
             "damping %g N m s/rad) "
             "gives about %g rad/s on its own: its stiffness or damping is outside the range of "
             "mechanisms",
             m->dt_bound, rj__dt_bound_of(m->omega_links, 0), worst, m->jdef[worst].spring_k,
             m->jdef[worst].penalty_k, m->jdef[worst].damping, fastest);
    return 0;
}

/* The step and its bound must be finite positive numbers, and the initial state finite
   (its kinetic energy and the joints' spring energy too). */
static int rj__usable_step(const rj_model *m, rj_error *err)
{
    double ke = 0;
    int i, link, node;
    if ((!(m->dt_bound >= RJ__MIN_BOUND) || !rj__finite(m->dt_bound)) &&
        rj__dt_bound_of(m->omega_links, 0) >= RJ__MIN_BOUND)
        return rj__joint_unusable(m, err);
    if (!(m->dt_bound >= RJ__MIN_BOUND) || !rj__finite(m->dt_bound) || !(m->dt > 0) ||
        !rj__finite(m->dt)) {
        /* name the link with the shortest wave transit l0 / c (Eq 28) */
        int l, fastest = 0;
        double best = HUGE_VAL;
        char f[64];
        for (l = 0; l < m->nl; l++) {
            const double transit = m->link_l0[l] / sqrt(m->ldef[l].E / m->ldef[l].rho);
            if (transit < best) {
                best = transit;
                fastest = l;
            }
        }
        RJ__FIELD(f, "links[%d]", fastest);
        rj__fail(err, RJ_ERR_INVALID, f, m->dt,
                 "no usable step: the stability bound is %g s (omega_max %g rad/s; at least 1e-15 "
                 "s is needed) and the step %g s; links[%d] (length %g m, %d elements, E %g Pa, "
                 "rho %g kg/m^3; element wave transit %g s, Eq 28) "
                 "or a joint's stiffness or damping is outside the range of mechanisms (SI units: "
                 "m, Pa, kg/m^3)",
                 m->dt_bound, m->omega_max, m->dt, fastest, m->ldef[fastest].length,
                 m->ldef[fastest].elements, m->ldef[fastest].E, m->ldef[fastest].rho, best);
        return 0;
    }
    for (i = 0; i < m->nn; i++) {
        const double v = m->x0[i] + m->y0[i] + m->phi0[i];
        ke += m->mass[i] * (m->vx0[i] * m->vx0[i] + m->vy0[i] * m->vy0[i]) +
              m->rinertia[i] * m->w0[i] * m->w0[i];
        if (rj__finite(v) && rj__finite(ke))
            continue;
        rj__node_of(m, i, &link, &node);
        {
            char f[64];
            RJ__FIELD(f, "links[%d]", link);
            rj__fail(err, RJ_ERR_INVALID, f, rj__finite(v) ? ke : v,
                     "links[%d] node %d starts with a non-finite %s: the placement or the initial "
                     "velocities are outside what doubles resolve",
                     link, node, rj__finite(v) ? "kinetic energy" : "position");
        }
        return 0;
    }
    if (!rj__placement_resolved(m, err) || !rj__loops_closed(m, err))
        return 0;
    for (i = 0; i < m->nj; i++) {
        const rj_joint_def *d = &m->jdef[i];
        const double twist = d->angle0 - d->spring_free_angle;
        if (rj__finite(0.5 * d->spring_k * twist * twist))
            continue;
        {
            char f[64];
            RJ__FIELD(f, "joints[%d].spring_k", i);
            rj__fail(err, RJ_ERR_INVALID, f, d->spring_k,
                     "joints[%d] starts with a non-finite spring energy (spring_k %g N m/rad, %g "
                     "rad from its free angle)",
                     i, d->spring_k, twist);
        }
        return 0;
    }
    return 1;
}

