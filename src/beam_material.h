/* ------------------------------------------------------------------ the material path */
/* Links whose material needs more than the fused kernels' elastic Green element take
   their own path through the beam pass, in scalars, so that the fused kernels of every
   other link stay as they are and a scene without them pays nothing: structural damping
   (rj_link_def.eta, damping, mass_damping), yielding layers (yield, hardening) and the
   Biot axial law (strain). The elastic Green element is the kernels' own
   (rj__chunk_elements); what the material adds is added to its results.

   Kelvin-Voigt: each element's stress is E (strain + eta d(strain)/dt), on the axial
   Green strain and on the local end rotations that carry its bending. The viscous part
   maps to node forces as the elastic part does (rj__elem_forces), with the strains'
   rates in place of the strains: the Green strain's rate e . e' / l0^2, and the end
   rotations' rates w_a - beta', w_b - beta', beta' = (e x e') / |e|^2 the chord's turn.
   Mass-proportional damping adds -mass_damping m v to each node (m w: its rotation).
   Both act here on the velocities at n - 1/2, as the joints' damping does (Eq 27):
   explicit, bounded by dt <= (2 / omega) (sqrt(1 + zeta^2) - zeta) (rj__structural_rate).
   Kelvin-Voigt does only on a link a rigid body carries a node of; on the others it is
   implicit, taken after this pass (src/viscous.h), and its viscous rows here are 0.

   Their loss joins the accounts in the step's own discrete form: the kinetic energy
   1/2 v^{n-1/2} M v^{n+1/2} changes over a step by dt/2 v^{n-1/2} . (F^n + F^{n-1}), so the
   damping forces' share is -dt/2 F_d^n . v^{n-1/2} (summed here) and -dt/2 F_d^n .
   v^{n+1/2}, which the next step takes (rj__material_accounts, from the forces kept in
   rj_state.damp).

   Yielding layers: the plastic strain of each layer is kept at two sections of each
   element, its Gauss points (rj__gauss_xi), where the cubic element's curvature kappa
   = ((6 xi - 4) th_a + (6 xi - 2) th_b) / l0 is exact in the bending energy. A layer's
   strain at its mid-depth z is eps0 - z kappa; its stress E (strain - plastic strain),
   returned to the yield surface |sigma - H ep| <= yield of bilinear kinematic hardening
   (plastic modulus H) each step. The section's N and M are the elastic ones, integrated
   exactly, less E times the plastic strains over the layers (constant through each
   layer): with no plastic strain the element is the elastic one to the bit. The plastic
   work, the account W_plastic, is each return's (sigma_trial + sigma) / 2 times its
   plastic strain: the elastic energy's drop at the strain it returned at, so that the
   balance closes as the elastic one does. */

/* The viscous stresses of an element with chord (ex, ey), 1 / |e|^2 inv_l2, chord rate
   (dex, dey) and end rotation rates wa, wb, for a link with constants kc (rj_model.
   link_kc) and eta: node b's force and the end moments (u 0: their power is summed over
   the nodes, rj__material_nodes). */
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
    f->u = 0;
}

/* The chunk's elements 0 .. nc - 1 (first node na) of link l: their viscous forces, at
   the positions at n and the velocities at n - 1/2, into the rows FD (entry i + 1: element
   i, as the kernels fill the chunk buffer). */
static void rj__chunk_viscous(const rj__pass *p, int l, int na, int nc, double *FD)
{
    const double *kc = p->m->link_kc + 4 * (size_t) l;
    const double eta = RJ__LD(p->m, l)[RJ__LD_LAGGED];
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
static void rj__material_nodes(const rj__pass *p, int l, int na, int cnt, const double *FB,
                             const double *FD, double *power)
{
    const double alpha = RJ__LD(p->m, l)[RJ__LD_MASS];
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

/* A link's material as the material path reads it. */
typedef struct rj__material {
    double E, EA, l0;        /* Pa, N, m */
    double yield, hard;      /* Pa: the layers' yield stress (0: elastic), plastic modulus */
    double width, height;    /* m: a rectangular section's */
    int layers, biot;        /* its layers; the Biot axial law */
} rj__material;

static void rj__material_of(const rj_model *m, int l, rj__material *mt)
{
    const rj_link_def *d = &m->ldef[l];
    mt->E = d->E;
    mt->EA = m->link_EA[l];
    mt->l0 = m->link_l0[l];
    mt->yield = d->yield;
    mt->hard = d->hardening;
    mt->width = d->width;
    mt->height = d->height;
    mt->layers = d->layers;
    mt->biot = d->strain == RJ_STRAIN_BIOT;
}

/* The element's two sections, as fractions of its length: the Gauss points. */
static const double rj__gauss_xi[2] = { 0.21132486540518713, 0.78867513459481287 };

/* What one section's layers add to the elastic section, per unit length: N, M, the
   elastic energy's change, the plastic work of this step's return. */
typedef struct rj__section_sums {
    double N, M, U, work;
    double smax; /* Pa: the largest |stress| at a layer's mid-depth */
} rj__section_sums;

/* One section at axial strain eps0 and curvature kappa: each layer's plastic strain from
   ep (NULL: none), returned to the yield surface into ep_new when given; into *out. */
static void rj__section_layers(const rj__material *mt, double eps0, double kappa,
                               const double *ep, double *ep_new, rj__section_sums *out)
{
    const double depth = mt->height / mt->layers;
    const double area = mt->width * depth;
    int k;
    memset(out, 0, sizeof *out);
    for (k = 0; k < mt->layers; k++) {
        const double z = -0.5 * mt->height + (k + 0.5) * depth;
        const double strain = eps0 - z * kappa;
        double plastic = ep ? ep[k] : 0.0;
        if (ep_new) {
            /* the return to |sigma - H ep| <= yield */
            const double trial = mt->E * (strain - plastic);
            const double over = trial - mt->hard * plastic;
            const double excess = fabs(over) - mt->yield;
            if (excess > 0) {
                const double step = (over > 0 ? excess : -excess) / (mt->E + mt->hard);
                out->work += area * (trial - 0.5 * mt->E * step) * step;
                plastic += step;
            }
            ep_new[k] = plastic;
        }
        out->N -= mt->E * area * plastic;
        out->M += mt->E * area * z * plastic;
        out->U += mt->E * area * plastic * (0.5 * plastic - strain);
        if (fabs(mt->E * (strain - plastic)) > out->smax)
            out->smax = fabs(mt->E * (strain - plastic));
    }
}

/* What the material adds to the fused kernels' elastic Green element with chord (ex,
   ey) and local end rotations tha, thb: the Biot axial law, and the layers' plastic
   strains ep (2 sections x layers; NULL: none) returned into ep_new when given. Added to
   f (node b's force, end moments, strain energy); returns the plastic work (J), the
   largest |stress| at a layer's mid-depth (where the layers yield) into *smax. */
static double rj__elem_material(const rj__material *mt, double ex, double ey, double tha,
                                double thb, const double *ep, double *ep_new,
                                rj__elem_force *f, double *smax)
{
    const double l0 = mt->l0;
    const double L2 = ex * ex + ey * ey;
    const double green = (L2 - l0 * l0) / (2.0 * l0 * l0);
    const double L = sqrt(L2);
    const double biot = L / l0 - 1.0;
    const double eps0 = mt->biot ? biot : green;
    double N = 0, ma = 0, mb = 0, U = 0, work = 0, dnax, s;
    int g;
    *smax = 0;
    if (mt->yield > 0) {
        for (g = 0; g < 2; g++) {
            const double xi = rj__gauss_xi[g];
            const double kappa = ((6.0 * xi - 4.0) * tha + (6.0 * xi - 2.0) * thb) / l0;
            const int at = g * mt->layers;
            rj__section_sums sec;
            rj__section_layers(mt, eps0, kappa, ep ? ep + at : NULL, ep_new ? ep_new + at : NULL,
                               &sec);
            /* two-point Gauss: weights l0 / 2; the end moments M_a = int M (6 xi - 4) dxi */
            N += 0.5 * sec.N;
            ma += 0.5 * sec.M * (6.0 * xi - 4.0);
            mb += 0.5 * sec.M * (6.0 * xi - 2.0);
            U += 0.5 * l0 * sec.U;
            work += 0.5 * l0 * sec.work;
            if (sec.smax > *smax)
                *smax = sec.smax;
        }
    }
    /* node b's axial force -nax e: Green's work conjugate l0 eps, Biot's L */
    if (mt->biot) {
        dnax = (mt->EA * biot + N) / L - mt->EA * green / l0;
        U += 0.5 * mt->EA * l0 * (biot * biot - green * green);
    } else
        dnax = N / l0;
    s = (ma + mb) / L2;
    f->fx += -dnax * ex - s * ey;
    f->fy += -dnax * ey + s * ex;
    f->ma += ma;
    f->mb += mb;
    f->u += U;
    return work;
}

/* The chunk's elements 0 .. nc - 1 (first element e0 of link l, first node na): what
   the material adds to the kernels' results in the chunk buffer FB (entry i + 1) and the
   strain energies; ep, ep_new: the link's plastic strains (NULL: none, or no return).
   Returns the plastic work. */
static double rj__chunk_material(const rj__pass *p, const rj__material *mt, int e0, int na,
                                 int nc, double *FB, const double *ep, double *ep_new)
{
    const int per = 2 * mt->layers;
    double work = 0, smax;
    int i;
    for (i = 0; i < nc; i++) {
        const int e = e0 + i;
        const double ex = p->x[na + i + 1] - p->x[na + i];
        const double ey = p->y[na + i + 1] - p->y[na + i];
        const double bt = p->beta_out[e];
        rj__elem_force f;
        f.fx = FB[1 + i];
        f.fy = FB[RJ__FROW + 1 + i];
        f.ma = FB[2 * RJ__FROW + 1 + i];
        f.mb = FB[3 * RJ__FROW + 1 + i];
        f.u = p->eu[e];
        work += rj__elem_material(mt, ex, ey, p->phi[na + i] - bt, p->phi[na + i + 1] - bt,
                                  ep ? ep + (size_t) per * i : NULL,
                                  ep_new ? ep_new + (size_t) per * i : NULL, &f, &smax);
        FB[1 + i] = f.fx;
        FB[RJ__FROW + 1 + i] = f.fy;
        FB[2 * RJ__FROW + 1 + i] = f.ma;
        FB[3 * RJ__FROW + 1 + i] = f.mb;
        p->eu[e] = f.u;
    }
    return work;
}

/* The chunk buffer's entries around a link's elements (rj__beam_pass_body's): -0.0
   before the first, +0.0 after the last (at entry at). */
static void rj__chunk_edge(double *F, int at, double value)
{
    int r;
    for (r = 0; r < 4; r++)
        F[r * RJ__FROW + at] = r < 2 ? value : 0.0;
}

/* Link l on the material path, chunk by chunk as rj__beam_pass_body takes the others:
   the elastic element forces by the scalar kernels, what the material adds to them (its
   axial law, its layers' plastic strains: ep at n - 1, returned into ep_new when given),
   the viscous forces beside them, the nodes advanced with all (forces only, without the
   step: no viscous ones). sums[0] gains the damping's power at n - 1/2, sums[1] the
   plastic work. */
static void rj__beam_material_link(const rj__pass *p, int l, int ip, const double *ep,
                                   double *ep_new, double sums[2])
{
    const int n0 = p->m->link_first[l];
    const int e0 = p->m->link_efirst[l];
    const int ne = p->m->link_efirst[l + 1] - e0;
    const size_t per = 2 * (size_t) p->m->ldef[l].layers;
    double FB[4 * RJ__FROW], FD[4 * RJ__FROW], EB[3 * RJ__CHUNK];
    rj__material mt;
    int c0, r;
    rj__material_of(p->m, l, &mt);
    rj__chunk_edge(FB, 0, -0.0);
    rj__chunk_edge(FD, 0, 0.0);
    for (c0 = 0; c0 < ne; c0 += RJ__CHUNK) {
        const int nc = ne - c0 < RJ__CHUNK ? ne - c0 : RJ__CHUNK;
        const int last = c0 + nc == ne;
        rj__elems c;
        rj__elems_at(&c, p, l, e0 + c0, n0 + c0, FB + 1, ip ? EB : NULL);
        rj__chunk_elements(&c, nc, p->en, ip, 0);
        if (mt.yield > 0 || mt.biot)
            sums[1] += rj__chunk_material(p, &mt, e0 + c0, n0 + c0, nc, FB,
                                          ep ? ep + per * c0 : NULL,
                                          ep_new ? ep_new + per * c0 : NULL);
        if (last)
            rj__chunk_edge(FB, nc + 1, 0.0);
        if (!p->adv) {
            rj__node_scalar(0, nc + last, n0 + c0, FB, p->fx, p->fy, p->mz, p->x, p->y, p->phi,
                            NULL);
        } else {
            /* without eta the viscous rows are 0 */
            if (RJ__LD(p->m, l)[RJ__LD_LAGGED] > 0)
                rj__chunk_viscous(p, l, n0 + c0, nc, FD);
            else
                memset(FD, 0, sizeof FD);
            if (last)
                rj__chunk_edge(FD, nc + 1, 0.0);
            rj__material_nodes(p, l, n0 + c0, nc + last, FB, FD, &sums[0]);
        }
        /* this chunk's last element is entry 0 of the next */
        for (r = 0; r < 4; r++) {
            FB[r * RJ__FROW] = FB[r * RJ__FROW + nc];
            FD[r * RJ__FROW] = FD[r * RJ__FROW + nc];
        }
    }
}

/* The beam pass's part for the links on the material path, which the fused pass leaves:
   after it for forces alone (rj__beam_pass: no plastic strains), before it in the step
   (rj__beam_material_step: the frames' blocks of plastic strains, at n - 1 in ep and at
   n into ep_new). With the step, the damping's power at n - 1/2 and the plastic work go
   to rj_state.damp's last two entries. */
static RJ__NOINLINE void rj__beam_material_links(const rj_model *m, const double *x,
                                                 const double *y, const double *phi,
                                                 const double *beta, const double *cx,
                                                 const double *cy, double *eu, double *beta_out,
                                                 double *cx_out, double *cy_out, double *fx,
                                                 double *fy, double *mz, const rj__adv *adv,
                                                 const double *ep, double *ep_new)
{
    rj__pass p;
    double sums[2] = { 0, 0 };
    const int ip = adv && adv->ip;
    int l;
    rj__pass_open(&p, m, x, y, phi, beta, cx, cy, eu, beta_out, cx_out, cy_out, fx, fy, mz, adv);
    for (l = 0; l < m->nl; l++) {
        const int at = m->link_pl[l];
        if (m->link_path[l] != RJ__PATH_MATERIAL)
            continue;
        rj__beam_material_link(&p, l, ip, ep && at >= 0 ? ep + at : NULL,
                               ep_new && at >= 0 ? ep_new + at : NULL, sums);
    }
    if (adv) {
        adv->damp[3 * (size_t) m->nn] = sums[0];
        adv->damp[3 * (size_t) m->nn + 1] = sums[1];
    }
}

/* The material's accounts at the end of a step, from the scalars at n (osc) into those
   at n + 1 (nsc): the structural damping's loss, the half the step before left (F_d^{n-1}
   . v^{n-1/2}) and this step's first (the power at n - 1/2, rj_state.damp), and the half
   the next step takes, -dt/2 F_d^n . v^{n+1/2} with the velocities vx, vy, w as the step
   left them; the plastic work. Returns both losses' sum. */
static RJ__NOINLINE double rj__material_accounts(const rj_model *m, const rj_state *s,
                                                   const double *osc, double *nsc,
                                                   const double *vx, const double *vy,
                                                   const double *w)
{
    const size_t nn = (size_t) m->nn;
    const double *d = s->damp;
    double sum = 0;
    int l, n;
    for (l = 0; l < m->nl; l++) {
        if (m->link_path[l] != RJ__PATH_MATERIAL)
            continue;
        for (n = m->link_first[l]; n < m->link_first[l + 1]; n++)
            sum += d[n] * vx[n] + d[nn + n] * vy[n] + d[2 * nn + n] * w[n];
    }
    nsc[RJ__FS_LSTRUCT] =
        osc[RJ__FS_LSTRUCT] + osc[RJ__FS_SPEND] - 0.5 * m->dt * d[3 * nn];
    nsc[RJ__FS_SPEND] = -0.5 * m->dt * sum;
    nsc[RJ__FS_LPLAST] = osc[RJ__FS_LPLAST] + d[3 * nn + 1];
    return nsc[RJ__FS_LSTRUCT] + nsc[RJ__FS_LPLAST];
}
