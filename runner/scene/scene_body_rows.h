/*
 * scene_body_rows.h - the rows of SCENE_KEYS (scene.h) for the bodies of the
 * general model (rps3_model.bodies, platform, leg; docs/runner.md,
 * "General bodies"), written once per body and friction law as
 * RPS3_LEG_FIELDS writes the library's.  Leg K's keys are LIB rows of
 * RPS3_F_LEGK_*; the keys under manipulator.legs are LEGS rows, one value
 * for the three legs (scene_own.legs), each filling that field of every
 * leg whose own key is not in the file (scene_legs_fill).
 */
#ifndef RPS3_RUNNER_SCENE_BODY_ROWS_H
#define RPS3_RUNNER_SCENE_BODY_ROWS_H

/* the rows of a body: ID##_MASS, _COM, _INERTIA at PATH.mass, .com,
   .inertia, library fields FID##_MASS ...; ORIGIN names its frame */
#define SCENE_BODY_ROWS(X, ID, PATH, SRC, FID, WHAT, ORIGIN, NOTE)             \
  X(ID##_MASS, PATH ".mass", KEY_REAL, SRC, FID##_MASS, REQ_NO, "-",           \
    WHAT ": mass" NOTE)                                                        \
  X(ID##_COM, PATH ".com", KEY_REAL3, SRC, FID##_COM, REQ_NO, "-",             \
    WHAT ": centre of mass [x, y, z] from " ORIGIN NOTE)                       \
  X(ID##_INERTIA, PATH ".inertia", KEY_REAL6, SRC, FID##_INERTIA, REQ_NO, "-", \
    WHAT ": inertia [Ixx, Ixy, Ixz, Iyy, Iyz, Izz] about its com" NOTE)

/* the rows of a friction law (rps3_friction) */
#define SCENE_FRICTION_ROWS(X, ID, PATH, SRC, FID, WHAT, NOTE)                \
  X(ID##_VISCOUS, PATH ".viscous", KEY_REAL, SRC, FID##_VISCOUS, REQ_NO, "-", \
    WHAT ": viscous coefficient" NOTE)                                        \
  X(ID##_COULOMB, PATH ".coulomb", KEY_REAL, SRC, FID##_COULOMB, REQ_NO, "-", \
    WHAT ": Coulomb level" NOTE)                                              \
  X(ID##_VREG, PATH ".vreg", KEY_REAL, SRC, FID##_VREG, REQ_NO, "-",          \
    WHAT ": Coulomb law tanh(v / vreg) instead of sign(v), 0 = sign" NOTE)

/* the rows of a leg, in the order of RPS3_LEG_FIELDS (scene_bodies.c
   relies on it): cylinder, piston, pin friction, prismatic friction */
#define SCENE_LEG_ROWS(X, ID, PATH, SRC, FID, WHICH, NOTE)                \
  SCENE_BODY_ROWS(X, ID##_CYL, PATH ".cylinder", SRC, FID##_CYLINDER,     \
                  "general: " WHICH " cylinder",                          \
                  "the pin P_i, axes e1 along the link, e2 the pin axis", \
                  NOTE)                                                   \
  SCENE_BODY_ROWS(X, ID##_PIST, PATH ".piston", SRC, FID##_PISTON,        \
                  "general: " WHICH " piston",                            \
                  "the ball joint b_i, its cylinder's axes", NOTE)        \
  SCENE_FRICTION_ROWS(X, ID##_PIN, PATH ".pin_friction", SRC, FID##_PIN,  \
                      "general: " WHICH " pin friction", NOTE)            \
  SCENE_FRICTION_ROWS(X, ID##_PRISM, PATH ".prismatic_friction", SRC,     \
                      FID##_PRISMATIC,                                    \
                      WHICH " prismatic friction, either bodies", NOTE)

#define SCENE_BODY_KEYS(X)                                                     \
  X(K_BODIES, "manipulator.bodies", KEY_ENUM, LIB, RPS3_F_BODIES, REQ_NO, "-", \
    "paper (M, m, d, link_Ic, pin_friction) or general (platform, legs)")      \
  X(K_PLATFORM_MASS, "manipulator.platform.mass", KEY_REAL, LIB,               \
    RPS3_F_PLATFORM_BODY_MASS, REQ_GENERAL, "-", "general: platform mass")     \
  X(K_PLATFORM_COM, "manipulator.platform.com", KEY_REAL3, LIB,                \
    RPS3_F_PLATFORM_BODY_COM, REQ_NO, "-",                                     \
    "general: platform centre of mass [x, y, z] in platform axes")             \
  X(K_PLATFORM_INERTIA, "manipulator.platform.inertia", KEY_REAL6, LIB,        \
    RPS3_F_PLATFORM_BODY_INERTIA, REQ_GENERAL, "-",                            \
    "general: platform inertia [Ixx, Ixy, Ixz, Iyy, Iyz, Izz] about its "      \
    "centre of mass, platform axes")                                           \
  SCENE_LEG_ROWS(X, K_LEGS, "manipulator.legs", LEGS, RPS3_F_LEG1,             \
                 "every leg's", "; a leg's own key (leg1 ...) overrides it")   \
  SCENE_LEG_ROWS(X, K_LEG1, "manipulator.leg1", LIB, RPS3_F_LEG1, "leg 1's",   \
                 "")                                                           \
  SCENE_LEG_ROWS(X, K_LEG2, "manipulator.leg2", LIB, RPS3_F_LEG2, "leg 2's",   \
                 "")                                                           \
  SCENE_LEG_ROWS(X, K_LEG3, "manipulator.leg3", LIB, RPS3_F_LEG3, "leg 3's", "")

/* the fields of one leg in RPS3_FIELDS (and the keys of one leg) */
#define SCENE_LEG_NFIELD (RPS3_F_LEG2_CYLINDER_MASS - RPS3_F_LEG1_CYLINDER_MASS)

#endif /* RPS3_RUNNER_SCENE_BODY_ROWS_H */
