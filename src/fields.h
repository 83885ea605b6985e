/* ------------------------------------------------------------------ definition fields */
/* Every member of a definition (rj_link_def, rj_joint_def, rj_solver_def, rj_load_def,
   rj_actuator_def, rj_coupling_def) is one row of its kind's table below: its scene key,
   unit, kind of value, default, range with the one sentence that states it, when it
   applies, how the writer puts it in a scene file, and where it enters the model's hash. The defaults (rj_default_*_def),
   validation (rj__validate), the scene parser, the scene writer and the model hash read
   these rows; docs/scene-format.md's key table is checked against them (tests/keys.py).
   Rules that tie members together (a lock needs a limit, a body is a link the scene has)
   are code, grouped by concept in validate.h.

   Row k of a table, for k below the kind's key count (RJ__LK_N, RJ__JK_N, RJ__VK_N,
   RJ__AK_N), is the scene key k, in the order the enums below give. Members that no key
   sets alone follow: a member derived from other keys (a link's section shape) and the
   second parts of keys that take two (a spring's free angle, a limit's on/off flag). */

/* keys; index 0 of an item's position array is its section line, key k is at 1 + k */
enum {
    RJ__LK_LENGTH,
    RJ__LK_ELEMENTS,
    RJ__LK_MATERIAL,
    RJ__LK_SECTION,
    RJ__LK_E,
    RJ__LK_RHO,
    RJ__LK_AREA,
    RJ__LK_INERTIA,
    RJ__LK_WIDTH,
    RJ__LK_HEIGHT,
    RJ__LK_LAYERS,
    RJ__LK_TIP_MASS,
    RJ__LK_TIP_INERTIA,
    RJ__LK_ROOT,
    RJ__LK_X,
    RJ__LK_Y,
    RJ__LK_ANGLE,
    RJ__LK_VX,
    RJ__LK_VY,
    RJ__LK_OMEGA,
    RJ__LK_FIDELITY,
    RJ__LK_ETA,
    RJ__LK_DAMPING,
    RJ__LK_MASS_DAMPING,
    RJ__LK_YIELD,
    RJ__LK_HARDENING,
    RJ__LK_STRAIN,
    RJ__LK_N,
    RJ__LF_SHAPE = RJ__LK_N, /* members no key sets alone */
    RJ__LF_N
};
enum {
    RJ__JK_BODY1,
    RJ__JK_BODY2,
    RJ__JK_NODE1,
    RJ__JK_NODE2,
    RJ__JK_GROUND_X,
    RJ__JK_GROUND_Y,
    RJ__JK_GROUND_ANGLE,
    RJ__JK_ANGLE0,
    RJ__JK_RATE0,
    RJ__JK_TABLE,
    RJ__JK_SPRING,
    RJ__JK_FORWARD,
    RJ__JK_REVERSE,
    RJ__JK_LOCK,
    RJ__JK_METHOD,
    RJ__JK_RELEASE,
    RJ__JK_PENALTY_K,
    RJ__JK_RESTITUTION,
    RJ__JK_DAMPING,
    RJ__JK_FRICTION,
    RJ__JK_REFERENCE,
    RJ__JK_N,
    RJ__JF_FREE_ANGLE = RJ__JK_N,
    RJ__JF_HAS_FORWARD,
    RJ__JF_HAS_REVERSE,
    RJ__JF_N
};
enum {
    RJ__AK_LINK,
    RJ__AK_NODE,
    RJ__AK_FORCE,
    RJ__AK_MOMENT,
    RJ__AK_TABLE,
    RJ__AK_FOLLOWER,
    RJ__AK_N,
    RJ__AF_N = RJ__AK_N
};
enum {
    RJ__CK_JOINT,
    RJ__CK_TYPE,
    RJ__CK_TORQUE,
    RJ__CK_TABLE,
    RJ__CK_STALL_TORQUE,
    RJ__CK_NO_LOAD_SPEED,
    RJ__CK_CUTOFF,
    RJ__CK_KP,
    RJ__CK_KD,
    RJ__CK_TORQUE_MAX,
    RJ__CK_TARGET,
    RJ__CK_PROFILE,
    RJ__CK_START,
    RJ__CK_ROTOR_INERTIA,
    RJ__CK_GEAR_RATIO,
    RJ__CK_N,
    RJ__CF_HAS_CUTOFF = RJ__CK_N,
    RJ__CF_PROFILE_VALUE,
    RJ__CF_PROFILE_TIME,
    RJ__CF_N
};
enum {
    RJ__PK_JOINTS,
    RJ__PK_RATIO,
    RJ__PK_OFFSET,
    RJ__PK_STIFFNESS,
    RJ__PK_DAMPING,
    RJ__PK_EXACT,
    RJ__PK_N,
    RJ__PF_JOINT_B = RJ__PK_N,
    RJ__PF_N
};
enum {
    RJ__VK_DT,
    RJ__VK_ALLOW_UNSTABLE,
    RJ__VK_ENERGY_GROWTH,
    RJ__VK_ENERGY_EVERY,
    RJ__VK_IN_PLACE,
    RJ__VK_GRAVITY,
    RJ__VK_N,
    RJ__VF_N = RJ__VK_N
};

/* What a row holds, and so how it is read, checked and written. */
enum {
    RJ__FT_REAL,  /* a number, SI */
    RJ__FT_ANGLE, /* rad; a file may say deg */
    RJ__FT_RATE,  /* rad/s; a file may say deg/s */
    RJ__FT_INT,   /* an int in [lo, hi] */
    RJ__FT_ENUM,  /* an int 0 .. count - 1 named by names in files */
    RJ__FT_BOOL,  /* an int 0 or 1: no / yes in files */
    RJ__FT_VEC2,  /* two numbers (x, y), each in the range */
    RJ__FT_LINK,  /* an int: a link of the scene (a joint's body1 may be -1, ground) */
    RJ__FT_JOINT, /* an int: a joint of the scene */
    RJ__FT_NODE,  /* an int: a node of a link, -1 its last ("last" in files) */
    RJ__FT_TABLE, /* an int count, then two arrays of RJ_TABLE_MAX doubles from aux */
    RJ__FT_LIMIT, /* an angle in [lo, hi), on when the int at aux is 1 ("none" when off) */
    RJ__FT_PART,  /* no member: a file names a material or section to take values from */
    RJ__FT_PROFILE, /* an enum (rj_profile) and its numbers, its parts ("ramp 0.5 rad/s") */
    RJ__FT_N
};

/* When a row is checked and written: always, or only for one variant of its item (a
   link's section shape, an actuator's type); GROUND and ON_LINK rows are checked always
   and written only for a joint on ground or on a link. */
enum {
    RJ__WHEN_ALL,
    RJ__WHEN_RECT,
    RJ__WHEN_GENERAL,
    RJ__WHEN_TORQUE,
    RJ__WHEN_DC,
    RJ__WHEN_SERVO,
    RJ__WHEN_PRESCRIBED,
    RJ__WHEN_PROFILED, /* a servo's or a prescribed joint's profile */
    RJ__WHEN_TABLED,   /* a torque's table, or a profile's */
    RJ__WHEN_GROUND,
    RJ__WHEN_ON_LINK,
    RJ__WHEN_PLACE /* a link's placement: with a note when a joint places the link */
};

/* How the writer puts a row in a file: always; when it differs from its default in its
   bits (-0.0 is written); with its line (when any row of the line differs); or not at
   all (a part of another key, written with it). Rows of one line number follow each
   other and share a line. */
enum { RJ__WR_ALWAYS, RJ__WR_SET, RJ__WR_LINE, RJ__WR_NONE };

/* The enum names a row may point to (rj__names_of): none, or one of the rj__sk_* lists. */
enum {
    RJ__NM_NONE,
    RJ__NM_ROOT,
    RJ__NM_FIDELITY,
    RJ__NM_SHAPE,
    RJ__NM_METHOD,
    RJ__NM_RELEASE,
    RJ__NM_REFERENCE,
    RJ__NM_IN_PLACE,
    RJ__NM_ACTUATOR,
    RJ__NM_PROFILE,
    RJ__NM_STRAIN
};

/* A row is read-only data without relocations (char arrays and a names index, no
   pointers), so the tables sit in .rodata. */
typedef struct rj__field {
    char key[20];    /* the scene key; for a member that no key sets alone, its C name */
    char member[20]; /* the C member in messages ("length", "gravity"); "" for PART */
    char unit[12];   /* SI unit, "" none */
    int offset;         /* of the member in its definition; -1 for PART */
    int aux;            /* TABLE: the first array's offset; LIMIT: the flag's; else -1 */
    unsigned char type; /* RJ__FT_* */
    unsigned char when; /* RJ__WHEN_* */
    unsigned char write, line; /* RJ__WR_*, line number among the item's lines */
    signed char hash_at;       /* its place in the model hash, -1 not hashed */
    char hash_as;              /* 'd' as a double, 'i' as an int, 'z' only when not default */
    int part_of;               /* the key row this member is a second part of, else -1 */
    double def;                /* the default (VEC2: of both) */
    double lo, hi;              /* the range (ENUM: 0 .. count - 1) */
    unsigned char lo_in, hi_in; /* whether the range includes its ends */
    char rule[80]; /* the sentence a value outside the range gets (a C++ build refuses a
                      longer literal: the header's check compiles it so) */
    unsigned char names;        /* ENUM, PROFILE: RJ__NM_* of its count names, stride apart */
    unsigned char stride, count;
} rj__field;

/* The sentences of rules that several rows share. */
#define RJ__RULE_LENGTH "must be in (0, 1e6] m" /* a link's length, a section's width */
#define RJ__RULE_ANGLE "must be a finite angle within +-1e6 rad"
#define RJ__RULE_STIFFNESS "must be >= 0 N m/rad"
#define RJ__RULE_FINITE "must be finite"
#define RJ__RULE_LIMIT "a limit must be in [0, 2 pi) rad, [0, 360) deg"
#define RJ__RULE_BOOL "0 or 1"

/* enum names in files, in the enums' order: char arrays, not pointer arrays (read-only
   data without relocations) */
static const char rj__sk_in_place[3][5] = { "auto", "on", "off" };
static const char rj__sk_root[4][8] = { "free", "pinned", "clamped", "fixed" };
static const char rj__sk_fidelity[3][13] = { "flexible", "rigid", "inextensible" };
static const char rj__sk_method[5][9] = { "penalty", "adaptive", "momentum", "forced", "energy" };
static const char rj__sk_release[2][5] = { "rc12", "rc13" };
static const char rj__sk_reference[2][8] = { "tangent", "chord" };
static const char rj__sk_shape[2][8] = { "rect", "general" };
static const char rj__sk_actuator[4][11] = { "torque", "dc", "servo", "prescribed" };
static const char rj__sk_profile[4][10] = { "ramp", "cycloidal", "spinup", "table" };
static const char rj__sk_strain[2][6] = { "green", "biot" };

#define RJ__NAMES(id, a) id, (unsigned char) sizeof a[0], (unsigned char) (sizeof a / sizeof a[0])
#define RJ__NO_NAMES RJ__NM_NONE, 0, 0
#define RJ__OFF(T, m) (int) offsetof(T, m)


/* Range columns: lo, whether lo is in, hi, whether hi is in. */
#define RJ__R(lo, lo_in, hi, hi_in) lo, hi, lo_in, hi_in
#define RJ__ANY RJ__R(-HUGE_VAL, 0, HUGE_VAL, 0)

/* A row of member m of the definition RJ__DEF: key, unit, type, when, write, line, hash
   place and form, default, range and its sentence. */
#define RJ__F(key, m, unit, type, when, wr, line, hat, has, def, range, rule)                 \
    {                                                                                         \
        key, #m, unit, RJ__OFF(RJ__DEF, m), -1, type, when, wr, line, hat, has, -1, def,      \
            range, rule, RJ__NO_NAMES                                                         \
    }
/* An enum member's row: its names in files; validation's sentence names its C values. */
#define RJ__FE(key, m, id, names, wr, line, hat, has, def, rule)                              \
    {                                                                                         \
        key, #m, "", RJ__OFF(RJ__DEF, m), -1, RJ__FT_ENUM, RJ__WHEN_ALL, wr, line, hat, has,  \
            -1, def, RJ__R(0.0, 1, (double) (sizeof names / sizeof names[0]) - 1, 1), rule,   \
            RJ__NAMES(id, names)                                                              \
    }
/* A row with an aux offset (TABLE, LIMIT) or one that is a part of key row part_of. */
#define RJ__FA(key, m, unit, type, aux, part_of, wr, line, hat, has, def, range, rule, st)      \
    {                                                                                         \
        key, #m, unit, RJ__OFF(RJ__DEF, m), aux, type, RJ__WHEN_ALL, wr, line, hat, has,      \
            part_of, def, range, rule, RJ__NM_NONE, st, 0                                     \
    }
/* A key that names a material or a section (no member). */
#define RJ__FPART(key)                                                                        \
    {                                                                                         \
        key, "", "", -1, -1, RJ__FT_PART, RJ__WHEN_ALL, RJ__WR_NONE, 0, -1, 'd', -1, 0.0,     \
            RJ__ANY, "", RJ__NO_NAMES                                                         \
    }

#define RJ__DEF rj_link_def
static const rj__field rj__link_fields[RJ__LF_N] = {
    RJ__F("length", length, "m", RJ__FT_REAL, RJ__WHEN_ALL, RJ__WR_ALWAYS, 1, 0, 'd', 1.0,
          RJ__R(0.0, 0, 1e6, 1), RJ__RULE_LENGTH),
    RJ__F("elements", elements, "", RJ__FT_INT, RJ__WHEN_ALL, RJ__WR_ALWAYS, 1, 15, 'd', 10.0,
          RJ__R(1.0, 1, 1e6, 1), "must be 1..1000000"),
    RJ__FPART("material"),
    RJ__FPART("section"),
    RJ__F("E", E, "Pa", RJ__FT_REAL, RJ__WHEN_ALL, RJ__WR_ALWAYS, 2, 1, 'd', 70e9,
          RJ__R(0.0, 0, 1e30, 1), "must be in (0, 1e30] Pa"),
    RJ__F("rho", rho, "kg/m^3", RJ__FT_REAL, RJ__WHEN_ALL, RJ__WR_ALWAYS, 2, 2, 'd', 2710.0,
          RJ__R(0.0, 0, 1e30, 1), "must be in (0, 1e30] kg/m^3"),
    RJ__F("area", area, "m^2", RJ__FT_REAL, RJ__WHEN_GENERAL, RJ__WR_ALWAYS, 3, 5, 'd', 0.0,
          RJ__R(0.0, 0, 1e12, 1), "must be in (0, 1e12] m^2"),
    RJ__F("inertia", inertia, "m^4", RJ__FT_REAL, RJ__WHEN_GENERAL, RJ__WR_ALWAYS, 3, 6, 'd',
          0.0, RJ__R(0.0, 0, 1e24, 1), "must be in (0, 1e24] m^4"),
    RJ__F("width", width, "m", RJ__FT_REAL, RJ__WHEN_RECT, RJ__WR_ALWAYS, 3, 3, 'd', 0.05,
          RJ__R(0.0, 0, 1e6, 1), RJ__RULE_LENGTH),
    /* the in-plane depth; a general section's drawn thickness (> 0 for a rectangle: a
       rule of the section's shape) */
    RJ__F("height", height, "m", RJ__FT_REAL, RJ__WHEN_ALL, RJ__WR_ALWAYS, 3, 4, 'd', 0.2,
          RJ__R(0.0, 1, 1e6, 1), "must be in [0, 1e6] m (> 0 for a rectangular section)"),
    RJ__F("layers", layers, "", RJ__FT_INT, RJ__WHEN_RECT, RJ__WR_SET, 3, 17, 'd', 1.0,
          RJ__R(1.0, 1, 1000.0, 1), "must be 1..1000"),
    RJ__F("tip_mass", tip_mass, "kg", RJ__FT_REAL, RJ__WHEN_ALL, RJ__WR_LINE, 4, 7, 'd', 0.0,
          RJ__R(0.0, 1, 1e40, 1), "must be in [0, 1e40] kg"),
    RJ__F("tip_inertia", tip_inertia, "kg m^2", RJ__FT_REAL, RJ__WHEN_ALL, RJ__WR_LINE, 4, 8,
          'd', 0.0, RJ__R(0.0, 1, 1e50, 1), "must be in [0, 1e50] kg m^2"),
    RJ__FE("root", root, RJ__NM_ROOT, rj__sk_root, RJ__WR_SET, 5, 18, 'd', 0.0,
           "RJ_ROOT_FREE, _PINNED, _CLAMPED or _FIXED"),
    RJ__F("x", x, "m", RJ__FT_REAL, RJ__WHEN_PLACE, RJ__WR_LINE, 6, 9, 'd', 0.0, RJ__ANY,
          RJ__RULE_FINITE),
    RJ__F("y", y, "m", RJ__FT_REAL, RJ__WHEN_PLACE, RJ__WR_LINE, 6, 10, 'd', 0.0, RJ__ANY,
          RJ__RULE_FINITE),
    /* within 1e6 rad, as angle0: beyond it a rotation of 1e-7 rad (the stability bound's
       finite differences) falls below what the angle's double resolves */
    RJ__F("angle", angle, "rad", RJ__FT_ANGLE, RJ__WHEN_PLACE, RJ__WR_LINE, 6, 11, 'd', 0.0,
          RJ__R(-1e6, 1, 1e6, 1), RJ__RULE_ANGLE),
    RJ__F("vx", vx, "m/s", RJ__FT_REAL, RJ__WHEN_ALL, RJ__WR_LINE, 7, 12, 'd', 0.0, RJ__ANY,
          RJ__RULE_FINITE),
    RJ__F("vy", vy, "m/s", RJ__FT_REAL, RJ__WHEN_ALL, RJ__WR_LINE, 7, 13, 'd', 0.0, RJ__ANY,
          RJ__RULE_FINITE),
    RJ__F("omega", omega, "rad/s", RJ__FT_RATE, RJ__WHEN_ALL, RJ__WR_LINE, 7, 14, 'd', 0.0,
          RJ__ANY, RJ__RULE_FINITE),
    RJ__FE("fidelity", fidelity, RJ__NM_FIDELITY, rj__sk_fidelity, RJ__WR_SET, 8, 19, 'i', 0.0,
           "RJ_LINK_FLEXIBLE, RJ_LINK_RIGID or RJ_LINK_INEXTENSIBLE"),
    /* structural damping: hashed only when set, so scenes without it keep their hash */
    RJ__F("eta", eta, "s", RJ__FT_REAL, RJ__WHEN_ALL, RJ__WR_SET, 9, 20, 'z', 0.0,
          RJ__R(0.0, 1, 1e6, 1), "must be in [0, 1e6] s"),
    RJ__F("damping", damping, "", RJ__FT_VEC2, RJ__WHEN_ALL, RJ__WR_SET, 9, 21, 'z', 0.0,
          RJ__R(0.0, 1, 1e9, 1), "a ratio and a frequency in Hz, each in [0, 1e9]"),
    RJ__F("mass_damping", mass_damping, "1/s", RJ__FT_REAL, RJ__WHEN_ALL, RJ__WR_SET, 9, 22,
          'z', 0.0, RJ__R(0.0, 1, 1e9, 1), "must be in [0, 1e9] 1/s"),
    /* elastic-plastic layers and the axial law: hashed only when set too */
    RJ__F("yield", yield, "Pa", RJ__FT_REAL, RJ__WHEN_ALL, RJ__WR_SET, 10, 24, 'z', 0.0,
          RJ__R(0.0, 1, 1e30, 1), "must be in [0, 1e30] Pa (0: elastic)"),
    RJ__F("hardening", hardening, "Pa", RJ__FT_REAL, RJ__WHEN_ALL, RJ__WR_SET, 10, 25, 'z', 0.0,
          RJ__R(0.0, 1, 1e30, 1), "must be in [0, 1e30] Pa"),
    RJ__FE("strain", strain, RJ__NM_STRAIN, rj__sk_strain, RJ__WR_SET, 10, 26, 'z', 0.0,
           "RJ_STRAIN_GREEN or RJ_STRAIN_BIOT"),
    /* derived: area and inertia in a file make a general section */
    RJ__FE("section", section, RJ__NM_SHAPE, rj__sk_shape, RJ__WR_NONE, 0, 16, 'd', 0.0,
           "RJ_SECTION_RECT or RJ_SECTION_GENERAL"),
};
#undef RJ__DEF

#define RJ__DEF rj_joint_def
static const rj__field rj__joint_fields[RJ__JF_N] = {
    RJ__F("body1", body1, "", RJ__FT_LINK, RJ__WHEN_ALL, RJ__WR_ALWAYS, 1, 0, 'd', -1.0,
          RJ__ANY, ""),
    RJ__F("body2", body2, "", RJ__FT_LINK, RJ__WHEN_ALL, RJ__WR_ALWAYS, 1, 2, 'd', 0.0, RJ__ANY,
          ""),
    RJ__F("node1", node1, "", RJ__FT_NODE, RJ__WHEN_ON_LINK, RJ__WR_SET, 1, 1, 'd', -1.0,
          RJ__ANY, ""),
    /* hashed only when set: every scene before it pins node 0 and keeps its hash */
    RJ__F("node2", node2, "", RJ__FT_NODE, RJ__WHEN_ALL, RJ__WR_SET, 1, 23, 'z', 0.0,
          RJ__ANY, ""),
    RJ__F("ground_x", ground_x, "m", RJ__FT_REAL, RJ__WHEN_GROUND, RJ__WR_LINE, 2, 3, 'd', 0.0,
          RJ__ANY, RJ__RULE_FINITE),
    RJ__F("ground_y", ground_y, "m", RJ__FT_REAL, RJ__WHEN_GROUND, RJ__WR_LINE, 2, 4, 'd', 0.0,
          RJ__ANY, RJ__RULE_FINITE),
    RJ__F("ground_angle", ground_angle, "rad", RJ__FT_ANGLE, RJ__WHEN_GROUND, RJ__WR_LINE, 2, 5,
          'd', 0.0, RJ__ANY, RJ__RULE_FINITE),
    RJ__F("angle0", angle0, "rad", RJ__FT_ANGLE, RJ__WHEN_ALL, RJ__WR_ALWAYS, 3, 6, 'd', RJ__PI,
          RJ__R(-1e6, 1, 1e6, 1), RJ__RULE_ANGLE),
    RJ__F("rate0", rate0, "rad/s", RJ__FT_RATE, RJ__WHEN_ALL, RJ__WR_SET, 3, 7, 'd', 0.0,
          RJ__ANY, RJ__RULE_FINITE),
    /* angle torque pairs (Eq 4); first column angles (stride 1) */
    RJ__FA("table", table_count, "N m", RJ__FT_TABLE, RJ__OFF(rj_joint_def, table_angle), -1,
           RJ__WR_SET, 4, 22, 'i', 0.0, RJ__R(2.0, 1, RJ_TABLE_MAX, 1), "", 1),
    RJ__FA("spring", spring_k, "N m/rad", RJ__FT_REAL, -1, -1, RJ__WR_LINE, 5, 8, 'd', 0.0,
           RJ__R(0.0, 1, HUGE_VAL, 0), RJ__RULE_STIFFNESS, 0),
    RJ__FA("forward", forward, "rad", RJ__FT_LIMIT, RJ__OFF(rj_joint_def, has_forward), -1,
           RJ__WR_SET, 6, 11, 'd', 0.0, RJ__R(0.0, 1, RJ__TWO_PI, 0), RJ__RULE_LIMIT, 0),
    RJ__FA("reverse", reverse, "rad", RJ__FT_LIMIT, RJ__OFF(rj_joint_def, has_reverse), -1,
           RJ__WR_SET, 7, 13, 'd', 0.0, RJ__R(0.0, 1, RJ__TWO_PI, 0), RJ__RULE_LIMIT, 0),
    RJ__F("lock", lock, "", RJ__FT_BOOL, RJ__WHEN_ALL, RJ__WR_SET, 8, 14, 'd', 0.0,
          RJ__R(0.0, 1, 1.0, 1), RJ__RULE_BOOL),
    RJ__FE("method", method, RJ__NM_METHOD, rj__sk_method,
           RJ__WR_ALWAYS, 9, 15, 'd', RJ_METHOD_ADAPTIVE,
           "one of RJ_METHOD_PENALTY..RJ_METHOD_ENERGY"),
    RJ__FE("release", release, RJ__NM_RELEASE, rj__sk_release,
           RJ__WR_SET, 9, 16, 'd', RJ_RELEASE_RC13,
           "RJ_RELEASE_RC12 or RJ_RELEASE_RC13"),
    RJ__F("penalty_k", penalty_k, "N m/rad", RJ__FT_REAL, RJ__WHEN_ALL, RJ__WR_SET, 10, 17, 'd',
          0.0, RJ__R(0.0, 1, HUGE_VAL, 0), RJ__RULE_STIFFNESS),
    RJ__F("restitution", restitution, "", RJ__FT_REAL, RJ__WHEN_ALL, RJ__WR_SET, 11, 18, 'd',
          0.0, RJ__R(0.0, 1, 1.0, 1), "must be in [0, 1]"),
    RJ__F("damping", damping, "N m s/rad", RJ__FT_REAL, RJ__WHEN_ALL, RJ__WR_SET, 12, 19, 'd',
          0.0, RJ__R(0.0, 1, HUGE_VAL, 0), "must be >= 0 N m s/rad"),
    RJ__F("friction", friction, "N m", RJ__FT_REAL, RJ__WHEN_ALL, RJ__WR_SET, 13, 20, 'd', 0.0,
          RJ__R(0.0, 1, HUGE_VAL, 0), "must be >= 0 N m"),
    RJ__FE("reference", reference, RJ__NM_REFERENCE, rj__sk_reference, RJ__WR_SET, 14, 21, 'i', 0.0,
           "RJ_REF_TANGENT or RJ_REF_CHORD"),
    /* second parts: spring = k angle; a limit's on/off */
    RJ__FA("spring_free_angle", spring_free_angle, "rad", RJ__FT_ANGLE, -1, RJ__JK_SPRING,
           RJ__WR_NONE, 5, 9, 'd', RJ__PI, RJ__R(-1e6, 1, 1e6, 1), RJ__RULE_ANGLE, 0),
    RJ__FA("has_forward", has_forward, "", RJ__FT_BOOL, -1, RJ__JK_FORWARD, RJ__WR_NONE, 6, 10,
           'd', 0.0, RJ__R(0.0, 1, 1.0, 1), RJ__RULE_BOOL, 0),
    RJ__FA("has_reverse", has_reverse, "", RJ__FT_BOOL, -1, RJ__JK_REVERSE, RJ__WR_NONE, 7, 12,
           'd', 0.0, RJ__R(0.0, 1, 1.0, 1), RJ__RULE_BOOL, 0),
};
#undef RJ__DEF

#define RJ__DEF rj_solver_def
static const rj__field rj__solver_fields[RJ__VF_N] = {
    RJ__F("dt", dt, "s", RJ__FT_REAL, RJ__WHEN_ALL, RJ__WR_SET, 1, -1, 'd', 0.0,
          RJ__R(0.0, 1, 1.0, 1), "must be 0 (automatic) or a step in (0, 1] s"),
    RJ__F("allow_unstable", allow_unstable, "", RJ__FT_BOOL, RJ__WHEN_ALL, RJ__WR_SET, 2, -1,
          'd', 0.0, RJ__R(0.0, 1, 1.0, 1), "must be 0 or 1"),
    RJ__F("energy_growth", energy_growth, "", RJ__FT_REAL, RJ__WHEN_ALL, RJ__WR_SET, 3, -1, 'd',
          10.0, RJ__R(1.0, 0, HUGE_VAL, 0), "must be > 1"),
    RJ__F("energy_every", energy_every, "", RJ__FT_INT, RJ__WHEN_ALL, RJ__WR_SET, 4, -1, 'd',
          1.0, RJ__R(1.0, 1, 1000.0, 1), "must be 1..1000 steps"),
    RJ__FE("in_place", in_place, RJ__NM_IN_PLACE, rj__sk_in_place,
           RJ__WR_SET, 5, -1, 'd', RJ_IN_PLACE_AUTO,
           "must be RJ_IN_PLACE_AUTO (0), RJ_IN_PLACE_ON (1) or RJ_IN_PLACE_OFF (2)"),
    RJ__F("gravity", gravity, "m/s^2", RJ__FT_VEC2, RJ__WHEN_ALL, RJ__WR_SET, 6, 0, 'd', 0.0,
          RJ__R(-1e5, 1, 1e5, 1),
          "each component must be a finite acceleration within +-1e5 m/s^2"),
};
#undef RJ__DEF

#define RJ__DEF rj_load_def
static const rj__field rj__load_fields[RJ__AF_N] = {
    RJ__F("link", link, "", RJ__FT_LINK, RJ__WHEN_ALL, RJ__WR_ALWAYS, 1, 0, 'i', 0.0, RJ__ANY,
          ""),
    RJ__F("node", node, "", RJ__FT_NODE, RJ__WHEN_ALL, RJ__WR_SET, 1, 1, 'i', -1.0, RJ__ANY, ""),
    RJ__F("force", force, "N", RJ__FT_VEC2, RJ__WHEN_ALL, RJ__WR_SET, 2, 2, 'd', 0.0,
          RJ__R(-1e30, 1, 1e30, 1), "must be a finite force within +-1e30 N"),
    RJ__F("moment", moment, "N m", RJ__FT_REAL, RJ__WHEN_ALL, RJ__WR_SET, 3, 3, 'd', 0.0,
          RJ__R(-1e30, 1, 1e30, 1), "must be a finite moment within +-1e30 N m"),
    /* time factor pairs */
    RJ__FA("table", table_count, "", RJ__FT_TABLE, RJ__OFF(rj_load_def, table_time), -1,
           RJ__WR_SET, 4, 5, 'i', 0.0, RJ__R(1.0, 1, RJ_TABLE_MAX, 1), "", 0),
    RJ__F("follower", follower, "", RJ__FT_BOOL, RJ__WHEN_ALL, RJ__WR_SET, 5, 4, 'i', 0.0,
          RJ__R(0.0, 1, 1.0, 1), "must be 0 (global frame) or 1 (turns with the node)"),
};
#undef RJ__DEF

/* A row of an actuator's member m that applies to one type (when). */
#define RJ__FC(key, m, unit, type, when, wr, line, hat, def, range, rule)                     \
    {                                                                                         \
        key, #m, unit, RJ__OFF(RJ__DEF, m), -1, type, when, wr, line, hat, 'd', -1, def,      \
            range, rule, RJ__NO_NAMES                                                         \
    }

#define RJ__DEF rj_actuator_def
static const rj__field rj__actuator_fields[RJ__CF_N] = {
    RJ__F("joint", joint, "", RJ__FT_JOINT, RJ__WHEN_ALL, RJ__WR_ALWAYS, 1, 0, 'i', 0.0,
          RJ__ANY, ""),
    RJ__FE("type", type, RJ__NM_ACTUATOR, rj__sk_actuator,
           RJ__WR_ALWAYS, 1, 1, 'i', RJ_ACTUATOR_TORQUE,
           "RJ_ACTUATOR_TORQUE, _DC, _SERVO or _PRESCRIBED"),
    RJ__FC("torque", torque, "N m", RJ__FT_REAL, RJ__WHEN_TORQUE, RJ__WR_ALWAYS, 2, 2, 0.0,
           RJ__R(-1e30, 1, 1e30, 1), "must be a finite torque within +-1e30 N m"),
    /* time factor pairs, as a load's */
    { "table", "table_count", "", RJ__OFF(rj_actuator_def, table_count),
      RJ__OFF(rj_actuator_def, table_time), RJ__FT_TABLE, RJ__WHEN_TABLED, RJ__WR_SET, 3, 3,
      'i', -1, 0.0, RJ__R(1.0, 1, RJ_TABLE_MAX, 1), "", RJ__NM_NONE, 0, 0 },
    RJ__FC("stall_torque", stall_torque, "N m", RJ__FT_REAL, RJ__WHEN_DC, RJ__WR_ALWAYS, 4, 4,
           0.0, RJ__R(-1e30, 1, 1e30, 1), "must be a finite torque within +-1e30 N m"),
    RJ__FC("no_load_speed", no_load_speed, "rad/s", RJ__FT_RATE, RJ__WHEN_DC, RJ__WR_ALWAYS, 4,
           5, 1.0, RJ__R(-1e6, 1, 1e6, 1),
           "must be a rate within +-1e6 rad/s, not 0, of the stall torque's sign"),
    { "cutoff", "cutoff", "rad", RJ__OFF(rj_actuator_def, cutoff),
      RJ__OFF(rj_actuator_def, has_cutoff), RJ__FT_LIMIT, RJ__WHEN_DC, RJ__WR_SET, 5, 7, 'd', -1,
      0.0, RJ__R(0.0, 1, RJ__TWO_PI, 0), "a cutoff must be in [0, 2 pi) rad, [0, 360) deg",
      RJ__NM_NONE, 0, 0 },
    RJ__FC("kp", kp, "N m/rad", RJ__FT_REAL, RJ__WHEN_SERVO, RJ__WR_ALWAYS, 6, 8, 0.0,
           RJ__R(0.0, 1, 1e30, 1), "must be in [0, 1e30] N m/rad"),
    RJ__FC("kd", kd, "N m s/rad", RJ__FT_REAL, RJ__WHEN_SERVO, RJ__WR_ALWAYS, 6, 9, 0.0,
           RJ__R(0.0, 1, 1e30, 1), "must be in [0, 1e30] N m s/rad"),
    RJ__FC("torque_max", torque_max, "N m", RJ__FT_REAL, RJ__WHEN_SERVO, RJ__WR_SET, 7, 10, 0.0,
           RJ__R(0.0, 1, 1e30, 1), "must be in [0, 1e30] N m (0: no bound)"),
    RJ__FC("target", target, "rad", RJ__FT_ANGLE, RJ__WHEN_SERVO, RJ__WR_ALWAYS, 8, 11, RJ__PI,
           RJ__R(-1e6, 1, 1e6, 1), RJ__RULE_ANGLE),
    /* ramp RATE, cycloidal ANGLE DURATION, spinup OMEGA TS */
    { "profile", "profile", "", RJ__OFF(rj_actuator_def, profile), -1, RJ__FT_PROFILE,
      RJ__WHEN_PROFILED, RJ__WR_SET, 9, 12, 'i', -1, 0.0, RJ__R(0.0, 1, 3.0, 1),
      "RJ_PROFILE_RAMP, _CYCLOIDAL, _SPINUP or _TABLE", RJ__NAMES(RJ__NM_PROFILE, rj__sk_profile) },
    RJ__FC("start", start, "s", RJ__FT_REAL, RJ__WHEN_PROFILED, RJ__WR_SET, 9, 15, 0.0,
           RJ__R(-1e9, 1, 1e9, 1), "must be a finite time within +-1e9 s"),
    /* the rotor behind its gear, for every type */
    RJ__FC("rotor_inertia", rotor_inertia, "kg m^2", RJ__FT_REAL, RJ__WHEN_ALL, RJ__WR_LINE, 10,
           16, 0.0, RJ__R(0.0, 1, 1e30, 1), "must be in [0, 1e30] kg m^2"),
    RJ__FC("gear_ratio", gear_ratio, "", RJ__FT_REAL, RJ__WHEN_ALL, RJ__WR_LINE, 10, 17, 1.0,
           RJ__R(-1e6, 1, 1e6, 1), "must be a finite ratio within +-1e6, not 0"),
    /* the cutoff's on/off */
    { "has_cutoff", "has_cutoff", "", RJ__OFF(rj_actuator_def, has_cutoff), -1, RJ__FT_BOOL,
      RJ__WHEN_DC, RJ__WR_NONE, 5, 6, 'i', RJ__CK_CUTOFF, 0.0, RJ__R(0.0, 1, 1.0, 1),
      RJ__RULE_BOOL, RJ__NM_NONE, 0, 0 },
    /* the profile's numbers */
    { "profile_value", "profile_value", "", RJ__OFF(rj_actuator_def, profile_value), -1,
      RJ__FT_REAL, RJ__WHEN_PROFILED, RJ__WR_NONE, 9, 13, 'd', RJ__CK_PROFILE, 0.0,
      RJ__R(-1e6, 1, 1e6, 1), "must be a finite rate or angle within +-1e6 (rad/s or rad)",
      RJ__NM_NONE, 0, 0 },
    { "profile_time", "profile_time", "s", RJ__OFF(rj_actuator_def, profile_time), -1,
      RJ__FT_REAL, RJ__WHEN_PROFILED, RJ__WR_NONE, 9, 14, 'd', RJ__CK_PROFILE, 1.0,
      RJ__R(0.0, 0, 1e9, 1), "must be a time in (0, 1e9] s", RJ__NM_NONE, 0, 0 },
};
#undef RJ__DEF

#define RJ__DEF rj_coupling_def
static const rj__field rj__coupling_fields[RJ__PF_N] = {
    /* joints = A B: joint_a, then its part joint_b */
    RJ__F("joints", joint_a, "", RJ__FT_JOINT, RJ__WHEN_ALL, RJ__WR_ALWAYS, 1, 0, 'i', 0.0,
          RJ__ANY, ""),
    RJ__F("ratio", ratio, "", RJ__FT_REAL, RJ__WHEN_ALL, RJ__WR_SET, 2, 2, 'd', 1.0,
          RJ__R(-1e6, 1, 1e6, 1), "must be a finite ratio within +-1e6"),
    RJ__F("offset", offset, "rad", RJ__FT_ANGLE, RJ__WHEN_ALL, RJ__WR_SET, 2, 3, 'd', 0.0,
          RJ__R(-1e6, 1, 1e6, 1), RJ__RULE_ANGLE),
    RJ__F("stiffness", stiffness, "N m/rad", RJ__FT_REAL, RJ__WHEN_ALL, RJ__WR_ALWAYS, 3, 4, 'd',
          0.0, RJ__R(0.0, 1, 1e30, 1), "must be in [0, 1e30] N m/rad"),
    RJ__F("damping", damping, "N m s/rad", RJ__FT_REAL, RJ__WHEN_ALL, RJ__WR_SET, 3, 5, 'd', 0.0,
          RJ__R(0.0, 1, 1e30, 1), "must be in [0, 1e30] N m s/rad"),
    RJ__F("exact", exact, "", RJ__FT_BOOL, RJ__WHEN_ALL, RJ__WR_SET, 4, 6, 'i', 0.0,
          RJ__R(0.0, 1, 1.0, 1), "must be 0 (a cable) or 1 (a constraint)"),
    RJ__FA("joint_b", joint_b, "", RJ__FT_JOINT, -1, RJ__PK_JOINTS, RJ__WR_NONE, 1, 1, 'i', 1.0,
           RJ__ANY, "", 0),
};
#undef RJ__DEF

/* ------------------------------------------------------------------ reading rows */
/* The enum names of a row (its names index): count names, stride bytes apart. */
static const char *rj__names_of(int id)
{
    switch (id) {
    case RJ__NM_ROOT:
        return rj__sk_root[0];
    case RJ__NM_FIDELITY:
        return rj__sk_fidelity[0];
    case RJ__NM_SHAPE:
        return rj__sk_shape[0];
    case RJ__NM_METHOD:
        return rj__sk_method[0];
    case RJ__NM_RELEASE:
        return rj__sk_release[0];
    case RJ__NM_REFERENCE:
        return rj__sk_reference[0];
    case RJ__NM_IN_PLACE:
        return rj__sk_in_place[0];
    case RJ__NM_ACTUATOR:
        return rj__sk_actuator[0];
    case RJ__NM_PROFILE:
        return rj__sk_profile[0];
    case RJ__NM_STRAIN:
        return rj__sk_strain[0];
    default:
        return "";
    }
}

/* The definition kinds, and each one's table. */
enum {
    RJ__DEF_LINK,
    RJ__DEF_JOINT,
    RJ__DEF_SOLVER,
    RJ__DEF_LOAD,
    RJ__DEF_ACTUATOR,
    RJ__DEF_COUPLING
};

static const rj__field *rj__fields(int kind, int *count)
{
    switch (kind) {
    case RJ__DEF_LINK:
        *count = RJ__LF_N;
        return rj__link_fields;
    case RJ__DEF_JOINT:
        *count = RJ__JF_N;
        return rj__joint_fields;
    case RJ__DEF_SOLVER:
        *count = RJ__VF_N;
        return rj__solver_fields;
    case RJ__DEF_LOAD:
        *count = RJ__AF_N;
        return rj__load_fields;
    case RJ__DEF_ACTUATOR:
        *count = RJ__CF_N;
        return rj__actuator_fields;
    default:
        *count = RJ__PF_N;
        return rj__coupling_fields;
    }
}

/* How many of kind's rows are scene keys (the first ones). */
static int rj__key_count(int kind)
{
    switch (kind) {
    case RJ__DEF_LINK:
        return RJ__LK_N;
    case RJ__DEF_JOINT:
        return RJ__JK_N;
    case RJ__DEF_SOLVER:
        return RJ__VK_N;
    case RJ__DEF_LOAD:
        return RJ__AK_N;
    case RJ__DEF_ACTUATOR:
        return RJ__CK_N;
    default:
        return RJ__PK_N;
    }
}

/* The double at row r of def (VEC2: component c). */
static double rj__row_real(const void *def, const rj__field *r, int c)
{
    double v;
    memcpy(&v, (const char *) def + r->offset + c * sizeof(double), sizeof v);
    return v;
}

static void rj__row_set_real(void *def, const rj__field *r, int c, double v)
{
    memcpy((char *) def + r->offset + c * sizeof(double), &v, sizeof v);
}

/* The int at row r of def (INT, ENUM, BOOL, LINK, NODE, a TABLE's count); at the flag of
   a LIMIT. */
static int rj__row_int(const void *def, const rj__field *r)
{
    int v;
    const int at = r->type == RJ__FT_LIMIT ? r->aux : r->offset;
    memcpy(&v, (const char *) def + at, sizeof v);
    return v;
}

static void rj__row_set_int(void *def, const rj__field *r, int v)
{
    memcpy((char *) def + r->offset, &v, sizeof v);
}

/* Whether row r holds a double (REAL, ANGLE, RATE, LIMIT, VEC2) rather than an int. */
static int rj__row_is_real(const rj__field *r)
{
    return r->type == RJ__FT_REAL || r->type == RJ__FT_ANGLE || r->type == RJ__FT_RATE ||
           r->type == RJ__FT_LIMIT || r->type == RJ__FT_VEC2;
}

/* Every member of def at its default: zeros, then each row's default. */
static void rj__rows_default(void *def, size_t size, int kind)
{
    int n, k;
    const rj__field *t = rj__fields(kind, &n);
    memset(def, 0, size);
    for (k = 0; k < n; k++) {
        const rj__field *r = &t[k];
        if (r->type == RJ__FT_PART)
            continue;
        if (rj__row_is_real(r)) {
            rj__row_set_real(def, r, 0, r->def);
            if (r->type == RJ__FT_VEC2)
                rj__row_set_real(def, r, 1, r->def);
        } else
            rj__row_set_int(def, r, (int) r->def);
    }
}

/* Whether row r applies to an item of variant (a link's section shape, an actuator's
   type; -1 for other kinds) and is checked (write 0) or written (write 1) for a joint on
   ground (or not). */
static int rj__row_applies(const rj__field *r, int variant, int on_ground, int write)
{
    switch (r->when) {
    case RJ__WHEN_RECT:
        return variant == RJ_SECTION_RECT;
    case RJ__WHEN_GENERAL:
        return variant == RJ_SECTION_GENERAL;
    case RJ__WHEN_TORQUE:
        return variant == RJ_ACTUATOR_TORQUE;
    case RJ__WHEN_DC:
        return variant == RJ_ACTUATOR_DC;
    case RJ__WHEN_SERVO:
        return variant == RJ_ACTUATOR_SERVO;
    case RJ__WHEN_PRESCRIBED:
        return variant == RJ_ACTUATOR_PRESCRIBED;
    case RJ__WHEN_PROFILED:
    case RJ__WHEN_TABLED:
        return variant == RJ_ACTUATOR_SERVO || variant == RJ_ACTUATOR_PRESCRIBED ||
               (r->when == RJ__WHEN_TABLED && variant == RJ_ACTUATOR_TORQUE);
    case RJ__WHEN_GROUND:
        return !write || on_ground;
    case RJ__WHEN_ON_LINK:
        return !write || !on_ground;
    default:
        return 1;
    }
}
