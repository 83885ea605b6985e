/* revjoint.h v0.1 - planar flexible links joined by revolute joints with rotation limits,
   locking, resistive torque, friction and damping (Wong, Hamouda & Hashmi 2002).
   MIT licence, see the end of the file.

   This file is generated: it joins the parts in src/ in the order of src/parts.txt
   (tools/amalgamate.sh, run by make). Edit the parts, never this file.

   "sec. N" and "Eq N" below and in the comments are the sections and equations of the
   paper: S. V. Wong, A. M. S. Hamouda, M. S. J. Hashmi, "Development of Revolute-Joint
   Element with Rotation Limits, Locking, Resistive Moment and Damping", Engineering with
   Computers 18 (2002) 1-13. Documentation: README.md, docs/modelling.md (how to describe
   a mechanism), docs/scene-format.md, docs/design.md (the readings of the paper taken).

USAGE
   In exactly one C or C++ file:
       #define REVJOINT_IMPLEMENTATION
       #include "revjoint.h"
   Everywhere else just #include "revjoint.h". Depends on libc and libm only.

CONFIGURATION MACROS (define before including the implementation)
   RJ_STATIC                 make every function static (private to one translation unit)
   RJ_MALLOC(sz,ctx), RJ_FREE(p,ctx)
                             allocator used by rj_model_create / rj_state_create and the
                             scene parser (define both or neither); ctx is the user pointer
                             given to those calls
   RJ_ASSERT(x)              programmer-error checks (NULL, index out of range); default assert
   RJ_NO_SIMD                plain scalar loops instead of GCC/Clang vector lanes in the step
                             (same results to the bit: tests/lanes.sh)
   RJ_NO_DISPATCH            on x86-64 without -mavx, do not also compile the lane kernels
                             for AVX2 (chosen per step when the CPU has it): 2-lane kernels
                             only, the faster build for CPUs without AVX2 (with dispatch
                             these run the scalar loops)
   RJ_NO_SCENE_FILES         leave out the scene-file parser and writer (rj_scene_*)
   RJ_IN_PLACE_NODES         with solver.in_place AUTO, models of at least this many nodes
                             step in place (default 400; 0: every model that can)

QUICK START
   rj_link_def links[2]; rj_joint_def joints[2]; rj_solver_def solver; rj_scene_def scene;
   rj_model *m; rj_state *s; rj_error err;
   links[0] = rj_default_link_def(); links[1] = rj_default_link_def();
   joints[0] = rj_default_joint_def(); joints[0].body1 = -1; joints[0].body2 = 0;
   joints[1] = rj_default_joint_def(); joints[1].body1 = 0;  joints[1].body2 = 1;
   joints[1].spring_k = 0.5; joints[1].spring_free_angle = rj_rad(90.0);
   solver = rj_default_solver_def();
   scene = rj_default_scene_def();
   scene.links = links; scene.link_count = 2; scene.joints = joints; scene.joint_count = 2;
   scene.solver = solver;
   if (rj_model_create(&scene, &m, &err, NULL) != RJ_OK) { puts(err.msg); return 1; }
   rj_state_create(m, &s, NULL);
   while (rj_state_time(s) < 1.0) if (rj_step(m, s) != RJ_OK) break;
   printf("theta = %g deg\n", rj_deg(rj_joint_theta(m, s, 1)));
   rj_state_destroy(s, NULL); rj_model_destroy(m, NULL);

CONCEPTS
   Model and state. rj_model is built once from definition structs, validated, and never
   changes; rj_state holds everything that moves (two time levels of the central-difference
   pair, joint flags, running angles, energy accounts). Every simulation call takes
   (const rj_model *, rj_state *): many states may share one model, from many threads.

   Units and signs. SI throughout; angles in radians, counter-clockwise positive. rj_rad()
   and rj_deg() convert at the edges.

   Links. A link is a planar, geometrically nonlinear Euler-Bernoulli beam of `elements`
   co-rotational Hermite elements, nodes 0..elements, node 0 at its root. Each node has a
   position (x, y) and a rotation phi. Mass is lumped: rho A l / 2 per element end on the
   translations, max(rho A l^3 / 78, rho I l / 2) per element end on the rotation. A link
   may instead be inextensible or rigid (rj_fidelity).

   Joints. Joint j pins node node2 of link body2 (node 0 unless set) to node node1 of link
   body1 (or to a ground point when body1 = -1). A link hangs from its first joint as
   body2; a later joint with the same body2 closes a loop (through links of any
   model, with every part of the joint element), and must
   find its pins together, moving together, at its angle0 where the other joints place
   the links. Its rotary location theta (sec. 3.1, Eqs 1-3) is the
   counter-clockwise angle from body 1's direction at the pin, pointing back towards body
   1's root (I->K; for ground, the fixed direction ground_angle), to body 2's direction
   (J->L). Two links that continue each other have theta = pi. It starts at angle0; by
   default (RJ_REF_TANGENT) it follows the pin nodes' rotations, with RJ_REF_CHORD the
   paper's chords. theta is tracked as an unwrapped running angle: a joint never jumps
   across 0/2pi, limits and springs use it.

   Stability. Central differences are stable while dt < 2 / omega_max. rj_model_create
   computes omega_max of the linearised model (beams, tip masses, joint stiffnesses and
   damping in use) by Lanczos iteration, uses 0.9 x its bound when solver.dt is 0, and
   refuses a larger solver dt unless solver.allow_unstable is set. rj_model_dt_eq28,
   rj_joint_dt_eq29 and rj_joint_kmax_eq31 give the paper's Eqs 28, 29 and 31 (sec. 3.7)
   for comparison.

   Scene files. rj_scene_load / rj_scene_parse read a small text format into the same
   definition structs and rj_scene_write writes it back (docs/scene-format.md).

ERRORS
   Functions that can fail return rj_result. Validation fills an rj_error with the field
   name, the bad value and a sentence. A failed call changes none of the caller's objects.
   rj_step stops with RJ_ERR_BLOWUP or RJ_ERR_TUNNEL and leaves the last good state intact.

THREAD SAFETY
   No globals. A model may be shared read-only by any number of threads; a state belongs
   to one thread at a time.
*/
#ifndef REVJOINT_H
#define REVJOINT_H

#include <stddef.h>

#ifdef RJ_STATIC
#define RJDEF static
#else
#define RJDEF extern
#endif

#ifdef __cplusplus
extern "C" {
#endif

#define RJ_VERSION "0.1.0"

/* Result codes. */
typedef enum rj_result {
    RJ_OK = 0,
    RJ_ERR_INVALID,      /* a definition field or an argument is out of range */
    RJ_ERR_NOMEM,        /* allocation failed or caller's block too small */
    RJ_ERR_UNSTABLE_DT,  /* dt above the stability bound and not overridden */
    RJ_ERR_BLOWUP,       /* non-finite value or energy growth beyond the bound */
    RJ_ERR_TUNNEL,       /* a joint turned more than a quarter revolution (pi/2 rad) in one step */
    RJ_ERR_CHECKPOINT,   /* a checkpoint buffer is truncated, corrupted or for another model */
    RJ_ERR_PARSE,        /* scene text malformed */
    RJ_ERR_NOT_CONVERGED /* rj_settle: no equilibrium within its steps */
} rj_result;

/* Validation and runtime error details, filled by the calls that take it (may be NULL). */
typedef struct rj_error {
    rj_result code;
    char field[64]; /* e.g. "joints[1].forward" */
    double value;   /* the offending value (NaN when not numeric) */
    char msg[512];  /* one full sentence */
} rj_error;

/* Root support of a link that is not the body2 of any joint. */
typedef enum rj_root { RJ_ROOT_FREE = 0, RJ_ROOT_PINNED, RJ_ROOT_CLAMPED, RJ_ROOT_FIXED } rj_root;

/* Link model. RJ_LINK_RIGID links have no bending or axial freedom. A rigid link is a
   uniform rod (rho A L, rho A L^3/12 about its centre) with its tip mass and inertia.
   - A scene of rigid links only is integrated in joint coordinates (one per joint), so its
     step is limited only by the joints' stiffnesses; every rigid link then hangs from one
     joint or is RJ_ROOT_FIXED, RJ_METHOD_ENERGY is not available, and the nodes are kept
     only to report and draw the links.
   - In a scene with flexible or inextensible links too, each rigid link is one rigid body
     (free, turning about a fixed pin, or held) carrying its nodes, which are massless
     attachment points (rj_node_mass gives mass 0 and the body's inertia about its
     anchor), and the nodes of other links pinned to it. Two rigid links pinned together
     there are kept together on positions (as SHAKE keeps inextensible links); their
     joint takes a spring, a table, damping, friction (with the pinned pair's give), a
     motor's torque, a prescribed profile (as a torque, RJ_TORQUE_DRIVE), cable loops,
     and limits and locks by every method but energy (as torques, RJ_TORQUE_LIMIT, an
     exact cable loop's too). Joints on a rigid link use
     RJ_REF_TANGENT; the flexible links set the step. */
/* RJ_LINK_INEXTENSIBLE links bend like flexible ones, but their element lengths are
   constraints (SHAKE projection along the previous chords: a tridiagonal solve per chain
   of links joined tip to root; chains that meet inside a link or close a loop through a
   moving pin form one sparse system), so the axial wave no longer limits the step: only
   bending does. They mix freely with flexible links. */
typedef enum rj_fidelity { RJ_LINK_FLEXIBLE = 0, RJ_LINK_RIGID, RJ_LINK_INEXTENSIBLE } rj_fidelity;

/* Section description. */
typedef enum rj_section { RJ_SECTION_RECT = 0, RJ_SECTION_GENERAL } rj_section;
/* A flexible link's axial law (docs/modelling.md, "The axial law"): GREEN, force EA eps L /
   l0 with the Green strain eps (St. Venant-Kirchhoff); BIOT, force EA e with the
   engineering strain e = L / l0 - 1. */
typedef enum rj_strain { RJ_STRAIN_GREEN = 0, RJ_STRAIN_BIOT } rj_strain;

/* Limit response methods (the paper's sec. 3.4, Eqs 14-26). */
typedef enum rj_method {
    RJ_METHOD_PENALTY = 0, /* user stiffness penalty_k (COMBIN7-like) */
    RJ_METHOD_ADAPTIVE,    /* K_AP = I1 I2 / ((I1 + I2) dt^2), Eq 21 */
    RJ_METHOD_MOMENTUM,    /* momentum balance with restitution e, Eqs 23-24 */
    RJ_METHOD_FORCED,      /* forced displacement back to the limit */
    RJ_METHOD_ENERGY       /* energy conservation, Eqs 25-26 */
} rj_method;

/* How a joint measures its rotary location and applies its torques.
   RJ_REF_TANGENT (default): theta from the nodal rotations (the beam's tangent directions)
     at the pin, torques as moments on those rotations; I1, I2 are the pin nodes' rotary
     inertias. Converges at second order with mesh refinement (docs/validation.md: 10 vs 40 elements).
   RJ_REF_CHORD: the paper's literal form, theta from the chords I->K and J->L, torques as
     force couples on them; I1, I2 = m_K |IK|^2, m_L |JL|^2. First order in the element
     length, because a couple over the first element is not a moment at the pin. */
typedef enum rj_reference { RJ_REF_TANGENT = 0, RJ_REF_CHORD } rj_reference;

/* Release rules (Eqs 8-13: RC12 position-based, RC13 velocity-based). */
typedef enum rj_release { RJ_RELEASE_RC12 = 0, RJ_RELEASE_RC13 } rj_release;
/* Where the step writes the nodes and elements (rj_solver_def.in_place): AUTO in place from
   RJ_IN_PLACE_NODES (400) nodes on, ON whenever the scene allows, OFF never (see the solver). */
typedef enum rj_in_place { RJ_IN_PLACE_AUTO = 0, RJ_IN_PLACE_ON, RJ_IN_PLACE_OFF } rj_in_place;

/* Joint status flag, Eq 7. */
typedef enum rj_flag { RJ_FREE = 0, RJ_AT_FORWARD = 1, RJ_AT_REVERSE = 2, RJ_LOCKED = 3 } rj_flag;

/* Torque components (about the joint, acting on body 2; body 1 gets the opposite). */
typedef enum rj_torque {
    RJ_TORQUE_TABLE = 0,
    RJ_TORQUE_SPRING,
    RJ_TORQUE_DAMPING,
    RJ_TORQUE_FRICTION,
    RJ_TORQUE_LIMIT,
    RJ_TORQUE_DRIVE, /* the joint's actuator (rj_actuator_def) */
    RJ_TORQUE_TOTAL,
    RJ_TORQUE_COUNT
} rj_torque;

/* Link definition. Defaults (rj_default_link_def):
     length 1 m; elements 10; E 70e9 Pa; rho 2710 kg/m^3;
     section RJ_SECTION_RECT, width 0.05 m, height 0.2 m (in-plane depth), layers 1;
     area 0 m^2, inertia 0 m^4 (used only by RJ_SECTION_GENERAL);
     tip_mass 0 kg, tip_inertia 0 kg m^2;
     root RJ_ROOT_FREE; x 0 m, y 0 m, angle 0 rad (root placement, used when the link is not
     the body2 of a joint); vx, vy 0 m/s, omega 0 rad/s (initial rigid motion of a root link); fidelity RJ_LINK_FLEXIBLE;
     eta 0 s, damping 0 0, mass_damping 0 1/s (no structural damping); yield 0 Pa (elastic),
     hardening 0 Pa, strain RJ_STRAIN_GREEN. */
typedef struct rj_link_def {
    double length;        /* m, > 0 */
    int elements;         /* >= 1 */
    double E;             /* Young's modulus, Pa, > 0 */
    double rho;           /* density, kg/m^3, > 0 */
    int section;          /* rj_section */
    double width;         /* m, out-of-plane width (RECT) */
    double height;        /* m, in-plane depth (RECT; drawn thickness for GENERAL if > 0) */
    int layers;           /* >= 1, layers across the depth (RECT); elastic layers cost nothing */
    double area;          /* m^2 (GENERAL) */
    double inertia;       /* m^4 second moment of area (GENERAL) */
    double tip_mass;      /* kg, >= 0, point mass at the last node */
    double tip_inertia;   /* kg m^2, >= 0, rotary inertia of the tip mass about its centre */
    int root;             /* rj_root */
    double x, y, angle;   /* m, m, rad */
    double vx, vy, omega; /* m/s, m/s, rad/s */
    int fidelity;         /* rj_fidelity */
    /* Structural damping (flexible and inextensible links; docs/modelling.md): */
    double eta;          /* s, >= 0: Kelvin-Voigt, stress E (strain + eta d(strain)/dt) on the
                            axial and bending strains: mode n damped at ratio eta omega_n / 2;
                            on the rates at n + 1/2 (no shorter step), lagged on a link a
                            rigid body carries a node of (docs/modelling.md) */
    double damping[2];   /* ratio, Hz: the eta that gives the ratio at that frequency,
                            ratio / (pi Hz); 0 0 none (not with eta) */
    double mass_damping; /* 1/s, >= 0: force -mass_damping m v on every node (m omega: its
                            rotation), mode n damped at ratio mass_damping / (2 omega_n) */
    /* Elastic-plastic layers (flexible links of rectangular section): */
    double yield;     /* Pa, >= 0: each layer's yield stress; 0 elastic */
    double hardening; /* Pa, >= 0: the plastic modulus of bilinear kinematic hardening */
    int strain;       /* rj_strain: the axial law (flexible links) */
    unsigned cookie;     /* set by rj_default_link_def; catches undefaulted structs */
} rj_link_def;

/* Joint definition. Defaults (rj_default_joint_def):
     body1 -1 (ground), node1 -1 (last node of body1), body2 0, node2 0 (its first node);
     ground_x 0 m, ground_y 0 m, ground_angle 0 rad;
     angle0 pi rad (straight), rate0 0 rad/s;
     table none (table_count 0); spring_k 0 N m/rad, spring_free_angle pi rad;
     has_forward 0, forward 0 rad; has_reverse 0, reverse 0 rad; lock 0;
     method RJ_METHOD_ADAPTIVE, release RJ_RELEASE_RC13, penalty_k 0 N m/rad (0 with
     RJ_METHOD_PENALTY is invalid), restitution 0;
     damping 0 N m s/rad, friction 0 N m; reference RJ_REF_TANGENT. */
#define RJ_TABLE_MAX 32
typedef struct rj_joint_def {
    int body1; /* link index, or -1 for ground */
    int node1; /* node of body1 carrying the pin; -1 = last node */
    int node2; /* node of body2 carrying the pin; 0 (default) its first, -1 its last (the
                  tangent reference; a flexible body2, or rigid links only) */
    int body2; /* link index; pinned at its node 0 */
    double ground_x, ground_y,
        ground_angle; /* m, m, rad: pin and reference direction when body1 = -1 */
    double angle0;    /* rad, initial rotary location (start of the running angle; any real) */
    double rate0;     /* rad/s, initial theta_dot */
    int table_count;  /* 0, or 2..RJ_TABLE_MAX points */
    double table_angle[RJ_TABLE_MAX];  /* rad, in [0, 2 pi]; segment i runs from point i to i+1
                                          when the angle rises; a fall starts a new run, so
                                          later segments may overlap earlier ones (Eq 4) */
    double table_torque[RJ_TABLE_MAX]; /* N m, resistive torque at table_angle */
    double spring_k; /* N m/rad, >= 0: torque -spring_k (theta_run - spring_free_angle) on body 2 */
    double spring_free_angle; /* rad, on the running angle (may lie outside [0, 2 pi)) */
    int has_forward;          /* forward limit enabled */
    double forward;           /* rad, theta_f in [0, 2 pi) */
    int has_reverse;          /* reverse limit enabled */
    double reverse;           /* rad, theta_r in [0, 2 pi) */
    int lock;                 /* bLock: latch for good at the first limit reached */
    int method;               /* rj_method */
    int release;              /* rj_release */
    double penalty_k;         /* N m/rad, RJ_METHOD_PENALTY */
    double restitution;       /* e in [0, 1], RJ_METHOD_MOMENTUM */
    double damping;           /* C, N m s/rad, >= 0 (Eq 27) */
    double friction;          /* T_f, N m, >= 0 */
    int reference;            /* rj_reference */
    unsigned cookie;
} rj_joint_def;

/* Solver definition. Defaults (rj_default_solver_def):
     dt 0 s (0 = use 0.9 x the stability bound); allow_unstable 0;
     energy_growth 10 (blow-up when total energy exceeds 10 x max(initial energy, energy put
     in by springs) + 1e-9 J); energy_every 1; gravity 0 0 m/s^2.
   gravity: a uniform acceleration on every mass of every link model (nodes, tip masses,
   rigid links and bodies); its potential -m g . x is the energy account rj_energy.gravity.
   energy_every K > 1: the kinetic, strain and spring energies (rj_state_energy) and the
   energy-based blow-up checks are taken K steps after the last time only, and on the step
   before each of rj_run's samples and its last step, so sampled histories and the state
   rj_run leaves are the same as with K = 1;
   between them rj_state_energy keeps the last ones (rj_state_energy_time says when). Positions,
   velocities and the work of damping, friction and limits are the same bits either way;
   flexible links' steps take about a quarter fewer instructions (sh bench/instr.sh), rigid
   ones skip the kinetic energy's M q' product; a blow-up is caught up to K - 1 steps later.
   in_place (rj_in_place, default AUTO): the step advances the nodes and elements where they
   are instead of into a second frame, which halves what a large model moves through the
   caches (1.36-1.49x faster at 2000 elements in make bench, docs/performance.md); it keeps a copy of the state
   at most 64 steps old and, when a step fails, takes the steps since it again, so a failed
   step leaves the state as it was either way, and the results are the same bits. It costs a
   third frame of memory, and a few copies per step that only pay from a few hundred nodes
   on: AUTO uses it from RJ_IN_PLACE_NODES nodes (400; a compile-time setting). Scenes with
   inextensible links never step in place (SHAKE reads every node's old position), nor do
   states given node forces (rj_state_node_forces: their kick reads a node's old velocity).
   In place the pin forces at t^n are known (from the pins' nodes the step keeps), the
   element loads are not (rj_element_loads). */
typedef struct rj_solver_def {
    double dt;            /* s, >= 0 */
    int allow_unstable;   /* accept dt above the bound */
    double energy_growth; /* > 1 */
    int energy_every;     /* 1 .. 1000 steps */
    int in_place;         /* rj_in_place */
    double gravity[2];    /* m/s^2, the acceleration of gravity (x, y); default 0 0 */
    unsigned cookie;
} rj_solver_def;

/* Applied load definition: a force and a moment on one node of one link, scaled in time
   by a table. Defaults (rj_default_load_def): link 0, node -1 (the link's last node);
   force 0 0 N; moment 0 N m; follower 0; no table (constant).
   force: N, in the global frame; with follower 1, in the node's own frame (x along the
   section's rotation, the link's axis where it starts straight; y normal to it), so that it
   turns with the node, as a thruster or a pressure on the tip would. moment: N m,
   counter-clockwise. table: table_count points (time, factor) with times strictly
   increasing; the load is factor(t) (force, moment), linear between the points and held at
   the end values outside them. Every load's work is rj_energy.work_applied. */
typedef struct rj_load_def {
    int link;                          /* link index */
    int node;                          /* node of the link, 0 .. elements; -1 = the last */
    double force[2];                   /* N (x, y) */
    double moment;                     /* N m */
    int follower;                      /* 0: global frame; 1: turns with the node */
    int table_count;                   /* 0 (constant), or 1..RJ_TABLE_MAX points */
    double table_time[RJ_TABLE_MAX];   /* s, strictly increasing */
    double table_factor[RJ_TABLE_MAX]; /* the load's scale at table_time */
    unsigned cookie;
} rj_load_def;

/* Actuator definition: a motor on one joint, acting on body 2 (body 1 takes the
   reaction), in every link model. A joint has at most one. Defaults
   (rj_default_actuator_def): joint 0, type RJ_ACTUATOR_TORQUE, torque 0 N m, no table;
   stall_torque 0 N m, no_load_speed 1 rad/s, no cutoff; kp 0 N m/rad, kd 0 N m s/rad,
   torque_max 0 N m (no bound), target pi rad.
   RJ_ACTUATOR_TORQUE: torque times the table's factor at t (time factor pairs, as a
     load's: linear between the points, held at the end values; none: 1).
   RJ_ACTUATOR_DC: a DC motor's line, stall_torque (1 - rate / no_load_speed) for the
     joint's rate, within +-|stall_torque|; both of one sign, the direction it drives.
     With a cutoff (an angle in [0, 2 pi), as a limit's) it is off while the joint's angle
     is at or past the cutoff's first crossing in that direction from angle0: an
     end-of-travel switch.
   RJ_ACTUATOR_SERVO: kp (target - theta_run) - kd rate, within +-torque_max when it is
     > 0; target on the running angle (as spring_free_angle), plus a profile (below) of
     the time since start when one is given (the default, a ramp of 0, holds it).
   RJ_ACTUATOR_PRESCRIBED: the joint's angle follows a profile exactly (to round-off): held
     at angle0 until start (s), then angle0 + the profile of (t - start): RJ_PROFILE_RAMP
     profile_value (rad/s) times it; RJ_PROFILE_CYCLOIDAL rest to rest through
     profile_value (rad) in profile_time (s); RJ_PROFILE_SPINUP to profile_value (rad/s)
     in profile_time TS (s), (OMEGA/TS) [t^2/2 + (TS/2 pi)^2 (cos(2 pi t/TS) - 1)] for
     t < TS, then OMEGA (t - TS/2); RJ_PROFILE_TABLE the actuator's table read as times
     and angles (rad), the cubic spline through them with rest at both ends (rate and
     acceleration continuous in between), held at the first angle before its first time
     and at the last after. The torque it takes is RJ_TORQUE_DRIVE (the impulse
     that keeps the joint on its profile, over the step). A prescribed joint has no limits
     or lock (refused). rj_settle holds it at its start.
   Every type may have a rotor: rotor_inertia (kg m^2) behind a gear of ratio N, whose
   reflected inertia N^2 rotor_inertia acts on the joint's relative rotation (in the mass,
   the kinetic energy and the stability bound: a damper's rate over it is what keeps a
   servo's kd on a flexible arm's light pin well behaved). A rotor needs the tangent
   reference and, in a scene with flexible links, two flexible bodies (or ground) and a
   pin node of its own.
   The rate is the one joint damping reads (Eq 27), so kd and a DC motor's slope
   stall_torque / no_load_speed are dampers and kp a spring to the stability bound. The
   torque is RJ_TORQUE_DRIVE; its work is rj_energy.work_drive. */
typedef enum rj_actuator_type {
    RJ_ACTUATOR_TORQUE = 0,
    RJ_ACTUATOR_DC,
    RJ_ACTUATOR_SERVO,
    RJ_ACTUATOR_PRESCRIBED
} rj_actuator_type;
typedef enum rj_profile {
    RJ_PROFILE_RAMP = 0,
    RJ_PROFILE_CYCLOIDAL,
    RJ_PROFILE_SPINUP,
    RJ_PROFILE_TABLE
} rj_profile;
typedef struct rj_actuator_def {
    int joint;                         /* joint index */
    int type;                          /* rj_actuator_type */
    double torque;                     /* N m (TORQUE) */
    int table_count;                   /* 0, or 1..RJ_TABLE_MAX points (TORQUE; a profile
                                          table: 2..RJ_TABLE_MAX) */
    double table_time[RJ_TABLE_MAX];   /* s, strictly increasing */
    double table_factor[RJ_TABLE_MAX]; /* the torque's scale; a profile table's angle, rad */
    double stall_torque;               /* N m (DC) */
    double no_load_speed;              /* rad/s, not 0, the sign of stall_torque (DC) */
    int has_cutoff;                    /* the cutoff is on (DC) */
    double cutoff;                     /* rad, in [0, 2 pi) (DC) */
    double kp;                         /* N m/rad, >= 0 (SERVO) */
    double kd;                         /* N m s/rad, >= 0 (SERVO) */
    double torque_max;                 /* N m, >= 0, 0: no bound (SERVO) */
    double target;                     /* rad, on the running angle (SERVO) */
    int profile;                       /* rj_profile (PRESCRIBED) */
    double profile_value;              /* rad/s (RAMP, SPINUP) or rad (CYCLOIDAL) */
    double profile_time;               /* s, > 0 (CYCLOIDAL: duration, SPINUP: TS) */
    double start;                      /* s, when the profile begins (PRESCRIBED) */
    double rotor_inertia;              /* kg m^2, >= 0: the motor's rotor */
    double gear_ratio;                 /* N, the rotor turns N times the joint; not 0 */
    unsigned cookie;
} rj_actuator_def;

/* Coupling definition: a cable loop tying two joints (a closed cable loop, CCL, that
   makes every panel of an array open in step). The elastic cable holds
   e = (theta_b - angle0_b) - ratio (theta_a - angle0_a) - offset at 0, on the running
   angles' changes from their starts (so offset 0 is a cable slack-free at the start),
   with the torque -stiffness e - damping de/dt on joint b and ratio times its opposite on
   joint a (the virtual work of a cable over pulleys of ratio). Defaults
   (rj_default_coupling_def): joint_a 0, joint_b 1, ratio 1, offset 0 rad, stiffness
   0 N m/rad, damping 0 N m s/rad. Its torques are reported in the two joints' spring and
   damping components (RJ_TORQUE_SPRING, RJ_TORQUE_DAMPING); its energy is in
   rj_energy.spring, its damping's work in lost_damping; the stability bound counts both.
   exact = 1: a constraint instead of a cable: e is held at 0 to round-off (each step's
   impulse on the two joints, reported over the step in their spring components; its
   share of the kinetic energy's discrete form is counted with the limits', lost_limit);
   stiffness and damping must then be 0. Exact couplings need the tangent reference. They
   are constraint rows, solved together with the step's prescribed joints (and, with
   rigid links only, its locked joints and plastic contacts); with flexible links before
   the latches' jumps, with rigid links after the single joints' impulses. */
typedef struct rj_coupling_def {
    int joint_a, joint_b; /* joint indices, two different joints */
    double ratio;         /* theta_b follows ratio theta_a; within +-1e6 */
    double offset;        /* rad, within +-1e6 */
    double stiffness;     /* N m/rad, >= 0: the cable loop's torsional stiffness at joint b */
    double damping;       /* N m s/rad, >= 0 */
    int exact;            /* 1: a constraint (no stiffness, no damping) */
    unsigned cookie;
} rj_coupling_def;

/* A whole scene. The arrays are read during rj_model_create only. loads (load_count of
   them) may be NULL when load_count is 0. */
typedef struct rj_scene_def {
    const rj_link_def *links;
    int link_count;
    const rj_joint_def *joints;
    int joint_count;
    rj_solver_def solver;
    const rj_load_def *loads;
    int load_count;
    const rj_actuator_def *actuators; /* may be NULL when actuator_count is 0 */
    int actuator_count;
    const rj_coupling_def *couplings; /* may be NULL when coupling_count is 0 */
    int coupling_count;
} rj_scene_def;

/* Energy accounts, J. total = kinetic + strain + spring; balance = total + lost - initial. */
typedef struct rj_energy {
    double kinetic, strain, spring; /* spring: torsion springs and tables */
    double gravity;                 /* the potential of gravity, -sum m g . x */
    double work_applied; /* J done on the model by the applied loads and caller's inputs so far */
    double work_drive;   /* J done on the model by the joints' actuators so far */
    double lost_damping, lost_friction, lost_limit;
    double lost_structural; /* J dissipated by the links' eta and mass_damping so far */
    double lost_plastic;    /* J of plastic work in the links' layers so far */
    double total, balance;
} rj_energy;

/* The accounts of rj_energy by number, in rj run's order (its columns E_kin ... W_limit;
   the balance and the total follow from them): how many, account k's column name, and
   its value in e. */
RJDEF int rj_energy_account_count(void);
RJDEF const char *rj_energy_account_name(int k);
RJDEF double rj_energy_account(const rj_energy *e, int k);

typedef struct rj_model rj_model;
typedef struct rj_state rj_state;
/* Whether account k can move in model m (W_drive needs actuators): rj run writes only
   those. */
RJDEF int rj_energy_account_in(const rj_model *m, int k);
/* The model's actuators (rj_scene_def.actuator_count). */
RJDEF int rj_model_actuator_count(const rj_model *m);

/* Degree/radian helpers. */
RJDEF double rj_rad(double deg);
RJDEF double rj_deg(double rad);

/* Definition structs with every default filled in. */
RJDEF rj_link_def rj_default_link_def(void);
RJDEF rj_joint_def rj_default_joint_def(void);
RJDEF rj_solver_def rj_default_solver_def(void);
RJDEF rj_load_def rj_default_load_def(void);
RJDEF rj_actuator_def rj_default_actuator_def(void);
RJDEF rj_coupling_def rj_default_coupling_def(void);
RJDEF rj_scene_def rj_default_scene_def(void);
/* Result code as text. */
RJDEF const char *rj_result_str(rj_result r);

/* Validates the scene and builds a model. rj_model_size checks every field and the totals
   and gives the bytes rj_model_init needs (0 when the scene is invalid, with err filled);
   rj_model_init builds into the caller's block (aligned to 16), checking the joint graph
   too (one joint per body2, no loops; it needs the block's scratch for that, so that
   every check is linear in the scene) and refusing a model with no usable step;
   rj_model_create allocates one block with RJ_MALLOC. */
RJDEF size_t rj_model_size(const rj_scene_def *scene, rj_error *err);
RJDEF rj_result rj_model_init(const rj_scene_def *scene, void *mem, size_t size, rj_model **out,
                              rj_error *err);
/* Closes the scene's loops (rj_model_create refuses a loop that does not close where the
   tree of first joints places the links): moves the angle0 of the joints on each loop,
   all but the loop's first joint (its input: a four-bar's crank keeps its angle), by the
   least change (in the sum of their squares) that closes every loop to 1e-13 of the
   longest link, then sets each joint that closes a loop to the angle0 the geometry gives
   it. joints: the caller's copy of scene->joints (joint_count entries), corrected in
   place; scene->joints is not read. RJ_ERR_INVALID, err naming the loop's joint and how
   far apart its pins stay at best, when a loop cannot close; or the scene's first invalid
   field. Allocates its working arrays (RJ_MALLOC) and frees them. */
RJDEF rj_result rj_scene_assemble(const rj_scene_def *scene, rj_joint_def *joints,
                                  rj_error *err);
/* The scene's mobility as rigid bars at its start: the tree's freedom (one a link hanging
   from a joint, three a free root link, one a pinned root) less the rank its loops'
   constraints really have there (*rank: the rank of the loops' pin gaps over the joint
   angles, by elimination, 1e-9 of the largest entry counting as 0). A four-bar: 1, rank
   2; at a singular position the rank drops and the mobility grows. Allocates its working
   arrays (RJ_MALLOC) and frees them. */
RJDEF rj_result rj_scene_mobility(const rj_scene_def *scene, int *mobility, int *rank,
                                  rj_error *err);
RJDEF rj_result rj_model_create(const rj_scene_def *scene, rj_model **out, rj_error *err,
                                void *alloc_ctx);
RJDEF void rj_model_destroy(rj_model *m, void *alloc_ctx);

/* States: size query, init into caller memory, or allocate; reset to the initial conditions. */
RJDEF size_t rj_state_size(const rj_model *m);
RJDEF rj_result rj_state_init(const rj_model *m, void *mem, size_t size, rj_state **out);
RJDEF rj_result rj_state_create(const rj_model *m, rj_state **out, void *alloc_ctx);
RJDEF void rj_state_destroy(rj_state *s, void *alloc_ctx);
RJDEF void rj_state_reset(const rj_model *m, rj_state *s);
RJDEF rj_result rj_state_copy(const rj_model *m, rj_state *dst, const rj_state *src);

/* One central-difference step of the model's dt. Never allocates, prints or reads. */
RJDEF rj_result rj_step(const rj_model *m, rj_state *s);
/* Steps until time >= t_end (to half a step); calls sample(m, s, user) at the start and at
   the step nearest to every multiple of sample_dt (every step when sample_dt is 0). A
   nonzero return from sample stops the run. */
typedef int (*rj_sample_fn)(const rj_model *m, const rj_state *s, void *user);
RJDEF rj_result rj_run(const rj_model *m, rj_state *s, double t_end, double sample_dt,
                       rj_sample_fn sample, void *user);
/* rj_run, and each_step(m, s, user) after every step besides: for what a caller watches
   at every step (joint flags, pin forces, peaks) without asking for the energy accounts
   there, which solver.energy_every then takes only every K-th step and at the samples
   (rj_run with sample_dt 0 takes them at every step). Samples at the start and at the
   steps nearest to every multiple of sample_dt after it (rj_run's from time 0). A nonzero
   return from either stops the run; at a sample step each_step is called first. */
RJDEF rj_result rj_run_watched(const rj_model *m, rj_state *s, double t_end, double sample_dt,
                               rj_sample_fn sample, rj_sample_fn each_step, void *user);
/* Static equilibrium under the present loads (gravity, springs, limits) by dynamic
   relaxation with kinetic damping: steps on, and at each peak of the kinetic energy sets
   every velocity to zero, until a peak's kinetic energy is below tol times the potential
   energy that moved (strain, springs and gravity's, since the start; tol in (0, 1), 1e-12
   is tight), or below the energy of round-off. A scene already at rest settles at once.
   Time runs while it settles, so a load's table acts as it would in a run (a ramp brings a
   load on gently); it settles only past the last point of every load's table, where the
   loads stay constant, and the settled state keeps that time: the run goes on under the
   loads it settled under. The step count,
   energy accounts and joint events restart from zero, velocities zero, joint flags and
   running angles kept (rj_state_steps counts the steps since the last start from rest).
   Returns RJ_OK; RJ_ERR_INVALID for bad arguments; RJ_ERR_NOT_CONVERGED (the state at
   max_steps kept, its velocities zeroed) when it has not settled within max_steps; a step's
   error as rj_step. */
RJDEF rj_result rj_settle(const rj_model *m, rj_state *s, double tol, long max_steps);
/* rj_settle with progress(m, s, user) called every 4096 steps (NULL: never); a nonzero
   return stops the settling with RJ_ERR_NOT_CONVERGED, the velocities zeroed. */
RJDEF rj_result rj_settle_ex(const rj_model *m, rj_state *s, double tol, long max_steps,
                             rj_sample_fn progress, void *user);
/* Last step error text (empty when none). */
RJDEF const char *rj_state_error(const rj_state *s);
/* The caller's torques on the joints, one per joint (N m on body 2 and the opposite on body
   1, counter-clockwise positive), applied by every step until changed, as a controller or a
   motor would; zero after rj_state_create and rj_state_reset; copied by rj_state_copy and
   saved in checkpoints. Their work is rj_energy.work_applied. The first call switches them
   on: a state that never asks pays nothing per step. */
RJDEF double *rj_state_joint_torques(const rj_model *m, rj_state *s);
/* The caller's forces and moments on the nodes, three per node in the scene's node order
   (fx N, fy N, moment N m, in the global frame; link l's node k is entry
   3 (first node of l + k), rj_model_node_index), applied by every step until changed
   (MuJoCo's xfrc_applied); zero after rj_state_create and rj_state_reset; copied by
   rj_state_copy and saved in checkpoints. Their work is rj_energy.work_applied. The first
   call switches them on: a state that never asks pays nothing per step (one that does
   steps double-buffered: the kick they give a node reads its old velocity). */
RJDEF double *rj_state_node_forces(const rj_model *m, rj_state *s);
/* Warnings so far (a contact caught more than 0.05 rad past its limit, or past the whole
   limited range: tunnelling) and the latest warning's text. */
RJDEF long rj_state_warning_count(const rj_state *s);
RJDEF const char *rj_state_warning(const rj_state *s);

/* Model queries. */
/* Warnings about the definitions, found while building (a limit the joint starts past,
   or that its spring never drives it to): their number, and their text, one per line
   ("" when none). The model is built and usable either way. */
RJDEF int rj_model_warning_count(const rj_model *m);
RJDEF const char *rj_model_warnings(const rj_model *m);
RJDEF double rj_model_dt(const rj_model *m);        /* s, step in use */
RJDEF double rj_model_dt_bound(const rj_model *m);  /* s, 0.98 x 2/omega_max of the linearised model */
RJDEF double rj_model_omega_max(const rj_model *m); /* rad/s */
RJDEF int rj_model_link_count(const rj_model *m);
RJDEF int rj_model_joint_count(const rj_model *m);
RJDEF int rj_model_node_count(const rj_model *m);
/* Whether the step advances the nodes where they are (solver.in_place: AUTO from
   RJ_IN_PLACE_NODES nodes on, never with inextensible links); 1 or 0. */
RJDEF int rj_model_in_place(const rj_model *m);
RJDEF const rj_link_def *rj_model_link_def(const rj_model *m, int link);
RJDEF const rj_joint_def *rj_model_joint_def(const rj_model *m, int joint);
RJDEF int rj_link_node_count(const rj_model *m, int link); /* elements + 1 */
/* Node k of link l in the scene's node order (-1 for the last), -1 when out of range. */
RJDEF int rj_model_node_index(const rj_model *m, int link, int node);
RJDEF int rj_model_load_count(const rj_model *m);
RJDEF const rj_load_def *rj_model_load_def(const rj_model *m, int load);
RJDEF const rj_actuator_def *rj_model_actuator_def(const rj_model *m, int actuator);
RJDEF int rj_model_coupling_count(const rj_model *m);
RJDEF const rj_coupling_def *rj_model_coupling_def(const rj_model *m, int coupling);
/* Lumped mass (kg) and rotary inertia (kg m^2) of a node, tip mass included (a rigid
   link's node in a mixed scene: 0 and its body's inertia, see rj_fidelity). */
RJDEF void rj_node_mass(const rj_model *m, int link, int node, double *mass, double *rinertia);
RJDEF double rj_link_EA(const rj_model *m, int link);
RJDEF double rj_link_EI(const rj_model *m, int link);
/* Paper's bounds: Eq 28 dt = l / c of the shortest element of the joint's two links;
   Eq 29 min(Eq 28, sqrt(rho I l / K)); Eq 31 K_max = 0.81 rho I l / dt^2 (I second moment,
   rho, l of the smaller of the two links; ground counts as infinitely large). */
RJDEF double rj_model_dt_eq28(const rj_model *m);
RJDEF double rj_joint_dt_eq29(const rj_model *m, int joint, double K);
RJDEF double rj_joint_kmax_eq31(const rj_model *m, int joint, double dt);
/* Joint inertias I1, I2 (kg m^2) of the reference segments, and the stiffness the joint
   uses at its limits with the model's dt (K_AP for adaptive, penalty_k for penalty). */
RJDEF void rj_joint_inertias(const rj_model *m, int joint, double *I1, double *I2);
RJDEF double rj_joint_stiffness(const rj_model *m, int joint);

/* The linearised model at the initial configuration, for modal analysis and tests: out =
   M^-1/2 K M^-1/2 u over 3 x node_count DOFs (x, y, phi per node; fixed DOFs and all but
   the first node of a pin group give 0). Its eigenvalues are omega^2. work holds
   rj_model_work_size(m) doubles. */
RJDEF size_t rj_model_work_size(const rj_model *m);
RJDEF void rj_model_apply_stiffness(const rj_model *m, const double *u, double *out, double *work);

/* State queries. */
RJDEF double rj_state_time(const rj_state *s);
/* Steps since the state last started from rest: rj_state_create, rj_state_reset, rj_settle
   (time, rj_state_time, runs on through rj_settle). */
RJDEF long rj_state_steps(const rj_state *s);
RJDEF void rj_node_position(const rj_model *m, const rj_state *s, int link, int node, double xy[2]);
RJDEF void rj_node_velocity(const rj_model *m, const rj_state *s, int link, int node, double v[2]);
RJDEF double rj_node_rotation(const rj_model *m, const rj_state *s, int link, int node);
RJDEF double rj_node_rate(const rj_model *m, const rj_state *s, int link, int node); /* rad/s */
RJDEF void rj_joint_position(const rj_model *m, const rj_state *s, int joint, double xy[2]);
RJDEF double rj_joint_theta(const rj_model *m, const rj_state *s, int joint); /* [0, 2 pi) */
RJDEF double rj_joint_theta_running(const rj_model *m, const rj_state *s,
                                    int joint);                              /* unwrapped */
RJDEF double rj_joint_rate(const rj_model *m, const rj_state *s, int joint); /* rad/s */
RJDEF int rj_joint_flag(const rj_model *m, const rj_state *s, int joint);    /* rj_flag */
RJDEF double rj_joint_torque(const rj_model *m, const rj_state *s, int joint, int component);
RJDEF double rj_joint_penetration(const rj_model *m, const rj_state *s, int joint); /* rad, Eq 19 */
/* N m s: the angular impulse on body 2 that a velocity-level limit response (momentum,
   forced, energy: Eqs 23-26) applied in the last step, 0 in a step without one. Those
   methods latch by a jump in the rates, so their RJ_TORQUE_LIMIT is 0; while a joint is
   held at its limit, impulse / dt is the mean constraint torque over the step, the latch
   load. Penalty and adaptive limits report theirs as RJ_TORQUE_LIMIT instead (the torque
   of a spring whose stiffness is a numerical choice: see docs/validation.md). */
RJDEF double rj_joint_latch_impulse(const rj_model *m, const rj_state *s, int joint);
/* The force body 1 exerts on body 2 at the joint's pin, N, global x and y, recomputed
   from the state (the step pays nothing).
   - Rigid links without loops: the links below the joint's m (a_c - g) less the loads
     and the caller's forces on them, with the rates at n + 1/2 and the step's
     accelerations (first order in dt).
   - Rigid links with loops: a loop joint's from its two rows' impulses over the last
     step; the others as without loops, the loops' forces among those from outside, at
     the step's configuration q^n and rates (each bar's moment balance then holds to
     round-off: build/test_loops). Not before a step.
   - Flexible links: body 2's pin node's m a - m g less its link's element forces,
     loads and the caller's force on it, and the force couples chord-referenced joints'
     torques put on it (from the torques the step recorded, on the chords at n), at
     t^n, a step before the state's time (a from the rates at n - 1/2 and n + 1/2);
     where body 2 is a rigid body of a mixed scene, the same on body 1's flexible node,
     reversed.
   - Scenes with inextensible links, and pins between two rigid bodies or a rigid body
     and the ground in mixed scenes: Newton's second law for the links below the joint,
     their nodes' and bodies' m a - m g less loads and the caller's forces (their
     elements', lengths' and pins' forces cancel inside them), and less the forces of
     the loop joints that tie them to the rest of the scene, at t^n.
   - A loop joint of those scenes: its pin node's balance as for flexible links, less
     what the node's own link's lengths put on it over the step (SHAKE's pushes, which
     the step records); between two rigid bodies, the pushes of the pin between them
     over the step (recorded too); pinning a rigid body to the ground, the body's m a -
     m g less its loads and its other pins' forces on it (each node it carries: that
     node's balance; its pins to other bodies and the carried links' lengths: their
     recorded pushes), at t^n. Each pin's two sides agree to the round-off of positions
     over dt^2 (build/test_loops).
   - After an in-place step (solver.in_place): the same balances from what the step
     keeps of the pins' nodes, their values at n and the forces it moved them with; a
     rigid body's pin to the ground from the body's balance, as for a loop above. Equal
     to the double-buffered step's to round-off (build/test_loops).
   RJ_ERR_INVALID, force 0, not yet: a loop joint with a chord reference on a flexible
   pin node, and the joints whose links such a loop ties to the rest; a held body among
   the links below a joint, or pinned to the ground by a loop, or one a loop pins to the
   ground whose carried node takes a chord reference's forces or is pinned to the ground
   too; a pin node that is a chord-referenced joint's far node (its K or L, which
   latches move by jumps no record keeps), before a step (or after a failed one,
   a checkpoint's load, rj_settle: the state a step before is needed). */
RJDEF rj_result rj_joint_pin_force(const rj_model *m, const rj_state *s, int joint,
                                   double force[2]);
/* Every joint's pin force at once (2 per joint in forces, as rj_joint_pin_force; NaN
   where there is none yet): in a scene of rigid links in time linear in the links, and
   with inextensible links or rigid bodies in the nodes and joints (one pass up the joint
   tree sums each subtree once: the joint by joint query's sums in another order, equal
   to round-off), where the joint by joint query costs that each (RJ_MALLOC's scratch,
   RJ_ERR_NOMEM without it). */
RJDEF rj_result rj_joint_pin_forces(const rj_model *m, const rj_state *s, double *forces);
/* Element element of a flexible link at t^n (a step before the state's time, as the
   step took it), recomputed from the state (implicit Kelvin-Voigt damping's viscous part
   as the step kept it): loads[0] the axial force N (N, tension
   positive), [1] the shear V (N), [2] and [3] the bending moment at its first and its
   second node (N m), each the force or moment the part of the link beyond the section
   exerts on the part before it, along the chord, across it (counter-clockwise of the
   chord) and counter-clockwise; [4] the largest outer-fibre stress |N| / A + |M| h / 2I
   (Pa; NaN for a general section, whose fibre distance the model does not know; for
   yielding layers the largest |stress| at a layer's mid-depth in its two sections, where
   the layers yield: the outer layers' mid-depth, not the outer fibre). RJ_ERR_INVALID, loads 0: a rigid or inextensible link,
   after an in-place step (it keeps only the pins' nodes at n: solver.in_place off gives
   these loads, the same bits), before a step, an element out of range. */
RJDEF rj_result rj_element_loads(const rj_model *m, const rj_state *s, int link, int element,
                                 double loads[5]);
/* Peaks over a run: rj_state_track_peaks(m, s, 1) makes the steps after it track each
   joint's largest |pin force| (rj_joint_pin_force) and each flexible link's largest
   |bending moment| and stress (rj_element_loads: every element's ends), with when and
   where. They are taken on the steps that take the energy accounts: exact when
   solver.energy_every is 1 (the default), every K-th step otherwise. Off after
   rj_state_create and rj_state_reset; a settled state (rj_settle) starts them again;
   rj_state_copy and checkpoints carry them. A model that steps in place tracks the pin
   forces alone (no element loads at t^n there: the links' peaks stay -1). Tracking
   costs the steps about what the queries cost; off, nothing. */
typedef struct rj_peak {
    double value;    /* N or N m or Pa; -1: none yet (or none known: a rigid link's moment) */
    double time;     /* s, t^n of the step the loads are of */
    int element;     /* the link's element (-1 for a joint) */
    int end;         /* a moment's: 0 the element's first node, 1 its second (-1 else) */
} rj_peak;
RJDEF rj_result rj_state_track_peaks(const rj_model *m, rj_state *s, int on);
RJDEF rj_peak rj_joint_peak_pin_force(const rj_model *m, const rj_state *s, int joint);
RJDEF rj_peak rj_link_peak_moment(const rj_model *m, const rj_state *s, int link);
RJDEF rj_peak rj_link_peak_stress(const rj_model *m, const rj_state *s, int link);
/* A yielding link's plastic strain in layer `layer` (0 the outermost on the side of the
   link's local -y, its right looking from node 0 along it) of element `element`'s section
   `section`
   (0, 1: its Gauss points, at 0.211 and 0.789 of its length), as the last step left it;
   0 for an elastic link, NaN out of range. */
RJDEF double rj_element_plastic_strain(const rj_model *m, const rj_state *s, int link,
                                       int element, int section, int layer);
RJDEF double rj_joint_event_time(const rj_model *m, const rj_state *s,
                                 int joint); /* first limit contact or lock, s; -1 if none */
RJDEF double rj_joint_release_time(const rj_model *m, const rj_state *s,
                                   int joint); /* latest release from a limit, s; -1 if none */
/* The first time the joint's two links passed through each other (its angle turned
   through a multiple of 360 deg, where they lie over each other; links do not contact
   each other), s; -1 if never, and always -1 for a joint to ground. Also a warning. */
RJDEF double rj_joint_overlap_time(const rj_model *m, const rj_state *s, int joint);
RJDEF double rj_joint_peak_penetration(const rj_model *m, const rj_state *s,
                                       int joint); /* rad, largest |penetration| so far */
RJDEF double rj_joint_contact_penetration(
    const rj_model *m, const rj_state *s,
    int joint); /* rad, penetration when the latest contact was detected */
/* Energy accounts at time rj_state_energy_time(s) = time - dt (with solver.energy_every
   K > 1: of the last step that took them, at most K steps back; rj_run takes them before
   every sample and at its end): the kinetic energy of the central-difference pair is
   1/2 m v^{n-1/2}.v^{n+1/2}, which closes the balance exactly for linear systems. */
RJDEF void rj_state_energy(const rj_model *m, const rj_state *s, rj_energy *e);
RJDEF double rj_state_energy_time(const rj_state *s);

/* Checkpoints: a state to and from bytes. rj_state_save returns the bytes needed when buf
   is NULL or too small (and writes nothing then). rj_state_load rejects a truncated,
   corrupted or foreign buffer and leaves the state unchanged. */
RJDEF size_t rj_state_save(const rj_model *m, const rj_state *s, void *buf, size_t size);
RJDEF rj_result rj_state_load(const rj_model *m, rj_state *s, const void *buf, size_t size,
                              rj_error *err);

/* The element's pure equations, exposed for tests and for users' own codes. */
RJDEF double rj_rotary_location(double ax, double ay, double bx,
                                double by); /* Eqs 1-3, [0, 2 pi) */
RJDEF double rj_table_torque(const double *angle, const double *torque, int count,
                             double theta);                        /* Eq 4 */
RJDEF int rj_blimit(double theta, double forward, double reverse); /* Eq 6 */
RJDEF int rj_flag_next(int prev, int beyond_forward, int beyond_reverse, double rate, int lock,
                       int release);                         /* Eqs 7-13 */
RJDEF double rj_k_adaptive(double I1, double I2, double dt); /* Eq 21 */
RJDEF void rj_momentum_balance(double I1, double I2, double e, double *w1,
                               double *w2);                                 /* Eqs 23-24 */
RJDEF void rj_energy_balance(double I1, double I2, double *w1, double *w2); /* Eqs 25-26 */

/* ------------------------------------------------------------------ scene files
   A small, strict, line-oriented text format for whole scenes (docs/scene-format.md). Define
   RJ_NO_SCENE_FILES to compile this part out. */
#ifndef RJ_NO_SCENE_FILES
#define RJ_SCENE_MAX_LINKS     256
#define RJ_SCENE_MAX_JOINTS    256
#define RJ_SCENE_MAX_LOADS     256
#define RJ_SCENE_MAX_ACTUATORS 256
#define RJ_SCENE_MAX_COUPLINGS 256
#define RJ_SCENE_MAX_MATERIALS 64
#define RJ_SCENE_MAX_SECTIONS  64
#define RJ_SCENE_MAX_LINE      1024 /* characters per line, line end excluded */
#define RJ_SCENE_MAX_TOKENS    512 /* tokens per statement (a statement may continue after a ',') */
#define RJ_SCENE_MAX_SETS      64  /* changes given to rj_scene_parse_set */
#define RJ_SCENE_NAME_MAX      32  /* names are 1..31 characters */
#define RJ_SCENE_MAX_BYTES     (64u << 20) /* input size */
#define RJ_SCENE_TITLE_MAX     128         /* a title is 0..127 bytes */

/* A place in the file: 1-based line and column (column counts bytes); line 0 = nowhere. */
typedef struct rj_scene_pos {
    int line, col;
} rj_scene_pos;

/* A parsed scene. Everything lives in one block from RJ_MALLOC; rj_scene_file_free
   releases it. links[i] and link_names[i] are the i-th link section in order of
   appearance, likewise for joints and loads; but a link with fidelity = pieces is there
   as its rigid pieces (NAME, NAME_p1 ..), and its bending springs (NAME_b1 ..) are among
   the joints (docs/scene-format.md, "Links cut into pieces"). The fields ending in _ are
   private. */
typedef struct rj_scene_file {
    rj_link_def *links;
    int link_count;
    rj_joint_def *joints;
    int joint_count;
    rj_solver_def solver;
    char (*link_names)[RJ_SCENE_NAME_MAX];
    char (*joint_names)[RJ_SCENE_NAME_MAX];
    char filename[96];                    /* as given to rj_scene_parse (truncated) */
    char title[RJ_SCENE_TITLE_MAX];       /* title = "..." at the top of the file; "" when none */
    rj_scene_pos *link_pos_, *joint_pos_; /* per item: header, then the value of each key */
    rj_scene_pos
        solver_pos_[7]; /* header, then dt, allow_unstable, energy_growth, energy_every, in_place,
                           gravity */
    void *block_, *alloc_ctx_;
    rj_load_def *loads;
    int load_count;
    char (*load_names)[RJ_SCENE_NAME_MAX];
    rj_scene_pos *load_pos_;
    rj_actuator_def *actuators;
    int actuator_count;
    char (*actuator_names)[RJ_SCENE_NAME_MAX];
    rj_scene_pos *actuator_pos_;
    rj_coupling_def *couplings;
    int coupling_count;
    char (*coupling_names)[RJ_SCENE_NAME_MAX];
    rj_scene_pos *coupling_pos_;
} rj_scene_file;

/* Parses len bytes of text (need not be NUL-terminated) named filename in messages
   (NULL: "<input>"). On success fills *out. On failure returns RJ_ERR_PARSE (syntax, a value
   out of range, an unknown name, a limit exceeded) or the code of rj_model_create's
   validation (RJ_ERR_INVALID) for a scene that parses but that the model rejects, with
   err->msg "file:line:col: message" (the line and column of the offending text), err->field
   the key (or the model's field), err->value the offending number (NaN when not numeric);
   nothing is left allocated and *out is zeroed (rj_scene_file_free on it is a no-op).
   alloc_ctx is passed to RJ_MALLOC / RJ_FREE (rj_scene_parse passes NULL). */
RJDEF rj_result rj_scene_parse(const char *text, size_t len, const char *filename,
                               rj_scene_file *out, rj_error *err);
RJDEF rj_result rj_scene_parse_ex(const char *text, size_t len, const char *filename,
                                  rj_scene_file *out, rj_error *err, void *alloc_ctx);
/* Reads the file at path (at most RJ_SCENE_MAX_BYTES) and parses it. A file that cannot
   be opened or read gives RJ_ERR_PARSE, err->field "path", err->value errno and err->msg
   "path: cannot open the file for reading: " and the system's reason (strerror). */
RJDEF rj_result rj_scene_load(const char *path, rj_scene_file *out, rj_error *err);
/* The same with changes on top of the text, each as if written last in its section
   (a key the file sets is set again): sets[k] is "KIND.NAME.KEY=VALUE" (KIND material,
   section, link, joint, load, actuator or coupling; NAME the item's name in the file)
   or "solver.KEY=VALUE", the value as a file writes it ("link.arm1.E=69e9",
   "joint.j2.forward=181 deg", "solver.gravity=0 -9.81"). A material's change reaches
   the links that name it. Each is read, checked and refused as a line of the file would
   be, its messages "--set:K:COL:" for change K; a change naming no item of the file is
   refused, naming it. At most RJ_SCENE_MAX_SETS. */
RJDEF rj_result rj_scene_parse_set(const char *text, size_t len, const char *filename,
                                   const char *const *sets, int nsets, rj_scene_file *out,
                                   rj_error *err);
RJDEF rj_result rj_scene_load_set(const char *path, const char *const *sets, int nsets,
                                  rj_scene_file *out, rj_error *err);
/* A scene definition pointing into f (valid until rj_scene_file_free). */
RJDEF rj_scene_def rj_scene_file_def(const rj_scene_file *f);
RJDEF void rj_scene_file_free(rj_scene_file *f);
/* Index of the link or joint with that name, -1 if none. */
RJDEF int rj_scene_link_index(const rj_scene_file *f, const char *name);
RJDEF int rj_scene_joint_index(const rj_scene_file *f, const char *name);
/* For an error from rj_model_create (or rj_model_size/init) on rj_scene_file_def(f): puts
   "file:line:col: " before err->msg, pointing at the key its err->field names (or at the
   link's or joint's section line), and the item's name after it. Call once per error;
   an error whose field names no item gets "file: " only. */
RJDEF void rj_scene_file_locate(const rj_scene_file *f, rj_error *err);
/* Writes the scene as scene-file text into buf (size bytes, always NUL-terminated when
   size > 0) and returns the length of the whole text (excluding the NUL), like snprintf:
   call with size 0 to learn the size. link_names / joint_names may be NULL ("link0", ...,
   "joint0", ...); given names must be valid (1..31 of [A-Za-z0-9_.-], not starting with a
   digit, '.' or '-'; a link not named "ground") and unique. Returns 0 (and writes nothing)
   for an unwritable scene: counts outside 1..RJ_SCENE_MAX_LINKS / 0..RJ_SCENE_MAX_JOINTS /
   0..RJ_SCENE_MAX_LOADS, a body or load index out of range, a non-finite number in a field
   it writes, a bad name. Loads are written as load0, load1, ... Reading
   the text back with rj_scene_parse gives every field the model uses bit for bit, -0.0
   included (numbers are written in their shortest round-trip form, angles in deg when that
   round-trips, else in rad), so any scene rj_model_create accepts within those counts
   builds the same model from the text. Fields the model ignores (width/layers of a general
   section, area/inertia of a rectangular one, the value of a disabled limit, table points
   past table_count, node1 and ground_* where they do not apply) are not written, so they
   may hold anything (NaN too), and come back as their defaults. */
RJDEF size_t rj_scene_write(const rj_scene_def *scene, const char *const *link_names,
                            const char *const *joint_names, char *buf, size_t size);
/* rj_scene_write with a title line (title = "...") after the header comment, which
   rj_scene_parse reads back into rj_scene_file.title. title NULL or "" writes none (that is
   rj_scene_write). Returns 0 (and writes nothing) also for a title that a file cannot hold:
   RJ_SCENE_TITLE_MAX bytes or more, a '"', or a control byte (tab included). */
RJDEF size_t rj_scene_write_ex(const rj_scene_def *scene, const char *const *link_names,
                               const char *const *joint_names, const char *title, char *buf,
                               size_t size);
#endif /* RJ_NO_SCENE_FILES */

#ifdef __cplusplus
}
#endif
#endif /* REVJOINT_H */

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

/* ------------------------------------------------------------------ energy accounts */
/* The energy accounts, one row each: its column in rj run, the frame scalar that holds
   it, where it stands in the balance (an energy in the total; a loss added to it; work
   done on the model taken from it), and its field in rj_energy. rj_state_energy, the
   first step's zeroing, the checkpoints' check and rj run's columns read this table; the
   step accumulates each account where its physics is (rj__sums). An account is a row
   here, a frame scalar (RJ__FS_*), a field of rj_energy and its physics. */
enum rj__account_kind { RJ__ACC_ENERGY = 0, RJ__ACC_LOSS, RJ__ACC_WORK };
/* What a model needs for an account to move: nothing (every model), actuators, links with
   structural damping, links with yielding layers. */
enum rj__account_need {
    RJ__NEED_NONE = 0,
    RJ__NEED_ACTUATORS,
    RJ__NEED_STRUCTURAL,
    RJ__NEED_PLASTIC
};
typedef struct rj__account {
    char column[16]; /* rj run's column name */
    int slot;        /* RJ__FS_* */
    int kind;        /* rj__account_kind */
    size_t field;    /* offsetof(rj_energy, ...) */
    int need;        /* rj__account_need */
} rj__account;
#define RJ__ACCOUNT_COUNT 11
static const rj__account rj__accounts[RJ__ACCOUNT_COUNT] = {
    { "E_kin", RJ__FS_KE, RJ__ACC_ENERGY, offsetof(rj_energy, kinetic), RJ__NEED_NONE },
    { "E_strain", RJ__FS_STRAIN, RJ__ACC_ENERGY, offsetof(rj_energy, strain), RJ__NEED_NONE },
    { "E_spring", RJ__FS_SPRING, RJ__ACC_ENERGY, offsetof(rj_energy, spring), RJ__NEED_NONE },
    { "E_gravity", RJ__FS_GRAV, RJ__ACC_ENERGY, offsetof(rj_energy, gravity), RJ__NEED_NONE },
    { "W_applied", RJ__FS_WORK, RJ__ACC_WORK, offsetof(rj_energy, work_applied), RJ__NEED_NONE },
    { "W_drive", RJ__FS_DRIVE, RJ__ACC_WORK, offsetof(rj_energy, work_drive), RJ__NEED_ACTUATORS },
    { "W_damping", RJ__FS_LDAMP, RJ__ACC_LOSS, offsetof(rj_energy, lost_damping), RJ__NEED_NONE },
    { "W_friction", RJ__FS_LFRIC, RJ__ACC_LOSS, offsetof(rj_energy, lost_friction), RJ__NEED_NONE },
    { "W_limit", RJ__FS_LLIM, RJ__ACC_LOSS, offsetof(rj_energy, lost_limit), RJ__NEED_NONE },
    { "W_structural", RJ__FS_LSTRUCT, RJ__ACC_LOSS, offsetof(rj_energy, lost_structural),
      RJ__NEED_STRUCTURAL },
    { "W_plastic", RJ__FS_LPLAST, RJ__ACC_LOSS, offsetof(rj_energy, lost_plastic),
      RJ__NEED_PLASTIC },
};

RJDEF int rj_energy_account_count(void)
{
    return RJ__ACCOUNT_COUNT;
}

RJDEF const char *rj_energy_account_name(int k)
{
    RJ_ASSERT(k >= 0 && k < RJ__ACCOUNT_COUNT);
    return rj__accounts[k].column;
}

RJDEF int rj_energy_account_in(const rj_model *m, int k)
{
    RJ_ASSERT(m && k >= 0 && k < RJ__ACCOUNT_COUNT);
    switch (rj__accounts[k].need) {
    case RJ__NEED_ACTUATORS:
        return m->nact > 0;
    case RJ__NEED_STRUCTURAL:
        return m->nstruct > 0;
    case RJ__NEED_PLASTIC:
        return m->nplastic > 0;
    default:
        return 1;
    }
}

RJDEF int rj_model_actuator_count(const rj_model *m)
{
    return m->nact;
}

RJDEF double rj_energy_account(const rj_energy *e, int k)
{
    RJ_ASSERT(e && k >= 0 && k < RJ__ACCOUNT_COUNT);
    return *(const double *) (const void *) ((const char *) e + rj__accounts[k].field);
}

/* The total and the balance from a frame's scalars: the energies summed in the table's
   order, then the losses added, the work taken away and the initial energy last. *e
   receives each account (NULL: the sums alone, as the checkpoints' check wants). */
static double rj__accounts_read(const double *scalars, rj_energy *e, double *total)
{
    double sum = 0, balance;
    int k;
    for (k = 0; k < RJ__ACCOUNT_COUNT; k++) {
        const double v = scalars[rj__accounts[k].slot];
        if (e)
            *(double *) (void *) ((char *) e + rj__accounts[k].field) = v;
        if (rj__accounts[k].kind == RJ__ACC_ENERGY)
            sum = k == 0 ? v : sum + v;
    }
    balance = sum;
    for (k = 0; k < RJ__ACCOUNT_COUNT; k++)
        if (rj__accounts[k].kind == RJ__ACC_LOSS)
            balance += scalars[rj__accounts[k].slot];
    for (k = 0; k < RJ__ACCOUNT_COUNT; k++)
        if (rj__accounts[k].kind == RJ__ACC_WORK)
            balance -= scalars[rj__accounts[k].slot];
    *total = sum;
    return balance - scalars[RJ__FS_E0];
}

/* A first step's accounts: every loss and work from zero. */
static void rj__accounts_zero(double *scalars)
{
    int k;
    for (k = 0; k < RJ__ACCOUNT_COUNT; k++)
        if (rj__accounts[k].kind != RJ__ACC_ENERGY)
            scalars[rj__accounts[k].slot] = 0;
}
/* ------------------------------------------------------------------ definition fields */
/* Every member of a definition (rj_link_def, rj_joint_def, rj_solver_def, rj_load_def,
   rj_actuator_def, rj_coupling_def) is one row of its kind's table below: its scene key,
   unit, kind of value, default, range with the one sentence that states it, when it
   applies, how the writer puts it in a scene file, and where it enters the model's hash. The defaults (rj_default_*_def),
   validation (rj__validate), the scene parser, the scene writer and the model hash read
   these rows; docs/scene-format.md's key table is checked against them (tests/keys.py).
   Rules that tie members together (a lock needs a limit, a body is a link the scene has)
   are code, grouped by concept in validate.h.

   Row k of a table, for k below the kind's key count (RJ__LK_N, RJ__JK_N, RJ__VK_N,
   RJ__AK_N), is the scene key k, in the order the enums below give. Members that no key
   sets alone follow: a member derived from other keys (a link's section shape) and the
   second parts of keys that take two (a spring's free angle, a limit's on/off flag). */

/* keys; index 0 of an item's position array is its section line, key k is at 1 + k */
enum {
    RJ__LK_LENGTH,
    RJ__LK_ELEMENTS,
    RJ__LK_MATERIAL,
    RJ__LK_SECTION,
    RJ__LK_E,
    RJ__LK_RHO,
    RJ__LK_AREA,
    RJ__LK_INERTIA,
    RJ__LK_WIDTH,
    RJ__LK_HEIGHT,
    RJ__LK_LAYERS,
    RJ__LK_TIP_MASS,
    RJ__LK_TIP_INERTIA,
    RJ__LK_ROOT,
    RJ__LK_X,
    RJ__LK_Y,
    RJ__LK_ANGLE,
    RJ__LK_VX,
    RJ__LK_VY,
    RJ__LK_OMEGA,
    RJ__LK_FIDELITY,
    RJ__LK_ETA,
    RJ__LK_DAMPING,
    RJ__LK_MASS_DAMPING,
    RJ__LK_YIELD,
    RJ__LK_HARDENING,
    RJ__LK_STRAIN,
    RJ__LK_N,
    RJ__LF_SHAPE = RJ__LK_N, /* members no key sets alone */
    RJ__LF_N
};
enum {
    RJ__JK_BODY1,
    RJ__JK_BODY2,
    RJ__JK_NODE1,
    RJ__JK_NODE2,
    RJ__JK_GROUND_X,
    RJ__JK_GROUND_Y,
    RJ__JK_GROUND_ANGLE,
    RJ__JK_ANGLE0,
    RJ__JK_RATE0,
    RJ__JK_TABLE,
    RJ__JK_SPRING,
    RJ__JK_FORWARD,
    RJ__JK_REVERSE,
    RJ__JK_LOCK,
    RJ__JK_METHOD,
    RJ__JK_RELEASE,
    RJ__JK_PENALTY_K,
    RJ__JK_RESTITUTION,
    RJ__JK_DAMPING,
    RJ__JK_FRICTION,
    RJ__JK_REFERENCE,
    RJ__JK_N,
    RJ__JF_FREE_ANGLE = RJ__JK_N,
    RJ__JF_HAS_FORWARD,
    RJ__JF_HAS_REVERSE,
    RJ__JF_N
};
enum {
    RJ__AK_LINK,
    RJ__AK_NODE,
    RJ__AK_FORCE,
    RJ__AK_MOMENT,
    RJ__AK_TABLE,
    RJ__AK_FOLLOWER,
    RJ__AK_N,
    RJ__AF_N = RJ__AK_N
};
enum {
    RJ__CK_JOINT,
    RJ__CK_TYPE,
    RJ__CK_TORQUE,
    RJ__CK_TABLE,
    RJ__CK_STALL_TORQUE,
    RJ__CK_NO_LOAD_SPEED,
    RJ__CK_CUTOFF,
    RJ__CK_KP,
    RJ__CK_KD,
    RJ__CK_TORQUE_MAX,
    RJ__CK_TARGET,
    RJ__CK_PROFILE,
    RJ__CK_START,
    RJ__CK_ROTOR_INERTIA,
    RJ__CK_GEAR_RATIO,
    RJ__CK_N,
    RJ__CF_HAS_CUTOFF = RJ__CK_N,
    RJ__CF_PROFILE_VALUE,
    RJ__CF_PROFILE_TIME,
    RJ__CF_N
};
enum {
    RJ__PK_JOINTS,
    RJ__PK_RATIO,
    RJ__PK_OFFSET,
    RJ__PK_STIFFNESS,
    RJ__PK_DAMPING,
    RJ__PK_EXACT,
    RJ__PK_N,
    RJ__PF_JOINT_B = RJ__PK_N,
    RJ__PF_N
};
enum {
    RJ__VK_DT,
    RJ__VK_ALLOW_UNSTABLE,
    RJ__VK_ENERGY_GROWTH,
    RJ__VK_ENERGY_EVERY,
    RJ__VK_IN_PLACE,
    RJ__VK_GRAVITY,
    RJ__VK_N,
    RJ__VF_N = RJ__VK_N
};

/* What a row holds, and so how it is read, checked and written. */
enum {
    RJ__FT_REAL,  /* a number, SI */
    RJ__FT_ANGLE, /* rad; a file may say deg */
    RJ__FT_RATE,  /* rad/s; a file may say deg/s */
    RJ__FT_INT,   /* an int in [lo, hi] */
    RJ__FT_ENUM,  /* an int 0 .. count - 1 named by names in files */
    RJ__FT_BOOL,  /* an int 0 or 1: no / yes in files */
    RJ__FT_VEC2,  /* two numbers (x, y), each in the range */
    RJ__FT_LINK,  /* an int: a link of the scene (a joint's body1 may be -1, ground) */
    RJ__FT_JOINT, /* an int: a joint of the scene */
    RJ__FT_NODE,  /* an int: a node of a link, -1 its last ("last" in files) */
    RJ__FT_TABLE, /* an int count, then two arrays of RJ_TABLE_MAX doubles from aux */
    RJ__FT_LIMIT, /* an angle in [lo, hi), on when the int at aux is 1 ("none" when off) */
    RJ__FT_PART,  /* no member: a file names a material or section to take values from */
    RJ__FT_PROFILE, /* an enum (rj_profile) and its numbers, its parts ("ramp 0.5 rad/s") */
    RJ__FT_N
};

/* When a row is checked and written: always, or only for one variant of its item (a
   link's section shape, an actuator's type); GROUND and ON_LINK rows are checked always
   and written only for a joint on ground or on a link. */
enum {
    RJ__WHEN_ALL,
    RJ__WHEN_RECT,
    RJ__WHEN_GENERAL,
    RJ__WHEN_TORQUE,
    RJ__WHEN_DC,
    RJ__WHEN_SERVO,
    RJ__WHEN_PRESCRIBED,
    RJ__WHEN_PROFILED, /* a servo's or a prescribed joint's profile */
    RJ__WHEN_TABLED,   /* a torque's table, or a profile's */
    RJ__WHEN_GROUND,
    RJ__WHEN_ON_LINK,
    RJ__WHEN_PLACE /* a link's placement: with a note when a joint places the link */
};

/* How the writer puts a row in a file: always; when it differs from its default in its
   bits (-0.0 is written); with its line (when any row of the line differs); or not at
   all (a part of another key, written with it). Rows of one line number follow each
   other and share a line. */
enum { RJ__WR_ALWAYS, RJ__WR_SET, RJ__WR_LINE, RJ__WR_NONE };

/* The enum names a row may point to (rj__names_of): none, or one of the rj__sk_* lists. */
enum {
    RJ__NM_NONE,
    RJ__NM_ROOT,
    RJ__NM_FIDELITY,
    RJ__NM_SHAPE,
    RJ__NM_METHOD,
    RJ__NM_RELEASE,
    RJ__NM_REFERENCE,
    RJ__NM_IN_PLACE,
    RJ__NM_ACTUATOR,
    RJ__NM_PROFILE,
    RJ__NM_STRAIN
};

/* A row is read-only data without relocations (char arrays and a names index, no
   pointers), so the tables sit in .rodata. */
typedef struct rj__field {
    char key[20];    /* the scene key; for a member that no key sets alone, its C name */
    char member[20]; /* the C member in messages ("length", "gravity"); "" for PART */
    char unit[12];   /* SI unit, "" none */
    int offset;         /* of the member in its definition; -1 for PART */
    int aux;            /* TABLE: the first array's offset; LIMIT: the flag's; else -1 */
    unsigned char type; /* RJ__FT_* */
    unsigned char when; /* RJ__WHEN_* */
    unsigned char write, line; /* RJ__WR_*, line number among the item's lines */
    signed char hash_at;       /* its place in the model hash, -1 not hashed */
    char hash_as;              /* 'd' as a double, 'i' as an int, 'z' only when not default */
    int part_of;               /* the key row this member is a second part of, else -1 */
    double def;                /* the default (VEC2: of both) */
    double lo, hi;              /* the range (ENUM: 0 .. count - 1) */
    unsigned char lo_in, hi_in; /* whether the range includes its ends */
    char rule[80]; /* the sentence a value outside the range gets (a C++ build refuses a
                      longer literal: the header's check compiles it so) */
    unsigned char names;        /* ENUM, PROFILE: RJ__NM_* of its count names, stride apart */
    unsigned char stride, count;
} rj__field;

/* The sentences of rules that several rows share. */
#define RJ__RULE_LENGTH "must be in (0, 1e6] m" /* a link's length, a section's width */
#define RJ__RULE_ANGLE "must be a finite angle within +-1e6 rad"
#define RJ__RULE_STIFFNESS "must be >= 0 N m/rad"
#define RJ__RULE_FINITE "must be finite"
#define RJ__RULE_LIMIT "a limit must be in [0, 2 pi) rad, [0, 360) deg"
#define RJ__RULE_BOOL "0 or 1"

/* enum names in files, in the enums' order: char arrays, not pointer arrays (read-only
   data without relocations) */
static const char rj__sk_in_place[3][5] = { "auto", "on", "off" };
static const char rj__sk_root[4][8] = { "free", "pinned", "clamped", "fixed" };
static const char rj__sk_fidelity[3][13] = { "flexible", "rigid", "inextensible" };
static const char rj__sk_method[5][9] = { "penalty", "adaptive", "momentum", "forced", "energy" };
static const char rj__sk_release[2][5] = { "rc12", "rc13" };
static const char rj__sk_reference[2][8] = { "tangent", "chord" };
static const char rj__sk_shape[2][8] = { "rect", "general" };
static const char rj__sk_actuator[4][11] = { "torque", "dc", "servo", "prescribed" };
static const char rj__sk_profile[4][10] = { "ramp", "cycloidal", "spinup", "table" };
static const char rj__sk_strain[2][6] = { "green", "biot" };

#define RJ__NAMES(id, a) id, (unsigned char) sizeof a[0], (unsigned char) (sizeof a / sizeof a[0])
#define RJ__NO_NAMES RJ__NM_NONE, 0, 0
#define RJ__OFF(T, m) (int) offsetof(T, m)


/* Range columns: lo, whether lo is in, hi, whether hi is in. */
#define RJ__R(lo, lo_in, hi, hi_in) lo, hi, lo_in, hi_in
#define RJ__ANY RJ__R(-HUGE_VAL, 0, HUGE_VAL, 0)

/* A row of member m of the definition RJ__DEF: key, unit, type, when, write, line, hash
   place and form, default, range and its sentence. */
#define RJ__F(key, m, unit, type, when, wr, line, hat, has, def, range, rule)                 \
    {                                                                                         \
        key, #m, unit, RJ__OFF(RJ__DEF, m), -1, type, when, wr, line, hat, has, -1, def,      \
            range, rule, RJ__NO_NAMES                                                         \
    }
/* An enum member's row: its names in files; validation's sentence names its C values. */
#define RJ__FE(key, m, id, names, wr, line, hat, has, def, rule)                              \
    {                                                                                         \
        key, #m, "", RJ__OFF(RJ__DEF, m), -1, RJ__FT_ENUM, RJ__WHEN_ALL, wr, line, hat, has,  \
            -1, def, RJ__R(0.0, 1, (double) (sizeof names / sizeof names[0]) - 1, 1), rule,   \
            RJ__NAMES(id, names)                                                              \
    }
/* A row with an aux offset (TABLE, LIMIT) or one that is a part of key row part_of. */
#define RJ__FA(key, m, unit, type, aux, part_of, wr, line, hat, has, def, range, rule, st)      \
    {                                                                                         \
        key, #m, unit, RJ__OFF(RJ__DEF, m), aux, type, RJ__WHEN_ALL, wr, line, hat, has,      \
            part_of, def, range, rule, RJ__NM_NONE, st, 0                                     \
    }
/* A key that names a material or a section (no member). */
#define RJ__FPART(key)                                                                        \
    {                                                                                         \
        key, "", "", -1, -1, RJ__FT_PART, RJ__WHEN_ALL, RJ__WR_NONE, 0, -1, 'd', -1, 0.0,     \
            RJ__ANY, "", RJ__NO_NAMES                                                         \
    }

#define RJ__DEF rj_link_def
static const rj__field rj__link_fields[RJ__LF_N] = {
    RJ__F("length", length, "m", RJ__FT_REAL, RJ__WHEN_ALL, RJ__WR_ALWAYS, 1, 0, 'd', 1.0,
          RJ__R(0.0, 0, 1e6, 1), RJ__RULE_LENGTH),
    RJ__F("elements", elements, "", RJ__FT_INT, RJ__WHEN_ALL, RJ__WR_ALWAYS, 1, 15, 'd', 10.0,
          RJ__R(1.0, 1, 1e6, 1), "must be 1..1000000"),
    RJ__FPART("material"),
    RJ__FPART("section"),
    RJ__F("E", E, "Pa", RJ__FT_REAL, RJ__WHEN_ALL, RJ__WR_ALWAYS, 2, 1, 'd', 70e9,
          RJ__R(0.0, 0, 1e30, 1), "must be in (0, 1e30] Pa"),
    RJ__F("rho", rho, "kg/m^3", RJ__FT_REAL, RJ__WHEN_ALL, RJ__WR_ALWAYS, 2, 2, 'd', 2710.0,
          RJ__R(0.0, 0, 1e30, 1), "must be in (0, 1e30] kg/m^3"),
    RJ__F("area", area, "m^2", RJ__FT_REAL, RJ__WHEN_GENERAL, RJ__WR_ALWAYS, 3, 5, 'd', 0.0,
          RJ__R(0.0, 0, 1e12, 1), "must be in (0, 1e12] m^2"),
    RJ__F("inertia", inertia, "m^4", RJ__FT_REAL, RJ__WHEN_GENERAL, RJ__WR_ALWAYS, 3, 6, 'd',
          0.0, RJ__R(0.0, 0, 1e24, 1), "must be in (0, 1e24] m^4"),
    RJ__F("width", width, "m", RJ__FT_REAL, RJ__WHEN_RECT, RJ__WR_ALWAYS, 3, 3, 'd', 0.05,
          RJ__R(0.0, 0, 1e6, 1), RJ__RULE_LENGTH),
    /* the in-plane depth; a general section's drawn thickness (> 0 for a rectangle: a
       rule of the section's shape) */
    RJ__F("height", height, "m", RJ__FT_REAL, RJ__WHEN_ALL, RJ__WR_ALWAYS, 3, 4, 'd', 0.2,
          RJ__R(0.0, 1, 1e6, 1), "must be in [0, 1e6] m (> 0 for a rectangular section)"),
    RJ__F("layers", layers, "", RJ__FT_INT, RJ__WHEN_RECT, RJ__WR_SET, 3, 17, 'd', 1.0,
          RJ__R(1.0, 1, 1000.0, 1), "must be 1..1000"),
    RJ__F("tip_mass", tip_mass, "kg", RJ__FT_REAL, RJ__WHEN_ALL, RJ__WR_LINE, 4, 7, 'd', 0.0,
          RJ__R(0.0, 1, 1e40, 1), "must be in [0, 1e40] kg"),
    RJ__F("tip_inertia", tip_inertia, "kg m^2", RJ__FT_REAL, RJ__WHEN_ALL, RJ__WR_LINE, 4, 8,
          'd', 0.0, RJ__R(0.0, 1, 1e50, 1), "must be in [0, 1e50] kg m^2"),
    RJ__FE("root", root, RJ__NM_ROOT, rj__sk_root, RJ__WR_SET, 5, 18, 'd', 0.0,
           "RJ_ROOT_FREE, _PINNED, _CLAMPED or _FIXED"),
    RJ__F("x", x, "m", RJ__FT_REAL, RJ__WHEN_PLACE, RJ__WR_LINE, 6, 9, 'd', 0.0, RJ__ANY,
          RJ__RULE_FINITE),
    RJ__F("y", y, "m", RJ__FT_REAL, RJ__WHEN_PLACE, RJ__WR_LINE, 6, 10, 'd', 0.0, RJ__ANY,
          RJ__RULE_FINITE),
    /* within 1e6 rad, as angle0: beyond it a rotation of 1e-7 rad (the stability bound's
       finite differences) falls below what the angle's double resolves */
    RJ__F("angle", angle, "rad", RJ__FT_ANGLE, RJ__WHEN_PLACE, RJ__WR_LINE, 6, 11, 'd', 0.0,
          RJ__R(-1e6, 1, 1e6, 1), RJ__RULE_ANGLE),
    RJ__F("vx", vx, "m/s", RJ__FT_REAL, RJ__WHEN_ALL, RJ__WR_LINE, 7, 12, 'd', 0.0, RJ__ANY,
          RJ__RULE_FINITE),
    RJ__F("vy", vy, "m/s", RJ__FT_REAL, RJ__WHEN_ALL, RJ__WR_LINE, 7, 13, 'd', 0.0, RJ__ANY,
          RJ__RULE_FINITE),
    RJ__F("omega", omega, "rad/s", RJ__FT_RATE, RJ__WHEN_ALL, RJ__WR_LINE, 7, 14, 'd', 0.0,
          RJ__ANY, RJ__RULE_FINITE),
    RJ__FE("fidelity", fidelity, RJ__NM_FIDELITY, rj__sk_fidelity, RJ__WR_SET, 8, 19, 'i', 0.0,
           "RJ_LINK_FLEXIBLE, RJ_LINK_RIGID or RJ_LINK_INEXTENSIBLE"),
    /* structural damping: hashed only when set, so scenes without it keep their hash */
    RJ__F("eta", eta, "s", RJ__FT_REAL, RJ__WHEN_ALL, RJ__WR_SET, 9, 20, 'z', 0.0,
          RJ__R(0.0, 1, 1e6, 1), "must be in [0, 1e6] s"),
    RJ__F("damping", damping, "", RJ__FT_VEC2, RJ__WHEN_ALL, RJ__WR_SET, 9, 21, 'z', 0.0,
          RJ__R(0.0, 1, 1e9, 1), "a ratio and a frequency in Hz, each in [0, 1e9]"),
    RJ__F("mass_damping", mass_damping, "1/s", RJ__FT_REAL, RJ__WHEN_ALL, RJ__WR_SET, 9, 22,
          'z', 0.0, RJ__R(0.0, 1, 1e9, 1), "must be in [0, 1e9] 1/s"),
    /* elastic-plastic layers and the axial law: hashed only when set too */
    RJ__F("yield", yield, "Pa", RJ__FT_REAL, RJ__WHEN_ALL, RJ__WR_SET, 10, 24, 'z', 0.0,
          RJ__R(0.0, 1, 1e30, 1), "must be in [0, 1e30] Pa (0: elastic)"),
    RJ__F("hardening", hardening, "Pa", RJ__FT_REAL, RJ__WHEN_ALL, RJ__WR_SET, 10, 25, 'z', 0.0,
          RJ__R(0.0, 1, 1e30, 1), "must be in [0, 1e30] Pa"),
    RJ__FE("strain", strain, RJ__NM_STRAIN, rj__sk_strain, RJ__WR_SET, 10, 26, 'z', 0.0,
           "RJ_STRAIN_GREEN or RJ_STRAIN_BIOT"),
    /* derived: area and inertia in a file make a general section */
    RJ__FE("section", section, RJ__NM_SHAPE, rj__sk_shape, RJ__WR_NONE, 0, 16, 'd', 0.0,
           "RJ_SECTION_RECT or RJ_SECTION_GENERAL"),
};
#undef RJ__DEF

#define RJ__DEF rj_joint_def
static const rj__field rj__joint_fields[RJ__JF_N] = {
    RJ__F("body1", body1, "", RJ__FT_LINK, RJ__WHEN_ALL, RJ__WR_ALWAYS, 1, 0, 'd', -1.0,
          RJ__ANY, ""),
    RJ__F("body2", body2, "", RJ__FT_LINK, RJ__WHEN_ALL, RJ__WR_ALWAYS, 1, 2, 'd', 0.0, RJ__ANY,
          ""),
    RJ__F("node1", node1, "", RJ__FT_NODE, RJ__WHEN_ON_LINK, RJ__WR_SET, 1, 1, 'd', -1.0,
          RJ__ANY, ""),
    /* hashed only when set: every scene before it pins node 0 and keeps its hash */
    RJ__F("node2", node2, "", RJ__FT_NODE, RJ__WHEN_ALL, RJ__WR_SET, 1, 23, 'z', 0.0,
          RJ__ANY, ""),
    RJ__F("ground_x", ground_x, "m", RJ__FT_REAL, RJ__WHEN_GROUND, RJ__WR_LINE, 2, 3, 'd', 0.0,
          RJ__ANY, RJ__RULE_FINITE),
    RJ__F("ground_y", ground_y, "m", RJ__FT_REAL, RJ__WHEN_GROUND, RJ__WR_LINE, 2, 4, 'd', 0.0,
          RJ__ANY, RJ__RULE_FINITE),
    RJ__F("ground_angle", ground_angle, "rad", RJ__FT_ANGLE, RJ__WHEN_GROUND, RJ__WR_LINE, 2, 5,
          'd', 0.0, RJ__ANY, RJ__RULE_FINITE),
    RJ__F("angle0", angle0, "rad", RJ__FT_ANGLE, RJ__WHEN_ALL, RJ__WR_ALWAYS, 3, 6, 'd', RJ__PI,
          RJ__R(-1e6, 1, 1e6, 1), RJ__RULE_ANGLE),
    RJ__F("rate0", rate0, "rad/s", RJ__FT_RATE, RJ__WHEN_ALL, RJ__WR_SET, 3, 7, 'd', 0.0,
          RJ__ANY, RJ__RULE_FINITE),
    /* angle torque pairs (Eq 4); first column angles (stride 1) */
    RJ__FA("table", table_count, "N m", RJ__FT_TABLE, RJ__OFF(rj_joint_def, table_angle), -1,
           RJ__WR_SET, 4, 22, 'i', 0.0, RJ__R(2.0, 1, RJ_TABLE_MAX, 1), "", 1),
    RJ__FA("spring", spring_k, "N m/rad", RJ__FT_REAL, -1, -1, RJ__WR_LINE, 5, 8, 'd', 0.0,
           RJ__R(0.0, 1, HUGE_VAL, 0), RJ__RULE_STIFFNESS, 0),
    RJ__FA("forward", forward, "rad", RJ__FT_LIMIT, RJ__OFF(rj_joint_def, has_forward), -1,
           RJ__WR_SET, 6, 11, 'd', 0.0, RJ__R(0.0, 1, RJ__TWO_PI, 0), RJ__RULE_LIMIT, 0),
    RJ__FA("reverse", reverse, "rad", RJ__FT_LIMIT, RJ__OFF(rj_joint_def, has_reverse), -1,
           RJ__WR_SET, 7, 13, 'd', 0.0, RJ__R(0.0, 1, RJ__TWO_PI, 0), RJ__RULE_LIMIT, 0),
    RJ__F("lock", lock, "", RJ__FT_BOOL, RJ__WHEN_ALL, RJ__WR_SET, 8, 14, 'd', 0.0,
          RJ__R(0.0, 1, 1.0, 1), RJ__RULE_BOOL),
    RJ__FE("method", method, RJ__NM_METHOD, rj__sk_method,
           RJ__WR_ALWAYS, 9, 15, 'd', RJ_METHOD_ADAPTIVE,
           "one of RJ_METHOD_PENALTY..RJ_METHOD_ENERGY"),
    RJ__FE("release", release, RJ__NM_RELEASE, rj__sk_release,
           RJ__WR_SET, 9, 16, 'd', RJ_RELEASE_RC13,
           "RJ_RELEASE_RC12 or RJ_RELEASE_RC13"),
    RJ__F("penalty_k", penalty_k, "N m/rad", RJ__FT_REAL, RJ__WHEN_ALL, RJ__WR_SET, 10, 17, 'd',
          0.0, RJ__R(0.0, 1, HUGE_VAL, 0), RJ__RULE_STIFFNESS),
    RJ__F("restitution", restitution, "", RJ__FT_REAL, RJ__WHEN_ALL, RJ__WR_SET, 11, 18, 'd',
          0.0, RJ__R(0.0, 1, 1.0, 1), "must be in [0, 1]"),
    RJ__F("damping", damping, "N m s/rad", RJ__FT_REAL, RJ__WHEN_ALL, RJ__WR_SET, 12, 19, 'd',
          0.0, RJ__R(0.0, 1, HUGE_VAL, 0), "must be >= 0 N m s/rad"),
    RJ__F("friction", friction, "N m", RJ__FT_REAL, RJ__WHEN_ALL, RJ__WR_SET, 13, 20, 'd', 0.0,
          RJ__R(0.0, 1, HUGE_VAL, 0), "must be >= 0 N m"),
    RJ__FE("reference", reference, RJ__NM_REFERENCE, rj__sk_reference, RJ__WR_SET, 14, 21, 'i', 0.0,
           "RJ_REF_TANGENT or RJ_REF_CHORD"),
    /* second parts: spring = k angle; a limit's on/off */
    RJ__FA("spring_free_angle", spring_free_angle, "rad", RJ__FT_ANGLE, -1, RJ__JK_SPRING,
           RJ__WR_NONE, 5, 9, 'd', RJ__PI, RJ__R(-1e6, 1, 1e6, 1), RJ__RULE_ANGLE, 0),
    RJ__FA("has_forward", has_forward, "", RJ__FT_BOOL, -1, RJ__JK_FORWARD, RJ__WR_NONE, 6, 10,
           'd', 0.0, RJ__R(0.0, 1, 1.0, 1), RJ__RULE_BOOL, 0),
    RJ__FA("has_reverse", has_reverse, "", RJ__FT_BOOL, -1, RJ__JK_REVERSE, RJ__WR_NONE, 7, 12,
           'd', 0.0, RJ__R(0.0, 1, 1.0, 1), RJ__RULE_BOOL, 0),
};
#undef RJ__DEF

#define RJ__DEF rj_solver_def
static const rj__field rj__solver_fields[RJ__VF_N] = {
    RJ__F("dt", dt, "s", RJ__FT_REAL, RJ__WHEN_ALL, RJ__WR_SET, 1, -1, 'd', 0.0,
          RJ__R(0.0, 1, 1.0, 1), "must be 0 (automatic) or a step in (0, 1] s"),
    RJ__F("allow_unstable", allow_unstable, "", RJ__FT_BOOL, RJ__WHEN_ALL, RJ__WR_SET, 2, -1,
          'd', 0.0, RJ__R(0.0, 1, 1.0, 1), "must be 0 or 1"),
    RJ__F("energy_growth", energy_growth, "", RJ__FT_REAL, RJ__WHEN_ALL, RJ__WR_SET, 3, -1, 'd',
          10.0, RJ__R(1.0, 0, HUGE_VAL, 0), "must be > 1"),
    RJ__F("energy_every", energy_every, "", RJ__FT_INT, RJ__WHEN_ALL, RJ__WR_SET, 4, -1, 'd',
          1.0, RJ__R(1.0, 1, 1000.0, 1), "must be 1..1000 steps"),
    RJ__FE("in_place", in_place, RJ__NM_IN_PLACE, rj__sk_in_place,
           RJ__WR_SET, 5, -1, 'd', RJ_IN_PLACE_AUTO,
           "must be RJ_IN_PLACE_AUTO (0), RJ_IN_PLACE_ON (1) or RJ_IN_PLACE_OFF (2)"),
    RJ__F("gravity", gravity, "m/s^2", RJ__FT_VEC2, RJ__WHEN_ALL, RJ__WR_SET, 6, 0, 'd', 0.0,
          RJ__R(-1e5, 1, 1e5, 1),
          "each component must be a finite acceleration within +-1e5 m/s^2"),
};
#undef RJ__DEF

#define RJ__DEF rj_load_def
static const rj__field rj__load_fields[RJ__AF_N] = {
    RJ__F("link", link, "", RJ__FT_LINK, RJ__WHEN_ALL, RJ__WR_ALWAYS, 1, 0, 'i', 0.0, RJ__ANY,
          ""),
    RJ__F("node", node, "", RJ__FT_NODE, RJ__WHEN_ALL, RJ__WR_SET, 1, 1, 'i', -1.0, RJ__ANY, ""),
    RJ__F("force", force, "N", RJ__FT_VEC2, RJ__WHEN_ALL, RJ__WR_SET, 2, 2, 'd', 0.0,
          RJ__R(-1e30, 1, 1e30, 1), "must be a finite force within +-1e30 N"),
    RJ__F("moment", moment, "N m", RJ__FT_REAL, RJ__WHEN_ALL, RJ__WR_SET, 3, 3, 'd', 0.0,
          RJ__R(-1e30, 1, 1e30, 1), "must be a finite moment within +-1e30 N m"),
    /* time factor pairs */
    RJ__FA("table", table_count, "", RJ__FT_TABLE, RJ__OFF(rj_load_def, table_time), -1,
           RJ__WR_SET, 4, 5, 'i', 0.0, RJ__R(1.0, 1, RJ_TABLE_MAX, 1), "", 0),
    RJ__F("follower", follower, "", RJ__FT_BOOL, RJ__WHEN_ALL, RJ__WR_SET, 5, 4, 'i', 0.0,
          RJ__R(0.0, 1, 1.0, 1), "must be 0 (global frame) or 1 (turns with the node)"),
};
#undef RJ__DEF

/* A row of an actuator's member m that applies to one type (when). */
#define RJ__FC(key, m, unit, type, when, wr, line, hat, def, range, rule)                     \
    {                                                                                         \
        key, #m, unit, RJ__OFF(RJ__DEF, m), -1, type, when, wr, line, hat, 'd', -1, def,      \
            range, rule, RJ__NO_NAMES                                                         \
    }

#define RJ__DEF rj_actuator_def
static const rj__field rj__actuator_fields[RJ__CF_N] = {
    RJ__F("joint", joint, "", RJ__FT_JOINT, RJ__WHEN_ALL, RJ__WR_ALWAYS, 1, 0, 'i', 0.0,
          RJ__ANY, ""),
    RJ__FE("type", type, RJ__NM_ACTUATOR, rj__sk_actuator,
           RJ__WR_ALWAYS, 1, 1, 'i', RJ_ACTUATOR_TORQUE,
           "RJ_ACTUATOR_TORQUE, _DC, _SERVO or _PRESCRIBED"),
    RJ__FC("torque", torque, "N m", RJ__FT_REAL, RJ__WHEN_TORQUE, RJ__WR_ALWAYS, 2, 2, 0.0,
           RJ__R(-1e30, 1, 1e30, 1), "must be a finite torque within +-1e30 N m"),
    /* time factor pairs, as a load's */
    { "table", "table_count", "", RJ__OFF(rj_actuator_def, table_count),
      RJ__OFF(rj_actuator_def, table_time), RJ__FT_TABLE, RJ__WHEN_TABLED, RJ__WR_SET, 3, 3,
      'i', -1, 0.0, RJ__R(1.0, 1, RJ_TABLE_MAX, 1), "", RJ__NM_NONE, 0, 0 },
    RJ__FC("stall_torque", stall_torque, "N m", RJ__FT_REAL, RJ__WHEN_DC, RJ__WR_ALWAYS, 4, 4,
           0.0, RJ__R(-1e30, 1, 1e30, 1), "must be a finite torque within +-1e30 N m"),
    RJ__FC("no_load_speed", no_load_speed, "rad/s", RJ__FT_RATE, RJ__WHEN_DC, RJ__WR_ALWAYS, 4,
           5, 1.0, RJ__R(-1e6, 1, 1e6, 1),
           "must be a rate within +-1e6 rad/s, not 0, of the stall torque's sign"),
    { "cutoff", "cutoff", "rad", RJ__OFF(rj_actuator_def, cutoff),
      RJ__OFF(rj_actuator_def, has_cutoff), RJ__FT_LIMIT, RJ__WHEN_DC, RJ__WR_SET, 5, 7, 'd', -1,
      0.0, RJ__R(0.0, 1, RJ__TWO_PI, 0), "a cutoff must be in [0, 2 pi) rad, [0, 360) deg",
      RJ__NM_NONE, 0, 0 },
    RJ__FC("kp", kp, "N m/rad", RJ__FT_REAL, RJ__WHEN_SERVO, RJ__WR_ALWAYS, 6, 8, 0.0,
           RJ__R(0.0, 1, 1e30, 1), "must be in [0, 1e30] N m/rad"),
    RJ__FC("kd", kd, "N m s/rad", RJ__FT_REAL, RJ__WHEN_SERVO, RJ__WR_ALWAYS, 6, 9, 0.0,
           RJ__R(0.0, 1, 1e30, 1), "must be in [0, 1e30] N m s/rad"),
    RJ__FC("torque_max", torque_max, "N m", RJ__FT_REAL, RJ__WHEN_SERVO, RJ__WR_SET, 7, 10, 0.0,
           RJ__R(0.0, 1, 1e30, 1), "must be in [0, 1e30] N m (0: no bound)"),
    RJ__FC("target", target, "rad", RJ__FT_ANGLE, RJ__WHEN_SERVO, RJ__WR_ALWAYS, 8, 11, RJ__PI,
           RJ__R(-1e6, 1, 1e6, 1), RJ__RULE_ANGLE),
    /* ramp RATE, cycloidal ANGLE DURATION, spinup OMEGA TS */
    { "profile", "profile", "", RJ__OFF(rj_actuator_def, profile), -1, RJ__FT_PROFILE,
      RJ__WHEN_PROFILED, RJ__WR_SET, 9, 12, 'i', -1, 0.0, RJ__R(0.0, 1, 3.0, 1),
      "RJ_PROFILE_RAMP, _CYCLOIDAL, _SPINUP or _TABLE", RJ__NAMES(RJ__NM_PROFILE, rj__sk_profile) },
    RJ__FC("start", start, "s", RJ__FT_REAL, RJ__WHEN_PROFILED, RJ__WR_SET, 9, 15, 0.0,
           RJ__R(-1e9, 1, 1e9, 1), "must be a finite time within +-1e9 s"),
    /* the rotor behind its gear, for every type */
    RJ__FC("rotor_inertia", rotor_inertia, "kg m^2", RJ__FT_REAL, RJ__WHEN_ALL, RJ__WR_LINE, 10,
           16, 0.0, RJ__R(0.0, 1, 1e30, 1), "must be in [0, 1e30] kg m^2"),
    RJ__FC("gear_ratio", gear_ratio, "", RJ__FT_REAL, RJ__WHEN_ALL, RJ__WR_LINE, 10, 17, 1.0,
           RJ__R(-1e6, 1, 1e6, 1), "must be a finite ratio within +-1e6, not 0"),
    /* the cutoff's on/off */
    { "has_cutoff", "has_cutoff", "", RJ__OFF(rj_actuator_def, has_cutoff), -1, RJ__FT_BOOL,
      RJ__WHEN_DC, RJ__WR_NONE, 5, 6, 'i', RJ__CK_CUTOFF, 0.0, RJ__R(0.0, 1, 1.0, 1),
      RJ__RULE_BOOL, RJ__NM_NONE, 0, 0 },
    /* the profile's numbers */
    { "profile_value", "profile_value", "", RJ__OFF(rj_actuator_def, profile_value), -1,
      RJ__FT_REAL, RJ__WHEN_PROFILED, RJ__WR_NONE, 9, 13, 'd', RJ__CK_PROFILE, 0.0,
      RJ__R(-1e6, 1, 1e6, 1), "must be a finite rate or angle within +-1e6 (rad/s or rad)",
      RJ__NM_NONE, 0, 0 },
    { "profile_time", "profile_time", "s", RJ__OFF(rj_actuator_def, profile_time), -1,
      RJ__FT_REAL, RJ__WHEN_PROFILED, RJ__WR_NONE, 9, 14, 'd', RJ__CK_PROFILE, 1.0,
      RJ__R(0.0, 0, 1e9, 1), "must be a time in (0, 1e9] s", RJ__NM_NONE, 0, 0 },
};
#undef RJ__DEF

#define RJ__DEF rj_coupling_def
static const rj__field rj__coupling_fields[RJ__PF_N] = {
    /* joints = A B: joint_a, then its part joint_b */
    RJ__F("joints", joint_a, "", RJ__FT_JOINT, RJ__WHEN_ALL, RJ__WR_ALWAYS, 1, 0, 'i', 0.0,
          RJ__ANY, ""),
    RJ__F("ratio", ratio, "", RJ__FT_REAL, RJ__WHEN_ALL, RJ__WR_SET, 2, 2, 'd', 1.0,
          RJ__R(-1e6, 1, 1e6, 1), "must be a finite ratio within +-1e6"),
    RJ__F("offset", offset, "rad", RJ__FT_ANGLE, RJ__WHEN_ALL, RJ__WR_SET, 2, 3, 'd', 0.0,
          RJ__R(-1e6, 1, 1e6, 1), RJ__RULE_ANGLE),
    RJ__F("stiffness", stiffness, "N m/rad", RJ__FT_REAL, RJ__WHEN_ALL, RJ__WR_ALWAYS, 3, 4, 'd',
          0.0, RJ__R(0.0, 1, 1e30, 1), "must be in [0, 1e30] N m/rad"),
    RJ__F("damping", damping, "N m s/rad", RJ__FT_REAL, RJ__WHEN_ALL, RJ__WR_SET, 3, 5, 'd', 0.0,
          RJ__R(0.0, 1, 1e30, 1), "must be in [0, 1e30] N m s/rad"),
    RJ__F("exact", exact, "", RJ__FT_BOOL, RJ__WHEN_ALL, RJ__WR_SET, 4, 6, 'i', 0.0,
          RJ__R(0.0, 1, 1.0, 1), "must be 0 (a cable) or 1 (a constraint)"),
    RJ__FA("joint_b", joint_b, "", RJ__FT_JOINT, -1, RJ__PK_JOINTS, RJ__WR_NONE, 1, 1, 'i', 1.0,
           RJ__ANY, "", 0),
};
#undef RJ__DEF

/* ------------------------------------------------------------------ reading rows */
/* The enum names of a row (its names index): count names, stride bytes apart. */
static const char *rj__names_of(int id)
{
    switch (id) {
    case RJ__NM_ROOT:
        return rj__sk_root[0];
    case RJ__NM_FIDELITY:
        return rj__sk_fidelity[0];
    case RJ__NM_SHAPE:
        return rj__sk_shape[0];
    case RJ__NM_METHOD:
        return rj__sk_method[0];
    case RJ__NM_RELEASE:
        return rj__sk_release[0];
    case RJ__NM_REFERENCE:
        return rj__sk_reference[0];
    case RJ__NM_IN_PLACE:
        return rj__sk_in_place[0];
    case RJ__NM_ACTUATOR:
        return rj__sk_actuator[0];
    case RJ__NM_PROFILE:
        return rj__sk_profile[0];
    case RJ__NM_STRAIN:
        return rj__sk_strain[0];
    default:
        return "";
    }
}

/* The definition kinds, and each one's table. */
enum {
    RJ__DEF_LINK,
    RJ__DEF_JOINT,
    RJ__DEF_SOLVER,
    RJ__DEF_LOAD,
    RJ__DEF_ACTUATOR,
    RJ__DEF_COUPLING
};

static const rj__field *rj__fields(int kind, int *count)
{
    switch (kind) {
    case RJ__DEF_LINK:
        *count = RJ__LF_N;
        return rj__link_fields;
    case RJ__DEF_JOINT:
        *count = RJ__JF_N;
        return rj__joint_fields;
    case RJ__DEF_SOLVER:
        *count = RJ__VF_N;
        return rj__solver_fields;
    case RJ__DEF_LOAD:
        *count = RJ__AF_N;
        return rj__load_fields;
    case RJ__DEF_ACTUATOR:
        *count = RJ__CF_N;
        return rj__actuator_fields;
    default:
        *count = RJ__PF_N;
        return rj__coupling_fields;
    }
}

/* How many of kind's rows are scene keys (the first ones). */
static int rj__key_count(int kind)
{
    switch (kind) {
    case RJ__DEF_LINK:
        return RJ__LK_N;
    case RJ__DEF_JOINT:
        return RJ__JK_N;
    case RJ__DEF_SOLVER:
        return RJ__VK_N;
    case RJ__DEF_LOAD:
        return RJ__AK_N;
    case RJ__DEF_ACTUATOR:
        return RJ__CK_N;
    default:
        return RJ__PK_N;
    }
}

/* The double at row r of def (VEC2: component c). */
static double rj__row_real(const void *def, const rj__field *r, int c)
{
    double v;
    memcpy(&v, (const char *) def + r->offset + c * sizeof(double), sizeof v);
    return v;
}

static void rj__row_set_real(void *def, const rj__field *r, int c, double v)
{
    memcpy((char *) def + r->offset + c * sizeof(double), &v, sizeof v);
}

/* The int at row r of def (INT, ENUM, BOOL, LINK, NODE, a TABLE's count); at the flag of
   a LIMIT. */
static int rj__row_int(const void *def, const rj__field *r)
{
    int v;
    const int at = r->type == RJ__FT_LIMIT ? r->aux : r->offset;
    memcpy(&v, (const char *) def + at, sizeof v);
    return v;
}

static void rj__row_set_int(void *def, const rj__field *r, int v)
{
    memcpy((char *) def + r->offset, &v, sizeof v);
}

/* Whether row r holds a double (REAL, ANGLE, RATE, LIMIT, VEC2) rather than an int. */
static int rj__row_is_real(const rj__field *r)
{
    return r->type == RJ__FT_REAL || r->type == RJ__FT_ANGLE || r->type == RJ__FT_RATE ||
           r->type == RJ__FT_LIMIT || r->type == RJ__FT_VEC2;
}

/* Every member of def at its default: zeros, then each row's default. */
static void rj__rows_default(void *def, size_t size, int kind)
{
    int n, k;
    const rj__field *t = rj__fields(kind, &n);
    memset(def, 0, size);
    for (k = 0; k < n; k++) {
        const rj__field *r = &t[k];
        if (r->type == RJ__FT_PART)
            continue;
        if (rj__row_is_real(r)) {
            rj__row_set_real(def, r, 0, r->def);
            if (r->type == RJ__FT_VEC2)
                rj__row_set_real(def, r, 1, r->def);
        } else
            rj__row_set_int(def, r, (int) r->def);
    }
}

/* Whether row r applies to an item of variant (a link's section shape, an actuator's
   type; -1 for other kinds) and is checked (write 0) or written (write 1) for a joint on
   ground (or not). */
static int rj__row_applies(const rj__field *r, int variant, int on_ground, int write)
{
    switch (r->when) {
    case RJ__WHEN_RECT:
        return variant == RJ_SECTION_RECT;
    case RJ__WHEN_GENERAL:
        return variant == RJ_SECTION_GENERAL;
    case RJ__WHEN_TORQUE:
        return variant == RJ_ACTUATOR_TORQUE;
    case RJ__WHEN_DC:
        return variant == RJ_ACTUATOR_DC;
    case RJ__WHEN_SERVO:
        return variant == RJ_ACTUATOR_SERVO;
    case RJ__WHEN_PRESCRIBED:
        return variant == RJ_ACTUATOR_PRESCRIBED;
    case RJ__WHEN_PROFILED:
    case RJ__WHEN_TABLED:
        return variant == RJ_ACTUATOR_SERVO || variant == RJ_ACTUATOR_PRESCRIBED ||
               (r->when == RJ__WHEN_TABLED && variant == RJ_ACTUATOR_TORQUE);
    case RJ__WHEN_GROUND:
        return !write || on_ground;
    case RJ__WHEN_ON_LINK:
        return !write || !on_ground;
    default:
        return 1;
    }
}
/* ------------------------------------------------------------------ defaults */
/* Each definition's defaults are its rows' (fields.h); the cookie marks it as made here. */
RJDEF rj_link_def rj_default_link_def(void)
{
    rj_link_def d;
    rj__rows_default(&d, sizeof d, RJ__DEF_LINK);
    d.cookie = RJ__COOKIE_LINK;
    return d;
}
RJDEF rj_joint_def rj_default_joint_def(void)
{
    rj_joint_def d;
    rj__rows_default(&d, sizeof d, RJ__DEF_JOINT);
    d.cookie = RJ__COOKIE_JOINT;
    return d;
}
RJDEF rj_solver_def rj_default_solver_def(void)
{
    rj_solver_def d;
    rj__rows_default(&d, sizeof d, RJ__DEF_SOLVER);
    d.cookie = RJ__COOKIE_SOLVER;
    return d;
}
RJDEF rj_load_def rj_default_load_def(void)
{
    rj_load_def d;
    rj__rows_default(&d, sizeof d, RJ__DEF_LOAD);
    d.cookie = RJ__COOKIE_LOAD;
    return d;
}
RJDEF rj_scene_def rj_default_scene_def(void)
{
    rj_scene_def d;
    memset(&d, 0, sizeof d);
    d.links = NULL;
    d.link_count = 0;
    d.joints = NULL;
    d.joint_count = 0;
    d.solver = rj_default_solver_def();
    return d;
}
RJDEF rj_actuator_def rj_default_actuator_def(void)
{
    rj_actuator_def d;
    rj__rows_default(&d, sizeof d, RJ__DEF_ACTUATOR);
    d.cookie = RJ__COOKIE_ACTUATOR;
    return d;
}
RJDEF rj_coupling_def rj_default_coupling_def(void)
{
    rj_coupling_def d;
    rj__rows_default(&d, sizeof d, RJ__DEF_COUPLING);
    d.cookie = RJ__COOKIE_COUPLING;
    return d;
}
/* ------------------------------------------------------------------ pure element equations */
/* Eqs 1-3: angle from a to b, counter-clockwise, in [0, 2 pi). */
RJDEF double rj_rotary_location(double ax, double ay, double bx, double by)
{
    return rj__mod2pi(atan2(ax * by - ay * bx, ax * bx + ay * by));
}

/* Eq 4: sum over segments containing theta of the linear interpolant; overlapping segments add. */
RJDEF double rj_table_torque(const double *angle, const double *torque, int count, double theta)
{
    double t = 0.0;
    int i;
    for (i = 0; i + 1 < count; i++) {
        double a0 = angle[i], a1 = angle[i + 1];
        if (a1 > a0 && theta >= a0 && theta <= a1)
            t += torque[i] + (theta - a0) / (a1 - a0) * (torque[i + 1] - torque[i]);
    }
    return t;
}

/* Integral of Eq 4 from 0 to theta (the table's potential). */
static double rj__table_potential(const double *angle, const double *torque, int count,
                                  double theta)
{
    double v = 0.0;
    int i;
    for (i = 0; i + 1 < count; i++) {
        double a0 = angle[i], a1 = angle[i + 1], hi, k;
        if (!(a1 > a0) || theta <= a0)
            continue;
        hi = theta < a1 ? theta : a1;
        k = (torque[i + 1] - torque[i]) / (a1 - a0);
        v += (hi - a0) * (torque[i] + 0.5 * k * (hi - a0));
    }
    return v;
}

/* Eq 6: bLimit for wrapped theta. forward > reverse: limited outside (reverse, forward);
   forward < reverse: limited inside [forward, reverse] (free range wraps through 0). */
RJDEF int rj_blimit(double theta, double forward, double reverse)
{
    if (forward > reverse)
        return theta >= forward || theta <= reverse;
    if (forward < reverse)
        return theta >= forward && theta <= reverse;
    return theta == forward;
}

/* Eqs 7-13: next status flag. beyond_forward / beyond_reverse split bLimit by side (our
   reading: a body past the forward limit cannot be "at the reverse limit"). */
RJDEF int rj_flag_next(int prev, int beyond_forward, int beyond_reverse, double rate, int lock,
                       int release)
{
    if (prev == RJ_LOCKED)
        return RJ_LOCKED; /* never released */
    if (lock && (beyond_forward || beyond_reverse))
        return RJ_LOCKED;             /* Eq 7, L = 3 */
    if (release == RJ_RELEASE_RC12) { /* Eqs 8, 9, 12 */
        if (beyond_forward && (prev == RJ_AT_FORWARD || (prev == RJ_FREE && rate >= 0)))
            return RJ_AT_FORWARD;
        if (beyond_reverse && (prev == RJ_AT_REVERSE || (prev == RJ_FREE && rate <= 0)))
            return RJ_AT_REVERSE;
        return RJ_FREE;
    }
    /* RC13, Eqs 10, 11, 13: the motion must still point into the limit */
    if (beyond_forward && (prev == RJ_FREE || prev == RJ_AT_FORWARD) && rate >= 0)
        return RJ_AT_FORWARD;
    if (beyond_reverse && (prev == RJ_FREE || prev == RJ_AT_REVERSE) && rate <= 0)
        return RJ_AT_REVERSE;
    return RJ_FREE;
}

/* Eq 21. I1 or I2 may be infinite (ground). */
RJDEF double rj_k_adaptive(double I1, double I2, double dt)
{
    double ired;
    if (!rj__finite(I1))
        ired = I2;
    else if (!rj__finite(I2))
        ired = I1;
    else
        ired = I1 * I2 / (I1 + I2);
    return ired / (dt * dt);
}

/* Eqs 23-24: w2' = (w2 (I2 - I1 e) + I1 w1 (1 + e)) / (I1 + I2), w1' = w2' - e (w1 - w2),
   written with the shares so that an infinite I1 (ground) works. */
RJDEF void rj_momentum_balance(double I1, double I2, double e, double *w1, double *w2)
{
    double a1, a2, o1 = *w1, o2 = *w2, n1, n2;
    if (!rj__finite(I1)) {
        a1 = 1.0;
        a2 = 0.0;
    } else if (!rj__finite(I2)) {
        a1 = 0.0;
        a2 = 1.0;
    } else {
        a1 = I1 / (I1 + I2);
        a2 = I2 / (I1 + I2);
    }
    n2 = o2 * (a2 - a1 * e) + a1 * o1 * (1.0 + e);
    n1 = n2 - e * (o1 - o2);
    *w1 = n1;
    *w2 = n2;
}

/* Eqs 25-26: common velocity with the kinetic energy kept. */
RJDEF void rj_energy_balance(double I1, double I2, double *w1, double *w2)
{
    double a1, a2, s, w;
    if (!rj__finite(I1)) {
        a1 = 1.0;
        a2 = 0.0;
    } else if (!rj__finite(I2)) {
        a1 = 0.0;
        a2 = 1.0;
    } else {
        a1 = I1 / (I1 + I2);
        a2 = I2 / (I1 + I2);
    }
    s = a1 * *w1 * fabs(*w1) + a2 * *w2 * fabs(*w2);
    w = (s >= 0 ? 1.0 : -1.0) * sqrt(fabs(s));
    *w1 = w;
    *w2 = w;
}


/* A prescribed joint's running angle at t (rj_actuator_def, RJ_ACTUATOR_PRESCRIBED):
   angle0 until start, then angle0 plus the profile of the time since. */
/* The clamped cubic spline (rest at both ends) through n points (x strictly increasing,
   y): its second derivatives into M, by the tridiagonal solve (Thomas; work: n doubles). */
static void rj__spline_build(int n, const double *x, const double *y, double *M, double *work)
{
    int i;
    /* rows: h_{i-1} M_{i-1} + 2 (h_{i-1} + h_i) M_i + h_i M_{i+1} = 6 (slope_i - slope_{i-1}),
       ends: 2 h M_0 + h M_1 = 6 slope_0, h M_{n-2} + 2 h M_{n-1} = -6 slope_{n-2} */
    for (i = 0; i < n; i++) {
        const double hl = i > 0 ? x[i] - x[i - 1] : 0, hr = i < n - 1 ? x[i + 1] - x[i] : 0;
        const double sl = i > 0 ? (y[i] - y[i - 1]) / hl : 0;
        const double sr = i < n - 1 ? (y[i + 1] - y[i]) / hr : 0;
        const double diag = 2 * (hl + hr), rhs = 6 * (sr - sl);
        const double m = i > 0 ? hl / work[i - 1] : 0;
        work[i] = diag - m * hl;
        M[i] = rhs - m * (i > 0 ? M[i - 1] : 0);
    }
    for (i = n - 1; i >= 0; i--) {
        const double hr = i < n - 1 ? x[i + 1] - x[i] : 0;
        M[i] = (M[i] - (i < n - 1 ? hr * M[i + 1] : 0)) / work[i];
    }
}

/* The spline of rj__spline_build at t, held at the end values outside [x_0, x_{n-1}]. */
static double rj__spline_at(int n, const double *x, const double *y, const double *M, double t)
{
    int k;
    if (!(t > x[0]))
        return y[0];
    for (k = 1; k < n; k++)
        if (t < x[k]) {
            const double h = x[k] - x[k - 1], A = (x[k] - t) / h, B = 1 - A;
            return A * y[k - 1] + B * y[k] +
                   ((A * A * A - A) * M[k - 1] + (B * B * B - B) * M[k]) * h * h / 6;
        }
    return y[n - 1];
}

static double rj__profile_angle(const rj_actuator_def *a, const double *spline, double angle0,
                                double t)
{
    const double tau = t - a->start, v = a->profile_value, T = a->profile_time;
    double x;
    if (a->profile == RJ_PROFILE_TABLE)
        return angle0 + rj__spline_at(a->table_count, a->table_time, a->table_factor, spline,
                                      tau);
    if (!(tau > 0))
        return angle0;
    switch (a->profile) {
    case RJ_PROFILE_RAMP:
        return angle0 + v * tau;
    case RJ_PROFILE_CYCLOIDAL:
        if (tau >= T)
            return angle0 + v;
        x = tau / T;
        return angle0 + v * (x - sin(2.0 * RJ__PI * x) / (2.0 * RJ__PI));
    default:
        if (tau >= T)
            return angle0 + v * (tau - 0.5 * T);
        x = T / (2.0 * RJ__PI);
        return angle0 + (v / T) * (0.5 * tau * tau + x * x * (cos(tau / x) - 1.0));
    }
}

/* A factor in time from a table of count points (times strictly increasing): linear
   between the points, held at the end values outside them; 1 without a table (a load's,
   an actuator's). */
static double rj__time_factor(int count, const double *time, const double *factor, double t)
{
    const int last = count - 1;
    int k;
    if (count == 0)
        return 1.0;
    if (!(t > time[0]))
        return factor[0];
    for (k = 1; k <= last; k++)
        if (t < time[k]) {
            const double t0 = time[k - 1], t1 = time[k];
            const double f0 = factor[k - 1], f1 = factor[k];
            return f0 + (f1 - f0) * ((t - t0) / (t1 - t0));
        }
    return factor[last];
}
/* ------------------------------------------------------------------ validation */
#define RJ__FIELD(buf, fmt, i) snprintf(buf, sizeof buf, fmt, i)

/* The ranges of single members, and their sentences, are the rows of fields.h. They are
   far beyond any material or mechanism, and small enough that what the step, the energy
   accounts and a checkpoint (whose values stay within 1e100) compute from them stays
   within reach: a link of 1e6 m, 1e6 m deep, of 1e30 kg/m^3 under 1e5 m/s^2 has a
   potential of about 1e65 J. */

static int rj__check_num(rj_error *err, const char *field, double v, double lo, int lo_incl,
                         double hi, int hi_incl, const char *what)
{
    int ok = rj__finite(v) && (lo_incl ? v >= lo : v > lo) && (hi_incl ? v <= hi : v < hi);
    if (!ok) {
        rj__fail(err, RJ_ERR_INVALID, field, v, "%s = %g is invalid: %s", field, v, what);
        return 0;
    }
    return 1;
}

/* Whether v is finite and in row r's range. */
static int rj__row_in_range(const rj__field *r, double v)
{
    return rj__finite(v) && (r->lo_in ? v >= r->lo : v > r->lo) &&
           (r->hi_in ? v <= r->hi : v < r->hi);
}

/* Row r of def, item (a prefix such as "links[3]", "solver"): its value in the row's
   range, or the row's sentence (the field's name is written only then: validation is
   linear in the scene, and cheap). Rows of links, nodes and tables are checked by their
   concepts' code. */
static int rj__check_row(rj_error *err, const char *item, const rj__field *r, const void *def)
{
    char f[64];
    int c, v;
    switch (r->type) {
    case RJ__FT_REAL:
    case RJ__FT_ANGLE:
    case RJ__FT_RATE:
    case RJ__FT_LIMIT:
    case RJ__FT_VEC2:
        for (c = 0; c < (r->type == RJ__FT_VEC2 ? 2 : 1); c++) {
            const double x = rj__row_real(def, r, c);
            if (rj__row_in_range(r, x))
                continue;
            if (r->type == RJ__FT_VEC2)
                snprintf(f, sizeof f, "%s.%s[%d]", item, r->member, c);
            else
                snprintf(f, sizeof f, "%s.%s", item, r->member);
            rj__fail(err, RJ_ERR_INVALID, f, x, "%s = %g is invalid: %s", f, x, r->rule);
            return 0;
        }
        return 1;
    case RJ__FT_INT:
    case RJ__FT_ENUM:
    case RJ__FT_BOOL:
    case RJ__FT_PROFILE:
        v = rj__row_int(def, r);
        if (v >= r->lo && v <= r->hi)
            return 1;
        snprintf(f, sizeof f, "%s.%s", item, r->member);
        rj__fail(err, RJ_ERR_INVALID, f, v, "%s = %d is invalid: %s", f, v, r->rule);
        return 0;
    default:
        return 1;
    }
}

/* Every row of a definition of kind (fields.h) that applies to it, in the table's
   order; shape: a link's section shape, -1 for other kinds. */
static int rj__check_rows(rj_error *err, const char *item, int kind, const void *def,
                          int shape)
{
    int n, k;
    const rj__field *t = rj__fields(kind, &n);
    for (k = 0; k < n; k++)
        if (rj__row_applies(&t[k], shape, 0, 0) && !rj__check_row(err, item, &t[k], def))
            return 0;
    return 1;
}

static int rj__all_rigid(const rj_scene_def *sc)
{
    int i;
    for (i = 0; i < sc->link_count; i++)
        if (sc->links[i].fidelity != RJ_LINK_RIGID)
            return 0;
    return 1;
}

/* An array of the scene: count in fewest..100000 and the array there when count > 0.
   name: "link" for link_count and a links array. */
static int rj__check_array(rj_error *err, const char *name, int count, int fewest,
                           const void *array)
{
    char field[32];
    if (count >= fewest && count <= 100000 && (count == 0 || array))
        return 1;
    snprintf(field, sizeof field, "%s_count", name);
    rj__fail(err, RJ_ERR_INVALID, field, count,
             "%s = %d is invalid: need %d..100000 %ss and the %ss array", field, count, fewest, name,
             name);
    return 0;
}

/* Item i of a definitions array (field "links[%d]") was made by its default function
   (maker, "rj_default_link_def()"): its cookie. */
static int rj__check_cookie(rj_error *err, const char *field_format, int i, unsigned cookie,
                            unsigned want, const char *maker)
{
    char f[64];
    if (cookie == want)
        return 1;
    RJ__FIELD(f, field_format, i);
    rj__fail(err, RJ_ERR_INVALID, f, 0, "%s was not initialised with %s", f, maker);
    return 0;
}

/* A table in time (a load's, an actuator's) of item (prefix "loads[2]"): 0 (constant) or
   1..RJ_TABLE_MAX points, times finite and strictly increasing, within +-1e9 s, factors
   within +-1e6. */
static int rj__validate_time_table(rj_error *err, const char *item, int count,
                                   const double *time, const double *factor)
{
    char f[64];
    int k;
    if (count < 0 || count > RJ_TABLE_MAX) {
        snprintf(f, sizeof f, "%s.table_count", item);
        rj__fail(err, RJ_ERR_INVALID, f, count,
                 "%s = %d is invalid: must be 0 (constant) or 1..%d points", f, count,
                 RJ_TABLE_MAX);
        return 0;
    }
    for (k = 0; k < count; k++) {
        snprintf(f, sizeof f, "%s.table_time[%d]", item, k);
        if (!rj__check_num(err, f, time[k], -1e9, 1, 1e9, 1,
                           "must be a finite time within +-1e9 s (further than any run "
                           "reaches, where a step no longer resolves the table)"))
            return 0;
        if (k > 0 && !(time[k] > time[k - 1])) {
            rj__fail(err, RJ_ERR_INVALID, f, time[k],
                     "%s = %g is invalid: the table's times must increase strictly (the point "
                     "before is at %g s)",
                     f, time[k], time[k - 1]);
            return 0;
        }
        snprintf(f, sizeof f, "%s.table_factor[%d]", item, k);
        if (!rj__check_num(err, f, factor[k], -1e6, 1, 1e6, 1,
                           "must be a finite factor within +-1e6"))
            return 0;
    }
    return 1;
}

/* Applied loads: a known link and node, the rows' ranges, a table in time. */
static int rj__validate_loads(const rj_scene_def *sc, rj_error *err)
{
    char f[64], item[32];
    int i;
    if (!rj__check_array(err, "load", sc->load_count, 0, sc->loads))
        return 0;
    for (i = 0; i < sc->load_count; i++) {
        const rj_load_def *d = &sc->loads[i];
        if (!rj__check_cookie(err, "loads[%d]", i, d->cookie, RJ__COOKIE_LOAD,
                              "rj_default_load_def()"))
            return 0;
        if (d->link < 0 || d->link >= sc->link_count) {
            RJ__FIELD(f, "loads[%d].link", i);
            rj__fail(err, RJ_ERR_INVALID, f, d->link,
                     "%s = %d is invalid: the scene has links 0..%d", f, d->link,
                     sc->link_count - 1);
            return 0;
        }
        if (d->node < -1 || d->node > sc->links[d->link].elements) {
            RJ__FIELD(f, "loads[%d].node", i);
            rj__fail(err, RJ_ERR_INVALID, f, d->node,
                     "%s = %d is invalid: link %d has nodes 0..%d (-1: the last)", f, d->node,
                     d->link, sc->links[d->link].elements);
            return 0;
        }
        RJ__FIELD(item, "loads[%d]", i);
        if (!rj__check_rows(err, item, RJ__DEF_LOAD, d, -1))
            return 0;
        if (!rj__validate_time_table(err, item, d->table_count, d->table_time, d->table_factor))
            return 0;
    }
    return 1;
}

/* The solver: its rows. */
static int rj__validate_solver(const rj_solver_def *s, rj_error *err)
{
    if (s->cookie != RJ__COOKIE_SOLVER) {
        rj__fail(err, RJ_ERR_INVALID, "solver", 0,
                 "solver was not initialised with rj_default_solver_def()");
        return 0;
    }
    return rj__check_rows(err, "solver", RJ__DEF_SOLVER, s, -1);
}

/* Link i: its section's shape first (which rows apply depends on it), then its rows; a
   rectangle's height is > 0. */
/* A link's structural damping: on a link that strains (a rigid one has none to damp), a
   ratio with its frequency, and eta or the ratio, not both. */
static int rj__validate_link_damping(const rj_link_def *L, int i, rj_error *err)
{
    char f[64];
    const int any = L->eta > 0 || L->damping[0] > 0 || L->mass_damping > 0;
    if (any && L->fidelity == RJ_LINK_RIGID) {
        RJ__FIELD(f, "links[%d].eta", i);
        rj__fail(err, RJ_ERR_INVALID, f, L->eta,
                 "links[%d] is rigid: eta, damping and mass_damping damp a link's strain and "
                 "vibration, which a rigid link does not have (use joint damping)",
                 i);
        return 0;
    }
    if (L->damping[0] > 0 && !(L->damping[1] > 0)) {
        RJ__FIELD(f, "links[%d].damping[1]", i);
        rj__fail(err, RJ_ERR_INVALID, f, L->damping[1],
                 "%s = %g is invalid: a damping ratio needs the frequency it holds at, > 0 Hz",
                 f, L->damping[1]);
        return 0;
    }
    if (L->damping[0] > 0 && L->eta > 0) {
        RJ__FIELD(f, "links[%d].damping", i);
        rj__fail(err, RJ_ERR_INVALID, f, L->damping[0],
                 "%s = %g %g and eta = %g: give eta or a damping ratio, not both", f,
                 L->damping[0], L->damping[1], L->eta);
        return 0;
    }
    return 1;
}

/* A link's yielding layers: a flexible link (a rigid one has no strain, an inextensible
   one's axial force is a constraint's) of rectangular section (its layers are the
   sections the plastic strains live in), and a state of size that an int indexes. The
   Biot law is a flexible link's axial law. */
static int rj__validate_link_plastic(const rj_link_def *L, int i, rj_error *err)
{
    char f[64];
    const double strains = 2.0 * L->layers * (double) L->elements;
    if (L->strain == RJ_STRAIN_BIOT && L->fidelity != RJ_LINK_FLEXIBLE) {
        RJ__FIELD(f, "links[%d].strain", i);
        rj__fail(err, RJ_ERR_INVALID, f, L->strain,
                 "%s = RJ_STRAIN_BIOT is an axial law for a flexible link; links[%d] is %s", f,
                 i, L->fidelity == RJ_LINK_RIGID ? "rigid" : "inextensible");
        return 0;
    }
    if (!(L->yield > 0))
        return 1;
    RJ__FIELD(f, "links[%d].yield", i);
    if (L->fidelity != RJ_LINK_FLEXIBLE || L->section != RJ_SECTION_RECT) {
        rj__fail(err, RJ_ERR_INVALID, f, L->yield,
                 "%s = %g: yielding layers need a flexible link of rectangular section "
                 "(links[%d] is %s)",
                 f, L->yield, i,
                 L->fidelity == RJ_LINK_RIGID          ? "rigid"
                 : L->fidelity == RJ_LINK_INEXTENSIBLE ? "inextensible"
                                                       : "of general section");
        return 0;
    }
    if (L->layers < 2) {
        rj__fail(err, RJ_ERR_INVALID, f, L->yield,
                 "%s = %g needs 2 or more layers (links[%d].layers = %d): a single layer "
                 "sits at mid-depth, where bending never strains it",
                 f, L->yield, i, L->layers);
        return 0;
    }
    if (strains > 1e8) {
        rj__fail(err, RJ_ERR_INVALID, f, L->yield,
                 "%s = %g: %d layers of %d elements are %.3g plastic strains (two sections "
                 "an element), more than the 1e8 a link may keep",
                 f, L->yield, L->layers, L->elements, strains);
        return 0;
    }
    return 1;
}

/* The scene's plastic strains all told: an int indexes them (1e9 at most). */
static int rj__validate_plastic_total(const rj_scene_def *sc, rj_error *err)
{
    double total = 0;
    int i;
    for (i = 0; i < sc->link_count; i++)
        if (sc->links[i].yield > 0)
            total += 2.0 * sc->links[i].layers * (double) sc->links[i].elements;
    if (total <= 1e9)
        return 1;
    rj__fail(err, RJ_ERR_INVALID, "links", total,
             "the yielding links keep %.3g plastic strains all told, more than the 1e9 a "
             "scene may",
             total);
    return 0;
}

static int rj__validate_link(const rj_link_def *L, int i, rj_error *err)
{
    char f[64], item[32];
    if (!rj__check_cookie(err, "links[%d]", i, L->cookie, RJ__COOKIE_LINK,
                          "rj_default_link_def()"))
        return 0;
    RJ__FIELD(item, "links[%d]", i);
    if (!rj__check_row(err, item, &rj__link_fields[RJ__LF_SHAPE], L))
        return 0;
    if (!rj__check_rows(err, item, RJ__DEF_LINK, L, L->section))
        return 0;
    if (L->section == RJ_SECTION_RECT && !(L->height > 0)) {
        const rj__field *r = &rj__link_fields[RJ__LK_HEIGHT];
        RJ__FIELD(f, "links[%d].height", i);
        rj__fail(err, RJ_ERR_INVALID, f, L->height, "%s = %g is invalid: %s", f, L->height,
                 r->rule);
        return 0;
    }
    return rj__validate_link_damping(L, i, err) && rj__validate_link_plastic(L, i, err);
}

/* Joint j's bodies: links of the scene (body1 may be ground), two of them, a node body1
   has, and body2 free to hang from the joint. */
static int rj__validate_bodies(const rj_scene_def *sc, const rj_joint_def *J, int j,
                               rj_error *err)
{
    char f[64];
    if (J->body1 < -1 || J->body1 >= sc->link_count) {
        RJ__FIELD(f, "joints[%d].body1", j);
        rj__fail(err, RJ_ERR_INVALID, f, J->body1,
                 "%s = %d is invalid: a link index 0..%d or -1 for ground", f, J->body1,
                 sc->link_count - 1);
        return 0;
    }
    if (J->body2 < 0 || J->body2 >= sc->link_count) {
        RJ__FIELD(f, "joints[%d].body2", j);
        rj__fail(err, RJ_ERR_INVALID, f, J->body2, "%s = %d is invalid: a link index 0..%d", f,
                 J->body2, sc->link_count - 1);
        return 0;
    }
    if (J->body1 == J->body2) {
        RJ__FIELD(f, "joints[%d].body2", j);
        rj__fail(err, RJ_ERR_INVALID, f, J->body2,
                 "%s = %d is invalid: a joint cannot connect link %d to itself", f, J->body2,
                 J->body2);
        return 0;
    }
    if (J->body1 >= 0 && (J->node1 < -1 || J->node1 > sc->links[J->body1].elements)) {
        RJ__FIELD(f, "joints[%d].node1", j);
        rj__fail(err, RJ_ERR_INVALID, f, J->node1,
                 "%s = %d is invalid: a node 0..%d of link %d, or -1 for its last node", f,
                 J->node1, sc->links[J->body1].elements, J->body1);
        return 0;
    }
    if (J->node2 < -1 || J->node2 > sc->links[J->body2].elements) {
        RJ__FIELD(f, "joints[%d].node2", j);
        rj__fail(err, RJ_ERR_INVALID, f, J->node2,
                 "%s = %d is invalid: a node 0..%d of link %d, or -1 for its last node", f,
                 J->node2, sc->links[J->body2].elements, J->body2);
        return 0;
    }
    if (J->node2 != 0 &&
        J->reference != RJ_REF_TANGENT) {
        RJ__FIELD(f, "joints[%d].node2", j);
        rj__fail(err, RJ_ERR_INVALID, f, J->node2,
                 "%s = %d is not supported: a pin away from body2's first node needs the "
                 "tangent reference",
                 f, J->node2);
        return 0;
    }
    if (sc->links[J->body2].root != RJ_ROOT_FREE) {
        RJ__FIELD(f, "links[%d].root", J->body2);
        rj__fail(err, RJ_ERR_INVALID, f, sc->links[J->body2].root,
                 "%s = %d is invalid: link %d is body2 of joint %d, its root must be RJ_ROOT_FREE",
                 f, sc->links[J->body2].root, J->body2, j);
        return 0;
    }
    return 1;
}

/* A joint's table (Eq 4): 0, or 2..RJ_TABLE_MAX points, angles in [0, 2 pi], finite
   torques. */
static int rj__validate_joint_table(const rj_joint_def *J, int j, rj_error *err)
{
    char f[64];
    int k;
    if (J->table_count != 0 && (J->table_count < 2 || J->table_count > RJ_TABLE_MAX)) {
        RJ__FIELD(f, "joints[%d].table_count", j);
        rj__fail(err, RJ_ERR_INVALID, f, J->table_count, "%s = %d is invalid: 0, or 2..%d points",
                 f, J->table_count, RJ_TABLE_MAX);
        return 0;
    }
    for (k = 0; k < J->table_count; k++) {
        snprintf(f, sizeof f, "joints[%d].table_angle[%d]", j, k);
        if (!rj__check_num(err, f, J->table_angle[k], 0, 1, RJ__TWO_PI, 1,
                           "must be in [0, 2 pi] rad"))
            return 0;
        snprintf(f, sizeof f, "joints[%d].table_torque[%d]", j, k);
        if (!rj__check_num(err, f, J->table_torque[k], -HUGE_VAL, 0, HUGE_VAL, 0,
                           RJ__RULE_FINITE))
            return 0;
    }
    return 1;
}

/* A joint's limits: a lock latches at one, two limits leave a free range between them,
   and a penalty limit has a stiffness. */
static int rj__validate_limits(const rj_joint_def *J, int j, rj_error *err)
{
    char f[64];
    if (J->lock && !J->has_forward && !J->has_reverse) {
        RJ__FIELD(f, "joints[%d].lock", j);
        rj__fail(err, RJ_ERR_INVALID, f, J->lock,
                 "%s = 1 is invalid: a lock latches at a limit, and joint %d has none (set "
                 "has_forward or has_reverse)",
                 f, j);
        return 0;
    }
    if (J->has_forward && J->has_reverse && J->forward == J->reverse) {
        RJ__FIELD(f, "joints[%d].forward", j);
        rj__fail(err, RJ_ERR_INVALID, f, J->forward,
                 "%s = %g is invalid: equal to the reverse limit leaves no free range", f,
                 J->forward);
        return 0;
    }
    if (J->method == RJ_METHOD_PENALTY && (J->has_forward || J->has_reverse) &&
        !(J->penalty_k > 0)) {
        RJ__FIELD(f, "joints[%d].penalty_k", j);
        rj__fail(err, RJ_ERR_INVALID, f, J->penalty_k,
                 "%s = %g is invalid: RJ_METHOD_PENALTY with a limit needs a stiffness > 0", f,
                 J->penalty_k);
        return 0;
    }
    return 1;
}

/* Joint j: its bodies, its rows, its table, its limits. */
static int rj__validate_joint(const rj_scene_def *sc, int j, rj_error *err)
{
    const rj_joint_def *J = &sc->joints[j];
    char item[32];
    if (!rj__check_cookie(err, "joints[%d]", j, J->cookie, RJ__COOKIE_JOINT,
                          "rj_default_joint_def()"))
        return 0;
    RJ__FIELD(item, "joints[%d]", j);
    return rj__validate_bodies(sc, J, j, err) && rj__check_rows(err, item, RJ__DEF_JOINT, J, -1) &&
           rj__validate_joint_table(J, j, err) && rj__validate_limits(J, j, err);
}

/* A joint between two rigid bodies of a mixed scene (their pin is kept by
   rj__body_pins, after the rows): what it may not have yet, the field, or NULL. Its
   limits, lock and friction, a prescribed profile or a cable loop act through rows whose
   gives do not see the pin (tried: an adaptive limit blew up, a plastic latch lost 1.5 J
   of 3.9 J unbooked); its spring, table, damping and a motor's torque act as torques. */
static const char *rj__body_pair_refusal(const rj_scene_def *sc, int j, char *f, size_t n)
{
    const rj_joint_def *J = &sc->joints[j];
    f[0] = 0;
    /* every part is a torque there (rj__stage_pair_latches) but the energy method's
       balance (Eqs 25-26), which would need the pinned pair's inertia */
    if ((J->has_forward || J->has_reverse) && J->method == RJ_METHOD_ENERGY)
        snprintf(f, n, "joints[%d].method", j);
    return f[0] ? f : NULL;
}

/* Mixed scenes (a rigid link is one rigid body, with flexible links pinned to it): a
   joint between two rigid links without the parts rj__body_pair_refusal names, and
   tangent references on rigid links. Scenes of rigid links alone have no energy
   method. */
static int rj__validate_mixed(const rj_scene_def *sc, rj_error *err)
{
    char f[64];
    int j;
    if (rj__all_rigid(sc)) {
        for (j = 0; j < sc->joint_count; j++)
            if (sc->joints[j].method == RJ_METHOD_ENERGY) {
                RJ__FIELD(f, "joints[%d].method", j);
                rj__fail(err, RJ_ERR_INVALID, f, RJ_METHOD_ENERGY,
                         "%s = RJ_METHOD_ENERGY is not available for rigid links (use momentum "
                         "with e = 0, forced or adaptive)",
                         f);
                return 0;
            }
        return 1;
    }
    for (j = 0; j < sc->joint_count; j++) {
        const rj_joint_def *J = &sc->joints[j];
        const int r1 = J->body1 >= 0 && sc->links[J->body1].fidelity == RJ_LINK_RIGID,
                  r2 = sc->links[J->body2].fidelity == RJ_LINK_RIGID;
        if (r1 && r2 && rj__body_pair_refusal(sc, j, f, sizeof f)) {
            rj__fail(err, RJ_ERR_INVALID, f, j,
                     "%s is not supported: joint %d pins two rigid links (%d and %d) in a scene "
                     "with flexible links, where it takes a spring, a table, damping, friction, "
                     "a motor's torque, a prescribed profile, cable loops, and limits and locks "
                     "by any method but energy: make every link rigid, or one of the two "
                     "flexible",
                     f, j, J->body1, J->body2);
            return 0;
        }
        if ((r1 || r2) && J->reference == RJ_REF_CHORD) {
            RJ__FIELD(f, "joints[%d].reference", j);
            rj__fail(err, RJ_ERR_INVALID, f, J->reference,
                     "%s = RJ_REF_CHORD is invalid: joint %d holds rigid link %d in a scene "
                     "with flexible links; use RJ_REF_TANGENT (on a rigid link the chord and "
                     "the tangent are the same line)",
                     f, j, r1 ? J->body1 : J->body2);
            return 0;
        }
    }
    return 1;
}

/* Actuator i's joint: one of the scene's, driven by no other actuator before it. */
static int rj__validate_actuator_joint(const rj_scene_def *sc, int i, rj_error *err)
{
    const rj_actuator_def *d = &sc->actuators[i];
    char f[64];
    int k;
    RJ__FIELD(f, "actuators[%d].joint", i);
    if (d->joint < 0 || d->joint >= sc->joint_count) {
        rj__fail(err, RJ_ERR_INVALID, f, d->joint, "%s = %d is invalid: the scene has joints 0..%d",
                 f, d->joint, sc->joint_count - 1);
        return 0;
    }
    for (k = 0; k < i; k++)
        if (sc->actuators[k].joint == d->joint) {
            rj__fail(err, RJ_ERR_INVALID, f, d->joint,
                     "%s = %d is invalid: actuators[%d] drives joint %d already (a joint has "
                     "at most one actuator)",
                     f, d->joint, k, d->joint);
            return 0;
        }
    return 1;
}

/* A DC motor's no-load speed: not 0, and of its stall torque's sign (the direction it
   drives). */
static int rj__validate_dc(const rj_actuator_def *d, int i, rj_error *err)
{
    const rj__field *r = &rj__actuator_fields[RJ__CK_NO_LOAD_SPEED];
    char f[64];
    if (d->type != RJ_ACTUATOR_DC)
        return 1;
    if (d->no_load_speed != 0 && !(d->stall_torque * d->no_load_speed < 0))
        return 1;
    RJ__FIELD(f, "actuators[%d].no_load_speed", i);
    rj__fail(err, RJ_ERR_INVALID, f, d->no_load_speed, "%s = %g is invalid: %s (%g N m)", f,
             d->no_load_speed, r->rule, d->stall_torque);
    return 0;
}

/* A prescribed joint's angle follows its profile: a limit or a lock on it is refused. */
static int rj__validate_prescribed(const rj_scene_def *sc, const rj_actuator_def *d, int i,
                                   rj_error *err)
{
    const rj_joint_def *J = &sc->joints[d->joint];
    char f[64];
    if (d->type != RJ_ACTUATOR_PRESCRIBED || (!J->has_forward && !J->has_reverse && !J->lock))
        return 1;
    RJ__FIELD(f, "actuators[%d].type", i);
    rj__fail(err, RJ_ERR_INVALID, f, d->type,
             "%s = RJ_ACTUATOR_PRESCRIBED is invalid: joint %d has a limit or a lock, and a "
             "prescribed joint's angle follows its profile alone (remove the limits, or drive "
             "it with a servo)",
             f, d->joint);
    return 0;
}

/* Joint j's pin on body 1 as (link, node), node -1 for ground; body 2's is (body2, 0). */
static void rj__pin_of(const rj_scene_def *sc, int j, int *link, int *node)
{
    const rj_joint_def *J = &sc->joints[j];
    *link = J->body1;
    *node = J->body1 < 0 ? -1 : J->node1 < 0 ? sc->links[J->body1].elements : J->node1;
}

/* Whether joints j and k share a pin node (their rotors would couple one node twice). */
static int rj__pins_meet(const rj_scene_def *sc, int j, int k)
{
    int lj, nj, lk, nk;
    rj__pin_of(sc, j, &lj, &nj);
    rj__pin_of(sc, k, &lk, &nk);
    return (lj >= 0 && lj == lk && nj == nk) || (lj == sc->joints[k].body2 && nj == 0) ||
           (lk == sc->joints[j].body2 && nk == 0);
}

/* A motor's rotor: a gear ratio not 0; on a joint with the tangent reference, between
   flexible bodies (or ground) unless every link is rigid, with pin nodes no other rotor's
   joint uses. */
static int rj__validate_rotor(const rj_scene_def *sc, int i, rj_error *err)
{
    const rj_actuator_def *d = &sc->actuators[i];
    const rj_joint_def *J = &sc->joints[d->joint];
    const char *why = NULL;
    char f[64];
    int k;
    if (d->gear_ratio == 0) {
        RJ__FIELD(f, "actuators[%d].gear_ratio", i);
        rj__fail(err, RJ_ERR_INVALID, f, 0, "%s = 0 is invalid: %s", f,
                 rj__actuator_fields[RJ__CK_GEAR_RATIO].rule);
        return 0;
    }
    if (!(d->rotor_inertia > 0) || rj__all_rigid(sc))
        return 1;
    if (J->reference != RJ_REF_TANGENT)
        why = "its joint uses the chord reference (a rotor needs the tangent)";
    else if (sc->links[J->body2].fidelity == RJ_LINK_RIGID ||
             (J->body1 >= 0 && sc->links[J->body1].fidelity == RJ_LINK_RIGID))
        why = "its joint holds a rigid link in a scene with flexible links";
    for (k = 0; k < i && !why; k++)
        if (sc->actuators[k].rotor_inertia > 0 && rj__pins_meet(sc, d->joint, sc->actuators[k].joint))
            why = "its joint shares a pin node with another rotor's joint";
    if (!why)
        return 1;
    RJ__FIELD(f, "actuators[%d].rotor_inertia", i);
    rj__fail(err, RJ_ERR_INVALID, f, d->rotor_inertia, "%s = %g is not supported: %s", f,
             d->rotor_inertia, why);
    return 0;
}

/* A servo's or a prescribed joint's table is its profile's (profile = table): 2 points at
   least, and a prescribed one starts at 0 rad (the joint starts at angle0); without that
   profile it has none. */
static int rj__validate_profile_table(const rj_actuator_def *d, int i, rj_error *err)
{
    const char *why = NULL;
    char f[64];
    if (d->type == RJ_ACTUATOR_TORQUE || d->type == RJ_ACTUATOR_DC)
        return 1;
    if (d->profile != RJ_PROFILE_TABLE && d->table_count != 0)
        why = "a table applies with profile = table";
    else if (d->profile == RJ_PROFILE_TABLE && d->table_count < 2)
        why = "profile = table needs a table of 2 points at least";
    else if (d->profile == RJ_PROFILE_TABLE && d->type == RJ_ACTUATOR_PRESCRIBED &&
             d->table_factor[0] != 0)
        why = "a prescribed table's first angle is 0 rad (the joint starts at angle0)";
    if (!why)
        return 1;
    RJ__FIELD(f, "actuators[%d].table_count", i);
    rj__fail(err, RJ_ERR_INVALID, f, d->table_count, "%s = %d is invalid: %s", f,
             d->table_count, why);
    return 0;
}

/* Actuators: a joint each, the rows of their type, a table in time. */
static int rj__validate_actuators(const rj_scene_def *sc, rj_error *err)
{
    char item[32];
    int i;
    if (!rj__check_array(err, "actuator", sc->actuator_count, 0, sc->actuators))
        return 0;
    for (i = 0; i < sc->actuator_count; i++) {
        const rj_actuator_def *d = &sc->actuators[i];
        if (!rj__check_cookie(err, "actuators[%d]", i, d->cookie, RJ__COOKIE_ACTUATOR,
                              "rj_default_actuator_def()"))
            return 0;
        RJ__FIELD(item, "actuators[%d]", i);
        if (!rj__check_row(err, item, &rj__actuator_fields[RJ__CK_TYPE], d) ||
            !rj__validate_actuator_joint(sc, i, err) ||
            !rj__check_rows(err, item, RJ__DEF_ACTUATOR, d, d->type) ||
            !rj__validate_dc(d, i, err) || !rj__validate_prescribed(sc, d, i, err) ||
            !rj__validate_rotor(sc, i, err))
            return 0;
        if (!rj__validate_time_table(err, item, d->table_count, d->table_time, d->table_factor) ||
            !rj__validate_profile_table(d, i, err))
            return 0;
    }
    return 1;
}

/* An exact coupling is a constraint: no stiffness or damping of its own; on joints with
   the tangent reference (a chord's impulse moves the chord's far nodes, whose work the
   rows' form does not count). */
static int rj__validate_exact(const rj_scene_def *sc, const rj_coupling_def *d, int i,
                              rj_error *err)
{
    const int joint[2] = { d->joint_a, d->joint_b };
    const char *why = NULL;
    char f[64];
    int k;
    if (!d->exact)
        return 1;
    if (d->stiffness != 0 || d->damping != 0)
        why = "an exact coupling is a constraint: give it no stiffness or damping";
    for (k = 0; k < 2 && !why; k++) {
        const rj_joint_def *J = &sc->joints[joint[k]];
        if (J->reference != RJ_REF_TANGENT)
            why = "an exact coupling needs the tangent reference on both joints";
    }
    if (!why)
        return 1;
    RJ__FIELD(f, "couplings[%d].exact", i);
    rj__fail(err, RJ_ERR_INVALID, f, 1, "%s = 1 is not supported: %s", f, why);
    return 0;
}

/* Couplings: two different joints of the scene, and the rows. */
static int rj__validate_couplings(const rj_scene_def *sc, rj_error *err)
{
    char f[64], item[32];
    int i;
    if (!rj__check_array(err, "coupling", sc->coupling_count, 0, sc->couplings))
        return 0;
    for (i = 0; i < sc->coupling_count; i++) {
        const rj_coupling_def *d = &sc->couplings[i];
        if (!rj__check_cookie(err, "couplings[%d]", i, d->cookie, RJ__COOKIE_COUPLING,
                              "rj_default_coupling_def()"))
            return 0;
        if (d->joint_a < 0 || d->joint_a >= sc->joint_count) {
            RJ__FIELD(f, "couplings[%d].joint_a", i);
            rj__fail(err, RJ_ERR_INVALID, f, d->joint_a,
                     "%s = %d is invalid: the scene has joints 0..%d", f, d->joint_a,
                     sc->joint_count - 1);
            return 0;
        }
        if (d->joint_b < 0 || d->joint_b >= sc->joint_count || d->joint_b == d->joint_a) {
            RJ__FIELD(f, "couplings[%d].joint_b", i);
            rj__fail(err, RJ_ERR_INVALID, f, d->joint_b,
                     "%s = %d is invalid: a joint 0..%d other than joint_a (%d)", f, d->joint_b,
                     sc->joint_count - 1, d->joint_a);
            return 0;
        }
        RJ__FIELD(item, "couplings[%d]", i);
        if (!rj__check_rows(err, item, RJ__DEF_COUPLING, d, -1) ||
            !rj__validate_exact(sc, d, i, err))
            return 0;
    }
    return 1;
}

static int rj__validate(const rj_scene_def *sc, rj_error *err)
{
    int i, j;
    if (!sc) {
        rj__fail(err, RJ_ERR_INVALID, "scene", 0, "scene is NULL");
        return 0;
    }
    if (!rj__check_array(err, "link", sc->link_count, 1, sc->links) ||
        !rj__check_array(err, "joint", sc->joint_count, 0, sc->joints))
        return 0;
    if (!rj__validate_solver(&sc->solver, err))
        return 0;
    for (i = 0; i < sc->link_count; i++)
        if (!rj__validate_link(&sc->links[i], i, err))
            return 0;
    if (!rj__validate_plastic_total(sc, err))
        return 0;
    for (j = 0; j < sc->joint_count; j++)
        if (!rj__validate_joint(sc, j, err))
            return 0;
    return rj__validate_mixed(sc, err) && rj__validate_loads(sc, err) &&
           rj__validate_actuators(sc, err) && rj__validate_couplings(sc, err);
}

/* Node and element totals, counted in size_t; 0 when they pass RJ__MAX_NODES. */
static int rj__counts(const rj_scene_def *sc, size_t *nn, size_t *ne, rj_error *err)
{
    int i;
    *nn = 0;
    *ne = 0;
    for (i = 0; i < sc->link_count; i++) {
        *nn += (size_t) sc->links[i].elements + 1;
        *ne += (size_t) sc->links[i].elements;
    }
    if (*nn > RJ__MAX_NODES) {
        rj__fail(err, RJ_ERR_INVALID, "links", (double) *nn,
                 "the scene has %.0f nodes in all, more than the %d a model can hold (node indices "
                 "are ints)",
                 (double) *nn, RJ__MAX_NODES);
        return 0;
    }
    return 1;
}

/* The link a link hangs from (-1: ground or none), given each link's joint in parent. */
static int rj__up(const rj_scene_def *sc, const int *parent, int link)
{
    return parent[link] >= 0 ? sc->joints[parent[link]].body1 : -1;
}

/* The node a joint pins on body1 (-1 for ground), numbered across the scene (first[l]:
   link l's first node), the key the pin check sorts joints by. */
static long rj__pin_key(const rj_scene_def *sc, const int *first, int j)
{
    const rj_joint_def *J = &sc->joints[j];
    if (J->body1 < 0)
        return -1;
    return (long) first[J->body1] + (J->node1 < 0 ? sc->links[J->body1].elements : J->node1);
}

/* Sorts joint indices by (pin node, index): heap sort, in place and without recursion. */
static void rj__sort_pins(const rj_scene_def *sc, const int *first, int *idx, int n)
{
    int end, root, child, top;
    for (top = n / 2 - 1, end = n; end > 1 || top >= 0;) {
        if (top >= 0)
            root = top--;
        else {
            const int t = idx[0];
            idx[0] = idx[--end];
            idx[end] = t;
            root = 0;
        }
        /* sift idx[root] down among idx[0 .. end) */
        for (; (child = 2 * root + 1) < end; root = child) {
            long kc = rj__pin_key(sc, first, idx[child]), kr;
            if (child + 1 < end) {
                const long k2 = rj__pin_key(sc, first, idx[child + 1]);
                if (k2 > kc || (k2 == kc && idx[child + 1] > idx[child])) {
                    child++;
                    kc = k2;
                }
            }
            kr = rj__pin_key(sc, first, idx[root]);
            if (kr > kc || (kr == kc && idx[root] > idx[child]))
                break;
            {
                const int t = idx[root];
                idx[root] = idx[child];
                idx[child] = t;
            }
        }
    }
}

/* The rigid link a joint holds in a mixed scene (body2 when rigid, else body1). */
static int rj__pin_rigid(const rj_scene_def *sc, int j)
{
    const rj_joint_def *J = &sc->joints[j];
    return sc->links[J->body2].fidelity == RJ_LINK_RIGID ? J->body2 : J->body1;
}

/* Two rigid links may not share a pin through a flexible node in a mixed scene. The
   joints that hold a rigid link at a body1 node, sorted by (node, index): at each node the
   first names the rigid link there, and the earliest joint that names another is the
   error (as a scan of the joints in order would find it). Scratch: nl + nj ints. */
static int rj__validate_pins(const rj_scene_def *sc, int *first, int *idx, rj_error *err)
{
    char f[64];
    int i, j, end, n = 0, bad = -1, bad_first = -1;
    long nodes = 0;
    for (i = 0; i < sc->link_count; i++) {
        first[i] = (int) nodes;
        nodes += sc->links[i].elements + 1;
    }
    for (j = 0; j < sc->joint_count; j++) {
        const rj_joint_def *J = &sc->joints[j];
        if (J->body1 < 0)
            continue;
        if (sc->links[J->body1].fidelity == RJ_LINK_RIGID ||
            sc->links[J->body2].fidelity == RJ_LINK_RIGID)
            idx[n++] = j;
    }
    rj__sort_pins(sc, first, idx, n);
    for (i = 0; i < n; i = end) {
        const int head = idx[i];
        const long key = rj__pin_key(sc, first, head);
        for (end = i + 1; end < n && rj__pin_key(sc, first, idx[end]) == key; end++) {
            const int k = idx[end];
            if (bad >= 0 && k > bad)
                continue;
            if (rj__pin_rigid(sc, k) == rj__pin_rigid(sc, head))
                continue;
            bad = k;
            bad_first = head;
        }
    }
    if (bad < 0)
        return 1;
    RJ__FIELD(f, "joints[%d].body1", bad);
    rj__fail(err, RJ_ERR_INVALID, f, sc->joints[bad].body1,
             "%s = %d is invalid: joints %d and %d pin rigid links %d and %d at the same node in a "
             "scene with flexible links, which is not supported",
             f, sc->joints[bad].body1, bad_first, bad, rj__pin_rigid(sc, bad_first),
             rj__pin_rigid(sc, bad));
    return 0;
}

/* The checks of the joint graph, in time linear in the scene (n log n for the pins of
   mixed scenes), with scratch of 2 nl + nj ints (RJ__GRAPH_SCRATCH): a link hangs from one joint; in a scene of rigid links each
   hangs from a joint or is fixed; mixed scenes' pins (rj__validate_pins); the joints form
   a forest. */
static int rj__validate_graph(const rj_scene_def *sc, int *scratch, rj_error *err)
{
    const int nl = sc->link_count;
    int *parent = scratch, *mark = scratch + nl, *joints = scratch + 2 * (size_t) nl;
    char f[64];
    int i, j;
    for (i = 0; i < nl; i++)
        parent[i] = -1;
    /* a link hangs from its first joint as body2: parent[] holds it; a later joint with
       the same body2 closes a loop, with every part a tree joint has */
    for (j = 0; j < sc->joint_count; j++) {
        const int b2 = sc->joints[j].body2;
        if (parent[b2] < 0)
            parent[b2] = j;
    }
    if (rj__all_rigid(sc))
        for (i = 0; i < nl; i++)
            if (parent[i] < 0 && sc->links[i].root != RJ_ROOT_FIXED) {
                RJ__FIELD(f, "links[%d].root", i);
                rj__fail(err, RJ_ERR_INVALID, f, sc->links[i].root,
                         "%s = %d is invalid: in a scene of rigid links each must hang from a "
                         "joint or be RJ_ROOT_FIXED",
                         f, sc->links[i].root);
                return 0;
            }
    if (!rj__all_rigid(sc) && !rj__validate_pins(sc, mark, joints, err))
        return 0;
    /* the joint graph must be a forest: walking up from any link ends at a root. A walk
       marks its links 1 while under way and 2 once it is known to reach a root, so each
       link is walked once; meeting a 1 is a loop */
    for (i = 0; i < nl; i++)
        mark[i] = 0;
    for (i = 0; i < nl; i++) {
        int cur = i, top;
        while (cur >= 0 && mark[cur] == 0) {
            mark[cur] = 1;
            cur = rj__up(sc, parent, cur);
        }
        if (cur >= 0 && mark[cur] == 1) {
            RJ__FIELD(f, "links[%d]", i);
            rj__fail(err, RJ_ERR_INVALID, f, i,
                     "the joints that hang links from each other form a loop through link %d "
                     "that no joint holds to the ground or a fixed link",
                     i);
            return 0;
        }
        top = cur;
        for (cur = i; cur != top; cur = rj__up(sc, parent, cur))
            mark[cur] = 2;
    }
    return 1;
}

/* ------------------------------------------------------------------ memory layout */
/* The next aligned offset for count elements; a block past what size_t counts (a 32-bit
   size_t) saturates at (size_t)-1, which no allocation satisfies. */
static size_t rj__carve(size_t *off, size_t count, size_t elsize)
{
    const size_t full = (size_t) -1;
    size_t at;
    if (*off > full - 2 * RJ__ALIGN)
        return *off = full;
    at = (*off + RJ__ALIGN - 1) / RJ__ALIGN * RJ__ALIGN;
    if (count > (full - 2 * RJ__ALIGN - at) / elsize)
        return *off = full;
    *off = at + count * elsize;
    return at;
}

typedef struct rj__layout {
    size_t total, ldef, jdef, jnt, link_first, link_efirst, link_l0, link_EA, link_EI, link_rho,
        link_I;
    size_t node_cl, bp_node, cl_first, cl_node, cl_fix, cl_M, cl_I, cl_th0, cl_rx, cl_ry;
    size_t node_grp, ch_first, ch_node, ch_l0sq, gs_int, gs_l0sq, rb_mass, rb_icm, rb_dcm, rb_pjoint, jorder, qj, jq, wcol, jpin,
        jref, mass, rinertia, tinv, rinv, einv, kmass, krot, grp_first, grp_node, grp_inv, dnode,
        link_un, link_kc, link_path, link_pl, link_damp, visc_first, visc_joint, x0, y0, phi0, vx0, vy0, w0, beta0, load, load_node, act, spl, cp, lz;
} rj__layout;

/* Whether a rigid scene of nq coordinates, nloop joints that close loops and ncp
   couplings is solved by articulated bodies (rj_model.rig_tree) rather than a dense M. */
static int rj__rig_is_tree(int nq, int nloop, int ncp)
{
    return !nloop && !ncp && nq >= RJ__RIG_TREE_MIN;
}

/* rj__rig_is_tree for a scene of rigid links, before its model is built. A valid scene
   hangs each link that is not fixed from the first joint that names it body 2, and names
   no fixed link body 2: the coordinates are the links less the fixed ones, and every
   other joint closes a loop (rj__init_joint_nodes counts them the same). */
static int rj__scene_rig_tree(const rj_scene_def *sc)
{
    int l, nq = 0;
    for (l = 0; l < sc->link_count; l++)
        nq += sc->links[l].root != RJ_ROOT_FIXED;
    return rj__rig_is_tree(nq, sc->joint_count - nq, sc->coupling_count);
}

/* The rigid stability bound's scratch in the building area (rj__rig_setup): the solver's
   without columns or rows, then for a dense M the nj x nj M^-1, for a tree each
   coordinate's 3 x 3 response (rj__rig_tree_minv). */
static size_t rj__rig_bound_scratch(const rj_scene_def *sc)
{
    const size_t nj = (size_t) sc->joint_count, nl = (size_t) sc->link_count;
    const int dense = !rj__scene_rig_tree(sc);
    return rj__rigid_scratch(nj, nl, dense, 0, 0, 0) + (dense ? nj * nj : 9 * nj);
}

/* The model's block: every array linear in the scene. The building scratch lz holds the
   Lanczos vectors (15 nn) and the elements' table after them (10 ne: rj__lz_table, also
   the inextensible chains' graph, rj__gs_build), the joint-graph checks (rj__validate_graph: 2 nl + nj ints) and for
   rigid scenes the stability bound's (rj__rig_bound_scratch: nj^2 with a dense M, linear
   for articulated bodies). */
static void rj__model_layout(const rj_scene_def *sc, size_t nn, size_t ne, rj__layout *L)
{
    const int nl = sc->link_count, nj = sc->joint_count, rigid = rj__all_rigid(sc);
    size_t off = sizeof(rj_model);
    int inext = 0, l;
    for (l = 0; l < nl; l++)
        inext |= sc->links[l].fidelity == RJ_LINK_INEXTENSIBLE;
    L->ldef = rj__carve(&off, (size_t) nl, sizeof(rj_link_def));
    L->jdef = rj__carve(&off, (size_t) nj, sizeof(rj_joint_def));
    L->jnt = rj__carve(&off, (size_t) nj, sizeof(rj__joint));
    L->link_first = rj__carve(&off, (size_t) nl + 1, sizeof(int));
    L->link_efirst = rj__carve(&off, (size_t) nl + 1, sizeof(int));
    L->link_l0 = rj__carve(&off, (size_t) nl, sizeof(double));
    L->link_EA = rj__carve(&off, (size_t) nl, sizeof(double));
    L->link_EI = rj__carve(&off, (size_t) nl, sizeof(double));
    L->link_rho = rj__carve(&off, (size_t) nl, sizeof(double));
    L->link_I = rj__carve(&off, (size_t) nl, sizeof(double));
    L->ch_first = rj__carve(&off, (size_t) nl + 1, sizeof(int));
    L->node_cl = rj__carve(&off, (size_t) nn, sizeof(int));
    L->bp_node = rj__carve(&off, 2 * (size_t) nj + 2, sizeof(int));
    L->cl_first = rj__carve(&off, (size_t) nl + 1, sizeof(int));
    L->cl_node = rj__carve(&off, (size_t) nn, sizeof(int));
    L->cl_fix = rj__carve(&off, (size_t) nl, sizeof(int));
    L->cl_M = rj__carve(&off, (size_t) nl, sizeof(double));
    L->cl_I = rj__carve(&off, (size_t) nl, sizeof(double));
    L->cl_th0 = rj__carve(&off, (size_t) 3 * nl, sizeof(double));
    L->cl_rx = rj__carve(&off, (size_t) nn, sizeof(double));
    L->cl_ry = rj__carve(&off, (size_t) nn, sizeof(double));
    L->ch_node = rj__carve(&off, (size_t) nn + nl, sizeof(int));
    L->ch_l0sq = rj__carve(&off, (size_t) nn + nl, sizeof(double));
    L->gs_int = rj__carve(&off, inext ? 6 * ne + 2 * nn + 1 : 0, sizeof(int));
    L->gs_l0sq = rj__carve(&off, inext ? ne : 0, sizeof(double));
    L->rb_mass = rj__carve(&off, (size_t) nl, sizeof(double));
    L->rb_icm = rj__carve(&off, (size_t) nl, sizeof(double));
    L->rb_dcm = rj__carve(&off, (size_t) nl, sizeof(double));
    L->rb_pjoint = rj__carve(&off, (size_t) nl, sizeof(int));
    L->jorder = rj__carve(&off, (size_t) nj + 1, sizeof(int));
    L->qj = rj__carve(&off, (size_t) nj + 1, sizeof(int));
    L->jq = rj__carve(&off, (size_t) nj + 1, sizeof(int));
    L->wcol = rj__carve(&off, rigid ? (size_t) nj + 1 : 0, sizeof(int));
    L->jpin = rj__carve(&off, (size_t) nj + 1, sizeof(double));
    L->jref = rj__carve(&off, (size_t) nj + 1, sizeof(double));
    L->mass = rj__carve(&off, (size_t) nn, sizeof(double));
    L->rinertia = rj__carve(&off, (size_t) nn, sizeof(double));
    L->tinv = rj__carve(&off, (size_t) nn, sizeof(double));
    L->rinv = rj__carve(&off, (size_t) nn, sizeof(double));
    L->einv = rj__carve(&off, (size_t) nn, sizeof(double));
    L->kmass = rj__carve(&off, (size_t) nn, sizeof(double));
    L->krot = rj__carve(&off, (size_t) nn, sizeof(double));
    L->grp_first = rj__carve(&off, (size_t) nj + 1, sizeof(int));
    L->grp_node = rj__carve(&off, (size_t) 2 * nj + 1, sizeof(int));
    L->node_grp = rj__carve(&off, (size_t) nn, sizeof(int));
    L->grp_inv = rj__carve(&off, (size_t) nj + 1, sizeof(double));
    L->dnode = rj__carve(&off, (size_t) nn + 1, sizeof(int));
    L->link_un = rj__carve(&off, (size_t) 5 * nl + 1, sizeof(double));
    L->link_kc = rj__carve(&off, (size_t) 4 * nl + 1, sizeof(double));
    L->link_path = rj__carve(&off, (size_t) nl + 1, sizeof(int));
    L->link_pl = rj__carve(&off, (size_t) nl + 1, sizeof(int));
    L->link_damp = rj__carve(&off, (size_t) RJ__LD_PER * nl + 1, sizeof(double));
    L->visc_first = rj__carve(&off, (size_t) nl + 1, sizeof(int));
    L->visc_joint = rj__carve(&off, 2 * (size_t) nj + 1, sizeof(int));
    L->x0 = rj__carve(&off, (size_t) nn, sizeof(double));
    L->y0 = rj__carve(&off, (size_t) nn, sizeof(double));
    L->phi0 = rj__carve(&off, (size_t) nn, sizeof(double));
    L->vx0 = rj__carve(&off, (size_t) nn, sizeof(double));
    L->vy0 = rj__carve(&off, (size_t) nn, sizeof(double));
    L->w0 = rj__carve(&off, (size_t) nn, sizeof(double));
    L->beta0 = rj__carve(&off, (size_t) ne, sizeof(double));
    L->load = rj__carve(&off, (size_t) sc->load_count + 1, sizeof(rj_load_def));
    L->load_node = rj__carve(&off, (size_t) sc->load_count + 1, sizeof(int));
    L->act = rj__carve(&off, (size_t) sc->actuator_count + 1, sizeof(rj_actuator_def));
    L->spl = rj__carve(&off, ((size_t) sc->actuator_count + 1) * RJ_TABLE_MAX, sizeof(double));
    L->cp = rj__carve(&off, (size_t) sc->coupling_count + 1, sizeof(rj_coupling_def));
    L->lz = rj__carve(&off,
                      15 * nn + 10 * ne + 8 + RJ__GRAPH_SCRATCH(nl, nj) +
                          (rigid ? rj__rig_bound_scratch(sc) : 0),
                      sizeof(double));
    L->total = off == (size_t) -1 ? off : off + RJ__ALIGN;
}


RJDEF size_t rj_model_size(const rj_scene_def *scene, rj_error *err)
{
    rj__layout L;
    size_t nn, ne;
    if (!rj__validate(scene, err))
        return 0;
    if (!rj__counts(scene, &nn, &ne, err))
        return 0;
    rj__model_layout(scene, nn, ne, &L);
    if (L.total == (size_t) -1) {
        rj__fail(err, RJ_ERR_NOMEM, "links", (double) nn,
                 "a model of %.0f nodes needs more bytes than size_t counts here", (double) nn);
        return 0;
    }
    return L.total;
}

/* Everything rj_model_init checks before it builds: the fields (rj_model_size) and the
   joint graph, whose scratch comes from RJ_MALLOC (the scene parser's check). */
static rj_result rj__validate_all(const rj_scene_def *scene, rj_error *err, void *alloc_ctx)
{
    rj_error local;
    rj_error *e = err ? err : &local;
    int *scratch;
    int ok;
    if (!rj_model_size(scene, e))
        return e->code;
    scratch = (int *) RJ_MALLOC(
        sizeof(int) * RJ__GRAPH_SCRATCH(scene->link_count, scene->joint_count), alloc_ctx);
    if (!scratch) {
        rj__fail(e, RJ_ERR_NOMEM, "joint_count", scene->joint_count,
                 "could not allocate the joint graph's scratch");
        return RJ_ERR_NOMEM;
    }
    ok = rj__validate_graph(scene, scratch, e);
    RJ_FREE(scratch, alloc_ctx);
    return ok ? RJ_OK : RJ_ERR_INVALID;
}

/* ------------------------------------------------------------------ beam forces */
/* Co-rotational planar Euler-Bernoulli element (Crisfield): chord e = x_b - x_a, axial
   Green strain eps = (|e|^2 - l0^2) / (2 l0^2), chord angle beta tracked incrementally
   from a reference chord (no atan2 per element), local rotations th_a = phi_a - beta,
   th_b = phi_b - beta, end moments M_a = EI/l0 (4 th_a + 2 th_b), M_b = EI/l0 (2 th_a + 4 th_b).
   Forces: node b gets -EA/l0 eps e + (M_a + M_b) perp(e) / |e|^2, node a the opposite;
   moments -M_a, -M_b. The arithmetic is written twice, side by side below: on scalars
   (rj__elem_fast, rj__elem_forces) and on vector lanes (rj__elem_lane_step).

   The beam pass's kernels are plain functions, forced inline, whose variants (energy, in
   place, gravity, stored forces, uniform node values) are int arguments that every caller
   passes as a literal constant: each inlined copy keeps only its own variant's code. The
   pass's views of the arrays (rj__elems, rj__nodes) are locals of the pass whose address
   goes to inlined functions only, so that their fields stay in registers: the kernels'
   vector stores (memcpy) could alias anything that other code can reach. */

/* Rows of a chunk's element-result buffer (one base pointer for the kernels): FX, FY,
   M1, M2, each RJ__FROW long; see rj__beam_chunk for what the entries hold. */
#define RJ__CHUNK 128
#define RJ__FROW  (RJ__CHUNK + 2)

/* The element kernels' view of a chunk of one link's elements: every array at the chunk's
   first element, node arrays at its first node (element i joins nodes i and i + 1; its
   results go to entry i of the chunk buffer's rows), and the link's constants. */
typedef struct rj__elems {
    const double *x, *y, *phi;          /* nodes at n */
    const double *beta, *cx, *cy;       /* chord angles and reference chords at n */
    double *eu;                         /* strain energies */
    double *beta_out, *cx_out, *cy_out; /* the new chord angles and chords (in place: beta ..) */
    double *F;                          /* row FX of the chunk buffer, at the chunk's first */
    double *bk; /* in place: the chunk's old chord angles and chords, rows of RJ__CHUNK */
    double kb, kax, l0sq, half_inv_l0sq; /* the link's EI/l0, EA/l0, l0^2, 1/(2 l0^2) */
} rj__elems;

/* One element's results, in scalars: node b's force, the end moments, strain energy. */
typedef struct rj__elem_force {
    double fx, fy, ma, mb, u;
} rj__elem_force;

/* The element from its chord (ex, ey), chord angle bt, 1/|e|^2 and its nodes' rotations:
   end rotations and moments, axial force, node b's force, strain energy. The fast path
   (rj__elem_fast) and the exact one (rj__elem_exact) share it; rj__elem_lane_step repeats
   it on vector lanes, operation for operation. */
static RJ__FORCE_INLINE void rj__elem_forces(const rj__elems *c, double ex, double ey, double bt,
                                             double inv_l2, double phi_a, double phi_b,
                                             rj__elem_force *f)
{
    const double tha = phi_a - bt;
    const double thb = phi_b - bt;
    const double ma = c->kb * (4.0 * tha + 2.0 * thb);
    const double mb = c->kb * (2.0 * tha + 4.0 * thb);
    const double eps = (ex * ex + ey * ey - c->l0sq) * c->half_inv_l0sq;
    const double nax = c->kax * eps;
    const double s = (ma + mb) * inv_l2;
    f->fx = -nax * ex - s * ey;
    f->fy = -nax * ey + s * ex;
    f->ma = ma;
    f->mb = mb;
    f->u = 0.5 * (ma * tha + mb * thb) + 0.5 * c->kax * c->l0sq * eps * eps;
}

/* The chunk's element i: its results into the chunk buffer's rows and the arrays. */
static RJ__FORCE_INLINE void rj__elem_store(const rj__elems *c, int i, double bt, double ex,
                                            double ey, const rj__elem_force *f)
{
    c->beta_out[i] = bt;
    c->cx_out[i] = ex;
    c->cy_out[i] = ey;
    c->F[i] = f->fx;
    c->F[RJ__FROW + i] = f->fy;
    c->F[2 * RJ__FROW + i] = f->ma;
    c->F[3 * RJ__FROW + i] = f->mb;
    c->eu[i] = f->u;
}

/* The chunk's element i on the fast path, in scalars: the chord's turn r against the
   reference chord from one division, the new chord angle by the series of atan(r), then
   rj__elem_forces. bk: in place, its old chord angle and chord kept in c->bk first (the
   exact path may need them after its new ones overwrote them). Returns nonzero where the
   chord turned too far or back, or a value is NaN (bitwise: no branch). */
static RJ__FORCE_INLINE long long rj__elem_fast(const rj__elems *c, int i, int bk)
{
    const double ex = c->x[i + 1] - c->x[i];
    const double ey = c->y[i + 1] - c->y[i];
    const double cross = c->cx[i] * ey - c->cy[i] * ex;
    const double dot = c->cx[i] * ex + c->cy[i] * ey;
    const double l2 = ex * ex + ey * ey;
    const double inv = 1.0 / (dot * l2);
    const double r = cross * l2 * inv;
    const double inv_l2 = dot * inv;
    const double r2 = r * r;
    const double bt = c->beta[i] + r * (1.0 - r2 * (1.0 / 3.0 - r2 * (1.0 / 5.0)));
    rj__elem_force f;
    if (bk) {
        c->bk[i] = c->beta[i];
        c->bk[RJ__CHUNK + i] = c->cx[i];
        c->bk[2 * RJ__CHUNK + i] = c->cy[i];
    }
    rj__elem_forces(c, ex, ey, bt, inv_l2, c->phi[i], c->phi[i + 1], &f);
    rj__elem_store(c, i, bt, ex, ey, &f);
    return (long long) !(r2 < 4e-6) | (long long) !(dot > 0.0);
}

#ifdef RJ__LANES
/* d in every lane of *v */
static RJ__FORCE_INLINE void rj__splat(rj__vd *v, double d)
{
    rj__vd lanes = { 0 };
    int k;
    for (k = 0; k < RJ__VW; k++)
        lanes[k] = d;
    *v = lanes;
}

/* The chunk's elements i .. i + RJ__VW - 1 on the fast path, in vector lanes: rj__elem_fast
   and rj__elem_forces, the same operations in the same order (keep the three alike:
   tests/lanes.sh compares the bits with the scalar build's). en: their strain energies too
   (without, the compiler drops that arithmetic); bk: in place, their old values kept
   first. A lane of ok is cleared where its chord turned too far or back (or NaN). */
static RJ__FORCE_INLINE void rj__elem_lane_step(const rj__elems *c, int i, int en, int bk,
                                                rj__vl *ok)
{
    rj__vd lim, zero, xa, xb, ya, yb, phia, phib, b, ox, oy;
    rj__splat(&lim, 4e-6);
    rj__splat(&zero, 0.0);
    RJ__VLD(xa, c->x + i);
    RJ__VLD(xb, c->x + i + 1);
    RJ__VLD(ya, c->y + i);
    RJ__VLD(yb, c->y + i + 1);
    RJ__VLD(phia, c->phi + i);
    RJ__VLD(phib, c->phi + i + 1);
    RJ__VLD(b, c->beta + i);
    RJ__VLD(ox, c->cx + i);
    RJ__VLD(oy, c->cy + i);
    if (bk) {
        RJ__VST(c->bk + i, b);
        RJ__VST(c->bk + RJ__CHUNK + i, ox);
        RJ__VST(c->bk + 2 * RJ__CHUNK + i, oy);
    }
    {
        /* rj__elem_fast's turn and chord angle */
        const rj__vd ex = xb - xa;
        const rj__vd ey = yb - ya;
        const rj__vd cross = ox * ey - oy * ex;
        const rj__vd dot = ox * ex + oy * ey;
        const rj__vd l2 = ex * ex + ey * ey;
        const rj__vd inv = 1.0 / (dot * l2);
        const rj__vd r = cross * l2 * inv;
        const rj__vd inv_l2 = dot * inv;
        const rj__vd r2 = r * r;
        const rj__vd bt = b + r * (1.0 - r2 * (1.0 / 3.0 - r2 * (1.0 / 5.0)));
        /* rj__elem_forces */
        const rj__vd tha = phia - bt;
        const rj__vd thb = phib - bt;
        const rj__vd ma = c->kb * (4.0 * tha + 2.0 * thb);
        const rj__vd mb = c->kb * (2.0 * tha + 4.0 * thb);
        const rj__vd eps = (ex * ex + ey * ey - c->l0sq) * c->half_inv_l0sq;
        const rj__vd nax = c->kax * eps;
        const rj__vd s = (ma + mb) * inv_l2;
        const rj__vd fx = -nax * ex - s * ey;
        const rj__vd fy = -nax * ey + s * ex;
        const rj__vd u = 0.5 * (ma * tha + mb * thb) + 0.5 * c->kax * c->l0sq * eps * eps;
        *ok &= (r2 < lim) & (dot > zero);
        /* rj__elem_store */
        RJ__VST(c->beta_out + i, bt);
        RJ__VST(c->cx_out + i, ex);
        RJ__VST(c->cy_out + i, ey);
        RJ__VST(c->F + i, fx);
        RJ__VST(c->F + RJ__FROW + i, fy);
        RJ__VST(c->F + 2 * RJ__FROW + i, ma);
        RJ__VST(c->F + 3 * RJ__FROW + i, mb);
        if (en)
            RJ__VST(c->eu + i, u);
    }
}

/* The lane steps over the chunk's elements 0 .. ne - 1 (ne >= RJ__VW) in steps of RJ__VW.
   Double-buffered, where RJ__VW does not divide ne the last RJ__VW again: the same inputs
   give the same bits. In place (bk) that would read values already overwritten, so whole
   lanes only, and the scalar loop does the rest. Returns how many elements it did. */
static RJ__FORCE_INLINE int rj__elem_lane_loop(const rj__elems *c, int ne, int en, int bk,
                                               rj__vl *ok)
{
    int i;
    for (i = 0; i + RJ__VW <= ne; i += RJ__VW)
        rj__elem_lane_step(c, i, en, bk, ok);
    if (bk)
        return i;
    if (i < ne)
        rj__elem_lane_step(c, ne - RJ__VW, en, bk, ok);
    return ne;
}

/* The element loop in vector lanes over the chunk's ne >= RJ__VW elements, their strain
   energies if en is set (a constant for the loop, chosen here once per chunk). Returns -1
   when some chord turned too far (or a result is NaN), else how many elements it did. */
static RJ__FORCE_INLINE int rj__elem_lanes(const rj__elems *c, int ne, int en, int bk)
{
    rj__vd zero;
    rj__vl ok;
    long long all = -1;
    int done, k;
    rj__splat(&zero, 0.0);
    ok = zero == zero; /* every lane set */
    if (en)
        done = rj__elem_lane_loop(c, ne, 1, bk, &ok);
    else
        done = rj__elem_lane_loop(c, ne, 0, bk, &ok);
    /* one test for all lanes, branch-free */
    for (k = 0; k < RJ__VW; k++)
        all &= ok[k];
    return all ? done : -1;
}
#endif

/* The fast path over the chunk's elements i .. ne - 1 in scalars (after the vector lanes,
   or all of them), branch-free: one division per element, atan(r) of the small per-step
   chord turn r by its series r - r^3/3 + r^5/5 (error < r^7/7 < 2e-20 for |r| < 2e-3; a
   chord turns about omega dt, 1e-5 in the deployment). Returns -1 when some chord turned
   more than that, or turned back, and the exact path must redo the chunk, else ne. */
static RJ__FORCE_INLINE int rj__elem_scalar(const rj__elems *c, int i, int ne, int bk)
{
    long long bad = 0;
    for (; i < ne; i++)
        bad |= rj__elem_fast(c, i, bk);
    return bad != 0 ? -1 : ne;
}

/* The exact path over the chunk's nc elements, for a chunk where some chord turned more
   than 0.02 rad in one step: each chord angle by atan2 from its old one. In place the
   first nb elements' old chord angles and chords are in c->bk (the fast path overwrote
   them), the rest's still where they were. Its chords are stored again: in place the
   lanes may not have, double-buffered they hold these bits already. */
static RJ__NOINLINE void rj__elem_exact(rj__elems view, int nc, int nb, int ip)
{
    const rj__elems *c = &view;
    int i;
    for (i = 0; i < nc; i++) {
        const int kept = ip && i < nb;
        const double ex = c->x[i + 1] - c->x[i];
        const double ey = c->y[i + 1] - c->y[i];
        const double ox = kept ? c->bk[RJ__CHUNK + i] : c->cx[i];
        const double oy = kept ? c->bk[2 * RJ__CHUNK + i] : c->cy[i];
        const double b = kept ? c->bk[i] : c->beta[i];
        const double bt = b + atan2(ox * ey - oy * ex, ox * ex + oy * ey);
        const double inv_l2 = 1.0 / (ex * ex + ey * ey);
        rj__elem_force f;
        rj__elem_forces(c, ex, ey, bt, inv_l2, c->phi[i], c->phi[i + 1], &f);
        rj__elem_store(c, i, bt, ex, ey, &f);
    }
}

/* A chunk's nc elements: vector lanes (lanes_on set, chunks of at least RJ__VW), the scalar loop
   after them, and the exact path for the whole chunk where some chord turned too far. */
static RJ__FORCE_INLINE void rj__chunk_elements(const rj__elems *c, int nc, int en, int ip,
                                                int lanes_on)
{
    int done = 0; /* elements the fast path did, or -1 */
    int nb = 0;   /* in place: elements whose old values are in c->bk */
#ifdef RJ__LANES
    if (lanes_on && nc >= RJ__VW) {
        done = rj__elem_lanes(c, nc, en, ip);
        nb = ip ? nc / RJ__VW * RJ__VW : 0;
    }
#else
    (void) en; /* the scalar loop stores every element's energy */
    (void) lanes_on;
#endif
    if (done >= 0 && done < nc) {
        done = rj__elem_scalar(c, done, nc, ip);
        nb = ip ? nc : 0;
    }
    if (done < 0)
        rj__elem_exact(*c, nc, nb, ip);
}

/* Sum in eight fixed partial sums: deterministic, and it vectorises where the target can. */
static double rj__sum8(const double *RJ__RESTRICT a, int n)
{
    int i = 0;
#ifdef RJ__LANES
    /* the same eight sums in vector lanes */
    rj__vd2 v0 = { 0.0, 0.0 }, v1 = v0, v2 = v0, v3 = v0, t;
    for (; i + 7 < n; i += 8) {
        RJ__VLD(t, a + i);
        v0 += t;
        RJ__VLD(t, a + i + 2);
        v1 += t;
        RJ__VLD(t, a + i + 4);
        v2 += t;
        RJ__VLD(t, a + i + 6);
        v3 += t;
    }
    if (i < n) { /* the rest into the first sum, in order */
        double p0 = v0[0];
        for (; i < n; i++)
            p0 += a[i];
        v0[0] = p0;
    }
    return ((v0[0] + v0[1]) + (v1[0] + v1[1])) + ((v2[0] + v2[1]) + (v3[0] + v3[1]));
#else
    double p[8] = { 0, 0, 0, 0, 0, 0, 0, 0 };
    int k;
    for (; i + 7 < n; i += 8)
        for (k = 0; k < 8; k++)
            p[k] += a[i + k];
    for (; i < n; i++)
        p[0] += a[i];
    return ((p[0] + p[1]) + (p[2] + p[3])) + ((p[4] + p[5]) + (p[6] + p[7]));
#endif
}

/* What the step's fused pass needs to advance nodes as soon as their forces are summed:
   v^{n+1/2} = v^{n-1/2} + kick f / m and x^{n+1} = x^n + dt v^{n+1/2}, and each node's share
   of twice the kinetic energy at n, v^{n-1/2}.v^{n+1/2} m. */
typedef struct rj__adv {
    double kick, dt;
    const double *vx, *vy, *w, *ti, *ri, *km, *kj;
    double *nx, *ny, *nphi, *nvx, *nvy, *nw, *kn;
    double *fx, *fy, *mz; /* node forces, for the nodes advanced again (rj_model.dnode) */
    int en;               /* this step takes the energy accounts (solver.energy_every) */
    int ip;               /* in place: the pass writes the nodes and elements where it reads them */
    int grav;             /* gravity: every moving node's force gains its kinetic mass times g */
    double gx, gy;        /* m/s^2, the acceleration of gravity */
    double *fin; /* the sum of every advanced node's x + y + phi: finite while they all are */
    double *damp; /* the material path's sums: damping forces, power, plastic work
                     (rj_state.damp) */
} rj__adv;

/* One node's update with its final forces (rj__node_lane_advance does the same operations
   in the same order). */
static RJ__INLINE void rj__advance_node(const rj__adv *a, int i, double fx, double fy, double mz,
                                        const double *x, const double *y, const double *phi)
{
    const double ux = a->vx[i] + a->kick * fx * a->ti[i];
    const double uy = a->vy[i] + a->kick * fy * a->ti[i];
    const double uw = a->w[i] + a->kick * mz * a->ri[i];
    a->kn[i] = a->km[i] * (a->vx[i] * ux + a->vy[i] * uy) + a->kj[i] * a->w[i] * uw;
    a->nvx[i] = ux;
    a->nvy[i] = uy;
    a->nw[i] = uw;
    a->nx[i] = x[i] + a->dt * ux;
    a->ny[i] = y[i] + a->dt * uy;
    a->nphi[i] = phi[i] + a->dt * uw;
    /* finite positions at n + 1 from finite ones at n mean finite velocities too */
    *a->fin += (a->nx[i] + a->ny[i]) + a->nphi[i];
}

#ifdef RJ__LANES
/* The node lanes' view of a chunk's nodes: the step's arrays (rj__adv) and the positions at
   n, every one at the chunk's first node, and the chunk buffer (node k takes entries k and
   k + 1 of its rows). */
typedef struct rj__nodes {
    const double *F;                 /* the chunk buffer: rows FX, FY, M1, M2 */
    const double *x, *y, *phi;       /* positions at n (in place: the arrays nx .. nphi) */
    const double *vx, *vy, *w;       /* velocities at n - 1/2 (in place: nvx .. nw) */
    const double *ti, *ri, *km, *kj; /* each node's 1/m, 1/J, kinetic masses */
    double *fx, *fy, *mz;            /* forces kept for the nodes the step advances again */
    double *nx, *ny, *nphi, *nvx, *nvy, *nw, *kn;
    double *fin; /* the sum of the advanced nodes' x + y + phi (rj__adv) */
    double kick, dt, gx, gy;
} rj__nodes;

/* The chunk's nodes k .. k + RJ__VW - 1: their forces from the chunk buffer into f (fx,
   fy, mz) as rj__node_scalar sums them; st: stored too, gr: with each node's own m g (the
   link's uniform masses are not its end nodes', which the step advances again with these
   forces). */
static RJ__FORCE_INLINE void rj__node_lane_forces(const rj__nodes *v, int k, int st, int gr,
                                                  rj__vd *f)
{
    rj__vd fa, fb, ga, gb, m1, m2, km, gfx, gfy;
    RJ__VLD(fa, v->F + k);
    RJ__VLD(fb, v->F + k + 1);
    RJ__VLD(ga, v->F + RJ__FROW + k);
    RJ__VLD(gb, v->F + RJ__FROW + k + 1);
    RJ__VLD(m2, v->F + 3 * RJ__FROW + k);
    RJ__VLD(m1, v->F + 2 * RJ__FROW + k + 1);
    f[0] = fa - fb;
    f[1] = ga - gb;
    f[2] = -m2 - m1;
    if (st && !gr) {
        RJ__VST(v->fx + k, f[0]);
        RJ__VST(v->fy + k, f[1]);
        RJ__VST(v->mz + k, f[2]);
    }
    if (st && gr) {
        RJ__VLD(km, v->km + k);
        gfx = f[0] + km * v->gx;
        gfy = f[1] + km * v->gy;
        RJ__VST(v->fx + k, gfx);
        RJ__VST(v->fy + k, gfy);
        RJ__VST(v->mz + k, f[2]);
    }
}

/* The chunk's nodes k .. k + RJ__VW - 1 advanced with their final forces f and their
   ti, ri, km, kj in mass: rj__advance_node's operations in its order; en: their
   kinetic-energy shares too. fin sums their new positions, lane by lane. */
static RJ__FORCE_INLINE void rj__node_lane_advance(const rj__nodes *v, const rj__vd *mass,
                                                   const rj__vd *f, rj__vd *fin, int k, int en)
{
    rj__vd vx, vy, w, t;
    RJ__VLD(vx, v->vx + k);
    RJ__VLD(vy, v->vy + k);
    RJ__VLD(w, v->w + k);
    {
        const rj__vd ux = vx + v->kick * f[0] * mass[0];
        const rj__vd uy = vy + v->kick * f[1] * mass[0];
        const rj__vd uw = w + v->kick * f[2] * mass[1];
        const rj__vd kn = mass[2] * (vx * ux + vy * uy) + mass[3] * w * uw;
        RJ__VST(v->nvx + k, ux);
        RJ__VST(v->nvy + k, uy);
        RJ__VST(v->nw + k, uw);
        if (en)
            RJ__VST(v->kn + k, kn);
        RJ__VLD(t, v->x + k);
        t = t + v->dt * ux;
        RJ__VST(v->nx + k, t);
        *fin = *fin + t;
        RJ__VLD(t, v->y + k);
        t = t + v->dt * uy;
        RJ__VST(v->ny + k, t);
        *fin = *fin + t;
        RJ__VLD(t, v->phi + k);
        t = t + v->dt * uw;
        RJ__VST(v->nphi + k, t);
        *fin = *fin + t;
    }
}

/* The chunk's nodes k .. k + RJ__VW - 1 in vector lanes. uni: the link's uniform node
   values (link_mass: ti, ri, km, kj), else each node's own; st: their forces stored too;
   en: their kinetic-energy shares; gr: gravity's m g on their forces (km is 0 where a node
   does not move on its own). */
static RJ__FORCE_INLINE void rj__node_lane_step(const rj__nodes *v, int k, const rj__vd *link_mass,
                                                rj__vd *fin, int uni, int st, int en, int gr)
{
    rj__vd mass[4];
    rj__vd f[3];
    if (uni) {
        mass[0] = link_mass[0];
        mass[1] = link_mass[1];
        mass[2] = link_mass[2];
        mass[3] = link_mass[3];
    } else {
        RJ__VLD(mass[0], v->ti + k);
        RJ__VLD(mass[1], v->ri + k);
        RJ__VLD(mass[2], v->km + k);
        RJ__VLD(mass[3], v->kj + k);
    }
    rj__node_lane_forces(v, k, st, gr, f);
    if (gr) {
        f[0] = f[0] + mass[2] * v->gx;
        f[1] = f[1] + mass[2] * v->gy;
    }
    rj__node_lane_advance(v, mass, f, fin, k, en);
}

/* The lane steps over the chunk's nodes 0 .. cnt - 1 (cnt >= RJ__VW), the last RJ__VW again
   where RJ__VW does not divide cnt (in place the caller passes whole lanes only). */
static RJ__FORCE_INLINE void rj__node_lane_loop(const rj__nodes *v, int cnt,
                                                const rj__vd *link_mass, rj__vd *fin, int uni,
                                                int st, int en, int gr)
{
    int k;
    for (k = 0; k + RJ__VW <= cnt; k += RJ__VW)
        rj__node_lane_step(v, k, link_mass, fin, uni, st, en, gr);
    if (k < cnt)
        rj__node_lane_step(v, cnt - RJ__VW, link_mass, fin, uni, st, en, gr);
}

/* The node view of nodes n .. of the step's arrays a, with positions x, y, phi at n and
   the chunk buffer F. */
static RJ__FORCE_INLINE void rj__nodes_at(rj__nodes *v, const rj__adv *a, int n, const double *F,
                                          const double *x, const double *y, const double *phi)
{
    v->F = F;
    v->x = x + n;
    v->y = y + n;
    v->phi = phi + n;
    v->vx = a->vx + n;
    v->vy = a->vy + n;
    v->w = a->w + n;
    v->ti = a->ti + n;
    v->ri = a->ri + n;
    v->km = a->km + n;
    v->kj = a->kj + n;
    v->fx = a->fx + n;
    v->fy = a->fy + n;
    v->mz = a->mz + n;
    v->nx = a->nx + n;
    v->ny = a->ny + n;
    v->nphi = a->nphi + n;
    v->nvx = a->nvx + n;
    v->nvy = a->nvy + n;
    v->nw = a->nw + n;
    v->kn = a->kn + n;
    v->fin = a->fin;
    v->kick = a->kick;
    v->dt = a->dt;
    v->gx = a->gx;
    v->gy = a->gy;
}

/* The chunk's nodes n .. n + cnt - 1 (cnt >= RJ__VW) advanced in vector lanes with their
   forces from the chunk buffer F, their forces stored too if store is set and their
   kinetic-energy shares if en is. un: the link's uniform node values (ti, ri, km, kj, and
   1 when every inner node has them); gr: gravity (a constant: the pass's two calls). The
   run-time choices become constants here, once per chunk. */
static RJ__FORCE_INLINE void rj__node_lanes(const rj__adv *a, int n, int cnt, const double *un,
                                            const double *F, const double *x, const double *y,
                                            const double *phi, int store, int en, int gr)
{
    rj__nodes view;
    const rj__nodes *v = &view;
    rj__vd link_mass[4];
    rj__vd fin;
    double fin_sum = 0;
    int k;
    rj__nodes_at(&view, a, n, F, x, y, phi);
    rj__splat(&link_mass[0], un[0]);
    rj__splat(&link_mass[1], un[1]);
    rj__splat(&link_mass[2], un[2]);
    rj__splat(&link_mass[3], un[3]);
    rj__splat(&fin, 0.0);
    if (un[4] == 0) /* each node's own values: rare; forces and energy shares always stored */
        rj__node_lane_loop(v, cnt, link_mass, &fin, 0, 1, 1, gr);
    else if (store && en)
        rj__node_lane_loop(v, cnt, link_mass, &fin, 1, 1, 1, gr);
    else if (store)
        rj__node_lane_loop(v, cnt, link_mass, &fin, 1, 1, 0, gr);
    else if (en)
        rj__node_lane_loop(v, cnt, link_mass, &fin, 1, 0, 1, gr);
    else
        rj__node_lane_loop(v, cnt, link_mass, &fin, 1, 0, 0, gr);
    /* the new positions' sum: NaN or infinite when one of them is */
    for (k = 0; k < RJ__VW; k++)
        fin_sum += fin[k];
    *v->fin += fin_sum;
}
#endif

/* Nodes n + k .. n + cnt - 1 from the chunk buffer F (rows FX, FY, M1, M2) laid out so
   that node k takes FX[k] - FX[k+1] (its element on the left, -0.0 before a link's first,
   minus the one on the right, +0.0 after its last: the same bits as -FX[0] and FX[last])
   and mz = -M2[k] - M1[k+1]: the forces (into fx, fy, mz), and with step (not NULL) the
   advanced velocities, positions and kinetic-energy shares (the lanes did nodes 0 .. k - 1,
   or none: the pass's copy without them). */
static void rj__node_scalar(int k, int cnt, int n, const double *F, double *fx, double *fy,
                            double *mz, const double *x, const double *y, const double *phi,
                            const rj__adv *step)
{
    const double *FX = F;
    const double *FY = F + RJ__FROW;
    const double *M1 = F + 2 * RJ__FROW;
    const double *M2 = F + 3 * RJ__FROW;
    rj__adv a; /* a local copy, whose fields the stores below cannot change */
    if (!step) {
        for (; k < cnt; k++) {
            fx[n + k] = FX[k] - FX[k + 1];
            fy[n + k] = FY[k] - FY[k + 1];
            mz[n + k] = -M2[k] - M1[k + 1];
        }
        return;
    }
    a = *step;
    for (; k < cnt; k++) {
        double fxv = FX[k] - FX[k + 1];
        double fyv = FY[k] - FY[k + 1];
        const double mzv = -M2[k] - M1[k + 1];
        if (a.grav) { /* as the lanes: m g on every node that moves on its own */
            fxv = fxv + a.km[n + k] * a.gx;
            fyv = fyv + a.km[n + k] * a.gy;
        }
        fx[n + k] = fxv;
        fy[n + k] = fyv;
        mz[n + k] = mzv;
        rj__advance_node(&a, n + k, fxv, fyv, mzv, x, y, phi);
    }
}

/* The beam pass's arguments (rj__beam_pass_body), for its parts to share. */
typedef struct rj__pass {
    const rj_model *m;
    const double *x, *y, *phi;    /* nodes at n */
    const double *beta, *cx, *cy; /* chord angles and reference chords at n */
    double *eu;                   /* strain energies */
    double *beta_out, *cx_out, *cy_out;
    double *fx, *fy, *mz; /* node forces */
    const rj__adv *adv;   /* the step's node update, or NULL: forces only */
    int en;               /* strain energies wanted */
} rj__pass;

/* A rigid link has no elements: its chord angles and chords are carried over, its nodes
   take only what joints apply (and are advanced with the joints' nodes). */
static RJ__FORCE_INLINE void rj__beam_rigid_link(const rj__pass *p, int l)
{
    const int n0 = p->m->link_first[l];
    const int e0 = p->m->link_efirst[l];
    const int ne = p->m->link_efirst[l + 1] - e0;
    int i;
    for (i = e0; i < e0 + ne; i++) {
        p->beta_out[i] = p->beta[i];
        p->cx_out[i] = p->cx[i];
        p->cy_out[i] = p->cy[i];
        p->eu[i] = 0;
    }
    for (i = n0; i <= n0 + ne; i++) {
        p->fx[i] = 0;
        p->fy[i] = 0;
        p->mz[i] = 0;
    }
}

/* The element view of link l's chunk whose first element is a and first node na: the
   chunk buffer's row FX at F, in place the old values' buffer bk (else NULL). */
static RJ__FORCE_INLINE void rj__elems_at(rj__elems *c, const rj__pass *p, int l, int a, int na,
                                          double *F, double *bk)
{
    const double *kc = p->m->link_kc + 4 * (size_t) l;
    c->x = p->x + na;
    c->y = p->y + na;
    c->phi = p->phi + na;
    c->beta = p->beta + a;
    c->cx = p->cx + a;
    c->cy = p->cy + a;
    c->eu = p->eu + a;
    c->beta_out = p->beta_out + a;
    c->cx_out = p->cx_out + a;
    c->cy_out = p->cy_out + a;
    c->F = F;
    c->bk = bk;
    c->kb = kc[0];
    c->kax = kc[1];
    c->l0sq = kc[2];
    c->half_inv_l0sq = kc[3];
}

/* The chunk's nodes whose elements are all summed once its elements are: the chunk's nc,
   and the link's last node with the last chunk (last). Their forces are stored in the
   chunks that hold nodes the step advances again (m->dnode: a link's end nodes, and inner
   ones only in scenes with dn_inner: first, last). lanes_on: in vector lanes (in place whole
   lanes only) and the scalar loop after them, else in the scalar loop. */
static RJ__FORCE_INLINE void rj__chunk_nodes(const rj__pass *p, int l, int na, int first, int last,
                                             int nc, const double *FB, int ip, int lanes_on)
{
    const int cnt = nc + last;
    int done = 0;
#ifdef RJ__LANES
    if (lanes_on && p->adv && cnt >= RJ__VW) {
        const int lanes = ip ? cnt / RJ__VW * RJ__VW : cnt;
        const int store = first || last || p->m->dn_inner;
        const double *un = p->m->link_un + 5 * l;
        if (p->adv->grav)
            rj__node_lanes(p->adv, na, lanes, un, FB, p->x, p->y, p->phi, store, p->en, 1);
        else
            rj__node_lanes(p->adv, na, lanes, un, FB, p->x, p->y, p->phi, store, p->en, 0);
        done = lanes;
    }
#else
    (void) l;
    (void) first;
    (void) ip;
    (void) lanes_on;
#endif
    if (done < cnt)
        rj__node_scalar(done, cnt, na, FB, p->fx, p->fy, p->mz, p->x, p->y, p->phi, p->adv);
}

/* Link l's elements c0 .. c0 + nc - 1 and the nodes they complete, while they are in L1.
   The chunk buffer FB has rows FX, FY, M1, M2: entry 0 the previous chunk's last element
   (or the -0.0 / +0.0 before a link's first), entries 1 .. nc this chunk's, nc + 1 the +0.0
   after a link's last; node k takes FX[k] - FX[k + 1] (rj__node_scalar). EB: in place,
   the chunk's old chord angles and chords. */
static RJ__FORCE_INLINE void rj__beam_chunk(const rj__pass *p, int l, int c0, double *FB,
                                            double *EB, int ip, int lanes_on)
{
    const int n0 = p->m->link_first[l];
    const int e0 = p->m->link_efirst[l];
    const int ne = p->m->link_efirst[l + 1] - e0;
    const int nc = ne - c0 < RJ__CHUNK ? ne - c0 : RJ__CHUNK;
    const int last = c0 + nc == ne;
    rj__elems c;
    rj__elems_at(&c, p, l, e0 + c0, n0 + c0, FB + 1, ip ? EB : NULL);
    rj__chunk_elements(&c, nc, p->en, ip, lanes_on);
    if (last) {
        FB[nc + 1] = 0.0;
        FB[RJ__FROW + nc + 1] = 0.0;
        FB[2 * RJ__FROW + nc + 1] = 0.0;
    }
    rj__chunk_nodes(p, l, n0 + c0, c0 == 0, last, nc, FB, ip, lanes_on);
    /* this chunk's last element is entry 0 of the next */
    FB[0] = FB[nc];
    FB[RJ__FROW] = FB[RJ__FROW + nc];
    FB[2 * RJ__FROW] = FB[2 * RJ__FROW + nc];
    FB[3 * RJ__FROW] = FB[3 * RJ__FROW + nc];
}

/* The pass's arguments into its record. */
static RJ__FORCE_INLINE void rj__pass_open(rj__pass *p, const rj_model *m, const double *x,
                                           const double *y, const double *phi,
                                           const double *beta, const double *cx,
                                           const double *cy, double *eu, double *beta_out,
                                           double *cx_out, double *cy_out, double *fx,
                                           double *fy, double *mz, const rj__adv *adv)
{
    p->m = m;
    p->x = x;
    p->y = y;
    p->phi = phi;
    p->beta = beta;
    p->cx = cx;
    p->cy = cy;
    p->eu = eu;
    p->beta_out = beta_out;
    p->cx_out = cx_out;
    p->cy_out = cy_out;
    p->fx = fx;
    p->fy = fy;
    p->mz = mz;
    p->adv = adv;
    p->en = !adv || adv->en;
}

static RJ__NOINLINE void rj__beam_material_links(const rj_model *m, const double *x,
                                                 const double *y, const double *phi,
                                                 const double *beta, const double *cx,
                                                 const double *cy, double *eu, double *beta_out,
                                                 double *cx_out, double *cy_out, double *fx,
                                                 double *fy, double *mz, const rj__adv *adv,
                                                 const double *ep, double *ep_new);

/* Internal forces at x: element forces summed into the nodes (fx, fy, mz: node b of element
   e gets +ef, node a gets -ef), chunk by chunk; the updated chord angles and this step's
   chords (the next step's references) go to beta_out, cx_out, cy_out; eu receives the
   elements' strain energies. With adv (the step), every node of a flexible link is also
   advanced as soon as its forces are summed; nodes that joints act on are advanced again
   later (m->dnode); with adv->en clear the lanes leave eu stale. Returns whether eu is
   complete (rj__beam_pass then sums it into the strain energy). Two constants: ip, in place
   (the step's rj_model.ip), where beta_out .. cy_out are beta .. cy and the step's nodes
   are advanced where they are; lanes_on, the vector kernels (0: the scalar loops alone). */
static RJ__FORCE_INLINE int rj__beam_pass_body(const rj_model *m, const double *x, const double *y,
                                               const double *phi, const double *beta,
                                               const double *cx, const double *cy, double *eu,
                                               double *beta_out, double *cx_out, double *cy_out,
                                               double *fx, double *fy, double *mz,
                                               const rj__adv *adv, int ip, int lanes_on)
{
    rj__pass p;
    double FB[4 * RJ__FROW];
    double EB[3 * RJ__CHUNK];
    int l, c0;
    rj__pass_open(&p, m, x, y, phi, beta, cx, cy, eu, beta_out, cx_out, cy_out, fx, fy, mz, adv);
    for (l = 0; l < p.m->nl; l++) {
        const int ne = p.m->link_efirst[l + 1] - p.m->link_efirst[l];
        /* rigid links here; the material path's apart (rj__beam_material_links) */
        if (p.m->link_path[l] != RJ__PATH_FUSED) {
            if (p.m->link_path[l] == RJ__PATH_RIGID)
                rj__beam_rigid_link(&p, l);
            continue;
        }
        /* before the link's first element: -0.0 (node 0 takes -FX[1], the same bits) */
        FB[0] = -0.0;
        FB[RJ__FROW] = -0.0;
        FB[2 * RJ__FROW] = 0.0;
        FB[3 * RJ__FROW] = 0.0;
        for (c0 = 0; c0 < ne; c0 += RJ__CHUNK)
            rj__beam_chunk(&p, l, c0, FB, EB, ip, lanes_on);
    }
    return p.en;
}

/* The pass compiled whole, kernels inlined, once per target and in-place choice, so that
   the CPU is asked once per step: for AVX2 where the header dispatches (rj__beam_pass), and
   for the including file's own target. Each returns to its caller and calls no other code
   on its way out: a function compiled for AVX2 that jumps into SSE code without clearing
   the registers' upper halves (gcc 12 left out its vzeroupper before such a tail call)
   makes every later SSE instruction of the step pay for them (the paper's settings ran
   1.3x slower). An always_inline function without a target may be inlined into an AVX2
   one (gcc, clang), not the other way round. Where the header dispatches, RJ__VW is 4 for
   the AVX2 copy, and the copy for CPUs without AVX2 takes the scalar loops: gcc keeps a
   4-double vector that SSE2 registers cannot hold on the stack (30-40 % more instructions
   than 2 lanes, and 6 % more compile time for the whole header; docs/performance.md).
   RJ_NO_DISPATCH builds 2 lanes for such CPUs. */
#ifdef RJ__DISPATCH
#define RJ__DEFAULT_LANES_ON 0
#else
#define RJ__DEFAULT_LANES_ON 1
#endif
#ifdef RJ__DISPATCH
RJ__AVX2 static int rj__beam_pass_avx2(const rj_model *m, const double *x, const double *y,
                                       const double *phi, const double *beta, const double *cx,
                                       const double *cy, double *eu, double *beta_out,
                                       double *cx_out, double *cy_out, double *fx, double *fy,
                                       double *mz, const rj__adv *adv)
{
    return rj__beam_pass_body(m, x, y, phi, beta, cx, cy, eu, beta_out, cx_out, cy_out, fx, fy, mz,
                              adv, 0, 1);
}

RJ__AVX2 static int rj__beam_pass_avx2_ip(const rj_model *m, const double *x, const double *y,
                                          const double *phi, const double *beta, const double *cx,
                                          const double *cy, double *eu, double *beta_out,
                                          double *cx_out, double *cy_out, double *fx, double *fy,
                                          double *mz, const rj__adv *adv)
{
    return rj__beam_pass_body(m, x, y, phi, beta, cx, cy, eu, beta_out, cx_out, cy_out, fx, fy, mz,
                              adv, 1, 1);
}
#endif

static int rj__beam_pass_default(const rj_model *m, const double *x, const double *y,
                                 const double *phi, const double *beta, const double *cx,
                                 const double *cy, double *eu, double *beta_out, double *cx_out,
                                 double *cy_out, double *fx, double *fy, double *mz,
                                 const rj__adv *adv)
{
    return rj__beam_pass_body(m, x, y, phi, beta, cx, cy, eu, beta_out, cx_out, cy_out, fx, fy, mz,
                              adv, 0, RJ__DEFAULT_LANES_ON);
}

static int rj__beam_pass_default_ip(const rj_model *m, const double *x, const double *y,
                                    const double *phi, const double *beta, const double *cx,
                                    const double *cy, double *eu, double *beta_out, double *cx_out,
                                    double *cy_out, double *fx, double *fy, double *mz,
                                    const rj__adv *adv)
{
    return rj__beam_pass_body(m, x, y, phi, beta, cx, cy, eu, beta_out, cx_out, cy_out, fx, fy, mz,
                              adv, 1, RJ__DEFAULT_LANES_ON);
}

/* Internal forces at x (rj__beam_pass_body), in the widest lanes the CPU has; returns the
   strain energy, or 0 where the step does not take it (adv->en clear). */
static RJ__FORCE_INLINE double rj__beam_pass(const rj_model *m, const double *x, const double *y,
                                             const double *phi, const double *beta,
                                             const double *cx, const double *cy, double *eu,
                                             double *beta_out, double *cx_out, double *cy_out,
                                             double *fx, double *fy, double *mz, const rj__adv *adv)
{
    const int ip = adv && adv->ip;
    int en;
#if defined(RJ__DISPATCH)
    if (__builtin_cpu_supports("avx2"))
        en = (ip ? rj__beam_pass_avx2_ip : rj__beam_pass_avx2)(
            m, x, y, phi, beta, cx, cy, eu, beta_out, cx_out, cy_out, fx, fy, mz, adv);
    else
        en = (ip ? rj__beam_pass_default_ip : rj__beam_pass_default)(
            m, x, y, phi, beta, cx, cy, eu, beta_out, cx_out, cy_out, fx, fy, mz, adv);
#else
    en = (ip ? rj__beam_pass_default_ip : rj__beam_pass_default)(
        m, x, y, phi, beta, cx, cy, eu, beta_out, cx_out, cy_out, fx, fy, mz, adv);
#endif
    /* forces alone: the links on the material path too, without plastic strains (the
       step takes them before the pass, rj__beam_material_step) */
    if (m->nmaterial && !adv)
        rj__beam_material_links(m, x, y, phi, beta, cx, cy, eu, beta_out, cx_out, cy_out, fx,
                                fy, mz, adv, NULL, NULL);
    return en ? rj__sum8(eu, m->ne) : 0.0;
}
/* ------------------------------------------------------------------ the material path */
/* Links whose material needs more than the fused kernels' elastic Green element take
   their own path through the beam pass, in scalars, so that the fused kernels of every
   other link stay as they are and a scene without them pays nothing: structural damping
   (rj_link_def.eta, damping, mass_damping), yielding layers (yield, hardening) and the
   Biot axial law (strain). The elastic Green element is the kernels' own
   (rj__chunk_elements); what the material adds is added to its results.

   Kelvin-Voigt: each element's stress is E (strain + eta d(strain)/dt), on the axial
   Green strain and on the local end rotations that carry its bending. The viscous part
   maps to node forces as the elastic part does (rj__elem_forces), with the strains'
   rates in place of the strains: the Green strain's rate e . e' / l0^2, and the end
   rotations' rates w_a - beta', w_b - beta', beta' = (e x e') / |e|^2 the chord's turn.
   Mass-proportional damping adds -mass_damping m v to each node (m w: its rotation).
   Both act here on the velocities at n - 1/2, as the joints' damping does (Eq 27):
   explicit, bounded by dt <= (2 / omega) (sqrt(1 + zeta^2) - zeta) (rj__structural_rate).
   Kelvin-Voigt does only on a link a rigid body carries a node of; on the others it is
   implicit, taken after this pass (src/viscous.h), and its viscous rows here are 0.

   Their loss joins the accounts in the step's own discrete form: the kinetic energy
   1/2 v^{n-1/2} M v^{n+1/2} changes over a step by dt/2 v^{n-1/2} . (F^n + F^{n-1}), so the
   damping forces' share is -dt/2 F_d^n . v^{n-1/2} (summed here) and -dt/2 F_d^n .
   v^{n+1/2}, which the next step takes (rj__material_accounts, from the forces kept in
   rj_state.damp).

   Yielding layers: the plastic strain of each layer is kept at two sections of each
   element, its Gauss points (rj__gauss_xi), where the cubic element's curvature kappa
   = ((6 xi - 4) th_a + (6 xi - 2) th_b) / l0 is exact in the bending energy. A layer's
   strain at its mid-depth z is eps0 - z kappa; its stress E (strain - plastic strain),
   returned to the yield surface |sigma - H ep| <= yield of bilinear kinematic hardening
   (plastic modulus H) each step. The section's N and M are the elastic ones, integrated
   exactly, less E times the plastic strains over the layers (constant through each
   layer): with no plastic strain the element is the elastic one to the bit. The plastic
   work, the account W_plastic, is each return's (sigma_trial + sigma) / 2 times its
   plastic strain: the elastic energy's drop at the strain it returned at, so that the
   balance closes as the elastic one does. */

/* The viscous stresses of an element with chord (ex, ey), 1 / |e|^2 inv_l2, chord rate
   (dex, dey) and end rotation rates wa, wb, for a link with constants kc (rj_model.
   link_kc) and eta: node b's force and the end moments (u 0: their power is summed over
   the nodes, rj__material_nodes). */
static RJ__INLINE void rj__elem_viscous(const double *kc, double eta, double ex, double ey,
                                        double inv_l2, double dex, double dey, double wa,
                                        double wb, rj__elem_force *f)
{
    /* the Green strain's rate, e . e' / l0^2, and the chord's turn rate */
    const double eps_rate = (ex * dex + ey * dey) * (2.0 * kc[3]);
    const double turn = (ex * dey - ey * dex) * inv_l2;
    const double tha = wa - turn;
    const double thb = wb - turn;
    /* the end moments and axial force of rj__elem_forces, on the rates, times eta */
    const double ma = eta * kc[0] * (4.0 * tha + 2.0 * thb);
    const double mb = eta * kc[0] * (2.0 * tha + 4.0 * thb);
    const double nax = eta * kc[1] * eps_rate;
    const double s = (ma + mb) * inv_l2;
    f->fx = -nax * ex - s * ey;
    f->fy = -nax * ey + s * ex;
    f->ma = ma;
    f->mb = mb;
    f->u = 0;
}

/* The chunk's elements 0 .. nc - 1 (first node na) of link l: their viscous forces, at
   the positions at n and the velocities at n - 1/2, into the rows FD (entry i + 1: element
   i, as the kernels fill the chunk buffer). */
static void rj__chunk_viscous(const rj__pass *p, int l, int na, int nc, double *FD)
{
    const double *kc = p->m->link_kc + 4 * (size_t) l;
    const double eta = RJ__LD(p->m, l)[RJ__LD_LAGGED];
    const double *x = p->x + na, *y = p->y + na;
    const double *vx = p->adv->vx + na, *vy = p->adv->vy + na, *w = p->adv->w + na;
    int i;
    for (i = 0; i < nc; i++) {
        const double ex = x[i + 1] - x[i];
        const double ey = y[i + 1] - y[i];
        const double inv_l2 = 1.0 / (ex * ex + ey * ey);
        rj__elem_force f;
        rj__elem_viscous(kc, eta, ex, ey, inv_l2, vx[i + 1] - vx[i], vy[i + 1] - vy[i], w[i],
                         w[i + 1], &f);
        FD[1 + i] = f.fx;
        FD[RJ__FROW + 1 + i] = f.fy;
        FD[2 * RJ__FROW + 1 + i] = f.ma;
        FD[3 * RJ__FROW + 1 + i] = f.mb;
    }
}

/* Node n's damping force: the viscous rows FD's (entry k the element before it, k + 1 the
   one after, as rj__node_scalar reads the chunk buffer) and its mass-proportional share,
   -alpha m v at n - 1/2; into d (fx, fy, mz). */
static RJ__INLINE void rj__node_damping(const rj__pass *p, int n, int k, const double *FD,
                                        double alpha, double d[3])
{
    const rj__adv *a = p->adv;
    d[0] = FD[k] - FD[k + 1] - alpha * p->m->mass[n] * a->vx[n];
    d[1] = FD[RJ__FROW + k] - FD[RJ__FROW + k + 1] - alpha * p->m->mass[n] * a->vy[n];
    d[2] = -FD[3 * RJ__FROW + k] - FD[2 * RJ__FROW + k + 1] -
           alpha * p->m->rinertia[n] * a->w[n];
}

/* The chunk's nodes na .. na + cnt - 1 in the step: their forces, the elastic ones from
   the chunk buffer FB with gravity and the damping ones; the damping ones kept
   (rj_state.damp) and their power at n - 1/2 summed; then advanced (rj__advance_node). */
static void rj__material_nodes(const rj__pass *p, int l, int na, int cnt, const double *FB,
                             const double *FD, double *power)
{
    const double alpha = RJ__LD(p->m, l)[RJ__LD_MASS];
    const rj__adv *a = p->adv;
    const size_t nn = (size_t) p->m->nn;
    int k;
    for (k = 0; k < cnt; k++) {
        const int n = na + k;
        double fxv = FB[k] - FB[k + 1];
        double fyv = FB[RJ__FROW + k] - FB[RJ__FROW + k + 1];
        double mzv = -FB[3 * RJ__FROW + k] - FB[2 * RJ__FROW + k + 1];
        double d[3];
        rj__node_damping(p, n, k, FD, alpha, d);
        if (a->grav) {
            fxv += a->km[n] * a->gx;
            fyv += a->km[n] * a->gy;
        }
        fxv += d[0];
        fyv += d[1];
        mzv += d[2];
        p->fx[n] = fxv;
        p->fy[n] = fyv;
        p->mz[n] = mzv;
        a->damp[n] = d[0];
        a->damp[nn + n] = d[1];
        a->damp[2 * nn + n] = d[2];
        *power += d[0] * a->vx[n] + d[1] * a->vy[n] + d[2] * a->w[n];
        rj__advance_node(a, n, fxv, fyv, mzv, p->x, p->y, p->phi);
    }
}

/* A link's material as the material path reads it. */
typedef struct rj__material {
    double E, EA, l0;        /* Pa, N, m */
    double yield, hard;      /* Pa: the layers' yield stress (0: elastic), plastic modulus */
    double width, height;    /* m: a rectangular section's */
    int layers, biot;        /* its layers; the Biot axial law */
} rj__material;

static void rj__material_of(const rj_model *m, int l, rj__material *mt)
{
    const rj_link_def *d = &m->ldef[l];
    mt->E = d->E;
    mt->EA = m->link_EA[l];
    mt->l0 = m->link_l0[l];
    mt->yield = d->yield;
    mt->hard = d->hardening;
    mt->width = d->width;
    mt->height = d->height;
    mt->layers = d->layers;
    mt->biot = d->strain == RJ_STRAIN_BIOT;
}

/* The element's two sections, as fractions of its length: the Gauss points. */
static const double rj__gauss_xi[2] = { 0.21132486540518713, 0.78867513459481287 };

/* What one section's layers add to the elastic section, per unit length: N, M, the
   elastic energy's change, the plastic work of this step's return. */
typedef struct rj__section_sums {
    double N, M, U, work;
    double smax; /* Pa: the largest |stress| at a layer's mid-depth */
} rj__section_sums;

/* One section at axial strain eps0 and curvature kappa: each layer's plastic strain from
   ep (NULL: none), returned to the yield surface into ep_new when given; into *out. */
static void rj__section_layers(const rj__material *mt, double eps0, double kappa,
                               const double *ep, double *ep_new, rj__section_sums *out)
{
    const double depth = mt->height / mt->layers;
    const double area = mt->width * depth;
    int k;
    memset(out, 0, sizeof *out);
    for (k = 0; k < mt->layers; k++) {
        const double z = -0.5 * mt->height + (k + 0.5) * depth;
        const double strain = eps0 - z * kappa;
        double plastic = ep ? ep[k] : 0.0;
        if (ep_new) {
            /* the return to |sigma - H ep| <= yield */
            const double trial = mt->E * (strain - plastic);
            const double over = trial - mt->hard * plastic;
            const double excess = fabs(over) - mt->yield;
            if (excess > 0) {
                const double step = (over > 0 ? excess : -excess) / (mt->E + mt->hard);
                out->work += area * (trial - 0.5 * mt->E * step) * step;
                plastic += step;
            }
            ep_new[k] = plastic;
        }
        out->N -= mt->E * area * plastic;
        out->M += mt->E * area * z * plastic;
        out->U += mt->E * area * plastic * (0.5 * plastic - strain);
        if (fabs(mt->E * (strain - plastic)) > out->smax)
            out->smax = fabs(mt->E * (strain - plastic));
    }
}

/* What the material adds to the fused kernels' elastic Green element with chord (ex,
   ey) and local end rotations tha, thb: the Biot axial law, and the layers' plastic
   strains ep (2 sections x layers; NULL: none) returned into ep_new when given. Added to
   f (node b's force, end moments, strain energy); returns the plastic work (J), the
   largest |stress| at a layer's mid-depth (where the layers yield) into *smax. */
static double rj__elem_material(const rj__material *mt, double ex, double ey, double tha,
                                double thb, const double *ep, double *ep_new,
                                rj__elem_force *f, double *smax)
{
    const double l0 = mt->l0;
    const double L2 = ex * ex + ey * ey;
    const double green = (L2 - l0 * l0) / (2.0 * l0 * l0);
    const double L = sqrt(L2);
    const double biot = L / l0 - 1.0;
    const double eps0 = mt->biot ? biot : green;
    double N = 0, ma = 0, mb = 0, U = 0, work = 0, dnax, s;
    int g;
    *smax = 0;
    if (mt->yield > 0) {
        for (g = 0; g < 2; g++) {
            const double xi = rj__gauss_xi[g];
            const double kappa = ((6.0 * xi - 4.0) * tha + (6.0 * xi - 2.0) * thb) / l0;
            const int at = g * mt->layers;
            rj__section_sums sec;
            rj__section_layers(mt, eps0, kappa, ep ? ep + at : NULL, ep_new ? ep_new + at : NULL,
                               &sec);
            /* two-point Gauss: weights l0 / 2; the end moments M_a = int M (6 xi - 4) dxi */
            N += 0.5 * sec.N;
            ma += 0.5 * sec.M * (6.0 * xi - 4.0);
            mb += 0.5 * sec.M * (6.0 * xi - 2.0);
            U += 0.5 * l0 * sec.U;
            work += 0.5 * l0 * sec.work;
            if (sec.smax > *smax)
                *smax = sec.smax;
        }
    }
    /* node b's axial force -nax e: Green's work conjugate l0 eps, Biot's L */
    if (mt->biot) {
        dnax = (mt->EA * biot + N) / L - mt->EA * green / l0;
        U += 0.5 * mt->EA * l0 * (biot * biot - green * green);
    } else
        dnax = N / l0;
    s = (ma + mb) / L2;
    f->fx += -dnax * ex - s * ey;
    f->fy += -dnax * ey + s * ex;
    f->ma += ma;
    f->mb += mb;
    f->u += U;
    return work;
}

/* The chunk's elements 0 .. nc - 1 (first element e0 of link l, first node na): what
   the material adds to the kernels' results in the chunk buffer FB (entry i + 1) and the
   strain energies; ep, ep_new: the link's plastic strains (NULL: none, or no return).
   Returns the plastic work. */
static double rj__chunk_material(const rj__pass *p, const rj__material *mt, int e0, int na,
                                 int nc, double *FB, const double *ep, double *ep_new)
{
    const int per = 2 * mt->layers;
    double work = 0, smax;
    int i;
    for (i = 0; i < nc; i++) {
        const int e = e0 + i;
        const double ex = p->x[na + i + 1] - p->x[na + i];
        const double ey = p->y[na + i + 1] - p->y[na + i];
        const double bt = p->beta_out[e];
        rj__elem_force f;
        f.fx = FB[1 + i];
        f.fy = FB[RJ__FROW + 1 + i];
        f.ma = FB[2 * RJ__FROW + 1 + i];
        f.mb = FB[3 * RJ__FROW + 1 + i];
        f.u = p->eu[e];
        work += rj__elem_material(mt, ex, ey, p->phi[na + i] - bt, p->phi[na + i + 1] - bt,
                                  ep ? ep + (size_t) per * i : NULL,
                                  ep_new ? ep_new + (size_t) per * i : NULL, &f, &smax);
        FB[1 + i] = f.fx;
        FB[RJ__FROW + 1 + i] = f.fy;
        FB[2 * RJ__FROW + 1 + i] = f.ma;
        FB[3 * RJ__FROW + 1 + i] = f.mb;
        p->eu[e] = f.u;
    }
    return work;
}

/* The chunk buffer's entries around a link's elements (rj__beam_pass_body's): -0.0
   before the first, +0.0 after the last (at entry at). */
static void rj__chunk_edge(double *F, int at, double value)
{
    int r;
    for (r = 0; r < 4; r++)
        F[r * RJ__FROW + at] = r < 2 ? value : 0.0;
}

/* Link l on the material path, chunk by chunk as rj__beam_pass_body takes the others:
   the elastic element forces by the scalar kernels, what the material adds to them (its
   axial law, its layers' plastic strains: ep at n - 1, returned into ep_new when given),
   the viscous forces beside them, the nodes advanced with all (forces only, without the
   step: no viscous ones). sums[0] gains the damping's power at n - 1/2, sums[1] the
   plastic work. */
static void rj__beam_material_link(const rj__pass *p, int l, int ip, const double *ep,
                                   double *ep_new, double sums[2])
{
    const int n0 = p->m->link_first[l];
    const int e0 = p->m->link_efirst[l];
    const int ne = p->m->link_efirst[l + 1] - e0;
    const size_t per = 2 * (size_t) p->m->ldef[l].layers;
    double FB[4 * RJ__FROW], FD[4 * RJ__FROW], EB[3 * RJ__CHUNK];
    rj__material mt;
    int c0, r;
    rj__material_of(p->m, l, &mt);
    rj__chunk_edge(FB, 0, -0.0);
    rj__chunk_edge(FD, 0, 0.0);
    for (c0 = 0; c0 < ne; c0 += RJ__CHUNK) {
        const int nc = ne - c0 < RJ__CHUNK ? ne - c0 : RJ__CHUNK;
        const int last = c0 + nc == ne;
        rj__elems c;
        rj__elems_at(&c, p, l, e0 + c0, n0 + c0, FB + 1, ip ? EB : NULL);
        rj__chunk_elements(&c, nc, p->en, ip, 0);
        if (mt.yield > 0 || mt.biot)
            sums[1] += rj__chunk_material(p, &mt, e0 + c0, n0 + c0, nc, FB,
                                          ep ? ep + per * c0 : NULL,
                                          ep_new ? ep_new + per * c0 : NULL);
        if (last)
            rj__chunk_edge(FB, nc + 1, 0.0);
        if (!p->adv) {
            rj__node_scalar(0, nc + last, n0 + c0, FB, p->fx, p->fy, p->mz, p->x, p->y, p->phi,
                            NULL);
        } else {
            /* without eta the viscous rows are 0 */
            if (RJ__LD(p->m, l)[RJ__LD_LAGGED] > 0)
                rj__chunk_viscous(p, l, n0 + c0, nc, FD);
            else
                memset(FD, 0, sizeof FD);
            if (last)
                rj__chunk_edge(FD, nc + 1, 0.0);
            rj__material_nodes(p, l, n0 + c0, nc + last, FB, FD, &sums[0]);
        }
        /* this chunk's last element is entry 0 of the next */
        for (r = 0; r < 4; r++) {
            FB[r * RJ__FROW] = FB[r * RJ__FROW + nc];
            FD[r * RJ__FROW] = FD[r * RJ__FROW + nc];
        }
    }
}

/* The beam pass's part for the links on the material path, which the fused pass leaves:
   after it for forces alone (rj__beam_pass: no plastic strains), before it in the step
   (rj__beam_material_step: the frames' blocks of plastic strains, at n - 1 in ep and at
   n into ep_new). With the step, the damping's power at n - 1/2 and the plastic work go
   to rj_state.damp's last two entries. */
static RJ__NOINLINE void rj__beam_material_links(const rj_model *m, const double *x,
                                                 const double *y, const double *phi,
                                                 const double *beta, const double *cx,
                                                 const double *cy, double *eu, double *beta_out,
                                                 double *cx_out, double *cy_out, double *fx,
                                                 double *fy, double *mz, const rj__adv *adv,
                                                 const double *ep, double *ep_new)
{
    rj__pass p;
    double sums[2] = { 0, 0 };
    const int ip = adv && adv->ip;
    int l;
    rj__pass_open(&p, m, x, y, phi, beta, cx, cy, eu, beta_out, cx_out, cy_out, fx, fy, mz, adv);
    for (l = 0; l < m->nl; l++) {
        const int at = m->link_pl[l];
        if (m->link_path[l] != RJ__PATH_MATERIAL)
            continue;
        rj__beam_material_link(&p, l, ip, ep && at >= 0 ? ep + at : NULL,
                               ep_new && at >= 0 ? ep_new + at : NULL, sums);
    }
    if (adv) {
        adv->damp[3 * (size_t) m->nn] = sums[0];
        adv->damp[3 * (size_t) m->nn + 1] = sums[1];
    }
}

/* The material's accounts at the end of a step, from the scalars at n (osc) into those
   at n + 1 (nsc): the structural damping's loss, the half the step before left (F_d^{n-1}
   . v^{n-1/2}) and this step's first (the power at n - 1/2, rj_state.damp), and the half
   the next step takes, -dt/2 F_d^n . v^{n+1/2} with the velocities vx, vy, w as the step
   left them; the plastic work. Returns both losses' sum. */
static RJ__NOINLINE double rj__material_accounts(const rj_model *m, const rj_state *s,
                                                   const double *osc, double *nsc,
                                                   const double *vx, const double *vy,
                                                   const double *w)
{
    const size_t nn = (size_t) m->nn;
    const double *d = s->damp;
    double sum = 0;
    int l, n;
    for (l = 0; l < m->nl; l++) {
        if (m->link_path[l] != RJ__PATH_MATERIAL)
            continue;
        for (n = m->link_first[l]; n < m->link_first[l + 1]; n++)
            sum += d[n] * vx[n] + d[nn + n] * vy[n] + d[2 * nn + n] * w[n];
    }
    nsc[RJ__FS_LSTRUCT] =
        osc[RJ__FS_LSTRUCT] + osc[RJ__FS_SPEND] - 0.5 * m->dt * d[3 * nn];
    nsc[RJ__FS_SPEND] = -0.5 * m->dt * sum;
    nsc[RJ__FS_LPLAST] = osc[RJ__FS_LPLAST] + d[3 * nn + 1];
    return nsc[RJ__FS_LSTRUCT] + nsc[RJ__FS_LPLAST];
}
/* ------------------------------------------------------------------ implicit Kelvin-Voigt damping */
/* Kelvin-Voigt damping is stiffness-proportional: on the lagged rates (v^{n-1/2}) it
   bounds the step by dt <= (2 / omega)(sqrt(1 + zeta^2) - zeta) at the stiffest mode,
   an element's axial or rotary one, whose ratio eta omega_max / 2 is huge on a slender
   link (the paper's deployment at 2 % and 2 Hz: a step 340 times shorter). So a link's
   viscous forces are taken on the rates at n + 1/2 instead, F_d = -C v^{n+1/2}: each
   step solves

       (M + kick C) dv = -kick C v*,   v^{n+1/2} = v* + dv,

   v* the velocities the other forces give. C = sum_e B_e^T D_e B_e is the link's damping
   matrix: B_e maps an element's node rates to its strains' rates (the Green strain's
   e . e' / l0^2 and the end rotations' w - beta', as rj__elem_viscous takes them) along
   its chord at n + 1/2 as v* predicts it (objective: a rigid turn strains nothing), D_e
   their stiffnesses times eta. M + kick C is block tridiagonal along the
   link (3 x 3 blocks, a node's x, y, rotation) and positive definite: one pass down and
   one up (block Thomas), O(n). A DOF that does not move (inverse mass 0) keeps dv = 0.

   The scheme is stable at the undamped bound for any eta (for one mode x'' + c x' +
   omega^2 x = 0 taken so, the step needs omega dt < sqrt(4 + 2 c dt)), and damps a mode
   of omega dt << 1 at ratio eta omega / 2 as before. Links whose nodes a rigid body
   carries keep the lagged form (their bound counts it). */

/* An element's damping matrix C_e = B^T D B (6 x 6 over its nodes' x, y, rotation: node a,
   then b) for chord (ex, ey) and constants kc (rj_model.link_kc), as three blocks: C_aa,
   C_ab, C_bb (row-major 3 x 3 each) into out[27]. B's rows: the Green strain's rate
   e . e' (stiffness d = eta EA / l0^3) on (-e, e) over the translations; the end
   rotations' w - beta', beta' = t . (v_a - v_b) with t = (e_y, -e_x) / |e|^2, their
   moments k [4 2; 2 4] (k = eta EI / l0). Written out: the translations take P =
   d e e^T + 12 k t t^T as [P -P; -P P], node a's translation and either rotation
   -6 k t, node b's +6 k t, the rotations k [4 2; 2 4]. */
static RJ__INLINE void rj__visc_elem(const double *kc, double eta, double ex, double ey,
                                     double out[27])
{
    const double inv_l2 = 1.0 / (ex * ex + ey * ey);
    const double d = eta * kc[1] * 2.0 * kc[3];
    const double k = eta * kc[0];
    const double tx = ey * inv_l2, ty = -ex * inv_l2;
    const double pxx = d * ex * ex + 12.0 * k * tx * tx;
    const double pxy = d * ex * ey + 12.0 * k * tx * ty;
    const double pyy = d * ey * ey + 12.0 * k * ty * ty;
    const double qx = 6.0 * k * tx, qy = 6.0 * k * ty;
    const double aa[9] = { pxx, pxy, -qx, pxy, pyy, -qy, -qx, -qy, 4.0 * k };
    const double ab[9] = { -pxx, -pxy, -qx, -pxy, -pyy, -qy, qx, qy, 2.0 * k };
    const double bb[9] = { pxx, pxy, qx, pxy, pyy, qy, qx, qy, 4.0 * k };
    memcpy(out, aa, sizeof aa);
    memcpy(out + 9, ab, sizeof ab);
    memcpy(out + 18, bb, sizeof bb);
}

/* out += A v (A row-major 3 x 3). */
static RJ__INLINE void rj__visc_mv(const double *A, const double *v, double *out)
{
    out[0] += A[0] * v[0] + A[1] * v[1] + A[2] * v[2];
    out[1] += A[3] * v[0] + A[4] * v[1] + A[5] * v[2];
    out[2] += A[6] * v[0] + A[7] * v[1] + A[8] * v[2];
}

/* out += A^T v. */
static RJ__INLINE void rj__visc_mtv(const double *A, const double *v, double *out)
{
    out[0] += A[0] * v[0] + A[3] * v[1] + A[6] * v[2];
    out[1] += A[1] * v[0] + A[4] * v[1] + A[7] * v[2];
    out[2] += A[2] * v[0] + A[5] * v[1] + A[8] * v[2];
}

/* The inverse of a symmetric positive definite 3 x 3 matrix (cofactors). */
static RJ__INLINE void rj__visc_inv3(const double *A, double *inv)
{
    const double c00 = A[4] * A[8] - A[5] * A[7];
    const double c01 = A[5] * A[6] - A[3] * A[8];
    const double c02 = A[3] * A[7] - A[4] * A[6];
    const double det = A[0] * c00 + A[1] * c01 + A[2] * c02;
    const double r = 1.0 / det;
    inv[0] = c00 * r;
    inv[1] = (A[2] * A[7] - A[1] * A[8]) * r;
    inv[2] = (A[1] * A[5] - A[2] * A[4]) * r;
    inv[3] = c01 * r;
    inv[4] = (A[0] * A[8] - A[2] * A[6]) * r;
    inv[5] = (A[2] * A[3] - A[0] * A[5]) * r;
    inv[6] = c02 * r;
    inv[7] = (A[1] * A[6] - A[0] * A[7]) * r;
    inv[8] = (A[0] * A[4] - A[1] * A[3]) * r;
}

/* A link's system, node by node in the scratch (RJ__VISC_PER doubles a node), after a
   record before the first node whose element and solution are 0 (and the last node's
   element 0), so that every node is solved alike: */
enum {
    RJ__VI_DINV = 0,  /* the pivot block's inverse */
    RJ__VI_Y = 9,     /* z_i, then dv */
    RJ__VI_V = 12,    /* v*: the velocities the other forces give */
    RJ__VI_MINV = 15, /* the DOFs' inverse masses (0: does not move) */
    RJ__VI_C = 18,    /* the element from this node to the next: C_aa, C_ab, C_bb */
    RJ__VI_U = 45,    /* its coupling block in the system (rj__visc_upper) */
    RJ__VI_E = 54,    /* its chord at n + 1/2 as predicted (rj__visc_chord) */
    RJ__VI_T = 56,    /* D^-1 times the coupling block (block LDL^T) */
    RJ__VI_MASK = 65, /* 1 for a DOF that moves, 0 for one that does not */
    RJ__VI_MASS = 68, /* its mass (1 where it does not move: the identity's row) */
    RJ__VISC_PER = 71
};

/* The record before the first node's: its element and solution 0. */
static void rj__visc_pad(double *W)
{
    double *pad = W - RJ__VISC_PER;
    memset(pad, 0, sizeof(double) * RJ__VISC_PER);
}

/* Node i's rows of C v (into cv): the element before it (its C_bb, C_ab^T) and the one
   after (C_aa, C_ab), from the velocities v* of each node's record. */
static RJ__INLINE void rj__visc_cv(const double *W, int i, double *cv)
{
    const double *me = W + (size_t) RJ__VISC_PER * i, *before = me - RJ__VISC_PER;
    cv[0] = cv[1] = cv[2] = 0;
    rj__visc_mv(before + RJ__VI_C + 18, me + RJ__VI_V, cv);
    rj__visc_mtv(before + RJ__VI_C + 9, before + RJ__VI_V, cv);
    rj__visc_mv(me + RJ__VI_C, me + RJ__VI_V, cv);
    rj__visc_mv(me + RJ__VI_C + 9, me + RJ__VISC_PER + RJ__VI_V, cv);
}

/* The coupling block A_{i,i+1} = kick C_ab of element i, with the rows of node i's and the
   columns of node i + 1's fixed DOFs zero, into node i's record. */
static RJ__INLINE void rj__visc_upper(double *W, int i, double kick)
{
    double *me = W + (size_t) RJ__VISC_PER * i;
    const double *next = me + RJ__VISC_PER;
    int p, q;
    for (p = 0; p < 3; p++)
        for (q = 0; q < 3; q++)
            me[RJ__VI_U + 3 * p + q] = kick * me[RJ__VI_MASK + p] * next[RJ__VI_MASK + q] *
                                       me[RJ__VI_C + 9 + 3 * p + q];
}

/* Node i's diagonal block M + kick (C_bb before + C_aa after); a fixed DOF's row and
   column are the identity's. */
static RJ__INLINE void rj__visc_diag(const double *W, int i, double kick, double *A)
{
    const double *me = W + (size_t) RJ__VISC_PER * i, *before = me - RJ__VISC_PER;
    int p, q;
    for (p = 0; p < 3; p++)
        for (q = 0; q < 3; q++)
            A[3 * p + q] = kick * me[RJ__VI_MASK + p] * me[RJ__VI_MASK + q] *
                           (me[RJ__VI_C + 3 * p + q] + before[RJ__VI_C + 18 + 3 * p + q]);
    for (p = 0; p < 3; p++)
        A[4 * p] += me[RJ__VI_MASS + p];
}

/* (M + kick C) dv = -kick C v* over a link's nodes (their records in W filled: v*, the
   inverse masses, each element's blocks; the record before W padded): dv into each
   record's RJ__VI_Y. Block LDL^T: the pivots D_i = A_ii - U^T D_{i-1}^-1 U (U =
   A_{i-1,i}, symmetric), z_i = D_i^-1 (y_i - U^T z_{i-1}), then dv_i = z_i - T_i dv_{i+1}
   with T_i = D_i^-1 A_{i,i+1}. */
static void rj__visc_solve(double *W, int nodes, double kick)
{
    double A[9], y[3];
    int i, p, q;
    for (i = 0; i < nodes; i++) {
        double *me = W + (size_t) RJ__VISC_PER * i;
        const double *before = me - RJ__VISC_PER;
        const double *U = before + RJ__VI_U, *T = before + RJ__VI_T;
        rj__visc_cv(W, i, y);
        for (p = 0; p < 3; p++)
            y[p] *= -kick * me[RJ__VI_MASK + p];
        rj__visc_diag(W, i, kick, A);
        /* A -= U^T T (its upper triangle, then mirrored) and y -= U^T z_{i-1} */
        for (p = 0; p < 3; p++)
            for (q = p; q < 3; q++)
                A[3 * p + q] -= U[p] * T[q] + U[3 + p] * T[3 + q] + U[6 + p] * T[6 + q];
        A[3] = A[1];
        A[6] = A[2];
        A[7] = A[5];
        for (p = 0; p < 3; p++)
            y[p] -= U[p] * before[RJ__VI_Y] + U[3 + p] * before[RJ__VI_Y + 1] +
                    U[6 + p] * before[RJ__VI_Y + 2];
        rj__visc_inv3(A, me + RJ__VI_DINV);
        me[RJ__VI_Y] = me[RJ__VI_Y + 1] = me[RJ__VI_Y + 2] = 0;
        rj__visc_mv(me + RJ__VI_DINV, y, me + RJ__VI_Y);
        rj__visc_upper(W, i, kick);
        for (p = 0; p < 3; p++)
            for (q = 0; q < 3; q++)
                me[RJ__VI_T + 3 * p + q] = me[RJ__VI_DINV + 3 * p] * me[RJ__VI_U + q] +
                                           me[RJ__VI_DINV + 3 * p + 1] * me[RJ__VI_U + 3 + q] +
                                           me[RJ__VI_DINV + 3 * p + 2] * me[RJ__VI_U + 6 + q];
    }
    /* back: dv_i = z_i - T_i dv_{i+1} (the last node's T is 0) */
    for (i = nodes - 2; i >= 0; i--) {
        double *me = W + (size_t) RJ__VISC_PER * i;
        double t[3] = { 0, 0, 0 };
        rj__visc_mv(me + RJ__VI_T, me + RJ__VISC_PER + RJ__VI_Y, t);
        for (p = 0; p < 3; p++)
            me[RJ__VI_Y + p] -= t[p];
    }
}
/* ------------------------------------------------------------------ joint kinematics */
/* The element needs four things from the bodies it joins: the rotary location, its rate,
   a way to apply a torque pair, and the inertias it acts on. Both reference modes supply
   them here; everything above (flags, methods, friction, energy) is shared. */
typedef struct rj__jgeo {
    double ax, ay, bx, by, a2, b2;
} rj__jgeo;

static RJ__INLINE void rj__joint_geo(const rj_model *m, const rj__joint *J, const double *x,
                                     const double *y, rj__jgeo *g)
{
    (void) m;
    if (!J->chord) {
        g->ax = g->ay = g->bx = g->by = 0;
        g->a2 = g->b2 = 1;
        return;
    }
    if (J->nK >= 0) {
        g->ax = x[J->nK] - x[J->nI];
        g->ay = y[J->nK] - y[J->nI];
    } else {
        g->ax = J->gax;
        g->ay = J->gay;
    }
    g->bx = x[J->nL] - x[J->nJ];
    g->by = y[J->nL] - y[J->nJ];
    g->a2 = g->ax * g->ax + g->ay * g->ay;
    g->b2 = g->bx * g->bx + g->by * g->by;
}

/* raw rotary location: chord mode atan2 in (-pi, pi] (to be unwrapped), tangent mode the
   running angle itself */
static RJ__INLINE double rj__joint_raw(const rj__joint *J, const rj__jgeo *g, const double *phi)
{
    if (J->chord)
        return atan2(g->ax * g->by - g->ay * g->bx, g->ax * g->bx + g->ay * g->by);
    return J->off + phi[J->nJ] - (J->nI >= 0 ? phi[J->nI] : 0.0);
}

/* theta_dot = omega_2 - omega_1; chord mode omega = (r x v_r) / |r|^2 (from Eqs 1-3) */
static RJ__INLINE double rj__joint_rate(const rj__joint *J, const rj__jgeo *g, const double *vx,
                                        const double *vy, const double *w, double *w1, double *w2)
{
    double o1 = 0.0, o2;
    if (J->chord) {
        if (J->nK >= 0)
            o1 = (g->ax * (vy[J->nK] - vy[J->nI]) - g->ay * (vx[J->nK] - vx[J->nI])) / g->a2;
        o2 = (g->bx * (vy[J->nL] - vy[J->nJ]) - g->by * (vx[J->nL] - vx[J->nJ])) / g->b2;
    } else {
        if (J->nI >= 0)
            o1 = w[J->nI];
        o2 = w[J->nJ];
    }
    if (w1)
        *w1 = o1;
    if (w2)
        *w2 = o2;
    return o2 - o1;
}

/* Torque tau on body 2 and -tau on body 1. Chord mode: force couples on J-L and I-K,
   F_L = tau perp(b)/|b|^2 = -F_J, F_K = -tau perp(a)/|a|^2 = -F_I. Tangent mode: moments
   on the pin nodes' rotations. Either way the force is tau times the gradient of theta. */
static RJ__INLINE void rj__apply_torque(const rj__joint *J, const rj__jgeo *g, double tau,
                                        double *fx, double *fy, double *mz)
{
    double sx, sy;
    if (!J->chord) {
        mz[J->nJ] += tau;
        if (J->nI >= 0)
            mz[J->nI] -= tau;
        return;
    }
    sx = -tau * g->by / g->b2;
    sy = tau * g->bx / g->b2;
    fx[J->nL] += sx;
    fy[J->nL] += sy;
    fx[J->nJ] -= sx;
    fy[J->nJ] -= sy;
    if (J->nK >= 0) {
        sx = tau * g->ay / g->a2;
        sy = -tau * g->ax / g->a2;
        fx[J->nK] += sx;
        fy[J->nK] += sy;
        fx[J->nI] -= sx;
        fy[J->nI] -= sy;
    }
}

/* g^T M^-1 g: rate change per unit torque impulse (1/I_red, with the pin's own mass). */
static RJ__INLINE double rj__joint_compliance(const rj_model *m, const rj__joint *J,
                                              const rj__jgeo *g)
{
    double c, px, py;
    if (!J->chord) {
        /* a rotor's reflected inertia on the relative rotation (rj__stage_rotors) */
        c = m->rinv[J->nJ] + (J->nI >= 0 ? m->rinv[J->nI] : 0.0);
        return J->rotor > 0 ? c / (1.0 + J->rotor * c) : c;
    }
    c = m->einv[J->nL] / g->b2;
    px = g->by / g->b2;
    py = -g->bx / g->b2; /* g_J = -perp(b)/|b|^2 */
    if (J->nK >= 0) {
        c += m->einv[J->nK] / g->a2;
        px += -g->ay / g->a2;
        py += g->ax / g->a2; /* g_I = perp(a)/|a|^2 */
    }
    c += m->einv[J->nJ] * (px * px + py * py);
    return c;
}

/* Adds rotation increments dw1 to body 1's and dw2 to body 2's reference (node K / L
   velocities in chord mode, pin rotations in tangent mode). */
static void rj__spin(const rj__joint *J, const rj__jgeo *g, double dw1, double dw2, double *vx,
                     double *vy, double *w)
{
    if (!J->chord) {
        w[J->nJ] += dw2;
        if (J->nI >= 0)
            w[J->nI] += dw1;
        return;
    }
    vx[J->nL] += -dw2 * g->by;
    vy[J->nL] += dw2 * g->bx;
    if (J->nK >= 0) {
        vx[J->nK] += -dw1 * g->ay;
        vy[J->nK] += dw1 * g->ax;
    }
}

/* Turns body 2's reference by d2 and body 1's by d1 (forced displacement). */
/* The positions of a joint's nodes summed: finite while they all are. */
static double rj__joint_nodes_sum(const rj__joint *J, const double *x, const double *y,
                                  const double *phi)
{
    const int nodes[4] = { J->nI, J->nK, J->nJ, J->nL };
    double sum = 0;
    int k;
    for (k = 0; k < 4; k++)
        if (nodes[k] >= 0)
            sum += (x[nodes[k]] + y[nodes[k]]) + phi[nodes[k]];
    return sum;
}

static void rj__turn(const rj__joint *J, double d1, double d2, double *x, double *y, double *phi)
{
    double c, sn, rx, ry;
    if (!J->chord) {
        phi[J->nJ] += d2;
        if (J->nI >= 0)
            phi[J->nI] += d1;
        return;
    }
    if (d2 != 0) {
        c = cos(d2);
        sn = sin(d2);
        rx = x[J->nL] - x[J->nJ];
        ry = y[J->nL] - y[J->nJ];
        x[J->nL] = x[J->nJ] + c * rx - sn * ry;
        y[J->nL] = y[J->nJ] + sn * rx + c * ry;
    }
    if (d1 != 0 && J->nK >= 0) {
        c = cos(d1);
        sn = sin(d1);
        rx = x[J->nK] - x[J->nI];
        ry = y[J->nK] - y[J->nI];
        x[J->nK] = x[J->nI] + c * rx - sn * ry;
        y[J->nK] = y[J->nI] + sn * rx + c * ry;
    }
}

/* Table and spring: resistive torque on body 2 is -(table + spring); potential energy. */
static double rj__table_turns_potential(const rj_joint_def *d, const rj__joint *J, double run,
                                        double *torque)
{
    double th = rj__mod2pi(run), turns = floor(run / RJ__TWO_PI);
    *torque = rj_table_torque(d->table_angle, d->table_torque, d->table_count, th);
    return rj__table_potential(d->table_angle, d->table_torque, d->table_count, th) +
           turns * J->tv_turn;
}

/* ------------------------------------------------------------------ model build */
/* Places link l straight at angle ang with its node at on (px, py), turning at om about
   it while that node moves at (vpx, vpy). */
static void rj__place(const rj_model *m, int l, int at, double px, double py, double ang,
                      double vpx, double vpy, double om, double *x, double *y, double *phi,
                      double *vx, double *vy, double *w)
{
    int i, n0 = m->link_first[l], ne = m->ldef[l].elements;
    double c = cos(ang), s = sin(ang), l0 = m->link_l0[l];
    for (i = 0; i <= ne; i++) {
        double rx = c * l0 * (i - at), ry = s * l0 * (i - at);
        x[n0 + i] = px + rx;
        y[n0 + i] = py + ry;
        phi[n0 + i] = ang;
        vx[n0 + i] = vpx - om * ry;
        vy[n0 + i] = vpy + om * rx;
        w[n0 + i] = om;
    }
}


/* Coupling c's torques on joint b, elastic and damping (joint a takes -ratio times each),
   from the joints' running angles and rates; *energy gains the cable's 1/2 k e^2. */
static void rj__coupling_torques(const rj_model *m, const rj_coupling_def *c, double th_a,
                                 double th_b, double w_a, double w_b, double *elastic,
                                 double *damp, double *energy)
{
    const double turn_a = th_a - m->jdef[c->joint_a].angle0;
    const double turn_b = th_b - m->jdef[c->joint_b].angle0;
    const double e = turn_b - c->ratio * turn_a - c->offset;
    *elastic = -c->stiffness * e;
    *damp = -c->damping * (w_b - c->ratio * w_a);
    *energy += 0.5 * c->stiffness * e * e;
}

/* Coupling c's torques into the two joints' new records (their spring and damping
   components); returns the total on joint b. */
static double rj__coupling_record(const rj_coupling_def *c, double elastic, double damp,
                                  double *rec_a, double *rec_b)
{
    rec_b[RJ__JD_TQ0 + RJ_TORQUE_SPRING] += elastic;
    rec_b[RJ__JD_TQ0 + RJ_TORQUE_DAMPING] += damp;
    rec_a[RJ__JD_TQ0 + RJ_TORQUE_SPRING] -= c->ratio * elastic;
    rec_a[RJ__JD_TQ0 + RJ_TORQUE_DAMPING] -= c->ratio * damp;
    return elastic + damp;
}
/* ------------------------------------------------------------------ rigid bodies in mixed scenes */
/* A rigid link among flexible ones is one rigid body. It carries its own nodes, whose
   translation and rotation follow it, and the nodes pinned to them, whose translation
   follows it while their rotation stays free (the pin). The body's state is its anchor
   (the centre of mass, or the fixed pin it turns about), the anchor's velocity, its rate
   and its angle; node forces act on it at their points, node moments on its own nodes
   add to its torque. Its nodes are massless attachment points; the body's mass and
   inertia are the link's exact ones (rod, tip mass and inertia) plus the pinned nodes'
   lumped masses. The step is the same central difference: rates at half steps, the
   nodes placed by the exact rotation, so the body stays rigid to round-off. */
#define RJ__FCL(m, f, c) ((f) + (m)->cl_off + 6 * (size_t) (c))
#define RJ__CL_RIGID(m, n)                                                                         \
    ((m)->node_cl[n] >= 0 && (n) >= (m)->link_first[(m)->node_cl[n]] &&                            \
     (n) < (m)->link_first[(m)->node_cl[n] + 1])

/* A section's area as the rigid bodies take it: width x height for a rectangle (not its
   layers' sum), else the given area. */
static double rj__plain_area(const rj_link_def *d)
{
    return d->section == RJ_SECTION_RECT ? d->width * d->height : d->area;
}

/* The link and the node within it of global node i (binary search on link_first). */
static void rj__node_of(const rj_model *m, int i, int *link, int *node)
{
    int lo = 0, hi = m->nl - 1;
    while (lo < hi) {
        const int mid = lo + (hi - lo + 1) / 2;
        if (m->link_first[mid] <= i)
            lo = mid;
        else
            hi = mid - 1;
    }
    *link = lo;
    *node = i - m->link_first[lo];
}

/* Whether node n is one of a rigid link's own nodes (its link is a body of the scene). */
static int rj__rigid_own(const rj_model *m, int n)
{
    int link, node;
    rj__node_of(m, n, &link, &node);
    return m->ldef[link].fidelity == RJ_LINK_RIGID;
}

/* A rigid body's own node in a mixed scene (massless: its body carries it)? */
static int rj__own_body_node(const rj_model *m, int k)
{
    return k >= 0 && m->ncl && RJ__CL_RIGID(m, k);
}

/* A pin group holding nodes of two rigid links: a pin between two bodies (rj__body_pins
   keeps them together), from body l's node mine to every own node of a later rigid link
   in the group; a body's members are its own nodes and the group's other nodes. */
static void rj__body_pin_group(rj_model *m, int l, int gi, int mine)
{
    int k;
    for (k = m->grp_first[gi]; k < m->grp_first[gi + 1]; k++) {
        const int n = m->grp_node[k];
        int link, node;
        if (!rj__rigid_own(m, n))
            continue;
        rj__node_of(m, n, &link, &node);
        if (link <= l)
            continue;
        m->bp_node[2 * m->nbp] = mine;
        m->bp_node[2 * m->nbp + 1] = n;
        m->nbp++;
    }
}

static int rj__clusters(rj_model *m, rj_error *err)
{
    int l, i, gi, k, cnt = 0, ng = 0, q = 0;
    m->nbp = 0;
    for (l = 0; l < m->nl; l++) {
        const rj_link_def *d = &m->ldef[l];
        const int n0 = m->link_first[l], nt = m->link_first[l + 1] - 1;
        double A, mr, mt, dc, ux, uy, cx, cy, vcx, vcy, M, ax, ay, vax, vay, I, w0 = m->w0[n0];
        int nfix = 0, fixn = -1, held = 0;
        m->cl_first[l] = cnt;
        if (d->fidelity != RJ_LINK_RIGID)
            continue;
        for (i = n0; i <= nt; i++) {
            m->cl_node[cnt++] = i;
            m->node_cl[i] = l;
        }
        for (gi = 0; gi < m->ng; gi++) {
            int has = 0, mine = -1;
            for (k = m->grp_first[gi]; k < m->grp_first[gi + 1]; k++)
                if (m->grp_node[k] >= n0 && m->grp_node[k] <= nt) {
                    has = 1;
                    mine = m->grp_node[k];
                }
            if (!has)
                continue;
            rj__body_pin_group(m, l, gi, mine);
            if (m->grp_inv[gi] == 0) {
                nfix++;
                fixn = m->grp_node[m->grp_first[gi]];
            } /* pinned to something fixed */
            for (k = m->grp_first[gi]; k < m->grp_first[gi + 1]; k++) {
                const int n = m->grp_node[k];
                /* another body's own node is that body's: a pin between the two */
                if (m->node_cl[n] < 0 && !rj__rigid_own(m, n)) {
                    m->cl_node[cnt++] = n;
                    m->node_cl[n] = l;
                }
            }
        }
        for (i = n0; i <= nt; i++) {
            if (m->rinv[i] == 0)
                held = 1; /* clamped or fixed */
            if (m->node_grp[i] < 0 && m->tinv[i] == 0) {
                nfix++;
                fixn = i;
            }
        }
        /* the link as a body: rod plus tip mass, as in scenes of rigid links */
        A = rj__plain_area(d);
        mr = d->rho * A * d->length;
        mt = mr + d->tip_mass;
        dc = (mr * 0.5 * d->length + d->tip_mass * d->length) / mt;
        ux = (m->x0[nt] - m->x0[n0]) / d->length;
        uy = (m->y0[nt] - m->y0[n0]) / d->length;
        cx = m->x0[n0] + dc * ux;
        cy = m->y0[n0] + dc * uy;
        vcx = m->vx0[n0] - w0 * (cy - m->y0[n0]);
        vcy = m->vy0[n0] + w0 * (cx - m->x0[n0]);
        M = mt;
        ax = mt * cx;
        ay = mt * cy;
        vax = mt * vcx;
        vay = mt * vcy;
        for (k = m->cl_first[l]; k < cnt; k++) {
            const int n = m->cl_node[k];
            if (n >= n0 && n <= nt)
                continue;
            M += m->mass[n];
            ax += m->mass[n] * m->x0[n];
            ay += m->mass[n] * m->y0[n];
            vax += m->mass[n] * m->vx0[n];
            vay += m->mass[n] * m->vy0[n];
        }
        ax /= M;
        ay /= M;
        vax /= M;
        vay /= M;
        m->cl_fix[l] = held || nfix > 1 ? 2 : nfix;
        if (nfix >= 1) {
            ax = m->x0[fixn];
            ay = m->y0[fixn];
            vax = vay = 0;
        }
        if (m->cl_fix[l] == 2) {
            vax = vay = 0;
            w0 = 0;
        }
        I = mr * d->length * d->length / 12.0 +
            mr * (0.5 * d->length - dc) * (0.5 * d->length - dc) +
            d->tip_mass * (d->length - dc) * (d->length - dc) + d->tip_inertia +
            mt * ((cx - ax) * (cx - ax) + (cy - ay) * (cy - ay));
        for (k = m->cl_first[l]; k < cnt; k++) {
            const int n = m->cl_node[k];
            if (n < n0 || n > nt)
                I += m->mass[n] *
                     ((m->x0[n] - ax) * (m->x0[n] - ax) + (m->y0[n] - ay) * (m->y0[n] - ay));
        }
        m->cl_M[l] = M;
        m->cl_I[l] = I;
        m->cl_th0[3 * l] = m->phi0[n0];
        m->cl_th0[3 * l + 1] = vax;
        m->cl_th0[3 * l + 2] = vay;
        for (k = m->cl_first[l]; k < cnt; k++) {
            const int n = m->cl_node[k];
            const int own = n >= n0 && n <= nt;
            m->cl_rx[n] = m->x0[n] - ax;
            m->cl_ry[n] = m->y0[n] - ay;
            m->einv[n] = 0;
            m->kmass[n] = 0;
            /* a pinned node's translation is the body's point there: its largest inverse
               mass (1/M + r^2/I) stands in for it in the stability bound and in the rate
               predictions of joints between flexible links at that node; the body's
               update overwrites what the node update does with it */
            m->tinv[n] = own || m->cl_fix[l] == 2
                             ? 0.0
                             : (m->cl_fix[l] == 0 ? 1.0 / M : 0.0) +
                                   (m->cl_rx[n] * m->cl_rx[n] + m->cl_ry[n] * m->cl_ry[n]) / I;
            /* the initial velocities of the rigid motion */
            m->vx0[n] = vax - w0 * m->cl_ry[n];
            m->vy0[n] = vay + w0 * m->cl_rx[n];
            if (own) {
                m->krot[n] = 0;
                m->mass[n] = 0;
                m->rinertia[n] = I;
                m->rinv[n] = m->cl_fix[l] == 2 ? 0.0 : 1.0 / I;
                m->w0[n] = w0;
            }
        }
    }
    m->cl_first[m->nl] = cnt;
    /* pin groups holding a body's node are the body's now */
    for (gi = 0; gi < m->ng; gi++) {
        const int f0 = m->grp_first[gi], f1 = m->grp_first[gi + 1];
        int absorbed = m->node_cl[m->grp_node[f0]] >= 0;
        if (absorbed) {
            for (k = f0; k < f1; k++)
                m->node_grp[m->grp_node[k]] = -1;
            continue;
        }
        m->grp_inv[ng] = m->grp_inv[gi];
        for (k = f0; k < f1; k++) {
            m->grp_node[q++] = m->grp_node[k];
            m->node_grp[m->grp_node[k]] = ng;
        }
        m->grp_first[++ng] = q;
    }
    m->ng = ng;
    (void) err;
    return 1;
}

/* Twice a body's kinetic energy in the v^{n-1/2}.v^{n+1/2} form (first step: v(0) given). */
static double rj__cl_ke2(const rj_model *m, int c, const double *oc, const double *nc, int first)
{
    const double vx = first ? 2 * oc[2] - nc[2] : oc[2], vy = first ? 2 * oc[3] - nc[3] : oc[3],
                 w = first ? 2 * oc[4] - nc[4] : oc[4];
    return (m->cl_fix[c] == 0 ? m->cl_M[c] * (vx * nc[2] + vy * nc[3]) : 0.0) +
           m->cl_I[c] * w * nc[4];
}

/* The body's torque about its anchor and force from the node loads (x, y at step n). */
static void rj__cl_load(const rj_model *m, int c, const double *oc, const double *x,
                        const double *y, const double *fx, const double *fy, const double *mz,
                        double *Fx, double *Fy, double *T)
{
    int k;
    *Fx = *Fy = *T = 0;
    for (k = m->cl_first[c]; k < m->cl_first[c + 1]; k++) {
        const int n = m->cl_node[k];
        *Fx += fx[n];
        *Fy += fy[n];
        *T += (x[n] - oc[0]) * fy[n] - (y[n] - oc[1]) * fx[n];
        if (RJ__CL_RIGID(m, n))
            *T += mz[n];
    }
}

/* One body of a pinned pair at the pin: its point r from the anchor, the pin's velocity
   (the step's, rj__pair_side_at), its inverse mass and inertia (0 where held). */
typedef struct rj__pair_side {
    double r[2], v[2], tinv, rinv;
} rj__pair_side;

/* The give of a torque pair on two bodies pinned together, c = 1/I_a + 1/I_b -
   u^T K^-1 u, with K the pin's mobility (the sum of 1/M + perp(r) perp(r)^T / I) and
   u = sum perp(r) / I: a torque turns both, and the pin's impulse keeps its points
   together. K (xx, xy, yy), u and det K are left for the pin's impulse; det 0 where the
   pin adds nothing (two bodies turning about one point, or held), c then 1/I_a + 1/I_b. */
static double rj__pair_give(const rj__pair_side *a, const rj__pair_side *b, double *K,
                            double *u, double *det)
{
    K[0] = a->tinv + b->tinv + a->rinv * a->r[1] * a->r[1] + b->rinv * b->r[1] * b->r[1];
    K[1] = -(a->rinv * a->r[1] * a->r[0] + b->rinv * b->r[1] * b->r[0]);
    K[2] = a->tinv + b->tinv + a->rinv * a->r[0] * a->r[0] + b->rinv * b->r[0] * b->r[0];
    u[0] = -(a->rinv * a->r[1] + b->rinv * b->r[1]);
    u[1] = a->rinv * a->r[0] + b->rinv * b->r[0];
    *det = K[0] * K[2] - K[1] * K[1];
    if (!(*det > 1e-12 * (K[0] + K[2]) * (K[0] + K[2]))) {
        *det = 0;
        return a->rinv + b->rinv;
    }
    return a->rinv + b->rinv -
           (K[2] * u[0] * u[0] - 2 * K[1] * u[0] * u[1] + K[0] * u[1] * u[1]) / *det;
}

/* Joint J's give between two rigid bodies without their pin, 1/I_a + 1/I_b (about the
   anchors): the inertia an adaptive limit's stiffness takes there (Eq 21). The pinned
   pair's (rj__pair_give, smaller) made the limit too stiff for the stability bound,
   which sees the pair's bodies through their nodes (omega dt 2.21 with the limits
   counted, the adaptive limits' search found no step); with this one the limit's true
   omega dt stays below 1. */
static double rj__pair_free_give(const rj_model *m, const rj__joint *J)
{
    const int a = m->node_cl[J->nI], b = m->node_cl[J->nJ];
    const double ra = m->cl_fix[a] != 2 ? 1.0 / m->cl_I[a] : 0.0;
    const double rb = m->cl_fix[b] != 2 ? 1.0 / m->cl_I[b] : 0.0;
    return ra + rb;
}

/* Body c's record pushed by the impulse imp (x, y, and angular about its anchor), as
   SHAKE and the pins between bodies push it: the anchor and the angle move by imp over
   the body's mass and inertia, and its rates by that over dt (positions and rates stay
   each other's chord); a body turning about a fixed pin keeps its anchor. */
static void rj__cl_push(const rj_model *m, int c, const double *imp, double dt, double *nc)
{
    if (m->cl_fix[c] == 0) {
        nc[0] += imp[0] / m->cl_M[c];
        nc[1] += imp[1] / m->cl_M[c];
        nc[2] += imp[0] / (m->cl_M[c] * dt);
        nc[3] += imp[1] / (m->cl_M[c] * dt);
    }
    nc[5] += imp[2] / m->cl_I[c];
    nc[4] += imp[2] / (m->cl_I[c] * dt);
}

/* Places the body's members at its record (anchor, angle); with setv the node velocities
   become the chord velocities (x^{n+1} - x^n)/dt and its own nodes take its rate. */
static double rj__cl_pose(const rj_model *m, int c, const double *nc, const double *x,
                          const double *y, double dt, int setv, double *nx, double *ny,
                          double *nphi, double *nvx, double *nvy, double *nw)
{
    const double th0 = m->cl_th0[3 * c], co = cos(nc[5] - th0), sn = sin(nc[5] - th0);
    double sum = nc[4]; /* the positions written and the rate: finite while they all are */
    int k;
    for (k = m->cl_first[c]; k < m->cl_first[c + 1]; k++) {
        const int n = m->cl_node[k];
        const double px = nc[0] + co * m->cl_rx[n] - sn * m->cl_ry[n],
                     py = nc[1] + sn * m->cl_rx[n] + co * m->cl_ry[n];
        if (setv) {
            nvx[n] = (px - x[n]) / dt;
            nvy[n] = (py - y[n]) / dt;
        }
        nx[n] = px;
        ny[n] = py;
        if (RJ__CL_RIGID(m, n)) {
            nphi[n] = nc[5] + (m->phi0[n] - th0);
            if (setv)
                nw[n] = nc[4];
        }
        sum += (px + py) + nphi[n];
        /* the velocities come from positions here, not the other way round: a position of
           1e308 m at n (a crafted state) makes them infinite while both positions are finite */
        if (setv)
            sum += nvx[n] + nvy[n];
    }
    return sum;
}

/* The inverse mass of DOF k of node i (0, 1: translation, its group's when grouped; 2:
   rotation), as the stability bound's operator takes it (rj__lz_apply). */
static double rj__lz_inv(const rj_model *m, int i, int k)
{
    if (k == 2)
        return m->rinv[i];
    if (m->node_grp[i] >= 0)
        return m->grp_inv[m->node_grp[i]];
    return m->tinv[i];
}

/* A joint's rate change per unit torque impulse at the start (1/I_red): (M^-1)_jj in
   joint coordinates for rigid scenes, else from the pin nodes (rj__joint_compliance). */
static double rj__joint_compliance0(const rj_model *m, int j)
{
    rj__jgeo g;
    if (m->rigid)
        return m->jnt[j].minv;
    rj__joint_geo(m, &m->jnt[j], m->x0, m->y0, &g);
    return rj__joint_compliance(m, &m->jnt[j], &g);
}

/* The fastest damping rate a joint's damper gives the bodies it joins, 1/s: C times the
   rate change per unit torque impulse (1/I_red), the largest over the joints. */
static double rj__damping_rate(const rj_model *m)
{
    double worst = 0;
    int j;
    for (j = 0; j < m->nj; j++) {
        double rate;
        if (!(m->jnt[j].c_lin > 0))
            continue;
        rate = m->jnt[j].c_lin * rj__joint_compliance0(m, j);
        if (rate > worst)
            worst = rate;
    }
    /* a cable loop's damper acts on both joints' rates, joint a through the ratio */
    for (j = 0; j < m->ncp; j++) {
        const rj_coupling_def *c = &m->cp[j];
        const double rate = c->damping * (rj__joint_compliance0(m, c->joint_b) +
                                          c->ratio * c->ratio *
                                              rj__joint_compliance0(m, c->joint_a));
        if (rate > worst)
            worst = rate;
    }
    return worst;
}

/* Central differences with damping on the lagged velocity are stable for a mode of
   frequency omega and damping ratio zeta while dt <= (2/omega)(sqrt(1 + zeta^2) - zeta);
   with 2 zeta omega = d (the damping rate) that is dt <= 2 / (d/2 + sqrt(omega^2 + d^2/4)),
   which holds for omega = 0 too (dt <= 2/d). The fastest mode paired with the fastest
   damping rate bounds every pairing the model can have. No stiffness and no damping:
   nothing bounds the step (rigid bodies alone), 1 s stands for that. */
static double rj__dt_bound_of(double omega, double damp_rate)
{
    const double half = 0.5 * damp_rate;
    const double denom = half + sqrt(omega * omega + half * half);
    if (denom == 0)
        return 1.0;
    return RJ__DT_MARGIN * 2.0 / denom; /* NaN or 0 when omega is NaN or infinite */
}

/* omega from the eigenvalue estimate: a round-off negative is 0; NaN stays NaN, so that
   a model whose stiffness or mass leaves doubles behind is refused, not given a bound */
static double rj__omega_of(double om2)
{
    if (om2 == om2 && om2 < 0)
        return 0;
    return sqrt(om2);
}

static unsigned long long rj__fnv(unsigned long long h, const void *p, size_t n)
{
    const unsigned char *c = (const unsigned char *) p;
    size_t i;
    for (i = 0; i < n; i++) {
        h ^= c[i];
        h *= 1099511628211ULL;
    }
    return h;
}

/* FNV-1a of a double or an int (their bytes), one value at a time. */
static unsigned long long rj__fnv_d(unsigned long long h, double v)
{
    return rj__fnv(h, &v, sizeof v);
}
static unsigned long long rj__fnv_i(unsigned long long h, int v)
{
    return rj__fnv(h, &v, sizeof v);
}

/* Row r of def into the hash: as its hash form says (an int as a double or as an int;
   a vector's two components; a table's count and its pairs). */
static unsigned long long rj__fnv_row(unsigned long long h, const rj__field *r, const void *def)
{
    int k, n;
    if (r->type == RJ__FT_TABLE) {
        const double *first = (const double *) (const void *) ((const char *) def + r->aux);
        n = rj__row_int(def, r);
        h = rj__fnv_i(h, n);
        for (k = 0; k < n; k++) {
            h = rj__fnv_d(h, first[k]);
            h = rj__fnv_d(h, first[RJ_TABLE_MAX + k]);
        }
        return h;
    }
    if (rj__row_is_real(r)) {
        const double v0 = rj__row_real(def, r, 0);
        const double v1 = r->type == RJ__FT_VEC2 ? rj__row_real(def, r, 1) : r->def;
        /* 'z': hashed only when it differs from its default */
        if (r->hash_as == 'z' && v0 == r->def && v1 == r->def)
            return h;
        h = rj__fnv_d(h, v0);
        return r->type == RJ__FT_VEC2 ? rj__fnv_d(h, rj__row_real(def, r, 1)) : h;
    }
    memcpy(&n, (const char *) def + r->offset, sizeof n);
    /* 'z': an int hashed only when it differs from its default */
    if (r->hash_as == 'z')
        return n == (int) r->def ? h : rj__fnv_i(h, n);
    return r->hash_as == 'i' ? rj__fnv_i(h, n) : rj__fnv_d(h, (double) n);
}

/* The rows of kind in the order of their hash places: into order (room for 64), their
   count returned. */
static int rj__hash_order(int kind, const rj__field **order)
{
    int n, k, at, count = 0;
    const rj__field *t = rj__fields(kind, &n);
    for (at = 0; count < 64; at++) {
        const int before = count;
        for (k = 0; k < n && count < 64; k++)
            if (t[k].hash_at == at)
                order[count++] = &t[k];
        if (count == before)
            return count;
    }
    return count;
}

/* A definition into the hash: its rows in hash order (rj__hash_order). */
static unsigned long long rj__fnv_def(unsigned long long h, const rj__field *const *order,
                                      int count, const void *def)
{
    int k;
    for (k = 0; k < count; k++)
        h = rj__fnv_row(h, order[k], def);
    return h;
}

/* The model's identity for checkpoints: every definition member that a state's meaning
   depends on (member by member, in the order of the rows' hash places: a struct's
   padding bytes are not defined), the step in use, and the masses and start positions
   derived from them. */
static unsigned long long rj__model_hash(const rj_model *m)
{
    unsigned long long h = 14695981039346656037ULL;
    const rj__field *lo[64], *jo[64], *so[64], *ao[64];
    const int nlo = rj__hash_order(RJ__DEF_LINK, lo), njo = rj__hash_order(RJ__DEF_JOINT, jo);
    const int nso = rj__hash_order(RJ__DEF_SOLVER, so), nao = rj__hash_order(RJ__DEF_LOAD, ao);
    const rj__field *co[64], *po[64];
    const int nco = rj__hash_order(RJ__DEF_ACTUATOR, co);
    const int npo = rj__hash_order(RJ__DEF_COUPLING, po);
    int l, j, k;
    h = rj__fnv_i(h, m->nn);
    h = rj__fnv_i(h, m->ne);
    h = rj__fnv_i(h, m->nj);
    h = rj__fnv_d(h, m->dt);
    for (l = 0; l < m->nl; l++)
        h = rj__fnv_def(h, lo, nlo, &m->ldef[l]);
    for (j = 0; j < m->nj; j++)
        h = rj__fnv_def(h, jo, njo, &m->jdef[j]);
    h = rj__fnv(h, m->mass, sizeof(double) * (size_t) m->nn);
    h = rj__fnv(h, m->x0, sizeof(double) * (size_t) m->nn);
    h = rj__fnv_def(h, so, nso, &m->solver);
    for (k = 0; k < m->nload; k++)
        h = rj__fnv_def(h, ao, nao, &m->load[k]);
    for (k = 0; k < m->nact; k++)
        h = rj__fnv_def(h, co, nco, &m->act[k]);
    for (k = 0; k < m->ncp; k++)
        h = rj__fnv_def(h, po, npo, &m->cp[k]);
    return h;
}

/* The first place in m->dnode (ascending) whose node is n or after. */
static int rj__dnode_from(const rj_model *m, int n)
{
    int lo = 0, hi = m->ndn;
    while (lo < hi) {
        const int mid = lo + (hi - lo) / 2;
        if (m->dnode[mid] < n)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}

/* Is node n one of m->dnode? */
static int rj__is_dnode(const rj_model *m, int n)
{
    const int at = rj__dnode_from(m, n);
    return at < m->ndn && m->dnode[at] == n;
}

/* A link whose sizes and material leave doubles behind (an element length whose square
   underflows, a stiffness or a mass that overflows or vanishes) has no usable step or no
   finite energy: refused here, naming the link and the quantity, before anything uses it. */
static int rj__check_links(const rj_model *m, rj_error *err)
{
    char f[64];
    int l, k;
    for (l = 0; l < m->nl; l++) {
        const rj_link_def *d = &m->ldef[l];
        const double *kc = m->link_kc + 4 * (size_t) l;
        const int n0 = m->link_first[l];
        const char *what = NULL;
        double value = 0;
        if (!(kc[2] >= DBL_MIN) || !rj__finite(kc[3])) {
            what = "its element length squared";
            value = kc[2];
        } else if (!(m->link_EA[l] >= DBL_MIN) || !rj__finite(m->link_EA[l])) {
            what = "its axial stiffness EA (N)";
            value = m->link_EA[l];
        } else if (!(m->link_EI[l] >= DBL_MIN) || !rj__finite(m->link_EI[l])) {
            what = "its bending stiffness EI (N m^2)";
            value = m->link_EI[l];
        } else if (!rj__finite(kc[0]) || !rj__finite(kc[1])) {
            what = "its element stiffness EI/l0 or EA/l0";
            value = rj__finite(kc[0]) ? kc[1] : kc[0];
        }
        for (k = 0; !what && k <= d->elements; k++) {
            const double mass = m->mass[n0 + k], rot = m->rinertia[n0 + k];
            if (!(mass >= DBL_MIN) || !rj__finite(mass) || !rj__finite(1.0 / mass)) {
                what = "a node's mass (kg)";
                value = mass;
            } else if (!(rot >= DBL_MIN) || !rj__finite(rot) || !rj__finite(1.0 / rot)) {
                what = "a node's rotary inertia (kg m^2)";
                value = rot;
            }
        }
        if (!what)
            continue;
        RJ__FIELD(f, "links[%d]", l);
        rj__fail(err, RJ_ERR_INVALID, f, value,
                 "links[%d] (length %g m, %d elements, E %g Pa, rho %g kg/m^3) gives %s = %g, "
                 "which is zero, infinite or below what doubles resolve: no step is usable; scale "
                 "the link's sizes or material into range",
                 l, d->length, d->elements, d->E, d->rho, what, value);
        return 0;
    }
    return 1;
}

/* Adds one warning line to the model's list (as much as fits). */
static void rj__model_warn(rj_model *m, const char *fmt, ...)
{
    char line[320];
    va_list ap;
    int wanted;
    va_start(ap, fmt);
    wanted = vsnprintf(line, sizeof line, fmt, ap);
    va_end(ap);
    rj__fit_words(line, sizeof line, wanted);
    m->nwarn++;
    if (strlen(m->warnings) + strlen(line) + 2 > sizeof m->warnings)
        return;
    rj__cat(m->warnings, sizeof m->warnings, line);
    rj__cat(m->warnings, sizeof m->warnings, "\n");
}

/* Limits a careful engineer would question: one the joint starts past, and one its spring
   never drives it to (the spring comes to rest at its free angle first, or turns the joint
   away from its only limit). Running angles (the limits as the joint meets them from
   angle0, J->fwd and J->rev), in degrees in the text. */
static void rj__limit_warnings(rj_model *m)
{
    int j;
    for (j = 0; j < m->nj; j++) {
        const rj_joint_def *d = &m->jdef[j];
        const rj__joint *J = &m->jnt[j];
        const double start = d->angle0, rest = d->spring_free_angle;
        const int drive = d->spring_k > 0 ? (rest > start) - (rest < start) : 0;
        if (!d->has_forward && !d->has_reverse)
            continue;
        if (d->has_forward && start > J->fwd)
            rj__model_warn(m, "joints[%d] starts %.4g deg past its forward limit", j,
                           rj_deg(start - J->fwd));
        else if (d->has_reverse && start < J->rev)
            rj__model_warn(m, "joints[%d] starts %.4g deg past its reverse limit", j,
                           rj_deg(J->rev - start));
        else if (drive > 0 && d->has_forward && J->fwd > rest)
            rj__model_warn(m,
                           "joints[%d]: its spring turns it forward from %.4g deg and rests at "
                           "%.4g deg, short of its forward limit, met at %.4g deg: the spring "
                           "alone never brings it there%s",
                           j, rj_deg(start), rj_deg(rest), rj_deg(J->fwd),
                           d->lock ? " (it never latches)" : "");
        else if (drive < 0 && d->has_reverse && J->rev < rest)
            rj__model_warn(m,
                           "joints[%d]: its spring turns it in reverse from %.4g deg and rests at "
                           "%.4g deg, short of its reverse limit, met at %.4g deg: the spring "
                           "alone never brings it there%s",
                           j, rj_deg(start), rj_deg(rest), rj_deg(J->rev),
                           d->lock ? " (it never latches)" : "");
        else if (drive > 0 && !d->has_forward)
            rj__model_warn(
                m,
                "joints[%d]: its spring turns it forward from %.4g deg, away from its only limit "
                "(reverse, met at %.4g deg): the spring alone never brings it there%s",
                j, rj_deg(start), rj_deg(J->rev), d->lock ? " (it never latches)" : "");
        else if (drive < 0 && !d->has_reverse)
            rj__model_warn(
                m,
                "joints[%d]: its spring turns it in reverse from %.4g deg, away from its only "
                "limit (forward, met at %.4g deg): the spring alone never brings it there%s",
                j, rj_deg(start), rj_deg(J->fwd), d->lock ? " (it never latches)" : "");
    }
}

/* The root of node's set (union-find, each path pointed at its root as it is walked). */
static int rj__set_root(int *set, int node)
{
    int root = node;
    while (set[root] != root)
        root = set[root];
    while (set[node] != root) {
        const int next = set[node];
        set[node] = root;
        node = next;
    }
    return root;
}

/* Adds node to group g at its cursor unless it is a member already (mark[node] = g). */
static void rj__group_add(rj_model *m, int *mark, int *cursor, int g, int node)
{
    if (mark[node] >= 0)
        return;
    mark[node] = g;
    m->grp_node[cursor[g]++] = node;
}

/* Pin groups: the nodes that joints pin together, each set of them one group, in the
   order of their first joint. Its first member is its anchor: the first body1 pin (in
   joint order) that no joint pins as a body2 node (a chain's top), else the first body1
   pin (a loop); then the body2 pins in joint order, then any other body1 pin. In a scene
   without loops that is each body1 pin node with the body2 nodes pinned to it however
   they are reached. Linear in the joints, with scratch of 4 nn + ng ints (each node's
   set, mark, anchor and group, then each group's fill cursor); node_grp is -1 on entry.
   Returns the number of groups. */
static int rj__pin_groups(rj_model *m, int *scratch)
{
    const int nn = m->nn;
    int *set = scratch, *mark = scratch + nn, *anchor = scratch + 2 * (size_t) nn;
    int *gid = scratch + 3 * (size_t) nn, *cursor = scratch + 4 * (size_t) nn;
    int ng = 0, j, i, g;
    for (i = 0; i < nn; i++) {
        set[i] = i;
        mark[i] = -1;
        anchor[i] = -1;
        gid[i] = -1;
    }
    /* the sets, and the body2 pins marked -2 */
    for (j = 0; j < m->nj; j++) {
        const rj__joint *J = &m->jnt[j];
        if (J->nI < 0)
            continue;
        set[rj__set_root(set, J->nJ)] = rj__set_root(set, J->nI);
        mark[J->nJ] = -2;
    }
    /* each set's anchor and group number */
    for (j = 0; j < m->nj; j++) {
        const int pin = m->jnt[j].nI;
        int r;
        if (pin < 0)
            continue;
        r = rj__set_root(set, pin);
        if (anchor[r] < 0 || (mark[anchor[r]] == -2 && mark[pin] != -2))
            anchor[r] = pin;
        if (gid[r] < 0)
            gid[r] = ng++;
    }
    /* counts, then the fill */
    for (g = 0; g <= ng; g++)
        m->grp_first[g] = 0;
    for (i = 0; i < nn; i++) {
        const int r = rj__set_root(set, i);
        if (gid[r] >= 0)
            m->grp_first[gid[r] + 1]++;
    }
    for (g = 0; g < ng; g++) {
        m->grp_first[g + 1] += m->grp_first[g];
        cursor[g] = m->grp_first[g];
    }
    for (i = 0; i < nn; i++)
        mark[i] = -1;
    for (j = 0; j < m->nj; j++) {
        const rj__joint *J = &m->jnt[j];
        int r;
        if (J->nI < 0)
            continue;
        r = rj__set_root(set, J->nI);
        rj__group_add(m, mark, cursor, gid[r], anchor[r]);
    }
    for (j = 0; j < m->nj; j++)
        if (m->jnt[j].nI >= 0)
            rj__group_add(m, mark, cursor, gid[rj__set_root(set, m->jnt[j].nI)], m->jnt[j].nJ);
    for (j = 0; j < m->nj; j++)
        if (m->jnt[j].nI >= 0)
            rj__group_add(m, mark, cursor, gid[rj__set_root(set, m->jnt[j].nI)], m->jnt[j].nI);
    return ng;
}

/* Inextensible chains: each starts at an inextensible link not hanging from the tip of
   another inextensible link, and follows while the tip carries exactly one inextensible
   child. Linear in the scene, with scratch of 2 nl + 2 nn ints: each link's use and
   joint, each node's count of inextensible children and its last one. */
static void rj__inext_chains(rj_model *m, int *scratch)
{
    int *used = scratch, *joint_of = scratch + m->nl;
    int *children = scratch + 2 * (size_t) m->nl, *child_of = children + m->nn;
    int cnt = 0, l, j, k;
    for (l = 0; l < m->nl; l++) {
        used[l] = 0;
        joint_of[l] = -1;
    }
    for (k = 0; k < m->nn; k++) {
        children[k] = 0;
        child_of[k] = -1;
    }
    for (j = 0; j < m->nj; j++) {
        /* a joint closing a loop neither hangs a link nor continues a chain */
        if (m->jnt[j].loop)
            continue;
        joint_of[m->jdef[j].body2] = j;
        if (m->jnt[j].nI < 0 || m->ldef[m->jdef[j].body2].fidelity != RJ_LINK_INEXTENSIBLE)
            continue;
        children[m->jnt[j].nI]++;
        child_of[m->jnt[j].nI] = m->jdef[j].body2;
    }
    m->nch = 0;
    m->ch_first[0] = 0;
    for (l = 0; l < m->nl; l++) {
        const int pj = joint_of[l];
        int cur = l;
        if (m->ldef[l].fidelity != RJ_LINK_INEXTENSIBLE || used[l])
            continue;
        if (pj >= 0) {
            const int b1 = m->jdef[pj].body1;
            /* the only inextensible child at an inextensible parent's tip continues its chain */
            if (b1 >= 0 && m->ldef[b1].fidelity == RJ_LINK_INEXTENSIBLE &&
                m->jnt[pj].nI == m->link_first[b1 + 1] - 1 && children[m->jnt[pj].nI] == 1)
                continue;
        }
        for (;;) {
            const int n0 = m->link_first[cur], ne = m->ldef[cur].elements,
                      first = cnt == m->ch_first[m->nch];
            const int tip = n0 + ne;
            used[cur] = 1;
            for (k = first ? 0 : 1; k <= ne; k++) {
                m->ch_node[cnt] = n0 + k;
                m->ch_l0sq[cnt] = m->link_l0[cur] * m->link_l0[cur];
                cnt++;
            }
            if (children[tip] != 1 || used[child_of[tip]])
                break;
            cur = child_of[tip];
        }
        m->ch_first[++m->nch] = cnt;
    }
}

/* Places one link (its joint j, or its own root placement when j < 0) from its parent's
   nodes, which are placed already. */
static void rj__place_link(rj_model *m, int l, int j)
{
    const rj_link_def *ld = &m->ldef[l];
    const rj_joint_def *d;
    const rj__joint *J;
    double px, py, refang, om1 = 0, vpx = 0, vpy = 0;
    if (j < 0) {
        rj__place(m, l, 0, ld->x, ld->y, ld->angle, ld->vx, ld->vy, ld->omega, m->x0, m->y0, m->phi0,
                  m->vx0, m->vy0, m->w0);
        return;
    }
    d = &m->jdef[j];
    J = &m->jnt[j];
    if (d->body1 < 0) {
        px = d->ground_x;
        py = d->ground_y;
        refang = d->ground_angle;
    } else {
        px = m->x0[J->nI];
        py = m->y0[J->nI];
        refang = atan2(m->y0[J->nK] - py, m->x0[J->nK] - px);
        om1 = m->w0[J->nI];
        vpx = m->vx0[J->nI];
        vpy = m->vy0[J->nI];
        if (m->ldef[d->body1].root == RJ_ROOT_FIXED) {
            om1 = 0;
            vpx = 0;
            vpy = 0;
        }
    }
    rj__place(m, l, J->nJ - m->link_first[l], px, py, refang + d->angle0, vpx, vpy, om1 + d->rate0,
              m->x0, m->y0, m->phi0,
              m->vx0, m->vy0, m->w0);
}

/* Initial placement of every link after the link it hangs from (its first joint as body2:
   the joints that close loops place nothing), in time linear in the scene: scratch of
   3 nl ints (placed flags, each link's joint, a path of links still to place). */
static void rj__place_all(rj_model *m, int *scratch)
{
    int *placed = scratch, *joint_of = scratch + m->nl, *path = scratch + 2 * (size_t) m->nl;
    int l, j;
    for (l = 0; l < m->nl; l++) {
        placed[l] = 0;
        joint_of[l] = -1;
    }
    for (j = 0; j < m->nj; j++)
        if (!m->jnt[j].loop)
            joint_of[m->jdef[j].body2] = j;
    for (l = 0; l < m->nl; l++) {
        int depth = 0, cur = l;
        /* up to the first placed link or a root, then down again */
        while (cur >= 0 && !placed[cur]) {
            path[depth++] = cur;
            cur = joint_of[cur] >= 0 ? m->jdef[joint_of[cur]].body1 : -1;
        }
        while (depth > 0) {
            cur = path[--depth];
            rj__place_link(m, cur, joint_of[cur]);
            placed[cur] = 1;
        }
    }
}

/* Every element's placed chord has its rest length to 1e-8: far from the origin the
   coordinates no longer resolve an element (a root at x = 1e12 m rounds 0.1 m elements by
   1e-3), and the rounding would start as strain energy that the step then releases. */
static int rj__placement_resolved(const rj_model *m, rj_error *err)
{
    int l, k;
    for (l = 0; l < m->nl; l++) {
        const double l0 = m->link_l0[l];
        for (k = m->link_first[l]; k < m->link_first[l + 1] - 1; k++) {
            const double chord = hypot(m->x0[k + 1] - m->x0[k], m->y0[k + 1] - m->y0[k]);
            char f[64];
            if (fabs(chord - l0) <= 1e-8 * l0)
                continue;
            RJ__FIELD(f, "links[%d]", l);
            rj__fail(err, RJ_ERR_INVALID, f, m->x0[k],
                     "links[%d] is placed where doubles do not resolve its %g m elements (node %d "
                     "at x = %g m, y = %g m, spacing %g m): place the mechanism nearer the origin",
                     l, l0, k - m->link_first[l], m->x0[k], m->y0[k], fabs(m->x0[k]) * DBL_EPSILON);
            return 0;
        }
    }
    return 1;
}

/* Where joint J pins body 1 at the start, its velocity there, and the direction theta
   is measured from (ground: the fixed point and direction). */
static void rj__pin1_start(const rj_model *m, const rj_joint_def *d, const rj__joint *J,
                           double p[2], double v[2], double *ref)
{
    if (d->body1 < 0) {
        p[0] = d->ground_x;
        p[1] = d->ground_y;
        v[0] = v[1] = 0;
        *ref = d->ground_angle;
        return;
    }
    p[0] = m->x0[J->nI];
    p[1] = m->y0[J->nI];
    v[0] = m->vx0[J->nI];
    v[1] = m->vy0[J->nI];
    *ref = atan2(m->y0[J->nK] - p[1], m->x0[J->nK] - p[0]);
}

/* A joint that closes a loop must find its pins together where the other joints place
   the links (within 1e-9 of the longest link), moving together, at its angle0 (within
   1e-9 rad): otherwise the gap, the velocity or the angle it finds is named. */
static int rj__loops_closed(const rj_model *m, rj_error *err)
{
    double longest = 0;
    int j, l;
    char f[64];
    for (l = 0; l < m->nl; l++)
        longest = fmax(longest, m->ldef[l].length);
    for (j = 0; j < m->nj; j++) {
        const rj_joint_def *d = &m->jdef[j];
        const rj__joint *J = &m->jnt[j];
        double p[2], v[2], ref, gap, slip, turn;
        if (!J->loop)
            continue;
        rj__pin1_start(m, d, J, p, v, &ref);
        gap = hypot(m->x0[J->nJ] - p[0], m->y0[J->nJ] - p[1]);
        slip = hypot(m->vx0[J->nJ] - v[0], m->vy0[J->nJ] - v[1]);
        turn = remainder(m->phi0[J->nJ] - ref - d->angle0, RJ__TWO_PI);
        if (gap > 1e-9 * longest) {
            RJ__FIELD(f, "joints[%d]", j);
            rj__fail(err, RJ_ERR_INVALID, f, gap,
                     "joints[%d] closes a loop, but the other joints place its pins %.6g m apart "
                     "(body1 at %.9g, %.9g m; body2 at %.9g, %.9g m): the loop does not close at "
                     "these angle0",
                     j, gap, p[0], p[1], m->x0[J->nJ], m->y0[J->nJ]);
            return 0;
        }
        if (slip > 1e-9 * (1 + hypot(v[0], v[1]))) {
            RJ__FIELD(f, "joints[%d]", j);
            rj__fail(err, RJ_ERR_INVALID, f, slip,
                     "joints[%d] closes a loop, but its pins start %.6g m/s apart: the rate0 of "
                     "the loop's joints do not close it",
                     j, slip);
            return 0;
        }
        if (fabs(turn) > 1e-9) {
            RJ__FIELD(f, "joints[%d].angle0", j);
            rj__fail(err, RJ_ERR_INVALID, f, d->angle0,
                     "%s = %.12g rad (%.9g deg) is not the angle its loop places it at, %.12g rad "
                     "(%.9g deg)",
                     f, d->angle0, rj_deg(d->angle0), d->angle0 + turn, rj_deg(d->angle0 + turn));
            return 0;
        }
    }
    return 1;
}

/* The links alone have a usable bound, so a joint's stiffness or damping takes it below
   RJ__MIN_BOUND: named, with what it gives on its own. */
static int rj__joint_unusable(const rj_model *m, rj_error *err)
{
    int j, worst = 0;
    double fastest = -1;
    char f[64];
    for (j = 0; j < m->nj; j++) {
        const double c = rj__joint_compliance0(m, j);
        const double rate = sqrt(m->jnt[j].k_lin * c) + m->jnt[j].c_lin * c;
        if (rate > fastest) {
            fastest = rate;
            worst = j;
        }
    }
    RJ__FIELD(f, "joints[%d]", worst);
    rj__fail(err, RJ_ERR_INVALID, f, m->dt_bound,
             "no usable step: the stability bound is %g s (at least 1e-15 s is needed); the links "
             "alone would allow %g s, and joints[%d] (spring %g N m/rad, penalty K %g N m/rad, "
             "damping %g N m s/rad) "
             "gives about %g rad/s on its own: its stiffness or damping is outside the range of "
             "mechanisms",
             m->dt_bound, rj__dt_bound_of(m->omega_links, 0), worst, m->jdef[worst].spring_k,
             m->jdef[worst].penalty_k, m->jdef[worst].damping, fastest);
    return 0;
}

/* The step and its bound must be finite positive numbers, and the initial state finite
   (its kinetic energy and the joints' spring energy too). */
static int rj__usable_step(const rj_model *m, rj_error *err)
{
    double ke = 0;
    int i, link, node;
    if ((!(m->dt_bound >= RJ__MIN_BOUND) || !rj__finite(m->dt_bound)) &&
        rj__dt_bound_of(m->omega_links, 0) >= RJ__MIN_BOUND)
        return rj__joint_unusable(m, err);
    if (!(m->dt_bound >= RJ__MIN_BOUND) || !rj__finite(m->dt_bound) || !(m->dt > 0) ||
        !rj__finite(m->dt)) {
        /* name the link with the shortest wave transit l0 / c (Eq 28) */
        int l, fastest = 0;
        double best = HUGE_VAL;
        char f[64];
        for (l = 0; l < m->nl; l++) {
            const double transit = m->link_l0[l] / sqrt(m->ldef[l].E / m->ldef[l].rho);
            if (transit < best) {
                best = transit;
                fastest = l;
            }
        }
        RJ__FIELD(f, "links[%d]", fastest);
        rj__fail(err, RJ_ERR_INVALID, f, m->dt,
                 "no usable step: the stability bound is %g s (omega_max %g rad/s; at least 1e-15 "
                 "s is needed) and the step %g s; links[%d] (length %g m, %d elements, E %g Pa, "
                 "rho %g kg/m^3; element wave transit %g s, Eq 28) "
                 "or a joint's stiffness or damping is outside the range of mechanisms (SI units: "
                 "m, Pa, kg/m^3)",
                 m->dt_bound, m->omega_max, m->dt, fastest, m->ldef[fastest].length,
                 m->ldef[fastest].elements, m->ldef[fastest].E, m->ldef[fastest].rho, best);
        return 0;
    }
    for (i = 0; i < m->nn; i++) {
        const double v = m->x0[i] + m->y0[i] + m->phi0[i];
        ke += m->mass[i] * (m->vx0[i] * m->vx0[i] + m->vy0[i] * m->vy0[i]) +
              m->rinertia[i] * m->w0[i] * m->w0[i];
        if (rj__finite(v) && rj__finite(ke))
            continue;
        rj__node_of(m, i, &link, &node);
        {
            char f[64];
            RJ__FIELD(f, "links[%d]", link);
            rj__fail(err, RJ_ERR_INVALID, f, rj__finite(v) ? ke : v,
                     "links[%d] node %d starts with a non-finite %s: the placement or the initial "
                     "velocities are outside what doubles resolve",
                     link, node, rj__finite(v) ? "kinetic energy" : "position");
        }
        return 0;
    }
    if (!rj__placement_resolved(m, err) || !rj__loops_closed(m, err))
        return 0;
    for (i = 0; i < m->nj; i++) {
        const rj_joint_def *d = &m->jdef[i];
        const double twist = d->angle0 - d->spring_free_angle;
        if (rj__finite(0.5 * d->spring_k * twist * twist))
            continue;
        {
            char f[64];
            RJ__FIELD(f, "joints[%d].spring_k", i);
            rj__fail(err, RJ_ERR_INVALID, f, d->spring_k,
                     "joints[%d] starts with a non-finite spring energy (spring_k %g N m/rad, %g "
                     "rad from its free angle)",
                     i, d->spring_k, twist);
        }
        return 0;
    }
    return 1;
}

/* ------------------------------------------------------------------ the stability bound */
/* omega_max^2, the largest eigenvalue of M^-1 K for the linearised model (K: the tangent of
   the elements' forces, the joints' springs and the cable loops' at the start; M: the
   lumped masses), sets the step. Lanczos on the whole linearised operator (rj__lz_apply)
   estimates it from below; it stops once its largest Ritz value has settled, which takes
   8 to 40 of its RJ__LANCZOS_ITERS steps where the spectrum's top is not crowded.

   Settling alone could be a plateau, so a second estimate checks it from above, element by
   element (Irons and Treharne 1971; Flanagan and Belytschko 1981): split K into pieces K_p
   (each element, each joint spring, each cable loop) and each DOF's mass among the pieces
   that touch it (M = sum M_p); then u.K u = sum u.K_p u <= sum lambda_p u.M_p u <=
   max_p lambda_p u.M u, so omega_max^2 is at most the largest lambda_p, the piece's own
   eigenvalue with its share of the masses. A DOF's mass is shared in proportion to each
   piece's stiffness on it. The bound is exact for a link whose axial mode is its fastest,
   and up to 18 % high where bending and rotary inertia set the top (a uniform link of 200
   elements; 3.7 % at 2000), so Lanczos may stop only within RJ__BOUND_GAP below it; where
   it never gets there it runs its whole course. */
#define RJ__BOUND_GAP 0.25
#define RJ__LZ_TOL    1e-4

/* A translation DOF of node i lives at its group's first member (the root). */
static int rj__ub_root(const rj_model *m, int i)
{
    return m->node_grp[i] >= 0 ? m->grp_node[m->grp_first[m->node_grp[i]]] : i;
}

/* An element's linearisation at the start, all that its tangent's product needs: its
   chord e, 1 / |e|^2, its axial force, its end moments' sum over |e|^2 and its section's
   constants (kc: EI / l0, EA / l0, l0^2, 1 / (2 l0^2)). */
typedef struct rj__elem_lin {
    double ex, ey, inv_r, n_ax, s_r, kb, kax, l0sq;
} rj__elem_lin;

/* The element at chord (ex, ey) with ends turned tha, thb off it (r = |e|^2). */
static RJ__INLINE void rj__elem_lin_at(const double *kc, double ex, double ey, double tha,
                                       double thb, rj__elem_lin *e)
{
    const double kb = kc[0], kax = kc[1], l0sq = kc[2], half_inv_l0sq = kc[3];
    const double r = ex * ex + ey * ey, inv_r = 1.0 / r;
    e->ex = ex;
    e->ey = ey;
    e->inv_r = inv_r;
    e->n_ax = kax * (r - l0sq) * half_inv_l0sq;
    e->s_r = 6.0 * kb * (tha + thb) * inv_r;
    e->kb = kb;
    e->kax = kax;
    e->l0sq = l0sq;
}

/* An element's tangent stiffness times dq (its nodes' x, y, rotation: a, then b), in closed
   form: the derivative of rj__elem_forces at the element's start, whatever its stress
   there. The strain's change is e.de / l0^2, the chord angle's perp(e).de / r (perp(e) =
   (-ey, ex)), each end's turn dphi - dbeta; node b's force -N e + (S / r) perp(e) (S = ma
   + mb) changes by -dN e - N de + (dS / r - 2 S e.de / r^2) perp(e) + (S / r) perp(de). */
static RJ__INLINE void rj__elem_lin_apply(const rj__elem_lin *e, const double dq[6],
                                          double out[6])
{
    const double ex = e->ex, ey = e->ey, inv_r = e->inv_r, kb = e->kb;
    const double n_ax = e->n_ax, s_r = e->s_r;
    const double dex = dq[3] - dq[0], dey = dq[4] - dq[1];
    const double e_de = ex * dex + ey * dey;
    const double dbeta = (-ey * dex + ex * dey) * inv_r;
    const double dtha = dq[2] - dbeta, dthb = dq[5] - dbeta;
    const double dma = kb * (4.0 * dtha + 2.0 * dthb);
    const double dmb = kb * (2.0 * dtha + 4.0 * dthb);
    const double dn = e->kax * e_de / e->l0sq;
    const double dsr = ((dma + dmb) - 2.0 * s_r * e_de) * inv_r;
    const double dfx = -dn * ex - n_ax * dex - dsr * ey - s_r * dey;
    const double dfy = -dn * ey - n_ax * dey + dsr * ex + s_r * dex;
    /* K = -dF/dq with F = (-f_b, -ma, f_b, -mb) */
    out[0] = dfx;
    out[1] = dfy;
    out[2] = dma;
    out[3] = -dfx;
    out[4] = -dfy;
    out[5] = dmb;
}

/* The tangent's product for an element at chord (ex, ey), ends turned tha, thb. */
static RJ__INLINE void rj__elem_tangent(const double *kc, double ex, double ey, double tha,
                                        double thb, const double dq[6], double out[6])
{
    rj__elem_lin e;
    rj__elem_lin_at(kc, ex, ey, tha, thb, &e);
    rj__elem_lin_apply(&e, dq, out);
}

/* Element k of link l at the start: its chord and its ends' turns off it. */
static void rj__elem_start(const rj_model *m, int l, int k, double *ex, double *ey,
                           double *tha, double *thb)
{
    const int a = m->link_first[l] + (k - m->link_efirst[l]);
    *ex = m->x0[a + 1] - m->x0[a];
    *ey = m->y0[a + 1] - m->y0[a];
    *tha = m->phi0[a] - m->beta0[k];
    *thb = m->phi0[a + 1] - m->beta0[k];
}

/* A symmetric tridiagonal matrix (al, be: be[i] couples i and i + 1), k <=
   RJ__LANCZOS_ITERS, scaled to entries of order 1: the Sturm recurrence squares the
   off-diagonal, which for a model of omega^2 ~ 1e-166 (a link of 1e150 kg/m^3) underflowed
   and cut omega_max by 6. Into al_s and be2 (be2[i] = be[i - 1]^2, be2[0] = 0) with
   Gershgorin's interval [lo, hi], which holds every eigenvalue; returns the scale (0: a
   zero matrix). */
static double rj__tridiag_scaled(const double *al_in, const double *be_in, int k, double *al,
                                 double *be2, double *lo, double *hi)
{
    double scale = 0;
    int i;
    *lo = 0;
    *hi = 0;
    for (i = 0; i < k; i++) {
        if (fabs(al_in[i]) > scale)
            scale = fabs(al_in[i]);
        if (fabs(be_in[i]) > scale)
            scale = fabs(be_in[i]);
    }
    if (scale == 0)
        return 0;
    for (i = 0; i < k; i++) {
        const double be_prev = i > 0 ? be_in[i - 1] / scale : 0;
        const double be_next = i + 1 < k ? be_in[i] / scale : 0;
        const double r = fabs(be_prev) + fabs(be_next);
        al[i] = al_in[i] / scale;
        be2[i] = be_prev * be_prev;
        if (al[i] + r > *hi)
            *hi = al[i] + r;
        if (al[i] - r < *lo)
            *lo = al[i] - r;
    }
    return scale;
}

/* How many eigenvalues of the scaled tridiagonal lie below x: the negative pivots of
   T - x. */
static int rj__sturm_below(const double *al, const double *be2, int k, double x)
{
    double q = al[0] - x;
    int i, cnt;
    if (q == 0.0)
        q = 1e-300;
    cnt = q < 0;
    for (i = 1; i < k; i++) {
        q = al[i] - x - be2[i] / q;
        if (q == 0.0)
            q = 1e-300;
        cnt += q < 0;
    }
    return cnt;
}

/* The top eigenvalue by bisection of [lo, hi] until the bracket is within rtol of it;
   returns hi. near: the top to within 1e-11 from above (rj__tridiag_top), or 0 for none.
   A midpoint farther than 1e-10 of near from it takes its side without a Sturm count,
   which could not say otherwise there (the count is exact for a matrix within round-off
   of T), so the result is the bits of the bisection that counts every time. */
static double rj__tridiag_bisect(const double *al, const double *be2, int k, double lo,
                                 double hi, double rtol, double near)
{
    const double above = near > 0 ? near * (1.0 + 1e-10) : HUGE_VAL;
    const double below = near > 0 ? near * (1.0 - 1e-10) : -HUGE_VAL;
    int it;
    for (it = 0; it < 200; it++) {
        const double mid = 0.5 * (lo + hi);
        int all_below;
        if (mid > above)
            all_below = 1;
        else if (mid < below)
            all_below = 0;
        else
            all_below = rj__sturm_below(al, be2, k, mid) == k;
        if (all_below)
            hi = mid;
        else
            lo = mid;
        if (hi - lo <= rtol * fabs(hi))
            break;
    }
    return hi;
}

/* Largest eigenvalue of a symmetric tridiagonal matrix to rtol of itself (Sturm bisection
   from Gershgorin's interval). */
static double rj__tridiag_max_to(const double *al_in, const double *be_in, int k, double rtol)
{
    double al[RJ__LANCZOS_ITERS], be2[RJ__LANCZOS_ITERS], lo, hi;
    const double scale = rj__tridiag_scaled(al_in, be_in, k, al, be2, &lo, &hi);
    if (scale == 0)
        return 0;
    return rj__tridiag_bisect(al, be2, k, lo, hi, rtol, 0.0) * scale;
}

/* The same to 1e-14 (the estimate the bound returns), near: its top to 1e-11 from above
   (rj__tridiag_top), which spares most of the counts; the same bits. */
static double rj__tridiag_max_near(const double *al_in, const double *be_in, int k, double near)
{
    double al[RJ__LANCZOS_ITERS], be2[RJ__LANCZOS_ITERS], lo, hi;
    const double scale = rj__tridiag_scaled(al_in, be_in, k, al, be2, &lo, &hi);
    if (scale == 0)
        return 0;
    return rj__tridiag_bisect(al, be2, k, lo, hi, 1e-14, near / scale) * scale;
}

/* Newton's step toward the top eigenvalue from x above it: the pivots q_i of x - T (all
   positive there) and their derivatives give p'/p = sum q_i' / q_i of p(x) = det(x - T),
   which is sum 1 / (x - lambda_j) >= 1 / (x - lambda_max): x - p / p' stays above the
   top. Returns p'/p, or 0 when a pivot is not positive (x is not above the top). */
static double rj__tridiag_newton_sum(const double *al, const double *be2, int k, double x)
{
    double q = x - al[0], dq = 1.0, inv_q, sum;
    int i;
    if (!(q > 0))
        return 0;
    inv_q = 1.0 / q;
    sum = dq * inv_q;
    for (i = 1; i < k; i++) {
        const double t = be2[i] * inv_q;
        dq = 1.0 + t * dq * inv_q;
        q = x - al[i] - t;
        if (!(q > 0))
            return 0;
        inv_q = 1.0 / q;
        sum += dq * inv_q;
    }
    return sum;
}

/* The largest eigenvalue of a tridiagonal matrix to rtol, from above, for the convergence
   checks: bisection until one eigenvalue lies above lo, then Newton's method from hi (each
   step stays above the top), stopped once its step is within rtol and a Sturm count puts
   the top above x (1 - rtol); bisection again where Newton stalls. */
static double rj__tridiag_top(const double *al_in, const double *be_in, int k, double rtol)
{
    double al[RJ__LANCZOS_ITERS], be2[RJ__LANCZOS_ITERS], lo, hi, x;
    const double scale = rj__tridiag_scaled(al_in, be_in, k, al, be2, &lo, &hi);
    int it, above = k;
    if (scale == 0)
        return 0;
    for (it = 0; it < 200 && above > 1 && hi - lo > rtol * fabs(hi); it++) {
        const double mid = 0.5 * (lo + hi);
        const int below = rj__sturm_below(al, be2, k, mid);
        if (below == k)
            hi = mid;
        else {
            lo = mid;
            above = k - below;
        }
    }
    if (above > 1)
        return hi * scale;
    x = hi;
    for (it = 0; it < 40; it++) {
        const double sum = rj__tridiag_newton_sum(al, be2, k, x);
        /* a pivot not positive: the last step rounded past the top, which it bracketed */
        if (!(sum > 0)) {
            lo = x > lo && x < hi ? x : lo;
            break;
        }
        if (!(x - 1.0 / sum > lo))
            break;
        hi = x;
        x -= 1.0 / sum;
        if (1.0 / sum <= 0.5 * rtol * fabs(x) &&
            rj__sturm_below(al, be2, k, x - rtol * fabs(x)) < k)
            return x * scale;
    }
    /* Newton stalled: bisection of what it bracketed */
    return rj__tridiag_bisect(al, be2, k, lo, hi, rtol, 0.0) * scale;
}

/* The largest eigenvalue to 1e-14 of itself: the estimate the bound returns. */
static double rj__tridiag_max(const double *al, const double *be, int k)
{
    return rj__tridiag_max_to(al, be, k, 1e-14);
}
/* The largest eigenvalue of a symmetric 6 x 6 matrix (A is destroyed; NaN when an entry
   is not finite): Householder's reflections make it tridiagonal (the trailing block takes
   A - v w^T - w v^T with p = A v, w = 2 (p - (v.p) v), |v| = 1), then its top by
   rj__tridiag_top to 1e-13. Cyclic Jacobi took 4 to 6 sweeps, 6700 instructions. */
static double rj__ub_eig6(double A[36])
{
    double al[6], be[6];
    int k, i, j;
    for (i = 0; i < 36; i++)
        if (!rj__finite(A[i]))
            return A[i] - A[i];
    for (k = 0; k < 4; k++) {
        double v[6], p[6], nrm = 0, alpha, vp = 0;
        for (i = k + 1; i < 6; i++) {
            v[i] = A[6 * i + k];
            nrm += v[i] * v[i];
        }
        nrm = sqrt(nrm);
        alpha = v[k + 1] > 0 ? -nrm : nrm;
        v[k + 1] -= alpha;
        nrm = 0;
        for (i = k + 1; i < 6; i++)
            nrm += v[i] * v[i];
        if (nrm == 0)
            continue;
        nrm = 1.0 / sqrt(nrm);
        for (i = k + 1; i < 6; i++)
            v[i] *= nrm;
        /* column k below the diagonal becomes (alpha, 0, ...) */
        A[6 * (k + 1) + k] = A[6 * k + k + 1] = alpha;
        for (i = k + 2; i < 6; i++)
            A[6 * i + k] = A[6 * k + i] = 0;
        for (i = k + 1; i < 6; i++) {
            p[i] = 0;
            for (j = k + 1; j < 6; j++)
                p[i] += A[6 * i + j] * v[j];
            vp += v[i] * p[i];
        }
        for (i = k + 1; i < 6; i++)
            p[i] = 2.0 * (p[i] - vp * v[i]);
        for (i = k + 1; i < 6; i++)
            for (j = k + 1; j < 6; j++)
                A[6 * i + j] -= v[i] * p[j] + p[i] * v[j];
    }
    for (i = 0; i < 6; i++) {
        al[i] = A[7 * i];
        be[i] = i < 5 ? A[6 * (i + 1) + i] : 0.0;
    }
    return rj__tridiag_top(al, be, 6, 1e-13);
}

/* The element stiffness, computed again only when the element's start or constants differ
   from the last one's (a uniform straight link's inner elements are all alike). It is
   taken in the element's own frame (its chord along x), where alike elements match
   whatever way they point; translation masses are the same in x and y, so the shares and
   the eigenvalue do not depend on the frame. */
typedef struct rj__ub_cache {
    double key[7]; /* kb, kax, l0^2, 1/(2 l0^2), chord length, tha, thb */
    double K[36];
    double s[6], lam; /* the eigenvalue at the mass shares s (lam < 0: none) */
} rj__ub_cache;

/* Whether two keys match to 1e-9, relative, and their last nabs entries (turns, near 0)
   absolute: the elements of a straight link differ in their last bits, where the nodes'
   places were summed, and the bound is a check that needs nothing like that precision. */
static int rj__ub_alike(const double *a, const double *b, int n, int nabs)
{
    int i;
    for (i = 0; i < n; i++) {
        const double big = fabs(a[i]) > fabs(b[i]) ? fabs(a[i]) : fabs(b[i]);
        const double tol = i >= n - nabs ? 1e-9 : 1e-9 * big;
        if (!(fabs(a[i] - b[i]) <= tol))
            return 0;
    }
    return 1;
}

static const double *rj__ub_elem(const rj_model *m, int l, int k, rj__ub_cache *cache)
{
    const double *kc = m->link_kc + 4 * (size_t) l;
    double key[7], ex, ey;
    int i, j;
    rj__elem_start(m, l, k, &ex, &ey, &key[5], &key[6]);
    for (i = 0; i < 4; i++)
        key[i] = kc[i];
    key[4] = sqrt(ex * ex + ey * ey);
    if (rj__ub_alike(key, cache->key, 7, 2))
        return cache->K;
    memcpy(cache->key, key, sizeof key);
    cache->lam = -1.0;
    for (j = 0; j < 6; j++) {
        double dq[6] = { 0, 0, 0, 0, 0, 0 }, col[6];
        dq[j] = 1.0;
        rj__elem_tangent(kc, key[4], 0.0, key[5], key[6], dq, col);
        for (i = 0; i < 6; i++)
            cache->K[6 * i + j] = col[i];
    }
    return cache->K;
}

/* A rank-one piece k v v^T (a joint's spring, a cable loop): v's entries by DOF, a node's
   translation under the key 3 r (r its root, x and y in vx, vy), its rotation under 3 i + 2
   (in vx). At most two joints of four nodes each. */
typedef struct rj__ub_piece {
    int n;
    int key[16];
    double vx[16], vy[16];
} rj__ub_piece;

static void rj__ub_add(rj__ub_piece *p, int key, double vx, double vy)
{
    int i;
    for (i = 0; i < p->n; i++)
        if (p->key[i] == key)
            break;
    if (i == p->n) {
        p->key[p->n] = key;
        p->vx[p->n] = 0;
        p->vy[p->n] = 0;
        p->n++;
    }
    p->vx[i] += vx;
    p->vy[i] += vy;
}

/* scale times the DOFs a unit torque on joint J loads at the start (rj__apply_torque's
   entries, the virtual work of a turn of the joint). */
static void rj__ub_torque(const rj_model *m, const rj__joint *J, double scale, rj__ub_piece *p)
{
    rj__jgeo g;
    double sx, sy;
    if (!J->chord) {
        rj__ub_add(p, 3 * J->nJ + 2, scale, 0);
        if (J->nI >= 0)
            rj__ub_add(p, 3 * J->nI + 2, -scale, 0);
        return;
    }
    rj__joint_geo(m, J, m->x0, m->y0, &g);
    sx = -scale * g.by / g.b2;
    sy = scale * g.bx / g.b2;
    rj__ub_add(p, 3 * rj__ub_root(m, J->nL), sx, sy);
    rj__ub_add(p, 3 * rj__ub_root(m, J->nJ), -sx, -sy);
    if (J->nK >= 0) {
        sx = scale * g.ay / g.a2;
        sy = -scale * g.ax / g.a2;
        rj__ub_add(p, 3 * rj__ub_root(m, J->nK), sx, sy);
        rj__ub_add(p, 3 * rj__ub_root(m, J->nI), -sx, -sy);
    }
}

/* The inverse mass of a DOF key (a translation's root, or a rotation). */
static RJ__FORCE_INLINE double rj__ub_inv(const rj_model *m, int key)
{
    return key % 3 == 2 ? m->rinv[key / 3] : rj__lz_inv(m, key / 3, 0);
}

/* Rank-one piece i: joint i's spring (i < nj, k_lin > 0) or cable loop i - nj; its
   stiffness k (0: no piece). */
static double rj__ub_rank_one(const rj_model *m, int i, rj__ub_piece *p)
{
    p->n = 0;
    if (i < m->nj) {
        if (!(m->jnt[i].k_lin > 0))
            return 0;
        rj__ub_torque(m, &m->jnt[i], 1.0, p);
        return m->jnt[i].k_lin;
    } else {
        const rj_coupling_def *c = &m->cp[i - m->nj];
        if (!(c->stiffness > 0))
            return 0;
        /* the loop's error e = turn_b - ratio turn_a */
        rj__ub_torque(m, &m->jnt[c->joint_b], 1.0, p);
        rj__ub_torque(m, &m->jnt[c->joint_a], -c->ratio, p);
        return c->stiffness;
    }
}

/* A rank-one piece's stiffness on each DOF key, k |v|^2, into W. */
static void rj__ub_rank_one_weights(const rj__ub_piece *p, double k, double *W)
{
    int i;
    for (i = 0; i < p->n; i++)
        W[p->key[i]] += k * (p->vx[i] * p->vx[i] + p->vy[i] * p->vy[i]);
}

/* A rank-one piece's eigenvalue with its share of the masses: with shares
   k |v_d|^2 / W_d of each DOF's mass, k v.M_p^-1 v = sum of W_d / m_d over its DOFs. */
static double rj__ub_rank_one_lambda(const rj_model *m, const rj__ub_piece *p, const double *W)
{
    double lam = 0;
    int i;
    for (i = 0; i < p->n; i++)
        if (p->vx[i] != 0 || p->vy[i] != 0)
            lam += W[p->key[i]] * rj__ub_inv(m, p->key[i]);
    return lam;
}

/* Element k of link l: its DOF keys (x and y of node a share the first, node b's the
   fourth) and its stiffness on each node's translation and rotation. */
static void rj__ub_elem_keys(const rj_model *m, int l, int k, int key[6])
{
    const int a = m->link_first[l] + (k - m->link_efirst[l]);
    key[0] = key[1] = 3 * rj__ub_root(m, a);
    key[2] = 3 * a + 2;
    key[3] = key[4] = 3 * rj__ub_root(m, a + 1);
    key[5] = 3 * (a + 1) + 2;
}

static void rj__ub_elem_weights(const double *K, const int key[6], double *W)
{
    W[key[0]] += fabs(K[0]) + fabs(K[7]);
    W[key[2]] += fabs(K[14]);
    W[key[3]] += fabs(K[21]) + fabs(K[28]);
    W[key[5]] += fabs(K[35]);
}

/* An element's eigenvalue with its share of the masses: DOF j takes the share w_j / W_j
   of its mass (w_j the element's own weight on it), so M_p^-1/2 K M_p^-1/2 has entries
   K_ij sqrt(s_i s_j), s_j = W_j / (w_j m_j). A DOF the element loads but gives no weight
   (a stressed start's off-diagonal alone): no bound (HUGE_VAL). */
static double rj__ub_elem_lambda(const rj_model *m, const double *K, const int key[6],
                                 const double *W, rj__ub_cache *cache)
{
    const double w[6] = { fabs(K[0]) + fabs(K[7]), fabs(K[0]) + fabs(K[7]), fabs(K[14]),
                          fabs(K[21]) + fabs(K[28]), fabs(K[21]) + fabs(K[28]), fabs(K[35]) };
    double s[6], A[36];
    int i, j;
    if (key[0] == key[3])
        return HUGE_VAL;
    for (i = 0; i < 6; i++) {
        const double inv = rj__ub_inv(m, key[i]);
        s[i] = w[i] > 0 ? W[key[i]] / w[i] * inv : 0.0;
        if (w[i] == 0 && inv > 0)
            for (j = 0; j < 6; j++)
                if (K[6 * i + j] != 0)
                    return HUGE_VAL;
    }
    /* the last element's eigenvalue again when its stiffness and shares are the same */
    if (cache->lam >= 0 && rj__ub_alike(s, cache->s, 6, 0))
        return cache->lam;
    for (i = 0; i < 6; i++)
        for (j = 0; j < 6; j++)
            A[6 * i + j] = 0.5 * (K[6 * i + j] + K[6 * j + i]) * sqrt(s[i] * s[j]);
    memcpy(cache->s, s, sizeof s);
    cache->lam = rj__ub_eig6(A);
    return cache->lam;
}

/* The upper bound on omega_max^2 (above); W: 3 nn doubles of scratch. */
static double rj__omega2_upper(const rj_model *m, double *W)
{
    rj__ub_cache cache;
    rj__ub_piece p;
    double top = 0;
    int l, k, i, key[6];
    for (i = 0; i < 3 * m->nn; i++)
        W[i] = 0;
    /* each piece's stiffness on each DOF: the weights that share its mass */
    for (i = 0; i < 7; i++)
        cache.key[i] = -1.0; /* no element has EI < 0: empty */
    cache.lam = -1.0;
    for (l = 0; l < m->nl; l++)
        for (k = m->link_efirst[l]; k < m->link_efirst[l + 1]; k++)
            if (m->link_path[l] != RJ__PATH_RIGID) {
                rj__ub_elem_keys(m, l, k, key);
                rj__ub_elem_weights(rj__ub_elem(m, l, k, &cache), key, W);
            }
    for (i = 0; i < m->nj + m->ncp; i++)
        rj__ub_rank_one_weights(&p, rj__ub_rank_one(m, i, &p), W);
    /* each piece's eigenvalue with its share */
    for (l = 0; l < m->nl; l++)
        for (k = m->link_efirst[l]; k < m->link_efirst[l + 1]; k++)
            if (m->link_path[l] != RJ__PATH_RIGID) {
                double lam;
                rj__ub_elem_keys(m, l, k, key);
                lam = rj__ub_elem_lambda(m, rj__ub_elem(m, l, k, &cache), key, W, &cache);
                if (lam > top || lam != lam)
                    top = lam;
            }
    for (i = 0; i < m->nj + m->ncp; i++)
        if (rj__ub_rank_one(m, i, &p) > 0) {
            const double lam = rj__ub_rank_one_lambda(m, &p, W);
            if (lam > top || lam != lam)
                top = lam;
        }
    return top;
}


/* M^-1/2 of every DOF (rj__lz_inv), for rj__lz_apply. */
static void rj__lz_scales(const rj_model *m, double *sc)
{
    int i;
    for (i = 0; i < m->nn; i++) {
        sc[3 * i] = sqrt(rj__lz_inv(m, i, 0));
        sc[3 * i + 1] = sc[3 * i];
        sc[3 * i + 2] = sqrt(m->rinv[i]);
    }
}

/* The elements' part of f = K d (d: the DOFs' moves; a node's translation at its root's). */
static void rj__lz_elements(const rj_model *m, const double *d, double *f)
{
    int l, k;
    for (l = 0; l < m->nl; l++) {
        const double *kc = m->link_kc + 4 * (size_t) l;
        const int shift = m->link_first[l] - m->link_efirst[l];
        if (m->link_path[l] == RJ__PATH_RIGID)
            continue;
        for (k = m->link_efirst[l]; k < m->link_efirst[l + 1]; k++) {
            const int a = k + shift;
            const int ta = 3 * rj__ub_root(m, a), tb = 3 * rj__ub_root(m, a + 1);
            const double dq[6] = { d[ta], d[ta + 1], d[3 * a + 2], d[tb], d[tb + 1], d[3 * a + 5] };
            double fe[6];
            rj__elem_tangent(kc, m->x0[a + 1] - m->x0[a], m->y0[a + 1] - m->y0[a],
                             m->phi0[a] - m->beta0[k], m->phi0[a + 1] - m->beta0[k], dq, fe);
            f[ta] += fe[0];
            f[ta + 1] += fe[1];
            f[3 * a + 2] += fe[2];
            f[tb] += fe[3];
            f[tb + 1] += fe[4];
            f[3 * a + 5] += fe[5];
        }
    }
}

/* The vector index of DOF key (3 i + k) of node i: interleaved, or with each kind of DOF
   apart when kinds is the node count (the Lanczos vectors, src/lanczos.h). */
static RJ__FORCE_INLINE size_t rj__lz_index(int key, int kinds)
{
    return kinds ? (size_t) (key % 3) * (size_t) kinds + (size_t) (key / 3) : (size_t) key;
}

/* The joints' springs and the cable loops' part of f = K d: k v (v . d) each; kinds as
   rj__lz_index's (a translation's y follows its x by 1, or by the node count). */
static void rj__lz_rank_one(const rj_model *m, const double *d, double *f, int kinds)
{
    const size_t to_y = kinds ? (size_t) kinds : 1;
    rj__ub_piece p;
    int i, q;
    for (i = 0; i < m->nj + m->ncp; i++) {
        const double k = rj__ub_rank_one(m, i, &p);
        double dot = 0;
        if (!(k > 0))
            continue;
        for (q = 0; q < p.n; q++) {
            const size_t at = rj__lz_index(p.key[q], kinds);
            dot += p.vx[q] * d[at] + (p.key[q] % 3 == 0 ? p.vy[q] * d[at + to_y] : 0.0);
        }
        for (q = 0; q < p.n; q++) {
            const size_t at = rj__lz_index(p.key[q], kinds);
            f[at] += k * dot * p.vx[q];
            if (p.key[q] % 3 == 0)
                f[at + to_y] += k * dot * p.vy[q];
        }
    }
}

/* The linearised operator out = M^-1/2 K M^-1/2 u over the 3 nn node DOFs (a grouped
   node's translation lives at its group's first member; the other members' entries are
   unused and come out 0): the elements' tangents in closed form, the joints' linearised
   springs k g g^T (g: the DOFs a unit torque loads) and the cable loops'. sc: M^-1/2 of
   each DOF (rj__lz_scales); d: 3 nn doubles of scratch. */
static void rj__lz_apply(const rj_model *m, const double *sc, const double *u, double *out,
                         double *d)
{
    const int n = 3 * m->nn;
    int i;
    for (i = 0; i < n; i++) {
        d[i] = u[i] * sc[i];
        out[i] = 0.0;
    }
    rj__lz_elements(m, d, out);
    rj__lz_rank_one(m, d, out, 0);
    for (i = 0; i < n; i++)
        out[i] *= sc[i];
}

/* Lanczos's start: on every DOF that moves, entries of a fixed pseudo-random sequence in
   [-1, 1) (splitmix64 of the index), which meet every mode alike (a smooth start barely
   meets the zigzag modes at the spectrum's top, and settled on a plateau 0.5 % below it on
   a link of 2000 elements); v0 = 0. Returns 0 when none moves. */
static int rj__lz_start(const rj_model *m, double *v0, double *v1)
{
    const int n = 3 * m->nn;
    double nrm = 0;
    int i;
    for (i = 0; i < n; i++) {
        unsigned long long z = (unsigned long long) (i + 1) * 0x9E3779B97F4A7C15ULL;
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
        z ^= z >> 31;
        v1[i] = (double) (z >> 11) * (2.0 / 9007199254740992.0) - 1.0;
        v0[i] = 0;
    }
    for (i = 0; i < m->nn; i++) {
        if (m->tinv[i] == 0) {
            v1[3 * i] = 0;
            v1[3 * i + 1] = 0;
        }
        if (m->rinv[i] == 0)
            v1[3 * i + 2] = 0;
    }
    for (i = 0; i < m->ng; i++) {
        int r = m->grp_node[m->grp_first[i]];
        if (m->grp_inv[i] > 0) {
            v1[3 * r] = 1.0;
            v1[3 * r + 1] = 0.7;
        }
    }
    for (i = 0; i < n; i++)
        nrm += v1[i] * v1[i];
    if (nrm == 0)
        return 0;
    nrm = sqrt(nrm);
    for (i = 0; i < n; i++)
        v1[i] /= nrm;
    return 1;
}
/* ------------------------------------------------------------ Lanczos in vector lanes */
/* The Lanczos iteration of the stability bound (rj__omega2_max). Its vectors hold each
   kind of DOF apart (x of every node, then y, then the rotations: rj__lz_index), so that
   the elements along a link read their nodes in whole lanes. Its product takes the
   elements' linearisations from a table built once (rj__lz_table). Where the header has
   vector lanes (src/impl.h), the element products and the vector passes run in them,
   dispatched as the beam pass is: every lane does the scalar code's operations in its
   order, each DOF's sum takes its elements' terms in element order, and the dot products
   and norms sum their terms node by node (x, y, rotation), the order of rj__lz_apply's
   interleaved vectors: every build gives the same bits (tests/lanes.sh). */

/* The interleaved vector in (3 i + k) into its DOF kinds. */
static void rj__lz_split(const double *in, double *out, int nn)
{
    int i, k;
    for (i = 0; i < nn; i++)
        for (k = 0; k < 3; k++)
            out[rj__lz_index(3 * i + k, nn)] = in[3 * i + k];
}

/* The elements' linearisations (rj__elem_lin, one array a field, for the lanes) and their
   nodes, taken once for all of Lanczos's products: the chord's length and the ends' turns
   need a division and a dozen products an element, which the product then does not
   repeat. An element is plain when its nodes' translations are their own (no pin group);
   plain[c] counts the plain elements from c on along its link, which the lanes take
   whole. */
typedef struct rj__lz_table {
    const double *ex, *ey, *inv_r, *n_ax, *s_r, *kb, *kax, *l0sq;
    const int *ta, *tb; /* the nodes holding a's and b's translations */
    const int *ra;      /* node a (its rotation; b's is ra + 1) */
    const int *plain;
    int count;          /* the elements of the links that bend */
} rj__lz_table;

/* One element's row of the table. */
static void rj__lz_table_row(const rj_model *m, int l, int k, int c, double *f, int *idx)
{
    const size_t ne = (size_t) m->ne;
    const int a = m->link_first[l] + (k - m->link_efirst[l]);
    rj__elem_lin e;
    rj__elem_lin_at(m->link_kc + 4 * (size_t) l, m->x0[a + 1] - m->x0[a],
                    m->y0[a + 1] - m->y0[a], m->phi0[a] - m->beta0[k],
                    m->phi0[a + 1] - m->beta0[k], &e);
    f[c] = e.ex;
    f[ne + c] = e.ey;
    f[2 * ne + c] = e.inv_r;
    f[3 * ne + c] = e.n_ax;
    f[4 * ne + c] = e.s_r;
    f[5 * ne + c] = e.kb;
    f[6 * ne + c] = e.kax;
    f[7 * ne + c] = e.l0sq;
    idx[c] = rj__ub_root(m, a);
    idx[ne + c] = rj__ub_root(m, a + 1);
    idx[2 * ne + c] = a;
}

/* The table in area (8 ne doubles, then 4 ne ints), in rj__lz_elements's order. */
static void rj__lz_table_build(const rj_model *m, double *area, rj__lz_table *t)
{
    const size_t ne = (size_t) m->ne;
    double *f = area;
    int *idx = (int *) (void *) (area + 8 * ne), *plain = idx + 3 * ne;
    int l, k, c = 0;
    for (l = 0; l < m->nl; l++)
        if (m->link_path[l] != RJ__PATH_RIGID)
            for (k = m->link_efirst[l]; k < m->link_efirst[l + 1]; k++, c++)
                rj__lz_table_row(m, l, k, c, f, idx);
    /* from the last element back: a plain element starts a run one longer than the
       next element's, when that one is the next along the same link */
    for (k = c - 1; k >= 0; k--) {
        const int a = idx[2 * ne + k];
        const int own = idx[k] == a && idx[ne + k] == a + 1;
        const int next = k + 1 < c && idx[2 * ne + k + 1] == a + 1 ? plain[k + 1] : 0;
        plain[k] = own ? 1 + next : 0;
    }
    t->ex = f;
    t->ey = f + ne;
    t->inv_r = f + 2 * ne;
    t->n_ax = f + 3 * ne;
    t->s_r = f + 4 * ne;
    t->kb = f + 5 * ne;
    t->kax = f + 6 * ne;
    t->l0sq = f + 7 * ne;
    t->ta = idx;
    t->tb = idx + ne;
    t->ra = idx + 2 * ne;
    t->plain = plain;
    t->count = c;
}

/* Element c's product K_e d summed into f (rj__lz_elements's sums in its order). */
static RJ__FORCE_INLINE void rj__lz_element(const rj__lz_table *t, int c, const double *d,
                                            double *f, int nn)
{
    const int ta = t->ta[c], tb = t->tb[c], ra = t->ra[c];
    const double *dx = d, *dy = d + nn, *dr = d + 2 * (size_t) nn;
    double *fx = f, *fy = f + nn, *fr = f + 2 * (size_t) nn;
    const double dq[6] = { dx[ta], dy[ta], dr[ra], dx[tb], dy[tb], dr[ra + 1] };
    rj__elem_lin e;
    double fe[6];
    e.ex = t->ex[c];
    e.ey = t->ey[c];
    e.inv_r = t->inv_r[c];
    e.n_ax = t->n_ax[c];
    e.s_r = t->s_r[c];
    e.kb = t->kb[c];
    e.kax = t->kax[c];
    e.l0sq = t->l0sq[c];
    rj__elem_lin_apply(&e, dq, fe);
    fx[ta] += fe[0];
    fy[ta] += fe[1];
    fr[ra] += fe[2];
    fx[tb] += fe[3];
    fy[tb] += fe[4];
    fr[ra + 1] += fe[5];
}

#ifdef RJ__LANES
/* One kind of DOF of the lane's nodes a .. a + RJ__VW: node a + j takes b's term of
   element j - 1, then a's of element j (the scalar code's order; -0.0 adds nothing at
   node a, whose b term came before), node a + RJ__VW b's term of the last. */
static RJ__FORCE_INLINE void rj__lz_node_sums(double *f, const rj__vd *fa, const rj__vd *fb)
{
    double shifted[RJ__VW + 1];
    rj__vd sum, prev;
    shifted[0] = -0.0;
    RJ__VST(shifted + 1, *fb);
    RJ__VLD(prev, shifted);
    RJ__VLD(sum, f);
    sum = (sum + prev) + *fa;
    RJ__VST(f, sum);
    f[RJ__VW] += shifted[RJ__VW];
}

/* The plain elements c .. c + RJ__VW - 1 (nodes a .. a + RJ__VW, a = ra[c]) in vector
   lanes: rj__elem_lin_apply's operations in its order (keep the two alike). */
static RJ__FORCE_INLINE void rj__lz_element_lanes(const rj__lz_table *t, int c,
                                                  const double *d, double *f, int nn)
{
    const size_t a = (size_t) t->ra[c], n2 = 2 * (size_t) nn;
    rj__vd q0, q1, q2, q3, q4, q5, ex, ey, inv_r, n_ax, s_r, kb, kax, l0sq;
    rj__vd dex, dey, e_de, dbeta, dtha, dthb, dma, dmb, dn, dsr, dfx, dfy, bx, by;
    RJ__VLD(q0, d + a);
    RJ__VLD(q1, d + nn + a);
    RJ__VLD(q2, d + n2 + a);
    RJ__VLD(q3, d + a + 1);
    RJ__VLD(q4, d + nn + a + 1);
    RJ__VLD(q5, d + n2 + a + 1);
    RJ__VLD(ex, t->ex + c);
    RJ__VLD(ey, t->ey + c);
    RJ__VLD(inv_r, t->inv_r + c);
    RJ__VLD(n_ax, t->n_ax + c);
    RJ__VLD(s_r, t->s_r + c);
    RJ__VLD(kb, t->kb + c);
    RJ__VLD(kax, t->kax + c);
    RJ__VLD(l0sq, t->l0sq + c);
    dex = q3 - q0;
    dey = q4 - q1;
    e_de = ex * dex + ey * dey;
    dbeta = (-ey * dex + ex * dey) * inv_r;
    dtha = q2 - dbeta;
    dthb = q5 - dbeta;
    dma = kb * (4.0 * dtha + 2.0 * dthb);
    dmb = kb * (2.0 * dtha + 4.0 * dthb);
    dn = kax * e_de / l0sq;
    dsr = ((dma + dmb) - 2.0 * s_r * e_de) * inv_r;
    dfx = -dn * ex - n_ax * dex - dsr * ey - s_r * dey;
    dfy = -dn * ey - n_ax * dey + dsr * ex + s_r * dex;
    bx = -dfx;
    by = -dfy;
    rj__lz_node_sums(f + a, &dfx, &bx);
    rj__lz_node_sums(f + nn + a, &dfy, &by);
    rj__lz_node_sums(f + n2 + a, &dma, &dmb);
}

/* *mag = |v| lane by lane */
static RJ__FORCE_INLINE void rj__vabs(const rj__vd *v, rj__vd *mag)
{
    rj__vl sign = { 0 };
    int k;
    for (k = 0; k < RJ__VW; k++)
        sign[k] = 0x7fffffffffffffffLL;
    *mag = (rj__vd) ((rj__vl) *v & sign);
}

/* Lanes' three kinds of terms for nodes i .. i + RJ__VW - 1 added to sum node by node. */
static RJ__FORCE_INLINE double rj__lz_sum_nodes(const rj__vd *px, const rj__vd *py,
                                                const rj__vd *pr, double sum)
{
    int k;
    for (k = 0; k < RJ__VW; k++) {
        sum += (*px)[k];
        sum += (*py)[k];
        sum += (*pr)[k];
    }
    return sum;
}
#endif

/* K d of the elements into f, plain runs in lanes where lanes_on. */
static RJ__FORCE_INLINE void rj__lz_elements_body(const rj__lz_table *t, const double *d,
                                                  double *f, int nn, int lanes_on)
{
    int c = 0;
    while (c < t->count) {
#ifdef RJ__LANES
        if (lanes_on && t->plain[c] >= RJ__VW) {
            rj__lz_element_lanes(t, c, d, f, nn);
            c += RJ__VW;
            continue;
        }
#else
        (void) lanes_on;
#endif
        rj__lz_element(t, c, d, f, nn);
        c++;
    }
}

/* After the product (w = K d): w = M^-1/2 w and alpha = w . v1, node by node. */
static RJ__FORCE_INLINE double rj__lz_unscale_dot(double *w, const double *sc, const double *v1,
                                                  int nn, int lanes_on)
{
    double a = 0;
    int i = 0, k;
#ifdef RJ__LANES
    if (lanes_on)
        for (; i + RJ__VW <= nn; i += RJ__VW) {
            double *wx = w + i, *wy = w + nn + i, *wr = w + 2 * (size_t) nn + i;
            const double *sx = sc + i, *sy = sc + nn + i, *sr = sc + 2 * (size_t) nn + i;
            const double *vx = v1 + i, *vy = v1 + nn + i, *vr = v1 + 2 * (size_t) nn + i;
            rj__vd x, y, r, s, v;
            RJ__VLD(x, wx);
            RJ__VLD(s, sx);
            x *= s;
            RJ__VST(wx, x);
            RJ__VLD(y, wy);
            RJ__VLD(s, sy);
            y *= s;
            RJ__VST(wy, y);
            RJ__VLD(r, wr);
            RJ__VLD(s, sr);
            r *= s;
            RJ__VST(wr, r);
            RJ__VLD(v, vx);
            x *= v;
            RJ__VLD(v, vy);
            y *= v;
            RJ__VLD(v, vr);
            r *= v;
            a = rj__lz_sum_nodes(&x, &y, &r, a);
        }
#else
    (void) lanes_on;
#endif
    for (; i < nn; i++)
        for (k = 0; k < 3; k++) {
            const size_t at = (size_t) k * (size_t) nn + (size_t) i;
            w[at] *= sc[at];
            a += w[at] * v1[at];
        }
    return a;
}

/* The three-term recurrence w -= alpha v1 + beta v0 over all 3 nn DOFs; returns max |w|. */
static RJ__FORCE_INLINE double rj__lz_recur(double *w, const double *v1, const double *v0,
                                            double a, double b, int n, int lanes_on)
{
    double big = 0;
    int i = 0;
#ifdef RJ__LANES
    if (lanes_on) {
        rj__vd va, vb, vbig;
        double p[RJ__VW];
        int k;
        rj__splat(&va, a);
        rj__splat(&vb, b);
        rj__splat(&vbig, 0.0);
        for (; i + RJ__VW <= n; i += RJ__VW) {
            rj__vd wv, x, y, mag;
            rj__vl more;
            RJ__VLD(wv, w + i);
            RJ__VLD(x, v1 + i);
            RJ__VLD(y, v0 + i);
            wv -= va * x + vb * y;
            RJ__VST(w + i, wv);
            rj__vabs(&wv, &mag);
            more = mag > vbig;
            vbig = (rj__vd) (((rj__vl) mag & more) | ((rj__vl) vbig & ~more));
        }
        RJ__VST(p, vbig);
        for (k = 0; k < RJ__VW; k++)
            if (p[k] > big)
                big = p[k];
    }
#else
    (void) lanes_on;
#endif
    for (; i < n; i++) {
        w[i] -= a * v1[i] + b * v0[i];
        if (fabs(w[i]) > big)
            big = fabs(w[i]);
    }
    return big;
}

/* |w| given big = max |w_i|, scaled by it so that the squares neither underflow nor
   overflow (omega^2 ~ 1e-166 for a link of 1e150 kg/m^3); the squares summed node by
   node. */
static RJ__FORCE_INLINE double rj__lz_norm(const double *w, double big, int nn, int lanes_on)
{
    double sum = 0, inv_big;
    int i = 0, k;
    if (big == 0 || !rj__finite(big))
        return big;
    inv_big = 1.0 / big;
#ifdef RJ__LANES
    if (lanes_on) {
        rj__vd vinv;
        rj__splat(&vinv, inv_big);
        for (; i + RJ__VW <= nn; i += RJ__VW) {
            rj__vd x, y, r;
            RJ__VLD(x, w + i);
            RJ__VLD(y, w + nn + i);
            RJ__VLD(r, w + 2 * (size_t) nn + i);
            x *= vinv;
            y *= vinv;
            r *= vinv;
            x *= x;
            y *= y;
            r *= r;
            sum = rj__lz_sum_nodes(&x, &y, &r, sum);
        }
    }
#else
    (void) lanes_on;
#endif
    for (; i < nn; i++)
        for (k = 0; k < 3; k++) {
            const double x = w[(size_t) k * (size_t) nn + (size_t) i];
            sum += (x * inv_big) * (x * inv_big);
        }
    return big * sqrt(sum);
}

/* After the product: alpha, the recurrence and beta = |w|. */
static RJ__FORCE_INLINE void rj__lz_orth_body(double *w, const double *sc, const double *v1,
                                              const double *v0, double beta_prev, int nn,
                                              double *alpha, double *beta, int lanes_on)
{
    double big;
    *alpha = rj__lz_unscale_dot(w, sc, v1, nn, lanes_on);
    big = rj__lz_recur(w, v1, v0, *alpha, beta_prev, 3 * nn, lanes_on);
    *beta = rj__lz_norm(w, big, nn, lanes_on);
}

/* The next Lanczos vector w / beta, its product's input d = M^-1/2 w, and v0 cleared: it
   becomes the next w. */
static RJ__FORCE_INLINE void rj__lz_advance_body(double *w, double inv_beta, const double *sc,
                                                 double *d, double *v0, int n, int lanes_on)
{
    int i = 0;
#ifdef RJ__LANES
    rj__vd vinv, zero;
    rj__splat(&vinv, inv_beta);
    rj__splat(&zero, 0.0);
    if (lanes_on)
        for (; i + RJ__VW <= n; i += RJ__VW) {
            rj__vd wv, s;
            RJ__VLD(wv, w + i);
            RJ__VLD(s, sc + i);
            wv *= vinv;
            RJ__VST(w + i, wv);
            wv *= s;
            RJ__VST(d + i, wv);
            RJ__VST(v0 + i, zero);
        }
#else
    (void) lanes_on;
#endif
    for (; i < n; i++) {
        w[i] *= inv_beta;
        d[i] = w[i] * sc[i];
        v0[i] = 0.0;
    }
}

/* The three passes compiled for AVX2 where the header dispatches, and for the including
   file's own target (lanes where RJ__DEFAULT_LANES_ON). */
#ifdef RJ__DISPATCH
RJ__AVX2 static void rj__lz_elements_avx2(const rj__lz_table *t, const double *d, double *f,
                                          int nn)
{
    rj__lz_elements_body(t, d, f, nn, 1);
}

RJ__AVX2 static void rj__lz_orth_avx2(double *w, const double *sc, const double *v1,
                                      const double *v0, double beta_prev, int nn, double *alpha,
                                      double *beta)
{
    rj__lz_orth_body(w, sc, v1, v0, beta_prev, nn, alpha, beta, 1);
}

RJ__AVX2 static void rj__lz_advance_avx2(double *w, double inv_beta, const double *sc, double *d,
                                         double *v0, int n)
{
    rj__lz_advance_body(w, inv_beta, sc, d, v0, n, 1);
}
#endif

static void rj__lz_elements_default(const rj__lz_table *t, const double *d, double *f, int nn)
{
    rj__lz_elements_body(t, d, f, nn, RJ__DEFAULT_LANES_ON);
}

static void rj__lz_orth_default(double *w, const double *sc, const double *v1, const double *v0,
                                double beta_prev, int nn, double *alpha, double *beta)
{
    rj__lz_orth_body(w, sc, v1, v0, beta_prev, nn, alpha, beta, RJ__DEFAULT_LANES_ON);
}

static void rj__lz_advance_default(double *w, double inv_beta, const double *sc, double *d,
                                   double *v0, int n)
{
    rj__lz_advance_body(w, inv_beta, sc, d, v0, n, RJ__DEFAULT_LANES_ON);
}

/* The passes in the widest lanes the CPU has, chosen once a bound. */
typedef struct rj__lz_passes {
    void (*elements)(const rj__lz_table *, const double *, double *, int);
    void (*orth)(double *, const double *, const double *, const double *, double, int,
                 double *, double *);
    void (*advance)(double *, double, const double *, double *, double *, int);
} rj__lz_passes;

static void rj__lz_passes_pick(rj__lz_passes *p)
{
    p->elements = rj__lz_elements_default;
    p->orth = rj__lz_orth_default;
    p->advance = rj__lz_advance_default;
#ifdef RJ__DISPATCH
    if (__builtin_cpu_supports("avx2")) {
        p->elements = rj__lz_elements_avx2;
        p->orth = rj__lz_orth_avx2;
        p->advance = rj__lz_advance_avx2;
    }
#endif
}

/* Whether Lanczos has converged after k steps (every 4th, from the 8th): its largest Ritz
   value theta moved by less than RJ__LZ_TOL of itself in the last 4 steps (*last: theta
   then), and it is within RJ__BOUND_GAP of the upper bound, so that a plateau far below
   omega_max^2 cannot pass for convergence. A theta above the bound (round-off in a model of
   extreme scales) voids the bound (*upper = HUGE_VAL): Lanczos runs its course. These tests
   take theta to 1e-11 by Newton's method (rj__tridiag_top; its last bits cannot move
   them); the estimate returned is bisection's to 1e-14 (rj__tridiag_max_near). */
static int rj__lz_converged(const double *al, const double *be, int k, double *last,
                            double *upper)
{
    double theta, moved;
    if (k % 4 != 0 || k < 8 || !(*upper < HUGE_VAL))
        return 0;
    theta = rj__tridiag_top(al, be, k, 1e-11);
    moved = theta - *last;
    *last = theta;
    if (theta > *upper * (1.0 + 1e-9)) {
        *upper = HUGE_VAL;
        return 0;
    }
    return fabs(moved) <= RJ__LZ_TOL * theta && theta >= (1.0 - RJ__BOUND_GAP) * *upper;
}

/* Lanczos's first product's input d = M^-1/2 v1, and w = 0 to sum the product into. */
static void rj__lz_load(const double *v1, const double *sc, double *d, double *w, int n)
{
    int i;
    for (i = 0; i < n; i++) {
        d[i] = v1[i] * sc[i];
        w[i] = 0.0;
    }
}

/* omega_max^2 of the linearised model by Lanczos (no reorthogonalisation: ghosts do not
   move the extreme Ritz value), stopped once converged (rj__lz_converged). Its product is
   rj__lz_apply's on vectors of DOF kinds (rj__lz_index), with the elements' linearisations
   tabled (rj__lz_table) after the five vectors. */
static double rj__omega2_max(rj_model *m, double *lanczos)
{
    const int n = 3 * m->nn;
    double *v0 = lanczos, *v1 = lanczos + n, *w = lanczos + 2 * n;
    double *sc = lanczos + 3 * n, *d = lanczos + 4 * n;
    double al[RJ__LANCZOS_ITERS], be[RJ__LANCZOS_ITERS], last = 0;
    double upper = rj__omega2_upper(m, v0);
    rj__lz_table table;
    rj__lz_passes pass;
    int i, k, kmax;
    /* the start and the scales as the interleaved vectors had them, then split */
    if (!rj__lz_start(m, v0, w))
        return 0;
    rj__lz_split(w, v1, m->nn);
    rj__lz_scales(m, d);
    rj__lz_split(d, sc, m->nn);
    rj__lz_table_build(m, lanczos + 5 * n, &table);
    rj__lz_passes_pick(&pass);
    rj__lz_load(v1, sc, d, w, n);
    kmax = n < RJ__LANCZOS_ITERS ? n : RJ__LANCZOS_ITERS;
    for (k = 0; k < kmax; k++) {
        double a, b, *t;
        pass.elements(&table, d, w, m->nn);
        rj__lz_rank_one(m, d, w, m->nn);
        pass.orth(w, sc, v1, v0, k > 0 ? be[k - 1] : 0.0, m->nn, &a, &b);
        al[k] = a;
        be[k] = b;
        /* a NaN or an infinity: no finite frequency (below) */
        if (!rj__finite(a) || !rj__finite(b) || b < 1e-12 * fabs(a) || b == 0) {
            k++;
            break;
        }
        if (rj__lz_converged(al, be, k + 1, &last, &upper))
            return rj__tridiag_max_near(al, be, k + 1, last);
        pass.advance(w, 1.0 / b, sc, d, v0, n);
        t = v0;
        v0 = v1;
        v1 = w;
        w = t;
    }
    /* a NaN or an infinity in the recurrence: no finite frequency (the bound refuses it) */
    for (i = 0; i < k; i++)
        if (!rj__finite(al[i]) || !rj__finite(be[i]))
            return HUGE_VAL;
    return rj__tridiag_max(al, be, k);
}
/* ------------------------------------------------------------------ SHAKE over chains that meet */
/* Inextensible chains that meet (a chain hanging from inside another, or a loop closed
   through a moving pin) are not tridiagonal: an element couples to every element that
   moves one of its nodes. Their elements form one sparse system A lambda = r, with
   A_ij = 4 sum_k s_ik s_jk w_k (e_i . e_j^n) over the owners k the two share (a pin
   group or a node; s = -1 at an element's first node, +1 at its second). Built once:
   the elements ordered by reverse Cuthill-McKee, so the factor's profile (envelope)
   stays narrow (a chain 1, a ring 2), with its first column per row. Each step factors
   A in that profile (Crout, no pivoting: A is a small perturbation of J W J^T, which is
   positive definite away from singular positions) without allocating. A pivot below
   1e-10 of its diagonal is a redundant element (a flat loop): its lambda is 0. */

/* The element graph's owner of a node: its pin group's first member, or the node;
   -1 for a node that does not move (inverse mass 0). */
static int rj__gs_owner(const rj_model *m, int k)
{
    const int g = m->node_grp[k];
    if (m->einv[k] == 0)
        return -1;
    return g >= 0 ? m->grp_node[m->grp_first[g]] : k;
}

/* Chains that meet: a moving pin group holding entries of two chains, or two entries
   of one chain (a loop). A group on a moving rigid body stays with the chain solver.
   Marks each such chain (mark: nch ints); count: ng ints. Returns how many. */
static int rj__gs_mark_chains(const rj_model *m, int *count, int *mark)
{
    int c, q, g, marked = 0;
    for (g = 0; g < m->ng; g++)
        count[g] = 0;
    for (q = 0; q < m->ch_first[m->nch]; q++) {
        g = m->node_grp[m->ch_node[q]];
        if (g >= 0 && m->grp_inv[g] > 0)
            count[g]++;
    }
    /* a group with a node on a moving body: its chains are solved with the body */
    for (g = 0; g < m->ng && m->ncl; g++)
        for (q = m->grp_first[g]; q < m->grp_first[g + 1]; q++) {
            const int cl = m->node_cl[m->grp_node[q]];
            if (cl >= 0 && m->cl_fix[cl] != 2)
                count[g] = 0;
        }
    for (c = 0; c < m->nch; c++) {
        mark[c] = 0;
        for (q = m->ch_first[c]; q < m->ch_first[c + 1]; q++) {
            g = m->node_grp[m->ch_node[q]];
            if (g >= 0 && count[g] >= 2)
                mark[c] = 1;
        }
        marked += mark[c];
    }
    return marked;
}

/* The marked chains' elements (their end nodes, squared lengths) in chain order; the
   chain list keeps the others, moved down over the taken ones. Returns the count. */
static int rj__gs_take_chains(rj_model *m, const int *mark, int *na, int *nb, double *l0sq)
{
    int c, q, n = 0, kept = 0, kept_chains = 0;
    for (c = 0; c < m->nch; c++) {
        const int f0 = m->ch_first[c], f1 = m->ch_first[c + 1];
        if (!mark[c]) {
            for (q = f0; q < f1; q++) {
                m->ch_node[kept + q - f0] = m->ch_node[q];
                m->ch_l0sq[kept + q - f0] = m->ch_l0sq[q];
            }
            kept += f1 - f0;
            m->ch_first[++kept_chains] = kept;
            continue;
        }
        for (q = f0; q + 1 < f1; q++) {
            na[n] = m->ch_node[q];
            nb[n] = m->ch_node[q + 1];
            l0sq[n] = m->ch_l0sq[q + 1];
            n++;
        }
    }
    m->nch = kept_chains;
    return n;
}

/* The elements that move owner o of each, as lists: list[start[o]] to list[start[o + 1]]
   (start: nn + 1, list: 2 n). */
static void rj__gs_owner_lists(const rj_model *m, int n, const int *oa, const int *ob,
                               int *start, int *list)
{
    int k, i;
    for (k = 0; k <= m->nn; k++)
        start[k] = 0;
    for (i = 0; i < n; i++) {
        if (oa[i] >= 0)
            start[oa[i] + 1]++;
        if (ob[i] >= 0 && ob[i] != oa[i])
            start[ob[i] + 1]++;
    }
    for (k = 0; k < m->nn; k++)
        start[k + 1] += start[k];
    /* filled through start[o] as a cursor, which ends at the next owner's start */
    for (i = 0; i < n; i++) {
        if (oa[i] >= 0)
            list[start[oa[i]]++] = i;
        if (ob[i] >= 0 && ob[i] != oa[i])
            list[start[ob[i]]++] = i;
    }
    for (k = m->nn; k > 0; k--)
        start[k] = start[k - 1];
    start[0] = 0;
}

/* Breadth first from element v over the elements sharing an owner, appending to order
   from *len and marking seen; returns the last element reached (the farthest). */
static int rj__gs_breadth(int v, const int *oa, const int *ob, const int *start,
                          const int *list, int *seen, int *order, int *len)
{
    int head = *len, last = v;
    order[(*len)++] = v;
    seen[v] = 1;
    while (head < *len) {
        const int e = order[head++];
        const int owners[2] = { oa[e], ob[e] };
        int side, q;
        last = e;
        for (side = 0; side < 2; side++) {
            if (owners[side] < 0)
                continue;
            for (q = start[owners[side]]; q < start[owners[side] + 1]; q++)
                if (!seen[list[q]]) {
                    seen[list[q]] = 1;
                    order[(*len)++] = list[q];
                }
        }
    }
    return last;
}

/* Reverse Cuthill-McKee without the degree sort: each connected set of elements from
   its far end (found by one sweep), the whole order then reversed. */
static void rj__gs_order(int n, const int *oa, const int *ob, const int *start,
                         const int *list, int *seen, int *order)
{
    int i, len = 0;
    for (i = 0; i < n; i++)
        seen[i] = 0;
    for (i = 0; i < n; i++) {
        int from = len, far, q;
        if (seen[i])
            continue;
        far = rj__gs_breadth(i, oa, ob, start, list, seen, order, &len);
        for (q = from; q < len; q++)
            seen[order[q]] = 0;
        len = from;
        rj__gs_breadth(far, oa, ob, start, list, seen, order, &len);
    }
    for (i = 0; i < n / 2; i++) {
        const int t = order[i];
        order[i] = order[n - 1 - i];
        order[n - 1 - i] = t;
    }
}

/* The nodes the elements move (every member of a moving pin group), each with its
   owner; mark: nn ints. */
static void rj__gs_nodes(rj_model *m, int *mark)
{
    int k, i, side;
    m->gs_nodes = 0;
    for (k = 0; k < m->nn; k++)
        mark[k] = 0;
    for (i = 0; i < m->gs_n; i++)
        for (side = 0; side < 2; side++) {
            const int node = side ? m->gs_nb[i] : m->gs_na[i];
            const int g = m->node_grp[node];
            const int first = g >= 0 ? m->grp_first[g] : 0, last = g >= 0 ? m->grp_first[g + 1] : 1;
            int q;
            if (rj__gs_owner(m, node) < 0)
                continue;
            for (q = first; q < last; q++) {
                const int member = g >= 0 ? m->grp_node[q] : node;
                if (mark[member])
                    continue;
                mark[member] = 1;
                m->gs_node[m->gs_nodes] = member;
                m->gs_nown[m->gs_nodes] = rj__gs_owner(m, node);
                m->gs_nodes++;
            }
        }
}

/* Builds the system of the chains that meet, taking them from the chain list; scratch
   from the building area (3 ne doubles and 6 ne + 2 nn + ng + nl + 1 ints). */
static void rj__gs_build(rj_model *m, double *area)
{
    double *l0sq = area;
    int *na = (int *) (void *) (area + m->ne), *nb = na + m->ne, *oa = nb + m->ne;
    int *ob = oa + m->ne, *order = ob + m->ne, *seen = order + m->ne;
    int *start = seen + m->ne, *list = start + m->nn + 1, *count = list + 2 * (size_t) m->ne;
    int *mark = count + m->ng + 1;
    int n, i, q;
    m->gs_n = 0;
    m->gs_prof = 0;
    if (!m->nch || !rj__gs_mark_chains(m, count, mark))
        return;
    n = rj__gs_take_chains(m, mark, na, nb, l0sq);
    for (i = 0; i < n; i++) {
        oa[i] = rj__gs_owner(m, na[i]);
        ob[i] = rj__gs_owner(m, nb[i]);
    }
    rj__gs_owner_lists(m, n, oa, ob, start, list);
    rj__gs_order(n, oa, ob, start, list, seen, order);
    /* the elements in the new order; seen becomes each old element's new index */
    m->gs_n = n;
    for (i = 0; i < n; i++) {
        m->gs_na[i] = na[order[i]];
        m->gs_nb[i] = nb[order[i]];
        m->gs_oa[i] = oa[order[i]];
        m->gs_ob[i] = ob[order[i]];
        m->gs_l0sq[i] = l0sq[order[i]];
        seen[order[i]] = i;
    }
    /* the profile: each row from its first coupled column */
    m->gs_off[0] = 0;
    for (i = 0; i < n; i++) {
        const int owners[2] = { m->gs_oa[i], m->gs_ob[i] };
        int first = i, side;
        for (side = 0; side < 2; side++)
            if (owners[side] >= 0)
                for (q = start[owners[side]]; q < start[owners[side] + 1]; q++)
                    if (seen[list[q]] < first)
                        first = seen[list[q]];
        m->gs_first[i] = first;
        m->gs_off[i + 1] = m->gs_off[i] + (i - first);
    }
    m->gs_prof = (size_t) m->gs_off[n];
    rj__gs_nodes(m, start);
}

/* sum_k s_ik s_jk w_k over the owners elements i and j share (see above). */
static double rj__gs_shared(const rj_model *m, int i, int j)
{
    const int ai = m->gs_oa[i], bi = m->gs_ob[i], aj = m->gs_oa[j], bj = m->gs_ob[j];
    double sum = 0;
    if (ai >= 0) {
        sum += ai == aj ? m->einv[ai] : 0.0;
        sum -= ai == bj ? m->einv[ai] : 0.0;
    }
    if (bi >= 0) {
        sum -= bi == aj ? m->einv[bi] : 0.0;
        sum += bi == bj ? m->einv[bi] : 0.0;
    }
    return sum;
}

/* Scratch of the system (rj_state.gsw): the factor's lower and upper profiles, the
   reciprocal pivots, the residuals, the multipliers, the chords now and at n, and each
   owner's push. */
typedef struct rj__gs_work {
    double *lower, *upper, *dinv, *r, *lam, *cx, *cy, *ox, *oy, *push;
} rj__gs_work;

static rj__gs_work rj__gs_carve(const rj_model *m, const rj_state *s)
{
    rj__gs_work w;
    const size_t n = (size_t) m->gs_n;
    w.lower = s->gsw;
    w.upper = w.lower + m->gs_prof;
    w.dinv = w.upper + m->gs_prof;
    w.r = w.dinv + n;
    w.lam = w.r + n;
    w.cx = w.lam + n;
    w.cy = w.cx + n;
    w.ox = w.cy + n;
    w.oy = w.ox + n;
    w.push = w.oy + n;
    return w;
}

/* A = L U in the profile (Crout, row by row): row i of L and column i of U from the
   first coupled column. */
static void rj__gs_factor(const rj_model *m, const rj__gs_work *w)
{
    int i, j, k;
    for (i = 0; i < m->gs_n; i++) {
        const int fi = m->gs_first[i];
        double *li = w->lower + m->gs_off[i] - fi, *ui = w->upper + m->gs_off[i] - fi;
        double aii, d;
        for (j = fi; j < i; j++) {
            const int fj = m->gs_first[j];
            const double *lj = w->lower + m->gs_off[j] - fj, *uj = w->upper + m->gs_off[j] - fj;
            const double shared = 4.0 * rj__gs_shared(m, i, j);
            double aij = shared * (w->cx[i] * w->ox[j] + w->cy[i] * w->oy[j]);
            double aji = shared * (w->cx[j] * w->ox[i] + w->cy[j] * w->oy[i]);
            for (k = fi > fj ? fi : fj; k < j; k++) {
                aij -= li[k] * uj[k];
                aji -= lj[k] * ui[k];
            }
            ui[j] = aji;
            li[j] = aij * w->dinv[j];
        }
        aii = 4.0 * rj__gs_shared(m, i, i) * (w->cx[i] * w->ox[i] + w->cy[i] * w->oy[i]);
        d = aii;
        for (k = fi; k < i; k++)
            d -= li[k] * ui[k];
        /* a pivot gone with its diagonal: a redundant or unmovable element */
        w->dinv[i] = aii > 0 && fabs(d) > 1e-10 * aii ? 1.0 / d : 0.0;
    }
}

/* lambda = A^-1 r: forward through L, back through U by columns. */
static void rj__gs_solve(const rj_model *m, const rj__gs_work *w)
{
    double *y = w->r;
    int i, k;
    for (i = 0; i < m->gs_n; i++) {
        const int fi = m->gs_first[i];
        const double *li = w->lower + m->gs_off[i] - fi;
        for (k = fi; k < i; k++)
            y[i] -= li[k] * y[k];
    }
    for (i = m->gs_n - 1; i >= 0; i--) {
        const int fi = m->gs_first[i];
        const double *ui = w->upper + m->gs_off[i] - fi;
        w->lam[i] = y[i] * w->dinv[i];
        for (k = fi; k < i; k++)
            y[k] -= ui[k] * w->lam[i];
    }
}

/* Each owner's push sum_i s_i lambda_i e_i^n, then every node it moves by 2 w push. */
static void rj__gs_move(const rj_model *m, const rj__gs_work *w, double *nx, double *ny)
{
    double *push = w->push;
    int i, q;
    for (q = 0; q < m->gs_nodes; q++) {
        push[2 * m->gs_nown[q]] = 0;
        push[2 * m->gs_nown[q] + 1] = 0;
    }
    for (i = 0; i < m->gs_n; i++) {
        const double px = w->lam[i] * w->ox[i], py = w->lam[i] * w->oy[i];
        if (m->gs_oa[i] >= 0) {
            push[2 * m->gs_oa[i]] -= px;
            push[2 * m->gs_oa[i] + 1] -= py;
        }
        if (m->gs_ob[i] >= 0) {
            push[2 * m->gs_ob[i]] += px;
            push[2 * m->gs_ob[i] + 1] += py;
        }
    }
    for (q = 0; q < m->gs_nodes; q++) {
        const int k = m->gs_node[q], o = m->gs_nown[q];
        nx[k] += 2.0 * m->einv[k] * push[2 * o];
        ny[k] += 2.0 * m->einv[k] * push[2 * o + 1];
    }
}

/* With loops: each element's push lambda_i e_i^n into shp by its second node, summed over
   the iterations (rj__loop_records takes a loop's pin node's share). */
static void rj__gs_track(const rj_model *m, const rj__gs_work *w, double *shp)
{
    int i;
    for (i = 0; i < m->gs_n; i++) {
        shp[2 * m->gs_nb[i]] += w->lam[i] * w->ox[i];
        shp[2 * m->gs_nb[i] + 1] += w->lam[i] * w->oy[i];
    }
}

/* The residuals -g_i = l0^2 - |e_i|^2 (0 for an element nothing moves), the chords now;
   returns the largest |g_i| / l0^2. */
static double rj__gs_residuals(const rj_model *m, const rj__gs_work *w, const double *nx,
                               const double *ny)
{
    double worst = 0;
    int i;
    for (i = 0; i < m->gs_n; i++) {
        const double ex = nx[m->gs_nb[i]] - nx[m->gs_na[i]];
        const double ey = ny[m->gs_nb[i]] - ny[m->gs_na[i]];
        const int moves = m->gs_oa[i] >= 0 || m->gs_ob[i] >= 0;
        const double g = moves ? ex * ex + ey * ey - m->gs_l0sq[i] : 0.0;
        if (fabs(g) > worst * m->gs_l0sq[i])
            worst = fabs(g) / m->gs_l0sq[i];
        w->r[i] = -g;
        w->cx[i] = ex;
        w->cy[i] = ey;
    }
    return worst;
}

/* Newton iterations on the lengths of the chains that meet; the matrix of the first
   serves the later ones (it changes with the chords by the size of the correction). */
static void rj__shake_graph(const rj_model *m, rj_state *s, const double *x, const double *y,
                            double *nx, double *ny)
{
    const rj__gs_work w = rj__gs_carve(m, s);
    int it, i;
    for (i = 0; i < m->gs_n; i++) {
        w.ox[i] = x[m->gs_nb[i]] - x[m->gs_na[i]];
        w.oy[i] = y[m->gs_nb[i]] - y[m->gs_na[i]];
    }
    for (it = 0; it < 8; it++) {
        if (rj__gs_residuals(m, &w, nx, ny) < 1e-14)
            break;
        if (it == 0)
            rj__gs_factor(m, &w);
        rj__gs_solve(m, &w);
        rj__gs_move(m, &w, nx, ny);
        if (m->nloop)
            rj__gs_track(m, &w, s->shp);
    }
}
/* ------------------------------------------------------------------ building the model */
/* The model's building area (m->lz, sized by rj__model_layout) as the phases of
   rj_model_init use it. The phases run one after another, so every view starts at the
   area's start and each phase leaves nothing the next one reads; the rigid links' power
   iteration works after the Lanczos vectors. */
typedef struct rj__build_scratch {
    int *graph;                /* RJ__GRAPH_SCRATCH(nl, nj) ints: rj__validate_graph */
    int *pin_groups;           /* 4 nn + ng ints: rj__pin_groups */
    int *placement;            /* 3 nl ints: rj__place_all */
    int *chains;               /* 2 nl + 2 nn ints: rj__inext_chains; nj ints in rigid
                                  scenes: rj__init_joint_order */
    double *lanczos;           /* 5 vectors of 3 nn, then 8 ne doubles and 3 ne ints of the
                                  elements' table (rj__lz_table): rj__omega2_max */
    double *rigid_bound;       /* rj__rig_bound_scratch: the solver's, then a dense M^-1 or
                                  a tree's responses (rj__rig_tree_minv) */
    int *step_node_mark;       /* nn ints: rj__init_step_nodes */
} rj__build_scratch;

/* Points every phase's scratch into the building area. */
static void rj__build_scratch_carve(const rj_model *m, rj__build_scratch *s)
{
    void *area = m->lz;
    s->graph = (int *) area;
    s->pin_groups = (int *) area;
    s->placement = (int *) area;
    s->chains = (int *) area;
    s->lanczos = m->lz;
    s->rigid_bound = m->lz + 15 * (size_t) m->nn;
    s->step_node_mark = (int *) area;
}

/* Before anything is written: err cleared, out given, the scene's fields and totals valid
   (rj_model_size), and a block as large as the layout that *L gets. */
static rj_result rj__init_check_args(const rj_scene_def *sc, void *mem, size_t size, rj_model **out,
                                     size_t *nodes, size_t *elements, rj__layout *L,
                                     int validated, rj_error *err)
{
    rj_error size_err;
    /* set on every path: compilers cannot tell that a refusal's code is never RJ_OK */
    *nodes = 0;
    *elements = 0;
    memset(L, 0, sizeof *L);
    if (err) {
        err->code = RJ_OK;
        err->field[0] = 0;
        err->msg[0] = 0;
        err->value = 0;
    }
    if (!out) {
        rj__fail(err, RJ_ERR_INVALID, "out", 0, "out is NULL");
        return RJ_ERR_INVALID;
    }
    if (!validated && !rj_model_size(sc, err ? err : &size_err))
        return err ? err->code : size_err.code;
    rj__counts(sc, nodes, elements, err);
    rj__model_layout(sc, *nodes, *elements, L);
    if (!mem) {
        rj__fail(err, RJ_ERR_NOMEM, "mem", 0,
                 "mem is NULL: the model needs a block of %lu bytes (rj_model_size)",
                 (unsigned long) L->total);
        return RJ_ERR_NOMEM;
    }
    if (size < L->total) {
        rj__fail(err, RJ_ERR_NOMEM, "size", (double) size,
                 "memory block of %lu bytes is smaller than the %lu the model needs",
                 (unsigned long) size, (unsigned long) L->total);
        return RJ_ERR_NOMEM;
    }
    return RJ_OK;
}

/* The model sits at the block's first 16-byte boundary, zeroed, with its counts. */
static rj_model *rj__init_block(const rj_scene_def *sc, void *mem, const rj__layout *L,
                                size_t nodes, size_t elements)
{
    char *base = (char *) mem;
    rj_model *m;
    base += (RJ__ALIGN - ((size_t) base % RJ__ALIGN)) % RJ__ALIGN;
    memset(base, 0, L->total - RJ__ALIGN);
    m = (rj_model *) (void *) base;
    m->bytes = L->total - RJ__ALIGN;
    m->nl = sc->link_count;
    m->nj = sc->joint_count;
    m->nn = (int) nodes;
    m->ne = (int) elements;
    m->solver = sc->solver;
    return m;
}

/* The model's arrays at the offsets of the layout (rj__model_layout), after the struct. */
static void rj__init_arrays(rj_model *m, const rj__layout *L)
{
    char *base = (char *) (void *) m;
#define RJ__SET(field, type) m->field = (type *) (void *) (base + L->field)
    RJ__SET(ldef, rj_link_def);
    RJ__SET(jdef, rj_joint_def);
    RJ__SET(jnt, rj__joint);
    RJ__SET(link_first, int);
    RJ__SET(link_efirst, int);
    RJ__SET(link_l0, double);
    RJ__SET(link_EA, double);
    RJ__SET(link_EI, double);
    RJ__SET(link_rho, double);
    RJ__SET(link_I, double);
    RJ__SET(ch_first, int);
    RJ__SET(ch_node, int);
    RJ__SET(ch_l0sq, double);
    RJ__SET(node_cl, int);
    RJ__SET(bp_node, int);
    RJ__SET(cl_first, int);
    RJ__SET(cl_node, int);
    RJ__SET(cl_fix, int);
    RJ__SET(cl_M, double);
    RJ__SET(cl_I, double);
    RJ__SET(cl_th0, double);
    RJ__SET(cl_rx, double);
    RJ__SET(cl_ry, double);
    RJ__SET(rb_mass, double);
    RJ__SET(rb_icm, double);
    RJ__SET(rb_dcm, double);
    RJ__SET(rb_pjoint, int);
    RJ__SET(jorder, int);
    RJ__SET(qj, int);
    RJ__SET(jq, int);
    RJ__SET(wcol, int);
    RJ__SET(jpin, double);
    RJ__SET(jref, double);
    RJ__SET(mass, double);
    RJ__SET(rinertia, double);
    RJ__SET(tinv, double);
    RJ__SET(rinv, double);
    RJ__SET(einv, double);
    RJ__SET(kmass, double);
    RJ__SET(krot, double);
    RJ__SET(grp_first, int);
    RJ__SET(grp_node, int);
    RJ__SET(node_grp, int);
    RJ__SET(grp_inv, double);
    RJ__SET(dnode, int);
    RJ__SET(link_un, double);
    RJ__SET(link_kc, double);
    RJ__SET(link_path, int);
    RJ__SET(link_pl, int);
    RJ__SET(link_damp, double);
    RJ__SET(visc_first, int);
    RJ__SET(visc_joint, int);
    RJ__SET(x0, double);
    RJ__SET(y0, double);
    RJ__SET(phi0, double);
    RJ__SET(vx0, double);
    RJ__SET(vy0, double);
    RJ__SET(w0, double);
    RJ__SET(beta0, double);
    RJ__SET(load, rj_load_def);
    RJ__SET(load_node, int);
    RJ__SET(act, rj_actuator_def);
    RJ__SET(spl, double);
    RJ__SET(cp, rj_coupling_def);
    RJ__SET(lz, double);
    RJ__SET(gs_l0sq, double);
#undef RJ__SET
    /* the system of the chains that meet: its int arrays in one block */
    m->gs_na = (int *) (void *) (base + L->gs_int);
    m->gs_nb = m->gs_na + m->ne;
    m->gs_oa = m->gs_nb + m->ne;
    m->gs_ob = m->gs_oa + m->ne;
    m->gs_first = m->gs_ob + m->ne;
    m->gs_off = m->gs_first + m->ne;
    m->gs_node = m->gs_off + m->ne + 1;
    m->gs_nown = m->gs_node + m->nn;
}

/* The model keeps its own copy of the definitions: the scene's arrays may go. */
static void rj__init_copy_defs(rj_model *m, const rj_scene_def *sc)
{
    int k;
    memcpy(m->ldef, sc->links, sizeof(rj_link_def) * (size_t) m->nl);
    if (m->nj)
        memcpy(m->jdef, sc->joints, sizeof(rj_joint_def) * (size_t) m->nj);
    m->has_gravity = sc->solver.gravity[0] != 0 || sc->solver.gravity[1] != 0;
    m->nload = sc->load_count;
    if (m->nload)
        memcpy(m->load, sc->loads, sizeof(rj_load_def) * (size_t) m->nload);
    m->nact = sc->actuator_count;
    if (m->nact)
        memcpy(m->act, sc->actuators, sizeof(rj_actuator_def) * (size_t) m->nact);
    m->ncp = sc->coupling_count;
    if (m->ncp)
        memcpy(m->cp, sc->couplings, sizeof(rj_coupling_def) * (size_t) m->ncp);
    for (k = 0; k < m->ncp; k++)
        m->nexact += m->cp[k].exact;
    m->nmotion += m->nexact;
}

/* A link's section: area and second moment (layers integrate EA and EI exactly for the
   elastic rectangle). */
static void rj__link_section(const rj_link_def *d, double *area, double *inertia)
{
    double A = 0, I = 0, layer;
    int k;
    if (d->section != RJ_SECTION_RECT) {
        *area = d->area;
        *inertia = d->inertia;
        return;
    }
    layer = d->height / d->layers;
    for (k = 0; k < d->layers; k++) {
        const double z = -0.5 * d->height + (k + 0.5) * layer;
        A += d->width * layer;
        I += d->width * layer * layer * layer / 12.0 + d->width * layer * z * z;
    }
    *area = A;
    *inertia = I;
}

/* Link l's node and element ranges, its element length and stiffnesses, and the element's
   constants: EI/l0, EA/l0 (0 for inextensible links: a constraint instead), l0^2,
   1/(2 l0^2). */
static void rj__init_link_constants(rj_model *m, int l, double area, double inertia)
{
    const rj_link_def *d = &m->ldef[l];
    const double l0 = d->length / d->elements;
    double *kc = m->link_kc + 4 * (size_t) l;
    m->link_first[l + 1] = m->link_first[l] + d->elements + 1;
    m->link_efirst[l + 1] = m->link_efirst[l] + d->elements;
    m->link_l0[l] = l0;
    m->link_EA[l] = d->E * area;
    m->link_EI[l] = d->E * inertia;
    kc[0] = m->link_EI[l] / l0;
    kc[1] = d->fidelity == RJ_LINK_INEXTENSIBLE ? 0.0 : m->link_EA[l] / l0;
    kc[2] = l0 * l0;
    kc[3] = 0.5 / kc[2];
    m->link_rho[l] = d->rho;
    m->link_I[l] = inertia;
}

/* Link l's lumped masses and rotary inertias (each element gives each of its two nodes
   end_mass and end_rot, the larger of the rod's and the section's rotary share; the tip
   mass sits on the last node), their inverses, and the roots that hold them (inverse 0). */
static void rj__init_link_masses(rj_model *m, int l, double area, double inertia)
{
    const rj_link_def *d = &m->ldef[l];
    const double l0 = m->link_l0[l];
    const double end_mass = 0.5 * d->rho * area * l0;
    const int n0 = m->link_first[l];
    double end_rot = d->rho * area * l0 * l0 * l0 / 78.0;
    int k;
    if (0.5 * d->rho * inertia * l0 > end_rot)
        end_rot = 0.5 * d->rho * inertia * l0;
    for (k = 0; k <= d->elements; k++) {
        const double elements_here = (k == 0 || k == d->elements) ? 1.0 : 2.0;
        m->mass[n0 + k] = elements_here * end_mass;
        m->rinertia[n0 + k] = elements_here * end_rot;
    }
    m->mass[n0 + d->elements] += d->tip_mass;
    m->rinertia[n0 + d->elements] += d->tip_inertia;
    for (k = 0; k <= d->elements; k++) {
        m->tinv[n0 + k] = 1.0 / m->mass[n0 + k];
        m->rinv[n0 + k] = 1.0 / m->rinertia[n0 + k];
    }
    if (d->root == RJ_ROOT_PINNED || d->root == RJ_ROOT_CLAMPED)
        m->tinv[n0] = 0;
    if (d->root == RJ_ROOT_CLAMPED)
        m->rinv[n0] = 0;
    if (d->root == RJ_ROOT_FIXED)
        for (k = 0; k <= d->elements; k++) {
            m->tinv[n0 + k] = 0;
            m->rinv[n0 + k] = 0;
        }
}

/* Link l's path through the beam pass and its material: the structural damping's eta
   (given, or from a ratio at a frequency, ratio / (pi f), so that eta omega / 2 is the
   ratio there) and mass-proportional rate; a yielding link's plastic strains in the
   frame (two sections an element, each of the link's layers). */
static void rj__init_link_material(rj_model *m, int l)
{
    const rj_link_def *d = &m->ldef[l];
    double *damp = RJ__LD(m, l);
    const int damped = d->eta > 0 || d->damping[0] > 0 || d->mass_damping > 0;
    const int yielding = d->yield > 0;
    /* eta lagged until rj__init_viscous knows whether a rigid body carries the link */
    damp[RJ__LD_LAGGED] = d->damping[0] > 0 ? d->damping[0] / (RJ__PI * d->damping[1]) : d->eta;
    damp[RJ__LD_MASS] = d->mass_damping;
    damp[RJ__LD_IMPLICIT] = 0;
    m->link_pl[l] = -1;
    if (yielding) {
        m->link_pl[l] = (int) m->npl;
        m->npl += 2 * (size_t) d->layers * (size_t) d->elements;
    }
    m->link_path[l] = RJ__PATH_FUSED;
    if (d->fidelity == RJ_LINK_RIGID)
        m->link_path[l] = RJ__PATH_RIGID;
    else if (damped || yielding || d->strain == RJ_STRAIN_BIOT)
        m->link_path[l] = RJ__PATH_MATERIAL;
    m->nstruct += damped;
    m->nplastic += yielding;
    m->nmaterial += m->link_path[l] == RJ__PATH_MATERIAL;
}

/* Every link's section, constants and masses, link by link. */
static void rj__init_links(rj_model *m)
{
    int l;
    m->link_first[0] = 0;
    m->link_efirst[0] = 0;
    for (l = 0; l < m->nl; l++) {
        double area, inertia;
        rj__link_section(&m->ldef[l], &area, &inertia);
        rj__init_link_constants(m, l, area, inertia);
        rj__init_link_masses(m, l, area, inertia);
        rj__init_link_material(m, l);
    }
}

/* The node each applied load acts on, in the scene's node order (-1: the link's last). */
static void rj__init_load_nodes(rj_model *m)
{
    int k;
    for (k = 0; k < m->nload; k++) {
        const rj_load_def *d = &m->load[k];
        m->load_node[k] = rj_model_node_index(m, d->link, d->node);
    }
}

/* Each joint's nodes: nI pin on body 1 and nK its neighbour (-1 for ground), nJ body 2's
   pin (node2: node 0 unless set) and nL its neighbour (towards the tip, or back from the
   tip). A node pinned to ground does not translate. The nodes' effective inverse masses
   start as their own. */
static void rj__init_joint_nodes(rj_model *m)
{
    int i, j;
    for (i = 0; i < m->nn; i++)
        m->einv[i] = m->tinv[i];
    for (i = 0; i < m->nn; i++)
        m->node_grp[i] = -1;
    m->grp_first[0] = 0;
    /* a link's first joint as body2 hangs it; a later one closes a loop (node_grp of its
       root marks it hung until the pin groups take node_grp over) */
    m->nq = m->nloop = 0;
    for (j = 0; j < m->nj; j++) {
        const int root = m->link_first[m->jdef[j].body2];
        m->jnt[j].loop = m->node_grp[root] == 1;
        m->node_grp[root] = 1;
        /* the tree's joints are the joint coordinates of rigid scenes */
        m->jq[j] = m->jnt[j].loop ? -1 : m->nq;
        if (m->jnt[j].loop)
            m->nloop++;
        else
            m->qj[m->nq++] = j;
    }
    for (i = 0; i < m->nn; i++)
        m->node_grp[i] = -1;
    for (j = 0; j < m->nj; j++) {
        const rj_joint_def *d = &m->jdef[j];
        rj__joint *J = &m->jnt[j];
        const int ne2 = m->ldef[d->body2].elements;
        const int at = d->node2 < 0 ? ne2 : d->node2;
        const int pin2 = m->link_first[d->body2] + at;
        J->nJ = pin2;
        J->nL = pin2 + (at < ne2 ? 1 : -1);
        if (d->body1 < 0) {
            J->nI = -1;
            J->nK = -1;
            J->gax = cos(d->ground_angle);
            J->gay = sin(d->ground_angle);
            m->tinv[pin2] = 0;
            m->einv[pin2] = 0;
        } else {
            const int pin = d->node1 < 0 ? m->ldef[d->body1].elements : d->node1;
            J->nI = m->link_first[d->body1] + pin;
            J->nK = J->nI + (pin > 0 ? -1 : 1);
        }
    }
}

/* Pin groups (body 1's pin node and every body 2 root pinned to it share their
   translation): the group's inverse mass (0 when a member is held) becomes each member's
   effective one, and the members' own translation is the group's (tinv 0). */
static void rj__init_pin_groups(rj_model *m, int *scratch)
{
    int group, k;
    m->ng = rj__pin_groups(m, scratch);
    for (group = 0; group < m->ng; group++) {
        double mass_sum = 0;
        int held = 0;
        for (k = m->grp_first[group]; k < m->grp_first[group + 1]; k++) {
            const int node = m->grp_node[k];
            mass_sum += m->mass[node];
            if (m->tinv[node] == 0)
                held = 1;
        }
        m->grp_inv[group] = held ? 0.0 : 1.0 / mass_sum;
        for (k = m->grp_first[group]; k < m->grp_first[group + 1]; k++) {
            m->einv[m->grp_node[k]] = m->grp_inv[group];
            m->tinv[m->grp_node[k]] = 0;
            m->node_grp[m->grp_node[k]] = group;
        }
    }
}

/* The masses and rotary inertias the kinetic energy counts node by node (0 for held or
   grouped nodes: a group's translation is counted once, by the step). */
static void rj__init_energy_masses(rj_model *m)
{
    int i;
    for (i = 0; i < m->nn; i++) {
        m->kmass[i] = m->tinv[i] > 0 ? m->mass[i] : 0.0;
        m->krot[i] = m->rinv[i] > 0 ? m->rinertia[i] : 0.0;
    }
}

/* The initial state: each link placed after the link it hangs from, and no initial
   velocity where the node cannot move (fixed links, held translations and rotations). */
static void rj__init_placement(rj_model *m, int *scratch)
{
    int i, l, k;
    rj__place_all(m, scratch);
    for (l = 0; l < m->nl; l++) {
        if (m->ldef[l].root != RJ_ROOT_FIXED)
            continue;
        for (k = m->link_first[l]; k < m->link_first[l + 1]; k++) {
            m->vx0[k] = 0;
            m->vy0[k] = 0;
            m->w0[k] = 0;
        }
    }
    for (i = 0; i < m->nn; i++)
        if (m->einv[i] == 0) {
            m->vx0[i] = 0;
            m->vy0[i] = 0;
        }
    for (i = 0; i < m->nn; i++)
        if (m->rinv[i] == 0)
            m->w0[i] = 0;
}

/* Each element's initial chord angle, on the same branch as its first node's rotation, so
   phi - beta starts near 0. */
static void rj__init_chord_angles(rj_model *m)
{
    int l, k;
    for (l = 0; l < m->nl; l++)
        for (k = m->link_efirst[l]; k < m->link_efirst[l + 1]; k++) {
            const int a = m->link_first[l] + (k - m->link_efirst[l]);
            const double chord = atan2(m->y0[a + 1] - m->y0[a], m->x0[a + 1] - m->x0[a]);
            m->beta0[k] = m->phi0[a] + rj__wrap(chord - m->phi0[a]);
        }
}

/* The joints whose two pins are own nodes of two rigid bodies (mixed scenes): the pin
   between the bodies turns both with the joint's torques (rj__pair_terms). */
static void rj__init_body_pairs(rj_model *m)
{
    int j;
    m->npair = 0;
    for (j = 0; j < m->nj; j++) {
        rj__joint *J = &m->jnt[j];
        J->pair = 0;
        if (!m->ncl || J->nI < 0)
            continue;
        J->pair = RJ__CL_RIGID(m, J->nI) && RJ__CL_RIGID(m, J->nJ) &&
                  m->node_cl[J->nI] != m->node_cl[J->nJ];
        m->npair += J->pair;
    }
}

/* Rigid links in a scene with flexible ones move as bodies (clusters, rj__clusters); a
   scene of rigid links alone runs in joint coordinates instead and has none. */
static int rj__init_clusters(rj_model *m, const rj_scene_def *sc, rj_error *err)
{
    int i, l;
    for (i = 0; i < m->nn; i++)
        m->node_cl[i] = -1;
    if (!rj__all_rigid(sc))
        for (l = 0; l < m->nl; l++)
            if (m->ldef[l].fidelity == RJ_LINK_RIGID)
                m->ncl = m->nl;
    if (m->ncl && !rj__clusters(m, err))
        return 0;
    rj__init_body_pairs(m);
    return 1;
}

/* Joint j's inertias on either side (chord reference: from the neighbour nodes' effective
   masses; tangent: the pin nodes' rotary inertias; HUGE_VAL where held), the weights that
   split its torque between them, and the tangent reference's angle offset. */
static void rj__init_joint_inertias(rj_model *m, int j)
{
    const rj_joint_def *d = &m->jdef[j];
    rj__joint *J = &m->jnt[j];
    rj__jgeo g;
    J->chord = d->reference == RJ_REF_CHORD;
    rj__joint_geo(m, J, m->x0, m->y0, &g);
    if (J->chord) {
        J->I1 = (J->nK >= 0 && m->einv[J->nK] > 0) ? g.a2 / m->einv[J->nK] : HUGE_VAL;
        J->I2 = m->einv[J->nL] > 0 ? g.b2 / m->einv[J->nL] : HUGE_VAL;
    } else {
        J->I1 = (J->nI >= 0 && m->rinv[J->nI] > 0) ? m->rinertia[J->nI] : HUGE_VAL;
        J->I2 = m->rinv[J->nJ] > 0 ? m->rinertia[J->nJ] : HUGE_VAL;
        J->off = d->angle0 - m->phi0[J->nJ] + (J->nI >= 0 ? m->phi0[J->nI] : 0.0);
    }
    if (!rj__finite(J->I1)) {
        J->w1 = 0;
        J->w2 = 1;
    } else if (!rj__finite(J->I2)) {
        J->w1 = 1;
        J->w2 = 0;
    } else {
        J->w1 = J->I2 / (J->I1 + J->I2);
        J->w2 = J->I1 / (J->I1 + J->I2);
    }
}

/* A joint's limits on the running angle. Both enabled: the free arc runs counter-clockwise
   from reverse to forward; a start inside the limited arc counts as past the nearer limit.
   One limit (a wall): the reverse limit is the largest theta_r + 2 pi k <= angle0 + pi/2,
   the forward limit the smallest theta_f + 2 pi k >= angle0 - pi/2, so a start up to
   90 deg past it counts as penetrated. */
static void rj__init_running_limits(const rj_joint_def *d, rj__joint *J)
{
    if (d->has_forward && d->has_reverse) {
        const double free_arc = rj__mod2pi(d->forward - d->reverse);
        const double past_reverse = rj__mod2pi(d->angle0 - d->reverse);
        if (past_reverse <= free_arc) {
            J->rev = d->angle0 - past_reverse;
            J->fwd = J->rev + free_arc;
        } else if (past_reverse - free_arc <= RJ__TWO_PI - past_reverse) {
            J->fwd = d->angle0 - (past_reverse - free_arc);
            J->rev = J->fwd - free_arc;
        } else {
            J->rev = d->angle0 + (RJ__TWO_PI - past_reverse);
            J->fwd = J->rev + free_arc;
        }
        return;
    }
    J->fwd = HUGE_VAL;
    J->rev = -HUGE_VAL;
    if (d->has_reverse)
        J->rev =
            d->reverse + RJ__TWO_PI * floor((d->angle0 + 0.5 * RJ__PI - d->reverse) / RJ__TWO_PI);
    if (d->has_forward)
        J->fwd =
            d->forward + RJ__TWO_PI * ceil((d->angle0 - 0.5 * RJ__PI - d->forward) / RJ__TWO_PI);
}

/* The steepest the torque table gets anywhere (N m/rad): at each rising segment, the sum
   of the slopes of every rising segment that overlaps it (later runs add, Eq 4). */
static double rj__table_stiffness(const rj_joint_def *d)
{
    const double *angle = d->table_angle, *torque = d->table_torque;
    double steepest = 0;
    int k, k2;
    for (k = 0; k + 1 < d->table_count; k++) {
        double slopes = 0;
        if (!(angle[k + 1] > angle[k]))
            continue;
        for (k2 = 0; k2 + 1 < d->table_count; k2++) {
            if (!(angle[k2 + 1] > angle[k2]))
                continue;
            if (angle[k2 + 1] < angle[k] || angle[k2] > angle[k + 1])
                continue;
            slopes += fabs((torque[k2 + 1] - torque[k2]) / (angle[k2 + 1] - angle[k2]));
        }
        if (slopes > steepest)
            steepest = slopes;
    }
    return steepest;
}

/* A DC motor's cutoff on the running angle: its first crossing from angle0 in the
   direction the motor drives (angle0 itself when they are the same angle). */
static double rj__running_cutoff(const rj_actuator_def *a, double angle0)
{
    const double ahead = rj__mod2pi(a->cutoff - angle0);
    if (a->no_load_speed > 0)
        return angle0 + ahead;
    return ahead == 0 ? angle0 : angle0 - (RJ__TWO_PI - ahead);
}

/* An actuator on its joint: the joint keeps it; a servo's gain is a spring and its
   damping, like a DC motor's slope, a damper to the stability bound; a cutoff on the
   running angle. */
static void rj__init_actuator(rj_model *m, const rj_actuator_def *a)
{
    rj__joint *J = &m->jnt[a->joint];
    J->act = a;
    J->rotor = a->gear_ratio * a->gear_ratio * a->rotor_inertia;
    if (a->type != RJ_ACTUATOR_TORQUE && a->profile == RJ_PROFILE_TABLE) {
        double *M = m->spl + (size_t) (a - m->act) * RJ_TABLE_MAX, work[RJ_TABLE_MAX];
        rj__spline_build(a->table_count, a->table_time, a->table_factor, M, work);
        J->spline = M;
    }
    m->nrotor += J->rotor > 0;
    m->npres += a->type == RJ_ACTUATOR_PRESCRIBED;
    /* a prescribed joint is a row, but between two rigid bodies a torque */
    m->nmotion += a->type == RJ_ACTUATOR_PRESCRIBED && !J->pair;
    if (a->type == RJ_ACTUATOR_SERVO) {
        J->k_lin += a->kp;
        J->c_lin += a->kd;
    }
    if (a->type == RJ_ACTUATOR_DC) {
        J->c_lin += a->stall_torque / a->no_load_speed;
        if (a->has_cutoff)
            J->cut = rj__running_cutoff(a, m->jdef[a->joint].angle0);
    }
}

/* Every joint's constants: inertias, limits on the running angle, the table's potential
   over a turn, and the linear stiffness of its spring and table (limits come later); its
   actuator. */
static void rj__init_joint_constants(rj_model *m)
{
    int j, k;
    m->nchord = 0;
    for (j = 0; j < m->nj; j++) {
        const rj_joint_def *d = &m->jdef[j];
        rj__joint *J = &m->jnt[j];
        rj__init_joint_inertias(m, j);
        m->nchord += J->chord;
        rj__init_running_limits(d, J);
        J->tv_turn = d->table_count ? rj__table_potential(d->table_angle, d->table_torque,
                                                          d->table_count, RJ__TWO_PI)
                                    : 0.0;
        J->k_lin = d->spring_k + rj__table_stiffness(d);
        J->k_limit = 0;
        J->c_lin = d->damping;
        J->act = NULL;
        J->cut = HUGE_VAL;
        J->rotor = 0;
        J->spline = NULL;
    }
    for (k = 0; k < m->nact; k++)
        rj__init_actuator(m, &m->act[k]);
}

/* Inextensible links: the chains SHAKE solves (links joined tip to root form one). */
static void rj__init_inextensible(rj_model *m, int *scratch)
{
    int l;
    for (l = 0; l < m->nl; l++)
        if (m->ldef[l].fidelity == RJ_LINK_INEXTENSIBLE)
            m->any_inext = 1;
    if (!m->any_inext)
        return;
    rj__inext_chains(m, scratch);
    rj__gs_build(m, m->lz);
}

/* Rigid scenes: each link as a body (rod plus tip mass): its mass, the distance of its
   centre of mass from the root, and its inertia about that centre. */
static void rj__init_rigid_bodies(rj_model *m)
{
    int l;
    for (l = 0; l < m->nl; l++) {
        const rj_link_def *d = &m->ldef[l];
        const double A = rj__plain_area(d);
        const double rod = d->rho * A * d->length;
        const double total = rod + d->tip_mass;
        const double dc = (rod * 0.5 * d->length + d->tip_mass * d->length) / total;
        m->rb_mass[l] = total;
        m->rb_dcm[l] = dc;
        m->rb_icm[l] = rod * d->length * d->length / 12.0 +
                       rod * (0.5 * d->length - dc) * (0.5 * d->length - dc) +
                       d->tip_mass * (d->length - dc) * (d->length - dc) + d->tip_inertia;
        m->rb_pjoint[l] = -1;
    }
}

/* Rigid scenes: each link's joint to its parent, and each joint's pin along body 1 with
   the reference direction there (pi at a node past the root: I->K points back). */
static void rj__init_rigid_pins(rj_model *m)
{
    int j;
    for (j = 0; j < m->nj; j++) {
        const rj_joint_def *d = &m->jdef[j];
        if (!m->jnt[j].loop)
            m->rb_pjoint[d->body2] = j;
        if (d->body1 >= 0) {
            const int pin = d->node1 < 0 ? m->ldef[d->body1].elements : d->node1;
            m->jpin[j] = pin * m->link_l0[d->body1];
            m->jref[j] = pin > 0 ? RJ__PI : 0.0;
        } else {
            m->jpin[j] = 0;
            m->jref[j] = 0;
        }
    }
}

/* Rigid scenes: the tree's joints in an order with parents before children (the
   kinematics run down the tree): passes in joint order, each placing the joints whose
   parent joint is placed. is_placed: nj ints of scratch (a list search made a chain of
   10 000 links take 0.55e9 instructions here). */
static void rj__init_joint_order(rj_model *m, int *is_placed)
{
    int placed = 0, pass, j;
    for (j = 0; j < m->nj; j++)
        is_placed[j] = 0;
    for (pass = 0; placed < m->nq && pass <= m->nj; pass++)
        for (j = 0; j < m->nj; j++) {
            const int b1 = m->jdef[j].body1;
            const int parent = b1 >= 0 ? m->rb_pjoint[b1] : -1;
            const int done = m->jnt[j].loop || is_placed[j];
            const int ready = parent < 0 || is_placed[parent];
            if (!done && ready) {
                m->jorder[placed++] = j;
                is_placed[j] = 1;
            }
        }
}

/* Whether joint j of a rigid scene can open a row in a step (rj__rig_rows_build): a
   prescribed joint's profile, or a latch of a velocity-level method (a lock or a plastic
   contact), which needs a limit to reach (a flag other than free). */
static int rj__rig_can_row(const rj_model *m, int j)
{
    const rj_joint_def *d = &m->jdef[j];
    const rj_actuator_def *a = m->jnt[j].act;
    const int velocity_level = d->method == RJ_METHOD_MOMENTUM || d->method == RJ_METHOD_FORCED;
    if (a && a->type == RJ_ACTUATOR_PRESCRIBED)
        return 1;
    return velocity_level && (d->has_forward || d->has_reverse);
}

/* The most rows a rigid step opens, which size its system (S and SL, rows x rows): one
   per joint that can open one (tree or loop joint), one per exact coupling, and two per
   loop (its pins' gap in x and y). The loops' projection opens fewer: the two per loop
   and one per forced loop joint at a limit. */
static int rj__rig_rows_max(const rj_model *m)
{
    int j, rows = m->nexact + 2 * m->nloop;
    for (j = 0; j < m->nj; j++)
        rows += rj__rig_can_row(m, j);
    return rows;
}

/* The columns of M^-1 a rigid step keeps (W): for a dense M, one per coordinate (a loop's
   latch row may be any coordinate's rate alone). Articulated bodies (a tree without
   couplings) keep those of the joints that can open a row, which their impulses and rows
   read after friction made them (stage 3): k such joints keep k n doubles. Friction on a
   joint that cannot spends its column at once (rj__rig_stage_friction). */
static void rj__init_rigid_columns(rj_model *m)
{
    int k;
    m->nwcol = 0;
    for (k = 0; k < m->nq; k++) {
        const int kept = !m->rig_tree || rj__rig_can_row(m, m->qj[k]);
        m->wcol[k] = kept ? m->nwcol++ : -1;
    }
    m->rig_rows = rj__rig_rows_max(m);
}

/* Links held by constraints: SHAKE's inextensible chains, and in a scene of rigid links
   alone (joint coordinates) the bodies, pins and joint order, the solver (a dense M or
   articulated bodies, as rj_model_size counted its scratch) and the columns and rows its
   step keeps. */
static void rj__init_rigid(rj_model *m, const rj_scene_def *sc, int *chain_scratch)
{
    m->rigid = rj__all_rigid(sc);
    rj__init_inextensible(m, chain_scratch);
    if (!m->rigid)
        return;
    rj__init_rigid_bodies(m);
    rj__init_rigid_pins(m);
    rj__init_joint_order(m, chain_scratch);
    m->rig_tree = rj__rig_is_tree(m->nq, m->nloop, m->ncp);
    RJ_ASSERT(m->rig_tree == rj__scene_rig_tree(sc));
    rj__init_rigid_columns(m);
}

/* omega_max^2 at the stiffnesses in m->jnt: power iteration in joint coordinates for
   rigid scenes (it also sets each joint's 1/I_red, J->minv), Lanczos otherwise. */
static double rj__bound_omega2(rj_model *m, const rj__build_scratch *s)
{
    return m->rigid ? rj__rig_setup(m, s->rigid_bound) : rj__omega2_max(m, s->lanczos);
}

/* omega_max and the stability bound from omega_max^2; returns it. */
static double rj__set_bound(rj_model *m, double om2, double damp_rate)
{
    m->omega_max = rj__omega_of(om2);
    m->dt_bound = rj__dt_bound_of(m->omega_max, damp_rate);
    return om2;
}

/* omega_max and the stability bound at the stiffnesses in m->jnt; returns omega_max^2. */
static double rj__init_bound(rj_model *m, const rj__build_scratch *s, double damp_rate)
{
    return rj__set_bound(m, rj__bound_omega2(m, s), damp_rate);
}

/* What the search for the step carries: dt depends on K_AP and K_AP on dt. */
typedef struct rj__dt_search {
    double damp_rate;       /* the fastest joint damping rate, 1/s */
    double om2_no_adaptive; /* omega_max^2 without the adaptive limits */
    double dt;              /* the step under test */
} rj__dt_search;

/* A penalty limit switches on and off with the contact, which pumps energy long before the
   linear bound: measured on the impact benchmark, RC13 contact blows up at omega dt = 1.67
   where the same spring always on is stable. Counting it as 4 K keeps omega dt <= 1, where
   switching was never seen to pump. Returns whether any joint has adaptive limits;
   *counted: whether any penalty limit changed a stiffness. */
static int rj__count_penalty_limits(rj_model *m, int *counted)
{
    int j, any_adaptive = 0;
    *counted = 0;
    for (j = 0; j < m->nj; j++) {
        const rj_joint_def *d = &m->jdef[j];
        const int limited = d->has_forward || d->has_reverse;
        if (limited && d->method == RJ_METHOD_PENALTY && d->penalty_k != 0) {
            m->jnt[j].k_lin += 4.0 * d->penalty_k;
            *counted = 1;
        }
        if (limited && d->method == RJ_METHOD_ADAPTIVE)
            any_adaptive = 1;
    }
    return any_adaptive;
}

/* Eq 21's K_AP = I_red / dt^2 for joint J: I_red the joint's own effective inertia
   1 / (M^-1)_jj in rigid scenes, the two bodies' own between two rigid bodies of a
   mixed scene (rj__pair_free_give), else the two sides' (I1, I2). */
static double rj__adaptive_k(const rj_model *m, const rj__joint *J, double dt)
{
    if (m->rigid)
        return 1.0 / (J->minv * dt * dt);
    if (J->pair)
        return 1.0 / (rj__pair_free_give(m, J) * dt * dt);
    return rj_k_adaptive(J->I1, J->I2, dt);
}

/* The adaptive limits' K_AP at the step under test (rigid: the joint's own effective
   inertia 1 / (M^-1)_jj, Eq 21 for two free bodies), counted twice in k_lin. */
static void rj__count_adaptive_limits(rj_model *m, const rj__dt_search *q)
{
    const double dt = q->dt;
    int j;
    for (j = 0; j < m->nj; j++) {
        const rj_joint_def *d = &m->jdef[j];
        rj__joint *J = &m->jnt[j];
        if (!(d->has_forward || d->has_reverse) || d->method != RJ_METHOD_ADAPTIVE)
            continue;
        J->k_limit = rj__adaptive_k(m, J, dt);
        J->k_lin = J->k_free + 2.0 * J->k_limit;
    }
}

/* The step whose 0.9 x bound holds with omega^2(dt) ~ a + b / dt^2 (a: without the
   adaptive limits, b from this pass) and the joints' damping rate d: with c = 0.9 x 2 x
   margin, the bound dt (d/2 + sqrt(omega^2 + d^2/4)) <= c (rj__dt_bound_of) is
   a dt^2 + c d dt + b - c^2 <= 0, whose positive root is the step; b < c^2. */
static double rj__adaptive_dt_root(double a, double b, double d, double c, double dt_now)
{
    const double room = c * c - b;
    if (a > 0)
        return 2.0 * room / (c * d + sqrt(c * c * d * d + 4.0 * a * room));
    if (d > 0)
        return room / (c * d);
    return dt_now;
}

/* The next step to test. K_AP = I_red / dt^2: omega dt of the adaptive limits does not
   fall with dt, so when they alone are above the bound no step is stable: refused; so is
   a search that has not settled in its passes, with what it reached. */
static int rj__next_adaptive_dt(rj_model *m, rj__dt_search *q, double om2, int pass, rj_error *err)
{
    const double c = 0.9 * RJ__DT_MARGIN * 2.0;
    const double b = (om2 - q->om2_no_adaptive) * q->dt * q->dt;
    if (b >= c * c) {
        rj__fail(err, RJ_ERR_UNSTABLE_DT, "solver.dt", q->dt,
                 "no stable step for the adaptive limits: their stiffness K_AP (Eq 21) "
                 "grows as 1/dt^2, so their omega dt, %.3g with the limits counted as in "
                 "the bound, is the same at every dt and not below the %.3g the automatic "
                 "step allows; use RJ_METHOD_MOMENTUM (or penalty with a fixed K) for these "
                 "joints%s",
                 sqrt(b), c, m->rigid ? ", as rigid links usually want" : "");
        return 0;
    }
    if (pass == 19) {
        rj__fail(err, RJ_ERR_UNSTABLE_DT, "solver.dt", q->dt,
                 "no stable step found for the adaptive limits: after 20 passes the step "
                 "%.4g s is still above 0.9 x its bound %.4g s (the adaptive limits' omega "
                 "dt %.3g, the joints' damping rate %.4g 1/s); give solver.dt below the "
                 "bound with solver.allow_unstable, or use RJ_METHOD_MOMENTUM for these "
                 "joints",
                 q->dt, m->dt_bound, sqrt(b), q->damp_rate);
        return 0;
    }
    /* a step that small always has a bound at least as large: never go past it */
    q->dt = rj__adaptive_dt_root(q->om2_no_adaptive, b, q->damp_rate, c, q->dt);
    if (q->dt > 0.9 * m->dt_bound)
        q->dt = 0.9 * m->dt_bound;
    /* where omega^2 is not a + b / dt^2 (a cable loop and a latch on the same pins) the
       root creeps down on the bound from above (42 % of the gap a pass): from the fifth
       pass, 2 % below it each pass, so a step a few per cent under the best is found */
    if (pass >= 4)
        q->dt *= 0.98;
    return 1;
}

/* Adaptive limits: K_AP = I_red/dt^2 gives omega dt = 1 on its own. Contact chatter near
   the links' bound pumps energy with it too (stress suite: RC13 impacts blew up at 0.95 x
   the bound with K_AP counted once), so it counts twice; K_AP grows as dt shrinks, so the
   automatic dt is searched (rj__next_adaptive_dt); each pass checks the step it settles
   on. A given dt is taken as it is, with its bound. */
static int rj__search_adaptive_dt(rj_model *m, const rj_scene_def *sc, const rj__build_scratch *s,
                                  rj__dt_search *q, rj_error *err)
{
    const int passes = sc->solver.dt > 0 ? 1 : 20;
    int pass;
    for (pass = 0; pass < passes; pass++) {
        double om2;
        rj__count_adaptive_limits(m, q);
        om2 = rj__init_bound(m, s, q->damp_rate);
        if (sc->solver.dt > 0 || q->dt <= 0.9 * m->dt_bound * 1.000001)
            break;
        if (!rj__next_adaptive_dt(m, q, om2, pass, err))
            return 0;
    }
    return 1;
}

/* The limits' stiffness in use: a penalty limit's K, an adaptive limit's K_AP at dt. */
static void rj__init_limit_stiffness(rj_model *m, double dt)
{
    int j;
    for (j = 0; j < m->nj; j++) {
        const rj_joint_def *d = &m->jdef[j];
        rj__joint *J = &m->jnt[j];
        if (d->method == RJ_METHOD_PENALTY)
            J->k_limit = d->penalty_k;
        if (d->method == RJ_METHOD_ADAPTIVE)
            J->k_limit = rj__adaptive_k(m, J, dt);
    }
}

/* Rigid scenes without stiff joints: no stiffness bounds the step, so it is 1 ms at most,
   and 0.004 of the time a link takes to swing under gravity, sqrt(l / g), for the shortest
   link (measured on the two-link strip with its adaptive latch under 1e4 and 1e5 m/s^2:
   0.003 of it runs, 0.01 blows up as the latch catches; at 9.81 m/s^2 this binds only
   links under 0.6 m). */
static double rj__rigid_dt_cap(const rj_model *m)
{
    const double g = sqrt(m->solver.gravity[0] * m->solver.gravity[0] +
                          m->solver.gravity[1] * m->solver.gravity[1]);
    double cap = 1e-3, shortest = HUGE_VAL;
    int l;
    for (l = 0; l < m->nl; l++)
        if (m->ldef[l].length < shortest)
            shortest = m->ldef[l].length;
    if (g > 0 && 0.004 * sqrt(shortest / g) < cap)
        cap = 0.004 * sqrt(shortest / g);
    return cap;
}

/* The fastest damping rate 2 zeta omega that the links' structural damping on lagged
   rates gives a mode: eta omega^2 + mass_damping, at the links' omega_max (a mode's rate
   is its Rayleigh quotient, at most each part's largest: eta's at the stiffest mode).
   Implicit eta (src/viscous.h) needs no shorter step. */
static double rj__structural_rate(const rj_model *m)
{
    double rate = 0;
    int l;
    for (l = 0; l < m->nl; l++) {
        const double *damp = RJ__LD(m, l);
        const double r = damp[RJ__LD_LAGGED] * m->omega_links * m->omega_links +
                         damp[RJ__LD_MASS];
        if (r > rate)
            rate = r;
    }
    return rate;
}

/* A warning when the links' structural damping shortens their bound ten times or more:
   eta acts on every mode at eta omega / 2, the stiffest (an element's axial mode) too. */
static void rj__structural_warning(rj_model *m)
{
    const double plain = rj__dt_bound_of(m->omega_links, 0);
    const double damped = rj__dt_bound_of(m->omega_links, m->struct_rate);
    if (!(m->struct_rate > 0) || !(damped * 10 <= plain))
        return;
    rj__model_warn(m,
                   "structural damping shortens the links' stability bound %.3g times "
                   "(%.3g s to %.3g s): eta damps every mode at eta omega / 2, the stiffest "
                   "(omega_max %.4g rad/s) at %.3g of critical; mass_damping costs no step",
                   plain / damped, plain, damped, m->omega_links,
                   0.5 * m->struct_rate / m->omega_links);
}

/* Stability: omega_max of beams + springs + tables alone (kept for the refusal's advice),
   then with the limits counted; joint damping acts on the rates it lags (Eq 27 on
   v^{n-1/2}): it shortens the step, as the links' structural damping does (on the same
   rates), by dt <= (2 / omega) (sqrt(1 + zeta^2) - zeta) with 2 zeta omega both rates'
   sum. The step: solver.dt, or 0.9 x the bound (rigid scenes
   without stiff joints are not bounded: 1 ms at most), searched with adaptive limits. */
static rj_result rj__init_step(rj_model *m, const rj_scene_def *sc, const rj__build_scratch *s,
                               rj_error *err)
{
    rj__dt_search q;
    int j, any_adaptive, penalty_counted;
    double om2, om2_links;
    for (j = 0; j < m->nj; j++)
        m->jnt[j].k_free = m->jnt[j].k_lin;
    om2_links = rj__bound_omega2(m, s);
    m->omega_links = rj__omega_of(om2_links);
    m->struct_rate = rj__structural_rate(m);
    q.damp_rate = rj__damping_rate(m) + m->struct_rate;
    rj__structural_warning(m);
    any_adaptive = rj__count_penalty_limits(m, &penalty_counted);
    /* the same stiffnesses give the same omega_max: computed again only when they moved */
    if (penalty_counted)
        om2 = rj__init_bound(m, s, q.damp_rate);
    else
        om2 = rj__set_bound(m, om2_links, q.damp_rate);
    q.dt = sc->solver.dt > 0 ? sc->solver.dt : 0.9 * m->dt_bound;
    if (m->rigid && sc->solver.dt <= 0) {
        const double cap = rj__rigid_dt_cap(m);
        if (q.dt > cap)
            q.dt = cap;
    }
    q.om2_no_adaptive = om2;
    if (any_adaptive && !rj__search_adaptive_dt(m, sc, s, &q, err))
        return RJ_ERR_UNSTABLE_DT;
    rj__init_limit_stiffness(m, q.dt);
    m->dt = q.dt;
    return RJ_OK;
}

/* The joint whose stiffness on its own gives the highest omega = sqrt(k_lin c) at the
   start (c: 1/I_red), with that omega and c; -1 when none gives more than 0. */
static int rj__stiffest_joint(const rj_model *m, double *omega, double *compliance)
{
    int j, worst = -1;
    *omega = 0;
    *compliance = 0;
    for (j = 0; j < m->nj; j++) {
        const double c = rj__joint_compliance0(m, j);
        const double om = sqrt(m->jnt[j].k_lin * c);
        if (om > *omega) {
            *omega = om;
            worst = j;
            *compliance = c;
        }
    }
    return worst;
}

/* The advice a step above the bound gets: what the stiffest joint's limit admits when it
   alone is above omega dt = 1, or the links' own bound when they alone are above it. */
static void rj__unstable_dt_advice(const rj_model *m, int worst, double omega, double compliance,
                                   char *extra, size_t size)
{
    extra[0] = 0;
    if (worst >= 0 && omega * m->dt > 1.0) {
        const double room = (RJ__DT_MARGIN * 2.0 / m->dt) * (RJ__DT_MARGIN * 2.0 / m->dt) -
                            m->omega_links * m->omega_links;
        /* what this bound admits for a penalty limit (counted 4 K, added to the links'
           omega^2) */
        const double k_ok = room > 0 ? room / (4.0 * compliance) : 0.0;
        if (m->jdef[worst].method == RJ_METHOD_ADAPTIVE)
            snprintf(extra, size,
                     "; joint %d's adaptive limit gives about omega dt = %.3g, and its K_AP "
                     "(Eq 21) grows as 1/dt^2, so a smaller dt helps little: "
                     "solver.dt = 0 finds the largest stable step if there is one, or use "
                     "RJ_METHOD_MOMENTUM%s",
                     worst, omega * m->dt, m->rigid ? " (rigid links)" : " or a penalty K");
        else if (room > 0 && !m->rigid)
            snprintf(extra, size,
                     "; joint %d's stiffness gives omega dt = %.3g: this model accepts a "
                     "penalty K up to about %.4g N m/rad at this dt (Eq 31 would give %.4g)",
                     worst, omega * m->dt, k_ok, rj_joint_kmax_eq31(m, worst, m->dt));
        else if (room > 0)
            snprintf(extra, size,
                     "; joint %d's stiffness gives omega dt = %.3g: this model accepts a "
                     "penalty K up to about %.4g N m/rad at this dt",
                     worst, omega * m->dt, k_ok);
    }
    if (m->omega_links > 0 && m->dt > rj__dt_bound_of(m->omega_links, m->struct_rate))
        snprintf(extra, size, "; the links alone need dt <= %.4g s%s",
                 rj__dt_bound_of(m->omega_links, m->struct_rate),
                 m->struct_rate > 0 ? " with their structural damping (eta omega_max^2 + "
                                      "mass_damping, the rate it gives the stiffest mode)"
                                    : "");
}

/* A given step above the bound is refused (unless solver.allow_unstable), naming the
   stiffest joint when a joint, not a link, sets the bound. */
static rj_result rj__refuse_unstable_dt(const rj_model *m, rj_error *err)
{
    double omega, compliance;
    char extra[240];
    const int worst = rj__stiffest_joint(m, &omega, &compliance);
    const int adaptive_worst =
        worst >= 0 && omega * m->dt > 1.0 && m->jdef[worst].method == RJ_METHOD_ADAPTIVE;
    rj__unstable_dt_advice(m, worst, omega, compliance, extra, sizeof extra);
    rj__fail(err, RJ_ERR_UNSTABLE_DT, "solver.dt", m->dt,
             "solver.dt = %.9g s is above the stability bound %.9g s (omega_max %g rad/s)%s; %s",
             m->dt, m->dt_bound, m->omega_max, extra,
             adaptive_worst ? "or set solver.allow_unstable"
                            : "use a smaller dt or set solver.allow_unstable");
    return RJ_ERR_UNSTABLE_DT;
}

/* The step in use must be stable (unless solver.allow_unstable) and usable: a bound or a
   step that is not a finite positive number leaves nothing to run, nor does a start that
   is not finite. */
static rj_result rj__check_step(const rj_model *m, const rj_scene_def *sc, rj_error *err)
{
    if (m->dt > m->dt_bound && !sc->solver.allow_unstable)
        return rj__refuse_unstable_dt(m, err);
    if (!rj__usable_step(m, err))
        return RJ_ERR_INVALID;
    return RJ_OK;
}

/* Eq 28 over the whole model: the shortest element wave transit l0 / c. */
static void rj__init_dt_eq28(rj_model *m)
{
    int l;
    m->dt_eq28 = HUGE_VAL;
    for (l = 0; l < m->nl; l++) {
        const double wave_speed = sqrt(m->ldef[l].E / m->ldef[l].rho);
        const double transit = m->link_l0[l] / wave_speed;
        if (transit < m->dt_eq28)
            m->dt_eq28 = transit;
    }
}

/* The nodes the step advances again after the joints, once each and in ascending order:
   every node a joint or an applied load acts on, rigid links' nodes (their bodies move
   them), and every link's end nodes (tip masses: not the link's uniform values). mark
   (nn ints) keeps which they are for rj__init_link_uniform. */
static void rj__init_step_nodes(rj_model *m, int *mark)
{
    int i, j, l, k;
    m->ndn = 0;
    for (i = 0; i < m->nn; i++)
        mark[i] = 0;
    for (j = 0; j < m->nj; j++) {
        const rj__joint *J = &m->jnt[j];
        const int nodes[4] = { J->nI, J->nJ, J->chord ? J->nK : -1, J->chord ? J->nL : -1 };
        for (k = 0; k < 4; k++)
            if (nodes[k] >= 0)
                mark[nodes[k]] = 1;
    }
    for (k = 0; k < m->nload; k++)
        mark[m->load_node[k]] = 1;
    for (l = 0; l < m->nl; l++) {
        const int n0 = m->link_first[l], ne_l = m->ldef[l].elements;
        if (m->ldef[l].fidelity == RJ_LINK_RIGID)
            for (k = n0; k <= n0 + ne_l; k++)
                mark[k] = 1;
        mark[n0 + ne_l] = 1;
        mark[n0] = 1;
    }
    for (i = 0; i < m->nn; i++)
        if (mark[i])
            m->dnode[m->ndn++] = i;
    m->dn_inner = 0;
    for (l = 0; l < m->nl; l++) {
        const int n0 = m->link_first[l], ne_l = m->ldef[l].elements;
        if (m->ldef[l].fidelity != RJ_LINK_RIGID)
            for (k = n0 + 1; k < n0 + ne_l; k++)
                if (mark[k])
                    m->dn_inner = 1;
    }
}

/* A link whose other (unmarked) nodes share their inverse masses and energy weights
   (uniform sections: all of them) lets the fused pass read four numbers instead of four
   arrays: tinv, rinv, kmass, krot, and 1 when they all agree. */
static void rj__init_link_uniform(rj_model *m, const int *mark)
{
    int l, k;
    for (l = 0; l < m->nl; l++) {
        const int n0 = m->link_first[l], ne_l = m->ldef[l].elements;
        double *u = m->link_un + 5 * l;
        int first = 1, same = 1;
        u[3] = 0;
        u[2] = 0;
        u[1] = 0;
        u[0] = 0;
        for (k = n0; k <= n0 + ne_l; k++) {
            if (mark[k])
                continue;
            if (first) {
                u[0] = m->tinv[k];
                u[1] = m->rinv[k];
                u[2] = m->kmass[k];
                u[3] = m->krot[k];
                first = 0;
            } else if (!(u[0] == m->tinv[k] && u[1] == m->rinv[k] && u[2] == m->kmass[k] &&
                         u[3] == m->krot[k]))
                same = 0;
        }
        u[4] = same;
    }
}

/* A frame's size: nodes, elements (beta, chords), joints, scalars, then the clusters'
   records and the yielding layers' plastic strains; and its flags, one per joint. */
static void rj__init_frames(rj_model *m)
{
    m->frame_doubles =
        6 * (size_t) m->nn + 3 * (size_t) m->ne + RJ__JD_COUNT * (size_t) m->nj + RJ__FS_COUNT;
    m->cl_off = m->frame_doubles;
    m->frame_doubles += 6 * (size_t) m->ncl;
    m->pl_off = m->frame_doubles;
    m->frame_doubles += m->npl;
    m->frame_ints = (size_t) m->nj;
}

/* Kelvin-Voigt damping taken implicitly (src/viscous.h) on every damped link but those a
   rigid body carries a node of (their pins move with the body, which the link's solve
   does not see): those keep it on the lagged rates, which their bound counts. */
static void rj__init_viscous(rj_model *m)
{
    int l, n;
    m->nvisc = 0;
    m->visc_nodes = 0;
    for (l = 0; l < m->nl; l++) {
        double *damp = RJ__LD(m, l);
        const int nodes = m->link_first[l + 1] - m->link_first[l];
        int carried = 0;
        if (!(damp[RJ__LD_LAGGED] > 0))
            continue;
        for (n = m->link_first[l]; n < m->link_first[l + 1] && m->ncl; n++)
            carried |= m->node_cl[n] >= 0;
        if (carried)
            continue;
        damp[RJ__LD_IMPLICIT] = damp[RJ__LD_LAGGED];
        damp[RJ__LD_LAGGED] = 0;
        m->nvisc++;
        if (nodes > m->visc_nodes)
            m->visc_nodes = nodes;
    }
    m->applied = m->nload > 0 || m->nvisc > 0;
}

/* The link of node n when its Kelvin-Voigt damping is implicit, else -1. */
static int rj__visc_link_of(const rj_model *m, int n)
{
    int link, node;
    if (n < 0)
        return -1;
    rj__node_of(m, n, &link, &node);
    return RJ__LD(m, link)[RJ__LD_IMPLICIT] > 0 ? link : -1;
}

/* The damped links joint j's solve holds (rj__visc_hold): those of its pin nodes (lJ -1
   where both are on one link); none for a chord-referenced joint or one between two
   bodies. */
static void rj__visc_joint_links(const rj_model *m, int j, int *lI, int *lJ)
{
    const rj__joint *J = &m->jnt[j];
    *lI = *lJ = -1;
    if (J->chord || J->pair)
        return;
    *lI = rj__visc_link_of(m, J->nI);
    *lJ = rj__visc_link_of(m, J->nJ);
    if (*lJ == *lI)
        *lJ = -1;
}

/* Each damped link's joints for its solve to hold, in joint order: a count a link, the
   runs, then each joint into its links' runs. The step walked every joint for every
   link. */
static void rj__init_visc_holds(rj_model *m)
{
    int *first = m->visc_first, j, l, lI, lJ;
    for (l = 0; l <= m->nl; l++)
        first[l] = 0;
    for (j = 0; j < m->nj && m->nvisc; j++) {
        rj__visc_joint_links(m, j, &lI, &lJ);
        first[lI + 1] += lI >= 0;
        first[lJ + 1] += lJ >= 0;
    }
    for (l = 0; l < m->nl; l++)
        first[l + 1] += first[l];
    /* first[l] is now where link l's run ends as it fills */
    for (j = 0; j < m->nj && m->nvisc; j++) {
        rj__visc_joint_links(m, j, &lI, &lJ);
        if (lI >= 0)
            m->visc_joint[first[lI]++] = j;
        if (lJ >= 0)
            m->visc_joint[first[lJ]++] = j;
    }
    for (l = m->nl; l > 0; l--)
        first[l] = first[l - 1];
    first[0] = 0;
}

/* In place: not with inextensible links (SHAKE reads every node at n), and only if every
   node of a pin group or a rigid body is one the step keeps (m->dnode: it is). */
static void rj__init_in_place(rj_model *m)
{
    int i, q;
    /* not with inextensible links or pins between bodies (their projections read every
       node at n), nor with implicit damping (its power, every damped node's v^{n-1/2}) */
    m->project = m->any_inext || m->nbp;
    m->ip = !m->rigid && !m->project && !m->nvisc && m->solver.in_place != RJ_IN_PLACE_OFF &&
            (m->solver.in_place == RJ_IN_PLACE_ON || m->nn >= RJ_IN_PLACE_NODES);
    for (i = 0; i < m->ng && m->ip; i++)
        for (q = m->grp_first[i]; q < m->grp_first[i + 1]; q++)
            if (!rj__is_dnode(m, m->grp_node[q]))
                m->ip = 0;
    for (i = 0; i < m->ncl && m->ip; i++)
        for (q = m->cl_first[i]; q < m->cl_first[i + 1]; q++)
            if (!rj__is_dnode(m, m->cl_node[q]))
                m->ip = 0;
}

/* The model, phase by phase. A refusal returns at the first error, the checks in their
   order: arguments and fields (unless validated: rj_model_size has just checked them),
   the joint graph, the links' numbers, the step. */
static rj_result rj__model_init(const rj_scene_def *sc, void *mem, size_t size, rj_model **out,
                                int validated, rj_error *err)
{
    rj__layout L;
    rj__build_scratch s;
    rj_model *m;
    size_t nodes, elements;
    rj_result r =
        rj__init_check_args(sc, mem, size, out, &nodes, &elements, &L, validated, err);
    if (r != RJ_OK)
        return r;
    m = rj__init_block(sc, mem, &L, nodes, elements);
    rj__init_arrays(m, &L);
    rj__build_scratch_carve(m, &s);
    if (!rj__validate_graph(sc, s.graph, err))
        return RJ_ERR_INVALID;
    rj__init_copy_defs(m, sc);
    rj__init_links(m);
    rj__init_load_nodes(m);
    if (!rj__check_links(m, err))
        return RJ_ERR_INVALID;
    rj__init_joint_nodes(m);
    rj__init_pin_groups(m, s.pin_groups);
    rj__init_energy_masses(m);
    rj__init_placement(m, s.placement);
    rj__init_chord_angles(m);
    if (!rj__init_clusters(m, sc, err))
        return RJ_ERR_INVALID;
    rj__init_viscous(m);
    rj__init_joint_constants(m);
    rj__init_visc_holds(m);
    rj__init_rigid(m, sc, s.chains);
    rj__limit_warnings(m);
    r = rj__init_step(m, sc, &s, err);
    if (r != RJ_OK)
        return r;
    r = rj__check_step(m, sc, err);
    if (r != RJ_OK)
        return r;
    rj__init_dt_eq28(m);
    rj__init_step_nodes(m, s.step_node_mark);
    rj__init_link_uniform(m, s.step_node_mark);
    rj__init_frames(m);
    rj__init_in_place(m);
    m->hash = rj__model_hash(m);
    *out = m;
    return RJ_OK;
}

RJDEF rj_result rj_model_init(const rj_scene_def *sc, void *mem, size_t size, rj_model **out,
                              rj_error *err)
{
    return rj__model_init(sc, mem, size, out, 0, err);
}

RJDEF rj_result rj_model_create(const rj_scene_def *scene, rj_model **out, rj_error *err,
                                void *alloc_ctx)
{
    size_t sz;
    void *mem;
    rj_result r;
    rj_error size_err;
    (void) alloc_ctx;
    if (!out) {
        rj__fail(err, RJ_ERR_INVALID, "out", 0, "out is NULL");
        return RJ_ERR_INVALID;
    }
    sz = rj_model_size(scene, err ? err : &size_err);
    if (!sz)
        return err ? err->code : size_err.code;
    mem = RJ_MALLOC(sz, alloc_ctx);
    if (!mem) {
        rj__fail(err, RJ_ERR_NOMEM, "size", (double) sz, "could not allocate %lu bytes",
                 (unsigned long) sz);
        return RJ_ERR_NOMEM;
    }
    /* rj_model_size has just validated the scene */
    r = rj__model_init(scene, mem, sz, out, 1, err);
    if (r != RJ_OK) {
        RJ_FREE(mem, alloc_ctx);
        return r;
    }
    /* remember the raw pointer for free: the model sits at the aligned start of mem */
    if ((void *) *out != mem) {
        /* alignment moved the start; keep it simple: allocators return 16-aligned blocks */
        RJ_FREE(mem, alloc_ctx);
        rj__fail(err, RJ_ERR_NOMEM, "size", 0,
                 "RJ_MALLOC returned a block not aligned to 16 bytes");
        *out = NULL;
        return RJ_ERR_NOMEM;
    }
    return RJ_OK;
}

RJDEF void rj_model_destroy(rj_model *m, void *alloc_ctx)
{
    (void) alloc_ctx;
    if (m)
        RJ_FREE(m, alloc_ctx);
}

/* ------------------------------------------------------------------ states */
typedef struct rj__slayout {
    size_t total, fd0, fd1, fd2, fi0, fi1, fi2, fx, fy, mz, kn, damp, visc, visc_force, peaks,
        peak_work, sha, shb, shc, shr, shp, gsw, bpw, eu, ebt, jsc,
        rsc, rows, terms, rsys, input_torque, input_node, node_applied, snap_torque, loop_force;
} rj__slayout;

/* The doubles of a state's peaks (rj_state.peaks). */
static size_t rj__peaks_count(const rj_model *m)
{
    return RJ__PEAK_JOINT * (size_t) m->nj + RJ__PEAK_LINK * (size_t) m->nl;
}

/* No peak yet: each value -1 (a magnitude is >= 0), its time, element and end -1. */
static void rj__peaks_clear(const rj_model *m, rj_state *s)
{
    size_t k;
    for (k = 0; k < rj__peaks_count(m); k++)
        s->peaks[k] = -1;
}

static void rj__state_layout(const rj_model *m, rj__slayout *L)
{
    size_t off = sizeof(rj_state);
    L->fd0 = rj__carve(&off, m->frame_doubles, sizeof(double));
    L->fd1 = rj__carve(&off, m->frame_doubles, sizeof(double));
    L->fi0 = rj__carve(&off, m->frame_ints + 1, sizeof(int));
    L->fi1 = rj__carve(&off, m->frame_ints + 1, sizeof(int));
    L->fd2 = rj__carve(&off, m->ip ? m->frame_doubles : 0, sizeof(double));
    L->fi2 = rj__carve(&off, m->ip ? m->frame_ints + 1 : 0, sizeof(int));
    L->fx = rj__carve(&off, (size_t) m->nn, sizeof(double));
    L->fy = rj__carve(&off, (size_t) m->nn, sizeof(double));
    L->mz = rj__carve(&off, (size_t) m->nn, sizeof(double));
    L->kn = rj__carve(&off, (size_t) m->nn, sizeof(double));
    L->damp = rj__carve(&off, m->nmaterial ? 3 * (size_t) m->nn + 2 : 0, sizeof(double));
    L->visc = rj__carve(&off, m->nvisc ? RJ__VISC_PER * ((size_t) m->visc_nodes + 1) : 0,
                        sizeof(double));
    L->visc_force = rj__carve(&off, m->nvisc ? 4 * (size_t) m->ne : 0, sizeof(double));
    L->peaks = rj__carve(&off, rj__peaks_count(m) + 1, sizeof(double));
    L->peak_work = rj__carve(&off,
                             RJ__PIN_PER_LINK * ((size_t) m->nl + 1) + 2 * (size_t) m->nj + 1,
                             sizeof(double));
    L->sha = rj__carve(&off, m->any_inext ? (size_t) m->ne : 0, sizeof(double));
    L->shb = rj__carve(&off, m->any_inext ? (size_t) m->ne : 0, sizeof(double));
    L->shc = rj__carve(&off, m->any_inext ? (size_t) m->ne : 0, sizeof(double));
    L->shr = rj__carve(&off, m->any_inext ? (size_t) m->ne : 0, sizeof(double));
    /* with loops: SHAKE's pushes over the step, for the loop joints' records */
    L->shp = rj__carve(&off, m->any_inext && m->nloop ? 2 * (size_t) m->nn : 0, sizeof(double));
    L->gsw = rj__carve(&off,
                       m->gs_n ? 2 * m->gs_prof + 9 * (size_t) m->gs_n + 2 * (size_t) m->nn : 0,
                       sizeof(double));
    L->bpw = rj__carve(&off,
                       m->nbp ? 8 * (size_t) m->nbp * (size_t) m->nbp + 4 * (size_t) m->nbp +
                                    3 * (size_t) m->ncl + (m->nloop ? 2 * (size_t) m->nbp : 0)
                              : 0,
                       sizeof(double));
    L->eu = rj__carve(&off, (size_t) m->ne, sizeof(double));
    L->ebt = rj__carve(&off, (size_t) m->ne, sizeof(double));
    L->jsc = rj__carve(&off, (size_t) m->nj * 8 + 1, sizeof(double));
    L->rsc = rj__carve(&off, m->rigid ? rj__rig_step_scratch(m) : 3 * (size_t) m->ncl + 1,
                       sizeof(double));
    /* rigid scenes: the rows their joints, couplings and loops can open (rj_model.rig_rows);
       a loop's two rows name every coordinate at most */
    L->rows = rj__carve(&off,
                        m->rigid ? (size_t) m->rig_rows + 1
                                 : (size_t) rj__rows_capacity(m->nj, m->ncp + m->nloop),
                        sizeof(rj__row));
    /* a loop's two rows and its joint's latch or profile row name every coordinate at
       most (4 nq with one spare), and so may a coupling on a loop joint, twice when both
       its joints close loops */
    L->terms = rj__carve(&off,
                         (size_t) rj__terms_capacity(m->nj, m->ncp) +
                             4 * (size_t) m->nloop * (size_t) m->nq +
                             (m->nloop ? 2 * (size_t) m->ncp * (size_t) m->nq : 0),
                         sizeof(rj__term));
    L->rsys = rj__carve(&off, 2 * (size_t) m->nmotion * (size_t) (m->nmotion + 1) + 1,
                        sizeof(double));
    L->loop_force = rj__carve(&off, 2 * (size_t) m->nj + 1, sizeof(double));
    L->input_torque = rj__carve(&off, (size_t) m->nj + 1, sizeof(double));
    L->snap_torque = rj__carve(&off, (size_t) m->nj + 1, sizeof(double));
    L->input_node = rj__carve(&off, 3 * (size_t) m->nn, sizeof(double));
    L->node_applied = rj__carve(&off, 3 * (size_t) m->nn, sizeof(double));
    L->total = off == (size_t) -1 ? off : off + RJ__ALIGN;
}

RJDEF size_t rj_state_size(const rj_model *m)
{
    rj__slayout L;
    RJ_ASSERT(m);
    rj__state_layout(m, &L);
    return L.total;
}

/* frame accessors */
#define RJ__FX(m, f)    ((f) + RJ__FS_COUNT)
#define RJ__FY(m, f)    ((f) + RJ__FS_COUNT + (m)->nn)
#define RJ__FPHI(m, f)  ((f) + RJ__FS_COUNT + 2 * (size_t) (m)->nn)
#define RJ__FVX(m, f)   ((f) + RJ__FS_COUNT + 3 * (size_t) (m)->nn)
#define RJ__FVY(m, f)   ((f) + RJ__FS_COUNT + 4 * (size_t) (m)->nn)
#define RJ__FW(m, f)    ((f) + RJ__FS_COUNT + 5 * (size_t) (m)->nn)
#define RJ__FBETA(m, f) ((f) + RJ__FS_COUNT + 6 * (size_t) (m)->nn)
#define RJ__FCX(m, f)   ((f) + RJ__FS_COUNT + 6 * (size_t) (m)->nn + (m)->ne)
#define RJ__FCY(m, f)   ((f) + RJ__FS_COUNT + 6 * (size_t) (m)->nn + 2 * (size_t) (m)->ne)
#define RJ__FJ(m, f, j)                                                                            \
    ((f) + RJ__FS_COUNT + 6 * (size_t) (m)->nn + 3 * (size_t) (m)->ne + RJ__JD_COUNT * (size_t) (j))
#define RJ__FS(m, f) (f)

/* One joint's spring and table potentials at the running angle run, added to *V (spring
   first, then table: every caller sums in this order, so the totals agree to the bit); the
   table's torque goes to *table_torque. */
static void rj__joint_potential(const rj_joint_def *d, const rj__joint *J, double run, double *V,
                                double *table_torque)
{
    *table_torque = 0;
    if (d->spring_k > 0)
        *V += 0.5 * d->spring_k * (run - d->spring_free_angle) * (run - d->spring_free_angle);
    if (d->table_count)
        *V += rj__table_turns_potential(d, J, run, table_torque);
}

static double rj__spring_energy(const rj_model *m, const double *f)
{
    double V = 0, t;
    int j;
    for (j = 0; j < m->nj; j++)
        rj__joint_potential(&m->jdef[j], &m->jnt[j], RJ__FJ(m, f, j)[RJ__JD_THETA], &V, &t);
    for (j = 0; j < m->ncp; j++) {
        const rj_coupling_def *c = &m->cp[j];
        double elastic, damp;
        rj__coupling_torques(m, c, RJ__FJ(m, f, c->joint_a)[RJ__JD_THETA],
                             RJ__FJ(m, f, c->joint_b)[RJ__JD_THETA], 0, 0, &elastic, &damp, &V);
    }
    return V;
}

RJDEF void rj_state_reset(const rj_model *m, rj_state *s)
{
    double *f = s->fd[0], *sc;
    int j, i;
    s->cur = 0;
    s->steps = 0;
    s->loop_force[2 * m->nj] = -1;
    memset(s->input_torque, 0, sizeof(double) * (size_t) m->nj);
    s->inputs = 0;
    memset(s->input_node, 0, 3 * sizeof(double) * (size_t) m->nn);
    memset(s->node_applied, 0, 3 * sizeof(double) * (size_t) m->nn);
    s->node_inputs = 0;
    s->settle_scale = 0;
    s->snap = -1;
    s->err[0] = 0;
    s->warn[0] = 0;
    s->at_n = RJ__AT_N_NONE;
    s->peaks_on = 0;
    rj__peaks_clear(m, s);
    memset(s->fd[0], 0, sizeof(double) * m->frame_doubles);
    memset(s->fd[1], 0, sizeof(double) * m->frame_doubles);
    memset(s->fi[0], 0, sizeof(int) * (m->frame_ints + 1));
    memset(s->fi[1], 0, sizeof(int) * (m->frame_ints + 1));
    memcpy(RJ__FX(m, f), m->x0, sizeof(double) * (size_t) m->nn);
    memcpy(RJ__FY(m, f), m->y0, sizeof(double) * (size_t) m->nn);
    memcpy(RJ__FPHI(m, f), m->phi0, sizeof(double) * (size_t) m->nn);
    memcpy(RJ__FVX(m, f), m->vx0, sizeof(double) * (size_t) m->nn);
    memcpy(RJ__FVY(m, f), m->vy0, sizeof(double) * (size_t) m->nn);
    memcpy(RJ__FW(m, f), m->w0, sizeof(double) * (size_t) m->nn);
    memcpy(RJ__FBETA(m, f), m->beta0, sizeof(double) * (size_t) m->ne);
    for (i = 0; i < m->nl; i++) {
        int k;
        for (k = m->link_efirst[i]; k < m->link_efirst[i + 1]; k++) {
            int a = m->link_first[i] + (k - m->link_efirst[i]);
            RJ__FCX(m, f)[k] = m->x0[a + 1] - m->x0[a];
            RJ__FCY(m, f)[k] = m->y0[a + 1] - m->y0[a];
        }
    }
    for (j = 0; j < m->nj; j++) {
        double *jd = RJ__FJ(m, f, j);
        rj__jgeo g;
        rj__joint_geo(m, &m->jnt[j], m->x0, m->y0, &g);
        jd[RJ__JD_THETA] = m->jdef[j].angle0;
        jd[RJ__JD_RATE] = m->rigid
                              ? m->jdef[j].rate0
                              : rj__joint_rate(&m->jnt[j], &g, m->vx0, m->vy0, m->w0, NULL, NULL);
        jd[RJ__JD_EVENT] = -1;
        jd[RJ__JD_RELEASE] = -1;
        jd[RJ__JD_ZONE_LO] = RJ__NO_ZONE;
        jd[RJ__JD_ZONE_HI] = -RJ__NO_ZONE;
        jd[RJ__JD_BAND] = RJ__NO_ZONE;
        jd[RJ__JD_OVERLAP] = -1;
    }
    if (m->rigid) {
        /* nodes from the joint-coordinate kinematics, so that both descriptions agree */
        rj__rig r;
        rj__rig_map(m, s->rsc, &r, 1);
        for (j = 0; j < m->nq; j++) {
            r.q[j] = m->jdef[m->qj[j]].angle0;
            r.qd[j] = m->jdef[m->qj[j]].rate0;
        }
        /* a loop joint turns at the rate its loop gives it (g . q') */
        for (j = 0; j < m->nj && m->nloop; j++)
            if (m->jq[j] < 0)
                RJ__FJ(m, f, j)[RJ__JD_RATE] = rj__rig_loop_rate(m, j, r.qd, r.tmp);
        rj__rig_kin(m, &r, r.q, r.qd, r.qd);
        rj__rig_nodes(m, &r, f);
    }
    sc = RJ__FS(m, f);
    {
        double ke = 0, U;
        for (i = 0; i < m->nn; i++)
            ke += 0.5 * m->mass[i] * (m->vx0[i] * m->vx0[i] + m->vy0[i] * m->vy0[i]) *
                      (m->einv[i] > 0) +
                  0.5 * m->rinertia[i] * m->w0[i] * m->w0[i] *
                      (m->rinv[i] > 0 && !RJ__CL_RIGID(m, i));
        for (i = 0; i < m->ncl; i++) {
            /* rigid bodies: anchor, its velocity, rate, angle */
            double *c = RJ__FCL(m, f, i);
            const int n0 = m->link_first[i];
            if (m->cl_first[i] == m->cl_first[i + 1])
                continue;
            c[0] = m->x0[n0] - m->cl_rx[n0];
            c[1] = m->y0[n0] - m->cl_ry[n0];
            c[2] = m->cl_th0[3 * i + 1];
            c[3] = m->cl_th0[3 * i + 2];
            c[4] = m->w0[n0];
            c[5] = m->cl_th0[3 * i];
            ke += 0.5 * m->cl_M[i] * (c[2] * c[2] + c[3] * c[3]) * (m->cl_fix[i] == 0) +
                  0.5 * m->cl_I[i] * c[4] * c[4];
        }
        double *o = s->fd[1]; /* scratch for the chords, cleared again below */
        U = rj__beam_pass(m, m->x0, m->y0, m->phi0, m->beta0, RJ__FCX(m, f), RJ__FCY(m, f), s->eu,
                          s->ebt, RJ__FCX(m, o), RJ__FCY(m, o), s->fx, s->fy, s->mz, NULL);
        memset(o, 0, sizeof(double) * m->frame_doubles);
        sc[RJ__FS_KE] = ke;
        sc[RJ__FS_STRAIN] = U;
        sc[RJ__FS_SPRING] = rj__spring_energy(m, f);
        sc[RJ__FS_GRAV] = rj__gravity_potential(m, RJ__FX(m, f), RJ__FY(m, f));
        sc[RJ__FS_E0] = ke + U + sc[RJ__FS_SPRING] + sc[RJ__FS_GRAV];
    }
}

RJDEF rj_result rj_state_init(const rj_model *m, void *mem, size_t size, rj_state **out)
{
    rj__slayout L;
    rj_state *s;
    char *base;
    if (!m || !out)
        return RJ_ERR_INVALID;
    rj__state_layout(m, &L);
    if (!mem || size < L.total)
        return RJ_ERR_NOMEM;
    base = (char *) mem;
    base += (RJ__ALIGN - ((size_t) base % RJ__ALIGN)) % RJ__ALIGN;
    memset(base, 0, L.total - RJ__ALIGN);
    s = (rj_state *) (void *) base;
    s->bytes = L.total - RJ__ALIGN;
    s->fd[0] = (double *) (void *) (base + L.fd0);
    s->fd[1] = (double *) (void *) (base + L.fd1);
    s->fi[0] = (int *) (void *) (base + L.fi0);
    s->fi[1] = (int *) (void *) (base + L.fi1);
    s->fd[2] = m->ip ? (double *) (void *) (base + L.fd2) : NULL;
    s->fi[2] = m->ip ? (int *) (void *) (base + L.fi2) : NULL;
    s->fx = (double *) (void *) (base + L.fx);
    s->fy = (double *) (void *) (base + L.fy);
    s->mz = (double *) (void *) (base + L.mz);
    s->sha = (double *) (void *) (base + L.sha);
    s->shb = (double *) (void *) (base + L.shb);
    s->shc = (double *) (void *) (base + L.shc);
    s->shr = (double *) (void *) (base + L.shr);
    s->shp = (double *) (void *) (base + L.shp);
    s->gsw = (double *) (void *) (base + L.gsw);
    s->bpw = (double *) (void *) (base + L.bpw);
    s->eu = (double *) (void *) (base + L.eu);
    s->ebt = (double *) (void *) (base + L.ebt);
    s->kn = (double *) (void *) (base + L.kn);
    s->damp = (double *) (void *) (base + L.damp);
    s->visc = (double *) (void *) (base + L.visc);
    s->visc_force = (double *) (void *) (base + L.visc_force);
    s->peaks = (double *) (void *) (base + L.peaks);
    s->peak_work = (double *) (void *) (base + L.peak_work);
    s->jsc = (double *) (void *) (base + L.jsc);
    s->rsc = (double *) (void *) (base + L.rsc);
    s->rows = (rj__row *) (void *) (base + L.rows);
    s->terms = (rj__term *) (void *) (base + L.terms);
    s->rsys = (double *) (void *) (base + L.rsys);
    s->loop_force = (double *) (void *) (base + L.loop_force);
    s->input_torque = (double *) (void *) (base + L.input_torque);
    s->snap_torque = (double *) (void *) (base + L.snap_torque);
    s->input_node = (double *) (void *) (base + L.input_node);
    s->node_applied = (double *) (void *) (base + L.node_applied);
    rj_state_reset(m, s);
    *out = s;
    return RJ_OK;
}

RJDEF rj_result rj_state_create(const rj_model *m, rj_state **out, void *alloc_ctx)
{
    size_t sz;
    void *mem;
    rj_result r;
    (void) alloc_ctx;
    if (!m || !out)
        return RJ_ERR_INVALID;
    sz = rj_state_size(m);
    mem = RJ_MALLOC(sz, alloc_ctx);
    if (!mem)
        return RJ_ERR_NOMEM;
    r = rj_state_init(m, mem, sz, out);
    if (r != RJ_OK || (void *) *out != mem) {
        RJ_FREE(mem, alloc_ctx);
        *out = NULL;
        return r != RJ_OK ? r : RJ_ERR_NOMEM;
    }
    return RJ_OK;
}

RJDEF void rj_state_destroy(rj_state *s, void *alloc_ctx)
{
    (void) alloc_ctx;
    if (s)
        RJ_FREE(s, alloc_ctx);
}

RJDEF rj_result rj_state_copy(const rj_model *m, rj_state *dst, const rj_state *src)
{
    if (!m || !dst || !src)
        return RJ_ERR_INVALID;
    memcpy(dst->fd[0], src->fd[src->cur], sizeof(double) * m->frame_doubles);
    memcpy(dst->fi[0], src->fi[src->cur], sizeof(int) * (m->frame_ints + 1));
    /* the state a step before too, for the loads at t^n (rj_joint_pin_force) */
    memcpy(dst->fd[1], src->fd[1 - src->cur], sizeof(double) * m->frame_doubles);
    memcpy(dst->fi[1], src->fi[1 - src->cur], sizeof(int) * (m->frame_ints + 1));
    dst->at_n = src->at_n;
    /* in place, the nodes' values at n the step kept, and their forces */
    if (src->at_n == RJ__AT_N_KEPT) {
        memcpy(dst->fd[2], src->fd[2], sizeof(double) * m->frame_doubles);
        memcpy(dst->fx, src->fx, sizeof(double) * (size_t) m->nn);
        memcpy(dst->fy, src->fy, sizeof(double) * (size_t) m->nn);
    }
    /* the implicit damping's element forces of that step (the loads at t^n) */
    if (m->nvisc)
        memcpy(dst->visc_force, src->visc_force, sizeof(double) * 4 * (size_t) m->ne);
    dst->peaks_on = src->peaks_on;
    memcpy(dst->peaks, src->peaks, sizeof(double) * rj__peaks_count(m));
    dst->cur = 0;
    dst->steps = src->steps;
    /* the loops' pin forces of the step that led here */
    memcpy(dst->loop_force, src->loop_force, sizeof(double) * (2 * (size_t) m->nj + 1));
    dst->snap = -1;
    memcpy(dst->input_torque, src->input_torque, sizeof(double) * (size_t) m->nj);
    dst->inputs = src->inputs;
    memcpy(dst->input_node, src->input_node, 3 * sizeof(double) * (size_t) m->nn);
    memcpy(dst->node_applied, src->node_applied, 3 * sizeof(double) * (size_t) m->nn);
    dst->node_inputs = src->node_inputs;
    dst->settle_scale = 0;
    memcpy(dst->err, src->err, sizeof dst->err);
    memcpy(dst->warn, src->warn, sizeof dst->warn);
    return RJ_OK;
}

/* ------------------------------------------------------------------ a failed step: its message */
static rj_result rj__stop(const rj_model *m, rj_state *s, rj_result r, const char *fmt, ...)
{
    va_list ap;
    int wanted;
    (void) m;
    va_start(ap, fmt);
    wanted = vsnprintf(s->err, sizeof s->err, fmt, ap);
    va_end(ap);
    rj__fit_words(s->err, sizeof s->err, wanted);
    return r;
}

/* Where a rigid scene's blow-up shows: the fastest joint of the new frame and its
   rotation per step. In joint coordinates no stiffness bounds the step; the step's energy
   error is second order in dt, and grows where a long chain whips or folds on itself (its
   mass matrix nears singular), which no bound foresees. */
static void rj__rig_fastest(const rj_model *m, const rj_state *s, char *where, size_t size)
{
    const double *next = s->fd[1 - s->cur];
    double fastest = 0;
    int j, worst = -1;
    for (j = 0; j < m->nj; j++) {
        const double rate = fabs(RJ__FJ(m, next, j)[RJ__JD_RATE]);
        if (rate > fastest) {
            fastest = rate;
            worst = j;
        }
    }
    if (worst < 0 || !rj__finite(fastest)) {
        snprintf(where, size, "rigid links in joint coordinates");
        return;
    }
    snprintf(where, size,
             "rigid links in joint coordinates (fastest joint %d at %.4g rad/s, %.3g rad a "
             "step): the step's energy error is second order in dt (half the step, a quarter "
             "of the error) and grows as a long chain whips or folds; a smaller solver.dt, "
             "or inextensible links for a chain of many",
             worst, fastest, fastest * m->dt);
}

/* The causes of a blow-up that this model can have, for the step's messages: only what
   the model holds (a step above the bound, loads whose work is most of the energy in
   motion, limits and how they respond, stiff joints), else what every model has (fast
   rotation, which the linearised bound leaves out). */
static const char *rj__blowup_causes(const rj_model *m, int applied, double work, double moving,
                                     char *buf, size_t size)
{
    int j, stiff_limit = 0, velocity_limit = 0, springs = 0;
    if (m->dt > m->dt_bound)
        return "the step is above the stability bound: use a smaller solver.dt, or 0 for the "
               "automatic step";
    /* loads and the caller's inputs whose work is most of the energy in motion */
    if (applied && fabs(work) > 0.5 * moving && work == work) {
        snprintf(buf, size,
                 "the applied loads and the caller's torques and forces (%.3g J of work): "
                 "loads that large move the model faster than its step can follow",
                 -work);
        return buf;
    }
    for (j = 0; j < m->nj; j++) {
        const rj_joint_def *d = &m->jdef[j];
        const int limits = d->has_forward || d->has_reverse;
        if (limits && (d->method == RJ_METHOD_PENALTY || d->method == RJ_METHOD_ADAPTIVE))
            stiff_limit = 1;
        if (limits && d->method != RJ_METHOD_PENALTY && d->method != RJ_METHOD_ADAPTIVE)
            velocity_limit = 1;
        if (d->spring_k > 0 || d->table_count > 0)
            springs = 1;
    }
    buf[0] = 0;
    if (applied)
        rj__cat(buf, size,
                "the applied loads or the caller's torques and forces, if they move a node "
                "farther in a step than its elements can follow; ");
    if (stiff_limit)
        rj__cat(buf, size,
                "a penalty or adaptive limit caught late (it stores about the relative kinetic "
                "energy when it catches a joint a rate x dt past its limit): RJ_METHOD_MOMENTUM "
                "catches it without a stiffness; ");
    if (velocity_limit)
        rj__cat(buf, size, "contact chatter at a limit; ");
    if (springs)
        rj__cat(buf, size, "a joint spring or table stiffer than the bound counts (Eq 31); ");
    rj__cat(buf, size,
            "fast rotation (its centrifugal and Coriolis terms are not in the linearised bound): a "
            "smaller solver.dt");
    return buf;
}

/* Names the node with the largest speed in the new frame, for blow-up reports. */
static void rj__worst_node(const rj_model *m, const double *f, int *link, int *node)
{
    const double *vx = RJ__FVX(m, f), *vy = RJ__FVY(m, f);
    double best = -1;
    int i, worst = 0;
    for (i = 0; i < m->nn; i++) {
        double v = vx[i] * vx[i] + vy[i] * vy[i];
        if (!(v <= best)) {
            best = v;
            worst = i;
            if (!(v == v))
                break;
        }
    }
    rj__node_of(m, worst, link, node);
}

/* A step that wrote a non-finite value stops, naming the first such node (or joint). */
static rj_result rj__stop_nonfinite(const rj_model *m, rj_state *s, const double *f, double t)
{
    const double *v[6];
    int i, k, link, node;
    v[0] = RJ__FX(m, f);
    v[1] = RJ__FY(m, f);
    v[2] = RJ__FPHI(m, f);
    v[3] = RJ__FVX(m, f);
    v[4] = RJ__FVY(m, f);
    v[5] = RJ__FW(m, f);
    for (i = 0; i < m->nn; i++)
        for (k = 0; k < 6; k++)
            if (!rj__finite(v[k][i])) {
                const char *what = k == 0   ? "x"
                                   : k == 1 ? "y"
                                   : k == 2 ? "rotation"
                                   : k == 3 ? "x velocity"
                                   : k == 4 ? "y velocity"
                                            : "rotation rate";
                rj__node_of(m, i, &link, &node);
                return rj__stop(
                    m, s, RJ_ERR_BLOWUP,
                    "t = %.9g s: link %d node %d's %s became %g: the state is no longer finite%s",
                    t, link, node, what, v[k][i],
                    m->dt > m->dt_bound ? " (the step is above the stability bound)" : "");
            }
    return rj__stop(m, s, RJ_ERR_BLOWUP,
                    "t = %.9g s: a joint's angle, rate or torque, or a rigid body's motion, became "
                    "non-finite%s",
                    t, m->dt > m->dt_bound ? " (the step is above the stability bound)" : "");
}

/* ------------------------------------------------------------------ SHAKE: inextensible links */
/* Inextensible links: SHAKE. After the position update, Newton iterations on the element
   length constraints |x_{i+1} - x_i|^2 = l0^2 with corrections along the previous chords
   e_i^n, dx_k = 2 w_k (lambda_{k-1} e_{k-1}^n - lambda_k e_k^n) (w: inverse masses, the
   group's for pinned nodes), give a tridiagonal system per chain (Thomas algorithm); links
   joined tip to root form one chain. Velocities follow the corrected positions. */
/* SHAKE weight of a node: its inverse mass, or for a node on a rigid body the body's
   inverse mass seen at that point along the element direction (ux, uy). */
static double rj__shake_w(const rj_model *m, const rj_state *s, int k, const double *nx,
                          const double *ny, double ux, double uy)
{
    const int c = m->ncl ? m->node_cl[k] : -1;
    const double *nc;
    double rx, ry, cr, u2;
    if (c < 0)
        return m->einv[k];
    if (m->cl_fix[c] == 2)
        return 0.0;
    nc = RJ__FCL(m, s->fd[1 - s->cur], c);
    rx = nx[k] - nc[0];
    ry = ny[k] - nc[1];
    cr = rx * uy - ry * ux;
    u2 = ux * ux + uy * uy;
    return (m->cl_fix[c] == 0 ? 1.0 / m->cl_M[c] : 0.0) + cr * cr / (u2 * m->cl_I[c]);
}

/* With loops: a chain's pushes lambda_i e_i^n into shp by each element's second node,
   summed over the iterations (as rj__gs_track; the chords at n as the update takes them). */
static void rj__shake_track(const int *nd, int ne, const double *lam, const double *x,
                            const double *y, double *shp)
{
    int i;
    for (i = 0; i < ne; i++) {
        shp[2 * nd[i + 1]] += lam[i] * (x[nd[i + 1]] - x[nd[i]]);
        shp[2 * nd[i + 1] + 1] += lam[i] * (y[nd[i + 1]] - y[nd[i]]);
    }
}

static void rj__shake(const rj_model *m, rj_state *s, const double *x, const double *y,
                             double *nx, double *ny)
{
    /* element scratch (ne >= chain elements): the factored tridiagonal (multipliers a,
       reciprocal pivots b, upper c), the residuals r, the multipliers lam */
    double *a = s->sha, *b = s->shb, *c = s->shc, *r = s->shr, *lam = s->eu;
    double *nf = s->fd[1 - s->cur], *imp = s->rsc,
           *act = s->ebt; /* act: 1 for an element that can move, 0 between two fixed nodes */
    const double dt = m->dt;
    int ch, it, i, q, gi;
    if (m->nloop)
        memset(s->shp, 0, 2 * sizeof(double) * (size_t) m->nn);
    if (m->gs_n)
        rj__shake_graph(m, s, x, y, nx, ny);
    for (ch = 0; ch < m->nch; ch++) {
        const int *nd = m->ch_node + m->ch_first[ch],
                  ne = m->ch_first[ch + 1] - m->ch_first[ch] - 1;
        const double *l0sq = m->ch_l0sq + m->ch_first[ch];
        int bodies = 0;
        if (m->ncl)
            for (i = 0; i <= ne; i++)
                bodies |= m->node_cl[nd[i]] >= 0 &&
                          m->cl_fix[m->node_cl[nd[i]]] != 2; /* a held body is a fixed node */
        for (i = 0; i < ne; i++) {
            const int k = nd[i], k1 = nd[i + 1];
            act[i] =
                (bodies
                     ? rj__shake_w(m, s, k, nx, ny, 1, 0) + rj__shake_w(m, s, k, nx, ny, 0, 1) +
                           rj__shake_w(m, s, k1, nx, ny, 1, 0) + rj__shake_w(m, s, k1, nx, ny, 0, 1)
                     : m->einv[k] + m->einv[k1]) > 0
                    ? 1.0
                    : 0.0;
        }
        /* (the loops carry a node's position or an element's chord on to the next element
           instead of loading and subtracting it again: the same values) */
        for (it = 0; it < (bodies ? 12 : 4); it++) {
            double worst = 0, px = nx[nd[0]], py = ny[nd[0]], hx = 0,
                   hy = 0; /* hx, hy: the update's old chord i - 1 */
            for (i = 0; i < ne; i++) {
                const double qx = nx[nd[i + 1]], qy = ny[nd[i + 1]];
                const double ex = qx - px, ey = qy - py,
                             g = (ex * ex + ey * ey - l0sq[i + 1]) * act[i];
                if (fabs(g) > worst * l0sq[i + 1])
                    worst = fabs(g) / l0sq[i + 1];
                r[i] = -g;
                px = qx;
                py = qy;
            }
            if (worst < 1e-14)
                break;
            if (it == 0) {
                /* the Newton matrix of the first iteration serves the later ones: it
                   changes with the chords by the size of the correction (about 1e-8) */
                double pox = 0, poy = 0, ox = x[nd[1]] - x[nd[0]],
                       oy = y[nd[1]] - y[nd[0]]; /* old chords i - 1, i */
                for (i = 0; i < ne; i++) {
                    const int k = nd[i], k1 = nd[i + 1];
                    const double ex = nx[k1] - nx[k], ey = ny[k1] - ny[k];
                    const double wi = bodies ? rj__shake_w(m, s, k, nx, ny, ox, oy) : m->einv[k];
                    const double wj = bodies ? rj__shake_w(m, s, k1, nx, ny, ox, oy) : m->einv[k1];
                    double qox = 0, qoy = 0; /* old chord i + 1 */
                    if (i + 1 < ne) {
                        qox = x[nd[i + 2]] - x[k1];
                        qoy = y[nd[i + 2]] - y[k1];
                    }
                    b[i] = 4.0 * (wi + wj) * (ex * ox + ey * oy);
                    a[i] = i > 0 ? -4.0 * wi * (ex * pox + ey * poy) : 0.0;
                    c[i] = i + 1 < ne ? -4.0 * wj * (ex * qox + ey * qoy) : 0.0;
                    if (act[i] == 0) {
                        b[i] = 1.0;
                        a[i] = c[i] = 0.0;
                    } /* an identity row: lam = 0 */
                    pox = ox;
                    poy = oy;
                    ox = qox;
                    oy = qoy;
                }
                b[0] = 1.0 / b[0];
                for (i = 1; i < ne; i++) {
                    a[i] *= b[i - 1];
                    b[i] = 1.0 / (b[i] - a[i] * c[i - 1]);
                }
            }
            for (i = 1; i < ne; i++)
                r[i] -= a[i] * r[i - 1];
            lam[ne - 1] = r[ne - 1] * b[ne - 1];
            for (i = ne - 2; i >= 0; i--)
                lam[i] = (r[i] - c[i] * lam[i + 1]) * b[i];
            if (m->nloop)
                rj__shake_track(nd, ne, lam, x, y, s->shp);
            if (bodies)
                for (q = 0; q < 3 * m->ncl; q++)
                    imp[q] = 0;
            for (i = 0; i <= ne; i++) {
                const int k = nd[i];
                double dx = 0, dy = 0, ox = 0, oy = 0;
                if (i > 0) {
                    dx += lam[i - 1] * hx;
                    dy += lam[i - 1] * hy;
                }
                if (i < ne) {
                    ox = x[nd[i + 1]] - x[k];
                    oy = y[nd[i + 1]] - y[k];
                    dx -= lam[i] * ox;
                    dy -= lam[i] * oy;
                }
                hx = ox;
                hy = oy;
                if (bodies && m->node_cl[k] >= 0) {
                    /* on a body: the body takes the push (mass times displacement 2 dx) */
                    const int cl = m->node_cl[k];
                    const double *nc = RJ__FCL(m, nf, cl);
                    imp[3 * cl] += 2.0 * dx;
                    imp[3 * cl + 1] += 2.0 * dy;
                    imp[3 * cl + 2] += (nx[k] - nc[0]) * 2.0 * dy - (ny[k] - nc[1]) * 2.0 * dx;
                    continue;
                }
                nx[k] += 2.0 * m->einv[k] * dx;
                ny[k] += 2.0 * m->einv[k] * dy;
            }
            if (bodies)
                for (q = 0; q < m->ncl; q++) {
                    double *nc = RJ__FCL(m, nf, q);
                    if (m->cl_first[q] == m->cl_first[q + 1] || m->cl_fix[q] == 2 ||
                        (imp[3 * q] == 0 && imp[3 * q + 1] == 0 && imp[3 * q + 2] == 0))
                        continue;
                    rj__cl_push(m, q, imp + 3 * q, dt, nc);
                    rj__cl_pose(m, q, nc, x, y, dt, 1, nx, ny, RJ__FPHI(m, nf), RJ__FVX(m, nf),
                                RJ__FVY(m, nf), RJ__FW(m, nf));
                }
        }
    }
    /* pins: every member of a group takes the position of the member a chain moved last */
    for (gi = 0; gi < m->ng; gi++) {
        const int f0 = m->grp_first[gi], f1 = m->grp_first[gi + 1];
        int src = m->grp_node[f0];
        for (q = f0; q < f1; q++)
            if (nx[m->grp_node[q]] != nx[src] || ny[m->grp_node[q]] != ny[src]) {
                /* the chain entry is the lowest-index member on an inextensible link */
                int k;
                for (k = f0; k < f1; k++) {
                    int l, on = 0;
                    for (l = 0; l < m->nl; l++)
                        if (m->grp_node[k] >= m->link_first[l] &&
                            m->grp_node[k] < m->link_first[l + 1] &&
                            m->ldef[l].fidelity == RJ_LINK_INEXTENSIBLE)
                            on = 1;
                    if (on) {
                        src = m->grp_node[k];
                        break;
                    }
                }
                break;
            }
        for (q = f0; q < f1; q++) {
            nx[m->grp_node[q]] = nx[src];
            ny[m->grp_node[q]] = ny[src];
        }
    }
}


/* ------------------------------------------------------------------ the joint element */
/* Links do not contact each other: where a joint between two links turns through a
   multiple of 360 deg, its two links lie over each other and pass through. That is
   reported once per joint, as a warning and its time (rj_joint_overlap_time): when the
   angle is clearly (1 deg) inside a band of 360 deg other than the one it was last
   clearly in. A hinge stowed folded at 0 or 360 deg, or vibrating there, has not passed.
   The zone the angle is in (a band's clear inside, or a fold) is kept in the joint's
   record, so that a step costs two comparisons while the angle stays in it. */
#define RJ__OVERLAP_MARGIN 0.0174532925199432958
static void rj__overlap_band(const rj_model *m, rj_state *s, int j, double run, double t,
                             const double *oj, double *nj_, double *nsc)
{
    const double band = floor(run / RJ__TWO_PI);
    const double lo = band * RJ__TWO_PI + RJ__OVERLAP_MARGIN;
    const double hi = (band + 1) * RJ__TWO_PI - RJ__OVERLAP_MARGIN;
    const double last_lo = oj[RJ__JD_BAND];
    /* at a fold: its zone, 1 deg either side, decides nothing */
    if (run < lo || run > hi) {
        const double fold = run < lo ? band * RJ__TWO_PI : (band + 1) * RJ__TWO_PI;
        nj_[RJ__JD_ZONE_LO] = fold - RJ__OVERLAP_MARGIN;
        nj_[RJ__JD_ZONE_HI] = fold + RJ__OVERLAP_MARGIN;
        return;
    }
    nj_[RJ__JD_ZONE_LO] = lo;
    nj_[RJ__JD_ZONE_HI] = hi;
    nj_[RJ__JD_BAND] = lo;
    if (last_lo == RJ__NO_ZONE || last_lo == lo || oj[RJ__JD_OVERLAP] >= 0)
        return;
    nj_[RJ__JD_OVERLAP] = t;
    nsc[RJ__FS_WARN] += 1;
    snprintf(s->warn, sizeof s->warn,
             "t = %.9g s: joint %d turned through %.0f deg: its links %d and %d passed "
             "through each other (links do not contact each other)",
             t, j, rj_deg(lo > last_lo ? lo - RJ__OVERLAP_MARGIN : hi + RJ__OVERLAP_MARGIN),
             m->jdef[j].body1, m->jdef[j].body2);
}
static RJ__FORCE_INLINE void rj__overlap(const rj_model *m, rj_state *s, int j, double run,
                                         double t, const double *oj, double *nj_, double *nsc)
{
    if (run >= oj[RJ__JD_ZONE_LO] && run <= oj[RJ__JD_ZONE_HI])
        return;
    rj__overlap_band(m, s, j, run, t, oj, nj_, nsc);
}

/* A value within +-cap. */
static double rj__clamp(double v, double cap)
{
    return v > cap ? cap : (v < -cap ? -cap : v);
}

/* The torque of joint J's actuator on body 2 at t, the joint at its running angle run
   with the rate damping reads (rj_actuator_def). */
static double rj__drive_torque(const rj_state *s, const rj__joint *J, double run, double rate,
                               double t)
{
    const rj_actuator_def *a = J->act;
    double tq;
    switch (a->type) {
    case RJ_ACTUATOR_TORQUE:
        return a->torque * rj__time_factor(a->table_count, a->table_time, a->table_factor, t);
    case RJ_ACTUATOR_DC:
        /* off at or past the cutoff, in the direction it drives */
        if (a->has_cutoff && (a->no_load_speed > 0 ? run >= J->cut : run <= J->cut))
            return 0;
        tq = a->stall_torque * (1.0 - rate / a->no_load_speed);
        return rj__clamp(tq, fabs(a->stall_torque));
    case RJ_ACTUATOR_SERVO:
        /* its target follows the profile from start (none: ramp 0), held while settling */
        tq = a->kp * (rj__profile_angle(a, J->spline, a->target, s->settling ? a->start : t) -
                      run) -
             a->kd * rate;
        return a->torque_max > 0 ? rj__clamp(tq, a->torque_max) : tq;
    default: /* prescribed: its torque is the impulse that keeps it on its profile */
        return 0;
    }
}

/* The revolute element for one joint and one step, shared by every link model: status
   flag (Eqs 7-13), contact bookkeeping, penetration (Eq 19), and the torques on body 2 from
   the table (Eq 4), the torsion spring, damping (Eq 27) and the penalty / adaptive limit
   (Eq 22). Writes the components into the new frame's joint record (friction is added
   later) and returns the torque to apply now; *p_out receives the penetration. */
static double rj__element(const rj_model *m, rj_state *s, int j, const double *oj, double *nj_,
                          int oflag, int *nflag, double rate, double t, double *nsc, double *p_out,
                          double *v_acc)
{
    const rj_joint_def *d = &m->jdef[j];
    const rj__joint *J = &m->jnt[j];
    const double run = oj[RJ__JD_THETA];
    double tq_table = 0, tq_spring = 0, tq_damp = 0, tq_lim = 0, tq, p = 0;
    const int bf = run >= J->fwd, br = run <= J->rev;
    const int flag = rj_flag_next(oflag, bf, br, rate, d->lock, d->release);
    memcpy(nj_, oj, sizeof(double) * RJ__JD_COUNT);
    nj_[RJ__JD_IMPULSE] = 0; /* a velocity-level latch sets it in this step */
    if (flag == RJ_LOCKED && oflag != RJ_LOCKED)
        nj_[RJ__JD_LOCK] = bf ? J->fwd : J->rev;
    if (flag != RJ_FREE && oj[RJ__JD_EVENT] < 0)
        nj_[RJ__JD_EVENT] = t;
    if (flag != RJ_FREE && oflag == RJ_FREE) {
        /* a new contact: how far past the limit was it caught? */
        double p0 =
            flag == RJ_AT_FORWARD || (flag == RJ_LOCKED && bf) ? J->fwd - run : J->rev - run;
        double width =
            (rj__finite(J->fwd) && rj__finite(J->rev)) ? RJ__TWO_PI - (J->fwd - J->rev) : HUGE_VAL;
        nj_[RJ__JD_P0] = p0;
        if (fabs(p0) > RJ__LATE || fabs(p0) > width) {
            nsc[RJ__FS_WARN] += 1;
            snprintf(s->warn, sizeof s->warn,
                     "t = %.9g s: joint %d caught its limit %.4g rad late%s (rate %.4g rad/s, step "
                     "%.3g s)",
                     t, j, fabs(p0), fabs(p0) > width ? ", past the whole limited range" : "", rate,
                     m->dt);
        }
    }
    if (flag == RJ_FREE && oflag != RJ_FREE)
        nj_[RJ__JD_RELEASE] = t; /* latest release */
    if (d->body1 >= 0)
        rj__overlap(m, s, j, run, t, oj, nj_, nsc);
    *nflag = flag;
    /* Eq 19 penetration */
    if (flag == RJ_AT_FORWARD)
        p = J->fwd - run;
    else if (flag == RJ_AT_REVERSE)
        p = J->rev - run;
    else if (flag == RJ_LOCKED)
        p = nj_[RJ__JD_LOCK] - run;
    if (fabs(p) > nj_[RJ__JD_PEAKP])
        nj_[RJ__JD_PEAKP] = fabs(p);
    /* Eq 4 table, torsion spring, Eq 27 damping (resistive: minus on body 2) */
    { /* the potentials join v_acc as in rj__spring_energy */
        double tt;
        rj__joint_potential(d, J, run, v_acc, &tt);
        if (d->table_count)
            tq_table = -tt;
    }
    if (d->spring_k > 0)
        tq_spring = -d->spring_k * (run - d->spring_free_angle);
    if (d->damping > 0)
        tq_damp = -d->damping * rate;
    /* Eq 22 / penalty: tau_2 = K p while at a limit */
    if (flag != RJ_FREE && (d->method == RJ_METHOD_PENALTY || d->method == RJ_METHOD_ADAPTIVE))
        tq_lim = J->k_limit * p;
    nj_[RJ__JD_TQ0 + RJ_TORQUE_TABLE] = tq_table;
    nj_[RJ__JD_TQ0 + RJ_TORQUE_SPRING] = tq_spring;
    nj_[RJ__JD_TQ0 + RJ_TORQUE_DAMPING] = tq_damp;
    nj_[RJ__JD_TQ0 + RJ_TORQUE_LIMIT] = tq_lim;
    nj_[RJ__JD_TQ0 + RJ_TORQUE_FRICTION] = 0;
    *p_out = p;
    tq = tq_table + tq_spring + tq_damp + tq_lim;
    /* the actuator: its slot stays 0 (copied from the old record) on a joint without */
    if (J->act) {
        const double tq_drive = rj__drive_torque(s, J, run, rate, t);
        nj_[RJ__JD_TQ0 + RJ_TORQUE_DRIVE] = tq_drive;
        tq += tq_drive;
    }
    return tq;
}

/* Coulomb friction: the torque that stops the relative rotation within the step (ratep is
   the rate the step would end with, c the rate change per unit torque), capped at T_f. */
static double rj__friction(double ratep, double c, double tf)
{
    double tau = c > 0 ? -ratep / c : 0;
    return tau > tf ? tf : (tau < -tf ? -tf : tau);
}

/* Is this a velocity-level limit method (a jump in the rates at the limit)? */
static RJ__INLINE int rj__velocity_method(int method)
{
    return method == RJ_METHOD_MOMENTUM || method == RJ_METHOD_ENERGY || method == RJ_METHOD_FORCED;
}

/* Does a velocity-level method act (the rate still points into the limit, or any rate
   while locked)? */
static int rj__into_limit(int flag, double ratep)
{
    return (flag == RJ_AT_FORWARD && ratep > 0) || (flag == RJ_AT_REVERSE && ratep < 0) ||
           (flag == RJ_LOCKED && ratep != 0);
}

/* Work of the joint's non-conservative torques over the step, in the form that matches
   the kinetic energy 1/2 v^{n-1/2}.v^{n+1/2}: dt/2 (tau^n rate^{n-1/2} + tau^{n-1} times the
   previous step's end rate, same geometry). */
static RJ__FORCE_INLINE void rj__element_work(const double *oj, const double *nj_, double rate_m,
                                              double dt, double *ld, double *lf, double *ll)
{
    *ld -= 0.5 * dt *
           (nj_[RJ__JD_TQ0 + RJ_TORQUE_DAMPING] * rate_m +
            oj[RJ__JD_TQ0 + RJ_TORQUE_DAMPING] * oj[RJ__JD_RATE]);
    *lf -= 0.5 * dt *
           (nj_[RJ__JD_TQ0 + RJ_TORQUE_FRICTION] * rate_m +
            oj[RJ__JD_TQ0 + RJ_TORQUE_FRICTION] * oj[RJ__JD_RATE]);
    *ll -= 0.5 * dt *
           (nj_[RJ__JD_TQ0 + RJ_TORQUE_LIMIT] * rate_m +
            oj[RJ__JD_TQ0 + RJ_TORQUE_LIMIT] * oj[RJ__JD_RATE]);
}

/* Whether joint J's angle follows a profile (its actuator is prescribed). */
static RJ__INLINE int rj__prescribed(const rj__joint *J)
{
    return J->act && J->act->type == RJ_ACTUATOR_PRESCRIBED;
}

/* The rate that takes a prescribed joint from its running angle run at t to its profile
   at t + dt (held at its start while rj_settle runs). */
static double rj__prescribed_rate(const rj_model *m, const rj_state *s, int j, double run,
                                  double t, double dt)
{
    const rj_actuator_def *a = m->jnt[j].act;
    const double at = s->settling ? a->start : t + dt;
    return (rj__profile_angle(a, m->jnt[j].spline, m->jdef[j].angle0, at) - run) / dt;
}

/* The work of the joint's actuator over the step, in the form of rj__element_work. */
static RJ__FORCE_INLINE double rj__drive_work(const double *oj, const double *nj_, double rate_m,
                                              double dt)
{
    return 0.5 * dt *
           (nj_[RJ__JD_TQ0 + RJ_TORQUE_DRIVE] * rate_m +
            oj[RJ__JD_TQ0 + RJ_TORQUE_DRIVE] * oj[RJ__JD_RATE]);
}

/* The work of the caller's torque over the step, in the form of rj__element_work. */
static RJ__FORCE_INLINE double rj__input_work(const double *oj, const double *nj_, double rate_m,
                                              double dt)
{
    return 0.5 * dt * (nj_[RJ__JD_INPUT] * rate_m + oj[RJ__JD_INPUT] * oj[RJ__JD_RATE]);
}

/* ------------------------------------------------------------------ articulated bodies */
/* A rigid tree's M(q) x = b in O(n), without M: Featherstone's articulated-body recursion
   in the plane. Each coordinate q_j turns its joint's body 2 (and all that hangs from it)
   about the joint's pin P_j; quantities of that subtree are taken about P_j, on the motion
   (omega, v at P_j):
   - a body's inertia about its pin, with d = c - P and its mass m, centre c, inertia I:
     [[I + m |d|^2, -m d_y, m d_x], [-m d_y, m, 0], [m d_x, 0, m]];
   - moving a child's quantity from its pin to the parent's (r = P_child - P_parent; the
     child's pin moves at v + omega z x r): X = [[1, 0, 0], [-r_y, 1, 0], [r_x, 0, 1]]
     takes the parent's motion to the child's, X^T the child's force (moment about its
     pin, force) to the parent's, X^T A X an inertia.
   The factor (leaves first): IA_j = own_j + sum over children of X^T Ia_k X; U = IA_j s,
   D = s.U + rotor (s = (1, 0, 0): turning about the pin; a motor's rotor adds its
   reflected inertia to the joint's own rate only); Ia_j = IA_j - U U^T / D. A solve: u_j
   = b_j - s.p_j and p_parent += X^T (p_j + U u_j / D) leaves first, then x_j = (u_j -
   U.a_in) / D and a_j = a_in + s x_j, a_in = X a_parent, root first. A product M x runs
   the same tree as inverse dynamics at rest: accelerations root first, forces back. The
   dense path (rj__chol) stays for small trees, where it is cheaper, and for loops and
   cable loops, whose rows and rotors need M. */

/* The coordinate of body 2's parent joint, or -1 when body 1 is the ground or fixed. */
static int rj__ab_parent(const rj_model *m, int j)
{
    const int p = m->jdef[j].body1;
    return p >= 0 && m->rb_pjoint[p] >= 0 ? m->jq[m->rb_pjoint[p]] : -1;
}

/* X^T A X added into B (symmetric 3 x 3, 6 entries), r the arm. */
static void rj__ab_shift_inertia(const double *A, double rx, double ry, double *B)
{
    B[0] += A[0] + ry * ry * A[3] + rx * rx * A[5] - 2.0 * ry * A[1] + 2.0 * rx * A[2] -
            2.0 * rx * ry * A[4];
    B[1] += A[1] - ry * A[3] + rx * A[4];
    B[2] += A[2] - ry * A[4] + rx * A[5];
    B[3] += A[3];
    B[4] += A[4];
    B[5] += A[5];
}

/* A symmetric 3 x 3 (6 entries) times v. */
static void rj__ab_sym_mul(const double *A, const double *v, double *out)
{
    out[0] = A[0] * v[0] + A[1] * v[1] + A[2] * v[2];
    out[1] = A[1] * v[0] + A[3] * v[1] + A[4] * v[2];
    out[2] = A[2] * v[0] + A[4] * v[1] + A[5] * v[2];
}

/* Coordinate k's body's own inertia about its pin, from its own sums (rj__rig_own: mass,
   first moment m (c - P), inertia about P), which also starts its articulated inertia;
   its parent's coordinate and its rotor. Its arm from its parent's pin is written as
   the subtrees are gathered (rj__rig_tree_factor), which take the same difference. */
static void rj__ab_own(const rj_model *m, rj__rig *r, int k, const double *b)
{
    const int j = m->qj[k];
    double *rec = r->ab + RJ__AB_COUNT * (size_t) k;
    double *own = rec + RJ__AB_OWN;
    int i;
    own[0] = b[RJ__RL_SUB_J];
    own[1] = -b[RJ__RL_SUB_SY];
    own[2] = b[RJ__RL_SUB_SX];
    own[3] = b[RJ__RL_SUB_M];
    own[4] = 0;
    own[5] = b[RJ__RL_SUB_M];
    for (i = 0; i < 6; i++)
        rec[RJ__AB_IA + i] = own[i];
    rec[RJ__AB_PQ] = rj__ab_parent(m, j);
    rec[RJ__AB_ROT] = m->jnt[j].rotor;
    /* a root (on the ground or a fixed link) passes nothing up: no arm */
    rec[RJ__AB_RX] = rec[RJ__AB_RY] = 0;
}

/* The acceleration a coordinate's pin takes from its parent's (X a_parent), or 0. */
static void rj__ab_accel_in(const rj__rig *r, const double *rec, int pq, double *a)
{
    const double *ap;
    if (pq < 0) {
        a[0] = a[1] = a[2] = 0;
        return;
    }
    ap = r->ab + RJ__AB_COUNT * (size_t) pq + RJ__AB_A;
    a[0] = ap[0];
    a[1] = ap[1] - rec[RJ__AB_RY] * ap[0];
    a[2] = ap[2] + rec[RJ__AB_RX] * ap[0];
}

/* The factor's step at coordinate qi, whose articulated inertia IA is whole (its
   children's passed in): U, 1 / D, and its Ia moved to its parent's pin into the
   parent's IA. Nonzero when D is not positive. */
static int rj__ab_factor_at(rj__rig *r, int qi)
{
    double *rec = r->ab + RJ__AB_COUNT * (size_t) qi;
    const int pq = (int) rec[RJ__AB_PQ];
    const double *A = rec + RJ__AB_IA;
    double *U = rec + RJ__AB_U, Ia[6], inv_d;
    const double D = A[0] + rec[RJ__AB_ROT];
    U[0] = A[0];
    U[1] = A[1];
    U[2] = A[2];
    if (!(D > 0))
        return -1;
    inv_d = 1.0 / D;
    rec[RJ__AB_D] = inv_d;
    if (pq < 0)
        return 0;
    Ia[0] = A[0] - U[0] * U[0] * inv_d;
    Ia[1] = A[1] - U[0] * U[1] * inv_d;
    Ia[2] = A[2] - U[0] * U[2] * inv_d;
    Ia[3] = A[3] - U[1] * U[1] * inv_d;
    Ia[4] = A[4] - U[1] * U[2] * inv_d;
    Ia[5] = A[5] - U[2] * U[2] * inv_d;
    rj__ab_shift_inertia(Ia, rec[RJ__AB_RX], rec[RJ__AB_RY],
                         r->ab + RJ__AB_COUNT * (size_t) pq + RJ__AB_IA);
    return 0;
}

/* Coordinate qi's u from its b and the force its children passed, and its own force
   moved to its parent's pin (none at a root). */
static void rj__ab_pass_up(rj__rig *r, int qi, double b)
{
    double *rec = r->ab + RJ__AB_COUNT * (size_t) qi;
    const int pq = (int) rec[RJ__AB_PQ];
    const double *U = rec + RJ__AB_U, *f = rec + RJ__AB_F;
    const double u = b - f[0], w = u * rec[RJ__AB_D];
    double *fp, px, py, pz;
    rec[RJ__AB_UU] = u;
    if (pq < 0)
        return;
    px = f[0] + U[0] * w;
    py = f[1] + U[1] * w;
    pz = f[2] + U[2] * w;
    fp = r->ab + RJ__AB_COUNT * (size_t) pq + RJ__AB_F;
    fp[0] += px - rec[RJ__AB_RY] * py + rec[RJ__AB_RX] * pz;
    fp[1] += py;
    fp[2] += pz;
}

/* The solve's pass from the leaves: u_j = b_j - s.p_j, and the force p_j + U u_j / D
   that each subtree passes to its parent's pin. */
static void rj__aba_leaves(const rj_model *m, rj__rig *r, const double *b)
{
    const int n = m->nq;
    int k;
    for (k = 0; k < n; k++) {
        double *f = r->ab + RJ__AB_COUNT * (size_t) k + RJ__AB_F;
        f[0] = f[1] = f[2] = 0;
    }
    for (k = n - 1; k >= 0; k--) {
        const int qi = m->jq[m->jorder[k]];
        rj__ab_pass_up(r, qi, b[qi]);
    }
}

/* The same for b = e_unit: every subtree without the unit passes nothing, so only the
   unit's path to its root is walked (u = 0 elsewhere). */
static void rj__aba_leaves_unit(const rj_model *m, rj__rig *r, int unit)
{
    int k;
    for (k = 0; k < m->nq; k++)
        r->ab[RJ__AB_COUNT * (size_t) k + RJ__AB_UU] = 0;
    for (k = unit; k >= 0; k = (int) r->ab[RJ__AB_COUNT * (size_t) k + RJ__AB_PQ]) {
        double *f = r->ab + RJ__AB_COUNT * (size_t) k + RJ__AB_F;
        f[0] = f[1] = f[2] = 0;
    }
    for (k = unit; k >= 0; k = (int) r->ab[RJ__AB_COUNT * (size_t) k + RJ__AB_PQ])
        rj__ab_pass_up(r, k, k == unit ? 1.0 : 0.0);
}

/* x = M^-1 b with the factor (b NULL: b = e_unit, a column of M^-1). */
static void rj__aba_solve(const rj_model *m, rj__rig *r, const double *b, int unit, double *x)
{
    const int n = m->nq;
    int k;
    if (b)
        rj__aba_leaves(m, r, b);
    else
        rj__aba_leaves_unit(m, r, unit);
    for (k = 0; k < n; k++) {
        const int qi = m->jq[m->jorder[k]];
        double *rec = r->ab + RJ__AB_COUNT * (size_t) qi;
        const double *U = rec + RJ__AB_U;
        double *a = rec + RJ__AB_A;
        rj__ab_accel_in(r, rec, (int) rec[RJ__AB_PQ], a);
        x[qi] = (rec[RJ__AB_UU] - (U[0] * a[0] + U[1] * a[1] + U[2] * a[2])) * rec[RJ__AB_D];
        a[0] += x[qi];
    }
}

/* y = M x (the bodies' inertias as the factor found them): accelerations root first,
   the subtrees' m a and its moment leaves first. */
static void rj__aba_mul(const rj_model *m, rj__rig *r, const double *x, double *y)
{
    const int n = m->nq;
    int k;
    for (k = 0; k < n; k++) {
        const int qi = m->jq[m->jorder[k]];
        double *rec = r->ab + RJ__AB_COUNT * (size_t) qi;
        double *a = rec + RJ__AB_A;
        rj__ab_accel_in(r, rec, (int) rec[RJ__AB_PQ], a);
        a[0] += x[qi];
        rj__ab_sym_mul(rec + RJ__AB_OWN, a, rec + RJ__AB_F);
    }
    for (k = n - 1; k >= 0; k--) {
        const int qi = m->jq[m->jorder[k]];
        const double *rec = r->ab + RJ__AB_COUNT * (size_t) qi, *f = rec + RJ__AB_F;
        const int pq = (int) rec[RJ__AB_PQ];
        double *fp;
        y[qi] = f[0] + rec[RJ__AB_ROT] * x[qi];
        if (pq < 0)
            continue;
        fp = r->ab + RJ__AB_COUNT * (size_t) pq + RJ__AB_F;
        fp[0] += f[0] - rec[RJ__AB_RY] * f[1] + rec[RJ__AB_RX] * f[2];
        fp[1] += f[1];
        fp[2] += f[2];
    }
}
/* ------------------------------------------------------------------ rigid links */
/* Scenes of rigid links are integrated in joint coordinates q (the joints' running
   angles), so nothing but the joints limits the step. Kinematics run down the tree
   (parents first): phi_child = phi_parent + ref + q_j (ref = pi: the reference direction
   I->K points back along body 1), pins and centres follow. The equations of motion
   M(q) q'' = Q - h(q, q') come from the bodies' Jacobians: d c_b / d q_j = z x (c_b - P_j)
   and d phi_b / d q_j = 1 for every joint j on b's path to the ground; h collects the
   centripetal accelerations -omega^2 r of every segment. The element (flags, torques,
   friction, methods) is the same code as for flexible links; a joint torque is a
   generalised force on q_j, and a velocity jump is an impulse along q_j. */
/* The rigid solver's scratch for n coordinates and nl links: with a dense M, M and its
   factor L (n x n each; articulated bodies need neither); cols columns of M^-1 (W); the
   rows' system S and its factor SL (rows x rows each); others columns of the rows that
   are not one joint's rate (Y); vectors of n and of rows; the link and coordinate
   records. */
static size_t rj__rigid_scratch(size_t n, size_t nl, int dense, size_t cols, size_t rows,
                                size_t others)
{
    const size_t square = dense ? 2 * n * n : 0;
    return square + cols * n + 2 * rows * rows + others * n + 10 * n + 3 * rows +
           RJ__RL_COUNT * nl + (RJ__AB_COUNT + 2) * n + 8;
}

/* The step's scratch (rj_state.rsc) for the model's solver, columns and rows; n counts
   the joints, those that close loops too (their vectors are scratch of nq or more). */
static size_t rj__rig_step_scratch(const rj_model *m)
{
    const size_t others = (size_t) m->ncp + 2 * (size_t) m->nloop;
    return rj__rigid_scratch((size_t) m->nj, (size_t) m->nl, !m->rig_tree, (size_t) m->nwcol,
                             (size_t) m->rig_rows, others);
}

/* The rigid solver's arrays in its scratch, as rj__rigid_scratch counts them: the step's
   (solve: W, the rows' system and Y, rj__rig_step_scratch) or the stability bound's
   (none of those, rj__rig_bound_scratch). M and L are NULL for articulated bodies. */
static RJ__FORCE_INLINE void rj__rig_map(const rj_model *m, double *base, rj__rig *r,
                                         int solve)
{
    const size_t n = (size_t) m->nj, square = m->rig_tree ? 0 : n * n;
    const size_t cols = solve ? (size_t) m->nwcol : 0;
    const size_t rows = solve ? (size_t) m->rig_rows : 0;
    const size_t others = solve ? (size_t) m->ncp + 2 * (size_t) m->nloop : 0;
    r->M = m->rig_tree ? NULL : base;
    r->h = base + square;
    r->L = m->rig_tree ? NULL : r->h + n;
    r->W = r->h + n + square;
    r->q = r->W + cols * n;
    r->qd = r->q + n;
    r->qdp = r->qd + n;
    r->qdd = r->qdp + n;
    r->Q = r->qdd + n;
    r->x = r->Q + n;
    r->tmp = r->x + n;
    r->xd = r->tmp + 2 * n;
    r->S = r->xd + n;
    r->SL = r->S + rows * rows;
    r->lam = r->SL + rows * rows;
    r->rhs = r->lam + rows;
    r->Y = r->rhs + rows;
    r->lk = r->Y + others * n;
    r->ab = r->lk + RJ__RL_COUNT * (size_t) m->nl;
}

/* The joint above joint j on the way to the ground (-1 at a root). */
static int rj__rig_up(const rj_model *m, int j)
{
    const int b1 = m->jdef[j].body1;
    return b1 >= 0 ? m->rb_pjoint[b1] : -1;
}

/* The gradient of the angle of joint j, which closes a loop, over the coordinates: +1 for
   each tree joint on body 2's path to the ground, -1 on body 1's (a joint on both
   cancels): its angle is angle0 + g . (q - q(0)), its rate g . q'. */
static void rj__rig_loop_gradient(const rj_model *m, int j, double *g)
{
    int k, up;
    for (k = 0; k < m->nq; k++)
        g[k] = 0;
    for (up = m->rb_pjoint[m->jdef[j].body2]; up >= 0; up = rj__rig_up(m, up))
        g[m->jq[up]] += 1;
    if (m->jdef[j].body1 >= 0)
        for (up = m->rb_pjoint[m->jdef[j].body1]; up >= 0; up = rj__rig_up(m, up))
            g[m->jq[up]] -= 1;
}

/* Positions, velocities (rates qd; skipped when qd is NULL, as the step needs none) and
   centripetal accelerations (rates qdp) of every link, into the link records; cos and sin
   of a hanging link's angle are kept there for its children. q, qd, qdp are over the
   joint coordinates (the tree's joints: m->jq). */
static void rj__rig_kin(const rj_model *m, rj__rig *r, const double *q, const double *qd,
                        const double *qdp)
{
    double *lk = r->lk;
    int k, l;
    for (l = 0; l < m->nl; l++)
        if (m->rb_pjoint[l] < 0) {
            const rj_link_def *d = &m->ldef[l];
            double *b = lk + RJ__RL_COUNT * (size_t) l;
            b[RJ__RL_PHI] = d->angle;
            b[RJ__RL_RX] = b[RJ__RL_PX] = d->x;
            b[RJ__RL_RY] = b[RJ__RL_PY] = d->y;
            b[RJ__RL_OM] = b[RJ__RL_VX] = b[RJ__RL_VY] = b[RJ__RL_ARX] = b[RJ__RL_ARY] =
                b[RJ__RL_OMB] = 0;
        }
    for (k = 0; k < m->nq; k++) {
        const int j = m->jorder[k], qi = m->jq[j];
        const rj_joint_def *jd = &m->jdef[j];
        const int p = jd->body1, c = jd->body2;
        double *RJ__RESTRICT b = lk + RJ__RL_COUNT * (size_t) c;
        const double dc = m->rb_dcm[c];
        double ph, ex, ey, omb, rx, ry, arx, ary;
        if (p < 0) {
            ph = jd->ground_angle + q[qi];
            omb = qdp[qi];
            rx = jd->ground_x;
            ry = jd->ground_y;
            arx = ary = 0;
            if (qd) {
                b[RJ__RL_OM] = qd[qi];
                b[RJ__RL_VX] = b[RJ__RL_VY] = 0;
            }
        } else {
            const double *pb = lk + RJ__RL_COUNT * (size_t) p;
            const double s = m->jpin[j], ompb = pb[RJ__RL_OMB];
            double cp, sp;
            if (m->rb_pjoint[p] >= 0) {
                cp = pb[RJ__RL_EC];
                sp = pb[RJ__RL_ES];
            } /* parents come first */
            else {
                cp = cos(pb[RJ__RL_PHI]);
                sp = sin(pb[RJ__RL_PHI]);
            } /* a fixed link */
            ph = pb[RJ__RL_PHI] + m->jref[j] + q[qi];
            omb = ompb + qdp[qi];
            rx = pb[RJ__RL_RX] + s * cp;
            ry = pb[RJ__RL_RY] + s * sp;
            arx = pb[RJ__RL_ARX] - ompb * ompb * s * cp;
            ary = pb[RJ__RL_ARY] - ompb * ompb * s * sp;
            if (qd) {
                const double omp = pb[RJ__RL_OM];
                b[RJ__RL_OM] = omp + qd[qi];
                b[RJ__RL_VX] = pb[RJ__RL_VX] - omp * s * sp;
                b[RJ__RL_VY] = pb[RJ__RL_VY] + omp * s * cp;
            }
        }
        ex = cos(ph);
        ey = sin(ph);
        b[RJ__RL_PX] = rx;
        b[RJ__RL_PY] = ry;
        /* a pin at node at: the root at -at l0 along the link, moving and turning about it */
        if (m->jnt[j].nJ != m->link_first[c]) {
            const double off = (m->jnt[j].nJ - m->link_first[c]) * m->link_l0[c];
            rx -= off * ex;
            ry -= off * ey;
            arx += omb * omb * off * ex;
            ary += omb * omb * off * ey;
            if (qd) {
                b[RJ__RL_VX] += b[RJ__RL_OM] * off * ey;
                b[RJ__RL_VY] -= b[RJ__RL_OM] * off * ex;
            }
        }
        b[RJ__RL_PHI] = ph;
        b[RJ__RL_EC] = ex;
        b[RJ__RL_ES] = ey;
        b[RJ__RL_RX] = rx;
        b[RJ__RL_RY] = ry;
        b[RJ__RL_ARX] = arx;
        b[RJ__RL_ARY] = ary;
        b[RJ__RL_OMB] = omb; /* the angular rate used for the centripetal terms */
        b[RJ__RL_CX] = rx + dc * ex;
        b[RJ__RL_CY] = ry + dc * ey;
        b[RJ__RL_ACX] = arx - omb * omb * dc * ex;
        b[RJ__RL_ACY] = ary - omb * omb * dc * ey;
    }
}

/* One link's own share of the subtree sums of its parent joint (pin P, centre c):
   mass m, first moment m (c - P), inertia I + m |c - P|^2 about P, m a and its moment
   m (c - P) x a, with a the centre's centripetal acceleration. */
static RJ__FORCE_INLINE void rj__rig_own(const rj_model *m, int link, double *b)
{
    const double mass = m->rb_mass[link];
    const double dx = b[RJ__RL_CX] - b[RJ__RL_PX];
    const double dy = b[RJ__RL_CY] - b[RJ__RL_PY];
    b[RJ__RL_SUB_M] = mass;
    b[RJ__RL_SUB_SX] = mass * dx;
    b[RJ__RL_SUB_SY] = mass * dy;
    b[RJ__RL_SUB_J] = m->rb_icm[link] + mass * (dx * dx + dy * dy);
    b[RJ__RL_SUB_FX] = mass * b[RJ__RL_ACX];
    b[RJ__RL_SUB_FY] = mass * b[RJ__RL_ACY];
    b[RJ__RL_SUB_N] = mass * (dx * b[RJ__RL_ACY] - dy * b[RJ__RL_ACX]);
}

/* Adds a complete subtree (record sub, pin at sub's root) to its parent's sums, moved
   from the child's pin to the parent's by d = P_child - P_parent (parallel axes). */
static RJ__FORCE_INLINE void rj__rig_gather(const double *sub, double *parent, double dx,
                                            double dy)
{
    const double mass = sub[RJ__RL_SUB_M];
    const double moment = dx * sub[RJ__RL_SUB_SX] + dy * sub[RJ__RL_SUB_SY];
    parent[RJ__RL_SUB_M] += mass;
    parent[RJ__RL_SUB_J] += sub[RJ__RL_SUB_J] + 2 * moment + mass * (dx * dx + dy * dy);
    parent[RJ__RL_SUB_SX] += sub[RJ__RL_SUB_SX] + mass * dx;
    parent[RJ__RL_SUB_SY] += sub[RJ__RL_SUB_SY] + mass * dy;
    parent[RJ__RL_SUB_FX] += sub[RJ__RL_SUB_FX];
    parent[RJ__RL_SUB_FY] += sub[RJ__RL_SUB_FY];
    parent[RJ__RL_SUB_N] += sub[RJ__RL_SUB_N] + dx * sub[RJ__RL_SUB_FY] - dy * sub[RJ__RL_SUB_FX];
}

/* rj__rig_gather's force sums alone (m a and its moment), all the bias h needs: an
   articulated-body tree without gravity reads no other subtree sum. */
static void rj__rig_gather_forces(const double *sub, double *parent, double dx, double dy)
{
    parent[RJ__RL_SUB_FX] += sub[RJ__RL_SUB_FX];
    parent[RJ__RL_SUB_FY] += sub[RJ__RL_SUB_FY];
    parent[RJ__RL_SUB_N] += sub[RJ__RL_SUB_N] + dx * sub[RJ__RL_SUB_FY] - dy * sub[RJ__RL_SUB_FX];
}

/* The subtrees' sums and the bias h (with the centripetal accelerations from rj__rig_kin),
   by composite bodies. Joint j turns the subtree beyond it (its body 2 and all that hangs
   from it), whose inertia J_j and first moment S_j about j's pin P_j are gathered leaves
   first, in O(n); h_j is the moment of the subtree's m a about P_j. The dense M
   (rj__rig_mass_links) reads them, its pairs at four flops each; without the motors'
   rotors (rj__rig_mass adds them). */
static void rj__rig_subtrees(const rj_model *m, rj__rig *r)
{
    const int n = m->nq;
    double *h = r->h, *lk = r->lk, *up;
    int k;
    for (k = 0; k < n; k++) {
        const int body = m->jdef[m->qj[k]].body2;
        rj__rig_own(m, body, lk + RJ__RL_COUNT * (size_t) body);
    }
    /* jorder has parents before children: backwards, a subtree is whole when gathered */
    for (k = n - 1; k >= 0; k--) {
        const int j = m->jorder[k], qi = m->jq[j];
        const int parent = m->jdef[j].body1;
        const double *sub = lk + RJ__RL_COUNT * (size_t) m->jdef[j].body2;
        h[qi] = sub[RJ__RL_SUB_N];
        if (parent < 0 || m->rb_pjoint[parent] < 0)
            continue; /* on the ground or a fixed link */
        up = lk + RJ__RL_COUNT * (size_t) parent;
        rj__rig_gather(sub, up, sub[RJ__RL_PX] - up[RJ__RL_PX], sub[RJ__RL_PY] - up[RJ__RL_PY]);
    }
}

/* An articulated-body tree's factor and bias h (rj__rig_subtrees and the factor's steps,
   rj__ab_factor_at, in one pass each way): each body's own sums and inertia, then leaves
   first each subtree's sums and its articulated inertia, both moved to the parent's pin
   by the same arm P_child - P_parent, taken once. Without gravity only the force sums
   are gathered (h reads no other). Nonzero when a pivot D is not positive. */
static int rj__rig_tree_factor(const rj_model *m, rj__rig *r)
{
    const int n = m->nq, moments = m->has_gravity;
    double *h = r->h, *lk = r->lk;
    int k;
    for (k = 0; k < n; k++) {
        const int body = m->jdef[m->qj[k]].body2;
        double *b = lk + RJ__RL_COUNT * (size_t) body;
        rj__rig_own(m, body, b);
        rj__ab_own(m, r, k, b);
    }
    /* jorder has parents before children: backwards, a subtree is whole when reached */
    for (k = n - 1; k >= 0; k--) {
        const int j = m->jorder[k], qi = m->jq[j];
        const int parent = m->jdef[j].body1;
        const double *sub = lk + RJ__RL_COUNT * (size_t) m->jdef[j].body2;
        double *rec = r->ab + RJ__AB_COUNT * (size_t) qi;
        h[qi] = sub[RJ__RL_SUB_N];
        /* the same test as the factor's parent coordinate (rj__ab_parent) */
        if (parent >= 0 && m->rb_pjoint[parent] >= 0) {
            double *up = lk + RJ__RL_COUNT * (size_t) parent;
            const double dx = sub[RJ__RL_PX] - up[RJ__RL_PX];
            const double dy = sub[RJ__RL_PY] - up[RJ__RL_PY];
            rec[RJ__AB_RX] = dx;
            rec[RJ__AB_RY] = dy;
            if (moments)
                rj__rig_gather(sub, up, dx, dy);
            else
                rj__rig_gather_forces(sub, up, dx, dy);
        }
        if (rj__ab_factor_at(r, qi))
            return -1;
    }
    return 0;
}

/* The dense M from the subtrees' sums: M_jj = J_j, M_jk = J_j + (P_j - P_k) . S_j for
   every joint k above j. */
static void rj__rig_mass_links(const rj_model *m, rj__rig *r)
{
    const int n = m->nq;
    double *M = r->M, *lk = r->lk;
    int i, k;
    for (i = 0; i < n * n; i++)
        M[i] = 0;
    for (k = 0; k < n; k++) {
        const double *sub = lk + RJ__RL_COUNT * (size_t) m->jdef[m->qj[k]].body2;
        int up;
        M[(size_t) k * n + k] = sub[RJ__RL_SUB_J];
        for (up = rj__rig_up(m, m->qj[k]); up >= 0; up = rj__rig_up(m, up)) {
            const double *pin = lk + RJ__RL_COUNT * (size_t) m->jdef[up].body2;
            const double dx = sub[RJ__RL_PX] - pin[RJ__RL_PX];
            const double dy = sub[RJ__RL_PY] - pin[RJ__RL_PY];
            const double v = sub[RJ__RL_SUB_J] + dx * sub[RJ__RL_SUB_SX] + dy * sub[RJ__RL_SUB_SY];
            M[(size_t) k * n + m->jq[up]] = v;
            M[(size_t) m->jq[up] * n + k] = v;
        }
    }
}

/* A rotor on a joint that closes a loop: its kinetic energy I (g . q')^2 / 2 adds I g g^T
   (g: nq doubles of scratch). */
static void rj__rig_loop_rotors(const rj_model *m, double *M, double *g)
{
    const int n = m->nq;
    int j, a, b;
    for (j = 0; j < m->nj; j++) {
        if (m->jq[j] >= 0 || m->jnt[j].rotor == 0)
            continue;
        rj__rig_loop_gradient(m, j, g);
        for (a = 0; a < n; a++)
            for (b = 0; b < n; b++)
                M[(size_t) a * n + b] += m->jnt[j].rotor * g[a] * g[b];
    }
}

/* M(q): the links', and each motor's rotor, whose reflected inertia acts on its joint's
   rate. */
static void rj__rig_mass(const rj_model *m, rj__rig *r)
{
    const int n = m->nq;
    int k;
    rj__rig_subtrees(m, r);
    rj__rig_mass_links(m, r);
    for (k = 0; k < n; k++)
        r->M[(size_t) k * n + k] += m->jnt[m->qj[k]].rotor;
    if (m->nloop)
        rj__rig_loop_rotors(m, r->M, r->tmp);
}

/* Cholesky factor of the n x n SPD matrix M into L (lower), and solves L L^T x = b. The
   2 x 2 case (a two-link arm) is written out: the same operations in the same order as
   the loops, without their overhead, which dominates at that size. */
static int rj__chol(int n, const double *M, double *L)
{
    int i, j, k;
    if (n == 2) {
        double sum = M[0];
        if (!(sum > 0))
            return -1;
        L[0] = sqrt(sum);
        L[2] = M[2] / L[0];
        sum = M[3] - L[2] * L[2];
        if (!(sum > 0))
            return -1;
        L[3] = sqrt(sum);
        return 0;
    }
    for (i = 0; i < n; i++) {
        const double *Mi = M + (size_t) i * n;
        double *Li = L + (size_t) i * n, sum;
        for (j = 0; j < i; j++) {
            const double *Lj = L + (size_t) j * n;
            sum = Mi[j];
            for (k = 0; k < j; k++)
                sum -= Li[k] * Lj[k];
            Li[j] = sum / Lj[j];
        }
        sum = Mi[i];
        for (k = 0; k < i; k++)
            sum -= Li[k] * Li[k];
        if (!(sum > 0))
            return -1;
        Li[i] = sqrt(sum);
    }
    return 0;
}
static void rj__chol_solve(int n, const double *L, const double *b, double *x)
{
    int i, k;
    if (n == 2) {
        const double x0 = b[0] / L[0], x1 = (b[1] - L[2] * x0) / L[3] / L[3];
        x[1] = x1;
        x[0] = (x0 - L[2] * x1) / L[0];
        return;
    }
    for (i = 0; i < n; i++) {
        const double *Li = L + (size_t) i * n;
        double sum = b[i];
        for (k = 0; k < i; k++)
            sum -= Li[k] * x[k];
        x[i] = sum / Li[i];
    }
    for (i = n - 1; i >= 0; i--) {
        double sum = x[i];
        for (k = i + 1; k < n; k++)
            sum -= L[(size_t) k * n + i] * x[k];
        x[i] = sum / L[(size_t) i * n + i];
    }
}
/* Column j of M^-1: rj__chol_solve with b = e_j, without the arithmetic on its leading
   zeros (the forward pass gives exact zeros above j, and 1 / L_jj at j). */
static void rj__chol_unit(int n, const double *L, int j, double *x)
{
    int i, k;
    if (n == 2) {
        const double x0 = j ? 0.0 : 1.0 / L[0],
                     x1 = (j ? 1.0 / L[3] : (0.0 - L[2] * x0) / L[3]) / L[3];
        x[1] = x1;
        x[0] = (x0 - L[2] * x1) / L[0];
        return;
    }
    x[j] = 1.0 / L[(size_t) j * n + j];
    for (i = j + 1; i < n; i++) {
        const double *Li = L + (size_t) i * n;
        double sum = 0;
        for (k = j; k < i; k++)
            sum -= Li[k] * x[k];
        x[i] = sum / Li[i];
    }
    for (i = n - 1; i >= 0; i--) {
        double sum = i >= j ? x[i] : 0.0;
        for (k = i + 1; k < n; k++)
            sum -= L[(size_t) k * n + i] * x[k];
        x[i] = sum / L[(size_t) i * n + i];
    }
}

/* M(q) and its factor at the kinematics in r->lk, as the model solves them: dense
   (Cholesky) or articulated bodies (rj__rig_tree_factor); nonzero when M is not positive
   definite. */
static RJ__FORCE_INLINE int rj__rig_factor(const rj_model *m, rj__rig *r)
{
    if (m->rig_tree)
        return rj__rig_tree_factor(m, r);
    rj__rig_mass(m, r);
    return rj__chol(m->nq, r->M, r->L);
}

/* x = M^-1 b with the factor. */
static RJ__FORCE_INLINE void rj__rig_solve(const rj_model *m, rj__rig *r, const double *b, double *x)
{
    if (m->rig_tree)
        rj__aba_solve(m, r, b, -1, x);
    else
        rj__chol_solve(m->nq, r->L, b, x);
}

/* Column j of M^-1 with the factor. */
static RJ__FORCE_INLINE void rj__rig_unit(const rj_model *m, rj__rig *r, int j, double *x)
{
    if (m->rig_tree)
        rj__aba_solve(m, r, NULL, j, x);
    else
        rj__chol_unit(m->nq, r->L, j, x);
}

/* y = M x at the factor's configuration. */
static RJ__FORCE_INLINE void rj__rig_mul(const rj_model *m, rj__rig *r, const double *x, double *y)
{
    const int n = m->nq;
    int j, k;
    if (m->rig_tree) {
        rj__aba_mul(m, r, x, y);
        return;
    }
    for (j = 0; j < n; j++) {
        const double *Mj = r->M + (size_t) j * n;
        double sum = 0;
        for (k = 0; k < n; k++)
            sum += Mj[k] * x[k];
        y[j] = sum;
    }
}

/* Writes the links' nodes (for queries and drawing) from the kinematics. */
static void rj__rig_nodes(const rj_model *m, const rj__rig *r, double *f)
{
    double *x = RJ__FX(m, f), *y = RJ__FY(m, f), *phi = RJ__FPHI(m, f), *vx = RJ__FVX(m, f),
           *vy = RJ__FVY(m, f), *w = RJ__FW(m, f);
    int l, i;
    for (l = 0; l < m->nl; l++) {
        const double *b = r->lk + RJ__RL_COUNT * (size_t) l;
        const double c = cos(b[RJ__RL_PHI]), s = sin(b[RJ__RL_PHI]), l0 = m->link_l0[l];
        for (i = 0; i <= m->ldef[l].elements; i++) {
            const int k = m->link_first[l] + i;
            x[k] = b[RJ__RL_RX] + i * l0 * c;
            y[k] = b[RJ__RL_RY] + i * l0 * s;
            phi[k] = b[RJ__RL_PHI];
            vx[k] = b[RJ__RL_VX] - b[RJ__RL_OM] * i * l0 * s;
            vy[k] = b[RJ__RL_VY] + b[RJ__RL_OM] * i * l0 * c;
            w[k] = b[RJ__RL_OM];
        }
    }
}

/* The rate of joint j, which closes a loop, at coordinate rates qd (g: nq doubles). */
static double rj__rig_loop_rate(const rj_model *m, int j, const double *qd, double *g)
{
    double rate = 0;
    int k;
    rj__rig_loop_gradient(m, j, g);
    for (k = 0; k < m->nq; k++)
        rate += g[k] * qd[k];
    return rate;
}

/* Joint j's rate at coordinate rates qd: its coordinate's, or for a joint that closes a
   loop g . qd (g: nq doubles of scratch). */
static double rj__rig_joint_rate(const rj_model *m, int j, const double *qd, double *g)
{
    return m->jq[j] >= 0 ? qd[m->jq[j]] : rj__rig_loop_rate(m, j, qd, g);
}

/* A torque tau at joint j as a generalised force into Q: on its coordinate, or tau g for
   a joint that closes a loop (g: nq doubles of scratch). */
static void rj__rig_joint_force(const rj_model *m, int j, double tau, double *Q, double *g)
{
    int k;
    if (m->jq[j] >= 0) {
        Q[m->jq[j]] += tau;
        return;
    }
    rj__rig_loop_gradient(m, j, g);
    for (k = 0; k < m->nq; k++)
        Q[k] += tau * g[k];
}

/* K v for the joints' stiffnesses (a loop joint's k g g^T), and the cable loops' (k w w^T,
   w = e_b - ratio e_a); g: nq doubles of scratch. */
static void rj__rig_stiffness(const rj_model *m, const double *v, double *kv, double *g)
{
    int j, k;
    for (k = 0; k < m->nq; k++)
        kv[k] = m->jnt[m->qj[k]].k_lin * v[k];
    for (j = 0; j < m->nj && m->nloop; j++) {
        double gv = 0;
        if (m->jq[j] >= 0 || m->jnt[j].k_lin == 0)
            continue;
        rj__rig_loop_gradient(m, j, g);
        for (k = 0; k < m->nq; k++)
            gv += g[k] * v[k];
        for (k = 0; k < m->nq; k++)
            kv[k] += m->jnt[j].k_lin * g[k] * gv;
    }
    for (j = 0; j < m->ncp; j++) {
        const rj_coupling_def *c = &m->cp[j];
        const double e = rj__rig_joint_rate(m, c->joint_b, v, g) -
                         c->ratio * rj__rig_joint_rate(m, c->joint_a, v, g);
        rj__rig_joint_force(m, c->joint_b, c->stiffness * e, kv, g);
        rj__rig_joint_force(m, c->joint_a, -(c->ratio * c->stiffness * e), kv, g);
    }
}

/* omega_max^2 with cable loops, whose stiffness ties joints: the largest eigenvalue of
   M^-1 K by power iteration (K is no longer diagonal; the iterates' growth converges to
   it). v, u, kv: nj doubles each. */
static double rj__rig_coupled_bound(const rj_model *m, const double *minv, double *v,
                                    double *u, double *kv, double *g)
{
    const int n = m->nq;
    double lam = 0;
    int j, k, it;
    for (j = 0; j < n; j++)
        v[j] = 1.0 + 0.1 * j;
    for (it = 0; it < 500; it++) {
        double nrm = 0, nv = 0;
        rj__rig_stiffness(m, v, kv, g);
        for (j = 0; j < n; j++) {
            double sum = 0;
            for (k = 0; k < n; k++)
                sum += minv[(size_t) j * n + k] * kv[k];
            u[j] = sum;
            nrm += sum * sum;
            nv += v[j] * v[j];
        }
        if (nrm == 0)
            return 0;
        lam = sqrt(nrm / nv);
        for (j = 0; j < n; j++)
            v[j] = u[j] / sqrt(nrm);
    }
    return lam;
}

/* Each loop joint's rate change per unit torque impulse, g^T M^-1 g, and the inertias
   its element reads (those of its bodies about the pin, as a tree joint's); g, mg: nq
   doubles of scratch. */
static void rj__rig_loop_minv(rj_model *m, const double *minv, double *g, double *mg)
{
    const int n = m->nq;
    int j, a, b;
    for (j = 0; j < m->nj; j++) {
        rj__joint *J = &m->jnt[j];
        double c = 0;
        if (m->jq[j] >= 0)
            continue;
        rj__rig_loop_gradient(m, j, g);
        for (a = 0; a < n; a++) {
            mg[a] = 0;
            for (b = 0; b < n; b++)
                mg[a] += minv[(size_t) a * n + b] * g[b];
            c += g[a] * mg[a];
        }
        J->minv = c;
        J->I2 = 1.0 / c;
        J->I1 = HUGE_VAL;
        J->w1 = 0;
        J->w2 = 1;
    }
}

/* Coordinate k's joint: the inertias its element reads (its bodies' about the pin) and
   the weights that share its torque between them. */
static void rj__rig_joint_inertias(rj_model *m, const rj__rig *r, int k)
{
    const int j = m->qj[k];
    rj__joint *J = &m->jnt[j];
    const int b1 = m->jdef[j].body1, b2 = m->jdef[j].body2;
    /* body 2's centre from the pin (its root unless the joint pins another node) */
    const double arm = m->rb_dcm[b2] - (J->nJ - m->link_first[b2]) * m->link_l0[b2];
    double dx, dy;
    J->I2 = m->rb_icm[b2] + m->rb_mass[b2] * arm * arm;
    if (b1 < 0 || m->rb_pjoint[b1] < 0)
        J->I1 = HUGE_VAL;
    else {
        dx = r->lk[RJ__RL_COUNT * (size_t) b1 + RJ__RL_CX] -
             r->lk[RJ__RL_COUNT * (size_t) b2 + RJ__RL_PX];
        dy = r->lk[RJ__RL_COUNT * (size_t) b1 + RJ__RL_CY] -
             r->lk[RJ__RL_COUNT * (size_t) b2 + RJ__RL_PY];
        J->I1 = m->rb_icm[b1] + m->rb_mass[b1] * (dx * dx + dy * dy);
    }
    J->w1 = rj__finite(J->I1) ? J->I2 / (J->I1 + J->I2) : 0;
    J->w2 = 1 - J->w1;
}

/* A power iteration's step from v to its image u: the estimate v.u (v of unit length) into
   *lam and v = u / |u|; 0 when u is 0. */
static int rj__power_next(double *v, const double *u, int n, double *lam)
{
    double nrm = 0;
    int j;
    for (j = 0; j < n; j++)
        nrm += u[j] * u[j];
    nrm = sqrt(nrm);
    if (nrm == 0)
        return 0;
    *lam = 0;
    for (j = 0; j < n; j++)
        *lam += v[j] * u[j];
    for (j = 0; j < n; j++)
        v[j] = u[j] / nrm;
    return 1;
}

/* A 3 x 3 product C = A B (row-major). */
static void rj__mat3_mul(const double *A, const double *B, double *C)
{
    int i, j;
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++)
            C[3 * i + j] = A[3 * i] * B[j] + A[3 * i + 1] * B[3 + j] + A[3 * i + 2] * B[6 + j];
}

/* C = A B A^T (3 x 3, row-major; T: 9 doubles of scratch). */
static void rj__mat3_congruent(const double *A, const double *B, double *T, double *C)
{
    double At[9];
    int i, j;
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++)
            At[3 * i + j] = A[3 * j + i];
    rj__mat3_mul(A, B, T);
    rj__mat3_mul(T, At, C);
}

/* Every coordinate's 1 / I_red = (M^-1)_kk of an articulated tree in O(n), root first,
   from the factor (rj__rig_tree_factor). In rj__aba_solve with b = e_k, coordinate k's
   subtree passes the force w = X^T U_k / D_k to its parent's pin, which then accelerates
   by -Lam_p w, Lam_p the parent's response to a force on it in the whole tree (a = -Lam
   f); so (M^-1)_kk = 1 / D_k + w.Lam_p w. The same solve with a force F on body k gives
   Lam_k = P X Lam_p X^T P^T + s s^T / D_k, P = I - s U^T / D_k (s = (1, 0, 0)); a root's
   parent is the ground (Lam = 0). lam: 9 doubles a coordinate. A column of M^-1 a joint
   (O(n^2)) took 1.8 s for a chain of 10 000 links. */
static void rj__rig_tree_minv(rj_model *m, rj__rig *r, double *lam)
{
    int k;
    for (k = 0; k < m->nq; k++) {
        const int qi = m->jq[m->jorder[k]];
        const double *rec = r->ab + RJ__AB_COUNT * (size_t) qi;
        const double *U = rec + RJ__AB_U, inv_d = rec[RJ__AB_D];
        const double rx = rec[RJ__AB_RX], ry = rec[RJ__AB_RY];
        const int pq = (int) rec[RJ__AB_PQ];
        double *L = lam + 9 * (size_t) qi, minv = inv_d;
        int i;
        for (i = 0; i < 9; i++)
            L[i] = 0;
        if (pq >= 0) {
            const double *Lp = lam + 9 * (size_t) pq;
            const double X[9] = { 1, 0, 0, -ry, 1, 0, rx, 0, 1 };
            const double P[9] = { 1 - U[0] * inv_d, -U[1] * inv_d, -U[2] * inv_d, 0, 1, 0, 0, 0, 1 };
            /* w = X^T U / D and its quadratic form on the parent's response */
            const double w[3] = { (U[0] - ry * U[1] + rx * U[2]) * inv_d, U[1] * inv_d,
                                  U[2] * inv_d };
            double T[9], XLX[9];
            for (i = 0; i < 3; i++)
                minv += w[i] * (Lp[3 * i] * w[0] + Lp[3 * i + 1] * w[1] + Lp[3 * i + 2] * w[2]);
            rj__mat3_congruent(X, Lp, T, XLX);
            rj__mat3_congruent(P, XLX, T, L);
        }
        L[0] += inv_d;
        m->jnt[m->qj[qi]].minv = minv;
    }
}

/* An articulated-body tree's constants and bound: each 1 / I_red (rj__rig_tree_minv) and
   the power iteration on K^1/2 M^-1 K^1/2 with a solve per iteration instead of the dense
   inverse. lam: rj__rig_tree_minv's scratch. */
static double rj__rig_tree_setup(rj_model *m, rj__rig *r, double *lam)
{
    const int n = m->nq;
    double *v = r->x, *u = r->tmp, *col = r->qdd, lam_top = 0;
    int j, it;
    for (j = 0; j < n; j++)
        rj__rig_joint_inertias(m, r, j);
    rj__rig_tree_minv(m, r, lam);
    for (j = 0; j < n; j++)
        v[j] = 1.0 + 0.1 * j;
    for (it = 0; it < 500; it++) {
        for (j = 0; j < n; j++)
            u[j] = sqrt(m->jnt[m->qj[j]].k_lin) * v[j];
        rj__rig_solve(m, r, u, col);
        for (j = 0; j < n; j++)
            u[j] = sqrt(m->jnt[m->qj[j]].k_lin) * col[j];
        if (!rj__power_next(v, u, n, &lam_top))
            return 0;
    }
    return lam_top;
}

/* The solver in scratch at the start, at rest, its mass matrix factored; nonzero when
   there is nothing to factor or M is not positive definite. */
static int rj__rig_at_start(const rj_model *m, double *scratch, rj__rig *r)
{
    const int n = m->nq;
    int j;
    rj__rig_map(m, scratch, r, 0);
    for (j = 0; j < n; j++) {
        r->q[j] = m->jdef[m->qj[j]].angle0;
        r->qd[j] = r->qdp[j] = 0;
    }
    rj__rig_kin(m, r, r->q, r->qd, r->qdp);
    return n == 0 || rj__rig_factor(m, r);
}

/* Rigid-link model constants and the stability bound: omega_max^2 = largest eigenvalue of
   K^1/2 M^-1 K^1/2 at the initial configuration (power iteration), K the joints' linear
   stiffnesses (limits counted as for flexible links). Returns omega_max^2. scratch: the
   solver's without columns or rows, then a dense M's inverse or a tree's responses
   (rj__rig_bound_scratch). */
static double rj__rig_setup(rj_model *m, double *scratch)
{
    rj__rig r;
    const int n = m->nq;
    const size_t nj = (size_t) m->nj, nl = (size_t) m->nl;
    double *minv = scratch + rj__rigid_scratch(nj, nl, !m->rig_tree, 0, 0, 0), lam = 0, *v, *u;
    int j, k, it;
    if (rj__rig_at_start(m, scratch, &r))
        return 0;
    /* a tree's responses where a dense M's inverse would be */
    if (m->rig_tree)
        return rj__rig_tree_setup(m, &r, minv);
    for (j = 0; j < n; j++) {
        for (k = 0; k < n; k++)
            r.tmp[k] = k == j ? 1.0 : 0.0;
        rj__chol_solve(n, r.L, r.tmp, minv + (size_t) j * n);
    }
    for (k = 0; k < n; k++) {
        rj__rig_joint_inertias(m, &r, k);
        m->jnt[m->qj[k]].minv = minv[(size_t) k * n + k]; /* rate change per unit torque impulse: 1 / I_red */
    }
    if (m->nloop)
        rj__rig_loop_minv(m, minv, r.qd, r.qdp);
    if (m->ncp || m->nloop)
        return rj__rig_coupled_bound(m, minv, r.x, r.tmp, r.q, r.qd);
    /* power iteration on K^1/2 M^-1 K^1/2 */
    v = r.x;
    u = r.tmp;
    for (j = 0; j < n; j++)
        v[j] = 1.0 + 0.1 * j;
    for (it = 0; it < 500; it++) {
        for (j = 0; j < n; j++) {
            double sum = 0;
            for (k = 0; k < n; k++)
                sum += minv[(size_t) j * n + k] * sqrt(m->jnt[m->qj[k]].k_lin) * v[k];
            u[j] = sqrt(m->jnt[m->qj[j]].k_lin) * sum;
        }
        if (!rj__power_next(v, u, n, &lam))
            return 0;
    }
    return lam;
}

/* ------------------------------------------------------------------ constraint rows */
/* A constraint row holds a combination of joint rates, J q' = sum_t coef_t q'_(joint_t),
   at a target rate over the step, n + 1/2, by an impulse lam along J^T within bounds
   [lo, hi]. A row with a position to keep (a profile, a coupling's e = 0) aims its target
   rate at that position at n + 1: target = (position(t + dt) - position(t)) / dt.

   Rows are the one way the step imposes motion. Every kind is built the same way (its
   terms, target and bounds) and solved by the space its scene steps in:
   - joint coordinates (rigid scenes): W lam = target - J q' with W = J M^-1 J^T, dense,
     over the active rows, a bounded row that would pull dropped and the set solved
     again (rj__rows_solve_dense);
   - node space (flexible and mixed scenes): a row's impulse is a pair of torque
     impulses on its joints' pins (rj__joint_impulse); W from the joints' gives and the
     bodies they share (rj__joint_cross), solved at once (rj__rows_direct), then swept
     row by row until none misses (a check that finds round-off).
   The work of a row's impulse in the kinetic energy's discrete form is
   -1/2 lam J q'^{n-1/2} now and -1/2 lam J q'^{n+1/2} with the next step (the latches'
   rule, rj__joint_jump), whatever the space.

   Kinds: a locked joint (rigid scenes), a plastic contact at a limit (rigid scenes,
   pushing only), a prescribed joint, an exact coupling. The closed loops' rows are the
   next kind: rows of J over the joints around a loop. */
/* Opens row of kind for owner; its terms follow with rj__row_term. */
static rj__row *rj__row_open(rj__rows *R, int kind, int owner, double target, double lo,
                             double hi)
{
    rj__row *row = &R->row[R->count];
    R->count++;
    row->kind = kind;
    row->owner = owner;
    row->first = R->terms;
    row->count = 0;
    row->active = 1;
    row->target = target;
    row->lo = lo;
    row->hi = hi;
    row->lam = 0;
    return row;
}

static void rj__row_term(rj__rows *R, rj__row *row, int joint, double coef)
{
    R->term[R->terms].joint = joint;
    R->term[R->terms].coef = coef;
    R->terms++;
    row->count++;
}

/* J x for a vector x over the joints. */
static double rj__row_dot(const rj__rows *R, const rj__row *row, const double *x)
{
    const rj__term *t = R->term + row->first;
    double sum = 0;
    int k;
    for (k = 0; k < row->count; k++)
        sum += t[k].coef * x[t[k].joint];
    return sum;
}

/* Whether the row is one joint's rate alone (its column of M^-1 is W's). */
static int rj__row_unit(const rj__rows *R, const rj__row *row)
{
    return row->count == 1 && R->term[row->first].coef == 1.0;
}

/* A prescribed joint's row: its rate lands it on its profile at n + 1; its term at index
   at (the joint, or its coordinate in joint coordinates). */
static void rj__row_prescribed(const rj_model *m, const rj_state *s, rj__rows *R, int j, int at,
                               double run, double t, double dt)
{
    const double target = rj__prescribed_rate(m, s, j, run, t, dt);
    rj__row *row = rj__row_open(R, RJ__ROW_PRESCRIBED, j, target, -HUGE_VAL, HUGE_VAL);
    rj__row_term(R, row, at, 1.0);
}

/* Exact coupling k's row, from the joints' running angles at n (stride apart in
   angles): e = (theta_b - angle0_b) - ratio (theta_a - angle0_a) - offset back to 0 at
   n + 1, along w = e_b - ratio e_a. map: a joint's index in angles and terms (its
   coordinate in joint coordinates), NULL for the joint itself. */
/* Exact coupling c's stretch e at its joints' running angles. */
static double rj__coupling_stretch(const rj_model *m, const rj_coupling_def *c, double theta_a,
                                   double theta_b)
{
    return (theta_b - m->jdef[c->joint_b].angle0) -
           c->ratio * (theta_a - m->jdef[c->joint_a].angle0) - c->offset;
}

static void rj__row_coupling(const rj_model *m, rj__rows *R, int k, const double *angles,
                             size_t stride, const int *map, double dt)
{
    const rj_coupling_def *c = &m->cp[k];
    const int a = map ? map[c->joint_a] : c->joint_a, b = map ? map[c->joint_b] : c->joint_b;
    const double theta_a = angles[stride * (size_t) a], theta_b = angles[stride * (size_t) b];
    const double e_n = rj__coupling_stretch(m, c, theta_a, theta_b);
    rj__row *row = rj__row_open(R, RJ__ROW_COUPLING, k, -e_n / dt, -HUGE_VAL, HUGE_VAL);
    rj__row_term(R, row, b, 1.0);
    rj__row_term(R, row, a, -c->ratio);
}

/* Whether coupling k is exact with a joint between two rigid bodies of a mixed scene: a
   torque pair then (rj__pair_coupling), not a row. */
static int rj__coupling_on_pair(const rj_model *m, int k)
{
    const rj_coupling_def *c = &m->cp[k];
    return c->exact && (m->jnt[c->joint_a].pair || m->jnt[c->joint_b].pair);
}

/* The exact couplings' rows. */
static void rj__rows_couplings(const rj_model *m, rj__rows *R, const double *angles,
                               size_t stride, const int *map, double dt)
{
    int k;
    for (k = 0; k < m->ncp; k++)
        if (m->cp[k].exact && !rj__coupling_on_pair(m, k))
            rj__row_coupling(m, R, k, angles, stride, map, dt);
}

/* Whether a pushing-only row's rate has turned against its bound: a contact whose
   impulse may only be negative (its forward limit) holds rates up to its target. */
static int rj__row_violated(const rj__row *row, double rate)
{
    if (row->hi == 0)
        return rate > row->target;
    if (row->lo == 0)
        return rate < row->target;
    return 0;
}

/* Whether an active row's impulse lies outside its bounds (a bounded row that pulls). */
static int rj__row_pulls(const rj__row *row, double lam)
{
    return lam > row->hi || lam < row->lo;
}

/* What the dense solve works in: M's factor, M^-1's columns for the joints (W, n each,
   coordinate j's at W + wcol[j] n: rj_model.wcol), the other rows' M^-1 J^T (Y, n each),
   the system and its factor (S, SL: R x R), vectors (lam, rhs: R; scratch: n), and the row
   a single impulse before the solve already holds exactly (-1: none), which alone needs
   no solve. */
typedef struct rj__dense {
    int n;
    const rj_model *m;
    rj__rig *rig; /* M's factor (rj__rig_factor) */
    double *W, *Y, *S, *SL, *lam, *rhs, *scratch;
    int held;
} rj__dense;

/* A row's M^-1 J^T: W's column for a unit row (made here), else the next column of Y
   (the other rows before it took *others). */
static const double *rj__row_column(const rj__rows *R, const rj__row *row, const rj__dense *D,
                                    int *others)
{
    const int n = D->n;
    double *y, *scratch = D->scratch;
    int k;
    if (rj__row_unit(R, row)) {
        const int j = R->term[row->first].joint;
        y = D->W + (size_t) D->m->wcol[j] * n;
        rj__rig_unit(D->m, D->rig, j, y);
        return y;
    }
    y = D->Y + (size_t) *others * n;
    (*others)++;
    for (k = 0; k < n; k++)
        scratch[k] = 0;
    for (k = 0; k < row->count; k++)
        scratch[R->term[row->first + k].joint] += R->term[row->first + k].coef;
    rj__rig_solve(D->m, D->rig, scratch, y);
    return y;
}

/* The Cholesky factor of the k x k positive semi-definite S into L, a row whose pivot
   falls below 1e-10 of S's largest diagonal dropped (its column of L zero, its diagonal
   0): the rows that repeat others (a parallelogram's loops at its flat position) take no
   impulse, the others what they need. */
static void rj__chol_psd(int k, const double *S, double *L, double largest)
{
    int i, j, p;
    for (i = 0; i < k * k; i++)
        L[i] = 0;
    for (j = 0; j < k; j++) {
        double d = S[(size_t) j * k + j];
        for (p = 0; p < j; p++)
            d -= L[(size_t) j * k + p] * L[(size_t) j * k + p];
        if (!(d > 1e-10 * largest))
            continue;
        L[(size_t) j * k + j] = sqrt(d);
        for (i = j + 1; i < k; i++) {
            double v = S[(size_t) i * k + j];
            for (p = 0; p < j; p++)
                v -= L[(size_t) i * k + p] * L[(size_t) j * k + p];
            L[(size_t) i * k + j] = v / L[(size_t) j * k + j];
        }
    }
}

/* Solves L L^T x = b with rj__chol_psd's factor, x 0 on the dropped rows. */
static void rj__chol_psd_solve(int k, const double *L, const double *b, double *x)
{
    int i, p;
    for (i = 0; i < k; i++) {
        double v = b[i];
        if (L[(size_t) i * k + i] == 0) {
            x[i] = 0;
            continue;
        }
        for (p = 0; p < i; p++)
            v -= L[(size_t) i * k + p] * x[p];
        x[i] = v / L[(size_t) i * k + i];
    }
    for (i = k - 1; i >= 0; i--) {
        double v = x[i];
        if (L[(size_t) i * k + i] == 0)
            continue;
        for (p = i + 1; p < k; p++)
            v -= L[(size_t) p * k + i] * x[p];
        x[i] = v / L[(size_t) i * k + i];
    }
}

/* Whether a Cholesky factor has a pivot below 1e-10 of the largest diagonal (its rows
   nearly repeat each other: the plain solve would give them huge, opposed impulses). */
static int rj__chol_nearly_singular(int k, const double *L, double largest)
{
    int i;
    for (i = 0; i < k; i++)
        if (!(L[(size_t) i * k + i] * L[(size_t) i * k + i] > 1e-10 * largest))
            return 1;
    return 0;
}

/* The active rows' system S lam = target - J q', its factor in SL. Rows that (nearly)
   repeat each other are dropped from it (rj__chol_psd; D->psd says so to the solve).
   Returns the number of active rows. */
static int rj__rows_system(const rj__rows *R, const rj__dense *D, const double *qdp, int *psd)
{
    int a, b, k = 0, row = 0;
    double largest = 0;
    for (a = 0; a < R->count; a++)
        k += R->row[a].active;
    for (a = 0; a < R->count; a++) {
        int c = 0;
        if (!R->row[a].active)
            continue;
        for (b = 0; b < R->count; b++) {
            if (!R->row[b].active)
                continue;
            D->S[(size_t) row * k + c] = rj__row_dot(R, &R->row[a], R->row[b].col);
            c++;
        }
        D->rhs[row] = R->row[a].target - rj__row_dot(R, &R->row[a], qdp);
        if (D->S[(size_t) row * k + row] > largest)
            largest = D->S[(size_t) row * k + row];
        row++;
    }
    *psd = rj__chol(k, D->S, D->SL) || rj__chol_nearly_singular(k, D->SL, largest);
    if (*psd)
        rj__chol_psd(k, D->S, D->SL, largest);
    return k;
}

/* One pass of the dense solve: the active rows' impulses into D->lam; rows that would
   pull leave the set (returns 1: solve again); else the impulses move q' and the rows
   keep them (returns 0). -1: no solution. */
static int rj__rows_pass(rj__rows *R, const rj__dense *D, double *qdp)
{
    const int n = D->n;
    int a, i, k, row = 0, dropped = 0, psd;
    k = rj__rows_system(R, D, qdp, &psd);
    if (psd)
        rj__chol_psd_solve(k, D->SL, D->rhs, D->lam);
    else
        rj__chol_solve(k, D->SL, D->rhs, D->lam);
    for (a = 0; a < R->count; a++) {
        if (!R->row[a].active)
            continue;
        if (rj__row_pulls(&R->row[a], R->row[a].lam + D->lam[row])) {
            R->row[a].active = 0;
            dropped = 1;
        }
        row++;
    }
    if (dropped)
        return 1;
    row = 0;
    for (a = 0; a < R->count; a++) {
        if (!R->row[a].active)
            continue;
        for (i = 0; i < n; i++)
            qdp[i] += R->row[a].col[i] * D->lam[row];
        R->row[a].lam += D->lam[row];
        row++;
    }
    return 0;
}

/* The rows in joint coordinates: passes until no bounded row pulls and none left out
   is violated (at most one pass per row and one more). Returns 0, or -1 when the system
   has no solution. */
static int rj__rows_solve_dense(rj__rows *R, const rj__dense *D, double *qdp)
{
    int a, pass, changed = 1, others = 0;
    for (a = 0; a < R->count; a++)
        R->row[a].col = rj__row_column(R, &R->row[a], D, &others);
    for (pass = 0; pass <= R->count && changed; pass++) {
        int any = 0, step;
        for (a = 0; a < R->count; a++)
            any += R->row[a].active;
        /* none, or only the row a single impulse held exactly */
        if (!any || (any == 1 && D->held >= 0 && R->row[D->held].active))
            return 0;
        step = rj__rows_pass(R, D, qdp);
        if (step < 0)
            return -1;
        changed = step;
        /* rows dropped, q' not moved: solve again without them before asking which rows
           the impulses turn against their bounds (asked of q' before the impulses, a
           row that pulls is dropped and taken back on every pass, and none acts) */
        if (step)
            continue;
        /* a bounded row left out that the impulses turned against its bound joins */
        for (a = 0; a < R->count; a++) {
            rj__row *row = &R->row[a];
            if (row->active || !rj__row_violated(row, rj__row_dot(R, row, qdp)))
                continue;
            row->active = 1;
            changed = 1;
        }
    }
    return 0;
}
/* ------------------------------------------------------------------ assembly */
/* rj_scene_assemble: a user writes approximate angles; this closes the loops. The tree
   (each link hanging from its first joint as body2) places the links from the joints'
   angle0 exactly as rj_model_create does; each joint that closes a loop leaves a gap
   between its pins. The angle0 of the tree joints on the loops, all but each loop's
   first (its input, the crank of a four-bar), move by Gauss-Newton with the least change
   (minimum norm: dq = -J^T (J J^T)^-1 gap, J by central differences; Levenberg-Marquardt
   damping where that step does not shrink the gaps) until every gap is below 1e-13 of
   the longest link; then each loop joint's angle0 is the angle the geometry gives it. A
   loop that cannot close ends at the least gap the links allow, which is reported. */

/* The assembly's working arrays, one block: per link its angle, root, parent joint and
   marks; per joint its unknown's index; the Jacobian, its normal matrix and factor, the
   gaps and the step. */
typedef struct rj__asm {
    const rj_scene_def *sc;
    rj_joint_def *joints;
    double *phi, *rx, *ry;
    int *parent, *placed, *path, *unknown, *marks;
    int nu, nloop;
    double *J, *N, *D, *NL, *gap, *y, *trial;
} rj__asm;

/* Node at of link l's straight placement: its root plus at element lengths. */
static void rj__asm_node(const rj__asm *A, int l, int at, double p[2])
{
    const rj_link_def *d = &A->sc->links[l];
    const double along = d->length / d->elements * at;
    p[0] = A->rx[l] + along * cos(A->phi[l]);
    p[1] = A->ry[l] + along * sin(A->phi[l]);
}

/* Joint j's pin on body 1 and the direction theta is measured from there (ground: the
   fixed point and direction; a link: back towards its root, or along it at node 0). */
static void rj__asm_pin1(const rj__asm *A, int j, double p[2], double *ref)
{
    const rj_joint_def *d = &A->joints[j];
    int at;
    if (d->body1 < 0) {
        p[0] = d->ground_x;
        p[1] = d->ground_y;
        *ref = d->ground_angle;
        return;
    }
    at = d->node1 < 0 ? A->sc->links[d->body1].elements : d->node1;
    rj__asm_node(A, d->body1, at, p);
    *ref = A->phi[d->body1] + (at > 0 ? RJ__PI : 0.0);
}

/* Joint j's pin on body 2. */
static void rj__asm_pin2(const rj__asm *A, int j, double p[2])
{
    const rj_joint_def *d = &A->joints[j];
    rj__asm_node(A, d->body2, d->node2 < 0 ? A->sc->links[d->body2].elements : d->node2, p);
}

/* Link l placed from its parent joint (rj__place_link's geometry), or at its own root. */
static void rj__asm_place_link(rj__asm *A, int l)
{
    const int j = A->parent[l];
    const rj_link_def *ld = &A->sc->links[l];
    double pin[2], ref, along;
    int at;
    if (j < 0) {
        A->phi[l] = ld->angle;
        A->rx[l] = ld->x;
        A->ry[l] = ld->y;
        return;
    }
    rj__asm_pin1(A, j, pin, &ref);
    A->phi[l] = ref + A->joints[j].angle0;
    at = A->joints[j].node2 < 0 ? ld->elements : A->joints[j].node2;
    along = ld->length / ld->elements * at;
    A->rx[l] = pin[0] - along * cos(A->phi[l]);
    A->ry[l] = pin[1] - along * sin(A->phi[l]);
}

/* Every link, parents first (the walk of rj__place_all). */
static void rj__asm_place(rj__asm *A)
{
    const int nl = A->sc->link_count;
    int l;
    for (l = 0; l < nl; l++)
        A->placed[l] = 0;
    for (l = 0; l < nl; l++) {
        int depth = 0, cur = l;
        while (cur >= 0 && !A->placed[cur]) {
            A->path[depth++] = cur;
            cur = A->parent[cur] >= 0 ? A->joints[A->parent[cur]].body1 : -1;
        }
        while (depth > 0) {
            cur = A->path[--depth];
            rj__asm_place_link(A, cur);
            A->placed[cur] = 1;
        }
    }
}

/* Whether joint j closes a loop (its body2 hangs from another joint). */
static int rj__asm_loop(const rj__asm *A, int j)
{
    return A->parent[A->joints[j].body2] != j;
}

/* The gaps pin1 - pin2 of the loop joints, two each, into gap; the largest returned. */
static double rj__asm_gaps(rj__asm *A, double *gap)
{
    double worst = 0;
    int j, k = 0;
    rj__asm_place(A);
    for (j = 0; j < A->sc->joint_count; j++) {
        double p1[2], p2[2], ref;
        if (!rj__asm_loop(A, j))
            continue;
        rj__asm_pin1(A, j, p1, &ref);
        rj__asm_pin2(A, j, p2);
        gap[k] = p1[0] - p2[0];
        gap[k + 1] = p1[1] - p2[1];
        worst = fmax(worst, hypot(gap[k], gap[k + 1]));
        k += 2;
    }
    return worst;
}

/* Marks (1) the tree joints between link l and the ground; returns nothing. A joint seen
   from both sides of a loop (above where they meet) gets 2 and moves nothing in it. */
static void rj__asm_mark_path(rj__asm *A, int l, int *mark)
{
    while (l >= 0 && A->parent[l] >= 0) {
        mark[A->parent[l]]++;
        l = A->joints[A->parent[l]].body1;
    }
}

/* The unknowns: every tree joint on a loop but, when hold, each loop's first (lowest
   index), which keeps its angle0. Returns their count. */
static int rj__asm_unknowns(rj__asm *A, int hold)
{
    const int nj = A->sc->joint_count;
    int j, k, nu = 0;
    for (j = 0; j < nj; j++)
        A->unknown[j] = -2; /* not on a loop */
    for (j = 0; j < nj; j++) {
        int first = -1;
        if (!rj__asm_loop(A, j))
            continue;
        for (k = 0; k < nj; k++)
            A->marks[k] = 0;
        if (A->joints[j].body1 >= 0)
            rj__asm_mark_path(A, A->joints[j].body1, A->marks);
        rj__asm_mark_path(A, A->joints[j].body2, A->marks);
        for (k = 0; k < nj; k++) {
            if (A->marks[k] != 1)
                continue;
            if (first < 0)
                first = k;
            if (A->unknown[k] == -2)
                A->unknown[k] = -1; /* on a loop: an unknown unless some loop holds it */
        }
        if (first >= 0 && hold)
            A->unknown[first] = -3; /* held: the loop's input */
    }
    for (j = 0; j < nj; j++)
        if (A->unknown[j] == -1)
            A->unknown[j] = nu++;
    return nu;
}

/* The Jacobian of the gaps over the unknowns by central differences (1e-7 rad), column
   by column into A->J (rows 2 nloop, stride nu). */
static void rj__asm_jacobian(rj__asm *A)
{
    const int rows = 2 * A->nloop, nu = A->nu;
    const double h = 1e-7;
    int j, k;
    for (j = 0; j < A->sc->joint_count; j++) {
        const int u = A->unknown[j];
        const double keep = A->joints[j].angle0;
        if (u < 0)
            continue;
        A->joints[j].angle0 = keep + h;
        rj__asm_gaps(A, A->trial);
        for (k = 0; k < rows; k++)
            A->J[(size_t) k * nu + u] = A->trial[k];
        A->joints[j].angle0 = keep - h;
        rj__asm_gaps(A, A->trial);
        for (k = 0; k < rows; k++)
            A->J[(size_t) k * nu + u] = (A->J[(size_t) k * nu + u] - A->trial[k]) / (2 * h);
        A->joints[j].angle0 = keep;
    }
}

/* Moves the unknowns by -J^T y (y from rj__asm_step), keeping their angles in trial. */
static void rj__asm_move(rj__asm *A, int rows)
{
    int a, j;
    for (j = 0; j < A->sc->joint_count; j++) {
        double dq = 0;
        const int u = A->unknown[j];
        if (u < 0)
            continue;
        for (a = 0; a < rows; a++)
            dq -= A->J[(size_t) a * A->nu + u] * A->y[a];
        A->trial[rows + u] = A->joints[j].angle0;
        A->joints[j].angle0 += dq;
    }
}

/* One Levenberg-Marquardt step in the gaps' space: (J J^T + lambda) y = gap, dq = -J^T y,
   the least change that closes the gaps for lambda near 0 (Gauss-Newton), a short step
   down the gaps' gradient for lambda large; lambda grows tenfold until the largest gap
   falls (at most 30 times), and the step it took is the next one's start. Returns the
   largest gap after it (the one before when no lambda helps). */
static double rj__asm_step(rj__asm *A, double worst, double *lambda)
{
    const int rows = 2 * A->nloop, nu = A->nu;
    double largest = 0, after;
    int a, b, k, j, tries;
    rj__asm_jacobian(A);
    for (a = 0; a < rows; a++)
        for (b = 0; b < rows; b++) {
            double sum = 0;
            for (k = 0; k < nu; k++)
                sum += A->J[(size_t) a * nu + k] * A->J[(size_t) b * nu + k];
            A->N[(size_t) a * rows + b] = sum;
            largest = a == b ? fmax(largest, sum) : largest;
        }
    for (tries = 0; tries < 30; tries++, *lambda *= 10) {
        memcpy(A->D, A->N, sizeof(double) * (size_t) rows * (size_t) rows);
        for (a = 0; a < rows; a++)
            A->D[(size_t) a * rows + a] += *lambda * largest + 1e-300;
        if (rj__chol(rows, A->D, A->NL))
            continue;
        rj__chol_solve(rows, A->NL, A->gap, A->y);
        rj__asm_move(A, rows);
        after = rj__asm_gaps(A, A->trial);
        if (after < worst) {
            *lambda = fmax(*lambda * 0.01, 1e-14);
            return rj__asm_gaps(A, A->gap);
        }
        for (j = 0; j < A->sc->joint_count; j++)
            if (A->unknown[j] >= 0)
                A->joints[j].angle0 = A->trial[rows + A->unknown[j]];
    }
    return worst;
}

/* The loop joint whose gap is largest, and that gap. */
static int rj__asm_worst(rj__asm *A, double *gap_out)
{
    int j, k = 0, worst = -1;
    double g = -1;
    for (j = 0; j < A->sc->joint_count; j++) {
        double here;
        if (!rj__asm_loop(A, j))
            continue;
        here = hypot(A->gap[k], A->gap[k + 1]);
        if (here > g) {
            g = here;
            worst = j;
        }
        k += 2;
    }
    *gap_out = g;
    return worst;
}

/* Each loop joint's angle0: the angle the closed geometry gives it, the nearest to the
   one written (a whole turn apart at most). */
static void rj__asm_loop_angles(rj__asm *A)
{
    int j;
    rj__asm_place(A);
    for (j = 0; j < A->sc->joint_count; j++) {
        double p[2], ref;
        rj_joint_def *d = &A->joints[j];
        if (!rj__asm_loop(A, j))
            continue;
        rj__asm_pin1(A, j, p, &ref);
        d->angle0 += remainder(A->phi[d->body2] - ref - d->angle0, RJ__TWO_PI);
    }
}

/* Carves the block's arrays (sizes from the scene and its loop count). */
static size_t rj__asm_carve(rj__asm *A, void *block, int nl, int nj, int rows)
{
    double *dd = (double *) block;
    int *ii;
    const size_t doubles = 3 * (size_t) nl + (size_t) rows * (size_t) nj +
                           3 * (size_t) rows * (size_t) rows + 3 * (size_t) rows + (size_t) nj;
    if (!block)
        return doubles * sizeof(double) + 6 * ((size_t) nl + (size_t) nj + 1) * sizeof(int);
    A->phi = dd;
    A->rx = A->phi + nl;
    A->ry = A->rx + nl;
    A->J = A->ry + nl;
    A->N = A->J + (size_t) rows * (size_t) nj;
    A->D = A->N + (size_t) rows * (size_t) rows;
    A->NL = A->D + (size_t) rows * (size_t) rows;
    A->gap = A->NL + (size_t) rows * (size_t) rows;
    A->y = A->gap + rows;
    A->trial = A->y + rows;
    ii = (int *) (void *) (A->trial + rows + nj);
    A->parent = ii;
    A->placed = A->parent + nl;
    A->path = A->placed + nl;
    A->unknown = A->path + nl;
    A->marks = A->unknown + nj;
    return 0;
}

/* The parents (each link's first joint as body2) and the loop count. */
static int rj__asm_tree(rj__asm *A)
{
    int j, l, loops = 0;
    for (l = 0; l < A->sc->link_count; l++)
        A->parent[l] = -1;
    for (j = 0; j < A->sc->joint_count; j++) {
        int *p = &A->parent[A->joints[j].body2];
        if (*p < 0)
            *p = j;
        else
            loops++;
    }
    return loops;
}

/* Newton to 1e-13 of the longest link (100 steps at most); RJ_ERR_INVALID naming the
   loop that stays open. */
static rj_result rj__asm_solve(rj__asm *A, rj_error *err)
{
    double longest = 0, worst, gap, lambda = 1e-14;
    int l, it, j;
    char f[64];
    for (l = 0; l < A->sc->link_count; l++)
        longest = fmax(longest, A->sc->links[l].length);
    worst = rj__asm_gaps(A, A->gap);
    for (it = 0; it < 200 && worst > 1e-13 * longest && A->nu > 0; it++) {
        const double before = worst;
        worst = rj__asm_step(A, worst, &lambda);
        if (!(worst < before))
            break;
    }
    if (worst <= 1e-13 * longest) {
        rj__asm_loop_angles(A);
        return RJ_OK;
    }
    j = rj__asm_worst(A, &gap);
    RJ__FIELD(f, "joints[%d]", j);
    rj__fail(err, RJ_ERR_INVALID, f, gap,
             "the loop that joints[%d] closes cannot close: its pins stay %.6g m apart at best "
             "(the links between them too short or too long for where the loop's other joints "
             "are)",
             j, gap);
    return RJ_ERR_INVALID;
}

RJDEF rj_result rj_scene_assemble(const rj_scene_def *scene, rj_joint_def *joints,
                                  rj_error *err)
{
    rj__asm A;
    rj_scene_def copy;
    rj_result r;
    void *block;
    int rows;
    if (!scene || !joints) {
        rj__fail(err, RJ_ERR_INVALID, scene ? "joints" : "scene", 0, "%s is NULL",
                 scene ? "joints" : "scene");
        return RJ_ERR_INVALID;
    }
    copy = *scene;
    copy.joints = joints;
    r = rj__validate_all(&copy, err, NULL);
    if (r != RJ_OK)
        return r;
    memset(&A, 0, sizeof A);
    A.sc = &copy;
    A.joints = joints;
    rows = 2 * scene->joint_count;
    block = RJ_MALLOC(rj__asm_carve(&A, NULL, scene->link_count, scene->joint_count, rows), NULL);
    if (!block) {
        rj__fail(err, RJ_ERR_NOMEM, "joint_count", scene->joint_count,
                 "could not allocate the assembly's arrays");
        return RJ_ERR_NOMEM;
    }
    rj__asm_carve(&A, block, scene->link_count, scene->joint_count, rows);
    A.nloop = rj__asm_tree(&A);
    A.nu = rj__asm_unknowns(&A, 1);
    r = A.nloop ? rj__asm_solve(&A, err) : RJ_OK;
    RJ_FREE(block, NULL);
    return r;
}

/* The rank of the rows x cols matrix J (stride cols) by Gaussian elimination with partial
   pivoting, an entry below 1e-9 of J's largest counting as 0. Destroys J. */
static int rj__asm_rank(double *J, int rows, int cols)
{
    double largest = 0;
    int rank = 0, c, r, k, p;
    for (k = 0; k < rows * cols; k++)
        largest = fmax(largest, fabs(J[k]));
    for (c = 0; c < cols && rank < rows; c++) {
        for (p = rank, r = rank + 1; r < rows; r++)
            if (fabs(J[(size_t) r * cols + c]) > fabs(J[(size_t) p * cols + c]))
                p = r;
        if (!(fabs(J[(size_t) p * cols + c]) > 1e-9 * largest))
            continue;
        for (k = 0; k < cols; k++) {
            const double t = J[(size_t) p * cols + k];
            J[(size_t) p * cols + k] = J[(size_t) rank * cols + k];
            J[(size_t) rank * cols + k] = t;
        }
        for (r = rank + 1; r < rows; r++) {
            const double f = J[(size_t) r * cols + c] / J[(size_t) rank * cols + c];
            for (k = c; k < cols; k++)
                J[(size_t) r * cols + k] -= f * J[(size_t) rank * cols + k];
        }
        rank++;
    }
    return rank;
}

/* The tree's freedom as rigid bars: one a hanging link, three a free root link, one a
   pinned root. */
static int rj__asm_tree_freedom(const rj__asm *A)
{
    int l, dof = 0;
    for (l = 0; l < A->sc->link_count; l++) {
        const int root = A->sc->links[l].root;
        if (A->parent[l] >= 0)
            dof += 1;
        else if (root == RJ_ROOT_FREE)
            dof += 3;
        else if (root == RJ_ROOT_PINNED)
            dof += 1;
    }
    return dof;
}

RJDEF rj_result rj_scene_mobility(const rj_scene_def *scene, int *mobility, int *rank,
                                  rj_error *err)
{
    rj__asm A;
    rj_joint_def *joints;
    rj_scene_def copy;
    rj_result r;
    void *block;
    const int rows = scene ? 2 * scene->joint_count : 0;
    size_t arrays;
    if (!scene || !mobility || !rank) {
        rj__fail(err, RJ_ERR_INVALID, !scene ? "scene" : !mobility ? "mobility" : "rank", 0,
                 "%s is NULL", !scene ? "scene" : !mobility ? "mobility" : "rank");
        return RJ_ERR_INVALID;
    }
    r = rj__validate_all(scene, err, NULL);
    if (r != RJ_OK)
        return r;
    memset(&A, 0, sizeof A);
    /* the arrays, then the joints' copy (the Jacobian turns their angle0 and back) */
    arrays = (rj__asm_carve(&A, NULL, scene->link_count, scene->joint_count, rows) + 15) /
             16 * 16;
    block = RJ_MALLOC(arrays + sizeof(rj_joint_def) * ((size_t) scene->joint_count + 1), NULL);
    if (!block) {
        rj__fail(err, RJ_ERR_NOMEM, "joint_count", scene->joint_count,
                 "could not allocate the mobility's arrays");
        return RJ_ERR_NOMEM;
    }
    joints = (rj_joint_def *) (void *) ((char *) block + arrays);
    memcpy(joints, scene->joints, sizeof(rj_joint_def) * (size_t) scene->joint_count);
    copy = *scene;
    copy.joints = joints;
    A.sc = &copy;
    A.joints = joints;
    rj__asm_carve(&A, block, scene->link_count, scene->joint_count, rows);
    A.nloop = rj__asm_tree(&A);
    A.nu = rj__asm_unknowns(&A, 0);
    *rank = 0;
    if (A.nloop && A.nu) {
        rj__asm_jacobian(&A);
        *rank = rj__asm_rank(A.J, 2 * A.nloop, A.nu);
    }
    *mobility = rj__asm_tree_freedom(&A) - *rank;
    RJ_FREE(block, NULL);
    return RJ_OK;
}
/* ------------------------------------------------------------------ the step: its stages */
/* A node's rotation rate at the end of the step under the loads so far (a body's own node:
   the body's). */
static RJ__INLINE double rj__rate_pred(const rj_model *m, const double *of, int n, const double *x,
                                       const double *y, const double *w, const double *fx,
                                       const double *fy, const double *mz, double kick)
{
    if (m->ncl && RJ__CL_RIGID(m, n)) {
        const int c = m->node_cl[n];
        const double *oc = RJ__FCL(m, of, c);
        double Fx, Fy, T;
        if (m->cl_fix[c] == 2)
            return 0.0;
        rj__cl_load(m, c, oc, x, y, fx, fy, mz, &Fx, &Fy, &T);
        return oc[4] + kick * T / m->cl_I[c];
    }
    return w[n] + kick * mz[n] * m->rinv[n];
}

/* The frames one step reads and writes. Double-buffered, the step reads the current frame
   and writes the other; in place (rj__step), the nodes and elements advance in the current
   frame itself, and the third frame (s->fd[2]) takes the joints, bodies and scalars at
   n + 1 and keeps the values at n of the nodes the step reads after the beams (m->dnode). */
typedef struct rj__frames {
    double *current;      /* s->fd[s->cur] */
    const double *old;    /* the values at n: the current frame */
    double *next;         /* joints, bodies and scalars at n + 1 */
    double *advanced;     /* nodes and elements at n + 1: next, or current in place */
    const int *old_flags; /* joint flags at n */
    int *new_flags;       /* at n + 1 */
    const double *x, *y, *phi, *vx, *vy, *w; /* nodes at n (in place: from next) */
    double *nx, *ny, *nphi, *nvx, *nvy, *nw; /* nodes at n + 1 */
    const double *old_scalars;               /* time, accounts at n */
    double *new_scalars;                     /* at n + 1 */
    double t, dt;
    double kick; /* dt, or dt / 2 at the first step (from v(0)) */
    int first;   /* the first step */
    int en;      /* this step takes the energy accounts */
    int ip;      /* in place */
} rj__frames;

/* What a step adds up for the energy accounts, in J. */
typedef struct rj__sums {
    double strain;                                  /* the beams' strain energy at x^n */
    double spring;                                  /* the joints' springs and tables at n */
    double gravity;                                 /* gravity's potential at n, -sum m g . x */
    double kinetic;                                 /* 1/2 v^{n-1/2} . v^{n+1/2} */
    double lost_damping, lost_friction, lost_limit; /* since the start */
    double lost_material; /* the links' structural damping and plastic work since the start */
    double work;    /* done by the caller's inputs since the start */
    double drive;   /* done by the actuators since the start */
    double drive_pending; /* a prescribed joint's impulse's work the next step takes */
    double drive_flow;    /* the actuators' work moved, sum of |its change| (a scale) */
    double pending; /* a jump's loss the next step takes (its second half) */
} rj__sums;

/* The first moment sum m r of a rigid body's own link (rod and tip mass) at node
   positions x, y; its nodes carry no mass of their own. */
static void rj__cl_own_moment(const rj_model *m, int c, const double *x, const double *y,
                              double *mx, double *my)
{
    const rj_link_def *d = &m->ldef[c];
    const int n0 = m->link_first[c], nt = m->link_first[c + 1] - 1;
    const double area = rj__plain_area(d);
    const double rod = d->rho * area * d->length, own = rod + d->tip_mass;
    const double along = (rod * 0.5 + d->tip_mass) / own; /* the centre, as a fraction */
    *mx = own * (x[n0] + along * (x[nt] - x[n0]));
    *my = own * (y[n0] + along * (y[nt] - y[n0]));
}

/* The frames and step constants: the accounts when asked, at the start, or
   solver.energy_every steps after the last ones (no division). The nodes' arrays are
   rj__frames_nodes'. */
static RJ__FORCE_INLINE void rj__frames_open(const rj_model *m, rj_state *s, int want_energy,
                                             int ip, rj__frames *f)
{
    double *current = s->fd[s->cur];
    double *next = s->fd[ip ? 2 : 1 - s->cur];
    f->current = current;
    f->old = current;
    f->next = next;
    f->advanced = ip ? current : next;
    f->old_flags = s->fi[s->cur];
    f->new_flags = s->fi[ip ? 2 : 1 - s->cur];
    f->old_scalars = RJ__FS(m, current);
    f->new_scalars = RJ__FS(m, next);
    f->t = f->old_scalars[RJ__FS_TIME];
    f->dt = m->dt;
    f->first = s->steps == 0;
    /* the stored velocities are v(0) at the start and v^{n-1/2} after: the first kick is
       half a step, which makes the start second-order accurate too */
    f->kick = f->first ? 0.5 * m->dt : m->dt;
    f->en = want_energy || m->solver.energy_every <= 1 || s->steps == 0 ||
            f->t - f->old_scalars[RJ__FS_ETIME] > ((double) m->solver.energy_every - 0.5) * m->dt;
    f->ip = ip;
}

/* The nodes at n (in place: kept in the next frame) and at n + 1. */
static RJ__FORCE_INLINE void rj__frames_nodes(const rj_model *m, rj__frames *f)
{
    const double *at_n = f->ip ? f->next : f->current;
    double *advanced = f->advanced;
    f->x = RJ__FX(m, at_n);
    f->y = RJ__FY(m, at_n);
    f->phi = RJ__FPHI(m, at_n);
    f->vx = RJ__FVX(m, at_n);
    f->vy = RJ__FVY(m, at_n);
    f->w = RJ__FW(m, at_n);
    f->nx = RJ__FX(m, advanced);
    f->ny = RJ__FY(m, advanced);
    f->nphi = RJ__FPHI(m, advanced);
    f->nvx = RJ__FVX(m, advanced);
    f->nvy = RJ__FVY(m, advanced);
    f->nw = RJ__FW(m, advanced);
}

/* The accounts carried from the step before. */
static RJ__FORCE_INLINE void rj__sums_open(const double *old_scalars, rj__sums *e)
{
    e->strain = 0;
    e->spring = 0;
    e->gravity = 0;
    e->kinetic = 0;
    e->lost_damping = old_scalars[RJ__FS_LDAMP];
    e->lost_friction = old_scalars[RJ__FS_LFRIC];
    e->lost_limit = old_scalars[RJ__FS_LLIM] + old_scalars[RJ__FS_PEND];
    e->lost_material = 0;
    e->work = old_scalars[RJ__FS_WORK];
    e->drive = old_scalars[RJ__FS_DRIVE] + old_scalars[RJ__FS_DPEND];
    e->drive_pending = 0;
    e->drive_flow = old_scalars[RJ__FS_DFLOW];
    e->pending = 0;
}

/* The step's links on the material path, from the frame at n (old) into the advanced
   one (their plastic strains into next's block), before the fused pass, out of line. It
   takes a copy of the step's update, never its address, and returns the sum of the
   positions it wrote (rj__adv.fin): the address of the step's own record, given to it,
   cost the step 60 instructions on the paper's deployment, which has no such links. */
static RJ__NOINLINE double rj__beam_material_step(const rj_model *m, rj_state *s,
                                                  const double *old, double *advanced,
                                                  double *next, rj__adv adv)
{
    double fin = 0;
    adv.fin = &fin;
    adv.damp = s->damp;
    rj__beam_material_links(m, RJ__FX(m, old), RJ__FY(m, old), RJ__FPHI(m, old),
                            RJ__FBETA(m, old), RJ__FCX(m, old), RJ__FCY(m, old), s->eu,
                            RJ__FBETA(m, advanced), RJ__FCX(m, advanced), RJ__FCY(m, advanced),
                            s->fx, s->fy, s->mz, &adv, old + m->pl_off, next + m->pl_off);
    return fin;
}

/* Stage 1, the beams: internal forces at x^n and the new chord angles; every node advanced
   at once (v^{n+1/2}, x^{n+1}); the joints' nodes are advanced again in stage 4 (in place,
   from their values at n, kept first). */
static RJ__FORCE_INLINE void rj__stage_beams(const rj_model *m, rj_state *s, const rj__frames *f,
                                             rj__adv *adv, rj__sums *e)
{
    const double *old = f->old;
    double *next = f->next;
    /* gravity's potential at x^n, before the pass advances the nodes (in place too) */
    if (m->has_gravity && f->en)
        e->gravity = rj__gravity_potential(m, RJ__FX(m, old), RJ__FY(m, old));
    if (f->ip) {
        double *kept[6];
        const double *at_n[6];
        int i, k;
        kept[0] = RJ__FX(m, next);
        kept[1] = RJ__FY(m, next);
        kept[2] = RJ__FPHI(m, next);
        kept[3] = RJ__FVX(m, next);
        kept[4] = RJ__FVY(m, next);
        kept[5] = RJ__FW(m, next);
        at_n[0] = RJ__FX(m, old);
        at_n[1] = RJ__FY(m, old);
        at_n[2] = RJ__FPHI(m, old);
        at_n[3] = RJ__FVX(m, old);
        at_n[4] = RJ__FVY(m, old);
        at_n[5] = RJ__FW(m, old);
        for (i = 0; i < m->ndn; i++)
            for (k = 0; k < 6; k++)
                kept[k][m->dnode[i]] = at_n[k][m->dnode[i]];
    }
    adv->kick = f->kick;
    adv->dt = f->dt;
    adv->vx = RJ__FVX(m, old);
    adv->vy = RJ__FVY(m, old);
    adv->w = RJ__FW(m, old);
    adv->ti = m->tinv;
    adv->ri = m->rinv;
    adv->km = m->kmass;
    adv->kj = m->krot;
    adv->nx = f->nx;
    adv->ny = f->ny;
    adv->nphi = f->nphi;
    adv->nvx = f->nvx;
    adv->nvy = f->nvy;
    adv->nw = f->nw;
    adv->kn = s->kn;
    adv->fx = s->fx;
    adv->fy = s->fy;
    adv->mz = s->mz;
    adv->en = f->en;
    adv->ip = f->ip;
    adv->grav = m->has_gravity;
    adv->gx = m->solver.gravity[0];
    adv->gy = m->solver.gravity[1];
    if (m->nmaterial)
        *adv->fin += rj__beam_material_step(m, s, old, f->advanced, next, *adv);
    e->strain =
        rj__beam_pass(m, RJ__FX(m, old), RJ__FY(m, old), RJ__FPHI(m, old), RJ__FBETA(m, old),
                      RJ__FCX(m, old), RJ__FCY(m, old), s->eu, RJ__FBETA(m, f->advanced),
                      RJ__FCX(m, f->advanced), RJ__FCY(m, f->advanced), s->fx, s->fy, s->mz, adv);
    /* stage 4 advances the joints' nodes from their values at n */
    adv->vx = f->vx;
    adv->vy = f->vy;
    adv->w = f->w;
}

/* The joint geometry stage 2 kept. */
static RJ__FORCE_INLINE void rj__kept_geo(const double *kept, rj__jgeo *g)
{
    g->ax = kept[0];
    g->ay = kept[1];
    g->bx = kept[2];
    g->by = kept[3];
    g->a2 = kept[6];
    g->b2 = kept[7];
}

/* Stage 2 of scenes with couplings: each cable loop's torques on its two joints' nodes,
   from their running angles at n and the rates the element read (kept in s->jsc); returns
   the loops' energy. Apart (not inlined, given the frames' pointers, not their record,
   whose address would keep it out of registers): a scene without loops pays one test. */
static RJ__NOINLINE double rj__stage_couplings(const rj_model *m, rj_state *s, const double *old,
                                               double *next)
{
    double energy = 0;
    int k;
    for (k = 0; k < m->ncp; k++) {
        const rj_coupling_def *c = &m->cp[k];
        const double *kept_a = s->jsc + 8 * c->joint_a, *kept_b = s->jsc + 8 * c->joint_b;
        double *rec_a = RJ__FJ(m, next, c->joint_a), *rec_b = RJ__FJ(m, next, c->joint_b);
        double elastic, damp, on_b;
        rj__jgeo g;
        rj__coupling_torques(m, c, RJ__FJ(m, old, c->joint_a)[RJ__JD_THETA],
                             RJ__FJ(m, old, c->joint_b)[RJ__JD_THETA], kept_a[4], kept_b[4],
                             &elastic, &damp, &energy);
        on_b = rj__coupling_record(c, elastic, damp, rec_a, rec_b);
        rj__kept_geo(kept_b, &g);
        rj__apply_torque(&m->jnt[c->joint_b], &g, on_b, s->fx, s->fy, s->mz);
        rj__kept_geo(kept_a, &g);
        rj__apply_torque(&m->jnt[c->joint_a], &g, -c->ratio * on_b, s->fx, s->fy, s->mz);
    }
    return energy;
}

/* Stage 2, the joints' element: rate, flag (Eqs 7-13), table, spring, damping and limit
   torques (Eqs 4, 22, 27) on the nodes; the geometry and rate kept in s->jsc for the
   stages after. */
static RJ__FORCE_INLINE void rj__stage_joint_torques(const rj_model *m, rj_state *s,
                                                     const rj__frames *f, rj__sums *e)
{
    /* the element sums the springs' energy through a pointer: a local of its own keeps the
       other sums out of memory */
    double spring = e->spring;
    int j;
    f->new_scalars[RJ__FS_WARN] = f->old_scalars[RJ__FS_WARN];
    for (j = 0; j < m->nj; j++) {
        const rj__joint *J = &m->jnt[j];
        const double *old_joint = RJ__FJ(m, f->old, j);
        double *new_joint = RJ__FJ(m, f->next, j);
        double *kept = s->jsc + 8 * j;
        rj__jgeo g;
        double rate, penetration, torque;
        rj__joint_geo(m, J, f->x, f->y, &g);
        rate = rj__joint_rate(J, &g, f->vx, f->vy, f->w, NULL, NULL);
        torque = rj__element(m, s, j, old_joint, new_joint, f->old_flags[j], &f->new_flags[j], rate,
                             f->t, f->new_scalars, &penetration, &spring);
        rj__apply_torque(J, &g, torque, s->fx, s->fy, s->mz);
        kept[0] = g.ax;
        kept[1] = g.ay;
        kept[2] = g.bx;
        kept[3] = g.by;
        kept[4] = rate;
        kept[5] = penetration;
        kept[6] = g.a2;
        kept[7] = g.b2;
    }
    e->spring = spring;
}


/* A node's velocity at the end of the step under the forces so far (a grouped node: its
   group's, gravity on it as rj__update_groups adds it: the members' forces do not hold
   it, while a node that moves on its own has it in its force). */
static RJ__FORCE_INLINE void rj__velocity_pred(const rj_model *m, const rj_state *s,
                                               const rj__frames *f, int n, double *pvx, double *pvy)
{
    const double kick = f->kick;
    if (m->tinv[n] == 0 && m->einv[n] > 0) {
        /* grouped node: the group's acceleration */
        double sx = 0, sy = 0, ginv = m->einv[n];
        const int g0 = m->node_grp[n];
        int q;
        for (q = m->grp_first[g0]; q < m->grp_first[g0 + 1]; q++) {
            sx += s->fx[m->grp_node[q]];
            sy += s->fy[m->grp_node[q]];
        }
        *pvx = f->vx[n] + kick * sx * ginv + kick * m->solver.gravity[0];
        *pvy = f->vy[n] + kick * sy * ginv + kick * m->solver.gravity[1];
    } else {
        *pvx = f->vx[n] + kick * s->fx[n] * m->tinv[n];
        *pvy = f->vy[n] + kick * s->fy[n] * m->tinv[n];
    }
}

/* The relative rate joint J would end the step with under the forces so far. */
static RJ__FORCE_INLINE double rj__joint_rate_pred(const rj_model *m, const rj_state *s,
                                                   const rj__frames *f, const rj__joint *J,
                                                   const rj__jgeo *g)
{
    double pvx[4], pvy[4], ratep;
    int nodes[4], k;
    if (!J->chord) {
        ratep = rj__rate_pred(m, f->old, J->nJ, f->x, f->y, f->w, s->fx, s->fy, s->mz, f->kick);
        if (J->nI >= 0)
            ratep -=
                rj__rate_pred(m, f->old, J->nI, f->x, f->y, f->w, s->fx, s->fy, s->mz, f->kick);
        return ratep;
    }
    nodes[0] = J->nI;
    nodes[1] = J->nK;
    nodes[2] = J->nJ;
    nodes[3] = J->nL;
    for (k = 0; k < 4; k++) {
        if (nodes[k] < 0) {
            pvx[k] = pvy[k] = 0;
            continue;
        }
        rj__velocity_pred(m, s, f, nodes[k], &pvx[k], &pvy[k]);
    }
    ratep = (g->bx * (pvy[3] - pvy[2]) - g->by * (pvx[3] - pvx[2])) / g->b2;
    if (J->nK >= 0)
        ratep -= (g->ax * (pvy[1] - pvy[0]) - g->ay * (pvx[1] - pvx[0])) / g->a2;
    return ratep;
}

/* The caller's torques are numbers the step can use: finite, within 1e100 N m (the
   checkpoints' bound). Else the step stops naming the joint, the state as it was. */
static int rj__inputs_ok(const rj_model *m, rj_state *s)
{
    int j;
    for (j = 0; j < m->nj; j++) {
        const double torque = s->input_torque[j];
        if (fabs(torque) <= 1e100)
            continue;
        rj__stop(m, s, RJ_ERR_INVALID,
                 "t = %.9g s: rj_state_joint_torques()[%d] = %g N m is not a finite torque "
                 "within 1e100 N m",
                 RJ__FS(m, s->fd[s->cur])[RJ__FS_TIME], j, torque);
        return 0;
    }
    return 1;
}

/* The caller's joint torques (rj_state_joint_torques, checked by rj__step before the
   step began), on the joint geometry stage 2 kept. */
static void rj__stage_inputs(const rj_model *m, rj_state *s, double *next)
{
    int j;
    for (j = 0; j < m->nj; j++) {
        const double torque = s->input_torque[j];
        rj__jgeo g;
        rj__kept_geo(s->jsc + 8 * j, &g);
        rj__apply_torque(&m->jnt[j], &g, torque, s->fx, s->fy, s->mz);
        RJ__FJ(m, next, j)[RJ__JD_INPUT] = torque;
    }
}

/* The work of the caller's joint torques over the step (after the velocity-level limits,
   which set the joints' rates at n + 1/2). */
static double rj__inputs_work(const rj_model *m, const rj_state *s, const double *old,
                              const double *next)
{
    double work = 0;
    int j;
    for (j = 0; j < m->nj; j++)
        work += rj__input_work(RJ__FJ(m, old, j), RJ__FJ(m, next, j), s->jsc[8 * j + 4], m->dt);
    return work;
}

/* A load's factor at time t: its table, linear between the points, held outside them
   (1 without a table). */
static double rj__load_factor(const rj_load_def *d, double t)
{
    return rj__time_factor(d->table_count, d->table_time, d->table_factor, t);
}

/* A load's force (global frame) and moment at time t on a node turned to phi: a follower
   load's force is given in the node's frame and turns with it. */
static void rj__load_value(const rj_load_def *d, double t, double phi, double out[3])
{
    const double scale = rj__load_factor(d, t);
    const double fx = scale * d->force[0], fy = scale * d->force[1];
    if (d->follower) {
        const double c = cos(phi), s = sin(phi);
        out[0] = c * fx - s * fy;
        out[1] = s * fx + c * fy;
    } else {
        out[0] = fx;
        out[1] = fy;
    }
    out[2] = scale * d->moment;
}

/* The work of a force and moment held at node n over the step, now at t^n and prev at
   t^{n-1}: (prev + now) / 2 . (x^n - x^{n-1}), the trapezoid whose sum is exactly the
   change it makes in the kinetic energy of the central-difference pair (as
   rj__input_work); at_n: the frame of the nodes at n (v^{n-1/2}). */
static double rj__node_work(const rj_model *m, const double *at_n, int n, const double *now,
                            const double *prev)
{
    const double vx = RJ__FVX(m, at_n)[n], vy = RJ__FVY(m, at_n)[n], w = RJ__FW(m, at_n)[n];
    return 0.5 * m->dt *
           ((now[0] + prev[0]) * vx + (now[1] + prev[1]) * vy + (now[2] + prev[2]) * w);
}

/* Stage 2c, the model's applied loads at t^n on their nodes (the step advances them after
   the joints: m->dnode); returns their work over the step before (the loads at t^{n-1}
   are their definitions' at t - dt, on the node turned back by dt w^{n-1/2}). */
static double rj__stage_loads(const rj_model *m, rj_state *s, double t, const double *at_n)
{
    const double *phi = RJ__FPHI(m, at_n), *w = RJ__FW(m, at_n);
    double work = 0;
    int k;
    for (k = 0; k < m->nload; k++) {
        const int n = m->load_node[k];
        double now[3], prev[3];
        rj__load_value(&m->load[k], t, phi[n], now);
        rj__load_value(&m->load[k], t - m->dt, phi[n] - m->dt * w[n], prev);
        s->fx[n] += now[0];
        s->fy[n] += now[1];
        s->mz[n] += now[2];
        work += rj__node_work(m, at_n, n, now, prev);
    }
    return work;
}

/* A caller's node force that is not a number the step can use (finite, within 1e100, the
   checkpoints' bound) stops the step, naming it, the state as it was. */
static int rj__node_input_ok(const rj_model *m, rj_state *s, int n)
{
    const double *in = s->input_node + 3 * (size_t) n;
    int k;
    for (k = 0; k < 3; k++) {
        if (fabs(in[k]) <= 1e100)
            continue;
        rj__stop(m, s, RJ_ERR_INVALID,
                 "t = %.9g s: rj_state_node_forces()[%d] = %g (node %d, %s) is not a finite "
                 "value within 1e100",
                 RJ__FS(m, s->fd[s->cur])[RJ__FS_TIME], 3 * n + k, in[k], n,
                 k == 2 ? "moment, N m" : "force, N");
        return 0;
    }
    return 1;
}

/* The node forces' sizes now and at the last step, summed: 0 when there are none to
   apply nor to account for (NaN for a NaN: the stage then refuses it). Branch-free, as most
   nodes of most states have none. */
static RJ__INLINE double rj__node_input_size(const double *in, const double *prev)
{
    return (fabs(in[0]) + fabs(in[1])) + (fabs(in[2]) + fabs(prev[0])) +
           (fabs(prev[1]) + fabs(prev[2]));
}

/* A force in (fx, fy, mz) on node i, which the beam pass has advanced already (not in
   m->dnode): v^{n+1/2} takes kick f / m on top (nothing on a grouped node's translation,
   which its group's stage gives: tinv 0), x^{n+1} follows, and the node's share of the
   kinetic energy the matching v^{n-1/2} . kick f. at_n, advanced: the frames of the
   nodes at n and at n + 1 (rj__frames_nodes). Returns the new position's x + y + phi. */
static double rj__node_kick(const rj_model *m, rj_state *s, int i, const double *in,
                            const double *at_n, double *advanced, double kick)
{
    const double dvx = kick * in[0] * m->tinv[i];
    const double dvy = kick * in[1] * m->tinv[i];
    const double dw = kick * in[2] * m->rinv[i];
    const double vx = RJ__FVX(m, at_n)[i], vy = RJ__FVY(m, at_n)[i], w = RJ__FW(m, at_n)[i];
    double *nx = RJ__FX(m, advanced), *ny = RJ__FY(m, advanced), *nphi = RJ__FPHI(m, advanced);
    double *nvx = RJ__FVX(m, advanced), *nvy = RJ__FVY(m, advanced), *nw = RJ__FW(m, advanced);
    s->kn[i] += m->kmass[i] * (vx * dvx + vy * dvy) + m->krot[i] * w * dw;
    nvx[i] += dvx;
    nvy[i] += dvy;
    nw[i] += dw;
    nx[i] += m->dt * dvx;
    ny[i] += m->dt * dvy;
    nphi[i] += m->dt * dw;
    return (nx[i] + ny[i]) + nphi[i];
}

/* Stage 2d, the caller's node forces, only where they or the last step's are not zero:
   with the joints' forces on the nodes the step advances after the joints (m->dnode); as
   a kick on the others, which the beam pass has advanced (their sum of new positions
   into s->step_fin). Their work over the step before, with the forces the last step
   applied (s->node_applied), into s->step_work. */
static rj_result rj__stage_node_inputs(const rj_model *m, rj_state *s, const double *at_n,
                                       double *advanced, double kick)
{
    double work = 0, fin = 0;
    int i;
    for (i = 0; i < m->nn; i++) {
        const double *in = s->input_node + 3 * (size_t) i;
        const double *prev = s->node_applied + 3 * (size_t) i;
        if (rj__node_input_size(in, prev) == 0)
            continue;
        if (!rj__node_input_ok(m, s, i))
            return RJ_ERR_INVALID;
        work += rj__node_work(m, at_n, i, in, prev);
        if (!rj__is_dnode(m, i)) {
            fin += rj__node_kick(m, s, i, in, at_n, advanced, kick);
            continue;
        }
        s->fx[i] += in[0];
        s->fy[i] += in[1];
        s->mz[i] += in[2];
    }
    s->step_fin = fin;
    s->step_work += work;
    return RJ_OK;
}

static double rj__stage_viscous(const rj_model *m, rj_state *s, const rj__frames *f);

/* Stage 2b, applied loads: the caller's joint torques, the model's loads and the
   caller's node forces, in that order, before friction so that it sees them; the work of
   the last two over the step before in s->step_work; then the links' implicit damping
   (stage 2e), which sees them all, on frames of its own (never in place). next: the new
   frame; t: the time at n; at_n, advanced: the frames of the nodes at n and n + 1; kick:
   the step's velocity kick per unit acceleration. This stage and rj__applied_work take
   plain values, not the step's frames, and are never inlined: a scene that applies
   nothing pays one test for both (the frames' address, given to the damping, cost the
   paper's step 15 instructions). */
static RJ__NOINLINE rj_result rj__stage_applied(const rj_model *m, rj_state *s, double *next,
                                                double t, const double *at_n, double *advanced,
                                                double kick)
{
    s->step_work = 0;
    s->step_fin = 0;
    if (s->inputs)
        rj__stage_inputs(m, s, next);
    if (m->nload)
        s->step_work += rj__stage_loads(m, s, t, at_n);
    if (s->node_inputs) {
        const rj_result r = rj__stage_node_inputs(m, s, at_n, advanced, kick);
        if (r != RJ_OK)
            return r;
    }
    if (m->nvisc) {
        rj__frames f;
        rj__frames_open(m, s, 0, 0, &f);
        rj__frames_nodes(m, &f);
        s->step_fin += rj__stage_viscous(m, s, &f);
    }
    return RJ_OK;
}

/* The work of the caller's joint torques over the step (after the velocity-level limits,
   which set the joints' rates): old, next: the frames at n and n + 1. */
static RJ__NOINLINE double rj__applied_work(const rj_model *m, const rj_state *s, const double *old,
                                            const double *next)
{
    return s->inputs ? rj__inputs_work(m, s, old, next) : 0.0;
}

/* Node n's translation as the stages after this one move it: a grouped node's is its
   group's (rj__update_groups: the members' summed force and gravity on the summed mass),
   a node the step advances again (m->dnode) takes its force then; the others the beam
   pass has advanced. Into v (x, y) and minv (their inverse mass, 0: fixed). */
static void rj__visc_translation(const rj_model *m, const rj_state *s, const rj__frames *f,
                                 int n, int again, double v[2], double minv[2])
{
    minv[0] = minv[1] = m->einv[n];
    if (again || (m->tinv[n] == 0 && m->einv[n] > 0)) {
        rj__velocity_pred(m, s, f, n, &v[0], &v[1]);
        return;
    }
    v[0] = f->nvx[n];
    v[1] = f->nvy[n];
}

/* A node's rotation rate as predicted (rj__rate_pred; none: the ground's, 0). */
static double rj__visc_rate_pred(const rj_model *m, const rj_state *s, const rj__frames *f,
                                 int n)
{
    if (n < 0)
        return 0.0;
    return rj__rate_pred(m, f->old, n, f->x, f->y, f->w, s->fx, s->fy, s->mz, f->kick);
}

/* Element i's chord at n + 1/2 as v* predicts it, e^n + dt/2 (v*_b - v*_a), into its
   record. The strains' rates are taken along it: at e^n, a link turning rigidly at
   omega showed an axial rate of omega^2 dt / 2 relative (v^{n+1/2} is square to the
   chord half a step on), which the axial viscosity eta EA made a force of 15 % of the
   centrifugal pull on the chain of `make bench`'s feature rows; along the midpoint chord
   a rigid turn has none. */
static void rj__visc_chord(const rj__frames *f, int n, double *W, int i)
{
    double *me = W + (size_t) RJ__VISC_PER * i;
    const double *next = me + RJ__VISC_PER;
    me[RJ__VI_E] = f->x[n + 1] - f->x[n] + 0.5 * f->dt * (next[RJ__VI_V] - me[RJ__VI_V]);
    me[RJ__VI_E + 1] =
        f->y[n + 1] - f->y[n] + 0.5 * f->dt * (next[RJ__VI_V + 1] - me[RJ__VI_V + 1]);
}

/* Link l's records for rj__visc_solve: every node's v* and inverse masses, then every
   element's chord at n + 1/2 and damping blocks there. dn: the first of m->dnode at or
   after the link's first node. */
static void rj__visc_gather(const rj_model *m, const rj_state *s, const rj__frames *f, int l,
                            int dn, double *W)
{
    const int n0 = m->link_first[l], nodes = m->link_first[l + 1] - n0;
    const double *kc = m->link_kc + 4 * (size_t) l;
    const double eta = RJ__LD(m, l)[RJ__LD_IMPLICIT];
    int i;
    for (i = 0; i < nodes; i++) {
        const int n = n0 + i;
        double *me = W + (size_t) RJ__VISC_PER * i;
        const int again = dn < m->ndn && m->dnode[dn] == n;
        dn += again;
        rj__visc_translation(m, s, f, n, again, me + RJ__VI_V, me + RJ__VI_MINV);
        me[RJ__VI_V + 2] = again ? rj__visc_rate_pred(m, s, f, n) : f->nw[n];
        me[RJ__VI_MINV + 2] = m->rinv[n];
    }
    for (i = 0; i + 1 < nodes; i++) {
        double *me = W + (size_t) RJ__VISC_PER * i;
        rj__visc_chord(f, n0 + i, W, i);
        rj__visc_elem(kc, eta, me[RJ__VI_E], me[RJ__VI_E + 1], me + RJ__VI_C);
    }
    memset(W + (size_t) RJ__VISC_PER * (nodes - 1) + RJ__VI_C, 0, 27 * sizeof(double));
}

/* Every node's masks and masses from its inverse masses (rj__visc_solve's). */
static void rj__visc_masses(double *W, int nodes)
{
    int i, p;
    for (i = 0; i < nodes; i++) {
        double *me = W + (size_t) RJ__VISC_PER * i;
        for (p = 0; p < 3; p++) {
            const double minv = me[RJ__VI_MINV + p];
            me[RJ__VI_MASK + p] = minv > 0 ? 1.0 : 0.0;
            me[RJ__VI_MASS + p] = minv > 0 ? 1.0 / minv : 1.0;
        }
    }
}

/* The rate a velocity-level method will hold joint j at this step (a lock, a limit the
   rate runs into, a prescribed profile: the rate that lands it there, as the later
   stages take it; friction that can stop the rate: 0), its pin nodes' rates wI, wJ as
   predicted; returns 0 when none holds it. */
static int rj__visc_held_rate(const rj_model *m, const rj_state *s, const rj__frames *f, int j,
                              double wI, double wJ, double *rate)
{
    const rj_joint_def *d = &m->jdef[j];
    const rj__joint *J = &m->jnt[j];
    const int flag = f->new_flags[j];
    const double p = s->jsc[8 * j + 5]; /* the element's penetration */
    if (rj__prescribed(J)) {
        *rate = rj__prescribed_rate(m, s, j, RJ__FJ(m, f->old, j)[RJ__JD_THETA], f->t, f->dt);
        return 1;
    }
    if (flag != RJ_FREE && rj__velocity_method(d->method) && rj__into_limit(flag, wJ - wI)) {
        *rate = flag == RJ_LOCKED || d->method == RJ_METHOD_FORCED ? p / f->dt : 0.0;
        return 1;
    }
    /* friction that can stop the joint (rj__friction) will hold it */
    if (d->friction > 0) {
        const double riI = J->nI >= 0 ? m->rinv[J->nI] : 0.0;
        const double give = f->kick * (riI + m->rinv[J->nJ]);
        *rate = 0.0;
        return fabs(wJ - wI) <= give * d->friction;
    }
    return 0;
}

/* A held joint's pin rotations in link l's records (first node n0, nodes of them): the
   two rotate as one of their summed inertia at the held rate apart, their angular
   momentum kept (as the later stages' torque pair keeps it); a fixed side (ground, a
   clamped node) holds the other. Without this a pin node's light rotation followed the
   damping in the solve, which the held joint then undid: the damping forces came from
   rates the step did not take (a root locked by the forced method rang 40 % slower). */
static void rj__visc_hold(const rj_model *m, const rj_state *s, const rj__frames *f, int j,
                          int n0, int nodes, double *W)
{
    const rj__joint *J = &m->jnt[j];
    const int nI = J->nI, nJ = J->nJ;
    const double riI = nI >= 0 ? m->rinv[nI] : 0.0, riJ = m->rinv[nJ];
    double wI, wJ, rate, uI, uJ, minv;
    wI = rj__visc_rate_pred(m, s, f, nI);
    wJ = rj__visc_rate_pred(m, s, f, nJ);
    if (!rj__visc_held_rate(m, s, f, j, wI, wJ, &rate))
        return;
    if (riI == 0 || riJ == 0) {
        /* the fixed side holds the other */
        uI = riI == 0 ? wI : wJ - rate;
        uJ = riJ == 0 ? wJ : wI + rate;
        minv = 0.0;
    } else {
        const double JI = 1.0 / riI, JJ = 1.0 / riJ;
        uI = (JI * wI + JJ * wJ - JJ * rate) / (JI + JJ);
        uJ = uI + rate;
        minv = 1.0 / (JI + JJ);
    }
    if (nI >= n0 && nI < n0 + nodes) {
        W[(size_t) RJ__VISC_PER * (nI - n0) + RJ__VI_V + 2] = uI;
        W[(size_t) RJ__VISC_PER * (nI - n0) + RJ__VI_MINV + 2] = riI == 0 ? 0.0 : minv;
    }
    if (nJ >= n0 && nJ < n0 + nodes) {
        W[(size_t) RJ__VISC_PER * (nJ - n0) + RJ__VI_V + 2] = uJ;
        W[(size_t) RJ__VISC_PER * (nJ - n0) + RJ__VI_MINV + 2] = riJ == 0 ? 0.0 : minv;
    }
}

/* Element i of link l's viscous forces on the rates solved for (records i and i + 1's
   v* + dv), as rj__elem_viscous gives them (-C_e v: build/test_mixed checks the two
   agree), kept (rj_state.visc_force) for the loads queries. */
static void rj__visc_elem_force(const rj_model *m, rj_state *s, int l, int i, const double *W,
                                rj__elem_force *out)
{
    const double *me = W + (size_t) RJ__VISC_PER * i;
    const double *va = me + RJ__VI_V, *vb = va + RJ__VISC_PER;
    const double ex = me[RJ__VI_E], ey = me[RJ__VI_E + 1];
    double *kept = s->visc_force + 4 * ((size_t) m->link_efirst[l] + (size_t) i);
    rj__elem_viscous(m->link_kc + 4 * (size_t) l, RJ__LD(m, l)[RJ__LD_IMPLICIT], ex, ey,
                     1.0 / (ex * ex + ey * ey), vb[0] - va[0], vb[1] - va[1], va[2], vb[2],
                     out);
    kept[0] = out->fx;
    kept[1] = out->fy;
    kept[2] = out->ma;
    kept[3] = out->mb;
}

/* Node n's damping force F on top of the others: kept in rj_state.damp with the
   mass-proportional part there already, its power at n - 1/2 into *power; a force on a
   node the stages after move (grouped, or in m->dnode: again), a kick on the others.
   Returns the positions written. */
static double rj__visc_node(const rj_model *m, rj_state *s, const rj__frames *f, int n,
                            int again, const double F[3], double *power)
{
    const size_t nn = (size_t) m->nn;
    s->damp[n] += F[0];
    s->damp[nn + n] += F[1];
    s->damp[2 * nn + n] += F[2];
    *power += F[0] * f->vx[n] + F[1] * f->vy[n] + F[2] * f->w[n];
    s->fx[n] += F[0];
    s->fy[n] += F[1];
    s->mz[n] += F[2];
    if (again)
        return 0.0;
    return rj__node_kick(m, s, n, F, f->current, f->advanced, f->kick);
}

/* Link l's damping forces F_d = -C (v* + dv) after the solve, element by element
   (rj__visc_elem_force), each node taking the element before it and the one after as
   rj__node_damping takes the lagged ones. Returns the positions written. */
static double rj__visc_apply(const rj_model *m, rj_state *s, const rj__frames *f, int l, int dn,
                             double *W, double *power)
{
    const int n0 = m->link_first[l], nodes = m->link_first[l + 1] - n0;
    rj__elem_force before, after;
    double fin = 0;
    int i, p;
    for (i = 0; i < nodes; i++) {
        double *me = W + (size_t) RJ__VISC_PER * i;
        for (p = 0; p < 3; p++)
            me[RJ__VI_V + p] += me[RJ__VI_Y + p];
    }
    memset(&before, 0, sizeof before);
    for (i = 0; i < nodes; i++) {
        const int n = n0 + i;
        const int again = dn < m->ndn && m->dnode[dn] == n;
        double F[3];
        dn += again;
        memset(&after, 0, sizeof after);
        if (i + 1 < nodes)
            rj__visc_elem_force(m, s, l, i, W, &after);
        F[0] = before.fx - after.fx;
        F[1] = before.fy - after.fy;
        F[2] = -before.mb - after.ma;
        fin += rj__visc_node(m, s, f, n, again, F, power);
        before = after;
    }
    return fin;
}

/* Stage 2e, the links' implicit Kelvin-Voigt damping (src/viscous.h), after every force
   but friction's, which then sees it: link by link, each seeing the ones before through
   their forces on the pins they share (the groups' sums), so that every solve only takes
   energy out. Its forces' power at n - 1/2 joins the material path's (rj_state.damp).
   Called by rj__stage_applied. Returns the positions written. */
static double rj__stage_viscous(const rj_model *m, rj_state *s, const rj__frames *f)
{
    double *W = s->visc + RJ__VISC_PER;
    double power = 0, fin = 0;
    int l, q;
    rj__visc_pad(W);
    for (l = 0; l < m->nl; l++) {
        const int n0 = m->link_first[l], nodes = m->link_first[l + 1] - n0;
        int dn;
        if (!(RJ__LD(m, l)[RJ__LD_IMPLICIT] > 0))
            continue;
        dn = rj__dnode_from(m, n0);
        rj__visc_gather(m, s, f, l, dn, W);
        for (q = m->visc_first[l]; q < m->visc_first[l + 1]; q++)
            rj__visc_hold(m, s, f, m->visc_joint[q], n0, nodes, W);
        rj__visc_masses(W, nodes);
        rj__visc_solve(W, nodes, f->kick);
        fin += rj__visc_apply(m, s, f, l, dn, W, &power);
    }
    s->damp[3 * (size_t) m->nn] += power;
    return fin;
}

/* One body of a pinned pair at the pin: its point r from the anchor, the pin's mean
   velocity over the step under the forces so far (the point turned exactly, as the
   bodies' poses turn it: the linear v + w perp(r) left out the pin's centripetal pull,
   and a stuck joint crept at first order in dt), its inverse mass and inertia (0 where
   held). */
static void rj__pair_side_at(const rj_model *m, const rj_state *s, const rj__frames *at, int n,
                             rj__pair_side *p)
{
    const int c = m->node_cl[n];
    const double *oc = RJ__FCL(m, at->old, c);
    double Fx, Fy, T, w, cw, sw;
    p->tinv = m->cl_fix[c] == 0 ? 1.0 / m->cl_M[c] : 0.0;
    p->rinv = m->cl_fix[c] != 2 ? 1.0 / m->cl_I[c] : 0.0;
    p->r[0] = at->x[n] - oc[0];
    p->r[1] = at->y[n] - oc[1];
    rj__cl_load(m, c, oc, at->x, at->y, s->fx, s->fy, s->mz, &Fx, &Fy, &T);
    w = oc[4] + at->kick * T * p->rinv;
    cw = cos(at->dt * w);
    sw = sin(at->dt * w);
    p->v[0] = oc[2] + at->kick * Fx * p->tinv + ((cw - 1) * p->r[0] - sw * p->r[1]) / at->dt;
    p->v[1] = oc[3] + at->kick * Fy * p->tinv + (sw * p->r[0] + (cw - 1) * p->r[1]) / at->dt;
}

/* A joint between two rigid bodies of a mixed scene, seen through the pin between them
   (rj__body_pins), whose impulse lambda keeps the pin's two points together: the rate
   the step would end with is the one that impulse leaves, rate - u . lambda, and the
   give of a torque pair is the pinned pair's, c = 1/I_1 + 1/I_2 - u^T K^-1 u, with K the
   pin's mobility (sum of 1/M + perp(r) perp(r)^T / I) and u = sum perp(r) / I. With the
   bodies' own gives alone, friction fell short and a stuck joint crept. */
static void rj__pair_terms(const rj_model *m, const rj_state *s, const rj__frames *f,
                              const rj__joint *J, double *ratep, double *give)
{
    rj__pair_side a, b;
    double K[3], u[2], gap[2], det, lam[2], c;
    rj__pair_side_at(m, s, f, J->nI, &a);
    rj__pair_side_at(m, s, f, J->nJ, &b);
    c = rj__pair_give(&a, &b, K, u, &det);
    /* two bodies turning about one point, or held: nothing for the pin to add */
    if (!(det > 0))
        return;
    gap[0] = a.v[0] - b.v[0];
    gap[1] = a.v[1] - b.v[1];
    lam[0] = -(K[2] * gap[0] - K[1] * gap[1]) / det;
    lam[1] = -(K[0] * gap[1] - K[1] * gap[0]) / det;
    *ratep -= u[0] * lam[0] + u[1] * lam[1];
    if (J->rotor > 0)
        c /= 1.0 + J->rotor * c;
    *give = f->kick * c;
}

/* Joint j's geometry at n (as stage 2 kept it), the rate it would end the step with
   under the forces so far, and its rate change per unit torque over the step; pairs:
   seen through the pin when it joins two rigid bodies (rj__pair_terms). */
static RJ__FORCE_INLINE void rj__joint_terms(const rj_model *m, const rj_state *s,
                                             const rj__frames *f, int j, int pairs,
                                             rj__jgeo *g, double *ratep, double *give)
{
    const rj__joint *J = &m->jnt[j];
    rj__kept_geo(s->jsc + 8 * j, g);
    *ratep = rj__joint_rate_pred(m, s, f, J, g);
    *give = f->kick * rj__joint_compliance(m, J, g);
    if (pairs && J->pair)
        rj__pair_terms(m, s, f, J, ratep, give);
}

/* Joint j's friction torque, applied and recorded (stage 3, below). */
static RJ__FORCE_INLINE void rj__friction_joint(const rj_model *m, rj_state *s,
                                                const rj__frames *f, int j, int pairs)
{
    const rj_joint_def *d = &m->jdef[j];
    const rj__joint *J = &m->jnt[j];
    double *new_joint = RJ__FJ(m, f->next, j);
    rj__jgeo g;
    double ratep, compliance, tau;
    rj__joint_terms(m, s, f, j, pairs, &g, &ratep, &compliance);
    tau = rj__friction(ratep, compliance, d->friction);
    rj__apply_torque(J, &g, tau, s->fx, s->fy, s->mz);
    new_joint[RJ__JD_TQ0 + RJ_TORQUE_FRICTION] = tau;
}

/* Stage 3, Coulomb friction: the torque that would stop the relative rotation in this
   step, capped at T_f, with every other force known; it never reverses the rate and holds
   a stuck joint exactly. */
static RJ__FORCE_INLINE void rj__stage_friction(const rj_model *m, rj_state *s, const rj__frames *f,
                                                int held)
{
    int j;
    for (j = 0; j < m->nj; j++)
        if (m->jdef[j].friction > 0)
            rj__friction_joint(m, s, f, j, held && m->npair);
}

/* Gravity's potential -sum m g . x at the nodes x, y (rigid bodies' own links from their
   nodes' positions too). */
static RJ__NOINLINE double rj__gravity_potential(const rj_model *m, const double *x,
                                                 const double *y)
{
    const double gx = m->solver.gravity[0], gy = m->solver.gravity[1];
    double sum = 0;
    int i;
    /* every node's mass (a body's own nodes carry none; the nodes its pins carry do) */
    for (i = 0; i < m->nn; i++)
        sum += m->mass[i] * (gx * x[i] + gy * y[i]);
    for (i = 0; i < m->ncl; i++) {
        double mx, my;
        if (m->cl_first[i] == m->cl_first[i + 1])
            continue;
        rj__cl_own_moment(m, i, x, y, &mx, &my);
        sum += gx * mx + gy * my;
    }
    return -sum;
}

/* Stage 4a: v^{n+1/2} and x^{n+1} of the nodes the joints acted on (the beam pass advanced
   the rest); the kinetic energy at n as v^{n-1/2}.v^{n+1/2}, from v^{-1/2} = 2 v(0) -
   v^{1/2} at the start. */
static RJ__FORCE_INLINE void rj__update_joint_nodes(const rj_model *m, rj_state *s,
                                                    const rj__frames *f, const rj__adv *adv,
                                                    rj__sums *e)
{
    const double *km = m->kmass, *kj = m->krot;
    const double *vx = f->vx, *vy = f->vy, *w = f->w;
    const double *nvx = f->nvx, *nvy = f->nvy, *nw = f->nw;
    double ke;
    int i;
    for (i = 0; i < m->ndn; i++) {
        const int n = m->dnode[i];
        rj__advance_node(adv, n, s->fx[n], s->fy[n], s->mz[n], f->x, f->y, f->phi);
    }
    ke = f->en ? rj__sum8(s->kn, m->nn) : 0.0;
    if (f->first) {
        ke = 0;
        for (i = 0; i < m->nn; i++)
            ke += km[i] * ((2 * vx[i] - nvx[i]) * nvx[i] + (2 * vy[i] - nvy[i]) * nvy[i]) +
                  kj[i] * (2 * w[i] - nw[i]) * nw[i];
    }
    e->kinetic = ke;
}

/* Stage 4b: groups of nodes that move together (a pin shared by links) take their summed
   force on their summed mass. */
static RJ__FORCE_INLINE void rj__update_groups(const rj_model *m, rj_state *s, const rj__frames *f,
                                               rj__sums *e, double *fin)
{
    const double *vx = f->vx, *vy = f->vy;
    int gi;
    for (gi = 0; gi < m->ng; gi++) {
        const int f0 = m->grp_first[gi], f1 = m->grp_first[gi + 1], r = m->grp_node[f0];
        double sx = 0, sy = 0, msum = 0, ux, uy;
        int q;
        for (q = f0; q < f1; q++) {
            sx += s->fx[m->grp_node[q]];
            sy += s->fy[m->grp_node[q]];
            msum += m->mass[m->grp_node[q]];
        }
        ux = vx[r] + f->kick * sx * m->grp_inv[gi];
        uy = vy[r] + f->kick * sy * m->grp_inv[gi];
        if (m->has_gravity && m->grp_inv[gi] > 0) {
            ux += f->kick * m->solver.gravity[0];
            uy += f->kick * m->solver.gravity[1];
        }
        if (m->grp_inv[gi] > 0)
            e->kinetic += f->first ? msum * ((2 * vx[r] - ux) * ux + (2 * vy[r] - uy) * uy)
                                   : msum * (vx[r] * ux + vy[r] * uy);
        for (q = f0; q < f1; q++) {
            const int n = m->grp_node[q];
            f->nvx[n] = ux;
            f->nvy[n] = uy;
            f->nx[n] = f->x[n] + f->dt * ux;
            f->ny[n] = f->y[n] + f->dt * uy;
            *fin += f->nx[n] + f->ny[n];
        }
    }
}

/* Gravity on a rigid body of a mixed scene: M g at its centre of mass (the link's rod and
   tip mass, and the nodes of other links its pins carry), a moment about its anchor when
   the anchor is a pin rather than the centre. */
static void rj__cl_gravity(const rj_model *m, int c, const double *oc, const double *x,
                           const double *y, double *Fx, double *Fy, double *T)
{
    const int n0 = m->link_first[c], nt = m->link_first[c + 1] - 1;
    const double gx = m->solver.gravity[0], gy = m->solver.gravity[1];
    double mx, my;
    int k;
    rj__cl_own_moment(m, c, x, y, &mx, &my);
    for (k = m->cl_first[c]; k < m->cl_first[c + 1]; k++) {
        const int n = m->cl_node[k];
        if (n >= n0 && n <= nt)
            continue;
        mx += m->mass[n] * x[n];
        my += m->mass[n] * y[n];
    }
    /* M g, and its moment about the anchor: sum m (r - anchor) x g */
    *Fx += m->cl_M[c] * gx;
    *Fy += m->cl_M[c] * gy;
    *T += (mx - m->cl_M[c] * oc[0]) * gy - (my - m->cl_M[c] * oc[1]) * gx;
}

/* Stage 4c: rigid bodies in mixed scenes: anchor velocity and rate at n + 1/2. */
static RJ__FORCE_INLINE void rj__update_bodies(const rj_model *m, rj_state *s, const rj__frames *f,
                                               rj__sums *e)
{
    int gi;
    for (gi = 0; gi < m->ncl; gi++) {
        const double *oc = RJ__FCL(m, f->old, gi);
        double *nc = RJ__FCL(m, f->next, gi), Fx, Fy, T;
        int q;
        if (m->cl_first[gi] == m->cl_first[gi + 1])
            continue;
        memcpy(nc, oc, 6 * sizeof(double));
        if (m->cl_fix[gi] == 2)
            continue;
        rj__cl_load(m, gi, oc, f->x, f->y, s->fx, s->fy, s->mz, &Fx, &Fy, &T);
        if (m->has_gravity)
            rj__cl_gravity(m, gi, oc, f->x, f->y, &Fx, &Fy, &T);
        if (m->cl_fix[gi] == 0) {
            nc[2] = oc[2] + f->kick * Fx / m->cl_M[gi];
            nc[3] = oc[3] + f->kick * Fy / m->cl_M[gi];
        }
        nc[4] = oc[4] + f->kick * T / m->cl_I[gi];
        e->kinetic += rj__cl_ke2(m, gi, oc, nc, f->first);
        for (q = m->cl_first[gi]; q < m->cl_first[gi + 1]; q++)
            if (RJ__CL_RIGID(m, m->cl_node[q]))
                f->nw[m->cl_node[q]] = nc[4];
    }
}

/* Stage 4, the update: velocities at n + 1/2 and positions at n + 1 (grouped nodes and
   nodes a velocity-level method changes are redone after). */
/* The pin nodes' rates at n - 1/2 and n + 1/2 and their angles, for the rotors' stage
   (given apart from the step's frames, whose record keeps its registers). */
typedef struct rj__pins {
    const double *w, *phi;
    double *nw, *nphi;
    double dt;
    int first;
} rj__pins;

/* What the rotors' stage returns: the kinetic energy's change in its form, and the sum
   of the angles it moved (finite while they are). */
typedef struct rj__rotor_sums {
    double ke, fin;
} rj__rotor_sums;

/* One rotor's share of its joint's pin rotations: the rates the step gave the two pin nodes
   (each on its own rotary inertia) moved to those of the 2 x 2 mass that the rotor's
   reflected inertia Jr couples, diag(I_I, I_J) + Jr [1 -1; -1 1] (Sherman-Morrison: the
   relative change shrinks by 1 + Jr (1/I_I + 1/I_J), the momentum kept), their angles
   after, and the kinetic energy's change in its form (sum of kn, the rotor's Jr w w'). */
static void rj__rotor_pins(const rj_model *m, const rj__pins *p, const rj__joint *J,
                           rj__rotor_sums *out)
{
    const int nI = J->nI, nJ = J->nJ, first = p->first;
    const double riI = nI >= 0 ? m->rinv[nI] : 0.0, riJ = m->rinv[nJ];
    const double *w = p->w, *kj = m->krot;
    const double wI = nI >= 0 ? w[nI] : 0.0, oI = nI >= 0 ? p->nw[nI] : 0.0, oJ = p->nw[nJ];
    const double share = J->rotor * ((oJ - w[nJ]) - (oI - wI)) /
                         (1.0 + J->rotor * (riI + riJ));
    const double uI = oI + share * riI, uJ = oJ - share * riJ;
    const double rel_m = w[nJ] - wI, rel_p = uJ - uI;
    /* each node's kn, before and after, and the rotor's */
    out->ke += first ? kj[nJ] * ((2 * w[nJ] - uJ) * uJ - (2 * w[nJ] - oJ) * oJ)
                     : kj[nJ] * w[nJ] * (uJ - oJ);
    out->ke += J->rotor * (first ? (2 * rel_m - rel_p) * rel_p : rel_m * rel_p);
    p->nw[nJ] = uJ;
    p->nphi[nJ] = p->phi[nJ] + p->dt * uJ;
    out->fin += p->nphi[nJ];
    if (nI < 0)
        return;
    out->ke += first ? kj[nI] * ((2 * wI - uI) * uI - (2 * wI - oI) * oI)
                     : kj[nI] * wI * (uI - oI);
    p->nw[nI] = uI;
    p->nphi[nI] = p->phi[nI] + p->dt * uI;
    out->fin += p->nphi[nI];
}

/* Stage 4c of scenes with rotors: every rotor's joint pins (rj__rotor_pins). Apart (not
   inlined): a scene without rotors pays one test. */
static RJ__NOINLINE rj__rotor_sums rj__stage_rotors(const rj_model *m, rj__pins p)
{
    rj__rotor_sums out;
    int j;
    out.ke = 0;
    out.fin = 0;
    for (j = 0; j < m->nj; j++)
        if (m->jnt[j].rotor > 0)
            rj__rotor_pins(m, &p, &m->jnt[j], &out);
    return out;
}

/* The rotors' stage on the step's frames. */
static RJ__FORCE_INLINE void rj__update_rotors(const rj_model *m, const rj__frames *f,
                                               rj__sums *e, double *fin)
{
    rj__pins p;
    rj__rotor_sums out;
    p.w = f->w;
    p.phi = f->phi;
    p.nw = f->nw;
    p.nphi = f->nphi;
    p.dt = f->dt;
    p.first = f->first;
    out = rj__stage_rotors(m, p);
    *fin += out.fin;
    if (f->en || f->first)
        e->kinetic += out.ke;
}

static RJ__FORCE_INLINE void rj__stage_update(const rj_model *m, rj_state *s, const rj__frames *f,
                                              const rj__adv *adv, rj__sums *e, double *fin)
{
    rj__update_joint_nodes(m, s, f, adv, e);
    if (m->nrotor)
        rj__update_rotors(m, f, e, fin);
    rj__update_groups(m, s, f, e, fin);
    rj__update_bodies(m, s, f, e);
    e->kinetic *= 0.5;
}

/* Coupling c's stretch rate at the end of the step under the forces so far, its joints
   seen through their pins (rj__joint_terms), and their geometries at n. */
static double rj__coupling_rate_pred(const rj_model *m, const rj_state *s, const rj__frames *f,
                                     const rj_coupling_def *c, rj__jgeo *ga, rj__jgeo *gb)
{
    double rate_a, rate_b, give;
    rj__joint_terms(m, s, f, c->joint_a, 1, ga, &rate_a, &give);
    rj__joint_terms(m, s, f, c->joint_b, 1, gb, &rate_b, &give);
    return rate_b - c->ratio * rate_a;
}

/* The force entries a torque on joint j writes (rj__apply_torque): 0 .. 3 its nodes
   I, K, J, L (-1: none), saved into or put back from keep (12 doubles). */
static void rj__torque_entries(const rj__joint *J, rj_state *s, double *keep, int put)
{
    const int nodes[4] = { J->nI, J->nK, J->nJ, J->nL };
    int k;
    for (k = 0; k < 4; k++) {
        double *at[3];
        int q;
        if (nodes[k] < 0)
            continue;
        at[0] = &s->fx[nodes[k]];
        at[1] = &s->fy[nodes[k]];
        at[2] = &s->mz[nodes[k]];
        for (q = 0; q < 3; q++) {
            if (put)
                *at[q] = keep[3 * k + q];
            else
                keep[3 * k + q] = *at[q];
        }
    }
}

/* An exact cable loop with a joint between two rigid bodies, as a torque pair after the
   latches (rj__stage_pair_latches): tau on joint b and -ratio tau on joint a, aimed at
   the stretch's rate -e / dt that closes it at n + 1. Its give is probed with a unit
   torque pair and the force entries put back bit for bit: through the pin it is linear
   but for the pin's turn over the step, whose share the next step's aim takes up.
   Booked with the limits' torques, as the rows' couplings are. */
static void rj__pair_coupling(const rj_model *m, rj_state *s, const rj__frames *f, int k)
{
    const rj_coupling_def *c = &m->cp[k];
    const rj__joint *Ja = &m->jnt[c->joint_a], *Jb = &m->jnt[c->joint_b];
    const double *old_joints = RJ__FJ(m, f->old, 0);
    const double e_n = rj__coupling_stretch(
        m, c, old_joints[(size_t) RJ__JD_COUNT * c->joint_a + RJ__JD_THETA],
        old_joints[(size_t) RJ__JD_COUNT * c->joint_b + RJ__JD_THETA]);
    double keep[24], rate0, rate1, tau;
    rj__jgeo ga, gb;
    rate0 = rj__coupling_rate_pred(m, s, f, c, &ga, &gb);
    rj__torque_entries(Ja, s, keep, 0);
    rj__torque_entries(Jb, s, keep + 12, 0);
    rj__apply_torque(Jb, &gb, 1.0, s->fx, s->fy, s->mz);
    rj__apply_torque(Ja, &ga, -c->ratio, s->fx, s->fy, s->mz);
    rate1 = rj__coupling_rate_pred(m, s, f, c, &ga, &gb);
    rj__torque_entries(Jb, s, keep + 12, 1);
    rj__torque_entries(Ja, s, keep, 1);
    if (!(rate1 != rate0))
        return;
    tau = (-e_n / f->dt - rate0) / (rate1 - rate0);
    rj__apply_torque(Jb, &gb, tau, s->fx, s->fy, s->mz);
    rj__apply_torque(Ja, &ga, -c->ratio * tau, s->fx, s->fy, s->mz);
    RJ__FJ(m, f->next, c->joint_b)[RJ__JD_TQ0 + RJ_TORQUE_LIMIT] += tau;
    RJ__FJ(m, f->next, c->joint_a)[RJ__JD_TQ0 + RJ_TORQUE_LIMIT] -= c->ratio * tau;
}

/* Latches and plastic limits on the joints between two rigid bodies of a mixed scene, as
   torques after friction (stage 3): the jump of stage 5 sees neither the pin between the
   bodies nor the flexible links they carry, and tried there it lost 1.5 J of 3.9 J
   unbooked. The torque brings the pinned pair's rate (rj__pair_terms) to its target
   within the step: p / dt, which puts a lock or a forced limit back on its angle at
   n + 1; for a momentum contact 0, or -e times the rate it came with at its first step
   (a bounce, which the rate pointing out then releases); a contact only pushes. As a force
   in the step, its work is booked with the limit's torque, and the flexible links
   pinned to the bodies take its effect with the next step, as from any force. A
   prescribed profile there is the same torque aimed at the profile's rate, booked as
   the drive's. */
static void rj__stage_pair_latches(const rj_model *m, rj_state *s, const rj__frames *f)
{
    int j;
    for (j = 0; j < m->nj; j++) {
        const rj_joint_def *d = &m->jdef[j];
        const rj__joint *J = &m->jnt[j];
        const int flag = f->new_flags[j];
        const double p = s->jsc[8 * j + 5]; /* the element's penetration */
        rj__jgeo g;
        const int driven = rj__prescribed(J);
        double ratep, give, target, tau;
        if (!J->pair || (!driven && (flag == RJ_FREE || !rj__velocity_method(d->method))))
            continue;
        rj__joint_terms(m, s, f, j, 1, &g, &ratep, &give);
        if (driven) {
            const double run = RJ__FJ(m, f->old, j)[RJ__JD_THETA];
            tau = (rj__prescribed_rate(m, s, j, run, f->t, f->dt) - ratep) / give;
            rj__apply_torque(J, &g, tau, s->fx, s->fy, s->mz);
            RJ__FJ(m, f->next, j)[RJ__JD_TQ0 + RJ_TORQUE_DRIVE] = tau;
            continue;
        }
        target = flag == RJ_LOCKED || d->method == RJ_METHOD_FORCED ? p / f->dt : 0.0;
        if (flag != RJ_LOCKED && d->method == RJ_METHOD_MOMENTUM &&
            f->old_flags[j] == RJ_FREE)
            target = -d->restitution * ratep;
        tau = (target - ratep) / give;
        if ((flag == RJ_AT_FORWARD && tau > 0) || (flag == RJ_AT_REVERSE && tau < 0))
            tau = 0;
        rj__apply_torque(J, &g, tau, s->fx, s->fy, s->mz);
        RJ__FJ(m, f->next, j)[RJ__JD_TQ0 + RJ_TORQUE_LIMIT] += tau;
    }
    for (j = 0; j < m->ncp; j++)
        if (rj__coupling_on_pair(m, j))
            rj__pair_coupling(m, s, f, j);
}

/* A velocity-level joint released under RC13 (rate pointing out at the step's start) that
   the step's kick turns back in while still past its limit is in contact again now, not one
   step later: that lag let the bodies behind ratchet it through the stop (stress suite:
   48 deg in a 1000:1 chain). Returns the flag. */
static RJ__FORCE_INLINE int rj__recontact(const rj__joint *J, const double *old_joint, double ratep,
                                          int *new_flag, double *kept)
{
    const double run = old_joint[RJ__JD_THETA];
    if (run <= J->rev && ratep < 0) {
        *new_flag = RJ_AT_REVERSE;
        kept[5] = J->rev - run;
    } else if (run >= J->fwd && ratep > 0) {
        *new_flag = RJ_AT_FORWARD;
        kept[5] = J->fwd - run;
    }
    return *new_flag;
}

/* After a jump, the joint's nodes move with the new rates (rj__spin changes nK and nL only
   with a chord reference); a rigid body's node carries its whole body. */
static RJ__FORCE_INLINE void rj__jump_nodes(const rj_model *m, const rj__frames *f,
                                            const rj__joint *J, double *fin)
{
    const int nodes[4] = { J->nI, J->chord ? J->nK : -1, J->nJ, J->chord ? J->nL : -1 };
    int k;
    for (k = 0; k < 4; k++) {
        const int n = nodes[k];
        if (n < 0)
            continue;
        f->nx[n] = f->x[n] + f->dt * f->nvx[n];
        f->ny[n] = f->y[n] + f->dt * f->nvy[n];
        f->nphi[n] = f->phi[n] + f->dt * f->nw[n];
        *fin += (f->nx[n] + f->ny[n]) + f->nphi[n];
        if (m->ncl && RJ__CL_RIGID(m, n)) {
            const int c = m->node_cl[n];
            int q;
            RJ__FCL(m, f->next, c)[4] = f->nw[n];
            for (q = m->cl_first[c]; q < m->cl_first[c + 1]; q++)
                if (RJ__CL_RIGID(m, m->cl_node[q]))
                    f->nw[m->cl_node[q]] = f->nw[n];
        }
    }
}

/* The jump of one velocity-level joint turning into its limit (momentum: Eqs 23-24 with
   e; energy: Eq 26; forced, or any while locked: plastic). In the kinetic energy's form
   1/2 v^{n-1/2}.v^{n+1/2} a jump from w_b to w_b' loses 1/2 I_b (w_b^{n-1/2} + w_b')
   (w_b - w_b') per body: this step takes the first half, the next the second (pending).
   A latch that only cancels the step's small relative rate loses almost nothing, as a
   workless constraint should. Returns the rate after. */
static RJ__FORCE_INLINE double rj__joint_jump(const rj_model *m, const rj__frames *f, int j,
                                              int flag, const rj__jgeo *g, double w1, double w2,
                                              rj__sums *e, double *fin)
{
    const rj_joint_def *d = &m->jdef[j];
    const rj__joint *J = &m->jnt[j];
    double *new_joint = RJ__FJ(m, f->next, j);
    const double o1 = w1, o2 = w2;
    double m1 = 0, m2 = 0, loss = 0;
    /* the bodies' rates at n - 1/2 */
    rj__joint_rate(J, g, f->vx, f->vy, f->w, &m1, &m2);
    if (d->method == RJ_METHOD_MOMENTUM)
        rj_momentum_balance(J->I1, J->I2, flag == RJ_LOCKED ? 0.0 : d->restitution, &w1, &w2);
    else if (d->method == RJ_METHOD_ENERGY && flag != RJ_LOCKED)
        rj_energy_balance(J->I1, J->I2, &w1, &w2);
    else
        rj_momentum_balance(J->I1, J->I2, 0.0, &w1, &w2);
    if (!rj__finite(J->I1))
        w1 = o1;
    if (!rj__finite(J->I2))
        w2 = o2;
    if (rj__finite(J->I1)) {
        loss += 0.5 * J->I1 * m1 * (o1 - w1);
        e->pending += 0.5 * J->I1 * w1 * (o1 - w1);
    }
    if (rj__finite(J->I2)) {
        loss += 0.5 * J->I2 * m2 * (o2 - w2);
        e->pending += 0.5 * J->I2 * w2 * (o2 - w2);
    }
    /* a rotor spins with the relative rate: its share of the jump */
    loss += 0.5 * J->rotor * (m2 - m1) * ((o2 - o1) - (w2 - w1));
    e->pending += 0.5 * J->rotor * (w2 - w1) * ((o2 - o1) - (w2 - w1));
    /* the latch's angular impulse on body 2 (body 1 takes the opposite) */
    new_joint[RJ__JD_IMPULSE] = (rj__finite(J->I2) ? J->I2 * (w2 - o2) : -J->I1 * (w1 - o1)) +
                                J->rotor * ((w2 - w1) - (o2 - o1));
    rj__spin(J, g, w1 - o1, w2 - o2, f->nvx, f->nvy, f->nw);
    rj__jump_nodes(m, f, J, fin);
    e->lost_limit += loss;
    e->kinetic -= loss;
    return rj__joint_rate(J, g, f->nvx, f->nvy, f->nw, NULL, NULL);
}

/* Joint j's rate from node rates vx, vy, w, in the step's kept geometry. */
static double rj__kept_rate(const rj_model *m, const rj_state *s, int j, const double *vx,
                            const double *vy, const double *w)
{
    rj__jgeo g;
    rj__kept_geo(s->jsc + 8 * j, &g);
    return rj__joint_rate(&m->jnt[j], &g, vx, vy, w, NULL, NULL);
}

/* Joint j's rate at n + 1/2 from the nodes' now. */
static double rj__rate_now(const rj_model *m, const rj_state *s, const rj__frames *f, int j)
{
    return rj__kept_rate(m, s, j, f->nvx, f->nvy, f->nw);
}

/* The rate change of joint J per unit torque impulse on its pins, and each body's share:
   1 / I over 1 + rotor c0 (c0 = 1/I1 + 1/I2; a rotor's reflected inertia acts on the
   relative rotation; ground or a fixed body, I infinite, takes none). */
static double rj__joint_give(const rj__joint *J, double *give1, double *give2)
{
    const double c1 = rj__finite(J->I1) ? 1.0 / J->I1 : 0.0;
    const double c2 = rj__finite(J->I2) ? 1.0 / J->I2 : 0.0;
    const double share = 1.0 / (1.0 + J->rotor * (c1 + c2));
    if (give1)
        *give1 = c1 * share;
    if (give2)
        *give2 = c2 * share;
    return (c1 + c2) * share;
}

/* Which body turns with side (1 or 2) of joint J: its pin node, or the rigid body of a
   mixed scene whose own node it is (-2 less the body's link); -1 for ground. */
static int rj__side_body(const rj_model *m, const rj__joint *J, int side)
{
    const int n = side == 2 ? J->nJ : J->nI;
    if (n < 0)
        return -1;
    if (m->ncl && RJ__CL_RIGID(m, n))
        return -2 - m->node_cl[n];
    return n;
}

/* Joint q's rate change per unit torque impulse on joint p: each side of p moves its
   body by its give, and each side of q that turns with the same body sees it. */
static double rj__joint_cross(const rj_model *m, int p, int q)
{
    const rj__joint *Jp = &m->jnt[p], *Jq = &m->jnt[q];
    double give[3], sum = 0;
    int a, b;
    rj__joint_give(Jp, &give[1], &give[2]);
    for (a = 1; a <= 2; a++)
        for (b = 1; b <= 2; b++) {
            const int body = rj__side_body(m, Jp, a);
            if (body == -1 || body != rj__side_body(m, Jq, b))
                continue;
            sum += (a == b ? 1.0 : -1.0) * give[a];
        }
    return sum;
}

/* A torque impulse P on joint j's pins (P on body 2, -P on body 1): the bodies' rates move
   by their gives (rj__joint_give), the nodes with them. The momentum I1 w1 + I2 w2 is
   kept, as a latch's jump keeps it (rj__joint_jump). */
static void rj__joint_impulse(const rj_model *m, const rj_state *s, const rj__frames *f, int j,
                              double P, double *fin)
{
    const rj__joint *J = &m->jnt[j];
    double give1, give2;
    rj__jgeo g;
    rj__kept_geo(s->jsc + 8 * j, &g);
    rj__joint_give(J, &give1, &give2);
    rj__spin(J, &g, -P * give1, P * give2, f->nvx, f->nvy, f->nw);
    rj__jump_nodes(m, f, J, fin);
}

/* Row's impulse P: P coef on each of its joints; the row keeps the sum. */
static void rj__row_impulse(const rj_model *m, const rj_state *s, const rj__frames *f,
                            const rj__rows *R, rj__row *row, double P, double *fin)
{
    int k;
    for (k = 0; k < row->count; k++)
        rj__joint_impulse(m, s, f, R->term[row->first + k].joint,
                          R->term[row->first + k].coef * P, fin);
    row->lam += P;
}

/* A row's rate J v at n + 1/2 now, and its give J M^-1 J^T (rj__joint_cross). */
static double rj__row_rate(const rj_model *m, const rj_state *s, const rj__frames *f,
                           const rj__rows *R, const rj__row *row, double *give)
{
    const rj__term *t = R->term + row->first;
    double rate = 0, sum = 0;
    int k, q;
    for (k = 0; k < row->count; k++) {
        rate += t[k].coef * rj__rate_now(m, s, f, t[k].joint);
        for (q = 0; q < row->count && give; q++)
            sum += t[k].coef * t[q].coef * rj__joint_cross(m, t[k].joint, t[q].joint);
    }
    if (give)
        *give = sum;
    return rate;
}

/* Node space's rows system W lam = target - J v, W_ab = sum over the rows' joints p, q
   of coef_p coef_q times q's rate change per unit impulse on p (rj__joint_cross: the
   sides they share); in s->rsys (rows k: k x k, its factor,
   k, k). A singular W (rows that repeat each other) is regularised by 1e-12 of its
   largest diagonal, a least-squares answer. */
static void rj__rows_direct(const rj_model *m, const rj_state *s, const rj__frames *f,
                            rj__rows *R, double *fin)
{
    const int k = R->count;
    double *S = s->rsys, *SL = S + (size_t) k * k, *rhs = SL + (size_t) k * k, *lam = rhs + k;
    double largest = 0;
    int a, b, p, q;
    for (a = 0; a < k; a++) {
        const rj__row *ra = &R->row[a];
        for (b = 0; b < k; b++) {
            const rj__row *rb = &R->row[b];
            double sum = 0;
            for (p = 0; p < ra->count; p++)
                for (q = 0; q < rb->count; q++) {
                    const rj__term *tp = &R->term[ra->first + p], *tq = &R->term[rb->first + q];
                    sum += tp->coef * tq->coef * rj__joint_cross(m, tp->joint, tq->joint);
                }
            S[(size_t) a * k + b] = sum;
        }
        rhs[a] = ra->target - rj__row_rate(m, s, f, R, ra, NULL);
        largest = fmax(largest, S[(size_t) a * k + a]);
    }
    if (rj__chol(k, S, SL)) {
        for (a = 0; a < k; a++)
            S[(size_t) a * k + a] += 1e-12 * largest;
        if (rj__chol(k, S, SL))
            return;
    }
    rj__chol_solve(k, SL, rhs, lam);
    for (a = 0; a < k; a++)
        rj__row_impulse(m, s, f, R, &R->row[a], lam[a], fin);
}

/* One sweep over the rows: each one's impulse to its target, its terms' joints in turn,
   where it misses by more than 1e-15 rad at n + 1 (its rate's miss times dt). Returns
   how many took one. */
static int rj__rows_sweep(const rj_model *m, const rj_state *s, const rj__frames *f,
                          rj__rows *R, double *fin)
{
    int a, moved = 0;
    for (a = 0; a < R->count; a++) {
        rj__row *row = &R->row[a];
        double give;
        const double rate = rj__row_rate(m, s, f, R, row, &give);
        if (!(fabs(row->target - rate) * f->dt > 1e-15))
            continue;
        rj__row_impulse(m, s, f, R, row, (row->target - rate) / give, fin);
        moved++;
    }
    return moved;
}

/* The node-space rows' rates before any impulse, for the first step's work. */
static void rj__rows_before(const rj_model *m, const rj_state *s, const rj__frames *f,
                            rj__rows *R)
{
    int a;
    for (a = 0; a < R->count; a++)
        R->row[a].before = rj__row_rate(m, s, f, R, &R->row[a], NULL);
}

/* What the rows' stage returns: the work of the prescribed joints' impulses, this step's
   and the next's; the exact couplings' loss, this step's and the next's; the sum of the
   positions they moved (finite while they are). */
typedef struct rj__rows_sums {
    double drive, drive_pending, loss, pending, fin;
} rj__rows_sums;

/* A row's impulse in the accounts and the joints' records: -1/2 lam J v^{n-1/2} now and
   -1/2 lam J v^{n+1/2} with the next step, as the drive's work (a prescribed joint: its
   torque) or the limits' loss (an exact coupling: its torque in the spring columns). */
static void rj__row_account(const rj_model *m, const rj_state *s, const rj__frames *f,
                            const rj__rows *R, const rj__row *row, rj__rows_sums *out)
{
    double back = 0, after = 0;
    int k;
    for (k = 0; k < row->count; k++) {
        const rj__term *t = &R->term[row->first + k];
        const double rate = rj__rate_now(m, s, f, t->joint);
        double *record = RJ__FJ(m, f->next, t->joint);
        /* from the nodes' rates at n - 1/2 (at the first step, at 0) */
        back += t->coef * rj__kept_rate(m, s, t->joint, f->vx, f->vy, f->w);
        after += t->coef * rate;
        record[RJ__JD_RATE] = rate;
        if (row->kind == RJ__ROW_PRESCRIBED)
            record[RJ__JD_TQ0 + RJ_TORQUE_DRIVE] = row->lam / f->kick;
        else
            record[RJ__JD_TQ0 + RJ_TORQUE_SPRING] += t->coef * row->lam / f->kick;
    }
    /* the first step's J v^{-1/2}: 2 J v(0) less the rate before the impulses */
    if (f->first)
        back = 2 * back - row->before;
    if (row->kind == RJ__ROW_PRESCRIBED) {
        out->drive += 0.5 * row->lam * back;
        out->drive_pending += 0.5 * row->lam * after;
    } else {
        out->loss -= 0.5 * row->lam * back;
        out->pending -= 0.5 * row->lam * after;
    }
}
/* Stage 5c of scenes with prescribed joints or exact couplings: their rows (src/rows.h)
   in node space, before the latches: the prescribed joints land on their profiles, the
   couplings' e at 0, at n + 1. Several rows are solved together (rj__rows_direct), then
   swept one by one until none misses its target by more than 1e-15 rad (at most 100
   sweeps; after the solve the first finds round-off). Apart (not inlined; the frames' record by value and the
   sums returned: a pointer to the record would keep it out of registers in the whole
   step), so a scene without rows pays one test. */
static RJ__NOINLINE rj__rows_sums rj__stage_rows(const rj_model *m, const rj_state *s,
                                                 rj__frames f)
{
    rj__rows_sums out;
    rj__rows R;
    int j, sweep;
    memset(&out, 0, sizeof out);
    R.row = s->rows;
    R.term = s->terms;
    R.count = R.terms = 0;
    /* a pair's profile is a torque (rj__stage_pair_latches) */
    for (j = 0; j < m->nj; j++)
        if (rj__prescribed(&m->jnt[j]) && !m->jnt[j].pair)
            rj__row_prescribed(m, s, &R, j, j, RJ__FJ(m, f.old, j)[RJ__JD_THETA], f.t, f.dt);
    rj__rows_couplings(m, &R, RJ__FJ(m, f.old, 0) + RJ__JD_THETA, RJ__JD_COUNT, NULL, f.dt);
    rj__rows_before(m, s, &f, &R);
    if (R.count > 1)
        rj__rows_direct(m, s, &f, &R, &out.fin);
    for (sweep = 0; sweep < 100; sweep++)
        if (!rj__rows_sweep(m, s, &f, &R, &out.fin))
            break;
    for (j = 0; j < R.count; j++)
        rj__row_account(m, s, &f, &R, &R.row[j], &out);
    return out;
}

/* The rows' stage on the step's frames and sums. */
static RJ__FORCE_INLINE void rj__update_rows(const rj_model *m, const rj_state *s,
                                             const rj__frames *f, rj__sums *e, double *fin)
{
    const rj__rows_sums out = rj__stage_rows(m, s, *f);
    e->drive += out.drive;
    e->kinetic += out.drive;
    e->drive_pending += out.drive_pending;
    e->lost_limit += out.loss;
    e->kinetic -= out.loss;
    e->pending += out.pending;
    *fin += out.fin;
}

/* Stage 5, the limits' velocity-level responses, and the work of the joint torques. */
static RJ__FORCE_INLINE void rj__stage_velocity_limits(const rj_model *m, rj_state *s,
                                                       const rj__frames *f, rj__sums *e,
                                                       double *fin, int held)
{
    int j;
    if (m->nmotion)
        rj__update_rows(m, s, f, e, fin);
    for (j = 0; j < m->nj; j++) {
        const rj_joint_def *d = &m->jdef[j];
        const rj__joint *J = &m->jnt[j];
        double *new_joint = RJ__FJ(m, f->next, j), *kept = s->jsc + 8 * j;
        const double *old_joint = RJ__FJ(m, f->old, j);
        rj__jgeo g;
        double w1, w2, ratep;
        int flag = f->new_flags[j];
        rj__kept_geo(kept, &g);
        ratep = rj__joint_rate(J, &g, f->nvx, f->nvy, f->nw, &w1, &w2);
        /* a pair's latches acted as torques (rj__stage_pair_latches) */
        if (flag == RJ_FREE && rj__velocity_method(d->method) && !(held && J->pair))
            flag = rj__recontact(J, old_joint, ratep, &f->new_flags[j], kept);
        if (flag != RJ_FREE && rj__velocity_method(d->method) && !(held && J->pair) &&
            rj__into_limit(flag, ratep))
            ratep = rj__joint_jump(m, f, j, flag, &g, w1, w2, e, fin);
        rj__element_work(old_joint, new_joint, kept[4], f->dt, &e->lost_damping, &e->lost_friction,
                         &e->lost_limit);
        /* a prescribed joint's work is its row's, but a pair's is its torque's */
        if (J->act && (!rj__prescribed(J) || (held && J->pair)))
            e->drive += rj__drive_work(old_joint, new_joint, kept[4], f->dt);
        new_joint[RJ__JD_RATE] = ratep;
    }
}

/* Stage 6a: rigid bodies' poses at n + 1. */
static RJ__FORCE_INLINE void rj__constrain_bodies(const rj_model *m, const rj__frames *f,
                                                  double *fin)
{
    int gi;
    for (gi = 0; gi < m->ncl; gi++) {
        const double *oc = RJ__FCL(m, f->old, gi);
        double *nc = RJ__FCL(m, f->next, gi);
        if (m->cl_first[gi] == m->cl_first[gi + 1])
            continue;
        nc[0] = oc[0] + f->dt * nc[2];
        nc[1] = oc[1] + f->dt * nc[3];
        nc[5] = oc[5] + f->dt * nc[4];
        *fin += rj__cl_pose(m, gi, nc, f->x, f->y, f->dt, 1, f->nx, f->ny, f->nphi, f->nvx, f->nvy,
                            f->nw);
    }
}

/* The kinetic energy again, with the projected velocities (inextensible links). */
static RJ__FORCE_INLINE double rj__kinetic_again(const rj_model *m, const rj__frames *f)
{
    const double *vx = f->vx, *vy = f->vy, *w = f->w;
    const double *nvx = f->nvx, *nvy = f->nvy, *nw = f->nw;
    const int first = f->first;
    double k0 = 0;
    int i, gi;
    for (i = 0; i < m->nn; i++) {
        const double vmx = first ? 2 * vx[i] - nvx[i] : vx[i],
                     vmy = first ? 2 * vy[i] - nvy[i] : vy[i];
        const double vmw = first ? 2 * w[i] - nw[i] : w[i];
        k0 += m->kmass[i] * (vmx * nvx[i] + vmy * nvy[i]) + m->krot[i] * vmw * nw[i];
    }
    for (gi = 0; gi < m->ng; gi++) {
        const int r0 = m->grp_node[m->grp_first[gi]];
        double msum = 0;
        int q;
        if (!(m->grp_inv[gi] > 0))
            continue;
        for (q = m->grp_first[gi]; q < m->grp_first[gi + 1]; q++)
            msum += m->mass[m->grp_node[q]];
        k0 += msum * ((first ? 2 * vx[r0] - nvx[r0] : vx[r0]) * nvx[r0] +
                      (first ? 2 * vy[r0] - nvy[r0] : vy[r0]) * nvy[r0]);
    }
    for (gi = 0; gi < m->ncl; gi++)
        if (m->cl_first[gi] < m->cl_first[gi + 1] && m->cl_fix[gi] != 2)
            k0 += rj__cl_ke2(m, gi, RJ__FCL(m, f->old, gi), RJ__FCL(m, f->next, gi), first);
    return 0.5 * k0;
}

/* Node k's offset from its body's anchor at n (old: the positions at n and the body's
   old record) or now. The pushes act along the pins' directions at n, as SHAKE's along
   the chords at n: with those of the poses now the balance lost 0.019 J of 9 J in 2 s. */
static void rj__body_point(const rj_model *m, const rj__frames *f, int k, int old, double r[2])
{
    const int c = m->node_cl[k];
    const double *nc = RJ__FCL(m, old ? f->old : f->next, c);
    r[0] = (old ? f->x[k] : f->nx[k]) - nc[0];
    r[1] = (old ? f->y[k] : f->ny[k]) - nc[1];
}

/* The 2 x 2 block of pins p, q through body c: sign ((1/M) I + (1/I) perp(rp) perp(rq)^T),
   rp now, rq at n (perp(r) = (-r_y, r_x)). */
static void rj__body_block(const rj_model *m, int c, const double rp[2], const double rq[2],
                           double sign, double *A, int n2, int p, int q)
{
    const double tinv = m->cl_fix[c] == 0 ? 1.0 / m->cl_M[c] : 0.0;
    const double rinv = m->cl_fix[c] != 2 ? 1.0 / m->cl_I[c] : 0.0;
    A[(size_t) (2 * p) * n2 + 2 * q] += sign * (tinv + rinv * rp[1] * rq[1]);
    A[(size_t) (2 * p) * n2 + 2 * q + 1] += sign * (-rinv * rp[1] * rq[0]);
    A[(size_t) (2 * p + 1) * n2 + 2 * q] += sign * (-rinv * rp[0] * rq[1]);
    A[(size_t) (2 * p + 1) * n2 + 2 * q + 1] += sign * (tinv + rinv * rp[0] * rq[0]);
}

/* Newton's matrix of the pins between bodies: pin p's gap P_a - P_b moves by A_pq
   lambda_q when the push lambda_q acts on q's first body and -lambda_q on its second. */
static void rj__body_pins_matrix(const rj_model *m, const rj__frames *f, double *A)
{
    const int n2 = 2 * m->nbp;
    int p, q, sp, sq;
    for (p = 0; p < n2 * n2; p++)
        A[p] = 0;
    for (p = 0; p < m->nbp; p++)
        for (q = 0; q < m->nbp; q++)
            for (sp = 0; sp < 2; sp++)
                for (sq = 0; sq < 2; sq++) {
                    const int kp = m->bp_node[2 * p + sp], kq = m->bp_node[2 * q + sq];
                    const int c = m->node_cl[kp];
                    double rp[2], rq[2];
                    if (c != m->node_cl[kq] || m->cl_fix[c] == 2)
                        continue;
                    rj__body_point(m, f, kp, 0, rp);
                    rj__body_point(m, f, kq, 1, rq);
                    rj__body_block(m, c, rp, rq, (sp ? -1.0 : 1.0) * (sq ? -1.0 : 1.0), A, n2,
                                   p, q);
                }
}

/* Solves the n x n system A x = b in place (A and b overwritten) by elimination with
   partial pivoting; a pivot below 1e-12 of the largest diagonal is a repeated pin (a
   closed chain of bodies gone flat): its unknown is 0. */
static void rj__body_pins_solve(int n, double *A, double *b, double *x)
{
    double largest = 0;
    int i, j, k;
    for (i = 0; i < n; i++)
        largest = fmax(largest, fabs(A[(size_t) i * n + i]));
    for (k = 0; k < n; k++) {
        int pivot = k;
        for (i = k + 1; i < n; i++)
            if (fabs(A[(size_t) i * n + k]) > fabs(A[(size_t) pivot * n + k]))
                pivot = i;
        for (j = 0; j < n && pivot != k; j++) {
            const double t = A[(size_t) k * n + j];
            A[(size_t) k * n + j] = A[(size_t) pivot * n + j];
            A[(size_t) pivot * n + j] = t;
        }
        if (pivot != k) {
            const double t = b[k];
            b[k] = b[pivot];
            b[pivot] = t;
        }
        if (!(fabs(A[(size_t) k * n + k]) > 1e-12 * largest))
            continue;
        for (i = k + 1; i < n; i++) {
            const double factor = A[(size_t) i * n + k] / A[(size_t) k * n + k];
            for (j = k; j < n; j++)
                A[(size_t) i * n + j] -= factor * A[(size_t) k * n + j];
            b[i] -= factor * b[k];
        }
    }
    for (k = n - 1; k >= 0; k--) {
        double v = b[k];
        if (!(fabs(A[(size_t) k * n + k]) > 1e-12 * largest)) {
            x[k] = 0;
            continue;
        }
        for (j = k + 1; j < n; j++)
            v -= A[(size_t) k * n + j] * x[j];
        x[k] = v / A[(size_t) k * n + k];
    }
}

/* The pushes lambda on the bodies, along the pins at n: each body moves by its share in
   position and, over dt, in velocity (as SHAKE moves a node), then takes its members to
   its pose. */
static void rj__body_pins_move(const rj_model *m, const rj__frames *f, const double *lam,
                               double *imp, double *fin)
{
    int p, side, c;
    for (c = 0; c < 3 * m->ncl; c++)
        imp[c] = 0;
    for (p = 0; p < m->nbp; p++)
        for (side = 0; side < 2; side++) {
            const int k = m->bp_node[2 * p + side];
            const double sign = side ? -1.0 : 1.0, lx = sign * lam[2 * p],
                         ly = sign * lam[2 * p + 1];
            double r[2];
            c = m->node_cl[k];
            rj__body_point(m, f, k, 1, r);
            imp[3 * c] += lx;
            imp[3 * c + 1] += ly;
            imp[3 * c + 2] += r[0] * ly - r[1] * lx;
        }
    for (c = 0; c < m->ncl; c++) {
        double *nc = RJ__FCL(m, f->next, c);
        if (m->cl_fix[c] == 2 || (imp[3 * c] == 0 && imp[3 * c + 1] == 0 && imp[3 * c + 2] == 0))
            continue;
        rj__cl_push(m, c, imp + 3 * c, f->dt, nc);
        *fin += rj__cl_pose(m, c, nc, f->x, f->y, f->dt, 1, f->nx, f->ny, f->nphi, f->nvx,
                            f->nvy, f->nw);
    }
}

/* With loops: the pushes of the pins between bodies summed over a step's passes, 2 a pin
   (x, y), after rj__body_pins' matrices, gaps, pushes and bodies' impulses in its
   scratch (rj_state.bpw). */
static double *rj__body_pins_tot(const rj_model *m, const rj_state *s)
{
    const size_t n2 = 2 * (size_t) m->nbp;
    return s->bpw + 2 * n2 * n2 + 2 * n2 + 3 * (size_t) m->ncl;
}

/* Pins between two rigid bodies of a mixed scene, on positions: Newton on the pins' gaps
   (the matrix of the first pass serves the later ones; at most 20 passes, to 1e-14 of the
   longest body pinned), the bodies' velocities following their corrections, as SHAKE
   does for inextensible links; the sum of what it wrote into *fin. With loops, each
   pin's pushes summed over the passes into tot (rj__body_pins_tot). */
static void rj__body_pins(const rj_model *m, rj_state *s, const rj__frames *f, double *fin)
{
    const int n2 = 2 * m->nbp;
    double *A = s->bpw, *LU = A + (size_t) n2 * n2, *gap = LU + (size_t) n2 * n2;
    double *lam = gap + n2, *imp = lam + n2, *tot = rj__body_pins_tot(m, s), scale = 0;
    int pass, p;
    for (p = 0; p < n2 && m->nloop; p++)
        tot[p] = 0;
    for (p = 0; p < m->nbp; p++) {
        int link, node;
        rj__node_of(m, m->bp_node[2 * p], &link, &node);
        scale = fmax(scale, m->ldef[link].length);
    }
    for (pass = 0; pass < 20; pass++) {
        double worst = 0;
        for (p = 0; p < m->nbp; p++) {
            const int a = m->bp_node[2 * p], b = m->bp_node[2 * p + 1];
            gap[2 * p] = -(f->nx[a] - f->nx[b]);
            gap[2 * p + 1] = -(f->ny[a] - f->ny[b]);
            worst = fmax(worst, fmax(fabs(gap[2 * p]), fabs(gap[2 * p + 1])));
        }
        if (!(worst > 1e-14 * scale))
            break;
        if (pass == 0)
            rj__body_pins_matrix(m, f, A);
        memcpy(LU, A, sizeof(double) * (size_t) n2 * (size_t) n2);
        rj__body_pins_solve(n2, LU, gap, lam);
        rj__body_pins_move(m, f, lam, imp, fin);
        for (p = 0; p < n2 && m->nloop; p++)
            tot[p] += lam[p];
    }
}

/* Node space: the pin node whose balance gives joint j's pin force, body 2's, or body 1's
   (*sign -1) where body 2 is a rigid body of a mixed scene (its own nodes are massless,
   their body takes the pin's force); -1 for the ground. */
static int rj__balance_node(const rj_model *m, int j, double *sign)
{
    const rj__joint *J = &m->jnt[j];
    const int body2 = rj__own_body_node(m, J->nJ);
    *sign = body2 ? -1.0 : 1.0;
    return body2 ? J->nI : J->nJ;
}

/* How node space knows a loop joint's pin force (rj__loop_side). */
enum { RJ__LOOP_NONE, RJ__LOOP_NODE, RJ__LOOP_BODIES, RJ__LOOP_GROUND };

/* Node space: where loop joint j's pin force comes from: between two rigid bodies, the
   pushes of the pin between them (RJ__LOOP_BODIES); pinning a rigid body to the ground,
   the body's balance (RJ__LOOP_GROUND: the body holds its pin to the ground itself);
   else the balance of its pin node *node (rj__balance_node, RJ__LOOP_NODE) less what its
   own link's lengths put on it. None for a chord reference on a flexible pin node (the
   joint's torque acts on that node as forces). */
static int rj__loop_side(const rj_model *m, int j, int *node, double *sign)
{
    const rj__joint *J = &m->jnt[j];
    *node = rj__balance_node(m, j, sign);
    if (*sign < 0 && rj__own_body_node(m, J->nI))
        return RJ__LOOP_BODIES;
    if (*sign < 0 && J->nI < 0)
        return RJ__LOOP_GROUND;
    if (*node < 0 || J->chord)
        return RJ__LOOP_NONE;
    return RJ__LOOP_NODE;
}

/* The pushes of the pins between bodies at node k on its body over the step (summed
   over the passes, rj__body_pins_tot), into out: +lambda on a pin's first node, -lambda
   on its second. */
static void rj__loop_pins_push(const rj_model *m, const rj_state *s, int k, double out[2])
{
    const double *tot = rj__body_pins_tot(m, s);
    int p;
    for (p = 0; p < m->nbp; p++) {
        double sign = 0;
        if (m->bp_node[2 * p] == k)
            sign = 1;
        if (m->bp_node[2 * p + 1] == k)
            sign = -1;
        out[0] += sign * tot[2 * p];
        out[1] += sign * tot[2 * p + 1];
    }
}

/* SHAKE's pushes over the step (rj_state.shp) on node k from its own link's elements, into
   out: the element before it (k its second node) and the one after (k + 1 its second
   node; a link's root is no element's second node, so past its tip none). A push moves
   its owner by 2 / M of it. */
static void rj__loop_shake_push(const rj_model *m, const rj_state *s, int k, double out[2])
{
    out[0] = 2.0 * s->shp[2 * k];
    out[1] = 2.0 * s->shp[2 * k + 1];
    if (k + 1 == m->nn)
        return;
    out[0] -= 2.0 * s->shp[2 * k + 2];
    out[1] -= 2.0 * s->shp[2 * k + 3];
}

/* The projections' pushes over the step on rigid body c of a mixed scene, into out: the
   pins between it and other bodies' on its own nodes (rj__loop_pins_push), and the
   lengths' of the inextensible links whose nodes it carries on those nodes
   (rj__loop_shake_push). */
static void rj__loop_body_push(const rj_model *m, const rj_state *s, int c, double out[2])
{
    int q;
    for (q = m->cl_first[c]; q < m->cl_first[c + 1]; q++) {
        const int k = m->cl_node[q];
        double push[2] = { 0, 0 };
        if (RJ__CL_RIGID(m, k) && m->nbp)
            rj__loop_pins_push(m, s, k, push);
        if (!RJ__CL_RIGID(m, k) && m->any_inext)
            rj__loop_shake_push(m, s, k, push);
        out[0] += push[0];
        out[1] += push[1];
    }
}

/* The projections' forces in the step on the loop joints, the step's record of them
   (rj_state.loop_force), stamped with the step they belong to: on a loop's pin node
   (rj__loop_side), its own link's lengths' (rj__loop_shake_push; none on a flexible
   link); between two rigid bodies, the pin's on body 2 (rj__loop_pins_push); pinning a
   rigid body to the ground, all the body's (rj__loop_body_push). A push moves
   positions, and the velocities over dt: an impulse over dt, a force over the kick too. */
static RJ__NOINLINE void rj__loop_records(const rj_model *m, rj_state *s, const rj__frames *f)
{
    const double per = 1.0 / (f->dt * f->kick);
    int j, node;
    for (j = 0; j < m->nj; j++) {
        double *rec = s->loop_force + 2 * j, sign;
        const int kind = m->jnt[j].loop ? rj__loop_side(m, j, &node, &sign) : RJ__LOOP_NONE;
        rec[0] = rec[1] = 0;
        if (kind == RJ__LOOP_BODIES)
            rj__loop_pins_push(m, s, m->jnt[j].nJ, rec);
        if (kind == RJ__LOOP_GROUND)
            rj__loop_body_push(m, s, m->node_cl[m->jnt[j].nJ], rec);
        if (kind == RJ__LOOP_NODE && m->any_inext)
            rj__loop_shake_push(m, s, node, rec);
        rec[0] *= per;
        rec[1] *= per;
    }
    s->loop_force[2 * m->nj] = (double) (s->steps + 1);
}

/* The joints' rates at n + 1/2 again, from the projected velocities, on the geometry at n
   that stage 5 took them on. The next step books each joint torque's work over this
   step as its torque times this rate: taken before the projection, a motor on a rigid
   body that a pin between bodies turned did 40 % less work in the accounts than on the
   bodies, and the balance stopped the run at its first step. */
static void rj__rates_again(const rj_model *m, const rj_state *s, const rj__frames *f)
{
    int j;
    for (j = 0; j < m->nj; j++) {
        rj__jgeo g;
        rj__kept_geo(s->jsc + 8 * j, &g);
        RJ__FJ(m, f->next, j)[RJ__JD_RATE] =
            rj__joint_rate(&m->jnt[j], &g, f->nvx, f->nvy, f->nw, NULL, NULL);
    }
}

/* Stage 6, constraints on positions: rigid bodies' poses, the pins between bodies;
   inextensible links projected (constraint forces do no work: the velocities follow the
   projected positions, and the kinetic energy is taken again with them). */
static RJ__FORCE_INLINE void rj__stage_constraints(const rj_model *m, rj_state *s,
                                                   const rj__frames *f, rj__sums *e, double *fin,
                                                   int held)
{
    const double *x = f->x, *y = f->y;
    double *nx = f->nx, *ny = f->ny;
    double idt;
    int i;
    rj__constrain_bodies(m, f, fin);
    if (!held || !m->project)
        return;
    idt = 1.0 / f->dt;
    if (m->nbp)
        rj__body_pins(m, s, f, fin);
    if (m->any_inext)
        rj__shake(m, s, x, y, nx, ny);
    if (m->nloop)
        rj__loop_records(m, s, f);
    for (i = 0; i < m->nn; i++) {
        f->nvx[i] = (nx[i] - x[i]) * idt;
        f->nvy[i] = (ny[i] - y[i]) * idt;
        /* velocities from positions: summed too (see rj__cl_pose) */
        *fin += ((nx[i] + ny[i]) + f->nphi[i]) + (f->nvx[i] + f->nvy[i]);
    }
    if (f->en)
        e->kinetic = rj__kinetic_again(m, f);
    rj__rates_again(m, s, f);
}

/* Forced displacement (sec. 3): a joint past its limit, or off its lock, turned back by p;
   a rigid body's node turns its body (positions only). Returns the running angle. */
static RJ__FORCE_INLINE double rj__force_back(const rj_model *m, const rj__frames *f, int j,
                                              const rj__jgeo *g, double run, double *fin)
{
    const rj__joint *J = &m->jnt[j];
    const int flag = f->new_flags[j];
    double target = run, p;
    int k;
    if (flag == RJ_AT_FORWARD && run > J->fwd)
        target = J->fwd;
    else if (flag == RJ_AT_REVERSE && run < J->rev)
        target = J->rev;
    else if (flag == RJ_LOCKED)
        target = RJ__FJ(m, f->next, j)[RJ__JD_LOCK];
    p = target - run;
    if (p == 0)
        return run;
    rj__turn(J, -p * J->w1, p * J->w2, f->nx, f->ny, f->nphi);
    *fin += rj__joint_nodes_sum(J, f->nx, f->ny, f->nphi);
    if (m->ncl) {
        const int nodes[2] = { J->nI, J->nJ };
        for (k = 0; k < 2; k++)
            if (nodes[k] >= 0 && RJ__CL_RIGID(m, nodes[k])) {
                const int c = m->node_cl[nodes[k]];
                double *nc = RJ__FCL(m, f->next, c);
                nc[5] = f->nphi[nodes[k]] - (m->phi0[nodes[k]] - m->cl_th0[3 * c]);
                *fin += rj__cl_pose(m, c, nc, f->x, f->y, f->dt, 0, f->nx, f->ny, f->nphi, f->nvx,
                                    f->nvy, f->nw);
            }
    }
    return J->chord ? target : rj__joint_raw(J, g, f->nphi);
}

/* Stage 7, the joints' running angles at n + 1 (unwrapped in chord mode), and forced
   displacement back to the limit. */
static RJ__FORCE_INLINE rj_result rj__stage_joint_angles(const rj_model *m, rj_state *s,
                                                         const rj__frames *f, double *fin,
                                                         int held)
{
    int j;
    for (j = 0; j < m->nj; j++) {
        const rj_joint_def *d = &m->jdef[j];
        const rj__joint *J = &m->jnt[j];
        double *new_joint = RJ__FJ(m, f->next, j);
        rj__jgeo g;
        double raw, turn, run;
        rj__joint_geo(m, J, f->nx, f->ny, &g);
        raw = rj__joint_raw(J, &g, f->nphi);
        turn = J->chord ? rj__wrap(raw - new_joint[RJ__JD_THETA]) : raw - new_joint[RJ__JD_THETA];
        if (!(fabs(turn) <= 0.5 * RJ__PI))
            return rj__stop(m, s, RJ_ERR_TUNNEL,
                            "t = %.9g s: joint %d turned %.4g rad in one step (more than a quarter "
                            "revolution, pi/2 rad): the step %g s is far too large for its speed%s",
                            f->t, j, turn, f->dt,
                            d->has_forward || d->has_reverse ? "; its limits could be tunnelled"
                                                             : "");
        run = new_joint[RJ__JD_THETA] + turn;
        /* a pair's forced limit acted as a torque (rj__stage_pair_latches) */
        if (d->method == RJ_METHOD_FORCED && f->new_flags[j] != RJ_FREE && !(held && J->pair))
            run = rj__force_back(m, f, j, &g, run, fin);
        new_joint[RJ__JD_THETA] = run;
    }
    return RJ_OK;
}

/* The energy tests' verdict when they fail: the message, naming the test, the fastest
   node (frame; NULL for rigid links in joint coordinates) and the likely causes. */
static rj_result rj__energy_stop(const rj_model *m, rj_state *s, const double *frame, double t,
                                 rj__sums e, double scale, double created)
{
    const double ke = e.kinetic, U = e.strain, lost_l = e.lost_limit;
    const double E = U > fabs(ke) ? U : fabs(ke);
    char buffer[400], where[400];
    const char *causes;
    if (frame) {
        int bl, bn;
        rj__worst_node(m, frame, &bl, &bn);
        snprintf(where, sizeof where, "fastest node link %d node %d", bl, bn);
    } else
        rj__rig_fastest(m, s, where, sizeof where);
    causes = rj__blowup_causes(m, m->nload > 0 || s->inputs || s->node_inputs, e.work,
                               fabs(ke) + fabs(U), buffer, sizeof buffer);
    if (created > RJ__CREATED * scale || lost_l < -RJ__CREATED * scale)
        return rj__stop(m, s, RJ_ERR_BLOWUP,
                        "t = %.9g s: %.6g J of energy created (balance %.6g J, limit work %.6g J; "
                        "more than %g of the initial %.6g J); %s; %s",
                        t, created > -lost_l ? created : -lost_l, created, -lost_l, RJ__CREATED,
                        scale, where, causes);
    if (!rj__finite(E) || !rj__finite(ke + U) || !rj__finite(lost_l))
        return rj__stop(m, s, RJ_ERR_BLOWUP, "t = %.9g s: non-finite energy, %s; %s", t, where,
                        causes);
    return rj__stop(m, s, RJ_ERR_BLOWUP,
                    "t = %.9g s: kinetic or strain energy %.6g J exceeds %g x the initial %.6g J; "
                    "%s; %s",
                    t, E, m->solver.energy_growth, scale, where, causes);
}

/* The energy tests, the same for every link model. An unstable mode alternates in sign:
   v^{n-1/2}.v^{n+1/2} turns negative while the strain grows, and their sum is what the
   scheme conserves, so each is tested alone; and limit responses are dissipative, so energy
   they put in means chatter. frame: the nodes to name the fastest of (NULL: rigid links in
   joint coordinates). e0 is the initial energy, old_spring the springs' energy at n - 1. */
static RJ__FORCE_INLINE rj_result rj__energy_check(const rj_model *m, rj_state *s,
                                                   const double *frame, double t, const rj__sums *e,
                                                   double old_spring, double e0)
{
    const double ke = e->kinetic, U = e->strain, V = e->spring, lost_l = e->lost_limit;
    const double E = U > fabs(ke) ? U : fabs(ke);
    /* the initial energy less gravity's potential now, plus the inputs' work: what gravity
       has released and the caller has put in may turn into kinetic energy */
    const double outside = e->gravity - e->work - e->drive; /* gravity, the caller, the drives */
    /* a drive that lifts a load and holds it moves energy that outside nets out */
    const double scale =
        fabs(e0 - outside) + fabs(old_spring) + s->settle_scale + e->drive_flow + 1e-9;
    const double created = ke + U + V + outside + e->lost_damping + e->lost_friction + lost_l +
                           e->lost_material - e0;
    if (!rj__finite(E) || !rj__finite(ke + U) || !rj__finite(lost_l) ||
        E > m->solver.energy_growth * (scale + fabs(V)) || created > RJ__CREATED * scale ||
        lost_l < -RJ__CREATED * scale)
        return rj__energy_stop(m, s, frame, t, *e, scale, created);
    return RJ_OK;
}

/* The actuators' work moved this step, into the flow the energy tests scale by. */
static void rj__drive_flow(const double *osc, double *nsc, rj__sums *e)
{
    const double before = osc[RJ__FS_DRIVE] + osc[RJ__FS_DPEND];
    const double after = e->drive + e->drive_pending;
    e->drive_flow += fabs(after - before);
    nsc[RJ__FS_DFLOW] = e->drive_flow;
}

/* Gravity's potential moved since the last accounts (the state's start sets it), into
   the same flow: a pendulum at the top of its swing has released nothing net, but the
   scheme's error is on all that moved (a four-bar of rigid bars stopped there with
   1.1e-6 J "created" of 5.6e-5 J). */
static void rj__gravity_flow(const double *osc, double *nsc, rj__sums *e)
{
    e->drive_flow += fabs(e->gravity - osc[RJ__FS_GRAV]);
    nsc[RJ__FS_DFLOW] = e->drive_flow;
}

/* The accounts of a first step (from rest): the energy there is the initial energy, and
   the losses and work start from zero. */
static void rj__first_accounts(double *new_scalars, rj__sums *e, double energy)
{
    /* a prescribed joint driven from the start has put its first step's work into the
       energy there: the initial energy is the one before it, and the work is kept (its
       second half, pending, is the next step's) */
    new_scalars[RJ__FS_E0] = energy - e->drive;
    rj__accounts_zero(new_scalars);
    e->lost_damping = e->lost_friction = e->work = e->lost_limit = e->lost_material = 0;
    new_scalars[RJ__FS_DRIVE] = e->drive;
    new_scalars[RJ__FS_DPEND] = e->drive_pending;
}

/* The new frame's scalars: time, the accounts (on the steps that take them; the initial
   energy in the same discrete form as every later one), and the energy tests. */
static RJ__FORCE_INLINE rj_result rj__step_accounts(const rj_model *m, rj_state *s,
                                                    const rj__frames *f, rj__sums *e)
{
    const double *osc = f->old_scalars;
    double *nsc = f->new_scalars;
    const double warn = nsc[RJ__FS_WARN]; /* counted in this step already */
    memcpy(nsc, osc, sizeof(double) * RJ__FS_COUNT);
    nsc[RJ__FS_WARN] = warn;
    nsc[RJ__FS_TIME] = f->t + f->dt;
    nsc[RJ__FS_LDAMP] = e->lost_damping;
    nsc[RJ__FS_LFRIC] = e->lost_friction;
    nsc[RJ__FS_LLIM] = e->lost_limit;
    nsc[RJ__FS_PEND] = e->pending;
    if (m->nmaterial)
        e->lost_material = rj__material_accounts(m, s, osc, nsc, f->nvx, f->nvy, f->nw);
    nsc[RJ__FS_WORK] = e->work;
    nsc[RJ__FS_DRIVE] = e->drive;
    nsc[RJ__FS_DPEND] = e->drive_pending;
    if (m->nact)
        rj__drive_flow(osc, nsc, e);
    if (!f->en)
        return RJ_OK;
    nsc[RJ__FS_ETIME] = f->t;
    nsc[RJ__FS_KE] = e->kinetic;
    nsc[RJ__FS_STRAIN] = e->strain;
    nsc[RJ__FS_SPRING] = e->spring;
    if (m->has_gravity)
        rj__gravity_flow(osc, nsc, e);
    nsc[RJ__FS_GRAV] = e->gravity;
    if (f->first)
        rj__first_accounts(nsc, e, e->kinetic + e->strain + e->spring + e->gravity);
    return rj__energy_check(m, s, f->advanced, f->t, e, osc[RJ__FS_SPRING], nsc[RJ__FS_E0]);
}

/* The step's end: in place, the new scalars, joints and bodies join the advanced nodes;
   double-buffered, the frames swap. */
static RJ__FORCE_INLINE void rj__step_commit(const rj_model *m, rj_state *s, const rj__frames *f)
{
    if (f->ip) {
        const size_t j0 = RJ__FS_COUNT + 6 * (size_t) m->nn + 3 * (size_t) m->ne;
        memcpy(f->current, f->next, sizeof(double) * RJ__FS_COUNT);
        memcpy(f->current + j0, f->next + j0, sizeof(double) * (m->frame_doubles - j0));
        memcpy(s->fi[s->cur], f->new_flags, sizeof(int) * (m->frame_ints + 1));
    } else
        s->cur = 1 - s->cur;
    s->steps++;
}

/* One step of flexible, inextensible and mixed scenes, stage by stage; the energy accounts
   are taken when want_energy is set, at the first step, and solver.energy_every steps after
   the last time. ip: in place (rj__step below); held: the scene has constraints on
   positions or joints between two rigid bodies (rj__step_held), compiled apart so that
   the others carry none of their code. Every stage adds to fin the positions it
   wrote, each from the velocity, torque or body motion behind it: finite while they all
   are. Applied loads enter between stages 2 and 3, so that friction sees them. */
static RJ__FORCE_INLINE rj_result rj__step_run(const rj_model *m, rj_state *s, int want_energy,
                                               int ip, int held)
{
    rj__frames f;
    rj__sums e;
    rj__adv adv;
    rj_result r;
    double fin = 0;
    /* rj__stage_applied's */
    const int applied = s->inputs | s->node_inputs | m->applied;
    rj__frames_open(m, s, want_energy, ip, &f);
    rj__frames_nodes(m, &f);
    rj__sums_open(f.old_scalars, &e);
    adv.fin = &fin;
    rj__stage_beams(m, s, &f, &adv, &e);
    rj__stage_joint_torques(m, s, &f, &e);
    if (m->ncp)
        e.spring += rj__stage_couplings(m, s, f.old, f.next);
    if (applied) {
        r = rj__stage_applied(m, s, f.next, f.t, f.ip ? f.next : f.current, f.advanced, f.kick);
        if (r != RJ_OK)
            return r;
        e.work += s->step_work;
        fin += s->step_fin;
    }
    rj__stage_friction(m, s, &f, held);
    if (held && m->npair)
        rj__stage_pair_latches(m, s, &f);
    rj__stage_update(m, s, &f, &adv, &e, &fin);
    rj__stage_velocity_limits(m, s, &f, &e, &fin, held);
    if (applied)
        e.work += rj__applied_work(m, s, f.old, f.next);
    rj__stage_constraints(m, s, &f, &e, &fin, held);
    r = rj__stage_joint_angles(m, s, &f, &fin, held);
    if (r != RJ_OK)
        return r;
    if (!rj__finite(fin))
        return rj__stop_nonfinite(m, s, f.advanced, f.t);
    r = rj__step_accounts(m, s, &f, &e);
    if (r != RJ_OK)
        return r;
    rj__step_commit(m, s, &f);
    return RJ_OK;
}

/* ------------------------------------------------------------------ the rigid step */
/* Does joint j take plastic impulses at this flag (locked, forced, or e = 0 at a limit)? */
static int rj__rig_plastic(const rj_joint_def *d, int flag)
{
    const int velocity_level = d->method == RJ_METHOD_MOMENTUM || d->method == RJ_METHOD_FORCED;
    if (!velocity_level || flag == RJ_FREE)
        return 0;
    return flag == RJ_LOCKED || d->method == RJ_METHOD_FORCED || d->restitution == 0;
}

/* What the rigid step's impulses did: how many joints took one alone, the last of them,
   and whether any was an impact (a new contact or lock, or a bounce). */
typedef struct rj__rig_jumps {
    int count, last, impact;
} rj__rig_jumps;

/* Node at of rigid link l where the kinematics put it (r->lk). */
static void rj__rig_link_node(const rj_model *m, const rj__rig *r, int l, int at, double p[2])
{
    const double *b = r->lk + RJ__RL_COUNT * (size_t) l;
    const double along = at * m->link_l0[l];
    p[0] = b[RJ__RL_RX] + along * cos(b[RJ__RL_PHI]);
    p[1] = b[RJ__RL_RY] + along * sin(b[RJ__RL_PHI]);
}

/* Joint j's pins at the kinematics' positions: on body 1 (or ground) and on body 2. */
static void rj__rig_pins(const rj_model *m, const rj__rig *r, int j, double p1[2], double p2[2])
{
    const rj_joint_def *d = &m->jdef[j];
    if (d->body1 < 0) {
        p1[0] = d->ground_x;
        p1[1] = d->ground_y;
    } else
        rj__rig_link_node(m, r, d->body1, d->node1 < 0 ? m->ldef[d->body1].elements : d->node1,
                          p1);
    rj__rig_link_node(m, r, d->body2, m->jnt[j].nJ - m->link_first[d->body2], p2);
}

/* Adds to one loop row (x: axis 0, y: 1) the terms of point p on link l: sign times
   d p / d q_k = perp(p - P_k) for each tree joint k on l's path to the ground. */
static void rj__rig_loop_terms(const rj_model *m, const rj__rig *r, rj__rows *R, rj__row *row,
                               int l, const double p[2], int axis, double sign)
{
    int up;
    for (up = l >= 0 ? m->rb_pjoint[l] : -1; up >= 0; up = rj__rig_up(m, up)) {
        const double *pin = r->lk + RJ__RL_COUNT * (size_t) m->jdef[up].body2;
        const double d = axis == 0 ? -(p[1] - pin[RJ__RL_PY]) : p[0] - pin[RJ__RL_PX];
        rj__row_term(R, row, m->jq[up], sign * d);
    }
}

/* The loop joints' rows: their pins' gap p1 - p2 back to 0 at n + 1, in x and in y. A
   coordinate on both pins' paths appears twice in a row (the dot products sum them). */
static void rj__rig_loop_rows(const rj_model *m, const rj__rig *r, double dt, rj__rows *R)
{
    int j, axis;
    for (j = 0; j < m->nj; j++) {
        double p1[2], p2[2];
        if (m->jq[j] >= 0)
            continue;
        rj__rig_pins(m, r, j, p1, p2);
        for (axis = 0; axis < 2; axis++) {
            rj__row *row = rj__row_open(R, RJ__ROW_LOOP, j, -(p1[axis] - p2[axis]) / dt,
                                        -HUGE_VAL, HUGE_VAL);
            rj__rig_loop_terms(m, r, R, row, m->jdef[j].body1, p1, axis, 1.0);
            rj__rig_loop_terms(m, r, R, row, m->jdef[j].body2, p2, axis, -1.0);
        }
    }
}

/* Adds coef times joint j's rate to a row: its coordinate, or g for a joint that closes
   a loop (g: nq doubles of scratch). */
static void rj__rig_joint_terms(const rj_model *m, rj__rows *R, rj__row *row, int j, double coef,
                                double *g)
{
    int k;
    if (m->jq[j] >= 0) {
        rj__row_term(R, row, m->jq[j], coef);
        return;
    }
    rj__rig_loop_gradient(m, j, g);
    for (k = 0; k < m->nq; k++)
        if (g[k] != 0)
            rj__row_term(R, row, k, coef * g[k]);
}

/* A loop joint's bounce: at a limit by momentum with e > 0 (its row's target is -e times
   the rate the loops leave it, rj__rig_loop_bounces). */
static int rj__rig_loop_bounce(const rj_model *m, const rj__frames *f, int j)
{
    const rj_joint_def *d = &m->jdef[j];
    const int flag = f->new_flags[j];
    return d->method == RJ_METHOD_MOMENTUM && d->restitution > 0 && flag != RJ_FREE &&
           flag != RJ_LOCKED;
}

/* The rows of the joints that close loops, each along the loop joint's gradient g and
   owned by -1 - j (no single impulse holds it): a prescribed joint's profile; a latch
   (locked, or at a limit by momentum or forced displacement), a lock or a plastic contact
   row; a bounce's contact row, its target set once the loops' rows have acted. */
static void rj__rig_loop_latches(const rj_model *m, const rj_state *s, const rj__frames *f,
                                 const rj__rig *r, rj__rows *R)
{
    const int *ni = f->new_flags;
    const double *old_joints = RJ__FJ(m, f->old, 0);
    double *g = r->tmp;
    int j, k;
    for (j = 0; j < m->nj; j++) {
        const rj_joint_def *d = &m->jdef[j];
        const double theta = old_joints[(size_t) RJ__JD_COUNT * j + RJ__JD_THETA];
        const int forward = ni[j] == RJ_AT_FORWARD;
        const int velocity_level = d->method == RJ_METHOD_MOMENTUM || d->method == RJ_METHOD_FORCED;
        double target;
        rj__row *row;
        if (m->jq[j] >= 0)
            continue;
        if (rj__prescribed(&m->jnt[j])) {
            target = rj__prescribed_rate(m, s, j, theta, f->t, f->dt);
            row = rj__row_open(R, RJ__ROW_PRESCRIBED, -1 - j, target, -HUGE_VAL, HUGE_VAL);
            rj__rig_joint_terms(m, R, row, j, 1.0, g);
            continue;
        }
        if (!velocity_level || ni[j] == RJ_FREE)
            continue;
        rj__rig_loop_gradient(m, j, g);
        if (ni[j] == RJ_LOCKED)
            row = rj__row_open(R, RJ__ROW_LOCK, -1 - j, 0.0, -HUGE_VAL, HUGE_VAL);
        else if (rj__rig_loop_bounce(m, f, j)) {
            row = rj__row_open(R, RJ__ROW_CONTACT, -1 - j, 0.0, -HUGE_VAL, HUGE_VAL);
            row->active = 0;
        } else {
            /* held from the start when its rate, as the loops leave it, turns into the
               limit (rj__rows_solve_dense takes it in then), not at the rate before them */
            row = rj__row_open(R, RJ__ROW_CONTACT, -1 - j, 0.0, forward ? -HUGE_VAL : 0.0,
                               forward ? 0.0 : HUGE_VAL);
            row->active = 0;
        }
        for (k = 0; k < m->nq; k++)
            if (g[k] != 0)
                rj__row_term(R, row, k, g[k]);
    }
}

/* The exact couplings' rows in a scene with loops: e from the joints' angles at n (a
   loop joint's from its record), along w = e_b - ratio e_a over the coordinates. */
static void rj__rig_loop_couplings(const rj_model *m, const rj__frames *f, rj__rows *R,
                                   double *g)
{
    int k;
    for (k = 0; k < m->ncp; k++) {
        const rj_coupling_def *c = &m->cp[k];
        const double e_n = rj__coupling_stretch(m, c, RJ__FJ(m, f->old, c->joint_a)[RJ__JD_THETA],
                                                RJ__FJ(m, f->old, c->joint_b)[RJ__JD_THETA]);
        rj__row *row;
        if (!c->exact)
            continue;
        row = rj__row_open(R, RJ__ROW_COUPLING, k, -e_n / f->dt, -HUGE_VAL, HUGE_VAL);
        rj__rig_joint_terms(m, R, row, c->joint_b, 1.0, g);
        rj__rig_joint_terms(m, R, row, c->joint_a, -c->ratio, g);
    }
}

/* Rigid step, stage 5b: the rows in joint coordinates (src/rows.h), in joint order: a
   prescribed joint's profile; a locked joint; a plastic contact, held from the start when
   it turns into its limit or a single impulse moved its rate (a later joint's impulse
   moves an earlier one off the rate its own gave it; r->h holds the rates before them);
   then the exact couplings. The joints' impulses move each other (M^-1 couples them), so
   they are solved together: one joint after another (as the single impulses) left a
   locked joint drifting at up to 0.3 deg/s in the fidelity benchmark's rigid solar
   array, and sweeping that to convergence took hundreds of passes (W is ill-conditioned
   along a chain). */
static void rj__rig_rows_build(const rj_model *m, const rj_state *s, const rj__frames *f,
                               const rj__rig *r, rj__rows *R)
{
    const int *ni = f->new_flags;
    int k;
    R->count = R->terms = 0;
    for (k = 0; k < m->nq; k++) {
        const int j = m->qj[k];
        const double rate = r->qdp[k];
        const int forward = ni[j] == RJ_AT_FORWARD;
        rj__row *row;
        if (rj__prescribed(&m->jnt[j])) {
            rj__row_prescribed(m, s, R, j, k, r->q[k], f->t, f->dt);
            continue;
        }
        if (!rj__rig_plastic(&m->jdef[j], ni[j]))
            continue;
        if (ni[j] == RJ_LOCKED)
            row = rj__row_open(R, RJ__ROW_LOCK, k, 0.0, -HUGE_VAL, HUGE_VAL);
        else {
            row = rj__row_open(R, RJ__ROW_CONTACT, k, 0.0, forward ? -HUGE_VAL : 0.0,
                               forward ? 0.0 : HUGE_VAL);
            row->active = rate != r->h[k] || rj__into_limit(ni[j], rate);
        }
        rj__row_term(R, row, k, 1.0);
    }
    if (!m->nloop) {
        rj__rows_couplings(m, R, r->q, 1, m->jq, f->dt);
        return;
    }
    rj__rig_loop_couplings(m, f, R, r->tmp);
    rj__rig_loop_latches(m, s, f, r, R);
    rj__rig_loop_rows(m, r, f->dt, R);
}

/* The row of the one joint that took a single impulse (which held it exactly), or -1. */
static int rj__rig_held_row(const rj__rows *R, const rj__rig_jumps *jumps)
{
    int a;
    if (jumps->count != 1)
        return -1;
    for (a = 0; a < R->count; a++)
        if (R->row[a].kind <= RJ__ROW_CONTACT && R->row[a].owner == jumps->last)
            return a;
    return -1;
}

/* A prescribed loop joint's row: its impulse over the step is its drive's torque, each
   coordinate's share into r->xd (rj__rig_jump_loss books their work as the drive's). */
static void rj__rig_loop_drive(const rj_model *m, const rj__frames *f, const rj__rows *R,
                               const rj__row *row, rj__rig *r)
{
    int k;
    RJ__FJ(m, f->next, -1 - row->owner)[RJ__JD_TQ0 + RJ_TORQUE_DRIVE] = row->lam / f->kick;
    for (k = 0; k < row->count; k++) {
        const rj__term *t = &R->term[row->first + k];
        r->xd[t->joint] += t->coef * row->lam;
    }
}

/* An exact coupling's row in a scene with loops: its impulse on each coordinate into r->x,
   its torques on its two joints (lambda on b, -ratio lambda on a) into their spring
   columns. */
static void rj__rig_loop_coupling_torques(const rj_model *m, const rj__frames *f,
                                          const rj__rows *R, const rj__row *row, rj__rig *r)
{
    const rj_coupling_def *c = &m->cp[row->owner];
    int k;
    for (k = 0; k < row->count; k++) {
        const rj__term *t = &R->term[row->first + k];
        r->x[t->joint] += t->coef * row->lam;
    }
    RJ__FJ(m, f->next, c->joint_b)[RJ__JD_TQ0 + RJ_TORQUE_SPRING] += row->lam / f->kick;
    RJ__FJ(m, f->next, c->joint_a)[RJ__JD_TQ0 + RJ_TORQUE_SPRING] +=
        -c->ratio * row->lam / f->kick;
}

/* The exact couplings' and the loops' impulses: each coordinate's share into r->x
   (rj__rig_jump_loss keeps it out of the latches' impulses), the couplings' torques into
   their joints' spring columns. */
static void rj__rig_coupling_torques(const rj_model *m, const rj__frames *f, const rj__rows *R,
                                     rj__rig *r)
{
    double *new_joints = RJ__FJ(m, f->next, 0);
    int a, k;
    for (k = 0; k < m->nq; k++)
        r->x[k] = 0;
    for (k = 0; k < m->nq && m->nloop; k++)
        r->xd[k] = 0;
    for (a = 0; a < R->count; a++) {
        const rj__row *row = &R->row[a];
        const int loop_latch = row->kind <= RJ__ROW_CONTACT && row->owner < 0;
        if (row->kind == RJ__ROW_PRESCRIBED && row->owner < 0) {
            rj__rig_loop_drive(m, f, R, row, r);
            continue;
        }
        if (row->kind == RJ__ROW_COUPLING && m->nloop) {
            rj__rig_loop_coupling_torques(m, f, R, row, r);
            continue;
        }
        if (row->kind != RJ__ROW_COUPLING && row->kind != RJ__ROW_LOOP && !loop_latch)
            continue;
        /* a loop joint's latch: its impulse on its own record */
        if (loop_latch)
            new_joints[(size_t) RJ__JD_COUNT * (-1 - row->owner) + RJ__JD_IMPULSE] = row->lam;
        for (k = 0; k < row->count; k++) {
            const rj__term *t = &R->term[row->first + k];
            const double impulse = t->coef * row->lam;
            r->x[t->joint] += impulse;
            if (row->kind == RJ__ROW_COUPLING)
                new_joints[(size_t) RJ__JD_COUNT * m->qj[t->joint] + RJ__JD_TQ0 +
                           RJ_TORQUE_SPRING] += impulse / f->kick;
        }
    }
}

/* The loops' rows on positions (SHAKE): their Jacobian stays the one at q^n, where the
   pins' forces act, and their targets move until the pins meet at q^{n+1} = q^n + dt
   q'^{n+1/2}, not only to first order (a row on the rate alone, J(q^n) q' = -gap/dt,
   leaves the crank of a four-bar off the exact motion at first order in dt); the other
   rows keep their rates. At most 20 passes, to 1e-14 of the longest link. Near a
   singular position (a parallelogram going flat) the Jacobian at q^n no longer sees the
   gap's direction and the passes diverge: the rates of the best pass are kept (r->x
   holds them) and the projection onto the loop closes what is left. The kinematics run
   at the trial q (r->lk is not read again in the step). */
static void rj__rig_loops_shake(const rj_model *m, const rj__frames *f, rj__rig *r,
                                rj__rows *R, const rj__dense *D)
{
    double *q = r->tmp + m->nq, *best_rates = r->x, longest = 0, best = HUGE_VAL;
    int pass, k, a, l, axis;
    for (l = 0; l < m->nl; l++)
        longest = fmax(longest, m->ldef[l].length);
    for (pass = 0; pass < 20; pass++) {
        double worst = 0;
        for (k = 0; k < m->nq; k++)
            q[k] = r->q[k] + f->dt * r->qdp[k];
        rj__rig_kin(m, r, q, NULL, r->qdp);
        for (a = 0; a < R->count; a++) {
            rj__row *row = &R->row[a];
            double p1[2], p2[2];
            if (row->kind != RJ__ROW_LOOP)
                continue;
            rj__rig_pins(m, r, row->owner, p1, p2);
            /* a loop's x row, then its y row (rj__rig_loop_rows) */
            for (axis = 0; axis < 2; axis++, row++) {
                const double gap = p1[axis] - p2[axis];
                worst = fmax(worst, fabs(gap));
                row->target = rj__row_dot(R, row, r->qdp) - gap / f->dt;
            }
            a++;
        }
        if (worst < best) {
            best = worst;
            memcpy(best_rates, r->qdp, sizeof(double) * (size_t) m->nq);
        } else if (worst > 4 * best)
            break;
        if (worst <= 1e-14 * longest)
            return;
        rj__rows_solve_dense(R, D, r->qdp);
    }
    memcpy(r->qdp, best_rates, sizeof(double) * (size_t) m->nq);
}

/* The dense rows' solve's working arrays, in the rigid solver's scratch. */
static void rj__rig_dense(const rj_model *m, rj__rig *r, rj__dense *D)
{
    D->n = m->nq;
    D->m = m;
    D->rig = r;
    D->W = r->W;
    D->Y = r->Y;
    D->S = r->S;
    D->SL = r->SL;
    D->lam = r->lam;
    D->rhs = r->rhs;
    D->scratch = r->tmp;
}

/* The loop joints' bounces: the rows solved without them (the loops' own rows move the
   rate at which a loop joint meets its limit), each bounce row then aims at -e times that
   rate, pushing only, and the rows are solved again from the rates before (kept in
   r->xd, free until the impulses are shared out). */
static void rj__rig_loop_bounces(const rj_model *m, const rj__frames *f, rj__rig *r,
                                 rj__rows *R, const rj__dense *D)
{
    int a, any = 0;
    for (a = 0; a < R->count; a++) {
        rj__row *row = &R->row[a];
        int j, forward;
        double rate;
        if (row->kind != RJ__ROW_CONTACT || row->owner >= 0)
            continue;
        j = -1 - row->owner;
        if (!rj__rig_loop_bounce(m, f, j))
            continue;
        forward = f->new_flags[j] == RJ_AT_FORWARD;
        rate = rj__row_dot(R, row, r->qdp);
        row->target = -m->jdef[j].restitution * rate;
        row->lo = forward ? -HUGE_VAL : 0.0;
        row->hi = forward ? 0.0 : HUGE_VAL;
        row->active = rj__into_limit(f->new_flags[j], rate);
        any |= row->active;
    }
    if (!any)
        return;
    /* the second solve's impulses are the step's: the first's are dropped with its rates */
    for (a = 0; a < R->count; a++)
        R->row[a].lam = 0;
    memcpy(r->qdp, r->xd, sizeof(double) * (size_t) m->nq);
    rj__rows_solve_dense(R, D, r->qdp);
}

/* Whether a loop joint's latch row made an impact (a new contact or lock, or a bounce):
   then the step's rates are not the constrained motion's (rj__rig_stage_rates). */
static int rj__rig_loop_impact(const rj_model *m, const rj__frames *f, const rj__rows *R)
{
    int a;
    for (a = 0; a < R->count; a++) {
        const rj__row *row = &R->row[a];
        int j;
        if (row->kind > RJ__ROW_CONTACT || row->owner >= 0 || !row->active)
            continue;
        j = -1 - row->owner;
        if (f->new_flags[j] != f->old_flags[j] || rj__rig_loop_bounce(m, f, j))
            return 1;
    }
    return 0;
}

/* Each loop joint's pin force over the step, the force body 1 exerts on body 2: its two
   rows' impulses (on the gap p1 - p2, so the impulse on body 2 is -lambda) over the kick,
   stamped with the step they belong to (rj__pin_forces reads them). */
static void rj__rig_loop_forces(const rj_model *m, const rj_state *s, const rj__frames *f,
                                const rj__rows *R)
{
    int a;
    for (a = 0; a < R->count; a++) {
        const rj__row *row = &R->row[a];
        if (row->kind != RJ__ROW_LOOP)
            continue;
        /* a loop's x row, then its y row (rj__rig_loop_rows) */
        s->loop_force[2 * row->owner] = -row->lam / f->kick;
        s->loop_force[2 * row->owner + 1] = -row[1].lam / f->kick;
        a++;
    }
    s->loop_force[2 * m->nj] = (double) (s->steps + 1);
}

/* The rows' solve: none to do when the only row held is the one a single impulse held;
   with every joint locked (and no coupling) q' = 0, which the system gives to round-off. */
static void rj__rig_rows(const rj_model *m, const rj_state *s, const rj__frames *f, rj__rig *r,
                         rj__rig_jumps *jumps)
{
    rj__rows R;
    rj__dense D;
    int j, active = 0, locked = 0;
    R.row = s->rows;
    R.term = s->terms;
    rj__rig_rows_build(m, s, f, r, &R);
    D.held = rj__rig_held_row(&R, jumps);
    for (j = 0; j < R.count; j++)
        active += R.row[j].active;
    for (j = 0; j < m->nq; j++)
        locked += f->new_flags[m->qj[j]] == RJ_LOCKED;
    if (active == 0 || (active == 1 && D.held >= 0 && R.row[D.held].active))
        return;
    if (locked == m->nq && !m->nexact && !m->nloop) {
        for (j = 0; j < m->nq; j++)
            r->qdp[j] = 0;
        return;
    }
    rj__rig_dense(m, r, &D);
    if (m->nloop)
        memcpy(r->xd, r->qdp, sizeof(double) * (size_t) m->nq);
    rj__rows_solve_dense(&R, &D, r->qdp);
    if (m->nloop) {
        rj__rig_loop_bounces(m, f, r, &R, &D);
        rj__rig_loops_shake(m, f, r, &R, &D);
        rj__rig_loop_forces(m, s, f, &R);
        jumps->impact |= rj__rig_loop_impact(m, f, &R);
    }
    if (m->nexact || m->nloop)
        rj__rig_coupling_torques(m, f, &R, r);
}

/* Rigid step, stage 1: q^n, rates q'^{n-1/2} and the predicted q'^n for the centripetal
   terms; the kinematics, M(q^n) and its factor; the new frame's scalars (the element
   counts late contacts in RJ__FS_WARN). */
static RJ__FORCE_INLINE rj_result rj__rig_stage_kinematics(const rj_model *m, rj_state *s,
                                                           const rj__frames *f, rj__rig *r)
{
    const double *old_scalars = f->old_scalars;
    double *new_scalars = f->new_scalars;
    double *RJ__RESTRICT q = r->q, *RJ__RESTRICT qd = r->qd, *RJ__RESTRICT qdp = r->qdp;
    const double *old_joints = RJ__FJ(m, f->old, 0);
    const double dt = f->dt;
    const int n = m->nq;
    int j;
    for (j = 0; j < n; j++) {
        const double *old_joint = old_joints + (size_t) RJ__JD_COUNT * m->qj[j];
        q[j] = old_joint[RJ__JD_THETA];
        qd[j] = old_joint[RJ__JD_RATE];
        qdp[j] = qd[j] + 0.5 * dt * old_joint[RJ__JD_QDD];
    }
    rj__rig_kin(m, r, r->q, NULL, r->qdp);
    memcpy(new_scalars, old_scalars, sizeof(double) * RJ__FS_COUNT);
    new_scalars[RJ__FS_TIME] = f->t + f->dt;
    if (f->en)
        new_scalars[RJ__FS_ETIME] = f->t;
    new_scalars[RJ__FS_STRAIN] = 0;
    if (rj__rig_factor(m, r))
        return rj__stop(m, s, RJ_ERR_BLOWUP,
                        "t = %.9g s: the rigid mass matrix is not positive definite", f->t);
    return RJ_OK;
}

/* Gravity in joint coordinates: joint j carries the subtree beyond it, whose first moment
   about its pin is S_j (rj__rig_mass), so gravity's generalised force is S_j x g; its
   potential is -sum m g . c over the moving links. */
static void rj__rig_gravity(const rj_model *m, const rj__rig *r, double *Q, rj__sums *e)
{
    const double gx = m->solver.gravity[0], gy = m->solver.gravity[1];
    double potential = 0;
    int j, l;
    for (j = 0; j < m->nq; j++) {
        const double *sub = r->lk + RJ__RL_COUNT * (size_t) m->jdef[m->qj[j]].body2;
        Q[j] += sub[RJ__RL_SUB_SX] * gy - sub[RJ__RL_SUB_SY] * gx;
    }
    for (l = 0; l < m->nl; l++) {
        const double *b = r->lk + RJ__RL_COUNT * (size_t) l;
        if (m->rb_pjoint[l] >= 0)
            potential -= m->rb_mass[l] * (gx * b[RJ__RL_CX] + gy * b[RJ__RL_CY]);
    }
    e->gravity = potential;
}

/* A force (global frame) and moment on node k of rigid link l, at q^n: a generalised force
   (p - P_j) x f + moment on every joint j between the link and the ground (P_j its pin),
   added to the joints' RJ__JD_INPUT in new_joints. */
static void rj__rig_node_load(const rj_model *m, const rj__rig *r, int l, int k,
                              const double *value, double *new_joints)
{
    const double *b = r->lk + RJ__RL_COUNT * (size_t) l;
    const double along = k * m->link_l0[l];
    const double px = b[RJ__RL_RX] + along * b[RJ__RL_EC];
    const double py = b[RJ__RL_RY] + along * b[RJ__RL_ES];
    int j;
    for (j = m->rb_pjoint[l]; j >= 0; j = rj__rig_up(m, j)) {
        const double *pin = r->lk + RJ__RL_COUNT * (size_t) m->jdef[j].body2;
        const double dx = px - pin[RJ__RL_PX], dy = py - pin[RJ__RL_PY];
        new_joints[(size_t) RJ__JD_COUNT * j + RJ__JD_INPUT] +=
            dx * value[1] - dy * value[0] + value[2];
    }
}

/* The model's loads at t^n and the caller's node forces in joint coordinates. */
static void rj__rig_loads(const rj_model *m, const rj_state *s, const rj__rig *r, double t,
                          double *new_joints)
{
    int k, l;
    for (k = 0; k < m->nload; k++) {
        const rj_load_def *d = &m->load[k];
        const int node = m->load_node[k] - m->link_first[d->link];
        const double phi = r->lk[RJ__RL_COUNT * (size_t) d->link + RJ__RL_PHI];
        double value[3];
        rj__load_value(d, t, phi, value);
        rj__rig_node_load(m, r, d->link, node, value, new_joints);
    }
    if (!s->node_inputs)
        return;
    for (l = 0; l < m->nl; l++)
        for (k = 0; k <= m->ldef[l].elements; k++) {
            const double *in = s->input_node + 3 * (size_t) (m->link_first[l] + k);
            if (in[0] != 0 || in[1] != 0 || in[2] != 0)
                rj__rig_node_load(m, r, l, k, in, new_joints);
        }
}

/* A torque tau at joint j, which closes a loop: tau g on the coordinates (g: nq doubles
   of scratch). */
static void rj__rig_loop_force(const rj_model *m, int j, double tau, double *Q, double *g)
{
    int k;
    if (tau == 0)
        return;
    rj__rig_loop_gradient(m, j, g);
    for (k = 0; k < m->nq; k++)
        Q[k] += tau * g[k];
}

/* The element on the joints that close loops: each one's torque at the rate and angle
   its record keeps, as a generalised force on the coordinates. */
static void rj__rig_loop_torques(const rj_model *m, rj_state *s, const rj__frames *f,
                                 rj__rig *r, double *spring)
{
    const double *old_joints = RJ__FJ(m, f->old, 0);
    double *new_joints = RJ__FJ(m, f->next, 0);
    int j;
    for (j = 0; j < m->nj; j++) {
        const size_t at = (size_t) RJ__JD_COUNT * j;
        double penetration, torque;
        if (m->jq[j] >= 0)
            continue;
        torque = rj__element(m, s, j, old_joints + at, new_joints + at, f->old_flags[j],
                             &f->new_flags[j], old_joints[at + RJ__JD_RATE], f->t,
                             f->new_scalars, &penetration, spring);
        rj__rig_loop_force(m, j, torque, r->Q, r->tmp);
    }
}

/* Rigid step, stage 2: the element's torques as generalised forces, less the centripetal
   bias; the accelerations M^-1 Q. */
static RJ__FORCE_INLINE void rj__rig_stage_torques(const rj_model *m, rj_state *s,
                                                   const rj__frames *f, rj__rig *r, rj__sums *e)
{
    const double *RJ__RESTRICT qd = r->qd, *RJ__RESTRICT bias = r->h;
    double *RJ__RESTRICT Q = r->Q;
    const double *old_joints = RJ__FJ(m, f->old, 0);
    double *new_joints = RJ__FJ(m, f->next, 0);
    const double t = f->t;
    const int n = m->nq;
    double spring = 0;
    int j;
    for (j = 0; j < n; j++) {
        const size_t at = (size_t) RJ__JD_COUNT * m->qj[j];
        double penetration;
        const double torque =
            rj__element(m, s, m->qj[j], old_joints + at, new_joints + at, f->old_flags[m->qj[j]],
                        &f->new_flags[m->qj[j]], qd[j], t, f->new_scalars, &penetration, &spring);
        Q[j] = torque - bias[j];
    }
    if (m->nloop)
        rj__rig_loop_torques(m, s, f, r, &spring);
    /* cable loops: their torques on both joints, from q^n and the rates the element read */
    for (j = 0; j < m->ncp; j++) {
        const rj_coupling_def *c = &m->cp[j];
        const size_t at_a = (size_t) RJ__JD_COUNT * c->joint_a;
        const size_t at_b = (size_t) RJ__JD_COUNT * c->joint_b;
        const double rate_a = rj__rig_joint_rate(m, c->joint_a, qd, r->tmp);
        const double rate_b = rj__rig_joint_rate(m, c->joint_b, qd, r->tmp);
        double elastic, damp, on_b;
        rj__coupling_torques(m, c, old_joints[at_a + RJ__JD_THETA],
                             old_joints[at_b + RJ__JD_THETA], rate_a, rate_b, &elastic, &damp,
                             &spring);
        on_b = rj__coupling_record(c, elastic, damp, new_joints + at_a, new_joints + at_b);
        rj__rig_joint_force(m, c->joint_b, on_b, Q, r->tmp);
        rj__rig_joint_force(m, c->joint_a, -(c->ratio * on_b), Q, r->tmp);
    }
    /* the caller's torques, the loads and the caller's node forces: generalised forces on
       the joints, kept in the new frame for their work (rj__step_rigid checked them) */
    if (s->inputs || m->nload || s->node_inputs) {
        for (j = 0; j < m->nj; j++)
            new_joints[(size_t) RJ__JD_COUNT * j + RJ__JD_INPUT] =
                s->inputs ? s->input_torque[j] : 0.0;
        rj__rig_loads(m, s, r, t, new_joints);
        for (j = 0; j < n; j++)
            Q[j] += new_joints[(size_t) RJ__JD_COUNT * m->qj[j] + RJ__JD_INPUT];
        for (j = 0; j < m->nj && m->nloop; j++)
            if (m->jq[j] < 0)
                rj__rig_loop_force(m, j, new_joints[(size_t) RJ__JD_COUNT * j + RJ__JD_INPUT],
                                   Q, r->tmp);
    }
    if (m->has_gravity)
        rj__rig_gravity(m, r, Q, e);
    /* springs and tables at q^n, from the element */
    f->new_scalars[RJ__FS_SPRING] = spring;
    e->spring = spring;
    rj__rig_solve(m, r, r->Q, r->qdd);
}

/* Friction at the joints that close loops, as at the tree's: the loop's rate g . q' and
   its give g . M^-1 g (the column M^-1 g into r->Y's first n, spent before the rows). */
static void rj__rig_loop_friction(const rj_model *m, const rj__frames *f, rj__rig *r)
{
    const int n = m->nq;
    double *g = r->tmp, *y = r->Y;
    int j, k;
    for (j = 0; j < m->nj; j++) {
        const double tf = m->jdef[j].friction;
        double rate = 0, give = 0, tau;
        if (m->jq[j] >= 0 || !(tf > 0))
            continue;
        rj__rig_loop_gradient(m, j, g);
        rj__chol_solve(n, r->L, g, y);
        for (k = 0; k < n; k++) {
            rate += g[k] * (r->qd[k] + f->kick * r->qdd[k]);
            give += g[k] * y[k];
        }
        tau = rj__friction(rate, f->kick * give, tf);
        for (k = 0; k < n; k++)
            r->qdd[k] += y[k] * tau;
        RJ__FJ(m, f->next, j)[RJ__JD_TQ0 + RJ_TORQUE_FRICTION] = tau;
    }
}

/* Rigid step, stage 3: friction, joint by joint, each with its column M^-1 e_j, which
   W keeps (at m->wcol) for the impulses of a joint that can latch; another's is made in
   r->tmp and spent here (a column reads the factor alone: made before or after the
   joints before it, it is the same). */
static RJ__FORCE_INLINE void rj__rig_stage_friction(const rj_model *m, const rj__frames *f,
                                                    rj__rig *r)
{
    const int n = m->nq;
    const double *RJ__RESTRICT qd = r->qd;
    double *RJ__RESTRICT qdd = r->qdd, *W = r->W;
    int j, k;
    for (j = 0; j < n; j++) {
        const double tf = m->jdef[m->qj[j]].friction;
        double tau, *w;
        if (!(tf > 0))
            continue;
        w = m->wcol[j] >= 0 ? W + (size_t) m->wcol[j] * n : r->tmp;
        rj__rig_unit(m, r, j, w);
        tau = rj__friction(qd[j] + f->kick * qdd[j], f->kick * w[j], tf);
        for (k = 0; k < n; k++)
            qdd[k] += w[k] * tau;
        RJ__FJ(m, f->next, m->qj[j])[RJ__JD_TQ0 + RJ_TORQUE_FRICTION] = tau;
    }
    if (m->nloop)
        rj__rig_loop_friction(m, f, r);
}

/* Rigid step, stage 5a: velocity-level methods, joint by joint: an impulse along q_j to e
   times the reversed rate (plastic while locked or for forced displacement). r->h keeps the
   rates before the jumps. */
static RJ__FORCE_INLINE void rj__rig_single_impulses(const rj_model *m, const rj__frames *f,
                                                     rj__rig *r, rj__rig_jumps *jumps)
{
    const int n = m->nq;
    const double *RJ__RESTRICT q = r->q;
    double *RJ__RESTRICT qdp = r->qdp, *RJ__RESTRICT rates_before = r->h, *W = r->W;
    int *ni = f->new_flags;
    int j, k;
    for (j = 0; j < n; j++) {
        const int jj = m->qj[j];
        const rj_joint_def *d = &m->jdef[jj];
        double e, lam, *w;
        if (!(d->method == RJ_METHOD_MOMENTUM || d->method == RJ_METHOD_FORCED))
            continue;
        /* re-contact within the step, as for flexible links */
        if (ni[jj] == RJ_FREE && q[j] <= m->jnt[jj].rev && qdp[j] < 0)
            ni[jj] = RJ_AT_REVERSE;
        if (ni[jj] == RJ_FREE && q[j] >= m->jnt[jj].fwd && qdp[j] > 0)
            ni[jj] = RJ_AT_FORWARD;
        if (ni[jj] == RJ_FREE || !rj__into_limit(ni[jj], qdp[j]))
            continue;
        e = (d->method == RJ_METHOD_MOMENTUM && ni[jj] != RJ_LOCKED) ? d->restitution : 0.0;
        if (!jumps->count)
            for (k = 0; k < n; k++)
                rates_before[k] = qdp[k];
        jumps->count++;
        jumps->last = j;
        if (ni[jj] != f->old_flags[jj] || e > 0)
            jumps->impact = 1;
        /* stage 3 made the column of a joint with friction */
        w = W + (size_t) m->wcol[j] * n;
        if (!(d->friction > 0))
            rj__rig_unit(m, r, j, w);
        lam = (-e * qdp[j] - qdp[j]) / w[j];
        for (k = 0; k < n; k++)
            qdp[k] += w[k] * lam;
    }
}

/* Rigid step, stage 5b: the jumps' loss in the kinetic energy's form: 1/2 q'^{n-1/2} M
   (q'_before - q'_after) now, 1/2 q'_after M (q'_before - q'_after) with the next step
   (pending); the generalised impulse along q_j is the latch's angular impulse on body 2. */
static RJ__FORCE_INLINE void rj__rig_jump_loss(const rj_model *m, const rj__frames *f,
                                               rj__rig *r, rj__sums *e)
{
    const int n = m->nq, first = f->first;
    const double *RJ__RESTRICT qd = r->qd, *RJ__RESTRICT qdp = r->qdp;
    const double *RJ__RESTRICT rates_before = r->h;
    double *jump = r->ab + RJ__AB_COUNT * (size_t) n, *m_jump = jump + n;
    double *new_joints = RJ__FJ(m, f->next, 0);
    double lost_limit = e->lost_limit, pending = e->pending;
    int j;
    /* M (q'_before - q'_after): the generalised impulses */
    for (j = 0; j < n; j++)
        jump[j] = rates_before[j] - qdp[j];
    rj__rig_mul(m, r, jump, m_jump);
    for (j = 0; j < n; j++) {
        const rj__joint *J = &m->jnt[m->qj[j]];
        double *record = new_joints + (size_t) RJ__JD_COUNT * m->qj[j];
        /* an exact coupling's or a loop's share of the joint's impulse (its work is the
           limits') */
        const double coupled = m->nexact || m->nloop ? r->x[j] : 0.0;
        /* the first step's q'^{-1/2} is 2 q'(0) less the rates before any impulse */
        const double back = first ? 2 * qd[j] - rates_before[j] : qd[j];
        double sum = m_jump[j];
        /* a prescribed loop joint's share is its drive's work, not a latch's */
        if (m->nloop) {
            e->drive += 0.5 * back * r->xd[j];
            e->drive_pending += 0.5 * qdp[j] * r->xd[j];
            sum += r->xd[j];
        }
        /* a prescribed joint's impulse, less a coupling's, is its drive's: torque and work */
        if (rj__prescribed(J)) {
            const double driven = sum + coupled;
            e->drive -= 0.5 * back * driven;
            e->drive_pending -= 0.5 * qdp[j] * driven;
            record[RJ__JD_TQ0 + RJ_TORQUE_DRIVE] = -driven / f->kick;
            sum = -coupled;
        }
        lost_limit += 0.5 * back * sum;
        pending += 0.5 * qdp[j] * sum;
        /* the latches' impulse: less an exact coupling's, reported as a torque */
        if (!rj__prescribed(J))
            record[RJ__JD_IMPULSE] = -sum - coupled;
    }
    e->lost_limit = lost_limit;
    e->pending = pending;
}

/* Rigid step, stages 4 and 5: rates q'^{n+1/2}, then the velocity-level limit methods.
   Without an impact the jumps only keep locked joints and resting contacts at rest, and
   (q'^{n+1/2} - q'^{n-1/2}) / kick is the constrained acceleration: the next step's
   centripetal terms predict q'^{n+1} from it, not from the unconstrained one, which turns a
   locked joint at up to dt / 2 times its reaction over its inertia. */
static RJ__FORCE_INLINE void rj__rig_stage_rates(const rj_model *m, const rj_state *s,
                                                 const rj__frames *f, rj__rig *r, rj__sums *e)
{
    const int n = m->nq;
    const double kick = f->kick;
    const double *RJ__RESTRICT qd = r->qd;
    double *RJ__RESTRICT qdp = r->qdp, *RJ__RESTRICT qdd = r->qdd;
    rj__rig_jumps jumps;
    int j;
    for (j = 0; j < n; j++)
        qdp[j] = qd[j] + kick * qdd[j];
    /* the first step's kinetic energy reads the rates before any impulse (Q is spent) */
    if (f->first)
        for (j = 0; j < n; j++)
            r->Q[j] = qdp[j];
    jumps.count = 0;
    jumps.last = -1;
    jumps.impact = 0;
    rj__rig_single_impulses(m, f, r, &jumps);
    if (!jumps.count && !m->npres && !m->nexact && !m->nloop)
        return;
    if (!jumps.count)
        for (j = 0; j < n; j++)
            r->h[j] = qdp[j];
    rj__rig_rows(m, s, f, r, &jumps);
    if (!jumps.impact)
        for (j = 0; j < n; j++)
            qdd[j] = (qdp[j] - qd[j]) / kick;
    rj__rig_jump_loss(m, f, r, e);
}

/* Forced displacement at the joints that close loops, on positions: a loop joint past its
   limit, or off its lock angle, goes back to it with the projection (dq, rows at dt = 1),
   as a tree joint's angle is put back; its rate is the plastic row's. q: the angles at
   n + 1; g: nq doubles of scratch. */
static void rj__rig_loop_forced(const rj_model *m, const rj__frames *f, const double *q,
                                double *g, rj__rows *R)
{
    int j, k;
    for (j = 0; j < m->nj; j++) {
        const int flag = f->new_flags[j];
        const rj__joint *J = &m->jnt[j];
        double theta = m->jdef[j].angle0, back = 0;
        rj__row *row;
        if (m->jq[j] >= 0 || m->jdef[j].method != RJ_METHOD_FORCED || flag == RJ_FREE)
            continue;
        rj__rig_loop_gradient(m, j, g);
        for (k = 0; k < m->nq; k++)
            theta += g[k] * (q[k] - m->jdef[m->qj[k]].angle0);
        if (flag == RJ_LOCKED)
            back = RJ__FJ(m, f->next, j)[RJ__JD_LOCK] - theta;
        else if (flag == RJ_AT_FORWARD && theta > J->fwd)
            back = J->fwd - theta;
        else if (flag == RJ_AT_REVERSE && theta < J->rev)
            back = J->rev - theta;
        else
            continue;
        row = rj__row_open(R, RJ__ROW_LOCK, -1 - j, back, -HUGE_VAL, HUGE_VAL);
        rj__rig_joint_terms(m, R, row, j, 1.0, g);
    }
}

/* The loops closed at n + 1: the coordinates' angles moved by the least (in M's metric)
   that puts every loop joint's pins together, dq = M^-1 J^T (J M^-1 J^T)^-1 (-gap) (the
   loops' rows on positions, two Newton passes), so that they do not drift apart over a
   long run. */
static void rj__rig_loops_project(const rj_model *m, const rj_state *s, const rj__frames *f,
                                  rj__rig *r)
{
    /* r->h (the bias, spent by now) takes the step dq; r->tmp's second half q */
    double *new_joints = RJ__FJ(m, f->next, 0), *q = r->tmp + m->nq, *dq = r->h;
    rj__rows R;
    rj__dense D;
    int pass, k;
    R.row = s->rows;
    R.term = s->terms;
    rj__rig_dense(m, r, &D);
    D.held = -1;
    for (pass = 0; pass < 2; pass++) {
        for (k = 0; k < m->nq; k++) {
            q[k] = new_joints[(size_t) RJ__JD_COUNT * m->qj[k] + RJ__JD_THETA];
            dq[k] = 0;
        }
        rj__rig_kin(m, r, q, NULL, r->qdp);
        R.count = R.terms = 0;
        rj__rig_loop_rows(m, r, 1.0, &R);
        rj__rig_loop_forced(m, f, q, r->tmp, &R);
        rj__rows_solve_dense(&R, &D, dq);
        for (k = 0; k < m->nq; k++)
            new_joints[(size_t) RJ__JD_COUNT * m->qj[k] + RJ__JD_THETA] += dq[k];
    }
}

/* Rigid step, stage 6b, the joints that close loops: the loops closed at n + 1
   (rj__rig_loops_project), then each loop joint's angle and rate from the coordinates
   (angle0 + g . (q - q(0)), g . q'), and its element's work as any joint's; r->qdp
   keeps q'^{n+1/2}. */
static void rj__rig_loops_close(const rj_model *m, const rj_state *s, const rj__frames *f,
                                const rj__rig *r, int applied, rj__sums *e,
                                double *lost_damping, double *lost_friction, double *lost_limit)
{
    const double *old_joints = RJ__FJ(m, f->old, 0);
    double *new_joints = RJ__FJ(m, f->next, 0), *g = r->tmp;
    rj__rig scratch = *r; /* the same arrays: the projection's kinematics write them */
    int j, k;
    rj__rig_loops_project(m, s, f, &scratch);
    for (j = 0; j < m->nj; j++) {
        const double *old_joint = old_joints + (size_t) RJ__JD_COUNT * j;
        double *new_joint = new_joints + (size_t) RJ__JD_COUNT * j;
        double turn = 0, rate = 0;
        if (m->jq[j] >= 0)
            continue;
        rj__rig_loop_gradient(m, j, g);
        for (k = 0; k < m->nq; k++) {
            const int jk = m->qj[k];
            turn += g[k] * (new_joints[(size_t) RJ__JD_COUNT * jk + RJ__JD_THETA] -
                            m->jdef[jk].angle0);
            rate += g[k] * r->qdp[k];
        }
        new_joint[RJ__JD_THETA] = m->jdef[j].angle0 + turn;
        new_joint[RJ__JD_RATE] = rate;
        new_joint[RJ__JD_QDD] = 0;
        rj__element_work(old_joint, new_joint, old_joint[RJ__JD_RATE], f->dt, lost_damping,
                         lost_friction, lost_limit);
        if (applied)
            e->work += rj__input_work(old_joint, new_joint, old_joint[RJ__JD_RATE], f->dt);
        /* a prescribed loop joint's work is its row's (rj__rig_jump_loss) */
        if (m->jnt[j].act && !rj__prescribed(&m->jnt[j]))
            e->drive += rj__drive_work(old_joint, new_joint, old_joint[RJ__JD_RATE], f->dt);
    }
}

/* Rigid step, stage 6: angles q^{n+1}, forced displacement back to the limit, and the
   work of the joint torques. */
static RJ__FORCE_INLINE rj_result rj__rig_stage_angles(const rj_model *m, rj_state *s,
                                                       const rj__frames *f, const rj__rig *r,
                                                       rj__sums *e)
{
    const double *RJ__RESTRICT q = r->q, *RJ__RESTRICT qdp = r->qdp;
    const double *RJ__RESTRICT qd = r->qd, *RJ__RESTRICT qdd = r->qdd;
    const double *old_joints = RJ__FJ(m, f->old, 0);
    double *new_joints = RJ__FJ(m, f->next, 0);
    const double dt = f->dt;
    const int n = m->nq;
    double lost_damping = e->lost_damping;
    double lost_friction = e->lost_friction;
    double lost_limit = e->lost_limit;
    const int *ni = f->new_flags;
    const int applied = s->inputs || m->nload || s->node_inputs; /* RJ__JD_INPUT written */
    int j;
    for (j = 0; j < n; j++) {
        const int jj = m->qj[j];
        const rj_joint_def *d = &m->jdef[jj];
        const double *old_joint = old_joints + (size_t) RJ__JD_COUNT * jj;
        double *new_joint = new_joints + (size_t) RJ__JD_COUNT * jj;
        double qn = q[j] + dt * qdp[j];
        if (d->method == RJ_METHOD_FORCED && ni[jj] != RJ_FREE) {
            const rj__joint *J = &m->jnt[jj];
            if (ni[jj] == RJ_AT_FORWARD && qn > J->fwd)
                qn = J->fwd;
            else if (ni[jj] == RJ_AT_REVERSE && qn < J->rev)
                qn = J->rev;
            else if (ni[jj] == RJ_LOCKED)
                qn = new_joint[RJ__JD_LOCK];
        }
        if (!(fabs(qn - q[j]) <= 0.5 * RJ__PI))
            return rj__stop(m, s, RJ_ERR_TUNNEL,
                            "t = %.9g s: joint %d turned %.4g rad in one step (more than a quarter "
                            "revolution, pi/2 rad): the step %g s is far too large for its speed",
                            f->t, jj, qn - q[j], dt);
        new_joint[RJ__JD_THETA] = qn;
        new_joint[RJ__JD_RATE] = qdp[j];
        new_joint[RJ__JD_QDD] = qdd[j];
        rj__element_work(old_joint, new_joint, qd[j], dt, &lost_damping, &lost_friction,
                         &lost_limit);
        if (applied)
            e->work += rj__input_work(old_joint, new_joint, qd[j], dt);
        if (m->jnt[jj].act && !rj__prescribed(&m->jnt[jj]))
            e->drive += rj__drive_work(old_joint, new_joint, qd[j], dt);
    }
    if (m->nloop)
        rj__rig_loops_close(m, s, f, r, applied, e, &lost_damping, &lost_friction, &lost_limit);
    e->lost_damping = lost_damping;
    e->lost_friction = lost_friction;
    e->lost_limit = lost_limit;
    return RJ_OK;
}

/* The caller's node forces, every one a number the step can use (rj__node_input_ok). */
static int rj__rig_node_inputs_ok(const rj_model *m, rj_state *s)
{
    int i;
    for (i = 0; i < m->nn; i++)
        if (!rj__node_input_ok(m, s, i))
            return 0;
    return 1;
}

/* Rigid step, stage 7: the losses and work (every step); on the steps that take the energy
   accounts (f->en, as for flexible links: solver.energy_every) the kinetic energy
   1/2 q'^{n-1/2} M q'^{n+1/2} (q'^{-1/2} = 2 q'(0) - q'^{1/2}) and the energy tests;
   commit (nodes are computed when queried: rj__rig_pose). */
static RJ__FORCE_INLINE rj_result rj__rig_stage_accounts(const rj_model *m, rj_state *s,
                                                         const rj__frames *f, rj__rig *r,
                                                         rj__sums *e)
{
    const int n = m->nq, first = f->first;
    const double *RJ__RESTRICT qd = r->qd, *RJ__RESTRICT qdp = r->qdp;
    double *m_qdp = r->ab + RJ__AB_COUNT * (size_t) n;
    double *new_scalars = f->new_scalars;
    double ke = 0;
    rj_result res;
    int j;
    new_scalars[RJ__FS_LDAMP] = e->lost_damping;
    new_scalars[RJ__FS_LFRIC] = e->lost_friction;
    new_scalars[RJ__FS_LLIM] = e->lost_limit;
    new_scalars[RJ__FS_PEND] = e->pending;
    new_scalars[RJ__FS_WORK] = e->work;
    new_scalars[RJ__FS_DRIVE] = e->drive;
    new_scalars[RJ__FS_DPEND] = e->drive_pending;
    if (m->nact)
        rj__drive_flow(f->old_scalars, new_scalars, e);
    if (!f->en) {
        s->cur = 1 - s->cur;
        s->steps++;
        return RJ_OK;
    }
    rj__rig_mul(m, r, qdp, m_qdp);
    for (j = 0; j < n; j++) {
        const double sum = m_qdp[j];
        /* the first step's q'^{-1/2}: 2 q'(0) less the rates before the step's impulses
           (kept in Q by rj__rig_stage_rates), which an impulse does not move */
        ke += 0.5 * (first ? 2 * qd[j] - r->Q[j] : qd[j]) * sum;
    }
    e->kinetic = ke;
    new_scalars[RJ__FS_KE] = ke;
    if (m->has_gravity)
        rj__gravity_flow(f->old_scalars, new_scalars, e);
    new_scalars[RJ__FS_GRAV] = e->gravity;
    if (f->first)
        rj__first_accounts(new_scalars, e, ke + e->spring + e->gravity);
    res = rj__energy_check(m, s, NULL, f->t, e, f->old_scalars[RJ__FS_SPRING],
                           new_scalars[RJ__FS_E0]);
    if (res != RJ_OK)
        return res;
    s->cur = 1 - s->cur;
    s->steps++;
    return RJ_OK;
}

/* One step of a rigid-link scene: central differences in joint coordinates, stage by
   stage as for flexible links (rj__step_run). The work that does not wait for the new
   rates (spring energy, frame scalars) comes early, so that the end of a step, between the
   new angles and the next step's kinematics, stays short. */
static rj_result rj__step_rigid(const rj_model *m, rj_state *s, int want_energy)
{
    rj__frames f;
    rj__sums e;
    rj__rig r;
    rj_result res;
    rj__frames_open(m, s, want_energy, 0, &f);
    rj__sums_open(f.old_scalars, &e);
    rj__rig_map(m, s->rsc, &r, 1);
    if (s->inputs && !rj__inputs_ok(m, s))
        return RJ_ERR_INVALID;
    if (s->node_inputs && !rj__rig_node_inputs_ok(m, s))
        return RJ_ERR_INVALID;
    res = rj__rig_stage_kinematics(m, s, &f, &r);
    if (res != RJ_OK)
        return res;
    rj__rig_stage_torques(m, s, &f, &r, &e);
    rj__rig_stage_friction(m, &f, &r);
    rj__rig_stage_rates(m, s, &f, &r, &e);
    res = rj__rig_stage_angles(m, s, &f, &r, &e);
    if (res != RJ_OK)
        return res;
    return rj__rig_stage_accounts(m, s, &f, &r, &e);
}

/* ------------------------------------------------------------------ stepping and running */
/* The step. In place (rj_model.ip: solver.in_place, never with inextensible links; after
   the first step) it writes the nodes and elements where it reads them, which halves what a
   large model moves through the caches each step; the other frame then holds a copy of the
   state taken at most RJ__SNAP steps before. A step that fails puts that copy back and takes the steps since
   again, with the same energy requests (s->want) and the same inputs: the same bits, so a
   failed step leaves the state as it was, as the double-buffered step does. */
#define RJ__SNAP 64

/* In place: whether the caller's inputs are those every step since the copy took, so that
   a replay takes them again. A change steps double-buffered once; the copy is then taken
   anew with the new inputs. Every caller input the in-place step reads belongs here (the
   node forces always step double-buffered). */
static int rj__inputs_since_snap(const rj_model *m, const rj_state *s)
{
    if (s->inputs != s->snap_inputs)
        return 0;
    return !s->inputs ||
           memcmp(s->snap_torque, s->input_torque, sizeof(double) * (size_t) m->nj) == 0;
}
static rj_result rj__step_plain(const rj_model *m, rj_state *s, int want_energy)
{
    return rj__step_run(m, s, want_energy, 0, 0);
}
static rj_result rj__step_held(const rj_model *m, rj_state *s, int want_energy)
{
    return rj__step_run(m, s, want_energy, 0, 1);
}
static rj_result rj__step_ip(const rj_model *m, rj_state *s, int want_energy)
{
    return rj__step_run(m, s, want_energy, 1, 0);
}
/* Double-buffered: scenes with constraints on positions (inextensible links, pins
   between rigid bodies, so every joint between two bodies) take the step compiled with
   their parts. */
static rj_result rj__step_dbl(const rj_model *m, rj_state *s, int want_energy)
{
    if (m->project)
        return rj__step_held(m, s, want_energy);
    return rj__step_plain(m, s, want_energy);
}
static RJ__NOINLINE void rj__track_peaks(const rj_model *m, rj_state *s);

/* After a double-buffered step (result r): the other frame holds the state a step
   before, and the peaks are tracked where asked, on the steps that took the accounts
   (their time is the frame's before). */
static RJ__FORCE_INLINE rj_result rj__step_after(const rj_model *m, rj_state *s, rj_result r)
{
    s->at_n = r == RJ_OK ? RJ__AT_N_FRAME : RJ__AT_N_NONE;
    if (s->peaks_on && r == RJ_OK && !s->settling &&
        s->fd[s->cur][RJ__FS_ETIME] == s->fd[1 - s->cur][RJ__FS_TIME])
        rj__track_peaks(m, s);
    return r;
}

/* After an in-place step with peaks on: they are tracked as after a double-buffered
   step, on a step that took the accounts (at its start, a step before the time now; the
   ones before it a step earlier still). */
static RJ__NOINLINE void rj__step_ip_peaks(const rj_model *m, rj_state *s)
{
    const double *now = s->fd[s->cur];
    if (!s->settling && now[RJ__FS_ETIME] > now[RJ__FS_TIME] - 1.5 * m->dt)
        rj__track_peaks(m, s);
}

static rj_result rj__step(const rj_model *m, rj_state *s, int want_energy)
{
    rj_result r;
    long n, k;
    char err[sizeof s->err], warn[sizeof s->warn];
    const double t = rj_state_time(s);
    /* a step too small for the time reached would leave time where it is: rj_run would
       never end */
    if (!(t + m->dt > t))
        return rj__stop(m, s, RJ_ERR_INVALID,
                        "t = %.17g s: the step %g s no longer advances time (it is below the "
                        "time's resolution, %g s)",
                        t, m->dt, t * DBL_EPSILON);
    if (m->rigid)
        return rj__step_after(m, s, rj__step_rigid(m, s, want_energy));
    /* the caller's torques checked before anything moves */
    if (s->inputs && !rj__inputs_ok(m, s))
        return RJ_ERR_INVALID;
    /* the caller's node forces kick nodes from their old velocities: double-buffered; so
       is a step whose inputs differ from those since the in-place copy */
    if (!m->ip || s->steps == 0 || s->node_inputs ||
        (s->snap >= 0 && !rj__inputs_since_snap(m, s))) {
        s->snap = -1;
        r = rj__step_dbl(m, s, want_energy);
        /* what a step applied is the next one's forces at n - 1 (their work) */
        if (s->node_inputs && r == RJ_OK)
            memcpy(s->node_applied, s->input_node, 3 * sizeof(double) * (size_t) m->nn);
        return rj__step_after(m, s, r);
    }
    /* in place, the other frame is a copy from some steps before; the third keeps the
       values at n of the nodes the loads at t^n read (m->dnode), and s->fx, fy their
       forces of the step */
    s->at_n = RJ__AT_N_KEPT;
    if (s->snap < 0 || s->steps - s->snap >= RJ__SNAP) {
        memcpy(s->fd[1 - s->cur], s->fd[s->cur], sizeof(double) * m->frame_doubles);
        memcpy(s->fi[1 - s->cur], s->fi[s->cur], sizeof(int) * (m->frame_ints + 1));
        s->snap = s->steps;
        s->want = 0;
        s->snap_inputs = s->inputs;
        memcpy(s->snap_torque, s->input_torque, sizeof(double) * (size_t) m->nj);
    }
    if (want_energy)
        s->want |= (unsigned long long) 1 << (s->steps - s->snap);
    r = rj__step_ip(m, s, want_energy);
    if (r == RJ_OK && s->peaks_on)
        rj__step_ip_peaks(m, s);
    if (r == RJ_OK)
        return r;
    s->at_n = RJ__AT_N_NONE;
    memcpy(err, s->err, sizeof err);
    memcpy(warn, s->warn, sizeof warn);
    n = s->steps;
    memcpy(s->fd[s->cur], s->fd[1 - s->cur], sizeof(double) * m->frame_doubles);
    memcpy(s->fi[s->cur], s->fi[1 - s->cur], sizeof(int) * (m->frame_ints + 1));
    s->steps = s->snap;
    for (k = s->snap; k < n; k++)
        if (rj__step_ip(m, s, (int) ((s->want >> (k - s->snap)) & 1)) != RJ_OK)
            break;
    memcpy(s->err, err, sizeof err);
    memcpy(s->warn, warn, sizeof warn);
    return r;
}

RJDEF rj_result rj_step(const rj_model *m, rj_state *s)
{
    return rj__step(m, s, 0);
}

/* rj_run and rj_run_watched: samples at the steps nearest to k sample_dt from time 0, or
   from the run's start (from_start), every step when sample_dt is 0; each_step (or NULL)
   after every step. */
static rj_result rj__run(const rj_model *m, rj_state *s, double t_end, double sample_dt,
                         int from_start, rj_sample_fn sample, rj_sample_fn each_step,
                         void *user)
{
    double next;
    rj_result r;
    if (!m || !s)
        return RJ_ERR_INVALID;
    if (!(t_end == t_end) || !(sample_dt >= 0) || !rj__finite(sample_dt))
        return RJ_ERR_INVALID;
    next = sample_dt > 0 && !from_start ? sample_dt * floor(rj_state_time(s) / sample_dt + 0.5)
                                        : rj_state_time(s);
    if (sample && rj_state_time(s) >= next - 0.5 * m->dt) {
        if (sample(m, s, user))
            return RJ_OK;
        next += sample_dt;
    }
    while (rj_state_time(s) < t_end - 0.5 * m->dt) {
        /* the energy accounts at every sample and at the end (solver.energy_every) */
        const double t1 = rj_state_time(s) + m->dt;
        r = rj__step(m, s, t1 >= t_end - 0.5 * m->dt || (sample && t1 >= next - 0.5 * m->dt));
        if (r != RJ_OK)
            return r;
        if (each_step && each_step(m, s, user))
            return RJ_OK;
        if (sample && rj_state_time(s) >= next - 0.5 * m->dt) {
            if (sample(m, s, user))
                return RJ_OK;
            if (sample_dt > 0)
                while (next <= rj_state_time(s) + 0.5 * m->dt)
                    next += sample_dt;
        }
    }
    return RJ_OK;
}

RJDEF rj_result rj_run(const rj_model *m, rj_state *s, double t_end, double sample_dt,
                       rj_sample_fn sample, void *user)
{
    return rj__run(m, s, t_end, sample_dt, 0, sample, NULL, user);
}

RJDEF rj_result rj_run_watched(const rj_model *m, rj_state *s, double t_end, double sample_dt,
                               rj_sample_fn sample, rj_sample_fn each_step, void *user)
{
    return rj__run(m, s, t_end, sample_dt, 1, sample, each_step, user);
}

/* ------------------------------------------------------------------ settling */
/* Every velocity of the current frame to zero: nodes, bodies, joint rates (and the rigid
   solver's predicted accelerations). The state then starts again from rest where it is:
   the next step is a first step (a half kick, the energy accounts from there), and the
   in-place copy is dropped, as it would replay steps from before the change. */
static void rj__zero_velocities(const rj_model *m, rj_state *s)
{
    double *f = s->fd[s->cur];
    int i;
    memset(RJ__FVX(m, f), 0, sizeof(double) * (size_t) m->nn);
    memset(RJ__FVY(m, f), 0, sizeof(double) * (size_t) m->nn);
    memset(RJ__FW(m, f), 0, sizeof(double) * (size_t) m->nn);
    for (i = 0; i < m->ncl; i++) {
        double *c = RJ__FCL(m, f, i);
        c[2] = c[3] = c[4] = 0;
    }
    for (i = 0; i < m->nj; i++) {
        double *jd = RJ__FJ(m, f, i);
        jd[RJ__JD_RATE] = 0;
        jd[RJ__JD_QDD] = 0;
    }
    s->snap = -1;
    s->steps = 0;
    s->at_n = RJ__AT_N_NONE;
    s->loop_force[2 * m->nj] = -1;
}

/* The settled state as a new start: step count, accounts and joint events from zero; time
   goes on from where the settling left it, so that a load's table reads on from the value
   it settled under. */
static void rj__restart(const rj_model *m, rj_state *s)
{
    double *f = s->fd[s->cur];
    double *sc = RJ__FS(m, f);
    const double warn = sc[RJ__FS_WARN], strain = sc[RJ__FS_STRAIN];
    const double spring = sc[RJ__FS_SPRING], gravity = sc[RJ__FS_GRAV];
    const double time = sc[RJ__FS_TIME];
    int j;
    rj__zero_velocities(m, s);
    /* a new start: the peaks too (their tracking stays as it was) */
    rj__peaks_clear(m, s);
    /* the potential energies of the last step stand until the first step takes them again */
    memset(sc, 0, sizeof(double) * RJ__FS_COUNT);
    sc[RJ__FS_TIME] = time;
    sc[RJ__FS_ETIME] = time;
    sc[RJ__FS_WARN] = warn;
    sc[RJ__FS_STRAIN] = strain;
    sc[RJ__FS_SPRING] = spring;
    sc[RJ__FS_GRAV] = gravity;
    sc[RJ__FS_E0] = strain + spring + gravity;
    for (j = 0; j < m->nj; j++) {
        double *jd = RJ__FJ(m, f, j);
        jd[RJ__JD_EVENT] = -1;
        jd[RJ__JD_RELEASE] = -1;
        jd[RJ__JD_OVERLAP] = -1;
        jd[RJ__JD_PEAKP] = 0;
        jd[RJ__JD_IMPULSE] = 0;
    }
}

/* The potential energy the settling has moved: strain and springs, and gravity's change. */
static double rj__settle_scale(const double *sc, double gravity_start)
{
    return fabs(sc[RJ__FS_STRAIN]) + fabs(sc[RJ__FS_SPRING]) +
           fabs(sc[RJ__FS_GRAV] - gravity_start) + 1e-300;
}

/* The energy of round-off: what a link stores when it is stretched by 64 ulps of its
   length, EA L (64 eps)^2, summed over the links. A kinetic energy below it cannot be
   told from rest, whatever the tolerance asks: it is the absolute floor of rj_settle's
   threshold (a 1 m aluminium link at rest shows peaks of 1e-21 J from round-off alone,
   against a floor of 1.4e-19 J; a 2000-element cantilever's first step from rest under
   gravity has 2e-15 J). */
static double rj__settle_floor(const rj_model *m)
{
    const double slip = 64.0 * DBL_EPSILON;
    double floor_energy = 0;
    int l;
    for (l = 0; l < m->nl; l++)
        floor_energy += m->link_EA[l] * m->ldef[l].length * slip * slip;
    return floor_energy;
}

/* The time from which every load is constant: its table's last point (it holds its last
   factor after it); 0 without tables. */
static double rj__loads_steady_time(const rj_model *m)
{
    double steady = 0;
    int k;
    for (k = 0; k < m->nload; k++) {
        const rj_load_def *d = &m->load[k];
        if (d->table_count > 0 && d->table_time[d->table_count - 1] > steady)
            steady = d->table_time[d->table_count - 1];
    }
    return steady;
}

/* What rj_settle carries from step to step. */
typedef struct rj__settle_run {
    double previous;     /* the kinetic energy of the step before, J */
    double last_peak;    /* the kinetic energy at the latest peak, J */
    double gravity;      /* gravity's potential at the start, J */
    double floor_energy; /* the threshold's absolute floor, J (rj__settle_floor) */
    double steady;       /* the time from which the loads are constant, s */
    long rise;           /* steps since the last restart from rest */
    long longest_rise;   /* the longest rise from rest to a peak seen so far */
    long quiet;          /* steps below the threshold since checking began (-1: not checking) */
} rj__settle_run;

/* One settling step's verdict on the kinetic energy ke against the threshold limit:
   1 settled; 0 go on; the velocities are zeroed at a peak. A peak below the threshold
   starts the check, and so does a kinetic energy that stays exactly where it was below it
   (nothing moves: a scene already at rest has no peak to show). */
static int rj__settle_judge(const rj_model *m, rj_state *s, rj__settle_run *q, double ke,
                            double limit)
{
    q->rise++;
    if (q->quiet >= 0) {
        /* checking: quiet for long enough means settled; a rise means not yet */
        if (ke > limit)
            q->quiet = -1;
        else if (++q->quiet >= q->longest_rise + q->longest_rise / 2)
            return 1;
    }
    /* rising, or the first step from rest (its kinetic energy, negative in the central
       difference's form, is no peak) */
    if (ke > q->previous || (ke == q->previous && ke > limit) || q->rise == 1) {
        q->previous = ke;
        return 0;
    }
    /* past a peak, or at rest */
    q->last_peak = q->previous;
    if (q->quiet < 0 && q->previous <= limit)
        q->quiet = 0;
    if (q->quiet < 0) {
        if (q->rise > q->longest_rise)
            q->longest_rise = q->rise;
        rj__zero_velocities(m, s);
        q->previous = 0;
        q->rise = 0;
    }
    return 0;
}

/* The settling's start: from rest, with the threshold's floor, the time from which the
   loads are constant, and gravity's potential to measure what it moves from. */
static void rj__settle_start(const rj_model *m, rj_state *s, rj__settle_run *q)
{
    q->previous = 0;
    q->last_peak = 0;
    q->gravity = RJ__FS(m, s->fd[s->cur])[RJ__FS_GRAV];
    q->floor_energy = rj__settle_floor(m);
    q->steady = rj__loads_steady_time(m);
    q->rise = 0;
    q->longest_rise = 1;
    q->quiet = -1;
    rj__zero_velocities(m, s);
}

/* The arguments rj_settle takes: tol in (0, 1), at least one step. Else RJ_ERR_INVALID
   with the argument named in rj_state_error. */
static rj_result rj__settle_args(const rj_model *m, rj_state *s, double tol, long max_steps)
{
    if (!(tol > 0 && tol < 1))
        return rj__stop(m, s, RJ_ERR_INVALID,
                        "rj_settle: tol = %g is invalid: it must be in (0, 1) (1e-12 is tight)",
                        tol);
    if (max_steps < 1)
        return rj__stop(m, s, RJ_ERR_INVALID,
                        "rj_settle: max_steps = %ld is invalid: it must be at least 1",
                        max_steps);
    return RJ_OK;
}

/* Kinetic damping: every velocity to zero at each peak of the kinetic energy. A peak below
   tol times the potential energy moved is not yet the end: from rest, a mode far slower
   than the others can take many steps to show, while the faster ones make small peaks
   first. So the state must then stay below it, without damping, for 1.5 times the longest
   rise from rest to a peak seen so far (that slow mode's quarter period, once it has
   shown). progress (when not NULL) is called every RJ__SETTLE_EVERY steps; a nonzero
   return stops the settling. The steps, from a start at rest (rj__settle_start). */
#define RJ__SETTLE_EVERY 4096
static rj_result rj__settle_steps(const rj_model *m, rj_state *s, rj__settle_run *q, double tol,
                                  long max_steps, rj_sample_fn progress, void *user)
{
    long k;
    for (k = 0; k < max_steps; k++) {
        const double *sc;
        double moved;
        const rj_result r = rj__step(m, s, 1);
        if (r != RJ_OK)
            return r;
        sc = RJ__FS(m, s->fd[s->cur]);
        moved = rj__settle_scale(sc, q->gravity);
        /* each restart from rest starts the accounts again, from an energy that shrinks as
           the state settles: the blow-up tests measure against what the settling moved */
        if (moved > s->settle_scale)
            s->settle_scale = moved;
        /* settled only under the loads that act from then on: past their tables */
        if (rj__settle_judge(m, s, q, sc[RJ__FS_KE], tol * moved + q->floor_energy) &&
            sc[RJ__FS_TIME] >= q->steady) {
            rj__restart(m, s);
            return RJ_OK;
        }
        if (progress && (k + 1) % RJ__SETTLE_EVERY == 0 && progress(m, s, user)) {
            rj__zero_velocities(m, s);
            return rj__stop(m, s, RJ_ERR_NOT_CONVERGED,
                            "rj_settle: stopped by the caller after %ld steps (t = %.9g s)",
                            k + 1, rj_state_time(s));
        }
    }
    rj__zero_velocities(m, s);
    return rj__stop(m, s, RJ_ERR_NOT_CONVERGED,
                    "rj_settle: not settled within %ld steps (t = %.9g s; the last kinetic "
                    "energy peak %.3g J; tol %g of the %.3g J of potential energy moved)",
                    max_steps, rj_state_time(s), q->last_peak, tol,
                    rj__settle_scale(RJ__FS(m, s->fd[s->cur]), q->gravity));
}

/* rj_settle with progress: the settling's scale for the blow-up tests holds while it
   steps, whatever ends it. */
RJDEF rj_result rj_settle_ex(const rj_model *m, rj_state *s, double tol, long max_steps,
                             rj_sample_fn progress, void *user)
{
    rj__settle_run q;
    rj_result r;
    if (!m || !s)
        return RJ_ERR_INVALID;
    r = rj__settle_args(m, s, tol, max_steps);
    if (r != RJ_OK)
        return r;
    s->err[0] = 0;
    rj__settle_start(m, s, &q);
    s->settling = 1;
    r = rj__settle_steps(m, s, &q, tol, max_steps, progress, user);
    s->settling = 0;
    s->settle_scale = 0;
    return r;
}

RJDEF rj_result rj_settle(const rj_model *m, rj_state *s, double tol, long max_steps)
{
    return rj_settle_ex(m, s, tol, max_steps, NULL, NULL);
}

/* ------------------------------------------------------------------ inputs and queries */
RJDEF double *rj_state_joint_torques(const rj_model *m, rj_state *s)
{
    RJ_ASSERT(m && s);
    (void) m;
    s->inputs = 1;
    return s->input_torque;
}

RJDEF double *rj_state_node_forces(const rj_model *m, rj_state *s)
{
    RJ_ASSERT(m && s);
    (void) m;
    s->node_inputs = 1;
    return s->input_node;
}

RJDEF const char *rj_state_error(const rj_state *s)
{
    return s->err;
}
RJDEF long rj_state_warning_count(const rj_state *s)
{
    return (long) s->fd[s->cur][RJ__FS_WARN];
}
RJDEF const char *rj_state_warning(const rj_state *s)
{
    return s->warn;
}

/* ------------------------------------------------------------------ queries */
RJDEF int rj_model_warning_count(const rj_model *m)
{
    return m->nwarn;
}
RJDEF const char *rj_model_warnings(const rj_model *m)
{
    return m->warnings;
}
RJDEF double rj_model_dt(const rj_model *m)
{
    return m->dt;
}
RJDEF double rj_model_dt_bound(const rj_model *m)
{
    return m->dt_bound;
}
RJDEF double rj_model_omega_max(const rj_model *m)
{
    return m->omega_max;
}
RJDEF int rj_model_link_count(const rj_model *m)
{
    return m->nl;
}
RJDEF int rj_model_joint_count(const rj_model *m)
{
    return m->nj;
}
RJDEF int rj_model_node_count(const rj_model *m)
{
    return m->nn;
}
RJDEF int rj_model_in_place(const rj_model *m)
{
    return m->ip;
}
RJDEF const rj_link_def *rj_model_link_def(const rj_model *m, int l)
{
    RJ_ASSERT(l >= 0 && l < m->nl);
    return &m->ldef[l];
}
RJDEF const rj_joint_def *rj_model_joint_def(const rj_model *m, int j)
{
    RJ_ASSERT(j >= 0 && j < m->nj);
    return &m->jdef[j];
}
RJDEF int rj_link_node_count(const rj_model *m, int l)
{
    RJ_ASSERT(l >= 0 && l < m->nl);
    return m->ldef[l].elements + 1;
}
RJDEF int rj_model_node_index(const rj_model *m, int l, int k)
{
    if (!m || l < 0 || l >= m->nl || k < -1 || k > m->ldef[l].elements)
        return -1;
    return m->link_first[l] + (k < 0 ? m->ldef[l].elements : k);
}
RJDEF int rj_model_load_count(const rj_model *m)
{
    return m->nload;
}
RJDEF const rj_load_def *rj_model_load_def(const rj_model *m, int k)
{
    RJ_ASSERT(k >= 0 && k < m->nload);
    return &m->load[k];
}
RJDEF const rj_actuator_def *rj_model_actuator_def(const rj_model *m, int k)
{
    RJ_ASSERT(k >= 0 && k < m->nact);
    return &m->act[k];
}
RJDEF int rj_model_coupling_count(const rj_model *m)
{
    return m->ncp;
}
RJDEF const rj_coupling_def *rj_model_coupling_def(const rj_model *m, int k)
{
    RJ_ASSERT(k >= 0 && k < m->ncp);
    return &m->cp[k];
}
RJDEF double rj_link_EA(const rj_model *m, int l)
{
    RJ_ASSERT(l >= 0 && l < m->nl);
    return m->link_EA[l];
}
RJDEF double rj_link_EI(const rj_model *m, int l)
{
    RJ_ASSERT(l >= 0 && l < m->nl);
    return m->link_EI[l];
}
RJDEF double rj_model_dt_eq28(const rj_model *m)
{
    return m->dt_eq28;
}
RJDEF size_t rj_model_work_size(const rj_model *m)
{
    return 6 * (size_t) m->nn + 4 * (size_t) m->ne;
}
RJDEF void rj_model_apply_stiffness(const rj_model *m, const double *u, double *out, double *work)
{
    rj__lz_scales(m, work);
    rj__lz_apply(m, work, u, out, work + 3 * (size_t) m->nn);
}

/* the smaller of the joint's two links by rho I l (ground is infinitely large) */
static double rj__eq31_rho_i_l(const rj_model *m, int j)
{
    const rj_joint_def *d = &m->jdef[j];
    double v2 = m->link_rho[d->body2] * m->link_I[d->body2] * m->link_l0[d->body2], v1;
    if (d->body1 < 0)
        return v2;
    v1 = m->link_rho[d->body1] * m->link_I[d->body1] * m->link_l0[d->body1];
    return v1 < v2 ? v1 : v2;
}
RJDEF double rj_joint_dt_eq29(const rj_model *m, int j, double K)
{
    const rj_joint_def *d;
    double t, c, t2;
    RJ_ASSERT(j >= 0 && j < m->nj);
    d = &m->jdef[j];
    c = sqrt(m->ldef[d->body2].E / m->ldef[d->body2].rho);
    t = m->link_l0[d->body2] / c;
    if (d->body1 >= 0) {
        double t1 = m->link_l0[d->body1] / sqrt(m->ldef[d->body1].E / m->ldef[d->body1].rho);
        if (t1 < t)
            t = t1;
    }
    if (!(K > 0))
        return t;
    t2 = sqrt(rj__eq31_rho_i_l(m, j) / K);
    return t2 < t ? t2 : t;
}
RJDEF double rj_joint_kmax_eq31(const rj_model *m, int j, double dt)
{
    RJ_ASSERT(j >= 0 && j < m->nj);
    return 0.81 * rj__eq31_rho_i_l(m, j) / (dt * dt);
}
RJDEF void rj_joint_inertias(const rj_model *m, int j, double *I1, double *I2)
{
    RJ_ASSERT(j >= 0 && j < m->nj);
    if (I1)
        *I1 = m->jnt[j].I1;
    if (I2)
        *I2 = m->jnt[j].I2;
}
RJDEF double rj_joint_stiffness(const rj_model *m, int j)
{
    RJ_ASSERT(j >= 0 && j < m->nj);
    return m->jnt[j].k_limit;
}

RJDEF double rj_state_time(const rj_state *s)
{
    return s->fd[s->cur][RJ__FS_TIME];
}

RJDEF long rj_state_steps(const rj_state *s)
{
    return s->steps;
}

/* Rigid scenes: the pose and motion of link l from the joint coordinates of a frame,
   walking up to the ground (used by the node queries; the step itself stores only q). */
static void rj__rig_pose(const rj_model *m, const double *f, int l, double *phi, double *rx,
                         double *ry, double *om, double *vx, double *vy)
{
    int j = m->rb_pjoint[l], p;
    double ph, x, y, o, ux, uy;
    if (j < 0) {
        const rj_link_def *d = &m->ldef[l];
        *phi = d->angle;
        *rx = d->x;
        *ry = d->y;
        *om = 0;
        *vx = 0;
        *vy = 0;
        return;
    }
    p = m->jdef[j].body1;
    if (p < 0) {
        ph = m->jdef[j].ground_angle;
        x = m->jdef[j].ground_x;
        y = m->jdef[j].ground_y;
        o = 0;
        ux = uy = 0;
    } else {
        double pp, px, py, po, pvx, pvy, c, sn;
        rj__rig_pose(m, f, p, &pp, &px, &py, &po, &pvx, &pvy);
        c = cos(pp);
        sn = sin(pp);
        x = px + m->jpin[j] * c;
        y = py + m->jpin[j] * sn;
        ux = pvx - po * m->jpin[j] * sn;
        uy = pvy + po * m->jpin[j] * c;
        ph = pp + m->jref[j];
        o = po;
    }
    *phi = ph + RJ__FJ(m, f, j)[RJ__JD_THETA];
    *om = o + RJ__FJ(m, f, j)[RJ__JD_RATE];
    /* a pin at node at: the root at -at l0 along the link */
    if (m->jnt[j].nJ != m->link_first[l]) {
        const double off = (m->jnt[j].nJ - m->link_first[l]) * m->link_l0[l];
        const double c = cos(*phi), sn = sin(*phi);
        x -= off * c;
        y -= off * sn;
        ux += *om * off * sn;
        uy -= *om * off * c;
    }
    *rx = x;
    *ry = y;
    *vx = ux;
    *vy = uy;
}
/* Rigid scenes: every hanging link's angle, rate, angular acceleration, root and the
   root's acceleration (7 per link in k), down the tree in joint order (parents first):
   O(nl). The angles from frame fq, the rates from frame fr's rates and accelerations
   (RJ__JD_RATE + ahead RJ__JD_QDD: the step's predicted rates at n when fr is the frame at
   n and ahead dt / 2), the accelerations from frame fa. Each hanging link's direction
   (cos, sin of its angle: 2 per link in dir) is taken once, for its children's pins and
   its centre (rj__rig_pin_forces). */
static void rj__rig_accels(const rj_model *m, const double *fq, const double *fr, double ahead,
                           const double *fa, double *k, double *dir)
{
    int q, l;
    /* a link no joint hangs (fixed, or a free root in joint coordinates) stays put; the
       joints below write all of a hanging link's record */
    for (l = 0; l < m->nl; l++) {
        double *kl = k + RJ__KA_N * (size_t) l;
        if (m->rb_pjoint[l] >= 0)
            continue;
        memset(kl, 0, sizeof(double) * RJ__KA_N);
        kl[RJ__KA_PHI] = m->ldef[l].angle;
        kl[RJ__KA_RX] = m->ldef[l].x;
        kl[RJ__KA_RY] = m->ldef[l].y;
    }
    for (q = 0; q < m->nq; q++) {
        const int j = m->jorder[q], l = m->jdef[j].body2, p = m->jdef[j].body1;
        const double *jq = RJ__FJ(m, fq, j), *jr = RJ__FJ(m, fr, j), *ja = RJ__FJ(m, fa, j);
        double *kl = k + RJ__KA_N * (size_t) l, pin[2], a_pin[2], e[2], ph, om, al, off;
        if (p < 0) {
            ph = m->jdef[j].ground_angle;
            om = al = 0;
            pin[0] = m->jdef[j].ground_x;
            pin[1] = m->jdef[j].ground_y;
            a_pin[0] = a_pin[1] = 0;
        } else {
            const double *kp = k + RJ__KA_N * (size_t) p;
            /* a hanging parent's direction came before (parents first); a fixed link's */
            const int hangs = m->rb_pjoint[p] >= 0;
            const double cp = hangs ? dir[2 * p] : cos(kp[RJ__KA_PHI]);
            const double sp = hangs ? dir[2 * p + 1] : sin(kp[RJ__KA_PHI]);
            const double d[2] = { m->jpin[j] * cp, m->jpin[j] * sp };
            ph = kp[RJ__KA_PHI] + m->jref[j];
            om = kp[RJ__KA_OM];
            al = kp[RJ__KA_AL];
            pin[0] = kp[RJ__KA_RX] + d[0];
            pin[1] = kp[RJ__KA_RY] + d[1];
            /* the pin on body 1: a_root + alpha perp(d) - omega^2 d */
            a_pin[0] = kp[RJ__KA_AX] - al * d[1] - om * om * d[0];
            a_pin[1] = kp[RJ__KA_AY] + al * d[0] - om * om * d[1];
        }
        ph += jq[RJ__JD_THETA];
        om += jr[RJ__JD_RATE] + ahead * jr[RJ__JD_QDD];
        al += ja[RJ__JD_QDD];
        /* the root sits off the pin by the pin node's distance along the link */
        off = (m->jnt[j].nJ - m->link_first[l]) * m->link_l0[l];
        e[0] = cos(ph);
        e[1] = sin(ph);
        dir[2 * l] = e[0];
        dir[2 * l + 1] = e[1];
        kl[RJ__KA_PHI] = ph;
        kl[RJ__KA_OM] = om;
        kl[RJ__KA_AL] = al;
        kl[RJ__KA_RX] = pin[0] - off * e[0];
        kl[RJ__KA_RY] = pin[1] - off * e[1];
        kl[RJ__KA_AX] = a_pin[0] + off * (al * e[1] + om * om * e[0]);
        kl[RJ__KA_AY] = a_pin[1] + off * (-al * e[0] + om * om * e[1]);
    }
}

/* The loop joints' pin forces (rj__rig_loop_forces) into forces, and as forces from
   outside the tree on their bodies into the subtrees' sums: F on body 2, -F on body 1. */
static void rj__rig_loop_pins(const rj_model *m, const rj_state *s, double *sum, double *forces)
{
    int j, axis;
    for (j = 0; j < m->nj && m->nloop; j++) {
        const int b1 = m->jdef[j].body1, b2 = m->jdef[j].body2;
        if (m->jq[j] >= 0)
            continue;
        for (axis = 0; axis < 2; axis++) {
            const double F = s->loop_force[2 * j + axis];
            forces[2 * j + axis] = F;
            sum[2 * b2 + axis] -= F;
            if (b1 >= 0)
                sum[2 * b1 + axis] += F;
        }
    }
}

/* Rigid scenes: every joint's pin force (2 per joint in forces), the force body 1 exerts
   on body 2: the sum over the links below of m (a_c - g) less the loads, the caller's
   forces and the loops' pin forces on them (Newton's second law for the subtree; the rates
   at n + 1/2, the step's accelerations), gathered up the tree in reverse joint order; a
   loop joint's own from its rows (rj__rig_loop_forces). work: 9 nl doubles. */
static void rj__rig_pin_forces(const rj_model *m, const rj_state *s, double *work,
                               double *forces)
{
    const double *f = s->fd[s->cur];
    double *k = work, *sum = work + RJ__KA_N * (size_t) m->nl;
    int l, q, i;
    /* with loops, the step's configuration and predicted rates at n, where the rows'
       impulses act; else the new frame's (the forces at n + 1 of a tree) */
    if (m->nloop) {
        const double *at_n = s->fd[1 - s->cur];
        rj__rig_accels(m, at_n, at_n, s->steps == 1 ? 0.0 : 0.5 * m->dt, f, k, sum);
    } else
        rj__rig_accels(m, f, f, 0.0, f, k, sum);
    for (l = 0; l < m->nl; l++) {
        const double *kl = k + RJ__KA_N * (size_t) l, dc = m->rb_dcm[l];
        double e[2];
        if (m->rb_pjoint[l] < 0) {
            sum[2 * l] = sum[2 * l + 1] = 0;
            continue;
        }
        /* sum holds a hanging link's direction (rj__rig_accels) until its sum replaces it */
        e[0] = sum[2 * l];
        e[1] = sum[2 * l + 1];
        /* the centre: a_root + alpha perp(dc e) - omega^2 dc e */
        sum[2 * l] = m->rb_mass[l] * (kl[RJ__KA_AX] - kl[RJ__KA_AL] * dc * e[1] -
                                      kl[RJ__KA_OM] * kl[RJ__KA_OM] * dc * e[0] -
                                      m->solver.gravity[0]);
        sum[2 * l + 1] = m->rb_mass[l] * (kl[RJ__KA_AY] + kl[RJ__KA_AL] * dc * e[0] -
                                          kl[RJ__KA_OM] * kl[RJ__KA_OM] * dc * e[1] -
                                          m->solver.gravity[1]);
        for (i = 0; i <= m->ldef[l].elements && s->node_inputs; i++) {
            const double *in = s->input_node + 3 * (size_t) (m->link_first[l] + i);
            sum[2 * l] -= in[0];
            sum[2 * l + 1] -= in[1];
        }
    }
    for (q = 0; q < m->nload; q++) {
        double value[3];
        l = m->load[q].link;
        if (m->rb_pjoint[l] < 0)
            continue;
        rj__load_value(&m->load[q], RJ__FS(m, f)[RJ__FS_TIME], k[RJ__KA_N * (size_t) l], value);
        sum[2 * l] -= value[0];
        sum[2 * l + 1] -= value[1];
    }
    rj__rig_loop_pins(m, s, sum, forces);
    for (q = m->nq - 1; q >= 0; q--) {
        const int j = m->jorder[q], l2 = m->jdef[j].body2, p = m->jdef[j].body1;
        forces[2 * j] = sum[2 * l2];
        forces[2 * j + 1] = sum[2 * l2 + 1];
        if (p >= 0) {
            sum[2 * p] += sum[2 * l2];
            sum[2 * p + 1] += sum[2 * l2 + 1];
        }
    }
}

/* What the material path adds to element e (local) of link l at n (src/beam_material.h):
   its axial law and its layers' plastic strains at n (kept in the current frame, as the
   chord angles), their largest outer-fibre stress into *smax; the viscous part, lagged
   on the rates at n - 1/2, or implicit as the step kept it (src/viscous.h). */
static void rj__elem_material_at_n(const rj_model *m, const rj_state *s, int l, int e,
                                   double ex, double ey, double tha, double thb,
                                   rj__elem_force *f, double *smax)
{
    const double *at_n = s->fd[1 - s->cur];
    const double *vx = RJ__FVX(m, at_n), *vy = RJ__FVY(m, at_n), *w = RJ__FW(m, at_n);
    const int a = m->link_first[l] + e;
    const double inv_l2 = 1.0 / (ex * ex + ey * ey);
    rj__material mt;
    rj__elem_force v;
    const double *ep = m->link_pl[l] < 0 ? NULL
                                         : s->fd[s->cur] + m->pl_off + m->link_pl[l] +
                                               2 * (size_t) m->ldef[l].layers * (size_t) e;
    rj__material_of(m, l, &mt);
    rj__elem_material(&mt, ex, ey, tha, thb, ep, NULL, f, smax);
    if (RJ__LD(m, l)[RJ__LD_IMPLICIT] > 0) {
        const double *kept = s->visc_force + 4 * ((size_t) m->link_efirst[l] + (size_t) e);
        v.fx = kept[0];
        v.fy = kept[1];
        v.ma = kept[2];
        v.mb = kept[3];
    } else
        rj__elem_viscous(m->link_kc + 4 * (size_t) l, RJ__LD(m, l)[RJ__LD_LAGGED], ex, ey,
                         inv_l2, vx[a + 1] - vx[a], vy[a + 1] - vy[a], w[a], w[a + 1], &v);
    f->fx += v.fx;
    f->fy += v.fy;
    f->ma += v.ma;
    f->mb += v.mb;
}

/* Node space: element e (local) of link l at n, as the beam pass gives it: the force on
   its second node, its end moments (the positions and rotations at n, the chord angle
   the step took there, and what its material adds); its chord's unit vector into unit;
   a yielding link's largest outer-fibre stress at its sections into *smax (else 0). */
static void rj__elem_at_n(const rj_model *m, const rj_state *s, int l, int e,
                          rj__elem_force *f, double unit[2], double *smax)
{
    const double *at_n = s->fd[1 - s->cur];
    const double *x = RJ__FX(m, at_n), *y = RJ__FY(m, at_n), *phi = RJ__FPHI(m, at_n);
    const double *beta = RJ__FBETA(m, s->fd[s->cur]);
    const int a = m->link_first[l] + e;
    const double ex = x[a + 1] - x[a], ey = y[a + 1] - y[a], len = sqrt(ex * ex + ey * ey);
    rj__elems c;
    memset(&c, 0, sizeof c);
    c.kb = m->link_kc[4 * (size_t) l];
    c.kax = m->link_kc[4 * (size_t) l + 1];
    c.l0sq = m->link_kc[4 * (size_t) l + 2];
    c.half_inv_l0sq = m->link_kc[4 * (size_t) l + 3];
    const double bt = beta[m->link_efirst[l] + e];
    rj__elem_forces(&c, ex, ey, bt, 1.0 / (len * len), phi[a], phi[a + 1], f);
    *smax = 0;
    if (m->link_path[l] == RJ__PATH_MATERIAL)
        rj__elem_material_at_n(m, s, l, e, ex, ey, phi[a] - bt, phi[a + 1] - bt, f, smax);
    unit[0] = ex / len;
    unit[1] = ey / len;
}

/* Element e of a flexible link's loads at t^n (rj_element_loads, without its checks). */
static void rj__element_loads(const rj_model *m, const rj_state *s, int link, int element,
                              double loads[5])
{
    const rj_link_def *d = &m->ldef[link];
    rj__elem_force f;
    double unit[2], A, I, smax;
    rj__elem_at_n(m, s, link, element, &f, unit, &smax);
    /* the part beyond each section on the part before: -(the force on the second node) */
    loads[0] = -(f.fx * unit[0] + f.fy * unit[1]);
    loads[1] = -(-f.fx * unit[1] + f.fy * unit[0]);
    loads[2] = -f.ma;
    loads[3] = f.mb;
    A = m->link_EA[link] / d->E;
    I = m->link_EI[link] / d->E;
    if (d->yield > 0)
        loads[4] = smax;
    else if (d->section == RJ_SECTION_RECT)
        loads[4] = fabs(loads[0]) / A + fmax(fabs(loads[2]), fabs(loads[3])) * 0.5 * d->height / I;
    else
        loads[4] = NAN;
}

RJDEF rj_result rj_element_loads(const rj_model *m, const rj_state *s, int link, int element,
                                 double loads[5])
{
    const rj_link_def *d;
    int k;
    RJ_ASSERT(m && s && loads && link >= 0 && link < m->nl);
    for (k = 0; k < 5; k++)
        loads[k] = 0;
    d = &m->ldef[link];
    if (element < 0 || element >= d->elements || d->fidelity != RJ_LINK_FLEXIBLE ||
        s->at_n != RJ__AT_N_FRAME)
        return RJ_ERR_INVALID;
    rj__element_loads(m, s, link, element, loads);
    return RJ_OK;
}

RJDEF double rj_element_plastic_strain(const rj_model *m, const rj_state *s, int link,
                                       int element, int section, int layer)
{
    const rj_link_def *d;
    RJ_ASSERT(m && s && link >= 0 && link < m->nl);
    d = &m->ldef[link];
    if (element < 0 || element >= d->elements || section < 0 || section > 1 || layer < 0 ||
        layer >= d->layers)
        return NAN;
    if (m->link_pl[link] < 0)
        return 0.0;
    return s->fd[s->cur][m->pl_off + (size_t) m->link_pl[link] +
                         2 * (size_t) d->layers * (size_t) element +
                         (size_t) d->layers * (size_t) section + (size_t) layer];
}

/* Node space: the force on node k from its own link's elements at n (the positions and
   rotations at n, the chord angles the step took there), as the beam pass gives it. */
static void rj__elem_node_force(const rj_model *m, const rj_state *s, int k, double out[2])
{
    int link, node, side;
    rj__node_of(m, k, &link, &node);
    out[0] = out[1] = 0;
    /* the element before the node (the node its second) and the one after (its first) */
    for (side = 0; side < 2; side++) {
        const int local = side ? node : node - 1;
        rj__elem_force f;
        double unit[2], smax;
        if (local < 0 || local >= m->ldef[link].elements)
            continue;
        rj__elem_at_n(m, s, link, local, &f, unit, &smax);
        out[0] += side ? -f.fx : f.fx;
        out[1] += side ? -f.fy : f.fy;
    }
}

/* Node space: applied load q's force at t^n, a step before the state's time (on its
   node's rotation then). */
static void rj__load_at_n(const rj_model *m, const rj_state *s, int q, double value[3])
{
    const double *at_n = s->fd[1 - s->cur];
    const double t = RJ__FS(m, s->fd[s->cur])[RJ__FS_TIME] - m->dt;
    rj__load_value(&m->load[q], t, RJ__FPHI(m, at_n)[m->load_node[q]], value);
}

/* Node space: what node k (of link l) asks of the forces not yet counted (its elements,
   the pins at it), at t^n: m a - m g less its loads (with loads set; the all-joints pass
   takes them by load), the caller's force and its mass-proportional damping (a from the
   rates at n - 1/2 and n + 1/2, the step's kick). */
static void rj__node_ask(const rj_model *m, const rj_state *s, int l, int k, int loads,
                         double out[2])
{
    const double *now = s->fd[s->cur], *at_n = s->fd[1 - s->cur];
    const double kick = s->steps == 1 ? 0.5 * m->dt : m->dt;
    int q;
    out[0] = m->mass[k] * ((RJ__FVX(m, now)[k] - RJ__FVX(m, at_n)[k]) / kick -
                           m->solver.gravity[0]);
    out[1] = m->mass[k] * ((RJ__FVY(m, now)[k] - RJ__FVY(m, at_n)[k]) / kick -
                           m->solver.gravity[1]);
    for (q = 0; loads && q < m->nload; q++)
        if (m->load_node[q] == k) {
            double value[3];
            rj__load_at_n(m, s, q, value);
            out[0] -= value[0];
            out[1] -= value[1];
        }
    if (s->node_inputs) {
        out[0] -= s->input_node[3 * (size_t) k];
        out[1] -= s->input_node[3 * (size_t) k + 1];
    }
    if (m->link_path[l] == RJ__PATH_MATERIAL) {
        const double alpha = RJ__LD(m, l)[RJ__LD_MASS];
        out[0] += alpha * m->mass[k] * RJ__FVX(m, at_n)[k];
        out[1] += alpha * m->mass[k] * RJ__FVY(m, at_n)[k];
    }
}

/* Node space: node k's momentum ask with its loads (rj__node_ask). */
static void rj__node_momentum(const rj_model *m, const rj_state *s, int k, double out[2])
{
    int link, node;
    rj__node_of(m, k, &link, &node);
    rj__node_ask(m, s, link, k, 1, out);
}

/* The frame that holds the nodes' values at n (rj_state.at_n): the other one after a
   double-buffered step; after an in-place one the third, for m->dnode's nodes only
   (every joint's and every link's end nodes). */
static const double *rj__nodes_at_n(const rj_state *s)
{
    return s->at_n == RJ__AT_N_KEPT ? s->fd[2] : s->fd[1 - s->cur];
}

/* A rigid body's own link (rod and tip mass; mixed scenes): its momentum's ask, M (a_c -
   g) with a_c from its end nodes' rates at n - 1/2 and n + 1/2 (the body moves them), the
   centre a fraction of the way along them. Its nodes carry no mass of their own; the
   nodes of other links it carries count as theirs. */
static void rj__body_momentum(const rj_model *m, const rj_state *s, int c, double out[2])
{
    const rj_link_def *d = &m->ldef[c];
    const int n0 = m->link_first[c], nt = m->link_first[c + 1] - 1;
    const double rod = d->rho * rj__plain_area(d) * d->length, own = rod + d->tip_mass;
    const double along = (rod * 0.5 + d->tip_mass) / own;
    const double *now = s->fd[s->cur], *at_n = rj__nodes_at_n(s);
    const double kick = s->steps == 1 ? 0.5 * m->dt : m->dt;
    int axis;
    for (axis = 0; axis < 2; axis++) {
        const double *v1 = axis ? RJ__FVY(m, now) : RJ__FVX(m, now);
        const double *v0 = axis ? RJ__FVY(m, at_n) : RJ__FVX(m, at_n);
        const double after = v1[n0] + along * (v1[nt] - v1[n0]);
        const double before = v0[n0] + along * (v0[nt] - v0[n0]);
        out[axis] = own * ((after - before) / kick - m->solver.gravity[axis]);
    }
}

/* In place: the force node k's pins put on it at n (k one of m->dnode), m a - m g less
   every other force the step put on it: s->fx, fy keep the sum the step moved the node
   with (its elements', its loads', its mass-proportional damping), with m g where the
   node moves on its own (its kinetic mass); a from v^{n-1/2}, which the third frame
   keeps, and v^{n+1/2}. */
static void rj__kept_node_balance(const rj_model *m, const rj_state *s, int k, double out[2])
{
    const double *now = s->fd[s->cur], *at_n = s->fd[2];
    const double kick = s->steps == 1 ? 0.5 * m->dt : m->dt;
    const double *g = m->solver.gravity;
    const double ax = (RJ__FVX(m, now)[k] - RJ__FVX(m, at_n)[k]) / kick;
    const double ay = (RJ__FVY(m, now)[k] - RJ__FVY(m, at_n)[k]) / kick;
    out[0] = m->mass[k] * (ax - g[0]) - (s->fx[k] - m->kmass[k] * g[0]);
    out[1] = m->mass[k] * (ay - g[1]) - (s->fy[k] - m->kmass[k] * g[1]);
}

/* Node space: what the chord-reference joints' torques put on node k in the step that
   led here, into out: each joint's torque (its components and the caller's, as the step
   recorded them) as the force couples rj__apply_torque made of it on the chords at n.
   Returns 0 where node k is a chord's far node (K or L), whose latches move it by jumps
   (rj__spin) that no record keeps. */
static int rj__chord_forces_at(const rj_model *m, const rj_state *s, int k, double out[2])
{
    const double *at_n = rj__nodes_at_n(s);
    const double *x = RJ__FX(m, at_n), *y = RJ__FY(m, at_n);
    int j, c;
    out[0] = out[1] = 0;
    for (j = 0; j < m->nj; j++) {
        const rj__joint *J = &m->jnt[j];
        const double *rec = RJ__FJ(m, s->fd[s->cur], j);
        double tau = rec[RJ__JD_INPUT], bx, by, b2;
        if (!J->chord || (k != J->nI && k != J->nJ && k != J->nK && k != J->nL))
            continue;
        if (k == J->nK || k == J->nL)
            return 0;
        for (c = 0; c < RJ_TORQUE_COUNT; c++)
            if (c != RJ_TORQUE_TOTAL)
                tau += rec[RJ__JD_TQ0 + c];
        /* body 2's chord J -> L takes the torque, body 1's I -> K its opposite */
        bx = k == J->nJ ? x[J->nL] - x[J->nJ] : x[J->nK] - x[J->nI];
        by = k == J->nJ ? y[J->nL] - y[J->nJ] : y[J->nK] - y[J->nI];
        b2 = bx * bx + by * by;
        if (k == J->nI)
            tau = -tau;
        out[0] += tau * by / b2;
        out[1] -= tau * bx / b2;
    }
    return 1;
}

/* Node space: the force node k's pins put on it at n, its momentum's ask less its own
   link's elements (rj__node_momentum; a rigid body's own node has no elements) and what
   chord-reference joints' torques put on it (rj__chord_forces_at); in place from the
   step's forces, which hold those (rj__kept_node_balance). */
static void rj__pin_node_balance(const rj_model *m, const rj_state *s, int k, double out[2])
{
    double elements[2] = { 0, 0 }, chords[2];
    if (s->at_n == RJ__AT_N_KEPT) {
        rj__kept_node_balance(m, s, k, out);
        return;
    }
    if (!rj__own_body_node(m, k))
        rj__elem_node_force(m, s, k, elements);
    rj__node_momentum(m, s, k, out);
    if (m->nchord && rj__chord_forces_at(m, s, k, chords)) {
        elements[0] += chords[0];
        elements[1] += chords[1];
    }
    out[0] -= elements[0];
    out[1] -= elements[1];
}

/* Node space, flexible links: the force on body 2's pin node from the rest of the pin
   (rj__pin_node_balance), at n. When body 2 is a rigid body of a mixed scene, the same
   on body 1's node, reversed (rj__balance_node). */
static void rj__node_pin_force(const rj_model *m, const rj_state *s, int j, double force[2])
{
    double sign;
    const int k = rj__balance_node(m, j, &sign);
    rj__pin_node_balance(m, s, k, force);
    force[0] *= sign;
    force[1] *= sign;
}

/* Whether node n is one rigid body c carries but does not own: a node of another link
   pinned to it, whose translation the body's pin gives. */
static int rj__body_carries(const rj_model *m, int c, int n)
{
    return n >= 0 && m->node_cl[n] == c && !RJ__CL_RIGID(m, n);
}

/* Whether rigid body c's balance (rj__body_ground_force) has the forces of its pins to
   the nodes it carries: not where such a node is pinned to the ground too (that pin
   shares the body's), nor where a chord reference's torque acts on one as forces. */
static int rj__body_pins_known(const rj_model *m, int c)
{
    int j, k;
    for (j = 0; j < m->nj; j++) {
        const rj__joint *J = &m->jnt[j];
        const int nodes[4] = { J->nI, J->nK, J->nJ, J->nL };
        if (J->nI < 0 && rj__body_carries(m, c, J->nJ))
            return 0;
        for (k = 0; k < 4 && J->chord; k++)
            if (rj__body_carries(m, c, nodes[k]))
                return 0;
    }
    return 1;
}

/* Node space: the force the ground puts on rigid body c of a mixed scene at the pin it
   turns about (its anchor) at t^n, from the body's Newton's second law: its own link's
   momentum ask (rj__body_momentum) and its own nodes' (their loads and the caller's
   forces), less the forces its other pins put on it: on each node it carries, the
   reverse of that node's pin's force (rj__pin_node_balance), and where the step
   projected (rec, its record: rj__loop_body_push) the pushes of its pins to other bodies
   and of the carried links' lengths. Returns 0 where unknown (force 0): a held body, or
   one whose pins' forces are not known (rj__body_pins_known). */
static int rj__body_ground_force(const rj_model *m, const rj_state *s, int c,
                                 const double *rec, double force[2])
{
    int q;
    force[0] = force[1] = 0;
    if (m->cl_fix[c] != 1 || !rj__body_pins_known(m, c))
        return 0;
    rj__body_momentum(m, s, c, force);
    for (q = m->cl_first[c]; q < m->cl_first[c + 1]; q++) {
        double pin[2];
        rj__pin_node_balance(m, s, m->cl_node[q], pin);
        force[0] += pin[0];
        force[1] += pin[1];
    }
    if (rec) {
        force[0] -= rec[0];
        force[1] -= rec[1];
    }
    return 1;
}

/* Node space: loop joint j's pin force (rj__loop_side): its pin node's balance
   (rj__node_pin_force) less what the node's own link's lengths put on it in the step;
   between two rigid bodies the pin's pushes; pinning a rigid body to the ground, the
   body's balance less its pins' pushes (rj__body_ground_force); each from the step's
   record (rj__loop_records). Returns 0 where it has none, force 0: none is known there
   (rj__loop_side: a chord reference; rj__body_ground_force), or no record of the step
   that led here (needed with inextensible links, between bodies, and on a body with
   pins to others). */
static int rj__loop_pin_force(const rj_model *m, const rj_state *s, int j, double force[2])
{
    const double *rec = s->loop_force + 2 * j;
    const int recorded = s->loop_force[2 * m->nj] == (double) s->steps;
    double sign;
    int node;
    const int kind = rj__loop_side(m, j, &node, &sign);
    const int needs =
        kind == RJ__LOOP_BODIES || m->any_inext || (kind == RJ__LOOP_GROUND && m->nbp);
    force[0] = force[1] = 0;
    if (kind == RJ__LOOP_NONE || (!recorded && needs))
        return 0;
    if (kind == RJ__LOOP_BODIES) {
        force[0] = rec[0];
        force[1] = rec[1];
        return 1;
    }
    if (kind == RJ__LOOP_GROUND)
        return rj__body_ground_force(m, s, m->node_cl[m->jnt[j].nJ], m->project ? rec : NULL,
                                     force);
    rj__node_pin_force(m, s, j, force);
    if (m->any_inext) {
        force[0] -= sign * rec[0];
        force[1] -= sign * rec[1];
    }
    return 1;
}

/* The links below joint j (its body 2 and the links that hang from them, down the joint
   tree) marked 1 in below (nl). */
static void rj__links_below(const rj_model *m, int j, double *below)
{
    int l, k, grew = 1;
    for (l = 0; l < m->nl; l++)
        below[l] = l == m->jdef[j].body2;
    while (grew) {
        grew = 0;
        for (k = 0; k < m->nj; k++) {
            const int b1 = m->jdef[k].body1, b2 = m->jdef[k].body2;
            if (!m->jnt[k].loop && b1 >= 0 && below[b1] != 0 && below[b2] == 0) {
                below[b2] = 1;
                grew = 1;
            }
        }
    }
}

/* The loop joints that tie the links marked in below to the rest, their pin forces on
   them as forces from outside: subtracted from the links' sum in force (F on body 2, -F
   on body 1). Returns 0 where one has none (rj__loop_pin_force). */
static int rj__loops_across(const rj_model *m, const rj_state *s, const double *below,
                            double force[2])
{
    int k;
    for (k = 0; k < m->nj; k++) {
        const int b1 = m->jdef[k].body1, b2 = m->jdef[k].body2;
        const int in1 = b1 >= 0 && below[b1] != 0, in2 = below[b2] != 0;
        const double sign = in2 ? 1.0 : -1.0;
        double loop[2];
        if (!m->jnt[k].loop || in1 == in2)
            continue;
        if (!rj__loop_pin_force(m, s, k, loop))
            return 0;
        force[0] -= sign * loop[0];
        force[1] -= sign * loop[1];
    }
    return 1;
}

/* Node space with inextensible links or rigid bodies: joint j's pin force as Newton's
   second law for the links below it, the sum of their nodes' momentum asks
   (rj__node_momentum) and their bodies' (rj__body_momentum) less the forces of the loops
   that tie them to the rest (rj__loops_across): the elements' forces, their lengths'
   constraint forces and the pins among them are internal and cancel. below: nl doubles
   of scratch. Returns 0 where such a loop has no force, or a held body is among them. */
static int rj__subtree_pin_force(const rj_model *m, const rj_state *s, int j, double *below,
                                 double force[2])
{
    int l, k;
    force[0] = force[1] = 0;
    rj__links_below(m, j, below);
    for (l = 0; l < m->nl; l++) {
        if (below[l] == 0)
            continue;
        if (m->link_path[l] == RJ__PATH_RIGID) {
            double ask[2];
            if (m->cl_fix[l] == 2)
                return 0;
            rj__body_momentum(m, s, l, ask);
            force[0] += ask[0];
            force[1] += ask[1];
        }
        for (k = m->link_first[l]; k < m->link_first[l + 1]; k++) {
            double ask[2];
            rj__node_momentum(m, s, k, ask);
            force[0] += ask[0];
            force[1] += ask[1];
        }
    }
    return rj__loops_across(m, s, below, force);
}

/* Whether node space takes joint j's pin force from the links below it
   (rj__subtree_pin_force): with inextensible links (their lengths' forces), and at a pin
   between two rigid bodies or a rigid body and the ground (their projection's); never
   at a loop joint (rj__loop_pin_force). */
static int rj__pin_by_subtree(const rj_model *m, int j)
{
    const rj__joint *J = &m->jnt[j];
    if (J->loop)
        return 0;
    return m->any_inext ||
           (rj__own_body_node(m, J->nJ) && (J->nI < 0 || rj__own_body_node(m, J->nI)));
}

/* Where rj_joint_pin_force has no answer yet: no state a step before (rj_state.at_n:
   before a step, after a failed one); a chord reference (the joint's forces on the pin
   node) on the pin node's own balance; in node space, a loop joint without a force
   (rj__loop_pin_force), or one tying the links below the joint to the rest, or a held
   body among them (rj__subtree_pin_force, NaN; in place rj__kept_body_pin_force's);
   loops of rigid links before a step (their rows' forces). */
static int rj__pin_force_unknown(const rj_model *m, const rj_state *s, int j)
{
    const rj__joint *J = &m->jnt[j];
    if (m->rigid)
        return m->nloop > 0 && s->loop_force[2 * m->nj] != (double) s->steps;
    double sign, chords[2];
    if (s->at_n == RJ__AT_N_NONE)
        return 1;
    if (J->loop || rj__pin_by_subtree(m, j) || !m->nchord)
        return 0;
    return !rj__chord_forces_at(m, s, rj__balance_node(m, j, &sign), chords);
}

/* The scratch doubles rj__pin_forces needs: rigid scenes' kinematics, the all-joints
   pass's arrays with inextensible links or rigid bodies (rj__pin_pass). */
static size_t rj__pin_work_size(const rj_model *m)
{
    if (m->rigid)
        return (RJ__KA_N + 2) * ((size_t) m->nl + 1);
    return m->any_inext || m->ncl ? RJ__PIN_PASS_N * ((size_t) m->nl + 1) : 0;
}

/* Node space's all-joints pass (rj__pin_pass_run): Newton's second law for every
   subtree of the joint tree at once, children before parents, so all joints cost one
   walk of the nodes. Its arrays, nl + 1 doubles each (RJ__PIN_PASS_N of them, carved
   from the pin-force scratch; indices and marks kept as doubles, exact). */
typedef struct rj__pin_pass {
    double *need;    /* 1 where a joint's force needs the link's ask (rj__pin_pass_need) */
    double *fx, *fy; /* each link's subtree's momentum ask (NaN: a held body in it) */
    double *up;      /* the tree joint it hangs from, -1 for a root */
    double *wait;    /* its children not yet summed; then its children's next place */
    double *order;   /* the links, each after its children */
    double *size;    /* its subtree's links */
    double *pre;     /* its place in a preorder: its subtree's are pre .. pre + size - 1 */
    double *lo, *hi; /* the lowest and highest place of a loop's far end inside it */
} rj__pin_pass;

/* The pass's arrays in work (rj__pin_work_size doubles). */
static rj__pin_pass rj__pin_pass_of(const rj_model *m, double *work)
{
    const size_t n = (size_t) m->nl + 1;
    rj__pin_pass p;
    p.fx = work;
    p.fy = work + n;
    p.up = work + 2 * n;
    p.wait = work + 3 * n;
    p.order = work + 4 * n;
    p.size = work + 5 * n;
    p.pre = work + 6 * n;
    p.lo = work + 7 * n;
    p.hi = work + 8 * n;
    p.need = work + 9 * n;
    return p;
}

/* The link link l hangs from in the joint tree (-1: ground, or l a root). */
static int rj__pin_pass_up(const rj_model *m, const rj__pin_pass *p, int l)
{
    const int j = (int) p->up[l];
    return j >= 0 ? m->jdef[j].body1 : -1;
}

/* The pass's order: each link's tree joint, then the links each after its children
   (leaves first; a parent once its last child is placed). The tree joints form a forest
   (rj__validate_graph), so every link is placed. */
static void rj__pin_pass_order(const rj_model *m, const rj__pin_pass *p)
{
    int l, j, head, tail = 0;
    for (l = 0; l < m->nl; l++) {
        p->up[l] = -1;
        p->wait[l] = 0;
    }
    /* a link's first joint as body2 hangs it; a later one closes a loop */
    for (j = 0; j < m->nj; j++) {
        const int b1 = m->jdef[j].body1;
        if (m->jnt[j].loop)
            continue;
        p->up[m->jdef[j].body2] = j;
        if (b1 >= 0)
            p->wait[b1] += 1;
    }
    /* the leaves first, then each parent once its last child is placed */
    for (l = 0; l < m->nl; l++)
        if (p->wait[l] == 0)
            p->order[tail++] = l;
    for (head = 0; head < tail; head++) {
        const int up = rj__pin_pass_up(m, p, (int) p->order[head]);
        if (up < 0)
            continue;
        p->wait[up] -= 1;
        if (p->wait[up] == 0)
            p->order[tail++] = up;
    }
}

/* The links whose asks a joint's force needs, marked 1 in need: those below a joint
   rj__pin_by_subtree takes (every tree joint with inextensible links; in a mixed scene the
   pins to and between rigid bodies, whose flexible neighbours' nodes are left out).
   Parents before children (the pass's order backwards): a child of a marked link is. */
static void rj__pin_pass_need(const rj_model *m, const rj__pin_pass *p)
{
    int l, j, i;
    for (l = 0; l < m->nl; l++)
        p->need[l] = 0;
    /* the joints the pass gives mark their body 2, which marks the links below it */
    for (j = 0; j < m->nj; j++)
        if (rj__pin_by_subtree(m, j))
            p->need[m->jdef[j].body2] = 1;
    for (i = m->nl - 1; i >= 0; i--) {
        const int child = (int) p->order[i], up = rj__pin_pass_up(m, p, child);
        if (up >= 0 && p->need[up] != 0)
            p->need[child] = 1;
    }
}

/* Link l's own momentum ask but for its applied loads: its rigid body's
   (rj__body_momentum) and its nodes' (rj__node_ask). A held body has none (NaN, which
   every sum that holds it keeps: rj__subtree_pin_force gives none there either). */
static void rj__link_momentum(const rj_model *m, const rj_state *s, int l, double out[2])
{
    int k;
    out[0] = out[1] = 0;
    if (m->link_path[l] == RJ__PATH_RIGID && m->cl_fix[l] == 2) {
        out[0] = out[1] = NAN;
        return;
    }
    if (m->link_path[l] == RJ__PATH_RIGID)
        rj__body_momentum(m, s, l, out);
    for (k = m->link_first[l]; k < m->link_first[l + 1]; k++) {
        double ask[2];
        rj__node_ask(m, s, l, k, 0, ask);
        out[0] += ask[0];
        out[1] += ask[1];
    }
}

/* The loop joints' pin forces (forces; NaN where none) on the links where needed, as
   forces from outside the tree: each link's own sum less them (F on body 2, -F on body
   1; a subtree holding both ends gets none). Those without one tie the subtrees they
   cross to the rest (rj__pin_pass_loops). */
static void rj__pin_pass_loop_forces(const rj_model *m, const rj__pin_pass *p,
                                     const double *forces)
{
    int j;
    for (j = 0; j < m->nj; j++) {
        const int b1 = m->jdef[j].body1, b2 = m->jdef[j].body2;
        const double *F = forces + 2 * j;
        if (!m->jnt[j].loop || F[0] != F[0])
            continue;
        if (p->need[b2] != 0) {
            p->fx[b2] -= F[0];
            p->fy[b2] -= F[1];
        }
        if (b1 >= 0 && p->need[b1] != 0) {
            p->fx[b1] += F[0];
            p->fy[b1] += F[1];
        }
    }
}

/* Every subtree's momentum ask (where needed) less the loops' forces on it, and its
   size, children before parents (the pass's order): each link's own plus its children's
   subtrees'. */
static void rj__pin_pass_sums(const rj_model *m, const rj_state *s, const rj__pin_pass *p,
                              const double *forces)
{
    int l, q, i;
    for (l = 0; l < m->nl; l++) {
        double own[2] = { 0, 0 };
        if (p->need[l] != 0)
            rj__link_momentum(m, s, l, own);
        p->fx[l] = own[0];
        p->fy[l] = own[1];
        p->size[l] = 1;
    }
    /* the applied loads once each, off their nodes' links, not node by node */
    for (q = 0; q < m->nload; q++) {
        double value[3];
        int link, node;
        if (m->load_node[q] < 0)
            continue;
        rj__node_of(m, m->load_node[q], &link, &node);
        if (p->need[link] == 0)
            continue;
        rj__load_at_n(m, s, q, value);
        p->fx[link] -= value[0];
        p->fy[link] -= value[1];
    }
    rj__pin_pass_loop_forces(m, p, forces);
    /* a child's subtree is summed once its own children's are in it */
    for (i = 0; i < m->nl; i++) {
        const int child = (int) p->order[i], up = rj__pin_pass_up(m, p, child);
        if (up < 0)
            continue;
        p->fx[up] += p->fx[child];
        p->fy[up] += p->fy[child];
        p->size[up] += p->size[child];
    }
}

/* With loops: each link's place in a preorder, parents before children (the pass's
   order backwards), each subtree's places one run: a root's after the roots before it,
   a child's the next its parent has free (wait, all 0 once the order is taken). */
static void rj__pin_pass_preorder(const rj_model *m, const rj__pin_pass *p)
{
    double next_root = 0;
    int i;
    for (i = m->nl - 1; i >= 0; i--) {
        const int l = (int) p->order[i], up = rj__pin_pass_up(m, p, l);
        if (up < 0) {
            p->pre[l] = next_root;
            next_root += p->size[l];
        } else {
            p->pre[l] = p->wait[up];
            p->wait[up] += p->size[l];
        }
        p->wait[l] = p->pre[l] + 1;
    }
}

/* A loop joint's end on link l, its far end's place far (-1 for ground): into l's
   lowest and highest far places. */
static void rj__pin_pass_far(const rj__pin_pass *p, int l, double far)
{
    p->lo[l] = fmin(p->lo[l], far);
    p->hi[l] = fmax(p->hi[l], far);
}

/* With loops that have no pin force (forces NaN): each subtree's lowest and highest
   place of such a loop joint's far end, from the ends inside it (children before
   parents). A subtree such a loop ties to the rest has one outside its own places
   (ground's, -1, is outside every subtree). */
static void rj__pin_pass_loops(const rj_model *m, const rj__pin_pass *p, const double *forces)
{
    int l, j, i;
    for (l = 0; l < m->nl; l++) {
        p->lo[l] = m->nl;
        p->hi[l] = -1;
    }
    /* each such loop joint's two ends, each seeing the other's place */
    for (j = 0; j < m->nj; j++) {
        const int b1 = m->jdef[j].body1, b2 = m->jdef[j].body2;
        if (!m->jnt[j].loop || forces[2 * j] == forces[2 * j])
            continue;
        rj__pin_pass_far(p, b2, b1 >= 0 ? p->pre[b1] : -1.0);
        if (b1 >= 0)
            rj__pin_pass_far(p, b1, p->pre[b2]);
    }
    /* a subtree's ends are its own link's and its children's subtrees' */
    for (i = 0; i < m->nl; i++) {
        const int child = (int) p->order[i], up = rj__pin_pass_up(m, p, child);
        if (up < 0)
            continue;
        p->lo[up] = fmin(p->lo[up], p->lo[child]);
        p->hi[up] = fmax(p->hi[up], p->hi[child]);
    }
}

/* The all-joints pass over work (rj__pin_work_size doubles): every subtree's sums with
   the loop joints' forces (forces, NaN where none), and with loops the places that tell
   which subtrees a loop without a force ties to the rest. */
static void rj__pin_pass_run(const rj_model *m, const rj_state *s, double *work,
                             const double *forces)
{
    const rj__pin_pass p = rj__pin_pass_of(m, work);
    rj__pin_pass_order(m, &p);
    rj__pin_pass_need(m, &p);
    rj__pin_pass_sums(m, s, &p, forces);
    if (!m->nloop)
        return;
    rj__pin_pass_preorder(m, &p);
    rj__pin_pass_loops(m, &p, forces);
}

/* Joint j's pin force from the pass over work: its body 2's subtree's sum
   (rj__subtree_pin_force's, in another order). Returns 0 where a loop without a force
   ties that subtree to the rest. */
static int rj__pin_pass_force(const rj_model *m, double *work, int j, double force[2])
{
    const rj__pin_pass p = rj__pin_pass_of(m, work);
    const int b = m->jdef[j].body2;
    force[0] = p.fx[b];
    force[1] = p.fy[b];
    if (!m->nloop)
        return 1;
    return p.lo[b] >= p.pre[b] && p.hi[b] < p.pre[b] + p.size[b];
}

/* Whether rj__pin_forces takes the all-joints pass: node space, the rates at n - 1/2
   there, and a joint whose force it gives (rj__pin_by_subtree). */
static int rj__pin_pass_wanted(const rj_model *m, const rj_state *s)
{
    int j;
    if (m->rigid || s->at_n != RJ__AT_N_FRAME)
        return 0;
    for (j = 0; j < m->nj; j++)
        if (rj__pin_by_subtree(m, j))
            return 1;
    return 0;
}

/* In place: joint j's pin force where node space takes it from the links below
   (rj__pin_by_subtree), whose nodes' values at n the step does not keep: a rigid body's
   pin to the ground (the only such joint in place, which projects nothing), from the
   body's own balance (rj__body_ground_force). Returns 0 where it has none, force 0. */
static int rj__kept_body_pin_force(const rj_model *m, const rj_state *s, int j,
                                   double force[2])
{
    const rj__joint *J = &m->jnt[j];
    force[0] = force[1] = 0;
    if (J->nI >= 0 || !rj__own_body_node(m, J->nJ))
        return 0;
    return rj__body_ground_force(m, s, m->node_cl[J->nJ], NULL, force);
}

/* Node space: joint j's pin force into force (NaN where unknown): a loop joint's own
   (rj__loop_pin_force); else from the all-joints pass over work where it takes the
   joint (rj__pin_by_subtree; in place from the body, rj__kept_body_pin_force), else from
   its pin node's balance. */
static void rj__node_joint_force(const rj_model *m, const rj_state *s, double *work, int j,
                                 double force[2])
{
    int known = !rj__pin_force_unknown(m, s, j);
    force[0] = force[1] = 0.0;
    if (known && m->jnt[j].loop)
        known = rj__loop_pin_force(m, s, j, force);
    else if (known && rj__pin_by_subtree(m, j) && s->at_n == RJ__AT_N_KEPT)
        known = rj__kept_body_pin_force(m, s, j, force);
    else if (known && rj__pin_by_subtree(m, j))
        known = rj__pin_pass_force(m, work, j, force);
    else if (known)
        rj__node_pin_force(m, s, j, force);
    if (!known)
        force[0] = force[1] = NAN;
}

/* Every joint's pin force into forces (2 a joint, NaN where unknown), with work
   (rj__pin_work_size doubles; allocated when NULL). */
static rj_result rj__pin_forces(const rj_model *m, const rj_state *s, double *work,
                                double *forces)
{
    double *own = NULL;
    int j;
    if (!work && rj__pin_work_size(m)) {
        own = (double *) RJ_MALLOC(sizeof(double) * rj__pin_work_size(m), NULL);
        if (!own)
            return RJ_ERR_NOMEM;
        work = own;
    }
    /* node space: the loop joints' first, which the pass takes as forces from outside;
       then the subtrees all at once, before the other joints read them */
    for (j = 0; j < m->nj && !m->rigid; j++)
        if (m->jnt[j].loop)
            rj__node_joint_force(m, s, work, j, forces + 2 * j);
    if (rj__pin_pass_wanted(m, s))
        rj__pin_pass_run(m, s, work, forces);
    for (j = 0; j < m->nj && !m->rigid; j++)
        if (!m->jnt[j].loop)
            rj__node_joint_force(m, s, work, j, forces + 2 * j);
    /* rigid scenes: the joints' kinematics come down the tree for all of them at once */
    for (j = 0; j < m->nj && m->rigid; j++) {
        const double none = rj__pin_force_unknown(m, s, j) ? NAN : 0.0;
        forces[2 * j] = forces[2 * j + 1] = none;
    }
    if (m->rigid && m->nj && !rj__pin_force_unknown(m, s, 0))
        rj__rig_pin_forces(m, s, work, forces);
    if (own)
        RJ_FREE(own, NULL);
    return RJ_OK;
}

RJDEF rj_result rj_joint_pin_forces(const rj_model *m, const rj_state *s, double *forces)
{
    RJ_ASSERT(m && s && forces);
    return rj__pin_forces(m, s, NULL, forces);
}

/* Node space: joint j's pin force from the links below it alone
   (rj__subtree_pin_force, which rj__pin_forces' pass gives for all joints at once):
   RJ_ERR_INVALID, force 0, where it has none. */
static rj_result rj__one_subtree_pin_force(const rj_model *m, const rj_state *s, int j,
                                           double force[2])
{
    double *below = (double *) RJ_MALLOC(sizeof(double) * ((size_t) m->nl + 1), NULL);
    int known;
    if (!below)
        return RJ_ERR_NOMEM;
    known = rj__subtree_pin_force(m, s, j, below, force);
    RJ_FREE(below, NULL);
    if (known)
        return RJ_OK;
    force[0] = force[1] = 0;
    return RJ_ERR_INVALID;
}

RJDEF rj_result rj_joint_pin_force(const rj_model *m, const rj_state *s, int j, double force[2])
{
    double *all;
    rj_result r;
    RJ_ASSERT(m && s && force && j >= 0 && j < m->nj);
    force[0] = force[1] = 0;
    if (rj__pin_force_unknown(m, s, j))
        return RJ_ERR_INVALID;
    if (!m->rigid && m->jnt[j].loop)
        return rj__loop_pin_force(m, s, j, force) ? RJ_OK : RJ_ERR_INVALID;
    if (!m->rigid && !rj__pin_by_subtree(m, j)) {
        rj__node_pin_force(m, s, j, force);
        return RJ_OK;
    }
    if (!m->rigid && s->at_n == RJ__AT_N_KEPT)
        return rj__kept_body_pin_force(m, s, j, force) ? RJ_OK : RJ_ERR_INVALID;
    if (!m->rigid)
        return rj__one_subtree_pin_force(m, s, j, force);
    /* rigid scenes: the joints' kinematics come down the tree for all of them at once */
    all = (double *) RJ_MALLOC(sizeof(double) * 2 * (size_t) m->nj, NULL);
    if (!all)
        return RJ_ERR_NOMEM;
    r = rj_joint_pin_forces(m, s, all);
    if (r == RJ_OK && all[2 * j] != all[2 * j])
        r = RJ_ERR_INVALID;
    else if (r == RJ_OK) {
        force[0] = all[2 * j];
        force[1] = all[2 * j + 1];
    }
    RJ_FREE(all, NULL);
    return r;
}
static void rj__rig_node(const rj_model *m, const rj_state *s, int l, int n, double xy[2],
                         double v[2], double *phi)
{
    double ph, rx, ry, om, vx, vy, c, sn, d = n * m->link_l0[l];
    rj__rig_pose(m, s->fd[s->cur], l, &ph, &rx, &ry, &om, &vx, &vy);
    if (phi)
        *phi = ph;
    if (!xy && !v)
        return;
    c = cos(ph);
    sn = sin(ph);
    if (xy) {
        xy[0] = rx + d * c;
        xy[1] = ry + d * sn;
    }
    if (v) {
        v[0] = vx - om * d * sn;
        v[1] = vy + om * d * c;
    }
}

static int rj__node(const rj_model *m, int l, int n)
{
    RJ_ASSERT(l >= 0 && l < m->nl);
    RJ_ASSERT(n >= 0 && n <= m->ldef[l].elements);
    return m->link_first[l] + n;
}
RJDEF void rj_node_position(const rj_model *m, const rj_state *s, int l, int n, double xy[2])
{
    const double *f = s->fd[s->cur];
    int i = rj__node(m, l, n);
    if (m->rigid) {
        rj__rig_node(m, s, l, n, xy, NULL, NULL);
        return;
    }
    xy[0] = RJ__FX(m, f)[i];
    xy[1] = RJ__FY(m, f)[i];
}
RJDEF void rj_node_velocity(const rj_model *m, const rj_state *s, int l, int n, double v[2])
{
    const double *f = s->fd[s->cur];
    int i = rj__node(m, l, n);
    if (m->rigid) {
        rj__rig_node(m, s, l, n, NULL, v, NULL);
        return;
    }
    v[0] = RJ__FVX(m, f)[i];
    v[1] = RJ__FVY(m, f)[i];
}
RJDEF double rj_node_rotation(const rj_model *m, const rj_state *s, int l, int n)
{
    double ph;
    if (m->rigid) {
        rj__node(m, l, n);
        rj__rig_node(m, s, l, n, NULL, NULL, &ph);
        return ph;
    }
    return RJ__FPHI(m, s->fd[s->cur])[rj__node(m, l, n)];
}
RJDEF double rj_node_rate(const rj_model *m, const rj_state *s, int l, int n)
{
    if (m->rigid) {
        double ph, rx, ry, om, vx, vy;
        rj__node(m, l, n);
        rj__rig_pose(m, s->fd[s->cur], l, &ph, &rx, &ry, &om, &vx, &vy);
        return om;
    }
    return RJ__FW(m, s->fd[s->cur])[rj__node(m, l, n)];
}
RJDEF void rj_node_mass(const rj_model *m, int l, int n, double *mass, double *rinertia)
{
    int i = rj__node(m, l, n);
    if (mass)
        *mass = m->mass[i];
    if (rinertia)
        *rinertia = m->rinertia[i];
}
RJDEF void rj_joint_position(const rj_model *m, const rj_state *s, int j, double xy[2])
{
    const double *f = s->fd[s->cur];
    RJ_ASSERT(j >= 0 && j < m->nj);
    if (m->rigid) {
        rj__rig_node(m, s, m->jdef[j].body2, m->jnt[j].nJ - m->link_first[m->jdef[j].body2], xy,
                     NULL, NULL);
        return;
    }
    xy[0] = RJ__FX(m, f)[m->jnt[j].nJ];
    xy[1] = RJ__FY(m, f)[m->jnt[j].nJ];
}
RJDEF double rj_joint_theta_running(const rj_model *m, const rj_state *s, int j)
{
    RJ_ASSERT(j >= 0 && j < m->nj);
    return RJ__FJ(m, s->fd[s->cur], j)[RJ__JD_THETA];
}
RJDEF double rj_joint_theta(const rj_model *m, const rj_state *s, int j)
{
    return rj__mod2pi(rj_joint_theta_running(m, s, j));
}
RJDEF double rj_joint_rate(const rj_model *m, const rj_state *s, int j)
{
    RJ_ASSERT(j >= 0 && j < m->nj);
    return RJ__FJ(m, s->fd[s->cur], j)[RJ__JD_RATE];
}
RJDEF int rj_joint_flag(const rj_model *m, const rj_state *s, int j)
{
    RJ_ASSERT(j >= 0 && j < m->nj);
    return s->fi[s->cur][j];
}
RJDEF double rj_joint_torque(const rj_model *m, const rj_state *s, int j, int c)
{
    const double *jd;
    double t = 0;
    int k;
    RJ_ASSERT(j >= 0 && j < m->nj);
    RJ_ASSERT(c >= 0 && c < RJ_TORQUE_COUNT);
    jd = RJ__FJ(m, s->fd[s->cur], j);
    if (c != RJ_TORQUE_TOTAL)
        return jd[RJ__JD_TQ0 + c];
    for (k = 0; k < RJ_TORQUE_COUNT; k++)
        if (k != RJ_TORQUE_TOTAL)
            t += jd[RJ__JD_TQ0 + k];
    return t;
}
RJDEF double rj_joint_penetration(const rj_model *m, const rj_state *s, int j)
{
    const double *jd;
    int flag;
    RJ_ASSERT(j >= 0 && j < m->nj);
    jd = RJ__FJ(m, s->fd[s->cur], j);
    flag = s->fi[s->cur][j];
    if (flag == RJ_AT_FORWARD)
        return m->jnt[j].fwd - jd[RJ__JD_THETA];
    if (flag == RJ_AT_REVERSE)
        return m->jnt[j].rev - jd[RJ__JD_THETA];
    if (flag == RJ_LOCKED)
        return jd[RJ__JD_LOCK] - jd[RJ__JD_THETA];
    return 0.0;
}
RJDEF double rj_joint_latch_impulse(const rj_model *m, const rj_state *s, int j)
{
    RJ_ASSERT(j >= 0 && j < m->nj);
    return RJ__FJ(m, s->fd[s->cur], j)[RJ__JD_IMPULSE];
}
RJDEF double rj_joint_event_time(const rj_model *m, const rj_state *s, int j)
{
    RJ_ASSERT(j >= 0 && j < m->nj);
    return RJ__FJ(m, s->fd[s->cur], j)[RJ__JD_EVENT];
}
RJDEF double rj_joint_release_time(const rj_model *m, const rj_state *s, int j)
{
    RJ_ASSERT(j >= 0 && j < m->nj);
    return RJ__FJ(m, s->fd[s->cur], j)[RJ__JD_RELEASE];
}
RJDEF double rj_joint_overlap_time(const rj_model *m, const rj_state *s, int j)
{
    RJ_ASSERT(j >= 0 && j < m->nj);
    return RJ__FJ(m, s->fd[s->cur], j)[RJ__JD_OVERLAP];
}
RJDEF double rj_joint_peak_penetration(const rj_model *m, const rj_state *s, int j)
{
    RJ_ASSERT(j >= 0 && j < m->nj);
    return RJ__FJ(m, s->fd[s->cur], j)[RJ__JD_PEAKP];
}
RJDEF double rj_joint_contact_penetration(const rj_model *m, const rj_state *s, int j)
{
    RJ_ASSERT(j >= 0 && j < m->nj);
    return RJ__FJ(m, s->fd[s->cur], j)[RJ__JD_P0];
}
RJDEF void rj_state_energy(const rj_model *m, const rj_state *s, rj_energy *e)
{
    (void) m;
    e->balance = rj__accounts_read(RJ__FS(m, s->fd[s->cur]), e, &e->total);
}
RJDEF double rj_state_energy_time(const rj_state *s)
{
    return s->fd[s->cur][RJ__FS_ETIME];
}

/* ------------------------------------------------------------------ peaks */
/* A state may track the run's peaks (rj_state_track_peaks): each joint's |pin force| and
   when, each flexible link's |bending moment| and outer-fibre stress and where. They are
   taken after the steps that take the energy accounts (every step unless
   solver.energy_every > 1: then every K-th, and a peak between them is missed), from the
   loads at t^n that rj_joint_pin_forces and rj_element_loads give, into rj_state.peaks:
   per joint [|F|, t], then per link [|M|, t, element, end, stress, t, element]. */

/* The peaks from the loads at t^n of the step just taken (src/run.h), a step that took
   the accounts (their time is t^n): the pin forces', and the element loads' but in a
   model that steps in place (its steps keep only the pins' nodes at n: rj_element_loads
   has none, and peaks of the steps that do not would mislead). */
static RJ__NOINLINE void rj__track_peaks(const rj_model *m, rj_state *s)
{
    const double t = s->fd[s->cur][RJ__FS_ETIME];
    double *pins = s->peak_work + RJ__PIN_PER_LINK * ((size_t) m->nl + 1);
    int j, l, e;
    rj__pin_forces(m, s, s->peak_work, pins);
    for (j = 0; j < m->nj; j++) {
        double *pk = s->peaks + RJ__PEAK_JOINT * (size_t) j;
        const double size = sqrt(pins[2 * j] * pins[2 * j] + pins[2 * j + 1] * pins[2 * j + 1]);
        if (size > pk[0]) {
            pk[0] = size;
            pk[1] = t;
        }
    }
    for (l = 0; l < m->nl && !m->ip; l++) {
        double *pk = s->peaks + RJ__PEAK_JOINT * (size_t) m->nj + RJ__PEAK_LINK * (size_t) l;
        if (m->ldef[l].fidelity != RJ_LINK_FLEXIBLE)
            continue;
        for (e = 0; e < m->ldef[l].elements; e++) {
            double loads[5];
            int end;
            rj__element_loads(m, s, l, e, loads);
            for (end = 0; end < 2; end++)
                if (fabs(loads[2 + end]) > pk[0]) {
                    pk[0] = fabs(loads[2 + end]);
                    pk[1] = t;
                    pk[2] = e;
                    pk[3] = end;
                }
            if (loads[4] > pk[4]) {
                pk[4] = loads[4];
                pk[5] = t;
                pk[6] = e;
            }
        }
    }
}

RJDEF rj_result rj_state_track_peaks(const rj_model *m, rj_state *s, int on)
{
    RJ_ASSERT(m && s);
    if (on && !s->peaks_on)
        rj__peaks_clear(m, s);
    s->peaks_on = on != 0;
    return RJ_OK;
}

/* A peak from its record (value, time, then element and end where given: -1 else). */
static rj_peak rj__peak_of(const double *pk, int has_element, int has_end)
{
    rj_peak p;
    p.value = pk[0];
    p.time = pk[1];
    p.element = has_element && pk[0] >= 0 ? (int) pk[2] : -1;
    p.end = has_end && pk[0] >= 0 ? (int) pk[3] : -1;
    return p;
}

RJDEF rj_peak rj_joint_peak_pin_force(const rj_model *m, const rj_state *s, int joint)
{
    RJ_ASSERT(m && s && joint >= 0 && joint < m->nj);
    return rj__peak_of(s->peaks + RJ__PEAK_JOINT * (size_t) joint, 0, 0);
}

RJDEF rj_peak rj_link_peak_moment(const rj_model *m, const rj_state *s, int link)
{
    RJ_ASSERT(m && s && link >= 0 && link < m->nl);
    return rj__peak_of(s->peaks + RJ__PEAK_JOINT * (size_t) m->nj + RJ__PEAK_LINK * (size_t) link,
                       1, 1);
}

RJDEF rj_peak rj_link_peak_stress(const rj_model *m, const rj_state *s, int link)
{
    RJ_ASSERT(m && s && link >= 0 && link < m->nl);
    return rj__peak_of(
        s->peaks + RJ__PEAK_JOINT * (size_t) m->nj + RJ__PEAK_LINK * (size_t) link + 4, 1, 0);
}
/* ------------------------------------------------------------------ checkpoints */
/* Layout: "RJCK" | u32 version | u64 model hash | u64 payload bytes | payload | u64 FNV-1a
   of everything before it. Payload: steps (i64), frame doubles, frame ints, then the
   caller's inputs: whether the joint torques are on (a double, 0 or 1) and the torques
   (nj), then whether the node forces are on, the forces (3 nn) and those the last step
   applied (3 nn); then whether the peaks are tracked (a double, 0 or 1) and the peaks
   (src/peaks.h). */
#define RJ__CK_HEAD 24
/* the layout's version: 8 since the run's peaks joined the payload (7: the structural
   damping's and plastic work's accounts joined each frame's scalars) */
#define RJ__CK_VERSION 8u
/* the payload's bytes */
static size_t rj__ck_payload(const rj_model *m)
{
    return 8 + sizeof(double) * m->frame_doubles + sizeof(int) * (m->frame_ints + 1) +
           sizeof(double) * ((size_t) m->nj + 1) + sizeof(double) * (6 * (size_t) m->nn + 1) +
           sizeof(double) * (rj__peaks_count(m) + 1);
}
/* An input block's bytes: its switch (0 or 1, a double), then its count values. */
static unsigned char *rj__ck_put_inputs(unsigned char *at, int on, const double *values,
                                        size_t count)
{
    const double flag = on ? 1.0 : 0.0;
    memcpy(at, &flag, sizeof(double));
    memcpy(at + sizeof(double), values, sizeof(double) * count);
    return at + sizeof(double) * (count + 1);
}
RJDEF size_t rj_state_save(const rj_model *m, const rj_state *s, void *buf, size_t size)
{
    size_t pay = rj__ck_payload(m);
    size_t need = RJ__CK_HEAD + pay + 8;
    unsigned char *b = (unsigned char *) buf;
    unsigned char *in_bytes;
    unsigned int ver = RJ__CK_VERSION;
    unsigned long long h, pl = pay, st = (unsigned long long) s->steps;
    if (!buf || size < need)
        return need;
    memcpy(b, "RJCK", 4);
    memcpy(b + 4, &ver, 4);
    memcpy(b + 8, &m->hash, 8);
    memcpy(b + 16, &pl, 8);
    memcpy(b + RJ__CK_HEAD, &st, 8);
    memcpy(b + RJ__CK_HEAD + 8, s->fd[s->cur], sizeof(double) * m->frame_doubles);
    memcpy(b + RJ__CK_HEAD + 8 + sizeof(double) * m->frame_doubles, s->fi[s->cur],
           sizeof(int) * (m->frame_ints + 1));
    in_bytes =
        b + RJ__CK_HEAD + 8 + sizeof(double) * m->frame_doubles + sizeof(int) * (m->frame_ints + 1);
    in_bytes = rj__ck_put_inputs(in_bytes, s->inputs, s->input_torque, (size_t) m->nj);
    in_bytes = rj__ck_put_inputs(in_bytes, s->node_inputs, s->input_node, 3 * (size_t) m->nn);
    memcpy(in_bytes, s->node_applied, 3 * sizeof(double) * (size_t) m->nn);
    in_bytes += 3 * sizeof(double) * (size_t) m->nn;
    rj__ck_put_inputs(in_bytes, s->peaks_on, s->peaks, rj__peaks_count(m));
    h = rj__fnv(14695981039346656037ULL, b, RJ__CK_HEAD + pay);
    memcpy(b + RJ__CK_HEAD + pay, &h, 8);
    return need;
}
/* The steps a checkpoint may count: the counter must stay far from overflowing a long
   (32 bits on some systems) */
#define RJ__CK_MAX_STEPS 2000000000.0
/* The largest magnitude a checkpoint's value may have */
#define RJ__CK_MAX_VALUE 1e100

/* A checkpoint's frame is checked as the model validation checks a definition: every value
   finite, time and counts in range, each joint's flag one its definition allows. Returns 0
   with err filled when a value is out of range. */
static int rj__ck_frame_ok(const rj_model *m, const double *fd, const int *fi,
                           unsigned long long steps, rj_error *err)
{
    const double *sc = RJ__FS(m, fd);
    size_t k;
    int j;
    if (steps > (unsigned long long) RJ__CK_MAX_STEPS) {
        rj__fail(err, RJ_ERR_CHECKPOINT, "steps", (double) steps,
                 "checkpoint counts %.0f steps, more than the %.0f a state counts", (double) steps,
                 RJ__CK_MAX_STEPS);
        return 0;
    }
    /* every value finite and within 1e100 in magnitude: no state a model reaches comes near
       it, and sums of such values (a joint's total torque, the energy balance) stay finite */
    for (k = 0; k < m->frame_doubles; k++)
        if (!(fabs(fd[k]) <= RJ__CK_MAX_VALUE)) {
            rj__fail(err, RJ_ERR_CHECKPOINT, "payload", fd[k],
                     "checkpoint holds %g at value %lu: not finite, or beyond the 1e100 that no "
                     "state reaches",
                     fd[k], (unsigned long) k);
            return 0;
        }
    if (!(sc[RJ__FS_TIME] >= 0) || !(sc[RJ__FS_ETIME] <= sc[RJ__FS_TIME])) {
        rj__fail(err, RJ_ERR_CHECKPOINT, "time", sc[RJ__FS_TIME],
                 "checkpoint time %g s (energy time %g s) is out of range", sc[RJ__FS_TIME],
                 sc[RJ__FS_ETIME]);
        return 0;
    }
    {
        /* the accounts' sums (rj_state_energy) must be finite too, not only their terms */
        double total;
        const double balance = rj__accounts_read(sc, NULL, &total) + sc[RJ__FS_PEND];
        if (!rj__finite(total) || !rj__finite(balance)) {
            rj__fail(err, RJ_ERR_CHECKPOINT, "energy", balance,
                     "checkpoint's energy accounts do not add up to a finite total (%g) and "
                     "balance (%g)",
                     total, balance);
            return 0;
        }
    }
    if (!(sc[RJ__FS_WARN] >= 0 && sc[RJ__FS_WARN] <= RJ__CK_MAX_STEPS &&
          sc[RJ__FS_WARN] == floor(sc[RJ__FS_WARN]))) {
        rj__fail(err, RJ_ERR_CHECKPOINT, "warnings", sc[RJ__FS_WARN],
                 "checkpoint warning count %g is not a count", sc[RJ__FS_WARN]);
        return 0;
    }
    for (j = 0; j < m->nj; j++) {
        /* event times: -1 (none yet) or a time already reached; the peak penetration >= 0 */
        const double *jd = RJ__FJ(m, fd, j);
        const double times[2] = { jd[RJ__JD_EVENT], jd[RJ__JD_RELEASE] };
        int k2;
        for (k2 = 0; k2 < 2; k2++)
            if (!(times[k2] == -1 || (times[k2] >= 0 && times[k2] <= sc[RJ__FS_TIME]))) {
                rj__fail(err, RJ_ERR_CHECKPOINT, "event", times[k2],
                         "checkpoint gives joint %d an event time of %g s at t = %g s", j,
                         times[k2], sc[RJ__FS_TIME]);
                return 0;
            }
        if (!(jd[RJ__JD_PEAKP] >= 0)) {
            rj__fail(err, RJ_ERR_CHECKPOINT, "peak", jd[RJ__JD_PEAKP],
                     "checkpoint gives joint %d a peak penetration of %g rad", j, jd[RJ__JD_PEAKP]);
            return 0;
        }
    }
    for (j = 0; j < m->nj; j++) {
        const rj_joint_def *d = &m->jdef[j];
        const int flag = fi[j];
        const int ok = flag == RJ_FREE || (flag == RJ_AT_FORWARD && d->has_forward) ||
                       (flag == RJ_AT_REVERSE && d->has_reverse) ||
                       (flag == RJ_LOCKED && d->lock && (d->has_forward || d->has_reverse));
        if (ok)
            continue;
        rj__fail(err, RJ_ERR_CHECKPOINT, "flag", flag,
                 "checkpoint gives joint %d the flag %d, which its definition does not allow", j,
                 flag);
        return 0;
    }
    return 1;
}

/* The int after the joints' flags is spare and always 0: a checkpoint with anything else
   there was not written by rj_state_save. */
static int rj__ck_spare_ok(const rj_model *m, const int *fi, rj_error *err)
{
    if (fi[m->frame_ints] == 0)
        return 1;
    rj__fail(err, RJ_ERR_CHECKPOINT, "payload", fi[m->frame_ints],
             "checkpoint holds %d in its spare slot, which rj_state_save leaves 0",
             fi[m->frame_ints]);
    return 0;
}

/* A checkpoint's input block (rj__ck_put_inputs): the switch 0 or 1, each value finite
   within 1e100. field names the block (and the switch: field with "s" after it). */
static int rj__ck_input_block_ok(const unsigned char *at, size_t count, const char *field,
                                 const char *what, rj_error *err)
{
    static const double off = 0.0, on = 1.0;
    double v;
    size_t k;
    memcpy(&v, at, sizeof(double));
    /* the very bytes of 0 or 1 (not -0), so that a loaded state saves back the same bytes */
    if (memcmp(at, &off, sizeof off) != 0 && memcmp(at, &on, sizeof on) != 0) {
        rj__fail(err, RJ_ERR_CHECKPOINT, "inputs", v,
                 "checkpoint's switch of the %ss is %g, not 0 or 1", what, v);
        return 0;
    }
    for (k = 0; k < count; k++) {
        memcpy(&v, at + sizeof(double) * (k + 1), sizeof(double));
        if (!(fabs(v) <= RJ__CK_MAX_VALUE)) {
            rj__fail(err, RJ_ERR_CHECKPOINT, field, v,
                     "checkpoint's %s %lu is %g: not finite within 1e100", what, (unsigned long) k,
                     v);
            return 0;
        }
    }
    return 1;
}
/* Where the checkpoint's peaks block starts, after the inputs'. */
static const unsigned char *rj__ck_peaks_at(const rj_model *m, const unsigned char *in_bytes)
{
    return in_bytes + sizeof(double) * ((size_t) m->nj + 1 + 6 * (size_t) m->nn + 1);
}

/* A link's peak record: none (-1) or a magnitude with an element the link has and an end
   0 or 1 (they become ints). */
static int rj__ck_link_peak_ok(const rj_model *m, int l, const double *pk)
{
    const double ne = m->ldef[l].elements;
    const int moment = pk[0] < 0 || (pk[2] == floor(pk[2]) && pk[2] >= 0 && pk[2] < ne &&
                                      (pk[3] == 0 || pk[3] == 1));
    const int stress = pk[4] < 0 || (pk[6] == floor(pk[6]) && pk[6] >= 0 && pk[6] < ne);
    return moment && stress;
}

/* The checkpoint's peaks: a switch and finite values, each link's elements its own. */
static int rj__ck_peaks_ok(const rj_model *m, const unsigned char *at, rj_error *err)
{
    double pk[RJ__PEAK_LINK];
    int l;
    if (!rj__ck_input_block_ok(at, rj__peaks_count(m), "peaks", "peak", err))
        return 0;
    for (l = 0; l < m->nl; l++) {
        const size_t k = 1 + RJ__PEAK_JOINT * (size_t) m->nj + RJ__PEAK_LINK * (size_t) l;
        memcpy(pk, at + sizeof(double) * k, sizeof pk);
        if (!rj__ck_link_peak_ok(m, l, pk)) {
            rj__fail(err, RJ_ERR_CHECKPOINT, "peaks", l,
                     "checkpoint's peaks of link %d name element %g, end %g: not one the "
                     "link has",
                     l, pk[2], pk[3]);
            return 0;
        }
    }
    return 1;
}

/* The checkpoint's inputs: the joint torques' block, then the node forces', then the
   peaks'. */
static int rj__ck_inputs_ok(const rj_model *m, const unsigned char *in_bytes, rj_error *err)
{
    const size_t nj = (size_t) m->nj;
    return rj__ck_input_block_ok(in_bytes, nj, "input_torque", "input torque", err) &&
           rj__ck_input_block_ok(in_bytes + sizeof(double) * (nj + 1), 6 * (size_t) m->nn,
                                 "input_node", "input node force", err) &&
           rj__ck_peaks_ok(m, rj__ck_peaks_at(m, in_bytes), err);
}
static void rj__ck_inputs_load(const rj_model *m, rj_state *s, const unsigned char *in_bytes)
{
    const size_t nj = (size_t) m->nj;
    const unsigned char *node_bytes = in_bytes + sizeof(double) * (nj + 1);
    double v;
    memcpy(&v, in_bytes, sizeof(double));
    s->inputs = v == 1;
    memcpy(s->input_torque, in_bytes + sizeof(double), sizeof(double) * nj);
    memcpy(&v, node_bytes, sizeof(double));
    s->node_inputs = v == 1;
    memcpy(s->input_node, node_bytes + sizeof(double), 3 * sizeof(double) * (size_t) m->nn);
    memcpy(s->node_applied, node_bytes + sizeof(double) * (3 * (size_t) m->nn + 1),
           3 * sizeof(double) * (size_t) m->nn);
    memcpy(&v, rj__ck_peaks_at(m, in_bytes), sizeof(double));
    s->peaks_on = v == 1;
    memcpy(s->peaks, rj__ck_peaks_at(m, in_bytes) + sizeof(double),
           sizeof(double) * rj__peaks_count(m));
}

RJDEF rj_result rj_state_load(const rj_model *m, rj_state *s, const void *buf, size_t size,
                              rj_error *err)
{
    const size_t pay = rj__ck_payload(m);
    const size_t need = RJ__CK_HEAD + pay + 8;
    const unsigned char *b = (const unsigned char *) buf;
    const unsigned char *fd_bytes = b + RJ__CK_HEAD + 8;
    const unsigned char *fi_bytes = fd_bytes + sizeof(double) * m->frame_doubles;
    const unsigned char *in_bytes = fi_bytes + sizeof(int) * (m->frame_ints + 1);
    unsigned int ver;
    unsigned long long h, hh, mh, pl, st;
    /* the header first: a checkpoint of another model (or none) is told apart from a cut one */
    if (!buf || size < RJ__CK_HEAD) {
        rj__fail(err, RJ_ERR_CHECKPOINT, "size", (double) size,
                 "checkpoint of %lu bytes is truncated: this model's checkpoints are %lu bytes",
                 (unsigned long) size, (unsigned long) need);
        return RJ_ERR_CHECKPOINT;
    }
    if (memcmp(b, "RJCK", 4) != 0) {
        rj__fail(err, RJ_ERR_CHECKPOINT, "magic", 0, "not a revjoint checkpoint (bad magic)");
        return RJ_ERR_CHECKPOINT;
    }
    memcpy(&ver, b + 4, 4);
    memcpy(&mh, b + 8, 8);
    memcpy(&pl, b + 16, 8);
    if (ver != RJ__CK_VERSION) {
        rj__fail(err, RJ_ERR_CHECKPOINT, "version", ver,
                 "checkpoint version %u is not supported (%u: the run's peaks joined the "
                 "payload)",
                 ver, RJ__CK_VERSION);
        return RJ_ERR_CHECKPOINT;
    }
    if (mh != m->hash || pl != pay) {
        rj__fail(err, RJ_ERR_CHECKPOINT, "model", 0,
                 "checkpoint is for another model (its definitions, step or size differ from this "
                 "model's)");
        return RJ_ERR_CHECKPOINT;
    }
    if (size < need) {
        rj__fail(err, RJ_ERR_CHECKPOINT, "size", (double) size,
                 "checkpoint of %lu bytes is truncated: this model's checkpoints are %lu bytes",
                 (unsigned long) size, (unsigned long) need);
        return RJ_ERR_CHECKPOINT;
    }
    if (size > need) {
        rj__fail(err, RJ_ERR_CHECKPOINT, "size", (double) size,
                 "checkpoint of %lu bytes has %lu bytes after its end: this model's checkpoints "
                 "are %lu bytes",
                 (unsigned long) size, (unsigned long) (size - need), (unsigned long) need);
        return RJ_ERR_CHECKPOINT;
    }
    memcpy(&hh, b + RJ__CK_HEAD + pay, 8);
    h = rj__fnv(14695981039346656037ULL, b, RJ__CK_HEAD + pay);
    if (h != hh) {
        rj__fail(err, RJ_ERR_CHECKPOINT, "checksum", 0,
                 "checkpoint is corrupted (checksum mismatch)");
        return RJ_ERR_CHECKPOINT;
    }
    memcpy(&st, b + RJ__CK_HEAD, 8);
    /* the checksum is no seal: every value is checked before the state changes, in the
       frame that is not current (a failed load leaves the state as it was) */
    {
        const int spare = 1 - s->cur;
        memcpy(s->fd[spare], fd_bytes, sizeof(double) * m->frame_doubles);
        memcpy(s->fi[spare], fi_bytes, sizeof(int) * (m->frame_ints + 1));
        if (!rj__ck_frame_ok(m, s->fd[spare], s->fi[spare], st, err) ||
            !rj__ck_spare_ok(m, s->fi[spare], err) || !rj__ck_inputs_ok(m, in_bytes, err)) {
            s->snap = -1; /* in place the spare frame held the rollback copy: take a new one */
            return RJ_ERR_CHECKPOINT;
        }
        s->cur = spare;
        rj__ck_inputs_load(m, s, in_bytes);
    }
    s->snap = -1;
    s->steps = (long) st;
    s->at_n = RJ__AT_N_NONE;
    s->loop_force[2 * m->nj] = -1; /* not in a checkpoint: known again after a step */
    s->err[0] = 0;
    s->warn[0] = 0;
    return RJ_OK;
}
/* ------------------------------------------------------------------ scene files */
#ifndef RJ_NO_SCENE_FILES
#include <string.h>
#include <stdlib.h>
#include <math.h>
#include <stdio.h>
#include <errno.h>

enum {
    RJ__SK_NONE,
    RJ__SK_SOLVER,
    RJ__SK_MATERIAL,
    RJ__SK_SECTION,
    RJ__SK_LINK,
    RJ__SK_JOINT,
    RJ__SK_LOAD,
    RJ__SK_ACTUATOR,
    RJ__SK_COUPLING,
    RJ__SK_COUNT
};

/* char arrays, not pointer arrays: read-only data without relocations */
static const char rj__sk_kind[RJ__SK_COUNT][10] = { "",     "solver", "material", "section",
                                                    "link", "joint",  "load",     "actuator",
                                                    "coupling" };
#define RJ__SK_MAT_KEYS                                                                            \
    ((1u << RJ__LK_E) | (1u << RJ__LK_RHO) | (1u << RJ__LK_ETA) | (1u << RJ__LK_DAMPING) |        \
     (1u << RJ__LK_MASS_DAMPING) | (1u << RJ__LK_YIELD) | (1u << RJ__LK_HARDENING) |              \
     (1u << RJ__LK_STRAIN))
#define RJ__SK_SEC_KEYS                                                                            \
    ((1u << RJ__LK_AREA) | (1u << RJ__LK_INERTIA) | (1u << RJ__LK_WIDTH) | (1u << RJ__LK_HEIGHT) | \
     (1u << RJ__LK_LAYERS))

typedef struct rj__stok {
    const char *s;
    int len, line, col;
    char kind;
} rj__stok; /* kind 'w', '=', ',' or 'q' (a quoted string, quotes included) */

/* a material or a section: a partial link definition */
typedef struct rj__spart {
    char name[RJ_SCENE_NAME_MAX];
    rj_link_def d;
    unsigned mask;
    rj_scene_pos pos[1 + RJ__LK_N];
} rj__spart;

typedef struct rj__sp {
    const char *text, *fname;
    size_t len, at;
    int lineno;
    rj_error *err;
    char dp[8]; /* the C library's decimal point in the current locale */
    int dplen;
    rj__stok *tok;
    int ntok;
    rj_scene_file *f;
    int cap_links, cap_joints, cap_loads, cap_acts, cap_cps;
    rj__spart *mat, *sec;
    int nmat, nsec, cap_mat, cap_sec;
    int kind, item; /* current section: kind and index (materials, sections, links, joints) */
    unsigned seen;  /* keys set in the current section */
    int link_mat, link_sec; /* current link's material and section, -1 none */
    int solver_seen;
    int title_line;              /* line of the title statement, 0 none yet */
    char where[80], forkey[128]; /* message pieces */
    rj_result code;              /* of the first error */
    const char *const *sets;     /* rj_scene_parse_set's changes, each taken at its section's end */
    int nsets;
    unsigned long long sets_done; /* bit k: sets[k] taken */
    rj__stok *set_tok;            /* their tokens */
    unsigned char pieces[RJ_SCENE_MAX_LINKS]; /* link k says fidelity = pieces (rj__sp_cut) */
} rj__sp;

/* ------------------------------------------------------------------ small helpers */
static double rj__sp_nan(void)
{
    return strtod("nan", NULL);
}

static void rj__sp_locale(char *dp, int *dplen)
{
    char t[16];
    int n = snprintf(t, sizeof t, "%.1f", 1.5), k;
    *dplen = 0;
    if (n >= 3 && n - 2 < 7)
        for (k = 1; k < n - 1; k++)
            dp[(*dplen)++] = t[k];
    if (*dplen == 0) {
        dp[0] = '.';
        *dplen = 1;
    }
    dp[*dplen] = 0;
}

/* strict decimal number: [+-]? (d+ (. d*)? | . d+) ([eE] [+-]? d+)?
   returns 1 ok, 0 malformed, -1 nan/inf spelled out, -2 out of range, -3 too long */
static int rj__sp_strtonum(const char *s, int n, const char *dp, int dplen, double *out)
{
    char buf[160];
    int i = 0, digits = 0, k, o = 0;
    double v;
    char *end;
    if (n <= 0)
        return 0;
    {
        int j = (s[0] == '+' || s[0] == '-') ? 1 : 0, m = n - j;
        const char *w = s + j;
        if ((m == 3 || m == 8) &&
            (((w[0] | 32) == 'i' && (w[1] | 32) == 'n' && (w[2] | 32) == 'f') ||
             (m == 3 && (w[0] | 32) == 'n' && (w[1] | 32) == 'a' && (w[2] | 32) == 'n'))) {
            if (m == 3)
                return -1;
            if (((w[3] | 32) == 'i' && (w[4] | 32) == 'n' && (w[5] | 32) == 'i' &&
                 (w[6] | 32) == 't' && (w[7] | 32) == 'y'))
                return -1;
        }
    }
    if (s[i] == '+' || s[i] == '-')
        i++;
    while (i < n && s[i] >= '0' && s[i] <= '9') {
        i++;
        digits++;
    }
    if (i < n && s[i] == '.') {
        i++;
        while (i < n && s[i] >= '0' && s[i] <= '9') {
            i++;
            digits++;
        }
    }
    if (!digits)
        return 0;
    if (i < n && (s[i] == 'e' || s[i] == 'E')) {
        int ed = 0;
        i++;
        if (i < n && (s[i] == '+' || s[i] == '-'))
            i++;
        while (i < n && s[i] >= '0' && s[i] <= '9') {
            i++;
            ed++;
        }
        if (!ed)
            return 0;
    }
    if (i != n)
        return 0;
    if (n + dplen >= (int) sizeof buf)
        return -3;
    for (k = 0; k < n; k++) {
        if (s[k] == '.') {
            memcpy(buf + o, dp, (size_t) dplen);
            o += dplen;
        } else
            buf[o++] = s[k];
    }
    buf[o] = 0;
    v = strtod(buf, &end);
    if (end != buf + o)
        return 0;
    if (!(v == v) || v - v != 0.0)
        return -2;
    *out = v;
    return 1;
}

/* strict integer: [+-]? d+ ; returns 1 ok, 0 malformed, -2 beyond +-2e9 */
static int rj__sp_strtoint(const char *s, int n, int *out)
{
    int i = 0, neg = 0, big = 0;
    long v = 0;
    if (n <= 0)
        return 0;
    if (s[0] == '+' || s[0] == '-') {
        neg = s[0] == '-';
        i = 1;
    }
    if (i == n)
        return 0;
    for (; i < n; i++) {
        if (s[i] < '0' || s[i] > '9')
            return 0;
        if (v > 200000000L)
            big = 1;
        else
            v = v * 10 + (s[i] - '0');
    }
    if (big || v > 2000000000L)
        return -2;
    *out = (int) (neg ? -v : v);
    return 1;
}

/* text for messages: at most 40 characters, control and non-ASCII bytes as \xNN */
static void rj__sp_quote(char *dst, size_t size, const char *s, int n)
{
    size_t o = 0;
    int i;
    for (i = 0; i < n && o + 5 < size; i++) {
        unsigned char c = (unsigned char) s[i];
        if (i >= 40) {
            if (o + 4 < size) {
                memcpy(dst + o, "...", 3);
                o += 3;
            }
            break;
        }
        if (c < 0x20 || c >= 0x7f) {
            snprintf(dst + o, size - o, "\\x%02x", c);
            o += 4;
        } else
            dst[o++] = (char) c;
    }
    dst[o < size ? o : size - 1] = 0;
}

/* message builder: concatenates up to 7 pieces (NULL skipped) into dst, truncating */
static void rj__sp_cat(char *dst, size_t size, const char *a, const char *b, const char *c,
                       const char *d, const char *e, const char *f, const char *g)
{
    const char *pc[7];
    size_t o = 0;
    int k;
    pc[0] = a;
    pc[1] = b;
    pc[2] = c;
    pc[3] = d;
    pc[4] = e;
    pc[5] = f;
    pc[6] = g;
    if (!size)
        return;
    for (k = 0; k < 7; k++) {
        size_t n, room;
        if (!pc[k])
            continue;
        n = strlen(pc[k]);
        room = size - 1 - o;
        if (n > room)
            n = room;
        memcpy(dst + o, pc[k], n);
        o += n;
    }
    dst[o] = 0;
}

static const char *rj__sp_itoa(char *buf, long v) /* buf: 24 bytes */
{
    snprintf(buf, 24, "%ld", v);
    return buf;
}

static int rj__sp_fail(rj__sp *P, int line, int col, const char *key, double value, const char *msg)
{
    char l[24], c[24];
    P->code = RJ_ERR_PARSE;
    if (P->err) {
        P->err->code = RJ_ERR_PARSE;
        rj__sp_cat(P->err->field, sizeof P->err->field, key, NULL, NULL, NULL, NULL, NULL, NULL);
        P->err->value = value;
        rj__sp_cat(P->err->msg, sizeof P->err->msg, P->fname, ":", rj__sp_itoa(l, line), ":",
                   rj__sp_itoa(c, col), ": ", msg);
    }
    return 0;
}

/* msg = a b c d e */
static int rj__sp_err(rj__sp *P, int line, int col, const char *key, double value, const char *a,
                      const char *b, const char *c, const char *d, const char *e)
{
    char m[256];
    rj__sp_cat(m, sizeof m, a, b, c, d, e, NULL, NULL);
    return rj__sp_fail(P, line, col, key, value, m);
}

/* msg = pre 'token text' b c d e */
static int rj__sp_err_tok5(rj__sp *P, const rj__stok *t, const char *key, double value,
                           const char *pre, const char *b, const char *c, const char *d,
                           const char *e)
{
    char q[200], m1[256], m[256];
    rj__sp_quote(q, sizeof q, t->s, t->len);
    rj__sp_cat(m1, sizeof m1, pre, "'", q, "'", NULL, NULL, NULL);
    rj__sp_cat(m, sizeof m, m1, b, c, d, e, NULL, NULL);
    return rj__sp_fail(P, t->line, t->col, key, value, m);
}

/* msg = pre 'token text' b c d */
static int rj__sp_err_tok(rj__sp *P, const rj__stok *t, const char *key, double value,
                          const char *pre, const char *b, const char *c, const char *d)
{
    char q[200], m[256];
    rj__sp_quote(q, sizeof q, t->s, t->len);
    rj__sp_cat(m, sizeof m, pre, "'", q, "'", b, c, d);
    return rj__sp_fail(P, t->line, t->col, key, value, m);
}

static const char *rj__sp_item_name(const rj__sp *P)
{
    switch (P->kind) {
    case RJ__SK_MATERIAL:
        return P->mat[P->item].name;
    case RJ__SK_SECTION:
        return P->sec[P->item].name;
    case RJ__SK_LINK:
        return P->f->link_names[P->item];
    case RJ__SK_JOINT:
        return P->f->joint_names[P->item];
    case RJ__SK_LOAD:
        return P->f->load_names[P->item];
    case RJ__SK_ACTUATOR:
        return P->f->actuator_names[P->item];
    case RJ__SK_COUPLING:
        return P->f->coupling_names[P->item];
    }
    return "";
}

/* " in link 'arm1'" for messages, into P->where */
static const char *rj__sp_where(rj__sp *P)
{
    if (P->kind == RJ__SK_SOLVER)
        rj__sp_cat(P->where, sizeof P->where, " in solver", NULL, NULL, NULL, NULL, NULL, NULL);
    else if (P->kind == RJ__SK_NONE)
        P->where[0] = 0;
    else
        rj__sp_cat(P->where, sizeof P->where, " in ", rj__sk_kind[P->kind], " '",
                   rj__sp_item_name(P), "'", NULL, NULL);
    return P->where;
}

/* " for 'key' in link 'arm1'" into P->forkey */
static const char *rj__sp_for(rj__sp *P, const char *key)
{
    rj__sp_cat(P->forkey, sizeof P->forkey, " for '", key, "'", rj__sp_where(P), NULL, NULL, NULL);
    return P->forkey;
}

static int rj__sp_is(const rj__stok *t, const char *s)
{
    size_t n = strlen(s);
    return t->kind == 'w' && (size_t) t->len == n && memcmp(t->s, s, n) == 0;
}

static int rj__sp_name_ok(const char *s, int n)
{
    int i;
    if (n < 1 || n >= RJ_SCENE_NAME_MAX)
        return 0;
    for (i = 0; i < n; i++) {
        char c = s[i];
        int alpha = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_';
        int other = (c >= '0' && c <= '9') || c == '.' || c == '-';
        if (!alpha && !(i > 0 && other))
            return 0;
    }
    return 1;
}

static rj_scene_pos *rj__sp_pos(rj__sp *P, int k) /* position slot of key k of the current item */
{
    switch (P->kind) {
    case RJ__SK_SOLVER:
        return &P->f->solver_pos_[1 + k];
    case RJ__SK_MATERIAL:
        return &P->mat[P->item].pos[1 + k];
    case RJ__SK_SECTION:
        return &P->sec[P->item].pos[1 + k];
    case RJ__SK_LINK:
        return &P->f->link_pos_[(size_t) P->item * (1 + RJ__LK_N) + 1 + k];
    case RJ__SK_LOAD:
        return &P->f->load_pos_[(size_t) P->item * (1 + RJ__AK_N) + 1 + k];
    case RJ__SK_ACTUATOR:
        return &P->f->actuator_pos_[(size_t) P->item * (1 + RJ__CK_N) + 1 + k];
    case RJ__SK_COUPLING:
        return &P->f->coupling_pos_[(size_t) P->item * (1 + RJ__PK_N) + 1 + k];
    default:
        return &P->f->joint_pos_[(size_t) P->item * (1 + RJ__JK_N) + 1 + k];
    }
}

/* ------------------------------------------------------------------ suggestions */
static int rj__sp_lower(int c)
{
    return c >= 'A' && c <= 'Z' ? c + ('a' - 'A') : c;
}

/* edit distance of s[0..n) and b, ignoring case: insertions, deletions, substitutions and
   swaps of two neighbours (optimal string alignment), so 'lenght' is 1 from 'length'.
   99 when the lengths differ by more than 2 (never near enough to suggest). */
static int rj__sp_dist(const char *s, int n, const char *b)
{
    int m = (int) strlen(b), r[3][RJ_SCENE_NAME_MAX + 2], i, j;
    if (n - m > 2 || m - n > 2 || m > RJ_SCENE_NAME_MAX)
        return 99;
    for (j = 0; j <= m; j++)
        r[0][j] = j;
    for (i = 1; i <= n; i++) {
        int *cur = r[i % 3], *up = r[(i + 2) % 3], *up2 = r[(i + 1) % 3];
        int ca = rj__sp_lower((unsigned char) s[i - 1]);
        cur[0] = i;
        for (j = 1; j <= m; j++) {
            int cb = rj__sp_lower((unsigned char) b[j - 1]), v = up[j - 1] + (ca != cb);
            if (up[j] + 1 < v)
                v = up[j] + 1;
            if (cur[j - 1] + 1 < v)
                v = cur[j - 1] + 1;
            if (i > 1 && j > 1 && ca == rj__sp_lower((unsigned char) b[j - 2]) &&
                rj__sp_lower((unsigned char) s[i - 2]) == cb && up2[j - 2] + 1 < v)
                v = up2[j - 2] + 1;
            cur[j] = v;
        }
    }
    return r[n % 3][m];
}

/* The nearest so far (*best at *bd edits, *ties others as near) with name nm also
   weighed: a suggestion must be within 2 edits of a name of 5 or more characters, 1 of 3
   or 4, and differ only in case from a shorter one. */
static void rj__sp_weigh(const char *s, int n, const char *nm, const char **best, int *bd,
                         int *ties)
{
    const int len = (int) strlen(nm), lim = len >= 5 ? 2 : len >= 3 ? 1 : 0;
    const int d = rj__sp_dist(s, n, nm);
    if (d > lim || d > *bd)
        return;
    if (d == *bd) {
        (*ties)++;
        return;
    }
    *best = nm;
    *bd = d;
    *ties = 0;
}

/* The name among names[k] (stride apart, k < count) nearest to s[0..n), or NULL when none
   is near (rj__sp_weigh) or two are as near (a tie suggests nothing rather than a guess). */
static const char *rj__sp_near(const char *s, int n, const char *names, size_t stride, int count)
{
    const char *best = NULL;
    int k, bd = 99, ties = 0;
    for (k = 0; k < count; k++)
        rj__sp_weigh(s, n, names + stride * (size_t) k, &best, &bd, &ties);
    return ties ? NULL : best;
}

/* The same among the keys of rows (the first count; for k < 32 only those in mask). */
static const char *rj__sp_near_row(const char *s, int n, const rj__field *rows, int count,
                                   unsigned mask)
{
    const char *best = NULL;
    int k, bd = 99, ties = 0;
    for (k = 0; k < count; k++)
        if (k >= 32 || (mask >> k & 1u))
            rj__sp_weigh(s, n, rows[k].key, &best, &bd, &ties);
    return ties ? NULL : best;
}

/* the key of the current section nearest to t (rj__sp_near_row), NULL when none is */
static const char *rj__sp_near_key(const rj__sp *P, const rj__stok *t)
{
    switch (P->kind) {
    case RJ__SK_SOLVER:
        return rj__sp_near_row(t->s, t->len, rj__solver_fields, RJ__VK_N, ~0u);
    case RJ__SK_JOINT:
        return rj__sp_near_row(t->s, t->len, rj__joint_fields, RJ__JK_N, ~0u);
    case RJ__SK_MATERIAL:
        return rj__sp_near_row(t->s, t->len, rj__link_fields, RJ__LK_N, RJ__SK_MAT_KEYS);
    case RJ__SK_SECTION:
        return rj__sp_near_row(t->s, t->len, rj__link_fields, RJ__LK_N, RJ__SK_SEC_KEYS);
    case RJ__SK_LINK:
        return rj__sp_near_row(t->s, t->len, rj__link_fields, RJ__LK_N, ~0u);
    case RJ__SK_LOAD:
        return rj__sp_near_row(t->s, t->len, rj__load_fields, RJ__AK_N, ~0u);
    case RJ__SK_ACTUATOR:
        return rj__sp_near_row(t->s, t->len, rj__actuator_fields, RJ__CK_N, ~0u);
    case RJ__SK_COUPLING:
        return rj__sp_near_row(t->s, t->len, rj__coupling_fields, RJ__PK_N, ~0u);
    }
    return NULL;
}

/* "; did you mean 'name'?" into buf (buf: 48 bytes), "" when name is NULL */
static const char *rj__sp_mean(char *buf, const char *name)
{
    buf[0] = 0;
    if (name)
        rj__sp_cat(buf, 48, "; did you mean '", name, "'?", NULL, NULL, NULL, NULL);
    return buf;
}

/* ------------------------------------------------------------------ unit words
   Numbers are SI without a unit ("length = 1", not "1 m"); only angles and rates take one.
   A unit word after a number, or glued to it, gets a message that says so. */
static int rj__sp_alpha(unsigned char c)
{
    return ((c | 32) >= 'a' && (c | 32) <= 'z') || c >= 0x80;
}

/* the SI unit of key (a key of any section's rows), "" when it has none */
static const char *rj__sp_unit(const char *key)
{
    int kind, n, k;
    for (kind = RJ__DEF_LINK; kind <= RJ__DEF_COUPLING; kind++) {
        const rj__field *t = rj__fields(kind, &n);
        for (k = 0; k < n; k++)
            if (strcmp(key, t[k].key) == 0)
                return t[k].unit;
    }
    return "";
}

/* the end of the number that starts t when a word is glued to it ("1mm" -> 1), else 0 */
static int rj__sp_glued(const rj__sp *P, const rj__stok *t)
{
    int p;
    double x;
    for (p = t->len - 1; p > 0; p--)
        if (rj__sp_alpha((unsigned char) t->s[p]) &&
            rj__sp_strtonum(t->s, p, P->dp, P->dplen, &x) == 1)
            return p;
    return 0;
}

/* why the word w after the number num is wrong, into buf (200 bytes): what the key takes,
   and for a prefixed SI unit the number to write ("E is in Pa: write 70e9 for 70 GPa") */
static const char *rj__sp_unit_hint(char *buf, const char *what, const char *unit, const char *num,
                                    int nn, const char *w, int wn)
{
    static const char pre[8] = "GMkcmun",
                      ex[7][4] = { "e9", "e6", "e3", "e-2", "e-3", "e-6", "e-9" };
    char q[200], u[200], t[200];
    const char *p = w[0] ? strchr(pre, w[0]) : NULL;
    int ul = (int) strlen(unit);
    rj__sp_quote(q, sizeof q, num, nn);
    rj__sp_quote(u, sizeof u, w, wn);
    if (strcmp(unit, "rad") == 0 || strcmp(unit, "rad/s") == 0) {
        rj__sp_cat(t, sizeof t, "'", q, ul == 3 ? " deg' or '" : " deg/s' or '", q,
                   ul == 3 ? " rad'" : " rad/s'", NULL, NULL);
        rj__sp_cat(buf, 200,
                   ul == 3 ? ": an angle is a number in rad, or a number and deg or rad: "
                           : ": a rate is a number in rad/s, or a number and deg/s or rad/s: ",
                   t, NULL, NULL, NULL, NULL, NULL);
        return buf;
    }
    t[0] = 0;
    if (ul && wn == ul && memcmp(w, unit, (size_t) ul) == 0)
        rj__sp_cat(t, sizeof t, " is in ", unit, " already: write ", q, NULL, NULL, NULL);
    else if (ul && p && wn == ul + 1 && memcmp(w + 1, unit, (size_t) ul) == 0 &&
             !memchr(num, 'e', (size_t) nn) && !memchr(num, 'E', (size_t) nn)) {
        char n2[220];
        rj__sp_cat(n2, sizeof n2, q, ex[p - pre], " for ", q, " ", u, NULL);
        rj__sp_cat(t, sizeof t, " is in ", unit, ": write ", n2, NULL, NULL, NULL);
    } else if (ul)
        rj__sp_cat(t, sizeof t, " is in ", unit, NULL, NULL, NULL, NULL, NULL);
    rj__sp_cat(buf, 200, ": quantities are plain numbers in SI units, without a unit word",
               ul ? " (" : "", ul ? what : "", t, ul ? ")" : "", NULL, NULL);
    return buf;
}

/* ------------------------------------------------------------------ values */
/* a number that did not read (r from rj__sp_strtonum); unit: what key takes, for the hint */
static int rj__sp_num_err(rj__sp *P, const rj__stok *t, const char *key, int r, const char *unit)
{
    char h[200];
    int p = r == 0 ? rj__sp_glued(P, t) : 0;
    h[0] = 0;
    if (p)
        rj__sp_unit_hint(h, key, unit, t->s, p, t->s + p, t->len - p);
    return rj__sp_err_tok(P, t, key, rj__sp_nan(),
                          r == -1   ? "not a finite number: "
                          : r == -2 ? "number out of range: "
                          : r == -3 ? "number too long: "
                                    : "malformed number ",
                          rj__sp_for(P, key), h, NULL);
}

static int rj__sp_num(rj__sp *P, const rj__stok *t, const char *key, double *out)
{
    int r;
    if (t->kind != 'w')
        return rj__sp_err_tok(P, t, key, rj__sp_nan(), "expected a number, found ",
                              rj__sp_for(P, key), NULL, NULL);
    r = rj__sp_strtonum(t->s, t->len, P->dp, P->dplen, out);
    if (r == 1)
        return 1;
    return rj__sp_num_err(P, t, key, r, rj__sp_unit(key));
}

/* an int in lo..hi; out of range, the sentence rule (NULL: "must be lo..hi") */
static int rj__sp_int(rj__sp *P, const rj__stok *t, const char *key, int lo, int hi,
                      const char *rule, int *out)
{
    char a[24], b[24], q[200], m[256], m2[256];
    int v = 0, r = t->kind == 'w' ? rj__sp_strtoint(t->s, t->len, &v) : 0;
    if (r == 1 && v >= lo && v <= hi) {
        *out = v;
        return 1;
    }
    if (r == 1 || r == -2) {
        rj__sp_quote(q, sizeof q, t->s, t->len);
        rj__sp_cat(m, sizeof m, key, " = ", q, " is out of range", rj__sp_where(P), ": ", NULL);
        if (rule)
            rj__sp_cat(m2, sizeof m2, m, rule, NULL, NULL, NULL, NULL, NULL);
        else
            rj__sp_cat(m2, sizeof m2, m, "must be ", rj__sp_itoa(a, lo), "..", rj__sp_itoa(b, hi),
                       NULL, NULL);
        return rj__sp_fail(P, t->line, t->col, key, r == 1 ? (double) v : rj__sp_nan(), m2);
    }
    return rj__sp_err_tok(P, t, key, rj__sp_nan(), "expected an integer, found ",
                          rj__sp_for(P, key), NULL, NULL);
}

/* a value with an optional unit: "1.5", "90 deg", "90deg"; units are "deg"/"rad" (angles)
   or "deg/s"/"rad/s" (rates), rad when none. Reads toks[*i..b), advances *i. */
static int rj__sp_angle(rj__sp *P, int *i, int b, const char *key, int rate, double *out)
{
    const rj__stok *t = &P->tok[*i];
    const char *ud = rate ? "deg/s" : "deg", *ur = rate ? "rad/s" : "rad";
    int ul = rate ? 5 : 3;
    double v;
    if (t->kind == 'w' && rj__sp_strtonum(t->s, t->len, P->dp, P->dplen, &v) == 1) {
        (*i)++;
        if (*i < b && P->tok[*i].kind == 'w') {
            const rj__stok *u = &P->tok[*i];
            if (rj__sp_is(u, ud)) {
                v = rj_rad(v);
                (*i)++;
            } else if (rj__sp_is(u, ur))
                (*i)++;
            else if ((u->s[0] >= 'a' && u->s[0] <= 'z') || (u->s[0] >= 'A' && u->s[0] <= 'Z'))
                return rj__sp_err_tok(P, u, key, v, "unknown unit ", rj__sp_for(P, key),
                                      rate ? " (deg/s or rad/s)" : " (deg or rad)", NULL);
        }
        if (!(v - v == 0.0))
            return rj__sp_err_tok(P, t, key, rj__sp_nan(),
                                  "number out of range: ", rj__sp_for(P, key), NULL, NULL);
        *out = v;
        return 1;
    }
    /* unit glued to the number */
    if (t->kind == 'w' && t->len > ul) {
        int isd = memcmp(t->s + t->len - ul, ud, (size_t) ul) == 0,
            isr = memcmp(t->s + t->len - ul, ur, (size_t) ul) == 0;
        if ((isd || isr) && rj__sp_strtonum(t->s, t->len - ul, P->dp, P->dplen, &v) == 1) {
            if (isd)
                v = rj_rad(v);
            if (!(v - v == 0.0))
                return rj__sp_err_tok(P, t, key, rj__sp_nan(),
                                      "number out of range: ", rj__sp_for(P, key), NULL, NULL);
            (*i)++;
            *out = v;
            return 1;
        }
    }
    if (t->kind != 'w')
        return rj__sp_num(P, t, key, &v); /* reports the right error */
    return rj__sp_num_err(P, t, key, rj__sp_strtonum(t->s, t->len, P->dp, P->dplen, &v),
                          rate ? "rad/s" : "rad");
}

/* range check on an already parsed value; the message shows the text of toks[a..e) */
static int rj__sp_range(rj__sp *P, int a, int e, const char *key, double v, int ok,
                        const char *rule)
{
    char q[200], m[256];
    const rj__stok *t = &P->tok[a], *z = &P->tok[e - 1];
    if (ok)
        return 1;
    if (z->line == t->line && z->s >= t->s)
        rj__sp_quote(q, sizeof q, t->s, (int) (z->s + z->len - t->s));
    else
        rj__sp_quote(q, sizeof q, t->s, t->len);
    rj__sp_cat(m, sizeof m, key, " = ", q, " is out of range", rj__sp_where(P), ": ", rule);
    return rj__sp_fail(P, t->line, t->col, key, v, m);
}

static int rj__sp_enum(rj__sp *P, const rj__stok *t, const char *key, const char *names,
                       size_t stride, int count, int *out)
{
    char list[100], tmp[100], q[200], m[256], m2[256], mean[48];
    int k;
    for (k = 0; k < count; k++)
        if (rj__sp_is(t, names + stride * (size_t) k)) {
            *out = k;
            return 1;
        }
    list[0] = 0;
    for (k = 0; k < count; k++) {
        rj__sp_cat(tmp, sizeof tmp, list, k ? (k == count - 1 ? " or " : ", ") : "",
                   names + stride * (size_t) k, NULL, NULL, NULL, NULL);
        memcpy(list, tmp, sizeof list);
    }
    rj__sp_quote(q, sizeof q, t->s, t->len);
    rj__sp_cat(m, sizeof m, "unknown value '", q, "'", rj__sp_for(P, key), " (expected ", NULL,
               NULL);
    rj__sp_cat(m2, sizeof m2, m, list, ")",
               rj__sp_mean(mean, rj__sp_near(t->s, t->len, names, stride, count)), NULL, NULL,
               NULL);
    return rj__sp_fail(P, t->line, t->col, key, rj__sp_nan(), m2);
}

static int rj__sp_bool(rj__sp *P, const rj__stok *t, const char *key, int *out)
{
    static const char names[4][6] = { "no", "yes", "false", "true" };
    int k = 0;
    if (!rj__sp_enum(P, t, key, names[0], sizeof names[0], 4, &k))
        return 0;
    *out = k & 1;
    return 1;
}

static int rj__sp_name_ref(rj__sp *P, const rj__stok *t, const char *key)
{
    if (t->kind == 'w' && rj__sp_name_ok(t->s, t->len))
        return 1;
    return rj__sp_err_tok(P, t, key, rj__sp_nan(), "expected a name, found ", rj__sp_for(P, key),
                          NULL, NULL);
}

static int rj__sp_find(const char *s, int n, const char *names, size_t stride, int count)
{
    int k;
    for (k = 0; k < count; k++) {
        const char *nm = names + stride * (size_t) k;
        if ((int) strlen(nm) == n && memcmp(nm, s, (size_t) n) == 0)
            return k;
    }
    return -1;
}

/* ------------------------------------------------------------------ keys */
#define RJ__SP_RULE(cond, rule) rj__sp_range(P, a, *i, key, v, (cond), (rule))

/* whether v is in row r's range */
static int rj__sp_in_range(const rj__field *r, double v)
{
    return (r->lo_in ? v >= r->lo : v > r->lo) && (r->hi_in ? v <= r->hi : v < r->hi);
}

/* key = x y: two numbers, each in row r's range */
static int rj__sp_vec2(rj__sp *P, const rj__field *r, int a, int *i, int b, void *def)
{
    const char *key = r->key;
    char shape[64];
    int c;
    for (c = 0; c < 2; c++) {
        double v = 0;
        if (c == 1 && *i >= b) {
            const rj__stok *z = &P->tok[*i - 1];
            const char x[2] = { key[0], 0 };
            rj__sp_cat(shape, sizeof shape, " (", key, " = ", x, "x ", x, "y, in ");
            return rj__sp_err(P, z->line, z->col + z->len, key, rj__sp_nan(),
                              "missing y component after the x component", rj__sp_where(P),
                              shape, r->unit, ")");
        }
        a = *i;
        if (!rj__sp_num(P, &P->tok[*i], key, &v))
            return 0;
        (*i)++;
        if (!RJ__SP_RULE(rj__sp_in_range(r, v), r->rule))
            return 0;
        rj__row_set_real(def, r, c, v);
    }
    return 1;
}

/* a key whose row r says all (a number, an angle or rate, an int, an enum, a yes/no, a
   vector): a value of its type in its range, into def */
static int rj__sp_row(rj__sp *P, const rj__field *r, int a, int *i, int b, void *def)
{
    const char *key = r->key;
    const rj__stok *t = &P->tok[a];
    double v = 0;
    int n = 0;
    switch (r->type) {
    case RJ__FT_INT:
        if (!rj__sp_int(P, t, key, (int) r->lo, (int) r->hi, r->rule, &n))
            return 0;
        rj__row_set_int(def, r, n);
        (*i)++;
        return 1;
    case RJ__FT_ENUM:
        if (!rj__sp_enum(P, t, key, rj__names_of(r->names), r->stride, r->count, &n))
            return 0;
        rj__row_set_int(def, r, n);
        (*i)++;
        return 1;
    case RJ__FT_BOOL:
        if (!rj__sp_bool(P, t, key, &n))
            return 0;
        rj__row_set_int(def, r, n);
        (*i)++;
        return 1;
    case RJ__FT_VEC2:
        return rj__sp_vec2(P, r, a, i, b, def);
    case RJ__FT_ANGLE:
    case RJ__FT_RATE:
        if (!rj__sp_angle(P, i, b, key, r->type == RJ__FT_RATE, &v))
            return 0;
        break;
    default:
        if (!rj__sp_num(P, t, key, &v))
            return 0;
        (*i)++;
    }
    if (!RJ__SP_RULE(rj__sp_in_range(r, v), r->rule))
        return 0;
    rj__row_set_real(def, r, 0, v);
    return 1;
}

/* material = NAME, section = NAME: a part defined above the link */
static int rj__sp_part(rj__sp *P, int k, const rj__stok *t)
{
    const char *key = rj__link_fields[k].key;
    const rj__spart *parts = k == RJ__LK_MATERIAL ? P->mat : P->sec;
    int idx, np = k == RJ__LK_MATERIAL ? P->nmat : P->nsec;
    char mean[48];
    if (!rj__sp_name_ref(P, t, key))
        return 0;
    idx = np ? rj__sp_find(t->s, t->len, parts[0].name, sizeof(rj__spart), np) : -1;
    if (idx < 0)
        return rj__sp_err_tok(P, t, key, rj__sp_nan(),
                              k == RJ__LK_MATERIAL ? "unknown material " : "unknown section ",
                              rj__sp_where(P), " (define it above the link)",
                              np ? rj__sp_mean(mean, rj__sp_near(t->s, t->len, parts[0].name,
                                                                 sizeof(rj__spart), np))
                                 : "");
    if (k == RJ__LK_MATERIAL)
        P->link_mat = idx;
    else
        P->link_sec = idx;
    return 1;
}

/* fidelity = flexible | rigid | inextensible, the model's (rj__sk_fidelity, in its
   order), or pieces, the file's own: a link cut into rigid pieces after the file is read
   (rj__sp_cut). Its pieces are rigid links, so the link is one until then. */
static int rj__sp_fidelity(rj__sp *P, const rj__stok *t, rj_link_def *d)
{
    static const char names[4][13] = { "flexible", "rigid", "inextensible", "pieces" };
    int n = 0;
    if (!rj__sp_enum(P, t, "fidelity", names[0], sizeof names[0], 4, &n))
        return 0;
    P->pieces[P->item] = n == 3;
    d->fidelity = n == 3 ? RJ_LINK_RIGID : n;
    return 1;
}

static int rj__sp_link_key(rj__sp *P, int k, int a, int *i, int b, rj_link_def *d)
{
    /* only a link section takes fidelity (not a material or a section) */
    if (k == RJ__LK_FIDELITY && P->kind == RJ__SK_LINK) {
        if (!rj__sp_fidelity(P, &P->tok[a], d))
            return 0;
        (*i)++;
        return 1;
    }
    if (rj__link_fields[k].type == RJ__FT_PART) {
        if (!rj__sp_part(P, k, &P->tok[a]))
            return 0;
        (*i)++;
        return 1;
    }
    return rj__sp_row(P, &rj__link_fields[k], a, i, b, d);
}

/* forward / reverse / cutoff = an angle in row r's range, or none */
static int rj__sp_limit(rj__sp *P, const rj__field *r, int a, int *i, int b, int *has,
                        double *lim)
{
    const char *key = r->key;
    char rule[96];
    double v = 0;
    if (rj__sp_is(&P->tok[a], "none")) {
        *has = 0;
        *lim = 0;
        (*i)++;
        return 1;
    }
    if (!rj__sp_angle(P, i, b, key, 0, &v))
        return 0;
    rj__sp_cat(rule, sizeof rule, r->rule, ", or none", NULL, NULL, NULL, NULL, NULL);
    if (!RJ__SP_RULE(rj__sp_in_range(r, v), rule))
        return 0;
    *has = 1;
    *lim = v;
    return 1;
}

/* a link defined above the statement, named by t, into *link; users: what names links
   (the message's "define links above the joints that use them") */
static int rj__sp_link_ref(rj__sp *P, const rj__stok *t, const char *key, const char *users,
                           int *link)
{
    const int idx = P->f->link_count ? rj__sp_find(t->s, t->len, (const char *) P->f->link_names,
                                                   RJ_SCENE_NAME_MAX, P->f->link_count)
                                     : -1;
    char mean[48], tail[64];
    if (idx >= 0) {
        *link = idx;
        return 1;
    }
    rj__sp_mean(mean, P->f->link_count ? rj__sp_near(t->s, t->len, (const char *) P->f->link_names,
                                                     RJ_SCENE_NAME_MAX, P->f->link_count)
                                       : NULL);
    rj__sp_cat(tail, sizeof tail, " (define links above the ", users, " that use them)", NULL, NULL,
               NULL, NULL);
    return rj__sp_err_tok(P, t, key, rj__sp_nan(), "unknown link ", rj__sp_for(P, key), tail, mean);
}

/* a node of a link: last (-1) or its index (the link's range is checked when its section
   ends) */
static int rj__sp_node_ref(rj__sp *P, const rj__stok *t, const char *key, int *i, int *node)
{
    if (rj__sp_is(t, "last"))
        *node = -1;
    else if (!rj__sp_int(P, t, key, 0, 1000000, NULL, node))
        return 0;
    (*i)++;
    return 1;
}

/* What a table's pairs hold: the first an angle (deg or rad, in [0, 360] deg) or a plain
   number, the second a plain number; their names and the second's unit for messages; the
   fewest points a table has. */
typedef struct rj__sp_form {
    int angles;
    const char *first, *second, *second_what, *second_unit, *shape;
    int fewest;
} rj__sp_form;

/* the first value of a table's pair into *v (a: where it starts, for the range rule) */
static int rj__sp_pair_first(rj__sp *P, int *i, int b, const rj__sp_form *t, double *out)
{
    const char *key = "table";
    const int a = *i;
    double v = 0;
    if (!t->angles) {
        if (!rj__sp_num(P, &P->tok[*i], key, out))
            return 0;
        (*i)++;
        return 1;
    }
    if (!rj__sp_angle(P, i, b, key, 0, &v))
        return 0;
    /* angles may fall: as in rj_model_create, a fall starts a new run (Eq 4) */
    if (!RJ__SP_RULE(v >= 0 && v <= 2.0 * 3.14159265358979323846,
                     "table angles must be in [0, 360] deg"))
        return 0;
    *out = v;
    return 1;
}

/* after a pair: the end of the table, or ',' and another pair; "1 Nm" gets why the
   second takes no unit word. Returns 1 at the end, 2 for another pair, 0 on an error. */
static int rj__sp_pair_next(rj__sp *P, int *i, int b, const rj__sp_form *t)
{
    const char *key = "table";
    if (*i >= b)
        return 1;
    if (P->tok[*i].kind != ',') {
        const rj__stok *u = &P->tok[*i], *q = &P->tok[*i - 1];
        char h[200];
        h[0] = 0;
        if (t->second_unit && u->kind == 'w' && rj__sp_alpha((unsigned char) u->s[0]))
            rj__sp_unit_hint(h, t->second_what, t->second_unit, q->s, q->len, u->s, u->len);
        return rj__sp_err_tok(P, u, key, rj__sp_nan(),
                              "expected ',' or the end of the table, found ", rj__sp_where(P),
                              t->shape, h);
    }
    (*i)++;
    if (*i >= b) {
        const rj__stok *z = &P->tok[*i - 1];
        return rj__sp_err(P, z->line, z->col, key, rj__sp_nan(), "table ends with ','",
                          rj__sp_where(P), NULL, NULL, NULL);
    }
    return 2;
}

/* table = a b, a b, ...: t->fewest .. RJ_TABLE_MAX pairs into first[] and second[] */
static int rj__sp_pairs(rj__sp *P, int *i, int b, const rj__sp_form *t, double *first,
                        double *second, int *count)
{
    const char *key = "table";
    char nb[24], missing[64];
    int n = 0, a = *i, more = 2;
    while (more == 2) {
        a = *i;
        if (n == RJ_TABLE_MAX)
            return rj__sp_err(P, P->tok[a].line, P->tok[a].col, key, rj__sp_nan(),
                              "table has more than ", rj__sp_itoa(nb, RJ_TABLE_MAX), " points",
                              rj__sp_where(P), NULL);
        if (!rj__sp_pair_first(P, i, b, t, &first[n]))
            return 0;
        if (*i >= b || P->tok[*i].kind == ',') {
            const rj__stok *z = &P->tok[*i - 1];
            rj__sp_cat(missing, sizeof missing, "missing ", t->second, " after the table ",
                       t->first, NULL, NULL, NULL);
            return rj__sp_err(P, z->line, z->col + z->len, key, rj__sp_nan(), missing,
                              rj__sp_where(P), t->shape, NULL, NULL);
        }
        if (!rj__sp_num(P, &P->tok[*i], key, &second[n]))
            return 0;
        (*i)++;
        n++;
        more = rj__sp_pair_next(P, i, b, t);
        if (!more)
            return 0;
    }
    if (n < t->fewest)
        return rj__sp_err(P, P->tok[a].line, P->tok[a].col, key, rj__sp_nan(),
                          "a table needs at least 2 points", rj__sp_where(P), NULL, NULL, NULL);
    *count = n;
    return 1;
}

/* a joint's table = angle torque, angle torque, ... (Eq 4) */
static int rj__sp_table(rj__sp *P, int *i, int b, rj_joint_def *d)
{
    const rj__sp_form form = { 1,          "angle", "torque",
                               "a torque", "N m",   " (table = angle torque, angle torque, ...)",
                               2 };
    return rj__sp_pairs(P, i, b, &form, d->table_angle, d->table_torque, &d->table_count);
}

/* body1 = ground or a link, body2 = a link */
static int rj__sp_body(rj__sp *P, int k, const rj__stok *t, rj_joint_def *d)
{
    const char *key = rj__joint_fields[k].key;
    int idx;
    if (!rj__sp_name_ref(P, t, key))
        return 0;
    if (rj__sp_is(t, "ground")) {
        if (k == RJ__JK_BODY2)
            return rj__sp_err_tok(P, t, key, rj__sp_nan(), "body2 must be a link, not ",
                                  rj__sp_where(P), " (body1 may be ground)", NULL);
        d->body1 = -1;
        return 1;
    }
    if (!rj__sp_link_ref(P, t, key, "joints", &idx))
        return 0;
    if (k == RJ__JK_BODY1)
        d->body1 = idx;
    else
        d->body2 = idx;
    return 1;
}

/* spring = k angle: a stiffness and a free angle, each in its row's range */
static int rj__sp_spring(rj__sp *P, int a, int *i, int b, rj_joint_def *d)
{
    const rj__field *rk = &rj__joint_fields[RJ__JK_SPRING];
    const rj__field *ra = &rj__joint_fields[RJ__JF_FREE_ANGLE];
    const char *key = rk->key;
    const rj__stok *t = &P->tok[a];
    char rule[128];
    double v = 0;
    if (!rj__sp_num(P, t, key, &v))
        return 0;
    (*i)++;
    rj__sp_cat(rule, sizeof rule, "the spring stiffness ", rk->rule, NULL, NULL, NULL, NULL,
               NULL);
    if (!RJ__SP_RULE(rj__sp_in_range(rk, v), rule))
        return 0;
    d->spring_k = v;
    if (*i >= b)
        return rj__sp_err(P, t->line, t->col + t->len, key, rj__sp_nan(),
                          "missing free angle after the stiffness", rj__sp_where(P),
                          " (spring = k angle)", NULL, NULL);
    a = *i;
    if (!rj__sp_angle(P, i, b, key, 0, &v))
        return 0;
    rj__sp_cat(rule, sizeof rule, "the free angle ", ra->rule, NULL, NULL, NULL, NULL, NULL);
    if (!RJ__SP_RULE(rj__sp_in_range(ra, v), rule))
        return 0;
    d->spring_free_angle = v;
    return 1;
}

static int rj__sp_joint_key(rj__sp *P, int k, int a, int *i, int b, rj_joint_def *d)
{
    const rj__field *r = &rj__joint_fields[k];
    switch (r->type) {
    case RJ__FT_LINK:
        if (!rj__sp_body(P, k, &P->tok[a], d))
            return 0;
        (*i)++;
        return 1;
    case RJ__FT_NODE:
        return rj__sp_node_ref(P, &P->tok[a], r->key, i, k == RJ__JK_NODE2 ? &d->node2 : &d->node1);
    case RJ__FT_TABLE:
        return rj__sp_table(P, i, b, d);
    case RJ__FT_LIMIT:
        return k == RJ__JK_FORWARD ? rj__sp_limit(P, r, a, i, b, &d->has_forward, &d->forward)
                                   : rj__sp_limit(P, r, a, i, b, &d->has_reverse, &d->reverse);
    }
    if (k == RJ__JK_SPRING)
        return rj__sp_spring(P, a, i, b, d);
    return rj__sp_row(P, r, a, i, b, d);
}

static int rj__sp_solver_key(rj__sp *P, int k, int a, int *i, int b, rj_solver_def *s)
{
    return rj__sp_row(P, &rj__solver_fields[k], a, i, b, s);
}

/* a load's table = time factor, time factor, ...: 1..RJ_TABLE_MAX points, times in s
   (strictly increasing: rj_model_create checks it, naming the point) */
static int rj__sp_load_table(rj__sp *P, int *i, int b, rj_load_def *d)
{
    const rj__sp_form form = { 0,    "time", "factor",
                               NULL, NULL,   " (table = time factor, time factor, ...)",
                               1 };
    return rj__sp_pairs(P, i, b, &form, d->table_time, d->table_factor, &d->table_count);
}

static int rj__sp_load_key(rj__sp *P, int k, int a, int *i, int b, rj_load_def *d)
{
    const rj__field *r = &rj__load_fields[k];
    const rj__stok *t = &P->tok[a];
    switch (r->type) {
    case RJ__FT_LINK:
        if (!rj__sp_name_ref(P, t, r->key) || !rj__sp_link_ref(P, t, r->key, "loads", &d->link))
            return 0;
        (*i)++;
        return 1;
    case RJ__FT_NODE:
        return rj__sp_node_ref(P, t, r->key, i, &d->node);
    case RJ__FT_TABLE:
        return rj__sp_load_table(P, i, b, d);
    }
    return rj__sp_row(P, r, a, i, b, d);
}

/* joint = NAME: a joint defined above the actuator */
static int rj__sp_joint_ref(rj__sp *P, const rj__stok *t, const char *key, int *joint)
{
    const char *users = P->kind == RJ__SK_COUPLING ? " (define joints above the couplings that "
                                                     "tie them)"
                                                   : " (define joints above the actuators "
                                                     "that drive them)";
    const int idx = P->f->joint_count
                        ? rj__sp_find(t->s, t->len, (const char *) P->f->joint_names,
                                      RJ_SCENE_NAME_MAX, P->f->joint_count)
                        : -1;
    char mean[48];
    if (!rj__sp_name_ref(P, t, key))
        return 0;
    if (idx >= 0) {
        *joint = idx;
        return 1;
    }
    rj__sp_mean(mean, P->f->joint_count
                          ? rj__sp_near(t->s, t->len, (const char *) P->f->joint_names,
                                        RJ_SCENE_NAME_MAX, P->f->joint_count)
                          : NULL);
    return rj__sp_err_tok(P, t, key, rj__sp_nan(), "unknown joint ", rj__sp_for(P, key), users,
                          mean);
}

/* an actuator's table = time factor, time factor, ... (as a load's) */
static int rj__sp_actuator_table(rj__sp *P, int *i, int b, rj_actuator_def *d)
{
    const rj__sp_form form = { 0,    "time", "factor",
                               NULL, NULL,   " (table = time factor, time factor, ...)",
                               1 };
    return rj__sp_pairs(P, i, b, &form, d->table_time, d->table_factor, &d->table_count);
}

/* profile = ramp RATE | cycloidal ANGLE DURATION | spinup OMEGA TS: the name, then its
   numbers in their rows' ranges (rates and angles may say deg/s or deg) */
static int rj__sp_profile(rj__sp *P, int a, int *i, int b, rj_actuator_def *d)
{
    const rj__field *rv = &rj__actuator_fields[RJ__CF_PROFILE_VALUE];
    const rj__field *rt = &rj__actuator_fields[RJ__CF_PROFILE_TIME];
    const char *key = "profile";
    static const char shape[] = " (profile = ramp RATE, cycloidal ANGLE DURATION, spinup "
                                "OMEGA TS or table)";
    double v = 0;
    if (!rj__sp_enum(P, &P->tok[a], key, rj__sk_profile[0], sizeof rj__sk_profile[0], 4,
                     &d->profile))
        return 0;
    (*i)++;
    if (d->profile == RJ_PROFILE_TABLE) /* its points are the table's */
        return 1;
    if (*i >= b)
        return rj__sp_err(P, P->tok[a].line, P->tok[a].col + P->tok[a].len, key, rj__sp_nan(),
                          "missing the profile's numbers", rj__sp_where(P), shape, NULL, NULL);
    a = *i;
    if (!rj__sp_angle(P, i, b, key, d->profile != RJ_PROFILE_CYCLOIDAL, &v))
        return 0;
    if (!RJ__SP_RULE(rj__sp_in_range(rv, v), rv->rule))
        return 0;
    d->profile_value = v;
    if (d->profile == RJ_PROFILE_RAMP)
        return 1;
    if (*i >= b)
        return rj__sp_err(P, P->tok[a].line, P->tok[a].col + P->tok[a].len, key, rj__sp_nan(),
                          "missing the profile's time", rj__sp_where(P), shape, NULL, NULL);
    a = *i;
    if (!rj__sp_num(P, &P->tok[a], key, &v))
        return 0;
    (*i)++;
    if (!RJ__SP_RULE(rj__sp_in_range(rt, v), rt->rule))
        return 0;
    d->profile_time = v;
    return 1;
}

static int rj__sp_actuator_key(rj__sp *P, int k, int a, int *i, int b, rj_actuator_def *d)
{
    const rj__field *r = &rj__actuator_fields[k];
    switch (r->type) {
    case RJ__FT_PROFILE:
        return rj__sp_profile(P, a, i, b, d);
    case RJ__FT_JOINT:
        if (!rj__sp_joint_ref(P, &P->tok[a], r->key, &d->joint))
            return 0;
        (*i)++;
        return 1;
    case RJ__FT_TABLE:
        return rj__sp_actuator_table(P, i, b, d);
    case RJ__FT_LIMIT:
        return rj__sp_limit(P, r, a, i, b, &d->has_cutoff, &d->cutoff);
    }
    return rj__sp_row(P, r, a, i, b, d);
}

/* an actuator names its joint, and sets only keys of its type */
static int rj__sp_finish_actuator(rj__sp *P)
{
    const rj_actuator_def *d = &P->f->actuators[P->item];
    const rj_scene_pos *pos = &P->f->actuator_pos_[(size_t) P->item * (1 + RJ__CK_N)];
    const char *name = P->f->actuator_names[P->item];
    int k;
    if (!(P->seen >> RJ__CK_JOINT & 1u))
        return rj__sp_err(P, pos[0].line, pos[0].col, "joint", rj__sp_nan(), "actuator '", name,
                          "' has no joint (the joint it drives)", NULL, NULL);
    for (k = 0; k < RJ__CK_N; k++) {
        const rj__field *r = &rj__actuator_fields[k];
        char m[128];
        if (!(P->seen >> k & 1u) || rj__row_applies(r, d->type, 0, 0))
            continue;
        rj__sp_cat(m, sizeof m, r->key, " does not apply to type = ", rj__sk_actuator[d->type],
                   ", in actuator '", name, "'", NULL);
        return rj__sp_err(P, pos[1 + k].line, pos[1 + k].col, r->key, rj__sp_nan(), m, NULL, NULL,
                          NULL, NULL);
    }
    return 1;
}

/* joints = A B: two joints defined above the coupling */
static int rj__sp_coupling_key(rj__sp *P, int k, int a, int *i, int b, rj_coupling_def *d)
{
    const rj__field *r = &rj__coupling_fields[k];
    if (k != RJ__PK_JOINTS)
        return rj__sp_row(P, r, a, i, b, d);
    if (!rj__sp_joint_ref(P, &P->tok[a], r->key, &d->joint_a))
        return 0;
    (*i)++;
    if (*i >= b) {
        const rj__stok *z = &P->tok[a];
        return rj__sp_err(P, z->line, z->col + z->len, r->key, rj__sp_nan(),
                          "missing the second joint", rj__sp_where(P), " (joints = A B)", NULL,
                          NULL);
    }
    if (!rj__sp_joint_ref(P, &P->tok[*i], r->key, &d->joint_b))
        return 0;
    (*i)++;
    return 1;
}

/* a coupling names its two joints, and they differ */
static int rj__sp_finish_coupling(rj__sp *P)
{
    const rj_coupling_def *d = &P->f->couplings[P->item];
    const rj_scene_pos *pos = &P->f->coupling_pos_[(size_t) P->item * (1 + RJ__PK_N)];
    const char *name = P->f->coupling_names[P->item];
    if (!(P->seen >> RJ__PK_JOINTS & 1u))
        return rj__sp_err(P, pos[0].line, pos[0].col, "joints", rj__sp_nan(), "coupling '",
                          name, "' has no joints (joints = A B)", NULL, NULL);
    if (d->joint_a == d->joint_b)
        return rj__sp_err(P, pos[1 + RJ__PK_JOINTS].line, pos[1 + RJ__PK_JOINTS].col, "joints",
                          rj__sp_nan(), "coupling '", name, "' ties joint '",
                          P->f->joint_names[d->joint_a], "' to itself");
    return 1;
}

/* ------------------------------------------------------------------ sections */
static int rj__sp_key_index(int kind, const rj__stok *t)
{
    int k;
    switch (kind) {
    case RJ__SK_SOLVER:
        for (k = 0; k < RJ__VK_N; k++)
            if (rj__sp_is(t, rj__solver_fields[k].key))
                return k;
        break;
    case RJ__SK_MATERIAL:
    case RJ__SK_SECTION:
    case RJ__SK_LINK: {
        unsigned allowed = kind == RJ__SK_MATERIAL  ? RJ__SK_MAT_KEYS
                           : kind == RJ__SK_SECTION ? RJ__SK_SEC_KEYS
                                                    : ~0u;
        for (k = 0; k < RJ__LK_N; k++)
            if ((allowed >> k & 1u) && rj__sp_is(t, rj__link_fields[k].key))
                return k;
        break;
    }
    case RJ__SK_JOINT:
        for (k = 0; k < RJ__JK_N; k++)
            if (rj__sp_is(t, rj__joint_fields[k].key))
                return k;
        break;
    case RJ__SK_LOAD:
        for (k = 0; k < RJ__AK_N; k++)
            if (rj__sp_is(t, rj__load_fields[k].key))
                return k;
        break;
    case RJ__SK_ACTUATOR:
        for (k = 0; k < RJ__CK_N; k++)
            if (rj__sp_is(t, rj__actuator_fields[k].key))
                return k;
        break;
    case RJ__SK_COUPLING:
        for (k = 0; k < RJ__PK_N; k++)
            if (rj__sp_is(t, rj__coupling_fields[k].key))
                return k;
        break;
    }
    return -1;
}

static const char *rj__sp_key_name(int kind, int k)
{
    if (kind == RJ__SK_SOLVER)
        return rj__solver_fields[k].key;
    if (kind == RJ__SK_JOINT)
        return rj__joint_fields[k].key;
    if (kind == RJ__SK_LOAD)
        return rj__load_fields[k].key;
    if (kind == RJ__SK_ACTUATOR)
        return rj__actuator_fields[k].key;
    if (kind == RJ__SK_COUPLING)
        return rj__coupling_fields[k].key;
    return rj__link_fields[k].key;
}

/* section rules shared by sections and links: eff = keys in effect, pos[k] where key k came from */
static int rj__sp_check_shape(rj__sp *P, unsigned eff, const rj_link_def *d,
                              const rj_scene_pos *pos, rj_scene_pos head, const char *what)
{
    unsigned gen = (1u << RJ__LK_AREA) | (1u << RJ__LK_INERTIA);
    if (eff & gen) {
        int k;
        if ((eff & gen) != gen) {
            int has = (eff >> RJ__LK_AREA & 1u) ? RJ__LK_AREA : RJ__LK_INERTIA;
            rj_scene_pos p = pos[has].line ? pos[has] : head;
            return rj__sp_err(P, p.line, p.col, rj__link_fields[has].key, rj__sp_nan(), what, " sets ",
                              rj__link_fields[has].key,
                              has == RJ__LK_AREA ? " but not inertia" : " but not area",
                              ": a general section needs both area and inertia");
        }
        for (k = RJ__LK_WIDTH; k <= RJ__LK_LAYERS; k++)
            if (k != RJ__LK_HEIGHT && (eff >> k & 1u)) {
                rj_scene_pos p = pos[k].line ? pos[k] : head;
                return rj__sp_err(
                    P, p.line, p.col, rj__link_fields[k].key, rj__sp_nan(), what, " mixes ", rj__link_fields[k].key,
                    " with area/inertia: ", "width and layers apply only to rectangular sections");
            }
    } else if ((eff >> RJ__LK_HEIGHT & 1u) && !(d->height > 0)) {
        return rj__sp_err(P, pos[RJ__LK_HEIGHT].line, pos[RJ__LK_HEIGHT].col, "height", d->height,
                          what, " has height = 0: a rectangular section needs height > 0", NULL,
                          NULL, NULL);
    }
    return 1;
}

/* a load names its link, and a node the link has */
static int rj__sp_finish_load(rj__sp *P)
{
    const rj_load_def *d = &P->f->loads[P->item];
    const rj_scene_pos *pos = &P->f->load_pos_[(size_t) P->item * (1 + RJ__AK_N)];
    const char *name = P->f->load_names[P->item];
    char a[24], b[24], m[256];
    if (!(P->seen >> RJ__AK_LINK & 1u))
        return rj__sp_err(P, pos[0].line, pos[0].col, "link", rj__sp_nan(), "load '", name,
                          "' has no link (the link it acts on)", NULL, NULL);
    if (d->node <= P->f->links[d->link].elements)
        return 1;
    rj__sp_cat(m, sizeof m, "node = ", rj__sp_itoa(a, d->node), " is out of range in load '", name,
               "': link '", P->f->link_names[d->link], "' has nodes 0..");
    return rj__sp_err(P, pos[1 + RJ__AK_NODE].line, pos[1 + RJ__AK_NODE].col, "node", d->node, m,
                      rj__sp_itoa(b, P->f->links[d->link].elements), " (or last)", NULL, NULL);
}

/* A link's material: each material key the link leaves out (its keys so far, eff) comes
   from the material, with its place in the file; returns the keys the link has now. */
static unsigned rj__sp_take_material(const rj__spart *s, unsigned eff, rj_link_def *d,
                                     rj_scene_pos *pos)
{
    int k;
    for (k = 0; k < RJ__LK_N; k++) {
        const rj__field *r = &rj__link_fields[k];
        if (!(RJ__SK_MAT_KEYS >> k & 1u) || (eff >> k & 1u) || !(s->mask >> k & 1u))
            continue;
        rj__row_set_real(d, r, 0, rj__row_real(&s->d, r, 0));
        if (r->type == RJ__FT_VEC2)
            rj__row_set_real(d, r, 1, rj__row_real(&s->d, r, 1));
        pos[1 + k] = s->pos[1 + k];
    }
    return eff | s->mask;
}

/* ------------------------------------------------------------------ changes (--set) */
static int rj__sp_next(rj__sp *P);
static int rj__sp_assignments(rj__sp *P);

/* A change "KIND.NAME.KEY=VALUE" ("solver.KEY=VALUE"): its section kind, its item's name
   and its key, each a start and a length (a name may hold dots: the key follows the last
   one before the '='). Returns 0 when it is not of that form. */
typedef struct rj__sp_set {
    int kind;
    const char *name, *key;
    int nlen, klen;
} rj__sp_set;

static int rj__sp_set_split(const char *s, rj__sp_set *o)
{
    const char *eq = strchr(s, '=');
    const char *dot = strchr(s, '.');
    const char *last = NULL, *c;
    int k;
    if (!eq || !dot || dot > eq)
        return 0;
    o->kind = 0;
    for (k = RJ__SK_SOLVER; k <= RJ__SK_COUPLING; k++)
        if (strlen(rj__sk_kind[k]) == (size_t) (dot - s) &&
            strncmp(s, rj__sk_kind[k], (size_t) (dot - s)) == 0)
            o->kind = k;
    for (c = dot; c < eq; c++)
        if (*c == '.')
            last = c;
    o->name = dot + 1;
    o->nlen = o->kind == RJ__SK_SOLVER ? 0 : (int) (last - dot - 1);
    o->key = o->kind == RJ__SK_SOLVER ? dot + 1 : last + 1;
    o->klen = (int) (eq - o->key);
    return o->kind && o->klen > 0 && (o->kind == RJ__SK_SOLVER || o->nlen > 0);
}

/* Change k into the current item, as a statement written last in its section (its key,
   if the file set it, set again; its position none, for validation's messages): read
   from the change's own text, "--set" line k + 1 in messages. */
static int rj__sp_set_take(rj__sp *P, int k, const rj__sp_set *o)
{
    const char *text = P->text, *fname = P->fname;
    const size_t len = P->len, at = P->at;
    const int lineno = P->lineno, ntok = P->ntok;
    rj__stok *tok = P->tok;
    int ok, key = -1;
    P->text = P->sets[k];
    P->len = strlen(P->sets[k]);
    P->at = 0;
    P->lineno = k;
    P->fname = "--set";
    P->tok = P->set_tok;
    ok = rj__sp_next(P) > 0 && P->ntok >= 2 && P->tok[1].kind == '=';
    if (ok) {
        /* the statement's key: the change's last part before '=' */
        P->tok[0].col += (int) (o->key - P->sets[k]);
        P->tok[0].s = o->key;
        P->tok[0].len = o->klen;
        key = rj__sp_key_index(P->kind, &P->tok[0]);
        if (key >= 0)
            P->seen &= ~(1u << key);
        ok = rj__sp_assignments(P);
        if (ok && key >= 0)
            rj__sp_pos(P, key)->line = 0;
    } else if (P->code == RJ_OK)
        rj__sp_fail(P, k + 1, 1, "set", rj__sp_nan(), "expected KIND.NAME.KEY=VALUE");
    P->text = text;
    P->len = len;
    P->at = at;
    P->lineno = lineno;
    P->fname = fname;
    P->tok = tok;
    P->ntok = ntok;
    P->sets_done |= 1ull << k;
    return ok;
}

/* The changes for the section that ends here (its kind and its item's name). */
static int rj__sp_sets(rj__sp *P)
{
    int k;
    for (k = 0; k < P->nsets; k++) {
        rj__sp_set o;
        const char *name = rj__sp_item_name(P);
        if ((P->sets_done >> k & 1u) || !rj__sp_set_split(P->sets[k], &o) || o.kind != P->kind)
            continue;
        if (o.kind != RJ__SK_SOLVER &&
            (strlen(name) != (size_t) o.nlen || strncmp(name, o.name, (size_t) o.nlen) != 0))
            continue;
        if (!rj__sp_set_take(P, k, &o))
            return 0;
    }
    return 1;
}

/* Change k refused at column col of its own text ("--set:K:COL:"). */
static int rj__sp_set_fail(rj__sp *P, int k, int col, const char *msg)
{
    P->fname = "--set";
    return rj__sp_fail(P, k + 1, col, "set", rj__sp_nan(), msg);
}

/* After the file: changes of the solver when it has no section (the defaults take them),
   and a change that named no item of the file, or no kind: refused, naming it. */
static int rj__sp_sets_left(rj__sp *P)
{
    int k;
    for (k = 0; k < P->nsets; k++) {
        rj__sp_set o;
        char name[RJ_SCENE_NAME_MAX], m[200];
        if (P->sets_done >> k & 1u)
            continue;
        if (!rj__sp_set_split(P->sets[k], &o))
            return rj__sp_set_fail(P, k, 1,
                                   "a change is KIND.NAME.KEY=VALUE, or solver.KEY=VALUE; KIND "
                                   "is material, section, link, joint, load, actuator or "
                                   "coupling");
        if (o.kind == RJ__SK_SOLVER) {
            P->kind = RJ__SK_SOLVER;
            P->seen = 0;
            if (!rj__sp_set_take(P, k, &o))
                return 0;
            continue;
        }
        snprintf(name, sizeof name, "%.*s", o.nlen < RJ_SCENE_NAME_MAX ? o.nlen : 0, o.name);
        snprintf(m, sizeof m, "the file has no %s '%s' to change", rj__sk_kind[o.kind], name);
        return rj__sp_set_fail(P, k, (int) (o.name - P->sets[k]) + 1, m);
    }
    return 1;
}

/* checks and completes the section that ends here */
static int rj__sp_finish(rj__sp *P)
{
    char what[80];
    if (P->nsets && P->kind != RJ__SK_NONE && !rj__sp_sets(P))
        return 0;
    switch (P->kind) {
    case RJ__SK_NONE:
    case RJ__SK_SOLVER:
        break;
    case RJ__SK_MATERIAL:
        P->mat[P->item].mask = P->seen;
        break;
    case RJ__SK_SECTION: {
        rj__spart *s = &P->sec[P->item];
        s->mask = P->seen;
        rj__sp_cat(what, sizeof what, "section '", s->name, "'", NULL, NULL, NULL, NULL);
        if (!rj__sp_check_shape(P, s->mask, &s->d, s->pos + 1, s->pos[0], what))
            return 0;
        break;
    }
    case RJ__SK_LINK: {
        rj_link_def *d = &P->f->links[P->item];
        rj_scene_pos *pos = &P->f->link_pos_[(size_t) P->item * (1 + RJ__LK_N)];
        unsigned eff = P->seen;
        int k;
        if (P->link_mat >= 0)
            eff = rj__sp_take_material(&P->mat[P->link_mat], eff, d, pos);
        if (P->link_sec >= 0) {
            const rj__spart *s = &P->sec[P->link_sec];
            for (k = RJ__LK_AREA; k <= RJ__LK_LAYERS; k++) {
                if ((eff >> k & 1u) || !(s->mask >> k & 1u))
                    continue;
                switch (k) {
                case RJ__LK_AREA:
                    d->area = s->d.area;
                    break;
                case RJ__LK_INERTIA:
                    d->inertia = s->d.inertia;
                    break;
                case RJ__LK_WIDTH:
                    d->width = s->d.width;
                    break;
                case RJ__LK_HEIGHT:
                    d->height = s->d.height;
                    break;
                default:
                    d->layers = s->d.layers;
                    break;
                }
                pos[1 + k] = s->pos[1 + k];
            }
            eff |= s->mask;
        }
        rj__sp_cat(what, sizeof what, "link '", P->f->link_names[P->item], "'", NULL, NULL, NULL,
                   NULL);
        if (!rj__sp_check_shape(P, eff, d, pos + 1, pos[0], what))
            return 0;
        d->section = (eff & ((1u << RJ__LK_AREA) | (1u << RJ__LK_INERTIA))) ? RJ_SECTION_GENERAL
                                                                            : RJ_SECTION_RECT;
        break;
    }
    case RJ__SK_JOINT: {
        rj_joint_def *d = &P->f->joints[P->item];
        rj_scene_pos *pos = &P->f->joint_pos_[(size_t) P->item * (1 + RJ__JK_N)];
        const char *jn = P->f->joint_names[P->item];
        char a[24], b[24];
        int k;
        for (k = RJ__JK_BODY1; k <= RJ__JK_BODY2; k++)
            if (!(P->seen >> k & 1u))
                return rj__sp_err(P, pos[0].line, pos[0].col, rj__joint_fields[k].key, rj__sp_nan(),
                                  "joint '", jn, "' has no ", rj__joint_fields[k].key,
                                  k == RJ__JK_BODY1 ? " (ground or a link)" : " (a link)");
        if (d->body1 == d->body2)
            return rj__sp_err(P, pos[1 + RJ__JK_BODY2].line, pos[1 + RJ__JK_BODY2].col, "body2",
                              d->body2, "joint '", jn, "' connects link '",
                              P->f->link_names[d->body2], "' to itself (body1 = body2)");
        if (d->body1 < 0 && (P->seen >> RJ__JK_NODE1 & 1u))
            return rj__sp_err(P, pos[1 + RJ__JK_NODE1].line, pos[1 + RJ__JK_NODE1].col, "node1",
                              d->node1, "node1 applies only when body1 is a link, in joint '", jn,
                              "' (body1 = ground)", NULL, NULL);
        if (d->node2 > P->f->links[d->body2].elements) {
            char m[256];
            rj__sp_cat(m, sizeof m, "node2 = ", rj__sp_itoa(a, d->node2),
                       " is out of range in joint '", jn, "': link '",
                       P->f->link_names[d->body2], "' has nodes 0..");
            return rj__sp_err(P, pos[1 + RJ__JK_NODE2].line, pos[1 + RJ__JK_NODE2].col, "node2",
                              d->node2, m, rj__sp_itoa(b, P->f->links[d->body2].elements), NULL,
                              NULL, NULL);
        }
        if (d->body1 >= 0) {
            for (k = RJ__JK_GROUND_X; k <= RJ__JK_GROUND_ANGLE; k++)
                if (P->seen >> k & 1u)
                    return rj__sp_err(P, pos[1 + k].line, pos[1 + k].col, rj__joint_fields[k].key,
                                      rj__sp_nan(), rj__joint_fields[k].key,
                                      " applies only when body1 = ground, in joint '", jn, "'",
                                      NULL);
            if (d->node1 > P->f->links[d->body1].elements) {
                char m[256];
                rj__sp_cat(m, sizeof m, "node1 = ", rj__sp_itoa(a, d->node1),
                           " is out of range in joint '", jn, "': link '",
                           P->f->link_names[d->body1], "' has nodes 0..");
                return rj__sp_err(P, pos[1 + RJ__JK_NODE1].line, pos[1 + RJ__JK_NODE1].col, "node1",
                                  d->node1, m, rj__sp_itoa(b, P->f->links[d->body1].elements), NULL,
                                  NULL, NULL);
            }
        }
        break;
    }
    case RJ__SK_LOAD:
        if (!rj__sp_finish_load(P))
            return 0;
        break;
    case RJ__SK_ACTUATOR:
        if (!rj__sp_finish_actuator(P))
            return 0;
        break;
    case RJ__SK_COUPLING:
        if (!rj__sp_finish_coupling(P))
            return 0;
        break;
    }
    P->kind = RJ__SK_NONE;
    return 1;
}

static int rj__sp_header(rj__sp *P)
{
    const rj__stok *t0 = &P->tok[0], *nt;
    char nb[24];
    int kind = 0, k, cap = 0, count = 0, dup = -1;
    for (k = RJ__SK_SOLVER; k <= RJ__SK_COUPLING; k++)
        if (rj__sp_is(t0, rj__sk_kind[k]))
            kind = k;
    if (!kind) {
        /* "title Solar array": the key without its '=' */
        if (P->kind == RJ__SK_NONE && rj__sp_is(t0, "title"))
            return rj__sp_err(P, t0->line, t0->col + t0->len, "title", rj__sp_nan(),
                              "missing '=' after 'title' (write title = \"text\")", NULL, NULL,
                              NULL, NULL);
        if (P->kind != RJ__SK_NONE && rj__sp_key_index(P->kind, t0) >= 0) {
            const char *kn = rj__sp_key_name(P->kind, rj__sp_key_index(P->kind, t0));
            return rj__sp_err(P, t0->line, t0->col + t0->len, kn, rj__sp_nan(),
                              "missing '=' after '", kn, "'", rj__sp_where(P), NULL);
        }
        { /* a near section keyword, else a near key of the current section */
            const char *near =
                rj__sp_near(t0->s, t0->len, rj__sk_kind[1], sizeof rj__sk_kind[0], 8);
            char mean[48];
            if (!near && P->kind != RJ__SK_NONE)
                near = rj__sp_near_key(P, t0);
            return rj__sp_err_tok(
                P, t0, "", rj__sp_nan(),
                P->kind != RJ__SK_NONE ? "unknown key or section " : "unknown section ",
                P->kind != RJ__SK_NONE ? " (a key needs '= value'; sections are solver, material, "
                                         "section, link, joint, load, actuator, coupling)"
                                       : " (expected solver, material, section, link, joint, "
                                         "load, actuator or coupling)",
                rj__sp_mean(mean, near), NULL);
        }
    }
    if (!rj__sp_finish(P))
        return 0;
    if (kind == RJ__SK_SOLVER) {
        if (P->ntok > 1)
            return rj__sp_err_tok(P, &P->tok[1], "", rj__sp_nan(), "unexpected ",
                                  " after 'solver' (the solver section has no name)", NULL, NULL);
        if (P->solver_seen)
            return rj__sp_err(P, t0->line, t0->col, "solver", rj__sp_nan(),
                              "duplicate solver section (first on line ",
                              rj__sp_itoa(nb, P->f->solver_pos_[0].line), ")", NULL, NULL);
        P->solver_seen = 1;
        P->f->solver_pos_[0].line = t0->line;
        P->f->solver_pos_[0].col = t0->col;
        P->kind = kind;
        P->item = 0;
        P->seen = 0;
        return 1;
    }
    if (P->ntok < 2)
        return rj__sp_err(P, t0->line, t0->col + t0->len, rj__sk_kind[kind], rj__sp_nan(),
                          "missing name after '", rj__sk_kind[kind], "'", NULL, NULL);
    nt = &P->tok[1];
    if (nt->kind != 'w' || !rj__sp_name_ok(nt->s, nt->len))
        return rj__sp_err_tok(P, nt, rj__sk_kind[kind], rj__sp_nan(), "invalid name ", " after '",
                              rj__sk_kind[kind],
                              "' (1..31 of A-Z a-z 0-9 _ . -, starting with a letter or _)");
    if (P->ntok > 2)
        return rj__sp_err_tok(P, &P->tok[2], "", rj__sp_nan(), "unexpected ", " after the name of ",
                              rj__sk_kind[kind], " (one statement per line)");
    switch (kind) {
    case RJ__SK_MATERIAL:
        cap = RJ_SCENE_MAX_MATERIALS;
        count = P->nmat;
        if (count)
            dup = rj__sp_find(nt->s, nt->len, P->mat[0].name, sizeof(rj__spart), count);
        break;
    case RJ__SK_SECTION:
        cap = RJ_SCENE_MAX_SECTIONS;
        count = P->nsec;
        if (count)
            dup = rj__sp_find(nt->s, nt->len, P->sec[0].name, sizeof(rj__spart), count);
        break;
    case RJ__SK_LINK:
        cap = RJ_SCENE_MAX_LINKS;
        count = P->f->link_count;
        if (count)
            dup = rj__sp_find(nt->s, nt->len, (const char *) P->f->link_names, RJ_SCENE_NAME_MAX,
                              count);
        break;
    case RJ__SK_LOAD:
        cap = RJ_SCENE_MAX_LOADS;
        count = P->f->load_count;
        if (count)
            dup = rj__sp_find(nt->s, nt->len, (const char *) P->f->load_names, RJ_SCENE_NAME_MAX,
                              count);
        break;
    case RJ__SK_ACTUATOR:
        cap = RJ_SCENE_MAX_ACTUATORS;
        count = P->f->actuator_count;
        if (count)
            dup = rj__sp_find(nt->s, nt->len, (const char *) P->f->actuator_names,
                              RJ_SCENE_NAME_MAX, count);
        break;
    case RJ__SK_COUPLING:
        cap = RJ_SCENE_MAX_COUPLINGS;
        count = P->f->coupling_count;
        if (count)
            dup = rj__sp_find(nt->s, nt->len, (const char *) P->f->coupling_names,
                              RJ_SCENE_NAME_MAX, count);
        break;
    default:
        cap = RJ_SCENE_MAX_JOINTS;
        count = P->f->joint_count;
        if (count)
            dup = rj__sp_find(nt->s, nt->len, (const char *) P->f->joint_names, RJ_SCENE_NAME_MAX,
                              count);
        break;
    }
    if (dup >= 0) {
        int line = kind == RJ__SK_MATERIAL  ? P->mat[dup].pos[0].line
                   : kind == RJ__SK_SECTION ? P->sec[dup].pos[0].line
                   : kind == RJ__SK_LINK    ? P->f->link_pos_[(size_t) dup * (1 + RJ__LK_N)].line
                   : kind == RJ__SK_LOAD    ? P->f->load_pos_[(size_t) dup * (1 + RJ__AK_N)].line
                   : kind == RJ__SK_ACTUATOR
                       ? P->f->actuator_pos_[(size_t) dup * (1 + RJ__CK_N)].line
                   : kind == RJ__SK_COUPLING
                       ? P->f->coupling_pos_[(size_t) dup * (1 + RJ__PK_N)].line
                                            : P->f->joint_pos_[(size_t) dup * (1 + RJ__JK_N)].line;
        char pre[40];
        rj__sp_cat(pre, sizeof pre, "duplicate ", rj__sk_kind[kind], " name ", NULL, NULL, NULL,
                   NULL);
        return rj__sp_err_tok(P, nt, rj__sk_kind[kind], rj__sp_nan(), pre,
                              " (first defined on line ", rj__sp_itoa(nb, line), ")");
    }
    if (kind == RJ__SK_LINK && rj__sp_is(nt, "ground"))
        return rj__sp_err_tok(P, nt, "link", rj__sp_nan(), "a link cannot be named ",
                              " (reserved for body1 = ground)", NULL, NULL);
    { /* the counting pass sized the arrays; it never counts fewer items than there are */
        int room = kind == RJ__SK_MATERIAL  ? P->cap_mat
                   : kind == RJ__SK_SECTION ? P->cap_sec
                   : kind == RJ__SK_LINK    ? P->cap_links
                   : kind == RJ__SK_LOAD    ? P->cap_loads
                   : kind == RJ__SK_ACTUATOR ? P->cap_acts
                   : kind == RJ__SK_COUPLING ? P->cap_cps
                                            : P->cap_joints;
        if (count >= cap || count >= room)
            return rj__sp_err(P, t0->line, t0->col, rj__sk_kind[kind], count + 1, "too many ",
                              rj__sk_kind[kind], " sections (at most ", rj__sp_itoa(nb, cap), ")");
    }
    {
        rj_scene_pos head;
        head.line = t0->line;
        head.col = t0->col;
        switch (kind) {
        case RJ__SK_MATERIAL:
        case RJ__SK_SECTION: {
            rj__spart *s = kind == RJ__SK_MATERIAL ? &P->mat[P->nmat++] : &P->sec[P->nsec++];
            memset(s, 0, sizeof *s);
            memcpy(s->name, nt->s, (size_t) nt->len);
            s->d = rj_default_link_def();
            s->pos[0] = head;
            break;
        }
        case RJ__SK_LINK: {
            int n = P->f->link_count++;
            memcpy(P->f->link_names[n], nt->s, (size_t) nt->len);
            P->f->link_names[n][nt->len] = 0;
            P->f->links[n] = rj_default_link_def();
            P->f->link_pos_[(size_t) n * (1 + RJ__LK_N)] = head;
            P->link_mat = -1;
            P->link_sec = -1;
            break;
        }
        case RJ__SK_LOAD: {
            int n = P->f->load_count++;
            memcpy(P->f->load_names[n], nt->s, (size_t) nt->len);
            P->f->load_names[n][nt->len] = 0;
            P->f->loads[n] = rj_default_load_def();
            P->f->load_pos_[(size_t) n * (1 + RJ__AK_N)] = head;
            break;
        }
        case RJ__SK_ACTUATOR: {
            int n = P->f->actuator_count++;
            memcpy(P->f->actuator_names[n], nt->s, (size_t) nt->len);
            P->f->actuator_names[n][nt->len] = 0;
            P->f->actuators[n] = rj_default_actuator_def();
            P->f->actuator_pos_[(size_t) n * (1 + RJ__CK_N)] = head;
            break;
        }
        case RJ__SK_COUPLING: {
            int n = P->f->coupling_count++;
            memcpy(P->f->coupling_names[n], nt->s, (size_t) nt->len);
            P->f->coupling_names[n][nt->len] = 0;
            P->f->couplings[n] = rj_default_coupling_def();
            P->f->coupling_pos_[(size_t) n * (1 + RJ__PK_N)] = head;
            break;
        }
        default: {
            int n = P->f->joint_count++;
            memcpy(P->f->joint_names[n], nt->s, (size_t) nt->len);
            P->f->joint_names[n][nt->len] = 0;
            P->f->joints[n] = rj_default_joint_def();
            P->f->joint_pos_[(size_t) n * (1 + RJ__JK_N)] = head;
            break;
        }
        }
        P->kind = kind;
        P->item = count;
        P->seen = 0;
    }
    return 1;
}

/* text after a complete value of key kn at toks[v]; a unit word right after a number
   ("length = 1 m", "E = 70 GPa") gets why numbers take none */
static int rj__sp_trailing(rj__sp *P, int v, const char *kn)
{
    const rj__stok *t = &P->tok[v], *n = &P->tok[v - 1];
    char q[200], h[200], m[256];
    double x;
    h[0] = 0;
    if (t->kind == 'w' && rj__sp_alpha((unsigned char) t->s[0]) && n->kind == 'w' &&
        rj__sp_strtonum(n->s, n->len, P->dp, P->dplen, &x) == 1)
        rj__sp_unit_hint(h, kn, rj__sp_unit(kn), n->s, n->len, t->s, t->len);
    rj__sp_quote(q, sizeof q, t->s, t->len);
    rj__sp_cat(m, sizeof m, "unexpected '", q, "' after the value of '", kn, "'", rj__sp_where(P),
               h);
    return rj__sp_fail(P, t->line, t->col, kn, rj__sp_nan(), m);
}

/* whether toks[v] is a unit word after the number that starts the value of kn: checked
   before the value, so "dt = 10 us" says so instead of that 10 s is out of range. Not for
   angles and tables, whose numbers take deg or rad. */
static int rj__sp_unit_word(const rj__sp *P, int v, const char *kn)
{
    const rj__stok *t = &P->tok[v], *n = &P->tok[v - 1];
    const char *u = rj__sp_unit(kn);
    double x;
    if (strcmp(u, "rad") == 0 || strcmp(u, "rad/s") == 0 || strcmp(kn, "table") == 0)
        return 0;
    /* nan and inf spelled out are numbers, not units: the value's parse names them */
    if (t->kind == 'w' && rj__sp_strtonum(t->s, t->len, P->dp, P->dplen, &x) == -1)
        return 0;
    return t->kind == 'w' && rj__sp_alpha((unsigned char) t->s[0]) && n->kind == 'w' &&
           rj__sp_strtonum(n->s, n->len, P->dp, P->dplen, &x) == 1;
}

/* ------------------------------------------------------------------ title */
/* The first byte of a title that a file cannot hold on one line (a control byte: tab, CR),
   -1 when there is none. The writer refuses the same bytes, so what it writes reads back. */
static int rj__sp_title_bad(const char *s, int n)
{
    int k;
    for (k = 0; k < n; k++) {
        unsigned char c = (unsigned char) s[k];
        if (c < 0x20 || c == 0x7f)
            return k;
    }
    return -1;
}

/* a title's value: one quoted string, at most RJ_SCENE_TITLE_MAX - 1 bytes of text */
static int rj__sp_title_value(rj__sp *P, const rj__stok *v)
{
    char a[24], b[24], m[120];
    int n = v->len - 2;
    int bad;
    if (v->kind != 'q')
        return rj__sp_err_tok(P, v, "title", rj__sp_nan(), "expected a quoted string, found ",
                              " for 'title' (write title = \"text\")", NULL, NULL);
    if (n >= RJ_SCENE_TITLE_MAX) {
        rj__sp_cat(m, sizeof m, "title of ", rj__sp_itoa(a, n), " bytes is too long (at most ",
                   rj__sp_itoa(b, RJ_SCENE_TITLE_MAX - 1), ")", NULL, NULL);
        return rj__sp_fail(P, v->line, v->col, "title", (double) n, m);
    }
    bad = rj__sp_title_bad(v->s + 1, n);
    if (bad >= 0) {
        snprintf(m, sizeof m, "byte 0x%02x in the title: a title is printable text (no tabs)",
                 (unsigned char) v->s[1 + bad]);
        return rj__sp_fail(P, v->line, v->col + 1 + bad, "title", rj__sp_nan(), m);
    }
    memcpy(P->f->title, v->s + 1, (size_t) n);
    P->f->title[n] = 0;
    return 1;
}

/* title = "text", before the first section (toks[i..j)): once, a value, nothing after it */
static int rj__sp_title(rj__sp *P, int i, int j)
{
    const rj__stok *kt = &P->tok[i];
    char nb[24];
    if (P->title_line)
        return rj__sp_err(P, kt->line, kt->col, "title", rj__sp_nan(),
                          "duplicate title (first set on line ", rj__sp_itoa(nb, P->title_line),
                          ")", NULL, NULL);
    if (j == i + 2)
        return rj__sp_err(P, P->tok[i + 1].line, P->tok[i + 1].col + 1, "title", rj__sp_nan(),
                          "missing value for 'title'", NULL, NULL, NULL, NULL);
    if (!rj__sp_title_value(P, &P->tok[i + 2]))
        return 0;
    if (j > i + 3)
        return rj__sp_trailing(P, i + 3, "title");
    P->title_line = kt->line;
    return 1;
}

static int rj__sp_assignments(rj__sp *P)
{
    int i = 0;
    char nb[24];
    while (i < P->ntok) {
        const rj__stok *kt = &P->tok[i];
        const char *kn;
        int j = i + 2, k, v;
        while (j < P->ntok &&
               !(P->tok[j].kind == 'w' && j + 1 < P->ntok && P->tok[j + 1].kind == '='))
            j++;
        /* the one statement outside a section: the title, before the first section */
        if (P->kind == RJ__SK_NONE && rj__sp_is(kt, "title")) {
            if (!rj__sp_title(P, i, j))
                return 0;
            i = j;
            continue;
        }
        if (P->kind == RJ__SK_NONE) {
            char mean[48];
            return rj__sp_err_tok(
                P, kt, "", rj__sp_nan(), "key ",
                " outside any section (start one with solver, material, section, link, joint, "
                "load, actuator or coupling)",
                rj__sp_mean(mean, rj__sp_near(kt->s, kt->len, "title", 6, 1)), NULL);
        }
        k = rj__sp_key_index(P->kind, kt);
        /* a title inside a section: say where it belongs */
        if (k < 0 && rj__sp_is(kt, "title"))
            return rj__sp_err_tok(
                P, kt, "title", rj__sp_nan(), "unknown key ", rj__sp_where(P),
                " (a title goes at the top of the file, before the first section)", NULL);
        if (k < 0) {
            char q[64], mean[48];
            rj__sp_quote(q, sizeof q, kt->s, kt->len);
            return rj__sp_err_tok(P, kt, q, rj__sp_nan(), "unknown key ", rj__sp_where(P),
                                  rj__sp_mean(mean, rj__sp_near_key(P, kt)), NULL);
        }
        kn = rj__sp_key_name(P->kind, k);
        if (P->seen >> k & 1u)
            return rj__sp_err_tok5(P, kt, kn, rj__sp_nan(), "duplicate key ", rj__sp_where(P),
                                   " (first set on line ", rj__sp_itoa(nb, rj__sp_pos(P, k)->line),
                                   ")");
        if (j == i + 2) {
            const rj__stok *eq = &P->tok[i + 1];
            return rj__sp_err(P, eq->line, eq->col + 1, kn, rj__sp_nan(), "missing value for '", kn,
                              "'", rj__sp_where(P), NULL);
        }
        if (j > i + 3 && rj__sp_unit_word(P, i + 3, kn))
            return rj__sp_trailing(P, i + 3, kn);
        v = i + 2;
        switch (P->kind) {
        case RJ__SK_SOLVER:
            if (!rj__sp_solver_key(P, k, i + 2, &v, j, &P->f->solver))
                return 0;
            break;
        case RJ__SK_MATERIAL:
            if (!rj__sp_link_key(P, k, i + 2, &v, j, &P->mat[P->item].d))
                return 0;
            break;
        case RJ__SK_SECTION:
            if (!rj__sp_link_key(P, k, i + 2, &v, j, &P->sec[P->item].d))
                return 0;
            break;
        case RJ__SK_LINK:
            if (!rj__sp_link_key(P, k, i + 2, &v, j, &P->f->links[P->item]))
                return 0;
            break;
        case RJ__SK_LOAD:
            if (!rj__sp_load_key(P, k, i + 2, &v, j, &P->f->loads[P->item]))
                return 0;
            break;
        case RJ__SK_ACTUATOR:
            if (!rj__sp_actuator_key(P, k, i + 2, &v, j, &P->f->actuators[P->item]))
                return 0;
            break;
        case RJ__SK_COUPLING:
            if (!rj__sp_coupling_key(P, k, i + 2, &v, j, &P->f->couplings[P->item]))
                return 0;
            break;
        default:
            if (!rj__sp_joint_key(P, k, i + 2, &v, j, &P->f->joints[P->item]))
                return 0;
            break;
        }
        if (v < j)
            return rj__sp_trailing(P, v, kn);
        P->seen |= 1u << k;
        rj__sp_pos(P, k)->line = P->tok[i + 2].line;
        rj__sp_pos(P, k)->col = P->tok[i + 2].col;
        i = j;
    }
    return 1;
}

/* ------------------------------------------------------------------ lines */
static int rj__sp_is_sep(unsigned char c)
{
    return c == ' ' || c == '\t' || c == '=' || c == ',' || c == '#' || c < 0x20 || c == 0x7f;
}

/* Text is printable bytes, tabs and line ends (LF, CR). A NUL or another control byte
   anywhere, comments included, means the input is not a scene file, most likely a binary
   one: say so, with the first such byte and where it is, before parsing reports whatever
   its first "line" happens to look like (often one longer than RJ_SCENE_MAX_LINE). */
static int rj__sp_text(rj__sp *P)
{
    size_t k, bol = 0;
    int line = 1;
    for (k = 0; k < P->len; k++) {
        unsigned char c = (unsigned char) P->text[k];
        char m[200];
        if (c == '\n') {
            line++;
            bol = k + 1;
            continue;
        }
        if ((c >= 0x20 && c != 0x7f) || c == '\t' || c == '\r')
            continue;
        snprintf(m, sizeof m,
                 "not a text scene file: byte 0x%02x at byte offset %lu is a %s (a scene file has "
                 "only printable characters, tabs and line ends)",
                 c, (unsigned long) k, c ? "control character" : "NUL");
        return rj__sp_fail(P, line, (int) (k - bol) + 1, "", (double) c, m);
    }
    return 1;
}

/* a quoted string at s (its opening '"'), rest bytes to the line end, at column *k + 1:
   a 'q' token with the quotes, *k past it; 0 (the error set) when the line has no closing
   '"'. Titles need spaces, which separate tokens everywhere else. */
static int rj__sp_quoted(rj__sp *P, const char *s, size_t rest, size_t *k)
{
    const char *close = rest > 1 ? (const char *) memchr(s + 1, '"', rest - 1) : NULL;
    rj__stok *t = &P->tok[P->ntok];
    if (!close)
        return rj__sp_fail(P, P->lineno, (int) *k + 1, "", rj__sp_nan(),
                           "unterminated string: no closing '\"' on this line");
    t->s = s;
    t->len = (int) (close - s) + 1;
    t->line = P->lineno;
    t->col = (int) *k + 1;
    t->kind = 'q';
    P->ntok++;
    *k += (size_t) t->len;
    return 1;
}

/* next statement into P->tok: returns 1 (maybe empty), 0 at the end, -1 on error.
   A line whose last token is ',' continues on the next line. */
static int rj__sp_next(rj__sp *P)
{
    P->ntok = 0;
    if (P->at >= P->len)
        return 0;
    for (;;) {
        size_t start = P->at, end = start, n, k;
        char m[120];
        while (end < P->len && P->text[end] != '\n')
            end++;
        n = end - start;
        if (n && P->text[end - 1] == '\r')
            n--;
        P->lineno++;
        P->at = end < P->len ? end + 1 : end;
        if (n > RJ_SCENE_MAX_LINE) {
            snprintf(m, sizeof m, "line is longer than %d characters", RJ_SCENE_MAX_LINE);
            rj__sp_fail(P, P->lineno, RJ_SCENE_MAX_LINE + 1, "", rj__sp_nan(), m);
            return -1;
        }
        for (k = 0; k < n;) {
            const char *s = P->text + start + k;
            unsigned char c = (unsigned char) *s;
            if (c == '#')
                break;
            if (c == ' ' || c == '\t') {
                k++;
                continue;
            }
            if (c < 0x20 || c == 0x7f) { /* only a CR gets here: rj__sp_text let no other through */
                snprintf(m, sizeof m,
                         "invalid character 0x%02x (a carriage return ends a line only before a "
                         "line feed)",
                         c);
                rj__sp_fail(P, P->lineno, (int) k + 1, "", rj__sp_nan(), m);
                return -1;
            }
            if (P->ntok == RJ_SCENE_MAX_TOKENS) {
                snprintf(m, sizeof m, "statement has more than %d tokens", RJ_SCENE_MAX_TOKENS);
                rj__sp_fail(P, P->lineno, (int) k + 1, "", rj__sp_nan(), m);
                return -1;
            }
            /* a quoted string runs to the next '"' on the same line (no escapes) */
            if (c == '"') {
                if (!rj__sp_quoted(P, s, n - k, &k))
                    return -1;
                continue;
            }
            {
                rj__stok *t = &P->tok[P->ntok++];
                t->s = s;
                t->line = P->lineno;
                t->col = (int) k + 1;
                if (c == '=' || c == ',') {
                    t->kind = (char) c;
                    t->len = 1;
                    k++;
                } else {
                    size_t e = k + 1;
                    while (e < n && !rj__sp_is_sep((unsigned char) P->text[start + e]))
                        e++;
                    t->kind = 'w';
                    t->len = (int) (e - k);
                    k = e;
                }
            }
        }
        if (!(P->ntok > 0 && P->tok[P->ntok - 1].kind == ',' && P->at < P->len))
            return 1;
    }
}

/* counting pass: an upper bound on each kind of section (a first word that is a section
   keyword and is not followed by '='), capped one above the limits */
static void rj__sp_count(const char *text, size_t len, int counts[RJ__SK_COUNT])
{
    size_t at = 0;
    int k;
    for (k = 0; k < RJ__SK_COUNT; k++)
        counts[k] = 0;
    while (at < len) {
        size_t e, w;
        while (at < len && (text[at] == ' ' || text[at] == '\t'))
            at++;
        w = at;
        while (at < len && !rj__sp_is_sep((unsigned char) text[at]))
            at++;
        e = at;
        while (at < len && (text[at] == ' ' || text[at] == '\t'))
            at++;
        if (e > w && !(at < len && text[at] == '=')) {
            for (k = RJ__SK_MATERIAL; k <= RJ__SK_COUPLING; k++) {
                size_t n = strlen(rj__sk_kind[k]);
                if (e - w == n && memcmp(text + w, rj__sk_kind[k], n) == 0) {
                    int cap = k == RJ__SK_MATERIAL  ? RJ_SCENE_MAX_MATERIALS
                              : k == RJ__SK_SECTION ? RJ_SCENE_MAX_SECTIONS
                              : k == RJ__SK_LINK    ? RJ_SCENE_MAX_LINKS
                              : k == RJ__SK_LOAD    ? RJ_SCENE_MAX_LOADS
                              : k == RJ__SK_ACTUATOR ? RJ_SCENE_MAX_ACTUATORS
                              : k == RJ__SK_COUPLING ? RJ_SCENE_MAX_COUPLINGS
                                                    : RJ_SCENE_MAX_JOINTS;
                    if (counts[k] < cap)
                        counts[k]++;
                }
            }
        }
        while (at < len && text[at] != '\n')
            at++;
        if (at < len)
            at++;
    }
}

static size_t rj__sp_carve(size_t *off, size_t n, size_t el)
{
    size_t at = (*off + 15) / 16 * 16;
    *off = at + n * el;
    return at;
}

/* field "loads[2].force[1]" (prefix "loads[") -> position in f: the key's value, else
   the item's section line. Items of count, their positions (1 + nk per item), names,
   kind's rows; what: "load". */
static int rj__sp_item_pos(const char *field, const char *prefix, int count,
                           const rj_scene_pos *all, char (*names)[RJ_SCENE_NAME_MAX], int kind,
                           const char *what, rj_scene_pos *pos, char *item, size_t isize)
{
    const rj_scene_pos *ap;
    const char *p = field + strlen(prefix);
    const int nk = rj__key_count(kind);
    int n, idx = 0, digits = 0, k;
    const rj__field *rows = rj__fields(kind, &n);
    while (*p >= '0' && *p <= '9' && digits < 7) {
        idx = idx * 10 + (*p - '0');
        p++;
        digits++;
    }
    if (!digits || *p != ']' || idx >= count)
        return 0;
    p++;
    ap = &all[(size_t) idx * (1 + nk)];
    *pos = ap[0];
    for (k = 0; k < n && *p == '.'; k++) {
        /* the member's name, or the key's at its start ("table" of "table_time[2]") */
        const int key = rows[k].part_of >= 0 ? rows[k].part_of : k;
        const char *member = rows[k].member[0] ? rows[k].member : rows[k].key;
        const size_t len = strlen(member), klen = strlen(rows[k].key);
        const int named = strncmp(p + 1, member, len) == 0 &&
                          (p[1 + len] == 0 || p[1 + len] == '[');
        if (key < nk && (named || strncmp(p + 1, rows[k].key, klen) == 0) && ap[1 + key].line)
            *pos = ap[1 + key];
    }
    rj__sp_cat(item, isize, " (", what, " '", names[idx], "')", NULL, NULL);
    return pos->line > 0;
}

/* field "links[3].rho" / "joints[1].table_angle[2]" / "solver.dt" -> position in f */
static int rj__sp_field_pos(const rj_scene_file *f, const char *field, rj_scene_pos *pos,
                            char *item, size_t isize)
{
    int idx = 0, k, digits = 0, joint;
    const char *p;
    char name[40];
    size_t n = 0;
    item[0] = 0;
    if (strncmp(field, "solver.", 7) == 0) {
        for (k = 0; k < RJ__VK_N; k++)
            if (strcmp(field + 7, rj__solver_fields[k].key) == 0 && f->solver_pos_[1 + k].line) {
                *pos = f->solver_pos_[1 + k];
                return 1;
            }
        if (f->solver_pos_[0].line) {
            *pos = f->solver_pos_[0];
            return 1;
        }
        return 0;
    }
    if (strncmp(field, "loads[", 6) == 0)
        return rj__sp_item_pos(field, "loads[", f->load_count, f->load_pos_, f->load_names,
                               RJ__DEF_LOAD, "load", pos, item, isize);
    if (strncmp(field, "couplings[", 10) == 0)
        return rj__sp_item_pos(field, "couplings[", f->coupling_count, f->coupling_pos_,
                               f->coupling_names, RJ__DEF_COUPLING, "coupling", pos, item, isize);
    if (strncmp(field, "actuators[", 10) == 0)
        return rj__sp_item_pos(field, "actuators[", f->actuator_count, f->actuator_pos_,
                               f->actuator_names, RJ__DEF_ACTUATOR, "actuator", pos, item, isize);
    if (strncmp(field, "links[", 6) == 0) {
        joint = 0;
        p = field + 6;
    } else if (strncmp(field, "joints[", 7) == 0) {
        joint = 1;
        p = field + 7;
    } else
        return 0;
    while (*p >= '0' && *p <= '9' && digits < 7) {
        idx = idx * 10 + (*p - '0');
        p++;
        digits++;
    }
    if (!digits || *p != ']')
        return 0;
    p++;
    if (joint ? idx >= f->joint_count : idx >= f->link_count)
        return 0;
    if (*p == '.') {
        p++;
        while (p[n] && p[n] != '[' && n + 1 < sizeof name) {
            name[n] = p[n];
            n++;
        }
    }
    name[n] = 0;
    rj__sp_cat(item, isize, joint ? " (joint '" : " (link '",
               joint ? f->joint_names[idx] : f->link_names[idx], "')", NULL, NULL, NULL, NULL);
    if (!joint) {
        const rj_scene_pos *lp = &f->link_pos_[(size_t) idx * (1 + RJ__LK_N)];
        *pos = lp[0];
        for (k = 0; k < RJ__LK_N; k++)
            if (strcmp(name, rj__link_fields[k].key) == 0 && lp[1 + k].line)
                *pos = lp[1 + k];
        if (strcmp(name, "section") == 0) {
            if (lp[1 + RJ__LK_SECTION].line)
                *pos = lp[1 + RJ__LK_SECTION];
            else if (lp[1 + RJ__LK_AREA].line)
                *pos = lp[1 + RJ__LK_AREA];
        }
    } else {
        const rj_scene_pos *jp = &f->joint_pos_[(size_t) idx * (1 + RJ__JK_N)];
        int key = -1;
        *pos = jp[0];
        /* the key of the member's row, or of the key it is a part of */
        for (k = 0; k < RJ__JF_N; k++)
            if (strcmp(name, rj__joint_fields[k].member) == 0)
                key = rj__joint_fields[k].part_of >= 0 ? rj__joint_fields[k].part_of : k;
        if (strncmp(name, "table_", 6) == 0)
            key = RJ__JK_TABLE;
        if (key == RJ__JK_PENALTY_K && !jp[1 + key].line)
            key = RJ__JK_METHOD;
        if (key == RJ__JK_FORWARD && !jp[1 + key].line)
            key = RJ__JK_REVERSE;
        if (key >= 0 && jp[1 + key].line)
            *pos = jp[1 + key];
    }
    return pos->line > 0;
}

/* ------------------------------------------------------------------ links cut into pieces
   fidelity = pieces is the file's own link model, the rigid-finite-element layout of
   deploy_segmented_scene (examples/scenes.h): once the file and its changes are read, a
   link of N = elements segments of l = length / N becomes N + 1 rigid links (the two end
   pieces l / 2 long, the others l; the tip mass on the last) joined by N joints with a
   bending spring E I / l, free and started straight (180 deg). The pieces take the link's
   place among the links, named NAME (the first), NAME_p1 .. NAME_pN; its springs NAME_b1 ..
   NAME_bN follow the first joint that holds the link as body2 (else the file's joints).
   Node k of the link (at k l from its root) is piece k's middle for 0 < k < N (that
   piece then has 2 elements: a rigid link's mass and inertia do not depend on them),
   node 0 the first piece's root, node N the last piece's tip. The arrays grow in place:
   the counting pass gave them the most links and joints a scene may have when the text
   says "pieces" (rj__sp_says_pieces). */
typedef struct rj__sp_plan {
    int n[RJ_SCENE_MAX_LINKS];             /* each file link's segments when cut, else 0 */
    int base[RJ_SCENE_MAX_LINKS];          /* its first link after the cut */
    int bend[RJ_SCENE_MAX_LINKS];          /* a cut link's first spring joint, -1 none yet */
    double k[RJ_SCENE_MAX_LINKS];          /* a cut link's spring stiffness E I / l */
    int jnew[RJ_SCENE_MAX_JOINTS];         /* each file joint's index after the cut */
    unsigned char mid[RJ_SCENE_MAX_LINKS]; /* links after the cut with a middle node */
    int tail;                              /* the first spring that follows no file joint */
    int links, joints;                     /* the counts after the cut */
} rj__sp_plan;

/* whether "pieces" is anywhere in the text or the changes (in a comment too: that only
   costs the room) */
static int rj__sp_says_pieces(const char *text, size_t len, const char *const *sets, int nsets)
{
    size_t k;
    int s;
    for (k = 0; k + 6 <= len; k++)
        if (text[k] == 'p' && memcmp(text + k, "pieces", 6) == 0)
            return 1;
    for (s = 0; s < nsets; s++)
        if (strstr(sets[s], "pieces"))
            return 1;
    return 0;
}

/* where key k of file link i is written: its value, else the link's section line */
static rj_scene_pos rj__sp_link_at(const rj_scene_file *f, int i, int k)
{
    const rj_scene_pos *p = &f->link_pos_[(size_t) i * (1 + RJ__LK_N)];
    return p[1 + k].line ? p[1 + k] : p[0];
}

/* node k of a link cut into n segments (-1: its last): the piece holding it and that
   piece's node (the middle, 1, of an inner piece; -1 stays last) */
static void rj__sp_piece_node(int n, int k, int *piece, int *node)
{
    *piece = k < 0 ? n : k;
    *node = k < 0 ? -1 : k == 0 ? 0 : 1;
}

/* "NAME", or "NAME_p3" (tag "_p", k 3) */
static void rj__sp_piece_name(char *dst, const char *name, const char *tag, int k)
{
    char nb[24];
    rj__sp_cat(dst, RJ_SCENE_NAME_MAX, name, k ? tag : NULL, k ? rj__sp_itoa(nb, k) : NULL, NULL,
               NULL, NULL, NULL);
}

/* more links (links 1) or joints (0) after the cut, total, than a scene may have, max:
   refused at the elements of the link cut into the most pieces, naming the counts */
static int rj__sp_cut_over(rj__sp *P, const rj__sp_plan *pl, int links, int total, int max)
{
    const rj_scene_file *f = P->f;
    char a[24], b[24], c[24], d[24], m[256], m2[256];
    rj_scene_pos at;
    int i, big = 0;
    for (i = 1; i < f->link_count; i++)
        if (pl->n[i] > pl->n[big])
            big = i;
    at = rj__sp_link_at(f, big, RJ__LK_ELEMENTS);
    rj__sp_cat(m, sizeof m, "elements = ", rj__sp_itoa(a, pl->n[big]), " in link '",
               f->link_names[big], "' (fidelity = pieces) makes ",
               rj__sp_itoa(b, pl->n[big] + links), links ? " rigid pieces" : " bending joints");
    rj__sp_cat(m2, sizeof m2, m, ": the scene would have ", rj__sp_itoa(c, total),
               links ? " links" : " joints", ", more than the ", rj__sp_itoa(d, max), NULL);
    return rj__sp_err(P, at.line, at.col, "elements", pl->n[big], m2, " a scene may have", NULL,
                      NULL, NULL);
}

/* The links after the cut: where each file link goes, its segments and spring stiffness;
   refused when they are more than a scene may have (the cap is RJ_SCENE_MAX_LINKS when
   the text says "pieces") or a piece's name would be too long. */
static int rj__sp_plan_links(rj__sp *P, rj__sp_plan *pl)
{
    const rj_scene_file *f = P->f;
    int i, at = 0;
    for (i = 0; i < f->link_count; i++) {
        pl->n[i] = P->pieces[i] ? f->links[i].elements : 0;
        pl->base[i] = at;
        pl->bend[i] = -1;
        at += pl->n[i] + 1;
    }
    if (at > P->cap_links)
        return rj__sp_cut_over(P, pl, 1, at, P->cap_links);
    pl->links = at;
    for (i = 0; i < f->link_count; i++) {
        const rj_link_def *d = &f->links[i];
        char nb[24], last[64];
        double A, I;
        if (!pl->n[i])
            continue;
        rj__sp_cat(last, sizeof last, f->link_names[i], "_p", rj__sp_itoa(nb, pl->n[i]), NULL, NULL,
                   NULL, NULL);
        if (strlen(last) >= RJ_SCENE_NAME_MAX) {
            const rj_scene_pos h = f->link_pos_[(size_t) i * (1 + RJ__LK_N)];
            return rj__sp_err(P, h.line, h.col, "link", rj__sp_nan(), "link name '",
                              f->link_names[i],
                              "' is too long for fidelity = pieces: its last piece would be '",
                              last, "' (names are 1..31 characters)");
        }
        /* the flexible link's E I (rj__link_section), over the segment's length */
        rj__link_section(d, &A, &I);
        pl->k[i] = d->E * I / (d->length / pl->n[i]);
    }
    return 1;
}

/* A joint's body2 on cut link: the first piece's root, node2 = 0, the one node it can be
   (the pieces hang from it, each from the one before) */
static int rj__sp_cut_node2(rj__sp *P, int j)
{
    const rj_scene_file *f = P->f;
    const rj_joint_def *d = &f->joints[j];
    const rj_scene_pos *p = &f->joint_pos_[(size_t) j * (1 + RJ__JK_N)];
    const rj_scene_pos at = p[1 + RJ__JK_NODE2].line ? p[1 + RJ__JK_NODE2] : p[0];
    char a[24], m[256];
    rj__sp_cat(m, sizeof m, "node2 = ", d->node2 < 0 ? "last" : rj__sp_itoa(a, d->node2),
               " in joint '", f->joint_names[j], "' cannot be placed: link '",
               f->link_names[d->body2], "' is cut into pieces (fidelity = pieces)");
    return rj__sp_err(P, at.line, at.col, "node2", d->node2, m,
                      ", which hang from its node 0: a joint holds it there (node2 = 0)", NULL,
                      NULL, NULL);
}

/* The joints after the cut (as many as the file's and the cut links' segments; the cap
   is RJ_SCENE_MAX_JOINTS when the text says "pieces"): each file joint's index, each cut
   link's springs after the first joint that holds it as body2 (else after the file's
   joints); the inner pieces a joint's node1 or a load's node sits in the middle of. */
static int rj__sp_plan_joints(rj__sp *P, rj__sp_plan *pl)
{
    const rj_scene_file *f = P->f;
    int i, j, at = 0;
    pl->joints = f->joint_count;
    for (i = 0; i < f->link_count; i++)
        pl->joints += pl->n[i];
    if (pl->joints > P->cap_joints)
        return rj__sp_cut_over(P, pl, 0, pl->joints, P->cap_joints);
    for (j = 0; j < f->joint_count; j++) {
        const rj_joint_def *d = &f->joints[j];
        pl->jnew[j] = at++;
        if (pl->n[d->body2] && d->node2 != 0)
            return rj__sp_cut_node2(P, j);
        if (pl->n[d->body2] && pl->bend[d->body2] < 0) {
            pl->bend[d->body2] = at;
            at += pl->n[d->body2];
        }
        if (d->body1 >= 0 && d->node1 > 0 && d->node1 < pl->n[d->body1])
            pl->mid[pl->base[d->body1] + d->node1] = 1;
    }
    pl->tail = at;
    for (i = 0; i < f->link_count; i++)
        if (pl->n[i] && pl->bend[i] < 0) {
            pl->bend[i] = at;
            at += pl->n[i];
        }
    for (i = 0; i < f->load_count; i++) {
        const rj_load_def *d = &f->loads[i];
        if (d->node > 0 && d->node < pl->n[d->link])
            pl->mid[pl->base[d->link] + d->node] = 1;
    }
    return 1;
}

/* piece k of the link d cut into n segments (mid: it has a middle node); the first
   keeps the link's root, placement and initial motion, the others hang from springs */
static rj_link_def rj__sp_piece(const rj_link_def *d, int n, int k, int mid)
{
    const double l = d->length / n;
    const rj_link_def z = rj_default_link_def();
    rj_link_def p = *d;
    p.elements = mid ? 2 : 1;
    p.fidelity = RJ_LINK_RIGID;
    p.length = k == 0 || k == n ? 0.5 * l : l;
    /* the tip mass rides on the last piece */
    p.tip_mass = k == n ? d->tip_mass : 0.0;
    p.tip_inertia = k == n ? d->tip_inertia : 0.0;
    if (k == 0)
        return p;
    p.root = z.root;
    p.x = z.x;
    p.y = z.y;
    p.angle = z.angle;
    p.vx = z.vx;
    p.vy = z.vy;
    p.omega = z.omega;
    return p;
}

/* The links after the cut, written from the last back: each lands at or after where it
   was, so none is overwritten before it is read. Every piece keeps the link's places in
   the file, for messages. */
static void rj__sp_move_links(rj__sp *P, const rj__sp_plan *pl)
{
    rj_scene_file *f = P->f;
    const size_t np = 1 + RJ__LK_N;
    int i, k;
    for (i = f->link_count - 1; i >= 0; i--) {
        const rj_link_def d = f->links[i];
        rj_scene_pos pos[1 + RJ__LK_N];
        char name[RJ_SCENE_NAME_MAX];
        memcpy(pos, &f->link_pos_[(size_t) i * np], sizeof pos);
        memcpy(name, f->link_names[i], sizeof name);
        for (k = pl->n[i]; k >= 0; k--) {
            const int x = pl->base[i] + k;
            f->links[x] = pl->n[i] ? rj__sp_piece(&d, pl->n[i], k, pl->mid[x]) : d;
            memcpy(&f->link_pos_[(size_t) x * np], pos, sizeof pos);
            rj__sp_piece_name(f->link_names[x], name, "_p", k);
        }
    }
    f->link_count = pl->links;
}

/* cut file link i's springs (the links not moved yet: its name and places are the
   file's), each at the fidelity key (else the link's section line) for messages */
static void rj__sp_put_bend(rj__sp *P, const rj__sp_plan *pl, int i)
{
    rj_scene_file *f = P->f;
    const rj_scene_pos at = rj__sp_link_at(f, i, RJ__LK_FIDELITY);
    int k;
    for (k = 1; k <= pl->n[i]; k++) {
        const int x = pl->bend[i] + k - 1;
        rj_scene_pos *pos = &f->joint_pos_[(size_t) x * (1 + RJ__JK_N)];
        rj_joint_def *d = &f->joints[x];
        *d = rj_default_joint_def();
        d->body1 = pl->base[i] + k - 1;
        d->node1 = -1;
        d->body2 = pl->base[i] + k;
        /* a bending spring: straight (theta = pi) is its free angle */
        d->angle0 = rj_rad(180.0);
        d->spring_k = pl->k[i];
        d->spring_free_angle = rj_rad(180.0);
        memset(pos, 0, sizeof(rj_scene_pos) * (1 + RJ__JK_N));
        pos[0] = at;
        rj__sp_piece_name(f->joint_names[x], f->link_names[i], "_b", k);
    }
}

/* a joint's bodies after the cut: on a cut link body1's node goes to the piece holding
   it (rj__sp_piece_node), body2 is the first piece */
static void rj__sp_remap_joint(const rj__sp_plan *pl, rj_joint_def *d)
{
    int piece = 0;
    if (d->body1 >= 0 && pl->n[d->body1])
        rj__sp_piece_node(pl->n[d->body1], d->node1, &piece, &d->node1);
    if (d->body1 >= 0)
        d->body1 = pl->base[d->body1] + piece;
    d->body2 = pl->base[d->body2];
}

/* The joints after the cut, written from the last back as the links are: first the
   springs after every file joint, then each file joint and the springs that follow it. */
static void rj__sp_move_joints(rj__sp *P, const rj__sp_plan *pl)
{
    rj_scene_file *f = P->f;
    const size_t np = 1 + RJ__JK_N;
    int i, j;
    for (i = 0; i < f->link_count; i++)
        if (pl->n[i] && pl->bend[i] >= pl->tail)
            rj__sp_put_bend(P, pl, i);
    for (j = f->joint_count - 1; j >= 0; j--) {
        rj_joint_def d = f->joints[j];
        rj_scene_pos pos[1 + RJ__JK_N];
        char name[RJ_SCENE_NAME_MAX];
        const int b2 = d.body2, x = pl->jnew[j];
        memcpy(pos, &f->joint_pos_[(size_t) j * np], sizeof pos);
        memcpy(name, f->joint_names[j], sizeof name);
        if (pl->n[b2] && pl->bend[b2] == x + 1)
            rj__sp_put_bend(P, pl, b2);
        rj__sp_remap_joint(pl, &d);
        f->joints[x] = d;
        memcpy(&f->joint_pos_[(size_t) x * np], pos, sizeof pos);
        memcpy(f->joint_names[x], name, sizeof name);
    }
    f->joint_count = pl->joints;
}

/* loads, actuators and couplings: their links' nodes and their joints after the cut */
static void rj__sp_remap_rest(rj__sp *P, const rj__sp_plan *pl)
{
    rj_scene_file *f = P->f;
    int i;
    for (i = 0; i < f->load_count; i++) {
        rj_load_def *d = &f->loads[i];
        int piece = 0;
        if (pl->n[d->link])
            rj__sp_piece_node(pl->n[d->link], d->node, &piece, &d->node);
        d->link = pl->base[d->link] + piece;
    }
    for (i = 0; i < f->actuator_count; i++)
        f->actuators[i].joint = pl->jnew[f->actuators[i].joint];
    for (i = 0; i < f->coupling_count; i++) {
        f->couplings[i].joint_a = pl->jnew[f->couplings[i].joint_a];
        f->couplings[i].joint_b = pl->jnew[f->couplings[i].joint_b];
    }
}

/* names[x], the name made for piece or spring k of a cut link whose first piece is link
   f0 after the cut, that another of the count names (the links' or the joints', their
   places pos) has too: refused at the link's fidelity key, naming both */
static int rj__sp_cut_clash(rj__sp *P, char (*names)[RJ_SCENE_NAME_MAX], int count, int x, int f0,
                            const char *what, int k, const rj_scene_pos *pos)
{
    const rj_scene_file *f = P->f;
    const rj_scene_pos *fp = &f->link_pos_[(size_t) f0 * (1 + RJ__LK_N)];
    const int link = names == f->link_names;
    const size_t np = link ? 1 + RJ__LK_N : 1 + RJ__JK_N;
    const rj_scene_pos at = fp[1 + RJ__LK_FIDELITY].line ? fp[1 + RJ__LK_FIDELITY] : fp[0];
    char a[24], b[24], m[256], m2[256];
    int y;
    for (y = 0; y < count; y++)
        if (y != x && strcmp(names[y], names[x]) == 0)
            break;
    if (y == count)
        return 1;
    rj__sp_cat(m, sizeof m, "fidelity = pieces in link '", f->link_names[f0], "' names its ", what,
               " ", rj__sp_itoa(a, k), " '");
    rj__sp_cat(m2, sizeof m2, m, names[x], "', which the ", link ? "link" : "joint", " on line ",
               rj__sp_itoa(b, pos[(size_t) y * np].line), " has too");
    return rj__sp_err(P, at.line, at.col, "fidelity", rj__sp_nan(), m2,
                      " (rename one: a link's pieces are NAME_p1.., its springs NAME_b1..)", NULL,
                      NULL, NULL);
}

/* The names made for the pieces (NAME_pK) and the springs (NAME_bK) after the cut: none
   may be another link's or joint's. */
static int rj__sp_cut_names(rj__sp *P, const rj__sp_plan *pl, int file_links)
{
    rj_scene_file *f = P->f;
    int i, k;
    for (i = 0; i < file_links; i++)
        for (k = 1; k <= pl->n[i]; k++) {
            if (!rj__sp_cut_clash(P, f->link_names, f->link_count, pl->base[i] + k, pl->base[i],
                                  "piece", k, f->link_pos_))
                return 0;
            if (!rj__sp_cut_clash(P, f->joint_names, f->joint_count, pl->bend[i] + k - 1,
                                  pl->base[i], "bending joint", k, f->joint_pos_))
                return 0;
        }
    return 1;
}

/* The file's links with fidelity = pieces cut into their pieces and springs, the other
   items following them (see the top of this part); 1 when there are none. */
static int rj__sp_cut(rj__sp *P)
{
    rj__sp_plan pl;
    const int file_links = P->f->link_count;
    int i, any = 0;
    for (i = 0; i < file_links; i++)
        any |= P->pieces[i];
    if (!any)
        return 1;
    memset(&pl, 0, sizeof pl);
    if (!rj__sp_plan_links(P, &pl) || !rj__sp_plan_joints(P, &pl))
        return 0;
    /* the joints first: their springs take the file links' names and places */
    rj__sp_move_joints(P, &pl);
    rj__sp_move_links(P, &pl);
    rj__sp_remap_rest(P, &pl);
    return rj__sp_cut_names(P, &pl, file_links);
}

/* ------------------------------------------------------------------ public */
RJDEF void rj_scene_file_locate(const rj_scene_file *f, rj_error *err)
{
    char m[sizeof err->msg], item[80];
    rj_scene_pos pos;
    if (!f || !err)
        return;
    if (rj__sp_field_pos(f, err->field, &pos, item, sizeof item)) {
        char l[24], c[24], m1[sizeof err->msg];
        rj__sp_cat(m1, sizeof m1, f->filename, ":", rj__sp_itoa(l, pos.line), ":",
                   rj__sp_itoa(c, pos.col), ": ", NULL);
        rj__sp_cat(m, sizeof m, m1, err->msg, item, NULL, NULL, NULL, NULL);
    } else
        rj__sp_cat(m, sizeof m, f->filename, ": ", err->msg, NULL, NULL, NULL, NULL);
    memcpy(err->msg, m, sizeof m);
}

/* The parser: rj_scene_parse_ex, with the changes sets (nsets, 0..RJ_SCENE_MAX_SETS)
   taken at their sections' ends. */
static rj_result rj__sp_parse(const char *text, size_t len, const char *filename,
                              const char *const *sets, int nsets, rj_scene_file *out,
                              rj_error *err, void *alloc_ctx)
{
    rj__sp P;
    rj_scene_file F;
    int counts[RJ__SK_COUNT], r;
    size_t off = 0, o_links, o_joints, o_lpos, o_jpos, o_lnames, o_jnames, w_tok, w_mat, w_sec, w_set;
    size_t o_loads, o_apos, o_anames, o_acts, o_cpos, o_cnames, o_cps, o_ppos, o_pnames;
    char *block = NULL, *work = NULL;
    memset(&P, 0, sizeof P);
    memset(&F, 0, sizeof F);
    if (err) {
        err->code = RJ_OK;
        err->field[0] = 0;
        err->msg[0] = 0;
        err->value = 0;
    }
    P.fname = filename ? filename : "<input>";
    P.err = err;
    if (!out || (!text && len)) {
        if (err) {
            err->code = RJ_ERR_INVALID;
            snprintf(err->field, sizeof err->field, "%s", out ? "text" : "out");
            err->value = 0;
            snprintf(err->msg, sizeof err->msg, "%s is NULL", out ? "text" : "out");
        }
        if (out)
            memset(out, 0, sizeof *out);
        return RJ_ERR_INVALID;
    }
    memset(out, 0, sizeof *out);
    if (len > RJ_SCENE_MAX_BYTES) {
        char m[120];
        snprintf(m, sizeof m, "input of %lu bytes is larger than the %lu a scene file may have",
                 (unsigned long) len, (unsigned long) RJ_SCENE_MAX_BYTES);
        rj__sp_fail(&P, 1, 1, "", (double) len, m);
        return RJ_ERR_PARSE;
    }
    P.text = text ? text : "";
    P.len = len;
    if (!rj__sp_text(&P))
        return RJ_ERR_PARSE;
    rj__sp_locale(P.dp, &P.dplen);
    rj__sp_count(P.text, len, counts);
    P.cap_links = counts[RJ__SK_LINK];
    P.cap_joints = counts[RJ__SK_JOINT];
    P.cap_mat = counts[RJ__SK_MATERIAL];
    P.cap_sec = counts[RJ__SK_SECTION];
    P.cap_loads = counts[RJ__SK_LOAD];
    P.cap_acts = counts[RJ__SK_ACTUATOR];
    P.cap_cps = counts[RJ__SK_COUPLING];
    /* links cut into pieces (rj__sp_cut) grow the links and joints in place */
    if (rj__sp_says_pieces(P.text, len, sets, nsets)) {
        P.cap_links = RJ_SCENE_MAX_LINKS;
        P.cap_joints = RJ_SCENE_MAX_JOINTS;
    }
    /* the result block */
    o_links = rj__sp_carve(&off, (size_t) P.cap_links, sizeof(rj_link_def));
    o_joints = rj__sp_carve(&off, (size_t) P.cap_joints, sizeof(rj_joint_def));
    o_lpos = rj__sp_carve(&off, (size_t) P.cap_links * (1 + RJ__LK_N), sizeof(rj_scene_pos));
    o_jpos = rj__sp_carve(&off, (size_t) P.cap_joints * (1 + RJ__JK_N), sizeof(rj_scene_pos));
    o_lnames = rj__sp_carve(&off, (size_t) P.cap_links, RJ_SCENE_NAME_MAX);
    o_loads = rj__sp_carve(&off, (size_t) P.cap_loads, sizeof(rj_load_def));
    o_apos = rj__sp_carve(&off, (size_t) P.cap_loads * (1 + RJ__AK_N), sizeof(rj_scene_pos));
    o_anames = rj__sp_carve(&off, (size_t) P.cap_loads, RJ_SCENE_NAME_MAX);
    o_acts = rj__sp_carve(&off, (size_t) P.cap_acts, sizeof(rj_actuator_def));
    o_cpos = rj__sp_carve(&off, (size_t) P.cap_acts * (1 + RJ__CK_N), sizeof(rj_scene_pos));
    o_cnames = rj__sp_carve(&off, (size_t) P.cap_acts, RJ_SCENE_NAME_MAX);
    o_cps = rj__sp_carve(&off, (size_t) P.cap_cps, sizeof(rj_coupling_def));
    o_ppos = rj__sp_carve(&off, (size_t) P.cap_cps * (1 + RJ__PK_N), sizeof(rj_scene_pos));
    o_pnames = rj__sp_carve(&off, (size_t) P.cap_cps, RJ_SCENE_NAME_MAX);
    o_jnames = rj__sp_carve(&off, (size_t) P.cap_joints, RJ_SCENE_NAME_MAX);
    block = (char *) RJ_MALLOC(off + 16, alloc_ctx);
    /* the parser's workspace: tokens, materials, sections */
    off = 0;
    w_tok = rj__sp_carve(&off, RJ_SCENE_MAX_TOKENS, sizeof(rj__stok));
    w_mat = rj__sp_carve(&off, (size_t) P.cap_mat, sizeof(rj__spart));
    w_sec = rj__sp_carve(&off, (size_t) P.cap_sec, sizeof(rj__spart));
    w_set = rj__sp_carve(&off, nsets ? RJ_SCENE_MAX_TOKENS : 0, sizeof(rj__stok));
    work = block ? (char *) RJ_MALLOC(off + 16, alloc_ctx) : NULL;
    if (!block || !work) {
        if (block)
            RJ_FREE(block, alloc_ctx);
        if (err) {
            err->code = RJ_ERR_NOMEM;
            snprintf(err->field, sizeof err->field, "size");
            err->value = (double) off;
            rj__sp_cat(err->msg, sizeof err->msg, P.fname, ": out of memory", NULL, NULL, NULL,
                       NULL, NULL);
        }
        return RJ_ERR_NOMEM;
    }
    memset(block, 0, o_jnames + (size_t) P.cap_joints * RJ_SCENE_NAME_MAX);
    F.links = (rj_link_def *) (void *) (block + o_links);
    F.joints = (rj_joint_def *) (void *) (block + o_joints);
    F.link_pos_ = (rj_scene_pos *) (void *) (block + o_lpos);
    F.joint_pos_ = (rj_scene_pos *) (void *) (block + o_jpos);
    F.link_names = (char(*)[RJ_SCENE_NAME_MAX])(void *) (block + o_lnames);
    F.joint_names = (char(*)[RJ_SCENE_NAME_MAX])(void *) (block + o_jnames);
    F.loads = (rj_load_def *) (void *) (block + o_loads);
    F.load_pos_ = (rj_scene_pos *) (void *) (block + o_apos);
    F.load_names = (char(*)[RJ_SCENE_NAME_MAX])(void *) (block + o_anames);
    F.actuators = (rj_actuator_def *) (void *) (block + o_acts);
    F.actuator_pos_ = (rj_scene_pos *) (void *) (block + o_cpos);
    F.actuator_names = (char(*)[RJ_SCENE_NAME_MAX])(void *) (block + o_cnames);
    F.couplings = (rj_coupling_def *) (void *) (block + o_cps);
    F.coupling_pos_ = (rj_scene_pos *) (void *) (block + o_ppos);
    F.coupling_names = (char(*)[RJ_SCENE_NAME_MAX])(void *) (block + o_pnames);
    F.solver = rj_default_solver_def();
    F.block_ = block;
    F.alloc_ctx_ = alloc_ctx;
    rj__sp_cat(F.filename, sizeof F.filename, P.fname, NULL, NULL, NULL, NULL, NULL, NULL);
    P.f = &F;
    P.tok = (rj__stok *) (void *) (work + w_tok);
    P.mat = (rj__spart *) (void *) (work + w_mat);
    P.sec = (rj__spart *) (void *) (work + w_sec);
    P.set_tok = (rj__stok *) (void *) (work + w_set);
    P.sets = sets;
    P.nsets = nsets;
    P.kind = RJ__SK_NONE;

    while ((r = rj__sp_next(&P)) > 0) {
        if (!P.ntok)
            continue;
        if (P.tok[0].kind != 'w') {
            rj__sp_err_tok(&P, &P.tok[0], "", rj__sp_nan(),
                           "expected a key or a section keyword, found ", NULL, NULL, NULL);
            goto fail;
        }
        if (P.ntok >= 2 && P.tok[1].kind == '=') {
            if (!rj__sp_assignments(&P))
                goto fail;
        } else if (!rj__sp_header(&P))
            goto fail;
    }
    if (r < 0 || !rj__sp_finish(&P) || (nsets && !rj__sp_sets_left(&P)))
        goto fail;
    if (F.link_count == 0) {
        rj__sp_fail(&P, P.lineno > 0 ? P.lineno : 1, 1, "link_count", 0,
                    "the scene has no links (a scene needs at least one 'link' section)");
        goto fail;
    }
    if (!rj__sp_cut(&P))
        goto fail;
    RJ_FREE(work, alloc_ctx);
    work = NULL;
    { /* the model's own validation, located in the file */
        rj_scene_def sd = rj_scene_file_def(&F);
        rj_error me;
        if (rj__validate_all(&sd, &me, alloc_ctx) != RJ_OK) {
            rj_scene_file_locate(&F, &me);
            P.code = me.code;
            if (err)
                *err = me;
            goto fail;
        }
    }
    *out = F;
    return RJ_OK;
fail:
    if (work)
        RJ_FREE(work, alloc_ctx);
    RJ_FREE(block, alloc_ctx);
    memset(out, 0, sizeof *out);
    return P.code != RJ_OK ? P.code : RJ_ERR_PARSE;
}

RJDEF rj_result rj_scene_parse_ex(const char *text, size_t len, const char *filename,
                                  rj_scene_file *out, rj_error *err, void *alloc_ctx)
{
    return rj__sp_parse(text, len, filename, NULL, 0, out, err, alloc_ctx);
}

RJDEF rj_result rj_scene_parse(const char *text, size_t len, const char *filename,
                               rj_scene_file *out, rj_error *err)
{
    return rj_scene_parse_ex(text, len, filename, out, err, NULL);
}

/* The changes' own checks: a count in 0..RJ_SCENE_MAX_SETS, each a string of a line's
   length at most. */
static int rj__sp_sets_ok(const char *const *sets, int nsets, rj_error *err)
{
    int k;
    const char *bad = nsets < 0 || nsets > RJ_SCENE_MAX_SETS || (nsets && !sets)
                          ? "must be 0..64 changes, and the array there"
                          : NULL;
    for (k = 0; !bad && k < nsets; k++)
        if (!sets[k] || strlen(sets[k]) > RJ_SCENE_MAX_LINE)
            bad = "a change is a string of at most RJ_SCENE_MAX_LINE characters";
    if (!bad)
        return 1;
    if (err) {
        err->code = RJ_ERR_INVALID;
        snprintf(err->field, sizeof err->field, "nsets");
        err->value = nsets;
        snprintf(err->msg, sizeof err->msg, "nsets = %d: %s", nsets, bad);
    }
    return 0;
}

RJDEF rj_result rj_scene_parse_set(const char *text, size_t len, const char *filename,
                                   const char *const *sets, int nsets, rj_scene_file *out,
                                   rj_error *err)
{
    if (out)
        memset(out, 0, sizeof *out);
    if (!rj__sp_sets_ok(sets, nsets, err))
        return RJ_ERR_INVALID;
    return rj__sp_parse(text, len, filename, sets, nsets, out, err, NULL);
}

/* a failure of rj_scene_load: "path: what: the system's reason" when errnum is set (the
   user needs to know whether the file is missing, unreadable or a directory) */
static rj_result rj__sp_load_fail(rj_error *err, rj_result code, const char *path, const char *what,
                                  int errnum, double value)
{
    if (!err)
        return code;
    err->code = code;
    snprintf(err->field, sizeof err->field, "%s", code == RJ_ERR_NOMEM ? "size" : "path");
    err->value = value;
    rj__sp_cat(err->msg, sizeof err->msg, path, ": ", what, errnum ? ": " : "",
               errnum ? strerror(errnum) : "", NULL, NULL);
    return code;
}

/* reads all of fp into *buf (RJ_MALLOC; the caller frees it, also on failure), at most
   RJ_SCENE_MAX_BYTES */
static rj_result rj__sp_read(FILE *fp, const char *path, char **buf, size_t *n, rj_error *err)
{
    size_t cap = 0;
    *buf = NULL;
    *n = 0;
    for (;;) {
        size_t got;
        if (*n == cap) {
            size_t nc = cap ? cap * 2 : 65536;
            char *nb;
            if (nc > (size_t) RJ_SCENE_MAX_BYTES + 1)
                nc = (size_t) RJ_SCENE_MAX_BYTES + 1;
            if (cap > RJ_SCENE_MAX_BYTES)
                return rj__sp_load_fail(err, RJ_ERR_PARSE, path,
                                        "the file is larger than 64 MiB (RJ_SCENE_MAX_BYTES)", 0,
                                        (double) *n);
            nb = (char *) RJ_MALLOC(nc, NULL);
            if (!nb)
                return rj__sp_load_fail(err, RJ_ERR_NOMEM, path, "out of memory reading the file",
                                        0, (double) nc);
            if (*n)
                memcpy(nb, *buf, *n);
            if (*buf)
                RJ_FREE(*buf, NULL);
            *buf = nb;
            cap = nc;
        }
        errno = 0;
        got = fread(*buf + *n, 1, cap - *n, fp);
        *n += got;
        if (got == 0)
            break;
    }
    if (ferror(fp))
        return rj__sp_load_fail(err, RJ_ERR_PARSE, path, "cannot read the file", errno, errno);
    return RJ_OK;
}

RJDEF rj_result rj_scene_load_set(const char *path, const char *const *sets, int nsets,
                                  rj_scene_file *out, rj_error *err)
{
    FILE *fp;
    char *buf = NULL;
    size_t n = 0;
    rj_result r;
    if (out)
        memset(out, 0, sizeof *out);
    if (!path || !out) {
        if (err) {
            err->code = RJ_ERR_INVALID;
            snprintf(err->field, sizeof err->field, "%s", path ? "out" : "path");
            err->value = 0;
            snprintf(err->msg, sizeof err->msg, "%s is NULL", path ? "out" : "path");
        }
        return RJ_ERR_INVALID;
    }
    if (!rj__sp_sets_ok(sets, nsets, err))
        return RJ_ERR_INVALID;
    errno = 0;
    fp = fopen(path, "rb");
    if (!fp)
        return rj__sp_load_fail(err, RJ_ERR_PARSE, path, "cannot open the file for reading", errno,
                                errno);
    r = rj__sp_read(fp, path, &buf, &n, err);
    fclose(fp);
    if (r == RJ_OK)
        r = rj__sp_parse(buf, n, path, sets, nsets, out, err, NULL);
    if (buf)
        RJ_FREE(buf, NULL);
    return r;
}

RJDEF rj_result rj_scene_load(const char *path, rj_scene_file *out, rj_error *err)
{
    return rj_scene_load_set(path, NULL, 0, out, err);
}

RJDEF rj_scene_def rj_scene_file_def(const rj_scene_file *f)
{
    rj_scene_def d = rj_default_scene_def();
    if (!f)
        return d;
    d.links = f->links;
    d.link_count = f->link_count;
    d.joints = f->joints;
    d.joint_count = f->joint_count;
    d.solver = f->solver;
    d.loads = f->loads;
    d.load_count = f->load_count;
    d.actuators = f->actuators;
    d.actuator_count = f->actuator_count;
    d.couplings = f->couplings;
    d.coupling_count = f->coupling_count;
    return d;
}

RJDEF void rj_scene_file_free(rj_scene_file *f)
{
    if (!f)
        return;
    if (f->block_)
        RJ_FREE(f->block_, f->alloc_ctx_);
    memset(f, 0, sizeof *f);
}

RJDEF int rj_scene_link_index(const rj_scene_file *f, const char *name)
{
    int k;
    if (!f || !name)
        return -1;
    for (k = 0; k < f->link_count; k++)
        if (strcmp(f->link_names[k], name) == 0)
            return k;
    return -1;
}

RJDEF int rj_scene_joint_index(const rj_scene_file *f, const char *name)
{
    int k;
    if (!f || !name)
        return -1;
    for (k = 0; k < f->joint_count; k++)
        if (strcmp(f->joint_names[k], name) == 0)
            return k;
    return -1;
}

/* ------------------------------------------------------------------ writer
   It writes a scene definition, which has no place for the file's fidelity = pieces: a
   parsed file's links cut into pieces are written as the rigid links and bending joints
   they became (rj__sp_cut), and read back as the same scene. */
typedef struct rj__sw {
    char *buf;
    size_t size, n;
    char dp[8];
    int dplen;
} rj__sw;

static void rj__sw_put(rj__sw *W, const char *s)
{
    size_t k = strlen(s);
    if (W->n < W->size) {
        size_t room = W->size - 1 - W->n, c = k < room ? k : room;
        memcpy(W->buf + W->n, s, c);
        W->buf[W->n + c] = 0;
    }
    W->n += k;
}

/* text of v with '.' whatever the locale; returns whether it reads back as target
   (through rj_rad when deg) */
static int rj__sw_fmt(const rj__sw *W, double v, int fixed, int p, int deg, double target,
                      char *out, size_t size)
{
    char t[400];
    double back = 0;
    int k, o = 0, n = snprintf(t, sizeof t, fixed ? "%.*f" : "%.*g", p, v);
    if (n < 0 || n >= (int) sizeof t)
        n = 0;
    for (k = 0; k < n && o + 1 < (int) size;) {
        if (W->dp[0] != '.' && k + W->dplen <= n && memcmp(t + k, W->dp, (size_t) W->dplen) == 0) {
            out[o++] = '.';
            k += W->dplen;
        } else
            out[o++] = t[k++];
    }
    out[o] = 0;
    return k == n && rj__sp_strtonum(out, o, W->dp, W->dplen, &back) == 1 &&
           (deg ? rj_rad(back) : back) == target;
}

/* shortest text of v that reads back as target: %.Ng (N = 1..17) or, for moderate
   magnitudes, %.Nf (N = 0..17) when that is no longer; returns 0 when none reads back */
static int rj__sw_num_try(const rj__sw *W, double v, int deg, double target, char *out, size_t size)
{
    char g[64], f[64];
    int p, okg = 0, okf = 0;
    for (p = 1; p <= 17 && !okg; p++)
        okg = rj__sw_fmt(W, v, 0, p, deg, target, g, sizeof g);
    if (fabs(v) < 1e15)
        for (p = 0; p <= 17 && !okf; p++)
            okf = rj__sw_fmt(W, v, 1, p, deg, target, f, sizeof f);
    if (okf && (!okg || strlen(f) <= strlen(g))) {
        memcpy(out, f, strlen(f) + 1 < size ? strlen(f) + 1 : size);
        out[size - 1] = 0;
        return 1;
    }
    if (okg) {
        memcpy(out, g, strlen(g) + 1 < size ? strlen(g) + 1 : size);
        out[size - 1] = 0;
        return 1;
    }
    rj__sw_fmt(W, v, 0, 17, deg, target, out, size);
    return 0;
}

static void rj__sw_num(rj__sw *W, double v)
{
    char s[64];
    rj__sw_num_try(W, v, 0, v, s, sizeof s);
    rj__sw_put(W, s);
}

/* an angle in the shorter of its exact deg and rad forms ("90 deg", "-10 rad/s") */
static void rj__sw_angle(rj__sw *W, double v, int rate)
{
    char d[64], r[64];
    rj__sw_num_try(W, v, 0, v, r, sizeof r);
    if (rj__sw_num_try(W, rj_deg(v), 1, v, d, sizeof d) && strlen(d) <= strlen(r)) {
        rj__sw_put(W, d);
        rj__sw_put(W, rate ? " deg/s" : " deg");
        return;
    }
    rj__sw_put(W, r);
    rj__sw_put(W, rate ? " rad/s" : " rad");
}

static void rj__sw_key(rj__sw *W, const char *key)
{
    rj__sw_put(W, "  ");
    rj__sw_put(W, key);
    rj__sw_put(W, " = ");
}

static int rj__sw_finite(double v)
{
    return v - v == 0.0;
}

/* whether v differs from def in its bits, not only in value: -0.0 must be written (a
   ground pin at x = -0.0 puts -0.0 into the node positions), so it reads back as -0.0 */
static int rj__sw_set(double v, double def)
{
    return memcmp(&v, &def, sizeof v) != 0;
}

/* Row r of def differs from its default: in its bits for numbers (-0.0 is written), an
   enabled limit, a table with points; with the parts written after it (a spring's free
   angle). rows: its kind's table. */
static int rj__sw_row_set(const rj__field *rows, int n, int k, const void *def)
{
    const rj__field *r = &rows[k];
    int p;
    switch (r->type) {
    case RJ__FT_LIMIT:
    case RJ__FT_TABLE:
        return rj__row_int(def, r) != 0;
    case RJ__FT_VEC2:
        if (rj__sw_set(rj__row_real(def, r, 1), r->def))
            return 1;
        /* fall through */
    case RJ__FT_REAL:
    case RJ__FT_ANGLE:
    case RJ__FT_RATE:
        if (rj__sw_set(rj__row_real(def, r, 0), r->def))
            return 1;
        break;
    default:
        if (rj__row_int(def, r) != (int) r->def)
            return 1;
    }
    for (p = 0; p < n; p++)
        if (rows[p].part_of == k && rj__sw_set(rj__row_real(def, &rows[p], 0), rows[p].def))
            return 1;
    return 0;
}

/* What the writer knows of the item besides its rows. */
typedef struct rj__sw_item {
    int shape;                     /* a link's section shape, else -1 */
    int on_ground;                 /* a joint's body1 is ground */
    int root_link;                 /* a link no joint places */
    const char *const *link_names;  /* names of the scene's links, or NULL */
    const char *const *joint_names; /* names of the scene's joints, or NULL */
} rj__sw_item;

/* Whether the writer writes row k of def (its kind's rows, the first nk keys). */
static int rj__sw_wanted(const rj__field *rows, int n, int nk, int k, const void *def,
                         const rj__sw_item *it)
{
    const rj__field *r = &rows[k];
    int q;
    if (r->write == RJ__WR_NONE || r->type == RJ__FT_PART ||
        !rj__row_applies(r, it->shape, it->on_ground, 1))
        return 0;
    if (r->write == RJ__WR_ALWAYS)
        return 1;
    if (r->write == RJ__WR_SET)
        return rj__sw_row_set(rows, n, k, def);
    for (q = 0; q < nk; q++)
        if (rows[q].line == r->line && rows[q].write == RJ__WR_LINE &&
            rj__row_applies(&rows[q], it->shape, it->on_ground, 1) &&
            rj__sw_row_set(rows, n, q, def))
            return 1;
    return 0;
}

/* A table's pairs, four to a line (a line ending in ',' continues); the first column
   angles when the row says so (stride 1). */
static void rj__sw_pairs(rj__sw *W, const rj__field *r, const void *def)
{
    const double *first = (const double *) (const void *) ((const char *) def + r->aux);
    const int count = rj__row_int(def, r);
    int k;
    for (k = 0; k < count; k++) {
        if (k)
            rj__sw_put(W, k % 4 == 0 ? ",\n    " : ", ");
        if (r->stride == 1)
            rj__sw_angle(W, first[k], 0);
        else
            rj__sw_num(W, first[k]);
        rj__sw_put(W, " ");
        rj__sw_num(W, first[RJ_TABLE_MAX + k]);
    }
}

/* names[i], or prefix and i when the caller gave no names */
static void rj__sw_name(rj__sw *W, const char *const *names, const char *prefix, int i)
{
    char nm[40];
    if (names) {
        rj__sw_put(W, names[i]);
        return;
    }
    snprintf(nm, sizeof nm, "%s%d", prefix, i);
    rj__sw_put(W, nm);
}

/* A prescribed actuator's profile: its name and numbers ("cycloidal 90 deg 2"). */
static void rj__sw_profile(rj__sw *W, const rj_actuator_def *d)
{
    rj__sw_put(W, rj__sk_profile[d->profile]);
    if (d->profile == RJ_PROFILE_TABLE) /* its points are the table's */
        return;
    rj__sw_put(W, " ");
    rj__sw_angle(W, d->profile_value, d->profile != RJ_PROFILE_CYCLOIDAL);
    if (d->profile == RJ_PROFILE_RAMP)
        return;
    rj__sw_put(W, " ");
    rj__sw_num(W, d->profile_time);
}

/* The value of row r of def as a file says it. */
static void rj__sw_value(rj__sw *W, const rj__field *r, const void *def, const rj__sw_item *it)
{
    char nm[24];
    const int v = rj__row_is_real(r) || r->type == RJ__FT_TABLE ? 0 : rj__row_int(def, r);
    switch (r->type) {
    case RJ__FT_REAL:
        rj__sw_num(W, rj__row_real(def, r, 0));
        return;
    case RJ__FT_ANGLE:
    case RJ__FT_RATE:
    case RJ__FT_LIMIT:
        rj__sw_angle(W, rj__row_real(def, r, 0), r->type == RJ__FT_RATE);
        return;
    case RJ__FT_VEC2:
        rj__sw_num(W, rj__row_real(def, r, 0));
        rj__sw_put(W, " ");
        rj__sw_num(W, rj__row_real(def, r, 1));
        return;
    case RJ__FT_TABLE:
        rj__sw_pairs(W, r, def);
        return;
    case RJ__FT_ENUM:
        rj__sw_put(W, rj__names_of(r->names) + (size_t) r->stride * (size_t) v);
        return;
    case RJ__FT_BOOL:
        rj__sw_put(W, v ? "yes" : "no");
        return;
    case RJ__FT_LINK:
        if (v < 0)
            rj__sw_put(W, "ground");
        else
            rj__sw_name(W, it->link_names, "link", v);
        return;
    case RJ__FT_JOINT:
        rj__sw_name(W, it->joint_names, "joint", v);
        return;
    case RJ__FT_PROFILE:
        rj__sw_profile(W, (const rj_actuator_def *) def);
        return;
    case RJ__FT_NODE:
        if (v < 0) {
            rj__sw_put(W, "last");
            return;
        }
        snprintf(nm, sizeof nm, "%d", v);
        rj__sw_put(W, nm);
        return;
    default:
        snprintf(nm, sizeof nm, "%d", v);
        rj__sw_put(W, nm);
    }
}

/* The keys of an item of kind, in its rows' order, rows of one line number on one line:
   "  key = value  key = value"; the parts of a key after its value ("spring = k angle"). */
static void rj__sw_rows(rj__sw *W, int kind, const void *def, const rj__sw_item *it)
{
    int n, nk, k, p, line = -1, place = 0;
    const rj__field *rows = rj__fields(kind, &n);
    nk = rj__key_count(kind);
    for (k = 0; k < nk; k++) {
        const rj__field *r = &rows[k];
        if (!rj__sw_wanted(rows, n, nk, k, def, it))
            continue;
        if (line >= 0 && r->line != line) {
            rj__sw_put(W, place ? "   # unused: the link hangs from a joint\n" : "\n");
            place = 0;
        }
        line = r->line;
        place |= r->when == RJ__WHEN_PLACE && !it->root_link;
        rj__sw_key(W, r->key);
        rj__sw_value(W, r, def, it);
        for (p = nk; p < n; p++)
            if (rows[p].part_of == k && rows[p].type != RJ__FT_BOOL &&
                r->type != RJ__FT_PROFILE) {
                rj__sw_put(W, " ");
                rj__sw_value(W, &rows[p], def, it);
            }
    }
    if (line >= 0)
        rj__sw_put(W, place ? "   # unused: the link hangs from a joint\n" : "\n");
}

/* Whether the writer can express the item's rows that it would write: enums, yes/no and
   ints in range, tables of 0..RJ_TABLE_MAX points, numbers finite. Members the model
   ignores are not written, so anything in them is fine: width and layers of a general
   section, area and inertia of a rectangular one, a limit that is off, ground_* of a
   joint on a link. */
static int rj__sw_rows_ok(int kind, const void *def, int shape, int on_ground)
{
    int n, k, c;
    const rj__field *rows = rj__fields(kind, &n);
    for (k = 0; k < n; k++) {
        const rj__field *r = &rows[k];
        const int parts = r->type == RJ__FT_VEC2 ? 2 : 1;
        if (r->type == RJ__FT_PART || !rj__row_applies(r, shape, on_ground, 1))
            continue;
        if (r->type == RJ__FT_TABLE) {
            const double *first = (const double *) (const void *) ((const char *) def + r->aux);
            const int count = rj__row_int(def, r);
            if (count < 0 || count > RJ_TABLE_MAX)
                return 0;
            for (c = 0; c < count; c++)
                if (!rj__sw_finite(first[c]) || !rj__sw_finite(first[RJ_TABLE_MAX + c]))
                    return 0;
        } else if (r->type == RJ__FT_LIMIT) {
            if (rj__row_int(def, r) && !rj__sw_finite(rj__row_real(def, r, 0)))
                return 0;
        } else if (rj__row_is_real(r)) {
            for (c = 0; c < parts; c++)
                if (!rj__sw_finite(rj__row_real(def, r, c)))
                    return 0;
        } else if (r->type == RJ__FT_ENUM || r->type == RJ__FT_BOOL || r->type == RJ__FT_INT ||
                   r->type == RJ__FT_PROFILE) {
            const int v = rj__row_int(def, r);
            if (v < r->lo || v > r->hi)
                return 0;
        }
    }
    return 1;
}

/* names and numbers first: rj_scene_write writes nothing for a scene it cannot write */
static int rj__sw_ok(const rj_scene_def *sc, const char *const *link_names,
                     const char *const *joint_names)
{
    int i, k;
    for (k = 0; k < 2; k++) {
        const char *const *names = k ? joint_names : link_names;
        int n = k ? sc->joint_count : sc->link_count, a, b;
        if (!names)
            continue;
        for (a = 0; a < n; a++) {
            if (!names[a] || !rj__sp_name_ok(names[a], (int) strlen(names[a])))
                return 0;
            if (!k && strcmp(names[a], "ground") == 0)
                return 0;
            for (b = 0; b < a; b++)
                if (names[b] && strcmp(names[a], names[b]) == 0)
                    return 0;
        }
    }
    if (!rj__sw_rows_ok(RJ__DEF_SOLVER, &sc->solver, -1, 0))
        return 0;
    for (i = 0; i < sc->link_count; i++) {
        const rj_link_def *d = &sc->links[i];
        if (!rj__sw_rows_ok(RJ__DEF_LINK, d, d->section, 0))
            return 0;
    }
    for (i = 0; i < sc->joint_count; i++) {
        const rj_joint_def *d = &sc->joints[i];
        if (d->body1 < -1 || d->body1 >= sc->link_count || d->body2 < 0 ||
            d->body2 >= sc->link_count || !rj__sw_rows_ok(RJ__DEF_JOINT, d, -1, d->body1 < 0))
            return 0;
    }
    for (i = 0; i < sc->load_count; i++) {
        const rj_load_def *d = &sc->loads[i];
        if (d->link < 0 || d->link >= sc->link_count || d->node < -1 ||
            d->node > sc->links[d->link].elements || !rj__sw_rows_ok(RJ__DEF_LOAD, d, -1, 0))
            return 0;
    }
    for (i = 0; i < sc->actuator_count; i++) {
        const rj_actuator_def *d = &sc->actuators[i];
        if (d->joint < 0 || d->joint >= sc->joint_count ||
            !rj__sw_rows_ok(RJ__DEF_ACTUATOR, d, d->type, 0))
            return 0;
    }
    for (i = 0; i < sc->coupling_count; i++) {
        const rj_coupling_def *d = &sc->couplings[i];
        if (d->joint_a < 0 || d->joint_a >= sc->joint_count || d->joint_b < 0 ||
            d->joint_b >= sc->joint_count || !rj__sw_rows_ok(RJ__DEF_COUPLING, d, -1, 0))
            return 0;
    }
    return 1;
}

/* the solver section, only when some value differs from the defaults */
static void rj__sw_solver(rj__sw *W, const rj_solver_def *s)
{
    const rj__sw_item it = { -1, 0, 1, NULL, NULL };
    int k;
    for (k = 0; k < RJ__VF_N; k++)
        if (rj__sw_row_set(rj__solver_fields, RJ__VF_N, k, s))
            break;
    if (k == RJ__VF_N)
        return;
    rj__sw_put(W, "solver\n");
    rj__sw_rows(W, RJ__DEF_SOLVER, s, &it);
}

/* whether a file can hold title: shorter than RJ_SCENE_TITLE_MAX, no '"', no control byte
   (what rj__sp_title_value accepts); NULL is no title */
static int rj__sw_title_ok(const char *title)
{
    size_t n;
    if (!title)
        return 1;
    n = strlen(title);
    if (n >= RJ_SCENE_TITLE_MAX)
        return 0;
    if (memchr(title, '"', n))
        return 0;
    return rj__sp_title_bad(title, (int) n) < 0;
}

/* the title line, none for an empty title (which reads back as "" too) */
static void rj__sw_title(rj__sw *W, const char *title)
{
    if (!title || !title[0])
        return;
    rj__sw_put(W, "title = \"");
    rj__sw_put(W, title);
    rj__sw_put(W, "\"\n");
}

RJDEF size_t rj_scene_write(const rj_scene_def *sc, const char *const *link_names,
                            const char *const *joint_names, char *buf, size_t size)
{
    return rj_scene_write_ex(sc, link_names, joint_names, NULL, buf, size);
}

RJDEF size_t rj_scene_write_ex(const rj_scene_def *sc, const char *const *link_names,
                               const char *const *joint_names, const char *title, char *buf,
                               size_t size)
{
    rj__sw W;
    rj__sw_item item;
    int i, k;
    if (buf && size)
        buf[0] = 0;
    if (!sc || sc->link_count < 1 || sc->link_count > RJ_SCENE_MAX_LINKS || !sc->links ||
        sc->joint_count < 0 || sc->joint_count > RJ_SCENE_MAX_JOINTS ||
        (sc->joint_count && !sc->joints) || sc->load_count < 0 ||
        sc->load_count > RJ_SCENE_MAX_LOADS || (sc->load_count && !sc->loads) ||
        sc->actuator_count < 0 || sc->actuator_count > RJ_SCENE_MAX_ACTUATORS ||
        (sc->actuator_count && !sc->actuators) || sc->coupling_count < 0 ||
        sc->coupling_count > RJ_SCENE_MAX_COUPLINGS || (sc->coupling_count && !sc->couplings))
        return 0;
    if (!rj__sw_ok(sc, link_names, joint_names))
        return 0;
    if (!rj__sw_title_ok(title))
        return 0;
    item.link_names = link_names;
    item.joint_names = joint_names;
    W.buf = buf;
    W.size = buf ? size : 0;
    W.n = 0;
    rj__sp_locale(W.dp, &W.dplen);
    rj__sw_put(&W, "# revjoint scene (written by rj_scene_write, revjoint.h " RJ_VERSION ")\n");
    rj__sw_title(&W, title);
    rj__sw_solver(&W, &sc->solver);
    for (i = 0; i < sc->link_count; i++) {
        int root_link = 1;
        for (k = 0; k < sc->joint_count; k++)
            if (sc->joints[k].body2 == i)
                root_link = 0;
        rj__sw_put(&W, "link ");
        rj__sw_name(&W, link_names, "link", i);
        rj__sw_put(&W, "\n");
        item.shape = sc->links[i].section;
        item.on_ground = 0;
        item.root_link = root_link;
        rj__sw_rows(&W, RJ__DEF_LINK, &sc->links[i], &item);
    }
    for (i = 0; i < sc->joint_count; i++) {
        rj__sw_put(&W, "joint ");
        rj__sw_name(&W, joint_names, "joint", i);
        rj__sw_put(&W, "\n");
        item.shape = -1;
        item.on_ground = sc->joints[i].body1 < 0;
        item.root_link = 1;
        rj__sw_rows(&W, RJ__DEF_JOINT, &sc->joints[i], &item);
    }
    for (i = 0; i < sc->load_count; i++) {
        rj__sw_put(&W, "load ");
        rj__sw_name(&W, NULL, "load", i);
        rj__sw_put(&W, "\n");
        item.shape = -1;
        item.on_ground = 0;
        item.root_link = 1;
        rj__sw_rows(&W, RJ__DEF_LOAD, &sc->loads[i], &item);
    }
    for (i = 0; i < sc->actuator_count; i++) {
        rj__sw_put(&W, "actuator ");
        rj__sw_name(&W, NULL, "actuator", i);
        rj__sw_put(&W, "\n");
        item.shape = sc->actuators[i].type;
        rj__sw_rows(&W, RJ__DEF_ACTUATOR, &sc->actuators[i], &item);
    }
    for (i = 0; i < sc->coupling_count; i++) {
        rj__sw_put(&W, "coupling ");
        rj__sw_name(&W, NULL, "coupling", i);
        rj__sw_put(&W, "\n");
        item.shape = -1;
        rj__sw_rows(&W, RJ__DEF_COUPLING, &sc->couplings[i], &item);
    }
    return W.n;
}
#endif /* RJ_NO_SCENE_FILES */
/* ------------------------------------------------------------------ end of the implementation */
#if defined(RJ__FP_PRAGMAS) && defined(__clang__)
#pragma float_control(pop)
#elif defined(RJ__FP_PRAGMAS)
#pragma GCC pop_options
#endif
#endif

/*
------------------------------------------------------------------------------
LICENSE: MIT. Copyright (c) 2026 the revjoint.h authors.
Permission is hereby granted, free of charge, to any person obtaining a copy of this
software and associated documentation files (the "Software"), to deal in the Software
without restriction, including without limitation the rights to use, copy, modify, merge,
publish, distribute, sublicense, and/or sell copies of the Software, and to permit persons
to whom the Software is furnished to do so, subject to the following conditions: The above
copyright notice and this permission notice shall be included in all copies or substantial
portions of the Software. THE SOFTWARE IS PROVIDED "AS IS", WITHOUT WARRANTY OF ANY KIND.
------------------------------------------------------------------------------
*/
