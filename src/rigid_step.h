/* ------------------------------------------------------------------ the rigid step */
/* Does joint j take plastic impulses at this flag (locked, forced, or e = 0 at a limit)? */
static int rj__rig_plastic(const rj_joint_def *d, int flag)
{
    const int velocity_level = d->method == RJ_METHOD_MOMENTUM || d->method == RJ_METHOD_FORCED;
    if (!velocity_level || flag == RJ_FREE)
        return 0;
    return flag == RJ_LOCKED || d->method == RJ_METHOD_FORCED || d->restitution == 0;
}

/* W_SS lam = -q'_S for the k joints flagged in act, as a compact k x k system (W's
   columns for them in r->W); lam in r->lam, in the order of the set. Nonzero when the
   system is singular. */
static int rj__rig_set_solve(const rj_model *m, int k, rj__rig *r, const double *qdp)
{
    const int n = m->nj;
    const double *act = r->act, *W = r->W;
    double *S = r->S, *rhs = r->rhs;
    int a, b, row = 0;
    for (a = 0; a < n; a++) {
        int col = 0;
        if (act[a] == 0)
            continue;
        for (b = 0; b < n; b++) {
            if (act[b] == 0)
                continue;
            S[(size_t) row * k + col] = W[(size_t) b * n + a];
            col++;
        }
        /* a prescribed joint's target rate (rj__rig_targets), else rest */
        rhs[row] = m->npres ? r->x[a] - qdp[a] : -qdp[a];
        row++;
    }
    if (rj__chol(k, S, r->SL))
        return 1;
    rj__chol_solve(k, r->SL, rhs, r->lam);
    return 0;
}

/* Drops from the set every contact (not a lock, not a prescribed joint) whose impulse would
   pull it off its limit; returns how many it dropped. */
static int rj__rig_set_drop(const rj_model *m, const int *ni, rj__rig *r)
{
    const int n = m->nj;
    int a, row = 0, dropped = 0;
    for (a = 0; a < n; a++) {
        double lam;
        if (r->act[a] == 0)
            continue;
        lam = r->lam[row];
        row++;
        if (ni[a] == RJ_LOCKED || rj__prescribed(&m->jnt[a]))
            continue;
        if ((ni[a] == RJ_AT_FORWARD && lam > 0) || (ni[a] == RJ_AT_REVERSE && lam < 0)) {
            r->act[a] = 0;
            dropped++;
        }
    }
    return dropped;
}

/* One joint's impulse moves the others (M^-1 couples them), so the plastic ones take
   their impulses together: W_SS lam = -q'_S with W = M^-1, S the set; a contact whose
   impulse would pull is dropped and the set solved again. One joint after another (as
   the single impulses before this) left a locked joint drifting at up to 0.3 deg/s in the
   fidelity benchmark's rigid solar array; sweeping that to convergence took hundreds of
   passes (W is ill-conditioned along a chain). The set starts with every locked joint and
   every plastic contact that turns into its limit or whose rate the single impulses
   changed: a later joint's impulse moves an earlier one off the rate its own gave it.
   r->h holds the rates before the impulses. */
static void rj__rig_plastic_set(const rj_model *m, rj__rig *r, const int *ni, int jumped,
                                int last_jump)
{
    const int n = m->nj;
    double *qdp = r->qdp, *act = r->act;
    const double *rates_before = r->h;
    int j, pass, changed = 1;
    for (j = 0; j < n; j++) {
        const int moved = qdp[j] != rates_before[j] || rj__into_limit(ni[j], qdp[j]);
        act[j] = rj__rig_plastic(&m->jdef[j], ni[j]) && (ni[j] == RJ_LOCKED || moved) ? 1.0 : 0.0;
        if (rj__prescribed(&m->jnt[j]))
            act[j] = 1.0;
    }
    for (pass = 0; pass <= n && changed; pass++) {
        int k = 0, row = 0, locked = 0;
        changed = 0;
        for (j = 0; j < n; j++)
            k += act[j] != 0;
        /* none, or only the one joint that took an impulse before: that was exact */
        if (k == 0 || (k == 1 && jumped == 1 && act[last_jump] != 0))
            return;
        /* every joint locked (no contact could pull): q' = 0, which the system would
           give to round-off */
        for (j = 0; j < n; j++)
            locked += ni[j] == RJ_LOCKED;
        if (locked == n) {
            for (j = 0; j < n; j++)
                qdp[j] = 0;
            return;
        }
        for (j = 0; j < n; j++)
            if (act[j] != 0)
                rj__chol_unit(n, r->L, j, r->W + (size_t) j * n);
        if (rj__rig_set_solve(m, k, r, qdp))
            return;
        if (rj__rig_set_drop(m, ni, r)) {
            changed = 1;
            continue;
        }
        for (j = 0; j < n; j++) {
            const double *w = r->W + (size_t) j * n;
            int i;
            if (act[j] == 0)
                continue;
            for (i = 0; i < n; i++)
                qdp[i] += w[i] * r->lam[row];
            row++;
        }
        /* a plastic contact the impulses turned into its limit joins the set */
        for (j = 0; j < n; j++) {
            if (act[j] != 0 || !rj__rig_plastic(&m->jdef[j], ni[j]) ||
                !rj__into_limit(ni[j], qdp[j]))
                continue;
            act[j] = 1;
            changed = 1;
        }
    }
}

/* Rigid step, stage 1: q^n, rates q'^{n-1/2} and the predicted q'^n for the centripetal
   terms; the kinematics, M(q^n) and its factor; the new frame's scalars (the element
   counts late contacts in RJ__FS_WARN). */
static RJ__FORCE_INLINE rj_result rj__rig_stage_kinematics(const rj_model *m, rj_state *s,
                                                           const rj__frames *f, rj__rig *r)
{
    const double *old_scalars = f->old_scalars;
    double *new_scalars = f->new_scalars;
    double *RJ__RESTRICT q = r->q, *RJ__RESTRICT qd = r->qd, *RJ__RESTRICT qdp = r->qdp;
    const double *old_joints = RJ__FJ(m, f->old, 0);
    const double dt = f->dt;
    const int n = m->nj;
    int j;
    for (j = 0; j < n; j++) {
        const double *old_joint = old_joints + (size_t) RJ__JD_COUNT * j;
        q[j] = old_joint[RJ__JD_THETA];
        qd[j] = old_joint[RJ__JD_RATE];
        qdp[j] = qd[j] + 0.5 * dt * old_joint[RJ__JD_QDD];
    }
    rj__rig_kin(m, r, r->q, NULL, r->qdp);
    memcpy(new_scalars, old_scalars, sizeof(double) * RJ__FS_COUNT);
    new_scalars[RJ__FS_TIME] = f->t + f->dt;
    new_scalars[RJ__FS_ETIME] = f->t;
    new_scalars[RJ__FS_STRAIN] = 0;
    rj__rig_mass(m, r);
    if (rj__chol(m->nj, r->M, r->L))
        return rj__stop(m, s, RJ_ERR_BLOWUP,
                        "t = %.9g s: the rigid mass matrix is not positive definite", f->t);
    return RJ_OK;
}

/* Gravity in joint coordinates: joint j carries the subtree beyond it, whose first moment
   about its pin is S_j (rj__rig_mass), so gravity's generalised force is S_j x g; its
   potential is -sum m g . c over the moving links. */
static void rj__rig_gravity(const rj_model *m, const rj__rig *r, double *Q, rj__sums *e)
{
    const double gx = m->solver.gravity[0], gy = m->solver.gravity[1];
    double potential = 0;
    int j, l;
    for (j = 0; j < m->nj; j++) {
        const double *sub = r->lk + RJ__RL_COUNT * (size_t) m->jdef[j].body2;
        Q[j] += sub[RJ__RL_SUB_SX] * gy - sub[RJ__RL_SUB_SY] * gx;
    }
    for (l = 0; l < m->nl; l++) {
        const double *b = r->lk + RJ__RL_COUNT * (size_t) l;
        if (m->rb_pjoint[l] >= 0)
            potential -= m->rb_mass[l] * (gx * b[RJ__RL_CX] + gy * b[RJ__RL_CY]);
    }
    e->gravity = potential;
}

/* A force (global frame) and moment on node k of rigid link l, at q^n: a generalised force
   (p - P_j) x f + moment on every joint j between the link and the ground (P_j its pin),
   added to the joints' RJ__JD_INPUT in new_joints. */
static void rj__rig_node_load(const rj_model *m, const rj__rig *r, int l, int k,
                              const double *value, double *new_joints)
{
    const double *b = r->lk + RJ__RL_COUNT * (size_t) l;
    const double along = k * m->link_l0[l];
    const double px = b[RJ__RL_RX] + along * b[RJ__RL_EC];
    const double py = b[RJ__RL_RY] + along * b[RJ__RL_ES];
    int j;
    for (j = m->rb_pjoint[l]; j >= 0; j = rj__rig_up(m, j)) {
        const double *pin = r->lk + RJ__RL_COUNT * (size_t) m->jdef[j].body2;
        const double dx = px - pin[RJ__RL_RX], dy = py - pin[RJ__RL_RY];
        new_joints[(size_t) RJ__JD_COUNT * j + RJ__JD_INPUT] +=
            dx * value[1] - dy * value[0] + value[2];
    }
}

/* The model's loads at t^n and the caller's node forces in joint coordinates. */
static void rj__rig_loads(const rj_model *m, const rj_state *s, const rj__rig *r, double t,
                          double *new_joints)
{
    int k, l;
    for (k = 0; k < m->nload; k++) {
        const rj_load_def *d = &m->load[k];
        const int node = m->load_node[k] - m->link_first[d->link];
        const double phi = r->lk[RJ__RL_COUNT * (size_t) d->link + RJ__RL_PHI];
        double value[3];
        rj__load_value(d, t, phi, value);
        rj__rig_node_load(m, r, d->link, node, value, new_joints);
    }
    if (!s->node_inputs)
        return;
    for (l = 0; l < m->nl; l++)
        for (k = 0; k <= m->ldef[l].elements; k++) {
            const double *in = s->input_node + 3 * (size_t) (m->link_first[l] + k);
            if (in[0] != 0 || in[1] != 0 || in[2] != 0)
                rj__rig_node_load(m, r, l, k, in, new_joints);
        }
}

/* Rigid step, stage 2: the element's torques as generalised forces, less the centripetal
   bias; the accelerations M^-1 Q. */
static RJ__FORCE_INLINE void rj__rig_stage_torques(const rj_model *m, rj_state *s,
                                                   const rj__frames *f, rj__rig *r, rj__sums *e)
{
    const double *RJ__RESTRICT qd = r->qd, *RJ__RESTRICT bias = r->h;
    double *RJ__RESTRICT Q = r->Q;
    const double *old_joints = RJ__FJ(m, f->old, 0);
    double *new_joints = RJ__FJ(m, f->next, 0);
    const double t = f->t;
    const int n = m->nj;
    double spring = 0;
    int j;
    for (j = 0; j < n; j++) {
        const size_t at = (size_t) RJ__JD_COUNT * j;
        double penetration;
        const double torque =
            rj__element(m, s, j, old_joints + at, new_joints + at, f->old_flags[j],
                        &f->new_flags[j], qd[j], t, f->new_scalars, &penetration, &spring);
        Q[j] = torque - bias[j];
    }
    /* cable loops: their torques on both joints, from q^n and the rates the element read */
    for (j = 0; j < m->ncp; j++) {
        const rj_coupling_def *c = &m->cp[j];
        const size_t at_a = (size_t) RJ__JD_COUNT * c->joint_a;
        const size_t at_b = (size_t) RJ__JD_COUNT * c->joint_b;
        double elastic, damp, on_b;
        rj__coupling_torques(m, c, old_joints[at_a + RJ__JD_THETA],
                             old_joints[at_b + RJ__JD_THETA], qd[c->joint_a], qd[c->joint_b],
                             &elastic, &damp, &spring);
        on_b = rj__coupling_record(c, elastic, damp, new_joints + at_a, new_joints + at_b);
        Q[c->joint_b] += on_b;
        Q[c->joint_a] -= c->ratio * on_b;
    }
    /* the caller's torques, the loads and the caller's node forces: generalised forces on
       the joints, kept in the new frame for their work (rj__step_rigid checked them) */
    if (s->inputs || m->nload || s->node_inputs) {
        for (j = 0; j < n; j++)
            new_joints[(size_t) RJ__JD_COUNT * j + RJ__JD_INPUT] =
                s->inputs ? s->input_torque[j] : 0.0;
        rj__rig_loads(m, s, r, t, new_joints);
        for (j = 0; j < n; j++)
            Q[j] += new_joints[(size_t) RJ__JD_COUNT * j + RJ__JD_INPUT];
    }
    if (m->has_gravity)
        rj__rig_gravity(m, r, Q, e);
    /* springs and tables at q^n, from the element */
    f->new_scalars[RJ__FS_SPRING] = spring;
    e->spring = spring;
    rj__chol_solve(m->nj, r->L, r->Q, r->qdd);
}

/* Rigid step, stage 3: friction, joint by joint, with the column M^-1 e_j (kept in W for
   the impulses). */
static RJ__FORCE_INLINE void rj__rig_stage_friction(const rj_model *m, const rj__frames *f,
                                                    rj__rig *r)
{
    const int n = m->nj;
    const double *RJ__RESTRICT qd = r->qd;
    double *RJ__RESTRICT qdd = r->qdd, *W = r->W;
    int j, k;
    for (j = 0; j < n; j++)
        if (m->jdef[j].friction > 0)
            rj__chol_unit(n, r->L, j, W + (size_t) j * n);
    for (j = 0; j < n; j++) {
        const double tf = m->jdef[j].friction, *w = W + (size_t) j * n;
        double tau;
        if (!(tf > 0))
            continue;
        tau = rj__friction(qd[j] + f->kick * qdd[j], f->kick * w[j], tf);
        for (k = 0; k < n; k++)
            qdd[k] += w[k] * tau;
        RJ__FJ(m, f->next, j)[RJ__JD_TQ0 + RJ_TORQUE_FRICTION] = tau;
    }
}

/* What the rigid step's impulses did: how many joints took one alone, the last of them,
   and whether any was an impact (a new contact or lock, or a bounce). */
typedef struct rj__rig_jumps {
    int count, last, impact;
} rj__rig_jumps;

/* Rigid step, stage 5a: velocity-level methods, joint by joint: an impulse along q_j to e
   times the reversed rate (plastic while locked or for forced displacement). r->h keeps the
   rates before the jumps. */
static RJ__FORCE_INLINE void rj__rig_single_impulses(const rj_model *m, const rj__frames *f,
                                                     rj__rig *r, rj__rig_jumps *jumps)
{
    const int n = m->nj;
    const double *RJ__RESTRICT q = r->q;
    double *RJ__RESTRICT qdp = r->qdp, *RJ__RESTRICT rates_before = r->h, *W = r->W;
    const double *L = r->L;
    int *ni = f->new_flags;
    int j, k;
    for (j = 0; j < n; j++) {
        const rj_joint_def *d = &m->jdef[j];
        const double *w = W + (size_t) j * n;
        double e, lam;
        if (!(d->method == RJ_METHOD_MOMENTUM || d->method == RJ_METHOD_FORCED))
            continue;
        /* re-contact within the step, as for flexible links */
        if (ni[j] == RJ_FREE && q[j] <= m->jnt[j].rev && qdp[j] < 0)
            ni[j] = RJ_AT_REVERSE;
        if (ni[j] == RJ_FREE && q[j] >= m->jnt[j].fwd && qdp[j] > 0)
            ni[j] = RJ_AT_FORWARD;
        if (ni[j] == RJ_FREE || !rj__into_limit(ni[j], qdp[j]))
            continue;
        e = (d->method == RJ_METHOD_MOMENTUM && ni[j] != RJ_LOCKED) ? d->restitution : 0.0;
        if (!jumps->count)
            for (k = 0; k < n; k++)
                rates_before[k] = qdp[k];
        jumps->count++;
        jumps->last = j;
        if (ni[j] != f->old_flags[j] || e > 0)
            jumps->impact = 1;
        /* stage 3 made the column of a joint with friction */
        if (!(d->friction > 0))
            rj__chol_unit(n, L, j, W + (size_t) j * n);
        lam = (-e * qdp[j] - qdp[j]) / w[j];
        for (k = 0; k < n; k++)
            qdp[k] += w[k] * lam;
    }
}

/* Rigid step, stage 5b: the jumps' loss in the kinetic energy's form: 1/2 q'^{n-1/2} M
   (q'_before - q'_after) now, 1/2 q'_after M (q'_before - q'_after) with the next step
   (pending); the generalised impulse along q_j is the latch's angular impulse on body 2. */
static RJ__FORCE_INLINE void rj__rig_jump_loss(const rj_model *m, const rj__frames *f,
                                               const rj__rig *r, rj__sums *e)
{
    const int n = m->nj, first = f->first;
    const double *RJ__RESTRICT qd = r->qd, *RJ__RESTRICT qdp = r->qdp;
    const double *RJ__RESTRICT rates_before = r->h, *M = r->M;
    double *new_joints = RJ__FJ(m, f->next, 0);
    double lost_limit = e->lost_limit, pending = e->pending;
    int j, k;
    for (j = 0; j < n; j++) {
        const double *Mj = M + (size_t) j * n;
        double *record = new_joints + (size_t) RJ__JD_COUNT * j;
        double sum = 0, now;
        for (k = 0; k < n; k++)
            sum += Mj[k] * (rates_before[k] - qdp[k]);
        /* the first step's q'^{-1/2} is 2 q'(0) less the rates before any impulse */
        now = 0.5 * (first ? 2 * qd[j] - rates_before[j] : qd[j]) * sum;
        /* a prescribed joint's impulse is its drive's: torque and work */
        if (rj__prescribed(&m->jnt[j])) {
            e->drive -= now;
            e->drive_pending -= 0.5 * qdp[j] * sum;
            record[RJ__JD_TQ0 + RJ_TORQUE_DRIVE] = -sum / f->kick;
            continue;
        }
        lost_limit += now;
        pending += 0.5 * qdp[j] * sum;
        /* the latches' impulse: less an exact coupling's, reported as a torque */
        record[RJ__JD_IMPULSE] = -sum - (m->nexact ? r->x[j] : 0.0);
    }
    e->lost_limit = lost_limit;
    e->pending = pending;
}

/* The prescribed joints' rates at n + 1/2 into r->x (0 for the others), and the rates
   before any impulse into r->h: the plastic set takes them with its locks. */
static void rj__rig_targets(const rj_model *m, const rj_state *s, const rj__frames *f,
                            rj__rig *r)
{
    int j;
    for (j = 0; j < m->nj; j++) {
        r->x[j] = rj__prescribed(&m->jnt[j])
                      ? rj__prescribed_rate(m, s, j, r->q[j], f->t, f->dt)
                      : 0.0;
        r->h[j] = r->qdp[j];
    }
}

/* Rigid step, stage 5c: each exact coupling's impulse along w = e_b - ratio e_a, P =
   -(w . q' + e^n / dt) / (w . M^-1 w), which lands e at 0 at n + 1 (after the latches);
   reported as the two joints' spring torques over the kick (rj__rig_jump_loss counts its
   energy with the latches' and keeps it out of their impulses: r->x). r->tmp: w, M^-1 w. */
static void rj__rig_exact(const rj_model *m, const rj__frames *f, rj__rig *r)
{
    const int n = m->nj;
    double *w = r->tmp, *mw = r->tmp + n, *new_joints = RJ__FJ(m, f->next, 0);
    int k, j;
    /* r->x (the prescribed targets, spent by now): each joint's coupling impulse */
    for (j = 0; j < n; j++)
        r->x[j] = 0;
    for (k = 0; k < m->ncp; k++) {
        const rj_coupling_def *c = &m->cp[k];
        const int a = c->joint_a, b = c->joint_b;
        const double e_n = (r->q[b] - m->jdef[b].angle0) -
                           c->ratio * (r->q[a] - m->jdef[a].angle0) - c->offset;
        double P;
        if (!c->exact)
            continue;
        for (j = 0; j < n; j++)
            w[j] = 0;
        w[b] = 1;
        w[a] = -c->ratio;
        rj__chol_solve(n, r->L, w, mw);
        P = -(r->qdp[b] - c->ratio * r->qdp[a] + e_n / f->dt) / (mw[b] - c->ratio * mw[a]);
        for (j = 0; j < n; j++)
            r->qdp[j] += mw[j] * P;
        r->x[b] += P;
        r->x[a] -= c->ratio * P;
        new_joints[(size_t) RJ__JD_COUNT * b + RJ__JD_TQ0 + RJ_TORQUE_SPRING] += P / f->kick;
        new_joints[(size_t) RJ__JD_COUNT * a + RJ__JD_TQ0 + RJ_TORQUE_SPRING] -=
            c->ratio * P / f->kick;
    }
}

/* Rigid step, stages 4 and 5: rates q'^{n+1/2}, then the velocity-level limit methods.
   Without an impact the jumps only keep locked joints and resting contacts at rest, and
   (q'^{n+1/2} - q'^{n-1/2}) / kick is the constrained acceleration: the next step's
   centripetal terms predict q'^{n+1} from it, not from the unconstrained one, which turns a
   locked joint at up to dt / 2 times its reaction over its inertia. */
static RJ__FORCE_INLINE void rj__rig_stage_rates(const rj_model *m, const rj_state *s,
                                                 const rj__frames *f, rj__rig *r, rj__sums *e)
{
    const int n = m->nj;
    const double kick = f->kick;
    const double *RJ__RESTRICT qd = r->qd;
    double *RJ__RESTRICT qdp = r->qdp, *RJ__RESTRICT qdd = r->qdd;
    rj__rig_jumps jumps;
    int j;
    for (j = 0; j < n; j++)
        qdp[j] = qd[j] + kick * qdd[j];
    /* the first step's kinetic energy reads the rates before any impulse (Q is spent) */
    if (f->first)
        for (j = 0; j < n; j++)
            r->Q[j] = qdp[j];
    jumps.count = 0;
    jumps.last = -1;
    jumps.impact = 0;
    if (m->npres)
        rj__rig_targets(m, s, f, r);
    rj__rig_single_impulses(m, f, r, &jumps);
    if (!jumps.count && !m->npres && !m->nexact)
        return;
    if (!jumps.count && !m->npres)
        for (j = 0; j < n; j++)
            r->h[j] = qdp[j];
    if (jumps.count || m->npres)
        rj__rig_plastic_set(m, r, f->new_flags, jumps.count, jumps.last);
    if (m->nexact)
        rj__rig_exact(m, f, r);
    if (!jumps.impact)
        for (j = 0; j < n; j++)
            qdd[j] = (qdp[j] - qd[j]) / kick;
    rj__rig_jump_loss(m, f, r, e);
}

/* Rigid step, stage 6: angles q^{n+1}, forced displacement back to the limit, and the
   work of the joint torques. */
static RJ__FORCE_INLINE rj_result rj__rig_stage_angles(const rj_model *m, rj_state *s,
                                                       const rj__frames *f, const rj__rig *r,
                                                       rj__sums *e)
{
    const double *RJ__RESTRICT q = r->q, *RJ__RESTRICT qdp = r->qdp;
    const double *RJ__RESTRICT qd = r->qd, *RJ__RESTRICT qdd = r->qdd;
    const double *old_joints = RJ__FJ(m, f->old, 0);
    double *new_joints = RJ__FJ(m, f->next, 0);
    const double dt = f->dt;
    const int n = m->nj;
    double lost_damping = e->lost_damping;
    double lost_friction = e->lost_friction;
    double lost_limit = e->lost_limit;
    const int *ni = f->new_flags;
    const int applied = s->inputs || m->nload || s->node_inputs; /* RJ__JD_INPUT written */
    int j;
    for (j = 0; j < n; j++) {
        const rj_joint_def *d = &m->jdef[j];
        const double *old_joint = old_joints + (size_t) RJ__JD_COUNT * j;
        double *new_joint = new_joints + (size_t) RJ__JD_COUNT * j;
        double qn = q[j] + dt * qdp[j];
        if (d->method == RJ_METHOD_FORCED && ni[j] != RJ_FREE) {
            const rj__joint *J = &m->jnt[j];
            if (ni[j] == RJ_AT_FORWARD && qn > J->fwd)
                qn = J->fwd;
            else if (ni[j] == RJ_AT_REVERSE && qn < J->rev)
                qn = J->rev;
            else if (ni[j] == RJ_LOCKED)
                qn = new_joint[RJ__JD_LOCK];
        }
        if (!(fabs(qn - q[j]) <= 0.5 * RJ__PI))
            return rj__stop(m, s, RJ_ERR_TUNNEL,
                            "t = %.9g s: joint %d turned %.4g rad in one step (more than a quarter "
                            "revolution, pi/2 rad): the step %g s is far too large for its speed",
                            f->t, j, qn - q[j], dt);
        new_joint[RJ__JD_THETA] = qn;
        new_joint[RJ__JD_RATE] = qdp[j];
        new_joint[RJ__JD_QDD] = qdd[j];
        rj__element_work(old_joint, new_joint, qd[j], dt, &lost_damping, &lost_friction,
                         &lost_limit);
        if (applied)
            e->work += rj__input_work(old_joint, new_joint, qd[j], dt);
        if (m->jnt[j].act && !rj__prescribed(&m->jnt[j]))
            e->drive += rj__drive_work(old_joint, new_joint, qd[j], dt);
    }
    e->lost_damping = lost_damping;
    e->lost_friction = lost_friction;
    e->lost_limit = lost_limit;
    return RJ_OK;
}

/* The caller's node forces, every one a number the step can use (rj__node_input_ok). */
static int rj__rig_node_inputs_ok(const rj_model *m, rj_state *s)
{
    int i;
    for (i = 0; i < m->nn; i++)
        if (!rj__node_input_ok(m, s, i))
            return 0;
    return 1;
}

/* Rigid step, stage 7: the kinetic energy 1/2 q'^{n-1/2} M q'^{n+1/2} (q'^{-1/2} = 2 q'(0)
   - q'^{1/2}), the accounts (every step) and the energy tests; commit (nodes are computed
   when queried: rj__rig_pose). */
static RJ__FORCE_INLINE rj_result rj__rig_stage_accounts(const rj_model *m, rj_state *s,
                                                         const rj__frames *f, const rj__rig *r,
                                                         rj__sums *e)
{
    const int n = m->nj, first = f->first;
    const double *RJ__RESTRICT qd = r->qd, *RJ__RESTRICT qdp = r->qdp, *M = r->M;
    double *new_scalars = f->new_scalars;
    double ke = 0;
    rj_result res;
    int j, k;
    for (j = 0; j < n; j++) {
        const double *Mj = M + (size_t) j * n;
        double sum = 0;
        for (k = 0; k < n; k++)
            sum += Mj[k] * qdp[k];
        /* the first step's q'^{-1/2}: 2 q'(0) less the rates before the step's impulses
           (kept in Q by rj__rig_stage_rates), which an impulse does not move */
        ke += 0.5 * (first ? 2 * qd[j] - r->Q[j] : qd[j]) * sum;
    }
    e->kinetic = ke;
    new_scalars[RJ__FS_KE] = ke;
    new_scalars[RJ__FS_LDAMP] = e->lost_damping;
    new_scalars[RJ__FS_LFRIC] = e->lost_friction;
    new_scalars[RJ__FS_LLIM] = e->lost_limit;
    new_scalars[RJ__FS_PEND] = e->pending;
    new_scalars[RJ__FS_GRAV] = e->gravity;
    new_scalars[RJ__FS_WORK] = e->work;
    new_scalars[RJ__FS_DRIVE] = e->drive;
    new_scalars[RJ__FS_DPEND] = e->drive_pending;
    if (m->nact)
        rj__drive_flow(f->old_scalars, new_scalars, e);
    if (f->first)
        rj__first_accounts(new_scalars, e, ke + e->spring + e->gravity);
    res = rj__energy_check(m, s, NULL, f->t, e, f->old_scalars[RJ__FS_SPRING],
                           new_scalars[RJ__FS_E0]);
    if (res != RJ_OK)
        return res;
    s->cur = 1 - s->cur;
    s->steps++;
    return RJ_OK;
}

/* One step of a rigid-link scene: central differences in joint coordinates, stage by
   stage as for flexible links (rj__step_run). The work that does not wait for the new
   rates (spring energy, frame scalars) comes early, so that the end of a step, between the
   new angles and the next step's kinematics, stays short. */
static rj_result rj__step_rigid(const rj_model *m, rj_state *s)
{
    rj__frames f;
    rj__sums e;
    rj__rig r;
    rj_result res;
    rj__frames_open(m, s, 1, 0, &f);
    rj__sums_open(f.old_scalars, &e);
    rj__rig_map(m, s->rsc, &r);
    if (s->inputs && !rj__inputs_ok(m, s))
        return RJ_ERR_INVALID;
    if (s->node_inputs && !rj__rig_node_inputs_ok(m, s))
        return RJ_ERR_INVALID;
    res = rj__rig_stage_kinematics(m, s, &f, &r);
    if (res != RJ_OK)
        return res;
    rj__rig_stage_torques(m, s, &f, &r, &e);
    rj__rig_stage_friction(m, &f, &r);
    rj__rig_stage_rates(m, s, &f, &r, &e);
    res = rj__rig_stage_angles(m, s, &f, &r, &e);
    if (res != RJ_OK)
        return res;
    return rj__rig_stage_accounts(m, s, &f, &r, &e);
}

