/* ------------------------------------------------------------------ peaks */
/* A state may track the run's peaks (rj_state_track_peaks): each joint's |pin force| and
   when, each flexible link's |bending moment| and outer-fibre stress and where. They are
   taken after the steps that take the energy accounts (every step unless
   solver.energy_every > 1: then every K-th, and a peak between them is missed), from the
   loads at t^n that rj_joint_pin_forces and rj_element_loads give, into rj_state.peaks:
   per joint [|F|, t], then per link [|M|, t, element, end, stress, t, element]. */

/* The peaks from the loads at t^n of the step just taken (src/run.h), a step that took
   the accounts (their time is t^n): the pin forces', and the element loads' but in a
   model that steps in place (its steps keep only the pins' nodes at n: rj_element_loads
   has none, and peaks of the steps that do not would mislead). */
static RJ__NOINLINE void rj__track_peaks(const rj_model *m, rj_state *s)
{
    const double t = s->fd[s->cur][RJ__FS_ETIME];
    double *pins = s->peak_work + RJ__PIN_PER_LINK * ((size_t) m->nl + 1);
    int j, l, e;
    rj__pin_forces(m, s, s->peak_work, pins);
    for (j = 0; j < m->nj; j++) {
        double *pk = s->peaks + RJ__PEAK_JOINT * (size_t) j;
        const double size = sqrt(pins[2 * j] * pins[2 * j] + pins[2 * j + 1] * pins[2 * j + 1]);
        if (size > pk[0]) {
            pk[0] = size;
            pk[1] = t;
        }
    }
    for (l = 0; l < m->nl && !m->ip; l++) {
        double *pk = s->peaks + RJ__PEAK_JOINT * (size_t) m->nj + RJ__PEAK_LINK * (size_t) l;
        if (m->ldef[l].fidelity != RJ_LINK_FLEXIBLE)
            continue;
        for (e = 0; e < m->ldef[l].elements; e++) {
            double loads[5];
            int end;
            rj__element_loads(m, s, l, e, loads);
            for (end = 0; end < 2; end++)
                if (fabs(loads[2 + end]) > pk[0]) {
                    pk[0] = fabs(loads[2 + end]);
                    pk[1] = t;
                    pk[2] = e;
                    pk[3] = end;
                }
            if (loads[4] > pk[4]) {
                pk[4] = loads[4];
                pk[5] = t;
                pk[6] = e;
            }
        }
    }
}

RJDEF rj_result rj_state_track_peaks(const rj_model *m, rj_state *s, int on)
{
    RJ_ASSERT(m && s);
    if (on && !s->peaks_on)
        rj__peaks_clear(m, s);
    s->peaks_on = on != 0;
    return RJ_OK;
}

/* A peak from its record (value, time, then element and end where given: -1 else). */
static rj_peak rj__peak_of(const double *pk, int has_element, int has_end)
{
    rj_peak p;
    p.value = pk[0];
    p.time = pk[1];
    p.element = has_element && pk[0] >= 0 ? (int) pk[2] : -1;
    p.end = has_end && pk[0] >= 0 ? (int) pk[3] : -1;
    return p;
}

RJDEF rj_peak rj_joint_peak_pin_force(const rj_model *m, const rj_state *s, int joint)
{
    RJ_ASSERT(m && s && joint >= 0 && joint < m->nj);
    return rj__peak_of(s->peaks + RJ__PEAK_JOINT * (size_t) joint, 0, 0);
}

RJDEF rj_peak rj_link_peak_moment(const rj_model *m, const rj_state *s, int link)
{
    RJ_ASSERT(m && s && link >= 0 && link < m->nl);
    return rj__peak_of(s->peaks + RJ__PEAK_JOINT * (size_t) m->nj + RJ__PEAK_LINK * (size_t) link,
                       1, 1);
}

RJDEF rj_peak rj_link_peak_stress(const rj_model *m, const rj_state *s, int link)
{
    RJ_ASSERT(m && s && link >= 0 && link < m->nl);
    return rj__peak_of(
        s->peaks + RJ__PEAK_JOINT * (size_t) m->nj + RJ__PEAK_LINK * (size_t) link + 4, 1, 0);
}
