/* test_model.c - model defaults, validation, names, workspace life cycle. */
#include "testutil.h"

static void defaults_are_table_ii(void **state) {
  rps3_model m;
  rps3_check chk;
  (void)state;
  rps3_model_default(&m);
  assert_int_equal(rps3_model_init(&m, &chk), RPS3_OK);
  assert_true(m.valid);
  assert_true(m.R == 0.2286 && m.rho == 0.5 && m.M == 0.18);
  assert_true(m.m == 0.09 && m.d == 0.1524); /* m/M = 0.5 */
  CHECK_REL(m.r, 0.1143, 1e-15, 0.0, "r = rho R");
  /* disc of (21): Ixx = Iyy = Izz / 2 = M r^2 / 4 */
  CHECK_REL(m.Ip[0], 0.25 * 0.18 * 0.1143 * 0.1143, 1e-15, 0.0, "Ixx");
  CHECK_REL(m.Ip[2], 2.0 * m.Ip[1], 1e-15, 0.0, "Izz");
  assert_int_equal(m.opt.effects, RPS3_EFF_DEFAULT);
}

/* each bad field is rejected; the message names it, and chk->field is
   the row of that name (its component in chk->comp); without chk the
   status is the same */
#define BAD(field_text, stmt)                                                 \
  do {                                                                        \
    rps3_model m;                                                             \
    rps3_check chk;                                                           \
    char name[64];                                                            \
    rps3_model_default(&m);                                                   \
    stmt;                                                                     \
    assert_int_equal(rps3_model_init(&m, NULL), RPS3_EINVAL);                 \
    assert_int_equal(rps3_model_init(&m, &chk), RPS3_EINVAL);                 \
    assert_false(m.valid);                                                    \
    if (strncmp(chk.msg, field_text " = ", strlen(field_text " = ")) != 0)  \
      fail_msg("message '%s' does not start with '%s = '", chk.msg,          \
               field_text);                                                   \
    assert_non_null(rps3_field(chk.field));                                   \
    if (rps3_field(chk.field)->n == 1)                                        \
      snprintf(name, sizeof name, "%s", rps3_field(chk.field)->name);         \
    else                                                                      \
      snprintf(name, sizeof name, "%s[%d]", rps3_field(chk.field)->name,      \
               chk.comp);                                                     \
    assert_string_equal(name, field_text);                                    \
  } while (0)

static void rejects_each_field(void **state) {
  (void)state;
  BAD("R", m.R = 0.0);
  BAD("R", m.R = (double)NAN);
  BAD("R", m.R = -0.2);
  BAD("rho", m.rho = 0.0);
  BAD("rho", m.rho = (double)INFINITY);
  BAD("M", m.M = -1e-3);
  BAD("m", m.m = (double)NAN);
  BAD("d", m.d = -0.1);
  BAD("link_Ic", m.link_Ic = -1.0);
  BAD("g", m.g = -9.8);
  BAD("payload.mass", m.payload.mass = -0.5);
  BAD("payload.com[1]", m.payload.com[1] = (double)NAN);
  BAD("payload.inertia[2]", m.payload.inertia[2] = -1.0);
  BAD("payload.inertia[0]", (m.payload.inertia[0] = 1.0, m.payload.inertia[1] = 0.2,
                   m.payload.inertia[2] = 0.3));
  BAD("pin_friction.viscous", m.friction.viscous = -0.1);
  BAD("pin_friction.coulomb", m.friction.coulomb = (double)NAN);
  BAD("opt.effects", m.opt.effects = 1 << 9);
  BAD("opt.method", m.opt.method = (rps3_method)7);
  BAD("opt.theta", m.opt.theta = (rps3_theta_route)3);
  BAD("opt.solver", m.opt.solver = (rps3_solver)RPS3_NSOLVER);
  BAD("opt.tol", m.opt.tol = 0.0);
  BAD("opt.max_iter", m.opt.max_iter = 0);
  BAD("opt.cond_warn", m.opt.cond_warn = 0.5);
  BAD("opt.cond_max", m.opt.cond_max = 10.0);
  BAD("rho", (m.R = 1e300, m.rho = 1e300));
  assert_int_equal(rps3_model_init(NULL, NULL), RPS3_EINVAL);
}

/* rps3_model_init names the failing field by identifier and
   component, and each row's name, offset and range agree with the
   structure */
#define BAD_ID(id, comp_, rel, stmt)                                          \
  do {                                                                        \
    rps3_model m;                                                             \
    rps3_check chk;                                                           \
    rps3_model_default(&m);                                                   \
    stmt;                                                                     \
    assert_int_equal(rps3_model_init(&m, &chk), RPS3_EINVAL);                 \
    assert_int_equal(chk.field, id);                                          \
    assert_int_equal(chk.comp, comp_);                                        \
    assert_int_equal(chk.related[0], rel);                                    \
    assert_true(strncmp(chk.msg, rps3_field(id)->name,                        \
                        strlen(rps3_field(id)->name)) == 0);                  \
  } while (0)

static void validate_names_field_by_id(void **state) {
  rps3_model m0;
  rps3_check c0;
  int id;
  (void)state;
  BAD_ID(RPS3_F_R, 0, -1, m.R = -1.0);
  BAD_ID(RPS3_F_PAYLOAD_COM, 2, -1, m.payload.com[2] = (double)INFINITY);
  BAD_ID(RPS3_F_PAYLOAD_INERTIA, 1, RPS3_F_PAYLOAD_INERTIA,
         (m.payload.inertia[0] = 0.1, m.payload.inertia[1] = 1.0,
          m.payload.inertia[2] = 0.2));
  BAD_ID(RPS3_F_SOLVER, 0, -1, m.opt.solver = (rps3_solver)-1);
  BAD_ID(RPS3_F_MAX_ITER, 0, -1, m.opt.max_iter = 0);
  BAD_ID(RPS3_F_COND_MAX, 0, RPS3_F_COND_WARN, m.opt.cond_max = 10.0);
  BAD_ID(RPS3_F_RHO, 0, RPS3_F_R, (m.R = 1e300, m.rho = 1e300));
  /* a success clears what an earlier failure left in the same chk */
  rps3_model_default(&m0);
  m0.rho = -1.0;
  assert_int_equal(rps3_model_init(&m0, &c0), RPS3_EINVAL);
  assert_int_equal(c0.field, RPS3_F_RHO);
  rps3_model_default(&m0);
  assert_int_equal(rps3_model_init(&m0, &c0), RPS3_OK);
  assert_int_equal(c0.field, -1);
  assert_int_equal(c0.related[0], -1);
  assert_string_equal(c0.msg, "");
  assert_int_equal(rps3_model_init(NULL, &c0), RPS3_EINVAL);
  assert_int_equal(c0.field, -1);
  assert_string_equal(c0.msg, "model is NULL");
  assert_null(rps3_field(-1));
  assert_null(rps3_field(RPS3_NFIELD));
  /* the offset of a row is where its member is: the defaults read back
     through the table equal the members */
  assert_int_equal(rps3_field(RPS3_F_G)->offset, offsetof(rps3_model, g));
  assert_int_equal(rps3_field(RPS3_F_TOL)->offset,
                   offsetof(rps3_model, opt.tol));
  assert_int_equal(rps3_field(RPS3_F_HELIX_BLEND)->offset,
                   offsetof(rps3_traj, helix.blend));
  for (id = 0; id < RPS3_NFIELD; id++) {
    const rps3_field_info *f = rps3_field(id);
    assert_non_null(f->name);
    assert_true(f->n == 0 || f->n == 1 || f->n == 3 || f->n == 6);
    assert_true(f->lo <= f->hi);
  }
}

static void names_round_trip(void **state) {
  int k;
  (void)state;
  for (k = 0; k < RPS3_NEFFECT; k++)
    assert_int_equal(rps3_effect_index(rps3_effect_name(k)), k);
  assert_null(rps3_effect_name(RPS3_NEFFECT));
  assert_null(rps3_effect_name(-1));
  assert_int_equal(rps3_effect_index("gravity"), -1);
  assert_int_equal(rps3_effect_index(NULL), -1);
  assert_string_equal(rps3_effect_name(4), "payload");
  for (k = 0; k < RPS3_NSOLVER; k++)
    assert_int_equal(rps3_solver_index(rps3_solver_name(k)), k);
  assert_int_equal(rps3_solver_index("lm"), -1);
  assert_null(rps3_solver_name(RPS3_NSOLVER));
  assert_string_equal(rps3_version(), RPS3_VERSION_STRING);
}

static void every_status_has_a_message(void **state) {
  static const int codes[] = {RPS3_OK,     RPS3_EREACH, RPS3_ENOCONV,
                              RPS3_EBRANCH, RPS3_ESING, RPS3_EDOMAIN,
                              RPS3_EINVAL, RPS3_ENOMEM, RPS3_ESTATE,
                              RPS3_ERANGE, RPS3_EMODE,  RPS3_EEMPTY};
  size_t i, j;
  (void)state;
  for (i = 0; i < sizeof codes / sizeof codes[0]; i++) {
    assert_non_null(rps3_strerror(codes[i]));
    assert_string_not_equal(rps3_strerror(codes[i]), "unknown status");
    for (j = 0; j < i; j++)
      assert_string_not_equal(rps3_strerror(codes[i]), rps3_strerror(codes[j]));
  }
  assert_string_equal(rps3_strerror(12345), "unknown status");
}

static void data_life_cycle(void **state) {
  rps3_model m;
  rps3_data *d = NULL;
  int s;
  (void)state;
  rps3_model_default(&m);
  /* not initialised yet */
  assert_int_equal(rps3_data_alloc(&m, &d), RPS3_EINVAL);
  assert_null(d);
  assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
  assert_int_equal(rps3_data_alloc(&m, NULL), RPS3_EINVAL);
  assert_int_equal(rps3_data_alloc(NULL, &d), RPS3_EINVAL);
  for (s = 0; s < RPS3_NSOLVER; s++) {
    m.opt.solver = (rps3_solver)s;
    assert_int_equal(rps3_model_init(&m, NULL), RPS3_OK);
    assert_int_equal(rps3_data_alloc(&m, &d), RPS3_OK);
    d->have_theta = 1;
    d->theta[0] = 1.234;
    rps3_data_reset(d);
    assert_int_equal(d->have_theta, 0);
    assert_true(d->theta[0] == 0.0);
    rps3_data_free(d);
  }
  rps3_data_free(NULL);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(defaults_are_table_ii),
      cmocka_unit_test(rejects_each_field),
      cmocka_unit_test(validate_names_field_by_id),
      cmocka_unit_test(names_round_trip),
      cmocka_unit_test(every_status_has_a_message),
      cmocka_unit_test(data_life_cycle),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
