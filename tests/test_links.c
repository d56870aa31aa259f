/*
 * test_links.c - the lean pass of rps3_inverse_batch (kblink_pos and
 * kblink_load of src/batch_kmech.h) link by link against the staged
 * route: its link vectors, lengths and angles' rates from the formulas of
 * src/links.h at its scaled vectors (v = l phi, q = l dphi, 1 / l^2), and
 * its loads, which it sums into one ball force and one pin torque with
 * fused multiply-adds, against each effect's load of src/loads.h on the
 * stages' phi, dphi, l and b'' (the form of src/invdyn.c's
 * lagrange_effect): the oracle of the form the lean pass keeps on purpose
 * (docs/library.md, "The formulation").  Both of its instances, unfused
 * (fu = 0) and fused (fu = 1), on the paper's model and on one of high
 * entropy.
 */
#include <float.h>
#include <stdlib.h>

#include "batch_kmech.h"
#include "testutil.h"

#define NPOINT 3000

/* the effects the lean pass serves, all four */
#define LEAN_EFFECTS                                       \
  (RPS3_EFF_PLATFORM_GRAVITY | RPS3_EFF_PLATFORM_INERTIA | \
   RPS3_EFF_LINK_GRAVITY | RPS3_EFF_LINK_INERTIA)

/* the staged route's loads of link i, each effect by src/loads.h as
   lagrange_effect forms them (b'' from the joint rates, c'' their mean):
   wl (on l_i), wt (on theta_i) and the size of their terms */
static void staged_loads(const rps3_model *m, const rps3_data *d, int i,
                         double *wl, double *wt, double *size) {
  const double m6 = RPS3_DISC_BALL_MASS(m->M);
  const double W = RPS3_PLATFORM_BALL_WEIGHT(m->M, m->g);
  const double mgd = RPS3_LINK_WEIGHT_MOMENT(m->m, m->g, m->d);
  double bdd[3][3], cdd[3] = {0.0, 0.0, 0.0};
  double wl1, wt1, wl2, wt2, wt3, wt4;
  int k, q;
  for (k = 0; k < 3; k++) {
    RPS3_BALL_ACC_JOINTS(RPS3_V3C, d->phi[k], d->dphi[k], d->l[k], d->dl[k],
                         d->dtheta[k], d->ddl[k], d->ddtheta[k], bdd[k]);
    for (q = 0; q < 3; q++) cdd[q] += bdd[k][q] / 3.0;
  }
  RPS3_LOAD_PLATFORM_INERTIA(RPS3_V3C, m6, cdd, bdd[i], d->phi[i], d->dphi[i],
                             d->l[i], wl1, wt1);
  RPS3_LOAD_PLATFORM_GRAVITY(W, d->phi[i][2], d->dphi[i][2], d->l[i], wl2, wt2);
  RPS3_LOAD_LINK_GRAVITY(mgd, d->dphi[i][2], wt3);
  RPS3_LOAD_LINK_INERTIA(m->Jlink, d->ddtheta[i], wt4);
  *wl = wl1 + wl2;
  *wt = wt1 + wt2 + wt3 + wt4;
  *size =
      d->l[i] * (m6 * (fabs(cdd[0]) + fabs(cdd[1]) + fabs(cdd[2]) +
                       fabs(bdd[i][0]) + fabs(bdd[i][1]) + fabs(bdd[i][2])) +
                 W) +
      fabs(mgd) + fabs(wt4);
}

/* the lean pass's links at the point of d against the stages' */
static void compare_point(const rps3_model *m, const rps3_data *d,
                          const kbconst *K, int fu) {
  const double *p = d->pose, *dp = d->dpose, *ddp = d->ddpose;
  const kpose P = kpose_eval(m->r, p[0], p[1], p[2], dp[0], dp[1], dp[2],
                             ddp[0], ddp[1], ddp[2], fu);
  int i, q;
  for (i = 0; i < 3; i++) {
    kblink L = kblink_pos(K, i, P.rx, P.ry, P.c, fu);
    double wl, wt, size, v[3] = {L.v.x, L.v.y, L.v.z};
    double qv[3] = {L.q.x, L.q.y, L.q.z};
    L = kblink_load(K, L, P.w, P.vc, P.dw, P.ac, fu);
    assert_true(L.ok == 1.0);
    /* positions: v = l phi, q = l dphi (29) */
    CHECK_REL(L.l, d->l[i], TOL_EXACT, d->l[i], "l_%d fu %d", i, fu);
    for (q = 0; q < 3; q++) {
      CHECK_REL(v[q], d->l[i] * d->phi[i][q], TOL_EXACT, d->l[i],
                "v_%d[%d] fu %d", i, q, fu);
      CHECK_REL(qv[q], d->l[i] * d->dphi[i][q], TOL_EXACT, d->l[i],
                "q_%d[%d] fu %d", i, q, fu);
    }
    /* loads: l wl and wt */
    staged_loads(m, d, i, &wl, &wt, &size);
    CHECK_REL(L.wl, d->l[i] * wl, TOL_EXACT, size, "l wl_%d fu %d", i, fu);
    CHECK_REL(L.wt, wt, TOL_EXACT, size, "wt_%d fu %d", i, fu);
  }
}

/* random points of the workspace, their rates and accelerations: the
   lean pass's loads link by link within TOL_EXACT of the size of their
   terms (the two forms differ by rounding alone: b'' as the platform's
   rigid motion against b'' from the joint rates, one summed force against
   four loads, the vector sine against libm's) */
static void run(rps3_model *m, uint64_t seed) {
  rps3_data *d = NULL;
  kbconst K;
  int n, fu, done = 0;
  m->opt.effects = LEAN_EFFECTS;
  assert_int_equal(rps3_model_init(m, NULL), RPS3_OK);
  assert_int_equal(rps3_data_alloc(m, &d), RPS3_OK);
  kbconst_set(&K, m, 1.0);
  for (n = 0; n < NPOINT; n++) {
    int c;
    d->pose[0] = rnd_uniform(&seed, -3.1, 3.1);
    d->pose[1] = rnd_uniform(&seed, 0.02, 0.45);
    d->pose[2] = rnd_uniform(&seed, 0.6, 1.6) * m->R;
    for (c = 0; c < 3; c++) {
      d->dpose[c] = rnd_uniform(&seed, -1.3, 1.3);
      d->ddpose[c] = rnd_uniform(&seed, -4.1, 4.1);
    }
    d->dpose[2] *= m->R;
    d->ddpose[2] *= m->R;
    if (rps3_ik(m, d) != RPS3_OK || rps3_velocity(m, d) != RPS3_OK ||
        rps3_acceleration(m, d) != RPS3_OK)
      continue;
    for (fu = 0; fu < 2; fu++) compare_point(m, d, &K, fu);
    done++;
  }
  /* most of the box is reachable: the test compared points */
  assert_true(done > NPOINT / 2);
  rps3_data_free(d);
}

static void lean_loads_paper_model(void **state) {
  rps3_model m;
  (void)state;
  rps3_model_default(&m);
  run(&m, 0x11a5);
}

static void lean_loads_entropy_model(void **state) {
  rps3_model m;
  (void)state;
  model_entropy(&m);
  run(&m, 0x2b7e);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(lean_loads_paper_model),
      cmocka_unit_test(lean_loads_entropy_model),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
