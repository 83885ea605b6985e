/* ------------------------------------------------------------------ implicit Kelvin-Voigt damping */
/* Kelvin-Voigt damping is stiffness-proportional: on the lagged rates (v^{n-1/2}) it
   bounds the step by dt <= (2 / omega)(sqrt(1 + zeta^2) - zeta) at the stiffest mode,
   an element's axial or rotary one, whose ratio eta omega_max / 2 is huge on a slender
   link (the paper's deployment at 2 % and 2 Hz: a step 340 times shorter). So a link's
   viscous forces are taken on the rates at n + 1/2 instead, F_d = -C v^{n+1/2}: each
   step solves

       (M + kick C) dv = -kick C v*,   v^{n+1/2} = v* + dv,

   v* the velocities the other forces give. C = sum_e B_e^T D_e B_e is the link's damping
   matrix: B_e maps an element's node rates to its strains' rates (the Green strain's
   e . e' / l0^2 and the end rotations' w - beta', as rj__elem_viscous takes them) along
   its chord at n + 1/2 as v* predicts it (objective: a rigid turn strains nothing), D_e
   their stiffnesses times eta. M + kick C is block tridiagonal along the
   link (3 x 3 blocks, a node's x, y, rotation) and positive definite: one pass down and
   one up (block Thomas), O(n). A DOF that does not move (inverse mass 0) keeps dv = 0.

   The scheme is stable at the undamped bound for any eta (for one mode x'' + c x' +
   omega^2 x = 0 taken so, the step needs omega dt < sqrt(4 + 2 c dt)), and damps a mode
   of omega dt << 1 at ratio eta omega / 2 as before. Links whose nodes a rigid body
   carries keep the lagged form (their bound counts it). */

/* An element's damping matrix C_e = B^T D B (6 x 6 over its nodes' x, y, rotation: node a,
   then b) for chord (ex, ey) and constants kc (rj_model.link_kc), as three blocks: C_aa,
   C_ab, C_bb (row-major 3 x 3 each) into out[27]. B's rows: the Green strain's rate
   e . e' (stiffness d = eta EA / l0^3) on (-e, e) over the translations; the end
   rotations' w - beta', beta' = t . (v_a - v_b) with t = (e_y, -e_x) / |e|^2, their
   moments k [4 2; 2 4] (k = eta EI / l0). Written out: the translations take P =
   d e e^T + 12 k t t^T as [P -P; -P P], node a's translation and either rotation
   -6 k t, node b's +6 k t, the rotations k [4 2; 2 4]. */
static RJ__INLINE void rj__visc_elem(const double *kc, double eta, double ex, double ey,
                                     double out[27])
{
    const double inv_l2 = 1.0 / (ex * ex + ey * ey);
    const double d = eta * kc[1] * 2.0 * kc[3];
    const double k = eta * kc[0];
    const double tx = ey * inv_l2, ty = -ex * inv_l2;
    const double pxx = d * ex * ex + 12.0 * k * tx * tx;
    const double pxy = d * ex * ey + 12.0 * k * tx * ty;
    const double pyy = d * ey * ey + 12.0 * k * ty * ty;
    const double qx = 6.0 * k * tx, qy = 6.0 * k * ty;
    const double aa[9] = { pxx, pxy, -qx, pxy, pyy, -qy, -qx, -qy, 4.0 * k };
    const double ab[9] = { -pxx, -pxy, -qx, -pxy, -pyy, -qy, qx, qy, 2.0 * k };
    const double bb[9] = { pxx, pxy, qx, pxy, pyy, qy, qx, qy, 4.0 * k };
    memcpy(out, aa, sizeof aa);
    memcpy(out + 9, ab, sizeof ab);
    memcpy(out + 18, bb, sizeof bb);
}

/* out += A v (A row-major 3 x 3). */
static RJ__INLINE void rj__visc_mv(const double *A, const double *v, double *out)
{
    out[0] += A[0] * v[0] + A[1] * v[1] + A[2] * v[2];
    out[1] += A[3] * v[0] + A[4] * v[1] + A[5] * v[2];
    out[2] += A[6] * v[0] + A[7] * v[1] + A[8] * v[2];
}

/* out += A^T v. */
static RJ__INLINE void rj__visc_mtv(const double *A, const double *v, double *out)
{
    out[0] += A[0] * v[0] + A[3] * v[1] + A[6] * v[2];
    out[1] += A[1] * v[0] + A[4] * v[1] + A[7] * v[2];
    out[2] += A[2] * v[0] + A[5] * v[1] + A[8] * v[2];
}

/* The inverse of a symmetric positive definite 3 x 3 matrix (cofactors). */
static RJ__INLINE void rj__visc_inv3(const double *A, double *inv)
{
    const double c00 = A[4] * A[8] - A[5] * A[7];
    const double c01 = A[5] * A[6] - A[3] * A[8];
    const double c02 = A[3] * A[7] - A[4] * A[6];
    const double det = A[0] * c00 + A[1] * c01 + A[2] * c02;
    const double r = 1.0 / det;
    inv[0] = c00 * r;
    inv[1] = (A[2] * A[7] - A[1] * A[8]) * r;
    inv[2] = (A[1] * A[5] - A[2] * A[4]) * r;
    inv[3] = c01 * r;
    inv[4] = (A[0] * A[8] - A[2] * A[6]) * r;
    inv[5] = (A[2] * A[3] - A[0] * A[5]) * r;
    inv[6] = c02 * r;
    inv[7] = (A[1] * A[6] - A[0] * A[7]) * r;
    inv[8] = (A[0] * A[4] - A[1] * A[3]) * r;
}

/* A link's system, node by node in the scratch (RJ__VISC_PER doubles a node), after a
   record before the first node whose element and solution are 0 (and the last node's
   element 0), so that every node is solved alike: */
enum {
    RJ__VI_DINV = 0,  /* the pivot block's inverse */
    RJ__VI_Y = 9,     /* z_i, then dv */
    RJ__VI_V = 12,    /* v*: the velocities the other forces give */
    RJ__VI_MINV = 15, /* the DOFs' inverse masses (0: does not move) */
    RJ__VI_C = 18,    /* the element from this node to the next: C_aa, C_ab, C_bb */
    RJ__VI_U = 45,    /* its coupling block in the system (rj__visc_upper) */
    RJ__VI_E = 54,    /* its chord at n + 1/2 as predicted (rj__visc_chord) */
    RJ__VI_T = 56,    /* D^-1 times the coupling block (block LDL^T) */
    RJ__VI_MASK = 65, /* 1 for a DOF that moves, 0 for one that does not */
    RJ__VI_MASS = 68, /* its mass (1 where it does not move: the identity's row) */
    RJ__VISC_PER = 71
};

/* The record before the first node's: its element and solution 0. */
static void rj__visc_pad(double *W)
{
    double *pad = W - RJ__VISC_PER;
    memset(pad, 0, sizeof(double) * RJ__VISC_PER);
}

/* Node i's rows of C v (into cv): the element before it (its C_bb, C_ab^T) and the one
   after (C_aa, C_ab), from the velocities v* of each node's record. */
static RJ__INLINE void rj__visc_cv(const double *W, int i, double *cv)
{
    const double *me = W + (size_t) RJ__VISC_PER * i, *before = me - RJ__VISC_PER;
    cv[0] = cv[1] = cv[2] = 0;
    rj__visc_mv(before + RJ__VI_C + 18, me + RJ__VI_V, cv);
    rj__visc_mtv(before + RJ__VI_C + 9, before + RJ__VI_V, cv);
    rj__visc_mv(me + RJ__VI_C, me + RJ__VI_V, cv);
    rj__visc_mv(me + RJ__VI_C + 9, me + RJ__VISC_PER + RJ__VI_V, cv);
}

/* The coupling block A_{i,i+1} = kick C_ab of element i, with the rows of node i's and the
   columns of node i + 1's fixed DOFs zero, into node i's record. */
static RJ__INLINE void rj__visc_upper(double *W, int i, double kick)
{
    double *me = W + (size_t) RJ__VISC_PER * i;
    const double *next = me + RJ__VISC_PER;
    int p, q;
    for (p = 0; p < 3; p++)
        for (q = 0; q < 3; q++)
            me[RJ__VI_U + 3 * p + q] = kick * me[RJ__VI_MASK + p] * next[RJ__VI_MASK + q] *
                                       me[RJ__VI_C + 9 + 3 * p + q];
}

/* Node i's diagonal block M + kick (C_bb before + C_aa after); a fixed DOF's row and
   column are the identity's. */
static RJ__INLINE void rj__visc_diag(const double *W, int i, double kick, double *A)
{
    const double *me = W + (size_t) RJ__VISC_PER * i, *before = me - RJ__VISC_PER;
    int p, q;
    for (p = 0; p < 3; p++)
        for (q = 0; q < 3; q++)
            A[3 * p + q] = kick * me[RJ__VI_MASK + p] * me[RJ__VI_MASK + q] *
                           (me[RJ__VI_C + 3 * p + q] + before[RJ__VI_C + 18 + 3 * p + q]);
    for (p = 0; p < 3; p++)
        A[4 * p] += me[RJ__VI_MASS + p];
}

/* (M + kick C) dv = -kick C v* over a link's nodes (their records in W filled: v*, the
   inverse masses, each element's blocks; the record before W padded): dv into each
   record's RJ__VI_Y. Block LDL^T: the pivots D_i = A_ii - U^T D_{i-1}^-1 U (U =
   A_{i-1,i}, symmetric), z_i = D_i^-1 (y_i - U^T z_{i-1}), then dv_i = z_i - T_i dv_{i+1}
   with T_i = D_i^-1 A_{i,i+1}. */
static void rj__visc_solve(double *W, int nodes, double kick)
{
    double A[9], y[3];
    int i, p, q;
    for (i = 0; i < nodes; i++) {
        double *me = W + (size_t) RJ__VISC_PER * i;
        const double *before = me - RJ__VISC_PER;
        const double *U = before + RJ__VI_U, *T = before + RJ__VI_T;
        rj__visc_cv(W, i, y);
        for (p = 0; p < 3; p++)
            y[p] *= -kick * me[RJ__VI_MASK + p];
        rj__visc_diag(W, i, kick, A);
        /* A -= U^T T (its upper triangle, then mirrored) and y -= U^T z_{i-1} */
        for (p = 0; p < 3; p++)
            for (q = p; q < 3; q++)
                A[3 * p + q] -= U[p] * T[q] + U[3 + p] * T[3 + q] + U[6 + p] * T[6 + q];
        A[3] = A[1];
        A[6] = A[2];
        A[7] = A[5];
        for (p = 0; p < 3; p++)
            y[p] -= U[p] * before[RJ__VI_Y] + U[3 + p] * before[RJ__VI_Y + 1] +
                    U[6 + p] * before[RJ__VI_Y + 2];
        rj__visc_inv3(A, me + RJ__VI_DINV);
        me[RJ__VI_Y] = me[RJ__VI_Y + 1] = me[RJ__VI_Y + 2] = 0;
        rj__visc_mv(me + RJ__VI_DINV, y, me + RJ__VI_Y);
        rj__visc_upper(W, i, kick);
        for (p = 0; p < 3; p++)
            for (q = 0; q < 3; q++)
                me[RJ__VI_T + 3 * p + q] = me[RJ__VI_DINV + 3 * p] * me[RJ__VI_U + q] +
                                           me[RJ__VI_DINV + 3 * p + 1] * me[RJ__VI_U + 3 + q] +
                                           me[RJ__VI_DINV + 3 * p + 2] * me[RJ__VI_U + 6 + q];
    }
    /* back: dv_i = z_i - T_i dv_{i+1} (the last node's T is 0) */
    for (i = nodes - 2; i >= 0; i--) {
        double *me = W + (size_t) RJ__VISC_PER * i;
        double t[3] = { 0, 0, 0 };
        rj__visc_mv(me + RJ__VI_T, me + RJ__VISC_PER + RJ__VI_Y, t);
        for (p = 0; p < 3; p++)
            me[RJ__VI_Y + p] -= t[p];
    }
}
