/* selftest.c - tests for rj_render: context, text, plots, PNG round trip, determinism,
   comparison, mechanism frames; "--bench" adds timings. Writes /tmp/rjr_*.png (or the
   directory given with --out DIR) for visual inspection.
   Ends with the line "N passed, N failed"; exit status 0 only when nothing failed. */
#define _POSIX_C_SOURCE 199309L
#define REVJOINT_IMPLEMENTATION
#include "../revjoint.h"
#include "rj_render.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

typedef struct tally { int pass, fail; } tally;

static void check(tally *t, int ok, const char *what, const char *detail)
{
    if (ok) t->pass++;
    else t->fail++;
    printf("%s %s%s%s\n", ok ? "ok  " : "FAIL", what, detail && *detail ? ": " : "", detail ? detail : "");
}

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : (x > y);
}

static double median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

static const char *outdir = "/tmp";

static const char *out_path(const char *name)
{
    static char buf[4][512];
    static int k;
    k = (k + 1) % 4;
    snprintf(buf[k], sizeof buf[k], "%s/%s", outdir, name);
    return buf[k];
}

/* ---- scenes ---- */

typedef struct scene {
    rj_link_def links[4];
    rj_joint_def joints[4];
    rj_scene_def def;
    rj_model *m;
    rj_state *s;
} scene;

/* Two links: joint 0 ground pin (body1 -1, body2 0), joint 1 between links 0 and 1, both
   with reverse and forward limits. extra_deg rotates link 1 (joint 1 angle0). */
static int make_two_link(scene *sc, double extra_deg, char *err, size_t errlen)
{
    rj_error e;
    memset(sc, 0, sizeof *sc);
    sc->links[0] = rj_default_link_def();
    sc->links[1] = rj_default_link_def();
    sc->links[1].length = 0.8;
    sc->links[1].height = 0.08;
    sc->links[1].tip_mass = 2.0;
    sc->links[0].height = 0.1;
    sc->joints[0] = rj_default_joint_def();
    sc->joints[0].body1 = -1; sc->joints[0].body2 = 0;
    sc->joints[0].ground_angle = 0.0;
    sc->joints[0].angle0 = rj_rad(40.0);
    sc->joints[0].has_reverse = 1; sc->joints[0].reverse = rj_rad(10.0);
    sc->joints[0].has_forward = 1; sc->joints[0].forward = rj_rad(150.0);
    sc->joints[1] = rj_default_joint_def();
    sc->joints[1].body1 = 0; sc->joints[1].body2 = 1;
    sc->joints[1].angle0 = rj_rad(130.0 + extra_deg);
    sc->joints[1].has_reverse = 1; sc->joints[1].reverse = rj_rad(90.0);
    sc->joints[1].has_forward = 1; sc->joints[1].forward = rj_rad(250.0);
    sc->def = rj_default_scene_def();
    sc->def.links = sc->links; sc->def.link_count = 2;
    sc->def.joints = sc->joints; sc->def.joint_count = 2;
    sc->def.solver = rj_default_solver_def();
    if (rj_model_create(&sc->def, &sc->m, &e, NULL) != RJ_OK) { snprintf(err, errlen, "%s", e.msg); return -1; }
    if (rj_state_create(sc->m, &sc->s, NULL) != RJ_OK) { snprintf(err, errlen, "rj_state_create failed"); return -1; }
    return 0;
}

/* A richer scene: a fixed ground beam, a clamped cantilever with a tip mass, and a
   pinned two-link arm that swings into its limit. */
static int make_rich(scene *sc, char *err, size_t errlen)
{
    rj_error e;
    memset(sc, 0, sizeof *sc);
    sc->links[0] = rj_default_link_def();           /* fixed beam (ground body) */
    sc->links[0].root = RJ_ROOT_FIXED;
    sc->links[0].x = -0.2; sc->links[0].y = 0.0; sc->links[0].length = 1.4; sc->links[0].height = 0.06;
    sc->links[0].elements = 4;
    sc->links[1] = rj_default_link_def();           /* arm 1, pinned to the beam end */
    sc->links[1].length = 0.7; sc->links[1].height = 0.05; sc->links[1].E = 2e8;
    sc->links[2] = rj_default_link_def();           /* arm 2 */
    sc->links[2].length = 0.6; sc->links[2].height = 0.04; sc->links[2].tip_mass = 1.0; sc->links[2].E = 2e9;
    sc->links[3] = rj_default_link_def();           /* clamped cantilever */
    sc->links[3].root = RJ_ROOT_CLAMPED; sc->links[3].x = -0.6; sc->links[3].y = 0.4;
    sc->links[3].angle = rj_rad(-10.0); sc->links[3].length = 0.5; sc->links[3].height = 0.03;
    sc->joints[0] = rj_default_joint_def();
    sc->joints[0].body1 = 0; sc->joints[0].node1 = -1; sc->joints[0].body2 = 1;
    sc->joints[0].angle0 = rj_rad(120.0); sc->joints[0].rate0 = 6.0;
    sc->joints[0].has_forward = 1; sc->joints[0].forward = rj_rad(160.0);
    sc->joints[1] = rj_default_joint_def();
    sc->joints[1].body1 = 1; sc->joints[1].body2 = 2;
    sc->joints[1].angle0 = rj_rad(200.0);
    sc->joints[1].has_reverse = 1; sc->joints[1].reverse = rj_rad(100.0);
    sc->joints[1].has_forward = 1; sc->joints[1].forward = rj_rad(260.0);
    sc->joints[1].lock = 1;
    sc->def = rj_default_scene_def();
    sc->def.links = sc->links; sc->def.link_count = 4;
    sc->def.joints = sc->joints; sc->def.joint_count = 2;
    sc->def.solver = rj_default_solver_def();
    if (rj_model_create(&sc->def, &sc->m, &e, NULL) != RJ_OK) { snprintf(err, errlen, "%s", e.msg); return -1; }
    if (rj_state_create(sc->m, &sc->s, NULL) != RJ_OK) { snprintf(err, errlen, "rj_state_create failed"); return -1; }
    return 0;
}

static void free_scene(scene *sc)
{
    if (sc->s) rj_state_destroy(sc->s, NULL);
    if (sc->m) rj_model_destroy(sc->m, NULL);
    sc->s = NULL; sc->m = NULL;
}

/* ---- pages ---- */

static int draw_text_page(rjr_context *c)
{
    static const char *lines[] = {
        "0123456789 +-=.,:/%()[]_'*<>!?#",
        "ABCDEFGHIJKLMNOPQRSTUVWXYZ",
        "abcdefghijklmnopqrstuvwxyz",
        "The quick brown fox jumps over the lazy dog.",
        "t = 0.0125 s   lock 2   E = 70e9 Pa   1e-6   12.5%",
    };
    double sizes[] = { 8, 10, 12, 16, 24 };
    double y = 14;
    int i, k;
    if (rjr_begin(c, 0xffffff) != 0) return -1;
    for (k = 0; k < 5; k++) {
        for (i = 0; i < 5; i++) {
            if (k < 2 && i == 3) continue;
            y += sizes[k] * 1.75;
            if (y > rjr_height(c) - 95) break;
            rjr_text(c, 10, y, sizes[k], 0.0, RJR_LEFT | RJR_BASELINE, 0x202020, lines[i]);
        }
    }
    /* alignment marks and rotated text */
    rjr_rect(c, 200, 400, 1, 75, 0xcc0000);
    rjr_rect(c, 120, 430, 160, 1, 0xcc0000);
    rjr_text(c, 200, 430, 14, 0.0, RJR_RIGHT | RJR_BASELINE, 0x1f5fbf, "right");
    rjr_text(c, 200, 430, 14, 0.0, RJR_LEFT | RJR_TOP, 0x1f5fbf, "top-left");
    rjr_text(c, 200, 460, 14, 0.0, RJR_CENTER | RJR_MIDDLE, 0x1f5fbf, "centre-middle");
    rjr_text(c, 620, 470, 14, 90.0, RJR_LEFT | RJR_BASELINE, 0x2ca02c, "rotated 90");
    rjr_text(c, 380, 470, 14, 30.0, RJR_LEFT | RJR_BASELINE, 0xd62728, "30 deg");
    return rjr_end(c);
}

static int draw_sine_plot(rjr_context *c)
{
    static double x[400], y1[400], y2[400], y3[40], x3[40];
    rjr_plot_def d = rjr_plot_default();
    int i;
    for (i = 0; i < 400; i++) {
        x[i] = i * 0.025;
        y1[i] = sin(x[i]);
        y2[i] = 0.8 * cos(x[i]) * exp(-0.1 * x[i]);
    }
    for (i = 0; i < 40; i++) {
        x3[i] = i * 0.25;
        y3[i] = 0.5 * sin(2.0 * x3[i]);
    }
    d.title = "Joint angles (sine / cosine test)";
    d.xlabel = "time t [s]";
    d.ylabel = "theta [rad]";
    d.series_count = 3;
    d.series[0].x = x; d.series[0].y = y1; d.series[0].n = 400; d.series[0].label = "sin(t)";
    d.series[1].x = x; d.series[1].y = y2; d.series[1].n = 400; d.series[1].label = "0.8 cos(t) exp(-t/10)";
    d.series[1].dashed = 1;
    d.series[2].x = x3; d.series[2].y = y3; d.series[2].n = 40; d.series[2].label = "samples";
    d.series[2].points = 1; d.series[2].width_px = 1.0;
    d.marker_count = 3;
    d.markers[0].x = 1.5708; d.markers[0].label = "lock 2";
    d.markers[1].x = 4.2; d.markers[1].label = "release";
    d.markers[2].x = 9.6; d.markers[2].label = "limit 1";
    return rjr_plot(c, &d);
}

static int draw_loglog_plot(rjr_context *c)
{
    static double t1[6], e1[6], t2[6], e2[6];
    rjr_plot_def d = rjr_plot_default();
    int i;
    for (i = 0; i < 6; i++) {
        double dt = pow(2.0, -i);
        t1[i] = 0.003 / dt;  e1[i] = 0.05 * dt * dt;
        t2[i] = 0.011 / dt;  e2[i] = 2e-3 * pow(dt, 4.0);
    }
    d.title = "Work-precision";
    d.xlabel = "wall time [s]";
    d.ylabel = "error at t = 1 s";
    d.logx = d.logy = 1;
    d.series_count = 2;
    d.series[0].x = t1; d.series[0].y = e1; d.series[0].n = 6; d.series[0].label = "central difference";
    d.series[0].points = 1;
    d.series[1].x = t2; d.series[1].y = e2; d.series[1].n = 6; d.series[1].label = "RK4 (reference)";
    d.series[1].points = 1; d.series[1].dashed = 1;
    d.legend = RJR_LEGEND_BOTTOM_LEFT;
    return rjr_plot(c, &d);
}

/* ---- main ---- */

int main(int argc, char **argv)
{
    tally t = { 0, 0 };
    char err[512], msg[512];
    rjr_context *c;
    int W = 640, H = 480, i, bench = 0;
    unsigned char *a, *b, *l;
    int lw, lh;
    rjr_diff df;

    for (i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--bench")) bench = 1;
        else if (!strcmp(argv[i], "--out") && i + 1 < argc) outdir = argv[++i];
        else { fprintf(stderr, "usage: %s [--bench] [--out DIR]\n", argv[0]); return 2; }
    }

    c = rjr_create(W, H, err, sizeof err);
    check(&t, c != NULL, "rjr_create 640x480", c ? "" : err);
    if (!c) { printf("%d passed, %d failed\n", t.pass, t.fail); return 1; }
    printf("     backend %s, GL_RENDERER %s, GL_VERSION %s, samples %d\n", rjr_backend(c), rjr_gl_renderer(c),
           rjr_gl_version(c), rjr_samples(c));
    check(&t, strncmp(rjr_gl_renderer(c), "llvmpipe", 8) == 0, "renderer is llvmpipe", rjr_gl_renderer(c));
    check(&t, rjr_samples(c) == 4, "4x MSAA", "");

    a = (unsigned char *)malloc((size_t)1280 * 720 * 3);
    b = (unsigned char *)malloc((size_t)1280 * 720 * 3);
    if (!a || !b) return 1;

    /* text */
    check(&t, draw_text_page(c) == 0, "text page", rjr_error(c));
    check(&t, rjr_save_png(c, out_path("rjr_text.png"), err, sizeof err) == 0, "save rjr_text.png", err);
    check(&t, rjr_text_width("", 12) == 0.0 && rjr_text_width("1", 12) > 0, "text width", "");
    check(&t, fabs(rjr_text_width("0123", 12) - rjr_text_width("9876", 12)) < 1e-9, "digits have equal width", "");

    /* plots */
    check(&t, draw_sine_plot(c) == 0, "sine/cosine plot", rjr_error(c));
    check(&t, rjr_save_png(c, out_path("rjr_plot_sin.png"), err, sizeof err) == 0, "save rjr_plot_sin.png", err);
    rjr_read_pixels(c, a);
    {   /* the plot background is white, the frame is drawn */
        long nonwhite = 0;
        for (i = 0; i < W * H; i++) nonwhite += (a[3 * i] != 255 || a[3 * i + 1] != 255 || a[3 * i + 2] != 255);
        snprintf(msg, sizeof msg, "%ld non-white pixels, top-left %d %d %d", nonwhite, a[0], a[1], a[2]);
        check(&t, nonwhite > 5000 && a[0] == 255 && a[1] == 255 && a[2] == 255, "plot has content on white", msg);
    }
    check(&t, draw_loglog_plot(c) == 0, "log-log plot", rjr_error(c));
    check(&t, rjr_save_png(c, out_path("rjr_plot_loglog.png"), err, sizeof err) == 0, "save rjr_plot_loglog.png", err);
    {
        rjr_plot_def d = rjr_plot_default();
        double x[3] = { 1, 2, 3 }, y[3] = { 1, -1, 2 };
        d.logy = 1; d.ymin = -1; d.ymax = 10;
        d.series_count = 1; d.series[0].x = x; d.series[0].y = y; d.series[0].n = 3;
        check(&t, rjr_plot(c, &d) != 0 && rjr_error(c)[0], "log axis with negative range is an error", rjr_error(c));
        d = rjr_plot_default();                                /* empty plot */
        check(&t, rjr_plot(c, &d) == 0, "empty plot", rjr_error(c));
    }

    /* determinism and PNG round trip */
    draw_sine_plot(c);
    rjr_read_pixels(c, a);
    draw_text_page(c);
    draw_sine_plot(c);
    rjr_read_pixels(c, b);
    check(&t, memcmp(a, b, (size_t)W * H * 3) == 0, "render twice gives identical pixels", "");
    check(&t, rjr_write_png(out_path("rjr_roundtrip.png"), a, W, H, err, sizeof err) == 0, "write png", err);
    check(&t, rjr_load_png(out_path("rjr_roundtrip.png"), &l, &lw, &lh, err, sizeof err) == 0, "load png", err);
    if (l) {
        check(&t, lw == W && lh == H && memcmp(a, l, (size_t)W * H * 3) == 0, "png round trip is exact", "");
        free(l);
    }
    check(&t, rjr_load_png(out_path("does-not-exist.png"), &l, &lw, &lh, err, sizeof err) != 0 && err[0], "load missing file fails", err);
    check(&t, rjr_write_png("/nonexistent-dir/x.png", a, W, H, err, sizeof err) != 0 && err[0], "write to bad path fails", err);

    /* comparison: identical, then shifted by one pixel */
    rjr_compare(a, b, W, H, 16, &df);
    check(&t, df.max_delta == 0 && df.bad_pixels == 0 && isinf(df.psnr), "compare identical", "");
    memcpy(b, a, (size_t)W * H * 3);
    for (i = 0; i < H; i++) memmove(b + (size_t)i * W * 3 + 3, a + (size_t)i * W * 3, (size_t)(W - 1) * 3);
    rjr_compare(a, b, W, H, 16, &df);
    snprintf(msg, sizeof msg, "max %d, bad %ld, psnr %.2f dB", df.max_delta, df.bad_pixels, df.psnr);
    check(&t, df.bad_pixels > 1000 && df.max_delta > 100 && df.psnr < 30, "compare 1-px shift finds bad pixels", msg);
    check(&t, rjr_write_diff_png(out_path("rjr_diff_shift.png"), a, b, W, H, 16, err, sizeof err) == 0, "write diff png", err);

    /* a second context of another size, used in between, does not disturb the first */
    {
        rjr_context *c2 = rjr_create(320, 240, err, sizeof err);
        check(&t, c2 != NULL, "second context 320x240", c2 ? "" : err);
        if (c2) {
            draw_sine_plot(c);
            check(&t, draw_loglog_plot(c2) == 0 && rjr_save_png(c2, out_path("rjr_plot_loglog_320.png"), err, sizeof err) == 0,
                  "plot in the second context", err);
            rjr_read_pixels(c, b);
            check(&t, memcmp(a, b, (size_t)W * H * 3) == 0, "first context unchanged by the second", "");
            rjr_destroy(c2);
            draw_sine_plot(c);
            rjr_read_pixels(c, b);
            check(&t, memcmp(a, b, (size_t)W * H * 3) == 0, "first context works after destroying the second", "");
        }
    }

    /* resize */
    check(&t, rjr_resize(c, 1280, 720) == 0 && rjr_width(c) == 1280 && rjr_height(c) == 720, "resize to 1280x720", rjr_error(c));
    check(&t, draw_loglog_plot(c) == 0 && rjr_save_png(c, out_path("rjr_plot_loglog_720.png"), err, sizeof err) == 0,
          "log-log plot at 1280x720", err);
    check(&t, rjr_resize(c, W, H) == 0, "resize back", rjr_error(c));

    /* mechanism frames */
    {
        scene s1, s2, s3;
        rjr_view v;
        double box[4];
        if (make_two_link(&s1, 0.0, err, sizeof err) != 0) check(&t, 0, "two-link model", err);
        else {
            v = rjr_view_default();
            check(&t, rjr_view_fit(&v, s1.m, s1.s, W, H, 60) == 0, "view fit", "");
            check(&t, rjr_draw_state(c, s1.m, s1.s, &v) == 0, "draw two-link state", rjr_error(c));
            check(&t, rjr_save_png(c, out_path("rjr_scene.png"), err, sizeof err) == 0, "save rjr_scene.png", err);
            rjr_read_pixels(c, a);
            rjr_draw_state(c, s1.m, s1.s, &v);
            rjr_read_pixels(c, b);
            check(&t, memcmp(a, b, (size_t)W * H * 3) == 0, "scene render twice identical", "");
            /* link 1 rotated by 0.5 degree */
            if (make_two_link(&s2, 0.5, err, sizeof err) == 0) {
                rjr_draw_state(c, s2.m, s2.s, &v);
                rjr_read_pixels(c, b);
                rjr_compare(a, b, W, H, 16, &df);
                snprintf(msg, sizeof msg, "max %d, bad(>16) %ld, psnr %.2f dB", df.max_delta, df.bad_pixels, df.psnr);
                check(&t, df.bad_pixels > 32, "link 1 rotated 0.5 deg is detected", msg);
                rjr_write_diff_png(out_path("rjr_diff_rot05.png"), a, b, W, H, 16, err, sizeof err);
                free_scene(&s2);
            }
            if (make_two_link(&s2, 0.1, err, sizeof err) == 0) {
                rjr_draw_state(c, s2.m, s2.s, &v);
                rjr_read_pixels(c, b);
                rjr_compare(a, b, W, H, 16, &df);
                snprintf(msg, sizeof msg, "max %d, bad(>16) %ld, psnr %.2f dB", df.max_delta, df.bad_pixels, df.psnr);
                check(&t, df.bad_pixels > 0, "link 1 rotated 0.1 deg changes pixels", msg);
                free_scene(&s2);
            }
            /* thin links (no exaggeration), nodes shown */
            v.thickness_factor = 0.2; v.show_nodes = 1; v.caption = "factor 0.2, nodes";
            check(&t, rjr_draw_state(c, s1.m, s1.s, &v) == 0 && rjr_save_png(c, out_path("rjr_scene_thin.png"), err, sizeof err) == 0,
                  "thin scene", err);
            free_scene(&s1);
        }
        if (make_rich(&s3, err, sizeof err) != 0) check(&t, 0, "rich model", err);
        else {
            int k, f0 = 0, f1 = 0, frames = 0;
            v = rjr_view_default();
            /* fix the view over the whole run so the frames do not jump */
            rjr_bbox_init(box);
            rjr_bbox_add(box, s3.m, s3.s);
            rjr_view_fit_box(&v, box, W, H, 70);
            v.caption = "rich scene";
            check(&t, rjr_draw_state(c, s3.m, s3.s, &v) == 0 && rjr_save_png(c, out_path("rjr_rich_0.png"), err, sizeof err) == 0,
                  "rich scene t = 0", err);
            for (k = 0; k < 400 && rj_state_time(s3.s) < 0.6; k++) {
                if (rj_run(s3.m, s3.s, rj_state_time(s3.s) + 0.0015, 0.0, NULL, NULL) != RJ_OK) break;
                f0 = rj_joint_flag(s3.m, s3.s, 0);
                f1 = rj_joint_flag(s3.m, s3.s, 1);
                if (f0 != RJ_FREE || f1 != RJ_FREE) { frames++; if (frames > 3) break; }
            }
            snprintf(msg, sizeof msg, "t = %.4f, flags %d %d, error '%s'", rj_state_time(s3.s), f0, f1, rj_state_error(s3.s));
            check(&t, rjr_draw_state(c, s3.m, s3.s, &v) == 0 && rjr_save_png(c, out_path("rjr_rich_1.png"), err, sizeof err) == 0,
                  "rich scene later", msg);
            free_scene(&s3);
        }
    }

    if (bench) {
        int sizes[2][2] = { { 640, 480 }, { 1280, 720 } }, z, n = 15;
        double td[15], tp[15], tt[15];
        scene s1;
        if (make_two_link(&s1, 0.0, err, sizeof err) == 0) {
            for (z = 0; z < 2; z++) {
                rjr_view v = rjr_view_default();
                int w = sizes[z][0], h = sizes[z][1];
                rjr_resize(c, w, h);
                rjr_view_fit(&v, s1.m, s1.s, w, h, 60);
                for (i = 0; i < 2; i++) { rjr_draw_state(c, s1.m, s1.s, &v); rjr_read_pixels(c, a); }   /* warm up */
                for (i = 0; i < n; i++) {
                    double t0 = now_ms(), t1, t2;
                    rjr_draw_state(c, s1.m, s1.s, &v);
                    rjr_read_pixels(c, a);
                    t1 = now_ms();
                    rjr_write_png(out_path("rjr_bench.png"), a, w, h, err, sizeof err);
                    t2 = now_ms();
                    td[i] = t1 - t0; tp[i] = t2 - t1; tt[i] = t2 - t0;
                }
                printf("bench %dx%d scene: draw+readback %.2f ms, png write %.2f ms, total %.2f ms (median of %d)\n",
                       w, h, median(td, n), median(tp, n), median(tt, n), n);
                for (i = 0; i < n; i++) {
                    double t0 = now_ms(), t1, t2;
                    draw_sine_plot(c);
                    rjr_read_pixels(c, a);
                    t1 = now_ms();
                    rjr_write_png(out_path("rjr_bench.png"), a, w, h, err, sizeof err);
                    t2 = now_ms();
                    td[i] = t1 - t0; tp[i] = t2 - t1; tt[i] = t2 - t0;
                }
                printf("bench %dx%d plot : draw+readback %.2f ms, png write %.2f ms, total %.2f ms (median of %d)\n",
                       w, h, median(td, n), median(tp, n), median(tt, n), n);
            }
            free_scene(&s1);
        }
    }

    free(a);
    free(b);
    rjr_destroy(c);
    printf("%d passed, %d failed\n", t.pass, t.fail);
    return t.fail ? 1 : 0;
}
