/* ------------------------------------------------------------------ the stability bound */
/* omega_max^2, the largest eigenvalue of M^-1 K for the linearised model (K: the tangent of
   the elements' forces, the joints' springs and the cable loops' at the start; M: the
   lumped masses), sets the step. Lanczos on the whole linearised operator (rj__lz_apply)
   estimates it from below; it stops once its largest Ritz value has settled, which takes
   8 to 40 of its RJ__LANCZOS_ITERS steps where the spectrum's top is not crowded.

   Settling alone could be a plateau, so a second estimate checks it from above, element by
   element (Irons and Treharne 1971; Flanagan and Belytschko 1981): split K into pieces K_p
   (each element, each joint spring, each cable loop) and each DOF's mass among the pieces
   that touch it (M = sum M_p); then u.K u = sum u.K_p u <= sum lambda_p u.M_p u <=
   max_p lambda_p u.M u, so omega_max^2 is at most the largest lambda_p, the piece's own
   eigenvalue with its share of the masses. A DOF's mass is shared in proportion to each
   piece's stiffness on it. The bound is exact for a link whose axial mode is its fastest,
   and up to 18 % high where bending and rotary inertia set the top (a uniform link of 200
   elements; 3.7 % at 2000), so Lanczos may stop only within RJ__BOUND_GAP below it; where
   it never gets there it runs its whole course. */
#define RJ__BOUND_GAP 0.25
#define RJ__LZ_TOL    1e-4

/* A translation DOF of node i lives at its group's first member (the root). */
static int rj__ub_root(const rj_model *m, int i)
{
    return m->node_grp[i] >= 0 ? m->grp_node[m->grp_first[m->node_grp[i]]] : i;
}

/* An element's linearisation at the start, all that its tangent's product needs: its
   chord e, 1 / |e|^2, its axial force, its end moments' sum over |e|^2 and its section's
   constants (kc: EI / l0, EA / l0, l0^2, 1 / (2 l0^2)). */
typedef struct rj__elem_lin {
    double ex, ey, inv_r, n_ax, s_r, kb, kax, l0sq;
} rj__elem_lin;

/* The element at chord (ex, ey) with ends turned tha, thb off it (r = |e|^2). */
static RJ__INLINE void rj__elem_lin_at(const double *kc, double ex, double ey, double tha,
                                       double thb, rj__elem_lin *e)
{
    const double kb = kc[0], kax = kc[1], l0sq = kc[2], half_inv_l0sq = kc[3];
    const double r = ex * ex + ey * ey, inv_r = 1.0 / r;
    e->ex = ex;
    e->ey = ey;
    e->inv_r = inv_r;
    e->n_ax = kax * (r - l0sq) * half_inv_l0sq;
    e->s_r = 6.0 * kb * (tha + thb) * inv_r;
    e->kb = kb;
    e->kax = kax;
    e->l0sq = l0sq;
}

/* An element's tangent stiffness times dq (its nodes' x, y, rotation: a, then b), in closed
   form: the derivative of rj__elem_forces at the element's start, whatever its stress
   there. The strain's change is e.de / l0^2, the chord angle's perp(e).de / r (perp(e) =
   (-ey, ex)), each end's turn dphi - dbeta; node b's force -N e + (S / r) perp(e) (S = ma
   + mb) changes by -dN e - N de + (dS / r - 2 S e.de / r^2) perp(e) + (S / r) perp(de). */
static RJ__INLINE void rj__elem_lin_apply(const rj__elem_lin *e, const double dq[6],
                                          double out[6])
{
    const double ex = e->ex, ey = e->ey, inv_r = e->inv_r, kb = e->kb;
    const double n_ax = e->n_ax, s_r = e->s_r;
    const double dex = dq[3] - dq[0], dey = dq[4] - dq[1];
    const double e_de = ex * dex + ey * dey;
    const double dbeta = (-ey * dex + ex * dey) * inv_r;
    const double dtha = dq[2] - dbeta, dthb = dq[5] - dbeta;
    const double dma = kb * (4.0 * dtha + 2.0 * dthb);
    const double dmb = kb * (2.0 * dtha + 4.0 * dthb);
    const double dn = e->kax * e_de / e->l0sq;
    const double dsr = ((dma + dmb) - 2.0 * s_r * e_de) * inv_r;
    const double dfx = -dn * ex - n_ax * dex - dsr * ey - s_r * dey;
    const double dfy = -dn * ey - n_ax * dey + dsr * ex + s_r * dex;
    /* K = -dF/dq with F = (-f_b, -ma, f_b, -mb) */
    out[0] = dfx;
    out[1] = dfy;
    out[2] = dma;
    out[3] = -dfx;
    out[4] = -dfy;
    out[5] = dmb;
}

/* The tangent's product for an element at chord (ex, ey), ends turned tha, thb. */
static RJ__INLINE void rj__elem_tangent(const double *kc, double ex, double ey, double tha,
                                        double thb, const double dq[6], double out[6])
{
    rj__elem_lin e;
    rj__elem_lin_at(kc, ex, ey, tha, thb, &e);
    rj__elem_lin_apply(&e, dq, out);
}

/* Element k of link l at the start: its chord and its ends' turns off it. */
static void rj__elem_start(const rj_model *m, int l, int k, double *ex, double *ey,
                           double *tha, double *thb)
{
    const int a = m->link_first[l] + (k - m->link_efirst[l]);
    *ex = m->x0[a + 1] - m->x0[a];
    *ey = m->y0[a + 1] - m->y0[a];
    *tha = m->phi0[a] - m->beta0[k];
    *thb = m->phi0[a + 1] - m->beta0[k];
}

/* A symmetric tridiagonal matrix (al, be: be[i] couples i and i + 1), k <=
   RJ__LANCZOS_ITERS, scaled to entries of order 1: the Sturm recurrence squares the
   off-diagonal, which for a model of omega^2 ~ 1e-166 (a link of 1e150 kg/m^3) underflowed
   and cut omega_max by 6. Into al_s and be2 (be2[i] = be[i - 1]^2, be2[0] = 0) with
   Gershgorin's interval [lo, hi], which holds every eigenvalue; returns the scale (0: a
   zero matrix). */
static double rj__tridiag_scaled(const double *al_in, const double *be_in, int k, double *al,
                                 double *be2, double *lo, double *hi)
{
    double scale = 0;
    int i;
    *lo = 0;
    *hi = 0;
    for (i = 0; i < k; i++) {
        if (fabs(al_in[i]) > scale)
            scale = fabs(al_in[i]);
        if (fabs(be_in[i]) > scale)
            scale = fabs(be_in[i]);
    }
    if (scale == 0)
        return 0;
    for (i = 0; i < k; i++) {
        const double be_prev = i > 0 ? be_in[i - 1] / scale : 0;
        const double be_next = i + 1 < k ? be_in[i] / scale : 0;
        const double r = fabs(be_prev) + fabs(be_next);
        al[i] = al_in[i] / scale;
        be2[i] = be_prev * be_prev;
        if (al[i] + r > *hi)
            *hi = al[i] + r;
        if (al[i] - r < *lo)
            *lo = al[i] - r;
    }
    return scale;
}

/* How many eigenvalues of the scaled tridiagonal lie below x: the negative pivots of
   T - x. */
static int rj__sturm_below(const double *al, const double *be2, int k, double x)
{
    double q = al[0] - x;
    int i, cnt;
    if (q == 0.0)
        q = 1e-300;
    cnt = q < 0;
    for (i = 1; i < k; i++) {
        q = al[i] - x - be2[i] / q;
        if (q == 0.0)
            q = 1e-300;
        cnt += q < 0;
    }
    return cnt;
}

/* The top eigenvalue by bisection of [lo, hi] until the bracket is within rtol of it;
   returns hi. near: the top to within 1e-11 from above (rj__tridiag_top), or 0 for none.
   A midpoint farther than 1e-10 of near from it takes its side without a Sturm count,
   which could not say otherwise there (the count is exact for a matrix within round-off
   of T), so the result is the bits of the bisection that counts every time. */
static double rj__tridiag_bisect(const double *al, const double *be2, int k, double lo,
                                 double hi, double rtol, double near)
{
    const double above = near > 0 ? near * (1.0 + 1e-10) : HUGE_VAL;
    const double below = near > 0 ? near * (1.0 - 1e-10) : -HUGE_VAL;
    int it;
    for (it = 0; it < 200; it++) {
        const double mid = 0.5 * (lo + hi);
        int all_below;
        if (mid > above)
            all_below = 1;
        else if (mid < below)
            all_below = 0;
        else
            all_below = rj__sturm_below(al, be2, k, mid) == k;
        if (all_below)
            hi = mid;
        else
            lo = mid;
        if (hi - lo <= rtol * fabs(hi))
            break;
    }
    return hi;
}

/* Largest eigenvalue of a symmetric tridiagonal matrix to rtol of itself (Sturm bisection
   from Gershgorin's interval). */
static double rj__tridiag_max_to(const double *al_in, const double *be_in, int k, double rtol)
{
    double al[RJ__LANCZOS_ITERS], be2[RJ__LANCZOS_ITERS], lo, hi;
    const double scale = rj__tridiag_scaled(al_in, be_in, k, al, be2, &lo, &hi);
    if (scale == 0)
        return 0;
    return rj__tridiag_bisect(al, be2, k, lo, hi, rtol, 0.0) * scale;
}

/* The same to 1e-14 (the estimate the bound returns), near: its top to 1e-11 from above
   (rj__tridiag_top), which spares most of the counts; the same bits. */
static double rj__tridiag_max_near(const double *al_in, const double *be_in, int k, double near)
{
    double al[RJ__LANCZOS_ITERS], be2[RJ__LANCZOS_ITERS], lo, hi;
    const double scale = rj__tridiag_scaled(al_in, be_in, k, al, be2, &lo, &hi);
    if (scale == 0)
        return 0;
    return rj__tridiag_bisect(al, be2, k, lo, hi, 1e-14, near / scale) * scale;
}

/* Newton's step toward the top eigenvalue from x above it: the pivots q_i of x - T (all
   positive there) and their derivatives give p'/p = sum q_i' / q_i of p(x) = det(x - T),
   which is sum 1 / (x - lambda_j) >= 1 / (x - lambda_max): x - p / p' stays above the
   top. Returns p'/p, or 0 when a pivot is not positive (x is not above the top). */
static double rj__tridiag_newton_sum(const double *al, const double *be2, int k, double x)
{
    double q = x - al[0], dq = 1.0, inv_q, sum;
    int i;
    if (!(q > 0))
        return 0;
    inv_q = 1.0 / q;
    sum = dq * inv_q;
    for (i = 1; i < k; i++) {
        const double t = be2[i] * inv_q;
        dq = 1.0 + t * dq * inv_q;
        q = x - al[i] - t;
        if (!(q > 0))
            return 0;
        inv_q = 1.0 / q;
        sum += dq * inv_q;
    }
    return sum;
}

/* The largest eigenvalue of a tridiagonal matrix to rtol, from above, for the convergence
   checks: bisection until one eigenvalue lies above lo, then Newton's method from hi (each
   step stays above the top), stopped once its step is within rtol and a Sturm count puts
   the top above x (1 - rtol); bisection again where Newton stalls. */
static double rj__tridiag_top(const double *al_in, const double *be_in, int k, double rtol)
{
    double al[RJ__LANCZOS_ITERS], be2[RJ__LANCZOS_ITERS], lo, hi, x;
    const double scale = rj__tridiag_scaled(al_in, be_in, k, al, be2, &lo, &hi);
    int it, above = k;
    if (scale == 0)
        return 0;
    for (it = 0; it < 200 && above > 1 && hi - lo > rtol * fabs(hi); it++) {
        const double mid = 0.5 * (lo + hi);
        const int below = rj__sturm_below(al, be2, k, mid);
        if (below == k)
            hi = mid;
        else {
            lo = mid;
            above = k - below;
        }
    }
    if (above > 1)
        return hi * scale;
    x = hi;
    for (it = 0; it < 40; it++) {
        const double sum = rj__tridiag_newton_sum(al, be2, k, x);
        /* a pivot not positive: the last step rounded past the top, which it bracketed */
        if (!(sum > 0)) {
            lo = x > lo && x < hi ? x : lo;
            break;
        }
        if (!(x - 1.0 / sum > lo))
            break;
        hi = x;
        x -= 1.0 / sum;
        if (1.0 / sum <= 0.5 * rtol * fabs(x) &&
            rj__sturm_below(al, be2, k, x - rtol * fabs(x)) < k)
            return x * scale;
    }
    /* Newton stalled: bisection of what it bracketed */
    return rj__tridiag_bisect(al, be2, k, lo, hi, rtol, 0.0) * scale;
}

/* The largest eigenvalue to 1e-14 of itself: the estimate the bound returns. */
static double rj__tridiag_max(const double *al, const double *be, int k)
{
    return rj__tridiag_max_to(al, be, k, 1e-14);
}
/* The largest eigenvalue of a symmetric 6 x 6 matrix (A is destroyed; NaN when an entry
   is not finite): Householder's reflections make it tridiagonal (the trailing block takes
   A - v w^T - w v^T with p = A v, w = 2 (p - (v.p) v), |v| = 1), then its top by
   rj__tridiag_top to 1e-13. Cyclic Jacobi took 4 to 6 sweeps, 6700 instructions. */
static double rj__ub_eig6(double A[36])
{
    double al[6], be[6];
    int k, i, j;
    for (i = 0; i < 36; i++)
        if (!rj__finite(A[i]))
            return A[i] - A[i];
    for (k = 0; k < 4; k++) {
        double v[6], p[6], nrm = 0, alpha, vp = 0;
        for (i = k + 1; i < 6; i++) {
            v[i] = A[6 * i + k];
            nrm += v[i] * v[i];
        }
        nrm = sqrt(nrm);
        alpha = v[k + 1] > 0 ? -nrm : nrm;
        v[k + 1] -= alpha;
        nrm = 0;
        for (i = k + 1; i < 6; i++)
            nrm += v[i] * v[i];
        if (nrm == 0)
            continue;
        nrm = 1.0 / sqrt(nrm);
        for (i = k + 1; i < 6; i++)
            v[i] *= nrm;
        /* column k below the diagonal becomes (alpha, 0, ...) */
        A[6 * (k + 1) + k] = A[6 * k + k + 1] = alpha;
        for (i = k + 2; i < 6; i++)
            A[6 * i + k] = A[6 * k + i] = 0;
        for (i = k + 1; i < 6; i++) {
            p[i] = 0;
            for (j = k + 1; j < 6; j++)
                p[i] += A[6 * i + j] * v[j];
            vp += v[i] * p[i];
        }
        for (i = k + 1; i < 6; i++)
            p[i] = 2.0 * (p[i] - vp * v[i]);
        for (i = k + 1; i < 6; i++)
            for (j = k + 1; j < 6; j++)
                A[6 * i + j] -= v[i] * p[j] + p[i] * v[j];
    }
    for (i = 0; i < 6; i++) {
        al[i] = A[7 * i];
        be[i] = i < 5 ? A[6 * (i + 1) + i] : 0.0;
    }
    return rj__tridiag_top(al, be, 6, 1e-13);
}

/* The element stiffness, computed again only when the element's start or constants differ
   from the last one's (a uniform straight link's inner elements are all alike). It is
   taken in the element's own frame (its chord along x), where alike elements match
   whatever way they point; translation masses are the same in x and y, so the shares and
   the eigenvalue do not depend on the frame. */
typedef struct rj__ub_cache {
    double key[7]; /* kb, kax, l0^2, 1/(2 l0^2), chord length, tha, thb */
    double K[36];
    double s[6], lam; /* the eigenvalue at the mass shares s (lam < 0: none) */
} rj__ub_cache;

/* Whether two keys match to 1e-9, relative, and their last nabs entries (turns, near 0)
   absolute: the elements of a straight link differ in their last bits, where the nodes'
   places were summed, and the bound is a check that needs nothing like that precision. */
static int rj__ub_alike(const double *a, const double *b, int n, int nabs)
{
    int i;
    for (i = 0; i < n; i++) {
        const double big = fabs(a[i]) > fabs(b[i]) ? fabs(a[i]) : fabs(b[i]);
        const double tol = i >= n - nabs ? 1e-9 : 1e-9 * big;
        if (!(fabs(a[i] - b[i]) <= tol))
            return 0;
    }
    return 1;
}

static const double *rj__ub_elem(const rj_model *m, int l, int k, rj__ub_cache *cache)
{
    const double *kc = m->link_kc + 4 * (size_t) l;
    double key[7], ex, ey;
    int i, j;
    rj__elem_start(m, l, k, &ex, &ey, &key[5], &key[6]);
    for (i = 0; i < 4; i++)
        key[i] = kc[i];
    key[4] = sqrt(ex * ex + ey * ey);
    if (rj__ub_alike(key, cache->key, 7, 2))
        return cache->K;
    memcpy(cache->key, key, sizeof key);
    cache->lam = -1.0;
    for (j = 0; j < 6; j++) {
        double dq[6] = { 0, 0, 0, 0, 0, 0 }, col[6];
        dq[j] = 1.0;
        rj__elem_tangent(kc, key[4], 0.0, key[5], key[6], dq, col);
        for (i = 0; i < 6; i++)
            cache->K[6 * i + j] = col[i];
    }
    return cache->K;
}

/* A rank-one piece k v v^T (a joint's spring, a cable loop): v's entries by DOF, a node's
   translation under the key 3 r (r its root, x and y in vx, vy), its rotation under 3 i + 2
   (in vx). At most two joints of four nodes each. */
typedef struct rj__ub_piece {
    int n;
    int key[16];
    double vx[16], vy[16];
} rj__ub_piece;

static void rj__ub_add(rj__ub_piece *p, int key, double vx, double vy)
{
    int i;
    for (i = 0; i < p->n; i++)
        if (p->key[i] == key)
            break;
    if (i == p->n) {
        p->key[p->n] = key;
        p->vx[p->n] = 0;
        p->vy[p->n] = 0;
        p->n++;
    }
    p->vx[i] += vx;
    p->vy[i] += vy;
}

/* scale times the DOFs a unit torque on joint J loads at the start (rj__apply_torque's
   entries, the virtual work of a turn of the joint). */
static void rj__ub_torque(const rj_model *m, const rj__joint *J, double scale, rj__ub_piece *p)
{
    rj__jgeo g;
    double sx, sy;
    if (!J->chord) {
        rj__ub_add(p, 3 * J->nJ + 2, scale, 0);
        if (J->nI >= 0)
            rj__ub_add(p, 3 * J->nI + 2, -scale, 0);
        return;
    }
    rj__joint_geo(m, J, m->x0, m->y0, &g);
    sx = -scale * g.by / g.b2;
    sy = scale * g.bx / g.b2;
    rj__ub_add(p, 3 * rj__ub_root(m, J->nL), sx, sy);
    rj__ub_add(p, 3 * rj__ub_root(m, J->nJ), -sx, -sy);
    if (J->nK >= 0) {
        sx = scale * g.ay / g.a2;
        sy = -scale * g.ax / g.a2;
        rj__ub_add(p, 3 * rj__ub_root(m, J->nK), sx, sy);
        rj__ub_add(p, 3 * rj__ub_root(m, J->nI), -sx, -sy);
    }
}

/* The inverse mass of a DOF key (a translation's root, or a rotation). */
static RJ__FORCE_INLINE double rj__ub_inv(const rj_model *m, int key)
{
    return key % 3 == 2 ? m->rinv[key / 3] : rj__lz_inv(m, key / 3, 0);
}

/* Rank-one piece i: joint i's spring (i < nj, k_lin > 0) or cable loop i - nj; its
   stiffness k (0: no piece). */
static double rj__ub_rank_one(const rj_model *m, int i, rj__ub_piece *p)
{
    p->n = 0;
    if (i < m->nj) {
        if (!(m->jnt[i].k_lin > 0))
            return 0;
        rj__ub_torque(m, &m->jnt[i], 1.0, p);
        return m->jnt[i].k_lin;
    } else {
        const rj_coupling_def *c = &m->cp[i - m->nj];
        if (!(c->stiffness > 0))
            return 0;
        /* the loop's error e = turn_b - ratio turn_a */
        rj__ub_torque(m, &m->jnt[c->joint_b], 1.0, p);
        rj__ub_torque(m, &m->jnt[c->joint_a], -c->ratio, p);
        return c->stiffness;
    }
}

/* A rank-one piece's stiffness on each DOF key, k |v|^2, into W. */
static void rj__ub_rank_one_weights(const rj__ub_piece *p, double k, double *W)
{
    int i;
    for (i = 0; i < p->n; i++)
        W[p->key[i]] += k * (p->vx[i] * p->vx[i] + p->vy[i] * p->vy[i]);
}

/* A rank-one piece's eigenvalue with its share of the masses: with shares
   k |v_d|^2 / W_d of each DOF's mass, k v.M_p^-1 v = sum of W_d / m_d over its DOFs. */
static double rj__ub_rank_one_lambda(const rj_model *m, const rj__ub_piece *p, const double *W)
{
    double lam = 0;
    int i;
    for (i = 0; i < p->n; i++)
        if (p->vx[i] != 0 || p->vy[i] != 0)
            lam += W[p->key[i]] * rj__ub_inv(m, p->key[i]);
    return lam;
}

/* Element k of link l: its DOF keys (x and y of node a share the first, node b's the
   fourth) and its stiffness on each node's translation and rotation. */
static void rj__ub_elem_keys(const rj_model *m, int l, int k, int key[6])
{
    const int a = m->link_first[l] + (k - m->link_efirst[l]);
    key[0] = key[1] = 3 * rj__ub_root(m, a);
    key[2] = 3 * a + 2;
    key[3] = key[4] = 3 * rj__ub_root(m, a + 1);
    key[5] = 3 * (a + 1) + 2;
}

static void rj__ub_elem_weights(const double *K, const int key[6], double *W)
{
    W[key[0]] += fabs(K[0]) + fabs(K[7]);
    W[key[2]] += fabs(K[14]);
    W[key[3]] += fabs(K[21]) + fabs(K[28]);
    W[key[5]] += fabs(K[35]);
}

/* An element's eigenvalue with its share of the masses: DOF j takes the share w_j / W_j
   of its mass (w_j the element's own weight on it), so M_p^-1/2 K M_p^-1/2 has entries
   K_ij sqrt(s_i s_j), s_j = W_j / (w_j m_j). A DOF the element loads but gives no weight
   (a stressed start's off-diagonal alone): no bound (HUGE_VAL). */
static double rj__ub_elem_lambda(const rj_model *m, const double *K, const int key[6],
                                 const double *W, rj__ub_cache *cache)
{
    const double w[6] = { fabs(K[0]) + fabs(K[7]), fabs(K[0]) + fabs(K[7]), fabs(K[14]),
                          fabs(K[21]) + fabs(K[28]), fabs(K[21]) + fabs(K[28]), fabs(K[35]) };
    double s[6], A[36];
    int i, j;
    if (key[0] == key[3])
        return HUGE_VAL;
    for (i = 0; i < 6; i++) {
        const double inv = rj__ub_inv(m, key[i]);
        s[i] = w[i] > 0 ? W[key[i]] / w[i] * inv : 0.0;
        if (w[i] == 0 && inv > 0)
            for (j = 0; j < 6; j++)
                if (K[6 * i + j] != 0)
                    return HUGE_VAL;
    }
    /* the last element's eigenvalue again when its stiffness and shares are the same */
    if (cache->lam >= 0 && rj__ub_alike(s, cache->s, 6, 0))
        return cache->lam;
    for (i = 0; i < 6; i++)
        for (j = 0; j < 6; j++)
            A[6 * i + j] = 0.5 * (K[6 * i + j] + K[6 * j + i]) * sqrt(s[i] * s[j]);
    memcpy(cache->s, s, sizeof s);
    cache->lam = rj__ub_eig6(A);
    return cache->lam;
}

/* The upper bound on omega_max^2 (above); W: 3 nn doubles of scratch. */
static double rj__omega2_upper(const rj_model *m, double *W)
{
    rj__ub_cache cache;
    rj__ub_piece p;
    double top = 0;
    int l, k, i, key[6];
    for (i = 0; i < 3 * m->nn; i++)
        W[i] = 0;
    /* each piece's stiffness on each DOF: the weights that share its mass */
    for (i = 0; i < 7; i++)
        cache.key[i] = -1.0; /* no element has EI < 0: empty */
    cache.lam = -1.0;
    for (l = 0; l < m->nl; l++)
        for (k = m->link_efirst[l]; k < m->link_efirst[l + 1]; k++)
            if (m->link_path[l] != RJ__PATH_RIGID) {
                rj__ub_elem_keys(m, l, k, key);
                rj__ub_elem_weights(rj__ub_elem(m, l, k, &cache), key, W);
            }
    for (i = 0; i < m->nj + m->ncp; i++)
        rj__ub_rank_one_weights(&p, rj__ub_rank_one(m, i, &p), W);
    /* each piece's eigenvalue with its share */
    for (l = 0; l < m->nl; l++)
        for (k = m->link_efirst[l]; k < m->link_efirst[l + 1]; k++)
            if (m->link_path[l] != RJ__PATH_RIGID) {
                double lam;
                rj__ub_elem_keys(m, l, k, key);
                lam = rj__ub_elem_lambda(m, rj__ub_elem(m, l, k, &cache), key, W, &cache);
                if (lam > top || lam != lam)
                    top = lam;
            }
    for (i = 0; i < m->nj + m->ncp; i++)
        if (rj__ub_rank_one(m, i, &p) > 0) {
            const double lam = rj__ub_rank_one_lambda(m, &p, W);
            if (lam > top || lam != lam)
                top = lam;
        }
    return top;
}


/* M^-1/2 of every DOF (rj__lz_inv), for rj__lz_apply. */
static void rj__lz_scales(const rj_model *m, double *sc)
{
    int i;
    for (i = 0; i < m->nn; i++) {
        sc[3 * i] = sqrt(rj__lz_inv(m, i, 0));
        sc[3 * i + 1] = sc[3 * i];
        sc[3 * i + 2] = sqrt(m->rinv[i]);
    }
}

/* The elements' part of f = K d (d: the DOFs' moves; a node's translation at its root's). */
static void rj__lz_elements(const rj_model *m, const double *d, double *f)
{
    int l, k;
    for (l = 0; l < m->nl; l++) {
        const double *kc = m->link_kc + 4 * (size_t) l;
        const int shift = m->link_first[l] - m->link_efirst[l];
        if (m->link_path[l] == RJ__PATH_RIGID)
            continue;
        for (k = m->link_efirst[l]; k < m->link_efirst[l + 1]; k++) {
            const int a = k + shift;
            const int ta = 3 * rj__ub_root(m, a), tb = 3 * rj__ub_root(m, a + 1);
            const double dq[6] = { d[ta], d[ta + 1], d[3 * a + 2], d[tb], d[tb + 1], d[3 * a + 5] };
            double fe[6];
            rj__elem_tangent(kc, m->x0[a + 1] - m->x0[a], m->y0[a + 1] - m->y0[a],
                             m->phi0[a] - m->beta0[k], m->phi0[a + 1] - m->beta0[k], dq, fe);
            f[ta] += fe[0];
            f[ta + 1] += fe[1];
            f[3 * a + 2] += fe[2];
            f[tb] += fe[3];
            f[tb + 1] += fe[4];
            f[3 * a + 5] += fe[5];
        }
    }
}

/* The vector index of DOF key (3 i + k) of node i: interleaved, or with each kind of DOF
   apart when kinds is the node count (the Lanczos vectors, src/lanczos.h). */
static RJ__FORCE_INLINE size_t rj__lz_index(int key, int kinds)
{
    return kinds ? (size_t) (key % 3) * (size_t) kinds + (size_t) (key / 3) : (size_t) key;
}

/* The joints' springs and the cable loops' part of f = K d: k v (v . d) each; kinds as
   rj__lz_index's (a translation's y follows its x by 1, or by the node count). */
static void rj__lz_rank_one(const rj_model *m, const double *d, double *f, int kinds)
{
    const size_t to_y = kinds ? (size_t) kinds : 1;
    rj__ub_piece p;
    int i, q;
    for (i = 0; i < m->nj + m->ncp; i++) {
        const double k = rj__ub_rank_one(m, i, &p);
        double dot = 0;
        if (!(k > 0))
            continue;
        for (q = 0; q < p.n; q++) {
            const size_t at = rj__lz_index(p.key[q], kinds);
            dot += p.vx[q] * d[at] + (p.key[q] % 3 == 0 ? p.vy[q] * d[at + to_y] : 0.0);
        }
        for (q = 0; q < p.n; q++) {
            const size_t at = rj__lz_index(p.key[q], kinds);
            f[at] += k * dot * p.vx[q];
            if (p.key[q] % 3 == 0)
                f[at + to_y] += k * dot * p.vy[q];
        }
    }
}

/* The linearised operator out = M^-1/2 K M^-1/2 u over the 3 nn node DOFs (a grouped
   node's translation lives at its group's first member; the other members' entries are
   unused and come out 0): the elements' tangents in closed form, the joints' linearised
   springs k g g^T (g: the DOFs a unit torque loads) and the cable loops'. sc: M^-1/2 of
   each DOF (rj__lz_scales); d: 3 nn doubles of scratch. */
static void rj__lz_apply(const rj_model *m, const double *sc, const double *u, double *out,
                         double *d)
{
    const int n = 3 * m->nn;
    int i;
    for (i = 0; i < n; i++) {
        d[i] = u[i] * sc[i];
        out[i] = 0.0;
    }
    rj__lz_elements(m, d, out);
    rj__lz_rank_one(m, d, out, 0);
    for (i = 0; i < n; i++)
        out[i] *= sc[i];
}

/* Lanczos's start: on every DOF that moves, entries of a fixed pseudo-random sequence in
   [-1, 1) (splitmix64 of the index), which meet every mode alike (a smooth start barely
   meets the zigzag modes at the spectrum's top, and settled on a plateau 0.5 % below it on
   a link of 2000 elements); v0 = 0. Returns 0 when none moves. */
static int rj__lz_start(const rj_model *m, double *v0, double *v1)
{
    const int n = 3 * m->nn;
    double nrm = 0;
    int i;
    for (i = 0; i < n; i++) {
        unsigned long long z = (unsigned long long) (i + 1) * 0x9E3779B97F4A7C15ULL;
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
        z ^= z >> 31;
        v1[i] = (double) (z >> 11) * (2.0 / 9007199254740992.0) - 1.0;
        v0[i] = 0;
    }
    for (i = 0; i < m->nn; i++) {
        if (m->tinv[i] == 0) {
            v1[3 * i] = 0;
            v1[3 * i + 1] = 0;
        }
        if (m->rinv[i] == 0)
            v1[3 * i + 2] = 0;
    }
    for (i = 0; i < m->ng; i++) {
        int r = m->grp_node[m->grp_first[i]];
        if (m->grp_inv[i] > 0) {
            v1[3 * r] = 1.0;
            v1[3 * r + 1] = 0.7;
        }
    }
    for (i = 0; i < n; i++)
        nrm += v1[i] * v1[i];
    if (nrm == 0)
        return 0;
    nrm = sqrt(nrm);
    for (i = 0; i < n; i++)
        v1[i] /= nrm;
    return 1;
}
