/* animate - renders an example scene to numbered PNG frames DIR/frame_00000.png ...
   Turn them into a video with, for example:
     ffmpeg -framerate 30 -i out/frames/frame_%05d.png -pix_fmt yuv420p deploy.mp4 */
#define _POSIX_C_SOURCE 200809L
#define REVJOINT_IMPLEMENTATION
#include "../revjoint.h"
#include "scenes.h"
#include "cli.h"
#include "../render/rj_render.h"
#include <time.h>
#include <unistd.h>

static const char usage[] =
    "usage: animate [options]\n"
    "  --scene deploy|impact|FILE.rjs   a benchmark, or a scene file (default deploy)\n"
    "  --out DIR               frames directory (default out/frames)\n"
    "  --fps N                 frames per simulated second (default 30 for deploy, 20000 for impact)\n"
    "  --size WxH              image size (default 640x480)\n"
    "  --t-end S               simulated time (default 6 deploy, 0.02 impact)\n"
    "  --thickness F           drawn thickness = F x true (default 2 deploy, 1 impact)\n"
    "  --force                 run even above 1e8 steps or 1e5 frames (refused otherwise)\n"
    "  --legend                a key to the joint colours (free, at a limit, locked)\n"
    "  --labels                each joint's name and running angle (deg) beside it\n"
    "  --band                  a band at the top for the time and caption, clear of the links\n"
    "  --separate              links lying on one another (stowed panels) drawn side by side\n"
    "  The caption is the scene file's title, else its path.\n"
    "  DIR and its parents are created; frame_NNNNN.png files already there are removed.\n";

typedef struct anim {
    rjr_context *ctx; rjr_view view; const char *dir; double fdt; int frame, total, tty;
    int failed;   /* a frame could not be written: the run stopped there */
} anim;

/* joint names of the built-in scenes, as in their scene files */
static const char *const deploy_names[] = { "j1", "j2" };
static const char *const impact_names[] = { "hinge" };

/* the view options the flags turn on; labels take the scene's joint names */
typedef struct aids { int legend, labels, band, separate; } aids;

static void apply_aids(rjr_view *v, const aids *x, const char *const *names)
{
    v->show_legend = x->legend;
    v->show_joint_angles = x->labels;
    v->joint_names = x->labels ? names : NULL;
    v->text_band = x->band;
    v->separate_stacked = x->separate;
}

static int on_sample(const rj_model *m, const rj_state *s, void *u)
{
    anim *a = (anim *)u;
    char path[4200], err[256];
    /* rj_run takes a nonzero return as "stop", not as an error: remember it */
    if (cli_frame_path("animate", path, sizeof path, a->dir, a->frame) != 0) {
        a->failed = 1;
        return 1;
    }
    err[0] = '\0';
    if (rjr_draw_state(a->ctx, m, s, &a->view) || rjr_save_png(a->ctx, path, err, sizeof err)) {
        /* the PNG writer's text has the system's reason; a drawing error is the context's */
        const char *why = err[0] ? err : rjr_error(a->ctx);
        fprintf(stderr, "%sanimate: cannot write %s: %s\n", a->tty ? "\n" : "", path, why);
        a->failed = 1;
        return 1;
    }
    a->frame++;
    if (a->tty) fprintf(stderr, "\ranimate: frame %d/%d  t = %.4f s ", a->frame, a->total, rj_state_time(s));
    return 0;
}

int main(int argc, char **argv)
{
    static const char *const scenes[] = { "deploy", "impact" };
    cli c;
    /* --size: each side 16 .. 8192 pixels */
    static const int size_lim[4] = { 16, 8192, 16, 8192 };
    int scene = 0, w = 640, h = 480, force = 0, k;
    aids ax = { 0, 0, 0, 0 };
    rj_scene_file sf;
    const char *names[RJ_SCENE_MAX_JOINTS];
    double fps = -1, t_end = -1, thick = -1, frames;
    const char *dir = "out/frames", *a, *scene_file = NULL;
    anim an;
    rj_model *m = NULL; rj_state *s; rj_error e;
    char err[256];
    clock_t c0;
    c.argc = argc; c.argv = argv; c.i = 0; c.usage = usage;
    while ((a = cli_next(&c)) != NULL) {
        if (!strcmp(a, "--scene")) {
            const char *v = cli_str(&c, a);
            size_t n = strlen(v);
            if (n > 4 && !strcmp(v + n - 4, ".rjs")) { scene = 2; scene_file = v; }
            else { c.i--; scene = cli_choice(&c, a, scenes, 2); }
        }
        else if (!strcmp(a, "--out")) dir = cli_str(&c, a);
        else if (!strcmp(a, "--fps")) fps = cli_num(&c, a, 1e-3, 1e9);
        else if (!strcmp(a, "--t-end")) t_end = cli_num(&c, a, 0, 1e6);
        else if (!strcmp(a, "--thickness")) thick = cli_num(&c, a, 0.01, 1000);
        else if (!strcmp(a, "--size")) cli_pair(&c, a, 'x', &w, &h, size_lim, "WxH, each 16..8192");
        else if (!strcmp(a, "--force")) force = 1;
        else if (!strcmp(a, "--legend")) ax.legend = 1;
        else if (!strcmp(a, "--labels")) ax.labels = 1;
        else if (!strcmp(a, "--band")) ax.band = 1;
        else if (!strcmp(a, "--separate")) ax.separate = 1;
        else if (!strcmp(a, "--help") || !strcmp(a, "-h")) { fputs(usage, stdout); return 0; }
        else cli_die(&c, "unknown option '%s'%s", a, "");
    }
    memset(&an, 0, sizeof an);
    memset(&sf, 0, sizeof sf);
    an.view = rjr_view_default();
    if (scene == 0) {
        deploy_opts o = deploy_default_opts();
        double box[4] = { -1.2, -0.3, 1.3, 2.2 };
        if (deploy_build(&o, &m, &e) != RJ_OK) { fprintf(stderr, "animate: %s\n", e.msg); return 1; }
        fps = fps < 0 ? 30 : fps; t_end = t_end < 0 ? 6 : t_end; thick = thick < 0 ? 2 : thick;
        rjr_view_fit_box(&an.view, box, w, h, 20);
        an.view.caption = "two-link deployment (paper sec. 5)";
        apply_aids(&an.view, &ax, deploy_names);
    } else if (scene == 2) {
        rj_scene_def sd;
        if (rj_scene_load(scene_file, &sf, &e) != RJ_OK) { fprintf(stderr, "animate: %s\n", e.msg); return 1; }
        sd = rj_scene_file_def(&sf);
        if (rj_model_create(&sd, &m, &e, NULL) != RJ_OK) { rj_scene_file_locate(&sf, &e); fprintf(stderr, "animate: %s\n", e.msg); return 1; }
        fps = fps < 0 ? 30 : fps; t_end = t_end < 0 ? 6 : t_end; thick = thick < 0 ? 2 : thick;
        /* the file's title names the scene for people; its path when it has none. The names
           and the title live in sf, freed at the end. */
        an.view.caption = sf.title[0] ? sf.title : scene_file;
        for (k = 0; k < sf.joint_count; k++)
            names[k] = sf.joint_names[k];
        apply_aids(&an.view, &ax, names);
    } else {
        impact_opts o = impact_default_opts();
        rj_link_def L[2]; rj_joint_def J; rj_scene_def sc;
        double box[4] = { -1.1, -0.6, 1.1, 0.6 };
        impact_scene(&o, L, &J, &sc);
        if (rj_model_create(&sc, &m, &e, NULL) != RJ_OK) { fprintf(stderr, "animate: %s\n", e.msg); return 1; }
        fps = fps < 0 ? 20000 : fps; t_end = t_end < 0 ? 0.02 : t_end; thick = thick < 0 ? 1 : thick;
        rjr_view_fit_box(&an.view, box, w, h, 20);
        an.view.caption = "impact on a reverse limit (paper sec. 4)";
        apply_aids(&an.view, &ax, impact_names);
    }
    /* refuse runs that would not end before anything runs (the scene pass below included):
       a frame at every multiple of 1/fps, but at most one per step */
    cli_check_steps("animate", t_end, rj_model_dt(m), force);
    frames = t_end * (fps < 1.0 / rj_model_dt(m) ? fps : 1.0 / rj_model_dt(m)) + 1;
    cli_check_frames("animate", frames, force);
    if (scene == 2) {
        rj_state *s0;
        double box[4];
        /* fix the view on the whole motion: a quick pass at 10x fewer samples */
        rj_state_create(m, &s0, NULL);
        rjr_bbox_init(box);
        rjr_bbox_add(box, m, s0);
        while (rj_state_time(s0) < t_end && rj_run(m, s0, rj_state_time(s0) + t_end / 50, 0, NULL, NULL) == RJ_OK) rjr_bbox_add(box, m, s0);
        rj_state_destroy(s0, NULL);
        rjr_view_fit_box(&an.view, box, w, h, 20);
    }
    an.view.thickness_factor = thick;
    rj_state_create(m, &s, NULL);
    /* the whole path, and no frames of an earlier run left to mix into the video */
    if (cli_frames_dir("animate", dir) != 0) return 1;
    an.ctx = rjr_create(w, h, err, sizeof err);
    if (!an.ctx) { fprintf(stderr, "animate: %s\n", err); return 1; }
    an.dir = dir;
    an.fdt = 1.0 / fps;
    /* frames is at most 1e5 unless --force: clamp the progress display's count */
    an.total = frames < INT_MAX ? (int)frames : INT_MAX;
    an.tty = isatty(2);
    c0 = clock();
    if (rj_run(m, s, t_end, an.fdt, on_sample, &an) != RJ_OK) { fprintf(stderr, "\nanimate: %s\n", rj_state_error(s)); return 1; }
    /* a frame that failed stopped the run; none at all is a failure too */
    if (an.failed) return 1;
    if (an.frame == 0) {
        fprintf(stderr, "animate: no frame written to %s\n", dir);
        return 1;
    }
    fprintf(stderr, "%sanimate: wrote %d frames %s/frame_%%05d.png (%dx%d) in %.2f s CPU\n", an.tty ? "\n" : "", an.frame, dir, w, h,
            (double)(clock() - c0) / CLOCKS_PER_SEC);
    rjr_destroy(an.ctx);
    rj_state_destroy(s, NULL); rj_model_destroy(m, NULL);
    rj_scene_file_free(&sf);
    return 0;
}
