/* ------------------------------------------------------------------ assembly */
/* rj_scene_assemble: a user writes approximate angles; this closes the loops. The tree
   (each link hanging from its first joint as body2) places the links from the joints'
   angle0 exactly as rj_model_create does; each joint that closes a loop leaves a gap
   between its pins. The angle0 of the tree joints on the loops, all but each loop's
   first (its input, the crank of a four-bar), move by Gauss-Newton with the least change
   (minimum norm: dq = -J^T (J J^T)^-1 gap, J by central differences; Levenberg-Marquardt
   damping where that step does not shrink the gaps) until every gap is below 1e-13 of
   the longest link; then each loop joint's angle0 is the angle the geometry gives it. A
   loop that cannot close ends at the least gap the links allow, which is reported. */

/* The assembly's working arrays, one block: per link its angle, root, parent joint and
   marks; per joint its unknown's index; the Jacobian, its normal matrix and factor, the
   gaps and the step. */
typedef struct rj__asm {
    const rj_scene_def *sc;
    rj_joint_def *joints;
    double *phi, *rx, *ry;
    int *parent, *placed, *path, *unknown, *marks;
    int nu, nloop;
    double *J, *N, *D, *NL, *gap, *y, *trial;
} rj__asm;

/* Node at of link l's straight placement: its root plus at element lengths. */
static void rj__asm_node(const rj__asm *A, int l, int at, double p[2])
{
    const rj_link_def *d = &A->sc->links[l];
    const double along = d->length / d->elements * at;
    p[0] = A->rx[l] + along * cos(A->phi[l]);
    p[1] = A->ry[l] + along * sin(A->phi[l]);
}

/* Joint j's pin on body 1 and the direction theta is measured from there (ground: the
   fixed point and direction; a link: back towards its root, or along it at node 0). */
static void rj__asm_pin1(const rj__asm *A, int j, double p[2], double *ref)
{
    const rj_joint_def *d = &A->joints[j];
    int at;
    if (d->body1 < 0) {
        p[0] = d->ground_x;
        p[1] = d->ground_y;
        *ref = d->ground_angle;
        return;
    }
    at = d->node1 < 0 ? A->sc->links[d->body1].elements : d->node1;
    rj__asm_node(A, d->body1, at, p);
    *ref = A->phi[d->body1] + (at > 0 ? RJ__PI : 0.0);
}

/* Joint j's pin on body 2. */
static void rj__asm_pin2(const rj__asm *A, int j, double p[2])
{
    const rj_joint_def *d = &A->joints[j];
    rj__asm_node(A, d->body2, d->node2 < 0 ? A->sc->links[d->body2].elements : d->node2, p);
}

/* Link l placed from its parent joint (rj__place_link's geometry), or at its own root. */
static void rj__asm_place_link(rj__asm *A, int l)
{
    const int j = A->parent[l];
    const rj_link_def *ld = &A->sc->links[l];
    double pin[2], ref, along;
    int at;
    if (j < 0) {
        A->phi[l] = ld->angle;
        A->rx[l] = ld->x;
        A->ry[l] = ld->y;
        return;
    }
    rj__asm_pin1(A, j, pin, &ref);
    A->phi[l] = ref + A->joints[j].angle0;
    at = A->joints[j].node2 < 0 ? ld->elements : A->joints[j].node2;
    along = ld->length / ld->elements * at;
    A->rx[l] = pin[0] - along * cos(A->phi[l]);
    A->ry[l] = pin[1] - along * sin(A->phi[l]);
}

/* Every link, parents first (the walk of rj__place_all). */
static void rj__asm_place(rj__asm *A)
{
    const int nl = A->sc->link_count;
    int l;
    for (l = 0; l < nl; l++)
        A->placed[l] = 0;
    for (l = 0; l < nl; l++) {
        int depth = 0, cur = l;
        while (cur >= 0 && !A->placed[cur]) {
            A->path[depth++] = cur;
            cur = A->parent[cur] >= 0 ? A->joints[A->parent[cur]].body1 : -1;
        }
        while (depth > 0) {
            cur = A->path[--depth];
            rj__asm_place_link(A, cur);
            A->placed[cur] = 1;
        }
    }
}

/* Whether joint j closes a loop (its body2 hangs from another joint). */
static int rj__asm_loop(const rj__asm *A, int j)
{
    return A->parent[A->joints[j].body2] != j;
}

/* The gaps pin1 - pin2 of the loop joints, two each, into gap; the largest returned. */
static double rj__asm_gaps(rj__asm *A, double *gap)
{
    double worst = 0;
    int j, k = 0;
    rj__asm_place(A);
    for (j = 0; j < A->sc->joint_count; j++) {
        double p1[2], p2[2], ref;
        if (!rj__asm_loop(A, j))
            continue;
        rj__asm_pin1(A, j, p1, &ref);
        rj__asm_pin2(A, j, p2);
        gap[k] = p1[0] - p2[0];
        gap[k + 1] = p1[1] - p2[1];
        worst = fmax(worst, hypot(gap[k], gap[k + 1]));
        k += 2;
    }
    return worst;
}

/* Marks (1) the tree joints between link l and the ground; returns nothing. A joint seen
   from both sides of a loop (above where they meet) gets 2 and moves nothing in it. */
static void rj__asm_mark_path(rj__asm *A, int l, int *mark)
{
    while (l >= 0 && A->parent[l] >= 0) {
        mark[A->parent[l]]++;
        l = A->joints[A->parent[l]].body1;
    }
}

/* The unknowns: every tree joint on a loop but, when hold, each loop's first (lowest
   index), which keeps its angle0. Returns their count. */
static int rj__asm_unknowns(rj__asm *A, int hold)
{
    const int nj = A->sc->joint_count;
    int j, k, nu = 0;
    for (j = 0; j < nj; j++)
        A->unknown[j] = -2; /* not on a loop */
    for (j = 0; j < nj; j++) {
        int first = -1;
        if (!rj__asm_loop(A, j))
            continue;
        for (k = 0; k < nj; k++)
            A->marks[k] = 0;
        if (A->joints[j].body1 >= 0)
            rj__asm_mark_path(A, A->joints[j].body1, A->marks);
        rj__asm_mark_path(A, A->joints[j].body2, A->marks);
        for (k = 0; k < nj; k++) {
            if (A->marks[k] != 1)
                continue;
            if (first < 0)
                first = k;
            if (A->unknown[k] == -2)
                A->unknown[k] = -1; /* on a loop: an unknown unless some loop holds it */
        }
        if (first >= 0 && hold)
            A->unknown[first] = -3; /* held: the loop's input */
    }
    for (j = 0; j < nj; j++)
        if (A->unknown[j] == -1)
            A->unknown[j] = nu++;
    return nu;
}

/* The Jacobian of the gaps over the unknowns by central differences (1e-7 rad), column
   by column into A->J (rows 2 nloop, stride nu). */
static void rj__asm_jacobian(rj__asm *A)
{
    const int rows = 2 * A->nloop, nu = A->nu;
    const double h = 1e-7;
    int j, k;
    for (j = 0; j < A->sc->joint_count; j++) {
        const int u = A->unknown[j];
        const double keep = A->joints[j].angle0;
        if (u < 0)
            continue;
        A->joints[j].angle0 = keep + h;
        rj__asm_gaps(A, A->trial);
        for (k = 0; k < rows; k++)
            A->J[(size_t) k * nu + u] = A->trial[k];
        A->joints[j].angle0 = keep - h;
        rj__asm_gaps(A, A->trial);
        for (k = 0; k < rows; k++)
            A->J[(size_t) k * nu + u] = (A->J[(size_t) k * nu + u] - A->trial[k]) / (2 * h);
        A->joints[j].angle0 = keep;
    }
}

/* Moves the unknowns by -J^T y (y from rj__asm_step), keeping their angles in trial. */
static void rj__asm_move(rj__asm *A, int rows)
{
    int a, j;
    for (j = 0; j < A->sc->joint_count; j++) {
        double dq = 0;
        const int u = A->unknown[j];
        if (u < 0)
            continue;
        for (a = 0; a < rows; a++)
            dq -= A->J[(size_t) a * A->nu + u] * A->y[a];
        A->trial[rows + u] = A->joints[j].angle0;
        A->joints[j].angle0 += dq;
    }
}

/* One Levenberg-Marquardt step in the gaps' space: (J J^T + lambda) y = gap, dq = -J^T y,
   the least change that closes the gaps for lambda near 0 (Gauss-Newton), a short step
   down the gaps' gradient for lambda large; lambda grows tenfold until the largest gap
   falls (at most 30 times), and the step it took is the next one's start. Returns the
   largest gap after it (the one before when no lambda helps). */
static double rj__asm_step(rj__asm *A, double worst, double *lambda)
{
    const int rows = 2 * A->nloop, nu = A->nu;
    double largest = 0, after;
    int a, b, k, j, tries;
    rj__asm_jacobian(A);
    for (a = 0; a < rows; a++)
        for (b = 0; b < rows; b++) {
            double sum = 0;
            for (k = 0; k < nu; k++)
                sum += A->J[(size_t) a * nu + k] * A->J[(size_t) b * nu + k];
            A->N[(size_t) a * rows + b] = sum;
            largest = a == b ? fmax(largest, sum) : largest;
        }
    for (tries = 0; tries < 30; tries++, *lambda *= 10) {
        memcpy(A->D, A->N, sizeof(double) * (size_t) rows * (size_t) rows);
        for (a = 0; a < rows; a++)
            A->D[(size_t) a * rows + a] += *lambda * largest + 1e-300;
        if (rj__chol(rows, A->D, A->NL))
            continue;
        rj__chol_solve(rows, A->NL, A->gap, A->y);
        rj__asm_move(A, rows);
        after = rj__asm_gaps(A, A->trial);
        if (after < worst) {
            *lambda = fmax(*lambda * 0.01, 1e-14);
            return rj__asm_gaps(A, A->gap);
        }
        for (j = 0; j < A->sc->joint_count; j++)
            if (A->unknown[j] >= 0)
                A->joints[j].angle0 = A->trial[rows + A->unknown[j]];
    }
    return worst;
}

/* The loop joint whose gap is largest, and that gap. */
static int rj__asm_worst(rj__asm *A, double *gap_out)
{
    int j, k = 0, worst = -1;
    double g = -1;
    for (j = 0; j < A->sc->joint_count; j++) {
        double here;
        if (!rj__asm_loop(A, j))
            continue;
        here = hypot(A->gap[k], A->gap[k + 1]);
        if (here > g) {
            g = here;
            worst = j;
        }
        k += 2;
    }
    *gap_out = g;
    return worst;
}

/* Each loop joint's angle0: the angle the closed geometry gives it, the nearest to the
   one written (a whole turn apart at most). */
static void rj__asm_loop_angles(rj__asm *A)
{
    int j;
    rj__asm_place(A);
    for (j = 0; j < A->sc->joint_count; j++) {
        double p[2], ref;
        rj_joint_def *d = &A->joints[j];
        if (!rj__asm_loop(A, j))
            continue;
        rj__asm_pin1(A, j, p, &ref);
        d->angle0 += remainder(A->phi[d->body2] - ref - d->angle0, RJ__TWO_PI);
    }
}

/* Carves the block's arrays (sizes from the scene and its loop count). */
static size_t rj__asm_carve(rj__asm *A, void *block, int nl, int nj, int rows)
{
    double *dd = (double *) block;
    int *ii;
    const size_t doubles = 3 * (size_t) nl + (size_t) rows * (size_t) nj +
                           3 * (size_t) rows * (size_t) rows + 3 * (size_t) rows + (size_t) nj;
    if (!block)
        return doubles * sizeof(double) + 6 * ((size_t) nl + (size_t) nj + 1) * sizeof(int);
    A->phi = dd;
    A->rx = A->phi + nl;
    A->ry = A->rx + nl;
    A->J = A->ry + nl;
    A->N = A->J + (size_t) rows * (size_t) nj;
    A->D = A->N + (size_t) rows * (size_t) rows;
    A->NL = A->D + (size_t) rows * (size_t) rows;
    A->gap = A->NL + (size_t) rows * (size_t) rows;
    A->y = A->gap + rows;
    A->trial = A->y + rows;
    ii = (int *) (void *) (A->trial + rows + nj);
    A->parent = ii;
    A->placed = A->parent + nl;
    A->path = A->placed + nl;
    A->unknown = A->path + nl;
    A->marks = A->unknown + nj;
    return 0;
}

/* The parents (each link's first joint as body2) and the loop count. */
static int rj__asm_tree(rj__asm *A)
{
    int j, l, loops = 0;
    for (l = 0; l < A->sc->link_count; l++)
        A->parent[l] = -1;
    for (j = 0; j < A->sc->joint_count; j++) {
        int *p = &A->parent[A->joints[j].body2];
        if (*p < 0)
            *p = j;
        else
            loops++;
    }
    return loops;
}

/* Newton to 1e-13 of the longest link (100 steps at most); RJ_ERR_INVALID naming the
   loop that stays open. */
static rj_result rj__asm_solve(rj__asm *A, rj_error *err)
{
    double longest = 0, worst, gap, lambda = 1e-14;
    int l, it, j;
    char f[64];
    for (l = 0; l < A->sc->link_count; l++)
        longest = fmax(longest, A->sc->links[l].length);
    worst = rj__asm_gaps(A, A->gap);
    for (it = 0; it < 200 && worst > 1e-13 * longest && A->nu > 0; it++) {
        const double before = worst;
        worst = rj__asm_step(A, worst, &lambda);
        if (!(worst < before))
            break;
    }
    if (worst <= 1e-13 * longest) {
        rj__asm_loop_angles(A);
        return RJ_OK;
    }
    j = rj__asm_worst(A, &gap);
    RJ__FIELD(f, "joints[%d]", j);
    rj__fail(err, RJ_ERR_INVALID, f, gap,
             "the loop that joints[%d] closes cannot close: its pins stay %.6g m apart at best "
             "(the links between them too short or too long for where the loop's other joints "
             "are)",
             j, gap);
    return RJ_ERR_INVALID;
}

RJDEF rj_result rj_scene_assemble(const rj_scene_def *scene, rj_joint_def *joints,
                                  rj_error *err)
{
    rj__asm A;
    rj_scene_def copy;
    rj_result r;
    void *block;
    int rows;
    if (!scene || !joints) {
        rj__fail(err, RJ_ERR_INVALID, scene ? "joints" : "scene", 0, "%s is NULL",
                 scene ? "joints" : "scene");
        return RJ_ERR_INVALID;
    }
    copy = *scene;
    copy.joints = joints;
    r = rj__validate_all(&copy, err, NULL);
    if (r != RJ_OK)
        return r;
    memset(&A, 0, sizeof A);
    A.sc = &copy;
    A.joints = joints;
    rows = 2 * scene->joint_count;
    block = RJ_MALLOC(rj__asm_carve(&A, NULL, scene->link_count, scene->joint_count, rows), NULL);
    if (!block) {
        rj__fail(err, RJ_ERR_NOMEM, "joint_count", scene->joint_count,
                 "could not allocate the assembly's arrays");
        return RJ_ERR_NOMEM;
    }
    rj__asm_carve(&A, block, scene->link_count, scene->joint_count, rows);
    A.nloop = rj__asm_tree(&A);
    A.nu = rj__asm_unknowns(&A, 1);
    r = A.nloop ? rj__asm_solve(&A, err) : RJ_OK;
    RJ_FREE(block, NULL);
    return r;
}

/* The rank of the rows x cols matrix J (stride cols) by Gaussian elimination with partial
   pivoting, an entry below 1e-9 of J's largest counting as 0. Destroys J. */
static int rj__asm_rank(double *J, int rows, int cols)
{
    double largest = 0;
    int rank = 0, c, r, k, p;
    for (k = 0; k < rows * cols; k++)
        largest = fmax(largest, fabs(J[k]));
    for (c = 0; c < cols && rank < rows; c++) {
        for (p = rank, r = rank + 1; r < rows; r++)
            if (fabs(J[(size_t) r * cols + c]) > fabs(J[(size_t) p * cols + c]))
                p = r;
        if (!(fabs(J[(size_t) p * cols + c]) > 1e-9 * largest))
            continue;
        for (k = 0; k < cols; k++) {
            const double t = J[(size_t) p * cols + k];
            J[(size_t) p * cols + k] = J[(size_t) rank * cols + k];
            J[(size_t) rank * cols + k] = t;
        }
        for (r = rank + 1; r < rows; r++) {
            const double f = J[(size_t) r * cols + c] / J[(size_t) rank * cols + c];
            for (k = c; k < cols; k++)
                J[(size_t) r * cols + k] -= f * J[(size_t) rank * cols + k];
        }
        rank++;
    }
    return rank;
}

/* The tree's freedom as rigid bars: one a hanging link, three a free root link, one a
   pinned root. */
static int rj__asm_tree_freedom(const rj__asm *A)
{
    int l, dof = 0;
    for (l = 0; l < A->sc->link_count; l++) {
        const int root = A->sc->links[l].root;
        if (A->parent[l] >= 0)
            dof += 1;
        else if (root == RJ_ROOT_FREE)
            dof += 3;
        else if (root == RJ_ROOT_PINNED)
            dof += 1;
    }
    return dof;
}

RJDEF rj_result rj_scene_mobility(const rj_scene_def *scene, int *mobility, int *rank,
                                  rj_error *err)
{
    rj__asm A;
    rj_joint_def *joints;
    rj_scene_def copy;
    rj_result r;
    void *block;
    const int rows = scene ? 2 * scene->joint_count : 0;
    size_t arrays;
    if (!scene || !mobility || !rank) {
        rj__fail(err, RJ_ERR_INVALID, !scene ? "scene" : !mobility ? "mobility" : "rank", 0,
                 "%s is NULL", !scene ? "scene" : !mobility ? "mobility" : "rank");
        return RJ_ERR_INVALID;
    }
    r = rj__validate_all(scene, err, NULL);
    if (r != RJ_OK)
        return r;
    memset(&A, 0, sizeof A);
    /* the arrays, then the joints' copy (the Jacobian turns their angle0 and back) */
    arrays = (rj__asm_carve(&A, NULL, scene->link_count, scene->joint_count, rows) + 15) /
             16 * 16;
    block = RJ_MALLOC(arrays + sizeof(rj_joint_def) * ((size_t) scene->joint_count + 1), NULL);
    if (!block) {
        rj__fail(err, RJ_ERR_NOMEM, "joint_count", scene->joint_count,
                 "could not allocate the mobility's arrays");
        return RJ_ERR_NOMEM;
    }
    joints = (rj_joint_def *) (void *) ((char *) block + arrays);
    memcpy(joints, scene->joints, sizeof(rj_joint_def) * (size_t) scene->joint_count);
    copy = *scene;
    copy.joints = joints;
    A.sc = &copy;
    A.joints = joints;
    rj__asm_carve(&A, block, scene->link_count, scene->joint_count, rows);
    A.nloop = rj__asm_tree(&A);
    A.nu = rj__asm_unknowns(&A, 0);
    *rank = 0;
    if (A.nloop && A.nu) {
        rj__asm_jacobian(&A);
        *rank = rj__asm_rank(A.J, 2 * A.nloop, A.nu);
    }
    *mobility = rj__asm_tree_freedom(&A) - *rank;
    RJ_FREE(block, NULL);
    return RJ_OK;
}
