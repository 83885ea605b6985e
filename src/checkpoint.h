/* ------------------------------------------------------------------ checkpoints */
/* Layout: "RJCK" | u32 version | u64 model hash | u64 payload bytes | payload | u64 FNV-1a
   of everything before it. Payload: steps (i64), frame doubles, frame ints, then the
   caller's inputs: whether the joint torques are on (a double, 0 or 1) and the torques
   (nj), then whether the node forces are on, the forces (3 nn) and those the last step
   applied (3 nn); then whether the peaks are tracked (a double, 0 or 1) and the peaks
   (src/peaks.h). */
#define RJ__CK_HEAD 24
/* the layout's version: 8 since the run's peaks joined the payload (7: the structural
   damping's and plastic work's accounts joined each frame's scalars) */
#define RJ__CK_VERSION 8u
/* the payload's bytes */
static size_t rj__ck_payload(const rj_model *m)
{
    return 8 + sizeof(double) * m->frame_doubles + sizeof(int) * (m->frame_ints + 1) +
           sizeof(double) * ((size_t) m->nj + 1) + sizeof(double) * (6 * (size_t) m->nn + 1) +
           sizeof(double) * (rj__peaks_count(m) + 1);
}
/* An input block's bytes: its switch (0 or 1, a double), then its count values. */
static unsigned char *rj__ck_put_inputs(unsigned char *at, int on, const double *values,
                                        size_t count)
{
    const double flag = on ? 1.0 : 0.0;
    memcpy(at, &flag, sizeof(double));
    memcpy(at + sizeof(double), values, sizeof(double) * count);
    return at + sizeof(double) * (count + 1);
}
RJDEF size_t rj_state_save(const rj_model *m, const rj_state *s, void *buf, size_t size)
{
    size_t pay = rj__ck_payload(m);
    size_t need = RJ__CK_HEAD + pay + 8;
    unsigned char *b = (unsigned char *) buf;
    unsigned char *in_bytes;
    unsigned int ver = RJ__CK_VERSION;
    unsigned long long h, pl = pay, st = (unsigned long long) s->steps;
    if (!buf || size < need)
        return need;
    memcpy(b, "RJCK", 4);
    memcpy(b + 4, &ver, 4);
    memcpy(b + 8, &m->hash, 8);
    memcpy(b + 16, &pl, 8);
    memcpy(b + RJ__CK_HEAD, &st, 8);
    memcpy(b + RJ__CK_HEAD + 8, s->fd[s->cur], sizeof(double) * m->frame_doubles);
    memcpy(b + RJ__CK_HEAD + 8 + sizeof(double) * m->frame_doubles, s->fi[s->cur],
           sizeof(int) * (m->frame_ints + 1));
    in_bytes =
        b + RJ__CK_HEAD + 8 + sizeof(double) * m->frame_doubles + sizeof(int) * (m->frame_ints + 1);
    in_bytes = rj__ck_put_inputs(in_bytes, s->inputs, s->input_torque, (size_t) m->nj);
    in_bytes = rj__ck_put_inputs(in_bytes, s->node_inputs, s->input_node, 3 * (size_t) m->nn);
    memcpy(in_bytes, s->node_applied, 3 * sizeof(double) * (size_t) m->nn);
    in_bytes += 3 * sizeof(double) * (size_t) m->nn;
    rj__ck_put_inputs(in_bytes, s->peaks_on, s->peaks, rj__peaks_count(m));
    h = rj__fnv(14695981039346656037ULL, b, RJ__CK_HEAD + pay);
    memcpy(b + RJ__CK_HEAD + pay, &h, 8);
    return need;
}
/* The steps a checkpoint may count: the counter must stay far from overflowing a long
   (32 bits on some systems) */
#define RJ__CK_MAX_STEPS 2000000000.0
/* The largest magnitude a checkpoint's value may have */
#define RJ__CK_MAX_VALUE 1e100

/* A checkpoint's frame is checked as the model validation checks a definition: every value
   finite, time and counts in range, each joint's flag one its definition allows. Returns 0
   with err filled when a value is out of range. */
static int rj__ck_frame_ok(const rj_model *m, const double *fd, const int *fi,
                           unsigned long long steps, rj_error *err)
{
    const double *sc = RJ__FS(m, fd);
    size_t k;
    int j;
    if (steps > (unsigned long long) RJ__CK_MAX_STEPS) {
        rj__fail(err, RJ_ERR_CHECKPOINT, "steps", (double) steps,
                 "checkpoint counts %.0f steps, more than the %.0f a state counts", (double) steps,
                 RJ__CK_MAX_STEPS);
        return 0;
    }
    /* every value finite and within 1e100 in magnitude: no state a model reaches comes near
       it, and sums of such values (a joint's total torque, the energy balance) stay finite */
    for (k = 0; k < m->frame_doubles; k++)
        if (!(fabs(fd[k]) <= RJ__CK_MAX_VALUE)) {
            rj__fail(err, RJ_ERR_CHECKPOINT, "payload", fd[k],
                     "checkpoint holds %g at value %lu: not finite, or beyond the 1e100 that no "
                     "state reaches",
                     fd[k], (unsigned long) k);
            return 0;
        }
    if (!(sc[RJ__FS_TIME] >= 0) || !(sc[RJ__FS_ETIME] <= sc[RJ__FS_TIME])) {
        rj__fail(err, RJ_ERR_CHECKPOINT, "time", sc[RJ__FS_TIME],
                 "checkpoint time %g s (energy time %g s) is out of range", sc[RJ__FS_TIME],
                 sc[RJ__FS_ETIME]);
        return 0;
    }
    {
        /* the accounts' sums (rj_state_energy) must be finite too, not only their terms */
        double total;
        const double balance = rj__accounts_read(sc, NULL, &total) + sc[RJ__FS_PEND];
        if (!rj__finite(total) || !rj__finite(balance)) {
            rj__fail(err, RJ_ERR_CHECKPOINT, "energy", balance,
                     "checkpoint's energy accounts do not add up to a finite total (%g) and "
                     "balance (%g)",
                     total, balance);
            return 0;
        }
    }
    if (!(sc[RJ__FS_WARN] >= 0 && sc[RJ__FS_WARN] <= RJ__CK_MAX_STEPS &&
          sc[RJ__FS_WARN] == floor(sc[RJ__FS_WARN]))) {
        rj__fail(err, RJ_ERR_CHECKPOINT, "warnings", sc[RJ__FS_WARN],
                 "checkpoint warning count %g is not a count", sc[RJ__FS_WARN]);
        return 0;
    }
    for (j = 0; j < m->nj; j++) {
        /* event times: -1 (none yet) or a time already reached; the peak penetration >= 0 */
        const double *jd = RJ__FJ(m, fd, j);
        const double times[2] = { jd[RJ__JD_EVENT], jd[RJ__JD_RELEASE] };
        int k2;
        for (k2 = 0; k2 < 2; k2++)
            if (!(times[k2] == -1 || (times[k2] >= 0 && times[k2] <= sc[RJ__FS_TIME]))) {
                rj__fail(err, RJ_ERR_CHECKPOINT, "event", times[k2],
                         "checkpoint gives joint %d an event time of %g s at t = %g s", j,
                         times[k2], sc[RJ__FS_TIME]);
                return 0;
            }
        if (!(jd[RJ__JD_PEAKP] >= 0)) {
            rj__fail(err, RJ_ERR_CHECKPOINT, "peak", jd[RJ__JD_PEAKP],
                     "checkpoint gives joint %d a peak penetration of %g rad", j, jd[RJ__JD_PEAKP]);
            return 0;
        }
    }
    for (j = 0; j < m->nj; j++) {
        const rj_joint_def *d = &m->jdef[j];
        const int flag = fi[j];
        const int ok = flag == RJ_FREE || (flag == RJ_AT_FORWARD && d->has_forward) ||
                       (flag == RJ_AT_REVERSE && d->has_reverse) ||
                       (flag == RJ_LOCKED && d->lock && (d->has_forward || d->has_reverse));
        if (ok)
            continue;
        rj__fail(err, RJ_ERR_CHECKPOINT, "flag", flag,
                 "checkpoint gives joint %d the flag %d, which its definition does not allow", j,
                 flag);
        return 0;
    }
    return 1;
}

/* The int after the joints' flags is spare and always 0: a checkpoint with anything else
   there was not written by rj_state_save. */
static int rj__ck_spare_ok(const rj_model *m, const int *fi, rj_error *err)
{
    if (fi[m->frame_ints] == 0)
        return 1;
    rj__fail(err, RJ_ERR_CHECKPOINT, "payload", fi[m->frame_ints],
             "checkpoint holds %d in its spare slot, which rj_state_save leaves 0",
             fi[m->frame_ints]);
    return 0;
}

/* A checkpoint's input block (rj__ck_put_inputs): the switch 0 or 1, each value finite
   within 1e100. field names the block (and the switch: field with "s" after it). */
static int rj__ck_input_block_ok(const unsigned char *at, size_t count, const char *field,
                                 const char *what, rj_error *err)
{
    static const double off = 0.0, on = 1.0;
    double v;
    size_t k;
    memcpy(&v, at, sizeof(double));
    /* the very bytes of 0 or 1 (not -0), so that a loaded state saves back the same bytes */
    if (memcmp(at, &off, sizeof off) != 0 && memcmp(at, &on, sizeof on) != 0) {
        rj__fail(err, RJ_ERR_CHECKPOINT, "inputs", v,
                 "checkpoint's switch of the %ss is %g, not 0 or 1", what, v);
        return 0;
    }
    for (k = 0; k < count; k++) {
        memcpy(&v, at + sizeof(double) * (k + 1), sizeof(double));
        if (!(fabs(v) <= RJ__CK_MAX_VALUE)) {
            rj__fail(err, RJ_ERR_CHECKPOINT, field, v,
                     "checkpoint's %s %lu is %g: not finite within 1e100", what, (unsigned long) k,
                     v);
            return 0;
        }
    }
    return 1;
}
/* Where the checkpoint's peaks block starts, after the inputs'. */
static const unsigned char *rj__ck_peaks_at(const rj_model *m, const unsigned char *in_bytes)
{
    return in_bytes + sizeof(double) * ((size_t) m->nj + 1 + 6 * (size_t) m->nn + 1);
}

/* A link's peak record: none (-1) or a magnitude with an element the link has and an end
   0 or 1 (they become ints). */
static int rj__ck_link_peak_ok(const rj_model *m, int l, const double *pk)
{
    const double ne = m->ldef[l].elements;
    const int moment = pk[0] < 0 || (pk[2] == floor(pk[2]) && pk[2] >= 0 && pk[2] < ne &&
                                      (pk[3] == 0 || pk[3] == 1));
    const int stress = pk[4] < 0 || (pk[6] == floor(pk[6]) && pk[6] >= 0 && pk[6] < ne);
    return moment && stress;
}

/* The checkpoint's peaks: a switch and finite values, each link's elements its own. */
static int rj__ck_peaks_ok(const rj_model *m, const unsigned char *at, rj_error *err)
{
    double pk[RJ__PEAK_LINK];
    int l;
    if (!rj__ck_input_block_ok(at, rj__peaks_count(m), "peaks", "peak", err))
        return 0;
    for (l = 0; l < m->nl; l++) {
        const size_t k = 1 + RJ__PEAK_JOINT * (size_t) m->nj + RJ__PEAK_LINK * (size_t) l;
        memcpy(pk, at + sizeof(double) * k, sizeof pk);
        if (!rj__ck_link_peak_ok(m, l, pk)) {
            rj__fail(err, RJ_ERR_CHECKPOINT, "peaks", l,
                     "checkpoint's peaks of link %d name element %g, end %g: not one the "
                     "link has",
                     l, pk[2], pk[3]);
            return 0;
        }
    }
    return 1;
}

/* The checkpoint's inputs: the joint torques' block, then the node forces', then the
   peaks'. */
static int rj__ck_inputs_ok(const rj_model *m, const unsigned char *in_bytes, rj_error *err)
{
    const size_t nj = (size_t) m->nj;
    return rj__ck_input_block_ok(in_bytes, nj, "input_torque", "input torque", err) &&
           rj__ck_input_block_ok(in_bytes + sizeof(double) * (nj + 1), 6 * (size_t) m->nn,
                                 "input_node", "input node force", err) &&
           rj__ck_peaks_ok(m, rj__ck_peaks_at(m, in_bytes), err);
}
static void rj__ck_inputs_load(const rj_model *m, rj_state *s, const unsigned char *in_bytes)
{
    const size_t nj = (size_t) m->nj;
    const unsigned char *node_bytes = in_bytes + sizeof(double) * (nj + 1);
    double v;
    memcpy(&v, in_bytes, sizeof(double));
    s->inputs = v == 1;
    memcpy(s->input_torque, in_bytes + sizeof(double), sizeof(double) * nj);
    memcpy(&v, node_bytes, sizeof(double));
    s->node_inputs = v == 1;
    memcpy(s->input_node, node_bytes + sizeof(double), 3 * sizeof(double) * (size_t) m->nn);
    memcpy(s->node_applied, node_bytes + sizeof(double) * (3 * (size_t) m->nn + 1),
           3 * sizeof(double) * (size_t) m->nn);
    memcpy(&v, rj__ck_peaks_at(m, in_bytes), sizeof(double));
    s->peaks_on = v == 1;
    memcpy(s->peaks, rj__ck_peaks_at(m, in_bytes) + sizeof(double),
           sizeof(double) * rj__peaks_count(m));
}

RJDEF rj_result rj_state_load(const rj_model *m, rj_state *s, const void *buf, size_t size,
                              rj_error *err)
{
    const size_t pay = rj__ck_payload(m);
    const size_t need = RJ__CK_HEAD + pay + 8;
    const unsigned char *b = (const unsigned char *) buf;
    const unsigned char *fd_bytes = b + RJ__CK_HEAD + 8;
    const unsigned char *fi_bytes = fd_bytes + sizeof(double) * m->frame_doubles;
    const unsigned char *in_bytes = fi_bytes + sizeof(int) * (m->frame_ints + 1);
    unsigned int ver;
    unsigned long long h, hh, mh, pl, st;
    /* the header first: a checkpoint of another model (or none) is told apart from a cut one */
    if (!buf || size < RJ__CK_HEAD) {
        rj__fail(err, RJ_ERR_CHECKPOINT, "size", (double) size,
                 "checkpoint of %lu bytes is truncated: this model's checkpoints are %lu bytes",
                 (unsigned long) size, (unsigned long) need);
        return RJ_ERR_CHECKPOINT;
    }
    if (memcmp(b, "RJCK", 4) != 0) {
        rj__fail(err, RJ_ERR_CHECKPOINT, "magic", 0, "not a revjoint checkpoint (bad magic)");
        return RJ_ERR_CHECKPOINT;
    }
    memcpy(&ver, b + 4, 4);
    memcpy(&mh, b + 8, 8);
    memcpy(&pl, b + 16, 8);
    if (ver != RJ__CK_VERSION) {
        rj__fail(err, RJ_ERR_CHECKPOINT, "version", ver,
                 "checkpoint version %u is not supported (%u: the run's peaks joined the "
                 "payload)",
                 ver, RJ__CK_VERSION);
        return RJ_ERR_CHECKPOINT;
    }
    if (mh != m->hash || pl != pay) {
        rj__fail(err, RJ_ERR_CHECKPOINT, "model", 0,
                 "checkpoint is for another model (its definitions, step or size differ from this "
                 "model's)");
        return RJ_ERR_CHECKPOINT;
    }
    if (size < need) {
        rj__fail(err, RJ_ERR_CHECKPOINT, "size", (double) size,
                 "checkpoint of %lu bytes is truncated: this model's checkpoints are %lu bytes",
                 (unsigned long) size, (unsigned long) need);
        return RJ_ERR_CHECKPOINT;
    }
    if (size > need) {
        rj__fail(err, RJ_ERR_CHECKPOINT, "size", (double) size,
                 "checkpoint of %lu bytes has %lu bytes after its end: this model's checkpoints "
                 "are %lu bytes",
                 (unsigned long) size, (unsigned long) (size - need), (unsigned long) need);
        return RJ_ERR_CHECKPOINT;
    }
    memcpy(&hh, b + RJ__CK_HEAD + pay, 8);
    h = rj__fnv(14695981039346656037ULL, b, RJ__CK_HEAD + pay);
    if (h != hh) {
        rj__fail(err, RJ_ERR_CHECKPOINT, "checksum", 0,
                 "checkpoint is corrupted (checksum mismatch)");
        return RJ_ERR_CHECKPOINT;
    }
    memcpy(&st, b + RJ__CK_HEAD, 8);
    /* the checksum is no seal: every value is checked before the state changes, in the
       frame that is not current (a failed load leaves the state as it was) */
    {
        const int spare = 1 - s->cur;
        memcpy(s->fd[spare], fd_bytes, sizeof(double) * m->frame_doubles);
        memcpy(s->fi[spare], fi_bytes, sizeof(int) * (m->frame_ints + 1));
        if (!rj__ck_frame_ok(m, s->fd[spare], s->fi[spare], st, err) ||
            !rj__ck_spare_ok(m, s->fi[spare], err) || !rj__ck_inputs_ok(m, in_bytes, err)) {
            s->snap = -1; /* in place the spare frame held the rollback copy: take a new one */
            return RJ_ERR_CHECKPOINT;
        }
        s->cur = spare;
        rj__ck_inputs_load(m, s, in_bytes);
    }
    s->snap = -1;
    s->steps = (long) st;
    s->at_n = RJ__AT_N_NONE;
    s->loop_force[2 * m->nj] = -1; /* not in a checkpoint: known again after a step */
    s->err[0] = 0;
    s->warn[0] = 0;
    return RJ_OK;
}
