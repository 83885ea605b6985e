/* ------------------------------------------------------------------ writer
   It writes a scene definition, which has no place for the file's fidelity = pieces: a
   parsed file's links cut into pieces are written as the rigid links and bending joints
   they became (rj__sp_cut), and read back as the same scene. */
typedef struct rj__sw {
    char *buf;
    size_t size, n;
    char dp[8];
    int dplen;
} rj__sw;

static void rj__sw_put(rj__sw *W, const char *s)
{
    size_t k = strlen(s);
    if (W->n < W->size) {
        size_t room = W->size - 1 - W->n, c = k < room ? k : room;
        memcpy(W->buf + W->n, s, c);
        W->buf[W->n + c] = 0;
    }
    W->n += k;
}

/* text of v with '.' whatever the locale; returns whether it reads back as target
   (through rj_rad when deg) */
static int rj__sw_fmt(const rj__sw *W, double v, int fixed, int p, int deg, double target,
                      char *out, size_t size)
{
    char t[400];
    double back = 0;
    int k, o = 0, n = snprintf(t, sizeof t, fixed ? "%.*f" : "%.*g", p, v);
    if (n < 0 || n >= (int) sizeof t)
        n = 0;
    for (k = 0; k < n && o + 1 < (int) size;) {
        if (W->dp[0] != '.' && k + W->dplen <= n && memcmp(t + k, W->dp, (size_t) W->dplen) == 0) {
            out[o++] = '.';
            k += W->dplen;
        } else
            out[o++] = t[k++];
    }
    out[o] = 0;
    return k == n && rj__sp_strtonum(out, o, W->dp, W->dplen, &back) == 1 &&
           (deg ? rj_rad(back) : back) == target;
}

/* shortest text of v that reads back as target: %.Ng (N = 1..17) or, for moderate
   magnitudes, %.Nf (N = 0..17) when that is no longer; returns 0 when none reads back */
static int rj__sw_num_try(const rj__sw *W, double v, int deg, double target, char *out, size_t size)
{
    char g[64], f[64];
    int p, okg = 0, okf = 0;
    for (p = 1; p <= 17 && !okg; p++)
        okg = rj__sw_fmt(W, v, 0, p, deg, target, g, sizeof g);
    if (fabs(v) < 1e15)
        for (p = 0; p <= 17 && !okf; p++)
            okf = rj__sw_fmt(W, v, 1, p, deg, target, f, sizeof f);
    if (okf && (!okg || strlen(f) <= strlen(g))) {
        memcpy(out, f, strlen(f) + 1 < size ? strlen(f) + 1 : size);
        out[size - 1] = 0;
        return 1;
    }
    if (okg) {
        memcpy(out, g, strlen(g) + 1 < size ? strlen(g) + 1 : size);
        out[size - 1] = 0;
        return 1;
    }
    rj__sw_fmt(W, v, 0, 17, deg, target, out, size);
    return 0;
}

static void rj__sw_num(rj__sw *W, double v)
{
    char s[64];
    rj__sw_num_try(W, v, 0, v, s, sizeof s);
    rj__sw_put(W, s);
}

/* an angle in the shorter of its exact deg and rad forms ("90 deg", "-10 rad/s") */
static void rj__sw_angle(rj__sw *W, double v, int rate)
{
    char d[64], r[64];
    rj__sw_num_try(W, v, 0, v, r, sizeof r);
    if (rj__sw_num_try(W, rj_deg(v), 1, v, d, sizeof d) && strlen(d) <= strlen(r)) {
        rj__sw_put(W, d);
        rj__sw_put(W, rate ? " deg/s" : " deg");
        return;
    }
    rj__sw_put(W, r);
    rj__sw_put(W, rate ? " rad/s" : " rad");
}

static void rj__sw_key(rj__sw *W, const char *key)
{
    rj__sw_put(W, "  ");
    rj__sw_put(W, key);
    rj__sw_put(W, " = ");
}

static int rj__sw_finite(double v)
{
    return v - v == 0.0;
}

/* whether v differs from def in its bits, not only in value: -0.0 must be written (a
   ground pin at x = -0.0 puts -0.0 into the node positions), so it reads back as -0.0 */
static int rj__sw_set(double v, double def)
{
    return memcmp(&v, &def, sizeof v) != 0;
}

/* Row r of def differs from its default: in its bits for numbers (-0.0 is written), an
   enabled limit, a table with points; with the parts written after it (a spring's free
   angle). rows: its kind's table. */
static int rj__sw_row_set(const rj__field *rows, int n, int k, const void *def)
{
    const rj__field *r = &rows[k];
    int p;
    switch (r->type) {
    case RJ__FT_LIMIT:
    case RJ__FT_TABLE:
        return rj__row_int(def, r) != 0;
    case RJ__FT_VEC2:
        if (rj__sw_set(rj__row_real(def, r, 1), r->def))
            return 1;
        /* fall through */
    case RJ__FT_REAL:
    case RJ__FT_ANGLE:
    case RJ__FT_RATE:
        if (rj__sw_set(rj__row_real(def, r, 0), r->def))
            return 1;
        break;
    default:
        if (rj__row_int(def, r) != (int) r->def)
            return 1;
    }
    for (p = 0; p < n; p++)
        if (rows[p].part_of == k && rj__sw_set(rj__row_real(def, &rows[p], 0), rows[p].def))
            return 1;
    return 0;
}

/* What the writer knows of the item besides its rows. */
typedef struct rj__sw_item {
    int shape;                     /* a link's section shape, else -1 */
    int on_ground;                 /* a joint's body1 is ground */
    int root_link;                 /* a link no joint places */
    const char *const *link_names;  /* names of the scene's links, or NULL */
    const char *const *joint_names; /* names of the scene's joints, or NULL */
} rj__sw_item;

/* Whether the writer writes row k of def (its kind's rows, the first nk keys). */
static int rj__sw_wanted(const rj__field *rows, int n, int nk, int k, const void *def,
                         const rj__sw_item *it)
{
    const rj__field *r = &rows[k];
    int q;
    if (r->write == RJ__WR_NONE || r->type == RJ__FT_PART ||
        !rj__row_applies(r, it->shape, it->on_ground, 1))
        return 0;
    if (r->write == RJ__WR_ALWAYS)
        return 1;
    if (r->write == RJ__WR_SET)
        return rj__sw_row_set(rows, n, k, def);
    for (q = 0; q < nk; q++)
        if (rows[q].line == r->line && rows[q].write == RJ__WR_LINE &&
            rj__row_applies(&rows[q], it->shape, it->on_ground, 1) &&
            rj__sw_row_set(rows, n, q, def))
            return 1;
    return 0;
}

/* A table's pairs, four to a line (a line ending in ',' continues); the first column
   angles when the row says so (stride 1). */
static void rj__sw_pairs(rj__sw *W, const rj__field *r, const void *def)
{
    const double *first = (const double *) (const void *) ((const char *) def + r->aux);
    const int count = rj__row_int(def, r);
    int k;
    for (k = 0; k < count; k++) {
        if (k)
            rj__sw_put(W, k % 4 == 0 ? ",\n    " : ", ");
        if (r->stride == 1)
            rj__sw_angle(W, first[k], 0);
        else
            rj__sw_num(W, first[k]);
        rj__sw_put(W, " ");
        rj__sw_num(W, first[RJ_TABLE_MAX + k]);
    }
}

/* names[i], or prefix and i when the caller gave no names */
static void rj__sw_name(rj__sw *W, const char *const *names, const char *prefix, int i)
{
    char nm[40];
    if (names) {
        rj__sw_put(W, names[i]);
        return;
    }
    snprintf(nm, sizeof nm, "%s%d", prefix, i);
    rj__sw_put(W, nm);
}

/* A prescribed actuator's profile: its name and numbers ("cycloidal 90 deg 2"). */
static void rj__sw_profile(rj__sw *W, const rj_actuator_def *d)
{
    rj__sw_put(W, rj__sk_profile[d->profile]);
    if (d->profile == RJ_PROFILE_TABLE) /* its points are the table's */
        return;
    rj__sw_put(W, " ");
    rj__sw_angle(W, d->profile_value, d->profile != RJ_PROFILE_CYCLOIDAL);
    if (d->profile == RJ_PROFILE_RAMP)
        return;
    rj__sw_put(W, " ");
    rj__sw_num(W, d->profile_time);
}

/* The value of row r of def as a file says it. */
static void rj__sw_value(rj__sw *W, const rj__field *r, const void *def, const rj__sw_item *it)
{
    char nm[24];
    const int v = rj__row_is_real(r) || r->type == RJ__FT_TABLE ? 0 : rj__row_int(def, r);
    switch (r->type) {
    case RJ__FT_REAL:
        rj__sw_num(W, rj__row_real(def, r, 0));
        return;
    case RJ__FT_ANGLE:
    case RJ__FT_RATE:
    case RJ__FT_LIMIT:
        rj__sw_angle(W, rj__row_real(def, r, 0), r->type == RJ__FT_RATE);
        return;
    case RJ__FT_VEC2:
        rj__sw_num(W, rj__row_real(def, r, 0));
        rj__sw_put(W, " ");
        rj__sw_num(W, rj__row_real(def, r, 1));
        return;
    case RJ__FT_TABLE:
        rj__sw_pairs(W, r, def);
        return;
    case RJ__FT_ENUM:
        rj__sw_put(W, rj__names_of(r->names) + (size_t) r->stride * (size_t) v);
        return;
    case RJ__FT_BOOL:
        rj__sw_put(W, v ? "yes" : "no");
        return;
    case RJ__FT_LINK:
        if (v < 0)
            rj__sw_put(W, "ground");
        else
            rj__sw_name(W, it->link_names, "link", v);
        return;
    case RJ__FT_JOINT:
        rj__sw_name(W, it->joint_names, "joint", v);
        return;
    case RJ__FT_PROFILE:
        rj__sw_profile(W, (const rj_actuator_def *) def);
        return;
    case RJ__FT_NODE:
        if (v < 0) {
            rj__sw_put(W, "last");
            return;
        }
        snprintf(nm, sizeof nm, "%d", v);
        rj__sw_put(W, nm);
        return;
    default:
        snprintf(nm, sizeof nm, "%d", v);
        rj__sw_put(W, nm);
    }
}

/* The keys of an item of kind, in its rows' order, rows of one line number on one line:
   "  key = value  key = value"; the parts of a key after its value ("spring = k angle"). */
static void rj__sw_rows(rj__sw *W, int kind, const void *def, const rj__sw_item *it)
{
    int n, nk, k, p, line = -1, place = 0;
    const rj__field *rows = rj__fields(kind, &n);
    nk = rj__key_count(kind);
    for (k = 0; k < nk; k++) {
        const rj__field *r = &rows[k];
        if (!rj__sw_wanted(rows, n, nk, k, def, it))
            continue;
        if (line >= 0 && r->line != line) {
            rj__sw_put(W, place ? "   # unused: the link hangs from a joint\n" : "\n");
            place = 0;
        }
        line = r->line;
        place |= r->when == RJ__WHEN_PLACE && !it->root_link;
        rj__sw_key(W, r->key);
        rj__sw_value(W, r, def, it);
        for (p = nk; p < n; p++)
            if (rows[p].part_of == k && rows[p].type != RJ__FT_BOOL &&
                r->type != RJ__FT_PROFILE) {
                rj__sw_put(W, " ");
                rj__sw_value(W, &rows[p], def, it);
            }
    }
    if (line >= 0)
        rj__sw_put(W, place ? "   # unused: the link hangs from a joint\n" : "\n");
}

/* Whether the writer can express the item's rows that it would write: enums, yes/no and
   ints in range, tables of 0..RJ_TABLE_MAX points, numbers finite. Members the model
   ignores are not written, so anything in them is fine: width and layers of a general
   section, area and inertia of a rectangular one, a limit that is off, ground_* of a
   joint on a link. */
static int rj__sw_rows_ok(int kind, const void *def, int shape, int on_ground)
{
    int n, k, c;
    const rj__field *rows = rj__fields(kind, &n);
    for (k = 0; k < n; k++) {
        const rj__field *r = &rows[k];
        const int parts = r->type == RJ__FT_VEC2 ? 2 : 1;
        if (r->type == RJ__FT_PART || !rj__row_applies(r, shape, on_ground, 1))
            continue;
        if (r->type == RJ__FT_TABLE) {
            const double *first = (const double *) (const void *) ((const char *) def + r->aux);
            const int count = rj__row_int(def, r);
            if (count < 0 || count > RJ_TABLE_MAX)
                return 0;
            for (c = 0; c < count; c++)
                if (!rj__sw_finite(first[c]) || !rj__sw_finite(first[RJ_TABLE_MAX + c]))
                    return 0;
        } else if (r->type == RJ__FT_LIMIT) {
            if (rj__row_int(def, r) && !rj__sw_finite(rj__row_real(def, r, 0)))
                return 0;
        } else if (rj__row_is_real(r)) {
            for (c = 0; c < parts; c++)
                if (!rj__sw_finite(rj__row_real(def, r, c)))
                    return 0;
        } else if (r->type == RJ__FT_ENUM || r->type == RJ__FT_BOOL || r->type == RJ__FT_INT ||
                   r->type == RJ__FT_PROFILE) {
            const int v = rj__row_int(def, r);
            if (v < r->lo || v > r->hi)
                return 0;
        }
    }
    return 1;
}

/* names and numbers first: rj_scene_write writes nothing for a scene it cannot write */
static int rj__sw_ok(const rj_scene_def *sc, const char *const *link_names,
                     const char *const *joint_names)
{
    int i, k;
    for (k = 0; k < 2; k++) {
        const char *const *names = k ? joint_names : link_names;
        int n = k ? sc->joint_count : sc->link_count, a, b;
        if (!names)
            continue;
        for (a = 0; a < n; a++) {
            if (!names[a] || !rj__sp_name_ok(names[a], (int) strlen(names[a])))
                return 0;
            if (!k && strcmp(names[a], "ground") == 0)
                return 0;
            for (b = 0; b < a; b++)
                if (names[b] && strcmp(names[a], names[b]) == 0)
                    return 0;
        }
    }
    if (!rj__sw_rows_ok(RJ__DEF_SOLVER, &sc->solver, -1, 0))
        return 0;
    for (i = 0; i < sc->link_count; i++) {
        const rj_link_def *d = &sc->links[i];
        if (!rj__sw_rows_ok(RJ__DEF_LINK, d, d->section, 0))
            return 0;
    }
    for (i = 0; i < sc->joint_count; i++) {
        const rj_joint_def *d = &sc->joints[i];
        if (d->body1 < -1 || d->body1 >= sc->link_count || d->body2 < 0 ||
            d->body2 >= sc->link_count || !rj__sw_rows_ok(RJ__DEF_JOINT, d, -1, d->body1 < 0))
            return 0;
    }
    for (i = 0; i < sc->load_count; i++) {
        const rj_load_def *d = &sc->loads[i];
        if (d->link < 0 || d->link >= sc->link_count || d->node < -1 ||
            d->node > sc->links[d->link].elements || !rj__sw_rows_ok(RJ__DEF_LOAD, d, -1, 0))
            return 0;
    }
    for (i = 0; i < sc->actuator_count; i++) {
        const rj_actuator_def *d = &sc->actuators[i];
        if (d->joint < 0 || d->joint >= sc->joint_count ||
            !rj__sw_rows_ok(RJ__DEF_ACTUATOR, d, d->type, 0))
            return 0;
    }
    for (i = 0; i < sc->coupling_count; i++) {
        const rj_coupling_def *d = &sc->couplings[i];
        if (d->joint_a < 0 || d->joint_a >= sc->joint_count || d->joint_b < 0 ||
            d->joint_b >= sc->joint_count || !rj__sw_rows_ok(RJ__DEF_COUPLING, d, -1, 0))
            return 0;
    }
    return 1;
}

/* the solver section, only when some value differs from the defaults */
static void rj__sw_solver(rj__sw *W, const rj_solver_def *s)
{
    const rj__sw_item it = { -1, 0, 1, NULL, NULL };
    int k;
    for (k = 0; k < RJ__VF_N; k++)
        if (rj__sw_row_set(rj__solver_fields, RJ__VF_N, k, s))
            break;
    if (k == RJ__VF_N)
        return;
    rj__sw_put(W, "solver\n");
    rj__sw_rows(W, RJ__DEF_SOLVER, s, &it);
}

/* whether a file can hold title: shorter than RJ_SCENE_TITLE_MAX, no '"', no control byte
   (what rj__sp_title_value accepts); NULL is no title */
static int rj__sw_title_ok(const char *title)
{
    size_t n;
    if (!title)
        return 1;
    n = strlen(title);
    if (n >= RJ_SCENE_TITLE_MAX)
        return 0;
    if (memchr(title, '"', n))
        return 0;
    return rj__sp_title_bad(title, (int) n) < 0;
}

/* the title line, none for an empty title (which reads back as "" too) */
static void rj__sw_title(rj__sw *W, const char *title)
{
    if (!title || !title[0])
        return;
    rj__sw_put(W, "title = \"");
    rj__sw_put(W, title);
    rj__sw_put(W, "\"\n");
}

RJDEF size_t rj_scene_write(const rj_scene_def *sc, const char *const *link_names,
                            const char *const *joint_names, char *buf, size_t size)
{
    return rj_scene_write_ex(sc, link_names, joint_names, NULL, buf, size);
}

RJDEF size_t rj_scene_write_ex(const rj_scene_def *sc, const char *const *link_names,
                               const char *const *joint_names, const char *title, char *buf,
                               size_t size)
{
    rj__sw W;
    rj__sw_item item;
    int i, k;
    if (buf && size)
        buf[0] = 0;
    if (!sc || sc->link_count < 1 || sc->link_count > RJ_SCENE_MAX_LINKS || !sc->links ||
        sc->joint_count < 0 || sc->joint_count > RJ_SCENE_MAX_JOINTS ||
        (sc->joint_count && !sc->joints) || sc->load_count < 0 ||
        sc->load_count > RJ_SCENE_MAX_LOADS || (sc->load_count && !sc->loads) ||
        sc->actuator_count < 0 || sc->actuator_count > RJ_SCENE_MAX_ACTUATORS ||
        (sc->actuator_count && !sc->actuators) || sc->coupling_count < 0 ||
        sc->coupling_count > RJ_SCENE_MAX_COUPLINGS || (sc->coupling_count && !sc->couplings))
        return 0;
    if (!rj__sw_ok(sc, link_names, joint_names))
        return 0;
    if (!rj__sw_title_ok(title))
        return 0;
    item.link_names = link_names;
    item.joint_names = joint_names;
    W.buf = buf;
    W.size = buf ? size : 0;
    W.n = 0;
    rj__sp_locale(W.dp, &W.dplen);
    rj__sw_put(&W, "# revjoint scene (written by rj_scene_write, revjoint.h " RJ_VERSION ")\n");
    rj__sw_title(&W, title);
    rj__sw_solver(&W, &sc->solver);
    for (i = 0; i < sc->link_count; i++) {
        int root_link = 1;
        for (k = 0; k < sc->joint_count; k++)
            if (sc->joints[k].body2 == i)
                root_link = 0;
        rj__sw_put(&W, "link ");
        rj__sw_name(&W, link_names, "link", i);
        rj__sw_put(&W, "\n");
        item.shape = sc->links[i].section;
        item.on_ground = 0;
        item.root_link = root_link;
        rj__sw_rows(&W, RJ__DEF_LINK, &sc->links[i], &item);
    }
    for (i = 0; i < sc->joint_count; i++) {
        rj__sw_put(&W, "joint ");
        rj__sw_name(&W, joint_names, "joint", i);
        rj__sw_put(&W, "\n");
        item.shape = -1;
        item.on_ground = sc->joints[i].body1 < 0;
        item.root_link = 1;
        rj__sw_rows(&W, RJ__DEF_JOINT, &sc->joints[i], &item);
    }
    for (i = 0; i < sc->load_count; i++) {
        rj__sw_put(&W, "load ");
        rj__sw_name(&W, NULL, "load", i);
        rj__sw_put(&W, "\n");
        item.shape = -1;
        item.on_ground = 0;
        item.root_link = 1;
        rj__sw_rows(&W, RJ__DEF_LOAD, &sc->loads[i], &item);
    }
    for (i = 0; i < sc->actuator_count; i++) {
        rj__sw_put(&W, "actuator ");
        rj__sw_name(&W, NULL, "actuator", i);
        rj__sw_put(&W, "\n");
        item.shape = sc->actuators[i].type;
        rj__sw_rows(&W, RJ__DEF_ACTUATOR, &sc->actuators[i], &item);
    }
    for (i = 0; i < sc->coupling_count; i++) {
        rj__sw_put(&W, "coupling ");
        rj__sw_name(&W, NULL, "coupling", i);
        rj__sw_put(&W, "\n");
        item.shape = -1;
        rj__sw_rows(&W, RJ__DEF_COUPLING, &sc->couplings[i], &item);
    }
    return W.n;
}
#endif /* RJ_NO_SCENE_FILES */
