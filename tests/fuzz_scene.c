/* fuzz_scene.c - libFuzzer target for the scene-file parser (revjoint.h, RJ_NO_SCENE_FILES not set).
   Build and run from the repository root (one process: the machine's cores are shared):
     clang -g -O1 -fsanitize=fuzzer,address,undefined tests/fuzz_scene.c -I. -o /tmp/fuzz_scene -lm
     mkdir -p /tmp/fuzz_corpus && /tmp/fuzz_scene -jobs=1 -max_total_time=600 -max_len=8192 /tmp/fuzz_corpus tests/fuzz_corpus
   For every input: parse it; when it parses, check the writer's round trip (write, parse
   again, every field the model uses equal, the solver's gravity and the load sections'
   fields included (not their names: the writer names loads load0, load1, ...), else abort)
   and build a model with
   rj_model_create, step it 10 times, free everything. Models above RJ_FUZZ_MAX_NODES nodes
   are only validated (rj_model_size), not built: the parser accepts up to 256 links of up to
   10^6 elements each, which is a legal scene but no unit of fuzzing work. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define REVJOINT_IMPLEMENTATION
#include "../revjoint.h"

#ifndef RJ_FUZZ_MAX_NODES
#define RJ_FUZZ_MAX_NODES 2000
#endif

/* every field the model uses, compared in bits (the writer keeps -0.0 as -0.0) */
#define FZ(f) if (memcmp(&x->f, &y->f, sizeof x->f)) return 0;
static int fz_same(const rj_scene_file *a, const rj_scene_file *b)
{
    int i, k;
    if (a->link_count != b->link_count || a->joint_count != b->joint_count || a->load_count != b->load_count) return 0;
    {
        const rj_solver_def *x = &a->solver, *y = &b->solver;
        FZ(dt) FZ(allow_unstable) FZ(energy_growth) FZ(energy_every) FZ(in_place) FZ(gravity[0]) FZ(gravity[1])
    }
    for (i = 0; i < a->link_count; i++) {
        const rj_link_def *x = &a->links[i], *y = &b->links[i];
        if (strcmp(a->link_names[i], b->link_names[i])) return 0;
        FZ(length) FZ(elements) FZ(E) FZ(rho) FZ(section) FZ(height) FZ(tip_mass) FZ(tip_inertia) FZ(root)
        FZ(x) FZ(y) FZ(angle) FZ(vx) FZ(vy) FZ(omega) FZ(fidelity)
        if (x->section == RJ_SECTION_RECT) { FZ(width) FZ(layers) }
        if (x->section == RJ_SECTION_GENERAL) { FZ(area) FZ(inertia) }
    }
    for (i = 0; i < a->joint_count; i++) {
        const rj_joint_def *x = &a->joints[i], *y = &b->joints[i];
        if (strcmp(a->joint_names[i], b->joint_names[i])) return 0;
        FZ(body1) FZ(body2) FZ(angle0) FZ(rate0) FZ(table_count) FZ(spring_k) FZ(spring_free_angle)
        FZ(has_forward) FZ(has_reverse) FZ(lock) FZ(method) FZ(release) FZ(penalty_k) FZ(restitution)
        FZ(damping) FZ(friction) FZ(reference)
        if (x->body1 >= 0) { FZ(node1) }
        if (x->body1 < 0) { FZ(ground_x) FZ(ground_y) FZ(ground_angle) }
        if (x->has_forward) { FZ(forward) }
        if (x->has_reverse) { FZ(reverse) }
        for (k = 0; k < x->table_count; k++) { FZ(table_angle[k]) FZ(table_torque[k]) }
    }
    for (i = 0; i < a->load_count; i++) {
        const rj_load_def *x = &a->loads[i], *y = &b->loads[i];
        FZ(link) FZ(node) FZ(force[0]) FZ(force[1]) FZ(moment) FZ(follower) FZ(table_count)
        for (k = 0; k < x->table_count; k++) { FZ(table_time[k]) FZ(table_factor[k]) }
    }
    return 1;
}
#undef FZ

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    rj_scene_file f, g;
    rj_error err;
    rj_scene_def sd;
    long nodes = 0;
    int i;
    /* an exact-size copy, so reading past size is caught (the parser must not need a NUL) */
    char *text = (char *)malloc(size ? size : 1);
    if (size) memcpy(text, data, size);
    if (rj_scene_parse(text, size, "fuzz.rjs", &f, &err) != RJ_OK) {
        if (err.msg[0] == 0 || memchr(err.msg, 0, sizeof err.msg) == NULL) abort();   /* every error has a message */
        free(text);
        return 0;
    }
    free(text);
    sd = rj_scene_file_def(&f);
    /* writer round trip */
    {
        const char *ln[RJ_SCENE_MAX_LINKS], *jn[RJ_SCENE_MAX_JOINTS];
        size_t n, n2;
        char *buf;
        for (i = 0; i < f.link_count; i++) ln[i] = f.link_names[i];
        for (i = 0; i < f.joint_count; i++) jn[i] = f.joint_names[i];
        n = rj_scene_write_ex(&sd, ln, jn, f.title, NULL, 0);
        if (n == 0) abort();
        buf = (char *)malloc(n + 1);
        n2 = rj_scene_write_ex(&sd, ln, jn, f.title, buf, n + 1);
        if (n2 != n || strlen(buf) != n) abort();
        if (rj_scene_parse(buf, n, "fuzz-written.rjs", &g, &err) != RJ_OK) abort();
        if (!fz_same(&f, &g)) abort();
        /* a title that parsed is one the writer can write, and it reads back the same */
        if (strcmp(f.title, g.title) != 0) abort();
        rj_scene_file_free(&g);
        free(buf);
    }
    for (i = 0; i < f.link_count; i++) nodes += f.links[i].elements + 1;
    if (nodes <= RJ_FUZZ_MAX_NODES) {
        rj_model *m = NULL;
        rj_state *s = NULL;
        if (rj_model_create(&sd, &m, &err, NULL) == RJ_OK) {
            if (rj_state_create(m, &s, NULL) == RJ_OK) {
                for (i = 0; i < 10; i++) if (rj_step(m, s) != RJ_OK) break;
                rj_state_destroy(s, NULL);
            }
            rj_model_destroy(m, NULL);
        } else {
            rj_scene_file_locate(&f, &err);
        }
    }
    rj_scene_file_free(&f);
    return 0;
}
