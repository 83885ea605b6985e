/* ------------------------------------------------------------------ rigid links */
/* Scenes of rigid links are integrated in joint coordinates q (the joints' running
   angles), so nothing but the joints limits the step. Kinematics run down the tree
   (parents first): phi_child = phi_parent + ref + q_j (ref = pi: the reference direction
   I->K points back along body 1), pins and centres follow. The equations of motion
   M(q) q'' = Q - h(q, q') come from the bodies' Jacobians: d c_b / d q_j = z x (c_b - P_j)
   and d phi_b / d q_j = 1 for every joint j on b's path to the ground; h collects the
   centripetal accelerations -omega^2 r of every segment. The element (flags, torques,
   friction, methods) is the same code as for flexible links; a joint torque is a
   generalised force on q_j, and a velocity jump is an impulse along q_j. */
/* The rigid solver's scratch for n coordinates and nl links: with a dense M, M and its
   factor L (n x n each; articulated bodies need neither); cols columns of M^-1 (W); the
   rows' system S and its factor SL (rows x rows each); others columns of the rows that
   are not one joint's rate (Y); vectors of n and of rows; the link and coordinate
   records. */
static size_t rj__rigid_scratch(size_t n, size_t nl, int dense, size_t cols, size_t rows,
                                size_t others)
{
    const size_t square = dense ? 2 * n * n : 0;
    return square + cols * n + 2 * rows * rows + others * n + 10 * n + 3 * rows +
           RJ__RL_COUNT * nl + (RJ__AB_COUNT + 2) * n + 8;
}

/* The step's scratch (rj_state.rsc) for the model's solver, columns and rows; n counts
   the joints, those that close loops too (their vectors are scratch of nq or more). */
static size_t rj__rig_step_scratch(const rj_model *m)
{
    const size_t others = (size_t) m->ncp + 2 * (size_t) m->nloop;
    return rj__rigid_scratch((size_t) m->nj, (size_t) m->nl, !m->rig_tree, (size_t) m->nwcol,
                             (size_t) m->rig_rows, others);
}

/* The rigid solver's arrays in its scratch, as rj__rigid_scratch counts them: the step's
   (solve: W, the rows' system and Y, rj__rig_step_scratch) or the stability bound's
   (none of those, rj__rig_bound_scratch). M and L are NULL for articulated bodies. */
static RJ__FORCE_INLINE void rj__rig_map(const rj_model *m, double *base, rj__rig *r,
                                         int solve)
{
    const size_t n = (size_t) m->nj, square = m->rig_tree ? 0 : n * n;
    const size_t cols = solve ? (size_t) m->nwcol : 0;
    const size_t rows = solve ? (size_t) m->rig_rows : 0;
    const size_t others = solve ? (size_t) m->ncp + 2 * (size_t) m->nloop : 0;
    r->M = m->rig_tree ? NULL : base;
    r->h = base + square;
    r->L = m->rig_tree ? NULL : r->h + n;
    r->W = r->h + n + square;
    r->q = r->W + cols * n;
    r->qd = r->q + n;
    r->qdp = r->qd + n;
    r->qdd = r->qdp + n;
    r->Q = r->qdd + n;
    r->x = r->Q + n;
    r->tmp = r->x + n;
    r->xd = r->tmp + 2 * n;
    r->S = r->xd + n;
    r->SL = r->S + rows * rows;
    r->lam = r->SL + rows * rows;
    r->rhs = r->lam + rows;
    r->Y = r->rhs + rows;
    r->lk = r->Y + others * n;
    r->ab = r->lk + RJ__RL_COUNT * (size_t) m->nl;
}

/* The joint above joint j on the way to the ground (-1 at a root). */
static int rj__rig_up(const rj_model *m, int j)
{
    const int b1 = m->jdef[j].body1;
    return b1 >= 0 ? m->rb_pjoint[b1] : -1;
}

/* The gradient of the angle of joint j, which closes a loop, over the coordinates: +1 for
   each tree joint on body 2's path to the ground, -1 on body 1's (a joint on both
   cancels): its angle is angle0 + g . (q - q(0)), its rate g . q'. */
static void rj__rig_loop_gradient(const rj_model *m, int j, double *g)
{
    int k, up;
    for (k = 0; k < m->nq; k++)
        g[k] = 0;
    for (up = m->rb_pjoint[m->jdef[j].body2]; up >= 0; up = rj__rig_up(m, up))
        g[m->jq[up]] += 1;
    if (m->jdef[j].body1 >= 0)
        for (up = m->rb_pjoint[m->jdef[j].body1]; up >= 0; up = rj__rig_up(m, up))
            g[m->jq[up]] -= 1;
}

/* Positions, velocities (rates qd; skipped when qd is NULL, as the step needs none) and
   centripetal accelerations (rates qdp) of every link, into the link records; cos and sin
   of a hanging link's angle are kept there for its children. q, qd, qdp are over the
   joint coordinates (the tree's joints: m->jq). */
static void rj__rig_kin(const rj_model *m, rj__rig *r, const double *q, const double *qd,
                        const double *qdp)
{
    double *lk = r->lk;
    int k, l;
    for (l = 0; l < m->nl; l++)
        if (m->rb_pjoint[l] < 0) {
            const rj_link_def *d = &m->ldef[l];
            double *b = lk + RJ__RL_COUNT * (size_t) l;
            b[RJ__RL_PHI] = d->angle;
            b[RJ__RL_RX] = b[RJ__RL_PX] = d->x;
            b[RJ__RL_RY] = b[RJ__RL_PY] = d->y;
            b[RJ__RL_OM] = b[RJ__RL_VX] = b[RJ__RL_VY] = b[RJ__RL_ARX] = b[RJ__RL_ARY] =
                b[RJ__RL_OMB] = 0;
        }
    for (k = 0; k < m->nq; k++) {
        const int j = m->jorder[k], qi = m->jq[j];
        const rj_joint_def *jd = &m->jdef[j];
        const int p = jd->body1, c = jd->body2;
        double *RJ__RESTRICT b = lk + RJ__RL_COUNT * (size_t) c;
        const double dc = m->rb_dcm[c];
        double ph, ex, ey, omb, rx, ry, arx, ary;
        if (p < 0) {
            ph = jd->ground_angle + q[qi];
            omb = qdp[qi];
            rx = jd->ground_x;
            ry = jd->ground_y;
            arx = ary = 0;
            if (qd) {
                b[RJ__RL_OM] = qd[qi];
                b[RJ__RL_VX] = b[RJ__RL_VY] = 0;
            }
        } else {
            const double *pb = lk + RJ__RL_COUNT * (size_t) p;
            const double s = m->jpin[j], ompb = pb[RJ__RL_OMB];
            double cp, sp;
            if (m->rb_pjoint[p] >= 0) {
                cp = pb[RJ__RL_EC];
                sp = pb[RJ__RL_ES];
            } /* parents come first */
            else {
                cp = cos(pb[RJ__RL_PHI]);
                sp = sin(pb[RJ__RL_PHI]);
            } /* a fixed link */
            ph = pb[RJ__RL_PHI] + m->jref[j] + q[qi];
            omb = ompb + qdp[qi];
            rx = pb[RJ__RL_RX] + s * cp;
            ry = pb[RJ__RL_RY] + s * sp;
            arx = pb[RJ__RL_ARX] - ompb * ompb * s * cp;
            ary = pb[RJ__RL_ARY] - ompb * ompb * s * sp;
            if (qd) {
                const double omp = pb[RJ__RL_OM];
                b[RJ__RL_OM] = omp + qd[qi];
                b[RJ__RL_VX] = pb[RJ__RL_VX] - omp * s * sp;
                b[RJ__RL_VY] = pb[RJ__RL_VY] + omp * s * cp;
            }
        }
        ex = cos(ph);
        ey = sin(ph);
        b[RJ__RL_PX] = rx;
        b[RJ__RL_PY] = ry;
        /* a pin at node at: the root at -at l0 along the link, moving and turning about it */
        if (m->jnt[j].nJ != m->link_first[c]) {
            const double off = (m->jnt[j].nJ - m->link_first[c]) * m->link_l0[c];
            rx -= off * ex;
            ry -= off * ey;
            arx += omb * omb * off * ex;
            ary += omb * omb * off * ey;
            if (qd) {
                b[RJ__RL_VX] += b[RJ__RL_OM] * off * ey;
                b[RJ__RL_VY] -= b[RJ__RL_OM] * off * ex;
            }
        }
        b[RJ__RL_PHI] = ph;
        b[RJ__RL_EC] = ex;
        b[RJ__RL_ES] = ey;
        b[RJ__RL_RX] = rx;
        b[RJ__RL_RY] = ry;
        b[RJ__RL_ARX] = arx;
        b[RJ__RL_ARY] = ary;
        b[RJ__RL_OMB] = omb; /* the angular rate used for the centripetal terms */
        b[RJ__RL_CX] = rx + dc * ex;
        b[RJ__RL_CY] = ry + dc * ey;
        b[RJ__RL_ACX] = arx - omb * omb * dc * ex;
        b[RJ__RL_ACY] = ary - omb * omb * dc * ey;
    }
}

/* One link's own share of the subtree sums of its parent joint (pin P, centre c):
   mass m, first moment m (c - P), inertia I + m |c - P|^2 about P, m a and its moment
   m (c - P) x a, with a the centre's centripetal acceleration. */
static RJ__FORCE_INLINE void rj__rig_own(const rj_model *m, int link, double *b)
{
    const double mass = m->rb_mass[link];
    const double dx = b[RJ__RL_CX] - b[RJ__RL_PX];
    const double dy = b[RJ__RL_CY] - b[RJ__RL_PY];
    b[RJ__RL_SUB_M] = mass;
    b[RJ__RL_SUB_SX] = mass * dx;
    b[RJ__RL_SUB_SY] = mass * dy;
    b[RJ__RL_SUB_J] = m->rb_icm[link] + mass * (dx * dx + dy * dy);
    b[RJ__RL_SUB_FX] = mass * b[RJ__RL_ACX];
    b[RJ__RL_SUB_FY] = mass * b[RJ__RL_ACY];
    b[RJ__RL_SUB_N] = mass * (dx * b[RJ__RL_ACY] - dy * b[RJ__RL_ACX]);
}

/* Adds a complete subtree (record sub, pin at sub's root) to its parent's sums, moved
   from the child's pin to the parent's by d = P_child - P_parent (parallel axes). */
static RJ__FORCE_INLINE void rj__rig_gather(const double *sub, double *parent, double dx,
                                            double dy)
{
    const double mass = sub[RJ__RL_SUB_M];
    const double moment = dx * sub[RJ__RL_SUB_SX] + dy * sub[RJ__RL_SUB_SY];
    parent[RJ__RL_SUB_M] += mass;
    parent[RJ__RL_SUB_J] += sub[RJ__RL_SUB_J] + 2 * moment + mass * (dx * dx + dy * dy);
    parent[RJ__RL_SUB_SX] += sub[RJ__RL_SUB_SX] + mass * dx;
    parent[RJ__RL_SUB_SY] += sub[RJ__RL_SUB_SY] + mass * dy;
    parent[RJ__RL_SUB_FX] += sub[RJ__RL_SUB_FX];
    parent[RJ__RL_SUB_FY] += sub[RJ__RL_SUB_FY];
    parent[RJ__RL_SUB_N] += sub[RJ__RL_SUB_N] + dx * sub[RJ__RL_SUB_FY] - dy * sub[RJ__RL_SUB_FX];
}

/* rj__rig_gather's force sums alone (m a and its moment), all the bias h needs: an
   articulated-body tree without gravity reads no other subtree sum. */
static void rj__rig_gather_forces(const double *sub, double *parent, double dx, double dy)
{
    parent[RJ__RL_SUB_FX] += sub[RJ__RL_SUB_FX];
    parent[RJ__RL_SUB_FY] += sub[RJ__RL_SUB_FY];
    parent[RJ__RL_SUB_N] += sub[RJ__RL_SUB_N] + dx * sub[RJ__RL_SUB_FY] - dy * sub[RJ__RL_SUB_FX];
}

/* The subtrees' sums and the bias h (with the centripetal accelerations from rj__rig_kin),
   by composite bodies. Joint j turns the subtree beyond it (its body 2 and all that hangs
   from it), whose inertia J_j and first moment S_j about j's pin P_j are gathered leaves
   first, in O(n); h_j is the moment of the subtree's m a about P_j. The dense M
   (rj__rig_mass_links) reads them, its pairs at four flops each; without the motors'
   rotors (rj__rig_mass adds them). */
static void rj__rig_subtrees(const rj_model *m, rj__rig *r)
{
    const int n = m->nq;
    double *h = r->h, *lk = r->lk, *up;
    int k;
    for (k = 0; k < n; k++) {
        const int body = m->jdef[m->qj[k]].body2;
        rj__rig_own(m, body, lk + RJ__RL_COUNT * (size_t) body);
    }
    /* jorder has parents before children: backwards, a subtree is whole when gathered */
    for (k = n - 1; k >= 0; k--) {
        const int j = m->jorder[k], qi = m->jq[j];
        const int parent = m->jdef[j].body1;
        const double *sub = lk + RJ__RL_COUNT * (size_t) m->jdef[j].body2;
        h[qi] = sub[RJ__RL_SUB_N];
        if (parent < 0 || m->rb_pjoint[parent] < 0)
            continue; /* on the ground or a fixed link */
        up = lk + RJ__RL_COUNT * (size_t) parent;
        rj__rig_gather(sub, up, sub[RJ__RL_PX] - up[RJ__RL_PX], sub[RJ__RL_PY] - up[RJ__RL_PY]);
    }
}

/* An articulated-body tree's factor and bias h (rj__rig_subtrees and the factor's steps,
   rj__ab_factor_at, in one pass each way): each body's own sums and inertia, then leaves
   first each subtree's sums and its articulated inertia, both moved to the parent's pin
   by the same arm P_child - P_parent, taken once. Without gravity only the force sums
   are gathered (h reads no other). Nonzero when a pivot D is not positive. */
static int rj__rig_tree_factor(const rj_model *m, rj__rig *r)
{
    const int n = m->nq, moments = m->has_gravity;
    double *h = r->h, *lk = r->lk;
    int k;
    for (k = 0; k < n; k++) {
        const int body = m->jdef[m->qj[k]].body2;
        double *b = lk + RJ__RL_COUNT * (size_t) body;
        rj__rig_own(m, body, b);
        rj__ab_own(m, r, k, b);
    }
    /* jorder has parents before children: backwards, a subtree is whole when reached */
    for (k = n - 1; k >= 0; k--) {
        const int j = m->jorder[k], qi = m->jq[j];
        const int parent = m->jdef[j].body1;
        const double *sub = lk + RJ__RL_COUNT * (size_t) m->jdef[j].body2;
        double *rec = r->ab + RJ__AB_COUNT * (size_t) qi;
        h[qi] = sub[RJ__RL_SUB_N];
        /* the same test as the factor's parent coordinate (rj__ab_parent) */
        if (parent >= 0 && m->rb_pjoint[parent] >= 0) {
            double *up = lk + RJ__RL_COUNT * (size_t) parent;
            const double dx = sub[RJ__RL_PX] - up[RJ__RL_PX];
            const double dy = sub[RJ__RL_PY] - up[RJ__RL_PY];
            rec[RJ__AB_RX] = dx;
            rec[RJ__AB_RY] = dy;
            if (moments)
                rj__rig_gather(sub, up, dx, dy);
            else
                rj__rig_gather_forces(sub, up, dx, dy);
        }
        if (rj__ab_factor_at(r, qi))
            return -1;
    }
    return 0;
}

/* The dense M from the subtrees' sums: M_jj = J_j, M_jk = J_j + (P_j - P_k) . S_j for
   every joint k above j. */
static void rj__rig_mass_links(const rj_model *m, rj__rig *r)
{
    const int n = m->nq;
    double *M = r->M, *lk = r->lk;
    int i, k;
    for (i = 0; i < n * n; i++)
        M[i] = 0;
    for (k = 0; k < n; k++) {
        const double *sub = lk + RJ__RL_COUNT * (size_t) m->jdef[m->qj[k]].body2;
        int up;
        M[(size_t) k * n + k] = sub[RJ__RL_SUB_J];
        for (up = rj__rig_up(m, m->qj[k]); up >= 0; up = rj__rig_up(m, up)) {
            const double *pin = lk + RJ__RL_COUNT * (size_t) m->jdef[up].body2;
            const double dx = sub[RJ__RL_PX] - pin[RJ__RL_PX];
            const double dy = sub[RJ__RL_PY] - pin[RJ__RL_PY];
            const double v = sub[RJ__RL_SUB_J] + dx * sub[RJ__RL_SUB_SX] + dy * sub[RJ__RL_SUB_SY];
            M[(size_t) k * n + m->jq[up]] = v;
            M[(size_t) m->jq[up] * n + k] = v;
        }
    }
}

/* A rotor on a joint that closes a loop: its kinetic energy I (g . q')^2 / 2 adds I g g^T
   (g: nq doubles of scratch). */
static void rj__rig_loop_rotors(const rj_model *m, double *M, double *g)
{
    const int n = m->nq;
    int j, a, b;
    for (j = 0; j < m->nj; j++) {
        if (m->jq[j] >= 0 || m->jnt[j].rotor == 0)
            continue;
        rj__rig_loop_gradient(m, j, g);
        for (a = 0; a < n; a++)
            for (b = 0; b < n; b++)
                M[(size_t) a * n + b] += m->jnt[j].rotor * g[a] * g[b];
    }
}

/* M(q): the links', and each motor's rotor, whose reflected inertia acts on its joint's
   rate. */
static void rj__rig_mass(const rj_model *m, rj__rig *r)
{
    const int n = m->nq;
    int k;
    rj__rig_subtrees(m, r);
    rj__rig_mass_links(m, r);
    for (k = 0; k < n; k++)
        r->M[(size_t) k * n + k] += m->jnt[m->qj[k]].rotor;
    if (m->nloop)
        rj__rig_loop_rotors(m, r->M, r->tmp);
}

/* Cholesky factor of the n x n SPD matrix M into L (lower), and solves L L^T x = b. The
   2 x 2 case (a two-link arm) is written out: the same operations in the same order as
   the loops, without their overhead, which dominates at that size. */
static int rj__chol(int n, const double *M, double *L)
{
    int i, j, k;
    if (n == 2) {
        double sum = M[0];
        if (!(sum > 0))
            return -1;
        L[0] = sqrt(sum);
        L[2] = M[2] / L[0];
        sum = M[3] - L[2] * L[2];
        if (!(sum > 0))
            return -1;
        L[3] = sqrt(sum);
        return 0;
    }
    for (i = 0; i < n; i++) {
        const double *Mi = M + (size_t) i * n;
        double *Li = L + (size_t) i * n, sum;
        for (j = 0; j < i; j++) {
            const double *Lj = L + (size_t) j * n;
            sum = Mi[j];
            for (k = 0; k < j; k++)
                sum -= Li[k] * Lj[k];
            Li[j] = sum / Lj[j];
        }
        sum = Mi[i];
        for (k = 0; k < i; k++)
            sum -= Li[k] * Li[k];
        if (!(sum > 0))
            return -1;
        Li[i] = sqrt(sum);
    }
    return 0;
}
static void rj__chol_solve(int n, const double *L, const double *b, double *x)
{
    int i, k;
    if (n == 2) {
        const double x0 = b[0] / L[0], x1 = (b[1] - L[2] * x0) / L[3] / L[3];
        x[1] = x1;
        x[0] = (x0 - L[2] * x1) / L[0];
        return;
    }
    for (i = 0; i < n; i++) {
        const double *Li = L + (size_t) i * n;
        double sum = b[i];
        for (k = 0; k < i; k++)
            sum -= Li[k] * x[k];
        x[i] = sum / Li[i];
    }
    for (i = n - 1; i >= 0; i--) {
        double sum = x[i];
        for (k = i + 1; k < n; k++)
            sum -= L[(size_t) k * n + i] * x[k];
        x[i] = sum / L[(size_t) i * n + i];
    }
}
/* Column j of M^-1: rj__chol_solve with b = e_j, without the arithmetic on its leading
   zeros (the forward pass gives exact zeros above j, and 1 / L_jj at j). */
static void rj__chol_unit(int n, const double *L, int j, double *x)
{
    int i, k;
    if (n == 2) {
        const double x0 = j ? 0.0 : 1.0 / L[0],
                     x1 = (j ? 1.0 / L[3] : (0.0 - L[2] * x0) / L[3]) / L[3];
        x[1] = x1;
        x[0] = (x0 - L[2] * x1) / L[0];
        return;
    }
    x[j] = 1.0 / L[(size_t) j * n + j];
    for (i = j + 1; i < n; i++) {
        const double *Li = L + (size_t) i * n;
        double sum = 0;
        for (k = j; k < i; k++)
            sum -= Li[k] * x[k];
        x[i] = sum / Li[i];
    }
    for (i = n - 1; i >= 0; i--) {
        double sum = i >= j ? x[i] : 0.0;
        for (k = i + 1; k < n; k++)
            sum -= L[(size_t) k * n + i] * x[k];
        x[i] = sum / L[(size_t) i * n + i];
    }
}

/* M(q) and its factor at the kinematics in r->lk, as the model solves them: dense
   (Cholesky) or articulated bodies (rj__rig_tree_factor); nonzero when M is not positive
   definite. */
static RJ__FORCE_INLINE int rj__rig_factor(const rj_model *m, rj__rig *r)
{
    if (m->rig_tree)
        return rj__rig_tree_factor(m, r);
    rj__rig_mass(m, r);
    return rj__chol(m->nq, r->M, r->L);
}

/* x = M^-1 b with the factor. */
static RJ__FORCE_INLINE void rj__rig_solve(const rj_model *m, rj__rig *r, const double *b, double *x)
{
    if (m->rig_tree)
        rj__aba_solve(m, r, b, -1, x);
    else
        rj__chol_solve(m->nq, r->L, b, x);
}

/* Column j of M^-1 with the factor. */
static RJ__FORCE_INLINE void rj__rig_unit(const rj_model *m, rj__rig *r, int j, double *x)
{
    if (m->rig_tree)
        rj__aba_solve(m, r, NULL, j, x);
    else
        rj__chol_unit(m->nq, r->L, j, x);
}

/* y = M x at the factor's configuration. */
static RJ__FORCE_INLINE void rj__rig_mul(const rj_model *m, rj__rig *r, const double *x, double *y)
{
    const int n = m->nq;
    int j, k;
    if (m->rig_tree) {
        rj__aba_mul(m, r, x, y);
        return;
    }
    for (j = 0; j < n; j++) {
        const double *Mj = r->M + (size_t) j * n;
        double sum = 0;
        for (k = 0; k < n; k++)
            sum += Mj[k] * x[k];
        y[j] = sum;
    }
}

/* Writes the links' nodes (for queries and drawing) from the kinematics. */
static void rj__rig_nodes(const rj_model *m, const rj__rig *r, double *f)
{
    double *x = RJ__FX(m, f), *y = RJ__FY(m, f), *phi = RJ__FPHI(m, f), *vx = RJ__FVX(m, f),
           *vy = RJ__FVY(m, f), *w = RJ__FW(m, f);
    int l, i;
    for (l = 0; l < m->nl; l++) {
        const double *b = r->lk + RJ__RL_COUNT * (size_t) l;
        const double c = cos(b[RJ__RL_PHI]), s = sin(b[RJ__RL_PHI]), l0 = m->link_l0[l];
        for (i = 0; i <= m->ldef[l].elements; i++) {
            const int k = m->link_first[l] + i;
            x[k] = b[RJ__RL_RX] + i * l0 * c;
            y[k] = b[RJ__RL_RY] + i * l0 * s;
            phi[k] = b[RJ__RL_PHI];
            vx[k] = b[RJ__RL_VX] - b[RJ__RL_OM] * i * l0 * s;
            vy[k] = b[RJ__RL_VY] + b[RJ__RL_OM] * i * l0 * c;
            w[k] = b[RJ__RL_OM];
        }
    }
}

/* The rate of joint j, which closes a loop, at coordinate rates qd (g: nq doubles). */
static double rj__rig_loop_rate(const rj_model *m, int j, const double *qd, double *g)
{
    double rate = 0;
    int k;
    rj__rig_loop_gradient(m, j, g);
    for (k = 0; k < m->nq; k++)
        rate += g[k] * qd[k];
    return rate;
}

/* Joint j's rate at coordinate rates qd: its coordinate's, or for a joint that closes a
   loop g . qd (g: nq doubles of scratch). */
static double rj__rig_joint_rate(const rj_model *m, int j, const double *qd, double *g)
{
    return m->jq[j] >= 0 ? qd[m->jq[j]] : rj__rig_loop_rate(m, j, qd, g);
}

/* A torque tau at joint j as a generalised force into Q: on its coordinate, or tau g for
   a joint that closes a loop (g: nq doubles of scratch). */
static void rj__rig_joint_force(const rj_model *m, int j, double tau, double *Q, double *g)
{
    int k;
    if (m->jq[j] >= 0) {
        Q[m->jq[j]] += tau;
        return;
    }
    rj__rig_loop_gradient(m, j, g);
    for (k = 0; k < m->nq; k++)
        Q[k] += tau * g[k];
}

/* K v for the joints' stiffnesses (a loop joint's k g g^T), and the cable loops' (k w w^T,
   w = e_b - ratio e_a); g: nq doubles of scratch. */
static void rj__rig_stiffness(const rj_model *m, const double *v, double *kv, double *g)
{
    int j, k;
    for (k = 0; k < m->nq; k++)
        kv[k] = m->jnt[m->qj[k]].k_lin * v[k];
    for (j = 0; j < m->nj && m->nloop; j++) {
        double gv = 0;
        if (m->jq[j] >= 0 || m->jnt[j].k_lin == 0)
            continue;
        rj__rig_loop_gradient(m, j, g);
        for (k = 0; k < m->nq; k++)
            gv += g[k] * v[k];
        for (k = 0; k < m->nq; k++)
            kv[k] += m->jnt[j].k_lin * g[k] * gv;
    }
    for (j = 0; j < m->ncp; j++) {
        const rj_coupling_def *c = &m->cp[j];
        const double e = rj__rig_joint_rate(m, c->joint_b, v, g) -
                         c->ratio * rj__rig_joint_rate(m, c->joint_a, v, g);
        rj__rig_joint_force(m, c->joint_b, c->stiffness * e, kv, g);
        rj__rig_joint_force(m, c->joint_a, -(c->ratio * c->stiffness * e), kv, g);
    }
}

/* omega_max^2 with cable loops, whose stiffness ties joints: the largest eigenvalue of
   M^-1 K by power iteration (K is no longer diagonal; the iterates' growth converges to
   it). v, u, kv: nj doubles each. */
static double rj__rig_coupled_bound(const rj_model *m, const double *minv, double *v,
                                    double *u, double *kv, double *g)
{
    const int n = m->nq;
    double lam = 0;
    int j, k, it;
    for (j = 0; j < n; j++)
        v[j] = 1.0 + 0.1 * j;
    for (it = 0; it < 500; it++) {
        double nrm = 0, nv = 0;
        rj__rig_stiffness(m, v, kv, g);
        for (j = 0; j < n; j++) {
            double sum = 0;
            for (k = 0; k < n; k++)
                sum += minv[(size_t) j * n + k] * kv[k];
            u[j] = sum;
            nrm += sum * sum;
            nv += v[j] * v[j];
        }
        if (nrm == 0)
            return 0;
        lam = sqrt(nrm / nv);
        for (j = 0; j < n; j++)
            v[j] = u[j] / sqrt(nrm);
    }
    return lam;
}

/* Each loop joint's rate change per unit torque impulse, g^T M^-1 g, and the inertias
   its element reads (those of its bodies about the pin, as a tree joint's); g, mg: nq
   doubles of scratch. */
static void rj__rig_loop_minv(rj_model *m, const double *minv, double *g, double *mg)
{
    const int n = m->nq;
    int j, a, b;
    for (j = 0; j < m->nj; j++) {
        rj__joint *J = &m->jnt[j];
        double c = 0;
        if (m->jq[j] >= 0)
            continue;
        rj__rig_loop_gradient(m, j, g);
        for (a = 0; a < n; a++) {
            mg[a] = 0;
            for (b = 0; b < n; b++)
                mg[a] += minv[(size_t) a * n + b] * g[b];
            c += g[a] * mg[a];
        }
        J->minv = c;
        J->I2 = 1.0 / c;
        J->I1 = HUGE_VAL;
        J->w1 = 0;
        J->w2 = 1;
    }
}

/* Coordinate k's joint: the inertias its element reads (its bodies' about the pin) and
   the weights that share its torque between them. */
static void rj__rig_joint_inertias(rj_model *m, const rj__rig *r, int k)
{
    const int j = m->qj[k];
    rj__joint *J = &m->jnt[j];
    const int b1 = m->jdef[j].body1, b2 = m->jdef[j].body2;
    /* body 2's centre from the pin (its root unless the joint pins another node) */
    const double arm = m->rb_dcm[b2] - (J->nJ - m->link_first[b2]) * m->link_l0[b2];
    double dx, dy;
    J->I2 = m->rb_icm[b2] + m->rb_mass[b2] * arm * arm;
    if (b1 < 0 || m->rb_pjoint[b1] < 0)
        J->I1 = HUGE_VAL;
    else {
        dx = r->lk[RJ__RL_COUNT * (size_t) b1 + RJ__RL_CX] -
             r->lk[RJ__RL_COUNT * (size_t) b2 + RJ__RL_PX];
        dy = r->lk[RJ__RL_COUNT * (size_t) b1 + RJ__RL_CY] -
             r->lk[RJ__RL_COUNT * (size_t) b2 + RJ__RL_PY];
        J->I1 = m->rb_icm[b1] + m->rb_mass[b1] * (dx * dx + dy * dy);
    }
    J->w1 = rj__finite(J->I1) ? J->I2 / (J->I1 + J->I2) : 0;
    J->w2 = 1 - J->w1;
}

/* A power iteration's step from v to its image u: the estimate v.u (v of unit length) into
   *lam and v = u / |u|; 0 when u is 0. */
static int rj__power_next(double *v, const double *u, int n, double *lam)
{
    double nrm = 0;
    int j;
    for (j = 0; j < n; j++)
        nrm += u[j] * u[j];
    nrm = sqrt(nrm);
    if (nrm == 0)
        return 0;
    *lam = 0;
    for (j = 0; j < n; j++)
        *lam += v[j] * u[j];
    for (j = 0; j < n; j++)
        v[j] = u[j] / nrm;
    return 1;
}

/* A 3 x 3 product C = A B (row-major). */
static void rj__mat3_mul(const double *A, const double *B, double *C)
{
    int i, j;
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++)
            C[3 * i + j] = A[3 * i] * B[j] + A[3 * i + 1] * B[3 + j] + A[3 * i + 2] * B[6 + j];
}

/* C = A B A^T (3 x 3, row-major; T: 9 doubles of scratch). */
static void rj__mat3_congruent(const double *A, const double *B, double *T, double *C)
{
    double At[9];
    int i, j;
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++)
            At[3 * i + j] = A[3 * j + i];
    rj__mat3_mul(A, B, T);
    rj__mat3_mul(T, At, C);
}

/* Every coordinate's 1 / I_red = (M^-1)_kk of an articulated tree in O(n), root first,
   from the factor (rj__rig_tree_factor). In rj__aba_solve with b = e_k, coordinate k's
   subtree passes the force w = X^T U_k / D_k to its parent's pin, which then accelerates
   by -Lam_p w, Lam_p the parent's response to a force on it in the whole tree (a = -Lam
   f); so (M^-1)_kk = 1 / D_k + w.Lam_p w. The same solve with a force F on body k gives
   Lam_k = P X Lam_p X^T P^T + s s^T / D_k, P = I - s U^T / D_k (s = (1, 0, 0)); a root's
   parent is the ground (Lam = 0). lam: 9 doubles a coordinate. A column of M^-1 a joint
   (O(n^2)) took 1.8 s for a chain of 10 000 links. */
static void rj__rig_tree_minv(rj_model *m, rj__rig *r, double *lam)
{
    int k;
    for (k = 0; k < m->nq; k++) {
        const int qi = m->jq[m->jorder[k]];
        const double *rec = r->ab + RJ__AB_COUNT * (size_t) qi;
        const double *U = rec + RJ__AB_U, inv_d = rec[RJ__AB_D];
        const double rx = rec[RJ__AB_RX], ry = rec[RJ__AB_RY];
        const int pq = (int) rec[RJ__AB_PQ];
        double *L = lam + 9 * (size_t) qi, minv = inv_d;
        int i;
        for (i = 0; i < 9; i++)
            L[i] = 0;
        if (pq >= 0) {
            const double *Lp = lam + 9 * (size_t) pq;
            const double X[9] = { 1, 0, 0, -ry, 1, 0, rx, 0, 1 };
            const double P[9] = { 1 - U[0] * inv_d, -U[1] * inv_d, -U[2] * inv_d, 0, 1, 0, 0, 0, 1 };
            /* w = X^T U / D and its quadratic form on the parent's response */
            const double w[3] = { (U[0] - ry * U[1] + rx * U[2]) * inv_d, U[1] * inv_d,
                                  U[2] * inv_d };
            double T[9], XLX[9];
            for (i = 0; i < 3; i++)
                minv += w[i] * (Lp[3 * i] * w[0] + Lp[3 * i + 1] * w[1] + Lp[3 * i + 2] * w[2]);
            rj__mat3_congruent(X, Lp, T, XLX);
            rj__mat3_congruent(P, XLX, T, L);
        }
        L[0] += inv_d;
        m->jnt[m->qj[qi]].minv = minv;
    }
}

/* An articulated-body tree's constants and bound: each 1 / I_red (rj__rig_tree_minv) and
   the power iteration on K^1/2 M^-1 K^1/2 with a solve per iteration instead of the dense
   inverse. lam: rj__rig_tree_minv's scratch. */
static double rj__rig_tree_setup(rj_model *m, rj__rig *r, double *lam)
{
    const int n = m->nq;
    double *v = r->x, *u = r->tmp, *col = r->qdd, lam_top = 0;
    int j, it;
    for (j = 0; j < n; j++)
        rj__rig_joint_inertias(m, r, j);
    rj__rig_tree_minv(m, r, lam);
    for (j = 0; j < n; j++)
        v[j] = 1.0 + 0.1 * j;
    for (it = 0; it < 500; it++) {
        for (j = 0; j < n; j++)
            u[j] = sqrt(m->jnt[m->qj[j]].k_lin) * v[j];
        rj__rig_solve(m, r, u, col);
        for (j = 0; j < n; j++)
            u[j] = sqrt(m->jnt[m->qj[j]].k_lin) * col[j];
        if (!rj__power_next(v, u, n, &lam_top))
            return 0;
    }
    return lam_top;
}

/* The solver in scratch at the start, at rest, its mass matrix factored; nonzero when
   there is nothing to factor or M is not positive definite. */
static int rj__rig_at_start(const rj_model *m, double *scratch, rj__rig *r)
{
    const int n = m->nq;
    int j;
    rj__rig_map(m, scratch, r, 0);
    for (j = 0; j < n; j++) {
        r->q[j] = m->jdef[m->qj[j]].angle0;
        r->qd[j] = r->qdp[j] = 0;
    }
    rj__rig_kin(m, r, r->q, r->qd, r->qdp);
    return n == 0 || rj__rig_factor(m, r);
}

/* Rigid-link model constants and the stability bound: omega_max^2 = largest eigenvalue of
   K^1/2 M^-1 K^1/2 at the initial configuration (power iteration), K the joints' linear
   stiffnesses (limits counted as for flexible links). Returns omega_max^2. scratch: the
   solver's without columns or rows, then a dense M's inverse or a tree's responses
   (rj__rig_bound_scratch). */
static double rj__rig_setup(rj_model *m, double *scratch)
{
    rj__rig r;
    const int n = m->nq;
    const size_t nj = (size_t) m->nj, nl = (size_t) m->nl;
    double *minv = scratch + rj__rigid_scratch(nj, nl, !m->rig_tree, 0, 0, 0), lam = 0, *v, *u;
    int j, k, it;
    if (rj__rig_at_start(m, scratch, &r))
        return 0;
    /* a tree's responses where a dense M's inverse would be */
    if (m->rig_tree)
        return rj__rig_tree_setup(m, &r, minv);
    for (j = 0; j < n; j++) {
        for (k = 0; k < n; k++)
            r.tmp[k] = k == j ? 1.0 : 0.0;
        rj__chol_solve(n, r.L, r.tmp, minv + (size_t) j * n);
    }
    for (k = 0; k < n; k++) {
        rj__rig_joint_inertias(m, &r, k);
        m->jnt[m->qj[k]].minv = minv[(size_t) k * n + k]; /* rate change per unit torque impulse: 1 / I_red */
    }
    if (m->nloop)
        rj__rig_loop_minv(m, minv, r.qd, r.qdp);
    if (m->ncp || m->nloop)
        return rj__rig_coupled_bound(m, minv, r.x, r.tmp, r.q, r.qd);
    /* power iteration on K^1/2 M^-1 K^1/2 */
    v = r.x;
    u = r.tmp;
    for (j = 0; j < n; j++)
        v[j] = 1.0 + 0.1 * j;
    for (it = 0; it < 500; it++) {
        for (j = 0; j < n; j++) {
            double sum = 0;
            for (k = 0; k < n; k++)
                sum += minv[(size_t) j * n + k] * sqrt(m->jnt[m->qj[k]].k_lin) * v[k];
            u[j] = sqrt(m->jnt[m->qj[j]].k_lin) * sum;
        }
        if (!rj__power_next(v, u, n, &lam))
            return 0;
    }
    return lam;
}

