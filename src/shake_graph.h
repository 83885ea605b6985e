/* ------------------------------------------------------------------ SHAKE over chains that meet */
/* Inextensible chains that meet (a chain hanging from inside another, or a loop closed
   through a moving pin) are not tridiagonal: an element couples to every element that
   moves one of its nodes. Their elements form one sparse system A lambda = r, with
   A_ij = 4 sum_k s_ik s_jk w_k (e_i . e_j^n) over the owners k the two share (a pin
   group or a node; s = -1 at an element's first node, +1 at its second). Built once:
   the elements ordered by reverse Cuthill-McKee, so the factor's profile (envelope)
   stays narrow (a chain 1, a ring 2), with its first column per row. Each step factors
   A in that profile (Crout, no pivoting: A is a small perturbation of J W J^T, which is
   positive definite away from singular positions) without allocating. A pivot below
   1e-10 of its diagonal is a redundant element (a flat loop): its lambda is 0. */

/* The element graph's owner of a node: its pin group's first member, or the node;
   -1 for a node that does not move (inverse mass 0). */
static int rj__gs_owner(const rj_model *m, int k)
{
    const int g = m->node_grp[k];
    if (m->einv[k] == 0)
        return -1;
    return g >= 0 ? m->grp_node[m->grp_first[g]] : k;
}

/* Chains that meet: a moving pin group holding entries of two chains, or two entries
   of one chain (a loop). A group on a moving rigid body stays with the chain solver.
   Marks each such chain (mark: nch ints); count: ng ints. Returns how many. */
static int rj__gs_mark_chains(const rj_model *m, int *count, int *mark)
{
    int c, q, g, marked = 0;
    for (g = 0; g < m->ng; g++)
        count[g] = 0;
    for (q = 0; q < m->ch_first[m->nch]; q++) {
        g = m->node_grp[m->ch_node[q]];
        if (g >= 0 && m->grp_inv[g] > 0)
            count[g]++;
    }
    /* a group with a node on a moving body: its chains are solved with the body */
    for (g = 0; g < m->ng && m->ncl; g++)
        for (q = m->grp_first[g]; q < m->grp_first[g + 1]; q++) {
            const int cl = m->node_cl[m->grp_node[q]];
            if (cl >= 0 && m->cl_fix[cl] != 2)
                count[g] = 0;
        }
    for (c = 0; c < m->nch; c++) {
        mark[c] = 0;
        for (q = m->ch_first[c]; q < m->ch_first[c + 1]; q++) {
            g = m->node_grp[m->ch_node[q]];
            if (g >= 0 && count[g] >= 2)
                mark[c] = 1;
        }
        marked += mark[c];
    }
    return marked;
}

/* The marked chains' elements (their end nodes, squared lengths) in chain order; the
   chain list keeps the others, moved down over the taken ones. Returns the count. */
static int rj__gs_take_chains(rj_model *m, const int *mark, int *na, int *nb, double *l0sq)
{
    int c, q, n = 0, kept = 0, kept_chains = 0;
    for (c = 0; c < m->nch; c++) {
        const int f0 = m->ch_first[c], f1 = m->ch_first[c + 1];
        if (!mark[c]) {
            for (q = f0; q < f1; q++) {
                m->ch_node[kept + q - f0] = m->ch_node[q];
                m->ch_l0sq[kept + q - f0] = m->ch_l0sq[q];
            }
            kept += f1 - f0;
            m->ch_first[++kept_chains] = kept;
            continue;
        }
        for (q = f0; q + 1 < f1; q++) {
            na[n] = m->ch_node[q];
            nb[n] = m->ch_node[q + 1];
            l0sq[n] = m->ch_l0sq[q + 1];
            n++;
        }
    }
    m->nch = kept_chains;
    return n;
}

/* The elements that move owner o of each, as lists: list[start[o]] to list[start[o + 1]]
   (start: nn + 1, list: 2 n). */
static void rj__gs_owner_lists(const rj_model *m, int n, const int *oa, const int *ob,
                               int *start, int *list)
{
    int k, i;
    for (k = 0; k <= m->nn; k++)
        start[k] = 0;
    for (i = 0; i < n; i++) {
        if (oa[i] >= 0)
            start[oa[i] + 1]++;
        if (ob[i] >= 0 && ob[i] != oa[i])
            start[ob[i] + 1]++;
    }
    for (k = 0; k < m->nn; k++)
        start[k + 1] += start[k];
    /* filled through start[o] as a cursor, which ends at the next owner's start */
    for (i = 0; i < n; i++) {
        if (oa[i] >= 0)
            list[start[oa[i]]++] = i;
        if (ob[i] >= 0 && ob[i] != oa[i])
            list[start[ob[i]]++] = i;
    }
    for (k = m->nn; k > 0; k--)
        start[k] = start[k - 1];
    start[0] = 0;
}

/* Breadth first from element v over the elements sharing an owner, appending to order
   from *len and marking seen; returns the last element reached (the farthest). */
static int rj__gs_breadth(int v, const int *oa, const int *ob, const int *start,
                          const int *list, int *seen, int *order, int *len)
{
    int head = *len, last = v;
    order[(*len)++] = v;
    seen[v] = 1;
    while (head < *len) {
        const int e = order[head++];
        const int owners[2] = { oa[e], ob[e] };
        int side, q;
        last = e;
        for (side = 0; side < 2; side++) {
            if (owners[side] < 0)
                continue;
            for (q = start[owners[side]]; q < start[owners[side] + 1]; q++)
                if (!seen[list[q]]) {
                    seen[list[q]] = 1;
                    order[(*len)++] = list[q];
                }
        }
    }
    return last;
}

/* Reverse Cuthill-McKee without the degree sort: each connected set of elements from
   its far end (found by one sweep), the whole order then reversed. */
static void rj__gs_order(int n, const int *oa, const int *ob, const int *start,
                         const int *list, int *seen, int *order)
{
    int i, len = 0;
    for (i = 0; i < n; i++)
        seen[i] = 0;
    for (i = 0; i < n; i++) {
        int from = len, far, q;
        if (seen[i])
            continue;
        far = rj__gs_breadth(i, oa, ob, start, list, seen, order, &len);
        for (q = from; q < len; q++)
            seen[order[q]] = 0;
        len = from;
        rj__gs_breadth(far, oa, ob, start, list, seen, order, &len);
    }
    for (i = 0; i < n / 2; i++) {
        const int t = order[i];
        order[i] = order[n - 1 - i];
        order[n - 1 - i] = t;
    }
}

/* The nodes the elements move (every member of a moving pin group), each with its
   owner; mark: nn ints. */
static void rj__gs_nodes(rj_model *m, int *mark)
{
    int k, i, side;
    m->gs_nodes = 0;
    for (k = 0; k < m->nn; k++)
        mark[k] = 0;
    for (i = 0; i < m->gs_n; i++)
        for (side = 0; side < 2; side++) {
            const int node = side ? m->gs_nb[i] : m->gs_na[i];
            const int g = m->node_grp[node];
            const int first = g >= 0 ? m->grp_first[g] : 0, last = g >= 0 ? m->grp_first[g + 1] : 1;
            int q;
            if (rj__gs_owner(m, node) < 0)
                continue;
            for (q = first; q < last; q++) {
                const int member = g >= 0 ? m->grp_node[q] : node;
                if (mark[member])
                    continue;
                mark[member] = 1;
                m->gs_node[m->gs_nodes] = member;
                m->gs_nown[m->gs_nodes] = rj__gs_owner(m, node);
                m->gs_nodes++;
            }
        }
}

/* Builds the system of the chains that meet, taking them from the chain list; scratch
   from the building area (3 ne doubles and 6 ne + 2 nn + ng + nl + 1 ints). */
static void rj__gs_build(rj_model *m, double *area)
{
    double *l0sq = area;
    int *na = (int *) (void *) (area + m->ne), *nb = na + m->ne, *oa = nb + m->ne;
    int *ob = oa + m->ne, *order = ob + m->ne, *seen = order + m->ne;
    int *start = seen + m->ne, *list = start + m->nn + 1, *count = list + 2 * (size_t) m->ne;
    int *mark = count + m->ng + 1;
    int n, i, q;
    m->gs_n = 0;
    m->gs_prof = 0;
    if (!m->nch || !rj__gs_mark_chains(m, count, mark))
        return;
    n = rj__gs_take_chains(m, mark, na, nb, l0sq);
    for (i = 0; i < n; i++) {
        oa[i] = rj__gs_owner(m, na[i]);
        ob[i] = rj__gs_owner(m, nb[i]);
    }
    rj__gs_owner_lists(m, n, oa, ob, start, list);
    rj__gs_order(n, oa, ob, start, list, seen, order);
    /* the elements in the new order; seen becomes each old element's new index */
    m->gs_n = n;
    for (i = 0; i < n; i++) {
        m->gs_na[i] = na[order[i]];
        m->gs_nb[i] = nb[order[i]];
        m->gs_oa[i] = oa[order[i]];
        m->gs_ob[i] = ob[order[i]];
        m->gs_l0sq[i] = l0sq[order[i]];
        seen[order[i]] = i;
    }
    /* the profile: each row from its first coupled column */
    m->gs_off[0] = 0;
    for (i = 0; i < n; i++) {
        const int owners[2] = { m->gs_oa[i], m->gs_ob[i] };
        int first = i, side;
        for (side = 0; side < 2; side++)
            if (owners[side] >= 0)
                for (q = start[owners[side]]; q < start[owners[side] + 1]; q++)
                    if (seen[list[q]] < first)
                        first = seen[list[q]];
        m->gs_first[i] = first;
        m->gs_off[i + 1] = m->gs_off[i] + (i - first);
    }
    m->gs_prof = (size_t) m->gs_off[n];
    rj__gs_nodes(m, start);
}

/* sum_k s_ik s_jk w_k over the owners elements i and j share (see above). */
static double rj__gs_shared(const rj_model *m, int i, int j)
{
    const int ai = m->gs_oa[i], bi = m->gs_ob[i], aj = m->gs_oa[j], bj = m->gs_ob[j];
    double sum = 0;
    if (ai >= 0) {
        sum += ai == aj ? m->einv[ai] : 0.0;
        sum -= ai == bj ? m->einv[ai] : 0.0;
    }
    if (bi >= 0) {
        sum -= bi == aj ? m->einv[bi] : 0.0;
        sum += bi == bj ? m->einv[bi] : 0.0;
    }
    return sum;
}

/* Scratch of the system (rj_state.gsw): the factor's lower and upper profiles, the
   reciprocal pivots, the residuals, the multipliers, the chords now and at n, and each
   owner's push. */
typedef struct rj__gs_work {
    double *lower, *upper, *dinv, *r, *lam, *cx, *cy, *ox, *oy, *push;
} rj__gs_work;

static rj__gs_work rj__gs_carve(const rj_model *m, const rj_state *s)
{
    rj__gs_work w;
    const size_t n = (size_t) m->gs_n;
    w.lower = s->gsw;
    w.upper = w.lower + m->gs_prof;
    w.dinv = w.upper + m->gs_prof;
    w.r = w.dinv + n;
    w.lam = w.r + n;
    w.cx = w.lam + n;
    w.cy = w.cx + n;
    w.ox = w.cy + n;
    w.oy = w.ox + n;
    w.push = w.oy + n;
    return w;
}

/* A = L U in the profile (Crout, row by row): row i of L and column i of U from the
   first coupled column. */
static void rj__gs_factor(const rj_model *m, const rj__gs_work *w)
{
    int i, j, k;
    for (i = 0; i < m->gs_n; i++) {
        const int fi = m->gs_first[i];
        double *li = w->lower + m->gs_off[i] - fi, *ui = w->upper + m->gs_off[i] - fi;
        double aii, d;
        for (j = fi; j < i; j++) {
            const int fj = m->gs_first[j];
            const double *lj = w->lower + m->gs_off[j] - fj, *uj = w->upper + m->gs_off[j] - fj;
            const double shared = 4.0 * rj__gs_shared(m, i, j);
            double aij = shared * (w->cx[i] * w->ox[j] + w->cy[i] * w->oy[j]);
            double aji = shared * (w->cx[j] * w->ox[i] + w->cy[j] * w->oy[i]);
            for (k = fi > fj ? fi : fj; k < j; k++) {
                aij -= li[k] * uj[k];
                aji -= lj[k] * ui[k];
            }
            ui[j] = aji;
            li[j] = aij * w->dinv[j];
        }
        aii = 4.0 * rj__gs_shared(m, i, i) * (w->cx[i] * w->ox[i] + w->cy[i] * w->oy[i]);
        d = aii;
        for (k = fi; k < i; k++)
            d -= li[k] * ui[k];
        /* a pivot gone with its diagonal: a redundant or unmovable element */
        w->dinv[i] = aii > 0 && fabs(d) > 1e-10 * aii ? 1.0 / d : 0.0;
    }
}

/* lambda = A^-1 r: forward through L, back through U by columns. */
static void rj__gs_solve(const rj_model *m, const rj__gs_work *w)
{
    double *y = w->r;
    int i, k;
    for (i = 0; i < m->gs_n; i++) {
        const int fi = m->gs_first[i];
        const double *li = w->lower + m->gs_off[i] - fi;
        for (k = fi; k < i; k++)
            y[i] -= li[k] * y[k];
    }
    for (i = m->gs_n - 1; i >= 0; i--) {
        const int fi = m->gs_first[i];
        const double *ui = w->upper + m->gs_off[i] - fi;
        w->lam[i] = y[i] * w->dinv[i];
        for (k = fi; k < i; k++)
            y[k] -= ui[k] * w->lam[i];
    }
}

/* Each owner's push sum_i s_i lambda_i e_i^n, then every node it moves by 2 w push. */
static void rj__gs_move(const rj_model *m, const rj__gs_work *w, double *nx, double *ny)
{
    double *push = w->push;
    int i, q;
    for (q = 0; q < m->gs_nodes; q++) {
        push[2 * m->gs_nown[q]] = 0;
        push[2 * m->gs_nown[q] + 1] = 0;
    }
    for (i = 0; i < m->gs_n; i++) {
        const double px = w->lam[i] * w->ox[i], py = w->lam[i] * w->oy[i];
        if (m->gs_oa[i] >= 0) {
            push[2 * m->gs_oa[i]] -= px;
            push[2 * m->gs_oa[i] + 1] -= py;
        }
        if (m->gs_ob[i] >= 0) {
            push[2 * m->gs_ob[i]] += px;
            push[2 * m->gs_ob[i] + 1] += py;
        }
    }
    for (q = 0; q < m->gs_nodes; q++) {
        const int k = m->gs_node[q], o = m->gs_nown[q];
        nx[k] += 2.0 * m->einv[k] * push[2 * o];
        ny[k] += 2.0 * m->einv[k] * push[2 * o + 1];
    }
}

/* With loops: each element's push lambda_i e_i^n into shp by its second node, summed over
   the iterations (rj__loop_records takes a loop's pin node's share). */
static void rj__gs_track(const rj_model *m, const rj__gs_work *w, double *shp)
{
    int i;
    for (i = 0; i < m->gs_n; i++) {
        shp[2 * m->gs_nb[i]] += w->lam[i] * w->ox[i];
        shp[2 * m->gs_nb[i] + 1] += w->lam[i] * w->oy[i];
    }
}

/* The residuals -g_i = l0^2 - |e_i|^2 (0 for an element nothing moves), the chords now;
   returns the largest |g_i| / l0^2. */
static double rj__gs_residuals(const rj_model *m, const rj__gs_work *w, const double *nx,
                               const double *ny)
{
    double worst = 0;
    int i;
    for (i = 0; i < m->gs_n; i++) {
        const double ex = nx[m->gs_nb[i]] - nx[m->gs_na[i]];
        const double ey = ny[m->gs_nb[i]] - ny[m->gs_na[i]];
        const int moves = m->gs_oa[i] >= 0 || m->gs_ob[i] >= 0;
        const double g = moves ? ex * ex + ey * ey - m->gs_l0sq[i] : 0.0;
        if (fabs(g) > worst * m->gs_l0sq[i])
            worst = fabs(g) / m->gs_l0sq[i];
        w->r[i] = -g;
        w->cx[i] = ex;
        w->cy[i] = ey;
    }
    return worst;
}

/* Newton iterations on the lengths of the chains that meet; the matrix of the first
   serves the later ones (it changes with the chords by the size of the correction). */
static void rj__shake_graph(const rj_model *m, rj_state *s, const double *x, const double *y,
                            double *nx, double *ny)
{
    const rj__gs_work w = rj__gs_carve(m, s);
    int it, i;
    for (i = 0; i < m->gs_n; i++) {
        w.ox[i] = x[m->gs_nb[i]] - x[m->gs_na[i]];
        w.oy[i] = y[m->gs_nb[i]] - y[m->gs_na[i]];
    }
    for (it = 0; it < 8; it++) {
        if (rj__gs_residuals(m, &w, nx, ny) < 1e-14)
            break;
        if (it == 0)
            rj__gs_factor(m, &w);
        rj__gs_solve(m, &w);
        rj__gs_move(m, &w, nx, ny);
        if (m->nloop)
            rj__gs_track(m, &w, s->shp);
    }
}
