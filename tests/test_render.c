/* Golden images of the locking benchmark (SPEC 9.2) and proof that the comparison bites.
   Rule (render/README.md, osmesa.md sec. 4): a pixel is bad when its largest RGB difference
   exceeds 16 (driver noise measured here is at most 2); the image fails above 32 bad pixels
   (0.01 % of 640x480). Measured below on every run: a 0.5 deg turn of the arm and a 2-pixel
   shift must both exceed the limit. On failure the rendered image and a difference image
   are written next to the golden one.
   usage: test_render [--write-golden] [--golden-dir DIR] */
#define REVJOINT_IMPLEMENTATION
#include "../revjoint.h"
#include "../examples/scenes.h"
#include "../render/rj_render.h"
#include "rjt.h"
#include <stdlib.h>
#include <string.h>

#define W 640
#define H 480
#define THRESH 16
#define MAXBAD 32

static const double times[6] = { 0.0, 1.5, 2.99, 3.1, 4.5, 6.0 };

static rjr_view deploy_view(void)
{
    rjr_view v = rjr_view_default();
    double box[4] = { -1.2, -0.3, 1.3, 2.2 };
    rjr_view_fit_box(&v, box, W, H, 20);
    v.thickness_factor = 2.0;
    v.caption = "two-link deployment (SPEC 9.2)";
    return v;
}

static int render(rjr_context *ctx, const rj_model *m, const rj_state *s, const rjr_view *v, unsigned char *rgb)
{
    return rjr_draw_state(ctx, m, s, v) || rjr_read_pixels(ctx, rgb);
}

int main(int argc, char **argv)
{
    rjt_ctx c = { 0, 0 };
    const char *dir = "tests/golden";
    int write = 0, i, k;
    char err[256], path[512];
    rjr_context *ctx;
    rj_model *m; rj_state *s; rj_error e;
    deploy_opts o = deploy_default_opts();
    rjr_view v = deploy_view();
    unsigned char *img = (unsigned char *)malloc(W * H * 3), *img2 = (unsigned char *)malloc(W * H * 3);
    for (i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--write-golden")) write = 1;
        else if (!strcmp(argv[i], "--golden-dir") && i + 1 < argc) dir = argv[++i];
        else { fprintf(stderr, "usage: test_render [--write-golden] [--golden-dir DIR]\n"); return 2; }
    }
    ctx = rjr_create(W, H, err, sizeof err);
    if (!ctx) { printf("FAIL render context: %s\n", err); return 1; }
    printf("renderer: %s, %s, %s, %d samples\n", rjr_backend(ctx), rjr_gl_renderer(ctx), rjr_gl_version(ctx), rjr_samples(ctx));
    if (deploy_build(&o, &m, &e) != RJ_OK) { printf("FAIL deploy model: %s\n", e.msg); return 1; }
    rj_state_create(m, &s, NULL);
    for (k = 0; k < 6; k++) {
        char name[96];
        if (rj_run(m, s, times[k], 0, NULL, NULL) != RJ_OK) { printf("FAIL run to %g s: %s\n", times[k], rj_state_error(s)); return 1; }
        snprintf(path, sizeof path, "%s/deploy_t%05.2f.png", dir, times[k]);
        if (render(ctx, m, s, &v, img)) { printf("FAIL render: %s\n", rjr_error(ctx)); return 1; }
        snprintf(name, sizeof name, "golden image t = %.2f s", times[k]);
        if (write) {
            rjt_check(&c, rjr_write_png(path, img, W, H, err, sizeof err) == 0, name, "wrote %s %s", path, err);
            continue;
        }
        {
            unsigned char *g = NULL; int gw, gh;
            rjr_diff d;
            if (rjr_load_png(path, &g, &gw, &gh, err, sizeof err) || gw != W || gh != H) { rjt_check(&c, 0, name, "cannot read %s: %s", path, err); free(g); continue; }
            rjr_compare(g, img, W, H, THRESH, &d);
            if (!rjt_check(&c, d.bad_pixels <= MAXBAD, name, "%ld pixels differ by more than %d (limit %d), max delta %d, PSNR %.1f dB",
                           d.bad_pixels, THRESH, MAXBAD, d.max_delta, d.psnr)) {
                char pa[600], pd[600];
                snprintf(pa, sizeof pa, "%s/deploy_t%05.2f.actual.png", dir, times[k]);
                snprintf(pd, sizeof pd, "%s/deploy_t%05.2f.diff.png", dir, times[k]);
                rjr_write_png(pa, img, W, H, err, sizeof err);
                rjr_write_diff_png(pd, g, img, W, H, THRESH, err, sizeof err);
                printf("  rendered image: %s\n  difference image: %s\n", pa, pd);
            }
            free(g);
        }
    }
    rj_state_destroy(s, NULL); rj_model_destroy(m, NULL);
    if (write) goto done;
    /* the comparison bites: the t = 0 scene with joint 1 turned by 0.5 deg, and the same
       scene shifted by 2 pixels, against the t = 0 rendering */
    {
        rj_link_def L[2]; rj_joint_def J[2]; rj_scene_def sc; rjr_diff d; rj_model *m2; rj_state *s2;
        rjr_view v2 = v;
        deploy_scene(&o, L, J, &sc); J[1].penalty_k = 1000;
        rj_model_create(&sc, &m2, &e, NULL); rj_state_create(m2, &s2, NULL);
        render(ctx, m2, s2, &v, img);
        render(ctx, m2, s2, &v, img2);
        rjr_compare(img, img2, W, H, 0, &d);
        rjt_check(&c, d.max_delta == 0, "rendering the same state twice gives identical pixels", "max delta %d", d.max_delta);
        rj_state_destroy(s2, NULL); rj_model_destroy(m2, NULL);
        J[0].angle0 = rj_rad(0.5);
        rj_model_create(&sc, &m2, &e, NULL); rj_state_create(m2, &s2, NULL);
        render(ctx, m2, s2, &v, img2);
        rjr_compare(img, img2, W, H, THRESH, &d);
        rjt_check(&c, d.bad_pixels > MAXBAD, "comparison bites: arm turned by 0.5 deg fails", "%ld bad pixels > %d (max delta %d)", d.bad_pixels, MAXBAD, d.max_delta);
        rj_state_destroy(s2, NULL); rj_model_destroy(m2, NULL);
        J[0].angle0 = 0;
        rj_model_create(&sc, &m2, &e, NULL); rj_state_create(m2, &s2, NULL);
        v2.cx += 2 * v2.mpp;
        render(ctx, m2, s2, &v2, img2);
        rjr_compare(img, img2, W, H, THRESH, &d);
        rjt_check(&c, d.bad_pixels > MAXBAD, "comparison bites: scene moved by 2 pixels fails", "%ld bad pixels > %d (max delta %d)", d.bad_pixels, MAXBAD, d.max_delta);
        rj_state_destroy(s2, NULL); rj_model_destroy(m2, NULL);
    }
done:
    rjr_destroy(ctx);
    free(img); free(img2);
    return rjt_summary(&c, "test_render");
}
