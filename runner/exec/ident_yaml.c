/*
 * ident_yaml.c - the manipulator section of an identification's fit
 * (ident_run.h, ident_manipulator_yaml): a scene's `manipulator:` keys
 * (docs/runner.md) that the runner's own validation accepts.
 */
#include "ident_run.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_eigen.h>
#include <gsl/gsl_matrix.h>

/* a growing text */
typedef struct {
  char *s;
  size_t len, cap;
  int bad;
} text;

static void add(text *t, const char *fmt, ...) {
  va_list ap;
  int n;
  if (t->bad) return;
  for (;;) {
    size_t room = t->cap - t->len;
    va_start(ap, fmt);
    n = vsnprintf(t->s ? t->s + t->len : NULL, t->s ? room : 0, fmt, ap);
    va_end(ap);
    if (n < 0) {
      t->bad = 1;
      return;
    }
    if (t->s && (size_t)n < room) {
      t->len += (size_t)n;
      return;
    }
    {
      size_t cap = 2 * (t->cap + (size_t)n + 64);
      char *s = realloc(t->s, cap);
      if (!s) {
        t->bad = 1;
        return;
      }
      t->s = s;
      t->cap = cap;
    }
  }
}

/* the shortest %g that reads back the same double */
static void num(char *buf, size_t sz, double x) {
  int prec;
  if (x == 0) x = 0; /* no "-0" */
  for (prec = 15; prec <= 17; prec++) {
    snprintf(buf, sz, "%.*g", prec, x);
    if (strtod(buf, NULL) == x) return;
  }
}

static void add_num(text *t, const char *key, double x) {
  char b[40];
  num(b, sizeof b, x);
  add(t, "%s: %s", key, b);
}

static void add_list(text *t, const char *key, const double *v, int n) {
  char b[40];
  int i;
  add(t, "%s: [", key);
  for (i = 0; i < n; i++) {
    num(b, sizeof b, v[i]);
    add(t, "%s%s", i ? ", " : "", b);
  }
  add(t, "]");
}

/*
 * A body's mass, centre of mass and inertia about it (Ixx, Ixy, Ixz, Iyy,
 * Iyz, Izz) from its 10 standard parameters about its origin, by the
 * parallel-axis theorem; a mass at most tiny: none (com 0, the origin's
 * inertia).  The inertia is then projected on the consistent set: its
 * principal second moments (tr(I)/2 - I_k) clipped at 0, so that the
 * rounding of a fit that ends on the set's boundary cannot fail the
 * scene's check (src/model.c: a slack of 1e-12 of the trace).  0, or -1
 * when GSL's workspace cannot be had.
 */
static int body_of(const double p[10], double tiny, double *mass,
                   double com[3], double in[6]) {
  double m = p[0], c[3] = {0, 0, 0}, I[3][3], cc;
  double ev[3], sum, s[3];
  gsl_matrix *A = gsl_matrix_alloc(3, 3), *V = gsl_matrix_alloc(3, 3);
  gsl_vector *e = gsl_vector_alloc(3);
  gsl_eigen_symmv_workspace *w = gsl_eigen_symmv_alloc(3);
  int i, j, k, rc = -1;
  if (!A || !V || !e || !w) goto done;
  I[0][0] = p[4];
  I[0][1] = I[1][0] = p[5];
  I[0][2] = I[2][0] = p[6];
  I[1][1] = p[7];
  I[1][2] = I[2][1] = p[8];
  I[2][2] = p[9];
  if (m > tiny) {
    for (i = 0; i < 3; i++) c[i] = p[1 + i] / m;
    cc = c[0] * c[0] + c[1] * c[1] + c[2] * c[2];
    for (i = 0; i < 3; i++)
      for (j = 0; j < 3; j++) I[i][j] -= m * ((i == j) * cc - c[i] * c[j]);
  } else
    m = 0;
  for (i = 0; i < 3; i++)
    for (j = 0; j < 3; j++) gsl_matrix_set(A, i, j, I[i][j]);
  if (gsl_eigen_symmv(A, e, V, w)) goto done;
  for (k = 0; k < 3; k++) ev[k] = gsl_vector_get(e, k);
  sum = 0.5 * (ev[0] + ev[1] + ev[2]);
  for (k = 0; k < 3; k++) s[k] = fmax(sum - ev[k], 0.0);
  for (k = 0; k < 3; k++) ev[k] = s[0] + s[1] + s[2] - s[k];
  for (i = 0; i < 3; i++)
    for (j = 0; j < 3; j++) {
      double v = 0;
      for (k = 0; k < 3; k++)
        v += gsl_matrix_get(V, i, k) * ev[k] * gsl_matrix_get(V, j, k);
      I[i][j] = v;
    }
  *mass = m;
  for (i = 0; i < 3; i++) com[i] = c[i];
  in[0] = I[0][0];
  in[1] = 0.5 * (I[0][1] + I[1][0]);
  in[2] = 0.5 * (I[0][2] + I[2][0]);
  in[3] = I[1][1];
  in[4] = 0.5 * (I[1][2] + I[2][1]);
  in[5] = I[2][2];
  rc = 0;
done:
  if (A) gsl_matrix_free(A);
  if (V) gsl_matrix_free(V);
  if (e) gsl_vector_free(e);
  if (w) gsl_eigen_symmv_free(w);
  return rc;
}

static int add_body(text *t, const char *indent, const char *name,
                    const double p[10], double tiny) {
  double m, c[3], in[6];
  if (body_of(p, tiny, &m, c, in)) return -1;
  add(t, "%s%s:\n%s  ", indent, name, indent);
  add_num(t, "mass", m);
  add(t, "\n%s  ", indent);
  add_list(t, "com", c, 3);
  add(t, "\n%s  ", indent);
  add_list(t, "inertia", in, 6);
  add(t, "\n");
  return 0;
}

static void add_friction(text *t, const char *name, double fv, double fc,
                         double vreg) {
  add(t, "    %s: {", name);
  add_num(t, "viscous", fv);
  add(t, ", ");
  add_num(t, "coulomb", fc);
  add(t, ", ");
  add_num(t, "vreg", vreg);
  add(t, "}\n");
}

/* the section's head: a warning comment when the consistent fit it
   comes from stopped short of its optimality test (its parameters are
   consistent, maybe not the optimum), then the geometry */
static void add_geometry(text *t, const rps3_model *m, const ident_fit *r) {
  if (r->cstatus > 0)
    add(t,
        "# warning: the consistent fit stopped short of its optimality "
        "test (consistent, maybe not optimal): %s\n",
        r->cmsg);
  add(t, "manipulator:\n  ");
  add_num(t, "R", m->R);
  add(t, "\n  ");
  add_num(t, "rho", m->rho);
  add(t, "\n  ");
  add_num(t, "g", m->g);
  add(t, "\n");
}

static char *finish(text *t, char *why, size_t whysz) {
  if (!t->bad) return t->s;
  free(t->s);
  snprintf(why, whysz, "out of memory");
  return NULL;
}

/* the general model's section, from the consistent fit */
static char *general_yaml(const ident_plan *p, const ident_fit *r, char *why,
                          size_t whysz) {
  static const char *const part[2] = {"cylinder", "piston"};
  const rps3_model *m = &p->c.model;
  double pi[RPS3_NSTD], tiny = 0;
  text t = {NULL, 0, 0, 0};
  size_t j;
  int q, i, b;
  if (!p->ids.consistent || r->cstatus < 0) {
    snprintf(why, whysz,
             "the general model's manipulator section is the consistent "
             "fit's (a base estimate is not a body's parameters): set "
             "identify.consistent: true");
    return NULL;
  }
  if (!r->consistent) {
    snprintf(why, whysz, "the consistent fit is not consistent: %s", r->cmsg);
    return NULL;
  }
  /* the scene's values, then the fit's layout parameters over them */
  memcpy(pi, p->std_truth, sizeof pi);
  for (j = 0; j < p->nlay; j++)
    for (q = 0; q < 3 && p->lay_std[j][q] >= 0; q++)
      pi[p->lay_std[j][q]] = r->ctheta[j];
  for (b = 0; b < RPS3_NBODY; b++) tiny += fabs(pi[10 * b]);
  tiny *= 1e-12;
  add_geometry(&t, m, r);
  add(&t, "  bodies: general\n");
  if (add_body(&t, "  ", "platform", pi, tiny)) goto fail;
  for (i = 0; i < 3; i++) {
    add(&t, "  leg%d:\n", i + 1);
    for (q = 0; q < 2; q++)
      if (add_body(&t, "    ", part[q], pi + 10 * (1 + 2 * i + q), tiny))
        goto fail;
    /* a friction law where the effects select it or it is not zero (a
       zero law of an unselected kind is no information) */
    if ((m->opt.effects & RPS3_EFF_PIN_FRICTION) || pi[76 + 2 * i] != 0 ||
        pi[77 + 2 * i] != 0)
      add_friction(&t, "pin_friction", pi[76 + 2 * i], pi[77 + 2 * i],
                   m->pinf[i].vreg);
    if ((m->opt.effects & RPS3_EFF_PRISMATIC_FRICTION) ||
        pi[70 + 2 * i] != 0 || pi[71 + 2 * i] != 0)
      add_friction(&t, "prismatic_friction", pi[70 + 2 * i], pi[71 + 2 * i],
                   m->leg[i].prismatic.vreg);
  }
  return finish(&t, why, whysz);
fail:
  free(t.s);
  snprintf(why, whysz, "out of memory");
  return NULL;
}

/* a value of the paper section below 0: 0 when rounding (at most 1e-12
   of scale below), else -1 with why */
static int nonneg(double *v, double scale, const char *what, char *why,
                  size_t whysz) {
  if (*v >= 0) return 0;
  if (*v >= -1e-12 * fabs(scale)) {
    *v = 0;
    return 0;
  }
  snprintf(why, whysz,
           "the fit's %s is %g, below 0: not a manipulator (identify."
           "consistent: true keeps it >= 0)",
           what, *v);
  return -1;
}

/* the paper model's section: the consistent fit when there is one, else
   the estimate */
static char *paper_yaml(const ident_plan *p, const ident_fit *r, char *why,
                        size_t whysz) {
  const rps3_model *mo = &p->c.model;
  const double *th = r->cstatus >= 0 && r->consistent ? r->ctheta : r->theta;
  double pi[RPS3_NPAPER], m, lic, pm, c[3] = {0, 0, 0}, in[3], fv, fc;
  int payload = mo->payload.mass > 0, i, prism = 0, fitted_m = 0;
  int pinf = (mo->opt.effects & RPS3_EFF_PIN_FRICTION) != 0;
  text t = {NULL, 0, 0, 0};
  rps3_check chk;
  size_t j;
  if (mo->bodies == RPS3_BODIES_GENERAL) {
    snprintf(why, whysz,
             "the scene's bodies are general: the paper model's parameters "
             "do not give them");
    return NULL;
  }
  rps3_paper_params(mo, pi, &chk);
  for (j = 0; j < p->p; j++) {
    pi[p->col[j]] = th[j];
    payload |= p->col[j] >= 3 && p->col[j] <= 9;
    fitted_m |= p->col[j] == 0;
  }
  /* without M the payload's columns hold the platform's disc as well (the
     disc is a body of the payload's kind, include/rps3.h): M keeps the
     scene's value and its disc leaves the payload's estimate */
  if (payload && !fitted_m &&
      (mo->opt.effects &
       (RPS3_EFF_PLATFORM_GRAVITY | RPS3_EFF_PLATFORM_INERTIA))) {
    for (j = 0; j < p->p; j++) {
      int k = p->col[j];
      if (k == 3) pi[3] -= mo->M;
      if (k >= 7 && k <= 9) pi[k] -= mo->Ip[k - 7];
    }
  }
  m = mo->d > 0 ? pi[1] / mo->d : mo->m;
  lic = pi[2] - m * mo->d * mo->d;
  pm = pi[3];
  fv = pi[10];
  fc = pi[11];
  if (nonneg(&pi[0], pi[0], "M", why, whysz) ||
      nonneg(&m, m, "link mass md / d", why, whysz) ||
      nonneg(&lic, pi[2], "link_Ic = Ipin - m d^2", why, whysz) ||
      nonneg(&pm, pm, "payload mass", why, whysz) ||
      nonneg(&fv, fv, "pin viscous friction", why, whysz) ||
      nonneg(&fc, fc, "pin Coulomb friction", why, whysz))
    return NULL;
  if (pm > 0)
    for (i = 0; i < 3; i++) c[i] = pi[4 + i] / pm;
  /* about the com: I_c,xx = I_xx - m (c_y^2 + c_z^2), ... */
  for (i = 0; i < 3; i++) {
    double cc = c[0] * c[0] + c[1] * c[1] + c[2] * c[2] - c[i] * c[i];
    in[i] = pi[7 + i] - pm * cc;
  }
  if (payload) {
    /* principal moments on the consistent set, as body_of does */
    double s[3], sum = 0.5 * (in[0] + in[1] + in[2]);
    for (i = 0; i < 3; i++) s[i] = fmax(sum - in[i], 0.0);
    for (i = 0; i < 3; i++) in[i] = fmax(s[0] + s[1] + s[2] - s[i], 0.0);
  }
  add_geometry(&t, mo, r);
  add(&t, "  ");
  add_num(&t, "M", pi[0]);
  add(&t, "\n  ");
  add_num(&t, "m", m);
  add(&t, "\n  ");
  add_num(&t, "d", mo->d);
  add(&t, "\n  ");
  add_num(&t, "link_Ic", lic);
  add(&t, "\n");
  if (payload) {
    add(&t, "  payload:\n    ");
    add_num(&t, "mass", pm);
    add(&t, "\n    ");
    add_list(&t, "com", c, 3);
    add(&t, "\n    ");
    add_list(&t, "inertia", in, 3);
    add(&t, "\n");
  }
  if (pinf || fv != 0 || fc != 0) {
    add(&t, "  pin_friction:\n    ");
    add_num(&t, "viscous", fv);
    add(&t, "\n    ");
    add_num(&t, "coulomb", fc);
    add(&t, "\n    ");
    add_num(&t, "vreg", mo->friction.vreg);
    add(&t, "\n");
  }
  for (i = 0; i < 3; i++)
    prism |= mo->leg[i].prismatic.viscous != 0 ||
             mo->leg[i].prismatic.coulomb != 0;
  for (i = 0; prism && i < 3; i++) {
    add(&t, "  leg%d:\n", i + 1);
    add_friction(&t, "prismatic_friction", mo->leg[i].prismatic.viscous,
                 mo->leg[i].prismatic.coulomb, mo->leg[i].prismatic.vreg);
  }
  return finish(&t, why, whysz);
}

char *ident_manipulator_yaml(const ident_plan *p, const ident_fit *r,
                             char *why, size_t whysz) {
  if (r->status != RPS3_OK) {
    snprintf(why, whysz, "the fit failed: %s", r->msg);
    return NULL;
  }
  return p->general ? general_yaml(p, r, why, whysz)
                    : paper_yaml(p, r, why, whysz);
}
