/*
 * ident_file.c - an identification's file (ident_run.h): the fit of the
 * noise-free forces over the parameter dimension, each parameter also
 * alone in its own units (as python/rps3/ident_io.py writes a fit), the
 * per-draw datasets of the Monte Carlo and their summary.
 */
#include "ident_run.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <hdf5_hl.h>

/* the units of a variable over the parameter dimension */
#define VARIOUS "various: see parameter_units"

/* the scales: parameter (and again for cov's columns), bound, actuator,
   body, eigenvalue, draw (-1: none) */
enum {
  SC_PAR,
  SC_PAR2,
  SC_BOUND,
  SC_ACT,
  SC_BODY,
  SC_EIG,
  SC_DRAW,
  SC_STD,
  NSC
};

/* the unit of fitted column j (general: of its layout column) */
static const char *par_unit(const ident_plan *p, size_t j) {
  return p->general ? rps3_std_unit(p->lay_std[p->col[j]][0])
                    : rps3_paper_unit(p->col[j]);
}

/* a dataset of rank dims over the scales ax (-1 ended), written from v
   when not NULL; chunk and fill as out_h5_dataset; the handle or -1 */
static hid_t put(const out_file *f, const hid_t *sc, const char *name,
                 hid_t type, const int *ax, const hsize_t *chunk,
                 const void *fill, const void *v, const char *units,
                 const char *long_name, const char *doc) {
  hsize_t dims[4];
  int r, rank;
  hid_t ds;
  for (rank = 0; ax[rank] >= 0; rank++) {
    hid_t sp = H5Dget_space(sc[ax[rank]]);
    H5Sget_simple_extent_dims(sp, &dims[rank], NULL);
    H5Sclose(sp);
  }
  ds = out_h5_dataset(f->file, f->str, name, type, rank, dims, chunk, 0, fill,
                      units, doc);
  if (ds < 0 || out_cf_long_name(ds, f->str, long_name) < 0 ||
      (v && H5Dwrite(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, v) < 0))
    goto fail;
  for (r = 0; r < rank; r++)
    if (H5DSattach_scale(ds, sc[ax[r]], (unsigned)r) < 0) goto fail;
  return ds;
fail:
  if (ds >= 0) H5Dclose(ds);
  return -1;
}

/* put, closed; 0 or -1 */
static int put1(const out_file *f, const hid_t *sc, const char *name,
                hid_t type, const int *ax, const void *v, const char *units,
                const char *long_name, const char *doc) {
  hid_t ds = put(f, sc, name, type, ax, NULL, NULL, v, units, long_name, doc);
  return ds < 0 ? -1 : H5Dclose(ds) < 0 ? -1 : 0;
}

/* a scalar dataset; 0 or -1 */
static int put0(const out_file *f, const char *name, hid_t type, const void *v,
                const char *units, const char *long_name, const char *doc) {
  static const int none[] = {-1};
  return put1(f, NULL, name, type, none, v, units, long_name, doc);
}

/* a scale with its long_name; the handle or -1 */
static hid_t scale(const out_file *f, const char *name, hid_t type, size_t n,
                   const void *v, const char *long_name, const char *doc) {
  hid_t ds = out_h5_scale(f->file, f->str, name, type, n, v, "1", doc);
  if (ds >= 0 && out_cf_long_name(ds, f->str, long_name) < 0) {
    H5Dclose(ds);
    ds = -1;
  }
  return ds;
}

/* the scales of the file */
static int make_scales(const out_file *f, const ident_plan *p, hid_t *sc) {
  static const int32_t bound[2] = {0, 1}, act[3] = {1, 2, 3},
                       eig[4] = {1, 2, 3, 4};
  static const char *const body[2] = {"link", "payload"};
  size_t k, runs = (size_t)p->ids.runs;
  int64_t *draw;
  sc[SC_PAR] = scale(f, "parameter", f->str, p->p, p->names, "parameter",
                     p->general
                         ? "the general model's base parameter: the layout's "
                           "standard parameter it is named after, with those "
                           "that regroup into it (base_matrix)"
                         : "the paper model's parameter (rps3_paper_name)");
  /* CF: a variable's dimensions differ, so cov's columns have their own */
  sc[SC_PAR2] = scale(f, "parameter_column", f->str, p->p, p->names,
                      "parameter of the covariance's column",
                      "the paper model's parameter, as parameter");
  sc[SC_BOUND] = scale(f, "bound", H5T_NATIVE_INT32, 2, bound,
                       "bound of the interval", "0: lower, 1: upper bound");
  sc[SC_ACT] = scale(f, "actuator", H5T_NATIVE_INT32, 3, act, "actuator number",
                     "actuator (link) number i");
  if (p->general) {
    sc[SC_STD] = scale(f, "standard_parameter", f->str, p->nlay, p->lay_names,
                       "parameter of the layout",
                       "the general model's standard parameter of the "
                       "layout (identify.legs; python/rps3/ident.py "
                       "Layout.names): body.m, .mcx, .mcy, .mcz [kg, kg m] "
                       "and .Ixx ... .Izz about the body's origin [kg m^2], "
                       "friction fv, fc");
    if (sc[SC_STD] < 0) return -1;
  }
  if (p->ids.consistent && p->general) {
    sc[SC_BODY] = scale(f, "body", f->str, p->nbody, p->body_names, "body",
                        "body of the consistent fit's layout: its frame's "
                        "origin as docs/runner.md \"General bodies\"");
    sc[SC_EIG] =
        scale(f, "eigenvalue", H5T_NATIVE_INT32, 4, eig, "eigenvalue number",
              "pseudo-inertia eigenvalue k, ascending");
  } else if (p->ids.consistent) {
    sc[SC_BODY] = scale(f, "body", f->str, 2, body, "body",
                        "body of the consistent fit's layout "
                        "(rps3_ident_paper_layout)");
    sc[SC_EIG] =
        scale(f, "eigenvalue", H5T_NATIVE_INT32, 4, eig, "eigenvalue number",
              "pseudo-inertia eigenvalue k, ascending");
  }
  if (sc[SC_PAR] < 0 || sc[SC_PAR2] < 0 || sc[SC_BOUND] < 0 || sc[SC_ACT] < 0 ||
      (p->ids.consistent && (sc[SC_BODY] < 0 || sc[SC_EIG] < 0)))
    return -1;
  if (runs == 0) return 0;
  if (!(draw = malloc(runs * sizeof *draw))) return -1;
  for (k = 0; k < runs; k++) draw[k] = (int64_t)k;
  sc[SC_DRAW] =
      scale(f, "draw", H5T_NATIVE_INT64, runs, draw, "Monte Carlo draw number",
            "Monte Carlo draw i: its noise is seeded by "
            "(identify.monte_carlo.seed, i)");
  free(draw);
  return sc[SC_DRAW] < 0 ? -1 : 0;
}

/* each parameter alone, in its own units (CF readers that take one unit
   per variable) */
static int put_alone(const out_file *f, const ident_plan *p,
                     const ident_fit *r) {
  hid_t g =
      H5Gcreate2(f->file, "parameters", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  size_t j;
  int rc = g < 0 ? -1 : 0;
  for (j = 0; rc == 0 && j < p->p; j++) {
    const char *u = par_unit(p, j);
    char doc[160];
    hsize_t one = 1;
    hid_t ds;
    snprintf(doc, sizeof doc, "estimate of %s (method %s)", p->names[j],
             p->ids.method == IDENT_OLS ? "ols" : "wls");
    ds = out_h5_dataset(g, f->str, p->names[j], H5T_NATIVE_DOUBLE, 0, &one,
                        NULL, 0, NULL, u, doc);
    rc = ds < 0 ||
                 H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT,
                          &r->theta[j]) < 0 ||
                 out_h5_attr_n(ds, "std", H5T_NATIVE_DOUBLE, 0, &r->std[j]) <
                     0 ||
                 out_h5_attr_n(ds, "ci", H5T_NATIVE_DOUBLE, 2, r->ci[j]) < 0
             ? -1
             : 0;
    if (ds >= 0) H5Dclose(ds);
  }
  if (g >= 0) H5Gclose(g);
  return rc;
}

/* the fit of the noise-free forces, with the truth and the shares */
static int put_fit(const out_file *f, const hid_t *sc, const ident_plan *p,
                   const ident_fit *r) {
  static const int par[] = {SC_PAR, -1}, pb[] = {SC_PAR, SC_BOUND, -1},
                   pp[] = {SC_PAR, SC_PAR2, -1}, act[] = {SC_ACT, -1};
  const char *units[IDENT_PMAX];
  int64_t rank = (int64_t)r->rank, dof = (int64_t)r->dof;
  size_t j;
  for (j = 0; j < p->p; j++) units[j] = par_unit(p, j);
  return put1(f, sc, "parameter_units", f->str, par, units, "1",
              "units of the parameter", "UDUNITS units of each parameter") ||
                 put1(f, sc, "theta", H5T_NATIVE_DOUBLE, par, r->theta, VARIOUS,
                      "estimate", "the fitted parameters") ||
                 put1(f, sc, "std", H5T_NATIVE_DOUBLE, par, r->std, VARIOUS,
                      "standard deviation",
                      "standard deviation of the estimate, sqrt(diag cov)") ||
                 put1(f, sc, "ci95", H5T_NATIVE_DOUBLE, pb, r->ci, VARIOUS,
                      "confidence interval",
                      "interval of the estimate at identify.level (attribute "
                      "level), theta -+ t(dof) std") ||
                 put1(f, sc, "cov", H5T_NATIVE_DOUBLE, pp, r->cov,
                      "various: products of parameter_units", "covariance",
                      "covariance of the estimate, s2 (Y^T W Y)^-1") ||
                 put1(f, sc, "unidentifiable", H5T_NATIVE_INT32, par,
                      r->unident, "1", "not determined by the data",
                      "1 for a column the data do not determine") ||
                 put1(f, sc, "truth", H5T_NATIVE_DOUBLE, par, p->truth, VARIOUS,
                      "the model's value",
                      "the scene's parameters (rps3_paper_params), whose "
                      "inverse dynamics are the fitted forces") ||
                 put1(f, sc, "share", H5T_NATIVE_DOUBLE, par, p->share, "1",
                      "share of the RMS force",
                      "RMS of Y_k theta_k over the RMS force (truth)") ||
                 put1(f, sc, "sigma", H5T_NATIVE_DOUBLE, act, r->sigma, "N",
                      "noise standard deviation",
                      "each actuator's residual standard deviation") ||
                 put1(f, sc, "force_rms", H5T_NATIVE_DOUBLE, act, p->rms, "N",
                      "RMS force", "each actuator's RMS force (noise-free)") ||
                 put0(f, "condition_number", H5T_NATIVE_DOUBLE, &r->cond, "1",
                      "condition number",
                      "of the weighted regressor with unit-norm columns") ||
                 put0(f, "rank", H5T_NATIVE_INT64, &rank, "1", "numerical rank",
                      "of the regressor (rank_tol 1e-10)") ||
                 put0(f, "dof", H5T_NATIVE_INT64, &dof, "1",
                      "degrees of freedom", "rows minus parameters") ||
                 put0(f, "residual_rms", H5T_NATIVE_DOUBLE, &r->resid_rms, "N",
                      "residual RMS", "RMS of F - Y theta over every row") ||
                 put_alone(f, p, r)
             ? -1
             : 0;
}

/* the general model's layout: its units, the scene's values, and the
   grouping of its parameters into the base ones */
static int put_layout(const out_file *f, const hid_t *sc, const ident_plan *p) {
  static const int lay[] = {SC_STD, -1}, ps[] = {SC_PAR, SC_STD, -1};
  const char *units[IDENT_PMAX];
  size_t j;
  for (j = 0; j < p->nlay; j++) units[j] = rps3_std_unit(p->lay_std[j][0]);
  return put1(f, sc, "standard_parameter_units", f->str, lay, units, "1",
              "units of the layout's parameter",
              "UDUNITS units of each standard parameter of the layout") ||
                 put1(f, sc, "standard_truth", H5T_NATIVE_DOUBLE, lay,
                      p->lay_truth, "various: see standard_parameter_units",
                      "the model's layout parameters",
                      "the scene's standard parameters (rps3_std_params) "
                      "of the layout; identical legs: the legs' mean") ||
                 put1(f, sc, "base_matrix", H5T_NATIVE_DOUBLE, ps, p->K,
                      "various: parameter_units over standard_parameter_units",
                      "grouping of the base parameters",
                      "K: base parameter = K times the layout's standard "
                      "parameters, from the structural base at random "
                      "states (docs/identification.md)")
             ? -1
             : 0;
}

/* the consistent fit */
static int put_consistent(const out_file *f, const hid_t *sc,
                          const ident_plan *p, const ident_fit *r) {
  static const int par[] = {SC_PAR, -1}, lay[] = {SC_STD, -1};
  int32_t ok = r->consistent, st = r->cstatus;
  hid_t eig;
  hsize_t dims[2] = {2, 4};
  int rc;
  dims[0] = p->general ? p->nbody : 2;
  if (put1(f, sc, "consistent_theta", H5T_NATIVE_DOUBLE,
           p->general ? lay : par, r->ctheta,
           p->general ? "various: see standard_parameter_units" : VARIOUS,
           "physically consistent estimate",
           p->general
               ? "rps3_ident_consistent of the layout's parameters: every "
                 "body's pseudo-inertia positive semidefinite, the friction "
                 ">= 0"
               : "rps3_ident_consistent: every pseudo-inertia positive "
                 "semidefinite, M and the friction >= 0") ||
      put0(f, "consistent", H5T_NATIVE_INT32, &ok, "1", "consistency flag",
           "1: the consistent fit's eigenvalues checked >= 0") ||
      put0(f, "consistent_status", H5T_NATIVE_INT32, &st, "1",
           "status of the consistent fit", "rps3_status (0: converged)"))
    return -1;
  eig = out_h5_dataset(f->file, f->str, "consistent_eigenvalues",
                       H5T_NATIVE_DOUBLE, 2, dims, NULL, 0, NULL, "kg m^2",
                       "each body's pseudo-inertia eigenvalues, ascending "
                       "(kg for its mass direction)");
  rc = eig < 0 ||
               out_cf_long_name(eig, f->str, "pseudo-inertia eigenvalue") < 0 ||
               H5Dwrite(eig, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT,
                        r->eig) < 0 ||
               H5DSattach_scale(eig, sc[SC_BODY], 0) < 0 ||
               H5DSattach_scale(eig, sc[SC_EIG], 1) < 0 ||
               out_h5_attr(eig, f->str, "message", r->cmsg) < 0
           ? -1
           : 0;
  if (eig >= 0) H5Dclose(eig);
  return rc;
}

/* a per-draw dataset (chunked by work unit as the others, so that parts
   merge) or, without ax, a scalar of the summary; NaN or `fill` until
   written; 0 or -1 */
static int put_draw(const out_file *f, const hid_t *sc, const char *name,
                    hid_t type, int per_draw, const void *fill,
                    const char *units, const char *long_name, const char *doc) {
  static const int d1[] = {SC_DRAW, -1}, none[] = {-1};
  hsize_t c1[1] = {IDENT_UNIT};
  hid_t ds = put(f, sc, name, type, per_draw ? d1 : none,
                 per_draw ? c1 : NULL, fill, NULL, units, long_name, doc);
  return ds < 0 ? -1 : H5Dclose(ds) < 0 ? -1 : 0;
}

/* the per-draw datasets of the held-out samples (a holdout) and of the
   consistent fit (identify.consistent), and their summary's */
static int put_draws_holdout(const out_file *f, const hid_t *sc,
                             const ident_plan *p) {
  const int32_t unset = OUT_STATUS_NOT_COMPUTED, none = 0;
  const double fnan = (double)NAN;
  int hold = p->nfit < p->n, cons = p->ids.consistent != 0;
  int rc = 0;
  if (hold)
    rc = put_draw(f, sc, "mc_holdout_nrmse", H5T_NATIVE_DOUBLE, 1, &fnan, "1",
                  "held-out force NRMSE of the draw's fit",
                  "RMS of Y theta - F over the RMS of F on the held-out "
                  "samples (identify.monte_carlo.holdout, the last ones; F "
                  "with the draw's noise), theta the draw's fit of the "
                  "others") ||
         put_draw(f, sc, "mc_holdout_nrmse_median", H5T_NATIVE_DOUBLE, 0,
                  &fnan, "1", "median held-out force NRMSE",
                  "median over the draws of mc_holdout_nrmse (NaN in a "
                  "part: computed when merged)");
  if (rc == 0 && cons)
    rc = put_draw(f, sc, "mc_consistent_status", H5T_NATIVE_INT32, 1, &unset,
                  "1", "status of the draw's consistent fit",
                  "rps3_status of the draw's rps3_ident_consistent (0: "
                  "converged); -1: not run (the draw's fit failed); -1000: "
                  "not computed") ||
         put_draw(f, sc, "mc_consistent", H5T_NATIVE_INT32, 1, &none, "1",
                  "consistency flag of the draw",
                  "1: the draw's consistent fit's eigenvalues checked >= 0") ||
         put_draw(f, sc, "mc_consistent_fraction", H5T_NATIVE_DOUBLE, 0, &fnan,
                  "1", "fraction of consistent draws",
                  "fraction of the draws whose consistent fit is physically "
                  "consistent (mc_consistent 1)") ||
         put_draw(f, sc, "mc_converged_fraction", H5T_NATIVE_DOUBLE, 0, &fnan,
                  "1", "fraction of converged draws",
                  "fraction of the draws whose consistent fit converged "
                  "(mc_consistent_status 0)");
  if (rc == 0 && cons && hold)
    rc = put_draw(f, sc, "mc_consistent_holdout_nrmse", H5T_NATIVE_DOUBLE, 1,
                  &fnan, "1", "held-out force NRMSE of the consistent fit",
                  p->general
                      ? "as mc_holdout_nrmse, the prediction Ylay pi of the "
                        "draw's consistent fit of the layout's parameters"
                      : "as mc_holdout_nrmse, the prediction Y theta of the "
                        "draw's consistent fit") ||
         put_draw(f, sc, "mc_consistent_holdout_nrmse_median",
                  H5T_NATIVE_DOUBLE, 0, &fnan, "1",
                  "median held-out force NRMSE of the consistent fit",
                  "median over the draws of mc_consistent_holdout_nrmse") ||
         put_draw(f, sc, "mc_holdout_ratio_median", H5T_NATIVE_DOUBLE, 0, &fnan,
                  "1", "median ratio of the held-out NRMSEs",
                  "median over the draws of mc_consistent_holdout_nrmse / "
                  "mc_holdout_nrmse") ||
         put_draw(f, sc, "mc_holdout_ratio_max", H5T_NATIVE_DOUBLE, 0, &fnan,
                  "1", "largest ratio of the held-out NRMSEs",
                  "maximum over the draws of mc_consistent_holdout_nrmse / "
                  "mc_holdout_nrmse");
  return rc;
}

/* the per-draw datasets, chunked by work unit, and the summary's */
static int put_draws(const out_file *f, const hid_t *sc, const ident_plan *p) {
  static const int d1[] = {SC_DRAW, -1}, dp[] = {SC_DRAW, SC_PAR, -1},
                   dpb[] = {SC_DRAW, SC_PAR, SC_BOUND, -1},
                   da[] = {SC_DRAW, SC_ACT, -1}, par[] = {SC_PAR, -1};
  const int32_t unset = OUT_STATUS_NOT_COMPUTED, none = -1;
  const double fnan = (double)NAN;
  hsize_t c1[1] = {IDENT_UNIT}, cp[2] = {IDENT_UNIT, p->p},
          cpb[3] = {IDENT_UNIT, p->p, 2}, ca[2] = {IDENT_UNIT, 3};
  hid_t ds[9];
  int i, rc = 0;
  ds[0] = put(f, sc, "status", H5T_NATIVE_INT32, d1, c1, &unset, NULL, "1",
              "status of the draw's fit",
              "rps3_status of the draw's fit (0: ok); -1000: not computed");
  ds[1] = put(f, sc, "mc_theta", H5T_NATIVE_DOUBLE, dp, cp, &fnan, NULL,
              VARIOUS, "estimate of the draw", "the draw's fitted parameters");
  ds[2] = put(f, sc, "mc_std", H5T_NATIVE_DOUBLE, dp, cp, &fnan, NULL, VARIOUS,
              "standard deviation of the draw's estimate",
              "sqrt(diag cov) of the draw's fit");
  ds[3] = put(f, sc, "mc_ci", H5T_NATIVE_DOUBLE, dpb, cpb, &fnan, NULL, VARIOUS,
              "confidence interval of the draw",
              "the draw's interval at identify.level");
  ds[4] = put(f, sc, "mc_sigma", H5T_NATIVE_DOUBLE, da, ca, &fnan, NULL, "N",
              "noise standard deviation of the draw",
              "each actuator's residual standard deviation in the draw");
  ds[5] = put(f, sc, "mc_median_rel_error", H5T_NATIVE_DOUBLE, par, NULL, &fnan,
              NULL, "1", "median relative error",
              "median over the draws of abs(estimate - truth) / abs(truth) "
              "(NaN in a part: computed when merged)");
  ds[6] = put(f, sc, "mc_rel_bias", H5T_NATIVE_DOUBLE, par, NULL, &fnan, NULL,
              "1", "relative bias",
              "mean over the draws of (estimate - truth) / abs(truth)");
  ds[7] = put(f, sc, "mc_coverage", H5T_NATIVE_DOUBLE, par, NULL, &fnan, NULL,
              "1", "coverage of the intervals",
              "fraction of the draws whose interval holds the truth");
  ds[8] = put(f, sc, "mc_counted", H5T_NATIVE_INT32, par, NULL, &none, NULL,
              "1", "counted parameter",
              "1: share >= 0.01, the summary is a test of it; -1 not yet "
              "computed");
  for (i = 0; i < 9; i++) {
    if (ds[i] < 0)
      rc = -1;
    else
      H5Dclose(ds[i]);
  }
  return rc ? rc : put_draws_holdout(f, sc, p);
}

out_file *ident_file_open(const char *path, const scene *s, const ident_plan *p,
                          const ident_fit *r, const char *yaml,
                          const char *yaml_why, const out_meta *meta,
                          char *err, size_t errsz) {
  out_spec sp;
  out_file *f;
  hid_t sc[NSC] = {-1, -1, -1, -1, -1, -1, -1, -1};
  int k, rc;
  memset(&sp, 0, sizeof sp);
  sp.files = OUT_IDENT;
  sp.title = p->general ? "rps3: identification of the Lee & Shah 3-RPS "
                          "manipulator's general-model base parameters"
                        : "rps3: identification of the Lee & Shah 3-RPS "
                          "manipulator's paper-model parameters";
  sp.content = "identification";
  sp.grid_common = 1;
  sp.tile_cases = sp.case_chunk = 1;
  if (!(f = out_open(path, s, &sp, meta, err, errsz))) return NULL;
  rc = make_scales(f, p, sc) || put_fit(f, sc, p, r) ||
       (p->general && put_layout(f, sc, p)) ||
       (p->ids.consistent && r->cstatus != -1 && put_consistent(f, sc, p, r)) ||
       (p->ids.runs > 0 && put_draws(f, sc, p)) ||
       out_h5_attr(f->file, f->str, "method",
                   p->ids.method == IDENT_OLS ? "ols" : "wls") < 0 ||
       out_h5_attr_n(f->file, "level", H5T_NATIVE_DOUBLE, 0, &p->ids.level) <
           0 ||
       out_h5_attr_n(f->file, "force_noise", H5T_NATIVE_DOUBLE, 0,
                     &p->ids.force_noise) < 0 ||
       (p->ids.runs > 0 &&
        out_h5_attr_n(f->file, "holdout", H5T_NATIVE_DOUBLE, 0,
                      &p->ids.holdout) < 0) ||
       (p->warning[0] &&
        out_h5_attr(f->file, f->str, "warning", p->warning) < 0) ||
       (p->general &&
        out_h5_attr(f->file, f->str, "model", "general") < 0) ||
       (p->general &&
        out_h5_attr(f->file, f->str, "legs",
                    p->ids.legs == IDENT_LEGS_IDENTICAL ? "identical"
                                                        : "each") < 0) ||
       (yaml && out_h5_attr(f->file, f->str, "manipulator_yaml", yaml) < 0) ||
       (!yaml && yaml_why &&
        out_h5_attr(f->file, f->str, "manipulator_yaml_missing", yaml_why) <
            0);
  for (k = 0; k < NSC; k++)
    if (sc[k] >= 0) H5Dclose(sc[k]);
  if (rc == 0) return f;
  out_fail(err, errsz, "%s: cannot write the identification's datasets", path);
  out_close(f, NULL, 0);
  return NULL;
}
