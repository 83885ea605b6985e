/* ------------------------------------------------------------------ states */
typedef struct rj__slayout {
    size_t total, fd0, fd1, fd2, fi0, fi1, fi2, fx, fy, mz, kn, damp, visc, visc_force, peaks,
        peak_work, sha, shb, shc, shr, shp, gsw, bpw, eu, ebt, jsc,
        rsc, rows, terms, rsys, input_torque, input_node, node_applied, snap_torque, loop_force;
} rj__slayout;

/* The doubles of a state's peaks (rj_state.peaks). */
static size_t rj__peaks_count(const rj_model *m)
{
    return RJ__PEAK_JOINT * (size_t) m->nj + RJ__PEAK_LINK * (size_t) m->nl;
}

/* No peak yet: each value -1 (a magnitude is >= 0), its time, element and end -1. */
static void rj__peaks_clear(const rj_model *m, rj_state *s)
{
    size_t k;
    for (k = 0; k < rj__peaks_count(m); k++)
        s->peaks[k] = -1;
}

static void rj__state_layout(const rj_model *m, rj__slayout *L)
{
    size_t off = sizeof(rj_state);
    L->fd0 = rj__carve(&off, m->frame_doubles, sizeof(double));
    L->fd1 = rj__carve(&off, m->frame_doubles, sizeof(double));
    L->fi0 = rj__carve(&off, m->frame_ints + 1, sizeof(int));
    L->fi1 = rj__carve(&off, m->frame_ints + 1, sizeof(int));
    L->fd2 = rj__carve(&off, m->ip ? m->frame_doubles : 0, sizeof(double));
    L->fi2 = rj__carve(&off, m->ip ? m->frame_ints + 1 : 0, sizeof(int));
    L->fx = rj__carve(&off, (size_t) m->nn, sizeof(double));
    L->fy = rj__carve(&off, (size_t) m->nn, sizeof(double));
    L->mz = rj__carve(&off, (size_t) m->nn, sizeof(double));
    L->kn = rj__carve(&off, (size_t) m->nn, sizeof(double));
    L->damp = rj__carve(&off, m->nmaterial ? 3 * (size_t) m->nn + 2 : 0, sizeof(double));
    L->visc = rj__carve(&off, m->nvisc ? RJ__VISC_PER * ((size_t) m->visc_nodes + 1) : 0,
                        sizeof(double));
    L->visc_force = rj__carve(&off, m->nvisc ? 4 * (size_t) m->ne : 0, sizeof(double));
    L->peaks = rj__carve(&off, rj__peaks_count(m) + 1, sizeof(double));
    L->peak_work = rj__carve(&off,
                             RJ__PIN_PER_LINK * ((size_t) m->nl + 1) + 2 * (size_t) m->nj + 1,
                             sizeof(double));
    L->sha = rj__carve(&off, m->any_inext ? (size_t) m->ne : 0, sizeof(double));
    L->shb = rj__carve(&off, m->any_inext ? (size_t) m->ne : 0, sizeof(double));
    L->shc = rj__carve(&off, m->any_inext ? (size_t) m->ne : 0, sizeof(double));
    L->shr = rj__carve(&off, m->any_inext ? (size_t) m->ne : 0, sizeof(double));
    /* with loops: SHAKE's pushes over the step, for the loop joints' records */
    L->shp = rj__carve(&off, m->any_inext && m->nloop ? 2 * (size_t) m->nn : 0, sizeof(double));
    L->gsw = rj__carve(&off,
                       m->gs_n ? 2 * m->gs_prof + 9 * (size_t) m->gs_n + 2 * (size_t) m->nn : 0,
                       sizeof(double));
    L->bpw = rj__carve(&off,
                       m->nbp ? 8 * (size_t) m->nbp * (size_t) m->nbp + 4 * (size_t) m->nbp +
                                    3 * (size_t) m->ncl + (m->nloop ? 2 * (size_t) m->nbp : 0)
                              : 0,
                       sizeof(double));
    L->eu = rj__carve(&off, (size_t) m->ne, sizeof(double));
    L->ebt = rj__carve(&off, (size_t) m->ne, sizeof(double));
    L->jsc = rj__carve(&off, (size_t) m->nj * 8 + 1, sizeof(double));
    L->rsc = rj__carve(&off, m->rigid ? rj__rig_step_scratch(m) : 3 * (size_t) m->ncl + 1,
                       sizeof(double));
    /* rigid scenes: the rows their joints, couplings and loops can open (rj_model.rig_rows);
       a loop's two rows name every coordinate at most */
    L->rows = rj__carve(&off,
                        m->rigid ? (size_t) m->rig_rows + 1
                                 : (size_t) rj__rows_capacity(m->nj, m->ncp + m->nloop),
                        sizeof(rj__row));
    /* a loop's two rows and its joint's latch or profile row name every coordinate at
       most (4 nq with one spare), and so may a coupling on a loop joint, twice when both
       its joints close loops */
    L->terms = rj__carve(&off,
                         (size_t) rj__terms_capacity(m->nj, m->ncp) +
                             4 * (size_t) m->nloop * (size_t) m->nq +
                             (m->nloop ? 2 * (size_t) m->ncp * (size_t) m->nq : 0),
                         sizeof(rj__term));
    L->rsys = rj__carve(&off, 2 * (size_t) m->nmotion * (size_t) (m->nmotion + 1) + 1,
                        sizeof(double));
    L->loop_force = rj__carve(&off, 2 * (size_t) m->nj + 1, sizeof(double));
    L->input_torque = rj__carve(&off, (size_t) m->nj + 1, sizeof(double));
    L->snap_torque = rj__carve(&off, (size_t) m->nj + 1, sizeof(double));
    L->input_node = rj__carve(&off, 3 * (size_t) m->nn, sizeof(double));
    L->node_applied = rj__carve(&off, 3 * (size_t) m->nn, sizeof(double));
    L->total = off == (size_t) -1 ? off : off + RJ__ALIGN;
}

RJDEF size_t rj_state_size(const rj_model *m)
{
    rj__slayout L;
    RJ_ASSERT(m);
    rj__state_layout(m, &L);
    return L.total;
}

/* frame accessors */
#define RJ__FX(m, f)    ((f) + RJ__FS_COUNT)
#define RJ__FY(m, f)    ((f) + RJ__FS_COUNT + (m)->nn)
#define RJ__FPHI(m, f)  ((f) + RJ__FS_COUNT + 2 * (size_t) (m)->nn)
#define RJ__FVX(m, f)   ((f) + RJ__FS_COUNT + 3 * (size_t) (m)->nn)
#define RJ__FVY(m, f)   ((f) + RJ__FS_COUNT + 4 * (size_t) (m)->nn)
#define RJ__FW(m, f)    ((f) + RJ__FS_COUNT + 5 * (size_t) (m)->nn)
#define RJ__FBETA(m, f) ((f) + RJ__FS_COUNT + 6 * (size_t) (m)->nn)
#define RJ__FCX(m, f)   ((f) + RJ__FS_COUNT + 6 * (size_t) (m)->nn + (m)->ne)
#define RJ__FCY(m, f)   ((f) + RJ__FS_COUNT + 6 * (size_t) (m)->nn + 2 * (size_t) (m)->ne)
#define RJ__FJ(m, f, j)                                                                            \
    ((f) + RJ__FS_COUNT + 6 * (size_t) (m)->nn + 3 * (size_t) (m)->ne + RJ__JD_COUNT * (size_t) (j))
#define RJ__FS(m, f) (f)

/* One joint's spring and table potentials at the running angle run, added to *V (spring
   first, then table: every caller sums in this order, so the totals agree to the bit); the
   table's torque goes to *table_torque. */
static void rj__joint_potential(const rj_joint_def *d, const rj__joint *J, double run, double *V,
                                double *table_torque)
{
    *table_torque = 0;
    if (d->spring_k > 0)
        *V += 0.5 * d->spring_k * (run - d->spring_free_angle) * (run - d->spring_free_angle);
    if (d->table_count)
        *V += rj__table_turns_potential(d, J, run, table_torque);
}

static double rj__spring_energy(const rj_model *m, const double *f)
{
    double V = 0, t;
    int j;
    for (j = 0; j < m->nj; j++)
        rj__joint_potential(&m->jdef[j], &m->jnt[j], RJ__FJ(m, f, j)[RJ__JD_THETA], &V, &t);
    for (j = 0; j < m->ncp; j++) {
        const rj_coupling_def *c = &m->cp[j];
        double elastic, damp;
        rj__coupling_torques(m, c, RJ__FJ(m, f, c->joint_a)[RJ__JD_THETA],
                             RJ__FJ(m, f, c->joint_b)[RJ__JD_THETA], 0, 0, &elastic, &damp, &V);
    }
    return V;
}

RJDEF void rj_state_reset(const rj_model *m, rj_state *s)
{
    double *f = s->fd[0], *sc;
    int j, i;
    s->cur = 0;
    s->steps = 0;
    s->loop_force[2 * m->nj] = -1;
    memset(s->input_torque, 0, sizeof(double) * (size_t) m->nj);
    s->inputs = 0;
    memset(s->input_node, 0, 3 * sizeof(double) * (size_t) m->nn);
    memset(s->node_applied, 0, 3 * sizeof(double) * (size_t) m->nn);
    s->node_inputs = 0;
    s->settle_scale = 0;
    s->snap = -1;
    s->err[0] = 0;
    s->warn[0] = 0;
    s->at_n = RJ__AT_N_NONE;
    s->peaks_on = 0;
    rj__peaks_clear(m, s);
    memset(s->fd[0], 0, sizeof(double) * m->frame_doubles);
    memset(s->fd[1], 0, sizeof(double) * m->frame_doubles);
    memset(s->fi[0], 0, sizeof(int) * (m->frame_ints + 1));
    memset(s->fi[1], 0, sizeof(int) * (m->frame_ints + 1));
    memcpy(RJ__FX(m, f), m->x0, sizeof(double) * (size_t) m->nn);
    memcpy(RJ__FY(m, f), m->y0, sizeof(double) * (size_t) m->nn);
    memcpy(RJ__FPHI(m, f), m->phi0, sizeof(double) * (size_t) m->nn);
    memcpy(RJ__FVX(m, f), m->vx0, sizeof(double) * (size_t) m->nn);
    memcpy(RJ__FVY(m, f), m->vy0, sizeof(double) * (size_t) m->nn);
    memcpy(RJ__FW(m, f), m->w0, sizeof(double) * (size_t) m->nn);
    memcpy(RJ__FBETA(m, f), m->beta0, sizeof(double) * (size_t) m->ne);
    for (i = 0; i < m->nl; i++) {
        int k;
        for (k = m->link_efirst[i]; k < m->link_efirst[i + 1]; k++) {
            int a = m->link_first[i] + (k - m->link_efirst[i]);
            RJ__FCX(m, f)[k] = m->x0[a + 1] - m->x0[a];
            RJ__FCY(m, f)[k] = m->y0[a + 1] - m->y0[a];
        }
    }
    for (j = 0; j < m->nj; j++) {
        double *jd = RJ__FJ(m, f, j);
        rj__jgeo g;
        rj__joint_geo(m, &m->jnt[j], m->x0, m->y0, &g);
        jd[RJ__JD_THETA] = m->jdef[j].angle0;
        jd[RJ__JD_RATE] = m->rigid
                              ? m->jdef[j].rate0
                              : rj__joint_rate(&m->jnt[j], &g, m->vx0, m->vy0, m->w0, NULL, NULL);
        jd[RJ__JD_EVENT] = -1;
        jd[RJ__JD_RELEASE] = -1;
        jd[RJ__JD_ZONE_LO] = RJ__NO_ZONE;
        jd[RJ__JD_ZONE_HI] = -RJ__NO_ZONE;
        jd[RJ__JD_BAND] = RJ__NO_ZONE;
        jd[RJ__JD_OVERLAP] = -1;
    }
    if (m->rigid) {
        /* nodes from the joint-coordinate kinematics, so that both descriptions agree */
        rj__rig r;
        rj__rig_map(m, s->rsc, &r, 1);
        for (j = 0; j < m->nq; j++) {
            r.q[j] = m->jdef[m->qj[j]].angle0;
            r.qd[j] = m->jdef[m->qj[j]].rate0;
        }
        /* a loop joint turns at the rate its loop gives it (g . q') */
        for (j = 0; j < m->nj && m->nloop; j++)
            if (m->jq[j] < 0)
                RJ__FJ(m, f, j)[RJ__JD_RATE] = rj__rig_loop_rate(m, j, r.qd, r.tmp);
        rj__rig_kin(m, &r, r.q, r.qd, r.qd);
        rj__rig_nodes(m, &r, f);
    }
    sc = RJ__FS(m, f);
    {
        double ke = 0, U;
        for (i = 0; i < m->nn; i++)
            ke += 0.5 * m->mass[i] * (m->vx0[i] * m->vx0[i] + m->vy0[i] * m->vy0[i]) *
                      (m->einv[i] > 0) +
                  0.5 * m->rinertia[i] * m->w0[i] * m->w0[i] *
                      (m->rinv[i] > 0 && !RJ__CL_RIGID(m, i));
        for (i = 0; i < m->ncl; i++) {
            /* rigid bodies: anchor, its velocity, rate, angle */
            double *c = RJ__FCL(m, f, i);
            const int n0 = m->link_first[i];
            if (m->cl_first[i] == m->cl_first[i + 1])
                continue;
            c[0] = m->x0[n0] - m->cl_rx[n0];
            c[1] = m->y0[n0] - m->cl_ry[n0];
            c[2] = m->cl_th0[3 * i + 1];
            c[3] = m->cl_th0[3 * i + 2];
            c[4] = m->w0[n0];
            c[5] = m->cl_th0[3 * i];
            ke += 0.5 * m->cl_M[i] * (c[2] * c[2] + c[3] * c[3]) * (m->cl_fix[i] == 0) +
                  0.5 * m->cl_I[i] * c[4] * c[4];
        }
        double *o = s->fd[1]; /* scratch for the chords, cleared again below */
        U = rj__beam_pass(m, m->x0, m->y0, m->phi0, m->beta0, RJ__FCX(m, f), RJ__FCY(m, f), s->eu,
                          s->ebt, RJ__FCX(m, o), RJ__FCY(m, o), s->fx, s->fy, s->mz, NULL);
        memset(o, 0, sizeof(double) * m->frame_doubles);
        sc[RJ__FS_KE] = ke;
        sc[RJ__FS_STRAIN] = U;
        sc[RJ__FS_SPRING] = rj__spring_energy(m, f);
        sc[RJ__FS_GRAV] = rj__gravity_potential(m, RJ__FX(m, f), RJ__FY(m, f));
        sc[RJ__FS_E0] = ke + U + sc[RJ__FS_SPRING] + sc[RJ__FS_GRAV];
    }
}

RJDEF rj_result rj_state_init(const rj_model *m, void *mem, size_t size, rj_state **out)
{
    rj__slayout L;
    rj_state *s;
    char *base;
    if (!m || !out)
        return RJ_ERR_INVALID;
    rj__state_layout(m, &L);
    if (!mem || size < L.total)
        return RJ_ERR_NOMEM;
    base = (char *) mem;
    base += (RJ__ALIGN - ((size_t) base % RJ__ALIGN)) % RJ__ALIGN;
    memset(base, 0, L.total - RJ__ALIGN);
    s = (rj_state *) (void *) base;
    s->bytes = L.total - RJ__ALIGN;
    s->fd[0] = (double *) (void *) (base + L.fd0);
    s->fd[1] = (double *) (void *) (base + L.fd1);
    s->fi[0] = (int *) (void *) (base + L.fi0);
    s->fi[1] = (int *) (void *) (base + L.fi1);
    s->fd[2] = m->ip ? (double *) (void *) (base + L.fd2) : NULL;
    s->fi[2] = m->ip ? (int *) (void *) (base + L.fi2) : NULL;
    s->fx = (double *) (void *) (base + L.fx);
    s->fy = (double *) (void *) (base + L.fy);
    s->mz = (double *) (void *) (base + L.mz);
    s->sha = (double *) (void *) (base + L.sha);
    s->shb = (double *) (void *) (base + L.shb);
    s->shc = (double *) (void *) (base + L.shc);
    s->shr = (double *) (void *) (base + L.shr);
    s->shp = (double *) (void *) (base + L.shp);
    s->gsw = (double *) (void *) (base + L.gsw);
    s->bpw = (double *) (void *) (base + L.bpw);
    s->eu = (double *) (void *) (base + L.eu);
    s->ebt = (double *) (void *) (base + L.ebt);
    s->kn = (double *) (void *) (base + L.kn);
    s->damp = (double *) (void *) (base + L.damp);
    s->visc = (double *) (void *) (base + L.visc);
    s->visc_force = (double *) (void *) (base + L.visc_force);
    s->peaks = (double *) (void *) (base + L.peaks);
    s->peak_work = (double *) (void *) (base + L.peak_work);
    s->jsc = (double *) (void *) (base + L.jsc);
    s->rsc = (double *) (void *) (base + L.rsc);
    s->rows = (rj__row *) (void *) (base + L.rows);
    s->terms = (rj__term *) (void *) (base + L.terms);
    s->rsys = (double *) (void *) (base + L.rsys);
    s->loop_force = (double *) (void *) (base + L.loop_force);
    s->input_torque = (double *) (void *) (base + L.input_torque);
    s->snap_torque = (double *) (void *) (base + L.snap_torque);
    s->input_node = (double *) (void *) (base + L.input_node);
    s->node_applied = (double *) (void *) (base + L.node_applied);
    rj_state_reset(m, s);
    *out = s;
    return RJ_OK;
}

RJDEF rj_result rj_state_create(const rj_model *m, rj_state **out, void *alloc_ctx)
{
    size_t sz;
    void *mem;
    rj_result r;
    (void) alloc_ctx;
    if (!m || !out)
        return RJ_ERR_INVALID;
    sz = rj_state_size(m);
    mem = RJ_MALLOC(sz, alloc_ctx);
    if (!mem)
        return RJ_ERR_NOMEM;
    r = rj_state_init(m, mem, sz, out);
    if (r != RJ_OK || (void *) *out != mem) {
        RJ_FREE(mem, alloc_ctx);
        *out = NULL;
        return r != RJ_OK ? r : RJ_ERR_NOMEM;
    }
    return RJ_OK;
}

RJDEF void rj_state_destroy(rj_state *s, void *alloc_ctx)
{
    (void) alloc_ctx;
    if (s)
        RJ_FREE(s, alloc_ctx);
}

RJDEF rj_result rj_state_copy(const rj_model *m, rj_state *dst, const rj_state *src)
{
    if (!m || !dst || !src)
        return RJ_ERR_INVALID;
    memcpy(dst->fd[0], src->fd[src->cur], sizeof(double) * m->frame_doubles);
    memcpy(dst->fi[0], src->fi[src->cur], sizeof(int) * (m->frame_ints + 1));
    /* the state a step before too, for the loads at t^n (rj_joint_pin_force) */
    memcpy(dst->fd[1], src->fd[1 - src->cur], sizeof(double) * m->frame_doubles);
    memcpy(dst->fi[1], src->fi[1 - src->cur], sizeof(int) * (m->frame_ints + 1));
    dst->at_n = src->at_n;
    /* in place, the nodes' values at n the step kept, and their forces */
    if (src->at_n == RJ__AT_N_KEPT) {
        memcpy(dst->fd[2], src->fd[2], sizeof(double) * m->frame_doubles);
        memcpy(dst->fx, src->fx, sizeof(double) * (size_t) m->nn);
        memcpy(dst->fy, src->fy, sizeof(double) * (size_t) m->nn);
    }
    /* the implicit damping's element forces of that step (the loads at t^n) */
    if (m->nvisc)
        memcpy(dst->visc_force, src->visc_force, sizeof(double) * 4 * (size_t) m->ne);
    dst->peaks_on = src->peaks_on;
    memcpy(dst->peaks, src->peaks, sizeof(double) * rj__peaks_count(m));
    dst->cur = 0;
    dst->steps = src->steps;
    /* the loops' pin forces of the step that led here */
    memcpy(dst->loop_force, src->loop_force, sizeof(double) * (2 * (size_t) m->nj + 1));
    dst->snap = -1;
    memcpy(dst->input_torque, src->input_torque, sizeof(double) * (size_t) m->nj);
    dst->inputs = src->inputs;
    memcpy(dst->input_node, src->input_node, 3 * sizeof(double) * (size_t) m->nn);
    memcpy(dst->node_applied, src->node_applied, 3 * sizeof(double) * (size_t) m->nn);
    dst->node_inputs = src->node_inputs;
    dst->settle_scale = 0;
    memcpy(dst->err, src->err, sizeof dst->err);
    memcpy(dst->warn, src->warn, sizeof dst->warn);
    return RJ_OK;
}

