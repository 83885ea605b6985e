/* ------------------------------------------------------------------ structural damping */
/* Links with structural damping (rj_link_def.eta, damping, mass_damping) take their own
   path through the beam pass, in scalars, so that the fused kernels of every other link
   stay as they are and a scene without it pays nothing.

   Kelvin-Voigt: each element's stress is E (strain + eta d(strain)/dt), on the axial
   Green strain and on the local end rotations that carry its bending. The viscous part
   maps to node forces as the elastic part does (rj__elem_forces), with the strains'
   rates in place of the strains: the Green strain's rate e . e' / l0^2, and the end
   rotations' rates w_a - beta', w_b - beta', beta' = (e x e') / |e|^2 the chord's turn.
   Mass-proportional damping adds -mass_damping m v to each node (m w: its rotation).
   Both act on the velocities at n - 1/2, as the joints' damping does (Eq 27): explicit,
   bounded by dt <= (2 / omega) (sqrt(1 + zeta^2) - zeta) (rj__structural_rate).

   Their loss joins the accounts in the step's own discrete form: the kinetic energy
   1/2 v^{n-1/2} M v^{n+1/2} changes over a step by dt/2 v^{n-1/2} . (F^n + F^{n-1}), so the
   damping forces' share is -dt/2 F_d^n . v^{n-1/2} (summed here) and -dt/2 F_d^n .
   v^{n+1/2}, which the next step takes (rj__structural_accounts, from the forces kept in
   rj_state.damp). */

/* The viscous stresses of an element with chord (ex, ey), 1 / |e|^2 inv_l2, chord rate
   (dex, dey) and end rotation rates wa, wb, for a link with constants kc (rj_model.
   link_kc) and eta: node b's force, the end moments, and in u the power they develop
   (<= 0: what the element dissipates, with its sign). */
static RJ__INLINE void rj__elem_viscous(const double *kc, double eta, double ex, double ey,
                                        double inv_l2, double dex, double dey, double wa,
                                        double wb, rj__elem_force *f)
{
    /* the Green strain's rate, e . e' / l0^2, and the chord's turn rate */
    const double eps_rate = (ex * dex + ey * dey) * (2.0 * kc[3]);
    const double turn = (ex * dey - ey * dex) * inv_l2;
    const double tha = wa - turn;
    const double thb = wb - turn;
    /* the end moments and axial force of rj__elem_forces, on the rates, times eta */
    const double ma = eta * kc[0] * (4.0 * tha + 2.0 * thb);
    const double mb = eta * kc[0] * (2.0 * tha + 4.0 * thb);
    const double nax = eta * kc[1] * eps_rate;
    const double s = (ma + mb) * inv_l2;
    f->fx = -nax * ex - s * ey;
    f->fy = -nax * ey + s * ex;
    f->ma = ma;
    f->mb = mb;
    f->u = -(nax * kc[2] * eps_rate + ma * tha + mb * thb);
}

/* The chunk's elements 0 .. nc - 1 (first node na) of link l: their viscous forces, at
   the positions at n and the velocities at n - 1/2, into the rows FD (entry i + 1: element
   i, as the kernels fill the chunk buffer). */
static void rj__chunk_viscous(const rj__pass *p, int l, int na, int nc, double *FD)
{
    const double *kc = p->m->link_kc + 4 * (size_t) l;
    const double eta = p->m->link_damp[2 * (size_t) l];
    const double *x = p->x + na, *y = p->y + na;
    const double *vx = p->adv->vx + na, *vy = p->adv->vy + na, *w = p->adv->w + na;
    int i;
    for (i = 0; i < nc; i++) {
        const double ex = x[i + 1] - x[i];
        const double ey = y[i + 1] - y[i];
        const double inv_l2 = 1.0 / (ex * ex + ey * ey);
        rj__elem_force f;
        rj__elem_viscous(kc, eta, ex, ey, inv_l2, vx[i + 1] - vx[i], vy[i + 1] - vy[i], w[i],
                         w[i + 1], &f);
        FD[1 + i] = f.fx;
        FD[RJ__FROW + 1 + i] = f.fy;
        FD[2 * RJ__FROW + 1 + i] = f.ma;
        FD[3 * RJ__FROW + 1 + i] = f.mb;
    }
}

/* Node n's damping force: the viscous rows FD's (entry k the element before it, k + 1 the
   one after, as rj__node_scalar reads the chunk buffer) and its mass-proportional share,
   -alpha m v at n - 1/2; into d (fx, fy, mz). */
static RJ__INLINE void rj__node_damping(const rj__pass *p, int n, int k, const double *FD,
                                        double alpha, double d[3])
{
    const rj__adv *a = p->adv;
    d[0] = FD[k] - FD[k + 1] - alpha * p->m->mass[n] * a->vx[n];
    d[1] = FD[RJ__FROW + k] - FD[RJ__FROW + k + 1] - alpha * p->m->mass[n] * a->vy[n];
    d[2] = -FD[3 * RJ__FROW + k] - FD[2 * RJ__FROW + k + 1] -
           alpha * p->m->rinertia[n] * a->w[n];
}

/* The chunk's nodes na .. na + cnt - 1 in the step: their forces, the elastic ones from
   the chunk buffer FB with gravity and the damping ones; the damping ones kept
   (rj_state.damp) and their power at n - 1/2 summed; then advanced (rj__advance_node). */
static void rj__damped_nodes(const rj__pass *p, int l, int na, int cnt, const double *FB,
                             const double *FD, double *power)
{
    const double alpha = p->m->link_damp[2 * (size_t) l + 1];
    const rj__adv *a = p->adv;
    const size_t nn = (size_t) p->m->nn;
    int k;
    for (k = 0; k < cnt; k++) {
        const int n = na + k;
        double fxv = FB[k] - FB[k + 1];
        double fyv = FB[RJ__FROW + k] - FB[RJ__FROW + k + 1];
        double mzv = -FB[3 * RJ__FROW + k] - FB[2 * RJ__FROW + k + 1];
        double d[3];
        rj__node_damping(p, n, k, FD, alpha, d);
        if (a->grav) {
            fxv += a->km[n] * a->gx;
            fyv += a->km[n] * a->gy;
        }
        fxv += d[0];
        fyv += d[1];
        mzv += d[2];
        p->fx[n] = fxv;
        p->fy[n] = fyv;
        p->mz[n] = mzv;
        a->damp[n] = d[0];
        a->damp[nn + n] = d[1];
        a->damp[2 * nn + n] = d[2];
        *power += d[0] * a->vx[n] + d[1] * a->vy[n] + d[2] * a->w[n];
        rj__advance_node(a, n, fxv, fyv, mzv, p->x, p->y, p->phi);
    }
}

/* The chunk buffer's entries around a link's elements (rj__beam_pass_body's): -0.0
   before the first, +0.0 after the last (at entry at). */
static void rj__chunk_edge(double *F, int at, double value)
{
    int r;
    for (r = 0; r < 4; r++)
        F[r * RJ__FROW + at] = r < 2 ? value : 0.0;
}

/* Link l with structural damping, chunk by chunk as rj__beam_pass_body takes the others:
   the elastic element forces by the scalar kernels, the viscous ones beside them, the
   nodes advanced with both (forces only, without the step: the elastic ones). Its power
   at n - 1/2 is added to *power. */
static void rj__beam_damped_link(const rj__pass *p, int l, int ip, double *power)
{
    const int n0 = p->m->link_first[l];
    const int e0 = p->m->link_efirst[l];
    const int ne = p->m->link_efirst[l + 1] - e0;
    double FB[4 * RJ__FROW], FD[4 * RJ__FROW], EB[3 * RJ__CHUNK];
    int c0, r;
    rj__chunk_edge(FB, 0, -0.0);
    rj__chunk_edge(FD, 0, 0.0);
    for (c0 = 0; c0 < ne; c0 += RJ__CHUNK) {
        const int nc = ne - c0 < RJ__CHUNK ? ne - c0 : RJ__CHUNK;
        const int last = c0 + nc == ne;
        rj__elems c;
        rj__elems_at(&c, p, l, e0 + c0, n0 + c0, FB + 1, ip ? EB : NULL);
        rj__chunk_elements(&c, nc, p->en, ip, 0);
        if (last)
            rj__chunk_edge(FB, nc + 1, 0.0);
        if (!p->adv) {
            rj__node_scalar(0, nc + last, n0 + c0, FB, p->fx, p->fy, p->mz, p->x, p->y, p->phi,
                            NULL);
        } else {
            /* without eta the viscous rows are 0 */
            if (p->m->link_damp[2 * (size_t) l] > 0)
                rj__chunk_viscous(p, l, n0 + c0, nc, FD);
            else
                memset(FD, 0, sizeof FD);
            if (last)
                rj__chunk_edge(FD, nc + 1, 0.0);
            rj__damped_nodes(p, l, n0 + c0, nc + last, FB, FD, power);
        }
        /* this chunk's last element is entry 0 of the next */
        for (r = 0; r < 4; r++) {
            FB[r * RJ__FROW] = FB[r * RJ__FROW + nc];
            FD[r * RJ__FROW] = FD[r * RJ__FROW + nc];
        }
    }
}

/* The beam pass's part for the links with structural damping, which the fused pass
   leaves: after it for forces alone (rj__beam_pass), before it in the step
   (rj__beam_damped_step). With the step, their power at n - 1/2 goes to rj_state.damp's
   last entry. */
static RJ__NOINLINE void rj__beam_damped_links(const rj_model *m, const double *x,
                                               const double *y, const double *phi,
                                               const double *beta, const double *cx,
                                               const double *cy, double *eu, double *beta_out,
                                               double *cx_out, double *cy_out, double *fx,
                                               double *fy, double *mz, const rj__adv *adv)
{
    rj__pass p;
    double power = 0;
    const int ip = adv && adv->ip;
    int l;
    rj__pass_open(&p, m, x, y, phi, beta, cx, cy, eu, beta_out, cx_out, cy_out, fx, fy, mz, adv);
    for (l = 0; l < m->nl; l++)
        if (m->link_path[l] == RJ__PATH_DAMPED)
            rj__beam_damped_link(&p, l, ip, &power);
    if (adv)
        adv->damp[3 * (size_t) m->nn] = power;
}

/* The structural damping's accounts at the end of a step, from the scalars at n (osc)
   into those at n + 1 (nsc): its loss, the half the step before left (F_d^{n-1} .
   v^{n-1/2}) and this step's first (the power at n - 1/2, rj_state.damp), and the half
   the next step takes, -dt/2 F_d^n . v^{n+1/2} with the velocities vx, vy, w as the step
   left them. Returns the loss. */
static RJ__NOINLINE double rj__structural_accounts(const rj_model *m, const rj_state *s,
                                                   const double *osc, double *nsc,
                                                   const double *vx, const double *vy,
                                                   const double *w)
{
    const size_t nn = (size_t) m->nn;
    const double *d = s->damp;
    double sum = 0;
    int l, n;
    for (l = 0; l < m->nl; l++) {
        if (m->link_path[l] != RJ__PATH_DAMPED)
            continue;
        for (n = m->link_first[l]; n < m->link_first[l + 1]; n++)
            sum += d[n] * vx[n] + d[nn + n] * vy[n] + d[2 * nn + n] * w[n];
    }
    nsc[RJ__FS_LSTRUCT] =
        osc[RJ__FS_LSTRUCT] + osc[RJ__FS_SPEND] - 0.5 * m->dt * d[3 * nn];
    nsc[RJ__FS_SPEND] = -0.5 * m->dt * sum;
    return nsc[RJ__FS_LSTRUCT];
}
