/* rj - one program for scene files (.rjs): run a scene to a CSV history, check what a
   scene is and what a simulated second costs, plot a run, render it to PNG frames, sweep
   it over random samples of its keys.
     rj run examples/scenes/deploy.rjs --t-end 6 --csv out/deploy.csv
     rj check examples/scenes/solar_array.rjs
     rj plot examples/scenes/solar_array.rjs --t-end 4 --out angles.png
     rj animate examples/scenes/deploy.rjs --t-end 6 --out out/frames --mp4 deploy.mp4
     rj sweep examples/scenes/solar_array.rjs --vary joint.h1.friction=0.01:0.03 --samples 100
   Every subcommand loads the file with rj_scene_load and names links and joints as the
   file does. Exit status: 0 done; 1 the simulation stopped or an output failed while
   being written; 2 bad usage, an invalid scene, a missing file, an output that cannot be
   opened. */
#define _POSIX_C_SOURCE 200809L
#define REVJOINT_IMPLEMENTATION
#include "../revjoint.h"
#include "scenes.h"
#include "cli.h"
#include "../render/rj_render.h"
#include <signal.h>
#include <stdarg.h>
#include <time.h>
#include <pthread.h>
#include <sys/wait.h>

#define RJ_TWO_PI 6.283185307179586476925
/* a run without --t-end: scene files have no duration key, and the documented scenes show
   their first motion within it (impact: contact and release in 20 ms) */
#define DEFAULT_T_END 1.0
/* plots keep at most about this many samples a series: 1 ms apart, or t_end / this */
#define PLOT_SAMPLES 20000
/* a flag change is printed once it has held this long (s): the end of an impact's contact
   is the start of a free interval of at least 0.1 ms in BENCHMARKS.md's impact tables */
#define EVENT_HOLD 1e-4
/* rj run --settle: rj_settle's tolerance (a peak's kinetic energy against the potential
   energy moved: tight) and its most steps, counted in the bound on a run's length */
#define SETTLE_TOL 1e-12
#define SETTLE_MAX_STEPS 1e7

/* Usage texts: rj --help, and each subcommand's --help (also printed after bad usage). */
static const char usage_main[] =
    "usage: rj SUBCOMMAND SCENE.rjs [options]\n"
    "  run      simulate the scene; CSV history, events and a summary\n"
    "  check    validate the scene; links, joints, gravity and loads, the step and what sets\n"
    "           it, the cost of a simulated second, warnings\n"
    "  plot     simulate and plot joint angles, limit torques, tip deflections, energies\n"
    "           or loads (pin forces, bending moments)\n"
    "  animate  simulate and render PNG frames (and an MP4 with ffmpeg, when installed)\n"
    "  sweep    run the scene over samples of --set keys (random, Latin hypercube, grid);\n"
    "           a CSV row per sample: lock and first-contact times, peak pin forces and\n"
    "           bending moments (rj plot --what sweep draws them)\n"
    "  rj SUBCOMMAND --help   that subcommand's options (rj help SUBCOMMAND too)\n"
    "Exit status: 0 done; 1 the simulation stopped (blow-up, tunnelling) or an output\n"
    "failed while being written; 2 bad usage, an invalid scene (file:line:col: message),\n"
    "a missing file, or an output that cannot be opened.\n";

/* rj run's usage in two parts, each within the 4095 characters C99 asks compilers to take
   in one string; cmd_run joins them. */
static const char usage_run[] =
    "usage: rj run SCENE.rjs [options]\n"
    "  Simulates the scene and writes its history as CSV, one row per sample.\n"
    "  --t-end S          simulated time (default 1 s: scene files have no duration); with\n"
    "                     --settle it counts from the settled state\n"
    "  --dt S             time step, instead of the file's solver.dt (0 = automatic,\n"
    "                     0.9 x the stability bound)\n"
    "  --sample S         row interval: a row at the step nearest to each multiple of S from\n"
    "                     the run's start (default 0.001 s: every step when the step is\n"
    "                     longer; 0 = every step)\n"
    "  --csv FILE         the history (default, or -, standard output)\n"
    "  --probe LINK:NODE  add that node's x, y, phi (repeatable; NODE an index or 'last')\n"
    "  --loads LINK       add L.E.N, L.E.V (N), L.E.M0, L.E.M1 (N m) for each element E\n"
    "                     (rj_element_loads; repeatable); the summary: their peaks\n"
    "  --nodes FILE       every node at the end: link,node,x,y,phi\n"
    "  --progress         progress line on standard error (percent, simulated time,\n"
    "                     steps/s, ETA); without it only on a terminal, after 2 s of wall time\n"
    "  --force            run even above 1e8 steps (refused otherwise; with --settle its\n"
    "                     1e7 steps at most count too)\n"
    "  --settle           start from the static equilibrium under the scene's loads (gravity,\n"
    "                     springs, limits, tabled loads past their last point):\n"
    "                     rj_settle_ex, kinetic damping, to 1e-12 of the potential energy\n"
    "                     moved, at most 1e7 steps. Time runs while it settles and is kept:\n"
    "                     the run starts at the settled time (said on standard error), goes\n"
    "                     on for --t-end, and the t column is the library's time; steps,\n"
    "                     losses and work in the energy columns count from there. Progress\n"
    "                     (steps, time) as the run's: --progress, or on a terminal after 2 s\n"
    "  --set KIND.NAME.KEY=VALUE  change one field of the scene, as if written last in\n"
    "                     its section (repeatable, 64 at most): link.arm1.E=69e9,\n"
    "                     material.alu.rho=2700, joint.j2.forward=181 deg,\n"
    "                     solver.gravity=0 -9.81 (rj_scene_load_set)\n"
    ;
static const char usage_run_output[] =
    "  Columns: t (s); for each joint J: J.theta_deg (running angle), J.rate (rad/s), J.flag\n"
    "  (0 free, 1 at the forward limit, 2 at the reverse limit, 3 locked), J.torque_spring,\n"
    "  J.torque_table, J.torque_damping, J.torque_friction, J.torque_limit (N m on body 2),\n"
    "  J.latch_impulse (N m s that a velocity-level limit applied in the last step), and in\n"
    "  scenes with actuators J.torque_drive (N m, the actuator's); J.Fx, J.Fy (N on body\n"
    "  2 at the pin: rj_joint_pin_force, empty where there is none yet; rj run steps\n"
    "  double-buffered, solver.in_place off, which keeps the loads at t^n: the same bits,\n"
    "  a little slower on large scenes); for each\n"
    "  link L: L.tip_x, L.tip_y (m), L.tip_defl (m: the last node's distance from the\n"
    "  tangent at node 0, counter-clockwise positive); for each probe L.N.x, L.N.y (m),\n"
    "  L.N.phi (rad); E_kin, E_strain, E_spring, E_gravity (J: gravity's potential, -m g . x),\n"
    "  W_applied (J: work of the scene's loads so far), W_drive (J: the actuators' work, in\n"
    "  scenes with actuators), W_damping, W_friction, W_limit (J lost so far), W_structural\n"
    "  and W_plastic (J, in scenes whose links damp or yield), E_balance (J: energy + losses\n"
    "  - initial; rj_state_energy at the row's step).\n"
    "  Standard error: the model's warnings, then events as they happen (contacts, locks,\n"
    "  releases, late contacts; at the time of the state the library decided them on, as\n"
    "  rj_joint_event_time; the links of a joint passing through each other, once per\n"
    "  joint, as rj_joint_overlap_time), then a summary:\n"
    "  per joint the first contact, the lock, peak penetration, peak |limit torque|, peak\n"
    "  |latch impulse|, peak |pin force|, and between two links when they overlapped;\n"
    "  steps, wall time, steps/s.\n"
    "  A lock and the first contact are printed at once, other flag changes once they have\n"
    "  held 0.1 ms (contacts may toggle step by step); the summary counts every change.\n"
    "  Events and peaks are checked every step, so the energy accounts are taken every\n"
    "  step too (solver.energy_every saves nothing here).\n"
    "  Exit status: 0 done, also when the reader of standard output stops (rj run x | head);\n"
    "  1 the simulation stopped (the library's message; the CSV ends at the last good\n"
    "  state) or a write failed (full disk); 2 bad usage, an invalid scene, a missing file,\n"
    "  an output that cannot be opened, a run above 1e8 steps without --force.\n";

static const char usage_check[] =
    "usage: rj check SCENE.rjs [--dt S] [--progress] [--assemble FILE]\n"
    "  Validates the scene and prints the model: links (model, elements, length, mass),\n"
    "  joints (bodies, spring, table, limits, lock, method, friction, damping), gravity and\n"
    "  the loads (node, force and its frame, moment, table), the step\n"
    "  (dt, the stability bound, omega_max, and what sets them: the fastest link on its own,\n"
    "  the stiffest joint), the cost of one simulated second here (200-step batches timed),\n"
    "  and warnings (the model's own, penalty stiffness above Eq 31, a heavy tip mass on a\n"
    "  coarse mesh, a step near or above the bound).\n"
    "  The steps are timed from the scene's start: a scene whose steps fail there (a blow-up,\n"
    "  a step too large) is not valid; the first line and the cost line say so.\n"
    "  --dt S             time step, instead of the file's solver.dt (0 = automatic)\n"
    "  --set KIND.NAME.KEY=VALUE  change one field of the scene, as if written last in\n"
    "                     its section (repeatable, 64 at most): link.arm1.E=69e9,\n"
    "                     material.alu.rho=2700, joint.j2.forward=181 deg,\n"
    "                     solver.gravity=0 -9.81 (rj_scene_load_set)\n"
    "  --assemble FILE    close the scene's loops first (rj_scene_assemble: the angle0 of\n"
    "                     the joints on each loop but its first move the least that closes\n"
    "                     it), write the corrected scene to FILE and check that\n"
    "  --progress         each phase (building the model, each link alone, timing the steps)\n"
    "                     on standard error as it starts, with the wall time; without it\n"
    "                     once the check has taken 1 s (a link of 1e6 elements: minutes)\n"
    "  Exit status: 0 valid; 1 the scene loads but a step fails (the library's message on\n"
    "  standard error); 2 invalid (file:line:col: message) or bad usage.\n";

static const char usage_plot[] =
    "usage: rj plot SCENE.rjs --out FILE.png [options]\n"
    "       rj plot --what sweep --csv ROWS.csv --out FILE.png [--x COL] [--y COL]\n"
    "  Simulates the scene and plots its history, locks and first contacts marked.\n"
    "  --out FILE.png     the plot (required)\n"
    "  --what angles|torques|tips|energy|loads|sweep   (default angles)\n"
    "                     angles: each joint's running angle (deg); torques: each limited\n"
    "                     joint's limit torque, or latch impulse / dt for velocity-level\n"
    "                     methods (momentum, forced, energy); tips: each link's tip\n"
    "                     deflection (m, as rj run's L.tip_defl); energy: kinetic, strain,\n"
    "                     spring, balance; loads: each joint's pin force |F| (N), and in a\n"
    "                     second plot below it each flexible link's largest |bending\n"
    "                     moment| over its elements (N m); each marked at its peak over\n"
    "                     every step (the summary's), which a spike between two samples\n"
    "                     puts above the line. A joint without a pin force\n"
    "                     (rj_joint_pin_force) is said on stderr, not drawn. Stepped\n"
    "                     double-buffered, as rj run (the loads at t^n; the same bits).\n"
    "                     At most 8 series a plot: the first 8 (said on stderr).\n"
    "                     sweep: no simulation; the rows of rj sweep (--csv ROWS.csv) in\n"
    "                     four plots: each joint's lock times and peak pin forces as\n"
    "                     histograms (legend: the samples that never locked, or had no\n"
    "                     pin force), one column against another as points (--x COL,\n"
    "                     default the first --vary key; --y COL, default the first\n"
    "                     joint's lock; -1, none, not drawn), and the share of samples\n"
    "                     in which each joint latched. Rows whose status is not ok are\n"
    "                     left out and counted in that title. Default size 1000x750\n"
    "  --t-end S          simulated time (default 1 s)\n"
    "  --dt S             time step, instead of the file's solver.dt (0 = automatic)\n"
    "  --set KIND.NAME.KEY=VALUE  change one field of the scene, as if written last in\n"
    "                     its section (repeatable, 64 at most): link.arm1.E=69e9,\n"
    "                     material.alu.rho=2700, joint.j2.forward=181 deg,\n"
    "                     solver.gravity=0 -9.81 (rj_scene_load_set)\n"
    "  --size WxH         image size (default 900x560)\n"
    "  --progress, --force  as rj run\n"
    "  Samples every 1 ms (every step when the step is longer), or t-end / 20000 if longer.\n"
    "  Exit status as rj run; 1 also when the plot cannot be drawn or written.\n";

static const char usage_animate[] =
    "usage: rj animate SCENE.rjs --out DIR [options]\n"
    "  Simulates the scene and renders DIR/frame_00000.png ... at the steps nearest to\n"
    "  every multiple of 1/fps. The view is fixed once on the whole motion; the links are\n"
    "  drawn twice their thickness. The frames carry a key to the joint colours (free, at a\n"
    "  limit, locked), each joint's name and angle beside it, the time and the caption\n"
    "  (the scene's title, else its file name) in a band above the links, and stowed links\n"
    "  drawn side by side.\n"
    "  --plain            without those aids: the frames of build/animate --scene FILE.rjs\n"
    "                     (for a scene without a title its caption is the path as given:\n"
    "                     the same when FILE.rjs has no directory)\n"
    "  --out DIR          frames directory (required); created with its parents, and the\n"
    "                     frame_NNNNN.png files of an earlier run there removed first\n"
    "  --fps N            frames per simulated second (default 30)\n"
    "  --size WxH         image size (default 640x480)\n"
    "  --t-end S          simulated time (default 1 s)\n"
    "  --dt S             time step, instead of the file's solver.dt (0 = automatic)\n"
    "  --set KIND.NAME.KEY=VALUE  change one field of the scene, as if written last in\n"
    "                     its section (repeatable, 64 at most): link.arm1.E=69e9,\n"
    "                     material.alu.rho=2700, joint.j2.forward=181 deg,\n"
    "                     solver.gravity=0 -9.81 (rj_scene_load_set)\n"
    "  --mp4 FILE         also encode FILE with ffmpeg when it is on PATH; otherwise print\n"
    "                     the ffmpeg command to run\n"
    "  --progress         as rj run\n"
    "  --force            run even above 1e8 steps or 1e5 frames (refused otherwise)\n"
    "  Exit status as rj run; 1 also when a frame or the MP4 cannot be written.\n";

static const char usage_sweep[] =
    "usage: rj sweep SCENE.rjs --vary KEY=LO:HI [--vary ...] --samples N|--grid K [options]\n"
    "  Runs the scene once per sample, the varied keys' values drawn or on a grid, and\n"
    "  writes one CSV row per sample.\n"
    "  --vary KEY=LO:HI   a --set key (KIND.NAME.KEY or solver.KEY), uniform in [LO, HI]:\n"
    "                     joint.h1.friction=0.01:0.03, material.alu.E=65e9:75e9\n"
    "  --vary KEY=normal:MEAN:SD  normal, SD >= 0, not cut off: a value the file refuses\n"
    "                     is a failed row. Both forms may end in a unit the key takes in\n"
    "                     the file (joint.h1.angle0=85:95deg); the column KEY[deg] holds\n"
    "                     the values in it. Repeatable; the key must name an item of the\n"
    "                     file and LO and HI (or MEAN) must load, else it is refused\n"
    "  --samples N        samples 0..N-1, each key's values independent\n"
    "  --lhs              with --samples: a Latin hypercube, each key's N strata of equal\n"
    "                     probability holding one sample each\n"
    "  --grid K           instead of --samples: every combination of K values a key (LO to\n"
    "                     HI evenly; K = 1 the midpoint; LO:HI keys only), K^n samples,\n"
    "                     1e9 at most; the last --vary varies fastest\n"
    "  --seed S           integer in [0, 1e15] (default 1). Sample k's values depend only\n"
    "                     on S, k, the --vary's place (splitmix64) and with --lhs N, never\n"
    "                     on --shard or --threads\n"
    "  --shard i/n        only the samples k with k % n == i (default 0/1). Every shard\n"
    "                     writes the header, and shards joined by\n"
    "                     { head -1 s0.csv; tail -q -n +2 s*.csv | sort -t, -k1,1n; }\n"
    "                     are the unsharded output byte for byte\n"
    "  --shard auto       i/n of a Slurm job array: SLURM_ARRAY_TASK_ID less\n"
    "                     SLURM_ARRAY_TASK_MIN (0 when unset) of SLURM_ARRAY_TASK_COUNT;\n"
    "                     refused when missing or bad, or the array has a step\n"
    "  --threads N        samples on N threads, 256 at most (default 1): the same bytes\n"
    "  --resume           with --csv FILE holding a cut-short run of this sweep (its header\n"
    "                     and rows checked, else refused): a last partial line is cut, and\n"
    "                     only the samples it lacks run, appended. A missing FILE is begun\n"
    "  --progress         samples done, samples/s, ETA on standard error (without it only\n"
    "                     on a terminal, after 2 s)\n"
    "  --t-end S          simulated time of each sample (default 1 s)\n"
    "  --dt S             time step, instead of the file's solver.dt (0 = automatic)\n"
    "  --set KIND.NAME.KEY=VALUE  a change every sample has (with --vary 64 at most)\n"
    "  --csv FILE         the rows (default, or -, standard output)\n"
    "  --force            run even above 1e8 steps a sample at the file's values (or\n"
    "                     at a --vary solver.dt=LO:HI's LO)\n"
    "  Columns: sample (k); each --vary's value (%.17g: rj run --set KEY=VALUE runs the\n"
    "  sample again); per joint J in the file's order J.first_contact, J.lock (s, as rj\n"
    "  run's summary), J.peak_pin_force (N); per flexible link L L.peak_moment (N m);\n"
    "  -1: none. Then status (ok, or parse, invalid, unstable_dt, blowup, tunnel, ...) and\n"
    "  the library's message, quoted. A sample that does not load or build has empty\n"
    "  numbers; one whose step fails, the numbers up to the failure. rj plot --what sweep\n"
    "  draws the rows. Standard error: --resume's count, then a summary.\n"
    "  Exit status: 0 every row written (a failed sample is a row, not an error); 1 a\n"
    "  write failed; 2 bad usage, an invalid scene or --vary, an output that cannot be\n"
    "  opened, a --resume FILE of another sweep.\n";

/* ================================================================ options */

enum { CMD_RUN = 1, CMD_CHECK = 2, CMD_PLOT = 4, CMD_ANIMATE = 8, CMD_SWEEP = 16 };
#define NCMDS 5
enum { WHAT_ANGLES = 0, WHAT_TORQUES, WHAT_TIPS, WHAT_ENERGY, WHAT_LOADS, NWHAT };
static const char *const what_names[NWHAT] = { "angles", "torques", "tips", "energy", "loads" };
/* rj plot --what sweep draws a sweep's CSV, not a run: outside what_names, whose list
   the message for an unknown --what gives (its values are the run's plots) */
#define WHAT_SWEEP NWHAT

/* rj sweep --vary: how a key's values are drawn */
enum { DIST_UNIFORM = 0, DIST_NORMAL };
/* rj sweep: how the samples cover the keys (--samples, --samples --lhs, --grid) */
enum { DESIGN_RANDOM = 0, DESIGN_LHS, DESIGN_GRID };

/* rj sweep --vary KEY=LO:HI or KEY=normal:MEAN:SD, with an optional unit: the --set key
   (spec's first keylen characters), the distribution and its numbers, in unit. */
typedef struct vary {
    const char *spec;
    int keylen;
    int dist;            /* DIST_* */
    double lo, hi;       /* uniform: the range */
    double mean, sd;     /* normal */
    const char *unit;    /* the unit word of the numbers ("deg"), "" for the file's own */
} vary;

/* Every subcommand's options; each parses only its own (opt_shared, opt_own). */
typedef struct opts {
    int cmd;
    const char *scene;
    double t_end, dt, sample, fps;   /* dt < 0: the file's */
    const char *csv, *nodes, *out, *mp4;
    const char *assemble; /* rj check: where the scene with its loops closed goes */
    const char **probes;
    const char **loads; /* rj run --loads: link names (the second half of probes' array) */
    int nprobes, nloads, what, w, h, progress, force;
    int plain;   /* rj animate: build/animate's frames, without the reading aids */
    const char **sets; /* --set: changes to the scene (rj_scene_load_set) */
    int nsets;
    int settle;  /* rj run: start from the static equilibrium (rj_settle) */
    vary *varies; /* rj sweep --vary, nvary of them */
    int nvary;
    int samples, shard_i, shard_n; /* rj sweep: samples 0..samples-1 with k % shard_n == shard_i */
    unsigned long long seed;       /* rj sweep --seed */
    int threads, resume;           /* rj sweep --threads, --resume */
    int design, grid;              /* rj sweep: DESIGN_*; --grid K (0: none) */
    const char *x_col, *y_col;     /* rj plot --what sweep --x, --y (NULL: the defaults) */
    int size_given;                /* --size was given (rj plot --what sweep has its own default) */
} opts;

/* The defaults of every subcommand; the sizes are those of build/deploy's plot and of
   build/animate's frames. */
static void opts_default(opts *o, int cmd, int argc)
{
    memset(o, 0, sizeof *o);
    o->cmd = cmd;
    o->t_end = DEFAULT_T_END;
    o->dt = -1;
    o->sample = 1e-3;
    o->fps = 30;
    o->w = cmd == CMD_PLOT ? 900 : 640;
    o->h = cmd == CMD_PLOT ? 560 : 480;
    /* at most one probe, and one --loads, per argument: one array, two halves */
    o->probes = (const char **)malloc(sizeof(char *) * 2 * (size_t)(argc > 0 ? argc : 1));
    if (!o->probes) {
        fprintf(stderr, "rj: out of memory\n");
        exit(1);
    }
    o->loads = o->probes + (argc > 0 ? argc : 1);
    o->sets = (const char **)malloc(sizeof(char *) * (size_t)(argc > 0 ? argc : 1));
    o->varies = (vary *)malloc(sizeof(vary) * (size_t)(argc > 0 ? argc : 1));
    o->seed = 1;
    o->shard_n = 1;
    o->threads = 1;
    if (!o->sets || !o->varies) {
        fprintf(stderr, "rj: out of memory\n");
        exit(1);
    }
}

/* Every option and the subcommands that take it: an option is parsed only for these, and
   a misspelt one is matched against them for "did you mean". */
typedef struct optname { const char *name; int cmds; } optname;
#define CMD_SIM (CMD_RUN | CMD_PLOT | CMD_ANIMATE)
#define CMD_ALL (CMD_SIM | CMD_CHECK)
static const optname optnames[] = {
    { "--help", CMD_ALL | CMD_SWEEP }, { "--t-end", CMD_SIM | CMD_SWEEP }, { "--dt", CMD_ALL | CMD_SWEEP },
    { "--progress", CMD_ALL | CMD_SWEEP }, { "--force", CMD_SIM | CMD_SWEEP },  { "--out", CMD_PLOT | CMD_ANIMATE },
    { "--size", CMD_PLOT | CMD_ANIMATE },               { "--csv", CMD_RUN | CMD_PLOT | CMD_SWEEP },
    { "--x", CMD_PLOT },       { "--y", CMD_PLOT },     { "--lhs", CMD_SWEEP },   { "--grid", CMD_SWEEP },
    { "--sample", CMD_RUN },   { "--nodes", CMD_RUN },  { "--probe", CMD_RUN },   { "--loads", CMD_RUN },
    { "--settle", CMD_RUN },   { "--what", CMD_PLOT },  { "--fps", CMD_ANIMATE },
    { "--mp4", CMD_ANIMATE },  { "--plain", CMD_ANIMATE }, { "--assemble", CMD_CHECK },
    { "--set", CMD_ALL | CMD_SWEEP }, { "--vary", CMD_SWEEP }, { "--samples", CMD_SWEEP },
    { "--seed", CMD_SWEEP },   { "--shard", CMD_SWEEP }, { "--threads", CMD_SWEEP }, { "--resume", CMD_SWEEP }
};
#define NOPTS ((int)(sizeof optnames / sizeof optnames[0]))
static const char *const cmd_names[NCMDS] = { "run", "check", "plot", "animate", "sweep" };

/* The subcommand's name for a CMD_* bit. */
static const char *cmd_name(int cmd)
{
    int k;
    for (k = 0; k < NCMDS; k++)
        if (cmd == 1 << k) return cmd_names[k];
    return "?";
}

/* The CMD_* bits of the subcommands that take option a (0: none does). */
static int opt_cmds(const char *a)
{
    int k;
    for (k = 0; k < NOPTS; k++)
        if (!strcmp(a, optnames[k].name)) return optnames[k].cmds;
    return 0;
}

/* An option this subcommand does not take: another's is named as such, anything else
   gets the nearest of this subcommand's options. Exits 2 with the usage. */
static void opt_unknown(const cli *c, int cmd, const char *a)
{
    const char *names[NOPTS];
    const int other = opt_cmds(a);
    int k, n = 0;
    if (other) {
        for (k = 0; k < NCMDS && !(other & 1 << k); k++) {}
        fprintf(stderr, "%s: unknown option '%s' (rj %s takes it, not rj %s)\n%s", c->argv[0], a, cmd_name(1 << k),
                cmd_name(cmd), c->usage);
        exit(2);
    }
    for (k = 0; k < NOPTS; k++)
        if (optnames[k].cmds & cmd) names[n++] = optnames[k].name;
    cli_unknown(c, "option", a, names, n);
}

/* Options of more than one subcommand (opts_parse has checked that this one takes a);
   returns 1 when a was one of them. */
static int opt_shared(cli *c, opts *o, const char *a)
{
    if (!strcmp(a, "--t-end")) o->t_end = cli_num(c, a, 0, 1e6);
    else if (!strcmp(a, "--dt")) o->dt = cli_num(c, a, 0, 1);
    else if (!strcmp(a, "--progress")) o->progress = 1;
    else if (!strcmp(a, "--force")) o->force = 1;
    else if (!strcmp(a, "--out")) o->out = cli_str(c, a);
    else if (!strcmp(a, "--set")) o->sets[o->nsets++] = cli_str(c, a);
    else if (!strcmp(a, "--size")) {
        /* each side 16 .. 8192 pixels, as build/animate */
        static const int lim[4] = { 16, 8192, 16, 8192 };
        cli_pair(c, a, 'x', &o->w, &o->h, lim, "WxH, each 16..8192");
        o->size_given = 1;
    } else return 0;
    return 1;
}

/* The unit words a --vary may end with: those a scene file takes after an angle or a
   rate. Whether the key takes one is the file's to say (sweep_check loads it). */
static const char *const vary_units[] = { "deg/s", "rad/s", "deg", "rad" };

/* The unit word at the end of the len characters at s, glued to the number ("95deg") or
   after blanks ("95 deg"): returned, with *numlen the characters before it and the
   blanks; "" and len when there is none. */
static const char *vary_unit(const char *s, size_t len, size_t *numlen)
{
    size_t k;
    for (k = 0; k < sizeof vary_units / sizeof vary_units[0]; k++) {
        const size_t ul = strlen(vary_units[k]);
        size_t n;
        if (len <= ul || strcmp(s + len - ul, vary_units[k]) != 0) continue;
        /* the blanks between the number and the unit are neither's */
        for (n = len - ul; n > 0 && s[n - 1] == ' '; n--) {}
        *numlen = n;
        return vary_units[k];
    }
    *numlen = len;
    return "";
}

/* One number of a --vary: the n characters at s, a finite decimal number. 0, or -1. */
static int vary_number(const char *s, size_t n, double *v)
{
    char buf[64];
    if (n == 0 || n >= sizeof buf) return -1;
    memcpy(buf, s, n);
    buf[n] = '\0';
    /* cli_is_decimal refuses nan, inf and hex; 1e999 reads as inf and is refused too */
    if (!cli_is_decimal(buf)) return -1;
    *v = strtod(buf, NULL);
    return isfinite(*v) ? 0 : -1;
}

/* rj sweep --vary KEY=LO:HI (LO <= HI) or KEY=normal:MEAN:SD (SD >= 0), either with a
   unit word at the end. Whether the scene has the key, takes the unit and loads the
   ends (or the mean) is checked against the file (sweep_check). */
static void vary_parse(cli *c, const char *opt, vary *v)
{
    static const char need[] = "KEY=LO:HI or KEY=normal:MEAN:SD, a --set key and finite decimal numbers, "
                               "then a unit (deg, rad, deg/s, rad/s) where the key takes one";
    const char *s = cli_str(c, opt), *eq = strchr(s, '='), *nums, *colon;
    size_t len;
    double a, b;
    if (!eq || eq == s) cli_bad(c, opt, s, need);
    v->spec = s;
    v->keylen = (int)(eq - s);
    v->unit = vary_unit(eq + 1, strlen(eq + 1), &len);
    v->dist = !strncmp(eq + 1, "normal:", 7) ? DIST_NORMAL : DIST_UNIFORM;
    /* the two numbers: after "normal:" for a normal, one ':' between them */
    nums = eq + 1 + (v->dist == DIST_NORMAL ? 7 : 0);
    len -= (size_t)(nums - eq - 1);
    colon = (const char *)memchr(nums, ':', len);
    if (!colon || memchr(colon + 1, ':', len - (size_t)(colon + 1 - nums))) cli_bad(c, opt, s, need);
    if (vary_number(nums, (size_t)(colon - nums), &a) != 0) cli_bad(c, opt, s, need);
    if (vary_number(colon + 1, len - (size_t)(colon + 1 - nums), &b) != 0) cli_bad(c, opt, s, need);
    v->lo = v->mean = a;
    v->hi = v->sd = b;
    if (v->dist == DIST_UNIFORM && a > b) cli_bad(c, opt, s, "LO <= HI");
    if (v->dist == DIST_NORMAL && b < 0) cli_bad(c, opt, s, "SD >= 0, the normal's standard deviation");
}

/* --seed takes an integer in [0, 1e15] */
#define SEED_MAX 1000000000000000LL

/* rj sweep --grid K: at most this many samples, K^n for n --vary keys (an int indexes
   them; --resume keeps a byte for each) */
#define GRID_MAX_SAMPLES 1000000000

/* rj sweep --threads: at most this many, each with a model and a state of its own */
#define SWEEP_MAX_THREADS 256

/* --shard auto: one of the variables a Slurm job array sets, decimal digits in [lo, hi];
   missing or malformed it is bad usage, named (no guess at a shard). */
static int slurm_var(const cli *c, const char *name, int lo, int hi)
{
    const char *s = getenv(name), *rest;
    long long v = -1;
    char msg[200];
    if (!s || !*s)
        cli_die(c, "option --shard auto: %s is not set (Slurm sets it in a job array, sbatch --array=0-N; "
                "or give --shard i/n)%s", name, "");
    if (cli_digits(s, '\0', &rest, &v) != 0 || v < lo || v > hi) {
        snprintf(msg, sizeof msg, "%s='%.40s' is not an integer in [%d, %d]", name, s, lo, hi);
        cli_die(c, "option --shard auto: %s%s", msg, "");
    }
    return (int)v;
}

/* --shard auto: --shard i/n from the job array, n its task count and i the task's id
   less the array's first id (SLURM_ARRAY_TASK_MIN; 0 when unset, the first release's
   arrays), so that --array=1-8 runs 0/8 .. 7/8. An array whose tasks would not be the n
   shards once each is refused: one with a step (--array=0-15:2), ids that are not
   consecutive (--array=1,3,5), an id outside it. */
static void shard_auto(const cli *c, opts *o)
{
    const char *min_text = getenv("SLURM_ARRAY_TASK_MIN"), *max_text = getenv("SLURM_ARRAY_TASK_MAX");
    const char *step_text = getenv("SLURM_ARRAY_TASK_STEP");
    const int has_min = min_text && *min_text;
    int id, first = 0, last, step;
    char msg[300];
    o->shard_n = slurm_var(c, "SLURM_ARRAY_TASK_COUNT", 1, INT_MAX);
    id = slurm_var(c, "SLURM_ARRAY_TASK_ID", 0, INT_MAX - 1);
    if (has_min) first = slurm_var(c, "SLURM_ARRAY_TASK_MIN", 0, INT_MAX - 1);
    /* a step: the ids are first, first + step, ...; the shards would be missed */
    step = step_text && *step_text ? slurm_var(c, "SLURM_ARRAY_TASK_STEP", 1, INT_MAX) : 1;
    if (step != 1) {
        snprintf(msg, sizeof msg, "SLURM_ARRAY_TASK_STEP=%d: the array has a step, so its ids do not number "
                 "the shards (give sbatch consecutive ids: --array=%d-%d)", step, first, first + o->shard_n - 1);
        cli_die(c, "option --shard auto: %s%s", msg, "");
    }
    /* ids that are not consecutive (a list): the last is not first + count - 1 */
    last = max_text && *max_text ? slurm_var(c, "SLURM_ARRAY_TASK_MAX", 0, INT_MAX - 1) : first + o->shard_n - 1;
    if (has_min && (long long)last - first + 1 != o->shard_n) {
        snprintf(msg, sizeof msg, "SLURM_ARRAY_TASK_MIN=%d, SLURM_ARRAY_TASK_MAX=%d and SLURM_ARRAY_TASK_COUNT=%d: "
                 "the ids are not consecutive (give sbatch a range: --array=%d-%d)", first, last, o->shard_n, first,
                 first + o->shard_n - 1);
        cli_die(c, "option --shard auto: %s%s", msg, "");
    }
    o->shard_i = id - first;
    if (o->shard_i >= 0 && o->shard_i < o->shard_n) return;
    if (!has_min)
        snprintf(msg, sizeof msg, "SLURM_ARRAY_TASK_ID=%d is not below SLURM_ARRAY_TASK_COUNT=%d (number the array "
                 "from 0: sbatch --array=0-%d)", id, o->shard_n, o->shard_n - 1);
    else
        snprintf(msg, sizeof msg, "SLURM_ARRAY_TASK_ID=%d less SLURM_ARRAY_TASK_MIN=%d is %d, not in [0, %d] "
                 "(SLURM_ARRAY_TASK_COUNT=%d)", id, first, o->shard_i, o->shard_n - 1, o->shard_n);
    cli_die(c, "option --shard auto: %s%s", msg, "");
}

/* rj sweep's own options; returns 1 when a was one. */
static int opt_sweep(cli *c, opts *o, const char *a)
{
    /* --shard i/n: i >= 0, n >= 1 (i < n is checked once both are read) */
    static const int shard_lim[4] = { 0, INT_MAX - 1, 1, INT_MAX };
    if (!strcmp(a, "--vary")) vary_parse(c, a, &o->varies[o->nvary++]);
    else if (!strcmp(a, "--samples")) o->samples = cli_int(c, a, 1, 10000000);
    else if (!strcmp(a, "--lhs")) o->design = DESIGN_LHS;
    else if (!strcmp(a, "--grid")) o->grid = cli_int(c, a, 1, GRID_MAX_SAMPLES);
    else if (!strcmp(a, "--seed")) o->seed = (unsigned long long)cli_long(c, a, 0, SEED_MAX);
    else if (!strcmp(a, "--threads")) o->threads = cli_int(c, a, 1, SWEEP_MAX_THREADS);
    else if (!strcmp(a, "--resume")) o->resume = 1;
    else if (!strcmp(a, "--shard") && c->i + 1 < c->argc && !strcmp(c->argv[c->i + 1], "auto")) {
        c->i++;
        shard_auto(c, o);
    } else if (!strcmp(a, "--shard")) {
        cli_pair(c, a, '/', &o->shard_i, &o->shard_n, shard_lim, "i/n with 0 <= i < n");
        if (o->shard_i >= o->shard_n) cli_bad(c, a, c->argv[c->i], "i/n with 0 <= i < n");
    } else return 0;
    return 1;
}

/* rj plot --what: one of what_names, or sweep (a misspelt sweep suggested, since
   cli_choice knows only what_names). */
static int what_parse(cli *c, const char *opt)
{
    static const char *const sweep_name[1] = { "sweep" };
    const char *s = c->i + 1 < c->argc ? c->argv[c->i + 1] : "";
    int k;
    if (!strcmp(s, "sweep")) {
        c->i++;
        return WHAT_SWEEP;
    }
    for (k = 0; k < NWHAT && strcmp(s, what_names[k]) != 0; k++) {}
    if (k == NWHAT && cli_nearest(s, sweep_name, 1) && !cli_nearest(s, what_names, NWHAT))
        cli_die(c, "option --what: unknown value '%s'; did you mean '%s'?", s, "sweep");
    return cli_choice(c, opt, what_names, NWHAT);
}

/* Options of one subcommand each (checked by opts_parse); returns 1 when a was one. */
static int opt_own(cli *c, opts *o, const char *a)
{
    if (!strcmp(a, "--csv")) o->csv = cli_str(c, a);
    else if (!strcmp(a, "--sample")) o->sample = cli_num(c, a, 0, 1e6);
    else if (!strcmp(a, "--nodes")) o->nodes = cli_str(c, a);
    else if (!strcmp(a, "--probe")) o->probes[o->nprobes++] = cli_str(c, a);
    else if (!strcmp(a, "--loads")) o->loads[o->nloads++] = cli_str(c, a);
    else if (!strcmp(a, "--settle")) o->settle = 1;
    else if (!strcmp(a, "--what")) o->what = what_parse(c, a);
    else if (!strcmp(a, "--x")) o->x_col = cli_str(c, a);
    else if (!strcmp(a, "--y")) o->y_col = cli_str(c, a);
    else if (!strcmp(a, "--fps")) o->fps = cli_num(c, a, 1e-3, 1e9);
    else if (!strcmp(a, "--mp4")) o->mp4 = cli_str(c, a);
    else if (!strcmp(a, "--plain")) o->plain = 1;
    else if (!strcmp(a, "--assemble")) o->assemble = cli_str(c, a);
    else return opt_sweep(c, o, a);
    return 1;
}

/* rj sweep --grid K: the K^n samples of n keys, each a range; refused above
   GRID_MAX_SAMPLES, the number named. */
static void grid_samples(const cli *c, opts *o)
{
    double n = 1;
    int i;
    char msg[200];
    for (i = 0; i < o->nvary; i++) {
        const vary *v = &o->varies[i];
        if (v->dist == DIST_UNIFORM) continue;
        cli_die(c, "option --grid takes LO:HI ranges: --vary %s is a normal (draw it with --samples N, "
                "or give it a range)%s", v->spec, "");
    }
    for (i = 0; i < o->nvary; i++) n *= o->grid;
    if (n > GRID_MAX_SAMPLES) {
        snprintf(msg, sizeof msg, "option --grid %d: %d --vary keys make %d^%d = %.4g samples, more than the "
                 "1e9 a sweep takes (fewer points or keys)", o->grid, o->nvary, o->grid, o->nvary, n);
        cli_die(c, "%s%s", msg, "");
    }
    o->samples = (int)n;
    o->design = DESIGN_GRID;
}

/* rj sweep: --vary, and one of --samples (with --lhs or not) and --grid; --resume with a
   file. */
static void sweep_opts_check(const cli *c, opts *o)
{
    if (!o->nvary) cli_die(c, "option %s is required%s", "--vary", "");
    if (o->grid && o->samples)
        cli_die(c, "options --grid and --samples do not go together: --grid K runs K^n samples, every "
                "combination of K values of the n keys%s%s", "", "");
    if (o->grid && o->design == DESIGN_LHS)
        cli_die(c, "options --grid and --lhs do not go together: --lhs draws --samples N samples, --grid "
                "K sets them on a grid%s%s", "", "");
    if (o->grid) grid_samples(c, o);
    if (!o->samples) cli_die(c, "option %s is required (or --grid K)%s", "--samples", "");
    if (o->resume && (!o->csv || !strcmp(o->csv, "-")))
        cli_die(c, "option %s needs --csv FILE, the rows of the sweep to resume%s", "--resume", "");
}

/* rj plot: --what sweep reads --csv ROWS.csv instead of running a scene; --csv, --x and
   --y are for it alone. */
static void plot_opts_check(const cli *c, opts *o)
{
    const char *only = o->csv ? "--csv" : o->x_col ? "--x" : o->y_col ? "--y" : NULL;
    if (o->what != WHAT_SWEEP && only)
        cli_die(c, "option %s is for --what sweep (the rows of rj sweep)%s", only, "");
    if (o->what != WHAT_SWEEP) return;
    if (!o->csv) cli_die(c, "option --what sweep needs --csv ROWS.csv, the rows of rj sweep%s%s", "", "");
    if (o->scene)
        cli_die(c, "option --what sweep draws --csv ROWS.csv and runs no scene: unexpected argument '%s'%s",
                o->scene, "");
    if (!o->size_given) {
        o->w = 1000;
        o->h = 750;
    }
}

/* Parses a subcommand's arguments (argv[0] is "rj SUBCOMMAND"): options anywhere, one
   scene file. Bad usage prints the message and the usage and exits 2; --help exits 0. */
static void opts_parse(opts *o, int cmd, int argc, char **argv, const char *usage)
{
    cli c;
    const char *a;
    opts_default(o, cmd, argc);
    c.argc = argc;
    c.argv = argv;
    c.i = 0;
    c.usage = usage;
    while ((a = cli_next(&c)) != NULL) {
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            fputs(usage, stdout);
            exit(0);
        }
        if (a[0] == '-' && !(opt_cmds(a) & cmd)) opt_unknown(&c, cmd, a);
        if (opt_shared(&c, o, a) || opt_own(&c, o, a)) continue;
        if (o->scene) cli_die(&c, "one scene file only: unexpected argument '%s'%s", a, "");
        o->scene = a;
    }
    if (cmd == CMD_PLOT) plot_opts_check(&c, o);
    if (!o->scene && !(cmd == CMD_PLOT && o->what == WHAT_SWEEP))
        cli_die(&c, "missing the scene file (SCENE.rjs)%s%s", "", "");
    if ((cmd & (CMD_PLOT | CMD_ANIMATE)) && !o->out) cli_die(&c, "option %s is required%s", "--out", "");
    if (cmd == CMD_SWEEP) sweep_opts_check(&c, o);
}

/* ================================================================ the scene */

/* A loaded scene: the file (its names) and the model built from it. */
static double wall_now(void);

typedef struct scene {
    const char *path;
    rj_scene_file f;     /* kept for the link and joint names */
    rj_model *m;
    double build_s;      /* s, wall time rj_model_create took (rj check's cost line) */
} scene;

/* Loads and builds the scene, with solver.dt replaced when dt >= 0; loads: the command
   reads the element loads at t^n, which in-place stepping does not keep (solver.in_place,
   automatic from 400 nodes; its pin forces it does), so it steps double-buffered: the
   same bits, a little slower (rj_solver_def). Prints the parser's or the model's message
   as they give it ("file:line:col: message"); a step the command line set is blamed on
   the option, not on the file's dt key. Returns 0, or 2. */
static int scene_open(scene *sc, const char *path, double dt, const char **sets, int nsets,
                      int loads)
{
    rj_error e;
    rj_scene_def d;
    sc->path = path;
    sc->m = NULL;
    if (rj_scene_load_set(path, sets, nsets, &sc->f, &e) != RJ_OK) {
        fprintf(stderr, "%s\n", e.msg);
        return 2;
    }
    if (dt >= 0) sc->f.solver.dt = dt;
    if (loads) sc->f.solver.in_place = RJ_IN_PLACE_OFF;
    d = rj_scene_file_def(&sc->f);
    sc->build_s = wall_now();
    if (rj_model_create(&d, &sc->m, &e, NULL) == RJ_OK) {
        sc->build_s = wall_now() - sc->build_s;
        return 0;
    }
    if (dt >= 0 && !strcmp(e.field, "solver.dt")) {
        fprintf(stderr, "rj: option --dt %g: %s\n", dt, e.msg);
    } else {
        rj_scene_file_locate(&sc->f, &e);
        fprintf(stderr, "%s\n", e.msg);
    }
    rj_scene_file_free(&sc->f);
    return 2;
}

/* Frees what scene_open built. */
static void scene_close(scene *sc)
{
    rj_model_destroy(sc->m, NULL);
    rj_scene_file_free(&sc->f);
}

/* Names as the file gives them: columns, events and reports use them, not indices. */
static const char *joint_name(const scene *sc, int j) { return sc->f.joint_names[j]; }
static const char *link_name(const scene *sc, int l) { return sc->f.link_names[l]; }

/* The file name without its directories (the frames' caption, the plot's title). */
static const char *base_name(const char *path)
{
    const char *s = strrchr(path, '/');
    return s ? s + 1 : path;
}

/* The library's texts name joints by index ("joints[1] starts ...", "joint 1 caught ..."):
   " (joint 'NAME')" for the first one in text[0..len), or "" when there is none. */
static void joint_suffix(const scene *sc, const char *text, int len, char *buf, size_t n)
{
    const char *p = strstr(text, "joint");
    int j = -1;
    buf[0] = '\0';
    if (p && p - text < len) {
        const char *q = p + 5;
        if (*q == 's' && q[1] == '[') q += 2;
        else if (*q == ' ') q++;
        if (*q >= '0' && *q <= '9') j = atoi(q);
    }
    if (j >= 0 && j < rj_model_joint_count(sc->m)) snprintf(buf, n, " (joint '%s')", joint_name(sc, j));
}

/* One of the library's texts on standard error, the joint's name after it. */
static void print_named(const scene *sc, const char *prefix, const char *text, int len)
{
    char suffix[64];
    joint_suffix(sc, text, len, suffix, sizeof suffix);
    fprintf(stderr, "%s%.*s%s\n", prefix, len, text, suffix);
}

/* The model's warnings (a limit the joint starts past, a spring that never gets there),
   one a line, on standard error before a run. */
static void model_warnings(const scene *sc, const char *prog)
{
    const char *w = rj_model_warnings(sc->m);
    char prefix[48];
    snprintf(prefix, sizeof prefix, "%s: warning: ", prog);
    while (*w) {
        const char *e = strchr(w, '\n');
        const int len = e ? (int)(e - w) : (int)strlen(w);
        if (len > 0) print_named(sc, prefix, w, len);
        w += len + (e ? 1 : 0);
    }
}

/* ================================================================ the run */

/* Per joint: what the events summary reports, and the event lines' state. */
typedef struct jlog {
    int flag;                /* after the latest step */
    double lock_t;           /* s, when it locked (-1: never) */
    long contacts, releases; /* every flag change counted */
    double peak_limit;       /* N m, largest |limit torque| of any step */
    double peak_latch;       /* N m s, largest |latch impulse| of any step */
    double peak_pin;         /* N, largest |pin force| of any step (-1: none known) */
    double peak_pin_t;       /* s, its time (t^n: the step's start, as the force's) */
    int shown;               /* the flag the latest event line reported */
    int pend;                /* a change not printed yet (-1: none) */
    double pend_t;           /* s, its time */
    double overlap_t;        /* s, when its links passed through each other (-1: never) */
} jlog;

enum { PROGRESS_OFF = 0, PROGRESS_TTY, PROGRESS_ALWAYS };
/* The progress line: shown on a terminal once a run is long, or always with --progress. */
typedef struct progress {
    int mode;                /* PROGRESS_TTY: only after 2 s of wall time */
    int tty;                 /* standard error is a terminal: one line, redrawn */
    int shown;               /* such a line is on the screen: clear it before other text */
    double wall0, next;      /* s, monotonic clock: the start, the next update */
} progress;

enum { STOP_NONE = 0, STOP_FAIL, STOP_QUIET };
typedef struct runner runner;
/* Called at every sample; a nonzero return stops the run, r->stop says why. */
typedef int (*sink_fn)(runner *r, const rj_state *s);

/* One run of a scene: the per-step checks (events, peaks, warnings, progress) and the
   samples, which go to a sink: CSV rows, plot history or frames. */
struct runner {
    const scene *sc;
    const char *prog;
    rj_state *s;
    double t0, t_end;        /* s: the run's start (the settled time after --settle), its length */
    double every;            /* rows at the steps nearest to t0 + multiples of every */
    double t_prev;           /* s, time of the state before the latest step */
    long sampled;            /* steps at the latest sample (-1: none yet) */
    long warns;              /* state warnings printed so far */
    jlog *jl;
    double *pin;             /* every joint's pin force after the latest step */
    const int *peak_links;   /* rj run --loads: links whose element loads' peaks are kept */
    int npeak;
    double *peak;            /* per such link: |M|, its element, its end (0, 1), when; stress */
    sink_fn sink;
    void *data;
    int stop;                /* STOP_*: why a sink stopped the run */
    progress pr;
    double wall;             /* s, the run's wall time */
};

/* Wall time in seconds on the monotonic clock (a clock change does not skew rates). */
static double wall_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* A state at the start and the per-joint logs. every below the step is every step, which
   is what rj_run's rule gives then (and keeps its catch-up loop short). */
static int runner_init(runner *r, const scene *sc, const char *prog, double t_end, double every, int progress_opt)
{
    const rj_model *m = sc->m;
    const int nj = rj_model_joint_count(m);
    int j;
    memset(r, 0, sizeof *r);
    r->sc = sc;
    r->prog = prog;
    r->t_end = t_end;
    r->every = every < rj_model_dt(m) ? 0 : every;
    r->sampled = -1;
    r->jl = (jlog *)calloc((size_t)(nj > 0 ? nj : 1), sizeof *r->jl);
    r->pin = (double *)calloc(2 * (size_t)(nj > 0 ? nj : 1), sizeof *r->pin);
    if (!r->jl || !r->pin || rj_state_create(m, &r->s, NULL) != RJ_OK) {
        fprintf(stderr, "%s: out of memory\n", prog);
        return -1;
    }
    for (j = 0; j < nj; j++) {
        r->jl[j].flag = rj_joint_flag(m, r->s, j);
        r->jl[j].shown = r->jl[j].flag;
        r->jl[j].pend = -1;
        r->jl[j].lock_t = -1;
        r->jl[j].overlap_t = -1;
        r->jl[j].peak_pin = -1;
    }
    r->pr.tty = isatty(2);
    r->pr.mode = progress_opt ? PROGRESS_ALWAYS : r->pr.tty ? PROGRESS_TTY : PROGRESS_OFF;
    return 0;
}

/* Frees what runner_init made. */
static void runner_free(runner *r)
{
    if (r->s) rj_state_destroy(r->s, NULL);
    free(r->jl);
    free(r->pin);
    free(r->peak);
}

/* ---- progress ---- */

/* Clears the progress line (on a terminal) before other text goes to standard error. */
static void progress_clear(runner *r)
{
    if (!r->pr.shown) return;
    fprintf(stderr, "\r%79s\r", "");
    r->pr.shown = 0;
}

/* One progress line: percent, simulated time, steps/s and the remaining wall time at
   that rate; on a terminal it is redrawn in place, otherwise a line each time. */
static void progress_print(runner *r, const rj_state *s, double now)
{
    const double t = rj_state_time(s), el = now - r->pr.wall0, done = t - r->t0;
    const double frac = r->t_end > 0 && done < r->t_end ? done / r->t_end : 1.0;
    const double rate = el > 0 ? (double)rj_state_steps(s) / el : 0.0;
    const double eta = done > 0 ? el * (r->t_end - done) / done : 0.0;
    fprintf(stderr, "%s%s: %5.1f %%  t = %.4g s  %.3g steps/s  ETA %.0f s%s", r->pr.tty ? "\r" : "",
            r->prog, 100.0 * frac, t, rate, eta > 0 ? eta : 0.0, r->pr.tty ? "   " : "\n");
    r->pr.shown = r->pr.tty;
}

/* Every 64 steps: the clock costs about 20 ns, a step 0.2 us at the least. */
static void progress_tick(runner *r, const rj_state *s)
{
    double now;
    if (r->pr.mode == PROGRESS_OFF || (rj_state_steps(s) & 63) != 0) return;
    now = wall_now();
    if (now < r->pr.next) return;
    if (r->pr.mode == PROGRESS_TTY && now - r->pr.wall0 < 2.0) return;
    progress_print(r, s, now);
    r->pr.next = now + (r->pr.tty ? 0.25 : 1.0);
}

/* ---- events ---- */

/* Whether a lock at theta is at the forward limit: the nearer of the joint's limits. */
static int lock_is_forward(const rj_joint_def *d, double theta)
{
    if (!d->has_reverse) return 1;
    if (!d->has_forward) return 0;
    return fabs(remainder(theta - d->forward, RJ_TWO_PI)) <= fabs(remainder(theta - d->reverse, RJ_TWO_PI));
}

/* "the forward limit (90 deg)": the limit a flag (or the flag left) refers to. */
static void limit_text(const rj_joint_def *d, int flag, double theta, char *buf, size_t n)
{
    const int fwd = flag == RJ_LOCKED ? lock_is_forward(d, theta) : flag == RJ_AT_FORWARD;
    snprintf(buf, n, "the %s limit (%g deg)", fwd ? "forward" : "reverse", rj_deg(fwd ? d->forward : d->reverse));
}

/* One event line: the change from the flag last reported to flag, at t. */
static void event_print(runner *r, const rj_state *s, int j, int flag, double t)
{
    const rj_model *m = r->sc->m;
    jlog *L = &r->jl[j];
    const char *what = "contact with";
    char where[96];
    limit_text(rj_model_joint_def(m, j), flag != RJ_FREE ? flag : L->shown, rj_joint_theta_running(m, s, j), where, sizeof where);
    if (flag == RJ_FREE) what = "released from";
    else if (flag == RJ_LOCKED) what = "locked at";
    else if (L->contacts == 1 && L->releases == 0) what = "first contact with";
    L->shown = flag;
    L->pend = -1;
    progress_clear(r);
    fprintf(stderr, "%s: t = %.9g s: %s %s %s\n", r->prog, t, joint_name(r->sc, j), what, where);
}

/* A joint's flag changed in the latest step. Its time is that of the state the flag was
   decided on (the step's start), as rj_joint_event_time and rj_joint_release_time give
   it. A lock, and the first contact, are printed at once. Other changes wait until they
   have held EVENT_HOLD: adaptive and RC13 limits toggle the flag step by step while in
   contact, and a line per step would bury the events; the summary counts every change. */
static void flag_change(runner *r, const rj_state *s, int j, int flag)
{
    jlog *L = &r->jl[j];
    if (flag != RJ_FREE && L->flag == RJ_FREE) L->contacts++;
    if (flag == RJ_FREE) L->releases++;
    if (flag == RJ_LOCKED) L->lock_t = r->t_prev;
    L->flag = flag;
    if (flag == RJ_LOCKED || (flag != RJ_FREE && L->contacts == 1 && L->releases == 0)) {
        event_print(r, s, j, flag, r->t_prev);
        return;
    }
    if (flag == L->shown) {
        /* back to what was reported before it held: chatter */
        L->pend = -1;
        return;
    }
    if (L->pend < 0) L->pend_t = r->t_prev;
    L->pend = flag;
}

/* A pending change is printed once it has held EVENT_HOLD, or at the end (force). */
static void pending_check(runner *r, const rj_state *s, int j, int force)
{
    jlog *L = &r->jl[j];
    if (L->pend < 0) return;
    if (force || rj_state_time(s) - L->pend_t >= EVENT_HOLD) event_print(r, s, j, L->pend, L->pend_t);
}

/* A joint's two links passed through each other (links do not contact each other; the
   library records the first time, rj_joint_overlap_time): an event line, once per joint,
   with the multiple of 360 deg its angle turned through, the one nearest to it now.
   Returns 1 when this step reported one. */
static int overlap_check(runner *r, const rj_state *s, int j)
{
    const rj_model *m = r->sc->m;
    const rj_joint_def *d = rj_model_joint_def(m, j);
    const double t = rj_joint_overlap_time(m, s, j);
    const double turn = 360.0 * floor(rj_deg(rj_joint_theta_running(m, s, j)) / 360.0 + 0.5);
    if (r->jl[j].overlap_t >= 0 || t < 0 || d->body1 < 0) return 0;
    r->jl[j].overlap_t = t;
    progress_clear(r);
    fprintf(stderr, "%s: t = %.9g s: %s: links %s and %s passed through each other (it turned through %g deg; "
            "links do not contact each other)\n", r->prog, t, joint_name(r->sc, j), link_name(r->sc, d->body1),
            link_name(r->sc, d->body2), turn);
    return 1;
}

/* The state's latest warning, when the count has grown by more than the overlaps this
   step reported: the library counts each overlap as a warning too, and the event line
   has said it already. */
static void warning_check(runner *r, const rj_state *s, int overlaps)
{
    const long count = rj_state_warning_count(s);
    const long fresh = count - r->warns;
    char prefix[48];
    if (fresh == 0) return;
    r->warns = count;
    if (fresh <= overlaps) return;
    snprintf(prefix, sizeof prefix, "%s: warning: ", r->prog);
    progress_clear(r);
    print_named(r->sc, prefix, rj_state_warning(s), (int)strlen(rj_state_warning(s)));
}

/* ---- loads ---- */

/* Every joint's pin force, 2 a joint (NaN where the library has none). The library marks
   each joint it has none for; a call that fails whole (no memory for the rigid links'
   pass) leaves numbers that mean nothing, and those are made NaN too. */
static void pin_forces(const rj_model *m, const rj_state *s, double *pin)
{
    const int n = 2 * rj_model_joint_count(m);
    rj_result res;
    int j;
    for (j = 0; j < n; j++) pin[j] = NAN;
    res = rj_joint_pin_forces(m, s, pin);
    if (res == RJ_OK || res == RJ_ERR_INVALID) return;
    for (j = 0; j < n; j++) pin[j] = NAN;
}

/* A flexible link's largest |bending moment| over its elements' ends in state s (N m; -1
   where the library has none: a rigid or inextensible link, before a step); at[] gets its
   element and end (0, 1), the first where there are equal ones; *stress the largest
   outer-fibre stress (Pa, 0 where none is known). */
static double link_moment(const rj_model *m, const rj_state *s, int link, int at[2], double *stress)
{
    double best = -1;
    int e, end;
    *stress = 0;
    for (e = 0; e < rj_link_node_count(m, link) - 1; e++) {
        double L[5];
        if (rj_element_loads(m, s, link, e, L) != RJ_OK) continue;
        for (end = 0; end < 2; end++)
            if (fabs(L[2 + end]) > best) {
                best = fabs(L[2 + end]);
                at[0] = e;
                at[1] = end;
            }
        if (L[4] > *stress) *stress = L[4];
    }
    return best;
}

/* The peak links' largest bending moment (where, when) and outer-fibre stress. */
static void peak_moments(runner *r, const rj_state *s)
{
    const rj_model *m = r->sc->m;
    int j;
    for (j = 0; j < r->npeak; j++) {
        double *pk = r->peak + 5 * j, stress;
        int at[2] = { 0, 0 };
        const double mm = link_moment(m, s, r->peak_links[j], at, &stress);
        if (mm > pk[0]) {
            pk[0] = mm;
            pk[1] = at[0];
            pk[2] = at[1];
            pk[3] = rj_state_time(s) - rj_model_dt(m); /* the loads are at t^n */
        }
        if (stress > pk[4]) pk[4] = stress;
    }
}

/* The flags, the peaks, the overlaps and the state's warnings after each step. */
static void step_check(runner *r, const rj_state *s)
{
    const rj_model *m = r->sc->m;
    const int nj = rj_model_joint_count(m);
    int j, overlaps = 0;
    peak_moments(r, s);
    /* every joint's pin force (NaN where the library has none) for the peaks */
    pin_forces(m, s, r->pin);
    for (j = 0; j < nj; j++) {
        jlog *L = &r->jl[j];
        const int f = rj_joint_flag(m, s, j);
        const double pin = hypot(r->pin[2 * j], r->pin[2 * j + 1]);
        const double tl = fabs(rj_joint_torque(m, s, j, RJ_TORQUE_LIMIT));
        const double li = fabs(rj_joint_latch_impulse(m, s, j));
        if (f != L->flag) flag_change(r, s, j, f);
        pending_check(r, s, j, 0);
        if (tl > L->peak_limit) L->peak_limit = tl;
        if (li > L->peak_latch) L->peak_latch = li;
        if (!isnan(pin) && pin > L->peak_pin) {
            L->peak_pin = pin;
            L->peak_pin_t = rj_state_time(s) - rj_model_dt(m);
        }
        overlaps += overlap_check(r, s, j);
    }
    warning_check(r, s, overlaps);
}

/* rj_run_watched's callback at every step: events and peaks need every step, without the
   energy accounts (solver.energy_every takes them every K-th step and at the rows). */
static int on_step(const rj_model *m, const rj_state *s, void *u)
{
    runner *r = (runner *)u;
    (void)m;
    step_check(r, s);
    progress_tick(r, s);
    r->t_prev = rj_state_time(s);
    return 0;
}

/* Its callback at the rows: the start and the step nearest to each multiple of --sample
   from it (every step when the row interval is below the step). */
static int on_sample(const rj_model *m, const rj_state *s, void *u)
{
    runner *r = (runner *)u;
    (void)m;
    r->sampled = rj_state_steps(s);
    return r->sink(r, s);
}

/* Runs for t_end from the state's time (0, or where --settle left it). A failed step
   leaves the last good state: it is sampled too (unless it just was), so that a history
   ends there. Returns rj_run's result. */
static rj_result runner_go(runner *r)
{
    rj_result res;
    int j;
    r->t0 = rj_state_time(r->s);
    r->t_prev = r->t0;
    r->pr.wall0 = wall_now();
    r->pr.next = r->pr.wall0 + (r->pr.mode == PROGRESS_ALWAYS ? 0.5 : 0.0);
    res = rj_run_watched(r->sc->m, r->s, r->t0 + r->t_end, r->every, on_sample, on_step, r);
    r->wall = wall_now() - r->pr.wall0;
    /* --progress into a file or pipe ends with the line of the end */
    if (r->pr.mode == PROGRESS_ALWAYS && !r->pr.tty && r->stop != STOP_QUIET) progress_print(r, r->s, wall_now());
    progress_clear(r);
    for (j = 0; j < rj_model_joint_count(r->sc->m) && r->stop != STOP_QUIET; j++) pending_check(r, r->s, j, 1);
    if (res != RJ_OK && !r->stop && r->sampled != rj_state_steps(r->s)) r->sink(r, r->s);
    return res;
}

/* "1.234 s", or "none" for a negative time. */
static const char *time_text(double t, char *buf, size_t n)
{
    if (t < 0) snprintf(buf, n, "none");
    else snprintf(buf, n, "%.9g s", t);
    return buf;
}

/* A joint's summary line: the first contact (the library's rj_joint_event_time), the
   lock seen by the per-step check, the counts and the peaks; for a joint between two
   links, when they first passed through each other. */
static void joint_summary(const runner *r, int j)
{
    const rj_model *m = r->sc->m;
    const jlog *L = &r->jl[j];
    char a[40], b[40], c[64], p[48];
    c[0] = '\0';
    if (L->peak_pin >= 0) snprintf(p, sizeof p, "%.4g N", L->peak_pin);
    else snprintf(p, sizeof p, "none known");
    if (rj_model_joint_def(m, j)->body1 >= 0) {
        time_text(L->overlap_t, a, sizeof a);
        snprintf(c, sizeof c, ", links overlap %s", a);
    }
    fprintf(stderr, "%s: %s: first contact %s, lock %s, %ld contacts, %ld releases, peak penetration %.4g deg, "
            "peak |limit torque| %.4g N m, peak |latch impulse| %.4g N m s, peak |pin force| %s%s\n",
            r->prog, joint_name(r->sc, j), time_text(rj_joint_event_time(m, r->s, j), a, sizeof a),
            time_text(L->lock_t, b, sizeof b), L->contacts, L->releases,
            rj_deg(rj_joint_peak_penetration(m, r->s, j)), L->peak_limit, L->peak_latch, p, c);
}

/* The summary on standard error; a stopped simulation gets the library's message. */
static void runner_summary(const runner *r, rj_result res)
{
    const long steps = rj_state_steps(r->s);
    int j;
    if (res != RJ_OK) {
        fprintf(stderr, "%s: the simulation stopped after t = %.9g s (%s): %s\n", r->prog, rj_state_time(r->s),
                rj_result_str(res), rj_state_error(r->s));
    }
    fprintf(stderr, "%s: %s at t = %.9g s: %ld steps of %.4g s, wall %.3f s, %.3g steps/s\n", r->prog,
            res == RJ_OK && !r->stop ? "done" : "stopped", rj_state_time(r->s), steps, rj_model_dt(r->sc->m), r->wall,
            r->wall > 0 ? (double)steps / r->wall : 0.0);
    for (j = 0; j < rj_model_joint_count(r->sc->m); j++) joint_summary(r, j);
    for (j = 0; j < r->npeak; j++) {
        const double *pk = r->peak + 5 * j;
        fprintf(stderr, "%s: %s: peak |bending moment| %.6g N m at element %d, its %s node, t = %.9g s; "
                "peak outer-fibre stress %.6g Pa\n", r->prog, link_name(r->sc, r->peak_links[j]), pk[0],
                (int)pk[1], pk[2] ? "second" : "first", pk[3], pk[4]);
    }
}

/* ================================================================ rj run */

typedef struct probe { int link, node; } probe;

/* The history sink of rj run: the output, and the nodes to probe. */
typedef struct csv_sink {
    cli_out out;
    const probe *probes;
    int nprobes;
    const int *load_links; /* --loads: the links whose elements' loads are columns */
    int nloads;
    double *pin; /* every joint's pin force for the row (rj_joint_pin_forces) */
} csv_sink;

/* Column names after each joint's, link's and probe's name, and the energy columns. */
static const char *const joint_cols[] = { "theta_deg", "rate", "flag", "torque_spring", "torque_table",
                                          "torque_damping", "torque_friction", "torque_limit", "latch_impulse" };
static const char *const link_cols[] = { "tip_x", "tip_y", "tip_defl" };
static const char *const probe_cols[] = { "x", "y", "phi" };
#define NCOLS(a) ((int)(sizeof(a) / sizeof((a)[0])))

/* The header line: every column named from the file's own link and joint names. */
static void csv_header(csv_sink *c, const scene *sc)
{
    const rj_model *m = sc->m;
    int i, k;
    cli_put(&c->out, fputs("t", c->out.f));
    for (i = 0; i < rj_model_joint_count(m); i++) {
        for (k = 0; k < NCOLS(joint_cols); k++) cli_put(&c->out, fprintf(c->out.f, ",%s.%s", joint_name(sc, i), joint_cols[k]));
        if (rj_model_actuator_count(m)) cli_put(&c->out, fprintf(c->out.f, ",%s.torque_drive", joint_name(sc, i)));
        cli_put(&c->out, fprintf(c->out.f, ",%s.Fx,%s.Fy", joint_name(sc, i), joint_name(sc, i)));
    }
    for (i = 0; i < rj_model_link_count(m); i++)
        for (k = 0; k < NCOLS(link_cols); k++) cli_put(&c->out, fprintf(c->out.f, ",%s.%s", link_name(sc, i), link_cols[k]));
    for (i = 0; i < c->nprobes; i++)
        for (k = 0; k < NCOLS(probe_cols); k++)
            cli_put(&c->out, fprintf(c->out.f, ",%s.%d.%s", link_name(sc, c->probes[i].link), c->probes[i].node, probe_cols[k]));
    for (i = 0; i < c->nloads; i++) {
        const int l = c->load_links[i];
        for (k = 0; k < rj_link_node_count(m, l) - 1; k++)
            cli_put(&c->out, fprintf(c->out.f, ",%s.%d.N,%s.%d.V,%s.%d.M0,%s.%d.M1", link_name(sc, l), k,
                                     link_name(sc, l), k, link_name(sc, l), k, link_name(sc, l), k));
    }
    /* the library's energy accounts, then their balance */
    for (k = 0; k < rj_energy_account_count(); k++)
        if (rj_energy_account_in(m, k)) cli_put(&c->out, fprintf(c->out.f, ",%s", rj_energy_account_name(k)));
    cli_put(&c->out, fputs(",E_balance\n", c->out.f));
}

/* A joint's columns: angle in degrees (running, so it never jumps at 360), rate, flag,
   the torque components and the latch impulse. */
static void csv_joint(cli_out *o, const rj_model *m, const rj_state *s, int j, const double *pin)
{
    cli_put(o, fprintf(o->f, ",%.10g,%.10g,%d,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g",
                       rj_deg(rj_joint_theta_running(m, s, j)), rj_joint_rate(m, s, j), rj_joint_flag(m, s, j),
                       rj_joint_torque(m, s, j, RJ_TORQUE_SPRING), rj_joint_torque(m, s, j, RJ_TORQUE_TABLE),
                       rj_joint_torque(m, s, j, RJ_TORQUE_DAMPING), rj_joint_torque(m, s, j, RJ_TORQUE_FRICTION),
                       rj_joint_torque(m, s, j, RJ_TORQUE_LIMIT), rj_joint_latch_impulse(m, s, j)));
    /* the actuator's torque, in scenes that have actuators */
    if (rj_model_actuator_count(m)) cli_put(o, fprintf(o->f, ",%.10g", rj_joint_torque(m, s, j, RJ_TORQUE_DRIVE)));
    /* the pin force on body 2, empty where the library has none yet (NaN) */
    if (!isnan(pin[2 * j])) cli_put(o, fprintf(o->f, ",%.10g,%.10g", pin[2 * j], pin[2 * j + 1]));
    else cli_put(o, fputs(",,", o->f));
}

/* Tip position and the tip's deflection from the tangent at node 0 (second order in the
   element length, where the chord's is first order: scenes.h). */
static void csv_link(cli_out *o, const rj_model *m, const rj_state *s, int l)
{
    double tip[2];
    rj_node_position(m, s, l, rj_link_node_count(m, l) - 1, tip);
    cli_put(o, fprintf(o->f, ",%.10g,%.10g,%.10g", tip[0], tip[1], scene_tip_defl_tangent(m, s, l)));
}

/* The energy accounts, and the row's end. */
static void csv_energy(cli_out *o, const rj_model *m, const rj_state *s)
{
    rj_energy e;
    int k;
    rj_state_energy(m, s, &e);
    for (k = 0; k < rj_energy_account_count(); k++)
        if (rj_energy_account_in(m, k)) cli_put(o, fprintf(o->f, ",%.10g", rj_energy_account(&e, k)));
    cli_put(o, fprintf(o->f, ",%.10g\n", e.balance));
}

/* One row. A reader that went away (EPIPE on standard output) stops the run quietly. */
static int csv_sink_fn(runner *r, const rj_state *s)
{
    csv_sink *c = (csv_sink *)r->data;
    const rj_model *m = r->sc->m;
    int i;
    cli_put(&c->out, fprintf(c->out.f, "%.12g", rj_state_time(s)));
    pin_forces(m, s, c->pin);
    for (i = 0; i < rj_model_joint_count(m); i++) csv_joint(&c->out, m, s, i, c->pin);
    for (i = 0; i < rj_model_link_count(m); i++) csv_link(&c->out, m, s, i);
    for (i = 0; i < c->nprobes; i++) {
        double xy[2];
        rj_node_position(m, s, c->probes[i].link, c->probes[i].node, xy);
        cli_put(&c->out, fprintf(c->out.f, ",%.10g,%.10g,%.10g", xy[0], xy[1],
                                 rj_node_rotation(m, s, c->probes[i].link, c->probes[i].node)));
    }
    for (i = 0; i < c->nloads; i++) {
        int e;
        for (e = 0; e < rj_link_node_count(m, c->load_links[i]) - 1; e++) {
            double L[5];
            /* empty where the library has none (rj_element_loads) */
            if (rj_element_loads(m, s, c->load_links[i], e, L) == RJ_OK)
                cli_put(&c->out, fprintf(c->out.f, ",%.10g,%.10g,%.10g,%.10g", L[0], L[1], L[2], L[3]));
            else
                cli_put(&c->out, fputs(",,,,", c->out.f));
        }
    }
    csv_energy(&c->out, m, s);
    if (!c->out.err) return 0;
    r->stop = c->out.f == stdout && c->out.err == EPIPE ? STOP_QUIET : STOP_FAIL;
    return 1;
}

/* Flushes and closes the history. A reader of standard output that went away is no
   failure (rj run x.rjs | head): *quiet is set and nothing is printed. */
static int csv_close(cli_out *o, int *quiet)
{
    if (o->f && fflush(o->f) != 0 && !o->err) o->err = errno ? errno : EIO;
    if (o->f == stdout && o->err == EPIPE) {
        *quiet = 1;
        o->f = NULL;
        return 0;
    }
    return cli_close(o, "rj run");
}

/* "LINK:NODE" (NODE an index or "last") against the scene; prints why not and returns 2. */
static int probe_parse(const scene *sc, const char *spec, probe *p)
{
    const char *colon = strrchr(spec, ':'), *rest;
    char name[RJ_SCENE_NAME_MAX];
    long long v;
    int last;
    if (!colon || colon == spec || colon - spec >= (long)sizeof name) {
        fprintf(stderr, "rj run: option --probe: bad value '%s' (need LINK:NODE)\n", spec);
        return 2;
    }
    memcpy(name, spec, (size_t)(colon - spec));
    name[colon - spec] = '\0';
    p->link = rj_scene_link_index(&sc->f, name);
    if (p->link < 0) {
        fprintf(stderr, "rj run: option --probe %s: %s has no link '%s'\n", spec, sc->path, name);
        return 2;
    }
    last = rj_link_node_count(sc->m, p->link) - 1;
    p->node = last;
    if (!strcmp(colon + 1, "last")) return 0;
    if (cli_digits(colon + 1, '\0', &rest, &v) == 0 && v <= last) {
        p->node = (int)v;
        return 0;
    }
    fprintf(stderr, "rj run: option --probe %s: link '%s' has nodes 0..%d (or last)\n", spec, name, last);
    return 2;
}

/* Every node at the end, by link name. */
static int nodes_write(cli_out *o, const scene *sc, const rj_state *s)
{
    const rj_model *m = sc->m;
    int l, n;
    cli_put(o, fputs("link,node,x,y,phi\n", o->f));
    for (l = 0; l < rj_model_link_count(m); l++)
        for (n = 0; n < rj_link_node_count(m, l); n++) {
            double xy[2];
            rj_node_position(m, s, l, n, xy);
            cli_put(o, fprintf(o->f, "%s,%d,%.10g,%.10g,%.10g\n", link_name(sc, l), n, xy[0], xy[1], rj_node_rotation(m, s, l, n)));
        }
    return cli_close(o, "rj run");
}

/* Opens the history and the nodes file before anything runs: one that cannot be opened
   is bad usage (2), named by cli_open. */
static int run_outputs(const opts *o, csv_sink *c, cli_out *nodes)
{
    const char *csv = o->csv && strcmp(o->csv, "-") ? o->csv : NULL;
    memset(nodes, 0, sizeof *nodes);
    if (csv && cli_mkparent("rj run", csv) != 0) return 2;
    if (o->nodes && cli_mkparent("rj run", o->nodes) != 0) return 2;
    if (cli_open(&c->out, "rj run", csv) != 0) return 2;
    if (o->nodes && cli_open(nodes, "rj run", o->nodes) != 0) {
        cli_close(&c->out, "rj run");
        return 2;
    }
    return 0;
}

/* rj run --settle: what the settling's progress line needs. */
typedef struct settling {
    runner *r;
    double t_start;          /* s, the state's time when the settling began */
    double wall0;            /* s, monotonic clock at that moment */
} settling;

/* rj_settle_ex's callback (every 4096 steps): the progress line of the settling, under the
   run's rule (--progress, or on a terminal after 2 s). Steps are counted from the time:
   the library restarts its own count at each start from rest. Never stops it. */
static int settle_progress(const rj_model *m, const rj_state *s, void *user)
{
    settling *g = (settling *)user;
    runner *r = g->r;
    const double now = wall_now(), el = now - g->wall0;
    const double steps = floor((rj_state_time(s) - g->t_start) / rj_model_dt(m) + 0.5);
    if (r->pr.mode == PROGRESS_OFF || now < r->pr.next) return 0;
    if (r->pr.mode == PROGRESS_TTY && el < 2.0) return 0;
    fprintf(stderr, "%s%s: settling: %.0f steps (at most %.0e), t = %.4g s, %.3g steps/s%s", r->pr.tty ? "\r" : "",
            r->prog, steps, SETTLE_MAX_STEPS, rj_state_time(s), el > 0 ? steps / el : 0.0, r->pr.tty ? "   " : "\n");
    r->pr.shown = r->pr.tty;
    r->pr.next = now + (r->pr.tty ? 0.25 : 1.0);
    return 0;
}

/* rj run --settle: the state to the static equilibrium before the history starts. The
   library keeps the time the settling reached (a tabled load goes on from there), so the
   run starts at that time and lasts --t-end. Returns 0, or 1 (the library's message) when
   it does not settle. */
static int run_settle(runner *r, const scene *sc)
{
    settling g;
    rj_result res;
    int j;
    g.r = r;
    g.t_start = rj_state_time(r->s);
    g.wall0 = wall_now();
    r->pr.next = g.wall0 + (r->pr.mode == PROGRESS_ALWAYS ? 0.5 : 0.0);
    res = rj_settle_ex(sc->m, r->s, SETTLE_TOL, (long)SETTLE_MAX_STEPS, settle_progress, &g);
    progress_clear(r);
    if (res != RJ_OK) {
        fprintf(stderr, "rj run: --settle: %s\n", rj_state_error(r->s));
        return 1;
    }
    /* the joints' flags as settled, for the events that follow */
    for (j = 0; j < rj_model_joint_count(sc->m); j++) {
        r->jl[j].flag = rj_joint_flag(sc->m, r->s, j);
        r->jl[j].shown = r->jl[j].flag;
    }
    fprintf(stderr, "rj run: settled to the static equilibrium at t = %.9g s (%.0f steps, wall %.3f s); "
            "time starts there: the run goes on to t = %.9g s (--t-end %g s)\n", rj_state_time(r->s),
            floor((rj_state_time(r->s) - g.t_start) / rj_model_dt(sc->m) + 0.5), wall_now() - g.wall0,
            rj_state_time(r->s) + r->t_end, r->t_end);
    return 0;
}

/* The run and what it leaves: the history's end, the nodes, the summary. */
static int run_go(runner *r, csv_sink *c, cli_out *nodes)
{
    rj_result res;
    int quiet = 0, st;
    res = runner_go(r);
    st = csv_close(&c->out, &quiet);
    if (nodes->f && nodes_write(nodes, r->sc, r->s) != 0) st = 1;
    /* a closed pipe ends quietly, with nothing more on standard error */
    if (quiet || r->stop == STOP_QUIET) return st;
    runner_summary(r, res);
    if (res != RJ_OK) return 1;
    return st || r->stop == STOP_FAIL ? 1 : 0;
}

/* The --probe options against the scene, into pr (nprobes + 1 entries); 0, or 2 after
   saying which one is wrong. */
static int probes_resolve(const scene *sc, const opts *o, probe *pr)
{
    int i;
    for (i = 0; i < o->nprobes; i++)
        if (probe_parse(sc, o->probes[i], &pr[i]) != 0) return 2;
    return 0;
}

/* The --loads options against the scene, into links (nloads + 1 entries); 0, or 2 after
   saying which one is wrong. */
static int loads_resolve(const scene *sc, const opts *o, int *links)
{
    int i;
    for (i = 0; i < o->nloads; i++) {
        links[i] = rj_scene_link_index(&sc->f, o->loads[i]);
        if (links[i] < 0) {
            fprintf(stderr, "rj run: option --loads %s: %s has no link '%s'\n", o->loads[i], sc->path,
                    o->loads[i]);
            return 2;
        }
    }
    return 0;
}

/* rj run: the scene, the probes, the step bound and the outputs are checked before any
   output is written; then the run. */
static int cmd_run(int argc, char **argv)
{
    opts o;
    scene sc;
    runner r;
    csv_sink c;
    cli_out nodes;
    probe *pr;
    int *load_links;
    int st = 2;
    char usage[sizeof usage_run + sizeof usage_run_output];
    snprintf(usage, sizeof usage, "%s%s", usage_run, usage_run_output);
    opts_parse(&o, CMD_RUN, argc, argv, usage);
    /* every row's J.Fx, J.Fy and the summary's peaks are loads at t^n */
    if (scene_open(&sc, o.scene, o.dt, o.sets, o.nsets, 1) != 0) return 2;
    pr = (probe *)malloc(sizeof(probe) * (size_t)(o.nprobes + 1));
    load_links = (int *)malloc(sizeof(int) * (size_t)(o.nloads + 1));
    c.pin = (double *)malloc(sizeof(double) * 2 * (size_t)(rj_model_joint_count(sc.m) + 1));
    if (pr && load_links && c.pin && probes_resolve(&sc, &o, pr) == 0 && loads_resolve(&sc, &o, load_links) == 0) {
        /* the settling's steps count at their most, with the run's */
        cli_check_steps_plus("rj run", o.t_end, rj_model_dt(sc.m), o.settle ? SETTLE_MAX_STEPS : 0,
                             "settling steps (--settle)", o.force);
        st = run_outputs(&o, &c, &nodes);
    }
    if (pr && st == 0) {
        c.probes = pr;
        c.nprobes = o.nprobes;
        c.load_links = load_links;
        c.nloads = o.nloads;
        model_warnings(&sc, "rj run");
        csv_header(&c, &sc);
        st = runner_init(&r, &sc, "rj run", o.t_end, o.sample, o.progress) != 0 ? 1 : 0;
        r.sink = csv_sink_fn;
        r.data = &c;
        r.peak_links = load_links;
        r.npeak = o.nloads;
        r.peak = (double *)calloc(5 * (size_t)(o.nloads + 1), sizeof(double));
        if (!r.peak) st = 1;
        if (st == 0 && o.settle) st = run_settle(&r, &sc);
        /* the peaks count from the run's start, not the settling's */
        if (st == 0) memset(r.peak, 0, 5 * (size_t)(o.nloads + 1) * sizeof(double));
        if (st == 0) st = run_go(&r, &c, &nodes);
        runner_free(&r);
    }
    free(pr);
    free(load_links);
    free(c.pin);
    free((void *)o.probes);
    scene_close(&sc);
    return pr && load_links && c.pin ? st : 1;
}

/* ================================================================ rj check */

/* ---- rj check's progress
   Building the model (Lanczos for the step bound), building each link alone and timing the
   steps take minutes on a link of a million elements, and building reports nothing while it
   runs. So each phase is announced on standard error, with the wall time it started at:
   all of them with --progress; otherwise once the check has taken 1 s, the phase under way
   by a timer (SIGALRM: its handler only write()s the line prepared for it) and every phase
   after it directly. */
static volatile sig_atomic_t check_late;   /* phases are announced as they start */
static volatile sig_atomic_t check_told;   /* the current phase's line is out (or none) */
static volatile sig_atomic_t check_len;    /* its length */
static char check_line[256];               /* the current phase's line */
static double check_wall0;                 /* s, monotonic clock at the check's start */

/* The timer, 1 s into the check: from now on phases are announced, this one at once. */
static void check_alarm(int sig)
{
    (void)sig;
    check_late = 1;
    if (check_told) return;
    check_told = 1;
    if (write(2, check_line, (size_t)check_len) < 0) return;
}

/* Starts the check's clock; the timer, or with --progress every phase from the start.
   SA_RESTART: the timer must not cut a write to standard output short. */
static void check_progress_start(int always)
{
    struct sigaction sa;
    check_wall0 = wall_now();
    check_late = always;
    check_told = 1;
    if (always) return;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = check_alarm;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESTART;
    if (sigaction(SIGALRM, &sa, NULL) == 0) alarm(1);
}

/* A phase starts: its line goes out now when the check is late, else it waits for the
   timer. SIGALRM is held while the line changes, so the handler never reads half of it. */
static void check_phase(const char *fmt, ...)
{
    sigset_t alrm, old;
    va_list ap;
    char text[200];
    int len;
    va_start(ap, fmt);
    vsnprintf(text, sizeof text, fmt, ap);
    va_end(ap);
    sigemptyset(&alrm);
    sigaddset(&alrm, SIGALRM);
    sigprocmask(SIG_BLOCK, &alrm, &old);
    len = snprintf(check_line, sizeof check_line, "rj check: %.1f s: %s\n", wall_now() - check_wall0, text);
    check_len = len < 0 ? 0 : len < (int)sizeof check_line ? len : (int)sizeof check_line - 1;
    check_told = check_late;
    sigprocmask(SIG_SETMASK, &old, NULL);
    if (check_late) fputs(check_line, stderr);
}

/* The check is over: no timer; when phases were announced, the end is too. */
static void check_progress_stop(void)
{
    alarm(0);
    check_told = 1;
    if (check_late) fprintf(stderr, "rj check: %.1f s: done\n", wall_now() - check_wall0);
}

static const char *const fidelity_names[] = { "flexible", "rigid", "inextensible" };
static const char *const root_names[] = { "free", "pinned", "clamped", "fixed" };

/* Appends printf-style text to buf (size n); what does not fit is cut. */
static void cat(char *buf, size_t n, const char *fmt, ...)
{
    const size_t len = strlen(buf);
    va_list ap;
    if (len + 1 >= n) return;
    va_start(ap, fmt);
    vsnprintf(buf + len, n - len, fmt, ap);
    va_end(ap);
}

/* The cross-section's area, as the library takes it for each section kind. */
static double link_area(const rj_link_def *d)
{
    return d->section == RJ_SECTION_GENERAL ? d->area : d->width * d->height;
}

/* The link's own mass (rho A L), tip mass excluded. */
static double link_mass(const rj_link_def *d) { return d->rho * link_area(d) * d->length; }

/* Eq 28 for one link: the axial wave's transit of one element, l0 / sqrt(E / rho). */
static double link_eq28(const rj_link_def *d) { return d->length / d->elements / sqrt(d->E / d->rho); }

/* One line a link: model, mesh, length, masses, root, and its own Eq 28 step. */
static void check_links(const scene *sc)
{
    const rj_model *m = sc->m;
    int l;
    printf("links: %d, %d nodes\n", rj_model_link_count(m), rj_model_node_count(m));
    for (l = 0; l < rj_model_link_count(m); l++) {
        const rj_link_def *d = rj_model_link_def(m, l);
        printf("  %-12s %-12s %5d elements  length %g m  mass %.6g kg", link_name(sc, l),
               fidelity_names[d->fidelity], d->elements, d->length, link_mass(d));
        if (d->tip_mass > 0) printf("  tip mass %g kg", d->tip_mass);
        if (d->root != RJ_ROOT_FREE) printf("  root %s", root_names[d->root]);
        if (d->fidelity == RJ_LINK_RIGID) printf("\n");
        else printf("  Eq 28 %.4g s\n", link_eq28(d));
    }
}

/* The limit's method and what it uses: K, e, the release rule. */
static void limit_features(const rj_model *m, int j, char *buf, size_t n)
{
    const rj_joint_def *d = rj_model_joint_def(m, j);
    cat(buf, n, "; method %s", cli_methods[d->method]);
    if (d->method == RJ_METHOD_PENALTY) cat(buf, n, " (K %g N m/rad)", d->penalty_k);
    if (d->method == RJ_METHOD_ADAPTIVE) cat(buf, n, " (K_AP %.4g N m/rad at this dt)", rj_joint_stiffness(m, j));
    if (d->method == RJ_METHOD_MOMENTUM) cat(buf, n, " (e = %g)", d->restitution);
    cat(buf, n, ", release %s", cli_releases[d->release]);
}

/* What a joint uses, "; "-separated; a joint that uses nothing says so. */
static void joint_features(const rj_model *m, int j, char *buf, size_t n)
{
    const rj_joint_def *d = rj_model_joint_def(m, j);
    const int limited = d->has_forward || d->has_reverse;
    buf[0] = '\0';
    if (d->spring_k > 0) cat(buf, n, "; spring %g N m/rad free at %g deg", d->spring_k, rj_deg(d->spring_free_angle));
    if (d->table_count > 0) cat(buf, n, "; table of %d points", d->table_count);
    if (d->has_forward) cat(buf, n, "; forward limit %g deg", rj_deg(d->forward));
    if (d->has_reverse) cat(buf, n, "; reverse limit %g deg", rj_deg(d->reverse));
    if (d->lock) cat(buf, n, "; lock");
    if (limited) limit_features(m, j, buf, n);
    if (d->friction > 0) cat(buf, n, "; friction %g N m", d->friction);
    if (d->damping > 0) cat(buf, n, "; damping %g N m s/rad", d->damping);
    if (d->reference == RJ_REF_CHORD) cat(buf, n, "; chord reference");
    if (!buf[0]) cat(buf, n, "; bare (no spring, table, limit, friction or damping)");
}

/* Whether joint j closes a loop: an earlier joint has the same body2 (a link hangs from
   its first joint as body2). */
static int closes_loop(const rj_model *m, int j)
{
    int k;
    for (k = 0; k < j; k++)
        if (rj_model_joint_def(m, k)->body2 == rj_model_joint_def(m, j)->body2) return 1;
    return 0;
}

/* The mechanism's mobility as rigid bars (Gruebler's count): 3 a moving link, less 2 a
   joint, 2 a pinned root, 3 a clamped one. */
static int gruebler(const rj_model *m)
{
    int l, dof = 0;
    for (l = 0; l < rj_model_link_count(m); l++) {
        const rj_link_def *d = rj_model_link_def(m, l);
        if (d->root == RJ_ROOT_FIXED) continue;
        dof += 3;
        if (d->root == RJ_ROOT_PINNED) dof -= 2;
        if (d->root == RJ_ROOT_CLAMPED) dof -= 3;
    }
    return dof - 2 * rj_model_joint_count(m);
}

/* One line a joint: its bodies (and pin nodes when not the defaults), start angle,
   features; then the loops and the mobility. */
static void check_joints(const scene *sc)
{
    const rj_model *m = sc->m;
    int j, loops = 0;
    printf("joints: %d\n", rj_model_joint_count(m));
    for (j = 0; j < rj_model_joint_count(m); j++) {
        const rj_joint_def *d = rj_model_joint_def(m, j);
        char feat[640], b1[64], b2[64];
        if (d->body1 < 0) snprintf(b1, sizeof b1, "ground");
        else if (d->node1 < 0) snprintf(b1, sizeof b1, "%s", link_name(sc, d->body1));
        else snprintf(b1, sizeof b1, "%s node %d", link_name(sc, d->body1), d->node1);
        if (d->node2 == 0) snprintf(b2, sizeof b2, "%s", link_name(sc, d->body2));
        else if (d->node2 < 0) snprintf(b2, sizeof b2, "%s last node", link_name(sc, d->body2));
        else snprintf(b2, sizeof b2, "%s node %d", link_name(sc, d->body2), d->node2);
        joint_features(m, j, feat, sizeof feat);
        printf("  %-12s %s -> %s, starts at %g deg%s: %s\n", joint_name(sc, j), b1, b2,
               rj_deg(d->angle0), closes_loop(m, j) ? ", closes a loop" : "", feat + 2);
        loops += closes_loop(m, j);
    }
    if (loops) {
        rj_scene_def d = rj_scene_file_def(&sc->f);
        int mobility, rank;
        printf("loops: %d; as rigid bars the mechanism has %d degree%s of freedom (Gruebler)", loops,
               gruebler(m), gruebler(m) == 1 ? "" : "s");
        if (rj_scene_mobility(&d, &mobility, &rank, NULL) == RJ_OK)
            printf("; its loops' constraints have rank %d of %d, so %d at the start", rank, 2 * loops, mobility);
        printf("\n");
    }
}

/* Gravity and one line a load: its node, force (and frame), moment, table. Nothing when
   the scene has neither. */
static void check_loads(const scene *sc)
{
    const rj_model *m = sc->m;
    const rj_solver_def *sv = &sc->f.solver;
    int k;
    if (sv->gravity[0] != 0 || sv->gravity[1] != 0)
        printf("gravity: (%g, %g) m/s^2\n", sv->gravity[0], sv->gravity[1]);
    if (rj_model_load_count(m) == 0) return;
    printf("loads: %d\n", rj_model_load_count(m));
    for (k = 0; k < rj_model_load_count(m); k++) {
        const rj_load_def *d = rj_model_load_def(m, k);
        char node[32], table[96];
        if (d->node < 0) snprintf(node, sizeof node, "last node");
        else snprintf(node, sizeof node, "node %d", d->node);
        table[0] = '\0';
        if (d->table_count > 0)
            snprintf(table, sizeof table, "; a table of %d points from %g to %g s", d->table_count,
                     d->table_time[0], d->table_time[d->table_count - 1]);
        printf("  %-12s %s %s: force (%g, %g) N %s, moment %g N m%s\n", sc->f.load_names[k],
               link_name(sc, d->link), node, d->force[0], d->force[1],
               d->follower ? "turning with the node" : "fixed", d->moment, table);
    }
}

/* The actuators, one line each: type, joint and what drives it. */
static void check_actuators(const scene *sc)
{
    const rj_model *m = sc->m;
    int k;
    if (rj_model_actuator_count(m) == 0) return;
    printf("actuators: %d\n", rj_model_actuator_count(m));
    for (k = 0; k < rj_model_actuator_count(m); k++) {
        const rj_actuator_def *d = rj_model_actuator_def(m, k);
        printf("  %-12s on %s: ", sc->f.actuator_names[k], joint_name(sc, d->joint));
        if (d->type == RJ_ACTUATOR_TORQUE)
            printf("torque %g N m%s\n", d->torque, d->table_count ? " times its table" : "");
        else if (d->type == RJ_ACTUATOR_DC) {
            printf("DC motor, stall %g N m, no load %g rad/s", d->stall_torque, d->no_load_speed);
            if (d->has_cutoff) printf(", off from %g deg", rj_deg(d->cutoff));
            printf("\n");
        } else if (d->type == RJ_ACTUATOR_SERVO) {
            printf("servo to %g deg", rj_deg(d->target));
            if (d->profile != RJ_PROFILE_RAMP || d->profile_value != 0)
                printf(" along a profile from t = %g s", d->start);
            printf(", kp %g N m/rad, kd %g N m s/rad", d->kp, d->kd);
            if (d->torque_max > 0) printf(", within +-%g N m", d->torque_max);
            printf("\n");
        } else {
            static const char *const names[3] = { "ramp at", "cycloidal stroke of", "spin-up to" };
            if (d->profile == RJ_PROFILE_TABLE)
                printf("prescribed along a table of %d points over %g s", d->table_count,
                       d->table_time[d->table_count - 1] - d->table_time[0]);
            else
                printf("prescribed %s %g %s", names[d->profile],
                       d->profile == RJ_PROFILE_CYCLOIDAL ? rj_deg(d->profile_value) : d->profile_value,
                       d->profile == RJ_PROFILE_CYCLOIDAL ? "deg" : "rad/s");
            if (d->profile == RJ_PROFILE_CYCLOIDAL || d->profile == RJ_PROFILE_SPINUP)
                printf(" in %g s", d->profile_time);
            printf(" from t = %g s\n", d->start);
        }
        if (d->rotor_inertia > 0)
            printf("  %-12s rotor %g kg m^2 behind %g:1 (reflected %g kg m^2)\n", "", d->rotor_inertia,
                   d->gear_ratio, d->gear_ratio * d->gear_ratio * d->rotor_inertia);
    }
}

/* The cable loops, one line each. */
static void check_couplings(const scene *sc)
{
    const rj_model *m = sc->m;
    int k;
    if (rj_model_coupling_count(m) == 0) return;
    printf("couplings: %d\n", rj_model_coupling_count(m));
    for (k = 0; k < rj_model_coupling_count(m); k++) {
        const rj_coupling_def *d = rj_model_coupling_def(m, k);
        printf("  %-12s %s follows %g x %s", sc->f.coupling_names[k], joint_name(sc, d->joint_b), d->ratio,
               joint_name(sc, d->joint_a));
        if (d->offset != 0) printf(" %+g deg", rj_deg(d->offset));
        printf(": stiffness %g N m/rad, damping %g N m s/rad\n", d->stiffness, d->damping);
    }
}

/* omega_max of one link alone (its root as defined, no joints): how fast its own modes
   are, beams and tip mass. Rigid links have none (0); NaN when it cannot be built. */
static double link_omega(const rj_model *m, int l)
{
    rj_link_def d = *rj_model_link_def(m, l);
    rj_scene_def sd = rj_default_scene_def();
    rj_model *lm;
    rj_error e;
    double om;
    if (d.fidelity == RJ_LINK_RIGID) return 0;
    d.vx = 0;
    d.vy = 0;
    d.omega = 0;
    sd.links = &d;
    sd.link_count = 1;
    if (rj_model_create(&sd, &lm, &e, NULL) != RJ_OK) return NAN;
    om = rj_model_omega_max(lm);
    rj_model_destroy(lm, NULL);
    return om;
}

/* A joint's omega ~ sqrt(k (1/I1 + 1/I2)), k as the bound counts it: the spring, and a
   limit's stiffness 4 K for penalty (a contact that switches pumps energy above omega dt
   = 1) or 2 K_AP for adaptive (K_AP alone gives omega dt = 1 at any dt). Ground: 1/I1 = 0. */
static double joint_omega(const rj_model *m, int j, double *k_out)
{
    const rj_joint_def *d = rj_model_joint_def(m, j);
    double I1, I2, k = d->spring_k, c;
    const int limited = d->has_forward || d->has_reverse;
    rj_joint_inertias(m, j, &I1, &I2);
    if (limited && d->method == RJ_METHOD_PENALTY) k += 4.0 * rj_joint_stiffness(m, j);
    if (limited && d->method == RJ_METHOD_ADAPTIVE) k += 2.0 * rj_joint_stiffness(m, j);
    c = (d->body1 >= 0 && I1 > 0 ? 1.0 / I1 : 0.0) + (I2 > 0 ? 1.0 / I2 : 0.0);
    *k_out = k;
    return sqrt(k * c);
}

/* A joint's compliance 1/I1 + 1/I2 (ground or a fixed body: its side 0). */
static double joint_compliance(const rj_model *m, int j)
{
    double I1, I2;
    rj_joint_inertias(m, j, &I1, &I2);
    return (rj_model_joint_def(m, j)->body1 >= 0 && I1 > 0 ? 1.0 / I1 : 0.0) + (I2 > 0 ? 1.0 / I2 : 0.0);
}

/* A cable loop's omega on its own: sqrt(k (c_b + ratio^2 c_a)), its stiffness over the two
   joints' compliances. */
static double loop_omega(const rj_model *m, int k)
{
    const rj_coupling_def *d = rj_model_coupling_def(m, k);
    return sqrt(d->stiffness * (joint_compliance(m, d->joint_b) +
                                d->ratio * d->ratio * joint_compliance(m, d->joint_a)));
}

/* Where the step comes from: the file (or --dt), or the library's automatic choice, 0.9 x
   the bound unless capped (rigid links without stiff joints: 1 ms). */
static const char *dt_source(const scene *sc)
{
    const rj_model *m = sc->m;
    if (sc->f.solver.dt > 0) return "solver.dt";
    if (fabs(rj_model_dt(m) / (0.9 * rj_model_dt_bound(m)) - 1) < 1e-6) return "automatic: 0.9 x the bound";
    return "automatic, below 0.9 x the bound: rigid links step at most 1 ms, adaptive limits as their K_AP allows";
}

/* The step in use, the bound, and the paper's Eq 28 with the link that has it (the
   library's minimum over every link; a rigid link has no axial wave to limit it). */
static void check_dt(const scene *sc)
{
    const rj_model *m = sc->m;
    const double dt = rj_model_dt(m), bound = rj_model_dt_bound(m);
    int l, lmin = 0;
    printf("step:\n  dt %.6g s (%s), %.3g x the stability bound\n", dt, dt_source(sc), dt / bound);
    printf("  stability bound %.6g s = 2 x 0.98 / omega_max (less with joint damping), omega_max %.6g rad/s\n",
           bound, rj_model_omega_max(m));
    for (l = 1; l < rj_model_link_count(m); l++)
        if (link_eq28(rj_model_link_def(m, l)) < link_eq28(rj_model_link_def(m, lmin))) lmin = l;
    printf("  Eq 28 (paper) %.6g s: the axial wave's transit of one element of link %s%s\n", rj_model_dt_eq28(m),
           link_name(sc, lmin), rj_model_link_def(m, lmin)->fidelity == RJ_LINK_RIGID ? " (rigid: no wave limits it)" : "");
}

/* What sets the bound: the fastest link on its own against the stiffest joint, each as a
   share of the model's omega_max (Lanczos on the whole linearised model). */
static void check_binding(const scene *sc)
{
    const rj_model *m = sc->m;
    const double om = rj_model_omega_max(m);
    double lo = 0, jo = 0, jk = 0;
    int l, j, lb = -1, jb = -1;
    for (l = 0; l < rj_model_link_count(m); l++) {
        double w;
        check_phase("building link %s alone (%d elements) for its own step bound", link_name(sc, l),
                    rj_model_link_def(m, l)->elements);
        w = link_omega(m, l);
        if (!(w > lo)) continue;
        lo = w;
        lb = l;
    }
    for (j = 0; j < rj_model_joint_count(m); j++) {
        double k;
        const double w = joint_omega(m, j, &k);
        if (!(w > jo)) continue;
        jo = w;
        jb = j;
        jk = k;
    }
    {
        /* a cable loop can be the stiffest thing too */
        double co = 0;
        int k, cb = -1;
        for (k = 0; k < rj_model_coupling_count(m); k++)
            if (loop_omega(m, k) > co) {
                co = loop_omega(m, k);
                cb = k;
            }
        if (cb >= 0 && co > lo && co > jo) {
            printf("  stiffest cable loop: %s, omega ~ sqrt(k (c_b + ratio^2 c_a)) = %.4g rad/s (%.0f %% of omega_max)\n",
                   sc->f.coupling_names[cb], co, 100 * co / om);
            printf("  the bound is set by cable loop %s\n", sc->f.coupling_names[cb]);
            return;
        }
    }
    if (lb >= 0) printf("  fastest link on its own: %s, omega %.4g rad/s (%.0f %% of omega_max)\n", link_name(sc, lb), lo, 100 * lo / om);
    if (jb >= 0) printf("  stiffest joint: %s, omega ~ sqrt(k (1/I1 + 1/I2)) = %.4g rad/s with k = %.4g N m/rad (%.0f %% of omega_max)\n",
                        joint_name(sc, jb), jo, jk, 100 * jo / om);
    if (lb < 0 && jb < 0) printf("  nothing stiff bounds the step (rigid links, no stiff joint)\n");
    else if (lo >= jo) printf("  the bound is set by link %s\n", link_name(sc, lb));
    else printf("  the bound is set by joint %s\n", joint_name(sc, jb));
}

/* Seconds for 200 steps, or a negative number when a step fails. */
static double time_batch(const rj_model *m, rj_state *s)
{
    const double w0 = wall_now();
    int k;
    for (k = 0; k < 200; k++)
        if (rj_step(m, s) != RJ_OK) return -1;
    return wall_now() - w0;
}

/* qsort order for doubles (the batch times' median). */
static int cmp_double(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* What timing the steps found: the median batch, or the step that failed and why. */
typedef struct cost {
    double per;          /* s a step: the median batch / 200 (batches > 0) */
    int batches;         /* batches timed */
    int failed;          /* a step failed */
    double t_fail;       /* s, the time of the state the failed step left */
    char msg[640];       /* the library's message (rj_state_error) */
    double build;        /* s, the median of the builds after the first */
    int builds;          /* those builds */
} cost;

/* A sweep builds the model once a sample, in memory the last one freed: the builds
   after the first, until 10 ms or 15 of them; their median into c (the first, which
   faults its memory in, is scene_open's). A first build over 0.1 s is not repeated. */
static void cost_builds(const scene *sc, cost *c)
{
    const rj_scene_def d = rj_scene_file_def(&sc->f);
    double b[15], total = 0;
    int n = 0;
    while (n < 15 && total < 0.01 && sc->build_s <= 0.1) {
        rj_model *m = NULL;
        rj_error e;
        const double t0 = wall_now();
        if (rj_model_create(&d, &m, &e, NULL) != RJ_OK) break;
        b[n] = wall_now() - t0;
        rj_model_destroy(m, NULL);
        total += b[n++];
    }
    qsort(b, (size_t)n, sizeof b[0], cmp_double);
    c->builds = n;
    c->build = n > 0 ? b[n / 2] : 0;
}

/* The cost of one simulated second here: 200-step batches timed after one batch of
   warm-up (the first steps fault pages in), until 10 ms or 15 batches; the median batch,
   extrapolated to 1 / dt steps. A step that fails stops the timing and is kept in c. */
static void cost_measure(const scene *sc, cost *c)
{
    const rj_model *m = sc->m;
    rj_state *s;
    double b[15], total = 0;
    int n = 0;
    memset(c, 0, sizeof *c);
    check_phase("timing 200-step batches (%d nodes)", rj_model_node_count(m));
    if (rj_state_create(m, &s, NULL) != RJ_OK) return;
    b[0] = time_batch(m, s);
    while (b[0] >= 0 && n < 15 && total < 0.01) {
        b[n] = time_batch(m, s);
        if (b[n] < 0) break;
        total += b[n++];
    }
    c->failed = rj_state_error(s)[0] != '\0';
    c->t_fail = rj_state_time(s);
    snprintf(c->msg, sizeof c->msg, "%s", rj_state_error(s));
    c->batches = n;
    qsort(b, (size_t)n, sizeof b[0], cmp_double);
    c->per = n > 0 ? b[n / 2] / 200 : 0;
    rj_state_destroy(s, NULL);
    cost_builds(sc, c);
}

/* The cost line, and the failed step when there was one. */
static void cost_print(const scene *sc, const cost *c)
{
    const double dt = rj_model_dt(sc->m);
    if (c->batches > 0) {
        printf("cost: 1 simulated second = %.6g steps, about %.3g s here (%.3g us a step: the median of %d batches of 200)\n",
               1.0 / dt, c->per / dt, 1e6 * c->per, c->batches);
        /* what a sweep pays per sample before its first step */
        if (c->builds > 0)
            printf("cost: building the model took %.3g ms, as long as %.0f steps (the median of %d builds after the first, which took %.3g ms; wall time)\n",
                   1e3 * c->build, c->build / c->per, c->builds, 1e3 * sc->build_s);
        else
            printf("cost: building the model took %.3g ms, as long as %.0f steps (one build, wall time)\n",
                   1e3 * sc->build_s, sc->build_s / c->per);
    }
    if (c->failed && c->batches == 0) printf("cost: the first steps fail at t = %.6g s: %s\n", c->t_fail, c->msg);
    else if (c->failed) printf("cost: then a step fails at t = %.6g s: %s\n", c->t_fail, c->msg);
}

/* One warning line; counts them. */
static void warn(int *count, const char *fmt, ...)
{
    va_list ap;
    if (*count == 0) printf("warnings:\n");
    (*count)++;
    fputs("  - ", stdout);
    va_start(ap, fmt);
    vprintf(fmt, ap);
    va_end(ap);
    fputc('\n', stdout);
}

/* A penalty stiffness above Eq 31 at the step in use (the paper's bound on K). */
static void warn_joints(const scene *sc, int *count)
{
    const rj_model *m = sc->m;
    int j;
    for (j = 0; j < rj_model_joint_count(m); j++) {
        const rj_joint_def *d = rj_model_joint_def(m, j);
        const int limited = d->has_forward || d->has_reverse;
        const double kmax = rj_joint_kmax_eq31(m, j, rj_model_dt(m));
        if (limited && d->method == RJ_METHOD_PENALTY && d->penalty_k > kmax)
            warn(count, "joint %s: penalty_k %g N m/rad is above Eq 31's K_max %.6g N m/rad at dt %.4g s",
                 joint_name(sc, j), d->penalty_k, kmax, rj_model_dt(m));
    }
}

/* A tip mass above twice the link's own mass on fewer than 10 elements. The tip mass then
   sets the link's first mode, and the link's own mass and stiffness around it are
   resolved only as well as the mesh resolves them: the deployment benchmark (arm1's tip
   mass is 2.3 x its mass) needs 20 elements to get the joint angles within 0.1 deg of the
   converged reference, and 10 elements are 0.44 deg off (BENCHMARKS.md, sweep). Below 10
   elements such a link is off by more than that; at 10 and above, or with a lighter tip,
   the mesh is the engineer's ordinary choice. */
static void warn_links(const scene *sc, int *count)
{
    const rj_model *m = sc->m;
    int l;
    for (l = 0; l < rj_model_link_count(m); l++) {
        const rj_link_def *d = rj_model_link_def(m, l);
        const double lm = link_mass(d);
        if (d->fidelity != RJ_LINK_RIGID && d->tip_mass > 2.0 * lm && d->elements < 10)
            warn(count, "link %s: tip mass %g kg is %.3g x the link's own %.4g kg on %d elements: "
                 "too coarse a mesh for the mode the tip mass sets (use 10 or more)",
                 link_name(sc, l), d->tip_mass, d->tip_mass / lm, lm, d->elements);
    }
}

/* The warnings: the model's own first, then ours, then the step against the bound. */
static void check_warnings(const scene *sc)
{
    const rj_model *m = sc->m;
    const char *w = rj_model_warnings(m);
    const double dt = rj_model_dt(m), bound = rj_model_dt_bound(m);
    int count = 0;
    while (*w) {
        const char *e = strchr(w, '\n');
        const int len = e ? (int)(e - w) : (int)strlen(w);
        char suffix[64];
        joint_suffix(sc, w, len, suffix, sizeof suffix);
        if (len > 0) warn(&count, "%.*s%s (the model's warning)", len, w, suffix);
        w += len + (e ? 1 : 0);
    }
    warn_joints(sc, &count);
    warn_links(sc, &count);
    if (dt > bound) warn(&count, "dt %.4g s is above the stability bound %.4g s (allow_unstable): expect a blow-up", dt, bound);
    else if (dt > 0.9 * bound * 1.000001) warn(&count, "dt %.4g s is %.3g x the stability bound: the automatic step keeps 0.9", dt, dt / bound);
    if (count == 0) printf("warnings: none\n");
}

/* rj check: valid scenes print their report and exit 0; invalid ones exit 2 in scene_open.
   A scene whose steps fail while they are timed cannot be simulated: it is not valid, and
   the check says why and exits 1. The steps are timed first, so that the first line can
   say so; the phases go to standard error on a long check. */
/* The scene text of f with its joints J, into a new buffer (NULL: out of memory). */
static char *scene_text(const rj_scene_file *f, const rj_joint_def *J)
{
    rj_scene_def d = rj_scene_file_def(f);
    const char **ln = (const char **)malloc(sizeof(char *) * (size_t)(d.link_count + d.joint_count + 1));
    char *buf = NULL;
    size_t n;
    int k;
    if (!ln) return NULL;
    for (k = 0; k < d.link_count; k++) ln[k] = f->link_names[k];
    for (k = 0; k < d.joint_count; k++) ln[d.link_count + k] = f->joint_names[k];
    d.joints = J;
    n = rj_scene_write_ex(&d, ln, ln + d.link_count, f->title, NULL, 0);
    if (n) buf = (char *)malloc(n + 1);
    if (buf) rj_scene_write_ex(&d, ln, ln + d.link_count, f->title, buf, n + 1);
    free((void *)ln);
    return buf;
}

/* rj check --assemble FILE: the scene's loops closed (rj_scene_assemble), written to FILE.
   0, or 2 with the message on standard error. */
static int check_assemble(const char *path, const char *out)
{
    rj_scene_file f;
    rj_error e;
    rj_scene_def d;
    rj_joint_def *J;
    char *text = NULL;
    FILE *fp;
    int k, moved = 0, rc = 2;
    if (rj_scene_load(path, &f, &e) != RJ_OK) {
        fprintf(stderr, "%s\n", e.msg);
        return 2;
    }
    d = rj_scene_file_def(&f);
    J = (rj_joint_def *)malloc(sizeof(rj_joint_def) * (size_t)(d.joint_count + 1));
    if (J) memcpy(J, d.joints, sizeof(rj_joint_def) * (size_t)d.joint_count);
    if (!J) fprintf(stderr, "rj: out of memory\n");
    else if (rj_scene_assemble(&d, J, &e) != RJ_OK) {
        rj_scene_file_locate(&f, &e);
        fprintf(stderr, "%s\n", e.msg);
    } else if (!(text = scene_text(&f, J))) fprintf(stderr, "rj: out of memory\n");
    else if (!(fp = fopen(out, "w"))) fprintf(stderr, "rj check: cannot write %s: %s\n", out, strerror(errno));
    else {
        const int ok = fputs(text, fp) >= 0;
        if (fclose(fp) == 0 && ok) rc = 0;
        else fprintf(stderr, "rj check: writing %s failed\n", out);
    }
    for (k = 0; J && k < d.joint_count; k++) moved += J[k].angle0 != d.joints[k].angle0;
    if (rc == 0) fprintf(stderr, "rj check: %s: its loops closed (%d angle0 moved), written to %s\n", path, moved, out);
    free(text);
    free(J);
    rj_scene_file_free(&f);
    return rc;
}

static int cmd_check(int argc, char **argv)
{
    opts o;
    scene sc;
    cost c;
    opts_parse(&o, CMD_CHECK, argc, argv, usage_check);
    free((void *)o.probes);
    if (o.assemble) {
        if (check_assemble(o.scene, o.assemble) != 0) return 2;
        o.scene = o.assemble;
    }
    check_progress_start(o.progress);
    check_phase("loading %s and building its model (the step bound: Lanczos on the whole model)", o.scene);
    if (scene_open(&sc, o.scene, o.dt, o.sets, o.nsets, 0) != 0) {
        check_progress_stop();
        return 2;
    }
    cost_measure(&sc, &c);
    if (c.failed) printf("%s: not valid: it cannot be simulated: a step fails at t = %.6g s\n", o.scene, c.t_fail);
    else printf("%s: valid\n", o.scene);
    check_links(&sc);
    check_joints(&sc);
    check_loads(&sc);
    check_actuators(&sc);
    check_couplings(&sc);
    check_dt(&sc);
    check_binding(&sc);
    cost_print(&sc, &c);
    check_warnings(&sc);
    check_progress_stop();
    scene_close(&sc);
    if (!c.failed) return 0;
    fprintf(stderr, "rj check: %s cannot be simulated: %s\n", o.scene, c.msg);
    return 1;
}

/* ================================================================ rj plot */

/* The plots of one image: --what loads draws two, one above the other, since pin forces
   (N) and bending moments (N m) do not share a y axis; every other --what draws one. */
enum { PANEL_PINS = 0, PANEL_MOMENTS, NPANELS };
#define HIST_MAX (NPANELS * RJR_MAX_SERIES)

/* The history of rj plot: the series chosen by --what, sampled by the run. */
typedef struct history {
    int what, nseries;            /* series kept (at most RJR_MAX_SERIES a plot) */
    int ncand[NPANELS], kept[NPANELS]; /* each plot's series, all and kept */
    int idx[HIST_MAX];            /* the joint or link of each series */
    int latch[HIST_MAX];          /* torques: latch impulse / dt instead of the limit torque */
    int panel[HIST_MAX];          /* its plot: PANEL_MOMENTS for loads' moments, else 0 */
    char label[HIST_MAX][48];
    long n, cap;
    double *t, *y[HIST_MAX];
    double *pin;                  /* loads: every joint's pin force at the sample */
    int *flex;                    /* loads: the flexible links, whose peaks the run keeps */
} history;

/* A series of a plot: kept when that plot has room, counted either way. */
static void series_add(history *h, int panel, int idx, int latch, const char *label, const char *suffix)
{
    const int k = h->nseries;
    h->ncand[panel]++;
    if (h->kept[panel] == RJR_MAX_SERIES) return;
    h->idx[k] = idx;
    h->latch[k] = latch;
    h->panel[k] = panel;
    snprintf(h->label[k], sizeof h->label[0], "%s%s", label, suffix);
    h->kept[panel]++;
    h->nseries++;
}

/* Torques: every joint with a limit (every joint when none has one). */
static void series_torques(history *h, const scene *sc)
{
    const rj_model *m = sc->m;
    int j, any = 0;
    for (j = 0; j < rj_model_joint_count(m); j++) any |= rj_model_joint_def(m, j)->has_forward || rj_model_joint_def(m, j)->has_reverse;
    for (j = 0; j < rj_model_joint_count(m); j++) {
        const rj_joint_def *d = rj_model_joint_def(m, j);
        const int vel = d->method == RJ_METHOD_MOMENTUM || d->method == RJ_METHOD_FORCED || d->method == RJ_METHOD_ENERGY;
        if (any && !d->has_forward && !d->has_reverse) continue;
        series_add(h, 0, j, vel, joint_name(sc, j), vel ? " latch impulse/dt" : " limit torque");
    }
}

/* Whether a link has element loads: rigid and inextensible ones have none. */
static int link_flexible(const rj_model *m, int l)
{
    return rj_model_link_def(m, l)->fidelity == RJ_LINK_FLEXIBLE;
}

/* Loads: every joint's pin force; every flexible link's largest bending moment, labelled
   abs(M): the plot's font has no '|'. */
static void series_loads(history *h, const scene *sc)
{
    const rj_model *m = sc->m;
    int i;
    for (i = 0; i < rj_model_joint_count(m); i++) series_add(h, PANEL_PINS, i, 0, joint_name(sc, i), " pin force");
    for (i = 0; i < rj_model_link_count(m); i++)
        if (link_flexible(m, i)) series_add(h, PANEL_MOMENTS, i, 0, link_name(sc, i), " max abs(M)");
}

/* The series of each --what, in the file's order of joints and links. */
static void series_setup(history *h, const scene *sc, int what)
{
    static const char *const energies[] = { "kinetic", "strain", "spring", "balance" };
    const rj_model *m = sc->m;
    int i;
    memset(h, 0, sizeof *h);
    h->what = what;
    if (what == WHAT_ANGLES) for (i = 0; i < rj_model_joint_count(m); i++) series_add(h, 0, i, 0, joint_name(sc, i), "");
    if (what == WHAT_TORQUES) series_torques(h, sc);
    if (what == WHAT_TIPS) for (i = 0; i < rj_model_link_count(m); i++) series_add(h, 0, i, 0, link_name(sc, i), "");
    if (what == WHAT_ENERGY) for (i = 0; i < 4; i++) series_add(h, 0, i, 0, energies[i], "");
    if (what == WHAT_LOADS) series_loads(h, sc);
}

/* Series left out for want of room, said for each plot. */
static void series_note(const history *h)
{
    int k;
    for (k = 0; k < NPANELS; k++) {
        const char *what = h->what != WHAT_LOADS ? "" : k ? "bending moment " : "pin force ";
        if (h->ncand[k] > h->kept[k])
            fprintf(stderr, "rj plot: %d %sseries, more than a plot holds: plotting the first %d\n", h->ncand[k], what,
                    h->kept[k]);
    }
}

/* Loads' series k in state s: |pin force| from the sample's (NaN where there is none), or
   the link's largest |bending moment|; NaN before a step, where the library documents
   none (its rigid links' pass answers there: the weight alone, no acceleration yet). */
static double loads_value(const history *h, int k, const rj_model *m, const rj_state *s)
{
    const int i = h->idx[k];
    int at[2];
    double stress, mm;
    if (rj_state_steps(s) == 0) return NAN;
    if (h->panel[k] == PANEL_PINS) return hypot(h->pin[2 * i], h->pin[2 * i + 1]);
    mm = link_moment(m, s, i, at, &stress);
    return mm >= 0 ? mm : NAN;
}

/* Series k's value in state s. */
static double series_value(const history *h, int k, const rj_model *m, const rj_state *s)
{
    const int i = h->idx[k];
    rj_energy e;
    if (h->what == WHAT_ANGLES) return rj_deg(rj_joint_theta_running(m, s, i));
    if (h->what == WHAT_TORQUES && h->latch[k]) return rj_joint_latch_impulse(m, s, i) / rj_model_dt(m);
    if (h->what == WHAT_TORQUES) return rj_joint_torque(m, s, i, RJ_TORQUE_LIMIT);
    if (h->what == WHAT_TIPS) return scene_tip_defl_tangent(m, s, i);
    if (h->what == WHAT_LOADS) return loads_value(h, k, m, s);
    rj_state_energy(m, s, &e);
    return i == 0 ? e.kinetic : i == 1 ? e.strain : i == 2 ? e.spring : e.balance;
}

/* Room for one more sample: the arrays double. */
static int history_grow(history *h)
{
    const long cap = h->cap ? 2 * h->cap : 1024;
    double *t = (double *)realloc(h->t, sizeof(double) * (size_t)cap);
    int k;
    if (!t) return -1;
    h->t = t;
    for (k = 0; k < h->nseries; k++) {
        double *y = (double *)realloc(h->y[k], sizeof(double) * (size_t)cap);
        if (!y) return -1;
        h->y[k] = y;
    }
    h->cap = cap;
    return 0;
}

/* Appends a sample to every series; running out of memory stops the run. */
static int plot_sink_fn(runner *r, const rj_state *s)
{
    history *h = (history *)r->data;
    int k;
    if (h->n == h->cap && history_grow(h) != 0) {
        fprintf(stderr, "rj plot: out of memory for the history\n");
        r->stop = STOP_FAIL;
        return 1;
    }
    h->t[h->n] = rj_state_time(s);
    /* loads: the pin forces once for every joint's series */
    if (h->pin) pin_forces(r->sc->m, s, h->pin);
    for (k = 0; k < h->nseries; k++) h->y[k][h->n] = series_value(h, k, r->sc->m, s);
    h->n++;
    return 0;
}

/* Loads: the pin forces' buffer; the run keeps every flexible link's peak bending moment
   (the summary's line and the plot's marker), as rj run --loads does. 0, or -1. */
static int loads_setup(history *h, runner *r)
{
    const rj_model *m = r->sc->m;
    const int nl = rj_model_link_count(m);
    int l;
    h->pin = (double *)malloc(sizeof(double) * 2 * (size_t)(rj_model_joint_count(m) + 1));
    h->flex = (int *)malloc(sizeof(int) * (size_t)(nl + 1));
    r->peak = (double *)calloc(5 * (size_t)(nl + 1), sizeof(double));
    if (!h->pin || !h->flex || !r->peak) {
        fprintf(stderr, "rj plot: out of memory\n");
        return -1;
    }
    for (l = 0; l < nl; l++)
        if (link_flexible(m, l)) h->flex[r->npeak++] = l;
    r->peak_links = h->flex;
    return 0;
}

/* Frees the history's arrays. */
static void history_free(history *h)
{
    int k;
    free(h->t);
    for (k = 0; k < h->nseries; k++) free(h->y[k]);
    free(h->pin);
    free(h->flex);
}

/* A marker at x labelled "NAME what", when the plot has room; 1 when it has none. */
static int marker_add(rjr_plot_def *p, char (*labels)[48], double x, const char *name, const char *what)
{
    const int i = p->marker_count;
    if (i == RJR_MAX_MARKERS) return 1;
    snprintf(labels[i], 48, "%s %s", name, what);
    p->markers[i].x = x;
    p->markers[i].label = labels[i];
    p->marker_count++;
    return 0;
}

/* Locks and first contacts, labelled "NAME lock" / "NAME contact"; returns how many
   found no room (a plot has RJR_MAX_MARKERS). */
static int plot_markers(rjr_plot_def *p, const runner *r, char (*labels)[48])
{
    const rj_model *m = r->sc->m;
    int j, k, lost = 0;
    for (j = 0; j < rj_model_joint_count(m); j++) {
        const double first = rj_joint_event_time(m, r->s, j), lock = r->jl[j].lock_t;
        const double at[2] = { first != lock ? first : -1, lock };
        for (k = 0; k < 2; k++)
            if (at[k] >= 0) lost += marker_add(p, labels, at[k], joint_name(r->sc, j), k ? "lock" : "contact");
    }
    return lost;
}

/* Loads' series k: its peak over every step of the run (the summary's: a spike between
   two samples counts), its time in *t; -1 when none is known. */
static double series_peak(const history *h, int k, const runner *r, double *t)
{
    const int i = h->idx[k];
    int j;
    if (h->panel[k] == PANEL_PINS) {
        *t = r->jl[i].peak_pin_t;
        return r->jl[i].peak_pin;
    }
    for (j = 0; j < r->npeak; j++)
        if (r->peak_links[j] == i) {
            *t = r->peak[5 * j + 3];
            return r->peak[5 * j];
        }
    return -1;
}

/* Loads: the peak of each of the n drawn series, "NAME peak 8.74 N", after the events;
   those that find no room are said on standard error. */
static void peak_markers(rjr_plot_def *p, const history *h, const runner *r, const int *drawn, int n,
                         char (*labels)[48])
{
    int q, lost = 0;
    for (q = 0; q < n; q++) {
        const int k = drawn[q], pins = h->panel[k] == PANEL_PINS;
        const char *name = pins ? joint_name(r->sc, h->idx[k]) : link_name(r->sc, h->idx[k]);
        char what[40];
        double t;
        const double v = series_peak(h, k, r, &t);
        if (!(v > 0)) continue;
        snprintf(what, sizeof what, "peak %.4g %s", v, pins ? "N" : "N m");
        lost += marker_add(p, labels, t, name, what);
    }
    if (lost) fprintf(stderr, "rj plot: %d peaks more than the %d markers a plot has: not marked\n", lost,
                      RJR_MAX_MARKERS);
}

/* Whether series k has no number in the whole run: it is not drawn, and said. */
static int series_empty(const history *h, int k)
{
    static const char *const why[NPANELS] = { "rj_joint_pin_force has none for this joint",
                                              "rj_element_loads has none for this link" };
    long i;
    for (i = 0; i < h->n; i++)
        if (isfinite(h->y[k][i])) return 0;
    fprintf(stderr, "rj plot: %s: none in the whole run (%s): not plotted\n", h->label[k],
            h->what == WHAT_LOADS ? why[h->panel[k]] : "not a number in any sample");
    return 1;
}

/* One plot of the image: its series with a number, the run's span, the events and (loads)
   the peaks marked. Returns how many events found no room. */
static int plot_panel(const opts *o, const history *h, const runner *r, int panel, rjr_plot_def *p, char *title,
                      char (*labels)[48])
{
    /* one entry per --what, then loads' second plot */
    static const char *const ylabels[] = { "joint angle (deg)", "torque (N m)", "tip deflection (m)", "energy (J)",
                                           "pin force (N)", "max abs bending moment (N m)" };
    static const char *const titles[] = { "joint angles", "limit torques", "tip deflections", "energies",
                                          "pin forces", "largest bending moments" };
    int drawn[RJR_MAX_SERIES], k, n = 0, lost;
    *p = rjr_plot_default();
    snprintf(title, 160, "%s: %s", r->sc->f.title[0] ? r->sc->f.title : base_name(o->scene), titles[o->what + panel]);
    p->title = title;
    p->xlabel = "t (s)";
    p->ylabel = ylabels[o->what + panel];
    /* the axis spans the run, not the next round number past it */
    p->xmin = 0;
    p->xmax = h->t[h->n - 1];
    for (k = 0; k < h->nseries; k++) {
        if (h->panel[k] != panel || series_empty(h, k)) continue;
        drawn[n] = k;
        p->series[n].x = h->t;
        p->series[n].y = h->y[k];
        p->series[n].n = (int)h->n;
        p->series[n].label = h->label[k];
        p->series[n].colour = RJR_AUTO_COLOUR;
        n++;
    }
    p->series_count = n;
    lost = plot_markers(p, r, labels);
    if (h->what == WHAT_LOADS) peak_markers(p, h, r, drawn, n, labels);
    return lost;
}

/* Loads' two plots in one image, the pin forces above the moments on the same time axis
   (labelled under the lower one only). A plot without series is left out; with none in
   either the pin forces' is drawn, empty, as other --what draw theirs. */
static int plot_loads(rjr_context *ctx, rjr_plot_def *p)
{
    const int w = rjr_width(ctx), h = rjr_height(ctx);
    const int low = p[PANEL_MOMENTS].series_count > 0;
    const int up = p[PANEL_PINS].series_count > 0 || !low;
    const int split = up && low ? h / 2 : up ? h : 0;
    int rc = 0;
    if (up && low) p[PANEL_PINS].xlabel = NULL;
    if (rjr_begin(ctx, 0xffffff) != 0) return -1;
    if (up && rjr_plot_rect(ctx, &p[PANEL_PINS], 0, 0, w, split) != 0) rc = -1;
    if (low && rjr_plot_rect(ctx, &p[PANEL_MOMENTS], 0, split, w, h - split) != 0) rc = -1;
    if (rjr_end(ctx) != 0) return -1;
    return rc;
}

/* Draws and writes the plot (loads: its two); 0, or 1 after saying why. */
static int plot_write(const opts *o, const history *h, const runner *r)
{
    rjr_plot_def p[NPANELS];
    char title[NPANELS][160], err[256], labels[NPANELS][RJR_MAX_MARKERS][48];
    rjr_context *ctx;
    const int np = h->what == WHAT_LOADS ? NPANELS : 1;
    int k, rc, lost = 0;
    for (k = 0; k < np; k++) lost = plot_panel(o, h, r, k, &p[k], title[k], labels[k]);
    /* the same events in every plot: said once */
    if (lost) fprintf(stderr, "rj plot: %d more events than the %d markers a plot has: not marked\n", lost, RJR_MAX_MARKERS);
    err[0] = '\0';
    ctx = rjr_create(o->w, o->h, err, sizeof err);
    if (!ctx) {
        fprintf(stderr, "rj plot: %s\n", err);
        return 1;
    }
    rc = (h->what == WHAT_LOADS ? plot_loads(ctx, p) : rjr_plot(ctx, &p[PANEL_PINS])) ||
         rjr_save_png(ctx, o->out, err, sizeof err);
    if (rc) fprintf(stderr, "rj plot: cannot write %s: %s\n", o->out, err[0] ? err : rjr_error(ctx));
    rjr_destroy(ctx);
    return rc ? 1 : 0;
}

/* Whether path can be written, before a run: an existing file must be writable, else its
   directory must be. Prints "prog: cannot write PATH: reason" and returns -1 if not. */
static int out_writable(const char *prog, const char *path)
{
    struct stat st;
    char dir[4096];
    const char *slash = strrchr(path, '/');
    int e = 0;
    if (stat(path, &st) == 0) e = S_ISDIR(st.st_mode) ? EISDIR : access(path, W_OK) == 0 ? 0 : errno;
    else if (errno != ENOENT) e = errno;
    else if (!slash) e = access(".", W_OK | X_OK) == 0 ? 0 : errno;
    else if ((size_t)(slash - path) >= sizeof dir) e = ENAMETOOLONG;
    else {
        memcpy(dir, path, (size_t)(slash - path));
        dir[slash - path] = '\0';
        e = access(slash == path ? "/" : dir, W_OK | X_OK) == 0 ? 0 : errno;
    }
    if (!e) return 0;
    fprintf(stderr, "%s: cannot write %s: %s\n", prog, path, strerror(e));
    return -1;
}

/* ---- rj plot --what sweep: the rows of rj sweep, drawn */

/* Bins of a histogram at most: a joint's values take about the square root of their
   count, between these */
#define HIST_BINS_MIN 5
#define HIST_BINS_MAX 40
/* points of one histogram's outline: up and across each bin, down at the end */
#define HIST_POINTS (2 * HIST_BINS_MAX + 2)

/* The columns of a sweep's CSV that the plots read, by their place in its header, and
   the rows whose status is ok: for each drawn joint its lock and peak pin force, then the
   scatter's x and y, STUDY_STRIDE values a row. */
typedef struct study {
    const char *path;
    char *header;                    /* the header line, commas made NULs */
    char **col;                      /* its column names */
    int ncol;
    int nvary;                       /* columns 1..nvary: the varied keys */
    int njoint, ndrawn;              /* joints in the header, drawn (RJR_MAX_SERIES at most) */
    int lock_col[RJR_MAX_SERIES];    /* a drawn joint's J.lock; J.peak_pin_force follows it */
    char joint[RJR_MAX_SERIES][48];  /* its name */
    int x_col, y_col;                /* the scatter's columns */
    long nrow, nok, cap;             /* rows, ok rows, rows val has room for */
    double *val;
} study;
#define STUDY_STRIDE(st) (2 * (st)->ndrawn + 2)

/* Whether column name is J.suffix for the joint J of len characters at j. */
static int col_is(const char *name, const char *j, size_t len, const char *suffix)
{
    return !strncmp(name, j, len) && name[len] == '.' && !strcmp(name + len + 1, suffix);
}

/* The joints of the header: each a J.first_contact, J.lock, J.peak_pin_force triple, in
   the file's order; the varied keys are the columns before the first outcome. */
static void study_columns(study *st)
{
    int i, first_outcome = st->ncol - 2;
    for (i = 1; i + 2 < st->ncol - 2; i++) {
        const char *dot = strrchr(st->col[i], '.');
        const size_t len = dot ? (size_t)(dot - st->col[i]) : 0;
        if (!dot || strcmp(dot, ".first_contact") != 0) continue;
        if (!col_is(st->col[i + 1], st->col[i], len, "lock")) continue;
        if (!col_is(st->col[i + 2], st->col[i], len, "peak_pin_force")) continue;
        if (i < first_outcome) first_outcome = i;
        if (st->ndrawn < RJR_MAX_SERIES) {
            snprintf(st->joint[st->ndrawn], sizeof st->joint[0], "%.*s", (int)len, st->col[i]);
            st->lock_col[st->ndrawn++] = i + 1;
        }
        st->njoint++;
    }
    for (i = 1; i < first_outcome; i++)
        if (strlen(st->col[i]) > 12 && !strcmp(st->col[i] + strlen(st->col[i]) - 12, ".peak_moment")) break;
    st->nvary = i - 1;
}

/* The column --x or --y names: a header's name, or a varied key without its [unit];
   -1 after saying why not (the nearest name suggested). Status and message are text. */
static int study_find(const study *st, const char *opt, const char *name)
{
    const char *near;
    int i;
    for (i = 0; i < st->ncol - 2; i++) {
        const char *bracket = strchr(st->col[i], '[');
        const size_t len = bracket ? (size_t)(bracket - st->col[i]) : strlen(st->col[i]);
        if (!strcmp(st->col[i], name) || (bracket && strlen(name) == len && !strncmp(st->col[i], name, len)))
            return i;
    }
    near = cli_nearest(name, (const char *const *)st->col, st->ncol - 2);
    fprintf(stderr, "rj plot: option %s: %s has no number column '%s'", opt, st->path, name);
    if (near) fprintf(stderr, "; did you mean '%s'?", near);
    fprintf(stderr, " (a varied key, or an outcome such as %s.lock)\n", st->ndrawn ? st->joint[0] : "J");
    return -1;
}

/* The header: its columns, checked to be a sweep's (sample first, status and message
   last); the joints; the scatter's columns. 0, or 2 after saying why not. */
static int study_header(study *st, const opts *o)
{
    char *p = st->header;
    size_t n = strcspn(p, "\r\n");
    int i;
    p[n] = '\0';
    st->ncol = 1;
    for (i = 0; p[i]; i++) st->ncol += p[i] == ',';
    st->col = (char **)malloc(sizeof(char *) * (size_t)st->ncol);
    if (!st->col) {
        fprintf(stderr, "rj plot: out of memory\n");
        return 1;
    }
    for (i = 0; i < st->ncol; i++) {
        st->col[i] = p;
        p += strcspn(p, ",");
        if (*p) *p++ = '\0';
    }
    if (st->ncol < 4 || strcmp(st->col[0], "sample") || strcmp(st->col[st->ncol - 2], "status") ||
        strcmp(st->col[st->ncol - 1], "message")) {
        fprintf(stderr, "rj plot: option --csv: %s is not the rows of rj sweep (a header from 'sample' to "
                "'status,message')\n", st->path);
        return 2;
    }
    study_columns(st);
    if (st->njoint > st->ndrawn)
        fprintf(stderr, "rj plot: %d joints, more than a plot holds: plotting the first %d\n", st->njoint,
                st->ndrawn);
    st->x_col = o->x_col ? study_find(st, "--x", o->x_col) : st->nvary > 0 ? 1 : 0;
    st->y_col = o->y_col ? study_find(st, "--y", o->y_col) : st->ndrawn ? st->lock_col[0] : st->ncol - 3;
    return st->x_col < 0 || st->y_col < 0 ? 2 : 0;
}

/* A row's fields, in place: commas made NULs, a quoted field (the message) unquoted
   enough to count it as one. Returns how many, at most max (max + 1: more). */
static int csv_fields(char *line, char **field, int max)
{
    int n = 0;
    char *p = line;
    line[strcspn(line, "\r\n")] = '\0';
    for (;;) {
        if (n == max) return max + 1;
        field[n++] = p;
        if (*p == '"')
            for (p++; *p && !(p[0] == '"' && p[1] != '"'); p += p[0] == '"' ? 2 : 1) {}
        p += strcspn(p, ",");
        if (!*p) return n;
        *p++ = '\0';
    }
}

/* A field's number: empty (a sample that did not load) is NaN; anything else must read
   as a number to its end. 0, or -1. */
static int field_number(const char *f, double *v)
{
    char *end;
    if (!*f) {
        *v = NAN;
        return 0;
    }
    *v = strtod(f, &end);
    return *end ? -1 : 0;
}

/* One row (line lineno): an ok row's values appended, others counted. 0, or 2 after
   naming the line. */
static int study_row(study *st, char *line, char **field, long lineno)
{
    const int stride = STUDY_STRIDE(st);
    const int want[2] = { st->x_col, st->y_col };
    double *row;
    int n = csv_fields(line, field, st->ncol), j, bad = -1;
    if (n != st->ncol) {
        fprintf(stderr, "rj plot: %s:%ld: %d fields, the header has %d\n", st->path, lineno, n, st->ncol);
        return 2;
    }
    st->nrow++;
    if (strcmp(field[st->ncol - 2], "ok") != 0) return 0;
    if (st->nok == st->cap) {
        const long cap = st->cap ? 2 * st->cap : 1024;
        double *v = (double *)realloc(st->val, sizeof(double) * (size_t)(cap * stride));
        if (!v) {
            fprintf(stderr, "rj plot: out of memory for the rows of %s\n", st->path);
            return 1;
        }
        st->val = v;
        st->cap = cap;
    }
    row = st->val + st->nok * stride;
    for (j = 0; j < st->ndrawn && bad < 0; j++) {
        if (field_number(field[st->lock_col[j]], &row[2 * j]) != 0) bad = st->lock_col[j];
        if (field_number(field[st->lock_col[j] + 1], &row[2 * j + 1]) != 0) bad = st->lock_col[j] + 1;
    }
    for (j = 0; j < 2 && bad < 0; j++)
        if (field_number(field[want[j]], &row[2 * st->ndrawn + j]) != 0) bad = want[j];
    if (bad >= 0) {
        fprintf(stderr, "rj plot: %s:%ld: %s is '%s', not a number\n", st->path, lineno, st->col[bad], field[bad]);
        return 2;
    }
    st->nok++;
    return 0;
}

/* Reads the sweep's CSV: the header, then every row. 0, 1 (memory, a read error) or 2. */
static int study_read(study *st, const opts *o)
{
    FILE *f = fopen(o->csv, "r");
    char *line = NULL, **field = NULL;
    size_t cap = 0;
    long lineno = 1;
    int st_rc;
    memset(st, 0, sizeof *st);
    st->path = o->csv;
    if (!f) {
        fprintf(stderr, "rj plot: option --csv: cannot read %s: %s\n", o->csv, strerror(errno));
        return 2;
    }
    if (getline(&st->header, &cap, f) <= 0) {
        fprintf(stderr, "rj plot: option --csv: %s is empty, not the rows of rj sweep\n", o->csv);
        fclose(f);
        return 2;
    }
    cap = 0;
    st_rc = study_header(st, o);
    if (st_rc == 0) field = (char **)malloc(sizeof(char *) * (size_t)(st->ncol + 1));
    if (st_rc == 0 && !field) {
        fprintf(stderr, "rj plot: out of memory\n");
        st_rc = 1;
    }
    while (st_rc == 0 && getline(&line, &cap, f) > 0) st_rc = study_row(st, line, field, ++lineno);
    if (st_rc == 0 && ferror(f)) {
        fprintf(stderr, "rj plot: cannot read %s: %s\n", o->csv, strerror(errno));
        st_rc = 1;
    }
    free(line);
    free(field);
    fclose(f);
    return st_rc;
}

/* Frees what study_read made. */
static void study_free(study *st)
{
    free(st->header);
    free(st->col);
    free(st->val);
}

/* The plots' arrays: each histogram's outline, the bars, the scatter's points. */
typedef struct study_plots {
    double hist_x[2][RJR_MAX_SERIES][HIST_POINTS], hist_y[2][RJR_MAX_SERIES][HIST_POINTS];
    double bar_x[RJR_MAX_SERIES][4], bar_y[RJR_MAX_SERIES][4];
    double *px, *py;
    char label[3][RJR_MAX_SERIES][64];
    char title[4][160], xlabel[2][64];
    rjr_plot_def p[4];
} study_plots;

/* The top of a y axis from 0 whose data reach top, with room above for a legend of n
   rows in the top-right corner of a panel_h pixels high plot: the legend's height and the
   plot area's as rjr_plot_rect lays them out (its font from the panel's size). */
static double legend_clear_top(double top, int n, int panel_w, int panel_h)
{
    double f = floor((panel_w < panel_h ? panel_w : panel_h) * 0.03), fs, area, legend;
    f = f < 10 ? 10 : f > 16 ? 16 : f;
    fs = floor(f * 0.85 + 0.5);
    area = panel_h - 2 * floor(f * 0.8) - 2.2 * f - 9 - 1.5 * fs - 1.9 * f;
    legend = 8 + n * floor(fs * 1.8) + fs * 0.8 + 8;
    if (top <= 0) top = 1;
    return area > 2 * legend ? top * area / (area - legend) : 2 * top;
}

/* Histogram of the drawn joint j's values (which: 0 lock, 1 peak pin force) over the ok
   rows, as an outline: sqrt(n) bins over its own range. Returns its highest count; sets
   *none to the rows without a value (-1: never locked, no pin force). */
static int study_hist(const study *st, int which, int j, double *x, double *y, int *npts, int *none)
{
    const int stride = STUDY_STRIDE(st);
    int count[HIST_BINS_MAX], nb, b, top = 0;
    long r, n = 0;
    double lo = HUGE_VAL, hi = -HUGE_VAL, half;
    *none = 0;
    for (r = 0; r < st->nok; r++) {
        const double v = st->val[r * stride + 2 * j + which];
        if (!(v >= 0)) {
            (*none)++;
            continue;
        }
        lo = v < lo ? v : lo;
        hi = v > hi ? v : hi;
        n++;
    }
    *npts = 0;
    if (n == 0) return 0;
    /* a single value: one bin around it */
    half = fabs(lo) > 0 ? 0.005 * fabs(lo) : 0.5;
    if (hi == lo) {
        lo -= half;
        hi += half;
    }
    nb = (int)ceil(sqrt((double)n));
    nb = nb < HIST_BINS_MIN ? HIST_BINS_MIN : nb > HIST_BINS_MAX ? HIST_BINS_MAX : nb;
    memset(count, 0, sizeof count);
    for (r = 0; r < st->nok; r++) {
        const double v = st->val[r * stride + 2 * j + which];
        if (!(v >= 0)) continue;
        b = (int)((v - lo) / (hi - lo) * nb);
        count[b < nb ? b : nb - 1]++;
    }
    /* up from 0 at the first edge, across each bin at its count, down at the last edge */
    for (b = 0; b <= nb; b++) {
        x[2 * b] = x[2 * b + 1] = lo + (hi - lo) * b / nb;
        y[2 * b] = b == 0 ? 0 : count[b - 1];
        y[2 * b + 1] = b == nb ? 0 : count[b];
        top = b < nb && count[b] > top ? count[b] : top;
    }
    *npts = 2 * nb + 2;
    return top;
}

/* Panel which (0 lock times, 1 peak pin forces): each drawn joint's histogram, its
   legend saying how many ok rows had no value (never locked, no pin force). */
static void study_hist_panel(const study *st, study_plots *sp, int which, int pw, int ph)
{
    static const char *const what[2] = { "lock times", "peak pin forces" };
    static const char *const none_what[2] = { "never locked", "without a pin force" };
    rjr_plot_def *p = &sp->p[which];
    int j, top = 0, nonzero = 0;
    *p = rjr_plot_default();
    for (j = 0; j < st->ndrawn; j++) {
        rjr_series *s = &p->series[j];
        int npts, none;
        const int t = study_hist(st, which, j, sp->hist_x[which][j], sp->hist_y[which][j], &npts, &none);
        top = t > top ? t : top;
        nonzero += none > 0;
        if (none) snprintf(sp->label[which][j], 64, "%s: %d %s", st->joint[j], none, none_what[which]);
        else snprintf(sp->label[which][j], 64, "%s", st->joint[j]);
        s->x = sp->hist_x[which][j];
        s->y = sp->hist_y[which][j];
        s->n = npts;
        s->label = sp->label[which][j];
        s->colour = RJR_AUTO_COLOUR;
    }
    p->series_count = st->ndrawn;
    /* the title says when no joint lacks a value; the legend names those that do */
    snprintf(sp->title[which], sizeof sp->title[0], "%s, %ld samples%s", what[which], st->nok,
             nonzero || which ? "" : ", all locked");
    p->title = sp->title[which];
    p->xlabel = which ? "peak pin force (N)" : "lock time (s)";
    p->ylabel = "samples a bin";
    p->ymin = 0;
    p->ymax = legend_clear_top(top, st->ndrawn, pw, ph);
}

/* The scatter: --y against --x over the ok rows; an outcome's -1 (none) and empty
   numbers are not drawn, and counted in the title. 0, or 1 when memory ran out. */
static int study_scatter(const study *st, study_plots *sp)
{
    const int stride = STUDY_STRIDE(st), outcome_x = st->x_col > st->nvary, outcome_y = st->y_col > st->nvary;
    rjr_plot_def *p = &sp->p[2];
    long r, n = 0;
    sp->px = (double *)malloc(sizeof(double) * (size_t)(st->nok + 1));
    sp->py = (double *)malloc(sizeof(double) * (size_t)(st->nok + 1));
    if (!sp->px || !sp->py) return 1;
    for (r = 0; r < st->nok; r++) {
        const double x = st->val[r * stride + 2 * st->ndrawn], y = st->val[r * stride + 2 * st->ndrawn + 1];
        if (!isfinite(x) || !isfinite(y) || (outcome_x && x < 0) || (outcome_y && y < 0)) continue;
        sp->px[n] = x;
        sp->py[n] = y;
        n++;
    }
    *p = rjr_plot_default();
    p->series[0].x = sp->px;
    p->series[0].y = sp->py;
    p->series[0].n = (int)n;
    p->series[0].colour = RJR_AUTO_COLOUR;
    p->series[0].points = 1;
    p->series[0].no_line = 1;
    p->series_count = 1;
    p->legend = RJR_LEGEND_NONE;
    snprintf(sp->title[2], sizeof sp->title[0], "%s against %s", st->col[st->y_col], st->col[st->x_col]);
    if (n < st->nok)
        snprintf(sp->title[2] + strlen(sp->title[2]), sizeof sp->title[0] - strlen(sp->title[2]),
                 " (%ld without a value)", st->nok - n);
    p->title = sp->title[2];
    p->xlabel = st->col[st->x_col];
    p->ylabel = st->col[st->y_col];
    return 0;
}

/* The share of the ok rows in which each drawn joint latched: a bar each, at 1, 2, ...
   in the file's order, its colour and share in the legend. */
static void study_bars(const study *st, study_plots *sp, int pw, int ph)
{
    const int stride = STUDY_STRIDE(st);
    rjr_plot_def *p = &sp->p[3];
    int j;
    *p = rjr_plot_default();
    for (j = 0; j < st->ndrawn; j++) {
        long r, locked = 0;
        double share;
        for (r = 0; r < st->nok; r++) locked += st->val[r * stride + 2 * j] >= 0;
        share = st->nok ? 100.0 * (double)locked / (double)st->nok : 0.0;
        sp->bar_x[j][0] = sp->bar_x[j][1] = j + 1 - 0.3;
        sp->bar_x[j][2] = sp->bar_x[j][3] = j + 1 + 0.3;
        sp->bar_y[j][0] = sp->bar_y[j][3] = 0;
        sp->bar_y[j][1] = sp->bar_y[j][2] = share;
        snprintf(sp->label[2][j], 64, "%s: %.4g %% (%ld)", st->joint[j], share, locked);
        p->series[j].x = sp->bar_x[j];
        p->series[j].y = sp->bar_y[j];
        p->series[j].n = 4;
        p->series[j].label = sp->label[2][j];
        p->series[j].colour = RJR_AUTO_COLOUR;
        p->series[j].width_px = 3;
    }
    p->series_count = st->ndrawn;
    snprintf(sp->title[3], sizeof sp->title[0], "latched, %ld ok samples", st->nok);
    if (st->nrow > st->nok)
        snprintf(sp->title[3] + strlen(sp->title[3]), sizeof sp->title[0] - strlen(sp->title[3]),
                 " (%ld not ok)", st->nrow - st->nok);
    p->title = sp->title[3];
    p->xlabel = "joint, in the file's order";
    p->ylabel = "samples latched (%)";
    p->xmin = 0.5;
    p->xmax = st->ndrawn + 0.5;
    p->ymin = 0;
    p->ymax = legend_clear_top(100, st->ndrawn, pw, ph);
}

/* The four plots in a 2 x 2 image: lock times, peak pin forces; the scatter, the
   latched shares. 0, or 1 after saying why not. */
static int study_draw(const opts *o, const study *st, study_plots *sp)
{
    const int pw = o->w / 2, ph = o->h / 2;
    rjr_context *ctx;
    char err[256];
    int k, rc = 0;
    study_hist_panel(st, sp, 0, pw, ph);
    study_hist_panel(st, sp, 1, pw, ph);
    if (study_scatter(st, sp) != 0) {
        fprintf(stderr, "rj plot: out of memory\n");
        return 1;
    }
    study_bars(st, sp, pw, ph);
    err[0] = '\0';
    ctx = rjr_create(o->w, o->h, err, sizeof err);
    if (!ctx) {
        fprintf(stderr, "rj plot: %s\n", err);
        return 1;
    }
    if (rjr_begin(ctx, 0xffffff) != 0) rc = -1;
    for (k = 0; k < 4 && rc == 0; k++)
        if (rjr_plot_rect(ctx, &sp->p[k], (k % 2) * pw, (k / 2) * ph, k % 2 ? o->w - pw : pw,
                          k / 2 ? o->h - ph : ph) != 0)
            rc = -1;
    if (rjr_end(ctx) != 0) rc = -1;
    if (rc == 0) rc = rjr_save_png(ctx, o->out, err, sizeof err);
    if (rc) fprintf(stderr, "rj plot: cannot write %s: %s\n", o->out, err[0] ? err : rjr_error(ctx));
    rjr_destroy(ctx);
    return rc ? 1 : 0;
}

/* rj plot --what sweep: the output checked, the rows read, the four plots drawn. */
static int plot_sweep(const opts *o)
{
    study st;
    study_plots *sp;
    int rc;
    if (cli_mkparent("rj plot", o->out) != 0 || out_writable("rj plot", o->out) != 0) return 2;
    rc = study_read(&st, o);
    sp = rc == 0 ? (study_plots *)calloc(1, sizeof *sp) : NULL;
    if (rc == 0 && !sp) {
        fprintf(stderr, "rj plot: out of memory\n");
        rc = 1;
    }
    if (rc == 0) rc = study_draw(o, &st, sp);
    if (rc == 0)
        fprintf(stderr, "rj plot: %s: %ld rows, %ld ok, %d joints drawn\n", o->csv, st.nrow, st.nok, st.ndrawn);
    if (sp) {
        free(sp->px);
        free(sp->py);
    }
    free(sp);
    study_free(&st);
    return rc;
}

/* rj plot: checks the output can be written before the run, draws after it. */
static int cmd_plot(int argc, char **argv)
{
    opts o;
    scene sc;
    runner r;
    history h;
    rj_result res;
    int st;
    opts_parse(&o, CMD_PLOT, argc, argv, usage_plot);
    free((void *)o.probes);
    if (o.what == WHAT_SWEEP) {
        st = plot_sweep(&o);
        free(o.varies);
        free((void *)o.sets);
        return st;
    }
    if (scene_open(&sc, o.scene, o.dt, o.sets, o.nsets, o.what == WHAT_LOADS) != 0) return 2;
    cli_check_steps("rj plot", o.t_end, rj_model_dt(sc.m), o.force);
    if (cli_mkparent("rj plot", o.out) != 0 || out_writable("rj plot", o.out) != 0) return 2;
    model_warnings(&sc, "rj plot");
    series_setup(&h, &sc, o.what);
    series_note(&h);
    if (runner_init(&r, &sc, "rj plot", o.t_end, fmax(1e-3, o.t_end / PLOT_SAMPLES), o.progress) != 0) return 1;
    if (o.what == WHAT_LOADS && loads_setup(&h, &r) != 0) return 1;
    r.sink = plot_sink_fn;
    r.data = &h;
    res = runner_go(&r);
    runner_summary(&r, res);
    st = res != RJ_OK || r.stop ? 1 : 0;
    if (r.stop != STOP_FAIL && h.n > 0 && plot_write(&o, &h, &r) != 0) st = 1;
    history_free(&h);
    runner_free(&r);
    scene_close(&sc);
    return st;
}

/* ================================================================ rj animate */

/* The frames sink of rj animate. */
typedef struct frames {
    rjr_context *ctx;
    rjr_view view;
    const char *dir;
    int frame;
    const char **names;   /* the joints' names for the labels (malloc'd) */
} frames;

/* One frame per sample; a frame that cannot be written stops the run. */
static int frame_sink_fn(runner *r, const rj_state *s)
{
    frames *f = (frames *)r->data;
    char path[4200], err[256];
    err[0] = '\0';
    if (cli_frame_path("rj animate", path, sizeof path, f->dir, f->frame) != 0) {
        r->stop = STOP_FAIL;
        return 1;
    }
    if (rjr_draw_state(f->ctx, r->sc->m, s, &f->view) || rjr_save_png(f->ctx, path, err, sizeof err)) {
        /* the PNG writer's text has the system's reason; a drawing error is the context's */
        progress_clear(r);
        fprintf(stderr, "rj animate: cannot write %s: %s\n", path, err[0] ? err : rjr_error(f->ctx));
        r->stop = STOP_FAIL;
        return 1;
    }
    f->frame++;
    return 0;
}

/* The view, fixed once on the whole motion: a pass over t_end in 50 pieces, the box of
   every piece's end (as build/animate, so that the frames are the same). A piece shorter
   than half a step would not step at all: one step is taken then. */
static void view_fit(const scene *sc, double t_end, int w, int h, rjr_view *v)
{
    const rj_model *m = sc->m;
    rj_state *s;
    double box[4];
    if (rj_state_create(m, &s, NULL) != RJ_OK) return;
    rjr_bbox_init(box);
    rjr_bbox_add(box, m, s);
    while (rj_state_time(s) < t_end) {
        const double t0 = rj_state_time(s);
        if (rj_run(m, s, t0 + t_end / 50, 0, NULL, NULL) != RJ_OK) break;
        if (rj_state_time(s) == t0 && rj_step(m, s) != RJ_OK) break;
        rjr_bbox_add(box, m, s);
    }
    rj_state_destroy(s, NULL);
    rjr_view_fit_box(v, box, w, h, 20);
}

/* Quotes a word for a POSIX shell when it needs it. */
static void shell_word(const char *w)
{
    const char *p;
    if (*w && strspn(w, "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_./%=:,+-") == strlen(w)) {
        fputs(w, stderr);
        return;
    }
    fputc('\'', stderr);
    for (p = w; *p; p++) {
        if (*p == '\'') fputs("'\\''", stderr);
        else fputc(*p, stderr);
    }
    fputc('\'', stderr);
}

/* Whether an executable named name is on PATH. */
static int on_path(const char *name)
{
    const char *p = getenv("PATH");
    char buf[4200];
    while (p && *p) {
        const size_t n = strcspn(p, ":");
        const int len = snprintf(buf, sizeof buf, "%.*s/%s", (int)n, n ? p : ".", name);
        if (len > 0 && (size_t)len < sizeof buf && access(buf, X_OK) == 0) return 1;
        p += n + (p[n] == ':');
    }
    return 0;
}

/* Runs argv (a NULL-terminated list) and waits; 0 when it exits with status 0. */
static int spawn(char **argv)
{
    int status;
    const pid_t pid = fork();
    if (pid < 0) return -1;
    if (pid == 0) {
        execvp(argv[0], argv);
        _exit(127);
    }
    if (waitpid(pid, &status, 0) != pid) return -1;
    return WIFEXITED(status) && WEXITSTATUS(status) == 0 ? 0 : -1;
}

/* The video: ffmpeg when it is on PATH, else the command to run. Odd sizes are padded by
   a pixel: yuv420p, which players expect, needs even ones. */
static int mp4_write(const opts *o)
{
    char fps[32], pattern[4200];
    char *av[16];
    int n = 0, k;
    snprintf(fps, sizeof fps, "%g", o->fps);
    snprintf(pattern, sizeof pattern, "%s/frame_%%05d.png", o->out);
    av[n++] = (char *)"ffmpeg";
    av[n++] = (char *)"-y";
    av[n++] = (char *)"-loglevel";
    av[n++] = (char *)"error";
    av[n++] = (char *)"-framerate";
    av[n++] = fps;
    av[n++] = (char *)"-i";
    av[n++] = pattern;
    if (o->w % 2 || o->h % 2) {
        av[n++] = (char *)"-vf";
        av[n++] = (char *)"pad=ceil(iw/2)*2:ceil(ih/2)*2";
    }
    av[n++] = (char *)"-pix_fmt";
    av[n++] = (char *)"yuv420p";
    av[n++] = (char *)o->mp4;
    av[n] = NULL;
    fputs(on_path("ffmpeg") ? "rj animate: running " : "rj animate: ffmpeg is not on PATH; to make the video, run\n  ", stderr);
    for (k = 0; k < n; k++) {
        if (k) fputc(' ', stderr);
        shell_word(av[k]);
    }
    fputc('\n', stderr);
    if (!on_path("ffmpeg")) return 0;
    if (spawn(av) == 0) return 0;
    fprintf(stderr, "rj animate: ffmpeg failed: %s not written\n", o->mp4);
    return 1;
}

/* Frames a person reads without the source: a key to the joint colours, each joint's
   name and angle beside it, the time and caption in a band of their own above the links,
   stowed links drawn side by side. */
static int frames_readable(const scene *sc, frames *f)
{
    const int nj = rj_model_joint_count(sc->m);
    int j;
    f->names = (const char **)malloc(sizeof *f->names * (size_t)(nj + 1));
    if (!f->names) {
        fprintf(stderr, "rj animate: out of memory\n");
        return 1;
    }
    for (j = 0; j < nj; j++) f->names[j] = sc->f.joint_names[j];
    f->view.show_legend = 1;
    f->view.joint_names = f->names;
    f->view.show_joint_angles = 1;
    f->view.text_band = 1;
    f->view.separate_stacked = 1;
    return 0;
}

/* The frames directory, the view and the context, before the run. 2 when the directory
   cannot be made, 1 when the renderer cannot start. */
static int frames_setup(const opts *o, const scene *sc, frames *f)
{
    char err[256];
    memset(f, 0, sizeof *f);
    f->view = rjr_view_default();
    f->dir = o->out;
    view_fit(sc, o->t_end, o->w, o->h, &f->view);
    /* build/animate draws scene files twice their thickness */
    f->view.thickness_factor = 2;
    f->view.caption = sc->f.title[0] ? sc->f.title : base_name(sc->path);
    if (!o->plain && frames_readable(sc, f) != 0) return 1;
    if (cli_frames_dir("rj animate", o->out) != 0) return 2;
    err[0] = '\0';
    f->ctx = rjr_create(o->w, o->h, err, sizeof err);
    if (f->ctx) return 0;
    fprintf(stderr, "rj animate: %s\n", err);
    return 1;
}

/* Refuses runs that would not end: steps, and frames (one per 1/fps, at most one a step). */
static void animate_bounds(const opts *o, const scene *sc)
{
    const double dt = rj_model_dt(sc->m);
    cli_check_steps("rj animate", o->t_end, dt, o->force);
    cli_check_frames("rj animate", o->t_end * (o->fps < 1.0 / dt ? o->fps : 1.0 / dt) + 1, o->force);
}

/* rj animate: bounds, outputs and view first, then the frames, then the video. */
static int cmd_animate(int argc, char **argv)
{
    opts o;
    scene sc;
    runner r;
    frames f;
    rj_result res;
    int st;
    opts_parse(&o, CMD_ANIMATE, argc, argv, usage_animate);
    free((void *)o.probes);
    if (scene_open(&sc, o.scene, o.dt, o.sets, o.nsets, 0) != 0) return 2;
    animate_bounds(&o, &sc);
    if (o.mp4 && (cli_mkparent("rj animate", o.mp4) != 0 || out_writable("rj animate", o.mp4) != 0)) return 2;
    model_warnings(&sc, "rj animate");
    st = frames_setup(&o, &sc, &f);
    if (st) return st;
    if (runner_init(&r, &sc, "rj animate", o.t_end, 1.0 / o.fps, o.progress) != 0) return 1;
    r.sink = frame_sink_fn;
    r.data = &f;
    res = runner_go(&r);
    runner_summary(&r, res);
    st = res != RJ_OK || r.stop ? 1 : 0;
    if (!st) fprintf(stderr, "rj animate: wrote %d frames %s/frame_%%05d.png (%dx%d)\n", f.frame, o.out, o.w, o.h);
    if (!st && o.mp4) st = mp4_write(&o);
    rjr_destroy(f.ctx);
    free(f.names);
    runner_free(&r);
    scene_close(&sc);
    return st;
}

/* ================================================================ rj sweep */

/* splitmix64's step: a well-mixed 64-bit value of x, for the samples' values. */
static unsigned long long mix64(unsigned long long x)
{
    unsigned long long z = x + 0x9E3779B97F4A7C15ULL;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
}

/* splitmix64's increment: a stream's values are mix64(start + i * SPLITMIX_GAMMA) */
#define SPLITMIX_GAMMA 0x9E3779B97F4A7C15ULL
/* --lhs: what the permutations' streams start from besides the seed, so that they are
   not the draws' */
#define LHS_SALT 0x4C48535045524DULL

/* The 64 bits sample k's draw of the v-th --vary starts from: from (seed, k, v) alone
   (the first release's, so that its uniform samples keep their values). */
static unsigned long long draw_bits(unsigned long long seed, int k, int v)
{
    return mix64(mix64(mix64(seed) ^ (unsigned long long)k) ^ (unsigned long long)v);
}

/* The top 53 bits as a uniform in [0, 1) (half_open) or in (0, 1), the centre of each
   of the 2^53 cells: a normal's quantile is finite there. */
static double draw_unit(unsigned long long h, int half_open)
{
    return ((double)(h >> 11) + (half_open ? 0.0 : 0.5)) / 9007199254740992.0;
}

/* The standard normal's quantile x = Phi^-1(p), for p in (0, 0.5]: Acklam's rational
   approximation (relative error below 1.2e-9), then one step of Halley's method on
   Phi(x) - p = 0, Phi from erfc, which leaves about the double's own precision. */
static double normal_lower_quantile(double p)
{
    static const double a[6] = { -3.969683028665376e+01, 2.209460984245205e+02, -2.759285104469687e+02,
                                 1.383577518672690e+02,  -3.066479806614716e+01, 2.506628277459239e+00 };
    static const double b[5] = { -5.447609879822406e+01, 1.615858368580409e+02, -1.556989798598866e+02,
                                 6.680131188771972e+01,  -1.328068155288572e+01 };
    static const double c[6] = { -7.784894002430293e-03, -3.223964580411365e-01, -2.400758277161838e+00,
                                 -2.549732539343734e+00, 4.374664141464968e+00,  2.938163982698783e+00 };
    static const double d[4] = { 7.784695709041462e-03, 3.224671290700398e-01, 2.445134137142996e+00,
                                 3.754408661907416e+00 };
    double x, q, r, err, u;
    if (p < 0.02425) {
        /* the tail: a rational function of sqrt(-2 log p) */
        q = sqrt(-2 * log(p));
        x = (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
            ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1);
    } else {
        /* the centre: a rational function of (p - 1/2)^2, times p - 1/2 */
        q = p - 0.5;
        r = q * q;
        x = (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
            (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1);
    }
    /* Halley: err = Phi(x) - p, u = err / phi(x); x <= 0, so erfc's argument is >= 0
       and Phi(x) keeps its relative precision in the tail */
    err = 0.5 * erfc(-x / sqrt(2.0)) - p;
    u = err * sqrt(RJ_TWO_PI) * exp(0.5 * x * x);
    return x - u / (1 + 0.5 * x * u);
}

/* Phi^-1(p) for p in (0, 1): the upper half by symmetry, from 1 - p, which is exact for
   p >= 1/2, so that both tails are as precise. */
static double normal_quantile(double p)
{
    return p > 0.5 ? -normal_lower_quantile(1 - p) : normal_lower_quantile(p);
}

/* A --vary's value at the uniform u: in [lo, hi] (u in [0, 1)), or the normal's
   quantile (u in (0, 1)). */
static double vary_at(const vary *va, double u)
{
    double x;
    if (va->dist == DIST_NORMAL) return va->mean + va->sd * normal_quantile(u);
    x = va->lo + (va->hi - va->lo) * u;
    return x > va->hi ? va->hi : x; /* rounding may pass hi by an ulp */
}

/* --lhs: the strata of the v-th --vary, a permutation of 0..n-1 that depends only on
   (seed, v, n): Fisher-Yates, its choices from a splitmix64 stream that starts from the
   seed and v. (The modulo's bias, n / 2^64, is far below anything a study sees.) */
static void lhs_perm(int *perm, int n, unsigned long long seed, int v)
{
    const unsigned long long start = mix64(mix64(seed ^ LHS_SALT) ^ (unsigned long long)v);
    int i;
    for (i = 0; i < n; i++) perm[i] = i;
    for (i = n - 1; i > 0; i--) {
        const unsigned long long h = mix64(start + (unsigned long long)i * SPLITMIX_GAMMA);
        const int j = (int)(h % (unsigned long long)(i + 1));
        const int t = perm[i];
        perm[i] = perm[j];
        perm[j] = t;
    }
}

/* --grid K: the v-th key's point in sample k, the first --vary the slowest digit of k in
   base K (rows run as nested loops in the --vary's order); its value: LO, HI and K - 2
   points evenly between (K = 1: the midpoint). */
static double grid_value(const vary *va, int grid, int nvary, int k, int v)
{
    int i;
    char text[32];
    double x;
    for (i = nvary - 1; i > v; i--) k /= grid;
    k %= grid;
    if (grid > 1 && k == 0) return va->lo;
    if (grid > 1 && k == grid - 1) return va->hi;
    x = grid == 1 ? 0.5 * va->lo + 0.5 * va->hi : va->lo + (va->hi - va->lo) * k / (grid - 1);
    /* between the ends, the value to 15 significant digits (which a double holds as
       written): 0.01:0.03 in 3 points is 0.01, 0.02, 0.03, not 0.019999999999999997 */
    snprintf(text, sizeof text, "%.15g", x);
    x = strtod(text, NULL);
    return x < va->lo ? va->lo : x > va->hi ? va->hi : x;
}

/* A result's short name for the status column: the enum's, RJ_ERR_ dropped. */
static const char *result_name(rj_result r)
{
    static const char *const names[] = { "ok", "invalid", "nomem", "unstable_dt", "blowup", "tunnel",
                                         "checkpoint", "parse", "not_converged" };
    return (int)r >= 0 && (int)r < NCOLS(names) ? names[r] : "error";
}

/* Rows done but not yet written, per thread: a slow sample holds the rows after it back
   until it is done, and the ring of those rows bounds the memory they take. */
#define SWEEP_RING_PER_THREAD 4

struct sweep;
/* One thread's own: the changes its sample loads with, the values, and the row, written
   into memory (open_memstream) and handed to the writer. Threads share only the sweep's
   read-only parts and, under its lock, the ring; each sample builds its own model. */
typedef struct worker {
    struct sweep *w;
    const char **sets; /* --set's changes, then one "KEY=VALUE" per --vary */
    char **text;       /* the --vary changes' texts (sets' last nvary) */
    double *x;         /* the sample's values */
    cli_out row;       /* the row being written, in memory */
    pthread_t th;
} worker;

/* A row done, waiting for its turn: its text (NULL: there was no memory for it). */
typedef struct pending {
    char *text;
    size_t len;
    int ready;
} pending;

/* The whole sweep: the options, the scene at the file's values (names, flexible links),
   the header, the threads, and the output with the ring of rows waiting for it. A row
   goes out in the samples' order, whichever thread finishes it. */
typedef struct sweep {
    const opts *o;
    const scene *sc;
    int *flex, nflex;      /* the flexible links (file order) */
    char *header;          /* the header line, newline included */
    size_t header_len;
    unsigned char *have;   /* --resume: have[k] when the file holds sample k (NULL: none) */
    int **perm;            /* --lhs: each --vary's strata, perm[v][k] sample k's (NULL: none) */
    worker *wk;            /* o->threads of them */
    cli_out out;
    pthread_mutex_t lock;  /* guards the rest */
    pthread_cond_t ready;  /* a row is ready (the writer waits) */
    pthread_cond_t room;   /* the ring has room, or the sweep stops (the threads wait) */
    pending *ring;         /* place p's row at ring[p % nring] */
    int nring;
    int next_k;            /* the next sample to hand out (-1: none left) */
    int handed, written;   /* places in the run's order: handed to a thread, written */
    int todo, done, bad;   /* samples to run, run, not ok */
    int held;              /* --resume: the samples the file holds */
    int stop;              /* the output failed: hand out no more */
} sweep;

/* Sample k's value of the v-th --vary, from the seed, k and v alone (with --lhs also
   the permutations of --samples N strata; with --grid its point), so that a sample is
   the same in every sweep of that design and seed, sharded or not. A normal is drawn by
   its quantile at a uniform, the same transform as its strata under --lhs. */
static double sweep_value(const sweep *w, int k, int v)
{
    const opts *o = w->o;
    const vary *va = &o->varies[v];
    const unsigned long long h = draw_bits(o->seed, k, v);
    if (o->design == DESIGN_GRID) return grid_value(va, o->grid, o->nvary, k, v);
    /* stratum perm[v][k] of N, and a place inside it: never on a stratum's edge */
    if (o->design == DESIGN_LHS) return vary_at(va, (w->perm[v][k] + draw_unit(h, 0)) / o->samples);
    return vary_at(va, draw_unit(h, va->dist == DIST_UNIFORM));
}

/* The --set change of the v-th --vary at value x: "KEY=x", or "KEY=x UNIT" as the file
   writes an angle in degrees. buf holds the longest key and 40 characters more. */
static void vary_change(char *buf, const vary *va, double x)
{
    sprintf(buf, "%.*s=%.17g%s%s", va->keylen, va->spec, x, va->unit[0] ? " " : "", va->unit);
}

/* Per sample: each joint's lock time, seen step by step as rj run's summary sees it. */
typedef struct locks {
    int *flag;     /* after the latest step */
    double *t;     /* s, -1: not locked */
    double t_prev; /* s, time of the state before the latest step */
} locks;

/* rj_run's callback at every step: a joint that turned RJ_LOCKED in this step locked at
   the time of the state the step started from (rj run's summary, rj_joint_event_time). */
static int locks_step(const rj_model *m, const rj_state *s, void *u)
{
    locks *lk = (locks *)u;
    int j;
    for (j = 0; j < rj_model_joint_count(m); j++) {
        const int f = rj_joint_flag(m, s, j);
        if (rj_state_steps(s) > 0 && f == RJ_LOCKED && lk->flag[j] != RJ_LOCKED && lk->t[j] < 0)
            lk->t[j] = lk->t_prev;
        lk->flag[j] = f;
    }
    lk->t_prev = rj_state_time(s);
    return 0;
}

/* A CSV field in quotes, quotes doubled; a line break (none expected) becomes a blank so
   that a row stays one line. */
static void csv_quoted(cli_out *o, const char *t)
{
    cli_put(o, fputc('"', o->f));
    for (; *t; t++) {
        if (*t == '"') cli_put(o, fputc('"', o->f));
        cli_put(o, fputc(*t == '\n' || *t == '\r' ? ' ' : *t, o->f));
    }
    cli_put(o, fputs("\"\n", o->f));
}

/* The header: sample, the varied keys, each joint's and flexible link's columns. */
static void sweep_header(const sweep *w, cli_out *out)
{
    const scene *sc = w->sc;
    int i;
    cli_put(out, fputs("sample", out->f));
    for (i = 0; i < w->o->nvary; i++) {
        const vary *v = &w->o->varies[i];
        /* a unit given names the column's: KEY[deg] */
        cli_put(out, fprintf(out->f, ",%.*s%s%s%s", v->keylen, v->spec, v->unit[0] ? "[" : "", v->unit,
                             v->unit[0] ? "]" : ""));
    }
    for (i = 0; i < rj_model_joint_count(sc->m); i++)
        cli_put(out, fprintf(out->f, ",%s.first_contact,%s.lock,%s.peak_pin_force", joint_name(sc, i),
                             joint_name(sc, i), joint_name(sc, i)));
    for (i = 0; i < w->nflex; i++) cli_put(out, fprintf(out->f, ",%s.peak_moment", link_name(sc, w->flex[i])));
    cli_put(out, fputs(",status,message\n", out->f));
}

/* The header's text, once: written to the output, and compared with the file's by
   --resume. Returns 0, or -1 when memory ran out. */
static int sweep_header_text(sweep *w)
{
    cli_out o;
    o.name = "memory";
    o.err = 0;
    o.f = open_memstream(&w->header, &w->header_len);
    if (!o.f) return -1;
    sweep_header(w, &o);
    return fclose(o.f) != 0 || o.err ? -1 : 0;
}

/* The row's start: the index and the values, as loaded (%.17g round-trips). */
static void sweep_row_start(worker *h, int k)
{
    int i;
    cli_put(&h->row, fprintf(h->row.f, "%d", k));
    for (i = 0; i < h->w->o->nvary; i++) cli_put(&h->row, fprintf(h->row.f, ",%.17g", h->x[i]));
}

/* A sample whose scene did not load or build: its numbers empty, the result and message. */
static void sweep_row_failed(worker *h, int k, rj_result res, const char *msg)
{
    int i;
    const int n = 3 * rj_model_joint_count(h->w->sc->m) + h->w->nflex;
    sweep_row_start(h, k);
    for (i = 0; i < n; i++) cli_put(&h->row, fputc(',', h->row.f));
    cli_put(&h->row, fprintf(h->row.f, ",%s,", result_name(res)));
    csv_quoted(&h->row, msg);
}

/* A run's row: per joint first contact, lock, peak |pin force|; per flexible link its
   peak |bending moment|; the run's result. */
static void sweep_row(worker *h, int k, const rj_model *m, const rj_state *s, const locks *lk, rj_result res)
{
    int j;
    sweep_row_start(h, k);
    for (j = 0; j < rj_model_joint_count(m); j++)
        cli_put(&h->row, fprintf(h->row.f, ",%.10g,%.10g,%.10g", rj_joint_event_time(m, s, j), lk->t[j],
                                 rj_joint_peak_pin_force(m, s, j).value));
    for (j = 0; j < h->w->nflex; j++)
        cli_put(&h->row, fprintf(h->row.f, ",%.10g", rj_link_peak_moment(m, s, h->w->flex[j]).value));
    cli_put(&h->row, fprintf(h->row.f, ",%s,", result_name(res)));
    csv_quoted(&h->row, res == RJ_OK ? "" : rj_state_error(s));
}

/* Runs a built model to --t-end with peaks tracked and the locks seen at every step.
   Returns the run's result. */
static rj_result sweep_run(worker *h, int k, const rj_model *m)
{
    const int nj = rj_model_joint_count(m);
    rj_state *s = NULL;
    rj_result res = RJ_ERR_NOMEM;
    locks lk;
    int j;
    lk.flag = (int *)malloc(sizeof(int) * (size_t)(nj + 1));
    lk.t = (double *)malloc(sizeof(double) * (size_t)(nj + 1));
    if (!lk.flag || !lk.t || rj_state_create(m, &s, NULL) != RJ_OK) {
        sweep_row_failed(h, k, RJ_ERR_NOMEM, "out of memory");
    } else {
        for (j = 0; j < nj; j++) {
            lk.flag[j] = rj_joint_flag(m, s, j);
            lk.t[j] = -1;
        }
        lk.t_prev = 0;
        /* the model is built without in-place stepping (sweep_sample): tracking works */
        res = rj_state_track_peaks(m, s, 1);
        /* a callback at every step makes rj_run take the energy accounts, and so the
           peaks, at every step, as rj run's */
        if (res == RJ_OK) res = rj_run(m, s, h->w->o->t_end, 0, locks_step, &lk);
        sweep_row(h, k, m, s, &lk, res);
    }
    if (s) rj_state_destroy(s, NULL);
    free(lk.flag);
    free(lk.t);
    return res;
}

/* Sample k: its values into the --vary changes, the scene loaded with them and built,
   then run; a failure at any stage is the row's status and message. Returns 1 when the
   sample is not ok. */
static int sweep_sample(worker *h, int k)
{
    const opts *o = h->w->o;
    rj_scene_file f;
    rj_scene_def d;
    rj_model *m = NULL;
    rj_error e;
    rj_result res;
    int i;
    for (i = 0; i < o->nvary; i++) {
        h->x[i] = sweep_value(h->w, k, i);
        vary_change(h->text[i], &o->varies[i], h->x[i]);
    }
    if (rj_scene_load_set(o->scene, h->sets, o->nsets + o->nvary, &f, &e) != RJ_OK) {
        sweep_row_failed(h, k, e.code, e.msg);
        return 1;
    }
    if (o->dt >= 0) f.solver.dt = o->dt;
    /* the links' peaks need the element loads at t^n, which in-place stepping does not
       keep; the results are the same bits either way (rj_solver_def) */
    f.solver.in_place = RJ_IN_PLACE_OFF;
    d = rj_scene_file_def(&f);
    res = rj_model_create(&d, &m, &e, NULL);
    if (res != RJ_OK) {
        rj_scene_file_locate(&f, &e);
        sweep_row_failed(h, k, e.code, e.msg);
    } else {
        res = sweep_run(h, k, m);
        rj_model_destroy(m, NULL);
    }
    rj_scene_file_free(&f);
    return res != RJ_OK;
}

/* Sample k run into a row in memory: p's text, NULL when memory ran out (the writer
   then fails the output). Returns 1 when the sample is not ok. */
static int sweep_sample_row(worker *h, int k, pending *p)
{
    int bad;
    p->text = NULL;
    p->len = 0;
    p->ready = 1;
    h->row.name = "memory";
    h->row.err = 0;
    h->row.f = open_memstream(&p->text, &p->len);
    if (!h->row.f) {
        p->text = NULL;
        return 1;
    }
    bad = sweep_sample(h, k);
    if (fclose(h->row.f) != 0 || h->row.err) {
        free(p->text);
        p->text = NULL;
    }
    return bad;
}

/* Whether the scene loads with the --set changes and v at x (what names x: LO, HI,
   MEAN). 0, or 2 after the file's message. Uses the first thread's buffers. */
static int vary_loads(sweep *w, const vary *v, const char *what, double x)
{
    worker *h = &w->wk[0];
    rj_scene_file f;
    rj_error e;
    vary_change(h->text[0], v, x);
    if (rj_scene_load_set(w->o->scene, h->sets, w->o->nsets + 1, &f, &e) != RJ_OK) {
        fprintf(stderr, "rj sweep: option --vary %s: at %s = %.17g%s%s: %s\n", v->spec, what, x,
                v->unit[0] ? " " : "", v->unit, e.msg);
        return 2;
    }
    rj_scene_file_free(&f);
    return 0;
}

/* Each --vary against the file before anything runs: its key must name an item and both
   ends (a normal's mean) must load with the --set changes, in the unit given, and no key
   may be varied twice. A sample's
   failure is a row; a range that cannot be right for any sample is bad usage. Returns 0,
   or 2 after naming the option. Uses the first thread's buffers. */
static int sweep_check(sweep *w)
{
    const opts *o = w->o;
    int i, j, end;
    if (o->nsets + o->nvary > RJ_SCENE_MAX_SETS) {
        fprintf(stderr, "rj sweep: %d --set and --vary changes, more than the %d a scene takes\n",
                o->nsets + o->nvary, RJ_SCENE_MAX_SETS);
        return 2;
    }
    for (i = 0; i < o->nvary; i++) {
        const vary *v = &o->varies[i];
        for (j = 0; j < i; j++)
            if (v->keylen == o->varies[j].keylen && !strncmp(v->spec, o->varies[j].spec, (size_t)v->keylen)) {
                fprintf(stderr, "rj sweep: option --vary %s: %.*s is varied twice\n", v->spec, v->keylen,
                        v->spec);
                return 2;
            }
        /* a range at both ends; a normal at its mean (a draw far out is a failed row) */
        if (v->dist == DIST_NORMAL && vary_loads(w, v, "MEAN", v->mean) != 0) return 2;
        for (end = 0; v->dist == DIST_UNIFORM && end < 2; end++)
            if (vary_loads(w, v, end ? "HI" : "LO", end ? v->hi : v->lo) != 0) return 2;
    }
    return 0;
}

/* A thread's changes' texts: each "KEY=", a %.17g number (at most 24 characters) and a
   unit (" deg/s"), each buffer long enough for any key (sweep_check writes every key into
   the first). */
static int worker_alloc(worker *h, sweep *w, int longest)
{
    const opts *o = w->o;
    int i;
    h->w = w;
    h->sets = (const char **)malloc(sizeof(char *) * (size_t)(o->nsets + o->nvary));
    h->text = (char **)calloc((size_t)o->nvary, sizeof(char *));
    h->x = (double *)malloc(sizeof(double) * (size_t)o->nvary);
    if (!h->sets || !h->text || !h->x) return -1;
    for (i = 0; i < o->nsets; i++) h->sets[i] = o->sets[i];
    for (i = 0; i < o->nvary; i++) {
        h->text[i] = (char *)malloc((size_t)longest + 40);
        if (!h->text[i]) return -1;
        h->sets[o->nsets + i] = h->text[i];
    }
    return 0;
}

/* --lhs: each --vary's permutation of the --samples N strata (lhs_perm), the same in
   every shard: N ints a key. 0, or -1 when memory ran out. */
static int lhs_alloc(sweep *w)
{
    const opts *o = w->o;
    int v;
    w->perm = (int **)calloc((size_t)o->nvary, sizeof(int *));
    if (!w->perm) return -1;
    for (v = 0; v < o->nvary; v++) {
        w->perm[v] = (int *)malloc(sizeof(int) * (size_t)o->samples);
        if (!w->perm[v]) return -1;
        lhs_perm(w->perm[v], o->samples, o->seed, v);
    }
    return 0;
}

/* The threads' buffers, the --lhs strata, the flexible links and the header. */
static int sweep_alloc(sweep *w)
{
    const opts *o = w->o;
    const rj_model *m = w->sc->m;
    int i, longest = 0;
    w->wk = (worker *)calloc((size_t)o->threads, sizeof(worker));
    w->flex = (int *)malloc(sizeof(int) * (size_t)(rj_model_link_count(m) + 1));
    if (!w->wk || !w->flex) return -1;
    for (i = 0; i < o->nvary; i++)
        if (o->varies[i].keylen > longest) longest = o->varies[i].keylen;
    for (i = 0; i < o->threads; i++)
        if (worker_alloc(&w->wk[i], w, longest) != 0) return -1;
    if (o->design == DESIGN_LHS && lhs_alloc(w) != 0) return -1;
    w->nflex = 0;
    for (i = 0; i < rj_model_link_count(m); i++)
        if (link_flexible(m, i)) w->flex[w->nflex++] = i;
    return sweep_header_text(w);
}

/* Frees what sweep_alloc made. */
static void sweep_free(sweep *w)
{
    int i, t;
    for (t = 0; w->wk && t < w->o->threads; t++) {
        worker *h = &w->wk[t];
        for (i = 0; h->text && i < w->o->nvary; i++) free(h->text[i]);
        free(h->text);
        free((void *)h->sets);
        free(h->x);
    }
    free(w->wk);
    free(w->flex);
    free(w->header);
    free(w->have);
    for (i = 0; w->perm && i < w->o->nvary; i++) free(w->perm[i]);
    free(w->perm);
}

/* ---- which samples: the shard's, less those --resume found in the file */

/* The shard's sample after k, or -1; the step never passes INT_MAX (--shard i/n takes n
   up to it). */
static int shard_step(const opts *o, int k)
{
    return o->shard_n < o->samples - k ? k + o->shard_n : -1;
}

/* The shard's first sample from k on (k in the shard, or -1) that the file does not hold
   yet, or -1. */
static int sweep_next(const sweep *w, int k)
{
    for (; k >= 0; k = shard_step(w->o, k))
        if (!w->have || !w->have[k]) return k;
    return -1;
}

/* The shard's first sample to run, or -1. */
static int sweep_first(const sweep *w)
{
    return sweep_next(w, w->o->shard_i < w->o->samples ? w->o->shard_i : -1);
}

/* How many samples this run has to do. */
static int sweep_count(const sweep *w)
{
    int k, n = 0;
    for (k = sweep_first(w); k >= 0; k = sweep_next(w, shard_step(w->o, k))) n++;
    return n;
}

/* ---- --resume: a cut-short run's file, checked, cut after its last whole row, continued */

/* The file's first line (n bytes, the newline included when it is whole) against this
   sweep's header: the same, or cut short, its start. Returns 0, or 2 after showing both. */
static int sweep_resume_header(const sweep *w, const char *line, size_t n, const char *path)
{
    const int whole = line[n - 1] == '\n';
    if ((whole ? n == w->header_len : n < w->header_len) && !memcmp(line, w->header, n)) return 0;
    fprintf(stderr,
            "rj sweep: option --resume: the header of %s differs from this sweep's (another scene or --vary?); "
            "the file's:\n%.*s%sthis sweep's:\n%s",
            path, (int)n, line, whole ? "" : "\n", w->header);
    return 2;
}

/* One of the file's whole rows: its index, a sample of the shard not seen before, then
   the values this sweep draws for it, as sweep_row_start writes them. A row of another
   sweep (--seed, the ranges, --samples, --shard) is refused: appended to, the file would
   mix two sweeps. Returns 0, or 2 after naming the line. */
static int sweep_resume_row(sweep *w, const char *line, const char *path, long lineno)
{
    const opts *o = w->o;
    const char *p = line;
    char num[48], why[160];
    long k = 0;
    int i;
    why[0] = '\0';
    for (; *p >= '0' && *p <= '9' && k <= o->samples; p++) k = 10 * k + (*p - '0');
    if (p == line || (line[0] == '0' && p - line > 1)) snprintf(why, sizeof why, "no sample index");
    else if (k >= o->samples) snprintf(why, sizeof why, "sample %ld is past --samples %d", k, o->samples);
    else if (*p != ',') snprintf(why, sizeof why, "no sample index");
    else if (k % o->shard_n != o->shard_i)
        snprintf(why, sizeof why, "sample %ld is not in shard %d/%d", k, o->shard_i, o->shard_n);
    else if (w->have[k]) snprintf(why, sizeof why, "sample %ld again", k);
    for (i = 0; !why[0] && i < o->nvary; i++) {
        const int len = snprintf(num, sizeof num, ",%.17g", sweep_value(w, (int)k, i));
        if (strncmp(p, num, (size_t)len) != 0 || (p[len] != ',' && p[len] != '\n'))
            snprintf(why, sizeof why, "sample %ld's %.*s is not this sweep's %s (another --seed or range?)", k,
                     o->varies[i].keylen, o->varies[i].spec, num + 1);
        p += len;
    }
    if (why[0]) {
        fprintf(stderr, "rj sweep: option --resume: %s:%ld: not a row of this sweep: %s\n", path, lineno, why);
        return 2;
    }
    w->have[k] = 1;
    w->held++;
    return 0;
}

/* Reads the file: the header, then each whole row into w->have; a last line without its
   newline (the run stopped while writing it) is not kept. Returns the bytes to keep, or
   -1 after saying why not. */
static off_t sweep_resume_scan(sweep *w, FILE *f, const char *path)
{
    char *line = NULL;
    size_t cap = 0;
    ssize_t n;
    off_t keep = 0;
    long lineno = 0;
    int st = 0;
    while (st == 0 && (n = getline(&line, &cap, f)) > 0) {
        if (++lineno == 1) st = sweep_resume_header(w, line, (size_t)n, path);
        if (line[n - 1] != '\n') break;
        if (lineno > 1) st = sweep_resume_row(w, line, path, lineno);
        if (st == 0) keep += (off_t)n;
    }
    if (st == 0 && ferror(f)) {
        fprintf(stderr, "rj sweep: option --resume: cannot read %s: %s\n", path, strerror(errno));
        st = 2;
    }
    free(line);
    return st ? -1 : keep;
}

/* --resume: the file checked and cut after its last whole row (sweep_resume_scan), then
   opened to append to; a file that does not exist yet, or holds no whole line, is a sweep
   from the start, header first. Returns 0, 1 (out of memory) or 2. */
static int sweep_resume_open(sweep *w, const char *path)
{
    FILE *f;
    off_t keep = 0;
    w->have = (unsigned char *)calloc((size_t)w->o->samples, 1);
    if (!w->have) {
        fprintf(stderr, "rj sweep: out of memory\n");
        return 1;
    }
    f = fopen(path, "r");
    if (!f && errno != ENOENT) {
        fprintf(stderr, "rj sweep: option --resume: cannot read %s: %s\n", path, strerror(errno));
        return 2;
    }
    if (f) {
        keep = sweep_resume_scan(w, f, path);
        fclose(f);
        if (keep < 0) return 2;
        if (truncate(path, keep) != 0) {
            fprintf(stderr, "rj sweep: option --resume: cannot cut %s after its last whole row: %s\n", path,
                    strerror(errno));
            return 2;
        }
    } else if (cli_mkparent("rj sweep", path) != 0) return 2;
    w->out.err = 0;
    w->out.name = path;
    w->out.f = fopen(path, "a");
    if (!w->out.f) {
        fprintf(stderr, "rj sweep: cannot open %s for writing: %s\n", path, strerror(errno));
        return 2;
    }
    if (keep == 0) cli_put(&w->out, fputs(w->header, w->out.f));
    return 0;
}

/* The output (csv NULL: standard output), header first, or --resume's file. Returns 0,
   1 or 2. */
static int sweep_open(sweep *w, const char *csv)
{
    if (w->o->resume) return sweep_resume_open(w, csv);
    if ((csv && cli_mkparent("rj sweep", csv) != 0) || cli_open(&w->out, "rj sweep", csv) != 0) return 2;
    cli_put(&w->out, fputs(w->header, w->out.f));
    return 0;
}

/* ---- the progress line, as rj run's: with --progress always (every second; a quarter
   of one on a terminal, redrawn in place), without it only on a terminal after 2 s */

static void sweep_progress_start(progress *pr, int always)
{
    memset(pr, 0, sizeof *pr);
    pr->tty = isatty(2);
    pr->mode = always ? PROGRESS_ALWAYS : pr->tty ? PROGRESS_TTY : PROGRESS_OFF;
    pr->wall0 = wall_now();
}

/* One line: samples done of this run's, samples/s and the remaining wall time at that
   rate. */
static void sweep_progress_print(progress *pr, int done, int total, double now)
{
    const double el = now - pr->wall0;
    const double rate = el > 0 ? done / el : 0.0;
    const double eta = done > 0 ? el * (total - done) / done : 0.0;
    fprintf(stderr, "%srj sweep: %5.1f %%  %d / %d samples  %.3g samples/s  ETA %.0f s%s", pr->tty ? "\r" : "",
            100.0 * done / (total > 0 ? total : 1), done, total, rate, eta, pr->tty ? "   " : "\n");
    pr->shown = pr->tty;
}

/* Called at least every quarter second (the writer's wait): a line when one is due. */
static void sweep_progress_tick(progress *pr, int done, int total)
{
    const double now = wall_now();
    if (pr->mode == PROGRESS_OFF || now < pr->next) return;
    if (pr->mode == PROGRESS_TTY && now - pr->wall0 < 2.0) return;
    sweep_progress_print(pr, done, total, now);
    pr->next = now + (pr->tty ? 0.25 : 1.0);
}

/* The end: on a terminal the line is cleared; into a file or pipe --progress ends with
   the line of the end. */
static void sweep_progress_end(progress *pr, int done, int total)
{
    if (pr->shown) fprintf(stderr, "\r%79s\r", "");
    if (pr->mode == PROGRESS_ALWAYS && !pr->tty) sweep_progress_print(pr, done, total, wall_now());
}

/* ---- the threads and the writer */

/* A thread: takes the next sample while the ring has room for its row, runs it, and
   leaves the row at its place in the ring; ends when none is left or the sweep stops. */
static void *sweep_thread(void *arg)
{
    worker *h = (worker *)arg;
    sweep *w = h->w;
    for (;;) {
        pending p;
        int k, place, bad;
        pthread_mutex_lock(&w->lock);
        while (!w->stop && w->next_k >= 0 && w->handed - w->written >= w->nring)
            pthread_cond_wait(&w->room, &w->lock);
        k = w->stop ? -1 : w->next_k;
        place = w->handed;
        if (k >= 0) {
            w->handed++;
            w->next_k = sweep_next(w, shard_step(w->o, k));
        }
        pthread_mutex_unlock(&w->lock);
        if (k < 0) return NULL;
        bad = sweep_sample_row(h, k, &p);
        pthread_mutex_lock(&w->lock);
        w->ring[place % w->nring] = p;
        w->done++;
        w->bad += bad;
        pthread_cond_signal(&w->ready);
        pthread_mutex_unlock(&w->lock);
    }
}

/* The writer's wait for the next row (the lock held): a quarter second at most, so that
   the progress line keeps its pace. */
static void sweep_wait(sweep *w)
{
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    ts.tv_nsec += 250000000L;
    if (ts.tv_nsec >= 1000000000L) {
        ts.tv_sec++;
        ts.tv_nsec -= 1000000000L;
    }
    pthread_cond_timedwait(&w->ready, &w->lock, &ts);
}

/* The writer (this thread): each row in the samples' order once its thread has left it
   in the ring, the progress line meanwhile. A failed write, or a row memory could not
   hold, stops the handing out; the threads end with the samples under way. */
static void sweep_write(sweep *w)
{
    progress pr;
    int done;
    sweep_progress_start(&pr, w->o->progress);
    pthread_mutex_lock(&w->lock);
    while (!w->stop && w->written < w->todo) {
        pending *slot = &w->ring[w->written % w->nring], p;
        sweep_progress_tick(&pr, w->done, w->todo);
        if (!slot->ready) {
            sweep_wait(w);
            continue;
        }
        p = *slot;
        slot->ready = 0;
        w->written++;
        pthread_cond_broadcast(&w->room);
        pthread_mutex_unlock(&w->lock);
        if (!p.text && !w->out.err) w->out.err = ENOMEM;
        if (p.text) cli_put(&w->out, fwrite(p.text, 1, p.len, w->out.f) == p.len ? 0 : -1);
        free(p.text);
        pthread_mutex_lock(&w->lock);
        if (w->out.err) {
            w->stop = 1;
            pthread_cond_broadcast(&w->room);
        }
    }
    done = w->done;
    pthread_mutex_unlock(&w->lock);
    sweep_progress_end(&pr, done, w->todo);
}

/* The samples on --threads threads, each with its own models and states, the rows
   written in the samples' order (sweep_write). Returns 0, or 1 when no thread started. */
static int sweep_go(sweep *w)
{
    const opts *o = w->o;
    int t, started, rc = 0;
    w->nring = SWEEP_RING_PER_THREAD * o->threads;
    w->ring = (pending *)calloc((size_t)w->nring, sizeof(pending));
    if (!w->ring) {
        fprintf(stderr, "rj sweep: out of memory\n");
        return 1;
    }
    w->next_k = sweep_first(w);
    pthread_mutex_init(&w->lock, NULL);
    pthread_cond_init(&w->ready, NULL);
    pthread_cond_init(&w->room, NULL);
    for (started = 0; started < o->threads; started++)
        if ((rc = pthread_create(&w->wk[started].th, NULL, sweep_thread, &w->wk[started])) != 0) break;
    if (started == 0) fprintf(stderr, "rj sweep: cannot start a thread: %s\n", strerror(rc));
    else if (started < o->threads)
        fprintf(stderr, "rj sweep: warning: %d of %d threads started: %s\n", started, o->threads, strerror(rc));
    if (started > 0) sweep_write(w);
    for (t = 0; t < started; t++) pthread_join(w->wk[t].th, NULL);
    /* rows left by a sweep that stopped */
    for (t = 0; t < w->nring; t++)
        if (w->ring[t].ready) free(w->ring[t].text);
    pthread_cond_destroy(&w->room);
    pthread_cond_destroy(&w->ready);
    pthread_mutex_destroy(&w->lock);
    free(w->ring);
    return started > 0 ? 0 : 1;
}

/* rj sweep: the bound on a run's length at the smallest step a --vary solver.dt=LO:HI
   draws, LO (> 0; 0 is the automatic step, the file's check), so that a study of the step
   cannot run for days unasked. Exits 2 above it, unless --force. --dt, which every sample
   takes instead (sweep_sample), was checked as the file's step. */
static void sweep_check_dt(const opts *o)
{
    char prog[300];
    int i;
    for (i = 0; o->dt < 0 && i < o->nvary; i++) {
        const vary *v = &o->varies[i];
        if (v->dist != DIST_UNIFORM || v->keylen != 9 || strncmp(v->spec, "solver.dt", 9) != 0 || !(v->lo > 0))
            continue;
        snprintf(prog, sizeof prog, "rj sweep: option --vary %.200s: at LO", v->spec);
        cli_check_steps(prog, o->t_end, v->lo, o->force);
    }
}

/* rj sweep: the options, the scene at the file's values (names, the step bound), every
   --vary's ends and the output (--resume: the file's rows) are checked before any sample
   runs; then the samples. */
static int cmd_sweep(int argc, char **argv)
{
    opts o;
    scene sc;
    sweep w;
    int st = 2;
    double wall;
    const char *csv;
    opts_parse(&o, CMD_SWEEP, argc, argv, usage_sweep);
    free((void *)o.probes);
    if (scene_open(&sc, o.scene, o.dt, o.sets, o.nsets, 0) != 0) return 2;
    memset(&w, 0, sizeof w);
    w.o = &o;
    w.sc = &sc;
    csv = o.csv && strcmp(o.csv, "-") ? o.csv : NULL;
    if (sweep_alloc(&w) != 0) {
        fprintf(stderr, "rj sweep: out of memory\n");
        st = 1;
    } else if (sweep_check(&w) == 0) {
        /* the bound on a run's length at the file's step: a varied key may change it */
        cli_check_steps("rj sweep", o.t_end, rj_model_dt(sc.m), o.force);
        sweep_check_dt(&o);
        st = sweep_open(&w, csv);
    }
    if (st == 0) {
        wall = wall_now();
        w.todo = sweep_count(&w);
        if (o.resume)
            fprintf(stderr, "rj sweep: --resume: %s holds %d of the shard's samples; %d to run\n", csv, w.held,
                    w.todo);
        st = sweep_go(&w);
        st = cli_close(&w.out, "rj sweep") != 0 ? 1 : st;
        fprintf(stderr, "rj sweep: %d samples (shard %d/%d), %d not ok, wall %.3f s\n", w.done, o.shard_i,
                o.shard_n, w.bad, wall_now() - wall);
    }
    sweep_free(&w);
    free(o.varies);
    free((void *)o.sets);
    scene_close(&sc);
    return st;
}

/* ================================================================ main */

typedef int (*cmd_fn)(int argc, char **argv);

/* The subcommand named by the first argument gets the rest; argv[0] becomes "rj NAME"
   so that cli.h's messages name it. */
int main(int argc, char **argv)
{
    static const cmd_fn cmds[NCMDS] = { cmd_run, cmd_check, cmd_plot, cmd_animate, cmd_sweep };
    /* what a misspelt subcommand is matched against */
    static const char *const words[] = { "run", "check", "plot", "animate", "sweep", "help" };
    char prog[32];
    cli c;
    int k;
    /* a reader that goes away (rj run x.rjs | head) shows up as EPIPE on the write, which
       the run treats as a quiet end, instead of killing the program */
    signal(SIGPIPE, SIG_IGN);
    if (argc >= 2 && (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h") || (argc == 2 && !strcmp(argv[1], "help")))) {
        fputs(usage_main, stdout);
        return 0;
    }
    /* "rj help SUBCOMMAND" is "rj SUBCOMMAND --help" */
    if (argc == 3 && !strcmp(argv[1], "help")) {
        argv[1] = argv[2];
        argv[2] = (char *)"--help";
    }
    for (k = 0; argc >= 2 && k < NCMDS; k++) {
        if (strcmp(argv[1], cmd_names[k]) != 0) continue;
        snprintf(prog, sizeof prog, "rj %s", cmd_names[k]);
        argv[1] = prog;
        return cmds[k](argc - 1, argv + 1);
    }
    c.argc = argc;
    c.argv = argv;
    c.i = 1;
    c.usage = usage_main;
    argv[0] = (char *)"rj";
    if (argc >= 2) cli_unknown(&c, "subcommand", argv[1], words, NCMDS + 1);
    fputs(usage_main, stderr);
    return 2;
}
