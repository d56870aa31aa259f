/*
 * fwddyn_general.c - Mq and hq of the general bodies (RPS3_BODIES_GENERAL)
 * from the inverse dynamics' own loads.
 *
 * The paper's bodies have a Gram form of Mq (src/fwddyn.c's header); a
 * general platform (body_load of src/invdyn.c, through the frame's second
 * derivatives) and general legs (rps3_leg_loads of src/bodies.c, a
 * cylinder and a piston each) have none that is cheaper than their loads'
 * columns, so Mq is formed as the virtual-power argument states it, with
 * the Lagrange route's own loads (rps3_lagrange_loads) and (34):
 *   Mq e_j = F of the inertia loads at l'' = e_j, theta'' = G e_j, the
 *            rates zero (the loads are linear in the accelerations then),
 *   hq     = F of every selected effect at l'' = 0, theta'' =
 *            theta''_bias and the state's rates (weights, friction),
 * F = wl + G^T wt.  The payload keeps its rigid-body terms
 * (rps3_fd_add_body) as for the paper's bodies.  Four evaluations of the
 * loads a state make rps3_fwddyn about 4.5 times the paper bodies' call
 * (docs/simulation.md has the timings).
 *
 * The point is built from the plane alone (the lengths, theta's cosines
 * and sines): the library's position code writes the links' directions,
 * the ball joints and the frame into a local rps3_data, so that a lean
 * state (positions NaN in d) and a controller at a kept plant state
 * (src/fwddyn_shared.c) form the same Mq and hq.
 */
#include "fwddyn_plane.h"

/* F = wl + G^T wt of the loads w (w[0..2] on l, w[3..5] on theta), (34) */
static void force_of(const plane *p, const double w[6], double F[3]) {
  fd_force(p, w, w + 3, F);
}

void rps3_fd_general(const rps3_model *m, const plane *p, double Mq[3][3],
                     double hq[3]) {
  const int eff = m->opt.effects;
  const int inertia =
      eff & (RPS3_EFF_PLATFORM_INERTIA | RPS3_EFF_LINK_INERTIA);
  rps3_data t; /* the fields rps3_lagrange_loads reads, set below */
  double w[6], A[3][3], col[3];
  int i, j;
  /* positions: (29), (12)-(14), (11) and (18)-(20) from the plane */
  v3_copy(t.l, p->q.l);
  rps3_links_from_trig(m, &t, p->q.c, p->q.s);
  rps3_frame_from_balls(m, &t);
  /* hq: the selected effects but the payload at the state's rates and
     the bias accelerations */
  for (i = 0; i < 3; i++) {
    t.dl[i] = p->dl[i];
    t.dtheta[i] = p->dth[i];
    t.ddl[i] = 0.0;
    t.ddtheta[i] = p->ddb[i];
  }
  rps3_lagrange_loads(m, &t, eff & ~RPS3_EFF_PAYLOAD, w);
  force_of(p, w, hq);
  /* Mq's columns: the inertia loads at l'' = e_j, at rest */
  for (i = 0; i < 3; i++) t.dl[i] = t.dtheta[i] = 0.0;
  for (j = 0; j < 3; j++) {
    for (i = 0; i < 3; i++) {
      t.ddl[i] = (i == j) ? 1.0 : 0.0;
      t.ddtheta[i] = p->G[i][j];
    }
    rps3_lagrange_loads(m, &t, inertia, w);
    force_of(p, w, col);
    for (i = 0; i < 3; i++) A[i][j] = col[i];
  }
  /* symmetric by construction: the columns' own asymmetry is rounding
     (tests/test_fd_bodies.c holds Mq to the inverse dynamics' columns by
     both formulations, which an asymmetric error would fail) */
  for (i = 0; i < 3; i++)
    for (j = i; j < 3; j++) Mq[i][j] = Mq[j][i] = 0.5 * (A[i][j] + A[j][i]);
}
