/* ------------------------------------------------------------------ settling */
/* Every velocity of the current frame to zero: nodes, bodies, joint rates (and the rigid
   solver's predicted accelerations). The state then starts again from rest where it is:
   the next step is a first step (a half kick, the energy accounts from there), and the
   in-place copy is dropped, as it would replay steps from before the change. */
static void rj__zero_velocities(const rj_model *m, rj_state *s)
{
    double *f = s->fd[s->cur];
    int i;
    memset(RJ__FVX(m, f), 0, sizeof(double) * (size_t) m->nn);
    memset(RJ__FVY(m, f), 0, sizeof(double) * (size_t) m->nn);
    memset(RJ__FW(m, f), 0, sizeof(double) * (size_t) m->nn);
    for (i = 0; i < m->ncl; i++) {
        double *c = RJ__FCL(m, f, i);
        c[2] = c[3] = c[4] = 0;
    }
    for (i = 0; i < m->nj; i++) {
        double *jd = RJ__FJ(m, f, i);
        jd[RJ__JD_RATE] = 0;
        jd[RJ__JD_QDD] = 0;
    }
    s->snap = -1;
    s->steps = 0;
    s->at_n = RJ__AT_N_NONE;
    s->loop_force[2 * m->nj] = -1;
}

/* The settled state as a new start: step count, accounts and joint events from zero; time
   goes on from where the settling left it, so that a load's table reads on from the value
   it settled under. */
static void rj__restart(const rj_model *m, rj_state *s)
{
    double *f = s->fd[s->cur];
    double *sc = RJ__FS(m, f);
    const double warn = sc[RJ__FS_WARN], strain = sc[RJ__FS_STRAIN];
    const double spring = sc[RJ__FS_SPRING], gravity = sc[RJ__FS_GRAV];
    const double time = sc[RJ__FS_TIME];
    int j;
    rj__zero_velocities(m, s);
    /* a new start: the peaks too (their tracking stays as it was) */
    rj__peaks_clear(m, s);
    /* the potential energies of the last step stand until the first step takes them again */
    memset(sc, 0, sizeof(double) * RJ__FS_COUNT);
    sc[RJ__FS_TIME] = time;
    sc[RJ__FS_ETIME] = time;
    sc[RJ__FS_WARN] = warn;
    sc[RJ__FS_STRAIN] = strain;
    sc[RJ__FS_SPRING] = spring;
    sc[RJ__FS_GRAV] = gravity;
    sc[RJ__FS_E0] = strain + spring + gravity;
    for (j = 0; j < m->nj; j++) {
        double *jd = RJ__FJ(m, f, j);
        jd[RJ__JD_EVENT] = -1;
        jd[RJ__JD_RELEASE] = -1;
        jd[RJ__JD_OVERLAP] = -1;
        jd[RJ__JD_PEAKP] = 0;
        jd[RJ__JD_IMPULSE] = 0;
    }
}

/* The potential energy the settling has moved: strain and springs, and gravity's change. */
static double rj__settle_scale(const double *sc, double gravity_start)
{
    return fabs(sc[RJ__FS_STRAIN]) + fabs(sc[RJ__FS_SPRING]) +
           fabs(sc[RJ__FS_GRAV] - gravity_start) + 1e-300;
}

/* The energy of round-off: what a link stores when it is stretched by 64 ulps of its
   length, EA L (64 eps)^2, summed over the links. A kinetic energy below it cannot be
   told from rest, whatever the tolerance asks: it is the absolute floor of rj_settle's
   threshold (a 1 m aluminium link at rest shows peaks of 1e-21 J from round-off alone,
   against a floor of 1.4e-19 J; a 2000-element cantilever's first step from rest under
   gravity has 2e-15 J). */
static double rj__settle_floor(const rj_model *m)
{
    const double slip = 64.0 * DBL_EPSILON;
    double floor_energy = 0;
    int l;
    for (l = 0; l < m->nl; l++)
        floor_energy += m->link_EA[l] * m->ldef[l].length * slip * slip;
    return floor_energy;
}

/* The time from which every load is constant: its table's last point (it holds its last
   factor after it); 0 without tables. */
static double rj__loads_steady_time(const rj_model *m)
{
    double steady = 0;
    int k;
    for (k = 0; k < m->nload; k++) {
        const rj_load_def *d = &m->load[k];
        if (d->table_count > 0 && d->table_time[d->table_count - 1] > steady)
            steady = d->table_time[d->table_count - 1];
    }
    return steady;
}

/* What rj_settle carries from step to step. */
typedef struct rj__settle_run {
    double previous;     /* the kinetic energy of the step before, J */
    double last_peak;    /* the kinetic energy at the latest peak, J */
    double gravity;      /* gravity's potential at the start, J */
    double floor_energy; /* the threshold's absolute floor, J (rj__settle_floor) */
    double steady;       /* the time from which the loads are constant, s */
    long rise;           /* steps since the last restart from rest */
    long longest_rise;   /* the longest rise from rest to a peak seen so far */
    long quiet;          /* steps below the threshold since checking began (-1: not checking) */
} rj__settle_run;

/* One settling step's verdict on the kinetic energy ke against the threshold limit:
   1 settled; 0 go on; the velocities are zeroed at a peak. A peak below the threshold
   starts the check, and so does a kinetic energy that stays exactly where it was below it
   (nothing moves: a scene already at rest has no peak to show). */
static int rj__settle_judge(const rj_model *m, rj_state *s, rj__settle_run *q, double ke,
                            double limit)
{
    q->rise++;
    if (q->quiet >= 0) {
        /* checking: quiet for long enough means settled; a rise means not yet */
        if (ke > limit)
            q->quiet = -1;
        else if (++q->quiet >= q->longest_rise + q->longest_rise / 2)
            return 1;
    }
    /* rising, or the first step from rest (its kinetic energy, negative in the central
       difference's form, is no peak) */
    if (ke > q->previous || (ke == q->previous && ke > limit) || q->rise == 1) {
        q->previous = ke;
        return 0;
    }
    /* past a peak, or at rest */
    q->last_peak = q->previous;
    if (q->quiet < 0 && q->previous <= limit)
        q->quiet = 0;
    if (q->quiet < 0) {
        if (q->rise > q->longest_rise)
            q->longest_rise = q->rise;
        rj__zero_velocities(m, s);
        q->previous = 0;
        q->rise = 0;
    }
    return 0;
}

/* The settling's start: from rest, with the threshold's floor, the time from which the
   loads are constant, and gravity's potential to measure what it moves from. */
static void rj__settle_start(const rj_model *m, rj_state *s, rj__settle_run *q)
{
    q->previous = 0;
    q->last_peak = 0;
    q->gravity = RJ__FS(m, s->fd[s->cur])[RJ__FS_GRAV];
    q->floor_energy = rj__settle_floor(m);
    q->steady = rj__loads_steady_time(m);
    q->rise = 0;
    q->longest_rise = 1;
    q->quiet = -1;
    rj__zero_velocities(m, s);
}

/* The arguments rj_settle takes: tol in (0, 1), at least one step. Else RJ_ERR_INVALID
   with the argument named in rj_state_error. */
static rj_result rj__settle_args(const rj_model *m, rj_state *s, double tol, long max_steps)
{
    if (!(tol > 0 && tol < 1))
        return rj__stop(m, s, RJ_ERR_INVALID,
                        "rj_settle: tol = %g is invalid: it must be in (0, 1) (1e-12 is tight)",
                        tol);
    if (max_steps < 1)
        return rj__stop(m, s, RJ_ERR_INVALID,
                        "rj_settle: max_steps = %ld is invalid: it must be at least 1",
                        max_steps);
    return RJ_OK;
}

/* Kinetic damping: every velocity to zero at each peak of the kinetic energy. A peak below
   tol times the potential energy moved is not yet the end: from rest, a mode far slower
   than the others can take many steps to show, while the faster ones make small peaks
   first. So the state must then stay below it, without damping, for 1.5 times the longest
   rise from rest to a peak seen so far (that slow mode's quarter period, once it has
   shown). progress (when not NULL) is called every RJ__SETTLE_EVERY steps; a nonzero
   return stops the settling. The steps, from a start at rest (rj__settle_start). */
#define RJ__SETTLE_EVERY 4096
static rj_result rj__settle_steps(const rj_model *m, rj_state *s, rj__settle_run *q, double tol,
                                  long max_steps, rj_sample_fn progress, void *user)
{
    long k;
    for (k = 0; k < max_steps; k++) {
        const double *sc;
        double moved;
        const rj_result r = rj__step(m, s, 1);
        if (r != RJ_OK)
            return r;
        sc = RJ__FS(m, s->fd[s->cur]);
        moved = rj__settle_scale(sc, q->gravity);
        /* each restart from rest starts the accounts again, from an energy that shrinks as
           the state settles: the blow-up tests measure against what the settling moved */
        if (moved > s->settle_scale)
            s->settle_scale = moved;
        /* settled only under the loads that act from then on: past their tables */
        if (rj__settle_judge(m, s, q, sc[RJ__FS_KE], tol * moved + q->floor_energy) &&
            sc[RJ__FS_TIME] >= q->steady) {
            rj__restart(m, s);
            return RJ_OK;
        }
        if (progress && (k + 1) % RJ__SETTLE_EVERY == 0 && progress(m, s, user)) {
            rj__zero_velocities(m, s);
            return rj__stop(m, s, RJ_ERR_NOT_CONVERGED,
                            "rj_settle: stopped by the caller after %ld steps (t = %.9g s)",
                            k + 1, rj_state_time(s));
        }
    }
    rj__zero_velocities(m, s);
    return rj__stop(m, s, RJ_ERR_NOT_CONVERGED,
                    "rj_settle: not settled within %ld steps (t = %.9g s; the last kinetic "
                    "energy peak %.3g J; tol %g of the %.3g J of potential energy moved)",
                    max_steps, rj_state_time(s), q->last_peak, tol,
                    rj__settle_scale(RJ__FS(m, s->fd[s->cur]), q->gravity));
}

/* rj_settle with progress: the settling's scale for the blow-up tests holds while it
   steps, whatever ends it. */
RJDEF rj_result rj_settle_ex(const rj_model *m, rj_state *s, double tol, long max_steps,
                             rj_sample_fn progress, void *user)
{
    rj__settle_run q;
    rj_result r;
    if (!m || !s)
        return RJ_ERR_INVALID;
    r = rj__settle_args(m, s, tol, max_steps);
    if (r != RJ_OK)
        return r;
    s->err[0] = 0;
    rj__settle_start(m, s, &q);
    s->settling = 1;
    r = rj__settle_steps(m, s, &q, tol, max_steps, progress, user);
    s->settling = 0;
    s->settle_scale = 0;
    return r;
}

RJDEF rj_result rj_settle(const rj_model *m, rj_state *s, double tol, long max_steps)
{
    return rj_settle_ex(m, s, tol, max_steps, NULL, NULL);
}

