/* ------------------------------------------------------------------ a failed step: its message */
static rj_result rj__stop(const rj_model *m, rj_state *s, rj_result r, const char *fmt, ...)
{
    va_list ap;
    int wanted;
    (void) m;
    va_start(ap, fmt);
    wanted = vsnprintf(s->err, sizeof s->err, fmt, ap);
    va_end(ap);
    rj__fit_words(s->err, sizeof s->err, wanted);
    return r;
}

/* Where a rigid scene's blow-up shows: the fastest joint of the new frame and its
   rotation per step. In joint coordinates no stiffness bounds the step; the step's energy
   error is second order in dt, and grows where a long chain whips or folds on itself (its
   mass matrix nears singular), which no bound foresees. */
static void rj__rig_fastest(const rj_model *m, const rj_state *s, char *where, size_t size)
{
    const double *next = s->fd[1 - s->cur];
    double fastest = 0;
    int j, worst = -1;
    for (j = 0; j < m->nj; j++) {
        const double rate = fabs(RJ__FJ(m, next, j)[RJ__JD_RATE]);
        if (rate > fastest) {
            fastest = rate;
            worst = j;
        }
    }
    if (worst < 0 || !rj__finite(fastest)) {
        snprintf(where, size, "rigid links in joint coordinates");
        return;
    }
    snprintf(where, size,
             "rigid links in joint coordinates (fastest joint %d at %.4g rad/s, %.3g rad a "
             "step): the step's energy error is second order in dt (half the step, a quarter "
             "of the error) and grows as a long chain whips or folds; a smaller solver.dt, "
             "or inextensible links for a chain of many",
             worst, fastest, fastest * m->dt);
}

/* The causes of a blow-up that this model can have, for the step's messages: only what
   the model holds (a step above the bound, loads whose work is most of the energy in
   motion, limits and how they respond, stiff joints), else what every model has (fast
   rotation, which the linearised bound leaves out). */
static const char *rj__blowup_causes(const rj_model *m, int applied, double work, double moving,
                                     char *buf, size_t size)
{
    int j, stiff_limit = 0, velocity_limit = 0, springs = 0;
    if (m->dt > m->dt_bound)
        return "the step is above the stability bound: use a smaller solver.dt, or 0 for the "
               "automatic step";
    /* loads and the caller's inputs whose work is most of the energy in motion */
    if (applied && fabs(work) > 0.5 * moving && work == work) {
        snprintf(buf, size,
                 "the applied loads and the caller's torques and forces (%.3g J of work): "
                 "loads that large move the model faster than its step can follow",
                 -work);
        return buf;
    }
    for (j = 0; j < m->nj; j++) {
        const rj_joint_def *d = &m->jdef[j];
        const int limits = d->has_forward || d->has_reverse;
        if (limits && (d->method == RJ_METHOD_PENALTY || d->method == RJ_METHOD_ADAPTIVE))
            stiff_limit = 1;
        if (limits && d->method != RJ_METHOD_PENALTY && d->method != RJ_METHOD_ADAPTIVE)
            velocity_limit = 1;
        if (d->spring_k > 0 || d->table_count > 0)
            springs = 1;
    }
    buf[0] = 0;
    if (applied)
        rj__cat(buf, size,
                "the applied loads or the caller's torques and forces, if they move a node "
                "farther in a step than its elements can follow; ");
    if (stiff_limit)
        rj__cat(buf, size,
                "a penalty or adaptive limit caught late (it stores about the relative kinetic "
                "energy when it catches a joint a rate x dt past its limit): RJ_METHOD_MOMENTUM "
                "catches it without a stiffness; ");
    if (velocity_limit)
        rj__cat(buf, size, "contact chatter at a limit; ");
    if (springs)
        rj__cat(buf, size, "a joint spring or table stiffer than the bound counts (Eq 31); ");
    rj__cat(buf, size,
            "fast rotation (its centrifugal and Coriolis terms are not in the linearised bound): a "
            "smaller solver.dt");
    return buf;
}

/* Names the node with the largest speed in the new frame, for blow-up reports. */
static void rj__worst_node(const rj_model *m, const double *f, int *link, int *node)
{
    const double *vx = RJ__FVX(m, f), *vy = RJ__FVY(m, f);
    double best = -1;
    int i, worst = 0;
    for (i = 0; i < m->nn; i++) {
        double v = vx[i] * vx[i] + vy[i] * vy[i];
        if (!(v <= best)) {
            best = v;
            worst = i;
            if (!(v == v))
                break;
        }
    }
    rj__node_of(m, worst, link, node);
}

/* A step that wrote a non-finite value stops, naming the first such node (or joint). */
static rj_result rj__stop_nonfinite(const rj_model *m, rj_state *s, const double *f, double t)
{
    const double *v[6];
    int i, k, link, node;
    v[0] = RJ__FX(m, f);
    v[1] = RJ__FY(m, f);
    v[2] = RJ__FPHI(m, f);
    v[3] = RJ__FVX(m, f);
    v[4] = RJ__FVY(m, f);
    v[5] = RJ__FW(m, f);
    for (i = 0; i < m->nn; i++)
        for (k = 0; k < 6; k++)
            if (!rj__finite(v[k][i])) {
                const char *what = k == 0   ? "x"
                                   : k == 1 ? "y"
                                   : k == 2 ? "rotation"
                                   : k == 3 ? "x velocity"
                                   : k == 4 ? "y velocity"
                                            : "rotation rate";
                rj__node_of(m, i, &link, &node);
                return rj__stop(
                    m, s, RJ_ERR_BLOWUP,
                    "t = %.9g s: link %d node %d's %s became %g: the state is no longer finite%s",
                    t, link, node, what, v[k][i],
                    m->dt > m->dt_bound ? " (the step is above the stability bound)" : "");
            }
    return rj__stop(m, s, RJ_ERR_BLOWUP,
                    "t = %.9g s: a joint's angle, rate or torque, or a rigid body's motion, became "
                    "non-finite%s",
                    t, m->dt > m->dt_bound ? " (the step is above the stability bound)" : "");
}

