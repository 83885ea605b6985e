/* deploy - the two-link deployment with locking of Wong, Hamouda & Hashmi 2002, sec. 5
   (paper sec. 5, Nagaraj et al.'s rig): flexible links, torsion springs, friction, locks.
   --rigid prints the rigid-body reference (examples/rigid2.h) in the same CSV. */
#define _POSIX_C_SOURCE 200809L
#define REVJOINT_IMPLEMENTATION
#include "../revjoint.h"
#include "scenes.h"
#include "cli.h"
#include "rigid2.h"
#include "../render/rj_render.h"
#include <time.h>

static const char usage[] =
    "usage: deploy [options]\n"
    "  The defaults are the cheapest settings that keep q1, q2 within 0.1 deg of the converged\n"
    "  reference before joint 2 locks and link 2's tip vibration within 2 % after (BENCHMARKS.md):\n"
    "  20 elements per link, joint 2 adaptive, dt = 0.9 x the stability bound.\n"
    "  --paper                the paper's settings instead (paper sec. 5): 10 elements per link,\n"
    "                         dt 7.5 us, joint 2 penalty with K from Eq 31 (the golden history)\n"
    "  --dt S                 time step (default 0.9 x the bound; with --method penalty 0.45 x)\n"
    "  --elements N           elements per link (default 20)\n"
    "  --t-end S              simulated time (default 6)\n"
    "  --joint1 forced|adaptive|penalty   joint 1 lock method (default forced)\n"
    "  --method penalty|adaptive          joint 2 lock method (default adaptive)\n"
    "  --K N_m_per_rad        joint 2 penalty stiffness (default: Eq 31 at dt)\n"
    "  --extra-friction       add sec. 5's +0.175 / +0.008 N m at joints 1 / 2\n"
    "  --rigid                the rigid-body reference (examples/rigid2.h) instead of the flexible model\n"
    "  --links flexible|rigid|inextensible|pieces   the library's link model (rigid: joint coordinates,\n"
    "                         default dt 2 ms, within 1e-3 deg of the rigid reference\n"
    "                         (build/studies), joint 2 momentum with e = 0 unless --method\n"
    "                         is given; inextensible: length constraints, dt from the bound,\n"
    "                         5 elements per link unless --paper or --elements: link 2's tip\n"
    "                         vibration within 0.3 % of the converged reference at 1/50 of the\n"
    "                         paper's steps, but the angles before the lock are a 5-element\n"
    "                         mesh's, about 1.3 deg off); pieces: each link cut into N rigid\n"
    "                         pieces and bending springs EI/l (--elements N, default 10; joint\n"
    "                         coordinates, both latches momentum, dt 0.9 x the bound): 10\n"
    "                         pieces run the 6 s in about 0.09 s, 0.019 / 0.038 deg before the\n"
    "                         lock, vibration +0.4 % (docs/validation.md, coarse meshes)\n"
    "  --scene FILE.rjs       the two-link mechanism from a scene file (examples/scenes/deploy.rjs)\n"
    "  --csv FILE             history, one row per ms, or per step when dt is longer\n"
    "                         (default standard output)\n"
    "  --plot FILE.png        q1, q2 against time, flexible against rigid, locks marked\n"
    "  --frames DIR           animation frames DIR/frame_00000.png ... (640x480); DIR and its\n"
    "                         parents are created, frame_NNNNN.png files there removed first\n"
    "  --fps N                frame rate for --frames (default 30)\n"
    "  --energy-every K       solver.energy_every: the energy accounts and blow-up checks every\n"
    "                         K steps and at every CSV row (default 16; the output is the same\n"
    "                         for every K, 1 .. 1000)\n"
    "  --force                run even above 1e8 steps or 1e5 frames (refused otherwise)\n";

#define MAXS 200000
#define MAX_PIECES 100
typedef struct run {
    cli_out out;                          /* the CSV history; out.f NULL: none */
    int n; double *t, *q1, *q2;           /* for the plot */
    rjr_context *ctx; rjr_view view; const char *frames; double frame_dt; int frame;
    int frame_failed;                     /* a frame could not be written: the run stopped */
    int pieces;                           /* rigid pieces per link (0: one link per arm) */
} run;

/* joint 2's index: the second arm's first joint */
static int joint2(const run *r)
{
    return r->pieces ? r->pieces + 1 : 1;
}

/* returns nonzero once a CSV write has failed */
static int row(run *r, double t, double q1, double q2, double q1d, double q2d, int f1, int f2,
               double tx, double ty, double defl)
{
    if (r->t && r->n < MAXS) { r->t[r->n] = t; r->q1[r->n] = q1; r->q2[r->n] = q2; r->n++; }
    if (!r->out.f) return 0;
    return cli_put(&r->out, fprintf(r->out.f,
                                    "%.6f,%.10g,%.10g,%.10g,%.10g,%d,%d,%.10g,%.10g,%.10g\n",
                                    t, q1, q2, q1d, q2d, f1, f2, tx, ty, defl));
}

static int flex_sample(const rj_model *m, const rj_state *s, void *u)
{
    run *r = (run *)u;
    const int j2 = joint2(r), tip_link = rj_model_link_count(m) - 1;
    double tip[2], t = rj_state_time(s);
    int werr;
    rj_node_position(m, s, tip_link, rj_link_node_count(m, tip_link) - 1, tip);
    werr = row(r, t, deploy_q1_deg(m, s),
               r->pieces ? deploy_segmented_q2_deg(m, s, r->pieces) : deploy_q2_deg(m, s),
               rj_joint_rate(m, s, 0), rj_joint_rate(m, s, j2),
               rj_joint_flag(m, s, 0), rj_joint_flag(m, s, j2), tip[0], tip[1],
               r->pieces ? deploy_segmented_tip_defl(m, s, r->pieces) : scene_tip_defl(m, s, 1));
    /* the history cannot be written (a full disk): stop, main reports it */
    if (werr) return 1;
    if (r->frames && t >= r->frame * r->frame_dt - 1e-9) {
        char path[4200], err[256];
        /* rj_run takes a nonzero return as "stop", not as an error: remember it */
        if (cli_frame_path("deploy", path, sizeof path, r->frames, r->frame) != 0) {
            r->frame_failed = 1;
            return 1;
        }
        err[0] = '\0';
        if (rjr_draw_state(r->ctx, m, s, &r->view) || rjr_save_png(r->ctx, path, err, sizeof err)) {
            /* the PNG writer's text has the system's reason; a drawing error is the context's */
            const char *why = err[0] ? err : rjr_error(r->ctx);
            fprintf(stderr, "deploy: cannot write %s: %s\n", path, why);
            r->frame_failed = 1;
            return 1;
        }
        r->frame++;
    }
    return 0;
}

/* Opens the history (standard output when csv is NULL) and writes its header line. */
static int open_csv(run *r, const char *csv)
{
    static const char head[] = "t,q1_deg,q2_deg,q1dot,q2dot,flag1,flag2,"
                               "tip2_x,tip2_y,tip2_defl_m\n";
    if (cli_open(&r->out, "deploy", csv) != 0) return -1;
    cli_put(&r->out, fputs(head, r->out.f));
    return 0;
}

static void rigid_sample(const rigid2_sample *s, void *u)
{
    run *r = (run *)u;
    double q1 = rj_deg(s->q[0]), q2 = rj_deg(s->q[1]);
    row(r, s->t, q1, q2, s->qd[0], s->qd[1], s->locked[0] ? 3 : 0, s->locked[1] ? 3 : 0, s->tip2[0], s->tip2[1], 0.0);
}

int main(int argc, char **argv)
{
    static const char *const j1names[] = { "penalty", "adaptive", "momentum", "forced" };
    cli c;
    deploy_opts o = deploy_default_opts();
    double t_end = 6.0, fps = 30, lock_rigid[2];
    const char *csv = NULL, *plot = NULL, *frames = NULL, *a, *scene_file = NULL;
    int rigid = 0, rigid_links = 0, dt_given = 0, method_given = 0, paper = 0, elements_given = 0;
    int force = 0;
    static const char *const fids[] = { "flexible", "rigid", "inextensible", "pieces" };
    run r;
    clock_t c0;
    rigid2_params rp;
    /* nothing here reads the accounts between rows: take them every 16th step (2875
       instructions per step instead of 3256 at the paper's settings, bench/instr.sh) */
    o.energy_every = 16;
    c.argc = argc; c.argv = argv; c.i = 0; c.usage = usage;
    while ((a = cli_next(&c)) != NULL) {
        if (!strcmp(a, "--dt")) { o.dt = cli_num(&c, a, 1e-12, 1); dt_given = 1; }
        else if (!strcmp(a, "--links")) rigid_links = cli_choice(&c, a, fids, 4);
        else if (!strcmp(a, "--elements")) { o.elements = cli_int(&c, a, 1, 100000); elements_given = 1; }
        else if (!strcmp(a, "--paper")) paper = 1;
        else if (!strcmp(a, "--t-end")) t_end = cli_num(&c, a, 0, 1e6);
        else if (!strcmp(a, "--joint1")) { o.joint1_method = cli_choice(&c, a, j1names, 4); if (o.joint1_method == 2) cli_die(&c, "option --joint1: unknown value '%s'%s", "momentum", ""); }
        else if (!strcmp(a, "--method")) { o.joint2_method = cli_choice(&c, a, cli_methods, 2); method_given = 1; }
        else if (!strcmp(a, "--K")) o.joint2_K = cli_num(&c, a, 1e-12, 1e30);
        else if (!strcmp(a, "--extra-friction")) o.extra_friction = 1;
        else if (!strcmp(a, "--rigid")) rigid = 1;
        else if (!strcmp(a, "--csv")) csv = cli_str(&c, a);
        else if (!strcmp(a, "--scene")) scene_file = cli_str(&c, a);
        else if (!strcmp(a, "--plot")) plot = cli_str(&c, a);
        else if (!strcmp(a, "--frames")) frames = cli_str(&c, a);
        else if (!strcmp(a, "--fps")) fps = cli_num(&c, a, 0.01, 10000);
        else if (!strcmp(a, "--energy-every")) o.energy_every = cli_int(&c, a, 1, 1000);
        else if (!strcmp(a, "--force")) force = 1;
        else if (!strcmp(a, "--help") || !strcmp(a, "-h")) { fputs(usage, stdout); return 0; }
        else cli_die(&c, "unknown option '%s'%s", a, "");
    }
    if (rigid_links == 3 && elements_given && o.elements > MAX_PIECES)
        cli_die(&c, "option --elements: at most 100 pieces per link with --links pieces%s%s", "", "");
    if (rigid_links == 3 && method_given)
        cli_die(&c, "option --method: --links pieces latches joint 2 by momentum%s%s", "", "");
    if (!paper) {
        /* the cheapest accurate settings (see usage) */
        if (!elements_given) o.elements = rigid_links == 2 ? 5 : rigid_links == 3 ? 10 : 20;
        if (!method_given) o.joint2_method = RJ_METHOD_ADAPTIVE;
        if (!dt_given) o.dt = 0;
    }
    memset(&r, 0, sizeof r);
    rigid2_default_params(&rp);
    if (o.extra_friction) rigid2_add_extra_friction(&rp);
    c0 = clock();
    if (rigid) {
        int e;
        if (open_csv(&r, csv) != 0) return 1;
        e = rigid2_run(&rp, t_end, 1e-3, rigid_sample, &r, lock_rigid);
        /* a history that could not be written fails the run */
        if (cli_close(&r.out, "deploy") != 0) return 1;
        fprintf(stderr, "deploy --rigid: joint 1 locks at %.6f s, joint 2 at %.6f s; wall %.4f s\n", lock_rigid[0], lock_rigid[1], (double)(clock() - c0) / CLOCKS_PER_SEC);
        return e ? 1 : 0;
    }
    {
        rj_model *m; rj_state *s; rj_error err; rj_result res;
        if (scene_file) {
            rj_scene_file sf;
            rj_scene_def sd;
            if (rj_scene_load(scene_file, &sf, &err) != RJ_OK) { fprintf(stderr, "deploy: %s\n", err.msg); return 1; }
            sd = rj_scene_file_def(&sf);
            if (sd.joint_count < 2 || sd.link_count < 2) { fprintf(stderr, "deploy: %s: needs two links and two joints\n", scene_file); return 1; }
            if (rj_model_create(&sd, &m, &err, NULL) != RJ_OK) { rj_scene_file_locate(&sf, &err); fprintf(stderr, "deploy: %s\n", err.msg); rj_scene_file_free(&sf); return 1; }
            rj_scene_file_free(&sf);
        } else if (rigid_links == 3) {
            static rj_link_def pieces_links[2 * (MAX_PIECES + 1)];
            static rj_joint_def pieces_joints[2 * (MAX_PIECES + 1)];
            rj_scene_def sc;
            if (paper && !dt_given) o.dt = 0;
            deploy_segmented_scene(&o, o.elements, pieces_links, pieces_joints, &sc);
            r.pieces = o.elements;
            if (rj_model_create(&sc, &m, &err, NULL) != RJ_OK) { fprintf(stderr, "deploy: %s\n", err.msg); return 1; }
        } else if (rigid_links) {
            rj_link_def L[2]; rj_joint_def J[2]; rj_scene_def sc;
            if (!dt_given) o.dt = rigid_links == 1 ? (paper ? 1e-3 : 2e-3) : 0;
            deploy_scene(&o, L, J, &sc);
            L[0].fidelity = L[1].fidelity = rigid_links == 1 ? RJ_LINK_RIGID : RJ_LINK_INEXTENSIBLE;
            if (rigid_links == 1) L[0].elements = L[1].elements = 1;
            if (!method_given) J[1].method = RJ_METHOD_MOMENTUM;
            else if (o.joint2_K > 0) J[1].penalty_k = o.joint2_K;
            else J[1].penalty_k = 1015;
            if (rj_model_create(&sc, &m, &err, NULL) != RJ_OK) { fprintf(stderr, "deploy: %s\n", err.msg); return 1; }
        } else {
            if (deploy_build(&o, &m, &err) != RJ_OK) { fprintf(stderr, "deploy: %s\n", err.msg); return 1; }
            if (!paper && !dt_given && o.joint2_method == RJ_METHOD_PENALTY) {
                /* penalty's K = Eq 31 is soft at 0.9 x the bound: half that step is its cheapest accurate one */
                o.dt = 0.5 * rj_model_dt(m);
                rj_model_destroy(m, NULL);
                if (deploy_build(&o, &m, &err) != RJ_OK) { fprintf(stderr, "deploy: %s\n", err.msg); return 1; }
            }
        }
        /* refuse runs that would not end, before any output is opened: frames come at the
           1 ms samples (every step when dt is longer), and at most fps of them a second */
        cli_check_steps("deploy", t_end, rj_model_dt(m), force);
        if (frames) {
            const double per_s = 1.0 / (rj_model_dt(m) > 1e-3 ? rj_model_dt(m) : 1e-3);
            cli_check_frames("deploy", t_end * (fps < per_s ? fps : per_s) + 1, force);
        }
        if (open_csv(&r, csv) != 0) return 1;
        rj_state_create(m, &s, NULL);
        if (plot) {
            r.t = (double *)malloc(sizeof(double) * MAXS); r.q1 = (double *)malloc(sizeof(double) * MAXS); r.q2 = (double *)malloc(sizeof(double) * MAXS);
        }
        if (frames) {
            char e2[256];
            double box[4] = { -1.2, -0.3, 1.3, 2.2 };
            /* the whole path, and no frames of an earlier run left to mix into the video */
            if (cli_frames_dir("deploy", frames) != 0) return 1;
            r.ctx = rjr_create(640, 480, e2, sizeof e2);
            if (!r.ctx) { fprintf(stderr, "deploy: %s\n", e2); return 1; }
            r.view = rjr_view_default();
            rjr_view_fit_box(&r.view, box, 640, 480, 20);
            r.view.thickness_factor = 2.0;
            r.view.caption = "two-link deployment (paper sec. 5)";
            /* the pieces' bending joints have no limits to show */
            if (r.pieces) r.view.show_limits = 0;
            r.frames = frames; r.frame_dt = 1.0 / fps;
        }
        c0 = clock();
        res = rj_run(m, s, t_end, 1e-3, flex_sample, &r);
        /* a history that could not be written, or a frame, fails the run (rj_run returns
           RJ_OK when a sample stops it) */
        if (cli_close(&r.out, "deploy") != 0) return 1;
        if (r.frame_failed) return 1;
        if (frames && r.frame == 0) {
            fprintf(stderr, "deploy: no frame written to %s\n", frames);
            return 1;
        }
        fprintf(stderr, "deploy: dt %.4g s (bound %.4g s), joint 2 K %.4g N m/rad; joint 1 locks at %.6f s, joint 2 at %.6f s; wall %.3f s\n",
                rj_model_dt(m), rj_model_dt_bound(m), rj_joint_stiffness(m, joint2(&r)), rj_joint_event_time(m, s, 0), rj_joint_event_time(m, s, joint2(&r)),
                (double)(clock() - c0) / CLOCKS_PER_SEC);
        if (frames) fprintf(stderr, "deploy: wrote %d frames to %s/frame_%%05d.png\n", r.frame, frames);
        if (res != RJ_OK) { fprintf(stderr, "deploy: %s\n", rj_state_error(s)); return 1; }
        if (plot) {
            run rr; char e2[256];
            rjr_context *ctx = r.ctx ? r.ctx : rjr_create(900, 560, e2, sizeof e2);
            rjr_plot_def p = rjr_plot_default();
            memset(&rr, 0, sizeof rr);
            rr.t = (double *)malloc(sizeof(double) * MAXS); rr.q1 = (double *)malloc(sizeof(double) * MAXS); rr.q2 = (double *)malloc(sizeof(double) * MAXS);
            rigid2_run(&rp, t_end, 1e-3, rigid_sample, &rr, lock_rigid);
            if (!ctx) { fprintf(stderr, "deploy: %s\n", e2); return 1; }
            if (r.ctx) rjr_resize(ctx, 900, 560);
            p.title = "Two-link deployment: joint angles"; p.xlabel = "t (s)"; p.ylabel = "angle (deg)";
            p.series_count = 4;
            p.series[0].x = r.t; p.series[0].y = r.q1; p.series[0].n = r.n; p.series[0].label = "q1 flexible"; p.series[0].colour = 0x1f77b4;
            p.series[1].x = rr.t; p.series[1].y = rr.q1; p.series[1].n = rr.n; p.series[1].label = "q1 rigid"; p.series[1].colour = 0x1f77b4; p.series[1].dashed = 1;
            p.series[2].x = r.t; p.series[2].y = r.q2; p.series[2].n = r.n; p.series[2].label = "q2 flexible"; p.series[2].colour = 0xd62728;
            p.series[3].x = rr.t; p.series[3].y = rr.q2; p.series[3].n = rr.n; p.series[3].label = "q2 rigid"; p.series[3].colour = 0xd62728; p.series[3].dashed = 1;
            p.marker_count = 0;
            if (rj_joint_event_time(m, s, joint2(&r)) >= 0) { p.markers[p.marker_count].x = rj_joint_event_time(m, s, joint2(&r)); p.markers[p.marker_count++].label = "lock 2"; }
            if (rj_joint_event_time(m, s, 0) >= 0) { p.markers[p.marker_count].x = rj_joint_event_time(m, s, 0); p.markers[p.marker_count++].label = "lock 1"; }
            p.legend = RJR_LEGEND_TOP_RIGHT;
            if (rjr_plot(ctx, &p) || rjr_save_png(ctx, plot, e2, sizeof e2)) { fprintf(stderr, "deploy: plot: %s %s\n", rjr_error(ctx), e2); return 1; }
            fprintf(stderr, "deploy: wrote %s\n", plot);
            if (!r.ctx) rjr_destroy(ctx);
            free(rr.t); free(rr.q1); free(rr.q2);
        }
        if (r.ctx) rjr_destroy(r.ctx);
        free(r.t); free(r.q1); free(r.q2);
        rj_state_destroy(s, NULL); rj_model_destroy(m, NULL);
    }
    return 0;
}
