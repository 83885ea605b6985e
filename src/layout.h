/* ------------------------------------------------------------------ memory layout */
/* The next aligned offset for count elements; a block past what size_t counts (a 32-bit
   size_t) saturates at (size_t)-1, which no allocation satisfies. */
static size_t rj__carve(size_t *off, size_t count, size_t elsize)
{
    const size_t full = (size_t) -1;
    size_t at;
    if (*off > full - 2 * RJ__ALIGN)
        return *off = full;
    at = (*off + RJ__ALIGN - 1) / RJ__ALIGN * RJ__ALIGN;
    if (count > (full - 2 * RJ__ALIGN - at) / elsize)
        return *off = full;
    *off = at + count * elsize;
    return at;
}

typedef struct rj__layout {
    size_t total, ldef, jdef, jnt, link_first, link_efirst, link_l0, link_EA, link_EI, link_rho,
        link_I;
    size_t node_cl, bp_node, cl_first, cl_node, cl_fix, cl_M, cl_I, cl_th0, cl_rx, cl_ry;
    size_t node_grp, ch_first, ch_node, ch_l0sq, gs_int, gs_l0sq, rb_mass, rb_icm, rb_dcm, rb_pjoint, jorder, qj, jq, wcol, jpin,
        jref, mass, rinertia, tinv, rinv, einv, kmass, krot, grp_first, grp_node, grp_inv, dnode,
        link_un, link_kc, link_path, link_pl, link_damp, visc_first, visc_joint, x0, y0, phi0, vx0, vy0, w0, beta0, load, load_node, act, spl, cp, lz;
} rj__layout;

/* Whether a rigid scene of nq coordinates, nloop joints that close loops and ncp
   couplings is solved by articulated bodies (rj_model.rig_tree) rather than a dense M. */
static int rj__rig_is_tree(int nq, int nloop, int ncp)
{
    return !nloop && !ncp && nq >= RJ__RIG_TREE_MIN;
}

/* rj__rig_is_tree for a scene of rigid links, before its model is built. A valid scene
   hangs each link that is not fixed from the first joint that names it body 2, and names
   no fixed link body 2: the coordinates are the links less the fixed ones, and every
   other joint closes a loop (rj__init_joint_nodes counts them the same). */
static int rj__scene_rig_tree(const rj_scene_def *sc)
{
    int l, nq = 0;
    for (l = 0; l < sc->link_count; l++)
        nq += sc->links[l].root != RJ_ROOT_FIXED;
    return rj__rig_is_tree(nq, sc->joint_count - nq, sc->coupling_count);
}

/* The rigid stability bound's scratch in the building area (rj__rig_setup): the solver's
   without columns or rows, then for a dense M the nj x nj M^-1, for a tree each
   coordinate's 3 x 3 response (rj__rig_tree_minv). */
static size_t rj__rig_bound_scratch(const rj_scene_def *sc)
{
    const size_t nj = (size_t) sc->joint_count, nl = (size_t) sc->link_count;
    const int dense = !rj__scene_rig_tree(sc);
    return rj__rigid_scratch(nj, nl, dense, 0, 0, 0) + (dense ? nj * nj : 9 * nj);
}

/* The model's block: every array linear in the scene. The building scratch lz holds the
   Lanczos vectors (15 nn) and the elements' table after them (10 ne: rj__lz_table, also
   the inextensible chains' graph, rj__gs_build), the joint-graph checks (rj__validate_graph: 2 nl + nj ints) and for
   rigid scenes the stability bound's (rj__rig_bound_scratch: nj^2 with a dense M, linear
   for articulated bodies). */
static void rj__model_layout(const rj_scene_def *sc, size_t nn, size_t ne, rj__layout *L)
{
    const int nl = sc->link_count, nj = sc->joint_count, rigid = rj__all_rigid(sc);
    size_t off = sizeof(rj_model);
    int inext = 0, l;
    for (l = 0; l < nl; l++)
        inext |= sc->links[l].fidelity == RJ_LINK_INEXTENSIBLE;
    L->ldef = rj__carve(&off, (size_t) nl, sizeof(rj_link_def));
    L->jdef = rj__carve(&off, (size_t) nj, sizeof(rj_joint_def));
    L->jnt = rj__carve(&off, (size_t) nj, sizeof(rj__joint));
    L->link_first = rj__carve(&off, (size_t) nl + 1, sizeof(int));
    L->link_efirst = rj__carve(&off, (size_t) nl + 1, sizeof(int));
    L->link_l0 = rj__carve(&off, (size_t) nl, sizeof(double));
    L->link_EA = rj__carve(&off, (size_t) nl, sizeof(double));
    L->link_EI = rj__carve(&off, (size_t) nl, sizeof(double));
    L->link_rho = rj__carve(&off, (size_t) nl, sizeof(double));
    L->link_I = rj__carve(&off, (size_t) nl, sizeof(double));
    L->ch_first = rj__carve(&off, (size_t) nl + 1, sizeof(int));
    L->node_cl = rj__carve(&off, (size_t) nn, sizeof(int));
    L->bp_node = rj__carve(&off, 2 * (size_t) nj + 2, sizeof(int));
    L->cl_first = rj__carve(&off, (size_t) nl + 1, sizeof(int));
    L->cl_node = rj__carve(&off, (size_t) nn, sizeof(int));
    L->cl_fix = rj__carve(&off, (size_t) nl, sizeof(int));
    L->cl_M = rj__carve(&off, (size_t) nl, sizeof(double));
    L->cl_I = rj__carve(&off, (size_t) nl, sizeof(double));
    L->cl_th0 = rj__carve(&off, (size_t) 3 * nl, sizeof(double));
    L->cl_rx = rj__carve(&off, (size_t) nn, sizeof(double));
    L->cl_ry = rj__carve(&off, (size_t) nn, sizeof(double));
    L->ch_node = rj__carve(&off, (size_t) nn + nl, sizeof(int));
    L->ch_l0sq = rj__carve(&off, (size_t) nn + nl, sizeof(double));
    L->gs_int = rj__carve(&off, inext ? 6 * ne + 2 * nn + 1 : 0, sizeof(int));
    L->gs_l0sq = rj__carve(&off, inext ? ne : 0, sizeof(double));
    L->rb_mass = rj__carve(&off, (size_t) nl, sizeof(double));
    L->rb_icm = rj__carve(&off, (size_t) nl, sizeof(double));
    L->rb_dcm = rj__carve(&off, (size_t) nl, sizeof(double));
    L->rb_pjoint = rj__carve(&off, (size_t) nl, sizeof(int));
    L->jorder = rj__carve(&off, (size_t) nj + 1, sizeof(int));
    L->qj = rj__carve(&off, (size_t) nj + 1, sizeof(int));
    L->jq = rj__carve(&off, (size_t) nj + 1, sizeof(int));
    L->wcol = rj__carve(&off, rigid ? (size_t) nj + 1 : 0, sizeof(int));
    L->jpin = rj__carve(&off, (size_t) nj + 1, sizeof(double));
    L->jref = rj__carve(&off, (size_t) nj + 1, sizeof(double));
    L->mass = rj__carve(&off, (size_t) nn, sizeof(double));
    L->rinertia = rj__carve(&off, (size_t) nn, sizeof(double));
    L->tinv = rj__carve(&off, (size_t) nn, sizeof(double));
    L->rinv = rj__carve(&off, (size_t) nn, sizeof(double));
    L->einv = rj__carve(&off, (size_t) nn, sizeof(double));
    L->kmass = rj__carve(&off, (size_t) nn, sizeof(double));
    L->krot = rj__carve(&off, (size_t) nn, sizeof(double));
    L->grp_first = rj__carve(&off, (size_t) nj + 1, sizeof(int));
    L->grp_node = rj__carve(&off, (size_t) 2 * nj + 1, sizeof(int));
    L->node_grp = rj__carve(&off, (size_t) nn, sizeof(int));
    L->grp_inv = rj__carve(&off, (size_t) nj + 1, sizeof(double));
    L->dnode = rj__carve(&off, (size_t) nn + 1, sizeof(int));
    L->link_un = rj__carve(&off, (size_t) 5 * nl + 1, sizeof(double));
    L->link_kc = rj__carve(&off, (size_t) 4 * nl + 1, sizeof(double));
    L->link_path = rj__carve(&off, (size_t) nl + 1, sizeof(int));
    L->link_pl = rj__carve(&off, (size_t) nl + 1, sizeof(int));
    L->link_damp = rj__carve(&off, (size_t) RJ__LD_PER * nl + 1, sizeof(double));
    L->visc_first = rj__carve(&off, (size_t) nl + 1, sizeof(int));
    L->visc_joint = rj__carve(&off, 2 * (size_t) nj + 1, sizeof(int));
    L->x0 = rj__carve(&off, (size_t) nn, sizeof(double));
    L->y0 = rj__carve(&off, (size_t) nn, sizeof(double));
    L->phi0 = rj__carve(&off, (size_t) nn, sizeof(double));
    L->vx0 = rj__carve(&off, (size_t) nn, sizeof(double));
    L->vy0 = rj__carve(&off, (size_t) nn, sizeof(double));
    L->w0 = rj__carve(&off, (size_t) nn, sizeof(double));
    L->beta0 = rj__carve(&off, (size_t) ne, sizeof(double));
    L->load = rj__carve(&off, (size_t) sc->load_count + 1, sizeof(rj_load_def));
    L->load_node = rj__carve(&off, (size_t) sc->load_count + 1, sizeof(int));
    L->act = rj__carve(&off, (size_t) sc->actuator_count + 1, sizeof(rj_actuator_def));
    L->spl = rj__carve(&off, ((size_t) sc->actuator_count + 1) * RJ_TABLE_MAX, sizeof(double));
    L->cp = rj__carve(&off, (size_t) sc->coupling_count + 1, sizeof(rj_coupling_def));
    L->lz = rj__carve(&off,
                      15 * nn + 10 * ne + 8 + RJ__GRAPH_SCRATCH(nl, nj) +
                          (rigid ? rj__rig_bound_scratch(sc) : 0),
                      sizeof(double));
    L->total = off == (size_t) -1 ? off : off + RJ__ALIGN;
}


RJDEF size_t rj_model_size(const rj_scene_def *scene, rj_error *err)
{
    rj__layout L;
    size_t nn, ne;
    if (!rj__validate(scene, err))
        return 0;
    if (!rj__counts(scene, &nn, &ne, err))
        return 0;
    rj__model_layout(scene, nn, ne, &L);
    if (L.total == (size_t) -1) {
        rj__fail(err, RJ_ERR_NOMEM, "links", (double) nn,
                 "a model of %.0f nodes needs more bytes than size_t counts here", (double) nn);
        return 0;
    }
    return L.total;
}

/* Everything rj_model_init checks before it builds: the fields (rj_model_size) and the
   joint graph, whose scratch comes from RJ_MALLOC (the scene parser's check). */
static rj_result rj__validate_all(const rj_scene_def *scene, rj_error *err, void *alloc_ctx)
{
    rj_error local;
    rj_error *e = err ? err : &local;
    int *scratch;
    int ok;
    if (!rj_model_size(scene, e))
        return e->code;
    scratch = (int *) RJ_MALLOC(
        sizeof(int) * RJ__GRAPH_SCRATCH(scene->link_count, scene->joint_count), alloc_ctx);
    if (!scratch) {
        rj__fail(e, RJ_ERR_NOMEM, "joint_count", scene->joint_count,
                 "could not allocate the joint graph's scratch");
        return RJ_ERR_NOMEM;
    }
    ok = rj__validate_graph(scene, scratch, e);
    RJ_FREE(scratch, alloc_ctx);
    return ok ? RJ_OK : RJ_ERR_INVALID;
}

