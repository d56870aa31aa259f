/* test_fd_loads.c - the forward dynamics' Mq and hq (assemble,
   src/fwddyn_plane.h: hq from the loads of src/loads.h in each link's
   frame, Mq in the Gram form of their columns) against the same
   quantities formed from those loads in world axes by virtual power
   (tests/fd_loads_columns.h), and against Kane's form written by hand
   (tests/fd_gram_oracle.h): a change of a load that the inverse
   dynamics sees, the forward dynamics' check sees too. */
#include <stdlib.h>

#include "testutil.h"

#include "fd_gram_oracle.h"
#include "fd_loads_columns.h"

/* a random point of a random smooth trajectory through rps3_inverse, as
   the forward dynamics' state (l, dl) on the inverse's assembly mode */
static void random_fd_state(const rps3_model *m, rps3_data *inv, rps3_data *fd,
                            uint64_t *s) {
  rps3_traj tr;
  double t;
  traj_random(&tr, s);
  t = rnd_uniform(s, 0.0, tr.sine.duration);
  assert_int_equal(
      rps3_traj_eval(m, &tr, t, inv->pose, inv->dpose, inv->ddpose), RPS3_OK);
  if (rps3_inverse(m, inv) != RPS3_OK) fail_msg("inverse: %s", inv->err.msg);
  rps3_data_reset(fd);
  memcpy(fd->l, inv->l, sizeof(fd->l));
  memcpy(fd->dl, inv->dl, sizeof(fd->dl));
  memcpy(fd->theta, inv->theta, sizeof(fd->theta));
  fd->have_theta = 1;
}

/* Mq and hq of every effect, of all but the payload, and of each effect
   alone, on random states with random rates (the trajectory's and 20
   times faster): the library's (rps3_fwddyn_state of a model with that
   selection) within TOL_EXACT of the loads' columns at the kinematics
   kept by a state of all effects (the same l, dl, start: the same root),
   entry by entry against the sum of the absolute values of its terms
   (the payload's shared rps3_fd_add_body terms against the entry); and
   the hand-written Kane form: the same Mq bit for bit (the library's
   is that Gram form), hq within the same bound */
static void mass_and_bias_are_the_loads(void **state) {
  uint64_t s = 0xfd10ad5ull;
  int sets[RPS3_NEFFECT + 2], nset = 0, c, n, e, j, q;
  rps3_model ma;
  rps3_data *inv, *fa;
  rps3_fd_state *k = calloc(1, sizeof(*k)), *kc = calloc(1, sizeof(*kc));
  (void)state;
  assert_non_null(k);
  assert_non_null(kc);
  sets[nset++] = RPS3_EFF_ALL;
  sets[nset++] = RPS3_EFF_ALL & ~RPS3_EFF_PAYLOAD;
  for (e = 0; e < RPS3_NEFFECT; e++) sets[nset++] = 1 << e;
  model_entropy(&ma);
  assert_int_equal(rps3_model_init(&ma, NULL), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&ma, &inv), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&ma, &fa), RPS3_OK);
  for (c = 0; c < nset; c++) {
    rps3_model m;
    rps3_data *fd;
    model_entropy(&m);
    m.opt.effects = sets[c];
    assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
    assert_int_equal(rps3_data_alloc(&m, &fd), RPS3_OK);
    for (n = 0; n < 40; n++) {
      double Mq[3][3], hq[3], sM[3][3], sh[3], Mg[3][3], hg[3];
      random_fd_state(&ma, inv, fa, &s);
      for (j = 0; j < 3; j++) fa->dl[j] *= (n % 2) ? 1.0 : 20.0;
      rps3_data_reset(fd);
      memcpy(fd->l, fa->l, sizeof(fd->l));
      memcpy(fd->dl, fa->dl, sizeof(fd->dl));
      memcpy(fd->theta, fa->theta, sizeof(fd->theta));
      fd->have_theta = 1;
      memset(k, 0, sizeof(*k));
      memset(kc, 0, sizeof(*kc));
      if (rps3_fwddyn_state(&ma, fa, k, RPS3_FD_KEEP) != RPS3_OK)
        fail_msg("all effects: %s", fa->err.msg);
      assert_true(k->have_kin);
      if (rps3_fwddyn_state(&m, fd, kc, RPS3_FD_NOFACTOR) != RPS3_OK)
        fail_msg("effects %#x: %s", sets[c], fd->err.msg);
      fd_loads_columns(&m, fa, k, &k->kin, Mq, hq, sM, sh);
      fd_gram_oracle(&m, fa, k, &k->kin, Mg, hg);
      assert_memory_equal(fd->Mq, Mg, sizeof(Mg));
      for (j = 0; j < 3; j++) {
        if (!(fabs(fd->hq[j] - hq[j]) <= TOL_EXACT * (sh[j] + fabs(hq[j]))))
          fail_msg("effects %#x, hq[%d] = %.17g, the loads' %.17g", sets[c], j,
                   fd->hq[j], hq[j]);
        if (!(fabs(fd->hq[j] - hg[j]) <= TOL_EXACT * (sh[j] + fabs(hg[j]))))
          fail_msg("effects %#x, hq[%d] = %.17g, the Gram form's %.17g",
                   sets[c], j, fd->hq[j], hg[j]);
        for (q = 0; q < 3; q++)
          if (!(fabs(fd->Mq[j][q] - Mq[j][q]) <=
                TOL_EXACT * (sM[j][q] + fabs(Mq[j][q]))))
            fail_msg("effects %#x, Mq[%d][%d] = %.17g, the loads' %.17g",
                     sets[c], j, q, fd->Mq[j][q], Mq[j][q]);
      }
    }
    rps3_data_free(fd);
  }
  rps3_data_free(inv);
  rps3_data_free(fa);
  free(k);
  free(kc);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(mass_and_bias_are_the_loads),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
