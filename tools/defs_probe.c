/* defs_probe.c - what the definitions layer answers for a corpus of inputs: for a
   refactor of definitions, validation, the scene parser, the writer or the model hash,
   run it before and after and diff the two outputs (tools/defs_probe.sh does both).

   It prints, one line each:
   - every scene file given on the command line: the parse verdict (the message on a
     refusal), the model's verdict and hash, and whether the written scene reads back
     to the same model hash;
   - every member of every definition set to each of a list of bad or edge values on a
     small scene, in C: rj_model_create's verdict, field and message;
   - every scene key given each of a list of values in a scene file: the parse and
     model verdicts and messages.
   The lists of members and keys here are its own, not the library's tables.
   Build: cc -std=c99 -O1 -I. tools/defs_probe.c -o build/defs_probe -lm */
#define REVJOINT_IMPLEMENTATION
#include "revjoint.h"

#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static char text_buf[1 << 20];

/* the model built from a scene file's text: "parse: MSG", "model: MSG" or the hash */
static void verdict(const char *text, const char *label, int write_back)
{
    rj_scene_file f;
    rj_error err;
    rj_model *m = NULL;
    rj_scene_def sc;
    memset(&err, 0, sizeof err);
    if (rj_scene_parse(text, strlen(text), "probe.rjs", &f, &err) != RJ_OK) {
        printf("%s: parse %s: %s\n", label, err.field, err.msg);
        return;
    }
    sc = rj_scene_file_def(&f);
    if (rj_model_create(&sc, &m, &err, NULL) != RJ_OK) {
        printf("%s: model %s: %s\n", label, err.field, err.msg);
        rj_scene_file_free(&f);
        return;
    }
    printf("%s: hash %016llx", label, (unsigned long long) m->hash);
    if (write_back) {
        static char out[1 << 20];
        const char *ln[RJ_SCENE_MAX_LINKS], *jn[RJ_SCENE_MAX_JOINTS];
        int i;
        size_t n;
        rj_scene_file g;
        rj_model *m2 = NULL;
        for (i = 0; i < f.link_count && i < RJ_SCENE_MAX_LINKS; i++)
            ln[i] = f.link_names[i];
        for (i = 0; i < f.joint_count && i < RJ_SCENE_MAX_JOINTS; i++)
            jn[i] = f.joint_names[i];
        n = rj_scene_write(&sc, ln, jn, out, sizeof out);
        if (n == 0 || n >= sizeof out) {
            printf(" write failed\n");
        } else if (rj_scene_parse(out, n, "w.rjs", &g, &err) != RJ_OK) {
            printf(" written: parse %s\n", err.msg);
        } else {
            rj_scene_def s2 = rj_scene_file_def(&g);
            if (rj_model_create(&s2, &m2, &err, NULL) != RJ_OK)
                printf(" written: model %s\n", err.msg);
            else
                printf(" written reads back %s\n",
                       m2->hash == m->hash ? "the same" : "DIFFERENT");
            rj_model_destroy(m2, NULL);
            rj_scene_file_free(&g);
        }
    } else
        printf("\n");
    rj_model_destroy(m, NULL);
    rj_scene_file_free(&f);
}

static void files(int argc, char **argv)
{
    int i;
    for (i = 1; i < argc; i++) {
        FILE *fp = fopen(argv[i], "rb");
        size_t n;
        if (!fp) {
            printf("%s: cannot open\n", argv[i]);
            continue;
        }
        n = fread(text_buf, 1, sizeof text_buf - 1, fp);
        fclose(fp);
        text_buf[n] = 0;
        verdict(text_buf, argv[i], 1);
    }
}

/* ---- members in C */
typedef struct member {
    const char *name;
    size_t off;
    int is_int;
} member;

#define ML(f, i) { #f, offsetof(rj_link_def, f), i }
static const member link_members[] = {
    ML(length, 0),  ML(elements, 1), ML(E, 0),        ML(rho, 0),         ML(section, 1),
    ML(width, 0),   ML(height, 0),   ML(layers, 1),   ML(area, 0),        ML(inertia, 0),
    ML(tip_mass, 0), ML(tip_inertia, 0), ML(root, 1), ML(x, 0),           ML(y, 0),
    ML(angle, 0),   ML(vx, 0),       ML(vy, 0),       ML(omega, 0),       ML(fidelity, 1),
};
#define MJ(f, i) { #f, offsetof(rj_joint_def, f), i }
static const member joint_members[] = {
    MJ(body1, 1),        MJ(node1, 1),       MJ(body2, 1),        MJ(ground_x, 0),
    MJ(ground_y, 0),     MJ(ground_angle, 0), MJ(angle0, 0),      MJ(rate0, 0),
    MJ(table_count, 1),  MJ(spring_k, 0),    MJ(spring_free_angle, 0), MJ(has_forward, 1),
    MJ(forward, 0),      MJ(has_reverse, 1), MJ(reverse, 0),      MJ(lock, 1),
    MJ(method, 1),       MJ(release, 1),     MJ(penalty_k, 0),    MJ(restitution, 0),
    MJ(damping, 0),      MJ(friction, 0),    MJ(reference, 1),
};
#define MS(f, i) { #f, offsetof(rj_solver_def, f), i }
static const member solver_members[] = {
    MS(dt, 0), MS(allow_unstable, 1), MS(energy_growth, 0), MS(energy_every, 1), MS(in_place, 1),
    { "gravity[0]", offsetof(rj_solver_def, gravity), 0 },
    { "gravity[1]", offsetof(rj_solver_def, gravity) + sizeof(double), 0 },
};
#define MA(f, i) { #f, offsetof(rj_load_def, f), i }
static const member load_members[] = {
    MA(link, 1), MA(node, 1), MA(moment, 0), MA(follower, 1), MA(table_count, 1),
    { "force[0]", offsetof(rj_load_def, force), 0 },
    { "force[1]", offsetof(rj_load_def, force) + sizeof(double), 0 },
};

static const double real_values[] = { 0.0, -1.0, -0.0, 1e-300, 0.5, 1.0, 2.0, 7.0, 1e6, 2e6,
                                      1e12, 1e13, 1e24, 1e25, 1e30, 1e31, 1e40, 1e41, 1e50,
                                      1e51, -1e31, 1e300 };
static const int int_values[] = { -3, -2, -1, 0, 1, 2, 3, 4, 5, 11, 33, 1000, 1001,
                                  1000001 };

static void create(const char *what, const rj_scene_def *sc)
{
    rj_model *m = NULL;
    rj_error err;
    memset(&err, 0, sizeof err);
    fflush(stdout);
    if (rj_model_create(sc, &m, &err, NULL) == RJ_OK) {
        printf("%s: ok %016llx\n", what, (unsigned long long) m->hash);
        rj_model_destroy(m, NULL);
    } else
        printf("%s: %s: %s\n", what, err.field, err.msg);
}

/* base scene: two links (the second general when general), a ground joint and a joint
   between them with limits, a load with a table */
static void base(rj_link_def *L, rj_joint_def *J, rj_load_def *A, rj_scene_def *sc, int general)
{
    L[0] = rj_default_link_def();
    L[1] = rj_default_link_def();
    L[0].elements = 4;
    L[1].elements = 4;
    if (general) {
        L[1].section = RJ_SECTION_GENERAL;
        L[1].area = 1e-3;
        L[1].inertia = 1e-7;
    }
    J[0] = rj_default_joint_def();
    J[0].body2 = 0;
    J[1] = rj_default_joint_def();
    J[1].body1 = 0;
    J[1].body2 = 1;
    J[1].has_forward = 1;
    J[1].forward = 3.0;
    J[1].has_reverse = 1;
    J[1].reverse = 1.0;
    J[1].spring_k = 10;
    A[0] = rj_default_load_def();
    A[0].link = 1;
    A[0].force[1] = 1;
    A[0].table_count = 2;
    A[0].table_time[0] = 0;
    A[0].table_time[1] = 1;
    A[0].table_factor[0] = 0;
    A[0].table_factor[1] = 1;
    *sc = rj_default_scene_def();
    sc->links = L;
    sc->link_count = 2;
    sc->joints = J;
    sc->joint_count = 2;
    sc->loads = A;
    sc->load_count = 1;
    sc->solver.dt = 1e-6;
}

static void poke(void *def, const member *mb, int vi, char *what, size_t size, const char *kind)
{
    char *p = (char *) def + mb->off;
    if (mb->is_int) {
        int v = int_values[vi];
        memcpy(p, &v, sizeof v);
        snprintf(what, size, "%s.%s = %d", kind, mb->name, v);
    } else {
        double v = real_values[vi];
        memcpy(p, &v, sizeof v);
        snprintf(what, size, "%s.%s = %g", kind, mb->name, v);
    }
}

static void members_c(void)
{
    const int nreal = (int) (sizeof real_values / sizeof real_values[0]);
    const int nint = (int) (sizeof int_values / sizeof int_values[0]);
    rj_link_def L[2];
    rj_joint_def J[2];
    rj_load_def A[1];
    rj_scene_def sc;
    char what[128];
    int general, k, v, which;
    for (general = 0; general < 2; general++)
        for (which = 0; which < 2; which++)
            for (k = 0; k < (int) (sizeof link_members / sizeof link_members[0]); k++)
                for (v = 0; v < (link_members[k].is_int ? nint : nreal); v++) {
                    base(L, J, A, &sc, general);
                    poke(&L[which], &link_members[k], v, what, sizeof what,
                         which ? (general ? "glink1" : "link1") : (general ? "glink0" : "link0"));
                    create(what, &sc);
                }
    for (which = 0; which < 2; which++)
        for (k = 0; k < (int) (sizeof joint_members / sizeof joint_members[0]); k++)
            for (v = 0; v < (joint_members[k].is_int ? nint : nreal); v++) {
                base(L, J, A, &sc, 0);
                poke(&J[which], &joint_members[k], v, what, sizeof what,
                     which ? "joint1" : "joint0");
                create(what, &sc);
            }
    for (k = 0; k < (int) (sizeof solver_members / sizeof solver_members[0]); k++)
        for (v = 0; v < (solver_members[k].is_int ? nint : nreal); v++) {
            base(L, J, A, &sc, 0);
            poke(&sc.solver, &solver_members[k], v, what, sizeof what, "solver");
            create(what, &sc);
        }
    for (k = 0; k < (int) (sizeof load_members / sizeof load_members[0]); k++)
        for (v = 0; v < (load_members[k].is_int ? nint : nreal); v++) {
            base(L, J, A, &sc, 0);
            poke(&A[0], &load_members[k], v, what, sizeof what, "load");
            create(what, &sc);
        }
}

/* ---- keys in scene files */
static const char *const key_values[] = {
    "0", "-1", "1", "2", "0.5", "1e6", "2e6", "1e12", "1e13", "1e24", "1e25", "1e30", "1e31",
    "1e41", "1e51", "-1e31", "nan", "inf", "abc", "yes", "no", "last", "none", "ground", "a",
    "b", "90 deg", "400 deg", "-10 deg", "2 rad/s", "90 deg/s", "1 2", "1 90 deg", "1",
    "0 1, 1 2", "0 0, 90 deg 1", "free", "pinned", "rigid", "penalty", "energy", "rc12",
    "chord", "on", "1e7 rad", "1 m", "1 2 3", ""
};
static const char *const section_keys[][2] = {
    { "solver", "dt" },          { "solver", "allow_unstable" }, { "solver", "energy_growth" },
    { "solver", "energy_every" }, { "solver", "in_place" },      { "solver", "gravity" },
    { "link", "length" },        { "link", "elements" },         { "link", "E" },
    { "link", "rho" },           { "link", "area" },             { "link", "inertia" },
    { "link", "width" },         { "link", "height" },           { "link", "layers" },
    { "link", "tip_mass" },      { "link", "tip_inertia" },      { "link", "root" },
    { "link", "x" },             { "link", "y" },                { "link", "angle" },
    { "link", "vx" },            { "link", "vy" },               { "link", "omega" },
    { "link", "fidelity" },      { "link", "material" },         { "link", "section" },
    { "joint", "body1" },        { "joint", "body2" },           { "joint", "node1" },
    { "joint", "ground_x" },     { "joint", "ground_y" },        { "joint", "ground_angle" },
    { "joint", "angle0" },       { "joint", "rate0" },           { "joint", "table" },
    { "joint", "spring" },       { "joint", "forward" },         { "joint", "reverse" },
    { "joint", "lock" },         { "joint", "method" },          { "joint", "release" },
    { "joint", "penalty_k" },    { "joint", "restitution" },     { "joint", "damping" },
    { "joint", "friction" },     { "joint", "reference" },       { "load", "link" },
    { "load", "node" },          { "load", "force" },            { "load", "moment" },
    { "load", "table" },         { "load", "follower" },         { "material", "E" },
    { "section", "area" },       { "section", "layers" },
};

static void keys_text(void)
{
    const int nv = (int) (sizeof key_values / sizeof key_values[0]);
    const int nk = (int) (sizeof section_keys / sizeof section_keys[0]);
    int k, v;
    for (k = 0; k < nk; k++)
        for (v = 0; v < nv; v++) {
            const char *sec = section_keys[k][0], *key = section_keys[k][1];
            char label[160];
            const char *sv = "", *lv = "", *jv = "", *av = "", *mv = "", *cv = "";
            char line[200];
            snprintf(line, sizeof line, "  %s = %s\n", key, key_values[v]);
            if (!strcmp(sec, "solver"))
                sv = line;
            else if (!strcmp(sec, "link"))
                lv = line;
            else if (!strcmp(sec, "joint"))
                jv = line;
            else if (!strcmp(sec, "load"))
                av = line;
            else if (!strcmp(sec, "material"))
                mv = line;
            else
                cv = line;
            snprintf(text_buf, sizeof text_buf,
                     "solver\n  dt = 1e-6\n%s"
                     "material m\n  E = 70e9\n%s"
                     "section s\n  width = 0.05\n  height = 0.01\n%s"
                     "link a\n  length = 1\n  elements = 4\n%s"
                     "link b\n  material = m\n  section = s\n  elements = 4\n"
                     "joint base\n  body1 = ground\n  body2 = a\n"
                     "joint hinge\n  body1 = a\n  body2 = b\n  forward = 170 deg\n%s"
                     "load push\n  link = b\n  force = 0 1\n%s",
                     sv, mv, cv, lv, jv, av);
            snprintf(label, sizeof label, "%s.%s = %s", sec, key, key_values[v]);
            verdict(text_buf, label, 1);
        }
}

int main(int argc, char **argv)
{
    files(argc, argv);
    members_c();
    keys_text();
    return 0;
}
