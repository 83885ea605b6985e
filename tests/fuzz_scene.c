/* fuzz_scene.c - libFuzzer target for the scene-file parser (revjoint.h, RJ_NO_SCENE_FILES not set).
   Build and run from the repository root (one process: the machine's cores are shared):
     clang -g -O1 -fsanitize=fuzzer,address,undefined tests/fuzz_scene.c -I. -o /tmp/fuzz_scene -lm
     mkdir -p /tmp/fuzz_corpus && /tmp/fuzz_scene -jobs=1 -max_total_time=600 -max_len=8192 /tmp/fuzz_corpus tests/fuzz_corpus
   For every input: parse it; when it parses, check the writer's round trip (write, parse
   again, every field the model uses equal, else abort) and build a model with
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

static int fz_same(const rj_scene_file *a, const rj_scene_file *b)
{
    int i, k;
    if (a->link_count != b->link_count || a->joint_count != b->joint_count) return 0;
    if (a->solver.dt != b->solver.dt || a->solver.allow_unstable != b->solver.allow_unstable || a->solver.energy_growth != b->solver.energy_growth || a->solver.energy_every != b->solver.energy_every || a->solver.in_place != b->solver.in_place) return 0;
    for (i = 0; i < a->link_count; i++) {
        const rj_link_def *x = &a->links[i], *y = &b->links[i];
        if (strcmp(a->link_names[i], b->link_names[i])) return 0;
        if (x->length != y->length || x->elements != y->elements || x->E != y->E || x->rho != y->rho || x->section != y->section
            || x->height != y->height || x->tip_mass != y->tip_mass || x->tip_inertia != y->tip_inertia || x->root != y->root
            || x->x != y->x || x->y != y->y || x->angle != y->angle || x->vx != y->vx || x->vy != y->vy || x->omega != y->omega) return 0;
        if (x->section == RJ_SECTION_RECT && (x->width != y->width || x->layers != y->layers)) return 0;
        if (x->section == RJ_SECTION_GENERAL && (x->area != y->area || x->inertia != y->inertia)) return 0;
    }
    for (i = 0; i < a->joint_count; i++) {
        const rj_joint_def *x = &a->joints[i], *y = &b->joints[i];
        if (strcmp(a->joint_names[i], b->joint_names[i])) return 0;
        if (x->body1 != y->body1 || x->body2 != y->body2 || x->node1 != y->node1 || x->angle0 != y->angle0 || x->rate0 != y->rate0
            || x->table_count != y->table_count || x->spring_k != y->spring_k || x->spring_free_angle != y->spring_free_angle
            || x->has_forward != y->has_forward || x->has_reverse != y->has_reverse || x->lock != y->lock || x->method != y->method
            || x->release != y->release || x->penalty_k != y->penalty_k || x->restitution != y->restitution || x->damping != y->damping
            || x->friction != y->friction || x->reference != y->reference) return 0;
        if (x->body1 < 0 && (x->ground_x != y->ground_x || x->ground_y != y->ground_y || x->ground_angle != y->ground_angle)) return 0;
        if (x->has_forward && x->forward != y->forward) return 0;
        if (x->has_reverse && x->reverse != y->reverse) return 0;
        for (k = 0; k < x->table_count; k++) if (x->table_angle[k] != y->table_angle[k] || x->table_torque[k] != y->table_torque[k]) return 0;
    }
    return 1;
}

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
        n = rj_scene_write(&sd, ln, jn, NULL, 0);
        if (n == 0) abort();
        buf = (char *)malloc(n + 1);
        n2 = rj_scene_write(&sd, ln, jn, buf, n + 1);
        if (n2 != n || strlen(buf) != n) abort();
        if (rj_scene_parse(buf, n, "fuzz-written.rjs", &g, &err) != RJ_OK) abort();
        if (!fz_same(&f, &g)) abort();
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
