/* ------------------------------------------------------------------ constraint rows */
/* A constraint row holds a combination of joint rates, J q' = sum_t coef_t q'_(joint_t),
   at a target rate over the step, n + 1/2, by an impulse lam along J^T within bounds
   [lo, hi]. A row with a position to keep (a profile, a coupling's e = 0) aims its target
   rate at that position at n + 1: target = (position(t + dt) - position(t)) / dt.

   Rows are the one way the step imposes motion. Every kind is built the same way (its
   terms, target and bounds) and solved by the space its scene steps in:
   - joint coordinates (rigid scenes): W lam = target - J q' with W = J M^-1 J^T, dense,
     over the active rows, a bounded row that would pull dropped and the set solved
     again (rj__rows_solve_dense);
   - node space (flexible and mixed scenes): a row's impulse is a pair of torque
     impulses on its joints' pins (rj__joint_impulse); W from the joints' gives and the
     bodies they share (rj__joint_cross), solved at once (rj__rows_direct), then swept
     row by row until none misses (a check that finds round-off).
   The work of a row's impulse in the kinetic energy's discrete form is
   -1/2 lam J q'^{n-1/2} now and -1/2 lam J q'^{n+1/2} with the next step (the latches'
   rule, rj__joint_jump), whatever the space.

   Kinds: a locked joint (rigid scenes), a plastic contact at a limit (rigid scenes,
   pushing only), a prescribed joint, an exact coupling. The closed loops' rows are the
   next kind: rows of J over the joints around a loop. */
/* Opens row of kind for owner; its terms follow with rj__row_term. */
static rj__row *rj__row_open(rj__rows *R, int kind, int owner, double target, double lo,
                             double hi)
{
    rj__row *row = &R->row[R->count];
    R->count++;
    row->kind = kind;
    row->owner = owner;
    row->first = R->terms;
    row->count = 0;
    row->active = 1;
    row->target = target;
    row->lo = lo;
    row->hi = hi;
    row->lam = 0;
    return row;
}

static void rj__row_term(rj__rows *R, rj__row *row, int joint, double coef)
{
    R->term[R->terms].joint = joint;
    R->term[R->terms].coef = coef;
    R->terms++;
    row->count++;
}

/* J x for a vector x over the joints. */
static double rj__row_dot(const rj__rows *R, const rj__row *row, const double *x)
{
    const rj__term *t = R->term + row->first;
    double sum = 0;
    int k;
    for (k = 0; k < row->count; k++)
        sum += t[k].coef * x[t[k].joint];
    return sum;
}

/* Whether the row is one joint's rate alone (its column of M^-1 is W's). */
static int rj__row_unit(const rj__rows *R, const rj__row *row)
{
    return row->count == 1 && R->term[row->first].coef == 1.0;
}

/* A prescribed joint's row: its rate lands it on its profile at n + 1; its term at index
   at (the joint, or its coordinate in joint coordinates). */
static void rj__row_prescribed(const rj_model *m, const rj_state *s, rj__rows *R, int j, int at,
                               double run, double t, double dt)
{
    const double target = rj__prescribed_rate(m, s, j, run, t, dt);
    rj__row *row = rj__row_open(R, RJ__ROW_PRESCRIBED, j, target, -HUGE_VAL, HUGE_VAL);
    rj__row_term(R, row, at, 1.0);
}

/* Exact coupling k's row, from the joints' running angles at n (stride apart in
   angles): e = (theta_b - angle0_b) - ratio (theta_a - angle0_a) - offset back to 0 at
   n + 1, along w = e_b - ratio e_a. map: a joint's index in angles and terms (its
   coordinate in joint coordinates), NULL for the joint itself. */
/* Exact coupling c's stretch e at its joints' running angles. */
static double rj__coupling_stretch(const rj_model *m, const rj_coupling_def *c, double theta_a,
                                   double theta_b)
{
    return (theta_b - m->jdef[c->joint_b].angle0) -
           c->ratio * (theta_a - m->jdef[c->joint_a].angle0) - c->offset;
}

static void rj__row_coupling(const rj_model *m, rj__rows *R, int k, const double *angles,
                             size_t stride, const int *map, double dt)
{
    const rj_coupling_def *c = &m->cp[k];
    const int a = map ? map[c->joint_a] : c->joint_a, b = map ? map[c->joint_b] : c->joint_b;
    const double theta_a = angles[stride * (size_t) a], theta_b = angles[stride * (size_t) b];
    const double e_n = rj__coupling_stretch(m, c, theta_a, theta_b);
    rj__row *row = rj__row_open(R, RJ__ROW_COUPLING, k, -e_n / dt, -HUGE_VAL, HUGE_VAL);
    rj__row_term(R, row, b, 1.0);
    rj__row_term(R, row, a, -c->ratio);
}

/* Whether coupling k is exact with a joint between two rigid bodies of a mixed scene: a
   torque pair then (rj__pair_coupling), not a row. */
static int rj__coupling_on_pair(const rj_model *m, int k)
{
    const rj_coupling_def *c = &m->cp[k];
    return c->exact && (m->jnt[c->joint_a].pair || m->jnt[c->joint_b].pair);
}

/* The exact couplings' rows. */
static void rj__rows_couplings(const rj_model *m, rj__rows *R, const double *angles,
                               size_t stride, const int *map, double dt)
{
    int k;
    for (k = 0; k < m->ncp; k++)
        if (m->cp[k].exact && !rj__coupling_on_pair(m, k))
            rj__row_coupling(m, R, k, angles, stride, map, dt);
}

/* Whether a pushing-only row's rate has turned against its bound: a contact whose
   impulse may only be negative (its forward limit) holds rates up to its target. */
static int rj__row_violated(const rj__row *row, double rate)
{
    if (row->hi == 0)
        return rate > row->target;
    if (row->lo == 0)
        return rate < row->target;
    return 0;
}

/* Whether an active row's impulse lies outside its bounds (a bounded row that pulls). */
static int rj__row_pulls(const rj__row *row, double lam)
{
    return lam > row->hi || lam < row->lo;
}

/* What the dense solve works in: M's factor, M^-1's columns for the joints (W, n each,
   coordinate j's at W + wcol[j] n: rj_model.wcol), the other rows' M^-1 J^T (Y, n each),
   the system and its factor (S, SL: R x R), vectors (lam, rhs: R; scratch: n), and the row
   a single impulse before the solve already holds exactly (-1: none), which alone needs
   no solve. */
typedef struct rj__dense {
    int n;
    const rj_model *m;
    rj__rig *rig; /* M's factor (rj__rig_factor) */
    double *W, *Y, *S, *SL, *lam, *rhs, *scratch;
    int held;
} rj__dense;

/* A row's M^-1 J^T: W's column for a unit row (made here), else the next column of Y
   (the other rows before it took *others). */
static const double *rj__row_column(const rj__rows *R, const rj__row *row, const rj__dense *D,
                                    int *others)
{
    const int n = D->n;
    double *y, *scratch = D->scratch;
    int k;
    if (rj__row_unit(R, row)) {
        const int j = R->term[row->first].joint;
        y = D->W + (size_t) D->m->wcol[j] * n;
        rj__rig_unit(D->m, D->rig, j, y);
        return y;
    }
    y = D->Y + (size_t) *others * n;
    (*others)++;
    for (k = 0; k < n; k++)
        scratch[k] = 0;
    for (k = 0; k < row->count; k++)
        scratch[R->term[row->first + k].joint] += R->term[row->first + k].coef;
    rj__rig_solve(D->m, D->rig, scratch, y);
    return y;
}

/* The Cholesky factor of the k x k positive semi-definite S into L, a row whose pivot
   falls below 1e-10 of S's largest diagonal dropped (its column of L zero, its diagonal
   0): the rows that repeat others (a parallelogram's loops at its flat position) take no
   impulse, the others what they need. */
static void rj__chol_psd(int k, const double *S, double *L, double largest)
{
    int i, j, p;
    for (i = 0; i < k * k; i++)
        L[i] = 0;
    for (j = 0; j < k; j++) {
        double d = S[(size_t) j * k + j];
        for (p = 0; p < j; p++)
            d -= L[(size_t) j * k + p] * L[(size_t) j * k + p];
        if (!(d > 1e-10 * largest))
            continue;
        L[(size_t) j * k + j] = sqrt(d);
        for (i = j + 1; i < k; i++) {
            double v = S[(size_t) i * k + j];
            for (p = 0; p < j; p++)
                v -= L[(size_t) i * k + p] * L[(size_t) j * k + p];
            L[(size_t) i * k + j] = v / L[(size_t) j * k + j];
        }
    }
}

/* Solves L L^T x = b with rj__chol_psd's factor, x 0 on the dropped rows. */
static void rj__chol_psd_solve(int k, const double *L, const double *b, double *x)
{
    int i, p;
    for (i = 0; i < k; i++) {
        double v = b[i];
        if (L[(size_t) i * k + i] == 0) {
            x[i] = 0;
            continue;
        }
        for (p = 0; p < i; p++)
            v -= L[(size_t) i * k + p] * x[p];
        x[i] = v / L[(size_t) i * k + i];
    }
    for (i = k - 1; i >= 0; i--) {
        double v = x[i];
        if (L[(size_t) i * k + i] == 0)
            continue;
        for (p = i + 1; p < k; p++)
            v -= L[(size_t) p * k + i] * x[p];
        x[i] = v / L[(size_t) i * k + i];
    }
}

/* Whether a Cholesky factor has a pivot below 1e-10 of the largest diagonal (its rows
   nearly repeat each other: the plain solve would give them huge, opposed impulses). */
static int rj__chol_nearly_singular(int k, const double *L, double largest)
{
    int i;
    for (i = 0; i < k; i++)
        if (!(L[(size_t) i * k + i] * L[(size_t) i * k + i] > 1e-10 * largest))
            return 1;
    return 0;
}

/* The active rows' system S lam = target - J q', its factor in SL. Rows that (nearly)
   repeat each other are dropped from it (rj__chol_psd; D->psd says so to the solve).
   Returns the number of active rows. */
static int rj__rows_system(const rj__rows *R, const rj__dense *D, const double *qdp, int *psd)
{
    int a, b, k = 0, row = 0;
    double largest = 0;
    for (a = 0; a < R->count; a++)
        k += R->row[a].active;
    for (a = 0; a < R->count; a++) {
        int c = 0;
        if (!R->row[a].active)
            continue;
        for (b = 0; b < R->count; b++) {
            if (!R->row[b].active)
                continue;
            D->S[(size_t) row * k + c] = rj__row_dot(R, &R->row[a], R->row[b].col);
            c++;
        }
        D->rhs[row] = R->row[a].target - rj__row_dot(R, &R->row[a], qdp);
        if (D->S[(size_t) row * k + row] > largest)
            largest = D->S[(size_t) row * k + row];
        row++;
    }
    *psd = rj__chol(k, D->S, D->SL) || rj__chol_nearly_singular(k, D->SL, largest);
    if (*psd)
        rj__chol_psd(k, D->S, D->SL, largest);
    return k;
}

/* One pass of the dense solve: the active rows' impulses into D->lam; rows that would
   pull leave the set (returns 1: solve again); else the impulses move q' and the rows
   keep them (returns 0). -1: no solution. */
static int rj__rows_pass(rj__rows *R, const rj__dense *D, double *qdp)
{
    const int n = D->n;
    int a, i, k, row = 0, dropped = 0, psd;
    k = rj__rows_system(R, D, qdp, &psd);
    if (psd)
        rj__chol_psd_solve(k, D->SL, D->rhs, D->lam);
    else
        rj__chol_solve(k, D->SL, D->rhs, D->lam);
    for (a = 0; a < R->count; a++) {
        if (!R->row[a].active)
            continue;
        if (rj__row_pulls(&R->row[a], R->row[a].lam + D->lam[row])) {
            R->row[a].active = 0;
            dropped = 1;
        }
        row++;
    }
    if (dropped)
        return 1;
    row = 0;
    for (a = 0; a < R->count; a++) {
        if (!R->row[a].active)
            continue;
        for (i = 0; i < n; i++)
            qdp[i] += R->row[a].col[i] * D->lam[row];
        R->row[a].lam += D->lam[row];
        row++;
    }
    return 0;
}

/* The rows in joint coordinates: passes until no bounded row pulls and none left out
   is violated (at most one pass per row and one more). Returns 0, or -1 when the system
   has no solution. */
static int rj__rows_solve_dense(rj__rows *R, const rj__dense *D, double *qdp)
{
    int a, pass, changed = 1, others = 0;
    for (a = 0; a < R->count; a++)
        R->row[a].col = rj__row_column(R, &R->row[a], D, &others);
    for (pass = 0; pass <= R->count && changed; pass++) {
        int any = 0, step;
        for (a = 0; a < R->count; a++)
            any += R->row[a].active;
        /* none, or only the row a single impulse held exactly */
        if (!any || (any == 1 && D->held >= 0 && R->row[D->held].active))
            return 0;
        step = rj__rows_pass(R, D, qdp);
        if (step < 0)
            return -1;
        changed = step;
        /* rows dropped, q' not moved: solve again without them before asking which rows
           the impulses turn against their bounds (asked of q' before the impulses, a
           row that pulls is dropped and taken back on every pass, and none acts) */
        if (step)
            continue;
        /* a bounded row left out that the impulses turned against its bound joins */
        for (a = 0; a < R->count; a++) {
            rj__row *row = &R->row[a];
            if (row->active || !rj__row_violated(row, rj__row_dot(R, row, qdp)))
                continue;
            row->active = 1;
            changed = 1;
        }
    }
    return 0;
}
