/* States: checkpoints resume bit-identically, bad checkpoints are rejected without touching
   the state, a failed step leaves the last good state, and a step never allocates. */
#include <stdlib.h>
#include <string.h>
#include <stdio.h>
/* counting allocator, installed through the library's RJ_MALLOC / RJ_FREE hooks */
typedef struct counter { long allocs, frees; } counter;
/* (the implementation is tests/rjt_impl_hooked.c) */
#include "rjt_alloc.h"
void *rjt_malloc(size_t n, void *ctx) { if (ctx) ((counter *)ctx)->allocs++; return malloc(n); }
void rjt_free(void *p, void *ctx) { if (ctx && p) ((counter *)ctx)->frees++; free(p); }
#include "../revjoint.h"
#include "../examples/scenes.h"
#include "rjt.h"

static int same_state(const rj_model *m, const rj_state *a, const rj_state *b)
{
    int l, i, j;
    for (l = 0; l < rj_model_link_count(m); l++) for (i = 0; i < rj_link_node_count(m, l); i++) {
        double pa[2], pb[2], va[2], vb[2];
        rj_node_position(m, a, l, i, pa); rj_node_position(m, b, l, i, pb);
        rj_node_velocity(m, a, l, i, va); rj_node_velocity(m, b, l, i, vb);
        if (memcmp(pa, pb, sizeof pa) || memcmp(va, vb, sizeof va)) return 0;
        if (rj_node_rotation(m, a, l, i) != rj_node_rotation(m, b, l, i)) return 0;
    }
    for (j = 0; j < rj_model_joint_count(m); j++)
        if (rj_joint_theta_running(m, a, j) != rj_joint_theta_running(m, b, j) || rj_joint_flag(m, a, j) != rj_joint_flag(m, b, j)) return 0;
    return rj_state_time(a) == rj_state_time(b);
}

int main(void)
{
    rjt_ctx c = { 0, 0 };
    counter cnt = { 0, 0 };
    deploy_opts o = deploy_default_opts();
    rj_link_def L[2]; rj_joint_def J[2]; rj_scene_def sc;
    rj_model *m; rj_state *a, *b; rj_error e;
    unsigned char *buf;
    size_t n;
    long k, before;
    deploy_scene(&o, L, J, &sc); J[1].penalty_k = 1000;
    rj_model_create(&sc, &m, &e, &cnt);
    rj_state_create(m, &a, &cnt); rj_state_create(m, &b, &cnt);
    /* zero allocations per step */
    before = cnt.allocs;
    for (k = 0; k < 100000; k++) rj_step(m, a);
    rjt_check(&c, cnt.allocs == before && cnt.allocs == 3, "no heap allocation in 1e5 steps (counting RJ_MALLOC)", "%ld allocations before, %ld after; model %lu bytes, state %lu bytes",
              before, cnt.allocs, (unsigned long)rj_model_size(&sc, NULL), (unsigned long)rj_state_size(m));
    /* checkpoint at 0.75 s, continue both through joint 2's lock to 3.5 s: bit-identical */
    n = rj_state_save(m, a, NULL, 0);
    buf = (unsigned char *)malloc(n);
    rjt_check(&c, rj_state_save(m, a, buf, n) == n, "checkpoint written", "%lu bytes", (unsigned long)n);
    {
        int ok = rj_state_load(m, b, buf, n, &e) == RJ_OK && same_state(m, a, b);
        rjt_check(&c, ok, "checkpoint restores the state exactly", "t = %.6f s", rj_state_time(b));
    }
    rj_run(m, a, 3.5, 0, NULL, NULL);
    rj_run(m, b, 3.5, 0, NULL, NULL);
    rjt_check(&c, same_state(m, a, b) && rj_joint_flag(m, b, 1) == RJ_LOCKED, "resumed run is bit-identical to the uninterrupted one (through the lock)", "t = %.6f s, steps %ld", rj_state_time(b), rj_state_steps(b));
    /* bad checkpoints: truncated, one byte flipped anywhere, foreign model; state untouched */
    {
        rj_state *snap;
        int bad_ok = 1, i;
        rj_state_create(m, &snap, NULL);
        rj_state_copy(m, snap, b);
        if (rj_state_load(m, b, buf, n - 1, &e) != RJ_ERR_CHECKPOINT || !same_state(m, b, snap)) bad_ok = 0;
        rjt_check(&c, bad_ok, "truncated checkpoint rejected, state unchanged", "\"%s\"", e.msg);
        for (i = 0; i < (int)n; i += 97) {
            buf[i] ^= 0x10;
            if (rj_state_load(m, b, buf, n, &e) != RJ_ERR_CHECKPOINT || !same_state(m, b, snap)) { bad_ok = 0; printf("  byte %d accepted\n", i); }
            buf[i] ^= 0x10;
        }
        rjt_check(&c, bad_ok, "corrupted checkpoint (bit flips every 97 bytes) rejected, state unchanged", "\"%s\"", e.msg);
        {
            /* same sizes, another model (a different dt): the model hash rejects it */
            rj_model *m2; rj_state *s2; size_t n2; unsigned char *b2;
            sc.solver.dt = 5e-6;
            rj_model_create(&sc, &m2, &e, NULL); rj_state_create(m2, &s2, NULL);
            n2 = rj_state_save(m2, s2, NULL, 0); b2 = (unsigned char *)malloc(n2); rj_state_save(m2, s2, b2, n2);
            rjt_check(&c, n2 == n && rj_state_load(m, b, b2, n2, &e) == RJ_ERR_CHECKPOINT && same_state(m, b, snap), "checkpoint of another model (same size) rejected", "\"%s\"", e.msg);
            free(b2); rj_state_destroy(s2, NULL); rj_model_destroy(m2, NULL);
        }
        rj_state_destroy(snap, NULL);
    }
    /* a failed step leaves the last good state: force a blow-up with dt above the bound */
    {
        rj_model *m3; rj_state *s3, *keep; rj_result r = RJ_OK; impact_opts io = impact_default_opts(); rj_link_def L3[2]; rj_joint_def J3; rj_scene_def sc3;
        io.dt = 12e-6;
        impact_scene(&io, L3, &J3, &sc3); sc3.solver.allow_unstable = 1;
        rj_model_create(&sc3, &m3, &e, NULL); rj_state_create(m3, &s3, NULL); rj_state_create(m3, &keep, NULL);
        for (k = 0; k < 200000 && r == RJ_OK; k++) { rj_state_copy(m3, keep, s3); r = rj_step(m3, s3); }
        rjt_check(&c, r == RJ_ERR_BLOWUP && same_state(m3, s3, keep) && strstr(rj_state_error(s3), "above the stability bound") != NULL,
                  "blow-up above the bound is detected, named, and the last good state kept", "after %ld steps: \"%s\"", k, rj_state_error(s3));
        rj_state_destroy(s3, NULL); rj_state_destroy(keep, NULL); rj_model_destroy(m3, NULL);
    }
    free(buf);
    rj_state_destroy(a, &cnt); rj_state_destroy(b, &cnt); rj_model_destroy(m, &cnt);
    rjt_check(&c, cnt.allocs == cnt.frees, "every allocation freed", "%ld allocations, %ld frees", cnt.allocs, cnt.frees);
    return rjt_summary(&c, "test_state");
}
