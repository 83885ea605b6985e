/* ------------------------------------------------------------------ pure element equations */
/* Eqs 1-3: angle from a to b, counter-clockwise, in [0, 2 pi). */
RJDEF double rj_rotary_location(double ax, double ay, double bx, double by)
{
    return rj__mod2pi(atan2(ax * by - ay * bx, ax * bx + ay * by));
}

/* Eq 4: sum over segments containing theta of the linear interpolant; overlapping segments add. */
RJDEF double rj_table_torque(const double *angle, const double *torque, int count, double theta)
{
    double t = 0.0;
    int i;
    for (i = 0; i + 1 < count; i++) {
        double a0 = angle[i], a1 = angle[i + 1];
        if (a1 > a0 && theta >= a0 && theta <= a1)
            t += torque[i] + (theta - a0) / (a1 - a0) * (torque[i + 1] - torque[i]);
    }
    return t;
}

/* Integral of Eq 4 from 0 to theta (the table's potential). */
static double rj__table_potential(const double *angle, const double *torque, int count,
                                  double theta)
{
    double v = 0.0;
    int i;
    for (i = 0; i + 1 < count; i++) {
        double a0 = angle[i], a1 = angle[i + 1], hi, k;
        if (!(a1 > a0) || theta <= a0)
            continue;
        hi = theta < a1 ? theta : a1;
        k = (torque[i + 1] - torque[i]) / (a1 - a0);
        v += (hi - a0) * (torque[i] + 0.5 * k * (hi - a0));
    }
    return v;
}

/* Eq 6: bLimit for wrapped theta. forward > reverse: limited outside (reverse, forward);
   forward < reverse: limited inside [forward, reverse] (free range wraps through 0). */
RJDEF int rj_blimit(double theta, double forward, double reverse)
{
    if (forward > reverse)
        return theta >= forward || theta <= reverse;
    if (forward < reverse)
        return theta >= forward && theta <= reverse;
    return theta == forward;
}

/* Eqs 7-13: next status flag. beyond_forward / beyond_reverse split bLimit by side (our
   reading: a body past the forward limit cannot be "at the reverse limit"). */
RJDEF int rj_flag_next(int prev, int beyond_forward, int beyond_reverse, double rate, int lock,
                       int release)
{
    if (prev == RJ_LOCKED)
        return RJ_LOCKED; /* never released */
    if (lock && (beyond_forward || beyond_reverse))
        return RJ_LOCKED;             /* Eq 7, L = 3 */
    if (release == RJ_RELEASE_RC12) { /* Eqs 8, 9, 12 */
        if (beyond_forward && (prev == RJ_AT_FORWARD || (prev == RJ_FREE && rate >= 0)))
            return RJ_AT_FORWARD;
        if (beyond_reverse && (prev == RJ_AT_REVERSE || (prev == RJ_FREE && rate <= 0)))
            return RJ_AT_REVERSE;
        return RJ_FREE;
    }
    /* RC13, Eqs 10, 11, 13: the motion must still point into the limit */
    if (beyond_forward && (prev == RJ_FREE || prev == RJ_AT_FORWARD) && rate >= 0)
        return RJ_AT_FORWARD;
    if (beyond_reverse && (prev == RJ_FREE || prev == RJ_AT_REVERSE) && rate <= 0)
        return RJ_AT_REVERSE;
    return RJ_FREE;
}

/* Eq 21. I1 or I2 may be infinite (ground). */
RJDEF double rj_k_adaptive(double I1, double I2, double dt)
{
    double ired;
    if (!rj__finite(I1))
        ired = I2;
    else if (!rj__finite(I2))
        ired = I1;
    else
        ired = I1 * I2 / (I1 + I2);
    return ired / (dt * dt);
}

/* Eqs 23-24: w2' = (w2 (I2 - I1 e) + I1 w1 (1 + e)) / (I1 + I2), w1' = w2' - e (w1 - w2),
   written with the shares so that an infinite I1 (ground) works. */
RJDEF void rj_momentum_balance(double I1, double I2, double e, double *w1, double *w2)
{
    double a1, a2, o1 = *w1, o2 = *w2, n1, n2;
    if (!rj__finite(I1)) {
        a1 = 1.0;
        a2 = 0.0;
    } else if (!rj__finite(I2)) {
        a1 = 0.0;
        a2 = 1.0;
    } else {
        a1 = I1 / (I1 + I2);
        a2 = I2 / (I1 + I2);
    }
    n2 = o2 * (a2 - a1 * e) + a1 * o1 * (1.0 + e);
    n1 = n2 - e * (o1 - o2);
    *w1 = n1;
    *w2 = n2;
}

/* Eqs 25-26: common velocity with the kinetic energy kept. */
RJDEF void rj_energy_balance(double I1, double I2, double *w1, double *w2)
{
    double a1, a2, s, w;
    if (!rj__finite(I1)) {
        a1 = 1.0;
        a2 = 0.0;
    } else if (!rj__finite(I2)) {
        a1 = 0.0;
        a2 = 1.0;
    } else {
        a1 = I1 / (I1 + I2);
        a2 = I2 / (I1 + I2);
    }
    s = a1 * *w1 * fabs(*w1) + a2 * *w2 * fabs(*w2);
    w = (s >= 0 ? 1.0 : -1.0) * sqrt(fabs(s));
    *w1 = w;
    *w2 = w;
}


/* A prescribed joint's running angle at t (rj_actuator_def, RJ_ACTUATOR_PRESCRIBED):
   angle0 until start, then angle0 plus the profile of the time since. */
/* The clamped cubic spline (rest at both ends) through n points (x strictly increasing,
   y): its second derivatives into M, by the tridiagonal solve (Thomas; work: n doubles). */
static void rj__spline_build(int n, const double *x, const double *y, double *M, double *work)
{
    int i;
    /* rows: h_{i-1} M_{i-1} + 2 (h_{i-1} + h_i) M_i + h_i M_{i+1} = 6 (slope_i - slope_{i-1}),
       ends: 2 h M_0 + h M_1 = 6 slope_0, h M_{n-2} + 2 h M_{n-1} = -6 slope_{n-2} */
    for (i = 0; i < n; i++) {
        const double hl = i > 0 ? x[i] - x[i - 1] : 0, hr = i < n - 1 ? x[i + 1] - x[i] : 0;
        const double sl = i > 0 ? (y[i] - y[i - 1]) / hl : 0;
        const double sr = i < n - 1 ? (y[i + 1] - y[i]) / hr : 0;
        const double diag = 2 * (hl + hr), rhs = 6 * (sr - sl);
        const double m = i > 0 ? hl / work[i - 1] : 0;
        work[i] = diag - m * hl;
        M[i] = rhs - m * (i > 0 ? M[i - 1] : 0);
    }
    for (i = n - 1; i >= 0; i--) {
        const double hr = i < n - 1 ? x[i + 1] - x[i] : 0;
        M[i] = (M[i] - (i < n - 1 ? hr * M[i + 1] : 0)) / work[i];
    }
}

/* The spline of rj__spline_build at t, held at the end values outside [x_0, x_{n-1}]. */
static double rj__spline_at(int n, const double *x, const double *y, const double *M, double t)
{
    int k;
    if (!(t > x[0]))
        return y[0];
    for (k = 1; k < n; k++)
        if (t < x[k]) {
            const double h = x[k] - x[k - 1], A = (x[k] - t) / h, B = 1 - A;
            return A * y[k - 1] + B * y[k] +
                   ((A * A * A - A) * M[k - 1] + (B * B * B - B) * M[k]) * h * h / 6;
        }
    return y[n - 1];
}

static double rj__profile_angle(const rj_actuator_def *a, const double *spline, double angle0,
                                double t)
{
    const double tau = t - a->start, v = a->profile_value, T = a->profile_time;
    double x;
    if (a->profile == RJ_PROFILE_TABLE)
        return angle0 + rj__spline_at(a->table_count, a->table_time, a->table_factor, spline,
                                      tau);
    if (!(tau > 0))
        return angle0;
    switch (a->profile) {
    case RJ_PROFILE_RAMP:
        return angle0 + v * tau;
    case RJ_PROFILE_CYCLOIDAL:
        if (tau >= T)
            return angle0 + v;
        x = tau / T;
        return angle0 + v * (x - sin(2.0 * RJ__PI * x) / (2.0 * RJ__PI));
    default:
        if (tau >= T)
            return angle0 + v * (tau - 0.5 * T);
        x = T / (2.0 * RJ__PI);
        return angle0 + (v / T) * (0.5 * tau * tau + x * x * (cos(tau / x) - 1.0));
    }
}

/* A factor in time from a table of count points (times strictly increasing): linear
   between the points, held at the end values outside them; 1 without a table (a load's,
   an actuator's). */
static double rj__time_factor(int count, const double *time, const double *factor, double t)
{
    const int last = count - 1;
    int k;
    if (count == 0)
        return 1.0;
    if (!(t > time[0]))
        return factor[0];
    for (k = 1; k <= last; k++)
        if (t < time[k]) {
            const double t0 = time[k - 1], t1 = time[k];
            const double f0 = factor[k - 1], f1 = factor[k];
            return f0 + (f1 - f0) * ((t - t0) / (t1 - t0));
        }
    return factor[last];
}
