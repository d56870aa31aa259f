/*
 * test_design.c - the design section of rps3.h: the design and its mass
 * model, the per-pose indices against a brute-force implementation of
 * their own (the paper's geometry written here from its definitions, the
 * output twists by GSL's SVD instead of the library's LU), the closed forms
 * of the level platform, scale invariance, singularities, the empty
 * workspace, bad designs and the task requirements.
 */
#include <gsl/gsl_linalg.h>

#include "testutil.h"

/*
 * Tolerances.
 * TOL_EXACT (testutil.h) for the positions, lengths and angles: the oracle
 * and the library evaluate exact formulas of the same quantity (rounding
 * only, ~1e-15 relative).
 * TOL_TWIST for the transmission indices and the condition number: the
 * oracle takes the output twist from an SVD null vector, the library from
 * an LU inverse; both are backward stable, so they agree to a few eps
 * times the condition number of G (cond_h, below 1e3 where compared):
 * 1e-15 * 1e3 * 10 = 1e-11 (2e-13 seen).
 * TOL_DIST: the clearance against a golden-section search over one
 * segment (convex in its parameter), converged to the rounding of the
 * distance: 1e-12 m on links of ~0.3 m.
 */
#define TOL_TWIST 1e-11
/* TOL_SUM: a sum of N = 2e5 slices accumulates up to N eps ~ 4e-11 of
   rounding */
#define TOL_SUM 1e-10
#define TOL_DIST 1e-12
#define COND_COMPARE 1e3

/* ---------------------------------------------------------------- oracle */

/* the paper's geometry at pose q, from its definitions only */
typedef struct {
  double rot[3][3], c[3], b[3][3], pin[3][3], axis[3][3];
  double l[3], theta[3], phi[3][3], ball[3], spin;
  int assembles;
} geo;

static void mat_mul(double C[3][3], double A[3][3], double B[3][3]) {
  double T[3][3];
  int i, j, k;
  for (i = 0; i < 3; i++)
    for (j = 0; j < 3; j++) {
      T[i][j] = 0.0;
      for (k = 0; k < 3; k++) T[i][j] += A[i][k] * B[k][j];
    }
  memcpy(C, T, sizeof(T));
}

static double dot(const double a[3], const double b[3]) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void cross(double r[3], const double a[3], const double b[3]) {
  r[0] = a[1] * b[2] - a[2] * b[1];
  r[1] = a[2] * b[0] - a[0] * b[2];
  r[2] = a[0] * b[1] - a[1] * b[0];
}

static double norm(const double a[3]) { return sqrt(dot(a, a)); }

/*
 * Orientation (2): Rz(alpha) Ry(beta) Rz(-alpha), as matrices.  The centre
 * (x_c, y_c) from the pins: a pin's axis is tangential, so its link and
 * ball joint stay in the vertical plane through the pin's radius,
 * b_i . t_i = 0 with t_i the tangent.  Two of the three planes fix x_c,
 * y_c; the third holds by the choice of the spin -alpha in (2), and the
 * result is the paper's (3)-(4) -- both checked here.
 */
static void oracle_geo(double R, double rho, const double q[3], geo *g) {
  double ca = cos(q[0]), sa = sin(q[0]), cb = cos(q[1]), sb = sin(q[1]);
  double Rz[3][3] = {{ca, -sa, 0}, {sa, ca, 0}, {0, 0, 1}};
  double Ry[3][3] = {{cb, 0, sb}, {0, 1, 0}, {-sb, 0, cb}};
  double Rzm[3][3] = {{ca, sa, 0}, {-sa, ca, 0}, {0, 0, 1}};
  double r = rho * R, w[3][3], t[3][3], e[3][3], A00, A01, A10, A11, det;
  int i, k;
  mat_mul(g->rot, Rz, Ry);
  mat_mul(g->rot, g->rot, Rzm);
  for (i = 0; i < 3; i++) {
    double psi = 2.0 * PI * i / 3.0, p[3];
    e[i][0] = cos(psi);
    e[i][1] = sin(psi);
    e[i][2] = 0.0;
    t[i][0] = -sin(psi);
    t[i][1] = cos(psi);
    t[i][2] = 0.0;
    for (k = 0; k < 3; k++) p[k] = r * e[i][k];
    for (k = 0; k < 3; k++)
      w[i][k] = g->rot[k][0] * p[0] + g->rot[k][1] * p[1] + g->rot[k][2] * p[2];
    for (k = 0; k < 3; k++) {
      g->pin[i][k] = R * e[i][k];
      g->axis[i][k] = t[i][k];
    }
  }
  /* (x, y) . t_i = -w_i . t_i for i = 0, 1 */
  A00 = t[0][0];
  A01 = t[0][1];
  A10 = t[1][0];
  A11 = t[1][1];
  det = A00 * A11 - A01 * A10;
  g->c[0] = (-dot(w[0], t[0]) * A11 + dot(w[1], t[1]) * A01) / det;
  g->c[1] = (-dot(w[1], t[1]) * A00 + dot(w[0], t[0]) * A10) / det;
  g->c[2] = q[2];
  g->assembles = 1;
  for (i = 0; i < 3; i++) {
    double dv[3];
    for (k = 0; k < 3; k++) g->b[i][k] = g->c[k] + w[i][k];
    for (k = 0; k < 3; k++) dv[k] = g->b[i][k] - g->pin[i][k];
    g->l[i] = norm(dv);
    for (k = 0; k < 3; k++) g->phi[i][k] = dv[k] / g->l[i];
    /* angle to the base plane, measured from the outward radius: below
       pi/2 the link leans inwards */
    g->theta[i] = atan2(dv[2], -dot(dv, e[i]));
    if (!(g->b[i][2] > 0.0)) g->assembles = 0;
    {
      /* ball joint angle by the half-angle formula 2 atan2(|u - a|,
         |u + a|), u the link, a the platform normal */
      double a[3] = {g->rot[0][2], g->rot[1][2], g->rot[2][2]}, dm[3], dp[3];
      for (k = 0; k < 3; k++) {
        dm[k] = g->phi[i][k] - a[k];
        dp[k] = g->phi[i][k] + a[k];
      }
      g->ball[i] = 2.0 * atan2(norm(dm), norm(dp));
    }
  }
  /* the third plane, and (3)-(4) */
  assert_true(fabs(dot(g->b[2], t[2])) <= 1e-14 * R);
  assert_true(fabs(g->c[0] + 0.5 * r * (1 - cb) * cos(2 * q[0])) <= 1e-14 * R);
  assert_true(fabs(g->c[1] - 0.5 * r * (1 - cb) * sin(2 * q[0])) <= 1e-14 * R);
  g->spin = atan2(g->rot[1][0], g->rot[0][0]);
}

/* distance from x to the segment p + s u, s in [0, 1] */
static double point_seg(const double x[3], const double p[3],
                        const double u[3]) {
  double d[3], s;
  int k;
  for (k = 0; k < 3; k++) d[k] = x[k] - p[k];
  s = dot(d, u) / dot(u, u);
  s = s < 0 ? 0 : (s > 1 ? 1 : s);
  for (k = 0; k < 3; k++) d[k] -= s * u[k];
  return norm(d);
}

/* least distance between two segments: golden-section search over the
   first one's parameter (the distance is convex in it) */
static double seg_seg(const double p[3], const double u[3], const double q[3],
                      const double v[3]) {
  const double gr = 0.5 * (sqrt(5.0) - 1.0);
  double a = 0.0, b = 1.0, x1, x2, f1, f2, y[3], best;
  int it, k;
#define AT(s, out)                                  \
  do {                                              \
    for (k = 0; k < 3; k++) y[k] = p[k] + (s)*u[k]; \
    out = point_seg(y, q, v);                       \
  } while (0)
  x1 = b - gr * (b - a);
  x2 = a + gr * (b - a);
  AT(x1, f1);
  AT(x2, f2);
  for (it = 0; it < 200; it++) {
    if (f1 < f2) {
      b = x2;
      x2 = x1;
      f2 = f1;
      x1 = b - gr * (b - a);
      AT(x1, f1);
    } else {
      a = x1;
      x1 = x2;
      f1 = f2;
      x2 = a + gr * (b - a);
      AT(x2, f2);
    }
  }
  best = f1 < f2 ? f1 : f2;
  AT(0.0, f1);
  if (f1 < best) best = f1;
  AT(1.0, f1);
  if (f1 < best) best = f1;
#undef AT
  return best;
}

/*
 * The transmission indices by the null space: the rows are the wrenches of
 * the legs, pure forces f through b_i, written with moments about the base
 * origin (not the platform centre: the index must not depend on the
 * reference point), (f, b_i x f).  The output twist of row k (v_O, omega),
 * v_O the velocity of the body point at the origin, is the null vector of
 * the other five (GSL's SVD: the right singular vector of the least
 * singular value); ball k moves with v_O + omega x b_k, and the index is
 * |f . v| / (|f| |v|).  cond: |G_h|_F |G_h^-1|_F / 6 with G_h's rows
 * (f, (b_i - c) x f / L), the inverse by GSL's LU; cond2 its 2-norm
 * condition number by GSL's SVD.
 */
static void oracle_indices(const geo *g, double L, double *oti, double *cti,
                           double *cond, double *cond2) {
  gsl_matrix *A = gsl_matrix_alloc(6, 6), *V = gsl_matrix_alloc(6, 6);
  gsl_matrix *Inv = gsl_matrix_alloc(6, 6);
  gsl_vector *S = gsl_vector_alloc(6), *work = gsl_vector_alloc(6);
  gsl_permutation *perm = gsl_permutation_alloc(6);
  double rows[6][6], hrows[6][6], fa = 0, fi = 0;
  int k, j, i, sg;
  for (k = 0; k < 6; k++) {
    const double *f = k < 3 ? g->phi[k] : g->axis[k - 3];
    const double *b = g->b[k % 3];
    double mo[3], rel[3], mh[3];
    cross(mo, b, f);
    for (j = 0; j < 3; j++) rel[j] = (b[j] - g->c[j]) / L;
    cross(mh, rel, f);
    for (j = 0; j < 3; j++) {
      rows[k][j] = f[j];
      rows[k][3 + j] = mo[j];
      hrows[k][j] = f[j];
      hrows[k][3 + j] = mh[j];
    }
  }
  *oti = *cti = 1.0;
  for (k = 0; k < 6; k++) {
    const double *f = k < 3 ? g->phi[k] : g->axis[k - 3];
    double v[3], w[3], vb[3], eta;
    for (i = 0; i < 6; i++)
      for (j = 0; j < 6; j++)
        gsl_matrix_set(A, i, j, i == k ? 0.0 : rows[i][j]);
    gsl_linalg_SV_decomp(A, V, S, work);
    for (j = 0; j < 3; j++) {
      v[j] = gsl_matrix_get(V, j, 5);
      w[j] = gsl_matrix_get(V, 3 + j, 5);
    }
    cross(vb, w, g->b[k % 3]);
    for (j = 0; j < 3; j++) vb[j] += v[j];
    eta = fabs(dot(f, vb)) / (norm(f) * norm(vb));
    if (k < 3 && eta < *oti) *oti = eta;
    if (k >= 3 && eta < *cti) *cti = eta;
  }
  for (i = 0; i < 6; i++)
    for (j = 0; j < 6; j++) {
      gsl_matrix_set(A, i, j, hrows[i][j]);
      fa += hrows[i][j] * hrows[i][j];
    }
  gsl_linalg_LU_decomp(A, perm, &sg);
  gsl_linalg_LU_invert(A, perm, Inv);
  for (i = 0; i < 6; i++)
    for (j = 0; j < 6; j++)
      fi += gsl_matrix_get(Inv, i, j) * gsl_matrix_get(Inv, i, j);
  *cond = sqrt(fa * fi) / 6.0;
  for (i = 0; i < 6; i++)
    for (j = 0; j < 6; j++) gsl_matrix_set(A, i, j, hrows[i][j]);
  gsl_linalg_SV_decomp(A, V, S, work);
  *cond2 = gsl_vector_get(S, 0) / gsl_vector_get(S, 5);
  gsl_matrix_free(A);
  gsl_matrix_free(V);
  gsl_matrix_free(Inv);
  gsl_vector_free(S);
  gsl_vector_free(work);
  gsl_permutation_free(perm);
}

/* ------------------------------------------------------------- fixtures */

typedef struct {
  int flags[4096];
  double l[3 * 4096], theta[3 * 4096], ball[3 * 4096], c[3 * 4096];
  double clearance[4096], lti[4096], oti[4096], cti[4096], cond[4096];
  double trans[4096], spin[4096];
  rps3_design_out out;
} outs;

static void outs_bind(outs *o) {
  o->out.flags = o->flags;
  o->out.l = o->l;
  o->out.theta = o->theta;
  o->out.ball = o->ball;
  o->out.clearance = o->clearance;
  o->out.lti = o->lti;
  o->out.oti = o->oti;
  o->out.cti = o->cti;
  o->out.cond_h = o->cond;
  o->out.transmission = o->trans;
  o->out.c = o->c;
  o->out.spin = o->spin;
}

static outs *outs_new(void) {
  outs *o = (outs *)test_calloc(1, sizeof(outs));
  outs_bind(o);
  return o;
}

/* a design with high-entropy values and every limit active */
static void design_entropy(rps3_design *ds) {
  rps3_design_default(ds);
  ds->R = 0.2385;
  ds->rho = 0.437;
  ds->l_min = 0.1713;
  ds->l_max = 0.4121;
  ds->theta_min = 0.3517;
  ds->theta_max = 2.7113;
  ds->ball_max = 0.8291;
  ds->link_radius = 0.0713;
  ds->M = 0.2137;
  ds->actuator_mass = 0.0731;
  ds->actuator_d = 0.1337;
  ds->link_density = 0.1893;
}

static rps3_design_ws *ws_new(void) {
  rps3_design_ws *w = NULL;
  assert_int_equal(rps3_design_ws_alloc(&w), RPS3_OK);
  assert_non_null(w);
  return w;
}

/* -------------------------------------------------------------- tests */

/* the default design's model is Table II, field by field */
static void default_is_table2(void **state) {
  rps3_design ds;
  rps3_model m, p;
  rps3_check chk;
  (void)state;
  rps3_design_default(&ds);
  assert_int_equal(rps3_design_model(&ds, &m, &chk), RPS3_OK);
  assert_int_equal(chk.field, -1);
  assert_string_equal(chk.msg, "");
  rps3_model_default(&p);
  assert_int_equal(rps3_model_init(&p, NULL), RPS3_OK);
  assert_true(m.R == 0.2286 && m.R == p.R);
  assert_true(m.rho == 0.5 && m.rho == p.rho);
  assert_true(m.M == 0.18 && m.M == p.M);
  assert_true(m.m == 0.09 && m.m == p.m);
  assert_true(m.d == 0.1524 && m.d == p.d);
  assert_true(m.link_Ic == 0.0 && m.g == p.g);
  assert_int_equal(m.opt.effects, p.opt.effects);
  assert_true(m.valid);
}

/*
 * The link mass model against its definition: the rod (density mu over
 * [0, l_max] from the pin) summed in 200000 slices by the midpoint rule
 * (relative error 1 / (12 N^2) ~ 2e-12 in the second moment) plus the
 * actuator's point mass; d the first moment over the mass, link_Ic the
 * second moment about the pin minus m d^2.  A payload selects its effect.
 */
static void mass_model_rule(void **state) {
  rps3_design ds;
  rps3_model m;
  const int N = 200000;
  double h, m0, m1, m2, d, ic;
  int k;
  (void)state;
  design_entropy(&ds);
  ds.payload = 0.0417;
  ds.payload_height = 0.0123;
  assert_int_equal(rps3_design_model(&ds, &m, NULL), RPS3_OK);
  h = ds.l_max / N;
  m0 = ds.actuator_mass;
  m1 = ds.actuator_mass * ds.actuator_d;
  m2 = ds.actuator_mass * ds.actuator_d * ds.actuator_d;
  for (k = 0; k < N; k++) {
    double x = (k + 0.5) * h, dm = ds.link_density * h;
    m0 += dm;
    m1 += dm * x;
    m2 += dm * x * x;
  }
  d = m1 / m0;
  ic = m2 - m0 * d * d;
  CHECK_REL(m.m, m0, TOL_SUM, 0.0, "link mass");
  CHECK_REL(m.d, d, TOL_SUM, 0.0, "link centroid d");
  CHECK_REL(m.link_Ic, ic, 1e-9, 0.0, "link inertia about the centroid");
  assert_true(m.payload.mass == ds.payload);
  assert_true(m.payload.com[2] == ds.payload_height);
  assert_true(m.opt.effects & RPS3_EFF_PAYLOAD);
  /* massless links: d = 0, no NaN */
  ds.actuator_mass = 0.0;
  ds.link_density = 0.0;
  assert_int_equal(rps3_design_model(&ds, &m, NULL), RPS3_OK);
  assert_true(m.m == 0.0 && m.d == 0.0 && m.link_Ic == 0.0);
}

/* each field refused alone with its name, by a NaN and by a value out of
   its range; then the rules between fields */
static void bad_designs_named(void **state) {
  static const double bad[RPS3_NDESIGN_FIELD] = {
      0.0,  -0.5, -0.1,     0.0,  -0.2, 3.3,  0.0, -1e-3,
      -1.0, -2.0, HUGE_VAL, -0.1, -0.3, -4.0, -9.8};
  rps3_design ds;
  rps3_model m;
  rps3_check chk;
  char want[64];
  int id;
  (void)state;
  for (id = 0; id < RPS3_NDESIGN_FIELD; id++) {
    const rps3_field_info *f = rps3_design_field(id);
    int pass;
    assert_non_null(f);
    assert_int_equal(f->in, RPS3_IN_DESIGN);
    for (pass = 0; pass < 2; pass++) {
      rps3_design_default(&ds);
      *(double *)((char *)&ds + f->offset) = pass ? bad[id] : (double)NAN;
      assert_int_equal(rps3_design_model(&ds, &m, NULL), RPS3_EINVAL);
      assert_int_equal(rps3_design_model(&ds, &m, &chk), RPS3_EINVAL);
      snprintf(want, sizeof want, "%s = ", f->name);
      if (strncmp(chk.msg, want, strlen(want)) != 0)
        fail_msg("field %s: message \"%s\"", f->name, chk.msg);
      assert_int_equal(chk.field, id);
    }
  }
  assert_null(rps3_design_field(RPS3_NDESIGN_FIELD));
  assert_null(rps3_design_field(-1));
  /* inverted and empty stroke, inverted and empty pin range */
  rps3_design_default(&ds);
  ds.l_min = 0.41;
  ds.l_max = 0.33;
  assert_int_equal(rps3_design_model(&ds, &m, &chk), RPS3_EINVAL);
  assert_true(strncmp(chk.msg, "l_max = 0.33: must be > l_min = 0.41", 36) == 0);
  assert_non_null(strstr(chk.msg, "stroke"));
  ds.l_max = ds.l_min;
  assert_int_equal(rps3_design_model(&ds, &m, &chk), RPS3_EINVAL);
  assert_int_equal(chk.field, RPS3_DF_L_MAX);
  assert_int_equal(chk.related[0], RPS3_DF_L_MIN);
  rps3_design_default(&ds);
  ds.theta_min = 1.3;
  ds.theta_max = 1.3;
  assert_int_equal(rps3_design_model(&ds, &m, &chk), RPS3_EINVAL);
  assert_int_equal(chk.field, RPS3_DF_THETA_MAX);
  assert_non_null(strstr(chk.msg, "theta_min"));
  /* products that overflow, named by the design's field */
  rps3_design_default(&ds);
  ds.link_density = 1e300;
  ds.l_max = 1e10;
  assert_int_equal(rps3_design_model(&ds, &m, &chk), RPS3_EINVAL);
  assert_int_equal(chk.field, RPS3_DF_LINK_DENSITY);
  rps3_design_default(&ds);
  ds.M = 1e308;
  assert_int_equal(rps3_design_model(&ds, &m, &chk), RPS3_EINVAL);
  assert_true(strncmp(chk.msg, "M = ", 4) == 0);
  assert_int_equal(chk.field, RPS3_DF_M);
  /* NULLs */
  assert_int_equal(rps3_design_model(NULL, &m, &chk), RPS3_EINVAL);
  assert_int_equal(chk.field, -1);
  assert_string_equal(chk.msg, "design is NULL");
  assert_int_equal(rps3_design_model(&ds, NULL, NULL), RPS3_EINVAL);
}

/* a bad design, bad options or bad poses through the evaluations: the
   status and the message, nothing evaluated */
static void bad_calls(void **state) {
  rps3_design ds;
  rps3_design_opts o;
  rps3_design_ws *w = ws_new();
  rps3_design_grid gr;
  rps3_design_summary s;
  double pose[6] = {0.1, 0.2, 0.3, 0.4, 0.25, (double)NAN};
  rps3_traj tr;
  rps3_design_task t;
  (void)state;
  rps3_design_default(&ds);
  rps3_design_grid_default(&ds, &gr);
  ds.rho = -1.0;
  assert_int_equal(rps3_design_eval_grid(w, &ds, NULL, &gr, NULL, &s),
                   RPS3_EINVAL);
  assert_true(strncmp(w->err.msg, "rho = -1", 8) == 0);
  rps3_design_default(&ds);
  assert_int_equal(rps3_design_eval(w, &ds, NULL, 2, pose, 1.0, NULL, &s),
                   RPS3_EINVAL);
  assert_non_null(strstr(w->err.msg, "z_c of pose 1"));
  assert_int_equal(rps3_design_eval(w, &ds, NULL, 0, pose, 1.0, NULL, &s),
                   RPS3_EINVAL);
  assert_int_equal(rps3_design_eval(w, &ds, NULL, 1, pose, -1.0, NULL, &s),
                   RPS3_EINVAL);
  /* a finite cell volume whose product with the count overflows */
  {
    const double two[6] = {0.0, 0.0, 0.0, 0.0, 0.3048, 0.3048};
    assert_int_equal(rps3_design_eval(w, &ds, NULL, 2, two, 1e308, NULL, &s),
                     RPS3_ERANGE);
    assert_non_null(strstr(w->err.msg, "volume"));
  }
  rps3_design_opts_default(&o);
  o.lti_good = 1.5;
  assert_int_equal(rps3_design_eval(w, &ds, &o, 1, pose, 1.0, NULL, &s),
                   RPS3_EINVAL);
  assert_non_null(strstr(w->err.msg, "lti_good"));
  gr.n[1] = 0;
  assert_int_equal(rps3_design_eval_grid(w, &ds, NULL, &gr, NULL, &s),
                   RPS3_EINVAL);
  rps3_traj_default(&tr);
  assert_int_equal(rps3_design_task_eval(w, &ds, NULL, &tr, 1, 1, &t),
                   RPS3_EINVAL);
  assert_int_equal(rps3_design_task_eval(w, &ds, NULL, &tr, 10, 2, &t),
                   RPS3_EINVAL);
  /* a helix wider than the design's platform allows: the trajectory's
     own message */
  ds.rho = 0.001;
  assert_int_equal(rps3_design_task_eval(w, &ds, NULL, &tr, 10, 1, &t),
                   RPS3_EINVAL);
  assert_true(strncmp(w->err.msg, "trajectory.radius", 17) == 0);
  assert_int_equal(rps3_design_eval(NULL, &ds, NULL, 1, pose, 1, NULL, &s),
                   RPS3_EINVAL);
  rps3_design_ws_free(w);
  rps3_design_ws_free(NULL);
  assert_int_equal(rps3_design_ws_alloc(NULL), RPS3_EINVAL);
}

/*
 * The fast evaluation against the oracle on a grid of 11 x 9 x 13 poses of
 * a design whose every limit is active somewhere: lengths, angles, centre,
 * spin, ball angles, clearance, the flags (each of the first five set
 * somewhere and clear somewhere), the transmission indices and the
 * condition number.  The force transmission is rps3_inverse's (the same
 * function, so: bitwise).
 */
static void brute_force_agrees(void **state) {
  rps3_design ds;
  rps3_design_ws *w = ws_new();
  rps3_design_grid gr;
  rps3_design_summary s;
  rps3_model m;
  rps3_data *d = NULL;
  outs *o = outs_new();
  size_t n, i;
  int seen_set = 0, seen_clear = 0, ncmp = 0;
  double worst_twist = 0.0, L;
  (void)state;
  design_entropy(&ds);
  gr.lo[0] = -3.1;
  gr.hi[0] = 3.05;
  gr.lo[1] = 0.0;
  gr.hi[1] = 1.3;
  gr.lo[2] = 0.01;
  gr.hi[2] = 0.47;
  gr.n[0] = 11;
  gr.n[1] = 9;
  gr.n[2] = 13;
  n = rps3_design_grid_size(&gr);
  assert_int_equal(n, 1287);
  assert_int_equal(rps3_design_eval_grid(w, &ds, NULL, &gr, &o->out, &s),
                   RPS3_OK);
  assert_int_equal(rps3_design_model(&ds, &m, NULL), RPS3_OK);
  m.opt.effects = RPS3_EFF_PLATFORM_GRAVITY;
  m.opt.outputs = RPS3_OUT_ALL & ~RPS3_OUT_CERTIFY;
  m.opt.trans_max = m.opt.trans_warn = m.opt.cond_max = m.opt.cond_warn = 1e300;
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
  L = ds.rho * ds.R;
  for (i = 0; i < n; i++) {
    double q[3], oti, cti, cond, cond2, clear = HUGE_VAL;
    geo g;
    int j, k, flags = 0;
    assert_int_equal(rps3_design_grid_pose(&gr, i, q), RPS3_OK);
    oracle_geo(ds.R, ds.rho, q, &g);
    if (!g.assembles) {
      assert_int_equal(o->flags[i], RPS3_DESIGN_ASSEMBLY);
      seen_set |= RPS3_DESIGN_ASSEMBLY;
      assert_true(isnan(o->lti[i]) && isnan(o->l[i]) && isnan(o->spin[i]));
      continue;
    }
    for (j = 0; j < 3; j++) {
      CHECK_REL(o->l[j * n + i], g.l[j], TOL_EXACT, 0.0, "l pose %zu", i);
      CHECK_REL(o->theta[j * n + i], g.theta[j], TOL_EXACT, 1.0, "theta");
      CHECK_REL(o->ball[j * n + i], g.ball[j], TOL_EXACT, 1.0, "ball");
      CHECK_REL(o->c[j * n + i], g.c[j], TOL_EXACT, ds.R, "c");
      if (!(g.l[j] >= ds.l_min && g.l[j] <= ds.l_max))
        flags |= RPS3_DESIGN_STROKE;
      if (!(g.theta[j] >= ds.theta_min && g.theta[j] <= ds.theta_max))
        flags |= RPS3_DESIGN_PIN;
      if (!(g.ball[j] <= ds.ball_max)) flags |= RPS3_DESIGN_BALL;
      for (k = j + 1; k < 3; k++) {
        double u[3], v[3], e;
        int c;
        for (c = 0; c < 3; c++) {
          u[c] = g.b[j][c] - g.pin[j][c];
          v[c] = g.b[k][c] - g.pin[k][c];
        }
        e = seg_seg(g.pin[j], u, g.pin[k], v);
        if (e < clear) clear = e;
      }
    }
    clear -= 2.0 * ds.link_radius;
    if (clear < 0.0) flags |= RPS3_DESIGN_INTERFERE;
    CHECK_REL(o->spin[i], g.spin, TOL_EXACT, 1.0, "spin");
    CHECK_REL(o->clearance[i], clear, TOL_DIST / ds.R, ds.R, "clearance");
    oracle_indices(&g, L, &oti, &cti, &cond, &cond2);
    if (cond > 1e8) flags |= RPS3_DESIGN_SINGULAR;
    assert_int_equal(o->flags[i], flags);
    seen_set |= flags;
    seen_clear |= ~flags;
    /* Frobenius within its bounds by the 2-norm's */
    assert_true(o->cond[i] >= cond2 / 6.0 * (1 - 1e-9) &&
                o->cond[i] <= cond2 * (1 + 1e-9));
    if (cond < COND_COMPARE) {
      double e1 = fabs(o->oti[i] - oti), e2 = fabs(o->cti[i] - cti);
      double e3 = fabs(o->cond[i] - cond) / cond;
      CHECK_REL(o->oti[i], oti, TOL_TWIST, 1.0, "OTI pose %zu", i);
      CHECK_REL(o->cti[i], cti, TOL_TWIST, 1.0, "CTI pose %zu", i);
      CHECK_REL(o->lti[i], oti < cti ? oti : cti, TOL_TWIST, 1.0, "LTI");
      CHECK_REL(o->cond[i], cond, TOL_TWIST, 0.0, "cond_h pose %zu", i);
      if (e1 > worst_twist) worst_twist = e1;
      if (e2 > worst_twist) worst_twist = e2;
      if (e3 > worst_twist) worst_twist = e3;
      ncmp++;
    }
    /* the force transmission is rps3_inverse's own */
    for (j = 0; j < 3; j++) d->pose[j] = q[j];
    assert_int_equal(rps3_inverse(&m, d), RPS3_OK);
    assert_true(o->trans[i] == d->transmission);
  }
  print_message(
      "brute force: %d poses compared, worst twist-index error "
      "%.3g, flags seen 0x%x, reachable %zu of %zu\n",
      ncmp, worst_twist, seen_set, s.nreach, n);
  /* every check decided somewhere (both ways) on this grid */
  for (i = 0; i < 5; i++) {
    assert_true(seen_set & (1 << i));
    assert_true(seen_clear & (1 << i));
  }
  assert_true(ncmp > 300);
  assert_true(s.nreach > 20);
  rps3_data_free(d);
  test_free(o);
  rps3_design_ws_free(w);
}

/*
 * The summary is what the per-pose outputs say: counts, fraction, volume
 * (reachable count times the cell), GTI the mean LTI, good fraction, the
 * extremes; over a grid that covers the box, the cell volume times n is
 * the box's volume.  Summary of a list equals the grid's.
 */
static void summary_of_outputs(void **state) {
  rps3_design ds;
  rps3_design_ws *w = ws_new();
  rps3_design_grid gr;
  rps3_design_summary s, s2;
  rps3_design_opts opt;
  outs *o = outs_new();
  double cv, sum = 0.0, lmin = HUGE_VAL, cmax = 0, xmax = 0, spmax = 0;
  double *pose;
  size_t n, i, nr = 0, ng = 0, nf[RPS3_DESIGN_NFLAG] = {0};
  int k;
  (void)state;
  rps3_design_default(&ds);
  rps3_design_grid_default(&ds, &gr);
  rps3_design_opts_default(&opt);
  opt.lti_good = 0.83;
  n = rps3_design_grid_size(&gr);
  assert_int_equal(rps3_design_eval_grid(w, &ds, &opt, &gr, &o->out, &s),
                   RPS3_OK);
  assert_int_equal(rps3_design_grid_cell(&gr, &cv), RPS3_OK);
  CHECK_REL(cv * (double)n, 2 * PI * (PI / 3) * 2 * ds.R, 1e-14, 0.0,
            "cells fill the box");
  for (i = 0; i < n; i++) {
    for (k = 0; k < RPS3_DESIGN_NFLAG; k++)
      if (o->flags[i] & (1 << k)) nf[k]++;
    if (o->flags[i]) continue;
    nr++;
    sum += o->lti[i];
    ng += o->lti[i] >= 0.83;
    if (o->lti[i] < lmin) lmin = o->lti[i];
    if (o->cond[i] > cmax) cmax = o->cond[i];
    if (fabs(o->c[i]) > xmax) xmax = fabs(o->c[i]);
    if (fabs(o->spin[i]) > spmax) spmax = fabs(o->spin[i]);
  }
  assert_int_equal(s.n, n);
  assert_int_equal(s.nreach, nr);
  for (k = 0; k < RPS3_DESIGN_NFLAG; k++) assert_int_equal(s.nflag[k], nf[k]);
  assert_true(nr > 0 && nr < n && ng > 0 && ng < nr);
  CHECK_REL(s.reach_fraction, (double)nr / n, 1e-15, 0.0, "fraction");
  CHECK_REL(s.volume, (double)nr * cv, 1e-15, 0.0, "volume");
  CHECK_REL(s.gti, sum / nr, 1e-13, 0.0, "GTI");
  CHECK_REL(s.good_fraction, (double)ng / nr, 1e-15, 0.0, "good");
  assert_true(s.lti_min == lmin && s.cond_h_max == cmax);
  assert_true(s.xc_max == xmax && s.spin_max == spmax);
  assert_true(s.spin_max > 0.0 && s.yc_max > 0.0);
  /* the same poses as a list: the same summary */
  pose = (double *)test_malloc(3 * n * sizeof(double));
  for (i = 0; i < n; i++) {
    double q[3];
    rps3_design_grid_pose(&gr, i, q);
    pose[i] = q[0];
    pose[n + i] = q[1];
    pose[2 * n + i] = q[2];
  }
  assert_int_equal(rps3_design_eval(w, &ds, &opt, n, pose, cv, NULL, &s2),
                   RPS3_OK);
  assert_true(memcmp(&s, &s2, sizeof(s)) == 0);
  test_free(pose);
  test_free(o);
  rps3_design_ws_free(w);
}

/*
 * LTI, OTI, CTI in [0, 1] and cond_h >= 1 at every pose of random
 * designs over wide pose ranges (singular ones included).
 */
static void indices_bounded(void **state) {
  rps3_design ds;
  rps3_design_ws *w = ws_new();
  outs *o = outs_new();
  uint64_t seed = 8831;
  double pose[3 * 500];
  size_t i;
  int rep, nas = 0;
  (void)state;
  for (rep = 0; rep < 20; rep++) {
    rps3_design_default(&ds);
    ds.R = rnd_uniform(&seed, 0.05, 2.0);
    ds.rho = rnd_uniform(&seed, 0.1, 1.6);
    ds.l_min = 0.0;
    ds.l_max = 10.0;
    ds.ball_max = PI;
    for (i = 0; i < 500; i++) {
      pose[i] = rnd_uniform(&seed, -PI, PI);
      pose[500 + i] = rnd_uniform(&seed, 0.0, 1.5);
      pose[1000 + i] = rnd_uniform(&seed, -0.1, 2.0) * ds.R;
    }
    rps3_design_eval(w, &ds, NULL, 500, pose, 0.0, &o->out, NULL);
    for (i = 0; i < 500; i++) {
      if (o->flags[i] & RPS3_DESIGN_ASSEMBLY) {
        nas++;
        continue;
      }
      assert_true(o->lti[i] >= 0.0 && o->lti[i] <= 1.0);
      assert_true(o->oti[i] >= 0.0 && o->oti[i] <= 1.0);
      assert_true(o->cti[i] >= 0.0 && o->cti[i] <= 1.0);
      assert_true(o->lti[i] == (o->oti[i] < o->cti[i] ? o->oti[i] : o->cti[i]));
      assert_true(o->cond[i] >= 1.0);
    }
  }
  assert_true(nas > 0 && nas < 20 * 500);
  test_free(o);
  rps3_design_ws_free(w);
}

/* the whole mechanism scaled by s (R, z_c, stroke, link radius, actuator
   position): LTI, OTI, CTI, cond_h, angles and flags unchanged, lengths
   and the centre scaled */
static void scale_invariant(void **state) {
  static const double sc[3] = {3.7, 1e-3, 0.0625};
  rps3_design ds, d2;
  rps3_design_ws *w = ws_new();
  rps3_design_grid gr, g2;
  outs *a = outs_new(), *b = outs_new();
  size_t n, i;
  int k, j;
  (void)state;
  design_entropy(&ds);
  rps3_design_grid_default(&ds, &gr);
  n = rps3_design_grid_size(&gr);
  assert_int_equal(rps3_design_eval_grid(w, &ds, NULL, &gr, &a->out, NULL),
                   RPS3_OK);
  for (k = 0; k < 3; k++) {
    double s = sc[k];
    d2 = ds;
    d2.R *= s;
    d2.l_min *= s;
    d2.l_max *= s;
    d2.link_radius *= s;
    d2.actuator_d *= s;
    g2 = gr;
    g2.lo[2] *= s;
    g2.hi[2] *= s;
    assert_int_equal(rps3_design_eval_grid(w, &d2, NULL, &g2, &b->out, NULL),
                     RPS3_OK);
    for (i = 0; i < n; i++) {
      assert_int_equal(a->flags[i], b->flags[i]);
      if (a->flags[i] & RPS3_DESIGN_ASSEMBLY) continue;
      CHECK_REL(b->lti[i], a->lti[i], TOL_EXACT, 0.0, "LTI scaled %g", s);
      CHECK_REL(b->oti[i], a->oti[i], TOL_EXACT, 0.0, "OTI scaled");
      CHECK_REL(b->cti[i], a->cti[i], TOL_EXACT, 0.0, "CTI scaled");
      CHECK_REL(b->cond[i], a->cond[i], TOL_EXACT, 0.0, "cond_h scaled");
      CHECK_REL(b->spin[i], a->spin[i], TOL_EXACT, 1.0, "spin scaled");
      CHECK_REL(b->trans[i], a->trans[i], TOL_EXACT, 0.0, "transmission");
      for (j = 0; j < 3; j++) {
        CHECK_REL(b->l[j * n + i], s * a->l[j * n + i], TOL_EXACT, 0.0, "l");
        CHECK_REL(b->ball[j * n + i], a->ball[j * n + i], TOL_EXACT, 1.0,
                  "ball");
      }
    }
  }
  test_free(a);
  test_free(b);
  rps3_design_ws_free(w);
}

/*
 * The level platform at height h, Table II: by symmetry every leg alike.
 * Closed forms (docs/design.md): the actuation rows' output twist moves
 * the platform vertically at ball i (the constraint forces hold x, y and
 * the spin, the other links hold their balls' heights), so
 * OTI = phi_i . Z = h / l = sin(theta); the constraint rows' output twist
 * moves ball i along its pin axis, CTI = 1.  So LTI = h / l, and the
 * paper's home pose (z_c = 0.3048 m) has LTI = 0.93633.  Lowered towards
 * the base, LTI = h / l -> 0: the links lie flat and cannot hold the
 * platform up (an actuation singularity).
 */
static void level_platform_closed_form(void **state) {
  rps3_design ds;
  rps3_design_ws *w = ws_new();
  outs *o = outs_new();
  double pose[3], h;
  int j;
  (void)state;
  rps3_design_default(&ds);
  ds.l_min = 1e-9;
  ds.ball_max = PI;
  for (h = 0.3048; h > 1e-7; h /= 4.1) {
    double R = ds.R, r = ds.rho * R, l = sqrt((R - r) * (R - r) + h * h);
    int st;
    pose[0] = 0.0;
    pose[1] = 0.0;
    pose[2] = h;
    st = rps3_design_eval(w, &ds, NULL, 1, pose, 0.0, &o->out, NULL);
    assert_true(st == RPS3_OK || st == RPS3_EEMPTY);
    CHECK_REL(o->oti[0], h / l, TOL_EXACT, 0.0, "OTI at h = %g", h);
    CHECK_REL(o->cti[0], 1.0, TOL_EXACT, 0.0, "CTI at h = %g", h);
    CHECK_REL(o->lti[0], h / l, TOL_EXACT, 0.0, "LTI at h = %g", h);
    for (j = 0; j < 3; j++) {
      CHECK_REL(o->l[j], l, TOL_EXACT, 0.0, "l");
      CHECK_REL(o->ball[j], atan2(R - r, h), TOL_EXACT, 1.0, "ball");
    }
    assert_true(fabs(o->c[0]) <= 1e-17 && fabs(o->c[1]) <= 1e-17);
    assert_true(fabs(o->spin[0]) <= 1e-17);
    if (h == 0.3048)
      CHECK_REL(o->lti[0], 0.93632917756904455, 1e-14, 0.0,
                "home pose of Table II");
  }
  assert_true(o->lti[0] < 1e-5);
  test_free(o);
  rps3_design_ws_free(w);
}

/*
 * A tilted approach to the singular surface det(df/dtheta) = 0 (found by
 * bisection on rps3_ik's assembly mode, alpha = 0.3, z_c = 0.2 m): the
 * platform can move with the actuators locked there, so LTI -> 0,
 * roughly in proportion to the distance, and cond_h grows without bound.
 */
static void singular_surface_lti_vanishes(void **state) {
  rps3_design ds;
  rps3_design_ws *w = ws_new();
  rps3_model m;
  rps3_data *d = NULL;
  outs *o = outs_new();
  double lo = 0.5, hi = 1.0, bs, e, prev = 2.0, pose[3];
  int k;
  (void)state;
  rps3_design_default(&ds);
  assert_int_equal(rps3_design_model(&ds, &m, NULL), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
  d->pose[0] = 0.3;
  d->pose[2] = 0.2;
  for (k = 0; k < 80; k++) {
    d->pose[1] = 0.5 * (lo + hi);
    assert_int_equal(rps3_ik(&m, d), RPS3_OK);
    if (d->mode == RPS3_MODE_LEVEL)
      lo = d->pose[1];
    else
      hi = d->pose[1];
  }
  bs = lo;
  for (e = 0.1; e > 1e-9; e /= 10.0) {
    pose[0] = 0.3;
    pose[1] = bs - e;
    pose[2] = 0.2;
    rps3_design_eval(w, &ds, NULL, 1, pose, 0.0, &o->out, NULL);
    assert_true(o->lti[0] < prev);
    if (e < 1e-3) {
      /* both kinds of rows lose their twist there, in proportion to the
         distance (OTI ~ 1.6 e, CTI ~ 27 e rad^-1), and cond_h ~ 1 / e */
      assert_true(o->oti[0] < 50.0 * e && o->cti[0] < 50.0 * e);
      assert_true(o->oti[0] > 0.5 * e && o->cti[0] > 0.5 * e);
      assert_true(o->cond[0] > 0.1 / e);
    }
    prev = o->lti[0];
  }
  assert_true(prev < 1e-7);
  assert_true(o->cond[0] > 1e7);
  rps3_data_free(d);
  test_free(o);
  rps3_design_ws_free(w);
}

/* no pose reachable: RPS3_EEMPTY, a message, a summary of zeros (never
   NaN), the per-pose outputs still written */
static void empty_workspace(void **state) {
  rps3_design ds;
  rps3_design_ws *w = ws_new();
  rps3_design_grid gr;
  rps3_design_summary s;
  outs *o = outs_new();
  size_t n, i;
  (void)state;
  rps3_design_default(&ds);
  ds.l_min = 5.0;
  ds.l_max = 6.0;
  rps3_design_grid_default(&ds, &gr);
  n = rps3_design_grid_size(&gr);
  assert_int_equal(rps3_design_eval_grid(w, &ds, NULL, &gr, &o->out, &s),
                   RPS3_EEMPTY);
  assert_non_null(strstr(w->err.msg, "empty workspace"));
  assert_non_null(strstr(w->err.msg, "stroke"));
  assert_string_equal(rps3_strerror(RPS3_EEMPTY),
                      "empty workspace: no pose reachable");
  assert_int_equal(s.n, n);
  assert_int_equal(s.nreach, 0);
  assert_true(s.reach_fraction == 0 && s.volume == 0 && s.gti == 0 &&
              s.good_fraction == 0 && s.lti_min == 0 && s.cond_h_max == 0 &&
              s.trans_max == 0 && s.xc_max == 0 && s.yc_max == 0 &&
              s.spin_max == 0 && s.l_lo == 0 && s.l_hi == 0);
  assert_int_equal(s.nflag[0], n - s.nflag[4]);
  for (i = 0; i < n; i++) assert_true(o->flags[i] != 0);
  test_free(o);
  rps3_design_ws_free(w);
}

/*
 * The task: the paper's helix at 1001 samples.  Its statistics against a
 * loop of rps3_inverse of the design's model at the same times
 * (aggregation, the sample times, the link mass switch: without link mass
 * the forces are the model's with its link effects off); a stroke too
 * short for the helix fails at the first sample whose longest link
 * (the oracle's geometry) passes l_max.
 */
static void task_requirements(void **state) {
  rps3_design ds;
  rps3_design_ws *w = ws_new();
  rps3_design_task t;
  rps3_traj tr;
  rps3_model m;
  rps3_data *d = NULL;
  const size_t N = 1001;
  double T, Fpk[3] = {0}, ss[3] = {0}, Ppk[3] = {0}, lmax_used = 0.0;
  double llo[3], lhi[3];
  size_t k, first = N;
  int lm, j;
  (void)state;
  rps3_design_default(&ds);
  rps3_traj_default(&tr);
  T = rps3_traj_duration(&tr);
  for (lm = 0; lm < 2; lm++) {
    assert_int_equal(rps3_design_task_eval(w, &ds, NULL, &tr, N, lm, &t),
                     RPS3_OK);
    assert_int_equal(t.nsamples, N);
    assert_int_equal(t.fail_index, N);
    assert_true(isnan(t.fail_time));
    assert_int_equal(rps3_design_model(&ds, &m, NULL), RPS3_OK);
    if (!lm) m.opt.effects &= ~(RPS3_EFF_LINK_GRAVITY | RPS3_EFF_LINK_INERTIA);
    assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
    if (d == NULL) assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
    memset(Fpk, 0, sizeof Fpk);
    memset(ss, 0, sizeof ss);
    memset(Ppk, 0, sizeof Ppk);
    for (j = 0; j < 3; j++) {
      llo[j] = HUGE_VAL;
      lhi[j] = 0.0;
    }
    for (k = 0; k < N; k++) {
      geo g;
      double tk = k + 1 == N ? T : T * (double)k / (double)(N - 1);
      assert_int_equal(
          rps3_traj_eval(&m, &tr, tk, d->pose, d->dpose, d->ddpose), RPS3_OK);
      assert_int_equal(rps3_inverse(&m, d), RPS3_OK);
      oracle_geo(ds.R, ds.rho, d->pose, &g);
      for (j = 0; j < 3; j++) {
        double F = d->F[j];
        if (g.l[j] < llo[j]) llo[j] = g.l[j];
        if (g.l[j] > lhi[j]) lhi[j] = g.l[j];
        if (fabs(F) > Fpk[j]) Fpk[j] = fabs(F);
        if (fabs(F * d->dl[j]) > Ppk[j]) Ppk[j] = fabs(F * d->dl[j]);
        ss[j] += F * F;
      }
    }
    for (j = 0; j < 3; j++) {
      CHECK_REL(t.F_peak[j], Fpk[j], 1e-12, 0.0, "peak force %d", j);
      CHECK_REL(t.F_rms[j], sqrt(ss[j] / N), 1e-12, 0.0, "rms force");
      CHECK_REL(t.P_peak[j], Ppk[j], 1e-12, 0.0, "peak power");
      CHECK_REL(t.l_lo[j], llo[j], TOL_EXACT, 0.0, "shortest link %d", j);
      CHECK_REL(t.l_hi[j], lhi[j], TOL_EXACT, 0.0, "longest link %d", j);
    }
    assert_true(t.lti_min > 0.85 && t.lti_min <= 1.0);
  }
  /* link mass costs force: the flag changes the result */
  {
    rps3_design_task a, b;
    rps3_design_task_eval(w, &ds, NULL, &tr, N, RPS3_DESIGN_LINK_MASS, &a);
    rps3_design_task_eval(w, &ds, NULL, &tr, N, RPS3_DESIGN_NO_LINK_MASS, &b);
    assert_true(a.F_peak[0] > b.F_peak[0] * 1.05);
  }
  /* a stroke that ends inside the helix: the first sample past it */
  ds.l_max = 0.34;
  for (k = 0; k < N && first == N; k++) {
    double q[3];
    geo g;
    rps3_traj_eval(&m, &tr, k + 1 == N ? T : T * (double)k / (N - 1), q, NULL,
                   NULL);
    oracle_geo(ds.R, ds.rho, q, &g);
    for (j = 0; j < 3; j++)
      if (g.l[j] > ds.l_max) first = k;
    if (first == N)
      for (j = 0; j < 3; j++)
        if (g.l[j] > lmax_used) lmax_used = g.l[j];
  }
  assert_true(first > 0 && first < N);
  assert_int_equal(rps3_design_task_eval(w, &ds, NULL, &tr, N, 1, &t),
                   RPS3_EREACH);
  assert_int_equal(t.fail_index, first);
  CHECK_REL(t.fail_time, T * (double)first / (N - 1), 1e-15, 1.0, "time");
  assert_int_equal(t.fail_flags, RPS3_DESIGN_STROKE);
  assert_int_equal(t.nsamples, first);
  CHECK_REL(t.l_hi[0] > t.l_hi[1]
                ? (t.l_hi[0] > t.l_hi[2] ? t.l_hi[0] : t.l_hi[2])
                : (t.l_hi[1] > t.l_hi[2] ? t.l_hi[1] : t.l_hi[2]),
            lmax_used, TOL_EXACT, 0.0, "longest link before the failure");
  assert_non_null(strstr(w->err.msg, "leaves the workspace: stroke"));
  assert_true(strncmp(w->err.msg, "t = ", 4) == 0);
  rps3_data_free(d);
  rps3_design_ws_free(w);
}

/* flag names, grid helpers' refusals, options defaults */
static void names_and_helpers(void **state) {
  static const char *const names[RPS3_DESIGN_NFLAG] = {
      "stroke", "pin", "ball", "interference", "assembly", "singular"};
  rps3_design_grid gr;
  rps3_design_opts o;
  double q[3], v;
  int k;
  (void)state;
  for (k = 0; k < RPS3_DESIGN_NFLAG; k++)
    assert_string_equal(rps3_design_flag_name(k), names[k]);
  assert_null(rps3_design_flag_name(RPS3_DESIGN_NFLAG));
  assert_null(rps3_design_flag_name(-1));
  rps3_design_grid_default(NULL, &gr);
  assert_int_equal(rps3_design_grid_size(&gr), 1000);
  assert_int_equal(rps3_design_grid_pose(&gr, 1000, q), RPS3_EINVAL);
  assert_int_equal(rps3_design_grid_pose(&gr, 999, q), RPS3_OK);
  CHECK_REL(q[0], PI - PI / 10, 1e-15, 1.0, "last alpha");
  CHECK_REL(q[2], 2 * 0.2286 - 0.2286 / 10, 1e-15, 1.0, "last z");
  assert_int_equal(rps3_design_grid_pose(&gr, 1, q), RPS3_OK);
  CHECK_REL(q[0], -PI + 3 * PI / 10, 1e-15, 1.0, "alpha fastest");
  gr.hi[1] = -1.0;
  assert_int_equal(rps3_design_grid_cell(&gr, &v), RPS3_EINVAL);
  assert_int_equal(rps3_design_grid_size(NULL), 0);
  rps3_design_opts_default(&o);
  assert_true(o.lti_good == 0.7 && o.length == 0.0 && o.cond_sing == 1e8);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(default_is_table2),
      cmocka_unit_test(mass_model_rule),
      cmocka_unit_test(bad_designs_named),
      cmocka_unit_test(bad_calls),
      cmocka_unit_test(brute_force_agrees),
      cmocka_unit_test(summary_of_outputs),
      cmocka_unit_test(indices_bounded),
      cmocka_unit_test(scale_invariant),
      cmocka_unit_test(level_platform_closed_form),
      cmocka_unit_test(singular_surface_lti_vanishes),
      cmocka_unit_test(empty_workspace),
      cmocka_unit_test(task_requirements),
      cmocka_unit_test(names_and_helpers),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
