/* ==================================================================== IMPLEMENTATION */
#if defined(REVJOINT_IMPLEMENTATION) && !defined(REVJOINT_IMPLEMENTATION_DONE)
#define REVJOINT_IMPLEMENTATION_DONE
#include <math.h>
#include <float.h>
#include <string.h>
#include <stdio.h>
#include <stdarg.h>
#include <stddef.h>

#if defined(RJ_MALLOC) != defined(RJ_FREE)
#error "define both RJ_MALLOC and RJ_FREE, or neither"
#endif
#ifndef RJ_MALLOC
#include <stdlib.h>
#define RJ_MALLOC(sz, ctx) ((void) (ctx), malloc(sz))
#define RJ_FREE(p, ctx)    ((void) (ctx), free(p))
#endif
/* With solver.in_place AUTO, models of at least this many nodes step in place (rj__step):
   below it a link's two frames (144 bytes per node) fit a 48 KB L1 data cache anyway, and
   in place costs copies of each chunk's chord angles and chords. Measured on a free link:
   slower in place at 100 and 200 elements, faster at 500 (docs/performance.md). */
#ifndef RJ_IN_PLACE_NODES
#define RJ_IN_PLACE_NODES 400
#endif
#ifndef RJ_ASSERT
#include <assert.h>
#define RJ_ASSERT(x) assert(x)
#endif
/* No FMA contraction in the library, whatever the including file's flags (gcc's GNU modes
   contract by default, clang's default mode within an expression; clang's
   -ffp-contract=fast ignores the pragma by design): the same bits from every build and
   lane width (tests/lanes.sh), -march=native included. The caller's code after the header
   keeps its own setting. (float_control needs clang 11, Apple's 13; older clangs and
   other compilers get no pragma.) */
#if defined(__clang__)
#if (!defined(__apple_build_version__) && __clang_major__ >= 11) || __clang_major__ >= 13
#define RJ__FP_PRAGMAS 1
#pragma float_control(push)
#pragma clang fp contract(off)
#endif
#elif defined(__GNUC__) && !defined(__INTEL_COMPILER)
#define RJ__FP_PRAGMAS 1
#pragma GCC push_options
#pragma GCC optimize("fp-contract=off")
#endif

#if defined(__cplusplus) && (defined(__GNUC__) || defined(_MSC_VER))
#define RJ__RESTRICT __restrict
#elif defined(__STDC_VERSION__) && __STDC_VERSION__ >= 199901L
#define RJ__RESTRICT restrict
#else
#define RJ__RESTRICT
#endif
/* The beam pass uses GCC/Clang vector extensions where they exist (RJ_NO_SIMD turns them
   off): its kernels are written once on the lane vector rj__vd of RJ__VW doubles. Where the
   pass is compiled for AVX that is 4 doubles: with -mavx, and on x86-64 without it, where
   the pass is compiled twice, once for AVX2 (RJ__AVX2) and chosen per step when the CPU
   has it (RJ_NO_DISPATCH turns that off); the copy for CPUs without AVX2 then takes the
   scalar loops (src/beam.h). Elsewhere (RJ_NO_DISPATCH, ARM) 2 doubles, one SSE2 or NEON
   register: a type is one per translation unit, and gcc keeps a 4-double vector it cannot
   hold in registers on the stack (docs/performance.md). No FMA (see above). Every lane does the scalar code's operations
   in the scalar code's order, so results are bit-identical in every case
   (tests/lanes.sh). 8-lane AVX-512 kernels were tried and measured no faster beyond this
   machine's noise (docs/performance.md), so there are none. */
#if !defined(RJ_NO_SIMD) && (defined(__GNUC__) || defined(__clang__))
#define RJ__LANES 1
typedef double rj__vd2 __attribute__((vector_size(16)));
#define RJ__VLD(v, p) memcpy(&(v), (p), sizeof(v))
#define RJ__VST(p, v) memcpy((p), &(v), sizeof(v))
#if !defined(__AVX__) && defined(__x86_64__) && !defined(RJ_NO_DISPATCH) &&                        \
    ((defined(__clang__) && __clang_major__ >= 4) || (!defined(__clang__) && __GNUC__ >= 6))
#define RJ__DISPATCH 1
#define RJ__AVX2     __attribute__((target("avx2")))
#endif
#if defined(__AVX__) || defined(RJ__DISPATCH)
#define RJ__VW 4
typedef double rj__vd __attribute__((vector_size(32)));
typedef long long rj__vl __attribute__((vector_size(32)));
#else
#define RJ__VW 2
typedef double rj__vd __attribute__((vector_size(16)));
typedef long long rj__vl __attribute__((vector_size(16)));
#endif
#endif
#ifndef RJ__AVX2
#define RJ__AVX2
#endif
#if defined(__cplusplus) || (defined(__STDC_VERSION__) && __STDC_VERSION__ >= 199901L)
#define RJ__INLINE inline
#else
#define RJ__INLINE
#endif
#if defined(__GNUC__) || defined(__clang__)
#define RJ__FORCE_INLINE __attribute__((always_inline)) RJ__INLINE
#define RJ__NOINLINE     __attribute__((noinline))
#else
#define RJ__FORCE_INLINE RJ__INLINE
#define RJ__NOINLINE
#endif
#define RJ__PI            3.14159265358979323846
#define RJ__TWO_PI        6.28318530717958647692
#define RJ__COOKIE_LINK   0x524a4c4bu
#define RJ__COOKIE_JOINT  0x524a4a54u
#define RJ__COOKIE_SOLVER 0x524a534fu
#define RJ__COOKIE_LOAD   0x524a4c44u
#define RJ__COOKIE_ACTUATOR 0x524a4143u
#define RJ__COOKIE_COUPLING 0x524a4350u
#define RJ__ALIGN         16
/* Margin on 2/omega_max: covers the Lanczos estimate (a lower bound of omega_max) and the
   geometric stiffness the linearisation leaves out. */
#define RJ__DT_MARGIN     0.98
#define RJ__LANCZOS_ITERS 160
/* Rigid trees of this many coordinates and more are solved by articulated bodies in O(n),
   smaller ones by the dense M and its Cholesky factor (docs/performance.md: the crossing). */
#ifndef RJ__RIG_TREE_MIN
#define RJ__RIG_TREE_MIN 16
#endif
/* a contact first seen more than this far past its limit is reported as caught late */
#define RJ__LATE 0.05
/* neither the energy balance (total + dissipated - initial) nor the limits' work may put in
   more than this share of the initial energy: springs, friction, damping and limits do not
   create energy, so that means chatter at a limit or a step above the bound: the step stops */
#define RJ__CREATED 0.02
/* Nodes a model may hold: node indices are ints, and the building scratch indexes up to
   25 values per node with them */
#define RJ__MAX_NODES 50000000
/* The shortest stability bound a model may have, s: below a femtosecond no mechanism is
   followed (a run of one second would take 1e15 steps), and what gets there is a link of
   atomic size or an unphysical material, usually numbers in the wrong units */
#define RJ__MIN_BOUND 1e-15
/* ints of scratch the joint-graph checks take (rj__validate_graph) */
#define RJ__GRAPH_SCRATCH(nl, nj) (2 * (size_t) (nl) + (size_t) (nj) + 1)

/* ------------------------------------------------------------------ internal types */
typedef struct rj__joint {
    int nI, nK, nJ,
        nL; /* global nodes: pin on body 1, its neighbour, pin on body 2, its neighbour; nI = nK = -1 for ground */
    int chord;       /* RJ_REF_CHORD */
    int loop;        /* it closes a loop: its body2 hangs from an earlier joint */
    int pair;        /* mixed scenes: it joins two rigid bodies (a pin between bodies) */
    double off;      /* tangent mode: theta = off + phi_J - phi_I */
    double minv;     /* rigid scenes: (M^-1)_jj, rate change per unit torque impulse */
    double gax, gay; /* ground reference direction (unit) when nK < 0 */
    double I1, I2;   /* reference-segment inertias, kg m^2 (I1 = inf for ground/fixed) */
    double w1, w2;   /* I2/(I1+I2), I1/(I1+I2): share of a correction taken by body 1 / body 2 */
    double k_limit;  /* stiffness at the limits (penalty_k or K_AP), N m/rad */
    double k_lin;    /* linear stiffness for the stability bound, N m/rad */
    double k_free;   /* k_lin without the limits (springs and tables), N m/rad */
    double fwd, rev; /* running (unwrapped) limits, rad; +-inf when disabled */
    double tv_turn;  /* table potential of a full turn, J */
    double c_lin;    /* linear damping for the stability bound (damper, actuator), N m s/rad */
    const rj_actuator_def *act; /* its actuator, or NULL */
    double cut;      /* a DC motor's cutoff on the running angle; +-inf: none */
    double rotor;    /* its actuator's reflected rotor inertia N^2 J, kg m^2 (0: none) */
    const double *spline; /* its actuator's profile table's second derivatives, or NULL */
} rj__joint;

/* An angle no joint reaches (within the 1e100 a checkpoint carries): the empty zone of the
   overlap record (RJ__JD_ZONE_LO above RJ__JD_ZONE_HI), and no band yet. */
#define RJ__NO_ZONE 1e99

/* Per-joint values in a frame (doubles), then per-joint ints. */
enum {
    RJ__JD_THETA = 0,
    RJ__JD_RATE,
    RJ__JD_LOCK,
    RJ__JD_EVENT,
    RJ__JD_RELEASE,
    RJ__JD_PEAKP,
    RJ__JD_P0,
    RJ__JD_QDD,
    RJ__JD_IMPULSE,
    RJ__JD_INPUT,   /* the caller's torque applied in the step that made this frame */
    RJ__JD_ZONE_LO, /* rad: the zone the angle is in, a band of 360 deg less 1 deg at each */
    RJ__JD_ZONE_HI, /* end or 1 deg about a fold (RJ__NO_ZONE and -RJ__NO_ZONE: none yet) */
    RJ__JD_BAND,    /* rad: the start of the last band's zone (RJ__NO_ZONE: none yet) */
    RJ__JD_OVERLAP, /* the first time the two links passed through each other, s (-1) */
    RJ__JD_TQ0,
    RJ__JD_COUNT = RJ__JD_TQ0 + RJ_TORQUE_COUNT
};
/* Frame scalars. */
enum {
    RJ__FS_TIME = 0,
    RJ__FS_ETIME,
    RJ__FS_KE,
    RJ__FS_STRAIN,
    RJ__FS_SPRING,
    RJ__FS_LDAMP,
    RJ__FS_LFRIC,
    RJ__FS_LLIM,
    RJ__FS_E0,
    RJ__FS_WARN,
    RJ__FS_PEND,
    RJ__FS_GRAV, /* the potential of gravity at x^n */
    RJ__FS_WORK, /* the work of the caller's inputs since the start */
    RJ__FS_DRIVE, /* the work of the actuators since the start */
    RJ__FS_DPEND, /* a prescribed joint's impulse's work the next step takes (its half) */
    RJ__FS_DFLOW, /* the actuators' work and gravity's potential moved so far, sum of |their
                     changes| (J): a scale */
    RJ__FS_LSTRUCT, /* the links' structural damping's loss since the start */
    RJ__FS_SPEND,   /* its half the next step takes, -dt/2 F_d^n . v^{n+1/2} */
    RJ__FS_LPLAST,  /* the plastic work since the start */
    RJ__FS_SPARE,   /* unused: 20 scalars keep the node arrays 32-byte aligned */
    RJ__FS_COUNT
};

struct rj_model {
    size_t bytes;
    unsigned long long hash;
    int nl, nj, nn, ne, ng;
    int rigid;         /* all links rigid: joint coordinates */
    int has_gravity;   /* solver.gravity is not zero */
    int nload;         /* applied loads (scene loads) */
    int nact;          /* actuators */
    int npres;         /* of them prescribed (RJ_ACTUATOR_PRESCRIBED) */
    int nrotor;        /* of them with a rotor (rotor_inertia > 0) */
    int nchord;        /* joints with the chord reference (RJ_REF_CHORD) */
    rj_actuator_def *act; /* (nact) their definitions */
    double *spl;          /* (nact x RJ_TABLE_MAX) profile tables' spline (rj__spline_build) */
    int ncp;              /* couplings */
    int nexact;           /* of them exact (constraints) */
    int nmotion;          /* prescribed joints and exact couplings: the step's rows */
    rj_coupling_def *cp;  /* (ncp) their definitions */
    rj_load_def *load; /* (nload) their definitions */
    int *load_node;    /* (nload) the node each acts on, in the scene's node order */
    double *rb_mass, *rb_icm,
        *rb_dcm;    /* (nl) rigid link mass, inertia about its centre, root-to-centre distance */
    int *rb_pjoint; /* (nl) joint whose body2 the link is, -1 if fixed */
    int *jorder;    /* (nq) the tree's joints with parents before children */
    int nq;         /* joint coordinates: the tree's joints (nj less those closing loops) */
    int nloop;      /* joints that close loops */
    int rig_tree;   /* rigid tree solved in O(n) (articulated bodies) instead of dense M */
    int *wcol;      /* (nq) a coordinate's column of M^-1 in the rigid scratch's W, -1: none */
    int nwcol;      /* W's columns: nq with a dense M, else those a tree's step keeps */
    int rig_rows;   /* rigid scenes: the most rows a step opens (rj__rig_rows_max) */
    int *qj;        /* (nq) coordinate k's joint */
    int *jq;        /* (nj) joint j's coordinate, -1 for a joint that closes a loop */
    double *jpin,
        *jref; /* (nj) pin distance along body 1 from its root; reference offset (pi or 0) */
    double dt, dt_bound, omega_max, dt_eq28, omega_links;
    rj_solver_def solver;
    rj_link_def *ldef;         /* (nl) */
    rj_joint_def *jdef;        /* (nj) */
    rj__joint *jnt;            /* (nj) */
    int *link_first;           /* (nl+1) first node of each link; nodes of a link are contiguous */
    int *link_efirst;          /* (nl+1) first element of each link */
    double *link_l0;           /* (nl) element rest length, m */
    double *link_EA, *link_EI; /* (nl) N, N m^2 */
    double *link_rho, *link_I; /* (nl) kg/m^3, m^4 */
    int any_inext;             /* some link is RJ_LINK_INEXTENSIBLE */
    /* mixed scenes: each rigid link is one rigid body (a cluster) carrying its own nodes
       (rotation and translation follow the body) and the nodes pinned to them (translation
       follows, rotation free); cluster c is link c, other links have no members */
    int ncl;                 /* nl in a mixed scene, else 0 */
    int *node_cl;            /* (nn) cluster of a node, -1 if none */
    int *cl_first, *cl_node; /* (nl+1), (nn) members */
    int *cl_fix;             /* (nl) 0 free body, 1 turns about a fixed pin (the anchor), 2 held */
    double *cl_M, *cl_I;     /* (nl) mass, inertia about the anchor (centre of mass, or the pin) */
    double *
        cl_th0; /* (3 nl) body angle at the start (its nodes' phi0), anchor velocity at the start */
    double *cl_rx, *cl_ry; /* (nn) member offsets from the anchor at the start */
    int nbp;               /* pins between two bodies (rj__body_pins) */
    int npair;             /* joints between two bodies (rj__joint.pair) */
    int project;           /* any_inext or nbp: stage 6 projects positions */
    int *bp_node;          /* (2 nj) each one's node on the first body, on the second */
    size_t
        cl_off; /* frame offset of the clusters' records: anchor x y, its velocity, omega, angle */
    int nch;    /* inextensible chains: links joined tip to root form one chain */
    int *ch_first;           /* (nl+1) first entry of each chain in ch_node */
    int *ch_node;            /* (nn+nl) node indices along the chains (a shared pin once) */
    double *ch_l0sq;         /* (nn+nl) squared rest length of the element after each entry */
    /* inextensible chains that meet: one sparse system (src/shake_graph.h) */
    int gs_n, gs_nodes;      /* its elements; the nodes they move */
    size_t gs_prof;          /* entries below the diagonal in the factor's profile */
    int *gs_na, *gs_nb;      /* (ne) an element's first and second node */
    int *gs_oa, *gs_ob;      /* (ne) their owners (rj__gs_owner) */
    int *gs_first, *gs_off;  /* (ne, ne+1) a row's first column, its offset in the profile */
    int *gs_node, *gs_nown;  /* (nn) the nodes moved, each one's owner */
    double *gs_l0sq;         /* (ne) squared rest lengths */
    double *mass, *rinertia; /* (nn) lumped translational mass kg, rotary inertia kg m^2 */
    double *tinv; /* (nn) 1/mass for free ungrouped nodes, 0 for fixed or grouped nodes */
    double *rinv; /* (nn) 1/rinertia, 0 for fixed rotations */
    double *einv; /* (nn) effective translational 1/mass (group's for grouped nodes) */
    double *kmass,
        *krot; /* (nn) mass / rotary inertia counted in the kinetic energy (0 for fixed or grouped) */
    int *grp_first; /* (ng+1) */
    int ndn;        /* nodes whose forces change after the beams, and links' end nodes */
    int dn_inner;   /* some flexible link has such a node inside (not at an end) */
    int ip;         /* the step runs in place (rj__step, RJ_IN_PLACE_NODES) */
    int *
        dnode; /* (ndn) those nodes and every link's end nodes: the fused beam pass advances them again */
    double *
        link_un; /* (5 nl) a link's other nodes' tinv, rinv, kmass, krot, and 1 when they all agree */
    double *
        link_kc; /* (4 nl) a link's element constants: EI/l0, EA/l0 (0 if inextensible), l0^2, 1/(2 l0^2) */
    /* structural damping (eta, mass_damping): links that have it take the beam pass's
       damped path (rj__beam_material_link) */
    int nstruct;        /* links with structural damping */
    int nplastic;       /* links with yielding layers */
    int nmaterial;      /* links on the material path: damping, yielding layers, Biot */
    int *link_path;     /* (nl) RJ__PATH_*: the beam pass's path for the link */
    int *link_pl;       /* (nl) a yielding link's first plastic strain in the frame's block */
    size_t pl_off, npl; /* the frame's block of plastic strains: its offset, its size */
    double *link_damp;  /* (RJ__LD_PER nl) a link's damping in use (RJ__LD) */
    int nvisc;          /* links whose Kelvin-Voigt damping is implicit (src/viscous.h) */
    int applied;        /* the step's rj__stage_applied has model loads or damping to take */
    int visc_nodes;     /* the most nodes of such a link (the step's scratch, rj_state.visc) */
    int *visc_first;    /* (nl + 1) each link's run of visc_joint */
    int *visc_joint;    /* (2 nj) the joints a damped link's solve holds (rj__visc_hold) */
    double struct_rate; /* 1/s: the fastest damping rate they give a mode, max eta w^2 + a */
    int *grp_node;   /* (members) */
    int *node_grp;   /* (nn) group of a node, -1 if none */
    double *grp_inv; /* (ng) 1/sum of member masses, 0 if a member is fixed */
    double *x0, *y0, *phi0, *vx0, *vy0, *w0; /* (nn) initial conditions */
    double *beta0;                           /* (ne) initial chord angles */
    double *lz;                              /* building scratch (rj__build_scratch) */
    int nwarn;            /* warnings about the definitions (rj_model_warnings) */
    char warnings[1024];  /* their text, one per line */
    size_t frame_doubles; /* doubles in a frame */
    size_t frame_ints;
};

/* A rigid link's kinematics in the pin-force query (rj__rig_accels): angle, rate,
   angular acceleration, root, the root's acceleration. */
enum { RJ__KA_PHI, RJ__KA_OM, RJ__KA_AL, RJ__KA_RX, RJ__KA_RY, RJ__KA_AX, RJ__KA_AY, RJ__KA_N };

/* The doubles a link takes in the pin-force queries' scratch (rj__pin_work_size): rigid
   scenes' kinematics and two more, or node space's all-joints pass's arrays
   (rj__pin_pass); a state keeps the larger for its peaks (rj_state.peak_work). */
#define RJ__PIN_PASS_N 10
#define RJ__PIN_PER_LINK (RJ__KA_N + 2 > RJ__PIN_PASS_N ? RJ__KA_N + 2 : RJ__PIN_PASS_N)

/* The peaks a state tracks (rj_state.peaks): per joint |pin force| and its time, per link
   the |bending moment| (its time, element, end) and the stress (its time, element). */
#define RJ__PEAK_JOINT 2
#define RJ__PEAK_LINK 7

/* The beam pass's path for a link (rj_model.link_path): the fused kernels, none (a rigid
   link: its body moves its nodes), or the material path's scalars (src/beam_material.h:
   structural damping, yielding layers, the Biot axial law). */
enum { RJ__PATH_FUSED = 0, RJ__PATH_RIGID, RJ__PATH_MATERIAL };

/* A link's damping in use (rj_model.link_damp): eta on the lagged rates (s; only where a
   rigid body carries one of its nodes), mass_damping (1/s), eta on the rates at
   n + 1/2 (s; src/viscous.h). */
enum { RJ__LD_LAGGED = 0, RJ__LD_MASS, RJ__LD_IMPLICIT, RJ__LD_PER };
#define RJ__LD(m, l) ((m)->link_damp + RJ__LD_PER * (size_t) (l))

/* Constraint rows (src/rows.h tells what they are and how they are solved). */
enum rj__row_kind {
    RJ__ROW_LOCK,       /* a locked joint: q'_j = 0 */
    RJ__ROW_CONTACT,    /* a plastic contact at its limit: q'_j = 0, its impulse pushing */
    RJ__ROW_PRESCRIBED, /* a prescribed joint: its profile's angle at n + 1 */
    RJ__ROW_COUPLING,   /* an exact coupling: e = 0 at n + 1 */
    RJ__ROW_LOOP        /* a loop joint's pins together (x or y), in joint coordinates */
};

/* One term of a row: coef times joint's rate. */
typedef struct rj__term {
    int joint;
    double coef;
} rj__term;

/* One row: its kind and owner (a joint, or a coupling), its terms in the pool, whether
   the solve holds it, its target rate, its impulse's bounds and the impulse it took. */
typedef struct rj__row {
    int kind, owner;
    int first, count;
    int active;
    const double *col; /* joint coordinates: M^-1 J^T (rj__row_column) */
    double target;
    double lo, hi;
    double lam;
    double before; /* node space: J v before the impulses (the first step's work) */
} rj__row;

/* A step's rows and their terms (the state's storage, rj__rows_capacity). */
typedef struct rj__rows {
    rj__row *row;
    rj__term *term;
    int count, terms;
} rj__rows;

/* At most one row per joint (a lock, a contact or a profile) and one per exact coupling;
   one term per joint's row, two per coupling's. */
static int rj__rows_capacity(int nj, int ncp)
{
    return nj + ncp + 1;
}

static int rj__terms_capacity(int nj, int ncp)
{
    return nj + 2 * ncp + 1;
}

/* What holds the state a step before, for the loads at t^n (rj_state.at_n): nothing
   (before a step, after a failed one, a checkpoint's load, rj_settle), the other frame
   (after a double-buffered step), or the third frame, which the in-place step leaves
   holding the values at n of m->dnode's nodes, with s->fx, fy their forces of the step. */
enum { RJ__AT_N_NONE, RJ__AT_N_FRAME, RJ__AT_N_KEPT };

struct rj_state {
    size_t bytes;
    int cur; /* index of the current frame */
    long steps;
    double
        *fd[3]; /* frames: x y phi vx vy w (nn each), beta cx cy (ne each), joints (nj*JD), scalars;
                                 in place (rj_model.ip) fd[2] takes the step's new joints and scalars */
    int *fi[3]; /* frames: flags (nj) */
    long snap;  /* in place: the other frame is a copy of the state at this step (-1: none) */
    unsigned long long
        want; /* in place: the energy requests of the steps since snap (bit k: step snap + k) */
    double *fx, *fy, *mz; /* (nn) forces */
    double *kn;           /* (nn) each node's share of twice the kinetic energy */
    double *damp; /* (3 nn + 2, with the material path) structural damping's forces at n on
                     every node, fx then fy then mz, their power at n - 1/2 and the plastic
                     work summed in the step: for their accounts (src/beam_material.h) */
    double *visc; /* (RJ__VISC_PER (visc_nodes + 1)) the implicit damping's solve
                     (src/viscous.h) */
    double *visc_force; /* (4 ne with implicit damping) each element's viscous force of the
                           last step as rj__elem_viscous gives it: its loads at t^n */
    int at_n;     /* what holds the state a step before, for the loads at t^n (rj__at_n) */
    int peaks_on; /* rj_state_track_peaks: the steps that take the accounts track peaks */
    double *peaks;     /* (2 nj + 7 nl) the peaks (src/peaks.h) */
    double *peak_work; /* (RJ__PIN_PER_LINK (nl + 1) + 2 nj) their queries' scratch */
    double *sha, *shb, *shc,
        *shr; /* (ne each with inextensible links, else none) SHAKE's tridiagonal and residuals */
    double *shp; /* (2 nn with inextensible links and loops, else none) SHAKE's pushes
                    over the step by each element's second node (rj__loop_records) */
    double *gsw; /* (2 gs_prof + 9 gs_n + 2 nn, or none) rj__gs_work */
    double *bpw; /* (with pins between bodies: 2 (2 nbp)^2 + 4 nbp + 3 ncl, and 2 nbp
                    with loops) rj__body_pins */
    double *eu,
        *ebt; /* (ne) element strain energies; scratch (chord angles at reset, SHAKE's active flags) */
    double *jsc;          /* (nj*8) joint scratch: ax ay bx by ratem tau_nc */
    double *input_torque; /* (nj) the caller's joint torques, N m on body 2 (kept until changed) */
    int inputs;           /* rj_state_joint_torques was called: the step applies them */
    double *input_node;   /* (3 nn) the caller's node forces fx fy mz (kept until changed) */
    int node_inputs;      /* rj_state_node_forces was called: the step applies them */
    double settle_scale;  /* rj_settle under way: the potential energy it has moved, J (else 0) */
    int settling;         /* rj_settle under way: prescribed joints hold their profiles' start */
    double *snap_torque;  /* (nj) in place: the caller's joint torques since snap */
    int snap_inputs;      /* in place: inputs (on or off) since snap */
    double *node_applied; /* (3 nn) the node forces the last step applied, for their work */
    double step_work;     /* the work of the loads and node forces in the step under way */
    double step_fin;      /* the positions their kicks wrote, summed (the finite test) */
    double *rsc;      /* rigid scenes: the solver's scratch (rj__rig_step_scratch); mixed:
                         body impulses (3 nl) */
    rj__row *rows;    /* the step's constraint rows (rigid scenes: rj_model.rig_rows + 1;
                         else rj__rows_capacity) */
    rj__term *terms;  /* their terms (rj__terms_capacity) */
    double *rsys;     /* node space: the rows' system, its factor, right side and impulses */
    double *loop_force; /* (2 nj + 1) rigid loops: each loop joint's pin force over the last
                           step, from its rows' impulses (rj__rig_loop_forces); node space:
                           what its projections gave it (rj__loop_records); then the step
                           count they belong to (-1: none) */
    char err[640];
    char warn[200]; /* latest warning (late contact), written only when one occurs */
};

static size_t rj__rigid_scratch(size_t n, size_t nl, int dense, size_t cols, size_t rows,
                                size_t others);
static size_t rj__rig_step_scratch(const rj_model *m);
static double rj__rig_setup(rj_model *m, double *scratch);
typedef struct rj__rig {
    double *M, *L; /* n x n with a dense M; NULL for articulated bodies (rj_model.rig_tree) */
    double *W;     /* columns of M^-1, n each: rj_model.nwcol of them (rj_model.wcol) */
    double *q, *qd, *qdp, *qdd, *Q, *h, *x, *tmp; /* n each (tmp 2 n) */
    double *xd; /* n: the impulse of the prescribed loop joints' rows on each coordinate */
    double *S, *SL, *lam,
        *rhs;   /* the rows' system (src/rows.h): R x R, its factor, R each (R rows at most) */
    double *Y;  /* the rows' M^-1 J^T that are not a column of M^-1: n each, one per coupling
                   and two per loop */
    double *lk; /* per link, RJ__RL_COUNT values: rj__rig_kin */
    double *ab; /* per coordinate, RJ__AB_COUNT values: the articulated bodies (rj__aba_*) */
} rj__rig;
/* a coordinate's record in rj__rig.ab: its body's own inertia about the joint's pin and the
   articulated inertia there (symmetric 3 x 3 on (omega, v_pin): 00 01 02 11 12 22), the
   factor's U = IA s and 1 / D (D = s.IA s + rotor), a force about the pin, the solve's u, an
   acceleration at the pin, the arm from the parent's pin, the parent's coordinate (-1:
   none) and the rotor; then two spare vectors for the callers' products */
enum {
    RJ__AB_OWN = 0,
    RJ__AB_IA = 6,
    RJ__AB_U = 12,
    RJ__AB_D = 15,
    RJ__AB_F = 16,
    RJ__AB_UU = 19,
    RJ__AB_A = 20,
    RJ__AB_RX = 23,
    RJ__AB_RY = 24,
    RJ__AB_PQ = 25,
    RJ__AB_ROT = 26,
    RJ__AB_COUNT = 27
};
/* a link's record in rj__rig.lk: angle and its cos, sin; root; centre; their accelerations
   (centripetal, at the predicted rates); predicted angular rate; rate and root velocity;
   then the subtree the link's parent joint carries (rj__rig_mass): its mass, first moment
   and inertia about the joint's pin, its sum of m a and that sum's moment about the pin */
enum {
    RJ__RL_PHI = 0,
    RJ__RL_EC,
    RJ__RL_ES,
    RJ__RL_RX,
    RJ__RL_RY,
    RJ__RL_CX,
    RJ__RL_CY,
    RJ__RL_ARX,
    RJ__RL_ARY,
    RJ__RL_ACX,
    RJ__RL_ACY,
    RJ__RL_OMB,
    RJ__RL_OM,
    RJ__RL_VX,
    RJ__RL_VY,
    RJ__RL_SUB_M,
    RJ__RL_SUB_SX,
    RJ__RL_SUB_SY,
    RJ__RL_SUB_J,
    RJ__RL_SUB_FX,
    RJ__RL_SUB_FY,
    RJ__RL_SUB_N,
    RJ__RL_PX, /* the pin of the link's joint (its root unless the joint pins another node) */
    RJ__RL_PY,
    RJ__RL_COUNT = 24
};
static RJ__FORCE_INLINE void rj__rig_map(const rj_model *m, double *base, rj__rig *r,
                                         int solve);
static double rj__rig_loop_rate(const rj_model *m, int j, const double *qd, double *g);
static double rj__gravity_potential(const rj_model *m, const double *x, const double *y);
static void rj__rig_kin(const rj_model *m, rj__rig *r, const double *q, const double *qd,
                        const double *qdp);
static void rj__rig_nodes(const rj_model *m, const rj__rig *r, double *f);

/* ------------------------------------------------------------------ small helpers */
RJDEF double rj_rad(double deg)
{
    return deg * (RJ__PI / 180.0);
}
RJDEF double rj_deg(double rad)
{
    return rad * (180.0 / RJ__PI);
}

static double rj__mod2pi(double a)
{
    double r = fmod(a, RJ__TWO_PI);
    if (r < 0)
        r += RJ__TWO_PI;
    if (r >= RJ__TWO_PI)
        r = 0.0;
    return r;
}
/* wrap into (-pi, pi] */
static double rj__wrap(double a)
{
    double r = rj__mod2pi(a + RJ__PI) - RJ__PI;
    if (r <= -RJ__PI)
        r += RJ__TWO_PI;
    return r;
}
static int rj__finite(double x)
{
    return x == x && x - x == 0.0;
}

/* Appends text to a NUL-terminated buffer, as much as fits. */
static void rj__cat(char *buf, size_t size, const char *text)
{
    size_t n = strlen(buf);
    while (*text && n + 1 < size)
        buf[n++] = *text++;
    buf[n] = 0;
}

/* A message that did not fit its buffer (vsnprintf wanted `wanted` chars) ends at its last
   whole word with "...", never in the middle of one. */
static void rj__fit_words(char *buf, size_t size, int wanted)
{
    size_t end;
    if (wanted >= 0 && (size_t) wanted < size)
        return;
    end = size - 4;
    while (end > 0 && buf[end] != ' ')
        end--;
    memcpy(buf + end, "...", 4);
}

static void rj__fail(rj_error *err, rj_result code, const char *field, double value,
                     const char *fmt, ...)
{
    va_list ap;
    int wanted;
    if (!err)
        return;
    err->code = code;
    snprintf(err->field, sizeof err->field, "%s", field);
    err->value = value;
    va_start(ap, fmt);
    wanted = vsnprintf(err->msg, sizeof err->msg, fmt, ap);
    va_end(ap);
    rj__fit_words(err->msg, sizeof err->msg, wanted);
}

RJDEF const char *rj_result_str(rj_result r)
{
    switch (r) {
    case RJ_OK:
        return "ok";
    case RJ_ERR_INVALID:
        return "invalid input";
    case RJ_ERR_NOMEM:
        return "out of memory";
    case RJ_ERR_UNSTABLE_DT:
        return "time step above the stability bound";
    case RJ_ERR_BLOWUP:
        return "numerical blow-up";
    case RJ_ERR_TUNNEL:
        return "joint turned more than a quarter revolution (pi/2 rad) in one step";
    case RJ_ERR_CHECKPOINT:
        return "bad checkpoint";
    case RJ_ERR_PARSE:
        return "scene text malformed";
    case RJ_ERR_NOT_CONVERGED:
        return "not settled";
    }
    return "unknown result";
}

