/*
 * ident_run.h - an identification (scene/identify.h): the regressor of the
 * paper model (rps3_regressor), or of the general model's layout
 * (rps3_regressor_std) reduced to its structural base parameters
 * (rps3_ident_base), and the forces of the inverse dynamics
 * (rps3_inverse) at every sample of the scene's trajectory, the fit of
 * the identify section's parameters (rps3_ident_wls, and with
 * identify.consistent rps3_ident_consistent), and its Monte Carlo: draw i
 * adds Gaussian noise of force_noise times each actuator's RMS force,
 * seeded by (seed, i) alone, and its first 1 - holdout of the samples
 * are fitted (and with identify.consistent by the consistent fit too), the
 * rest predicted (held-out NRMSE).  The draws are computed in
 * work units of IDENT_UNIT draws on the worker pool (pool.h), shard K of N
 * the units j with j mod N = K; a unit is one chunk row of every per-draw
 * dataset, so a part merges as a sweep's (shards/merge.h).  The file's
 * layout: docs/identification.md, "Through the runner".
 */
#ifndef RPS3_RUNNER_IDENT_RUN_H
#define RPS3_RUNNER_IDENT_RUN_H

#include <stdio.h>

#include <hdf5.h>

#include "core/progress.h"
#include "output/output.h"
#include "scene/identify.h"
#include "sweep.h"

#include "ident_fit.h"
#include "ident_plan.h"

/* The plan of identification s: its case, the parameters, Y and F0 along
   the trajectory, the truth and shares.  0, or -1 with err at the key or
   section that is wrong (a parameter the effects leave at zero, a sample
   the inverse dynamics fails at); free with ident_plan_free. */
int ident_plan_make(const scene *s, ident_plan *p, scene_error *err);
void ident_plan_free(ident_plan *p);

/*
 * The manipulator section (YAML, "manipulator:\n  ...") of the fit r: the
 * general model's from the consistent fit (bodies general, each body's
 * mass, com and inertia about the com, the friction), the paper model's
 * from the consistent fit or else the estimate (M, m = md / d, link_Ic =
 * Ipin - m d^2, the payload, the pin friction); what is not fitted keeps
 * the scene's values.  Returns a malloc'd text, or NULL with why (no
 * consistent fit for the general model, a value outside the scene's
 * ranges).
 */
char *ident_manipulator_yaml(const ident_plan *p, const ident_fit *r,
                             char *why, size_t whysz);

/* draws of shard k of n (all for n = 1) */
size_t ident_shard_draws(const ident_plan *p, size_t k, size_t n);

/* Create the file at path: root attributes and scene (out_open), the fit
   r of the noise-free forces, the manipulator section yaml (root attribute
   manipulator_yaml; NULL: yaml_why in manipulator_yaml_missing), and the
   per-draw datasets when the plan has draws; NULL with err.  Closed by out_close. */
out_file *ident_file_open(const char *path, const scene *s, const ident_plan *p,
                          const ident_fit *r, const char *yaml,
                          const char *yaml_why, const out_meta *meta,
                          char *err, size_t errsz);

/* The draws of shard `shard` of `nshard` into f on nthread threads,
   counts in st.  Returns 0, or -1 with err. */
int ident_mc_run(const ident_plan *p, out_file *f, size_t shard, size_t nshard,
                 int nthread, progress *pr, sweep_stats *st, char *err,
                 size_t errsz);

/*
 * The Monte Carlo's summary of the open file (read-write): per parameter
 * its median relative error, relative bias and the coverage of its
 * intervals over the draws whose status is 0, and of the draws' held-out
 * NRMSEs and consistent fits (the fractions consistent and converged, the
 * NRMSE ratio consistent / WLS), written to the mc_* summary datasets
 * and, when out is not NULL, printed.
 * A file that is not an identification with draws: nothing, 0.  Returns
 * 0 or -1 with err.
 */
int ident_summary(hid_t file, FILE *out, char *err, size_t errsz);

/* ident_summary of the file at path (merge's last step) */
int ident_summary_path(const char *path, FILE *out, char *err, size_t errsz);

#endif /* RPS3_RUNNER_IDENT_RUN_H */
