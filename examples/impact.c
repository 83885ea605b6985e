/* impact - the simple revolute-joint problem of Wong, Hamouda & Hashmi 2002, sec. 4
   (paper sec. 4): link 1 held fixed, link 2 in rigid rotation hits a reverse limit at 176 deg.
   Writes the history as CSV; --all prints one table over every method and release rule. */
#define _POSIX_C_SOURCE 200809L
#define REVJOINT_IMPLEMENTATION
#include "../revjoint.h"
#include "scenes.h"
#include "cli.h"
#include "../render/rj_render.h"
#include <time.h>

static const char usage[] =
    "usage: impact [options]\n"
    "  --method penalty|adaptive|momentum|forced|energy   limit response (default adaptive)\n"
    "  --release rc12|rc13     release rule (default rc13)\n"
    "  --K N_m_per_rad         penalty stiffness (default 5e8)\n"
    "  --e E                   restitution for momentum (default 0)\n"
    "  --elements N            elements per link (default 10)\n"
    "  --dt S                  time step (default 2.5e-6; see README on 15 us)\n"
    "  --t-end S               simulated time (default 0.05)\n"
    "  --H M                   in-plane depth of the links (default 0.2; 0.05 = long contact)\n"
    "  --csv FILE              history (default standard output)\n"
    "  --plot FILE.png         theta and tip deflection against time\n"
    "  --all                   table of every method and release rule instead of a history\n"
    "  --force                 run even above 1e8 steps (refused otherwise)\n";

typedef struct hist { cli_out out; double sign; int n, cap; double *t, *th, *defl; } hist;

static int sample(const rj_model *m, const rj_state *s, void *u)
{
    hist *h = (hist *)u;
    double t = rj_state_time(s), th = rj_deg(rj_joint_theta(m, s, 0)), d = h->sign * scene_tip_defl(m, s, 1);
    int werr;
    werr = cli_put(&h->out, fprintf(h->out.f, "%.8g,%.10g,%.10g,%d,%.10g,%.10g,%.10g\n",
                                    t, th, rj_joint_rate(m, s, 0), rj_joint_flag(m, s, 0),
                                    rj_joint_torque(m, s, 0, RJ_TORQUE_LIMIT), d,
                                    rj_joint_latch_impulse(m, s, 0)));
    if (h->t && h->n < h->cap) { h->t[h->n] = t * 1e3; h->th[h->n] = th; h->defl[h->n] = d * 1e3; h->n++; }
    /* the history cannot be written (a full disk): stop, main reports it */
    return werr != 0;
}

/* The longest run --all would make: the most steps of its ten models (a penalty K sets
   the step of some of them). Models that cannot be built are skipped: the run reports them. */
static double all_max_steps(const impact_opts *o, double t_end)
{
    double most = 0;
    int mth, rel;
    for (mth = 0; mth < 5; mth++) for (rel = 0; rel < 2; rel++) {
        rj_link_def L[2]; rj_joint_def J; rj_scene_def sc; rj_model *m; rj_error err;
        impact_opts q = *o;
        q.method = mth;
        q.release = rel;
        impact_scene(&q, L, &J, &sc);
        if (rj_model_create(&sc, &m, &err, NULL) != RJ_OK) continue;
        if (t_end / rj_model_dt(m) > most) most = t_end / rj_model_dt(m);
        rj_model_destroy(m, NULL);
    }
    return most;
}


int main(int argc, char **argv)
{
    cli c;
    impact_opts o = impact_default_opts();
    double t_end = 0.05;
    const char *csv = NULL, *plot = NULL, *a;
    int all = 0, force = 0;
    c.argc = argc; c.argv = argv; c.i = 0; c.usage = usage;
    while ((a = cli_next(&c)) != NULL) {
        if (!strcmp(a, "--method")) o.method = cli_choice(&c, a, cli_methods, 5);
        else if (!strcmp(a, "--release")) o.release = cli_choice(&c, a, cli_releases, 2);
        else if (!strcmp(a, "--K")) o.K = cli_num(&c, a, 1e-12, 1e30);
        else if (!strcmp(a, "--e")) o.e = cli_num(&c, a, 0, 1);
        else if (!strcmp(a, "--elements")) o.elements = cli_int(&c, a, 1, 100000);
        else if (!strcmp(a, "--dt")) o.dt = cli_num(&c, a, 1e-12, 1);
        else if (!strcmp(a, "--t-end")) t_end = cli_num(&c, a, 0, 1e6);
        else if (!strcmp(a, "--H")) o.H = cli_num(&c, a, 1e-9, 1e3);
        else if (!strcmp(a, "--csv")) csv = cli_str(&c, a);
        else if (!strcmp(a, "--plot")) plot = cli_str(&c, a);
        else if (!strcmp(a, "--all")) all = 1;
        else if (!strcmp(a, "--force")) force = 1;
        else if (!strcmp(a, "--help") || !strcmp(a, "-h")) { fputs(usage, stdout); return 0; }
        else cli_die(&c, "unknown option '%s'%s", a, "");
    }
    if (all) {
        static const char head[] = "| method | release | contact (ms) | release (ms) "
            "| peak penetration (rad) | rigid rate after (rad/s) | vibration energy (J) | wall (s) |\n"
            "|---|---|---:|---:|---:|---:|---:|---:|\n";
        int mth, rel;
        cli_out out;
        /* refuse a table that would not end, before any row of it */
        cli_check_steps("impact", t_end, t_end / all_max_steps(&o, t_end), force);
        cli_open(&out, "impact", NULL);
        cli_put(&out, fputs(head, stdout));
        for (mth = 0; mth < 5; mth++) for (rel = 0; rel < 2; rel++) {
            rj_link_def L[2]; rj_joint_def J; rj_scene_def sc; rj_model *m; rj_state *s; rj_error err;
            impact_opts q = o;
            double w, ev; clock_t c0 = clock(); rj_result r;
            q.method = mth; q.release = rel;
            impact_scene(&q, L, &J, &sc);
            if (rj_model_create(&sc, &m, &err, NULL) != RJ_OK) { fprintf(stderr, "impact: %s\n", err.msg); return 1; }
            if (rj_state_create(m, &s, NULL) != RJ_OK) { fprintf(stderr, "impact: out of memory\n"); return 1; }
            r = rj_run(m, s, t_end, 0, NULL, NULL);
            impact_rigid_part(m, s, &w, &ev);
            cli_put(&out, printf("| %s | %s | %.4f | %.4f | %.3g | %.4f | %.4g | %.3f |%s\n", cli_methods[mth], cli_releases[rel],
                   1e3 * rj_joint_event_time(m, s, 0), 1e3 * rj_joint_release_time(m, s, 0), rj_joint_peak_penetration(m, s, 0),
                   w, ev, (double)(clock() - c0) / CLOCKS_PER_SEC, r != RJ_OK ? " stopped" : ""));
            if (r != RJ_OK) fprintf(stderr, "impact: %s %s: %s\n", cli_methods[mth], cli_releases[rel], rj_state_error(s));
            rj_state_destroy(s, NULL); rj_model_destroy(m, NULL);
        }
        /* a table that did not reach its file fails the run */
        return cli_close(&out, "impact");
    }
    {
        rj_link_def L[2]; rj_joint_def J; rj_scene_def sc; rj_model *m; rj_state *s; rj_error err;
        hist h; rj_result r; clock_t c0 = clock();
        memset(&h, 0, sizeof h);
        impact_scene(&o, L, &J, &sc);
        if (rj_model_create(&sc, &m, &err, NULL) != RJ_OK) { fprintf(stderr, "impact: %s\n", err.msg); return 1; }
        /* refuse a run that would not end (rj_model_dt: the step in use), before any output */
        cli_check_steps("impact", t_end, rj_model_dt(m), force);
        rj_state_create(m, &s, NULL);
        if (cli_open(&h.out, "impact", csv) != 0) return 1;
        h.sign = o.rate0 < 0 ? -1.0 : 1.0;
        if (plot) {
            h.cap = (int)(t_end / 1e-5) + 16;
            h.t = (double *)malloc(sizeof(double) * (size_t)h.cap); h.th = (double *)malloc(sizeof(double) * (size_t)h.cap); h.defl = (double *)malloc(sizeof(double) * (size_t)h.cap);
        }
        cli_put(&h.out, fputs("t,theta_deg,theta_dot,flag,tau_limit,tip_defl_m,latch_impulse\n", h.out.f));
        r = rj_run(m, s, t_end, 1e-5, sample, &h);
        /* a history that could not be written fails the run (its sample stopped rj_run) */
        if (cli_close(&h.out, "impact") != 0) return 1;
        fprintf(stderr, "impact: %s %s dt %.3g s (bound %.3g s): contact %.4f ms, release %.4f ms, peak penetration %.4g rad, wall %.3f s\n",
                cli_methods[o.method], cli_releases[o.release], rj_model_dt(m), rj_model_dt_bound(m),
                1e3 * rj_joint_event_time(m, s, 0), 1e3 * rj_joint_release_time(m, s, 0), rj_joint_peak_penetration(m, s, 0),
                (double)(clock() - c0) / CLOCKS_PER_SEC);
        if (r != RJ_OK) { fprintf(stderr, "impact: %s\n", rj_state_error(s)); return 1; }
        if (plot) {
            char e2[256];
            rjr_context *ctx = rjr_create(900, 560, e2, sizeof e2);
            rjr_plot_def p = rjr_plot_default();
            if (!ctx) { fprintf(stderr, "impact: %s\n", e2); return 1; }
            p.title = "Impact on the reverse limit (paper sec. 4)"; p.xlabel = "t (ms)"; p.ylabel = "theta (deg), tip deflection (mm)";
            p.series_count = 2;
            p.series[0].x = h.t; p.series[0].y = h.th; p.series[0].n = h.n; p.series[0].label = "theta (deg)"; p.series[0].colour = RJR_AUTO_COLOUR;
            p.series[1].x = h.t; p.series[1].y = h.defl; p.series[1].n = h.n; p.series[1].label = "tip deflection (mm)"; p.series[1].colour = RJR_AUTO_COLOUR;
            if (rj_joint_event_time(m, s, 0) >= 0) { p.markers[p.marker_count].x = 1e3 * rj_joint_event_time(m, s, 0); p.markers[p.marker_count++].label = "contact"; }
            if (rj_joint_release_time(m, s, 0) >= 0) { p.markers[p.marker_count].x = 1e3 * rj_joint_release_time(m, s, 0); p.markers[p.marker_count++].label = "release"; }
            if (rjr_plot(ctx, &p) || rjr_save_png(ctx, plot, e2, sizeof e2)) { fprintf(stderr, "impact: %s %s\n", rjr_error(ctx), e2); return 1; }
            rjr_destroy(ctx);
            fprintf(stderr, "impact: wrote %s\n", plot);
        }
        free(h.t); free(h.th); free(h.defl);
        rj_state_destroy(s, NULL); rj_model_destroy(m, NULL);
    }
    return 0;
}
