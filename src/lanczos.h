/* ------------------------------------------------------------ Lanczos in vector lanes */
/* The Lanczos iteration of the stability bound (rj__omega2_max). Its product takes the
   elements' linearisations from a table built once (rj__lz_table); the vector passes after
   it are merged. Where the header has vector lanes (src/impl.h), the element products and
   the passes run in them, dispatched as the beam pass is: every lane does the scalar
   code's operations in its order, and the sums (alpha = w . v1, |w|^2) stay sums in DOF
   order, taken lane after lane, so that every build gives the same bits (tests/lanes.sh).
   Over the scalar loops, a 2000-element link's Lanczos step costs about a third. */

/* The elements' linearisations (rj__elem_lin, one array a field, for the lanes) and their
   DOFs, taken once for all of Lanczos's products: the chord's length and the ends' turns
   need a division and a dozen products an element, which the product then does not
   repeat. */
typedef struct rj__lz_table {
    const double *ex, *ey, *inv_r, *n_ax, *s_r, *kb, *kax, *l0sq;
    const int *dof; /* per element: a's translation, b's translation, a's rotation */
    int count;      /* the elements of the links that bend */
} rj__lz_table;

/* The table in area (8 ne doubles, then 3 ne ints), in rj__lz_elements's order. */
static void rj__lz_table_build(const rj_model *m, double *area, rj__lz_table *t)
{
    const size_t ne = (size_t) m->ne;
    double *f = area;
    int *dof = (int *) (void *) (area + 8 * ne);
    int l, k, c = 0;
    for (l = 0; l < m->nl; l++) {
        const double *kc = m->link_kc + 4 * (size_t) l;
        const int shift = m->link_first[l] - m->link_efirst[l];
        if (m->link_path[l] == RJ__PATH_RIGID)
            continue;
        for (k = m->link_efirst[l]; k < m->link_efirst[l + 1]; k++, c++) {
            const int a = k + shift;
            rj__elem_lin e;
            rj__elem_lin_at(kc, m->x0[a + 1] - m->x0[a], m->y0[a + 1] - m->y0[a],
                            m->phi0[a] - m->beta0[k], m->phi0[a + 1] - m->beta0[k], &e);
            f[c] = e.ex;
            f[ne + c] = e.ey;
            f[2 * ne + c] = e.inv_r;
            f[3 * ne + c] = e.n_ax;
            f[4 * ne + c] = e.s_r;
            f[5 * ne + c] = e.kb;
            f[6 * ne + c] = e.kax;
            f[7 * ne + c] = e.l0sq;
            dof[3 * c] = 3 * rj__ub_root(m, a);
            dof[3 * c + 1] = 3 * rj__ub_root(m, a + 1);
            dof[3 * c + 2] = 3 * a + 2;
        }
    }
    t->ex = f;
    t->ey = f + ne;
    t->inv_r = f + 2 * ne;
    t->n_ax = f + 3 * ne;
    t->s_r = f + 4 * ne;
    t->kb = f + 5 * ne;
    t->kax = f + 6 * ne;
    t->l0sq = f + 7 * ne;
    t->dof = dof;
    t->count = c;
}

/* Element c's product K_e d summed into f (rj__lz_elements's sums in its order). */
static RJ__FORCE_INLINE void rj__lz_element(const rj__lz_table *t, int c, const double *d,
                                            double *f)
{
    const int ta = t->dof[3 * c], tb = t->dof[3 * c + 1], ra = t->dof[3 * c + 2];
    const double dq[6] = { d[ta], d[ta + 1], d[ra], d[tb], d[tb + 1], d[ra + 3] };
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
    f[ta] += fe[0];
    f[ta + 1] += fe[1];
    f[ra] += fe[2];
    f[tb] += fe[3];
    f[tb + 1] += fe[4];
    f[ra + 3] += fe[5];
}

#ifdef RJ__LANES
/* Elements c .. c + RJ__VW - 1 in vector lanes: rj__elem_lin_apply's operations in its
   order (keep the two alike), then each element's six sums in element order. */
static RJ__FORCE_INLINE void rj__lz_element_lanes(const rj__lz_table *t, int c,
                                                  const double *d, double *f)
{
    double g[6][RJ__VW], o[6][RJ__VW];
    rj__vd q0, q1, q2, q3, q4, q5, ex, ey, inv_r, n_ax, s_r, kb, kax, l0sq;
    rj__vd dex, dey, e_de, dbeta, dtha, dthb, dma, dmb, dn, dsr, dfx, dfy;
    int k;
    for (k = 0; k < RJ__VW; k++) {
        const int *q = t->dof + 3 * (c + k);
        g[0][k] = d[q[0]];
        g[1][k] = d[q[0] + 1];
        g[2][k] = d[q[2]];
        g[3][k] = d[q[1]];
        g[4][k] = d[q[1] + 1];
        g[5][k] = d[q[2] + 3];
    }
    RJ__VLD(q0, g[0]);
    RJ__VLD(q1, g[1]);
    RJ__VLD(q2, g[2]);
    RJ__VLD(q3, g[3]);
    RJ__VLD(q4, g[4]);
    RJ__VLD(q5, g[5]);
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
    RJ__VST(o[0], dfx);
    RJ__VST(o[1], dfy);
    RJ__VST(o[2], dma);
    RJ__VST(o[3], dfx);
    RJ__VST(o[4], dfy);
    RJ__VST(o[5], dmb);
    for (k = 0; k < RJ__VW; k++) {
        const int *q = t->dof + 3 * (c + k);
        f[q[0]] += o[0][k];
        f[q[0] + 1] += o[1][k];
        f[q[2]] += o[2][k];
        f[q[1]] += -o[3][k];
        f[q[1] + 1] += -o[4][k];
        f[q[2] + 3] += o[5][k];
    }
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
#endif

/* K d of the elements into f, lanes where lanes_on. */
static RJ__FORCE_INLINE void rj__lz_elements_body(const rj__lz_table *t, const double *d,
                                                  double *f, int lanes_on)
{
    int c = 0;
#ifdef RJ__LANES
    if (lanes_on)
        for (; c + RJ__VW <= t->count; c += RJ__VW)
            rj__lz_element_lanes(t, c, d, f);
#else
    (void) lanes_on;
#endif
    for (; c < t->count; c++)
        rj__lz_element(t, c, d, f);
}

/* After the product (w = K d): w = M^-1/2 w, alpha = w . v1, the three-term recurrence
   w -= alpha v1 + beta v0, and |w| (scaled by its largest entry so that the squares
   neither underflow nor overflow: omega^2 ~ 1e-166 for a link of 1e150 kg/m^3). */
static RJ__FORCE_INLINE void rj__lz_orth_body(double *w, const double *sc, const double *v1,
                                              const double *v0, double beta_prev, int n,
                                              double *alpha, double *beta, int lanes_on)
{
    double a = 0, big = 0, sum = 0, inv_big;
    int i = 0;
#ifdef RJ__LANES
    rj__vd va, vb, vbig, vinv;
    double p[RJ__VW];
    int k;
#else
    (void) lanes_on;
#endif
#ifdef RJ__LANES
    if (lanes_on)
        for (; i + RJ__VW <= n; i += RJ__VW) {
            rj__vd wv, s, x;
            RJ__VLD(wv, w + i);
            RJ__VLD(s, sc + i);
            RJ__VLD(x, v1 + i);
            wv *= s;
            RJ__VST(w + i, wv);
            wv *= x;
            RJ__VST(p, wv);
            for (k = 0; k < RJ__VW; k++)
                a += p[k];
        }
#endif
    for (; i < n; i++) {
        w[i] *= sc[i];
        a += w[i] * v1[i];
    }
    *alpha = a;
    i = 0;
#ifdef RJ__LANES
    rj__splat(&va, a);
    rj__splat(&vb, beta_prev);
    rj__splat(&vbig, 0.0);
    if (lanes_on) {
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
#endif
    for (; i < n; i++) {
        w[i] -= a * v1[i] + beta_prev * v0[i];
        if (fabs(w[i]) > big)
            big = fabs(w[i]);
    }
    if (big == 0 || !rj__finite(big)) {
        *beta = big;
        return;
    }
    inv_big = 1.0 / big;
    i = 0;
#ifdef RJ__LANES
    rj__splat(&vinv, inv_big);
    if (lanes_on)
        for (; i + RJ__VW <= n; i += RJ__VW) {
            rj__vd wv;
            RJ__VLD(wv, w + i);
            wv *= vinv;
            wv *= wv;
            RJ__VST(p, wv);
            for (k = 0; k < RJ__VW; k++)
                sum += p[k];
        }
#endif
    for (; i < n; i++)
        sum += (w[i] * inv_big) * (w[i] * inv_big);
    *beta = big * sqrt(sum);
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
RJ__AVX2 static void rj__lz_elements_avx2(const rj__lz_table *t, const double *d, double *f)
{
    rj__lz_elements_body(t, d, f, 1);
}

RJ__AVX2 static void rj__lz_orth_avx2(double *w, const double *sc, const double *v1,
                                      const double *v0, double beta_prev, int n, double *alpha,
                                      double *beta)
{
    rj__lz_orth_body(w, sc, v1, v0, beta_prev, n, alpha, beta, 1);
}

RJ__AVX2 static void rj__lz_advance_avx2(double *w, double inv_beta, const double *sc, double *d,
                                         double *v0, int n)
{
    rj__lz_advance_body(w, inv_beta, sc, d, v0, n, 1);
}
#endif

static void rj__lz_elements_default(const rj__lz_table *t, const double *d, double *f)
{
    rj__lz_elements_body(t, d, f, RJ__DEFAULT_LANES_ON);
}

static void rj__lz_orth_default(double *w, const double *sc, const double *v1, const double *v0,
                                double beta_prev, int n, double *alpha, double *beta)
{
    rj__lz_orth_body(w, sc, v1, v0, beta_prev, n, alpha, beta, RJ__DEFAULT_LANES_ON);
}

static void rj__lz_advance_default(double *w, double inv_beta, const double *sc, double *d,
                                   double *v0, int n)
{
    rj__lz_advance_body(w, inv_beta, sc, d, v0, n, RJ__DEFAULT_LANES_ON);
}

/* The passes in the widest lanes the CPU has, chosen once a bound. */
typedef struct rj__lz_passes {
    void (*elements)(const rj__lz_table *, const double *, double *);
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
   rj__lz_apply's, with the elements' linearisations tabled (rj__lz_table) after the five
   vectors. */
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
    if (!rj__lz_start(m, v0, v1))
        return 0;
    rj__lz_scales(m, sc);
    rj__lz_table_build(m, lanczos + 5 * n, &table);
    rj__lz_passes_pick(&pass);
    rj__lz_load(v1, sc, d, w, n);
    kmax = n < RJ__LANCZOS_ITERS ? n : RJ__LANCZOS_ITERS;
    for (k = 0; k < kmax; k++) {
        double a, b, *t;
        pass.elements(&table, d, w);
        rj__lz_rank_one(m, d, w);
        pass.orth(w, sc, v1, v0, k > 0 ? be[k - 1] : 0.0, n, &a, &b);
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
