/* ------------------------------------------------------------------ building the model */
/* The model's building area (m->lz, sized by rj__model_layout) as the phases of
   rj_model_init use it. The phases run one after another, so every view starts at the
   area's start and each phase leaves nothing the next one reads; the rigid links' power
   iteration works after the Lanczos vectors. */
typedef struct rj__build_scratch {
    int *graph;                /* RJ__GRAPH_SCRATCH(nl, nj) ints: rj__validate_graph */
    int *pin_groups;           /* 4 nn + ng ints: rj__pin_groups */
    int *placement;            /* 3 nl ints: rj__place_all */
    int *chains;               /* 2 nl + 2 nn ints: rj__inext_chains; nj ints in rigid
                                  scenes: rj__init_joint_order */
    double *lanczos;           /* 5 vectors of 3 nn, then 8 ne doubles and 3 ne ints of the
                                  elements' table (rj__lz_table): rj__omega2_max */
    double *rigid_bound;       /* rj__rig_bound_scratch: the solver's, then a dense M^-1 or
                                  a tree's responses (rj__rig_tree_minv) */
    int *step_node_mark;       /* nn ints: rj__init_step_nodes */
} rj__build_scratch;

/* Points every phase's scratch into the building area. */
static void rj__build_scratch_carve(const rj_model *m, rj__build_scratch *s)
{
    void *area = m->lz;
    s->graph = (int *) area;
    s->pin_groups = (int *) area;
    s->placement = (int *) area;
    s->chains = (int *) area;
    s->lanczos = m->lz;
    s->rigid_bound = m->lz + 15 * (size_t) m->nn;
    s->step_node_mark = (int *) area;
}

/* Before anything is written: err cleared, out given, the scene's fields and totals valid
   (rj_model_size), and a block as large as the layout that *L gets. */
static rj_result rj__init_check_args(const rj_scene_def *sc, void *mem, size_t size, rj_model **out,
                                     size_t *nodes, size_t *elements, rj__layout *L,
                                     int validated, rj_error *err)
{
    rj_error size_err;
    /* set on every path: compilers cannot tell that a refusal's code is never RJ_OK */
    *nodes = 0;
    *elements = 0;
    memset(L, 0, sizeof *L);
    if (err) {
        err->code = RJ_OK;
        err->field[0] = 0;
        err->msg[0] = 0;
        err->value = 0;
    }
    if (!out) {
        rj__fail(err, RJ_ERR_INVALID, "out", 0, "out is NULL");
        return RJ_ERR_INVALID;
    }
    if (!validated && !rj_model_size(sc, err ? err : &size_err))
        return err ? err->code : size_err.code;
    rj__counts(sc, nodes, elements, err);
    rj__model_layout(sc, *nodes, *elements, L);
    if (!mem) {
        rj__fail(err, RJ_ERR_NOMEM, "mem", 0,
                 "mem is NULL: the model needs a block of %lu bytes (rj_model_size)",
                 (unsigned long) L->total);
        return RJ_ERR_NOMEM;
    }
    if (size < L->total) {
        rj__fail(err, RJ_ERR_NOMEM, "size", (double) size,
                 "memory block of %lu bytes is smaller than the %lu the model needs",
                 (unsigned long) size, (unsigned long) L->total);
        return RJ_ERR_NOMEM;
    }
    return RJ_OK;
}

/* The model sits at the block's first 16-byte boundary, zeroed, with its counts. */
static rj_model *rj__init_block(const rj_scene_def *sc, void *mem, const rj__layout *L,
                                size_t nodes, size_t elements)
{
    char *base = (char *) mem;
    rj_model *m;
    base += (RJ__ALIGN - ((size_t) base % RJ__ALIGN)) % RJ__ALIGN;
    memset(base, 0, L->total - RJ__ALIGN);
    m = (rj_model *) (void *) base;
    m->bytes = L->total - RJ__ALIGN;
    m->nl = sc->link_count;
    m->nj = sc->joint_count;
    m->nn = (int) nodes;
    m->ne = (int) elements;
    m->solver = sc->solver;
    return m;
}

/* The model's arrays at the offsets of the layout (rj__model_layout), after the struct. */
static void rj__init_arrays(rj_model *m, const rj__layout *L)
{
    char *base = (char *) (void *) m;
#define RJ__SET(field, type) m->field = (type *) (void *) (base + L->field)
    RJ__SET(ldef, rj_link_def);
    RJ__SET(jdef, rj_joint_def);
    RJ__SET(jnt, rj__joint);
    RJ__SET(link_first, int);
    RJ__SET(link_efirst, int);
    RJ__SET(link_l0, double);
    RJ__SET(link_EA, double);
    RJ__SET(link_EI, double);
    RJ__SET(link_rho, double);
    RJ__SET(link_I, double);
    RJ__SET(ch_first, int);
    RJ__SET(ch_node, int);
    RJ__SET(ch_l0sq, double);
    RJ__SET(node_cl, int);
    RJ__SET(bp_node, int);
    RJ__SET(cl_first, int);
    RJ__SET(cl_node, int);
    RJ__SET(cl_fix, int);
    RJ__SET(cl_M, double);
    RJ__SET(cl_I, double);
    RJ__SET(cl_th0, double);
    RJ__SET(cl_rx, double);
    RJ__SET(cl_ry, double);
    RJ__SET(rb_mass, double);
    RJ__SET(rb_icm, double);
    RJ__SET(rb_dcm, double);
    RJ__SET(rb_pjoint, int);
    RJ__SET(jorder, int);
    RJ__SET(qj, int);
    RJ__SET(jq, int);
    RJ__SET(wcol, int);
    RJ__SET(jpin, double);
    RJ__SET(jref, double);
    RJ__SET(mass, double);
    RJ__SET(rinertia, double);
    RJ__SET(tinv, double);
    RJ__SET(rinv, double);
    RJ__SET(einv, double);
    RJ__SET(kmass, double);
    RJ__SET(krot, double);
    RJ__SET(grp_first, int);
    RJ__SET(grp_node, int);
    RJ__SET(node_grp, int);
    RJ__SET(grp_inv, double);
    RJ__SET(dnode, int);
    RJ__SET(link_un, double);
    RJ__SET(link_kc, double);
    RJ__SET(link_path, int);
    RJ__SET(link_pl, int);
    RJ__SET(link_damp, double);
    RJ__SET(visc_first, int);
    RJ__SET(visc_joint, int);
    RJ__SET(x0, double);
    RJ__SET(y0, double);
    RJ__SET(phi0, double);
    RJ__SET(vx0, double);
    RJ__SET(vy0, double);
    RJ__SET(w0, double);
    RJ__SET(beta0, double);
    RJ__SET(load, rj_load_def);
    RJ__SET(load_node, int);
    RJ__SET(act, rj_actuator_def);
    RJ__SET(spl, double);
    RJ__SET(cp, rj_coupling_def);
    RJ__SET(lz, double);
    RJ__SET(gs_l0sq, double);
#undef RJ__SET
    /* the system of the chains that meet: its int arrays in one block */
    m->gs_na = (int *) (void *) (base + L->gs_int);
    m->gs_nb = m->gs_na + m->ne;
    m->gs_oa = m->gs_nb + m->ne;
    m->gs_ob = m->gs_oa + m->ne;
    m->gs_first = m->gs_ob + m->ne;
    m->gs_off = m->gs_first + m->ne;
    m->gs_node = m->gs_off + m->ne + 1;
    m->gs_nown = m->gs_node + m->nn;
}

/* The model keeps its own copy of the definitions: the scene's arrays may go. */
static void rj__init_copy_defs(rj_model *m, const rj_scene_def *sc)
{
    int k;
    memcpy(m->ldef, sc->links, sizeof(rj_link_def) * (size_t) m->nl);
    if (m->nj)
        memcpy(m->jdef, sc->joints, sizeof(rj_joint_def) * (size_t) m->nj);
    m->has_gravity = sc->solver.gravity[0] != 0 || sc->solver.gravity[1] != 0;
    m->nload = sc->load_count;
    if (m->nload)
        memcpy(m->load, sc->loads, sizeof(rj_load_def) * (size_t) m->nload);
    m->nact = sc->actuator_count;
    if (m->nact)
        memcpy(m->act, sc->actuators, sizeof(rj_actuator_def) * (size_t) m->nact);
    m->ncp = sc->coupling_count;
    if (m->ncp)
        memcpy(m->cp, sc->couplings, sizeof(rj_coupling_def) * (size_t) m->ncp);
    for (k = 0; k < m->ncp; k++)
        m->nexact += m->cp[k].exact;
    m->nmotion += m->nexact;
}

/* A link's section: area and second moment (layers integrate EA and EI exactly for the
   elastic rectangle). */
static void rj__link_section(const rj_link_def *d, double *area, double *inertia)
{
    double A = 0, I = 0, layer;
    int k;
    if (d->section != RJ_SECTION_RECT) {
        *area = d->area;
        *inertia = d->inertia;
        return;
    }
    layer = d->height / d->layers;
    for (k = 0; k < d->layers; k++) {
        const double z = -0.5 * d->height + (k + 0.5) * layer;
        A += d->width * layer;
        I += d->width * layer * layer * layer / 12.0 + d->width * layer * z * z;
    }
    *area = A;
    *inertia = I;
}

/* Link l's node and element ranges, its element length and stiffnesses, and the element's
   constants: EI/l0, EA/l0 (0 for inextensible links: a constraint instead), l0^2,
   1/(2 l0^2). */
static void rj__init_link_constants(rj_model *m, int l, double area, double inertia)
{
    const rj_link_def *d = &m->ldef[l];
    const double l0 = d->length / d->elements;
    double *kc = m->link_kc + 4 * (size_t) l;
    m->link_first[l + 1] = m->link_first[l] + d->elements + 1;
    m->link_efirst[l + 1] = m->link_efirst[l] + d->elements;
    m->link_l0[l] = l0;
    m->link_EA[l] = d->E * area;
    m->link_EI[l] = d->E * inertia;
    kc[0] = m->link_EI[l] / l0;
    kc[1] = d->fidelity == RJ_LINK_INEXTENSIBLE ? 0.0 : m->link_EA[l] / l0;
    kc[2] = l0 * l0;
    kc[3] = 0.5 / kc[2];
    m->link_rho[l] = d->rho;
    m->link_I[l] = inertia;
}

/* Link l's lumped masses and rotary inertias (each element gives each of its two nodes
   end_mass and end_rot, the larger of the rod's and the section's rotary share; the tip
   mass sits on the last node), their inverses, and the roots that hold them (inverse 0). */
static void rj__init_link_masses(rj_model *m, int l, double area, double inertia)
{
    const rj_link_def *d = &m->ldef[l];
    const double l0 = m->link_l0[l];
    const double end_mass = 0.5 * d->rho * area * l0;
    const int n0 = m->link_first[l];
    double end_rot = d->rho * area * l0 * l0 * l0 / 78.0;
    int k;
    if (0.5 * d->rho * inertia * l0 > end_rot)
        end_rot = 0.5 * d->rho * inertia * l0;
    for (k = 0; k <= d->elements; k++) {
        const double elements_here = (k == 0 || k == d->elements) ? 1.0 : 2.0;
        m->mass[n0 + k] = elements_here * end_mass;
        m->rinertia[n0 + k] = elements_here * end_rot;
    }
    m->mass[n0 + d->elements] += d->tip_mass;
    m->rinertia[n0 + d->elements] += d->tip_inertia;
    for (k = 0; k <= d->elements; k++) {
        m->tinv[n0 + k] = 1.0 / m->mass[n0 + k];
        m->rinv[n0 + k] = 1.0 / m->rinertia[n0 + k];
    }
    if (d->root == RJ_ROOT_PINNED || d->root == RJ_ROOT_CLAMPED)
        m->tinv[n0] = 0;
    if (d->root == RJ_ROOT_CLAMPED)
        m->rinv[n0] = 0;
    if (d->root == RJ_ROOT_FIXED)
        for (k = 0; k <= d->elements; k++) {
            m->tinv[n0 + k] = 0;
            m->rinv[n0 + k] = 0;
        }
}

/* Link l's path through the beam pass and its material: the structural damping's eta
   (given, or from a ratio at a frequency, ratio / (pi f), so that eta omega / 2 is the
   ratio there) and mass-proportional rate; a yielding link's plastic strains in the
   frame (two sections an element, each of the link's layers). */
static void rj__init_link_material(rj_model *m, int l)
{
    const rj_link_def *d = &m->ldef[l];
    double *damp = RJ__LD(m, l);
    const int damped = d->eta > 0 || d->damping[0] > 0 || d->mass_damping > 0;
    const int yielding = d->yield > 0;
    /* eta lagged until rj__init_viscous knows whether a rigid body carries the link */
    damp[RJ__LD_LAGGED] = d->damping[0] > 0 ? d->damping[0] / (RJ__PI * d->damping[1]) : d->eta;
    damp[RJ__LD_MASS] = d->mass_damping;
    damp[RJ__LD_IMPLICIT] = 0;
    m->link_pl[l] = -1;
    if (yielding) {
        m->link_pl[l] = (int) m->npl;
        m->npl += 2 * (size_t) d->layers * (size_t) d->elements;
    }
    m->link_path[l] = RJ__PATH_FUSED;
    if (d->fidelity == RJ_LINK_RIGID)
        m->link_path[l] = RJ__PATH_RIGID;
    else if (damped || yielding || d->strain == RJ_STRAIN_BIOT)
        m->link_path[l] = RJ__PATH_MATERIAL;
    m->nstruct += damped;
    m->nplastic += yielding;
    m->nmaterial += m->link_path[l] == RJ__PATH_MATERIAL;
}

/* Every link's section, constants and masses, link by link. */
static void rj__init_links(rj_model *m)
{
    int l;
    m->link_first[0] = 0;
    m->link_efirst[0] = 0;
    for (l = 0; l < m->nl; l++) {
        double area, inertia;
        rj__link_section(&m->ldef[l], &area, &inertia);
        rj__init_link_constants(m, l, area, inertia);
        rj__init_link_masses(m, l, area, inertia);
        rj__init_link_material(m, l);
    }
}

/* The node each applied load acts on, in the scene's node order (-1: the link's last). */
static void rj__init_load_nodes(rj_model *m)
{
    int k;
    for (k = 0; k < m->nload; k++) {
        const rj_load_def *d = &m->load[k];
        m->load_node[k] = rj_model_node_index(m, d->link, d->node);
    }
}

/* Each joint's nodes: nI pin on body 1 and nK its neighbour (-1 for ground), nJ body 2's
   pin (node2: node 0 unless set) and nL its neighbour (towards the tip, or back from the
   tip). A node pinned to ground does not translate. The nodes' effective inverse masses
   start as their own. */
static void rj__init_joint_nodes(rj_model *m)
{
    int i, j;
    for (i = 0; i < m->nn; i++)
        m->einv[i] = m->tinv[i];
    for (i = 0; i < m->nn; i++)
        m->node_grp[i] = -1;
    m->grp_first[0] = 0;
    /* a link's first joint as body2 hangs it; a later one closes a loop (node_grp of its
       root marks it hung until the pin groups take node_grp over) */
    m->nq = m->nloop = 0;
    for (j = 0; j < m->nj; j++) {
        const int root = m->link_first[m->jdef[j].body2];
        m->jnt[j].loop = m->node_grp[root] == 1;
        m->node_grp[root] = 1;
        /* the tree's joints are the joint coordinates of rigid scenes */
        m->jq[j] = m->jnt[j].loop ? -1 : m->nq;
        if (m->jnt[j].loop)
            m->nloop++;
        else
            m->qj[m->nq++] = j;
    }
    for (i = 0; i < m->nn; i++)
        m->node_grp[i] = -1;
    for (j = 0; j < m->nj; j++) {
        const rj_joint_def *d = &m->jdef[j];
        rj__joint *J = &m->jnt[j];
        const int ne2 = m->ldef[d->body2].elements;
        const int at = d->node2 < 0 ? ne2 : d->node2;
        const int pin2 = m->link_first[d->body2] + at;
        J->nJ = pin2;
        J->nL = pin2 + (at < ne2 ? 1 : -1);
        if (d->body1 < 0) {
            J->nI = -1;
            J->nK = -1;
            J->gax = cos(d->ground_angle);
            J->gay = sin(d->ground_angle);
            m->tinv[pin2] = 0;
            m->einv[pin2] = 0;
        } else {
            const int pin = d->node1 < 0 ? m->ldef[d->body1].elements : d->node1;
            J->nI = m->link_first[d->body1] + pin;
            J->nK = J->nI + (pin > 0 ? -1 : 1);
        }
    }
}

/* Pin groups (body 1's pin node and every body 2 root pinned to it share their
   translation): the group's inverse mass (0 when a member is held) becomes each member's
   effective one, and the members' own translation is the group's (tinv 0). */
static void rj__init_pin_groups(rj_model *m, int *scratch)
{
    int group, k;
    m->ng = rj__pin_groups(m, scratch);
    for (group = 0; group < m->ng; group++) {
        double mass_sum = 0;
        int held = 0;
        for (k = m->grp_first[group]; k < m->grp_first[group + 1]; k++) {
            const int node = m->grp_node[k];
            mass_sum += m->mass[node];
            if (m->tinv[node] == 0)
                held = 1;
        }
        m->grp_inv[group] = held ? 0.0 : 1.0 / mass_sum;
        for (k = m->grp_first[group]; k < m->grp_first[group + 1]; k++) {
            m->einv[m->grp_node[k]] = m->grp_inv[group];
            m->tinv[m->grp_node[k]] = 0;
            m->node_grp[m->grp_node[k]] = group;
        }
    }
}

/* The masses and rotary inertias the kinetic energy counts node by node (0 for held or
   grouped nodes: a group's translation is counted once, by the step). */
static void rj__init_energy_masses(rj_model *m)
{
    int i;
    for (i = 0; i < m->nn; i++) {
        m->kmass[i] = m->tinv[i] > 0 ? m->mass[i] : 0.0;
        m->krot[i] = m->rinv[i] > 0 ? m->rinertia[i] : 0.0;
    }
}

/* The initial state: each link placed after the link it hangs from, and no initial
   velocity where the node cannot move (fixed links, held translations and rotations). */
static void rj__init_placement(rj_model *m, int *scratch)
{
    int i, l, k;
    rj__place_all(m, scratch);
    for (l = 0; l < m->nl; l++) {
        if (m->ldef[l].root != RJ_ROOT_FIXED)
            continue;
        for (k = m->link_first[l]; k < m->link_first[l + 1]; k++) {
            m->vx0[k] = 0;
            m->vy0[k] = 0;
            m->w0[k] = 0;
        }
    }
    for (i = 0; i < m->nn; i++)
        if (m->einv[i] == 0) {
            m->vx0[i] = 0;
            m->vy0[i] = 0;
        }
    for (i = 0; i < m->nn; i++)
        if (m->rinv[i] == 0)
            m->w0[i] = 0;
}

/* Each element's initial chord angle, on the same branch as its first node's rotation, so
   phi - beta starts near 0. */
static void rj__init_chord_angles(rj_model *m)
{
    int l, k;
    for (l = 0; l < m->nl; l++)
        for (k = m->link_efirst[l]; k < m->link_efirst[l + 1]; k++) {
            const int a = m->link_first[l] + (k - m->link_efirst[l]);
            const double chord = atan2(m->y0[a + 1] - m->y0[a], m->x0[a + 1] - m->x0[a]);
            m->beta0[k] = m->phi0[a] + rj__wrap(chord - m->phi0[a]);
        }
}

/* The joints whose two pins are own nodes of two rigid bodies (mixed scenes): the pin
   between the bodies turns both with the joint's torques (rj__pair_terms). */
static void rj__init_body_pairs(rj_model *m)
{
    int j;
    m->npair = 0;
    for (j = 0; j < m->nj; j++) {
        rj__joint *J = &m->jnt[j];
        J->pair = 0;
        if (!m->ncl || J->nI < 0)
            continue;
        J->pair = RJ__CL_RIGID(m, J->nI) && RJ__CL_RIGID(m, J->nJ) &&
                  m->node_cl[J->nI] != m->node_cl[J->nJ];
        m->npair += J->pair;
    }
}

/* Rigid links in a scene with flexible ones move as bodies (clusters, rj__clusters); a
   scene of rigid links alone runs in joint coordinates instead and has none. */
static int rj__init_clusters(rj_model *m, const rj_scene_def *sc, rj_error *err)
{
    int i, l;
    for (i = 0; i < m->nn; i++)
        m->node_cl[i] = -1;
    if (!rj__all_rigid(sc))
        for (l = 0; l < m->nl; l++)
            if (m->ldef[l].fidelity == RJ_LINK_RIGID)
                m->ncl = m->nl;
    if (m->ncl && !rj__clusters(m, err))
        return 0;
    rj__init_body_pairs(m);
    return 1;
}

/* Joint j's inertias on either side (chord reference: from the neighbour nodes' effective
   masses; tangent: the pin nodes' rotary inertias; HUGE_VAL where held), the weights that
   split its torque between them, and the tangent reference's angle offset. */
static void rj__init_joint_inertias(rj_model *m, int j)
{
    const rj_joint_def *d = &m->jdef[j];
    rj__joint *J = &m->jnt[j];
    rj__jgeo g;
    J->chord = d->reference == RJ_REF_CHORD;
    rj__joint_geo(m, J, m->x0, m->y0, &g);
    if (J->chord) {
        J->I1 = (J->nK >= 0 && m->einv[J->nK] > 0) ? g.a2 / m->einv[J->nK] : HUGE_VAL;
        J->I2 = m->einv[J->nL] > 0 ? g.b2 / m->einv[J->nL] : HUGE_VAL;
    } else {
        J->I1 = (J->nI >= 0 && m->rinv[J->nI] > 0) ? m->rinertia[J->nI] : HUGE_VAL;
        J->I2 = m->rinv[J->nJ] > 0 ? m->rinertia[J->nJ] : HUGE_VAL;
        J->off = d->angle0 - m->phi0[J->nJ] + (J->nI >= 0 ? m->phi0[J->nI] : 0.0);
    }
    if (!rj__finite(J->I1)) {
        J->w1 = 0;
        J->w2 = 1;
    } else if (!rj__finite(J->I2)) {
        J->w1 = 1;
        J->w2 = 0;
    } else {
        J->w1 = J->I2 / (J->I1 + J->I2);
        J->w2 = J->I1 / (J->I1 + J->I2);
    }
}

/* A joint's limits on the running angle. Both enabled: the free arc runs counter-clockwise
   from reverse to forward; a start inside the limited arc counts as past the nearer limit.
   One limit (a wall): the reverse limit is the largest theta_r + 2 pi k <= angle0 + pi/2,
   the forward limit the smallest theta_f + 2 pi k >= angle0 - pi/2, so a start up to
   90 deg past it counts as penetrated. */
static void rj__init_running_limits(const rj_joint_def *d, rj__joint *J)
{
    if (d->has_forward && d->has_reverse) {
        const double free_arc = rj__mod2pi(d->forward - d->reverse);
        const double past_reverse = rj__mod2pi(d->angle0 - d->reverse);
        if (past_reverse <= free_arc) {
            J->rev = d->angle0 - past_reverse;
            J->fwd = J->rev + free_arc;
        } else if (past_reverse - free_arc <= RJ__TWO_PI - past_reverse) {
            J->fwd = d->angle0 - (past_reverse - free_arc);
            J->rev = J->fwd - free_arc;
        } else {
            J->rev = d->angle0 + (RJ__TWO_PI - past_reverse);
            J->fwd = J->rev + free_arc;
        }
        return;
    }
    J->fwd = HUGE_VAL;
    J->rev = -HUGE_VAL;
    if (d->has_reverse)
        J->rev =
            d->reverse + RJ__TWO_PI * floor((d->angle0 + 0.5 * RJ__PI - d->reverse) / RJ__TWO_PI);
    if (d->has_forward)
        J->fwd =
            d->forward + RJ__TWO_PI * ceil((d->angle0 - 0.5 * RJ__PI - d->forward) / RJ__TWO_PI);
}

/* The steepest the torque table gets anywhere (N m/rad): at each rising segment, the sum
   of the slopes of every rising segment that overlaps it (later runs add, Eq 4). */
static double rj__table_stiffness(const rj_joint_def *d)
{
    const double *angle = d->table_angle, *torque = d->table_torque;
    double steepest = 0;
    int k, k2;
    for (k = 0; k + 1 < d->table_count; k++) {
        double slopes = 0;
        if (!(angle[k + 1] > angle[k]))
            continue;
        for (k2 = 0; k2 + 1 < d->table_count; k2++) {
            if (!(angle[k2 + 1] > angle[k2]))
                continue;
            if (angle[k2 + 1] < angle[k] || angle[k2] > angle[k + 1])
                continue;
            slopes += fabs((torque[k2 + 1] - torque[k2]) / (angle[k2 + 1] - angle[k2]));
        }
        if (slopes > steepest)
            steepest = slopes;
    }
    return steepest;
}

/* A DC motor's cutoff on the running angle: its first crossing from angle0 in the
   direction the motor drives (angle0 itself when they are the same angle). */
static double rj__running_cutoff(const rj_actuator_def *a, double angle0)
{
    const double ahead = rj__mod2pi(a->cutoff - angle0);
    if (a->no_load_speed > 0)
        return angle0 + ahead;
    return ahead == 0 ? angle0 : angle0 - (RJ__TWO_PI - ahead);
}

/* An actuator on its joint: the joint keeps it; a servo's gain is a spring and its
   damping, like a DC motor's slope, a damper to the stability bound; a cutoff on the
   running angle. */
static void rj__init_actuator(rj_model *m, const rj_actuator_def *a)
{
    rj__joint *J = &m->jnt[a->joint];
    J->act = a;
    J->rotor = a->gear_ratio * a->gear_ratio * a->rotor_inertia;
    if (a->type != RJ_ACTUATOR_TORQUE && a->profile == RJ_PROFILE_TABLE) {
        double *M = m->spl + (size_t) (a - m->act) * RJ_TABLE_MAX, work[RJ_TABLE_MAX];
        rj__spline_build(a->table_count, a->table_time, a->table_factor, M, work);
        J->spline = M;
    }
    m->nrotor += J->rotor > 0;
    m->npres += a->type == RJ_ACTUATOR_PRESCRIBED;
    /* a prescribed joint is a row, but between two rigid bodies a torque */
    m->nmotion += a->type == RJ_ACTUATOR_PRESCRIBED && !J->pair;
    if (a->type == RJ_ACTUATOR_SERVO) {
        J->k_lin += a->kp;
        J->c_lin += a->kd;
    }
    if (a->type == RJ_ACTUATOR_DC) {
        J->c_lin += a->stall_torque / a->no_load_speed;
        if (a->has_cutoff)
            J->cut = rj__running_cutoff(a, m->jdef[a->joint].angle0);
    }
}

/* Every joint's constants: inertias, limits on the running angle, the table's potential
   over a turn, and the linear stiffness of its spring and table (limits come later); its
   actuator. */
static void rj__init_joint_constants(rj_model *m)
{
    int j, k;
    m->nchord = 0;
    for (j = 0; j < m->nj; j++) {
        const rj_joint_def *d = &m->jdef[j];
        rj__joint *J = &m->jnt[j];
        rj__init_joint_inertias(m, j);
        m->nchord += J->chord;
        rj__init_running_limits(d, J);
        J->tv_turn = d->table_count ? rj__table_potential(d->table_angle, d->table_torque,
                                                          d->table_count, RJ__TWO_PI)
                                    : 0.0;
        J->k_lin = d->spring_k + rj__table_stiffness(d);
        J->k_limit = 0;
        J->c_lin = d->damping;
        J->act = NULL;
        J->cut = HUGE_VAL;
        J->rotor = 0;
        J->spline = NULL;
    }
    for (k = 0; k < m->nact; k++)
        rj__init_actuator(m, &m->act[k]);
}

/* Inextensible links: the chains SHAKE solves (links joined tip to root form one). */
static void rj__init_inextensible(rj_model *m, int *scratch)
{
    int l;
    for (l = 0; l < m->nl; l++)
        if (m->ldef[l].fidelity == RJ_LINK_INEXTENSIBLE)
            m->any_inext = 1;
    if (!m->any_inext)
        return;
    rj__inext_chains(m, scratch);
    rj__gs_build(m, m->lz);
}

/* Rigid scenes: each link as a body (rod plus tip mass): its mass, the distance of its
   centre of mass from the root, and its inertia about that centre. */
static void rj__init_rigid_bodies(rj_model *m)
{
    int l;
    for (l = 0; l < m->nl; l++) {
        const rj_link_def *d = &m->ldef[l];
        const double A = rj__plain_area(d);
        const double rod = d->rho * A * d->length;
        const double total = rod + d->tip_mass;
        const double dc = (rod * 0.5 * d->length + d->tip_mass * d->length) / total;
        m->rb_mass[l] = total;
        m->rb_dcm[l] = dc;
        m->rb_icm[l] = rod * d->length * d->length / 12.0 +
                       rod * (0.5 * d->length - dc) * (0.5 * d->length - dc) +
                       d->tip_mass * (d->length - dc) * (d->length - dc) + d->tip_inertia;
        m->rb_pjoint[l] = -1;
    }
}

/* Rigid scenes: each link's joint to its parent, and each joint's pin along body 1 with
   the reference direction there (pi at a node past the root: I->K points back). */
static void rj__init_rigid_pins(rj_model *m)
{
    int j;
    for (j = 0; j < m->nj; j++) {
        const rj_joint_def *d = &m->jdef[j];
        if (!m->jnt[j].loop)
            m->rb_pjoint[d->body2] = j;
        if (d->body1 >= 0) {
            const int pin = d->node1 < 0 ? m->ldef[d->body1].elements : d->node1;
            m->jpin[j] = pin * m->link_l0[d->body1];
            m->jref[j] = pin > 0 ? RJ__PI : 0.0;
        } else {
            m->jpin[j] = 0;
            m->jref[j] = 0;
        }
    }
}

/* Rigid scenes: the tree's joints in an order with parents before children (the
   kinematics run down the tree): passes in joint order, each placing the joints whose
   parent joint is placed. is_placed: nj ints of scratch (a list search made a chain of
   10 000 links take 0.55e9 instructions here). */
static void rj__init_joint_order(rj_model *m, int *is_placed)
{
    int placed = 0, pass, j;
    for (j = 0; j < m->nj; j++)
        is_placed[j] = 0;
    for (pass = 0; placed < m->nq && pass <= m->nj; pass++)
        for (j = 0; j < m->nj; j++) {
            const int b1 = m->jdef[j].body1;
            const int parent = b1 >= 0 ? m->rb_pjoint[b1] : -1;
            const int done = m->jnt[j].loop || is_placed[j];
            const int ready = parent < 0 || is_placed[parent];
            if (!done && ready) {
                m->jorder[placed++] = j;
                is_placed[j] = 1;
            }
        }
}

/* Whether joint j of a rigid scene can open a row in a step (rj__rig_rows_build): a
   prescribed joint's profile, or a latch of a velocity-level method (a lock or a plastic
   contact), which needs a limit to reach (a flag other than free). */
static int rj__rig_can_row(const rj_model *m, int j)
{
    const rj_joint_def *d = &m->jdef[j];
    const rj_actuator_def *a = m->jnt[j].act;
    const int velocity_level = d->method == RJ_METHOD_MOMENTUM || d->method == RJ_METHOD_FORCED;
    if (a && a->type == RJ_ACTUATOR_PRESCRIBED)
        return 1;
    return velocity_level && (d->has_forward || d->has_reverse);
}

/* The most rows a rigid step opens, which size its system (S and SL, rows x rows): one
   per joint that can open one (tree or loop joint), one per exact coupling, and two per
   loop (its pins' gap in x and y). The loops' projection opens fewer: the two per loop
   and one per forced loop joint at a limit. */
static int rj__rig_rows_max(const rj_model *m)
{
    int j, rows = m->nexact + 2 * m->nloop;
    for (j = 0; j < m->nj; j++)
        rows += rj__rig_can_row(m, j);
    return rows;
}

/* The columns of M^-1 a rigid step keeps (W): for a dense M, one per coordinate (a loop's
   latch row may be any coordinate's rate alone). Articulated bodies (a tree without
   couplings) keep those of the joints that can open a row, which their impulses and rows
   read after friction made them (stage 3): k such joints keep k n doubles. Friction on a
   joint that cannot spends its column at once (rj__rig_stage_friction). */
static void rj__init_rigid_columns(rj_model *m)
{
    int k;
    m->nwcol = 0;
    for (k = 0; k < m->nq; k++) {
        const int kept = !m->rig_tree || rj__rig_can_row(m, m->qj[k]);
        m->wcol[k] = kept ? m->nwcol++ : -1;
    }
    m->rig_rows = rj__rig_rows_max(m);
}

/* Links held by constraints: SHAKE's inextensible chains, and in a scene of rigid links
   alone (joint coordinates) the bodies, pins and joint order, the solver (a dense M or
   articulated bodies, as rj_model_size counted its scratch) and the columns and rows its
   step keeps. */
static void rj__init_rigid(rj_model *m, const rj_scene_def *sc, int *chain_scratch)
{
    m->rigid = rj__all_rigid(sc);
    rj__init_inextensible(m, chain_scratch);
    if (!m->rigid)
        return;
    rj__init_rigid_bodies(m);
    rj__init_rigid_pins(m);
    rj__init_joint_order(m, chain_scratch);
    m->rig_tree = rj__rig_is_tree(m->nq, m->nloop, m->ncp);
    RJ_ASSERT(m->rig_tree == rj__scene_rig_tree(sc));
    rj__init_rigid_columns(m);
}

/* omega_max^2 at the stiffnesses in m->jnt: power iteration in joint coordinates for
   rigid scenes (it also sets each joint's 1/I_red, J->minv), Lanczos otherwise. */
static double rj__bound_omega2(rj_model *m, const rj__build_scratch *s)
{
    return m->rigid ? rj__rig_setup(m, s->rigid_bound) : rj__omega2_max(m, s->lanczos);
}

/* omega_max and the stability bound from omega_max^2; returns it. */
static double rj__set_bound(rj_model *m, double om2, double damp_rate)
{
    m->omega_max = rj__omega_of(om2);
    m->dt_bound = rj__dt_bound_of(m->omega_max, damp_rate);
    return om2;
}

/* omega_max and the stability bound at the stiffnesses in m->jnt; returns omega_max^2. */
static double rj__init_bound(rj_model *m, const rj__build_scratch *s, double damp_rate)
{
    return rj__set_bound(m, rj__bound_omega2(m, s), damp_rate);
}

/* What the search for the step carries: dt depends on K_AP and K_AP on dt. */
typedef struct rj__dt_search {
    double damp_rate;       /* the fastest joint damping rate, 1/s */
    double om2_no_adaptive; /* omega_max^2 without the adaptive limits */
    double dt;              /* the step under test */
} rj__dt_search;

/* A penalty limit switches on and off with the contact, which pumps energy long before the
   linear bound: measured on the impact benchmark, RC13 contact blows up at omega dt = 1.67
   where the same spring always on is stable. Counting it as 4 K keeps omega dt <= 1, where
   switching was never seen to pump. Returns whether any joint has adaptive limits;
   *counted: whether any penalty limit changed a stiffness. */
static int rj__count_penalty_limits(rj_model *m, int *counted)
{
    int j, any_adaptive = 0;
    *counted = 0;
    for (j = 0; j < m->nj; j++) {
        const rj_joint_def *d = &m->jdef[j];
        const int limited = d->has_forward || d->has_reverse;
        if (limited && d->method == RJ_METHOD_PENALTY && d->penalty_k != 0) {
            m->jnt[j].k_lin += 4.0 * d->penalty_k;
            *counted = 1;
        }
        if (limited && d->method == RJ_METHOD_ADAPTIVE)
            any_adaptive = 1;
    }
    return any_adaptive;
}

/* Eq 21's K_AP = I_red / dt^2 for joint J: I_red the joint's own effective inertia
   1 / (M^-1)_jj in rigid scenes, the two bodies' own between two rigid bodies of a
   mixed scene (rj__pair_free_give), else the two sides' (I1, I2). */
static double rj__adaptive_k(const rj_model *m, const rj__joint *J, double dt)
{
    if (m->rigid)
        return 1.0 / (J->minv * dt * dt);
    if (J->pair)
        return 1.0 / (rj__pair_free_give(m, J) * dt * dt);
    return rj_k_adaptive(J->I1, J->I2, dt);
}

/* The adaptive limits' K_AP at the step under test (rigid: the joint's own effective
   inertia 1 / (M^-1)_jj, Eq 21 for two free bodies), counted twice in k_lin. */
static void rj__count_adaptive_limits(rj_model *m, const rj__dt_search *q)
{
    const double dt = q->dt;
    int j;
    for (j = 0; j < m->nj; j++) {
        const rj_joint_def *d = &m->jdef[j];
        rj__joint *J = &m->jnt[j];
        if (!(d->has_forward || d->has_reverse) || d->method != RJ_METHOD_ADAPTIVE)
            continue;
        J->k_limit = rj__adaptive_k(m, J, dt);
        J->k_lin = J->k_free + 2.0 * J->k_limit;
    }
}

/* The step whose 0.9 x bound holds with omega^2(dt) ~ a + b / dt^2 (a: without the
   adaptive limits, b from this pass) and the joints' damping rate d: with c = 0.9 x 2 x
   margin, the bound dt (d/2 + sqrt(omega^2 + d^2/4)) <= c (rj__dt_bound_of) is
   a dt^2 + c d dt + b - c^2 <= 0, whose positive root is the step; b < c^2. */
static double rj__adaptive_dt_root(double a, double b, double d, double c, double dt_now)
{
    const double room = c * c - b;
    if (a > 0)
        return 2.0 * room / (c * d + sqrt(c * c * d * d + 4.0 * a * room));
    if (d > 0)
        return room / (c * d);
    return dt_now;
}

/* The next step to test. K_AP = I_red / dt^2: omega dt of the adaptive limits does not
   fall with dt, so when they alone are above the bound no step is stable: refused; so is
   a search that has not settled in its passes, with what it reached. */
static int rj__next_adaptive_dt(rj_model *m, rj__dt_search *q, double om2, int pass, rj_error *err)
{
    const double c = 0.9 * RJ__DT_MARGIN * 2.0;
    const double b = (om2 - q->om2_no_adaptive) * q->dt * q->dt;
    if (b >= c * c) {
        rj__fail(err, RJ_ERR_UNSTABLE_DT, "solver.dt", q->dt,
                 "no stable step for the adaptive limits: their stiffness K_AP (Eq 21) "
                 "grows as 1/dt^2, so their omega dt, %.3g with the limits counted as in "
                 "the bound, is the same at every dt and not below the %.3g the automatic "
                 "step allows; use RJ_METHOD_MOMENTUM (or penalty with a fixed K) for these "
                 "joints%s",
                 sqrt(b), c, m->rigid ? ", as rigid links usually want" : "");
        return 0;
    }
    if (pass == 19) {
        rj__fail(err, RJ_ERR_UNSTABLE_DT, "solver.dt", q->dt,
                 "no stable step found for the adaptive limits: after 20 passes the step "
                 "%.4g s is still above 0.9 x its bound %.4g s (the adaptive limits' omega "
                 "dt %.3g, the joints' damping rate %.4g 1/s); give solver.dt below the "
                 "bound with solver.allow_unstable, or use RJ_METHOD_MOMENTUM for these "
                 "joints",
                 q->dt, m->dt_bound, sqrt(b), q->damp_rate);
        return 0;
    }
    /* a step that small always has a bound at least as large: never go past it */
    q->dt = rj__adaptive_dt_root(q->om2_no_adaptive, b, q->damp_rate, c, q->dt);
    if (q->dt > 0.9 * m->dt_bound)
        q->dt = 0.9 * m->dt_bound;
    /* where omega^2 is not a + b / dt^2 (a cable loop and a latch on the same pins) the
       root creeps down on the bound from above (42 % of the gap a pass): from the fifth
       pass, 2 % below it each pass, so a step a few per cent under the best is found */
    if (pass >= 4)
        q->dt *= 0.98;
    return 1;
}

/* Adaptive limits: K_AP = I_red/dt^2 gives omega dt = 1 on its own. Contact chatter near
   the links' bound pumps energy with it too (stress suite: RC13 impacts blew up at 0.95 x
   the bound with K_AP counted once), so it counts twice; K_AP grows as dt shrinks, so the
   automatic dt is searched (rj__next_adaptive_dt); each pass checks the step it settles
   on. A given dt is taken as it is, with its bound. */
static int rj__search_adaptive_dt(rj_model *m, const rj_scene_def *sc, const rj__build_scratch *s,
                                  rj__dt_search *q, rj_error *err)
{
    const int passes = sc->solver.dt > 0 ? 1 : 20;
    int pass;
    for (pass = 0; pass < passes; pass++) {
        double om2;
        rj__count_adaptive_limits(m, q);
        om2 = rj__init_bound(m, s, q->damp_rate);
        if (sc->solver.dt > 0 || q->dt <= 0.9 * m->dt_bound * 1.000001)
            break;
        if (!rj__next_adaptive_dt(m, q, om2, pass, err))
            return 0;
    }
    return 1;
}

/* The limits' stiffness in use: a penalty limit's K, an adaptive limit's K_AP at dt. */
static void rj__init_limit_stiffness(rj_model *m, double dt)
{
    int j;
    for (j = 0; j < m->nj; j++) {
        const rj_joint_def *d = &m->jdef[j];
        rj__joint *J = &m->jnt[j];
        if (d->method == RJ_METHOD_PENALTY)
            J->k_limit = d->penalty_k;
        if (d->method == RJ_METHOD_ADAPTIVE)
            J->k_limit = rj__adaptive_k(m, J, dt);
    }
}

/* Rigid scenes without stiff joints: no stiffness bounds the step, so it is 1 ms at most,
   and 0.004 of the time a link takes to swing under gravity, sqrt(l / g), for the shortest
   link (measured on the two-link strip with its adaptive latch under 1e4 and 1e5 m/s^2:
   0.003 of it runs, 0.01 blows up as the latch catches; at 9.81 m/s^2 this binds only
   links under 0.6 m). */
static double rj__rigid_dt_cap(const rj_model *m)
{
    const double g = sqrt(m->solver.gravity[0] * m->solver.gravity[0] +
                          m->solver.gravity[1] * m->solver.gravity[1]);
    double cap = 1e-3, shortest = HUGE_VAL;
    int l;
    for (l = 0; l < m->nl; l++)
        if (m->ldef[l].length < shortest)
            shortest = m->ldef[l].length;
    if (g > 0 && 0.004 * sqrt(shortest / g) < cap)
        cap = 0.004 * sqrt(shortest / g);
    return cap;
}

/* The fastest damping rate 2 zeta omega that the links' structural damping on lagged
   rates gives a mode: eta omega^2 + mass_damping, at the links' omega_max (a mode's rate
   is its Rayleigh quotient, at most each part's largest: eta's at the stiffest mode).
   Implicit eta (src/viscous.h) needs no shorter step. */
static double rj__structural_rate(const rj_model *m)
{
    double rate = 0;
    int l;
    for (l = 0; l < m->nl; l++) {
        const double *damp = RJ__LD(m, l);
        const double r = damp[RJ__LD_LAGGED] * m->omega_links * m->omega_links +
                         damp[RJ__LD_MASS];
        if (r > rate)
            rate = r;
    }
    return rate;
}

/* A warning when the links' structural damping shortens their bound ten times or more:
   eta acts on every mode at eta omega / 2, the stiffest (an element's axial mode) too. */
static void rj__structural_warning(rj_model *m)
{
    const double plain = rj__dt_bound_of(m->omega_links, 0);
    const double damped = rj__dt_bound_of(m->omega_links, m->struct_rate);
    if (!(m->struct_rate > 0) || !(damped * 10 <= plain))
        return;
    rj__model_warn(m,
                   "structural damping shortens the links' stability bound %.3g times "
                   "(%.3g s to %.3g s): eta damps every mode at eta omega / 2, the stiffest "
                   "(omega_max %.4g rad/s) at %.3g of critical; mass_damping costs no step",
                   plain / damped, plain, damped, m->omega_links,
                   0.5 * m->struct_rate / m->omega_links);
}

/* Stability: omega_max of beams + springs + tables alone (kept for the refusal's advice),
   then with the limits counted; joint damping acts on the rates it lags (Eq 27 on
   v^{n-1/2}): it shortens the step, as the links' structural damping does (on the same
   rates), by dt <= (2 / omega) (sqrt(1 + zeta^2) - zeta) with 2 zeta omega both rates'
   sum. The step: solver.dt, or 0.9 x the bound (rigid scenes
   without stiff joints are not bounded: 1 ms at most), searched with adaptive limits. */
static rj_result rj__init_step(rj_model *m, const rj_scene_def *sc, const rj__build_scratch *s,
                               rj_error *err)
{
    rj__dt_search q;
    int j, any_adaptive, penalty_counted;
    double om2, om2_links;
    for (j = 0; j < m->nj; j++)
        m->jnt[j].k_free = m->jnt[j].k_lin;
    om2_links = rj__bound_omega2(m, s);
    m->omega_links = rj__omega_of(om2_links);
    m->struct_rate = rj__structural_rate(m);
    q.damp_rate = rj__damping_rate(m) + m->struct_rate;
    rj__structural_warning(m);
    any_adaptive = rj__count_penalty_limits(m, &penalty_counted);
    /* the same stiffnesses give the same omega_max: computed again only when they moved */
    if (penalty_counted)
        om2 = rj__init_bound(m, s, q.damp_rate);
    else
        om2 = rj__set_bound(m, om2_links, q.damp_rate);
    q.dt = sc->solver.dt > 0 ? sc->solver.dt : 0.9 * m->dt_bound;
    if (m->rigid && sc->solver.dt <= 0) {
        const double cap = rj__rigid_dt_cap(m);
        if (q.dt > cap)
            q.dt = cap;
    }
    q.om2_no_adaptive = om2;
    if (any_adaptive && !rj__search_adaptive_dt(m, sc, s, &q, err))
        return RJ_ERR_UNSTABLE_DT;
    rj__init_limit_stiffness(m, q.dt);
    m->dt = q.dt;
    return RJ_OK;
}

/* The joint whose stiffness on its own gives the highest omega = sqrt(k_lin c) at the
   start (c: 1/I_red), with that omega and c; -1 when none gives more than 0. */
static int rj__stiffest_joint(const rj_model *m, double *omega, double *compliance)
{
    int j, worst = -1;
    *omega = 0;
    *compliance = 0;
    for (j = 0; j < m->nj; j++) {
        const double c = rj__joint_compliance0(m, j);
        const double om = sqrt(m->jnt[j].k_lin * c);
        if (om > *omega) {
            *omega = om;
            worst = j;
            *compliance = c;
        }
    }
    return worst;
}

/* The advice a step above the bound gets: what the stiffest joint's limit admits when it
   alone is above omega dt = 1, or the links' own bound when they alone are above it. */
static void rj__unstable_dt_advice(const rj_model *m, int worst, double omega, double compliance,
                                   char *extra, size_t size)
{
    extra[0] = 0;
    if (worst >= 0 && omega * m->dt > 1.0) {
        const double room = (RJ__DT_MARGIN * 2.0 / m->dt) * (RJ__DT_MARGIN * 2.0 / m->dt) -
                            m->omega_links * m->omega_links;
        /* what this bound admits for a penalty limit (counted 4 K, added to the links'
           omega^2) */
        const double k_ok = room > 0 ? room / (4.0 * compliance) : 0.0;
        if (m->jdef[worst].method == RJ_METHOD_ADAPTIVE)
            snprintf(extra, size,
                     "; joint %d's adaptive limit gives about omega dt = %.3g, and its K_AP "
                     "(Eq 21) grows as 1/dt^2, so a smaller dt helps little: "
                     "solver.dt = 0 finds the largest stable step if there is one, or use "
                     "RJ_METHOD_MOMENTUM%s",
                     worst, omega * m->dt, m->rigid ? " (rigid links)" : " or a penalty K");
        else if (room > 0 && !m->rigid)
            snprintf(extra, size,
                     "; joint %d's stiffness gives omega dt = %.3g: this model accepts a "
                     "penalty K up to about %.4g N m/rad at this dt (Eq 31 would give %.4g)",
                     worst, omega * m->dt, k_ok, rj_joint_kmax_eq31(m, worst, m->dt));
        else if (room > 0)
            snprintf(extra, size,
                     "; joint %d's stiffness gives omega dt = %.3g: this model accepts a "
                     "penalty K up to about %.4g N m/rad at this dt",
                     worst, omega * m->dt, k_ok);
    }
    if (m->omega_links > 0 && m->dt > rj__dt_bound_of(m->omega_links, m->struct_rate))
        snprintf(extra, size, "; the links alone need dt <= %.4g s%s",
                 rj__dt_bound_of(m->omega_links, m->struct_rate),
                 m->struct_rate > 0 ? " with their structural damping (eta omega_max^2 + "
                                      "mass_damping, the rate it gives the stiffest mode)"
                                    : "");
}

/* A given step above the bound is refused (unless solver.allow_unstable), naming the
   stiffest joint when a joint, not a link, sets the bound. */
static rj_result rj__refuse_unstable_dt(const rj_model *m, rj_error *err)
{
    double omega, compliance;
    char extra[240];
    const int worst = rj__stiffest_joint(m, &omega, &compliance);
    const int adaptive_worst =
        worst >= 0 && omega * m->dt > 1.0 && m->jdef[worst].method == RJ_METHOD_ADAPTIVE;
    rj__unstable_dt_advice(m, worst, omega, compliance, extra, sizeof extra);
    rj__fail(err, RJ_ERR_UNSTABLE_DT, "solver.dt", m->dt,
             "solver.dt = %.9g s is above the stability bound %.9g s (omega_max %g rad/s)%s; %s",
             m->dt, m->dt_bound, m->omega_max, extra,
             adaptive_worst ? "or set solver.allow_unstable"
                            : "use a smaller dt or set solver.allow_unstable");
    return RJ_ERR_UNSTABLE_DT;
}

/* The step in use must be stable (unless solver.allow_unstable) and usable: a bound or a
   step that is not a finite positive number leaves nothing to run, nor does a start that
   is not finite. */
static rj_result rj__check_step(const rj_model *m, const rj_scene_def *sc, rj_error *err)
{
    if (m->dt > m->dt_bound && !sc->solver.allow_unstable)
        return rj__refuse_unstable_dt(m, err);
    if (!rj__usable_step(m, err))
        return RJ_ERR_INVALID;
    return RJ_OK;
}

/* Eq 28 over the whole model: the shortest element wave transit l0 / c. */
static void rj__init_dt_eq28(rj_model *m)
{
    int l;
    m->dt_eq28 = HUGE_VAL;
    for (l = 0; l < m->nl; l++) {
        const double wave_speed = sqrt(m->ldef[l].E / m->ldef[l].rho);
        const double transit = m->link_l0[l] / wave_speed;
        if (transit < m->dt_eq28)
            m->dt_eq28 = transit;
    }
}

/* The nodes the step advances again after the joints, once each and in ascending order:
   every node a joint or an applied load acts on, rigid links' nodes (their bodies move
   them), and every link's end nodes (tip masses: not the link's uniform values). mark
   (nn ints) keeps which they are for rj__init_link_uniform. */
static void rj__init_step_nodes(rj_model *m, int *mark)
{
    int i, j, l, k;
    m->ndn = 0;
    for (i = 0; i < m->nn; i++)
        mark[i] = 0;
    for (j = 0; j < m->nj; j++) {
        const rj__joint *J = &m->jnt[j];
        const int nodes[4] = { J->nI, J->nJ, J->chord ? J->nK : -1, J->chord ? J->nL : -1 };
        for (k = 0; k < 4; k++)
            if (nodes[k] >= 0)
                mark[nodes[k]] = 1;
    }
    for (k = 0; k < m->nload; k++)
        mark[m->load_node[k]] = 1;
    for (l = 0; l < m->nl; l++) {
        const int n0 = m->link_first[l], ne_l = m->ldef[l].elements;
        if (m->ldef[l].fidelity == RJ_LINK_RIGID)
            for (k = n0; k <= n0 + ne_l; k++)
                mark[k] = 1;
        mark[n0 + ne_l] = 1;
        mark[n0] = 1;
    }
    for (i = 0; i < m->nn; i++)
        if (mark[i])
            m->dnode[m->ndn++] = i;
    m->dn_inner = 0;
    for (l = 0; l < m->nl; l++) {
        const int n0 = m->link_first[l], ne_l = m->ldef[l].elements;
        if (m->ldef[l].fidelity != RJ_LINK_RIGID)
            for (k = n0 + 1; k < n0 + ne_l; k++)
                if (mark[k])
                    m->dn_inner = 1;
    }
}

/* A link whose other (unmarked) nodes share their inverse masses and energy weights
   (uniform sections: all of them) lets the fused pass read four numbers instead of four
   arrays: tinv, rinv, kmass, krot, and 1 when they all agree. */
static void rj__init_link_uniform(rj_model *m, const int *mark)
{
    int l, k;
    for (l = 0; l < m->nl; l++) {
        const int n0 = m->link_first[l], ne_l = m->ldef[l].elements;
        double *u = m->link_un + 5 * l;
        int first = 1, same = 1;
        u[3] = 0;
        u[2] = 0;
        u[1] = 0;
        u[0] = 0;
        for (k = n0; k <= n0 + ne_l; k++) {
            if (mark[k])
                continue;
            if (first) {
                u[0] = m->tinv[k];
                u[1] = m->rinv[k];
                u[2] = m->kmass[k];
                u[3] = m->krot[k];
                first = 0;
            } else if (!(u[0] == m->tinv[k] && u[1] == m->rinv[k] && u[2] == m->kmass[k] &&
                         u[3] == m->krot[k]))
                same = 0;
        }
        u[4] = same;
    }
}

/* A frame's size: nodes, elements (beta, chords), joints, scalars, then the clusters'
   records and the yielding layers' plastic strains; and its flags, one per joint. */
static void rj__init_frames(rj_model *m)
{
    m->frame_doubles =
        6 * (size_t) m->nn + 3 * (size_t) m->ne + RJ__JD_COUNT * (size_t) m->nj + RJ__FS_COUNT;
    m->cl_off = m->frame_doubles;
    m->frame_doubles += 6 * (size_t) m->ncl;
    m->pl_off = m->frame_doubles;
    m->frame_doubles += m->npl;
    m->frame_ints = (size_t) m->nj;
}

/* Kelvin-Voigt damping taken implicitly (src/viscous.h) on every damped link but those a
   rigid body carries a node of (their pins move with the body, which the link's solve
   does not see): those keep it on the lagged rates, which their bound counts. */
static void rj__init_viscous(rj_model *m)
{
    int l, n;
    m->nvisc = 0;
    m->visc_nodes = 0;
    for (l = 0; l < m->nl; l++) {
        double *damp = RJ__LD(m, l);
        const int nodes = m->link_first[l + 1] - m->link_first[l];
        int carried = 0;
        if (!(damp[RJ__LD_LAGGED] > 0))
            continue;
        for (n = m->link_first[l]; n < m->link_first[l + 1] && m->ncl; n++)
            carried |= m->node_cl[n] >= 0;
        if (carried)
            continue;
        damp[RJ__LD_IMPLICIT] = damp[RJ__LD_LAGGED];
        damp[RJ__LD_LAGGED] = 0;
        m->nvisc++;
        if (nodes > m->visc_nodes)
            m->visc_nodes = nodes;
    }
    m->applied = m->nload > 0 || m->nvisc > 0;
}

/* The link of node n when its Kelvin-Voigt damping is implicit, else -1. */
static int rj__visc_link_of(const rj_model *m, int n)
{
    int link, node;
    if (n < 0)
        return -1;
    rj__node_of(m, n, &link, &node);
    return RJ__LD(m, link)[RJ__LD_IMPLICIT] > 0 ? link : -1;
}

/* The damped links joint j's solve holds (rj__visc_hold): those of its pin nodes (lJ -1
   where both are on one link); none for a chord-referenced joint or one between two
   bodies. */
static void rj__visc_joint_links(const rj_model *m, int j, int *lI, int *lJ)
{
    const rj__joint *J = &m->jnt[j];
    *lI = *lJ = -1;
    if (J->chord || J->pair)
        return;
    *lI = rj__visc_link_of(m, J->nI);
    *lJ = rj__visc_link_of(m, J->nJ);
    if (*lJ == *lI)
        *lJ = -1;
}

/* Each damped link's joints for its solve to hold, in joint order: a count a link, the
   runs, then each joint into its links' runs. The step walked every joint for every
   link. */
static void rj__init_visc_holds(rj_model *m)
{
    int *first = m->visc_first, j, l, lI, lJ;
    for (l = 0; l <= m->nl; l++)
        first[l] = 0;
    for (j = 0; j < m->nj && m->nvisc; j++) {
        rj__visc_joint_links(m, j, &lI, &lJ);
        first[lI + 1] += lI >= 0;
        first[lJ + 1] += lJ >= 0;
    }
    for (l = 0; l < m->nl; l++)
        first[l + 1] += first[l];
    /* first[l] is now where link l's run ends as it fills */
    for (j = 0; j < m->nj && m->nvisc; j++) {
        rj__visc_joint_links(m, j, &lI, &lJ);
        if (lI >= 0)
            m->visc_joint[first[lI]++] = j;
        if (lJ >= 0)
            m->visc_joint[first[lJ]++] = j;
    }
    for (l = m->nl; l > 0; l--)
        first[l] = first[l - 1];
    first[0] = 0;
}

/* In place: not with inextensible links (SHAKE reads every node at n), and only if every
   node of a pin group or a rigid body is one the step keeps (m->dnode: it is). */
static void rj__init_in_place(rj_model *m)
{
    int i, q;
    /* not with inextensible links or pins between bodies (their projections read every
       node at n), nor with implicit damping (its power, every damped node's v^{n-1/2}) */
    m->project = m->any_inext || m->nbp;
    m->ip = !m->rigid && !m->project && !m->nvisc && m->solver.in_place != RJ_IN_PLACE_OFF &&
            (m->solver.in_place == RJ_IN_PLACE_ON || m->nn >= RJ_IN_PLACE_NODES);
    for (i = 0; i < m->ng && m->ip; i++)
        for (q = m->grp_first[i]; q < m->grp_first[i + 1]; q++)
            if (!rj__is_dnode(m, m->grp_node[q]))
                m->ip = 0;
    for (i = 0; i < m->ncl && m->ip; i++)
        for (q = m->cl_first[i]; q < m->cl_first[i + 1]; q++)
            if (!rj__is_dnode(m, m->cl_node[q]))
                m->ip = 0;
}

/* The model, phase by phase. A refusal returns at the first error, the checks in their
   order: arguments and fields (unless validated: rj_model_size has just checked them),
   the joint graph, the links' numbers, the step. */
static rj_result rj__model_init(const rj_scene_def *sc, void *mem, size_t size, rj_model **out,
                                int validated, rj_error *err)
{
    rj__layout L;
    rj__build_scratch s;
    rj_model *m;
    size_t nodes, elements;
    rj_result r =
        rj__init_check_args(sc, mem, size, out, &nodes, &elements, &L, validated, err);
    if (r != RJ_OK)
        return r;
    m = rj__init_block(sc, mem, &L, nodes, elements);
    rj__init_arrays(m, &L);
    rj__build_scratch_carve(m, &s);
    if (!rj__validate_graph(sc, s.graph, err))
        return RJ_ERR_INVALID;
    rj__init_copy_defs(m, sc);
    rj__init_links(m);
    rj__init_load_nodes(m);
    if (!rj__check_links(m, err))
        return RJ_ERR_INVALID;
    rj__init_joint_nodes(m);
    rj__init_pin_groups(m, s.pin_groups);
    rj__init_energy_masses(m);
    rj__init_placement(m, s.placement);
    rj__init_chord_angles(m);
    if (!rj__init_clusters(m, sc, err))
        return RJ_ERR_INVALID;
    rj__init_viscous(m);
    rj__init_joint_constants(m);
    rj__init_visc_holds(m);
    rj__init_rigid(m, sc, s.chains);
    rj__limit_warnings(m);
    r = rj__init_step(m, sc, &s, err);
    if (r != RJ_OK)
        return r;
    r = rj__check_step(m, sc, err);
    if (r != RJ_OK)
        return r;
    rj__init_dt_eq28(m);
    rj__init_step_nodes(m, s.step_node_mark);
    rj__init_link_uniform(m, s.step_node_mark);
    rj__init_frames(m);
    rj__init_in_place(m);
    m->hash = rj__model_hash(m);
    *out = m;
    return RJ_OK;
}

RJDEF rj_result rj_model_init(const rj_scene_def *sc, void *mem, size_t size, rj_model **out,
                              rj_error *err)
{
    return rj__model_init(sc, mem, size, out, 0, err);
}

RJDEF rj_result rj_model_create(const rj_scene_def *scene, rj_model **out, rj_error *err,
                                void *alloc_ctx)
{
    size_t sz;
    void *mem;
    rj_result r;
    rj_error size_err;
    (void) alloc_ctx;
    if (!out) {
        rj__fail(err, RJ_ERR_INVALID, "out", 0, "out is NULL");
        return RJ_ERR_INVALID;
    }
    sz = rj_model_size(scene, err ? err : &size_err);
    if (!sz)
        return err ? err->code : size_err.code;
    mem = RJ_MALLOC(sz, alloc_ctx);
    if (!mem) {
        rj__fail(err, RJ_ERR_NOMEM, "size", (double) sz, "could not allocate %lu bytes",
                 (unsigned long) sz);
        return RJ_ERR_NOMEM;
    }
    /* rj_model_size has just validated the scene */
    r = rj__model_init(scene, mem, sz, out, 1, err);
    if (r != RJ_OK) {
        RJ_FREE(mem, alloc_ctx);
        return r;
    }
    /* remember the raw pointer for free: the model sits at the aligned start of mem */
    if ((void *) *out != mem) {
        /* alignment moved the start; keep it simple: allocators return 16-aligned blocks */
        RJ_FREE(mem, alloc_ctx);
        rj__fail(err, RJ_ERR_NOMEM, "size", 0,
                 "RJ_MALLOC returned a block not aligned to 16 bytes");
        *out = NULL;
        return RJ_ERR_NOMEM;
    }
    return RJ_OK;
}

RJDEF void rj_model_destroy(rj_model *m, void *alloc_ctx)
{
    (void) alloc_ctx;
    if (m)
        RJ_FREE(m, alloc_ctx);
}

