/* ------------------------------------------------------------------ joint kinematics */
/* The element needs four things from the bodies it joins: the rotary location, its rate,
   a way to apply a torque pair, and the inertias it acts on. Both reference modes supply
   them here; everything above (flags, methods, friction, energy) is shared. */
typedef struct rj__jgeo {
    double ax, ay, bx, by, a2, b2;
} rj__jgeo;

static RJ__INLINE void rj__joint_geo(const rj_model *m, const rj__joint *J, const double *x,
                                     const double *y, rj__jgeo *g)
{
    (void) m;
    if (!J->chord) {
        g->ax = g->ay = g->bx = g->by = 0;
        g->a2 = g->b2 = 1;
        return;
    }
    if (J->nK >= 0) {
        g->ax = x[J->nK] - x[J->nI];
        g->ay = y[J->nK] - y[J->nI];
    } else {
        g->ax = J->gax;
        g->ay = J->gay;
    }
    g->bx = x[J->nL] - x[J->nJ];
    g->by = y[J->nL] - y[J->nJ];
    g->a2 = g->ax * g->ax + g->ay * g->ay;
    g->b2 = g->bx * g->bx + g->by * g->by;
}

/* raw rotary location: chord mode atan2 in (-pi, pi] (to be unwrapped), tangent mode the
   running angle itself */
static RJ__INLINE double rj__joint_raw(const rj__joint *J, const rj__jgeo *g, const double *phi)
{
    if (J->chord)
        return atan2(g->ax * g->by - g->ay * g->bx, g->ax * g->bx + g->ay * g->by);
    return J->off + phi[J->nJ] - (J->nI >= 0 ? phi[J->nI] : 0.0);
}

/* theta_dot = omega_2 - omega_1; chord mode omega = (r x v_r) / |r|^2 (from Eqs 1-3) */
static RJ__INLINE double rj__joint_rate(const rj__joint *J, const rj__jgeo *g, const double *vx,
                                        const double *vy, const double *w, double *w1, double *w2)
{
    double o1 = 0.0, o2;
    if (J->chord) {
        if (J->nK >= 0)
            o1 = (g->ax * (vy[J->nK] - vy[J->nI]) - g->ay * (vx[J->nK] - vx[J->nI])) / g->a2;
        o2 = (g->bx * (vy[J->nL] - vy[J->nJ]) - g->by * (vx[J->nL] - vx[J->nJ])) / g->b2;
    } else {
        if (J->nI >= 0)
            o1 = w[J->nI];
        o2 = w[J->nJ];
    }
    if (w1)
        *w1 = o1;
    if (w2)
        *w2 = o2;
    return o2 - o1;
}

/* Torque tau on body 2 and -tau on body 1. Chord mode: force couples on J-L and I-K,
   F_L = tau perp(b)/|b|^2 = -F_J, F_K = -tau perp(a)/|a|^2 = -F_I. Tangent mode: moments
   on the pin nodes' rotations. Either way the force is tau times the gradient of theta. */
static RJ__INLINE void rj__apply_torque(const rj__joint *J, const rj__jgeo *g, double tau,
                                        double *fx, double *fy, double *mz)
{
    double sx, sy;
    if (!J->chord) {
        mz[J->nJ] += tau;
        if (J->nI >= 0)
            mz[J->nI] -= tau;
        return;
    }
    sx = -tau * g->by / g->b2;
    sy = tau * g->bx / g->b2;
    fx[J->nL] += sx;
    fy[J->nL] += sy;
    fx[J->nJ] -= sx;
    fy[J->nJ] -= sy;
    if (J->nK >= 0) {
        sx = tau * g->ay / g->a2;
        sy = -tau * g->ax / g->a2;
        fx[J->nK] += sx;
        fy[J->nK] += sy;
        fx[J->nI] -= sx;
        fy[J->nI] -= sy;
    }
}

/* g^T M^-1 g: rate change per unit torque impulse (1/I_red, with the pin's own mass). */
static RJ__INLINE double rj__joint_compliance(const rj_model *m, const rj__joint *J,
                                              const rj__jgeo *g)
{
    double c, px, py;
    if (!J->chord) {
        /* a rotor's reflected inertia on the relative rotation (rj__stage_rotors) */
        c = m->rinv[J->nJ] + (J->nI >= 0 ? m->rinv[J->nI] : 0.0);
        return J->rotor > 0 ? c / (1.0 + J->rotor * c) : c;
    }
    c = m->einv[J->nL] / g->b2;
    px = g->by / g->b2;
    py = -g->bx / g->b2; /* g_J = -perp(b)/|b|^2 */
    if (J->nK >= 0) {
        c += m->einv[J->nK] / g->a2;
        px += -g->ay / g->a2;
        py += g->ax / g->a2; /* g_I = perp(a)/|a|^2 */
    }
    c += m->einv[J->nJ] * (px * px + py * py);
    return c;
}

/* Adds rotation increments dw1 to body 1's and dw2 to body 2's reference (node K / L
   velocities in chord mode, pin rotations in tangent mode). */
static void rj__spin(const rj__joint *J, const rj__jgeo *g, double dw1, double dw2, double *vx,
                     double *vy, double *w)
{
    if (!J->chord) {
        w[J->nJ] += dw2;
        if (J->nI >= 0)
            w[J->nI] += dw1;
        return;
    }
    vx[J->nL] += -dw2 * g->by;
    vy[J->nL] += dw2 * g->bx;
    if (J->nK >= 0) {
        vx[J->nK] += -dw1 * g->ay;
        vy[J->nK] += dw1 * g->ax;
    }
}

/* Turns body 2's reference by d2 and body 1's by d1 (forced displacement). */
/* The positions of a joint's nodes summed: finite while they all are. */
static double rj__joint_nodes_sum(const rj__joint *J, const double *x, const double *y,
                                  const double *phi)
{
    const int nodes[4] = { J->nI, J->nK, J->nJ, J->nL };
    double sum = 0;
    int k;
    for (k = 0; k < 4; k++)
        if (nodes[k] >= 0)
            sum += (x[nodes[k]] + y[nodes[k]]) + phi[nodes[k]];
    return sum;
}

static void rj__turn(const rj__joint *J, double d1, double d2, double *x, double *y, double *phi)
{
    double c, sn, rx, ry;
    if (!J->chord) {
        phi[J->nJ] += d2;
        if (J->nI >= 0)
            phi[J->nI] += d1;
        return;
    }
    if (d2 != 0) {
        c = cos(d2);
        sn = sin(d2);
        rx = x[J->nL] - x[J->nJ];
        ry = y[J->nL] - y[J->nJ];
        x[J->nL] = x[J->nJ] + c * rx - sn * ry;
        y[J->nL] = y[J->nJ] + sn * rx + c * ry;
    }
    if (d1 != 0 && J->nK >= 0) {
        c = cos(d1);
        sn = sin(d1);
        rx = x[J->nK] - x[J->nI];
        ry = y[J->nK] - y[J->nI];
        x[J->nK] = x[J->nI] + c * rx - sn * ry;
        y[J->nK] = y[J->nI] + sn * rx + c * ry;
    }
}

/* Table and spring: resistive torque on body 2 is -(table + spring); potential energy. */
static double rj__table_turns_potential(const rj_joint_def *d, const rj__joint *J, double run,
                                        double *torque)
{
    double th = rj__mod2pi(run), turns = floor(run / RJ__TWO_PI);
    *torque = rj_table_torque(d->table_angle, d->table_torque, d->table_count, th);
    return rj__table_potential(d->table_angle, d->table_torque, d->table_count, th) +
           turns * J->tv_turn;
}

/* ------------------------------------------------------------------ model build */
/* Places link l straight at angle ang with its node at on (px, py), turning at om about
   it while that node moves at (vpx, vpy). */
static void rj__place(const rj_model *m, int l, int at, double px, double py, double ang,
                      double vpx, double vpy, double om, double *x, double *y, double *phi,
                      double *vx, double *vy, double *w)
{
    int i, n0 = m->link_first[l], ne = m->ldef[l].elements;
    double c = cos(ang), s = sin(ang), l0 = m->link_l0[l];
    for (i = 0; i <= ne; i++) {
        double rx = c * l0 * (i - at), ry = s * l0 * (i - at);
        x[n0 + i] = px + rx;
        y[n0 + i] = py + ry;
        phi[n0 + i] = ang;
        vx[n0 + i] = vpx - om * ry;
        vy[n0 + i] = vpy + om * rx;
        w[n0 + i] = om;
    }
}


/* Coupling c's torques on joint b, elastic and damping (joint a takes -ratio times each),
   from the joints' running angles and rates; *energy gains the cable's 1/2 k e^2. */
static void rj__coupling_torques(const rj_model *m, const rj_coupling_def *c, double th_a,
                                 double th_b, double w_a, double w_b, double *elastic,
                                 double *damp, double *energy)
{
    const double turn_a = th_a - m->jdef[c->joint_a].angle0;
    const double turn_b = th_b - m->jdef[c->joint_b].angle0;
    const double e = turn_b - c->ratio * turn_a - c->offset;
    *elastic = -c->stiffness * e;
    *damp = -c->damping * (w_b - c->ratio * w_a);
    *energy += 0.5 * c->stiffness * e * e;
}

/* Coupling c's torques into the two joints' new records (their spring and damping
   components); returns the total on joint b. */
static double rj__coupling_record(const rj_coupling_def *c, double elastic, double damp,
                                  double *rec_a, double *rec_b)
{
    rec_b[RJ__JD_TQ0 + RJ_TORQUE_SPRING] += elastic;
    rec_b[RJ__JD_TQ0 + RJ_TORQUE_DAMPING] += damp;
    rec_a[RJ__JD_TQ0 + RJ_TORQUE_SPRING] -= c->ratio * elastic;
    rec_a[RJ__JD_TQ0 + RJ_TORQUE_DAMPING] -= c->ratio * damp;
    return elastic + damp;
}
