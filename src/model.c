/*
 * model.c - the immutable mechanism description: defaults (Table II),
 * validation and derived quantities.
 */
#include <string.h>

#include "internal.h"

void rps3_options_default(rps3_options *opt) {
  opt->effects = RPS3_EFF_DEFAULT;
  opt->method = RPS3_LAGRANGE;
  opt->theta = RPS3_THETA_CLOSED_FORM;
  opt->solver = RPS3_SOLVER_HYBRIDSJ;
  opt->tol = 1e-12;
  opt->max_iter = 50;
  opt->warm_start = 1;
  opt->certify = 1;
  opt->cond_warn = 1e6;
  opt->cond_max = 1e13;
}

void rps3_model_default(rps3_model *m) {
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

/* write a message naming the field and return RPS3_EINVAL */
static int bad(char *err, size_t errsz, const char *field, double value,
               const char *why) {
  if (err != NULL && errsz > 0)
    snprintf(err, errsz, "%s = %.17g: %s", field, value, why);
  return RPS3_EINVAL;
}

#define REQUIRE(cond, field, value, why)                                      \
  do {                                                                        \
    if (!(cond)) return bad(err, errsz, field, (double)(value), why);         \
  } while (0)

int rps3_model_init(rps3_model *m, char *err, size_t errsz) {
  const rps3_payload *p;
  const rps3_options *o;
  int i, k;
  if (m == NULL) {
    if (err != NULL && errsz > 0) snprintf(err, errsz, "model is NULL");
    return RPS3_EINVAL;
  }
  m->valid = 0;
  p = &m->payload;
  o = &m->opt;

  /* mechanism */
  REQUIRE(isfinite(m->R) && m->R > 0, "R", m->R, "must be finite and > 0");
  REQUIRE(isfinite(m->rho) && m->rho > 0, "rho", m->rho,
          "must be finite and > 0");
  REQUIRE(isfinite(m->M) && m->M >= 0, "M", m->M, "must be finite and >= 0");
  REQUIRE(isfinite(m->m) && m->m >= 0, "m", m->m, "must be finite and >= 0");
  REQUIRE(isfinite(m->d) && m->d >= 0, "d", m->d, "must be finite and >= 0");
  REQUIRE(isfinite(m->link_Ic) && m->link_Ic >= 0, "link_Ic", m->link_Ic,
          "must be finite and >= 0");
  REQUIRE(isfinite(m->g) && m->g >= 0, "g", m->g, "must be finite and >= 0");

  /* payload: a physical rigid body */
  REQUIRE(isfinite(p->mass) && p->mass >= 0, "payload.mass", p->mass,
          "must be finite and >= 0");
  for (k = 0; k < 3; k++) {
    static const char *const cname[3] = {"payload.com[0]", "payload.com[1]",
                                         "payload.com[2]"};
    static const char *const iname[3] = {
        "payload.inertia[0]", "payload.inertia[1]", "payload.inertia[2]"};
    REQUIRE(isfinite(p->com[k]), cname[k], p->com[k], "must be finite");
    REQUIRE(isfinite(p->inertia[k]) && p->inertia[k] >= 0, iname[k],
            p->inertia[k], "must be finite and >= 0");
  }
  for (k = 0; k < 3; k++) {
    /* principal moments of a real body: each at most the sum of the other
       two (the second moments are non-negative); relative slack for
       rounding in user data */
    double a = p->inertia[k], s = p->inertia[(k + 1) % 3] + p->inertia[(k + 2) % 3];
    REQUIRE(a <= s * (1 + 1e-12), "payload.inertia", a,
            "violates the triangle inequality of principal moments");
  }
  REQUIRE(isfinite(m->friction.viscous) && m->friction.viscous >= 0,
          "pin_friction.viscous", m->friction.viscous,
          "must be finite and >= 0");
  REQUIRE(isfinite(m->friction.coulomb) && m->friction.coulomb >= 0,
          "pin_friction.coulomb", m->friction.coulomb,
          "must be finite and >= 0");

  /* options */
  REQUIRE((o->effects & ~RPS3_EFF_ALL) == 0, "opt.effects", o->effects,
          "unknown effect bits");
  REQUIRE(o->method == RPS3_LAGRANGE || o->method == RPS3_NEWTON_EULER,
          "opt.method", o->method, "unknown method");
  REQUIRE(o->theta == RPS3_THETA_CLOSED_FORM || o->theta == RPS3_THETA_MULTIROOT,
          "opt.theta", o->theta, "unknown theta route");
  REQUIRE((int)o->solver >= 0 && (int)o->solver < RPS3_NSOLVER, "opt.solver",
          o->solver, "unknown solver");
  REQUIRE(isfinite(o->tol) && o->tol > 0, "opt.tol", o->tol,
          "must be finite and > 0");
  REQUIRE(o->max_iter >= 1, "opt.max_iter", o->max_iter, "must be >= 1");
  REQUIRE(isfinite(o->cond_warn) && o->cond_warn >= 1, "opt.cond_warn",
          o->cond_warn, "must be finite and >= 1");
  REQUIRE(isfinite(o->cond_max) && o->cond_max >= o->cond_warn,
          "opt.cond_max", o->cond_max, "must be finite and >= cond_warn");

  /* derived: platform radius and the uniform disc of (21) */
  m->r = m->rho * m->R;
  REQUIRE(isfinite(m->r), "rho", m->rho, "rho R overflows");
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
