/*
 * test_batch_kernel.c - the vectorised kernel of rps3_inverse_batch
 * (src/batch_kernel.c) against the scalar path it stands in for:
 *   - its sine, cosine and atan2 against libm, in ulp;
 *   - its force transmission (virtual power) against the 6 x 6 system of
 *     rps3_invdyn, and its condition number against the LU one;
 *   - every output of rps3_inverse_batch against rps3_inverse point by
 *     point, over random smooth trajectories and the paper's helix, for
 *     the configurations it serves, with the documented tolerances; the
 *     status and warning of every point equal, also with the warning
 *     thresholds lowered so that points fall on both sides of them.
 */
#include <float.h>
#include <stdlib.h>

#include "testutil.h"
#include "batch_kernel.h"

/* the former controller's path: F, lambda and the transmission */
#define OUT_ONLY (RPS3_OUT_FORCES | RPS3_OUT_LAMBDA | RPS3_OUT_TRANSMISSION)
#define N 2000
#define EPS DBL_EPSILON

/* the distance of got from want in units of the last place of want */
static double ulps(double got, double want) {
  double u = nextafter(fabs(want), HUGE_VAL) - fabs(want);
  return fabs(got - want) / u;
}

/* sin and cos within 3 ulp of libm's (which is within 1 ulp of the exact
   value; 2 measured): the Taylor series are truncated below 1e-19, so what
   is left is the rounding of the reduction and of the Horner sums */
static void sincos_within_3_ulp(void **state) {
  uint64_t seed = 0x51c05;
  double worst = 0.0, worst_e = 0.0;
  int i, fu;
  (void)state;
  for (i = 0; i < 400000; i++) {
    double hi = i < 200000 ? 3.3 : i < 300000 ? 120.0 : RPS3_KANGLE_MAX;
    double x = rnd_uniform(&seed, -hi, hi), s, c;
    /* also the points next to the quadrant boundaries */
    if (i % 10 == 0) x = (double)(i % 7 - 3) * (0.5 * PI) + x * 1e-9;
    rps3_ksincos(x, &s, &c);
    if (ulps(s, sin(x)) > worst) worst = ulps(s, sin(x));
    if (ulps(c, cos(x)) > worst) worst = ulps(c, cos(x));
    if (!(ulps(s, sin(x)) <= 3.0 && ulps(c, cos(x)) <= 3.0))
      fail_msg("x = %.17g: sin %.17g (libm %.17g), cos %.17g (libm %.17g)", x,
               s, sin(x), c, cos(x));
    /* the lean pass's: the same series by Estrin's scheme, with and
       without fused multiply-adds */
    for (fu = 0; fu < 2; fu++) {
      rps3_ksincos_e(x, fu, &s, &c);
      if (ulps(s, sin(x)) > worst_e) worst_e = ulps(s, sin(x));
      if (ulps(c, cos(x)) > worst_e) worst_e = ulps(c, cos(x));
      if (!(ulps(s, sin(x)) <= 3.0 && ulps(c, cos(x)) <= 3.0))
        fail_msg("x = %.17g (fused %d): Estrin sin %.17g (libm %.17g), cos "
                 "%.17g (libm %.17g)", x, fu, s, sin(x), c, cos(x));
    }
  }
  print_message("sincos: largest difference to libm %.2f ulp (Estrin's "
                "%.2f)\n", worst, worst_e);
  {
    double s, c;
    rps3_ksincos((double)NAN, &s, &c);
    assert_true(isnan(s) && isnan(c));
    rps3_ksincos_e((double)NAN, 0, &s, &c);
    assert_true(isnan(s) && isnan(c));
    rps3_ksincos_e((double)NAN, 1, &s, &c);
    assert_true(isnan(s) && isnan(c));
  }
}

/* atan2(y, x), y > 0, within 4 ulp of libm's (2 measured): the reduction
   to |u| <= 1/8 (one division), the series, and the octant's pi/2 or pi
   added */
static void atan2_within_4_ulp(void **state) {
  uint64_t seed = 0xa7a2;
  double worst = 0.0;
  int i;
  (void)state;
  for (i = 0; i < 400000; i++) {
    double y = rnd_uniform(&seed, 1e-6, 1.0), x = rnd_uniform(&seed, -1, 1);
    double got, want;
    if (i % 4 == 0) x *= 1e-3;         /* near pi/2 */
    if (i % 4 == 1) y *= 1e-3;         /* near 0 and pi */
    if (i % 8 == 2) x = y * (double)(i % 5 - 2) * 0.25; /* on the quarters */
    got = rps3_katan2(y, x);
    want = atan2(y, x);
    if (ulps(got, want) > worst) worst = ulps(got, want);
    if (!(ulps(got, want) <= 4.0))
      fail_msg("atan2(%.17g, %.17g) = %.17g, libm %.17g", y, x, got, want);
  }
  print_message("atan2: largest difference to libm %.2f ulp\n", worst);
}

/* the points of a batch, component-major */
typedef struct {
  double pose[3 * N], dpose[3 * N], ddpose[3 * N];
  int status[N], warn[N], niter[N];
  double l[3 * N], theta[3 * N], F[3 * N];
  double F_effect[RPS3_NEFFECT * 3 * N], lambda[3 * N], cond[N], eres[N];
  double trans[N], dl[3 * N], ddl[3 * N], cpos[3 * N], escale[N], sres[N];
} arrays;

#define AT(a, c, i) ((a)[(size_t)(c) * N + (size_t)(i)])

/* random smooth trajectories, or the paper's helix (seed 0) */
static void make_points(const rps3_model *m, arrays *a, uint64_t seed) {
  rps3_traj tr;
  double p[3], dp[3], ddp[3];
  int i, c;
  if (seed == 0)
    rps3_traj_default(&tr);
  else
    traj_random(&tr, &seed);
  for (i = 0; i < N; i++) {
    double t = rps3_traj_duration(&tr) * (double)i / (double)(N - 1);
    assert_int_equal(rps3_traj_eval(m, &tr, t, p, dp, ddp), RPS3_OK);
    for (c = 0; c < 3; c++) {
      AT(a->pose, c, i) = p[c];
      AT(a->dpose, c, i) = dp[c];
      AT(a->ddpose, c, i) = ddp[c];
    }
  }
}

/* the largest differences seen, in the units of the tolerances below */
typedef struct {
  double l, theta, F, lambda, cond, eres, trans, rates, centre, escale;
  int kernel; /* points the kernel certified */
} worst;

static void track(double *w, double x) {
  if (x > *w) *w = x;
}

/* every output of the batch into the arrays of a */
static void out_every(rps3_batch_out *out, arrays *a) {
  memset(out, 0, sizeof(*out));
  out->status = a->status;
  out->warn = a->warn;
  out->niter = a->niter;
  out->l = a->l;
  out->theta = a->theta;
  out->F = a->F;
  out->F_effect = a->F_effect;
  out->lambda = a->lambda;
  out->cond = a->cond;
  out->energy_residual = a->eres;
  out->transmission = a->trans;
  out->dl = a->dl;
  out->ddl = a->ddl;
  out->c = a->cpos;
  out->energy_scale = a->escale;
  out->solve_resid = a->sres;
}

/*
 * rps3_inverse_batch against rps3_inverse on the points of a.  Status and
 * warning equal for every point.  Values, for the points computed:
 *   - l within 4 ulp (the positions differ by the rounding of the pose's
 *     sines and cosines, a few ulp);
 *   - theta within 2 ulp of pi (atan2 within 4 ulp of its own result, of
 *     inputs that differ by a few ulp);
 *   - F, its shares and lambda (times R) within 8 eps cond of their scale
 *     (the largest magnitude among the forces and shares of the point: a
 *     force is a sum of shares): the same loads solved with a different
 *     rounding, through the lambda system whose condition number
 *     amplifies the difference (measured: up to 2.7 eps cond);
 *   - cond within 8 eps cond (an inverse by adjugate vs by LU);
 *   - the energy residual within 8 eps cond of the power scale, and that
 *     scale (a sum of magnitudes of the same terms) within 8 eps cond;
 *   - the transmission within 8 eps cond (the 6 x 6 LU vs rows of the
 *     3 x 3 adjugate);
 *   - the link rates and accelerations within 16 eps of the velocity
 *     (acceleration) scale of the point, r (|da| + |db|) + |dz| (and r
 *     (|dda| + |ddb| + (|da| + |db|)^2) + |ddz|): dot products of vectors
 *     of that size whose inputs differ by a few ulp;
 *   - the centre x_c, y_c within 4 eps r (one product of sines: (3)-(4)),
 *     z_c bitwise (the pose's own); no solve, so solve_resid 0.
 */
static void compare(const rps3_model *m, arrays *a, worst *w) {
  rps3_data *db = NULL, *dl = NULL;
  rps3_batch_in in;
  rps3_batch_out out;
  int i, c, k;
  assert_int_equal(rps3_data_alloc(m, &db), RPS3_OK);
  assert_int_equal(rps3_data_alloc(m, &dl), RPS3_OK);
  memset(&in, 0, sizeof(in));
  in.n = N;
  in.pose = a->pose;
  in.dpose = a->dpose;
  in.ddpose = a->ddpose;
  memset(&out, 0, sizeof(out));
  out_every(&out, a);
  assert_int_equal(rps3_inverse_batch(m, db, &in, &out), RPS3_OK);
  if (!(m->opt.outputs & RPS3_OUT_CERTIFY)) {
    /* without theta asked for, the kernel leaves out (39) and the
       certificate: the forces are the same operations, bit for bit */
    rps3_batch_out lean = out;
    double *F2 = malloc(3 * N * sizeof(double));
    assert_non_null(F2);
    lean.theta = NULL;
    lean.F = F2;
    assert_int_equal(rps3_inverse_batch(m, db, &in, &lean), RPS3_OK);
    assert_memory_equal(F2, a->F, 3 * N * sizeof(double));
    free(F2);
  }
  for (i = 0; i < N; i += RPS3_KBLOCK) {
    rps3_kblock kb;
    rps3_kout o;
    int p, nb = N - i < RPS3_KBLOCK ? N - i : RPS3_KBLOCK;
    rps3_kout_of_block(&o, &kb);
    rps3_kernel_block(m, &in, (size_t)i, nb, 1, RPS3_KFULL, &o);
    for (p = 0; p < nb; p++) w->kernel += kb.ok[p] != 0.0;
  }
  for (i = 0; i < N; i++) {
    double fs = 0.0, tol;
    int s;
    for (c = 0; c < 3; c++) {
      dl->pose[c] = AT(a->pose, c, i);
      dl->dpose[c] = AT(a->dpose, c, i);
      dl->ddpose[c] = AT(a->ddpose, c, i);
    }
    /* the stages themselves: rps3_inverse takes the kernel too, for
       F alone without the certificate */
    s = rps3_inverse_stages(m, dl);
    assert_int_equal(a->status[i], s);
    assert_int_equal(a->warn[i], dl->warn);
    if (s != RPS3_OK) continue;
    assert_int_equal(a->niter[i], 0);
    for (c = 0; c < 3; c++) {
      track(&fs, fabs(dl->F[c]));
      for (k = 0; k < RPS3_NEFFECT; k++) track(&fs, fabs(dl->F_effect[k][c]));
    }
    tol = 8.0 * EPS * dl->cond;
    for (c = 0; c < 3; c++) {
      double e;
      track(&w->l, ulps(AT(a->l, c, i), dl->l[c]) / 4.0);
      if (!(m->opt.outputs & RPS3_OUT_THETA))
        assert_true(isnan(AT(a->theta, c, i)) && isnan(dl->theta[c]));
      else
        track(&w->theta, fabs(AT(a->theta, c, i) - dl->theta[c]) /
                             (2.0 * (nextafter(PI, 4.0) - PI)));
      track(&w->F, fabs(AT(a->F, c, i) - dl->F[c]) / (tol * fs));
      for (k = 0; k < RPS3_NEFFECT; k++) {
        e = fabs(AT(a->F_effect, 3 * k + c, i) - dl->F_effect[k][c]);
        track(&w->F, e / (tol * fs));
        /* no shares asked for: NaN; an effect not selected: exactly
           zero, as in rps3_invdyn */
        if (!(m->opt.outputs & RPS3_OUT_EFFECTS))
          assert_true(isnan(AT(a->F_effect, 3 * k + c, i)));
        else if (!(m->opt.effects & (1 << k)))
          assert_true(AT(a->F_effect, 3 * k + c, i) == 0.0);
      }
      /* lambda [N/m] times a lever [m] is a force */
      e = fabs(AT(a->lambda, c, i) - dl->lambda[c]) * m->R;
      track(&w->lambda, e / (tol * fs));
    }
    track(&w->cond, fabs(a->cond[i] - dl->cond) / (tol * dl->cond));
    track(&w->eres, fabs(a->eres[i] - dl->energy_residual) /
                        (tol * (dl->energy_scale > 0 ? dl->energy_scale : 1)));
    track(&w->escale, fabs(a->escale[i] - dl->energy_scale) /
                          (tol * (dl->energy_scale > 0 ? dl->energy_scale
                                                       : 1)));
    track(&w->trans, fabs(a->trans[i] - dl->transmission) /
                         (tol * dl->transmission));
    {
      double da = fabs(AT(a->dpose, 0, i)), db_ = fabs(AT(a->dpose, 1, i));
      double vs = m->r * (da + db_) + fabs(AT(a->dpose, 2, i));
      double as = m->r * (fabs(AT(a->ddpose, 0, i)) +
                          fabs(AT(a->ddpose, 1, i)) + (da + db_) * (da + db_)) +
                  fabs(AT(a->ddpose, 2, i));
      int vel = (dl->stage & RPS3_STAGE_VEL) != 0;
      for (c = 0; c < 3; c++) {
        if (!vel) {
          /* no rates needed: not computed, NaN as the file says */
          assert_true(isnan(AT(a->dl, c, i)) && isnan(AT(a->ddl, c, i)));
          continue;
        }
        track(&w->rates, fabs(AT(a->dl, c, i) - dl->dl[c]) /
                             (16.0 * EPS * (vs > 0 ? vs : 1)));
        track(&w->rates, fabs(AT(a->ddl, c, i) - dl->ddl[c]) /
                             (16.0 * EPS * (as > 0 ? as : 1)));
      }
    }
    track(&w->centre, fabs(AT(a->cpos, 0, i) - dl->c[0]) / (4.0 * EPS * m->r));
    track(&w->centre, fabs(AT(a->cpos, 1, i) - dl->c[1]) / (4.0 * EPS * m->r));
    assert_true(AT(a->cpos, 2, i) == dl->c[2]);
    assert_true(a->sres[i] == 0.0);
  }
  rps3_data_free(db);
  rps3_data_free(dl);
}

static void check_worst(const worst *w, const char *what) {
  print_message("%s: %d points by the kernel; worst l %.3g, theta %.3g, "
                "F %.3g, lambda %.3g, cond %.3g, residual %.3g, scale %.3g, "
                "transmission %.3g, rates %.3g, centre %.3g of the "
                "tolerance\n",
                what, w->kernel, w->l, w->theta, w->F, w->lambda, w->cond,
                w->eres, w->escale, w->trans, w->rates, w->centre);
  assert_true(w->l <= 1.0);
  assert_true(w->theta <= 1.0);
  assert_true(w->F <= 1.0);
  assert_true(w->lambda <= 1.0);
  assert_true(w->cond <= 1.0);
  assert_true(w->eres <= 1.0);
  assert_true(w->escale <= 1.0);
  assert_true(w->trans <= 1.0);
  assert_true(w->rates <= 1.0);
  assert_true(w->centre <= 1.0);
}

static void scalar_compare(const rps3_model *m, const arrays *a, worst *w);

/* the kernel's configurations on random trajectories and the helix:
   rps3_inverse_batch (scalar 0) or rps3_inverse itself (scalar 1) against
   the stages */
static void agrees(int table2, int effects, int certify, int forces_only,
                   double cond_warn, double trans_warn, const char *what,
                   int scalar) {
  rps3_model m;
  arrays *a = calloc(1, sizeof(*a));
  worst w;
  uint64_t seed;
  assert_non_null(a);
  memset(&w, 0, sizeof(w));
  if (table2)
    rps3_model_default(&m);
  else
    model_entropy(&m);
  m.opt.effects = effects;
  m.opt.outputs = (certify) ? (m.opt.outputs | RPS3_OUT_CERTIFY)
      : (m.opt.outputs & ~RPS3_OUT_CERTIFY);
  /* forces_only: F, lambda and the transmission, no shares, no theta */
  if (forces_only)
    m.opt.outputs = OUT_ONLY | (certify ? RPS3_OUT_CERTIFY : 0);
  if (cond_warn > 0) m.opt.cond_warn = cond_warn;
  if (trans_warn > 0) m.opt.trans_warn = trans_warn;
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  assert_true(rps3_kernel_covers(&m));
  for (seed = 0; seed < 6; seed++) {
    make_points(&m, a, seed == 0 ? 0 : (scalar ? 0x5ca1 : 0x6e7) + seed);
    if (scalar)
      scalar_compare(&m, a, &w);
    else
      compare(&m, a, &w);
  }
  check_worst(&w, what);
  /* the kernel took most points; with the thresholds lowered, some */
  if (cond_warn <= 0 && trans_warn <= 0)
    assert_true(w.kernel > 5 * N);
  else
    assert_true(w.kernel > 0 && w.kernel < 6 * N);
  free(a);
}

static void paper_model_certified(void **state) {
  (void)state;
  agrees(1, RPS3_EFF_DEFAULT, 1, 0, 0, 0, "Table II, paper's effects", 0);
}

static void entropy_model_each_selection(void **state) {
  (void)state;
  agrees(0, RPS3_EFF_DEFAULT, 1, 0, 0, 0, "entropy model, four effects", 0);
  agrees(0, RPS3_EFF_PLATFORM_GRAVITY | RPS3_EFF_LINK_INERTIA, 0, 0, 0, 0,
         "entropy model, two effects, no certificate", 0);
  agrees(0, RPS3_EFF_DEFAULT, 0, 1, 0, 0, "entropy model, F, lambda, transmission", 0);
}

/*
 * rps3_inverse itself on the kernel's configurations: the point through
 * the kernel (rps3_inverse_kernel_point), against the stages
 * (rps3_inverse_stages), with compare()'s tolerances; status, warning and
 * assembly mode equal.  A point the kernel leaves is the stages', bit for
 * bit.  Everything the stages leave in the data is there, to rounding --
 * also on the controller's path (forces_only, no certificate: theta NaN,
 * no shares), where the kernel's lean pass runs -- so that no field holds
 * another point's value:
 *   - the orientation's entries within 4 eps, the ball joints within
 *     4 eps (R + |z_c|): products and sums of sines within 3 ulp;
 *   - the link directions within 8 eps R / l: a difference of ball joint
 *     and pin of size l, divided by l;
 *   - the platform's velocity, angular velocity and accelerations within
 *     16 eps of the point's velocity and acceleration scale (per metre of
 *     r for the angular ones), the link angle rates within 16 eps of that
 *     scale per metre of link;
 *   - the certificate's terms within 8 eps cond of its power scale;
 *   - the stage bits, have_theta and has_lambda equal.
 * With the thresholds lowered into the range of the points, the points
 * near them go through the stages (their warnings are then the stages').
 */
static void data_compare(const rps3_model *m, const rps3_data *dk,
                         const rps3_data *ds, double tol, double fs,
                         worst *w) {
  double da = fabs(ds->dpose[0]), db_ = fabs(ds->dpose[1]);
  double vs = m->r * (da + db_) + fabs(ds->dpose[2]);
  double as = m->r * (fabs(ds->ddpose[0]) + fabs(ds->ddpose[1]) +
                      (da + db_) * (da + db_)) +
              fabs(ds->ddpose[2]);
  double es = ds->energy_scale > 0 ? ds->energy_scale : 1.0;
  int i, c, e, rates = (ds->stage & RPS3_STAGE_VEL) != 0;
  vs = vs > 0 ? vs : 1.0;
  as = as > 0 ? as : 1.0;
  assert_int_equal(dk->stage, ds->stage);
  assert_int_equal(dk->have_theta, ds->have_theta);
  assert_int_equal(dk->has_lambda, ds->has_lambda);
  for (i = 0; i < 3; i++)
    for (c = 0; c < 3; c++) {
      track(&w->centre, fabs(dk->rot[i][c] - ds->rot[i][c]) / (4.0 * EPS));
      track(&w->centre, fabs(dk->b[i][c] - ds->b[i][c]) /
                            (4.0 * EPS * (m->R + fabs(ds->pose[2]))));
      track(&w->theta, fabs(dk->phi[i][c] - ds->phi[i][c]) /
                           (8.0 * EPS * m->R / ds->l[i]));
      track(&w->theta, fabs(dk->dphi[i][c] - ds->dphi[i][c]) /
                           (8.0 * EPS * m->R / ds->l[i]));
      for (e = 0; e < RPS3_NEFFECT; e++)
        track(&w->F, fabs(dk->F_effect[e][c] - ds->F_effect[e][c]) /
                         (tol * fs));
    }
  for (c = 0; c < 3; c++) {
    if (m->opt.outputs & RPS3_OUT_THETA)
      track(&w->theta, fabs(dk->theta[c] - ds->theta[c]) /
                           (2.0 * (nextafter(PI, 4.0) - PI)));
    else
      assert_true(isnan(dk->theta[c]) && isnan(ds->theta[c]));
    if (!rates) continue;
    track(&w->rates, fabs(dk->vc[c] - ds->vc[c]) / (16.0 * EPS * vs));
    track(&w->rates, fabs(dk->omega[c] - ds->omega[c]) * m->r /
                         (16.0 * EPS * vs));
    track(&w->rates, fabs(dk->ac[c] - ds->ac[c]) / (16.0 * EPS * as));
    track(&w->rates, fabs(dk->domega[c] - ds->domega[c]) * m->r /
                         (16.0 * EPS * as));
    track(&w->rates, fabs(dk->dtheta[c] - ds->dtheta[c]) * ds->l[c] /
                         (16.0 * EPS * vs));
    track(&w->rates, fabs(dk->ddtheta[c] - ds->ddtheta[c]) * ds->l[c] /
                         (16.0 * EPS * as));
  }
  track(&w->eres, fabs(dk->power - ds->power) / (tol * es));
  track(&w->eres, fabs(dk->dTdt - ds->dTdt) / (tol * es));
  track(&w->eres, fabs(dk->dPdt - ds->dPdt) / (tol * es));
  track(&w->eres, fabs(dk->energy_residual - ds->energy_residual) /
                      (tol * es));
  track(&w->escale, fabs(dk->energy_scale - ds->energy_scale) / (tol * es));
  if (m->opt.outputs & RPS3_OUT_CERTIFY)
    assert_true(dk->friction_power == 0.0 && ds->friction_power == 0.0);
  else
    assert_true(isnan(dk->friction_power) && isnan(ds->friction_power));
}

static void scalar_compare(const rps3_model *m, const arrays *a, worst *w) {
  rps3_data *dk = NULL, *ds = NULL, *dx = NULL;
  const int lean = m->opt.outputs == RPS3_OUT_FORCES;
  int i, c;
  assert_int_equal(rps3_data_alloc(m, &dk), RPS3_OK);
  assert_int_equal(rps3_data_alloc(m, &ds), RPS3_OK);
  assert_int_equal(rps3_data_alloc(m, &dx), RPS3_OK);
  for (i = 0; i < N; i++) {
    double fs = 0.0, tol;
    int s, served;
    for (c = 0; c < 3; c++) {
      dx->pose[c] = dk->pose[c] = ds->pose[c] = AT(a->pose, c, i);
      dx->dpose[c] = dk->dpose[c] = ds->dpose[c] = AT(a->dpose, c, i);
      dx->ddpose[c] = dk->ddpose[c] = ds->ddpose[c] = AT(a->ddpose, c, i);
    }
    served = rps3_inverse_kernel_point(m, dx);
    s = rps3_inverse(m, dk);
    assert_int_equal(s, rps3_inverse_stages(m, ds));
    assert_int_equal(dk->warn, ds->warn);
    if (s != RPS3_OK) {
      assert_false(served);
      continue;
    }
    assert_int_equal(dk->mode, ds->mode);
    if (!served) {
      /* a point left to the stages: theirs, bit for bit */
      assert_memory_equal(dk->F, ds->F, sizeof(dk->F));
      continue;
    }
    w->kernel++;
    assert_memory_equal(dk->F, dx->F, sizeof(dk->F));
    for (c = 0; c < 3; c++) track(&fs, fabs(ds->F[c]));
    {
      int e;
      for (e = 0; e < RPS3_NEFFECT; e++)
        for (c = 0; c < 3; c++) {
          track(&fs, fabs(ds->F_effect[e][c]));
          if (!(m->opt.outputs & RPS3_OUT_EFFECTS))
            assert_true(isnan(dk->F_effect[e][c]));
          else if (!(m->opt.effects & (1 << e)))
            assert_true(dk->F_effect[e][c] == 0.0);
        }
    }
    tol = 8.0 * EPS * ds->cond;
    for (c = 0; c < 3; c++) {
      track(&w->l, ulps(dk->l[c], ds->l[c]) / 4.0);
      track(&w->F, fabs(dk->F[c] - ds->F[c]) / (tol * fs));
      track(&w->lambda, fabs(dk->lambda[c] - ds->lambda[c]) * m->R /
                            (tol * fs));
    }
    track(&w->cond, fabs(dk->cond - ds->cond) / (tol * ds->cond));
    track(&w->trans, fabs(dk->transmission - ds->transmission) /
                         (tol * ds->transmission));
    {
      double da = fabs(ds->dpose[0]), db_ = fabs(ds->dpose[1]);
      double vs = m->r * (da + db_) + fabs(ds->dpose[2]);
      double as = m->r * (fabs(ds->ddpose[0]) + fabs(ds->ddpose[1]) +
                          (da + db_) * (da + db_)) +
                  fabs(ds->ddpose[2]);
      for (c = 0; c < 3; c++) {
        if (!(ds->stage & RPS3_STAGE_VEL)) {
          /* no rates needed: not computed, NaN (the stages leave them
             alone) */
          assert_true(isnan(dk->dl[c]) && isnan(dk->ddl[c]));
          continue;
        }
        track(&w->rates, fabs(dk->dl[c] - ds->dl[c]) /
                             (16.0 * EPS * (vs > 0 ? vs : 1)));
        track(&w->rates, fabs(dk->ddl[c] - ds->ddl[c]) /
                             (16.0 * EPS * (as > 0 ? as : 1)));
      }
    }
    track(&w->centre, fabs(dk->c[0] - ds->c[0]) / (4.0 * EPS * m->r));
    track(&w->centre, fabs(dk->c[1] - ds->c[1]) / (4.0 * EPS * m->r));
    assert_true(dk->c[2] == ds->c[2]);
    if (lean)
      assert_true(dk->energy_residual == 0.0 && dk->energy_scale == 0.0);
    data_compare(m, dk, ds, tol, fs, w);
    /* the data is whole: the next stage runs on it as on the stages' */
    assert_int_equal(rps3_velocity(m, dk), RPS3_OK);
  }
  rps3_data_free(dk);
  rps3_data_free(ds);
  rps3_data_free(dx);
}

static void scalar_path_by_the_kernel(void **state) {
  (void)state;
  agrees(1, RPS3_EFF_DEFAULT, 0, 1, 0, 0, "rps3_inverse, Table II", 1);
  agrees(0, RPS3_EFF_DEFAULT, 0, 1, 0, 0, "rps3_inverse, entropy", 1);
  agrees(0, RPS3_EFF_PLATFORM_GRAVITY | RPS3_EFF_LINK_GRAVITY, 0, 1, 0, 0,
         "rps3_inverse, gravity only (no rates)", 1);
  agrees(0, RPS3_EFF_DEFAULT, 0, 1, 0, 2.9, "rps3_inverse, trans_warn", 1);
  agrees(0, RPS3_EFF_DEFAULT, 0, 1, 3.6, 0, "rps3_inverse, cond_warn", 1);
  /* the default (every output, the certificate) and its variants */
  agrees(1, RPS3_EFF_DEFAULT, 1, 0, 0, 0, "rps3_inverse, default", 1);
  agrees(0, RPS3_EFF_DEFAULT, 1, 0, 0, 0, "rps3_inverse, entropy, certify",
         1);
  agrees(0, RPS3_EFF_DEFAULT, 0, 0, 0, 0, "rps3_inverse, no certificate", 1);
  agrees(0, RPS3_EFF_DEFAULT, 1, 1, 0, 0,
         "rps3_inverse, F, lambda, transmission, certify", 1);
  agrees(0, RPS3_EFF_PLATFORM_GRAVITY | RPS3_EFF_LINK_GRAVITY, 0, 0, 0, 0,
         "rps3_inverse, static, no rates", 1);
  agrees(0, RPS3_EFF_PLATFORM_GRAVITY | RPS3_EFF_LINK_INERTIA, 1, 0, 0, 0,
         "rps3_inverse, two effects", 1);
  agrees(0, RPS3_EFF_DEFAULT, 1, 0, 0, 2.9, "rps3_inverse, default, "
         "trans_warn", 1);
}

/*
 * rps3_inverse_batch is the loop of rps3_inverse bit for bit, kernel or
 * not: where the batch runs its vectorised loop, rps3_inverse runs the
 * same body on its one point (no contraction into FMA, the same
 * operations in the same order in every lane), and picks the same
 * variant (the summed load only on the controller's path).  Every output,
 * and F alone, for each selection of certificate and forces_only, with
 * warning thresholds that put points on both sides.
 */
static void batch_is_the_loop_bitwise(void **state) {
  arrays *a = calloc(1, sizeof(*a));
  int cfg, sel, i, c, k, lean_kept = 0;
  (void)state;
  assert_non_null(a);
  for (cfg = 0; cfg < 14; cfg++)
    for (sel = 0; sel < 2; sel++) {
      rps3_model m;
      rps3_data *db = NULL, *dl = NULL;
      rps3_batch_in in;
      rps3_batch_out out;
      model_entropy(&m);
      m.opt.effects = RPS3_EFF_DEFAULT;
      m.opt.outputs = (cfg & 1) ? (m.opt.outputs | RPS3_OUT_CERTIFY)
      : (m.opt.outputs & ~RPS3_OUT_CERTIFY);
      if ((cfg >> 1) & 1)
        m.opt.outputs = OUT_ONLY | (m.opt.outputs & RPS3_OUT_CERTIFY);
      if (cfg & 4) m.opt.trans_warn = 2.9;
      /* 8 .. 13: F alone (the leanest pass), and with the certificate, a
         lowered warning threshold, a static selection (no rates read) */
      if (cfg >= 8) {
        m.opt.outputs = RPS3_OUT_FORCES | (m.opt.outputs & RPS3_OUT_CERTIFY);
        if (cfg >= 12)
          m.opt.effects = RPS3_EFF_PLATFORM_GRAVITY | RPS3_EFF_LINK_GRAVITY;
      }
      assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
      assert_int_equal(rps3_data_alloc(&m, &db), RPS3_OK);
      assert_int_equal(rps3_data_alloc(&m, &dl), RPS3_OK);
      make_points(&m, a, 0xb17 + (uint64_t)cfg);
      memset(&in, 0, sizeof(in));
      in.n = N;
      in.pose = a->pose;
      in.dpose = a->dpose;
      in.ddpose = a->ddpose;
      memset(&out, 0, sizeof(out));
      if (sel) {
        out_every(&out, a);
      } else {
        out.status = a->status;
        out.F = a->F;
      }
      assert_int_equal(rps3_inverse_batch(&m, db, &in, &out), RPS3_OK);
      for (i = 0; i < N; i++) {
        for (c = 0; c < 3; c++) {
          dl->pose[c] = AT(a->pose, c, i);
          dl->dpose[c] = AT(a->dpose, c, i);
          dl->ddpose[c] = AT(a->ddpose, c, i);
        }
        assert_int_equal(rps3_inverse(&m, dl), a->status[i]);
        if (a->status[i] != RPS3_OK) continue;
        if (m.opt.outputs == RPS3_OUT_FORCES) {
          /* F, cond, warn; every other output NaN, and the kinematics at
             the pass's own points (the stages' points keep theirs) */
          for (c = 0; c < 3; c++)
            assert_memory_equal(&dl->F[c], &AT(a->F, c, i), sizeof(double));
          if (!sel) continue;
          assert_memory_equal(&dl->cond, &a->cond[i], sizeof(double));
          assert_int_equal(dl->warn, a->warn[i]);
          for (c = 0; c < 3; c++) {
            assert_true(isnan(AT(a->theta, c, i)) && isnan(dl->theta[c]));
            assert_true(isnan(AT(a->lambda, c, i)) && isnan(dl->lambda[c]));
            if (dl->stage == 0)
              assert_true(isnan(AT(a->l, c, i)) && isnan(AT(a->dl, c, i)) &&
                          isnan(AT(a->ddl, c, i)) &&
                          isnan(AT(a->cpos, c, i)));
            for (k = 0; k < RPS3_NEFFECT; k++)
              assert_true(isnan(AT(a->F_effect, 3 * k + c, i)) &&
                          isnan(dl->F_effect[k][c]));
          }
          assert_true(isnan(a->trans[i]) && isnan(a->eres[i]));
          assert_true(isnan(a->escale[i]));
          assert_true(isnan(dl->transmission) && isnan(dl->energy_residual));
          if (dl->stage == 0) assert_true(isnan(a->sres[i]));
          lean_kept += dl->stage == 0;
          continue;
        }
        for (c = 0; c < 3; c++) {
          assert_memory_equal(&dl->F[c], &AT(a->F, c, i), sizeof(double));
          if (!sel) continue;
          assert_memory_equal(&dl->lambda[c], &AT(a->lambda, c, i),
                              sizeof(double));
          assert_memory_equal(&dl->l[c], &AT(a->l, c, i), sizeof(double));
          assert_memory_equal(&dl->dl[c], &AT(a->dl, c, i), sizeof(double));
          assert_memory_equal(&dl->ddl[c], &AT(a->ddl, c, i),
                              sizeof(double));
          assert_memory_equal(&dl->c[c], &AT(a->cpos, c, i), sizeof(double));
          if (!(m.opt.outputs & RPS3_OUT_THETA))
            assert_true(isnan(dl->theta[c]) && isnan(AT(a->theta, c, i)));
          else
            assert_memory_equal(&dl->theta[c], &AT(a->theta, c, i),
                                sizeof(double));
          for (k = 0; k < RPS3_NEFFECT; k++)
            assert_memory_equal(&dl->F_effect[k][c],
                                &AT(a->F_effect, 3 * k + c, i),
                                sizeof(double));
        }
        if (!sel) continue;
        assert_int_equal(dl->warn, a->warn[i]);
        assert_memory_equal(&dl->cond, &a->cond[i], sizeof(double));
        assert_memory_equal(&dl->transmission, &a->trans[i], sizeof(double));
        assert_memory_equal(&dl->energy_residual, &a->eres[i],
                            sizeof(double));
        assert_memory_equal(&dl->energy_scale, &a->escale[i],
                            sizeof(double));
      }
      rps3_data_free(db);
      rps3_data_free(dl);
    }
  /* the lean configurations ran the lean pass, not only the stages */
  print_message("lean pass: %d points kept\n", lean_kept);
  assert_true(lean_kept > N);
  free(a);
}

/* warnings and their thresholds: with cond_warn and trans_warn inside the
   range the points cover, the status and warning of every point are the
   scalar path's (compare() checks them) */
static void thresholds_as_the_scalar_path(void **state) {
  (void)state;
  agrees(0, RPS3_EFF_DEFAULT, 1, 0, 0, 2.9, "trans_warn 2.9", 0);
  agrees(0, RPS3_EFF_DEFAULT, 1, 0, 3.6, 0, "cond_warn 3.6", 0);
}

/* the kernel's transmission and condition number against rps3_invdyn's */
static void transmission_by_virtual_power(void **state) {
  rps3_model m;
  rps3_data *d = NULL;
  arrays *a = calloc(1, sizeof(*a));
  rps3_batch_in in;
  rps3_kblock kb;
  rps3_kout o;
  double wt = 0.0, wc = 0.0;
  int i, p, c, seen = 0;
  (void)state;
  assert_non_null(a);
  model_entropy(&m);
  m.opt.effects = RPS3_EFF_DEFAULT;
  m.opt.trans_warn = 1e7; /* certify points far from the default's */
  m.opt.cond_warn = 1e7;
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
  make_points(&m, a, 0x7a5);
  memset(&in, 0, sizeof(in));
  in.n = N;
  in.pose = a->pose;
  in.dpose = a->dpose;
  in.ddpose = a->ddpose;
  for (i = 0; i < N; i += RPS3_KBLOCK) {
    int nb = N - i < RPS3_KBLOCK ? N - i : RPS3_KBLOCK;
    rps3_kout_of_block(&o, &kb);
    rps3_kernel_block(&m, &in, (size_t)i, nb, 1, RPS3_KFULL, &o);
    for (p = 0; p < nb; p++) {
      for (c = 0; c < 3; c++) {
        d->pose[c] = AT(a->pose, c, i + p);
        d->dpose[c] = AT(a->dpose, c, i + p);
        d->ddpose[c] = AT(a->ddpose, c, i + p);
      }
      if (rps3_inverse(&m, d) != RPS3_OK) continue;
      seen++;
      /* two formulations of the same numbers: to their rounding (the
         6 x 6 LU and the 3 x 3 adjugate, times cond) */
      CHECK_REL(kb.trans[p], d->transmission, 1e-12 * d->cond, 0.0,
                "transmission of point %d", i + p);
      CHECK_REL(kb.cond[p], d->cond, 1e-13 * d->cond, 0.0,
                "cond of point %d", i + p);
      track(&wt, fabs(kb.trans[p] - d->transmission) / d->transmission);
      track(&wc, fabs(kb.cond[p] - d->cond) / d->cond);
    }
  }
  print_message("%d points: transmission within %.3g, cond within %.3g "
                "(relative)\n", seen, wt, wc);
  assert_true(seen > N / 2);
  rps3_data_free(d);
  free(a);
}

/* points the kernel must leave to the scalar path: not finite, out of the
   reduction's range, unreachable, overflowing; the status is the scalar
   path's */
#define NH 9
static void hard_points_by_the_scalar_path(void **state) {
  rps3_model m;
  rps3_data *db = NULL, *dl = NULL;
  double pose[3 * NH], dpose[3 * NH], ddpose[3 * NH], F[3 * NH];
  int status[NH], i, c;
  const double bad[NH][3] = {
      {0.3, 0.2, 0.25},         {(double)NAN, 0.2, 0.25},
      {0.3, HUGE_VAL, 0.25},    {0.3, 0.2, -0.04},
      {2.0e5, 0.2, 0.25},       {0.3, 0.2, 1e200},
      {0.3 + 64.0 * PI, 0.2, 0.25}, {0.3, 0.2, 0.0}, {0.3, 0.2, 0.25}};
  rps3_batch_in in;
  rps3_batch_out out;
  (void)state;
  rps3_model_default(&m);
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &db), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &dl), RPS3_OK);
  for (i = 0; i < NH; i++)
    for (c = 0; c < 3; c++) {
      pose[c * NH + i] = bad[i][c];
      dpose[c * NH + i] = 0.0137 * (c + 1);
      ddpose[c * NH + i] = -0.0271 * (c + 1);
    }
  dpose[1 * NH + 7] = HUGE_VAL; /* non-finite rates */
  dpose[0 * NH + 8] = 1e200;    /* finite rates whose squares overflow */
  memset(&in, 0, sizeof(in));
  in.n = NH;
  in.pose = pose;
  in.dpose = dpose;
  in.ddpose = ddpose;
  memset(&out, 0, sizeof(out));
  out.status = status;
  out.F = F;
  assert_int_equal(rps3_inverse_batch(&m, db, &in, &out), RPS3_OK);
  for (i = 0; i < NH; i++) {
    for (c = 0; c < 3; c++) {
      dl->pose[c] = pose[c * NH + i];
      dl->dpose[c] = dpose[c * NH + i];
      dl->ddpose[c] = ddpose[c * NH + i];
    }
    assert_int_equal(status[i], rps3_inverse(&m, dl));
    if (status[i] == RPS3_OK)
      for (c = 0; c < 3; c++)
        CHECK_REL(F[c * NH + i], dl->F[c], 1e-13, 1.0, "F of point %d", i);
    else
      assert_true(isnan(F[i]));
  }
  assert_int_equal(status[0], RPS3_OK);
  assert_int_equal(status[4], RPS3_OK); /* beyond the reduction: scalar */
  assert_int_equal(status[6], RPS3_OK); /* alpha + 32 turns: the kernel */
  assert_int_equal(status[8], RPS3_ERANGE);
  assert_int_equal((int)out.nfail, 6);
  /* the same points through rps3_inverse on the controller's path (the
     kernel first): the stages' status, point by point */
  m.opt.outputs = OUT_ONLY;
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  for (i = 0; i < NH; i++) {
    for (c = 0; c < 3; c++) {
      db->pose[c] = dl->pose[c] = pose[c * NH + i];
      db->dpose[c] = dl->dpose[c] = dpose[c * NH + i];
      db->ddpose[c] = dl->ddpose[c] = ddpose[c * NH + i];
    }
    int st = rps3_inverse(&m, db);
    assert_int_equal(st, rps3_inverse_stages(&m, dl));
    if (st != RPS3_OK) assert_string_equal(db->err.msg, dl->err.msg);
  }
  rps3_data_free(db);
  rps3_data_free(dl);
}

/*
 * RPS3_FORCES_LEAN (rps3.h, enum rps3_forces).  On the point d holds, the
 * lean path against the default path (every output, certificate off) and
 * against RPS3_FORCES_ONLY by the stages (what the lean path hands a point
 * to).  A point the lean pass keeps: status RPS3_OK, no warning, d->stage
 * 0, transmission NaN, F within 8 eps cond of the default's force scale
 * (the largest force or share of the point: the same loads through the
 * same lambda system, another rounding, amplified by its condition
 * number), cond within 8 eps cond (the same adjugate, other rounding of
 * its entries).  A point it hands over: status, warning and F those of the
 * stages bit for bit.  Returns 1 when the lean pass kept the point; counts
 * in *gave_up the kept points where RPS3_FORCES_ONLY warns of the force
 * transmission (what the lean path gives up), and tracks the worst F and
 * cond in units of their tolerances.
 */
typedef struct {
  rps3_model def, only, lean; /* every output but the certificate;
                                 OUT_ONLY; F alone */
  rps3_data *dd, *df, *dl;
  double wF, wc; /* worst F and cond, in units of the tolerance */
  int kept, handed, gave_up;
} lean_bench;

static void lean_setup(lean_bench *b, const rps3_model *m) {
  memset(b, 0, sizeof(*b));
  b->def = *m;
  b->def.opt.outputs = RPS3_OUT_ALL & ~RPS3_OUT_CERTIFY;
  b->only = b->def;
  b->only.opt.outputs = OUT_ONLY;
  b->lean = b->def;
  b->lean.opt.outputs = RPS3_OUT_FORCES;
  assert_int_equal(rps3_model_init(&b->def, NULL), RPS3_OK);
  assert_int_equal(rps3_model_init(&b->only, NULL), RPS3_OK);
  assert_int_equal(rps3_model_init(&b->lean, NULL), RPS3_OK);
  assert_true(rps3_kernel_covers(&b->lean));
  assert_int_equal(rps3_data_alloc(&b->def, &b->dd), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&b->def, &b->df), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&b->def, &b->dl), RPS3_OK);
}

static void lean_teardown(lean_bench *b) {
  rps3_data_free(b->dd);
  rps3_data_free(b->df);
  rps3_data_free(b->dl);
}

static int lean_point(lean_bench *b, const double p[3], const double dp[3],
                      const double ddp[3]) {
  int c, k, st, sf;
  for (c = 0; c < 3; c++) {
    b->dd->pose[c] = b->df->pose[c] = b->dl->pose[c] = p[c];
    b->dd->dpose[c] = b->df->dpose[c] = b->dl->dpose[c] = dp[c];
    b->dd->ddpose[c] = b->df->ddpose[c] = b->dl->ddpose[c] = ddp[c];
  }
  b->dl->stage = -1; /* set by every outcome */
  st = rps3_inverse(&b->lean, b->dl);
  sf = rps3_inverse_stages(&b->only, b->df);
  if (st == RPS3_OK && b->dl->stage == 0) {
    double fs = 0.0, tol;
    b->kept++;
    assert_int_equal(b->dl->warn, 0);
    assert_true(isnan(b->dl->transmission));
    assert_int_equal(b->dl->have_theta, 0);
    assert_int_equal(b->dl->has_lambda, 0);
    for (c = 0; c < 3; c++) {
      assert_true(isnan(b->dl->theta[c]) && isnan(b->dl->lambda[c]));
      for (k = 0; k < RPS3_NEFFECT; k++)
        assert_true(isnan(b->dl->F_effect[k][c]));
    }
    assert_true(isnan(b->dl->energy_residual) && isnan(b->dl->power));
    assert_int_equal(rps3_inverse(&b->def, b->dd), RPS3_OK);
    /* the checks are not given up: a point the pass keeps is one whose
       transmission the stages find below both thresholds (the bound) */
    if (sf != RPS3_OK || (b->df->warn & RPS3_WARN_TRANS)) b->gave_up++;
    assert_int_equal(sf, RPS3_OK);
    assert_int_equal(b->df->warn, 0);
    for (c = 0; c < 3; c++) {
      track(&fs, fabs(b->dd->F[c]));
      for (k = 0; k < RPS3_NEFFECT; k++)
        track(&fs, fabs(b->dd->F_effect[k][c]));
    }
    tol = 8.0 * EPS * b->dd->cond;
    for (c = 0; c < 3; c++)
      track(&b->wF, fabs(b->dl->F[c] - b->dd->F[c]) / (tol * fs));
    track(&b->wc, fabs(b->dl->cond - b->dd->cond) / (tol * b->dd->cond));
    /* the pass without fused multiply-adds (a CPU without FMA): the same
       point, the same tolerance */
    assert_int_equal(rps3_inverse_lean_point_unfused(&b->lean, b->dl), 1);
    for (c = 0; c < 3; c++)
      track(&b->wF, fabs(b->dl->F[c] - b->dd->F[c]) / (tol * fs));
    track(&b->wc, fabs(b->dl->cond - b->dd->cond) / (tol * b->dd->cond));
    return 1;
  }
  /* handed to the stages: theirs, bit for bit */
  b->handed++;
  assert_int_equal(st, sf);
  assert_int_equal(b->dl->warn, b->df->warn);
  if (st == RPS3_OK)
    assert_memory_equal(b->dl->F, b->df->F, sizeof(b->dl->F));
  else
    assert_int_equal(b->dl->err.code, b->df->err.code);
  return 0;
}

static void lean_report(const lean_bench *b, const char *what) {
  print_message("%s: %d points kept by the lean pass, %d handed to the "
                "stages, %d kept where the transmission warns; worst F "
                "%.3g, cond %.3g of the tolerance\n",
                what, b->kept, b->handed, b->gave_up, b->wF, b->wc);
  assert_true(b->wF <= 1.0);
  assert_true(b->wc <= 1.0);
}

/* the lean path along the helix and random smooth trajectories, Table II
   and the high-entropy model, each selection of effects (a static one:
   no rates read) */
static void lean_forces_as_the_default(void **state) {
  static const int eff[3] = {
      RPS3_EFF_DEFAULT, RPS3_EFF_PLATFORM_GRAVITY | RPS3_EFF_LINK_GRAVITY,
      RPS3_EFF_PLATFORM_INERTIA | RPS3_EFF_LINK_INERTIA};
  arrays *a = calloc(1, sizeof(*a));
  int table2, e, i, c;
  uint64_t seed;
  (void)state;
  assert_non_null(a);
  for (table2 = 0; table2 < 2; table2++)
    for (e = 0; e < 3; e++) {
      rps3_model m;
      lean_bench b;
      if (table2)
        rps3_model_default(&m);
      else
        model_entropy(&m);
      m.opt.effects = eff[e];
      assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
      lean_setup(&b, &m);
      for (seed = 0; seed < 4; seed++) {
        make_points(&m, a, seed == 0 ? 0 : 0x1ea0 + seed);
        for (i = 0; i < N; i++) {
          double p[3], dp[3], ddp[3];
          for (c = 0; c < 3; c++) {
            p[c] = AT(a->pose, c, i);
            dp[c] = AT(a->dpose, c, i);
            ddp[c] = AT(a->ddpose, c, i);
          }
          lean_point(&b, p, dp, ddp);
        }
      }
      lean_report(&b, table2 ? "lean, Table II" : "lean, entropy model");
      /* smooth motions far from singular poses: the pass keeps them */
      assert_int_equal(b.handed, 0);
      lean_teardown(&b);
    }
  free(a);
}

/*
 * The lean path on hard poses: a level platform (beta = 0, -0, 1e-300,
 * beta -> 0), the pose where the lambda system is singular
 * (singular_beta: link 1 in the platform's plane) and a sweep towards it,
 * a level platform lowered towards the base (cond stays small, the
 * transmission grows without bound: the implausible-force guard hands it
 * over), non-finite, overflowing, unreachable and out-of-range inputs.
 * Statuses and warnings are RPS3_FORCES_ONLY's; the singular pose is
 * RPS3_ESING.
 */
static void lean_hard_poses(void **state) {
  rps3_model m;
  lean_bench b;
  const double dp[3] = {0.173, -0.0917, 0.0213};
  const double ddp[3] = {-0.519, 0.338, -0.0741};
  const double zero[3] = {0.0, 0.0, 0.0};
  double p[3], bs;
  int k, st;
  (void)state;
  rps3_model_default(&m);
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  lean_setup(&b, &m);
  /* level and nearly level */
  {
    const double betas[] = {0.0, -0.0, 1e-300, -1e-300, 1e-12, -3.7e-9,
                            2.1e-5, 1e-3};
    for (k = 0; k < (int)(sizeof(betas) / sizeof(betas[0])); k++) {
      p[0] = 0.7318;
      p[1] = betas[k];
      p[2] = 0.2286;
      assert_int_equal(lean_point(&b, p, dp, ddp), 1);
      assert_int_equal(lean_point(&b, p, zero, zero), 1);
    }
  }
  /* the singular pose, and towards it from both sides */
  bs = singular_beta(&m, b.dd, 0.12, 0.3, 1.5);
  assert_true(bs > 0.3 && bs < 1.5);
  p[0] = 0.0;
  p[1] = bs;
  p[2] = 0.12;
  assert_int_equal(lean_point(&b, p, dp, ddp), 0);
  assert_int_equal(rps3_inverse(&b.lean, b.dl), RPS3_ESING);
  for (k = 1; k <= 15; k++) {
    double h = pow(10.0, -(double)k);
    p[1] = bs + h;
    lean_point(&b, p, dp, ddp);
    p[1] = bs - h;
    lean_point(&b, p, dp, ddp);
  }
  /* a level platform lowered to the base: forces without bound, cond
     small; where the transmission bound does not clear it the lean pass
     hands it over (lean_point: the stages' status and warning), and low
     enough the stages warn or fail */
  p[0] = 0.4127;
  p[1] = 0.0;
  for (k = 1; k <= 8; k++) {
    p[2] = 0.2286 * pow(10.0, -(double)k);
    lean_point(&b, p, dp, ddp);
  }
  assert_int_equal(lean_point(&b, p, dp, ddp), 0);
  st = rps3_inverse(&b.lean, b.dl);
  assert_true(st == RPS3_ESING ||
              (st == RPS3_OK && (b.dl->warn & RPS3_WARN_TRANS)));
  p[2] = 0.2286e-4;
  assert_int_equal(lean_point(&b, p, dp, ddp), 0);
  /* inputs the pass leaves to the stages */
  {
    const double bad[][3] = {{(double)NAN, 0.2, 0.25}, {0.3, HUGE_VAL, 0.25},
                             {0.3, 0.2, -0.04},        {0.3, 0.2, 0.0},
                             {2.0e5, 0.2, 0.25},       {0.3, 0.2, 1e200}};
    const int want[] = {RPS3_EINVAL, RPS3_EINVAL, RPS3_EREACH, RPS3_EREACH,
                        RPS3_OK, RPS3_ERANGE};
    for (k = 0; k < 6; k++) {
      assert_int_equal(lean_point(&b, bad[k], dp, ddp), 0);
      assert_int_equal(rps3_inverse(&b.lean, b.dl), want[k]);
    }
    p[0] = 0.3;
    p[1] = 0.2;
    p[2] = 0.25;
    {
      const double inf_rate[3] = {0.1, HUGE_VAL, 0.1};
      const double big_rate[3] = {1e200, 0.1, 0.1};
      assert_int_equal(lean_point(&b, p, inf_rate, ddp), 0);
      assert_int_equal(rps3_inverse(&b.lean, b.dl), RPS3_EINVAL);
      assert_int_equal(lean_point(&b, p, big_rate, ddp), 0);
      assert_int_equal(rps3_inverse(&b.lean, b.dl), RPS3_ERANGE);
    }
  }
  lean_report(&b, "lean, hard poses");
  lean_teardown(&b);
}

/* the singularity check is the default's: with cond_max below every
   point's condition number, every point of the lean path is RPS3_ESING
   (and with cond_warn only, warned), as RPS3_FORCES_ONLY's */
static void lean_singular_is_an_error(void **state) {
  rps3_model m;
  lean_bench b;
  arrays *a = calloc(1, sizeof(*a));
  int i, c, pass;
  (void)state;
  assert_non_null(a);
  for (pass = 0; pass < 2; pass++) {
    rps3_model_default(&m);
    m.opt.cond_warn = 1.05;
    m.opt.cond_max = pass == 0 ? 1.1 : 1e13;
    assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
    lean_setup(&b, &m);
    make_points(&m, a, 0);
    for (i = 0; i < N; i += 7) {
      double p[3], dp[3], ddp[3];
      for (c = 0; c < 3; c++) {
        p[c] = AT(a->pose, c, i);
        dp[c] = AT(a->dpose, c, i);
        ddp[c] = AT(a->ddpose, c, i);
      }
      assert_int_equal(lean_point(&b, p, dp, ddp), 0);
      if (pass == 0) {
        assert_int_equal(rps3_inverse(&b.lean, b.dl), RPS3_ESING);
      } else {
        assert_int_equal(rps3_inverse(&b.lean, b.dl), RPS3_OK);
        assert_true(b.dl->warn & RPS3_WARN_ILLCOND);
      }
    }
    lean_teardown(&b);
  }
  free(a);
}

/* after a point of the lean pass nothing but F and cond is the point's:
   d->stage is 0, so every stage that would read the positions, rates or
   forces returns RPS3_ESTATE instead of another point's values (the data
   held a whole default point before) */
static void lean_leaves_no_stale_stage(void **state) {
  rps3_model m, ml;
  rps3_data *d = NULL;
  double T, P, fr;
  int c;
  (void)state;
  rps3_model_default(&m);
  m.opt.outputs &= ~RPS3_OUT_CERTIFY;
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  ml = m;
  ml.opt.outputs = RPS3_OUT_FORCES;
  assert_int_equal(rps3_model_init(&ml, NULL), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
  for (c = 0; c < 3; c++) {
    d->pose[c] = 0.1 * (c + 1) + 0.0213;
    d->dpose[c] = 0.0371 * (c + 1);
    d->ddpose[c] = -0.0529 * (c + 1);
  }
  assert_int_equal(rps3_inverse(&m, d), RPS3_OK);
  assert_int_equal(d->stage, RPS3_STAGE_POS | RPS3_STAGE_VEL |
                                 RPS3_STAGE_ACC | RPS3_STAGE_DYN);
  d->pose[0] = 1.387;
  d->pose[1] = 0.283;
  assert_int_equal(rps3_inverse(&ml, d), RPS3_OK);
  assert_int_equal(d->stage, 0);
  assert_true(isnan(d->transmission));
  /* every result but F and cond NaN, after a whole point and again after
     a point of the pass itself (which fills the NaNs once) */
  for (c = 0; c < 2; c++) {
    int i, k;
    for (i = 0; i < 3; i++) {
      assert_true(isnan(d->theta[i]) && isnan(d->lambda[i]));
      assert_true(isfinite(d->F[i]));
      for (k = 0; k < RPS3_NEFFECT; k++) assert_true(isnan(d->F_effect[k][i]));
    }
    assert_true(isnan(d->power) && isnan(d->dTdt) && isnan(d->dPdt) &&
                isnan(d->friction_power) && isnan(d->energy_residual) &&
                isnan(d->energy_scale) && isfinite(d->cond));
    d->pose[0] = 1.211;
    assert_int_equal(rps3_inverse(&ml, d), RPS3_OK);
    assert_int_equal(d->stage, 0);
  }
  assert_int_equal(rps3_invdyn(&m, d), RPS3_ESTATE);
  assert_int_equal(rps3_velocity(&m, d), RPS3_ESTATE);
  assert_int_equal(rps3_acceleration(&m, d), RPS3_ESTATE);
  assert_int_equal(rps3_joint_velocity(&m, d), RPS3_ESTATE);
  assert_int_equal(rps3_joint_acceleration(&m, d), RPS3_ESTATE);
  assert_int_equal(rps3_energy(&m, d, &T, &P, &fr), RPS3_ESTATE);
  /* the next default point makes the data whole again */
  assert_int_equal(rps3_inverse(&m, d), RPS3_OK);
  assert_int_equal(d->stage, RPS3_STAGE_POS | RPS3_STAGE_VEL |
                                 RPS3_STAGE_ACC | RPS3_STAGE_DYN);
  rps3_data_free(d);
}

/* the leanest pass's transmission bound is one: at least the stages'
   transmission at every pose, on Table II and the high-entropy model,
   along random trajectories, tilted and lowered platforms and towards the
   singular pose (the pass keeps a point only below it: lean_point) */
static void lean_bound_holds(void **state) {
  arrays *a = calloc(1, sizeof(*a));
  int table2, i, c, k, n = 0;
  double tightest = HUGE_VAL, loose = 0.0;
  (void)state;
  assert_non_null(a);
  for (table2 = 0; table2 < 2; table2++) {
    rps3_model m;
    rps3_data *d = NULL;
    uint64_t seed;
    if (table2)
      rps3_model_default(&m);
    else
      model_entropy(&m);
    m.opt.effects = RPS3_EFF_DEFAULT;
    m.opt.trans_max = m.opt.trans_warn = 1e300; /* every transmission */
    m.opt.cond_max = m.opt.cond_warn = 1e300;
    assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
    assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
    for (seed = 0; seed < 3; seed++) {
      make_points(&m, a, 0xb0d + seed);
      for (i = 0; i < N; i++) {
        double p[3], bound;
        for (c = 0; c < 3; c++) {
          p[c] = d->pose[c] = AT(a->pose, c, i);
          d->dpose[c] = d->ddpose[c] = 0.0;
        }
        /* tilted further, and lowered towards the base */
        for (k = 0; k < 3; k++) {
          if (k == 1) d->pose[1] = p[1] = 2.5 * p[1];
          if (k == 2) d->pose[2] = p[2] = 0.05 * p[2];
          if (rps3_inverse_stages(&m, d) != RPS3_OK) continue;
          bound = rps3_lean_trans_bound(&m, p);
          n++;
          if (bound / d->transmission < tightest) tightest = bound / d->transmission;
          if (bound / d->transmission > loose) loose = bound / d->transmission;
          if (!(bound >= d->transmission * (1.0 - 1e-12)))
            fail_msg("pose (%g, %g, %g): bound %.17g below the "
                     "transmission %.17g", p[0], p[1], p[2], bound,
                     d->transmission);
        }
      }
    }
    rps3_data_free(d);
  }
  print_message("transmission bound: %d poses, bound / transmission in "
                "[%.3g, %.3g]\n", n, tightest, loose);
  assert_true(n > 1000);
  free(a);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(lean_bound_holds),
      cmocka_unit_test(sincos_within_3_ulp),
      cmocka_unit_test(atan2_within_4_ulp),
      cmocka_unit_test(transmission_by_virtual_power),
      cmocka_unit_test(paper_model_certified),
      cmocka_unit_test(entropy_model_each_selection),
      cmocka_unit_test(thresholds_as_the_scalar_path),
      cmocka_unit_test(scalar_path_by_the_kernel),
      cmocka_unit_test(batch_is_the_loop_bitwise),
      cmocka_unit_test(hard_points_by_the_scalar_path),
      cmocka_unit_test(lean_forces_as_the_default),
      cmocka_unit_test(lean_hard_poses),
      cmocka_unit_test(lean_singular_is_an_error),
      cmocka_unit_test(lean_leaves_no_stale_stage),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
