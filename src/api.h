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

