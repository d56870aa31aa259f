/*
 * ident.c - the regressor of the paper model's parameters: F = Y pi.
 *
 * The forces of rps3_invdyn are linear in the masses, inertias and
 * friction coefficients at a fixed geometry, and so is every effect's load
 * (invdyn.c).  So a column of Y is the load of one unit parameter, pushed
 * through the formulation's own solve: after the point's motion (the
 * stages of rps3_inverse, once) and its checks, each column is an effect's
 * right-hand side computed with a copy of the model whose parameter is 1,
 * and all columns are solved with the one factorization (rps3_loads_*).
 * Nothing here writes an equation of motion.
 */
#include <stdint.h>
#include <string.h>

#include "ident_int.h"
#include "internal.h"

static const char *const paper_names[RPS3_NPAPER] = {
    "M",           "md",          "Ipin",        "payload.m",
    "payload.mcx", "payload.mcy", "payload.mcz", "payload.Ixx",
    "payload.Iyy", "payload.Izz", "pin.fv",      "pin.fc"};
static const char *const paper_units[RPS3_NPAPER] = {
    "kg",   "kg m",   "kg m^2", "kg",     "kg m",      "kg m",
    "kg m", "kg m^2", "kg m^2", "kg m^2", "N m s/rad", "N m"};

const char *rps3_paper_name(int k) {
  return (k >= 0 && k < RPS3_NPAPER) ? paper_names[k] : NULL;
}

const char *rps3_paper_unit(int k) {
  return (k >= 0 && k < RPS3_NPAPER) ? paper_units[k] : NULL;
}

/* 1 when a prismatic joint of m has friction */
static int has_prismatic(const rps3_model *m) {
  int i;
  for (i = 0; i < 3; i++)
    if (m->leg[i].prismatic.viscous != 0.0 ||
        m->leg[i].prismatic.coulomb != 0.0)
      return 1;
  return 0;
}

int rps3_paper_params(const rps3_model *m, double pi[RPS3_NPAPER],
                      rps3_check *chk) {
  char *err = chk != NULL ? chk->msg : NULL;
  size_t errsz = chk != NULL ? sizeof chk->msg : 0;
  const rps3_payload *p;
  double cc;
  int k, off = 0;
  rps3_check_clear(chk);
  if (m == NULL || !m->valid || pi == NULL) {
    if (err && errsz)
      snprintf(err, errsz, "%s",
               pi == NULL ? "pi is NULL" : "model is NULL or not initialised");
    return RPS3_EINVAL;
  }
  if (m->bodies != RPS3_BODIES_PAPER ||
      ((m->opt.effects & RPS3_EFF_PRISMATIC_FRICTION) && has_prismatic(m))) {
    memset(pi, 0, RPS3_NPAPER * sizeof(double));
    if (err && errsz)
      snprintf(err, errsz,
               "%s: outside the paper model's twelve parameters (use "
               "rps3_regressor_std and rps3_std_params)",
               m->bodies != RPS3_BODIES_PAPER ? "general bodies"
                                              : "prismatic friction");
    return RPS3_EINVAL;
  }
  p = &m->payload;
  cc = p->com[0] * p->com[0] + p->com[1] * p->com[1] + p->com[2] * p->com[2];
  pi[0] = m->M;
  pi[1] = m->m * m->d;
  pi[2] = m->Jlink;
  pi[3] = p->mass;
  for (k = 0; k < 3; k++) {
    pi[4 + k] = p->mass * p->com[k];
    /* parallel axes: about the platform centre */
    pi[7 + k] = p->inertia[k] + p->mass * (cc - p->com[k] * p->com[k]);
    off += p->com[k] != 0.0;
  }
  pi[10] = m->friction.viscous;
  pi[11] = m->friction.coulomb;
  if (off > 1 && p->mass != 0.0) {
    if (err && errsz)
      snprintf(err, errsz,
               "payload.com = (%g, %g, %g): off the platform axes, the "
               "payload has products of inertia about the platform centre "
               "that the paper parameters do not hold",
               p->com[0], p->com[1], p->com[2]);
    return RPS3_EINVAL;
  }
  return RPS3_OK;
}

/* the columns solved: the twelve, then the payload's first moments
   pushed the other way (a first moment comes with its second, m c c^T:
   half the difference of +e_k and -e_k is the linear part alone) */
#define NCOL (RPS3_NPAPER + 3)

static void set_payload(rps3_model *u, double mass, int axis, double h,
                        int inertia_axis) {
  memset(&u->payload, 0, sizeof(u->payload));
  u->payload.mass = mass;
  if (axis >= 0) u->payload.com[axis] = h;
  if (inertia_axis >= 0) u->payload.inertia[inertia_axis] = 1.0;
}

/* no force is computed by a regressor: none of another point's is left
   in d */
void rps3_regressor_unset(rps3_data *d) {
  int i, k;
  for (i = 0; i < 3; i++) {
    d->F[i] = d->lambda[i] = (double)NAN;
    for (k = 0; k < RPS3_NEFFECT; k++) d->F_effect[k][i] = (double)NAN;
  }
  d->has_lambda = 0;
  d->power = d->dTdt = d->dPdt = d->friction_power = d->energy_residual =
      d->energy_scale = (double)NAN;
}

int rps3_regressor_finite(rps3_data *d, double *Y, int ncol,
                          const char *(*name)(int)) {
  int bad, k;
  if (rps3_all_finite(Y, 3 * ncol)) return RPS3_OK;
  bad = rps3_first_nonfinite(Y, 3 * ncol);
  for (k = 0; k < 3 * ncol; k++) Y[k] = (double)NAN;
  RPS3_ERROR(d, RPS3_ERANGE,
             "regressor column %s (row %d) is not finite: finite inputs "
             "overflowed (a length or rate too large)",
             name(bad % ncol), bad / ncol);
}

int rps3_regressor(const rps3_model *m, rps3_data *d,
                   double Y[3][RPS3_NPAPER]) {
  rps3_cjac J;  /* the point's constraint Jacobian */
  rps3_loads L; /* its kinematics and factored system */
  rps3_model u; /* m with unit parameters, one column at a time */
  double rhs[RPS3_LOADS_MAXCOL][6];
  int status, i, k;
  if (Y != NULL)
    for (i = 0; i < 3; i++)
      for (k = 0; k < RPS3_NPAPER; k++) Y[i][k] = (double)NAN;
  if (m == NULL || d == NULL || !m->valid) return RPS3_EINVAL;
  if (Y == NULL) RPS3_ERROR(d, RPS3_EINVAL, "regressor: Y is NULL");

  /* the point's motion and checks, as rps3_inverse has them */
  status = rps3_inverse_motion(m, d, &J, rps3_need_rates(m));
  if (status != RPS3_OK) return status;
  status = rps3_loads_prepare(m, d, &J, &L);
  if (status != RPS3_OK) return status;
  rps3_regressor_unset(d);

  /* each column: one effect's load with its parameter 1 and the model's
     geometry; the disc's principal moments per unit mass (21) */
  u = *m;
  u.bodies = RPS3_BODIES_PAPER; /* the paper model's parameters */
  u.M = 1.0;
  u.Ip[0] = u.Ip[1] = 0.25 * m->r * m->r;
  u.Ip[2] = 0.5 * m->r * m->r;
  u.m = 1.0;
  u.d = 1.0; /* link gravity m g d: unit m d */
  u.Jlink = 1.0;
  rps3_loads_column(m, &u, d, &L,
                    RPS3_EFF_PLATFORM_GRAVITY | RPS3_EFF_PLATFORM_INERTIA,
                    rhs[0]);
  rps3_loads_column(m, &u, d, &L, RPS3_EFF_LINK_GRAVITY, rhs[1]);
  rps3_loads_column(m, &u, d, &L, RPS3_EFF_LINK_INERTIA, rhs[2]);
  set_payload(&u, 1.0, -1, 0.0, -1);
  rps3_loads_column(m, &u, d, &L, RPS3_EFF_PAYLOAD, rhs[3]);
  for (k = 0; k < 3; k++) {
    double minus[6];
    int r;
    set_payload(&u, 1.0, k, 1.0, -1);
    rps3_loads_column(m, &u, d, &L, RPS3_EFF_PAYLOAD, rhs[4 + k]);
    set_payload(&u, 1.0, k, -1.0, -1);
    rps3_loads_column(m, &u, d, &L, RPS3_EFF_PAYLOAD, minus);
    for (r = 0; r < 6; r++) rhs[4 + k][r] = 0.5 * (rhs[4 + k][r] - minus[r]);
    /* inertia about the centre: a massless payload's principal moment */
    set_payload(&u, 0.0, -1, 0.0, k);
    rps3_loads_column(m, &u, d, &L, RPS3_EFF_PAYLOAD, rhs[7 + k]);
  }
  for (i = 0; i < 3; i++) {
    u.pinf[i] = m->friction;
    u.pinf[i].viscous = 1.0;
    u.pinf[i].coulomb = 0.0;
  }
  rps3_loads_column(m, &u, d, &L, RPS3_EFF_PIN_FRICTION, rhs[10]);
  for (i = 0; i < 3; i++) {
    u.pinf[i].viscous = 0.0;
    u.pinf[i].coulomb = 1.0;
  }
  rps3_loads_column(m, &u, d, &L, RPS3_EFF_PIN_FRICTION, rhs[11]);

  /* one factorization, every column */
  rps3_loads_solve(&L, RPS3_NPAPER, rhs, &Y[0][0], RPS3_NPAPER);
  return rps3_regressor_finite(d, &Y[0][0], RPS3_NPAPER, rps3_paper_name);
}

/* component c of point i in a component-major array of n points */
#define AT(a, c, i, n) ((a)[(size_t)(c) * (n) + (i)])

/* a regressor of ncol columns at one point, into Y (3 x ncol, row
   major) */
typedef int (*regressor_fn)(const rps3_model *m, rps3_data *d, double *Y);

static int paper_point(const rps3_model *m, rps3_data *d, double *Y) {
  return rps3_regressor(m, d, (double(*)[RPS3_NPAPER])Y);
}

static int std_point(const rps3_model *m, rps3_data *d, double *Y) {
  return rps3_regressor_std(m, d, (double(*)[RPS3_NSTD])Y);
}

/* the batch of either regressor: point's columns over in's points */
static int regressor_batch(const rps3_model *m, rps3_data *d,
                           const rps3_batch_in *in, double *Y,
                           rps3_batch_out *out, int ncol, regressor_fn point,
                           double *Yp) {
  rps3_error first;
  size_t i, n;
  int c, k, rates;
  if (d == NULL) return RPS3_EINVAL;
  if (m == NULL || !m->valid)
    RPS3_ERROR(d, RPS3_EINVAL, "model is NULL or not initialised");
  if (in == NULL || out == NULL)
    RPS3_ERROR(d, RPS3_EINVAL, "batch %s is NULL", in == NULL ? "in" : "out");
  n = in->n;
  if (n > SIZE_MAX / (size_t)(3 * ncol))
    RPS3_ERROR(d, RPS3_EINVAL, "batch n = %lu is too large", (unsigned long)n);
  rates = rps3_need_rates(m);
  if (n > 0 && (Y == NULL || out->status == NULL || in->pose == NULL))
    RPS3_ERROR(d, RPS3_EINVAL, "batch %s is NULL",
               Y == NULL             ? "Y"
               : out->status == NULL ? "out.status"
                                     : "in.pose");
  if (n > 0 && rates && (in->dpose == NULL || in->ddpose == NULL))
    RPS3_ERROR(d, RPS3_EINVAL,
               "batch in.%s is NULL, and the selected effects need rates and "
               "accelerations",
               in->dpose == NULL ? "dpose" : "ddpose");
  memset(&first, 0, sizeof(first));
  out->nfail = 0;
  out->first_fail = n;
  for (i = 0; i < n; i++) {
    int status;
    for (c = 0; c < 3; c++) {
      d->pose[c] = AT(in->pose, c, i, n);
      d->dpose[c] = rates ? AT(in->dpose, c, i, n) : 0.0;
      d->ddpose[c] = rates ? AT(in->ddpose, c, i, n) : 0.0;
    }
    status = point(m, d, Yp);
    out->status[i] = status;
    if (out->warn) out->warn[i] = d->warn;
    for (c = 0; c < 3; c++)
      for (k = 0; k < ncol; k++) AT(Y, c * ncol + k, i, n) = Yp[c * ncol + k];
    for (c = 0; c < 3; c++) {
      int ok = status == RPS3_OK;
      if (out->l) AT(out->l, c, i, n) = ok ? d->l[c] : (double)NAN;
      if (out->theta) AT(out->theta, c, i, n) = ok ? d->theta[c] : (double)NAN;
      if (out->c) AT(out->c, c, i, n) = ok ? d->c[c] : (double)NAN;
      if (out->dl) AT(out->dl, c, i, n) = ok && rates ? d->dl[c] : (double)NAN;
      if (out->ddl)
        AT(out->ddl, c, i, n) = ok && rates ? d->ddl[c] : (double)NAN;
    }
    if (out->cond) out->cond[i] = status == RPS3_OK ? d->cond : (double)NAN;
    if (out->transmission)
      out->transmission[i] = status == RPS3_OK ? d->transmission : (double)NAN;
    if (status != RPS3_OK && out->nfail++ == 0) {
      out->first_fail = i;
      rps3_batch_name_point(d, status, i);
      first = d->err;
    }
  }
  if (out->nfail > 0) d->err = first;
  return RPS3_OK;
}

int rps3_regressor_batch(const rps3_model *m, rps3_data *d,
                         const rps3_batch_in *in, double *Y,
                         rps3_batch_out *out) {
  double Yp[3 * RPS3_NPAPER];
  return regressor_batch(m, d, in, Y, out, RPS3_NPAPER, paper_point, Yp);
}

int rps3_regressor_std_batch(const rps3_model *m, rps3_data *d,
                             const rps3_batch_in *in, double *Y,
                             rps3_batch_out *out) {
  double Yp[3 * RPS3_NSTD];
  return regressor_batch(m, d, in, Y, out, RPS3_NSTD, std_point, Yp);
}
