/* ------------------------------------------------------------------ beam forces */
/* Co-rotational planar Euler-Bernoulli element (Crisfield): chord e = x_b - x_a, axial
   Green strain eps = (|e|^2 - l0^2) / (2 l0^2), chord angle beta tracked incrementally
   from a reference chord (no atan2 per element), local rotations th_a = phi_a - beta,
   th_b = phi_b - beta, end moments M_a = EI/l0 (4 th_a + 2 th_b), M_b = EI/l0 (2 th_a + 4 th_b).
   Forces: node b gets -EA/l0 eps e + (M_a + M_b) perp(e) / |e|^2, node a the opposite;
   moments -M_a, -M_b. The arithmetic is written twice, side by side below: on scalars
   (rj__elem_fast, rj__elem_forces) and on vector lanes (rj__elem_lane_step).

   The beam pass's kernels are plain functions, forced inline, whose variants (energy, in
   place, gravity, stored forces, uniform node values) are int arguments that every caller
   passes as a literal constant: each inlined copy keeps only its own variant's code. The
   pass's views of the arrays (rj__elems, rj__nodes) are locals of the pass whose address
   goes to inlined functions only, so that their fields stay in registers: the kernels'
   vector stores (memcpy) could alias anything that other code can reach. */

/* Rows of a chunk's element-result buffer (one base pointer for the kernels): FX, FY,
   M1, M2, each RJ__FROW long; see rj__beam_chunk for what the entries hold. */
#define RJ__CHUNK 128
#define RJ__FROW  (RJ__CHUNK + 2)

/* The element kernels' view of a chunk of one link's elements: every array at the chunk's
   first element, node arrays at its first node (element i joins nodes i and i + 1; its
   results go to entry i of the chunk buffer's rows), and the link's constants. */
typedef struct rj__elems {
    const double *x, *y, *phi;          /* nodes at n */
    const double *beta, *cx, *cy;       /* chord angles and reference chords at n */
    double *eu;                         /* strain energies */
    double *beta_out, *cx_out, *cy_out; /* the new chord angles and chords (in place: beta ..) */
    double *F;                          /* row FX of the chunk buffer, at the chunk's first */
    double *bk; /* in place: the chunk's old chord angles and chords, rows of RJ__CHUNK */
    double kb, kax, l0sq, half_inv_l0sq; /* the link's EI/l0, EA/l0, l0^2, 1/(2 l0^2) */
} rj__elems;

/* One element's results, in scalars: node b's force, the end moments, strain energy. */
typedef struct rj__elem_force {
    double fx, fy, ma, mb, u;
} rj__elem_force;

/* The element from its chord (ex, ey), chord angle bt, 1/|e|^2 and its nodes' rotations:
   end rotations and moments, axial force, node b's force, strain energy. The fast path
   (rj__elem_fast) and the exact one (rj__elem_exact) share it; rj__elem_lane_step repeats
   it on vector lanes, operation for operation. */
static RJ__FORCE_INLINE void rj__elem_forces(const rj__elems *c, double ex, double ey, double bt,
                                             double inv_l2, double phi_a, double phi_b,
                                             rj__elem_force *f)
{
    const double tha = phi_a - bt;
    const double thb = phi_b - bt;
    const double ma = c->kb * (4.0 * tha + 2.0 * thb);
    const double mb = c->kb * (2.0 * tha + 4.0 * thb);
    const double eps = (ex * ex + ey * ey - c->l0sq) * c->half_inv_l0sq;
    const double nax = c->kax * eps;
    const double s = (ma + mb) * inv_l2;
    f->fx = -nax * ex - s * ey;
    f->fy = -nax * ey + s * ex;
    f->ma = ma;
    f->mb = mb;
    f->u = 0.5 * (ma * tha + mb * thb) + 0.5 * c->kax * c->l0sq * eps * eps;
}

/* The chunk's element i: its results into the chunk buffer's rows and the arrays. */
static RJ__FORCE_INLINE void rj__elem_store(const rj__elems *c, int i, double bt, double ex,
                                            double ey, const rj__elem_force *f)
{
    c->beta_out[i] = bt;
    c->cx_out[i] = ex;
    c->cy_out[i] = ey;
    c->F[i] = f->fx;
    c->F[RJ__FROW + i] = f->fy;
    c->F[2 * RJ__FROW + i] = f->ma;
    c->F[3 * RJ__FROW + i] = f->mb;
    c->eu[i] = f->u;
}

/* The chunk's element i on the fast path, in scalars: the chord's turn r against the
   reference chord from one division, the new chord angle by the series of atan(r), then
   rj__elem_forces. bk: in place, its old chord angle and chord kept in c->bk first (the
   exact path may need them after its new ones overwrote them). Returns nonzero where the
   chord turned too far or back, or a value is NaN (bitwise: no branch). */
static RJ__FORCE_INLINE long long rj__elem_fast(const rj__elems *c, int i, int bk)
{
    const double ex = c->x[i + 1] - c->x[i];
    const double ey = c->y[i + 1] - c->y[i];
    const double cross = c->cx[i] * ey - c->cy[i] * ex;
    const double dot = c->cx[i] * ex + c->cy[i] * ey;
    const double l2 = ex * ex + ey * ey;
    const double inv = 1.0 / (dot * l2);
    const double r = cross * l2 * inv;
    const double inv_l2 = dot * inv;
    const double r2 = r * r;
    const double bt = c->beta[i] + r * (1.0 - r2 * (1.0 / 3.0 - r2 * (1.0 / 5.0)));
    rj__elem_force f;
    if (bk) {
        c->bk[i] = c->beta[i];
        c->bk[RJ__CHUNK + i] = c->cx[i];
        c->bk[2 * RJ__CHUNK + i] = c->cy[i];
    }
    rj__elem_forces(c, ex, ey, bt, inv_l2, c->phi[i], c->phi[i + 1], &f);
    rj__elem_store(c, i, bt, ex, ey, &f);
    return (long long) !(r2 < 4e-6) | (long long) !(dot > 0.0);
}

#ifdef RJ__LANES
/* d in every lane of *v */
static RJ__FORCE_INLINE void rj__splat(rj__vd *v, double d)
{
    rj__vd lanes = { 0 };
    int k;
    for (k = 0; k < RJ__VW; k++)
        lanes[k] = d;
    *v = lanes;
}

/* The chunk's elements i .. i + RJ__VW - 1 on the fast path, in vector lanes: rj__elem_fast
   and rj__elem_forces, the same operations in the same order (keep the three alike:
   tests/lanes.sh compares the bits with the scalar build's). en: their strain energies too
   (without, the compiler drops that arithmetic); bk: in place, their old values kept
   first. A lane of ok is cleared where its chord turned too far or back (or NaN). */
static RJ__FORCE_INLINE void rj__elem_lane_step(const rj__elems *c, int i, int en, int bk,
                                                rj__vl *ok)
{
    rj__vd lim, zero, xa, xb, ya, yb, phia, phib, b, ox, oy;
    rj__splat(&lim, 4e-6);
    rj__splat(&zero, 0.0);
    RJ__VLD(xa, c->x + i);
    RJ__VLD(xb, c->x + i + 1);
    RJ__VLD(ya, c->y + i);
    RJ__VLD(yb, c->y + i + 1);
    RJ__VLD(phia, c->phi + i);
    RJ__VLD(phib, c->phi + i + 1);
    RJ__VLD(b, c->beta + i);
    RJ__VLD(ox, c->cx + i);
    RJ__VLD(oy, c->cy + i);
    if (bk) {
        RJ__VST(c->bk + i, b);
        RJ__VST(c->bk + RJ__CHUNK + i, ox);
        RJ__VST(c->bk + 2 * RJ__CHUNK + i, oy);
    }
    {
        /* rj__elem_fast's turn and chord angle */
        const rj__vd ex = xb - xa;
        const rj__vd ey = yb - ya;
        const rj__vd cross = ox * ey - oy * ex;
        const rj__vd dot = ox * ex + oy * ey;
        const rj__vd l2 = ex * ex + ey * ey;
        const rj__vd inv = 1.0 / (dot * l2);
        const rj__vd r = cross * l2 * inv;
        const rj__vd inv_l2 = dot * inv;
        const rj__vd r2 = r * r;
        const rj__vd bt = b + r * (1.0 - r2 * (1.0 / 3.0 - r2 * (1.0 / 5.0)));
        /* rj__elem_forces */
        const rj__vd tha = phia - bt;
        const rj__vd thb = phib - bt;
        const rj__vd ma = c->kb * (4.0 * tha + 2.0 * thb);
        const rj__vd mb = c->kb * (2.0 * tha + 4.0 * thb);
        const rj__vd eps = (ex * ex + ey * ey - c->l0sq) * c->half_inv_l0sq;
        const rj__vd nax = c->kax * eps;
        const rj__vd s = (ma + mb) * inv_l2;
        const rj__vd fx = -nax * ex - s * ey;
        const rj__vd fy = -nax * ey + s * ex;
        const rj__vd u = 0.5 * (ma * tha + mb * thb) + 0.5 * c->kax * c->l0sq * eps * eps;
        *ok &= (r2 < lim) & (dot > zero);
        /* rj__elem_store */
        RJ__VST(c->beta_out + i, bt);
        RJ__VST(c->cx_out + i, ex);
        RJ__VST(c->cy_out + i, ey);
        RJ__VST(c->F + i, fx);
        RJ__VST(c->F + RJ__FROW + i, fy);
        RJ__VST(c->F + 2 * RJ__FROW + i, ma);
        RJ__VST(c->F + 3 * RJ__FROW + i, mb);
        if (en)
            RJ__VST(c->eu + i, u);
    }
}

/* The lane steps over the chunk's elements 0 .. ne - 1 (ne >= RJ__VW) in steps of RJ__VW.
   Double-buffered, where RJ__VW does not divide ne the last RJ__VW again: the same inputs
   give the same bits. In place (bk) that would read values already overwritten, so whole
   lanes only, and the scalar loop does the rest. Returns how many elements it did. */
static RJ__FORCE_INLINE int rj__elem_lane_loop(const rj__elems *c, int ne, int en, int bk,
                                               rj__vl *ok)
{
    int i;
    for (i = 0; i + RJ__VW <= ne; i += RJ__VW)
        rj__elem_lane_step(c, i, en, bk, ok);
    if (bk)
        return i;
    if (i < ne)
        rj__elem_lane_step(c, ne - RJ__VW, en, bk, ok);
    return ne;
}

/* The element loop in vector lanes over the chunk's ne >= RJ__VW elements, their strain
   energies if en is set (a constant for the loop, chosen here once per chunk). Returns -1
   when some chord turned too far (or a result is NaN), else how many elements it did. */
static RJ__FORCE_INLINE int rj__elem_lanes(const rj__elems *c, int ne, int en, int bk)
{
    rj__vd zero;
    rj__vl ok;
    long long all = -1;
    int done, k;
    rj__splat(&zero, 0.0);
    ok = zero == zero; /* every lane set */
    if (en)
        done = rj__elem_lane_loop(c, ne, 1, bk, &ok);
    else
        done = rj__elem_lane_loop(c, ne, 0, bk, &ok);
    /* one test for all lanes, branch-free */
    for (k = 0; k < RJ__VW; k++)
        all &= ok[k];
    return all ? done : -1;
}
#endif

/* The fast path over the chunk's elements i .. ne - 1 in scalars (after the vector lanes,
   or all of them), branch-free: one division per element, atan(r) of the small per-step
   chord turn r by its series r - r^3/3 + r^5/5 (error < r^7/7 < 2e-20 for |r| < 2e-3; a
   chord turns about omega dt, 1e-5 in the deployment). Returns -1 when some chord turned
   more than that, or turned back, and the exact path must redo the chunk, else ne. */
static RJ__FORCE_INLINE int rj__elem_scalar(const rj__elems *c, int i, int ne, int bk)
{
    long long bad = 0;
    for (; i < ne; i++)
        bad |= rj__elem_fast(c, i, bk);
    return bad != 0 ? -1 : ne;
}

/* The exact path over the chunk's nc elements, for a chunk where some chord turned more
   than 0.02 rad in one step: each chord angle by atan2 from its old one. In place the
   first nb elements' old chord angles and chords are in c->bk (the fast path overwrote
   them), the rest's still where they were. Its chords are stored again: in place the
   lanes may not have, double-buffered they hold these bits already. */
static RJ__NOINLINE void rj__elem_exact(rj__elems view, int nc, int nb, int ip)
{
    const rj__elems *c = &view;
    int i;
    for (i = 0; i < nc; i++) {
        const int kept = ip && i < nb;
        const double ex = c->x[i + 1] - c->x[i];
        const double ey = c->y[i + 1] - c->y[i];
        const double ox = kept ? c->bk[RJ__CHUNK + i] : c->cx[i];
        const double oy = kept ? c->bk[2 * RJ__CHUNK + i] : c->cy[i];
        const double b = kept ? c->bk[i] : c->beta[i];
        const double bt = b + atan2(ox * ey - oy * ex, ox * ex + oy * ey);
        const double inv_l2 = 1.0 / (ex * ex + ey * ey);
        rj__elem_force f;
        rj__elem_forces(c, ex, ey, bt, inv_l2, c->phi[i], c->phi[i + 1], &f);
        rj__elem_store(c, i, bt, ex, ey, &f);
    }
}

/* A chunk's nc elements: vector lanes (lanes_on set, chunks of at least RJ__VW), the scalar loop
   after them, and the exact path for the whole chunk where some chord turned too far. */
static RJ__FORCE_INLINE void rj__chunk_elements(const rj__elems *c, int nc, int en, int ip,
                                                int lanes_on)
{
    int done = 0; /* elements the fast path did, or -1 */
    int nb = 0;   /* in place: elements whose old values are in c->bk */
#ifdef RJ__LANES
    if (lanes_on && nc >= RJ__VW) {
        done = rj__elem_lanes(c, nc, en, ip);
        nb = ip ? nc / RJ__VW * RJ__VW : 0;
    }
#else
    (void) en; /* the scalar loop stores every element's energy */
    (void) lanes_on;
#endif
    if (done >= 0 && done < nc) {
        done = rj__elem_scalar(c, done, nc, ip);
        nb = ip ? nc : 0;
    }
    if (done < 0)
        rj__elem_exact(*c, nc, nb, ip);
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
    double *damp; /* the material path's sums: damping forces, power, plastic work
                     (rj_state.damp) */
} rj__adv;

/* One node's update with its final forces (rj__node_lane_advance does the same operations
   in the same order). */
static RJ__INLINE void rj__advance_node(const rj__adv *a, int i, double fx, double fy, double mz,
                                        const double *x, const double *y, const double *phi)
{
    const double ux = a->vx[i] + a->kick * fx * a->ti[i];
    const double uy = a->vy[i] + a->kick * fy * a->ti[i];
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
/* The node lanes' view of a chunk's nodes: the step's arrays (rj__adv) and the positions at
   n, every one at the chunk's first node, and the chunk buffer (node k takes entries k and
   k + 1 of its rows). */
typedef struct rj__nodes {
    const double *F;                 /* the chunk buffer: rows FX, FY, M1, M2 */
    const double *x, *y, *phi;       /* positions at n (in place: the arrays nx .. nphi) */
    const double *vx, *vy, *w;       /* velocities at n - 1/2 (in place: nvx .. nw) */
    const double *ti, *ri, *km, *kj; /* each node's 1/m, 1/J, kinetic masses */
    double *fx, *fy, *mz;            /* forces kept for the nodes the step advances again */
    double *nx, *ny, *nphi, *nvx, *nvy, *nw, *kn;
    double *fin; /* the sum of the advanced nodes' x + y + phi (rj__adv) */
    double kick, dt, gx, gy;
} rj__nodes;

/* The chunk's nodes k .. k + RJ__VW - 1: their forces from the chunk buffer into f (fx,
   fy, mz) as rj__node_scalar sums them; st: stored too, gr: with each node's own m g (the
   link's uniform masses are not its end nodes', which the step advances again with these
   forces). */
static RJ__FORCE_INLINE void rj__node_lane_forces(const rj__nodes *v, int k, int st, int gr,
                                                  rj__vd *f)
{
    rj__vd fa, fb, ga, gb, m1, m2, km, gfx, gfy;
    RJ__VLD(fa, v->F + k);
    RJ__VLD(fb, v->F + k + 1);
    RJ__VLD(ga, v->F + RJ__FROW + k);
    RJ__VLD(gb, v->F + RJ__FROW + k + 1);
    RJ__VLD(m2, v->F + 3 * RJ__FROW + k);
    RJ__VLD(m1, v->F + 2 * RJ__FROW + k + 1);
    f[0] = fa - fb;
    f[1] = ga - gb;
    f[2] = -m2 - m1;
    if (st && !gr) {
        RJ__VST(v->fx + k, f[0]);
        RJ__VST(v->fy + k, f[1]);
        RJ__VST(v->mz + k, f[2]);
    }
    if (st && gr) {
        RJ__VLD(km, v->km + k);
        gfx = f[0] + km * v->gx;
        gfy = f[1] + km * v->gy;
        RJ__VST(v->fx + k, gfx);
        RJ__VST(v->fy + k, gfy);
        RJ__VST(v->mz + k, f[2]);
    }
}

/* The chunk's nodes k .. k + RJ__VW - 1 advanced with their final forces f and their
   ti, ri, km, kj in mass: rj__advance_node's operations in its order; en: their
   kinetic-energy shares too. fin sums their new positions, lane by lane. */
static RJ__FORCE_INLINE void rj__node_lane_advance(const rj__nodes *v, const rj__vd *mass,
                                                   const rj__vd *f, rj__vd *fin, int k, int en)
{
    rj__vd vx, vy, w, t;
    RJ__VLD(vx, v->vx + k);
    RJ__VLD(vy, v->vy + k);
    RJ__VLD(w, v->w + k);
    {
        const rj__vd ux = vx + v->kick * f[0] * mass[0];
        const rj__vd uy = vy + v->kick * f[1] * mass[0];
        const rj__vd uw = w + v->kick * f[2] * mass[1];
        const rj__vd kn = mass[2] * (vx * ux + vy * uy) + mass[3] * w * uw;
        RJ__VST(v->nvx + k, ux);
        RJ__VST(v->nvy + k, uy);
        RJ__VST(v->nw + k, uw);
        if (en)
            RJ__VST(v->kn + k, kn);
        RJ__VLD(t, v->x + k);
        t = t + v->dt * ux;
        RJ__VST(v->nx + k, t);
        *fin = *fin + t;
        RJ__VLD(t, v->y + k);
        t = t + v->dt * uy;
        RJ__VST(v->ny + k, t);
        *fin = *fin + t;
        RJ__VLD(t, v->phi + k);
        t = t + v->dt * uw;
        RJ__VST(v->nphi + k, t);
        *fin = *fin + t;
    }
}

/* The chunk's nodes k .. k + RJ__VW - 1 in vector lanes. uni: the link's uniform node
   values (link_mass: ti, ri, km, kj), else each node's own; st: their forces stored too;
   en: their kinetic-energy shares; gr: gravity's m g on their forces (km is 0 where a node
   does not move on its own). */
static RJ__FORCE_INLINE void rj__node_lane_step(const rj__nodes *v, int k, const rj__vd *link_mass,
                                                rj__vd *fin, int uni, int st, int en, int gr)
{
    rj__vd mass[4];
    rj__vd f[3];
    if (uni) {
        mass[0] = link_mass[0];
        mass[1] = link_mass[1];
        mass[2] = link_mass[2];
        mass[3] = link_mass[3];
    } else {
        RJ__VLD(mass[0], v->ti + k);
        RJ__VLD(mass[1], v->ri + k);
        RJ__VLD(mass[2], v->km + k);
        RJ__VLD(mass[3], v->kj + k);
    }
    rj__node_lane_forces(v, k, st, gr, f);
    if (gr) {
        f[0] = f[0] + mass[2] * v->gx;
        f[1] = f[1] + mass[2] * v->gy;
    }
    rj__node_lane_advance(v, mass, f, fin, k, en);
}

/* The lane steps over the chunk's nodes 0 .. cnt - 1 (cnt >= RJ__VW), the last RJ__VW again
   where RJ__VW does not divide cnt (in place the caller passes whole lanes only). */
static RJ__FORCE_INLINE void rj__node_lane_loop(const rj__nodes *v, int cnt,
                                                const rj__vd *link_mass, rj__vd *fin, int uni,
                                                int st, int en, int gr)
{
    int k;
    for (k = 0; k + RJ__VW <= cnt; k += RJ__VW)
        rj__node_lane_step(v, k, link_mass, fin, uni, st, en, gr);
    if (k < cnt)
        rj__node_lane_step(v, cnt - RJ__VW, link_mass, fin, uni, st, en, gr);
}

/* The node view of nodes n .. of the step's arrays a, with positions x, y, phi at n and
   the chunk buffer F. */
static RJ__FORCE_INLINE void rj__nodes_at(rj__nodes *v, const rj__adv *a, int n, const double *F,
                                          const double *x, const double *y, const double *phi)
{
    v->F = F;
    v->x = x + n;
    v->y = y + n;
    v->phi = phi + n;
    v->vx = a->vx + n;
    v->vy = a->vy + n;
    v->w = a->w + n;
    v->ti = a->ti + n;
    v->ri = a->ri + n;
    v->km = a->km + n;
    v->kj = a->kj + n;
    v->fx = a->fx + n;
    v->fy = a->fy + n;
    v->mz = a->mz + n;
    v->nx = a->nx + n;
    v->ny = a->ny + n;
    v->nphi = a->nphi + n;
    v->nvx = a->nvx + n;
    v->nvy = a->nvy + n;
    v->nw = a->nw + n;
    v->kn = a->kn + n;
    v->fin = a->fin;
    v->kick = a->kick;
    v->dt = a->dt;
    v->gx = a->gx;
    v->gy = a->gy;
}

/* The chunk's nodes n .. n + cnt - 1 (cnt >= RJ__VW) advanced in vector lanes with their
   forces from the chunk buffer F, their forces stored too if store is set and their
   kinetic-energy shares if en is. un: the link's uniform node values (ti, ri, km, kj, and
   1 when every inner node has them); gr: gravity (a constant: the pass's two calls). The
   run-time choices become constants here, once per chunk. */
static RJ__FORCE_INLINE void rj__node_lanes(const rj__adv *a, int n, int cnt, const double *un,
                                            const double *F, const double *x, const double *y,
                                            const double *phi, int store, int en, int gr)
{
    rj__nodes view;
    const rj__nodes *v = &view;
    rj__vd link_mass[4];
    rj__vd fin;
    double fin_sum = 0;
    int k;
    rj__nodes_at(&view, a, n, F, x, y, phi);
    rj__splat(&link_mass[0], un[0]);
    rj__splat(&link_mass[1], un[1]);
    rj__splat(&link_mass[2], un[2]);
    rj__splat(&link_mass[3], un[3]);
    rj__splat(&fin, 0.0);
    if (un[4] == 0) /* each node's own values: rare; forces and energy shares always stored */
        rj__node_lane_loop(v, cnt, link_mass, &fin, 0, 1, 1, gr);
    else if (store && en)
        rj__node_lane_loop(v, cnt, link_mass, &fin, 1, 1, 1, gr);
    else if (store)
        rj__node_lane_loop(v, cnt, link_mass, &fin, 1, 1, 0, gr);
    else if (en)
        rj__node_lane_loop(v, cnt, link_mass, &fin, 1, 0, 1, gr);
    else
        rj__node_lane_loop(v, cnt, link_mass, &fin, 1, 0, 0, gr);
    /* the new positions' sum: NaN or infinite when one of them is */
    for (k = 0; k < RJ__VW; k++)
        fin_sum += fin[k];
    *v->fin += fin_sum;
}
#endif

/* Nodes n + k .. n + cnt - 1 from the chunk buffer F (rows FX, FY, M1, M2) laid out so
   that node k takes FX[k] - FX[k+1] (its element on the left, -0.0 before a link's first,
   minus the one on the right, +0.0 after its last: the same bits as -FX[0] and FX[last])
   and mz = -M2[k] - M1[k+1]: the forces (into fx, fy, mz), and with step (not NULL) the
   advanced velocities, positions and kinetic-energy shares (the lanes did nodes 0 .. k - 1,
   or none: the pass's copy without them). */
static void rj__node_scalar(int k, int cnt, int n, const double *F, double *fx, double *fy,
                            double *mz, const double *x, const double *y, const double *phi,
                            const rj__adv *step)
{
    const double *FX = F;
    const double *FY = F + RJ__FROW;
    const double *M1 = F + 2 * RJ__FROW;
    const double *M2 = F + 3 * RJ__FROW;
    rj__adv a; /* a local copy, whose fields the stores below cannot change */
    if (!step) {
        for (; k < cnt; k++) {
            fx[n + k] = FX[k] - FX[k + 1];
            fy[n + k] = FY[k] - FY[k + 1];
            mz[n + k] = -M2[k] - M1[k + 1];
        }
        return;
    }
    a = *step;
    for (; k < cnt; k++) {
        double fxv = FX[k] - FX[k + 1];
        double fyv = FY[k] - FY[k + 1];
        const double mzv = -M2[k] - M1[k + 1];
        if (a.grav) { /* as the lanes: m g on every node that moves on its own */
            fxv = fxv + a.km[n + k] * a.gx;
            fyv = fyv + a.km[n + k] * a.gy;
        }
        fx[n + k] = fxv;
        fy[n + k] = fyv;
        mz[n + k] = mzv;
        rj__advance_node(&a, n + k, fxv, fyv, mzv, x, y, phi);
    }
}

/* The beam pass's arguments (rj__beam_pass_body), for its parts to share. */
typedef struct rj__pass {
    const rj_model *m;
    const double *x, *y, *phi;    /* nodes at n */
    const double *beta, *cx, *cy; /* chord angles and reference chords at n */
    double *eu;                   /* strain energies */
    double *beta_out, *cx_out, *cy_out;
    double *fx, *fy, *mz; /* node forces */
    const rj__adv *adv;   /* the step's node update, or NULL: forces only */
    int en;               /* strain energies wanted */
} rj__pass;

/* A rigid link has no elements: its chord angles and chords are carried over, its nodes
   take only what joints apply (and are advanced with the joints' nodes). */
static RJ__FORCE_INLINE void rj__beam_rigid_link(const rj__pass *p, int l)
{
    const int n0 = p->m->link_first[l];
    const int e0 = p->m->link_efirst[l];
    const int ne = p->m->link_efirst[l + 1] - e0;
    int i;
    for (i = e0; i < e0 + ne; i++) {
        p->beta_out[i] = p->beta[i];
        p->cx_out[i] = p->cx[i];
        p->cy_out[i] = p->cy[i];
        p->eu[i] = 0;
    }
    for (i = n0; i <= n0 + ne; i++) {
        p->fx[i] = 0;
        p->fy[i] = 0;
        p->mz[i] = 0;
    }
}

/* The element view of link l's chunk whose first element is a and first node na: the
   chunk buffer's row FX at F, in place the old values' buffer bk (else NULL). */
static RJ__FORCE_INLINE void rj__elems_at(rj__elems *c, const rj__pass *p, int l, int a, int na,
                                          double *F, double *bk)
{
    const double *kc = p->m->link_kc + 4 * (size_t) l;
    c->x = p->x + na;
    c->y = p->y + na;
    c->phi = p->phi + na;
    c->beta = p->beta + a;
    c->cx = p->cx + a;
    c->cy = p->cy + a;
    c->eu = p->eu + a;
    c->beta_out = p->beta_out + a;
    c->cx_out = p->cx_out + a;
    c->cy_out = p->cy_out + a;
    c->F = F;
    c->bk = bk;
    c->kb = kc[0];
    c->kax = kc[1];
    c->l0sq = kc[2];
    c->half_inv_l0sq = kc[3];
}

/* The chunk's nodes whose elements are all summed once its elements are: the chunk's nc,
   and the link's last node with the last chunk (last). Their forces are stored in the
   chunks that hold nodes the step advances again (m->dnode: a link's end nodes, and inner
   ones only in scenes with dn_inner: first, last). lanes_on: in vector lanes (in place whole
   lanes only) and the scalar loop after them, else in the scalar loop. */
static RJ__FORCE_INLINE void rj__chunk_nodes(const rj__pass *p, int l, int na, int first, int last,
                                             int nc, const double *FB, int ip, int lanes_on)
{
    const int cnt = nc + last;
    int done = 0;
#ifdef RJ__LANES
    if (lanes_on && p->adv && cnt >= RJ__VW) {
        const int lanes = ip ? cnt / RJ__VW * RJ__VW : cnt;
        const int store = first || last || p->m->dn_inner;
        const double *un = p->m->link_un + 5 * l;
        if (p->adv->grav)
            rj__node_lanes(p->adv, na, lanes, un, FB, p->x, p->y, p->phi, store, p->en, 1);
        else
            rj__node_lanes(p->adv, na, lanes, un, FB, p->x, p->y, p->phi, store, p->en, 0);
        done = lanes;
    }
#else
    (void) l;
    (void) first;
    (void) ip;
    (void) lanes_on;
#endif
    if (done < cnt)
        rj__node_scalar(done, cnt, na, FB, p->fx, p->fy, p->mz, p->x, p->y, p->phi, p->adv);
}

/* Link l's elements c0 .. c0 + nc - 1 and the nodes they complete, while they are in L1.
   The chunk buffer FB has rows FX, FY, M1, M2: entry 0 the previous chunk's last element
   (or the -0.0 / +0.0 before a link's first), entries 1 .. nc this chunk's, nc + 1 the +0.0
   after a link's last; node k takes FX[k] - FX[k + 1] (rj__node_scalar). EB: in place,
   the chunk's old chord angles and chords. */
static RJ__FORCE_INLINE void rj__beam_chunk(const rj__pass *p, int l, int c0, double *FB,
                                            double *EB, int ip, int lanes_on)
{
    const int n0 = p->m->link_first[l];
    const int e0 = p->m->link_efirst[l];
    const int ne = p->m->link_efirst[l + 1] - e0;
    const int nc = ne - c0 < RJ__CHUNK ? ne - c0 : RJ__CHUNK;
    const int last = c0 + nc == ne;
    rj__elems c;
    rj__elems_at(&c, p, l, e0 + c0, n0 + c0, FB + 1, ip ? EB : NULL);
    rj__chunk_elements(&c, nc, p->en, ip, lanes_on);
    if (last) {
        FB[nc + 1] = 0.0;
        FB[RJ__FROW + nc + 1] = 0.0;
        FB[2 * RJ__FROW + nc + 1] = 0.0;
    }
    rj__chunk_nodes(p, l, n0 + c0, c0 == 0, last, nc, FB, ip, lanes_on);
    /* this chunk's last element is entry 0 of the next */
    FB[0] = FB[nc];
    FB[RJ__FROW] = FB[RJ__FROW + nc];
    FB[2 * RJ__FROW] = FB[2 * RJ__FROW + nc];
    FB[3 * RJ__FROW] = FB[3 * RJ__FROW + nc];
}

/* The pass's arguments into its record. */
static RJ__FORCE_INLINE void rj__pass_open(rj__pass *p, const rj_model *m, const double *x,
                                           const double *y, const double *phi,
                                           const double *beta, const double *cx,
                                           const double *cy, double *eu, double *beta_out,
                                           double *cx_out, double *cy_out, double *fx,
                                           double *fy, double *mz, const rj__adv *adv)
{
    p->m = m;
    p->x = x;
    p->y = y;
    p->phi = phi;
    p->beta = beta;
    p->cx = cx;
    p->cy = cy;
    p->eu = eu;
    p->beta_out = beta_out;
    p->cx_out = cx_out;
    p->cy_out = cy_out;
    p->fx = fx;
    p->fy = fy;
    p->mz = mz;
    p->adv = adv;
    p->en = !adv || adv->en;
}

static RJ__NOINLINE void rj__beam_material_links(const rj_model *m, const double *x,
                                                 const double *y, const double *phi,
                                                 const double *beta, const double *cx,
                                                 const double *cy, double *eu, double *beta_out,
                                                 double *cx_out, double *cy_out, double *fx,
                                                 double *fy, double *mz, const rj__adv *adv,
                                                 const double *ep, double *ep_new);

/* Internal forces at x: element forces summed into the nodes (fx, fy, mz: node b of element
   e gets +ef, node a gets -ef), chunk by chunk; the updated chord angles and this step's
   chords (the next step's references) go to beta_out, cx_out, cy_out; eu receives the
   elements' strain energies. With adv (the step), every node of a flexible link is also
   advanced as soon as its forces are summed; nodes that joints act on are advanced again
   later (m->dnode); with adv->en clear the lanes leave eu stale. Returns whether eu is
   complete (rj__beam_pass then sums it into the strain energy). Two constants: ip, in place
   (the step's rj_model.ip), where beta_out .. cy_out are beta .. cy and the step's nodes
   are advanced where they are; lanes_on, the vector kernels (0: the scalar loops alone). */
static RJ__FORCE_INLINE int rj__beam_pass_body(const rj_model *m, const double *x, const double *y,
                                               const double *phi, const double *beta,
                                               const double *cx, const double *cy, double *eu,
                                               double *beta_out, double *cx_out, double *cy_out,
                                               double *fx, double *fy, double *mz,
                                               const rj__adv *adv, int ip, int lanes_on)
{
    rj__pass p;
    double FB[4 * RJ__FROW];
    double EB[3 * RJ__CHUNK];
    int l, c0;
    rj__pass_open(&p, m, x, y, phi, beta, cx, cy, eu, beta_out, cx_out, cy_out, fx, fy, mz, adv);
    for (l = 0; l < p.m->nl; l++) {
        const int ne = p.m->link_efirst[l + 1] - p.m->link_efirst[l];
        /* rigid links here; the material path's apart (rj__beam_material_links) */
        if (p.m->link_path[l] != RJ__PATH_FUSED) {
            if (p.m->link_path[l] == RJ__PATH_RIGID)
                rj__beam_rigid_link(&p, l);
            continue;
        }
        /* before the link's first element: -0.0 (node 0 takes -FX[1], the same bits) */
        FB[0] = -0.0;
        FB[RJ__FROW] = -0.0;
        FB[2 * RJ__FROW] = 0.0;
        FB[3 * RJ__FROW] = 0.0;
        for (c0 = 0; c0 < ne; c0 += RJ__CHUNK)
            rj__beam_chunk(&p, l, c0, FB, EB, ip, lanes_on);
    }
    return p.en;
}

/* The pass compiled whole, kernels inlined, once per target and in-place choice, so that
   the CPU is asked once per step: for AVX2 where the header dispatches (rj__beam_pass), and
   for the including file's own target. Each returns to its caller and calls no other code
   on its way out: a function compiled for AVX2 that jumps into SSE code without clearing
   the registers' upper halves (gcc 12 left out its vzeroupper before such a tail call)
   makes every later SSE instruction of the step pay for them (the paper's settings ran
   1.3x slower). An always_inline function without a target may be inlined into an AVX2
   one (gcc, clang), not the other way round. Where the header dispatches, RJ__VW is 4 for
   the AVX2 copy, and the copy for CPUs without AVX2 takes the scalar loops: gcc keeps a
   4-double vector that SSE2 registers cannot hold on the stack (30-40 % more instructions
   than 2 lanes, and 6 % more compile time for the whole header; docs/performance.md).
   RJ_NO_DISPATCH builds 2 lanes for such CPUs. */
#ifdef RJ__DISPATCH
#define RJ__DEFAULT_LANES_ON 0
#else
#define RJ__DEFAULT_LANES_ON 1
#endif
#ifdef RJ__DISPATCH
RJ__AVX2 static int rj__beam_pass_avx2(const rj_model *m, const double *x, const double *y,
                                       const double *phi, const double *beta, const double *cx,
                                       const double *cy, double *eu, double *beta_out,
                                       double *cx_out, double *cy_out, double *fx, double *fy,
                                       double *mz, const rj__adv *adv)
{
    return rj__beam_pass_body(m, x, y, phi, beta, cx, cy, eu, beta_out, cx_out, cy_out, fx, fy, mz,
                              adv, 0, 1);
}

RJ__AVX2 static int rj__beam_pass_avx2_ip(const rj_model *m, const double *x, const double *y,
                                          const double *phi, const double *beta, const double *cx,
                                          const double *cy, double *eu, double *beta_out,
                                          double *cx_out, double *cy_out, double *fx, double *fy,
                                          double *mz, const rj__adv *adv)
{
    return rj__beam_pass_body(m, x, y, phi, beta, cx, cy, eu, beta_out, cx_out, cy_out, fx, fy, mz,
                              adv, 1, 1);
}
#endif

static int rj__beam_pass_default(const rj_model *m, const double *x, const double *y,
                                 const double *phi, const double *beta, const double *cx,
                                 const double *cy, double *eu, double *beta_out, double *cx_out,
                                 double *cy_out, double *fx, double *fy, double *mz,
                                 const rj__adv *adv)
{
    return rj__beam_pass_body(m, x, y, phi, beta, cx, cy, eu, beta_out, cx_out, cy_out, fx, fy, mz,
                              adv, 0, RJ__DEFAULT_LANES_ON);
}

static int rj__beam_pass_default_ip(const rj_model *m, const double *x, const double *y,
                                    const double *phi, const double *beta, const double *cx,
                                    const double *cy, double *eu, double *beta_out, double *cx_out,
                                    double *cy_out, double *fx, double *fy, double *mz,
                                    const rj__adv *adv)
{
    return rj__beam_pass_body(m, x, y, phi, beta, cx, cy, eu, beta_out, cx_out, cy_out, fx, fy, mz,
                              adv, 1, RJ__DEFAULT_LANES_ON);
}

/* Internal forces at x (rj__beam_pass_body), in the widest lanes the CPU has; returns the
   strain energy, or 0 where the step does not take it (adv->en clear). */
static RJ__FORCE_INLINE double rj__beam_pass(const rj_model *m, const double *x, const double *y,
                                             const double *phi, const double *beta,
                                             const double *cx, const double *cy, double *eu,
                                             double *beta_out, double *cx_out, double *cy_out,
                                             double *fx, double *fy, double *mz, const rj__adv *adv)
{
    const int ip = adv && adv->ip;
    int en;
#if defined(RJ__DISPATCH)
    if (__builtin_cpu_supports("avx2"))
        en = (ip ? rj__beam_pass_avx2_ip : rj__beam_pass_avx2)(
            m, x, y, phi, beta, cx, cy, eu, beta_out, cx_out, cy_out, fx, fy, mz, adv);
    else
        en = (ip ? rj__beam_pass_default_ip : rj__beam_pass_default)(
            m, x, y, phi, beta, cx, cy, eu, beta_out, cx_out, cy_out, fx, fy, mz, adv);
#else
    en = (ip ? rj__beam_pass_default_ip : rj__beam_pass_default)(
        m, x, y, phi, beta, cx, cy, eu, beta_out, cx_out, cy_out, fx, fy, mz, adv);
#endif
    /* forces alone: the links on the material path too, without plastic strains (the
       step takes them before the pass, rj__beam_material_step) */
    if (m->nmaterial && !adv)
        rj__beam_material_links(m, x, y, phi, beta, cx, cy, eu, beta_out, cx_out, cy_out, fx,
                                fy, mz, adv, NULL, NULL);
    return en ? rj__sum8(eu, m->ne) : 0.0;
}
