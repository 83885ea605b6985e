/* ------------------------------------------------------------------ SHAKE: inextensible links */
/* Inextensible links: SHAKE. After the position update, Newton iterations on the element
   length constraints |x_{i+1} - x_i|^2 = l0^2 with corrections along the previous chords
   e_i^n, dx_k = 2 w_k (lambda_{k-1} e_{k-1}^n - lambda_k e_k^n) (w: inverse masses, the
   group's for pinned nodes), give a tridiagonal system per chain (Thomas algorithm); links
   joined tip to root form one chain. Velocities follow the corrected positions. */
/* SHAKE weight of a node: its inverse mass, or for a node on a rigid body the body's
   inverse mass seen at that point along the element direction (ux, uy). */
static double rj__shake_w(const rj_model *m, const rj_state *s, int k, const double *nx,
                          const double *ny, double ux, double uy)
{
    const int c = m->ncl ? m->node_cl[k] : -1;
    const double *nc;
    double rx, ry, cr, u2;
    if (c < 0)
        return m->einv[k];
    if (m->cl_fix[c] == 2)
        return 0.0;
    nc = RJ__FCL(m, s->fd[1 - s->cur], c);
    rx = nx[k] - nc[0];
    ry = ny[k] - nc[1];
    cr = rx * uy - ry * ux;
    u2 = ux * ux + uy * uy;
    return (m->cl_fix[c] == 0 ? 1.0 / m->cl_M[c] : 0.0) + cr * cr / (u2 * m->cl_I[c]);
}

/* With loops: a chain's pushes lambda_i e_i^n into shp by each element's second node,
   summed over the iterations (as rj__gs_track; the chords at n as the update takes them). */
static void rj__shake_track(const int *nd, int ne, const double *lam, const double *x,
                            const double *y, double *shp)
{
    int i;
    for (i = 0; i < ne; i++) {
        shp[2 * nd[i + 1]] += lam[i] * (x[nd[i + 1]] - x[nd[i]]);
        shp[2 * nd[i + 1] + 1] += lam[i] * (y[nd[i + 1]] - y[nd[i]]);
    }
}

static void rj__shake(const rj_model *m, rj_state *s, const double *x, const double *y,
                             double *nx, double *ny)
{
    /* element scratch (ne >= chain elements): the factored tridiagonal (multipliers a,
       reciprocal pivots b, upper c), the residuals r, the multipliers lam */
    double *a = s->sha, *b = s->shb, *c = s->shc, *r = s->shr, *lam = s->eu;
    double *nf = s->fd[1 - s->cur], *imp = s->rsc,
           *act = s->ebt; /* act: 1 for an element that can move, 0 between two fixed nodes */
    const double dt = m->dt;
    int ch, it, i, q, gi;
    if (m->nloop)
        memset(s->shp, 0, 2 * sizeof(double) * (size_t) m->nn);
    if (m->gs_n)
        rj__shake_graph(m, s, x, y, nx, ny);
    for (ch = 0; ch < m->nch; ch++) {
        const int *nd = m->ch_node + m->ch_first[ch],
                  ne = m->ch_first[ch + 1] - m->ch_first[ch] - 1;
        const double *l0sq = m->ch_l0sq + m->ch_first[ch];
        int bodies = 0;
        if (m->ncl)
            for (i = 0; i <= ne; i++)
                bodies |= m->node_cl[nd[i]] >= 0 &&
                          m->cl_fix[m->node_cl[nd[i]]] != 2; /* a held body is a fixed node */
        for (i = 0; i < ne; i++) {
            const int k = nd[i], k1 = nd[i + 1];
            act[i] =
                (bodies
                     ? rj__shake_w(m, s, k, nx, ny, 1, 0) + rj__shake_w(m, s, k, nx, ny, 0, 1) +
                           rj__shake_w(m, s, k1, nx, ny, 1, 0) + rj__shake_w(m, s, k1, nx, ny, 0, 1)
                     : m->einv[k] + m->einv[k1]) > 0
                    ? 1.0
                    : 0.0;
        }
        /* (the loops carry a node's position or an element's chord on to the next element
           instead of loading and subtracting it again: the same values) */
        for (it = 0; it < (bodies ? 12 : 4); it++) {
            double worst = 0, px = nx[nd[0]], py = ny[nd[0]], hx = 0,
                   hy = 0; /* hx, hy: the update's old chord i - 1 */
            for (i = 0; i < ne; i++) {
                const double qx = nx[nd[i + 1]], qy = ny[nd[i + 1]];
                const double ex = qx - px, ey = qy - py,
                             g = (ex * ex + ey * ey - l0sq[i + 1]) * act[i];
                if (fabs(g) > worst * l0sq[i + 1])
                    worst = fabs(g) / l0sq[i + 1];
                r[i] = -g;
                px = qx;
                py = qy;
            }
            if (worst < 1e-14)
                break;
            if (it == 0) {
                /* the Newton matrix of the first iteration serves the later ones: it
                   changes with the chords by the size of the correction (about 1e-8) */
                double pox = 0, poy = 0, ox = x[nd[1]] - x[nd[0]],
                       oy = y[nd[1]] - y[nd[0]]; /* old chords i - 1, i */
                for (i = 0; i < ne; i++) {
                    const int k = nd[i], k1 = nd[i + 1];
                    const double ex = nx[k1] - nx[k], ey = ny[k1] - ny[k];
                    const double wi = bodies ? rj__shake_w(m, s, k, nx, ny, ox, oy) : m->einv[k];
                    const double wj = bodies ? rj__shake_w(m, s, k1, nx, ny, ox, oy) : m->einv[k1];
                    double qox = 0, qoy = 0; /* old chord i + 1 */
                    if (i + 1 < ne) {
                        qox = x[nd[i + 2]] - x[k1];
                        qoy = y[nd[i + 2]] - y[k1];
                    }
                    b[i] = 4.0 * (wi + wj) * (ex * ox + ey * oy);
                    a[i] = i > 0 ? -4.0 * wi * (ex * pox + ey * poy) : 0.0;
                    c[i] = i + 1 < ne ? -4.0 * wj * (ex * qox + ey * qoy) : 0.0;
                    if (act[i] == 0) {
                        b[i] = 1.0;
                        a[i] = c[i] = 0.0;
                    } /* an identity row: lam = 0 */
                    pox = ox;
                    poy = oy;
                    ox = qox;
                    oy = qoy;
                }
                b[0] = 1.0 / b[0];
                for (i = 1; i < ne; i++) {
                    a[i] *= b[i - 1];
                    b[i] = 1.0 / (b[i] - a[i] * c[i - 1]);
                }
            }
            for (i = 1; i < ne; i++)
                r[i] -= a[i] * r[i - 1];
            lam[ne - 1] = r[ne - 1] * b[ne - 1];
            for (i = ne - 2; i >= 0; i--)
                lam[i] = (r[i] - c[i] * lam[i + 1]) * b[i];
            if (m->nloop)
                rj__shake_track(nd, ne, lam, x, y, s->shp);
            if (bodies)
                for (q = 0; q < 3 * m->ncl; q++)
                    imp[q] = 0;
            for (i = 0; i <= ne; i++) {
                const int k = nd[i];
                double dx = 0, dy = 0, ox = 0, oy = 0;
                if (i > 0) {
                    dx += lam[i - 1] * hx;
                    dy += lam[i - 1] * hy;
                }
                if (i < ne) {
                    ox = x[nd[i + 1]] - x[k];
                    oy = y[nd[i + 1]] - y[k];
                    dx -= lam[i] * ox;
                    dy -= lam[i] * oy;
                }
                hx = ox;
                hy = oy;
                if (bodies && m->node_cl[k] >= 0) {
                    /* on a body: the body takes the push (mass times displacement 2 dx) */
                    const int cl = m->node_cl[k];
                    const double *nc = RJ__FCL(m, nf, cl);
                    imp[3 * cl] += 2.0 * dx;
                    imp[3 * cl + 1] += 2.0 * dy;
                    imp[3 * cl + 2] += (nx[k] - nc[0]) * 2.0 * dy - (ny[k] - nc[1]) * 2.0 * dx;
                    continue;
                }
                nx[k] += 2.0 * m->einv[k] * dx;
                ny[k] += 2.0 * m->einv[k] * dy;
            }
            if (bodies)
                for (q = 0; q < m->ncl; q++) {
                    double *nc = RJ__FCL(m, nf, q);
                    if (m->cl_first[q] == m->cl_first[q + 1] || m->cl_fix[q] == 2 ||
                        (imp[3 * q] == 0 && imp[3 * q + 1] == 0 && imp[3 * q + 2] == 0))
                        continue;
                    rj__cl_push(m, q, imp + 3 * q, dt, nc);
                    rj__cl_pose(m, q, nc, x, y, dt, 1, nx, ny, RJ__FPHI(m, nf), RJ__FVX(m, nf),
                                RJ__FVY(m, nf), RJ__FW(m, nf));
                }
        }
    }
    /* pins: every member of a group takes the position of the member a chain moved last */
    for (gi = 0; gi < m->ng; gi++) {
        const int f0 = m->grp_first[gi], f1 = m->grp_first[gi + 1];
        int src = m->grp_node[f0];
        for (q = f0; q < f1; q++)
            if (nx[m->grp_node[q]] != nx[src] || ny[m->grp_node[q]] != ny[src]) {
                /* the chain entry is the lowest-index member on an inextensible link */
                int k;
                for (k = f0; k < f1; k++) {
                    int l, on = 0;
                    for (l = 0; l < m->nl; l++)
                        if (m->grp_node[k] >= m->link_first[l] &&
                            m->grp_node[k] < m->link_first[l + 1] &&
                            m->ldef[l].fidelity == RJ_LINK_INEXTENSIBLE)
                            on = 1;
                    if (on) {
                        src = m->grp_node[k];
                        break;
                    }
                }
                break;
            }
        for (q = f0; q < f1; q++) {
            nx[m->grp_node[q]] = nx[src];
            ny[m->grp_node[q]] = ny[src];
        }
    }
}


