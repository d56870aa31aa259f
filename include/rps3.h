/*
 * rps3.h - kinematics and inverse dynamics of the 3-DOF in-parallel actuated
 * manipulator of Lee & Shah (IEEE J. Robotics and Automation, 1988): three
 * extensible links pinned to a base, ball-jointed to a moving platform.
 *
 * This header is the documentation of the API.  Equation numbers "(n)" refer
 * to the paper; "errata" refers to the reading notes kept with the project.
 *
 * Conventions
 *   - SI units everywhere: metres, kilograms, seconds, newtons, radians.
 *   - Base frame XYZ: origin at the base centre, Z up, X towards pin joint 1.
 *     Pin i sits at R (cos psi_i, sin psi_i, 0), psi_i = 0, 2pi/3, 4pi/3.
 *   - Platform frame xyz: origin at the platform centre, x towards ball
 *     joint 1.  Orientation Rz(alpha) Ry(beta) Rz(-alpha) (Z-Y-Z Euler angles
 *     with spin gamma = -alpha, eq. (2)).
 *   - theta_i is the angle between link i and the base plane, 0 < theta < pi
 *     (eq. (8)-(10) branch); theta < pi/2 leans the link inwards.
 *   - F_i > 0 extends link i (pushes the platform away from pin i).
 *   - Gravity acts along -Z.
 *
 * Model / data split
 *   rps3_model is filled by the caller (start from rps3_model_default()),
 *   validated once by rps3_model_init(), and then only read (const).
 *   rps3_data holds every input of a point, every result and all scratch; it
 *   is allocated once by rps3_data_alloc().  After that no function of this
 *   library allocates, prints, exits or aborts.  Use one rps3_data per thread.
 *
 * GSL
 *   The library validates its arguments before every GSL call, keeps GSL's
 *   solvers away from the inputs GSL raises errors on, and checks every GSL
 *   status, so it never reaches GSL's (process-global, by default aborting)
 *   error handler and never changes it: a program needs no GSL call.  The
 *   exceptions (docs/library.md): an allocation failure inside GSL's own
 *   allocators (rps3_data_alloc, rps3_sim_alloc, and the identification's
 *   estimators rps3_ident_base, rps3_ident_wls, rps3_ident_consistent,
 *   which allocate their workspaces per call), which GSL reports only
 *   through that handler, and an exactly zero pivot in the LU of the
 *   implicit integrators' iteration matrix.  A program that must survive
 *   running out of memory there calls gsl_set_error_handler_off() once,
 *   from its main thread.
 */
#ifndef RPS3_H
#define RPS3_H

#include <math.h> /* HUGE_VAL in RPS3_FIELDS */
#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------ visibility */

/* RPS3_API marks the public functions, the only symbols librps3.so
   exports (docs/library.md, "Exported symbols"). */
#if defined(_WIN32)
#define RPS3_API
#elif defined(__GNUC__) && __GNUC__ >= 4
#define RPS3_API __attribute__((visibility("default")))
#else
#define RPS3_API
#endif

/* ---------------------------------------------------------------- version */

#define RPS3_VERSION_MAJOR 3
#define RPS3_VERSION_MINOR 0
#define RPS3_VERSION_PATCH 0
#define RPS3_VERSION_STRING "3.0.0"

/* Version string of the compiled library; compare with RPS3_VERSION_STRING. */
RPS3_API const char *rps3_version(void);

/* ----------------------------------------------------------- status codes */

/*
 * Every function that can fail returns one of these.  Positive codes are
 * point-level outcomes: a sweep records them and moves on to the next point.
 * Negative codes are caller errors (bad arguments, out of memory).  When a
 * function returns RPS3_OK, every quantity it reports is finite.  The void
 * functions accept NULL arguments and then do nothing (or write NaN into a
 * non-NULL output, as said at each).
 */
enum rps3_status {
  RPS3_OK = 0,      /* success */
  RPS3_EREACH = 1,  /* pose unreachable: a link length <= 0 or a ball joint
                       not above the base plane (theta outside (0, pi)) */
  RPS3_ENOCONV = 2, /* theta solve did not converge within max_iter, or the
                       solver stopped making progress */
  RPS3_EBRANCH = 3, /* theta solve converged outside 0 < theta < pi, or
                       to the spun-platform roots of (8)-(10) that no
                       pose describes */
  RPS3_ESING = 4,   /* singular configuration: the constraint Jacobian
                       d f / d theta (the lambda system) has condition number
                       above opt.cond_max, or a zero pivot; or (rps3_invdyn)
                       the force transmission is above opt.trans_max */
  RPS3_EDOMAIN = 5, /* a trajectory was evaluated outside its time span */
  RPS3_ERANGE = 6,  /* a result is not finite: the inputs were finite but a
                       reported quantity overflowed (e.g. M = 1e300, rates
                       of 1e300); the message names the quantity.  Every
                       status-returning function checks what it reports */
  RPS3_EMODE = 7,   /* wrong assembly mode: the theta solve converged to a
                       physical root of (8)-(10), but not the one asked
                       for -- in rps3_inverse (multiroot) a root other than
                       the pose's own (closed form (39)); in rps3_fk and
                       rps3_theta_solve a mode other than opt.mode */
  RPS3_EEMPTY = 8,  /* empty workspace: no pose of the set a design is
                       evaluated on is reachable (rps3_design_eval); its
                       summary is still filled (zeros, never NaN) */
  RPS3_EINVAL = -1, /* invalid argument: non-finite or out-of-range value,
                       NULL pointer, unknown enum value */
  RPS3_ENOMEM = -2, /* allocation failed (the _alloc functions only) */
  RPS3_ESTATE = -4  /* a stage was called before the stage it reads from */
};

/* Short static description of a status code (never NULL; "unknown status"
   for a value that is not a code). */
RPS3_API const char *rps3_strerror(int status);

/* Warning bits in rps3_data.warn: the result is returned, but look at it. */
enum rps3_warning {
  RPS3_WARN_ILLCOND = 1, /* cond of the lambda system > opt.cond_warn */
  RPS3_WARN_ALPHA = 2,   /* forward kinematics: beta ~ 0, so alpha is not
                            defined; alpha was set to 0 */
  RPS3_WARN_MODE = 4,    /* a warm-started theta solve returned another
                            assembly mode (rps3_data.mode) than the
                            previous sample's: the sequence crossed the
                            singular surface, or jumped to another root */
  RPS3_WARN_TRANS = 8    /* force transmission (rps3_data.transmission)
                            above opt.trans_warn: the actuators carry
                            many times the load on the platform */
};

/*
 * Assembly modes (rps3_data.mode, rps3_options.mode).  The same link
 * lengths fit several configurations (roots of (8)-(10) with 0 < theta <
 * pi), separated by the singular surface where det(df/dtheta) = 0.  Every
 * level platform (beta = 0, z_c > 0) has det(df/dtheta) > 0 (df/dtheta is
 * then cyclic with equal positive entries), so the sign of the determinant
 * tells on which side of that surface a configuration lies: RPS3_MODE_LEVEL
 * is the level platform's sign (it holds for every configuration reachable
 * from a level one without passing a singularity), RPS3_MODE_OTHER the
 * other.  docs/assembly-modes.md
 * shows them.
 */
enum rps3_mode {
  RPS3_MODE_OTHER = -1, /* det(df/dtheta) < 0 */
  RPS3_MODE_ANY = 0,    /* opt.mode: accept any; data.mode: singular */
  RPS3_MODE_LEVEL = 1   /* det(df/dtheta) > 0, the level platform's */
};

/* ---------------------------------------------------------------- effects */

/*
 * Physical effects a scene may select (bit flags, combine with |).  Only the
 * selected effects are computed, and rps3_data.F_effect holds the share of
 * each one in the actuating force; the shares sum to rps3_data.F.
 */
enum rps3_effect {
  RPS3_EFF_PLATFORM_GRAVITY = 1 << 0, /* weight of the platform, M g */
  RPS3_EFF_LINK_GRAVITY = 1 << 1,     /* weight of the links, term of (22) */
  RPS3_EFF_PLATFORM_INERTIA = 1 << 2, /* platform translation, rotation and
                                         gyroscopic terms, from (21) */
  RPS3_EFF_LINK_INERTIA = 1 << 3,     /* links swinging about their pins (21) */
  RPS3_EFF_PAYLOAD = 1 << 4,          /* payload rigidly fixed to the platform:
                                         its weight and its inertia */
  RPS3_EFF_PIN_FRICTION = 1 << 5,     /* viscous + Coulomb torque at the pins,
                                         the T_{i-3} of (23) (zero in paper) */
  RPS3_EFF_PRISMATIC_FRICTION = 1 << 6 /* viscous + Coulomb force in the
                                          prismatic joints, rps3_leg */
};
#define RPS3_NEFFECT 7
#define RPS3_EFF_ALL ((1 << RPS3_NEFFECT) - 1)
/* default selection: all but payload and friction, as in the paper */
#define RPS3_EFF_DEFAULT                               \
  (RPS3_EFF_PLATFORM_GRAVITY | RPS3_EFF_LINK_GRAVITY | \
   RPS3_EFF_PLATFORM_INERTIA | RPS3_EFF_LINK_INERTIA)
/* effects that need velocities and accelerations */
#define RPS3_EFF_DYNAMIC                                                  \
  (RPS3_EFF_PLATFORM_INERTIA | RPS3_EFF_LINK_INERTIA | RPS3_EFF_PAYLOAD | \
   RPS3_EFF_PIN_FRICTION | RPS3_EFF_PRISMATIC_FRICTION)

/* Name of effect index k (0 <= k < RPS3_NEFFECT), e.g. "platform_gravity";
   index k is the bit 1 << k.  NULL for k out of range. */
RPS3_API const char *rps3_effect_name(int k);

/* Index of the effect with this name, or -1 if there is none. */
RPS3_API int rps3_effect_index(const char *name);

/* ---------------------------------------------------------------- options */

/* How theta is obtained in rps3_inverse(). */
typedef enum {
  RPS3_THETA_CLOSED_FORM = 0, /* from the pose, eq. (39) (atan2 form) */
  RPS3_THETA_MULTIROOT = 1    /* from the link lengths, eqs. (8)-(10), GSL */
} rps3_theta_route;

/* Formulation of the inverse dynamics. */
typedef enum {
  RPS3_LAGRANGE = 0,    /* the paper's: coordinates (l_i, theta_i),
                           multipliers lambda, eqs. (21)-(24), (34) */
  RPS3_NEWTON_EULER = 1 /* platform and links as free bodies, ball-joint
                           forces solved directly; independent check */
} rps3_method;

/* GSL multiroot solver for the theta solve.  The first four use the
   analytic Jacobian (fdfsolver).  newton and gnewton allocate inside every
   iteration in GSL 2.7, and the derivative-free ones use finite-difference
   Jacobians: keep them for studies; hybridsj is the default. */
typedef enum {
  RPS3_SOLVER_HYBRIDSJ = 0,
  RPS3_SOLVER_HYBRIDJ = 1,
  RPS3_SOLVER_NEWTON = 2,
  RPS3_SOLVER_GNEWTON = 3,
  RPS3_SOLVER_HYBRIDS = 4,
  RPS3_SOLVER_HYBRID = 5,
  RPS3_SOLVER_DNEWTON = 6,
  RPS3_SOLVER_BROYDEN = 7
} rps3_solver;
#define RPS3_NSOLVER 8

/* Name of a solver ("hybridsj", ...), NULL if out of range. */
RPS3_API const char *rps3_solver_name(int solver);

/* Solver with this name, or -1 if there is none. */
RPS3_API int rps3_solver_index(const char *name);

/*
 * What rps3_inverse and rps3_invdyn report (rps3_options.outputs): a set
 * of bits, each one result.  A bit left out leaves that result's work out
 * where the route allows it, and its field is NaN after the call (a
 * result is never left holding another point's value); a bit never
 * changes what another field means.  Default RPS3_OUT_ALL.
 *
 *   RPS3_OUT_FORCES        F: the actuating forces (34).
 *   RPS3_OUT_EFFECTS       F_effect: the share of each selected effect
 *                          (zero for effects not selected).  Without it
 *                          the selected effects' loads are summed and
 *                          solved once (F equal to the shares' sum to
 *                          rounding, ~1e-15 of the forces' scale).
 *   RPS3_OUT_THETA         theta by the closed form (39).  The multiroot
 *                          route solves for theta, so there d->theta is
 *                          the solve's root whatever the bit (the next
 *                          point's warm start).  Without it phi and dphi
 *                          are still the pose's.
 *   RPS3_OUT_LAMBDA        lambda, has_lambda = 1 (Lagrange).  NaN, and
 *                          has_lambda 0, without it or under Newton-Euler.
 *   RPS3_OUT_TRANSMISSION  transmission (the force transmission).
 *   RPS3_OUT_CERTIFY       the energy-rate certificate: power, dTdt, dPdt,
 *                          friction_power, energy_residual, energy_scale.
 *                          It needs the rates and accelerations even for
 *                          a static selection.
 *
 * The checks do not depend on the bits: status and warn are the same for
 * every subset.  The lambda system's condition
 * number is always computed (d->cond; RPS3_ESING above opt.cond_max,
 * RPS3_WARN_ILLCOND above opt.cond_warn), and so is the finiteness of
 * every quantity the point computes (RPS3_ERANGE).  Without
 * RPS3_OUT_TRANSMISSION the force transmission check (RPS3_ESING above
 * opt.trans_max, RPS3_WARN_TRANS above opt.trans_warn) is still decided:
 * either by an upper bound that proves the transmission below both
 * thresholds,
 *   T <= (sqrt3 / 3) (1 + 4 / rho) (1 + 2 sqrt3 r |(df/dtheta)^-1|_inf
 *        (l_1 + l_2 + l_3))
 * with f_k = |b_i - b_j|^2 - 3 r^2 the constraints (8)-(10) in metres
 * (the platform twist per unit link rate through their Jacobian, whose
 * df/dl entries are at most 2 sqrt3 r, and the ball joints at distance r
 * from the centre), or, where the bound does not prove it, by computing
 * the transmission as with the bit.
 *
 * The leanest pass.  With outputs = RPS3_OUT_FORCES (F alone) on the
 * batch kernel's configurations (closed-form theta, Lagrange, no effect
 * beyond the paper's four), rps3_inverse computes a point in one pass that
 * forms F, the condition number and the bound above and nothing else, in
 * about 40 % of the time of the pass with the transmission
 * (docs/performance.md): a controller's path, with every check.  A point
 * the pass cannot keep (non-finite, unreachable, an angle beyond 1e5 rad,
 * cond or the bound near or above a threshold) goes through the stages,
 * whose status and warn it then has.  The pass leaves d->stage 0: the
 * positions, rates and mode of d are not this point's (a later stage call
 * returns RPS3_ESTATE instead of reading them), and l, c, dl, ddl are
 * NaN.  Where the CPU has fused multiply-adds the pass uses them, so its
 * last bits differ between CPUs with and without FMA (F within 8 eps cond
 * of the point's force scale of the default's either way).
 * rps3_inverse_batch runs the same pass
 * (bitwise the loop of rps3_inverse on one machine).
 */
enum rps3_output {
  RPS3_OUT_FORCES = 1 << 0,
  RPS3_OUT_EFFECTS = 1 << 1,
  RPS3_OUT_THETA = 1 << 2,
  RPS3_OUT_LAMBDA = 1 << 3,
  RPS3_OUT_TRANSMISSION = 1 << 4,
  RPS3_OUT_CERTIFY = 1 << 5
};
#define RPS3_NOUTPUT 6
#define RPS3_OUT_ALL ((1 << RPS3_NOUTPUT) - 1)

/* Name of output index k (0 <= k < RPS3_NOUTPUT), e.g. "forces", "effects",
   "theta", "lambda", "transmission", "certify"; index k is the bit 1 << k.
   NULL for k out of range. */
RPS3_API const char *rps3_output_name(int k);

/* Index of the output with this name, or -1 if there is none. */
RPS3_API int rps3_output_index(const char *name);

typedef struct {
  int effects;            /* selected effects, RPS3_EFF_* bits */
  rps3_method method;     /* formulation of the dynamics */
  rps3_theta_route theta; /* closed form or multiroot in rps3_inverse */
  rps3_solver solver;     /* multiroot solver: cold starts, and the
                             fallback when a warm start's Newton path
                             gives up (a warm start takes that path
                             whatever the solver) */
  double tol;             /* theta solve stops when max_k |f_k| <= tol,
                             f_k the dimensionless (8)-(10) (lengths in
                             units of R).  Default 1e-12 */
  int max_iter;           /* theta solve iteration limit, default 50 */
  int warm_start;         /* 1: theta solve starts from the data's last
                             solution when it has one (rps3_inverse's
                             multiroot route: moved along the change of
                             the lengths, rps3_inverse); 0: always cold */
  int outputs;            /* what rps3_inverse and rps3_invdyn report:
                             RPS3_OUT_* bits (enum rps3_output), default
                             RPS3_OUT_ALL; the checks do not depend on
                             them */
  double cond_warn;       /* set RPS3_WARN_ILLCOND above this 1-norm
                             condition number of the lambda system (1e6) */
  double cond_max;        /* RPS3_ESING above this (1e13) */
  double trans_warn;      /* set RPS3_WARN_TRANS above this force
                             transmission (rps3_data.transmission), 100 */
  double trans_max;       /* RPS3_ESING above this transmission (1e8) */
  int mode;               /* assembly mode rps3_theta_solve and rps3_fk
                             must return (enum rps3_mode): RPS3_MODE_ANY
                             (default), RPS3_MODE_LEVEL or RPS3_MODE_OTHER;
                             another one is RPS3_EMODE */
} rps3_options;

/* ------------------------------------------------------------------ model */

/* A rigid payload fixed to the platform. */
typedef struct {
  double mass;       /* [kg] */
  double com[3];     /* centre of mass in platform axes, from the platform
                        centre [m] */
  double inertia[3]; /* principal moments about the payload's centre of mass,
                        principal axes parallel to the platform axes
                        [kg m^2] */
} rps3_payload;

/* Pin-joint friction, a torque about each pin axis opposing theta-dot:
   T = -(viscous * dtheta + coulomb * s(dtheta)), with s = sign (sign(0) =
   0) when vreg = 0, and the regularised s = tanh(dtheta / vreg) when
   vreg > 0.  The same law serves the inverse and the forward dynamics.
   Exact sign makes the equations of motion discontinuous at dtheta = 0:
   an integrator then chatters around sticking (and an adaptive one stalls
   on it); vreg > 0 makes them smooth at the cost of a creep velocity of
   order vreg under a load below the Coulomb level (docs/simulation.md). */
typedef struct {
  double viscous; /* [N m s / rad]; in a prismatic joint [N s/m] */
  double coulomb; /* [N m]; in a prismatic joint [N] */
  double vreg;    /* regularisation velocity [rad/s], 0 = exact sign; in
                     a prismatic joint [m/s] */
} rps3_friction;

/*
 * A rigid body of the general model (docs/identification.md, "The
 * model"), in its own frame: the platform's is the platform centre with
 * the platform axes of (1); a cylinder's is its pin P_i with the axes
 * e1 = phi_i (along the link, to the platform), e2 = the pin axis (30),
 * e3 = e1 x e2; a piston's is the ball joint b_i with its cylinder's axes.
 */
typedef struct {
  double mass;       /* [kg] */
  double com[3];     /* centre of mass from the frame's origin, body axes
                        [m] */
  double inertia[6]; /* inertia tensor about the centre of mass, body axes:
                        Ixx, Ixy, Ixz, Iyy, Iyz, Izz [kg m^2]; positive
                        semidefinite, its principal moments obeying the
                        triangle inequality */
} rps3_body;

/* Leg i of the general model: the cylinder turns with the link about its
   pin, the piston slides in it (a prismatic joint: it does not turn in
   the cylinder); massless pistons and point-mass links are the paper's
   special case. */
typedef struct {
  rps3_body cylinder;
  rps3_body piston;
  rps3_friction pin;       /* at the pin, RPS3_EFF_PIN_FRICTION, with
                              RPS3_BODIES_GENERAL (the paper's bodies
                              share rps3_model.friction) */
  rps3_friction prismatic; /* in the prismatic joint, the force the
                              actuator overcomes, f = viscous l' + coulomb
                              s(l') (s as for the pins);
                              RPS3_EFF_PRISMATIC_FRICTION, either bodies */
} rps3_leg;

/* The bodies a model describes (rps3_model.bodies). */
enum rps3_bodies {
  RPS3_BODIES_PAPER = 0,  /* the paper's: a uniform disc platform of mass
                             M, links m at d plus link_Ic, massless pistons */
  RPS3_BODIES_GENERAL = 1 /* rps3_model.platform and rps3_model.leg */
};

/* Standard parameters of the general model (rps3_model.std): ten per
   body, platform, cylinder 1, piston 1, cylinder 2, ..., piston 3, each
   (m, m c_x, m c_y, m c_z, I_xx, I_xy, I_xz, I_yy, I_yz, I_zz) in its
   frame, I about the frame's origin; then the prismatic joints' (viscous,
   Coulomb) and the pins' (viscous, Coulomb), leg by leg: 82. */
#define RPS3_NBODY 7
#define RPS3_NSTD 82

typedef struct {
  /* mechanism, Table II */
  double R;       /* base radius: centre to pin joints [m] */
  double rho;     /* r / R, r the platform radius to the ball joints [-] */
  double M;       /* platform mass, a uniform disc of radius r [kg] */
  double m;       /* mass of each link [kg] */
  double d;       /* pin joint to link centroid, constant [m] */
  double link_Ic; /* moment of inertia of a link about its centroid, about
                     the pin direction [kg m^2]; 0 in the paper (point
                     mass) */
  double g;       /* gravitational acceleration, along -Z [m/s^2] */
  rps3_payload payload;   /* used when RPS3_EFF_PAYLOAD is selected */
  rps3_friction friction; /* used when RPS3_EFF_PIN_FRICTION is selected */
  int bodies;             /* enum rps3_bodies: RPS3_BODIES_PAPER (default)
                             reads M, m, d, link_Ic and friction;
                             RPS3_BODIES_GENERAL reads platform and leg
                             instead (R, rho, g, the payload and the
                             options either way) */
  rps3_body platform;     /* RPS3_BODIES_GENERAL: the platform */
  rps3_leg leg[3];        /* the legs' bodies and pin friction
                             (RPS3_BODIES_GENERAL), their prismatic
                             friction (either) */
  rps3_options opt;

  /* derived by rps3_model_init(); do not set */
  double r;            /* platform radius rho R [m] */
  double Ip[3];        /* platform principal moments (21): Mr^2/4, Mr^2/4,
                          Mr^2/2 [kg m^2] */
  double Jlink;        /* m d^2 + link_Ic [kg m^2] */
  double pin[3][3];    /* pin joint positions P_i [m] */
  double radial[3][3]; /* unit radial direction of pin i, (cos, sin, 0) */
  double axis[3][3];   /* pin axes phi_zi, eq. (30), unit */
  double body[3][3];   /* ball joints in platform axes, r_i of (27) [m] */
  double std[RPS3_NBODY][10]; /* RPS3_BODIES_GENERAL: each body's standard
                                 parameters (RPS3_NSTD's order); the
                                 dynamics read these, not platform and
                                 leg */
  rps3_friction pinf[3];      /* each pin's friction law: friction, or
                                 leg[i].pin for RPS3_BODIES_GENERAL */
  int valid;           /* 1 after a successful rps3_model_init() */
} rps3_model;

/* Fill m with the paper's Table II (R = 0.2286 m, rho = 0.5, M = 0.18 kg,
   m/M = 0.5, d = 0.1524 m, g = 9.80665 m/s^2), no payload, no friction and
   the default options.  Call rps3_model_init() afterwards.  m NULL: does
   nothing. */
RPS3_API void rps3_model_default(rps3_model *m);

/* Fill opt with the default options.  opt NULL: does nothing. */
RPS3_API void rps3_options_default(rps3_options *opt);

/*
 * What failed a validation (rps3_model_init, rps3_traj_check,
 * rps3_design_model) or the set-up of an allocation (rps3_sim_alloc,
 * rps3_sim_check_rate, rps3_ctrl_alloc): the field by identifier, for a
 * program that maps it back to its own input, and the message.  Each of
 * these functions clears *chk first and fills it when it refuses; chk may
 * be NULL.
 */
typedef struct {
  int field;      /* the failing field: an rps3_field_id (RPS3_FIELDS),
                     or for rps3_design_model an rps3_design_field_id;
                     -1 when the failure is not about one field of the
                     table (a NULL argument, a simulation option, running
                     out of memory) */
  int comp;       /* its component, 0 for a scalar field; the row of an
                     array field (waypoints, table) */
  int related[2]; /* other fields the failed rule reads (e.g. rho and R
                     for the helix radius bound), -1 when unused */
  char msg[256];  /* "NAME = VALUE: reason", NAME the field's dotted
                     name (rps3_field_info.name) with its component,
                     e.g. "rho", "payload.inertia[2]", "opt.tol";
                     empty after a success */
} rps3_check;

/*
 * Validate m and compute its derived fields.  Returns RPS3_OK, or
 * RPS3_EINVAL with the offending field in *chk (chk may be NULL).
 * Rejected: non-finite values, R <= 0, rho <= 0, negative masses,
 * inertias or friction, d < 0, g < 0, payload inertia violating the
 * triangle inequality, unknown enum values, tol <= 0, max_iter < 1,
 * cond_warn < 1, cond_max < cond_warn, and masses whose weight or inertia
 * overflows (M g, M r^2, m g d, m d^2, payload.mass g, payload.mass r^2
 * not finite, e.g. M = 1e308); a general body (checked whatever
 * m->bodies) whose inertia about its centre of mass is not a real body's
 * (its second moment tr(I)/2 1 - I not positive semidefinite, to 1e-12
 * of its trace: a principal moment above the sum of the other two, or
 * products of inertia too large) or whose standard parameters or weight
 * overflow.
 */
RPS3_API int rps3_model_init(rps3_model *m, rps3_check *chk);

/* ------------------------------------------------------------------- data */

/* Where the last error was raised (per data, so thread-safe). */
typedef struct {
  int code;         /* rps3_status */
  const char *func; /* function that raised it */
  const char *file;
  int line;
  char msg[256]; /* what went wrong, with the values involved */
} rps3_error;

struct rps3_solver_state; /* internal: GSL solver and its vectors */

/* stages completed for the current point (rps3_data.stage bits) */
enum rps3_stage {
  RPS3_STAGE_POS = 1, /* positions: rps3_ik, rps3_fk or rps3_theta_solve */
  RPS3_STAGE_VEL = 2, /* rps3_velocity or rps3_joint_velocity */
  RPS3_STAGE_ACC = 4, /* rps3_acceleration or rps3_joint_acceleration */
  RPS3_STAGE_DYN = 8  /* rps3_invdyn */
};

typedef struct {
  /* inputs of a point, set by the caller */
  double pose[3];   /* (alpha, beta, z_c) [rad, rad, m] */
  double dpose[3];  /* time derivative [rad/s, rad/s, m/s] */
  double ddpose[3]; /* second derivative [rad/s^2, rad/s^2, m/s^2] */

  /* positions; set by rps3_ik (from pose) or rps3_fk (from l) */
  double c[3];        /* platform centre (x_c, y_c, z_c), (3)-(4), (11) [m] */
  double rot[3][3];   /* platform orientation, columns n, o, a of (1) */
  double b[3][3];     /* ball joints b_i, (12)-(17) [m] */
  double l[3];        /* link lengths, (5)-(7) [m]; input of rps3_fk */
  double theta[3];    /* link angles, (39) or (8)-(10) [rad] */
  double phi[3][3];   /* unit vector along link i, (29) */
  double dphi[3][3];  /* d phi_i / d theta_i, unit, normal to the link */
  int solve_niter;    /* iterations of the last theta solve */
  double solve_resid; /* max |f_k| after the last theta solve [-] */
  int have_theta;     /* theta holds a solution usable as a warm start */
  int mode;           /* assembly mode of theta (enum rps3_mode): sign of
                         det(df/dtheta), +1 the level platform's side, -1
                         the other, 0 exactly singular; it changes only
                         through a singular configuration; set by rps3_ik,
                         rps3_theta_solve (so rps3_fk) and rps3_fwddyn */

  /* velocities; rps3_velocity (from dpose) or rps3_joint_velocity (dl) */
  double dl[3];     /* link extension rates [m/s]; input of
                       rps3_joint_velocity */
  double dtheta[3]; /* [rad/s] */
  double vc[3];     /* platform centre velocity, (25) [m/s] */
  double omega[3];  /* platform angular velocity, base axes [rad/s] */

  /* accelerations; rps3_acceleration or rps3_joint_acceleration */
  double ddl[3];     /* [m/s^2]; input of rps3_joint_acceleration */
  double ddtheta[3]; /* [rad/s^2] */
  double ac[3];      /* platform centre acceleration [m/s^2] */
  double domega[3];  /* angular acceleration, base axes [rad/s^2] */

  /* dynamics; rps3_invdyn */
  double F[3]; /* actuating forces, (34) [N], > 0 extends */
  double F_effect[RPS3_NEFFECT][3]; /* share of effect k in F [N]; zero for
                                       effects not selected */
  double lambda[3];    /* multipliers of (8)-(10) written in metres,
                          f_k = |b_i - b_j|^2 - 3 r^2 [N/m]; Lagrange only
                          (0 under Newton-Euler, see has_lambda) */
  int has_lambda;      /* 1 when lambda was computed (Lagrange) */
  double cond;         /* 1-norm condition number of the lambda system
                          (df/dtheta), both methods [-] */
  double transmission; /* force transmission [-]: the largest actuator
                          force per unit platform load, max_i sum_j
                          |dF_i / dw_j| s_j over the wrench w = (force,
                          moment / R) (s = 1, 1, 1, R, R, R), so that
                          |F_i| <= transmission max(|f|, |n| / R); 2.41
                          for the level platform at z_c = R, unbounded
                          towards singular configurations, also where cond
                          stays small (a level platform lowered to the
                          base); both methods */
  double power;        /* actuator power sum F_i dl_i [W]; this and the
                          certificate's terms below: RPS3_OUT_CERTIFY */
  double dTdt;         /* rate of kinetic energy of the selected effects [W] */
  double dPdt; /* rate of potential energy of the selected effects [W] */
  double friction_power;  /* power of the pin friction torques (<= 0) [W] */
  double energy_residual; /* power + friction_power - dTdt - dPdt [W]; zero
                             up to rounding when the forces are right;
                             finite whenever the status is RPS3_OK; NaN
                             without RPS3_OUT_CERTIFY */
  double energy_scale;    /* sum of the magnitudes of the terms above [W], to
                             make the residual relative */

  /* forward dynamics; rps3_fwddyn (reads l, dl, F) */
  double Mq[3][3]; /* joint-space mass matrix of the selected effects,
                      symmetric positive definite [kg] */
  double hq[3];    /* bias forces (velocity products, gravity, pin
                      friction): F = Mq ddl + hq [N] */
  double Mcond;    /* 1-norm condition number of Mq [-] */

  int warn;       /* RPS3_WARN_* bits of the last point */
  int stage;      /* RPS3_STAGE_* bits completed for this point */
  rps3_error err; /* last error */
  struct rps3_solver_state *solver; /* internal */
} rps3_data;

/*
 * Allocate a workspace for model m (which must have passed rps3_model_init)
 * into *out.  The workspace serves any model with the same opt.solver (the
 * GSL solver is built for it); rps3_theta_solve refuses a model that names
 * another solver with RPS3_EINVAL.  This is the only allocation of the library:
 * the GSL multiroot solver of m->opt.solver and its vectors.  Returns RPS3_OK,
 * RPS3_EINVAL (m NULL or not initialised, out NULL) or RPS3_ENOMEM (nothing
 * leaks).
 */
RPS3_API int rps3_data_alloc(const rps3_model *m, rps3_data **out);

/* Free a workspace; NULL is accepted. */
RPS3_API void rps3_data_free(rps3_data *d);

/* Forget the current point and the warm start (have_theta = 0). */
RPS3_API void rps3_data_reset(rps3_data *d);

/* ------------------------------------------------------------- kinematics */

/*
 * Inverse kinematics, eqs. (2)-(7) and (39): from d->pose = (alpha, beta,
 * z_c) compute c (3)-(4), rot (1), b, l, theta in closed form, phi, dphi.
 * Returns RPS3_OK, RPS3_EINVAL (non-finite pose), RPS3_EREACH (a link of
 * zero length or a ball joint not above the base plane) or RPS3_ERANGE (a
 * finite pose whose positions overflow, e.g. z_c = 1e200 m).
 */
RPS3_API int rps3_ik(const rps3_model *m, rps3_data *d);

/*
 * Cold starting guess for the theta solve from d->l alone: the theta each
 * link would have with the platform level (beta = 0), clamped into (0, pi).
 * Writes d->theta.  Returns RPS3_OK or RPS3_EINVAL (non-finite or
 * non-positive length).
 */
RPS3_API int rps3_theta_guess(const rps3_model *m, rps3_data *d);

/*
 * Solve the constraints (8)-(10) for theta given the link lengths d->l.
 * From a warm start (d->theta when m->opt.warm_start and d->have_theta)
 * Newton's method in the links' planes, at most 8 steps of at most 0.1 rad
 * each, the path rps3_fwddyn takes too; where it does not converge to a
 * root in (0, pi), and from a cold start (rps3_theta_guess()), the GSL
 * multiroot solver m->opt.solver (analytic Jacobian for the fdf solvers)
 * from the same start, which decides and reports.  Converged when max_k
 * |f_k| <= opt.tol;
 * writes d->theta, solve_niter, solve_resid, and the
 * positions b, c, rot, phi, dphi via (11)-(20).
 * Returns RPS3_OK, RPS3_EINVAL (bad lengths, or constraints that do not
 * evaluate to finite numbers), RPS3_ENOCONV (including any failure GSL
 * reports when starting or iterating, and any step that would make GSL
 * raise an error: a singular or curvature-dominated (finite-difference)
 * Jacobian for newton, gnewton, dnewton and broyden, a stalled broyden
 * step; with its message), RPS3_ERANGE (positions overflow: lengths near
 * 1e308 m) or RPS3_EBRANCH (a root with
 * theta outside (0, pi), or a root of the second family of (8)-(10): the
 * ball joints reflected through the Z axis, which no pose (alpha, beta,
 * z_c) describes).  Several roots may satisfy 0 < theta < pi (assembly
 * modes); the solve returns the one its starting point leads to, so start
 * it near the wanted one (warm start from the previous sample).
 */
RPS3_API int rps3_theta_solve(const rps3_model *m, rps3_data *d);

/*
 * Forward kinematics: link lengths d->l -> theta (rps3_theta_solve) ->
 * platform position (11) and orientation (18)-(20) -> d->pose = (alpha,
 * beta, z_c), with beta in [0, pi) and alpha in (-pi, pi].  When beta is
 * below 1e-9 rad alpha is not defined: it is set to 0 and RPS3_WARN_ALPHA is
 * raised.  Returns the status of rps3_theta_solve, or RPS3_ERANGE.
 */
RPS3_API int rps3_fk(const rps3_model *m, rps3_data *d);

/* The homogeneous transform (1) of the current platform pose.  T NULL: does
   nothing; d NULL: fills T's rotation and translation with NaN. */
RPS3_API void rps3_transform(const rps3_data *d, double T[4][4]);

/*
 * Velocities from pose rates: from d->dpose (after a position stage) compute
 * vc, omega, and the joint rates dl, dtheta (the map (alpha-dot, beta-dot,
 * z-dot) -> (l-dot, theta-dot)).  Returns RPS3_OK, RPS3_EINVAL (non-finite
 * dpose), RPS3_ESTATE or RPS3_ERANGE (finite rates that overflow).
 */
RPS3_API int rps3_velocity(const rps3_model *m, rps3_data *d);

/*
 * Accelerations from pose accelerations: from d->ddpose (after
 * rps3_velocity) compute ac, domega, ddl, ddtheta.  Returns RPS3_OK,
 * RPS3_EINVAL (non-finite ddpose), RPS3_ESTATE or RPS3_ERANGE (e.g. rates
 * of 1e200 whose squares overflow).
 */
RPS3_API int rps3_acceleration(const rps3_model *m, rps3_data *d);

/*
 * The link motion of a pose and its rates alone, a controller's desired
 * motion: l, dl and (acc not 0) ddl from d->pose, d->dpose (and
 * d->ddpose) by the derivatives of l_i^2 = |b_i - P_i|^2, with no theta
 * and no link directions (d->stage 0: nothing else of d is set), about
 * half the work of rps3_ik + rps3_velocity + rps3_acceleration, whose
 * l, dl, ddl it gives to rounding.  Returns RPS3_OK, RPS3_EINVAL (pose or
 * rates not finite), RPS3_EREACH (no link through a ball joint above
 * its pin) or RPS3_ERANGE (a result not finite).
 */
RPS3_API int rps3_link_motion(const rps3_model *m, rps3_data *d, int acc);

/*
 * Velocities from link rates, eqs. (25)-(30): from d->dl (after a position
 * stage) compute dtheta through the constraint Jacobian
 * (df/dtheta) dtheta = -(df/dl) dl, then vc (25) and omega from the ball
 * joint velocities (26)-(28).  Also fills d->dpose.  Returns RPS3_OK,
 * RPS3_EINVAL, RPS3_ESTATE, RPS3_ESING or RPS3_ERANGE.
 */
RPS3_API int rps3_joint_velocity(const rps3_model *m, rps3_data *d);

/*
 * The same one order higher: from d->ddl (after rps3_joint_velocity)
 * compute ddtheta, ac and domega.  Returns RPS3_OK, RPS3_EINVAL,
 * RPS3_ESTATE, RPS3_ESING or RPS3_ERANGE.
 */
RPS3_API int rps3_joint_acceleration(const rps3_model *m, rps3_data *d);

/*
 * Body-frame angular velocity (omega_x, omega_y, omega_z) by the paper's
 * (31)-(33) with the two printing errors corrected (errata), from the
 * current positions, dl, dtheta and vc.  A second formulation of omega,
 * kept for checking: rot^T omega must equal it.  omega_body NULL: does
 * nothing; m or d NULL (or m not initialised): omega_body is NaN.
 */
RPS3_API void rps3_omega_paper(const rps3_model *m, const rps3_data *d,
                               double omega_body[3]);

/* ---------------------------------------------------------------- dynamics */

/*
 * Inverse dynamics of the selected effects (m->opt.effects) by
 * m->opt.method, after the position stage and, when a dynamic effect is
 * selected (or RPS3_OUT_CERTIFY), the velocity and acceleration stages.
 * Writes F, F_effect, lambda (Lagrange), cond, warn and, with
 * RPS3_OUT_CERTIFY, the energy-rate certificate; the results of the
 * outputs left out of opt.outputs are NaN (enum rps3_output).  Returns
 * RPS3_OK, RPS3_EINVAL,
 * RPS3_ESTATE, RPS3_ESING or RPS3_ERANGE (a force, multiplier or power not
 * finite, e.g. M = 1e300 kg).
 */
RPS3_API int rps3_invdyn(const rps3_model *m, rps3_data *d);

/*
 * Whole pipeline for one point: the caller sets d->pose, d->dpose,
 * d->ddpose; theta comes from opt.theta (closed form, or multiroot warm
 * started from the previous point of the same data); velocities and
 * accelerations are computed only when a selected effect or the
 * certificate (RPS3_OUT_CERTIFY) needs
 * them.  Returns the first failing stage's status (any of the stages'
 * codes above).
 *
 * The multiroot route's warm start is the data's last root moved along
 * the change of the link lengths to second order (from the constraint
 * Jacobian there: off by O(|dl|^3), ~1e-14 rad on the paper's helix at
 * 1 kHz), from lengths only, never from the pose's closed form; only
 * while d->theta is still the root the last call returned, bit for bit
 * (a theta the caller wrote is the start as written).  As
 * rps3_theta_solve does with any start, a start within opt.tol is the
 * root (0 iterations, d->solve_resid its residual); the warm Newton path
 * (GSL's solver where it gives up) runs from it otherwise.  So the solve
 * stops where the tolerance says, not
 * below it: its theta error is up to about cond x tol, as documented for
 * the route.  A step above 0.01 rad is not predicted (the last root is the
 * start).
 *
 * With the closed-form theta, the Lagrange formulation and no effect
 * beyond the paper's four, the point is computed in one straight-line
 * pass, the batch kernel's (below) on one point: the stages' results, to
 * the kernel's tolerances (docs/library.md, "Batches", gives them and
 * the time).  A point the kernel does not certify
 * (non-finite, unreachable, overflowing, near or past a threshold) goes
 * through the stages, so status and warn are always theirs; d then holds
 * everything the stages leave.  With opt.outputs = RPS3_OUT_FORCES the
 * point goes through the leanest pass, which leaves d->stage 0 (enum
 * rps3_output).
 */
RPS3_API int rps3_inverse(const rps3_model *m, rps3_data *d);

/* ------------------------------------------------------------------- batch */

/*
 * Batch entry points: n points in one call.  Every array is a structure of
 * arrays, "component-major": component c of point i is at [c * n + i]
 * (alpha[0..n), then beta[0..n), then z_c[0..n) for poses).  The points are
 * computed in order with the one workspace d, as the loop
 *     for i: copy point i into d; rps3_<stage>(m, d); copy the results out
 * computes them, and the results are bitwise those of that loop (a
 * multiroot theta solve warm-starts from the previous point of d when
 * m->opt.warm_start) -- the vectorised kernel below included.  No
 * allocation; one workspace per thread, so a caller may split a batch
 * across threads, each thread with its own d.
 *
 * Vectorised kernel.  rps3_inverse_batch with the closed-form theta, the
 * Lagrange formulation and no effect beyond the paper's four (payload and
 * pin friction not selected) -- whatever opt.outputs -- computes blocks of
 * points in one straight-line loop the compiler vectorises (AVX2 or AVX-512
 * where the CPU has them), more than ten times the points per second of the
 * per-point loop (docs/performance.md); with out->theta NULL and without the
 * certificate it leaves theta and the certificate out as well; with outputs =
 * RPS3_OUT_FORCES it runs the leanest pass (enum rps3_output).  The
 * arrays of outputs left out of opt.outputs are NaN at the points
 * computed (F_effect: RPS3_OUT_EFFECTS; theta: RPS3_OUT_THETA on the
 * closed-form route; lambda; transmission; energy_residual and
 * energy_scale: RPS3_OUT_CERTIFY), and so are l, c, dl and ddl at the
 * points of the leanest pass.  rps3_inverse
 * runs the same loop body on its one point, so the batch and the loop of
 * rps3_inverse agree bit for bit.  Against
 * the per-point stages (the path of every other configuration) the
 * kernel agrees to rounding: l within 4 ulp, theta within 2 ulp of pi, F,
 * its shares and lambda R within 8 eps cond of the point's largest force
 * or share, cond within 8 eps cond; transmission and the energy scale
 * within 8 eps cond, dl and ddl within 16 eps of the point's velocity and
 * acceleration scale, x_c and y_c within 4 eps r.  A point it cannot
 * certify -- a non-finite
 * input, an angle beyond 1e5 rad, an unreachable pose, a result that
 * overflows, or a condition number or force transmission near or above
 * its warning threshold -- is computed by the per-point stages, so status
 * and warn are exactly the stages' for every point (warn is 0 and niter 0
 * for the kernel's points).  After the call d holds the last point the
 * loop computed, not necessarily point n - 1.  The kernel keeps one block
 * of results on the stack (about 20 kB).
 *
 * A point that fails gets its status in out->status[i] and NaN in its
 * floating-point outputs, and the other points are computed.  out->nfail
 * counts the failed points; the first one is out->first_fail, and its
 * message, prefixed "point I: ", is left in d->err.
 *
 * Returns RPS3_OK when the call ran (look at out->nfail and out->status),
 * or RPS3_EINVAL when the call itself is invalid (m not initialised, d, in
 * or out NULL, a required array NULL, 3 n overflowing size_t): then nothing
 * is computed, and d->err (d not NULL) says what is wrong.
 */

/* Inputs of the batch functions; each reads only the arrays it names. */
typedef struct {
  size_t n;             /* number of points */
  const double *pose;   /* 3 n: alpha, beta, z_c [rad, rad, m] (inverse,
                           ik) */
  const double *dpose;  /* 3 n: pose rates [rad/s, rad/s, m/s] (inverse,
                           required when a selected effect or
                           RPS3_OUT_CERTIFY needs rates, else may be
                           NULL) */
  const double *ddpose; /* 3 n: pose accelerations [rad/s^2, rad/s^2,
                           m/s^2] (inverse, same rule as dpose) */
  const double *l;      /* 3 n: link lengths [m] (fk) */
  const double *guess;  /* 3 n: starting theta of each point's solve [rad]
                           (fk; may be NULL) */
} rps3_batch_in;

/* Outputs of the batch functions; each writes the arrays it computes that
   are not NULL (zero the structure, then set the arrays wanted); status is
   required. */
typedef struct {
  int *status;             /* n: rps3_status of each point */
  int *warn;               /* n: RPS3_WARN_* bits of each point */
  double *pose;            /* 3 n: poses (fk) [rad, rad, m] */
  double *c;               /* 3 n: platform centre x_c, y_c, z_c (inverse, ik,
                              fk) [m], eqs. (3)-(4) */
  double *l;               /* 3 n: link lengths (ik, inverse) [m] */
  double *dl;              /* 3 n: link rates (inverse) [m/s]; NaN when no
                              selected effect nor the certificate needs rates */
  double *ddl;             /* 3 n: link accelerations (inverse) [m/s^2]; NaN
                              as dl */
  double *theta;           /* 3 n: link angles (all) [rad] */
  int *niter;              /* n: iterations of the theta solve (fk; inverse
                              with the multiroot route), 0 in closed form */
  double *solve_resid;     /* n: max |f_k| after the theta solve (inverse,
                              fk) [-]; 0 in closed form */
  double *F;               /* 3 n: actuating forces (inverse) [N] */
  double *F_effect;        /* RPS3_NEFFECT 3 n: share of effect k in F_j of
                              point i at [(k * 3 + j) * n + i] (inverse) [N] */
  double *lambda;          /* 3 n: multipliers (inverse) [N/m]; NaN where
                              not computed (Newton-Euler: has_lambda 0) */
  double *cond;            /* n: condition number of the lambda system
                              (inverse) [-] */
  double *transmission;    /* n: force transmission (inverse) [-], as
                              d->transmission */
  double *energy_residual; /* n: energy-rate residual (inverse) [W]; NaN
                              without RPS3_OUT_CERTIFY */
  double *energy_scale;    /* n: scale of the energy-rate residual (inverse)
                              [W]; NaN without RPS3_OUT_CERTIFY */
  size_t nfail;            /* written: number of points whose status is not
                              RPS3_OK */
  size_t first_fail;       /* written: index of the first of them (n if none) */
} rps3_batch_out;

/*
 * rps3_inverse (pose, rates, accelerations -> forces) over in->n points:
 * reads pose, dpose, ddpose; writes status, warn, l, theta, niter, F,
 * F_effect, lambda, cond, energy_residual, transmission, dl, ddl, c,
 * energy_scale, solve_resid.
 */
RPS3_API int rps3_inverse_batch(const rps3_model *m, rps3_data *d,
                                const rps3_batch_in *in, rps3_batch_out *out);

/*
 * rps3_ik over in->n points: reads pose; writes status, warn, l, theta, c.
 */
RPS3_API int rps3_ik_batch(const rps3_model *m, rps3_data *d,
                           const rps3_batch_in *in, rps3_batch_out *out);

/*
 * rps3_fk over in->n points: reads l and guess; writes status, warn, pose,
 * theta, niter, solve_resid, c.  With guess the solve of point i starts
 * from guess i, whatever opt.warm_start; without it, as rps3_fk starts: from
 * the previous point of d when opt.warm_start, else from rps3_theta_guess.
 */
RPS3_API int rps3_fk_batch(const rps3_model *m, rps3_data *d,
                           const rps3_batch_in *in, rps3_batch_out *out);

/* -------------------------------------------------------- forward dynamics */

/*
 * Forward dynamics: the accelerations the actuator forces produce.  The
 * paper's independent coordinates are the link lengths l (section III); its
 * equations (21)-(24), (34) eliminated to them read
 *   Mq(l) ddl + hq(l, dl) = F,
 * Mq the joint-space mass matrix and hq the bias forces of the selected
 * effects (m->opt.effects) and the model's bodies (m->bodies, the paper's
 * or the general ones), by virtual power (docs/simulation.md gives how
 * they are assembled).  rps3_invdyn is another formulation of the same
 * equations (Lagrange and Newton-Euler): one inverts the other.  Forces
 * F > 0 extend the links, as in rps3_invdyn.  The controllers of
 * rps3_ctrl_update apply their model's inverse dynamics in this form,
 * F = Mq ddl + hq.
 *
 * Reads d->l (lengths [m]), d->dl (rates [m/s]) and d->F (forces [N]);
 * theta is solved from l (Newton's method from d->theta when
 * m->opt.warm_start and d->have_theta, falling back to rps3_fk: keep one
 * data per simulated plant so that the solve tracks its assembly mode; a
 * root in another mode than opt.mode asks for is RPS3_EMODE).  Writes the
 * positions and d->pose (as rps3_fk), dtheta, vc, omega, dpose (as
 * rps3_joint_velocity), ddl, ddtheta, ac, domega, and Mq, hq, Mcond, mode.
 * d->ddpose is not written.  Allocates nothing.
 *
 * Returns RPS3_OK; RPS3_EINVAL (NULL or uninitialised model, non-finite
 * dl or F, or no inertia selected: one of platform_inertia,
 * link_inertia, payload must be, with a mass); the status of the theta
 * solve (RPS3_ENOCONV, RPS3_EBRANCH, RPS3_EMODE, RPS3_EINVAL for bad
 * lengths);
 * RPS3_ESING at a singular configuration, with "singular configuration:
 * " and the measure that decided in d->err: the constraint Jacobian
 * df/dtheta or Mq conditioned worse than opt.cond_max (1-norm), Mq not
 * positive definite (decided by its Cholesky factor, never by rounding
 * below cond_max), a failed theta solve whose doubled Newton step from
 * the warm start, of at most 0.05 rad, crosses det df/dtheta = 0 (the
 * lengths lie past the fold), or an acceleration not finite (no acceleration is
 * returned then, d->ddl is set to NaN so that it cannot be mistaken for one);
 * RPS3_ERANGE when another result overflows (ddtheta, ac, domega, hq, Mq; e.g.
 * rates of 1e200).  With pin friction of exact sign (friction.vreg = 0) the
 * acceleration is discontinuous where a dtheta_i changes sign.
 */
RPS3_API int rps3_fwddyn(const rps3_model *m, rps3_data *d);

/*
 * Kinetic energy T and potential energy P [J] of the selected effects at
 * the state in d (after rps3_fwddyn, or positions and rps3_joint_velocity,
 * or rps3_ik and rps3_velocity), written from the Cartesian motion (vc,
 * omega) of every body, independently of Mq: platform (1/2) M |vc|^2 +
 * (1/2) omega . I omega and M g z_c, links (1/2) Jlink dtheta^2 and
 * m g d sin(theta), payload likewise; general bodies (m->bodies) from
 * their standard parameters m->std and their frames' motion.  The zero of
 * P is the base plane.
 * *fric receives the power of the pin friction torques [W] (<= 0); any
 * output may be NULL.  Returns RPS3_OK, RPS3_EINVAL, RPS3_ESTATE
 * (positions or velocities missing) or RPS3_ERANGE (an energy or power not
 * finite; d is const, so no message is stored).
 */
RPS3_API int rps3_energy(const rps3_model *m, const rps3_data *d, double *T,
                         double *P, double *fric);

/* -------------------------------------------------------------- trajectory */

typedef enum {
  RPS3_TRAJ_HELIX = 1,     /* the paper's section VI helix, Tables I-II */
  RPS3_TRAJ_SINE = 2,      /* each pose coordinate a sinusoid */
  RPS3_TRAJ_WAYPOINTS = 3, /* poses at given times joined by a time law */
  RPS3_TRAJ_PATH = 4,      /* a Cartesian path of the platform centre */
  RPS3_TRAJ_TABLE = 5      /* samples of the pose, interpolated */
} rps3_traj_kind;

/* Helix (35): radius r*, pitch h, start z_i, one pitch in T* seconds; phi(t)
   linear with parabolic blends of length t_a at both ends, peak rate
   2 pi / (T* - t_a) so that phi(T*) = 2 pi; alpha = -phi/2 + pi/2 (36),
   cos beta = 1 - 2 r* / r (37, errata), z_c = z_i + h t / T*. */
typedef struct {
  double radius; /* r* [m], 0 <= r* < r/2 */
  double pitch;  /* h [m] */
  double z0;     /* z_i [m] */
  double period; /* T* [s] */
  double blend;  /* t_a [s], 0 < t_a <= T* / 2; t_b = T* - t_a */
} rps3_helix;

/* pose_k(t) = mean_k + amp_k sin(2 pi freq_k t + phase_k), k = alpha, beta,
   z_c, for 0 <= t <= duration. */
typedef struct {
  double mean[3];  /* [rad, rad, m] */
  double amp[3];   /* [rad, rad, m] */
  double freq[3];  /* [Hz] */
  double phase[3]; /* [rad] */
  double duration; /* [s] */
} rps3_sine;

/*
 * Time laws s(tau), tau in [0, 1], s(0) = 0, s(1) = 1, for a motion from
 * one pose (or path point) to the next:
 *   LSPB     linear segment with parabolic blends of a fraction f of the
 *            segment at both ends (as the paper's Table I): peak rate
 *            1 / (1 - f), acceleration 1 / (f (1 - f)); at rest at both ends.
 *   MINJERK  the minimum-jerk motion between rests (Flash & Hogan 1985),
 *            s = 10 tau^3 - 15 tau^4 + 6 tau^5: peak rate 15/8, peak
 *            acceleration 10 / sqrt(3); velocity and acceleration zero at
 *            both ends.
 *   QUINTIC  waypoints only: a quintic per segment through the waypoints
 *            without stopping; the rate at an inner waypoint is the mean of
 *            the slopes of its two segments when they have the same sign,
 *            else 0 (Craig's heuristic), the acceleration there 0; at rest
 *            at the first and last waypoint.  With two waypoints it is
 *            MINJERK.  Continuous rate and acceleration.
 */
typedef enum {
  RPS3_LAW_LSPB = 0,
  RPS3_LAW_MINJERK = 1,
  RPS3_LAW_QUINTIC = 2
} rps3_time_law;

/*
 * Waypoints: pose[i] at time[i], i = 0 .. n-1, joined by a time law per
 * coordinate.  The arrays belong to the caller and must outlive the
 * trajectory (they are read, never copied or freed).  With limits
 * (vmax_k > 0 or amax_k > 0; LSPB and MINJERK only) each segment is
 * stretched just enough that no coordinate exceeds them: a segment of
 * duration T moving coordinate k by D lasts
 *   max(T, |D| v* / vmax_k, sqrt(|D| a* / amax_k))
 * with v*, a* the law's peak rate and acceleration, and the later
 * waypoints move later.  rps3_traj_duration() is the stretched span;
 * evaluation finds the segment in O(n).
 */
typedef struct {
  size_t n;                /* number of waypoints, >= 2 */
  const double *time;      /* n times [s]: time[0] = 0, strictly increasing */
  const double (*pose)[3]; /* n poses (alpha, beta, z_c) [rad, rad, m] */
  rps3_time_law law;
  double blend;   /* LSPB: blend fraction f of each segment,
                     0 < f <= 1/2 */
  double vmax[3]; /* rate limits [rad/s, rad/s, m/s], 0: none */
  double amax[3]; /* acceleration limits [rad/s^2, rad/s^2, m/s^2],
                     0: none */
} rps3_waypoints;

/*
 * Table: samples of a motion, row i at time[i], interpolated per coordinate
 * with the exact first and second derivatives of the interpolant:
 *   rate and acc given   the quintic Hermite interpolant of the values,
 *                        rates and accelerations of each row: C2, exact
 *                        for quintics;
 *   rate given, acc NULL the cubic Hermite interpolant of the values and
 *                        rates: C1, the acceleration jumps at the rows (a
 *                        time on a row takes the segment that starts
 *                        there, the last row the last segment's end).
 * A table without measured rates takes them from rps3_table_spline(): the
 * slopes of the not-a-knot cubic spline through the values, with which the
 * cubic Hermite interpolant is that spline (C2, exact for cubics; for a
 * smooth motion sampled every h, its error is O(h^4) in the value, O(h^3)
 * in the rate and O(h^2) in the acceleration: docs/trajectories.md).
 * The trajectory's time is time[i] - time[0]: it starts at the first row
 * and lasts time[n-1] - time[0].  The arrays belong to the caller and must
 * outlive the trajectory (read, never copied or freed).  Evaluation finds
 * the segment by bisection, O(log n).
 */
typedef struct {
  size_t n;                 /* rows, >= 2 */
  const double *time;       /* n times [s], strictly increasing */
  const double (*value)[3]; /* n samples: the pose (alpha, beta, z_c)
                               [rad, rad, m], or the centre (x, y, z) [m]
                               of a path */
  const double (*rate)[3];  /* n rates [value unit / s], given or from
                               rps3_table_spline() */
  const double (*acc)[3];   /* n accelerations [value unit / s^2], or NULL */
} rps3_table;

/*
 * The slopes of the not-a-knot cubic spline through the n rows (time[i],
 * value[i]) into rate (n rows): the second and the last but one row are not
 * knots, i.e. the third derivative is continuous there (de Boor, A
 * Practical Guide to Splines, ch. IV; MATLAB's and SciPy's default), so
 * that any cubic is reproduced exactly.  work: n doubles of scratch.
 * Nothing is allocated.  Returns RPS3_OK, RPS3_EINVAL for a NULL pointer,
 * n < 4 (n = 3 leaves the not-a-knot system singular), times not finite
 * and strictly increasing, or a value not finite, or RPS3_ERANGE when a
 * rate overflows (rate then holds it).
 */
RPS3_API int rps3_table_spline(size_t n, const double *time,
                               const double (*value)[3], double (*rate)[3],
                               double *work);

/* shapes of a path of the platform centre */
typedef enum {
  RPS3_PATH_LINE = 0,   /* from start to end */
  RPS3_PATH_CIRCLE = 1, /* horizontal circle: centre, radius, angle0, turns */
  RPS3_PATH_HELIX = 2,  /* the circle rising by pitch per turn */
  RPS3_PATH_TABLE = 3   /* the centre sampled in a table (rps3_table) */
} rps3_path_shape;

/*
 * Path: the platform centre (x_c, y_c, z_c)(t), turned into the pose by
 * inverting (3)-(4): with rho_c = sqrt(x_c^2 + y_c^2) and psi the polar
 * angle of (x_c, y_c),
 *   1 - cos beta = 2 rho_c / r,  alpha = pi/2 - psi/2,
 * psi followed continuously along the path (the paper's (36)-(37) for the
 * helix).  The centre's x and y are set by alpha and beta (the paper: "the
 * Cartesian position may be controlled at the sacrifice of orientation
 * freedoms"), so every point of the path must keep 0 < rho_c < r/2: the
 * axis itself (rho_c = 0) leaves alpha undefined and its rates infinite.
 * The path parameter follows the time law over [0, duration]:
 *   line    c = start + s (end - start)
 *   circle  phi = angle0 + 2 pi turns s, c = centre + radius (cos phi,
 *           sin phi, 0)
 *   helix   as the circle, and z_c = centre_z + pitch turns t / duration:
 *           the rise is uniform in time, as in the paper's (35).
 *   table   the centre (x, y, z) of rps3_table's rows, interpolated as
 *           there; its time is the table's (duration, law and blend are
 *           not read), and psi on segment i is table_psi[i] plus the angle
 *           from row i's centre to c(t) (in (-pi, pi]): the path must turn
 *           by less than pi/2 about the axis from one row to the next.
 * The paper's helix is shape helix, centre (0, 0, z_i), radius r*,
 * angle0 0, turns 1, pitch h, duration T*, law LSPB with blend t_a / T*.
 */
typedef struct {
  rps3_path_shape shape;
  double start[3];   /* line: first point of the centre [m] */
  double end[3];     /* line: last point [m] */
  double centre[3];  /* circle, helix: centre of the circle at t = 0 [m] */
  double radius;     /* circle, helix: radius [m], > 0 */
  double angle0;     /* circle, helix: starting angle, from +X [rad] */
  double turns;      /* circle, helix: turns, < 0 clockwise */
  double pitch;      /* helix: rise per turn [m] */
  double duration;   /* [s] */
  rps3_time_law law; /* LSPB or MINJERK (QUINTIC is MINJERK here) */
  double blend;      /* LSPB: blend fraction, 0 < f <= 1/2 */
  rps3_table table;  /* table: rows of the centre (x, y, z) [m] */
  const double *table_psi; /* table: n polar angles of the rows' centres,
                              unwrapped, from rps3_table_unwrap() [rad] */
} rps3_path;

/*
 * The polar angles psi of the n centres (x, y, z) into psi (n values),
 * followed continuously: psi[0] = atan2(y_0, x_0), then each row adds the
 * angle from the previous centre to its own, in (-pi, pi].  Returns RPS3_OK
 * or RPS3_EINVAL for a NULL pointer or a centre not finite.  Nothing is
 * allocated.
 */
RPS3_API int rps3_table_unwrap(size_t n, const double (*centre)[3],
                               double *psi);

typedef struct {
  rps3_traj_kind kind;
  rps3_helix helix;  /* used when kind == RPS3_TRAJ_HELIX */
  rps3_sine sine;    /* used when kind == RPS3_TRAJ_SINE */
  rps3_waypoints wp; /* used when kind == RPS3_TRAJ_WAYPOINTS */
  rps3_path path;    /* used when kind == RPS3_TRAJ_PATH */
  rps3_table table;  /* used when kind == RPS3_TRAJ_TABLE: the pose */
} rps3_traj;

/* Name of a time law ("lspb", "minimum_jerk", "quintic"), NULL if out of
   range; and the law with this name, or -1. */
RPS3_API const char *rps3_time_law_name(int law);
RPS3_API int rps3_time_law_index(const char *name);

/* The paper's helix of Table II.  tr NULL: does nothing. */
RPS3_API void rps3_traj_default(rps3_traj *tr);

/*
 * Validate tr for model m (initialised).  RPS3_OK or RPS3_EINVAL with the
 * offending field in *chk (chk may be NULL; its name a dotted one such as
 * "trajectory.radius").  Besides each field's range
 * and each kind's rules, every kind must give what a run evaluates at
 * every sample: a span (rps3_traj_duration, stretched for waypoints) > 0
 * and at most RPS3_TRAJ_SPAN_MAX seconds, and rates whose squares (the
 * dynamics' velocity products) and accelerations are finite: checked in
 * closed form where a kind has one (the helix's and the sine's peaks,
 * each waypoint segment, each table segment, the centre's peaks of a
 * line, circle or helix path), and by evaluating the
 * trajectory at 65 times over its span (with the inverse dynamics'
 * closed-form stages where a rate passes 1e6 or an acceleration 1e12).  A short
 * segment (1e-300 s), a tiny limit (vmax 1e-308) or a huge count (turns 1e300)
 * is refused here rather than failing every sample of a run.
 */
#define RPS3_TRAJ_SPAN_MAX 1000000000000
RPS3_API int rps3_traj_check(const rps3_model *m, const rps3_traj *tr,
                             rps3_check *chk);

/* Time span of the trajectory [s] (T* for the helix); 0 for tr NULL, an
   unknown kind, or waypoints without their arrays. */
RPS3_API double rps3_traj_duration(const rps3_traj *tr);

/*
 * Pose, rate and acceleration at time t in [0, duration], exact (for a
 * table: the interpolant's own, see rps3_table).  The helix
 * acceleration jumps at the blend corners t_a and t_b: a sample exactly on a
 * corner takes the value of the segment that starts there (right limit),
 * except t = T*, which takes the left limit.  Any output may be NULL.
 * Returns RPS3_OK, RPS3_EINVAL (bad arguments: m or tr NULL, m not
 * initialised, t not finite, an unknown kind, law or path shape, blends
 * that do not fit (LSPB's f outside (0, 1/2], the helix's t_a outside
 * (0, T* / 2] or T* <= 0), or the arrays of a waypoints, table or path
 * table NULL or fewer than 2 rows; checked before the span),
 * RPS3_EDOMAIN (t outside the span), RPS3_EREACH (a path not checked by
 * rps3_traj_check() whose centre leaves 0 < rho_c < r/2 at t) or
 * RPS3_ERANGE (a pose, rate or
 * acceleration not finite: a trajectory that did not pass
 * rps3_traj_check, e.g. NaN in a field or a sine whose acceleration
 * overflows; the outputs then hold the non-finite values).  On any other
 * failure the outputs given are NaN.
 */
RPS3_API int rps3_traj_eval(const rps3_model *m, const rps3_traj *tr, double t,
                            double pose[3], double dpose[3], double ddpose[3]);

/* ------------------------------------------------------------ input fields */

/*
 * Every input field that rps3_model_init() and rps3_traj_check() validate,
 * one row each: RPS3_FIELDS(X) calls
 *   X(ID, IN, MEMBER, N, IS_INT, LO, LO_OPEN, HI, UNIT, NAME)
 * ID is the field's identifier (enum rps3_field_id), IN the structure that
 * holds it (RPS3_IN_MODEL: rps3_model; RPS3_IN_HELIX, RPS3_IN_SINE: the
 * rps3_traj of that kind), MEMBER its member designator, N its number of
 * components (doubles or ints; 0 for a pointer to a caller's array, whose
 * rows the kind's own rules check), IS_INT 1 for an int field.  Each component
 * must be finite and lie in [LO, HI], LO excluded when LO_OPEN; the rules
 * that involve several fields are listed in the comments of
 * rps3_model_init() and rps3_traj_check().  UNIT is the UDUNITS spelling
 * ("1": dimensionless, "-": a code).  NAME is the dotted name that starts
 * every message about the field.  A program that fills these structures
 * from its own input (a scene file) maps a failure back to its input by ID,
 * and may read the ranges here instead of repeating them.
 */
/* the rows of a general body (rps3_body) and of a friction law
   (rps3_friction), and those of leg K (1-3) of rps3_model.leg: e.g.
   RPS3_F_LEG2_PISTON_MASS, "leg2.piston.mass" */
#define RPS3_BODY_FIELDS(X, ID, MEMBER, NAME)                               \
  X(ID##_MASS, RPS3_IN_MODEL, MEMBER.mass, 1, 0, 0, 0, HUGE_VAL, "kg",      \
    NAME ".mass")                                                           \
  X(ID##_COM, RPS3_IN_MODEL, MEMBER.com, 3, 0, -HUGE_VAL, 0, HUGE_VAL, "m", \
    NAME ".com")                                                            \
  X(ID##_INERTIA, RPS3_IN_MODEL, MEMBER.inertia, 6, 0, -HUGE_VAL, 0,        \
    HUGE_VAL, "kg m^2", NAME ".inertia")
#define RPS3_FRICTION_FIELDS(X, ID, MEMBER, NAME, UV, UC, UR)               \
  X(ID##_VISCOUS, RPS3_IN_MODEL, MEMBER.viscous, 1, 0, 0, 0, HUGE_VAL, UV,  \
    NAME ".viscous")                                                        \
  X(ID##_COULOMB, RPS3_IN_MODEL, MEMBER.coulomb, 1, 0, 0, 0, HUGE_VAL, UC,  \
    NAME ".coulomb")                                                        \
  X(ID##_VREG, RPS3_IN_MODEL, MEMBER.vreg, 1, 0, 0, 0, HUGE_VAL, UR,        \
    NAME ".vreg")
#define RPS3_LEG_FIELDS(X, K)                                               \
  RPS3_BODY_FIELDS(X, RPS3_F_LEG##K##_CYLINDER, leg[K - 1].cylinder,        \
                   "leg" #K ".cylinder")                                    \
  RPS3_BODY_FIELDS(X, RPS3_F_LEG##K##_PISTON, leg[K - 1].piston,            \
                   "leg" #K ".piston")                                      \
  RPS3_FRICTION_FIELDS(X, RPS3_F_LEG##K##_PIN, leg[K - 1].pin,              \
                       "leg" #K ".pin_friction", "N m s/rad", "N m",        \
                       "rad/s")                                             \
  RPS3_FRICTION_FIELDS(X, RPS3_F_LEG##K##_PRISMATIC, leg[K - 1].prismatic,  \
                       "leg" #K ".prismatic_friction", "N s/m", "N", "m/s")

#define RPS3_FIELDS(X)                                                         \
  X(RPS3_F_R, RPS3_IN_MODEL, R, 1, 0, 0, 1, HUGE_VAL, "m", "R")                \
  X(RPS3_F_RHO, RPS3_IN_MODEL, rho, 1, 0, 0, 1, HUGE_VAL, "1", "rho")          \
  X(RPS3_F_PLATFORM_MASS, RPS3_IN_MODEL, M, 1, 0, 0, 0, HUGE_VAL, "kg", "M")   \
  X(RPS3_F_LINK_MASS, RPS3_IN_MODEL, m, 1, 0, 0, 0, HUGE_VAL, "kg", "m")       \
  X(RPS3_F_D, RPS3_IN_MODEL, d, 1, 0, 0, 0, HUGE_VAL, "m", "d")                \
  X(RPS3_F_LINK_IC, RPS3_IN_MODEL, link_Ic, 1, 0, 0, 0, HUGE_VAL, "kg m^2",    \
    "link_Ic")                                                                 \
  X(RPS3_F_G, RPS3_IN_MODEL, g, 1, 0, 0, 0, HUGE_VAL, "m/s^2", "g")            \
  X(RPS3_F_PAYLOAD_MASS, RPS3_IN_MODEL, payload.mass, 1, 0, 0, 0, HUGE_VAL,    \
    "kg", "payload.mass")                                                      \
  X(RPS3_F_PAYLOAD_COM, RPS3_IN_MODEL, payload.com, 3, 0, -HUGE_VAL, 0,        \
    HUGE_VAL, "m", "payload.com")                                              \
  X(RPS3_F_PAYLOAD_INERTIA, RPS3_IN_MODEL, payload.inertia, 3, 0, 0, 0,        \
    HUGE_VAL, "kg m^2", "payload.inertia")                                     \
  X(RPS3_F_VISCOUS, RPS3_IN_MODEL, friction.viscous, 1, 0, 0, 0, HUGE_VAL,     \
    "N m s/rad", "pin_friction.viscous")                                       \
  X(RPS3_F_COULOMB, RPS3_IN_MODEL, friction.coulomb, 1, 0, 0, 0, HUGE_VAL,     \
    "N m", "pin_friction.coulomb")                                             \
  X(RPS3_F_VREG, RPS3_IN_MODEL, friction.vreg, 1, 0, 0, 0, HUGE_VAL, "rad/s",  \
    "pin_friction.vreg")                                                       \
  X(RPS3_F_BODIES, RPS3_IN_MODEL, bodies, 1, 1, 0, 0, 1, "-", "bodies")        \
  RPS3_BODY_FIELDS(X, RPS3_F_PLATFORM_BODY, platform, "platform")              \
  RPS3_LEG_FIELDS(X, 1)                                                        \
  RPS3_LEG_FIELDS(X, 2)                                                        \
  RPS3_LEG_FIELDS(X, 3)                                                        \
  X(RPS3_F_EFFECTS, RPS3_IN_MODEL, opt.effects, 1, 1, 0, 0, RPS3_EFF_ALL, "-", \
    "opt.effects")                                                             \
  X(RPS3_F_METHOD, RPS3_IN_MODEL, opt.method, 1, 1, 0, 0, 1, "-",              \
    "opt.method")                                                              \
  X(RPS3_F_THETA, RPS3_IN_MODEL, opt.theta, 1, 1, 0, 0, 1, "-", "opt.theta")   \
  X(RPS3_F_SOLVER, RPS3_IN_MODEL, opt.solver, 1, 1, 0, 0, RPS3_NSOLVER - 1,    \
    "-", "opt.solver")                                                         \
  X(RPS3_F_TOL, RPS3_IN_MODEL, opt.tol, 1, 0, 0, 1, HUGE_VAL, "1", "opt.tol")  \
  X(RPS3_F_MAX_ITER, RPS3_IN_MODEL, opt.max_iter, 1, 1, 1, 0, 2147483647.0,    \
    "1", "opt.max_iter")                                                       \
  X(RPS3_F_WARM_START, RPS3_IN_MODEL, opt.warm_start, 1, 1, 0, 0, 1, "-",      \
    "opt.warm_start")                                                          \
  X(RPS3_F_OUTPUTS, RPS3_IN_MODEL, opt.outputs, 1, 1, 0, 0, RPS3_OUT_ALL, "-", \
    "opt.outputs")                                                             \
  X(RPS3_F_COND_WARN, RPS3_IN_MODEL, opt.cond_warn, 1, 0, 1, 0, HUGE_VAL, "1", \
    "opt.cond_warn")                                                           \
  X(RPS3_F_COND_MAX, RPS3_IN_MODEL, opt.cond_max, 1, 0, 1, 0, HUGE_VAL, "1",   \
    "opt.cond_max")                                                            \
  X(RPS3_F_TRANS_WARN, RPS3_IN_MODEL, opt.trans_warn, 1, 0, 0, 1, HUGE_VAL,    \
    "1", "opt.trans_warn")                                                     \
  X(RPS3_F_TRANS_MAX, RPS3_IN_MODEL, opt.trans_max, 1, 0, 0, 1, HUGE_VAL, "1", \
    "opt.trans_max")                                                           \
  X(RPS3_F_MODE, RPS3_IN_MODEL, opt.mode, 1, 1, -1, 0, 1, "-", "opt.mode")     \
  X(RPS3_F_KIND, RPS3_IN_TRAJ, kind, 1, 1, RPS3_TRAJ_HELIX, 0,                 \
    RPS3_TRAJ_TABLE, "-", "trajectory.kind")                                   \
  X(RPS3_F_HELIX_RADIUS, RPS3_IN_HELIX, helix.radius, 1, 0, 0, 0, HUGE_VAL,    \
    "m", "trajectory.radius")                                                  \
  X(RPS3_F_HELIX_PITCH, RPS3_IN_HELIX, helix.pitch, 1, 0, -HUGE_VAL, 0,        \
    HUGE_VAL, "m", "trajectory.pitch")                                         \
  X(RPS3_F_HELIX_Z0, RPS3_IN_HELIX, helix.z0, 1, 0, 0, 1, HUGE_VAL, "m",       \
    "trajectory.z0")                                                           \
  X(RPS3_F_HELIX_PERIOD, RPS3_IN_HELIX, helix.period, 1, 0, 0, 1, HUGE_VAL,    \
    "s", "trajectory.period")                                                  \
  X(RPS3_F_HELIX_BLEND, RPS3_IN_HELIX, helix.blend, 1, 0, 0, 1, HUGE_VAL, "s", \
    "trajectory.blend")                                                        \
  X(RPS3_F_SINE_MEAN, RPS3_IN_SINE, sine.mean, 3, 0, -HUGE_VAL, 0, HUGE_VAL,   \
    "rad, rad, m", "trajectory.mean")                                          \
  X(RPS3_F_SINE_AMP, RPS3_IN_SINE, sine.amp, 3, 0, -HUGE_VAL, 0, HUGE_VAL,     \
    "rad, rad, m", "trajectory.amp")                                           \
  X(RPS3_F_SINE_FREQ, RPS3_IN_SINE, sine.freq, 3, 0, 0, 0, HUGE_VAL, "Hz",     \
    "trajectory.freq")                                                         \
  X(RPS3_F_SINE_PHASE, RPS3_IN_SINE, sine.phase, 3, 0, -HUGE_VAL, 0, HUGE_VAL, \
    "rad", "trajectory.phase")                                                 \
  X(RPS3_F_SINE_DURATION, RPS3_IN_SINE, sine.duration, 1, 0, 0, 1, HUGE_VAL,   \
    "s", "trajectory.duration")                                                \
  X(RPS3_F_WP_TIME, RPS3_IN_WAYPOINTS, wp.time, 0, 0, 0, 0, HUGE_VAL, "s",     \
    "trajectory.waypoints.times")                                              \
  X(RPS3_F_WP_POSE, RPS3_IN_WAYPOINTS, wp.pose, 0, 0, -HUGE_VAL, 0, HUGE_VAL,  \
    "rad, rad, m", "trajectory.waypoints.poses")                               \
  X(RPS3_F_WP_LAW, RPS3_IN_WAYPOINTS, wp.law, 1, 1, 0, 0, 2, "-",              \
    "trajectory.waypoints.law")                                                \
  X(RPS3_F_WP_BLEND, RPS3_IN_WAYPOINTS, wp.blend, 1, 0, 0, 1, 0.5, "1",        \
    "trajectory.waypoints.blend_ratio")                                        \
  X(RPS3_F_WP_VMAX, RPS3_IN_WAYPOINTS, wp.vmax, 3, 0, 0, 0, HUGE_VAL,          \
    "rad/s, rad/s, m/s", "trajectory.waypoints.vmax")                          \
  X(RPS3_F_WP_AMAX, RPS3_IN_WAYPOINTS, wp.amax, 3, 0, 0, 0, HUGE_VAL,          \
    "rad/s^2, rad/s^2, m/s^2", "trajectory.waypoints.amax")                    \
  X(RPS3_F_PATH_SHAPE, RPS3_IN_PATH, path.shape, 1, 1, 0, 0, 3, "-",           \
    "trajectory.path.shape")                                                   \
  X(RPS3_F_PATH_START, RPS3_IN_PATH, path.start, 3, 0, -HUGE_VAL, 0, HUGE_VAL, \
    "m", "trajectory.path.start")                                              \
  X(RPS3_F_PATH_END, RPS3_IN_PATH, path.end, 3, 0, -HUGE_VAL, 0, HUGE_VAL,     \
    "m", "trajectory.path.end")                                                \
  X(RPS3_F_PATH_CENTRE, RPS3_IN_PATH, path.centre, 3, 0, -HUGE_VAL, 0,         \
    HUGE_VAL, "m", "trajectory.path.centre")                                   \
  X(RPS3_F_PATH_RADIUS, RPS3_IN_PATH, path.radius, 1, 0, 0, 0, HUGE_VAL, "m",  \
    "trajectory.path.radius")                                                  \
  X(RPS3_F_PATH_ANGLE0, RPS3_IN_PATH, path.angle0, 1, 0, -HUGE_VAL, 0,         \
    HUGE_VAL, "rad", "trajectory.path.angle0")                                 \
  X(RPS3_F_PATH_TURNS, RPS3_IN_PATH, path.turns, 1, 0, -HUGE_VAL, 0, HUGE_VAL, \
    "1", "trajectory.path.turns")                                              \
  X(RPS3_F_PATH_PITCH, RPS3_IN_PATH, path.pitch, 1, 0, -HUGE_VAL, 0, HUGE_VAL, \
    "m", "trajectory.path.pitch")                                              \
  X(RPS3_F_PATH_DURATION, RPS3_IN_PATH, path.duration, 1, 0, 0, 1, HUGE_VAL,   \
    "s", "trajectory.path.duration")                                           \
  X(RPS3_F_PATH_LAW, RPS3_IN_PATH, path.law, 1, 1, 0, 0, 2, "-",               \
    "trajectory.path.law")                                                     \
  X(RPS3_F_PATH_BLEND, RPS3_IN_PATH, path.blend, 1, 0, 0, 1, 0.5, "1",         \
    "trajectory.path.blend_ratio")                                             \
  X(RPS3_F_PATH_TABLE_TIME, RPS3_IN_PATH, path.table.time, 0, 0, -HUGE_VAL, 0, \
    HUGE_VAL, "s", "trajectory.path.table.t")                                  \
  X(RPS3_F_PATH_TABLE_VALUE, RPS3_IN_PATH, path.table.value, 0, 0, -HUGE_VAL,  \
    0, HUGE_VAL, "m", "trajectory.path.table.centre")                          \
  X(RPS3_F_PATH_TABLE_RATE, RPS3_IN_PATH, path.table.rate, 0, 0, -HUGE_VAL, 0, \
    HUGE_VAL, "m/s", "trajectory.path.table.rate")                             \
  X(RPS3_F_PATH_TABLE_ACC, RPS3_IN_PATH, path.table.acc, 0, 0, -HUGE_VAL, 0,   \
    HUGE_VAL, "m/s^2", "trajectory.path.table.acc")                            \
  X(RPS3_F_TABLE_TIME, RPS3_IN_TABLE, table.time, 0, 0, -HUGE_VAL, 0,          \
    HUGE_VAL, "s", "trajectory.table.t")                                       \
  X(RPS3_F_TABLE_VALUE, RPS3_IN_TABLE, table.value, 0, 0, -HUGE_VAL, 0,        \
    HUGE_VAL, "rad, rad, m", "trajectory.table.pose")                          \
  X(RPS3_F_TABLE_RATE, RPS3_IN_TABLE, table.rate, 0, 0, -HUGE_VAL, 0,          \
    HUGE_VAL, "rad/s, rad/s, m/s", "trajectory.table.rate")                    \
  X(RPS3_F_TABLE_ACC, RPS3_IN_TABLE, table.acc, 0, 0, -HUGE_VAL, 0, HUGE_VAL,  \
    "rad/s^2, rad/s^2, m/s^2", "trajectory.table.acc")

/* where a field lives: the model, or the trajectory (of one kind) */
enum rps3_field_in {
  RPS3_IN_MODEL = 0,
  RPS3_IN_TRAJ = 1,                    /* rps3_traj, any kind */
  RPS3_IN_HELIX = 1 + RPS3_TRAJ_HELIX, /* rps3_traj, kind helix */
  RPS3_IN_SINE = 1 + RPS3_TRAJ_SINE,   /* rps3_traj, kind sine */
  RPS3_IN_WAYPOINTS = 1 + RPS3_TRAJ_WAYPOINTS,
  RPS3_IN_PATH = 1 + RPS3_TRAJ_PATH,
  RPS3_IN_TABLE = 1 + RPS3_TRAJ_TABLE
};

#define RPS3_FIELD_ID_(ID, ...) ID,
typedef enum { RPS3_FIELDS(RPS3_FIELD_ID_) RPS3_NFIELD } rps3_field_id;
#undef RPS3_FIELD_ID_

/* one row of RPS3_FIELDS */
typedef struct {
  const char *name; /* dotted name, as in the messages */
  int in;           /* enum rps3_field_in */
  size_t offset;    /* offsetof(rps3_model or rps3_traj, MEMBER) */
  int n;            /* components */
  int is_int;       /* 1: int components, 0: double */
  double lo;        /* range of each component: [lo, hi], */
  int lo_open;      /* lo excluded when 1 */
  double hi;
  const char *unit; /* UDUNITS spelling */
} rps3_field_info;

/* Row of field id (0 <= id < RPS3_NFIELD), NULL otherwise. */
RPS3_API const rps3_field_info *rps3_field(int id);

/* -------------------------------------------------------------- simulation */

/*
 * Simulation of the plant: the state y = (l, dl) of the paper's independent
 * coordinates integrated by GSL odeiv2 with the accelerations of
 * rps3_fwddyn, theta solved at every evaluation warm-started from the
 * previous one so that the plant stays on the assembly mode it started in.
 * Two quadratures ride along: the work of the actuator forces W_F = int
 * F . dl dt and of the pin friction W_f = int sum T_i dtheta_i dt, so that
 * (T + P)(t) - (T + P)(t0) - W_F - W_f (the energy residual) measures the
 * integration error of every step and of the run.
 *
 * Forces come from a controller, called at a fixed rate with zero-order
 * hold (the integrator restarts at every tick, where the force jumps), or,
 * with rate 0, at every evaluation as a continuous force law (open-loop
 * feedforward, an ideal continuous controller).  At a tick the controller
 * sees the measured lengths and rates: the true ones plus optional Gaussian
 * noise (a generator of the simulation, seeded) and quantised; a
 * controller that declares RPS3_CTRL_USES_PLANT is offered the plant's
 * state there too (rps3_plant_state).  The actuators saturate at
 * |F_i| <= fmax.
 *
 * A run stops at the first failure with a status and the time: the plant's
 * forward dynamics failing (RPS3_ESING at the singular surface, whatever
 * the integrator, with "singular configuration at t = T s: " and the
 * measure that decided: the condition number of df/dtheta or of Mq above
 * opt.cond_max, Mq not positive definite, no theta near the last root
 * (twice the Newton step crosses det df/dtheta = 0), the assembly mode
 * changing, or an integrator that gave up one step h short of it;
 * RPS3_EBRANCH / RPS3_ENOCONV / RPS3_EREACH from the theta solve away
 * from it: docs/simulation.md), a link leaving [l_min, l_max]
 * (RPS3_EREACH), the integrator giving up (RPS3_ENOCONV: step below hmin or
 * more than max_steps steps in a control period), or the controller's own
 * status.  Nothing is allocated after rps3_sim_alloc (except inside GSL's
 * implicit steppers).  Integrators other than rk4 are GSL odeiv2's.
 */
typedef enum {
  RPS3_INT_RK4 = 0,   /* classical Runge-Kutta 4, fixed step h, four
                         evaluations a step: real time */
  RPS3_INT_RKF45 = 1, /* Runge-Kutta-Fehlberg 4(5), adaptive */
  RPS3_INT_RK8PD = 2, /* Runge-Kutta Prince-Dormand 8(9), adaptive */
  RPS3_INT_MSBDF = 3, /* variable-order BDF, implicit, adaptive (stiff) */
  RPS3_INT_RK4IMP = 4 /* implicit Gauss-Legendre 4, fixed step h (stiff).
                         GSL 2.7's implicit steppers (msbdf, rk4imp)
                         allocate inside their steps: offline use only */
} rps3_integrator;
#define RPS3_NINTEGRATOR 5

/* Name of an integrator ("rk4", "rkf45", "rk8pd", "msbdf", "rk4imp"), NULL
   if out of range; and the integrator of a name, or -1. */
RPS3_API const char *rps3_integrator_name(int integrator);
RPS3_API int rps3_integrator_index(const char *name);

typedef struct {
  rps3_integrator integrator;
  double h;           /* fixed step of rk4 and rk4imp, the largest that
                         divides each control period evenly is used; first
                         step of the adaptive ones [s].  Default 1e-3 */
  double epsabs;      /* adaptive error control on y = (l, dl, W_F, W_f):
                         |err_i| <= epsabs + epsrel |y_i|; epsabs > 0
                         for rkf45, rk8pd, msbdf.  Default 1e-9 */
  double epsrel;      /* default 1e-9 */
  double hmin;        /* adaptive steps below this fail the run [s], 1e-12 */
  long max_steps;     /* integrator steps per control period (or per call of
                         rps3_sim_advance with a continuous controller),
                         default 100000 */
  double fmax;        /* actuator saturation |F_i| <= fmax [N]; 0 = none */
  double l_min;       /* workspace: stroke of the links [m], default 0 */
  double l_max;       /* default +inf (HUGE_VAL) */
  double noise_l;     /* standard deviation of the measured lengths [m] */
  double noise_dl;    /* ... of the measured rates [m/s] */
  double quant_l;     /* quantum of the measured lengths [m], 0 = none */
  double quant_dl;    /* quantum of the measured rates [m/s], 0 = none */
  unsigned long seed; /* seed of the noise generator */
} rps3_sim_options;

/* Fill o with the defaults above (rk4, h = 1 ms, no noise, no limits); o
   NULL: does nothing. */
RPS3_API void rps3_sim_options_default(rps3_sim_options *o);

/*
 * A force law.  fn is called with its state, the time [s] and the measured
 * (rate > 0) or true (rate = 0) lengths [m] and rates [m/s], and writes the
 * commanded forces F [N]; it returns RPS3_OK or a status that stops the
 * run.  It must not allocate if the loop is to stay allocation-free.
 */
typedef int (*rps3_control_fn)(void *state, double t, const double l[3],
                               const double dl[3], double F[3]);

struct rps3_fd_state; /* internal: a forward-dynamics state */

/*
 * The plant at a controller's tick, offered to a controller that declares
 * RPS3_CTRL_USES_PLANT: a read-only view of the state the simulation has
 * evaluated there anyway, so that a controller whose model shares the
 * plant's geometry (or all of it) need not solve theta, or form Mq and hq,
 * again.  Valid only during the call.  Offered (not NULL) at a tick of a
 * controller with rate > 0 whose measurement is exact (no noise, no
 * quantisation: then l, dl below are the measured ones bit for bit); NULL
 * otherwise (noise or quantisation on, a continuous controller).  The
 * state is a lean one: no pose, no positions (rps3_sim_data holds them after
 * the call of rps3_sim_advance).  What the controller may take is its own
 * decision: e.g. theta and its rates when its model has the plant's R and
 * rho, Mq and hq only when its masses and effects are the plant's too.
 */
typedef struct {
  const rps3_model *model; /* the plant's model (the simulation's copy) */
  double t;                /* the tick's time [s] */
  double l[3], dl[3];      /* link lengths [m] and rates [m/s] */
  double theta[3];         /* link angles, the theta solve's root [rad] */
  double dtheta[3];        /* their rates [rad/s] */
  double Mq[9];            /* the plant's inverse dynamics in the link
                              coordinates, F = Mq ddl + hq ((23) in joint
                              space): Mq row-major [kg], */
  double hq[3];            /* hq [N] (gravity, velocity products and
                              friction of the plant's effects) */
  int mode;                /* assembly mode (rps3_data.mode) */
  const struct rps3_fd_state *fd; /* internal: the plant's kept state, whose
                                kinematics rps3_ctrl_update_plant takes
                                (NULL in a view built by hand: then it
                                solves its own) */
} rps3_plant_state;

/* rps3_controller.caps: what a controller declares it can use */
#define RPS3_CTRL_USES_PLANT                    \
  1u /* call fn_plant (not fn) with the plant's \
        state at the tick, or NULL */
#define RPS3_CTRL_CAPS_ALL RPS3_CTRL_USES_PLANT

/* The force law of a controller with RPS3_CTRL_USES_PLANT: fn's arguments
   and the plant's state at the tick (NULL when not offered, above). */
typedef int (*rps3_control_plant_fn)(void *state, double t, const double l[3],
                                     const double dl[3],
                                     const rps3_plant_state *plant,
                                     double F[3]);

/*
 * A controller: its law, its state and its rate; caps declares what it can
 * use (0: nothing but the measurement, fn is called).  The members after
 * rate are zero in an initialiser that names the first three only, e.g.
 *   rps3_controller c = {my_law, &my_state, 1000.0};
 * and a law that wants the plant's state declares it:
 *   rps3_controller c = {NULL, &my_state, 1000.0, RPS3_CTRL_USES_PLANT,
 *                        my_plant_law};
 */
typedef struct {
  rps3_control_fn fn; /* the law (caps without RPS3_CTRL_USES_PLANT) */
  void *state;        /* passed to fn or fn_plant */
  double rate;        /* control rate [Hz], zero-order hold; 0:
                         continuous */
  unsigned caps;      /* RPS3_CTRL_* bits; others are refused
                         (RPS3_EINVAL) */
  rps3_control_plant_fn fn_plant; /* the law with RPS3_CTRL_USES_PLANT */
} rps3_controller;

/* What a simulation reports of its state (rps3_sim_now): the state at
   s's time after rps3_sim_advance, or where the run stopped. */
typedef struct {
  double t;               /* simulated time [s] */
  double y[8];            /* l [m], dl [m/s], W_F, W_f [J] */
  double F_cmd[3];        /* last commanded forces [N] */
  double F[3];            /* forces applied (saturated) [N] */
  double l_meas[3];       /* last measured lengths [m] */
  double dl_meas[3];      /* last measured rates [m/s] */
  double T, P;            /* kinetic, potential energy at t [J] */
  double E0;              /* T + P at the start [J] */
  double energy_residual; /* T + P - E0 - W_F - W_f [J] */
  int mode;               /* tracked assembly mode (rps3_data.mode) */
  int status;             /* RPS3_OK, or why the run stopped */
  double failed_at;       /* time of the failure [s], NaN while running */
  long nsteps;            /* integrator steps taken */
  long nevals;            /* forward dynamics evaluations */
  long nticks;            /* controller calls at the control rate */
  long nsat;              /* ticks with a saturated actuator */
} rps3_sim_report;

/* A simulation: the plant (a copy), its options, its workspace, the
   integrator and the report, opaque; read it through
   rps3_sim_now, rps3_sim_data, rps3_sim_plant and rps3_sim_opts. */
typedef struct rps3_sim rps3_sim;

/* The report of s (valid until s is freed; rps3_sim_start and
   rps3_sim_advance update it), NULL for s NULL. */
RPS3_API const rps3_sim_report *rps3_sim_now(const rps3_sim *s);

/* The plant workspace of s, read-only: after rps3_sim_advance the
   positions, rates and accelerations of the state at its time, all of
   them, and after a failure err, which says why.  During a call it is the
   integrator's scratch.  NULL for s NULL. */
RPS3_API const rps3_data *rps3_sim_data(const rps3_sim *s);

/* The simulated plant (the copy s made) and the options of s; NULL for s
   NULL. */
RPS3_API const rps3_model *rps3_sim_plant(const rps3_sim *s);
RPS3_API const rps3_sim_options *rps3_sim_opts(const rps3_sim *s);

/*
 * Allocate a simulation of the plant (initialised; its options choose the
 * effects and the theta solve) with options o (NULL: defaults): the plant
 * data and the GSL driver.  Returns RPS3_OK, RPS3_EINVAL with "FIELD =
 * VALUE: reason" in chk->msg (FIELD e.g. "simulate.h"; chk->field -1: the
 * options are not rows of RPS3_FIELDS) or RPS3_ENOMEM with what could not
 * be allocated in chk->msg.  chk may be NULL.
 */
RPS3_API int rps3_sim_alloc(const rps3_model *plant, const rps3_sim_options *o,
                            rps3_sim **out, rps3_check *chk);

/* Free a simulation; NULL is accepted. */
RPS3_API void rps3_sim_free(rps3_sim *s);

/*
 * The limits of a control rate, which rps3_sim_advance applies at every
 * call (over |t| <= max(|t0|, |t_end|)), for a set-up to check first:
 * rate finite and >= 0 (0: a continuous controller), and a rate > 0 whose
 * period P = 1 / rate is
 *   - at least h / RPS3_SIM_RATE_H_MAX (rk4, rk4imp; hmin for the
 *     adaptive methods, whose h is a first guess): at most that many
 *     control periods a step;
 *   - at least t_max / RPS3_SIM_MAX_PERIODS: the ticks t0 + k P stay apart
 *     in double precision (far below the 1e-6 periods that merge times),
 *     and a run holds at most 1e8 control periods (1 kHz: up to 1e5 s);
 *   - for rk4 and rk4imp, at most max_steps steps of h (ceil(P / h)).
 * o NULL: the defaults.  Returns RPS3_OK or RPS3_EINVAL with "FIELD =
 * VALUE: reason" in chk->msg (FIELD "simulate.rate" or "simulate.h", or a
 * field of the options as rps3_sim_alloc names it; chk may be NULL).
 */
#define RPS3_SIM_RATE_H_MAX 1000
#define RPS3_SIM_MAX_PERIODS 100000000
RPS3_API int rps3_sim_check_rate(const rps3_sim_options *o, double rate,
                                 double t_max, rps3_check *chk);

/*
 * Start (or restart) at time t0 from the pose (alpha, beta, z_c) and its
 * rates: the closed-form inverse kinematics fixes l, dl and the assembly
 * mode.  Clears the work, the counters, the status, reseeds the noise.
 * Returns RPS3_OK or the status of rps3_ik / rps3_velocity / rps3_fwddyn
 * (with zero forces) at the start, also stored in the report's status
 * (rps3_sim_now); RPS3_EINVAL (nothing changed) for s, pose or dpose NULL or t0
 * not finite.
 */
RPS3_API int rps3_sim_start(rps3_sim *s, double t0, const double pose[3],
                            const double dpose[3]);

/*
 * Advance from s's time t (rps3_sim_now(s)->t) to t_end under controller
 * c (not NULL), calling it at the ticks t0 + k / rate that fall in
 * [t, t_end) (or at every evaluation when rate is 0).  On return the
 * report's t = t_end and the report (rps3_sim_now) and the workspace
 * (rps3_sim_data) describe that state; or the run stopped: the report's
 * status != RPS3_OK, failed_at the time, the workspace's err the message, and
 * the state the last good one (RPS3_ESING at the singular surface for every
 * integrator, "singular configuration at t = T s: " and its measure: see the
 * section's comment).  Returns the report's status; after a failure it returns
 * that status again without integrating.  An invalid call changes nothing and
 * returns RPS3_EINVAL with d->err's message: c or c->fn NULL, t_end not finite
 * or before the report's t (t_end = t does nothing), or a rate outside
 * rps3_sim_check_rate's limits; RPS3_ESTATE before rps3_sim_start.  Allocates
 * nothing.  The state is reported (d's positions, pose and rates; T, P, the
 * energy residual) at the call's end only, or where the run stopped: one call
 * over many control periods costs less than one call a period, and gives the
 * same run bit for bit when t_end is a tick (k / rate).  At a t_end just past a
 * tick (within rounding) that tick has been served: d's accelerations are those
 * of its new force.
 */
RPS3_API int rps3_sim_advance(rps3_sim *s, const rps3_controller *c,
                              double t_end);

/* ------------------------------------------------------------- controllers */

/*
 * Controllers shipped with the library, each following a trajectory with
 * its own model of the mechanism (which may differ from the plant's: e.g.
 * no link mass, as the paper's case 1 assumes).  The desired link motion
 * (l_d, dl_d, ddl_d) and the feedforward forces are rps3_inverse of the
 * controller's model along the trajectory at the tick's time (after the
 * trajectory's span: its final pose, at rest).  With e = l_d - l and
 * de = dl_d - dl from the measured l, dl:
 *   open loop       F = F_d, the inverse dynamics of the desired motion
 *                   (kp, kd unused; rate 0 makes it a continuous force)
 *   PD              F = kp e + kd de
 *   PD + gravity    F = kp e + kd de + G(l), G the controller model's
 *                   static forces at the measured lengths (rps3_invdyn at
 *                   dl = ddl = 0)
 *   computed torque F = rps3_invdyn of the controller's model at the
 *                   measured (l, dl) with ddl = ddl_d + kp e + kd de:
 *                   kp [1/s^2], kd [1/s] set the error dynamics
 *                   e'' + kd e' + kp e = 0 when the models agree.
 * PD gains are [N/m] and [N s/m].  The controllers use the plant's state
 * offered at a tick (rps3_plant_state) as any controller may, through
 * RPS3_CTRL_USES_PLANT (rps3_ctrl_bind): a model with the plant's geometry
 * (R, rho), no payload, warm starts and a theta tolerance no tighter than
 * the plant's takes the plant's theta and velocity maps at the tick
 * instead of solving them again, and the plant's Mq and hq when its masses
 * and effects are the plant's too; its limits stay its own, and its forces
 * those it would compute alone (to the solve's tolerance).
 */
typedef enum {
  RPS3_CTRL_OPEN_LOOP = 0,
  RPS3_CTRL_PD = 1,
  RPS3_CTRL_PD_GRAVITY = 2,
  RPS3_CTRL_COMPUTED_TORQUE = 3
} rps3_ctrl_kind;
#define RPS3_NCTRL 4

/* Name of a controller kind ("open_loop", "pd", "pd_gravity",
   "computed_torque"), NULL if out of range; and the kind of a name, or
   -1. */
RPS3_API const char *rps3_ctrl_name(int kind);
RPS3_API int rps3_ctrl_index(const char *name);

/* A library controller: its kind, gains, model (a copy), trajectory (a
   copy) and workspaces, opaque; what a caller reads is
   read through the functions below. */
typedef struct rps3_ctrl rps3_ctrl;

/*
 * Allocate a controller of this kind with gains kp, kd (finite, >= 0),
 * model (initialised) and trajectory (checked against model by
 * rps3_traj_check).  Returns RPS3_OK, RPS3_EINVAL with the failure in
 * *chk (a trajectory field by identifier; chk->field -1 for the kind and
 * the gains, "simulate.controller", "simulate.kp", "simulate.kd"), or
 * RPS3_ENOMEM with what could not be allocated in chk->msg.  chk may be
 * NULL.
 */
RPS3_API int rps3_ctrl_alloc(rps3_ctrl_kind kind, double kp, double kd,
                             const rps3_model *model, const rps3_traj *traj,
                             rps3_ctrl **out, rps3_check *chk);

/* Free a controller; NULL is accepted. */
RPS3_API void rps3_ctrl_free(rps3_ctrl *c);

/*
 * The control law, an rps3_control_fn: state is the rps3_ctrl.  Writes
 * F and the logging fields; returns RPS3_OK (F finite) or the status of
 * the model's stages (e.g. RPS3_ENOCONV when measured lengths have no
 * assembly near the last one), RPS3_EINVAL for a NULL pointer, a kind out
 * of range, or a time or measured length or rate not finite (a sensor
 * glitch: no law turns it into a force; the err of rps3_ctrl_measured
 * names the input), or RPS3_ERANGE for a force that overflows (the same
 * err).  Allocates nothing.
 * Bind it with rps3_ctrl_bind, or as
 *   rps3_controller c = {rps3_ctrl_update, ctrl, 1000.0};
 * which solves every measured state itself.
 */
RPS3_API int rps3_ctrl_update(void *state, double t, const double l[3],
                              const double dl[3], double F[3]);

/*
 * The same law as an rps3_control_plant_fn: with plant not NULL (the
 * plant's state at the tick, l and dl its own), the model takes what it
 * may of it (above); with plant NULL it is rps3_ctrl_update.
 */
RPS3_API int rps3_ctrl_update_plant(void *state, double t, const double l[3],
                                    const double dl[3],
                                    const rps3_plant_state *plant, double F[3]);

/* The controller of c at rate [Hz]: {rps3_ctrl_update, c, rate,
   RPS3_CTRL_USES_PLANT, rps3_ctrl_update_plant}. */
RPS3_API rps3_controller rps3_ctrl_bind(rps3_ctrl *c, double rate);

/* ------------------------------------------------------------------ design */

/*
 * Design optimisation: what a designer chooses before building (base radius,
 * platform ratio, link stroke, joint ranges, masses), the model it makes,
 * and the indices that say how good it is over a set of poses (reach, force
 * transmission, conditioning, parasitic motion) and along a task (actuator
 * force and power).  docs/design.md gives every definition with its
 * equation and unit.  The positions come from the library's own
 * kinematics (rps3_inverse: (2)-(7), (39)); this section adds only what it
 * measures on them.  A workspace (rps3_design_ws_alloc) holds all scratch:
 * the evaluations allocate nothing, print nothing, never abort.
 */

/*
 * A design.  The geometry of Table II, the joint limits and a mass model
 * whose links are an actuator body and a uniform rod:
 *   link mass      m       = actuator_mass + link_density l_max
 *   centroid       d       = (actuator_mass actuator_d
 *                             + link_density l_max^2 / 2) / m   (0 if m = 0)
 *   inertia        link_Ic = link_density l_max^3 / 12
 *                            + link_density l_max (l_max / 2 - d)^2
 *                            + actuator_mass (actuator_d - d)^2
 * about the centroid, about the pin direction: the rod spans the pin to
 * l_max (the cylinder and the rod of a linear actuator at full stroke, a
 * constant as the paper's d is), the actuator body is a point at
 * actuator_d from the pin.  rps3_design_default() gives Table II exactly
 * for the model: R = 0.2286, rho = 0.5, M = 0.18, m = 0.09 (all actuator,
 * link_density 0), d = 0.1524, link_Ic = 0.
 */
typedef struct {
  double R;                    /* base radius, centre to pin joints [m] */
  double rho;                  /* r / R, r the platform radius [-] */
  double l_min, l_max;         /* link stroke: shortest, longest length [m] */
  double theta_min, theta_max; /* pin joint range: link angle to the base
                                  plane, theta of (39) [rad], within
                                  [0, pi] */
  double ball_max;             /* ball joint cone half-angle [rad]: the largest
                                  angle between a link and the platform normal
                                  (the socket's axis), in (0, pi] */
  double link_radius;          /* radius of a link's capsule for interference
                                  between links [m]; 0: not checked */
  double M;              /* platform mass, a uniform disc of radius r [kg] */
  double payload;        /* payload mass, a point on the platform normal
                            through its centre [kg] */
  double payload_height; /* payload above the platform centre, along the
                           platform normal [m] */
  double actuator_mass;  /* mass of a link's actuator body [kg] */
  double actuator_d;     /* its distance from the pin [m] */
  double link_density;   /* mass per unit length of a link's rod [kg/m] */
  double g;              /* gravitational acceleration [m/s^2] */
} rps3_design;

/*
 * Every field of rps3_design that rps3_design_model() validates:
 * RPS3_DESIGN_FIELDS(X) calls X(ID, MEMBER, LO, LO_OPEN, HI, UNIT, NAME) as
 * RPS3_FIELDS does (NAME is the dotted name that starts a message, here the
 * member's name).  The rules between fields: l_max > l_min (a stroke > 0),
 * theta_max > theta_min, and a link mass model whose m, d, link_Ic are
 * finite.
 */
#define RPS3_DESIGN_FIELDS(X)                                             \
  X(RPS3_DF_R, R, 0, 1, HUGE_VAL, "m", "R")                               \
  X(RPS3_DF_RHO, rho, 0, 1, HUGE_VAL, "1", "rho")                         \
  X(RPS3_DF_L_MIN, l_min, 0, 0, HUGE_VAL, "m", "l_min")                   \
  X(RPS3_DF_L_MAX, l_max, 0, 1, HUGE_VAL, "m", "l_max")                   \
  X(RPS3_DF_THETA_MIN, theta_min, 0, 0, 3.14159265358979323846, "rad",    \
    "theta_min")                                                          \
  X(RPS3_DF_THETA_MAX, theta_max, 0, 0, 3.14159265358979323846, "rad",    \
    "theta_max")                                                          \
  X(RPS3_DF_BALL_MAX, ball_max, 0, 1, 3.14159265358979323846, "rad",      \
    "ball_max")                                                           \
  X(RPS3_DF_LINK_RADIUS, link_radius, 0, 0, HUGE_VAL, "m", "link_radius") \
  X(RPS3_DF_M, M, 0, 0, HUGE_VAL, "kg", "M")                              \
  X(RPS3_DF_PAYLOAD, payload, 0, 0, HUGE_VAL, "kg", "payload")            \
  X(RPS3_DF_PAYLOAD_HEIGHT, payload_height, -HUGE_VAL, 0, HUGE_VAL, "m",  \
    "payload_height")                                                     \
  X(RPS3_DF_ACTUATOR_MASS, actuator_mass, 0, 0, HUGE_VAL, "kg",           \
    "actuator_mass")                                                      \
  X(RPS3_DF_ACTUATOR_D, actuator_d, 0, 0, HUGE_VAL, "m", "actuator_d")    \
  X(RPS3_DF_LINK_DENSITY, link_density, 0, 0, HUGE_VAL, "kg/m",           \
    "link_density")                                                       \
  X(RPS3_DF_G, g, 0, 0, HUGE_VAL, "m/s^2", "g")

#define RPS3_DESIGN_FIELD_ID_(ID, ...) ID,
typedef enum {
  RPS3_DESIGN_FIELDS(RPS3_DESIGN_FIELD_ID_) RPS3_NDESIGN_FIELD
} rps3_design_field_id;
#undef RPS3_DESIGN_FIELD_ID_

/* rps3_field_info.in of a design field's row */
#define RPS3_IN_DESIGN 16

/* Row of design field id (0 <= id < RPS3_NDESIGN_FIELD), NULL otherwise;
   offset is offsetof(rps3_design, MEMBER), n 1, is_int 0. */
RPS3_API const rps3_field_info *rps3_design_field(int id);

/* Fill ds with Table II (above), the stroke l_min = R, l_max = 2 R (the
   paper gives none; it holds the helix of Table II), the pin range
   [0, pi] (no limit beyond the paper's branch), ball_max = pi/4, no
   interference check, no payload, g = 9.80665.  ds NULL: does nothing. */
RPS3_API void rps3_design_default(rps3_design *ds);

/*
 * Validate ds and fill m with its model: R, rho, M, the link mass model
 * above (m, d, link_Ic), g, the payload (mass and com (0, 0,
 * payload_height), no inertia; RPS3_EFF_PAYLOAD selected when payload > 0)
 * and the default options; m is then initialised (rps3_model_init).
 * Returns RPS3_OK or RPS3_EINVAL with the offending design field in *chk
 * (chk may be NULL): chk->field an rps3_design_field_id, chk->msg "NAME =
 * VALUE: reason" with the design field's NAME (e.g. "l_max = 0.4: must be
 * > l_min = 0.5 ...").  It is the design's validation: a program that
 * only validates passes a model of its own as scratch.
 */
RPS3_API int rps3_design_model(const rps3_design *ds, rps3_model *m,
                               rps3_check *chk);

/* Reachability: why a pose is outside a design's workspace (bits of
   rps3_design_out.flags).  A pose is reachable when none is set. */
enum rps3_design_flag {
  RPS3_DESIGN_STROKE = 1,    /* a link length outside [l_min, l_max] */
  RPS3_DESIGN_PIN = 2,       /* a link angle theta outside [theta_min,
                                theta_max] */
  RPS3_DESIGN_BALL = 4,      /* a ball joint bent past ball_max */
  RPS3_DESIGN_INTERFERE = 8, /* two link capsules (segment pin - ball,
                                radius link_radius) intersect */
  RPS3_DESIGN_ASSEMBLY = 16, /* no assembly: rps3_inverse refused the pose
                                (RPS3_EREACH: a ball joint not above the
                                base plane, or a link of zero length;
                                RPS3_EINVAL, RPS3_ERANGE); the other
                                outputs of the pose are NaN */
  RPS3_DESIGN_SINGULAR = 32  /* singular: the homogeneous condition number
                                above opts.cond_sing, or rps3_inverse's
                                RPS3_ESING */
};
#define RPS3_DESIGN_NFLAG 6

/* Name of flag index k (bit 1 << k): "stroke", "pin", "ball",
   "interference", "assembly", "singular"; NULL for k out of range. */
RPS3_API const char *rps3_design_flag_name(int k);

/* How the indices are evaluated. */
typedef struct {
  double lti_good;  /* good transmission: LTI >= lti_good, 0.7 [-] */
  double length;    /* characteristic length L of the homogeneous
                       condition number [m]; 0: the platform radius r */
  double cond_sing; /* RPS3_DESIGN_SINGULAR above this homogeneous
                       condition number, 1e8 [-] */
} rps3_design_opts;

/* Fill o with the defaults above.  o NULL: does nothing. */
RPS3_API void rps3_design_opts_default(rps3_design_opts *o);

/*
 * Per-pose results of rps3_design_eval, arrays of n (3 n component-major
 * as rps3_batch_out: link j of pose i at [j * n + i]); each is written
 * when not NULL; flags is required.  Where RPS3_DESIGN_ASSEMBLY is set
 * every other output of the pose is NaN; the others are computed for
 * every pose that assembles, reachable or not (an atlas shows why).
 *
 * Force transmission (docs/design.md).  At a pose, each leg i carries two
 * unit wrenches on the platform, both pure forces through its ball centre
 * b_i: the transmission wrench along the link phi_i (what the actuator
 * pushes), and the constraint wrench along the pin axis (what the R joint
 * holds; the leg, R-P-S, has 5 freedoms).  Their six rows
 * (f, (b_i - c) x f) make the overall Jacobian G (Joshi & Tsai 2002):
 * G (v_c, omega) = (l', 0).  The output twist of row k is the platform
 * twist t_k that every other row is reciprocal to, G t_k = e_k; the
 * velocity of b_k under it is v_k = v_c + omega x (b_k - c), and f_k . v_k
 * = 1.  The index of row k is the cosine of its pressure angle:
 *   eta_k = |f_k . v_k| / (|f_k| |v_k|) = 1 / |v_k|,  in [0, 1]
 * (Wang, Wu & Liu 2010, the output transmission index in its pressure
 * angle form).  OTI = min over the transmission rows (actuation
 * singularities), CTI = min over the constraint rows (constraint
 * singularities).  The input transmission index is 1 identically: the
 * prismatic actuator moves along the link, the line of its transmission
 * wrench.  LTI = min(ITI, OTI, CTI) = min(OTI, CTI); 0 where G is
 * singular.  Unit-free and invariant to scaling the mechanism.
 *
 * Homogeneous condition number: the condition number of G with its moment
 * columns divided by L (opts.length, default r), G_h with the rows
 * (f, (b_i - c) x f / L): every entry dimensionless, so metres and
 * radians are not mixed.  In the Frobenius norm, normalised (Angeles):
 *   cond_h = |G_h|_F |G_h^-1|_F / 6,   >= 1, 1 for an isotropic G_h,
 * within [cond_2 / 6, cond_2] of the 2-norm's, and smooth in the design
 * variables where the 2-norm's has kinks (singular values that cross), as
 * a gradient-based optimiser needs.  HUGE_VAL where G is singular.
 * Scaling the mechanism (R, z_c, the stroke, and L) leaves LTI and cond_h
 * unchanged.
 */
typedef struct {
  int *flags;           /* n: RPS3_DESIGN_* bits, 0 when reachable */
  double *l;            /* 3 n: link lengths (5)-(7) [m] */
  double *theta;        /* 3 n: link angles (39) [rad] */
  double *ball;         /* 3 n: ball joint angles: between link i and
                           the platform normal [rad] */
  double *clearance;    /* n: least distance between two link axes
                           (segments pin - ball) minus 2 link_radius [m] */
  double *lti;          /* n: local transmission index [-] */
  double *oti;          /* n: output transmission index [-] */
  double *cti;          /* n: constraint transmission index [-] */
  double *cond_h;       /* n: homogeneous condition number [-] */
  double *transmission; /* n: rps3_data.transmission [-] */
  double *c;            /* 3 n: platform centre (x_c, y_c, z_c), (3)-(4)
                           and the pose's z_c [m] */
  double *spin;         /* n: parasitic spin [rad], below */
} rps3_design_out;

/*
 * Summary over the reachable poses of a set (all zero, never NaN, when
 * none is: RPS3_EEMPTY).
 *
 * Parasitic spin: the orientation (2), Rz(alpha) Ry(beta) Rz(-alpha), has
 * no torsion about the platform normal in the tilt-and-torsion sense
 * (Bonev): its torsion is alpha - alpha = 0.  What the platform turns
 * about the vertical is its yaw in the Z-Y-X decomposition rot = Rz(spin)
 * Ry(pitch) Rx(roll), spin = atan2(rot[1][0], rot[0][0]), the measure of
 * parasitic rotation of the 3-RPS literature (Carretero et al. 2000),
 * reported with x_c, y_c of (3)-(4).
 */
typedef struct {
  size_t n;              /* poses evaluated */
  size_t nreach;         /* reachable poses */
  double reach_fraction; /* nreach / n [-] */
  double volume;         /* nreach times the cell volume [m rad^2] */
  double gti;            /* global transmission index: mean LTI [-] */
  double good_fraction;  /* reachable poses with LTI >= lti_good, over
                            nreach [-] */
  double lti_min;        /* least LTI [-] */
  double cond_h_max;     /* largest homogeneous condition number [-] */
  double trans_max;      /* largest rps3_data.transmission [-] */
  double xc_max, yc_max; /* largest |x_c|, |y_c| [m] */
  double spin_max;       /* largest |spin| [rad] */
  double l_lo, l_hi;     /* shortest and longest link used [m] */
  int flags_any;         /* OR of the flags of every pose */
  size_t nflag[RPS3_DESIGN_NFLAG]; /* poses with flag bit k set */
} rps3_design_summary;

/* A regular grid of poses, cell-centred: coordinate k of node j is
   lo[k] + (j + 1/2) (hi[k] - lo[k]) / n[k]; pose index i0 + n0 (i1 + n1
   i2), alpha fastest.  Cell volume prod_k (hi[k] - lo[k]) / n[k]. */
typedef struct {
  double lo[3], hi[3]; /* alpha, beta [rad], z_c [m] */
  size_t n[3];         /* nodes per coordinate, >= 1 */
} rps3_design_grid;

/* Fill gr for design ds: alpha in [-pi, pi], beta in [0, pi/3], z_c in
   [0, 2 R] (ds->R; 0.2286 when ds is NULL), 10 x 10 x 10 poses.  gr NULL:
   does nothing. */
RPS3_API void rps3_design_grid_default(const rps3_design *ds,
                                       rps3_design_grid *gr);

/* Number of poses of gr (0 for NULL, or when the product overflows). */
RPS3_API size_t rps3_design_grid_size(const rps3_design_grid *gr);

/* Pose i of gr into pose[3]; and the cell volume [m rad^2]. Return
   RPS3_OK or RPS3_EINVAL (NULL, i out of range, a bound not finite or
   hi < lo, n[k] = 0). */
RPS3_API int rps3_design_grid_pose(const rps3_design_grid *gr, size_t i,
                                   double pose[3]);
RPS3_API int rps3_design_grid_cell(const rps3_design_grid *gr, double *volume);

struct rps3_design_scratch; /* internal: GSL SVD and task blocks */

/* The workspace of the design functions: allocated once, serves any
   design; one per thread.  err holds the message of the last failure. */
typedef struct {
  rps3_model model;                /* the model of the last design evaluated */
  rps3_data *d;                    /* its data */
  rps3_error err;                  /* last error */
  struct rps3_design_scratch *scr; /* internal */
} rps3_design_ws;

/* Allocate a workspace into *out: RPS3_OK, RPS3_EINVAL (out NULL) or
   RPS3_ENOMEM (nothing leaks).  Free it with rps3_design_ws_free (NULL
   accepted). */
RPS3_API int rps3_design_ws_alloc(rps3_design_ws **out);
RPS3_API void rps3_design_ws_free(rps3_design_ws *w);

/*
 * Evaluate design ds at the n poses (alpha, beta, z_c), component-major
 * (3 n, as rps3_batch_in.pose), with options o (NULL: defaults): the
 * per-pose outputs of out (may be NULL) and the summary *sum (may be
 * NULL); cell_volume [m rad^2] (>= 0) makes sum->volume.  Returns RPS3_OK,
 * RPS3_EEMPTY (no pose reachable: out and sum filled, the summary zeros),
 * RPS3_ERANGE (the volume overflows: a cell volume near 1e308), or
 * RPS3_EINVAL with w->err (bad design, with its field's message; n = 0,
 * NULL arrays, a pose not finite, bad options).  Allocates nothing.
 */
RPS3_API int rps3_design_eval(rps3_design_ws *w, const rps3_design *ds,
                              const rps3_design_opts *o, size_t n,
                              const double *pose, double cell_volume,
                              rps3_design_out *out, rps3_design_summary *sum);

/* The same over the poses of grid gr (out's arrays hold its
   rps3_design_grid_size poses in its order), cell volume from gr. */
RPS3_API int rps3_design_eval_grid(rps3_design_ws *w, const rps3_design *ds,
                                   const rps3_design_opts *o,
                                   const rps3_design_grid *gr,
                                   rps3_design_out *out,
                                   rps3_design_summary *sum);

/* Task requirements of rps3_design_task. */
typedef struct {
  size_t nsamples;         /* samples evaluated (before a failure) */
  double F_peak[3];        /* max_t |F_i| [N] */
  double F_rms[3];         /* sqrt(mean_t F_i^2) [N] */
  double P_peak[3];        /* max_t |F_i l_i'| [W] */
  double v_peak[3];        /* max_t |l_i'| [m/s] */
  double l_lo[3], l_hi[3]; /* link length range [m] */
  double lti_min;          /* least LTI along the task [-] */
  size_t fail_index;       /* first sample outside the workspace, nsamples
                              requested if none */
  double fail_time;        /* its time [s]; NaN if none */
  int fail_flags;          /* its RPS3_DESIGN_* bits (0: rps3_inverse
                              failed, fail_status) */
  int fail_status;         /* rps3_inverse's status there (RPS3_OK if it
                              was the design's limits) */
} rps3_design_task;

/* link_mass argument of rps3_design_task */
#define RPS3_DESIGN_NO_LINK_MASS 0
#define RPS3_DESIGN_LINK_MASS 1

/*
 * What the task tr asks of design ds: the trajectory sampled at nsamples
 * (>= 2) equally spaced times t_k = k T / (nsamples - 1) over its span T,
 * the actuator forces by rps3_inverse_batch with the design's model (the
 * default effects, the payload when ds->payload > 0; with link_mass
 * RPS3_DESIGN_NO_LINK_MASS the links' gravity and inertia left out, the
 * paper's case 1), and the reachability of every sample as
 * rps3_design_eval has it.  Writes *res.  Returns RPS3_OK; RPS3_EREACH
 * when a sample is outside the workspace: res->fail_* name the first one,
 * w->err says "t = T s: " and why (the flags, or rps3_inverse's message),
 * and the statistics cover the samples before it; RPS3_EINVAL (bad
 * design, a trajectory that rps3_traj_check refuses for the design's
 * model, nsamples < 2, link_mass not 0 or 1, NULL).  Allocates nothing.
 */
RPS3_API int rps3_design_task_eval(rps3_design_ws *w, const rps3_design *ds,
                                   const rps3_design_opts *o,
                                   const rps3_traj *tr, size_t nsamples,
                                   int link_mass, rps3_design_task *res);

/*
 * The last tick of controller c, for logging: its time t [s], the desired
 * lengths l_des [m] and rates dl_des [m/s], and the feedforward forces
 * F_ff of the desired motion [N] (open loop only, which applies them; NaN
 * for the others, which do not compute them).  Before the first call, t
 * and every value are NaN.  Any output may be NULL.  Returns RPS3_OK, or
 * RPS3_EINVAL for c NULL (the outputs given are then NaN).
 */
RPS3_API int rps3_ctrl_last(const rps3_ctrl *c, double *t, double l_des[3],
                            double dl_des[3], double F_ff[3]);

/*
 * The workspaces of controller c, read-only: the desired motion's
 * (rps3_ctrl_desired: l, dl, ddl of the trajectory at the last tick) and
 * the measured state's (rps3_ctrl_measured: theta, warn and, after a
 * failed call, err, which says why).  NULL for c NULL.
 */
RPS3_API const rps3_data *rps3_ctrl_desired(const rps3_ctrl *c);
RPS3_API const rps3_data *rps3_ctrl_measured(const rps3_ctrl *c);

/* ---------------------------------------------------------- identification */

/*
 * Identification of the inertia and friction parameters
 * (docs/identification.md).  At a fixed geometry (R, rho, d, g and the
 * friction's vreg) the library's forces are linear in the paper model's
 * RPS3_NPAPER parameters pi, F = Y(q, q', q'') pi, in this order (the
 * names of rps3.ident_paper.PAPER_NAMES):
 *   0  M            platform mass, a uniform disc of radius r [kg]
 *   1  md           each link's m d [kg m] (its weight about the pin)
 *   2  Ipin         each link's m d^2 + link_Ic, about the pin [kg m^2]
 *   3  payload.m    payload mass [kg]
 *   4-6 payload.mcx, mcy, mcz   its first moment about the platform
 *                  centre, platform axes [kg m]
 *   7-9 payload.Ixx, Iyy, Izz   its inertia about the platform centre,
 *                  platform axes [kg m^2]
 *   10 pin.fv       pin viscous friction [N m s/rad]
 *   11 pin.fc       pin Coulomb friction [N m]
 * The payload of rps3_model (principal moments along the platform axes)
 * has no products of inertia about the platform centre exactly when its
 * centre of mass lies on a platform axis (two of com[] zero): only then
 * is its load in the span of these columns (rps3_paper_params).  Columns
 * 4-6 and 7-9 are linear combinations of M's with column 3 (the disc is
 * a body of the payload's kind), so a fit of all twelve is rank
 * deficient: leave M out when the payload is identified.
 */
#define RPS3_NPAPER 12

/* Name ("M", "md", "Ipin", "payload.m", ..., "pin.fc") and UDUNITS unit
   of parameter k (0 <= k < RPS3_NPAPER); NULL for k out of range. */
RPS3_API const char *rps3_paper_name(int k);
RPS3_API const char *rps3_paper_unit(int k);

/*
 * The paper parameters pi of model m (initialised): M, m d, Jlink, the
 * payload's mass, mass com and inertia about the platform centre
 * (inertia + mass (|com|^2 - com_k^2)), friction.viscous and coulomb,
 * whatever effects are selected.  Returns RPS3_OK, or RPS3_EINVAL with a
 * message in chk->msg (chk may be NULL; field -1): m NULL or not
 * initialised, pi NULL, a payload whose centre of mass is off the
 * platform axes (it has products of inertia the parameters do not hold;
 * pi is still written), general bodies (RPS3_BODIES_GENERAL) or a
 * selected prismatic friction that is not zero: outside these twelve
 * parameters, rps3_regressor_std and rps3_std_params hold them.
 */
RPS3_API int rps3_paper_params(const rps3_model *m, double pi[RPS3_NPAPER],
                               rps3_check *chk);

/*
 * The regressor of m's inverse dynamics at the point of d: Y with
 * F = Y pi for F of rps3_inverse and pi of rps3_paper_params, row i the
 * actuator, column k the parameter [N per unit of parameter k].  Reads
 * d->pose, dpose, ddpose as rps3_inverse does, and computes the
 * positions (m->opt.theta route, the multiroot one warm-started), the
 * rates and accelerations when a selected effect needs them, and the
 * singularity checks of rps3_invdyn (cond, transmission, warn); then each
 * column is the load of one unit parameter through the formulation of
 * m->opt.method and its own lambda (or ball-joint force) solve, one
 * factorization for all.  Columns of effects not selected in
 * m->opt.effects are zero (M's column holds the selected of
 * platform_gravity and platform_inertia).  No force is computed: d->F,
 * F_effect, lambda and the certificate are NaN; d->stage holds the motion
 * stages.  Allocates nothing.  Returns RPS3_OK, or the
 * status rps3_inverse returns at this point (RPS3_EINVAL, RPS3_EREACH,
 * RPS3_ESING, RPS3_ENOCONV, RPS3_EMODE, ...; RPS3_ERANGE for a column
 * not finite) with d->err; Y is then NaN.
 */
RPS3_API int rps3_regressor(const rps3_model *m, rps3_data *d,
                            double Y[3][RPS3_NPAPER]);

/*
 * rps3_regressor over in->n points (in->pose, dpose, ddpose as
 * rps3_inverse_batch reads them), component-major: Y[(i * RPS3_NPAPER +
 * k) * n + p] is row i (actuator), column k of point p.  out->status is
 * required; warn, l, theta, c, dl, ddl, cond and transmission are written
 * when not NULL; nfail, first_fail and d->err ("point P: ...") as
 * rps3_inverse_batch.  A failed point has NaN in Y.  Returns RPS3_OK, or
 * RPS3_EINVAL for an invalid call (as rps3_inverse_batch, and Y NULL).
 */
RPS3_API int rps3_regressor_batch(const rps3_model *m, rps3_data *d,
                                  const rps3_batch_in *in, double *Y,
                                  rps3_batch_out *out);

/*
 * The regressor of the general model's standard parameters (RPS3_NSTD,
 * docs/identification.md "The model"): Y (3 x RPS3_NSTD) at the point of
 * d, with F = Y pi for rps3_inverse's F and pi of rps3_std_params(m),
 * whatever m's bodies (the paper's are a special case of the general
 * ones).  Built as rps3_regressor is: each column the loads of one unit
 * standard parameter (a copy of m with the general bodies, every other
 * parameter zero) through the selected method's own solve; columns of
 * effects m does not select are zero (a platform column holds the
 * platform's gravity and inertia, a cylinder's or piston's the links').
 * Names "platform.m", "platform.mcx", ..., "piston3.Izz",
 * "prismatic1.fv", ..., "pin3.fc" and units by rps3_std_name(k),
 * rps3_std_unit(k).  Returns as rps3_regressor; allocates nothing.
 */
RPS3_API int rps3_regressor_std(const rps3_model *m, rps3_data *d,
                                double Y[3][RPS3_NSTD]);

/* rps3_regressor_std over the points of in, as rps3_regressor_batch:
   Y[(i * RPS3_NSTD + k) * n + p]. */
RPS3_API int rps3_regressor_std_batch(const rps3_model *m, rps3_data *d,
                                      const rps3_batch_in *in, double *Y,
                                      rps3_batch_out *out);

/* Name and UDUNITS unit of standard parameter k (0 <= k < RPS3_NSTD),
   NULL out of range. */
RPS3_API const char *rps3_std_name(int k);
RPS3_API const char *rps3_std_unit(int k);

/*
 * The standard parameters of model m (initialised) into pi (RPS3_NSTD):
 * its general bodies' (m->std), or for the paper's bodies the uniform
 * disc (21), each cylinder a point mass m at (d, 0, 0) with link_Ic about
 * its e2 and e3 axes, massless pistons; a selected payload added to the
 * platform's (parallel axes: F = Y pi then holds when the platform's
 * effects are selected with it); the prismatic friction of leg[i] and the
 * pin friction (friction, or leg[i].pin).  RPS3_OK, or RPS3_EINVAL (m not
 * initialised, pi NULL).
 */
RPS3_API int rps3_std_params(const rps3_model *m, double pi[RPS3_NSTD]);

/*
 * The base parameters of a regressor Y (n x p, row major) stacked over
 * exciting states: the independent columns, and how the others regroup
 * into them (docs/identification.md, "Base parameters").  The columns,
 * scaled to unit norm, are taken in their order: one is kept when its
 * part orthogonal to those kept before it is above tol (tol 1e-7, the
 * Python package's RANK_TOL, sits in the wide gap of the spectra
 * measured); a column of norm at most tol times the largest acts on
 * nothing.  Writes *nbase, the kept columns' indices in independent[0 ..
 * nbase - 1] (increasing) and K (nbase x p, row major): base = K pi, and
 * Y pi = Y[:, independent] base.  The number kept is checked against the
 * rank of the singular values (above tol times the largest): where they
 * differ tol is in no gap, RPS3_ESING.  Returns RPS3_OK, RPS3_EINVAL (NULL
 * arguments, n or p zero, p > 4096, tol outside (0, 1), a value of Y not
 * finite: named), RPS3_ESING (Y all zero, or the rank above) or
 * RPS3_ENOMEM, with the message in chk->msg (chk may be NULL).  Arrays
 * the caller's: independent of p, K of p x p.  Allocates its workspace.
 */
RPS3_API int rps3_ident_base(const double *Y, size_t n, size_t p, double tol,
                             int *independent, double *K, int *nbase,
                             rps3_check *chk);

/*
 * Estimators on a stacked regressor: n rows (one per actuator and
 * sample), p columns, F = Y theta + noise.  Unlike the per-point
 * functions they allocate their GSL workspaces on each call (once per
 * data set) and free them before returning: RPS3_ENOMEM when that fails
 * (GSL's allocators report a failure through its error handler first: a
 * program that must survive running out of memory here turns it off, see
 * "GSL" at the top).  Every other failure is a status with a message in
 * chk->msg (chk may be NULL; its field is -1), never GSL's handler.
 */
typedef struct {
  size_t n, p;              /* rows, columns; n > p */
  const double *Y;          /* n x p row-major: row r, column j at
                               [r * p + j] */
  const double *F;          /* n forces [N] */
  const int *actuator;      /* n actuator indices 0..2 of the rows (the
                               noise groups of the two-pass WLS); NULL:
                               row r is actuator r % 3 */
  const double *weight;     /* n weights > 0, the inverse variance of each
                               row [1/N^2]; NULL: rps3_ident_wls estimates
                               them (two passes), rps3_ident_consistent
                               takes 1 */
  const char *const *names; /* p column names for the messages; NULL:
                               "column j" */
} rps3_ident_data;

typedef struct {
  double rank_tol;         /* a singular value of the weighted regressor with
                              unit-norm columns below rank_tol times the largest
                              is zero: 1e-10, above the rounding of a regressor
                              computed to 1e-13 and below any usable excitation */
  double level;            /* confidence of the intervals, 0.95 */
  double reg;              /* consistent fit: weight of the total pseudo-inertia
                              trace sum_b (m_b + tr Sigma_b) [1/kg] against the
                              squared residual over |F|^2 (the tie-break among
                              bodies the data cannot tell apart; rps3.ident's
                              LMI_REG), 1e-9 */
  double xtol, gtol, ftol; /* consistent fit: GSL's convergence tests
                       (gsl_multifit_nlinear_test) of its log-Cholesky
                       stage, 1e-12, 1e-12, 0 */
  int max_iter;            /* consistent fit: iteration limit, 2000 */
  double eig_tol; /* consistent fit: a pseudo-inertia eigenvalue down to
                     -eig_tol times the body's largest counts as zero,
                     1e-10 (rounding of U U^T) */
  double opt_tol; /* consistent fit: converged when the optimality
                     measure fit->gap is at most opt_tol times fit->cost,
                     1e-6 */
} rps3_ident_opts;

/* Fill o with the defaults above.  o NULL: does nothing. */
RPS3_API void rps3_ident_opts_default(rps3_ident_opts *o);

/* Results of rps3_ident_wls; the arrays are the caller's (NULL: not
   written, theta required). */
typedef struct {
  double *theta;   /* p estimates */
  double *cov;     /* p x p covariance of theta, row-major:
                      s2 (Y^T W Y)^-1 */
  double *ci;      /* p x 2: the level's intervals, theta -+ t(dof)
                      std, t Student's quantile */
  int *unident;    /* p flags: 1 for a column in a direction the data do
                      not determine (a zero column, or a share >= 0.1 of
                      the right singular vectors below rank_tol) */
  double sigma[3]; /* each actuator's noise standard deviation [N]:
                      sqrt(|r_a|^2 / (n_a - p n_a / n)) of the first
                      pass (of the fit when the weights are given) */
  double s2;       /* weighted residual variance factor chisq / dof
                      (about 1 for right weights) */
  double cond;     /* condition number of the weighted regressor with
                      unit-norm columns */
  size_t rank;     /* numerical rank by rank_tol */
  size_t dof;      /* n - p */
} rps3_ident_result;

/*
 * Weighted least squares, theta = argmin sum_r w_r (F_r - Y_r theta)^2,
 * by gsl_multifit_wlinear on the column-scaled regressor.  Weights NULL:
 * two passes: an ordinary least-squares fit, each actuator's residual
 * variance sigma_a^2 (with a floor of 1e-24 times the mean square force,
 * so that exact data give equal weights), then w = 1 / sigma_a^2.  The
 * rank is decided before the fit by the singular values of the weighted
 * regressor with unit-norm columns (QR then SVD of R).  Returns RPS3_OK;
 * RPS3_ESING when the rank is below p: res->unident flags and chk->msg names
 * the columns the data do not determine (as many as it holds, then "and N
 * more"; theta, cov, ci NaN);
 * RPS3_EINVAL (NULL, n <= p, p = 0, a value not finite, a weight <= 0,
 * an actuator index outside 0..2 or an actuator with no row);
 * RPS3_ENOMEM.
 */
RPS3_API int rps3_ident_wls(const rps3_ident_data *data,
                            const rps3_ident_opts *o, rps3_ident_result *res,
                            rps3_check *chk);

/*
 * Which columns of pi are the 10 standard parameters of which rigid body,
 * for rps3_ident_consistent.  A body's standard parameters are, in its
 * axes about its origin: mass m [kg], first moment m c (mcx, mcy, mcz)
 * [kg m], inertia Ixx, Ixy, Ixz, Iyy, Iyz, Izz [kg m^2] (rps3.ident's
 * INERTIAL order).  col[b][k] is the column of pi holding parameter k of
 * body b, or -1 when pi does not hold it (the data do not see it; the fit
 * gives it the value of the lightest consistent body, and reports it in
 * fit->body).  A column belongs to at most one body.  kind[j] (NULL: all
 * 0) says what a column of no body is: 0 free, 1 >= 0 (friction, or a
 * body of fixed shape scaled by its mass, as the paper's disc M).
 * rps3_ident_paper_layout gives the paper model's.
 */
typedef struct {
  size_t nbody;
  const int (*col)[10];
  const int *kind;
} rps3_ident_layout;
#define RPS3_IDENT_FREE 0
#define RPS3_IDENT_NONNEG 1

/* The paper model's layout (columns as RPS3_NPAPER): body 0 a link in its
   axes at the pin, x along the link, z the pin axis (md its mcx, Ipin its
   Izz), body 1 the payload about the platform centre (its products of
   inertia -1: not in pi); M, pin.fv, pin.fc >= 0.  Static, never NULL. */
RPS3_API const rps3_ident_layout *rps3_ident_paper_layout(void);

/* Results of rps3_ident_consistent; arrays the caller's (theta
   required). */
typedef struct {
  double *theta;  /* p fitted parameters */
  double *body;   /* 10 nbody: each body's standard parameters, those
                     not in pi included */
  double *eig;    /* 4 nbody: each body's pseudo-inertia eigenvalues,
                     ascending */
  double rss;     /* sum_r w_r (F_r - Y_r theta)^2 */
  double cost;    /* rss / |F|_w^2 + reg sum_b tr J_b, minimised */
  int niter;      /* iterations */
  int consistent; /* 1: theta's every pseudo-inertia eigenvalue checked
                     >= -eig_tol times its body's largest, every >= 0
                     column >= 0 (also after RPS3_ENOCONV) */
  double gap;     /* optimality measure: how far cost may be above the
                     optimum's, from the KKT conditions (the duality gap
                     plus the decrease a violated dual condition offers) */
} rps3_ident_fit;

/*
 * Physically consistent least squares: minimise
 *   sum_r w_r (F_r - Y_r pi)^2 / |F|_w^2 + reg sum_b tr J_b
 * over pi with every body's 4 x 4 pseudo-inertia J_b = [[Sigma, m c],
 * [m c^T, m]] (Sigma = tr(I)/2 1 - I) positive semidefinite and the >= 0
 * columns >= 0 (the objective of rps3.ident.consistent).  Each J_b is
 * parametrised by a Cholesky factor, J = U U^T with U upper triangular,
 * a >= 0 column by a square, and the problem (reduced to p rows by a QR
 * of [W^1/2 Y, W^1/2 F]) solved by gsl_multifit_nlinear (trust region,
 * Powell's dogleg, Levenberg's scaling) with the analytic Jacobian, from
 * the minimum-norm least-squares solution made consistent: a few
 * iterations with the logarithms of U's diagonal as variables
 * (log-Cholesky, Rucker & Wensing 2022), then U itself, which reaches a
 * singular J_b at finite values, with Jacobian rows that carry the
 * second-order term Gauss-Newton leaves out (Newton's model near the
 * optimum) and, at a stationary point that is not optimal, a step along
 * the convex problem's best descent direction; where that plain stage
 * does not finish within 20 iterations, the convex problem itself by the
 * barrier method (Newton's method in pi with the exact Hessian of
 * -log det J_b, GSL's modified Cholesky; a stalled step hands back to
 * the plain stage).  Converged means the
 * KKT optimality measure fit->gap (the duality gap plus the decrease a
 * violated dual condition offers) is at most opt_tol times fit->cost
 * (or 1e-14, its rounding floor).  After the fit every eigenvalue is
 * checked, converged or not.  Returns RPS3_OK (fit->consistent 1);
 * RPS3_ENOCONV when the optimality test is not met within max_iter
 * iterations or the solver stopped without progress (err says so and
 * gives the measure; theta is the last iterate, fit->consistent 1 when
 * its check passed), or when the check fails (fit->consistent 0,
 * chk->msg names the body and eigenvalue); RPS3_EINVAL (bad data as
 * rps3_ident_wls, a bad layout: a column out of range or in two places,
 * a kind not 0 or 1); RPS3_ENOMEM.  No covariance: the constraints make
 * it one-sided where they are active.
 */
RPS3_API int rps3_ident_consistent(const rps3_ident_data *data,
                                   const rps3_ident_layout *layout,
                                   const rps3_ident_opts *o,
                                   rps3_ident_fit *fit, rps3_check *chk);

#ifdef __cplusplus
}
#endif

#endif /* RPS3_H */
