/* Golden images of the locking benchmark (paper sec. 5) and proof that the comparison bites.
   Rule (render/README.md, osmesa.md sec. 4): a pixel is bad when its largest RGB difference
   exceeds 16 (driver noise measured here is at most 2); the image fails above 32 bad pixels
   (0.01 % of 640x480). Measured below on every run: a 0.5 deg turn of the arm and a 2-pixel
   shift must both exceed the limit. On failure the rendered image and a difference image
   are written next to the golden one.
   usage: test_render [--write-golden] [--golden-dir DIR] */
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
    v.caption = "two-link deployment (paper sec. 5)";
    return v;
}

static int render(rjr_context *ctx, const rj_model *m, const rj_state *s, const rjr_view *v, unsigned char *rgb)
{
    return rjr_draw_state(ctx, m, s, v) || rjr_read_pixels(ctx, rgb);
}

/* ---- Frame aids: legend, joint labels, text band, separated stacks ----------------------
   Each aid is checked by what it adds: a frame with the aid against the same frame
   without it. A pixel is "drawn" when it is not the white background. */

#define NPIX (W * H)

static int drawn(const unsigned char *img, int i)
{
    const unsigned char *p = img + 3 * i;
    return p[0] != 255 || p[1] != 255 || p[2] != 255;
}

static int differs(const unsigned char *a, const unsigned char *b, int i)
{
    return memcmp(a + 3 * i, b + 3 * i, 3) != 0;
}

static int is_rgb(const unsigned char *img, int i, unsigned rgb, int tol)
{
    const unsigned char *p = img + 3 * i;
    return abs(p[0] - (int)(rgb >> 16 & 255)) <= tol && abs(p[1] - (int)(rgb >> 8 & 255)) <= tol && abs(p[2] - (int)(rgb & 255)) <= tol;
}

/* bounding box {x0, y0, x1, y1} of the pixels where a and b differ; the count */
static long diff_box(const unsigned char *a, const unsigned char *b, int box[4])
{
    long n = 0;
    int i;
    box[0] = W;
    box[1] = H;
    box[2] = -1;
    box[3] = -1;
    for (i = 0; i < NPIX; i++) {
        if (!differs(a, b, i))
            continue;
        n++;
        box[0] = i % W < box[0] ? i % W : box[0];
        box[1] = i / W < box[1] ? i / W : box[1];
        box[2] = i % W > box[2] ? i % W : box[2];
        box[3] = i / W > box[3] ? i / W : box[3];
    }
    return n;
}

/* pixels where a and b differ and base is drawn: what the aid drew over */
static long diff_on_drawn(const unsigned char *a, const unsigned char *b, const unsigned char *base)
{
    long n = 0;
    int i;
    for (i = 0; i < NPIX; i++)
        n += differs(a, b, i) && drawn(base, i);
    return n;
}

/* the deploy model at time t */
static int deploy_at(double t, rj_model **m, rj_state **s)
{
    deploy_opts o = deploy_default_opts();
    rj_error e;
    if (deploy_build(&o, m, &e) != RJ_OK || rj_state_create(*m, s, NULL) != RJ_OK)
        return -1;
    return rj_run(*m, *s, t, 0, NULL, NULL) == RJ_OK ? 0 : -1;
}

/* the legend at the frame corner the view gives, and what it adds: its box lies in a
   corner, it covers nothing that was drawn, and it shows the three joint colours exactly */
static void legend_case(rjt_ctx *c, rjr_context *ctx, const rj_model *m, const rj_state *s, rjr_view v, const char *name,
                        unsigned char *a, unsigned char *b, int box[4])
{
    static const unsigned cols[3] = { 0x1f5fbf, 0xf08c00, 0xd01f1f };
    long n, over, exact[3] = { 0, 0, 0 };
    int i, k, corner;
    v.show_legend = 0;
    render(ctx, m, s, &v, a);
    v.show_legend = 1;
    render(ctx, m, s, &v, b);
    n = diff_box(a, b, box);
    over = diff_on_drawn(a, b, a);
    corner = (box[0] < W / 4 || box[2] > 3 * W / 4) && (box[1] < H / 4 || box[3] > 3 * H / 4);
    for (i = 0; i < NPIX; i++)
        for (k = 0; k < 3; k++)
            exact[k] += differs(a, b, i) && is_rgb(b, i, cols[k], 0);
    rjt_check(c, n > 500 && corner && box[2] - box[0] < W / 3 && box[3] - box[1] < H / 4, name,
              "%ld pixels added in x %d..%d, y %d..%d (a corner, under a third of the width and a quarter of the height)", n, box[0], box[2], box[1], box[3]);
    rjt_check(c, over == 0, "legend covers nothing drawn", "%ld of its pixels were link, joint or text pixels without it", over);
    rjt_check(c, exact[0] >= 10 && exact[1] >= 10 && exact[2] >= 10, "legend shows the joint colours free, at a limit, locked",
              "%ld, %ld, %ld pixels of exactly 0x1f5fbf, 0xf08c00, 0xd01f1f", exact[0], exact[1], exact[2]);
}

/* the legend, then the same frame moved so the mechanism sits in that corner: the legend
   goes to another corner and still covers nothing */
static void test_legend(rjt_ctx *c, rjr_context *ctx, unsigned char *a, unsigned char *b)
{
    rj_model *m;
    rj_state *s;
    rjr_view v = deploy_view();
    int box[4], box2[4];
    double mx, my;
    if (deploy_at(3.1, &m, &s) != 0) {
        rjt_check(c, 0, "legend", "deploy model did not run");
        return;
    }
    legend_case(c, ctx, m, s, v, "legend in a corner (deploy, t = 3.1 s)", a, b, box);
    /* move the view so the elbow joint lands in the middle of the legend's box */
    {
        double p[2];
        rj_joint_position(m, s, 1, p);
        rjr_world_to_pixel(ctx, &v, p[0], p[1], &mx, &my);
    }
    v.cx += (mx - 0.5 * (box[0] + box[2])) * v.mpp;
    v.cy -= (my - 0.5 * (box[1] + box[3])) * v.mpp;
    legend_case(c, ctx, m, s, v, "legend moves away when the links come to its corner", a, b, box2);
    rjt_check(c, box2[0] != box[0] || box2[1] != box[1], "legend took another corner",
              "first at x %d, y %d; with the elbow there at x %d, y %d", box[0], box[1], box2[0], box2[1]);
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
}

/* labels: every added pixel lies near a joint (within 200 px: a label is up to about
   150 px long), each joint gets a label that starts within 60 px of it, and no label covers
   anything drawn (links, joints, texts) */
static void labels_case(rjt_ctx *c, rjr_context *ctx, const rj_model *m, const rj_state *s, rjr_view v, const char *name,
                        unsigned char *a, unsigned char *b)
{
    int i, j, nj = rj_model_joint_count(m), box[4];
    long n, far = 0, per[8] = { 0 }, over;
    double jx[8], jy[8], close[8];
    for (j = 0; j < nj && j < 8; j++) {
        double p[2];
        close[j] = 1e9;
        rj_joint_position(m, s, j, p);
        rjr_world_to_pixel(ctx, &v, p[0], p[1], &jx[j], &jy[j]);
    }
    render(ctx, m, s, &v, b);
    v.joint_names = NULL;
    v.show_joint_angles = 0;
    render(ctx, m, s, &v, a);
    n = diff_box(a, b, box);
    over = diff_on_drawn(a, b, a);
    for (i = 0; i < NPIX; i++) {
        double best = 1e9;
        int near = -1;
        if (!differs(a, b, i))
            continue;
        for (j = 0; j < nj && j < 8; j++)
            if (hypot(i % W - jx[j], i / W - jy[j]) < best) {
                best = hypot(i % W - jx[j], i / W - jy[j]);
                near = j;
            }
        far += best > 200;
        per[near]++;
        close[near] = best < close[near] ? best : close[near];
    }
    rjt_check(c, n > 100 && far == 0, name, "%ld pixels added, %ld of them farther than 200 px from every joint", n, far);
    for (j = 0; j < nj && j < 8; j++)
        rjt_check(c, per[j] > 40 && close[j] < 60, "a label beside each joint", "joint %d: %ld added pixels nearest to it, the nearest %.1f px away",
                  j, per[j], close[j]);
    rjt_check(c, over == 0, "labels cover nothing drawn", "%ld of their pixels were link, joint or text pixels without them", over);
}

static void test_labels(rjt_ctx *c, rjr_context *ctx, unsigned char *a, unsigned char *b)
{
    static const char *const names[2] = { "shoulder", "elbow" };
    static const double at[3] = { 0.0, 3.1, 6.0 };
    rj_model *m;
    rj_state *s;
    int k;
    if (deploy_at(0.0, &m, &s) != 0) {
        rjt_check(c, 0, "labels", "deploy model did not run");
        return;
    }
    for (k = 0; k < 3; k++) {
        rjr_view v = deploy_view();
        char name[80];
        rj_run(m, s, at[k], 0, NULL, NULL);
        v.joint_names = names;
        v.show_joint_angles = 1;
        snprintf(name, sizeof name, "joint labels near their joints (deploy, t = %.1f s)", at[k]);
        labels_case(c, ctx, m, s, v, name, a, b);
    }
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
}

/* the deploy arm at t = 6 s reaching the top edge of the frame, a long caption over it */
static rjr_view band_view(int band)
{
    rjr_view v = deploy_view();
    double box[4] = { -1.2, -0.3, 1.3, 2.02 };
    rjr_view_fit_box(&v, box, W, H, 2);
    v.caption = "a caption long enough to run across the top of the deployed arm";
    v.text_band = band;
    return v;
}

/* pixels the time stamp and caption add (full frame against the mechanism alone) that
   fall on the mechanism's pixels; *text: how many they add */
static long text_on_links(rjr_context *ctx, const rj_model *m, const rj_state *s, int band, unsigned char *a, unsigned char *b, long *text)
{
    rjr_view v = band_view(band);
    int box[4];
    render(ctx, m, s, &v, b);
    v.show_time = 0;
    v.caption = NULL;
    render(ctx, m, s, &v, a);
    *text = diff_box(a, b, box);
    return diff_on_drawn(a, b, a);
}

/* the band keeps the links out of the texts' line: without it the arm runs through the
   caption (so the check can fail), with it no text pixel falls on a mechanism pixel */
static void test_band(rjt_ctx *c, rjr_context *ctx, unsigned char *a, unsigned char *b)
{
    rj_model *m;
    rj_state *s;
    long off, on, text_off, text_on;
    if (deploy_at(6.0, &m, &s) != 0) {
        rjt_check(c, 0, "text band", "deploy model did not run");
        return;
    }
    off = text_on_links(ctx, m, s, 0, a, b, &text_off);
    on = text_on_links(ctx, m, s, 1, a, b, &text_on);
    rjt_check(c, off > 0, "without the band the arm runs through the caption (the check bites)", "%ld text pixels of %ld on mechanism pixels", off, text_off);
    rjt_check(c, on == 0 && text_on > 500, "with the band no text pixel falls on the mechanism", "%ld text pixels of %ld on mechanism pixels", on, text_on);
    /* rjr_world_to_pixel follows the band: the tip mass (a dark square) is where it says */
    {
        rjr_view v = band_view(1);
        double p[2], x, y;
        int i;
        rj_node_position(m, s, 1, rj_link_node_count(m, 1) - 1, p);
        rjr_world_to_pixel(ctx, &v, p[0], p[1], &x, &y);
        render(ctx, m, s, &v, b);
        i = (int)y * W + (int)x;
        rjt_check(c, b[3 * i] < 128 && b[3 * i + 1] < 128, "rjr_world_to_pixel follows the band (the tip mass is at the pixel it gives)",
                  "pixel (%d, %d) = %02x%02x%02x", (int)x, (int)y, b[3 * i], b[3 * i + 1], b[3 * i + 2]);
    }
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
}

/* a caption too long for the line: time stamp and caption stay apart (2 px between
   them). Time pixels: time stamp alone against neither; caption pixels: both against the
   time stamp alone. */
static void test_caption_fit(rjt_ctx *c, rjr_context *ctx, unsigned char *a, unsigned char *b, unsigned char *t)
{
    rj_model *m;
    rj_state *s;
    rjr_view v = deploy_view();
    int i, box[4];
    long both = 0, ncap;
    if (deploy_at(0.0, &m, &s) != 0) {
        rjt_check(c, 0, "caption fit", "deploy model did not run");
        return;
    }
    v.caption = "a caption far too long for one line beside the time stamp: it shrinks, then loses its end";
    render(ctx, m, s, &v, b);        /* time stamp and caption */
    v.caption = NULL;
    render(ctx, m, s, &v, t);        /* time stamp alone */
    v.show_time = 0;
    render(ctx, m, s, &v, a);        /* neither */
    ncap = diff_box(t, b, box);
    for (i = 0; i < NPIX; i++) {
        int x = i % W, y = i / W, dx, dy, near = 0;
        if (!differs(t, b, i))
            continue;
        for (dy = -2; dy <= 2; dy++)
            for (dx = -2; dx <= 2; dx++)
                if (x + dx >= 0 && x + dx < W && y + dy >= 0 && y + dy < H)
                    near |= differs(a, t, (y + dy) * W + x + dx);
        both += near;
    }
    rjt_check(c, ncap > 300 && both == 0, "a long caption keeps clear of the time stamp",
              "caption %ld pixels in x %d..%d, %ld of them within 2 px of the time stamp", ncap, box[0], box[2], both);
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
}

/* the fill colours met along pixel row y, in order, and whether a pixel darker than both
   neighbouring fills (the outline) lies between every two of them */
static int row_fills(const unsigned char *img, int y, const unsigned *fills, int nf, int *order, int *outlined)
{
    int x, n = 0, last = -1, dark = 0;
    *outlined = 1;
    for (x = 0; x < W; x++) {
        int k, i = y * W + x, lum = img[3 * i] + img[3 * i + 1] + img[3 * i + 2];
        dark |= lum < 330;
        for (k = 0; k < nf; k++) {
            if (!is_rgb(img, i, fills[k], 6) || k == last)
                continue;
            if (n > 0 && !dark)
                *outlined = 0;
            if (n < 8)
                order[n] = k;
            n++;
            last = k;
            dark = 0;
        }
    }
    return n;
}

/* the solar array stowed (t = 0): its four panels lie on one another. Separated, a row
   across them meets the four panel colours in order with a dark outline between each two;
   without the option only the top panel shows (the check bites). */
static void stowed_case(rjt_ctx *c, rjr_context *ctx, const rj_model *m, const rj_state *s, rjr_view v, const char *name, unsigned char *a)
{
    static const unsigned fills[4] = { 0x9fcf9a, 0xf2c27e, 0xc3a8e0, 0xe8a3a8 };   /* links 1..4 */
    int order[8], outlined, n, nsep;
    double x, y;
    rjr_world_to_pixel(ctx, &v, 0.3, -0.5, &x, &y);
    render(ctx, m, s, &v, a);
    n = row_fills(a, (int)y, fills, 4, order, &outlined);
    rjt_check(c, n <= 1, "stowed panels without separation show one panel", "%s: %d panel colours on row %d", name, n, (int)y);
    v.separate_stacked = 1;
    render(ctx, m, s, &v, a);
    nsep = row_fills(a, (int)y, fills, 4, order, &outlined);
    rjt_check(c, nsep == 4 && order[0] == 0 && order[1] == 1 && order[2] == 2 && order[3] == 3 && outlined,
              "stowed panels separated: four colours in order, an outline between each two",
              "%s: %d panel colours on row %d (order %d %d %d %d), outlines between them: %s", name, nsep, (int)y,
              order[0], nsep > 1 ? order[1] : -1, nsep > 2 ? order[2] : -1, nsep > 3 ? order[3] : -1, outlined ? "yes" : "no");
}

static void test_stowed(rjt_ctx *c, rjr_context *ctx, unsigned char *a)
{
    rj_scene_file sf;
    rj_scene_def sd;
    rj_model *m;
    rj_state *s;
    rj_error e;
    rjr_view v = rjr_view_default();
    double box[4] = { -0.3, -3.2, 4.4, 0.4 };   /* the whole deployment, as animate fits it */
    if (rj_scene_load("examples/scenes/solar_array.rjs", &sf, &e) != RJ_OK) {
        rjt_check(c, 0, "stowed panels", "%s", e.msg);
        return;
    }
    sd = rj_scene_file_def(&sf);
    if (rj_model_create(&sd, &m, &e, NULL) != RJ_OK || rj_state_create(m, &s, NULL) != RJ_OK) {
        rjt_check(c, 0, "stowed panels", "%s", e.msg);
        rj_scene_file_free(&sf);
        return;
    }
    rjr_view_fit(&v, m, s, W, H, 60);
    stowed_case(c, ctx, m, s, v, "fitted to the stowed array", a);
    v = rjr_view_default();
    rjr_view_fit_box(&v, box, W, H, 20);
    stowed_case(c, ctx, m, s, v, "the whole deployment in view (3 px panels)", a);
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
    rj_scene_file_free(&sf);
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
    test_legend(&c, ctx, img, img2);
    test_labels(&c, ctx, img, img2);
    test_band(&c, ctx, img, img2);
    {
        unsigned char *img3 = (unsigned char *)malloc(W * H * 3);
        test_caption_fit(&c, ctx, img, img2, img3);
        free(img3);
    }
    test_stowed(&c, ctx, img);
done:
    rjr_destroy(ctx);
    free(img); free(img2);
    return rjt_summary(&c, "test_render");
}
