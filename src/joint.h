/* ------------------------------------------------------------------ the joint element */
/* Links do not contact each other: where a joint between two links turns through a
   multiple of 360 deg, its two links lie over each other and pass through. That is
   reported once per joint, as a warning and its time (rj_joint_overlap_time): when the
   angle is clearly (1 deg) inside a band of 360 deg other than the one it was last
   clearly in. A hinge stowed folded at 0 or 360 deg, or vibrating there, has not passed.
   The zone the angle is in (a band's clear inside, or a fold) is kept in the joint's
   record, so that a step costs two comparisons while the angle stays in it. */
#define RJ__OVERLAP_MARGIN 0.0174532925199432958
static void rj__overlap_band(const rj_model *m, rj_state *s, int j, double run, double t,
                             const double *oj, double *nj_, double *nsc)
{
    const double band = floor(run / RJ__TWO_PI);
    const double lo = band * RJ__TWO_PI + RJ__OVERLAP_MARGIN;
    const double hi = (band + 1) * RJ__TWO_PI - RJ__OVERLAP_MARGIN;
    const double last_lo = oj[RJ__JD_BAND];
    /* at a fold: its zone, 1 deg either side, decides nothing */
    if (run < lo || run > hi) {
        const double fold = run < lo ? band * RJ__TWO_PI : (band + 1) * RJ__TWO_PI;
        nj_[RJ__JD_ZONE_LO] = fold - RJ__OVERLAP_MARGIN;
        nj_[RJ__JD_ZONE_HI] = fold + RJ__OVERLAP_MARGIN;
        return;
    }
    nj_[RJ__JD_ZONE_LO] = lo;
    nj_[RJ__JD_ZONE_HI] = hi;
    nj_[RJ__JD_BAND] = lo;
    if (last_lo == RJ__NO_ZONE || last_lo == lo || oj[RJ__JD_OVERLAP] >= 0)
        return;
    nj_[RJ__JD_OVERLAP] = t;
    nsc[RJ__FS_WARN] += 1;
    snprintf(s->warn, sizeof s->warn,
             "t = %.9g s: joint %d turned through %.0f deg: its links %d and %d passed "
             "through each other (links do not contact each other)",
             t, j, rj_deg(lo > last_lo ? lo - RJ__OVERLAP_MARGIN : hi + RJ__OVERLAP_MARGIN),
             m->jdef[j].body1, m->jdef[j].body2);
}
static RJ__FORCE_INLINE void rj__overlap(const rj_model *m, rj_state *s, int j, double run,
                                         double t, const double *oj, double *nj_, double *nsc)
{
    if (run >= oj[RJ__JD_ZONE_LO] && run <= oj[RJ__JD_ZONE_HI])
        return;
    rj__overlap_band(m, s, j, run, t, oj, nj_, nsc);
}

/* A value within +-cap. */
static double rj__clamp(double v, double cap)
{
    return v > cap ? cap : (v < -cap ? -cap : v);
}

/* The torque of joint J's actuator on body 2 at t, the joint at its running angle run
   with the rate damping reads (rj_actuator_def). */
static double rj__drive_torque(const rj_state *s, const rj__joint *J, double run, double rate,
                               double t)
{
    const rj_actuator_def *a = J->act;
    double tq;
    switch (a->type) {
    case RJ_ACTUATOR_TORQUE:
        return a->torque * rj__time_factor(a->table_count, a->table_time, a->table_factor, t);
    case RJ_ACTUATOR_DC:
        /* off at or past the cutoff, in the direction it drives */
        if (a->has_cutoff && (a->no_load_speed > 0 ? run >= J->cut : run <= J->cut))
            return 0;
        tq = a->stall_torque * (1.0 - rate / a->no_load_speed);
        return rj__clamp(tq, fabs(a->stall_torque));
    case RJ_ACTUATOR_SERVO:
        /* its target follows the profile from start (none: ramp 0), held while settling */
        tq = a->kp * (rj__profile_angle(a, J->spline, a->target, s->settling ? a->start : t) -
                      run) -
             a->kd * rate;
        return a->torque_max > 0 ? rj__clamp(tq, a->torque_max) : tq;
    default: /* prescribed: its torque is the impulse that keeps it on its profile */
        return 0;
    }
}

/* The revolute element for one joint and one step, shared by every link model: status
   flag (Eqs 7-13), contact bookkeeping, penetration (Eq 19), and the torques on body 2 from
   the table (Eq 4), the torsion spring, damping (Eq 27) and the penalty / adaptive limit
   (Eq 22). Writes the components into the new frame's joint record (friction is added
   later) and returns the torque to apply now; *p_out receives the penetration. */
static double rj__element(const rj_model *m, rj_state *s, int j, const double *oj, double *nj_,
                          int oflag, int *nflag, double rate, double t, double *nsc, double *p_out,
                          double *v_acc)
{
    const rj_joint_def *d = &m->jdef[j];
    const rj__joint *J = &m->jnt[j];
    const double run = oj[RJ__JD_THETA];
    double tq_table = 0, tq_spring = 0, tq_damp = 0, tq_lim = 0, tq, p = 0;
    const int bf = run >= J->fwd, br = run <= J->rev;
    const int flag = rj_flag_next(oflag, bf, br, rate, d->lock, d->release);
    memcpy(nj_, oj, sizeof(double) * RJ__JD_COUNT);
    nj_[RJ__JD_IMPULSE] = 0; /* a velocity-level latch sets it in this step */
    if (flag == RJ_LOCKED && oflag != RJ_LOCKED)
        nj_[RJ__JD_LOCK] = bf ? J->fwd : J->rev;
    if (flag != RJ_FREE && oj[RJ__JD_EVENT] < 0)
        nj_[RJ__JD_EVENT] = t;
    if (flag != RJ_FREE && oflag == RJ_FREE) {
        /* a new contact: how far past the limit was it caught? */
        double p0 =
            flag == RJ_AT_FORWARD || (flag == RJ_LOCKED && bf) ? J->fwd - run : J->rev - run;
        double width =
            (rj__finite(J->fwd) && rj__finite(J->rev)) ? RJ__TWO_PI - (J->fwd - J->rev) : HUGE_VAL;
        nj_[RJ__JD_P0] = p0;
        if (fabs(p0) > RJ__LATE || fabs(p0) > width) {
            nsc[RJ__FS_WARN] += 1;
            snprintf(s->warn, sizeof s->warn,
                     "t = %.9g s: joint %d caught its limit %.4g rad late%s (rate %.4g rad/s, step "
                     "%.3g s)",
                     t, j, fabs(p0), fabs(p0) > width ? ", past the whole limited range" : "", rate,
                     m->dt);
        }
    }
    if (flag == RJ_FREE && oflag != RJ_FREE)
        nj_[RJ__JD_RELEASE] = t; /* latest release */
    if (d->body1 >= 0)
        rj__overlap(m, s, j, run, t, oj, nj_, nsc);
    *nflag = flag;
    /* Eq 19 penetration */
    if (flag == RJ_AT_FORWARD)
        p = J->fwd - run;
    else if (flag == RJ_AT_REVERSE)
        p = J->rev - run;
    else if (flag == RJ_LOCKED)
        p = nj_[RJ__JD_LOCK] - run;
    if (fabs(p) > nj_[RJ__JD_PEAKP])
        nj_[RJ__JD_PEAKP] = fabs(p);
    /* Eq 4 table, torsion spring, Eq 27 damping (resistive: minus on body 2) */
    { /* the potentials join v_acc as in rj__spring_energy */
        double tt;
        rj__joint_potential(d, J, run, v_acc, &tt);
        if (d->table_count)
            tq_table = -tt;
    }
    if (d->spring_k > 0)
        tq_spring = -d->spring_k * (run - d->spring_free_angle);
    if (d->damping > 0)
        tq_damp = -d->damping * rate;
    /* Eq 22 / penalty: tau_2 = K p while at a limit */
    if (flag != RJ_FREE && (d->method == RJ_METHOD_PENALTY || d->method == RJ_METHOD_ADAPTIVE))
        tq_lim = J->k_limit * p;
    nj_[RJ__JD_TQ0 + RJ_TORQUE_TABLE] = tq_table;
    nj_[RJ__JD_TQ0 + RJ_TORQUE_SPRING] = tq_spring;
    nj_[RJ__JD_TQ0 + RJ_TORQUE_DAMPING] = tq_damp;
    nj_[RJ__JD_TQ0 + RJ_TORQUE_LIMIT] = tq_lim;
    nj_[RJ__JD_TQ0 + RJ_TORQUE_FRICTION] = 0;
    *p_out = p;
    tq = tq_table + tq_spring + tq_damp + tq_lim;
    /* the actuator: its slot stays 0 (copied from the old record) on a joint without */
    if (J->act) {
        const double tq_drive = rj__drive_torque(s, J, run, rate, t);
        nj_[RJ__JD_TQ0 + RJ_TORQUE_DRIVE] = tq_drive;
        tq += tq_drive;
    }
    return tq;
}

/* Coulomb friction: the torque that stops the relative rotation within the step (ratep is
   the rate the step would end with, c the rate change per unit torque), capped at T_f. */
static double rj__friction(double ratep, double c, double tf)
{
    double tau = c > 0 ? -ratep / c : 0;
    return tau > tf ? tf : (tau < -tf ? -tf : tau);
}

/* Is this a velocity-level limit method (a jump in the rates at the limit)? */
static RJ__INLINE int rj__velocity_method(int method)
{
    return method == RJ_METHOD_MOMENTUM || method == RJ_METHOD_ENERGY || method == RJ_METHOD_FORCED;
}

/* Does a velocity-level method act (the rate still points into the limit, or any rate
   while locked)? */
static int rj__into_limit(int flag, double ratep)
{
    return (flag == RJ_AT_FORWARD && ratep > 0) || (flag == RJ_AT_REVERSE && ratep < 0) ||
           (flag == RJ_LOCKED && ratep != 0);
}

/* Work of the joint's non-conservative torques over the step, in the form that matches
   the kinetic energy 1/2 v^{n-1/2}.v^{n+1/2}: dt/2 (tau^n rate^{n-1/2} + tau^{n-1} times the
   previous step's end rate, same geometry). */
static RJ__FORCE_INLINE void rj__element_work(const double *oj, const double *nj_, double rate_m,
                                              double dt, double *ld, double *lf, double *ll)
{
    *ld -= 0.5 * dt *
           (nj_[RJ__JD_TQ0 + RJ_TORQUE_DAMPING] * rate_m +
            oj[RJ__JD_TQ0 + RJ_TORQUE_DAMPING] * oj[RJ__JD_RATE]);
    *lf -= 0.5 * dt *
           (nj_[RJ__JD_TQ0 + RJ_TORQUE_FRICTION] * rate_m +
            oj[RJ__JD_TQ0 + RJ_TORQUE_FRICTION] * oj[RJ__JD_RATE]);
    *ll -= 0.5 * dt *
           (nj_[RJ__JD_TQ0 + RJ_TORQUE_LIMIT] * rate_m +
            oj[RJ__JD_TQ0 + RJ_TORQUE_LIMIT] * oj[RJ__JD_RATE]);
}

/* Whether joint J's angle follows a profile (its actuator is prescribed). */
static RJ__INLINE int rj__prescribed(const rj__joint *J)
{
    return J->act && J->act->type == RJ_ACTUATOR_PRESCRIBED;
}

/* The rate that takes a prescribed joint from its running angle run at t to its profile
   at t + dt (held at its start while rj_settle runs). */
static double rj__prescribed_rate(const rj_model *m, const rj_state *s, int j, double run,
                                  double t, double dt)
{
    const rj_actuator_def *a = m->jnt[j].act;
    const double at = s->settling ? a->start : t + dt;
    return (rj__profile_angle(a, m->jnt[j].spline, m->jdef[j].angle0, at) - run) / dt;
}

/* The work of the joint's actuator over the step, in the form of rj__element_work. */
static RJ__FORCE_INLINE double rj__drive_work(const double *oj, const double *nj_, double rate_m,
                                              double dt)
{
    return 0.5 * dt *
           (nj_[RJ__JD_TQ0 + RJ_TORQUE_DRIVE] * rate_m +
            oj[RJ__JD_TQ0 + RJ_TORQUE_DRIVE] * oj[RJ__JD_RATE]);
}

/* The work of the caller's torque over the step, in the form of rj__element_work. */
static RJ__FORCE_INLINE double rj__input_work(const double *oj, const double *nj_, double rate_m,
                                              double dt)
{
    return 0.5 * dt * (nj_[RJ__JD_INPUT] * rate_m + oj[RJ__JD_INPUT] * oj[RJ__JD_RATE]);
}

