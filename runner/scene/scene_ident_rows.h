/*
 * scene_ident_rows.h - the rows of SCENE_KEYS (scene.h) of an
 * identification's section, identify: (docs/identification.md, "Through
 * the runner"): IDS rows, values of scene_ident (scene.h), checked
 * against the scene by scene_ident_check_keys (identify.c).
 */
#ifndef RPS3_RUNNER_SCENE_IDENT_ROWS_H
#define RPS3_RUNNER_SCENE_IDENT_ROWS_H

#define SCENE_IDENT_KEYS(X)                                                    \
  X(K_ID_PARAMS, "identify.parameters", KEY_PARAMS, IDS,                       \
    (ids.params, 0, 0, RPS3_NPAPER - 1, "-", -1,                               \
     "by the effects: M, md, Ipin, pin.*, payload.*"),                         \
    REQ_NO, "pi",                                                              \
    "the paper model's parameters to fit, by name; default those the "         \
    "effects fill: M (without payload), md (link_gravity), Ipin "              \
    "(link_inertia), pin.fv, pin.fc (pin_friction), payload.m, .mcx, .mcy, "   \
    ".mcz, .Ixx, .Iyy, .Izz (payload)")                                        \
  X(K_ID_MODEL, "identify.model", KEY_ENUM, IDS,                              \
    (ids.model, 0, 0, 1, "-", -1, "manipulator.bodies"), REQ_NO, "-",          \
    "paper (the 12 parameters of identify.parameters) or general (the "       \
    "standard parameters of the bodies and friction the effects fill, as "    \
    "base parameters)")                                                        \
  X(K_ID_LEGS, "identify.legs", KEY_ENUM, IDS,                                 \
    (ids.legs, 0, 0, 1, "-", IDENT_LEGS_EACH, NULL), REQ_NO, "-",              \
    "model general: each (every leg its own cylinder, piston and friction) "  \
    "or identical (one cylinder, piston and friction for the three legs)")    \
  X(K_ID_METHOD, "identify.method", KEY_ENUM, IDS,                             \
    (ids.method, 0, 0, 1, "-", IDENT_WLS, NULL), REQ_NO, "-",                  \
    "ols (equal weights) or wls (each actuator weighted by its residual "      \
    "variance, two passes)")                                                   \
  X(K_ID_CONSISTENT, "identify.consistent", KEY_BOOL, IDS,                     \
    (ids.consistent, 0, 0, 1, "-", 0, NULL), REQ_NO, "-",                      \
    "also the physically consistent fit (pseudo-inertias positive "            \
    "semidefinite, M and the friction >= 0)")                                  \
  X(K_ID_MAX_ITER, "identify.max_iter", KEY_INT, IDS,                         \
    (ids.max_iter, 0, 1, 1000000.0, "1", 2000, NULL), REQ_NO, "-",             \
    "the consistent fit's iteration limit (rps3_ident_opts.max_iter); a fit "  \
    "that reaches it is kept, consistent, with a warning")                     \
  X(K_ID_LEVEL, "identify.level", KEY_REAL, IDS,                               \
    (ids.level, 0, 1, 0.9999, "1", 0.95, NULL), REQ_NO, "-",                   \
    "confidence level of the intervals (Student's t)")                         \
  X(K_ID_DATA, "identify.data", KEY_FILE, IDS,                                 \
    (file[TABLE_MEASURED], 0, 0, 0, "-", 0, "the trajectory's"), REQ_NO, "-",  \
    "measured table (CSV or HDF5, relative to the scene) of t, l1, l2, l3, "   \
    "l1_dot.., l1_ddot.., F1, F2, F3 [s, m, m/s, m/s^2, N]; without it the "   \
    "forces are the inverse dynamics along the trajectory")                    \
  X(K_ID_RUNS, "identify.monte_carlo.runs", KEY_INT, IDS,                      \
    (ids.runs, 0, 0, 10000000.0, "1", 0, NULL), REQ_NO, "-",                   \
    "Monte Carlo draws of force noise, each fitted; 0: none")                  \
  X(K_ID_NOISE, "identify.monte_carlo.force_noise", KEY_REAL, IDS,             \
    (ids.force_noise, GE0, "1", 0.01, NULL), REQ_NO, "-",                      \
    "standard deviation of the Gaussian force noise as a fraction of each "    \
    "actuator's RMS force")                                                    \
  X(K_ID_SEED, "identify.monte_carlo.seed", KEY_INT, IDS,                      \
    (ids.seed, 0, 0, 2147483647.0, "1", 1, NULL), REQ_NO, "-",                 \
    "seed of the draws: draw i's noise depends on (seed, i) only")          \
  X(K_ID_HOLDOUT, "identify.monte_carlo.holdout", KEY_REAL, IDS,               \
    (ids.holdout, 0, 0, 0.5, "1", 0.2, NULL), REQ_NO, "-",                     \
    "fraction of the samples (the last ones) the draws' fits leave out and "  \
    "predict (held-out NRMSE); 0: none")

#endif /* RPS3_RUNNER_SCENE_IDENT_ROWS_H */
