/*
 * ident_mc.c - the Monte Carlo of an identification (ident_run.h): the
 * draws on the worker pool, a work unit of IDENT_UNIT draws at a time,
 * and the summary of the draws read back from the file (so that a whole
 * run and merged parts summarise alike).
 */
#include "ident_run.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

/* the per-draw datasets, in the order of a slot's arrays */
static const char *const draw_sets[] = {"status",
                                        "mc_theta",
                                        "mc_std",
                                        "mc_ci",
                                        "mc_sigma",
                                        "mc_holdout_nrmse",
                                        "mc_consistent_status",
                                        "mc_consistent",
                                        "mc_consistent_holdout_nrmse"};
#define NDRAW_SET 9

/* 1 when the plan's file has per-draw dataset k of draw_sets: the
   held-out ones with a holdout, the consistent ones with
   identify.consistent */
static int draw_set_wanted(const ident_plan *p, int k) {
  int hold = p->nfit < p->n, cons = p->ids.consistent != 0;
  return k < 5 || (k == 5 && hold) || ((k == 6 || k == 7) && cons) ||
         (k == 8 && hold && cons);
}

/* one work unit's results */
typedef struct {
  int32_t status[IDENT_UNIT];
  double theta[IDENT_UNIT][IDENT_PMAX], std[IDENT_UNIT][IDENT_PMAX];
  double ci[IDENT_UNIT][IDENT_PMAX][2], sigma[IDENT_UNIT][3];
  double nrmse[IDENT_UNIT], cnrmse[IDENT_UNIT];
  int32_t cstatus[IDENT_UNIT], consistent[IDENT_UNIT];
} unit_slot;

/* which draws a filled slot holds */
typedef struct {
  size_t d0, nd;
} unit_info;

typedef struct {
  const ident_plan *p;
  hid_t ds[NDRAW_SET];
  progress *pr;
  sweep_stats *st;
} mc_job;

/* a worker's noisy forces and generator */
typedef struct {
  double *F;
  gsl_rng *rng;
} mc_worker;

static void worker_end(void *ctx, void *wctx) {
  mc_worker *w = wctx;
  (void)ctx;
  if (!w) return;
  free(w->F);
  if (w->rng) gsl_rng_free(w->rng);
  free(w);
}

static void *worker_begin(void *ctx) {
  const ident_plan *p = ((const mc_job *)ctx)->p;
  mc_worker *w = calloc(1, sizeof *w);
  if (w && (!(w->F = malloc(p->n * sizeof *w->F)) ||
            !(w->rng = gsl_rng_alloc(gsl_rng_mt19937)))) {
    worker_end(ctx, w);
    w = NULL;
  }
  return w;
}

/* the seed of draw i: SplitMix64 of (seed, i), so that a draw's noise
   does not depend on which thread or shard computes it */
static unsigned long draw_seed(int seed, size_t i) {
  uint64_t z = ((uint64_t)(uint32_t)seed << 32) ^ (uint64_t)i;
  z += 0x9E3779B97F4A7C15u;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9u;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBu;
  z ^= z >> 31;
  return (unsigned long)(z & 0xFFFFFFFFu);
}

/* draw i: the noise-free forces plus force_noise times each actuator's RMS
   force of Gaussian noise, its first nfit rows fitted (and the consistent
   fit with identify.consistent), the rest predicted, into slot row j */
static void one_draw(const ident_plan *p, mc_worker *w, size_t i, unit_slot *u,
                     size_t j) {
  ident_fit r;
  size_t k;
  gsl_rng_set(w->rng, draw_seed(p->ids.seed, i));
  for (k = 0; k < p->n; k++)
    w->F[k] = p->F0[k] + gsl_ran_gaussian_ziggurat(
                             w->rng, p->ids.force_noise * p->rms[k % 3]);
  ident_fit_rows(p, w->F, p->nfit, p->ids.consistent, &r);
  ident_holdout_nrmse(p, w->F, &r, &u->nrmse[j], &u->cnrmse[j]);
  u->cstatus[j] = r.cstatus;
  u->consistent[j] = r.consistent;
  u->status[j] = r.status;
  memcpy(u->theta[j], r.theta, sizeof u->theta[j]);
  memcpy(u->std[j], r.std, sizeof u->std[j]);
  memcpy(u->ci[j], r.ci, sizeof u->ci[j]);
  memcpy(u->sigma[j], r.sigma, sizeof u->sigma[j]);
  ident_fit_free(&r);
}

/* pool_job.slot_make, slot_free: a slot is plain data */
static int slot_make(void *ctx, void *slot, size_t i) {
  (void)ctx;
  (void)slot;
  (void)i;
  return 0;
}

static void slot_free(void *ctx, void *slot, size_t i) {
  (void)ctx;
  (void)slot;
  (void)i;
}

/* pool_job.run: work unit i */
static int unit_run(void *ctx, void *wctx, size_t i, pool_worker *pw, char *err,
                    size_t errsz) {
  const ident_plan *p = ((const mc_job *)ctx)->p;
  unit_slot *u = pool_slot(pw);
  unit_info info;
  size_t j, runs = (size_t)p->ids.runs;
  info.d0 = i * IDENT_UNIT;
  info.nd = runs - info.d0 < IDENT_UNIT ? runs - info.d0 : IDENT_UNIT;
  for (j = 0; j < info.nd; j++) one_draw(p, wctx, info.d0 + j, u, j);
  return pool_emit(pw, &info, err, errsz) ? 0 : -1;
}

/* rows [d0, d0 + nd) of dataset ds from buf, whose rows are `row` values
   of which the file holds the first `used` */
static int write_rows(hid_t ds, hid_t type, const void *buf, size_t d0,
                      size_t nd, size_t row, size_t used) {
  hid_t fs = H5Dget_space(ds), ms = -1;
  hsize_t fdims[3], fstart[3] = {d0, 0, 0}, count[3], mdims[3],
                    mstart[3] = {0, 0, 0};
  int r, rank = fs < 0 ? -1 : H5Sget_simple_extent_dims(fs, fdims, NULL), rc;
  for (r = 0; r < rank; r++) count[r] = mdims[r] = fdims[r];
  count[0] = mdims[0] = nd;
  /* the slot's rows are wider than the file's (IDENT_PMAX columns) */
  if (rank > 1 && used < row) mdims[1] = fdims[1] * row / used;
  ms = rank > 0 ? H5Screate_simple(rank, mdims, NULL) : -1;
  rc = ms >= 0 &&
               H5Sselect_hyperslab(ms, H5S_SELECT_SET, mstart, NULL, count,
                                   NULL) >= 0 &&
               H5Sselect_hyperslab(fs, H5S_SELECT_SET, fstart, NULL, count,
                                   NULL) >= 0 &&
               H5Dwrite(ds, type, ms, fs, H5P_DEFAULT, buf) >= 0
           ? 0
           : -1;
  if (fs >= 0) H5Sclose(fs);
  if (ms >= 0) H5Sclose(ms);
  return rc;
}

/* pool_job.write: a unit's rows of every per-draw dataset */
static int unit_write(void *ctx, void *slot, const void *info, char *err,
                      size_t errsz) {
  mc_job *m = ctx;
  const unit_slot *u = slot;
  const unit_info *in = info;
  size_t p = m->p->p, j;
  int rc =
      write_rows(m->ds[0], H5T_NATIVE_INT32, u->status, in->d0, in->nd, 1, 1) ||
      write_rows(m->ds[1], H5T_NATIVE_DOUBLE, u->theta, in->d0, in->nd,
                 IDENT_PMAX, p) ||
      write_rows(m->ds[2], H5T_NATIVE_DOUBLE, u->std, in->d0, in->nd,
                 IDENT_PMAX, p) ||
      write_rows(m->ds[3], H5T_NATIVE_DOUBLE, u->ci, in->d0, in->nd,
                 IDENT_PMAX, p) ||
      write_rows(m->ds[4], H5T_NATIVE_DOUBLE, u->sigma, in->d0, in->nd, 3,
                 3) ||
      (m->ds[5] >= 0 && write_rows(m->ds[5], H5T_NATIVE_DOUBLE, u->nrmse,
                                   in->d0, in->nd, 1, 1)) ||
      (m->ds[6] >= 0 && write_rows(m->ds[6], H5T_NATIVE_INT32, u->cstatus,
                                   in->d0, in->nd, 1, 1)) ||
      (m->ds[7] >= 0 && write_rows(m->ds[7], H5T_NATIVE_INT32, u->consistent,
                                   in->d0, in->nd, 1, 1)) ||
      (m->ds[8] >= 0 && write_rows(m->ds[8], H5T_NATIVE_DOUBLE, u->cnrmse,
                                   in->d0, in->nd, 1, 1));
  if (rc) {
    out_fail(err, errsz, "cannot write draws %zu to %zu", in->d0,
             in->d0 + in->nd - 1);
    return -1;
  }
  for (j = 0; j < in->nd; j++)
    if (u->status[j] != 0) {
      char what[64];
      snprintf(what, sizeof what, "draw %zu", in->d0 + j);
      progress_failure(m->pr, in->d0 + j, what, rps3_strerror(u->status[j]));
      m->st->nfailed++;
    }
  m->st->cases_done += in->nd;
  m->st->points_done += in->nd * m->p->ns;
  progress_update(m->pr, m->st->cases_done, m->st->points_done);
  return 0;
}

int ident_mc_run(const ident_plan *p, out_file *f, size_t shard, size_t nshard,
                 int nthread, progress *pr, sweep_stats *st, char *err,
                 size_t errsz) {
  mc_job m;
  pool_job job;
  int i, rc;
  memset(&m, 0, sizeof m);
  m.p = p;
  m.pr = pr;
  m.st = st;
  for (i = 0; i < NDRAW_SET; i++) m.ds[i] = -1;
  for (i = 0, rc = 0; i < NDRAW_SET && rc == 0; i++)
    if (draw_set_wanted(p, i) &&
        (m.ds[i] = H5Dopen2(f->file, draw_sets[i], H5P_DEFAULT)) < 0) {
      out_fail(err, errsz, "cannot open dataset %s", draw_sets[i]);
      rc = -1;
    }
  memset(&job, 0, sizeof job);
  job.ctx = &m;
  job.nitem = p->nunit;
  job.first = shard;
  job.stride = nshard;
  job.slot_size = sizeof(unit_slot);
  job.slot_make = slot_make;
  job.slot_free = slot_free;
  job.info_size = sizeof(unit_info);
  job.worker_begin = worker_begin;
  job.worker_end = worker_end;
  job.run = unit_run;
  job.write = unit_write;
  if (rc == 0) rc = pool_run(&job, nthread, err, errsz);
  for (i = 0; i < NDRAW_SET; i++)
    if (m.ds[i] >= 0) H5Dclose(m.ds[i]);
  return rc;
}

/* ------------------------------------------------------------ summary */

/* the whole of dataset name of file into a malloc'd buffer of type (n
   values, *n set when not NULL); NULL when absent or unreadable */
static void *read_all(hid_t file, const char *name, hid_t type, size_t *n) {
  hid_t ds = H5Dopen2(file, name, H5P_DEFAULT), sp = -1;
  hssize_t m;
  void *buf = NULL;
  if (ds < 0) return NULL;
  sp = H5Dget_space(ds);
  m = sp < 0 ? -1 : H5Sget_simple_extent_npoints(sp);
  if (m > 0 && (buf = malloc((size_t)m * H5Tget_size(type))) != NULL &&
      H5Dread(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf) < 0) {
    free(buf);
    buf = NULL;
  }
  if (n) *n = m > 0 ? (size_t)m : 0;
  if (sp >= 0) H5Sclose(sp);
  H5Dclose(ds);
  return buf;
}

/* write the whole of an existing dataset; 0 or -1 */
static int write_all(hid_t file, const char *name, hid_t type, const void *v) {
  hid_t ds = H5Dopen2(file, name, H5P_DEFAULT);
  int rc = ds >= 0 && H5Dwrite(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, v) >= 0
               ? 0
               : -1;
  if (ds >= 0) H5Dclose(ds);
  return rc;
}

static int by_value(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return x < y ? -1 : x > y;
}

/* the summary of parameter j over the nd draws: median relative error,
   relative bias, coverage */
typedef struct {
  double median, bias, coverage;
} par_summary;

static par_summary summarise(const int32_t *status, const double *theta,
                             const double *ci, size_t runs, size_t p, size_t j,
                             double truth, double *work) {
  par_summary s = {(double)NAN, (double)NAN, (double)NAN};
  size_t i, nd = 0, in = 0;
  double sum = 0;
  for (i = 0; i < runs; i++) {
    double e;
    if (status[i] != 0) continue;
    e = (theta[i * p + j] - truth) / fabs(truth);
    work[nd++] = fabs(e);
    sum += e;
    in += ci[(i * p + j) * 2] <= truth && truth <= ci[(i * p + j) * 2 + 1];
  }
  if (nd == 0) return s;
  qsort(work, nd, sizeof *work, by_value);
  s.median = nd % 2 ? work[nd / 2] : 0.5 * (work[nd / 2 - 1] + work[nd / 2]);
  s.bias = sum / (double)nd;
  s.coverage = (double)in / (double)nd;
  return s;
}

/* the table of the summary on out */
static void summary_print(FILE *out, char **names, const double *share,
                          const double *med, const double *bias,
                          const double *cov, const int32_t *counted, size_t p,
                          size_t nok, size_t runs) {
  size_t j;
  int w = 12; /* the paper's names; the general model's are longer */
  for (j = 0; j < p; j++)
    if ((int)strlen(names[j]) > w) w = (int)strlen(names[j]);
  fprintf(out,
          "identification Monte Carlo: %zu of %zu draws fitted\n"
          "%-*s %9s %12s %11s %9s  %s\n",
          nok, runs, w, "parameter", "share", "median |err|", "bias",
          "coverage", "counted");
  for (j = 0; j < p; j++)
    if (isnan(med[j])) /* zero in truth: no relative error */
      fprintf(out, "%-*s %8.3f%% %12s %11s %8.1f%%  %s\n", w, names[j],
              100 * share[j], "-", "-", 100 * cov[j], "no (truth 0)");
    else
      fprintf(out, "%-*s %8.3f%% %11.4f%% %+10.4f%% %8.1f%%  %s\n", w,
              names[j], 100 * share[j], 100 * med[j], 100 * bias[j],
              100 * cov[j], counted[j] ? "yes" : "no (share < 1 %)");
}

/* the median of the n values v (sorted in place); NaN for none */
static double median_of(double *v, size_t n) {
  if (n == 0) return (double)NAN;
  qsort(v, n, sizeof *v, by_value);
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* the summary of the held-out prediction and of the draws' consistent
   fits, over the runs draws (datasets the file does not have: not
   summarised): the fractions of draws whose consistent fit is consistent
   and converged, the median held-out NRMSE of each fit, and the median
   and maximum of their ratio over the draws where both are finite;
   written to the mc_* scalars and printed on out; 0 or -1 */
static int summary_holdout(hid_t file, FILE *out, size_t runs) {
  int32_t *cst = read_all(file, "mc_consistent_status", H5T_NATIVE_INT32, NULL);
  int32_t *cok = read_all(file, "mc_consistent", H5T_NATIVE_INT32, NULL);
  double *nw = read_all(file, "mc_holdout_nrmse", H5T_NATIVE_DOUBLE, NULL);
  double *nc =
      read_all(file, "mc_consistent_holdout_nrmse", H5T_NATIVE_DOUBLE, NULL);
  double *work = malloc((runs ? runs : 1) * sizeof *work);
  double fcons = (double)NAN, fconv = (double)NAN, medw = (double)NAN,
         medc = (double)NAN, rmed = (double)NAN, rmax = (double)NAN;
  size_t i, n, nconsistent = 0, nconverged = 0, nratio = 0;
  int rc = work ? 0 : -1;
  if (rc == 0 && cst && cok) {
    for (i = 0; i < runs; i++) {
      nconsistent += cok[i] == 1;
      nconverged += cst[i] == 0;
    }
    fcons = (double)nconsistent / (double)runs;
    fconv = (double)nconverged / (double)runs;
    rc = write_all(file, "mc_consistent_fraction", H5T_NATIVE_DOUBLE,
                   &fcons) ||
         write_all(file, "mc_converged_fraction", H5T_NATIVE_DOUBLE, &fconv);
  }
  if (rc == 0 && nw) {
    for (i = n = 0; i < runs; i++)
      if (isfinite(nw[i])) work[n++] = nw[i];
    medw = median_of(work, n);
    rc = write_all(file, "mc_holdout_nrmse_median", H5T_NATIVE_DOUBLE, &medw);
  }
  if (rc == 0 && nw && nc) {
    for (i = n = 0; i < runs; i++)
      if (isfinite(nc[i])) work[n++] = nc[i];
    medc = median_of(work, n);
    for (i = 0; i < runs; i++)
      if (isfinite(nc[i]) && isfinite(nw[i]) && nw[i] > 0) {
        work[nratio] = nc[i] / nw[i];
        rmax = nratio == 0 || work[nratio] > rmax ? work[nratio] : rmax;
        nratio++;
      }
    rmed = median_of(work, nratio);
    rc = write_all(file, "mc_consistent_holdout_nrmse_median",
                   H5T_NATIVE_DOUBLE, &medc) ||
         write_all(file, "mc_holdout_ratio_median", H5T_NATIVE_DOUBLE,
                   &rmed) ||
         write_all(file, "mc_holdout_ratio_max", H5T_NATIVE_DOUBLE, &rmax);
  }
  if (rc == 0 && out && cst && cok)
    fprintf(out,
            "consistent fit: %zu of %zu draws (%.1f %%) physically "
            "consistent, %zu (%.1f %%) converged\n",
            nconsistent, runs, 100 * fcons, nconverged, 100 * fconv);
  if (rc == 0 && out && nw)
    fprintf(out, "held-out force NRMSE, median: WLS %.4f %%\n", 100 * medw);
  if (rc == 0 && out && nw && nc)
    fprintf(out,
            "held-out force NRMSE, median: consistent %.4f %%; consistent / "
            "WLS over %zu draws: median %.5f, max %.5f\n",
            100 * medc, nratio, rmed, rmax);
  free(cst);
  free(cok);
  free(nw);
  free(nc);
  free(work);
  return rc;
}

int ident_summary(hid_t file, FILE *out, char *err, size_t errsz) {
  char *content = out_h5_read_text(file, "content", 1);
  size_t runs = 0, p = 0, j, nok = 0, i;
  int32_t *status = NULL, counted[IDENT_PMAX];
  double *theta = NULL, *ci = NULL, *truth = NULL, *share = NULL, *work = NULL;
  double med[IDENT_PMAX], bias[IDENT_PMAX], cov[IDENT_PMAX];
  char **names = NULL;
  hid_t str = H5Tcopy(H5T_C_S1);
  int rc = -1, is = content && strcmp(content, "identification") == 0;
  free(content);
  if (!is || H5Lexists(file, "status", H5P_DEFAULT) <= 0) {
    H5Tclose(str);
    return 0;
  }
  H5Tset_size(str, H5T_VARIABLE);
  status = read_all(file, "status", H5T_NATIVE_INT32, &runs);
  names = read_all(file, "parameter", str, &p);
  theta = read_all(file, "mc_theta", H5T_NATIVE_DOUBLE, NULL);
  ci = read_all(file, "mc_ci", H5T_NATIVE_DOUBLE, NULL);
  truth = read_all(file, "truth", H5T_NATIVE_DOUBLE, NULL);
  share = read_all(file, "share", H5T_NATIVE_DOUBLE, NULL);
  work = malloc((runs ? runs : 1) * sizeof *work);
  if (!status || !names || !theta || !ci || !truth || !share || !work ||
      p > IDENT_PMAX) {
    out_fail(err, errsz, "cannot read the draws");
    goto done;
  }
  for (i = 0; i < runs; i++) nok += status[i] == 0;
  for (j = 0; j < p; j++) {
    par_summary s = summarise(status, theta, ci, runs, p, j, truth[j], work);
    med[j] = share[j] >= IDENT_SHARE_ZERO ? s.median : (double)NAN;
    bias[j] = share[j] >= IDENT_SHARE_ZERO ? s.bias : (double)NAN;
    cov[j] = s.coverage;
    counted[j] = share[j] >= IDENT_SHARE_MIN;
  }
  if (write_all(file, "mc_median_rel_error", H5T_NATIVE_DOUBLE, med) ||
      write_all(file, "mc_rel_bias", H5T_NATIVE_DOUBLE, bias) ||
      write_all(file, "mc_coverage", H5T_NATIVE_DOUBLE, cov) ||
      write_all(file, "mc_counted", H5T_NATIVE_INT32, counted)) {
    out_fail(err, errsz, "cannot write the summary of the draws");
    goto done;
  }
  if (out)
    summary_print(out, names, share, med, bias, cov, counted, p, nok, runs);
  if (summary_holdout(file, out, runs)) {
    out_fail(err, errsz, "cannot write the summary of the held-out samples");
    goto done;
  }
  rc = 0;
done:
  for (j = 0; names && j < p; j++) H5free_memory(names[j]);
  free(names);
  free(status);
  free(theta);
  free(ci);
  free(truth);
  free(share);
  free(work);
  H5Tclose(str);
  return rc;
}

int ident_summary_path(const char *path, FILE *out, char *err, size_t errsz) {
  hid_t f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
  char *content = f < 0 ? NULL : out_h5_read_text(f, "content", 1);
  int rc, is = content && strcmp(content, "identification") == 0;
  free(content);
  /* another kind of file is left as it is, not even opened to write */
  if (f >= 0) H5Fclose(f);
  if (f >= 0 && !is) return 0;
  f = f < 0 ? -1 : H5Fopen(path, H5F_ACC_RDWR, H5P_DEFAULT);
  if (f < 0) {
    out_fail(err, errsz, "%s: cannot open", path);
    return -1;
  }
  rc = ident_summary(f, out, err, errsz);
  return H5Fclose(f) < 0 ? -1 : rc;
}
