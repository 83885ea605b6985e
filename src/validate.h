/* ------------------------------------------------------------------ validation */
#define RJ__FIELD(buf, fmt, i) snprintf(buf, sizeof buf, fmt, i)

/* The largest values a definition may hold, with the one rule each states (validation and
   the scene parser say the same). Far beyond any material or mechanism, and small enough
   that what the step, the energy accounts and a checkpoint (whose values stay within
   1e100) compute from them stays within reach: a link of 1e6 m, 1e6 m deep, of 1e30 kg/m^3
   under 1e5 m/s^2 has a potential of about 1e65 J. */
#define RJ__RULE_E "must be in (0, 1e30] Pa"
#define RJ__RULE_RHO "must be in (0, 1e30] kg/m^3"
#define RJ__RULE_AREA "must be in (0, 1e12] m^2"
#define RJ__RULE_INERTIA "must be in (0, 1e24] m^4"
#define RJ__RULE_DEPTH "must be in [0, 1e6] m (> 0 for a rectangular section)"
#define RJ__RULE_TIP_MASS "must be in [0, 1e40] kg"
#define RJ__RULE_TIP_INERTIA "must be in [0, 1e50] kg m^2"
#define RJ__RULE_LENGTH "must be in (0, 1e6] m" /* a link's length, a section's width and height */
#define RJ__RULE_ANGLE "must be a finite angle within +-1e6 rad"
#define RJ__RULE_STIFFNESS "must be >= 0 N m/rad"
#define RJ__RULE_RESTITUTION "must be in [0, 1]"
#define RJ__RULE_DAMPING "must be >= 0 N m s/rad"
#define RJ__RULE_FRICTION "must be >= 0 N m"
#define RJ__RULE_DT "must be 0 (automatic) or a step in (0, 1] s"
#define RJ__RULE_GROWTH "must be > 1"
#define RJ__RULE_GRAVITY "each component must be a finite acceleration within +-1e5 m/s^2"
#define RJ__MAX_GRAVITY 1e5

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
             "%s = %d is invalid: need %d..100000 %ss and a %ss array", field, count, fewest, name,
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

/* A load's time table: 1..RJ_TABLE_MAX points, times finite and strictly increasing,
   within +-1e9 s, factors within +-1e6. */
static int rj__validate_load_table(const rj_load_def *d, int i, rj_error *err)
{
    char f[64];
    int k;
    if (d->table_count < 0 || d->table_count > RJ_TABLE_MAX) {
        RJ__FIELD(f, "loads[%d].table_count", i);
        rj__fail(err, RJ_ERR_INVALID, f, d->table_count,
                 "%s = %d is invalid: must be 0 (constant) or 1..%d points", f, d->table_count,
                 RJ_TABLE_MAX);
        return 0;
    }
    for (k = 0; k < d->table_count; k++) {
        snprintf(f, sizeof f, "loads[%d].table_time[%d]", i, k);
        if (!rj__check_num(err, f, d->table_time[k], -1e9, 1, 1e9, 1,
                           "must be a finite time within +-1e9 s (further than any run "
                           "reaches, where a step no longer resolves the table)"))
            return 0;
        if (k > 0 && !(d->table_time[k] > d->table_time[k - 1])) {
            rj__fail(err, RJ_ERR_INVALID, f, d->table_time[k],
                     "%s = %g is invalid: the table's times must increase strictly (the point "
                     "before is at %g s)",
                     f, d->table_time[k], d->table_time[k - 1]);
            return 0;
        }
        snprintf(f, sizeof f, "loads[%d].table_factor[%d]", i, k);
        if (!rj__check_num(err, f, d->table_factor[k], -1e6, 1, 1e6, 1,
                           "must be a finite factor within +-1e6"))
            return 0;
    }
    return 1;
}

/* Applied loads: a known link and node, finite force and moment, a table in time. */
static int rj__validate_loads(const rj_scene_def *sc, rj_error *err)
{
    char f[64];
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
        RJ__FIELD(f, "loads[%d].force[0]", i);
        if (!rj__check_num(err, f, d->force[0], -1e30, 1, 1e30, 1,
                           "must be a finite force within +-1e30 N"))
            return 0;
        RJ__FIELD(f, "loads[%d].force[1]", i);
        if (!rj__check_num(err, f, d->force[1], -1e30, 1, 1e30, 1,
                           "must be a finite force within +-1e30 N"))
            return 0;
        RJ__FIELD(f, "loads[%d].moment", i);
        if (!rj__check_num(err, f, d->moment, -1e30, 1, 1e30, 1,
                           "must be a finite moment within +-1e30 N m"))
            return 0;
        if (d->follower != 0 && d->follower != 1) {
            RJ__FIELD(f, "loads[%d].follower", i);
            rj__fail(err, RJ_ERR_INVALID, f, d->follower,
                     "%s = %d is invalid: must be 0 (global frame) or 1 (turns with the node)", f,
                     d->follower);
            return 0;
        }
        if (!rj__validate_load_table(d, i, err))
            return 0;
    }
    return 1;
}

static int rj__validate(const rj_scene_def *sc, rj_error *err)
{
    char f[64];
    int i, j;
    double inf = HUGE_VAL;
    if (!sc) {
        rj__fail(err, RJ_ERR_INVALID, "scene", 0, "scene is NULL");
        return 0;
    }
    if (!rj__check_array(err, "link", sc->link_count, 1, sc->links) ||
        !rj__check_array(err, "joint", sc->joint_count, 0, sc->joints))
        return 0;
    if (sc->solver.cookie != RJ__COOKIE_SOLVER) {
        rj__fail(err, RJ_ERR_INVALID, "solver", 0,
                 "solver was not initialised with rj_default_solver_def()");
        return 0;
    }
    if (!rj__check_num(err, "solver.dt", sc->solver.dt, 0, 1, 1.0, 1, RJ__RULE_DT))
        return 0;
    if (!rj__check_num(err, "solver.energy_growth", sc->solver.energy_growth, 1.0, 0, inf, 0,
                       RJ__RULE_GROWTH))
        return 0;
    if (sc->solver.in_place < RJ_IN_PLACE_AUTO || sc->solver.in_place > RJ_IN_PLACE_OFF) {
        rj__fail(err, RJ_ERR_INVALID, "solver.in_place", sc->solver.in_place,
                 "solver.in_place = %d is invalid: must be RJ_IN_PLACE_AUTO (0), RJ_IN_PLACE_ON "
                 "(1) or RJ_IN_PLACE_OFF (2)",
                 sc->solver.in_place);
        return 0;
    }
    if (sc->solver.energy_every < 1 || sc->solver.energy_every > 1000) {
        rj__fail(err, RJ_ERR_INVALID, "solver.energy_every", sc->solver.energy_every,
                 "solver.energy_every = %d is invalid: must be 1 .. 1000 steps",
                 sc->solver.energy_every);
        return 0;
    }
    if (!rj__check_num(err, "solver.gravity[0]", sc->solver.gravity[0], -RJ__MAX_GRAVITY, 1,
                       RJ__MAX_GRAVITY, 1, RJ__RULE_GRAVITY) ||
        !rj__check_num(err, "solver.gravity[1]", sc->solver.gravity[1], -RJ__MAX_GRAVITY, 1,
                       RJ__MAX_GRAVITY, 1, RJ__RULE_GRAVITY))
        return 0;
    if (sc->solver.allow_unstable != 0 && sc->solver.allow_unstable != 1) {
        rj__fail(err, RJ_ERR_INVALID, "solver.allow_unstable", sc->solver.allow_unstable,
                 "solver.allow_unstable = %d is invalid: must be 0 or 1",
                 sc->solver.allow_unstable);
        return 0;
    }
    for (i = 0; i < sc->link_count; i++) {
        const rj_link_def *L = &sc->links[i];
        if (!rj__check_cookie(err, "links[%d]", i, L->cookie, RJ__COOKIE_LINK,
                              "rj_default_link_def()"))
            return 0;
        RJ__FIELD(f, "links[%d].length", i);
        if (!rj__check_num(err, f, L->length, 0, 0, 1e6, 1, RJ__RULE_LENGTH))
            return 0;
        if (L->elements < 1 || L->elements > 1000000) {
            RJ__FIELD(f, "links[%d].elements", i);
            rj__fail(err, RJ_ERR_INVALID, f, L->elements, "%s = %d is invalid: must be 1..1000000",
                     f, L->elements);
            return 0;
        }
        RJ__FIELD(f, "links[%d].E", i);
        if (!rj__check_num(err, f, L->E, 0, 0, 1e30, 1, RJ__RULE_E))
            return 0;
        RJ__FIELD(f, "links[%d].rho", i);
        if (!rj__check_num(err, f, L->rho, 0, 0, 1e30, 1, RJ__RULE_RHO))
            return 0;
        if (L->section != RJ_SECTION_RECT && L->section != RJ_SECTION_GENERAL) {
            RJ__FIELD(f, "links[%d].section", i);
            rj__fail(err, RJ_ERR_INVALID, f, L->section,
                     "%s = %d is invalid: RJ_SECTION_RECT or RJ_SECTION_GENERAL", f, L->section);
            return 0;
        }
        if (L->section == RJ_SECTION_RECT) {
            RJ__FIELD(f, "links[%d].width", i);
            if (!rj__check_num(err, f, L->width, 0, 0, 1e6, 1, RJ__RULE_LENGTH))
                return 0;
            RJ__FIELD(f, "links[%d].height", i);
            if (!rj__check_num(err, f, L->height, 0, 0, 1e6, 1, RJ__RULE_LENGTH))
                return 0;
            if (L->layers < 1 || L->layers > 1000) {
                RJ__FIELD(f, "links[%d].layers", i);
                rj__fail(err, RJ_ERR_INVALID, f, L->layers, "%s = %d is invalid: must be 1..1000",
                         f, L->layers);
                return 0;
            }
        } else {
            RJ__FIELD(f, "links[%d].area", i);
            if (!rj__check_num(err, f, L->area, 0, 0, 1e12, 1, RJ__RULE_AREA))
                return 0;
            RJ__FIELD(f, "links[%d].inertia", i);
            if (!rj__check_num(err, f, L->inertia, 0, 0, 1e24, 1, RJ__RULE_INERTIA))
                return 0;
            RJ__FIELD(f, "links[%d].height", i);
            if (!rj__check_num(err, f, L->height, 0, 1, 1e6, 1, RJ__RULE_DEPTH))
                return 0;
        }
        RJ__FIELD(f, "links[%d].tip_mass", i);
        if (!rj__check_num(err, f, L->tip_mass, 0, 1, 1e40, 1, RJ__RULE_TIP_MASS))
            return 0;
        RJ__FIELD(f, "links[%d].tip_inertia", i);
        if (!rj__check_num(err, f, L->tip_inertia, 0, 1, 1e50, 1, RJ__RULE_TIP_INERTIA))
            return 0;
        if (L->root < RJ_ROOT_FREE || L->root > RJ_ROOT_FIXED) {
            RJ__FIELD(f, "links[%d].root", i);
            rj__fail(err, RJ_ERR_INVALID, f, L->root,
                     "%s = %d is invalid: RJ_ROOT_FREE, _PINNED, _CLAMPED or _FIXED", f, L->root);
            return 0;
        }
        RJ__FIELD(f, "links[%d].x", i);
        if (!rj__check_num(err, f, L->x, -inf, 0, inf, 0, "must be finite"))
            return 0;
        RJ__FIELD(f, "links[%d].y", i);
        if (!rj__check_num(err, f, L->y, -inf, 0, inf, 0, "must be finite"))
            return 0;
        /* within 1e6 rad, as angle0: beyond it a rotation of 1e-7 rad (the stability bound's
           finite differences) falls below what the angle's double resolves */
        RJ__FIELD(f, "links[%d].angle", i);
        if (!rj__check_num(err, f, L->angle, -1e6, 1, 1e6, 1,
                           "must be a finite angle within 1e6 rad"))
            return 0;
        RJ__FIELD(f, "links[%d].vx", i);
        if (!rj__check_num(err, f, L->vx, -inf, 0, inf, 0, "must be finite"))
            return 0;
        RJ__FIELD(f, "links[%d].vy", i);
        if (!rj__check_num(err, f, L->vy, -inf, 0, inf, 0, "must be finite"))
            return 0;
        RJ__FIELD(f, "links[%d].omega", i);
        if (!rj__check_num(err, f, L->omega, -inf, 0, inf, 0, "must be finite"))
            return 0;
    }
    for (j = 0; j < sc->joint_count; j++) {
        const rj_joint_def *J = &sc->joints[j];
        int k;
        if (!rj__check_cookie(err, "joints[%d]", j, J->cookie, RJ__COOKIE_JOINT,
                              "rj_default_joint_def()"))
            return 0;
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
        if (sc->links[J->body2].root != RJ_ROOT_FREE) {
            RJ__FIELD(f, "links[%d].root", J->body2);
            rj__fail(
                err, RJ_ERR_INVALID, f, sc->links[J->body2].root,
                "%s = %d is invalid: link %d is body2 of joint %d, its root must be RJ_ROOT_FREE",
                f, sc->links[J->body2].root, J->body2, j);
            return 0;
        }
        RJ__FIELD(f, "joints[%d].ground_x", j);
        if (!rj__check_num(err, f, J->ground_x, -inf, 0, inf, 0, "must be finite"))
            return 0;
        RJ__FIELD(f, "joints[%d].ground_y", j);
        if (!rj__check_num(err, f, J->ground_y, -inf, 0, inf, 0, "must be finite"))
            return 0;
        RJ__FIELD(f, "joints[%d].ground_angle", j);
        if (!rj__check_num(err, f, J->ground_angle, -inf, 0, inf, 0, "must be finite"))
            return 0;
        RJ__FIELD(f, "joints[%d].angle0", j);
        if (!rj__check_num(err, f, J->angle0, -1e6, 1, 1e6, 1, RJ__RULE_ANGLE))
            return 0;
        RJ__FIELD(f, "joints[%d].rate0", j);
        if (!rj__check_num(err, f, J->rate0, -inf, 0, inf, 0, "must be finite"))
            return 0;
        if (J->table_count != 0 && (J->table_count < 2 || J->table_count > RJ_TABLE_MAX)) {
            RJ__FIELD(f, "joints[%d].table_count", j);
            rj__fail(err, RJ_ERR_INVALID, f, J->table_count,
                     "%s = %d is invalid: 0, or 2..%d points", f, J->table_count, RJ_TABLE_MAX);
            return 0;
        }
        for (k = 0; k < J->table_count; k++) {
            char g[64];
            snprintf(g, sizeof g, "joints[%d].table_angle[%d]", j, k);
            if (!rj__check_num(err, g, J->table_angle[k], 0, 1, RJ__TWO_PI, 1,
                               "must be in [0, 2 pi] rad"))
                return 0;
            snprintf(g, sizeof g, "joints[%d].table_torque[%d]", j, k);
            if (!rj__check_num(err, g, J->table_torque[k], -inf, 0, inf, 0, "must be finite"))
                return 0;
        }
        RJ__FIELD(f, "joints[%d].spring_k", j);
        if (!rj__check_num(err, f, J->spring_k, 0, 1, inf, 0, RJ__RULE_STIFFNESS))
            return 0;
        RJ__FIELD(f, "joints[%d].spring_free_angle", j);
        if (!rj__check_num(err, f, J->spring_free_angle, -1e6, 1, 1e6, 1, RJ__RULE_ANGLE))
            return 0;
        if (J->has_forward != 0 && J->has_forward != 1) {
            RJ__FIELD(f, "joints[%d].has_forward", j);
            rj__fail(err, RJ_ERR_INVALID, f, J->has_forward, "%s = %d is invalid: 0 or 1", f,
                     J->has_forward);
            return 0;
        }
        if (J->has_reverse != 0 && J->has_reverse != 1) {
            RJ__FIELD(f, "joints[%d].has_reverse", j);
            rj__fail(err, RJ_ERR_INVALID, f, J->has_reverse, "%s = %d is invalid: 0 or 1", f,
                     J->has_reverse);
            return 0;
        }
        if (J->lock != 0 && J->lock != 1) {
            RJ__FIELD(f, "joints[%d].lock", j);
            rj__fail(err, RJ_ERR_INVALID, f, J->lock, "%s = %d is invalid: 0 or 1", f, J->lock);
            return 0;
        }
        RJ__FIELD(f, "joints[%d].forward", j);
        if (!rj__check_num(err, f, J->forward, 0, 1, RJ__TWO_PI, 0,
                           "a limit must be in [0, 2 pi) rad"))
            return 0;
        RJ__FIELD(f, "joints[%d].reverse", j);
        if (!rj__check_num(err, f, J->reverse, 0, 1, RJ__TWO_PI, 0,
                           "a limit must be in [0, 2 pi) rad"))
            return 0;
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
        if (J->method < RJ_METHOD_PENALTY || J->method > RJ_METHOD_ENERGY) {
            RJ__FIELD(f, "joints[%d].method", j);
            rj__fail(err, RJ_ERR_INVALID, f, J->method,
                     "%s = %d is invalid: one of RJ_METHOD_PENALTY..RJ_METHOD_ENERGY", f,
                     J->method);
            return 0;
        }
        if (J->release != RJ_RELEASE_RC12 && J->release != RJ_RELEASE_RC13) {
            RJ__FIELD(f, "joints[%d].release", j);
            rj__fail(err, RJ_ERR_INVALID, f, J->release,
                     "%s = %d is invalid: RJ_RELEASE_RC12 or RJ_RELEASE_RC13", f, J->release);
            return 0;
        }
        RJ__FIELD(f, "joints[%d].penalty_k", j);
        if (!rj__check_num(err, f, J->penalty_k, 0, 1, inf, 0, RJ__RULE_STIFFNESS))
            return 0;
        if (J->method == RJ_METHOD_PENALTY && (J->has_forward || J->has_reverse) &&
            !(J->penalty_k > 0)) {
            rj__fail(err, RJ_ERR_INVALID, f, J->penalty_k,
                     "%s = %g is invalid: RJ_METHOD_PENALTY with a limit needs a stiffness > 0", f,
                     J->penalty_k);
            return 0;
        }
        RJ__FIELD(f, "joints[%d].restitution", j);
        if (!rj__check_num(err, f, J->restitution, 0, 1, 1, 1, RJ__RULE_RESTITUTION))
            return 0;
        RJ__FIELD(f, "joints[%d].damping", j);
        if (!rj__check_num(err, f, J->damping, 0, 1, inf, 0, RJ__RULE_DAMPING))
            return 0;
        RJ__FIELD(f, "joints[%d].friction", j);
        if (!rj__check_num(err, f, J->friction, 0, 1, inf, 0, RJ__RULE_FRICTION))
            return 0;
        if (J->reference != RJ_REF_TANGENT && J->reference != RJ_REF_CHORD) {
            RJ__FIELD(f, "joints[%d].reference", j);
            rj__fail(err, RJ_ERR_INVALID, f, J->reference,
                     "%s = %d is invalid: RJ_REF_TANGENT or RJ_REF_CHORD", f, J->reference);
            return 0;
        }
    }
    for (i = 0; i < sc->link_count; i++) {
        const rj_link_def *L = &sc->links[i];
        if (L->fidelity != RJ_LINK_FLEXIBLE && L->fidelity != RJ_LINK_RIGID &&
            L->fidelity != RJ_LINK_INEXTENSIBLE) {
            RJ__FIELD(f, "links[%d].fidelity", i);
            rj__fail(err, RJ_ERR_INVALID, f, L->fidelity,
                     "%s = %d is invalid: RJ_LINK_FLEXIBLE, RJ_LINK_RIGID or RJ_LINK_INEXTENSIBLE",
                     f, L->fidelity);
            return 0;
        }
    }
    /* mixed scenes: a rigid link is one rigid body, with flexible links pinned to it */
    if (!rj__all_rigid(sc))
        for (j = 0; j < sc->joint_count; j++) {
            const rj_joint_def *J = &sc->joints[j];
            const int r1 = J->body1 >= 0 && sc->links[J->body1].fidelity == RJ_LINK_RIGID,
                      r2 = sc->links[J->body2].fidelity == RJ_LINK_RIGID;
            if (r1 && r2) {
                RJ__FIELD(f, "joints[%d].body2", j);
                rj__fail(err, RJ_ERR_INVALID, f, J->body2,
                         "%s = %d is invalid: joint %d pins two rigid links (%d and %d) in a scene "
                         "with flexible links, which is not supported: make every link rigid, or "
                         "one of the two flexible",
                         f, J->body2, j, J->body1, J->body2);
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
    if (rj__all_rigid(sc))
        for (j = 0; j < sc->joint_count; j++)
            if (sc->joints[j].method == RJ_METHOD_ENERGY) {
                RJ__FIELD(f, "joints[%d].method", j);
                rj__fail(err, RJ_ERR_INVALID, f, RJ_METHOD_ENERGY,
                         "%s = RJ_METHOD_ENERGY is not available for rigid links (use momentum "
                         "with e = 0, forced or adaptive)",
                         f);
                return 0;
            }
    return rj__validate_loads(sc, err);
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
    /* a link hangs from one joint: parent[] holds the joint it hangs from */
    for (j = 0; j < sc->joint_count; j++) {
        const int b2 = sc->joints[j].body2;
        if (parent[b2] >= 0) {
            RJ__FIELD(f, "joints[%d].body2", j);
            rj__fail(err, RJ_ERR_INVALID, f, b2,
                     "%s = %d is invalid: link %d is already body2 of joint %d (a link hangs from "
                     "one joint)",
                     f, b2, b2, parent[b2]);
            return 0;
        }
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
            rj__fail(
                err, RJ_ERR_INVALID, f, i,
                "joints form a closed loop through link %d; only chains and trees are supported",
                i);
            return 0;
        }
        top = cur;
        for (cur = i; cur != top; cur = rj__up(sc, parent, cur))
            mark[cur] = 2;
    }
    return 1;
}

