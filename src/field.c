/*
 * field.c - the table of validated input fields (RPS3_FIELDS in rps3.h) and
 * the range check every row of it gets.  rps3_model_init() and
 * rps3_traj_check() run this check first and then the rules that involve
 * several fields, so that each range is written once, in the table.
 */
#include <string.h>

#include "internal.h"

/* the int fields are read through int *: the enums must be int-sized */
typedef char rps3_enum_is_int_[(sizeof(rps3_method) == sizeof(int) &&
                                sizeof(rps3_theta_route) == sizeof(int) &&
                                sizeof(rps3_solver) == sizeof(int) &&
                                sizeof(rps3_traj_kind) == sizeof(int) &&
                                sizeof(rps3_time_law) == sizeof(int) &&
                                sizeof(rps3_path_shape) == sizeof(int))
                                   ? 1
                                   : -1];

/* offsetof in the structure a row names */
#define OFF_RPS3_IN_MODEL(MEMBER) offsetof(rps3_model, MEMBER)
#define OFF_RPS3_IN_TRAJ(MEMBER) offsetof(rps3_traj, MEMBER)
#define OFF_RPS3_IN_HELIX(MEMBER) offsetof(rps3_traj, MEMBER)
#define OFF_RPS3_IN_SINE(MEMBER) offsetof(rps3_traj, MEMBER)
#define OFF_RPS3_IN_WAYPOINTS(MEMBER) offsetof(rps3_traj, MEMBER)
#define OFF_RPS3_IN_PATH(MEMBER) offsetof(rps3_traj, MEMBER)
#define OFF_RPS3_IN_TABLE(MEMBER) offsetof(rps3_traj, MEMBER)

#define ROW(ID, IN, MEMBER, N, IS_INT, LO, LO_OPEN, HI, UNIT, NAME) \
  {NAME, IN, OFF_##IN(MEMBER), N, IS_INT, LO, LO_OPEN, HI, UNIT},
static const rps3_field_info fields[RPS3_NFIELD] = {RPS3_FIELDS(ROW)};
#undef ROW

const rps3_field_info *rps3_field(int id) {
  return (id >= 0 && id < RPS3_NFIELD) ? &fields[id] : NULL;
}

void rps3_check_clear(rps3_check *chk) {
  if (chk == NULL) return;
  chk->field = -1;
  chk->comp = 0;
  chk->related[0] = chk->related[1] = -1;
  chk->msg[0] = '\0';
}

int rps3_check_fail(rps3_check *chk, int field, int comp, double value,
                    int rel0, int rel1, const char *why) {
  if (chk != NULL) {
    const rps3_field_info *f = rps3_field(field);
    chk->field = field;
    chk->comp = comp;
    chk->related[0] = rel0;
    chk->related[1] = rel1;
    if (f != NULL && f->n != 1)
      snprintf(chk->msg, sizeof chk->msg, "%s[%d] = %.16g: %s", f->name, comp,
               value, why);
    else
      snprintf(chk->msg, sizeof chk->msg, "%s = %.16g: %s",
               f != NULL ? f->name : "?", value, why);
  }
  return RPS3_EINVAL;
}

/* the reason a value outside row f's range is refused */
static void range_text(const rps3_field_info *f, char *buf, size_t sz) {
  if (f->lo == -HUGE_VAL && f->hi == HUGE_VAL)
    snprintf(buf, sz, "must be finite");
  else if (f->hi == HUGE_VAL)
    snprintf(buf, sz, "must be finite and %s %.17g",
             f->lo_open ? ">" : ">=", f->lo);
  else
    snprintf(buf, sz, "must be %sin %c%.17g, %.17g]",
             f->is_int ? "an integer " : "", f->lo_open ? '(' : '[', f->lo,
             f->hi);
}

int rps3_field_in_range(const rps3_field_info *f, double x) {
  if (!isfinite(x)) return 0;
  if (f->lo_open ? !(x > f->lo) : !(x >= f->lo)) return 0;
  return x <= f->hi;
}

int rps3_fields_check(int in, const void *base, rps3_check *chk) {
  int id, k;
  for (id = 0; id < RPS3_NFIELD; id++) {
    const rps3_field_info *f = &fields[id];
    const char *p = (const char *)base + f->offset;
    if (f->in != in) continue;
    for (k = 0; k < f->n; k++) {
      double x;
      if (f->is_int) {
        int v;
        memcpy(&v, p + (size_t)k * sizeof(int), sizeof v);
        x = (double)v;
      } else {
        memcpy(&x, p + (size_t)k * sizeof(double), sizeof x);
      }
      if (!rps3_field_in_range(f, x)) {
        char why[96];
        range_text(f, why, sizeof why);
        return rps3_check_fail(chk, id, k, x, -1, -1, why);
      }
    }
  }
  return RPS3_OK;
}
