/* ------------------------------------------------------------------ the rigid step */
/* Does joint j take plastic impulses at this flag (locked, forced, or e = 0 at a limit)? */
static int rj__rig_plastic(const rj_joint_def *d, int flag)
{
    const int velocity_level = d->method == RJ_METHOD_MOMENTUM || d->method == RJ_METHOD_FORCED;
    if (!velocity_level || flag == RJ_FREE)
        return 0;
    return flag == RJ_LOCKED || d->method == RJ_METHOD_FORCED || d->restitution == 0;
}

/* What the rigid step's impulses did: how many joints took one alone, the last of them,
   and whether any was an impact (a new contact or lock, or a bounce). */
typedef struct rj__rig_jumps {
    int count, last, impact;
} rj__rig_jumps;

/* Node at of rigid link l where the kinematics put it (r->lk). */
static void rj__rig_link_node(const rj_model *m, const rj__rig *r, int l, int at, double p[2])
{
    const double *b = r->lk + RJ__RL_COUNT * (size_t) l;
    const double along = at * m->link_l0[l];
    p[0] = b[RJ__RL_RX] + along * cos(b[RJ__RL_PHI]);
    p[1] = b[RJ__RL_RY] + along * sin(b[RJ__RL_PHI]);
}

/* Joint j's pins at the kinematics' positions: on body 1 (or ground) and on body 2. */
static void rj__rig_pins(const rj_model *m, const rj__rig *r, int j, double p1[2], double p2[2])
{
    const rj_joint_def *d = &m->jdef[j];
    if (d->body1 < 0) {
        p1[0] = d->ground_x;
        p1[1] = d->ground_y;
    } else
        rj__rig_link_node(m, r, d->body1, d->node1 < 0 ? m->ldef[d->body1].elements : d->node1,
                          p1);
    rj__rig_link_node(m, r, d->body2, m->jnt[j].nJ - m->link_first[d->body2], p2);
}

/* Adds to one loop row (x: axis 0, y: 1) the terms of point p on link l: sign times
   d p / d q_k = perp(p - P_k) for each tree joint k on l's path to the ground. */
static void rj__rig_loop_terms(const rj_model *m, const rj__rig *r, rj__rows *R, rj__row *row,
                               int l, const double p[2], int axis, double sign)
{
    int up;
    for (up = l >= 0 ? m->rb_pjoint[l] : -1; up >= 0; up = rj__rig_up(m, up)) {
        const double *pin = r->lk + RJ__RL_COUNT * (size_t) m->jdef[up].body2;
        const double d = axis == 0 ? -(p[1] - pin[RJ__RL_PY]) : p[0] - pin[RJ__RL_PX];
        rj__row_term(R, row, m->jq[up], sign * d);
    }
}

/* The loop joints' rows: their pins' gap p1 - p2 back to 0 at n + 1, in x and in y. A
   coordinate on both pins' paths appears twice in a row (the dot products sum them). */
static void rj__rig_loop_rows(const rj_model *m, const rj__rig *r, double dt, rj__rows *R)
{
    int j, axis;
    for (j = 0; j < m->nj; j++) {
        double p1[2], p2[2];
        if (m->jq[j] >= 0)
            continue;
        rj__rig_pins(m, r, j, p1, p2);
        for (axis = 0; axis < 2; axis++) {
            rj__row *row = rj__row_open(R, RJ__ROW_LOOP, j, -(p1[axis] - p2[axis]) / dt,
                                        -HUGE_VAL, HUGE_VAL);
            rj__rig_loop_terms(m, r, R, row, m->jdef[j].body1, p1, axis, 1.0);
            rj__rig_loop_terms(m, r, R, row, m->jdef[j].body2, p2, axis, -1.0);
        }
    }
}

/* Adds coef times joint j's rate to a row: its coordinate, or g for a joint that closes
   a loop (g: nq doubles of scratch). */
static void rj__rig_joint_terms(const rj_model *m, rj__rows *R, rj__row *row, int j, double coef,
                                double *g)
{
    int k;
    if (m->jq[j] >= 0) {
        rj__row_term(R, row, m->jq[j], coef);
        return;
    }
    rj__rig_loop_gradient(m, j, g);
    for (k = 0; k < m->nq; k++)
        if (g[k] != 0)
            rj__row_term(R, row, k, coef * g[k]);
}

/* A loop joint's bounce: at a limit by momentum with e > 0 (its row's target is -e times
   the rate the loops leave it, rj__rig_loop_bounces). */
static int rj__rig_loop_bounce(const rj_model *m, const rj__frames *f, int j)
{
    const rj_joint_def *d = &m->jdef[j];
    const int flag = f->new_flags[j];
    return d->method == RJ_METHOD_MOMENTUM && d->restitution > 0 && flag != RJ_FREE &&
           flag != RJ_LOCKED;
}

/* The rows of the joints that close loops, each along the loop joint's gradient g and
   owned by -1 - j (no single impulse holds it): a prescribed joint's profile; a latch
   (locked, or at a limit by momentum or forced displacement), a lock or a plastic contact
   row; a bounce's contact row, its target set once the loops' rows have acted. */
static void rj__rig_loop_latches(const rj_model *m, const rj_state *s, const rj__frames *f,
                                 const rj__rig *r, rj__rows *R)
{
    const int *ni = f->new_flags;
    const double *old_joints = RJ__FJ(m, f->old, 0);
    double *g = r->tmp;
    int j, k;
    for (j = 0; j < m->nj; j++) {
        const rj_joint_def *d = &m->jdef[j];
        const double theta = old_joints[(size_t) RJ__JD_COUNT * j + RJ__JD_THETA];
        const int forward = ni[j] == RJ_AT_FORWARD;
        const int velocity_level = d->method == RJ_METHOD_MOMENTUM || d->method == RJ_METHOD_FORCED;
        double target;
        rj__row *row;
        if (m->jq[j] >= 0)
            continue;
        if (rj__prescribed(&m->jnt[j])) {
            target = rj__prescribed_rate(m, s, j, theta, f->t, f->dt);
            row = rj__row_open(R, RJ__ROW_PRESCRIBED, -1 - j, target, -HUGE_VAL, HUGE_VAL);
            rj__rig_joint_terms(m, R, row, j, 1.0, g);
            continue;
        }
        if (!velocity_level || ni[j] == RJ_FREE)
            continue;
        rj__rig_loop_gradient(m, j, g);
        if (ni[j] == RJ_LOCKED)
            row = rj__row_open(R, RJ__ROW_LOCK, -1 - j, 0.0, -HUGE_VAL, HUGE_VAL);
        else if (rj__rig_loop_bounce(m, f, j)) {
            row = rj__row_open(R, RJ__ROW_CONTACT, -1 - j, 0.0, -HUGE_VAL, HUGE_VAL);
            row->active = 0;
        } else {
            /* held from the start when its rate, as the loops leave it, turns into the
               limit (rj__rows_solve_dense takes it in then), not at the rate before them */
            row = rj__row_open(R, RJ__ROW_CONTACT, -1 - j, 0.0, forward ? -HUGE_VAL : 0.0,
                               forward ? 0.0 : HUGE_VAL);
            row->active = 0;
        }
        for (k = 0; k < m->nq; k++)
            if (g[k] != 0)
                rj__row_term(R, row, k, g[k]);
    }
}

/* The exact couplings' rows in a scene with loops: e from the joints' angles at n (a
   loop joint's from its record), along w = e_b - ratio e_a over the coordinates. */
static void rj__rig_loop_couplings(const rj_model *m, const rj__frames *f, rj__rows *R,
                                   double *g)
{
    int k;
    for (k = 0; k < m->ncp; k++) {
        const rj_coupling_def *c = &m->cp[k];
        const double e_n = rj__coupling_stretch(m, c, RJ__FJ(m, f->old, c->joint_a)[RJ__JD_THETA],
                                                RJ__FJ(m, f->old, c->joint_b)[RJ__JD_THETA]);
        rj__row *row;
        if (!c->exact)
            continue;
        row = rj__row_open(R, RJ__ROW_COUPLING, k, -e_n / f->dt, -HUGE_VAL, HUGE_VAL);
        rj__rig_joint_terms(m, R, row, c->joint_b, 1.0, g);
        rj__rig_joint_terms(m, R, row, c->joint_a, -c->ratio, g);
    }
}

/* Rigid step, stage 5b: the rows in joint coordinates (src/rows.h), in joint order: a
   prescribed joint's profile; a locked joint; a plastic contact, held from the start when
   it turns into its limit or a single impulse moved its rate (a later joint's impulse
   moves an earlier one off the rate its own gave it; r->h holds the rates before them);
   then the exact couplings. The joints' impulses move each other (M^-1 couples them), so
   they are solved together: one joint after another (as the single impulses) left a
   locked joint drifting at up to 0.3 deg/s in the fidelity benchmark's rigid solar
   array, and sweeping that to convergence took hundreds of passes (W is ill-conditioned
   along a chain). */
static void rj__rig_rows_build(const rj_model *m, const rj_state *s, const rj__frames *f,
                               const rj__rig *r, rj__rows *R)
{
    const int *ni = f->new_flags;
    int k;
    R->count = R->terms = 0;
    for (k = 0; k < m->nq; k++) {
        const int j = m->qj[k];
        const double rate = r->qdp[k];
        const int forward = ni[j] == RJ_AT_FORWARD;
        rj__row *row;
        if (rj__prescribed(&m->jnt[j])) {
            rj__row_prescribed(m, s, R, j, k, r->q[k], f->t, f->dt);
            continue;
        }
        if (!rj__rig_plastic(&m->jdef[j], ni[j]))
            continue;
        if (ni[j] == RJ_LOCKED)
            row = rj__row_open(R, RJ__ROW_LOCK, k, 0.0, -HUGE_VAL, HUGE_VAL);
        else {
            row = rj__row_open(R, RJ__ROW_CONTACT, k, 0.0, forward ? -HUGE_VAL : 0.0,
                               forward ? 0.0 : HUGE_VAL);
            row->active = rate != r->h[k] || rj__into_limit(ni[j], rate);
        }
        rj__row_term(R, row, k, 1.0);
    }
    if (!m->nloop) {
        rj__rows_couplings(m, R, r->q, 1, m->jq, f->dt);
        return;
    }
    rj__rig_loop_couplings(m, f, R, r->tmp);
    rj__rig_loop_latches(m, s, f, r, R);
    rj__rig_loop_rows(m, r, f->dt, R);
}

/* The row of the one joint that took a single impulse (which held it exactly), or -1. */
static int rj__rig_held_row(const rj__rows *R, const rj__rig_jumps *jumps)
{
    int a;
    if (jumps->count != 1)
        return -1;
    for (a = 0; a < R->count; a++)
        if (R->row[a].kind <= RJ__ROW_CONTACT && R->row[a].owner == jumps->last)
            return a;
    return -1;
}

/* A prescribed loop joint's row: its impulse over the step is its drive's torque, each
   coordinate's share into r->xd (rj__rig_jump_loss books their work as the drive's). */
static void rj__rig_loop_drive(const rj_model *m, const rj__frames *f, const rj__rows *R,
                               const rj__row *row, rj__rig *r)
{
    int k;
    RJ__FJ(m, f->next, -1 - row->owner)[RJ__JD_TQ0 + RJ_TORQUE_DRIVE] = row->lam / f->kick;
    for (k = 0; k < row->count; k++) {
        const rj__term *t = &R->term[row->first + k];
        r->xd[t->joint] += t->coef * row->lam;
    }
}

/* An exact coupling's row in a scene with loops: its impulse on each coordinate into r->x,
   its torques on its two joints (lambda on b, -ratio lambda on a) into their spring
   columns. */
static void rj__rig_loop_coupling_torques(const rj_model *m, const rj__frames *f,
                                          const rj__rows *R, const rj__row *row, rj__rig *r)
{
    const rj_coupling_def *c = &m->cp[row->owner];
    int k;
    for (k = 0; k < row->count; k++) {
        const rj__term *t = &R->term[row->first + k];
        r->x[t->joint] += t->coef * row->lam;
    }
    RJ__FJ(m, f->next, c->joint_b)[RJ__JD_TQ0 + RJ_TORQUE_SPRING] += row->lam / f->kick;
    RJ__FJ(m, f->next, c->joint_a)[RJ__JD_TQ0 + RJ_TORQUE_SPRING] +=
        -c->ratio * row->lam / f->kick;
}

/* The exact couplings' and the loops' impulses: each coordinate's share into r->x
   (rj__rig_jump_loss keeps it out of the latches' impulses), the couplings' torques into
   their joints' spring columns. */
static void rj__rig_coupling_torques(const rj_model *m, const rj__frames *f, const rj__rows *R,
                                     rj__rig *r)
{
    double *new_joints = RJ__FJ(m, f->next, 0);
    int a, k;
    for (k = 0; k < m->nq; k++)
        r->x[k] = 0;
    for (k = 0; k < m->nq && m->nloop; k++)
        r->xd[k] = 0;
    for (a = 0; a < R->count; a++) {
        const rj__row *row = &R->row[a];
        const int loop_latch = row->kind <= RJ__ROW_CONTACT && row->owner < 0;
        if (row->kind == RJ__ROW_PRESCRIBED && row->owner < 0) {
            rj__rig_loop_drive(m, f, R, row, r);
            continue;
        }
        if (row->kind == RJ__ROW_COUPLING && m->nloop) {
            rj__rig_loop_coupling_torques(m, f, R, row, r);
            continue;
        }
        if (row->kind != RJ__ROW_COUPLING && row->kind != RJ__ROW_LOOP && !loop_latch)
            continue;
        /* a loop joint's latch: its impulse on its own record */
        if (loop_latch)
            new_joints[(size_t) RJ__JD_COUNT * (-1 - row->owner) + RJ__JD_IMPULSE] = row->lam;
        for (k = 0; k < row->count; k++) {
            const rj__term *t = &R->term[row->first + k];
            const double impulse = t->coef * row->lam;
            r->x[t->joint] += impulse;
            if (row->kind == RJ__ROW_COUPLING)
                new_joints[(size_t) RJ__JD_COUNT * m->qj[t->joint] + RJ__JD_TQ0 +
                           RJ_TORQUE_SPRING] += impulse / f->kick;
        }
    }
}

/* The loops' rows on positions (SHAKE): their Jacobian stays the one at q^n, where the
   pins' forces act, and their targets move until the pins meet at q^{n+1} = q^n + dt
   q'^{n+1/2}, not only to first order (a row on the rate alone, J(q^n) q' = -gap/dt,
   leaves the crank of a four-bar off the exact motion at first order in dt); the other
   rows keep their rates. At most 20 passes, to 1e-14 of the longest link. Near a
   singular position (a parallelogram going flat) the Jacobian at q^n no longer sees the
   gap's direction and the passes diverge: the rates of the best pass are kept (r->x
   holds them) and the projection onto the loop closes what is left. The kinematics run
   at the trial q (r->lk is not read again in the step). */
static void rj__rig_loops_shake(const rj_model *m, const rj__frames *f, rj__rig *r,
                                rj__rows *R, const rj__dense *D)
{
    double *q = r->tmp + m->nq, *best_rates = r->x, longest = 0, best = HUGE_VAL;
    int pass, k, a, l, axis;
    for (l = 0; l < m->nl; l++)
        longest = fmax(longest, m->ldef[l].length);
    for (pass = 0; pass < 20; pass++) {
        double worst = 0;
        for (k = 0; k < m->nq; k++)
            q[k] = r->q[k] + f->dt * r->qdp[k];
        rj__rig_kin(m, r, q, NULL, r->qdp);
        for (a = 0; a < R->count; a++) {
            rj__row *row = &R->row[a];
            double p1[2], p2[2];
            if (row->kind != RJ__ROW_LOOP)
                continue;
            rj__rig_pins(m, r, row->owner, p1, p2);
            /* a loop's x row, then its y row (rj__rig_loop_rows) */
            for (axis = 0; axis < 2; axis++, row++) {
                const double gap = p1[axis] - p2[axis];
                worst = fmax(worst, fabs(gap));
                row->target = rj__row_dot(R, row, r->qdp) - gap / f->dt;
            }
            a++;
        }
        if (worst < best) {
            best = worst;
            memcpy(best_rates, r->qdp, sizeof(double) * (size_t) m->nq);
        } else if (worst > 4 * best)
            break;
        if (worst <= 1e-14 * longest)
            return;
        rj__rows_solve_dense(R, D, r->qdp);
    }
    memcpy(r->qdp, best_rates, sizeof(double) * (size_t) m->nq);
}

/* The dense rows' solve's working arrays, in the rigid solver's scratch. */
static void rj__rig_dense(const rj_model *m, rj__rig *r, rj__dense *D)
{
    D->n = m->nq;
    D->m = m;
    D->rig = r;
    D->W = r->W;
    D->Y = r->Y;
    D->S = r->S;
    D->SL = r->SL;
    D->lam = r->lam;
    D->rhs = r->rhs;
    D->scratch = r->tmp;
}

/* The loop joints' bounces: the rows solved without them (the loops' own rows move the
   rate at which a loop joint meets its limit), each bounce row then aims at -e times that
   rate, pushing only, and the rows are solved again from the rates before (kept in
   r->xd, free until the impulses are shared out). */
static void rj__rig_loop_bounces(const rj_model *m, const rj__frames *f, rj__rig *r,
                                 rj__rows *R, const rj__dense *D)
{
    int a, any = 0;
    for (a = 0; a < R->count; a++) {
        rj__row *row = &R->row[a];
        int j, forward;
        double rate;
        if (row->kind != RJ__ROW_CONTACT || row->owner >= 0)
            continue;
        j = -1 - row->owner;
        if (!rj__rig_loop_bounce(m, f, j))
            continue;
        forward = f->new_flags[j] == RJ_AT_FORWARD;
        rate = rj__row_dot(R, row, r->qdp);
        row->target = -m->jdef[j].restitution * rate;
        row->lo = forward ? -HUGE_VAL : 0.0;
        row->hi = forward ? 0.0 : HUGE_VAL;
        row->active = rj__into_limit(f->new_flags[j], rate);
        any |= row->active;
    }
    if (!any)
        return;
    /* the second solve's impulses are the step's: the first's are dropped with its rates */
    for (a = 0; a < R->count; a++)
        R->row[a].lam = 0;
    memcpy(r->qdp, r->xd, sizeof(double) * (size_t) m->nq);
    rj__rows_solve_dense(R, D, r->qdp);
}

/* Whether a loop joint's latch row made an impact (a new contact or lock, or a bounce):
   then the step's rates are not the constrained motion's (rj__rig_stage_rates). */
static int rj__rig_loop_impact(const rj_model *m, const rj__frames *f, const rj__rows *R)
{
    int a;
    for (a = 0; a < R->count; a++) {
        const rj__row *row = &R->row[a];
        int j;
        if (row->kind > RJ__ROW_CONTACT || row->owner >= 0 || !row->active)
            continue;
        j = -1 - row->owner;
        if (f->new_flags[j] != f->old_flags[j] || rj__rig_loop_bounce(m, f, j))
            return 1;
    }
    return 0;
}

/* Each loop joint's pin force over the step, the force body 1 exerts on body 2: its two
   rows' impulses (on the gap p1 - p2, so the impulse on body 2 is -lambda) over the kick,
   stamped with the step they belong to (rj__pin_forces reads them). */
static void rj__rig_loop_forces(const rj_model *m, const rj_state *s, const rj__frames *f,
                                const rj__rows *R)
{
    int a;
    for (a = 0; a < R->count; a++) {
        const rj__row *row = &R->row[a];
        if (row->kind != RJ__ROW_LOOP)
            continue;
        /* a loop's x row, then its y row (rj__rig_loop_rows) */
        s->loop_force[2 * row->owner] = -row->lam / f->kick;
        s->loop_force[2 * row->owner + 1] = -row[1].lam / f->kick;
        a++;
    }
    s->loop_force[2 * m->nj] = (double) (s->steps + 1);
}

/* The rows' solve: none to do when the only row held is the one a single impulse held;
   with every joint locked (and no coupling) q' = 0, which the system gives to round-off. */
static void rj__rig_rows(const rj_model *m, const rj_state *s, const rj__frames *f, rj__rig *r,
                         rj__rig_jumps *jumps)
{
    rj__rows R;
    rj__dense D;
    int j, active = 0, locked = 0;
    R.row = s->rows;
    R.term = s->terms;
    rj__rig_rows_build(m, s, f, r, &R);
    D.held = rj__rig_held_row(&R, jumps);
    for (j = 0; j < R.count; j++)
        active += R.row[j].active;
    for (j = 0; j < m->nq; j++)
        locked += f->new_flags[m->qj[j]] == RJ_LOCKED;
    if (active == 0 || (active == 1 && D.held >= 0 && R.row[D.held].active))
        return;
    if (locked == m->nq && !m->nexact && !m->nloop) {
        for (j = 0; j < m->nq; j++)
            r->qdp[j] = 0;
        return;
    }
    rj__rig_dense(m, r, &D);
    if (m->nloop)
        memcpy(r->xd, r->qdp, sizeof(double) * (size_t) m->nq);
    rj__rows_solve_dense(&R, &D, r->qdp);
    if (m->nloop) {
        rj__rig_loop_bounces(m, f, r, &R, &D);
        rj__rig_loops_shake(m, f, r, &R, &D);
        rj__rig_loop_forces(m, s, f, &R);
        jumps->impact |= rj__rig_loop_impact(m, f, &R);
    }
    if (m->nexact || m->nloop)
        rj__rig_coupling_torques(m, f, &R, r);
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
    const int n = m->nq;
    int j;
    for (j = 0; j < n; j++) {
        const double *old_joint = old_joints + (size_t) RJ__JD_COUNT * m->qj[j];
        q[j] = old_joint[RJ__JD_THETA];
        qd[j] = old_joint[RJ__JD_RATE];
        qdp[j] = qd[j] + 0.5 * dt * old_joint[RJ__JD_QDD];
    }
    rj__rig_kin(m, r, r->q, NULL, r->qdp);
    memcpy(new_scalars, old_scalars, sizeof(double) * RJ__FS_COUNT);
    new_scalars[RJ__FS_TIME] = f->t + f->dt;
    if (f->en)
        new_scalars[RJ__FS_ETIME] = f->t;
    new_scalars[RJ__FS_STRAIN] = 0;
    if (rj__rig_factor(m, r))
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
    for (j = 0; j < m->nq; j++) {
        const double *sub = r->lk + RJ__RL_COUNT * (size_t) m->jdef[m->qj[j]].body2;
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
        const double dx = px - pin[RJ__RL_PX], dy = py - pin[RJ__RL_PY];
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

/* A torque tau at joint j, which closes a loop: tau g on the coordinates (g: nq doubles
   of scratch). */
static void rj__rig_loop_force(const rj_model *m, int j, double tau, double *Q, double *g)
{
    int k;
    if (tau == 0)
        return;
    rj__rig_loop_gradient(m, j, g);
    for (k = 0; k < m->nq; k++)
        Q[k] += tau * g[k];
}

/* The element on the joints that close loops: each one's torque at the rate and angle
   its record keeps, as a generalised force on the coordinates. */
static void rj__rig_loop_torques(const rj_model *m, rj_state *s, const rj__frames *f,
                                 rj__rig *r, double *spring)
{
    const double *old_joints = RJ__FJ(m, f->old, 0);
    double *new_joints = RJ__FJ(m, f->next, 0);
    int j;
    for (j = 0; j < m->nj; j++) {
        const size_t at = (size_t) RJ__JD_COUNT * j;
        double penetration, torque;
        if (m->jq[j] >= 0)
            continue;
        torque = rj__element(m, s, j, old_joints + at, new_joints + at, f->old_flags[j],
                             &f->new_flags[j], old_joints[at + RJ__JD_RATE], f->t,
                             f->new_scalars, &penetration, spring);
        rj__rig_loop_force(m, j, torque, r->Q, r->tmp);
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
    const int n = m->nq;
    double spring = 0;
    int j;
    for (j = 0; j < n; j++) {
        const size_t at = (size_t) RJ__JD_COUNT * m->qj[j];
        double penetration;
        const double torque =
            rj__element(m, s, m->qj[j], old_joints + at, new_joints + at, f->old_flags[m->qj[j]],
                        &f->new_flags[m->qj[j]], qd[j], t, f->new_scalars, &penetration, &spring);
        Q[j] = torque - bias[j];
    }
    if (m->nloop)
        rj__rig_loop_torques(m, s, f, r, &spring);
    /* cable loops: their torques on both joints, from q^n and the rates the element read */
    for (j = 0; j < m->ncp; j++) {
        const rj_coupling_def *c = &m->cp[j];
        const size_t at_a = (size_t) RJ__JD_COUNT * c->joint_a;
        const size_t at_b = (size_t) RJ__JD_COUNT * c->joint_b;
        const double rate_a = rj__rig_joint_rate(m, c->joint_a, qd, r->tmp);
        const double rate_b = rj__rig_joint_rate(m, c->joint_b, qd, r->tmp);
        double elastic, damp, on_b;
        rj__coupling_torques(m, c, old_joints[at_a + RJ__JD_THETA],
                             old_joints[at_b + RJ__JD_THETA], rate_a, rate_b, &elastic, &damp,
                             &spring);
        on_b = rj__coupling_record(c, elastic, damp, new_joints + at_a, new_joints + at_b);
        rj__rig_joint_force(m, c->joint_b, on_b, Q, r->tmp);
        rj__rig_joint_force(m, c->joint_a, -(c->ratio * on_b), Q, r->tmp);
    }
    /* the caller's torques, the loads and the caller's node forces: generalised forces on
       the joints, kept in the new frame for their work (rj__step_rigid checked them) */
    if (s->inputs || m->nload || s->node_inputs) {
        for (j = 0; j < m->nj; j++)
            new_joints[(size_t) RJ__JD_COUNT * j + RJ__JD_INPUT] =
                s->inputs ? s->input_torque[j] : 0.0;
        rj__rig_loads(m, s, r, t, new_joints);
        for (j = 0; j < n; j++)
            Q[j] += new_joints[(size_t) RJ__JD_COUNT * m->qj[j] + RJ__JD_INPUT];
        for (j = 0; j < m->nj && m->nloop; j++)
            if (m->jq[j] < 0)
                rj__rig_loop_force(m, j, new_joints[(size_t) RJ__JD_COUNT * j + RJ__JD_INPUT],
                                   Q, r->tmp);
    }
    if (m->has_gravity)
        rj__rig_gravity(m, r, Q, e);
    /* springs and tables at q^n, from the element */
    f->new_scalars[RJ__FS_SPRING] = spring;
    e->spring = spring;
    rj__rig_solve(m, r, r->Q, r->qdd);
}

/* Friction at the joints that close loops, as at the tree's: the loop's rate g . q' and
   its give g . M^-1 g (the column M^-1 g into r->Y's first n, spent before the rows). */
static void rj__rig_loop_friction(const rj_model *m, const rj__frames *f, rj__rig *r)
{
    const int n = m->nq;
    double *g = r->tmp, *y = r->Y;
    int j, k;
    for (j = 0; j < m->nj; j++) {
        const double tf = m->jdef[j].friction;
        double rate = 0, give = 0, tau;
        if (m->jq[j] >= 0 || !(tf > 0))
            continue;
        rj__rig_loop_gradient(m, j, g);
        rj__chol_solve(n, r->L, g, y);
        for (k = 0; k < n; k++) {
            rate += g[k] * (r->qd[k] + f->kick * r->qdd[k]);
            give += g[k] * y[k];
        }
        tau = rj__friction(rate, f->kick * give, tf);
        for (k = 0; k < n; k++)
            r->qdd[k] += y[k] * tau;
        RJ__FJ(m, f->next, j)[RJ__JD_TQ0 + RJ_TORQUE_FRICTION] = tau;
    }
}

/* Rigid step, stage 3: friction, joint by joint, each with its column M^-1 e_j, which
   W keeps (at m->wcol) for the impulses of a joint that can latch; another's is made in
   r->tmp and spent here (a column reads the factor alone: made before or after the
   joints before it, it is the same). */
static RJ__FORCE_INLINE void rj__rig_stage_friction(const rj_model *m, const rj__frames *f,
                                                    rj__rig *r)
{
    const int n = m->nq;
    const double *RJ__RESTRICT qd = r->qd;
    double *RJ__RESTRICT qdd = r->qdd, *W = r->W;
    int j, k;
    for (j = 0; j < n; j++) {
        const double tf = m->jdef[m->qj[j]].friction;
        double tau, *w;
        if (!(tf > 0))
            continue;
        w = m->wcol[j] >= 0 ? W + (size_t) m->wcol[j] * n : r->tmp;
        rj__rig_unit(m, r, j, w);
        tau = rj__friction(qd[j] + f->kick * qdd[j], f->kick * w[j], tf);
        for (k = 0; k < n; k++)
            qdd[k] += w[k] * tau;
        RJ__FJ(m, f->next, m->qj[j])[RJ__JD_TQ0 + RJ_TORQUE_FRICTION] = tau;
    }
    if (m->nloop)
        rj__rig_loop_friction(m, f, r);
}

/* Rigid step, stage 5a: velocity-level methods, joint by joint: an impulse along q_j to e
   times the reversed rate (plastic while locked or for forced displacement). r->h keeps the
   rates before the jumps. */
static RJ__FORCE_INLINE void rj__rig_single_impulses(const rj_model *m, const rj__frames *f,
                                                     rj__rig *r, rj__rig_jumps *jumps)
{
    const int n = m->nq;
    const double *RJ__RESTRICT q = r->q;
    double *RJ__RESTRICT qdp = r->qdp, *RJ__RESTRICT rates_before = r->h, *W = r->W;
    int *ni = f->new_flags;
    int j, k;
    for (j = 0; j < n; j++) {
        const int jj = m->qj[j];
        const rj_joint_def *d = &m->jdef[jj];
        double e, lam, *w;
        if (!(d->method == RJ_METHOD_MOMENTUM || d->method == RJ_METHOD_FORCED))
            continue;
        /* re-contact within the step, as for flexible links */
        if (ni[jj] == RJ_FREE && q[j] <= m->jnt[jj].rev && qdp[j] < 0)
            ni[jj] = RJ_AT_REVERSE;
        if (ni[jj] == RJ_FREE && q[j] >= m->jnt[jj].fwd && qdp[j] > 0)
            ni[jj] = RJ_AT_FORWARD;
        if (ni[jj] == RJ_FREE || !rj__into_limit(ni[jj], qdp[j]))
            continue;
        e = (d->method == RJ_METHOD_MOMENTUM && ni[jj] != RJ_LOCKED) ? d->restitution : 0.0;
        if (!jumps->count)
            for (k = 0; k < n; k++)
                rates_before[k] = qdp[k];
        jumps->count++;
        jumps->last = j;
        if (ni[jj] != f->old_flags[jj] || e > 0)
            jumps->impact = 1;
        /* stage 3 made the column of a joint with friction */
        w = W + (size_t) m->wcol[j] * n;
        if (!(d->friction > 0))
            rj__rig_unit(m, r, j, w);
        lam = (-e * qdp[j] - qdp[j]) / w[j];
        for (k = 0; k < n; k++)
            qdp[k] += w[k] * lam;
    }
}

/* Rigid step, stage 5b: the jumps' loss in the kinetic energy's form: 1/2 q'^{n-1/2} M
   (q'_before - q'_after) now, 1/2 q'_after M (q'_before - q'_after) with the next step
   (pending); the generalised impulse along q_j is the latch's angular impulse on body 2. */
static RJ__FORCE_INLINE void rj__rig_jump_loss(const rj_model *m, const rj__frames *f,
                                               rj__rig *r, rj__sums *e)
{
    const int n = m->nq, first = f->first;
    const double *RJ__RESTRICT qd = r->qd, *RJ__RESTRICT qdp = r->qdp;
    const double *RJ__RESTRICT rates_before = r->h;
    double *jump = r->ab + RJ__AB_COUNT * (size_t) n, *m_jump = jump + n;
    double *new_joints = RJ__FJ(m, f->next, 0);
    double lost_limit = e->lost_limit, pending = e->pending;
    int j;
    /* M (q'_before - q'_after): the generalised impulses */
    for (j = 0; j < n; j++)
        jump[j] = rates_before[j] - qdp[j];
    rj__rig_mul(m, r, jump, m_jump);
    for (j = 0; j < n; j++) {
        const rj__joint *J = &m->jnt[m->qj[j]];
        double *record = new_joints + (size_t) RJ__JD_COUNT * m->qj[j];
        /* an exact coupling's or a loop's share of the joint's impulse (its work is the
           limits') */
        const double coupled = m->nexact || m->nloop ? r->x[j] : 0.0;
        /* the first step's q'^{-1/2} is 2 q'(0) less the rates before any impulse */
        const double back = first ? 2 * qd[j] - rates_before[j] : qd[j];
        double sum = m_jump[j];
        /* a prescribed loop joint's share is its drive's work, not a latch's */
        if (m->nloop) {
            e->drive += 0.5 * back * r->xd[j];
            e->drive_pending += 0.5 * qdp[j] * r->xd[j];
            sum += r->xd[j];
        }
        /* a prescribed joint's impulse, less a coupling's, is its drive's: torque and work */
        if (rj__prescribed(J)) {
            const double driven = sum + coupled;
            e->drive -= 0.5 * back * driven;
            e->drive_pending -= 0.5 * qdp[j] * driven;
            record[RJ__JD_TQ0 + RJ_TORQUE_DRIVE] = -driven / f->kick;
            sum = -coupled;
        }
        lost_limit += 0.5 * back * sum;
        pending += 0.5 * qdp[j] * sum;
        /* the latches' impulse: less an exact coupling's, reported as a torque */
        if (!rj__prescribed(J))
            record[RJ__JD_IMPULSE] = -sum - coupled;
    }
    e->lost_limit = lost_limit;
    e->pending = pending;
}

/* Rigid step, stages 4 and 5: rates q'^{n+1/2}, then the velocity-level limit methods.
   Without an impact the jumps only keep locked joints and resting contacts at rest, and
   (q'^{n+1/2} - q'^{n-1/2}) / kick is the constrained acceleration: the next step's
   centripetal terms predict q'^{n+1} from it, not from the unconstrained one, which turns a
   locked joint at up to dt / 2 times its reaction over its inertia. */
static RJ__FORCE_INLINE void rj__rig_stage_rates(const rj_model *m, const rj_state *s,
                                                 const rj__frames *f, rj__rig *r, rj__sums *e)
{
    const int n = m->nq;
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
    rj__rig_single_impulses(m, f, r, &jumps);
    if (!jumps.count && !m->npres && !m->nexact && !m->nloop)
        return;
    if (!jumps.count)
        for (j = 0; j < n; j++)
            r->h[j] = qdp[j];
    rj__rig_rows(m, s, f, r, &jumps);
    if (!jumps.impact)
        for (j = 0; j < n; j++)
            qdd[j] = (qdp[j] - qd[j]) / kick;
    rj__rig_jump_loss(m, f, r, e);
}

/* Forced displacement at the joints that close loops, on positions: a loop joint past its
   limit, or off its lock angle, goes back to it with the projection (dq, rows at dt = 1),
   as a tree joint's angle is put back; its rate is the plastic row's. q: the angles at
   n + 1; g: nq doubles of scratch. */
static void rj__rig_loop_forced(const rj_model *m, const rj__frames *f, const double *q,
                                double *g, rj__rows *R)
{
    int j, k;
    for (j = 0; j < m->nj; j++) {
        const int flag = f->new_flags[j];
        const rj__joint *J = &m->jnt[j];
        double theta = m->jdef[j].angle0, back = 0;
        rj__row *row;
        if (m->jq[j] >= 0 || m->jdef[j].method != RJ_METHOD_FORCED || flag == RJ_FREE)
            continue;
        rj__rig_loop_gradient(m, j, g);
        for (k = 0; k < m->nq; k++)
            theta += g[k] * (q[k] - m->jdef[m->qj[k]].angle0);
        if (flag == RJ_LOCKED)
            back = RJ__FJ(m, f->next, j)[RJ__JD_LOCK] - theta;
        else if (flag == RJ_AT_FORWARD && theta > J->fwd)
            back = J->fwd - theta;
        else if (flag == RJ_AT_REVERSE && theta < J->rev)
            back = J->rev - theta;
        else
            continue;
        row = rj__row_open(R, RJ__ROW_LOCK, -1 - j, back, -HUGE_VAL, HUGE_VAL);
        rj__rig_joint_terms(m, R, row, j, 1.0, g);
    }
}

/* The loops closed at n + 1: the coordinates' angles moved by the least (in M's metric)
   that puts every loop joint's pins together, dq = M^-1 J^T (J M^-1 J^T)^-1 (-gap) (the
   loops' rows on positions, two Newton passes), so that they do not drift apart over a
   long run. */
static void rj__rig_loops_project(const rj_model *m, const rj_state *s, const rj__frames *f,
                                  rj__rig *r)
{
    /* r->h (the bias, spent by now) takes the step dq; r->tmp's second half q */
    double *new_joints = RJ__FJ(m, f->next, 0), *q = r->tmp + m->nq, *dq = r->h;
    rj__rows R;
    rj__dense D;
    int pass, k;
    R.row = s->rows;
    R.term = s->terms;
    rj__rig_dense(m, r, &D);
    D.held = -1;
    for (pass = 0; pass < 2; pass++) {
        for (k = 0; k < m->nq; k++) {
            q[k] = new_joints[(size_t) RJ__JD_COUNT * m->qj[k] + RJ__JD_THETA];
            dq[k] = 0;
        }
        rj__rig_kin(m, r, q, NULL, r->qdp);
        R.count = R.terms = 0;
        rj__rig_loop_rows(m, r, 1.0, &R);
        rj__rig_loop_forced(m, f, q, r->tmp, &R);
        rj__rows_solve_dense(&R, &D, dq);
        for (k = 0; k < m->nq; k++)
            new_joints[(size_t) RJ__JD_COUNT * m->qj[k] + RJ__JD_THETA] += dq[k];
    }
}

/* Rigid step, stage 6b, the joints that close loops: the loops closed at n + 1
   (rj__rig_loops_project), then each loop joint's angle and rate from the coordinates
   (angle0 + g . (q - q(0)), g . q'), and its element's work as any joint's; r->qdp
   keeps q'^{n+1/2}. */
static void rj__rig_loops_close(const rj_model *m, const rj_state *s, const rj__frames *f,
                                const rj__rig *r, int applied, rj__sums *e,
                                double *lost_damping, double *lost_friction, double *lost_limit)
{
    const double *old_joints = RJ__FJ(m, f->old, 0);
    double *new_joints = RJ__FJ(m, f->next, 0), *g = r->tmp;
    rj__rig scratch = *r; /* the same arrays: the projection's kinematics write them */
    int j, k;
    rj__rig_loops_project(m, s, f, &scratch);
    for (j = 0; j < m->nj; j++) {
        const double *old_joint = old_joints + (size_t) RJ__JD_COUNT * j;
        double *new_joint = new_joints + (size_t) RJ__JD_COUNT * j;
        double turn = 0, rate = 0;
        if (m->jq[j] >= 0)
            continue;
        rj__rig_loop_gradient(m, j, g);
        for (k = 0; k < m->nq; k++) {
            const int jk = m->qj[k];
            turn += g[k] * (new_joints[(size_t) RJ__JD_COUNT * jk + RJ__JD_THETA] -
                            m->jdef[jk].angle0);
            rate += g[k] * r->qdp[k];
        }
        new_joint[RJ__JD_THETA] = m->jdef[j].angle0 + turn;
        new_joint[RJ__JD_RATE] = rate;
        new_joint[RJ__JD_QDD] = 0;
        rj__element_work(old_joint, new_joint, old_joint[RJ__JD_RATE], f->dt, lost_damping,
                         lost_friction, lost_limit);
        if (applied)
            e->work += rj__input_work(old_joint, new_joint, old_joint[RJ__JD_RATE], f->dt);
        /* a prescribed loop joint's work is its row's (rj__rig_jump_loss) */
        if (m->jnt[j].act && !rj__prescribed(&m->jnt[j]))
            e->drive += rj__drive_work(old_joint, new_joint, old_joint[RJ__JD_RATE], f->dt);
    }
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
    const int n = m->nq;
    double lost_damping = e->lost_damping;
    double lost_friction = e->lost_friction;
    double lost_limit = e->lost_limit;
    const int *ni = f->new_flags;
    const int applied = s->inputs || m->nload || s->node_inputs; /* RJ__JD_INPUT written */
    int j;
    for (j = 0; j < n; j++) {
        const int jj = m->qj[j];
        const rj_joint_def *d = &m->jdef[jj];
        const double *old_joint = old_joints + (size_t) RJ__JD_COUNT * jj;
        double *new_joint = new_joints + (size_t) RJ__JD_COUNT * jj;
        double qn = q[j] + dt * qdp[j];
        if (d->method == RJ_METHOD_FORCED && ni[jj] != RJ_FREE) {
            const rj__joint *J = &m->jnt[jj];
            if (ni[jj] == RJ_AT_FORWARD && qn > J->fwd)
                qn = J->fwd;
            else if (ni[jj] == RJ_AT_REVERSE && qn < J->rev)
                qn = J->rev;
            else if (ni[jj] == RJ_LOCKED)
                qn = new_joint[RJ__JD_LOCK];
        }
        if (!(fabs(qn - q[j]) <= 0.5 * RJ__PI))
            return rj__stop(m, s, RJ_ERR_TUNNEL,
                            "t = %.9g s: joint %d turned %.4g rad in one step (more than a quarter "
                            "revolution, pi/2 rad): the step %g s is far too large for its speed",
                            f->t, jj, qn - q[j], dt);
        new_joint[RJ__JD_THETA] = qn;
        new_joint[RJ__JD_RATE] = qdp[j];
        new_joint[RJ__JD_QDD] = qdd[j];
        rj__element_work(old_joint, new_joint, qd[j], dt, &lost_damping, &lost_friction,
                         &lost_limit);
        if (applied)
            e->work += rj__input_work(old_joint, new_joint, qd[j], dt);
        if (m->jnt[jj].act && !rj__prescribed(&m->jnt[jj]))
            e->drive += rj__drive_work(old_joint, new_joint, qd[j], dt);
    }
    if (m->nloop)
        rj__rig_loops_close(m, s, f, r, applied, e, &lost_damping, &lost_friction, &lost_limit);
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

/* Rigid step, stage 7: the losses and work (every step); on the steps that take the energy
   accounts (f->en, as for flexible links: solver.energy_every) the kinetic energy
   1/2 q'^{n-1/2} M q'^{n+1/2} (q'^{-1/2} = 2 q'(0) - q'^{1/2}) and the energy tests;
   commit (nodes are computed when queried: rj__rig_pose). */
static RJ__FORCE_INLINE rj_result rj__rig_stage_accounts(const rj_model *m, rj_state *s,
                                                         const rj__frames *f, rj__rig *r,
                                                         rj__sums *e)
{
    const int n = m->nq, first = f->first;
    const double *RJ__RESTRICT qd = r->qd, *RJ__RESTRICT qdp = r->qdp;
    double *m_qdp = r->ab + RJ__AB_COUNT * (size_t) n;
    double *new_scalars = f->new_scalars;
    double ke = 0;
    rj_result res;
    int j;
    new_scalars[RJ__FS_LDAMP] = e->lost_damping;
    new_scalars[RJ__FS_LFRIC] = e->lost_friction;
    new_scalars[RJ__FS_LLIM] = e->lost_limit;
    new_scalars[RJ__FS_PEND] = e->pending;
    new_scalars[RJ__FS_WORK] = e->work;
    new_scalars[RJ__FS_DRIVE] = e->drive;
    new_scalars[RJ__FS_DPEND] = e->drive_pending;
    if (m->nact)
        rj__drive_flow(f->old_scalars, new_scalars, e);
    if (!f->en) {
        s->cur = 1 - s->cur;
        s->steps++;
        return RJ_OK;
    }
    rj__rig_mul(m, r, qdp, m_qdp);
    for (j = 0; j < n; j++) {
        const double sum = m_qdp[j];
        /* the first step's q'^{-1/2}: 2 q'(0) less the rates before the step's impulses
           (kept in Q by rj__rig_stage_rates), which an impulse does not move */
        ke += 0.5 * (first ? 2 * qd[j] - r->Q[j] : qd[j]) * sum;
    }
    e->kinetic = ke;
    new_scalars[RJ__FS_KE] = ke;
    if (m->has_gravity)
        rj__gravity_flow(f->old_scalars, new_scalars, e);
    new_scalars[RJ__FS_GRAV] = e->gravity;
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
static rj_result rj__step_rigid(const rj_model *m, rj_state *s, int want_energy)
{
    rj__frames f;
    rj__sums e;
    rj__rig r;
    rj_result res;
    rj__frames_open(m, s, want_energy, 0, &f);
    rj__sums_open(f.old_scalars, &e);
    rj__rig_map(m, s->rsc, &r, 1);
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

