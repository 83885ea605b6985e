/* ------------------------------------------------------------------ stepping and running */
/* The step. In place (rj_model.ip: solver.in_place, never with inextensible links; after
   the first step) it writes the nodes and elements where it reads them, which halves what a
   large model moves through the caches each step; the other frame then holds a copy of the
   state taken at most RJ__SNAP steps before. A step that fails puts that copy back and takes the steps since
   again, with the same energy requests (s->want) and the same inputs: the same bits, so a
   failed step leaves the state as it was, as the double-buffered step does. */
#define RJ__SNAP 64

/* In place: whether the caller's inputs are those every step since the copy took, so that
   a replay takes them again. A change steps double-buffered once; the copy is then taken
   anew with the new inputs. Every caller input the in-place step reads belongs here (the
   node forces always step double-buffered). */
static int rj__inputs_since_snap(const rj_model *m, const rj_state *s)
{
    if (s->inputs != s->snap_inputs)
        return 0;
    return !s->inputs ||
           memcmp(s->snap_torque, s->input_torque, sizeof(double) * (size_t) m->nj) == 0;
}
static rj_result rj__step_plain(const rj_model *m, rj_state *s, int want_energy)
{
    return rj__step_run(m, s, want_energy, 0, 0);
}
static rj_result rj__step_held(const rj_model *m, rj_state *s, int want_energy)
{
    return rj__step_run(m, s, want_energy, 0, 1);
}
static rj_result rj__step_ip(const rj_model *m, rj_state *s, int want_energy)
{
    return rj__step_run(m, s, want_energy, 1, 0);
}
/* Double-buffered: scenes with constraints on positions (inextensible links, pins
   between rigid bodies, so every joint between two bodies) take the step compiled with
   their parts. */
static rj_result rj__step_dbl(const rj_model *m, rj_state *s, int want_energy)
{
    if (m->project)
        return rj__step_held(m, s, want_energy);
    return rj__step_plain(m, s, want_energy);
}
static RJ__NOINLINE void rj__track_peaks(const rj_model *m, rj_state *s);

/* After a double-buffered step (result r): the other frame holds the state a step
   before, and the peaks are tracked where asked, on the steps that took the accounts
   (their time is the frame's before). */
static RJ__FORCE_INLINE rj_result rj__step_after(const rj_model *m, rj_state *s, rj_result r)
{
    s->at_n = r == RJ_OK ? RJ__AT_N_FRAME : RJ__AT_N_NONE;
    if (s->peaks_on && r == RJ_OK && !s->settling &&
        s->fd[s->cur][RJ__FS_ETIME] == s->fd[1 - s->cur][RJ__FS_TIME])
        rj__track_peaks(m, s);
    return r;
}

/* After an in-place step with peaks on: they are tracked as after a double-buffered
   step, on a step that took the accounts (at its start, a step before the time now; the
   ones before it a step earlier still). */
static RJ__NOINLINE void rj__step_ip_peaks(const rj_model *m, rj_state *s)
{
    const double *now = s->fd[s->cur];
    if (!s->settling && now[RJ__FS_ETIME] > now[RJ__FS_TIME] - 1.5 * m->dt)
        rj__track_peaks(m, s);
}

static rj_result rj__step(const rj_model *m, rj_state *s, int want_energy)
{
    rj_result r;
    long n, k;
    char err[sizeof s->err], warn[sizeof s->warn];
    const double t = rj_state_time(s);
    /* a step too small for the time reached would leave time where it is: rj_run would
       never end */
    if (!(t + m->dt > t))
        return rj__stop(m, s, RJ_ERR_INVALID,
                        "t = %.17g s: the step %g s no longer advances time (it is below the "
                        "time's resolution, %g s)",
                        t, m->dt, t * DBL_EPSILON);
    if (m->rigid)
        return rj__step_after(m, s, rj__step_rigid(m, s, want_energy));
    /* the caller's torques checked before anything moves */
    if (s->inputs && !rj__inputs_ok(m, s))
        return RJ_ERR_INVALID;
    /* the caller's node forces kick nodes from their old velocities: double-buffered; so
       is a step whose inputs differ from those since the in-place copy */
    if (!m->ip || s->steps == 0 || s->node_inputs ||
        (s->snap >= 0 && !rj__inputs_since_snap(m, s))) {
        s->snap = -1;
        r = rj__step_dbl(m, s, want_energy);
        /* what a step applied is the next one's forces at n - 1 (their work) */
        if (s->node_inputs && r == RJ_OK)
            memcpy(s->node_applied, s->input_node, 3 * sizeof(double) * (size_t) m->nn);
        return rj__step_after(m, s, r);
    }
    /* in place, the other frame is a copy from some steps before; the third keeps the
       values at n of the nodes the loads at t^n read (m->dnode), and s->fx, fy their
       forces of the step */
    s->at_n = RJ__AT_N_KEPT;
    if (s->snap < 0 || s->steps - s->snap >= RJ__SNAP) {
        memcpy(s->fd[1 - s->cur], s->fd[s->cur], sizeof(double) * m->frame_doubles);
        memcpy(s->fi[1 - s->cur], s->fi[s->cur], sizeof(int) * (m->frame_ints + 1));
        s->snap = s->steps;
        s->want = 0;
        s->snap_inputs = s->inputs;
        memcpy(s->snap_torque, s->input_torque, sizeof(double) * (size_t) m->nj);
    }
    if (want_energy)
        s->want |= (unsigned long long) 1 << (s->steps - s->snap);
    r = rj__step_ip(m, s, want_energy);
    if (r == RJ_OK && s->peaks_on)
        rj__step_ip_peaks(m, s);
    if (r == RJ_OK)
        return r;
    s->at_n = RJ__AT_N_NONE;
    memcpy(err, s->err, sizeof err);
    memcpy(warn, s->warn, sizeof warn);
    n = s->steps;
    memcpy(s->fd[s->cur], s->fd[1 - s->cur], sizeof(double) * m->frame_doubles);
    memcpy(s->fi[s->cur], s->fi[1 - s->cur], sizeof(int) * (m->frame_ints + 1));
    s->steps = s->snap;
    for (k = s->snap; k < n; k++)
        if (rj__step_ip(m, s, (int) ((s->want >> (k - s->snap)) & 1)) != RJ_OK)
            break;
    memcpy(s->err, err, sizeof err);
    memcpy(s->warn, warn, sizeof warn);
    return r;
}

RJDEF rj_result rj_step(const rj_model *m, rj_state *s)
{
    return rj__step(m, s, 0);
}

/* rj_run and rj_run_watched: samples at the steps nearest to k sample_dt from time 0, or
   from the run's start (from_start), every step when sample_dt is 0; each_step (or NULL)
   after every step. */
static rj_result rj__run(const rj_model *m, rj_state *s, double t_end, double sample_dt,
                         int from_start, rj_sample_fn sample, rj_sample_fn each_step,
                         void *user)
{
    double next;
    rj_result r;
    if (!m || !s)
        return RJ_ERR_INVALID;
    if (!(t_end == t_end) || !(sample_dt >= 0) || !rj__finite(sample_dt))
        return RJ_ERR_INVALID;
    next = sample_dt > 0 && !from_start ? sample_dt * floor(rj_state_time(s) / sample_dt + 0.5)
                                        : rj_state_time(s);
    if (sample && rj_state_time(s) >= next - 0.5 * m->dt) {
        if (sample(m, s, user))
            return RJ_OK;
        next += sample_dt;
    }
    while (rj_state_time(s) < t_end - 0.5 * m->dt) {
        /* the energy accounts at every sample and at the end (solver.energy_every) */
        const double t1 = rj_state_time(s) + m->dt;
        r = rj__step(m, s, t1 >= t_end - 0.5 * m->dt || (sample && t1 >= next - 0.5 * m->dt));
        if (r != RJ_OK)
            return r;
        if (each_step && each_step(m, s, user))
            return RJ_OK;
        if (sample && rj_state_time(s) >= next - 0.5 * m->dt) {
            if (sample(m, s, user))
                return RJ_OK;
            if (sample_dt > 0)
                while (next <= rj_state_time(s) + 0.5 * m->dt)
                    next += sample_dt;
        }
    }
    return RJ_OK;
}

RJDEF rj_result rj_run(const rj_model *m, rj_state *s, double t_end, double sample_dt,
                       rj_sample_fn sample, void *user)
{
    return rj__run(m, s, t_end, sample_dt, 0, sample, NULL, user);
}

RJDEF rj_result rj_run_watched(const rj_model *m, rj_state *s, double t_end, double sample_dt,
                               rj_sample_fn sample, rj_sample_fn each_step, void *user)
{
    return rj__run(m, s, t_end, sample_dt, 1, sample, each_step, user);
}

