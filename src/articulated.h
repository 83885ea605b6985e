/* ------------------------------------------------------------------ articulated bodies */
/* A rigid tree's M(q) x = b in O(n), without M: Featherstone's articulated-body recursion
   in the plane. Each coordinate q_j turns its joint's body 2 (and all that hangs from it)
   about the joint's pin P_j; quantities of that subtree are taken about P_j, on the motion
   (omega, v at P_j):
   - a body's inertia about its pin, with d = c - P and its mass m, centre c, inertia I:
     [[I + m |d|^2, -m d_y, m d_x], [-m d_y, m, 0], [m d_x, 0, m]];
   - moving a child's quantity from its pin to the parent's (r = P_child - P_parent; the
     child's pin moves at v + omega z x r): X = [[1, 0, 0], [-r_y, 1, 0], [r_x, 0, 1]]
     takes the parent's motion to the child's, X^T the child's force (moment about its
     pin, force) to the parent's, X^T A X an inertia.
   The factor (leaves first): IA_j = own_j + sum over children of X^T Ia_k X; U = IA_j s,
   D = s.U + rotor (s = (1, 0, 0): turning about the pin; a motor's rotor adds its
   reflected inertia to the joint's own rate only); Ia_j = IA_j - U U^T / D. A solve: u_j
   = b_j - s.p_j and p_parent += X^T (p_j + U u_j / D) leaves first, then x_j = (u_j -
   U.a_in) / D and a_j = a_in + s x_j, a_in = X a_parent, root first. A product M x runs
   the same tree as inverse dynamics at rest: accelerations root first, forces back. The
   dense path (rj__chol) stays for small trees, where it is cheaper, and for loops and
   cable loops, whose rows and rotors need M. */

/* The coordinate of body 2's parent joint, or -1 when body 1 is the ground or fixed. */
static int rj__ab_parent(const rj_model *m, int j)
{
    const int p = m->jdef[j].body1;
    return p >= 0 && m->rb_pjoint[p] >= 0 ? m->jq[m->rb_pjoint[p]] : -1;
}

/* X^T A X added into B (symmetric 3 x 3, 6 entries), r the arm. */
static void rj__ab_shift_inertia(const double *A, double rx, double ry, double *B)
{
    B[0] += A[0] + ry * ry * A[3] + rx * rx * A[5] - 2.0 * ry * A[1] + 2.0 * rx * A[2] -
            2.0 * rx * ry * A[4];
    B[1] += A[1] - ry * A[3] + rx * A[4];
    B[2] += A[2] - ry * A[4] + rx * A[5];
    B[3] += A[3];
    B[4] += A[4];
    B[5] += A[5];
}

/* A symmetric 3 x 3 (6 entries) times v. */
static void rj__ab_sym_mul(const double *A, const double *v, double *out)
{
    out[0] = A[0] * v[0] + A[1] * v[1] + A[2] * v[2];
    out[1] = A[1] * v[0] + A[3] * v[1] + A[4] * v[2];
    out[2] = A[2] * v[0] + A[4] * v[1] + A[5] * v[2];
}

/* Coordinate k's body's own inertia about its pin, from its own sums (rj__rig_own: mass,
   first moment m (c - P), inertia about P), which also starts its articulated inertia;
   its parent's coordinate and its rotor. Its arm from its parent's pin is written as
   the subtrees are gathered (rj__rig_tree_factor), which take the same difference. */
static void rj__ab_own(const rj_model *m, rj__rig *r, int k, const double *b)
{
    const int j = m->qj[k];
    double *rec = r->ab + RJ__AB_COUNT * (size_t) k;
    double *own = rec + RJ__AB_OWN;
    int i;
    own[0] = b[RJ__RL_SUB_J];
    own[1] = -b[RJ__RL_SUB_SY];
    own[2] = b[RJ__RL_SUB_SX];
    own[3] = b[RJ__RL_SUB_M];
    own[4] = 0;
    own[5] = b[RJ__RL_SUB_M];
    for (i = 0; i < 6; i++)
        rec[RJ__AB_IA + i] = own[i];
    rec[RJ__AB_PQ] = rj__ab_parent(m, j);
    rec[RJ__AB_ROT] = m->jnt[j].rotor;
    /* a root (on the ground or a fixed link) passes nothing up: no arm */
    rec[RJ__AB_RX] = rec[RJ__AB_RY] = 0;
}

/* The acceleration a coordinate's pin takes from its parent's (X a_parent), or 0. */
static void rj__ab_accel_in(const rj__rig *r, const double *rec, int pq, double *a)
{
    const double *ap;
    if (pq < 0) {
        a[0] = a[1] = a[2] = 0;
        return;
    }
    ap = r->ab + RJ__AB_COUNT * (size_t) pq + RJ__AB_A;
    a[0] = ap[0];
    a[1] = ap[1] - rec[RJ__AB_RY] * ap[0];
    a[2] = ap[2] + rec[RJ__AB_RX] * ap[0];
}

/* The factor's step at coordinate qi, whose articulated inertia IA is whole (its
   children's passed in): U, 1 / D, and its Ia moved to its parent's pin into the
   parent's IA. Nonzero when D is not positive. */
static int rj__ab_factor_at(rj__rig *r, int qi)
{
    double *rec = r->ab + RJ__AB_COUNT * (size_t) qi;
    const int pq = (int) rec[RJ__AB_PQ];
    const double *A = rec + RJ__AB_IA;
    double *U = rec + RJ__AB_U, Ia[6], inv_d;
    const double D = A[0] + rec[RJ__AB_ROT];
    U[0] = A[0];
    U[1] = A[1];
    U[2] = A[2];
    if (!(D > 0))
        return -1;
    inv_d = 1.0 / D;
    rec[RJ__AB_D] = inv_d;
    if (pq < 0)
        return 0;
    Ia[0] = A[0] - U[0] * U[0] * inv_d;
    Ia[1] = A[1] - U[0] * U[1] * inv_d;
    Ia[2] = A[2] - U[0] * U[2] * inv_d;
    Ia[3] = A[3] - U[1] * U[1] * inv_d;
    Ia[4] = A[4] - U[1] * U[2] * inv_d;
    Ia[5] = A[5] - U[2] * U[2] * inv_d;
    rj__ab_shift_inertia(Ia, rec[RJ__AB_RX], rec[RJ__AB_RY],
                         r->ab + RJ__AB_COUNT * (size_t) pq + RJ__AB_IA);
    return 0;
}

/* Coordinate qi's u from its b and the force its children passed, and its own force
   moved to its parent's pin (none at a root). */
static void rj__ab_pass_up(rj__rig *r, int qi, double b)
{
    double *rec = r->ab + RJ__AB_COUNT * (size_t) qi;
    const int pq = (int) rec[RJ__AB_PQ];
    const double *U = rec + RJ__AB_U, *f = rec + RJ__AB_F;
    const double u = b - f[0], w = u * rec[RJ__AB_D];
    double *fp, px, py, pz;
    rec[RJ__AB_UU] = u;
    if (pq < 0)
        return;
    px = f[0] + U[0] * w;
    py = f[1] + U[1] * w;
    pz = f[2] + U[2] * w;
    fp = r->ab + RJ__AB_COUNT * (size_t) pq + RJ__AB_F;
    fp[0] += px - rec[RJ__AB_RY] * py + rec[RJ__AB_RX] * pz;
    fp[1] += py;
    fp[2] += pz;
}

/* The solve's pass from the leaves: u_j = b_j - s.p_j, and the force p_j + U u_j / D
   that each subtree passes to its parent's pin. */
static void rj__aba_leaves(const rj_model *m, rj__rig *r, const double *b)
{
    const int n = m->nq;
    int k;
    for (k = 0; k < n; k++) {
        double *f = r->ab + RJ__AB_COUNT * (size_t) k + RJ__AB_F;
        f[0] = f[1] = f[2] = 0;
    }
    for (k = n - 1; k >= 0; k--) {
        const int qi = m->jq[m->jorder[k]];
        rj__ab_pass_up(r, qi, b[qi]);
    }
}

/* The same for b = e_unit: every subtree without the unit passes nothing, so only the
   unit's path to its root is walked (u = 0 elsewhere). */
static void rj__aba_leaves_unit(const rj_model *m, rj__rig *r, int unit)
{
    int k;
    for (k = 0; k < m->nq; k++)
        r->ab[RJ__AB_COUNT * (size_t) k + RJ__AB_UU] = 0;
    for (k = unit; k >= 0; k = (int) r->ab[RJ__AB_COUNT * (size_t) k + RJ__AB_PQ]) {
        double *f = r->ab + RJ__AB_COUNT * (size_t) k + RJ__AB_F;
        f[0] = f[1] = f[2] = 0;
    }
    for (k = unit; k >= 0; k = (int) r->ab[RJ__AB_COUNT * (size_t) k + RJ__AB_PQ])
        rj__ab_pass_up(r, k, k == unit ? 1.0 : 0.0);
}

/* x = M^-1 b with the factor (b NULL: b = e_unit, a column of M^-1). */
static void rj__aba_solve(const rj_model *m, rj__rig *r, const double *b, int unit, double *x)
{
    const int n = m->nq;
    int k;
    if (b)
        rj__aba_leaves(m, r, b);
    else
        rj__aba_leaves_unit(m, r, unit);
    for (k = 0; k < n; k++) {
        const int qi = m->jq[m->jorder[k]];
        double *rec = r->ab + RJ__AB_COUNT * (size_t) qi;
        const double *U = rec + RJ__AB_U;
        double *a = rec + RJ__AB_A;
        rj__ab_accel_in(r, rec, (int) rec[RJ__AB_PQ], a);
        x[qi] = (rec[RJ__AB_UU] - (U[0] * a[0] + U[1] * a[1] + U[2] * a[2])) * rec[RJ__AB_D];
        a[0] += x[qi];
    }
}

/* y = M x (the bodies' inertias as the factor found them): accelerations root first,
   the subtrees' m a and its moment leaves first. */
static void rj__aba_mul(const rj_model *m, rj__rig *r, const double *x, double *y)
{
    const int n = m->nq;
    int k;
    for (k = 0; k < n; k++) {
        const int qi = m->jq[m->jorder[k]];
        double *rec = r->ab + RJ__AB_COUNT * (size_t) qi;
        double *a = rec + RJ__AB_A;
        rj__ab_accel_in(r, rec, (int) rec[RJ__AB_PQ], a);
        a[0] += x[qi];
        rj__ab_sym_mul(rec + RJ__AB_OWN, a, rec + RJ__AB_F);
    }
    for (k = n - 1; k >= 0; k--) {
        const int qi = m->jq[m->jorder[k]];
        const double *rec = r->ab + RJ__AB_COUNT * (size_t) qi, *f = rec + RJ__AB_F;
        const int pq = (int) rec[RJ__AB_PQ];
        double *fp;
        y[qi] = f[0] + rec[RJ__AB_ROT] * x[qi];
        if (pq < 0)
            continue;
        fp = r->ab + RJ__AB_COUNT * (size_t) pq + RJ__AB_F;
        fp[0] += f[0] - rec[RJ__AB_RY] * f[1] + rec[RJ__AB_RX] * f[2];
        fp[1] += f[1];
        fp[2] += f[2];
    }
}
