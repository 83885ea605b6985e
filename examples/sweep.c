/* sweep - runs the deployment over Monte Carlo samples or a grid of parameters (friction,
   spring preload, tip mass, dt) on several threads and writes one CSV row per sample: lock
   times, peak penetration, peak tip deflection, whether anything failed. "Will it lock every
   time if friction is 20 % off?"
   Work is split by sample index, so `--shard i/n` runs samples k with k % n == i, and GNU
   parallel, xargs -P or a Slurm job array can spread a sweep over machines:
     for i in 0 1 2 3; do build/sweep --samples 1000 --shard $i/4 --csv part$i.csv & done
   Every sample's parameters depend only on --seed and its index, so shards concatenate. */
#define _POSIX_C_SOURCE 200809L
#define REVJOINT_IMPLEMENTATION
#include "../revjoint.h"
#include "scenes.h"
#include "cli.h"
#include <pthread.h>
#include <time.h>

static const char usage[] =
    "usage: sweep [options]\n"
    "  --samples N            Monte Carlo samples (default 64)\n"
    "  --grid K               instead: K values per varied parameter (K^4 samples)\n"
    "  --friction-pct P       friction varied by +-P % (default 20)\n"
    "  --preload-deg D        spring free angles varied by +-D deg (default 5)\n"
    "  --tip-pct P            tip masses varied by +-P % (default 10)\n"
    "  --dt-pct P             step varied by -P % .. 0 (default 0)\n"
    "  --links rigid|flexible|inextensible   link model (default rigid: fast)\n"
    "  --t-end S              simulated time (default 8)\n"
    "  --threads T            worker threads (default 2)\n"
    "  --shard i/n            run only samples k with k % n == i (default 0/1)\n"
    "  --seed S               random seed (default 1)\n"
    "  --csv FILE             output (default standard output)\n"
    "  --force                run even above 1e8 steps a sample (refused otherwise)\n"
    "  --progress             progress line on standard error (samples done, rate, ETA);\n"
    "                         without it only on a terminal, after 2 s of wall time\n";
/* the options, for "did you mean" after a misspelt one */
static const char *const opt_names[] = { "--samples", "--grid", "--friction-pct", "--preload-deg", "--tip-pct",
                                         "--dt-pct", "--links", "--t-end", "--threads", "--shard", "--seed",
                                         "--csv", "--force", "--progress", "--help" };

typedef struct job {
    int grid, samples, links, shard_i, shard_n, next, done;
    double fpct, pdeg, tpct, dtpct, t_end;
    unsigned long long seed;
    pthread_mutex_t lock;
    char **rows;
} job;

static unsigned long long splitmix(unsigned long long *x)
{
    unsigned long long z = (*x += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
}
/* the k-th sample's four factors in [-1, 1] */
static void factors(const job *jb, int k, double u[4])
{
    int i;
    if (jb->grid > 0) {
        int r = k;
        for (i = 0; i < 4; i++) { int g = r % jb->grid; r /= jb->grid; u[i] = jb->grid > 1 ? -1.0 + 2.0 * g / (jb->grid - 1) : 0.0; }
    } else {
        unsigned long long st = jb->seed * 1000003ULL + (unsigned long long)k;
        for (i = 0; i < 4; i++) u[i] = 2.0 * ((double)(splitmix(&st) >> 11) / 9007199254740992.0) - 1.0;
    }
}

/* The model of a sample with factors u (see factors), or NULL with e filled. */
static rj_model *sample_model(const job *jb, const double u[4], rj_error *e)
{
    deploy_opts o = deploy_default_opts();
    rj_link_def L[2]; rj_joint_def J[2]; rj_scene_def sc; rj_model *m = NULL;
    double fscale, pre, tscale;
    int i;
    fscale = 1 + jb->fpct / 100 * u[0]; pre = jb->pdeg * u[1]; tscale = 1 + jb->tpct / 100 * u[2];
    o.dt = jb->links == 1 ? 1e-3 : (jb->links == 2 ? 0 : 7.5e-6);
    deploy_scene(&o, L, J, &sc);
    if (jb->links == 1) { L[0].fidelity = L[1].fidelity = RJ_LINK_RIGID; L[0].elements = L[1].elements = 1; J[1].method = RJ_METHOD_MOMENTUM; }
    if (jb->links == 2) { L[0].fidelity = L[1].fidelity = RJ_LINK_INEXTENSIBLE; J[1].method = RJ_METHOD_MOMENTUM; }
    if (jb->links == 0) J[1].penalty_k = 1015;
    for (i = 0; i < 2; i++) {
        J[i].friction *= fscale; J[i].spring_free_angle += rj_rad(pre); L[i].tip_mass *= tscale;
    }
    /* dt: scale the default (or, when 0, the model's own choice) down by up to dt-pct */
    if (jb->dtpct > 0) {
        rj_model *mt;
        if (rj_model_create(&sc, &mt, e, NULL) == RJ_OK) { sc.solver.dt = rj_model_dt(mt) * (1 - jb->dtpct / 100 * 0.5 * (u[3] + 1)); rj_model_destroy(mt, NULL); }
    }
    if (rj_model_create(&sc, &m, e, NULL) != RJ_OK) return NULL;
    return m;
}

static void run_sample(const job *jb, int k, char *row, size_t rowlen)
{
    rj_model *m = NULL; rj_state *s = NULL; rj_error e;
    double u[4], peakdefl = 0, fscale, pre, tscale, dt;
    rj_result r = RJ_OK;
    factors(jb, k, u);
    fscale = 1 + jb->fpct / 100 * u[0]; pre = jb->pdeg * u[1]; tscale = 1 + jb->tpct / 100 * u[2];
    m = sample_model(jb, u, &e);
    if (!m) {
        snprintf(row, rowlen, "%d,%.6f,%.6f,%.6f,0,-1,-1,0,0,1,\"%.400s\"\n", k, fscale, pre, tscale, e.msg);
        return;
    }
    dt = rj_model_dt(m);
    rj_state_create(m, &s, NULL);
    while (rj_state_time(s) < jb->t_end - 0.5 * dt) {
        double d;
        r = rj_step(m, s);
        if (r != RJ_OK) break;
        if (jb->links != 1 && rj_state_steps(s) % 16 == 0 && fabs(d = scene_tip_defl(m, s, 1)) > peakdefl) peakdefl = fabs(d);
    }
    snprintf(row, rowlen, "%d,%.6f,%.6f,%.6f,%.6g,%.6f,%.6f,%.6g,%.6g,%d,\"%s\"\n", k, fscale, pre, tscale, dt,
             rj_joint_event_time(m, s, 0), rj_joint_event_time(m, s, 1), rj_joint_peak_penetration(m, s, 1), peakdefl,
             r != RJ_OK || rj_joint_flag(m, s, 0) != RJ_LOCKED || rj_joint_flag(m, s, 1) != RJ_LOCKED,
             r != RJ_OK ? rj_state_error(s) : (rj_joint_flag(m, s, 0) != RJ_LOCKED || rj_joint_flag(m, s, 1) != RJ_LOCKED ? "did not lock" : ""));
    rj_state_destroy(s, NULL); rj_model_destroy(m, NULL);
}

/* Wall time in seconds on the monotonic clock. */
static double wall_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* The samples this shard runs: k < samples with k % n == i. */
static int shard_total(const job *jb)
{
    return jb->samples / jb->shard_n + (jb->shard_i < jb->samples % jb->shard_n ? 1 : 0);
}

/* The progress line: samples done of the shard's, the rate and the remaining wall time at
   it; on a terminal redrawn in place (tty), otherwise a line each time. */
static void progress_line(int done, int total, double el, int tty)
{
    const double rate = el > 0 ? done / el : 0.0;
    const double eta = done > 0 ? el * (total - done) / done : 0.0;
    fprintf(stderr, "%ssweep: %d / %d samples (%.1f %%), %.1f s, %.3g samples/s, ETA %.0f s%s", tty ? "\r" : "", done,
            total, 100.0 * done / (total > 0 ? total : 1), el, rate, eta, tty ? "   " : "\n");
}

/* Waits until the workers have run every sample of the shard, with a progress line on
   standard error meanwhile: with --progress from half a second on (every second, every
   quarter on a terminal); without it only on a terminal, after 2 s. A long sweep (--grid
   50 is 6.25 million samples) is otherwise silent for hours. */
static void progress_wait(job *jb, int always)
{
    const int total = shard_total(jb), tty = isatty(2);
    const double wall0 = wall_now();
    const struct timespec nap = { 0, 20000000L };
    double next = wall0 + (always ? 0.5 : 2.0);
    int done = 0, shown = 0;
    while (done < total) {
        double now;
        nanosleep(&nap, NULL);
        pthread_mutex_lock(&jb->lock);
        done = jb->done;
        pthread_mutex_unlock(&jb->lock);
        now = wall_now();
        if ((!always && !tty) || now < next) continue;
        progress_line(done, total, now - wall0, tty);
        shown = tty;
        next = now + (tty ? 0.25 : 1.0);
    }
    /* the end: on a terminal the line is cleared, into a file --progress says it */
    if (shown) fprintf(stderr, "\r%79s\r", "");
    if (always && !tty) progress_line(done, total, wall_now() - wall0, 0);
}

/* --seed takes an integer in [0, 1e15] */
#define SEED_MAX 1000000000000000LL

static void *worker(void *arg)
{
    job *jb = (job *)arg;
    for (;;) {
        int k;
        char row[1024];
        pthread_mutex_lock(&jb->lock);
        while (jb->next < jb->samples && jb->next % jb->shard_n != jb->shard_i) jb->next++;
        k = jb->next < jb->samples ? jb->next++ : -1;
        pthread_mutex_unlock(&jb->lock);
        if (k < 0) return NULL;
        run_sample(jb, k, row, sizeof row);
        pthread_mutex_lock(&jb->lock);
        jb->rows[k] = (char *)malloc(strlen(row) + 1);
        if (jb->rows[k]) strcpy(jb->rows[k], row);
        jb->done++;
        pthread_mutex_unlock(&jb->lock);
    }
}

int main(int argc, char **argv)
{
    static const char *const fids[] = { "flexible", "rigid", "inextensible" };
    /* --shard i/n: i >= 0, n >= 1 (i < n is checked once both are read) */
    static const int shard_lim[4] = { 0, INT_MAX - 1, 1, INT_MAX };
    /* the factors of the sample with the smallest step, for the bound on a run's length */
    static const double slowest[4] = { 0, 0, 0, 1 };
    static const char head[] = "sample,friction_scale,preload_deg,tip_mass_scale,dt,lock1_s,lock2_s,"
                               "peak_penetration2_rad,peak_tip_defl_m,failed,message\n";
    cli c;
    job jb;
    const char *csv = NULL, *a;
    int threads = 2, t, k, fails = 0, n = 0, force = 0, progress = 0, started;
    pthread_t th[64];
    cli_out out;
    memset(&jb, 0, sizeof jb);
    jb.samples = 64; jb.fpct = 20; jb.pdeg = 5; jb.tpct = 10; jb.dtpct = 0; jb.links = 1; jb.t_end = 8; jb.seed = 1; jb.shard_n = 1;
    c.argc = argc; c.argv = argv; c.i = 0; c.usage = usage;
    while ((a = cli_next(&c)) != NULL) {
        if (!strcmp(a, "--samples")) jb.samples = cli_int(&c, a, 1, 10000000);
        else if (!strcmp(a, "--grid")) jb.grid = cli_int(&c, a, 1, 50);
        else if (!strcmp(a, "--friction-pct")) jb.fpct = cli_num(&c, a, 0, 100);
        else if (!strcmp(a, "--preload-deg")) jb.pdeg = cli_num(&c, a, 0, 180);
        else if (!strcmp(a, "--tip-pct")) jb.tpct = cli_num(&c, a, 0, 100);
        else if (!strcmp(a, "--dt-pct")) jb.dtpct = cli_num(&c, a, 0, 99);
        else if (!strcmp(a, "--links")) jb.links = cli_choice(&c, a, fids, 3);
        else if (!strcmp(a, "--t-end")) jb.t_end = cli_num(&c, a, 0, 1e6);
        else if (!strcmp(a, "--threads")) threads = cli_int(&c, a, 1, 64);
        else if (!strcmp(a, "--seed")) jb.seed = (unsigned long long)cli_long(&c, a, 0, SEED_MAX);
        else if (!strcmp(a, "--csv")) csv = cli_str(&c, a);
        else if (!strcmp(a, "--shard")) {
            cli_pair(&c, a, '/', &jb.shard_i, &jb.shard_n, shard_lim, "i/n with 0 <= i < n");
            /* i < n depends on both: checked once both are read */
            if (jb.shard_i >= jb.shard_n) cli_bad(&c, a, c.argv[c.i], "i/n with 0 <= i < n");
        }
        else if (!strcmp(a, "--force")) force = 1;
        else if (!strcmp(a, "--progress")) progress = 1;
        else if (!strcmp(a, "--help") || !strcmp(a, "-h")) { fputs(usage, stdout); return 0; }
        else cli_unknown(&c, "option", a, opt_names, (int)(sizeof opt_names / sizeof opt_names[0]));
    }
    if (jb.grid > 0) jb.samples = jb.grid * jb.grid * jb.grid * jb.grid;
    /* refuse samples that would not end: the smallest step a sample can get is the
       nominal one scaled down by the whole --dt-pct (factor u[3] = 1) */
    {
        rj_error e;
        rj_model *m = sample_model(&jb, slowest, &e);
        if (m) {
            cli_check_steps("sweep", jb.t_end, rj_model_dt(m), force);
            rj_model_destroy(m, NULL);
        }
    }
    /* open the output first: a sweep is long, and a path that cannot be written should
       not be found out at its end */
    if (cli_open(&out, "sweep", csv) != 0) return 1;
    jb.rows = (char **)calloc((size_t)jb.samples, sizeof(char *));
    pthread_mutex_init(&jb.lock, NULL);
    /* the workers run the samples while this thread reports progress; without a worker
       (none could be started) this thread runs them */
    for (started = 0; started < threads; started++)
        if (pthread_create(&th[started], NULL, worker, &jb) != 0) break;
    if (started == 0) worker(&jb);
    progress_wait(&jb, progress);
    for (t = 0; t < started; t++) pthread_join(th[t], NULL);
    if (jb.shard_i == 0) cli_put(&out, fputs(head, out.f));
    for (k = 0; k < jb.samples; k++) if (jb.rows[k]) {
        cli_put(&out, fputs(jb.rows[k], out.f));
        n++;
        if (strstr(jb.rows[k], ",1,\"")) fails++;
        free(jb.rows[k]);
    }
    free(jb.rows);
    /* rows that did not reach the file fail the sweep */
    if (cli_close(&out, "sweep") != 0) return 1;
    fprintf(stderr, "sweep: %d samples (shard %d/%d), %d did not lock or failed\n", n, jb.shard_i, jb.shard_n, fails);
    return 0;
}
