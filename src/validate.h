/* ------------------------------------------------------------------ validation */
#define RJ__FIELD(buf, fmt, i) snprintf(buf, sizeof buf, fmt, i)

/* The ranges of single members, and their sentences, are the rows of fields.h. They are
   far beyond any material or mechanism, and small enough that what the step, the energy
   accounts and a checkpoint (whose values stay within 1e100) compute from them stays
   within reach: a link of 1e6 m, 1e6 m deep, of 1e30 kg/m^3 under 1e5 m/s^2 has a
   potential of about 1e65 J. */

static int rj__check_num(rj_error *err, const char *field, double v, double lo, int lo_incl,
                         double hi, int hi_incl, const char *what)
{
    int ok = rj__finite(v) && (lo_incl ? v >= lo : v > lo) && (hi_incl ? v <= hi : v < hi);
    if (!ok) {
        rj__fail(err, RJ_ERR_INVALID, field, v, "%s = %g is invalid: %s", field, v, what);
        return 0;
    }
    return 1;
}

/* Whether v is finite and in row r's range. */
static int rj__row_in_range(const rj__field *r, double v)
{
    return rj__finite(v) && (r->lo_in ? v >= r->lo : v > r->lo) &&
           (r->hi_in ? v <= r->hi : v < r->hi);
}

/* Row r of def, item (a prefix such as "links[3]", "solver"): its value in the row's
   range, or the row's sentence (the field's name is written only then: validation is
   linear in the scene, and cheap). Rows of links, nodes and tables are checked by their
   concepts' code. */
static int rj__check_row(rj_error *err, const char *item, const rj__field *r, const void *def)
{
    char f[64];
    int c, v;
    switch (r->type) {
    case RJ__FT_REAL:
    case RJ__FT_ANGLE:
    case RJ__FT_RATE:
    case RJ__FT_LIMIT:
    case RJ__FT_VEC2:
        for (c = 0; c < (r->type == RJ__FT_VEC2 ? 2 : 1); c++) {
            const double x = rj__row_real(def, r, c);
            if (rj__row_in_range(r, x))
                continue;
            if (r->type == RJ__FT_VEC2)
                snprintf(f, sizeof f, "%s.%s[%d]", item, r->member, c);
            else
                snprintf(f, sizeof f, "%s.%s", item, r->member);
            rj__fail(err, RJ_ERR_INVALID, f, x, "%s = %g is invalid: %s", f, x, r->rule);
            return 0;
        }
        return 1;
    case RJ__FT_INT:
    case RJ__FT_ENUM:
    case RJ__FT_BOOL:
    case RJ__FT_PROFILE:
        v = rj__row_int(def, r);
        if (v >= r->lo && v <= r->hi)
            return 1;
        snprintf(f, sizeof f, "%s.%s", item, r->member);
        rj__fail(err, RJ_ERR_INVALID, f, v, "%s = %d is invalid: %s", f, v, r->rule);
        return 0;
    default:
        return 1;
    }
}

/* Every row of a definition of kind (fields.h) that applies to it, in the table's
   order; shape: a link's section shape, -1 for other kinds. */
static int rj__check_rows(rj_error *err, const char *item, int kind, const void *def,
                          int shape)
{
    int n, k;
    const rj__field *t = rj__fields(kind, &n);
    for (k = 0; k < n; k++)
        if (rj__row_applies(&t[k], shape, 0, 0) && !rj__check_row(err, item, &t[k], def))
            return 0;
    return 1;
}

static int rj__all_rigid(const rj_scene_def *sc)
{
    int i;
    for (i = 0; i < sc->link_count; i++)
        if (sc->links[i].fidelity != RJ_LINK_RIGID)
            return 0;
    return 1;
}

/* An array of the scene: count in fewest..100000 and the array there when count > 0.
   name: "link" for link_count and a links array. */
static int rj__check_array(rj_error *err, const char *name, int count, int fewest,
                           const void *array)
{
    char field[32];
    if (count >= fewest && count <= 100000 && (count == 0 || array))
        return 1;
    snprintf(field, sizeof field, "%s_count", name);
    rj__fail(err, RJ_ERR_INVALID, field, count,
             "%s = %d is invalid: need %d..100000 %ss and the %ss array", field, count, fewest, name,
             name);
    return 0;
}

/* Item i of a definitions array (field "links[%d]") was made by its default function
   (maker, "rj_default_link_def()"): its cookie. */
static int rj__check_cookie(rj_error *err, const char *field_format, int i, unsigned cookie,
                            unsigned want, const char *maker)
{
    char f[64];
    if (cookie == want)
        return 1;
    RJ__FIELD(f, field_format, i);
    rj__fail(err, RJ_ERR_INVALID, f, 0, "%s was not initialised with %s", f, maker);
    return 0;
}

/* A table in time (a load's, an actuator's) of item (prefix "loads[2]"): 0 (constant) or
   1..RJ_TABLE_MAX points, times finite and strictly increasing, within +-1e9 s, factors
   within +-1e6. */
static int rj__validate_time_table(rj_error *err, const char *item, int count,
                                   const double *time, const double *factor)
{
    char f[64];
    int k;
    if (count < 0 || count > RJ_TABLE_MAX) {
        snprintf(f, sizeof f, "%s.table_count", item);
        rj__fail(err, RJ_ERR_INVALID, f, count,
                 "%s = %d is invalid: must be 0 (constant) or 1..%d points", f, count,
                 RJ_TABLE_MAX);
        return 0;
    }
    for (k = 0; k < count; k++) {
        snprintf(f, sizeof f, "%s.table_time[%d]", item, k);
        if (!rj__check_num(err, f, time[k], -1e9, 1, 1e9, 1,
                           "must be a finite time within +-1e9 s (further than any run "
                           "reaches, where a step no longer resolves the table)"))
            return 0;
        if (k > 0 && !(time[k] > time[k - 1])) {
            rj__fail(err, RJ_ERR_INVALID, f, time[k],
                     "%s = %g is invalid: the table's times must increase strictly (the point "
                     "before is at %g s)",
                     f, time[k], time[k - 1]);
            return 0;
        }
        snprintf(f, sizeof f, "%s.table_factor[%d]", item, k);
        if (!rj__check_num(err, f, factor[k], -1e6, 1, 1e6, 1,
                           "must be a finite factor within +-1e6"))
            return 0;
    }
    return 1;
}

/* Applied loads: a known link and node, the rows' ranges, a table in time. */
static int rj__validate_loads(const rj_scene_def *sc, rj_error *err)
{
    char f[64], item[32];
    int i;
    if (!rj__check_array(err, "load", sc->load_count, 0, sc->loads))
        return 0;
    for (i = 0; i < sc->load_count; i++) {
        const rj_load_def *d = &sc->loads[i];
        if (!rj__check_cookie(err, "loads[%d]", i, d->cookie, RJ__COOKIE_LOAD,
                              "rj_default_load_def()"))
            return 0;
        if (d->link < 0 || d->link >= sc->link_count) {
            RJ__FIELD(f, "loads[%d].link", i);
            rj__fail(err, RJ_ERR_INVALID, f, d->link,
                     "%s = %d is invalid: the scene has links 0..%d", f, d->link,
                     sc->link_count - 1);
            return 0;
        }
        if (d->node < -1 || d->node > sc->links[d->link].elements) {
            RJ__FIELD(f, "loads[%d].node", i);
            rj__fail(err, RJ_ERR_INVALID, f, d->node,
                     "%s = %d is invalid: link %d has nodes 0..%d (-1: the last)", f, d->node,
                     d->link, sc->links[d->link].elements);
            return 0;
        }
        RJ__FIELD(item, "loads[%d]", i);
        if (!rj__check_rows(err, item, RJ__DEF_LOAD, d, -1))
            return 0;
        if (!rj__validate_time_table(err, item, d->table_count, d->table_time, d->table_factor))
            return 0;
    }
    return 1;
}

/* The solver: its rows. */
static int rj__validate_solver(const rj_solver_def *s, rj_error *err)
{
    if (s->cookie != RJ__COOKIE_SOLVER) {
        rj__fail(err, RJ_ERR_INVALID, "solver", 0,
                 "solver was not initialised with rj_default_solver_def()");
        return 0;
    }
    return rj__check_rows(err, "solver", RJ__DEF_SOLVER, s, -1);
}

/* Link i: its section's shape first (which rows apply depends on it), then its rows; a
   rectangle's height is > 0. */
/* A link's structural damping: on a link that strains (a rigid one has none to damp), a
   ratio with its frequency, and eta or the ratio, not both. */
static int rj__validate_link_damping(const rj_link_def *L, int i, rj_error *err)
{
    char f[64];
    const int any = L->eta > 0 || L->damping[0] > 0 || L->mass_damping > 0;
    if (any && L->fidelity == RJ_LINK_RIGID) {
        RJ__FIELD(f, "links[%d].eta", i);
        rj__fail(err, RJ_ERR_INVALID, f, L->eta,
                 "links[%d] is rigid: eta, damping and mass_damping damp a link's strain and "
                 "vibration, which a rigid link does not have (use joint damping)",
                 i);
        return 0;
    }
    if (L->damping[0] > 0 && !(L->damping[1] > 0)) {
        RJ__FIELD(f, "links[%d].damping[1]", i);
        rj__fail(err, RJ_ERR_INVALID, f, L->damping[1],
                 "%s = %g is invalid: a damping ratio needs the frequency it holds at, > 0 Hz",
                 f, L->damping[1]);
        return 0;
    }
    if (L->damping[0] > 0 && L->eta > 0) {
        RJ__FIELD(f, "links[%d].damping", i);
        rj__fail(err, RJ_ERR_INVALID, f, L->damping[0],
                 "%s = %g %g and eta = %g: give eta or a damping ratio, not both", f,
                 L->damping[0], L->damping[1], L->eta);
        return 0;
    }
    return 1;
}

/* A link's yielding layers: a flexible link (a rigid one has no strain, an inextensible
   one's axial force is a constraint's) of rectangular section (its layers are the
   sections the plastic strains live in), and a state of size that an int indexes. The
   Biot law is a flexible link's axial law. */
static int rj__validate_link_plastic(const rj_link_def *L, int i, rj_error *err)
{
    char f[64];
    const double strains = 2.0 * L->layers * (double) L->elements;
    if (L->strain == RJ_STRAIN_BIOT && L->fidelity != RJ_LINK_FLEXIBLE) {
        RJ__FIELD(f, "links[%d].strain", i);
        rj__fail(err, RJ_ERR_INVALID, f, L->strain,
                 "%s = RJ_STRAIN_BIOT is an axial law for a flexible link; links[%d] is %s", f,
                 i, L->fidelity == RJ_LINK_RIGID ? "rigid" : "inextensible");
        return 0;
    }
    if (!(L->yield > 0))
        return 1;
    RJ__FIELD(f, "links[%d].yield", i);
    if (L->fidelity != RJ_LINK_FLEXIBLE || L->section != RJ_SECTION_RECT) {
        rj__fail(err, RJ_ERR_INVALID, f, L->yield,
                 "%s = %g: yielding layers need a flexible link of rectangular section "
                 "(links[%d] is %s)",
                 f, L->yield, i,
                 L->fidelity == RJ_LINK_RIGID          ? "rigid"
                 : L->fidelity == RJ_LINK_INEXTENSIBLE ? "inextensible"
                                                       : "of general section");
        return 0;
    }
    if (L->layers < 2) {
        rj__fail(err, RJ_ERR_INVALID, f, L->yield,
                 "%s = %g needs 2 or more layers (links[%d].layers = %d): a single layer "
                 "sits at mid-depth, where bending never strains it",
                 f, L->yield, i, L->layers);
        return 0;
    }
    if (strains > 1e8) {
        rj__fail(err, RJ_ERR_INVALID, f, L->yield,
                 "%s = %g: %d layers of %d elements are %.3g plastic strains (two sections "
                 "an element), more than the 1e8 a link may keep",
                 f, L->yield, L->layers, L->elements, strains);
        return 0;
    }
    return 1;
}

/* The scene's plastic strains all told: an int indexes them (1e9 at most). */
static int rj__validate_plastic_total(const rj_scene_def *sc, rj_error *err)
{
    double total = 0;
    int i;
    for (i = 0; i < sc->link_count; i++)
        if (sc->links[i].yield > 0)
            total += 2.0 * sc->links[i].layers * (double) sc->links[i].elements;
    if (total <= 1e9)
        return 1;
    rj__fail(err, RJ_ERR_INVALID, "links", total,
             "the yielding links keep %.3g plastic strains all told, more than the 1e9 a "
             "scene may",
             total);
    return 0;
}

static int rj__validate_link(const rj_link_def *L, int i, rj_error *err)
{
    char f[64], item[32];
    if (!rj__check_cookie(err, "links[%d]", i, L->cookie, RJ__COOKIE_LINK,
                          "rj_default_link_def()"))
        return 0;
    RJ__FIELD(item, "links[%d]", i);
    if (!rj__check_row(err, item, &rj__link_fields[RJ__LF_SHAPE], L))
        return 0;
    if (!rj__check_rows(err, item, RJ__DEF_LINK, L, L->section))
        return 0;
    if (L->section == RJ_SECTION_RECT && !(L->height > 0)) {
        const rj__field *r = &rj__link_fields[RJ__LK_HEIGHT];
        RJ__FIELD(f, "links[%d].height", i);
        rj__fail(err, RJ_ERR_INVALID, f, L->height, "%s = %g is invalid: %s", f, L->height,
                 r->rule);
        return 0;
    }
    return rj__validate_link_damping(L, i, err) && rj__validate_link_plastic(L, i, err);
}

/* Joint j's bodies: links of the scene (body1 may be ground), two of them, a node body1
   has, and body2 free to hang from the joint. */
static int rj__validate_bodies(const rj_scene_def *sc, const rj_joint_def *J, int j,
                               rj_error *err)
{
    char f[64];
    if (J->body1 < -1 || J->body1 >= sc->link_count) {
        RJ__FIELD(f, "joints[%d].body1", j);
        rj__fail(err, RJ_ERR_INVALID, f, J->body1,
                 "%s = %d is invalid: a link index 0..%d or -1 for ground", f, J->body1,
                 sc->link_count - 1);
        return 0;
    }
    if (J->body2 < 0 || J->body2 >= sc->link_count) {
        RJ__FIELD(f, "joints[%d].body2", j);
        rj__fail(err, RJ_ERR_INVALID, f, J->body2, "%s = %d is invalid: a link index 0..%d", f,
                 J->body2, sc->link_count - 1);
        return 0;
    }
    if (J->body1 == J->body2) {
        RJ__FIELD(f, "joints[%d].body2", j);
        rj__fail(err, RJ_ERR_INVALID, f, J->body2,
                 "%s = %d is invalid: a joint cannot connect link %d to itself", f, J->body2,
                 J->body2);
        return 0;
    }
    if (J->body1 >= 0 && (J->node1 < -1 || J->node1 > sc->links[J->body1].elements)) {
        RJ__FIELD(f, "joints[%d].node1", j);
        rj__fail(err, RJ_ERR_INVALID, f, J->node1,
                 "%s = %d is invalid: a node 0..%d of link %d, or -1 for its last node", f,
                 J->node1, sc->links[J->body1].elements, J->body1);
        return 0;
    }
    if (J->node2 < -1 || J->node2 > sc->links[J->body2].elements) {
        RJ__FIELD(f, "joints[%d].node2", j);
        rj__fail(err, RJ_ERR_INVALID, f, J->node2,
                 "%s = %d is invalid: a node 0..%d of link %d, or -1 for its last node", f,
                 J->node2, sc->links[J->body2].elements, J->body2);
        return 0;
    }
    if (J->node2 != 0 &&
        J->reference != RJ_REF_TANGENT) {
        RJ__FIELD(f, "joints[%d].node2", j);
        rj__fail(err, RJ_ERR_INVALID, f, J->node2,
                 "%s = %d is not supported: a pin away from body2's first node needs the "
                 "tangent reference",
                 f, J->node2);
        return 0;
    }
    if (sc->links[J->body2].root != RJ_ROOT_FREE) {
        RJ__FIELD(f, "links[%d].root", J->body2);
        rj__fail(err, RJ_ERR_INVALID, f, sc->links[J->body2].root,
                 "%s = %d is invalid: link %d is body2 of joint %d, its root must be RJ_ROOT_FREE",
                 f, sc->links[J->body2].root, J->body2, j);
        return 0;
    }
    return 1;
}

/* A joint's table (Eq 4): 0, or 2..RJ_TABLE_MAX points, angles in [0, 2 pi], finite
   torques. */
static int rj__validate_joint_table(const rj_joint_def *J, int j, rj_error *err)
{
    char f[64];
    int k;
    if (J->table_count != 0 && (J->table_count < 2 || J->table_count > RJ_TABLE_MAX)) {
        RJ__FIELD(f, "joints[%d].table_count", j);
        rj__fail(err, RJ_ERR_INVALID, f, J->table_count, "%s = %d is invalid: 0, or 2..%d points",
                 f, J->table_count, RJ_TABLE_MAX);
        return 0;
    }
    for (k = 0; k < J->table_count; k++) {
        snprintf(f, sizeof f, "joints[%d].table_angle[%d]", j, k);
        if (!rj__check_num(err, f, J->table_angle[k], 0, 1, RJ__TWO_PI, 1,
                           "must be in [0, 2 pi] rad"))
            return 0;
        snprintf(f, sizeof f, "joints[%d].table_torque[%d]", j, k);
        if (!rj__check_num(err, f, J->table_torque[k], -HUGE_VAL, 0, HUGE_VAL, 0,
                           RJ__RULE_FINITE))
            return 0;
    }
    return 1;
}

/* A joint's limits: a lock latches at one, two limits leave a free range between them,
   and a penalty limit has a stiffness. */
static int rj__validate_limits(const rj_joint_def *J, int j, rj_error *err)
{
    char f[64];
    if (J->lock && !J->has_forward && !J->has_reverse) {
        RJ__FIELD(f, "joints[%d].lock", j);
        rj__fail(err, RJ_ERR_INVALID, f, J->lock,
                 "%s = 1 is invalid: a lock latches at a limit, and joint %d has none (set "
                 "has_forward or has_reverse)",
                 f, j);
        return 0;
    }
    if (J->has_forward && J->has_reverse && J->forward == J->reverse) {
        RJ__FIELD(f, "joints[%d].forward", j);
        rj__fail(err, RJ_ERR_INVALID, f, J->forward,
                 "%s = %g is invalid: equal to the reverse limit leaves no free range", f,
                 J->forward);
        return 0;
    }
    if (J->method == RJ_METHOD_PENALTY && (J->has_forward || J->has_reverse) &&
        !(J->penalty_k > 0)) {
        RJ__FIELD(f, "joints[%d].penalty_k", j);
        rj__fail(err, RJ_ERR_INVALID, f, J->penalty_k,
                 "%s = %g is invalid: RJ_METHOD_PENALTY with a limit needs a stiffness > 0", f,
                 J->penalty_k);
        return 0;
    }
    return 1;
}

/* Joint j: its bodies, its rows, its table, its limits. */
static int rj__validate_joint(const rj_scene_def *sc, int j, rj_error *err)
{
    const rj_joint_def *J = &sc->joints[j];
    char item[32];
    if (!rj__check_cookie(err, "joints[%d]", j, J->cookie, RJ__COOKIE_JOINT,
                          "rj_default_joint_def()"))
        return 0;
    RJ__FIELD(item, "joints[%d]", j);
    return rj__validate_bodies(sc, J, j, err) && rj__check_rows(err, item, RJ__DEF_JOINT, J, -1) &&
           rj__validate_joint_table(J, j, err) && rj__validate_limits(J, j, err);
}

/* A joint between two rigid bodies of a mixed scene (their pin is kept by
   rj__body_pins, after the rows): what it may not have yet, the field, or NULL. Its
   limits, lock and friction, a prescribed profile or a cable loop act through rows whose
   gives do not see the pin (tried: an adaptive limit blew up, a plastic latch lost 1.5 J
   of 3.9 J unbooked); its spring, table, damping and a motor's torque act as torques. */
static const char *rj__body_pair_refusal(const rj_scene_def *sc, int j, char *f, size_t n)
{
    const rj_joint_def *J = &sc->joints[j];
    f[0] = 0;
    /* every part is a torque there (rj__stage_pair_latches) but the energy method's
       balance (Eqs 25-26), which would need the pinned pair's inertia */
    if ((J->has_forward || J->has_reverse) && J->method == RJ_METHOD_ENERGY)
        snprintf(f, n, "joints[%d].method", j);
    return f[0] ? f : NULL;
}

/* Mixed scenes (a rigid link is one rigid body, with flexible links pinned to it): a
   joint between two rigid links without the parts rj__body_pair_refusal names, and
   tangent references on rigid links. Scenes of rigid links alone have no energy
   method. */
static int rj__validate_mixed(const rj_scene_def *sc, rj_error *err)
{
    char f[64];
    int j;
    if (rj__all_rigid(sc)) {
        for (j = 0; j < sc->joint_count; j++)
            if (sc->joints[j].method == RJ_METHOD_ENERGY) {
                RJ__FIELD(f, "joints[%d].method", j);
                rj__fail(err, RJ_ERR_INVALID, f, RJ_METHOD_ENERGY,
                         "%s = RJ_METHOD_ENERGY is not available for rigid links (use momentum "
                         "with e = 0, forced or adaptive)",
                         f);
                return 0;
            }
        return 1;
    }
    for (j = 0; j < sc->joint_count; j++) {
        const rj_joint_def *J = &sc->joints[j];
        const int r1 = J->body1 >= 0 && sc->links[J->body1].fidelity == RJ_LINK_RIGID,
                  r2 = sc->links[J->body2].fidelity == RJ_LINK_RIGID;
        if (r1 && r2 && rj__body_pair_refusal(sc, j, f, sizeof f)) {
            rj__fail(err, RJ_ERR_INVALID, f, j,
                     "%s is not supported: joint %d pins two rigid links (%d and %d) in a scene "
                     "with flexible links, where it takes a spring, a table, damping, friction, "
                     "a motor's torque, a prescribed profile, cable loops, and limits and locks "
                     "by any method but energy: make every link rigid, or one of the two "
                     "flexible",
                     f, j, J->body1, J->body2);
            return 0;
        }
        if ((r1 || r2) && J->reference == RJ_REF_CHORD) {
            RJ__FIELD(f, "joints[%d].reference", j);
            rj__fail(err, RJ_ERR_INVALID, f, J->reference,
                     "%s = RJ_REF_CHORD is invalid: joint %d holds rigid link %d in a scene "
                     "with flexible links; use RJ_REF_TANGENT (on a rigid link the chord and "
                     "the tangent are the same line)",
                     f, j, r1 ? J->body1 : J->body2);
            return 0;
        }
    }
    return 1;
}

/* Actuator i's joint: one of the scene's, driven by no other actuator before it. */
static int rj__validate_actuator_joint(const rj_scene_def *sc, int i, rj_error *err)
{
    const rj_actuator_def *d = &sc->actuators[i];
    char f[64];
    int k;
    RJ__FIELD(f, "actuators[%d].joint", i);
    if (d->joint < 0 || d->joint >= sc->joint_count) {
        rj__fail(err, RJ_ERR_INVALID, f, d->joint, "%s = %d is invalid: the scene has joints 0..%d",
                 f, d->joint, sc->joint_count - 1);
        return 0;
    }
    for (k = 0; k < i; k++)
        if (sc->actuators[k].joint == d->joint) {
            rj__fail(err, RJ_ERR_INVALID, f, d->joint,
                     "%s = %d is invalid: actuators[%d] drives joint %d already (a joint has "
                     "at most one actuator)",
                     f, d->joint, k, d->joint);
            return 0;
        }
    return 1;
}

/* A DC motor's no-load speed: not 0, and of its stall torque's sign (the direction it
   drives). */
static int rj__validate_dc(const rj_actuator_def *d, int i, rj_error *err)
{
    const rj__field *r = &rj__actuator_fields[RJ__CK_NO_LOAD_SPEED];
    char f[64];
    if (d->type != RJ_ACTUATOR_DC)
        return 1;
    if (d->no_load_speed != 0 && !(d->stall_torque * d->no_load_speed < 0))
        return 1;
    RJ__FIELD(f, "actuators[%d].no_load_speed", i);
    rj__fail(err, RJ_ERR_INVALID, f, d->no_load_speed, "%s = %g is invalid: %s (%g N m)", f,
             d->no_load_speed, r->rule, d->stall_torque);
    return 0;
}

/* A prescribed joint's angle follows its profile: a limit or a lock on it is refused. */
static int rj__validate_prescribed(const rj_scene_def *sc, const rj_actuator_def *d, int i,
                                   rj_error *err)
{
    const rj_joint_def *J = &sc->joints[d->joint];
    char f[64];
    if (d->type != RJ_ACTUATOR_PRESCRIBED || (!J->has_forward && !J->has_reverse && !J->lock))
        return 1;
    RJ__FIELD(f, "actuators[%d].type", i);
    rj__fail(err, RJ_ERR_INVALID, f, d->type,
             "%s = RJ_ACTUATOR_PRESCRIBED is invalid: joint %d has a limit or a lock, and a "
             "prescribed joint's angle follows its profile alone (remove the limits, or drive "
             "it with a servo)",
             f, d->joint);
    return 0;
}

/* Joint j's pin on body 1 as (link, node), node -1 for ground; body 2's is (body2, 0). */
static void rj__pin_of(const rj_scene_def *sc, int j, int *link, int *node)
{
    const rj_joint_def *J = &sc->joints[j];
    *link = J->body1;
    *node = J->body1 < 0 ? -1 : J->node1 < 0 ? sc->links[J->body1].elements : J->node1;
}

/* Whether joints j and k share a pin node (their rotors would couple one node twice). */
static int rj__pins_meet(const rj_scene_def *sc, int j, int k)
{
    int lj, nj, lk, nk;
    rj__pin_of(sc, j, &lj, &nj);
    rj__pin_of(sc, k, &lk, &nk);
    return (lj >= 0 && lj == lk && nj == nk) || (lj == sc->joints[k].body2 && nj == 0) ||
           (lk == sc->joints[j].body2 && nk == 0);
}

/* A motor's rotor: a gear ratio not 0; on a joint with the tangent reference, between
   flexible bodies (or ground) unless every link is rigid, with pin nodes no other rotor's
   joint uses. */
static int rj__validate_rotor(const rj_scene_def *sc, int i, rj_error *err)
{
    const rj_actuator_def *d = &sc->actuators[i];
    const rj_joint_def *J = &sc->joints[d->joint];
    const char *why = NULL;
    char f[64];
    int k;
    if (d->gear_ratio == 0) {
        RJ__FIELD(f, "actuators[%d].gear_ratio", i);
        rj__fail(err, RJ_ERR_INVALID, f, 0, "%s = 0 is invalid: %s", f,
                 rj__actuator_fields[RJ__CK_GEAR_RATIO].rule);
        return 0;
    }
    if (!(d->rotor_inertia > 0) || rj__all_rigid(sc))
        return 1;
    if (J->reference != RJ_REF_TANGENT)
        why = "its joint uses the chord reference (a rotor needs the tangent)";
    else if (sc->links[J->body2].fidelity == RJ_LINK_RIGID ||
             (J->body1 >= 0 && sc->links[J->body1].fidelity == RJ_LINK_RIGID))
        why = "its joint holds a rigid link in a scene with flexible links";
    for (k = 0; k < i && !why; k++)
        if (sc->actuators[k].rotor_inertia > 0 && rj__pins_meet(sc, d->joint, sc->actuators[k].joint))
            why = "its joint shares a pin node with another rotor's joint";
    if (!why)
        return 1;
    RJ__FIELD(f, "actuators[%d].rotor_inertia", i);
    rj__fail(err, RJ_ERR_INVALID, f, d->rotor_inertia, "%s = %g is not supported: %s", f,
             d->rotor_inertia, why);
    return 0;
}

/* A servo's or a prescribed joint's table is its profile's (profile = table): 2 points at
   least, and a prescribed one starts at 0 rad (the joint starts at angle0); without that
   profile it has none. */
static int rj__validate_profile_table(const rj_actuator_def *d, int i, rj_error *err)
{
    const char *why = NULL;
    char f[64];
    if (d->type == RJ_ACTUATOR_TORQUE || d->type == RJ_ACTUATOR_DC)
        return 1;
    if (d->profile != RJ_PROFILE_TABLE && d->table_count != 0)
        why = "a table applies with profile = table";
    else if (d->profile == RJ_PROFILE_TABLE && d->table_count < 2)
        why = "profile = table needs a table of 2 points at least";
    else if (d->profile == RJ_PROFILE_TABLE && d->type == RJ_ACTUATOR_PRESCRIBED &&
             d->table_factor[0] != 0)
        why = "a prescribed table's first angle is 0 rad (the joint starts at angle0)";
    if (!why)
        return 1;
    RJ__FIELD(f, "actuators[%d].table_count", i);
    rj__fail(err, RJ_ERR_INVALID, f, d->table_count, "%s = %d is invalid: %s", f,
             d->table_count, why);
    return 0;
}

/* Actuators: a joint each, the rows of their type, a table in time. */
static int rj__validate_actuators(const rj_scene_def *sc, rj_error *err)
{
    char item[32];
    int i;
    if (!rj__check_array(err, "actuator", sc->actuator_count, 0, sc->actuators))
        return 0;
    for (i = 0; i < sc->actuator_count; i++) {
        const rj_actuator_def *d = &sc->actuators[i];
        if (!rj__check_cookie(err, "actuators[%d]", i, d->cookie, RJ__COOKIE_ACTUATOR,
                              "rj_default_actuator_def()"))
            return 0;
        RJ__FIELD(item, "actuators[%d]", i);
        if (!rj__check_row(err, item, &rj__actuator_fields[RJ__CK_TYPE], d) ||
            !rj__validate_actuator_joint(sc, i, err) ||
            !rj__check_rows(err, item, RJ__DEF_ACTUATOR, d, d->type) ||
            !rj__validate_dc(d, i, err) || !rj__validate_prescribed(sc, d, i, err) ||
            !rj__validate_rotor(sc, i, err))
            return 0;
        if (!rj__validate_time_table(err, item, d->table_count, d->table_time, d->table_factor) ||
            !rj__validate_profile_table(d, i, err))
            return 0;
    }
    return 1;
}

/* An exact coupling is a constraint: no stiffness or damping of its own; on joints with
   the tangent reference (a chord's impulse moves the chord's far nodes, whose work the
   rows' form does not count). */
static int rj__validate_exact(const rj_scene_def *sc, const rj_coupling_def *d, int i,
                              rj_error *err)
{
    const int joint[2] = { d->joint_a, d->joint_b };
    const char *why = NULL;
    char f[64];
    int k;
    if (!d->exact)
        return 1;
    if (d->stiffness != 0 || d->damping != 0)
        why = "an exact coupling is a constraint: give it no stiffness or damping";
    for (k = 0; k < 2 && !why; k++) {
        const rj_joint_def *J = &sc->joints[joint[k]];
        if (J->reference != RJ_REF_TANGENT)
            why = "an exact coupling needs the tangent reference on both joints";
    }
    if (!why)
        return 1;
    RJ__FIELD(f, "couplings[%d].exact", i);
    rj__fail(err, RJ_ERR_INVALID, f, 1, "%s = 1 is not supported: %s", f, why);
    return 0;
}

/* Couplings: two different joints of the scene, and the rows. */
static int rj__validate_couplings(const rj_scene_def *sc, rj_error *err)
{
    char f[64], item[32];
    int i;
    if (!rj__check_array(err, "coupling", sc->coupling_count, 0, sc->couplings))
        return 0;
    for (i = 0; i < sc->coupling_count; i++) {
        const rj_coupling_def *d = &sc->couplings[i];
        if (!rj__check_cookie(err, "couplings[%d]", i, d->cookie, RJ__COOKIE_COUPLING,
                              "rj_default_coupling_def()"))
            return 0;
        if (d->joint_a < 0 || d->joint_a >= sc->joint_count) {
            RJ__FIELD(f, "couplings[%d].joint_a", i);
            rj__fail(err, RJ_ERR_INVALID, f, d->joint_a,
                     "%s = %d is invalid: the scene has joints 0..%d", f, d->joint_a,
                     sc->joint_count - 1);
            return 0;
        }
        if (d->joint_b < 0 || d->joint_b >= sc->joint_count || d->joint_b == d->joint_a) {
            RJ__FIELD(f, "couplings[%d].joint_b", i);
            rj__fail(err, RJ_ERR_INVALID, f, d->joint_b,
                     "%s = %d is invalid: a joint 0..%d other than joint_a (%d)", f, d->joint_b,
                     sc->joint_count - 1, d->joint_a);
            return 0;
        }
        RJ__FIELD(item, "couplings[%d]", i);
        if (!rj__check_rows(err, item, RJ__DEF_COUPLING, d, -1) ||
            !rj__validate_exact(sc, d, i, err))
            return 0;
    }
    return 1;
}

static int rj__validate(const rj_scene_def *sc, rj_error *err)
{
    int i, j;
    if (!sc) {
        rj__fail(err, RJ_ERR_INVALID, "scene", 0, "scene is NULL");
        return 0;
    }
    if (!rj__check_array(err, "link", sc->link_count, 1, sc->links) ||
        !rj__check_array(err, "joint", sc->joint_count, 0, sc->joints))
        return 0;
    if (!rj__validate_solver(&sc->solver, err))
        return 0;
    for (i = 0; i < sc->link_count; i++)
        if (!rj__validate_link(&sc->links[i], i, err))
            return 0;
    if (!rj__validate_plastic_total(sc, err))
        return 0;
    for (j = 0; j < sc->joint_count; j++)
        if (!rj__validate_joint(sc, j, err))
            return 0;
    return rj__validate_mixed(sc, err) && rj__validate_loads(sc, err) &&
           rj__validate_actuators(sc, err) && rj__validate_couplings(sc, err);
}

/* Node and element totals, counted in size_t; 0 when they pass RJ__MAX_NODES. */
static int rj__counts(const rj_scene_def *sc, size_t *nn, size_t *ne, rj_error *err)
{
    int i;
    *nn = 0;
    *ne = 0;
    for (i = 0; i < sc->link_count; i++) {
        *nn += (size_t) sc->links[i].elements + 1;
        *ne += (size_t) sc->links[i].elements;
    }
    if (*nn > RJ__MAX_NODES) {
        rj__fail(err, RJ_ERR_INVALID, "links", (double) *nn,
                 "the scene has %.0f nodes in all, more than the %d a model can hold (node indices "
                 "are ints)",
                 (double) *nn, RJ__MAX_NODES);
        return 0;
    }
    return 1;
}

/* The link a link hangs from (-1: ground or none), given each link's joint in parent. */
static int rj__up(const rj_scene_def *sc, const int *parent, int link)
{
    return parent[link] >= 0 ? sc->joints[parent[link]].body1 : -1;
}

/* The node a joint pins on body1 (-1 for ground), numbered across the scene (first[l]:
   link l's first node), the key the pin check sorts joints by. */
static long rj__pin_key(const rj_scene_def *sc, const int *first, int j)
{
    const rj_joint_def *J = &sc->joints[j];
    if (J->body1 < 0)
        return -1;
    return (long) first[J->body1] + (J->node1 < 0 ? sc->links[J->body1].elements : J->node1);
}

/* Sorts joint indices by (pin node, index): heap sort, in place and without recursion. */
static void rj__sort_pins(const rj_scene_def *sc, const int *first, int *idx, int n)
{
    int end, root, child, top;
    for (top = n / 2 - 1, end = n; end > 1 || top >= 0;) {
        if (top >= 0)
            root = top--;
        else {
            const int t = idx[0];
            idx[0] = idx[--end];
            idx[end] = t;
            root = 0;
        }
        /* sift idx[root] down among idx[0 .. end) */
        for (; (child = 2 * root + 1) < end; root = child) {
            long kc = rj__pin_key(sc, first, idx[child]), kr;
            if (child + 1 < end) {
                const long k2 = rj__pin_key(sc, first, idx[child + 1]);
                if (k2 > kc || (k2 == kc && idx[child + 1] > idx[child])) {
                    child++;
                    kc = k2;
                }
            }
            kr = rj__pin_key(sc, first, idx[root]);
            if (kr > kc || (kr == kc && idx[root] > idx[child]))
                break;
            {
                const int t = idx[root];
                idx[root] = idx[child];
                idx[child] = t;
            }
        }
    }
}

/* The rigid link a joint holds in a mixed scene (body2 when rigid, else body1). */
static int rj__pin_rigid(const rj_scene_def *sc, int j)
{
    const rj_joint_def *J = &sc->joints[j];
    return sc->links[J->body2].fidelity == RJ_LINK_RIGID ? J->body2 : J->body1;
}

/* Two rigid links may not share a pin through a flexible node in a mixed scene. The
   joints that hold a rigid link at a body1 node, sorted by (node, index): at each node the
   first names the rigid link there, and the earliest joint that names another is the
   error (as a scan of the joints in order would find it). Scratch: nl + nj ints. */
static int rj__validate_pins(const rj_scene_def *sc, int *first, int *idx, rj_error *err)
{
    char f[64];
    int i, j, end, n = 0, bad = -1, bad_first = -1;
    long nodes = 0;
    for (i = 0; i < sc->link_count; i++) {
        first[i] = (int) nodes;
        nodes += sc->links[i].elements + 1;
    }
    for (j = 0; j < sc->joint_count; j++) {
        const rj_joint_def *J = &sc->joints[j];
        if (J->body1 < 0)
            continue;
        if (sc->links[J->body1].fidelity == RJ_LINK_RIGID ||
            sc->links[J->body2].fidelity == RJ_LINK_RIGID)
            idx[n++] = j;
    }
    rj__sort_pins(sc, first, idx, n);
    for (i = 0; i < n; i = end) {
        const int head = idx[i];
        const long key = rj__pin_key(sc, first, head);
        for (end = i + 1; end < n && rj__pin_key(sc, first, idx[end]) == key; end++) {
            const int k = idx[end];
            if (bad >= 0 && k > bad)
                continue;
            if (rj__pin_rigid(sc, k) == rj__pin_rigid(sc, head))
                continue;
            bad = k;
            bad_first = head;
        }
    }
    if (bad < 0)
        return 1;
    RJ__FIELD(f, "joints[%d].body1", bad);
    rj__fail(err, RJ_ERR_INVALID, f, sc->joints[bad].body1,
             "%s = %d is invalid: joints %d and %d pin rigid links %d and %d at the same node in a "
             "scene with flexible links, which is not supported",
             f, sc->joints[bad].body1, bad_first, bad, rj__pin_rigid(sc, bad_first),
             rj__pin_rigid(sc, bad));
    return 0;
}

/* The checks of the joint graph, in time linear in the scene (n log n for the pins of
   mixed scenes), with scratch of 2 nl + nj ints (RJ__GRAPH_SCRATCH): a link hangs from one joint; in a scene of rigid links each
   hangs from a joint or is fixed; mixed scenes' pins (rj__validate_pins); the joints form
   a forest. */
static int rj__validate_graph(const rj_scene_def *sc, int *scratch, rj_error *err)
{
    const int nl = sc->link_count;
    int *parent = scratch, *mark = scratch + nl, *joints = scratch + 2 * (size_t) nl;
    char f[64];
    int i, j;
    for (i = 0; i < nl; i++)
        parent[i] = -1;
    /* a link hangs from its first joint as body2: parent[] holds it; a later joint with
       the same body2 closes a loop, with every part a tree joint has */
    for (j = 0; j < sc->joint_count; j++) {
        const int b2 = sc->joints[j].body2;
        if (parent[b2] < 0)
            parent[b2] = j;
    }
    if (rj__all_rigid(sc))
        for (i = 0; i < nl; i++)
            if (parent[i] < 0 && sc->links[i].root != RJ_ROOT_FIXED) {
                RJ__FIELD(f, "links[%d].root", i);
                rj__fail(err, RJ_ERR_INVALID, f, sc->links[i].root,
                         "%s = %d is invalid: in a scene of rigid links each must hang from a "
                         "joint or be RJ_ROOT_FIXED",
                         f, sc->links[i].root);
                return 0;
            }
    if (!rj__all_rigid(sc) && !rj__validate_pins(sc, mark, joints, err))
        return 0;
    /* the joint graph must be a forest: walking up from any link ends at a root. A walk
       marks its links 1 while under way and 2 once it is known to reach a root, so each
       link is walked once; meeting a 1 is a loop */
    for (i = 0; i < nl; i++)
        mark[i] = 0;
    for (i = 0; i < nl; i++) {
        int cur = i, top;
        while (cur >= 0 && mark[cur] == 0) {
            mark[cur] = 1;
            cur = rj__up(sc, parent, cur);
        }
        if (cur >= 0 && mark[cur] == 1) {
            RJ__FIELD(f, "links[%d]", i);
            rj__fail(err, RJ_ERR_INVALID, f, i,
                     "the joints that hang links from each other form a loop through link %d "
                     "that no joint holds to the ground or a fixed link",
                     i);
            return 0;
        }
        top = cur;
        for (cur = i; cur != top; cur = rj__up(sc, parent, cur))
            mark[cur] = 2;
    }
    return 1;
}

