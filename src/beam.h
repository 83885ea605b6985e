/* ------------------------------------------------------------------ beam forces */
/* Co-rotational planar Euler-Bernoulli element (Crisfield): chord e = x_b - x_a, axial
   Green strain eps = (|e|^2 - l0^2) / (2 l0^2), chord angle beta tracked incrementally
   from a reference chord (no atan2 per element), local rotations th_a = phi_a - beta,
   th_b = phi_b - beta, end moments M_a = EI/l0 (4 th_a + 2 th_b), M_b = EI/l0 (2 th_a + 4 th_b).
   Forces: node b gets -EA/l0 eps e + (M_a + M_b) perp(e) / |e|^2, node a the opposite;
   moments -M_a, -M_b. */
/* One element's force core on scalars or vector lanes alike (the same operations in the
   same order): chord turn r against the previous chord (ccx, ccy) as the series of atan(r),
   chord angle bt, end moments, axial force, node-b force (fx_, fy_) and strain energy u_. */
#define RJ__ELEM_CORE(T, ex, ey, cxv, cyv, bbv, pav, pbv)                                          \
    const T cr_ = (cxv) * (ey) - (cyv) * (ex), dp_ = (cxv) * (ex) + (cyv) * (ey);                  \
    const T L2_ = (ex) * (ex) + (ey) * (ey), inv_ = 1.0 / (dp_ * L2_);                             \
    const T r_ = cr_ * L2_ * inv_, invL2_ = dp_ * inv_, r2_ = r_ * r_;                             \
    const T bt_ = (bbv) + r_ * (1.0 - r2_ * (1.0 / 3.0 - r2_ * (1.0 / 5.0)));                      \
    RJ__ELEM_FORCES(T, ex, ey, bt_, invL2_, pav, pbv)

/* The rest of the element from its chord angle bt and 1/|e|^2: end rotations and moments,
   axial force, node-b force (fx_, fy_), strain energy u_ (the exact path uses it alone). */
#define RJ__ELEM_FORCES(T, ex, ey, bt, invL2, pav, pbv)                                            \
    const T tha_ = (pav) - (bt), thb_ = (pbv) - (bt);                                              \
    const T ma_ = kb * (4.0 * tha_ + 2.0 * thb_), mb_ = kb * (2.0 * tha_ + 4.0 * thb_);            \
    const T eps_ = ((ex) * (ex) + (ey) * (ey) -l0sq) * half_inv_l0sq;                              \
    const T nax_ = kax * eps_, s_ = (ma_ + mb_) * (invL2);                                         \
    const T fx_ = -nax_ * (ex) -s_ * (ey), fy_ = -nax_ * (ey) + s_ * (ex);                         \
    const T u_ = 0.5 * (ma_ * tha_ + mb_ * thb_) + 0.5 * kax * l0sq * eps_ * eps_

/* Rows of a chunk's element-result buffer (one base pointer for the kernels): FX, FY,
   M1, M2, each RJ__FROW long; see rj__beam_pass for what the entries hold. */
#define RJ__CHUNK 128
#define RJ__FROW  (RJ__CHUNK + 2)

#ifdef RJ__LANES
/* STEP (a lane step at index i) over 0 .. n - 1, n >= W, in steps of W; where W does not
   divide n the last W again, after the loop: the same inputs give the same bits. */
#define RJ__LANES_OVER(i, n, W, STEP)                                                              \
    for (i = 0; i + W <= n; i += W)                                                                \
        STEP if (i < n)                                                                            \
        {                                                                                          \
            i = n - W;                                                                             \
            STEP                                                                                   \
        }
/* W elements from element i on, in lanes; F + i is element i's slot in row FX; EN: their
   strain energies too (without, the compiler drops their arithmetic); BK: their old chord
   angles and chords kept in bk first (in place, bo is bb: the exact path reads them there). */
#define RJ__ELEM_STEP(VD, i, EN, BK)                                                               \
    {                                                                                              \
        VD x0, x1, y0, y1, p0, p1, b, cxv, cyv, ex, ey;                                            \
        RJ__VLD(x0, xa + i);                                                                       \
        RJ__VLD(x1, xa + i + 1);                                                                   \
        RJ__VLD(y0, ya + i);                                                                       \
        RJ__VLD(y1, ya + i + 1);                                                                   \
        RJ__VLD(p0, pa + i);                                                                       \
        RJ__VLD(p1, pa + i + 1);                                                                   \
        RJ__VLD(b, bb + i);                                                                        \
        RJ__VLD(cxv, ccx + i);                                                                     \
        RJ__VLD(cyv, ccy + i);                                                                     \
        if (BK) {                                                                                  \
            RJ__VST(bk + i, b);                                                                    \
            RJ__VST(bk + RJ__CHUNK + i, cxv);                                                      \
            RJ__VST(bk + 2 * RJ__CHUNK + i, cyv);                                                  \
        }                                                                                          \
        ex = x1 - x0;                                                                              \
        ey = y1 - y0;                                                                              \
        {                                                                                          \
            RJ__ELEM_CORE(VD, ex, ey, cxv, cyv, b, p0, p1);                                        \
            okv &= (r2_ < lim) & (dp_ > zero); /* NaN clears it too */                             \
            RJ__VST(bo + i, bt_);                                                                  \
            RJ__VST(cox + i, ex);                                                                  \
            RJ__VST(coy + i, ey);                                                                  \
            RJ__VST(F + i, fx_);                                                                   \
            RJ__VST(F + RJ__FROW + i, fy_);                                                        \
            RJ__VST(F + 2 * RJ__FROW + i, ma_);                                                    \
            RJ__VST(F + 3 * RJ__FROW + i, mb_);                                                    \
            if (EN)                                                                                \
                RJ__VST(ue + i, u_);                                                               \
        }                                                                                          \
    }
/* The element loop in lanes of W doubles over all ne >= W elements (RJ__LANES_OVER), their
   strain energies if en is set; returns -1 when some chord turned too far (or a result is
   NaN), else ne. kc: the link's element constants (link_kc). In place (NAME##ip: bo, cox,
   coy are bb, ccx, ccy) it takes whole lanes only and returns how many elements it did,
   keeping their old values in bk (RJ__ELEM_STEP). */
#define RJ__ELEM_LANES(W, VD, VL, ATTR)                                                            \
    RJ__ELEM_LANES_(W, VD, VL, ATTR, rj__elem_lanes##W, RJ__RESTRICT, 0)                           \
    RJ__ELEM_LANES_(W, VD, VL, ATTR, rj__elem_lanes##W##ip, , 1)
#define RJ__ELEM_LANES_(W, VD, VL, ATTR, NAME, RQ, BK)                                             \
    ATTR static RJ__FORCE_INLINE int NAME(                                                         \
        int ne, const double *kc, const double *RJ__RESTRICT xa, const double *RJ__RESTRICT ya,    \
        const double *RJ__RESTRICT pa, const double *RQ bb, const double *RQ ccx,                  \
        const double *RQ ccy, double *RJ__RESTRICT F, double *RJ__RESTRICT ue, double *RQ bo,      \
        double *RQ cox, double *RQ coy, double *RJ__RESTRICT bk, int en)                           \
    {                                                                                              \
        const double kb = kc[0], kax = kc[1], l0sq = kc[2], half_inv_l0sq = kc[3];                 \
        VD lim, zero;                                                                              \
        VL okv;                                                                                    \
        int i, k;                                                                                  \
        for (k = 0; k < W; k++) {                                                                  \
            lim[k] = 4e-6;                                                                         \
            zero[k] = 0.0;                                                                         \
        }                                                                                          \
        okv = zero < lim; /* all lanes set */                                                      \
        if (BK && en) {                                                                            \
            for (i = 0; i + W <= ne; i += W)                                                       \
                RJ__ELEM_STEP(VD, i, 1, 1)                                                         \
        } else if (BK) {                                                                           \
            for (i = 0; i + W <= ne; i += W)                                                       \
                RJ__ELEM_STEP(VD, i, 0, 1)                                                         \
        } else if (en) {                                                                           \
            RJ__LANES_OVER(i, ne, W, RJ__ELEM_STEP(VD, i, 1, 0))                                   \
        } else {                                                                                   \
            RJ__LANES_OVER(i, ne, W, RJ__ELEM_STEP(VD, i, 0, 0))                                   \
        }                                                                                          \
        (void) bk;                                                                                 \
        for (k = 0; k < W; k++)                                                                    \
            if (!okv[k])                                                                           \
                return -1;                                                                         \
        return BK ? i : ne;                                                                        \
    }
#ifdef RJ__LANES2
RJ__ELEM_LANES(2, rj__vd2, rj__vl2, )
#endif
#ifdef RJ__LANES4
RJ__ELEM_LANES(4, rj__vd4, rj__vl4, RJ__AVX2)
#endif
#endif

/* The fast path over a chunk of one link's elements, branch-free (vector lanes where the
   compiler has them, then this scalar loop from element i on): one division per element,
   atan(r) of the small per-step chord turn r by its series r - r^3/3 + r^5/5 (error
   < r^7/7 < 2e-20 for |r| < 2e-3; a chord turns about omega dt, 1e-5 in the deployment).
   Returns -1 when some chord turned more than that, or turned back, and the exact path
   must redo the chunk, else ne. F: row FX of the chunk buffer at the chunk's first element.
   bk (in place, where bo, cox, coy are bb, ccx, ccy; else NULL): each element's old values
   go there first, rows of RJ__CHUNK as in RJ__ELEM_STEP. */
static int rj__elem_scalar(int i, int ne, const double *kc, const double *xa, const double *ya,
                           const double *pa, const double *bb, const double *ccx, const double *ccy,
                           double *F, double *ue, double *bo, double *cox, double *coy, double *bk)
{
    const double kb = kc[0], kax = kc[1], l0sq = kc[2], half_inv_l0sq = kc[3];
    long long bad = 0;
    for (; i < ne; i++) {
        const double ex = xa[i + 1] - xa[i], ey = ya[i + 1] - ya[i];
        if (bk) {
            bk[i] = bb[i];
            bk[RJ__CHUNK + i] = ccx[i];
            bk[2 * RJ__CHUNK + i] = ccy[i];
        } /* in place */
        RJ__ELEM_CORE(double, ex, ey, ccx[i], ccy[i], bb[i], pa[i], pa[i + 1]);
        bad |=
            (long long) !(r2_ < 4e-6) | (long long) !(dp_ > 0.0); /* bitwise: no branch; NaN too */
        bo[i] = bt_;
        cox[i] = ex;
        coy[i] = ey;
        F[i] = fx_;
        F[RJ__FROW + i] = fy_;
        F[2 * RJ__FROW + i] = ma_;
        F[3 * RJ__FROW + i] = mb_;
        ue[i] = u_;
    }
    return bad != 0 ? -1 : ne;
}

/* Sum in eight fixed partial sums: deterministic, and it vectorises where the target can. */
static double rj__sum8(const double *RJ__RESTRICT a, int n)
{
    int i = 0;
#ifdef RJ__LANES
    /* the same eight sums in vector lanes */
    rj__vd2 v0 = { 0.0, 0.0 }, v1 = v0, v2 = v0, v3 = v0, t;
    for (; i + 7 < n; i += 8) {
        RJ__VLD(t, a + i);
        v0 += t;
        RJ__VLD(t, a + i + 2);
        v1 += t;
        RJ__VLD(t, a + i + 4);
        v2 += t;
        RJ__VLD(t, a + i + 6);
        v3 += t;
    }
    if (i < n) { /* the rest into the first sum, in order */
        double p0 = v0[0];
        for (; i < n; i++)
            p0 += a[i];
        v0[0] = p0;
    }
    return ((v0[0] + v0[1]) + (v1[0] + v1[1])) + ((v2[0] + v2[1]) + (v3[0] + v3[1]));
#else
    double p[8] = { 0, 0, 0, 0, 0, 0, 0, 0 };
    int k;
    for (; i + 7 < n; i += 8)
        for (k = 0; k < 8; k++)
            p[k] += a[i + k];
    for (; i < n; i++)
        p[0] += a[i];
    return ((p[0] + p[1]) + (p[2] + p[3])) + ((p[4] + p[5]) + (p[6] + p[7]));
#endif
}


/* What the step's fused pass needs to advance nodes as soon as their forces are summed:
   v^{n+1/2} = v^{n-1/2} + kick f / m and x^{n+1} = x^n + dt v^{n+1/2}, and each node's share
   of twice the kinetic energy at n, v^{n-1/2}.v^{n+1/2} m. */
typedef struct rj__adv {
    double kick, dt;
    const double *vx, *vy, *w, *ti, *ri, *km, *kj;
    double *nx, *ny, *nphi, *nvx, *nvy, *nw, *kn;
    double *fx, *fy, *mz; /* node forces, for the nodes advanced again (rj_model.dnode) */
    int en;               /* this step takes the energy accounts (solver.energy_every) */
    int ip;               /* in place: the pass writes the nodes and elements where it reads them */
    int grav;             /* gravity: every moving node's force gains its kinetic mass times g */
    double gx, gy;        /* m/s^2, the acceleration of gravity */
    double *fin; /* the sum of every advanced node's x + y + phi: finite while they all are */
} rj__adv;

/* One node's update with its final forces (the lanes below do the same operations in the
   same order). */
static RJ__INLINE void rj__advance_node(const rj__adv *a, int i, double fx, double fy, double mz,
                                        const double *x, const double *y, const double *phi)
{
    const double ux = a->vx[i] + a->kick * fx * a->ti[i], uy = a->vy[i] + a->kick * fy * a->ti[i];
    const double uw = a->w[i] + a->kick * mz * a->ri[i];
    a->kn[i] = a->km[i] * (a->vx[i] * ux + a->vy[i] * uy) + a->kj[i] * a->w[i] * uw;
    a->nvx[i] = ux;
    a->nvy[i] = uy;
    a->nw[i] = uw;
    a->nx[i] = x[i] + a->dt * ux;
    a->ny[i] = y[i] + a->dt * uy;
    a->nphi[i] = phi[i] + a->dt * uw;
    /* finite positions at n + 1 from finite ones at n mean finite velocities too */
    *a->fin += (a->nx[i] + a->ny[i]) + a->nphi[i];
}

#ifdef RJ__LANES
/* W nodes from node k on (chunk-relative), in lanes; UNI: the link's uniform node values in
   tiv .. kjv, else each node's own; ST: their forces are stored too; EN: their shares of
   the kinetic energy. */
#define RJ__NODE_STEP(VD, k, UNI, ST, EN, GR)                                                      \
    {                                                                                              \
        VD f0, f1, g0, g1, m1, m2, fxv, fyv, mzv, vxv, vyv, wv, t, tiv = tiu, riv = riu,           \
                                                                   kmv = kmu, kjv = kju;           \
        if (!UNI) {                                                                                \
            RJ__VLD(tiv, ti + k);                                                                  \
            RJ__VLD(riv, ri + k);                                                                  \
            RJ__VLD(kmv, km + k);                                                                  \
            RJ__VLD(kjv, kj + k);                                                                  \
        }                                                                                          \
        RJ__VLD(f0, F + k);                                                                        \
        RJ__VLD(f1, F + k + 1);                                                                    \
        RJ__VLD(g0, F + RJ__FROW + k);                                                             \
        RJ__VLD(g1, F + RJ__FROW + k + 1);                                                         \
        RJ__VLD(m2, F + 3 * RJ__FROW + k);                                                         \
        RJ__VLD(m1, F + 2 * RJ__FROW + k + 1);                                                     \
        fxv = f0 - f1;                                                                             \
        fyv = g0 - g1;                                                                             \
        mzv = -m2 - m1;                                                                            \
        if (ST && !GR) {                                                                           \
            RJ__VST(fx + k, fxv);                                                                  \
            RJ__VST(fy + k, fyv);                                                                  \
            RJ__VST(mz + k, mzv);                                                                  \
        }                                                                                          \
        if (ST &&                                                                                  \
            GR) { /* each node's own m g in the forces kept for the nodes advanced           \
                           again (the uniform values below are not theirs) */     \
            VD kmn, gfx, gfy;                                                                      \
            RJ__VLD(kmn, km + k);                                                                  \
            gfx = fxv + kmn * gxv;                                                                 \
            gfy = fyv + kmn * gyv;                                                                 \
            RJ__VST(fx + k, gfx);                                                                  \
            RJ__VST(fy + k, gfy);                                                                  \
            RJ__VST(mz + k, mzv);                                                                  \
        }                                                                                          \
        if (GR) { /* gravity, m g, on nodes that move on their own (kmass 0 else) */               \
            fxv = fxv + kmv * gxv;                                                                 \
            fyv = fyv + kmv * gyv;                                                                 \
        }                                                                                          \
        RJ__VLD(vxv, vx + k);                                                                      \
        RJ__VLD(vyv, vy + k);                                                                      \
        RJ__VLD(wv, w + k);                                                                        \
        {                                                                                          \
            const VD ux_ = vxv + kick * fxv * tiv, uy_ = vyv + kick * fyv * tiv,                   \
                     uw_ = wv + kick * mzv * riv;                                                  \
            const VD kn_ = kmv * (vxv * ux_ + vyv * uy_) + kjv * wv * uw_;                         \
            RJ__VST(nvx + k, ux_);                                                                 \
            RJ__VST(nvy + k, uy_);                                                                 \
            RJ__VST(nw + k, uw_);                                                                  \
            if (EN)                                                                                \
                RJ__VST(kn + k, kn_);                                                              \
            RJ__VLD(t, x + k);                                                                     \
            t = t + dt * ux_;                                                                      \
            RJ__VST(nx + k, t);                                                                    \
            fin = fin + t;                                                                         \
            RJ__VLD(t, y + k);                                                                     \
            t = t + dt * uy_;                                                                      \
            RJ__VST(ny + k, t);                                                                    \
            fin = fin + t;                                                                         \
            RJ__VLD(t, phi + k);                                                                   \
            t = t + dt * uw_;                                                                      \
            RJ__VST(nphi + k, t);                                                                  \
            fin = fin + t;                                                                         \
        }                                                                                          \
    }
/* The node pass in lanes of W doubles over all cnt >= W nodes (RJ__LANES_OVER), their
   forces stored too if store is set and their kinetic-energy shares if en is; returns cnt. */
#define RJ__NODE_LANES(W, VD, ATTR, NAME, GR)                                                      \
    ATTR static RJ__FORCE_INLINE int NAME(int cnt, int n, const double *un, const rj__adv *a,      \
                                          const double *RJ__RESTRICT F, const double *x_,          \
                                          const double *y_, const double *phi_, int store, int en) \
    {                                                                                              \
        double *RJ__RESTRICT fx = a->fx + n, *RJ__RESTRICT fy = a->fy + n,                         \
                             *RJ__RESTRICT mz = a->mz + n;                                         \
        const double kick = a->kick, dt = a->dt;                                                   \
        const double *x = x_ + n, *y = y_ + n,                                                     \
                     *phi = phi_ + n; /* these six alias the next six in place */                  \
        const double *vx = a->vx + n, *vy = a->vy + n, *w = a->w + n;                              \
        const double *RJ__RESTRICT ti = a->ti + n, *RJ__RESTRICT ri = a->ri + n;                   \
        const double *RJ__RESTRICT km = a->km + n, *RJ__RESTRICT kj = a->kj + n;                   \
        double *nx = a->nx + n, *ny = a->ny + n, *nphi = a->nphi + n;                              \
        double *nvx = a->nvx + n, *nvy = a->nvy + n, *nw = a->nw + n;                              \
        double *RJ__RESTRICT kn = a->kn + n;                                                       \
        VD tiu = { 0 }, riu = { 0 }, kmu = { 0 }, kju = { 0 }, gxv = { 0 }, gyv = { 0 },           \
           fin = { 0 };                                                                            \
        double fin_sum = 0;                                                                        \
        int k;                                                                                     \
        for (k = 0; k < W; k++) {                                                                  \
            tiu[k] = un[0];                                                                        \
            riu[k] = un[1];                                                                        \
            kmu[k] = un[2];                                                                        \
            kju[k] = un[3];                                                                        \
        }                                                                                          \
        if (GR)                                                                                    \
            for (k = 0; k < W; k++) {                                                              \
                gxv[k] = a->gx;                                                                    \
                gyv[k] = a->gy;                                                                    \
            }                                                                                      \
        switch ((un[4] != 0 ? 4 : 0) + (store ? 2 : 0) + (en ? 1 : 0)) {                           \
        case 4:                                                                                    \
            RJ__LANES_OVER(k, cnt, W, RJ__NODE_STEP(VD, k, 1, 0, 0, GR)) break;                    \
        case 5:                                                                                    \
            RJ__LANES_OVER(k, cnt, W, RJ__NODE_STEP(VD, k, 1, 0, 1, GR)) break;                    \
        case 6:                                                                                    \
            RJ__LANES_OVER(k, cnt, W, RJ__NODE_STEP(VD, k, 1, 1, 0, GR)) break;                    \
        case 7:                                                                                    \
            RJ__LANES_OVER(k, cnt, W, RJ__NODE_STEP(VD, k, 1, 1, 1, GR)) break;                    \
        default: /* per-node values: rare; forces and energy shares always stored */               \
            RJ__LANES_OVER(k, cnt, W, RJ__NODE_STEP(VD, k, 0, 1, 1, GR))                           \
        }                                                                                          \
        /* the new positions' sum: NaN or infinite when one of them is */                          \
        for (k = 0; k < W; k++)                                                                    \
            fin_sum += fin[k];                                                                     \
        *a->fin += fin_sum;                                                                        \
        return cnt;                                                                                \
    }
/* each width twice: without gravity (the code scenes ran before gravity existed) and
   with it (m g added to the forces of the nodes the pass advances) */
#ifdef RJ__LANES2
RJ__NODE_LANES(2, rj__vd2, , rj__node_lanes2, 0)
RJ__NODE_LANES(2, rj__vd2, , rj__node_lanes2g, 1)
#endif
#ifdef RJ__LANES4
RJ__NODE_LANES(4, rj__vd4, RJ__AVX2, rj__node_lanes4, 0)
RJ__NODE_LANES(4, rj__vd4, RJ__AVX2, rj__node_lanes4g, 1)
#endif
#endif

/* Nodes n + k .. n + cnt - 1 from the chunk buffer F (rows FX, FY, M1, M2) laid out so
   that node k takes FX[k] - FX[k+1] (its element on the left, -0.0 before a link's first,
   minus the one on the right, +0.0 after its last: the same bits as -FX[0] and FX[last])
   and mz = -M2[k] - M1[k+1]: the forces (into fx, fy, mz), and with a (not NULL) the
   advanced velocities, positions and kinetic-energy shares (the lanes did nodes 0 .. k - 1). */
static void rj__node_scalar(int k, int cnt, int n, const double *F, double *fx, double *fy,
                            double *mz, const double *x, const double *y, const double *phi,
                            const rj__adv *a)
{
    const double *FX = F, *FY = F + RJ__FROW, *M1 = F + 2 * RJ__FROW, *M2 = F + 3 * RJ__FROW;
    if (!a) {
        for (; k < cnt; k++) {
            fx[n + k] = FX[k] - FX[k + 1];
            fy[n + k] = FY[k] - FY[k + 1];
            mz[n + k] = -M2[k] - M1[k + 1];
        }
        return;
    }
    for (; k < cnt; k++) {
        double fxv = FX[k] - FX[k + 1], fyv = FY[k] - FY[k + 1];
        const double mzv = -M2[k] - M1[k + 1];
        if (a->grav) { /* as the lanes: m g on every node that moves on its own */
            fxv = fxv + a->km[n + k] * a->gx;
            fyv = fyv + a->km[n + k] * a->gy;
        }
        fx[n + k] = fxv;
        fy[n + k] = fyv;
        mz[n + k] = mzv;
        rj__advance_node(a, n + k, fxv, fyv, mzv, x, y, phi);
    }
}

/* Internal forces at x: element forces summed into the nodes (fx, fy, mz: node b of element
   e gets +ef, node a gets -ef), chunk by chunk; the updated chord angles and this step's
   chords (the next step's references) go to beta_out, cx_out, cy_out; eu receives the
   elements' strain energies. With adv (the step), every node of a flexible link is also
   advanced as soon as its forces are summed; nodes that joints act on are advanced again
   later (m->dnode); with adv->en clear the lanes leave eu stale. The pass is compiled once
   per lane width W (ELEM, NODE: that width's lane loops) so that the kernels inline into it
   and the CPU is asked once per step; it returns whether eu is complete (rj__beam_pass then
   sums it into the strain energy). IP: compiled in place (the step's rj_model.ip), where
   beta_out .. cy_out are beta .. cy and the step's nodes are advanced where they are; RQ:
   restrict, except in place. It calls no other code on its way out: a function compiled for AVX2
   that jumps into SSE code without clearing the registers' upper halves (gcc 12 left out
   its vzeroupper before such a tail call) makes every later SSE instruction of the step
   pay for them (the paper's settings ran 1.3x slower). */
/* In place, element i's old chord angle (k 0) or chord (1, 2) while the chunk's elements
   run: kept in EB for the first nb elements (RJ__ELEM_STEP), else still at p[i]. */
#define RJ__OLD(p, k) (ip && i < nb ? EB[(k) *RJ__CHUNK + i] : (p)[i])
#define RJ__BEAM_PASS(NAME, ATTR, W, ELEM, NODE, NODEG, IP, RQ)                                                                                             \
    ATTR static int NAME(const rj_model *m, const double *x, const double *y, const double *phi,                                                            \
                         const double *beta, const double *cx, const double *cy, double *eu,                                                                \
                         double *beta_out, double *cx_out, double *cy_out, double *fx, double *fy,                                                          \
                         double *mz, const rj__adv *adv)                                                                                                    \
    {                                                                                                                                                       \
        /* chunk buffers: entry 0 is the previous chunk's last element (or the -0.0 / +0.0 before                                                         \
       a link's first), entries 1 .. nc this chunk's, nc + 1 the +0.0 after a link's last */ \
        double FB[4 * RJ__FROW];                                                                                                                            \
        double *FX = FB, *FY = FB + RJ__FROW, *M1 = FB + 2 * RJ__FROW, *M2 = FB + 3 * RJ__FROW;                                                             \
        /* in place: the old chord angles and chords of a chunk's elements (RJ__OLD) */                                                                     \
        double EB[3 * RJ__CHUNK];                                                                                                                           \
        const int en = !adv || adv->en,                                                                                                                     \
                  ip = IP; /* strain energies wanted; in place (compiled apart) */                                                                          \
        int l;                                                                                                                                              \
        for (l = 0; l < m->nl; l++) {                                                                                                                       \
            const int n0 = m->link_first[l], e0 = m->link_efirst[l],                                                                                        \
                      ne = m->link_efirst[l + 1] - e0;                                                                                                      \
            const double *kc = m->link_kc + 4 * (size_t) l;                                                                                                 \
            const double kb = kc[0], kax = kc[1], l0sq = kc[2], half_inv_l0sq = kc[3];                                                                      \
            int c0;                                                                                                                                         \
            if (m->ldef[l].fidelity == RJ_LINK_RIGID) {                                                                                                     \
                /* a rigid link: no elements; its nodes take only what joints apply (and are                                                              \
               advanced with the joints' nodes) */ \
                for (c0 = 0; c0 < ne; c0++) {                                                                                                               \
                    beta_out[e0 + c0] = beta[e0 + c0];                                                                                                      \
                    cx_out[e0 + c0] = cx[e0 + c0];                                                                                                          \
                    cy_out[e0 + c0] = cy[e0 + c0];                                                                                                          \
                    eu[e0 + c0] = 0;                                                                                                                        \
                }                                                                                                                                           \
                for (c0 = 0; c0 <= ne; c0++)                                                                                                                \
                    fx[n0 + c0] = fy[n0 + c0] = mz[n0 + c0] = 0;                                                                                            \
                continue;                                                                                                                                   \
            }                                                                                                                                               \
            FX[0] = FY[0] = -0.0;                                                                                                                           \
            M1[0] = M2[0] = 0.0;                                                                                                                            \
            for (c0 = 0; c0 < ne; c0 += RJ__CHUNK) {                                                                                                        \
                const int nc = ne - c0 < RJ__CHUNK ? ne - c0 : RJ__CHUNK, a = e0 + c0,                                                                      \
                          na = n0 + c0, last = c0 + nc == ne;                                                                                               \
                const double *RQ xa = x + na, *RQ ya = y + na,                                                                                              \
                                 *RQ pa = phi + na; /* RQ: restrict, but in place */                                                                        \
                const double *RQ bb = beta + a, *RQ ccx = cx + a, *RQ ccy = cy + a;                                                                         \
                double *RJ__RESTRICT ue = eu + a, *RQ bo = beta_out + a; /* in place: bb */                                                                 \
                int nb = 0; /* in place: elements whose old values are in EB */                                                                             \
                int i;                                                                                                                                      \
                i = W > 1 && nc >= W ? ELEM(nc, kc, xa, ya, pa, bb, ccx, ccy, FB + 1, ue, bo,                                                               \
                                            cx_out + a, cy_out + a, ip ? EB : NULL, en)                                                                     \
                                     : 0;                                                                                                                   \
                if (ip && W > 1 && nc >= W)                                                                                                                 \
                    nb = nc / W * W;                                                                                                                        \
                if (i >= 0 && i < nc) {                                                                                                                     \
                    i = rj__elem_scalar(i, nc, kc, xa, ya, pa, bb, ccx, ccy, FB + 1, ue, bo,                                                                \
                                        cx_out + a, cy_out + a, ip ? EB : NULL);                                                                            \
                    nb = ip ? nc : 0;                                                                                                                       \
                }                                                                                                                                           \
                if (i < 0) {                                                                                                                                \
                    /* a chord turned more than 0.02 rad in one step: exact angles for this chunk */                                                        \
                    for (i = 0; i < nc; i++) {                                                                                                              \
                        const double ex = xa[i + 1] - xa[i], ey = ya[i + 1] - ya[i];                                                                        \
                        const double ox = RJ__OLD(ccx, 1),                                                                                                  \
                                     oy = RJ__OLD(ccy, 2); /* nb is 0 unless in place */                                                                    \
                        const double bt =                                                                                                                   \
                            RJ__OLD(bb, 0) + atan2(ox * ey - oy * ex, ox * ex + oy * ey);                                                                   \
                        RJ__ELEM_FORCES(double, ex, ey, bt, 1.0 / (ex * ex + ey * ey), pa[i],                                                               \
                                        pa[i + 1]);                                                                                                         \
                        bo[i] = bt;                                                                                                                         \
                        if (ip) {                                                                                                                           \
                            cx_out[a + i] = ex;                                                                                                             \
                            cy_out[a + i] = ey;                                                                                                             \
                        } /* (the lanes may not have) */                                                                                                    \
                        FX[1 + i] = fx_;                                                                                                                    \
                        FY[1 + i] = fy_;                                                                                                                    \
                        M1[1 + i] = ma_;                                                                                                                    \
                        M2[1 + i] = mb_;                                                                                                                    \
                        ue[i] = u_;                                                                                                                         \
                    }                                                                                                                                       \
                }                                                                                                                                           \
                if (last) {                                                                                                                                 \
                    FX[nc + 1] = FY[nc + 1] = M1[nc + 1] = 0.0;                                                                                             \
                }                                                                                                                                           \
                /* the chunk's nodes whose elements are all summed: na .. na + nc - 1, and the                                                            \
               link's last node with the last chunk; their forces are stored in the chunks                                                            \
               that hold nodes the step advances again (m->dnode: a link's end nodes, and                                                             \
               inner ones only in scenes with dn_inner) */ \
                i = 0;                                                                                                                                      \
                if (adv && W > 1 && nc + last >= W) {                                                                                                       \
                    const int cnt_ = ip ? (nc + last) / W * W : nc + last;                                                                                  \
                    const int store_ = c0 == 0 || last || m->dn_inner;                                                                                      \
                    i = adv->grav                                                                                                                           \
                            ? NODEG(cnt_, na, m->link_un + 5 * l, adv, FB, x, y, phi, store_, en)                                                           \
                            : NODE(cnt_, na, m->link_un + 5 * l, adv, FB, x, y, phi, store_, en);                                                           \
                }                                                                                                                                           \
                if (i < nc + last)                                                                                                                          \
                    rj__node_scalar(i, nc + last, na, FB, fx, fy, mz, x, y, phi, adv);                                                                      \
                FX[0] = FX[nc];                                                                                                                             \
                FY[0] = FY[nc];                                                                                                                             \
                M1[0] = M1[nc];                                                                                                                             \
                M2[0] = M2[nc];                                                                                                                             \
            }                                                                                                                                               \
        }                                                                                                                                                   \
        return en;                                                                                                                                          \
    }

#ifdef RJ__LANES4
RJ__BEAM_PASS(rj__beam_pass4, RJ__AVX2, 4, rj__elem_lanes4, rj__node_lanes4, rj__node_lanes4g, 0,
              RJ__RESTRICT)
RJ__BEAM_PASS(rj__beam_pass4ip, RJ__AVX2, 4, rj__elem_lanes4ip, rj__node_lanes4, rj__node_lanes4g,
              1, )
#endif
#ifdef RJ__LANES2
RJ__BEAM_PASS(rj__beam_pass2, , 2, rj__elem_lanes2, rj__node_lanes2, rj__node_lanes2g, 0,
              RJ__RESTRICT)
RJ__BEAM_PASS(rj__beam_pass2ip, , 2, rj__elem_lanes2ip, rj__node_lanes2, rj__node_lanes2g, 1, )
#endif
#ifndef RJ__LANES
static int rj__elem_none(int ne, const double *kc, const double *xa, const double *ya,
                         const double *pa, const double *bb, const double *ccx, const double *ccy,
                         double *F, double *ue, double *bo, double *cox, double *coy, double *bk,
                         int en)
{
    (void) kc;
    (void) xa;
    (void) ya;
    (void) pa;
    (void) bb;
    (void) ccx;
    (void) ccy;
    (void) F;
    (void) ue;
    (void) bo;
    (void) cox;
    (void) coy;
    (void) bk;
    (void) en;
    return ne * 0;
}
static int rj__node_none(int cnt, int n, const double *un, const rj__adv *a, const double *F,
                         const double *x, const double *y, const double *phi, int store, int en)
{
    (void) n;
    (void) un;
    (void) a;
    (void) F;
    (void) x;
    (void) y;
    (void) phi;
    (void) store;
    (void) en;
    return cnt * 0;
}
RJ__BEAM_PASS(rj__beam_pass1, , 1, rj__elem_none, rj__node_none, rj__node_none, 0, RJ__RESTRICT)
RJ__BEAM_PASS(rj__beam_pass1ip, , 1, rj__elem_none, rj__node_none, rj__node_none, 1, )
#endif

/* Internal forces at x (see RJ__BEAM_PASS), in the widest lanes the CPU has. */
static RJ__FORCE_INLINE double rj__beam_pass(const rj_model *m, const double *x, const double *y,
                                             const double *phi, const double *beta,
                                             const double *cx, const double *cy, double *eu,
                                             double *beta_out, double *cx_out, double *cy_out,
                                             double *fx, double *fy, double *mz, const rj__adv *adv)
{
    int en;
    const int ip = adv && adv->ip;
#if defined(RJ__DISPATCH)
    if (__builtin_cpu_supports("avx2"))
        en = (ip ? rj__beam_pass4ip : rj__beam_pass4)(m, x, y, phi, beta, cx, cy, eu, beta_out,
                                                      cx_out, cy_out, fx, fy, mz, adv);
    else
        en = (ip ? rj__beam_pass2ip : rj__beam_pass2)(m, x, y, phi, beta, cx, cy, eu, beta_out,
                                                      cx_out, cy_out, fx, fy, mz, adv);
#elif defined(RJ__LANES4)
    en = (ip ? rj__beam_pass4ip : rj__beam_pass4)(m, x, y, phi, beta, cx, cy, eu, beta_out, cx_out,
                                                  cy_out, fx, fy, mz, adv);
#elif defined(RJ__LANES2)
    en = (ip ? rj__beam_pass2ip : rj__beam_pass2)(m, x, y, phi, beta, cx, cy, eu, beta_out, cx_out,
                                                  cy_out, fx, fy, mz, adv);
#else
    en = (ip ? rj__beam_pass1ip : rj__beam_pass1)(m, x, y, phi, beta, cx, cy, eu, beta_out, cx_out,
                                                  cy_out, fx, fy, mz, adv);
#endif
    return en ? rj__sum8(eu, m->ne) : 0.0;
}

