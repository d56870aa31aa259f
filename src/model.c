/*
 * model.c - the immutable mechanism description: defaults (Table II),
 * validation and derived quantities.
 */
#include <string.h>

#include "internal.h"

void rps3_options_default(rps3_options *opt) {
  if (opt == NULL) return;
  opt->effects = RPS3_EFF_DEFAULT;
  opt->method = RPS3_LAGRANGE;
  opt->theta = RPS3_THETA_CLOSED_FORM;
  opt->solver = RPS3_SOLVER_HYBRIDSJ;
  opt->tol = 1e-12;
  opt->max_iter = 50;
  opt->warm_start = 1;
  opt->outputs = RPS3_OUT_ALL;
  opt->cond_warn = 1e6;
  opt->cond_max = 1e13;
  opt->trans_warn = 100.0;
  opt->trans_max = 1e8;
}

void rps3_model_default(rps3_model *m) {
  if (m == NULL) return;
  memset(m, 0, sizeof(*m));
  /* Table II */
  m->R = 0.2286;
  m->rho = 0.5;
  m->M = 0.18;
  m->m = 0.09;
  m->d = 0.1524;
  m->link_Ic = 0.0;
  m->g = 9.80665;
  rps3_options_default(&m->opt);
}

/* a body's inertia about its centre of mass is that of some mass
   distribution when its second moment Sigma = tr(I)/2 1 - I is positive
   semidefinite (the principal moments then obey the triangle inequality):
   every principal minor of Sigma >= 0, to a rounding slack relative to
   its trace.  The first failing rule, or NULL */
static const char *body_inertia_rule(const double in[6]) {
  const double I[3][3] = {{in[0], in[1], in[2]},
                          {in[1], in[3], in[4]},
                          {in[2], in[4], in[5]}};
  double S[3][3], tr = 0.5 * (in[0] + in[3] + in[5]), s, det;
  int i, j;
  for (i = 0; i < 3; i++)
    for (j = 0; j < 3; j++) S[i][j] = (i == j ? tr : 0.0) - I[i][j];
  s = S[0][0] + S[1][1] + S[2][2];
  if (!(s >= 0.0)) return "has a negative trace";
  for (i = 0; i < 3; i++)
    if (S[i][i] < -1e-12 * s)
      return "violates the triangle inequality of its moments";
  for (i = 0; i < 3; i++) {
    j = (i + 1) % 3;
    if (S[i][i] * S[j][j] - S[i][j] * S[i][j] < -1e-12 * s * s)
      return "is not positive semidefinite (products of inertia too large)";
  }
  det = S[0][0] * (S[1][1] * S[2][2] - S[1][2] * S[1][2]) -
        S[0][1] * (S[0][1] * S[2][2] - S[1][2] * S[0][2]) +
        S[0][2] * (S[0][1] * S[1][2] - S[1][1] * S[0][2]);
  if (det < -1e-12 * s * s * s)
    return "is not positive semidefinite (products of inertia too large)";
  return NULL;
}

/* the ten standard parameters of b in its frame: m, m c, and the inertia
   about the frame's origin by the parallel-axis theorem (RPS3_NSTD) */
void rps3_body_std(const rps3_body *b, double p[10]) {
  const double *c = b->com, m = b->mass;
  const double cc = c[0] * c[0] + c[1] * c[1] + c[2] * c[2];
  p[0] = m;
  p[1] = m * c[0];
  p[2] = m * c[1];
  p[3] = m * c[2];
  p[4] = b->inertia[0] + m * (cc - c[0] * c[0]);
  p[5] = b->inertia[1] - m * c[0] * c[1];
  p[6] = b->inertia[2] - m * c[0] * c[2];
  p[7] = b->inertia[3] + m * (cc - c[1] * c[1]);
  p[8] = b->inertia[4] - m * c[1] * c[2];
  p[9] = b->inertia[5] + m * (cc - c[2] * c[2]);
}

/* the general bodies: each a real body whose parameters and weight are
   finite; their standard parameters into m->std */
static int bodies_init(rps3_model *m, rps3_check *chk) {
  static const int field[RPS3_NBODY] = {
      RPS3_F_PLATFORM_BODY_MASS, RPS3_F_LEG1_CYLINDER_MASS,
      RPS3_F_LEG1_PISTON_MASS,   RPS3_F_LEG2_CYLINDER_MASS,
      RPS3_F_LEG2_PISTON_MASS,   RPS3_F_LEG3_CYLINDER_MASS,
      RPS3_F_LEG3_PISTON_MASS};
  int b, k;
  for (b = 0; b < RPS3_NBODY; b++) {
    const rps3_body *body = b == 0        ? &m->platform
                            : (b - 1) % 2 ? &m->leg[(b - 1) / 2].piston
                                          : &m->leg[(b - 1) / 2].cylinder;
    /* a body's rows are MASS, COM, INERTIA in that order */
    const char *why = body_inertia_rule(body->inertia);
    if (why != NULL)
      return rps3_check_fail(chk, field[b] + 2, 0, body->inertia[0],
                             field[b] + 2, -1, why);
    rps3_body_std(body, m->std[b]);
    for (k = 0; k < 10; k++)
      if (!isfinite(m->std[b][k]))
        return rps3_check_fail(chk, field[b], 0, body->mass, field[b] + 1, -1,
                               "its standard parameters overflow");
    if (!isfinite(body->mass * m->g))
      return rps3_check_fail(chk, field[b], 0, body->mass, RPS3_F_G, -1,
                             "its weight overflows");
  }
  return RPS3_OK;
}

int rps3_model_init(rps3_model *m, rps3_check *chk) {
  const rps3_payload *p;
  int i, k;
  rps3_check_clear(chk);
  if (m == NULL) {
    if (chk != NULL) snprintf(chk->msg, sizeof chk->msg, "model is NULL");
    return RPS3_EINVAL;
  }
  m->valid = 0;
  p = &m->payload;

  /* each field against its range (RPS3_FIELDS), then the rules that
     involve several fields */
  if (rps3_fields_check(RPS3_IN_MODEL, m, chk) != RPS3_OK) return RPS3_EINVAL;
  for (k = 0; k < 3; k++) {
    /* principal moments of a real body: each at most the sum of the other
       two (the second moments are non-negative); relative slack for
       rounding in user data */
    double a = p->inertia[k],
           s = p->inertia[(k + 1) % 3] + p->inertia[(k + 2) % 3];
    if (!(a <= s * (1 + 1e-12)))
      /* the rule reads the other two components: the field itself is
         related too */
      return rps3_check_fail(chk, RPS3_F_PAYLOAD_INERTIA, k, a,
                             RPS3_F_PAYLOAD_INERTIA, -1,
                             "violates the triangle inequality of principal "
                             "moments");
  }
  if (!(m->opt.trans_max >= m->opt.trans_warn))
    return rps3_check_fail(chk, RPS3_F_TRANS_MAX, 0, m->opt.trans_max,
                           RPS3_F_TRANS_WARN, -1,
                           "must be finite and >= trans_warn");
  if (!(m->opt.cond_max >= m->opt.cond_warn))
    return rps3_check_fail(chk, RPS3_F_COND_MAX, 0, m->opt.cond_max,
                           RPS3_F_COND_WARN, -1,
                           "must be finite and >= cond_warn");

  /* derived: platform radius and the uniform disc of (21) */
  m->r = m->rho * m->R;
  if (!isfinite(m->r))
    return rps3_check_fail(chk, RPS3_F_RHO, 0, m->rho, RPS3_F_R, -1,
                           "rho R overflows");
  /* products the dynamics forms from the inputs: a finite mass can still
     make a weight that overflows (M = 1e308) */
  if (m->bodies == RPS3_BODIES_GENERAL) {
    /* M, m and d are not read: the general platform's second moment
       about the centre reaches the ball joints at r */
    if (!isfinite(m->platform.mass * m->r * m->r))
      return rps3_check_fail(chk, RPS3_F_PLATFORM_BODY_MASS, 0,
                             m->platform.mass, RPS3_F_RHO, RPS3_F_R,
                             "platform.mass r^2 overflows");
  } else if (!(isfinite(m->M * m->g) && isfinite(m->M * m->r * m->r))) {
    return rps3_check_fail(chk, RPS3_F_PLATFORM_MASS, 0, m->M, RPS3_F_G,
                           RPS3_F_RHO, "M g or M r^2 overflows");
  } else if (!(isfinite(m->m * m->g * m->d) && isfinite(m->m * m->d * m->d))) {
    return rps3_check_fail(chk, RPS3_F_LINK_MASS, 0, m->m, RPS3_F_G, RPS3_F_D,
                           "m g d or m d^2 overflows");
  }
  if (!(isfinite(p->mass * m->g) && isfinite(p->mass * m->r * m->r)))
    return rps3_check_fail(chk, RPS3_F_PAYLOAD_MASS, 0, p->mass, RPS3_F_G,
                           RPS3_F_RHO,
                           "payload.mass g or payload.mass r^2 overflows");
  if (bodies_init(m, chk) != RPS3_OK) return RPS3_EINVAL;
  for (i = 0; i < 3; i++)
    m->pinf[i] = m->bodies == RPS3_BODIES_GENERAL ? m->leg[i].pin : m->friction;
  m->Ip[0] = m->Ip[1] = 0.25 * m->M * m->r * m->r;
  m->Ip[2] = 0.5 * m->M * m->r * m->r;
  m->Jlink = m->m * m->d * m->d + m->link_Ic;
  for (i = 0; i < 3; i++) {
    /* pins at psi_i = 0, 2pi/3, 4pi/3, written exactly */
    double cp = (i == 0) ? 1.0 : -0.5;
    double sp = (i == 0) ? 0.0 : (i == 1 ? 0.5 : -0.5) * RPS3_SQRT3;
    m->radial[i][0] = cp;
    m->radial[i][1] = sp;
    m->radial[i][2] = 0;
    m->pin[i][0] = m->R * cp;
    m->pin[i][1] = m->R * sp;
    m->pin[i][2] = 0;
    /* pin axis (30): the tangential direction, so that axis x phi = dphi */
    m->axis[i][0] = -sp;
    m->axis[i][1] = cp;
    m->axis[i][2] = 0;
    /* ball joint i in platform axes (27) */
    m->body[i][0] = m->r * cp;
    m->body[i][1] = m->r * sp;
    m->body[i][2] = 0;
  }
  m->valid = 1;
  return RPS3_OK;
}
