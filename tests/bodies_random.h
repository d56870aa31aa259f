/*
 * bodies_random.h - general bodies for the C tests (rps3_model.bodies =
 * RPS3_BODIES_GENERAL): the paper's bodies written as general ones, and
 * random real bodies with friction in every joint (test_bodies.c,
 * test_fd_bodies.c, test_sim_bodies.c).
 */
#ifndef RPS3_BODIES_RANDOM_H
#define RPS3_BODIES_RANDOM_H

#include "testutil.h"

/* g: p's bodies written as general ones (the disc, point-mass links at d
   with link_Ic about e2 and e3, massless pistons, the pins' friction) */
static inline void paper_as_general(const rps3_model *p, rps3_model *g) {
  const double r = p->rho * p->R;
  int i;
  *g = *p;
  g->bodies = RPS3_BODIES_GENERAL;
  memset(&g->platform, 0, sizeof g->platform);
  g->platform.mass = p->M;
  g->platform.inertia[0] = g->platform.inertia[3] = 0.25 * p->M * r * r;
  g->platform.inertia[5] = 0.5 * p->M * r * r;
  for (i = 0; i < 3; i++) {
    memset(&g->leg[i].cylinder, 0, sizeof(rps3_body));
    memset(&g->leg[i].piston, 0, sizeof(rps3_body));
    g->leg[i].cylinder.mass = p->m;
    g->leg[i].cylinder.com[0] = p->d;
    g->leg[i].cylinder.inertia[3] = g->leg[i].cylinder.inertia[5] = p->link_Ic;
    g->leg[i].pin = p->friction;
  }
}

/* a random real body: mass, centre of mass, principal moments obeying the
   triangle inequality along random axes */
static inline void random_body(rps3_body *b, uint64_t *s, double mass, double len) {
  double a[3], q[3], R[3][3], c[3], sn[3];
  int i, j, k;
  b->mass = rnd_uniform(s, 0.2, 1.0) * mass;
  for (k = 0; k < 3; k++) {
    b->com[k] = rnd_uniform(s, -len, len);
    a[k] = rnd_uniform(s, 1.0, 2.0) * b->mass * len * len;
    q[k] = rnd_uniform(s, -PI, PI);
    c[k] = cos(q[k]);
    sn[k] = sin(q[k]);
  }
  /* R = Rz(q0) Ry(q1) Rx(q2) */
  R[0][0] = c[0] * c[1];
  R[0][1] = c[0] * sn[1] * sn[2] - sn[0] * c[2];
  R[0][2] = c[0] * sn[1] * c[2] + sn[0] * sn[2];
  R[1][0] = sn[0] * c[1];
  R[1][1] = sn[0] * sn[1] * sn[2] + c[0] * c[2];
  R[1][2] = sn[0] * sn[1] * c[2] - c[0] * sn[2];
  R[2][0] = -sn[1];
  R[2][1] = c[1] * sn[2];
  R[2][2] = c[1] * c[2];
  {
    const int ij[6][2] = {{0, 0}, {0, 1}, {0, 2}, {1, 1}, {1, 2}, {2, 2}};
    for (k = 0; k < 6; k++) {
      i = ij[k][0];
      j = ij[k][1];
      b->inertia[k] = R[i][0] * a[0] * R[j][0] + R[i][1] * a[1] * R[j][1] +
                      R[i][2] * a[2] * R[j][2];
    }
  }
}

/* a model of random general bodies and friction in every joint, every
   effect selected, method meth */
static inline void random_general(rps3_model *m, uint64_t *s, int meth) {
  int i;
  model_entropy(m);
  m->bodies = RPS3_BODIES_GENERAL;
  m->opt.method = meth;
  random_body(&m->platform, s, 0.3, 0.05);
  for (i = 0; i < 3; i++) {
    random_body(&m->leg[i].cylinder, s, 0.1, 0.08);
    random_body(&m->leg[i].piston, s, 0.05, 0.06);
    m->leg[i].pin.viscous = rnd_uniform(s, 0.001, 0.02);
    m->leg[i].pin.coulomb = rnd_uniform(s, 0.001, 0.01);
    m->leg[i].pin.vreg = 0.01;
    m->leg[i].prismatic.viscous = rnd_uniform(s, 0.1, 2.0);
    m->leg[i].prismatic.coulomb = rnd_uniform(s, 0.01, 0.5);
    m->leg[i].prismatic.vreg = 1e-3;
  }
  assert_int_equal(rps3_model_init(m, NULL), RPS3_OK);
}

#endif /* RPS3_BODIES_RANDOM_H */
