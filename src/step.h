/* ------------------------------------------------------------------ the step: its stages */
/* A node's rotation rate at the end of the step under the loads so far (a body's own node:
   the body's). */
static RJ__INLINE double rj__rate_pred(const rj_model *m, const double *of, int n, const double *x,
                                       const double *y, const double *w, const double *fx,
                                       const double *fy, const double *mz, double kick)
{
    if (m->ncl && RJ__CL_RIGID(m, n)) {
        const int c = m->node_cl[n];
        const double *oc = RJ__FCL(m, of, c);
        double Fx, Fy, T;
        if (m->cl_fix[c] == 2)
            return 0.0;
        rj__cl_load(m, c, oc, x, y, fx, fy, mz, &Fx, &Fy, &T);
        return oc[4] + kick * T / m->cl_I[c];
    }
    return w[n] + kick * mz[n] * m->rinv[n];
}

/* The frames one step reads and writes. Double-buffered, the step reads the current frame
   and writes the other; in place (rj__step), the nodes and elements advance in the current
   frame itself, and the third frame (s->fd[2]) takes the joints, bodies and scalars at
   n + 1 and keeps the values at n of the nodes the step reads after the beams (m->dnode). */
typedef struct rj__frames {
    double *current;      /* s->fd[s->cur] */
    const double *old;    /* the values at n: the current frame */
    double *next;         /* joints, bodies and scalars at n + 1 */
    double *advanced;     /* nodes and elements at n + 1: next, or current in place */
    const int *old_flags; /* joint flags at n */
    int *new_flags;       /* at n + 1 */
    const double *x, *y, *phi, *vx, *vy, *w; /* nodes at n (in place: from next) */
    double *nx, *ny, *nphi, *nvx, *nvy, *nw; /* nodes at n + 1 */
    const double *old_scalars;               /* time, accounts at n */
    double *new_scalars;                     /* at n + 1 */
    double t, dt;
    double kick; /* dt, or dt / 2 at the first step (from v(0)) */
    int first;   /* the first step */
    int en;      /* this step takes the energy accounts */
    int ip;      /* in place */
} rj__frames;

/* What a step adds up for the energy accounts, in J. */
typedef struct rj__sums {
    double strain;                                  /* the beams' strain energy at x^n */
    double spring;                                  /* the joints' springs and tables at n */
    double gravity;                                 /* gravity's potential at n, -sum m g . x */
    double kinetic;                                 /* 1/2 v^{n-1/2} . v^{n+1/2} */
    double lost_damping, lost_friction, lost_limit; /* since the start */
    double lost_material; /* the links' structural damping and plastic work since the start */
    double work;    /* done by the caller's inputs since the start */
    double drive;   /* done by the actuators since the start */
    double drive_pending; /* a prescribed joint's impulse's work the next step takes */
    double drive_flow;    /* the actuators' work moved, sum of |its change| (a scale) */
    double pending; /* a jump's loss the next step takes (its second half) */
} rj__sums;

/* The first moment sum m r of a rigid body's own link (rod and tip mass) at node
   positions x, y; its nodes carry no mass of their own. */
static void rj__cl_own_moment(const rj_model *m, int c, const double *x, const double *y,
                              double *mx, double *my)
{
    const rj_link_def *d = &m->ldef[c];
    const int n0 = m->link_first[c], nt = m->link_first[c + 1] - 1;
    const double area = rj__plain_area(d);
    const double rod = d->rho * area * d->length, own = rod + d->tip_mass;
    const double along = (rod * 0.5 + d->tip_mass) / own; /* the centre, as a fraction */
    *mx = own * (x[n0] + along * (x[nt] - x[n0]));
    *my = own * (y[n0] + along * (y[nt] - y[n0]));
}

/* The frames and step constants: the accounts when asked, at the start, or
   solver.energy_every steps after the last ones (no division). The nodes' arrays are
   rj__frames_nodes'. */
static RJ__FORCE_INLINE void rj__frames_open(const rj_model *m, rj_state *s, int want_energy,
                                             int ip, rj__frames *f)
{
    double *current = s->fd[s->cur];
    double *next = s->fd[ip ? 2 : 1 - s->cur];
    f->current = current;
    f->old = current;
    f->next = next;
    f->advanced = ip ? current : next;
    f->old_flags = s->fi[s->cur];
    f->new_flags = s->fi[ip ? 2 : 1 - s->cur];
    f->old_scalars = RJ__FS(m, current);
    f->new_scalars = RJ__FS(m, next);
    f->t = f->old_scalars[RJ__FS_TIME];
    f->dt = m->dt;
    f->first = s->steps == 0;
    /* the stored velocities are v(0) at the start and v^{n-1/2} after: the first kick is
       half a step, which makes the start second-order accurate too */
    f->kick = f->first ? 0.5 * m->dt : m->dt;
    f->en = want_energy || m->solver.energy_every <= 1 || s->steps == 0 ||
            f->t - f->old_scalars[RJ__FS_ETIME] > ((double) m->solver.energy_every - 0.5) * m->dt;
    f->ip = ip;
}

/* The nodes at n (in place: kept in the next frame) and at n + 1. */
static RJ__FORCE_INLINE void rj__frames_nodes(const rj_model *m, rj__frames *f)
{
    const double *at_n = f->ip ? f->next : f->current;
    double *advanced = f->advanced;
    f->x = RJ__FX(m, at_n);
    f->y = RJ__FY(m, at_n);
    f->phi = RJ__FPHI(m, at_n);
    f->vx = RJ__FVX(m, at_n);
    f->vy = RJ__FVY(m, at_n);
    f->w = RJ__FW(m, at_n);
    f->nx = RJ__FX(m, advanced);
    f->ny = RJ__FY(m, advanced);
    f->nphi = RJ__FPHI(m, advanced);
    f->nvx = RJ__FVX(m, advanced);
    f->nvy = RJ__FVY(m, advanced);
    f->nw = RJ__FW(m, advanced);
}

/* The accounts carried from the step before. */
static RJ__FORCE_INLINE void rj__sums_open(const double *old_scalars, rj__sums *e)
{
    e->strain = 0;
    e->spring = 0;
    e->gravity = 0;
    e->kinetic = 0;
    e->lost_damping = old_scalars[RJ__FS_LDAMP];
    e->lost_friction = old_scalars[RJ__FS_LFRIC];
    e->lost_limit = old_scalars[RJ__FS_LLIM] + old_scalars[RJ__FS_PEND];
    e->lost_material = 0;
    e->work = old_scalars[RJ__FS_WORK];
    e->drive = old_scalars[RJ__FS_DRIVE] + old_scalars[RJ__FS_DPEND];
    e->drive_pending = 0;
    e->drive_flow = old_scalars[RJ__FS_DFLOW];
    e->pending = 0;
}

/* The step's links on the material path, from the frame at n (old) into the advanced
   one (their plastic strains into next's block), before the fused pass, out of line. It
   takes a copy of the step's update, never its address, and returns the sum of the
   positions it wrote (rj__adv.fin): the address of the step's own record, given to it,
   cost the step 60 instructions on the paper's deployment, which has no such links. */
static RJ__NOINLINE double rj__beam_material_step(const rj_model *m, rj_state *s,
                                                  const double *old, double *advanced,
                                                  double *next, rj__adv adv)
{
    double fin = 0;
    adv.fin = &fin;
    adv.damp = s->damp;
    rj__beam_material_links(m, RJ__FX(m, old), RJ__FY(m, old), RJ__FPHI(m, old),
                            RJ__FBETA(m, old), RJ__FCX(m, old), RJ__FCY(m, old), s->eu,
                            RJ__FBETA(m, advanced), RJ__FCX(m, advanced), RJ__FCY(m, advanced),
                            s->fx, s->fy, s->mz, &adv, old + m->pl_off, next + m->pl_off);
    return fin;
}

/* Stage 1, the beams: internal forces at x^n and the new chord angles; every node advanced
   at once (v^{n+1/2}, x^{n+1}); the joints' nodes are advanced again in stage 4 (in place,
   from their values at n, kept first). */
static RJ__FORCE_INLINE void rj__stage_beams(const rj_model *m, rj_state *s, const rj__frames *f,
                                             rj__adv *adv, rj__sums *e)
{
    const double *old = f->old;
    double *next = f->next;
    /* gravity's potential at x^n, before the pass advances the nodes (in place too) */
    if (m->has_gravity && f->en)
        e->gravity = rj__gravity_potential(m, RJ__FX(m, old), RJ__FY(m, old));
    if (f->ip) {
        double *kept[6];
        const double *at_n[6];
        int i, k;
        kept[0] = RJ__FX(m, next);
        kept[1] = RJ__FY(m, next);
        kept[2] = RJ__FPHI(m, next);
        kept[3] = RJ__FVX(m, next);
        kept[4] = RJ__FVY(m, next);
        kept[5] = RJ__FW(m, next);
        at_n[0] = RJ__FX(m, old);
        at_n[1] = RJ__FY(m, old);
        at_n[2] = RJ__FPHI(m, old);
        at_n[3] = RJ__FVX(m, old);
        at_n[4] = RJ__FVY(m, old);
        at_n[5] = RJ__FW(m, old);
        for (i = 0; i < m->ndn; i++)
            for (k = 0; k < 6; k++)
                kept[k][m->dnode[i]] = at_n[k][m->dnode[i]];
    }
    adv->kick = f->kick;
    adv->dt = f->dt;
    adv->vx = RJ__FVX(m, old);
    adv->vy = RJ__FVY(m, old);
    adv->w = RJ__FW(m, old);
    adv->ti = m->tinv;
    adv->ri = m->rinv;
    adv->km = m->kmass;
    adv->kj = m->krot;
    adv->nx = f->nx;
    adv->ny = f->ny;
    adv->nphi = f->nphi;
    adv->nvx = f->nvx;
    adv->nvy = f->nvy;
    adv->nw = f->nw;
    adv->kn = s->kn;
    adv->fx = s->fx;
    adv->fy = s->fy;
    adv->mz = s->mz;
    adv->en = f->en;
    adv->ip = f->ip;
    adv->grav = m->has_gravity;
    adv->gx = m->solver.gravity[0];
    adv->gy = m->solver.gravity[1];
    if (m->nmaterial)
        *adv->fin += rj__beam_material_step(m, s, old, f->advanced, next, *adv);
    e->strain =
        rj__beam_pass(m, RJ__FX(m, old), RJ__FY(m, old), RJ__FPHI(m, old), RJ__FBETA(m, old),
                      RJ__FCX(m, old), RJ__FCY(m, old), s->eu, RJ__FBETA(m, f->advanced),
                      RJ__FCX(m, f->advanced), RJ__FCY(m, f->advanced), s->fx, s->fy, s->mz, adv);
    /* stage 4 advances the joints' nodes from their values at n */
    adv->vx = f->vx;
    adv->vy = f->vy;
    adv->w = f->w;
}

/* The joint geometry stage 2 kept. */
static RJ__FORCE_INLINE void rj__kept_geo(const double *kept, rj__jgeo *g)
{
    g->ax = kept[0];
    g->ay = kept[1];
    g->bx = kept[2];
    g->by = kept[3];
    g->a2 = kept[6];
    g->b2 = kept[7];
}

/* Stage 2 of scenes with couplings: each cable loop's torques on its two joints' nodes,
   from their running angles at n and the rates the element read (kept in s->jsc); returns
   the loops' energy. Apart (not inlined, given the frames' pointers, not their record,
   whose address would keep it out of registers): a scene without loops pays one test. */
static RJ__NOINLINE double rj__stage_couplings(const rj_model *m, rj_state *s, const double *old,
                                               double *next)
{
    double energy = 0;
    int k;
    for (k = 0; k < m->ncp; k++) {
        const rj_coupling_def *c = &m->cp[k];
        const double *kept_a = s->jsc + 8 * c->joint_a, *kept_b = s->jsc + 8 * c->joint_b;
        double *rec_a = RJ__FJ(m, next, c->joint_a), *rec_b = RJ__FJ(m, next, c->joint_b);
        double elastic, damp, on_b;
        rj__jgeo g;
        rj__coupling_torques(m, c, RJ__FJ(m, old, c->joint_a)[RJ__JD_THETA],
                             RJ__FJ(m, old, c->joint_b)[RJ__JD_THETA], kept_a[4], kept_b[4],
                             &elastic, &damp, &energy);
        on_b = rj__coupling_record(c, elastic, damp, rec_a, rec_b);
        rj__kept_geo(kept_b, &g);
        rj__apply_torque(&m->jnt[c->joint_b], &g, on_b, s->fx, s->fy, s->mz);
        rj__kept_geo(kept_a, &g);
        rj__apply_torque(&m->jnt[c->joint_a], &g, -c->ratio * on_b, s->fx, s->fy, s->mz);
    }
    return energy;
}

/* Stage 2, the joints' element: rate, flag (Eqs 7-13), table, spring, damping and limit
   torques (Eqs 4, 22, 27) on the nodes; the geometry and rate kept in s->jsc for the
   stages after. */
static RJ__FORCE_INLINE void rj__stage_joint_torques(const rj_model *m, rj_state *s,
                                                     const rj__frames *f, rj__sums *e)
{
    /* the element sums the springs' energy through a pointer: a local of its own keeps the
       other sums out of memory */
    double spring = e->spring;
    int j;
    f->new_scalars[RJ__FS_WARN] = f->old_scalars[RJ__FS_WARN];
    for (j = 0; j < m->nj; j++) {
        const rj__joint *J = &m->jnt[j];
        const double *old_joint = RJ__FJ(m, f->old, j);
        double *new_joint = RJ__FJ(m, f->next, j);
        double *kept = s->jsc + 8 * j;
        rj__jgeo g;
        double rate, penetration, torque;
        rj__joint_geo(m, J, f->x, f->y, &g);
        rate = rj__joint_rate(J, &g, f->vx, f->vy, f->w, NULL, NULL);
        torque = rj__element(m, s, j, old_joint, new_joint, f->old_flags[j], &f->new_flags[j], rate,
                             f->t, f->new_scalars, &penetration, &spring);
        rj__apply_torque(J, &g, torque, s->fx, s->fy, s->mz);
        kept[0] = g.ax;
        kept[1] = g.ay;
        kept[2] = g.bx;
        kept[3] = g.by;
        kept[4] = rate;
        kept[5] = penetration;
        kept[6] = g.a2;
        kept[7] = g.b2;
    }
    e->spring = spring;
}


/* A node's velocity at the end of the step under the forces so far (a grouped node: its
   group's, gravity on it as rj__update_groups adds it: the members' forces do not hold
   it, while a node that moves on its own has it in its force). */
static RJ__FORCE_INLINE void rj__velocity_pred(const rj_model *m, const rj_state *s,
                                               const rj__frames *f, int n, double *pvx, double *pvy)
{
    const double kick = f->kick;
    if (m->tinv[n] == 0 && m->einv[n] > 0) {
        /* grouped node: the group's acceleration */
        double sx = 0, sy = 0, ginv = m->einv[n];
        const int g0 = m->node_grp[n];
        int q;
        for (q = m->grp_first[g0]; q < m->grp_first[g0 + 1]; q++) {
            sx += s->fx[m->grp_node[q]];
            sy += s->fy[m->grp_node[q]];
        }
        *pvx = f->vx[n] + kick * sx * ginv + kick * m->solver.gravity[0];
        *pvy = f->vy[n] + kick * sy * ginv + kick * m->solver.gravity[1];
    } else {
        *pvx = f->vx[n] + kick * s->fx[n] * m->tinv[n];
        *pvy = f->vy[n] + kick * s->fy[n] * m->tinv[n];
    }
}

/* The relative rate joint J would end the step with under the forces so far. */
static RJ__FORCE_INLINE double rj__joint_rate_pred(const rj_model *m, const rj_state *s,
                                                   const rj__frames *f, const rj__joint *J,
                                                   const rj__jgeo *g)
{
    double pvx[4], pvy[4], ratep;
    int nodes[4], k;
    if (!J->chord) {
        ratep = rj__rate_pred(m, f->old, J->nJ, f->x, f->y, f->w, s->fx, s->fy, s->mz, f->kick);
        if (J->nI >= 0)
            ratep -=
                rj__rate_pred(m, f->old, J->nI, f->x, f->y, f->w, s->fx, s->fy, s->mz, f->kick);
        return ratep;
    }
    nodes[0] = J->nI;
    nodes[1] = J->nK;
    nodes[2] = J->nJ;
    nodes[3] = J->nL;
    for (k = 0; k < 4; k++) {
        if (nodes[k] < 0) {
            pvx[k] = pvy[k] = 0;
            continue;
        }
        rj__velocity_pred(m, s, f, nodes[k], &pvx[k], &pvy[k]);
    }
    ratep = (g->bx * (pvy[3] - pvy[2]) - g->by * (pvx[3] - pvx[2])) / g->b2;
    if (J->nK >= 0)
        ratep -= (g->ax * (pvy[1] - pvy[0]) - g->ay * (pvx[1] - pvx[0])) / g->a2;
    return ratep;
}

/* The caller's torques are numbers the step can use: finite, within 1e100 N m (the
   checkpoints' bound). Else the step stops naming the joint, the state as it was. */
static int rj__inputs_ok(const rj_model *m, rj_state *s)
{
    int j;
    for (j = 0; j < m->nj; j++) {
        const double torque = s->input_torque[j];
        if (fabs(torque) <= 1e100)
            continue;
        rj__stop(m, s, RJ_ERR_INVALID,
                 "t = %.9g s: rj_state_joint_torques()[%d] = %g N m is not a finite torque "
                 "within 1e100 N m",
                 RJ__FS(m, s->fd[s->cur])[RJ__FS_TIME], j, torque);
        return 0;
    }
    return 1;
}

/* The caller's joint torques (rj_state_joint_torques, checked by rj__step before the
   step began), on the joint geometry stage 2 kept. */
static void rj__stage_inputs(const rj_model *m, rj_state *s, double *next)
{
    int j;
    for (j = 0; j < m->nj; j++) {
        const double torque = s->input_torque[j];
        rj__jgeo g;
        rj__kept_geo(s->jsc + 8 * j, &g);
        rj__apply_torque(&m->jnt[j], &g, torque, s->fx, s->fy, s->mz);
        RJ__FJ(m, next, j)[RJ__JD_INPUT] = torque;
    }
}

/* The work of the caller's joint torques over the step (after the velocity-level limits,
   which set the joints' rates at n + 1/2). */
static double rj__inputs_work(const rj_model *m, const rj_state *s, const double *old,
                              const double *next)
{
    double work = 0;
    int j;
    for (j = 0; j < m->nj; j++)
        work += rj__input_work(RJ__FJ(m, old, j), RJ__FJ(m, next, j), s->jsc[8 * j + 4], m->dt);
    return work;
}

/* A load's factor at time t: its table, linear between the points, held outside them
   (1 without a table). */
static double rj__load_factor(const rj_load_def *d, double t)
{
    return rj__time_factor(d->table_count, d->table_time, d->table_factor, t);
}

/* A load's force (global frame) and moment at time t on a node turned to phi: a follower
   load's force is given in the node's frame and turns with it. */
static void rj__load_value(const rj_load_def *d, double t, double phi, double out[3])
{
    const double scale = rj__load_factor(d, t);
    const double fx = scale * d->force[0], fy = scale * d->force[1];
    if (d->follower) {
        const double c = cos(phi), s = sin(phi);
        out[0] = c * fx - s * fy;
        out[1] = s * fx + c * fy;
    } else {
        out[0] = fx;
        out[1] = fy;
    }
    out[2] = scale * d->moment;
}

/* The work of a force and moment held at node n over the step, now at t^n and prev at
   t^{n-1}: (prev + now) / 2 . (x^n - x^{n-1}), the trapezoid whose sum is exactly the
   change it makes in the kinetic energy of the central-difference pair (as
   rj__input_work); at_n: the frame of the nodes at n (v^{n-1/2}). */
static double rj__node_work(const rj_model *m, const double *at_n, int n, const double *now,
                            const double *prev)
{
    const double vx = RJ__FVX(m, at_n)[n], vy = RJ__FVY(m, at_n)[n], w = RJ__FW(m, at_n)[n];
    return 0.5 * m->dt *
           ((now[0] + prev[0]) * vx + (now[1] + prev[1]) * vy + (now[2] + prev[2]) * w);
}

/* Stage 2c, the model's applied loads at t^n on their nodes (the step advances them after
   the joints: m->dnode); returns their work over the step before (the loads at t^{n-1}
   are their definitions' at t - dt, on the node turned back by dt w^{n-1/2}). */
static double rj__stage_loads(const rj_model *m, rj_state *s, double t, const double *at_n)
{
    const double *phi = RJ__FPHI(m, at_n), *w = RJ__FW(m, at_n);
    double work = 0;
    int k;
    for (k = 0; k < m->nload; k++) {
        const int n = m->load_node[k];
        double now[3], prev[3];
        rj__load_value(&m->load[k], t, phi[n], now);
        rj__load_value(&m->load[k], t - m->dt, phi[n] - m->dt * w[n], prev);
        s->fx[n] += now[0];
        s->fy[n] += now[1];
        s->mz[n] += now[2];
        work += rj__node_work(m, at_n, n, now, prev);
    }
    return work;
}

/* A caller's node force that is not a number the step can use (finite, within 1e100, the
   checkpoints' bound) stops the step, naming it, the state as it was. */
static int rj__node_input_ok(const rj_model *m, rj_state *s, int n)
{
    const double *in = s->input_node + 3 * (size_t) n;
    int k;
    for (k = 0; k < 3; k++) {
        if (fabs(in[k]) <= 1e100)
            continue;
        rj__stop(m, s, RJ_ERR_INVALID,
                 "t = %.9g s: rj_state_node_forces()[%d] = %g (node %d, %s) is not a finite "
                 "value within 1e100",
                 RJ__FS(m, s->fd[s->cur])[RJ__FS_TIME], 3 * n + k, in[k], n,
                 k == 2 ? "moment, N m" : "force, N");
        return 0;
    }
    return 1;
}

/* The node forces' sizes now and at the last step, summed: 0 when there are none to
   apply nor to account for (NaN for a NaN: the stage then refuses it). Branch-free, as most
   nodes of most states have none. */
static RJ__INLINE double rj__node_input_size(const double *in, const double *prev)
{
    return (fabs(in[0]) + fabs(in[1])) + (fabs(in[2]) + fabs(prev[0])) +
           (fabs(prev[1]) + fabs(prev[2]));
}

/* A force in (fx, fy, mz) on node i, which the beam pass has advanced already (not in
   m->dnode): v^{n+1/2} takes kick f / m on top (nothing on a grouped node's translation,
   which its group's stage gives: tinv 0), x^{n+1} follows, and the node's share of the
   kinetic energy the matching v^{n-1/2} . kick f. at_n, advanced: the frames of the
   nodes at n and at n + 1 (rj__frames_nodes). Returns the new position's x + y + phi. */
static double rj__node_kick(const rj_model *m, rj_state *s, int i, const double *in,
                            const double *at_n, double *advanced, double kick)
{
    const double dvx = kick * in[0] * m->tinv[i];
    const double dvy = kick * in[1] * m->tinv[i];
    const double dw = kick * in[2] * m->rinv[i];
    const double vx = RJ__FVX(m, at_n)[i], vy = RJ__FVY(m, at_n)[i], w = RJ__FW(m, at_n)[i];
    double *nx = RJ__FX(m, advanced), *ny = RJ__FY(m, advanced), *nphi = RJ__FPHI(m, advanced);
    double *nvx = RJ__FVX(m, advanced), *nvy = RJ__FVY(m, advanced), *nw = RJ__FW(m, advanced);
    s->kn[i] += m->kmass[i] * (vx * dvx + vy * dvy) + m->krot[i] * w * dw;
    nvx[i] += dvx;
    nvy[i] += dvy;
    nw[i] += dw;
    nx[i] += m->dt * dvx;
    ny[i] += m->dt * dvy;
    nphi[i] += m->dt * dw;
    return (nx[i] + ny[i]) + nphi[i];
}

/* Stage 2d, the caller's node forces, only where they or the last step's are not zero:
   with the joints' forces on the nodes the step advances after the joints (m->dnode); as
   a kick on the others, which the beam pass has advanced (their sum of new positions
   into s->step_fin). Their work over the step before, with the forces the last step
   applied (s->node_applied), into s->step_work. */
static rj_result rj__stage_node_inputs(const rj_model *m, rj_state *s, const double *at_n,
                                       double *advanced, double kick)
{
    double work = 0, fin = 0;
    int i;
    for (i = 0; i < m->nn; i++) {
        const double *in = s->input_node + 3 * (size_t) i;
        const double *prev = s->node_applied + 3 * (size_t) i;
        if (rj__node_input_size(in, prev) == 0)
            continue;
        if (!rj__node_input_ok(m, s, i))
            return RJ_ERR_INVALID;
        work += rj__node_work(m, at_n, i, in, prev);
        if (!rj__is_dnode(m, i)) {
            fin += rj__node_kick(m, s, i, in, at_n, advanced, kick);
            continue;
        }
        s->fx[i] += in[0];
        s->fy[i] += in[1];
        s->mz[i] += in[2];
    }
    s->step_fin = fin;
    s->step_work += work;
    return RJ_OK;
}

static double rj__stage_viscous(const rj_model *m, rj_state *s, const rj__frames *f);

/* Stage 2b, applied loads: the caller's joint torques, the model's loads and the
   caller's node forces, in that order, before friction so that it sees them; the work of
   the last two over the step before in s->step_work; then the links' implicit damping
   (stage 2e), which sees them all, on frames of its own (never in place). next: the new
   frame; t: the time at n; at_n, advanced: the frames of the nodes at n and n + 1; kick:
   the step's velocity kick per unit acceleration. This stage and rj__applied_work take
   plain values, not the step's frames, and are never inlined: a scene that applies
   nothing pays one test for both (the frames' address, given to the damping, cost the
   paper's step 15 instructions). */
static RJ__NOINLINE rj_result rj__stage_applied(const rj_model *m, rj_state *s, double *next,
                                                double t, const double *at_n, double *advanced,
                                                double kick)
{
    s->step_work = 0;
    s->step_fin = 0;
    if (s->inputs)
        rj__stage_inputs(m, s, next);
    if (m->nload)
        s->step_work += rj__stage_loads(m, s, t, at_n);
    if (s->node_inputs) {
        const rj_result r = rj__stage_node_inputs(m, s, at_n, advanced, kick);
        if (r != RJ_OK)
            return r;
    }
    if (m->nvisc) {
        rj__frames f;
        rj__frames_open(m, s, 0, 0, &f);
        rj__frames_nodes(m, &f);
        s->step_fin += rj__stage_viscous(m, s, &f);
    }
    return RJ_OK;
}

/* The work of the caller's joint torques over the step (after the velocity-level limits,
   which set the joints' rates): old, next: the frames at n and n + 1. */
static RJ__NOINLINE double rj__applied_work(const rj_model *m, const rj_state *s, const double *old,
                                            const double *next)
{
    return s->inputs ? rj__inputs_work(m, s, old, next) : 0.0;
}

/* Node n's translation as the stages after this one move it: a grouped node's is its
   group's (rj__update_groups: the members' summed force and gravity on the summed mass),
   a node the step advances again (m->dnode) takes its force then; the others the beam
   pass has advanced. Into v (x, y) and minv (their inverse mass, 0: fixed). */
static void rj__visc_translation(const rj_model *m, const rj_state *s, const rj__frames *f,
                                 int n, int again, double v[2], double minv[2])
{
    minv[0] = minv[1] = m->einv[n];
    if (again || (m->tinv[n] == 0 && m->einv[n] > 0)) {
        rj__velocity_pred(m, s, f, n, &v[0], &v[1]);
        return;
    }
    v[0] = f->nvx[n];
    v[1] = f->nvy[n];
}

/* A node's rotation rate as predicted (rj__rate_pred; none: the ground's, 0). */
static double rj__visc_rate_pred(const rj_model *m, const rj_state *s, const rj__frames *f,
                                 int n)
{
    if (n < 0)
        return 0.0;
    return rj__rate_pred(m, f->old, n, f->x, f->y, f->w, s->fx, s->fy, s->mz, f->kick);
}

/* Element i's chord at n + 1/2 as v* predicts it, e^n + dt/2 (v*_b - v*_a), into its
   record. The strains' rates are taken along it: at e^n, a link turning rigidly at
   omega showed an axial rate of omega^2 dt / 2 relative (v^{n+1/2} is square to the
   chord half a step on), which the axial viscosity eta EA made a force of 15 % of the
   centrifugal pull on the chain of `make bench`'s feature rows; along the midpoint chord
   a rigid turn has none. */
static void rj__visc_chord(const rj__frames *f, int n, double *W, int i)
{
    double *me = W + (size_t) RJ__VISC_PER * i;
    const double *next = me + RJ__VISC_PER;
    me[RJ__VI_E] = f->x[n + 1] - f->x[n] + 0.5 * f->dt * (next[RJ__VI_V] - me[RJ__VI_V]);
    me[RJ__VI_E + 1] =
        f->y[n + 1] - f->y[n] + 0.5 * f->dt * (next[RJ__VI_V + 1] - me[RJ__VI_V + 1]);
}

/* Link l's records for rj__visc_solve: every node's v* and inverse masses, then every
   element's chord at n + 1/2 and damping blocks there. dn: the first of m->dnode at or
   after the link's first node. */
static void rj__visc_gather(const rj_model *m, const rj_state *s, const rj__frames *f, int l,
                            int dn, double *W)
{
    const int n0 = m->link_first[l], nodes = m->link_first[l + 1] - n0;
    const double *kc = m->link_kc + 4 * (size_t) l;
    const double eta = RJ__LD(m, l)[RJ__LD_IMPLICIT];
    int i;
    for (i = 0; i < nodes; i++) {
        const int n = n0 + i;
        double *me = W + (size_t) RJ__VISC_PER * i;
        const int again = dn < m->ndn && m->dnode[dn] == n;
        dn += again;
        rj__visc_translation(m, s, f, n, again, me + RJ__VI_V, me + RJ__VI_MINV);
        me[RJ__VI_V + 2] = again ? rj__visc_rate_pred(m, s, f, n) : f->nw[n];
        me[RJ__VI_MINV + 2] = m->rinv[n];
    }
    for (i = 0; i + 1 < nodes; i++) {
        double *me = W + (size_t) RJ__VISC_PER * i;
        rj__visc_chord(f, n0 + i, W, i);
        rj__visc_elem(kc, eta, me[RJ__VI_E], me[RJ__VI_E + 1], me + RJ__VI_C);
    }
    memset(W + (size_t) RJ__VISC_PER * (nodes - 1) + RJ__VI_C, 0, 27 * sizeof(double));
}

/* Every node's masks and masses from its inverse masses (rj__visc_solve's). */
static void rj__visc_masses(double *W, int nodes)
{
    int i, p;
    for (i = 0; i < nodes; i++) {
        double *me = W + (size_t) RJ__VISC_PER * i;
        for (p = 0; p < 3; p++) {
            const double minv = me[RJ__VI_MINV + p];
            me[RJ__VI_MASK + p] = minv > 0 ? 1.0 : 0.0;
            me[RJ__VI_MASS + p] = minv > 0 ? 1.0 / minv : 1.0;
        }
    }
}

/* The rate a velocity-level method will hold joint j at this step (a lock, a limit the
   rate runs into, a prescribed profile: the rate that lands it there, as the later
   stages take it; friction that can stop the rate: 0), its pin nodes' rates wI, wJ as
   predicted; returns 0 when none holds it. */
static int rj__visc_held_rate(const rj_model *m, const rj_state *s, const rj__frames *f, int j,
                              double wI, double wJ, double *rate)
{
    const rj_joint_def *d = &m->jdef[j];
    const rj__joint *J = &m->jnt[j];
    const int flag = f->new_flags[j];
    const double p = s->jsc[8 * j + 5]; /* the element's penetration */
    if (rj__prescribed(J)) {
        *rate = rj__prescribed_rate(m, s, j, RJ__FJ(m, f->old, j)[RJ__JD_THETA], f->t, f->dt);
        return 1;
    }
    if (flag != RJ_FREE && rj__velocity_method(d->method) && rj__into_limit(flag, wJ - wI)) {
        *rate = flag == RJ_LOCKED || d->method == RJ_METHOD_FORCED ? p / f->dt : 0.0;
        return 1;
    }
    /* friction that can stop the joint (rj__friction) will hold it */
    if (d->friction > 0) {
        const double riI = J->nI >= 0 ? m->rinv[J->nI] : 0.0;
        const double give = f->kick * (riI + m->rinv[J->nJ]);
        *rate = 0.0;
        return fabs(wJ - wI) <= give * d->friction;
    }
    return 0;
}

/* A held joint's pin rotations in link l's records (first node n0, nodes of them): the
   two rotate as one of their summed inertia at the held rate apart, their angular
   momentum kept (as the later stages' torque pair keeps it); a fixed side (ground, a
   clamped node) holds the other. Without this a pin node's light rotation followed the
   damping in the solve, which the held joint then undid: the damping forces came from
   rates the step did not take (a root locked by the forced method rang 40 % slower). */
static void rj__visc_hold(const rj_model *m, const rj_state *s, const rj__frames *f, int j,
                          int n0, int nodes, double *W)
{
    const rj__joint *J = &m->jnt[j];
    const int nI = J->nI, nJ = J->nJ;
    const double riI = nI >= 0 ? m->rinv[nI] : 0.0, riJ = m->rinv[nJ];
    double wI, wJ, rate, uI, uJ, minv;
    wI = rj__visc_rate_pred(m, s, f, nI);
    wJ = rj__visc_rate_pred(m, s, f, nJ);
    if (!rj__visc_held_rate(m, s, f, j, wI, wJ, &rate))
        return;
    if (riI == 0 || riJ == 0) {
        /* the fixed side holds the other */
        uI = riI == 0 ? wI : wJ - rate;
        uJ = riJ == 0 ? wJ : wI + rate;
        minv = 0.0;
    } else {
        const double JI = 1.0 / riI, JJ = 1.0 / riJ;
        uI = (JI * wI + JJ * wJ - JJ * rate) / (JI + JJ);
        uJ = uI + rate;
        minv = 1.0 / (JI + JJ);
    }
    if (nI >= n0 && nI < n0 + nodes) {
        W[(size_t) RJ__VISC_PER * (nI - n0) + RJ__VI_V + 2] = uI;
        W[(size_t) RJ__VISC_PER * (nI - n0) + RJ__VI_MINV + 2] = riI == 0 ? 0.0 : minv;
    }
    if (nJ >= n0 && nJ < n0 + nodes) {
        W[(size_t) RJ__VISC_PER * (nJ - n0) + RJ__VI_V + 2] = uJ;
        W[(size_t) RJ__VISC_PER * (nJ - n0) + RJ__VI_MINV + 2] = riJ == 0 ? 0.0 : minv;
    }
}

/* Element i of link l's viscous forces on the rates solved for (records i and i + 1's
   v* + dv), as rj__elem_viscous gives them (-C_e v: build/test_mixed checks the two
   agree), kept (rj_state.visc_force) for the loads queries. */
static void rj__visc_elem_force(const rj_model *m, rj_state *s, int l, int i, const double *W,
                                rj__elem_force *out)
{
    const double *me = W + (size_t) RJ__VISC_PER * i;
    const double *va = me + RJ__VI_V, *vb = va + RJ__VISC_PER;
    const double ex = me[RJ__VI_E], ey = me[RJ__VI_E + 1];
    double *kept = s->visc_force + 4 * ((size_t) m->link_efirst[l] + (size_t) i);
    rj__elem_viscous(m->link_kc + 4 * (size_t) l, RJ__LD(m, l)[RJ__LD_IMPLICIT], ex, ey,
                     1.0 / (ex * ex + ey * ey), vb[0] - va[0], vb[1] - va[1], va[2], vb[2],
                     out);
    kept[0] = out->fx;
    kept[1] = out->fy;
    kept[2] = out->ma;
    kept[3] = out->mb;
}

/* Node n's damping force F on top of the others: kept in rj_state.damp with the
   mass-proportional part there already, its power at n - 1/2 into *power; a force on a
   node the stages after move (grouped, or in m->dnode: again), a kick on the others.
   Returns the positions written. */
static double rj__visc_node(const rj_model *m, rj_state *s, const rj__frames *f, int n,
                            int again, const double F[3], double *power)
{
    const size_t nn = (size_t) m->nn;
    s->damp[n] += F[0];
    s->damp[nn + n] += F[1];
    s->damp[2 * nn + n] += F[2];
    *power += F[0] * f->vx[n] + F[1] * f->vy[n] + F[2] * f->w[n];
    s->fx[n] += F[0];
    s->fy[n] += F[1];
    s->mz[n] += F[2];
    if (again)
        return 0.0;
    return rj__node_kick(m, s, n, F, f->current, f->advanced, f->kick);
}

/* Link l's damping forces F_d = -C (v* + dv) after the solve, element by element
   (rj__visc_elem_force), each node taking the element before it and the one after as
   rj__node_damping takes the lagged ones. Returns the positions written. */
static double rj__visc_apply(const rj_model *m, rj_state *s, const rj__frames *f, int l, int dn,
                             double *W, double *power)
{
    const int n0 = m->link_first[l], nodes = m->link_first[l + 1] - n0;
    rj__elem_force before, after;
    double fin = 0;
    int i, p;
    for (i = 0; i < nodes; i++) {
        double *me = W + (size_t) RJ__VISC_PER * i;
        for (p = 0; p < 3; p++)
            me[RJ__VI_V + p] += me[RJ__VI_Y + p];
    }
    memset(&before, 0, sizeof before);
    for (i = 0; i < nodes; i++) {
        const int n = n0 + i;
        const int again = dn < m->ndn && m->dnode[dn] == n;
        double F[3];
        dn += again;
        memset(&after, 0, sizeof after);
        if (i + 1 < nodes)
            rj__visc_elem_force(m, s, l, i, W, &after);
        F[0] = before.fx - after.fx;
        F[1] = before.fy - after.fy;
        F[2] = -before.mb - after.ma;
        fin += rj__visc_node(m, s, f, n, again, F, power);
        before = after;
    }
    return fin;
}

/* Stage 2e, the links' implicit Kelvin-Voigt damping (src/viscous.h), after every force
   but friction's, which then sees it: link by link, each seeing the ones before through
   their forces on the pins they share (the groups' sums), so that every solve only takes
   energy out. Its forces' power at n - 1/2 joins the material path's (rj_state.damp).
   Called by rj__stage_applied. Returns the positions written. */
static double rj__stage_viscous(const rj_model *m, rj_state *s, const rj__frames *f)
{
    double *W = s->visc + RJ__VISC_PER;
    double power = 0, fin = 0;
    int l, q;
    rj__visc_pad(W);
    for (l = 0; l < m->nl; l++) {
        const int n0 = m->link_first[l], nodes = m->link_first[l + 1] - n0;
        int dn;
        if (!(RJ__LD(m, l)[RJ__LD_IMPLICIT] > 0))
            continue;
        dn = rj__dnode_from(m, n0);
        rj__visc_gather(m, s, f, l, dn, W);
        for (q = m->visc_first[l]; q < m->visc_first[l + 1]; q++)
            rj__visc_hold(m, s, f, m->visc_joint[q], n0, nodes, W);
        rj__visc_masses(W, nodes);
        rj__visc_solve(W, nodes, f->kick);
        fin += rj__visc_apply(m, s, f, l, dn, W, &power);
    }
    s->damp[3 * (size_t) m->nn] += power;
    return fin;
}

/* One body of a pinned pair at the pin: its point r from the anchor, the pin's mean
   velocity over the step under the forces so far (the point turned exactly, as the
   bodies' poses turn it: the linear v + w perp(r) left out the pin's centripetal pull,
   and a stuck joint crept at first order in dt), its inverse mass and inertia (0 where
   held). */
static void rj__pair_side_at(const rj_model *m, const rj_state *s, const rj__frames *at, int n,
                             rj__pair_side *p)
{
    const int c = m->node_cl[n];
    const double *oc = RJ__FCL(m, at->old, c);
    double Fx, Fy, T, w, cw, sw;
    p->tinv = m->cl_fix[c] == 0 ? 1.0 / m->cl_M[c] : 0.0;
    p->rinv = m->cl_fix[c] != 2 ? 1.0 / m->cl_I[c] : 0.0;
    p->r[0] = at->x[n] - oc[0];
    p->r[1] = at->y[n] - oc[1];
    rj__cl_load(m, c, oc, at->x, at->y, s->fx, s->fy, s->mz, &Fx, &Fy, &T);
    w = oc[4] + at->kick * T * p->rinv;
    cw = cos(at->dt * w);
    sw = sin(at->dt * w);
    p->v[0] = oc[2] + at->kick * Fx * p->tinv + ((cw - 1) * p->r[0] - sw * p->r[1]) / at->dt;
    p->v[1] = oc[3] + at->kick * Fy * p->tinv + (sw * p->r[0] + (cw - 1) * p->r[1]) / at->dt;
}

/* A joint between two rigid bodies of a mixed scene, seen through the pin between them
   (rj__body_pins), whose impulse lambda keeps the pin's two points together: the rate
   the step would end with is the one that impulse leaves, rate - u . lambda, and the
   give of a torque pair is the pinned pair's, c = 1/I_1 + 1/I_2 - u^T K^-1 u, with K the
   pin's mobility (sum of 1/M + perp(r) perp(r)^T / I) and u = sum perp(r) / I. With the
   bodies' own gives alone, friction fell short and a stuck joint crept. */
static void rj__pair_terms(const rj_model *m, const rj_state *s, const rj__frames *f,
                              const rj__joint *J, double *ratep, double *give)
{
    rj__pair_side a, b;
    double K[3], u[2], gap[2], det, lam[2], c;
    rj__pair_side_at(m, s, f, J->nI, &a);
    rj__pair_side_at(m, s, f, J->nJ, &b);
    c = rj__pair_give(&a, &b, K, u, &det);
    /* two bodies turning about one point, or held: nothing for the pin to add */
    if (!(det > 0))
        return;
    gap[0] = a.v[0] - b.v[0];
    gap[1] = a.v[1] - b.v[1];
    lam[0] = -(K[2] * gap[0] - K[1] * gap[1]) / det;
    lam[1] = -(K[0] * gap[1] - K[1] * gap[0]) / det;
    *ratep -= u[0] * lam[0] + u[1] * lam[1];
    if (J->rotor > 0)
        c /= 1.0 + J->rotor * c;
    *give = f->kick * c;
}

/* Joint j's geometry at n (as stage 2 kept it), the rate it would end the step with
   under the forces so far, and its rate change per unit torque over the step; pairs:
   seen through the pin when it joins two rigid bodies (rj__pair_terms). */
static RJ__FORCE_INLINE void rj__joint_terms(const rj_model *m, const rj_state *s,
                                             const rj__frames *f, int j, int pairs,
                                             rj__jgeo *g, double *ratep, double *give)
{
    const rj__joint *J = &m->jnt[j];
    rj__kept_geo(s->jsc + 8 * j, g);
    *ratep = rj__joint_rate_pred(m, s, f, J, g);
    *give = f->kick * rj__joint_compliance(m, J, g);
    if (pairs && J->pair)
        rj__pair_terms(m, s, f, J, ratep, give);
}

/* Joint j's friction torque, applied and recorded (stage 3, below). */
static RJ__FORCE_INLINE void rj__friction_joint(const rj_model *m, rj_state *s,
                                                const rj__frames *f, int j, int pairs)
{
    const rj_joint_def *d = &m->jdef[j];
    const rj__joint *J = &m->jnt[j];
    double *new_joint = RJ__FJ(m, f->next, j);
    rj__jgeo g;
    double ratep, compliance, tau;
    rj__joint_terms(m, s, f, j, pairs, &g, &ratep, &compliance);
    tau = rj__friction(ratep, compliance, d->friction);
    rj__apply_torque(J, &g, tau, s->fx, s->fy, s->mz);
    new_joint[RJ__JD_TQ0 + RJ_TORQUE_FRICTION] = tau;
}

/* Stage 3, Coulomb friction: the torque that would stop the relative rotation in this
   step, capped at T_f, with every other force known; it never reverses the rate and holds
   a stuck joint exactly. */
static RJ__FORCE_INLINE void rj__stage_friction(const rj_model *m, rj_state *s, const rj__frames *f,
                                                int held)
{
    int j;
    for (j = 0; j < m->nj; j++)
        if (m->jdef[j].friction > 0)
            rj__friction_joint(m, s, f, j, held && m->npair);
}

/* Gravity's potential -sum m g . x at the nodes x, y (rigid bodies' own links from their
   nodes' positions too). */
static RJ__NOINLINE double rj__gravity_potential(const rj_model *m, const double *x,
                                                 const double *y)
{
    const double gx = m->solver.gravity[0], gy = m->solver.gravity[1];
    double sum = 0;
    int i;
    /* every node's mass (a body's own nodes carry none; the nodes its pins carry do) */
    for (i = 0; i < m->nn; i++)
        sum += m->mass[i] * (gx * x[i] + gy * y[i]);
    for (i = 0; i < m->ncl; i++) {
        double mx, my;
        if (m->cl_first[i] == m->cl_first[i + 1])
            continue;
        rj__cl_own_moment(m, i, x, y, &mx, &my);
        sum += gx * mx + gy * my;
    }
    return -sum;
}

/* Stage 4a: v^{n+1/2} and x^{n+1} of the nodes the joints acted on (the beam pass advanced
   the rest); the kinetic energy at n as v^{n-1/2}.v^{n+1/2}, from v^{-1/2} = 2 v(0) -
   v^{1/2} at the start. */
static RJ__FORCE_INLINE void rj__update_joint_nodes(const rj_model *m, rj_state *s,
                                                    const rj__frames *f, const rj__adv *adv,
                                                    rj__sums *e)
{
    const double *km = m->kmass, *kj = m->krot;
    const double *vx = f->vx, *vy = f->vy, *w = f->w;
    const double *nvx = f->nvx, *nvy = f->nvy, *nw = f->nw;
    double ke;
    int i;
    for (i = 0; i < m->ndn; i++) {
        const int n = m->dnode[i];
        rj__advance_node(adv, n, s->fx[n], s->fy[n], s->mz[n], f->x, f->y, f->phi);
    }
    ke = f->en ? rj__sum8(s->kn, m->nn) : 0.0;
    if (f->first) {
        ke = 0;
        for (i = 0; i < m->nn; i++)
            ke += km[i] * ((2 * vx[i] - nvx[i]) * nvx[i] + (2 * vy[i] - nvy[i]) * nvy[i]) +
                  kj[i] * (2 * w[i] - nw[i]) * nw[i];
    }
    e->kinetic = ke;
}

/* Stage 4b: groups of nodes that move together (a pin shared by links) take their summed
   force on their summed mass. */
static RJ__FORCE_INLINE void rj__update_groups(const rj_model *m, rj_state *s, const rj__frames *f,
                                               rj__sums *e, double *fin)
{
    const double *vx = f->vx, *vy = f->vy;
    int gi;
    for (gi = 0; gi < m->ng; gi++) {
        const int f0 = m->grp_first[gi], f1 = m->grp_first[gi + 1], r = m->grp_node[f0];
        double sx = 0, sy = 0, msum = 0, ux, uy;
        int q;
        for (q = f0; q < f1; q++) {
            sx += s->fx[m->grp_node[q]];
            sy += s->fy[m->grp_node[q]];
            msum += m->mass[m->grp_node[q]];
        }
        ux = vx[r] + f->kick * sx * m->grp_inv[gi];
        uy = vy[r] + f->kick * sy * m->grp_inv[gi];
        if (m->has_gravity && m->grp_inv[gi] > 0) {
            ux += f->kick * m->solver.gravity[0];
            uy += f->kick * m->solver.gravity[1];
        }
        if (m->grp_inv[gi] > 0)
            e->kinetic += f->first ? msum * ((2 * vx[r] - ux) * ux + (2 * vy[r] - uy) * uy)
                                   : msum * (vx[r] * ux + vy[r] * uy);
        for (q = f0; q < f1; q++) {
            const int n = m->grp_node[q];
            f->nvx[n] = ux;
            f->nvy[n] = uy;
            f->nx[n] = f->x[n] + f->dt * ux;
            f->ny[n] = f->y[n] + f->dt * uy;
            *fin += f->nx[n] + f->ny[n];
        }
    }
}

/* Gravity on a rigid body of a mixed scene: M g at its centre of mass (the link's rod and
   tip mass, and the nodes of other links its pins carry), a moment about its anchor when
   the anchor is a pin rather than the centre. */
static void rj__cl_gravity(const rj_model *m, int c, const double *oc, const double *x,
                           const double *y, double *Fx, double *Fy, double *T)
{
    const int n0 = m->link_first[c], nt = m->link_first[c + 1] - 1;
    const double gx = m->solver.gravity[0], gy = m->solver.gravity[1];
    double mx, my;
    int k;
    rj__cl_own_moment(m, c, x, y, &mx, &my);
    for (k = m->cl_first[c]; k < m->cl_first[c + 1]; k++) {
        const int n = m->cl_node[k];
        if (n >= n0 && n <= nt)
            continue;
        mx += m->mass[n] * x[n];
        my += m->mass[n] * y[n];
    }
    /* M g, and its moment about the anchor: sum m (r - anchor) x g */
    *Fx += m->cl_M[c] * gx;
    *Fy += m->cl_M[c] * gy;
    *T += (mx - m->cl_M[c] * oc[0]) * gy - (my - m->cl_M[c] * oc[1]) * gx;
}

/* Stage 4c: rigid bodies in mixed scenes: anchor velocity and rate at n + 1/2. */
static RJ__FORCE_INLINE void rj__update_bodies(const rj_model *m, rj_state *s, const rj__frames *f,
                                               rj__sums *e)
{
    int gi;
    for (gi = 0; gi < m->ncl; gi++) {
        const double *oc = RJ__FCL(m, f->old, gi);
        double *nc = RJ__FCL(m, f->next, gi), Fx, Fy, T;
        int q;
        if (m->cl_first[gi] == m->cl_first[gi + 1])
            continue;
        memcpy(nc, oc, 6 * sizeof(double));
        if (m->cl_fix[gi] == 2)
            continue;
        rj__cl_load(m, gi, oc, f->x, f->y, s->fx, s->fy, s->mz, &Fx, &Fy, &T);
        if (m->has_gravity)
            rj__cl_gravity(m, gi, oc, f->x, f->y, &Fx, &Fy, &T);
        if (m->cl_fix[gi] == 0) {
            nc[2] = oc[2] + f->kick * Fx / m->cl_M[gi];
            nc[3] = oc[3] + f->kick * Fy / m->cl_M[gi];
        }
        nc[4] = oc[4] + f->kick * T / m->cl_I[gi];
        e->kinetic += rj__cl_ke2(m, gi, oc, nc, f->first);
        for (q = m->cl_first[gi]; q < m->cl_first[gi + 1]; q++)
            if (RJ__CL_RIGID(m, m->cl_node[q]))
                f->nw[m->cl_node[q]] = nc[4];
    }
}

/* Stage 4, the update: velocities at n + 1/2 and positions at n + 1 (grouped nodes and
   nodes a velocity-level method changes are redone after). */
/* The pin nodes' rates at n - 1/2 and n + 1/2 and their angles, for the rotors' stage
   (given apart from the step's frames, whose record keeps its registers). */
typedef struct rj__pins {
    const double *w, *phi;
    double *nw, *nphi;
    double dt;
    int first;
} rj__pins;

/* What the rotors' stage returns: the kinetic energy's change in its form, and the sum
   of the angles it moved (finite while they are). */
typedef struct rj__rotor_sums {
    double ke, fin;
} rj__rotor_sums;

/* One rotor's share of its joint's pin rotations: the rates the step gave the two pin nodes
   (each on its own rotary inertia) moved to those of the 2 x 2 mass that the rotor's
   reflected inertia Jr couples, diag(I_I, I_J) + Jr [1 -1; -1 1] (Sherman-Morrison: the
   relative change shrinks by 1 + Jr (1/I_I + 1/I_J), the momentum kept), their angles
   after, and the kinetic energy's change in its form (sum of kn, the rotor's Jr w w'). */
static void rj__rotor_pins(const rj_model *m, const rj__pins *p, const rj__joint *J,
                           rj__rotor_sums *out)
{
    const int nI = J->nI, nJ = J->nJ, first = p->first;
    const double riI = nI >= 0 ? m->rinv[nI] : 0.0, riJ = m->rinv[nJ];
    const double *w = p->w, *kj = m->krot;
    const double wI = nI >= 0 ? w[nI] : 0.0, oI = nI >= 0 ? p->nw[nI] : 0.0, oJ = p->nw[nJ];
    const double share = J->rotor * ((oJ - w[nJ]) - (oI - wI)) /
                         (1.0 + J->rotor * (riI + riJ));
    const double uI = oI + share * riI, uJ = oJ - share * riJ;
    const double rel_m = w[nJ] - wI, rel_p = uJ - uI;
    /* each node's kn, before and after, and the rotor's */
    out->ke += first ? kj[nJ] * ((2 * w[nJ] - uJ) * uJ - (2 * w[nJ] - oJ) * oJ)
                     : kj[nJ] * w[nJ] * (uJ - oJ);
    out->ke += J->rotor * (first ? (2 * rel_m - rel_p) * rel_p : rel_m * rel_p);
    p->nw[nJ] = uJ;
    p->nphi[nJ] = p->phi[nJ] + p->dt * uJ;
    out->fin += p->nphi[nJ];
    if (nI < 0)
        return;
    out->ke += first ? kj[nI] * ((2 * wI - uI) * uI - (2 * wI - oI) * oI)
                     : kj[nI] * wI * (uI - oI);
    p->nw[nI] = uI;
    p->nphi[nI] = p->phi[nI] + p->dt * uI;
    out->fin += p->nphi[nI];
}

/* Stage 4c of scenes with rotors: every rotor's joint pins (rj__rotor_pins). Apart (not
   inlined): a scene without rotors pays one test. */
static RJ__NOINLINE rj__rotor_sums rj__stage_rotors(const rj_model *m, rj__pins p)
{
    rj__rotor_sums out;
    int j;
    out.ke = 0;
    out.fin = 0;
    for (j = 0; j < m->nj; j++)
        if (m->jnt[j].rotor > 0)
            rj__rotor_pins(m, &p, &m->jnt[j], &out);
    return out;
}

/* The rotors' stage on the step's frames. */
static RJ__FORCE_INLINE void rj__update_rotors(const rj_model *m, const rj__frames *f,
                                               rj__sums *e, double *fin)
{
    rj__pins p;
    rj__rotor_sums out;
    p.w = f->w;
    p.phi = f->phi;
    p.nw = f->nw;
    p.nphi = f->nphi;
    p.dt = f->dt;
    p.first = f->first;
    out = rj__stage_rotors(m, p);
    *fin += out.fin;
    if (f->en || f->first)
        e->kinetic += out.ke;
}

static RJ__FORCE_INLINE void rj__stage_update(const rj_model *m, rj_state *s, const rj__frames *f,
                                              const rj__adv *adv, rj__sums *e, double *fin)
{
    rj__update_joint_nodes(m, s, f, adv, e);
    if (m->nrotor)
        rj__update_rotors(m, f, e, fin);
    rj__update_groups(m, s, f, e, fin);
    rj__update_bodies(m, s, f, e);
    e->kinetic *= 0.5;
}

/* Coupling c's stretch rate at the end of the step under the forces so far, its joints
   seen through their pins (rj__joint_terms), and their geometries at n. */
static double rj__coupling_rate_pred(const rj_model *m, const rj_state *s, const rj__frames *f,
                                     const rj_coupling_def *c, rj__jgeo *ga, rj__jgeo *gb)
{
    double rate_a, rate_b, give;
    rj__joint_terms(m, s, f, c->joint_a, 1, ga, &rate_a, &give);
    rj__joint_terms(m, s, f, c->joint_b, 1, gb, &rate_b, &give);
    return rate_b - c->ratio * rate_a;
}

/* The force entries a torque on joint j writes (rj__apply_torque): 0 .. 3 its nodes
   I, K, J, L (-1: none), saved into or put back from keep (12 doubles). */
static void rj__torque_entries(const rj__joint *J, rj_state *s, double *keep, int put)
{
    const int nodes[4] = { J->nI, J->nK, J->nJ, J->nL };
    int k;
    for (k = 0; k < 4; k++) {
        double *at[3];
        int q;
        if (nodes[k] < 0)
            continue;
        at[0] = &s->fx[nodes[k]];
        at[1] = &s->fy[nodes[k]];
        at[2] = &s->mz[nodes[k]];
        for (q = 0; q < 3; q++) {
            if (put)
                *at[q] = keep[3 * k + q];
            else
                keep[3 * k + q] = *at[q];
        }
    }
}

/* An exact cable loop with a joint between two rigid bodies, as a torque pair after the
   latches (rj__stage_pair_latches): tau on joint b and -ratio tau on joint a, aimed at
   the stretch's rate -e / dt that closes it at n + 1. Its give is probed with a unit
   torque pair and the force entries put back bit for bit: through the pin it is linear
   but for the pin's turn over the step, whose share the next step's aim takes up.
   Booked with the limits' torques, as the rows' couplings are. */
static void rj__pair_coupling(const rj_model *m, rj_state *s, const rj__frames *f, int k)
{
    const rj_coupling_def *c = &m->cp[k];
    const rj__joint *Ja = &m->jnt[c->joint_a], *Jb = &m->jnt[c->joint_b];
    const double *old_joints = RJ__FJ(m, f->old, 0);
    const double e_n = rj__coupling_stretch(
        m, c, old_joints[(size_t) RJ__JD_COUNT * c->joint_a + RJ__JD_THETA],
        old_joints[(size_t) RJ__JD_COUNT * c->joint_b + RJ__JD_THETA]);
    double keep[24], rate0, rate1, tau;
    rj__jgeo ga, gb;
    rate0 = rj__coupling_rate_pred(m, s, f, c, &ga, &gb);
    rj__torque_entries(Ja, s, keep, 0);
    rj__torque_entries(Jb, s, keep + 12, 0);
    rj__apply_torque(Jb, &gb, 1.0, s->fx, s->fy, s->mz);
    rj__apply_torque(Ja, &ga, -c->ratio, s->fx, s->fy, s->mz);
    rate1 = rj__coupling_rate_pred(m, s, f, c, &ga, &gb);
    rj__torque_entries(Jb, s, keep + 12, 1);
    rj__torque_entries(Ja, s, keep, 1);
    if (!(rate1 != rate0))
        return;
    tau = (-e_n / f->dt - rate0) / (rate1 - rate0);
    rj__apply_torque(Jb, &gb, tau, s->fx, s->fy, s->mz);
    rj__apply_torque(Ja, &ga, -c->ratio * tau, s->fx, s->fy, s->mz);
    RJ__FJ(m, f->next, c->joint_b)[RJ__JD_TQ0 + RJ_TORQUE_LIMIT] += tau;
    RJ__FJ(m, f->next, c->joint_a)[RJ__JD_TQ0 + RJ_TORQUE_LIMIT] -= c->ratio * tau;
}

/* Latches and plastic limits on the joints between two rigid bodies of a mixed scene, as
   torques after friction (stage 3): the jump of stage 5 sees neither the pin between the
   bodies nor the flexible links they carry, and tried there it lost 1.5 J of 3.9 J
   unbooked. The torque brings the pinned pair's rate (rj__pair_terms) to its target
   within the step: p / dt, which puts a lock or a forced limit back on its angle at
   n + 1; for a momentum contact 0, or -e times the rate it came with at its first step
   (a bounce, which the rate pointing out then releases); a contact only pushes. As a force
   in the step, its work is booked with the limit's torque, and the flexible links
   pinned to the bodies take its effect with the next step, as from any force. A
   prescribed profile there is the same torque aimed at the profile's rate, booked as
   the drive's. */
static void rj__stage_pair_latches(const rj_model *m, rj_state *s, const rj__frames *f)
{
    int j;
    for (j = 0; j < m->nj; j++) {
        const rj_joint_def *d = &m->jdef[j];
        const rj__joint *J = &m->jnt[j];
        const int flag = f->new_flags[j];
        const double p = s->jsc[8 * j + 5]; /* the element's penetration */
        rj__jgeo g;
        const int driven = rj__prescribed(J);
        double ratep, give, target, tau;
        if (!J->pair || (!driven && (flag == RJ_FREE || !rj__velocity_method(d->method))))
            continue;
        rj__joint_terms(m, s, f, j, 1, &g, &ratep, &give);
        if (driven) {
            const double run = RJ__FJ(m, f->old, j)[RJ__JD_THETA];
            tau = (rj__prescribed_rate(m, s, j, run, f->t, f->dt) - ratep) / give;
            rj__apply_torque(J, &g, tau, s->fx, s->fy, s->mz);
            RJ__FJ(m, f->next, j)[RJ__JD_TQ0 + RJ_TORQUE_DRIVE] = tau;
            continue;
        }
        target = flag == RJ_LOCKED || d->method == RJ_METHOD_FORCED ? p / f->dt : 0.0;
        if (flag != RJ_LOCKED && d->method == RJ_METHOD_MOMENTUM &&
            f->old_flags[j] == RJ_FREE)
            target = -d->restitution * ratep;
        tau = (target - ratep) / give;
        if ((flag == RJ_AT_FORWARD && tau > 0) || (flag == RJ_AT_REVERSE && tau < 0))
            tau = 0;
        rj__apply_torque(J, &g, tau, s->fx, s->fy, s->mz);
        RJ__FJ(m, f->next, j)[RJ__JD_TQ0 + RJ_TORQUE_LIMIT] += tau;
    }
    for (j = 0; j < m->ncp; j++)
        if (rj__coupling_on_pair(m, j))
            rj__pair_coupling(m, s, f, j);
}

/* A velocity-level joint released under RC13 (rate pointing out at the step's start) that
   the step's kick turns back in while still past its limit is in contact again now, not one
   step later: that lag let the bodies behind ratchet it through the stop (stress suite:
   48 deg in a 1000:1 chain). Returns the flag. */
static RJ__FORCE_INLINE int rj__recontact(const rj__joint *J, const double *old_joint, double ratep,
                                          int *new_flag, double *kept)
{
    const double run = old_joint[RJ__JD_THETA];
    if (run <= J->rev && ratep < 0) {
        *new_flag = RJ_AT_REVERSE;
        kept[5] = J->rev - run;
    } else if (run >= J->fwd && ratep > 0) {
        *new_flag = RJ_AT_FORWARD;
        kept[5] = J->fwd - run;
    }
    return *new_flag;
}

/* After a jump, the joint's nodes move with the new rates (rj__spin changes nK and nL only
   with a chord reference); a rigid body's node carries its whole body. */
static RJ__FORCE_INLINE void rj__jump_nodes(const rj_model *m, const rj__frames *f,
                                            const rj__joint *J, double *fin)
{
    const int nodes[4] = { J->nI, J->chord ? J->nK : -1, J->nJ, J->chord ? J->nL : -1 };
    int k;
    for (k = 0; k < 4; k++) {
        const int n = nodes[k];
        if (n < 0)
            continue;
        f->nx[n] = f->x[n] + f->dt * f->nvx[n];
        f->ny[n] = f->y[n] + f->dt * f->nvy[n];
        f->nphi[n] = f->phi[n] + f->dt * f->nw[n];
        *fin += (f->nx[n] + f->ny[n]) + f->nphi[n];
        if (m->ncl && RJ__CL_RIGID(m, n)) {
            const int c = m->node_cl[n];
            int q;
            RJ__FCL(m, f->next, c)[4] = f->nw[n];
            for (q = m->cl_first[c]; q < m->cl_first[c + 1]; q++)
                if (RJ__CL_RIGID(m, m->cl_node[q]))
                    f->nw[m->cl_node[q]] = f->nw[n];
        }
    }
}

/* The jump of one velocity-level joint turning into its limit (momentum: Eqs 23-24 with
   e; energy: Eq 26; forced, or any while locked: plastic). In the kinetic energy's form
   1/2 v^{n-1/2}.v^{n+1/2} a jump from w_b to w_b' loses 1/2 I_b (w_b^{n-1/2} + w_b')
   (w_b - w_b') per body: this step takes the first half, the next the second (pending).
   A latch that only cancels the step's small relative rate loses almost nothing, as a
   workless constraint should. Returns the rate after. */
static RJ__FORCE_INLINE double rj__joint_jump(const rj_model *m, const rj__frames *f, int j,
                                              int flag, const rj__jgeo *g, double w1, double w2,
                                              rj__sums *e, double *fin)
{
    const rj_joint_def *d = &m->jdef[j];
    const rj__joint *J = &m->jnt[j];
    double *new_joint = RJ__FJ(m, f->next, j);
    const double o1 = w1, o2 = w2;
    double m1 = 0, m2 = 0, loss = 0;
    /* the bodies' rates at n - 1/2 */
    rj__joint_rate(J, g, f->vx, f->vy, f->w, &m1, &m2);
    if (d->method == RJ_METHOD_MOMENTUM)
        rj_momentum_balance(J->I1, J->I2, flag == RJ_LOCKED ? 0.0 : d->restitution, &w1, &w2);
    else if (d->method == RJ_METHOD_ENERGY && flag != RJ_LOCKED)
        rj_energy_balance(J->I1, J->I2, &w1, &w2);
    else
        rj_momentum_balance(J->I1, J->I2, 0.0, &w1, &w2);
    if (!rj__finite(J->I1))
        w1 = o1;
    if (!rj__finite(J->I2))
        w2 = o2;
    if (rj__finite(J->I1)) {
        loss += 0.5 * J->I1 * m1 * (o1 - w1);
        e->pending += 0.5 * J->I1 * w1 * (o1 - w1);
    }
    if (rj__finite(J->I2)) {
        loss += 0.5 * J->I2 * m2 * (o2 - w2);
        e->pending += 0.5 * J->I2 * w2 * (o2 - w2);
    }
    /* a rotor spins with the relative rate: its share of the jump */
    loss += 0.5 * J->rotor * (m2 - m1) * ((o2 - o1) - (w2 - w1));
    e->pending += 0.5 * J->rotor * (w2 - w1) * ((o2 - o1) - (w2 - w1));
    /* the latch's angular impulse on body 2 (body 1 takes the opposite) */
    new_joint[RJ__JD_IMPULSE] = (rj__finite(J->I2) ? J->I2 * (w2 - o2) : -J->I1 * (w1 - o1)) +
                                J->rotor * ((w2 - w1) - (o2 - o1));
    rj__spin(J, g, w1 - o1, w2 - o2, f->nvx, f->nvy, f->nw);
    rj__jump_nodes(m, f, J, fin);
    e->lost_limit += loss;
    e->kinetic -= loss;
    return rj__joint_rate(J, g, f->nvx, f->nvy, f->nw, NULL, NULL);
}

/* Joint j's rate from node rates vx, vy, w, in the step's kept geometry. */
static double rj__kept_rate(const rj_model *m, const rj_state *s, int j, const double *vx,
                            const double *vy, const double *w)
{
    rj__jgeo g;
    rj__kept_geo(s->jsc + 8 * j, &g);
    return rj__joint_rate(&m->jnt[j], &g, vx, vy, w, NULL, NULL);
}

/* Joint j's rate at n + 1/2 from the nodes' now. */
static double rj__rate_now(const rj_model *m, const rj_state *s, const rj__frames *f, int j)
{
    return rj__kept_rate(m, s, j, f->nvx, f->nvy, f->nw);
}

/* The rate change of joint J per unit torque impulse on its pins, and each body's share:
   1 / I over 1 + rotor c0 (c0 = 1/I1 + 1/I2; a rotor's reflected inertia acts on the
   relative rotation; ground or a fixed body, I infinite, takes none). */
static double rj__joint_give(const rj__joint *J, double *give1, double *give2)
{
    const double c1 = rj__finite(J->I1) ? 1.0 / J->I1 : 0.0;
    const double c2 = rj__finite(J->I2) ? 1.0 / J->I2 : 0.0;
    const double share = 1.0 / (1.0 + J->rotor * (c1 + c2));
    if (give1)
        *give1 = c1 * share;
    if (give2)
        *give2 = c2 * share;
    return (c1 + c2) * share;
}

/* Which body turns with side (1 or 2) of joint J: its pin node, or the rigid body of a
   mixed scene whose own node it is (-2 less the body's link); -1 for ground. */
static int rj__side_body(const rj_model *m, const rj__joint *J, int side)
{
    const int n = side == 2 ? J->nJ : J->nI;
    if (n < 0)
        return -1;
    if (m->ncl && RJ__CL_RIGID(m, n))
        return -2 - m->node_cl[n];
    return n;
}

/* Joint q's rate change per unit torque impulse on joint p: each side of p moves its
   body by its give, and each side of q that turns with the same body sees it. */
static double rj__joint_cross(const rj_model *m, int p, int q)
{
    const rj__joint *Jp = &m->jnt[p], *Jq = &m->jnt[q];
    double give[3], sum = 0;
    int a, b;
    rj__joint_give(Jp, &give[1], &give[2]);
    for (a = 1; a <= 2; a++)
        for (b = 1; b <= 2; b++) {
            const int body = rj__side_body(m, Jp, a);
            if (body == -1 || body != rj__side_body(m, Jq, b))
                continue;
            sum += (a == b ? 1.0 : -1.0) * give[a];
        }
    return sum;
}

/* A torque impulse P on joint j's pins (P on body 2, -P on body 1): the bodies' rates move
   by their gives (rj__joint_give), the nodes with them. The momentum I1 w1 + I2 w2 is
   kept, as a latch's jump keeps it (rj__joint_jump). */
static void rj__joint_impulse(const rj_model *m, const rj_state *s, const rj__frames *f, int j,
                              double P, double *fin)
{
    const rj__joint *J = &m->jnt[j];
    double give1, give2;
    rj__jgeo g;
    rj__kept_geo(s->jsc + 8 * j, &g);
    rj__joint_give(J, &give1, &give2);
    rj__spin(J, &g, -P * give1, P * give2, f->nvx, f->nvy, f->nw);
    rj__jump_nodes(m, f, J, fin);
}

/* Row's impulse P: P coef on each of its joints; the row keeps the sum. */
static void rj__row_impulse(const rj_model *m, const rj_state *s, const rj__frames *f,
                            const rj__rows *R, rj__row *row, double P, double *fin)
{
    int k;
    for (k = 0; k < row->count; k++)
        rj__joint_impulse(m, s, f, R->term[row->first + k].joint,
                          R->term[row->first + k].coef * P, fin);
    row->lam += P;
}

/* A row's rate J v at n + 1/2 now, and its give J M^-1 J^T (rj__joint_cross). */
static double rj__row_rate(const rj_model *m, const rj_state *s, const rj__frames *f,
                           const rj__rows *R, const rj__row *row, double *give)
{
    const rj__term *t = R->term + row->first;
    double rate = 0, sum = 0;
    int k, q;
    for (k = 0; k < row->count; k++) {
        rate += t[k].coef * rj__rate_now(m, s, f, t[k].joint);
        for (q = 0; q < row->count && give; q++)
            sum += t[k].coef * t[q].coef * rj__joint_cross(m, t[k].joint, t[q].joint);
    }
    if (give)
        *give = sum;
    return rate;
}

/* Node space's rows system W lam = target - J v, W_ab = sum over the rows' joints p, q
   of coef_p coef_q times q's rate change per unit impulse on p (rj__joint_cross: the
   sides they share); in s->rsys (rows k: k x k, its factor,
   k, k). A singular W (rows that repeat each other) is regularised by 1e-12 of its
   largest diagonal, a least-squares answer. */
static void rj__rows_direct(const rj_model *m, const rj_state *s, const rj__frames *f,
                            rj__rows *R, double *fin)
{
    const int k = R->count;
    double *S = s->rsys, *SL = S + (size_t) k * k, *rhs = SL + (size_t) k * k, *lam = rhs + k;
    double largest = 0;
    int a, b, p, q;
    for (a = 0; a < k; a++) {
        const rj__row *ra = &R->row[a];
        for (b = 0; b < k; b++) {
            const rj__row *rb = &R->row[b];
            double sum = 0;
            for (p = 0; p < ra->count; p++)
                for (q = 0; q < rb->count; q++) {
                    const rj__term *tp = &R->term[ra->first + p], *tq = &R->term[rb->first + q];
                    sum += tp->coef * tq->coef * rj__joint_cross(m, tp->joint, tq->joint);
                }
            S[(size_t) a * k + b] = sum;
        }
        rhs[a] = ra->target - rj__row_rate(m, s, f, R, ra, NULL);
        largest = fmax(largest, S[(size_t) a * k + a]);
    }
    if (rj__chol(k, S, SL)) {
        for (a = 0; a < k; a++)
            S[(size_t) a * k + a] += 1e-12 * largest;
        if (rj__chol(k, S, SL))
            return;
    }
    rj__chol_solve(k, SL, rhs, lam);
    for (a = 0; a < k; a++)
        rj__row_impulse(m, s, f, R, &R->row[a], lam[a], fin);
}

/* One sweep over the rows: each one's impulse to its target, its terms' joints in turn,
   where it misses by more than 1e-15 rad at n + 1 (its rate's miss times dt). Returns
   how many took one. */
static int rj__rows_sweep(const rj_model *m, const rj_state *s, const rj__frames *f,
                          rj__rows *R, double *fin)
{
    int a, moved = 0;
    for (a = 0; a < R->count; a++) {
        rj__row *row = &R->row[a];
        double give;
        const double rate = rj__row_rate(m, s, f, R, row, &give);
        if (!(fabs(row->target - rate) * f->dt > 1e-15))
            continue;
        rj__row_impulse(m, s, f, R, row, (row->target - rate) / give, fin);
        moved++;
    }
    return moved;
}

/* The node-space rows' rates before any impulse, for the first step's work. */
static void rj__rows_before(const rj_model *m, const rj_state *s, const rj__frames *f,
                            rj__rows *R)
{
    int a;
    for (a = 0; a < R->count; a++)
        R->row[a].before = rj__row_rate(m, s, f, R, &R->row[a], NULL);
}

/* What the rows' stage returns: the work of the prescribed joints' impulses, this step's
   and the next's; the exact couplings' loss, this step's and the next's; the sum of the
   positions they moved (finite while they are). */
typedef struct rj__rows_sums {
    double drive, drive_pending, loss, pending, fin;
} rj__rows_sums;

/* A row's impulse in the accounts and the joints' records: -1/2 lam J v^{n-1/2} now and
   -1/2 lam J v^{n+1/2} with the next step, as the drive's work (a prescribed joint: its
   torque) or the limits' loss (an exact coupling: its torque in the spring columns). */
static void rj__row_account(const rj_model *m, const rj_state *s, const rj__frames *f,
                            const rj__rows *R, const rj__row *row, rj__rows_sums *out)
{
    double back = 0, after = 0;
    int k;
    for (k = 0; k < row->count; k++) {
        const rj__term *t = &R->term[row->first + k];
        const double rate = rj__rate_now(m, s, f, t->joint);
        double *record = RJ__FJ(m, f->next, t->joint);
        /* from the nodes' rates at n - 1/2 (at the first step, at 0) */
        back += t->coef * rj__kept_rate(m, s, t->joint, f->vx, f->vy, f->w);
        after += t->coef * rate;
        record[RJ__JD_RATE] = rate;
        if (row->kind == RJ__ROW_PRESCRIBED)
            record[RJ__JD_TQ0 + RJ_TORQUE_DRIVE] = row->lam / f->kick;
        else
            record[RJ__JD_TQ0 + RJ_TORQUE_SPRING] += t->coef * row->lam / f->kick;
    }
    /* the first step's J v^{-1/2}: 2 J v(0) less the rate before the impulses */
    if (f->first)
        back = 2 * back - row->before;
    if (row->kind == RJ__ROW_PRESCRIBED) {
        out->drive += 0.5 * row->lam * back;
        out->drive_pending += 0.5 * row->lam * after;
    } else {
        out->loss -= 0.5 * row->lam * back;
        out->pending -= 0.5 * row->lam * after;
    }
}
/* Stage 5c of scenes with prescribed joints or exact couplings: their rows (src/rows.h)
   in node space, before the latches: the prescribed joints land on their profiles, the
   couplings' e at 0, at n + 1. Several rows are solved together (rj__rows_direct), then
   swept one by one until none misses its target by more than 1e-15 rad (at most 100
   sweeps; after the solve the first finds round-off). Apart (not inlined; the frames' record by value and the
   sums returned: a pointer to the record would keep it out of registers in the whole
   step), so a scene without rows pays one test. */
static RJ__NOINLINE rj__rows_sums rj__stage_rows(const rj_model *m, const rj_state *s,
                                                 rj__frames f)
{
    rj__rows_sums out;
    rj__rows R;
    int j, sweep;
    memset(&out, 0, sizeof out);
    R.row = s->rows;
    R.term = s->terms;
    R.count = R.terms = 0;
    /* a pair's profile is a torque (rj__stage_pair_latches) */
    for (j = 0; j < m->nj; j++)
        if (rj__prescribed(&m->jnt[j]) && !m->jnt[j].pair)
            rj__row_prescribed(m, s, &R, j, j, RJ__FJ(m, f.old, j)[RJ__JD_THETA], f.t, f.dt);
    rj__rows_couplings(m, &R, RJ__FJ(m, f.old, 0) + RJ__JD_THETA, RJ__JD_COUNT, NULL, f.dt);
    rj__rows_before(m, s, &f, &R);
    if (R.count > 1)
        rj__rows_direct(m, s, &f, &R, &out.fin);
    for (sweep = 0; sweep < 100; sweep++)
        if (!rj__rows_sweep(m, s, &f, &R, &out.fin))
            break;
    for (j = 0; j < R.count; j++)
        rj__row_account(m, s, &f, &R, &R.row[j], &out);
    return out;
}

/* The rows' stage on the step's frames and sums. */
static RJ__FORCE_INLINE void rj__update_rows(const rj_model *m, const rj_state *s,
                                             const rj__frames *f, rj__sums *e, double *fin)
{
    const rj__rows_sums out = rj__stage_rows(m, s, *f);
    e->drive += out.drive;
    e->kinetic += out.drive;
    e->drive_pending += out.drive_pending;
    e->lost_limit += out.loss;
    e->kinetic -= out.loss;
    e->pending += out.pending;
    *fin += out.fin;
}

/* Stage 5, the limits' velocity-level responses, and the work of the joint torques. */
static RJ__FORCE_INLINE void rj__stage_velocity_limits(const rj_model *m, rj_state *s,
                                                       const rj__frames *f, rj__sums *e,
                                                       double *fin, int held)
{
    int j;
    if (m->nmotion)
        rj__update_rows(m, s, f, e, fin);
    for (j = 0; j < m->nj; j++) {
        const rj_joint_def *d = &m->jdef[j];
        const rj__joint *J = &m->jnt[j];
        double *new_joint = RJ__FJ(m, f->next, j), *kept = s->jsc + 8 * j;
        const double *old_joint = RJ__FJ(m, f->old, j);
        rj__jgeo g;
        double w1, w2, ratep;
        int flag = f->new_flags[j];
        rj__kept_geo(kept, &g);
        ratep = rj__joint_rate(J, &g, f->nvx, f->nvy, f->nw, &w1, &w2);
        /* a pair's latches acted as torques (rj__stage_pair_latches) */
        if (flag == RJ_FREE && rj__velocity_method(d->method) && !(held && J->pair))
            flag = rj__recontact(J, old_joint, ratep, &f->new_flags[j], kept);
        if (flag != RJ_FREE && rj__velocity_method(d->method) && !(held && J->pair) &&
            rj__into_limit(flag, ratep))
            ratep = rj__joint_jump(m, f, j, flag, &g, w1, w2, e, fin);
        rj__element_work(old_joint, new_joint, kept[4], f->dt, &e->lost_damping, &e->lost_friction,
                         &e->lost_limit);
        /* a prescribed joint's work is its row's, but a pair's is its torque's */
        if (J->act && (!rj__prescribed(J) || (held && J->pair)))
            e->drive += rj__drive_work(old_joint, new_joint, kept[4], f->dt);
        new_joint[RJ__JD_RATE] = ratep;
    }
}

/* Stage 6a: rigid bodies' poses at n + 1. */
static RJ__FORCE_INLINE void rj__constrain_bodies(const rj_model *m, const rj__frames *f,
                                                  double *fin)
{
    int gi;
    for (gi = 0; gi < m->ncl; gi++) {
        const double *oc = RJ__FCL(m, f->old, gi);
        double *nc = RJ__FCL(m, f->next, gi);
        if (m->cl_first[gi] == m->cl_first[gi + 1])
            continue;
        nc[0] = oc[0] + f->dt * nc[2];
        nc[1] = oc[1] + f->dt * nc[3];
        nc[5] = oc[5] + f->dt * nc[4];
        *fin += rj__cl_pose(m, gi, nc, f->x, f->y, f->dt, 1, f->nx, f->ny, f->nphi, f->nvx, f->nvy,
                            f->nw);
    }
}

/* The kinetic energy again, with the projected velocities (inextensible links). */
static RJ__FORCE_INLINE double rj__kinetic_again(const rj_model *m, const rj__frames *f)
{
    const double *vx = f->vx, *vy = f->vy, *w = f->w;
    const double *nvx = f->nvx, *nvy = f->nvy, *nw = f->nw;
    const int first = f->first;
    double k0 = 0;
    int i, gi;
    for (i = 0; i < m->nn; i++) {
        const double vmx = first ? 2 * vx[i] - nvx[i] : vx[i],
                     vmy = first ? 2 * vy[i] - nvy[i] : vy[i];
        const double vmw = first ? 2 * w[i] - nw[i] : w[i];
        k0 += m->kmass[i] * (vmx * nvx[i] + vmy * nvy[i]) + m->krot[i] * vmw * nw[i];
    }
    for (gi = 0; gi < m->ng; gi++) {
        const int r0 = m->grp_node[m->grp_first[gi]];
        double msum = 0;
        int q;
        if (!(m->grp_inv[gi] > 0))
            continue;
        for (q = m->grp_first[gi]; q < m->grp_first[gi + 1]; q++)
            msum += m->mass[m->grp_node[q]];
        k0 += msum * ((first ? 2 * vx[r0] - nvx[r0] : vx[r0]) * nvx[r0] +
                      (first ? 2 * vy[r0] - nvy[r0] : vy[r0]) * nvy[r0]);
    }
    for (gi = 0; gi < m->ncl; gi++)
        if (m->cl_first[gi] < m->cl_first[gi + 1] && m->cl_fix[gi] != 2)
            k0 += rj__cl_ke2(m, gi, RJ__FCL(m, f->old, gi), RJ__FCL(m, f->next, gi), first);
    return 0.5 * k0;
}

/* Node k's offset from its body's anchor at n (old: the positions at n and the body's
   old record) or now. The pushes act along the pins' directions at n, as SHAKE's along
   the chords at n: with those of the poses now the balance lost 0.019 J of 9 J in 2 s. */
static void rj__body_point(const rj_model *m, const rj__frames *f, int k, int old, double r[2])
{
    const int c = m->node_cl[k];
    const double *nc = RJ__FCL(m, old ? f->old : f->next, c);
    r[0] = (old ? f->x[k] : f->nx[k]) - nc[0];
    r[1] = (old ? f->y[k] : f->ny[k]) - nc[1];
}

/* The 2 x 2 block of pins p, q through body c: sign ((1/M) I + (1/I) perp(rp) perp(rq)^T),
   rp now, rq at n (perp(r) = (-r_y, r_x)). */
static void rj__body_block(const rj_model *m, int c, const double rp[2], const double rq[2],
                           double sign, double *A, int n2, int p, int q)
{
    const double tinv = m->cl_fix[c] == 0 ? 1.0 / m->cl_M[c] : 0.0;
    const double rinv = m->cl_fix[c] != 2 ? 1.0 / m->cl_I[c] : 0.0;
    A[(size_t) (2 * p) * n2 + 2 * q] += sign * (tinv + rinv * rp[1] * rq[1]);
    A[(size_t) (2 * p) * n2 + 2 * q + 1] += sign * (-rinv * rp[1] * rq[0]);
    A[(size_t) (2 * p + 1) * n2 + 2 * q] += sign * (-rinv * rp[0] * rq[1]);
    A[(size_t) (2 * p + 1) * n2 + 2 * q + 1] += sign * (tinv + rinv * rp[0] * rq[0]);
}

/* Newton's matrix of the pins between bodies: pin p's gap P_a - P_b moves by A_pq
   lambda_q when the push lambda_q acts on q's first body and -lambda_q on its second. */
static void rj__body_pins_matrix(const rj_model *m, const rj__frames *f, double *A)
{
    const int n2 = 2 * m->nbp;
    int p, q, sp, sq;
    for (p = 0; p < n2 * n2; p++)
        A[p] = 0;
    for (p = 0; p < m->nbp; p++)
        for (q = 0; q < m->nbp; q++)
            for (sp = 0; sp < 2; sp++)
                for (sq = 0; sq < 2; sq++) {
                    const int kp = m->bp_node[2 * p + sp], kq = m->bp_node[2 * q + sq];
                    const int c = m->node_cl[kp];
                    double rp[2], rq[2];
                    if (c != m->node_cl[kq] || m->cl_fix[c] == 2)
                        continue;
                    rj__body_point(m, f, kp, 0, rp);
                    rj__body_point(m, f, kq, 1, rq);
                    rj__body_block(m, c, rp, rq, (sp ? -1.0 : 1.0) * (sq ? -1.0 : 1.0), A, n2,
                                   p, q);
                }
}

/* Solves the n x n system A x = b in place (A and b overwritten) by elimination with
   partial pivoting; a pivot below 1e-12 of the largest diagonal is a repeated pin (a
   closed chain of bodies gone flat): its unknown is 0. */
static void rj__body_pins_solve(int n, double *A, double *b, double *x)
{
    double largest = 0;
    int i, j, k;
    for (i = 0; i < n; i++)
        largest = fmax(largest, fabs(A[(size_t) i * n + i]));
    for (k = 0; k < n; k++) {
        int pivot = k;
        for (i = k + 1; i < n; i++)
            if (fabs(A[(size_t) i * n + k]) > fabs(A[(size_t) pivot * n + k]))
                pivot = i;
        for (j = 0; j < n && pivot != k; j++) {
            const double t = A[(size_t) k * n + j];
            A[(size_t) k * n + j] = A[(size_t) pivot * n + j];
            A[(size_t) pivot * n + j] = t;
        }
        if (pivot != k) {
            const double t = b[k];
            b[k] = b[pivot];
            b[pivot] = t;
        }
        if (!(fabs(A[(size_t) k * n + k]) > 1e-12 * largest))
            continue;
        for (i = k + 1; i < n; i++) {
            const double factor = A[(size_t) i * n + k] / A[(size_t) k * n + k];
            for (j = k; j < n; j++)
                A[(size_t) i * n + j] -= factor * A[(size_t) k * n + j];
            b[i] -= factor * b[k];
        }
    }
    for (k = n - 1; k >= 0; k--) {
        double v = b[k];
        if (!(fabs(A[(size_t) k * n + k]) > 1e-12 * largest)) {
            x[k] = 0;
            continue;
        }
        for (j = k + 1; j < n; j++)
            v -= A[(size_t) k * n + j] * x[j];
        x[k] = v / A[(size_t) k * n + k];
    }
}

/* The pushes lambda on the bodies, along the pins at n: each body moves by its share in
   position and, over dt, in velocity (as SHAKE moves a node), then takes its members to
   its pose. */
static void rj__body_pins_move(const rj_model *m, const rj__frames *f, const double *lam,
                               double *imp, double *fin)
{
    int p, side, c;
    for (c = 0; c < 3 * m->ncl; c++)
        imp[c] = 0;
    for (p = 0; p < m->nbp; p++)
        for (side = 0; side < 2; side++) {
            const int k = m->bp_node[2 * p + side];
            const double sign = side ? -1.0 : 1.0, lx = sign * lam[2 * p],
                         ly = sign * lam[2 * p + 1];
            double r[2];
            c = m->node_cl[k];
            rj__body_point(m, f, k, 1, r);
            imp[3 * c] += lx;
            imp[3 * c + 1] += ly;
            imp[3 * c + 2] += r[0] * ly - r[1] * lx;
        }
    for (c = 0; c < m->ncl; c++) {
        double *nc = RJ__FCL(m, f->next, c);
        if (m->cl_fix[c] == 2 || (imp[3 * c] == 0 && imp[3 * c + 1] == 0 && imp[3 * c + 2] == 0))
            continue;
        rj__cl_push(m, c, imp + 3 * c, f->dt, nc);
        *fin += rj__cl_pose(m, c, nc, f->x, f->y, f->dt, 1, f->nx, f->ny, f->nphi, f->nvx,
                            f->nvy, f->nw);
    }
}

/* With loops: the pushes of the pins between bodies summed over a step's passes, 2 a pin
   (x, y), after rj__body_pins' matrices, gaps, pushes and bodies' impulses in its
   scratch (rj_state.bpw). */
static double *rj__body_pins_tot(const rj_model *m, const rj_state *s)
{
    const size_t n2 = 2 * (size_t) m->nbp;
    return s->bpw + 2 * n2 * n2 + 2 * n2 + 3 * (size_t) m->ncl;
}

/* Pins between two rigid bodies of a mixed scene, on positions: Newton on the pins' gaps
   (the matrix of the first pass serves the later ones; at most 20 passes, to 1e-14 of the
   longest body pinned), the bodies' velocities following their corrections, as SHAKE
   does for inextensible links; the sum of what it wrote into *fin. With loops, each
   pin's pushes summed over the passes into tot (rj__body_pins_tot). */
static void rj__body_pins(const rj_model *m, rj_state *s, const rj__frames *f, double *fin)
{
    const int n2 = 2 * m->nbp;
    double *A = s->bpw, *LU = A + (size_t) n2 * n2, *gap = LU + (size_t) n2 * n2;
    double *lam = gap + n2, *imp = lam + n2, *tot = rj__body_pins_tot(m, s), scale = 0;
    int pass, p;
    for (p = 0; p < n2 && m->nloop; p++)
        tot[p] = 0;
    for (p = 0; p < m->nbp; p++) {
        int link, node;
        rj__node_of(m, m->bp_node[2 * p], &link, &node);
        scale = fmax(scale, m->ldef[link].length);
    }
    for (pass = 0; pass < 20; pass++) {
        double worst = 0;
        for (p = 0; p < m->nbp; p++) {
            const int a = m->bp_node[2 * p], b = m->bp_node[2 * p + 1];
            gap[2 * p] = -(f->nx[a] - f->nx[b]);
            gap[2 * p + 1] = -(f->ny[a] - f->ny[b]);
            worst = fmax(worst, fmax(fabs(gap[2 * p]), fabs(gap[2 * p + 1])));
        }
        if (!(worst > 1e-14 * scale))
            break;
        if (pass == 0)
            rj__body_pins_matrix(m, f, A);
        memcpy(LU, A, sizeof(double) * (size_t) n2 * (size_t) n2);
        rj__body_pins_solve(n2, LU, gap, lam);
        rj__body_pins_move(m, f, lam, imp, fin);
        for (p = 0; p < n2 && m->nloop; p++)
            tot[p] += lam[p];
    }
}

/* Node space: the pin node whose balance gives joint j's pin force, body 2's, or body 1's
   (*sign -1) where body 2 is a rigid body of a mixed scene (its own nodes are massless,
   their body takes the pin's force); -1 for the ground. */
static int rj__balance_node(const rj_model *m, int j, double *sign)
{
    const rj__joint *J = &m->jnt[j];
    const int body2 = rj__own_body_node(m, J->nJ);
    *sign = body2 ? -1.0 : 1.0;
    return body2 ? J->nI : J->nJ;
}

/* How node space knows a loop joint's pin force (rj__loop_side). */
enum { RJ__LOOP_NONE, RJ__LOOP_NODE, RJ__LOOP_BODIES, RJ__LOOP_GROUND };

/* Node space: where loop joint j's pin force comes from: between two rigid bodies, the
   pushes of the pin between them (RJ__LOOP_BODIES); pinning a rigid body to the ground,
   the body's balance (RJ__LOOP_GROUND: the body holds its pin to the ground itself);
   else the balance of its pin node *node (rj__balance_node, RJ__LOOP_NODE) less what its
   own link's lengths put on it. None for a chord reference on a flexible pin node (the
   joint's torque acts on that node as forces). */
static int rj__loop_side(const rj_model *m, int j, int *node, double *sign)
{
    const rj__joint *J = &m->jnt[j];
    *node = rj__balance_node(m, j, sign);
    if (*sign < 0 && rj__own_body_node(m, J->nI))
        return RJ__LOOP_BODIES;
    if (*sign < 0 && J->nI < 0)
        return RJ__LOOP_GROUND;
    if (*node < 0 || J->chord)
        return RJ__LOOP_NONE;
    return RJ__LOOP_NODE;
}

/* The pushes of the pins between bodies at node k on its body over the step (summed
   over the passes, rj__body_pins_tot), into out: +lambda on a pin's first node, -lambda
   on its second. */
static void rj__loop_pins_push(const rj_model *m, const rj_state *s, int k, double out[2])
{
    const double *tot = rj__body_pins_tot(m, s);
    int p;
    for (p = 0; p < m->nbp; p++) {
        double sign = 0;
        if (m->bp_node[2 * p] == k)
            sign = 1;
        if (m->bp_node[2 * p + 1] == k)
            sign = -1;
        out[0] += sign * tot[2 * p];
        out[1] += sign * tot[2 * p + 1];
    }
}

/* SHAKE's pushes over the step (rj_state.shp) on node k from its own link's elements, into
   out: the element before it (k its second node) and the one after (k + 1 its second
   node; a link's root is no element's second node, so past its tip none). A push moves
   its owner by 2 / M of it. */
static void rj__loop_shake_push(const rj_model *m, const rj_state *s, int k, double out[2])
{
    out[0] = 2.0 * s->shp[2 * k];
    out[1] = 2.0 * s->shp[2 * k + 1];
    if (k + 1 == m->nn)
        return;
    out[0] -= 2.0 * s->shp[2 * k + 2];
    out[1] -= 2.0 * s->shp[2 * k + 3];
}

/* The projections' pushes over the step on rigid body c of a mixed scene, into out: the
   pins between it and other bodies' on its own nodes (rj__loop_pins_push), and the
   lengths' of the inextensible links whose nodes it carries on those nodes
   (rj__loop_shake_push). */
static void rj__loop_body_push(const rj_model *m, const rj_state *s, int c, double out[2])
{
    int q;
    for (q = m->cl_first[c]; q < m->cl_first[c + 1]; q++) {
        const int k = m->cl_node[q];
        double push[2] = { 0, 0 };
        if (RJ__CL_RIGID(m, k) && m->nbp)
            rj__loop_pins_push(m, s, k, push);
        if (!RJ__CL_RIGID(m, k) && m->any_inext)
            rj__loop_shake_push(m, s, k, push);
        out[0] += push[0];
        out[1] += push[1];
    }
}

/* The projections' forces in the step on the loop joints, the step's record of them
   (rj_state.loop_force), stamped with the step they belong to: on a loop's pin node
   (rj__loop_side), its own link's lengths' (rj__loop_shake_push; none on a flexible
   link); between two rigid bodies, the pin's on body 2 (rj__loop_pins_push); pinning a
   rigid body to the ground, all the body's (rj__loop_body_push). A push moves
   positions, and the velocities over dt: an impulse over dt, a force over the kick too. */
static RJ__NOINLINE void rj__loop_records(const rj_model *m, rj_state *s, const rj__frames *f)
{
    const double per = 1.0 / (f->dt * f->kick);
    int j, node;
    for (j = 0; j < m->nj; j++) {
        double *rec = s->loop_force + 2 * j, sign;
        const int kind = m->jnt[j].loop ? rj__loop_side(m, j, &node, &sign) : RJ__LOOP_NONE;
        rec[0] = rec[1] = 0;
        if (kind == RJ__LOOP_BODIES)
            rj__loop_pins_push(m, s, m->jnt[j].nJ, rec);
        if (kind == RJ__LOOP_GROUND)
            rj__loop_body_push(m, s, m->node_cl[m->jnt[j].nJ], rec);
        if (kind == RJ__LOOP_NODE && m->any_inext)
            rj__loop_shake_push(m, s, node, rec);
        rec[0] *= per;
        rec[1] *= per;
    }
    s->loop_force[2 * m->nj] = (double) (s->steps + 1);
}

/* The joints' rates at n + 1/2 again, from the projected velocities, on the geometry at n
   that stage 5 took them on. The next step books each joint torque's work over this
   step as its torque times this rate: taken before the projection, a motor on a rigid
   body that a pin between bodies turned did 40 % less work in the accounts than on the
   bodies, and the balance stopped the run at its first step. */
static void rj__rates_again(const rj_model *m, const rj_state *s, const rj__frames *f)
{
    int j;
    for (j = 0; j < m->nj; j++) {
        rj__jgeo g;
        rj__kept_geo(s->jsc + 8 * j, &g);
        RJ__FJ(m, f->next, j)[RJ__JD_RATE] =
            rj__joint_rate(&m->jnt[j], &g, f->nvx, f->nvy, f->nw, NULL, NULL);
    }
}

/* Stage 6, constraints on positions: rigid bodies' poses, the pins between bodies;
   inextensible links projected (constraint forces do no work: the velocities follow the
   projected positions, and the kinetic energy is taken again with them). */
static RJ__FORCE_INLINE void rj__stage_constraints(const rj_model *m, rj_state *s,
                                                   const rj__frames *f, rj__sums *e, double *fin,
                                                   int held)
{
    const double *x = f->x, *y = f->y;
    double *nx = f->nx, *ny = f->ny;
    double idt;
    int i;
    rj__constrain_bodies(m, f, fin);
    if (!held || !m->project)
        return;
    idt = 1.0 / f->dt;
    if (m->nbp)
        rj__body_pins(m, s, f, fin);
    if (m->any_inext)
        rj__shake(m, s, x, y, nx, ny);
    if (m->nloop)
        rj__loop_records(m, s, f);
    for (i = 0; i < m->nn; i++) {
        f->nvx[i] = (nx[i] - x[i]) * idt;
        f->nvy[i] = (ny[i] - y[i]) * idt;
        /* velocities from positions: summed too (see rj__cl_pose) */
        *fin += ((nx[i] + ny[i]) + f->nphi[i]) + (f->nvx[i] + f->nvy[i]);
    }
    if (f->en)
        e->kinetic = rj__kinetic_again(m, f);
    rj__rates_again(m, s, f);
}

/* Forced displacement (sec. 3): a joint past its limit, or off its lock, turned back by p;
   a rigid body's node turns its body (positions only). Returns the running angle. */
static RJ__FORCE_INLINE double rj__force_back(const rj_model *m, const rj__frames *f, int j,
                                              const rj__jgeo *g, double run, double *fin)
{
    const rj__joint *J = &m->jnt[j];
    const int flag = f->new_flags[j];
    double target = run, p;
    int k;
    if (flag == RJ_AT_FORWARD && run > J->fwd)
        target = J->fwd;
    else if (flag == RJ_AT_REVERSE && run < J->rev)
        target = J->rev;
    else if (flag == RJ_LOCKED)
        target = RJ__FJ(m, f->next, j)[RJ__JD_LOCK];
    p = target - run;
    if (p == 0)
        return run;
    rj__turn(J, -p * J->w1, p * J->w2, f->nx, f->ny, f->nphi);
    *fin += rj__joint_nodes_sum(J, f->nx, f->ny, f->nphi);
    if (m->ncl) {
        const int nodes[2] = { J->nI, J->nJ };
        for (k = 0; k < 2; k++)
            if (nodes[k] >= 0 && RJ__CL_RIGID(m, nodes[k])) {
                const int c = m->node_cl[nodes[k]];
                double *nc = RJ__FCL(m, f->next, c);
                nc[5] = f->nphi[nodes[k]] - (m->phi0[nodes[k]] - m->cl_th0[3 * c]);
                *fin += rj__cl_pose(m, c, nc, f->x, f->y, f->dt, 0, f->nx, f->ny, f->nphi, f->nvx,
                                    f->nvy, f->nw);
            }
    }
    return J->chord ? target : rj__joint_raw(J, g, f->nphi);
}

/* Stage 7, the joints' running angles at n + 1 (unwrapped in chord mode), and forced
   displacement back to the limit. */
static RJ__FORCE_INLINE rj_result rj__stage_joint_angles(const rj_model *m, rj_state *s,
                                                         const rj__frames *f, double *fin,
                                                         int held)
{
    int j;
    for (j = 0; j < m->nj; j++) {
        const rj_joint_def *d = &m->jdef[j];
        const rj__joint *J = &m->jnt[j];
        double *new_joint = RJ__FJ(m, f->next, j);
        rj__jgeo g;
        double raw, turn, run;
        rj__joint_geo(m, J, f->nx, f->ny, &g);
        raw = rj__joint_raw(J, &g, f->nphi);
        turn = J->chord ? rj__wrap(raw - new_joint[RJ__JD_THETA]) : raw - new_joint[RJ__JD_THETA];
        if (!(fabs(turn) <= 0.5 * RJ__PI))
            return rj__stop(m, s, RJ_ERR_TUNNEL,
                            "t = %.9g s: joint %d turned %.4g rad in one step (more than a quarter "
                            "revolution, pi/2 rad): the step %g s is far too large for its speed%s",
                            f->t, j, turn, f->dt,
                            d->has_forward || d->has_reverse ? "; its limits could be tunnelled"
                                                             : "");
        run = new_joint[RJ__JD_THETA] + turn;
        /* a pair's forced limit acted as a torque (rj__stage_pair_latches) */
        if (d->method == RJ_METHOD_FORCED && f->new_flags[j] != RJ_FREE && !(held && J->pair))
            run = rj__force_back(m, f, j, &g, run, fin);
        new_joint[RJ__JD_THETA] = run;
    }
    return RJ_OK;
}

/* The energy tests' verdict when they fail: the message, naming the test, the fastest
   node (frame; NULL for rigid links in joint coordinates) and the likely causes. */
static rj_result rj__energy_stop(const rj_model *m, rj_state *s, const double *frame, double t,
                                 rj__sums e, double scale, double created)
{
    const double ke = e.kinetic, U = e.strain, lost_l = e.lost_limit;
    const double E = U > fabs(ke) ? U : fabs(ke);
    char buffer[400], where[400];
    const char *causes;
    if (frame) {
        int bl, bn;
        rj__worst_node(m, frame, &bl, &bn);
        snprintf(where, sizeof where, "fastest node link %d node %d", bl, bn);
    } else
        rj__rig_fastest(m, s, where, sizeof where);
    causes = rj__blowup_causes(m, m->nload > 0 || s->inputs || s->node_inputs, e.work,
                               fabs(ke) + fabs(U), buffer, sizeof buffer);
    if (created > RJ__CREATED * scale || lost_l < -RJ__CREATED * scale)
        return rj__stop(m, s, RJ_ERR_BLOWUP,
                        "t = %.9g s: %.6g J of energy created (balance %.6g J, limit work %.6g J; "
                        "more than %g of the initial %.6g J); %s; %s",
                        t, created > -lost_l ? created : -lost_l, created, -lost_l, RJ__CREATED,
                        scale, where, causes);
    if (!rj__finite(E) || !rj__finite(ke + U) || !rj__finite(lost_l))
        return rj__stop(m, s, RJ_ERR_BLOWUP, "t = %.9g s: non-finite energy, %s; %s", t, where,
                        causes);
    return rj__stop(m, s, RJ_ERR_BLOWUP,
                    "t = %.9g s: kinetic or strain energy %.6g J exceeds %g x the initial %.6g J; "
                    "%s; %s",
                    t, E, m->solver.energy_growth, scale, where, causes);
}

/* The energy tests, the same for every link model. An unstable mode alternates in sign:
   v^{n-1/2}.v^{n+1/2} turns negative while the strain grows, and their sum is what the
   scheme conserves, so each is tested alone; and limit responses are dissipative, so energy
   they put in means chatter. frame: the nodes to name the fastest of (NULL: rigid links in
   joint coordinates). e0 is the initial energy, old_spring the springs' energy at n - 1. */
static RJ__FORCE_INLINE rj_result rj__energy_check(const rj_model *m, rj_state *s,
                                                   const double *frame, double t, const rj__sums *e,
                                                   double old_spring, double e0)
{
    const double ke = e->kinetic, U = e->strain, V = e->spring, lost_l = e->lost_limit;
    const double E = U > fabs(ke) ? U : fabs(ke);
    /* the initial energy less gravity's potential now, plus the inputs' work: what gravity
       has released and the caller has put in may turn into kinetic energy */
    const double outside = e->gravity - e->work - e->drive; /* gravity, the caller, the drives */
    /* a drive that lifts a load and holds it moves energy that outside nets out */
    const double scale =
        fabs(e0 - outside) + fabs(old_spring) + s->settle_scale + e->drive_flow + 1e-9;
    const double created = ke + U + V + outside + e->lost_damping + e->lost_friction + lost_l +
                           e->lost_material - e0;
    if (!rj__finite(E) || !rj__finite(ke + U) || !rj__finite(lost_l) ||
        E > m->solver.energy_growth * (scale + fabs(V)) || created > RJ__CREATED * scale ||
        lost_l < -RJ__CREATED * scale)
        return rj__energy_stop(m, s, frame, t, *e, scale, created);
    return RJ_OK;
}

/* The actuators' work moved this step, into the flow the energy tests scale by. */
static void rj__drive_flow(const double *osc, double *nsc, rj__sums *e)
{
    const double before = osc[RJ__FS_DRIVE] + osc[RJ__FS_DPEND];
    const double after = e->drive + e->drive_pending;
    e->drive_flow += fabs(after - before);
    nsc[RJ__FS_DFLOW] = e->drive_flow;
}

/* Gravity's potential moved since the last accounts (the state's start sets it), into
   the same flow: a pendulum at the top of its swing has released nothing net, but the
   scheme's error is on all that moved (a four-bar of rigid bars stopped there with
   1.1e-6 J "created" of 5.6e-5 J). */
static void rj__gravity_flow(const double *osc, double *nsc, rj__sums *e)
{
    e->drive_flow += fabs(e->gravity - osc[RJ__FS_GRAV]);
    nsc[RJ__FS_DFLOW] = e->drive_flow;
}

/* The accounts of a first step (from rest): the energy there is the initial energy, and
   the losses and work start from zero. */
static void rj__first_accounts(double *new_scalars, rj__sums *e, double energy)
{
    /* a prescribed joint driven from the start has put its first step's work into the
       energy there: the initial energy is the one before it, and the work is kept (its
       second half, pending, is the next step's) */
    new_scalars[RJ__FS_E0] = energy - e->drive;
    rj__accounts_zero(new_scalars);
    e->lost_damping = e->lost_friction = e->work = e->lost_limit = e->lost_material = 0;
    new_scalars[RJ__FS_DRIVE] = e->drive;
    new_scalars[RJ__FS_DPEND] = e->drive_pending;
}

/* The new frame's scalars: time, the accounts (on the steps that take them; the initial
   energy in the same discrete form as every later one), and the energy tests. */
static RJ__FORCE_INLINE rj_result rj__step_accounts(const rj_model *m, rj_state *s,
                                                    const rj__frames *f, rj__sums *e)
{
    const double *osc = f->old_scalars;
    double *nsc = f->new_scalars;
    const double warn = nsc[RJ__FS_WARN]; /* counted in this step already */
    memcpy(nsc, osc, sizeof(double) * RJ__FS_COUNT);
    nsc[RJ__FS_WARN] = warn;
    nsc[RJ__FS_TIME] = f->t + f->dt;
    nsc[RJ__FS_LDAMP] = e->lost_damping;
    nsc[RJ__FS_LFRIC] = e->lost_friction;
    nsc[RJ__FS_LLIM] = e->lost_limit;
    nsc[RJ__FS_PEND] = e->pending;
    if (m->nmaterial)
        e->lost_material = rj__material_accounts(m, s, osc, nsc, f->nvx, f->nvy, f->nw);
    nsc[RJ__FS_WORK] = e->work;
    nsc[RJ__FS_DRIVE] = e->drive;
    nsc[RJ__FS_DPEND] = e->drive_pending;
    if (m->nact)
        rj__drive_flow(osc, nsc, e);
    if (!f->en)
        return RJ_OK;
    nsc[RJ__FS_ETIME] = f->t;
    nsc[RJ__FS_KE] = e->kinetic;
    nsc[RJ__FS_STRAIN] = e->strain;
    nsc[RJ__FS_SPRING] = e->spring;
    if (m->has_gravity)
        rj__gravity_flow(osc, nsc, e);
    nsc[RJ__FS_GRAV] = e->gravity;
    if (f->first)
        rj__first_accounts(nsc, e, e->kinetic + e->strain + e->spring + e->gravity);
    return rj__energy_check(m, s, f->advanced, f->t, e, osc[RJ__FS_SPRING], nsc[RJ__FS_E0]);
}

/* The step's end: in place, the new scalars, joints and bodies join the advanced nodes;
   double-buffered, the frames swap. */
static RJ__FORCE_INLINE void rj__step_commit(const rj_model *m, rj_state *s, const rj__frames *f)
{
    if (f->ip) {
        const size_t j0 = RJ__FS_COUNT + 6 * (size_t) m->nn + 3 * (size_t) m->ne;
        memcpy(f->current, f->next, sizeof(double) * RJ__FS_COUNT);
        memcpy(f->current + j0, f->next + j0, sizeof(double) * (m->frame_doubles - j0));
        memcpy(s->fi[s->cur], f->new_flags, sizeof(int) * (m->frame_ints + 1));
    } else
        s->cur = 1 - s->cur;
    s->steps++;
}

/* One step of flexible, inextensible and mixed scenes, stage by stage; the energy accounts
   are taken when want_energy is set, at the first step, and solver.energy_every steps after
   the last time. ip: in place (rj__step below); held: the scene has constraints on
   positions or joints between two rigid bodies (rj__step_held), compiled apart so that
   the others carry none of their code. Every stage adds to fin the positions it
   wrote, each from the velocity, torque or body motion behind it: finite while they all
   are. Applied loads enter between stages 2 and 3, so that friction sees them. */
static RJ__FORCE_INLINE rj_result rj__step_run(const rj_model *m, rj_state *s, int want_energy,
                                               int ip, int held)
{
    rj__frames f;
    rj__sums e;
    rj__adv adv;
    rj_result r;
    double fin = 0;
    /* rj__stage_applied's */
    const int applied = s->inputs | s->node_inputs | m->applied;
    rj__frames_open(m, s, want_energy, ip, &f);
    rj__frames_nodes(m, &f);
    rj__sums_open(f.old_scalars, &e);
    adv.fin = &fin;
    rj__stage_beams(m, s, &f, &adv, &e);
    rj__stage_joint_torques(m, s, &f, &e);
    if (m->ncp)
        e.spring += rj__stage_couplings(m, s, f.old, f.next);
    if (applied) {
        r = rj__stage_applied(m, s, f.next, f.t, f.ip ? f.next : f.current, f.advanced, f.kick);
        if (r != RJ_OK)
            return r;
        e.work += s->step_work;
        fin += s->step_fin;
    }
    rj__stage_friction(m, s, &f, held);
    if (held && m->npair)
        rj__stage_pair_latches(m, s, &f);
    rj__stage_update(m, s, &f, &adv, &e, &fin);
    rj__stage_velocity_limits(m, s, &f, &e, &fin, held);
    if (applied)
        e.work += rj__applied_work(m, s, f.old, f.next);
    rj__stage_constraints(m, s, &f, &e, &fin, held);
    r = rj__stage_joint_angles(m, s, &f, &fin, held);
    if (r != RJ_OK)
        return r;
    if (!rj__finite(fin))
        return rj__stop_nonfinite(m, s, f.advanced, f.t);
    r = rj__step_accounts(m, s, &f, &e);
    if (r != RJ_OK)
        return r;
    rj__step_commit(m, s, &f);
    return RJ_OK;
}

