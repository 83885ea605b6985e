/* ------------------------------------------------------------------ writer */
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

/* whether the writer can express the link: its enums in range and every number it writes
   finite. Fields the model ignores are not written, so anything in them is fine: width and
   layers of a general section, area and inertia of a rectangular one. */
static int rj__sw_link_ok(const rj_link_def *d)
{
    double v[14];
    int k, gen = d->section == RJ_SECTION_GENERAL;
    if (d->root < 0 || d->root > 3 || (d->section != RJ_SECTION_RECT && !gen) ||
        d->fidelity < RJ_LINK_FLEXIBLE || d->fidelity > RJ_LINK_INEXTENSIBLE)
        return 0;
    v[0] = d->length;
    v[1] = d->E;
    v[2] = d->rho;
    v[3] = d->height;
    v[4] = d->tip_mass;
    v[5] = d->tip_inertia;
    v[6] = d->x;
    v[7] = d->y;
    v[8] = d->angle;
    v[9] = d->vx;
    v[10] = d->vy;
    v[11] = d->omega;
    v[12] = gen ? d->area : d->width;
    v[13] = gen ? d->inertia : 0;
    for (k = 0; k < 14; k++)
        if (!rj__sw_finite(v[k]))
            return 0;
    return 1;
}

/* the same for a joint: ground_* are written only when body1 is ground, a limit's value
   only when it is enabled, table points only up to table_count */
static int rj__sw_joint_ok(const rj_joint_def *d, int link_count)
{
    double v[8];
    int k;
    if (d->body1 < -1 || d->body1 >= link_count || d->body2 < 0 || d->body2 >= link_count)
        return 0;
    if ((d->lock & ~1) || (d->has_forward & ~1) || (d->has_reverse & ~1) || d->table_count < 0 ||
        d->table_count > RJ_TABLE_MAX || d->method < 0 || d->method > 4 || d->release < 0 ||
        d->release > 1 || d->reference < 0 || d->reference > 1)
        return 0;
    v[0] = d->angle0;
    v[1] = d->rate0;
    v[2] = d->spring_k;
    v[3] = d->spring_free_angle;
    v[4] = d->penalty_k;
    v[5] = d->restitution;
    v[6] = d->damping;
    v[7] = d->friction;
    for (k = 0; k < 8; k++)
        if (!rj__sw_finite(v[k]))
            return 0;
    if (d->body1 < 0 && !(rj__sw_finite(d->ground_x) && rj__sw_finite(d->ground_y) &&
                          rj__sw_finite(d->ground_angle)))
        return 0;
    if ((d->has_forward && !rj__sw_finite(d->forward)) ||
        (d->has_reverse && !rj__sw_finite(d->reverse)))
        return 0;
    for (k = 0; k < d->table_count; k++)
        if (!rj__sw_finite(d->table_angle[k]) || !rj__sw_finite(d->table_torque[k]))
            return 0;
    return 1;
}

/* names and numbers first: rj_scene_write writes nothing for a scene it cannot write */
/* whether the writer can express the load: a link and node the scene has, finite
   numbers, a table of 0..RJ_TABLE_MAX points (its order is the model's to check) */
static int rj__sw_load_ok(const rj_load_def *d, const rj_scene_def *sc)
{
    int k;
    if (d->link < 0 || d->link >= sc->link_count || d->node < -1 ||
        d->node > sc->links[d->link].elements || (d->follower != 0 && d->follower != 1) ||
        d->table_count < 0 || d->table_count > RJ_TABLE_MAX)
        return 0;
    if (!rj__sw_finite(d->force[0]) || !rj__sw_finite(d->force[1]) || !rj__sw_finite(d->moment))
        return 0;
    for (k = 0; k < d->table_count; k++)
        if (!rj__sw_finite(d->table_time[k]) || !rj__sw_finite(d->table_factor[k]))
            return 0;
    return 1;
}

static int rj__sw_ok(const rj_scene_def *sc, const char *const *link_names,
                     const char *const *joint_names)
{
    const rj_solver_def *s = &sc->solver;
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
    if (!rj__sw_finite(s->dt) || !rj__sw_finite(s->energy_growth) ||
        !rj__sw_finite(s->gravity[0]) || !rj__sw_finite(s->gravity[1]) ||
        (s->allow_unstable != 0 && s->allow_unstable != 1) || s->energy_every < 1 ||
        s->energy_every > 1000 || s->in_place < RJ_IN_PLACE_AUTO || s->in_place > RJ_IN_PLACE_OFF)
        return 0;
    for (i = 0; i < sc->link_count; i++)
        if (!rj__sw_link_ok(&sc->links[i]))
            return 0;
    for (i = 0; i < sc->joint_count; i++)
        if (!rj__sw_joint_ok(&sc->joints[i], sc->link_count))
            return 0;
    for (i = 0; i < sc->load_count; i++)
        if (!rj__sw_load_ok(&sc->loads[i], sc))
            return 0;
    return 1;
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

/* the solver section, only when some value differs from the defaults */
static void rj__sw_solver(rj__sw *W, const rj_solver_def *s)
{
    rj_solver_def S0 = rj_default_solver_def();
    char nm[40];
    if (!rj__sw_set(s->dt, S0.dt) && !s->allow_unstable &&
        !rj__sw_set(s->energy_growth, S0.energy_growth) && s->energy_every == S0.energy_every &&
        s->in_place == S0.in_place && s->gravity[0] == 0 && s->gravity[1] == 0)
        return;
    rj__sw_put(W, "solver\n");
    if (rj__sw_set(s->dt, S0.dt)) {
        rj__sw_key(W, "dt");
        rj__sw_num(W, s->dt);
        rj__sw_put(W, "\n");
    }
    if (s->allow_unstable) {
        rj__sw_key(W, "allow_unstable");
        rj__sw_put(W, "yes\n");
    }
    if (rj__sw_set(s->energy_growth, S0.energy_growth)) {
        rj__sw_key(W, "energy_growth");
        rj__sw_num(W, s->energy_growth);
        rj__sw_put(W, "\n");
    }
    if (s->energy_every != S0.energy_every) {
        snprintf(nm, sizeof nm, "  energy_every = %d\n", s->energy_every);
        rj__sw_put(W, nm);
    }
    if (s->in_place != S0.in_place) {
        rj__sw_key(W, "in_place");
        rj__sw_put(W, rj__sk_in_place[s->in_place]);
        rj__sw_put(W, "\n");
    }
    if (s->gravity[0] != 0 || s->gravity[1] != 0) {
        rj__sw_key(W, "gravity");
        rj__sw_num(W, s->gravity[0]);
        rj__sw_put(W, " ");
        rj__sw_num(W, s->gravity[1]);
        rj__sw_put(W, "\n");
    }
}

/* a link section; root_link: the link hangs from no joint (else x, y, angle are unused) */
static void rj__sw_link(rj__sw *W, const rj_link_def *d, int root_link)
{
    rj_link_def L0 = rj_default_link_def();
    char nm[40];
    rj__sw_key(W, "length");
    rj__sw_num(W, d->length);
    snprintf(nm, sizeof nm, "  elements = %d\n", d->elements);
    rj__sw_put(W, nm);
    rj__sw_key(W, "E");
    rj__sw_num(W, d->E);
    rj__sw_put(W, "  rho = ");
    rj__sw_num(W, d->rho);
    rj__sw_put(W, "\n");
    if (d->section == RJ_SECTION_GENERAL) {
        rj__sw_key(W, "area");
        rj__sw_num(W, d->area);
        rj__sw_put(W, "  inertia = ");
        rj__sw_num(W, d->inertia);
        if (rj__sw_set(d->height, L0.height)) {
            rj__sw_put(W, "  height = ");
            rj__sw_num(W, d->height);
        }
    } else {
        rj__sw_key(W, "width");
        rj__sw_num(W, d->width);
        rj__sw_put(W, "  height = ");
        rj__sw_num(W, d->height);
        if (d->layers != L0.layers) {
            snprintf(nm, sizeof nm, "  layers = %d", d->layers);
            rj__sw_put(W, nm);
        }
    }
    rj__sw_put(W, "\n");
    if (rj__sw_set(d->tip_mass, 0) || rj__sw_set(d->tip_inertia, 0)) {
        rj__sw_key(W, "tip_mass");
        rj__sw_num(W, d->tip_mass);
        rj__sw_put(W, "  tip_inertia = ");
        rj__sw_num(W, d->tip_inertia);
        rj__sw_put(W, "\n");
    }
    if (d->root != L0.root) {
        rj__sw_key(W, "root");
        rj__sw_put(W, rj__sk_root[d->root]);
        rj__sw_put(W, "\n");
    }
    if (d->fidelity != L0.fidelity) {
        rj__sw_key(W, "fidelity");
        rj__sw_put(W, rj__sk_fidelity[d->fidelity]);
        rj__sw_put(W, "\n");
    }
    if (rj__sw_set(d->x, 0) || rj__sw_set(d->y, 0) || rj__sw_set(d->angle, 0)) {
        rj__sw_key(W, "x");
        rj__sw_num(W, d->x);
        rj__sw_put(W, "  y = ");
        rj__sw_num(W, d->y);
        rj__sw_put(W, "  angle = ");
        rj__sw_angle(W, d->angle, 0);
        rj__sw_put(W, root_link ? "\n" : "   # unused: the link hangs from a joint\n");
    }
    if (rj__sw_set(d->vx, 0) || rj__sw_set(d->vy, 0) || rj__sw_set(d->omega, 0)) {
        rj__sw_key(W, "vx");
        rj__sw_num(W, d->vx);
        rj__sw_put(W, "  vy = ");
        rj__sw_num(W, d->vy);
        rj__sw_put(W, "  omega = ");
        rj__sw_angle(W, d->omega, 1);
        rj__sw_put(W, "\n");
    }
}

/* a joint's table, four points to a line (a line ending in ',' continues) */
static void rj__sw_table(rj__sw *W, const rj_joint_def *d)
{
    int k;
    if (d->table_count <= 0)
        return;
    rj__sw_key(W, "table");
    for (k = 0; k < d->table_count; k++) {
        if (k)
            rj__sw_put(W, k % 4 == 0 ? ",\n    " : ", ");
        rj__sw_angle(W, d->table_angle[k], 0);
        rj__sw_put(W, " ");
        rj__sw_num(W, d->table_torque[k]);
    }
    rj__sw_put(W, "\n");
}

/* the keys after a joint's bodies */
static void rj__sw_joint_rest(rj__sw *W, const rj_joint_def *d)
{
    rj_joint_def J0 = rj_default_joint_def();
    rj__sw_key(W, "angle0");
    rj__sw_angle(W, d->angle0, 0);
    if (rj__sw_set(d->rate0, 0)) {
        rj__sw_put(W, "  rate0 = ");
        rj__sw_angle(W, d->rate0, 1);
    }
    rj__sw_put(W, "\n");
    rj__sw_table(W, d);
    if (rj__sw_set(d->spring_k, J0.spring_k) ||
        rj__sw_set(d->spring_free_angle, J0.spring_free_angle)) {
        rj__sw_key(W, "spring");
        rj__sw_num(W, d->spring_k);
        rj__sw_put(W, " ");
        rj__sw_angle(W, d->spring_free_angle, 0);
        rj__sw_put(W, "\n");
    }
    if (d->has_forward) {
        rj__sw_key(W, "forward");
        rj__sw_angle(W, d->forward, 0);
        rj__sw_put(W, "\n");
    }
    if (d->has_reverse) {
        rj__sw_key(W, "reverse");
        rj__sw_angle(W, d->reverse, 0);
        rj__sw_put(W, "\n");
    }
    if (d->lock) {
        rj__sw_key(W, "lock");
        rj__sw_put(W, "yes\n");
    }
    rj__sw_key(W, "method");
    rj__sw_put(W, rj__sk_method[d->method]);
    if (d->release != J0.release) {
        rj__sw_put(W, "  release = ");
        rj__sw_put(W, rj__sk_release[d->release]);
    }
    if (d->reference != J0.reference) {
        rj__sw_put(W, "  reference = ");
        rj__sw_put(W, rj__sk_reference[d->reference]);
    }
    rj__sw_put(W, "\n");
    if (rj__sw_set(d->penalty_k, 0)) {
        rj__sw_key(W, "penalty_k");
        rj__sw_num(W, d->penalty_k);
        rj__sw_put(W, "\n");
    }
    if (rj__sw_set(d->restitution, 0)) {
        rj__sw_key(W, "restitution");
        rj__sw_num(W, d->restitution);
        rj__sw_put(W, "\n");
    }
    if (rj__sw_set(d->damping, 0)) {
        rj__sw_key(W, "damping");
        rj__sw_num(W, d->damping);
        rj__sw_put(W, "\n");
    }
    if (rj__sw_set(d->friction, 0)) {
        rj__sw_key(W, "friction");
        rj__sw_num(W, d->friction);
        rj__sw_put(W, "\n");
    }
}

/* a joint section: bodies, node1 when body1 is a link, ground_* when it is ground */
static void rj__sw_joint(rj__sw *W, const rj_joint_def *d, const char *const *link_names)
{
    char nm[40];
    rj__sw_key(W, "body1");
    if (d->body1 < 0)
        rj__sw_put(W, "ground");
    else
        rj__sw_name(W, link_names, "link", d->body1);
    rj__sw_put(W, "  body2 = ");
    rj__sw_name(W, link_names, "link", d->body2);
    if (d->body1 >= 0 && d->node1 != -1) {
        snprintf(nm, sizeof nm, "  node1 = %d", d->node1);
        rj__sw_put(W, nm);
    }
    rj__sw_put(W, "\n");
    if (d->body1 < 0 && (rj__sw_set(d->ground_x, 0) || rj__sw_set(d->ground_y, 0) ||
                         rj__sw_set(d->ground_angle, 0))) {
        rj__sw_key(W, "ground_x");
        rj__sw_num(W, d->ground_x);
        rj__sw_put(W, "  ground_y = ");
        rj__sw_num(W, d->ground_y);
        rj__sw_put(W, "  ground_angle = ");
        rj__sw_angle(W, d->ground_angle, 0);
        rj__sw_put(W, "\n");
    }
    rj__sw_joint_rest(W, d);
}

/* a load section's keys: the link always, the others when they differ from the
   defaults (in their bits: -0.0 is written) */
static void rj__sw_load(rj__sw *W, const rj_load_def *d, const char *const *link_names)
{
    char nm[40];
    int k;
    rj__sw_key(W, "link");
    rj__sw_name(W, link_names, "link", d->link);
    if (d->node != -1) {
        snprintf(nm, sizeof nm, "  node = %d", d->node);
        rj__sw_put(W, nm);
    }
    rj__sw_put(W, "\n");
    if (rj__sw_set(d->force[0], 0) || rj__sw_set(d->force[1], 0)) {
        rj__sw_key(W, "force");
        rj__sw_num(W, d->force[0]);
        rj__sw_put(W, " ");
        rj__sw_num(W, d->force[1]);
        rj__sw_put(W, "\n");
    }
    if (rj__sw_set(d->moment, 0)) {
        rj__sw_key(W, "moment");
        rj__sw_num(W, d->moment);
        rj__sw_put(W, "\n");
    }
    if (d->follower)
        rj__sw_put(W, "  follower = yes\n");
    if (d->table_count <= 0)
        return;
    rj__sw_key(W, "table");
    for (k = 0; k < d->table_count; k++) {
        if (k)
            rj__sw_put(W, k % 4 == 0 ? ",\n    " : ", ");
        rj__sw_num(W, d->table_time[k]);
        rj__sw_put(W, " ");
        rj__sw_num(W, d->table_factor[k]);
    }
    rj__sw_put(W, "\n");
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
    int i, k;
    if (buf && size)
        buf[0] = 0;
    if (!sc || sc->link_count < 1 || sc->link_count > RJ_SCENE_MAX_LINKS || !sc->links ||
        sc->joint_count < 0 || sc->joint_count > RJ_SCENE_MAX_JOINTS ||
        (sc->joint_count && !sc->joints) || sc->load_count < 0 ||
        sc->load_count > RJ_SCENE_MAX_LOADS || (sc->load_count && !sc->loads))
        return 0;
    if (!rj__sw_ok(sc, link_names, joint_names))
        return 0;
    if (!rj__sw_title_ok(title))
        return 0;
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
        rj__sw_link(&W, &sc->links[i], root_link);
    }
    for (i = 0; i < sc->joint_count; i++) {
        rj__sw_put(&W, "joint ");
        rj__sw_name(&W, joint_names, "joint", i);
        rj__sw_put(&W, "\n");
        rj__sw_joint(&W, &sc->joints[i], link_names);
    }
    for (i = 0; i < sc->load_count; i++) {
        rj__sw_put(&W, "load ");
        rj__sw_name(&W, NULL, "load", i);
        rj__sw_put(&W, "\n");
        rj__sw_load(&W, &sc->loads[i], link_names);
    }
    return W.n;
}
#endif /* RJ_NO_SCENE_FILES */
