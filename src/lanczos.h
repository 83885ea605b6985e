/* ------------------------------------------------------------ Lanczos in vector lanes */
/* The Lanczos iteration of the stability bound (rj__omega2_max). Its vectors hold each
   kind of DOF apart (x of every node, then y, then the rotations: rj__lz_index), so that
   the elements along a link read their nodes in whole lanes. Its product takes the
   elements' linearisations from a table built once (rj__lz_table). Where the header has
   vector lanes (src/impl.h), the element products and the vector passes run in them,
   dispatched as the beam pass is: every lane does the scalar code's operations in its
   order, each DOF's sum takes its elements' terms in element order, and the dot products
   and norms sum their terms node by node (x, y, rotation), the order of rj__lz_apply's
   interleaved vectors: every build gives the same bits (tests/lanes.sh). */

/* The interleaved vector in (3 i + k) into its DOF kinds. */
static void rj__lz_split(const double *in, double *out, int nn)
{
    int i, k;
    for (i = 0; i < nn; i++)
        for (k = 0; k < 3; k++)
            out[rj__lz_index(3 * i + k, nn)] = in[3 * i + k];
}

/* The elements' linearisations (rj__elem_lin, one array a field, for the lanes) and their
   nodes, taken once for all of Lanczos's products: the chord's length and the ends' turns
   need a division and a dozen products an element, which the product then does not
   repeat. An element is plain when its nodes' translations are their own (no pin group);
   plain[c] counts the plain elements from c on along its link, which the lanes take
   whole. */
typedef struct rj__lz_table {
    const double *ex, *ey, *inv_r, *n_ax, *s_r, *kb, *kax, *l0sq;
    const int *ta, *tb; /* the nodes holding a's and b's translations */
    const int *ra;      /* node a (its rotation; b's is ra + 1) */
    const int *plain;
    int count;          /* the elements of the links that bend */
} rj__lz_table;

/* One element's row of the table. */
static void rj__lz_table_row(const rj_model *m, int l, int k, int c, double *f, int *idx)
{
    const size_t ne = (size_t) m->ne;
    const int a = m->link_first[l] + (k - m->link_efirst[l]);
    rj__elem_lin e;
    rj__elem_lin_at(m->link_kc + 4 * (size_t) l, m->x0[a + 1] - m->x0[a],
                    m->y0[a + 1] - m->y0[a], m->phi0[a] - m->beta0[k],
                    m->phi0[a + 1] - m->beta0[k], &e);
    f[c] = e.ex;
    f[ne + c] = e.ey;
    f[2 * ne + c] = e.inv_r;
    f[3 * ne + c] = e.n_ax;
    f[4 * ne + c] = e.s_r;
    f[5 * ne + c] = e.kb;
    f[6 * ne + c] = e.kax;
    f[7 * ne + c] = e.l0sq;
    idx[c] = rj__ub_root(m, a);
    idx[ne + c] = rj__ub_root(m, a + 1);
    idx[2 * ne + c] = a;
}

/* The table in area (8 ne doubles, then 4 ne ints), in rj__lz_elements's order. */
static void rj__lz_table_build(const rj_model *m, double *area, rj__lz_table *t)
{
    const size_t ne = (size_t) m->ne;
    double *f = area;
    int *idx = (int *) (void *) (area + 8 * ne), *plain = idx + 3 * ne;
    int l, k, c = 0;
    for (l = 0; l < m->nl; l++)
        if (m->link_path[l] != RJ__PATH_RIGID)
            for (k = m->link_efirst[l]; k < m->link_efirst[l + 1]; k++, c++)
                rj__lz_table_row(m, l, k, c, f, idx);
    /* from the last element back: a plain element starts a run one longer than the
       next element's, when that one is the next along the same link */
    for (k = c - 1; k >= 0; k--) {
        const int a = idx[2 * ne + k];
        const int own = idx[k] == a && idx[ne + k] == a + 1;
        const int next = k + 1 < c && idx[2 * ne + k + 1] == a + 1 ? plain[k + 1] : 0;
        plain[k] = own ? 1 + next : 0;
    }
    t->ex = f;
    t->ey = f + ne;
    t->inv_r = f + 2 * ne;
    t->n_ax = f + 3 * ne;
    t->s_r = f + 4 * ne;
    t->kb = f + 5 * ne;
    t->kax = f + 6 * ne;
    t->l0sq = f + 7 * ne;
    t->ta = idx;
    t->tb = idx + ne;
    t->ra = idx + 2 * ne;
    t->plain = plain;
    t->count = c;
}

/* Element c's product K_e d summed into f (rj__lz_elements's sums in its order). */
static RJ__FORCE_INLINE void rj__lz_element(const rj__lz_table *t, int c, const double *d,
                                            double *f, int nn)
{
    const int ta = t->ta[c], tb = t->tb[c], ra = t->ra[c];
    const double *dx = d, *dy = d + nn, *dr = d + 2 * (size_t) nn;
    double *fx = f, *fy = f + nn, *fr = f + 2 * (size_t) nn;
    const double dq[6] = { dx[ta], dy[ta], dr[ra], dx[tb], dy[tb], dr[ra + 1] };
    rj__elem_lin e;
    double fe[6];
    e.ex = t->ex[c];
    e.ey = t->ey[c];
    e.inv_r = t->inv_r[c];
    e.n_ax = t->n_ax[c];
    e.s_r = t->s_r[c];
    e.kb = t->kb[c];
    e.kax = t->kax[c];
    e.l0sq = t->l0sq[c];
    rj__elem_lin_apply(&e, dq, fe);
    fx[ta] += fe[0];
    fy[ta] += fe[1];
    fr[ra] += fe[2];
    fx[tb] += fe[3];
    fy[tb] += fe[4];
    fr[ra + 1] += fe[5];
}

#ifdef RJ__LANES
/* One kind of DOF of the lane's nodes a .. a + RJ__VW: node a + j takes b's term of
   element j - 1, then a's of element j (the scalar code's order; -0.0 adds nothing at
   node a, whose b term came before), node a + RJ__VW b's term of the last. */
static RJ__FORCE_INLINE void rj__lz_node_sums(double *f, const rj__vd *fa, const rj__vd *fb)
{
    double shifted[RJ__VW + 1];
    rj__vd sum, prev;
    shifted[0] = -0.0;
    RJ__VST(shifted + 1, *fb);
    RJ__VLD(prev, shifted);
    RJ__VLD(sum, f);
    sum = (sum + prev) + *fa;
    RJ__VST(f, sum);
    f[RJ__VW] += shifted[RJ__VW];
}

/* The plain elements c .. c + RJ__VW - 1 (nodes a .. a + RJ__VW, a = ra[c]) in vector
   lanes: rj__elem_lin_apply's operations in its order (keep the two alike). */
static RJ__FORCE_INLINE void rj__lz_element_lanes(const rj__lz_table *t, int c,
                                                  const double *d, double *f, int nn)
{
    const size_t a = (size_t) t->ra[c], n2 = 2 * (size_t) nn;
    rj__vd q0, q1, q2, q3, q4, q5, ex, ey, inv_r, n_ax, s_r, kb, kax, l0sq;
    rj__vd dex, dey, e_de, dbeta, dtha, dthb, dma, dmb, dn, dsr, dfx, dfy, bx, by;
    RJ__VLD(q0, d + a);
    RJ__VLD(q1, d + nn + a);
    RJ__VLD(q2, d + n2 + a);
    RJ__VLD(q3, d + a + 1);
    RJ__VLD(q4, d + nn + a + 1);
    RJ__VLD(q5, d + n2 + a + 1);
    RJ__VLD(ex, t->ex + c);
    RJ__VLD(ey, t->ey + c);
    RJ__VLD(inv_r, t->inv_r + c);
    RJ__VLD(n_ax, t->n_ax + c);
    RJ__VLD(s_r, t->s_r + c);
    RJ__VLD(kb, t->kb + c);
    RJ__VLD(kax, t->kax + c);
    RJ__VLD(l0sq, t->l0sq + c);
    dex = q3 - q0;
    dey = q4 - q1;
    e_de = ex * dex + ey * dey;
    dbeta = (-ey * dex + ex * dey) * inv_r;
    dtha = q2 - dbeta;
    dthb = q5 - dbeta;
    dma = kb * (4.0 * dtha + 2.0 * dthb);
    dmb = kb * (2.0 * dtha + 4.0 * dthb);
    dn = kax * e_de / l0sq;
    dsr = ((dma + dmb) - 2.0 * s_r * e_de) * inv_r;
    dfx = -dn * ex - n_ax * dex - dsr * ey - s_r * dey;
    dfy = -dn * ey - n_ax * dey + dsr * ex + s_r * dex;
    bx = -dfx;
    by = -dfy;
    rj__lz_node_sums(f + a, &dfx, &bx);
    rj__lz_node_sums(f + nn + a, &dfy, &by);
    rj__lz_node_sums(f + n2 + a, &dma, &dmb);
}

/* *mag = |v| lane by lane */
static RJ__FORCE_INLINE void rj__vabs(const rj__vd *v, rj__vd *mag)
{
    rj__vl sign = { 0 };
    int k;
    for (k = 0; k < RJ__VW; k++)
        sign[k] = 0x7fffffffffffffffLL;
    *mag = (rj__vd) ((rj__vl) *v & sign);
}

/* Lanes' three kinds of terms for nodes i .. i + RJ__VW - 1 added to sum node by node. */
static RJ__FORCE_INLINE double rj__lz_sum_nodes(const rj__vd *px, const rj__vd *py,
                                                const rj__vd *pr, double sum)
{
    int k;
    for (k = 0; k < RJ__VW; k++) {
        sum += (*px)[k];
        sum += (*py)[k];
        sum += (*pr)[k];
    }
    return sum;
}
#endif

/* K d of the elements into f, plain runs in lanes where lanes_on. */
static RJ__FORCE_INLINE void rj__lz_elements_body(const rj__lz_table *t, const double *d,
                                                  double *f, int nn, int lanes_on)
{
    int c = 0;
    while (c < t->count) {
#ifdef RJ__LANES
        if (lanes_on && t->plain[c] >= RJ__VW) {
            rj__lz_element_lanes(t, c, d, f, nn);
            c += RJ__VW;
            continue;
        }
#else
        (void) lanes_on;
#endif
        rj__lz_element(t, c, d, f, nn);
        c++;
    }
}

/* After the product (w = K d): w = M^-1/2 w and alpha = w . v1, node by node. */
static RJ__FORCE_INLINE double rj__lz_unscale_dot(double *w, const double *sc, const double *v1,
                                                  int nn, int lanes_on)
{
    double a = 0;
    int i = 0, k;
#ifdef RJ__LANES
    if (lanes_on)
        for (; i + RJ__VW <= nn; i += RJ__VW) {
            double *wx = w + i, *wy = w + nn + i, *wr = w + 2 * (size_t) nn + i;
            const double *sx = sc + i, *sy = sc + nn + i, *sr = sc + 2 * (size_t) nn + i;
            const double *vx = v1 + i, *vy = v1 + nn + i, *vr = v1 + 2 * (size_t) nn + i;
            rj__vd x, y, r, s, v;
            RJ__VLD(x, wx);
            RJ__VLD(s, sx);
            x *= s;
            RJ__VST(wx, x);
            RJ__VLD(y, wy);
            RJ__VLD(s, sy);
            y *= s;
            RJ__VST(wy, y);
            RJ__VLD(r, wr);
            RJ__VLD(s, sr);
            r *= s;
            RJ__VST(wr, r);
            RJ__VLD(v, vx);
            x *= v;
            RJ__VLD(v, vy);
            y *= v;
            RJ__VLD(v, vr);
            r *= v;
            a = rj__lz_sum_nodes(&x, &y, &r, a);
        }
#else
    (void) lanes_on;
#endif
    for (; i < nn; i++)
        for (k = 0; k < 3; k++) {
            const size_t at = (size_t) k * (size_t) nn + (size_t) i;
            w[at] *= sc[at];
            a += w[at] * v1[at];
        }
    return a;
}

/* The three-term recurrence w -= alpha v1 + beta v0 over all 3 nn DOFs; returns max |w|. */
static RJ__FORCE_INLINE double rj__lz_recur(double *w, const double *v1, const double *v0,
                                            double a, double b, int n, int lanes_on)
{
    double big = 0;
    int i = 0;
#ifdef RJ__LANES
    if (lanes_on) {
        rj__vd va, vb, vbig;
        double p[RJ__VW];
        int k;
        rj__splat(&va, a);
        rj__splat(&vb, b);
        rj__splat(&vbig, 0.0);
        for (; i + RJ__VW <= n; i += RJ__VW) {
            rj__vd wv, x, y, mag;
            rj__vl more;
            RJ__VLD(wv, w + i);
            RJ__VLD(x, v1 + i);
            RJ__VLD(y, v0 + i);
            wv -= va * x + vb * y;
            RJ__VST(w + i, wv);
            rj__vabs(&wv, &mag);
            more = mag > vbig;
            vbig = (rj__vd) (((rj__vl) mag & more) | ((rj__vl) vbig & ~more));
        }
        RJ__VST(p, vbig);
        for (k = 0; k < RJ__VW; k++)
            if (p[k] > big)
                big = p[k];
    }
#else
    (void) lanes_on;
#endif
    for (; i < n; i++) {
        w[i] -= a * v1[i] + b * v0[i];
        if (fabs(w[i]) > big)
            big = fabs(w[i]);
    }
    return big;
}

/* |w| given big = max |w_i|, scaled by it so that the squares neither underflow nor
   overflow (omega^2 ~ 1e-166 for a link of 1e150 kg/m^3); the squares summed node by
   node. */
static RJ__FORCE_INLINE double rj__lz_norm(const double *w, double big, int nn, int lanes_on)
{
    double sum = 0, inv_big;
    int i = 0, k;
    if (big == 0 || !rj__finite(big))
        return big;
    inv_big = 1.0 / big;
#ifdef RJ__LANES
    if (lanes_on) {
        rj__vd vinv;
        rj__splat(&vinv, inv_big);
        for (; i + RJ__VW <= nn; i += RJ__VW) {
            rj__vd x, y, r;
            RJ__VLD(x, w + i);
            RJ__VLD(y, w + nn + i);
            RJ__VLD(r, w + 2 * (size_t) nn + i);
            x *= vinv;
            y *= vinv;
            r *= vinv;
            x *= x;
            y *= y;
            r *= r;
            sum = rj__lz_sum_nodes(&x, &y, &r, sum);
        }
    }
#else
    (void) lanes_on;
#endif
    for (; i < nn; i++)
        for (k = 0; k < 3; k++) {
            const double x = w[(size_t) k * (size_t) nn + (size_t) i];
            sum += (x * inv_big) * (x * inv_big);
        }
    return big * sqrt(sum);
}

/* After the product: alpha, the recurrence and beta = |w|. */
static RJ__FORCE_INLINE void rj__lz_orth_body(double *w, const double *sc, const double *v1,
                                              const double *v0, double beta_prev, int nn,
                                              double *alpha, double *beta, int lanes_on)
{
    double big;
    *alpha = rj__lz_unscale_dot(w, sc, v1, nn, lanes_on);
    big = rj__lz_recur(w, v1, v0, *alpha, beta_prev, 3 * nn, lanes_on);
    *beta = rj__lz_norm(w, big, nn, lanes_on);
}

/* The next Lanczos vector w / beta, its product's input d = M^-1/2 w, and v0 cleared: it
   becomes the next w. */
static RJ__FORCE_INLINE void rj__lz_advance_body(double *w, double inv_beta, const double *sc,
                                                 double *d, double *v0, int n, int lanes_on)
{
    int i = 0;
#ifdef RJ__LANES
    rj__vd vinv, zero;
    rj__splat(&vinv, inv_beta);
    rj__splat(&zero, 0.0);
    if (lanes_on)
        for (; i + RJ__VW <= n; i += RJ__VW) {
            rj__vd wv, s;
            RJ__VLD(wv, w + i);
            RJ__VLD(s, sc + i);
            wv *= vinv;
            RJ__VST(w + i, wv);
            wv *= s;
            RJ__VST(d + i, wv);
            RJ__VST(v0 + i, zero);
        }
#else
    (void) lanes_on;
#endif
    for (; i < n; i++) {
        w[i] *= inv_beta;
        d[i] = w[i] * sc[i];
        v0[i] = 0.0;
    }
}

/* The three passes compiled for AVX2 where the header dispatches, and for the including
   file's own target (lanes where RJ__DEFAULT_LANES_ON). */
#ifdef RJ__DISPATCH
RJ__AVX2 static void rj__lz_elements_avx2(const rj__lz_table *t, const double *d, double *f,
                                          int nn)
{
    rj__lz_elements_body(t, d, f, nn, 1);
}

RJ__AVX2 static void rj__lz_orth_avx2(double *w, const double *sc, const double *v1,
                                      const double *v0, double beta_prev, int nn, double *alpha,
                                      double *beta)
{
    rj__lz_orth_body(w, sc, v1, v0, beta_prev, nn, alpha, beta, 1);
}

RJ__AVX2 static void rj__lz_advance_avx2(double *w, double inv_beta, const double *sc, double *d,
                                         double *v0, int n)
{
    rj__lz_advance_body(w, inv_beta, sc, d, v0, n, 1);
}
#endif

static void rj__lz_elements_default(const rj__lz_table *t, const double *d, double *f, int nn)
{
    rj__lz_elements_body(t, d, f, nn, RJ__DEFAULT_LANES_ON);
}

static void rj__lz_orth_default(double *w, const double *sc, const double *v1, const double *v0,
                                double beta_prev, int nn, double *alpha, double *beta)
{
    rj__lz_orth_body(w, sc, v1, v0, beta_prev, nn, alpha, beta, RJ__DEFAULT_LANES_ON);
}

static void rj__lz_advance_default(double *w, double inv_beta, const double *sc, double *d,
                                   double *v0, int n)
{
    rj__lz_advance_body(w, inv_beta, sc, d, v0, n, RJ__DEFAULT_LANES_ON);
}

/* The passes in the widest lanes the CPU has, chosen once a bound. */
typedef struct rj__lz_passes {
    void (*elements)(const rj__lz_table *, const double *, double *, int);
    void (*orth)(double *, const double *, const double *, const double *, double, int,
                 double *, double *);
    void (*advance)(double *, double, const double *, double *, double *, int);
} rj__lz_passes;

static void rj__lz_passes_pick(rj__lz_passes *p)
{
    p->elements = rj__lz_elements_default;
    p->orth = rj__lz_orth_default;
    p->advance = rj__lz_advance_default;
#ifdef RJ__DISPATCH
    if (__builtin_cpu_supports("avx2")) {
        p->elements = rj__lz_elements_avx2;
        p->orth = rj__lz_orth_avx2;
        p->advance = rj__lz_advance_avx2;
    }
#endif
}

/* Whether Lanczos has converged after k steps (every 4th, from the 8th): its largest Ritz
   value theta moved by less than RJ__LZ_TOL of itself in the last 4 steps (*last: theta
   then), and it is within RJ__BOUND_GAP of the upper bound, so that a plateau far below
   omega_max^2 cannot pass for convergence. A theta above the bound (round-off in a model of
   extreme scales) voids the bound (*upper = HUGE_VAL): Lanczos runs its course. These tests
   take theta to 1e-11 by Newton's method (rj__tridiag_top; its last bits cannot move
   them); the estimate returned is bisection's to 1e-14 (rj__tridiag_max_near). */
static int rj__lz_converged(const double *al, const double *be, int k, double *last,
                            double *upper)
{
    double theta, moved;
    if (k % 4 != 0 || k < 8 || !(*upper < HUGE_VAL))
        return 0;
    theta = rj__tridiag_top(al, be, k, 1e-11);
    moved = theta - *last;
    *last = theta;
    if (theta > *upper * (1.0 + 1e-9)) {
        *upper = HUGE_VAL;
        return 0;
    }
    return fabs(moved) <= RJ__LZ_TOL * theta && theta >= (1.0 - RJ__BOUND_GAP) * *upper;
}

/* Lanczos's first product's input d = M^-1/2 v1, and w = 0 to sum the product into. */
static void rj__lz_load(const double *v1, const double *sc, double *d, double *w, int n)
{
    int i;
    for (i = 0; i < n; i++) {
        d[i] = v1[i] * sc[i];
        w[i] = 0.0;
    }
}

/* omega_max^2 of the linearised model by Lanczos (no reorthogonalisation: ghosts do not
   move the extreme Ritz value), stopped once converged (rj__lz_converged). Its product is
   rj__lz_apply's on vectors of DOF kinds (rj__lz_index), with the elements' linearisations
   tabled (rj__lz_table) after the five vectors. */
static double rj__omega2_max(rj_model *m, double *lanczos)
{
    const int n = 3 * m->nn;
    double *v0 = lanczos, *v1 = lanczos + n, *w = lanczos + 2 * n;
    double *sc = lanczos + 3 * n, *d = lanczos + 4 * n;
    double al[RJ__LANCZOS_ITERS], be[RJ__LANCZOS_ITERS], last = 0;
    double upper = rj__omega2_upper(m, v0);
    rj__lz_table table;
    rj__lz_passes pass;
    int i, k, kmax;
    /* the start and the scales as the interleaved vectors had them, then split */
    if (!rj__lz_start(m, v0, w))
        return 0;
    rj__lz_split(w, v1, m->nn);
    rj__lz_scales(m, d);
    rj__lz_split(d, sc, m->nn);
    rj__lz_table_build(m, lanczos + 5 * n, &table);
    rj__lz_passes_pick(&pass);
    rj__lz_load(v1, sc, d, w, n);
    kmax = n < RJ__LANCZOS_ITERS ? n : RJ__LANCZOS_ITERS;
    for (k = 0; k < kmax; k++) {
        double a, b, *t;
        pass.elements(&table, d, w, m->nn);
        rj__lz_rank_one(m, d, w, m->nn);
        pass.orth(w, sc, v1, v0, k > 0 ? be[k - 1] : 0.0, m->nn, &a, &b);
        al[k] = a;
        be[k] = b;
        /* a NaN or an infinity: no finite frequency (below) */
        if (!rj__finite(a) || !rj__finite(b) || b < 1e-12 * fabs(a) || b == 0) {
            k++;
            break;
        }
        if (rj__lz_converged(al, be, k + 1, &last, &upper))
            return rj__tridiag_max_near(al, be, k + 1, last);
        pass.advance(w, 1.0 / b, sc, d, v0, n);
        t = v0;
        v0 = v1;
        v1 = w;
        w = t;
    }
    /* a NaN or an infinity in the recurrence: no finite frequency (the bound refuses it) */
    for (i = 0; i < k; i++)
        if (!rj__finite(al[i]) || !rj__finite(be[i]))
            return HUGE_VAL;
    return rj__tridiag_max(al, be, k);
}
